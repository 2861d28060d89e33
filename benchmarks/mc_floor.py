"""The CPU floor of `make reproduce`: the wang2023cja Monte Carlo alone, at the draw counts the band rule requires.

Issue #24 asks for a full-size `make reproduce` in <= 3 min on 2 cores with every printed band
resting on >= 1000 draws (docs/conventions.md, "Bands"). Notebooks 10 and 11 must therefore run,
at least:

* notebook 10: 1000 T1 sessions (with their AoA and roll sweeps) for the fitted model and 1000
  for the prior model, and 1000 T2–T4 triples for the fitted model;
* notebook 11: 1000 wind-tunnel runs for each of the two models.

This script times those library procedures (:func:`mtcal.studies.wang2023cja.predictive.turntable_predictive`
and :func:`~mtcal.studies.wang2023cja.predictive.windtunnel_predictive`, the calls the notebooks
make) on a few trials each, in the numerics environment `make reproduce` uses (pinned,
CPU-independent arithmetic: :func:`mtcal.runs.environment.numerics_env`) and on one thread,
measures CPU seconds per trial (``time.process_time``), and scales to the counts above. Divided by
2 cores it is a lower bound on the wall time of `make reproduce` at full size: perfect scaling, and
nothing else of those notebooks or of the other seven is counted.

Run alone::

    .venv/bin/python benchmarks/mc_floor.py --trials 20 --json

(the environment is set by the script itself, in a child process). `benchmarks/run.py` prints it
as the row under "make reproduce ... <= 3 min".
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: Draws per printed band required by docs/conventions.md ("Bands"): the notebooks' full size.
DRAWS_PER_BAND = 1000
#: Cores the issue-#24 target assumes.
CORES = 2
SEED = 2023


def _measure(trials: int) -> dict:
    """CPU seconds per trial of each procedure (this process, after an untimed warm-up of each)."""
    from mtcal.studies import wang2023cja as w
    from mtcal.studies.wang2023cja import predictive

    fit = w.fit_error_model(seed=SEED)
    sc = w.turntable_scenario(errors=fit.model)

    def t1(n):
        return predictive.turntable_predictive(sc, fit, "fitted", n, SEED, tests=("T1",))

    def t234(n):
        return predictive.turntable_predictive(sc, fit, "fitted", n, SEED + 1, tests=("T2", "T3", "T4"))

    def wind(n):
        return predictive.windtunnel_predictive(lambda m: w.windtunnel_scenario(errors=m), fit, "fitted", n, SEED,
                                                per_draw=5)

    out = {"trials": trials}
    for name, call in (("t1", t1), ("t234", t234), ("windtunnel", wind)):
        call(2)                                   # compile / fill the caches outside the timing
        c0 = time.process_time()
        call(trials)
        out[f"{name}_cpu_s_per_trial"] = (time.process_time() - c0) / trials
    c0 = time.process_time()
    w.fit_error_model(seed=SEED + 1)
    out["fit_cpu_s"] = time.process_time() - c0
    return out


def floor(per_trial: dict, draws: int = DRAWS_PER_BAND, cores: int = CORES) -> dict:
    """CPU seconds of the two notebooks' Monte Carlo at ``draws`` per band, and that over ``cores``.

    >>> f = floor({"t1_cpu_s_per_trial": 0.1, "t234_cpu_s_per_trial": 0.05, "windtunnel_cpu_s_per_trial": 0.2,
    ...            "fit_cpu_s": 5.0}, draws=1000, cores=2)
    >>> round(f["cpu_s"], 6), round(f["wall_floor_s"], 6)
    (660.0, 330.0)
    """
    nb10 = draws * (2 * per_trial["t1_cpu_s_per_trial"] + per_trial["t234_cpu_s_per_trial"]) + per_trial["fit_cpu_s"]
    nb11 = draws * 2 * per_trial["windtunnel_cpu_s_per_trial"] + per_trial["fit_cpu_s"]
    return {"nb10_cpu_s": nb10, "nb11_cpu_s": nb11, "cpu_s": nb10 + nb11, "wall_floor_s": (nb10 + nb11) / cores,
            "draws": draws, "cores": cores}


def run_child(trials: int) -> dict:
    """:func:`_measure` in a child process with the numerics environment and one numba thread."""
    sys.path.insert(0, str(ROOT))
    from mtcal.runs.environment import numerics_env

    env = dict(os.environ, **numerics_env(), NUMBA_NUM_THREADS="1", MTCAL_PROGRESS="0")
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT)] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p])
    res = subprocess.run([sys.executable, __file__, "--trials", str(trials), "--child"], cwd=ROOT, env=env,
                         capture_output=True, text=True, check=True)
    per_trial = json.loads(res.stdout.strip().splitlines()[-1])
    return {**per_trial, **floor(per_trial)}


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trials", type=int, default=20, help="trials timed per procedure (default 20)")
    ap.add_argument("--json", action="store_true", help="print one JSON line")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.trials < 2:
        ap.error(f"--trials must be >= 2, got {args.trials}")
    if args.child:
        out = _measure(args.trials)
        print(json.dumps(out))
        return out
    out = run_child(args.trials)
    if args.json:
        print(json.dumps(out))
    else:
        print(f"per trial (serial CPU, pinned arithmetic): T1 {out['t1_cpu_s_per_trial'] * 1e3:.0f} ms, "
              f"T2-T4 {out['t234_cpu_s_per_trial'] * 1e3:.0f} ms, wind tunnel "
              f"{out['windtunnel_cpu_s_per_trial'] * 1e3:.0f} ms; error-model fit {out['fit_cpu_s']:.1f} s")
        print(f"at {out['draws']} draws per band: notebook 10 {out['nb10_cpu_s']:.0f} CPU-s, notebook 11 "
              f"{out['nb11_cpu_s']:.0f} CPU-s; on {out['cores']} cores >= {out['wall_floor_s']:.0f} s")
    return out


if __name__ == "__main__":
    main()
