"""Anchors for ``make bench``: what a user would run instead of mtcal's batched filters.

Each anchor is a thin, faithful wrapper of a public library (or the plain numpy
a user would write) so that throughputs compare like with like:

* :func:`ahrs_mahony_batch` — ``ahrs.filters.Mahony(gyr=..., acc=...)`` (ahrs 0.4.0;
  internally a Python loop over ``updateIMU``).
* :func:`ahrs_mahony_loop` — the documented per-sample use,
  ``Q[t] = Mahony().updateIMU(Q[t-1], gyr[t], acc[t])``.
* :func:`imufusion_loop` — ``imufusion.Ahrs.update_no_magnetometer`` per sample
  (C library; gyro in °/s, accelerometer in g, as the library expects).
* :func:`vqf_batch` — ``vqf.VQF(Ts).updateBatch(gyr, acc)`` and
  ``vqf.BasicVQF(Ts).updateBatch(gyr, acc)`` (vqf 2.1, C++ loop over the
  record; gyro in rad/s, accelerometer in m/s² — mtcal's units, no conversion;
  ``quat6D`` is sensor → earth, z up, scalar first, like mtcal's ``q_ws``).
* :func:`memory_floor` — not a filter: a compiled trial-parallel pass that
  reads gyro + accel and writes a quaternion-sized output, i.e. the least
  memory traffic any filter of these records must do.
* :func:`filterpy_ekf_loop` — ``filterpy.kalman.ExtendedKalmanFilter`` with the
  4-state RAMS model ``x = [θ, b_x, b_y, b_z]`` (wang2022sensors Eq 24–33): predict with
  ``u = ω``, update with ``h(θ) = R(θ, v)ᵀ ā0`` (Joseph form inside filterpy).
* :func:`numpy_ekf_loop` — the same EKF written as textbook 4×4/3×3 numpy matrix
  algebra per sample (``inv(S)``, Joseph form).
* :func:`numpy_mahony_batched` — ahrs's Mahony algorithm written in natural numpy,
  vectorised over a leading trial axis (loop over time only), i.e. what a numpy
  user would write for a Monte Carlo.

Conventions follow each library (ahrs uses gyro sample ``t`` for the step
``t−1 → t``; the EKF predicts with sample ``k−1`` then corrects with accel ``k``,
like :class:`mtcal.filters.rams_ekf.RamsEkfReference`). The anchors are
benchmarks, not part of the mtcal library; their outputs are checked for sanity
and mutual agreement in ``tests/test_bench_smoke.py``.
"""

from __future__ import annotations

import numpy as np

from mtcal.filters.rams_ekf import RamsEkfParams

__all__ = ["ekf_matrices", "ekf_measurement", "ahrs_mahony_batch", "ahrs_mahony_loop", "imufusion_loop",
           "vqf_batch", "memory_floor", "numpy_copy_floor", "filterpy_ekf_loop", "numpy_ekf_loop",
           "numpy_mahony_batched"]

_G = 9.80665


# --------------------------------------------------------------------------- Mahony
def ahrs_mahony_batch(gyro_rad_s: np.ndarray, accel_m_s2: np.ndarray, dt_s: float,
                      kp: float = 1.0, ki: float = 0.02, q0=(1.0, 0.0, 0.0, 0.0)) -> np.ndarray:
    """ahrs 0.4.0 Mahony over a whole record (N, 3) → quaternions (N, 4)."""
    from ahrs.filters import Mahony

    return Mahony(gyr=gyro_rad_s, acc=accel_m_s2, frequency=1.0 / dt_s, k_P=kp, k_I=ki,
                  q0=np.asarray(q0, float)).Q


