"""Tests for mtcal.methods.gyro_roll (tan2022 Eq 5, 11-14, Fig 7) and the gyro scenarios."""

import numpy as np
import pytest

from mtcal.methods import gyro_roll
from mtcal.studies.tan2022.scenario import GyroErrors, Oscillation, ProjectionSweep, UniformRotation

D = np.radians
FS = 200.0
DT = 1.0 / FS


def constant_rate_gyro(rate_deg_s, roll_deg, n, error_deg_s=(0.0, 0.0, 0.0)):
    w = gyro_roll.body_rates_two_dof(D(rate_deg_s), D(roll_deg))
    return np.broadcast_to(w + D(np.array(error_deg_s)), (n, 3)).copy()


# ---------------------------------------------------------------- kinematics / simulator mapping
def test_body_rates_closed_form():
    w = gyro_roll.body_rates_two_dof(0.5, D(30.0), 0.1)
    np.testing.assert_allclose(w, [0.1, 0.5 * np.cos(D(30)), -0.5 * np.sin(D(30))])


def test_simulator_mapping_reproduces_eq2_and_eq11():
    t = np.arange(0, 2.0, DT)
    theta = D(40.0) * np.sin(np.pi * t)
    phi = D(20.0) + D(5.0) * t
    rec = gyro_roll.simulate_two_dof_imu(t, theta, phi)
    f = rec.accel_true_m_s2 / 9.80665
    np.testing.assert_allclose(f, np.stack([-np.sin(theta), np.cos(theta) * np.sin(phi),
                                            np.cos(theta) * np.cos(phi)], -1), atol=1e-12)
    # gyro sample k = mean rate over [t_k, t_k+1] ≈ Eq 11 at the interval midpoint
    tm = t + 0.5 * DT
    w_mid = gyro_roll.body_rates_two_dof(D(40.0) * np.pi * np.cos(np.pi * tm), D(20.0) + D(5.0) * tm, D(5.0))
    np.testing.assert_allclose(rec.gyro_true_rad_s[:-1], w_mid[:-1], atol=2e-4)


# ---------------------------------------------------------------- estimators, error-free
def test_estimators_exact_without_errors():
    n = 400
    w = constant_rate_gyro(20.0, 25.0, n)
    np.testing.assert_allclose(gyro_roll.roll_projection(w), D(25.0), atol=1e-12)
    np.testing.assert_allclose(gyro_roll.roll_decoupled_integration(w, DT, roll0=D(25.0)), D(25.0), atol=1e-12)
    h, use = gyro_roll.roll_hybrid(w, DT, D(0.5), roll0=0.0)
    assert use.all()
    np.testing.assert_allclose(h, D(25.0), atol=1e-12)


def test_projection_sign_of_pitch_rate_irrelevant():
    for rate in (-30.0, 30.0):
        np.testing.assert_allclose(gyro_roll.roll_projection(constant_rate_gyro(rate, -40.0, 3)), D(-40.0), atol=1e-12)


def test_decoupled_integration_drifts_linearly():
    n = 1000
    w = constant_rate_gyro(10.0, 0.0, n, error_deg_s=(0.2, 0.2, 0.2))
    phi = gyro_roll.roll_decoupled_integration(w, DT)
    np.testing.assert_allclose(phi, D(0.2) * DT * np.arange(n), atol=1e-12)


# ---------------------------------------------------------------- Eq 14
def test_eq14_first_order_and_inverse_rate():
    rates = D(np.geomspace(5, 200, 12))
    exact = gyro_roll.projection_roll_error_exact(0.0, rates, D(0.2), D(0.2))
    first = gyro_roll.projection_roll_error_eq14(0.0, rates, D(0.2), D(0.2))
    # at φ = 0: Δφ = −Δω_z/θ̇
    np.testing.assert_allclose(first, -D(0.2) / rates)
    # first order: relative gap ~ Δω_y/θ̇
    assert np.max(np.abs(exact - first) / np.abs(first)) < 0.05
    assert gyro_roll.loglog_slope(rates, exact) == pytest.approx(-1.0, abs=0.02)


