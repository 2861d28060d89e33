"""Six-position installation-error calibration as one procedure (wang2023cja §3.2, §4.1).

:func:`calibrate_installation` is the whole measurement over plain arrays —

1. sensor attitude: the QNCF (Eq 5–8) of raw gyro/accel, or the quaternions given;
2. zeroed at the first sample ("initial attitude angles 0°", §4.1;
   :func:`mtcal.core.rotations.relative_to_initial`);
3. rests found from the data (gyro norm or quaternion rate, :func:`detect_rests`)
   or given, the middle section of each averaged (Eq 14 columns);
4. rests matched to the reference positions (Eq 15 angles through Eq 9) and
   Eq 13 solved by least squares;
5. gates: conditioning of the positions, distance of Q̂ from SO(4), residuals;
6. installation angles (inverse of Eq 1) of the mounting part of Q̂'s SO(4)
   projection ``L(p) R(r)``, mounting quaternion ``q_bs = r*``.

Step 1 is the system's (the QNCF of :mod:`mtcal.filters.qncf`); steps 2–6 are one methods-level
procedure on that attitude, :func:`mtcal.methods.six_position.calibrate_from_rests`, which the
system calls once with the config's settings after checking every input here (the positions made
their Eq 9 reference attitudes at the same edge).

:func:`apply_installation` is Eq 10 on a stream (``q_body = normalize(Q̂ q_sensor)``): the
paper's *relative* body attitude, zeroed where the record starts (the turntable's zero).
:func:`absolute_body_attitude` is the gravity-referenced one for a record that starts anywhere
(a parked aircraft): ``q_body = q_ws ⊗ q_bs*`` with the mounting of Q̂, heading zeroed.
Each takes one frozen, checked :class:`InstallationConfig` (constructors for the paper's
settings, the studies' Monte Carlo, a sweep cell and the CLI options) plus the data arrays;
:func:`verify_installation` runs the same steps on a separate run with Q̂ given (the study's
verification). :func:`measure_session` measures a Monte Carlo session of stacked records in one call (one
QNCF, the session zeroed once, each block of trials' calibration and verification run:
:func:`mtcal.methods.six_position.calibrate_session`); :func:`measure_simulated_session` is the same for a Monte Carlo
whose records the procedure pulls from a :class:`mtcal.core.simulate.RecordSource` once its inputs are checked (with
later runs read with each block's Q̂: the wind-on groups). The CLI (``mtcal calibrate`` / ``mtcal apply``), the wang2023cja studies and the
``six_position`` sweep evaluator all call these functions; the arrays are checked here once,
at the edge, and the methods below trust them.

References
----------
wang2023cja — Wang X. et al., Chin. J. Aeronaut. 2023, doi:10.1016/j.cja.2022.12.006:
Eq 1 (installation angles), Eq 9 (ZXY quaternion), Eq 10 (calibrated attitude),
Eq 13–15 (least squares, positions), §3.2 (procedure), §4.1 (zeroing).

Examples
--------
:func:`calibrate_installation` recovers a mounting from a noise-free record and
:func:`apply_installation` then gives the body attitude back (see its example).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cached_property
from numbers import Real

import numpy as np

from mtcal.core import montecarlo, rotations
from mtcal.core.simulate import RecordSource
from mtcal.core.validate import as_float_array, float64_array, positive_scalar, sample_interval, unit_quaternion
from mtcal.filters.qncf import QncfParams, qncf, qncf_trusted
from mtcal.methods import constrained_fit, six_position
from mtcal.systems import attitude, plausibility
from mtcal.systems import rests as rests_system
from mtcal.systems.rests import RestsConfig

__all__ = ["MODELS", "missing_rotation_axis", "MAX_CONDITION", "MAX_SO4_DISTANCE", "MAX_RESIDUAL_RAD",
           "InstallationConfig", "InstallationCalibration", "CalibratedAttitude", "InstallationRefused", "detect_rests",
           "calibrate_installation", "verify_installation", "apply_installation", "absolute_body_attitude",
           "mounting_from_q_hat", "installation_angles_sigma", "calibrate_record", "apply_record", "RecordCalibration",
           "RecordApplication", "RecordRefused", "RefusalDiagnosis", "MISMATCH_MESSAGES", "POSITION_MISTAKES",
           "QUATERNION_CONVENTIONS", "SessionPiece", "SessionSweep", "SessionMeasurement", "measure_session",
           "measure_simulated_session", "AppliedRun", "AppliedRuns", "AppliedMeasurement", "measure_applied_runs"]

#: Gate: condition number of ``A_q^s (A_q^s)ᵀ`` (Eq 13) above which the positions are refused.
MAX_CONDITION = six_position.MAX_CONDITION
#: Gate: Frobenius distance of Q̂ from SO(4) above which Q̂ is not a calibration.
MAX_SO4_DISTANCE = 0.05
#: Gate: largest accepted residual at a position (rad), 1°.
MAX_RESIDUAL_RAD = float(np.radians(1.0))

#: Outcome of :func:`calibrate_installation` (:class:`mtcal.methods.six_position.PositionCalibration`).
InstallationCalibration = six_position.PositionCalibration
#: :func:`calibrate_installation` refused a record after it made its sensor attitude (no rest for a
#: position, a gate); ``q_ws`` holds that attitude (:class:`mtcal.methods.six_position.PositionsRefused`).
InstallationRefused = six_position.PositionsRefused
#: Error-map models of :func:`calibrate_installation`: name → (parameters, what the positions must span).
MODELS = six_position.MODELS
missing_rotation_axis = six_position.missing_rotation_axis


@dataclass(frozen=True)
class CalibratedAttitude:
    """Outcome of :func:`apply_installation`.

    Attributes
    ----------
    q_body : ndarray (N, 4) or (T, N, 4)
        Calibrated body attitude ``normalize(Q̂ q_sensor)`` (Eq 10), body → world, sign-continuous.
    q_sensor : ndarray (N, 4) or (T, N, 4)
        The sensor attitude it was computed from, zeroed at the first sample.
    """

    q_body: np.ndarray
    q_sensor: np.ndarray


@dataclass(frozen=True)
class InstallationConfig:
    """Every setting of the six-position procedure and its application, checked once when made.

    The procedure's functions (:func:`calibrate_installation`, :func:`verify_installation`,
    :func:`detect_rests`, :func:`apply_installation`, :func:`absolute_body_attitude`) take one
    config and the data arrays. Constructors: :meth:`paper` (wang2023cja §3.2, gates on),
    :meth:`monte_carlo` (the studies: gates off), :meth:`sweep_cell` (a sweep's simulated
    schedule) and :meth:`command_line` (``mtcal calibrate`` / ``mtcal apply`` options).

    Attributes
    ----------
    model : {"eq13", "so4", "mounting"}
        The error map fitted (see :data:`MODELS`): ``"eq13"`` the paper's 16-parameter least
        squares (needs rotations about all three axes), ``"so4"`` the nearest rotation of
        quaternion space ``L(p) R(r)`` (6 parameters, rotations about two axes suffice),
        ``"mounting"`` the mounting alone, ``q_body = q_bs ⊗ q_sensor ⊗ q_bs*`` (3 parameters).
    fraction : float
        Middle fraction of each rest averaged, (0, 1].
    min_rest_s, still_threshold_rad_s, still_window_s : float
        Rest detector (§3.2 stillness on the gyro norm or the quaternion rate): shortest rest
        (s), stillness threshold (rad/s; 0.2 °/s) and moving window (s).
    max_match_rad : float
        Largest distance between a rest and its position (rad).
    max_condition, max_so4_distance, max_residual_rad : float
        Gates (dimensionless, dimensionless, rad); ``inf`` switches one off. With a trial axis the
        worst trial is gated.
    rests_in_order : bool
        The rests given are known by construction, one per position in the positions' order (a
        simulated schedule): rest k is used for position k, without matching by attitude.
    zero_at_first_sample : bool
        Zero the sensor attitude at the record's first sample ("initial attitude angles 0°", §4.1);
        off for a record already zeroed at its session's start (a verification run).
    qncf_params : QncfParams
        QNCF (Eq 5–8) parameters for raw data.
    zero_heading : bool
        :func:`absolute_body_attitude`: zero the body yaw at the first sample.
    rest_detector : RestsConfig or None
        The rest detector of a raw log (:func:`calibrate_record`, :func:`apply_record`; ``detector="paper"``:
        the calibration matches the §3.2 stillness rests of :func:`detect_rests`).

    References
    ----------
    wang2023cja §3.2 (3 s rests, middle section, six positions), §4.1 (zeroed start), Eq 13.

    Examples
    --------
    >>> cfg = InstallationConfig.monte_carlo(fraction=0.5)
    >>> cfg.max_residual_rad, cfg.model
    (inf, 'eq13')
    >>> InstallationConfig(fraction=1.5)
    Traceback (most recent call last):
    ...
    ValueError: fraction must be in (0, 1], got 1.5
    """

    model: str = "eq13"
    fraction: float = 0.5
    min_rest_s: float = 2.0
    still_threshold_rad_s: float = float(np.radians(0.2))
    still_window_s: float = 0.1
    max_match_rad: float = float(np.radians(5.0))
    max_condition: float = MAX_CONDITION
    max_so4_distance: float = MAX_SO4_DISTANCE
    max_residual_rad: float = MAX_RESIDUAL_RAD
    rests_in_order: bool = False
    zero_at_first_sample: bool = True
    qncf_params: QncfParams = QncfParams()
    zero_heading: bool = True
    rest_detector: RestsConfig | None = None

    def __post_init__(self):
        if self.model not in MODELS:
            raise ValueError(f"model must be one of {', '.join(MODELS)}, got {self.model!r}")
        f = positive_scalar(self.fraction, "fraction")
        if f > 1:
            raise ValueError(f"fraction must be in (0, 1], got {f}")
        if self.rest_detector is not None and not isinstance(self.rest_detector, RestsConfig):
            raise TypeError(f"rest_detector must be a RestsConfig or None, got {type(self.rest_detector).__name__}")
        if not isinstance(self.qncf_params, QncfParams):
            raise TypeError(f"qncf_params must be a QncfParams, got {type(self.qncf_params).__name__}")
        values = dict(fraction=f, min_rest_s=positive_scalar(self.min_rest_s, "min_rest_s"),
                      still_threshold_rad_s=positive_scalar(self.still_threshold_rad_s, "still_threshold_rad_s"),
                      still_window_s=positive_scalar(self.still_window_s, "still_window_s"),
                      max_match_rad=positive_scalar(self.max_match_rad, "max_match_rad"),
                      **{k: _limit(getattr(self, k), k) for k in ("max_condition", "max_so4_distance",
                                                                  "max_residual_rad")},
                      **{k: bool(getattr(self, k)) for k in ("rests_in_order", "zero_at_first_sample",
                                                             "zero_heading")})
        for k, v in values.items():
            object.__setattr__(self, k, v)

    @classmethod
    def paper(cls, fraction: float = 0.5) -> "InstallationConfig":
        """wang2023cja §3.2: Eq 13, middle ``fraction`` of 3 s rests found by the 0.2 °/s stillness
        detector (2 s shortest), the paper's QNCF, gates on."""
        return cls(fraction=fraction)

    @classmethod
    def monte_carlo(cls, fraction: float = 0.5, *, zero_at_first_sample: bool = True,
                    qncf_params: QncfParams | None = None) -> "InstallationConfig":
        """The studies' Monte Carlo: :meth:`paper` with the gates off (``inf``) — a Monte Carlo reports
        the spread of every trial instead of refusing the set because one trial would be refused.
        ``zero_at_first_sample=False`` for a verification run already zeroed at its session's start;
        ``qncf_params`` the scenario's QNCF (None: the paper's, :func:`measure_session`)."""
        return cls(fraction=fraction, max_condition=np.inf, max_so4_distance=np.inf, max_residual_rad=np.inf,
                   zero_at_first_sample=zero_at_first_sample,
                   qncf_params=QncfParams() if qncf_params is None else qncf_params)

    @classmethod
    def sweep_cell(cls, fraction: float = 0.5) -> "InstallationConfig":
        """A sweep cell's simulated schedule: the holds known by construction (``rests_in_order``),
        middle ``fraction`` averaged, gates off."""
        return cls(fraction=fraction, rests_in_order=True, max_condition=np.inf, max_so4_distance=np.inf,
                   max_residual_rad=np.inf)

    @classmethod
    def command_line(cls, *, model: str = "eq13", fraction: float = 0.5, min_rest_s: float = 2.0,
                     still_threshold_rad_s: float = float(np.radians(0.2)),
                     max_so4_distance: float | None = None, max_residual_rad: float = MAX_RESIDUAL_RAD,
                     qncf_params: QncfParams | None = None,
                     rest_detector: RestsConfig | None = None) -> "InstallationConfig":
        """``mtcal calibrate`` / ``mtcal apply``: the options' values (SI), defaults as the commands'.

        ``max_so4_distance`` None is :data:`MAX_SO4_DISTANCE`; ``qncf_params`` None the paper's QNCF;
        ``rest_detector`` the rest options (a raw log's detector).
        """
        return cls(model=model, fraction=fraction, min_rest_s=min_rest_s, still_threshold_rad_s=still_threshold_rad_s,
                   max_so4_distance=MAX_SO4_DISTANCE if max_so4_distance is None else max_so4_distance,
                   max_residual_rad=max_residual_rad, qncf_params=QncfParams() if qncf_params is None else qncf_params,
                   rest_detector=rest_detector)


