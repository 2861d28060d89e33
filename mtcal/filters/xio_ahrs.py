"""Madgwick and Mahony orientation filters in the x-io formulation, compiled, over a grid of gains.

The two filters the BROAD case study (broad2021) runs, written from their papers in the
per-sample form of Madgwick's open-source implementation (x-io, 2011–2012), and run as
numba kernels with one *lane* per gain setting on the same record (a parameter grid in one
pass):

* **Madgwick** (Madgwick 2010, Eq 25–33; ICORR 2011): ``q̇ = ½ q ⊗ [0, ω] − β ∇f/‖∇f‖``,
  ``f`` the gravity residual (6D) or gravity + Earth-field residual (9D) with the field
  reference ``b = [0, b_x, 0, b_z]``, ``b_x = ‖h_xy‖``, ``b_z = h_z`` (``h = q ⊗ m ⊗ q*``,
  Eq 45–46); explicit Euler step, renormalised.
* **Mahony** (Mahony, Hamel & Pflimlin 2008, explicit complementary filter, Eq 32; x-io's
  9D form): error ``e = â × v̂ + m̂ × ŵ`` (``v̂`` predicted "up", ``ŵ`` predicted field from
  the horizontal/vertical reference), ``ω̃ = ω + K_p e + K_i ∫e dt`` (the integral is reset
  to 0 when ``K_i = 0``), explicit Euler step of ``½ q ⊗ [0, ω̃]``, renormalised.

Conventions: scalar-first ``q`` (sensor → earth), the earth frame of the filter has ``x``
along the horizontal magnetic field and ``z`` up (a 9D estimate is rotated by +90° about
``z`` into ENU with :data:`NWU_TO_ENU`, as BROAD does); output row ``k`` is the estimate
**after** sample ``k`` (``timing="after"``, BROAD's) or **before** it (``"before"``: the
attitude at ``t_k``, mtcal's convention, :mod:`mtcal.filters.anchors`).

``field_reference="c"`` reproduces the x-io C/C++ code BROAD ran, whose Earth-field
reference is half the paper's (it names ``‖h_xy‖`` "_2bx"; dlaidig/broad issue #1);
``"paper"`` uses Eq 46 as printed (``ahrs.filters.Madgwick.updateMARG`` does the same).
Everything here is float64; the C code runs in float32.

References
----------
.. [1] S. O. H. Madgwick, "An efficient orientation filter for inertial and inertial/magnetic
   sensor arrays", internal report, University of Bristol, 2010 (Eq 25–33, 45–46).
.. [2] R. Mahony, T. Hamel, J.-M. Pflimlin, "Nonlinear complementary filters on the special
   orthogonal group", IEEE TAC 53(5):1203–1218, 2008, doi:10.1109/TAC.2008.923738.
.. [3] D. Laidig, M. Caruso, A. Cereatti, T. Seel, "BROAD — A Benchmark for Robust Inertial
   Orientation Estimation", Data 6(7):72, 2021 (its example code and issue #1).

Examples
--------
>>> import numpy as np
>>> n = 200
>>> gyr = np.zeros((n, 3)); acc = np.tile([0.0, 0.0, 9.81], (n, 1)); mag = np.tile([20.0, 0.0, -40.0], (n, 1))
>>> q = madgwick(gyr, acc, 0.01, [0.1, 0.3], mag_uT=mag)
>>> q.shape, bool(np.allclose(q[:, -1], [1.0, 0, 0, 0], atol=1e-9))
((2, 200, 4), True)
>>> q = mahony(gyr, acc, 0.01, [0.5], [0.001], mag_uT=mag)
>>> bool(np.allclose(q[0, -1], [1.0, 0, 0, 0], atol=1e-9))
True
"""

from __future__ import annotations

import math

import numpy as np
from numba import prange

from mtcal.core.validate import as_float_array
from mtcal.filters._kernels_common import jit

__all__ = ["madgwick", "mahony", "initial_quaternion_acc_mag", "NWU_TO_ENU", "TIMINGS", "FIELD_REFERENCES"]

#: +90° about the vertical: the filter's earth frame (x along the horizontal field) → ENU.
NWU_TO_ENU = np.array([math.sqrt(0.5), 0.0, 0.0, math.sqrt(0.5)])
#: Output timing: estimate after sample k (BROAD) or before it (attitude at t_k, mtcal).
TIMINGS = ("after", "before")
#: Earth-field reference of the 9D Madgwick step: x-io C code ("c", half of Eq 46) or the paper's Eq 46.
FIELD_REFERENCES = ("c", "paper")


