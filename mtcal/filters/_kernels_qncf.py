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

Batches run as blocks of four trials in structure-of-arrays form
(:func:`_block`: one 4-lane SIMD vector per state variable,
:mod:`mtcal.filters._kernels_lanes`), blocks spread over threads with
``prange``; each lane performs the scalar kernel's operations on the same
operands, so a batched trial is bit-identical to the same trial run alone
(:func:`_trial`, used for single-trial records and a last lone trial).
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba import prange

from mtcal.core.montecarlo import (ASIN_C3, ASIN_C5, ASIN_C7, ASIN_C9, ATAN_C3, ATAN_C5, ATAN_C7, ATAN_C9, SERIES_MAX,
                                   table_errors)
from mtcal.filters._kernels_lanes import (add, adds, bc, div, divs, fabs, maxs, mul, muls, sqrt, sub, vmax,
                                          where_le, where_lt)
from mtcal.filters._kernels_common import jit

__all__ = ["qncf_one", "qncf_serial", "qncf_parallel"]

_T2 = 0.004 * 0.004   # |Δθ|² bound of the degree-2 series (TAYLOR2_MAX_INCREMENT_RAD²)
_T3 = 0.04 * 0.04     # |Δθ|² bound of the degree-3 series (TAYLOR_MAX_INCREMENT_RAD²)
#: |a|² below which a sample counts as "low" for the g-instead-of-m/s² check (MIN_MEDIAN_ACCEL_M_S2², with margin)
_LOW2 = 2.0 * 2.0 * (1.0 + 1e-9)
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


@numba.njit(inline="always")
def _lane(x, i0, i1, i2, i3):
    """(x[i0], x[i1], x[i2], x[i3]) of a 1-D array."""
    return (x[i0], x[i1], x[i2], x[i3])


