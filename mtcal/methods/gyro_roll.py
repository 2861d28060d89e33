"""tan2022 (Tan et al., 2022) — roll from gyros during pitch/roll 2-DOF motion.

Four estimators of the roll angle φ from body rates ``ω = [ω_x, ω_y, ω_z]``:

* :func:`euler_differential` — integrate the Euler-angle rates of Eq 5
  (tracks ψ too); singular at θ = ±90°: ``ψ̇ = (ω_y sinφ + ω_z cosφ)/cosθ``.
  It never raises on the singularity: it returns the spike (or NaN after an
  exact zero of cosθ) the paper shows in Fig 9.
* :func:`roll_decoupled_integration` — Eq 12, ``φ = φ0 + ∫ω_x dt`` (Eq 11
  with ψ̇ = 0): no singularity, drifts with the x-gyro error.
* :func:`roll_projection` — Eq 13, ``φ = arctan(−ω_z / ω_y)``: no memory, error
  Eq 14 ``Δφ = −(Δω_z cosφ + Δω_y sinφ)/θ̇`` — large when θ̇ → 0.
* :func:`roll_hybrid` — Fig 7: projection where the pitch rate exceeds a
  threshold θ̇_t, otherwise integration (Eq 12) from the last roll value.

Motion model and simulator mapping
----------------------------------
The 2-DOF mechanism pitches about body y and rolls about body x with ψ ≡ 0,
so the body attitude is ``C_wb = Ry(θ) Rx(φ)`` = aerospace Z-Y-X with ψ = 0,
and the exact body rates are Eq 11 (plus ``ω_x = φ̇``):
``ω = [φ̇, θ̇ cosφ, −θ̇ sinφ]`` (:func:`body_rates_two_dof`). Mechanism angles may
pass ±90° (uniform rotation); they are not Euler angles then.

For :mod:`mtcal.core.simulate` (world z-up, gravity −z) the body quaternion is
``q_wb = from_euler('ZYX', [ψ, θ, φ])`` (:func:`two_dof_trajectory`). Its static
accelerometer output is then ``C_wbᵀ [0, 0, g] = g [−sinθ, cosθ sinφ, cosθ cosφ]``,
exactly tan2022 Eq 2, and its gyro output is Eq 11. The price of the
mapping: in the simulator's z-up world a positive θ turns the nose *down*
(the paper's navigation frame is effectively z-down with the sign of f
flipped, which is what Eq 2 encodes); nothing in tan2022 depends on it.

Units: rad and rad/s inside; degrees only in notebooks.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from mtcal.core import simulate
from mtcal.core.validate import angle_rad, as_float_array, positive_scalar, time_vector

__all__ = ["MAX_RATE_RAD_S", "body_rates_two_dof", "two_dof_trajectory", "simulate_two_dof_imu",
           "euler_differential", "roll_decoupled_integration", "roll_projection",
           "pitch_rate_magnitude", "roll_hybrid", "roll_estimates", "roll_hybrid_rmse_sweep",
           "projection_hybrid_max_errors", "projection_hybrid_max_errors_noisy", "roll_error_summary",
           "projection_roll_error_eq14",
           "projection_roll_error_exact", "loglog_slope", "warm_up"]

#: Largest accepted body rate (rad/s) = ±2000 °/s, the full scale of common MEMS gyros;
#: larger values are taken as degrees passed as radians.
MAX_RATE_RAD_S = float(np.radians(2000.0))
_MECH_LIMIT_RAD = 4 * np.pi
_KERNEL_MIN_SIZE = 30_000  # array elements from which the compiled kernels beat numpy (numba import aside)


# --------------------------------------------------------------------------
# validation
# --------------------------------------------------------------------------
def _gyro(value, name: str = "gyro_rad_s") -> np.ndarray:
    """Gyro samples (..., N, 3) in rad/s, N ≥ 1, |ω| ≤ 2000 °/s."""
    w = as_float_array(value, name, last_dim=3, copy=False)  # read only here: no copy of long records
    if w.ndim < 2:
        raise ValueError(f"{name} must have shape (N, 3) or (T, N, 3), got {w.shape}")
    if w.shape[-2] == 0:
        raise ValueError(f"{name} must not be empty (zero samples), got shape {w.shape}")
    peak = max(float(w.max()), -float(w.min()))  # max |w| without an |w| temporary
    if peak > MAX_RATE_RAD_S:
        raise ValueError(f"{name} must be in rad/s with |{name}| <= {MAX_RATE_RAD_S:.4g} (2000 deg/s); "
                         f"got {peak:.6g} (degrees passed as radians?)")
    return w


def _rate(value, name: str) -> np.ndarray:
    r = as_float_array(value, name)
    if np.any(np.abs(r) > MAX_RATE_RAD_S):
        raise ValueError(f"{name} must be in rad/s with |{name}| <= {MAX_RATE_RAD_S:.4g} (2000 deg/s); "
                         f"got {np.max(np.abs(r)):.6g} (degrees passed as radians?)")
    return r


def _mech_angle(value, name: str) -> np.ndarray:
    return angle_rad(value, name, limit_rad=_MECH_LIMIT_RAD)


def _euler_pitch(value, name: str = "pitch0") -> np.ndarray:
    theta = angle_rad(value, name)
    if np.any(np.abs(theta) > 0.5 * np.pi + 1e-12):
        raise ValueError(f"{name} must be within [-pi/2, pi/2] rad (an Euler pitch); got "
                         f"{np.max(np.abs(theta)):.6g}")
    return theta


# --------------------------------------------------------------------------
# truth kinematics and simulated data
# --------------------------------------------------------------------------
def body_rates_two_dof(pitch_rate, roll, roll_rate=0.0) -> np.ndarray:
    """Exact body rates of the 2-DOF pitch/roll motion (ψ̇ = 0), Eq 11 (rad/s).

    Parameters
    ----------
    pitch_rate : array_like
        θ̇ in rad/s.
    roll : array_like
        φ in rad.
    roll_rate : array_like
        φ̇ in rad/s.

    Returns
    -------
    ndarray, shape (..., 3)
        ``[φ̇, θ̇ cosφ, −θ̇ sinφ]``.
    """
    dth = _rate(pitch_rate, "pitch_rate")
    phi = _mech_angle(roll, "roll")
    dphi = _rate(roll_rate, "roll_rate")
    dth, phi, dphi = np.broadcast_arrays(dth, phi, dphi)
    return np.stack([dphi, dth * np.cos(phi), -dth * np.sin(phi)], axis=-1)


def two_dof_trajectory(time_s, pitch_rad, roll_rad) -> simulate.Trajectory:
    """:class:`mtcal.core.simulate.Trajectory` of the mechanism (ψ = 0), tan2022 mapping.

    ``q_wb = from_euler('ZYX', [0, θ, φ])`` (scalar-first); see the module
    docstring for why this reproduces Eq 2 and Eq 11 in the z-up simulator.

    Parameters
    ----------
    time_s : array_like (N,)
        Uniform time grid (s).
    pitch_rad, roll_rad : array_like (N,)
        Mechanism pitch and roll (rad; may pass ±90°).
    """
    t = time_vector(time_s)
    theta = np.broadcast_to(_mech_angle(pitch_rad, "pitch_rad"), t.shape)
    phi = np.broadcast_to(_mech_angle(roll_rad, "roll_rad"), t.shape)
    euler = np.stack([np.zeros_like(t), theta, phi], axis=-1)
    q = Rotation.from_euler("ZYX", euler).as_quat(scalar_first=True)
    return simulate.Trajectory(t, q)


def simulate_two_dof_imu(time_s, pitch_rad, roll_rad, *, gyro_bias_rad_s=0.0,
                         gyro_noise_density=0.0, rng: np.random.Generator | None = None,
                         trials: int | None = None) -> simulate.ImuRecord:
    """Simulated IMU on the 2-DOF mechanism via :func:`mtcal.core.simulate.simulate_imu`.

    Parameters
    ----------
    time_s, pitch_rad, roll_rad : array_like (N,)
        As in :func:`two_dof_trajectory`.
    gyro_bias_rad_s : float or 3-tuple
        Constant gyro error per axis (rad/s) — the paper's "gyro output error".
    gyro_noise_density : float
        Gyro white noise (rad/s/√Hz).
    rng : numpy.random.Generator, optional
        Required when ``gyro_noise_density > 0``.
    trials : int, optional
        Monte Carlo trials (leading axis of the outputs).

    Returns
    -------
    mtcal.core.simulate.ImuRecord
        Gyro sample k is the mean rate over ``[t_k, t_{k+1}]``.
    """
    traj = two_dof_trajectory(time_s, pitch_rad, roll_rad)
    bias = as_float_array(gyro_bias_rad_s, "gyro_bias_rad_s")
    gyro = simulate.SensorErrors(bias=tuple(np.broadcast_to(bias, (3,))),
                                 noise_density=positive_scalar(gyro_noise_density, "gyro_noise_density",
                                                               allow_zero=True))
    model = simulate.ImuErrorModel(gyro=gyro)
    return simulate.simulate_imu(traj, model, rng, trials)


# --------------------------------------------------------------------------
# roll estimators
# --------------------------------------------------------------------------
def euler_differential(gyro_rad_s, dt_s: float, *, pitch0=0.0, roll0=0.0, yaw0=0.0,
                       engine: str = "numba") -> np.ndarray:
    """tan2022 Eq 5: integrate the Z-Y-X Euler-angle rates (forward Euler).

    ``ψ̇ = (ω_y sinφ + ω_z cosφ)/cosθ``, ``θ̇ = ω_y cosφ − ω_z sinφ``,
    ``φ̇ = ω_x + ψ̇ sinθ``. Near θ = ±90° the 1/cosθ term makes ψ and φ jump
    (the algorithmic singularity of Fig 9). The function does not raise
    there: ψ and φ are wrapped to [−π, π) after each step (θ is left
    continuous), and samples after an exact cosθ = 0 are NaN.

    Parameters
    ----------
    gyro_rad_s : array_like, shape (N, 3) or (T, N, 3)
        Body rates (rad/s); sample k acts over ``[t_k, t_{k+1}]``.
    dt_s : float
        Sample interval (s).
    pitch0, roll0, yaw0 : float or array_like (T,)
        Initial Euler angles (rad; |pitch0| ≤ π/2).
    engine : {"numba", "numpy"}
        Compiled loop (default, :mod:`mtcal.methods._gyro_roll_kernels`) or the numpy
        reference (a Python loop over time); equal to rounding.

    Returns
    -------
    ndarray, shape (..., N, 3)
        ``[ψ, θ, φ]`` at every sample (rad).

    Examples
    --------
    >>> w = np.tile([0.0, 0.1, 0.0], (100, 1))  # pitch at 0.1 rad/s for 1 s
    >>> float(euler_differential(w, 0.01)[-1, 1].round(6))
    0.099
    """
    w = _gyro(gyro_rad_s)
    dt = positive_scalar(dt_s, "dt_s")
    if engine not in ("numba", "numpy"):
        raise ValueError(f"engine must be one of ('numba', 'numpy'), got {engine!r}")
    lead = w.shape[:-2]
    state = np.empty(lead + (3,))
    state[..., 0] = angle_rad(yaw0, "yaw0")
    state[..., 1] = _euler_pitch(pitch0)
    state[..., 2] = angle_rad(roll0, "roll0")
    if engine == "numba":
        from mtcal.methods import _gyro_roll_kernels  # here: numba is imported only when called

        flat = np.ascontiguousarray(w.reshape((-1,) + w.shape[-2:]))
        return _gyro_roll_kernels.euler_differential(flat, dt, state.reshape(-1, 3)).reshape(w.shape)
    out = np.empty(w.shape)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for k in range(w.shape[-2]):  # recursive: loop over time, vectorised over trials
            out[..., k, :] = state
            wx, wy, wz = w[..., k, 0], w[..., k, 1], w[..., k, 2]
            psi, theta, phi = state[..., 0], state[..., 1], state[..., 2]
            sphi, cphi = np.sin(phi), np.cos(phi)
            dpsi = (wy * sphi + wz * cphi) / np.cos(theta)
            dtheta = wy * cphi - wz * sphi
            dphi = wx + dpsi * np.sin(theta)
            state = np.stack([_wrap(psi + dpsi * dt), theta + dtheta * dt, _wrap(phi + dphi * dt)],
                             axis=-1)
    return out


def _wrap(a: np.ndarray) -> np.ndarray:
    """Wrap to [−π, π) without validation (NaN/inf propagate as NaN)."""
    with np.errstate(invalid="ignore"):
        return (a + np.pi) % (2.0 * np.pi) - np.pi


def roll_decoupled_integration(gyro_rad_s, dt_s: float, *, roll0=0.0) -> np.ndarray:
    """tan2022 Eq 12: ``φ_k = φ0 + Σ_{j<k} ω_x,j Δt`` (rad), shape (..., N).

    Parameters
    ----------
    gyro_rad_s : array_like, shape (N, 3) or (T, N, 3)
        Body rates (rad/s).
    dt_s : float
        Sample interval (s).
    roll0 : float or array_like (T,)
        Initial roll φ0 (rad), e.g. from initial alignment.
    """
    w = _gyro(gyro_rad_s)
    dt = positive_scalar(dt_s, "dt_s")
    phi0 = np.asarray(angle_rad(roll0, "roll0"))[..., None]
    return phi0 + _cumulative_angle(w[..., 0], dt)


def _cumulative_angle(rate: np.ndarray, dt: float) -> np.ndarray:
    """``Φ_k = Σ_{j<k} rate_j dt`` along the last axis (Φ_0 = 0)."""
    cum = np.cumsum(rate * dt, axis=-1)
    return np.concatenate([np.zeros(cum.shape[:-1] + (1,)), cum[..., :-1]], axis=-1)


def roll_projection(gyro_rad_s) -> np.ndarray:
    """tan2022 Eq 13: ``φ = arctan(−ω_z / ω_y)`` (rad, in [−π/2, π/2]), shape (..., N).

    Evaluated as ``atan2(−ω_z sgn ω_y, |ω_y|)``, identical to the arctan of the
    ratio for either sign of θ̇ and defined at ω_y = 0. Meaningless when
    θ̇ → 0 (Eq 15): then it returns the angle of the gyro errors.
    """
    return _projection(_gyro(gyro_rad_s))


def _projection(w: np.ndarray) -> np.ndarray:
    """:func:`roll_projection` of a checked gyro record (finite float64 (..., N, 3), rad/s)."""
    if w.size >= _KERNEL_MIN_SIZE:  # long records: one compiled pass, the same operations
        from mtcal.methods import _gyro_roll_kernels  # here: numba is imported only when called

        flat = np.ascontiguousarray(w.reshape((-1,) + w.shape[-2:]))
        return _gyro_roll_kernels.projection(flat).reshape(w.shape[:-1])
    wy, wz = w[..., 1], w[..., 2]
    sign = np.where(wy < 0.0, -1.0, 1.0)
    return np.arctan2(-wz * sign, np.abs(wy))


def pitch_rate_magnitude(gyro_rad_s) -> np.ndarray:
    """``|θ̇| = √(ω_y² + ω_z²)`` (rad/s), exact for ψ̇ = 0 by Eq 11 and independent of φ."""
    return _pitch_rate(_gyro(gyro_rad_s))


def _pitch_rate(w: np.ndarray) -> np.ndarray:
    """:func:`pitch_rate_magnitude` of a checked gyro record (finite float64 (..., N, 3), rad/s)."""
    return np.hypot(w[..., 1], w[..., 2])


def roll_hybrid(gyro_rad_s, dt_s: float, threshold_rad_s: float, *,
                roll0=0.0) -> tuple[np.ndarray, np.ndarray]:
    """tan2022 Fig 7: projection (Eq 13) if |θ̇| > θ̇_t, else integration (Eq 12).

    The pitch rate is taken from the gyros, ``|θ̇| = √(ω_y² + ω_z²)``. During an
    integration stretch, roll starts from the last projection value (or φ0
    before the first one) and adds ``∫ω_x dt``. Vectorised (no time loop):
    ``φ_k = φ_P(j) + Φ_k − Φ_j`` with j the last projection sample ≤ k.

    Parameters
    ----------
    gyro_rad_s : array_like, shape (N, 3) or (T, N, 3)
        Body rates (rad/s).
    dt_s : float
        Sample interval (s).
    threshold_rad_s : float
        θ̇_t (rad/s, ≥ 0); the paper uses 0.5 °/s.
    roll0 : float or array_like (T,)
        Initial roll (rad).

    Returns
    -------
    roll_rad : ndarray, shape (..., N)
    uses_projection : ndarray of bool, shape (..., N)
    """
    _, _, hybrid, use = roll_estimates(gyro_rad_s, dt_s, threshold_rad_s, roll0=roll0)
    return hybrid, use


def roll_estimates(gyro_rad_s, dt_s: float, threshold_rad_s: float, *,
                   roll0=0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The three roll estimates of tan2022 from one pass over the parts they share (rad), shape (..., N) each.

    Projection (Eq 13, :func:`roll_projection`), integration (Eq 12,
    :func:`roll_decoupled_integration`) and the Fig 7 hybrid (:func:`roll_hybrid`, which
    is built from the other two), with the hybrid's switch: the same numbers as the three
    functions called one by one, the projection and the integrated x rate computed once.

    Parameters
    ----------
    gyro_rad_s, dt_s, threshold_rad_s, roll0
        As :func:`roll_hybrid`.

    Returns
    -------
    projection_rad, integration_rad, hybrid_rad : ndarray, shape (..., N)
    uses_projection : ndarray of bool, shape (..., N)

    Examples
    --------
    >>> w = np.tile([0.01, 0.2, 0.0], (50, 1))
    >>> p, i, h, use = roll_estimates(w, 0.01, 0.1)
    >>> bool(np.array_equal(h, roll_hybrid(w, 0.01, 0.1)[0]))
    True
    >>> bool(np.array_equal(i, roll_decoupled_integration(w, 0.01)) and np.array_equal(p, roll_projection(w)))
    True
    """
    w = _gyro(gyro_rad_s)
    dt = positive_scalar(dt_s, "dt_s")
    thr = positive_scalar(threshold_rad_s, "threshold_rad_s", allow_zero=True)
    if thr > MAX_RATE_RAD_S:
        raise ValueError(f"threshold_rad_s must be in rad/s (<= {MAX_RATE_RAD_S:.4g}); got {thr:.6g} "
                         "(degrees passed as radians?)")
    phi0 = np.asarray(angle_rad(roll0, "roll0"))[..., None]
    if w.size >= _KERNEL_MIN_SIZE:  # long records: one compiled pass, the same operations
        from mtcal.methods import _gyro_roll_kernels  # here: numba is imported only when called

        lead, n = w.shape[:-2], w.shape[-2]
        flat = np.ascontiguousarray(w.reshape((-1,) + w.shape[-2:]))
        m = flat.shape[0]
        p0 = np.array(np.broadcast_to(phi0[..., 0], lead), dtype=float).ravel()  # writeable: one kernel signature
        out = _gyro_roll_kernels.roll_estimates(flat, dt, thr, p0, np.empty((m, n)), np.empty((m, n)),
                                                np.empty((m, n)), np.empty((m, n), dtype=bool))
        return tuple(a.reshape(lead + (n,)) for a in out)
    proj = _projection(w)
    use = _pitch_rate(w) > thr
    cum = _cumulative_angle(w[..., 0], dt)
    return proj, phi0 + cum, _hybrid_from_parts(proj, cum, use, phi0), use


