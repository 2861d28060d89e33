"""Score effects of the wang2023cja deviations-ledger entries D5 and D6 (docs/deviations.md).

Usage (from the repository root, the Makefile's environment)::

    python tools/ledger_effects.py [--trials 1000] [--seed 2023]

Runs the library's own fit and posterior/prior predictive (``w.fit_error_model``,
``predictive.turntable_predictive`` on the T1 session with its sweeps, ``verdicts.one_to_one``,
``fidelity.aggregate``: the code path of notebook 10 at the paper's settings) and prints, for the
48 wang2023cja numbers of Tables 5–8 (held out when D5 and D6 were made; Tables 5 and 7 tuned since D10),
the scores ``fidelity_scores.csv`` reported for them, for:

* ``as committed`` — the model as it stands (position_error_arcsec prior (1, 300)″, per-hold term on);
* ``D5 without`` — the prior range of ``position_error_arcsec`` back to (1, 60)″ (refit, new draws);
* ``D6 without`` — no random angle error at the sweep holds (the term added to the Table 5/7 hold
  means is added back: the same trials, paired). ``ALPHA_PRIOR_SIGMA_DEG`` enters the prior
  predictive only (the fitted draws use the angles fitted on Tables 1–4), so its part of D6 has no
  "without" for the fitted rows; before d256e51 there was no prior predictive at all.

Nothing is written; the model is not changed (the two switches are scoped patches, restored on
exit). Seeded: the same numbers on every run.
"""

from __future__ import annotations

import argparse
import contextlib
import sys
import time

import numpy as np
import pandas as pd

from mtcal.reporting import fidelity
from mtcal.studies import wang2023cja as w
from mtcal.studies.wang2023cja import error_model, predictive, runs, verdicts

HOLD_ERROR_KEY = runs.HOLD_ERROR_KEY   # each sweep's per-hold angle errors, kept by the run
OLD_POSITION_ERROR_RANGE = (1.0, 60.0)   # the prior range before d256e51


@contextlib.contextmanager
def position_error_range(bounds):
    """``PRIOR_RANGES['position_error_arcsec']`` set to ``bounds`` (the one dict the fit and the draws read)."""
    old = error_model.PRIOR_RANGES["position_error_arcsec"]
    error_model.PRIOR_RANGES["position_error_arcsec"] = tuple(bounds)
    try:
        yield
    finally:
        error_model.PRIOR_RANGES["position_error_arcsec"] = old


def without_hold_errors(run_t1):
    """A copy of a T1 run's sweeps whose hold means carry no per-hold angle error (D6 switched off)."""
    out = dict(run_t1.sweeps)
    for name, d in run_t1.sweeps.items():
        e = d[HOLD_ERROR_KEY]
        out[name] = {**d, "before_mean": d["before_mean"] + e, "after_mean": d["after_mean"] + e}
    return out


#: The tables whose numbers D5 and D6 were judged on: held out when those entries were made (Tables 5 and 7
#: tuned since D10, because of D6 itself), so the effects are computed on all 48 of them, whatever their role now.
D5_D6_TABLES = ("wang2023cja_table05", "wang2023cja_table06", "wang2023cja_table07", "wang2023cja_table08")


def heldout_scores(samples: dict, seed: int) -> dict:
    """The fidelity scores of the Tables 5–8 rows of ``samples`` (``verdicts.printed_samples`` output), the 48
    numbers held out when D5 and D6 were made (:data:`D5_D6_TABLES`)."""
    one = verdicts.one_to_one(samples, seed=seed)
    t = one[one.role.isin(("heldout", "tuned")) & one.file.str.startswith(D5_D6_TABLES)]
    recs = pd.DataFrame({"paper_value": t["paper"].to_numpy(float), "fitted_low": t["low"].to_numpy(float),
                         "fitted_high": t["high"].to_numpy(float), "fitted_median": t["median"].to_numpy(float)})
    s = fidelity.aggregate(recs, "fitted")
    kinds = sorted(set(t["kind"]))
    return {"n": s["n"], "inside": s["inside"], "coverage": s["coverage"], "coverage_low": s["coverage_low"],
            "coverage_high": s["coverage_high"], "median_rel_width": s["median_rel_width"],
            "mean_rel_interval_score": s["mean_rel_interval_score"],
            "median_rel_interval_score": s["median_rel_interval_score"], "kind": "/".join(kinds),
            "draws": int(t["n"].min())}


def variant(trials: int, seed: int) -> dict:
    """Fit, then the T1 fitted and prior predictive (their sweeps keep the hold errors); returns runs and the fit."""
    t0 = time.perf_counter()
    fit = w.fit_error_model(seed=seed)
    sc = w.turntable_scenario(errors=fit.model)
    r = {kind: predictive.turntable_predictive(sc, fit, kind, trials, seed, tests=("T1",))["T1"]
         for kind in predictive.KINDS}
    return {"fit": fit, "runs": r, "seconds": time.perf_counter() - t0}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trials", type=int, default=1000,
                    help="T1 sessions per model (TURNTABLE_PER_DRAW per parameter draw; D5/D6 were computed with one)")
    ap.add_argument("--seed", type=int, default=2023, help="seed of the fit and the draws (notebook 10's SEED)")
    a = ap.parse_args(argv)
    if a.trials < 2:
        print(f"ledger_effects: error: --trials must be >= 2, got {a.trials}", file=sys.stderr)
        return 2
    t_all = time.perf_counter()
    now = variant(a.trials, a.seed)
    with position_error_range(OLD_POSITION_ERROR_RANGE):
        old = variant(a.trials, a.seed)
    rows = []
    for label, v, hold in (("as committed (300″ cap, per-hold term)", now, True),
                           ("D5 without (60″ cap, per-hold term)", old, True),
                           ("D6 without (300″ cap, no per-hold term)", now, False),
                           ("D5 and D6 without (60″ cap, no per-hold term)", old, False)):
        for kind in predictive.KINDS:
            run = v["runs"][kind]
            sweeps = run.sweeps if hold else without_hold_errors(run)
            samples = verdicts.printed_samples({"T1": _with_sweeps(run, sweeps)})
            s = heldout_scores(samples, a.seed)
            rows.append({"variant": label, "predictive": kind,
                         "position_error_ml_arcsec": round(v["fit"].model.position_error_arcsec, 1),
                         "at_bound": v["fit"].at_bound["position_error_arcsec"], **s})
    pd.set_option("display.width", 250)
    pd.set_option("display.max_columns", 30)
    print(pd.DataFrame(rows).to_string(index=False, float_format=lambda x: f"{x:.4f}"))
    print(f"trials {a.trials} per model, seed {a.seed}; fit + predictive {now['seconds']:.0f} s (as committed), "
          f"{old['seconds']:.0f} s (60″ cap); total {time.perf_counter() - t_all:.0f} s")
    return 0


def _with_sweeps(run, sweeps):
    from dataclasses import replace

    return replace(run, sweeps=sweeps)


if __name__ == "__main__":
    sys.exit(main())
