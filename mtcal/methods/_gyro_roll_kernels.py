"""Compiled per-trial loops of :mod:`mtcal.methods.gyro_roll` (tan2022 roll from gyros).

* :func:`projection` — Eq 13 over many samples (numpy's expression without its temporaries);
* :func:`euler_differential` — the Eq 5 recursion (forward Euler over time, one
  trial after the other), operation by operation the numpy loop it replaces;
* :func:`hybrid_rmse_sweep` — roll RMSE of the Fig 7 hybrid for K thresholds from raw
  gyro samples, one pass per trial with all thresholds advanced together (no (T, N) temporaries);
* :func:`oscillation_claims` — per trial, the Fig 11 spike ratio and the Fig 12
  hybrid max error from raw gyro samples in one pass; with ``accurate_rad`` finite
  it only decides whether both statements hold and stops a trial as soon as the
  hybrid error exceeds it (the statement then fails whatever follows);
  :func:`oscillation_claims_noisy` builds the samples ``(base + offset) + scale · normals``
  on the fly (no record);
* :func:`roll_estimates` — Eq 13, Eq 12 and the hybrid in one pass, bit for bit numpy's;
* :func:`roll_error_summary` — per trial, the Eq 5 / Eq 12 / Eq 13 errors a uniform
  rotation is judged on, in one pass, bit for bit the estimators' outputs reduced.

Kernels are float64 without ``fastmath`` (:func:`mtcal.core.compiled.jit`); sums run
in sample order (numpy's ``cumsum`` order); ``sin``/``cos``/``atan2`` come from the
platform's libm. Where a kernel replays numpy's element-wise expression (the same libm
``atan2``/``hypot``, the same order of operations, a sequential ``cumsum``), it is bit for bit
(tests compare with ``array_equal``); the Eq 5 recursion and the sweeps' sums agree with the
numpy references to rounding (tests compare them with ``allclose``).
"""

from __future__ import annotations

import math

import numpy as np

from mtcal.core._rotation_kernels import wrap_difference
from mtcal.core.compiled import jit

__all__ = ["euler_differential", "hybrid_rmse_sweep", "oscillation_claims",
           "oscillation_claims_noisy", "projection", "roll_error_summary", "roll_estimates"]

_TWO_PI = 2.0 * np.pi


@jit
def _wrap(a):
    """``(a + π) mod 2π − π`` (numpy's ``%`` sign convention); NaN for a non-finite angle."""
    x = a + np.pi
    if 0.0 <= x < _TWO_PI:  # fmod(x, 2π) = x exactly: the common case, without the division
        return x - np.pi
    if -_TWO_PI <= x < 0.0:  # fmod(x, 2π) = x, then + 2π (the sign rule of Python's and numpy's %)
        return (x + _TWO_PI) - np.pi
    if not math.isfinite(x):
        return np.nan
    return x % _TWO_PI - np.pi  # Python's float %: numpy's remainder (sign of the divisor)


@jit
def _div(num, den):
    """``num / den`` with numpy's result for a zero denominator (±inf, NaN for 0/0), no exception."""
    if den != 0.0:
        return num / den
    if num != num or num == 0.0:
        return np.nan
    return np.inf if (num > 0.0) == (math.copysign(1.0, den) > 0.0) else -np.inf


@jit
def euler_differential(w, dt, state0):
    """Eq 5 Euler-angle integration of ``w`` (M, N, 3) from ``state0`` (M, 3) ``[ψ, θ, φ]``; out (M, N, 3)."""
    m, n = w.shape[0], w.shape[1]
    out = np.empty((m, n, 3))
    for i in range(m):
        psi, theta, phi = state0[i, 0], state0[i, 1], state0[i, 2]
        for k in range(n):
            out[i, k, 0] = psi
            out[i, k, 1] = theta
            out[i, k, 2] = phi
            wx, wy, wz = w[i, k, 0], w[i, k, 1], w[i, k, 2]
            sphi, cphi = math.sin(phi), math.cos(phi)
            dpsi = _div(wy * sphi + wz * cphi, math.cos(theta))
            dtheta = wy * cphi - wz * sphi
            dphi = wx + dpsi * math.sin(theta)
            psi, theta, phi = _wrap(psi + dpsi * dt), theta + dtheta * dt, _wrap(phi + dphi * dt)
    return out