def test_projection_error_inverse_rate_in_simulation(rng):
    rates_deg = np.array([5.0, 10.0, 20.0, 40.0, 80.0])
    err = []
    for r in rates_deg:
        t = np.arange(0, 1.0, DT)
        rec = gyro_roll.simulate_two_dof_imu(t, D(r) * t, np.zeros_like(t), gyro_bias_rad_s=D(0.2),
                                             gyro_noise_density=D(0.0025), rng=rng, trials=20)
        err.append(np.mean(gyro_roll.roll_projection(rec.gyro_rad_s)))
    assert gyro_roll.loglog_slope(rates_deg, np.array(err)) == pytest.approx(-1.0, abs=0.05)


# ---------------------------------------------------------------- hybrid
def test_hybrid_picks_branch_by_threshold():
    # below threshold at samples 3..6: integration from the last projection value
    n = 10
    rates = np.array([10, 10, 10, 0.1, 0.1, 0.1, 0.1, 10, 10, 10.0])
    w = np.stack([np.full(n, D(1.0)), D(rates) * np.cos(D(5.0)), -D(rates) * np.sin(D(5.0))], -1)
    phi, use = gyro_roll.roll_hybrid(w, DT, D(0.5))
    np.testing.assert_array_equal(use, rates > 0.5)
    proj = gyro_roll.roll_projection(w)
    np.testing.assert_allclose(phi[use], proj[use])
    # k = 3..6: φ_P(2) + (k − 2) ω_x Δt
    np.testing.assert_allclose(phi[3:7], proj[2] + D(1.0) * DT * np.arange(1, 5), atol=1e-15)


def test_hybrid_starts_from_roll0_and_limits():
    w = constant_rate_gyro(0.1, 0.0, 5, error_deg_s=(0.2, 0.0, 0.0))
    phi, use = gyro_roll.roll_hybrid(w, DT, D(0.5), roll0=D(3.0))
    assert not use.any()
    np.testing.assert_allclose(phi, D(3.0) + D(0.2) * DT * np.arange(5))
    # threshold 0 → pure projection; threshold above every rate → pure integration (Eq 12)
    w = constant_rate_gyro(10.0, 10.0, 50, error_deg_s=(0.2, 0.2, 0.2))
    np.testing.assert_allclose(gyro_roll.roll_hybrid(w, DT, 0.0)[0], gyro_roll.roll_projection(w))
    np.testing.assert_allclose(gyro_roll.roll_hybrid(w, DT, D(100.0))[0], gyro_roll.roll_decoupled_integration(w, DT))


def test_hybrid_vectorised_over_trials(rng):
    w = constant_rate_gyro(3.0, 10.0, 100)[None] + D(0.5) * rng.standard_normal((4, 100, 3))
    phi, use = gyro_roll.roll_hybrid(w, DT, D(2.0))
    for k in range(4):
        p1, u1 = gyro_roll.roll_hybrid(w[k], DT, D(2.0))
        np.testing.assert_allclose(phi[k], p1)
        np.testing.assert_array_equal(use[k], u1)


def test_hybrid_beats_projection_in_oscillation(rng):
    sc = Oscillation(duration_s=4.0)
    t = sc.time_s()[::5]
    rec = gyro_roll.simulate_two_dof_imu(t, sc.pitch_rad(t), np.zeros_like(t), gyro_bias_rad_s=sc.gyro.error_rad_s,
                                         gyro_noise_density=sc.gyro.noise_density_rad_s_rthz, rng=rng, trials=5)
    dt = t[1] - t[0]
    proj = gyro_roll.roll_projection(rec.gyro_rad_s)
    hyb, _ = gyro_roll.roll_hybrid(rec.gyro_rad_s, dt, D(20.0))
    assert np.sqrt(np.mean(hyb**2)) < 0.5 * np.sqrt(np.mean(proj**2))


# ---------------------------------------------------------------- Eq 5 singularity
def test_euler_differential_exact_without_errors_and_blows_up_with_them():
    n = int(FS * 12.0)  # 10 °/s from 0° to 120°
    clean = constant_rate_gyro(10.0, 0.0, n)
    eul = gyro_roll.euler_differential(clean, DT)
    np.testing.assert_allclose(eul[:, 2], 0.0, atol=1e-12)
    np.testing.assert_allclose(eul[:, 1], D(10.0) * DT * np.arange(n), atol=1e-9)
    bad = constant_rate_gyro(10.0, 0.0, n, error_deg_s=(0.2, 0.2, 0.2))
    eul = gyro_roll.euler_differential(bad, DT)
    theta_true = 10.0 * DT * np.arange(n)
    phi_err = np.degrees(np.abs(eul[:, 2]))
    far = phi_err[theta_true < 60].max()
    near = phi_err[np.abs(theta_true - 90) < 5].max()
    integ = np.degrees(np.abs(gyro_roll.roll_decoupled_integration(bad, DT))).max()
    assert far < 5.0 and near > 5 * far and integ < 3.0


