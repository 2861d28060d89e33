"""Scenario evaluators: what one sweep cell computes for a block of Monte Carlo trials.

An evaluator maps a parameter dict and one ``numpy.random.Generator`` per trial
to per-trial metrics: ``func(params, rngs) -> {metric: ndarray (len(rngs),)}``.
Trial ``j`` must draw only from ``rngs[j]``, so its random inputs do not depend
on which other trials share the call (the engine keys ``rngs[j]`` by
(seed, cell, trial index)).

Registered evaluators (:func:`evaluator_names`):

* ``attitude`` — turntable AoA / roll sweeps and wind-tunnel AoA sweeps (with the
  running-tunnel vibration as parameters) of wang2023cja, any set of registered
  attitude filters (:mod:`mtcal.filters.registry`), any sensor grade
  (:mod:`mtcal.core.sensor_grades`); metrics: tilt error over the record and over
  the holds (the static angles the paper's tables report), maximum tilt error.
* ``surface`` — movable-surface rotations about a fixed hinge axis (wang2022sensors):
  any registered filter's angle about the axis (attitude filters: swing–twist;
  angle filters: their own output), via :func:`mtcal.filters.anchors.run_axis_angle_filter`;
  the RAMS EKF entry is the study's batched surface-angle procedure with the sweep cell's config
  (:meth:`mtcal.systems.surface_angle.SurfaceBatchConfig.sweep_cell`, declared in the filter registry's table).
* ``six_position`` — wang2023cja §3.2 installation-error calibration with K = 4…12
  turntable positions: QNCF attitudes, the calibration procedure of
  :mod:`mtcal.systems.installation` (as ``mtcal calibrate``), error left at 12
  validation attitudes.
* ``gaussian_check`` — the engine's self-check (RMS of white noise: median known
  in closed form).

Each simulation evaluator is one pass per layer: the cell's truth (profile, trajectory, holds,
sensor model: :mod:`mtcal.core`; for ``attitude`` and ``surface`` built once per process and cell and
shared by its blocks), every trial simulated at once (:func:`_simulate_block`, into the last block's
buffers), the gains resolved, the filters (or the installation system) run once on the stacked trials
(the evaluator's own records unchecked, the common levelled start computed once), then the metrics
(error and metrics in one compiled pass).

Motion values (sweep angles, rates, holds) are the wang2023cja / wang2022sensors
scenario values, restated here with their source so that the sweep does not
depend on the study packages' internals.

Examples
--------
>>> import numpy as np
>>> ev = get_evaluator("gaussian_check")
>>> rngs = [np.random.default_rng(s) for s in range(3)]
>>> out = ev(ev.resolve({"sigma": 2.0}), rngs)
>>> sorted(out), out["rms"].shape
(['mean', 'rms'], (3,))
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np

from mtcal.core import rotations
from mtcal.core.compiled import jit
from mtcal.core.profiles import AngleProfile, fixed_axis_trajectory, step_schedule, trajectory_from_euler_zxy
from mtcal.core.sensor_grades import grade_names, sensor_grade
from mtcal.core.simulate import ImuErrorModel, ImuStream, Trajectory, apply_sensor_errors
from mtcal.core.units import DEG

__all__ = ["Evaluator", "register_evaluator", "get_evaluator", "evaluator_names", "MOTIONS", "filter_gain",
           "RAMS_EKF_DEFAULT_GAIN", "SURFACE_AXIS",
           "attitude_profile", "surface_profile", "validation_positions_rad", "PARAMETER_HELP", "parameter_help"]

_REGISTRY: dict[str, "Evaluator"] = {}


@dataclass(frozen=True)
class Evaluator:
    """A registered scenario evaluator.

    Parameters
    ----------
    name : str
        Registry key (the spec's ``sweep.evaluator``).
    func : callable
        ``func(params, rngs) -> {metric: ndarray (len(rngs),)}``.
    base_defaults : dict
        Every parameter with its default; a spec may set only these (and, for an evaluator
        with ``gain_scale``, ``gain_<filter>`` of any registered filter: :attr:`defaults`).
    metrics : callable
        ``metrics(params) -> list[str]``: the metric names for resolved params.
    check : callable
        ``check(params)`` raises ``ValueError`` naming a bad parameter.
    description : str
        One line for listings.
    """

    name: str
    func: Callable
    base_defaults: dict
    metrics: Callable
    check: Callable = field(default=lambda params: None)
    description: str = ""

    @property
    def defaults(self) -> dict:
        """``base_defaults`` plus ``gain_<name>: None`` for every registered filter when the evaluator
        takes filter gains (``gain_scale`` in its defaults): a filter registered later is accepted."""
        if "gain_scale" not in self.base_defaults:
            return dict(self.base_defaults)
        from mtcal.filters.registry import filter_names

        return {**{f"gain_{f}": None for f in filter_names()}, **self.base_defaults}

    def resolve(self, params: dict) -> dict:
        """Defaults overridden by ``params``, validated (ValueError naming the key)."""
        if not isinstance(params, dict):
            raise TypeError(f"params must be a dict, got {type(params).__name__}")
        defaults = self.defaults
        unknown = sorted(set(params) - set(defaults))
        if unknown:
            raise ValueError(f"{unknown[0]} is not a parameter of evaluator {self.name!r}; "
                             f"valid: {sorted(defaults)}")
        out = dict(defaults)
        out.update(params)
        self.check(out)
        return out

    def __call__(self, params: dict, rngs: list) -> dict[str, np.ndarray]:
        """Evaluate a block of trials; checks the output (names, shapes, finiteness)."""
        if not rngs or not all(isinstance(r, np.random.Generator) for r in rngs):
            raise TypeError("rngs must be a non-empty list of numpy.random.Generator")
        out = self.func(params, rngs)
        names = list(self.metrics(params))
        if sorted(out) != sorted(names):
            raise RuntimeError(f"evaluator {self.name!r} returned metrics {sorted(out)}, expected {sorted(names)}")
        result = {}
        for name in names:
            arr = np.asarray(out[name], dtype=float)
            if arr.shape != (len(rngs),):
                raise RuntimeError(f"evaluator {self.name!r} metric {name!r} has shape {arr.shape}, "
                                   f"expected ({len(rngs)},)")
            result[name] = arr
        return result


#: Unit and meaning of every evaluator parameter (``mtcal sweep --list``); ``gain_<filter>`` is generic.
PARAMETER_HELP = {
    "motion": "-, truth motion: one of the MOTIONS schedules (wang2023cja turntable / wind-tunnel sweeps)",
    "filters": "-, list of attitude filters to run (mtcal.filters.registry names)",
    "grade": "-, sensor grade from mtcal.core.sensor_grades (bias, noise, instability of gyro and accel)",
    "fs_hz": "Hz, IMU sample rate",
    "vibration_m_s2": "m/s^2, sinusoidal vibration amplitude added to the accelerometer",
    "vibration_hz": "Hz, vibration frequency",
    "hold_s": "s, hold at each waypoint (null: the schedule's own)",
    "speed": "-, factor on the schedule's move rates",
    "gain_scale": "-, factor on every filter's default gain",
    "sigma": "-, standard deviation of the self-check's white noise",
    "n_samples": "-, samples per trial of the self-check",
    "n_positions": "-, calibration positions used (the first K of validation_positions_rad, 4-12)",
    "rest_s": "s, rest at each calibration position",
    "alpha_deg": "deg, installation angles [alpha1 about z, alpha2 about y, alpha3 about x] of wang2023cja Eq 1 "
                 "(C_b^s = Rz Ry Rx; the body relative to the sensor), as in the turntable study and mtcal calibrate",
    "step_deg": "deg, surface deflection step",
    "span_deg": "deg, surface deflection span",
    "rate_deg_s": "deg/s, surface move rate",
    "lever_arm_m": "m, distance of the IMU from the hinge axis",
}


def parameter_help(key: str) -> str:
    """Unit and meaning of an evaluator parameter (``"-"`` when dimensionless)."""
    if key.startswith("gain_") and key not in PARAMETER_HELP:
        return f"filter-specific, gain of filter {key[5:]} (null: its default times gain_scale)"
    return PARAMETER_HELP.get(key, "")


def register_evaluator(name: str, defaults: dict, metrics, check=None, description: str = ""):
    """Decorator registering ``func(params, rngs)`` under ``name`` (see :class:`Evaluator`)."""
    def wrap(func):
        _REGISTRY[name] = Evaluator(name, func, dict(defaults), metrics, check or (lambda p: None), description)
        return func
    return wrap


def evaluator_names() -> list[str]:
    """Names of the registered evaluators, sorted."""
    return sorted(_REGISTRY)


def get_evaluator(name) -> Evaluator:
    """The evaluator registered as ``name`` (ValueError listing the valid names)."""
    if not isinstance(name, str) or name not in _REGISTRY:
        raise ValueError(f"sweep.evaluator must be one of {evaluator_names()}, got {name!r}")
    return _REGISTRY[name]


# --------------------------------------------------------------------------- checks
def _number(params: dict, key: str, lo: float, hi: float, *, lo_open: bool = False) -> float:
    v = params[key]
    if (isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v)
            or v < lo or v > hi or (lo_open and v == lo)):
        bracket = "(" if lo_open else "["
        raise ValueError(f"{key} must be a number in {bracket}{lo:g}, {hi:g}], got {v!r}")
    return float(v)


def _integer(params: dict, key: str, lo: int, hi: int) -> int:
    v = params[key]
    if isinstance(v, bool) or not isinstance(v, int) or not lo <= v <= hi:
        raise ValueError(f"{key} must be an integer in [{lo}, {hi}], got {v!r}")
    return int(v)


def _choice(params: dict, key: str, choices) -> str:
    v = params[key]
    if v not in choices:
        raise ValueError(f"{key} must be one of {list(choices)}, got {v!r}")
    return v


def _filters(params: dict, key: str, choices) -> list[str]:
    v = params[key]
    if isinstance(v, str):
        v = [v]
    if not isinstance(v, (list, tuple)) or not v or any(f not in choices for f in v) or len(set(v)) != len(v):
        raise ValueError(f"{key} must be a non-empty list of distinct names from {list(choices)}, got {params[key]!r}")
    return list(v)


def _gains_check(params: dict, names) -> None:
    _number(params, "gain_scale", 0.0, 1e6, lo_open=True)
    for f in names:
        key = f"gain_{f}"
        if key in params and params[key] is not None:
            _number(params, key, 0.0, 1e6, lo_open=True)


#: Default of the RAMS EKF's tuned value, σa,moving (m/s²) (its registry entry's default gain).
RAMS_EKF_DEFAULT_GAIN = 2.0


def filter_gain(params: dict, name: str) -> float:
    """Gain used for filter ``name``: ``gain_<name>`` (or its default) × ``gain_scale``.

    Default: the filter's registry entry (:func:`mtcal.filters.registry.get_filter`).
    """
    from mtcal.filters.registry import get_filter

    base = params.get(f"gain_{name}")
    if base is None:
        base = get_filter(name).default_gain
    return float(base) * float(params.get("gain_scale", 1.0))


# --------------------------------------------------------------------------- simulation
def _simulate_block(truth: "Trajectory", model: ImuErrorModel, rngs: list, vibration_m_s2: float = 0.0,
                    vibration_hz: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Per-trial sensor errors on a shared truth: gyro, accel (T, N, 3).

    From the engine (``rngs`` a :class:`mtcal.sweep.engine.TrialStreams`): one batched
    :class:`~mtcal.core.simulate.ImuStream` filled at once (as :func:`~mtcal.core.simulate.simulate_imu`),
    the cell's keyed stream with the trials' global indices as ``trial_ids`` (trial j's numbers do not
    depend on its block-mates). From a plain list of generators: trial j uses ``rngs[j]`` only (one call
    per trial).
    """
    accel_err = model.accel
    if vibration_m_s2 > 0:
        accel_err = replace(accel_err, vibration_amplitude=float(vibration_m_s2),
                            vibration_freq_hz=float(vibration_hz))
    ids = getattr(rngs, "trial_ids", None)
    n = len(truth)
    if ids is not None:
        # the last block's buffers when its caller has dropped them (every element is written: no page faults)
        pool = _records_pool()
        gyro, accel = pool.take("gyro", (len(ids), n, 3)), pool.take("accel", (len(ids), n, 3))
        ImuStream(truth, replace(model, accel=accel_err), rngs.cell_rng(), len(ids), trial_ids=ids).fill(gyro, accel)
        pool.keep("gyro", gyro)
        pool.keep("accel", accel)
        return gyro, accel
    ideal = ImuStream(truth, ImuErrorModel(q_mount=model.q_mount))
    gyro = np.empty((len(rngs), n, 3))
    accel = np.empty((len(rngs), n, 3))
    for j, rng in enumerate(rngs):  # per-trial streams keep every trial independent of the block
        g_rng, a_rng = rng.spawn(2)
        gyro[j] = apply_sensor_errors(model.gyro, ideal.gyro_true, truth.time_s, g_rng,
                                      time_since_power_on_s=model.time_since_power_on_s)
        accel[j] = apply_sensor_errors(accel_err, ideal.accel_true, truth.time_s, a_rng,
                                       time_since_power_on_s=model.time_since_power_on_s)
    return gyro, accel


@functools.lru_cache(maxsize=1)
def _records_pool():
    """Simulated records of the last block (:func:`_simulate_block`), reused once the evaluator has dropped them
    (created on first use: importing the sweep does not load numba)."""
    from mtcal.filters._kernels_common import OutputPool

    return OutputPool(min_bytes=1 << 20)


def _rms_rows(x: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """RMS of each trial's row over ``mask``, summed row by row.

    numpy's ``mean(axis=1)`` of a (T, N) array sums in an order that depends on T,
    so a trial's last bit would depend on its batch-mates; a per-row reduction does not.
    """
    return np.array([np.sqrt(np.mean(row[mask] ** 2)) for row in x])


@jit
def _add_sample(e, after_k, hold_k, acc):  # pragma: no cover - compiled
    """One sample of a row's metrics: ``acc`` = (sum² after, count after, sum² holds, count holds, max |e|)."""
    s_a, n_a, s_h, n_h, m = acc
    if after_k:
        s_a += e * e
        n_a += 1
        a = abs(e)
        if a > m or a != a:
            m = a
    if hold_k:
        s_h += e * e
        n_h += 1
    return s_a, n_a, s_h, n_h, m


@jit
def _finish_row(acc, out, j):  # pragma: no cover - compiled
    s_a, n_a, s_h, n_h, m = acc
    out[j, 0] = np.sqrt(s_a / n_a) if n_a else np.nan
    out[j, 1] = np.sqrt(s_h / n_h) if n_h else np.nan
    out[j, 2] = m if n_a else np.nan


@jit
def _row_metrics_kernel(err, after, holds):  # pragma: no cover - compiled
    """Per trial: RMS over ``after``, RMS over ``holds``, max |err| over ``after`` (sequential sums per row)."""
    n_trials, n = err.shape
    out = np.empty((n_trials, 3))
    for j in range(n_trials):
        acc = (0.0, 0, 0.0, 0, -np.inf)
        for k in range(n):
            acc = _add_sample(err[j, k], after[k], holds[k], acc)
        _finish_row(acc, out, j)
    return out


@jit
def _tilt_deg(q_est, j, k, up_true):  # pragma: no cover - compiled
    """Tilt error (deg) of ``q_est[j, k]`` against the true "up" ``up_true[k]`` (sensor frame)."""
    q0, q1, q2, q3 = q_est[j, k, 0], q_est[j, k, 1], q_est[j, k, 2], q_est[j, k, 3]
    ux = 2.0 * (q1 * q3 - q0 * q2)
    uy = 2.0 * (q2 * q3 + q0 * q1)
    uz = q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3
    vx, vy, vz = up_true[k, 0], up_true[k, 1], up_true[k, 2]
    cx = uy * vz - uz * vy
    cy = uz * vx - ux * vz
    cz = ux * vy - uy * vx
    return np.degrees(np.arctan2(np.sqrt(cx * cx + cy * cy + cz * cz), ux * vx + uy * vy + uz * vz))


@jit
def _tilt_deg_kernel(q_est, up_true):  # pragma: no cover - compiled
    """Tilt error (deg) of ``q_est`` (T, N, 4) against the true "up" in the sensor frame ``up_true`` (N, 3)."""
    n_trials, n = q_est.shape[0], q_est.shape[1]
    out = np.empty((n_trials, n))
    for j in range(n_trials):
        for k in range(n):
            out[j, k] = _tilt_deg(q_est, j, k, up_true)
    return out


@jit
def _tilt_metrics_kernel(q_est, up_true, after, holds):  # pragma: no cover - compiled
    """``_row_metrics_kernel(_tilt_deg_kernel(q_est, up_true), after, holds)`` in one pass, no (T, N) array:
    the tilt is computed only where a metric reads it, the sums in the same order."""
    n_trials, n = q_est.shape[0], q_est.shape[1]
    out = np.empty((n_trials, 3))
    for j in range(n_trials):
        acc = (0.0, 0, 0.0, 0, -np.inf)
        for k in range(n):
            if after[k] or holds[k]:
                acc = _add_sample(_tilt_deg(q_est, j, k, up_true), after[k], holds[k], acc)
        _finish_row(acc, out, j)
    return out


@jit
def _angle_metrics_kernel(theta, theta_true, after, holds):  # pragma: no cover - compiled
    """``_row_metrics_kernel(np.degrees(wrap_angle(theta - theta_true)), after, holds)`` in one pass (the same
    operations: Python's float ``%`` is numpy's ``remainder``), computed only where a metric reads it."""
    n_trials, n = theta.shape
    out = np.empty((n_trials, 3))
    two_pi = 2.0 * np.pi
    for j in range(n_trials):
        acc = (0.0, 0, 0.0, 0, -np.inf)
        for k in range(n):
            if after[k] or holds[k]:
                e = np.degrees((theta[j, k] - theta_true[k] + np.pi) % two_pi - np.pi)
                acc = _add_sample(e, after[k], holds[k], acc)
        _finish_row(acc, out, j)
    return out


def _row_metrics(err: np.ndarray, after: np.ndarray, holds: np.ndarray) -> np.ndarray:
    """(T, 3): RMS over ``after``, RMS over ``holds``, max |err| over ``after`` of each trial's row.

    One compiled pass per row, summed sample by sample: a trial's numbers do not depend
    on its block-mates (as :func:`_rms_rows`), with no (T, N) temporaries.
    """
    return _row_metrics_kernel(np.ascontiguousarray(err, dtype=float), np.ascontiguousarray(after, dtype=np.bool_),
                               np.ascontiguousarray(holds, dtype=np.bool_))


def _tilt_error_deg(q_est: np.ndarray, q_true: np.ndarray) -> np.ndarray:
    """Tilt error (deg), shape (T, N): :func:`mtcal.filters.anchors.tilt_error_rad` in one compiled pass."""
    q = np.asarray(q_true, float)
    q0, q1, q2, q3 = q[:, 0], q[:, 1], q[:, 2], q[:, 3]
    up = np.stack([2.0 * (q1 * q3 - q0 * q2), 2.0 * (q2 * q3 + q0 * q1), q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3],
                  axis=-1)
    return _tilt_deg_kernel(np.ascontiguousarray(q_est, dtype=float), np.ascontiguousarray(up))


def _hold_mask(holds: list, n_samples: int, fraction: float = 0.5) -> np.ndarray:
    """Middle ``fraction`` of every hold slice in ``holds`` (the static evaluation windows), shape (n_samples,)."""
    mask = np.zeros(n_samples, bool)
    for s in holds:
        n = s.stop - s.start
        m = max(1, int(round(n * fraction)))
        a = s.start + (n - m) // 2
        mask[a:a + m] = True
    return mask


# --------------------------------------------------------------------------- attitude
#: Motions of the ``attitude`` evaluator: waypoints (deg) on the [ψ, θ, γ] channel, mean move rate (°/s),
#: hold (s) and source.
MOTIONS = {
    "aoa": dict(channel=1, waypoints_deg=(-4, 0, 4, 8, 12, 13, -5, 13), rate_deg_s=4.0, hold_s=5.0,
                source="wang2023cja turntable AoA sweep, Table 5 order; 4 °/s and 5 s holds (mtcal scenario)"),
    "roll": dict(channel=2, waypoints_deg=(90, 60, 30, 0, -30, -60, -90, 90), rate_deg_s=20.0, hold_s=5.0,
                 source="wang2023cja turntable roll sweep, Table 7 order; 20 °/s, 5 s holds (mtcal scenario)"),
    "windtunnel": dict(channel=1, waypoints_deg=(-4, 0, 4, 8, 12), rate_deg_s=2.0, hold_s=3.0,
                       source="wang2023cja wind-tunnel AoA sweep, Table 10 angles; mechanism 2 °/s, 3 s holds "
                              "with wind (mtcal scenario)"),
}
def _attitude_filters() -> list[str]:
    """Filters the attitude evaluator takes: every registered attitude filter."""
    from mtcal.filters.registry import filter_names

    return filter_names(output="attitude")


def _all_filters() -> list[str]:
    """Filters the surface evaluator takes: every registered filter (attitude ones via their twist)."""
    from mtcal.filters.registry import filter_names

    return filter_names()


_ATT_METRICS = ("tilt_rmse_deg", "hold_tilt_rmse_deg", "tilt_max_deg")


def attitude_profile(motion: str, fs_hz: float, *, hold_s: float | None = None, settle_s: float = 3.0,
                     speed: float = 1.0) -> AngleProfile:
    """[ψ, θ, γ] profile of a :data:`MOTIONS` entry: settle at zero, visit the waypoints, return.

    ``speed`` scales the move rates; ``hold_s`` overrides the hold per waypoint.

    ``fs_hz`` (Hz) is the sample rate, not ``dt_s``: the sweep cell states the rate (parameter ``fs_hz``) and
    :func:`mtcal.core.profiles.step_schedule` samples at a rate; a ``dt_s`` would reach it as ``1 / (1 / fs)``,
    which is not ``fs`` for 603 of the integer rates 20–4000 Hz (e.g. 49 Hz), and would move the schedule's bits.
    """
    m = MOTIONS[motion]
    wp = np.zeros((len(m["waypoints_deg"]) + 2, 3))
    wp[1:-1, m["channel"]] = np.radians(m["waypoints_deg"])
    hold = m["hold_s"] if hold_s is None else hold_s
    holds = np.r_[settle_s, np.full(len(m["waypoints_deg"]), hold), 1.0]
    return step_schedule(wp, m["rate_deg_s"] * speed * DEG, holds, fs_hz, min_move_s=0.5)


def _check_attitude(p: dict) -> None:
    _choice(p, "motion", tuple(MOTIONS))
    names = _filters(p, "filters", _attitude_filters())
    _choice(p, "grade", grade_names())
    _number(p, "fs_hz", 20.0, 4000.0)
    _number(p, "vibration_m_s2", 0.0, 50.0)
    _number(p, "vibration_hz", 0.1, 0.45 * p["fs_hz"], lo_open=False)
    if p["hold_s"] is not None:
        _number(p, "hold_s", 0.5, 600.0)
    _number(p, "speed", 0.1, 10.0)
    _gains_check(p, names)


def _filter_list(p: dict) -> list[str]:
    return [p["filters"]] if isinstance(p["filters"], str) else list(p["filters"])


def _attitude_metrics(p: dict) -> list[str]:
    return [f"{f}.{m}" for f in _filter_list(p) for m in _ATT_METRICS]


@register_evaluator(
    "attitude",
    defaults=dict(motion="aoa", filters=["qncf"], grade="wang2023cja", fs_hz=1000.0, vibration_m_s2=0.0,
                  vibration_hz=45.0, hold_s=None, speed=1.0, gain_scale=1.0),
    metrics=_attitude_metrics, check=_check_attitude,
    description="tilt error of attitude filters on wang2023cja turntable / wind-tunnel sweeps")
def _attitude(p: dict, rngs: list) -> dict[str, np.ndarray]:
    """Tilt errors (deg) of each filter after the settling rest: RMS, RMS over holds, max.

    One pass per layer: the truth (profile, trajectory, holds, sensor model: :mod:`mtcal.core`), the
    trials simulated at once, then each filter on the stacked trials with its gain, then its metrics.
    """
    from mtcal.filters.anchors import attitude_filter, levelled_start

    truth = _attitude_truth(p["motion"], float(p["fs_hz"]), p["hold_s"], float(p["speed"]))
    model = sensor_grade(p["grade"]).error_model(time_since_power_on_s=300.0)
    gyro, accel = _simulate_block(truth.traj, model, rngs, p["vibration_m_s2"], p["vibration_hz"])
    init = max(1, int(round(0.5 * p["fs_hz"])))   # level from the first 0.5 s of the settling rest
    gains = {name: filter_gain(p, name) for name in _filter_list(p)}
    hold_mask = _hold_mask(truth.holds[1:], truth.after.size)   # the metric windows: middle half of each hold
    # the simulated records are this evaluator's own (finite, rad/s and m/s²): every filter runs them
    # unchecked (the checks of run_attitude_filter, once per filter, were ≈ 6 % of the bake-off's CPU)
    q_init = levelled_start(accel, init)          # the common start, once per block
    out = {}
    for name, gain in gains.items():
        q = attitude_filter(name, gyro, accel, truth.traj.dt_s, gain, q_init)
        m = _tilt_metrics_kernel(np.ascontiguousarray(q, dtype=float), truth.up, truth.after, hold_mask)
        out[f"{name}.tilt_rmse_deg"], out[f"{name}.hold_tilt_rmse_deg"], out[f"{name}.tilt_max_deg"] = m.T
    return out


@dataclass(frozen=True)
class _CellTruth:
    """What every block of a cell shares (read-only arrays): the trajectory (its truth outputs memoised on
    the object, :func:`mtcal.core.simulate.simulate_imu`), its holds, the samples after the settling rest, the
    true "up" / angle."""

    traj: Trajectory
    holds: tuple
    after: np.ndarray
    up: np.ndarray = None
    theta: np.ndarray = None
    is_static: np.ndarray = None


def _frozen(*arrays):
    for a in arrays:
        if a is not None:
            a.flags.writeable = False


@functools.lru_cache(maxsize=8)
def _attitude_truth(motion: str, fs_hz: float, hold_s, speed: float) -> _CellTruth:
    """The attitude evaluator's truth of one cell, built once per process and shared by its blocks."""
    prof = attitude_profile(motion, fs_hz, hold_s=hold_s, speed=speed)
    traj = trajectory_from_euler_zxy(prof)
    holds = tuple(prof.hold_slices())
    after = prof.time_s >= prof.time_s[holds[0].stop - 1]
    q = np.asarray(traj.q_wb, float)
    q0, q1, q2, q3 = q[:, 0], q[:, 1], q[:, 2], q[:, 3]
    up = np.ascontiguousarray(np.stack([2.0 * (q1 * q3 - q0 * q2), 2.0 * (q2 * q3 + q0 * q1),
                                        q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3], axis=-1))
    truth = _CellTruth(traj, holds, np.ascontiguousarray(after, dtype=np.bool_), up=up)
    _frozen(truth.after, truth.up)
    return truth


# --------------------------------------------------------------------------- surface
#: wang2022sensors Fig. 11 simulation axis (Sec. 5) in the IMU frame.
SURFACE_AXIS = (0.1734, 0.9835, 0.0523)
_SURF_METRICS = ("angle_rmse_deg", "hold_angle_rmse_deg", "angle_max_deg")


def surface_profile(fs_hz: float, *, step_deg: float = 30.0, span_deg: float = 60.0, rate_deg_s: float = 20.0,
                    hold_s: float = 1.0, settle_s: float = 2.0) -> AngleProfile:
    """Surface deflection θ(t): settle at 0, then −span…+span in ``step_deg`` steps, back to 0.

    wang2022sensors Sec. 7 sweeps in steps with 1 s holds at 20 °/s (mtcal RotationSetup values).
    ``fs_hz`` (Hz) is the sample rate, not ``dt_s``, for the reason :func:`attitude_profile` states (the cell's
    rate reaches :func:`mtcal.core.profiles.step_schedule` unchanged).
    """
    n = int(round(2 * span_deg / step_deg))
    sweep = np.linspace(-span_deg, span_deg, n + 1)
    wp = np.radians(np.r_[0.0, sweep, 0.0])
    holds = np.r_[settle_s, np.full(sweep.size, hold_s), 1.0]
    return step_schedule(wp, rate_deg_s * DEG, holds, fs_hz, min_move_s=0.2)


def _check_surface(p: dict) -> None:
    names = _filters(p, "filters", _all_filters())
    _choice(p, "grade", grade_names())
    _number(p, "fs_hz", 20.0, 4000.0)
    _number(p, "step_deg", 1.0, 180.0)
    _number(p, "span_deg", 1.0, 170.0)
    _number(p, "rate_deg_s", 0.1, 500.0)
    _number(p, "hold_s", 0.2, 60.0)
    _number(p, "lever_arm_m", 0.0, 5.0)
    _number(p, "vibration_m_s2", 0.0, 50.0)
    _number(p, "vibration_hz", 0.1, 0.45 * p["fs_hz"])
    _gains_check(p, names)


def _surface_metrics(p: dict) -> list[str]:
    return [f"{f}.{m}" for f in _filter_list(p) for m in _SURF_METRICS]


@register_evaluator(
    "surface",
    defaults=dict(filters=["rams_ekf", "qncf"], grade="wang2022sensors", fs_hz=200.0, step_deg=30.0,
                  span_deg=60.0, rate_deg_s=20.0, hold_s=1.0, lever_arm_m=0.2, vibration_m_s2=0.0,
                  vibration_hz=45.0, gain_scale=1.0),
    metrics=_surface_metrics, check=_check_surface,
    description="angle about the hinge axis of a movable surface (wang2022sensors), filters vs RAMS EKF")
def _surface(p: dict, rngs: list) -> dict[str, np.ndarray]:
    """Angle-about-axis errors (deg): RMS after the settling rest, RMS over holds, max.

    The RAMS EKF runs as the study's batched procedure
    (:func:`mtcal.systems.surface_angle.surface_angle_batch` with
    :meth:`~mtcal.systems.surface_angle.SurfaceBatchConfig.sweep_cell`): the true axis, ā0 and the
    initial gyro bias = means of the settling rest, the schedule's rest flags as its
    ZVD input (and its holds as the restart points after gyro clipping), and noise
    from the grade (σθ = gyro noise per sample, σa,static = accelerometer noise per
    sample, floor 1 mg); its tuned gain is σa,moving (m/s², default 2). The attitude
    filters' angle is the twist of their attitude about the same axis since the
    settling rest.
    """
    from mtcal.filters.anchors import axis_angle_filter, levelled_start
    from mtcal.filters.registry import AxisContext

    truth = _surface_truth(float(p["fs_hz"]), float(p["step_deg"]), float(p["span_deg"]), float(p["rate_deg_s"]),
                           float(p["hold_s"]), float(p["lever_arm_m"]))
    holds = truth.holds
    grade = sensor_grade(p["grade"])
    gyro, accel = _simulate_block(truth.traj, grade.error_model(time_since_power_on_s=300.0), rngs,
                                  p["vibration_m_s2"], p["vibration_hz"])
    settle, ref = holds[0], holds[0].stop - 1
    gains = {name: filter_gain(p, name) for name in _filter_list(p)}
    hold_mask = _hold_mask(holds[1:], truth.after.size)         # the metric windows: middle half of each hold
    ctx = AxisContext(_SURFACE_AXIS_UNIT, np.broadcast_to(truth.is_static, accel.shape[:2]),
                      np.stack([np.mean(row[settle], axis=0) for row in accel]),
                      grade.gyro_noise_density_rad_s_rt_hz, grade.accel_noise_density_m_s2_rt_hz,
                      init=settle, rests=tuple(holds))
    init = max(1, int(round(0.5 * p["fs_hz"])))
    q_init = levelled_start(accel, init)          # the common start, once per block (records: as _attitude)
    out = {}
    for name, gain in gains.items():
        theta = axis_angle_filter(name, gyro, accel, truth.traj.dt_s, gain, ctx, ref, q_init)
        m = _angle_metrics_kernel(np.ascontiguousarray(theta, dtype=float), truth.theta, truth.after, hold_mask)
        out[f"{name}.angle_rmse_deg"], out[f"{name}.hold_angle_rmse_deg"], out[f"{name}.angle_max_deg"] = m.T
    return out


_SURFACE_AXIS_UNIT = np.asarray(SURFACE_AXIS) / np.linalg.norm(SURFACE_AXIS)
_SURFACE_AXIS_UNIT.flags.writeable = False


@functools.lru_cache(maxsize=8)
def _surface_truth(fs_hz: float, step_deg: float, span_deg: float, rate_deg_s: float, hold_s: float,
                   lever_arm_m: float) -> _CellTruth:
    """The surface evaluator's truth of one cell, built once per process and shared by its blocks."""
    prof = surface_profile(fs_hz, step_deg=step_deg, span_deg=span_deg, rate_deg_s=rate_deg_s, hold_s=hold_s)
    axis = _SURFACE_AXIS_UNIT
    chord = np.cross(axis, [0.0, 0.0, 1.0])
    lever = lever_arm_m * chord / np.linalg.norm(chord) + np.array([0.0, 0.0, 0.02])
    traj = fixed_axis_trajectory(prof, axis, lever_arm_b_m=lever)
    holds = tuple(prof.hold_slices())
    ref = holds[0].stop - 1
    after = np.arange(prof.time_s.size) >= ref
    truth = _CellTruth(traj, holds, np.ascontiguousarray(after, dtype=np.bool_),
                       theta=prof.angle_rad[:, 0] - prof.angle_rad[ref, 0], is_static=np.array(prof.is_static))
    _frozen(truth.after, truth.theta, truth.is_static)
    return truth


# --------------------------------------------------------------------------- six-position
def validation_positions_rad() -> np.ndarray:
    """12 turntable attitudes [ψ, θ, γ] (rad): the six of wang2023cja §3.2 first, then six combined ones.

    The first K are the calibration positions of a K-position run (ordered so that
    any K ≥ 4 rotates about all three axes: Eq 13 needs rank 4); all 12 are the
    validation set. Ranges as wang2023cja §4.1 (yaw ±8°, pitch −12°/+23°, roll ±90°).
    """
    deg = np.array([[8, 0, 0], [0, -12, 0], [0, 0, 90], [-8, 0, 0], [0, 23, 0], [0, 0, -90],
                    [8, 23, 0], [-8, -12, 0], [0, 23, 90], [0, -12, -90], [8, 0, 90], [-8, 0, -90]], float)
    return np.radians(deg)


def _check_six(p: dict) -> None:
    _integer(p, "n_positions", 4, 12)
    _choice(p, "grade", grade_names())
    _number(p, "fs_hz", 20.0, 4000.0)
    _number(p, "rest_s", 0.5, 60.0)
    a = p["alpha_deg"]
    if not isinstance(a, (list, tuple)) or len(a) != 3 or any(
            isinstance(x, bool) or not isinstance(x, (int, float)) or not abs(x) <= 10 for x in a):
        raise ValueError(f"alpha_deg must be 3 installation angles [alpha1 about z, alpha2 about y, alpha3 about x] "
                         f"(wang2023cja Eq 1, deg) within ±10°, got {a!r}")


@register_evaluator(
    "six_position",
    defaults=dict(n_positions=6, grade="wang2023cja", fs_hz=1000.0, rest_s=3.0,
                  alpha_deg=[-0.2434, -0.0359, 0.0521]),
    metrics=lambda p: ["residual_max_deg", "residual_rms_deg", "before_max_deg"], check=_check_six,
    description="installation-error calibration (wang2023cja §3.2, Eq 13) with 4…12 positions")
def _six_position(p: dict, rngs: list) -> dict[str, np.ndarray]:
    """Attitude error left at 12 validation attitudes after a K-position calibration (deg).

    The body visits the first K of :func:`validation_positions_rad` (3 s rests,
    20 °/s moves: wang2023cja §3.2 / mtcal scenario); the sensor is mounted with the
    installation angles ``alpha_deg`` (wang2023cja Eq 1, ``q_bs = mount_quaternion(α)`` as in
    the turntable study and ``mtcal calibrate``; default: the T1 fit of mtcal's turntable
    study); QNCF (paper gains) gives the sensor attitude; the calibration is
    :func:`mtcal.systems.installation.calibrate_installation` — the procedure ``mtcal
    calibrate`` runs — on the stacked trials with the sweep cell's config
    (:meth:`~mtcal.systems.installation.InstallationConfig.sweep_cell`: the scheduled holds, known
    by construction, matched in schedule order, middle half averaged, gates off). Validation: the
    zeroed sensor attitude at each of the 12 attitudes (``q_true(0)⁻¹ ⊗ q_b ⊗ q_bs``: the filter's
    start offset cancels in the zeroing) is mapped by Q̂ and compared with the true body attitude. ``before`` is the
    same error without calibration.
    """
    from mtcal.filters.anchors import run_attitude_filter
    from mtcal.methods.six_position import schedule_profile
    from mtcal.systems import installation

    config = installation.InstallationConfig.sweep_cell()
    val = validation_positions_rad()
    pos = val[:p["n_positions"]]
    prof = schedule_profile(pos, rate_rad_s=20 * DEG, rest_s=p["rest_s"], fs_hz=p["fs_hz"])
    traj = trajectory_from_euler_zxy(prof)
    rests = prof.hold_slices()[1:-1]
    q_bs = rotations.mount_quaternion(np.radians(p["alpha_deg"]))               # Eq 1, as the study and CLI
    q_b_val = rotations.quat_from_euler_zxy(val[:, 0], val[:, 1], val[:, 2])      # (12, 4)
    q_true0 = rotations.quat_multiply(traj.q_wb[0], q_bs)
    q_s_val = rotations.quat_multiply(rotations.quat_conjugate(q_true0), rotations.quat_multiply(q_b_val, q_bs))
    before = np.degrees(rotations.quat_angle_between(q_s_val, q_b_val))
    model = sensor_grade(p["grade"]).error_model(q_mount=q_bs, time_since_power_on_s=300.0)
    gyro, accel = _simulate_block(traj, model, rngs)
    init = max(1, int(round(0.5 * p["fs_hz"])))
    q_ws = run_attitude_filter("qncf", gyro, accel, traj.dt_s, init_samples=init)
    cal = installation.calibrate_installation(config, pos, 1.0 / p["fs_hz"], q_ws=q_ws, rests=rests)
    q_mat = cal.q_hat                                                             # (T, 4, 4), trials stacked
    # Eq 10 on the checked Q̂ (the system's) and the validation attitudes made here: core's trusted map
    after = rotations.apply_quat_matrix_trusted(q_mat, np.broadcast_to(q_s_val, (len(rngs),) + q_s_val.shape))
    res = np.degrees(rotations.quat_angle_between(after, q_b_val[None]))
    before = np.broadcast_to(before, res.shape)
    return {"residual_max_deg": res.max(axis=1), "residual_rms_deg": _rms_rows(res, np.ones(res.shape[1], bool)),
            "before_max_deg": before.max(axis=1)}


# --------------------------------------------------------------------------- self-check
@register_evaluator(
    "gaussian_check", defaults=dict(sigma=1.0, n_samples=1000),
    metrics=lambda p: ["rms", "mean"],
    check=lambda p: (_number(p, "sigma", 0.0, 1e12, lo_open=True), _integer(p, "n_samples", 1, 10_000_000)),
    description="engine self-check: RMS and mean of white noise N(0, sigma²)")
def _gaussian_check(p: dict, rngs: list) -> dict[str, np.ndarray]:
    """RMS and mean of ``n_samples`` draws of N(0, σ²) per trial (median RMS → σ; mean → 0)."""
    x = np.stack([r.standard_normal(p["n_samples"]) for r in rngs]) * p["sigma"]
    return {"rms": _rms_rows(x, np.ones(x.shape[1], bool)), "mean": np.array([row.mean() for row in x])}
