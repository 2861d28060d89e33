"""Bake-off adapters: each library's units, quaternion order, frame and timing give mtcal's attitude."""

import importlib.util

import numpy as np
import pytest

from mtcal.core import rotations
from mtcal.core.simulate import Trajectory, simulate_imu
from mtcal.filters import registry
from mtcal.filters.anchors import (available_filters, reference_difference, reference_runs, require_filter,
                                   run_attitude_filter, run_axis_angle_filter, tilt_error_rad, twist_angle_rad)
from mtcal.filters.registry import AxisContext, filter_names, get_filter

G = 9.80665
_LIBS = {"madgwick": "ahrs", "vqf": "vqf", "fusion": "imufusion"}


def _installed(name):
    lib = _LIBS.get(name)
    return lib is None or importlib.util.find_spec(lib) is not None


FILTERS = [pytest.param(n, marks=pytest.mark.skipif(not _installed(n), reason=f"optional {_LIBS.get(n)} missing"))
           for n in filter_names(output="attitude")]


def _up(q):
    q0, q1, q2, q3 = q
    return np.array([2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), q0**2 - q1**2 - q2**2 + q3**2])


@pytest.mark.parametrize("name", FILTERS)
def test_static_tilted_record_gives_the_right_tilt(name):
    # 30 s at rest, pitch 10°, roll −30° (wang2023cja Eq 9 angles), small noise
    rng = np.random.default_rng(0)
    q_true = rotations.quat_from_euler_zxy(np.radians(20.0), np.radians(10.0), np.radians(-30.0))
    n, dt = 3000, 0.01
    acc = np.tile(G * _up(q_true), (2, n, 1)) + rng.normal(0, 2e-3, (2, n, 3))
    gyr = rng.normal(0, 1e-4, (2, n, 3))
    q = run_attitude_filter(name, gyr, acc, dt)
    assert q.shape == (2, n, 4)
    np.testing.assert_allclose(np.linalg.norm(q, axis=-1), 1.0, atol=1e-6)
    assert np.degrees(tilt_error_rad(q[:, -1], q_true)).max() < 0.05
    pitch_roll = np.degrees(rotations.euler_zxy_from_quat(q[:, -1])[:, 1:])
    np.testing.assert_allclose(pitch_roll, [[10.0, -30.0]] * 2, atol=0.05)


@pytest.mark.parametrize("name", FILTERS)
def test_known_rotation_gives_the_right_quaternion(name):
    # 30 s at 30 °/s about a tilted axis: full attitude (incl. yaw) from q0 = truth at t0.
    # A wrong unit (°/s vs rad/s), quaternion order, frame or a one-sample timing shift
    # each gives errors of ≥ 0.3° here.
    fs, n = 100.0, 3000
    t = np.arange(n) / fs
    axis = np.array([0.6, 0.0, 0.8])
    q_true = rotations.quat_from_rotvec((np.radians(30.0) * t)[:, None] * axis)
    rec = simulate_imu(Trajectory(t, q_true))
    gyr = rec.gyro_rad_s[None] + 1e-9   # ahrs skips an update when the gyro is exactly zero
    q = run_attitude_filter(name, gyr, rec.accel_m_s2[None], 1 / fs, q0=q_true[0])
    err = np.degrees(rotations.quat_angle_between(q[0], q_true))
    assert err.max() < 0.1, f"{name}: max attitude error {err.max():.3f}°"


@pytest.mark.parametrize("name", FILTERS)
def test_gain_changes_the_answer_and_defaults_apply(name):
    rng = np.random.default_rng(2)
    q_true = rotations.quat_from_euler_zxy(0.0, np.radians(5.0), 0.0)
    acc = np.tile(G * _up(q_true), (1, 400, 1)) + rng.normal(0, 0.05, (1, 400, 3))
    gyr = rng.normal(0, 1e-3, (1, 400, 3))
    q_def = run_attitude_filter(name, gyr, acc, 0.01, q0=[1.0, 0, 0, 0])
    q_same = run_attitude_filter(name, gyr, acc, 0.01, get_filter(name).default_gain, q0=[1.0, 0, 0, 0])
    q_other = run_attitude_filter(name, gyr, acc, 0.01, 4 * get_filter(name).default_gain, q0=[1.0, 0, 0, 0])
    assert np.array_equal(q_def, q_same)
    assert not np.allclose(q_def, q_other)


