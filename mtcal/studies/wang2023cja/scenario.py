"""wang2023cja scenarios: frozen dataclasses with the paper's defaults, and builders from parameters.

Every value carries a unit and a source (field ``metadata``). Notebooks put the values an
engineer would change in their parameters cell (:data:`TURNTABLE_DEFAULTS`,
:data:`WINDTUNNEL_DEFAULTS`, defaults = the paper's setting) and build the scenario once with
:func:`turntable_scenario` / :func:`windtunnel_scenario`, which validate every value (one-line
``ValueError`` naming the parameter and the valid range or choices).

The scenario's physical models live here too — the mount compliance
(:func:`compliance_trajectory`), the wind-tunnel mechanism (:func:`mechanism_actual`)
and the pitch-ratio identification from the printed Q(2,2) (:func:`identify_pitch_ratio`)
— so :mod:`.runs` imports this module and never the other way round.

References
----------
wang2023cja §3.2, §4.1 (turntable), §4.2 (wind tunnel) (full citation: :mod:`mtcal.studies.wang2023cja`).

Examples
--------
>>> sc = turntable_scenario(gyro_grade="industrial")
>>> sc.imu.label, sc.fs_hz
('gyro industrial, accel wang2023cja', 1000.0)
>>> turntable_scenario(fs_hz=-1.0)
Traceback (most recent call last):
...
ValueError: fs_hz must be a number in [100.0, 10000.0] Hz, got -1.0
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field, replace

import numpy as np

from mtcal.core import rotations
from mtcal.core.profiles import AngleProfile
from mtcal.core.rotations import mount_quaternion
from mtcal.core.simulate import Trajectory, gravity_lateral_axis, tilted_trajectory
from mtcal.core.sensor_grades import GRADES, sensor_spec
from mtcal.core.sensors import SensorSpec
from mtcal.core.units import ARCSEC, DEG, DEG_H, UG
from mtcal.core.validate import angle_pair_deg, choice, merge_parameters, number_in_range
from mtcal.filters.qncf import QncfParams
from mtcal.methods import quaternion_lsq, six_position
from .error_model import MOUNT_TYPE, ErrorModel

__all__ = ["SOURCES", "ImuSpec", "IMU_ASSUMPTIONS", "paper_imu", "TurntableScenario", "WindTunnelScenario", "TURNTABLE_DEFAULTS",
           "WINDTUNNEL_DEFAULTS", "turntable_scenario", "windtunnel_scenario", "windtunnel_geometry",
           "PRINTED_WINDTUNNEL_Q22", "compliance_trajectory", "mechanism_actual", "stop_directions", "windtunnel_positions",
           "identify_pitch_ratio"]


def _f(value, unit: str, source: str):
    """Dataclass field with unit and source metadata."""
    return field(default=value, metadata={"unit": unit, "source": source})


#: Error sources that can be switched individually (error-budget table).
SOURCES = ("gyro_white", "gyro_bias_instability", "gyro_residual_bias", "gyro_warmup",
           "gyro_scale_factor", "accel_white", "accel_bias", "quantisation", "reference_angle",
           "accel_run_change", "mount_compliance")


#: The wang2023cja IMU's assumptions beyond its sensor grade (the paper prints no sensor numbers):
#: value (SI), unit and source of each.
IMU_ASSUMPTIONS = {
    "gyro_warmup_bias_rad_s": ((18 * DEG_H, -12 * DEG_H, 15 * DEG_H), "rad/s",
                               "bias at power-on, decaying with τ = 90 s; after the 5-min warm-up (§3.2 step 1) "
                               "≈ 0.6 °/h remains"),
    "gyro_warmup_tau_s": (90.0, "s", "assumed thermal settling time constant"),
    "gyro_lsb_rad_s": (0.00625 * DEG, "rad/s", "16-bit output LSB 0.00625 °/s (ADIS1649x)"),
    "accel_lsb_m_s2": (3.9 * UG, "m/s²", "20-bit LSB at ±2 g (ADXL355: 3.9 µg)"),
    "time_since_power_on_s": (300.0, "s", "§3.2 step (1): 5 min warm-up"),
}


def paper_imu(gyro_grade: str = "wang2023cja", accel_grade: str = "wang2023cja", fs_hz: float = 1000.0) -> SensorSpec:
    """The IMU of a wang2023cja run: :func:`~mtcal.core.sensor_grades.sensor_spec` of the two grades plus
    :data:`IMU_ASSUMPTIONS` (warm-up transient, quantisation); ``fs_hz`` §4.1 1 kHz.

    The paper prints no sensor numbers; its grade in :mod:`mtcal.core.sensor_grades` is
    ``"wang2023cja"`` (tactical MEMS after factory compensation). Raises ``ValueError`` naming
    the parameter for an unknown grade.

    >>> paper_imu().label, paper_imu().fs_hz
    ('gyro wang2023cja, accel wang2023cja', 1000.0)
    """
    for name, value in (("gyro_grade", gyro_grade), ("accel_grade", accel_grade)):
        choice(name, value, sorted(GRADES))
    spec = sensor_spec(gyro_grade, accel_grade, fs_hz=fs_hz)
    # the wang2023cja run applies no accelerometer bias instability (not in SOURCES)
    return replace(spec, **{k: v[0] for k, v in IMU_ASSUMPTIONS.items()})


#: Historical name of the paper's IMU builder (``ImuSpec()`` = the paper's IMU, a
#: :class:`mtcal.core.sensors.SensorSpec`); new code calls :func:`paper_imu`.
ImuSpec = paper_imu


# --------------------------------------------------------------------------
# scenarios
# --------------------------------------------------------------------------
@dataclass(frozen=True)
class TurntableScenario:
    """High-precision three-axis turntable (§4.1): tests T1–T4, AoA sweep, roll sweep."""

    imu: SensorSpec = field(default_factory=paper_imu)
    qncf: QncfParams = field(default_factory=QncfParams)
    errors: ErrorModel = field(default_factory=ErrorModel)
    alpha_deg: dict = _f(None, "deg", "fit_installation_angles(Tables 1–4, PAPER_SIGN), rounded to 1e-4°")
    yaw_positions_deg: tuple = _f((8.0, -8.0), "deg", "§4.1 yaw range ±8°, Table 1")
    pitch_positions_deg: tuple = _f((-12.0, 23.0), "deg", "§4.1 pitch range −12…23°, Table 1")
    roll_positions_deg: tuple = _f((90.0, -90.0), "deg", "§4.1 roll range ±90°, Table 1")
    rest_s: float = _f(3.0, "s", "§3.2 rest per position")
    turntable_rate_rad_s: float = _f(20 * DEG, "rad/s", "assumed mean move rate of the turntable")
    averaging_fraction: float = _f(0.5, "1", "middle half of each rest is averaged (§3.2 'middle section')")
    aoa_sweep_deg: tuple = _f((-4, 0, 4, 8, 12, 13, -5, 13), "deg", "Table 5 reference order")
    aoa_rate_rad_s: float = _f(4 * DEG, "rad/s", "assumed AoA sweep rate")
    sweep_hold_s: float = _f(5.0, "s", "assumed hold per sweep position")
    roll_sweep_deg: tuple = _f((90, 60, 30, 0, -30, -60, -90, 90), "deg", "Table 7 reference order")
    roll_rate_rad_s: float = _f(20 * DEG, "rad/s", "assumed roll sweep rate")

    def __post_init__(self) -> None:
        if self.alpha_deg is None:
            object.__setattr__(self, "alpha_deg", {
                "T1": (-0.2434, -0.0359, 0.0521), "T2": (-0.0130, 0.0184, -1.1484),
                "T3": (-0.2833, 0.2903, -0.8426), "T4": (-2.4856, -0.3096, -0.2227)})

    @property
    def fs_hz(self) -> float:
        """Sample rate (Hz): owned by the IMU spec (§4.1 1 kHz)."""
        return self.imu.fs_hz

    def alpha_rad(self, test: str) -> np.ndarray:
        """Installation angles α1..α3 of ``test`` (rad)."""
        return np.radians(self.alpha_deg[test])

    @property
    def reference_angle_sigma_rad(self) -> float:
        """Turntable angle error at a rest, 1σ per axis (rad), from the error model."""
        return self.errors.position_error_arcsec * ARCSEC


@dataclass(frozen=True)
class WindTunnelScenario:
    """Hypersonic wind tunnel (§4.2): support mechanism, wind-off sweep, five wind-on groups."""

    imu: SensorSpec = field(default_factory=paper_imu)
    qncf: QncfParams = field(default_factory=QncfParams)
    errors: ErrorModel = field(default_factory=ErrorModel)
    alpha_deg: tuple = _f(None, "deg", "mounting of the SO(4) projection of the printed wind-tunnel matrix "
                          "(training data; windtunnel_geometry)")
    rest_s: float = _f(3.0, "s", "§3.2")
    cal_yaw_deg: tuple = _f((4.0, -4.0), "deg", "assumed mechanism yaw range")
    cal_pitch_deg: tuple = _f((-5.0, 13.0), "deg", "AoA range of Tables 9/10")
    cal_roll_deg: tuple = _f((30.0, -30.0), "deg", "assumed mechanism roll range")
    mechanism_rate_rad_s: float = _f(2 * DEG, "rad/s", "assumed mechanism rate (groups 1–4)")
    group5_rate_rad_s: float = _f(1 * DEG, "rad/s", "Group 5: different rate (§4.2, value not given)")
    pitch_ratio_error: float = _f(None, "1", "mechanism pitch transmission-ratio error: noise-free Eq 13 "
                                  "reproduces the printed Q(2,2) = 1.004462 (training; identify_pitch_ratio); "
                                  "first guess 1/Q(2,2) − 1")
    transmission_gap_rad: float = _f(0.02 * DEG, "rad", "backlash: actual lags command by ±gap/2 "
                                     "depending on approach direction (§4.2 'transmission gap')")
    servo_lag_s: float = _f(0.002, "s", "servo following error: stops short by lag × mean move rate")
    non_orthogonality_rad: tuple = _f((0.0008, -0.0005), "rad/rad", "yaw and roll picked up per rad of "
                                      "pitch (mechanism non-orthogonality, §4.2)")
    repeatability_rad: float = _f(0.004 * DEG, "rad", "1σ mechanism repeatability per hold")
    aoa_sweep_deg: tuple = _f((-4, 0, 4, 8, 12, 13, -5, 13), "deg", "Table 9 reference order")
    wind_on_sweep_deg: tuple = _f((-4, 0, 4, 8, 12), "deg", "Table 10 reference angles")
    hold_s: float = _f(5.0, "s", "assumed hold per AoA position")
    elastic_true_deg: tuple = _f((0.0151, 0.01478), "deg, deg/deg", "true deflection c0 + c1·α, fitted to "
                                 "Table 10 Mean row (measured ≈ true after calibration)")
    elastic_model_deg: tuple = _f((-0.0050, 0.01413), "deg, deg/deg", "tunnel's elastic-correction model, "
                                  "fitted to Table 10 'After elastic angle correction' row")
    dynamic_pressure_sigma: float = _f(0.02, "1", "run-to-run dynamic-pressure scatter (assumed 2 %)")
    vibration_accel_m_s2: float = _f(3.0, "m/s²", "model vibration with wind on (assumed; trips the AMD)")
    vibration_freq_hz: float = _f(45.0, "Hz", "assumed first bending mode of model + sting")
    vibration_angle_rad: float = _f(0.01 * DEG, "rad", "angular pitch vibration amplitude (assumed)")
    wind_on_hold_s: float = _f(3.0, "s", "assumed hold per AoA with wind (short hypersonic run)")
    group_interval_s: float = _f(600.0, "s", "assumed time between wind-on runs (IMU stays powered)")

    @property
    def fs_hz(self) -> float:
        """Sample rate (Hz): owned by the IMU spec (§3.2 1 kHz)."""
        return self.imu.fs_hz

    def __post_init__(self) -> None:
        if self.alpha_deg is None or self.pitch_ratio_error is None:
            alpha_deg, ratio = windtunnel_geometry()
            if self.alpha_deg is None:
                object.__setattr__(self, "alpha_deg", alpha_deg)
            if self.pitch_ratio_error is None:
                object.__setattr__(self, "pitch_ratio_error", ratio)


def windtunnel_geometry() -> tuple[tuple, float]:
    """Installation angles (deg) and mechanism pitch-ratio error identified from the printed wind-tunnel matrix.

    The printed matrix is training data. Its SO(4) projection ``L(p) R(r)`` gives the
    mounting ``c = r*`` (Eq 1 angles by a least-squares match of ``mount_quaternion``); its
    pitch-axis diagonal Q(2,2) = 1.004462 is what Eq 13 does when the mechanism's actual pitch
    is ``(1 + ε)`` times the commanded one: Q(2,2) ≈ 1/(1 + ε), so ε = 1/Q(2,2) − 1.

    >>> alpha, eps = windtunnel_geometry()
    >>> round(eps, 5)
    -0.00444
    """
    return _windtunnel_geometry()


@functools.lru_cache(maxsize=1)
def _windtunnel_geometry() -> tuple[tuple, float]:
    """:func:`windtunnel_geometry`, fitted once per process (the printed matrix does not change; immutable result)."""
    from scipy.optimize import least_squares

    from mtcal.core import rotations
    from mtcal.methods import constrained_fit
    from mtcal.reporting import paper_numbers

    q = paper_numbers.training("wang2023cja")["wang2023cja_matrix_qbs_windtunnel"][["col_1", "col_2", "col_3", "col_4"]]
    q = q.to_numpy(float)
    c = rotations.quat_conjugate(constrained_fit.project_to_so4(q).r)
    c = c * np.sign(c[0])

    def resid(a):
        return rotations.mount_quaternion(a) - c
    alpha = least_squares(resid, np.zeros(3), xtol=1e-14, ftol=1e-14).x
    return tuple(round(float(x), 4) for x in np.degrees(alpha)), round(float(1.0 / q[1, 1] - 1.0), 6)


# --------------------------------------------------------------------------
# parameters-cell values → scenario
# --------------------------------------------------------------------------
#: Turntable notebook parameters (the paper's setting; units in the names).
TURNTABLE_DEFAULTS = {
    "gyro_grade": "wang2023cja", "accel_grade": "wang2023cja", "fs_hz": 1000.0, "rest_s": 3.0,
    "yaw_positions_deg": (8.0, -8.0), "pitch_positions_deg": (-12.0, 23.0), "roll_positions_deg": (90.0, -90.0),
    "turntable_rate_deg_s": 20.0,
}
#: Wind-tunnel notebook parameters (the paper's setting; units in the names).
WINDTUNNEL_DEFAULTS = {
    "gyro_grade": "wang2023cja", "accel_grade": "wang2023cja", "fs_hz": 1000.0, "rest_s": 3.0,
    "mechanism_rate_deg_s": 2.0, "group5_rate_deg_s": 1.0, "vibration_accel_m_s2": 3.0,
}


def turntable_scenario(errors: ErrorModel | None = None, **params) -> TurntableScenario:
    """:class:`TurntableScenario` from parameters-cell values (names of :data:`TURNTABLE_DEFAULTS`).

    ``errors`` is the identified (or prior-nominal) :class:`ErrorModel`.
    """
    p = merge_parameters(params, TURNTABLE_DEFAULTS)
    imu = paper_imu(p["gyro_grade"], p["accel_grade"], number_in_range("fs_hz", p["fs_hz"], 100.0, 10000.0, "Hz"))
    return TurntableScenario(
        imu=imu, errors=ErrorModel() if errors is None else errors,
        rest_s=number_in_range("rest_s", p["rest_s"], 2.5, 30.0, "s"),
        yaw_positions_deg=angle_pair_deg("yaw_positions_deg", p["yaw_positions_deg"], -30.0, 30.0),
        pitch_positions_deg=angle_pair_deg("pitch_positions_deg", p["pitch_positions_deg"], -60.0, 60.0),
        roll_positions_deg=angle_pair_deg("roll_positions_deg", p["roll_positions_deg"], -90.0, 90.0),
        turntable_rate_rad_s=number_in_range("turntable_rate_deg_s", p["turntable_rate_deg_s"], 1.0, 100.0, "deg/s") * DEG)


#: The printed wind-tunnel matrix's Q(2,2) (training data).
PRINTED_WINDTUNNEL_Q22 = 1.004462


def windtunnel_scenario(errors: ErrorModel | None = None, **params) -> WindTunnelScenario:
    """:class:`WindTunnelScenario` from parameters-cell values (names of :data:`WINDTUNNEL_DEFAULTS`).

    The installation angles come from the printed wind-tunnel matrix (:func:`windtunnel_geometry`);
    the pitch-ratio error is the one for which the noise-free simulated calibration reproduces its
    Q(2,2) (:func:`identify_pitch_ratio`), the mechanism's other stated errors included.
    """
    p = merge_parameters(params, WINDTUNNEL_DEFAULTS)
    alpha_deg, _ = windtunnel_geometry()
    sc = WindTunnelScenario(
        imu=paper_imu(p["gyro_grade"], p["accel_grade"], number_in_range("fs_hz", p["fs_hz"], 100.0, 10000.0, "Hz")),
        errors=ErrorModel() if errors is None else errors, alpha_deg=alpha_deg, pitch_ratio_error=0.0,
        rest_s=number_in_range("rest_s", p["rest_s"], 2.5, 30.0, "s"),
        mechanism_rate_rad_s=number_in_range("mechanism_rate_deg_s", p["mechanism_rate_deg_s"], 0.2, 20.0, "deg/s") * DEG,
        group5_rate_rad_s=number_in_range("group5_rate_deg_s", p["group5_rate_deg_s"], 0.2, 20.0, "deg/s") * DEG,
        vibration_accel_m_s2=number_in_range("vibration_accel_m_s2", p["vibration_accel_m_s2"], 0.0, 50.0, "m/s²"))
    return replace(sc, pitch_ratio_error=identify_pitch_ratio(sc, PRINTED_WINDTUNNEL_Q22))


# --------------------------------------------------------------------------
# the scenario's mechanism and mount (used by .runs and by identify_pitch_ratio)
# --------------------------------------------------------------------------
def compliance_trajectory(time_s, angle_rad, compliance_rad_per_g: float) -> Trajectory:
    """Truth trajectory of the IMU base: body attitude (Eq 9 of ``angle_rad``) tilted by the mount compliance.

    The mount rotates by ``k · (ẑ_b × ĝ_b)`` (rad, ĝ_b unit gravity in body axes,
    :func:`mtcal.core.simulate.gravity_lateral_axis`): zero when level, ``k`` about the lateral axis at 90° of
    roll or pitch (wang2023cja §4.1 gasket mounts). A Monte Carlo of many compliances on one schedule
    shares the untilted parts (:class:`mtcal.core.simulate.RecordSource`; the same numbers).
    """
    q_wb = rotations.quat_from_euler_zxy(angle_rad[:, 0], angle_rad[:, 1], angle_rad[:, 2])
    if compliance_rad_per_g == 0.0:
        return Trajectory(time_s, q_wb)
    return tilted_trajectory(time_s, q_wb, gravity_lateral_axis(q_wb), compliance_rad_per_g)


def stop_directions(prof: AngleProfile) -> np.ndarray:
    """Direction of each axis's last move at every sample of ``prof`` where it stands, (N, 3) of −1, 0, +1.

    0 while the axis moves and before its first move (the mechanism is zeroed where it stands at the
    start). It depends on the schedule alone: :func:`mechanism_actual` of many scenarios on one profile
    takes it from its ``stops`` argument instead of finding it again.

    Examples
    --------
    >>> import numpy as np
    >>> from mtcal.core.profiles import step_schedule
    >>> prof = step_schedule(np.radians([[0, 0, 0], [0, 10, 0], [0, 0, 0]]), np.radians(10.0), [1.0, 1.0, 1.0], 10.0)
    >>> d = stop_directions(prof)
    >>> d[0].tolist(), d[prof.segment == 2][0].tolist(), d[prof.segment == 4][0].tolist()
    ([0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0])
    """
    out = np.empty(prof.rate_rad_s.shape)
    for axis in range(out.shape[1]):
        rate = prof.rate_rad_s[:, axis]
        moving = np.abs(rate) > 1e-9
        direction = np.where(moving, np.sign(rate), 0.0)
        idx = np.where(moving, np.arange(rate.size), 0)
        np.maximum.accumulate(idx, out=idx)
        last = direction[idx]
        last[~moving & (idx == 0) & ~moving[0]] = 0.0
        out[:, axis] = last * ~moving
    return out


def mechanism_actual(sc: WindTunnelScenario, prof: AngleProfile, rate_rad_s: float, *,
                     stops: np.ndarray | None = None) -> np.ndarray:
    """Actual mechanism angles (N, 3) from the commanded ones (rad).

    * pitch transmission-ratio error: actual pitch = (1 + ε) · commanded;
    * every axis: transmission gap and servo stop error — at a hold the axis stops short of the
      command by ``gap/2 + servo_lag · rate`` in the direction of its last move. The mechanism is
      zeroed where it stands at the start (no offset before an axis first moves), so an axis that
      moved during the calibration comes back to zero with that offset;
    * non-orthogonality: yaw and roll pick up ``non_orthogonality_rad`` per rad of pitch.

    ``stops``: :func:`stop_directions` of ``prof`` when the caller has it (the same numbers).
    """
    cmd = prof.angle_rad
    act = cmd.copy()
    act[:, 1] *= 1.0 + sc.pitch_ratio_error
    stop = 0.5 * sc.transmission_gap_rad + sc.servo_lag_s * rate_rad_s
    # (last · ¬moving) · stop: the factor ¬moving is 0 or 1, so the product and its sign are those of
    # last · stop · ¬moving
    act -= (stop_directions(prof) if stops is None else stops) * stop
    act[:, 0] += sc.non_orthogonality_rad[0] * cmd[:, 1]
    act[:, 2] += sc.non_orthogonality_rad[1] * cmd[:, 1]
    return act



def windtunnel_positions(sc: WindTunnelScenario) -> np.ndarray:
    """The wind-tunnel six calibration positions (Eq 8 frame), (6, 3) rad."""
    return _positions_rad(sc.cal_yaw_deg, sc.cal_pitch_deg, sc.cal_roll_deg)


def _positions_rad(yaw_deg, pitch_deg, roll_deg) -> np.ndarray:
    """:func:`windtunnel_positions` from the scenario's three angle lists (deg), for a schedule built from settings."""
    return six_position.six_positions_rad(np.radians(yaw_deg), np.radians(pitch_deg), np.radians(roll_deg))


