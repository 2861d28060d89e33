"""tan2022 (Tan et al., 2022) scenarios: the paper's parameters plus stated choices.

Every field carries the paper's value where one exists (the shipped table
``mtcal/reporting/paper_data/tan2022_params.csv``) and otherwise a choice with
its source. Fields are in the paper's display units (named ``_deg``, ``_g``,
``_deg_s``); properties give the library units (rad, rad/s, m/s²).
:data:`PARAMETER_DEFAULTS` holds the notebooks' parameters-cell defaults once;
:func:`accel_scenario` and :func:`gyro_study` build validated scenarios from
parameters-cell values (one-line ``ValueError`` naming the parameter).

References
----------
Tan Q., Cheng Y., Tang B., Liu X., Zhou H., Li Y., "Large-angle attitude measurement
algorithm with pitch/roll coupling" (in Chinese), J. Terahertz Sci. Electron. Inf.
Technol. 2022, 20(9):946–952, doi:10.11805/TKYDA2020404.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from mtcal.core.sensors import SensorSpec
from mtcal.core.validate import STANDARD_GRAVITY_M_S2, as_float_array, merge_parameters, positive_scalar

__all__ = ["AccelScenario", "GyroErrors", "ProjectionSweep", "UniformRotation", "Oscillation", "GyroStudy",
           "ACCEL_PARAMETER_DEFAULTS", "GYRO_PARAMETER_DEFAULTS",
           "PARAMETER_DEFAULTS", "accel_scenario", "gyro_study"]


def _positive_tuple(values, name: str) -> tuple:
    arr = as_float_array(values, name, ndim=1)
    if np.any(arr <= 0):
        raise ValueError(f"{name} must be positive, got {tuple(arr)}")
    return tuple(float(v) for v in arr)


@dataclass(frozen=True)
class AccelScenario:
    """Accelerometer error analysis, Figs 2, 5, 8 (Sec. 1.1, 2.1, 3.1).

    Attributes
    ----------
    delta_accel_g : float
        Common-mode error ΔA on every axis, 1e-4 g (Sec. 1.1: "10^-4 g 量级",
        an order of magnitude; the error formulas are linear in it).
    lambda1_deg, lambda2_deg : float
        Preset angles 45° (θ ≤ 0) and −135° (θ ≥ 0), Eq 9.
    grid_step_deg : float
        θ, φ grid step over [−90°, 90°]; 1° (choice: the paper's figures are
        smooth contours over this range).
    independent_sigma_g : float
        1σ of *independent* per-axis errors for the beyond-paper Monte Carlo;
        1e-4 g, the same size as ΔA (choice, so the two cases compare).
    gravity_m_s2 : float
        Standard gravity.
    """

    delta_accel_g: float = 1e-4
    lambda1_deg: float = 45.0
    lambda2_deg: float = -135.0
    grid_step_deg: float = 1.0
    independent_sigma_g: float = 1e-4
    gravity_m_s2: float = STANDARD_GRAVITY_M_S2

    def __post_init__(self) -> None:
        for name in ("delta_accel_g", "grid_step_deg", "independent_sigma_g", "gravity_m_s2"):
            positive_scalar(getattr(self, name), name)
        if self.delta_accel_g > 0.1 or self.independent_sigma_g > 0.1:
            raise ValueError("delta_accel_g and independent_sigma_g are in g and must be <= 0.1")
        if not 0 < self.grid_step_deg <= 45:
            raise ValueError(f"grid_step_deg must be in (0, 45], got {self.grid_step_deg}")

    @property
    def delta_accel_m_s2(self) -> float:
        """ΔA in m/s²."""
        return self.delta_accel_g * self.gravity_m_s2

    @property
    def independent_sigma_m_s2(self) -> float:
        """Independent-error 1σ in m/s²."""
        return self.independent_sigma_g * self.gravity_m_s2

    def grid_rad(self, step_deg: float | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Meshgrid ``(θ, φ)`` in rad over [−90°, 90°]², ``indexing='ij'`` (θ along axis 0)."""
        step = self.grid_step_deg if step_deg is None else positive_scalar(step_deg, "step_deg")
        n = int(round(180.0 / step)) + 1
        axis = np.radians(np.linspace(-90.0, 90.0, n))
        return np.meshgrid(axis, axis, indexing="ij")