def test_tilt_error_ignores_yaw_and_twist_angle_recovers_rotation():
    q = rotations.quat_from_euler_zxy(np.radians([0.0, 70.0]), np.radians([3.0, 3.0]), 0.0)
    assert np.degrees(tilt_error_rad(q[0], q[1])) < 1e-12
    assert abs(np.degrees(tilt_error_rad(q[0], rotations.quat_from_euler_zxy(0.0, np.radians(5.0), 0.0))) - 2) < 1e-9
    axis = np.array([0.1734, 0.9835, 0.0523])
    axis /= np.linalg.norm(axis)
    theta = np.radians(np.linspace(-170, 170, 35))
    q0 = rotations.quat_from_euler_zxy(0.2, 0.1, -0.3)
    qs = rotations.quat_multiply(q0, rotations.quat_from_rotvec(theta[:, None] * axis))
    np.testing.assert_allclose(twist_angle_rad(qs, axis, ref_index=17), theta - theta[17], atol=1e-12)


def test_axis_angle_of_an_attitude_filter_is_the_twist_of_its_attitude():
    rng = np.random.default_rng(4)
    axis = np.array([0.1734, 0.9835, 0.0523])
    t = np.arange(300) * 0.01
    theta = 0.8 * np.sin(t)
    q_ws = rotations.quat_from_rotvec(theta[:, None] * (axis / np.linalg.norm(axis)))
    rec = simulate_imu(Trajectory(t, q_ws))
    gyro = rec.gyro_rad_s[None] + rng.normal(0, 1e-3, (2, t.size, 3))
    accel = rec.accel_m_s2[None] + rng.normal(0, 1e-2, (2, t.size, 3))
    ctx = AxisContext(axis, np.zeros((2, t.size), bool), accel[:, 0], 1e-4, 1e-3)
    got = run_axis_angle_filter("mahony", gyro, accel, 0.01, 0.5, ctx, ref_index=20, init_samples=30)
    q = run_attitude_filter("mahony", gyro, accel, 0.01, 0.5, init_samples=30)
    assert np.array_equal(got, twist_angle_rad(q, axis, ref_index=20))   # the same operations, bit for bit
    assert got.shape == (2, t.size) and np.all(got[:, 20] == 0.0)


def test_available_and_errors(monkeypatch):
    assert {"qncf", "mahony"} <= set(available_filters())
    with pytest.raises(ValueError, match="filter must be one of"):
        run_attitude_filter("kalman", np.zeros((1, 5, 3)), np.ones((1, 5, 3)), 0.01)
    with pytest.raises(ValueError, match="same shape"):
        run_attitude_filter("mahony", np.zeros((1, 5, 3)), np.ones((1, 4, 3)), 0.01)
    with pytest.raises(ValueError, match="gain"):
        run_attitude_filter("mahony", np.zeros((1, 5, 3)), np.ones((1, 5, 3)) * G, 0.01, gain=-1.0)
    with pytest.raises(ValueError, match="q0"):
        run_attitude_filter("mahony", np.zeros((2, 5, 3)), np.ones((2, 5, 3)) * G, 0.01,
                            q0=np.tile([1.0, 0, 0, 0], (3, 1)))
    with pytest.raises(ValueError, match="gyro_rad_s"):
        run_attitude_filter("qncf", np.zeros((5, 3)), np.ones((5, 3)), 0.01)
    # a missing optional library gives a clear ImportError and drops out of available_filters
    real = registry.importlib.import_module

    def fake(name, *a, **k):
        if name == "vqf":
            raise ImportError("No module named 'vqf'")
        return real(name, *a, **k)

    monkeypatch.setattr(registry.importlib, "import_module", fake)
    with pytest.raises(ImportError, match="optional package 'vqf'"):
        require_filter("vqf")
    assert "vqf" not in available_filters()


needs_ahrs = pytest.mark.skipif(not _installed("madgwick"), reason="optional ahrs missing")


def _rotating_record(n=6000, fs=200.0, seed=4):
    rng = np.random.default_rng(seed)
    t = np.arange(n) / fs
    angle = np.radians(40.0) * np.sin(2 * np.pi * 0.3 * t)
    q_true = rotations.quat_from_rotvec(angle[:, None] * np.array([0.6, 0.0, 0.8]))
    rec = simulate_imu(Trajectory(t, q_true))
    gyr = rec.gyro_rad_s[None] + rng.normal(0, 2e-3, (1, n, 3))
    acc = rec.accel_m_s2[None] + rng.normal(0, 0.05, (1, n, 3))
    return gyr, acc, 1 / fs


