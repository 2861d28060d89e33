"""Compiled (numba) filter kernels vs the numpy reference engines.

Agreement ≤ 1e-12 rad on realistic records (AMD gate and ZVD switching
included), bit-identical results for any numba thread count and any chunking,
graceful fallback when the numba cache cannot be written. No timing here
(speed lives in ``make bench``).
"""

import warnings

import numba
import numpy as np
import pytest

from mtcal.core import profiles, rotations, simulate
from mtcal.filters import _kernels_common
from mtcal.filters.baselines import MagneticDisturbance, angle_from_orientation, mahony_marg, simulate_magnetometer
from mtcal.filters.qncf import QncfFilter, QncfParams, qncf
from mtcal.filters.rams_ekf import RamsEkfFilter, initial_state, run_rams_ekf
from mtcal.studies.wang2022sensors.runs import ImuSpec as SensorsImu
from mtcal.studies.wang2022sensors.runs import RotationSetup, simulate_rotation
from mtcal.studies.wang2023cja import ImuSpec as CjaImu

FS = 1000.0
TOL_RAD = 1e-12


@pytest.fixture
def all_parallel(monkeypatch):
    """Route even tiny inputs through the prange kernels."""
    monkeypatch.setattr(_kernels_common, "PARALLEL_MIN_WORK", 1)


@pytest.fixture
def threads():
    """numba.set_num_threads, restored afterwards."""
    before = numba.get_num_threads()
    yield numba.set_num_threads
    numba.set_num_threads(before)


# --------------------------------------------------------------------------- QNCF
def _turntable_record(trials: int, vibrate: bool):
    """Pitch/roll/yaw step schedule, wang2023cja tactical MEMS IMU; optional tunnel-like vibration
    in the second half of trial 0 (AMD gate closes and reopens)."""
    wp = np.radians([[0, 0, 0], [20, 0, 0], [20, 30, 0], [0, 30, -40], [0, 0, 0]])
    prof = profiles.step_schedule(wp, np.radians(30), 0.8, FS)
    traj = profiles.trajectory_from_euler_zxy(prof)
    rec = simulate.simulate_imu(traj, CjaImu().error_model((1.0, 0.0, 0.0, 0.0)), np.random.default_rng(17),
                                trials=trials)
    accel = rec.accel_m_s2.copy()
    if vibrate:
        n = accel.shape[1]
        t = np.arange(n) / FS
        burst = ((t > 0.4 * t[-1]) & (t < 0.7 * t[-1]))[:, None] * 2.0 * np.sin(2 * np.pi * 45 * t)[:, None]
        accel[0] += burst * np.array([1.0, 0.5, 1.0])
    return rec, accel


def _qncf_angles(res):
    return rotations.euler_zxy_from_quat(res.q_ws)


@pytest.mark.parametrize("ki", [0.02, 0.0])
def test_qncf_numba_agrees_with_numpy_reference(ki):
    rec, accel = _turntable_record(3, vibrate=True)
    p = QncfParams(ki_rad_s2=ki)
    fast = qncf(rec.gyro_rad_s, accel, 1 / FS, p)
    ref = qncf(rec.gyro_rad_s, accel, 1 / FS, p, engine="numpy")
    assert fast.gate[0].any() and not fast.gate[0].all()  # the gate switched
    assert np.array_equal(fast.gate, ref.gate)
    np.testing.assert_allclose(fast.amd_pct, ref.amd_pct, rtol=1e-14, atol=0)
    np.testing.assert_allclose(fast.q_ws, ref.q_ws, rtol=0, atol=TOL_RAD)
    np.testing.assert_allclose(fast.euler_rad, ref.euler_rad, rtol=0, atol=TOL_RAD)


def test_qncf_single_trial_and_large_increments_agree():
    rec, accel = _turntable_record(None, vibrate=False)
    fast, ref = (qncf(rec.gyro_rad_s, accel, 1 / FS, engine=e) for e in ("numba", "numpy"))
    np.testing.assert_allclose(fast.q_ws, ref.q_ws, rtol=0, atol=TOL_RAD)
    # 16x longer sample interval: increments beyond the series (cos/sin path)
    g, a = rec.gyro_rad_s[::16], accel[::16]
    fast, ref = (qncf(g * 5.0, a, 16 / FS, engine=e) for e in ("numba", "numpy"))
    np.testing.assert_allclose(fast.q_ws, ref.q_ws, rtol=0, atol=TOL_RAD)