def ahrs_mahony_loop(gyro_rad_s: np.ndarray, accel_m_s2: np.ndarray, dt_s: float,
                     kp: float = 1.0, ki: float = 0.02, q0=(1.0, 0.0, 0.0, 0.0)) -> np.ndarray:
    """ahrs 0.4.0 ``Mahony.updateIMU`` called once per sample (N, 3) → (N, 4)."""
    from ahrs.filters import Mahony

    filt = Mahony(frequency=1.0 / dt_s, k_P=kp, k_I=ki)
    n = gyro_rad_s.shape[0]
    q = np.empty((n, 4))
    q[0] = q0
    for t in range(1, n):
        q[t] = filt.updateIMU(q[t - 1], gyro_rad_s[t], accel_m_s2[t], dt=dt_s)
    return q


def numpy_mahony_batched(gyro_rad_s: np.ndarray, accel_m_s2: np.ndarray, dt_s: float,
                         kp: float = 1.0, ki: float = 0.02, q0=(1.0, 0.0, 0.0, 0.0)) -> np.ndarray:
    """ahrs's Mahony in plain numpy over trials: (T, N, 3) → (T, N, 4).

    Same update as ``ahrs.filters.Mahony.updateIMU``: ``v = Cᵀ e_z``,
    ``e = â × v``, ``b ← b − k_I e Δt``, ``Ω = ω − b + k_P e``,
    ``q ← normalise(q + ½ q ⊗ [0, Ω] Δt)``; like ahrs, a trial whose gyro
    sample is exactly zero (quantised output) keeps q and b unchanged.
    """
    trials, n = gyro_rad_s.shape[:2]
    out = np.empty((trials, n, 4))
    out[:, 0] = q0
    bias = np.zeros((trials, 3))
    p = np.zeros((trials, 4))
    for t in range(1, n):
        q = out[:, t - 1]
        still = ~np.any(gyro_rad_s[:, t] != 0.0, axis=-1)  # ahrs returns q unchanged when ω == 0
        q0_, q1, q2, q3 = q[:, 0], q[:, 1], q[:, 2], q[:, 3]
        v = np.stack([2.0 * (q1 * q3 - q0_ * q2), 2.0 * (q0_ * q1 + q2 * q3),
                      q0_**2 - q1**2 - q2**2 + q3**2], axis=-1)
        a = accel_m_s2[:, t]
        e = np.cross(a / np.linalg.norm(a, axis=-1, keepdims=True), v)
        if still.any():
            e[still] = 0.0
        bias -= ki * e * dt_s
        p[:, 1:] = gyro_rad_s[:, t] - bias + kp * e
        q_new = q + 0.5 * _hamilton(q, p) * dt_s
        out[:, t] = q_new / np.linalg.norm(q_new, axis=-1, keepdims=True)
        if still.any():
            out[still, t] = q[still]
    return out