# --------------------------------------------------------------------------- the public edge
def _limit(value, name: str) -> float:
    """A gate threshold: a positive number; ``inf`` switches the gate off."""
    if isinstance(value, bool) or not isinstance(value, (Real, np.floating, np.integer)) or not float(value) > 0:
        raise ValueError(f"{name} must be a positive number (inf switches the gate off), got {value!r}")
    return float(value)


def _record(q_ws, gyro_rad_s, accel_m_s2, q0, need_dt: bool, dt_s):
    """Check the attitude source once: ``q_ws`` or raw ``gyro_rad_s`` + ``accel_m_s2``.

    Returns ``(q, gyro, accel, q0, stream)`` with ``stream`` the array that sets the record's shape.
    """
    if q_ws is not None:
        if accel_m_s2 is not None or q0 is not None:
            raise ValueError("give either q_ws (sensor attitude) or gyro_rad_s and accel_m_s2 (raw data for "
                             "the QNCF), not both; accel_m_s2 and q0 belong to the raw data")
        # only read inside (the results hold new arrays): no copies of the caller's records
        q = unit_quaternion(q_ws, "q_ws", copy=False)
        if q.ndim not in (2, 3):
            raise ValueError(f"q_ws must have shape (N, 4) or (T, N, 4), got {q.shape}")
        gyro = None if gyro_rad_s is None else as_float_array(gyro_rad_s, "gyro_rad_s", ndim=(2, 3), last_dim=3,
                                                               copy=False)
        if gyro is not None and gyro.shape[-2] != q.shape[-2]:
            raise ValueError(f"gyro_rad_s has {gyro.shape[-2]} samples but q_ws has {q.shape[-2]}")
        return q, gyro, None, None, q
    if gyro_rad_s is None or accel_m_s2 is None:
        raise ValueError("a sensor attitude is needed: give q_ws, or gyro_rad_s and accel_m_s2 for the QNCF")
    gyro = as_float_array(gyro_rad_s, "gyro_rad_s", ndim=(2, 3), last_dim=3, copy=False)      # only read inside
    accel = as_float_array(accel_m_s2, "accel_m_s2", ndim=(2, 3), last_dim=3, copy=False)
    if gyro.shape != accel.shape:
        raise ValueError(f"gyro_rad_s and accel_m_s2 must have the same shape, got {gyro.shape} and {accel.shape}")
    if need_dt and dt_s is None:
        raise ValueError("dt_s is needed to run the QNCF on raw data")
    return None, gyro, accel, q0, gyro


def _positions_record(config: InstallationConfig, positions_rad, dt_s, q_ws, gyro_rad_s, accel_m_s2, q0, rests,
                      q_hat=None):
    """The edge of :func:`calibrate_installation` and :func:`verify_installation` (with ``q_hat``): every
    input checked once; ``q_hat`` given, it leads the checked values."""
    if not isinstance(config, InstallationConfig):
        raise TypeError(f"config must be an InstallationConfig, got {type(config).__name__}")
    mat = None if q_hat is None else _q_hat(q_hat)
    q, gyro, accel, q0, stream = _record(q_ws, gyro_rad_s, accel_m_s2, q0, True, dt_s)
    pos = as_float_array(positions_rad, "positions_rad", ndim=(2, 3), last_dim=3)
    k = pos.shape[-2]
    if k < 4:
        raise ValueError(f"positions_rad must hold at least 4 positions for Eq 13 (16 unknowns), got {k}")
    refs = (pos, rotations.quat_from_euler_zxy_trusted(pos[..., 0], pos[..., 1], pos[..., 2]))      # Eq 9
    dt = sample_interval(dt_s)
    n = stream.shape[-2]
    if pos.ndim == 3 and (stream.ndim != 3 or stream.shape[0] != pos.shape[0]):
        raise ValueError(f"positions_rad of shape {pos.shape} needs a record with {pos.shape[0]} trials, "
                         f"got shape {stream.shape}")
    if config.rests_in_order and (rests is None or len(list(rests)) != k):
        raise ValueError(f"rests_in_order needs rests: one slice per position ({k})")
    if rests is not None:
        rests = list(rests)
        if any(not isinstance(r, slice) or r.start is None or r.stop is None or not 0 <= r.start < r.stop <= n
               for r in rests):
            raise ValueError(f"rests must be slices (start < stop) within the {n} samples of the record")
    checked = (refs, dt, q, gyro, accel, q0, rests)
    return checked if mat is None else (mat,) + checked


def _references(positions_rad, ndim=2) -> tuple:
    """The reference positions checked once (finite rad, K ≥ 4, shape (K, 3) or with ``ndim=(2, 3)`` also
    (T, K, 3)) and their attitudes (Eq 9, yaw about z, pitch about x, roll about y): ``(positions, q_ref)``."""
    pos = as_float_array(positions_rad, "positions_rad", ndim=ndim, last_dim=3)
    if pos.shape[-2] < 4:
        raise ValueError(f"positions_rad must hold at least 4 positions for Eq 13 (16 unknowns), got {pos.shape[-2]}")
    return pos, rotations.quat_from_euler_zxy_trusted(pos[..., 0], pos[..., 1], pos[..., 2])


def _fit_settings(config: InstallationConfig) -> dict:
    """The config's settings of the methods-level calibration
    (:func:`mtcal.methods.six_position.calibrate_from_rests`)."""
    return dict(model=config.model, zero=config.zero_at_first_sample, fraction=config.fraction,
                min_rest_s=config.min_rest_s, threshold_rad_s=config.still_threshold_rad_s,
                window_s=config.still_window_s, max_match_rad=config.max_match_rad, in_order=config.rests_in_order,
                max_condition=config.max_condition, max_so4_distance=config.max_so4_distance,
                max_residual_rad=config.max_residual_rad)


def _sensor_attitude(config: InstallationConfig, q, gyro, accel, q0, dt: float | None, zero: bool = True,
                     units_checked: bool = False) -> tuple:
    """Steps 1–2 on checked inputs: the QNCF of raw data (``q`` None), else ``q`` as given; and that
    attitude zeroed at the first sample (§4.1) if ``zero`` and the config say so. Returns ``(made, zeroed)``.

    ``units_checked``: the record's units were checked (:func:`mtcal.systems.plausibility.check_units`, a log
    procedure): the QNCF runs without its own tilt-rate scan (:func:`mtcal.filters.qncf.qncf_trusted`, the
    same numbers), as :func:`mtcal.systems.attitude.estimate_attitude` runs it."""
    if q is None:
        run = qncf_trusted if units_checked else qncf
        q = run(gyro, accel, dt, config.qncf_params, q0=q0, return_euler=False).q_ws
    if not (zero and config.zero_at_first_sample):
        return q, q
    return q, rotations.relative_to_initial(q[None])[0] if q.ndim == 2 else rotations.relative_to_initial(q)


def _calibrate(config: InstallationConfig, refs, dt, q, gyro, accel, q0, rests, q_hat=None,
               sigma: bool = False) -> InstallationCalibration:
    """Steps 1–6 on checked inputs (see :func:`calibrate_installation`): the sensor attitude (the QNCF of
    raw data, or ``q`` as given), then one methods-level calibration from its rests
    (:func:`mtcal.methods.six_position.calibrate_from_rests` with the config's settings); ``q_hat``
    given: a verification (Q̂ not fitted, no gate)."""
    if q is None:
        q = qncf(gyro, accel, dt, config.qncf_params, q0=q0, return_euler=False).q_ws
    return six_position.calibrate_from_rests(q, *refs, dt, q_hat=q_hat, gyro_rad_s=gyro, rests=rests, sigma=sigma,
                                             **_fit_settings(config))


# --------------------------------------------------------------------------- public procedure
def detect_rests(config: InstallationConfig, dt_s: float, *, gyro_rad_s=None, q_ws=None) -> list[slice]:
    """Rests of a calibration record, as :func:`calibrate_installation` finds them (§3.2 step 3).

    Parameters
    ----------
    config : InstallationConfig
        ``min_rest_s`` (shortest still run, s), ``still_threshold_rad_s`` and ``still_window_s``.
    dt_s : float
        Sample interval (s), ≤ 1 s (``1 / fs_hz`` of the record).
    gyro_rad_s : array_like, shape (N, 3) or (T, N, 3), optional
        Angular rate (rad/s): still where the window's moving mean of ‖ω‖ is below the
        threshold. Used when given.
    q_ws : array_like, shape (N, 4) or (T, N, 4), optional
        Sensor attitude: still where its rotation rate over the window is below the threshold.

    Returns
    -------
    list of slice
        Still runs (sample slices, time order); with a trial axis a sample is still only
        if it is still in every trial.

    References
    ----------
    wang2023cja §3.2 (3 s rests, middle section averaged).

    Examples
    --------
    >>> import numpy as np
    >>> gyro = np.zeros((1000, 3)); gyro[300:500, 2] = 0.5
    >>> detect_rests(InstallationConfig.paper(), 1.0 / 100.0, gyro_rad_s=gyro)
    [slice(0, 296, None), slice(505, 1000, None)]
    """
    if not isinstance(config, InstallationConfig):
        raise TypeError(f"config must be an InstallationConfig, got {type(config).__name__}")
    dt = sample_interval(dt_s)
    if gyro_rad_s is not None:
        gyro = as_float_array(gyro_rad_s, "gyro_rad_s", ndim=(2, 3), last_dim=3, copy=False)
        return six_position.still_rests(dt, config.min_rest_s, config.still_window_s, config.still_threshold_rad_s,
                                        gyro_rad_s=gyro)
    if q_ws is None:
        raise ValueError("give gyro_rad_s or q_ws to detect rests from")
    q = unit_quaternion(q_ws, "q_ws")
    if q.ndim not in (2, 3):
        raise ValueError(f"q_ws must have shape (N, 4) or (T, N, 4), got {q.shape}")
    return six_position.still_rests(dt, config.min_rest_s, config.still_window_s, config.still_threshold_rad_s, q=q)


