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

import numba
import numpy as np
from numba import prange

from mtcal.core.montecarlo import euler_errors as _euler_errors
from mtcal.filters._kernels_common import jit

__all__ = ["qncf_serial", "qncf_parallel"]

_T2 = 0.004 * 0.004   # |Δθ|² bound of the degree-2 series (TAYLOR2_MAX_INCREMENT_RAD²)
_T3 = 0.04 * 0.04     # |Δθ|² bound of the degree-3 series (TAYLOR_MAX_INCREMENT_RAD²)
#: |a|² below which a sample counts as "low" for the g-instead-of-m/s² check (MIN_MEDIAN_ACCEL_M_S2², with margin)
_LOW2 = 2.0 * 2.0 * (1.0 + 1e-9)
_C1, _C2, _C3 = -1.0 / 8.0, 1.0 / 384.0, -1.0 / 46080.0
_S0, _S1, _S2, _S3 = 0.5, -1.0 / 48.0, 1.0 / 3840.0, -1.0 / 645120.0


@numba.njit(inline="always")
def _step(q0, q1, q2, q3, i0, i1, i2, prev, ax, ay, az, wx, wy, wz, kp, kidt, use_ki, dt, alpha, gravity, thr):
    """One QNCF sample (AMD, gate, PI, increment, Eq 6); returns the new state, the gate and |a|²."""
    # AMD statistic and gate (QncfFilter._accel_chunk)
    n2 = (ax * ax + ay * ay) + az * az
    nrm = math.sqrt(n2)
    d = abs(nrm / gravity - 1.0) * 100.0
    prev = prev + (d - prev) * alpha
    gate = prev < thr
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
    nn1 = (h1 * q0 + q1 * c) + (q2 * h3 - q3 * h2)
    nn2 = (h2 * q0 + q2 * c) + (q3 * h1 - q1 * h3)
    nn3 = (h3 * q0 + q3 * c) + (q1 * h2 - q2 * h1)
    nq = math.sqrt(((n0 * n0 + nn1 * nn1) + nn2 * nn2) + nn3 * nn3)
    return n0 / nq, nn1 / nq, nn2 / nq, nn3 / nq, i0, i1, i2, prev, gate, n2