def test_euler_differential_does_not_crash_on_exact_singularity():
    w = np.zeros((3, 3))
    w[:, 2] = 0.1  # ω_z ≠ 0 while cosθ = 0 exactly is impossible in float; force via pitch0
    out = gyro_roll.euler_differential(w, DT, pitch0=np.pi / 2)
    assert out.shape == (3, 3)
    assert np.isfinite(out[0]).all()


def test_euler_differential_vectorised(rng):
    w = constant_rate_gyro(30.0, 0.0, 300)[None] + D(0.3) * rng.standard_normal((3, 300, 3))
    out = gyro_roll.euler_differential(w, DT, pitch0=np.array([0.0, 0.1, -0.1]))
    np.testing.assert_allclose(out[1], gyro_roll.euler_differential(w[1], DT, pitch0=0.1))


# ---------------------------------------------------------------- bad input
def test_bad_input_raises():
    w = constant_rate_gyro(10.0, 0.0, 10)
    with pytest.raises(ValueError, match="gyro_rad_s.*degrees"):
        gyro_roll.roll_projection(np.degrees(w) * 10)
    with pytest.raises(ValueError, match="gyro_rad_s"):
        gyro_roll.roll_projection(np.zeros((0, 3)))
    with pytest.raises(ValueError, match="gyro_rad_s"):
        gyro_roll.roll_decoupled_integration(np.full((4, 3), np.nan), DT)
    with pytest.raises(ValueError, match="gyro_rad_s"):
        gyro_roll.roll_projection(np.zeros(3))
    with pytest.raises(ValueError, match="dt_s"):
        gyro_roll.roll_decoupled_integration(w, 0.0)
    with pytest.raises(ValueError, match="threshold_rad_s"):
        gyro_roll.roll_hybrid(w, DT, -1.0)
    with pytest.raises(ValueError, match="threshold_rad_s.*degrees"):
        gyro_roll.roll_hybrid(w, DT, 50.0)
    with pytest.raises(ValueError, match="pitch0"):
        gyro_roll.euler_differential(w, DT, pitch0=D(95.0))
    with pytest.raises(ValueError, match="pitch_rate"):
        gyro_roll.projection_roll_error_eq14(0.0, 0.0, 0.1, 0.1)
    with pytest.raises(ValueError, match="pitch_rate.*degrees"):
        gyro_roll.body_rates_two_dof(60.0, 0.0)
    with pytest.raises(ValueError, match="roll.*degrees"):
        gyro_roll.body_rates_two_dof(1.0, 30.0)
    with pytest.raises(ValueError, match="x must be positive"):
        gyro_roll.loglog_slope([0.0, 1.0], [1.0, 2.0])
    with pytest.raises(ValueError, match="last axis must match"):
        gyro_roll.loglog_slope([1.0, 2.0, 3.0], np.ones((4, 2)))


def test_loglog_slope_per_row_matches_1d():
    x = np.array([1.0, 2.0, 5.0, 10.0])
    y = np.stack([3.0 * x**-1.0, -0.5 * x**-0.5, 2.0 * x**2])
    np.testing.assert_allclose(gyro_roll.loglog_slope(x, y), [-1.0, -0.5, 2.0], atol=1e-12)
    assert isinstance(gyro_roll.loglog_slope(x, y[0]), float)
    assert gyro_roll.loglog_slope(x, y[1]) == pytest.approx(-0.5, abs=1e-12)


