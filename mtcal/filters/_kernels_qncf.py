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

Batches run as blocks of :data:`LANES` trials (8 with AVX-512, else 4) in
structure-of-arrays form (:func:`_block`: one SIMD vector per state variable,
held in a true LLVM vector type, :class:`mtcal.filters._kernels_lanes.VecType`),
blocks handed to numba's threads (one contiguous range each, shared at the end);
each lane performs the scalar kernel's operations on the same operands, so a
batched trial is bit-identical to the same trial run alone (:func:`_trial`, used
for single-trial records and a last lone trial).
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba import prange

from mtcal.core.montecarlo import (ASIN_C3, ASIN_C5, ASIN_C7, ASIN_C9, ATAN_C3, ATAN_C5, ATAN_C7, ATAN_C9, SERIES_MAX,
                                   table_errors)
from mtcal.filters._kernels_lanes import (add, all_le, all_lt, div, fabs, fill, lane_ids, mul, put, put1, put3,
                                          put_lt, rows4, rows8, simd_lanes, sqrt, sub, take, take1, take3, vmax,
                                          where_le, where_lt)
from mtcal.filters._kernels_common import claim, jit, schedule

__all__ = ["qncf_one", "qncf_serial", "qncf_parallel"]

_T2 = 0.004 * 0.004   # |Δθ|² bound of the degree-2 series (TAYLOR2_MAX_INCREMENT_RAD²)
_T3 = 0.04 * 0.04     # |Δθ|² bound of the degree-3 series (TAYLOR_MAX_INCREMENT_RAD²)
#: |a|² below which a sample counts as "low" for the g-instead-of-m/s² check (MIN_MEDIAN_ACCEL_M_S2², with margin)
_LOW2 = 2.0 * 2.0 * (1.0 + 1e-9)
#: Trials per SIMD block (:func:`mtcal.filters._kernels_lanes.simd_lanes`: 8 with AVX-512, else 4).
LANES = simd_lanes()
_C1, _C2, _C3 = -1.0 / 8.0, 1.0 / 384.0, -1.0 / 46080.0
_S0, _S1, _S2, _S3 = 0.5, -1.0 / 48.0, 1.0 / 3840.0, -1.0 / 645120.0


