"""Sensor-grade catalogue: named MEMS IMU error models with datasheet-style values.

Each :class:`SensorGrade` holds the numbers an engineer reads off a datasheet, in
the datasheet's units (°/√h, °/h, µg/√Hz, mg, ppm), and converts them once to an
SI :class:`~mtcal.core.sensors.SensorSpec` (the one sensor-spec type; it owns the
sample rate) with :meth:`SensorGrade.sensor_spec` / :func:`sensor_spec`, whose
:meth:`~mtcal.core.sensors.SensorSpec.error_model` is the one conversion to the
simulator's :class:`~mtcal.core.simulate.ImuErrorModel`.
Use a grade by name in a notebook's parameters cell (``gyro_grade="industrial"``)
or from the library (:func:`sensor_grade`).

The values are typical of a class, not of one part; the ``source`` of each grade
names the parts it was read from. The papers' own sensors are included:
``wang2023cja`` (the tactical MEMS assumed for Wang 2023, which prints no sensor
numbers), ``wang2022sensors`` (Table 3 of Wang 2022) and ``tan2022`` (the 0.2 °/s
gyro error and 1e-4 g accelerometer error of Tan 2022's analysis).

Conversions (white noise and instability):

* angle random walk ARW [°/√h] → gyro noise density [rad/s/√Hz] = ARW · (π/180) / 60
* accelerometer noise density [µg/√Hz] → [m/s²/√Hz] = value · 9.80665e-6
* bias instability [°/h] → [rad/s] = value · (π/180) / 3600 (1σ of a Gauss–Markov
  bias with correlation time ``bias_instability_tau_s``)
* turn-on bias repeatability [°/h] or [mg] → 1σ of a bias drawn once per trial

References
----------
.. [1] IEEE Std 952-1997, *IEEE Standard Specification Format Guide and Test Procedure
   for Single-Axis Interferometric Fiber Optic Gyros* (ARW and bias-instability
   definitions used by MEMS datasheets).
.. [2] Analog Devices ADIS16470, ADIS16495, ADXL355 data sheets; Bosch BMI088 data
   sheet; TDK InvenSense ICM-20948 data sheet; Safran STIM300 data sheet;
   Honeywell HG4930 data sheet (values rounded to the class).

Examples
--------
>>> from mtcal.core.sensor_grades import sensor_grade, GRADES
>>> g = sensor_grade("industrial")
>>> round(g.gyro_arw_deg_rt_h, 2), round(g.gyro_bias_instability_deg_h, 1)
(0.3, 5.0)
>>> model = g.error_model()
>>> f"{model.gyro.noise_density:.3e}"  # rad/s/√Hz
'8.727e-05'
>>> sorted(GRADES)[:3]
['consumer', 'industrial', 'navigation']
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, replace

from mtcal.core.sensors import SensorSpec
from mtcal.core.simulate import ImuErrorModel
from mtcal.core.units import DEG, DEG_H, MG, UG
from mtcal.core.validate import positive_scalar

__all__ = ["SensorGrade", "GRADES", "sensor_grade", "grade_names", "sensor_spec"]


@dataclass(frozen=True)
class SensorGrade:
    """Datasheet-style error model of one IMU class (datasheet units; see module doc).

    Parameters
    ----------
    name : str
        Catalogue key.
    gyro_arw_deg_rt_h : float
        Gyro angle random walk (°/√h).
    gyro_bias_instability_deg_h : float
        Gyro in-run bias instability (°/h, 1σ Gauss–Markov).
    gyro_bias_repeatability_deg_h : float
        Gyro turn-on bias left after compensation (°/h, 1σ per trial).
    gyro_scale_factor_ppm : float
        Gyro residual scale-factor error (ppm, 1σ per axis per trial is *not* drawn:
        applied as a fixed +, −, + pattern so runs are comparable).
    accel_noise_ug_rt_hz : float
        Accelerometer noise density (µg/√Hz).
    accel_bias_instability_ug : float
        Accelerometer in-run bias instability (µg, 1σ Gauss–Markov).
    accel_bias_repeatability_mg : float
        Accelerometer turn-on bias left after compensation (mg, 1σ per trial).
    bias_instability_tau_s : float
        Correlation time of both Gauss–Markov biases (s).
    source : str
        Where the values come from.
    """

    name: str
    gyro_arw_deg_rt_h: float
    gyro_bias_instability_deg_h: float
    gyro_bias_repeatability_deg_h: float
    gyro_scale_factor_ppm: float
    accel_noise_ug_rt_hz: float
    accel_bias_instability_ug: float
    accel_bias_repeatability_mg: float
    bias_instability_tau_s: float = 100.0
    source: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f"name must be a non-empty str, got {self.name!r}")
        for f in ("gyro_arw_deg_rt_h", "gyro_bias_instability_deg_h", "gyro_bias_repeatability_deg_h",
                  "gyro_scale_factor_ppm", "accel_noise_ug_rt_hz", "accel_bias_instability_ug",
                  "accel_bias_repeatability_mg"):
            positive_scalar(getattr(self, f), f, allow_zero=True)
        positive_scalar(self.bias_instability_tau_s, "bias_instability_tau_s")

    # SI views -------------------------------------------------------------
    @property
    def gyro_noise_density_rad_s_rt_hz(self) -> float:
        """Gyro white-noise density (rad/s/√Hz) = ARW · (π/180) / 60."""
        return self.gyro_arw_deg_rt_h * DEG / 60.0

    @property
    def accel_noise_density_m_s2_rt_hz(self) -> float:
        """Accelerometer white-noise density (m/s²/√Hz)."""
        return self.accel_noise_ug_rt_hz * UG

    def with_overrides(self, **values) -> "SensorGrade":
        """A copy with some datasheet values changed (e.g. ``gyro_arw_deg_rt_h=0.5``).

        Raises ``ValueError`` naming the valid fields for an unknown name.
        """
        valid = set(asdict(self)) - {"name"}
        unknown = sorted(set(values) - valid)
        if unknown:
            raise ValueError(f"unknown sensor field(s) {unknown}; valid: {sorted(valid)}")
        return replace(self, name=f"{self.name}*" if values else self.name, **values)

    def sensor_spec(self, fs_hz: float = 1000.0, *, time_since_power_on_s: float = 300.0,
                    label: str | None = None) -> SensorSpec:
        """The SI :class:`~mtcal.core.sensors.SensorSpec` of this grade at output rate ``fs_hz``.

        Gyro scale factor applied as a fixed +, −, + pattern; turn-on biases as per-trial 1σ.

        Examples
        --------
        >>> s = sensor_grade("tactical").sensor_spec(200.0)
        >>> s.fs_hz, s.gyro_scale_factor
        (200.0, (0.0003, -0.0003, 0.0003))
        """
        sf = self.gyro_scale_factor_ppm * 1e-6
        return SensorSpec(fs_hz=fs_hz, label=self.name if label is None else label,
                          gyro_noise_rad_s_rt_hz=self.gyro_noise_density_rad_s_rt_hz,
                          gyro_bias_instability_rad_s=self.gyro_bias_instability_deg_h * DEG_H,
                          gyro_bias_sigma_rad_s=self.gyro_bias_repeatability_deg_h * DEG_H,
                          gyro_scale_factor=(sf, -sf, sf),
                          accel_noise_m_s2_rt_hz=self.accel_noise_density_m_s2_rt_hz,
                          accel_bias_instability_m_s2=self.accel_bias_instability_ug * UG,
                          accel_bias_sigma_m_s2=self.accel_bias_repeatability_mg * MG,
                          bias_instability_tau_s=self.bias_instability_tau_s,
                          time_since_power_on_s=time_since_power_on_s)

    def error_model(self, q_mount=(1.0, 0.0, 0.0, 0.0), time_since_power_on_s: float = 300.0) -> ImuErrorModel:
        """The SI :class:`~mtcal.core.simulate.ImuErrorModel` of this grade (via :meth:`sensor_spec`).

        Parameters
        ----------
        q_mount : 4-tuple
            Scalar-first mounting quaternion ``q_bs``.
        time_since_power_on_s : float
            Seconds since power-on (no warm-up transient is modelled by a grade).
        """
        return self.sensor_spec(time_since_power_on_s=time_since_power_on_s).error_model(q_mount)


#: Columns of :data:`_CATALOGUE` (the :class:`SensorGrade` fields, in this order).
_COLUMNS = ("name", "gyro_arw_deg_rt_h", "gyro_bias_instability_deg_h", "gyro_bias_repeatability_deg_h",
            "gyro_scale_factor_ppm", "accel_noise_ug_rt_hz", "accel_bias_instability_ug",
            "accel_bias_repeatability_mg", "source")
_CATALOGUE = (
    # name, gyro ARW °/√h, gyro bias instability °/h, gyro bias repeatability °/h, gyro scale factor ppm,
    # accel noise µg/√Hz, accel bias instability µg, accel bias repeatability mg; source
    ("consumer",                0.6, 20.0,        360.0, 3000.0, 150.0, 100.0, 20.0,
     "consumer MEMS (ICM-20948 / BMI088 class: 0.015 °/s/√Hz ≈ 0.6–0.9 °/√h, 150–230 µg/√Hz; "
     "turn-on bias after a user calibration ~0.1 °/s, ~20 mg)"),
    ("industrial",              0.3,  5.0,         30.0, 1000.0,  60.0,  15.0,  2.0,
     "industrial MEMS (ADIS16470 class: ARW 0.34 °/√h, in-run 8 °/h, accel 13 µg in-run)"),
    ("tactical",                0.1,  0.8,          3.0,  300.0,  25.0,   5.0,  0.1,
     "tactical MEMS (ADIS16495 / STIM300 class: ARW 0.12–0.15 °/√h, 0.5–0.8 °/h; "
     "ADXL355 25 µg/√Hz)"),
    ("navigation",             0.04, 0.25,          1.0,  100.0,  15.0,   3.0, 0.05,
     "navigation-grade MEMS (HG4930 class: ARW 0.04 °/√h, 0.25 °/h, accel 25 µg in-run)"),
    ("wang2023cja",             0.1,  0.8,          0.3,  100.0,  25.0,   0.0, 0.05,
     "Wang 2023 (Chin. J. Aeronaut.) prints no sensor numbers: the tactical MEMS assumed "
     "by mtcal.studies.wang2023cja.ImuSpec (factory-compensated, after warm-up)"),
    ("wang2022sensors", 0.02 * 60.0,  0.0, 0.7 * 3600.0,    0.0,  50.0,   0.0,  0.1,
     "Wang 2022 (Sensors) Table 3: gyro 0.02 °/s/√Hz (= 1.2 °/√h), bias 0.7 °/s; "
     "accel 50 µg/√Hz; accel bias after the paper's calibration 0.1 mg (mtcal)"),
    ("tan2022",                 0.0,  0.0, 0.2 * 3600.0,    0.0,   0.0,   0.0,  0.1,
     "Tan 2022 error analysis: gyro error 0.2 °/s, accelerometer error ΔA = 1e-4 g"),
)
GRADES: dict[str, SensorGrade] = {row[0]: SensorGrade(**dict(zip(_COLUMNS, row))) for row in _CATALOGUE}


def grade_names() -> list[str]:
    """Names of the catalogue's grades, sorted."""
    return sorted(GRADES)