@needs_ahrs
def test_compiled_madgwick_equals_ahrs_through_the_adapter():
    # the bake-off's Madgwick runs mtcal's compiled loop; ahrs' own (delayed inputs, q0 renormalised) is its reference
    gyr, acc, dt = _rotating_record()
    entry = get_filter("madgwick")
    assert entry.origin == "anchor" and entry.requires == "ahrs" and entry.reference is not None
    for beta in (0.0033, 0.033, 0.33):
        assert reference_difference("madgwick", gyr, acc, dt, beta) < 1e-12
    q = run_attitude_filter("madgwick", gyr, acc, dt)
    ref = run_attitude_filter("madgwick", gyr, acc, dt, reference=True)
    assert not np.array_equal(q, run_attitude_filter("mahony", gyr, acc, dt))
    np.testing.assert_allclose(q, ref, rtol=0, atol=1e-12)
    # ahrs holds q on an exactly zero rate sample; so does the compiled loop
    gyr0 = gyr.copy()
    gyr0[0, 1000:1400] = 0.0
    assert reference_difference("madgwick", gyr0, acc, dt) < 1e-12
    q0 = run_attitude_filter("madgwick", gyr0, acc, dt)
    assert np.array_equal(q0[0, 1001:1401], np.repeat(q0[0, 1001:1002], 400, axis=0))


@needs_ahrs
def test_reference_runs_swaps_in_the_library_and_restores():
    gyr, acc, dt = _rotating_record(n=800)
    compiled = get_filter("madgwick").run
    with reference_runs("madgwick"):
        assert get_filter("madgwick").run is get_filter("madgwick").reference
        inside = run_attitude_filter("madgwick", gyr, acc, dt)
    assert get_filter("madgwick").run is compiled
    assert np.array_equal(inside, run_attitude_filter("madgwick", gyr, acc, dt, reference=True))
    with pytest.raises(RuntimeError, match="boom"):
        with reference_runs("madgwick"):
            raise RuntimeError("boom")
    assert get_filter("madgwick").run is compiled
    assert filter_names(output="attitude") == ["qncf", "mahony", "madgwick", "vqf", "fusion"]


def test_reference_is_refused_for_a_filter_without_one():
    gyr, acc, dt = _rotating_record(n=300)
    with pytest.raises(ValueError, match="'qncf' has no reference runner"):
        run_attitude_filter("qncf", gyr, acc, dt, reference=True)
    with pytest.raises(ValueError, match=r"filters without a reference runner: \['qncf'\]"):
        with reference_runs("qncf"):
            pass


@pytest.mark.parametrize("name", FILTERS)
def test_units_are_checked_once_at_the_edge_for_every_filter(name):
    """run_attitude_filter checks units for every filter (the runners trust their inputs)."""
    acc = np.tile([0.0, 0.0, G], (1, 50, 1))
    with pytest.raises(ValueError, match=r"gyro_rad_s must be in rad/s"):
        run_attitude_filter(name, np.full((1, 50, 3), 100.0), acc, 0.01)       # deg/s passed as rad/s
    with pytest.raises(ValueError, match=r"accel_m_s2 looks like it is in g"):
        run_attitude_filter(name, np.zeros((1, 50, 3)), acc / G, 0.01)


@pytest.mark.parametrize("name", ["qncf", "mahony", "madgwick"])
def test_steps_below_the_edge_equal_the_checked_runs(name):
    """attitude_filter / axis_angle_filter (the trusting steps: a caller's own records, the start computed
    once) give run_attitude_filter's / run_axis_angle_filter's bits; no *_trusted twin is left."""
    if name not in available_filters():
        pytest.skip(f"{name} not installed")
    from mtcal.filters import anchors
    from mtcal.filters.anchors import attitude_filter, axis_angle_filter, levelled_start

    assert not [n for n in vars(anchors) if n.endswith("_trusted")]
    assert "Preconditions" in attitude_filter.__doc__ and "Preconditions" in axis_angle_filter.__doc__

    rng = np.random.default_rng(8)
    gyr = rng.normal(0, 0.02, (3, 200, 3))
    acc = rng.normal(0, 0.2, (3, 200, 3)) + [0, 0, G]
    q_init = levelled_start(acc, 30)
    checked = run_attitude_filter(name, gyr, acc, 0.01, 0.7, init_samples=30)
    assert attitude_filter(name, gyr, acc, 0.01, 0.7, q_init).tobytes() == checked.tobytes()
    axis = np.array([0.0, 0.6, 0.8])
    ctx = AxisContext(axis, np.zeros((3, 200), bool), acc[:, 0], 1e-4, 1e-3)
    got = axis_angle_filter(name, gyr, acc, 0.01, 0.7, ctx, 20, q_init)
    assert got.tobytes() == run_axis_angle_filter(name, gyr, acc, 0.01, 0.7, ctx, ref_index=20,
                                                  init_samples=30).tobytes()