@dataclass(frozen=True)
class GyroErrors:
    """Gyro errors and sampling for the roll simulations (Sec. 2.2.2, 3.2).

    Attributes
    ----------
    error_deg_s : 3-tuple
        Constant output error per axis, 0.2 °/s (Sec. 2.2.2, Fig 6; Sec. 3.2
        "各轴"). The paper prints it for x and z only, but Eq 14 needs y and z
        (paper README tan2022 item 4): all three axes get 0.2 °/s here.
    noise_density_deg_s_rthz : float
        White noise 0.0025 °/s/√Hz (choice: angle random walk 0.15 °/√h of an
        ADIS16465-class MEMS IMU, the high-grade MEMS unit named in wang2022sensors
        Table 2); the paper's simulations have only the constant error.
    fs_hz : float
        Gyro sample rate 1000 Hz (choice: the 1 kHz of wang2023cja; tan2022 gives none).
    roll0_deg : float
        Initial roll φ0 = 0° (Sec. 3.2).
    """

    error_deg_s: tuple = (0.2, 0.2, 0.2)
    noise_density_deg_s_rthz: float = 0.0025
    fs_hz: float = 1000.0
    roll0_deg: float = 0.0

    def __post_init__(self) -> None:
        err = as_float_array(self.error_deg_s, "error_deg_s", ndim=1, last_dim=3)
        object.__setattr__(self, "error_deg_s", tuple(float(v) for v in err))
        positive_scalar(self.noise_density_deg_s_rthz, "noise_density_deg_s_rthz", allow_zero=True)
        positive_scalar(self.fs_hz, "fs_hz")
        if abs(self.roll0_deg) > 90:
            raise ValueError(f"roll0_deg must be within [-90, 90], got {self.roll0_deg}")

    @property
    def error_rad_s(self) -> np.ndarray:
        """Constant gyro error per axis (rad/s)."""
        return np.radians(np.array(self.error_deg_s))

    @property
    def noise_density_rad_s_rthz(self) -> float:
        """White-noise density (rad/s/√Hz)."""
        return float(np.radians(self.noise_density_deg_s_rthz))

    @property
    def dt_s(self) -> float:
        """Sample interval (s)."""
        return 1.0 / self.fs_hz

    @property
    def roll0_rad(self) -> float:
        """Initial roll (rad)."""
        return float(np.radians(self.roll0_deg))

    def sensor_spec(self) -> SensorSpec:
        """The gyro as the one SI sensor-spec type (:class:`mtcal.core.sensors.SensorSpec`, owns ``fs_hz``):
        constant error = fixed bias, white noise; the accelerometer is not simulated in the roll runs."""
        return SensorSpec(fs_hz=float(self.fs_hz), label="tan2022 gyro",
                          gyro_bias_rad_s=tuple(float(v) for v in self.error_rad_s),
                          gyro_noise_rad_s_rt_hz=self.noise_density_rad_s_rthz)


@dataclass(frozen=True)
class ProjectionSweep:
    """Roll error of the projection method vs pitch rate (Fig 6, Eq 14).

    Attributes
    ----------
    rate_min_deg_s, rate_max_deg_s : float
        Pitch-rate range 0.5…100 °/s (choice: from the paper's threshold
        θ̇_t = 0.5 °/s up to beyond the 60 °/s of Fig 9).
    n_rates : int
        Number of log-spaced rates (choice).
    window_s : float
        Simulated duration per rate, 1 s (choice).
    roll_deg : float
        True roll 0° (Sec. 3.2 φ0 = 0).
    fit_min_deg_s : float
        Lower end of the log-log slope fit, 5 °/s (choice: where Eq 14 is
        first-order accurate, Δω/θ̇ ≤ 0.04).
    gyro : GyroErrors
    """

    rate_min_deg_s: float = 0.5
    rate_max_deg_s: float = 100.0
    n_rates: int = 25
    window_s: float = 1.0
    roll_deg: float = 0.0
    fit_min_deg_s: float = 5.0
    gyro: GyroErrors = field(default_factory=GyroErrors)

    def __post_init__(self) -> None:
        for name in ("rate_min_deg_s", "rate_max_deg_s", "window_s", "fit_min_deg_s"):
            positive_scalar(getattr(self, name), name)
        if self.rate_max_deg_s <= self.rate_min_deg_s:
            raise ValueError("rate_max_deg_s must exceed rate_min_deg_s")
        if self.n_rates < 3:
            raise ValueError(f"n_rates must be >= 3, got {self.n_rates}")

    @property
    def rates_rad_s(self) -> np.ndarray:
        """Log-spaced pitch rates (rad/s)."""
        return np.radians(np.geomspace(self.rate_min_deg_s, self.rate_max_deg_s, self.n_rates))


