"""Where `make reproduce` spends its time: CPU and wall per notebook, split into simulation / filter / metrics / other.

Issue #37 item 3: the row under the `make reproduce` target in `make bench`, so that a regression
shows where it happened. Each notebook runs in its own child process, the way `mtcal run` and
`mtcal reproduce` run a notebook as a script (:func:`mtcal.runs._runner._run_script`: the cells in
order, no kernel), in the numerics environment `make reproduce` pins, with no Monte Carlo cache
(every number is computed) and its outputs written to a temporary directory (committed outputs are
never touched). ``WORKERS=1`` is passed as a parameter, so a notebook that would fan out to worker
processes (notebook 50 at full size) runs in-process and is seen whole: its CPU is the same, its wall
is the serial one.

Attribution is by sampling (a thread of the child reads every Python thread's stack every
``--interval-ms``; no per-call profiler overhead, which would inflate pure-Python loops such as
``ahrs``' Madgwick several-fold): each Python thread's CPU since the previous sample (its own
clock, ``pthread_getcpuclockid``) goes to the class of its stack; the rest of the process CPU
(numba's parallel workers, which have no Python frame) and the wall time go to the main thread's;
the class of a stack is the category of the innermost frame that a rule in
:data:`RULES` names (first the strong rules, innermost first; then the weak ones, e.g. a rotation
helper called from study code counts as metrics; else "other": study code, calibration methods,
reporting, plotting, imports). Compiled kernels (numba, C++) have no Python frame, so their time goes
to the Python function that called them. The numba cache must be warm (``make venv`` warms it).

Run alone::

    .venv/bin/python benchmarks/reproduce_breakdown.py                  # every notebook at CI size
    .venv/bin/python benchmarks/reproduce_breakdown.py --size full 50   # one notebook at full size
    .venv/bin/python benchmarks/reproduce_breakdown.py --parts 50       # also the parts of each category

It writes ``build/bench/reproduce_breakdown.csv`` (one row per notebook, category and part).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import pandas as pd

ROOT = Path(__file__).resolve().parents[1]
CATEGORIES = ("simulation", "filter", "metrics", "other")
DEFAULT_CSV = ROOT / "build" / "bench" / "reproduce_breakdown.csv"

#: (category, part, path fragment, function names or None = any), strong rules: the innermost frame
#: that matches one decides. Path fragments use "/" and are matched against the frame's file name.
RULES = (
    ("metrics", "filters.anchors error metrics", "mtcal/filters/anchors.py",
     ("tilt_error_rad", "_up_in_sensor", "twist_angle_rad")),
    ("filter", "imufusion per-sample loop", "mtcal/filters/anchors.py", ("_fusion",)),
    ("filter", "ahrs Madgwick (pure Python)", "mtcal/filters/anchors.py", ("_madgwick",)),
    ("filter", "vqf (C++ batch)", "mtcal/filters/anchors.py", ("_vqf",)),
    ("filter", "ahrs Madgwick (pure Python)", "/ahrs/", None),
    ("filter", "imufusion per-sample loop", "/imufusion", None),
    ("filter", "vqf (C++ batch)", "/vqf/", None),
    ("filter", "filterpy", "/filterpy/", None),
    ("filter", "mtcal filters (compiled)", "mtcal/filters/", None),
    ("simulation", "wang2023cja runs: truth, draws, vibration", "mtcal/studies/wang2023cja/runs.py",
     ("run_turntable_jobs_kinds", "_wt_setup", "_wind_on_draws", "_wind_on_truth", "_vibration_accel",
      "_wt_schedule")),
    ("simulation", "wang2023cja scenario: mechanism, compliance", "mtcal/studies/wang2023cja/scenario.py", None),
    ("metrics", "wang2023cja runs: Eq 8 before/after", "mtcal/studies/wang2023cja/runs.py",
     ("_euler", "position_errors_deg")),
    ("metrics", "installation system: sweeps' Eq 8 before/after", "mtcal/systems/installation.py",
     ("_score_sweeps",)),
    ("simulation", "core.simulate", "mtcal/core/simulate.py", None),
    ("simulation", "core.rng / philox", "mtcal/core/rng.py", None),
    ("simulation", "core.rng / philox", "mtcal/core/philox.py", None),
    ("simulation", "core.sensors / profiles", "mtcal/core/sensors.py", None),
    ("simulation", "core.sensors / profiles", "mtcal/core/profiles.py", None),
    ("metrics", "core.metrics", "mtcal/core/metrics.py", None),
    ("metrics", "core.montecarlo", "mtcal/core/montecarlo.py", None),
)
#: Weak rules: used only when no strong rule matched anywhere on the stack (a rotation helper is a
#: filter's when a filter calls it, the Eq 8 metrics' when study code calls it).
WEAK_RULES = (
    ("metrics", "core.rotations (Eq 8)", "mtcal/core/rotations.py", None),
    ("metrics", "core.rotations (Eq 8)", "mtcal/core/_rotation_kernels.py", None),
)


def classify(frames) -> tuple[str, str]:
    """(category, part) of a stack given innermost first as ``(file name, function name)`` pairs.

    >>> classify([("/x/ahrs/filters/madgwick.py", "updateIMU"), ("/r/mtcal/filters/anchors.py", "_madgwick")])
    ('filter', 'ahrs Madgwick (pure Python)')
    >>> classify([("/r/mtcal/core/rotations.py", "euler_zxy"), ("/r/mtcal/filters/qncf.py", "qncf")])
    ('filter', 'mtcal filters (compiled)')
    >>> classify([("/r/mtcal/core/rotations.py", "euler_zxy"), ("10_x.py:cell3", "<module>")])
    ('metrics', 'core.rotations (Eq 8)')
    >>> classify([("/r/mtcal/methods/six_position.py", "fit"), ("10_x.py:cell3", "<module>")])
    ('other', 'mtcal.methods.six_position')
    >>> classify([("/v/site-packages/matplotlib/figure.py", "savefig"), ("/r/mtcal/reporting/output.py", "save")])
    ('other', 'mtcal.reporting.output')
    >>> classify([("<frozen importlib._bootstrap>", "_load"), ("10_x.py:cell1", "<module>")])
    ('other', 'notebook cells, imports, interpreter')
    """
    frames = [(f.replace(os.sep, "/"), fn) for f, fn in frames]
    for rules in (RULES, WEAK_RULES):
        for filename, func in frames:
            for category, part, fragment, funcs in rules:
                if fragment in filename and (funcs is None or func in funcs):
                    return category, part
    return "other", _other_part(frames)


def _other_part(frames) -> str:
    """The innermost mtcal module on the stack (``mtcal.x.y``), else the innermost third-party package."""
    for filename, _ in frames:
        if "/mtcal/" in filename and filename.endswith(".py") and not filename.endswith("/runs/_runner.py"):
            return "mtcal." + filename.rsplit("/mtcal/", 1)[1][:-3].replace("/", ".")
    for filename, _ in frames:
        if "-packages/" in filename:
            return filename.rsplit("-packages/", 1)[1].split("/", 1)[0].removesuffix(".py")
    return "notebook cells, imports, interpreter"


class StackSampler:
    """Samples the main thread's stack from a daemon thread; CPU and wall since the last sample go to its class."""

    def __init__(self, interval_s: float = 0.005):
        self.interval_s = interval_s
        self.cpu_s: dict[tuple[str, str], float] = {}
        self.wall_s: dict[tuple[str, str], float] = {}
        self.samples: dict[tuple[str, str], int] = {}
        self._stop = threading.Event()
        self._main = threading.main_thread().ident
        self._own = None
        self._thread = threading.Thread(target=self._loop, daemon=True)

    def _stacks(self) -> dict:
        """Every Python thread's stack but the sampler's, innermost frame first, by thread id."""
        out = {}
        for ident, frame in sys._current_frames().items():
            if ident == self._own:
                continue
            stack = []
            while frame is not None:
                stack.append((frame.f_code.co_filename, frame.f_code.co_name))
                frame = frame.f_back
            out[ident] = stack
        return out

    @staticmethod
    def _thread_cpu(ident: int) -> float | None:
        try:
            return time.clock_gettime(time.pthread_getcpuclockid(ident))
        except (AttributeError, OSError, ValueError):   # no per-thread clocks here, or the thread ended
            return None

    def _add(self, key, cpu_s: float, wall_s: float = 0.0, sample: int = 0) -> None:
        self.cpu_s[key] = self.cpu_s.get(key, 0.0) + cpu_s
        self.wall_s[key] = self.wall_s.get(key, 0.0) + wall_s
        self.samples[key] = self.samples.get(key, 0) + sample

    def _loop(self) -> None:
        """Each Python thread's CPU since the last sample goes to its own stack's class; the rest of the
        process CPU (numba/OpenMP workers, the sampler, ended threads) and the wall to the main thread's."""
        self._own = threading.get_ident()
        cpu, wall = time.process_time(), time.perf_counter()
        threads: dict[int, tuple] = {}   # ident -> (Thread object, its CPU clock at the last sample)
        while not self._stop.wait(self.interval_s):
            stacks = self._stacks()
            c, w = time.process_time(), time.perf_counter()
            attributed = 0.0
            for ident, stack in stacks.items():
                now = self._thread_cpu(ident)
                if now is None or ident == self._main:
                    continue
                obj = threading._active.get(ident)
                seen, before = threads.get(ident, (None, 0.0))
                # a thread seen for the first time (idents are reused by new pool threads): all its CPU so far
                delta = max(now - before, 0.0) if (seen is obj and obj is not None) else now
                delta = min(delta, max(c - cpu - attributed, 0.0))
                self._add(classify(stack), delta)
                attributed += delta
                threads[ident] = (obj, now)
            main = classify(stacks.get(self._main, []))
            self._add(main, max(c - cpu - attributed, 0.0), w - wall, 1)
            cpu, wall = c, w

    def __enter__(self):
        self._thread.start()
        return self

    def __exit__(self, *exc):
        self._stop.set()
        self._thread.join()


