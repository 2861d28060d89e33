"""Tests for mtcal.methods.six_position (six-position procedure, wang2023cja §3.2, Eq 13–15)."""

import numpy as np
import pytest

from mtcal.methods import quaternion_lsq, six_position
from mtcal.core import rotations
from mtcal.studies import wang2023cja
from mtcal.filters.qncf import qncf
from mtcal.core.profiles import trajectory_from_euler_zxy
from mtcal.core.simulate import ImuErrorModel, simulate_imu

FS = 1000.0
DT_S = 1.0 / FS
ALPHA = np.radians([0.4, -0.3, 0.6])


@pytest.fixture(scope="module")
def noise_free():
    pos = six_position.six_positions_rad()
    prof = six_position.schedule_profile(pos, fs_hz=FS)
    rec = simulate_imu(trajectory_from_euler_zxy(prof),
                       ImuErrorModel(q_mount=tuple(rotations.mount_quaternion(ALPHA))))
    res = qncf(rec.gyro_rad_s, rec.accel_m_s2, 1 / FS, return_euler=False)
    q_s = rotations.relative_to_initial(res.q_ws[None])[0]
    return pos, prof, rec, q_s


def test_schedule_within_one_minute(noise_free):
    _, prof, _, _ = noise_free
    assert prof.time_s[-1] < six_position.MAX_RUN_S


def _fit(pos, q_s, **kwargs):
    """Steps 3–6: the rests' Eq 14 columns (:func:`six_position.rest_attitudes`) and Eq 13."""
    q_ref = rotations.quat_from_euler_zxy(*pos.T)
    rests, matched, q_sensor = six_position.rest_attitudes(q_s, q_ref, DT_S, **kwargs)
    return rests, matched, q_sensor, quaternion_lsq.least_squares_error_matrix(q_sensor, q_ref)


def test_noise_free_recovers_true_map(noise_free):
    pos, prof, rec, q_s = noise_free
    rests, matched, q_sensor, q_matrix = _fit(pos, q_s, gyro_rad_s=rec.gyro_rad_s)
    assert len(rests) == 8 and list(matched) == [1, 2, 3, 4, 5, 6]
    assert np.abs(q_matrix - wang2023cja.true_error_matrix(ALPHA)).max() < 1e-9
    # calibrated Euler angles equal truth along the whole record
    after = quaternion_lsq.apply_error_matrix(q_matrix, q_s)
    truth = rotations.euler_zxy_from_quat(rotations.quat_from_euler_zxy(*prof.angle_rad.T))
    assert np.abs(metrics_diff(rotations.euler_zxy_from_quat(after), truth)).max() < 1e-9
    # quaternion-only stillness detection finds the same rests
    assert np.abs(_fit(pos, q_s)[3] - q_matrix).max() < 1e-9


def metrics_diff(a, b):
    return (a - b + np.pi) % (2 * np.pi) - np.pi


def test_sign_flipped_inputs_same_matrix(noise_free, rng):
    pos, _, rec, q_s = noise_free
    _, _, q_sensor, q_matrix = _fit(pos, q_s, gyro_rad_s=rec.gyro_rad_s)
    flip = np.where(rng.random(6) < 0.5, -1.0, 1.0)[:, None]
    q_ref = rotations.quat_from_euler_zxy(*pos.T)
    q2 = quaternion_lsq.least_squares_error_matrix(q_sensor * flip, q_ref * flip[::-1])
    assert np.allclose(q2, q_matrix, atol=1e-12)
    batch = quaternion_lsq.least_squares_error_matrix((q_sensor * flip)[None], q_ref)
    assert np.allclose(batch[0], q_matrix, atol=1e-12)


def test_rank_deficient_positions_raise():
    ang = np.radians([[5, 0, 0], [-5, 0, 0], [10, 0, 0], [-10, 0, 0]])
    q = rotations.quat_from_euler_zxy(*ang.T)
    with pytest.raises(ValueError, match="condition number"):
        quaternion_lsq.least_squares_error_matrix(q[None], q)


def test_too_few_rests(noise_free):
    pos, _, rec, q_s = noise_free
    with pytest.raises(ValueError, match="too few rests"):
        _fit(pos, q_s[:20000], gyro_rad_s=rec.gyro_rad_s[:20000])


def test_unmatched_position(noise_free):
    pos, _, rec, q_s = noise_free
    wrong = pos.copy()
    wrong[0, 0] = np.radians(40.0)
    with pytest.raises(ValueError, match="no rest within"):
        _fit(wrong, q_s, gyro_rad_s=rec.gyro_rad_s)


def test_mean_quaternion_sign_alignment(rng):
    q = rotations.quat_from_euler_zxy(0.1, 0.2, 0.3)
    stack = np.tile(q, (10, 1)) * np.where(rng.random(10) < 0.5, -1, 1)[:, None]
    m = six_position.mean_quaternion(stack, axis=0)
    assert np.allclose(np.abs(m @ q), 1.0, atol=1e-12)