def calibrate_installation(config: InstallationConfig, positions_rad, dt_s: float, *, q_ws=None, gyro_rad_s=None,
                           accel_m_s2=None, q0=None, rests=None, sigma: bool = False) -> InstallationCalibration:
    """Six-position installation-error calibration of a record (wang2023cja §3.2, Eq 1, 9, 13–15).

    Parameters
    ----------
    config : InstallationConfig
        Model, averaged fraction, rest detector, matching window, gates, QNCF parameters.
    positions_rad : array_like, shape (K, 3) or (T, K, 3)
        Reference ``[ψ, θ, γ]`` of each position (rad; Eq 8/9 frame: yaw about z, pitch
        about x, roll about y), K ≥ 4; per trial (T, K, 3) for a Monte Carlo whose
        reference angles carry their own errors.
    dt_s : float
        Sample interval (s), ≤ 1 s (``1 / fs_hz`` of the record); the QNCF step and the rest
        detector's windows.
    q_ws : array_like, shape (N, 4) or (T, N, 4), optional
        Sensor attitude (sensor → world, scalar-first), e.g. a logger's or a session QNCF's;
        zeroed here at its first sample.
    gyro_rad_s, accel_m_s2 : array_like, shape (N, 3) or (T, N, 3), optional
        Raw data (rad/s, m/s²). Without ``q_ws`` both are needed and the QNCF gives the
        attitude; with ``q_ws`` the gyro only serves rest detection.
    q0 : array_like, shape (4,) or (T, 4), optional
        The QNCF's start attitude with raw data (default: levelled from the first 100 samples).
    rests : list of slice, optional
        Rests found elsewhere (e.g. :func:`mtcal.methods.rest_detection.detect_rests`); by
        default :func:`detect_rests` on the gyro if given, else on ``q_ws``.
    sigma : bool
        Also the 1σ of the installation angles from the fit covariance (``angles_sigma_rad``,
        :func:`installation_angles_sigma`; one record, no trial axis).

    Returns
    -------
    InstallationCalibration

    Raises
    ------
    ValueError
        Bad inputs (the message names the argument).
    InstallationRefused
        A ValueError after the sensor attitude is made: too few rests; a position without a rest;
        degenerate positions; a gate refusing Q̂ (message names the measured value and the limit).

    References
    ----------
    wang2023cja Eq 13 (``Q̂ = A_q^b A_q^sᵀ (A_q^s A_q^sᵀ)⁻¹``), Eq 14–15 (positions as
    columns), Eq 9 (reference quaternions), Eq 1 (installation angles), §3.2 steps 1–7,
    §4.1 (zeroed start).

    Examples
    --------
    >>> import numpy as np
    >>> from mtcal.core import rotations
    >>> from mtcal.core.profiles import trajectory_from_euler_zxy
    >>> from mtcal.methods.six_position import schedule_profile, six_positions_rad
    >>> pos = six_positions_rad()
    >>> q_wb = trajectory_from_euler_zxy(schedule_profile(pos, fs_hz=100.0)).q_wb
    >>> q_ws = rotations.quat_multiply(q_wb, rotations.mount_quaternion(np.radians([1.0, 0.0, 0.0])))
    >>> cfg = InstallationConfig.paper()
    >>> cal = calibrate_installation(cfg, pos, 1.0 / 100.0, q_ws=q_ws)
    >>> (np.degrees(cal.installation_angles_rad).round(9) + 0.0).tolist(), float(cal.residual_rad.max()) < 1e-12
    ([1.0, 0.0, 0.0], True)
    >>> body = apply_installation(cfg, cal.q_hat, q_ws=q_ws)              # Eq 10: the body attitude back
    >>> bool(rotations.quat_angle_between(body.q_body, q_wb).max() < 1e-9)
    True
    """
    checked = _positions_record(config, positions_rad, dt_s, q_ws, gyro_rad_s, accel_m_s2, q0, rests)
    # ---- trusted inside
    return _calibrate(config, *checked, sigma=sigma)


def verify_installation(config: InstallationConfig, q_hat, positions_rad, dt_s: float, *, q_ws=None,
                        gyro_rad_s=None, accel_m_s2=None, q0=None, rests=None) -> InstallationCalibration:
    """A calibration ``q_hat`` checked on a separate six-position run: the same steps, Q̂ given, not fitted.

    Steps 1–5 of :func:`calibrate_installation` (sensor attitude, zeroing by the config, rests,
    middle-section means, matching) on the verification record, then Eq 10 at its positions; no
    gate refuses (the verification measures how well ``q_hat`` does). ``condition`` is that of
    the verification positions.

    Parameters
    ----------
    config : InstallationConfig
        As for :func:`calibrate_installation` (``zero_at_first_sample=False`` for a record already
        zeroed at its session's start, §4.1).
    q_hat : array_like, shape (4, 4) or (T, 4, 4)
        The calibration (Q̂ of :func:`calibrate_installation`), finite.
    positions_rad, dt_s, q_ws, gyro_rad_s, accel_m_s2, q0, rests :
        The verification run, as for :func:`calibrate_installation`.

    Returns
    -------
    InstallationCalibration
        ``q_hat`` as given; ``euler_before_rad``/``euler_after_rad`` the Eq 8 angles of the
        verification rest means before and after Eq 10, ``residual_rad`` their distance from
        the references.

    References
    ----------
    wang2023cja §4.1 (separate verification run), Eq 10.

    Examples
    --------
    A sensor mounted without error, verified with the identity (no calibration needed):

    >>> import numpy as np
    >>> from mtcal.core.profiles import trajectory_from_euler_zxy
    >>> from mtcal.methods.six_position import schedule_profile, six_positions_rad
    >>> q_ws = trajectory_from_euler_zxy(schedule_profile(six_positions_rad(), fs_hz=100.0)).q_wb
    >>> ver = verify_installation(InstallationConfig.paper(), np.eye(4), six_positions_rad(), 0.01, q_ws=q_ws)
    >>> float(ver.residual_rad.max()) < 1e-12, ver.matched.tolist()
    (True, [1, 2, 3, 4, 5, 6])
    """
    mat, refs, dt, q, gyro, accel, q0, rests = _positions_record(config, positions_rad, dt_s, q_ws, gyro_rad_s,
                                                                 accel_m_s2, q0, rests, q_hat)
    return _calibrate(config, refs, dt, q, gyro, accel, q0, rests, q_hat=mat)


# --------------------------------------------------------------------------- a session of runs
@dataclass(frozen=True)
class SessionPiece:
    """One block of a session's trials for :func:`measure_session`.

    Attributes
    ----------
    rows : slice
        The block's trial rows of the session's records (step 1).
    reference_rad : array_like, shape (K, 3) or (t, K, 3)
        The reference ``[ψ, θ, γ]`` fed to the block's calibration (rad, Eq 8/9 frame), K ≥ 4; per
        trial (t = the block's trials) when each trial's mechanism stood at its own angles.
    fraction : float
        Middle fraction of each rest averaged, (0, 1] (the config's other settings hold for every block);
        also picks the sweeps' hold windows (:attr:`SessionSweep.holds`).
    hold_errors_rad : mapping, optional
        Sweep name → (t, holds) angle error of the mechanism at each hold of that sweep (truth − command,
        rad), subtracted from the block's hold means; default none.
    trace_row : int, optional
        A row of the block (0 … t−1) whose full sweep error series are returned
        (:attr:`SessionMeasurement.traces`).
    """

    rows: slice
    reference_rad: np.ndarray
    fraction: float
    hold_errors_rad: dict | None = None
    trace_row: int | None = None


@dataclass(frozen=True)
class SessionSweep:
    """A sweep of the session scored after the calibration by :func:`measure_session`.

    The sweeps of wang2023cja's turntable (AoA and roll, §4.1: Tables 5–8) and wind-off wind tunnel
    (AoA, §4.2: Tables 9, 11): the attitude over ``span`` before and after Eq 10 compared with its
    reference (Eq 8 angles, wrapped errors), averaged over each hold of angle ``channel``, and MaxAE /
    RMSE of the ``scored_channels`` over the whole span.

    Attributes
    ----------
    name : str
        The sweep's name (the key of its scores).
    span : slice
        The sweep's samples of the session (step 1).
    reference_rad : ndarray, shape (n, 3)
        Reference Eq 8 angles ``[ψ, θ, γ]`` (rad) at each sample of the span, shared by the trials.
    channel : {0, 1, 2}
        The angle averaged at the holds.
    scored_channels : tuple of int
        The angles whose MaxAE and RMSE over the span are reported.
    holds : mapping
        Averaging fraction → sequence of hold windows (slices relative to the span), one entry for each
        fraction of the session's pieces.
    decimation : int
        Every ``decimation``-th sample of every trial's error series is kept (float32, ensemble figures).
    """

    name: str
    span: slice
    reference_rad: np.ndarray
    channel: int
    scored_channels: tuple
    holds: dict
    decimation: int = 20

    @cached_property
    def table(self) -> np.ndarray:
        """The reference's angles with their cosines and sines (:func:`mtcal.core.montecarlo.truth_table`),
        found once per sweep."""
        return montecarlo.truth_table(np.ascontiguousarray(self.reference_rad, dtype=float)[None])[0]


@dataclass(frozen=True)
class SessionMeasurement:
    """Outcome of :func:`measure_session` and :func:`measure_simulated_session`.

    Attributes
    ----------
    q_ws : ndarray (T, N, 4)
        The session's QNCF attitude (sensor → world), zeroed at the session's first sample (§4.1).
    calibrations : tuple of InstallationCalibration
        Per piece, the six-position calibration of the calibration run (trial axis t).
    verifications : tuple of InstallationCalibration or None
        Per piece, the verification run measured with that Q̂ (None without a verification run).
    sweeps : tuple of dict or None
        Per piece, sweep name → its scores (None without sweeps): ``"reference"`` (holds,) the reference's
        hold means of the averaged angle; for ``state`` in ``before``/``after`` (Eq 10): ``"{state}_mean"``
        (t, holds) hold means minus the piece's hold errors, ``"{state}_maxae_{c}"`` and ``"{state}_rmse_{c}"``
        (t,) of each scored angle ``c``, ``"{state}_err_dec"`` (t, ⌈n/decimation⌉, 3) float32 decimated
        errors (all rad).
    traces : tuple of dict or None
        Per piece, ``"{name}_{state}_err"`` (n, 3): the full error series of its ``trace_row`` ({} without one;
        None without sweeps).
    applied : AppliedMeasurement or None
        The later runs measured with the pieces' Q̂ (:func:`measure_simulated_session`'s ``applied``).
    """

    q_ws: np.ndarray
    calibrations: tuple
    verifications: tuple
    sweeps: tuple | None = None
    traces: tuple | None = None
    applied: AppliedMeasurement | None = None


def _score_sweeps(sweeps, q_ws, q_hat, fraction: float, hold_errors, trace_row) -> tuple[dict, dict]:
    """Each sweep's scores (:attr:`SessionMeasurement.sweeps`) of one piece's attitudes ``q_ws`` (t, N, 4) with
    its Q̂ (t, 4, 4), and the full error series of ``trace_row``. The errors of
    :func:`mtcal.core.montecarlo.channel_errors_before_after` are finite (checked there), so MaxAE and RMSE are
    ``max(|e|)`` and ``sqrt(mean(e²))`` without the metrics' validation copy and NaN mask (the same numbers)."""
    scores, trace = {}, {}
    for sw in sweeps:
        holds = sw.holds[fraction]
        before, after, errs = montecarlo.channel_errors_before_after(q_ws[:, sw.span], q_hat, sw.reference_rad,
                                                                     sw.channel, sw.table)
        s = {"reference": np.array([sw.reference_rad[h, sw.channel].mean() for h in holds])}
        for state, angle in (("before", before), ("after", after)):
            means = np.stack([angle[:, h].mean(axis=1) for h in holds], axis=1)
            s[f"{state}_mean"] = means if hold_errors is None else means - hold_errors[sw.name]
        del before, after
        for state in ("before", "after"):
            err = errs[state]
            for c in sw.scored_channels:
                e = err[..., c]
                s[f"{state}_maxae_{c}"], s[f"{state}_rmse_{c}"] = np.max(np.abs(e), axis=-1), np.sqrt(np.mean(e**2, axis=-1))
            s[f"{state}_err_dec"] = err[:, ::sw.decimation].astype(np.float32)
            if trace_row is not None:
                trace[f"{sw.name}_{state}_err"] = err[trace_row].copy()
        scores[sw.name] = s
    return scores, trace


