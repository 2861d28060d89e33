"""Identify the wang2022sensors hardware error model from Table 5 and predict the held-out numbers.

Fitted (uniform priors on a grid inside :data:`ERROR_PRIORS`): the
sensor-to-reference latency, the accelerometer white noise, the lever arm, the
turntable's move acceleration and the AHRS stand-in's magnetic heading
disturbance (5 parameters). Training set (declared, :data:`TRAINING`, = the ``train``
rows of ``paper_data/wang2022sensors_split.csv``, read with
:func:`mtcal.reporting.paper_numbers.training`): the six RAMS numbers of Table 5, the
six ref. [16] numbers (Bv2/Bv3 are near-copies of Bv1 in our axis-independent ref. [16]
model, so they are training replicates, not a test) and the AHRS's Bv1 static RMSE.
Held out (:data:`HELD_OUT`): the other five AHRS (Ellipse2-N) numbers; Fig. 14's
bound (text claims c01, c08, c10) is held out as well.

Likelihood: each training number y is one draw of our simulated quantity, log y ~
N(μ_c,l, s²_MC + s²_d), μ the Monte Carlo mean of log RMSE at grid cell c and
latency l, s²_MC its pooled repetition variance and s_d = :data:`DISCREPANCY_LOG_SD`
a declared model-discrepancy term (our stand-in sensors and rig are not the
paper's). The posterior on the grid is the normalised likelihood (uniform prior);
the predictive distribution of a held-out number mixes the Monte Carlo samples of
every cell with its posterior weight (prior predictive: uniform weights), times the
discrepancy.

References
----------
Wang C., Tu X., Chen Q., Yang Q., Fang T., Sensors 2022, 22, 8996, doi:10.3390/s22228996
(Table 5, Fig. 14).

Examples
--------
>>> w = np.array([0.0, 1.0, 3.0])
>>> [round(float(x), 3) for x in weighted_quantile(np.array([1.0, 2.0, 3.0]), w, [0.5])]
[3.0]
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import pandas as pd

from mtcal.core.cache import cached
from mtcal.core.units import DEG, UG
from mtcal.core.rng import stream_rng
from mtcal.reporting import compare, leak, paper_numbers

from .runs import ahrs_sweep_metrics, sweep_metrics
from .scenario import AhrsImu, Scenario, lever_arm_vector, scenario_from_parameters, table4_axes

__all__ = ["simulated_runs", "ERROR_PRIORS", "FIT_GRID", "FIT_GRID_CI", "LATENCY_GRID_S", "TRAINING", "HELD_OUT", "DISCREPANCY_LOG_SD", "SYSTEMS", "GridRun",
           "run_grid", "paper_table5", "log_likelihood", "posterior_weights", "prior_weights",
           "parameter_summary", "predictive_samples", "weighted_quantile"]

#: The hardware error sources the paper's Table 5 points to: (low, high) prior range, unit,
#: whether it is identified (fitted) or held at its stated value, and the source of the range.
ERROR_PRIORS = {
    "latency_s": dict(low=0.0, high=0.050, unit="s", fitted=True,
                      source="STM32F411 SPI read + EKF + USB/PC logging vs the turntable's position log: "
                             "0–50 ms (a 200 Hz sample is 5 ms; unsynchronised PC clocks add tens of ms)"),
    "accel_noise_ug_rt_hz": dict(low=22.5, high=175.0, unit="µg/√Hz", fitted=True,
                                 source="Table 2: ADXL355 22.5 (datasheet) … BMI088 175; Table 3 says 50"),
    "lever_arm_m": dict(low=0.05, high=0.5, unit="m", fitted=True,
                        source="RAMS on a turntable fixture / a flap: 5–50 cm from the axis"),
    "move_accel_deg_s2": dict(low=100.0, high=3000.0, unit="°/s²", fitted=True,
                              source="three-axis test tables (SGT320E class): max angular acceleration "
                                     "10²–10³ °/s² on the inner axis"),
    "magnetic_heading_sigma_deg": dict(low=0.2, high=10.0, unit="°", fitted=True,
                                       source="AHRS stand-in: heading disturbance of the test-hall field "
                                              "(steel, equipment), tenths to several degrees (Sec. 7 names it); "
                                              "spans the Ellipse2-N datasheet accuracy (Sec. 7: roll/pitch 0.1°, "
                                              "yaw 0.8°, split role input): from twice the roll/pitch figure, "
                                              "through the in-spec yaw error, to a disturbed hall"),
    "move_rate_deg_s": dict(low=10.0, high=60.0, unit="°/s", fitted=False,
                            source="held at 20 °/s: Table 5 constrains only latency × rate"),
    "reference_error_arcsec": dict(low=0.0, high=5.0, unit="″", fitted=False,
                                   source="SGT320E ±5″ (Sec. 7): 0.0014°, negligible"),
    "gyro_scale_factor_ppm": dict(low=0.0, high=3000.0, unit="ppm", fitted=False,
                                  source="held at 1000 ppm (residual after ref. [30]); < 0.01° per 10° step"),
}


#: Grid of the fitted parameters (log-spaced inside ERROR_PRIORS); latency is a post-hoc axis. The AHRS
#: stand-in's rows do not depend on the RAMS noise and change by < 10 % over the rig grid (checked:
#: lever arm 0.02 vs 0.2 m, 100 vs 1000 °/s²), so it runs once, at the middle lever arm and
#: acceleration, over the heading-disturbance values.
FIT_GRID = {"lever_arm_m": (0.1, 0.14, 0.2, 0.28, 0.4),
            "move_accel_deg_s2": (300.0, 1000.0, 3000.0),
            "accel_noise_ug_rt_hz": (35.0, 50.0, 70.0, 100.0),
            "magnetic_heading_sigma_deg": (0.5, 1.0, 2.0, 5.0)}
#: AHRS stand-in repetitions per heading value and axis at full size: 4 heading values × 250 = 1000 distinct runs
#: under each AHRS Table 5 band (the suite's ≥ 1000 draws per band, docs/conventions.md).
AHRS_REPS_FULL = 250
#: Coarser grid for CI-size runs (same ranges, fewer points).
FIT_GRID_CI = {"lever_arm_m": (0.14, 0.2, 0.28),
               "move_accel_deg_s2": (1000.0, 3000.0),
               "accel_noise_ug_rt_hz": (50.0, 100.0),
               "magnetic_heading_sigma_deg": (1.0, 2.0)}
LATENCY_GRID_S = np.round(np.arange(0.0, 0.0501, 0.001), 4)
#: Table 5 systems: paper name → ours.
SYSTEMS = {"RAMS": "RAMS", "Method in ref. [16]": "ref. [16]", "Ellipse2-N": "AHRS stand-in"}
#: Declared training subset: (axis, system, kind) -- the ``train`` rows of ``paper_data/wang2022sensors_split.csv``.
#: ref. [16] Bv2/Bv3 are training replicates: our ref. [16] model does not depend on the axis, so those rows
#: are near-copies of the Bv1 rows and carry no independent test.
TRAINING = (tuple((a, "RAMS", k) for k in ("static", "dynamic") for a in ("Bv1", "Bv2", "Bv3"))
            + tuple((a, "ref. [16]", k) for a in ("Bv1", "Bv2", "Bv3") for k in ("static", "dynamic"))
            + (("Bv1", "AHRS stand-in", "static"),))
#: Held-out Table 5 numbers (the ``heldout`` rows of the split): the AHRS (Ellipse2-N) rows not in TRAINING.
HELD_OUT = (("Bv1", "AHRS stand-in", "dynamic"),) + tuple(
    (a, "AHRS stand-in", k) for a in ("Bv2", "Bv3") for k in ("static", "dynamic"))
#: Stream of the leak-test predictive draws (:func:`fit_and_predict`).
STREAM_LEAK_DRAWS = 530
#: Grid of :func:`fit_and_predict` at CI size (one rig cell, two noise and two heading values).
LEAK_GRID_CI = {"lever_arm_m": (0.2,), "move_accel_deg_s2": (1000.0,), "accel_noise_ug_rt_hz": (50.0, 100.0),
                "magnetic_heading_sigma_deg": (1.0, 2.0)}
#: Model discrepancy (1σ of log RMSE): 15 %, declared before the fit.
DISCREPANCY_LOG_SD = 0.15


def paper_table5() -> dict[tuple[str, str, str], float]:
    """Table 5 as the fit sees it: {(axis, our system name, "static"/"dynamic"): RMSE in deg}.

    From :func:`mtcal.reporting.paper_numbers.training`: held-out numbers are NaN.
    """
    df = paper_numbers.training("wang2022sensors")["wang2022sensors_table05_rmse"]
    out = {}
    for r in df.itertuples():
        out[(r.rotation_axis, SYSTEMS[r.system], "static")] = float(r.rmse_static_deg)
        out[(r.rotation_axis, SYSTEMS[r.system], "dynamic")] = float(r.rmse_dynamic_deg)
    return out


@dataclass(frozen=True)
class GridRun:
    """Monte Carlo over the fit grid.

    ``cells`` (C, 3) parameter values in FIT_GRID key order; ``latency_s`` (L,);
    ``heading_deg`` (S,) AHRS heading-disturbance grid;
    ``log_rmse[(system, kind)]`` (C, L, S, A, R) log of RMSE in deg, with L = 1 (AHRS: no
    latency) or S = 1 (RAMS, ref. [16]: no magnetometer) where a quantity does not depend on it;
    ``hold_max_deg`` (C, A, R, H) RAMS max |error| per sweep hold (settled half);
    ``hold_max_whole_deg`` (C, A, R, H) the same over the whole hold;
    ``dynamic_max_deg`` (C, L, A, R) RAMS max |error| over the moving (ZVD dynamic) sweep samples, per latency;
    ``hold_angle_deg`` (H,); ``axes`` (A,) names.
    """

    names: tuple
    cells: np.ndarray
    latency_s: np.ndarray
    heading_deg: np.ndarray
    axes: tuple
    log_rmse: dict
    hold_max_deg: np.ndarray
    hold_angle_deg: np.ndarray
    hold_max_whole_deg: np.ndarray
    dynamic_max_deg: np.ndarray


def run_grid(sc: Scenario, reps: int, seed: int, *, grid: dict | None = None, latencies_s=None,
             ahrs: AhrsImu | None = None, ahrs_reps: int = 2) -> GridRun:
    """Simulate the Sec. 7 test (three Table 4 axes) at every grid cell; keep per-trial metrics only.

    One batched run per move acceleration (the time base changes with it); trials =
    lever arm × accel noise × axis × repetition. The AHRS stand-in runs once over the
    heading-disturbance values (see :data:`FIT_GRID`) and is shared by every cell.
    """
    g = FIT_GRID if grid is None else grid
    lat = LATENCY_GRID_S if latencies_s is None else np.asarray(latencies_s, float)
    ah = AhrsImu() if ahrs is None else ahrs
    if int(reps) < 2 or int(ahrs_reps) < 2:
        raise ValueError(f"reps and ahrs_reps must be >= 2 (the repetition variance enters the likelihood), got "
                         f"{reps!r}, {ahrs_reps!r}")
    imu = sc.imu.resolve()
    rig0 = sc.rig.resolve()
    axes_d = table4_axes()
    names = tuple(axes_d)
    ax = np.stack([axes_d[n] for n in names])
    levers, accels, noises = g["lever_arm_m"], g["move_accel_deg_s2"], g["accel_noise_ug_rt_hz"]
    n_l, n_a, n_n, n_ax = len(levers), len(accels), len(noises), len(names)
    shape = (n_l, n_a, n_n)
    keys = [(s, k) for s in ("RAMS", "ref. [16]") for k in ("static", "dynamic")]
    heading = tuple(g["magnetic_heading_sigma_deg"])
    out = {k: np.empty(shape + (lat.size, 1, n_ax, reps)) for k in keys}
    ahrs_out = {("AHRS stand-in", k): np.empty(shape + (1, len(heading), n_ax, ahrs_reps))
                for k in ("static", "dynamic")}
    hold = hold_whole = None
    dyn_max = np.empty(shape + (lat.size, n_ax, reps))
    for ia, acc in enumerate(accels):
        rig = replace(rig0, move_accel_rad_s2=acc * DEG)
        il, inn, iax, ir = (x.ravel() for x in np.meshgrid(np.arange(n_l), np.arange(n_n), np.arange(n_ax),
                                                            np.arange(reps), indexing="ij"))
        v = ax[iax]
        lever = np.stack([lever_arm_vector(vv, levers[i], rig.lever_arm_up_m) for vv, i in zip(v, il)])
        ids = ((ia * n_l + il) * n_n + inn) * 1000 + iax * 100 + ir
        m = sweep_metrics(rig, imu, v, lever, seed, ids, latencies_s=lat,
                          accel_noise_m_s2_rt_hz=np.asarray(noises)[inn] * UG)
        for (s, k), arr in out.items():
            val = getattr(m, {"RAMS": "rams", "ref. [16]": "ref16"}[s] + "_" + k)  # (T, L)
            arr[il, ia, inn, :, 0, iax, ir] = np.log(np.maximum(val, 1e-9))
        if hold is None:
            hold = np.empty(shape + (n_ax, reps, m.hold_max.shape[1]))
            hold_whole = np.empty_like(hold)
        hold[il, ia, inn, iax, ir] = m.hold_max
        hold_whole[il, ia, inn, iax, ir] = m.hold_max_whole
        dyn_max[il, ia, inn, :, iax, ir] = m.dynamic_max
    # AHRS stand-in: one batched run at the middle lever arm and acceleration (its rows change by
    # < 10 % over the rig grid, checked), over the heading-disturbance grid; shared by every cell
    rig = replace(rig0, move_accel_rad_s2=accels[n_a // 2] * DEG)
    hs, jax, jr = (x.ravel() for x in np.meshgrid(np.arange(len(heading)), np.arange(n_ax),
                                                  np.arange(ahrs_reps), indexing="ij"))
    va = ax[jax]
    lever_a = np.stack([lever_arm_vector(vv, levers[n_l // 2], rig.lever_arm_up_m) for vv in va])
    st, dy = ahrs_sweep_metrics(rig, imu.dt_s, va, lever_a, ah, seed, hs * 1000 + jax * 100 + jr,
                                heading_sigma_deg=np.asarray(heading)[hs])
    for k, val in (("static", st), ("dynamic", dy)):
        ahrs_out[("AHRS stand-in", k)][:, :, :, 0, hs, jax, jr] = np.log(np.maximum(val, 1e-9))
    cells = np.array([(lv, acc, nn) for lv in levers for acc in accels for nn in noises], float)
    flat = {k: v.reshape((-1,) + v.shape[3:]) for k, v in {**out, **ahrs_out}.items()}
    return GridRun(("lever_arm_m", "move_accel_deg_s2", "accel_noise_ug_rt_hz"), cells, lat,
                   np.asarray(heading, float), names, flat, hold.reshape((-1,) + hold.shape[3:]), m.hold_angle_deg,
                   hold_whole.reshape((-1,) + hold_whole.shape[3:]), dyn_max.reshape((-1,) + dyn_max.shape[3:]))


def _key_array(grid: GridRun, axis: str, system: str, kind: str) -> np.ndarray:
    """log RMSE (C, L, S, R) for one Table 5 entry (broadcast over the axes it does not depend on)."""
    arr = grid.log_rmse[(system, kind)][:, :, :, grid.axes.index(axis)]
    return np.broadcast_to(arr, (arr.shape[0], grid.latency_s.size, grid.heading_deg.size, arr.shape[-1]))


def simulated_runs(grid: GridRun, key) -> int:
    """How many distinct simulated runs (grid points × repetitions) the predictive draws of one Table 5
    quantity ``key`` = (axis, system, kind) resample (:func:`predictive_samples`): the band rests on these,
    each spread by the model discrepancy, however many draws are taken."""
    return int(np.unique(_key_array(grid, *key)).size)


def log_likelihood(grid: GridRun, keys=TRAINING, values: dict | None = None,
                   discrepancy_log_sd: float = DISCREPANCY_LOG_SD) -> np.ndarray:
    """Σ over ``keys`` of log N(log y; μ_c,l,s, s²_MC + s_d²): (C, L, S)."""
    vals = paper_table5() if values is None else values
    ll = np.zeros((grid.cells.shape[0], grid.latency_s.size, grid.heading_deg.size))
    for key in keys:
        x = _key_array(grid, *key)
        mu = x.mean(axis=-1)
        s2 = float(np.mean(x.var(axis=-1, ddof=1))) + discrepancy_log_sd ** 2
        ll += -0.5 * (np.log(vals[key]) - mu) ** 2 / s2 - 0.5 * np.log(2 * np.pi * s2)
    return ll


def posterior_weights(grid: GridRun, keys=TRAINING, values: dict | None = None) -> np.ndarray:
    """Posterior over (cell, latency, heading) with a uniform prior on the grid: (C, L, S), sums to 1."""
    ll = log_likelihood(grid, keys, values)
    w = np.exp(ll - ll.max())
    return w / w.sum()


def prior_weights(grid: GridRun) -> np.ndarray:
    """Uniform weights over (cell, latency, heading): the prior (prior-predictive baseline)."""
    w = np.ones((grid.cells.shape[0], grid.latency_s.size, grid.heading_deg.size))
    return w / w.sum()


def weighted_quantile(x: np.ndarray, w: np.ndarray, q) -> np.ndarray:
    """Quantiles ``q`` of a discrete distribution (values ``x``, weights ``w``), lower-value convention."""
    order = np.argsort(x)
    cw = np.cumsum(w[order]) / np.sum(w)
    return x[order][np.minimum(np.searchsorted(cw, np.asarray(q, float) - 1e-12), x.size - 1)]


def parameter_summary(grid: GridRun, weights: np.ndarray) -> pd.DataFrame:
    """Posterior mean, sd, 95 % interval and MAP of each fitted parameter, beside its prior range."""
    rows = []
    cols = {n: grid.cells[:, i][:, None, None] * np.ones_like(weights) for i, n in enumerate(grid.names)}
    cols["latency_s"] = grid.latency_s[None, :, None] * np.ones_like(weights)
    cols["magnetic_heading_sigma_deg"] = grid.heading_deg[None, None, :] * np.ones_like(weights)
    imap = np.unravel_index(np.argmax(weights), weights.shape)
    for name, val in cols.items():
        pr = ERROR_PRIORS[name]
        scale = 1e3 if name == "latency_s" else 1.0
        unit = "ms" if name == "latency_s" else pr["unit"]
        x, w = val.ravel() * scale, weights.ravel()
        mean = float(np.sum(w * x))
        sd = float(np.sqrt(np.sum(w * (x - mean) ** 2)))
        lo, hi = weighted_quantile(x, w, [0.025, 0.975])
        rows.append({"parameter": name, "unit": unit, "prior_low": pr["low"] * scale, "prior_high": pr["high"] * scale,
                     "posterior_mean": mean, "posterior_sd": sd, "low_95": float(lo), "high_95": float(hi),
                     "map": float(val[imap] * scale),
                     "inside_prior": bool(pr["low"] * scale <= lo and hi <= pr["high"] * scale),
                     "source": pr["source"]})
    return pd.DataFrame(rows)


def predictive_samples(grid: GridRun, weights: np.ndarray, key, rng: np.random.Generator, n: int = 4000,
                       discrepancy_log_sd: float = DISCREPANCY_LOG_SD) -> np.ndarray:
    """Draws (deg) of one Table 5 quantity: a grid point by weight, a repetition, × the discrepancy."""
    x = _key_array(grid, *key)
    flat = rng.choice(weights.size, size=n, p=weights.ravel())
    c, l, h = np.unravel_index(flat, weights.shape)
    r = rng.integers(0, x.shape[-1], size=n)
    return np.exp(x[c, l, h, r] + discrepancy_log_sd * rng.standard_normal(n))


def fig14_samples(grid: GridRun, weights: np.ndarray, rng: np.random.Generator, n: int = 4000,
                  window: str = "settled half") -> np.ndarray:
    """Draws (deg) of one experiment's largest per-angle max error (any axis), over each hold's ``window``.

    ``window``: ``"settled half"`` (the second half of each 1 s hold) or ``"whole hold"``.
    """
    if window not in FIG14_WINDOWS:
        raise ValueError(f"window must be one of {FIG14_WINDOWS}, got {window!r}")
    per = grid.hold_max_deg if window == "settled half" else grid.hold_max_whole_deg
    worst = per.max(axis=-1)  # (C, A, R)
    wc = weights.sum(axis=(1, 2))
    c = rng.choice(wc.size, size=n, p=wc)
    a = rng.integers(0, worst.shape[1], size=n)
    r = rng.integers(0, worst.shape[2], size=n)
    return worst[c, a, r]


def dynamic_max_samples(grid: GridRun, weights: np.ndarray, rng: np.random.Generator, n: int = 4000) -> np.ndarray:
    """Draws (deg) of one experiment's largest RAMS error while moving (ZVD dynamic samples, −180…180° sweep).

    Each draw picks a grid point (rig cell and latency; the heading disturbance does not enter the RAMS) by
    ``weights`` (C, L, S), an axis and a repetition there. The paper's claim c02: "a dynamic measurement error of
    less than 1° in the range of ±180°".
    """
    wcl = weights.sum(axis=2)  # (C, L)
    flat = rng.choice(wcl.size, size=n, p=wcl.ravel())
    c, l = np.unravel_index(flat, wcl.shape)
    a = rng.integers(0, grid.dynamic_max_deg.shape[2], size=n)
    r = rng.integers(0, grid.dynamic_max_deg.shape[3], size=n)
    return grid.dynamic_max_deg[c, l, a, r]


def dynamic_max_given_training(grid: GridRun, bound_deg: float = 1.0,
                               discrepancy_log_sd: float = DISCREPANCY_LOG_SD) -> dict:
    """How far the training implies claim c02: the prior runs' largest RAMS error while moving below ``bound_deg``,
    in the grid points whose RAMS dynamic Table 5 RMSEs (the training numbers c02 shares its error source with:
    latency × rate) all lie within 1.96 σ of the paper's (σ as in :func:`log_likelihood`) and in the others.

    Returns :func:`mtcal.reporting.compare.implied_by_training` over the (cell, latency, axis, repetition) runs,
    each equally likely under the prior.
    """
    x = grid.log_rmse[("RAMS", "dynamic")][:, :, 0]                      # (C, L, A, R)
    sd = np.sqrt(float(np.mean(x.var(axis=-1, ddof=1))) + discrepancy_log_sd ** 2)
    paper = paper_table5()
    near = np.ones(x.shape[:2], bool)
    for i, axis in enumerate(grid.axes):
        near &= np.abs(np.log(paper[(axis, "RAMS", "dynamic")]) - x[:, :, i].mean(axis=-1)) <= 1.96 * sd
    holds = grid.dynamic_max_deg < bound_deg
    training = np.broadcast_to(near[:, :, None, None], holds.shape)
    return compare.implied_by_training(holds.ravel(), training.ravel())


#: Readings of Fig. 14's "maximum measurement error for various angles": the error over each hold's settled second
#: half, or over the whole hold.
FIG14_WINDOWS = ("settled half", "whole hold")
__all__ += ["AHRS_REPS_FULL", "fig14_samples", "dynamic_max_samples", "dynamic_max_given_training", "FIG14_WINDOWS", "ErrorModelFit", "fit_error_model", "error_model_priors_table"]


@dataclass(frozen=True)
class ErrorModelFit:
    """The grid Monte Carlo, posterior and prior weights, and the fitted parameter table."""

    grid: GridRun
    posterior: np.ndarray
    prior: np.ndarray
    parameters: pd.DataFrame

    def map_parameters(self) -> dict:
        """MAP values in parameters-cell names (lever arm, move acceleration, latency)."""
        p = self.parameters.set_index("parameter")["map"]
        return {"lever_arm_m": float(p["lever_arm_m"]), "move_accel_deg_s2": float(p["move_accel_deg_s2"]),
                "latency_s": float(p["latency_s"]) / 1e3}


@cached  # Monte Carlo result cached under $MTCAL_CACHE_DIR (make reproduce/artifact)
def fit_error_model(sc: Scenario, reps: int, seed: int, grid: dict | None = None,
                    ahrs_reps: int = 2) -> ErrorModelFit:
    """Run the grid Monte Carlo and fit the error model to :data:`TRAINING` (see there).

    ``ahrs_reps``: repetitions of the AHRS stand-in per heading value and axis (:func:`run_grid`); its Table 5
    bands resample heading values × ``ahrs_reps`` distinct runs (:func:`simulated_runs`), so a band that rests
    on ≥ 1000 runs needs ``ahrs_reps`` ≥ 1000 / (heading values) (:data:`AHRS_REPS_FULL` at :data:`FIT_GRID`).
    """
    g = run_grid(sc, reps, seed, grid=grid, ahrs_reps=ahrs_reps)
    post = posterior_weights(g)
    return ErrorModelFit(g, post, prior_weights(g), parameter_summary(g, post))


def error_model_priors_table() -> pd.DataFrame:
    """The hardware error sources: prior range, unit, fitted or held, and the source of the range."""
    return pd.DataFrame([{"parameter": k, "low": v["low"], "high": v["high"], "unit": v["unit"],
                          "fitted": v["fitted"], "source": v["source"]} for k, v in ERROR_PRIORS.items()])


@leak.register("wang2022sensors")
def fit_and_predict(size: str = "ci", seed: int = 0) -> dict[str, np.ndarray]:
    """The error-model fit and its predictive bands from scratch, for the leak test (:mod:`mtcal.reporting.leak`).

    Parameters
    ----------
    size : {"ci", "full"}
        ``"ci"``: :data:`LEAK_GRID_CI` (seconds); ``"full"``: :data:`FIT_GRID`.
    seed : int
        RNG seed.

    Returns
    -------
    dict of str -> ndarray
        ``posterior`` (C, L, S) weights, ``parameters`` (P, 5) posterior mean, sd, 2.5 %, 97.5 %, MAP,
        ``bands_fitted`` / ``bands_prior`` (K, 3) 2.5/50/97.5 % of every Table 5 entry
        (TRAINING + HELD_OUT order) and ``fig14`` (3,) of the Fig. 14 bound.
    """
    if size not in ("ci", "full"):
        raise ValueError(f"size must be 'ci' or 'full', got {size!r}")
    sc = scenario_from_parameters()
    fit = fit_error_model(sc, 2, seed, grid=LEAK_GRID_CI if size == "ci" else FIT_GRID,
                          ahrs_reps=2 if size == "ci" else AHRS_REPS_FULL)
    rng = stream_rng(seed, STREAM_LEAK_DRAWS)
    q = [2.5, 50.0, 97.5]
    bands = {m: np.array([np.percentile(predictive_samples(fit.grid, w, k, rng, 2000), q)
                          for k in TRAINING + HELD_OUT]) for m, w in (("fitted", fit.posterior), ("prior", fit.prior))}
    cols = ["posterior_mean", "posterior_sd", "low_95", "high_95", "map"]
    return {"posterior": fit.posterior, "parameters": fit.parameters[cols].to_numpy(float),
            "bands_fitted": bands["fitted"], "bands_prior": bands["prior"],
            "fig14": np.percentile(fig14_samples(fit.grid, fit.posterior, rng, 2000), q)}


__all__ += ["fit_and_predict", "STREAM_LEAK_DRAWS", "LEAK_GRID_CI"]
