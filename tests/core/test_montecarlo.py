import numpy as np
import pytest

from mtcal.core import metrics, montecarlo, profiles, rotations, simulate
from mtcal.core.simulate import ImuErrorModel, SensorErrors


class GyroIntegrator:
    """Minimal consumer: integrates the gyro and accumulates attitude-angle errors."""

    def __init__(self, q0, dt, trials):
        self.q = np.tile(q0, (trials, 1))
        self.dt = dt
        self.acc = montecarlo.ErrorAccumulator((trials,))

    def update(self, chunk):
        inc = rotations.quat_from_rotvec(chunk.gyro_rad_s * self.dt)
        err = np.empty(inc.shape[:2])
        for k in range(inc.shape[1]):
            err[:, k] = rotations.quat_angle_between(self.q, np.broadcast_to(chunk.q_ws_true[k], self.q.shape))
            self.q = rotations.hamilton(self.q, inc[:, k])
        self.acc.add(err)


@pytest.fixture
def stream_args():
    wp = np.radians([[0, 0, 0], [8, 0, 0], [0, 20, -30]])
    traj = profiles.trajectory_from_euler_zxy(profiles.step_schedule(wp, np.radians(20), 0.3, 200))
    model = ImuErrorModel(gyro=SensorErrors(noise_density=1e-3, bias_sigma=1e-3))
    return traj, model


@pytest.mark.parametrize("chunk", [7, 64, 10_000])
def test_streaming_metrics_independent_of_chunk_size(stream_args, chunk):
    traj, model = stream_args
    results = []
    for size in (chunk, 50):
        stream = simulate.ImuStream(traj, model, np.random.default_rng(11), trials=5)
        consumer = GyroIntegrator(traj.q_wb[0], traj.dt_s, 5)
        montecarlo.run_streaming(stream, [consumer], size, progress=False)
        results.append((consumer.acc.rmse(), consumer.acc.max_abs()))
    np.testing.assert_allclose(results[0][0], results[1][0], rtol=1e-12)
    np.testing.assert_array_equal(results[0][1], results[1][1])


def test_accumulator_matches_batch_metrics(rng):
    err = rng.normal(size=(4, 100, 3))
    acc = montecarlo.ErrorAccumulator((4, 3))
    for part in np.array_split(err, 7, axis=1):
        acc.add(part)
    np.testing.assert_allclose(acc.rmse(), metrics.rmse(err, axis=1))
    np.testing.assert_allclose(acc.max_abs(), metrics.max_abs_error(err, axis=1))
    np.testing.assert_allclose(acc.mean(), err.mean(axis=1))
    mask = np.arange(100) < 30
    acc_m = montecarlo.ErrorAccumulator((4, 3))
    acc_m.add(err, mask=mask)
    np.testing.assert_allclose(acc_m.rmse(), metrics.rmse(err[:, :30], axis=1))


def test_accumulator_and_runner_errors(stream_args):
    acc = montecarlo.ErrorAccumulator((4,))
    with pytest.raises(ValueError, match="no samples"):
        acc.rmse()
    with pytest.raises(ValueError, match="error must have shape"):
        acc.add(np.zeros((3, 10)))
    with pytest.raises(ValueError, match="mask must be a boolean"):
        acc.add(np.zeros((4, 10)), mask=np.ones(10))
    with pytest.raises(TypeError, match="stream must be an ImuStream"):
        montecarlo.run_streaming([1, 2], [object()])
    traj, _ = stream_args
    with pytest.raises(TypeError, match="consumers must be"):
        montecarlo.run_streaming(simulate.ImuStream(traj), [object()])


def test_progress_switch(monkeypatch):
    monkeypatch.setenv("MTCAL_PROGRESS", "0")
    assert not montecarlo.progress_enabled()
    monkeypatch.setenv("MTCAL_PROGRESS", "1")
    assert montecarlo.progress_enabled()


