"""Compiled window pass of :func:`mtcal.methods.tilt_rate.tilt_rate_scale` (private).

One pass over the record gives what the scale needs per window of ``m`` samples:
the accelerometer and gyro means, the accelerometer's standard deviation (rms over
axes), whether a skipped sample falls in the window, and whether every value of the
record is finite. The sums are formed in numpy's order (sequential over the samples of
a window for the means, numpy's pairwise summation over the window's ``3 m`` squared
deviations for the standard deviation), so the results are bit-identical to the
numpy expressions ``blocks.mean(axis=1)`` and
``sqrt(((blocks - mean) ** 2).mean(axis=(1, 2)))`` they replace, on every CPU target.
Imported on first use (numba is not loaded by ``import mtcal``).
"""

from __future__ import annotations

import numba
import numpy as np

from mtcal.core.compiled import jit

__all__ = ["window_stats", "warm_up"]

#: numpy's pairwise-summation block (``PW_BLOCKSIZE`` of numpy's loops_utils.h).
_PW_BLOCK = 128


@numba.njit(inline="always")
def _pairwise_sum(buf, lo, n):
    """numpy's ``pairwise_sum`` of ``buf[lo:lo + n]`` (8 accumulators, halves above 128 values)."""
    if n < 8:
        res = 0.0
        for i in range(n):
            res += buf[lo + i]
        return res
    r0, r1, r2, r3 = buf[lo], buf[lo + 1], buf[lo + 2], buf[lo + 3]
    r4, r5, r6, r7 = buf[lo + 4], buf[lo + 5], buf[lo + 6], buf[lo + 7]
    i = 8
    stop = n - n % 8
    while i < stop:
        r0 += buf[lo + i]
        r1 += buf[lo + i + 1]
        r2 += buf[lo + i + 2]
        r3 += buf[lo + i + 3]
        r4 += buf[lo + i + 4]
        r5 += buf[lo + i + 5]
        r6 += buf[lo + i + 6]
        r7 += buf[lo + i + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += buf[lo + i]
        i += 1
    return res


@numba.njit(inline="always")
def _half(n):
    """numpy's split of a pairwise sum above the block size: ``n // 2`` rounded down to a multiple of 8."""
    n2 = n // 2
    return n2 - n2 % 8


@numba.njit
def _pairwise(buf, n, f_lo, f_n, f_left, f_state):
    """numpy's recursive pairwise sum of ``buf[:n]``, evaluated with an explicit stack (``f_*``: 64 frames).

    numba cannot cache a recursive function (loading it back crashes), so the recursion
    ``sum(lo, n) = sum(lo, h) + sum(lo + h, n − h)`` (``h`` = :func:`_half`) runs as a loop;
    the additions are the same, in the same association.
    """
    if n <= _PW_BLOCK:
        return _pairwise_sum(buf, 0, n)
    top = 0
    f_lo[0], f_n[0], f_state[0] = 0, n, 0
    while True:
        if f_n[top] <= _PW_BLOCK:  # a leaf: sum it, then return up through finished right children
            v = _pairwise_sum(buf, f_lo[top], f_n[top])
            top -= 1
            while top >= 0 and f_state[top] == 1:
                v = f_left[top] + v
                top -= 1
            if top < 0:
                return v
            f_left[top], f_state[top] = v, 1  # left child done: descend into the right one
            h = _half(f_n[top])
            f_lo[top + 1], f_n[top + 1], f_state[top + 1] = f_lo[top] + h, f_n[top] - h, 0
        else:  # descend into the left child
            h = _half(f_n[top])
            f_lo[top + 1], f_n[top + 1], f_state[top + 1] = f_lo[top], h, 0
        top += 1


@jit
def window_stats(w, a, m, skip, has_skip):
    """Per-window statistics of a (N, 3) gyro ``w`` and accelerometer ``a`` record, one pass.

    Parameters
    ----------
    w, a : ndarray (N, 3) float64, C-contiguous
    m : int
        Samples per window; windows ``[i m, (i + 1) m)`` for ``i < N // m``.
    skip : ndarray (N,) of bool
        Samples not to trust (ignored unless ``has_skip``).
    has_skip : bool

    Returns
    -------
    a_mean : ndarray (nb, 3)
    a_std : ndarray (nb,)
        ``sqrt(mean over the window's samples and axes of (a - a_mean)²)``.
    w_mean : ndarray (nb, 3)
    skipped : ndarray (nb,) of bool
    gyro_finite, accel_finite : bool
        Every value of ``w`` (``a``) is finite, the tail after the last window included.
    """
    n = a.shape[0]
    nb = n // m
    am = np.empty((nb, 3))
    wm = np.empty((nb, 3))
    sd = np.empty(nb)
    skipped = np.zeros(nb, np.bool_)
    buf = np.empty(3 * m)
    f_lo, f_n, f_state, f_left = np.empty(64, np.int64), np.empty(64, np.int64), np.empty(64, np.int64), np.empty(64)
    zero_w = 0.0
    zero_a = 0.0
    for i in range(nb):
        base = i * m
        sa0 = 0.0
        sa1 = 0.0
        sa2 = 0.0
        sw0 = 0.0
        sw1 = 0.0
        sw2 = 0.0
        for j in range(base, base + m):
            sa0 += a[j, 0]
            sa1 += a[j, 1]
            sa2 += a[j, 2]
            sw0 += w[j, 0]
            sw1 += w[j, 1]
            sw2 += w[j, 2]
            zero_a += (0.0 * a[j, 0] + 0.0 * a[j, 1]) + 0.0 * a[j, 2]  # NaN exactly when a value is not finite
            zero_w += (0.0 * w[j, 0] + 0.0 * w[j, 1]) + 0.0 * w[j, 2]
        m0, m1, m2 = sa0 / m, sa1 / m, sa2 / m
        am[i, 0], am[i, 1], am[i, 2] = m0, m1, m2
        wm[i, 0], wm[i, 1], wm[i, 2] = sw0 / m, sw1 / m, sw2 / m
        for j in range(m):
            d0 = a[base + j, 0] - m0
            d1 = a[base + j, 1] - m1
            d2 = a[base + j, 2] - m2
            buf[3 * j] = d0 * d0
            buf[3 * j + 1] = d1 * d1
            buf[3 * j + 2] = d2 * d2
        sd[i] = np.sqrt(_pairwise(buf, 3 * m, f_lo, f_n, f_left, f_state) / (3 * m))
        if has_skip:
            for j in range(base, base + m):
                if skip[j]:
                    skipped[i] = True
                    break
    for j in range(nb * m, n):  # the tail outside every window
        zero_a += (0.0 * a[j, 0] + 0.0 * a[j, 1]) + 0.0 * a[j, 2]
        zero_w += (0.0 * w[j, 0] + 0.0 * w[j, 1]) + 0.0 * w[j, 2]
    return am, sd, wm, skipped, zero_w == 0.0, zero_a == 0.0


def warm_up() -> None:
    """Compile (or load from numba's cache) :func:`window_stats`."""
    x = np.zeros((400, 3))
    window_stats(x, x, 150, np.zeros(400, np.bool_), True)
