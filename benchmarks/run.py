"""``make bench``: mtcal's batched filters against the libraries users would pick instead.

One process, one synthetic scenario (``benchmarks/mc_stream.py``: 60 s @ 1 kHz
pitch step schedule, wang2023cja tactical MEMS IMU, simulated with
:class:`mtcal.core.simulate.ImuStream` from a seeded generator), every method side by
side on the same numbers:

* the 1000-trial record is the first ``batch_record_s`` seconds of all trials
  (one :class:`~mtcal.core.simulate.ImuStream` chunk; 1000 × 60 s would need
  1.4 GB per array — the full length is the streaming Monte Carlo's job);
* the single-trial record is one 60 s realisation (``simulate_imu``, same
  scenario, error model and seed);
* slow per-sample Python loops (ahrs, filterpy, numpy EKF) run on the first
  ``loop_record_s`` seconds only (their cost per sample is constant, so the
  throughput is the same; stated in the table).

Timing: ``time.perf_counter`` around the call, inputs already in memory; calls
shorter than 1 s are repeated (``--repeats``) and the fastest is kept (the
machine is shared). Memory: a second, untimed call under ``tracemalloc`` gives
the peak of Python + numpy allocations during the call (inputs excluded, outputs
included). The streaming Monte Carlo runs in a subprocess so that its peak RSS
(``getrusage``) is its own.

Writes ``data/benchmarks.csv`` and ``benchmarks/profile_summary.txt`` (cProfile
of the batched filters at 1000 trials + per-step cost versus trial count).
Numbers depend on the machine and its load; they are not checked by CI.

Usage::

    .venv/bin/python benchmarks/run.py            # full sizes (≈ 2–3 min on 2 cores)
    .venv/bin/python benchmarks/run.py --quick    # small sizes, a few seconds
"""

from __future__ import annotations

import argparse
import cProfile
import io
import json
import os
import platform
import pstats
import subprocess
import sys
import time
import tracemalloc
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np
import pandas as pd

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
if str(HERE) not in sys.path:
    sys.path.insert(0, str(HERE))

import anchors  # noqa: E402
import mc_stream  # noqa: E402
from mtcal.filters.qncf import QncfFilter, QncfParams  # noqa: E402
from mtcal.core.simulate import ImuStream, simulate_imu  # noqa: E402

try:  # the RAMS EKF may be absent in an older checkout
    from mtcal.filters.rams_ekf import RamsEkfParams, run_rams_ekf
except ImportError:  # pragma: no cover - depends on the checkout
    RamsEkfParams = run_rams_ekf = None

__all__ = ["Sizes", "FULL", "QUICK", "BenchInputs", "make_inputs", "Measurement", "measure",
           "benchmark_methods", "results_table", "evaluate_targets", "main"]

FS_HZ = 1000.0
DT_S = 1.0 / FS_HZ
SEED = 2023
#: Anchors the ratio columns refer to (method names in the table).
ANCHORS = {"ahrs_mahony": "ahrs Mahony updateIMU loop", "imufusion": "imufusion Ahrs loop",
           "filterpy_ekf": "filterpy EKF loop"}
#: Targets of issue #7.
TARGETS = {"qncf_vs_ahrs": 700.0, "qncf_vs_imufusion": 10.0, "qncf_throughput": 7e6,
           "ekf_vs_filterpy": 300.0, "mc_wall_s": 30.0, "mc_rss_mb": 1024.0}


@dataclass(frozen=True)
class Sizes:
    """Problem sizes (s of data at 1 kHz, trial counts)."""

    record_s: float = 60.0         # single-trial record (mtcal, imufusion)
    batch_trials: int = 1000       # trials of the batched runs
    batch_record_s: float = 10.0   # record length of the batched runs (1000 × 60 s would be 1.4 GB per array)
    loop_record_s: float = 20.0    # record length of slow per-sample Python loops
    profile_s: float = 2.0         # record length of the cProfile runs (1000 trials)
    mc_trials: int = 1000
    mc_duration_s: float = 60.0
    repeats: int = 3


FULL = Sizes()
QUICK = Sizes(record_s=4.0, batch_trials=1000, batch_record_s=0.5, loop_record_s=1.0, profile_s=0.2,
              mc_trials=1000, mc_duration_s=2.0, repeats=3)