def _child(source: str, size: str, interval_s: float) -> dict:
    """Run one notebook's cells under the sampler (this process); totals and per-(category, part) times."""
    import resource

    from mtcal.runs._runner import _run_script

    c0, w0 = time.process_time(), time.perf_counter()
    with StackSampler(interval_s) as sampler:
        _run_script({"source": source, "parameters": {"WORKERS": 1}, "cwd": str(Path(source).parent)})
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    rows = [{"category": k[0], "part": k[1], "cpu_s": sampler.cpu_s[k], "wall_s": sampler.wall_s[k],
             "samples": sampler.samples[k]} for k in sampler.cpu_s]
    return {"notebook": Path(source).stem, "size": size, "cpu_s": cpu,
            "children_cpu_s": children.ru_utime + children.ru_stime, "wall_s": wall, "parts": rows}


def run_notebook(source: Path, size: str = "ci", interval_s: float = 0.005) -> dict:
    """:func:`_child` in its own process: pinned numerics, no cache, outputs into a temporary directory."""
    sys.path.insert(0, str(ROOT))
    from mtcal.runs.environment import numerics_env

    with tempfile.TemporaryDirectory(prefix="mtcal-breakdown-") as tmp:
        env = dict(os.environ, **numerics_env(), MTCAL_SIZE=size, MTCAL_OUTPUT_DIR=tmp, MTCAL_PROGRESS="0",
                   MPLBACKEND="Agg", PYTHONHASHSEED="0")
        env.pop("MTCAL_CACHE_DIR", None)
        res = subprocess.run([sys.executable, __file__, "--child", str(source), "--size", size,
                              "--interval-ms", str(interval_s * 1e3)], cwd=tmp, env=env,
                             capture_output=True, text=True)
    if res.returncode != 0:
        tail = (res.stderr.strip().splitlines() or ["no output"])[-1]
        raise RuntimeError(f"{source.stem} at size {size} failed: {tail}")
    return json.loads(res.stdout.strip().splitlines()[-1])