def test_find_rests_and_middle():
    still = np.zeros(10000, bool)
    still[1000:4000] = True
    still[5000:5500] = True
    rests = six_position.find_rests(still, 1.0 / 1000.0, min_rest_s=2.0)
    assert rests == [slice(1000, 4000)]
    assert six_position.middle_slices(rests, 0.5) == [slice(1750, 3250)]


def test_rests_from_another_detector(noise_free):
    """``rests=`` skips the stillness detector; the same rests give the same matrix bit for bit."""
    pos, _, rec, q_s = noise_free
    ref = _fit(pos, q_s, gyro_rad_s=rec.gyro_rad_s)
    got = _fit(pos, q_s, rests=ref[0])
    assert np.array_equal(got[3], ref[3]) and got[0] == ref[0]
    with pytest.raises(ValueError, match="too few rests"):
        _fit(pos, q_s, rests=ref[0][:3])


def test_rests_in_schedule_order_skip_the_matching(noise_free):
    """``in_order``: rest k is position k (a simulated schedule), whatever the attitudes say."""
    pos, prof, _, q_s = noise_free
    holds = prof.hold_slices()[1:-1]
    q_ref = rotations.quat_from_euler_zxy(*pos.T)
    rests, matched, q_sensor = six_position.rest_attitudes(q_s, q_ref[::-1], DT_S, rests=holds, in_order=True)
    assert list(matched) == list(range(6)) and rests == holds
    assert np.array_equal(q_sensor, six_position.rest_means(q_s, holds))
    assert list(six_position.rest_attitudes(q_s, q_ref[::-1], DT_S, rests=holds)[1]) == [5, 4, 3, 2, 1, 0]


@pytest.mark.parametrize("fs_hz", [100.0, 200.0, 1000.0])
def test_rest_length_counts_samples_of_dt(fs_hz):
    """A run of exactly ``min_rest_s / dt_s`` samples is a rest, one sample fewer is not."""
    n = int(2.0 * fs_hz)
    still = np.zeros(3 * n, bool)
    still[10:10 + n] = True
    assert six_position.find_rests(still, 1.0 / fs_hz, min_rest_s=2.0) == [slice(10, 10 + n)]
    still[10 + n - 1] = False
    assert six_position.find_rests(still, 1.0 / fs_hz, min_rest_s=2.0) == []


@pytest.mark.parametrize("shape", [(5000, 3), (2, 5000, 3)])
def test_compiled_stillness_matches_numpy_moving_mean(shape):
    rng = np.random.default_rng(11)
    w = rng.normal(size=shape) * np.radians(0.1)
    w[..., 2000:2600, :] += 0.3
    for window_s in (0.001, 0.002, 0.007, 0.1):
        win = max(1, int(round(window_s / DT_S)))
        ref_norm = np.linalg.norm(six_position._moving_mean(w, win, axis=-2), axis=-1)
        ref = ref_norm < np.radians(0.2)
        ref = ref if ref.ndim == 1 else np.all(ref, axis=0)
        got = six_position.stillness_from_gyro(w, DT_S, window_s, np.radians(0.2))
        assert got.shape == (shape[-2],) and np.array_equal(got, ref)
    w3 = w if w.ndim == 3 else w[None]
    mean = np.empty((w3.shape[0], 3, w3.shape[1]))
    six_position._moving_mean_kernel(w3, 100, mean)
    ref_mean = six_position._moving_mean(w3, 100, axis=-2)
    assert np.moveaxis(mean, 1, 2).tobytes() == np.ascontiguousarray(ref_mean).tobytes()


@pytest.mark.parametrize("seed", range(6))
def test_rest_means_compiled_pass_equals_mean_quaternion_bit_for_bit(seed):
    """The compiled sums of rest_means give mean_quaternion's numbers per rest: sign flips, (N, 4) and
    (T, N, 4), one-sample windows, and exact ±0 components (numpy's reduction sums them from +0)."""
    rng = np.random.default_rng(seed)
    t, n = int(rng.integers(1, 4)), int(rng.integers(50, 3000))
    q = rotations.quat_normalize(np.array([0.9, 0.1, -0.2, 0.3]) + rng.uniform(0.001, 0.8) * rng.standard_normal((t, n, 4)))
    q[:, rng.random(n) < 0.3] *= -1.0
    if seed == 0:                                          # exact zeros of both signs
        q[:] = 0.0
        q[:, :, 0] = np.where(rng.random((t, n)) < 0.5, -1.0, 1.0)
        q[:, :, 1:] *= -1.0
    cuts = np.sort(rng.choice(np.arange(1, n), size=8, replace=False))
    rests = [slice(int(cuts[2 * j]), int(cuts[2 * j + 1])) for j in range(4)] + [slice(3, 4)]
    frac = float(rng.uniform(0.05, 1.0))
    for arr in (q, np.ascontiguousarray(q[0])):
        got = six_position.rest_means(arr, rests, frac)
        ref = np.stack([six_position.mean_quaternion(arr[..., s, :], axis=-2)
                        for s in six_position.middle_slices(rests, frac)], axis=-2)
        assert got.shape == ref.shape and got.tobytes() == ref.tobytes()


