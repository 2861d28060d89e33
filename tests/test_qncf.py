"""Tests for mtcal.filters.qncf (seed 000 QNCF, Eq 5–8 + PI/AMD)."""

import numpy as np
import pytest

from mtcal import profiles, rotations, simulate
from mtcal.filters.qncf import QncfFilter, QncfParams, amd_statistic, initial_attitude_from_accel, qncf

FS = 1000.0


def _record(rng=None, model=None, trials=None):
    wp = np.radians([[0, 0, 0], [8, 0, 0], [0, 20, 0], [0, 0, 60]])
    prof = profiles.step_schedule(wp, np.radians(20), 1.0, FS)
    traj = profiles.trajectory_from_euler_zxy(prof)
    return simulate.simulate_imu(traj, model, rng=rng, trials=trials)


def test_zero_noise_tracks_truth():
    rec = _record()
    res = qncf(rec.gyro_rad_s, rec.accel_m_s2, 1 / FS)
    err = rotations.quat_angle_between(res.q_ws, rec.q_ws_true)
    assert err.max() < 1e-9
    assert np.allclose(res.euler_rad, rotations.euler_zxy_from_quat(rec.q_ws_true), atol=1e-9)
    assert res.gate.all()


def test_tilted_start_is_levelled_and_corrected():
    q_mount = rotations.quat_from_euler_zxy(0.0, np.radians(2.0), np.radians(-3.0))
    rec = _record(model=simulate.ImuErrorModel(q_mount=tuple(q_mount)))
    # start from a wrong attitude: the PI loop pulls pitch/roll back to gravity
    res = qncf(rec.gyro_rad_s, rec.accel_m_s2, 1 / FS, q0=[1.0, 0, 0, 0])
    e = rotations.euler_zxy_from_quat(res.q_ws) - rotations.euler_zxy_from_quat(rec.q_ws_true)
    assert abs(e[0, 1]) > np.radians(1.5)            # initially wrong by ~2 deg in pitch
    assert np.abs(e[3000:3500, 1:]).max() < np.radians(0.3)  # e^-3 after 3 s (Kp = 1/s)


def test_batch_equals_per_step(rng):
    model = simulate.ImuErrorModel(gyro=simulate.SensorErrors(noise_density=1e-4),
                                   accel=simulate.SensorErrors(noise_density=1e-3))
    rec = _record(rng, model, trials=3)
    g, a = rec.gyro_rad_s[:, :400], rec.accel_m_s2[:, :400]
    q0 = np.tile([1.0, 0, 0, 0], (3, 1))
    batch = qncf(g, a, 1 / FS, q0=q0)
    filt = QncfFilter(q0, 1 / FS)
    steps = [filt.update(g[:, k], a[:, k]) for k in range(g.shape[1])]
    assert np.allclose(np.stack(steps, axis=1)[:, :-1], batch.q_ws[:, 1:], atol=1e-14, rtol=0)
    # chunked run continues the state exactly
    f2 = QncfFilter(q0, 1 / FS)
    r1 = f2.run(g[:, :150], a[:, :150])
    r2 = f2.run(g[:, 150:], a[:, 150:], chunk=64)
    assert np.array_equal(np.concatenate([r1.q_ws, r2.q_ws], axis=1), batch.q_ws)


def test_does_not_mutate_inputs():
    rec = _record()
    g, a = rec.gyro_rad_s.copy(), rec.accel_m_s2.copy()
    qncf(g, a, 1 / FS)
    assert np.array_equal(g, rec.gyro_rad_s) and np.array_equal(a, rec.accel_m_s2)


def test_amd_gate_switches_off_accelerometer_under_vibration():
    t = np.arange(0, 4.0, 1 / FS)
    accel = np.tile([0.0, 0.0, 9.80665], (t.size, 1))
    vib = (t > 2.0)[:, None] * 3.0 * np.sin(2 * np.pi * 45 * t)[:, None] * np.array([1.0, 0.5, 1.0])
    accel_v = accel + vib
    gyro = np.zeros_like(accel)
    res = qncf(gyro, accel_v, 1 / FS, QncfParams(ki_rad_s2=0.0), q0=rotations.quat_from_euler_zxy(0.0, 0.01, 0.0))
    assert res.gate[: int(1.9 * FS)].all()
    assert not res.gate[int(2.5 * FS):].any()
    # gyro-only after the gate closes: attitude frozen (gyro zero, no integral term)
    assert np.allclose(res.q_ws[int(2.5 * FS)], res.q_ws[-1], atol=1e-12)
    amd = amd_statistic(accel_v, 1 / FS)
    assert np.allclose(amd, res.amd_pct)
    assert amd[int(3 * FS):].min() > 0.3 > amd[: int(1.9 * FS)].max()


def test_initial_attitude_from_accel_round_trip():
    q = rotations.quat_from_euler_zxy(0.0, 0.3, -1.2)
    f = rotations.quat_to_matrix(q).T @ np.array([0, 0, 9.81])
    assert np.allclose(initial_attitude_from_accel(f), q, atol=1e-12)


@pytest.mark.parametrize("bad, msg", [
    (np.full((10, 3), np.nan), "finite"),
    (np.zeros((10, 2)), "shape"),
])
def test_bad_inputs(bad, msg):
    with pytest.raises(ValueError, match=msg):
        qncf(bad, np.zeros((10, 3)) + 9.8, 1e-3)


def test_bad_params():
    with pytest.raises(ValueError, match="amd_threshold_pct"):
        QncfParams(amd_threshold_pct=0.0)
    with pytest.raises(ValueError, match="dt_s"):
        QncfFilter([1.0, 0, 0, 0], -1.0)
