"""Compiled per-trial reductions of :mod:`mtcal.methods.large_angle` (tan2022 preset accelerometer triads).

* :func:`max_abs_first_order` — per bias draw, the max over grid points of the first-order
  pitch error's magnitude (Eq 8 generalised to per-axis errors), without the (n, P) error array.

Float64 without ``fastmath`` (:func:`mtcal.core.compiled.jit`): each element is numpy's
expression ``−(cosθ Δf_x + sinθ (sin a Δf_y + cos a Δf_z)) / g`` operation by operation (the
trigonometric factors come in precomputed by numpy), so the maxima are bit for bit numpy's.
"""

from __future__ import annotations

import numpy as np

from mtcal.core.compiled import jit

__all__ = ["max_abs_first_order"]


@jit
def max_abs_first_order(cos_t, sin_t, sin_a, cos_a, delta, gg):
    """``max_p |−(cos_t[p] δx + sin_t[p] (sin_a[p] δy + cos_a[p] δz)) / gg|`` per row ``δ`` of ``delta`` (n, 3).

    NaN propagates as in ``np.max``.
    """
    n, m = delta.shape[0], cos_t.size
    out = np.empty(n)
    for i in range(n):
        dx, dy, dz = delta[i, 0], delta[i, 1], delta[i, 2]
        best = 0.0
        for p in range(m):
            v = abs(-(cos_t[p] * dx + sin_t[p] * (sin_a[p] * dy + cos_a[p] * dz)) / gg)
            if best == best and (v != v or v > best):
                best = v
        out[i] = best
    return out
