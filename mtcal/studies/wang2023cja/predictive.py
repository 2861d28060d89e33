"""wang2023cja predictive bands: every Monte Carlo trial draws its own parameters.

Two predictive distributions of the same simulation (:mod:`.runs`):

* **fitted posterior predictive** — each draw takes the :class:`.error_model.ErrorModel` from
  the joint Laplace approximation of the fit to Tables 1–4 (:func:`.error_model.fit_error_model`):
  the free values jointly normal with the full inverse-Hessian covariance (correlations kept), a
  value on its prior bound a half-normal from the bound inward whose 95 % point is the one-sided
  profile limit; all clipped to the prior range. Installation angles: those fitted to the
  "before" columns plus a normal draw with their least-squares covariance (:func:`posterior_draws`).
* **sessions per draw** — every parameter draw runs ``per_draw`` sessions (turntable 2, wind tunnel
  5 at full size in notebook 11), so that a band's variance splits into a parameter part
  and a sampling part (law of total variance, :func:`variance_parts`).
* **prior predictive** — each trial draws the error model from its prior ranges (scale
  parameters log-uniform, signed compliances uniform) and the installation angles from
  :data:`ALPHA_PRIOR_SIGMA_DEG` — nothing identified on Tables 1–4 is used.

The 2.5 % and 97.5 % band ends carry a Monte Carlo standard error (:func:`quantile_se`,
bootstrap over trials).

References
----------
wang2023cja §4.1 (Tables 1–8), §4.2 (Tables 9–11).

Examples
--------
>>> from mtcal.studies.wang2023cja.error_model import ErrorModel
>>> draws = prior_draws(3, seed=1)
>>> len(draws), isinstance(draws[0][0], ErrorModel)
(3, True)
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from mtcal.core.metrics import variance_parts  # re-exported here (notebooks 10, 11 call predictive.variance_parts)
from mtcal.core.rng import child_rngs, stream_rng
from mtcal.reporting import leak
from .error_model import FITTED_PARAMETERS, PRIOR_RANGES, TABLES_1_TO_4, ErrorModel, ErrorModelFit
from .runs import (TurntableJob, _map, run_turntable_jobs, run_turntable_jobs_kinds, run_windtunnel,
                   run_windtunnel_kinds, windtunnel_median_trial)

__all__ = ["ALPHA_PRIOR_SIGMA_DEG", "KINDS", "TURNTABLE_PER_DRAW", "variance_parts", "posterior_draws", "prior_draws",
           "turntable_predictive", "turntable_predictive_kinds", "windtunnel_predictive", "windtunnel_predictive_kinds",
           "windtunnel_median_trace", "quantile_se", "LEAK_SIZES",
           "fit_and_predict"]

# random streams of this module (mtcal.core.rng rule)
STREAM_POSTERIOR = 210
STREAM_PRIOR = 211
STREAM_QUANTILE_SE = 212
STREAM_TURNTABLE_TEST = 300   # key (seed, 300 + i): test i of turntable_predictive; its children, one per draw
STREAM_WINDTUNNEL = 11        # key (seed, 11): windtunnel_predictive_kinds; its children, one per draw (each kind)

#: Prior 1σ of each installation angle per test (deg): T1 screwed on a machined plate, T2–T4 one
#: side or corner raised by gaskets (§4.1 Figs 4–6; assumed, not fitted).
ALPHA_PRIOR_SIGMA_DEG = {"T1": 0.3, "T2": 1.5, "T3": 1.5, "T4": 1.5}
#: The two predictive distributions.
KINDS = ("fitted", "prior")
#: Turntable sessions per parameter draw (pairs: the band's variance splits into parameter and sampling parts).
TURNTABLE_PER_DRAW = 2
_SCALE = ("accel_run_bias_mg", "gyro_run_bias_deg_h", "position_error_arcsec", "gasket_load_tilt_deg_g")


def _clip(name, v):
    lo, hi = PRIOR_RANGES[name]
    return float(min(max(v, lo), hi))


def _sqrt_cov(cov) -> np.ndarray:
    """A matrix ``L`` with ``L Lᵀ = cov`` for a symmetric positive semi-definite ``cov`` (eigen-decomposition:
    a zero or slightly negative eigenvalue of a finite-difference Hessian's inverse is clipped to 0)."""
    c = np.asarray(cov, float)
    vals, vecs = np.linalg.eigh(0.5 * (c + c.T))
    return vecs * np.sqrt(np.clip(vals, 0.0, None))


def posterior_draws(fit: ErrorModelFit, n: int, seed: int) -> list[tuple[ErrorModel, dict]]:
    """``n`` parameter draws ``(ErrorModel, alpha_deg per test)`` from the fit's joint Laplace posterior.

    * **free values** (not on a prior bound): jointly normal, ``ML + L z`` with ``L Lᵀ = fit.cov`` (the full
      inverse Hessian of −log L: correlations kept); without a joint covariance (``fit.cov is None``)
      each value from its own σ;
    * **a value on its prior bound** (no Hessian row: the likelihood still rises at the bound): one-sided,
      a half-normal from the bound inward whose 95 % point is the one-sided profile limit
      (``fit.limit95``), independent of the others;
    * **installation angles** of each test: ``α̂ + L_t z_t`` with ``L_t L_tᵀ`` the least-squares
      covariance of the angles fitted to that test's "before" columns (``fit.alpha_cov_rad2``;
      independent of the error-model values, which are fitted to the "after" columns); held at their
      fit when it is ``None``.

    All values are clipped to their prior range. Draw order (seeded stream ``STREAM_POSTERIOR``):
    the (n, 6) error-model normals, then the (n, tests, 3) angle normals.

    >>> import math
    >>> from mtcal.studies.wang2023cja.error_model import ErrorModelFit, ErrorModel
    >>> f = ErrorModelFit(ErrorModel(), {k: 0.0 for k in FITTED_PARAMETERS}, {k: False for k in FITTED_PARAMETERS},
    ...                   0.0, 0.0, {t: np.zeros(3) for t in TABLES_1_TO_4}, 72, {k: math.nan for k in FITTED_PARAMETERS})
    >>> posterior_draws(f, 2, 0)[1][0] == ErrorModel()
    True
    """
    n = int(n)
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n}")
    rng = stream_rng(int(seed), STREAM_POSTERIOR)
    z = rng.standard_normal((n, len(FITTED_PARAMETERS)))
    tests = sorted(fit.alpha_rad)
    z_alpha = rng.standard_normal((n, len(tests), 3))
    ml = np.array([getattr(fit.model, name) for name in FITTED_PARAMETERS])
    x = ml.copy()[None].repeat(n, axis=0)
    free = [FITTED_PARAMETERS.index(name) for name in fit.free]   # a field the fit did not estimate stays at its value
    if fit.cov is not None and free:
        x[:, free] = ml[free] + z[:, free] @ _sqrt_cov(fit.cov).T
    else:
        for j in free:
            sd = fit.std[FITTED_PARAMETERS[j]]
            x[:, j] = ml[j] + z[:, j] * (sd if np.isfinite(sd) else 0.0)
    for j, name in enumerate(FITTED_PARAMETERS):
        if fit.at_bound[name]:
            lim = fit.limit95[name]
            if not np.isfinite(lim):
                lo, hi = PRIOR_RANGES[name]
                lim = hi if abs(ml[j] - lo) < abs(ml[j] - hi) else lo
            x[:, j] = ml[j] + np.sign(lim - ml[j]) * np.abs(z[:, j]) * abs(lim - ml[j]) / 1.96
    alpha = np.stack([np.broadcast_to(fit.alpha_rad[t], (n, 3)) for t in tests], axis=1).astype(float)
    if fit.alpha_cov_rad2 is not None:
        for k, t in enumerate(tests):
            alpha[:, k] += z_alpha[:, k] @ _sqrt_cov(fit.alpha_cov_rad2[t]).T
    alpha_deg = np.degrees(alpha)
    out = []
    for i in range(n):
        vals = {name: _clip(name, x[i, j]) for j, name in enumerate(FITTED_PARAMETERS)}
        out.append((replace(fit.model, **vals),
                    {t: tuple(float(v) for v in alpha_deg[i, k]) for k, t in enumerate(tests)}))
    return out


