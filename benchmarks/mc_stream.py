"""Streaming Monte Carlo benchmark: 1000 trials × 60 s @ 1 kHz of QNCF in bounded memory.

simulate (:class:`mtcal.core.simulate.ImuStream`) → QNCF (:class:`mtcal.filters.qncf.QncfFilter`,
state carried chunk to chunk) → metrics (:class:`mtcal.core.montecarlo.ErrorAccumulator`),
driven by :func:`mtcal.core.montecarlo.run_streaming`. Nothing of size
trials × samples is ever held: memory is O(trials × chunk_samples). Because the
stream's random draws and the filter step do not depend on the chunk size, the
per-sample errors are bit-identical for any chunk size; only the running sums
of the accumulator are added in a different order (rounding, ~1e-16 relative).

Scenario (also used by ``benchmarks/run.py`` so that every method sees the same
data): a 1-channel pitch step schedule about the body x axis (wang2023cja Eq 8/9
pitch; RAMS EKF axis v = x), waypoints 0 → 30 → −20 → 45 → 10 → 0 deg, 70 % of
the record in holds, 30 % in minimum-jerk moves (so the schedule scales with the
record length), no lever arm; the tactical MEMS IMU of wang2023cja
(:class:`mtcal.studies.wang2023cja.ImuSpec`, every error source on, 5 min after
power-on); QNCF with its default gains, started at the true initial attitude.

Run alone::

    .venv/bin/python benchmarks/mc_stream.py --trials 1000 --duration 60 --json

prints the wall time of the whole run (scenario + simulation + filter +
metrics), the process's CPU time (user + system: on a shared machine the wall
time depends on the other processes, the CPU time much less) and its peak RSS
(``resource.getrusage(RUSAGE_SELF)``, which includes the interpreter and the
imported libraries).

Target row (issue #24, in ``benchmarks/run.py``): "streaming Monte Carlo
1000 x 60 s wall <= 2 s" on 2 cores and "... peak RSS <= 512 MB". The simulator
draws its noise inside its compiled kernel (counter-based Philox,
:mod:`mtcal.core.philox`), trials in parallel, so no (trials, samples, 3)
noise array is made; only each chunk's measurements (T, chunk, 3) per sensor, whose
buffers the stream recycles once the filter has dropped them.

Threads (issue #24): by default the trials are split into one contiguous share per numba
thread, each streamed by its own worker thread through single-threaded kernels (simulator and
filter both release the GIL; trials are named by id, so every trial's numbers are those of
the whole run, bit for bit). Compared with trial-parallel kernels plus a prefetch thread
(``--workers 1``, the previous scheme, kept) this starts and joins no parallel region per
chunk and per stage, runs at most one busy thread per core, and halves each core's chunk.
"""

from __future__ import annotations

import argparse
import json
import resource
import sys
import time
from dataclasses import dataclass

import numpy as np

from mtcal.core import profiles, rotations
from mtcal.filters.qncf import QncfFilter, QncfParams
from mtcal.core.metrics import percentile_band
from mtcal.core.montecarlo import ErrorAccumulator, run_streaming
from mtcal.studies.wang2023cja import ImuSpec
from mtcal.core.simulate import ImuErrorModel, ImuRecord, ImuStream, Trajectory

__all__ = ["PITCH_WAYPOINTS_DEG", "BenchData", "bench_scenario", "error_model", "PrefetchStream",
           "QncfErrorConsumer",
           "run_mc", "peak_rss_mb", "vm_hwm_mb"]

#: Pitch waypoints of the benchmark schedule (deg).
PITCH_WAYPOINTS_DEG = (0.0, 30.0, -20.0, 45.0, 10.0, 0.0)
#: Rotation axis of the schedule in the body frame (pitch axis of wang2023cja Eq 9, ZXY).
AXIS_B = (1.0, 0.0, 0.0)
_HOLD_FRACTION = 0.7


@dataclass(frozen=True)
class BenchData:
    """Truth of the benchmark scenario.

    Attributes
    ----------
    trajectory : Trajectory
    is_static : ndarray (N,) of bool
        True inside holds (ZVD flags for the RAMS EKF).
    axis_b : ndarray (3,)
        Rotation axis (body = sensor frame, identity mounting).
    """

    trajectory: Trajectory
    is_static: np.ndarray
    axis_b: np.ndarray


def bench_scenario(duration_s: float = 60.0, fs_hz: float = 1000.0) -> BenchData:
    """Pitch step schedule of ``duration_s`` seconds at ``fs_hz`` (see module docstring)."""
    if duration_s * fs_hz < 50:
        raise ValueError(f"duration_s * fs_hz must be at least 50 samples, got {duration_s * fs_hz:g}")
    wp = np.radians(PITCH_WAYPOINTS_DEG)
    travel = float(np.abs(np.diff(wp)).sum())
    rate = travel / ((1.0 - _HOLD_FRACTION) * duration_s)
    hold = _HOLD_FRACTION * duration_s / wp.size
    prof = profiles.step_schedule(wp, rate, hold, fs_hz)
    traj = profiles.fixed_axis_trajectory(prof, AXIS_B)
    return BenchData(traj, prof.is_static.copy(), np.array(AXIS_B))


