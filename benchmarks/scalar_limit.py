"""Scalar-per-trial limit: an independent numba re-implementation of the QNCF and the RAMS EKF.

Written from the filters' equations (wang2023cja Eq 5–8 with the PI correction and the
AMD gate; wang2022sensors Eq 24–32 with the 4-state covariance), not from mtcal's kernels:
one trial per ``prange`` iteration, plain scalar recursion, the same outputs mtcal's
batched entry points keep (QNCF: q (T, M, 4), AMD, gate; EKF: θ, bias, P_θθ), no input
checks, no fused statistics. ``make bench`` times it next to mtcal's batched kernels as
the practical limit of a per-trial scalar implementation on this machine (what trial
vectorisation has to beat). Not used by mtcal itself.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba import prange

__all__ = ["qncf_scalar_limit", "ekf_scalar_limit"]


@numba.njit(parallel=True, cache=True)
def _qncf(w, a, q0, dt, kp, ki, alpha, gravity, thr, q_out, amd_out, gate_out):
    for t in prange(w.shape[0]):
        p0, p1, p2, p3 = q0[0], q0[1], q0[2], q0[3]
        bx = by = bz = 0.0
        ax, ay, az = a[t, 0, 0], a[t, 0, 1], a[t, 0, 2]
        amd = abs(math.sqrt(ax * ax + ay * ay + az * az) / gravity - 1.0) * 100.0
        for k in range(w.shape[1]):
            q_out[t, k, 0], q_out[t, k, 1], q_out[t, k, 2], q_out[t, k, 3] = p0, p1, p2, p3
            ax, ay, az = a[t, k, 0], a[t, k, 1], a[t, k, 2]
            n = math.sqrt(ax * ax + ay * ay + az * az)
            amd += alpha * (abs(n / gravity - 1.0) * 100.0 - amd)
            ok = amd < thr
            g = 1.0 / max(n, 1e-12) if ok else 0.0
            vx = 2.0 * (p1 * p3 - p0 * p2)
            vy = 2.0 * (p2 * p3 + p0 * p1)
            vz = p0 * p0 - p1 * p1 - p2 * p2 + p3 * p3
            ex = (ay * vz - az * vy) * g
            ey = (az * vx - ax * vz) * g
            ez = (ax * vy - ay * vx) * g
            bx += ki * ex * dt
            by += ki * ey * dt
            bz += ki * ez * dt
            hx = (w[t, k, 0] + kp * ex + bx) * dt
            hy = (w[t, k, 1] + kp * ey + by) * dt
            hz = (w[t, k, 2] + kp * ez + bz) * dt
            u = hx * hx + hy * hy + hz * hz          # |Δθ|²: rotation-vector quaternion by series
            c = 1.0 - u / 8.0 + u * u / 384.0
            s = 0.5 - u / 48.0 + u * u / 3840.0
            hx, hy, hz = hx * s, hy * s, hz * s
            r0 = p0 * c - p1 * hx - p2 * hy - p3 * hz
            r1 = p0 * hx + p1 * c + p2 * hz - p3 * hy
            r2 = p0 * hy + p2 * c + p3 * hx - p1 * hz
            r3 = p0 * hz + p3 * c + p1 * hy - p2 * hx
            inv = 1.0 / math.sqrt(r0 * r0 + r1 * r1 + r2 * r2 + r3 * r3)
            p0, p1, p2, p3 = r0 * inv, r1 * inv, r2 * inv, r3 * inv
            amd_out[t, k] = amd
            gate_out[t, k] = ok


def qncf_scalar_limit(gyro_rad_s, accel_m_s2, q0, dt_s, kp=1.0, ki=0.02, tau_s=0.05, gravity=9.80665,
                      threshold_pct=1.5):
    """QNCF over (T, M, 3) records, one trial per thread iteration; returns q (T, M, 4), AMD, gate."""
    t, m = gyro_rad_s.shape[:2]
    q_out, amd_out, gate_out = np.empty((t, m, 4)), np.empty((t, m)), np.empty((t, m), np.bool_)
    _qncf(gyro_rad_s, accel_m_s2, np.asarray(q0, float), dt_s, kp, ki, min(dt_s / tau_s, 1.0), gravity,
          threshold_pct, q_out, amd_out, gate_out)
    return q_out, amd_out, gate_out


@numba.njit(parallel=True, cache=True)
def _ekf(g, a, st, v, par, perp, wv, dt, var_z, var_m, q_theta, q_b, th_out, b_out, p_out):
    for t in prange(g.shape[0]):
        v0, v1, v2 = v[t, 0], v[t, 1], v[t, 2]
        f1, f2, f3 = -v0 * dt, -v1 * dt, -v2 * dt      # ∂θ_k+1/∂bias
        th = b0 = b1 = b2 = om = 0.0
        # symmetric 4 × 4 covariance, upper triangle
        c00, c01, c02, c03, c11, c12, c13, c22, c23, c33 = 1e-4, 0.0, 0.0, 0.0, 1e-4, 0.0, 0.0, 1e-4, 0.0, 1e-4
        for k in range(g.shape[1]):
            if k > 0:  # x ← F x, P ← F P Fᵀ + Q with F = I + e0 fᵀ
                th += om + f1 * b0 + f2 * b1 + f3 * b2
                u0 = f1 * c01 + f2 * c02 + f3 * c03
                u1 = f1 * c11 + f2 * c12 + f3 * c13
                u2 = f1 * c12 + f2 * c22 + f3 * c23
                u3 = f1 * c13 + f2 * c23 + f3 * c33
                c00 += 2.0 * u0 + f1 * u1 + f2 * u2 + f3 * u3 + q_theta
                c01 += u1
                c02 += u2
                c03 += u3
                c11 += q_b
                c22 += q_b
                c33 += q_b
            om = (g[t, k, 0] * v0 + g[t, k, 1] * v1 + g[t, k, 2] * v2) * dt
            c, s = math.cos(th), math.sin(th)
            h0 = -perp[t, 0] * s - wv[t, 0] * c
            h1 = -perp[t, 1] * s - wv[t, 1] * c
            h2 = -perp[t, 2] * s - wv[t, 2] * c
            y0 = a[t, k, 0] - (par[t, 0] + perp[t, 0] * c - wv[t, 0] * s)
            y1 = a[t, k, 1] - (par[t, 1] + perp[t, 1] * c - wv[t, 1] * s)
            y2 = a[t, k, 2] - (par[t, 2] + perp[t, 2] * c - wv[t, 2] * s)
            hh = h0 * h0 + h1 * h1 + h2 * h2
            sc = (var_z if st[k] else var_m) + c00 * hh
            r = (h0 * y0 + h1 * y1 + h2 * y2) / sc
            k0, k1, k2, k3 = c00, c01, c02, c03
            th += k0 * r
            b0 += k1 * r
            b1 += k2 * r
            b2 += k3 * r
            z = hh / sc
            c00 -= k0 * k0 * z
            c01 -= k0 * k1 * z
            c02 -= k0 * k2 * z
            c03 -= k0 * k3 * z
            c11 -= k1 * k1 * z
            c12 -= k1 * k2 * z
            c13 -= k1 * k3 * z
            c22 -= k2 * k2 * z
            c23 -= k2 * k3 * z
            c33 -= k3 * k3 * z
            th_out[t, k] = th
            b_out[t, k, 0], b_out[t, k, 1], b_out[t, k, 2] = b0, b1, b2
            p_out[t, k] = c00


def ekf_scalar_limit(gyro_rad_s, accel_m_s2, is_static, axis, accel0_m_s2, dt_s, var_z=1e-4, var_m=4.0,
                     q_theta=1e-10, q_b=1e-14):
    """RAMS EKF over (T, M, 3) records, one trial per thread iteration; returns θ (T, M), bias, P_θθ."""
    t, m = gyro_rad_s.shape[:2]
    vv = np.asarray(axis, float) / np.linalg.norm(axis)
    a0 = np.broadcast_to(np.asarray(accel0_m_s2, float), (t, 3))
    par = np.ascontiguousarray((a0 @ vv)[:, None] * vv)
    perp = np.ascontiguousarray(a0 - par)
    wv = np.ascontiguousarray(np.cross(vv, a0))
    v = np.ascontiguousarray(np.broadcast_to(vv, (t, 3)))
    th, b, p = np.empty((t, m)), np.empty((t, m, 3)), np.empty((t, m))
    _ekf(gyro_rad_s, accel_m_s2, np.ascontiguousarray(is_static[:m]), v, par, perp, wv, dt_s, var_z, var_m,
         q_theta, q_b, th, b, p)
    return th, b, p