def test_compiled_euler_error_statistics_match_numpy():
    rng = np.random.default_rng(4)
    q = rotations.quat_normalize(np.array([1.0, 0.0, 0.0, 0.0]) + 0.4 * rng.standard_normal((3, 50, 4)))
    truth = rotations.euler_zxy_from_quat(q[0]) + 0.01 * rng.standard_normal((50, 3))
    truth[::7, 0] += 2 * np.pi - 0.005  # wrapping
    ref = montecarlo.ErrorAccumulator((3, 3))
    fast = montecarlo.ErrorAccumulator((3, 3))
    for sl in (slice(0, 20), slice(20, 50)):
        ref.add(metrics.angle_difference(rotations.euler_zxy_from_quat(q[:, sl]), truth[sl]))
        fast.add_euler_zxy_errors(q[:, sl], truth[sl])
    np.testing.assert_allclose(fast.rmse(), ref.rmse(), rtol=1e-13, atol=0)
    np.testing.assert_allclose(fast.mean(), ref.mean(), rtol=0, atol=1e-15)
    np.testing.assert_allclose(fast.max_abs(), ref.max_abs(), rtol=0, atol=1e-15)
    with pytest.raises(ValueError, match="accumulator of shape"):
        montecarlo.ErrorAccumulator((3,)).add_euler_zxy_errors(q, truth)
    with pytest.raises(ValueError, match="does not match"):
        fast.add_euler_zxy_errors(q, truth[:10])


def test_qncf_run_error_stats_equals_run_then_accumulate():
    from mtcal.filters.qncf import QncfFilter

    wp = np.radians([[0, 0, 0], [8, 0, 0], [0, 20, -30]])
    traj = profiles.trajectory_from_euler_zxy(profiles.step_schedule(wp, np.radians(20), 0.3, 1000))
    model = ImuErrorModel(gyro=SensorErrors(noise_density=1e-4), accel=SensorErrors(noise_density=1e-3))
    rec = simulate.simulate_imu(traj, model, np.random.default_rng(1), trials=4)
    truth = rotations.euler_zxy_from_quat(rec.q_ws_true)
    f1, f2 = (QncfFilter(rec.q_ws_true[0], traj.dt_s, trials=4) for _ in range(2))
    a1, a2 = montecarlo.ErrorAccumulator((4, 3)), montecarlo.ErrorAccumulator((4, 3))
    for sl in (slice(0, 333), slice(333, None)):
        f1.run_error_stats(rec.gyro_rad_s[:, sl], rec.accel_m_s2[:, sl], truth[sl], a1)
        a2.add_euler_zxy_errors(f2.run(rec.gyro_rad_s[:, sl], rec.accel_m_s2[:, sl], return_euler=False).q_ws,
                                truth[sl])
    for name in ("rmse", "mean", "max_abs"):
        np.testing.assert_array_equal(getattr(a1, name)(), getattr(a2, name)())
    np.testing.assert_array_equal(f1.q_ws, f2.q_ws)
    with pytest.raises(TypeError, match="ErrorAccumulator"):
        f1.run_error_stats(rec.gyro_rad_s, rec.accel_m_s2, truth, montecarlo.ErrorAccumulator((4,)))
    with pytest.raises(ValueError, match="engine='numba'"):
        QncfFilter(rec.q_ws_true[0], traj.dt_s, trials=4, engine="numpy").run_error_stats(
            rec.gyro_rad_s, rec.accel_m_s2, truth, a1)


def test_compiled_wrap_equals_angle_difference_bit_for_bit():
    d = np.concatenate([np.linspace(-20.0, 20.0, 20001), [np.pi, -np.pi, 0.0, -0.0, 2 * np.pi, -2 * np.pi,
                                                          np.nextafter(np.pi, 0), np.nextafter(-np.pi, 0)]])
    got = np.array([montecarlo._wrap(x) for x in d])
    np.testing.assert_array_equal(got, metrics.angle_difference(d, 0.0))


