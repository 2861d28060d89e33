"""QNCF throughput: vectorised-over-trials filter vs a per-sample scalar Python loop.

Usage: ``.venv/bin/python benchmarks/bench_qncf.py [--trials 1000] [--seconds 10]``
or, kernel only: ``.venv/bin/python benchmarks/bench_qncf.py --kernel [--before OLD_KERNELS.py] [--repeats 7]``

The vectorised run processes ``trials × seconds × 1000`` samples (1 kHz) in
time chunks of 2048 samples (:meth:`QncfFilter.run`), so memory stays at the
input/output arrays (1000 × 10 s: ≈ 0.24 GB per (T, N, 3) float64 array). The
1000 × 60 s target is extrapolated from the measured throughput (the cost is
linear in samples). The reference is the same filter written as a plain
per-sample Python loop on one trial (scalar math), timed over a few thousand
samples. Not run by the tests.

``--kernel`` times the batched kernel alone (``qncf_parallel`` on numba's threads, and
``qncf_serial`` on one thread), with histories kept (as :meth:`QncfFilter.run`) and with the
fused Eq 8 error statistics (as :meth:`QncfFilter.run_error_stats`), best of ``--repeats``,
as CPU time (user + system of the process, all threads) per trial-step and wall time. With
``--before PATH`` (a copy of an earlier ``mtcal/filters/_kernels_qncf.py``) the earlier kernel
is timed in the same process, interleaved call by call, and both must give the same bits.
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import sys
import time
from pathlib import Path

import numpy as np

from mtcal.filters.qncf import QncfParams, qncf


def scalar_qncf(gyro, accel, dt, p=QncfParams()):
    """Same filter as mtcal.filters.qncf, one trial, scalar Python per sample (reference)."""
    q0, q1, q2, q3 = 1.0, 0.0, 0.0, 0.0
    ix = iy = iz = 0.0
    amd = None
    alpha = min(dt / p.amd_tau_s, 1.0)
    out = np.empty((len(gyro), 4))
    for k in range(len(gyro)):
        out[k] = (q0, q1, q2, q3)
        ax, ay, az = accel[k]
        n = math.sqrt(ax * ax + ay * ay + az * az)
        d = 100.0 * abs(n / p.gravity_m_s2 - 1.0)
        amd = d if amd is None else amd + alpha * (d - amd)
        g = 1.0 / n if amd < p.amd_threshold_pct else 0.0
        vx, vy, vz = 2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3
        ex, ey, ez = (ay * vz - az * vy) * g, (az * vx - ax * vz) * g, (ax * vy - ay * vx) * g
        ix += p.ki_rad_s2 * ex * dt; iy += p.ki_rad_s2 * ey * dt; iz += p.ki_rad_s2 * ez * dt
        wx = (gyro[k, 0] + p.kp_rad_s * ex + ix) * dt
        wy = (gyro[k, 1] + p.kp_rad_s * ey + iy) * dt
        wz = (gyro[k, 2] + p.kp_rad_s * ez + iz) * dt
        a = math.sqrt(wx * wx + wy * wy + wz * wz)
        c, s = math.cos(a / 2), (math.sin(a / 2) / a if a > 1e-8 else 0.5)
        h0, h1, h2, h3 = c, wx * s, wy * s, wz * s
        q0, q1, q2, q3 = (q0 * h0 - q1 * h1 - q2 * h2 - q3 * h3, q0 * h1 + q1 * h0 + q2 * h3 - q3 * h2,
                          q0 * h2 - q1 * h3 + q2 * h0 + q3 * h1, q0 * h3 + q1 * h2 - q2 * h1 + q3 * h0)
        nq = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
        q0, q1, q2, q3 = q0 / nq, q1 / nq, q2 / nq, q3 / nq
    return out


def _kernel_args(gyro, accel, with_stats: bool) -> list:
    """Arguments of the batched QNCF kernels: histories kept, or the fused Eq 8 statistics against a zero truth."""
    from mtcal.core.montecarlo import truth_table

    n, m = gyro.shape[:2]
    q = np.tile([1.0, 0.0, 0.0, 0.0], (n, 1))
    if with_stats:
        outs = (np.zeros((1, 1, 4)), np.zeros((1, 1)), np.zeros((1, 1), bool))   # placeholders (never written)
        truth, stats = truth_table(np.zeros((1, m, 3))), np.zeros((n, 9))
    else:
        outs = (np.empty((n, m, 4)), np.empty((n, m)), np.empty((n, m), bool))
        truth, stats = np.zeros((1, 1, 3)), np.zeros((1, 9))
    return [gyro, accel, q, np.zeros((n, 3)), np.full(n, np.nan), *outs, 1.0, 2e-5, True, 1e-3, 0.02, 9.80665,
            0.3, not with_stats, truth, stats, with_stats, np.empty((n, 4))]


def kernel_bench(gyro, accel, repeats: int, before_path: str | None) -> None:
    """Kernel-only CPU and wall time per trial-step (see the module docstring)."""
    import numba

    from mtcal.filters import _kernels_qncf

    kernels = {"after": _kernels_qncf}
    if before_path:
        name = Path(before_path).stem   # module named after its file (numba's cache records the name)
        spec = importlib.util.spec_from_file_location(name, before_path)
        before = importlib.util.module_from_spec(spec)
        sys.modules[name] = before
        spec.loader.exec_module(before)
        kernels = {"before": before, "after": _kernels_qncf}
    for mod in kernels.values():
        mod.warm_up()
    work = gyro.shape[0] * gyro.shape[1]
    print(f"kernel only, {gyro.shape[0]} trials x {gyro.shape[1]} samples, {_kernels_qncf.LANES} lanes per block; "
          f"best of {repeats}: CPU ns per trial-step (wall s)")
    threads = numba.get_num_threads()
    for fn_name, n_threads in (("qncf_parallel", threads), ("qncf_serial", 1)):
        numba.set_num_threads(n_threads)
        for with_stats in (False, True):
            best = {k: [math.inf, math.inf] for k in kernels}
            last = {}
            for _ in range(repeats):
                for name, mod in kernels.items():
                    x = _kernel_args(gyro, accel, with_stats)
                    c0, w0 = time.process_time(), time.perf_counter()
                    getattr(mod, fn_name)(*x)
                    c1, w1 = time.process_time(), time.perf_counter()
                    best[name] = [min(best[name][0], c1 - c0), min(best[name][1], w1 - w0)]
                    last[name] = x
            same = all(np.array_equal(u, v) for u, v in zip(*last.values()) if isinstance(u, np.ndarray))
            row = "  ".join(f"{k} {1e9 * c / work:6.2f} ({w:.3f})" for k, (c, w) in best.items())
            ratio = (f"  CPU {best['before'][0] / best['after'][0]:.2f}x, bit-identical {same}"
                     if len(kernels) > 1 else "")
            print(f"  {fn_name:<13} {n_threads} thread(s), {'Eq 8 stats' if with_stats else 'histories '}: "
                  f"{row}{ratio}")
    numba.set_num_threads(threads)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trials", type=int, default=1000)
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--scalar-samples", type=int, default=5000)
    ap.add_argument("--kernel", action="store_true", help="time the batched kernel alone")
    ap.add_argument("--before", default=None, help="with --kernel: path of an earlier _kernels_qncf.py")
    ap.add_argument("--repeats", type=int, default=7)
    args = ap.parse_args()
    fs = 1000.0
    n = int(args.seconds * fs)
    rng = np.random.default_rng(0)
    gyro = 1e-3 * rng.standard_normal((args.trials, n, 3))
    accel = np.array([0.0, 0.0, 9.80665]) + 2e-3 * rng.standard_normal((args.trials, n, 3))
    if args.kernel:
        kernel_bench(gyro, accel, args.repeats, args.before)
        return 0

    t0 = time.perf_counter()
    res = qncf(gyro, accel, 1 / fs, q0=[1.0, 0, 0, 0], return_euler=False)
    t_vec = time.perf_counter() - t0
    m = args.scalar_samples
    t0 = time.perf_counter()
    ref = scalar_qncf(gyro[0, :m], accel[0, :m], 1 / fs)
    t_sca = time.perf_counter() - t0
    agree = float(np.abs(ref - res.q_ws[0, :m]).max())

    vec_rate = args.trials * n / t_vec
    sca_rate = m / t_sca
    print(f"{'implementation':<36} {'trial-samples':>14} {'time (s)':>9} {'trial-samples/s':>16}")
    print(f"{'vectorised QNCF (mtcal)':<36} {args.trials * n:>14d} {t_vec:>9.2f} {vec_rate:>16.3e}")
    print(f"{'scalar per-sample Python loop':<36} {m:>14d} {t_sca:>9.2f} {sca_rate:>16.3e}")
    print(f"speed-up {vec_rate / sca_rate:.0f}x; max |q_vec - q_scalar| = {agree:.1e}")
    print(f"extrapolated 1000 trials x 60 s at 1 kHz: {1000 * 60000 / vec_rate:.1f} s (target <= 60 s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
