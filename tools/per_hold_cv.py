"""Leave-one-table-out check of the wang2023cja per-rest angle error: white (as committed) vs a drift.

Usage (from the repository root, the Makefile's environment)::

    python tools/per_hold_cv.py [--n-mc 4000] [--seed 2023]

Deviation D6 (docs/deviations.md) is the random angle error drawn independently at every rest
(and every sweep hold), ``position_error_arcsec`` ≈ 49″. The candidate that could replace it is a
time-correlated **drift**: a random walk over the session's rest times (the paper's §4.1 reading —
"the random drift errors of the gyro increase with time"), normalised so that its RMS over the 13
rests of a session equals σ (the same unit as the white term). Everything else is the committed
error model and likelihood (:func:`mtcal.studies.wang2023cja.error_model.fit_error_model`'s
linearised Gaussian, its Monte Carlo covariances, its logistic-transformed Nelder–Mead).

For each fold (one of Tables 1–4 held out) both variants are fitted on the other three tables and
score the held-out table's 18 "after − reference" numbers: log predictive density (linearised
Gaussian), coverage of the marginal 95 % intervals and the mean interval score (deg). The drift
replaces the white term only if it predicts better (higher summed log density, coverage no worse).

It complements :mod:`mtcal.studies.wang2023cja.crossval` (the same folds, scoring the committed
model's 95 % bands against the no-physics and prior baselines, where the per-rest structure is not a
switch): here two noise structures are compared by their held-out log density, a strictly proper
score. It writes nothing. Seeded: the same numbers on every run.
"""

from __future__ import annotations

import argparse
import sys
import time
import numpy as np

from mtcal.core.rng import stream_rng
from mtcal.core.units import DEG
from mtcal.reporting import fidelity
from mtcal.studies.wang2023cja import error_model as em

STREAM_DRIFT = 240          # random stream of the drift normals (mtcal.core.rng rule)
VARIANTS = ("white", "drift")


def drift_normals(z: np.ndarray, times_s: np.ndarray) -> np.ndarray:
    """``z`` (n, N_NORMALS) with its 13 rest-angle triples replaced by a unit-RMS random walk over the rest times."""
    k = times_s.size
    run_s = float(times_s[-1]) + 5.0
    t = np.concatenate([[0.0], times_s, run_s + times_s])          # rest_residuals' rest times
    dt = np.diff(np.concatenate([[-(t[1] - t[0])], t]))             # the start rest has one step of its own
    z_pos = z[:, :3 * (2 * k + 1)].reshape(z.shape[0], 2 * k + 1, 3)
    walk = np.cumsum(np.sqrt(dt)[None, :, None] * z_pos, axis=1) / np.sqrt(np.mean(np.cumsum(dt)))
    out = z.copy()
    out[:, :3 * (2 * k + 1)] = walk.reshape(z.shape[0], -1)
    return out


def linear_tests(variant: str, n_mc: int, seed: int) -> dict:
    """The committed linearised tests of Tables 1–4, the position source's covariance per ``variant``."""
    alphas = {t: em.fit_installation_angles(tab).alpha_rad for t, tab in em.TABLES_1_TO_4.items()}
    times = em.rest_times_s(em.paper_positions(), 20 * DEG, 3.0, 100.0)
    tests = em._linear_tests(alphas, n_mc, seed, times)
    if variant == "drift":
        rng = stream_rng(seed, STREAM_DRIFT)
        for test, lt in tests.items():
            z = drift_normals(rng.standard_normal((n_mc, em.N_NORMALS)), times)
            sim = em._residual_matrix(alphas[test], em._only_unchecked("position_error_arcsec", 1.0), lt.mount, z, times)
            lt.cov_unit["position_error_arcsec"] = np.cov(sim, rowvar=False)
    return tests


def fit(tests: dict) -> em.ErrorModel:
    """ML values on ``tests`` (the committed optimiser, :func:`error_model._maximise`)."""
    return em._maximise(tests, em.ErrorModel())[0]


def score(model: em.ErrorModel, lt) -> dict:
    """Held-out scores of one table: log density, inside count of 95 % marginal intervals, mean interval score (deg)."""
    mean, cov = em._linear_moments(model, lt)
    sd = np.sqrt(np.diag(cov))
    lo, hi = np.degrees(mean - 1.96 * sd), np.degrees(mean + 1.96 * sd)
    y = np.degrees(lt.data)
    return {"loglik": em._loglik(model, {"t": lt}), "inside": int(np.sum((lo <= y) & (y <= hi))), "n": int(y.size),
            "interval_score_deg": float(np.mean(fidelity.interval_score(lo, hi, y)))}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n-mc", type=int, default=4000, help="Monte Carlo draws of each covariance (the fit's default)")
    ap.add_argument("--seed", type=int, default=2023, help="seed (notebook 10's SEED)")
    a = ap.parse_args(argv)
    if a.n_mc < 100:
        print(f"per_hold_cv: error: --n-mc must be >= 100, got {a.n_mc}", file=sys.stderr)
        return 2
    t0 = time.perf_counter()
    total = {}
    for variant in VARIANTS:
        tests = linear_tests(variant, a.n_mc, a.seed)
        full = fit(tests)
        print(f"{variant}: all four tables: σ {full.position_error_arcsec:.1f}″, log L {em._loglik(full, tests):.1f}")
        s_all = []
        for held in em.TABLES_1_TO_4:
            m = fit({t: lt for t, lt in tests.items() if t != held})
            s = score(m, tests[held])
            s_all.append(s)
            print(f"  {variant:5s} fold {held}: σ {m.position_error_arcsec:6.1f}″  held-out log density {s['loglik']:8.2f}  "
                  f"inside {s['inside']:2d}/{s['n']}  interval score {s['interval_score_deg']:.4f}°")
        total[variant] = {"loglik": sum(s["loglik"] for s in s_all), "inside": sum(s["inside"] for s in s_all),
                          "n": sum(s["n"] for s in s_all),
                          "interval_score_deg": float(np.mean([s["interval_score_deg"] for s in s_all]))}
    for v, s in total.items():
        print(f"{v:5s} total: held-out log density {s['loglik']:.2f}, inside {s['inside']}/{s['n']}, "
              f"mean interval score {s['interval_score_deg']:.4f}°")
    better = (total["drift"]["loglik"] > total["white"]["loglik"] and total["drift"]["inside"] >= total["white"]["inside"])
    print(f"decision: {'drift predicts better: replace the white term' if better else 'keep the white per-rest term'} "
          f"(n_mc {a.n_mc}, seed {a.seed}; {time.perf_counter() - t0:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