@jit()
def _lanes(w, a, t, nl, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
           keep, truth, stats, with_stats, chk):
    """Run trials ``t`` and ``t + 1`` (``nl`` = 2) over all samples of the chunk, updating their state.

    Two trials are stepped side by side in one loop: the recursion is latency-bound, so two
    independent dependency chains keep the core busy (each trial's arithmetic is unchanged).
    ``keep``: write ``q_out``/``amd_out``/``gate_out``. ``with_stats``: fold the wrapped Eq 8
    errors of the attitude at t_k against ``truth`` ((1 or T), M, 3: yaw, pitch, roll in rad) into
    ``stats[t]`` = (sum ×3, sum of squares ×3, max |·| ×3) — what
    :meth:`mtcal.core.montecarlo.ErrorAccumulator.add_euler_zxy_errors` computes from ``q_out``.
    ``chk[t]`` = (Σ 0·gyro, max |gyro|, Σ 0·accel, count of |a| < 2 m/s²): the input scan (0 sums =
    all finite), done here off the recursion's critical path instead of in separate passes.
    """
    u = t + 1 if nl == 2 else t          # lane b (a duplicate of lane a when nl = 1; never stored)
    m = w.shape[1]
    per_trial_truth = truth.shape[0] > 1
    tra = truth[t] if per_trial_truth else truth[0]
    trb = truth[u] if per_trial_truth else truth[0]
    fwa = fwb = faa = fab = wma = wmb = lowa = lowb = 0.0
    s0a = s1a = s2a = s0b = s1b = s2b = 0.0
    ss0a = ss1a = ss2a = ss0b = ss1b = ss2b = 0.0
    m0a = m1a = m2a = m0b = m1b = m2b = 0.0
    if with_stats:
        m0a, m1a, m2a = stats[t, 6], stats[t, 7], stats[t, 8]
        m0b, m1b, m2b = stats[u, 6], stats[u, 7], stats[u, 8]
    q0a, q1a, q2a, q3a = q[t, 0], q[t, 1], q[t, 2], q[t, 3]
    q0b, q1b, q2b, q3b = q[u, 0], q[u, 1], q[u, 2], q[u, 3]
    i0a, i1a, i2a = integ[t, 0], integ[t, 1], integ[t, 2]
    i0b, i1b, i2b = integ[u, 0], integ[u, 1], integ[u, 2]
    preva, prevb = amd[t], amd[u]
    if m > 0 and math.isnan(preva):
        ax, ay, az = a[t, 0, 0], a[t, 0, 1], a[t, 0, 2]
        preva = abs(math.sqrt((ax * ax + ay * ay) + az * az) / gravity - 1.0) * 100.0
    if m > 0 and math.isnan(prevb):
        ax, ay, az = a[u, 0, 0], a[u, 0, 1], a[u, 0, 2]
        prevb = abs(math.sqrt((ax * ax + ay * ay) + az * az) / gravity - 1.0) * 100.0
    for k in range(m):
        if keep:
            q_out[t, k, 0], q_out[t, k, 1], q_out[t, k, 2], q_out[t, k, 3] = q0a, q1a, q2a, q3a
            if nl == 2:
                q_out[u, k, 0], q_out[u, k, 1], q_out[u, k, 2], q_out[u, k, 3] = q0b, q1b, q2b, q3b
        if with_stats:
            e0, e1, e2 = _euler_errors(q0a, q1a, q2a, q3a, tra[k, 0], tra[k, 1], tra[k, 2])
            s0a += e0
            s1a += e1
            s2a += e2
            ss0a += e0 * e0
            ss1a += e1 * e1
            ss2a += e2 * e2
            m0a, m1a, m2a = max(m0a, abs(e0)), max(m1a, abs(e1)), max(m2a, abs(e2))
            e0, e1, e2 = _euler_errors(q0b, q1b, q2b, q3b, trb[k, 0], trb[k, 1], trb[k, 2])
            s0b += e0
            s1b += e1
            s2b += e2
            ss0b += e0 * e0
            ss1b += e1 * e1
            ss2b += e2 * e2
            m0b, m1b, m2b = max(m0b, abs(e0)), max(m1b, abs(e1)), max(m2b, abs(e2))
        axa, aya, aza = a[t, k, 0], a[t, k, 1], a[t, k, 2]
        wxa, wya, wza = w[t, k, 0], w[t, k, 1], w[t, k, 2]
        axb, ayb, azb = a[u, k, 0], a[u, k, 1], a[u, k, 2]
        wxb, wyb, wzb = w[u, k, 0], w[u, k, 1], w[u, k, 2]
        fwa = fwa + ((wxa * 0.0 + wya * 0.0) + wza * 0.0)
        faa = faa + ((axa * 0.0 + aya * 0.0) + aza * 0.0)
        wma = max(wma, max(abs(wxa), max(abs(wya), abs(wza))))
        fwb = fwb + ((wxb * 0.0 + wyb * 0.0) + wzb * 0.0)
        fab = fab + ((axb * 0.0 + ayb * 0.0) + azb * 0.0)
        wmb = max(wmb, max(abs(wxb), max(abs(wyb), abs(wzb))))
        q0a, q1a, q2a, q3a, i0a, i1a, i2a, preva, gatea, n2a = _step(
            q0a, q1a, q2a, q3a, i0a, i1a, i2a, preva, axa, aya, aza, wxa, wya, wza, kp, kidt, use_ki, dt, alpha,
            gravity, thr)
        q0b, q1b, q2b, q3b, i0b, i1b, i2b, prevb, gateb, n2b = _step(
            q0b, q1b, q2b, q3b, i0b, i1b, i2b, prevb, axb, ayb, azb, wxb, wyb, wzb, kp, kidt, use_ki, dt, alpha,
            gravity, thr)
        if n2a < _LOW2:
            lowa += 1.0
        if n2b < _LOW2:
            lowb += 1.0
        if keep:
            amd_out[t, k] = preva
            gate_out[t, k] = gatea
            if nl == 2:
                amd_out[u, k] = prevb
                gate_out[u, k] = gateb
    q[t, 0], q[t, 1], q[t, 2], q[t, 3] = q0a, q1a, q2a, q3a
    integ[t, 0], integ[t, 1], integ[t, 2] = i0a, i1a, i2a
    amd[t] = preva
    chk[t, 0], chk[t, 1], chk[t, 2], chk[t, 3] = fwa, wma, faa, lowa
    if with_stats:
        stats[t, 0] += s0a
        stats[t, 1] += s1a
        stats[t, 2] += s2a
        stats[t, 3] += ss0a
        stats[t, 4] += ss1a
        stats[t, 5] += ss2a
        stats[t, 6], stats[t, 7], stats[t, 8] = m0a, m1a, m2a
    if nl == 2:
        q[u, 0], q[u, 1], q[u, 2], q[u, 3] = q0b, q1b, q2b, q3b
        integ[u, 0], integ[u, 1], integ[u, 2] = i0b, i1b, i2b
        amd[u] = prevb
        chk[u, 0], chk[u, 1], chk[u, 2], chk[u, 3] = fwb, wmb, fab, lowb
        if with_stats:
            stats[u, 0] += s0b
            stats[u, 1] += s1b
            stats[u, 2] += s2b
            stats[u, 3] += ss0b
            stats[u, 4] += ss1b
            stats[u, 5] += ss2b
            stats[u, 6], stats[u, 7], stats[u, 8] = m0b, m1b, m2b


