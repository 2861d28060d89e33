"""Tests for mtcal.methods.large_angle (tan2022 Eq 2-4, 6-10) and the accelerometer scenario."""

import numpy as np
import pytest

from mtcal.methods import large_angle
from mtcal.core import rotations
from mtcal.studies.tan2022.scenario import AccelScenario

G = 9.80665
DA = 1e-4 * G


def interior_grid(step=3.0):
    th = np.radians(np.arange(-87.0, 87.0 + 1e-9, step))
    ph = np.radians(np.arange(-90.0, 90.0 + 1e-9, step))
    return np.meshgrid(th, ph, indexing="ij")


# ---------------------------------------------------------------- closed forms
def test_eq2_round_trip():
    th, ph = interior_grid()
    est = large_angle.pitch_roll_eq2(rotations.specific_force_zyx(th, ph, G))
    np.testing.assert_allclose(est[..., 0], th, atol=1e-12)
    np.testing.assert_allclose(est[..., 1], ph, atol=1e-12)


def test_level_values():
    # θ = 0: Δθ = −ΔA/g whatever φ or λ (sinθ kills the second term)
    for lam in (0.0, large_angle.LAMBDA1_RAD, large_angle.LAMBDA2_RAD):
        np.testing.assert_allclose(large_angle.pitch_error_eq8(0.0, np.radians([-60, 0, 45, 90]), DA, preset_rad=lam),
                                   -1e-4, rtol=1e-12)
    # θ = 0, φ = 0: Eq 4 gives ΔA/g; printed Eq 3 gives −ΔA/g (1 + 1) = −2e-4
    assert large_angle.roll_error_eq4(0.0, 0.0, DA) == pytest.approx(1e-4)
    assert large_angle.pitch_error_eq3_printed(0.0, 0.0, DA) == pytest.approx(-2e-4)


def test_phi_zero_values():
    th = np.radians(30.0)
    # corrected Eq 3 at φ = 0: −ΔA/g (cosθ + sinθ)
    assert large_angle.pitch_error_eq8(th, 0.0, DA) == pytest.approx(-1e-4 * (np.cos(th) + np.sin(th)))
    # Eq 4 at φ = 0: ΔA / (g cosθ)
    assert large_angle.roll_error_eq4(th, 0.0, DA) == pytest.approx(1e-4 / np.cos(th))


def test_eq8_is_common_mode_of_general_formula():
    th, ph = interior_grid()
    for lam in (0.0, 0.3, large_angle.LAMBDA2_RAD):
        np.testing.assert_allclose(large_angle.pitch_error_first_order(th, ph, DA, preset_rad=lam),
                                   large_angle.pitch_error_eq8(th, ph, DA, preset_rad=lam), atol=1e-18)
        vec = np.full(th.shape + (3,), DA)
        np.testing.assert_allclose(large_angle.pitch_error_first_order(th, ph, vec, preset_rad=lam),
                                   large_angle.pitch_error_eq8(th, ph, DA, preset_rad=lam), atol=1e-18)


def test_eq10_matches_paper_closed_form():
    th, ph = interior_grid()
    sgn = np.where(th <= 0, 1.0, -1.0)  # sin(φ ± 90°) = ±cosφ
    expected = -(DA / G) * (np.cos(th) + np.sqrt(2) * np.sin(th) * sgn * np.cos(ph))
    np.testing.assert_allclose(large_angle.pitch_error_eq10(th, ph, DA), expected, atol=1e-18)


def test_preset_force_is_eq7_and_printed_eq6_flips_lambda():
    th, ph, lam = 0.3, 0.2, 0.5
    expected = G * np.array([-np.sin(th), np.cos(th) * np.sin(ph + lam), np.cos(th) * np.cos(ph + lam)])
    np.testing.assert_allclose(large_angle.preset_specific_force(th, ph, lam), expected, atol=1e-12)
    printed = large_angle.preset_matrix(lam, printed=True) @ rotations.specific_force_zyx(th, ph, G)
    np.testing.assert_allclose(printed[1], G * np.cos(th) * np.sin(ph - lam), atol=1e-12)
    m = large_angle.preset_matrix(np.array([0.1, 1.0]))
    np.testing.assert_allclose(m @ np.swapaxes(m, -1, -2), np.broadcast_to(np.eye(3), (2, 3, 3)), atol=1e-15)


