"""Compiled filter kernels as a whole: compile (or load from numba's cache) every one of them.

The kernels themselves are private modules (``_kernels_qncf``, ``_kernels_ekf``,
``_kernels_marg``, and the shared plumbing ``_kernels_common``); each public filter
imports its own kernel module when it first runs. This module sits above all of them
and is imported by none, so the kernel modules never import back upwards.
"""

from __future__ import annotations

import time

import numpy as np

from mtcal.core import csvtext, metrics, montecarlo, rotations, simulate
from mtcal.filters import _kernels_ekf, _kernels_mahony, _kernels_marg, _kernels_qncf
from mtcal.methods import gyro_roll, large_angle, rest_detection, tilt_rate

__all__ = ["warm_up_all"]


def warm_up_all() -> dict[str, float]:
    """Compile (or load from numba's cache) every compiled kernel of mtcal; seconds per group.

    E.g. once after installing (``python -c "from mtcal.filters.kernels import warm_up_all;
    print(warm_up_all())"``, as ``make venv`` does), so that the first notebook or CLI call does
    not pay the compile time (~10-20 s cold on 2 cores).

    Returns
    -------
    dict of str to float
        Seconds spent per kernel group: ``qncf``, ``rams_ekf``, ``marg`` (Madgwick and the Mahony lanes),
        ``tilt_rate`` (the filters' edge check), ``gyro_roll`` and ``large_angle`` (the roll and pitch error
        passes), ``rest_detection`` (its block sums), ``csv_text`` (the CLI's CSV writer), ``simulate``,
        ``metrics``, ``rotations`` (the compiled quaternion loops :mod:`mtcal.core.rotations` and
        :func:`mtcal.core.metrics.angle_difference` use on large arrays).

    Examples
    --------
    >>> groups = sorted(warm_up_all())
    >>> groups[:6]
    ['csv_text', 'gyro_roll', 'large_angle', 'marg', 'metrics', 'qncf']
    >>> groups[6:]
    ['rams_ekf', 'rest_detection', 'rotations', 'simulate', 'tilt_rate']
    """
    out = {}
    for name, fn in (("qncf", _kernels_qncf.warm_up), ("rams_ekf", _kernels_ekf.warm_up),
                     ("marg", lambda: (_kernels_marg.warm_up(), _kernels_mahony.warm_up())),
                     ("tilt_rate", tilt_rate.warm_up), ("gyro_roll", gyro_roll.warm_up),
                     ("large_angle", large_angle.warm_up),
                     ("rest_detection", rest_detection.warm_up), ("csv_text", csvtext.warm_up)):
        t0 = time.perf_counter()
        fn()
        out[name] = time.perf_counter() - t0
    t0 = time.perf_counter()
    every = simulate.SensorErrors(bias_sigma=1e-4, noise_density=1e-4, bias_random_walk=1e-5, bias_instability=1e-5,
                                  warmup_bias=1e-4, quantization=1e-6, vibration_amplitude=1e-4,
                                  vibration_freq_hz=10.0)
    t = np.arange(300) * 1e-3
    simulate.simulate_imu(simulate.Trajectory(t, np.tile([1.0, 0.0, 0.0, 0.0], (t.size, 1))),
                          simulate.ImuErrorModel(gyro=every), np.random.default_rng(0), trials=2)
    # the noise kernel per number of error models sharing one draw (1: a fill; 2: the predictive kinds'
    # fill_streams) — serial, and parallel from PARALLEL_MIN_WORK trial-samples when numba has threads
    for n in (t.size, simulate.PARALLEL_MIN_WORK // 2):
        traj = simulate.Trajectory(np.arange(n) * 1e-3, np.tile([1.0, 0.0, 0.0, 0.0], (n, 1)))
        for k in (1, 2):
            streams = [simulate.ImuStream(traj, simulate.ImuErrorModel(gyro=every), np.random.default_rng(0), trials=2)
                       for _ in range(k)]
            simulate.fill_streams(streams, [(np.empty((2, n, 3)), np.empty((2, n, 3))) for _ in range(k)])
    out["simulate"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    montecarlo._euler_error_stats(np.tile([1.0, 0.0, 0.0, 0.0], (2, 2, 1)), np.zeros((1, 2, 3)), np.zeros((2, 3)),
                                  np.zeros((2, 3)), np.zeros((2, 3)))
    q1 = np.tile([1.0, 0.0, 0.0, 0.0], (1, 2, 1))        # the sweeps' Eq 8 pass (wang2023cja notebooks)
    montecarlo.channel_errors_cs(q1, np.eye(4)[None], montecarlo.truth_table(np.zeros((1, 2, 3)))[0],
                                 rotations._LOCK_SIN, 1, np.empty((1, 2)), np.empty((1, 2)), np.empty((1, 2, 3)),
                                 np.empty((1, 2, 3)))
    out["metrics"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    n = rotations._KERNEL_MIN_ROWS  # the size from which the compiled loops are used
    ramp = np.linspace(0.0, 1.0, n)
    q = rotations.quat_from_euler_zxy(0.1 * ramp, 0.2 * ramp, 0.3 * ramp)
    q = rotations.make_continuous(rotations.quat_normalize(rotations.quat_multiply(q, rotations.quat_conjugate(q))))
    rotations.quat_from_rotvec(rotations.rotvec_from_quat(q))
    rotations.quat_to_matrix(q)
    e = rotations.euler_zxy_from_quat(q)
    metrics.angle_difference(e, e)
    out["rotations"] = time.perf_counter() - t0
    return out