def test_qncf_bit_identical_for_any_thread_count_and_chunking(all_parallel, threads):
    rec, accel = _turntable_record(5, vibrate=True)
    q0 = rec.q_ws_true[0]
    whole = {}
    for n_threads in sorted({1, min(2, numba.config.NUMBA_NUM_THREADS)}):
        threads(n_threads)
        whole[n_threads] = QncfFilter(q0, 1 / FS, trials=5).run(rec.gyro_rad_s, accel)
    first, *others = whole.values()
    for res in others:
        assert np.array_equal(res.q_ws, first.q_ws) and np.array_equal(res.amd_pct, first.amd_pct)
    filt = QncfFilter(q0, 1 / FS, trials=5)
    cuts = [0, 1, 137, 1000, 1001, 2500, rec.gyro_rad_s.shape[1]]
    parts = [filt.run(rec.gyro_rad_s[:, i:j], accel[:, i:j], return_euler=False) for i, j in zip(cuts, cuts[1:])]
    assert np.array_equal(np.concatenate([p.q_ws for p in parts], axis=1), first.q_ws)
    assert np.array_equal(np.concatenate([p.gate for p in parts], axis=1), first.gate)
    # one trial alone = the same trial inside the batch (trials are independent)
    one = qncf(rec.gyro_rad_s[2], accel[2], 1 / FS, q0=q0)
    assert np.array_equal(one.q_ws, first.q_ws[2])