def test_scenario_defaults_and_validation():
    sc = Oscillation()
    assert (sc.amplitude_deg, sc.freq_hz, sc.threshold_deg_s) == (40.0, 0.5, 0.5)
    assert sc.peak_rate_deg_s == pytest.approx(125.66, abs=0.01)
    assert GyroErrors().error_deg_s == (0.2, 0.2, 0.2)
    assert UniformRotation().pitch_rates_deg_s == (10.0, 20.0, 60.0)
    t, th = UniformRotation().profile(60.0)
    assert np.degrees(th[-1]) < 360.0 and t.size == 6000
    assert ProjectionSweep().rates_rad_s[0] == pytest.approx(D(0.5))
    with pytest.raises(ValueError, match="pitch_rates_deg_s"):
        UniformRotation(pitch_rates_deg_s=(10.0, -1.0))
    with pytest.raises(ValueError, match="error_deg_s"):
        GyroErrors(error_deg_s=(0.2, 0.2))
    with pytest.raises(ValueError, match="amplitude_deg"):
        Oscillation(amplitude_deg=95.0)
    with pytest.raises(ValueError, match="fs_hz"):
        GyroErrors(fs_hz=0.0)


def test_hybrid_rmse_sweep_matches_roll_hybrid():
    rng = np.random.default_rng(5)
    t = np.arange(0.0, 4.0, 1e-3)
    rate = np.radians(40.0) * np.pi * np.cos(np.pi * t)
    w = np.stack([np.zeros_like(t), rate, np.zeros_like(t)], -1) + np.radians(0.2) + 1e-3 * rng.standard_normal((3, t.size, 3))
    thr = np.radians([0.5, 5.0, 200.0])
    sweep = gyro_roll.roll_hybrid_rmse_sweep(w, 1e-3, thr, roll_true=0.0)
    direct = np.stack([np.sqrt(np.mean(gyro_roll.roll_hybrid(w, 1e-3, th)[0] ** 2, axis=-1)) for th in thr], -1)
    np.testing.assert_allclose(sweep, direct, rtol=1e-12)
    with pytest.raises(ValueError, match="thresholds_rad_s must be in rad/s"):
        gyro_roll.roll_hybrid_rmse_sweep(w, 1e-3, [-1.0])


# ---------------------------------------------------------------- compiled kernels vs the numpy references
def test_compiled_euler_matches_numpy_reference_bit_for_bit(rng):
    t = np.arange(0.0, 40.0, 0.01)  # one revolution at 10 °/s: through θ = ±90°, the angles wrap
    w = np.broadcast_to(gyro_roll.body_rates_two_dof(D(10.0), 0.0), (2, t.size, 3)) + D(0.5) * rng.standard_normal(
        (2, t.size, 3))
    fast = gyro_roll.euler_differential(w, 0.01, pitch0=np.array([0.0, 0.3]), roll0=0.1)
    ref = gyro_roll.euler_differential(w, 0.01, pitch0=np.array([0.0, 0.3]), roll0=0.1, engine="numpy")
    assert np.array_equal(fast, ref, equal_nan=True)
    assert np.nanmax(np.abs(fast[..., 2])) > 1.0  # the singularity was crossed (a jump), not a trivial run
    singular = np.zeros((3, 3))
    singular[:, 2] = 0.1
    assert np.array_equal(gyro_roll.euler_differential(singular, DT, pitch0=np.pi / 2),
                          gyro_roll.euler_differential(singular, DT, pitch0=np.pi / 2, engine="numpy"), equal_nan=True)
    with pytest.raises(ValueError, match="engine must be one of"):
        gyro_roll.euler_differential(singular, DT, engine="fortran")


def test_compiled_projection_matches_numpy_expression(rng):
    w = 0.3 * rng.standard_normal((4, 20_000, 3))
    w[0, :10, 1] = 0.0
    w[0, 10:20, 1] = -0.0
    wy, wz = w[..., 1], w[..., 2]
    assert w.size >= gyro_roll._KERNEL_MIN_SIZE  # the compiled path is the one under test
    assert np.array_equal(gyro_roll.roll_projection(w), np.arctan2(-wz * np.where(wy < 0.0, -1.0, 1.0), np.abs(wy)))