def test_streaming_trials_split_across_workers_give_the_same_metrics(stream_args):
    """Trials named by id: a run split in two (e.g. two workers) gives each trial the metrics of the whole run."""
    traj, model = stream_args
    model = ImuErrorModel(gyro=SensorErrors(noise_density=1e-3, bias_sigma=1e-3, bias_instability=1e-4),
                          accel=model.accel)
    results = {}
    for ids in ((0, 1, 2, 3, 4), (0, 1), (2, 3, 4)):
        stream = simulate.ImuStream(traj, model, np.random.default_rng(13), trial_ids=ids)
        consumer = GyroIntegrator(traj.q_wb[0], traj.dt_s, len(ids))
        montecarlo.run_streaming(stream, [consumer], 64, progress=False)
        results[ids] = (consumer.acc.rmse(), consumer.acc.max_abs())
    for k in range(2):
        np.testing.assert_array_equal(np.concatenate([results[(0, 1)][k], results[(2, 3, 4)][k]]),
                                      results[(0, 1, 2, 3, 4)][k])


def _fast_errors(q, truth):
    """Per-sample compiled errors (euler_errors_cs) of q (n, 4) against truth (n, 3)."""
    out = np.empty(truth.shape)
    montecarlo._euler_errors_rows(np.ascontiguousarray(q), montecarlo.truth_table(truth[None])[0], out)
    return out


def _bound_excess(q, truth):
    """max over samples of |fast − reference| (mod 2π) minus the stated bound (≤ 0 when it holds)."""
    ref_euler = rotations.euler_zxy_from_quat(q)
    ref = metrics.angle_difference(ref_euler, truth)
    diff = np.abs(metrics.angle_difference(_fast_errors(q, truth), ref))
    cos_pitch = np.cos(ref_euler[:, 1:2])
    return float(np.max(diff - (montecarlo.ERROR_BOUND_RAD + montecarlo.ERROR_BOUND_LOCK_RAD / cos_pitch)))


@pytest.mark.parametrize("scale", [0.0, 1e-9, 1e-5, 1e-2, 0.05, 3.0])
def test_series_euler_errors_stay_within_the_stated_bound_of_the_reference(rng, scale):
    """Property: random attitudes, errors from 0 to ±π (series path below SERIES_MAX, libm fallback above)."""
    n = 20_000
    q = rotations.quat_normalize(rng.standard_normal((n, 4)))
    truth = rotations.euler_zxy_from_quat(q) + scale * rng.standard_normal((n, 3))
    assert _bound_excess(q, truth) <= 0.0
    if 0 < scale <= 1e-5:  # the series path itself (no fallback) is exercised
        got = _fast_errors(q, truth)
        assert np.all(np.abs(got) < montecarlo.SERIES_MAX)


@pytest.mark.parametrize("scale", [0.0, 1e-6, 1e-2, 3.0])
def test_series_euler_errors_near_gimbal_lock(rng, scale):
    """Pitch within 1e-9 … 0.1 rad of ±90°: the bound grows as 1/cos θ (ill-conditioned Eq 8 in both)."""
    n = 20_000
    delta = 10 ** rng.uniform(-9, -1, n)
    pitch = rng.choice([-1.0, 1.0], n) * (np.pi / 2 - delta)
    q = rotations.quat_from_euler_zxy(rng.uniform(-np.pi, np.pi, n), pitch, rng.uniform(-np.pi, np.pi, n))
    truth = rotations.euler_zxy_from_quat(q) + scale * rng.standard_normal((n, 3))
    assert _bound_excess(q, truth) <= 0.0


def test_series_euler_errors_wrap_at_pi(rng):
    """Errors of ±(π − tiny) and truths outside [−π, π]: the rotated-vector form wraps by itself."""
    n = 20_000
    q = rotations.quat_normalize(rng.standard_normal((n, 4)))
    e = rotations.euler_zxy_from_quat(q)
    truth = e.copy()
    truth[:, 0] += np.pi + 1e-12 * rng.standard_normal(n)
    truth[:, 2] += rng.choice([-1.0, 1.0], n) * (np.pi - 1e-10) + 4 * np.pi
    truth[:, 1] += 1e-4 * rng.standard_normal(n) + 2 * np.pi
    assert _bound_excess(q, truth) <= 0.0
    got = _fast_errors(q, truth)
    assert np.all(np.abs(got[:, 0]) > 3.14) and np.all(np.abs(got[:, 1]) < 1e-3)


