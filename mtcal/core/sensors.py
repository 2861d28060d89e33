"""One sensor-spec type for every study: an IMU's error sources in SI units, and its sample rate.

:class:`SensorSpec` is what a scenario holds about its IMU, already in plain SI
values (rad/s, m/s², s, Hz) — the one unit convention. Datasheet units (°/√h,
µg/√Hz, mg, ppm) are converted once, where the numbers are read
(:func:`mtcal.core.sensor_grades.sensor_spec` for a catalogue grade, or a
study's scenario builder for the paper's table).

Time base: the spec owns the IMU's output rate ``fs_hz`` (``dt_s = 1 / fs_hz``);
a scenario reads its sample rate from its spec, never stores a second copy.
Gyro sample k is the mean rate over ``[t_k, t_{k+1}]``, the accelerometer
sample k is at ``t_k`` (:mod:`mtcal.core.simulate`).

:meth:`SensorSpec.error_model` is the one conversion to the simulator's
:class:`~mtcal.core.simulate.ImuErrorModel`, optionally with only some error
sources switched on (:data:`SENSOR_SOURCES`, for error budgets).

Examples
--------
>>> spec = SensorSpec(fs_hz=200.0, gyro_noise_rad_s_rt_hz=1e-4, accel_bias_sigma_m_s2=1e-3)
>>> spec.dt_s, spec.resolve() is spec
(0.005, True)
>>> m = spec.error_model(sources=("gyro_white",))
>>> m.gyro.noise_density, m.accel.bias_sigma
(0.0001, 0.0)
>>> SensorSpec(fs_hz=0.0)
Traceback (most recent call last):
...
ValueError: fs_hz must be > 0 (Hz), got 0.0
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields

import numpy as np

from mtcal.core.simulate import ImuErrorModel, SensorErrors

__all__ = ["SensorSpec", "SENSOR_SOURCES"]

#: Error sources of a spec that :meth:`SensorSpec.error_model` can switch individually.
SENSOR_SOURCES = ("gyro_white", "gyro_bias_instability", "gyro_residual_bias", "gyro_fixed_bias", "gyro_random_walk",
                  "gyro_warmup", "gyro_scale_factor", "accel_white", "accel_bias", "accel_fixed_bias",
                  "accel_bias_instability", "accel_random_walk", "quantisation")

def _f(value, unit: str, what: str):
    """Field with unit and meaning (``source``) metadata (:func:`mtcal.reporting.compare.describe`)."""
    return field(default=value, metadata={"unit": unit, "source": what})


_TUPLES = ("gyro_bias_rad_s", "gyro_warmup_bias_rad_s", "accel_bias_m_s2")


@dataclass(frozen=True)
class SensorSpec:
    """An IMU's error sources in SI units and its output rate (see the module doc).

    Parameters
    ----------
    fs_hz : float
        Output (sample) rate (Hz); the time base of every record of this IMU.
    label : str
        Display label (e.g. the grades it was built from).
    gyro_noise_rad_s_rt_hz : float
        Gyro white-noise density (rad/s/√Hz); per-sample σ = density · √fs.
    gyro_bias_rad_s : 3-tuple
        Fixed (deterministic) gyro bias (rad/s).
    gyro_bias_sigma_rad_s : float
        Turn-on gyro bias, 1σ per axis, drawn once per trial (rad/s).
    gyro_bias_instability_rad_s : float
        In-run bias instability, 1σ of a Gauss–Markov bias with ``bias_instability_tau_s`` (rad/s).
    gyro_rw_rad_s_rt_s : float
        Gyro bias random walk K (rad/s/√s): σ_bias(t) = K √t.
    gyro_warmup_bias_rad_s : 3-tuple
        Bias at power-on decaying with ``gyro_warmup_tau_s`` (rad/s).
    gyro_warmup_tau_s : float
        Warm-up time constant (s).
    gyro_scale_factor : float or 3-tuple
        Residual scale-factor error (1; per axis for a tuple).
    gyro_lsb_rad_s : float
        Output quantisation step (rad/s); 0 = none.
    accel_noise_m_s2_rt_hz : float
        Accelerometer white-noise density (m/s²/√Hz).
    accel_bias_m_s2 : 3-tuple
        Fixed accelerometer bias (m/s²).
    accel_bias_sigma_m_s2 : float
        Turn-on accelerometer bias, 1σ per axis per trial (m/s²).
    accel_bias_instability_m_s2 : float
        Gauss–Markov accelerometer bias instability, 1σ (m/s²).
    accel_rw_m_s2_rt_s : float
        Accelerometer bias random walk (m/s²/√s).
    accel_lsb_m_s2 : float
        Output quantisation step (m/s²).
    bias_instability_tau_s : float
        Correlation time of both Gauss–Markov biases (s).
    time_since_power_on_s : float
        Seconds since power-on at the start of a record (warm-up transient).

    References
    ----------
    IEEE Std 952-1997 (ARW, bias instability); ``docs/study_template.md`` (sensor spec rule).
    """

    fs_hz: float = field(metadata={"unit": "Hz", "source": "output rate (the IMU's time base)"})
    label: str = _f("", "-", "grades or table the values come from")
    gyro_noise_rad_s_rt_hz: float = _f(0.0, "rad/s/√Hz", "gyro white noise (ARW)")
    gyro_bias_rad_s: tuple = _f((0.0, 0.0, 0.0), "rad/s", "fixed gyro bias")
    gyro_bias_sigma_rad_s: float = _f(0.0, "rad/s", "gyro turn-on bias, 1σ per axis per trial")
    gyro_bias_instability_rad_s: float = _f(0.0, "rad/s", "gyro Gauss–Markov bias instability, 1σ")
    gyro_rw_rad_s_rt_s: float = _f(0.0, "rad/s/√s", "gyro bias random walk")
    gyro_warmup_bias_rad_s: tuple = _f((0.0, 0.0, 0.0), "rad/s", "gyro bias at power-on (decays)")
    gyro_warmup_tau_s: float = _f(90.0, "s", "warm-up time constant")
    gyro_scale_factor: float | tuple = _f(0.0, "1", "gyro residual scale-factor error")
    gyro_lsb_rad_s: float = _f(0.0, "rad/s", "gyro output quantisation step")
    accel_noise_m_s2_rt_hz: float = _f(0.0, "m/s²/√Hz", "accelerometer white noise (VRW)")
    accel_bias_m_s2: tuple = _f((0.0, 0.0, 0.0), "m/s²", "fixed accelerometer bias")
    accel_bias_sigma_m_s2: float = _f(0.0, "m/s²", "accelerometer turn-on bias, 1σ per axis per trial")
    accel_bias_instability_m_s2: float = _f(0.0, "m/s²", "accelerometer Gauss–Markov bias instability, 1σ")
    accel_rw_m_s2_rt_s: float = _f(0.0, "m/s²/√s", "accelerometer bias random walk")
    accel_lsb_m_s2: float = _f(0.0, "m/s²", "accelerometer output quantisation step")
    bias_instability_tau_s: float = _f(100.0, "s", "Gauss–Markov correlation time")
    time_since_power_on_s: float = _f(300.0, "s", "time since power-on at the record start")

    def __post_init__(self) -> None:
        if (isinstance(self.fs_hz, bool) or not isinstance(self.fs_hz, (int, float, np.floating))
                or not np.isfinite(self.fs_hz) or self.fs_hz <= 0):
            raise ValueError(f"fs_hz must be > 0 (Hz), got {self.fs_hz!r}")
        if not isinstance(self.label, str):
            raise TypeError(f"label must be a str, got {self.label!r}")
        for f in fields(self):
            if f.name in ("fs_hz", "label"):
                continue
            v = np.asarray(getattr(self, f.name), dtype=float)
            if f.name in _TUPLES or f.name == "gyro_scale_factor":
                if v.shape not in (((3,),) if f.name in _TUPLES else ((), (3,))) or not np.all(np.isfinite(v)):
                    raise ValueError(f"{f.name} must be {'a' if f.name in _TUPLES else 'a number or a'} "
                                     f"finite 3-vector, got {getattr(self, f.name)!r}")
                object.__setattr__(self, f.name, float(v) if v.ndim == 0 else tuple(float(x) for x in v))
            elif v.ndim != 0 or not np.isfinite(v) or v < 0:
                raise ValueError(f"{f.name} must be a finite value >= 0, got {getattr(self, f.name)!r}")
        for f in ("gyro_warmup_tau_s", "bias_instability_tau_s"):
            if getattr(self, f) <= 0:
                raise ValueError(f"{f} must be > 0 (s), got {getattr(self, f)!r}")

    @property
    def dt_s(self) -> float:
        """Sample interval (s) = 1 / fs_hz."""
        return 1.0 / self.fs_hz

    @property
    def accel_noise_per_sample_m_s2(self) -> float:
        """Accelerometer white-noise σ per sample (m/s²) = density · √fs."""
        return self.accel_noise_m_s2_rt_hz * np.sqrt(self.fs_hz)

    @property
    def gyro_noise_per_sample_rad_s(self) -> float:
        """Gyro white-noise σ per sample (rad/s) = density · √fs."""
        return self.gyro_noise_rad_s_rt_hz * np.sqrt(self.fs_hz)

    def resolve(self) -> "SensorSpec":
        """The plain values a run uses: the spec itself (already SI; kept so runs read ``spec.resolve()``)."""
        return self

    def error_model(self, q_mount=(1.0, 0.0, 0.0, 0.0), sources=None, errors=None) -> ImuErrorModel:
        """The simulator's :class:`~mtcal.core.simulate.ImuErrorModel` of this spec.

        Parameters
        ----------
        q_mount : 4-tuple
            Scalar-first mounting quaternion ``q_bs``.
        sources : iterable of str, optional
            Switch on only these :data:`SENSOR_SOURCES` (default: all). Names that are
            not sensor sources (a study's rig errors in the same list) are ignored.
        errors : object, optional
            An identified error model with an attribute ``gyro_run_bias_rad_s`` (1σ, rad/s),
            added in quadrature to ``gyro_bias_sigma_rad_s``.

        Returns
        -------
        ImuErrorModel
        """
        if sources is None:
            on = set(SENSOR_SOURCES)
        else:
            if isinstance(sources, str) or not all(isinstance(s, str) for s in sources):
                raise TypeError(f"sources must be an iterable of names, got {sources!r}")
            on = set(sources)
        extra = 0.0 if errors is None else float(getattr(errors, "gyro_run_bias_rad_s"))

        def use(name, value, off=0.0):
            return value if name in on else off

        gyro = SensorErrors(
            noise_density=use("gyro_white", self.gyro_noise_rad_s_rt_hz),
            bias=use("gyro_fixed_bias", self.gyro_bias_rad_s),
            bias_sigma=use("gyro_residual_bias", float(np.hypot(self.gyro_bias_sigma_rad_s, extra))),
            bias_instability=use("gyro_bias_instability", self.gyro_bias_instability_rad_s),
            bias_instability_tau_s=self.bias_instability_tau_s,
            bias_random_walk=use("gyro_random_walk", self.gyro_rw_rad_s_rt_s),
            warmup_bias=use("gyro_warmup", self.gyro_warmup_bias_rad_s),
            warmup_tau_s=self.gyro_warmup_tau_s,
            scale_factor=use("gyro_scale_factor", self.gyro_scale_factor),
            quantization=use("quantisation", self.gyro_lsb_rad_s))
        accel = SensorErrors(
            noise_density=use("accel_white", self.accel_noise_m_s2_rt_hz),
            bias=use("accel_fixed_bias", self.accel_bias_m_s2),
            bias_sigma=use("accel_bias", self.accel_bias_sigma_m_s2),
            bias_instability=use("accel_bias_instability", self.accel_bias_instability_m_s2),
            bias_instability_tau_s=self.bias_instability_tau_s,
            bias_random_walk=use("accel_random_walk", self.accel_rw_m_s2_rt_s),
            quantization=use("quantisation", self.accel_lsb_m_s2))
        return ImuErrorModel(gyro=gyro, accel=accel, q_mount=tuple(float(x) for x in np.asarray(q_mount, float)),
                             time_since_power_on_s=self.time_since_power_on_s)