def test_compiled_hybrid_sweep_matches_numpy_reference(rng):
    t = np.arange(0.0, 4.0, 1e-3)
    rate = np.radians(40.0) * np.pi * np.cos(np.pi * t)
    w = np.stack([np.zeros_like(t), rate, np.zeros_like(t)], -1) + np.radians(0.2) + 1e-3 * rng.standard_normal(
        (2, 3, t.size, 3))
    thr = np.radians([0.0, 0.5, 5.0, 200.0])
    truth = np.full(t.size, 0.01)
    fast = gyro_roll.roll_hybrid_rmse_sweep(w, 1e-3, thr, roll_true=truth, roll0=0.02)
    ref = gyro_roll.roll_hybrid_rmse_sweep(w, 1e-3, thr, roll_true=truth, roll0=0.02, engine="numpy")
    assert fast.shape == (2, 3, 4)
    np.testing.assert_allclose(fast, ref, rtol=1e-12)
    perm = [3, 0, 2, 1, 0]  # any order, repeats: each threshold's RMSE is the same number
    assert np.array_equal(gyro_roll.roll_hybrid_rmse_sweep(w, 1e-3, thr[perm], roll_true=truth, roll0=0.02),
                          fast[..., perm])
    with pytest.raises(ValueError, match="engine must be one of"):
        gyro_roll.roll_hybrid_rmse_sweep(w, 1e-3, thr, engine="gpu")


def test_projection_hybrid_max_errors_matches_the_estimators_and_stops_early(rng):
    t = np.arange(0.0, 4.0, 1e-3)
    rate = np.radians(40.0) * np.pi * np.cos(np.pi * t)
    w = np.stack([np.zeros_like(t), rate, np.zeros_like(t)], -1) + np.radians(0.2) + 1e-3 * rng.standard_normal(
        (5, t.size, 3))
    slow = np.abs(rate) < np.radians(5.0)
    spike, hyb, ok = gyro_roll.projection_hybrid_max_errors(w, 1e-3, np.radians(0.5), slow, roll0=0.0)
    e_p = np.abs(gyro_roll.roll_projection(w))
    np.testing.assert_allclose(spike, e_p[:, slow].max(-1) / e_p[:, ~slow].max(-1), rtol=1e-14)
    np.testing.assert_allclose(hyb, np.abs(gyro_roll.roll_hybrid(w, 1e-3, np.radians(0.5))[0]).max(-1), rtol=1e-14)
    assert ok.all()
    limit = float(np.median(hyb))  # some trials stay below it, some exceed it
    s2, h2, ok2 = gyro_roll.projection_hybrid_max_errors(w, 1e-3, np.radians(0.5), slow, stop_above_rad=limit)
    assert np.array_equal(ok2, hyb <= limit) and np.all(np.isnan(s2[~ok2])) and np.all(h2[~ok2] > limit)
    assert np.array_equal((s2 > 5) & (h2 < limit), (spike > 5) & (hyb < limit))  # the decision is unchanged
    with pytest.raises(ValueError, match="slow must be a boolean array"):
        gyro_roll.projection_hybrid_max_errors(w, 1e-3, 0.01, slow[:-1])
    with pytest.raises(ValueError, match="stop_above_rad must be > 0"):
        gyro_roll.projection_hybrid_max_errors(w, 1e-3, 0.01, slow, stop_above_rad=0.0)


def test_roll_estimates_equal_the_three_functions_bit_for_bit():
    rng = np.random.default_rng(5)
    t = np.arange(4000) * DT
    w = np.stack([np.full_like(t, D(0.2)), D(40.0) * np.cos(np.pi * t), np.full_like(t, D(0.2))], -1)
    w = w[None] + D(0.05) * rng.standard_normal((3, t.size, 3))      # (T, N, 3), long enough for the kernel
    roll0 = D(np.array([0.0, 3.0, -2.0]))
    p, i, h, use = gyro_roll.roll_estimates(w, DT, D(0.5), roll0=roll0)
    hyb, use_ref = gyro_roll.roll_hybrid(w, DT, D(0.5), roll0=roll0)
    assert np.array_equal(p, gyro_roll.roll_projection(w)) and np.array_equal(use, use_ref)
    assert np.array_equal(i, gyro_roll.roll_decoupled_integration(w, DT, roll0=roll0)) and np.array_equal(h, hyb)
    assert use.any() and not use.all()
    with pytest.raises(ValueError, match="threshold_rad_s must be in rad/s"):
        gyro_roll.roll_estimates(w, DT, 1e4)