# --------------------------------------------------------------------------- data
@dataclass(frozen=True)
class BenchInputs:
    """Simulated IMU data shared by every method (see module docstring)."""

    gyro_1: np.ndarray          # (N, 3) single trial, whole record
    accel_1: np.ndarray         # (N, 3)
    gyro_t: np.ndarray          # (T, M, 3) batched trials, first M samples
    accel_t: np.ndarray         # (T, M, 3)
    is_static: np.ndarray       # (N,)
    q0: np.ndarray              # (4,) true initial attitude
    axis: np.ndarray            # (3,) rotation axis
    accel0_1: np.ndarray        # (3,) ā0 of the single trial (mean of ≤ 100 samples of the first hold)
    accel0_t: np.ndarray        # (T, 3)


def make_inputs(sizes: Sizes, seed: int = SEED) -> BenchInputs:
    """Simulate the single-trial record and the first chunk of the batched stream."""
    data = mc_stream.bench_scenario(sizes.record_s, FS_HZ)
    model = mc_stream.error_model()
    one = simulate_imu(data.trajectory, model, np.random.default_rng(seed))
    stream = ImuStream(data.trajectory, model, np.random.default_rng(seed + 1), trials=sizes.batch_trials)
    m = int(round(sizes.batch_record_s * FS_HZ))
    batch = next(stream.chunks(m))
    first_move = int(np.argmin(data.is_static)) if not data.is_static.all() else data.is_static.size
    n0 = max(1, min(100, m, first_move))  # ā0 from the first hold (static), at most 100 samples
    return BenchInputs(one.gyro_rad_s, one.accel_m_s2, batch.gyro_rad_s, batch.accel_m_s2, data.is_static,
                       stream.q_ws[0].copy(), data.axis_b, one.accel_m_s2[:n0].mean(axis=0),
                       batch.accel_m_s2[:, :n0].mean(axis=1))


# --------------------------------------------------------------------------- measuring
@dataclass(frozen=True)
class Measurement:
    """One row of the benchmark table."""

    method: str
    library: str
    trials: int
    samples: int
    seconds: float
    peak_mb: float
    memory: str = "tracemalloc"
    note: str = ""

    @property
    def trial_samples(self) -> int:
        return self.trials * self.samples

    @property
    def throughput(self) -> float:
        """Trial-samples per second."""
        return self.trial_samples / self.seconds


def measure(method: str, library: str, fn: Callable[[], object], trials: int, samples: int,
            repeats: int = 3, note: str = "") -> Measurement:
    """Best wall time over up to ``repeats`` calls (no new call once 4 s have been spent),
    then one untimed call under tracemalloc for the peak allocation (MB)."""
    best, spent = np.inf, 0.0
    for _ in range(max(1, repeats)):
        t0 = time.perf_counter()
        fn()
        dt = time.perf_counter() - t0
        best, spent = min(best, dt), spent + dt
        if spent >= 4.0:
            break
    tracemalloc.start()
    tracemalloc.reset_peak()
    base = tracemalloc.get_traced_memory()[0]
    fn()
    peak = tracemalloc.get_traced_memory()[1] - base
    tracemalloc.stop()
    return Measurement(method, library, trials, samples, best, peak / 2**20, note=note)


def _qncf_call(gyro, accel, q0) -> Callable[[], object]:
    trials = gyro.shape[0]

    def call():
        return QncfFilter(q0, DT_S, QncfParams(), trials=trials).run(gyro, accel, return_euler=False)
    return call


def _ekf_call(gyro, accel, is_static, axis, accel0) -> Callable[[], object]:
    def call():
        return run_rams_ekf(gyro, accel, is_static, axis, accel0, DT_S, RamsEkfParams(),
                            keep_innovation=False)
    return call


