"""Tests of the RAMS EKF (wang2022sensors Sec. 3.3): reference vs fast, tracking, Fig. 9 effect."""

import numpy as np
import pytest

from mtcal.core import metrics, profiles, simulate
from mtcal.core.sensor_grades import sensor_grade
from mtcal.filters.rams_ekf import (RamsEkfFilter, RamsEkfParams, RamsEkfReference, initial_state,
                                    measurement_model, run_rams_ekf)

#: wang2022sensors Table 3 IMU at 200 Hz (core sensor grade), the Fig. 11 axis, a flap-like lever arm.
FS_HZ = 200.0
DT_S = 1.0 / FS_HZ
GRADE = sensor_grade("wang2022sensors")
AXIS = np.array([0.1734, 0.9835, 0.0523]) / np.linalg.norm([0.1734, 0.9835, 0.0523])
_CHORD = np.cross(AXIS, [0.0, 0.0, 1.0]) / np.linalg.norm(np.cross(AXIS, [0.0, 0.0, 1.0]))
LEVER_M = 0.2 * _CHORD + np.array([0.0, 0.0, 0.02])
PARAMS = RamsEkfParams(sigma_theta_rad_s=GRADE.gyro_noise_density_rad_s_rt_hz * np.sqrt(FS_HZ),
                       sigma_b_rad_s2=1e-7 / np.sqrt(DT_S),
                       sigma_a_static_m_s2=GRADE.accel_noise_density_m_s2_rt_hz * np.sqrt(FS_HZ),
                       sigma_a_moving_m_s2=5.0, p0_theta_rad2=1e-8, p0_bias_rad2_s2=np.radians(0.01) ** 2)


class _Record:
    def __init__(self, theta_rad, gyro_rad_s, accel_m_s2):
        self.theta_rad, self.gyro_rad_s, self.accel_m_s2 = theta_rad, gyro_rad_s, accel_m_s2


def _fig9_record(rng, trials=2):
    """Fig. 9-like record (rest, 40° move, rest) from the core truth and sensor models, (T, N, 3)."""
    prof = profiles.step_schedule(np.radians([0.0, 40.0]), np.radians(40.0), 1.0, FS_HZ)
    th = np.broadcast_to(prof.angle_rad[:, 0], (trials, prof.time_s.size))
    w_true, f_true = profiles.fixed_axis_imu_truth(th, np.broadcast_to(prof.rate_rad_s[:, 0], th.shape),
                                                   np.broadcast_to(prof.accel_rad_s2[:, 0], th.shape),
                                                   np.tile(AXIS, (trials, 1)), np.tile(LEVER_M, (trials, 1)),
                                                   [0.0, 0.0, 9.80665], DT_S)
    model = GRADE.error_model()
    r_gyro, r_accel = rng.spawn(2)
    gyro = simulate.apply_sensor_errors(model.gyro, w_true, prof.time_s, r_gyro,
                                        time_since_power_on_s=model.time_since_power_on_s)
    accel = simulate.apply_sensor_errors(model.accel, f_true, prof.time_s, r_accel,
                                         time_since_power_on_s=model.time_since_power_on_s)
    return prof, _Record(np.ascontiguousarray(th), gyro, accel)


