"""IMU simulator: exact truth kinematics plus a MEMS sensor error model.

Hardware is replaced by simulation with known truth (REPRODUCTION.md §1). A
:class:`Trajectory` holds the body attitude history ``q_wb`` (scalar-first,
body → world) and the linear acceleration of the sensor point; a
:class:`ImuErrorModel` holds the sensor errors; :func:`simulate_imu` draws one
or many Monte Carlo trials from a seeded ``numpy.random.Generator``.

Truth kinematics
----------------
The world frame is z-up with gravity ``g_w = [0, 0, −9.80665] m/s²`` by
default, so a level accelerometer at rest reads ``[0, 0, +g]``.

* Gyro (body-frame rate, rad/s). Sample ``k`` is the *mean rate over the
  interval* ``[t_k, t_{k+1}]``: ``ω_k = rotvec(q_k⁻¹ ⊗ q_{k+1}) / Δt_k`` — what
  an integrating (angular-increment) gyro reports. Integrating it with seed 000
  Eq 6–7 (``q_{k+1} = q_k ⊗ q(ω_k Δt)``) reproduces the attitude to rounding
  error. The last sample repeats the last interval.
* Accelerometer (specific force, m/s²): ``f_b = C_wbᵀ (a_w − g_w)`` at each
  sample.

Sensor error model (per axis, per sensor; units of the sensor)
--------------------------------------------------------------
``y = (I + S + M) x_true + b_const + b_turn_on + b_warm-up(t) + b_RW(t)
+ b_GM(t) + n_white + vibration``, then quantised; with

* ``S`` diagonal scale-factor error, ``M`` misalignment (off-diagonal);
* ``b_turn_on ~ N(0, bias_sigma²)`` once per trial;
* ``b_warm-up(t) = warmup_bias · exp(−(t + t_on)/warmup_tau_s)`` (bias
  settling after power-on; ``t_on`` = time already powered, e.g. 300 s);
* ``b_RW``: random walk with density ``bias_random_walk`` (unit/s/√Hz, i.e.
  the rate random walk K of an Allan plot: σ_A(τ) = K √(τ/3));
* ``b_GM``: first-order Gauss–Markov bias instability, 1σ
  ``bias_instability`` and correlation time ``bias_instability_tau_s``;
* ``n_white``: density ``noise_density`` (unit/√Hz): per-sample standard
  deviation ``noise_density · √fs`` (Allan σ_A(τ) = N/√τ);
* vibration: sinusoid ``amplitude · sin(2π f t + φ)``, φ uniform per trial
  and axis.

Each error source draws from its own child generator (``rng.spawn``), so
switching one source on or off leaves the others' draws unchanged (common
random numbers for error-budget tables).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.signal import lfilter

from mtcal import rotations
from mtcal._validate import (STANDARD_GRAVITY_M_S2, as_float_array, positive_int,
                             positive_scalar, time_vector, unit_quaternion)

__all__ = ["Trajectory", "SensorErrors", "ImuErrorModel", "ImuRecord", "body_rates",
           "specific_force", "simulate_imu", "integrate_gyro", "GRAVITY_W_M_S2"]

#: Default world gravity vector, z-up frame (m/s²).
GRAVITY_W_M_S2 = (0.0, 0.0, -STANDARD_GRAVITY_M_S2)

_SOURCES = ("turn_on", "white", "random_walk", "instability", "vibration")


def _frozen(arr: np.ndarray) -> np.ndarray:
    arr.setflags(write=False)
    return arr


def uniform_dt(time_s: np.ndarray, name: str = "time_s") -> float:
    """Sample interval of a uniformly sampled time vector (relative jitter < 1e-6)."""
    dt = np.diff(time_s)
    mean_dt = float(np.mean(dt))
    if np.max(np.abs(dt - mean_dt)) > 1e-6 * mean_dt:
        raise ValueError(f"{name} must be uniformly sampled (noise density is scaled by "
                         f"the sample rate); got dt in [{dt.min():.6g}, {dt.max():.6g}] s")
    return mean_dt


@dataclass(frozen=True)
class Trajectory:
    """Truth motion of the body carrying the IMU.

    Parameters
    ----------
    time_s : array_like, shape (N,)
        Strictly increasing, uniformly sampled time in s.
    q_wb : array_like, shape (N, 4)
        Scalar-first unit quaternion of the body attitude (body → world).
    accel_w_m_s2 : array_like, shape (N, 3), optional
        Linear acceleration of the sensor point in the world frame (m/s²);
        zero (no translation) by default.
    """

    time_s: np.ndarray
    q_wb: np.ndarray
    accel_w_m_s2: np.ndarray | None = None

    def __post_init__(self) -> None:
        t = time_vector(self.time_s)
        q = unit_quaternion(self.q_wb, "q_wb")
        if q.ndim != 2 or q.shape[0] != t.size:
            raise ValueError(f"q_wb must have shape ({t.size}, 4) to match time_s, got {q.shape}")
        acc = np.zeros((t.size, 3)) if self.accel_w_m_s2 is None else \
            as_float_array(self.accel_w_m_s2, "accel_w_m_s2", ndim=2, last_dim=3)
        if acc.shape[0] != t.size:
            raise ValueError(f"accel_w_m_s2 must have shape ({t.size}, 3), got {acc.shape}")
        uniform_dt(t)
        object.__setattr__(self, "time_s", _frozen(t))
        object.__setattr__(self, "q_wb", _frozen(rotations.make_continuous(q, axis=0)))
        object.__setattr__(self, "accel_w_m_s2", _frozen(acc))

    @property
    def dt_s(self) -> float:
        """Sample interval (s)."""
        return float(self.time_s[1] - self.time_s[0])

    @property
    def fs_hz(self) -> float:
        """Sample rate (Hz)."""
        return 1.0 / uniform_dt(self.time_s)

    def __len__(self) -> int:
        return int(self.time_s.size)


def body_rates(trajectory: Trajectory) -> np.ndarray:
    """Interval-mean body rates ``ω_k = rotvec(q_k⁻¹ ⊗ q_{k+1}) / Δt`` (rad/s), shape (N, 3)."""
    q = trajectory.q_wb
    dq = rotations.quat_multiply(rotations.quat_conjugate(q[:-1]), q[1:])
    omega = rotations.rotvec_from_quat(rotations.quat_normalize(dq)) / np.diff(trajectory.time_s)[:, None]
    return np.concatenate([omega, omega[-1:]], axis=0)


def specific_force(trajectory: Trajectory, gravity_w_m_s2=GRAVITY_W_M_S2) -> np.ndarray:
    """Specific force in the body frame ``f_b = C_wbᵀ (a_w − g_w)`` (m/s²), shape (N, 3)."""
    g = as_float_array(gravity_w_m_s2, "gravity_w_m_s2", ndim=1, last_dim=3)
    c_wb = rotations.quat_to_matrix(trajectory.q_wb)
    return np.einsum("nji,nj->ni", c_wb, trajectory.accel_w_m_s2 - g)


def integrate_gyro(q0, gyro_rad_s, dt_s: float) -> np.ndarray:
    """Seed 000 Eq 6–7 without correction: ``Q_{k+1} = Q_k ⊗ q(ω_k Δt)``.

    Parameters
    ----------
    q0 : array_like, shape (4,) or (T, 4)
        Initial scalar-first unit quaternion(s).
    gyro_rad_s : array_like, shape (N, 3) or (T, N, 3)
        Body rates (rad/s); sample k acts over ``[t_k, t_{k+1}]``.
    dt_s : float
        Sample interval (s).

    Returns
    -------
    ndarray, shape (N, 4) or (T, N, 4)
        Attitude at every sample time (``Q_0 = q0``).
    """
    dt = positive_scalar(dt_s, "dt_s")
    w = as_float_array(gyro_rad_s, "gyro_rad_s", ndim=(2, 3), last_dim=3)
    q = unit_quaternion(q0, "q0")
    inc = rotations.quat_from_rotvec(w * dt)
    out = np.empty(w.shape[:-1] + (4,))
    out[..., 0, :] = q
    for k in range(w.shape[-2] - 1):  # recursive: loop over time, vectorised over trials
        out[..., k + 1, :] = rotations.hamilton(out[..., k, :], inc[..., k, :])
    return out


def _vec3(value, name: str) -> np.ndarray:
    arr = as_float_array(value, name)
    if arr.shape not in ((), (3,)):
        raise ValueError(f"{name} must be a scalar or a 3-vector, got shape {arr.shape}")
    return np.broadcast_to(arr, (3,)).copy()


@dataclass(frozen=True)
class SensorErrors:
    """Error parameters of one sensor triad, in the sensor's unit ``u`` (rad/s or m/s²).

    Parameters
    ----------
    bias : float or 3-tuple
        Constant bias (u).
    bias_sigma : float
        1σ of the turn-on bias drawn once per trial (u).
    noise_density : float
        White-noise density (u/√Hz); gyro: angle random walk in rad/s/√Hz.
    bias_random_walk : float
        Bias random-walk density (u/s/√Hz = u/√s); gyro: rate random walk.
    bias_instability : float
        1σ of the first-order Gauss–Markov bias (u).
    bias_instability_tau_s : float
        Correlation time of that bias (s).
    warmup_bias : float or 3-tuple
        Extra bias at power-on (u), decaying with ``warmup_tau_s``.
    warmup_tau_s : float
        Warm-up settling time constant (s).
    scale_factor : float or 3-tuple
        Scale-factor error (dimensionless, 1e-3 = 1000 ppm).
    misalignment : 3×3 nested tuple
        Off-diagonal misalignment (rad, diagonal ignored).
    quantization : float
        Output resolution (u); 0 for none.
    vibration_amplitude : float or 3-tuple
        Sinusoidal vibration amplitude (u).
    vibration_freq_hz : float
        Vibration frequency (Hz).
    """

    bias: float | tuple = 0.0
    bias_sigma: float = 0.0
    noise_density: float = 0.0
    bias_random_walk: float = 0.0
    bias_instability: float = 0.0
    bias_instability_tau_s: float = 100.0
    warmup_bias: float | tuple = 0.0
    warmup_tau_s: float = 60.0
    scale_factor: float | tuple = 0.0
    misalignment: tuple = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    quantization: float = 0.0
    vibration_amplitude: float | tuple = 0.0
    vibration_freq_hz: float = 0.0

    def __post_init__(self) -> None:
        for name in ("bias_sigma", "noise_density", "bias_random_walk", "bias_instability",
                     "quantization", "vibration_freq_hz"):
            positive_scalar(getattr(self, name), name, allow_zero=True)
        for name in ("bias_instability_tau_s", "warmup_tau_s"):
            positive_scalar(getattr(self, name), name)
        for name in ("bias", "warmup_bias", "scale_factor", "vibration_amplitude"):
            _vec3(getattr(self, name), name)
        mis = as_float_array(self.misalignment, "misalignment")
        if mis.shape != (3, 3):
            raise ValueError(f"misalignment must be 3x3, got shape {mis.shape}")

    def matrix(self) -> np.ndarray:
        """``I + S + M``: scale factor on the diagonal, misalignment off it."""
        mis = np.array(self.misalignment, dtype=float)
        np.fill_diagonal(mis, 0.0)
        return np.eye(3) + np.diag(_vec3(self.scale_factor, "scale_factor")) + mis

    def apply(self, truth: np.ndarray, time_s: np.ndarray, dt_s: float, trials: int,
              rngs: dict, time_since_power_on_s: float) -> np.ndarray:
        """Corrupt a truth signal (N, 3) into ``trials`` measurements (T, N, 3)."""
        n = truth.shape[0]
        out = np.empty((trials, n, 3))
        out[:] = truth @ self.matrix().T
        out += _vec3(self.bias, "bias")
        warm = _vec3(self.warmup_bias, "warmup_bias")
        if np.any(warm):
            out += np.exp(-(time_s + time_since_power_on_s) / self.warmup_tau_s)[:, None] * warm
        if self.bias_sigma:
            out += self.bias_sigma * rngs["turn_on"].standard_normal((trials, 1, 3))
        if self.noise_density:
            out += (self.noise_density / np.sqrt(dt_s)) * rngs["white"].standard_normal((trials, n, 3))
        if self.bias_random_walk:
            steps = rngs["random_walk"].standard_normal((trials, n, 3))
            steps *= self.bias_random_walk * np.sqrt(dt_s)
            out += np.cumsum(steps, axis=1)
        if self.bias_instability:
            out += self._gauss_markov(rngs["instability"], trials, n, dt_s)
        vib = _vec3(self.vibration_amplitude, "vibration_amplitude")
        if np.any(vib) and self.vibration_freq_hz:
            phase = rngs["vibration"].uniform(0.0, 2 * np.pi, (trials, 1, 3))
            out += vib * np.sin(2 * np.pi * self.vibration_freq_hz * time_s[None, :, None] + phase)
        if self.quantization:
            np.round(out / self.quantization, out=out)
            out *= self.quantization
        return out

    def _gauss_markov(self, rng: np.random.Generator, trials: int, n: int, dt_s: float) -> np.ndarray:
        """First-order Gauss–Markov process, stationary from the first sample."""
        a = np.exp(-dt_s / self.bias_instability_tau_s)
        sigma = self.bias_instability
        w = rng.standard_normal((trials, n, 3))
        w[:, 0, :] *= sigma / np.sqrt(1.0 - a * a)  # stationary start: b_0 ~ N(0, σ²)
        w[:, 1:, :] *= sigma
        return lfilter([np.sqrt(1.0 - a * a)], [1.0, -a], w, axis=1)


@dataclass(frozen=True)
class ImuErrorModel:
    """Error model of a whole IMU plus its mounting on the body.

    Parameters
    ----------
    gyro : SensorErrors
        Gyro errors in rad/s units.
    accel : SensorErrors
        Accelerometer errors in m/s² units.
    q_mount : 4-tuple
        Scalar-first quaternion ``q_bs`` of the sensor frame relative to the
        body (``v_b = C(q_bs) v_s``); identity by default.
    time_since_power_on_s : float
        Time the IMU has been on when the record starts (s); 300 s = the
        5-minute warm-up of seed 000.
    """

    gyro: SensorErrors = field(default_factory=SensorErrors)
    accel: SensorErrors = field(default_factory=SensorErrors)
    q_mount: tuple = (1.0, 0.0, 0.0, 0.0)
    time_since_power_on_s: float = 0.0

    def __post_init__(self) -> None:
        for name in ("gyro", "accel"):
            if not isinstance(getattr(self, name), SensorErrors):
                raise TypeError(f"{name} must be a SensorErrors, got {type(getattr(self, name)).__name__}")
        q = unit_quaternion(self.q_mount, "q_mount")
        if q.shape != (4,):
            raise ValueError(f"q_mount must have shape (4,), got {q.shape}")
        positive_scalar(self.time_since_power_on_s, "time_since_power_on_s", allow_zero=True)
        if self.accel.noise_density > 1.0 or np.max(np.abs(_vec3(self.accel.bias, "bias"))) > 5.0:
            raise ValueError("accel errors look too large for m/s² (noise_density > 1 m/s²/√Hz or "
                             "|bias| > 5 m/s²); were they given in the wrong unit?")
        if self.gyro.noise_density > 0.1 or np.max(np.abs(_vec3(self.gyro.bias, "bias"))) > 1.0:
            raise ValueError("gyro errors look too large for rad/s (noise_density > 0.1 rad/s/√Hz or "
                             "|bias| > 1 rad/s); were degrees passed as radians?")


@dataclass(frozen=True)
class ImuRecord:
    """Simulated IMU output. Arrays are (N, 3) for one trial or (T, N, 3) for many.

    Attributes
    ----------
    time_s : ndarray (N,)
    gyro_rad_s : ndarray
        Body rates in the sensor frame (rad/s).
    accel_m_s2 : ndarray
        Specific force in the sensor frame (m/s²).
    q_ws_true : ndarray (N, 4)
        True sensor attitude (sensor → world), scalar-first.
    gyro_true_rad_s, accel_true_m_s2 : ndarray (N, 3)
        Error-free sensor outputs.
    """

    time_s: np.ndarray
    gyro_rad_s: np.ndarray
    accel_m_s2: np.ndarray
    q_ws_true: np.ndarray
    gyro_true_rad_s: np.ndarray
    accel_true_m_s2: np.ndarray


def simulate_imu(trajectory: Trajectory, model: ImuErrorModel | None = None,
                 rng: np.random.Generator | None = None, trials: int | None = None,
                 gravity_w_m_s2=GRAVITY_W_M_S2) -> ImuRecord:
    """Simulate gyro and accelerometer outputs along a trajectory.

    Parameters
    ----------
    trajectory : Trajectory
        Truth body motion.
    model : ImuErrorModel, optional
        Sensor errors and mounting; error-free and identity mounting if None.
    rng : numpy.random.Generator
        Source of every random draw (required when the model has random errors).
    trials : int, optional
        Number of Monte Carlo trials; output arrays get a leading trial axis.
        ``None`` gives a single trial without the leading axis.
    gravity_w_m_s2 : 3-vector
        World gravity (m/s²), default z-up ``[0, 0, −9.80665]``.

    Returns
    -------
    ImuRecord

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(0, 1, 0.01)
    >>> q = np.tile([1.0, 0, 0, 0], (t.size, 1))
    >>> rec = simulate_imu(Trajectory(t, q))
    >>> rec.accel_m_s2[0].round(5)
    array([0.     , 0.     , 9.80665])
    """
    if not isinstance(trajectory, Trajectory):
        raise TypeError(f"trajectory must be a Trajectory, got {type(trajectory).__name__}")
    model = ImuErrorModel() if model is None else model
    if not isinstance(model, ImuErrorModel):
        raise TypeError(f"model must be an ImuErrorModel, got {type(model).__name__}")
    if rng is not None and not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    n_trials = 1 if trials is None else positive_int(trials, "trials")

    q_bs = np.asarray(model.q_mount, dtype=float)
    q_ws = rotations.quat_multiply(trajectory.q_wb, q_bs)
    c_sb = rotations.quat_to_matrix(q_bs).T
    gyro_true = body_rates(trajectory) @ c_sb.T
    accel_true = specific_force(trajectory, gravity_w_m_s2) @ c_sb.T

    rngs = {}
    if rng is not None:
        children = rng.spawn(2 * len(_SOURCES))
        rngs = {"gyro": dict(zip(_SOURCES, children[:len(_SOURCES)])),
                "accel": dict(zip(_SOURCES, children[len(_SOURCES):]))}
    elif _has_random_errors(model):
        raise ValueError("rng must be a numpy.random.Generator when the error model has random errors")
    dt = trajectory.dt_s
    gyro = model.gyro.apply(gyro_true, trajectory.time_s, dt, n_trials, rngs.get("gyro", {}),
                            model.time_since_power_on_s)
    accel = model.accel.apply(accel_true, trajectory.time_s, dt, n_trials, rngs.get("accel", {}),
                              model.time_since_power_on_s)
    if trials is None:
        gyro, accel = gyro[0], accel[0]
    return ImuRecord(trajectory.time_s, gyro, accel, q_ws, gyro_true, accel_true)


def _has_random_errors(model: ImuErrorModel) -> bool:
    for s in (model.gyro, model.accel):
        if s.bias_sigma or s.noise_density or s.bias_random_walk or s.bias_instability:
            return True
        if np.any(_vec3(s.vibration_amplitude, "vibration_amplitude")) and s.vibration_freq_hz:
            return True
    return False
