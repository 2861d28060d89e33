"""Sweep scaling: throughput on 1 worker, 2 local processes and a 2-worker Dask LocalCluster.

Workload: the ``attitude`` evaluator (wang2023cja turntable AoA sweep at 100 Hz,
1 s holds, QNCF + Mahony, tactical/industrial/consumer/navigation grades), a
grid of 4 cells × ``--trials`` trials in tasks of ``--block`` trials.

Measured:

* per-task compute cost ``t_task`` (``run_block`` called in this process, median of
  a few calls) and peak memory of one task (``tracemalloc``);
* wall time of the whole sweep with ``workers=1`` (in-process), ``workers=2``
  (``ProcessPoolExecutor``, pool start-up included) and on a 2-worker
  ``dask.distributed.LocalCluster`` (processes, 1 thread each; cluster start-up
  timed separately);
* the per-task overhead of each executor, ``o = (W · wall − n_tasks · t_task) / n_tasks``;
* the Dask scheduler's per-task cost ``o_sched`` from 2000 no-op tasks.

Projection of a 10⁶-trial grid (same evaluator, same block size) on W workers::

    wall(W) ≈ start-up + n_tasks · (t_task + o_worker) / W + n_tasks · o_sched

with ``o_worker`` the measured Dask per-task overhead (serialisation, transfer)
and ``o_sched`` the scheduler's serial cost, which bounds the speed-up of very
many workers (raise ``block_trials`` to amortise it).

Usage::

    .venv/bin/python benchmarks/bench_sweep.py            # ≈ 1–2 min on 2 cores
    .venv/bin/python benchmarks/bench_sweep.py --quick    # ≈ 15 s
    .venv/bin/python benchmarks/bench_sweep.py --csv data/bench_sweep.csv

Numbers depend on the machine and its load (printed); they are not checked by CI.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time
import tracemalloc
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from mtcal.sweep.engine import run_block, run_sweep  # noqa: E402
from mtcal.sweep.spec import SweepSpec  # noqa: E402


def workload(trials: int, block: int) -> SweepSpec:
    return SweepSpec(name="bench", evaluator="attitude", seed=1, trials=trials, block_trials=block,
                     fixed={"motion": "aoa", "filters": ["qncf", "mahony"], "fs_hz": 100.0, "hold_s": 1.0},
                     grid={"grade": ["navigation", "tactical", "industrial", "consumer"]})


def _noop(x):
    return x


def task_cost(spec: SweepSpec, repeats: int) -> tuple[float, float]:
    """Median wall time of one task in this process, and its tracemalloc peak (bytes)."""
    from mtcal.sweep.evaluators import get_evaluator

    params = get_evaluator(spec.evaluator).resolve(spec.cells()[0])
    run_block(spec.evaluator, params, spec.seed, 0, 0, spec.block_trials)          # warm-up (numba cache, imports)
    times = []
    for r in range(repeats):
        t0 = time.perf_counter()
        run_block(spec.evaluator, params, spec.seed, 0, 0, spec.block_trials)
        times.append(time.perf_counter() - t0)
    tracemalloc.start()
    run_block(spec.evaluator, params, spec.seed, 0, 0, spec.block_trials)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return statistics.median(times), float(peak)


def timed(fn) -> float:
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small sizes (≈ 15 s)")
    ap.add_argument("--trials", type=int, default=None, help="trials per cell (default 64, quick 16)")
    ap.add_argument("--block", type=int, default=8, help="trials per task")
    ap.add_argument("--csv", default=None, help="write the measurements here (CSV)")
    args = ap.parse_args(argv)
    trials = args.trials or (16 if args.quick else 64)
    spec = workload(trials, args.block)
    n_tasks = spec.n_cells * -(-trials // args.block)
    print(f"load average before: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    print(f"workload: attitude evaluator, {spec.n_cells} cells x {trials} trials, {args.block} trials/task "
          f"-> {n_tasks} tasks")
    t_task, peak = task_cost(spec, 2 if args.quick else 4)
    rows = [{"quantity": "task compute cost (s/task)", "value": t_task},
            {"quantity": "trial compute cost (s/trial)", "value": t_task / args.block},
            {"quantity": "task peak memory (MB, tracemalloc)", "value": peak / 1e6}]
    compute = n_tasks * t_task
    results = {}
    walls = {"1 worker (in-process)": (1, lambda: run_sweep(spec, workers=1, progress=False)),
             "2 local processes": (2, lambda: run_sweep(spec, workers=2, progress=False))}
    tables = {}
    for label, (w, fn) in walls.items():
        wall = timed(lambda: tables.setdefault(label, fn().table))
        results[label] = (w, wall)
    dask_ok = True
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        dask_ok = False
        print("dask.distributed not installed: Dask rows skipped")
    o_sched = float("nan")
    if dask_ok:
        t0 = time.perf_counter()
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
        client = Client(cluster)
        startup = time.perf_counter() - t0
        rows.append({"quantity": "dask LocalCluster start-up (s)", "value": startup})
        client.run(lambda: __import__("mtcal.sweep.evaluators"))
        label = "2-worker dask LocalCluster"
        wall = timed(lambda: tables.setdefault(label, run_sweep(spec, scheduler=client, progress=False).table))
        results[label] = (2, wall)
        n_noop = 2000
        t0 = time.perf_counter()
        futs = client.map(_noop, range(n_noop), pure=False)
        client.gather(futs)
        o_sched = (time.perf_counter() - t0) / n_noop
        del futs
        client.close()
        cluster.close()
        rows.append({"quantity": "dask per-task scheduling cost, no-op tasks (s/task)", "value": o_sched})
    same = len({t.to_csv(index=False) for t in tables.values()}) == 1
    for label, (w, wall) in results.items():
        overhead = (w * wall - compute) / n_tasks
        rows += [{"quantity": f"{label}: wall (s)", "value": wall},
                 {"quantity": f"{label}: throughput (trials/s)", "value": spec.n_cells * trials / wall},
                 {"quantity": f"{label}: per-cell wall (s/cell)", "value": wall / spec.n_cells},
                 {"quantity": f"{label}: per-task overhead (s/task)", "value": overhead}]
    # projection of a 10^6-trial grid
    n_big = 1_000_000 // args.block
    dask_label = "2-worker dask LocalCluster"
    o_worker = max((2 * results[dask_label][1] - compute) / n_tasks, 0.0) if dask_label in results else \
        max((2 * results["2 local processes"][1] - compute) / n_tasks, 0.0)
    o_s = 0.0 if o_sched != o_sched else o_sched
    for w in (1, 100):
        if w == 1:
            wall_big = n_big * t_task
        else:
            wall_big = n_big * (t_task + o_worker) / w + n_big * o_s
        rows.append({"quantity": f"projected 10^6-trial grid on {w} worker(s) (h)", "value": wall_big / 3600})
    print()
    width = max(len(r["quantity"]) for r in rows)
    for r in rows:
        print(f"{r['quantity']:<{width}}  {r['value']:.4g}")
    print(f"\ntables identical across executors: {same}")
    print(f"load average after: {os.getloadavg()[0]:.2f}")
    if args.csv:
        import pandas as pd

        Path(args.csv).parent.mkdir(parents=True, exist_ok=True)
        pd.DataFrame(rows).to_csv(args.csv, index=False, float_format="%.6g")
    print(json.dumps({"identical": same, "tasks": n_tasks, "block_trials": args.block}))
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