def test_measurement_jacobian_matches_finite_difference():
    v = np.array([0.1734, 0.9835, 0.0523]) / np.linalg.norm([0.1734, 0.9835, 0.0523])
    a0 = np.array([0.1, 0.2, 9.8])
    h, hp = measurement_model(0.7, v, a0)
    from mtcal.core.rotations import axis_angle_matrix
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
    v = AXIS
    a0, b0 = initial_state(rec.gyro_rad_s, rec.accel_m_s2, 150)
    p = PARAMS
    fast = run_rams_ekf(rec.gyro_rad_s, rec.accel_m_s2, prof.is_static, v, a0, DT_S, p, bias0_rad_s=b0)
    for t in range(2):
        ref = RamsEkfReference(v, a0[t], DT_S, p, bias0_rad_s=b0[t]).run(
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
    v = AXIS
    a0, b0 = initial_state(rec.gyro_rad_s, rec.accel_m_s2, 150)
    kw = dict(bias0_rad_s=b0, keep_innovation=False)
    with_zvd = run_rams_ekf(rec.gyro_rad_s, rec.accel_m_s2, prof.is_static, v, a0, DT_S,
                            PARAMS, **kw)
    without = run_rams_ekf(rec.gyro_rad_s, rec.accel_m_s2, prof.is_static, v, a0, DT_S,
                           PARAMS, use_zvd=False, **kw)
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
    # run_rams_ekf trusts its inputs (documented preconditions): the checked filter class refuses them
    with pytest.raises(ValueError, match="unit vector"):
        RamsEkfFilter([1.0, 1.0, 0.0], a[0], 0.01, p, trials=1)
    with pytest.raises(ValueError, match="same shape"):
        RamsEkfFilter([1.0, 0.0, 0.0], a[0], 0.01, p, trials=1).run(g[:5], a, np.ones(10, bool))
    with pytest.raises(TypeError, match="boolean"):
        run_rams_ekf(g, a, np.ones(10), [1.0, 0.0, 0.0], a[0], 0.01, p)
    with pytest.raises(ValueError, match="sigma_a_static"):
        RamsEkfParams(sigma_a_static_m_s2=-1.0)


# --------------------------------------------------------------------------- fast filter regression
_P_SYN = RamsEkfParams(sigma_theta_rad_s=2e-3, sigma_b_rad_s2=1e-4, sigma_a_static_m_s2=0.02,
                       sigma_a_moving_m_s2=1.0, p0_theta_rad2=1e-4, p0_bias_rad2_s2=1e-6)


def _synthetic_record():
    """3 trials with different axes and ā0: rest, 1 s sinusoidal move (lever-arm-like accel noise), rest."""
    rng = np.random.default_rng(404)
    n, dt = 400, 0.005
    t = np.arange(n) * dt
    axes = np.array([[0.0, 1.0, 0.0], [0.6, 0.8, 0.0], [0.1734, 0.9835, 0.0523]])
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    a0 = np.array([[0.05, -0.1, 9.80], [0.2, 0.1, 9.79], [-0.1, 0.3, 9.80]])
    moving = (t > 0.5) & (t < 1.5)
    rate = np.where(moving, 0.7 * np.sin(np.pi * (t - 0.5)), 0.0)
    theta = np.concatenate([[0.0], np.cumsum(rate[:-1]) * dt])
    gyro = rate[None, :, None] * axes[:, None, :] + np.array([1e-3, -2e-3, 5e-4]) \
        + 2e-3 * rng.standard_normal((3, n, 3))
    h, _ = measurement_model(theta[None, :], axes[:, None, :], a0[:, None, :])
    accel = h + 0.02 * rng.standard_normal((3, n, 3)) + moving[None, :, None] * 0.5 * rng.standard_normal((3, n, 3))
    return gyro, accel, ~moving, axes, a0, dt


def _run_synthetic(**kw):
    g, a, st, v, a0, dt = _synthetic_record()
    return run_rams_ekf(g, a, st, v, a0, dt, _P_SYN, theta0_rad=np.array([0.0, 0.01, -0.01]),
                        bias0_rad_s=np.zeros(3), **kw)


def test_fast_regression_literals():
    """Values computed with the earlier (T, 4, 4) implementation (commit 1bea4b9); the packed
    component-major version forms every sum in the same order, so they agree to the last bit."""
    r = _run_synthetic()
    np.testing.assert_allclose(r.theta_rad[:, -1], [0.4455126934232382, 0.4455690157124846, 0.44567271178411805],
                               rtol=0, atol=1e-15)
    np.testing.assert_allclose(r.theta_rad[:, 250], [0.3772517833014278, 0.3784884359774213, 0.37703462574026214],
                               rtol=0, atol=1e-15)
    np.testing.assert_allclose(r.bias_rad_s[:, -1], [[0.0, -1.8478818492063641e-03, 0.0],
                                                     [-4.8854105998174082e-04, -6.5138807997565384e-04, 0.0],
                                                     [-2.9722439928766322e-04, -1.6858142831569173e-03,
                                                      -8.9647266913176569e-05]], rtol=0, atol=1e-17)
    np.testing.assert_allclose(r.p_theta_rad2[:, -1], [5.8092515447965805e-08, 5.8198441398686551e-08,
                                                       5.8389813736043545e-08], rtol=1e-14, atol=0)
    np.testing.assert_allclose(r.P[0], [[5.8092515447965805e-08, 0.0, -3.5414504925713372e-08, 0.0],
                                        [0.0, 1.0000997500000238e-06, 0.0, 0.0],
                                        [-3.5414504925713372e-08, 0.0, 4.5021723550493633e-08, 0.0],
                                        [0.0, 0.0, 0.0, 1.0000997500000238e-06]], rtol=1e-14, atol=1e-22)
    np.testing.assert_allclose(r.innovation_m_s2[:, 100],
                               [[-0.00967361759569355, -0.01599977428968982, 0.03166989871600201],
                                [-0.00613141506874179, 0.01635001042559268, 0.03451477182742124],
                                [-0.01222098245019734, -0.01344423676414092, -0.00318077390053162]],
                               rtol=0, atol=1e-15)


def test_fast_agrees_with_reference_per_trial_axes():
    g, a, st, v, a0, dt = _synthetic_record()
    fast = _run_synthetic()
    for t in range(3):
        ref = RamsEkfReference(v[t], a0[t], dt, _P_SYN, theta0_rad=[0.0, 0.01, -0.01][t]).run(g[t], a[t], st)
        np.testing.assert_allclose(fast.theta_rad[t], ref.theta_rad, atol=1e-9, rtol=0)
        np.testing.assert_allclose(fast.bias_rad_s[t], ref.bias_rad_s, atol=1e-9, rtol=0)
        np.testing.assert_allclose(fast.P[t], ref.P, atol=1e-12, rtol=1e-9)
        np.testing.assert_allclose(fast.K[t], ref.K, atol=1e-12, rtol=1e-9)


@pytest.mark.parametrize("use_zvd", [True, False])
def test_filter_in_chunks_equals_whole_record(use_zvd):
    g, a, st, v, a0, dt = _synthetic_record()
    whole = _run_synthetic(use_zvd=use_zvd)
    filt = RamsEkfFilter(v, a0, dt, _P_SYN, trials=3, theta0_rad=np.array([0.0, 0.01, -0.01]),
                         bias0_rad_s=np.zeros(3), use_zvd=use_zvd)
    parts = [filt.run(g[:, i:j], a[:, i:j], st[i:j], chunk=ch)
             for i, j, ch in [(0, 1, 8), (1, 150, 64), (150, 400, 37)]]
    for name in ("theta_rad", "bias_rad_s", "p_theta_rad2", "innovation_m_s2"):
        assert np.array_equal(np.concatenate([getattr(r, name) for r in parts], axis=1), getattr(whole, name))
    for name in ("P", "S", "K"):
        assert np.array_equal(getattr(parts[-1], name), getattr(whole, name))
    assert np.array_equal(filt.P, whole.P) and np.array_equal(filt.theta_rad, whole.theta_rad[:, -1])
    assert np.array_equal(filt.bias_rad_s, whole.bias_rad_s[:, -1])
    with pytest.raises(ValueError, match="3 trials"):
        filt.run(g[:2, :5], a[:2, :5], st[:5])


def test_fast_does_not_mutate_inputs():
    g, a, st, v, a0, dt = _synthetic_record()
    g0, a0_copy = g.copy(), a.copy()
    run_rams_ekf(g, a, st, v, a0, dt, _P_SYN)
    assert np.array_equal(g, g0) and np.array_equal(a, a0_copy)


def test_recycled_outputs_never_touch_a_held_result(monkeypatch):
    """Output histories are recycled (no fresh pages) only once the caller has dropped them; results equal."""
    import weakref

    from mtcal.filters import _kernels_common, rams_ekf
    monkeypatch.setattr(_kernels_common, "RECYCLE_MIN_BYTES", 0)
    monkeypatch.setattr(rams_ekf, "_POOL", _kernels_common.OutputPool())
    g, a, st, v, a0, dt = _synthetic_record()
    names = ("theta_rad", "bias_rad_s", "p_theta_rad2", "innovation_m_s2")
    first = run_rams_ekf(g, a, st, v, a0, dt, _P_SYN)
    kept = {name: getattr(first, name).copy() for name in names}
    second = run_rams_ekf(g[:, ::-1], a[:, ::-1], st[::-1], v, a0, dt, _P_SYN)   # other data, first held
    for name in names:
        assert np.array_equal(getattr(first, name), kept[name])
        assert not np.shares_memory(getattr(first, name), getattr(second, name))
    pooled = {name: weakref.ref(getattr(second, name)) for name in names}
    del second
    third = run_rams_ekf(g, a, st, v, a0, dt, _P_SYN)
    for name in names:
        assert pooled[name]() is getattr(third, name)                          # the dropped arrays came back
        assert np.array_equal(getattr(third, name), kept[name])
        assert np.array_equal(getattr(first, name), kept[name])


def test_run_once_equals_the_checked_filter_bit_for_bit():
    """run_rams_ekf (trusting its inputs, RamsEkfFilter.trusted) gives the checked RamsEkfFilter's result exactly."""
    prof = profiles.step_schedule(np.radians([0.0, 50.0, -20.0]), np.radians(40.0), 1.0, 100.0)
    v = np.array([0.6, 0.0, 0.8])
    two = [np.tile(x.T, (2, 1)) for x in (prof.angle_rad, prof.rate_rad_s, prof.accel_rad_s2)]
    w, f = profiles.fixed_axis_imu_truth(*two, [v, v],
                                         [[0.0, 0, 0], [0.1, 0, 0]], [0.0, 0.0, 9.81], 0.01)
    rng = np.random.default_rng(3)
    w = w + 1e-3 * rng.standard_normal(w.shape)
    f = f + 1e-2 * rng.standard_normal(f.shape)
    a0 = f[:, :50].mean(axis=1)
    b0 = w[:, :50].mean(axis=1)
    for engine in ("numba", "numpy"):
        ref = RamsEkfFilter(v, a0, 0.01, RamsEkfParams(), trials=2, bias0_rad_s=b0, engine=engine).run(
            w, f, prof.is_static)
        got = run_rams_ekf(w, f, prof.is_static, v, a0, 0.01, RamsEkfParams(), bias0_rad_s=b0, engine=engine)
        assert np.array_equal(ref.theta_rad, got.theta_rad) and np.array_equal(ref.bias_rad_s, got.bias_rad_s)
        assert np.array_equal(ref.P, got.P)
    with pytest.raises(ValueError, match="unit vector"):
        RamsEkfFilter(2 * v, a0, 0.01, RamsEkfParams(), trials=2)   # the public constructor checks
    from mtcal.filters import rams_ekf

    assert not [n for n, fn in vars(rams_ekf).items()
                if n.endswith("_trusted") and getattr(fn, "__module__", "") == rams_ekf.__name__]
    for fn in (run_rams_ekf, rams_ekf.run_rams_ekf_restarts, rams_ekf.run_rams_ekf_batch_restarts):
        assert "Preconditions" in fn.__doc__, fn.__name__


def test_batch_restarts_entry_equals_one_run_and_the_per_record_restarts():
    from mtcal.filters.rams_ekf import run_rams_ekf_batch_restarts, run_rams_ekf_restarts
    from mtcal.core import profiles

    prof = profiles.step_schedule(np.radians([0.0, 60.0, 20.0]), np.radians(60.0), 1.0, 100.0)
    v = np.array([0.6, 0.0, 0.8])
    w, f = profiles.fixed_axis_imu_truth(np.tile(prof.angle_rad[:, 0], (2, 1)), np.tile(prof.rate_rad_s[:, 0], (2, 1)),
                                         np.tile(prof.accel_rad_s2[:, 0], (2, 1)), np.tile(v, (2, 1)),
                                         np.zeros((2, 3)), [0.0, 0.0, 9.81], 0.01)
    rng = np.random.default_rng(3)
    w = w + 1e-3 * rng.standard_normal(w.shape)
    static = np.broadcast_to(prof.is_static, w.shape[:2])
    a0, b0 = f[:, :50].mean(axis=1), w[:, :50].mean(axis=1)
    params = RamsEkfParams(sigma_theta_rad_s=1e-3, sigma_a_static_m_s2=0.01)
    n = w.shape[1]
    cut = prof.hold_slices()[1].start
    got = run_rams_ekf_batch_restarts(w, f, static, [[0, n], [0, cut, n]], v, a0, b0, 0.01, params, 0.1)
    one = run_rams_ekf(w, f, static, v, a0, 0.01, params, bias0_rad_s=b0, keep_innovation=False).theta_rad
    assert np.array_equal(got[0], one[0])
    assert np.array_equal(got[1], run_rams_ekf_restarts(w[1], f[1], static[1], [0, cut, n], v, a0[1], b0[1],
                                                                0.01, params, 0.1))
    assert not np.array_equal(got[1], one[1])
