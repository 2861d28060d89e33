"""Compiled Table 1 ZVD of :func:`mtcal.methods.zero_velocity.detect_static`, bit for bit numpy's.

One pass per record instead of the numpy expression's dozen full-size temporaries; every
floating-point operation is the one numpy performs, in its order (checked bit for bit against
the numpy expression in ``tests/methods/test_zero_velocity.py``):

* ``np.linalg.norm(x, axis=-1)`` of a C-contiguous (…, 3) array: ``sqrt((x0² + x1²) + x2²)``;
* the trailing moving variance of ``d = (‖a‖ − g) − (‖a‖₀ − g)``: numpy's ``cumsum`` is a sequential
  running sum, ``c_k = c_(k−1) + d_k``; window sums ``C[stop] − C[start]`` with ``C[0] = 0``;
  ``max(s2 / n − (s1 / n)², 0)``;
* the causal run length of the joint condition (flag once it has held ``n_h`` samples).

Kernels are float64 without ``fastmath`` (:func:`mtcal.core.compiled.jit`): no reassociation
and no FMA contraction.
"""

from __future__ import annotations

import math

import numpy as np

from mtcal.core.compiled import jit

__all__ = ["zvd_flags", "warm_up"]


@jit
def zvd_flags(a, g, use_gyro, has_offset, offset, gravity, amin, amax, thr, window, n_h, gmax, out):
    """Static flags ``out`` (M, N) of records ``a`` (M, N, 3) (and ``g`` (M, N, 3) when ``use_gyro``, less
    ``offset[t]`` (M, 3) per record when ``has_offset``: ``‖ω − offset‖``, the difference taken first)."""
    n = a.shape[1]
    c1 = np.empty(n + 1)
    c2 = np.empty(n + 1)
    for t in range(a.shape[0]):
        c1[0] = 0.0
        c2[0] = 0.0
        x0 = 0.0
        for k in range(n):
            ax, ay, az = a[t, k, 0], a[t, k, 1], a[t, k, 2]
            x = math.sqrt((ax * ax + ay * ay) + az * az) - gravity
            if k == 0:
                x0 = x
            d = x - x0
            if k == 0:
                c1[1] = d
                c2[1] = d * d
            else:
                c1[k + 1] = c1[k] + d
                c2[k + 1] = c2[k] + d * d
        last_false = -1
        for k in range(n):
            ax, ay, az = a[t, k, 0], a[t, k, 1], a[t, k, 2]
            mag = math.sqrt((ax * ax + ay * ay) + az * az)
            stop = k + 1
            start = max(stop - window, 0)
            count = float(stop - start)
            s1 = c1[stop] - c1[start]
            s2 = c2[stop] - c2[start]
            mean = s1 / count
            var = max(s2 / count - mean * mean, 0.0)
            cond = (mag > amin) and (mag < amax) and (var < thr)
            if cond and use_gyro:
                gx, gy, gz = g[t, k, 0], g[t, k, 1], g[t, k, 2]
                if has_offset:
                    gx, gy, gz = gx - offset[t, 0], gy - offset[t, 1], gz - offset[t, 2]
                cond = math.sqrt((gx * gx + gy * gy) + gz * gz) < gmax
            if not cond:
                last_false = k
            out[t, k] = (k - last_false) >= n_h


def warm_up() -> None:
    """Compile (or load from the cache) the kernel on a tiny input."""
    a = np.zeros((1, 2, 3))
    a[..., 2] = 9.8
    for use_gyro in (False, True):
        zvd_flags(a, a, use_gyro, use_gyro, np.zeros((1, 3)), 9.80665, 9.76, 9.84, 1e-3, 3, 2, 0.03,
                  np.empty((1, 2), np.bool_))