def error_model() -> ImuErrorModel:
    """wang2023cja tactical MEMS IMU, every error source on, identity mounting."""
    return ImuSpec().error_model((1.0, 0.0, 0.0, 0.0))


class PrefetchStream(ImuStream):
    """:class:`ImuStream` that simulates the next chunk in a background thread.

    The chunks are the same objects in the same order as ``ImuStream.chunks``
    (same draws); only the simulation of chunk k+1 overlaps the filtering of
    chunk k. The simulator's kernel releases the GIL (``nogil``) and is itself
    parallel over trials; overlapping it with the filter fills the gaps of each
    stage (serial Python glue, the end of a parallel region waiting for its
    slowest thread). At most three chunks are alive (being filtered, queued,
    being made).
    """

    def chunks(self, chunk_samples: int):
        import queue
        import threading

        done = object()
        box: queue.Queue = queue.Queue(maxsize=1)
        stop = threading.Event()
        source = super().chunks(chunk_samples)

        def produce() -> None:
            try:
                for item in source:
                    while not stop.is_set():
                        try:
                            box.put(item, timeout=0.1)
                            break
                        except queue.Full:
                            continue
                    if stop.is_set():
                        return
                box.put(done)
            except BaseException as exc:  # hand errors to the consumer thread
                box.put(exc)

        worker = threading.Thread(target=produce, name="imu-prefetch", daemon=True)
        worker.start()
        try:
            while True:
                item = box.get()
                if item is done:
                    break
                if isinstance(item, BaseException):
                    raise item
                yield item
        finally:
            stop.set()
            worker.join()


class QncfErrorConsumer:
    """Chunk consumer: advances a :class:`QncfFilter` and folds Eq 8 angle errors in.

    Uses :meth:`QncfFilter.run_error_stats`: the filter kernel computes the wrapped
    yaw/pitch/roll errors of each attitude against the truth as it goes, so the
    chunk's (T, n, 4) quaternion history is never materialised.

    Parameters
    ----------
    q0 : array_like (4,)
        Initial attitude for every trial.
    dt_s : float
        Sample interval (s).
    trials : int
        Number of trials.
    params : QncfParams
        Filter tuning.
    """

    def __init__(self, q0, dt_s: float, trials: int, params: QncfParams = QncfParams()):
        self.filter = QncfFilter(q0, dt_s, params, trials=trials)
        self.errors = ErrorAccumulator((trials, 3))

    def update(self, chunk: ImuRecord) -> None:
        truth = rotations.euler_zxy_from_quat(chunk.q_ws_true)
        self.filter.run_error_stats(chunk.gyro_rad_s, chunk.accel_m_s2, truth, self.errors)


def run_mc(trials: int, duration_s: float = 60.0, *, chunk_samples: int = 1000, seed: int = 2023,
           fs_hz: float = 1000.0, prefetch: bool = True, progress: bool | None = None,
           workers: int | None = None) -> dict[str, np.ndarray]:
    """Streaming QNCF Monte Carlo; returns per-trial ``rmse``, ``max_abs``, ``mean`` (T, 3) in rad.

    Columns are Eq 8 yaw, pitch, roll errors (estimate − truth, wrapped).

    ``workers`` (default: numba's thread count) threads each stream their own contiguous share of
    the trials (``ImuStream(trial_ids=...)``) through simulator and filter with single-threaded
    kernels (both release the GIL): no parallel region to start and join twice per chunk, no
    threads competing for the cores, half the chunk per core. Trials are named by id and the
    filter's trials are independent (a 4-lane block equals each trial alone), so the numbers are
    bit-identical for any ``workers`` (tested). With ``workers=1`` the kernels run trial-parallel
    and ``prefetch`` simulates the next chunk in a background thread (:class:`PrefetchStream`);
    the numbers are the same either way.
    """
    import numba

    data = bench_scenario(duration_s, fs_hz)
    n_workers = max(1, min(int(numba.get_num_threads() if workers is None else workers), trials))
    if n_workers == 1:
        cls = PrefetchStream if prefetch else ImuStream
        stream = cls(data.trajectory, error_model(), np.random.default_rng(seed), trials=trials)
        consumer = QncfErrorConsumer(stream.q_ws[0], data.trajectory.dt_s, trials)
        run_streaming(stream, [consumer], chunk_samples, progress=progress)
        accs = [consumer.errors]
    else:
        accs = _run_workers(data, trials, chunk_samples, seed, n_workers, progress)
    return {name: np.concatenate([getattr(acc, name)() for acc in accs]) for name in ("rmse", "max_abs", "mean")}