def _hamilton(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    p0, p1, p2, p3 = p[..., 0], p[..., 1], p[..., 2], p[..., 3]
    q0, q1, q2, q3 = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.stack([p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3,
                     p0 * q1 + p1 * q0 + p2 * q3 - p3 * q2,
                     p0 * q2 - p1 * q3 + p2 * q0 + p3 * q1,
                     p0 * q3 + p1 * q2 - p2 * q1 + p3 * q0], axis=-1)


# --------------------------------------------------------------------------- imufusion
def imufusion_loop(gyro_rad_s: np.ndarray, accel_m_s2: np.ndarray, dt_s: float, gain: float = 0.5,
                   q0=(1.0, 0.0, 0.0, 0.0)) -> np.ndarray:
    """imufusion 1.3.3 ``Ahrs.update_no_magnetometer`` per sample (N, 3) → (N, 4).

    NWU convention (z up, like mtcal's world frame), start-up ramp skipped,
    acceleration rejection off. Unit conversion (rad/s → °/s, m/s² → g) is
    vectorised before the loop and included in the timing.
    """
    import imufusion

    ahrs = imufusion.Ahrs()
    ahrs.set_settings(imufusion.AhrsSettings(sample_rate=1.0 / dt_s, convention=imufusion.CONVENTION_NWU,
                                             gain=gain, gyroscope_range=2000.0, acceleration_rejection=0.0,
                                             magnetic_rejection=0.0, rejection_timeout=0))
    ahrs.skip_startup()
    ahrs.set_quaternion(np.asarray(q0, float))
    gyro_deg = np.degrees(gyro_rad_s)
    accel_g = accel_m_s2 / _G
    n = gyro_rad_s.shape[0]
    q = np.empty((n, 4))
    for k in range(n):
        q[k] = ahrs.get_quaternion()  # attitude at t_k, before sample k
        ahrs.update_no_magnetometer(gyro_deg[k], accel_g[k])
    return q


# --------------------------------------------------------------------------- vqf
def vqf_batch(gyro_rad_s: np.ndarray, accel_m_s2: np.ndarray, dt_s: float, basic: bool = False) -> np.ndarray:
    """vqf 2.1 ``VQF`` (or ``BasicVQF``) ``updateBatch`` over a record (N, 3) → ``quat6D`` (N, 4).

    Units: vqf takes rad/s and m/s² (mtcal's), so the arrays are passed as they are
    (contiguous float64 copies only if needed — vqf requires them).
    """
    import vqf

    cls = vqf.BasicVQF if basic else vqf.VQF
    filt = cls(dt_s)
    out = filt.updateBatch(np.ascontiguousarray(gyro_rad_s, dtype=float), np.ascontiguousarray(accel_m_s2, dtype=float))
    return out["quat6D"]


# --------------------------------------------------------------------------- memory floor
_FLOOR_KERNEL = None


def memory_floor(gyro_rad_s: np.ndarray, accel_m_s2: np.ndarray) -> np.ndarray:
    """Read gyro + accel (T, N, 3), write a (T, N, 4) output: the memory traffic floor of a filter.

    A numba ``prange`` kernel over trials (numba's threads, like mtcal's kernels);
    the output is a trivial function of the inputs so that nothing is optimised away.
    """
    global _FLOOR_KERNEL
    if _FLOOR_KERNEL is None:
        import numba

        @numba.njit(parallel=True, cache=True)
        def floor(g, a, out):
            for t in numba.prange(g.shape[0]):
                for k in range(g.shape[1]):
                    out[t, k, 0] = g[t, k, 0] + a[t, k, 0]
                    out[t, k, 1] = g[t, k, 1] + a[t, k, 1]
                    out[t, k, 2] = g[t, k, 2] + a[t, k, 2]
                    out[t, k, 3] = a[t, k, 2]
        _FLOOR_KERNEL = floor
    out = np.empty(gyro_rad_s.shape[:-1] + (4,))
    g3 = gyro_rad_s if gyro_rad_s.ndim == 3 else gyro_rad_s[None]
    a3 = accel_m_s2 if accel_m_s2.ndim == 3 else accel_m_s2[None]
    _FLOOR_KERNEL(g3, a3, out if out.ndim == 3 else out[None])
    return out


def numpy_copy_floor(gyro_rad_s: np.ndarray, accel_m_s2: np.ndarray) -> np.ndarray:
    """The same traffic with numpy copies (one thread): gyro and accel into a (T, N, 4) output."""
    out = np.empty(gyro_rad_s.shape[:-1] + (4,))
    out[..., :3] = gyro_rad_s
    out[..., 3] = accel_m_s2[..., 2]
    np.add(out[..., :3], accel_m_s2, out=out[..., :3])
    return out


# --------------------------------------------------------------------------- 4-state EKF
def ekf_matrices(params: RamsEkfParams, axis, dt_s: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """F, B (control ω), Q (``params.process_noise``, Eq 24–27) and P0 of the 4-state RAMS EKF."""
    v = np.asarray(axis, float)
    f = np.eye(4)
    f[0, 1:] = -v * dt_s
    b = np.zeros((4, 3))
    b[0] = v * dt_s
    return f, b, params.process_noise(v, dt_s), params.initial_covariance()


def ekf_measurement(theta_rad: float, axis, accel0_m_s2) -> tuple[np.ndarray, np.ndarray]:
    """``h(θ) = R(θ, v)ᵀ ā0`` (wang2022sensors Eq 28) and ``dh/dθ`` for one θ, shapes (3,) and (3,)."""
    v = np.asarray(axis, float)
    a0 = np.asarray(accel0_m_s2, float)
    par = v * (v @ a0)
    perp = a0 - par
    w = np.cross(v, a0)
    c, s = np.cos(theta_rad), np.sin(theta_rad)
    return par + c * perp - s * w, -s * perp - c * w


def filterpy_ekf_loop(gyro_rad_s: np.ndarray, accel_m_s2: np.ndarray, is_static: np.ndarray, axis,
                      accel0_m_s2, dt_s: float, noise: RamsEkfParams = RamsEkfParams(), theta0_rad: float = 0.0,
                      bias0_rad_s=(0.0, 0.0, 0.0)) -> tuple[np.ndarray, np.ndarray]:
    """filterpy ``ExtendedKalmanFilter`` RAMS loop (N, 3) → θ (N,), bias (N, 3)."""
    from filterpy.kalman import ExtendedKalmanFilter

    f, b, q, p0 = ekf_matrices(noise, axis, dt_s)
    ekf = ExtendedKalmanFilter(dim_x=4, dim_z=3)
    ekf.x = np.array([theta0_rad, *bias0_rad_s], float).reshape(4, 1)
    ekf.F, ekf.B, ekf.Q, ekf.P = f, b, q, p0.copy()
    r_static = noise.sigma_a_static_m_s2**2 * np.eye(3)
    r_moving = noise.sigma_a_moving_m_s2**2 * np.eye(3)

    def hx(x):
        return ekf_measurement(x[0, 0], axis, accel0_m_s2)[0].reshape(3, 1)

    def hjac(x):
        h = np.zeros((3, 4))
        h[:, 0] = ekf_measurement(x[0, 0], axis, accel0_m_s2)[1]
        return h

    n = accel_m_s2.shape[0]
    theta, bias = np.empty(n), np.empty((n, 3))
    for k in range(n):
        if k:
            ekf.predict(u=gyro_rad_s[k - 1].reshape(3, 1))
        ekf.update(accel_m_s2[k].reshape(3, 1), hjac, hx, R=r_static if is_static[k] else r_moving)
        theta[k] = ekf.x[0, 0]
        bias[k] = ekf.x[1:, 0]
    return theta, bias


def numpy_ekf_loop(gyro_rad_s: np.ndarray, accel_m_s2: np.ndarray, is_static: np.ndarray, axis,
                   accel0_m_s2, dt_s: float, noise: RamsEkfParams = RamsEkfParams(), theta0_rad: float = 0.0,
                   bias0_rad_s=(0.0, 0.0, 0.0)) -> tuple[np.ndarray, np.ndarray]:
    """Textbook numpy EKF (4×4 matrices, ``inv(S)``, Joseph form) per sample → θ (N,), bias (N, 3)."""
    f, b, q, p = ekf_matrices(noise, axis, dt_s)
    x = np.array([theta0_rad, *bias0_rad_s], float)
    r_static = noise.sigma_a_static_m_s2**2 * np.eye(3)
    r_moving = noise.sigma_a_moving_m_s2**2 * np.eye(3)
    eye4 = np.eye(4)
    hj = np.zeros((3, 4))
    n = accel_m_s2.shape[0]
    theta, bias = np.empty(n), np.empty((n, 3))
    for k in range(n):
        if k:
            x = f @ x + b @ gyro_rad_s[k - 1]
            p = f @ p @ f.T + q
        h, dh = ekf_measurement(x[0], axis, accel0_m_s2)
        hj[:, 0] = dh
        r = r_static if is_static[k] else r_moving
        s = hj @ p @ hj.T + r
        gain = p @ hj.T @ np.linalg.inv(s)
        x = x + gain @ (accel_m_s2[k] - h)
        ikh = eye4 - gain @ hj
        p = ikh @ p @ ikh.T + gain @ r @ gain.T
        theta[k] = x[0]
        bias[k] = x[1:]
    return theta, bias
