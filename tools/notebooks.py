"""Notebook tooling for the Makefile: jupytext sync, papermill execution, peak-memory measurement.

Usage (from the repository root)::

    python tools/notebooks.py sync    [notebooks/NN_x.py ...]   # .ipynb inputs from the .py (jupytext)
    python tools/notebooks.py execute [--jobs N] [--resources CSV] [notebooks/NN_x.py ...]
        # papermill, in place (default 2 jobs); --resources: start the longest notebooks of the
        # previous run first, then write each notebook's wall time and peak RSS (and the total) there
    python tools/notebooks.py measure [--out build/measure] [notebooks/NN_x.py ...]
        # each notebook in its own process tree; wall time and peak RSS → <out>/resources.csv

All notebooks (``notebooks/NN_*.py``) when none are given. ``execute`` writes each
notebook beside its source, figures/data under ``$MTCAL_OUTPUT_DIR`` (the
repository root for ``make reproduce``), ``--jobs`` notebooks at a time (default 2),
each in its own process with its own working directory and environment
(:mod:`mtcal.runs.executor`), and starts no new one after the first failure; each
failure is one line naming the partially executed ``.ipynb`` (kept). ``measure``
never touches the committed files (notebooks, data and figures go under ``--out``).
"""

from __future__ import annotations

import argparse
import csv
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from mtcal import runs  # noqa: E402


def _sources(paths: list[str]) -> list[Path]:
    return [Path(p) for p in paths] if paths else runs.notebook_sources(ROOT / "notebooks")


def cmd_sync(args) -> int:
    for src in _sources(args.notebooks):
        changed = runs.sync_notebook(src)
        print(f"{src.with_suffix('.ipynb')}: {'updated' if changed else 'in sync'}")
    return 0


def _previous_seconds(path: Path | None) -> dict[str, float]:
    """Wall time per notebook of the previous run recorded in ``path`` (empty when there is none)."""
    if path is None or not path.is_file():
        return {}
    try:
        with open(path, newline="") as fh:
            return {r["notebook"]: float(r["wall_s"]) for r in csv.DictReader(ln for ln in fh if not ln.startswith("#"))
                    if r.get("status") == "ok" and r.get("notebook") != "total"}
    except (OSError, KeyError, ValueError):
        return {}


def _write_resources(path: Path, results, total_s: float, jobs: int) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    rows = [{"notebook": Path(r.job.source).stem, "status": r.status, "wall_s": f"{r.seconds:.1f}",
             "peak_rss_kernel_mb": "" if r.peak_rss_mb != r.peak_rss_mb else f"{r.peak_rss_mb:.0f}"}
            for r in sorted(results, key=lambda r: Path(r.job.source).stem)]
    peaks = [float(r["peak_rss_kernel_mb"]) for r in rows if r["peak_rss_kernel_mb"]]
    rows.append({"notebook": "total", "status": "ok" if all(r.ok for r in results) else "failed",
                 "wall_s": f"{total_s:.1f}", "peak_rss_kernel_mb": f"{max(peaks):.0f}" if peaks else ""})
    tmp = path.with_name(path.name + ".tmp")
    with open(tmp, "w", newline="") as fh:
        fh.write(f"# tools/notebooks.py execute --jobs {jobs} MTCAL_SIZE={os.environ.get('MTCAL_SIZE', '')}: wall time "
                 "per notebook and in total (s), peak RSS of the notebook's kernel (MiB)\n")
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]), lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
    os.replace(tmp, path)


