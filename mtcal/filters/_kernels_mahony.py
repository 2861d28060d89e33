"""Compiled kernels of the IMU-only Mahony filter (numba, float64), trials stepped in SIMD lanes (private).

:func:`mahony_batch` runs :mod:`mtcal.filters.mahony`'s recursion over a (T, N, 3) batch in blocks of
:data:`LANES` trials (structure-of-arrays: one lane vector per state variable,
:mod:`mtcal.filters._kernels_lanes`), a lone last trial with the scalar kernel :func:`mahony_trial`. Each lane
performs the scalar kernel's IEEE-754 operations on the same operands in the same order (products and sums
as written there, ``cos``/``sin`` the same libm calls once per lane, the small-angle series a per-lane
select), so every trial is bit-identical to the scalar kernel run alone, whatever the batch (tested in
``tests/filters/test_mahony.py``). Serial: one thread (the sweep's workers are processes).
"""

from __future__ import annotations

import numpy as np

from mtcal.filters._kernels_common import jit
from mtcal.filters._kernels_lanes import (add, all_lt, cos, div, fill, mul, put, put3, rows4, rows8, simd_lanes, sin,
                                          sqrt, sub, take, take3, where_lt)

__all__ = ["LANES", "mahony_trial", "mahony_batch", "warm_up"]

#: Trials per SIMD block (:func:`mtcal.filters._kernels_lanes.simd_lanes`: 8 with AVX-512, else 4).
LANES = simd_lanes()
#: |Δθ| (rad) below which sin(|Δθ|/2)/|Δθ| is its two-term series.
_SMALL = 1e-4


@jit
def mahony_trial(gyro, accel, q0, dt, kp, ki, q_out, bias, t):  # pragma: no cover - compiled
    """Trial ``t``: Mahony 2008 Eq 32 with the gravity direction only (the filter's reference recursion)."""
    n = gyro.shape[1]
    a0, a1, a2, a3 = q0[t, 0], q0[t, 1], q0[t, 2], q0[t, 3]
    b0, b1, b2 = 0.0, 0.0, 0.0
    for k in range(n):
        q_out[t, k, 0] = a0
        q_out[t, k, 1] = a1
        q_out[t, k, 2] = a2
        q_out[t, k, 3] = a3
        v0 = 2.0 * (a1 * a3 - a0 * a2)
        v1 = 2.0 * (a2 * a3 + a0 * a1)
        v2 = a0 * a0 - a1 * a1 - a2 * a2 + a3 * a3
        x, y, z = accel[t, k, 0], accel[t, k, 1], accel[t, k, 2]
        nrm = np.sqrt(x * x + y * y + z * z)
        e0 = e1 = e2 = 0.0
        if nrm > 0.0:
            x, y, z = x / nrm, y / nrm, z / nrm
            e0 = y * v2 - z * v1
            e1 = z * v0 - x * v2
            e2 = x * v1 - y * v0
        b0 -= ki * e0 * dt
        b1 -= ki * e1 * dt
        b2 -= ki * e2 * dt
        w0 = (gyro[t, k, 0] - b0 + kp * e0) * dt
        w1 = (gyro[t, k, 1] - b1 + kp * e1) * dt
        w2 = (gyro[t, k, 2] - b2 + kp * e2) * dt
        ang = np.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
        c = np.cos(0.5 * ang)
        s = 0.5 - ang * ang / 48.0 if ang < _SMALL else np.sin(0.5 * ang) / ang
        h1, h2, h3 = s * w0, s * w1, s * w2
        n0 = a0 * c - a1 * h1 - a2 * h2 - a3 * h3
        n1 = a0 * h1 + a1 * c + a2 * h3 - a3 * h2
        n2 = a0 * h2 - a1 * h3 + a2 * c + a3 * h1
        n3 = a0 * h3 + a1 * h2 - a2 * h1 + a3 * c
        inv = 1.0 / np.sqrt(n0 * n0 + n1 * n1 + n2 * n2 + n3 * n3)
        a0, a1, a2, a3 = n0 * inv, n1 * inv, n2 * inv, n3 * inv
    bias[t, 0], bias[t, 1], bias[t, 2] = b0, b1, b2