def test_preset_triad_round_trip():
    th, ph = interior_grid()
    for lam in (large_angle.LAMBDA1_RAD, large_angle.LAMBDA2_RAD):
        est = large_angle.pitch_roll_from_preset_triad(large_angle.preset_specific_force(th, ph, lam), lam)
        np.testing.assert_allclose(est[..., 0], th, atol=1e-12)
        np.testing.assert_allclose(rotations.wrap_angle(est[..., 1] - ph), 0.0, atol=1e-12)


# ---------------------------------------------------------------- lambda selection
def test_lambda_selection_at_boundary():
    eps = 1e-9
    lam = large_angle.preset_lambda(np.array([-0.5, -eps, 0.0, eps, 0.5]))
    np.testing.assert_allclose(lam, np.radians([45, 45, 45, -135, -135]))
    # the choice at θ = 0 is immaterial: Eq 10 is continuous there
    ph = np.radians(np.linspace(-90, 90, 7))
    np.testing.assert_allclose(large_angle.pitch_error_eq10(-eps, ph, DA), large_angle.pitch_error_eq10(eps, ph, DA),
                               atol=1e-12)


def test_select_preset_pitch_uses_measured_sign():
    th = np.radians([-60.0, -1.0, 1.0, 60.0])
    ph = np.radians(20.0)
    f1 = large_angle.preset_specific_force(th, ph, large_angle.LAMBDA1_RAD)
    f2 = large_angle.preset_specific_force(th, ph, large_angle.LAMBDA2_RAD)
    pitch, use1 = large_angle.select_preset_pitch(f1, f2)
    np.testing.assert_array_equal(use1, [True, True, False, False])
    np.testing.assert_allclose(pitch, th, atol=1e-12)


def test_preset_reduces_common_mode_error_where_paper_says():
    sc = AccelScenario()
    th, ph = sc.grid_rad(2.0)
    plain = np.abs(large_angle.pitch_error_eq8(th, ph, sc.delta_accel_m_s2))
    preset = np.abs(large_angle.pitch_error_eq10(th, ph, sc.delta_accel_m_s2))
    assert np.max(plain) / 1e-4 == pytest.approx(np.sqrt(3), rel=1e-3)   # at θ = 54.7°, φ = 45°
    assert np.max(preset) / 1e-4 == pytest.approx(np.sqrt(2), rel=1e-6)  # at θ = ±90°, φ = 0
    assert np.mean(preset) < 0.75 * np.mean(plain)
    assert np.sqrt(np.mean(preset**2)) < 0.75 * np.sqrt(np.mean(plain**2))


# ---------------------------------------------------------------- formula vs perturbation
@pytest.mark.parametrize("lam", [0.0, large_angle.LAMBDA1_RAD, large_angle.LAMBDA2_RAD])
def test_perturbation_agrees_to_second_order(lam):
    th, ph = interior_grid()
    residual = []
    for scale in (1e-2, 1e-3, 1e-4):
        da = scale * G
        dth, dph = large_angle.perturbed_errors(th, ph, da, preset_rad=lam)
        r_th = np.max(np.abs(dth - large_angle.pitch_error_eq8(th, ph, da, preset_rad=lam)))
        residual.append(r_th)
        if lam == 0.0:
            r_ph = np.max(np.abs(dph - large_angle.roll_error_eq4(th, ph, da)))
            assert r_ph < 2e3 * scale**2 / np.cos(np.radians(87.0)) ** 2
    # residual shrinks quadratically: ×10 smaller ΔA → ×100 smaller residual
    assert residual[0] / residual[1] == pytest.approx(100, rel=0.05)
    assert residual[1] / residual[2] == pytest.approx(100, rel=0.05)