def _session_record(shapes, dt_s, calibration_run, verification_run, reference_rad, pieces, sweeps) -> tuple:
    """The edge of :func:`measure_session` and :func:`measure_simulated_session`: every input checked once, the
    records by their ``shapes`` (gyro's, accel's) before they are read (their type by the caller; their values
    are scanned by the QNCF's kernel as it filters). Returns ``(dt, calibration run, verification run,
    verification references or None, [(rows, positions, q_ref, fraction, hold errors, trace row), …],
    sweeps)``; the config is checked by the caller."""
    pieces = list(pieces)
    if not pieces or not all(isinstance(piece, SessionPiece) for piece in pieces):
        raise TypeError(f"pieces must be a non-empty sequence of SessionPiece, got {[type(p).__name__ for p in pieces]}")
    if verification_run is not None and reference_rad is None:
        raise ValueError("a verification run needs reference_rad: the positions it is measured against")
    # the references and their Eq 9 attitudes (K >= 4): each piece's, then the verification's
    sources = [(piece.reference_rad, (2, 3)) for piece in pieces]
    if verification_run is not None:
        sources.append((reference_rad, 2))
    refs = [_references(positions, ndim=ndim) for positions, ndim in sources]
    ver_refs = refs.pop() if verification_run is not None else None
    shape, accel_shape = (tuple(x) for x in shapes)
    if len(shape) != 3 or shape[-1] != 3 or shape != accel_shape or 0 in shape:
        raise ValueError(f"gyro_rad_s and accel_m_s2 must be stacked records of one shape (T, N, 3), got "
                         f"{shape} and {accel_shape}")
    dt = sample_interval(dt_s)
    fractions = [positive_scalar(piece.fraction, "a piece's fraction") for piece in pieces]
    trials, n = shape[:2]
    spans = [(calibration_run, "calibration_run", n, "samples")]
    if verification_run is not None:
        spans.append((verification_run, "verification_run", n, "samples"))
    spans += [(piece.rows, "a piece's rows", trials, "trials") for piece in pieces]
    sweeps = list(sweeps)
    if not all(isinstance(sw, SessionSweep) for sw in sweeps):
        raise TypeError(f"sweeps must be a sequence of SessionSweep, got {[type(sw).__name__ for sw in sweeps]}")
    spans += [(sw.span, f"sweep {sw.name!r}'s span", n, "samples") for sw in sweeps]
    for run, name, size, unit in spans:
        if not _is_window(run, size):
            raise ValueError(f"{name} must be a slice (start < stop, step 1) within the {size} {unit} of the "
                             f"records, got {run!r}")
    sweeps = [_sweep(sw, fractions) for sw in sweeps]
    checked = []
    for piece, (pos, q_ref), fraction in zip(pieces, refs, fractions):
        rows = piece.rows.stop - piece.rows.start
        if pos.ndim == 3 and pos.shape[0] != rows:
            raise ValueError(f"a piece's reference_rad of shape {pos.shape} needs {pos.shape[0]} rows, got "
                             f"{piece.rows}")
        if fraction > 1:
            raise ValueError(f"a piece's fraction must be in (0, 1], got {fraction}")
        hold_errors = None
        if piece.hold_errors_rad is not None:
            hold_errors = {sw.name: float64_array(piece.hold_errors_rad[sw.name], "a piece's hold_errors_rad")
                           for sw in sweeps if sw.name in piece.hold_errors_rad}
            for sw in sweeps:
                shape = (rows, len(sw.holds[fraction]))
                if hold_errors.get(sw.name, np.empty(0)).shape != shape:
                    raise ValueError(f"a piece's hold_errors_rad must hold sweep {sw.name!r} of shape {shape}, got "
                                     f"{getattr(hold_errors.get(sw.name), 'shape', None)}")
        trace_row = piece.trace_row
        if trace_row is not None and (not isinstance(trace_row, (int, np.integer)) or not 0 <= trace_row < rows):
            raise ValueError(f"a piece's trace_row must be a row of its {rows} trials, got {trace_row!r}")
        checked.append((slice(piece.rows.start, piece.rows.stop), pos, q_ref, fraction, hold_errors,
                        None if trace_row is None else int(trace_row)))
    ver_run = None if verification_run is None else slice(verification_run.start, verification_run.stop)
    return dt, slice(calibration_run.start, calibration_run.stop), ver_run, ver_refs, checked, sweeps


def _sweep(sw: SessionSweep, fractions) -> SessionSweep:
    """A sweep checked at the edge of :func:`measure_session` (its span by the caller): the reference (n, 3)
    finite, the channels, a hold list within the span for every fraction of the pieces, the decimation."""
    n = sw.span.stop - sw.span.start
    ref = float64_array(sw.reference_rad, f"sweep {sw.name!r}'s reference_rad")
    if ref.shape != (n, 3) or not np.isfinite(ref).all():
        raise ValueError(f"sweep {sw.name!r}'s reference_rad must be finite, of shape ({n}, 3), got {ref.shape}")
    channels = (sw.channel, *tuple(sw.scored_channels))
    if not all(isinstance(c, (int, np.integer)) and 0 <= c < 3 for c in channels):
        raise ValueError(f"sweep {sw.name!r}'s channel and scored_channels must be 0, 1 or 2, got {channels}")
    if not isinstance(sw.decimation, (int, np.integer)) or sw.decimation < 1:
        raise ValueError(f"sweep {sw.name!r}'s decimation must be an integer >= 1, got {sw.decimation!r}")
    for fraction in dict.fromkeys(fractions):
        holds = sw.holds.get(fraction) if hasattr(sw.holds, "get") else None
        if not holds or not all(_is_window(h, n) for h in holds):
            raise ValueError(f"sweep {sw.name!r}'s holds must give, for fraction {fraction}, hold windows (slices "
                             f"within its {n} samples), got {holds!r}")
    return sw if ref is sw.reference_rad else replace(sw, reference_rad=ref)


def measure_session(config: InstallationConfig, gyro_rad_s, accel_m_s2, dt_s: float, *, calibration_run: slice,
                    pieces, verification_run: slice | None = None, reference_rad=None, sweeps=(),
                    map_pieces=None) -> SessionMeasurement:
    """A power-on session of stacked records measured once: the QNCF, the calibration run, the verification run.

    The session's measurement in a turntable or wind-tunnel Monte Carlo (wang2023cja §3.2, §4.1):
    one QNCF over every trial (its cost is the loop over time, so a stack of T trials costs about one
    run), the session zeroed once at its first sample (§4.1, ``config.zero_at_first_sample``; in place: no
    copy); then, piece by piece (a block of trial rows with the reference fed to its calibration and its
    averaging fraction), the six-position
    calibration of the calibration run (Eq 13, as :func:`calibrate_installation` with rests found from
    the gyro) and, with ``verification_run``, that run measured with Q̂ given
    (:func:`verify_installation`): one methods-level call per piece
    (:func:`mtcal.methods.six_position.calibrate_session`); then each of ``sweeps`` scored with that Q̂
    (:class:`SessionSweep`: hold means, MaxAE and RMSE before and after Eq 10).

    Checked once here (types, shapes, spans, references, fractions); the QNCF's kernel scans the records'
    values as it filters; everything below trusts them.

    Parameters
    ----------
    config : InstallationConfig
        The QNCF's parameters (``qncf_params``), the rest detector, the matching window, the gates (a
        Monte Carlo: :meth:`InstallationConfig.monte_carlo`); ``fraction`` is each piece's.
    gyro_rad_s, accel_m_s2 : ndarray, shape (T, N, 3)
        The session's records (rad/s, m/s²), float64; read, not modified (a C-contiguous stack is used as
        it is: no copy).
    dt_s : float
        Sample interval (s), ≤ 1 s.
    calibration_run : slice
        The calibration run's samples.
    pieces : sequence of SessionPiece
        The blocks of trial rows (each with its own reference and fraction).
    verification_run : slice, optional
        The verification run's samples (a separate six-position run after the calibration run).
    reference_rad : array_like, shape (K, 3), optional
        The positions the verification run is measured against (rad), needed with ``verification_run``.
    sweeps : sequence of SessionSweep, optional
        The sweeps scored after the calibration (each piece's rows with its own Q̂ and fraction).
    map_pieces : callable, optional
        ``map_pieces(fn, items)`` → ``[fn(x) for x in items]`` in item order, e.g. spread over threads (each
        piece writes nothing shared: the numbers do not depend on it); default one after the other.

    Returns
    -------
    SessionMeasurement

    Raises
    ------
    TypeError, ValueError
        A bad input (the message names it); a record with non-finite values or a gyro out of range
        (the QNCF's kernel).

    References
    ----------
    wang2023cja §3.2 (procedure, Eq 13–15), §4.1 (zeroed start, separate verification run), Eq 5–8 (QNCF), Eq 10.

    Examples
    --------
    Two trials of a sensor mounted without error, calibrated and verified on two six-position runs:

    >>> import numpy as np
    >>> from mtcal.core.profiles import join_profiles, trajectory_from_euler_zxy
    >>> from mtcal.core.simulate import ImuErrorModel, simulate_imu
    >>> from mtcal.methods.six_position import schedule_profile, six_positions_rad
    >>> pos = six_positions_rad()
    >>> run = schedule_profile(pos, rate_rad_s=np.radians(60.0), fs_hz=100.0)
    >>> prof, (cal_run, ver_run) = join_profiles([run, run])
    >>> rec = simulate_imu(trajectory_from_euler_zxy(prof), ImuErrorModel())
    >>> gyro, accel = np.stack([rec.gyro_rad_s] * 2), np.stack([rec.accel_m_s2] * 2)
    >>> m = measure_session(InstallationConfig.monte_carlo(), gyro, accel, 0.01, calibration_run=cal_run,
    ...                     verification_run=ver_run, reference_rad=pos, pieces=[SessionPiece(slice(0, 2), pos, 0.5)])
    >>> m.q_ws.shape, m.calibrations[0].q_hat.shape, bool(m.verifications[0].residual_rad.max() < 1e-3)
    ((2, 6816, 4), (2, 4, 4), True)

    The verification run scored as a sweep: its pitch averaged over the middle half of each rest (the
    schedule's rests are its even segments: eight, the start and end rests included), and the full error
    series of the piece's first trial:

    >>> seg = prof.segment[ver_run]
    >>> rests = [np.flatnonzero(seg == s) for s in np.unique(seg[seg % 2 == 0])]
    >>> holds = six_position.middle_slices([slice(int(r[0]), int(r[-1]) + 1) for r in rests], 0.5)
    >>> sweep = SessionSweep("verification", ver_run, prof.angle_rad[ver_run], 1, (1,), {0.5: holds})
    >>> m = measure_session(InstallationConfig.monte_carlo(), gyro, accel, 0.01, calibration_run=cal_run,
    ...                     pieces=[SessionPiece(slice(0, 2), pos, 0.5, trace_row=0)], sweeps=[sweep])
    >>> s = m.sweeps[0]["verification"]
    >>> s["after_mean"].shape, bool(np.abs(s["after_mean"] - s["reference"]).max() < 1e-3)
    ((2, 8), True)
    >>> m.traces[0]["verification_after_err"].shape, s["after_err_dec"].dtype
    ((3408, 3), dtype('float32'))
    """
    gyro, accel = float64_array(gyro_rad_s, "gyro_rad_s"), float64_array(accel_m_s2, "accel_m_s2")
    return _measure(config, (gyro.shape, accel.shape), lambda: (gyro, accel), dt_s, calibration_run, pieces,
                    verification_run, reference_rad, sweeps, map_pieces)