def _hybrid_from_parts(proj: np.ndarray, cum: np.ndarray, use: np.ndarray, phi0: np.ndarray) -> np.ndarray:
    """Fig 7 combination: projection where ``use``, else last projection value + integrated x rate."""
    idx = np.arange(proj.shape[-1])
    last = np.maximum.accumulate(np.where(use, idx, -1), axis=-1)
    has = last >= 0
    safe = np.where(has, last, 0)
    base = np.where(has, np.take_along_axis(proj - cum, safe, axis=-1), phi0)
    return np.where(use, proj, base + cum)


def roll_hybrid_rmse_sweep(gyro_rad_s, dt_s: float, thresholds_rad_s, *, roll_true=0.0, roll0=0.0,
                           engine: str = "numba") -> np.ndarray:
    """Roll RMSE of :func:`roll_hybrid` for many thresholds θ̇_t, sharing the per-sample work (rad).

    Parameters
    ----------
    gyro_rad_s : array_like, shape (N, 3) or (T, N, 3)
        Body rates (rad/s).
    dt_s : float
        Sample interval (s).
    thresholds_rad_s : array_like (K,)
        Thresholds θ̇_t (rad/s, ≥ 0).
    roll_true : float or array_like (N,)
        True roll (rad) the errors are taken against.
    roll0 : float or array_like (T,)
        Initial roll (rad).
    engine : {"numba", "numpy"}
        Compiled sweep (default: one pass per trial, all thresholds together, no temporaries) or the
        numpy reference; equal to rounding (the sums run in another order).

    Returns
    -------
    ndarray, shape (..., K)
        RMSE over the samples for each threshold.

    Examples
    --------
    >>> t = np.arange(0.0, 2.0, 0.01)
    >>> w = np.stack([np.zeros_like(t), np.cos(np.pi * t), np.zeros_like(t)], -1)
    >>> rmse = roll_hybrid_rmse_sweep(w, 0.01, [0.1, 1.0])
    >>> bool(np.allclose(rmse, 0.0))
    True
    """
    w = _gyro(gyro_rad_s)
    dt = positive_scalar(dt_s, "dt_s")
    thr = as_float_array(thresholds_rad_s, "thresholds_rad_s", ndim=1)
    if np.any(thr < 0) or np.any(thr > MAX_RATE_RAD_S):
        raise ValueError(f"thresholds_rad_s must be in rad/s within [0, {MAX_RATE_RAD_S:.4g}]")
    if engine not in ("numba", "numpy"):
        raise ValueError(f"engine must be one of ('numba', 'numpy'), got {engine!r}")
    phi0 = np.asarray(angle_rad(roll0, "roll0"))[..., None]
    truth = np.asarray(angle_rad(roll_true, "roll_true"))
    if engine == "numba":  # projection, rate and integrated x angle sample by sample (no (T, N) arrays)
        from mtcal.methods import _gyro_roll_kernels  # here: numba is imported only when called

        lead, n = w.shape[:-2], w.shape[-2]
        order = np.argsort(thr, kind="stable")  # the kernel takes ascending thresholds
        out = np.empty((int(np.prod(lead, dtype=int)), thr.size))
        out[:, order] = _gyro_roll_kernels.hybrid_rmse_sweep(
            np.ascontiguousarray(w.reshape((-1,) + w.shape[-2:])), dt,
            np.array(np.broadcast_to(phi0[..., 0], lead), dtype=float).ravel(),  # writeable: one kernel signature
            np.array(np.broadcast_to(truth, (n,)), dtype=float), np.ascontiguousarray(thr[order]))
        return out.reshape(lead + (thr.size,))
    proj, rate, cum = _projection(w), _pitch_rate(w), _cumulative_angle(w[..., 0], dt)
    out = np.empty(w.shape[:-2] + (thr.size,))
    for k, th in enumerate(thr):  # loop over thresholds; samples and trials vectorised
        err = _hybrid_from_parts(proj, cum, rate > th, phi0) - truth
        out[..., k] = np.sqrt(np.mean(err**2, axis=-1))
    return out