@numba.njit(inline="always")
def _cs(u):
    """cos(|Δθ|/2) and sin(|Δθ|/2)/|Δθ| from u = |Δθ|², the series of degree 2 or 3 below their bounds, else exact."""
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
    return c, s


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
    c, s = _cs(u)
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
def _trial(w, a, t, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
           keep, truth, stats, with_stats, chk):
    """One trial alone (same arithmetic as a lane of :func:`_block`; used for a single or a last lone trial)."""
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
            e0, e1, e2 = table_errors(q0, q1, q2, q3, tr[k])
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
def _block(w, a, rows, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
           keep, truth, stats, with_stats, chk):
    """Trials ``rows`` (a tuple of :data:`LANES` trial indices) stepped together, one lane vector per state variable.

    Structure-of-arrays over trials: every state variable is a lane vector (one trial per lane,
    held in a true LLVM vector type, :class:`~mtcal.filters._kernels_lanes.VecType`: one vector
    register or spill slot, no per-step re-packing), each lane's operations are :func:`_step`'s
    with the same operands in the same order (the increment series is a per-lane select of the
    same two polynomials; a step where a lane needs the trigonometric increment, or has a NaN,
    takes the scalar :func:`_cs` per lane), so every trial is bit-identical to :func:`_trial`.
    Rows may repeat (the last trial of a short block fills the spare lanes): a repeated lane
    computes the same values bit for bit and stores them to the same places. Arguments as for
    :func:`_trial`.
    """
    m = w.shape[1]
    per_trial_truth = truth.shape[0] > 1
    Q0, Q1, Q2, Q3 = take(q, rows, 0), take(q, rows, 1), take(q, rows, 2), take(q, rows, 3)
    I0, I1, I2 = take(integ, rows, 0), take(integ, rows, 1), take(integ, rows, 2)
    P = take1(amd, rows)
    ids = lane_ids(P)
    spill = np.empty((len(ids), 7))   # per-lane scalar fallbacks: lanes in rows, values in columns
    if m > 0:  # a NaN AMD state starts from the first sample's statistic (as _trial)
        AX, AY, AZ = take3(a, rows, 0, 0), take3(a, rows, 0, 1), take3(a, rows, 0, 2)
        D = mul(fabs(add(div(sqrt(add(add(mul(AX, AX), mul(AY, AY)), mul(AZ, AZ))), fill(P, gravity)),
                         fill(P, -1.0))), fill(P, 100.0))
        P = where_le(P, P, P, D)
    zero = fill(P, 0.0)
    one = fill(P, 1.0)
    FW = FA = WM = LOW = zero
    S0 = S1 = S2 = SS0 = SS1 = SS2 = zero
    M0 = M1 = M2 = zero
    if with_stats:
        M0, M1, M2 = take(stats, rows, 6), take(stats, rows, 7), take(stats, rows, 8)
    KP, KIDT, DT, ALPHA, GRAV, THR = (fill(P, kp), fill(P, kidt), fill(P, dt), fill(P, alpha), fill(P, gravity),
                                      fill(P, thr))
    for k in range(m):
        if keep:
            put3(q_out, rows, k, 0, Q0)
            put3(q_out, rows, k, 1, Q1)
            put3(q_out, rows, k, 2, Q2)
            put3(q_out, rows, k, 3, Q3)
        if with_stats:
            E0, E1, E2 = _errors(Q0, Q1, Q2, Q3, truth, per_trial_truth, rows, k, spill)
            S0, S1, S2 = add(S0, E0), add(S1, E1), add(S2, E2)
            SS0, SS1, SS2 = add(SS0, mul(E0, E0)), add(SS1, mul(E1, E1)), add(SS2, mul(E2, E2))
            M0, M1, M2 = vmax(M0, fabs(E0)), vmax(M1, fabs(E1)), vmax(M2, fabs(E2))
        AX, AY, AZ = take3(a, rows, k, 0), take3(a, rows, k, 1), take3(a, rows, k, 2)
        WX, WY, WZ = take3(w, rows, k, 0), take3(w, rows, k, 1), take3(w, rows, k, 2)
        # input scan (see _trial)
        FW = add(FW, add(add(mul(WX, zero), mul(WY, zero)), mul(WZ, zero)))
        FA = add(FA, add(add(mul(AX, zero), mul(AY, zero)), mul(AZ, zero)))
        WM = vmax(WM, vmax(fabs(WX), vmax(fabs(WY), fabs(WZ))))
        # AMD statistic and gate
        N2 = add(add(mul(AX, AX), mul(AY, AY)), mul(AZ, AZ))
        NRM = sqrt(N2)
        D = mul(fabs(add(div(NRM, GRAV), fill(P, -1.0))), fill(P, 100.0))
        P = add(P, mul(sub(D, P), ALPHA))
        FAC = div(where_lt(P, THR, one, zero), vmax(NRM, fill(P, 1e-12)))
        UX, UY, UZ = mul(AX, FAC), mul(AY, FAC), mul(AZ, FAC)
        # predicted up direction and e = â × v̂
        two = fill(P, 2.0)
        V0 = mul(sub(mul(Q1, Q3), mul(Q0, Q2)), two)
        V1 = mul(add(mul(Q2, Q3), mul(Q0, Q1)), two)
        V2 = sub(sub(add(mul(Q0, Q0), mul(Q3, Q3)), mul(Q1, Q1)), mul(Q2, Q2))
        E0 = sub(mul(UY, V2), mul(UZ, V1))
        E1 = sub(mul(UZ, V0), mul(UX, V2))
        E2 = sub(mul(UX, V1), mul(UY, V0))
        if use_ki:
            I0, I1, I2 = add(I0, mul(E0, KIDT)), add(I1, mul(E1, KIDT)), add(I2, mul(E2, KIDT))
        X0 = mul(add(add(mul(E0, KP), WX), I0), DT)
        X1 = mul(add(add(mul(E1, KP), WY), I1), DT)
        X2 = mul(add(add(mul(E2, KP), WZ), I2), DT)
        U = add(add(mul(X0, X0), mul(X1, X1)), mul(X2, X2))
        if all_le(U, fill(P, _T3)):  # series: a select per lane
            T2 = fill(P, _T2)
            C = where_le(U, T2, add(mul(add(mul(U, fill(P, _C2)), fill(P, _C1)), U), one),
                         add(mul(add(mul(add(mul(U, fill(P, _C3)), fill(P, _C2)), U), fill(P, _C1)), U), one))
            S = where_le(U, T2, add(mul(add(mul(U, fill(P, _S2)), fill(P, _S1)), U), fill(P, _S0)),
                         add(mul(add(mul(add(mul(U, fill(P, _S3)), fill(P, _S2)), U), fill(P, _S1)), U),
                             fill(P, _S0)))
        else:
            put(spill, ids, 0, U)
            for j in range(len(ids)):
                spill[j, 1], spill[j, 2] = _cs(spill[j, 0])
            C, S = take(spill, ids, 1), take(spill, ids, 2)
        H1, H2, H3 = mul(X0, S), mul(X1, S), mul(X2, S)
        N0 = sub(mul(Q0, C), add(add(mul(Q1, H1), mul(Q2, H2)), mul(Q3, H3)))
        NN1 = add(add(mul(H1, Q0), mul(Q1, C)), sub(mul(Q2, H3), mul(Q3, H2)))
        NN2 = add(add(mul(H2, Q0), mul(Q2, C)), sub(mul(Q3, H1), mul(Q1, H3)))
        NN3 = add(add(mul(H3, Q0), mul(Q3, C)), sub(mul(Q1, H2), mul(Q2, H1)))
        NQ = sqrt(add(add(add(mul(N0, N0), mul(NN1, NN1)), mul(NN2, NN2)), mul(NN3, NN3)))
        Q0, Q1, Q2, Q3 = div(N0, NQ), div(NN1, NQ), div(NN2, NQ), div(NN3, NQ)
        LOW = add(LOW, where_lt(N2, fill(P, _LOW2), one, zero))
        if keep:
            put(amd_out, rows, k, P)
            put_lt(gate_out, rows, k, P, THR)
    put(q, rows, 0, Q0)
    put(q, rows, 1, Q1)
    put(q, rows, 2, Q2)
    put(q, rows, 3, Q3)
    put(integ, rows, 0, I0)
    put(integ, rows, 1, I1)
    put(integ, rows, 2, I2)
    put1(amd, rows, P)
    put(chk, rows, 0, FW)
    put(chk, rows, 1, WM)
    put(chk, rows, 2, FA)
    put(chk, rows, 3, LOW)
    if with_stats:  # every lane reads its row before any lane stores (repeated rows add once)
        put(stats, rows, 0, add(take(stats, rows, 0), S0))
        put(stats, rows, 1, add(take(stats, rows, 1), S1))
        put(stats, rows, 2, add(take(stats, rows, 2), S2))
        put(stats, rows, 3, add(take(stats, rows, 3), SS0))
        put(stats, rows, 4, add(take(stats, rows, 4), SS1))
        put(stats, rows, 5, add(take(stats, rows, 5), SS2))
        put(stats, rows, 6, M0)
        put(stats, rows, 7, M1)
        put(stats, rows, 8, M2)