def to_frame(results: list[dict]) -> pd.DataFrame:
    """One row per (notebook, category, part): CPU and wall seconds, and the notebook's totals.

    The parts' times are rescaled so that they add up to the notebook's measured totals (the sampler
    misses the time after its last sample); ``cpu_share``/``wall_share`` are fractions of the notebook.
    """
    rows = []
    for r in results:
        parts = r["parts"]
        cpu_sum = sum(p["cpu_s"] for p in parts) or 1.0
        wall_sum = sum(p["wall_s"] for p in parts) or 1.0
        for p in parts:
            rows.append({"notebook": r["notebook"], "size": r["size"], "category": p["category"], "part": p["part"],
                         "cpu_s": p["cpu_s"] / cpu_sum * r["cpu_s"], "wall_s": p["wall_s"] / wall_sum * r["wall_s"],
                         "cpu_share": p["cpu_s"] / cpu_sum, "wall_share": p["wall_s"] / wall_sum,
                         "samples": p["samples"], "notebook_cpu_s": r["cpu_s"], "notebook_wall_s": r["wall_s"],
                         "children_cpu_s": r["children_cpu_s"]})
    cols = ["notebook", "size", "category", "part", "cpu_s", "wall_s", "cpu_share", "wall_share", "samples",
            "notebook_cpu_s", "notebook_wall_s", "children_cpu_s"]
    return pd.DataFrame(rows, columns=cols).sort_values(["notebook", "category", "part"], ignore_index=True)


