import numpy as np
import pytest

from mtcal.core import profiles


def test_step_schedule_visits_waypoints_and_holds():
    wp = np.radians([[0.0, 0.0], [10.0, -5.0], [10.0, 20.0]])
    prof = profiles.step_schedule(wp, np.radians(5.0), hold_s=[1.0, 2.0, 1.5], fs_hz=100.0)
    holds = prof.hold_slices()
    assert len(holds) == 3
    for sl, target, dur in zip(holds, wp, [1.0, 2.0, 1.5]):
        np.testing.assert_allclose(prof.angle_rad[sl], np.broadcast_to(target, prof.angle_rad[sl].shape))
        assert (sl.stop - sl.start) / 100.0 == pytest.approx(dur, abs=0.011)
        assert np.all(prof.rate_rad_s[sl] == 0) and np.all(prof.is_static[sl])
    # move 1 lasts max|Δ| / rate = 10° / 5°/s = 2 s
    assert np.sum(prof.segment == 1) / 100.0 == pytest.approx(2.0, abs=0.011)


def test_step_schedule_derivatives_are_consistent():
    wp = np.radians([0.0, 30.0, -20.0])
    prof = profiles.step_schedule(wp, np.radians(20.0), 0.5, 1000.0)
    dt = 1e-3
    num_rate = np.gradient(prof.angle_rad[:, 0], dt)
    np.testing.assert_allclose(num_rate, prof.rate_rad_s[:, 0], atol=2e-4)
    num_acc = np.gradient(prof.rate_rad_s[:, 0], dt)
    np.testing.assert_allclose(num_acc[2:-2], prof.accel_rad_s2[2:-2, 0], atol=0.02)
    assert np.max(np.abs(prof.rate_rad_s)) == pytest.approx(1.875 * np.radians(20.0), rel=1e-3)


def test_sinusoid_and_constant_rate():
    prof = profiles.sinusoid(np.radians(40), 0.5, 4.0, 100.0)
    assert prof.angle_rad.shape == (400, 1)
    np.testing.assert_allclose(prof.rate_rad_s[0, 0], np.radians(40) * np.pi)
    cr = profiles.constant_rate(np.radians(-90), np.radians(90), np.radians(10), 100.0)
    assert cr.angle_rad[-1, 0] == pytest.approx(np.radians(90))
    assert np.all(cr.rate_rad_s == np.radians(10))


def test_trajectory_from_euler_requires_three_channels():
    prof = profiles.sinusoid(0.1, 1.0, 1.0, 100.0)
    with pytest.raises(ValueError, match="3 channels"):
        profiles.trajectory_from_euler_zxy(prof)


@pytest.mark.parametrize("kwargs,match", [
    (dict(waypoints_rad=[0.0, 1.0], rate_rad_s=0.0, hold_s=1.0, fs_hz=100.0), "rate_rad_s must be > 0"),
    (dict(waypoints_rad=[0.0, np.nan], rate_rad_s=1.0, hold_s=1.0, fs_hz=100.0), "finite"),
    (dict(waypoints_rad=[0.0, 1.0], rate_rad_s=1.0, hold_s=-1.0, fs_hz=100.0), "hold_s must be > 0"),
    (dict(waypoints_rad=[0.0, 1.0], rate_rad_s=1.0, hold_s=1.0, fs_hz=-5.0), "fs_hz must be > 0"),
])
def test_step_schedule_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        profiles.step_schedule(**kwargs)


def test_fixed_axis_bad_axis():
    prof = profiles.sinusoid(0.1, 1.0, 1.0, 100.0)
    with pytest.raises(ValueError, match="unit vector"):
        profiles.fixed_axis_trajectory(prof, [1.0, 1.0, 0.0])


