"""Compiled row formatter of :mod:`mtcal.core.csvtext` (private; imported on first use)."""

from __future__ import annotations

import numba
import numpy as np

from mtcal.core.compiled import jit

__all__ = ["format_block"]


@numba.njit(inline="always")
def _put_uint(out, pos, v, buf):
    """Decimal digits of ``v`` (≥ 0) at ``out[pos:]``; returns the new position."""
    nd = 0
    while True:
        buf[nd] = 48 + v % 10
        v //= 10
        nd += 1
        if v == 0:
            break
    for i in range(nd):
        out[pos + i] = buf[nd - 1 - i]
    return pos + nd


@jit
def format_block(vals, factor, p10, decimals, is_int, out):
    """CSV rows of ``vals`` (R, C) into ``out`` (uint8); returns the bytes used.

    Column c is an integer column (``is_int[c]``) or a float column printed as
    ``np.round(x, decimals[c])`` in Arrow's shortest form: ``K = rint(x · factor[c])``
    (``factor = 10^d`` as a double, ``p10`` the same as an integer), digits of ``|K|``
    with trailing zeros dropped, ``-`` for a negative (also zero) result, exponent
    notation ``d.ddde-N`` when ``|K| 10^-d < 1e-6``; NaN prints nothing.
    """
    rows, cols = vals.shape
    pos = 0
    buf = np.empty(48, np.int64)
    for row in range(rows):
        for c in range(cols):
            if c:
                out[pos] = 44  # ','
                pos += 1
            x = vals[row, c]
            if np.isnan(x):
                continue
            if is_int[c]:
                v = np.int64(x)
                if v < 0:
                    out[pos] = 45
                    pos += 1
                    v = -v
                pos = _put_uint(out, pos, v, buf)
                continue
            k = np.rint(x * factor[c])
            if k < 0.0 or (k == 0.0 and np.signbit(k)):
                out[pos] = 45  # '-'
                pos += 1
            kk = np.int64(abs(k))
            if kk == 0:
                out[pos] = 48
                pos += 1
                continue
            d = decimals[c]
            # digits of kk, least significant first, two per division
            nd = 0
            t = kk
            while t >= 100:
                hi = t // 100
                two = t - hi * 100
                q10 = two // 10
                buf[nd] = two - q10 * 10
                buf[nd + 1] = q10
                nd += 2
                t = hi
            if t >= 10:
                q10 = t // 10
                buf[nd] = t - q10 * 10
                buf[nd + 1] = q10
                nd += 2
            else:
                buf[nd] = t
                nd += 1
            lo = 0  # trailing zeros dropped
            while buf[lo] == 0:
                lo += 1
            exp10 = nd - 1 - d  # decimal exponent of the leading digit
            if exp10 < -6:  # Arrow: exponent notation below 1e-6
                out[pos] = 48 + buf[nd - 1]
                pos += 1
                if nd - 1 > lo:
                    out[pos] = 46
                    pos += 1
                    for i in range(nd - 2, lo - 1, -1):
                        out[pos] = 48 + buf[i]
                        pos += 1
                out[pos] = 101  # 'e'
                out[pos + 1] = 45
                pos = _put_uint(out, pos + 2, -exp10, buf[nd:])
                continue
            ip = kk // p10[c]
            pos = _put_uint(out, pos, ip, buf[nd:])
            if lo < d:  # fraction digits d-1 … lo (buf index), zero-padded on the left
                out[pos] = 46  # '.'
                pos += 1
                for i in range(d - 1, lo - 1, -1):
                    out[pos] = 48 + (buf[i] if i < nd else 0)
                    pos += 1
        out[pos] = 10  # '\n'
        pos += 1
    return pos