@jit
def _block(gyro, accel, q0, dt, kp, ki, q_out, bias, rows):  # pragma: no cover - compiled
    """Trials ``rows`` (:data:`LANES` indices; a short block repeats its last) stepped together:
    :func:`mahony_trial`'s operations per lane, bit for bit."""
    n = gyro.shape[1]
    A0, A1, A2, A3 = take(q0, rows, 0), take(q0, rows, 1), take(q0, rows, 2), take(q0, rows, 3)
    zero = fill(A0, 0.0)
    one = fill(A0, 1.0)
    two = fill(A0, 2.0)
    half = fill(A0, 0.5)
    small = fill(A0, _SMALL)
    c48 = fill(A0, 48.0)
    KP, KI, DT = fill(A0, kp), fill(A0, ki), fill(A0, dt)
    B0 = B1 = B2 = zero
    for k in range(n):
        put3(q_out, rows, k, 0, A0)
        put3(q_out, rows, k, 1, A1)
        put3(q_out, rows, k, 2, A2)
        put3(q_out, rows, k, 3, A3)
        V0 = mul(two, sub(mul(A1, A3), mul(A0, A2)))
        V1 = mul(two, add(mul(A2, A3), mul(A0, A1)))
        V2 = add(sub(sub(mul(A0, A0), mul(A1, A1)), mul(A2, A2)), mul(A3, A3))
        X, Y, Z = take3(accel, rows, k, 0), take3(accel, rows, k, 1), take3(accel, rows, k, 2)
        NRM = sqrt(add(add(mul(X, X), mul(Y, Y)), mul(Z, Z)))
        X, Y, Z = div(X, NRM), div(Y, NRM), div(Z, NRM)
        E0 = where_lt(zero, NRM, sub(mul(Y, V2), mul(Z, V1)), zero)     # nrm > 0 (ordered), else 0
        E1 = where_lt(zero, NRM, sub(mul(Z, V0), mul(X, V2)), zero)
        E2 = where_lt(zero, NRM, sub(mul(X, V1), mul(Y, V0)), zero)
        B0 = sub(B0, mul(mul(KI, E0), DT))
        B1 = sub(B1, mul(mul(KI, E1), DT))
        B2 = sub(B2, mul(mul(KI, E2), DT))
        W0 = mul(add(sub(take3(gyro, rows, k, 0), B0), mul(KP, E0)), DT)
        W1 = mul(add(sub(take3(gyro, rows, k, 1), B1), mul(KP, E1)), DT)
        W2 = mul(add(sub(take3(gyro, rows, k, 2), B2), mul(KP, E2)), DT)
        ANG = sqrt(add(add(mul(W0, W0), mul(W1, W1)), mul(W2, W2)))
        HALF = mul(half, ANG)
        C = cos(HALF)
        S = sub(half, div(mul(ANG, ANG), c48))
        if not all_lt(ANG, small):
            S = where_lt(ANG, small, S, div(sin(HALF), ANG))
        H1, H2, H3 = mul(S, W0), mul(S, W1), mul(S, W2)
        N0 = sub(sub(sub(mul(A0, C), mul(A1, H1)), mul(A2, H2)), mul(A3, H3))
        N1 = sub(add(add(mul(A0, H1), mul(A1, C)), mul(A2, H3)), mul(A3, H2))
        N2 = add(add(sub(mul(A0, H2), mul(A1, H3)), mul(A2, C)), mul(A3, H1))
        N3 = add(sub(add(mul(A0, H3), mul(A1, H2)), mul(A2, H1)), mul(A3, C))
        INV = div(one, sqrt(add(add(add(mul(N0, N0), mul(N1, N1)), mul(N2, N2)), mul(N3, N3))))
        A0, A1, A2, A3 = mul(N0, INV), mul(N1, INV), mul(N2, INV), mul(N3, INV)
    put(bias, rows, 0, B0)
    put(bias, rows, 1, B1)
    put(bias, rows, 2, B2)


_rows = rows8 if LANES == 8 else rows4


@jit
def mahony_batch(gyro, accel, q0, dt, kp, ki, q_out, bias):  # pragma: no cover - compiled
    """Every trial of a (T, N, 3) batch: blocks of :data:`LANES` trials in lanes, a lone last trial scalar.

    ``gyro``, ``accel`` C-contiguous float64 (T, N, 3); ``q0`` (T, 4); writes ``q_out`` (T, N, 4) (the
    attitude before sample k) and ``bias`` (T, 3) (the final gyro-bias estimate).
    """
    trials = gyro.shape[0]
    for b in range((trials + LANES - 1) // LANES):
        t0 = np.int64(b) * LANES
        nl = min(LANES, trials - t0)
        if nl == 1:
            mahony_trial(gyro, accel, q0, dt, kp, ki, q_out, bias, t0)
        else:
            _block(gyro, accel, q0, dt, kp, ki, q_out, bias, _rows(t0, nl))


def warm_up() -> None:
    """Compile (or load from the cache) the kernel on a tiny input."""
    a = np.zeros((2, 2, 3))
    a[..., 2] = 9.80665
    mahony_batch(np.zeros((2, 2, 3)), a, np.tile([1.0, 0, 0, 0], (2, 1)), 1e-3, 1.0, 0.02, np.empty((2, 2, 4)),
                 np.empty((2, 3)))
