"""IMU-only Mahony filter: closed-form cases, equivalence to QNCF without the gate, batching, errors."""

import numpy as np
import pytest

from mtcal.core import rotations
from mtcal.core.simulate import Trajectory, simulate_imu
from mtcal.filters.mahony import MahonyParams, mahony_imu
from mtcal.filters.qncf import QncfParams, qncf

G = 9.80665


def _up(q):
    q0, q1, q2, q3 = q
    return np.array([2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), q0**2 - q1**2 - q2**2 + q3**2])


def test_pure_integration_reproduces_truth_exactly():
    # K_p = K_i = 0: exact increments reproduce a known rotation (gyro = interval-mean rate)
    fs, n = 200.0, 600
    t = np.arange(n) / fs
    ang = np.radians(40.0) * t**2
    q_true = rotations.quat_from_rotvec(ang[:, None] * np.array([0.0, 0.6, 0.8]))
    rec = simulate_imu(Trajectory(t, q_true))
    res = mahony_imu(rec.gyro_rad_s, rec.accel_m_s2, 1 / fs, MahonyParams(0.0, 0.0), q0=q_true[0])
    assert np.max(rotations.quat_angle_between(res.q_ws, q_true)) < 1e-9


def test_converges_to_tilt_and_estimates_gyro_bias():
    q_true = rotations.quat_from_euler_zxy(0.3, np.radians(12.0), np.radians(-25.0))
    n, dt = 20000, 0.01
    acc = np.tile(G * _up(q_true), (n, 1))
    bias = np.array([0.01, -0.02, 0.005])
    gyr = np.tile(bias, (n, 1))
    res = mahony_imu(gyr, acc, dt, MahonyParams(1.0, 0.05), q0=[1.0, 0, 0, 0])
    up_est = _up(res.q_ws[-1])
    assert np.degrees(np.arccos(np.clip(up_est @ _up(q_true), -1, 1))) < 0.01
    # horizontal (tilt-observable) bias components are estimated, the vertical one is not
    v = _up(q_true)
    horiz = lambda b: b - (b @ v) * v  # noqa: E731
    np.testing.assert_allclose(horiz(res.bias_rad_s), horiz(bias), atol=2e-4)


def test_equals_qncf_when_the_amd_gate_never_closes():
    rng = np.random.default_rng(3)
    n, dt = 400, 1e-3
    acc = np.tile([0.5, -0.3, G], (2, n, 1)) + rng.normal(0, 1e-3, (2, n, 3))
    gyr = rng.normal(0, 1e-3, (2, n, 3))
    q0 = rotations.quat_from_euler_zxy(0.0, 0.01, -0.02)
    a = mahony_imu(gyr, acc, dt, MahonyParams(2.0, 0.1), q0=q0).q_ws
    b = qncf(gyr, acc, dt, QncfParams(kp_rad_s=2.0, ki_rad_s2=0.1, amd_threshold_pct=1e6), q0=q0,
             return_euler=False).q_ws
    assert np.max(rotations.quat_angle_between(a, b)) < 1e-9


def test_batch_rows_do_not_depend_on_the_batch():
    rng = np.random.default_rng(1)
    gyr = rng.normal(0, 0.01, (5, 300, 3))
    acc = rng.normal(0, 0.05, (5, 300, 3)) + [0, 0, G]
    whole = mahony_imu(gyr, acc, 0.01).q_ws
    part = mahony_imu(gyr[3:5], acc[3:5], 0.01).q_ws
    single = mahony_imu(gyr[4], acc[4], 0.01).q_ws
    assert whole[3:5].tobytes() == part.tobytes()
    assert whole[4].tobytes() == single.tobytes()
    assert single.shape == (300, 4)


def test_params_checked_when_made():
    with pytest.raises(ValueError, match="kp_rad_s"):
        MahonyParams(kp_rad_s=-1.0)