@jit()
def _block(w, a, t0, nl, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
           keep, truth, stats, with_stats, chk):
    """Trials ``t0 … t0 + nl - 1`` (``nl`` ≤ 4) stepped together as one 4-lane vector per state variable.

    Structure-of-arrays over trials: every state variable is a 4-tuple (one lane per trial,
    :mod:`mtcal.filters._kernels_lanes`), each lane's operations are :func:`_step`'s with the
    same operands in the same order (the increment series is a per-lane select of the same two
    polynomials; a block where a lane needs the trigonometric increment, or has a NaN, takes the
    scalar :func:`_cs` per lane), so every trial is bit-identical to :func:`_trial`. Lanes past
    ``nl`` repeat the last trial and are never stored. Arguments as for :func:`_trial`.
    """
    m = w.shape[1]
    ta, tb, tc, td = t0, t0 + min(1, nl - 1), t0 + min(2, nl - 1), t0 + min(3, nl - 1)
    per_trial_truth = truth.shape[0] > 1
    Q0 = (q[ta, 0], q[tb, 0], q[tc, 0], q[td, 0])
    Q1 = (q[ta, 1], q[tb, 1], q[tc, 1], q[td, 1])
    Q2 = (q[ta, 2], q[tb, 2], q[tc, 2], q[td, 2])
    Q3 = (q[ta, 3], q[tb, 3], q[tc, 3], q[td, 3])
    I0 = (integ[ta, 0], integ[tb, 0], integ[tc, 0], integ[td, 0])
    I1 = (integ[ta, 1], integ[tb, 1], integ[tc, 1], integ[td, 1])
    I2 = (integ[ta, 2], integ[tb, 2], integ[tc, 2], integ[td, 2])
    pv = np.empty(4)
    for j in range(4):
        tj = t0 + min(j, nl - 1)
        pv[j] = amd[tj]
        if m > 0 and math.isnan(pv[j]):
            ax, ay, az = a[tj, 0, 0], a[tj, 0, 1], a[tj, 0, 2]
            pv[j] = abs(math.sqrt((ax * ax + ay * ay) + az * az) / gravity - 1.0) * 100.0
    P = (pv[0], pv[1], pv[2], pv[3])
    zero = bc(0.0)
    FW = FA = WM = LOW = zero
    S0 = S1 = S2 = SS0 = SS1 = SS2 = zero
    M0 = M1 = M2 = zero
    if with_stats:
        M0 = (stats[ta, 6], stats[tb, 6], stats[tc, 6], stats[td, 6])
        M1 = (stats[ta, 7], stats[tb, 7], stats[tc, 7], stats[td, 7])
        M2 = (stats[ta, 8], stats[tb, 8], stats[tc, 8], stats[td, 8])
    for k in range(m):
        if keep:
            _store_q(q_out, ta, tb, tc, td, nl, k, Q0, Q1, Q2, Q3)
        if with_stats:
            E0, E1, E2 = _errors(Q0, Q1, Q2, Q3, truth, per_trial_truth, ta, tb, tc, td, k)
            S0, S1, S2 = add(S0, E0), add(S1, E1), add(S2, E2)
            SS0, SS1, SS2 = add(SS0, mul(E0, E0)), add(SS1, mul(E1, E1)), add(SS2, mul(E2, E2))
            M0, M1, M2 = vmax(M0, fabs(E0)), vmax(M1, fabs(E1)), vmax(M2, fabs(E2))
        AX = (a[ta, k, 0], a[tb, k, 0], a[tc, k, 0], a[td, k, 0])
        AY = (a[ta, k, 1], a[tb, k, 1], a[tc, k, 1], a[td, k, 1])
        AZ = (a[ta, k, 2], a[tb, k, 2], a[tc, k, 2], a[td, k, 2])
        WX = (w[ta, k, 0], w[tb, k, 0], w[tc, k, 0], w[td, k, 0])
        WY = (w[ta, k, 1], w[tb, k, 1], w[tc, k, 1], w[td, k, 1])
        WZ = (w[ta, k, 2], w[tb, k, 2], w[tc, k, 2], w[td, k, 2])
        # input scan (see _trial)
        FW = add(FW, add(add(muls(WX, 0.0), muls(WY, 0.0)), muls(WZ, 0.0)))
        FA = add(FA, add(add(muls(AX, 0.0), muls(AY, 0.0)), muls(AZ, 0.0)))
        WM = vmax(WM, vmax(fabs(WX), vmax(fabs(WY), fabs(WZ))))
        # AMD statistic and gate
        N2 = add(add(mul(AX, AX), mul(AY, AY)), mul(AZ, AZ))
        NRM = sqrt(N2)
        D = muls(fabs(adds(divs(NRM, gravity), -1.0)), 100.0)
        P = add(P, muls(sub(D, P), alpha))
        FAC = div(where_lt(P, bc(thr), bc(1.0), bc(0.0)), maxs(NRM, 1e-12))
        UX, UY, UZ = mul(AX, FAC), mul(AY, FAC), mul(AZ, FAC)
        # predicted up direction and e = â × v̂
        V0 = muls(sub(mul(Q1, Q3), mul(Q0, Q2)), 2.0)
        V1 = muls(add(mul(Q2, Q3), mul(Q0, Q1)), 2.0)
        V2 = sub(sub(add(mul(Q0, Q0), mul(Q3, Q3)), mul(Q1, Q1)), mul(Q2, Q2))
        E0 = sub(mul(UY, V2), mul(UZ, V1))
        E1 = sub(mul(UZ, V0), mul(UX, V2))
        E2 = sub(mul(UX, V1), mul(UY, V0))
        if use_ki:
            I0, I1, I2 = add(I0, muls(E0, kidt)), add(I1, muls(E1, kidt)), add(I2, muls(E2, kidt))
        X0 = muls(add(add(muls(E0, kp), WX), I0), dt)
        X1 = muls(add(add(muls(E1, kp), WY), I1), dt)
        X2 = muls(add(add(muls(E2, kp), WZ), I2), dt)
        U = add(add(mul(X0, X0), mul(X1, X1)), mul(X2, X2))
        if (U[0] <= _T3) & (U[1] <= _T3) & (U[2] <= _T3) & (U[3] <= _T3):  # series: a select per lane
            T2 = bc(_T2)
            C = where_le(U, T2, adds(mul(adds(muls(U, _C2), _C1), U), 1.0),
                         adds(mul(adds(mul(adds(muls(U, _C3), _C2), U), _C1), U), 1.0))
            S = where_le(U, T2, adds(mul(adds(muls(U, _S2), _S1), U), _S0),
                         adds(mul(adds(mul(adds(muls(U, _S3), _S2), U), _S1), U), _S0))
        else:
            ca, sa = _cs(U[0])
            cb, sb = _cs(U[1])
            cc, sc = _cs(U[2])
            cd, sd = _cs(U[3])
            C, S = (ca, cb, cc, cd), (sa, sb, sc, sd)
        H1, H2, H3 = mul(X0, S), mul(X1, S), mul(X2, S)
        N0 = sub(mul(Q0, C), add(add(mul(Q1, H1), mul(Q2, H2)), mul(Q3, H3)))
        NN1 = add(add(mul(H1, Q0), mul(Q1, C)), sub(mul(Q2, H3), mul(Q3, H2)))
        NN2 = add(add(mul(H2, Q0), mul(Q2, C)), sub(mul(Q3, H1), mul(Q1, H3)))
        NN3 = add(add(mul(H3, Q0), mul(Q3, C)), sub(mul(Q1, H2), mul(Q2, H1)))
        NQ = sqrt(add(add(add(mul(N0, N0), mul(NN1, NN1)), mul(NN2, NN2)), mul(NN3, NN3)))
        Q0, Q1, Q2, Q3 = div(N0, NQ), div(NN1, NQ), div(NN2, NQ), div(NN3, NQ)
        LOW = add(LOW, where_lt(N2, bc(_LOW2), bc(1.0), zero))
        if keep:  # constant lane indices: P stays in registers
            amd_out[t0, k], gate_out[t0, k] = P[0], P[0] < thr
            if nl > 1:
                amd_out[t0 + 1, k], gate_out[t0 + 1, k] = P[1], P[1] < thr
            if nl > 2:
                amd_out[t0 + 2, k], gate_out[t0 + 2, k] = P[2], P[2] < thr
            if nl > 3:
                amd_out[t0 + 3, k], gate_out[t0 + 3, k] = P[3], P[3] < thr
    for j in range(nl):
        t = t0 + j
        q[t, 0], q[t, 1], q[t, 2], q[t, 3] = Q0[j], Q1[j], Q2[j], Q3[j]
        integ[t, 0], integ[t, 1], integ[t, 2] = I0[j], I1[j], I2[j]
        amd[t] = P[j]
        chk[t, 0], chk[t, 1], chk[t, 2], chk[t, 3] = FW[j], WM[j], FA[j], LOW[j]
        if with_stats:
            stats[t, 0] += S0[j]
            stats[t, 1] += S1[j]
            stats[t, 2] += S2[j]
            stats[t, 3] += SS0[j]
            stats[t, 4] += SS1[j]
            stats[t, 5] += SS2[j]
            stats[t, 6], stats[t, 7], stats[t, 8] = M0[j], M1[j], M2[j]