@numba.njit(inline="always")
def _row(table, per_trial_truth, rows, k, j, like):
    """Lane vector of column ``j`` of the truth table at t_k (one load broadcast for a shared truth)."""
    if per_trial_truth:
        return take3(table, rows, k, j)
    return fill(like, table[0, k, j])


@numba.njit(inline="always")
def _atan_small_lanes(R):
    """Lane form of :func:`mtcal.core.montecarlo.atan_small` (same operations per lane)."""
    U = mul(R, R)
    return add(R, mul(R, mul(U, add(mul(U, add(mul(U, add(mul(U, fill(R, ATAN_C9)), fill(R, ATAN_C7))),
                                                 fill(R, ATAN_C5))), fill(R, ATAN_C3)))))


@numba.njit(inline="always")
def _asin_small_lanes(Y):
    """Lane form of :func:`mtcal.core.montecarlo.asin_small` (same operations per lane)."""
    U = mul(Y, Y)
    return add(Y, mul(Y, mul(U, add(mul(U, add(mul(U, add(mul(U, fill(Y, ASIN_C9)), fill(Y, ASIN_C7))),
                                                 fill(Y, ASIN_C5))), fill(Y, ASIN_C3)))))


@numba.njit(inline="always")
def _errors(Q0, Q1, Q2, Q3, table, per_trial_truth, rows, k, spill):
    """Per lane Eq 8 errors against the truth table row at t_k: :func:`mtcal.core.montecarlo.euler_errors_cs`
    as lane vectors when every lane takes its series path, else that scalar function per lane (bit-identical
    either way: the lane operations are the scalar ones with the same operands in the same order)."""
    C0 = _row(table, per_trial_truth, rows, k, 3, Q0)
    S0 = _row(table, per_trial_truth, rows, k, 4, Q0)
    C1 = _row(table, per_trial_truth, rows, k, 5, Q0)
    S1 = _row(table, per_trial_truth, rows, k, 6, Q0)
    C2 = _row(table, per_trial_truth, rows, k, 7, Q0)
    S2 = _row(table, per_trial_truth, rows, k, 8, Q0)
    S00, S11, S22, S33 = mul(Q0, Q0), mul(Q1, Q1), mul(Q2, Q2), mul(Q3, Q3)
    m2 = fill(Q0, -2.0)
    YX = sub(add(sub(S00, S11), S22), S33)
    YY = mul(sub(mul(Q1, Q2), mul(Q0, Q3)), m2)
    A = mul(add(mul(Q2, Q3), mul(Q0, Q1)), fill(Q0, 2.0))
    A = vmax(A, fill(Q0, -1.0))
    one = fill(Q0, 1.0)
    A = where_lt(one, A, one, A)               # min(a, 1.0) as numba computes it
    RX = add(sub(sub(S00, S11), S22), S33)
    RY = mul(sub(mul(Q1, Q3), mul(Q0, Q2)), m2)
    XA = add(mul(YX, C0), mul(YY, S0))
    YA = sub(mul(YY, C0), mul(YX, S0))
    CE = sqrt(mul(sub(one, A), add(A, one)))
    XB = add(mul(CE, C1), mul(A, S1))
    YB = sub(mul(A, C1), mul(CE, S1))
    XC = add(mul(RX, C2), mul(RY, S2))
    YC = sub(mul(RY, C2), mul(RX, S2))
    # the scalar's test |ya| < SERIES_MAX·xa, |yb| < SERIES_MAX, xb > 0, |yc| < SERIES_MAX·xc, in every lane
    smax = fill(Q0, SERIES_MAX)
    if (all_lt(fabs(YA), mul(XA, smax)) and all_lt(fabs(YB), smax) and all_lt(fill(Q0, 0.0), XB)
            and all_lt(fabs(YC), mul(XC, smax))):
        return _atan_small_lanes(div(YA, XA)), _asin_small_lanes(YB), _atan_small_lanes(div(YC, XC))
    ids = lane_ids(Q0)
    put(spill, ids, 0, Q0)
    put(spill, ids, 1, Q1)
    put(spill, ids, 2, Q2)
    put(spill, ids, 3, Q3)
    for j in range(len(ids)):
        r = table[rows[j]] if per_trial_truth else table[0]
        spill[j, 4], spill[j, 5], spill[j, 6] = table_errors(spill[j, 0], spill[j, 1], spill[j, 2], spill[j, 3],
                                                             r[k])
    return take(spill, ids, 4), take(spill, ids, 5), take(spill, ids, 6)