def table(df: pd.DataFrame, parts: bool = False) -> str:
    """Per notebook: total CPU and wall, then CPU / wall seconds of each category (and its parts)."""
    head = f"{'notebook':<36}{'size':>5}{'CPU s':>8}{'wall s':>8}" + "".join(
        f"{c + ' CPU/wall':>24}" for c in CATEGORIES)
    lines = [head]
    for nb, g in df.groupby("notebook", sort=True):
        by = g.groupby("category")[["cpu_s", "wall_s", "cpu_share"]].sum()
        cells = "".join(
            f"{by.cpu_s.get(c, 0.0):>9.1f}/{by.wall_s.get(c, 0.0):<6.1f}({100 * by.cpu_share.get(c, 0.0):3.0f}%)"
            for c in CATEGORIES)
        lines.append(f"{nb:<36}{g['size'].iloc[0]:>5}{g.notebook_cpu_s.iloc[0]:>8.1f}"
                     f"{g.notebook_wall_s.iloc[0]:>8.1f}{cells}")
        if parts:
            for _, p in g.sort_values("cpu_s", ascending=False).iterrows():
                lines.append(f"    {p.category:<11}{p.part:<36}{p.cpu_s:>8.2f} CPU-s {p.wall_s:>8.2f} wall-s "
                             f"{100 * p.cpu_share:5.1f} % of CPU")
    tot = df.groupby("category")[["cpu_s", "wall_s"]].sum()
    cpu = df.drop_duplicates("notebook").notebook_cpu_s.sum()
    wall = df.drop_duplicates("notebook").notebook_wall_s.sum()
    lines.append(f"{'all (serial sum)':<36}{'':>5}{cpu:>8.1f}{wall:>8.1f}" + "".join(
        f"{tot.cpu_s.get(c, 0.0):>9.1f}/{tot.wall_s.get(c, 0.0):<6.1f}"
        f"({100 * tot.cpu_s.get(c, 0.0) / (cpu or 1):3.0f}%)"
        for c in CATEGORIES))
    return "\n".join(lines)


def select(numbers: list[str]) -> list[Path]:
    """The notebooks' py:percent sources, all or those whose number (``NN``) is given."""
    sources = sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.py"))
    if not numbers:
        return sources
    chosen = [s for s in sources if s.name[:2] in numbers]
    missing = sorted(set(numbers) - {s.name[:2] for s in chosen})
    if missing:
        raise ValueError(f"no notebook numbered {', '.join(missing)} in notebooks/")
    return chosen


def main(argv: list[str] | None = None) -> pd.DataFrame | None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("notebooks", nargs="*", help="notebook numbers (NN), default all")
    ap.add_argument("--size", choices=("ci", "full"), default="ci", help="MTCAL_SIZE of the runs (default ci)")
    ap.add_argument("--csv", type=Path, default=DEFAULT_CSV,
                    help=f"output CSV (default {DEFAULT_CSV.relative_to(ROOT)})")
    ap.add_argument("--interval-ms", type=float, default=5.0, help="sampling interval (default 5 ms)")
    ap.add_argument("--parts", action="store_true", help="also print the parts of each category")
    ap.add_argument("--child", metavar="SOURCE", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if not args.interval_ms > 0:
        ap.error(f"--interval-ms must be > 0, got {args.interval_ms}")
    if args.child:
        print(json.dumps(_child(args.child, args.size, args.interval_ms / 1e3)))
        return None
    try:
        sources = select(args.notebooks)
    except ValueError as exc:
        ap.error(str(exc))
    results = []
    for src in sources:
        print(f"  {src.stem} ({args.size}) ...", flush=True)
        results.append(run_notebook(src, args.size, args.interval_ms / 1e3))
    df = to_frame(results)
    args.csv.parent.mkdir(parents=True, exist_ok=True)
    df.to_csv(args.csv, index=False, float_format="%.4g")
    print(table(df, parts=args.parts))
    print(f"(CPU = process_time of the notebook's process, all threads; shares by stack sampling every "
          f"{args.interval_ms:g} ms; written to {args.csv})")
    return df


if __name__ == "__main__":
    main()
