"""Compiled RAMS EKF kernels (numba, float64): one trial, or trials in parallel (private).

Same algebra as :meth:`mtcal.filters.rams_ekf.RamsEkfFilter._step` (the numpy
reference), per scalar and with the reference's operation order (packed
covariance rows :data:`mtcal.filters.rams_ekf.PACKED_INDEX`, every sum paired
the same way), so the two engines agree to the last bit except where numpy's
and libm's cos/sin differ (≤ 1 ulp). Trials are independent: bit-identical
results for any numba thread count and any chunking.

Per-trial state arrays: ``theta`` (T,), ``bias`` (T, 3), ``p`` (T, 10) packed
covariance, ``omega_prev`` (T,) = vᵀω Δt of the last gyro sample seen (used
when ``has_prev``); the last step's ``c = P e0`` (T, 4), ``h′`` (T, 3) and
``s`` (T,) are returned for S and K.

Batches run as blocks of :data:`LANES` trials (8 with AVX-512, else 4) in
structure-of-arrays form (:func:`_block`: one SIMD vector per state variable, held in
a true LLVM vector type, :class:`mtcal.filters._kernels_lanes.VecType`), blocks spread
over threads (``prange`` workers, one range of blocks each, shared at the end); a batched trial is
bit-identical to the same trial run alone (:func:`_trial`, used for single-trial records and
a last lone trial). Per trial
and step the cost is about half the libm ``sincos`` (the same call as the scalar path,
so results cannot differ) and half memory traffic (inputs read, histories written).
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba import prange

from mtcal.filters._kernels_lanes import (add, choose, cos, div, fabs, fill, mul, put, put1, put3, rows4, rows8, sin,
                                          simd_lanes, sub, take, take1, take3, vmax, where_lt)
from mtcal.filters._kernels_common import claim, jit, schedule

__all__ = ["ekf_one", "ekf_serial", "ekf_parallel"]

_LOW2 = 2.0 * 2.0 * (1.0 + 1e-9)   # see _kernels_qncf._LOW2


#: Trials per SIMD block (:func:`mtcal.filters._kernels_lanes.simd_lanes`: 8 with AVX-512, else 4).
LANES = simd_lanes()


@jit()
def _trial(g, a, st, t, v, par, perp, nperp, wv, f, theta_s, bias_s, p_s, om_s, has_prev, use_zvd,
           var_z, var_m, dt, q_theta, q_b, out_theta, out_bias, out_p, out_y, keep_y, last_c, last_hp, last_s, chk):
    fw = 0.0
    fa = 0.0
    wm = 0.0
    low = 0.0
    v0, v1, v2 = v[t, 0], v[t, 1], v[t, 2]
    f1, f2, f3 = f[t, 0], f[t, 1], f[t, 2]
    theta = theta_s[t]
    b0, b1, b2 = bias_s[t, 0], bias_s[t, 1], bias_s[t, 2]
    p00, p01, p02, p03 = p_s[t, 0], p_s[t, 1], p_s[t, 2], p_s[t, 3]
    p11, p22, p33 = p_s[t, 4], p_s[t, 5], p_s[t, 6]
    p12, p13, p23 = p_s[t, 7], p_s[t, 8], p_s[t, 9]
    pa0, pa1, pa2 = par[t, 0], par[t, 1], par[t, 2]
    pe0, pe1, pe2 = perp[t, 0], perp[t, 1], perp[t, 2]
    ne0, ne1, ne2 = nperp[t, 0], nperp[t, 1], nperp[t, 2]
    w0, w1, w2 = wv[t, 0], wv[t, 1], wv[t, 2]
    per_trial_flags = st.shape[0] > 1
    omega = om_s[t]
    c0 = c1 = c2 = c3 = 0.0
    h0 = h1 = h2 = 0.0
    s = 0.0
    for k in range(g.shape[1]):
        if has_prev or k > 0:  # prediction with the previous gyro sample (Eq 24–27)
            theta = theta + (omega - (((v0 * b0 + v2 * b2) + v1 * b1) * dt))
            u0 = (p01 * f1 + p03 * f3) + p02 * f2
            u1 = (p11 * f1 + p13 * f3) + p12 * f2
            u2 = (p12 * f1 + p23 * f3) + p22 * f2
            u3 = (p13 * f1 + p33 * f3) + p23 * f2
            r1 = (f1 * u1 + f3 * u3) + f2 * u2
            p00 = p00 + u0
            p00 = p00 + u0
            p00 = p00 + (r1 + q_theta)
            p01 = p01 + u1
            p02 = p02 + u2
            p03 = p03 + u3
            p11 = p11 + q_b
            p22 = p22 + q_b
            p33 = p33 + q_b
        # vᵀω Δt of this sample, for the next prediction
        gx, gy, gz = g[t, k, 0], g[t, k, 1], g[t, k, 2]
        ax, ay, az = a[t, k, 0], a[t, k, 1], a[t, k, 2]
        fw = fw + ((gx * 0.0 + gy * 0.0) + gz * 0.0)     # input scan (see _kernels_qncf._trial)
        fa = fa + ((ax * 0.0 + ay * 0.0) + az * 0.0)
        wm = max(wm, max(abs(gx), max(abs(gy), abs(gz))))
        if (ax * ax + ay * ay) + az * az < _LOW2:
            low += 1.0
        omega = ((gx * v0 + gz * v2) + gy * v1) * dt
        # correction (Eq 28–32), scalar-information form
        cs = math.cos(theta)
        sn = math.sin(theta)
        y0 = ax - ((pa0 + pe0 * cs) - w0 * sn)
        y1 = ay - ((pa1 + pe1 * cs) - w1 * sn)
        y2 = az - ((pa2 + pe2 * cs) - w2 * sn)
        h0 = ne0 * sn - w0 * cs
        h1 = ne1 * sn - w1 * cs
        h2 = ne2 * sn - w2 * cs
        r4 = (h0 * h0 + h2 * h2) + h1 * h1
        c0, c1, c2, c3 = p00, p01, p02, p03
        if not use_zvd:
            var = var_z
        elif per_trial_flags:
            var = var_z if st[t, k] else var_m
        else:
            var = var_z if st[0, k] else var_m
        s = var + c0 * r4
        r0 = ((h0 * y0 + h2 * y2) + h1 * y1) / s
        theta = theta + c0 * r0
        b0 = b0 + c1 * r0
        b1 = b1 + c2 * r0
        b2 = b2 + c3 * r0
        r4 = r4 / s
        p00 = p00 - (c0 * c0) * r4
        p01 = p01 - (c1 * c0) * r4
        p02 = p02 - (c2 * c0) * r4
        p03 = p03 - (c3 * c0) * r4
        p11 = p11 - (c1 * c1) * r4
        p22 = p22 - (c2 * c2) * r4
        p33 = p33 - (c3 * c3) * r4
        p12 = p12 - (c2 * c1) * r4
        p13 = p13 - (c3 * c1) * r4
        p23 = p23 - (c3 * c2) * r4
        out_theta[t, k] = theta
        out_bias[t, k, 0] = b0
        out_bias[t, k, 1] = b1
        out_bias[t, k, 2] = b2
        out_p[t, k] = p00
        if keep_y:
            out_y[t, k, 0] = y0
            out_y[t, k, 1] = y1
            out_y[t, k, 2] = y2
    theta_s[t] = theta
    bias_s[t, 0], bias_s[t, 1], bias_s[t, 2] = b0, b1, b2
    p_s[t, 0], p_s[t, 1], p_s[t, 2], p_s[t, 3] = p00, p01, p02, p03
    p_s[t, 4], p_s[t, 5], p_s[t, 6] = p11, p22, p33
    p_s[t, 7], p_s[t, 8], p_s[t, 9] = p12, p13, p23
    om_s[t] = omega
    chk[t, 0] = fw
    chk[t, 1] = wm
    chk[t, 2] = fa
    chk[t, 3] = low
    if g.shape[1] > 0:
        last_c[t, 0], last_c[t, 1], last_c[t, 2], last_c[t, 3] = c0, c1, c2, c3
        last_hp[t, 0], last_hp[t, 1], last_hp[t, 2] = h0, h1, h2
        last_s[t] = s


@numba.njit(inline="always")
def _lanes3(x, rows):
    """Columns 0, 1, 2 of a (T, 3) array at ``rows`` as three lane vectors."""
    return take(x, rows, 0), take(x, rows, 1), take(x, rows, 2)


@jit()
def _block(g, a, st, rows, v, par, perp, nperp, wv, f, theta_s, bias_s, p_s, om_s, has_prev, use_zvd,
           var_z, var_m, dt, q_theta, q_b, out_theta, out_bias, out_p, out_y, keep_y, last_c, last_hp, last_s, chk):
    """Trials ``rows`` (a tuple of LANES trial indices) as LANES-lane SIMD vectors (structure of arrays over trials).

    Each lane performs :func:`_trial`'s operations on the same operands in the same order
    (cos/sin per lane with the same libm calls), so every trial is bit-identical to
    :func:`_trial`. Rows may repeat (the last trial of a short block fills the spare lanes):
    a repeated lane computes the same values bit for bit and stores them to the same places.
    The state is held in lane vectors (:class:`~mtcal.filters._kernels_lanes.VecType`: one
    vector register or spill slot each, no per-step re-packing of tuples).
    """
    V0, V1, V2 = _lanes3(v, rows)
    F1, F2, F3 = _lanes3(f, rows)
    PA0, PA1, PA2 = _lanes3(par, rows)
    PE0, PE1, PE2 = _lanes3(perp, rows)
    NE0, NE1, NE2 = _lanes3(nperp, rows)
    W0, W1, W2 = _lanes3(wv, rows)
    TH = take1(theta_s, rows)
    B0, B1, B2 = _lanes3(bias_s, rows)
    P00, P01, P02, P03 = take(p_s, rows, 0), take(p_s, rows, 1), take(p_s, rows, 2), take(p_s, rows, 3)
    P11, P22, P33 = take(p_s, rows, 4), take(p_s, rows, 5), take(p_s, rows, 6)
    P12, P13, P23 = take(p_s, rows, 7), take(p_s, rows, 8), take(p_s, rows, 9)
    OM = take1(om_s, rows)
    per_trial_flags = st.shape[0] > 1
    zero = fill(TH, 0.0)
    FW = FA = WM = LOW = zero
    C0 = C1 = C2 = C3 = H0 = H1 = H2 = S = zero
    DT, QT, QB = fill(TH, dt), fill(TH, q_theta), fill(TH, q_b)
    LOW2, ONE, VZ = fill(TH, _LOW2), fill(TH, 1.0), fill(TH, var_z)
    for k in range(g.shape[1]):
        if has_prev or k > 0:  # prediction with the previous gyro sample (Eq 24–27)
            TH = add(TH, sub(OM, mul(add(add(mul(V0, B0), mul(V2, B2)), mul(V1, B1)), DT)))
            U0 = add(add(mul(P01, F1), mul(P03, F3)), mul(P02, F2))
            U1 = add(add(mul(P11, F1), mul(P13, F3)), mul(P12, F2))
            U2 = add(add(mul(P12, F1), mul(P23, F3)), mul(P22, F2))
            U3 = add(add(mul(P13, F1), mul(P33, F3)), mul(P23, F2))
            R1 = add(add(mul(F1, U1), mul(F3, U3)), mul(F2, U2))
            P00 = add(add(add(P00, U0), U0), add(R1, QT))
            P01, P02, P03 = add(P01, U1), add(P02, U2), add(P03, U3)
            P11, P22, P33 = add(P11, QB), add(P22, QB), add(P33, QB)
        GX, GY, GZ = take3(g, rows, k, 0), take3(g, rows, k, 1), take3(g, rows, k, 2)
        AX, AY, AZ = take3(a, rows, k, 0), take3(a, rows, k, 1), take3(a, rows, k, 2)
        FW = add(FW, add(add(mul(GX, zero), mul(GY, zero)), mul(GZ, zero)))
        FA = add(FA, add(add(mul(AX, zero), mul(AY, zero)), mul(AZ, zero)))
        WM = vmax(WM, vmax(fabs(GX), vmax(fabs(GY), fabs(GZ))))
        N2 = add(add(mul(AX, AX), mul(AY, AY)), mul(AZ, AZ))
        LOW = add(LOW, where_lt(N2, LOW2, ONE, zero))
        OM = mul(add(add(mul(GX, V0), mul(GZ, V2)), mul(GY, V1)), DT)
        # correction (Eq 28–32), scalar-information form
        CS = cos(TH)
        SN = sin(TH)
        Y0 = sub(AX, sub(add(PA0, mul(PE0, CS)), mul(W0, SN)))
        Y1 = sub(AY, sub(add(PA1, mul(PE1, CS)), mul(W1, SN)))
        Y2 = sub(AZ, sub(add(PA2, mul(PE2, CS)), mul(W2, SN)))
        H0 = sub(mul(NE0, SN), mul(W0, CS))
        H1 = sub(mul(NE1, SN), mul(W1, CS))
        H2 = sub(mul(NE2, SN), mul(W2, CS))
        R4 = add(add(mul(H0, H0), mul(H2, H2)), mul(H1, H1))
        C0, C1, C2, C3 = P00, P01, P02, P03
        if not use_zvd:
            VAR = VZ
        elif per_trial_flags:
            VAR = choose(st, rows, k, var_z, var_m)
        else:
            VAR = fill(TH, var_z if st[0, k] else var_m)
        S = add(VAR, mul(C0, R4))
        R0 = div(add(add(mul(H0, Y0), mul(H2, Y2)), mul(H1, Y1)), S)
        TH = add(TH, mul(C0, R0))
        B0, B1, B2 = add(B0, mul(C1, R0)), add(B1, mul(C2, R0)), add(B2, mul(C3, R0))
        R4 = div(R4, S)
        P00 = sub(P00, mul(mul(C0, C0), R4))
        P01 = sub(P01, mul(mul(C1, C0), R4))
        P02 = sub(P02, mul(mul(C2, C0), R4))
        P03 = sub(P03, mul(mul(C3, C0), R4))
        P11 = sub(P11, mul(mul(C1, C1), R4))
        P22 = sub(P22, mul(mul(C2, C2), R4))
        P33 = sub(P33, mul(mul(C3, C3), R4))
        P12 = sub(P12, mul(mul(C2, C1), R4))
        P13 = sub(P13, mul(mul(C3, C1), R4))
        P23 = sub(P23, mul(mul(C3, C2), R4))
        put(out_theta, rows, k, TH)
        put(out_p, rows, k, P00)
        put3(out_bias, rows, k, 0, B0)
        put3(out_bias, rows, k, 1, B1)
        put3(out_bias, rows, k, 2, B2)
        if keep_y:
            put3(out_y, rows, k, 0, Y0)
            put3(out_y, rows, k, 1, Y1)
            put3(out_y, rows, k, 2, Y2)
    put1(theta_s, rows, TH)
    put(bias_s, rows, 0, B0)
    put(bias_s, rows, 1, B1)
    put(bias_s, rows, 2, B2)
    put(p_s, rows, 0, P00)
    put(p_s, rows, 1, P01)
    put(p_s, rows, 2, P02)
    put(p_s, rows, 3, P03)
    put(p_s, rows, 4, P11)
    put(p_s, rows, 5, P22)
    put(p_s, rows, 6, P33)
    put(p_s, rows, 7, P12)
    put(p_s, rows, 8, P13)
    put(p_s, rows, 9, P23)
    put1(om_s, rows, OM)
    put(chk, rows, 0, FW)
    put(chk, rows, 1, WM)
    put(chk, rows, 2, FA)
    put(chk, rows, 3, LOW)
    if g.shape[1] > 0:
        put(last_c, rows, 0, C0)
        put(last_c, rows, 1, C1)
        put(last_c, rows, 2, C2)
        put(last_c, rows, 3, C3)
        put(last_hp, rows, 0, H0)
        put(last_hp, rows, 1, H1)
        put(last_hp, rows, 2, H2)
        put1(last_s, rows, S)


_rows = rows8 if LANES == 8 else rows4


@jit()
def _run_block(g, a, st, b, v, par, perp, nperp, wv, f, theta_s, bias_s, p_s, om_s, has_prev, use_zvd, var_z,
               var_m, dt, q_theta, q_b, out_theta, out_bias, out_p, out_y, keep_y, last_c, last_hp, last_s, chk):
    """Block ``b`` of :data:`LANES` trials (vector lanes), or its single trial with the scalar kernel."""
    t0 = np.int64(b) * LANES
    nl = min(LANES, g.shape[0] - t0)
    if nl == 1:
        _trial(g, a, st, t0, v, par, perp, nperp, wv, f, theta_s, bias_s, p_s, om_s, has_prev, use_zvd, var_z,
               var_m, dt, q_theta, q_b, out_theta, out_bias, out_p, out_y, keep_y, last_c, last_hp, last_s, chk)
    else:
        _block(g, a, st, _rows(t0, nl), v, par, perp, nperp, wv, f, theta_s, bias_s, p_s, om_s, has_prev, use_zvd,
               var_z, var_m, dt, q_theta, q_b, out_theta, out_bias, out_p, out_y, keep_y, last_c, last_hp, last_s,
               chk)


@jit()
def ekf_serial(g, a, st, v, par, perp, nperp, wv, f, theta_s, bias_s, p_s, om_s, has_prev, use_zvd, var_z,
               var_m, dt, q_theta, q_b, out_theta, out_bias, out_p, out_y, keep_y, last_c, last_hp, last_s, chk):
    """Blocks of :data:`LANES` trials one after the other."""
    for b in range((g.shape[0] + LANES - 1) // LANES):
        _run_block(g, a, st, b, v, par, perp, nperp, wv, f, theta_s, bias_s, p_s, om_s, has_prev, use_zvd, var_z,
                   var_m, dt, q_theta, q_b, out_theta, out_bias, out_p, out_y, keep_y, last_c, last_hp, last_s, chk)


@jit()
def ekf_one(g, a, st, v, par, perp, nperp, wv, f, theta_s, bias_s, p_s, om_s, has_prev, use_zvd, var_z,
            var_m, dt, q_theta, q_b, out_theta, out_bias, out_p, out_y, keep_y, last_c, last_hp, last_s, chk):
    """Trials one after the other with the scalar kernel only (single-trial records: the smallest code for
    numba to load from its cache)."""
    for t in range(g.shape[0]):
        _trial(g, a, st, t, v, par, perp, nperp, wv, f, theta_s, bias_s, p_s, om_s, has_prev, use_zvd, var_z,
               var_m, dt, q_theta, q_b, out_theta, out_bias, out_p, out_y, keep_y, last_c, last_hp, last_s, chk)


@jit(parallel=True)
def _ekf_parallel(g, a, st, v, par, perp, nperp, wv, f, theta_s, bias_s, p_s, om_s, has_prev, use_zvd, var_z,
                  var_m, dt, q_theta, q_b, out_theta, out_bias, out_p, out_y, keep_y, last_c, last_hp, last_s, chk,
                  counter, workers):
    """Blocks of :data:`LANES` trials spread over numba's threads: ``workers`` ``prange`` iterations (one per
    thread) each run their own contiguous range of blocks in order, then help with the others' from their far
    end (:func:`~mtcal.filters._kernels_common.claim`: a dynamic schedule that keeps the threads apart);
    each trial computed exactly as serially."""
    nb = (g.shape[0] + LANES - 1) // LANES
    for w in prange(workers):
        for j in range(workers):
            r = (w + j) % workers
            lo, hi = r * nb // workers, (r + 1) * nb // workers
            b = claim(counter, r, lo, hi, j == 0)
            while b >= 0:
                _run_block(g, a, st, b, v, par, perp, nperp, wv, f, theta_s, bias_s, p_s, om_s, has_prev, use_zvd,
                           var_z, var_m, dt, q_theta, q_b, out_theta, out_bias, out_p, out_y, keep_y, last_c, last_hp,
                           last_s, chk)
                b = claim(counter, r, lo, hi, j == 0)


def ekf_parallel(*args) -> None:
    """:func:`_ekf_parallel` on numba's threads (one range of blocks each, shared at the end).
    Arguments as :func:`ekf_serial`."""
    workers = numba.get_num_threads()
    _ekf_parallel(*args, schedule(workers), workers)


def warm_up() -> None:
    """Compile (or load from the cache) both kernels on a tiny input."""
    n, m = 2, 2
    g = np.zeros((n, m, 3))
    a = np.zeros((n, m, 3))
    a[..., 2] = 9.8
    vec = np.tile([1.0, 0.0, 0.0], (n, 1))
    for fn in (ekf_one, ekf_serial, ekf_parallel):
        fn(g, a, np.ones((1, m), np.bool_), vec, vec, vec, vec, vec, vec, np.zeros(n), np.zeros((n, 3)),
           np.ones((n, 10)), np.zeros(n), False, True, 1e-4, 4.0, 1e-3, 1e-10, 1e-14, np.empty((n, m)),
           np.empty((n, m, 3)), np.empty((n, m)), np.empty((n, m, 3)), True, np.empty((n, 4)), np.empty((n, 3)),
           np.empty(n), np.empty((n, 4)))