def benchmark_methods(inp: BenchInputs, sizes: Sizes, log=print) -> list[Measurement]:
    """Time every method on ``inp``; returns the table rows (MC excluded)."""
    n = inp.gyro_1.shape[0]
    t, m = inp.gyro_t.shape[:2]
    nl = min(n, int(round(sizes.loop_record_s * FS_HZ)))
    loop_note = f"first {nl / FS_HZ:g} s of the {n / FS_HZ:g} s record (per-sample loop)"
    g1, a1, gl, al, st = inp.gyro_1, inp.accel_1, inp.gyro_1[:nl], inp.accel_1[:nl], inp.is_static
    r = sizes.repeats
    rows = []

    def add(*args, **kw):
        row = measure(*args, repeats=r, **kw)
        log(f"  {row.method:34s} {row.trials:5d} x {row.samples:6d}  {row.seconds:8.3f} s")
        rows.append(row)

    add("mtcal QNCF batched", "mtcal", _qncf_call(g1[None], a1[None], inp.q0), 1, n,
        note="QncfFilter.run, quaternions only")
    add("mtcal QNCF batched", "mtcal", _qncf_call(inp.gyro_t, inp.accel_t, inp.q0), t, m,
        note="QncfFilter.run, quaternions only")
    if run_rams_ekf is not None:
        add("mtcal RAMS EKF batched", "mtcal", _ekf_call(g1[None], a1[None], st, inp.axis, inp.accel0_1),
            1, n, note="run_rams_ekf, keep_innovation=False")
        add("mtcal RAMS EKF batched", "mtcal",
            _ekf_call(inp.gyro_t, inp.accel_t, st[:m], inp.axis, inp.accel0_t), t, m,
            note="run_rams_ekf, keep_innovation=False")
    else:
        log("  mtcal RAMS EKF batched: not available (mtcal.filters.rams_ekf not importable)")
    add("ahrs Mahony batch API", "ahrs", lambda: anchors.ahrs_mahony_batch(gl, al, DT_S, q0=inp.q0), 1, nl,
        note=loop_note)
    add(ANCHORS["ahrs_mahony"], "ahrs", lambda: anchors.ahrs_mahony_loop(gl, al, DT_S, q0=inp.q0), 1, nl,
        note=loop_note)
    add(ANCHORS["imufusion"], "imufusion", lambda: anchors.imufusion_loop(g1, a1, DT_S, q0=inp.q0), 1, n,
        note="C library, Python loop over samples")
    add(ANCHORS["filterpy_ekf"], "filterpy",
        lambda: anchors.filterpy_ekf_loop(gl, al, st[:nl], inp.axis, inp.accel0_1, DT_S), 1, nl,
        note=loop_note)
    add("numpy EKF loop", "numpy",
        lambda: anchors.numpy_ekf_loop(gl, al, st[:nl], inp.axis, inp.accel0_1, DT_S), 1, nl,
        note=loop_note)
    add("numpy Mahony batched", "numpy",
        lambda: anchors.numpy_mahony_batched(inp.gyro_t, inp.accel_t, DT_S, q0=inp.q0), t, m,
        note="plain numpy over trials")
    return rows


def run_mc_subprocess(sizes: Sizes) -> tuple[Measurement, dict]:
    """Streaming Monte Carlo in its own process (peak RSS measured alone)."""
    cmd = [sys.executable, str(HERE / "mc_stream.py"), "--trials", str(sizes.mc_trials),
           "--duration", str(sizes.mc_duration_s), "--seed", str(SEED), "--json"]
    env = dict(os.environ, MTCAL_PROGRESS="0")
    out = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True, check=True)
    res = json.loads(out.stdout.strip().splitlines()[-1])
    hwm = res.get("vm_hwm_mb")
    row = Measurement("streaming Monte Carlo (QNCF)", "mtcal", res["trials"],
                      int(round(res["duration_s"] * FS_HZ)), res["wall_s"], res["peak_rss_mb"], memory="peak RSS",
                      note=f"simulate+QNCF+metrics, chunk {res['chunk_samples']}, prefetch "
                           f"{'on' if res.get('prefetch') else 'off'}, own process; getrusage peak RSS "
                           f"{res['peak_rss_mb']:.0f} MB, VmHWM {'n/a' if hwm is None else f'{hwm:.0f} MB'}")
    return row, res


# --------------------------------------------------------------------------- reporting
def results_table(rows: list[Measurement]) -> pd.DataFrame:
    """Rows as a DataFrame with throughput and ratio-to-anchor columns."""
    thr = {r.method: r.throughput for r in rows}
    df = pd.DataFrame([{"method": r.method, "library": r.library, "trials": r.trials, "samples": r.samples,
                        "seconds": r.seconds, "throughput_trial_samples_per_s": r.throughput,
                        "peak_mb": r.peak_mb, "memory": r.memory, "note": r.note} for r in rows])
    for key, name in ANCHORS.items():
        df[f"x_{key}"] = df["throughput_trial_samples_per_s"] / thr[name] if name in thr else np.nan
    return df


def _row(df: pd.DataFrame, method: str, trials: int):
    sel = df[(df["method"] == method) & (df["trials"] == trials)]
    return None if sel.empty else sel.iloc[0]


