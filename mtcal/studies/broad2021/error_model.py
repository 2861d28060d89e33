"""broad2021 twin: a simulated copy of each real trial, built blind, asked to predict each filter's real error.

Blind by construction: the twin of a trial is built only from what an engineer has before
running any filter against the optical reference —

* **truth trajectory** from the optical system: attitude = the optical quaternions (gaps filled by
  linear interpolation of sign-continuous components, then a Savitzky–Golay smoothing over
  ``smooth_quat_s`` = 0.1 s, order 2, renormalised); linear acceleration = the second derivative of
  the optical position (Savitzky–Golay, ``smooth_pos_s`` = 0.2 s, order 2). Lever arm between the
  optical body origin and the IMU: **zero** (not known to the engineer; stated, not fitted). Angular
  rate and specific force then follow from :func:`mtcal.core.simulate.simulate_imu` (interval-mean
  rates, ``f = Cᵀ (a − g)``), gravity ``local_gravity_m_s2`` (9.8128 m/s², Berlin);
* **IMU error model** from the trial's own initial rest (:func:`mtcal.studies.broad2021.runs.initial_rest`):
  gyro bias = the rest's mean rate (kept constant), white-noise densities = the rest's per-axis
  standard deviations × √Δt (RMS over axes), the accelerometer bias along the rest's gravity
  direction = ``‖ā‖ − g_local`` (constant), its other components unknown: a turn-on bias of 1σ
  ``|‖ā‖ − g_local| / √3`` per axis drawn per draw. Rests are 2–10 s: too short for an Allan fit of
  bias instability or random walk, which are therefore absent.

Never used: the IMU-vs-optical error of any filter, the published results, the movement phase's
IMU samples. Each draw of the twin is a new noise/bias realisation (stream :data:`STREAM_TWIN`,
keyed by trial number); every filter sees the same draws. :func:`predict_real_error` returns a
filter's inclination-RMSE draws and their spread (:func:`mtcal.core.metrics.band_or_range`: the
min–max range for fewer than 1000 draws, which covers (n−1)/(n+1) of the draws' distribution).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
from scipy.signal import savgol_filter

from mtcal.core import metrics, rotations
from mtcal.core.rng import trial_rng
from mtcal.core.simulate import ImuErrorModel, SensorErrors, Trajectory, simulate_imu
from mtcal.core.validate import positive_int, positive_scalar

from .runs import initial_rest, rmse_deg, run_6d
from .scenario import FILTERS_6D, Trial

__all__ = ["STREAM_TWIN", "STREAM_TWIN_MOUNT", "STREAM_TWIN_LOTO", "RestModel", "identify_rest_model", "twin_truth", "TwinTruth", "simulate_twin",
           "predict_real_error", "TwinPrediction", "twin_predictions", "twin_gaps", "trial_number", "LOCAL_GRAVITY_M_S2"]

#: Random stream of the twin's draws (keyed by seed, this stream, the trial number).
STREAM_TWIN = 60
#: Random stream of the direction of the twin's mount tilt (keyed by seed, this stream, the trial number).
STREAM_TWIN_MOUNT = 61
#: Random stream choosing, per draw, the other trial whose measured gaps a leave-one-trial-out twin borrows.
STREAM_TWIN_LOTO = 62
#: Gravity at the recording site (Berlin 52.5° N, normal gravity formula, m/s²).
LOCAL_GRAVITY_M_S2 = 9.8128


@dataclass(frozen=True)
class RestModel:
    """IMU error model identified from one initial rest (SI units).

    Attributes
    ----------
    rest_s : float
        Length of the rest used (s).
    gyro_bias_rad_s : ndarray (3,)
        Mean rate at rest.
    gyro_noise_density_rad_s_rthz, accel_noise_density_m_s2_rthz : float
        White-noise densities (RMS over axes of std × √Δt).
    accel_norm_offset_m_s2 : float
        ``‖ā‖ − g_local`` at rest.
    gravity_dir_s : ndarray (3,)
        Unit mean specific force at rest (sensor frame).
    """

    rest_s: float
    gyro_bias_rad_s: np.ndarray
    gyro_noise_density_rad_s_rthz: float
    accel_noise_density_m_s2_rthz: float
    accel_norm_offset_m_s2: float
    gravity_dir_s: np.ndarray

    def error_model(self) -> ImuErrorModel:
        """The simulator's :class:`~mtcal.core.simulate.ImuErrorModel` of this rest (see module docstring)."""
        off = self.accel_norm_offset_m_s2
        return ImuErrorModel(
            gyro=SensorErrors(bias=tuple(float(b) for b in self.gyro_bias_rad_s),
                              noise_density=self.gyro_noise_density_rad_s_rthz),
            accel=SensorErrors(bias=tuple(float(b) for b in off * self.gravity_dir_s),
                               bias_sigma=abs(off) / np.sqrt(3.0),
                               noise_density=self.accel_noise_density_m_s2_rthz))