@numba.njit(inline="always")
def _store_q(q_out, ta, tb, tc, td, nl, k, Q0, Q1, Q2, Q3):
    """q_out[t, k] = lane's quaternion for the ``nl`` real lanes."""
    q_out[ta, k, 0], q_out[ta, k, 1], q_out[ta, k, 2], q_out[ta, k, 3] = Q0[0], Q1[0], Q2[0], Q3[0]
    if nl > 1:
        q_out[tb, k, 0], q_out[tb, k, 1], q_out[tb, k, 2], q_out[tb, k, 3] = Q0[1], Q1[1], Q2[1], Q3[1]
    if nl > 2:
        q_out[tc, k, 0], q_out[tc, k, 1], q_out[tc, k, 2], q_out[tc, k, 3] = Q0[2], Q1[2], Q2[2], Q3[2]
    if nl > 3:
        q_out[td, k, 0], q_out[td, k, 1], q_out[td, k, 2], q_out[td, k, 3] = Q0[3], Q1[3], Q2[3], Q3[3]


@numba.njit(inline="always")
def _row(table, per_trial_truth, ta, tb, tc, td, k, j):
    """Lane vector of column ``j`` of the truth table at t_k (one load broadcast for a shared truth)."""
    if per_trial_truth:
        return (table[ta, k, j], table[tb, k, j], table[tc, k, j], table[td, k, j])
    return bc(table[0, k, j])


@numba.njit(inline="always")
def _atan_small4(R):
    """Lane form of :func:`mtcal.core.montecarlo.atan_small` (same operations per lane)."""
    U = mul(R, R)
    return add(R, mul(R, mul(U, adds(mul(U, adds(mul(U, adds(muls(U, ATAN_C9), ATAN_C7)), ATAN_C5)), ATAN_C3))))


@numba.njit(inline="always")
def _asin_small4(Y):
    """Lane form of :func:`mtcal.core.montecarlo.asin_small` (same operations per lane)."""
    U = mul(Y, Y)
    return add(Y, mul(Y, mul(U, adds(mul(U, adds(mul(U, adds(muls(U, ASIN_C9), ASIN_C7)), ASIN_C5)), ASIN_C3))))