def cmd_execute(args) -> int:
    """Execute notebooks, ``--jobs`` at a time, each in its own process (own cwd and environment:
    :func:`mtcal.runs.executor.execute_jobs`). The notebooks read nothing written by another and
    every result is seeded, so the files do not depend on the order or the number of jobs. No new
    notebook starts after the first failure; each failure is one line naming the partial notebook.
    With ``--resources``, the previous run's longest notebooks start first and this run's times and
    peak memory are written there."""
    from mtcal.runs.executor import NotebookJob, execute_jobs, longest_first

    sources = _sources(args.notebooks)
    if args.output and len(sources) != 1:
        print("notebooks: --output needs exactly one notebook", file=sys.stderr)
        return 2
    if args.jobs < 1:
        print(f"notebooks: --jobs must be >= 1, got {args.jobs}", file=sys.stderr)
        return 2
    resources = Path(args.resources) if args.resources else None
    jobs = [NotebookJob(src, Path(args.output) if args.output else src.with_suffix(".ipynb")) for src in sources]
    jobs = longest_first(jobs, _previous_seconds(resources))

    def report(result):
        if result.ok:
            print(f"{result.job.output}: executed in {result.seconds:.0f} s, peak RSS {result.peak_rss_mb:.0f} MiB",
                  flush=True)

    start = time.perf_counter()
    results = execute_jobs(jobs, n_jobs=args.jobs, on_result=report)
    if resources is not None:
        _write_resources(resources, results, time.perf_counter() - start, args.jobs)
    errors = [r.error for r in results if r.status == "failed"]
    for err in errors:
        print(f"notebooks: {err}", file=sys.stderr)
    skipped = [Path(r.job.source).stem for r in results if r.status == "skipped"]
    if skipped:
        print(f"notebooks: not started after the failure: {', '.join(skipped)}", file=sys.stderr)
    return 1 if errors else 0


def _tree_rss(proc) -> int:
    import psutil

    total = 0
    for p in [proc] + proc.children(recursive=True):
        try:
            total += p.memory_info().rss
        except psutil.Error:
            pass
    return total


def cmd_measure(args) -> int:
    import psutil

    out_dir = Path(args.out)
    out_dir.mkdir(parents=True, exist_ok=True)
    rows = []
    env = dict(os.environ, MTCAL_OUTPUT_DIR=str(out_dir.resolve()), **runs.numerics_env())
    env.setdefault("MTCAL_SIZE", "full")
    for src in _sources(args.notebooks):
        cmd = [sys.executable, __file__, "execute", str(src), "--output", str(out_dir / f"{src.stem}.ipynb")]
        start = time.perf_counter()
        child = subprocess.Popen(cmd, env=env)
        proc = psutil.Process(child.pid)
        peak_tree, status, usage = 0, None, None
        while status is None:
            pid, wait_status, rusage = os.wait4(child.pid, os.WNOHANG)
            if pid:
                status, usage = os.waitstatus_to_exitcode(wait_status), rusage
                break
            try:
                peak_tree = max(peak_tree, _tree_rss(proc))
            except psutil.Error:
                pass
            time.sleep(0.1)
        child.returncode = status
        wall = time.perf_counter() - start
        # wait4's ru_maxrss covers the child and its reaped descendants: the exact peak of the
        # largest single process of this notebook's tree (the kernel)
        rows.append({"notebook": src.stem, "size": env["MTCAL_SIZE"], "status": "ok" if status == 0 else "failed",
                     "wall_s": f"{wall:.0f}", "peak_rss_kernel_mb": f"{usage.ru_maxrss / 1024:.0f}",
                     "peak_rss_tree_mb": f"{peak_tree / 2**20:.0f}"})
        print(rows[-1], flush=True)
    with open(out_dir / "resources.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]), lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
    return 0 if all(r["status"] == "ok" for r in rows) else 1


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("sync")
    p.add_argument("notebooks", nargs="*")
    p.set_defaults(func=cmd_sync)
    p = sub.add_parser("execute")
    p.add_argument("notebooks", nargs="*")
    p.add_argument("--output", help="executed notebook path (one notebook only; default: in place)")
    p.add_argument("--jobs", type=int, default=2, help="notebooks executed at the same time (default 2)")
    p.add_argument("--resources", help="CSV of wall time and peak RSS per notebook: read (longest first) and rewritten")
    p.set_defaults(func=cmd_execute)
    p = sub.add_parser("measure")
    p.add_argument("notebooks", nargs="*")
    p.add_argument("--out", default="build/measure")
    p.set_defaults(func=cmd_measure)
    args = parser.parse_args(argv)
    if getattr(args, "output", None) and len(args.notebooks) != 1:
        parser.error("--output needs exactly one notebook")
    return args.func(args)


if __name__ == "__main__":
    sys.exit(main())