def evaluate_targets(df: pd.DataFrame, batch_trials: int, mc: dict | None) -> list[tuple[str, str, bool | None]]:
    """(target, measured, met) for the issue #7 targets; met is None when not measurable."""
    out = []
    q = _row(df, "mtcal QNCF batched", batch_trials)
    e = _row(df, "mtcal RAMS EKF batched", batch_trials)
    if q is not None:
        out.append((f"QNCF {batch_trials} trials >= {TARGETS['qncf_vs_ahrs']:.0f}x ahrs Mahony per-sample",
                    f"{q['x_ahrs_mahony']:.0f}x", bool(q["x_ahrs_mahony"] >= TARGETS["qncf_vs_ahrs"])))
        out.append((f"QNCF {batch_trials} trials >= {TARGETS['qncf_vs_imufusion']:.0f}x imufusion",
                    f"{q['x_imufusion']:.1f}x", bool(q["x_imufusion"] >= TARGETS["qncf_vs_imufusion"])))
        thr = q["throughput_trial_samples_per_s"]
        out.append((f"QNCF {batch_trials} trials >= {TARGETS['qncf_throughput'] / 1e6:.0f} M trial-samples/s",
                    f"{thr / 1e6:.2f} M/s", bool(thr >= TARGETS["qncf_throughput"])))
    if e is not None:
        out.append((f"RAMS EKF {batch_trials} trials >= {TARGETS['ekf_vs_filterpy']:.0f}x filterpy loop",
                    f"{e['x_filterpy_ekf']:.0f}x", bool(e["x_filterpy_ekf"] >= TARGETS["ekf_vs_filterpy"])))
    else:
        out.append(("RAMS EKF >= 300x filterpy loop", "not available", None))
    if mc is not None:
        full = mc["trials"] >= 1000 and mc["duration_s"] >= 60.0
        tag = "" if full else f" (measured at {mc['trials']} x {mc['duration_s']:g} s, not the target size)"
        out.append((f"Monte Carlo 1000 x 60 s wall <= {TARGETS['mc_wall_s']:.0f} s",
                    f"{mc['wall_s']:.1f} s{tag}", bool(mc["wall_s"] <= TARGETS["mc_wall_s"]) if full else None))
        out.append((f"Monte Carlo 1000 x 60 s peak RSS <= {TARGETS['mc_rss_mb'] / 1024:.0f} GB",
                    f"{mc['peak_rss_mb']:.0f} MB{tag}",
                    bool(mc["peak_rss_mb"] <= TARGETS["mc_rss_mb"]) if full else None))
    return out


def format_table(df: pd.DataFrame) -> str:
    head = (f"{'method':34s} {'trials':>6s} {'samples':>7s} {'seconds':>8s} {'trial-samples/s':>15s} "
            f"{'x ahrs':>8s} {'x imufus':>8s} {'x filterpy':>10s} {'peak MB':>8s}")
    lines = [head, "-" * len(head)]

    def ratio(x):
        return f"{x:.3g}" if np.isfinite(x) else "-"
    for _, r in df.iterrows():
        mem = f"{r['peak_mb']:.1f}" + ("*" if r["memory"] != "tracemalloc" else "")
        lines.append(f"{r['method']:34s} {r['trials']:6d} {r['samples']:7d} {r['seconds']:8.3f} "
                     f"{r['throughput_trial_samples_per_s']:15.4g} {ratio(r['x_ahrs_mahony']):>8s} "
                     f"{ratio(r['x_imufusion']):>8s} {ratio(r['x_filterpy_ekf']):>10s} {mem:>8s}")
    return "\n".join(lines)


# --------------------------------------------------------------------------- profiling
def _step_cost_us(make_call: Callable[[int, int], Callable[[], object]], trials: int, steps: int) -> float:
    call = make_call(trials, steps)
    call()
    best = np.inf
    for _ in range(3):
        t0 = time.perf_counter()
        call()
        best = min(best, time.perf_counter() - t0)
    return best / steps * 1e6


def profile_batched(inp: BenchInputs, sizes: Sizes) -> str:
    """cProfile of the batched filters (top functions by own time) + per-step cost vs trials."""
    m = min(inp.gyro_t.shape[1], int(round(sizes.profile_s * FS_HZ)))
    t = inp.gyro_t.shape[0]
    g, a = inp.gyro_t[:, :m], inp.accel_t[:, :m]
    targets = [("QNCF", _qncf_call(g, a, inp.q0))]
    if run_rams_ekf is not None:
        targets.append(("RAMS EKF", _ekf_call(g, a, inp.is_static[:m], inp.axis, inp.accel0_t)))
    parts = []
    for name, call in targets:
        prof = cProfile.Profile()
        prof.enable()
        call()
        prof.disable()
        buf = io.StringIO()
        stats = pstats.Stats(prof, stream=buf)
        stats.strip_dirs().sort_stats("tottime").print_stats(15)
        parts.append(f"=== cProfile: mtcal {name} batched, {t} trials x {m} samples "
                     f"(sorted by own time; numpy ufunc calls are not profiled separately and count "
                     f"in the caller's tottime) ===\n" + buf.getvalue().strip())
    parts.append(_line_profile_section(g, a, inp, min(m, 300)))
    parts.append(_scaling_section(inp, min(m, 500)))
    return "\n\n".join(parts) + "\n"


