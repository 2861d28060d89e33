"""Plausibility checks of a record (moved from the CLI): units/time base, clipping, gyro axis, integration."""

import numpy as np
import pytest

from mtcal.core import profiles, rotations
from mtcal.systems import plausibility

FS_HZ = 100.0
DT_S = 1.0 / FS_HZ
AXIS = np.array([0.6, 0.0, 0.8])


def _hinge(angles_deg=(0.0, 60.0, 120.0), rate_deg_s=60.0, hold_s=1.0):
    """Noise-free rotation about AXIS with holds: (gyro, accel, rests, profile)."""
    prof = profiles.step_schedule(np.radians(angles_deg), np.radians(rate_deg_s), hold_s, FS_HZ)
    w, f = profiles.fixed_axis_imu_truth(prof.angle_rad.T, prof.rate_rad_s.T, prof.accel_rad_s2.T, [AXIS],
                                         [[0.0, 0.0, 0.0]], [0.0, 0.0, 9.81], DT_S)
    return w[0], f[0], prof.hold_slices(), prof


def rotations_angle(a, b) -> float:
    return float(np.arctan2(np.linalg.norm(np.cross(a, b)), a @ b))


def test_cumulative_rotation_equals_the_sequential_product():
    rng = np.random.default_rng(0)
    gyro = rng.normal(0.0, 1.0, (37, 3))
    q = np.array([1.0, 0.0, 0.0, 0.0])
    for w in gyro:
        q = rotations.hamilton(q, rotations.quat_from_rotvec(w * DT_S))
    np.testing.assert_allclose(plausibility.cumulative_rotation(gyro, DT_S)[-1], q, atol=1e-14)


def test_cumulative_rotation_of_a_constant_rate_is_rate_times_time():
    gyro = np.tile([0.0, 0.0, np.radians(45.0)], (200, 1))          # 2 s at 45 deg/s = 90 deg
    q = plausibility.cumulative_rotation(gyro, DT_S)[-1]
    assert np.degrees(2 * np.arccos(q[0])) == pytest.approx(90.0, abs=1e-9)


def test_clipped_samples_finds_plateaus_only():
    gyro = np.zeros((50, 3))
    gyro[10:20, 1] = 2.0                       # 10-sample plateau at the peak
    gyro[30:32, 2] = -1.5                      # a 2-sample peak is not a plateau (min_run 3)
    mask, level = plausibility.clipped_samples(gyro)
    assert level == 2.0 and mask.sum() == 10 and mask[10:20].all()
    assert plausibility.clipped_samples(np.zeros((5, 3)))[1] == 0.0
    assert not plausibility.clipped_samples(gyro, min_run=11)[0].any()


def test_consistent_gyro_passes_with_ratio_one():
    gyro, accel, rests, _ = _hinge()
    out = plausibility.gyro_tilt_consistency(gyro, accel, DT_S, rests)
    # the accelerometer sees the 60 deg turn about an axis 53 deg above the horizon as a smaller tilt
    tilt = np.degrees(rotations_angle(accel[rests[0]].mean(axis=0), accel[rests[1]].mean(axis=0)))
    assert out["pairs"] == 2 and out["ratio"] == pytest.approx(60.0 / tilt, abs=1e-6) and out["worst_deg"] < 1e-6


@pytest.mark.parametrize("scale,match", [
    (180 / np.pi, "deg/s read as rad/s: use --gyro-unit deg/s"),
    (np.pi / 180, "rad/s read as deg/s: drop --gyro-unit deg/s"),
    (0.1, "10x too small: time column 10x too fast"),
    (2.0, "check gyro units, scale, axis order/signs"),
])
def test_inconsistent_gyro_is_refused_with_the_scale_that_fits(scale, match):
    gyro, accel, rests, prof = _hinge()
    with pytest.raises(ValueError, match=match):
        plausibility.gyro_tilt_consistency(gyro * scale, accel, DT_S, rests, time_s=prof.time_s)


def test_small_tilts_skipped_pairs_and_turning_rests_are_not_checked():
    gyro, accel, rests, _ = _hinge(angles_deg=(0.0, 2.0, 4.0))
    assert plausibility.gyro_tilt_consistency(gyro * 3.0, accel, DT_S, rests)["pairs"] == 0   # tilts < 5 deg
    gyro, accel, rests, _ = _hinge()
    skip = np.zeros(gyro.shape[0], bool)
    skip[rests[1].start] = True                                               # both pairs touch rest 1
    assert plausibility.gyro_tilt_consistency(gyro * 3.0, accel, DT_S, rests, skip=skip)["pairs"] == 0
    turning = [rests[0], slice(rests[0].stop, rests[1].start), rests[1], rests[2]]
    assert plausibility.gyro_tilt_consistency(gyro, accel, DT_S, turning)["pairs"] == 2  # the move is no rest