def measure_simulated_session(config: InstallationConfig, source: RecordSource, blocks, groups, *,
                              calibration_run: slice, pieces, verification_run: slice | None = None,
                              reference_rad=None, sweeps=(), applied: AppliedRuns | None = None,
                              map_pieces=None) -> SessionMeasurement:
    """:func:`measure_session` of simulated records the procedure pulls from ``source`` once its inputs are checked.

    The Monte Carlo form of the session's measurement: the study describes its blocks of trials
    (:class:`mtcal.core.simulate.RecordPiece`: sensor, generator, truth tilt, bias step, load tilt) in
    a :class:`mtcal.core.simulate.RecordSource`; this procedure checks the config and the session's
    runs, pieces and sweeps, asks the source for the records of ``blocks`` (stacked in that order, filled
    group by group of ``groups`` on ``map_pieces``: :meth:`~mtcal.core.simulate.RecordSource.fill`), then
    measures them as :func:`measure_session` does (the records are simulated: trusted). The numbers are
    those of :func:`measure_session` on the same records, bit for bit.

    Parameters
    ----------
    config : InstallationConfig
        As for :func:`measure_session`.
    source : mtcal.core.simulate.RecordSource
        The session's simulated blocks; its ``dt_s`` is the sample interval.
    blocks : sequence of int
        The source's blocks measured, stacked in this order (the trial rows of ``pieces`` refer to the stack).
    groups : sequence of sequence of int
        A partition of the positions ``0 … len(blocks) − 1``: blocks filled together (noise drawn once where
        shared).
    calibration_run, pieces, verification_run, reference_rad, sweeps, map_pieces
        As for :func:`measure_session` (``map_pieces`` also spreads the groups' filling).
    applied : AppliedRuns, optional
        Later runs of the session on records of their own, each measured with its piece's Q̂ after the
        calibration, as :func:`measure_applied_runs` does (:attr:`SessionMeasurement.applied`; wang2023cja §4.2:
        the wind-on groups after the wind-off calibration).

    Returns
    -------
    SessionMeasurement

    References
    ----------
    wang2023cja §3.2, §4.1 (as :func:`measure_session`).

    Examples
    --------
    >>> import numpy as np
    >>> from mtcal.core.profiles import join_profiles, trajectory_from_euler_zxy
    >>> from mtcal.core.simulate import ImuErrorModel, RecordPiece, RecordSource
    >>> from mtcal.methods.six_position import schedule_profile, six_positions_rad
    >>> pos = six_positions_rad()
    >>> run = schedule_profile(pos, rate_rad_s=np.radians(60.0), fs_hz=100.0)
    >>> prof, (cal_run, ver_run) = join_profiles([run, run])
    >>> q_wb = trajectory_from_euler_zxy(prof).q_wb
    >>> source = RecordSource(prof.time_s, q_wb, [RecordPiece(2, ImuErrorModel(), None)], 0.01)
    >>> m = measure_simulated_session(InstallationConfig.monte_carlo(), source, [0], [[0]], calibration_run=cal_run,
    ...                               verification_run=ver_run, reference_rad=pos,
    ...                               pieces=[SessionPiece(slice(0, 2), pos, 0.5)])
    >>> m.calibrations[0].q_hat.shape, bool(m.verifications[0].residual_rad.max() < 1e-3)
    ((2, 4, 4), True)
    """
    blocks, groups, shape = _source_blocks(source, blocks, groups)
    return _measure(config, (shape, shape), lambda: source.fill(blocks, groups, map_pieces), source.dt_s,
                    calibration_run, pieces, verification_run, reference_rad, sweeps, map_pieces, applied)


def _measure(config, shapes, records, dt_s, calibration_run, pieces, verification_run, reference_rad, sweeps,
             map_pieces, applied=None) -> SessionMeasurement:
    """:func:`measure_session` once the records' type is known: the inputs checked (their ``shapes``), then the
    records taken (``records()`` → gyro, accel) and measured."""
    if not isinstance(config, InstallationConfig):
        raise TypeError(f"config must be an InstallationConfig, got {type(config).__name__}")
    settings = _fit_settings(config)
    zero = settings.pop("zero")                    # the session is zeroed once, here
    dt, cal_run, ver_run, ver_refs, checked, sweeps = _session_record(
        shapes, dt_s, calibration_run, verification_run, reference_rad, pieces, sweeps)
    if applied is not None:
        applied = _applied_runs(applied, [rows.stop - rows.start for rows, *_ in checked])
    gyro, accel = records()
    # ---- trusted inside: one QNCF (the later runs' records: one more, in the same pass), the session zeroed once at
    #      its first sample (in place), one methods-level call per piece, then its sweeps and later runs with its Q̂
    q_ws = qncf_trusted(gyro, accel, dt, config.qncf_params, return_euler=False).q_ws
    later, later_runs = None, ()
    if applied is not None:
        source, blocks, groups, later_runs = applied
        later = qncf_trusted(*source.fill(blocks, groups, map_pieces), source.dt_s, config.qncf_params,
                             return_euler=False)
    if zero:
        q_ws = rotations.relative_to_initial(q_ws, out=q_ws)
    ver_pos, ver_q_ref = (None, None) if ver_refs is None else ver_refs

    def measure(item):
        i, (rows, pos, q_ref, fraction, hold_errors, trace_row) = item
        cal, ver = six_position.calibrate_session(
            q_ws[rows, cal_run], pos, q_ref, dt, gyro_calibration=gyro[rows, cal_run],
            q_verification=None if ver_run is None else q_ws[rows, ver_run],
            gyro_verification=None if ver_run is None else gyro[rows, ver_run], verification_positions_rad=ver_pos,
            verification_q_reference=ver_q_ref, **{**settings, "fraction": fraction})
        scored = _score_sweeps(sweeps, q_ws[rows], cal.q_hat, fraction, hold_errors, trace_row) if sweeps else None
        read = _read_runs(later, [(k, run) for k, run in enumerate(later_runs) if run[1] == i], cal.q_hat)
        return cal, ver, scored, read

    items = list(enumerate(checked))
    measured = [measure(p) for p in items] if map_pieces is None else list(map_pieces(measure, items))
    if applied is not None:
        read = {k: r for *_, piece_read in measured for k, r in piece_read.items()}
        applied = AppliedMeasurement(tuple(read[k][0] for k in range(len(later_runs))), later.gate,
                                     tuple(read[k][1] for k in range(len(later_runs))))
    return SessionMeasurement(q_ws, tuple(m[0] for m in measured),
                              None if ver_run is None else tuple(m[1] for m in measured),
                              None if not sweeps else tuple(m[2][0] for m in measured),
                              None if not sweeps else tuple(m[2][1] for m in measured), applied)


# --------------------------------------------------------------------------- later runs with a calibration
@dataclass(frozen=True)
class AppliedRun:
    """A later run of a session, on records of its own, measured with a calibration by :func:`measure_applied_runs`.

    Attributes
    ----------
    rows : slice
        The run's trial rows of the stacked records (step 1).
    q_hat : array_like, shape (t, 4, 4) or None
        Q̂ (Eq 10) of each row (t = the run's trials): the calibration of the session it belongs to (None
        within :func:`measure_simulated_session`: the Q̂ of its ``piece``).
    holds : sequence of slice
        Hold windows (samples of the run) where its calibrated pitch is averaged.
    samples : int
        The run's own length N_run ≤ the stack's (beyond it the records are held at their last sample).
    trace_row : int, optional
        A row of the run (0 … t−1) whose calibrated pitch series (zeroed at every sample), AMD percentage and
        gate are returned (:attr:`AppliedMeasurement.traces`).
    piece : int, optional
        Within :func:`measure_simulated_session` (:class:`AppliedRuns`): the session piece whose Q̂ measures it
        (its trials, in row order).
    """

    rows: slice
    q_hat: np.ndarray | None
    holds: tuple
    samples: int
    trace_row: int | None = None
    piece: int | None = None


@dataclass(frozen=True)
class AppliedRuns:
    """Later runs of a session on records of their own (``source``'s ``blocks`` filled in ``groups``), measured by
    :func:`measure_simulated_session` after its calibration: each run's ``piece`` names the session piece whose Q̂
    (one per trial, in row order) it is measured with (its ``q_hat`` None)."""

    source: RecordSource
    blocks: tuple
    groups: tuple
    runs: tuple


@dataclass(frozen=True)
class AppliedMeasurement:
    """Outcome of :func:`measure_applied_runs`.

    Attributes
    ----------
    hold_pitch_rad : tuple of ndarray
        Per run, (t, holds): the Eq 8 pitch after Eq 10 with the run's Q̂, the run zeroed at its first sample
        (§4.1), averaged over each hold (rad).
    gate : ndarray, shape (T, N) of bool
        The QNCF's AMD gate (accelerometer used) at every sample of every stacked row.
    traces : tuple of dict
        Per run, ``"pitch_rad"``, ``"amd_pct"``, ``"gate"`` (N_run,) of its ``trace_row`` ({} without one).
    """

    hold_pitch_rad: tuple
    gate: np.ndarray
    traces: tuple


def measure_applied_runs(config: InstallationConfig, source: RecordSource, blocks, groups, *, runs,
                         map_pieces=None) -> AppliedMeasurement:
    """Later runs of a session measured with its calibration: Eq 10 on the QNCF attitude of records of their own.

    wang2023cja §4.2 (wind on, Table 10): after the wind-off calibration, each group's AoA sweep is measured
    with that session's Q̂. The runs' records are pulled from ``source`` (:meth:`mtcal.core.simulate.RecordSource.fill`
    of ``blocks`` in ``groups``, after every input is checked) and stacked as trials of one QNCF (its cost is
    the loop over time); each run is zeroed at its first sample (§4.1) where it is read (its holds, in place),
    and its pitch after Eq 10 averaged over each hold.

    Parameters
    ----------
    config : InstallationConfig
        The QNCF's parameters (``qncf_params``).
    source : mtcal.core.simulate.RecordSource
        The runs' simulated records; its ``dt_s`` is the sample interval.
    blocks, groups
        As for :func:`measure_simulated_session`.
    runs : sequence of AppliedRun
    map_pieces : callable, optional
        ``map_pieces(fn, items)`` spreading the groups' filling (the numbers do not depend on it).

    Returns
    -------
    AppliedMeasurement

    References
    ----------
    wang2023cja §4.2 (wind-on groups, Table 10), Eq 5–8 (QNCF), Eq 10, §4.1 (zeroed start).

    Examples
    --------
    A level, noise-free sensor without installation error holds pitch 0 at every hold:

    >>> from mtcal.core.simulate import ImuErrorModel, RecordPiece, RecordSource, Trajectory
    >>> t = np.arange(0.0, 4.0, 0.01)
    >>> level = Trajectory(t, np.tile([1.0, 0.0, 0.0, 0.0], (t.size, 1)))
    >>> source = RecordSource(None, None, [RecordPiece(2, ImuErrorModel(), None, trajectory=level)], 0.01)
    >>> m = measure_applied_runs(InstallationConfig.monte_carlo(), source, [0], [[0]],
    ...                          runs=[AppliedRun(slice(0, 2), np.stack([np.eye(4)] * 2), [slice(100, 200)], t.size, 0)])
    >>> m.hold_pitch_rad[0].shape, float(np.abs(m.hold_pitch_rad[0]).max()) < 1e-12, m.traces[0]["pitch_rad"].shape
    ((2, 1), True, (400,))
    """
    if not isinstance(config, InstallationConfig):
        raise TypeError(f"config must be an InstallationConfig, got {type(config).__name__}")
    source, blocks, groups, checked = _applied_runs(AppliedRuns(source, blocks, groups, runs), None)
    # ---- trusted inside: one QNCF over the stack, each run read with its Q̂
    res = qncf_trusted(*source.fill(blocks, groups, map_pieces), source.dt_s, config.qncf_params, return_euler=False)
    read = _read_runs(res, list(enumerate(checked)))
    return AppliedMeasurement(tuple(read[k][0] for k in range(len(checked))), res.gate,
                              tuple(read[k][1] for k in range(len(checked))))


