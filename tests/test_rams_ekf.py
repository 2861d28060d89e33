"""Tests of the RAMS EKF (seed 004 Sec. 3.3): reference vs fast, tracking, Fig. 9 effect."""

import numpy as np
import pytest

from mtcal import metrics, profiles
from mtcal.filters.rams_ekf import (RamsEkfParams, RamsEkfReference, initial_state,
                                    measurement_model, run_rams_ekf)
from mtcal.scenarios004 import Imu004, RotationSetup, simulate_rotation

IMU = Imu004()


def _fig9_record(rng, trials=2):
    prof = profiles.step_schedule(np.radians([0.0, 40.0]), np.radians(40.0), 1.0, IMU.fs_hz)
    th = np.broadcast_to(prof.angle_rad[:, 0], (trials, prof.time_s.size))
    rec = simulate_rotation(th, np.broadcast_to(prof.rate_rad_s[:, 0], th.shape),
                            np.broadcast_to(prof.accel_rad_s2[:, 0], th.shape), prof.is_static,
                            RotationSetup(), IMU.error_model(), IMU.fs_hz, rng)
    return prof, rec


def test_measurement_jacobian_matches_finite_difference():
    v = np.array([0.1734, 0.9835, 0.0523]) / np.linalg.norm([0.1734, 0.9835, 0.0523])
    a0 = np.array([0.1, 0.2, 9.8])
    h, hp = measurement_model(0.7, v, a0)
    from mtcal.rotations import axis_angle_matrix
    np.testing.assert_allclose(h, axis_angle_matrix(0.7, v).T @ a0, atol=1e-12)
    eps = 1e-6
    fd = (measurement_model(0.7 + eps, v, a0)[0] - measurement_model(0.7 - eps, v, a0)[0]) / (2 * eps)
    np.testing.assert_allclose(hp, fd, atol=1e-8)


def test_process_noise_is_eq26():
    p = RamsEkfParams(sigma_theta_rad_s=0.01, sigma_b_rad_s2=0.001)
    q = p.process_noise([0.6, 0.8, 0.0], 0.01)
    np.testing.assert_allclose(q, np.diag([1e-8, 1e-10, 1e-10, 1e-10]), atol=1e-20)


def test_reference_and_fast_agree(rng):
    prof, rec = _fig9_record(rng, trials=2)
    v = RotationSetup().unit_axis()
    a0, b0 = initial_state(rec.gyro_rad_s, rec.accel_m_s2, 150)
    p = IMU.ekf_params()
    fast = run_rams_ekf(rec.gyro_rad_s, rec.accel_m_s2, prof.is_static, v, a0, IMU.dt_s, p, bias0_rad_s=b0)
    for t in range(2):
        ref = RamsEkfReference(v, a0[t], IMU.dt_s, p, bias0_rad_s=b0[t]).run(
            rec.gyro_rad_s[t], rec.accel_m_s2[t], prof.is_static)
        np.testing.assert_allclose(fast.theta_rad[t], ref.theta_rad, atol=1e-9, rtol=0)
        np.testing.assert_allclose(fast.bias_rad_s[t], ref.bias_rad_s, atol=1e-9, rtol=0)
        np.testing.assert_allclose(fast.innovation_m_s2[t], ref.innovation_m_s2, atol=1e-9, rtol=0)
        np.testing.assert_allclose(fast.P[t], ref.P, atol=1e-12, rtol=1e-9)
        np.testing.assert_allclose(fast.S[t], ref.S, atol=1e-12, rtol=1e-9)
        np.testing.assert_allclose(fast.K[t], ref.K, atol=1e-12, rtol=1e-9)


def test_tracks_truth_with_zvd_and_degrades_without(rng):
    """Fig. 9: with the covariance switched by rest/motion the error stays small
    during motion; the always-static EKF reads the lever-arm acceleration as angle."""
    prof, rec = _fig9_record(rng, trials=3)
    v = RotationSetup().unit_axis()
    a0, b0 = initial_state(rec.gyro_rad_s, rec.accel_m_s2, 150)
    kw = dict(bias0_rad_s=b0, keep_innovation=False)
    with_zvd = run_rams_ekf(rec.gyro_rad_s, rec.accel_m_s2, prof.is_static, v, a0, IMU.dt_s,
                            IMU.ekf_params(), **kw)
    without = run_rams_ekf(rec.gyro_rad_s, rec.accel_m_s2, prof.is_static, v, a0, IMU.dt_s,
                           IMU.ekf_params(), use_zvd=False, **kw)
    moving = ~prof.is_static
    e1 = np.degrees(metrics.rmse(with_zvd.theta_rad - rec.theta_rad, mask=moving))
    e2 = np.degrees(metrics.rmse(without.theta_rad - rec.theta_rad, mask=moving))
    assert np.all(e1 < 0.05)
    assert np.all(e2 > 5 * e1)
    end = slice(-50, None)
    assert np.all(np.degrees(np.abs(with_zvd.theta_rad[:, end] - rec.theta_rad[:, end])) < 0.05)


def test_bad_inputs_raise():
    p = RamsEkfParams()
    g = np.zeros((10, 3))
    a = np.tile([0, 0, 9.8], (10, 1))
    with pytest.raises(ValueError, match="unit vector"):
        run_rams_ekf(g, a, np.ones(10, bool), [1.0, 1.0, 0.0], a[0], 0.01, p)
    with pytest.raises(ValueError, match="same shape"):
        run_rams_ekf(g[:5], a, np.ones(10, bool), [1.0, 0.0, 0.0], a[0], 0.01, p)
    with pytest.raises(TypeError, match="boolean"):
        run_rams_ekf(g, a, np.ones(10), [1.0, 0.0, 0.0], a[0], 0.01, p)
    with pytest.raises(ValueError, match="sigma_a_static"):
        RamsEkfParams(sigma_a_static_m_s2=-1.0)