def line_times(func, call: Callable[[], object]) -> dict[int, float]:
    """Wall time spent on each source line of ``func`` during ``call()`` (s), via ``sys.settrace``.

    A minimal line profiler (no third-party dependency): each line event adds
    ~0.3-1 us of tracing overhead, small against the 1000-trial lines of interest.
    """
    code = func.__code__
    acc: dict[int, float] = {}
    state = {"line": None, "t": 0.0}

    def local(frame, event, arg):
        now = time.perf_counter()
        if state["line"] is not None:
            acc[state["line"]] = acc.get(state["line"], 0.0) + now - state["t"]
        state["line"] = frame.f_lineno if event == "line" else None
        state["t"] = time.perf_counter()
        return local

    def global_(frame, event, arg):
        return local if frame.f_code is code else None

    sys.settrace(global_)
    try:
        call()
    finally:
        sys.settrace(None)
    return acc


def _line_profile_section(g, a, inp: BenchInputs, steps: int) -> str:
    import inspect
    import linecache

    t = g.shape[0]
    g, a = g[:, :steps], a[:, :steps]
    targets = [("QNCF", QncfFilter._step, _qncf_call(g, a, inp.q0))]
    if run_rams_ekf is not None:
        from mtcal.filters.rams_ekf import RamsEkfFilter

        targets.append(("RAMS EKF", RamsEkfFilter._step, _ekf_call(g, a, inp.is_static[:steps], inp.axis,
                                                                   inp.accel0_t)))
    out = []
    for name, func, call in targets:
        acc = line_times(func, call)
        total = sum(acc.values())
        fname = inspect.getsourcefile(func)
        lines = [f"=== line times: mtcal {name} ({func.__qualname__}), {t} trials x {steps} steps, "
                 f"sys.settrace; top 12 lines, % of the function's traced time ==="]
        for ln, sec in sorted(acc.items(), key=lambda kv: -kv[1])[:12]:
            src = linecache.getline(fname, ln).strip()
            lines.append(f"{100 * sec / total:5.1f} %  {sec / steps * 1e6:7.1f} us/step  "
                         f"{Path(fname).name}:{ln}  {src[:90]}")
        out.append("\n".join(lines))
    return "\n\n".join(out)


def _scaling_section(inp: BenchInputs, steps: int) -> str:
    """Per-time-step cost versus trial count: fixed per-step overhead + per-trial cost."""
    rng = np.random.default_rng(0)
    lines = [f"=== per-time-step cost (us) vs trials ({steps} steps, best of 3); "
             f"fit cost = overhead + per_trial * T ==="]

    def data(trials, steps_):
        g = inp.gyro_t[:1, :steps_] + 1e-4 * rng.standard_normal((trials, steps_, 3))
        a = inp.accel_t[:1, :steps_] + 1e-3 * rng.standard_normal((trials, steps_, 3))
        return g, a

    makers = {"QNCF": lambda T, s: _qncf_call(*data(T, s), inp.q0)}
    if run_rams_ekf is not None:
        makers["RAMS EKF"] = lambda T, s: _ekf_call(*data(T, s), inp.is_static[:s], inp.axis,
                                                    inp.accel0_1)
    trial_counts = (1, 100, 1000, 4000)
    for name, make in makers.items():
        cost = np.array([_step_cost_us(make, T, steps) for T in trial_counts])
        slope, icpt = np.polyfit(trial_counts, cost, 1)
        pts = ", ".join(f"T={T}: {c:.1f}" for T, c in zip(trial_counts, cost))
        lines.append(f"{name:9s} {pts}  -> overhead {icpt:.1f} us/step + {slope * 1e3:.1f} ns/trial/step; "
                     f"at T=1000 overhead is {100 * icpt / (icpt + 1000 * slope):.0f} % of the step")
    return "\n".join(lines)