def _applied_runs(applied: AppliedRuns, piece_rows) -> tuple:
    """:class:`AppliedRuns` checked before any record is read: ``(source, blocks, groups, [(rows, q_hat or piece,
    holds, samples, trace row), …])``; ``piece_rows`` (the session's pieces' trial counts, or None outside a session)
    says which the runs name."""
    if not isinstance(applied, AppliedRuns):
        raise TypeError(f"applied must be an AppliedRuns, got {type(applied).__name__}")
    source = applied.source
    blocks, groups, (trials, n, _) = _source_blocks(source, applied.blocks, applied.groups)
    runs = list(applied.runs)
    if not runs or not all(isinstance(run, AppliedRun) for run in runs):
        raise TypeError(f"runs must be a non-empty sequence of AppliedRun, got {[type(r).__name__ for r in runs]}")
    checked = []
    for run in runs:
        r = run.rows
        if not _is_window(r, trials):
            raise ValueError(f"a run's rows must be a slice (start < stop, step 1) within the {trials} trials of the "
                             f"records, got {r!r}")
        t = r.stop - r.start
        if piece_rows is None:
            q_hat = float64_array(run.q_hat, "a run's q_hat")
            if q_hat.shape != (t, 4, 4) or not np.isfinite(q_hat).all():
                raise ValueError(f"a run's q_hat must be finite, of shape ({t}, 4, 4), got {q_hat.shape}")
        else:
            q_hat = run.piece
            if (run.q_hat is not None or not isinstance(q_hat, (int, np.integer)) or not 0 <= q_hat < len(piece_rows)
                    or piece_rows[q_hat] != t):
                raise ValueError(f"a run of a session must name a piece (0 … {len(piece_rows) - 1}, q_hat None) with "
                                 f"its {t} trials, got piece {run.piece!r}")
        if not isinstance(run.samples, (int, np.integer)) or not 0 < run.samples <= n:
            raise ValueError(f"a run's samples must be an integer in [1, {n}], got {run.samples!r}")
        holds = list(run.holds)
        if not holds or not all(_is_window(h, run.samples) for h in holds):
            raise ValueError(f"a run's holds must be slices within its {run.samples} samples, got {holds!r}")
        if run.trace_row is not None and (not isinstance(run.trace_row, (int, np.integer)) or not 0 <= run.trace_row < t):
            raise ValueError(f"a run's trace_row must be a row of its {t} trials, got {run.trace_row!r}")
        checked.append((slice(r.start, r.stop), q_hat, holds, int(run.samples), run.trace_row))
    return source, blocks, groups, checked


def _read_runs(res, runs, q_hat=None) -> dict:
    """Later runs ``[(k, (rows, q_hat or piece, holds, samples, trace row)), …]`` of the QNCF result ``res`` read
    with their Q̂ (``q_hat`` when given, the same for every row of the piece, else the run's own): each zeroed at its
    first sample (§4.1) where read (its holds, in place: each sample's product is its own), its pitch after Eq 10
    averaged over each hold. Returns ``{k: (hold means (t, holds), trace)}``."""
    out = {}
    for k, (rows, own, holds, m, trace_row) in runs:
        mat = own if q_hat is None else q_hat
        q_r = res.q_ws[rows]
        trace = {}
        if trace_row is not None:           # the traced row zeroed at every sample, before its holds are
            q_t = q_r[trace_row:trace_row + 1].copy()
            rotations.relative_to_initial(q_t, n0=1, out=q_t)
            trace = {"pitch_rad": rotations.mapped_pitch_trusted(mat[trace_row:trace_row + 1], q_t[:, :m])[0],
                     "amd_pct": res.amd_pct[rows.start + trace_row, :m], "gate": res.gate[rows.start + trace_row, :m]}
        rotations.relative_to_initial(q_r, n0=1, out=q_r, windows=holds)
        out[k] = (np.stack([rotations.mapped_pitch_trusted(mat, q_r[:, h]).mean(axis=1) for h in holds], axis=1), trace)
    return out


def _is_window(w, size: int) -> bool:
    """``w`` is a slice ``start < stop``, step 1, within ``0 … size`` (a run, a block of rows, a hold)."""
    return (isinstance(w, slice) and w.step in (None, 1) and w.start is not None and w.stop is not None
            and 0 <= w.start < w.stop <= size)


def _source_blocks(source, blocks, groups) -> tuple[list, list, tuple]:
    """``blocks`` of ``source`` and their fill ``groups``, checked (:func:`measure_simulated_session`), and the shape
    (T, N, 3) of their stack (from the source's counts: nothing simulated)."""
    if not isinstance(source, RecordSource):
        raise TypeError(f"source must be a RecordSource, got {type(source).__name__}")
    blocks = [int(b) for b in blocks]
    if not blocks or not all(0 <= b < len(source.pieces) for b in blocks):
        raise ValueError(f"blocks must be a non-empty sequence of the source's {len(source.pieces)} blocks, got {blocks}")
    groups = [[int(p) for p in group] for group in groups]
    if sorted(p for group in groups for p in group) != list(range(len(blocks))):
        raise ValueError(f"groups must partition the positions 0 … {len(blocks) - 1} of blocks, got {groups}")
    return blocks, groups, (sum(source.trial_counts[b] for b in blocks), max(source.sample_counts[b] for b in blocks), 3)


def _q_hat(q_hat) -> np.ndarray:
    mat = as_float_array(q_hat, "q_hat")
    if mat.ndim not in (2, 3) or mat.shape[-2:] != (4, 4):
        raise ValueError(f"q_hat must be a finite 4x4 array or a stack (T, 4, 4), got shape {mat.shape}")
    return mat


def apply_installation(config: InstallationConfig, q_hat, dt_s: float | None = None, *, q_ws=None,
                       gyro_rad_s=None, accel_m_s2=None, q0=None) -> CalibratedAttitude:
    """Calibrated body attitude of a record, wang2023cja Eq 10: ``q_body = normalize(Q̂ q_sensor)``.

    The sensor attitude is made exactly as in :func:`calibrate_installation` (QNCF of the raw
    data, or ``q_ws`` as given) and zeroed at the first sample, then mapped by Q̂.

    Parameters
    ----------
    config : InstallationConfig
        ``qncf_params`` (raw data) and ``zero_at_first_sample``.
    q_hat : array_like, shape (4, 4) or (T, 4, 4)
        Q̂ from :func:`calibrate_installation` (dimensionless); finite.
    dt_s : float, optional
        Sample interval (s), ≤ 1 s; needed with raw data.
    q_ws : array_like, shape (N, 4) or (T, N, 4), optional
        Sensor attitude (sensor → world, scalar-first).
    gyro_rad_s, accel_m_s2 : array_like, shape (N, 3) or (T, N, 3), optional
        Raw data (rad/s, m/s²) for the QNCF when ``q_ws`` is not given.
    q0 : array_like, optional
        The QNCF's start attitude, as in :func:`calibrate_installation`.

    Returns
    -------
    CalibratedAttitude

    References
    ----------
    wang2023cja Eq 10; §4.1 (zeroed start).

    Examples
    --------
    >>> import numpy as np
    >>> q = np.tile([1.0, 0.0, 0.0, 0.0], (3, 1))
    >>> apply_installation(InstallationConfig.paper(), np.eye(4), q_ws=q).q_body.tolist()[0]
    [1.0, 0.0, 0.0, 0.0]
    """
    mat = _q_hat(q_hat)
    dt, q, gyro, accel, q0, stream = _application_record(config, dt_s, q_ws, gyro_rad_s, accel_m_s2, q0)
    if mat.ndim == 3 and (stream.ndim != 3 or stream.shape[0] != mat.shape[0]):
        raise ValueError(f"a stack of {mat.shape[0]} matrices needs a record with as many trials, "
                         f"got shape {stream.shape}")
    return _body_attitude(config, "relative", mat, None, q, gyro, accel, q0, dt)


def _body_attitude(config: InstallationConfig, mode: str, mat, c, q, gyro, accel, q0, dt,
                   units_checked: bool = False) -> CalibratedAttitude:
    """The body attitude of a checked record: the sensor attitude made once, then ``mode="relative"``
    Eq 10 on it zeroed (:func:`apply_installation`, ``mat`` Q̂) or ``mode="absolute"`` the mounting ``c``
    taken off, heading zeroed by the config (:func:`absolute_body_attitude`)."""
    q_made, q_s = _sensor_attitude(config, q, gyro, accel, q0, dt, zero=mode == "relative",
                                   units_checked=units_checked)
    if mode == "relative":
        q_b = rotations.apply_quat_matrix_trusted(mat, q_s)                     # Eq 10, then sign-continuous
        return CalibratedAttitude(q_body=rotations.make_continuous(q_b, axis=-2), q_sensor=q_s)
    q_s = rotations.make_continuous(q_made, axis=-2)
    q_b = rotations.hamilton(q_s, rotations.quat_conjugate(c))
    if config.zero_heading:
        yaw0 = rotations.euler_zxy_unchecked(q_b[..., :1, :])[..., 0]           # (..., 1)
        turn = np.zeros(yaw0.shape + (4,))
        turn[..., 0], turn[..., 3] = np.cos(-yaw0 / 2), np.sin(-yaw0 / 2)
        q_b = rotations.hamilton(turn, q_b)
        q_s = rotations.hamilton(turn, q_s)
    return CalibratedAttitude(q_body=rotations.make_continuous(q_b, axis=-2), q_sensor=q_s)


def _application_record(config, dt_s, q_ws, gyro_rad_s, accel_m_s2, q0):
    """The edge of :func:`apply_installation` and :func:`absolute_body_attitude`."""
    if not isinstance(config, InstallationConfig):
        raise TypeError(f"config must be an InstallationConfig, got {type(config).__name__}")
    dt = None if dt_s is None else sample_interval(dt_s)
    return (dt,) + _record(q_ws, gyro_rad_s, accel_m_s2, q0, q_ws is None, dt)


def mounting_from_q_hat(q_hat) -> np.ndarray:
    """Mounting quaternion ``q_bs = r*`` (4,) of Q̂'s nearest SO(4) matrix ``L(p) R(r)``.

    Examples
    --------
    >>> import numpy as np
    >>> from mtcal.core import rotations
    >>> c = rotations.mount_quaternion(np.radians([0.3, -0.2, 0.5]))
    >>> bool(np.allclose(mounting_from_q_hat(rotations.right_matrix(rotations.quat_conjugate(c))), c))
    True
    """
    mat = as_float_array(q_hat, "q_hat")
    if mat.shape != (4, 4):
        raise ValueError(f"q_hat must be a finite 4x4 array, got shape {mat.shape}")
    return _mounting(mat)


def _mounting(mat: np.ndarray) -> np.ndarray:
    """:func:`mounting_from_q_hat` of a checked 4x4 Q̂ (the trusted projection and factoring of
    :func:`mtcal.methods.constrained_fit.project_to_so4`)."""
    r = constrained_fit._factor(constrained_fit._project(mat))[1]
    q = r * np.array([1.0, -1.0, -1.0, -1.0])                                 # conjugate: q_bs = r*
    return q if q[0] >= 0 else -q


def absolute_body_attitude(config: InstallationConfig, q_bs, dt_s: float | None = None, *, q_ws=None,
                           gyro_rad_s=None, accel_m_s2=None, q0=None) -> CalibratedAttitude:
    """Gravity-referenced body attitude of a record: ``q_body = q_ws ⊗ q_bs*``, heading zeroed.

    Eq 10 (:func:`apply_installation`) gives the body attitude *relative to where the record
    starts* (§4.1: the turntable starts at its zero). A flight log starts anywhere — parked at
    a few degrees of pitch and roll — and relative angles then carry that start as an error.
    Here the sensor attitude is the QNCF's own (levelled from the accelerometer: pitch and roll
    referenced to gravity) or ``q_ws`` as given (its world frame must be z up), and the mounting
    ``q_bs`` (sensor = body ⊗ q_bs) is taken off on the right. Heading is not observable from
    gravity: with ``config.zero_heading`` the body's yaw at the first sample is set to 0 (a rotation
    about the world vertical, which leaves pitch and roll — Eq 8 ZXY — unchanged).

    Parameters
    ----------
    config : InstallationConfig
        ``qncf_params`` (raw data) and ``zero_heading`` (zero the body yaw at the first sample).
    q_bs : array_like, shape (4,)
        Mounting quaternion (scalar-first), e.g. ``InstallationCalibration.mounting_quaternion_q_bs``
        or :func:`mounting_from_q_hat`.
    dt_s, q_ws, gyro_rad_s, accel_m_s2, q0 :
        The sensor attitude or the raw data for the QNCF, as in :func:`apply_installation`.

    Returns
    -------
    CalibratedAttitude
        ``q_body`` (body → world, z-up world, heading zeroed) and ``q_sensor`` (the sensor
        attitude in the same world frame).

    References
    ----------
    wang2023cja Eq 1 (mounting), Eq 8/9 (yaw about z, pitch about x, roll about y).

    Examples
    --------
    >>> import numpy as np
    >>> from mtcal.core import rotations
    >>> q_wb = rotations.quat_from_euler_zxy(np.radians(30.0), np.radians(2.0), np.radians(-1.5))[None]
    >>> q_bs = rotations.mount_quaternion(np.radians([0.3, 0.8, -0.5]))
    >>> att = absolute_body_attitude(InstallationConfig.paper(), q_bs, q_ws=rotations.quat_multiply(q_wb, q_bs))
    >>> np.degrees(rotations.euler_zxy_from_quat(att.q_body)).round(9).tolist()   # heading zeroed
    [[0.0, 2.0, -1.5]]
    """
    c = unit_quaternion(q_bs, "q_bs")
    if c.shape != (4,):
        raise ValueError(f"q_bs must be one quaternion of shape (4,), got {c.shape}")
    dt, q, gyro, accel, q0, _ = _application_record(config, dt_s, q_ws, gyro_rad_s, accel_m_s2, q0)
    return _body_attitude(config, "absolute", None, c, q, gyro, accel, q0, dt)


