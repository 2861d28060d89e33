"""Compiled loop behind :mod:`mtcal.methods.constrained_fit` (large float64, private).

The kernel performs the numpy reference's arithmetic operation by operation, in the same order
(products and sums of 3 or 4 terms left to right, as numpy reduces a short last axis; no
``fastmath``, no FMA contraction: :func:`mtcal.core.compiled.jit`), so its output is
bit-identical to the numpy expressions it replaces. The transcendental ``arctan2`` stays in numpy
(the caller applies it), so the result does not depend on which libm numba would link.

Imported lazily (on the first large array): ``import mtcal`` does not load numba.
"""

from __future__ import annotations

import numpy as np

from mtcal.core.compiled import jit

__all__ = ["angle_arguments"]

_BIG = np.finfo(np.float64).max


@jit
def _finite(v):  # pragma: no cover - compiled
    """``np.nan_to_num(v)`` (NaN → 0, ±inf → ±max) and whether ``v`` was NaN."""
    if np.isnan(v):
        return 0.0, True
    if v == np.inf:
        return _BIG, False
    if v == -np.inf:
        return -_BIG, False
    return v, False


@jit
def angle_arguments(q1, q2, vec_norm, scalar_abs, has_nan):  # pragma: no cover - compiled
    """Per row of (N, 4) ``q1``, ``q2``: ``d = conj(nan_to_num(q1)) ⊗ q2``; ``vec_norm = ‖d[1:]‖``,
    ``scalar_abs = |d[0]|``, ``has_nan`` = any NaN in the row of ``q1``.

    ``‖v‖ = sqrt((v1² + v2²) + v3²)`` (numpy's ``linalg.norm`` over a last axis of 3); the Hamilton
    product's terms in :func:`mtcal.core.rotations.hamilton`'s order.
    """
    for i in range(q1.shape[0]):
        a0, nan0 = _finite(q1[i, 0])
        a1, nan1 = _finite(q1[i, 1])
        a2, nan2 = _finite(q1[i, 2])
        a3, nan3 = _finite(q1[i, 3])
        nan = nan0 or nan1 or nan2 or nan3
        p0, p1, p2, p3 = a0, -a1, -a2, -a3
        r0, r1, r2, r3 = q2[i, 0], q2[i, 1], q2[i, 2], q2[i, 3]
        d0 = p0 * r0 - p1 * r1 - p2 * r2 - p3 * r3
        d1 = p0 * r1 + p1 * r0 + p2 * r3 - p3 * r2
        d2 = p0 * r2 - p1 * r3 + p2 * r0 + p3 * r1
        d3 = p0 * r3 + p1 * r2 - p2 * r1 + p3 * r0
        vec_norm[i] = np.sqrt((d1 * d1 + d2 * d2) + d3 * d3)
        scalar_abs[i] = abs(d0)
        has_nan[i] = nan