def sensor_grade(name: str, **overrides) -> SensorGrade:
    """Look up a grade by name, optionally overriding datasheet values.

    Raises
    ------
    ValueError
        For an unknown name (the message lists the valid ones) or an unknown field.

    Examples
    --------
    >>> sensor_grade("tactical", gyro_arw_deg_rt_h=0.2).gyro_arw_deg_rt_h
    0.2
    """
    if name not in GRADES:
        raise ValueError(f"grade must be one of {grade_names()}, got {name!r}")
    return GRADES[name].with_overrides(**overrides) if overrides else GRADES[name]


def sensor_spec(gyro_grade: str, accel_grade: str | None = None, *, fs_hz: float = 1000.0,
                time_since_power_on_s: float = 300.0) -> SensorSpec:
    """SI :class:`~mtcal.core.sensors.SensorSpec` from a gyro grade and an accelerometer grade (default: the same).

    Raises
    ------
    ValueError
        For an unknown grade name (the message lists the valid ones) or a bad ``fs_hz``.

    Examples
    --------
    >>> s = sensor_spec("industrial", "tactical", fs_hz=200.0)
    >>> s.label, round(s.accel_noise_m_s2_rt_hz / 9.80665e-6, 6)
    ('gyro industrial, accel tactical', 25.0)
    """
    accel_grade = gyro_grade if accel_grade is None else accel_grade
    g = sensor_grade(gyro_grade).sensor_spec(fs_hz, time_since_power_on_s=time_since_power_on_s)
    a = sensor_grade(accel_grade)
    return replace(g, label=f"gyro {gyro_grade}, accel {accel_grade}", accel_noise_m_s2_rt_hz=a.accel_noise_density_m_s2_rt_hz,
                   accel_bias_instability_m_s2=a.accel_bias_instability_ug * UG,
                   accel_bias_sigma_m_s2=a.accel_bias_repeatability_mg * MG)
