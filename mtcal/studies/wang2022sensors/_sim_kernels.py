"""Compiled sensor-error pass of :func:`mtcal.studies.wang2022sensors.runs.simulate_batch` and the latency
maximum of :func:`~mtcal.studies.wang2022sensors.runs.sweep_metrics` (private).

One pass over a block of trials writes the gyro and accelerometer records from the truth and the
trial's standard normals, with the operations of the numpy expression it replaces in the same
order, element by element (so the records are bit-identical; checked in
``tests/studies/test_wang2022sensors.py``)::

    accel = (((noise·√fs)·z_a + f) + σ_ba·z_ba) + b_a [+ rw_a·(cumsum(walk_a)·√Δt)]
    gyro  = (((N_g·√fs)·z_g + ω·(1 + s_g)) + b_g) + σ_bg·z_bg [+ rw_g·(cumsum(walk_g)·√Δt)]

``cumsum`` is numpy's sequential running sum along the samples. Kernels are float64 without
``fastmath`` (:func:`mtcal.core.compiled.jit`): no reassociation, no FMA contraction.
"""

from __future__ import annotations

import numpy as np

from mtcal.core.compiled import jit

__all__ = ["sensor_block", "latency_max_abs", "warm_up"]


@jit
def sensor_block(z, walk, has_walk, w_true, f, truth_row, noise_sq, t0, gyro_noise_sq, scale1, accel_bias, gyro_bias,
                 accel_bias_sigma, gyro_bias_sigma, sqrt_dt, accel_rw, gyro_rw, accel, gyro):
    """Rows ``t0 … t0 + B − 1`` of ``accel``/``gyro`` (T, N, 3) from block normals ``z`` (B, 2N + ≥2, 3) and
    ``walk`` (B, N, 6) (read only when ``has_walk``); ``w_true``/``f`` (R, N, 3), trial t reading row
    ``truth_row[t]`` (T,); ``noise_sq`` (T,)."""
    n = accel.shape[1]
    c = np.empty(6)
    for b in range(z.shape[0]):
        t = t0 + b
        tw = truth_row[t]
        tf = tw
        na = noise_sq[t]
        for j in range(6):
            c[j] = 0.0
        for k in range(n):
            for j in range(3):
                x = na * z[b, k, j]
                x = x + f[tf, k, j]
                x = x + accel_bias_sigma * z[b, 2 * n, j]
                x = x + accel_bias[j]
                y = gyro_noise_sq * z[b, n + k, j]
                y = y + w_true[tw, k, j] * scale1
                y = y + gyro_bias[j]
                y = y + gyro_bias_sigma * z[b, 2 * n + 1, j]
                if has_walk:
                    if k == 0:
                        c[j] = walk[b, k, j]
                        c[3 + j] = walk[b, k, 3 + j]
                    else:
                        c[j] = c[j] + walk[b, k, j]
                        c[3 + j] = c[3 + j] + walk[b, k, 3 + j]
                    x = x + accel_rw * (c[j] * sqrt_dt)
                    y = y + gyro_rw * (c[3 + j] * sqrt_dt)
                accel[t, k, j] = x
                gyro[t, k, j] = y


def warm_up() -> None:
    """Compile (or load from the cache) the kernel and the normals fill (:mod:`._pcg64_normals`) on a tiny input."""
    from . import _pcg64_normals

    _pcg64_normals.warm_up()
    latency_max_abs(np.zeros((1, 2)), np.zeros((1, 2)), np.ones((1, 2), np.bool_), np.empty((1, 1)))
    n = 2
    z = np.zeros((1, 2 * n + 4, 3))
    rec = np.zeros((1, n, 3))
    sensor_block(z, np.zeros((1, n, 6)), True, rec, rec, np.zeros(1, np.int64), np.ones(1), 0, 1.0, 1.0, np.zeros(3),
                 np.zeros(3), 0.0, 0.0, 1.0, 0.0, 0.0, np.empty((1, n, 3)), np.empty((1, n, 3)))


@jit
def latency_max_abs(err, delta, mask, out):
    """``out[t, l] = max_k |err[t, k] + delta[l, k]| · mask[t, k]`` for ``err`` (T, N), ``delta`` (L, N), ``mask``
    (T, N) bool: the numpy expression ``np.max(np.abs(err + d) * mask, axis=1)`` per latency (every term ≥ 0,
    so the maximum is the same number in any order; a NaN term gives NaN)."""
    for t in range(err.shape[0]):
        for ll in range(delta.shape[0]):
            m = 0.0
            for k in range(err.shape[1]):
                x = abs(err[t, k] + delta[ll, k]) * (1.0 if mask[t, k] else 0.0)
                if x != x:  # NaN propagates, as in numpy's max
                    m = x
                    break
                if k == 0 or x > m:
                    m = x
            out[t, ll] = m