@jit()
def _trial(w, a, t, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
           keep, truth, stats, with_stats, chk):
    """One trial alone (same arithmetic as a lane of :func:`_lanes`; used for a single or odd trial)."""
    m = w.shape[1]
    tr = truth[t] if truth.shape[0] > 1 else truth[0]
    fw = fa = wm = low = 0.0
    s0 = s1 = s2 = ss0 = ss1 = ss2 = 0.0
    m0 = m1 = m2 = 0.0
    if with_stats:
        m0, m1, m2 = stats[t, 6], stats[t, 7], stats[t, 8]
    q0, q1, q2, q3 = q[t, 0], q[t, 1], q[t, 2], q[t, 3]
    i0, i1, i2 = integ[t, 0], integ[t, 1], integ[t, 2]
    prev = amd[t]
    if m > 0 and math.isnan(prev):
        ax, ay, az = a[t, 0, 0], a[t, 0, 1], a[t, 0, 2]
        prev = abs(math.sqrt((ax * ax + ay * ay) + az * az) / gravity - 1.0) * 100.0
    for k in range(m):
        if keep:
            q_out[t, k, 0], q_out[t, k, 1], q_out[t, k, 2], q_out[t, k, 3] = q0, q1, q2, q3
        if with_stats:
            e0, e1, e2 = _euler_errors(q0, q1, q2, q3, tr[k, 0], tr[k, 1], tr[k, 2])
            s0 += e0
            s1 += e1
            s2 += e2
            ss0 += e0 * e0
            ss1 += e1 * e1
            ss2 += e2 * e2
            m0, m1, m2 = max(m0, abs(e0)), max(m1, abs(e1)), max(m2, abs(e2))
        ax, ay, az = a[t, k, 0], a[t, k, 1], a[t, k, 2]
        wx, wy, wz = w[t, k, 0], w[t, k, 1], w[t, k, 2]
        fw = fw + ((wx * 0.0 + wy * 0.0) + wz * 0.0)
        fa = fa + ((ax * 0.0 + ay * 0.0) + az * 0.0)
        wm = max(wm, max(abs(wx), max(abs(wy), abs(wz))))
        q0, q1, q2, q3, i0, i1, i2, prev, gate, n2 = _step(
            q0, q1, q2, q3, i0, i1, i2, prev, ax, ay, az, wx, wy, wz, kp, kidt, use_ki, dt, alpha, gravity, thr)
        if n2 < _LOW2:
            low += 1.0
        if keep:
            amd_out[t, k] = prev
            gate_out[t, k] = gate
    q[t, 0], q[t, 1], q[t, 2], q[t, 3] = q0, q1, q2, q3
    integ[t, 0], integ[t, 1], integ[t, 2] = i0, i1, i2
    amd[t] = prev
    chk[t, 0], chk[t, 1], chk[t, 2], chk[t, 3] = fw, wm, fa, low
    if with_stats:
        stats[t, 0] += s0
        stats[t, 1] += s1
        stats[t, 2] += s2
        stats[t, 3] += ss0
        stats[t, 4] += ss1
        stats[t, 5] += ss2
        stats[t, 6], stats[t, 7], stats[t, 8] = m0, m1, m2


@jit()
def _pair(w, a, p, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
          keep, truth, stats, with_stats, chk):
    """Trials 2p and 2p + 1 (or 2p alone at the end)."""
    t = np.int64(p) * 2
    if t + 1 < w.shape[0]:
        _lanes(w, a, t, 2, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
               keep, truth, stats, with_stats, chk)
    else:
        _trial(w, a, t, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
               keep, truth, stats, with_stats, chk)


@jit()
def qncf_serial(w, a, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
                keep, truth, stats, with_stats, chk):
    """Trials one pair after the other (single-trial records, small batches)."""
    for p in range((w.shape[0] + 1) // 2):
        _pair(w, a, p, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
              keep, truth, stats, with_stats, chk)


@jit(parallel=True)
def qncf_parallel(w, a, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
                  keep, truth, stats, with_stats, chk):
    """Pairs of trials spread over numba's threads (``prange``); each trial computed exactly as serially."""
    for p in prange((w.shape[0] + 1) // 2):
        _pair(w, a, p, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
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
