"""Tests for mtcal.scenarios000 (mapping, installation fit, budget plumbing, runners)."""

import numpy as np
import pytest

from mtcal import rotations, scenarios000 as s


def test_mount_quaternion_matches_eq1():
    a = np.radians([1.0, -2.0, 3.0])
    c_bs = rotations.installation_matrix(*a)
    assert np.allclose(rotations.quat_to_matrix(s.mount_quaternion(a)), c_bs.T, atol=1e-12)


def test_true_error_matrix_maps_sensor_to_body():
    a = np.radians([0.5, 0.2, -0.4])
    ref = np.radians([[8, 0, 0], [0, 23, 0], [0, 0, 90]])
    q_s = rotations.quat_from_euler_zxy(*s.predicted_before(a, ref).T)
    q_b = rotations.align_signs(q_s @ s.true_error_matrix(a).T)
    assert np.allclose(q_b, rotations.align_signs(rotations.quat_from_euler_zxy(*ref.T)), atol=1e-12)


@pytest.mark.parametrize("test", ["T1", "T2", "T3", "T4"])
def test_stored_alphas_are_the_fit(test):
    fit = s.fit_installation_angles(s.TABLES_1_TO_4[test])
    assert np.allclose(np.degrees(fit.alpha_rad), s.TurntableScenario().alpha_deg[test], atol=2e-4)
    assert fit.rms_deg < fit.raw_rms_deg


def test_handedness_flip_explains_tables_better():
    for table in s.TABLES_1_TO_4.values():
        proper = s.fit_installation_angles(table, sign=(1, 1, 1))
        flipped = s.fit_installation_angles(table)
        assert flipped.rms_deg < 0.4 * proper.rms_deg


def test_error_model_sources():
    spec = s.ImuSpec000()
    m = spec.error_model((1.0, 0, 0, 0), sources=["gyro_white"])
    assert m.gyro.noise_density > 0 and m.accel.noise_density == 0 and m.gyro.bias_sigma == 0
    assert m.time_since_power_on_s == 300.0
    with pytest.raises(ValueError, match="sources"):
        spec.error_model((1.0, 0, 0, 0), sources=["bogus"])
    df = s.describe(spec)
    assert (df["source"].str.len() > 0).all()


def test_turntable_noise_free_is_exact():
    sc = s.TurntableScenario()
    run = s.run_turntable(sc, "T2", np.random.default_rng(0), 1, sources=())
    assert np.abs(run.cal_after - run.reference).max() < 1e-8
    assert np.abs(run.q_matrix[0] - s.true_error_matrix(sc.alpha_rad("T2"))).max() < 1e-8


def test_turntable_with_errors_improves(rng):
    sc = s.TurntableScenario()
    run = s.run_turntable(sc, "T1", rng, 2)
    before = np.abs(run.cal_before - run.reference).max(axis=(1, 2))
    after = np.abs(run.cal_after - run.reference).max(axis=(1, 2))
    assert np.all(after < before) and np.all(after > 0)


def test_mechanism_backlash_depends_on_direction():
    sc = s.WindTunnelScenario()
    from mtcal.profiles import step_schedule
    prof = step_schedule(np.radians([[0, 0, 0], [0, 4, 0], [0, 0, 0]]), np.radians(2), 2.0, 100.0)
    act = s.mechanism_actual(sc, prof, np.radians(2))
    up = act[prof.segment == 2, 1].mean() - np.radians(4) * (1 + sc.pitch_ratio_error)
    down = act[prof.segment == 4, 1].mean()
    assert up < 0 < down
    assert np.isclose(down - up, sc.transmission_gap_rad + 2 * sc.servo_lag_s * np.radians(2))