def test_printed_eq3_disagrees_with_perturbation():
    th, ph = interior_grid()
    dth, _ = large_angle.perturbed_errors(th, ph, DA)
    wrong = np.max(np.abs(dth - large_angle.pitch_error_eq3_printed(th, ph, DA)))
    right = np.max(np.abs(dth - large_angle.pitch_error_eq8(th, ph, DA)))
    assert wrong > 1e-4 and right < 1e-6


def test_two_triad_preset_perturbation_matches_eq10():
    th, ph = interior_grid()
    exact = large_angle.perturbed_preset_pitch_error(th, ph, DA, DA)
    np.testing.assert_allclose(exact, large_angle.pitch_error_eq10(th, ph, DA), atol=1e-6)


def test_independent_errors_remove_the_preset_gain(rng):
    th, ph = interior_grid(step=15.0)
    mc = large_angle.monte_carlo_pitch_errors(th, ph, DA, rng, 400)
    rms = {k: np.sqrt(np.mean(v**2)) / 1e-4 for k, v in mc.items()}
    # first-order variance is σ²/g² for any λ: no gain from the preset rotation
    assert rms["single"] == pytest.approx(1.0, rel=0.05)
    assert rms["preset"] == pytest.approx(1.0, rel=0.05)
    assert rms["mean_of_two"] == pytest.approx(1 / np.sqrt(2), rel=0.05)
    assert mc["single"].shape == (400,) + th.shape


# ---------------------------------------------------------------- bad input
def test_pitch_beyond_90_raises():
    with pytest.raises(ValueError, match="pitch"):
        large_angle.pitch_error_eq8(np.radians(91.0), 0.0, DA)
    with pytest.raises(ValueError, match="pitch"):
        large_angle.preset_lambda(2.0)


def test_degrees_as_radians_raise():
    with pytest.raises(ValueError, match="roll.*degrees"):
        large_angle.pitch_error_eq8(0.1, 45.0, DA)
    with pytest.raises(ValueError, match="preset_rad"):
        large_angle.preset_matrix(-135.0)