def test_roll_error_summary_equals_the_estimators_reduced_bit_for_bit(rng):
    from mtcal.core.metrics import angle_difference

    t = np.arange(0.0, 40.0, 0.01)  # one revolution at 10 °/s: Eq 5 jumps at θ = ±90°
    w = np.broadcast_to(gyro_roll.body_rates_two_dof(D(10.0), 0.1), (3, t.size, 3)) + D(0.5) * rng.standard_normal(
        (3, t.size, 3))
    theta = D(10.0) * t
    masks = np.stack([np.degrees(theta) < 60, np.abs(np.degrees(theta) - 90) < 2])
    e_max, final, p_abs = gyro_roll.roll_error_summary(w, 0.01, masks, pitch0=0.0, roll0=0.1)
    e_E = angle_difference(gyro_roll.euler_differential(w, 0.01, pitch0=0.0, roll0=0.1)[..., 2], 0.1)
    assert e_max.shape == (2, 3) and final.shape == (3,) and p_abs.shape == (3, t.size)
    for j, mk in enumerate(masks):
        assert np.array_equal(e_max[j], np.max(np.abs(e_E[:, mk]), axis=1))
    assert np.array_equal(final, gyro_roll.roll_decoupled_integration(w, 0.01, roll0=0.1)[:, -1] - 0.1)
    assert np.array_equal(p_abs, np.abs(gyro_roll.roll_projection(w) - 0.1))
    singular = np.zeros((3, 3))  # NaN after cosθ = 0 exactly propagates as in np.max
    singular[:, 2] = 0.1
    e_nan, _, _ = gyro_roll.roll_error_summary(singular, DT, np.ones((1, 3), dtype=bool), pitch0=np.pi / 2)
    ref = np.max(np.abs(angle_difference(gyro_roll.euler_differential(singular, DT, pitch0=np.pi / 2)[..., 2], 0.0)))
    assert np.array_equal(e_nan[0], ref, equal_nan=True)
    one, _, _ = gyro_roll.roll_error_summary(w[0, :1], 0.01, np.ones((1, 1), dtype=bool))
    assert one.shape == (1,)
    with pytest.raises(ValueError, match="masks must be a boolean array"):
        gyro_roll.roll_error_summary(w, 0.01, masks[:, :-1])
    with pytest.raises(ValueError, match="masks must be a boolean array"):
        gyro_roll.roll_error_summary(w, 0.01, np.zeros((1, t.size), dtype=bool))


def test_projection_hybrid_max_errors_noisy_equals_the_record_bit_for_bit(rng):
    t = np.arange(0.0, 4.0, 1e-3)
    base = np.stack([np.zeros_like(t), np.radians(40.0) * np.pi * np.cos(np.pi * t), -0.0 * t], -1)
    z = rng.standard_normal((4, t.size, 3))
    z[0, :5] = 0.0
    slow = np.abs(base[:, 1]) < np.radians(5.0)
    scale, offset = np.array([0.0, 1e-4, 1e-3, 2e-3]), np.radians([0.2, 0.0, 0.1, 0.3])
    for kw, w in (({}, base + scale[:, None, None] * z),
                  ({"offset_rad_s": offset}, (base + offset[:, None, None]) + scale[:, None, None] * z)):
        for stop in (np.inf, 0.05):
            got = gyro_roll.projection_hybrid_max_errors_noisy(base, scale, z, 1e-3, np.radians(0.5), slow,
                                                               roll0=0.01, stop_above_rad=stop, **kw)
            ref = gyro_roll.projection_hybrid_max_errors(w, 1e-3, np.radians(0.5), slow, roll0=0.01,
                                                         stop_above_rad=stop)
            assert all(np.array_equal(a, b, equal_nan=True) for a, b in zip(got, ref))
    with pytest.raises(ValueError, match="normals must be a float64 array"):
        gyro_roll.projection_hybrid_max_errors_noisy(base, 1e-3, z[:, :-1], 1e-3, 0.01, slow)
    with pytest.raises(ValueError, match="base_rad_s must have shape"):
        gyro_roll.projection_hybrid_max_errors_noisy(base[None], 1e-3, z, 1e-3, 0.01, slow)
    with pytest.raises(ValueError, match="noise_scale_rad_s must be in rad/s"):
        gyro_roll.projection_hybrid_max_errors_noisy(base, -1.0, z, 1e-3, 0.01, slow)
    with pytest.raises(ValueError, match="slow must be a boolean array"):
        gyro_roll.projection_hybrid_max_errors_noisy(base, 1e-3, z, 1e-3, 0.01, slow[:-1])