@dataclass(frozen=True)
class UniformRotation:
    """Uniform pitch rotation through ±90° (Fig 9, Sec. 3.2).

    Attributes
    ----------
    pitch_rates_deg_s : tuple
        10, 20, 60 °/s (Sec. 3.2).
    roll_rate_deg_s : float
        0 °/s (Sec. 3.2).
    pitch_start_deg : float
        0° (choice: level start).
    sweep_deg : float
        360°: one revolution, passing θ = +90° and θ = 270° ≡ −90° (choice;
        the paper's time axis is not given).
    gyro : GyroErrors
    """

    pitch_rates_deg_s: tuple = (10.0, 20.0, 60.0)
    roll_rate_deg_s: float = 0.0
    pitch_start_deg: float = 0.0
    sweep_deg: float = 360.0
    gyro: GyroErrors = field(default_factory=GyroErrors)

    def __post_init__(self) -> None:
        object.__setattr__(self, "pitch_rates_deg_s", _positive_tuple(self.pitch_rates_deg_s,
                                                                       "pitch_rates_deg_s"))
        positive_scalar(self.sweep_deg, "sweep_deg")
        if self.sweep_deg > 720:
            raise ValueError(f"sweep_deg must be <= 720, got {self.sweep_deg}")

    def profile(self, rate_deg_s: float) -> tuple[np.ndarray, np.ndarray]:
        """``(time_s, pitch_rad)`` of the uniform rotation at ``rate_deg_s``."""
        rate = positive_scalar(rate_deg_s, "rate_deg_s")
        t = np.arange(0.0, self.sweep_deg / rate, self.gyro.dt_s)
        return t, np.radians(self.pitch_start_deg + rate * t)


@dataclass(frozen=True)
class Oscillation:
    """Pitch oscillation θ = θm sin(2π f t) (Eq 16–17, Figs 10–12).

    Attributes
    ----------
    amplitude_deg : float
        θm = 40° (Sec. 3.2).
    freq_hz : float
        f = 0.5 Hz (Sec. 3.2).
    duration_s : float
        20 s = 10 periods (choice; the paper's time axis is not given).
    threshold_deg_s : float
        θ̇_t = 0.5 °/s (Sec. 3.2, Fig 12).
    gyro : GyroErrors
    """

    amplitude_deg: float = 40.0
    freq_hz: float = 0.5
    duration_s: float = 20.0
    threshold_deg_s: float = 0.5
    gyro: GyroErrors = field(default_factory=GyroErrors)

    def __post_init__(self) -> None:
        for name in ("amplitude_deg", "freq_hz", "duration_s"):
            positive_scalar(getattr(self, name), name)
        positive_scalar(self.threshold_deg_s, "threshold_deg_s", allow_zero=True)
        if self.amplitude_deg >= 90:
            raise ValueError(f"amplitude_deg must be < 90, got {self.amplitude_deg}")

    @property
    def threshold_rad_s(self) -> float:
        """θ̇_t in rad/s."""
        return float(np.radians(self.threshold_deg_s))

    @property
    def peak_rate_deg_s(self) -> float:
        """Peak pitch rate 2π f θm (°/s), Eq 17."""
        return 2 * np.pi * self.freq_hz * self.amplitude_deg

    def time_s(self) -> np.ndarray:
        """Sample times (s)."""
        return np.arange(0.0, self.duration_s, self.gyro.dt_s)

    def pitch_rad(self, time_s) -> np.ndarray:
        """Eq 16: θ(t) in rad."""
        t = as_float_array(time_s, "time_s")
        return np.radians(self.amplitude_deg) * np.sin(2 * np.pi * self.freq_hz * t)

    def pitch_rate_rad_s(self, time_s) -> np.ndarray:
        """Eq 17: θ̇(t) in rad/s."""
        t = as_float_array(time_s, "time_s")
        return 2 * np.pi * self.freq_hz * np.radians(self.amplitude_deg) * np.cos(2 * np.pi * self.freq_hz * t)


@dataclass(frozen=True)
class GyroStudy:
    """Everything notebook 21 runs, resolved once from the parameters cell.

    Attributes
    ----------
    gyro : GyroErrors
    sweep : ProjectionSweep
        Fig 6.
    uniform : UniformRotation
        Fig 9.
    oscillation : Oscillation
        Figs 10–12.
    """

    gyro: GyroErrors = field(default_factory=GyroErrors)
    sweep: ProjectionSweep = field(default_factory=ProjectionSweep)
    uniform: UniformRotation = field(default_factory=UniformRotation)
    oscillation: Oscillation = field(default_factory=Oscillation)