@jit
def _oscillation_claims(src, base, offset, scale, mode, dt, thr, roll0, slow, accurate_rad):
    """:func:`oscillation_claims` of the samples built from ``src`` (M, N, 3): ``src`` itself (mode 0),
    ``base[k] + scale[i] src[i, k]`` (mode 1) or ``(base[k] + offset[i]) + scale[i] src[i, k]`` (mode 2),
    numpy's operations on the broadcast arrays."""
    m, n = src.shape[0], src.shape[1]
    spike = np.empty(m)
    hyb = np.empty(m)
    complete = np.ones(m, dtype=np.bool_)
    for i in range(m):
        cum = 0.0
        base_h = roll0
        slow_max, fast_max, h_max = 0.0, 0.0, 0.0
        for k in range(n):
            wx, wy, wz = src[i, k, 0], src[i, k, 1], src[i, k, 2]
            if mode != 0:  # inline (a helper taking the arrays costs reference counting per sample)
                bx, by, bz = base[k, 0], base[k, 1], base[k, 2]
                if mode == 2:
                    bx, by, bz = bx + offset[i], by + offset[i], bz + offset[i]
                wx, wy, wz = bx + scale[i] * wx, by + scale[i] * wy, bz + scale[i] * wz
            sign = -1.0 if wy < 0.0 else 1.0
            p = math.atan2(-wz * sign, abs(wy))
            e_p = abs(p - roll0)
            if slow[k]:
                slow_max = max(slow_max, e_p)
            else:
                fast_max = max(fast_max, e_p)
            if math.hypot(wy, wz) > thr:
                base_h = p - cum
                h = p
            else:
                h = base_h + cum
            h_max = max(h_max, abs(h - roll0))
            cum += wx * dt
            if h_max > accurate_rad:
                complete[i] = False
                break
        spike[i] = slow_max / max(fast_max, 1e-12) if complete[i] else np.nan
        hyb[i] = h_max
    return spike, hyb, complete


@jit
def oscillation_claims(w, dt, thr, roll0, slow, accurate_rad):
    """Per trial of ``w`` (M, N, 3): projection max |error| where ``slow`` / elsewhere and hybrid max |error| (rad).

    Returns ``(spike (M,), hybrid_max (M,), complete (M,) bool)``; a trial stops early (``complete``
    False, ``spike`` NaN) once its hybrid error exceeds ``accurate_rad`` (pass ``inf`` for full records).
    """
    none = np.empty(0)
    return _oscillation_claims(w, np.empty((0, 3)), none, none, 0, dt, thr, roll0, slow, accurate_rad)


@jit
def oscillation_claims_noisy(base, offset, scale, normals, dt, thr, roll0, slow, accurate_rad):
    """:func:`oscillation_claims` of ``w = (base + offset) + scale · normals`` built sample by sample.

    ``base`` (N, 3), ``offset`` (M,) per trial (empty: no offset, ``w = base + scale · normals``),
    ``scale`` (M,), ``normals`` (M, N, 3): numpy's broadcast expression without its (M, N, 3) temporaries.
    """
    mode = 2 if offset.size > 0 else 1
    return _oscillation_claims(normals, base, offset, scale, mode, dt, thr, roll0, slow, accurate_rad)


@jit
def projection(w):
    """Eq 13 ``atan2(−ω_z sgn ω_y, |ω_y|)`` of ``w`` (M, N, 3), out (M, N): numpy's expression, one pass."""
    m, n = w.shape[0], w.shape[1]
    out = np.empty((m, n))
    for i in range(m):
        for k in range(n):
            wy = w[i, k, 1]
            sign = -1.0 if wy < 0.0 else 1.0
            out[i, k] = math.atan2(-w[i, k, 2] * sign, abs(wy))
    return out


@jit
def _nan_max(cur, a):
    """numpy's ``maximum`` reduction step: NaN once NaN, else the larger."""
    if cur != cur:
        return cur
    if a != a or a > cur:
        return a
    return cur