def _run_workers(data: BenchData, trials: int, chunk_samples: int, seed: int, n_workers: int,
                 progress: bool | None) -> list[ErrorAccumulator]:
    """:func:`run_mc` split over ``n_workers`` threads by trial id; accumulators in trial order."""
    import threading

    import numba

    bounds = np.linspace(0, trials, n_workers + 1).round().astype(np.int64)
    accs: list = [None] * n_workers
    errors: list[BaseException] = []

    def work(w: int) -> None:
        try:
            numba.set_num_threads(1)   # per thread: this worker's kernels run serially
            ids = np.arange(bounds[w], bounds[w + 1])
            stream = ImuStream(data.trajectory, error_model(), np.random.default_rng(seed), trial_ids=ids)
            consumer = QncfErrorConsumer(stream.q_ws[0], data.trajectory.dt_s, ids.size)
            run_streaming(stream, [consumer], chunk_samples, progress=progress if w == 0 else False)
            accs[w] = consumer.errors
        except BaseException as exc:  # re-raised in the caller's thread
            errors.append(exc)

    threads = [threading.Thread(target=work, args=(w,), name=f"mc-worker-{w}") for w in range(n_workers)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    if errors:
        raise errors[0]
    return accs


def peak_rss_mb() -> float:
    """Peak resident set size of this process so far (MB; Linux reports ru_maxrss in KiB).

    Caveat (Linux): ``ru_maxrss`` survives ``execve``, so a child started by a
    large parent reports at least the parent's RSS at fork time; start the
    child while the parent is small (``benchmarks/run.py`` runs it first) and
    compare with :func:`vm_hwm_mb`.
    """
    kib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return kib / 1024.0 if sys.platform != "darwin" else kib / 2**20


def _cpu_s() -> float:
    """User + system CPU time of this process so far (s), all threads."""
    ru = resource.getrusage(resource.RUSAGE_SELF)
    return ru.ru_utime + ru.ru_stime


def vm_hwm_mb() -> float | None:
    """Peak RSS of the current address space (``VmHWM`` of /proc/self/status, MB); None if unavailable."""
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return None


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trials", type=int, default=1000)
    ap.add_argument("--duration", type=float, default=60.0, help="record length (s)")
    ap.add_argument("--chunk", type=int, default=1000, help="samples per chunk")
    ap.add_argument("--seed", type=int, default=2023)
    ap.add_argument("--no-prefetch", action="store_true", help="with --workers 1: simulate and filter in one thread")
    ap.add_argument("--workers", type=int, default=None,
                    help="threads, each streaming a share of the trials (default: numba's thread count)")
    ap.add_argument("--json", action="store_true", help="print one JSON line (for benchmarks/run.py)")
    args = ap.parse_args(argv)
    import numba

    workers = max(1, min(args.workers or numba.get_num_threads(), args.trials))
    rss0 = peak_rss_mb()
    t0, c0 = time.perf_counter(), _cpu_s()
    out = run_mc(args.trials, args.duration, chunk_samples=args.chunk, seed=args.seed,
                 prefetch=not args.no_prefetch, workers=workers)
    wall, cpu = time.perf_counter() - t0, _cpu_s() - c0
    band = percentile_band(np.degrees(out["rmse"]), axis=0)
    summary = {
        "trials": args.trials, "duration_s": args.duration, "chunk_samples": args.chunk,
        "prefetch": workers == 1 and not args.no_prefetch, "workers": workers,
        "trial_samples": int(args.trials * round(args.duration * 1000.0)),
        "wall_s": wall, "cpu_s": cpu, "peak_rss_mb": peak_rss_mb(), "vm_hwm_mb": vm_hwm_mb(),
        "rss_after_imports_mb": rss0,
        "rmse_deg_median": band["median"].tolist(), "rmse_deg_low": band["low"].tolist(),
        "rmse_deg_high": band["high"].tolist(),
    }
    if args.json:
        print(json.dumps(summary))
    else:
        print(f"streaming Monte Carlo: {args.trials} trials x {args.duration:g} s @ 1 kHz, "
              f"chunk {args.chunk} samples, {workers} worker thread(s)"
              f"{', prefetch ' + ('on' if summary['prefetch'] else 'off') if workers == 1 else ''}")
        hwm = summary["vm_hwm_mb"]
        print(f"  wall time {wall:.2f} s (CPU {cpu:.2f} s), peak RSS {summary['peak_rss_mb']:.0f} MB (getrusage; "
              f"VmHWM {'n/a' if hwm is None else f'{hwm:.0f} MB'}; after imports {rss0:.0f} MB)")
        for i, name in enumerate(("yaw", "pitch", "roll")):
            print(f"  {name:5s} RMSE median {band['median'][i]:.4f} deg, "
                  f"95 % band [{band['low'][i]:.4f}, {band['high'][i]:.4f}] deg")
    return summary


if __name__ == "__main__":
    main()
