"""wang2023cja leave-one-table-out cross-validation over Tables 1–4: blind by construction.

Each fold holds out one six-position verification table (Table 1: T1 screwed; Tables 2–4:
T2–T4 gasket-raised, §4.1 Figs 4–6), fits the error model on the other three
(:func:`.error_model.fit_error_model` with ``tables=``; the fold's fit opens only those three
tables' "before" and "after" columns), and predicts the 18 "after − reference" numbers of the
held-out table (the printed reference is an ``input``). No reading of the held-out table can bias
its prediction: the leak test (``tests/studies/test_wang2023cja_crossval.py``) perturbs the
held-out table's printed numbers and finds the fold's fit and bands bit-identical.

Choices, stated once:

* **Installation angles of the held-out test** (default ``alpha_source="prior"``): drawn per
  draw from their prior :data:`.predictive.ALPHA_PRIOR_SIGMA_DEG` — the held-out table is not
  read at all, "before" columns included. ``"before"`` instead fits them to the held-out
  table's own "before" columns (an input of the calibration procedure, as the full model does
  for every test) and never reads its "after" columns. The "after" residual left by Eq 10–13
  hardly depends on the angles: measured (seed 2023, 2000 draws per fold), the two give the same
  inside counts on every fold and a pooled mean interval score of 0.2026° either way.
* **Parameters the training tables cannot identify** (:func:`.error_model.identified_parameters`:
  the screwed-mount compliance when T1 is held out) are drawn from the prior
  (:func:`.predictive.prior_draws`); the others from the fold fit's posterior
  (:func:`.predictive.posterior_draws`, through its public signature).
* **Rest level, not the full simulator.** Each draw is one calibration + verification session of
  the rest-level model the fit's likelihood uses (:func:`.error_model.rest_residuals`: QNCF
  static equilibrium), all draws in one vectorised call (:class:`.error_model.ErrorModelDraws`).
  This is the consistent predictive of a rest-level fit: the fitted per-rest angle error (≈ 49″)
  already stands for what the rest level does not resolve, so the full simulator's sensor terms
  (notebook 10's ``wang2023cja_extra_error_budget``: gyro white noise 0.007° RMS after calibration,
  every other sensor term ≤ 0.003°, against 0.021° from the per-rest angle error) would count
  them twice. Cost, measured (seed 2023, Makefile environment, loaded 2-core machine): the four
  fold fits 6.8 CPU-s (cached by ``fit_error_model``), the predictions of 4 folds × 2 bands ×
  2000 draws 1.0 CPU-s; the full simulator costs 0.034 CPU-s per T2 session, i.e. ≈ 540 CPU-s
  for the same draws.

Baselines, scored on the same 18 rows per fold with the same interval score
(:func:`mtcal.reporting.fidelity.interval_score`, Gneiting & Raftery 2007 Eq 43, α = 0.05):

* ``fitted`` — the model (fold posterior predictive, above);
* ``prior`` — the prior predictive (:func:`.predictive.prior_draws`: error model from its prior
  ranges, installation angles from their prior; nothing fitted), same rest-level simulation;
* ``no-physics`` — ``0 ± 1.96 s``, ``s`` the RMS of the fold's *training* tables' 54
  "after − reference" residuals (:func:`.verdicts.no_physics_halfwidth_deg`).

References
----------
wang2023cja Tables 1–4 (six-position verification, "before"/"after" columns), Eq 10–13 (the
least-squares error quaternion matrix), §4.1 Figs 4–6 (mounts); Gneiting T., Raftery A. E.,
"Strictly proper scoring rules, prediction, and estimation", JASA 2007, Eq 43; issue #33 item 4.

Examples
--------
>>> training_tests("T2")
('T1', 'T3', 'T4')
>>> rows = cross_validate(n_draws=1000, n_mc=500, folds=("T3",))
>>> len(rows), int(rows["n"].iloc[0]), sorted(set(rows["fold"]))
(18, 1000, ['T3'])
>>> s = fold_scores(rows)
>>> list(s.baseline.unique())
['fitted', 'prior', 'no-physics']
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pandas as pd

from mtcal.core import metrics
from mtcal.core.cache import cached
from mtcal.core.rng import stream_rng
from mtcal.reporting import fidelity, paper_numbers
from .error_model import (FITTED_PARAMETERS, MOUNT_TYPE, N_NORMALS, PAPER_SIGN, TABLES_1_TO_4, ErrorModelDraws,
                          ErrorModelFit, fit_error_model, fit_installation_angles, identified_parameters,
                          paper_positions, rest_residuals)
from .predictive import ALPHA_PRIOR_SIGMA_DEG, posterior_draws, prior_draws
from .verdicts import no_physics_halfwidth_deg

__all__ = ["FOLDS", "ALPHA_SOURCES", "CV_BASELINES", "N_DRAWS", "ROLE", "training_tests", "fold_fit",
           "predicted_after_deg", "fold_draws", "predict_fold", "cross_validate", "fold_scores", "fold_artifact",
           "cv_records"]

# random streams of this module (mtcal.core.rng rule: key (seed, stream, fold))
STREAM_CV_ALPHA = 230      # held-out installation angles from their prior
STREAM_CV_NORMALS = 231    # rest-level session normals of the predictions

#: Held-out test of each fold (Table k ↔ Tk).
FOLDS = tuple(TABLES_1_TO_4)
#: Where the held-out test's installation angles come from.
ALPHA_SOURCES = ("prior", "before")
#: Predictive bands scored per fold (the model, then the two baselines).
CV_BASELINES = fidelity.CV_BASELINES
#: Parameter draws (= simulated sessions) per fold: a 95 % band from ≥ 1000 draws.
N_DRAWS = 2000
#: Role of the cross-validated rows in ``data/fidelity_scores.csv``.
ROLE = fidelity.CV_ROLE
_ANG = ("yaw", "pitch", "roll")


def _check_fold(heldout: str) -> str:
    if heldout not in FOLDS:
        raise ValueError(f"heldout must be one of {FOLDS}, got {heldout!r}")
    return heldout


def training_tests(heldout: str) -> tuple:
    """The three tests a fold fits on: every one of :data:`FOLDS` but ``heldout``."""
    _check_fold(heldout)
    return tuple(t for t in FOLDS if t != heldout)


def fold_fit(heldout: str, *, n_mc: int = 4000, seed: int = 2023) -> ErrorModelFit:
    """The error model fitted on the three tables other than ``heldout`` (same settings as the full fit)."""
    return fit_error_model(n_mc=n_mc, seed=seed, tables=training_tests(heldout))


def predicted_after_deg(models, alpha_rad, mount: str, z) -> np.ndarray:
    """Printed "after − reference" (deg, the paper's sign) of one verification table per draw, (n, 6, 3).

    Parameters
    ----------
    models : sequence of ErrorModel (n,)
        One error model per draw.
    alpha_rad : ndarray (n, 3)
        Installation angles per draw (rad, Eq 1).
    mount : {"screw", "gasket"}
    z : ndarray (n, N_NORMALS)
        Standard normals of the n sessions (:func:`.error_model.rest_residuals`).
    """
    res = rest_residuals(np.asarray(alpha_rad, float), ErrorModelDraws.stack(models), mount, z)
    return PAPER_SIGN * np.degrees(metrics.angle_difference(res["after"], paper_positions()[None]))


def fold_draws(heldout: str, fit: ErrorModelFit | None, n: int, seed: int, *, alpha_source: str = "prior"):
    """``(models, alpha_rad (n, 3))`` of one fold: the fold fit's posterior, or the prior when ``fit`` is None.

    With a fit: :func:`.predictive.posterior_draws`, every field the fold's training tables cannot
    identify replaced by its prior draw (:func:`.predictive.prior_draws`, same ``n`` and ``seed``), and
    the held-out test's installation angles from ``alpha_source`` (see the module docstring). Without a
    fit: :func:`.predictive.prior_draws` (angles from their prior).
    """
    _check_fold(heldout)
    if alpha_source not in ALPHA_SOURCES:
        raise ValueError(f"alpha_source must be one of {ALPHA_SOURCES}, got {alpha_source!r}")
    prior = prior_draws(n, seed)
    if fit is None:
        return [m for m, _ in prior], np.radians([a[heldout] for _, a in prior])
    if heldout in fit.alpha_rad:
        raise ValueError(f"the fit read the held-out test {heldout!r}: fit it with tables={training_tests(heldout)}")
    fixed = [f for f in FITTED_PARAMETERS if f not in identified_parameters(fit.alpha_rad)]
    post = posterior_draws(fit, n, seed)
    models = [replace(m, **{f: getattr(p, f) for f in fixed}) for (m, _), (p, _) in zip(post, prior)]
    if alpha_source == "prior":
        rng = stream_rng(int(seed), STREAM_CV_ALPHA, FOLDS.index(heldout))
        alpha = np.radians(rng.normal(0.0, ALPHA_PRIOR_SIGMA_DEG[heldout], (len(models), 3)))
    else:   # the held-out table's "before" columns (an input); its "after" columns are not read
        alpha = np.broadcast_to(fit_installation_angles(TABLES_1_TO_4[heldout]).alpha_rad, (len(models), 3))
    return models, alpha


def _paper_after(heldout: str):
    """Keys and printed "after − reference" (deg) of the held-out table: read for scoring only."""
    table = TABLES_1_TO_4[heldout]
    df = paper_numbers.load(table)
    keys, values = [], []
    for k in range(6):
        for a in _ANG:
            keys.append((table, k + 1, f"{a}_after_deg"))
            values.append(float(df[f"{a}_after_deg"].iloc[k]) - float(df[f"{a}_reference_deg"].iloc[k]))
    return keys, np.array(values)


def predict_fold(heldout: str, draws: dict, seed: int) -> dict:
    """Bands of the 18 "after − reference" numbers of ``heldout`` from each set of draws.

    Parameters
    ----------
    heldout : str
        Held-out test (:data:`FOLDS`).
    draws : dict
        Name → ``(models, alpha_rad)`` (:func:`fold_draws`), or name → half-width (deg) of a
        ``0 ± half`` band with no physics.
    seed : int
        Seed of the sessions' normals (the same normals for every set of draws of the fold: paired).

    Returns
    -------
    dict
        Name → ``{"median", "low", "high"}`` arrays (18,) in table order (positions 1–6 × yaw, pitch,
        roll), ``"n"`` and ``"kind"`` (:func:`mtcal.core.metrics.band_or_range`).
    """
    mount = MOUNT_TYPE[_check_fold(heldout)]
    out = {}
    for name, d in draws.items():
        if np.isscalar(d):
            half = float(d)
            out[name] = {"median": np.zeros(18), "low": np.full(18, -half), "high": np.full(18, half),
                         "n": 0, "kind": "no-physics band"}
            continue
        models, alpha = d
        z = stream_rng(int(seed), STREAM_CV_NORMALS, FOLDS.index(heldout)).standard_normal((len(models), N_NORMALS))
        b = metrics.band_or_range(predicted_after_deg(models, alpha, mount, z).reshape(len(models), 18))
        out[name] = {"median": b["median"], "low": b["low"], "high": b["high"], "n": b["n"], "kind": b["kind"]}
    return out


@cached  # the four fold fits and their predictions, under $MTCAL_CACHE_DIR (make reproduce)
def cross_validate(*, n_draws: int = N_DRAWS, n_mc: int = 4000, seed: int = 2023, alpha_source: str = "prior",
                   folds=FOLDS) -> pd.DataFrame:
    """Leave-one-table-out cross-validation over Tables 1–4: one row per held-out printed number.

    Parameters
    ----------
    n_draws : int
        Parameter draws (sessions) per fold and baseline (≥ 1000 for a 95 % band).
    n_mc : int
        Monte Carlo draws of each fold fit's likelihood (:func:`.error_model.fit_error_model`).
    seed : int
    alpha_source : {"prior", "before"}
        Held-out installation angles (module docstring).
    folds : sequence of str
        Held-out tests to run (default all four).

    Returns
    -------
    DataFrame
        ``fold, file, row, column, quantity, paper`` (printed after − reference, deg), then per
        baseline ``b`` of :data:`CV_BASELINES`: ``b_median, b_low, b_high, b_inside, b_interval_score``
        (deg, α = 0.05), and ``n``/``kind`` of the model's band.
    """
    if int(n_draws) < 1:
        raise ValueError(f"n_draws must be >= 1, got {n_draws}")
    rows = []
    for heldout in folds:
        fit = fold_fit(heldout, n_mc=n_mc, seed=seed)
        draws = {"fitted": fold_draws(heldout, fit, int(n_draws), seed, alpha_source=alpha_source),
                 "prior": fold_draws(heldout, None, int(n_draws), seed),
                 "no-physics": no_physics_halfwidth_deg(training_tests(heldout))}
        bands = predict_fold(heldout, draws, seed)
        keys, paper = _paper_after(heldout)         # scoring only: after the fold's fit and bands exist
        for i, (file, row, column) in enumerate(keys):
            r = {"fold": heldout, "file": file, "row": row, "column": column,
                 "quantity": f"{file.removeprefix('wang2023cja_')} r{row} {column}", "paper": paper[i]}
            for name in CV_BASELINES:
                lo, hi = float(bands[name]["low"][i]), float(bands[name]["high"][i])
                r.update({f"{name}_median": float(bands[name]["median"][i]), f"{name}_low": lo, f"{name}_high": hi,
                          f"{name}_inside": bool(lo <= paper[i] <= hi),
                          f"{name}_interval_score": float(fidelity.interval_score(lo, hi, paper[i]))})
            r.update(n=bands["fitted"]["n"], kind=bands["fitted"]["kind"])
            rows.append(r)
    return pd.DataFrame(rows)


def fold_artifact(heldout: str) -> str:
    """Artifact id of a fold's held-out table, e.g. ``"wang2023cja_table02"``."""
    return f"wang2023cja_table{FOLDS.index(_check_fold(heldout)) + 1:02d}"


def fold_scores(rows: pd.DataFrame) -> pd.DataFrame:
    """Per fold and pooled (``Tables 1–4``): coverage and interval score of each baseline, in degrees.

    Columns ``scope, baseline, n, inside, coverage, coverage_low, coverage_high`` (Wilson 95 %),
    ``median_width_deg, mean_interval_score_deg, median_interval_score_deg`` and
    ``skill_vs_no_physics, skill_vs_prior``: ``1 − mean IS / mean IS of that baseline`` (> 0: better
    than it; 0 for the baseline itself).
    """
    out = []
    scopes = [(fold_artifact(f), rows[rows.fold == f]) for f in FOLDS if (rows.fold == f).any()]
    for scope, part in scopes + [("Tables 1–4", rows)]:
        mean_is = {b: float(part[f"{b}_interval_score"].mean()) for b in CV_BASELINES}
        for b in CV_BASELINES:
            inside, n = int(part[f"{b}_inside"].sum()), len(part)
            lo, hi = fidelity.wilson_interval(inside, n)
            out.append({"scope": scope, "baseline": b, "n": n, "inside": inside, "coverage": inside / n,
                        "coverage_low": lo, "coverage_high": hi,
                        "median_width_deg": float((part[f"{b}_high"] - part[f"{b}_low"]).median()),
                        "mean_interval_score_deg": mean_is[b],
                        "median_interval_score_deg": float(part[f"{b}_interval_score"].median()),
                        "skill_vs_no_physics": 1.0 - mean_is[b] / mean_is["no-physics"],
                        "skill_vs_prior": 1.0 - mean_is[b] / mean_is["prior"]})
    return pd.DataFrame(out)


def cv_records(rows: pd.DataFrame, notebook: str) -> pd.DataFrame:
    """The rows as cross-validation records of :func:`mtcal.reporting.fidelity.write_cv_records`."""
    recs = pd.DataFrame({"notebook": notebook, "paper_key": "wang2023cja",
                         "artifact": [fold_artifact(f) for f in rows["fold"]], "quantity": rows["quantity"],
                         "ref": [f"{f}:{r}:{c}" for f, r, c in zip(rows["file"], rows["row"], rows["column"])],
                         "paper_value": rows["paper"]})
    for b in CV_BASELINES:
        for c in ("median", "low", "high"):
            recs[f"{b}_{c}"] = rows[f"{b}_{c}"].to_numpy(float)
    recs["draws"] = rows["n"].to_numpy(int)
    return recs[fidelity.CV_RECORD_COLUMNS]
