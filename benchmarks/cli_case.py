"""CLI end to end on a long generated log: what a user runs on a 1-hour 1 kHz recording.

``make_logs`` first compiles (or loads) every kernel with the library's own
warm-up (``warm_up_all``, as ``make venv`` does after installing), then
simulates one trial of the benchmark scenario (``mc_stream.bench_scenario``:
pitch steps about the body x axis, rests first, wang2023cja tactical MEMS IMU)
for ``hours`` hours at 1 kHz and writes it in the CLI's log schema
(``time_s, gyro_{x,y,z}_rad_s, accel_{x,y,z}_m_s2``) as CSV (pyarrow's writer)
and Parquet. ``run_case`` runs one command — ``mtcal.cli.main.main([...])`` — in
a fresh Python process and reports its wall time (measured by the parent:
interpreter start, imports, read, filter, write), its CPU time (user + sys of
the child, every thread; steadier than wall on a shared machine) and its peak RSS (``VmHWM`` of
the child, which is its own address space after ``exec``). Whatever CLI the
checkout has is run as it is; a command that fails is reported with its last
error line, not hidden.

Run alone::

    .venv/bin/python benchmarks/cli_case.py --hours 1
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
if str(HERE) not in sys.path:
    sys.path.insert(0, str(HERE))

import mc_stream  # noqa: E402

__all__ = ["COLUMNS", "make_logs", "cases", "run_case", "main"]

COLUMNS = ["time_s", "gyro_x_rad_s", "gyro_y_rad_s", "gyro_z_rad_s", "accel_x_m_s2", "accel_y_m_s2", "accel_z_m_s2"]
_MARK = "MTCAL_BENCH_CHILD "
_CHILD = r"""
import json, sys
from mtcal.cli.main import main
rc = main(json.loads(sys.argv[1]))
hwm = None
try:
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith("VmHWM:"):
                hwm = int(line.split()[1]) / 1024.0
except OSError:
    pass
print("MTCAL_BENCH_CHILD " + json.dumps({"rc": rc, "vm_hwm_mb": hwm}))
sys.exit(rc)
"""


def make_logs(hours: float, workdir: Path, seed: int = 2023, log=print) -> dict:
    """Simulate ``hours`` h at 1 kHz and write ``log.csv`` and ``log.parquet`` into ``workdir``."""
    import pyarrow as pa
    import pyarrow.csv as pacsv
    import pyarrow.parquet as pq

    from mtcal.core.simulate import simulate_imu

    from mtcal.filters.kernels import warm_up_all

    warm_up_all()  # as `make venv` does: the timed commands load every kernel from numba's cache, never compile
    t0 = time.perf_counter()
    data = mc_stream.bench_scenario(hours * 3600.0, 1000.0)
    rec = simulate_imu(data.trajectory, mc_stream.error_model(), np.random.default_rng(seed))
    cols = [rec.time_s, *rec.gyro_rad_s.T, *rec.accel_m_s2.T]
    table = pa.table({name: np.ascontiguousarray(c) for name, c in zip(COLUMNS, cols)})
    workdir.mkdir(parents=True, exist_ok=True)
    csv, parquet = workdir / "log.csv", workdir / "log.parquet"
    pacsv.write_csv(table, csv)
    pq.write_table(table, parquet)
    log(f"  generated {rec.time_s.size} samples in {time.perf_counter() - t0:.1f} s "
        f"(CSV {csv.stat().st_size / 2**20:.0f} MB, Parquet {parquet.stat().st_size / 2**20:.0f} MB)")
    return {"csv": csv, "parquet": parquet, "hours": hours, "samples": int(rec.time_s.size),
            "axis": ",".join(f"{x:g}" for x in data.axis_b)}


def _subcommands() -> set[str]:
    from mtcal.cli.main import build_parser

    parser = build_parser()
    for action in parser._actions:  # the subparsers action lists the commands this checkout has
        if hasattr(action, "choices") and isinstance(action.choices, dict):
            return set(action.choices)
    return set()


def cases(logs: dict) -> list[dict]:
    """Commands to run: ``angle`` (and ``attitude`` if the CLI has it) on the CSV and the Parquet log."""
    have = _subcommands()
    out = []
    for fmt in ("csv", "parquet"):
        src = str(logs[fmt])
        out.append({"name": f"mtcal angle ({fmt} in, {fmt} out)", "fmt": fmt,
                    "argv": ["angle", src, "--axis", logs["axis"], "--out", f"angle_out.{fmt}"]})
        if "attitude" in have:
            out.append({"name": f"mtcal attitude ({fmt} in, {fmt} out)", "fmt": fmt,
                        "argv": ["attitude", src, "--out", f"attitude_out.{fmt}"]})
    return out


def run_case(case: dict, logs: dict, workdir: Path) -> dict:
    """Run one CLI command in a fresh process; wall time from the parent, peak RSS from the child."""
    env = dict(os.environ, MTCAL_PROGRESS="0", MPLBACKEND="Agg")
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT)] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p])
    import resource

    ru0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    res = subprocess.run([sys.executable, "-c", _CHILD, json.dumps(case["argv"])], cwd=workdir, env=env,
                         capture_output=True, text=True)
    wall = time.perf_counter() - t0
    ru1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (ru1.ru_utime - ru0.ru_utime) + (ru1.ru_stime - ru0.ru_stime)  # user + sys of the child (all threads)
    info = next((json.loads(line[len(_MARK):]) for line in res.stdout.splitlines() if line.startswith(_MARK)), None)
    ok = res.returncode == 0 and info is not None
    err = ""
    if not ok:
        lines = [ln for ln in (res.stderr or res.stdout).strip().splitlines() if ln.strip()]
        err = lines[-1][:160] if lines else f"exit status {res.returncode}"
    return {"name": case["name"], "argv": case["argv"], "ok": ok, "wall_s": wall, "cpu_s": cpu, "error": err,
            "rss_mb": (info or {}).get("vm_hwm_mb") or float("nan"), "hours": logs["hours"],
            "samples": logs["samples"]}


def main(argv: list[str] | None = None) -> list[dict]:
    import tempfile

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--hours", type=float, default=1.0)
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="mtcal-cli-") as work:
        logs = make_logs(args.hours, Path(work))
        results = [run_case(c, logs, Path(work)) for c in cases(logs)]
    for r in results:
        print(f"{r['name']}: " + (f"{r['wall_s']:.2f} s (CPU user+sys {r['cpu_s']:.2f} s), peak RSS "
                                  f"{r['rss_mb']:.0f} MB" if r["ok"]
                                  else f"failed: {r['error']}"))
    return results


if __name__ == "__main__":
    main()