# 8 lanes (AVX-512 hosts): partial blocks (2-7), a full block + a lone trial (9, 17), full + partial (13);
# 4 lanes: full + partial (7), several blocks + a lone trial (9, 13, 17)
@pytest.mark.parametrize("trials", [2, 3, 5, 7, 9, 13, 17])
def test_qncf_batched_lanes_are_bit_identical_to_each_trial_alone(all_parallel, trials):
    """Lane blocks (odd counts: a short last block or a lone trial), the AMD gate closing in trial 0,
    a lane needing the trigonometric increment while the others use the series, the initial NaN AMD
    state: every trial of the batch equals the scalar kernel run on that trial alone."""
    rec, accel = _turntable_record(trials, vibrate=True)
    g, a, dt = rec.gyro_rad_s[:, ::16].copy(), accel[:, ::16], 16 / FS
    g[trials // 2] *= 5.0        # |Δθ| > 0.04 rad in this trial only
    q0 = rec.q_ws_true[0]
    batch = QncfFilter(q0, dt, trials=trials).run(g, a, return_euler=False)
    assert not batch.gate[0].all() and batch.gate.any()
    for t in range(trials):
        one = qncf(g[t], a[t], dt, q0=q0, return_euler=False)
        assert np.array_equal(one.q_ws, batch.q_ws[t]), t
        assert np.array_equal(one.amd_pct, batch.amd_pct[t]) and np.array_equal(one.gate, batch.gate[t]), t


@pytest.mark.parametrize("trials", [1, 3, 6])
def test_qncf_fused_error_statistics_match_per_trial_runs(all_parallel, trials):
    from mtcal.core.montecarlo import ErrorAccumulator

    rec, accel = _turntable_record(trials, vibrate=True)
    truth = rotations.euler_zxy_from_quat(rec.q_ws_true)
    q0 = rec.q_ws_true[0]
    fused = ErrorAccumulator((trials, 3))
    QncfFilter(q0, 1 / FS, trials=trials).run_error_stats(rec.gyro_rad_s, accel, truth, fused)
    for t in range(trials):
        alone = ErrorAccumulator((1, 3))
        QncfFilter(q0, 1 / FS, trials=1).run_error_stats(rec.gyro_rad_s[t:t + 1], accel[t:t + 1], truth, alone)
        assert np.array_equal(alone._sum[0], fused._sum[t]) and np.array_equal(alone._sumsq[0], fused._sumsq[t])
        assert np.array_equal(alone._max[0], fused._max[t]), t


def _qncf_kernel_args(keep: bool, with_stats: bool):
    """Direct arguments of the QNCF kernels for 5 trials: AMD gate closing (trial 0), a NaN initial AMD state in
    trials 0 and 3, the trigonometric increment in trial 2 only, per-trial truth with a large Eq 8 error (off
    the error series) in trial 1 only; unused outputs NaN-filled so that any stray store shows."""
    rec, accel = _turntable_record(5, vibrate=True)
    g, a = rec.gyro_rad_s[:, ::16].copy(), np.ascontiguousarray(accel[:, ::16])
    g[2] *= 5.0
    n, m = g.shape[:2]
    from mtcal.core.montecarlo import truth_table

    truth_e = rotations.euler_zxy_from_quat(rec.q_ws_true[::16])
    truth = truth_table(np.ascontiguousarray(truth_e + 1e-3 * np.arange(n)[:, None, None]))
    truth[1, 20:40, 3:] = truth_table(np.radians([[[170.0, 80.0, 100.0]]]))[0, 0, 3:]
    amd = np.linspace(0.0, 2.0, n)
    amd[[0, 3]] = np.nan
    full = (n, m) if keep else (1, 1)
    return [g, a, np.tile(rec.q_ws_true[0], (n, 1)), np.linspace(-1e-4, 1e-4, 3 * n).reshape(n, 3), amd,
            np.full(full + (4,), np.nan), np.full(full, np.nan), np.zeros(full, np.bool_), 1.0, 0.02 * 16 / FS,
            True, 16 / FS, 0.02, 9.80665, 0.3, keep, truth, np.linspace(0.0, 1e-3, 9 * n).reshape(n, 9),
            with_stats, np.full((n, 4), np.nan)]


@pytest.mark.parametrize("keep, with_stats", [(True, True), (False, True), (True, False)])
def test_qncf_blocks_of_4_and_8_lanes_are_bit_identical_to_the_scalar_trial(keep, with_stats):
    """Both block widths (whichever LANES this host compiles), spare lanes repeating the last trial, the
    per-lane scalar fallbacks (trigonometric increment, Eq 8 errors off their series, NaN initial AMD):
    state, histories, gate, error statistics and the input scan equal the scalar kernel bit for bit."""
    from mtcal.filters import _kernels_qncf as K

    ref = _qncf_kernel_args(keep, with_stats)
    K.qncf_one(*ref)
    outputs = (2, 3, 4, 5, 6, 7, 17, 19)  # q, integ, amd, q_out, amd_out, gate_out, stats, chk
    for rows in ((0, 1, 2, 3), (1, 2, 3, 4), (0, 1, 2, 3, 4, 4, 4, 4), (2, 3, 4, 4, 4, 4, 4, 4)):
        got = _qncf_kernel_args(keep, with_stats)
        K._block(got[0], got[1], rows, *got[2:])
        r = sorted(set(rows))
        other = sorted(set(range(5)) - set(r))
        for i in outputs:
            x, y = ref[i], got[i]
            if x.shape[0] == 5:
                assert np.array_equal(x[r], y[r], equal_nan=True), (rows, i)
                assert np.array_equal(y[other], _qncf_kernel_args(keep, with_stats)[i][other], equal_nan=True), (
                    rows, i)  # rows outside the block untouched
            else:
                assert np.isnan(y).all() or not y.any(), (rows, i)   # 1 x 1 placeholders never written
    assert not np.array_equal(ref[2], _qncf_kernel_args(keep, with_stats)[2])  # the kernel did move the state


def test_qncf_parallel_kernel_leaves_the_chunk_size_alone(all_parallel, threads):
    from mtcal.filters import _kernels_qncf as K

    threads(min(2, numba.config.NUMBA_NUM_THREADS))
    before = numba.get_parallel_chunksize()
    ref, got = _qncf_kernel_args(True, True), _qncf_kernel_args(True, True)
    K.qncf_serial(*ref)
    K.qncf_parallel(*got)
    assert numba.get_parallel_chunksize() == before
    for x, y in zip(ref, got):
        if isinstance(x, np.ndarray):
            assert np.array_equal(x, y, equal_nan=True)


def test_qncf_non_finite_sample_in_one_lane_raises_and_keeps_the_state(all_parallel):
    rec, accel = _turntable_record(6, vibrate=False)
    filt = QncfFilter(rec.q_ws_true[0], 1 / FS, trials=6)
    before = filt.q_ws.copy()
    bad = accel.copy()
    bad[5, 100, 2] = np.nan      # last trial of the second (short) block
    with pytest.raises(ValueError, match="accel_m_s2 must be finite"):
        filt.run(rec.gyro_rad_s, bad)
    assert np.array_equal(filt.q_ws, before)
    g = rec.gyro_rad_s.copy()
    g[2, 7, 0] = -np.inf
    with pytest.raises(ValueError, match="gyro_rad_s must be finite"):
        filt.run(g, accel)
    assert np.array_equal(filt.q_ws, before)


def test_qncf_update_per_sample_matches_run():
    rec, accel = _turntable_record(2, vibrate=False)
    g, a = rec.gyro_rad_s[:, :50], accel[:, :50]
    q0 = np.tile(rec.q_ws_true[0], (2, 1))
    filt = QncfFilter(q0, 1 / FS)
    steps = np.stack([filt.update(g[:, k], a[:, k]) for k in range(50)], axis=1)
    assert np.array_equal(steps[:, :-1], QncfFilter(q0, 1 / FS).run(g, a).q_ws[:, 1:])


def test_engine_argument_is_checked():
    with pytest.raises(ValueError, match="engine must be one of"):
        qncf(np.zeros((5, 3)), np.tile([0, 0, 9.8], (5, 1)), 1e-3, engine="cuda")
    with pytest.raises(ValueError, match="engine must be one of"):
        QncfFilter([1.0, 0, 0, 0], 1e-3, engine="c")
    with pytest.raises(ValueError, match="engine must be one of"):
        mahony_marg(np.zeros((1, 5, 3)), np.tile([0, 0, 9.8], (1, 5, 1)), np.ones((1, 5, 3)), 1e-3, engine="")


@pytest.mark.parametrize("engine", ["numba", "numpy"])
def test_fast_input_checks_keep_the_messages(engine):
    acc = np.tile([0.0, 0.0, 9.80665], (20, 1))
    bad = np.zeros((20, 3))
    bad[3, 1] = np.nan
    with pytest.raises(ValueError, match="gyro_rad_s must be finite"):
        qncf(bad, acc, 1e-3, engine=engine)
    with pytest.raises(ValueError, match="must be in rad/s"):
        qncf(np.full((20, 3), 90.0), acc, 1e-3, engine=engine)
    with pytest.raises(ValueError, match="looks like it is in g"):
        qncf(np.zeros((20, 3)), acc / 9.80665, 1e-3, engine=engine)
    with pytest.raises(ValueError, match="last dimension 3"):
        qncf(np.zeros((20, 2)), acc, 1e-3, engine=engine)
    with pytest.raises(TypeError, match="numeric array"):
        qncf("gyro", acc, 1e-3, engine=engine)
    with pytest.raises(ValueError, match="accel_m_s2 must be finite"):
        RamsEkfFilter([1.0, 0, 0], acc[0], 1e-3, SensorsImu().ekf_params(), trials=1, engine=engine).run(
            np.zeros((20, 3)), np.where(bad == 0, acc, np.inf), np.ones(20, bool))


def test_large_record_check_uses_the_parallel_pass():
    x = np.zeros(_kernels_common.PARALLEL_MIN_WORK * 30)
    assert _kernels_common._finite_max_abs(x) == (True, 0.0)
    x[-1] = -np.inf
    assert not _kernels_common._finite_max_abs(x)[0]
    x[-1] = -3.0
    assert _kernels_common._finite_max_abs(x) == (True, 3.0)


# --------------------------------------------------------------------------- RAMS EKF
def _ekf_record(trials: int):
    imu = SensorsImu()
    prof = profiles.step_schedule(np.radians([0.0, 40.0, -25.0, 10.0]), np.radians(40.0), 1.0, imu.fs_hz)
    th = np.broadcast_to(prof.angle_rad[:, 0], (trials, prof.time_s.size))
    rec = simulate_rotation(th, np.broadcast_to(prof.rate_rad_s[:, 0], th.shape),
                            np.broadcast_to(prof.accel_rad_s2[:, 0], th.shape), prof.is_static,
                            RotationSetup(), imu.error_model(), imu.dt_s, 5)
    a0, b0 = initial_state(rec.gyro_rad_s, rec.accel_m_s2, 150)
    # per-trial ZVD-like flags: the truth with a few flipped samples, different per trial
    flags = np.broadcast_to(prof.is_static, th.shape).copy()
    flags[:, ::97] = ~flags[:, ::97]
    flags[1:, ::53] = ~flags[1:, ::53]
    return imu, prof, rec, a0, b0, flags


@pytest.mark.parametrize("use_zvd, per_trial_flags", [(True, True), (True, False), (False, True)])
def test_ekf_numba_agrees_with_numpy_reference(use_zvd, per_trial_flags):
    imu, prof, rec, a0, b0, flags = _ekf_record(3)
    st = flags if per_trial_flags else prof.is_static
    v = RotationSetup().unit_axis()
    kw = dict(bias0_rad_s=b0, use_zvd=use_zvd, theta0_rad=np.array([0.0, 1e-3, -2e-3]))
    fast = run_rams_ekf(rec.gyro_rad_s, rec.accel_m_s2, st, v, a0, imu.dt_s, imu.ekf_params(), **kw)
    ref = run_rams_ekf(rec.gyro_rad_s, rec.accel_m_s2, st, v, a0, imu.dt_s, imu.ekf_params(), engine="numpy", **kw)
    np.testing.assert_allclose(fast.theta_rad, ref.theta_rad, rtol=0, atol=TOL_RAD)
    np.testing.assert_allclose(fast.bias_rad_s, ref.bias_rad_s, rtol=0, atol=TOL_RAD)
    np.testing.assert_allclose(fast.innovation_m_s2, ref.innovation_m_s2, rtol=0, atol=1e-11)
    for name in ("p_theta_rad2", "P", "S", "K"):
        np.testing.assert_allclose(getattr(fast, name), getattr(ref, name), rtol=1e-10, atol=1e-18, err_msg=name)


def test_ekf_bit_identical_for_any_thread_count_and_chunking(all_parallel, threads):
    imu, prof, rec, a0, b0, flags = _ekf_record(4)
    v = RotationSetup().unit_axis()
    results = []
    for n_threads in sorted({1, min(2, numba.config.NUMBA_NUM_THREADS)}):
        threads(n_threads)
        results.append(run_rams_ekf(rec.gyro_rad_s, rec.accel_m_s2, flags, v, a0, imu.dt_s, imu.ekf_params(),
                                    bias0_rad_s=b0))
    for res in results[1:]:
        assert np.array_equal(res.theta_rad, results[0].theta_rad) and np.array_equal(res.P, results[0].P)
    filt = RamsEkfFilter(v, a0, imu.dt_s, imu.ekf_params(), trials=4, bias0_rad_s=b0)
    n = rec.gyro_rad_s.shape[1]
    cuts = [0, 1, 333, 334, n // 2, n]
    parts = [filt.run(rec.gyro_rad_s[:, i:j], rec.accel_m_s2[:, i:j], flags[:, i:j]) for i, j in zip(cuts, cuts[1:])]
    assert np.array_equal(np.concatenate([p.theta_rad for p in parts], axis=1), results[0].theta_rad)
    assert np.array_equal(np.concatenate([p.innovation_m_s2 for p in parts], axis=1), results[0].innovation_m_s2)
    assert np.array_equal(parts[-1].P, results[0].P) and np.array_equal(parts[-1].K, results[0].K)


def test_ekf_dynamic_schedule_runs_every_block_once(all_parallel, threads):
    """Many blocks taken from the shared counter by 2 threads: every output equals the serial kernel's."""
    from mtcal.filters import _kernels_ekf as K

    imu, prof, rec, a0, b0, flags = _ekf_record(4)
    reps = 11                                              # 44 trials: several blocks per thread, a short last one
    g, a = np.tile(rec.gyro_rad_s, (reps, 1, 1)), np.tile(rec.accel_m_s2, (reps, 1, 1))
    v = RotationSetup().unit_axis()
    threads(min(2, numba.config.NUMBA_NUM_THREADS))
    whole = run_rams_ekf(g, a, np.tile(flags, (reps, 1)), v, np.tile(a0, (reps, 1)), imu.dt_s, imu.ekf_params(),
                         bias0_rad_s=np.tile(b0, (reps, 1)))
    calls = []
    serial = K.ekf_serial
    monkey = pytest.MonkeyPatch()
    monkey.setattr(K, "ekf_parallel", lambda *args: calls.append(1) or serial(*args))
    try:
        ref = run_rams_ekf(g, a, np.tile(flags, (reps, 1)), v, np.tile(a0, (reps, 1)), imu.dt_s, imu.ekf_params(),
                           bias0_rad_s=np.tile(b0, (reps, 1)))
    finally:
        monkey.undo()
    assert calls == [1]                                    # the first call did take the parallel kernel
    for name in ("theta_rad", "bias_rad_s", "p_theta_rad2", "innovation_m_s2", "P", "S", "K"):
        assert np.array_equal(getattr(whole, name), getattr(ref, name)), name


# with 8 lanes (AVX-512 hosts): partial blocks (2-7), a full block + a lone scalar trial (9), full + partial (13),
# two full blocks + a lone trial (17); with 4 lanes: full + partial (7), several blocks + a lone trial (9, 13, 17)
@pytest.mark.parametrize("trials, per_trial_flags", [(2, True), (3, False), (5, True), (7, False), (9, True),
                                                     (13, False), (17, True)])
def test_ekf_batched_lanes_are_bit_identical_to_each_trial_alone(all_parallel, trials, per_trial_flags):
    imu, prof, rec, a0, b0, flags = _ekf_record(trials)
    st = flags if per_trial_flags else prof.is_static
    v = RotationSetup().unit_axis()
    theta0 = np.linspace(-2e-3, 2e-3, trials)
    batch = run_rams_ekf(rec.gyro_rad_s, rec.accel_m_s2, st, v, a0, imu.dt_s, imu.ekf_params(), bias0_rad_s=b0,
                         theta0_rad=theta0)
    for t in range(trials):
        i = slice(t, t + 1)
        one = run_rams_ekf(rec.gyro_rad_s[i], rec.accel_m_s2[i], st[i] if per_trial_flags else st, v, a0[i],
                           imu.dt_s, imu.ekf_params(), bias0_rad_s=b0[i], theta0_rad=theta0[i])
        for name in ("theta_rad", "bias_rad_s", "p_theta_rad2", "innovation_m_s2", "P", "S", "K"):
            assert np.array_equal(getattr(one, name)[0], getattr(batch, name)[t]), (t, name)


def _ekf_kernel_args(trials: int, keep_y: bool):
    """Direct arguments of the EKF kernels (per-trial flags, a carried previous gyro sample, keep_y)."""
    imu, prof, rec, a0, b0, flags = _ekf_record(trials)
    filt = RamsEkfFilter(RotationSetup().unit_axis(), a0, imu.dt_s, imu.ekf_params(), trials=trials,
                         bias0_rad_s=b0, theta0_rad=np.linspace(-2e-3, 2e-3, trials))
    n, m = trials, rec.gyro_rad_s.shape[1]
    consts = tuple(np.ascontiguousarray(x.T) for x in (filt._v, filt._par, filt._perp, filt._nperp, filt._w, filt._f))
    om = np.linspace(-1e-4, 1e-4, n)
    return [rec.gyro_rad_s, rec.accel_m_s2, np.ascontiguousarray(flags), *consts, filt._theta.copy(),
            np.ascontiguousarray(filt._bias.T), np.ascontiguousarray(filt._p.T), om, True, True,
            float(filt._var[0]), float(filt._var[1]), imu.dt_s, float(filt._q_theta), float(filt._q_b),
            np.full((n, m), np.nan), np.full((n, m, 3), np.nan), np.full((n, m), np.nan),
            np.full((n, m, 3), np.nan) if keep_y else np.empty((1, 1, 3)), keep_y, np.full((n, 4), np.nan),
            np.full((n, 3), np.nan), np.full(n, np.nan), np.full((n, 4), np.nan)]


@pytest.mark.parametrize("keep_y", [True, False])
def test_ekf_blocks_of_4_and_8_lanes_are_bit_identical_to_the_scalar_trial(keep_y):
    """Both block widths (whichever LANES this host compiles), spare lanes repeating the last trial,
    reproduce the scalar kernel bit for bit: state, histories, last c/h'/s and the input scan."""
    from mtcal.filters import _kernels_ekf as K

    ref = _ekf_kernel_args(5, keep_y)
    K.ekf_one(*ref)
    for rows in ((0, 1, 2, 3), (1, 2, 3, 4), (0, 1, 2, 3, 4, 4, 4, 4), (2, 3, 4, 4, 4, 4, 4, 4)):
        got = _ekf_kernel_args(5, keep_y)
        K._block(got[0], got[1], got[2], rows, *got[3:])
        for i, (x, y) in enumerate(zip(ref[9:], got[9:])):
            if isinstance(x, np.ndarray) and x.shape[:1] == (5,):
                r = sorted(set(rows))
                assert np.array_equal(x[r], y[r]), (rows, i)
                other = sorted(set(range(5)) - set(r))
                assert np.isnan(y[other]).all() or i < 4, (rows, i)  # untouched rows keep their fill


def test_ekf_non_finite_sample_in_one_lane_raises(all_parallel):
    imu, prof, rec, a0, b0, flags = _ekf_record(3)
    g = rec.gyro_rad_s.copy()
    g[2, 50, 1] = np.nan
    with pytest.raises(ValueError, match="gyro_rad_s must be finite"):
        run_rams_ekf(g, rec.accel_m_s2, flags, RotationSetup().unit_axis(), a0, imu.dt_s, imu.ekf_params())


# --------------------------------------------------------------------------- MARG (AHRS stand-in)
def _marg_record(trials: int):
    rng = np.random.default_rng(8)
    n, dt = 4000, 1 / 200
    t = np.arange(n) * dt
    th = np.radians(35.0) * np.sin(2 * np.pi * 0.15 * t)
    v = np.array([0.1734, 0.9835, 0.0523]) / np.linalg.norm([0.1734, 0.9835, 0.0523])
    theta = np.broadcast_to(th, (trials, n))
    mag = simulate_magnetometer(theta, v, (1.0, 0, 0, 0), MagneticDisturbance(), dt, rng)
    acc = np.einsum("nji,j->ni", rotations.axis_angle_matrix(th, v), [0.0, 0.0, 9.80665])
    acc = acc + 0.03 * rng.standard_normal((trials, n, 3))
    gyro = np.gradient(th, dt)[None, :, None] * v + 2e-3 * rng.standard_normal((trials, n, 3))
    return gyro, acc, mag, dt, v


def test_marg_numba_agrees_with_numpy_reference_and_threads(all_parallel, threads):
    gyro, acc, mag, dt, v = _marg_record(3)
    fast = mahony_marg(gyro, acc, mag, dt)
    ref = mahony_marg(gyro, acc, mag, dt, engine="numpy")
    np.testing.assert_allclose(fast, ref, rtol=0, atol=TOL_RAD)
    np.testing.assert_allclose(angle_from_orientation(fast, v, 0), angle_from_orientation(ref, v, 0),
                               rtol=0, atol=TOL_RAD)
    threads(1)
    assert np.array_equal(mahony_marg(gyro, acc, mag, dt), fast)


# --------------------------------------------------------------------------- numba cache fallback
def test_jit_falls_back_to_no_cache_when_caching_is_impossible():
    # a function without a source file (exec) has no cache locator: numba refuses cache=True
    ns = {}
    exec("def twice(x):\n    return 2.0 * x\n", ns)
    with pytest.warns(RuntimeWarning, match="cannot cache"):
        fn = _kernels_common.jit()(ns["twice"])
    assert fn(1.5) == 3.0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert _kernels_common.jit()(_double)(2.0) == 4.0  # a normal module function caches silently


def _double(x):
    return 2.0 * x


def test_kernels_work_when_no_cache_directory_is_writable(tmp_path):
    """A read-only install with an unwritable home: the import picks a temporary cache dir and runs."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    env = dict(os.environ, HOME=str(tmp_path / "no-home"), PYTHONPATH=str(root))
    env.pop("NUMBA_CACHE_DIR", None)
    code = ("import os, numpy as np; from mtcal.filters.qncf import qncf; "
            "r = qncf(np.zeros((50, 3)), np.tile([0, 0, 9.80665], (50, 1)), 1e-3); "
            "print(r.q_ws.shape, os.environ.get('NUMBA_CACHE_DIR') is not None or os.access(os.path.dirname("
            "__import__('mtcal').__file__), os.W_OK))")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.strip() == "(50, 4) True"


def test_warm_up_all_compiles_every_kernel_group():
    from mtcal.filters.kernels import warm_up_all

    times = warm_up_all()
    assert set(times) == {"qncf", "rams_ekf", "marg", "tilt_rate", "gyro_roll", "large_angle", "rest_detection",
                          "csv_text", "simulate", "metrics", "rotations"}
    assert all(v >= 0.0 for v in times.values())
