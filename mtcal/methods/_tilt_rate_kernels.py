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

:func:`window_fit` then forms the scale's sums from the ~N/m window means, again in numpy's
arithmetic (median, 'linear' percentile, cross, einsum, pairwise sums), and
:func:`percentile_linear` is ``np.percentile``; only the spread's BLAS product and ``arccos``
stay numpy (their results may depend on the CPU's vector units).
"""

from __future__ import annotations

import numba
import numpy as np

from mtcal.core.compiled import jit

__all__ = ["window_stats", "window_fit", "percentile_linear", "warm_up"]

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


@numba.njit(inline="always")
def _norm3(x0, x1, x2):
    """``np.linalg.norm`` of one row of an (n, 3) array along axis 1: ``sqrt((x0² + x1²) + x2²)``."""
    return np.sqrt((x0 * x0 + x1 * x1) + x2 * x2)


@numba.njit
def _has_nan(x):
    """Whether ``x`` holds a NaN (numpy's median and percentile then return NaN)."""
    for v in x:
        if np.isnan(v):
            return True
    return False


@numba.njit
def _order_pair(x, k):
    """The ``k``-th and ``(k - 1)``-th smallest values of ``x`` (``k`` ≥ 1), by one partition (no full sort)."""
    s = np.partition(x, k)
    lower = s[0]
    for i in range(1, k):
        if s[i] > lower:
            lower = s[i]
    return s[k], lower


@numba.njit
def _median(x):
    """``np.median`` of a 1-D float array with at least one value (mean of the two middle values when even)."""
    if _has_nan(x):
        return np.nan
    n = x.shape[0]
    h = n // 2
    if n % 2 == 1:
        return 0.0 + np.partition(x, h)[h]
    upper, lower = _order_pair(x, h)
    return ((0.0 + lower) + upper) / 2.0


@numba.njit
def _percentile(x, q):
    """``np.percentile(x, 100 q)`` of a 1-D float array (method 'linear', numpy's ``_lerp``); ``q`` = ``p / 100``."""
    if _has_nan(x):
        return np.nan
    n = x.shape[0]
    v = (n - 1) * q
    if v >= n - 1:  # numpy: both neighbours are the last value
        return np.max(x)
    lo = int(np.floor(v))
    t = v - lo
    b, a = _order_pair(x, lo + 1)
    diff = b - a
    if t >= 0.5:
        return b - diff * (1 - t)
    return a + diff * t


@jit
def percentile_linear(x, q):
    """``np.percentile(x, 100 q)`` (method 'linear') of a non-empty 1-D float64 array, bit for bit."""
    return _percentile(x, q)


@jit
def window_fit(am, a_std, wm, skipped, m, dt_s, band_fraction):
    """What :func:`mtcal.methods.tilt_rate.tilt_rate_scale` forms from the window statistics, in numpy's arithmetic.

    Every step reproduces the numpy expression it replaces bit for bit (``np.linalg.norm``
    along axis 1, ``np.median``, ``np.percentile`` 'linear', ``np.cross``, ``np.einsum``
    'ij,ij->i' (numpy adds the products as ``(p0 + p2) + p1``), ``np.sum`` by numpy's
    pairwise summation), except the accelerometer spread, which needs a BLAS product and
    numpy's ``arccos`` and is left to the caller.

    Parameters
    ----------
    am, wm : ndarray (nb, 3)
        Window means of the accelerometer and the gyro, nb ≥ 3.
    a_std : ndarray (nb,)
    skipped : ndarray (nb,) of bool
    m : int
        Samples per window.
    dt_s, band_fraction : float

    Returns
    -------
    status : int
        0: no decision and no spread (median norm not positive, or fewer than 2 window pairs);
        1: the spread is due but fewer than 2 moving pairs; 2: the sums are valid.
    ah_ok : ndarray (n_ok, 3)
        Unit gravity directions of the windows within the band (``ah[ok]``; meaningless when ``status`` is 0).
    ref : ndarray (3,)
        Their mean ``ah[ok].mean(axis=0)`` (meaningless when ``status`` is 0).
    up, pp, uu, accel_tilt, gyro_tilt : float
        ``Σ u·p``, ``Σ p·p``, ``Σ u·u``, ``Σ ‖u‖``, ``Σ ‖p‖`` over the pairs used.
    count : int
        Pairs used.
    """
    nb = am.shape[0]
    ok = np.zeros(nb, np.bool_)
    ah = np.empty((nb, 3))
    nrm = np.empty(nb)
    for i in range(nb):
        nrm[i] = _norm3(am[i, 0], am[i, 1], am[i, 2])
    g = _median(nrm)
    if not g > 0:
        return 0, ah, ah[0], 0.0, 0.0, 0.0, 0.0, 0.0, 0
    lim = band_fraction * g
    for i in range(nb):
        ok[i] = (np.abs(nrm[i] - g) < lim) and (a_std[i] < lim) and not skipped[i]
        d = nrm[i]
        if d < 1e-12:
            d = 1e-12
        ah[i, 0], ah[i, 1], ah[i, 2] = am[i, 0] / d, am[i, 1] / d, am[i, 2] / d
    k = nb - 1
    u = np.empty((k, 3))
    du = np.empty(k)
    pair = np.zeros(k, np.bool_)
    npair = 0
    for i in range(k):
        a0, a1, a2 = ah[i, 0], ah[i, 1], ah[i, 2]
        b0, b1, b2 = ah[i + 1, 0], ah[i + 1, 1], ah[i + 1, 2]
        u0 = a1 * b2 - a2 * b1
        u1 = a2 * b0 - a0 * b2
        u2 = a0 * b1 - a1 * b0
        u[i, 0], u[i, 1], u[i, 2] = u0, u1, u2
        du[i] = _norm3(u0, u1, u2)
        if ok[i] and ok[i + 1]:
            pair[i] = True
            npair += 1
    if npair < 2:
        return 0, ah, ah[0], 0.0, 0.0, 0.0, 0.0, 0.0, 0
    nok = 0
    for i in range(nb):
        nok += ok[i]
    ah_ok = np.empty((nok, 3))  # ``ah[ok]`` and its ``.mean(axis=0)`` (numpy adds the rows in order)
    ref = np.zeros(3)
    j = 0
    for i in range(nb):
        if ok[i]:
            for c in range(3):
                ah_ok[j, c] = ah[i, c]
                ref[c] += ah[i, c]
            j += 1
    for c in range(3):
        ref[c] /= nok
    sel = np.empty(npair)
    j = 0
    for i in range(k):
        if pair[i]:
            sel[j] = du[i]
            j += 1
    q25 = _percentile(sel, 0.25)
    still = np.zeros(k, np.bool_)
    nstill = 0
    for i in range(k):
        if pair[i] and du[i] <= q25:
            still[i] = True
            nstill += 1
    wmid = np.empty((k, 3))
    for i in range(k):
        for c in range(3):
            wmid[i, c] = 0.5 * (wm[i, c] + wm[i + 1, c])
    bias = np.empty(3)
    col = np.empty(nstill)
    for c in range(3):
        j = 0
        for i in range(k):
            if still[i]:
                col[j] = wmid[i, c]
                j += 1
        bias[c] = _median(col)
    T = m * dt_s
    p = np.empty((k, 3))
    dp = np.empty(k)
    for i in range(k):
        s0 = 0.5 * (ah[i, 0] + ah[i + 1, 0])
        s1 = 0.5 * (ah[i, 1] + ah[i + 1, 1])
        s2 = 0.5 * (ah[i, 2] + ah[i + 1, 2])
        d = _norm3(s0, s1, s2)
        if d < 1e-12:
            d = 1e-12
        s0, s1, s2 = s0 / d, s1 / d, s2 / d
        r0, r1, r2 = wmid[i, 0] - bias[0], wmid[i, 1] - bias[1], wmid[i, 2] - bias[2]
        dot = (r0 * s0 + r2 * s2) + r1 * s1
        p0 = -(r0 - dot * s0) * T
        p1 = -(r1 - dot * s1) * T
        p2 = -(r2 - dot * s2) * T
        p[i, 0], p[i, 1], p[i, 2] = p0, p1, p2
        dp[i] = _norm3(p0, p1, p2)
    j = 0
    for i in range(k):
        if still[i]:
            col[j] = du[i]
            j += 1
    du_lim = 3.0 * _median(col)
    j = 0
    for i in range(k):
        if still[i]:
            col[j] = dp[i]
            j += 1
    dp_lim = 3.0 * _median(col)
    use = np.zeros(k, np.bool_)
    count = 0
    for i in range(k):
        if pair[i] and ((du[i] > du_lim) or (dp[i] > dp_lim)):
            use[i] = True
            count += 1
    if count < 2:
        return 1, ah_ok, ref, 0.0, 0.0, 0.0, 0.0, 0.0, count
    bup = np.empty(3 * count)
    bpp = np.empty(3 * count)
    buu = np.empty(3 * count)
    bdu = np.empty(count)
    bdp = np.empty(count)
    j = 0
    for i in range(k):
        if use[i]:
            for c in range(3):
                bup[3 * j + c] = u[i, c] * p[i, c]
                bpp[3 * j + c] = p[i, c] * p[i, c]
                buu[3 * j + c] = u[i, c] * u[i, c]
            bdu[j] = du[i]
            bdp[j] = dp[i]
            j += 1
    f_lo, f_n, f_state, f_left = np.empty(64, np.int64), np.empty(64, np.int64), np.empty(64, np.int64), np.empty(64)
    up = _pairwise(bup, 3 * count, f_lo, f_n, f_left, f_state)
    pp = _pairwise(bpp, 3 * count, f_lo, f_n, f_left, f_state)
    uu = _pairwise(buu, 3 * count, f_lo, f_n, f_left, f_state)
    accel_tilt = _pairwise(bdu, count, f_lo, f_n, f_left, f_state)
    gyro_tilt = _pairwise(bdp, count, f_lo, f_n, f_left, f_state)
    return 2, ah_ok, ref, up, pp, uu, accel_tilt, gyro_tilt, count


def warm_up() -> None:
    """Compile (or load from numba's cache) :func:`window_stats`, :func:`window_fit` and :func:`percentile_linear`."""
    x = np.zeros((400, 3))
    window_stats(x, x, 150, np.zeros(400, np.bool_), True)
    am = np.tile([0.0, 0.0, 9.81], (4, 1))
    window_fit(am, np.zeros(4), np.zeros((4, 3)), np.zeros(4, np.bool_), 50, 0.001, 0.05)
    percentile_linear(np.zeros(3), 0.99)