def prior_draws(n: int, seed: int) -> list[tuple[ErrorModel, dict]]:
    """``n`` parameter draws from the prior: scale parameters log-uniform, compliances uniform, angles normal."""
    n = int(n)
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n}")
    rng = stream_rng(int(seed), STREAM_PRIOR)
    out = []
    for _ in range(n):
        vals = {}
        for name in FITTED_PARAMETERS:
            lo, hi = PRIOR_RANGES[name]
            if name in _SCALE and lo > 0:
                vals[name] = _clip(name, float(np.exp(rng.uniform(np.log(lo), np.log(hi)))))
            else:
                vals[name] = _clip(name, float(rng.uniform(lo, hi)))
        alpha = {t: tuple(float(x) for x in rng.normal(0.0, s, 3)) for t, s in ALPHA_PRIOR_SIGMA_DEG.items()}
        out.append((ErrorModel(**vals), alpha))
    return out


def _draws(kind, fit, n, seed):
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {KINDS}, got {kind!r}")
    return posterior_draws(fit, n, seed) if kind == "fitted" else prior_draws(n, seed)


def turntable_predictive(sc, fit: ErrorModelFit, kind: str, trials: int, seed: int, *,
                         tests=("T1", "T2", "T3", "T4"), per_draw: int = TURNTABLE_PER_DRAW) -> dict:
    """Turntable sessions (T1 with its sweeps) with one parameter draw per ``per_draw`` trials.

    Parameters
    ----------
    sc : TurntableScenario
        The scenario (its ``errors``/``alpha_deg`` are replaced draw by draw).
    fit : ErrorModelFit
    kind : {"fitted", "prior"}
    trials : int
        Trials (sessions) per test.
    seed : int
    tests : tuple of str
        Tests to run.
    per_draw : int
        Consecutive trials sharing one parameter draw (the last draw may have fewer): trials
        ``per_draw·k … per_draw·k + per_draw − 1`` share draw ``k``, each session its own noise
        (:func:`variance_parts` splits a band's variance with them).

    Returns
    -------
    dict test → TurntableRun (trial axis = sessions, draw-major). :func:`turntable_predictive_kinds`
    runs several kinds at once (the same numbers).
    """
    return turntable_predictive_kinds(sc, fit, (kind,), trials, seed, tests=tests, per_draw=per_draw)[kind]