def test_angle_between_is_the_hamilton_expression_bit_for_bit():
    """The rests' distances run methods' compiled pass: the numbers of 2 atan2(‖d[1:]‖, |d[0]|), d = p* ⊗ q."""
    rng = np.random.default_rng(3)

    def unit(shape):
        q = rng.standard_normal(shape)
        return q / np.linalg.norm(q, axis=-1, keepdims=True)

    for a, b in (((8, 1, 4), (1, 6, 4)), ((2, 8, 1, 4), (2, 1, 6, 4)), ((5000, 4), (5000, 4)), ((6, 4), (6, 4))):
        p, q = unit(a), unit(b)
        d = rotations.hamilton(p * [1.0, -1.0, -1.0, -1.0], q)
        ref = 2.0 * np.arctan2(np.linalg.norm(d[..., 1:], axis=-1), np.abs(d[..., 0]))
        got = six_position._angle_between(p, q)
        assert got.shape == ref.shape and np.array_equal(got, ref)
    p = unit((3, 4))
    assert np.allclose(six_position._angle_between(p, p), 0.0, atol=1e-15)
    p[1, 2] = np.nan
    assert np.isnan(six_position._angle_between(p, unit((3, 4)))).tolist() == [False, True, False]


def test_a_refusal_carries_the_rests_mean_attitudes():
    """PositionsRefused hands the caller what each rest measured (zeroed), once they were made."""
    pos = six_position.six_positions_rad()
    prof = six_position.schedule_profile(pos, fs_hz=50.0)
    q = trajectory_from_euler_zxy(prof).q_wb
    holds = prof.hold_slices()
    wrong = pos * [1.0, -1.0, 1.0]                                        # pitch sign flipped
    with pytest.raises(six_position.PositionsRefused, match="has no rest within") as info:
        six_position.calibrate_from_rests(q, wrong, rotations.quat_from_euler_zxy(*wrong.T), 0.02, rests=holds)
    zeroed = rotations.relative_to_initial(q[None])[0]
    assert np.array_equal(info.value.rest_means, six_position.rest_means(zeroed, holds))
    assert info.value.q_ws is q
    with pytest.raises(six_position.PositionsRefused, match="too few rests") as info:
        six_position.calibrate_from_rests(q, pos, rotations.quat_from_euler_zxy(*pos.T), 0.02, rests=holds[:3])
    assert info.value.rest_means is None


def test_calibrate_session_is_calibrate_from_rests_of_both_runs(noise_free):
    """One methods call per block: the calibration run's calibration, then the verification run with that Q̂."""
    pos, prof, rec, q_s = noise_free
    q_ref = rotations.quat_from_euler_zxy(*pos.T)
    q_run = np.stack([q_s, q_s])
    gyro = np.stack([rec.gyro_rad_s, rec.gyro_rad_s])
    fed = pos + np.radians([0.01, -0.02, 0.03])
    cal, ver = six_position.calibrate_session(q_run, fed, rotations.quat_from_euler_zxy(*fed.T), DT_S,
                                              gyro_calibration=gyro, q_verification=q_run, gyro_verification=gyro,
                                              verification_positions_rad=pos, verification_q_reference=q_ref)
    ref_cal = six_position.calibrate_from_rests(q_run, fed, rotations.quat_from_euler_zxy(*fed.T), DT_S, zero=False,
                                                gyro_rad_s=gyro)
    ref_ver = six_position.calibrate_from_rests(q_run, pos, q_ref, DT_S, zero=False, gyro_rad_s=gyro,
                                                q_hat=ref_cal.q_hat)
    for got, ref in ((cal, ref_cal), (ver, ref_ver)):
        for name in ("q_hat", "q_sensor", "euler_before_rad", "euler_after_rad", "residual_rad", "matched",
                     "installation_angles_rad", "error_after_rad"):
            assert np.array_equal(getattr(got, name), getattr(ref, name)), name
    only, none = six_position.calibrate_session(q_s, pos, q_ref, DT_S, gyro_calibration=rec.gyro_rad_s)
    assert none is None and np.degrees(np.abs(only.installation_angles_rad - ALPHA)).max() < 0.01
    with pytest.raises(six_position.PositionsRefused, match=r"residual .* exceeds max_residual_rad"):
        bent = pos + np.radians(np.random.default_rng(1).normal(0.0, 0.5, pos.shape))     # off by 0.5 deg each
        six_position.calibrate_session(q_s, bent, rotations.quat_from_euler_zxy(*bent.T), DT_S,
                                       gyro_calibration=rec.gyro_rad_s, max_residual_rad=np.radians(0.01))