def test_nan_and_empty_raise():
    with pytest.raises(ValueError, match="pitch"):
        large_angle.roll_error_eq4(np.nan, 0.0, DA)
    with pytest.raises(ValueError, match="delta_accel_m_s2"):
        large_angle.pitch_error_eq8(0.1, 0.1, np.nan)
    with pytest.raises(ValueError, match="accel"):
        large_angle.pitch_roll_eq2(np.zeros((0, 3)))
    with pytest.raises(ValueError, match="accel"):
        large_angle.pitch_roll_eq2([1.0, 2.0])
    with pytest.raises(ValueError, match="zero vector"):
        large_angle.pitch_roll_eq2([0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="g must be"):
        large_angle.pitch_error_eq8(0.1, 0.1, DA, g=-1.0)


def test_monte_carlo_bad_input(rng):
    with pytest.raises(ValueError, match="sigma_m_s2"):
        large_angle.monte_carlo_pitch_errors(0.1, 0.1, 0.0, rng, 10)
    with pytest.raises(TypeError, match="rng"):
        large_angle.monte_carlo_pitch_errors(0.1, 0.1, DA, 1, 10)


def test_accel_scenario_defaults_and_validation():
    sc = AccelScenario()
    assert sc.delta_accel_m_s2 == pytest.approx(9.80665e-4)
    assert (sc.lambda1_deg, sc.lambda2_deg) == (45.0, -135.0)
    th, ph = sc.grid_rad()
    assert th.shape == (181, 181) and th[0, 0] == pytest.approx(-np.pi / 2)
    with pytest.raises(ValueError, match="delta_accel_g"):
        AccelScenario(delta_accel_g=9.8e-4 * 1000)
    with pytest.raises(ValueError, match="grid_step_deg"):
        AccelScenario(grid_step_deg=0.0)


# ---------------------------------------------------------------- static-bias grid RMS from moments
def test_rms_from_moments_matches_direct_grid():
    th, ph = interior_grid(10.0)
    rng = np.random.default_rng(3)
    bias = DA * (1 + rng.standard_normal((4, 3)))
    lam = np.radians(30.0)
    direct = np.sqrt(np.mean(large_angle.pitch_error_first_order(th[None], ph[None], bias[:, None, None, :],
                                                                 preset_rad=lam) ** 2, axis=(1, 2)))
    from_m = large_angle.rms_pitch_error_from_moments(large_angle.bias_moment_matrix(th, ph), bias, lam)
    np.testing.assert_allclose(from_m, direct, rtol=1e-12)


def test_rms_optimal_preset_angles_are_eq9_for_common_mode():
    th, ph = np.meshgrid(np.radians(np.arange(-90.0, 90.1, 5.0)), np.radians(np.arange(-90.0, 90.1, 5.0)),
                         indexing="ij")
    lam = np.radians(np.arange(-180.0, 180.0, 1.0))
    for half, expect in ((th <= 0, 45.0), (th > 0, -135.0)):
        m = large_angle.bias_moment_matrix(th[half], ph[half])
        rms = large_angle.rms_pitch_error_from_moments(m, np.full(3, DA), lam)
        assert np.degrees(lam[np.argmin(rms)]) == pytest.approx(expect)


def test_custom_preset_angles_propagate():
    th, ph = np.radians(60.0), np.radians(10.0)
    default = large_angle.pitch_error_eq10(th, ph, DA)
    other = large_angle.pitch_error_eq10(th, ph, DA, lambda2_rad=np.radians(-90.0))
    assert other != pytest.approx(default)
    np.testing.assert_allclose(large_angle.perturbed_preset_pitch_error(th, ph, DA, DA, lambda2_rad=np.radians(-90.0)),
                               other, atol=1e-7)


def test_moment_errors():
    with pytest.raises(ValueError, match="moments must have shape"):
        large_angle.rms_pitch_error_from_moments(np.eye(2), np.ones(3), 0.0)
    with pytest.raises(ValueError, match="bias_m_s2"):
        large_angle.rms_pitch_error_from_moments(np.eye(3), np.ones(2), 0.0)
    with pytest.raises(ValueError, match="pitch"):
        large_angle.bias_moment_matrix(np.radians(100.0), 0.0)


def test_max_abs_pitch_error_first_order_equals_the_error_array_reduced():
    rng = np.random.default_rng(3)
    th = np.radians(rng.uniform(-90.0, 90.0, 500))
    ph = np.radians(rng.uniform(-180.0, 180.0, 500))
    d = 1e-3 * rng.standard_normal((40, 3))
    lam = np.where(th <= 0, np.radians(45.0), np.radians(-135.0))
    for kw in ({}, {"preset_rad": 0.7}, {"preset_rad": lam}, {"preset_rad": lam, "g": 9.7}):
        ref = np.max(np.abs(large_angle.pitch_error_first_order(th, ph, d[:, None, :], **kw)), axis=1)
        assert np.array_equal(large_angle.max_abs_pitch_error_first_order(th, ph, d, **kw), ref)
    with pytest.raises(ValueError, match="pitch must not be empty"):
        large_angle.max_abs_pitch_error_first_order(th[:0], ph[:0], d)
    with pytest.raises(ValueError, match="pitch must be 1-D with at least one attitude"):
        large_angle.max_abs_pitch_error_first_order(th[None, :], ph, d)
    with pytest.raises(ValueError, match="delta_accel_m_s2 must have"):
        large_angle.max_abs_pitch_error_first_order(th, ph, d[:, :2])
    with pytest.raises(ValueError, match="must broadcast to"):
        large_angle.max_abs_pitch_error_first_order(th, ph[None, :], d)
