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
"""

from __future__ import annotations

import math

import numpy as np
from numba import prange

from mtcal.filters._kernels_common import jit

__all__ = ["ekf_serial", "ekf_parallel"]

_LOW2 = 2.0 * 2.0 * (1.0 + 1e-9)   # see _kernels_qncf._LOW2


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


@jit()
def ekf_serial(g, a, st, v, par, perp, nperp, wv, f, theta_s, bias_s, p_s, om_s, has_prev, use_zvd, var_z,
               var_m, dt, q_theta, q_b, out_theta, out_bias, out_p, out_y, keep_y, last_c, last_hp, last_s, chk):
    """Trials one after the other."""
    for t in range(g.shape[0]):
        _trial(g, a, st, t, v, par, perp, nperp, wv, f, theta_s, bias_s, p_s, om_s, has_prev, use_zvd, var_z,
               var_m, dt, q_theta, q_b, out_theta, out_bias, out_p, out_y, keep_y, last_c, last_hp, last_s, chk)


@jit(parallel=True)
def ekf_parallel(g, a, st, v, par, perp, nperp, wv, f, theta_s, bias_s, p_s, om_s, has_prev, use_zvd, var_z,
                 var_m, dt, q_theta, q_b, out_theta, out_bias, out_p, out_y, keep_y, last_c, last_hp, last_s, chk):
    """Trials spread over numba's threads (``prange``); each trial computed exactly as serially."""
    for t in prange(g.shape[0]):
        _trial(g, a, st, t, v, par, perp, nperp, wv, f, theta_s, bias_s, p_s, om_s, has_prev, use_zvd, var_z,
               var_m, dt, q_theta, q_b, out_theta, out_bias, out_p, out_y, keep_y, last_c, last_hp, last_s, chk)


def warm_up() -> None:
    """Compile (or load from the cache) both kernels on a tiny input."""
    n, m = 2, 2
    g = np.zeros((n, m, 3))
    a = np.zeros((n, m, 3))
    a[..., 2] = 9.8
    vec = np.tile([1.0, 0.0, 0.0], (n, 1))
    for fn in (ekf_serial, ekf_parallel):
        fn(g, a, np.ones((1, m), np.bool_), vec, vec, vec, vec, vec, vec, np.zeros(n), np.zeros((n, 3)),
           np.ones((n, 10)), np.zeros(n), False, True, 1e-4, 4.0, 1e-3, 1e-10, 1e-14, np.empty((n, m)),
           np.empty((n, m, 3)), np.empty((n, m)), np.empty((n, m, 3)), True, np.empty((n, 4)), np.empty((n, 3)),
           np.empty(n), np.empty((n, 4)))