def test_rotation_axis_from_gyro_recovers_the_hinge():
    gyro, _, _, prof = _hinge()
    bias = np.array([0.01, -0.02, 0.005])
    u, share = plausibility.rotation_axis_from_gyro(gyro + bias, bias, ~prof.is_static)
    assert abs(u @ AXIS) == pytest.approx(1.0, abs=1e-12) and share == pytest.approx(1.0, abs=1e-12)
    u, share = plausibility.rotation_axis_from_gyro(gyro, np.zeros(3), np.zeros(gyro.shape[0], bool))
    assert u is None and np.isnan(share)


# -- check_units: no answer without a units check -------------------------------------------------------------

def test_check_units_rest_pairs_first():
    w, f, rests, _ = _hinge()
    res = plausibility.check_units(w, f, DT_S, rests)
    assert res["method"] == "rest pairs" and res["pairs"] >= 1
    with pytest.raises(ValueError, match="--gyro-unit deg/s"):
        plausibility.check_units(np.degrees(w), f, DT_S, rests)


def test_check_units_tilt_rate_without_rests():
    w, f, _, _ = _hinge(angles_deg=(0.0, 30.0, 10.0, 40.0), rate_deg_s=20.0, hold_s=0.3)
    res = plausibility.check_units(w, f, DT_S, [])
    assert res["method"] == "tilt rate"
    with pytest.raises(ValueError, match="--gyro-unit deg/s"):
        plausibility.check_units(np.degrees(w), f, DT_S, [])
    with pytest.raises(ValueError, match="10x too slow"):
        plausibility.check_units(w, f, 10 * DT_S, [])


def test_check_units_checks_the_skip_mask():
    """The skip mask is checked here, at the units edge (moved from the trusting tilt_rate_scale)."""
    w, f, _, _ = _hinge(angles_deg=(0.0, 30.0, 10.0, 40.0), rate_deg_s=20.0, hold_s=0.3)
    with pytest.raises(ValueError, match=f"skip must be a boolean array of {len(w)} samples"):
        plausibility.check_units(w, f, DT_S, [], skip=np.zeros(10, bool))


def test_check_units_no_rotation_and_refusal():
    f = np.tile([0.0, 0.0, 9.81], (1000, 1))
    assert plausibility.check_units(np.zeros((1000, 3)), f, DT_S, [])["method"] == "no rotation"
    rng = np.random.default_rng(3)
    shaken = f + rng.normal(0, 4.0, f.shape)          # no gravity reading to compare with
    w = np.zeros((1000, 3))
    w[200:800, 0] = 0.4                                # a tilt the accelerometer cannot confirm
    with pytest.raises(ValueError, match="(cannot check the gyro units|gyro implausible).*"):
        plausibility.check_units(w, shaken, DT_S, [])
    # the refusal guesses no unit the evidence does not support; a stated unit is used, with the evidence
    with pytest.raises(ValueError, match=r"state the unit with --gyro-unit \(rad/s, the default, or deg/s\)"):
        plausibility.check_units(w, shaken, DT_S, [])
    stated = plausibility.check_units(w, shaken, DT_S, [], unit_stated="--gyro-unit rad/s")
    assert stated["method"] == "stated unit (unchecked)" and "(--gyro-unit rad/s)" in stated["warning"]


def test_check_units_turn_about_gravity():
    f = np.tile([0.0, 0.0, 9.81], (3000, 1))
    w = np.zeros((3000, 3))
    w[1000:1500, 2] = np.radians(40.0)
    rests = [slice(0, 900), slice(1600, 3000)]
    assert plausibility.check_units(w, f, DT_S, rests)["method"] == "rotation about gravity"
    w[1000:1500, 2] = 40.0  # a 40 deg/s turn logged in deg/s
    with pytest.raises(ValueError, match="no centripetal acceleration.*--gyro-unit deg/s"):
        plausibility.check_units(w, f, DT_S, rests)


def test_check_units_clipped_full_scale_accepted():
    w, f, rests, _ = _hinge()
    skip = np.zeros(len(w), bool)
    skip[rests[0].stop:rests[1].start] = True          # every move clipped: no usable pair
    skip[rests[1].stop:rests[2].start] = True
    w = np.clip(w, -np.radians(50.0), np.radians(50.0))
    res = plausibility.check_units(w, f, DT_S, rests, skip=skip)
    assert res["method"] in ("full-scale plateau", "tilt rate", "gravity tracking")