def test_series_paths_are_accurate_to_double_rounding():
    """atan/asin series below SERIES_MAX agree with libm to 1 ulp (truncation < 1e-19 relative)."""
    import math

    x = np.concatenate([np.linspace(-montecarlo.SERIES_MAX, montecarlo.SERIES_MAX, 40001)[1:-1],
                        [1e-300, -1e-12, 5e-324, 0.0]])
    at = np.array([montecarlo.atan_small(v) for v in x])
    asn = np.array([montecarlo.asin_small(v) for v in x])
    assert np.all(np.abs(at - np.array([math.atan(v) for v in x])) <= np.spacing(np.abs(at)))
    assert np.all(np.abs(asn - np.array([math.asin(v) for v in x])) <= np.spacing(np.abs(asn)))


def _before_after_inputs(seed, trials=3, n=1500):
    rng = np.random.default_rng(seed)
    q = rotations.quat_normalize(np.array([1.0, 0.1, -0.05, 0.02]) + 0.2 * rng.normal(size=(trials, n, 4)))
    q[:, ::7] *= -1.0                                                     # both signs of q0
    q_mat = np.eye(4) + 2e-3 * rng.normal(size=(trials, 4, 4))
    return q, q_mat


def _wrapped_gap(x, y):
    return np.abs(metrics.angle_difference(x, y))


@pytest.mark.parametrize("chan", [0, 1, 2])
@pytest.mark.parametrize("ref_spread", [1e-3, 0.3, 3.0])      # series path, mixed, libm fallback (errors up to ±π)
def test_channel_errors_within_the_stated_bound_of_the_libm_expressions(chan, ref_spread):
    """Angle ``chan`` (truth + error) and the three wrapped errors, before and after Eq 10, within
    ``ERROR_BOUND_RAD`` (angles: + one rounding of the angle) of the expressions the sweeps used before:
    ``euler_zxy_unchecked`` of ``q`` and of ``apply_error_matrix(q_mat, q)``, ``angle_difference``."""
    from mtcal.methods import quaternion_lsq

    q, q_mat = _before_after_inputs(11)
    truth = rotations.euler_zxy_unchecked(q[0])
    ref = truth + ref_spread * np.random.default_rng(12).normal(size=truth.shape)
    ref[:, 1] = np.clip(ref[:, 1], -1.2, 1.2)
    out = [np.full(q.shape[:-1], np.nan), np.full(q.shape[:-1], np.nan),
           np.full(q.shape[:-1] + (3,), np.nan), np.full(q.shape[:-1] + (3,), np.nan)]
    table = montecarlo.truth_table(np.ascontiguousarray(ref)[None])[0]
    assert montecarlo.channel_errors_cs(q, q_mat, table, rotations._LOCK_SIN, chan, *out) == 0
    bc, ac, ebc, eac = out
    b = rotations.euler_zxy_unchecked(q)
    a = rotations.euler_zxy_unchecked(quaternion_lsq.apply_error_matrix(q_mat, q))
    eb, ea = metrics.angle_difference(b, ref), metrics.angle_difference(a, ref)
    bound = montecarlo.ERROR_BOUND_RAD
    assert _wrapped_gap(ebc, eb).max() <= bound and _wrapped_gap(eac, ea).max() <= bound
    assert _wrapped_gap(bc, b[..., chan]).max() <= bound + np.spacing(np.pi)
    assert _wrapped_gap(ac, a[..., chan]).max() <= bound + np.spacing(np.pi)
    assert (np.abs(ebc) <= np.pi).all() and (np.abs(eac) <= np.pi).all()
    if ref_spread == 1e-3:                      # a converged filter: the errors agree far below the bound
        assert _wrapped_gap(ebc, eb).max() <= 1e-15 and _wrapped_gap(eac, ea).max() <= 1e-15