def test_fixed_axis_imu_truth_matches_the_trajectory_form():
    """The batched truth (ω = Δθ/Δt v, f = R(θ, v)ᵀ ā0 + lever-arm terms) and the attitude-trajectory form
    (simulate_imu differentiates the attitude) describe the same rotation."""
    from mtcal.core.simulate import simulate_imu

    prof = profiles.step_schedule(np.radians([0.0, 50.0, -20.0]), np.radians(40.0), 0.5, 400.0)
    v = np.array([0.48, 0.6, 0.64])
    r = np.array([0.2, -0.1, 0.05])
    ideal = simulate_imu(profiles.fixed_axis_trajectory(prof, v, lever_arm_b_m=r))
    w, f = profiles.fixed_axis_imu_truth(prof.angle_rad.T, prof.rate_rad_s.T, prof.accel_rad_s2.T, [v], [r],
                                         ideal.accel_true_m_s2[0], 1 / 400.0)
    np.testing.assert_allclose(f[0], ideal.accel_true_m_s2, atol=1e-9)
    np.testing.assert_allclose(w[0, :-1], ideal.gyro_true_rad_s[:-1], atol=1e-9)


def test_fixed_axis_imu_truth_closed_form_lever_arm():
    th = np.array([[0.0, 0.0, 0.0]])
    w, f = profiles.fixed_axis_imu_truth(th, [[2.0, 2.0, 2.0]], [[3.0, 3.0, 3.0]], [[0.0, 0.0, 1.0]],
                                         [[0.5, 0.0, 0.0]], [0.0, 0.0, 9.8], 0.01)
    # centripetal −ω² r = −2 m/s² along x, tangential θ̈ (v × r) = 1.5 m/s² along y, gravity on z
    np.testing.assert_allclose(f[0], np.tile([-2.0, 1.5, 9.8], (3, 1)), atol=1e-12)
    np.testing.assert_allclose(profiles.lever_arm_accel_b([2.0], [3.0], [0, 0, 1.0], [0.5, 0, 0]), [[-2.0, 1.5, 0.0]])
    assert np.all(w == 0)


@pytest.mark.parametrize("kwargs,match", [
    (dict(axes_b=[[1.0, 1.0, 0.0]]), "axes_b must be unit vectors"),
    (dict(axes_b=[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]), "must be \\(T, N\\)"),
    (dict(dt_s=0.0), "dt_s must be > 0"),
    (dict(theta_rad=[0.0, 1.0]), "theta_rad"),
])
def test_fixed_axis_imu_truth_bad_input(kwargs, match):
    args = dict(theta_rad=[[0.0, 1.0]], rate_rad_s=[[0.0, 0.0]], accel_rad_s2=[[0.0, 0.0]], axes_b=[[1.0, 0.0, 0.0]],
                lever_arms_b_m=[[0.0, 0.0, 0.0]], accel0_m_s2=[0.0, 0.0, 9.8], dt_s=0.01)
    with pytest.raises(ValueError, match=match):
        profiles.fixed_axis_imu_truth(**{**args, **kwargs})


def test_join_profiles_puts_parts_end_to_end_with_distinct_segments():
    a = profiles.step_schedule(np.radians([[0.0, 0.0], [10.0, 0.0]]), np.radians(20.0), 1.0, 100.0)
    b = profiles.step_schedule(np.radians([[0.0, 0.0], [0.0, -5.0], [0.0, 0.0]]), np.radians(20.0), 0.5, 100.0)
    prof, spans = profiles.join_profiles([a, b, a])
    assert [(s.start, s.stop) for s in spans] == [(0, a.time_s.size), (a.time_s.size, a.time_s.size + b.time_s.size),
                                                  (a.time_s.size + b.time_s.size, prof.time_s.size)]
    assert np.array_equal(prof.time_s, np.arange(prof.time_s.size) * (1.0 / a.fs_hz))
    for part, span in zip((a, b, a), spans):
        for k in ("angle_rad", "rate_rad_s", "accel_rad_s2", "is_static"):
            assert np.array_equal(getattr(prof, k)[span], getattr(part, k))
        assert np.array_equal(prof.segment[span] % 2, part.segment % 2)       # holds stay even, moves odd
    assert len(prof.hold_slices()) == 2 + 3 + 2                                # every hold stays distinct
    with pytest.raises(TypeError, match="parts must be a non-empty sequence of AngleProfile"):
        profiles.join_profiles([])
    with pytest.raises(TypeError, match="parts must be a non-empty sequence of AngleProfile"):
        profiles.join_profiles([a, np.zeros(3)])