@jit()
def _madgwick_lane(g, a, m, use_mag, q_init, beta, dt, field_k, before, hold_zero_rate, out, lane):
    q0, q1, q2, q3 = q_init[0], q_init[1], q_init[2], q_init[3]
    for i in range(g.shape[0]):
        if before:
            out[lane, i, 0] = q0
            out[lane, i, 1] = q1
            out[lane, i, 2] = q2
            out[lane, i, 3] = q3
        gx, gy, gz = g[i, 0], g[i, 1], g[i, 2]
        if hold_zero_rate and gx == 0.0 and gy == 0.0 and gz == 0.0:
            # ahrs' Madgwick.updateIMU/updateMARG return q unchanged on an exactly zero rate sample
            if not before:
                out[lane, i, 0] = q0
                out[lane, i, 1] = q1
                out[lane, i, 2] = q2
                out[lane, i, 3] = q3
            continue
        d0 = 0.5 * (-q1 * gx - q2 * gy - q3 * gz)
        d1 = 0.5 * (q0 * gx + q2 * gz - q3 * gy)
        d2 = 0.5 * (q0 * gy - q1 * gz + q3 * gx)
        d3 = 0.5 * (q0 * gz + q1 * gy - q2 * gx)
        ax, ay, az = a[i, 0], a[i, 1], a[i, 2]
        an = math.sqrt(ax * ax + ay * ay + az * az)
        if an > 0.0:
            ax /= an
            ay /= an
            az /= an
            # gravity residual f_g (Eq 25 with d = [0, 0, 0, 1]) and its Jacobian-transposed product
            f1 = 2.0 * (q1 * q3 - q0 * q2) - ax
            f2 = 2.0 * (q0 * q1 + q2 * q3) - ay
            f3 = 2.0 * (0.5 - q1 * q1 - q2 * q2) - az
            s0 = -2.0 * q2 * f1 + 2.0 * q1 * f2
            s1 = 2.0 * q3 * f1 + 2.0 * q0 * f2 - 4.0 * q1 * f3
            s2 = -2.0 * q0 * f1 + 2.0 * q3 * f2 - 4.0 * q2 * f3
            s3 = 2.0 * q1 * f1 + 2.0 * q2 * f2
            mx, my, mz = m[i, 0], m[i, 1], m[i, 2]
            mn = math.sqrt(mx * mx + my * my + mz * mz)
            if use_mag and mn > 0.0:
                mx /= mn
                my /= mn
                mz /= mn
                # h = q ⊗ m ⊗ q* (Eq 45), reference b = [0, bx, 0, bz] (Eq 46), scaled by field_k / 2
                hx = (mx * (1.0 - 2.0 * (q2 * q2 + q3 * q3)) + 2.0 * my * (q1 * q2 - q0 * q3)
                      + 2.0 * mz * (q1 * q3 + q0 * q2))
                hy = (2.0 * mx * (q1 * q2 + q0 * q3) + my * (1.0 - 2.0 * (q1 * q1 + q3 * q3))
                      + 2.0 * mz * (q2 * q3 - q0 * q1))
                hz = (2.0 * mx * (q1 * q3 - q0 * q2) + 2.0 * my * (q2 * q3 + q0 * q1)
                      + mz * (1.0 - 2.0 * (q1 * q1 + q2 * q2)))
                bx = 0.5 * field_k * math.sqrt(hx * hx + hy * hy)
                bz = 0.5 * field_k * hz
                # field residual f_b (Eq 29) and J_bᵀ f_b (Eq 30)
                f4 = bx * (1.0 - 2.0 * (q2 * q2 + q3 * q3)) + 2.0 * bz * (q1 * q3 - q0 * q2) - mx
                f5 = 2.0 * bx * (q1 * q2 - q0 * q3) + 2.0 * bz * (q0 * q1 + q2 * q3) - my
                f6 = 2.0 * bx * (q0 * q2 + q1 * q3) + bz * (1.0 - 2.0 * (q1 * q1 + q2 * q2)) - mz
                s0 += -2.0 * bz * q2 * f4 + (-2.0 * bx * q3 + 2.0 * bz * q1) * f5 + 2.0 * bx * q2 * f6
                s1 += 2.0 * bz * q3 * f4 + (2.0 * bx * q2 + 2.0 * bz * q0) * f5 + (2.0 * bx * q3 - 4.0 * bz * q1) * f6
                s2 += ((-4.0 * bx * q2 - 2.0 * bz * q0) * f4 + (2.0 * bx * q1 + 2.0 * bz * q3) * f5
                       + (2.0 * bx * q0 - 4.0 * bz * q2) * f6)
                s3 += (-4.0 * bx * q3 + 2.0 * bz * q1) * f4 + (-2.0 * bx * q0 + 2.0 * bz * q2) * f5 + 2.0 * bx * q1 * f6
            sn = math.sqrt(s0 * s0 + s1 * s1 + s2 * s2 + s3 * s3)
            if sn > 0.0:
                d0 -= beta * s0 / sn
                d1 -= beta * s1 / sn
                d2 -= beta * s2 / sn
                d3 -= beta * s3 / sn
        q0 += d0 * dt
        q1 += d1 * dt
        q2 += d2 * dt
        q3 += d3 * dt
        qn = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
        q0 /= qn
        q1 /= qn
        q2 /= qn
        q3 /= qn
        if not before:
            out[lane, i, 0] = q0
            out[lane, i, 1] = q1
            out[lane, i, 2] = q2
            out[lane, i, 3] = q3