def roll_error_summary(gyro_rad_s, dt_s: float, masks, *, pitch0=0.0, roll0=0.0
                       ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per trial, the three gyro roll estimators' errors against the constant true roll ``roll0``, in one pass.

    Bit-identical to the estimators' outputs reduced afterwards (compiled: no (T, N, 3) Euler
    output, no repeated validation):

    * ``euler_max[j] = max(|angle_difference(euler_differential(w, dt, pitch0=pitch0, roll0=roll0)[..., 2],
      roll0)|[..., masks[j]])`` (Eq 5; NaN propagates as in ``np.max``);
    * ``integration_final = roll_decoupled_integration(w, dt, roll0=roll0)[..., -1] − roll0`` (Eq 12);
    * ``projection_abs = |roll_projection(w) − roll0|`` (Eq 13, per sample).

    Parameters
    ----------
    gyro_rad_s : array_like, shape (N, 3) or (T, N, 3)
        Body rates (rad/s).
    dt_s : float
        Sample interval (s).
    masks : array_like of bool, shape (K, N)
        Sample sets of the Eq 5 maxima (each non-empty).
    pitch0 : float
        Initial Euler pitch (rad, |pitch0| ≤ π/2) of Eq 5.
    roll0 : float
        Initial and true roll (rad).

    Returns
    -------
    euler_max : ndarray, shape (K, ...) (rad)
    integration_final : ndarray, shape (...) (rad)
    projection_abs : ndarray, shape (..., N) (rad)

    Examples
    --------
    >>> w = np.tile([1e-3, 0.5, 0.0], (400, 1))  # pitch at 0.5 rad/s with an x-gyro error
    >>> masks = np.ones((1, 400), dtype=bool)
    >>> e_max, final, p_abs = roll_error_summary(w, 0.01, masks)
    >>> from mtcal.core.metrics import angle_difference
    >>> e = angle_difference(euler_differential(w, 0.01)[..., 2], 0.0)
    >>> bool(e_max[0] == np.max(np.abs(e)) and final == roll_decoupled_integration(w, 0.01)[-1])
    True
    """
    from mtcal.methods import _gyro_roll_kernels  # here: numba is imported only when called

    w = _gyro(gyro_rad_s)
    dt = positive_scalar(dt_s, "dt_s")
    mk = np.asarray(masks)
    if mk.dtype != bool or mk.ndim != 2 or mk.shape[1] != w.shape[-2] or not np.all(np.any(mk, axis=1)):
        raise ValueError(f"masks must be a boolean array of shape (K, {w.shape[-2]}) with every row selecting a "
                         f"sample, got {mk.dtype} {mk.shape}")
    theta0 = float(_euler_pitch(pitch0))
    phi0 = float(angle_rad(roll0, "roll0"))
    lead = w.shape[:-2]
    flat = np.ascontiguousarray(w.reshape((-1,) + w.shape[-2:]))
    state = np.zeros((flat.shape[0], 3))
    state[:, 1], state[:, 2] = theta0, phi0
    proj_abs = np.empty(flat.shape[:2])
    e_max, final = _gyro_roll_kernels.roll_error_summary(flat, dt, state, np.ascontiguousarray(mk), phi0, proj_abs)
    return e_max.reshape((mk.shape[0],) + lead), final.reshape(lead), proj_abs.reshape(w.shape[:-1])


# --------------------------------------------------------------------------
# error models
# --------------------------------------------------------------------------
def projection_roll_error_eq14(roll, pitch_rate, gyro_error_y, gyro_error_z) -> np.ndarray:
    """tan2022 Eq 14: first-order projection error ``−(Δω_z cosφ + Δω_y sinφ)/θ̇`` (rad).

    Parameters
    ----------
    roll : array_like
        True φ (rad).
    pitch_rate : array_like
        θ̇ (rad/s, non-zero).
    gyro_error_y, gyro_error_z : array_like
        Errors of the y and z gyros (rad/s).
    """
    phi = _mech_angle(roll, "roll")
    dth = _rate(pitch_rate, "pitch_rate")
    if np.any(dth == 0.0):
        raise ValueError("pitch_rate must be non-zero (Eq 14 diverges at 0; see Eq 15)")
    dy = _rate(gyro_error_y, "gyro_error_y")
    dz = _rate(gyro_error_z, "gyro_error_z")
    return -(dz * np.cos(phi) + dy * np.sin(phi)) / dth


def projection_roll_error_exact(roll, pitch_rate, gyro_error_y, gyro_error_z) -> np.ndarray:
    """Exact Eq 13 error with constant gyro errors: ``arctan(−(ω_z+Δω_z)/(ω_y+Δω_y)) − φ`` (rad).

    Uses the true rates of Eq 11; wrapped to [−π/2, π/2) (Eq 13 is defined mod π).
    """
    phi = _mech_angle(roll, "roll")
    dth = _rate(pitch_rate, "pitch_rate")
    dy = _rate(gyro_error_y, "gyro_error_y")
    dz = _rate(gyro_error_z, "gyro_error_z")
    wy = dth * np.cos(phi) + dy
    wz = -dth * np.sin(phi) + dz
    sign = np.where(wy < 0.0, -1.0, 1.0)
    err = np.arctan2(-wz * sign, np.abs(wy)) - phi
    return (err + 0.5 * np.pi) % np.pi - 0.5 * np.pi


def loglog_slope(x, y) -> float | np.ndarray:
    """Least-squares slope of ``log|y|`` against ``log x`` (power-law exponent).

    Parameters
    ----------
    x : array_like (K,)
        Positive abscissae (e.g. pitch rates).
    y : array_like (K,) or (T, K)
        Non-zero ordinates (e.g. roll errors); a 2-D array fits one slope per
        row (e.g. per Monte Carlo trial).

    Returns
    -------
    float, or ndarray (T,) for 2-D ``y``
    """
    xx = as_float_array(x, "x", ndim=1)
    yy = as_float_array(y, "y", ndim=(1, 2))
    if xx.size < 2 or yy.shape[-1] != xx.size:
        raise ValueError(f"x must be 1-D of length >= 2 and y's last axis must match it, got {xx.shape} and "
                         f"{yy.shape}")
    if np.any(xx <= 0) or np.any(yy == 0):
        raise ValueError("x must be positive and y non-zero for a log-log fit")
    slope = np.polyfit(np.log(xx), np.log(np.abs(yy)).T, 1)[0]
    return float(slope) if yy.ndim == 1 else slope


def projection_hybrid_max_errors(gyro_rad_s, dt_s: float, threshold_rad_s: float, slow, *, roll0=0.0,
                                 stop_above_rad: float = np.inf) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per trial: projection spike ratio and hybrid max |roll error| at constant true roll ``roll0`` (one pass).

    The spike ratio is max |Eq 13 error| over the samples where ``slow`` over the max
    elsewhere (tan2022 Fig 11); the hybrid max is max |Fig 7 hybrid error| (Fig 12), both
    against the constant true roll ``roll0``. Compiled (no (T, N) temporaries).

    Parameters
    ----------
    gyro_rad_s : array_like, shape (N, 3) or (T, N, 3)
        Body rates (rad/s).
    dt_s : float
        Sample interval (s).
    threshold_rad_s : float
        Hybrid switch θ̇_t (rad/s, ≥ 0).
    slow : array_like of bool (N,)
        Samples counted as "θ̇ → 0" for the spike ratio.
    roll0 : float
        Initial and true roll (rad).
    stop_above_rad : float
        A trial stops as soon as its hybrid error exceeds this (rad): its spike ratio is
        then NaN and ``complete`` False (for a test of "spikes and accurate" that is
        already decided). Default ``inf``: full records.

    Returns
    -------
    spike : ndarray, shape (T,) (0-d for one (N, 3) record)
    hybrid_max_rad : ndarray, shape (T,) (rad)
    complete : ndarray of bool, shape (T,)

    Examples
    --------
    >>> t = np.arange(0.0, 2.0, 0.001)
    >>> w = np.stack([np.zeros_like(t), np.cos(np.pi * t), np.full_like(t, 1e-3)], -1)
    >>> spike, hyb, ok = projection_hybrid_max_errors(w, 0.001, 0.01, np.abs(np.cos(np.pi * t)) < 0.1)
    >>> bool(spike > 5), bool(ok)
    (True, True)
    """
    from mtcal.methods import _gyro_roll_kernels  # here: numba is imported only when called

    w = _gyro(gyro_rad_s)
    dt, thr, mask, stop, phi0 = _claims_settings(w.shape[-2], dt_s, threshold_rad_s, slow, stop_above_rad, roll0)
    lead = w.shape[:-2]
    flat = np.ascontiguousarray(w.reshape((-1,) + w.shape[-2:]))
    spike, hyb, ok = _gyro_roll_kernels.oscillation_claims(flat, dt, thr, phi0, mask, stop)
    return spike.reshape(lead), hyb.reshape(lead), ok.reshape(lead)