def test_channel_errors_leave_gimbal_lock_rows_and_a_zero_matrix_to_the_caller():
    q, q_mat = _before_after_inputs(3, trials=2, n=40)
    q[0, 5] = rotations.quat_from_euler_zxy(0.1, np.pi / 2, 0.2)             # |sin pitch| = 1
    q_mat[1] = 0.0                                                           # norm 0 after Eq 10
    table = montecarlo.truth_table(np.zeros((1, 40, 3)))[0]
    out = [np.full((2, 40), np.nan), np.full((2, 40), np.nan), np.full((2, 40, 3), np.nan),
           np.full((2, 40, 3), np.nan)]
    bad = montecarlo.channel_errors_cs(q, q_mat, table, rotations._LOCK_SIN, 1, *out)
    assert bad == 1 + 40 and np.isnan(out[0][0, 5]) and np.isnan(out[2][1]).all() and np.isfinite(out[2][0, 6]).all()


def test_channel_errors_before_after_is_the_compiled_pass_or_the_expressions(monkeypatch):
    """One scoring call: the compiled pass where it applies (its outputs, bit for bit), else — a gimbal-lock
    row, a small input — the expressions ``euler_zxy_unchecked`` of ``q`` and of Eq 10, ``angle_difference``."""
    from mtcal.methods import quaternion_lsq

    q, q_mat = _before_after_inputs(11)
    ref = rotations.euler_zxy_unchecked(q[0]) + 0.01
    out = [np.empty(q.shape[:-1]), np.empty(q.shape[:-1]), np.empty(q.shape[:-1] + (3,)),
           np.empty(q.shape[:-1] + (3,))]
    table = montecarlo.truth_table(ref[None])[0]
    assert montecarlo.channel_errors_cs(q, q_mat, table, rotations._LOCK_SIN, 2, *out) == 0
    before, after, errs = montecarlo.channel_errors_before_after(q, q_mat, ref, 2)
    for x, y in zip((before, after, errs["before"], errs["after"]), out):
        assert np.array_equal(x, y)
    b = rotations.euler_zxy_unchecked(q)
    a = rotations.euler_zxy_unchecked(quaternion_lsq.apply_error_matrix(q_mat, q))
    q_lock = q.copy()
    q_lock[1, 7] = rotations.quat_from_euler_zxy(0.1, np.pi / 2, 0.2)          # a row the compiled pass leaves
    b_lock = rotations.euler_zxy_unchecked(q_lock)
    a_lock = rotations.euler_zxy_unchecked(quaternion_lsq.apply_error_matrix(q_mat, q_lock))

    def expressions(qq, bb, aa):
        before, after, errs = montecarlo.channel_errors_before_after(qq, q_mat, ref, 2)
        return (np.array_equal(before, bb[..., 2]) and np.array_equal(after, aa[..., 2])
                and np.array_equal(errs["before"], metrics.angle_difference(bb, ref))
                and np.array_equal(errs["after"], metrics.angle_difference(aa, ref)))

    assert expressions(q_lock, b_lock, a_lock)                                  # the compiled pass left a row
    monkeypatch.setattr(rotations, "_KERNEL_MIN_ROWS", 10 ** 12)              # a small input
    assert expressions(q, b, a)
    bad = q_mat.copy()
    bad[0, 2, 2] = np.nan
    with pytest.raises(FloatingPointError, match="Eq 8 angles are not finite"):
        montecarlo.channel_errors_before_after(q, bad, ref, 2)


def test_mapped_pitch_is_the_pitch_of_the_mapped_attitude():
    from mtcal.methods import quaternion_lsq

    q, q_mat = _before_after_inputs(13)
    expected = rotations.euler_zxy_unchecked(quaternion_lsq.apply_error_matrix(q_mat, q))[..., 1]
    assert np.array_equal(rotations.mapped_pitch_trusted(q_mat, q), expected)            # compiled pass
    assert np.array_equal(rotations.mapped_pitch_trusted(q_mat[:1], q[:1, :100]), expected[:1, :100])  # expressions
    bad = q_mat.copy()
    bad[1, 0, 0] = np.inf
    with pytest.raises(FloatingPointError, match="Eq 8 angles are not finite"):
        rotations.mapped_pitch_trusted(bad, q)