@jit(parallel=True)
def _madgwick_lanes(g, a, m, use_mag, q_init, betas, dt, field_k, before, hold_zero_rate, out):
    for lane in prange(betas.shape[0]):
        _madgwick_lane(g, a, m, use_mag, q_init, betas[lane], dt, field_k, before, hold_zero_rate, out, lane)


@jit()
def _mahony_lane(g, a, m, use_mag, q_init, kp, ki, dt, before, out, lane):
    q0, q1, q2, q3 = q_init[0], q_init[1], q_init[2], q_init[3]
    i0 = i1 = i2 = 0.0
    for i in range(g.shape[0]):
        if before:
            out[lane, i, 0] = q0
            out[lane, i, 1] = q1
            out[lane, i, 2] = q2
            out[lane, i, 3] = q3
        gx, gy, gz = g[i, 0], g[i, 1], g[i, 2]
        ax, ay, az = a[i, 0], a[i, 1], a[i, 2]
        an = math.sqrt(ax * ax + ay * ay + az * az)
        if an > 0.0:
            ax /= an
            ay /= an
            az /= an
            # predicted "up" v̂ = third row of C(q); e = â × v̂
            vx = 2.0 * (q1 * q3 - q0 * q2)
            vy = 2.0 * (q0 * q1 + q2 * q3)
            vz = 2.0 * (q0 * q0 - 0.5 + q3 * q3)
            ex = ay * vz - az * vy
            ey = az * vx - ax * vz
            ez = ax * vy - ay * vx
            mx, my, mz = m[i, 0], m[i, 1], m[i, 2]
            mn = math.sqrt(mx * mx + my * my + mz * mz)
            if use_mag and mn > 0.0:
                mx /= mn
                my /= mn
                mz /= mn
                hx = 2.0 * (mx * (0.5 - q2 * q2 - q3 * q3) + my * (q1 * q2 - q0 * q3) + mz * (q1 * q3 + q0 * q2))
                hy = 2.0 * (mx * (q1 * q2 + q0 * q3) + my * (0.5 - q1 * q1 - q3 * q3) + mz * (q2 * q3 - q0 * q1))
                bx = math.sqrt(hx * hx + hy * hy)
                bz = 2.0 * (mx * (q1 * q3 - q0 * q2) + my * (q2 * q3 + q0 * q1) + mz * (0.5 - q1 * q1 - q2 * q2))
                # predicted field ŵ = C(q)ᵀ [bx, 0, bz]; e += m̂ × ŵ
                wx = 2.0 * (bx * (0.5 - q2 * q2 - q3 * q3) + bz * (q1 * q3 - q0 * q2))
                wy = 2.0 * (bx * (q1 * q2 - q0 * q3) + bz * (q0 * q1 + q2 * q3))
                wz = 2.0 * (bx * (q0 * q2 + q1 * q3) + bz * (0.5 - q1 * q1 - q2 * q2))
                ex += my * wz - mz * wy
                ey += mz * wx - mx * wz
                ez += mx * wy - my * wx
            if ki > 0.0:
                i0 += ki * ex * dt
                i1 += ki * ey * dt
                i2 += ki * ez * dt
                gx += i0
                gy += i1
                gz += i2
            else:
                i0 = i1 = i2 = 0.0
            gx += kp * ex
            gy += kp * ey
            gz += kp * ez
        hx2 = 0.5 * dt * gx
        hy2 = 0.5 * dt * gy
        hz2 = 0.5 * dt * gz
        qa, qb, qc = q0, q1, q2
        q0 += -qb * hx2 - qc * hy2 - q3 * hz2
        q1 += qa * hx2 + qc * hz2 - q3 * hy2
        q2 += qa * hy2 - qb * hz2 + q3 * hx2
        q3 += qa * hz2 + qb * hy2 - qc * hx2
        qn = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
        q0 /= qn
        q1 /= qn
        q2 /= qn
        q3 /= qn
        if not before:
            out[lane, i, 0] = q0
            out[lane, i, 1] = q1
            out[lane, i, 2] = q2
            out[lane, i, 3] = q3


