"""wang2022sensors baselines: the accelerometer-only angle of ref. [16] and a commercial-AHRS stand-in.

* :func:`accel_only_angle` — ref. [16] (Cao et al. 2017) as the paper uses
  it: the angle is solved from the *static* acceleration model
  ``a = R(θ, v)ᵀ ā0`` sample by sample, no gyro, so sensor noise goes straight
  into the angle and any dynamic (lever-arm) acceleration is read as angle.
  Closed form: ``θ = atan2(vᵀ(a × ā0), a⊥ · ā0⊥)``.
* :func:`mahony_marg` — the AHRS stand-in for the Ellipse2-N: a 9-axis
  explicit complementary filter (Mahony et al. 2008, the paper's ref. [6]):
  tilt corrected by the accelerometer, heading by the magnetometer (its
  correction projected on the vertical), PI gains, vectorised over trials.
  The angle is read as the paper does: the orientation relative to θ = 0 in
  axis-angle form, projected on v (:func:`angle_from_orientation`).
* :class:`MagneticDisturbance` / :func:`simulate_magnetometer` — Earth field
  (Shanghai: ~48 µT, inclination ~47°) whose heading wanders as a
  Gauss–Markov process per trial (the "frequent changes in the magnetic field"
  of Sec. 7).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mtcal.core import rotations
from mtcal.core.validate import as_float_array, positive_scalar
from mtcal.filters._kernels_common import check_engine, use_parallel

__all__ = ["accel_only_angle", "MagneticDisturbance", "simulate_magnetometer", "mahony_marg",
           "MargGains", "angle_from_orientation", "triad_quaternion"]

from mtcal.core.units import DEG


def accel_only_angle(accel_m_s2, axis, accel0_m_s2) -> np.ndarray:
    """Ref. [16] angle from the static acceleration alone (rad), shape (..., N).

    Parameters
    ----------
    accel_m_s2 : array_like, shape (..., N, 3)
        Accelerometer samples (m/s²).
    axis : array_like, shape (3,) or (..., 3)
        Unit rotation axis v (per trial).
    accel0_m_s2 : array_like, shape (3,) or (..., 3)
        ā0 at θ = 0 (per trial).

    Notes
    -----
    With ``a = R(θ, v)ᵀ ā0 = (vvᵀ)ā0 + cosθ ā0⊥ − sinθ (v × ā0)``:
    ``a⊥·ā0⊥ = ‖ā0⊥‖² cosθ`` and ``vᵀ(a × ā0) = ‖ā0⊥‖² sinθ``.
    """
    a = as_float_array(accel_m_s2, "accel_m_s2", last_dim=3)
    v = as_float_array(axis, "axis", last_dim=3)
    a0 = as_float_array(accel0_m_s2, "accel0_m_s2", last_dim=3)
    if np.any(np.abs(np.linalg.norm(v, axis=-1) - 1.0) > 1e-6):
        raise ValueError("axis must be a unit vector")
    v = v[..., None, :]
    a0 = a0[..., None, :]
    a0p = a0 - v * np.sum(v * a0, axis=-1, keepdims=True)
    if np.min(np.linalg.norm(a0p, axis=-1)) < 1e-3 * np.max(np.linalg.norm(a0, axis=-1)):
        raise ValueError("axis is parallel to gravity: the accelerometer cannot see the rotation")
    num = np.sum(v * np.cross(a, a0), axis=-1)
    den = np.sum(a * a0p, axis=-1)
    return np.arctan2(num, den)


@dataclass(frozen=True)
class MagneticDisturbance:
    """Earth magnetic field with a wandering heading (mtcal choices).

    Parameters
    ----------
    field_uT : float
        Magnitude (µT); 48 µT ≈ Shanghai (WMM).
    inclination_deg : float
        Dip angle below the horizon (deg); 47° ≈ Shanghai.
    heading_sigma_deg : float
        1σ of the Gauss–Markov heading disturbance (deg): steel structures
        and moving equipment around an aircraft in a test hall.
    heading_tau_s : float
        Correlation time (s).
    """

    field_uT: float = 48.0
    inclination_deg: float = 47.0
    heading_sigma_deg: float = 5.0
    heading_tau_s: float = 20.0

    def heading_rad(self, n: int, dt_s: float, trials: int, rng: np.random.Generator) -> np.ndarray:
        """Disturbance heading ψ_d (T, N) in rad, stationary first-order Gauss–Markov."""
        a = np.exp(-dt_s / self.heading_tau_s)
        w = rng.standard_normal((trials, n))
        w[:, 0] /= np.sqrt(1.0 - a * a)
        return _lfilter([np.sqrt(1.0 - a * a) * self.heading_sigma_deg * DEG], [1.0, -a], w, axis=1)

    def field_world(self, heading_rad) -> np.ndarray:
        """World field (…, 3) in µT for a heading ψ (z-up world, north = +x at ψ = 0)."""
        inc = self.inclination_deg * DEG
        h = np.asarray(heading_rad, float)
        return self.field_uT * np.stack([np.cos(inc) * np.cos(h), np.cos(inc) * np.sin(h),
                                         -np.sin(inc) * np.ones_like(h)], axis=-1)


def simulate_magnetometer(theta_rad, axis, q_wb0, disturbance: MagneticDisturbance, dt_s: float,
                          rng: np.random.Generator, noise_fraction: float = 0.005) -> np.ndarray:
    """Magnetometer (µT, IMU frame) along a fixed-axis rotation, shape (T, N, 3).

    ``m_s = R(θ, v)ᵀ C_wb0ᵀ m_w(ψ_d(t)) + noise`` with white noise of
    ``noise_fraction × field`` per component.
    """
    th = np.atleast_2d(as_float_array(theta_rad, "theta_rad", ndim=(1, 2)))
    v = as_float_array(axis, "axis", ndim=1, last_dim=3)
    t_n, n = th.shape
    r_heading, r_noise = rng.spawn(2)
    mw = disturbance.field_world(disturbance.heading_rad(n, dt_s, t_n, r_heading))
    x = mw @ rotations.quat_to_matrix(np.asarray(q_wb0, float))  # C_wb0ᵀ m_w (row form)
    par = v * (x @ v)[..., None]
    perp = x - par
    m = par + np.cos(th)[..., None] * perp - np.sin(th)[..., None] * np.cross(v, x)
    m += noise_fraction * disturbance.field_uT * r_noise.standard_normal(m.shape)
    return m


def triad_quaternion(accel_m_s2, mag) -> np.ndarray:
    """Body→earth quaternion (scalar-first) from one accel and mag reading, (..., 3) → (..., 4).

    Earth frame: z up (along the static specific force), x magnetic north.
    """
    return _triad(as_float_array(accel_m_s2, "accel_m_s2", last_dim=3), as_float_array(mag, "mag", last_dim=3))


def _triad(a: np.ndarray, m: np.ndarray) -> np.ndarray:
    """:func:`triad_quaternion` of checked (finite float64 (..., 3)) accelerometer and magnetometer readings."""
    ez = a / np.linalg.norm(a, axis=-1, keepdims=True)
    ey = np.cross(ez, m)
    ey /= np.linalg.norm(ey, axis=-1, keepdims=True)
    ex = np.cross(ey, ez)
    c = np.stack([ex, ey, ez], axis=-2)  # rows: earth axes in body coords → body→earth matrix
    return rotations.quat_from_matrix(c)


@dataclass(frozen=True)
class MargGains:
    """PI gains of the explicit complementary filter (rad/s per unit error; mtcal choices)."""

    kp_accel: float = 0.5
    kp_mag: float = 0.5
    ki: float = 0.005


def _quat_matrix(q: np.ndarray) -> np.ndarray:
    """Body→earth DCM of scalar-first quaternions (T, 4) → (T, 3, 3), no checks (loop use)."""
    w, x, y, z = q[:, 0], q[:, 1], q[:, 2], q[:, 3]
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], -2)


def mahony_marg(gyro_rad_s, accel_m_s2, mag, dt_s: float, gains: MargGains | None = None,
                q0=None, *, engine: str = "numba") -> np.ndarray:
    """9-axis explicit complementary filter (Mahony 2008), vectorised over trials.

    Parameters
    ----------
    gyro_rad_s, accel_m_s2, mag : array_like, shape (T, N, 3)
        Gyro (rad/s), accelerometer (m/s²), magnetometer (any unit).
    dt_s : float
        Sample interval (s).
    gains : MargGains
    q0 : array_like (T, 4), optional
        Initial body→earth quaternion; TRIAD from the mean of the first 20
        samples otherwise (start the record at rest).
    engine : {"numba", "numpy"}
        Compiled kernel (default; trials in parallel over numba's threads,
        :mod:`mtcal.filters._kernels_marg`) or the numpy reference loop below
        (they agree to rounding, ≤ 1e-12 rad).

    Returns
    -------
    ndarray (T, N, 4)
        Body→earth quaternions (scalar-first).
    """
    g = as_float_array(gyro_rad_s, "gyro_rad_s", ndim=3, last_dim=3)
    a = as_float_array(accel_m_s2, "accel_m_s2", ndim=3, last_dim=3)
    m = as_float_array(mag, "mag", ndim=3, last_dim=3)
    if not g.shape == a.shape == m.shape:
        raise ValueError(f"gyro, accel and mag must share a shape, got {g.shape}, {a.shape}, {m.shape}")
    dt = positive_scalar(dt_s, "dt_s")
    k = MargGains() if gains is None else gains
    t_n, n = g.shape[:2]
    if q0 is None:
        q = _triad(a[:, :20].mean(axis=1), m[:, :20].mean(axis=1))
    else:
        q = np.broadcast_to(rotations.quat_normalize(as_float_array(q0, "q0", last_dim=4)), (t_n, 4)).copy()
    an = a / np.linalg.norm(a, axis=-1, keepdims=True)
    mn = m / np.linalg.norm(m, axis=-1, keepdims=True)
    if check_engine(engine) == "numba":
        from mtcal.filters import _kernels_marg

        out = np.empty((t_n, n, 4))
        fn = _kernels_marg.marg_parallel if use_parallel(t_n, n) else _kernels_marg.marg_serial
        fn(g, an, mn, np.ascontiguousarray(q, dtype=float), out, float(k.kp_accel), float(k.kp_mag),
           float(k.ki * dt), float(dt))
        return out
    integ = np.zeros((t_n, 3))
    out = np.empty((t_n, n, 4))
    for i in range(n):
        out[:, i] = q  # attitude at t_i; gyro sample i then carries it to t_{i+1}
        c = _quat_matrix(q)
        up_b = c[:, 2, :]                                  # earth z in body coords
        e_acc = np.cross(an[:, i], up_b)
        h = np.einsum("tij,tj->ti", c, mn[:, i])           # field in earth frame
        b = np.stack([np.hypot(h[:, 0], h[:, 1]), np.zeros(t_n), h[:, 2]], -1)
        m_pred = np.einsum("tji,tj->ti", c, b)
        e_mag = np.cross(mn[:, i], m_pred)
        e_mag = up_b * np.sum(e_mag * up_b, axis=1, keepdims=True)  # heading only
        err = k.kp_accel * e_acc + k.kp_mag * e_mag
        integ += k.ki * dt * (e_acc + e_mag)
        q = rotations.hamilton(q, rotations.quat_from_rotvec((g[:, i] + err + integ) * dt))
        q /= np.linalg.norm(q, axis=1, keepdims=True)
    return out


def angle_from_orientation(q_be, axis, ref_index: int) -> np.ndarray:
    """Rotation angle about v of the orientation relative to sample ``ref_index`` (rad), (T, N).

    ``q_rel = q(ref)⁻¹ ⊗ q(t)`` (body frame), angle ``2 atan2(q_rel,vec · v, q_rel,0)`` —
    the axis-angle form of Sec. 7, projected on the known axis.
    """
    q = as_float_array(q_be, "q_be", ndim=3, last_dim=4)
    v = as_float_array(axis, "axis", last_dim=3)
    ref = rotations.quat_conjugate(q[:, ref_index:ref_index + 1])
    rel = rotations.hamilton(np.broadcast_to(ref, q.shape), q)
    v = v[:, None, :] if v.ndim == 2 else v
    return rotations.wrap_angle(2.0 * np.arctan2(np.sum(rel[..., 1:] * v, axis=-1), rel[..., 0]))


def _lfilter(*args, **kwargs):
    """``scipy.signal.lfilter``, imported on first use (scipy.signal costs ~0.5-1 s of import time)."""
    from scipy.signal import lfilter

    return lfilter(*args, **kwargs)