def installation_angles_sigma(cal: InstallationCalibration, model: str = "eq13") -> np.ndarray:
    """1σ uncertainty (rad) of the installation angles ``[α1, α2, α3]`` from the fit covariance.

    :func:`mtcal.methods.six_position.angles_sigma` (the fit's least-squares covariance propagated
    through the SO(4) projection and the inverse of Eq 1) of a calibration; NaN when not estimable
    (K = 4 for Eq 13 leaves no degrees of freedom). :func:`calibrate_installation` with ``sigma=True``
    gives the same numbers as ``angles_sigma_rad``.

    Parameters
    ----------
    cal : InstallationCalibration
        One calibration (no trial axis).
    model : {"eq13", "so4", "mounting"}
        The model ``cal`` was fitted with.

    Returns
    -------
    ndarray (3,)
        1σ of ``[α1, α2, α3]`` (rad); NaN when not estimable.

    Examples
    --------
    The classic ±g set (no rotation about z) with the 3-parameter mounting model, noise-free:

    >>> import numpy as np
    >>> from mtcal.core import profiles, rotations
    >>> from mtcal.methods import six_position
    >>> pm_g = np.radians([[0, 0, 0], [0, 0, 180], [0, 90, 0], [0, -90, 0], [0, 0, 90], [0, 0, -90]])
    >>> truth = profiles.trajectory_from_euler_zxy(six_position.schedule_profile(pm_g, fs_hz=50.0))
    >>> mount = rotations.mount_quaternion(np.radians([0.5, 0.0, -0.2]))
    >>> cal = calibrate_installation(InstallationConfig(model="mounting"), pm_g, 1 / 50.0,
    ...                              q_ws=rotations.quat_multiply(truth.q_wb, mount))
    >>> bool(np.all(installation_angles_sigma(cal, "mounting") < 1e-9))       # no scatter, no uncertainty
    True
    """
    return six_position.angles_sigma(cal.q_sensor, cal.q_reference, cal.q_hat, model)


# --------------------------------------------------------------------------- whole logs (the CLI's procedures)
@dataclass(frozen=True)
class RefusalDiagnosis:
    """Per reference position the nearest rest of a refused calibration (zeroed sensor attitude).

    Attributes
    ----------
    nearest : list of slice
        For each position (K) the rest (sample slice) nearest to it.
    measured_rad : ndarray (K, 3)
        Eq 8 angles of that rest's middle-section mean (rad).
    distance_rad : ndarray (K,)
        Rotation angle between that rest and the position (rad).
    """

    nearest: list
    measured_rad: np.ndarray
    distance_rad: np.ndarray


@dataclass(frozen=True)
class RecordCalibration:
    """Outcome of :func:`calibrate_record`: what the procedure found, in the order it found it.

    Attributes
    ----------
    config : InstallationConfig
        The config as run (QNCF parameters of the log's rests).
    rests : list of slice
        The rests the positions are matched to.
    report : RestReport or None
        The rest detector's report (raw logs).
    units_check : dict or None
        :func:`mtcal.systems.plausibility.check_units` (raw logs).
    qncf : QncfLogSetup or None
        How the QNCF ran (raw logs).
    calibration : InstallationCalibration or None
        None when there are fewer rests than positions, or when refused.
    sigma_rad : ndarray (3,) or None
        1σ of the installation angles (:func:`installation_angles_sigma`).
    refusal : str or None
        The one-line refusal, with the likely convention mistake when one explains it.
    diagnosis : RefusalDiagnosis or None
        The nearest rest per position of a refusal looked into.
    mounting_euler_rad : ndarray (3,) or None
        Eq 8 yaw/pitch/roll of the mounting ``q_bs`` (rad): the sensor on the body.
    """

    config: InstallationConfig
    rests: list
    report: object = None
    units_check: dict | None = None
    qncf: object = None
    calibration: InstallationCalibration | None = None
    sigma_rad: np.ndarray | None = None
    refusal: str | None = None
    diagnosis: RefusalDiagnosis | None = None
    mounting_euler_rad: np.ndarray | None = None


class RecordRefused(ValueError):
    """A log refused after its rests were found (units check); ``report`` holds the rests for a figure."""

    def __init__(self, message: str, report):
        super().__init__(message)
        self.report = report


#: Refusals that mean "the rests do not match the positions" (a convention mistake is then looked for).
MISMATCH_MESSAGES = ("has no rest within", "Q_hat is not a calibration", "a rest does not match its reference")

#: Position-file mistakes tried on refusal: name → (transform of the positions in rad, what to do).
POSITION_MISTAKES = {
    "radians": (np.degrees, "the positions file holds radians: write degrees (yaw_deg, pitch_deg, roll_deg)"),
    "pitch sign flipped": (lambda p: p * [1.0, -1.0, 1.0], "negate pitch_deg (pitch is positive about +x, nose up)"),
    "roll sign flipped": (lambda p: p * [1.0, 1.0, -1.0], "negate roll_deg (roll is positive about +y)"),
    "yaw sign flipped": (lambda p: p * [-1.0, 1.0, 1.0], "negate yaw_deg (yaw is positive about +z, up)"),
    "pitch and roll swapped": (lambda p: p[:, [0, 2, 1]], "swap the pitch_deg and roll_deg columns "
                               "(pitch about x, roll about y: wang2023cja Eq 8/9)"),
}

#: Other quaternion conventions tried when a q0..q3 log matches no position: name → (transform, fix).
QUATERNION_CONVENTIONS = {
    "scalar-last (x, y, z, w)": (lambda q: q[:, [3, 0, 1, 2]],
                                 "map the scalar column to q0 with --columns q0=W,q1=X,q2=Y,q3=Z"),
    "conjugated (world -> sensor)": (lambda q: q * np.array([1.0, -1.0, -1.0, -1.0]),
                                     "give the sensor -> world attitude (negate q1..q3)"),
    "scalar-last and conjugated": (lambda q: q[:, [3, 0, 1, 2]] * np.array([1.0, -1.0, -1.0, -1.0]),
                                   "map the scalar column to q0 with --columns and negate q1..q3"),
}


def calibrate_record(config: InstallationConfig, positions_rad, dt_s: float, *, time_s=None, accel_m_s2=None,
                  gyro_rad_s=None, filter_gyro_rad_s=None, q_ws=None, gyro_unit_stated=None) -> RecordCalibration:
    """The whole ``mtcal calibrate`` measurement of one log: rests → units check → attitude → Eq 13 → diagnosis.

    The positions are checked once and made reference attitudes (Eq 9). A raw log (``gyro_rad_s`` and
    ``accel_m_s2``): rests by ``config.rest_detector`` (:func:`mtcal.systems.rests.find_rests`, which
    checks the arrays; with the paper's detector the calibration's rests are the §3.2 stillness of the
    gyro, as :func:`detect_rests` finds it), the gyro units checked against the accelerometer
    (:func:`mtcal.systems.plausibility.check_units`), the QNCF set from the rests
    (:func:`mtcal.systems.attitude.qncf_log_setup`) and run without a second tilt-rate scan (the units
    are checked). A q0..q3 log (``q_ws``, checked once): rests from the quaternion rate. Then one
    methods-level calibration from those rests (:func:`mtcal.methods.six_position.calibrate_from_rests`
    with the config's settings, trusted). A refusal meaning "the rests do not match the positions" is
    looked into: the convention mistake (a quaternion convention, FRD axes, radians, a sign, pitch/roll
    swapped, a late start) under which every position matches is named, and each position's nearest
    rest tabled from the rests' mean attitudes the refusal carries.

    Parameters
    ----------
    config : InstallationConfig
        The procedure's settings; ``config.rest_detector`` the raw log's rest detector (required for raw logs).
    positions_rad : array_like, shape (K, 3)
        Reference ``[ψ, θ, γ]`` (rad, Eq 8/9), K ≥ 4.
    dt_s : float
        Mean sample interval (s).
    time_s : array_like, shape (N,)
        Sample times (s).
    accel_m_s2, gyro_rad_s : array_like, shape (N, 3), optional
        Raw data (m/s², rad/s).
    filter_gyro_rad_s : array_like, shape (N, 3), optional
        The gyro for a fixed-step filter at ``dt_s`` (per-sample dt weighted); default ``gyro_rad_s``.
    q_ws : array_like, shape (N, 4), optional
        The logger's sensor attitude, when there is no raw data.
    gyro_unit_stated : str, optional
        The gyro unit the user stated (the units check warns instead of refusing).

    Returns
    -------
    RecordCalibration
        Too few rests: ``calibration`` None and no ``refusal`` (the caller words it from ``report``).

    Raises
    ------
    RecordRefused
        The units check refused the log (``report`` attached).

    References
    ----------
    wang2023cja §3.2, §4.1, Eq 13; see :func:`calibrate_installation`.
    """
    if not isinstance(config, InstallationConfig):
        raise TypeError(f"config must be an InstallationConfig, got {type(config).__name__}")
    settings = _fit_settings(config)
    pos, q_ref = _references(positions_rad)
    dt = sample_interval(dt_s)
    rep = chk = setup = None
    if gyro_rad_s is not None:
        # a raw log: the log's systems (rests, units check, QNCF set-up) check the arrays they read; the units
        # checked, the QNCF runs without its own tilt-rate scan (as estimate_attitude runs it)
        rep, found, chk, setup = _raw_record(config, dt, time_s, accel_m_s2, gyro_rad_s, filter_gyro_rad_s,
                                             gyro_unit_stated, paper_rests=config.rest_detector.detector == "paper")
        config = replace(config, qncf_params=setup.params)
        q = qncf_trusted(setup.gyro_rad_s, accel_m_s2, dt, setup.params, q0=setup.q0, return_euler=False).q_ws
    else:
        q = _logged_attitude(q_ws)
        found = six_position.still_rests(dt, config.min_rest_s, config.still_window_s, config.still_threshold_rad_s,
                                         q=q)
    done = dict(config=config, rests=found, report=rep, units_check=chk, qncf=setup)
    if len(found) < pos.shape[0]:
        return RecordCalibration(**done)
    # ---- trusted inside: the one methods-level calibration from the rests
    try:
        cal = six_position.calibrate_from_rests(q, pos, q_ref, dt, rests=found, sigma=True, **settings)
    except InstallationRefused as exc:
        return RecordCalibration(**done, **_refusal(settings, pos, q_ref, dt, found, q, exc, accel_m_s2, time_s,
                                                    logged=gyro_rad_s is None))
    return RecordCalibration(**done, calibration=cal, sigma_rad=cal.angles_sigma_rad,
                             mounting_euler_rad=rotations.euler_zxy_unchecked(cal.mounting_quaternion_q_bs))


def _logged_attitude(q_ws) -> np.ndarray:
    """A log's sensor attitude (N, 4), checked once."""
    q = unit_quaternion(q_ws, "q_ws", copy=False)
    if q.ndim != 2:
        raise ValueError(f"q_ws must have shape (N, 4), got {q.shape}")
    return q