@jit(parallel=True)
def _mahony_lanes(g, a, m, use_mag, q_init, kps, kis, dt, before, out):
    for lane in prange(kps.shape[0]):
        _mahony_lane(g, a, m, use_mag, q_init, kps[lane], kis[lane], dt, before, out, lane)


def _records(gyro_rad_s, accel_m_s2, mag_uT, q0):
    """C-contiguous float64 views of a checked record (copies only where the layout needs one) and the start."""
    g = np.ascontiguousarray(gyro_rad_s, dtype=np.float64)
    a = np.ascontiguousarray(accel_m_s2, dtype=np.float64)
    use_mag = mag_uT is not None
    m = np.ascontiguousarray(mag_uT, dtype=np.float64) if use_mag else np.zeros((1, 3))
    q_init = np.array([1.0, 0.0, 0.0, 0.0]) if q0 is None else np.array(q0, dtype=np.float64)
    return g, a, m, use_mag, q_init


def _lanes(values) -> np.ndarray:
    """One gain per lane: a float64 (L,) copy of a scalar or a sequence."""
    return np.atleast_1d(np.array(values, dtype=np.float64)).ravel()


def madgwick(gyro_rad_s: np.ndarray, accel_m_s2: np.ndarray, dt_s: float, beta_rad_s, *,
             mag_uT: np.ndarray | None = None, q0: np.ndarray | None = None, timing: str = "after",
             field_reference: str = "c", hold_zero_rate: bool = False) -> np.ndarray:
    """Madgwick's gradient-descent filter (6D, or 9D with ``mag_uT``) for each β, shape (L, N, 4).

    Parameters
    ----------
    gyro_rad_s, accel_m_s2 : ndarray, shape (N, 3)
        Rate (rad/s) and specific force (m/s², any unit: normalised).
    dt_s : float
        Sample interval (s).
    beta_rad_s : float or array_like, shape (L,)
        Gain β of Eq 33 (rad/s), one lane each.
    mag_uT : ndarray, shape (N, 3), optional
        Magnetometer (any unit: normalised); 9D when given.
    q0 : ndarray, shape (4,), optional
        Start (sensor → filter earth frame); identity by default.
    timing : {"after", "before"}
        Row k = estimate after sample k, or before it (attitude at ``t_k``).
    field_reference : {"c", "paper"}
        9D field reference: x-io's C code (half of Eq 46, what BROAD ran) or Eq 46.
    hold_zero_rate : bool
        Skip a sample whose rate is exactly zero (q unchanged), as ``ahrs``' Madgwick does
        (the compiled bake-off anchor, :mod:`mtcal.filters.anchors`); x-io's code updates.

    Returns
    -------
    ndarray, shape (L, N, 4)

    Preconditions
    -------------
    The caller guarantees (not checked here): ``gyro_rad_s`` and ``accel_m_s2`` finite float64 arrays of
    one shape (N, 3), the gyro in rad/s; ``mag_uT`` None or finite (N, 3); ``dt_s`` > 0 (s); every gain
    finite (β > 0, K_p and K_i ≥ 0); ``q0`` None or a unit quaternion (4,); ``timing`` in :data:`TIMINGS`;
    ``field_reference`` in :data:`FIELD_REFERENCES`. The records are checked once at their edge:
    :func:`mtcal.filters.anchors.run_attitude_filter` (``"madgwick"``, whose runner this is) or the
    broad2021 trial loader (:func:`mtcal.studies.broad2021.scenario.load_trial`).

    References
    ----------
    Madgwick 2010, Eq 25–33, 45–46 (module references).
    """
    g, a, m, use_mag, q_init = _records(gyro_rad_s, accel_m_s2, mag_uT, q0)
    betas = _lanes(beta_rad_s)
    out = np.empty((betas.size, g.shape[0], 4))
    _madgwick_lanes(g, a, m, use_mag, q_init, betas, float(dt_s), 1.0 if field_reference == "c" else 2.0,
                    timing == "before", bool(hold_zero_rate), out)
    return out


