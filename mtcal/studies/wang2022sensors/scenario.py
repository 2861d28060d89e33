"""wang2022sensors scenario: the Table 3 IMU, the rig (axis, lever arm, turntable moves), the
identified hardware error sources, and the parameters-cell defaults.

Every value has a source: "Table n" / "Sec. n" (the paper) or "mtcal" (our
choice, with the reason). The paper does not state the sample rate, the lever
arm, the turntable rates/accelerations, the sensor-to-reference latency or the
accelerometer bias left after the ref. [30] calibration; those are mtcal
choices — the ones the paper's Table 5 constrains are *identified* in
:mod:`mtcal.studies.wang2022sensors.error_model` (their prior ranges are its
:data:`~.error_model.ERROR_PRIORS`).

The IMU is the one sensor-spec type (:class:`mtcal.core.sensors.SensorSpec`, SI values, owns
the sample rate), built from Table 3 by :func:`table3_imu` (or from a sensor grade by
:func:`imu_from_grade`). A scenario is resolved once, at the top of a run, into plain SI values
(the spec itself, :class:`RigValues`); the runs never re-open the dataclasses.

Table 3 random-walk rows: the extracted units are ambiguous (paper-data README
item 4). mtcal's default reads them like MATLAB ``imuSensor``'s ``RandomWalk``
(u·√Hz = u/√s, a rate random walk K: σ_bias(t) = K √t); ``"per_sample"`` reads
the value as the std of each per-sample bias step (K = value·√fs), ``"none"``
switches the walk off.

References
----------
Wang C., Tu X., Chen Q., Yang Q., Fang T., "Movable Surface Rotation Angle
Measurement System Using IMU", Sensors 2022, 22, 8996, doi:10.3390/s22228996.

Examples
--------
>>> sc = scenario_from_parameters(lever_arm_m=0.1)
>>> round(sc.rig.lever_arm_m, 3), sc.imu.fs_hz
(0.1, 200.0)
>>> scenario_from_parameters(fs_hz=-1.0)
Traceback (most recent call last):
...
ValueError: fs_hz must be > 0 (Hz), got -1.0
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from mtcal.core import rotations
from mtcal.core.sensor_grades import grade_names, sensor_grade
from mtcal.core.sensors import SensorSpec
from mtcal.core.units import DEG, MG, UG
from mtcal.core.validate import STANDARD_GRAVITY_M_S2, choice, merge_parameters
from mtcal.filters.rams_ekf import RamsEkfParams
from mtcal.methods.zero_velocity import ZvdParams
from mtcal.reporting import paper_numbers

__all__ = ["PAPER_AXIS_FIG11", "table4_axes", "ImuSpec", "ImuValues", "table3_imu", "table3_reading", "imu_from_grade",
           "rams_ekf_params", "AhrsImu", "RigSetup", "RigValues", "Scenario", "PARAMETER_DEFAULTS",
           "scenario_from_parameters", "labels", "lever_arm_vector", "gravity0", "table1_zvd_params"]

#: Fig. 11 simulation axis (Sec. 5), signs as extracted (v_x ≥ 0 by convention).
PAPER_AXIS_FIG11 = (0.1734, 0.9835, 0.0523)


def table1_zvd_params() -> ZvdParams:
    """The ZVD thresholds of Table 1 as transcribed (``paper_data/wang2022sensors_table01_zvd_params.csv``).

    Returns
    -------
    ZvdParams
        ``th_a_min``, ``th_a_max`` (m/s²), ``th_ζa`` (m²/s⁴), ``t_w`` and ``th_t`` (s) from the table; the
        rest at :class:`~mtcal.methods.zero_velocity.ZvdParams`' defaults.

    References
    ----------
    wang2022sensors Table 1, Eq 21–22.

    Examples
    --------
    >>> table1_zvd_params() == ZvdParams()  # the method's defaults are Table 1
    True
    """
    name = "wang2022sensors_table01_zvd_params"
    return ZvdParams(accel_min_m_s2=paper_numbers.value(name, "value", symbol="th_a_min"),
                     accel_max_m_s2=paper_numbers.value(name, "value", symbol="th_a_max"),
                     var_threshold_m2_s4=paper_numbers.value(name, "value", symbol="th_zeta_a"),
                     window_s=paper_numbers.value(name, "value", symbol="t_w"),
                     min_duration_s=paper_numbers.value(name, "value", symbol="th_t"))


def table4_axes() -> dict[str, np.ndarray]:
    """Table 4 axes Bv1–Bv3, normalised (used as the *true* axes in simulation)."""
    df = paper_numbers.load("wang2022sensors_table04_rotation_axes")
    out = {}
    for row in df.itertuples():
        v = np.array([row.bv_x, row.bv_y, row.bv_z], float)
        out[row.axis_symbol] = v / np.linalg.norm(v)
    return out


def rams_ekf_params(imu: SensorSpec, sigma_a_moving_m_s2: float = 5.0) -> RamsEkfParams:
    """EKF noise matched to an IMU spec: σθ = gyro noise per sample, σb = K/√Δt (K = gyro bias random
    walk, floor 1e-7), V_z = accel noise per sample, V (moving) = 5 m/s² (mtcal: several times the
    lever-arm accelerations)."""
    k = max(imu.gyro_rw_rad_s_rt_s, 1e-7)
    return RamsEkfParams(sigma_theta_rad_s=imu.gyro_noise_per_sample_rad_s,
                         sigma_b_rad_s2=k / np.sqrt(imu.dt_s),
                         sigma_a_static_m_s2=imu.accel_noise_per_sample_m_s2,
                         sigma_a_moving_m_s2=sigma_a_moving_m_s2,
                         p0_theta_rad2=1e-8, p0_bias_rad2_s2=(0.01 * DEG) ** 2)


@dataclass(frozen=True)
class ImuValues(SensorSpec):
    """A wang2022sensors IMU: the one sensor-spec type (:class:`mtcal.core.sensors.SensorSpec`, SI
    values, owns the sample rate) plus the RAMS EKF tuning the runs derive from it."""

    def ekf_params(self, sigma_a_moving_m_s2: float = 5.0) -> RamsEkfParams:
        """:func:`rams_ekf_params` of this spec."""
        return rams_ekf_params(self, sigma_a_moving_m_s2)


_RW_SCALE = {"sqrt_hz": lambda fs: 1.0, "per_sample": np.sqrt, "none": lambda fs: 0.0}


def table3_imu(*, accel_noise_ug_rt_hz: float = 50.0, accel_random_walk: float = 10.0,
               accel_bias_residual_mg: float = 0.1, gyro_bias_deg_s: float = 0.7,
               gyro_noise_deg_s_rt_hz: float = 0.02, gyro_random_walk: float = 0.014,
               gyro_scale_factor_ppm: float = 1000.0, random_walk_interpretation: str = "sqrt_hz",
               accel_bias_compensated: bool = True, accel_bias_mg: float = 50.0, fs_hz: float = 200.0,
               label: str = "wang2022sensors Table 3") -> ImuValues:
    """The wang2022sensors IMU (Table 3), read from its datasheet units into the SI spec.

    Parameters
    ----------
    accel_noise_ug_rt_hz : float
        Table 3: 50 µg/√Hz.
    accel_random_walk : float
        Table 3: 10, unit ambiguous (module doc), default read as µg·√Hz.
    accel_bias_residual_mg : float
        mtcal: 0.1 mg 1σ per axis per trial — left after the ref. [30] calibration of
        Sec. 4 (Table 3's 50 mg is the uncalibrated bias; Eq 28 assumes none).
    gyro_bias_deg_s : float
        Table 3: 0.7 °/s, applied as [+, −, +] (the EKF estimates it).
    gyro_noise_deg_s_rt_hz : float
        Table 3: 0.02 °/s/√Hz.
    gyro_random_walk : float
        Table 3: 0.014, default read as (°/s)·√Hz.
    gyro_scale_factor_ppm : float
        mtcal: 1000 ppm residual after calibration (BMI088 sensitivity tolerance ±1 %
        before); applied to all three axes.
    random_walk_interpretation : {"sqrt_hz", "per_sample", "none"}
    accel_bias_compensated : bool
        mtcal: True (Sec. 4 calibrates with ref. [30]); False applies Table 3's 50 mg
        literally as [+, −, +]/√3 (Eq 28 assumes no bias: shown as a sensitivity).
    accel_bias_mg : float
        Table 3: 50 mg uncalibrated bias.
    fs_hz : float
        mtcal: 200 Hz (not stated; a BMI088 gyro output rate).

    Returns
    -------
    ImuValues
        SI spec (rad/s, m/s², Hz).

    Examples
    --------
    >>> v = table3_imu()
    >>> v.fs_hz, round(v.gyro_bias_rad_s[1], 6)
    (200.0, -0.012217)
    >>> table3_imu(random_walk_interpretation="x")
    Traceback (most recent call last):
    ...
    ValueError: random_walk_interpretation must be 'sqrt_hz', 'per_sample' or 'none', got 'x'
    """
    if random_walk_interpretation not in _RW_SCALE:
        raise ValueError("random_walk_interpretation must be 'sqrt_hz', 'per_sample' or 'none', "
                         f"got {random_walk_interpretation!r}")
    if not isinstance(accel_bias_compensated, bool):
        raise TypeError(f"accel_bias_compensated must be a bool, got {accel_bias_compensated!r}")
    values = dict(accel_noise_ug_rt_hz=accel_noise_ug_rt_hz, accel_random_walk=accel_random_walk,
                  accel_bias_residual_mg=accel_bias_residual_mg, gyro_bias_deg_s=gyro_bias_deg_s,
                  gyro_noise_deg_s_rt_hz=gyro_noise_deg_s_rt_hz, gyro_random_walk=gyro_random_walk,
                  gyro_scale_factor_ppm=gyro_scale_factor_ppm, accel_bias_mg=accel_bias_mg, fs_hz=fs_hz)
    for name, v in values.items():
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v) or v < 0:
            raise ValueError(f"{name} must be a finite value >= 0, got {v!r}")
    if fs_hz <= 0:
        raise ValueError(f"fs_hz must be > 0 (Hz), got {fs_hz!r}")
    rw = _RW_SCALE[random_walk_interpretation](fs_hz)
    pattern = np.array([1.0, -1.0, 1.0])
    return ImuValues(fs_hz=float(fs_hz), label=label,
                     gyro_noise_rad_s_rt_hz=gyro_noise_deg_s_rt_hz * DEG,
                     gyro_bias_rad_s=tuple(gyro_bias_deg_s * DEG * pattern),
                     gyro_rw_rad_s_rt_s=gyro_random_walk * DEG * rw,
                     gyro_scale_factor=gyro_scale_factor_ppm * 1e-6,
                     accel_noise_m_s2_rt_hz=accel_noise_ug_rt_hz * UG,
                     accel_bias_m_s2=(0.0, 0.0, 0.0) if accel_bias_compensated else
                     tuple(accel_bias_mg * MG * pattern / np.sqrt(3.0)),
                     accel_bias_sigma_m_s2=accel_bias_residual_mg * MG if accel_bias_compensated else 0.0,
                     accel_rw_m_s2_rt_s=accel_random_walk * UG * rw, time_since_power_on_s=0.0)


def table3_reading(imu: ImuValues, random_walk_interpretation: str = "sqrt_hz",
                   accel_bias_compensated: bool = True, accel_bias_mg: float = 50.0) -> ImuValues:
    """``imu`` (built with the default ``"sqrt_hz"`` reading) under another reading of Table 3's
    ambiguous rows: random walks × √fs (``"per_sample"``) or off (``"none"``); the 50 mg
    accelerometer bias applied literally as [+, −, +]/√3 when not compensated."""
    if random_walk_interpretation not in _RW_SCALE:
        raise ValueError("random_walk_interpretation must be 'sqrt_hz', 'per_sample' or 'none', "
                         f"got {random_walk_interpretation!r}")
    k = _RW_SCALE[random_walk_interpretation](imu.fs_hz)
    out = replace(imu, gyro_rw_rad_s_rt_s=imu.gyro_rw_rad_s_rt_s * k, accel_rw_m_s2_rt_s=imu.accel_rw_m_s2_rt_s * k)
    if not accel_bias_compensated:
        out = replace(out, accel_bias_m_s2=tuple(accel_bias_mg * MG * np.array([1.0, -1.0, 1.0]) / np.sqrt(3.0)),
                      accel_bias_sigma_m_s2=0.0)
    return out


def imu_from_grade(name: str, fs_hz: float = 200.0) -> ImuValues:
    """An IMU from :mod:`mtcal.core.sensor_grades` (white noise and turn-on biases, applied as the
    fixed [+, −, +] gyro bias of Table 3; the Table 3 random-walk rows only for the
    ``"wang2022sensors"`` grade)."""
    choice("sensor_grade", name, grade_names())
    g = sensor_grade(name)
    rw = name == "wang2022sensors"
    return table3_imu(accel_noise_ug_rt_hz=g.accel_noise_ug_rt_hz, accel_random_walk=10.0 if rw else 0.0,
                      accel_bias_residual_mg=g.accel_bias_repeatability_mg,
                      gyro_bias_deg_s=g.gyro_bias_repeatability_deg_h / 3600.0,
                      gyro_noise_deg_s_rt_hz=g.gyro_arw_deg_rt_h / 60.0, gyro_random_walk=0.014 if rw else 0.0,
                      gyro_scale_factor_ppm=1000.0 if rw else g.gyro_scale_factor_ppm, fs_hz=fs_hz, label=name)


#: Historical name of the Table 3 IMU builder (``ImuSpec()`` = Table 3 at 200 Hz, an SI
#: :class:`mtcal.core.sensors.SensorSpec`); new code calls :func:`table3_imu`.
ImuSpec = table3_imu


@dataclass(frozen=True)
class AhrsImu:
    """Sensors of the commercial-AHRS stand-in (mtcal; Ellipse2-N-class datasheet orders).

    gyro 0.15 °/√h ARW (≈ 0.0025 °/s/√Hz), residual bias 0.02 °/s, accel 57 µg/√Hz,
    magnetometer noise 0.5 % of the field; the field's heading wanders (Gauss–Markov,
    ``magnetic_heading_sigma_deg`` 1σ, τ = ``magnetic_heading_tau_s``; mtcal 5°, 20 s;
    identified from Table 5 in :mod:`.error_model`).
    """

    gyro_noise_deg_s_rt_hz: float = 0.0025
    gyro_bias_deg_s: float = 0.02
    accel_noise_ug_rt_hz: float = 57.0
    mag_noise_fraction: float = 0.005
    magnetic_heading_sigma_deg: float = 5.0
    magnetic_heading_tau_s: float = 20.0

    def resolve(self, fs_hz: float) -> ImuValues:
        """The IMU part as the SI sensor spec; the residual gyro bias is drawn per trial by the runs
        (σ = ``gyro_bias_deg_s``), so the spec carries none."""
        return ImuValues(fs_hz=float(fs_hz), label="AHRS stand-in",
                         gyro_noise_rad_s_rt_hz=self.gyro_noise_deg_s_rt_hz * DEG,
                         accel_noise_m_s2_rt_hz=self.accel_noise_ug_rt_hz * UG, time_since_power_on_s=0.0)


@dataclass(frozen=True)
class RigValues:
    """A resolved rig in plain SI values."""

    lever_arm_m: float
    lever_arm_up_m: float
    move_rate_rad_s: float
    move_accel_rad_s2: float
    hold_s: float
    step_rad: float
    axis_rest_s: float
    latency_s: float
    reference_error_rad: float
    zvd: ZvdParams


@dataclass(frozen=True)
class RigSetup:
    """The test rig of Sec. 7 (SGT320E turntable) and the hardware error sources.

    Parameters
    ----------
    lever_arm_m : float
        Distance of the IMU from the rotation axis along the surface chord (m);
        plus ``lever_arm_up_m`` normal to it. mtcal default 0.2 m (a sensor on a
        flap); identified from Table 5 (prior in :data:`.error_model.ERROR_PRIORS`).
    lever_arm_up_m : float
        mtcal: 0.02 m.
    move_rate_deg_s : float
        Turntable cruise rate of the 10° steps (°/s); mtcal 20 °/s (not stated).
    move_accel_deg_s2 : float
        Turntable acceleration limit of the trapezoidal-velocity moves (°/s²);
        mtcal default 1000 °/s², the value Table 5 identifies (notebook 31).
    hold_s, step_deg : float
        Sec. 7: 1 s pause at 10° intervals, −180…180°.
    axis_rest_s : float
        mtcal: 2 s at each of the three axis-estimation positions (Sec. 3.2: ≥ 1 s).
    latency_s : float
        RAMS output time minus turntable reference time (s): SPI read, EKF and
        USB framing on the STM32F411 vs the turntable's encoder log; mtcal default 0;
        identified.
    reference_error_arcsec : float
        SGT320E angular position accuracy ±5″ (Sec. 7, unit lost in extraction),
        uniform per hold.
    zvd : ZvdParams
        Table 1 (+ the optional gyro condition, see ``zvd_gyro_max_deg_s``).
    """

    lever_arm_m: float = 0.2
    lever_arm_up_m: float = 0.02
    move_rate_deg_s: float = 20.0
    move_accel_deg_s2: float = 1000.0
    hold_s: float = 1.0
    step_deg: float = 10.0
    axis_rest_s: float = 2.0
    latency_s: float = 0.0
    reference_error_arcsec: float = 5.0
    zvd: ZvdParams = field(default_factory=ZvdParams)

    def __post_init__(self) -> None:
        for f in ("lever_arm_m", "lever_arm_up_m", "latency_s", "reference_error_arcsec"):
            v = getattr(self, f)
            if not np.isfinite(v) or v < 0:
                raise ValueError(f"{f} must be a finite value >= 0, got {v!r}")
        for f in ("move_rate_deg_s", "move_accel_deg_s2", "hold_s", "step_deg", "axis_rest_s"):
            v = getattr(self, f)
            if not np.isfinite(v) or v <= 0:
                raise ValueError(f"{f} must be > 0, got {v!r}")
        if self.lever_arm_m > 5.0:
            raise ValueError(f"lever_arm_m must be in metres (<= 5), got {self.lever_arm_m!r}")
        if self.latency_s > 1.0:
            raise ValueError(f"latency_s must be in seconds (<= 1), got {self.latency_s!r}")

    def resolve(self) -> RigValues:
        return RigValues(lever_arm_m=float(self.lever_arm_m), lever_arm_up_m=float(self.lever_arm_up_m),
                         move_rate_rad_s=self.move_rate_deg_s * DEG, move_accel_rad_s2=self.move_accel_deg_s2 * DEG,
                         hold_s=float(self.hold_s), step_rad=self.step_deg * DEG, axis_rest_s=float(self.axis_rest_s),
                         latency_s=float(self.latency_s),
                         reference_error_rad=self.reference_error_arcsec * DEG / 3600.0, zvd=self.zvd)


def lever_arm_vector(axis, lever_arm_m: float, lever_arm_up_m: float) -> np.ndarray:
    """Lever arm (IMU frame, m): ``lever_arm_m`` along the chord v × z, plus ``lever_arm_up_m`` along z."""
    v = np.asarray(axis, float)
    chord = np.cross(v, [0.0, 0.0, 1.0])
    chord /= np.linalg.norm(chord)
    return lever_arm_m * chord + np.array([0.0, 0.0, lever_arm_up_m])


def gravity0(q_wb0=(1.0, 0.0, 0.0, 0.0)) -> np.ndarray:
    """ā0: specific force at rest at θ = 0 in the IMU frame (m/s²); identity = IMU level."""
    c = rotations.quat_to_matrix(np.asarray(q_wb0, float))
    return c.T @ np.array([0.0, 0.0, STANDARD_GRAVITY_M_S2])


@dataclass(frozen=True)
class Scenario:
    """A full wang2022sensors scenario: IMU, rig, Fig. 11 axis, EKF switching."""

    imu: ImuValues
    rig: RigSetup
    fig11_axis: tuple = PAPER_AXIS_FIG11
    sensor_grade: str = "wang2022sensors"


#: Parameters-cell defaults (the paper's setting where it states one; mtcal's stated choice otherwise).
PARAMETER_DEFAULTS = {
    "sensor_grade": "wang2022sensors",
    "fs_hz": 200.0,
    "fig11_axis": PAPER_AXIS_FIG11,
    "lever_arm_m": 0.2,
    "move_rate_deg_s": 20.0,
    "move_accel_deg_s2": 1000.0,
    "hold_s": 1.0,
    "step_deg": 10.0,
    "latency_s": 0.0,
    "zvd_accel_min_m_s2": 9.76,
    "zvd_accel_max_m_s2": 9.84,
    "zvd_var_threshold_m2_s4": 0.001,
    "zvd_gyro_max_deg_s": 2.0,
}


def scenario_from_parameters(**params) -> Scenario:
    """Build and validate a :class:`Scenario` from parameters-cell values (missing ones default).

    Raises ``ValueError`` naming the parameter and the valid names/range.
    """
    p = merge_parameters(params, PARAMETER_DEFAULTS)
    if not isinstance(p["fs_hz"], (int, float)) or not np.isfinite(p["fs_hz"]) or p["fs_hz"] <= 0:
        raise ValueError(f"fs_hz must be > 0 (Hz), got {p['fs_hz']!r}")
    axis = np.asarray(p["fig11_axis"], float)
    if axis.shape != (3,) or not np.all(np.isfinite(axis)) or np.linalg.norm(axis) < 1e-9:
        raise ValueError(f"fig11_axis must be a non-zero 3-vector, got {p['fig11_axis']!r}")
    if abs(axis[2]) / np.linalg.norm(axis) > np.sin(np.radians(85.0)):
        raise ValueError("fig11_axis must be at least 5° off vertical (the accelerometer cannot see the rotation)")
    gmax = p["zvd_gyro_max_deg_s"]
    zvd = ZvdParams(accel_min_m_s2=p["zvd_accel_min_m_s2"], accel_max_m_s2=p["zvd_accel_max_m_s2"],
                    var_threshold_m2_s4=p["zvd_var_threshold_m2_s4"],
                    gyro_max_rad_s=None if gmax is None else float(gmax) * DEG)
    imu = imu_from_grade(p["sensor_grade"], fs_hz=float(p["fs_hz"]))
    rig = RigSetup(lever_arm_m=p["lever_arm_m"], move_rate_deg_s=p["move_rate_deg_s"],
                   move_accel_deg_s2=p["move_accel_deg_s2"], hold_s=p["hold_s"], step_deg=p["step_deg"],
                   latency_s=p["latency_s"], zvd=zvd)
    return Scenario(imu=imu, rig=rig, fig11_axis=tuple(float(x) for x in axis), sensor_grade=p["sensor_grade"])


def labels(sc: Scenario) -> dict[str, str]:
    """Display labels derived from the scenario values (figure titles, table headers)."""
    r = sc.rig
    z = r.zvd
    zvd = "Table 1 ZVD" + ("" if z.gyro_max_rad_s is None else f" + ‖ω‖ < {z.gyro_max_rad_s / DEG:.3g}°/s")
    return {"imu": f"{sc.sensor_grade} IMU, {sc.imu.accel_noise_m_s2_rt_hz / UG:.3g} µg/√Hz, {sc.imu.fs_hz:.0f} Hz",
            "rig": (f"lever arm {r.lever_arm_m:g} m, turntable {r.move_rate_deg_s:g}°/s and "
                    f"{r.move_accel_deg_s2:g}°/s², latency {r.latency_s * 1e3:g} ms"),
            "sweep": f"{r.step_deg:g}° steps with {r.hold_s:g} s holds",
            "zvd": zvd,
            "axis": "v = [" + ", ".join(f"{x:.4f}" for x in np.asarray(sc.fig11_axis) /
                                        np.linalg.norm(sc.fig11_axis)) + "]"}