def identify_pitch_ratio(sc: WindTunnelScenario, q22: float) -> float:
    """Mechanism pitch-ratio error ε for which noise-free Eq 13 returns ``q22`` as Q(2,2).

    Noise-free: the QNCF at a rest returns the actual attitude, so the rest means are the
    mechanism's actual angles (:func:`mechanism_actual`, which also applies backlash, servo stop
    error and non-orthogonality), tilted by the mount compliance of ``sc.errors`` and seen
    through the mounting. Q(2,2) is affine in ε to first
    order, so two evaluations fix it.
    """
    pos = windtunnel_positions(sc)
    prof = six_position.schedule_profile(pos, rate_rad_s=5 * DEG, rest_s=sc.rest_s, fs_hz=sc.fs_hz)
    holds = six_position.middle_slices(prof.hold_slices()[1:-1], 0.5)
    q_bs = mount_quaternion(np.radians(sc.alpha_deg))
    q_ref = rotations.quat_from_euler_zxy(pos[:, 0], pos[:, 1], pos[:, 2])
    k_mount = sc.errors.compliance_deg_g(MOUNT_TYPE["windtunnel"]) * DEG
    stops = stop_directions(prof)

    def q22_at(eps):
        act = mechanism_actual(replace(sc, pitch_ratio_error=float(eps)), prof, sc.mechanism_rate_rad_s, stops=stops)
        mean = np.array([act[h].mean(axis=0) for h in holds])
        q_wb = compliance_trajectory(np.arange(len(mean), dtype=float), mean, k_mount).q_wb
        q_s = rotations.quat_multiply(rotations.quat_conjugate(q_bs), rotations.quat_multiply(q_wb, q_bs))
        return float(quaternion_lsq.least_squares_error_matrix(q_s, q_ref)[1, 1])
    e0, e1 = 0.0, -0.004
    f0, f1 = q22_at(e0), q22_at(e1)
    return round(float(e0 + (q22 - f0) * (e1 - e0) / (f1 - f0)), 6)