@jit
def roll_error_summary(w, dt, state0, masks, roll0, proj_abs):
    """Per trial of ``w`` (M, N, 3) against the constant roll ``roll0`` (also φ0 of Eq 12), in one pass.

    Returns ``euler_max`` (K, M): max over the samples of each row of ``masks`` (K, N) of
    |wrapped Eq 5 roll − roll0| (the Eq 5 recursion of :func:`euler_differential` from ``state0`` (M, 3),
    ψ not wrapped since it never feeds back), and ``integration_final`` (M,): the last Eq 12 roll
    ``roll0 + Σ_{k<N−1} ω_x,k dt`` (numpy's ``cumsum`` order) minus ``roll0``; writes |Eq 13 roll − roll0|
    per sample into ``proj_abs`` (M, N).
    """
    m, n = w.shape[0], w.shape[1]
    nk = masks.shape[0]
    euler_max = np.zeros((nk, m))
    final = np.empty(m)
    for i in range(m):
        theta, phi = state0[i, 1], state0[i, 2]
        acc = 0.0
        for k in range(n):
            a = abs(wrap_difference(phi, roll0))
            for j in range(nk):
                if masks[j, k]:
                    euler_max[j, i] = _nan_max(euler_max[j, i], a)
            wx, wy, wz = w[i, k, 0], w[i, k, 1], w[i, k, 2]
            sphi, cphi = math.sin(phi), math.cos(phi)
            dpsi = _div(wy * sphi + wz * cphi, math.cos(theta))
            dtheta = wy * cphi - wz * sphi
            dphi = wx + dpsi * math.sin(theta)
            theta, phi = theta + dtheta * dt, _wrap(phi + dphi * dt)
            sign = -1.0 if wy < 0.0 else 1.0
            proj_abs[i, k] = abs(math.atan2(-wz * sign, abs(wy)) - roll0)
            if k == 0:
                acc = wx * dt
            elif k < n - 1:
                acc = acc + wx * dt
        final[i] = ((roll0 + acc) if n > 1 else (roll0 + 0.0)) - roll0
    return euler_max, final


@jit
def roll_estimates(w, dt, thr, phi0, proj, integ, hyb, use):
    """Eq 13, Eq 12 and the Fig 7 hybrid of ``w`` (M, N, 3) from φ0 ``phi0`` (M,), written into (M, N) outputs.

    numpy's operations of :func:`mtcal.methods.gyro_roll.roll_estimates` sample by sample: the
    cumulative x angle in ``cumsum`` order (``Φ_0 = 0``, ``Φ_1 = ω_x,0 dt``, ``Φ_k = Φ_{k−1} + ω_x,k−1 dt``),
    ``use = hypot(ω_y, ω_z) > thr``, the hybrid ``(proj_j − Φ_j) + Φ_k`` from the last projection
    sample ``j ≤ k`` (``φ0 + Φ_k`` before the first one).
    """
    m, n = w.shape[0], w.shape[1]
    for i in range(m):
        p0 = phi0[i]
        cum = 0.0
        base = p0
        for k in range(n):
            wx, wy, wz = w[i, k, 0], w[i, k, 1], w[i, k, 2]
            sign = -1.0 if wy < 0.0 else 1.0
            p = math.atan2(-wz * sign, abs(wy))
            u = math.hypot(wy, wz) > thr
            proj[i, k] = p
            use[i, k] = u
            integ[i, k] = p0 + cum
            if u:
                base = p - cum
                hyb[i, k] = p
            else:
                hyb[i, k] = base + cum
            cum = wx * dt if k == 0 else cum + wx * dt
    return proj, integ, hyb, use


@jit
def hybrid_rmse_sweep(w, dt, phi0, truth, thresholds):
    """RMSE (M, K) of the hybrid ``where(rate > thr, proj, last(proj − cum) + cum) − truth`` per threshold.

    Projection, pitch rate and cumulative x angle per sample of ``w`` (M, N, 3) as :func:`roll_estimates`
    computes them (no (M, N) arrays); all ``thresholds`` (ascending) advance together, each with its own
    sequential sum in sample order."""
    m, n, nk = w.shape[0], w.shape[1], thresholds.size
    out = np.empty((m, nk))
    base = np.empty(nk)
    acc = np.empty(nk)
    for i in range(m):
        base[:] = phi0[i]
        acc[:] = 0.0
        cum = 0.0
        c = 0
        for k in range(n):
            wx, wy, wz = w[i, k, 0], w[i, k, 1], w[i, k, 2]
            sign = -1.0 if wy < 0.0 else 1.0
            p = math.atan2(-wz * sign, abs(wy))
            r = math.hypot(wy, wz)
            tk = truth[k]
            e_p = p - tk
            b_new = p - cum
            while c < nk and r > thresholds[c]:  # thresholds ascending: r > thresholds[j] exactly for j < c
                c += 1
            while c > 0 and not r > thresholds[c - 1]:
                c -= 1
            ep2 = e_p * e_p
            for j in range(c):  # projection samples
                base[j] = b_new
                acc[j] += ep2
            for j in range(c, nk):  # integration samples
                e = base[j] + cum - tk
                acc[j] += e * e
            cum = wx * dt if k == 0 else cum + wx * dt
        for j in range(nk):
            out[i, j] = math.sqrt(acc[j] / n)
    return out