# --------------------------------------------------------------------------- main
def _versions() -> str:
    import ahrs
    import filterpy
    import imufusion  # noqa: F401
    from importlib.metadata import version

    return (f"python {platform.python_version()}, numpy {np.__version__}, ahrs {ahrs.__version__}, "
            f"imufusion {version('imufusion')}, filterpy {filterpy.__version__}, "
            f"{os.cpu_count()} CPUs, {platform.machine()}")


def main(argv: list[str] | None = None) -> pd.DataFrame:
    ap = argparse.ArgumentParser(description="mtcal benchmarks against ahrs, imufusion and filterpy")
    ap.add_argument("--quick", action="store_true", help="small sizes for a fast check")
    ap.add_argument("--no-mc", action="store_true", help="skip the streaming Monte Carlo subprocess")
    ap.add_argument("--no-profile", action="store_true", help="skip cProfile")
    ap.add_argument("--csv", type=Path, default=ROOT / "data" / "benchmarks.csv")
    ap.add_argument("--profile-out", type=Path, default=HERE / "profile_summary.txt")
    args = ap.parse_args(argv)
    sizes = QUICK if args.quick else FULL
    t_start = time.perf_counter()
    print(f"mtcal benchmarks ({'quick' if args.quick else 'full'} sizes) - {_versions()}")
    print(f"data: {sizes.record_s:g} s @ {FS_HZ:g} Hz pitch schedule, wang2023cja tactical MEMS IMU, seed {SEED}; "
          f"{sizes.batch_trials} trials x first {sizes.batch_record_s:g} s for batched runs; "
          f"per-sample Python loops on the first {sizes.loop_record_s:g} s")
    print("load average before the run (1/5/15 min): "
          + ", ".join(f"{x:.2f}" for x in os.getloadavg()) + f" on {os.cpu_count()} CPUs "
          "(other processes on the machine slow every row alike)")
    mc = mc_row = None
    if not args.no_mc:  # first, while this process is small (ru_maxrss is inherited through fork/exec)
        print(f"streaming Monte Carlo {sizes.mc_trials} x {sizes.mc_duration_s:g} s in a subprocess ...")
        mc_row, mc = run_mc_subprocess(sizes)
        print(f"  {mc['wall_s']:.1f} s, peak RSS {mc['peak_rss_mb']:.0f} MB")
    t_sim = time.perf_counter()
    inp = make_inputs(sizes)
    print(f"simulated in {time.perf_counter() - t_sim:.1f} s; timing (best of up to {sizes.repeats}):")
    rows = benchmark_methods(inp, sizes)
    if mc_row is not None:
        rows.append(mc_row)
    df = results_table(rows)
    print()
    print(format_table(df))
    print("peak MB: tracemalloc peak during the call (inputs excluded); * = peak RSS of the whole process.")
    print("x ahrs / x imufus / x filterpy: throughput (trial-samples/s) relative to "
          + ", ".join(ANCHORS.values()) + ".")
    for _, r in df.iterrows():
        if r["note"].startswith("first") or r["memory"] != "tracemalloc":
            print(f"note: {r['method']}: {r['note']}")
    print()
    print("targets (issue #7):")
    for name, measured, met in evaluate_targets(df, sizes.batch_trials, mc):
        verdict = "n/a" if met is None else ("MET" if met else "MISSED")
        print(f"  [{verdict:6s}] {name}: {measured}")
    if mc is not None:
        med = ", ".join(f"{k} {v:.4f}" for k, v in zip(("yaw", "pitch", "roll"), mc["rmse_deg_median"]))
        print(f"  Monte Carlo RMSE medians (deg): {med}")
    if not args.no_profile:
        summary = profile_batched(inp, sizes)
        args.profile_out.parent.mkdir(parents=True, exist_ok=True)
        args.profile_out.write_text(f"# {_versions()}\n# sizes: {'quick' if args.quick else 'full'}\n\n"
                                    + summary)
        print()
        print(summary.split("\n\n")[-1].strip())
        print(f"cProfile tables written to {args.profile_out.relative_to(ROOT) if args.profile_out.is_relative_to(ROOT) else args.profile_out}")
    print("load average after the run: " + ", ".join(f"{x:.2f}" for x in os.getloadavg()))
    args.csv.parent.mkdir(parents=True, exist_ok=True)
    df.to_csv(args.csv, index=False, float_format="%.6g")
    print(f"results written to {args.csv.relative_to(ROOT) if args.csv.is_relative_to(ROOT) else args.csv}; "
          f"total {time.perf_counter() - t_start:.0f} s")
    return df


if __name__ == "__main__":
    main()