_rows = rows8 if LANES == 8 else rows4


@jit()
def _run_block(w, a, b, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
               keep, truth, stats, with_stats, chk):
    """Block ``b`` of :data:`LANES` trials (vector lanes), or its single trial with the scalar kernel."""
    t0 = np.int64(b) * LANES
    nl = min(LANES, w.shape[0] - t0)
    if nl == 1:
        _trial(w, a, t0, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
               keep, truth, stats, with_stats, chk)
    else:
        _block(w, a, _rows(t0, nl), q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity,
               thr, keep, truth, stats, with_stats, chk)


@jit()
def qncf_serial(w, a, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
                keep, truth, stats, with_stats, chk):
    """Blocks of :data:`LANES` trials one after the other (small batches, one thread per worker)."""
    for b in range((w.shape[0] + LANES - 1) // LANES):
        _run_block(w, a, b, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
                   keep, truth, stats, with_stats, chk)


@jit()
def qncf_one(w, a, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
             keep, truth, stats, with_stats, chk):
    """Trials one after the other with the scalar kernel only (single-trial records: the smallest code for
    numba to load from its cache, ~0.2 s less start-up for a CLI call)."""
    for t in range(w.shape[0]):
        _trial(w, a, t, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
               keep, truth, stats, with_stats, chk)


@jit(parallel=True)
def _qncf_parallel(w, a, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
                   keep, truth, stats, with_stats, chk, counter, workers):
    """Blocks of :data:`LANES` trials spread over numba's threads: ``workers`` ``prange`` iterations (one per
    thread) each run their own contiguous range of blocks in order, then help with the others' from their far
    end (:func:`~mtcal.filters._kernels_common.claim`: a dynamic schedule that keeps the threads apart);
    each trial computed exactly as serially."""
    nb = (w.shape[0] + LANES - 1) // LANES
    for i in prange(workers):
        for j in range(workers):
            r = (i + j) % workers
            lo, hi = r * nb // workers, (r + 1) * nb // workers
            b = claim(counter, r, lo, hi, j == 0)
            while b >= 0:
                _run_block(w, a, b, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity,
                           thr, keep, truth, stats, with_stats, chk)
                b = claim(counter, r, lo, hi, j == 0)


def qncf_parallel(*args) -> None:
    """:func:`_qncf_parallel` on numba's threads (one range of blocks each, shared at the end).
    Arguments as :func:`qncf_serial`."""
    workers = numba.get_num_threads()
    _qncf_parallel(*args, schedule(workers), workers)


def warm_up() -> None:
    """Compile (or load from the cache) both kernels on a tiny input."""
    w = np.zeros((2, 2, 3))
    a = np.zeros((2, 2, 3))
    a[..., 2] = 9.80665
    for fn in (qncf_one, qncf_serial, qncf_parallel):
        fn(w, a, np.tile([1.0, 0, 0, 0], (2, 1)), np.zeros((2, 3)), np.full(2, np.nan), np.empty((2, 2, 4)),
           np.empty((2, 2)), np.empty((2, 2), np.bool_), 1.0, 2e-5, True, 1e-3, 0.02, 9.80665, 0.3, True,
           np.zeros((1, 2, 9)), np.zeros((2, 9)), True, np.empty((2, 4)))