#: Parameters-cell defaults of notebook 20 (the paper's values; units in the names).
ACCEL_PARAMETER_DEFAULTS: dict = {"accel_error_g": 1e-4, "lambda1_deg": 45.0, "lambda2_deg": -135.0}

#: Parameters-cell defaults of notebook 21 (the paper's values, noise density our choice).
GYRO_PARAMETER_DEFAULTS: dict = {"gyro_error_x_deg_s": 0.2, "gyro_error_y_deg_s": 0.2, "gyro_error_z_deg_s": 0.2,
                                 "gyro_noise_density_deg_s_rthz": 0.0025, "fs_hz": 1000.0,
                                 "pitch_rates_deg_s": (10.0, 20.0, 60.0), "oscillation_amplitude_deg": 40.0,
                                 "oscillation_freq_hz": 0.5, "threshold_deg_s": 0.5, "roll0_deg": 0.0}

#: All tan2022 parameters (both notebooks).
PARAMETER_DEFAULTS: dict = {**ACCEL_PARAMETER_DEFAULTS, **GYRO_PARAMETER_DEFAULTS}


def accel_scenario(*, grid_step_deg: float = 1.0, **params) -> AccelScenario:
    """Build the notebook-20 scenario from parameters-cell values (validated).

    Parameters
    ----------
    grid_step_deg : float
        θ, φ grid step of the error maps (deg); a run-size choice, not a scenario parameter.
    **params
        Any of :data:`ACCEL_PARAMETER_DEFAULTS`: ``accel_error_g`` (ΔA, g, in
        (0, 0.1]), ``lambda1_deg``, ``lambda2_deg`` (preset angles, deg).

    Examples
    --------
    >>> accel_scenario(accel_error_g=1e-3).delta_accel_g
    0.001
    >>> accel_scenario(accel_error=1e-3)
    Traceback (most recent call last):
    ...
    ValueError: unknown tan2022 parameter(s) ['accel_error']; valid: ['accel_error_g', 'lambda1_deg', 'lambda2_deg']
    """
    p = merge_parameters(params, ACCEL_PARAMETER_DEFAULTS, what="tan2022 parameter")
    for name in ("lambda1_deg", "lambda2_deg"):
        v = p[name]
        if isinstance(v, bool) or not isinstance(v, (int, float, np.floating)) or not -180 <= v <= 180:
            raise ValueError(f"{name} must be a number of degrees within [-180, 180], got {v!r}")
    return AccelScenario(delta_accel_g=float(p["accel_error_g"]), lambda1_deg=float(p["lambda1_deg"]),
                         lambda2_deg=float(p["lambda2_deg"]), grid_step_deg=grid_step_deg)


def gyro_study(*, oscillation_duration_s: float = 20.0, **params) -> GyroStudy:
    """Build the notebook-21 scenarios from parameters-cell values (validated).

    Parameters
    ----------
    oscillation_duration_s : float
        Record length of the oscillation runs (s); a run-size choice, not a
        scenario parameter.
    **params
        Any of :data:`GYRO_PARAMETER_DEFAULTS` (units in the names).

    Examples
    --------
    >>> gyro_study(gyro_error_z_deg_s=0.05).gyro.error_deg_s
    (0.2, 0.2, 0.05)
    >>> gyro_study(fs_hz=-1.0)
    Traceback (most recent call last):
    ...
    ValueError: fs_hz must be > 0, got -1.0
    """
    p = merge_parameters(params, GYRO_PARAMETER_DEFAULTS, what="tan2022 parameter")
    err = tuple(float(p[f"gyro_error_{a}_deg_s"]) for a in "xyz")
    for a, v in zip("xyz", err):
        if not np.isfinite(v) or abs(v) > 100:
            raise ValueError(f"gyro_error_{a}_deg_s must be a finite error in deg/s with |value| <= 100, got {v}")
    gyro = GyroErrors(error_deg_s=err, noise_density_deg_s_rthz=float(p["gyro_noise_density_deg_s_rthz"]),
                      fs_hz=float(p["fs_hz"]), roll0_deg=float(p["roll0_deg"]))
    return GyroStudy(gyro=gyro, sweep=ProjectionSweep(gyro=gyro),
                     uniform=UniformRotation(pitch_rates_deg_s=p["pitch_rates_deg_s"], gyro=gyro),
                     oscillation=Oscillation(amplitude_deg=float(p["oscillation_amplitude_deg"]),
                                             freq_hz=float(p["oscillation_freq_hz"]),
                                             duration_s=positive_scalar(oscillation_duration_s,
                                                                        "oscillation_duration_s"),
                                             threshold_deg_s=float(p["threshold_deg_s"]), gyro=gyro))
