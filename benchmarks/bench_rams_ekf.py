"""Benchmark: fast batched RAMS EKF vs the filterpy reference loop, and vs the previous kernel.

Same simulated data (Table 3 IMU, a Fig. 9-like rest/move/rest record at
200 Hz). The reference is timed on a few trials and its per-trial cost
extrapolated (it is strictly linear in trials). Not run by the tests:
``.venv/bin/python benchmarks/bench_rams_ekf.py [TRIALS]``.

``--before [SAMPLES]``: the issue #24 before/after row on its own — ``run_rams_ekf``
(1000 trials x SAMPLES, default 2000, numba's threads) with the current kernels and with
the previous ones (``benchmarks/before_kernels_ekf.py``), in one process, interleaved,
best of ``--repeats`` calls each; wall and CPU (user + sys) time, and a check that both
give bit-identical results. On a shared machine compare the CPU columns as well as wall.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

from mtcal.core import profiles
from mtcal.filters.rams_ekf import RamsEkfParams, RamsEkfReference, initial_state, run_rams_ekf
from mtcal.studies.wang2022sensors.runs import ImuSpec, RotationSetup, simulate_rotation


def main(trials: int = 1000) -> int:
    imu = ImuSpec()
    prof = profiles.step_schedule(np.radians([0.0, 40.0, -20.0]), np.radians(40.0), 1.0, imu.fs_hz)
    th = np.broadcast_to(prof.angle_rad[:, 0], (trials, prof.time_s.size))
    rec = simulate_rotation(th, np.broadcast_to(prof.rate_rad_s[:, 0], th.shape),
                            np.broadcast_to(prof.accel_rad_s2[:, 0], th.shape), prof.is_static,
                            RotationSetup(), imu.error_model(), imu.dt_s, 0)
    v = RotationSetup().unit_axis()
    a0, b0 = initial_state(rec.gyro_rad_s, rec.accel_m_s2, 150)
    p = imu.ekf_params()
    n = prof.time_s.size
    t0 = time.perf_counter()
    fast = run_rams_ekf(rec.gyro_rad_s, rec.accel_m_s2, prof.is_static, v, a0, imu.dt_s, p,
                        bias0_rad_s=b0, keep_innovation=False)
    t_fast = time.perf_counter() - t0
    n_ref = 3
    t0 = time.perf_counter()
    diffs = []
    for t in range(n_ref):
        ref = RamsEkfReference(v, a0[t], imu.dt_s, p, bias0_rad_s=b0[t]).run(
            rec.gyro_rad_s[t], rec.accel_m_s2[t], prof.is_static)
        diffs.append(np.max(np.abs(ref.theta_rad - fast.theta_rad[t])))
    t_ref = (time.perf_counter() - t0) / n_ref
    rate_fast = trials * n / t_fast
    rate_ref = n / t_ref
    print(f"RAMS EKF, {trials} trials x {n} samples (max |fast - reference| = {max(diffs):.2e} rad)")
    print(f"{'implementation':<28}{'trial-samples/s':>18}")
    print(f"{'filterpy reference (loop)':<28}{rate_ref:>18.3e}")
    print(f"{'fast batched (numpy)':<28}{rate_fast:>18.3e}")
    print(f"{'speed-up':<28}{rate_fast / rate_ref:>17.0f}x")
    return 0


def _timed(fn) -> tuple[float, float]:
    """(wall, CPU = user + sys of all this process's threads) seconds of one call."""
    c0, w0 = time.process_time(), time.perf_counter()
    fn()
    w1, c1 = time.perf_counter(), time.process_time()
    return w1 - w0, c1 - c0


def before_after(trials: int = 1000, samples: int = 2000, repeats: int = 7, seed: int = 0) -> dict:
    """Current vs previous EKF kernel through ``run_rams_ekf``, same data, interleaved calls.

    Returns best wall/CPU seconds and rates (trial-samples/s) of both and their ratios.
    """
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    import before_kernels_ekf
    from mtcal.filters import _kernels_ekf

    rng = np.random.default_rng(seed)
    fs_hz = 1000.0
    t = np.arange(samples) / fs_hz
    theta = np.radians(30.0) * np.sin(2 * np.pi * 0.5 * t)                   # a swinging surface
    v = RotationSetup().unit_axis()
    gyro = np.gradient(theta, 1 / fs_hz)[None, :, None] * v + 2e-3 * rng.standard_normal((trials, samples, 3))
    c, s = np.cos(theta), np.sin(theta)
    g_b = np.array([0.0, 0.0, 9.80665])
    par = v * (v @ g_b)
    accel = (par + c[:, None] * (g_b - par) - s[:, None] * np.cross(v, g_b))[None]
    accel = accel + 0.02 * rng.standard_normal((trials, samples, 3))
    is_static = np.abs(np.gradient(theta, 1 / fs_hz)) < 0.05
    a0 = accel[:, :50].mean(axis=1)

    def call():
        return run_rams_ekf(gyro, accel, is_static, v, a0, 1 / fs_hz, RamsEkfParams(), keep_innovation=False)

    kernels = {"after": (_kernels_ekf.ekf_serial, _kernels_ekf.ekf_parallel),
               "before": (before_kernels_ekf.ekf_serial, before_kernels_ekf.ekf_parallel)}
    _kernels_ekf.warm_up()
    before_kernels_ekf.warm_up()
    results, best = {}, {k: [np.inf, np.inf] for k in kernels}
    try:
        for _ in range(repeats + 1):                       # first round: untimed (caches, page pools)
            for name, (serial, parallel) in kernels.items():
                _kernels_ekf.ekf_serial, _kernels_ekf.ekf_parallel = serial, parallel
                if name not in results:
                    results[name] = call()
                    continue
                wall, cpu = _timed(call)
                best[name] = [min(best[name][0], wall), min(best[name][1], cpu)]
    finally:
        _kernels_ekf.ekf_serial, _kernels_ekf.ekf_parallel = kernels["after"]
    same = all(np.array_equal(getattr(results["after"], f), getattr(results["before"], f))
               for f in ("theta_rad", "bias_rad_s", "p_theta_rad2", "P", "S", "K"))
    work = trials * samples
    out = {"trials": trials, "samples": samples, "bit_identical": same}
    for name, (wall, cpu) in best.items():
        out[name] = {"wall_s": wall, "cpu_s": cpu, "rate_wall": work / wall, "rate_cpu": work / cpu}
    out["ratio_wall"] = best["before"][0] / best["after"][0]
    out["ratio_cpu"] = best["before"][1] / best["after"][1]
    return out


def _print_before_after(res: dict) -> None:
    import numba

    from mtcal.filters._kernels_ekf import LANES

    print(f"RAMS EKF before/after, {res['trials']} trials x {res['samples']} samples, {numba.get_num_threads()} "
          f"threads, {LANES}-lane blocks, NUMBA_CPU_NAME={os.environ.get('NUMBA_CPU_NAME', '(native)')}, "
          f"bit-identical: {res['bit_identical']}, load average {os.getloadavg()[0]:.2f}")
    print(f"{'kernel':<10}{'wall ms':>10}{'M/s (wall)':>12}{'CPU ms':>10}{'M/s (CPU)':>12}")
    for name in ("after", "before"):
        r = res[name]
        print(f"{name:<10}{r['wall_s'] * 1e3:>10.1f}{r['rate_wall'] / 1e6:>12.1f}{r['cpu_s'] * 1e3:>10.1f}"
              f"{r['rate_cpu'] / 1e6:>12.1f}")
    print(f"after / before: {res['ratio_wall']:.2f}x wall, {res['ratio_cpu']:.2f}x CPU")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("trials", nargs="?", type=int, default=1000)
    ap.add_argument("--before", nargs="?", type=int, const=2000, default=None, metavar="SAMPLES",
                    help="time the current vs the previous kernel (SAMPLES per trial, default 2000)")
    ap.add_argument("--repeats", type=int, default=7)
    ns = ap.parse_args()
    if ns.before is not None:
        _print_before_after(before_after(ns.trials, ns.before, ns.repeats))
        sys.exit(0)
    sys.exit(main(ns.trials))