def _raw_record(config, dt_s, time_s, accel_m_s2, gyro_rad_s, filter_gyro_rad_s, gyro_unit_stated, *,
                paper_rests: bool) -> tuple:
    """A raw record's rests, units check and QNCF set-up: ``(report, rests, units check, QncfLogSetup)``.

    ``paper_rests``: the rests returned are the §3.2 stillness of the gyro (:func:`detect_rests` on the
    gyro :func:`mtcal.systems.rests.find_rests` checked), else the report's.
    """
    filter_gyro = gyro_rad_s if filter_gyro_rad_s is None else filter_gyro_rad_s
    detector = config.rest_detector
    rep = rests_system.find_rests(accel_m_s2, dt_s, detector, gyro_rad_s=gyro_rad_s if detector.use_gyro else None,
                                  time_s=time_s)
    found = rep.rests
    if paper_rests:          # the §3.2 stillness of the gyro (detect_rests; find_rests checked the gyro)
        found = six_position.still_rests(dt_s, config.min_rest_s, config.still_window_s,
                                         config.still_threshold_rad_s, gyro_rad_s=np.asarray(gyro_rad_s, dtype=float))
    try:
        chk = plausibility.check_units(filter_gyro, accel_m_s2, dt_s, found, time_s=time_s,
                                       skip=plausibility.clipped_samples(gyro_rad_s)[0], unit_stated=gyro_unit_stated)
    except ValueError as exc:
        raise RecordRefused(str(exc), rep) from None
    return rep, found, chk, attitude.qncf_log_setup(filter_gyro, accel_m_s2, dt_s, rep, gyro_rad_s=gyro_rad_s)


def _refusal(settings: dict, pos, q_ref, dt, rests, q, exc: InstallationRefused, accel, time_s, *,
             logged: bool) -> dict:
    """A refused calibration of a log, looked into when it means "the rests do not match the positions":
    ``refusal`` (the one line, with the convention mistake under which every position matches, tried in the
    order of :func:`_mistakes`) and ``diagnosis`` (per position the nearest rest; not for a quaternion
    convention). ``q`` is the sensor attitude the refused calibration was given (not zeroed), ``exc`` its refusal
    (with the rests' mean attitudes)."""
    message = str(exc)
    tiny = np.max(np.abs(np.degrees(pos))) <= np.pi / 2 + 1e-9        # values that may be radians
    if not (any(m in message for m in MISMATCH_MESSAGES) or (tiny and "ill-conditioned" in message)):
        return {"refusal": message}
    hint = next((text for text, cand_pos, cand_q, cand_rests in _mistakes(pos, q, rests, accel, time_s, logged=logged)
                 if cand_pos is None or _fits(settings, cand_pos, dt, cand_q, cand_rests)), None)
    if hint is not None and hint.startswith(_CONVENTION_HINT):
        return {"refusal": f"{message}{hint}", "diagnosis": None}
    if hint is None and np.max(np.abs(pos)) <= np.pi / 2 + 1e-9 and np.max(np.abs(pos)) > 0:
        hint = ("; the positions are all within +-1.571 deg: if they are radians, write degrees "
                "(the table above shows what each rest measured)")
    elif hint is None:
        hint = ("; no single convention mistake (radians, sign, pitch/roll swap, FRD axes, start) explains it: "
                "see the table above")
    means = exc.rest_means                                                         # (R, 4), zeroed attitude
    dist = rotations.quat_angle_between(means[:, None, :], q_ref[None, :, :])      # (R, K)
    near = np.argmin(dist, axis=0)
    diagnosis = RefusalDiagnosis(nearest=[rests[int(r)] for r in near],
                                 measured_rad=rotations.euler_zxy_from_quat(means[near]),
                                 distance_rad=dist[near, np.arange(pos.shape[0])])
    return {"refusal": f"{message}{hint}", "diagnosis": diagnosis}


def _fits(settings: dict, positions_rad, dt, q, rests) -> bool:
    """Whether the calibration with ``settings`` accepts the positions on the sensor attitude ``q`` (checked:
    unit, ``rests`` within it)."""
    try:
        pos, q_ref = _references(positions_rad)
        six_position.calibrate_from_rests(q, pos, q_ref, dt, rests=rests, **settings)
    except ValueError:
        return False
    return True


_CONVENTION_HINT = "; the log's q0..q3 would match every position if they were"


def _mistakes(pos, q, rests, accel, time_s, *, logged: bool):
    """The convention mistakes a refused log is tried under, in order, as ``(hint, positions, attitude, rests)``
    (the hint is taken when the calibration accepts them; ``positions`` None: the accelerometer shows it, no fit):
    a q0..q3 log's quaternion conventions, FRD axes, the positions file's mistakes, a log that starts before the
    mechanism zero (the attitude zeroed at a later rest)."""
    if logged:
        for name, (fn, fix) in QUATERNION_CONVENTIONS.items():
            yield f"{_CONVENTION_HINT} {name}: {fix}", pos, fn(q), rests
    if accel is not None and rests:
        a0 = accel[rests[0]].mean(axis=0)
        if a0[2] < -0.5 * np.linalg.norm(a0):
            yield (f"; likely mistake: the sensor reads -g on z at its first rest (a = [{a0[0]:+.2f}, {a0[1]:+.2f}, "
                   f"{a0[2]:+.2f}] m/s^2): FRD/NED axes (z down)? mtcal expects x right, y forward, z up (+g on z "
                   f"when level); map FRD to it with --columns gyro_x=<gyro y>,gyro_y=<gyro x>,accel_x=<accel y>,"
                   f"accel_y=<accel x> --gyro-scale 1,1,-1 --accel-scale 1,1,-1"), None, None, None
            return
    for name, (fn, fix) in POSITION_MISTAKES.items():
        cand = fn(pos)
        if name == "radians" and np.max(np.abs(cand)) > 2 * np.pi:
            continue
        yield f"; likely mistake: {name} — every position matches after that change: {fix}", cand, q, rests
    for i, r in enumerate(rests[1:], start=1):
        shifted = [slice(x.start - r.start, x.stop - r.start) for x in rests[i:]]
        if len(shifted) >= pos.shape[0]:
            yield ("; likely mistake: the log does not start at the mechanism zero — with the attitude zeroed at the "
                   f"rest at {time_s[r.start]:.1f} s every position matches: trim the log to start at the zero "
                   "(the positions are relative to where the log starts)"), pos, q[r.start:], shifted


@dataclass(frozen=True)
class RecordApplication:
    """Outcome of :func:`apply_record`.

    Attributes
    ----------
    q_bs : ndarray (4,)
        The calibration's mounting (:func:`mounting_from_q_hat`).
    attitude : CalibratedAttitude
        Body and sensor attitude of the log.
    report, units_check, qncf :
        As in :class:`RecordCalibration` (raw logs; None for a q0..q3 log).
    start_euler_rad : ndarray (3,) or None
        ``mode="relative"``: Eq 8 angles of the body at the log's start (the first rest's accelerometer
        levelling, or the first q0..q3 sample) — the tilt the relative angles carry; else None.
    start_rest : slice or None
        The rest ``start_euler_rad`` was levelled at (None: the first sample of a q0..q3 log).
    mounting_euler_rad : ndarray (3,)
        Eq 8 yaw/pitch/roll of ``q_bs`` (rad).
    body_euler_rad, sensor_euler_rad : ndarray (N, 3)
        Eq 8 yaw/pitch/roll (rad) of ``attitude.q_body`` and ``attitude.q_sensor`` (what the command
        prints and writes, :func:`mtcal.core.rotations.euler_zxy_rows_trusted`).
    """

    q_bs: np.ndarray
    attitude: CalibratedAttitude
    mounting_euler_rad: np.ndarray
    body_euler_rad: np.ndarray
    sensor_euler_rad: np.ndarray
    report: object = None
    units_check: dict | None = None
    qncf: object = None
    start_euler_rad: np.ndarray | None = None
    start_rest: slice | None = None


def apply_record(config: InstallationConfig, q_hat, dt_s: float, *, mode: str = "absolute", time_s=None, accel_m_s2=None,
              gyro_rad_s=None, filter_gyro_rad_s=None, q_ws=None, gyro_unit_stated=None) -> RecordApplication:
    """The whole ``mtcal apply`` measurement of one log: rests → units check → attitude → body attitude.

    ``mode="absolute"``: :func:`absolute_body_attitude` with the mounting of ``q_hat``;
    ``mode="relative"``: :func:`apply_installation` (Eq 10) and the body's tilt at the start. ``q_hat`` is
    refused when it is farther than ``config.max_so4_distance`` from SO(4) (no calibration is).
    The log's arrays, and the :class:`RecordRefused` of a units check that refuses, as in
    :func:`calibrate_record`.

    References
    ----------
    wang2023cja Eq 1, Eq 10, §4.1.
    """
    if mode not in ("absolute", "relative"):
        raise ValueError(f"mode must be 'absolute' or 'relative', got {mode!r}")
    mat = _calibration_q_hat(q_hat, config.max_so4_distance)
    rep = chk = setup = None
    cfg, raw = config, (None, q_ws, None, None, None)
    if gyro_rad_s is not None:
        rep, _, chk, setup = _raw_record(config, dt_s, time_s, accel_m_s2, gyro_rad_s, filter_gyro_rad_s,
                                         gyro_unit_stated, paper_rests=False)
        cfg = replace(config, qncf_params=setup.params)
        raw = (dt_s, None, setup.gyro_rad_s, accel_m_s2, setup.q0)
    checked = _application_record(cfg, *raw)
    return _apply_record_attitude(cfg, mat, mode, checked, rep, chk, setup, accel_m_s2)


def _calibration_q_hat(q_hat, max_so4_distance: float) -> np.ndarray:
    """The edge of :func:`apply_record` for Q̂: a finite 4×4 array within ``max_so4_distance`` of SO(4) — the gate
    :func:`calibrate_record` refuses a fit by, so that a matrix that is no calibration (all zero, a zero row, a
    multiple of the identity) is refused instead of giving a mounting or an attitude."""
    mat = np.array(q_hat, dtype=float)
    if mat.shape != (4, 4):
        raise ValueError(f"q_hat must be a 4x4 array, got shape {mat.shape}")
    if not np.all(np.isfinite(mat)):
        raise ValueError("q_hat must be finite (no NaN or inf)")
    distance = float(constrained_fit.project_to_so4(mat).distance)
    if not distance <= max_so4_distance:
        raise ValueError(f"the calibration's q_hat is {distance:.4g} from the nearest rotation of quaternion space "
                         f"(SO(4)), more than {max_so4_distance:.4g}: it is not an installation calibration (mtcal "
                         f"calibrate refuses such a fit)")
    return mat


def _apply_record_attitude(cfg, mat, mode, checked, rep, chk, setup, accel) -> RecordApplication:
    """:func:`apply_record` from the checked record on: the mounting, the body attitude, the tilt at the start."""
    dt, q, gyro, acc, q0, _ = checked
    q_bs = _mounting(mat)
    done = dict(q_bs=q_bs, report=rep, units_check=chk, qncf=setup)
    att = _body_attitude(cfg, mode, mat, q_bs, q, gyro, acc, q0, dt, units_checked=chk is not None)
    start, q_s0 = None, None
    if mode == "relative" and accel is not None and rep is not None and rep.rests:
        start = rep.rests[0]
        q_s0 = rotations.level_quat_zxy(accel[start].mean(axis=0))
    elif mode == "relative" and q is not None:
        q_s0 = q[0]
    tilt = None if q_s0 is None else rotations.euler_zxy_from_quat(
        rotations.quat_multiply(q_s0, rotations.quat_conjugate(q_bs)))
    return RecordApplication(attitude=att, mounting_euler_rad=rotations.euler_zxy_unchecked(q_bs), start_euler_rad=tilt,
                             start_rest=start, body_euler_rad=rotations.euler_zxy_rows_trusted(att.q_body),
                             sensor_euler_rad=rotations.euler_zxy_rows_trusted(att.q_sensor), **done)