def _claims_settings(n: int, dt_s, threshold_rad_s, slow, stop_above_rad, roll0):
    """Checked ``dt, threshold, slow mask, stop, roll0`` of :func:`projection_hybrid_max_errors` for N = ``n``."""
    dt = positive_scalar(dt_s, "dt_s")
    thr = positive_scalar(threshold_rad_s, "threshold_rad_s", allow_zero=True)
    mask = np.asarray(slow)
    if mask.dtype != bool or mask.shape != (n,):
        raise ValueError(f"slow must be a boolean array of shape ({n},), got {mask.dtype} {mask.shape}")
    stop = float(stop_above_rad)
    if not stop > 0:
        raise ValueError(f"stop_above_rad must be > 0, got {stop_above_rad}")
    return dt, thr, np.ascontiguousarray(mask), stop, float(angle_rad(roll0, "roll0"))


def projection_hybrid_max_errors_noisy(base_rad_s, noise_scale_rad_s, normals, dt_s: float, threshold_rad_s: float,
                                       slow, *, offset_rad_s=None, roll0=0.0, stop_above_rad: float = np.inf
                                       ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`projection_hybrid_max_errors` of ``w = (base + offset) + scale · normals``, built sample by sample.

    Bit-identical to ``projection_hybrid_max_errors(base + scale[:, None, None] * normals, ...)`` (or
    ``(base + offset[:, None, None]) + scale[:, None, None] * normals`` with ``offset_rad_s``) without
    the (T, N, 3) gyro record: a deterministic record plus per-trial white noise (and constant error).

    Parameters
    ----------
    base_rad_s : array_like, shape (N, 3)
        Deterministic body rates (rad/s).
    noise_scale_rad_s : float or array_like (T,)
        Per-trial noise standard deviation per sample (rad/s, ≥ 0).
    normals : ndarray, shape (T, N, 3)
        Standard normal draws.
    dt_s, threshold_rad_s, slow, roll0, stop_above_rad
        As in :func:`projection_hybrid_max_errors`.
    offset_rad_s : float or array_like (T,), optional
        Per-trial constant error added to every axis before the noise (rad/s).

    Returns
    -------
    spike, hybrid_max_rad, complete : ndarray, shape (T,)

    Examples
    --------
    >>> t = np.arange(0.0, 2.0, 0.001)
    >>> base = np.stack([np.zeros_like(t), np.cos(np.pi * t), np.full_like(t, 1e-3)], -1)
    >>> z = np.random.default_rng(0).standard_normal((2, t.size, 3))
    >>> slow = np.abs(np.cos(np.pi * t)) < 0.1
    >>> got = projection_hybrid_max_errors_noisy(base, 1e-4, z, 0.001, 0.01, slow)
    >>> ref = projection_hybrid_max_errors(base + 1e-4 * z, 0.001, 0.01, slow)
    >>> all(np.array_equal(a, b) for a, b in zip(got, ref))
    True
    """
    from mtcal.methods import _gyro_roll_kernels  # here: numba is imported only when called

    base = np.ascontiguousarray(_gyro(base_rad_s, "base_rad_s"))
    if base.ndim != 2:
        raise ValueError(f"base_rad_s must have shape (N, 3), got {base.shape}")
    z = np.asarray(normals)
    if z.dtype != np.float64 or z.ndim != 3 or z.shape[1:] != base.shape:
        raise ValueError(f"normals must be a float64 array of shape (T, {base.shape[0]}, 3), got {z.dtype} {z.shape}")
    scale = np.array(np.broadcast_to(as_float_array(noise_scale_rad_s, "noise_scale_rad_s"), (z.shape[0],)))
    if np.any(scale < 0) or np.any(scale > MAX_RATE_RAD_S):
        raise ValueError(f"noise_scale_rad_s must be in rad/s within [0, {MAX_RATE_RAD_S:.4g}]")
    offset = np.empty(0) if offset_rad_s is None else np.array(  # writeable copies: one kernel signature
        np.broadcast_to(_rate(offset_rad_s, "offset_rad_s"), (z.shape[0],)))
    dt, thr, mask, stop, phi0 = _claims_settings(base.shape[0], dt_s, threshold_rad_s, slow, stop_above_rad, roll0)
    return _gyro_roll_kernels.oscillation_claims_noisy(base, offset, scale, np.ascontiguousarray(z), dt, thr, phi0,
                                                       mask, stop)


def warm_up() -> None:
    """Compile (or load from numba's cache) every compiled kernel of this module, on tiny inputs.

    For ``make venv`` (:func:`mtcal.filters.kernels.warm_up_all`), so that notebook 21 does not pay
    the compile time on a fresh clone.

    Examples
    --------
    >>> warm_up()
    """
    from mtcal.methods import _gyro_roll_kernels as k

    w = np.zeros((1, 4, 3))
    w[..., 1] = 0.1
    first, line, one = np.zeros((1, 3)), np.zeros(4), np.zeros(1)
    k.euler_differential(w, 0.01, first)
    k.projection(w)
    k.oscillation_claims(w, 0.01, 0.0, 0.0, np.zeros(4, dtype=bool), np.inf)
    k.oscillation_claims_noisy(w[0], one, one, w, 0.01, 0.0, 0.0, np.zeros(4, dtype=bool), np.inf)
    k.roll_estimates(w, 0.01, 0.0, one, np.empty((1, 4)), np.empty((1, 4)), np.empty((1, 4)),
                     np.empty((1, 4), dtype=bool))
    k.hybrid_rmse_sweep(w, 0.01, one, line, np.array([0.0, 1.0]))
    k.roll_error_summary(w, 0.01, first, np.ones((1, 4), dtype=bool), 0.0, np.empty((1, 4)))