def _mean_var(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Column means and variances by serial sums (``cumsum``): the same bits whatever the array's memory
    alignment (numpy's pairwise SIMD sums are not), so the twin's draws never depend on where a trial sits."""
    n = x.shape[0]
    mean = np.cumsum(x, axis=0)[-1] / n
    return mean, np.cumsum((x - mean) ** 2, axis=0)[-1] / n


def identify_rest_model(trial: Trial, margin_s: float = 0.5,
                        local_gravity_m_s2: float = LOCAL_GRAVITY_M_S2) -> RestModel:
    """Identify the twin's IMU error model from the trial's initial rest (never from any filter's error).

    >>> import numpy as np
    >>> from mtcal.core.rng import stream_rng
    >>> from mtcal.studies.broad2021.scenario import Trial
    >>> rng = stream_rng(0, STREAM_TWIN); n = 1000
    >>> tr = Trial("t", 0.01 + 0.001 * rng.standard_normal((n, 3)), np.tile([0.0, 0.0, 9.9], (n, 1)),
    ...            np.ones((n, 3)), np.tile([1.0, 0, 0, 0], (n, 1)), np.zeros((n, 3)), np.arange(n) > 800, 100.0)
    >>> m = identify_rest_model(tr)
    >>> round(m.rest_s, 2), np.round(m.gyro_bias_rad_s, 3).tolist(), round(m.accel_norm_offset_m_s2, 4)
    (7.51, [0.01, 0.01, 0.01], 0.0872)
    """
    rest = initial_rest(trial, margin_s)
    g = trial.gyro_rad_s[rest]
    a = trial.accel_m_s2[rest]
    mean_g, var_g = _mean_var(g)
    mean_a, var_a = _mean_var(a)
    norm = float(np.linalg.norm(mean_a))
    root_dt = np.sqrt(trial.dt_s)
    return RestModel(rest_s=(rest.stop - rest.start) * trial.dt_s, gyro_bias_rad_s=mean_g,
                     gyro_noise_density_rad_s_rthz=float(np.sqrt(np.mean(var_g))) * root_dt,
                     accel_noise_density_m_s2_rthz=float(np.sqrt(np.mean(var_a))) * root_dt,
                     accel_norm_offset_m_s2=norm - positive_scalar(local_gravity_m_s2, "local_gravity_m_s2"),
                     gravity_dir_s=mean_a / norm)


def _fill(x: np.ndarray) -> np.ndarray:
    """Fill NaN rows by linear interpolation per column (nearest value beyond the ends)."""
    ok = np.isfinite(x[:, 0])
    if not ok.any():
        raise ValueError("the optical reference holds no finite sample")
    idx = np.arange(x.shape[0])
    return np.stack([np.interp(idx, idx[ok], x[ok, j]) for j in range(x.shape[1])], axis=1)


def _window(seconds: float, fs_hz: float) -> int:
    w = max(5, int(round(seconds * fs_hz)))
    return w + 1 if w % 2 == 0 else w


@dataclass(frozen=True)
class TwinTruth:
    """The twin's truth: smoothed optical attitude (N, 4, sensor → ENU) and world acceleration (N, 3, m/s²)."""

    q_ws: np.ndarray
    accel_w_m_s2: np.ndarray


def twin_truth(trial: Trial, smooth_quat_s: float = 0.1, smooth_pos_s: float = 0.2) -> TwinTruth:
    """The twin's truth trajectory from the optical data (see module docstring)."""
    q = trial.opt_quat.copy()
    ok = np.isfinite(q[:, 0])
    q[ok] = rotations.make_continuous(q[ok], axis=0)
    q = _fill(q)
    q = savgol_filter(q, _window(smooth_quat_s, trial.fs_hz), 2, axis=0)
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    pos = _fill(trial.opt_pos_m)
    acc = savgol_filter(pos, _window(smooth_pos_s, trial.fs_hz), 2, deriv=2, delta=trial.dt_s, axis=0)
    return TwinTruth(q_ws=q, accel_w_m_s2=acc)


def twin_gaps(trial: Trial, smooth_quat_s: float = 0.1, max_lag_samples: int = 10, *, matrix: bool = False,
              truth: TwinTruth | None = None):
    """What the twin lacks, measured after the fact on the movement phase (a diagnosis, never a twin input).

    Least squares of the real gyro on the twin's true rate (the smoothed optical attitude's interval-mean
    rate): ``ω_imu(t_k) ≈ A ω_opt(t_{k+lag}) + b``, over lags of ±``max_lag_samples`` samples; the lag with
    the smallest residual is the IMU-vs-optical time offset. ``A − I`` holds the gyro scale-factor errors
    (diagonal) and axis misalignment (off-diagonal), both absent from the twin.

    Returns
    -------
    dict
        ``gyro_scale_pct`` (mean |A_ii − 1|, %), ``gyro_misalignment_deg`` (RMS off-diagonal of A, deg),
        ``time_offset_ms`` (best lag), ``gyro_fit_residual_deg_s`` (RMS residual), ``opt_rate_rms_deg_s``;
        with ``matrix=True`` the fitted 3×3 ``A`` instead.

    ``truth``: the trial's :func:`twin_truth` at ``smooth_quat_s`` when the caller has it already (only its
    attitude is read); computed here otherwise.
    """
    gaps, a = _gaps(trial, twin_truth(trial, smooth_quat_s) if truth is None else truth, max_lag_samples)
    return a if matrix else gaps


def _gaps(trial: Trial, truth: TwinTruth, max_lag_samples: int) -> tuple[dict, np.ndarray]:
    """:func:`twin_gaps`' dict and fitted matrix ``A`` at once, from the trial's twin truth."""
    from mtcal.core.simulate import body_rates

    w_opt = body_rates(Trajectory(np.arange(trial.n) * trial.dt_s, truth.q_ws))
    ok = trial.movement & np.isfinite(trial.opt_quat[:, 0])
    idx = np.flatnonzero(ok)
    idx = idx[(idx >= max_lag_samples) & (idx < trial.n - max_lag_samples)]
    y = trial.gyro_rad_s[idx]
    best = None
    for lag in range(-max_lag_samples, max_lag_samples + 1):
        x = np.column_stack([w_opt[idx + lag], np.ones(idx.size)])
        coef, *_ = np.linalg.lstsq(x, y, rcond=None)
        res = float(np.sqrt(np.mean((y - x @ coef) ** 2)))
        if best is None or res < best[0]:
            best = (res, lag, coef[:3].T)
    res, lag, a = best
    off = a[~np.eye(3, dtype=bool)]
    return {"gyro_scale_pct": float(100.0 * np.mean(np.abs(np.diag(a) - 1.0))),
            "gyro_misalignment_deg": float(np.degrees(np.sqrt(np.mean(off ** 2)))),
            "time_offset_ms": 1000.0 * lag * trial.dt_s, "gyro_fit_residual_deg_s": float(np.degrees(res)),
            "opt_rate_rms_deg_s": float(np.degrees(np.sqrt(np.mean(w_opt[idx] ** 2))))}, a


def trial_number(trial: Trial) -> int:
    """The trial's number (leading digits of its name), the key of its random streams."""
    head = trial.name.split("_", 1)[0]
    return int(head) if head.isdigit() else sum(trial.name.encode())


def simulate_twin(trial: Trial, n_draws: int, seed: int, *, margin_s: float = 0.5, smooth_quat_s: float = 0.1,
                  smooth_pos_s: float = 0.2, local_gravity_m_s2: float = LOCAL_GRAVITY_M_S2,
                  mount_tilt_rad=0.0, gyro_matrix=None, time_offset_samples=0, truth: TwinTruth | None = None):
    """``n_draws`` simulated records of the trial's twin: (ImuRecord with (n_draws, N, 3) arrays, truth, RestModel).

    The blind twin has none of the three extra error sources below (their defaults); each may be one value
    or one per draw (what :func:`twin_gaps` measured on *other* trials, for a leave-one-trial-out test):

    * ``mount_tilt_rad`` ≥ 0: the simulated IMU is tilted against the optical body frame by that angle about
      a sensor-horizontal axis (x–y plane) of random direction per draw (stream :data:`STREAM_TWIN_MOUNT`);
    * ``gyro_matrix`` (3×3 ``I + S + M``, or (n_draws, 3, 3)): gyro scale-factor and misalignment errors;
    * ``time_offset_samples`` (int): record sample k is the simulated sample k + offset (clipped at the ends).

    Each draw keeps its noise numbers (``trial_ids``) whatever the extra sources. ``truth``: the trial's
    :func:`twin_truth` at ``smooth_quat_s``, ``smooth_pos_s`` when the caller has it already (computed here
    otherwise).
    """
    model = identify_rest_model(trial, margin_s, local_gravity_m_s2)
    if truth is None:
        truth = twin_truth(trial, smooth_quat_s, smooth_pos_s)
    traj = Trajectory(np.arange(trial.n) * trial.dt_s, truth.q_ws, truth.accel_w_m_s2)
    n_draws = positive_int(n_draws, "n_draws")
    gravity = (0.0, 0.0, -local_gravity_m_s2)
    errors = model.error_model()
    tilts = np.broadcast_to(np.asarray(mount_tilt_rad, dtype=float), (n_draws,))
    if not np.all(np.isfinite(tilts)) or np.any(tilts < 0):
        raise ValueError(f"mount_tilt_rad must be finite and >= 0, got {mount_tilt_rad!r}")
    lags = np.broadcast_to(np.asarray(time_offset_samples), (n_draws,))
    if lags.dtype.kind not in "iu":
        raise TypeError(f"time_offset_samples must be integers, got {lags.dtype}")
    mats = None
    if gyro_matrix is not None:
        mats = np.broadcast_to(np.asarray(gyro_matrix, dtype=float), (n_draws, 3, 3))
        if not np.all(np.isfinite(mats)):
            raise ValueError("gyro_matrix must be finite 3x3 matrices")
    rng = trial_rng(seed, STREAM_TWIN, trial_number(trial))
    if mats is None and not np.any(tilts) and not np.any(lags):
        return simulate_imu(traj, errors, rng, trials=n_draws, gravity_w_m_s2=gravity), truth, model
    phi = trial_rng(seed, STREAM_TWIN_MOUNT, trial_number(trial)).uniform(0.0, 2.0 * np.pi, n_draws)
    gyr, acc = [], []
    for d in range(n_draws):
        q_bs = rotations.quat_from_rotvec(tilts[d] * np.array([np.cos(phi[d]), np.sin(phi[d]), 0.0]))
        err = dataclasses.replace(errors, q_mount=tuple(float(v) for v in q_bs))
        if mats is not None:
            off = np.where(np.eye(3, dtype=bool), 0.0, mats[d])
            err = dataclasses.replace(err, gyro=dataclasses.replace(
                err.gyro, scale_factor=tuple(float(v) for v in np.diag(mats[d]) - 1.0),
                misalignment=tuple(tuple(float(v) for v in row) for row in off)))
        part = simulate_imu(traj, err, trial_rng(seed, STREAM_TWIN, trial_number(trial)), trials=1,
                            gravity_w_m_s2=gravity, trial_ids=[d])
        shift = np.clip(np.arange(trial.n) + int(lags[d]), 0, trial.n - 1)
        gyr.append(part.gyro_rad_s[:, shift])
        acc.append(part.accel_m_s2[:, shift])
    rec = dataclasses.replace(part, gyro_rad_s=np.concatenate(gyr), accel_m_s2=np.concatenate(acc))
    return rec, truth, model


@dataclass(frozen=True)
class TwinPrediction:
    """A filter's predicted inclination RMSE on a real trial.

    Attributes
    ----------
    filter : str
    rmse_deg : ndarray (n_draws,)
        Inclination RMSE (deg) of each twin draw over the trial's movement phase.
    band : dict
        :func:`mtcal.core.metrics.band_or_range` of the draws (``median, low, high, n, kind``).
    rest : RestModel
        The identified error model.
    """

    filter: str
    rmse_deg: np.ndarray
    band: dict
    rest: RestModel


def twin_predictions(trial: Trial, filters, n_draws: int, seed: int, **twin) -> dict[str, TwinPrediction]:
    """Every filter of ``filters`` on the same ``n_draws`` twin records of one trial (common random numbers)."""
    bad = [f for f in filters if f not in FILTERS_6D]
    if bad:
        raise ValueError(f"filters must be among {FILTERS_6D}, got {bad}")
    rec, truth, model = simulate_twin(trial, n_draws, seed, **twin)
    ref = np.where(np.isfinite(trial.opt_quat[:, :1]), truth.q_ws, np.nan)   # BROAD's NaN rule kept
    scored = Trial(trial.name, trial.gyro_rad_s, trial.accel_m_s2, trial.mag_uT, ref, trial.opt_pos_m,
                   trial.movement, trial.fs_hz, trial.groups)
    out = {}
    for f in filters:
        q = run_6d(f, rec.gyro_rad_s, rec.accel_m_s2, trial.dt_s)
        r = rmse_deg(q, scored, inclination_only=True)[0]
        out[f] = TwinPrediction(f, r, metrics.band_or_range(r, what="twin draws"), model)
    return out


def predict_real_error(trial: Trial, filter: str, n_draws: int = 20, seed: int = 2026, **twin) -> TwinPrediction:
    """Predict a 6D filter's inclination RMSE (deg) on a real trial from the trial's simulated twin.

    Parameters
    ----------
    trial : Trial
        A BROAD trial (:func:`mtcal.studies.broad2021.scenario.load_trial`); it needs an initial rest
        of at least 1 s before its movement phase.
    filter : str
        One of :data:`mtcal.studies.broad2021.scenario.FILTERS_6D`.
    n_draws : int
        Twin draws (noise and bias realisations).
    seed : int
        Seed of the keyed stream :data:`STREAM_TWIN` (the trial number is the key's trial).
    **twin
        ``margin_s``, ``smooth_quat_s``, ``smooth_pos_s``, ``local_gravity_m_s2`` (module docstring),
        ``mount_tilt_rad``, ``gyro_matrix``, ``time_offset_samples`` (:func:`simulate_twin`; none by default:
        the blind twin).

    Returns
    -------
    TwinPrediction
        Draws and their spread; compare ``band["low"] <= real <= band["high"]``.

    References
    ----------
    broad2021 (metric, Sec. 4); the twin is mtcal's (module docstring).

    Examples
    --------
    >>> from mtcal.studies.broad2021 import scenario
    >>> tr = scenario.load_trials(["01_undisturbed_slow_rotation_A"])[0]
    >>> p = predict_real_error(tr, "mahony", n_draws=2, seed=1)
    >>> p.rmse_deg.shape, p.band["kind"]
    ((2,), 'range')
    """
    return twin_predictions(trial, [filter], n_draws, seed, **twin)[filter]