@numba.njit(inline="always")
def _errors(Q0, Q1, Q2, Q3, table, per_trial_truth, ta, tb, tc, td, k):
    """Per lane Eq 8 errors against the truth table row at t_k: :func:`mtcal.core.montecarlo.euler_errors_cs`
    as 4-lane vectors when every lane takes its series path, else that scalar function per lane (bit-identical
    either way: the lane operations are the scalar ones with the same operands in the same order)."""
    C0 = _row(table, per_trial_truth, ta, tb, tc, td, k, 3)
    S0 = _row(table, per_trial_truth, ta, tb, tc, td, k, 4)
    C1 = _row(table, per_trial_truth, ta, tb, tc, td, k, 5)
    S1 = _row(table, per_trial_truth, ta, tb, tc, td, k, 6)
    C2 = _row(table, per_trial_truth, ta, tb, tc, td, k, 7)
    S2 = _row(table, per_trial_truth, ta, tb, tc, td, k, 8)
    S00, S11, S22, S33 = mul(Q0, Q0), mul(Q1, Q1), mul(Q2, Q2), mul(Q3, Q3)
    YX = sub(add(sub(S00, S11), S22), S33)
    YY = muls(sub(mul(Q1, Q2), mul(Q0, Q3)), -2.0)
    A = muls(add(mul(Q2, Q3), mul(Q0, Q1)), 2.0)
    A = maxs(A, -1.0)
    one = bc(1.0)
    A = where_lt(one, A, one, A)               # min(a, 1.0) as numba computes it
    RX = add(sub(sub(S00, S11), S22), S33)
    RY = muls(sub(mul(Q1, Q3), mul(Q0, Q2)), -2.0)
    XA = add(mul(YX, C0), mul(YY, S0))
    YA = sub(mul(YY, C0), mul(YX, S0))
    CE = sqrt(mul(sub(one, A), adds(A, 1.0)))
    XB = add(mul(CE, C1), mul(A, S1))
    YB = sub(mul(A, C1), mul(CE, S1))
    XC = add(mul(RX, C2), mul(RY, S2))
    YC = sub(mul(RY, C2), mul(RX, S2))
    # the scalar's test |ya| < SERIES_MAX·xa, |yb| < SERIES_MAX, xb > 0, |yc| < SERIES_MAX·xc, as one 0/1 lane mask
    zero = bc(0.0)
    OK = where_lt(fabs(YC), muls(XC, SERIES_MAX), one, zero)
    OK = where_lt(zero, XB, OK, zero)
    OK = where_lt(fabs(YB), bc(SERIES_MAX), OK, zero)
    OK = where_lt(fabs(YA), muls(XA, SERIES_MAX), OK, zero)
    if (OK[0] + OK[1]) + (OK[2] + OK[3]) == 4.0:
        return _atan_small4(div(YA, XA)), _asin_small4(YB), _atan_small4(div(YC, XC))
    ra = table[ta] if per_trial_truth else table[0]
    rb = table[tb] if per_trial_truth else table[0]
    rc = table[tc] if per_trial_truth else table[0]
    rd = table[td] if per_trial_truth else table[0]
    a0, a1, a2 = table_errors(Q0[0], Q1[0], Q2[0], Q3[0], ra[k])
    b0, b1, b2 = table_errors(Q0[1], Q1[1], Q2[1], Q3[1], rb[k])
    c0, c1, c2 = table_errors(Q0[2], Q1[2], Q2[2], Q3[2], rc[k])
    d0, d1, d2 = table_errors(Q0[3], Q1[3], Q2[3], Q3[3], rd[k])
    return (a0, b0, c0, d0), (a1, b1, c1, d1), (a2, b2, c2, d2)


@jit()
def _run_block(w, a, b, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
               keep, truth, stats, with_stats, chk):
    """Block ``b`` of 4 trials (vector lanes), or its single trial with the scalar kernel."""
    t0 = np.int64(b) * 4
    nl = min(4, w.shape[0] - t0)
    if nl == 1:
        _trial(w, a, t0, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
               keep, truth, stats, with_stats, chk)
    else:
        _block(w, a, t0, nl, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
               keep, truth, stats, with_stats, chk)


@jit()
def qncf_serial(w, a, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
                keep, truth, stats, with_stats, chk):
    """Blocks of 4 trials one after the other (single-trial records, small batches)."""
    for b in range((w.shape[0] + 3) // 4):
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
def qncf_parallel(w, a, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
                  keep, truth, stats, with_stats, chk):
    """Blocks of 4 trials spread over numba's threads (``prange``); each trial computed exactly as serially."""
    for b in prange((w.shape[0] + 3) // 4):
        _run_block(w, a, b, q, integ, amd, q_out, amd_out, gate_out, kp, kidt, use_ki, dt, alpha, gravity, thr,
                   keep, truth, stats, with_stats, chk)


def warm_up() -> None:
    """Compile (or load from the cache) both kernels on a tiny input."""
    w = np.zeros((2, 2, 3))
    a = np.zeros((2, 2, 3))
    a[..., 2] = 9.80665
    for fn in (qncf_one, qncf_serial, qncf_parallel):
        fn(w, a, np.tile([1.0, 0, 0, 0], (2, 1)), np.zeros((2, 3)), np.full(2, np.nan), np.empty((2, 2, 4)),
           np.empty((2, 2)), np.empty((2, 2), np.bool_), 1.0, 2e-5, True, 1e-3, 0.02, 9.80665, 0.3, True,
           np.zeros((1, 2, 9)), np.zeros((2, 9)), True, np.empty((2, 4)))
