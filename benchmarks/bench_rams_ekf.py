"""Benchmark: fast batched RAMS EKF vs the filterpy reference loop (trial-samples per second).

Same simulated data (Table 3 IMU, a Fig. 9-like rest/move/rest record at
200 Hz). The reference is timed on a few trials and its per-trial cost
extrapolated (it is strictly linear in trials). Not run by the tests:
``.venv/bin/python benchmarks/bench_rams_ekf.py [TRIALS]``.
"""

from __future__ import annotations

import sys
import time

import numpy as np

from mtcal.core import profiles
from mtcal.filters.rams_ekf import RamsEkfReference, initial_state, run_rams_ekf
from mtcal.studies.wang2022sensors.runs import ImuSpec, RotationSetup, simulate_rotation


def main(trials: int = 1000) -> int:
    imu = ImuSpec()
    prof = profiles.step_schedule(np.radians([0.0, 40.0, -20.0]), np.radians(40.0), 1.0, imu.fs_hz)
    th = np.broadcast_to(prof.angle_rad[:, 0], (trials, prof.time_s.size))
    rec = simulate_rotation(th, np.broadcast_to(prof.rate_rad_s[:, 0], th.shape),
                            np.broadcast_to(prof.accel_rad_s2[:, 0], th.shape), prof.is_static,
                            RotationSetup(), imu.error_model(), imu.fs_hz, np.random.default_rng(0))
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


if __name__ == "__main__":
    sys.exit(main(int(sys.argv[1]) if len(sys.argv) > 1 else 1000))
