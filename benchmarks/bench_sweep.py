"""Sweep scaling: throughput on 1 worker, 2 local processes and a 2-worker Dask LocalCluster.

Workload: the ``attitude`` evaluator (wang2023cja turntable AoA sweep at 100 Hz,
1 s holds, QNCF + Mahony, tactical/industrial/consumer/navigation grades), a
grid of 4 cells × ``--trials`` trials in tasks of ``--block`` trials.

Measured:

* per-task compute cost ``t_task`` (``run_block`` called in this process, median of
  a few calls) and peak memory of one task (``tracemalloc``);
* wall time of the whole sweep in-process, on 2 local processes
  (``ProcessPoolExecutor``) and on a 2-worker ``dask.distributed.LocalCluster``
  (processes, 1 thread each) — pools warmed up first (start-up timed separately);
* the workers' CPU time (``/proc`` for the pool, ``getrusage`` on the Dask workers),
  hence the per-task overhead in CPU, ``(CPU − n_tasks · t_task) / n_tasks``, which
  does not depend on how busy the machine is, and in wall time,
  ``(W · wall − n_tasks · t_task) / n_tasks``;
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
import resource
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


def _warm(evaluator: str, params: dict) -> int:
    """Worker warm-up: imports and the numba cache of the filters (run once per worker)."""
    run_block(evaluator, params, 0, 0, 0, 1)
    return os.getpid()


def _cpu_s() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def main(argv=None) -> int:
    from mtcal.sweep.evaluators import get_evaluator
    from mtcal.sweep.executors import DaskExecutor, LocalExecutor, SerialExecutor

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small sizes (≈ 15 s)")
    ap.add_argument("--trials", type=int, default=None, help="trials per cell (default 128, quick 16)")
    ap.add_argument("--block", type=int, default=8, help="trials per task")
    ap.add_argument("--csv", default=None, help="write the measurements here (CSV)")
    args = ap.parse_args(argv)
    trials = args.trials or (16 if args.quick else 128)
    spec = workload(trials, args.block)
    n_tasks = spec.n_cells * -(-trials // args.block)
    n_trials = spec.n_cells * trials
    params = get_evaluator(spec.evaluator).resolve(spec.cells()[0])
    print(f"load average before: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    print(f"workload: attitude evaluator, {spec.n_cells} cells x {trials} trials, {args.block} trials/task "
          f"-> {n_tasks} tasks")
    t_task, peak = task_cost(spec, 2 if args.quick else 4)
    c0 = _cpu_s()
    run_block(spec.evaluator, params, spec.seed, 0, 0, spec.block_trials)
    cpu_task = _cpu_s() - c0
    rows = [{"quantity": "task compute cost, wall (s/task)", "value": t_task},
            {"quantity": "task compute cost, CPU (s/task)", "value": cpu_task},
            {"quantity": "trial compute cost, wall (s/trial)", "value": t_task / args.block},
            {"quantity": "task peak memory (MB, tracemalloc)", "value": peak / 1e6}]
    results, tables = {}, {}

    def run_on(label, ex, workers, cpu_fn=None):
        before = cpu_fn() if cpu_fn else None
        wall = timed(lambda: tables.setdefault(label, run_sweep(spec, executor=ex, progress=False).table))
        cpu = (cpu_fn() - before) if cpu_fn else float("nan")
        results[label] = (workers, wall, cpu)

    run_on("1 worker (in-process)", SerialExecutor(), 1, _cpu_s)
    t0 = time.perf_counter()
    local = LocalExecutor(2)
    list(local.run([(k, _warm, (spec.evaluator, params)) for k in range(4)]))
    rows.append({"quantity": "local pool start-up + warm-up (s)", "value": time.perf_counter() - t0})

    def local_cpu():
        pids = list(local._pool._processes)
        total = 0.0
        for pid in pids:
            try:
                with open(f"/proc/{pid}/stat") as fh:
                    f = fh.read().rsplit(")", 1)[1].split()
                total += (int(f[11]) + int(f[12])) / os.sysconf("SC_CLK_TCK")
            except OSError:
                pass
        return total

    run_on("2 local processes", local, 2, local_cpu)
    local.close()
    o_sched = float("nan")
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        print("dask.distributed not installed: Dask rows skipped")
    else:
        t0 = time.perf_counter()
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
        client = Client(cluster)
        client.run(_warm, spec.evaluator, params)
        rows.append({"quantity": "dask LocalCluster start-up + warm-up (s)", "value": time.perf_counter() - t0})

        def dask_cpu():
            return sum(client.run(_cpu_s).values())

        run_on("2-worker dask LocalCluster", DaskExecutor(client), 2, dask_cpu)
        n_noop = 2000
        t0 = time.perf_counter()
        futs = client.map(_noop, range(n_noop), pure=False)
        client.gather(futs)
        o_sched = (time.perf_counter() - t0) / n_noop
        del futs
        client.close()
        cluster.close()
        rows.append({"quantity": "dask scheduling cost, 2000 no-op tasks (s/task)", "value": o_sched})
    same = len({t.to_csv(index=False) for t in tables.values()}) == 1
    serial_wall = results["1 worker (in-process)"][1]
    for label, (w, wall, cpu) in results.items():
        rows += [{"quantity": f"{label}: wall (s)", "value": wall},
                 {"quantity": f"{label}: throughput (trials/s)", "value": n_trials / wall},
                 {"quantity": f"{label}: speed-up vs 1 worker", "value": serial_wall / wall},
                 {"quantity": f"{label}: per-cell wall (s/cell)", "value": wall / spec.n_cells},
                 {"quantity": f"{label}: worker CPU (s)", "value": cpu},
                 {"quantity": f"{label}: CPU overhead per task (s/task)", "value": (cpu - n_tasks * cpu_task) / n_tasks},
                 {"quantity": f"{label}: wall overhead per task (s/task)",
                  "value": (w * wall - n_tasks * t_task) / n_tasks}]
    # projection of a 10^6-trial grid: compute + measured Dask per-task CPU overhead, spread over W workers,
    # plus the scheduler's serial per-task cost
    n_big = 1_000_000 // args.block
    dask_label = "2-worker dask LocalCluster"
    o_worker = 0.0
    if dask_label in results:
        w, wall, cpu = results[dask_label]
        o_worker = max((cpu - n_tasks * cpu_task) / n_tasks, 0.0)
    o_s = 0.0 if o_sched != o_sched else o_sched
    rows.append({"quantity": "projection inputs: compute (s/task), worker overhead (s/task), scheduler (s/task)",
                 "value": float("nan")})
    print(f"projection inputs: t_task = {cpu_task:.4f} s, o_worker = {o_worker:.4f} s, o_sched = {o_s:.5f} s, "
          f"{n_big} tasks of {args.block} trials")
    for w in (1, 100):
        wall_big = n_big * cpu_task if w == 1 else n_big * (cpu_task + o_worker) / w + n_big * o_s
        rows.append({"quantity": f"projected 10^6-trial grid on {w} worker(s) (h)", "value": wall_big / 3600})
    rows = [r for r in rows if r["value"] == r["value"]]
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
