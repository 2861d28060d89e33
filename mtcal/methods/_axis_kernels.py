"""Compiled masked rest means of :func:`mtcal.methods.rotation_axis.axes_from_rests`, bit for bit numpy's.

``a[t][mask[t]].mean(axis=0)`` copies the masked samples into a C-contiguous (k, 3) array, sums
it over its outer axis (numpy's order there is a sequential running sum per column,
``((x_0 + x_1) + x_2) + …``; the pairwise order applies only to a contiguous reduced axis) and
divides by ``k``; the kernel does the same operations without the copy, for every trial in
one call (checked bit for bit against numpy in ``tests/methods/test_rotation_axis.py``).
Kernels are float64 without ``fastmath`` (:func:`mtcal.core.compiled.jit`).
"""

from __future__ import annotations

import numpy as np

from mtcal.core.compiled import jit

__all__ = ["masked_means", "warm_up"]


@jit
def masked_means(a, mask, out):
    """``out[t] = a[t][mask[t]].mean(axis=0)`` for the trials with a masked sample (others untouched);
    ``a`` (T, N, 3), ``mask`` (T, N) bool, ``out`` (T, 3)."""
    for t in range(a.shape[0]):
        k = 0
        s0 = s1 = s2 = 0.0
        for i in range(a.shape[1]):
            if mask[t, i]:
                if k == 0:
                    s0, s1, s2 = a[t, i, 0], a[t, i, 1], a[t, i, 2]
                else:
                    s0 += a[t, i, 0]
                    s1 += a[t, i, 1]
                    s2 += a[t, i, 2]
                k += 1
        if k > 0:
            out[t, 0] = s0 / k
            out[t, 1] = s1 / k
            out[t, 2] = s2 / k


def warm_up() -> None:
    """Compile (or load from the cache) the kernel on a tiny input."""
    masked_means(np.ones((1, 2, 3)), np.ones((1, 2), np.bool_), np.empty((1, 3)))
