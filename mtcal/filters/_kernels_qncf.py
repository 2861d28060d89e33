"""Compiled QNCF kernels (numba, float64): one trial, or trials in parallel (private).

Same recursion as :meth:`mtcal.filters.qncf.QncfFilter._step` and
``_accel_chunk`` (the numpy reference), written per scalar with the
reference's operation order (every sum is formed in the same order, every
product with the same operands), so the two engines agree to rounding of the
increment series choice: the numpy engine picks the series order for a whole
time block from a bound, the kernel per sample from the actual |Δθ|
(both series are exact to double precision, see ``QncfFilter._step``), which
also makes the kernel's result independent of chunking. Each trial is
processed independently, so the trial-parallel kernel gives bit-identical
results for any thread count.
"""

from __future__ import annotations

import math

import numpy as np
from numba import prange

from mtcal.core.montecarlo import _wrap
from mtcal.filters._kernels_common import jit

__all__ = ["qncf_serial", "qncf_parallel"]

_T2 = 0.004 * 0.004   # |Δθ|² bound of the degree-2 series (TAYLOR2_MAX_INCREMENT_RAD²)
_T3 = 0.04 * 0.04     # |Δθ|² bound of the degree-3 series (TAYLOR_MAX_INCREMENT_RAD²)
#: |a|² below which a sample counts as "low" for the g-instead-of-m/s² check (MIN_MEDIAN_ACCEL_M_S2², with margin)
_LOW2 = 2.0 * 2.0 * (1.0 + 1e-9)
_C1, _C2, _C3 = -1.0 / 8.0, 1.0 / 384.0, -1.0 / 46080.0
_S0, _S1, _S2, _S3 = 0.5, -1.0 / 48.0, 1.0 / 3840.0, -1.0 / 645120.0