def turntable_predictive_kinds(sc, fit: ErrorModelFit, kinds, trials: int, seed: int, *,
                               tests=("T1", "T2", "T3", "T4"), per_draw: int = TURNTABLE_PER_DRAW) -> dict:
    """:func:`turntable_predictive` of each kind in ``kinds``, the kinds' T1 sessions side by side.

    Trial *j* of every kind draws from the same generator key, so the kinds' T1 pieces run in the same
    stacked QNCF calls, their IMU records filled together with the sensor noise (equal scales: the
    sensor spec's) drawn once (:func:`.runs.run_turntable_jobs_kinds`; each call holds the same number of
    trials as one kind alone); every kind keeps its own generators and parameter draws, so each run
    equals the one of a separate :func:`turntable_predictive` call bit for bit. T2–T4 run kind by kind.

    Returns
    -------
    dict kind → dict test → TurntableRun.
    """
    per_draw = int(per_draw)
    if per_draw < 1:
        raise ValueError(f"per_draw must be >= 1, got {per_draw}")
    for test in tests:
        if test not in TABLES_1_TO_4:
            raise ValueError(f"tests must be names from {sorted(TABLES_1_TO_4)}, got {test!r}")
    kinds = tuple(kinds)
    n_draws = -(-int(trials) // per_draw)
    jobs = {}
    for kind in kinds:
        draws = _draws(kind, fit, n_draws, seed)
        jobs[kind] = {}
        for i, test in enumerate(tests):
            rngs = child_rngs(stream_rng(int(seed), STREAM_TURNTABLE_TEST + i), n_draws)
            jobs[kind][test] = [TurntableJob(test, r, min(per_draw, int(trials) - k * per_draw), errors=m,
                                             alpha_deg=a[test]) for k, (r, (m, a)) in enumerate(zip(rngs, draws))]
    out = {kind: {} for kind in kinds}
    if "T1" in tests:
        t1 = run_turntable_jobs_kinds(sc, [jobs[kind]["T1"] for kind in kinds], with_sweeps=True, keep_trace=True,
                                      block=1)
        for m, kind in enumerate(kinds):        # each kind's per-job runs dropped once stacked (peak: one copy)
            out[kind]["T1"], t1[m] = _stack_jobs(t1[m]), None
    rest = [t for t in tests if t != "T1"]
    for kind in kinds if rest else ():
        # the sessions of one draw side by side (T2, T3, T4 of draw 0, then of draw 1, …): a draw's gasket
        # sessions share their compliance and so one truth trajectory (core.simulate.RecordSource); every job keeps
        # its own generator, so the numbers are those of one call per test
        runs = run_turntable_jobs(sc, [jobs[kind][t][j] for j in range(n_draws) for t in rest], block=1)
        out[kind].update((t, _stack_jobs(runs[k::len(rest)])) for k, t in enumerate(rest))
    return {kind: {t: out[kind][t] for t in tests} for kind in kinds}


def _stack_jobs(runs):
    from .runs import _concat_runs

    return _concat_runs(runs)


def windtunnel_predictive(make_scenario, fit: ErrorModelFit, kind: str, trials: int, seed: int, *,
                          per_draw: int = 5):
    """Wind-tunnel runs with one parameter draw per ``per_draw`` trials, the median session traced.

    ``make_scenario(errors)`` builds the :class:`WindTunnelScenario` of one draw (its installation
    angles and pitch-ratio error come from the printed wind-tunnel matrix: train; the turntable
    installation-angle draws do not enter). Returns one :class:`WindTunnelRun` with ``trials`` trials,
    draw-major (:func:`variance_parts` with ``per_draw``), its ``trace`` the median session's time series
    (:func:`windtunnel_median_trace`). :func:`windtunnel_predictive_kinds` runs several kinds at once (the
    same numbers).
    """
    run = windtunnel_predictive_kinds(make_scenario, fit, (kind,), trials, seed, per_draw=per_draw)[kind]
    run.trace = windtunnel_median_trace(make_scenario, fit, kind, run, seed, per_draw=per_draw)
    return run


def windtunnel_predictive_kinds(make_scenario, fit: ErrorModelFit, kinds, trials: int, seed: int, *,
                                per_draw: int = 5) -> dict:
    """:func:`windtunnel_predictive` of each kind in ``kinds``, draw by draw side by side.

    Trial *j* of every kind draws from the same generator key, so the kinds of one draw run side by
    side (:func:`.runs.run_windtunnel_kinds`): their IMU records are filled together, the sensor noise
    (equal scales: the sensor spec's) drawn once, and the wind-on accelerometer vibration (phases,
    time base and settings equal; checked) computed once; every kind keeps its own generators and
    parameter draws, so each run equals the one of a separate :func:`windtunnel_predictive` call bit
    for bit.

    Returns
    -------
    dict kind → WindTunnelRun, each ``trace`` holding its median session's index only (``"median_trial"``:
    :func:`windtunnel_median_trace` re-runs that session for the figures' time series).
    """
    per_draw = int(per_draw)
    if per_draw < 1:
        raise ValueError(f"per_draw must be >= 1, got {per_draw}")
    kinds = tuple(kinds)
    n_draws = -(-int(trials) // per_draw)
    draws = {kind: _draws(kind, fit, n_draws, seed) for kind in kinds}
    children = lambda: child_rngs(stream_rng(int(seed), STREAM_WINDTUNNEL), n_draws)  # noqa: E731
    rngs = {kind: children() for kind in kinds}          # one generator per kind and draw (run_windtunnel spawns)

    def one(k):       # each draw its own generators and scenarios: the same numbers for any thread count
        # the kinds' blocks side by side: their IMU records filled together (noise drawn once), the wind-on
        # vibration computed by the first kind (shared)
        return run_windtunnel_kinds([make_scenario(draws[kind][k][0]) for kind in kinds], [rngs[kind][k] for kind in kinds],
                                    min(per_draw, int(trials) - k * per_draw), block=per_draw, keep_trace=False, shared={})

    runs = _map(one, list(range(n_draws)))
    return {kind: _windtunnel_draws([r[i] for r in runs]) for i, kind in enumerate(kinds)}


def windtunnel_median_trace(make_scenario, fit: ErrorModelFit, kind: str, run, seed: int, *, per_draw: int = 5) -> dict:
    """The time series of ``run``'s median session (never trial 0) for the figures: that session's parameter draw
    re-run from a fresh copy of its generator, its trace kept (the same numbers as in ``run``).

    ``run`` is the :class:`WindTunnelRun` of :func:`windtunnel_predictive_kinds` for ``kind`` with these
    arguments (``make_scenario``, ``fit``, ``seed``, ``per_draw``); returns its ``trace`` with ``"median_trial"``.
    """
    per_draw = int(per_draw)
    trials = int(run.q_matrix.shape[0])
    n_draws = -(-trials // per_draw)
    k, i = divmod(int(run.trace["median_trial"]), per_draw)
    draw = _draws(kind, fit, n_draws, seed)[k]
    rng = child_rngs(stream_rng(int(seed), STREAM_WINDTUNNEL), n_draws)[k]
    trace = run_windtunnel(make_scenario(draw[0]), rng, min(per_draw, trials - k * per_draw), block=per_draw,
                           keep_trace=True, trace_trial=i).trace
    trace["median_trial"] = k * per_draw + i
    return trace


def _windtunnel_draws(runs):
    """The draws' runs as one WindTunnelRun, its median session named (``trace["median_trial"]``)."""
    cat = lambda xs: np.concatenate(xs, axis=0)  # noqa: E731
    first = runs[0]
    first.q_matrix = cat([r.q_matrix for r in runs])
    first.cal_before = cat([r.cal_before for r in runs])
    first.cal_after = cat([r.cal_after for r in runs])
    first.nowind = {k: (v if k == "reference" else cat([r.nowind[k] for r in runs])) for k, v in first.nowind.items()}
    if first.wind_on is not None:
        w = dict(first.wind_on)
        w["group_means"] = np.concatenate([r.wind_on["group_means"] for r in runs], axis=1)
        w["gate_fraction_on_trials"] = cat([r.wind_on["gate_fraction_on_trials"] for r in runs])
        w["gate_fraction_on"] = float(np.mean(w["gate_fraction_on_trials"]))
        first.wind_on = w
    first.trace = {"median_trial": windtunnel_median_trial(first)}
    return first


def quantile_se(samples, q: float, *, n_boot: int = 400, seed: int = 0) -> float:
    """Monte Carlo standard error of the ``q`` quantile (0–1) of 1-D ``samples``: bootstrap over trials.

    >>> round(quantile_se(np.arange(100.0), 0.5, seed=1), 1) > 0
    True
    """
    x = np.asarray(samples, float)
    if x.ndim != 1 or x.size < 2:
        raise ValueError(f"samples must be 1-D with at least 2 values, got shape {x.shape}")
    if not 0 < q < 1:
        raise ValueError(f"q must be in (0, 1), got {q}")
    rng = stream_rng(int(seed), STREAM_QUANTILE_SE)
    idx = rng.integers(0, x.size, (int(n_boot), x.size))
    return float(np.std(np.quantile(x[idx], q, axis=1), ddof=1))


#: Leak-test sizes: (fit Monte Carlo draws, turntable trials, wind-tunnel trials, sample rate Hz).
LEAK_SIZES = {"ci": (4000, 2, 2, 200.0), "full": (4000, 10, 10, 1000.0)}


@leak.register("wang2023cja")
def fit_and_predict(size: str = "ci", seed: int = 0) -> dict:
    """The fit and the predictions no fit may read, for the leak test (:mod:`mtcal.reporting.leak`).

    Fits the error model (Tables 1–4) and the wind-tunnel geometry (printed matrix), then
    predicts every held-out and tuned printed number (posterior predictive) with a small Monte Carlo:
    the leak test perturbs both, so none of these outputs may move.

    Parameters
    ----------
    size : {"ci", "full"}
        Monte Carlo size (:data:`LEAK_SIZES`).
    seed : int

    Returns
    -------
    dict of str → ndarray
        ``params`` (fitted values, σ, installation angles), ``windtunnel`` (angles, ratio error),
        and per held-out or tuned cell ``<file>:<row>:<column>`` its (median, low, high) of our number
        (measured from the printed reference, an ``input``).

    References
    ----------
    Issue #21 item 2; wang2023cja Tables 1–4 (train), 6 and 8 (held out), 5, 7 and 9–11 (tuned).

    Examples
    --------
    >>> sorted(LEAK_SIZES)
    ['ci', 'full']
    """
    from mtcal.core import metrics

    from .error_model import fit_error_model
    from .scenario import turntable_scenario, windtunnel_geometry, windtunnel_scenario
    from .verdicts import printed_samples, split

    if size not in LEAK_SIZES:
        raise ValueError(f"size must be one of {sorted(LEAK_SIZES)}, got {size!r}")
    n_mc, n_tt, n_wt, fs = LEAK_SIZES[size]
    fit = fit_error_model(n_mc=n_mc, seed=int(seed))
    out = {"params": np.array([getattr(fit.model, n) for n in FITTED_PARAMETERS]
                              + [fit.std[n] for n in FITTED_PARAMETERS]
                              + [float(x) for t in sorted(fit.alpha_rad) for x in fit.alpha_rad[t]])}
    alpha, ratio = windtunnel_geometry()
    out["windtunnel"] = np.array(list(alpha) + [ratio])
    sc = turntable_scenario(errors=fit.model, fs_hz=fs)
    tt = turntable_predictive(sc, fit, "fitted", n_tt, int(seed), tests=("T1",))
    wt = windtunnel_predictive(lambda m: windtunnel_scenario(errors=m, fs_hz=fs), fit, "fitted", n_wt, int(seed),
                               per_draw=n_wt)
    samples = printed_samples(tt, wt)
    sp = split()
    for r in sp[sp.role.isin(("heldout", "tuned"))].itertuples(index=False):   # every number no fit may read
        off, s = samples[(r.file, int(r.row), r.column)]
        b = metrics.percentile_band(np.asarray(s, float) - off)
        out[f"{r.file}:{r.row}:{r.column}"] = np.array([b["median"], b["low"], b["high"]], float)
    return out