def mahony(gyro_rad_s: np.ndarray, accel_m_s2: np.ndarray, dt_s: float, kp_rad_s, ki_rad_s2, *,
           mag_uT: np.ndarray | None = None, q0: np.ndarray | None = None, timing: str = "after") -> np.ndarray:
    """Mahony's explicit complementary filter (6D, or 9D with ``mag_uT``) for each (K_p, K_i), shape (L, N, 4).

    Parameters
    ----------
    gyro_rad_s, accel_m_s2 : ndarray, shape (N, 3)
        Rate (rad/s) and specific force (normalised).
    dt_s : float
        Sample interval (s).
    kp_rad_s, ki_rad_s2 : float or array_like, shape (L,)
        Proportional (1/s) and integral (1/s²) gains, one lane per pair (broadcast).
    mag_uT : ndarray, shape (N, 3), optional
        Magnetometer (normalised); 9D when given.
    q0 : ndarray, shape (4,), optional
        Start; identity by default.
    timing : {"after", "before"}
        As :func:`madgwick`.

    Returns
    -------
    ndarray, shape (L, N, 4)

    Preconditions
    -------------
    The caller guarantees (not checked here): ``gyro_rad_s`` and ``accel_m_s2`` finite float64 arrays of
    one shape (N, 3), the gyro in rad/s; ``mag_uT`` None or finite (N, 3); ``dt_s`` > 0 (s); every gain
    finite (β > 0, K_p and K_i ≥ 0); ``q0`` None or a unit quaternion (4,); ``timing`` in :data:`TIMINGS`.
    The records are checked once at their edge: the broad2021 trial loader
    (:func:`mtcal.studies.broad2021.scenario.load_trial`).

    References
    ----------
    Mahony, Hamel & Pflimlin 2008, Eq 32 (module references).
    """
    g, a, m, use_mag, q_init = _records(gyro_rad_s, accel_m_s2, mag_uT, q0)
    kp, ki = np.broadcast_arrays(_lanes(kp_rad_s), _lanes(ki_rad_s2))
    kp, ki = np.ascontiguousarray(kp), np.ascontiguousarray(ki)
    out = np.empty((kp.size, g.shape[0], 4))
    _mahony_lanes(g, a, m, use_mag, q_init, kp, ki, float(dt_s), timing == "before", out)
    return out


def initial_quaternion_acc_mag(accel, mag) -> np.ndarray:
    """Start attitude from one accelerometer and one magnetometer sample (sensor → x-field, z-up frame), (4,).

    Columns of the rotation matrix: ``z = a/‖a‖``, ``x ∝ (z × (−m)) × z = −m_h`` (minus the
    horizontal part of the field), ``y = z × x``; the quaternion of that matrix (BROAD's start, its
    ``quatFromAccMag``). Note the sign: the frame's ``x`` points *against* the horizontal field,
    whereas the 9D filters pull the horizontal field onto ``+x``.

    >>> q = initial_quaternion_acc_mag(np.array([0.0, 0.0, 9.81]), np.array([-20.0, 0.0, -40.0]))
    >>> np.round(q, 12).tolist()
    [1.0, -0.0, 0.0, -0.0]
    """
    from mtcal.core import rotations

    z = as_float_array(accel, "accel", ndim=1, last_dim=3)
    mv = as_float_array(mag, "mag", ndim=1, last_dim=3)
    x = np.cross(np.cross(z, -mv), z)
    y = np.cross(z, x)
    r = np.column_stack([x / np.linalg.norm(x), y / np.linalg.norm(y), z / np.linalg.norm(z)])
    return rotations.quat_from_matrix(r)