@jit()
def _trial(w, a, t, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
           keep, truth, stats, with_stats, chk):
    """Run trial ``t`` over all samples of the chunk; state ``q[t]``, ``integ[t]``, ``amd[t]`` updated.

    ``keep``: write ``q_out``/``amd_out``/``gate_out``. ``with_stats``: fold the wrapped Eq 8
    errors of the attitude at t_k against ``truth`` ((1 or T), M, 3: yaw, pitch, roll in rad) into
    ``stats[t]`` = (sum ×3, sum of squares ×3, max |·| ×3) — what
    :meth:`mtcal.core.montecarlo.ErrorAccumulator.add_euler_zxy_errors` computes from ``q_out``.
    ``chk[t]`` = (Σ 0·gyro, max |gyro|, Σ 0·accel, count of |a| < 2 m/s²): the input scan (0 sums = all finite), done
    here off the recursion's critical path instead of in separate passes.
    """
    fw = 0.0
    fa = 0.0
    wm = 0.0
    low = 0.0
    tr = truth[t] if truth.shape[0] > 1 else truth[0]
    s0, s1, s2 = 0.0, 0.0, 0.0
    ss0, ss1, ss2 = 0.0, 0.0, 0.0
    m0, m1, m2 = 0.0, 0.0, 0.0
    if with_stats:
        m0, m1, m2 = stats[t, 6], stats[t, 7], stats[t, 8]
    q0 = q[t, 0]
    q1 = q[t, 1]
    q2 = q[t, 2]
    q3 = q[t, 3]
    i0 = integ[t, 0]
    i1 = integ[t, 1]
    i2 = integ[t, 2]
    m = w.shape[1]
    prev = amd[t]
    if m > 0 and math.isnan(prev):
        ax, ay, az = a[t, 0, 0], a[t, 0, 1], a[t, 0, 2]
        nrm = math.sqrt((ax * ax + ay * ay) + az * az)
        prev = abs(nrm / gravity - 1.0) * 100.0
    for k in range(m):
        if keep:
            q_out[t, k, 0] = q0
            q_out[t, k, 1] = q1
            q_out[t, k, 2] = q2
            q_out[t, k, 3] = q3
        if with_stats:  # Eq 8 of q_k and its wrapped error (rotations.euler_zxy_unchecked, angle_difference)
            s00, s11, s22, s33 = q0 * q0, q1 * q1, q2 * q2, q3 * q3
            yaw = math.atan2(-2.0 * (q1 * q2 - q0 * q3), ((s00 - s11) + s22) - s33)
            pitch = math.asin(min(max(2.0 * (q2 * q3 + q0 * q1), -1.0), 1.0))
            roll = math.atan2(-2.0 * (q1 * q3 - q0 * q2), ((s00 - s11) - s22) + s33)
            e0 = _wrap(yaw - tr[k, 0])
            e1 = _wrap(pitch - tr[k, 1])
            e2 = _wrap(roll - tr[k, 2])
            s0 += e0
            s1 += e1
            s2 += e2
            ss0 += e0 * e0
            ss1 += e1 * e1
            ss2 += e2 * e2
            m0 = max(m0, abs(e0))
            m1 = max(m1, abs(e1))
            m2 = max(m2, abs(e2))
        # AMD statistic and gate (QncfFilter._accel_chunk)
        ax, ay, az = a[t, k, 0], a[t, k, 1], a[t, k, 2]
        wx, wy, wz = w[t, k, 0], w[t, k, 1], w[t, k, 2]
        fw = fw + ((wx * 0.0 + wy * 0.0) + wz * 0.0)
        fa = fa + ((ax * 0.0 + ay * 0.0) + az * 0.0)
        wm = max(wm, max(abs(wx), max(abs(wy), abs(wz))))
        n2 = (ax * ax + ay * ay) + az * az
        nrm = math.sqrt(n2)
        if n2 < _LOW2:
            low += 1.0
        d = abs(nrm / gravity - 1.0) * 100.0
        prev = prev + (d - prev) * alpha
        gate = prev < thr
        if keep:
            amd_out[t, k] = prev
            gate_out[t, k] = gate
        fac = (1.0 if gate else 0.0) / max(nrm, 1e-12)
        ux, uy, uz = ax * fac, ay * fac, az * fac
        # predicted up direction v̂ = C(q)ᵀ e_z
        v0 = (q1 * q3 + (-(q0 * q2))) * 2.0
        v1 = (q2 * q3 + q0 * q1) * 2.0
        v2 = ((q0 * q0 + q3 * q3) - q1 * q1) - q2 * q2
        # e = â × v̂
        e0 = uy * v2 - uz * v1
        e1 = uz * v0 - ux * v2
        e2 = ux * v1 - uy * v0
        if use_ki:
            i0 = i0 + e0 * kidt
            i1 = i1 + e1 * kidt
            i2 = i2 + e2 * kidt
        x0 = ((e0 * kp + wx) + i0) * dt
        x1 = ((e1 * kp + wy) + i1) * dt
        x2 = ((e2 * kp + wz) + i2) * dt
        u = (x0 * x0 + x1 * x1) + x2 * x2
        if u <= _T2:
            c = (u * _C2 + _C1) * u + 1.0
            s = (u * _S2 + _S1) * u + _S0
        elif u <= _T3:
            c = ((u * _C3 + _C2) * u + _C1) * u + 1.0
            s = ((u * _S3 + _S2) * u + _S1) * u + _S0
        else:
            ang = math.sqrt(u)
            half = 0.5 * ang
            c = math.cos(half)
            if ang < 1e-8:
                s = 0.5 - ang ** 2 / 48.0
            else:
                s = math.sin(half) / ang
        h1 = x0 * s
        h2 = x1 * s
        h3 = x2 * s
        # q ← q ⊗ q(h), renormalised (Eq 6)
        n0 = q0 * c - ((q1 * h1 + q2 * h2) + q3 * h3)
        n1 = (h1 * q0 + q1 * c) + (q2 * h3 - q3 * h2)
        n2 = (h2 * q0 + q2 * c) + (q3 * h1 - q1 * h3)
        n3 = (h3 * q0 + q3 * c) + (q1 * h2 - q2 * h1)
        nq = math.sqrt(((n0 * n0 + n1 * n1) + n2 * n2) + n3 * n3)
        q0 = n0 / nq
        q1 = n1 / nq
        q2 = n2 / nq
        q3 = n3 / nq
    q[t, 0] = q0
    q[t, 1] = q1
    q[t, 2] = q2
    q[t, 3] = q3
    integ[t, 0] = i0
    integ[t, 1] = i1
    integ[t, 2] = i2
    amd[t] = prev
    chk[t, 0] = fw
    chk[t, 1] = wm
    chk[t, 2] = fa
    chk[t, 3] = low
    if with_stats:
        stats[t, 0] += s0
        stats[t, 1] += s1
        stats[t, 2] += s2
        stats[t, 3] += ss0
        stats[t, 4] += ss1
        stats[t, 5] += ss2
        stats[t, 6], stats[t, 7], stats[t, 8] = m0, m1, m2


@jit()
def qncf_serial(w, a, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
                keep, truth, stats, with_stats, chk):
    """Trials one after the other (single-trial records, small batches)."""
    for t in range(w.shape[0]):
        _trial(w, a, t, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
               keep, truth, stats, with_stats, chk)


@jit(parallel=True)
def qncf_parallel(w, a, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
                  keep, truth, stats, with_stats, chk):
    """Trials spread over numba's threads (``prange``); each trial is computed exactly as serially."""
    for t in prange(w.shape[0]):
        _trial(w, a, t, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
               keep, truth, stats, with_stats, chk)


def warm_up() -> None:
    """Compile (or load from the cache) both kernels on a tiny input."""
    w = np.zeros((2, 2, 3))
    a = np.zeros((2, 2, 3))
    a[..., 2] = 9.80665
    for fn in (qncf_serial, qncf_parallel):
        fn(w, a, np.tile([1.0, 0, 0, 0], (2, 1)), np.zeros((2, 3)), np.full(2, np.nan), np.empty((2, 2, 4)),
           np.empty((2, 2)), np.empty((2, 2), np.bool_), 1.0, 2e-5, True, 1e-3, 0.02, 9.80665, 0.3, True,
           np.zeros((1, 2, 3)), np.zeros((2, 9)), True, np.empty((2, 4)))
