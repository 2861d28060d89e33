"""Tests of mtcal.methods.zero_velocity (wang2022sensors ZVD, Table 1)."""

import numpy as np
import pytest

from mtcal.core import profiles
from mtcal.studies.wang2022sensors.runs import ImuSpec, RotationSetup, simulate_rotation
from mtcal.methods.zero_velocity import ZvdParams, detect_static, moving_variance, rest_intervals


def test_table1_defaults_match_paper_csv():
    from mtcal.studies.wang2022sensors.scenario import table1_zvd_params

    assert table1_zvd_params() == ZvdParams()


def test_moving_variance_matches_loop(rng):
    x = rng.normal(size=(2, 50)) + 9.8
    mv = moving_variance(x, 5)
    for k in (0, 3, 4, 30, 49):
        np.testing.assert_allclose(mv[:, k], np.var(x[:, max(0, k - 4):k + 1], axis=1), atol=1e-12)


def test_flags_exactly_the_rests_of_a_schedule(rng):
    """Rotation seen through a lever arm: flags equal the schedule except near transitions.

    Tolerance: within 0.15 s of a rest boundary (ZVD windows plus the quintic
    move's near-zero-acceleration ends, which ‖a‖ cannot tell from rest), and
    with the gyro condition on."""
    imu = ImuSpec()
    prof = profiles.step_schedule(np.radians([0, 40, -30, 20]), np.radians(40), 1.0, imu.fs_hz)
    rec = simulate_rotation(prof.angle_rad[:, 0], prof.rate_rad_s[:, 0], prof.accel_rad_s2[:, 0],
                            prof.is_static, RotationSetup(), imu.error_model(), imu.dt_s, 12345)
    b0 = rec.gyro_rad_s[0, :150].mean(axis=0)
    st = detect_static(rec.accel_m_s2[0], 1.0 / imu.fs_hz, ZvdParams(gyro_max_rad_s=np.radians(2.0)),
                       rec.gyro_rad_s[0] - b0)
    edges = np.flatnonzero(np.diff(prof.is_static.astype(int)))
    near = np.zeros_like(st)
    near[:5] = True  # causal windows: the first samples of a record are not yet flagged
    for e in edges:
        near[max(e - 30, 0):e + 30] = True
    assert np.array_equal(st[~near], prof.is_static[~near])
    assert len(rest_intervals(st)) == 4


def test_rejects_bad_params():
    with pytest.raises(ValueError, match="accel_min_m_s2"):
        ZvdParams(accel_min_m_s2=9.9)
    with pytest.raises(ValueError, match="gyro_rad_s is required"):
        detect_static(np.tile([0, 0, 9.8], (10, 1)), 0.01, ZvdParams(gyro_max_rad_s=0.1))


def test_vectorised_over_trials_equals_single(rng):
    a = np.array([0, 0, 9.80665]) + 0.01 * rng.normal(size=(3, 200, 3))
    a[:, 80:120] += 0.5
    both = detect_static(a, 0.005)
    for t in range(3):
        assert np.array_equal(both[t], detect_static(a[t], 0.005))


def test_detector_trusts_its_inputs_and_params_are_typed(rng):
    from mtcal.methods import zero_velocity
    from mtcal.methods.zero_velocity import zvd_params

    a = np.tile([0.1, 0.2, 9.80], (2, 600, 1)) + rng.normal(0, 0.01, (2, 600, 3))
    a[:, 200:300] += 2.0
    p = ZvdParams(gyro_max_rad_s=0.05)
    assert np.array_equal(detect_static(a, 0.01), detect_static(a, 0.01, ZvdParams()))   # Table 1 by default
    assert zvd_params(None) == ZvdParams() and zvd_params(p) is p
    with pytest.raises(TypeError, match="params must be a ZvdParams"):
        zvd_params({"window_s": 0.01})
    with pytest.raises(ValueError, match="gyro_rad_s is required"):
        detect_static(a, 0.01, p)
    assert not [n for n, f in vars(zero_velocity).items()
                if n.endswith("_trusted") and getattr(f, "__module__", "") == zero_velocity.__name__]
    assert "Preconditions" in detect_static.__doc__ and "Preconditions" in zero_velocity.rest_masks.__doc__


def _numpy_zvd(a, dt, p, gyro):
    """The numpy expression the compiled ZVD replaces (the reference order of every operation)."""
    from mtcal.methods.zero_velocity import STANDARD_GRAVITY_M_S2, _min_run, _moving_variance

    mag = np.linalg.norm(a, axis=-1)
    band = (mag > p.accel_min_m_s2) & (mag < p.accel_max_m_s2)
    cond = band & (_moving_variance(mag - STANDARD_GRAVITY_M_S2, p.window_samples(dt)) < p.var_threshold_m2_s4)
    if p.gyro_max_rad_s is not None:
        cond &= np.linalg.norm(gyro, axis=-1) < p.gyro_max_rad_s
    return _min_run(cond, p.duration_samples(dt))


@pytest.mark.parametrize("params", [ZvdParams(), ZvdParams(gyro_max_rad_s=0.035),
                                    ZvdParams(window_s=0.05, min_duration_s=0.03, var_threshold_m2_s4=1e-4)])
def test_compiled_detector_equals_the_numpy_expression_bit_for_bit(params, rng):
    """Near-threshold records (noise at the variance and band limits): every flag as numpy's, for the
    compiled pass (C-contiguous), the numpy path (other layouts) and the gyro offset (ω − b0)."""
    for sigma, n in ((0.001, 1), (0.01, 37), (0.03, 400), (0.1, 250)):
        a = np.array([0.0, 0.0, 9.80665]) + sigma * rng.normal(size=(4, n, 3))
        g = 0.02 * rng.normal(size=(4, n, 3))
        b0 = 0.01 * rng.normal(size=(4, 3))
        ref = _numpy_zvd(a, 0.005, params, g - b0[:, None, :])
        assert np.array_equal(detect_static(a, 0.005, params, g, gyro_offset_rad_s=b0), ref)
        assert np.array_equal(detect_static(a, 0.005, params, g - b0[:, None, :]), ref)
        assert np.array_equal(detect_static(a[1], 0.005, params, g[1] - b0[1]), ref[1])
        a_f, g_f = np.asfortranarray(a), np.asfortranarray(g)   # not C-contiguous: the numpy path
        assert np.array_equal(detect_static(a_f, 0.005, params, g_f, gyro_offset_rad_s=b0), ref)