def test_records_checked_at_the_filter_family_edge():
    """mahony_imu trusts its inputs; run_attitude_filter("mahony") checks them once (moved, same messages)."""
    from mtcal.filters.anchors import run_attitude_filter

    g = np.zeros((1, 10, 3))
    a = np.tile([0, 0, G], (1, 10, 1))
    with pytest.raises(ValueError, match="same shape"):
        run_attitude_filter("mahony", g, a[:, :5], 0.01)
    with pytest.raises(ValueError, match="dt_s"):
        run_attitude_filter("mahony", g, a, 0.0)
    with pytest.raises(ValueError, match="rad/s"):
        run_attitude_filter("mahony", g + 100.0, a, 0.01)
    with pytest.raises(ValueError, match="q0"):
        run_attitude_filter("mahony", g, a, 0.01, q0=[1.0, 0, 0])
    with pytest.raises(ValueError, match="gyro_rad_s"):
        run_attitude_filter("mahony", np.full((1, 10, 3), np.nan), a, 0.01)


def test_one_function_the_registry_runner_calls():
    """No checked twin: the bake-off's mahony runner is mahony_imu itself (same bits), with documented preconditions."""
    from mtcal.filters import mahony
    from mtcal.filters.anchors import levelled_start, run_attitude_filter

    assert not [n for n in vars(mahony) if n.endswith("_trusted")] and "Preconditions" in mahony_imu.__doc__
    rng = np.random.default_rng(11)
    w = rng.normal(0, 0.2, (3, 400, 3))
    a = np.tile([0.3, -0.2, 9.8], (3, 400, 1)) + rng.normal(0, 0.05, (3, 400, 3))
    q0 = levelled_start(a, 100)
    direct = mahony_imu(w, a, 0.01, MahonyParams(1.5, 1.5 / 50.0), q0=q0).q_ws
    assert direct.tobytes() == run_attitude_filter("mahony", w, a, 0.01, 1.5).tobytes()


def test_lane_blocks_are_bit_identical_to_the_scalar_kernel():
    """SIMD lanes (blocks of 4, a short block repeating its last trial, a lone last trial) give every
    trial the scalar recursion's bits: moving and resting lanes mixed, a zero accelerometer sample."""
    from mtcal.filters._kernels_mahony import mahony_batch, mahony_trial

    rng = np.random.default_rng(7)
    trials, n = 9, 400
    gyr = rng.normal(0, 0.01, (trials, n, 3)) + 0.5 * np.sin(np.linspace(0, 9, n))[None, :, None] * (
        np.arange(trials) % 2)[:, None, None]          # odd trials move (sin branch), even ones rest (series)
    acc = rng.normal(0, 0.3, (trials, n, 3)) + [0, 0, G]
    acc[2, 50] = 0.0
    q0 = rng.normal(size=(trials, 4))
    q0 /= np.linalg.norm(q0, axis=1, keepdims=True)
    q_b, b_b = np.empty((trials, n, 4)), np.empty((trials, 3))
    mahony_batch(gyr, acc, q0, 0.005, 2.0, 0.04, q_b, b_b)
    q_s, b_s = np.empty((trials, n, 4)), np.empty((trials, 3))
    for t in range(trials):
        mahony_trial(gyr, acc, q0, 0.005, 2.0, 0.04, q_s, b_s, t)
    assert q_b.tobytes() == q_s.tobytes() and b_b.tobytes() == b_s.tobytes()


def test_recycled_history_never_touches_a_held_result(monkeypatch):
    """The batch's attitude history is recycled only once the caller has dropped it; results equal."""
    import weakref

    from mtcal.filters import _kernels_common, mahony

    monkeypatch.setattr(mahony, "_POOL", _kernels_common.OutputPool(min_bytes=0))
    rng = np.random.default_rng(2)
    gyr = rng.normal(0, 0.01, (3, 200, 3))
    acc = rng.normal(0, 0.05, (3, 200, 3)) + [0, 0, G]
    first = mahony_imu(gyr, acc, 0.01).q_ws
    kept = first.copy()
    second = mahony_imu(gyr[:, ::-1], acc[:, ::-1], 0.01).q_ws       # other data while the first is held
    assert np.array_equal(first, kept) and not np.shares_memory(first, second)
    pooled = weakref.ref(second)
    del second
    third = mahony_imu(gyr, acc, 0.01).q_ws
    assert pooled() is third and third.tobytes() == kept.tobytes()
