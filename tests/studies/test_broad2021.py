"""broad2021: trial loader, BROAD's published 9D numbers reproduced, the 6D runs, the blind twin."""

import numpy as np
import pandas as pd
import pytest

from mtcal.core import metrics
from mtcal.reporting import paper_numbers
from mtcal.studies import broad2021 as b
from mtcal.studies.broad2021 import artifacts, error_model, runs, scenario

FIRST = "01_undisturbed_slow_rotation_A"


@pytest.fixture(scope="module")
def trial():
    return scenario.load_trials([FIRST])[0]


def test_loader_reads_every_shipped_trial_with_groups():
    names = scenario.trial_names()
    assert len(names) == 14 and names[0] == FIRST
    tr = scenario.load_trials(names[-1:])[0]
    assert tr.gyro_rad_s.shape == (tr.n, 3) and tr.opt_quat.shape == (tr.n, 4) and tr.movement.dtype == bool
    assert abs(tr.fs_hz - 285.714) < 0.01 and "attached_magnet" in tr.groups


def test_data_dir_env_and_clear_error(tmp_path, monkeypatch):
    monkeypatch.setenv(scenario.DATA_ENV, str(tmp_path))
    with pytest.raises(FileNotFoundError, match="BROAD data not found in .*MTCAL_BROAD_DIR"):
        scenario.data_dir()


def test_trial_from_arrays_errors():
    with pytest.raises(ValueError, match=r"arrays \['imu_acc', 'imu_mag'"):
        scenario.trial_from_arrays("x", {"imu_gyr": np.zeros((3, 3))})
    arrays = {"imu_gyr": np.zeros((4, 3)), "imu_acc": np.zeros((4, 3)), "imu_mag": np.zeros((4, 3)),
              "opt_quat": np.zeros((4, 3)), "opt_pos": np.zeros((4, 3)), "movement": np.zeros(4),
              "sampling_rate": np.array(100.0)}
    with pytest.raises(ValueError, match=r"opt_quat must have shape \(4, 4\)"):
        scenario.trial_from_arrays("x", arrays)


def test_scenario_validation():
    with pytest.raises(ValueError, match="trials must be shipped BROAD trials"):
        scenario.scenario_from_parameters(trials=["nope"])
    with pytest.raises(ValueError, match="filters must be among"):
        scenario.scenario_from_parameters(filters=["kalman"])
    with pytest.raises(ValueError, match="not a valid broad2021 parameter|broad2021 parameter"):
        scenario.scenario_from_parameters(speed=1)


def test_published_9d_numbers_reproduced_on_first_trial(trial):
    pub = paper_numbers.load("broad2021_published_rmse")
    res = runs.run_9d(trial, [0.12], [0.74], [0.0012])
    for f in ("madgwick", "mahony"):
        row = pub[(pub["filter"] == f) & (pub["trial"] == FIRST)].iloc[0]
        want = row[["total_rmse_deg", "heading_rmse_deg", "inclination_rmse_deg"]].to_numpy(float)
        assert np.abs(res[f][:, 0] - want).max() <= artifacts.TOLERANCE_DEG
    # a wrong frame convention (no 90° rotation into ENU) must break the heading/total agreement
    from mtcal.filters import xio_ahrs
    q0 = xio_ahrs.initial_quaternion_acc_mag(trial.accel_m_s2[0], trial.mag_uT[0])
    q = xio_ahrs.madgwick(trial.gyro_rad_s, trial.accel_m_s2, trial.dt_s, 0.12, mag_uT=trial.mag_uT, q0=q0)[0]
    wrong = runs.rmse_deg(q, trial)
    assert abs(wrong[1] - pub[(pub["filter"] == "madgwick") & (pub["trial"] == FIRST)].heading_rmse_deg.iloc[0]) > 10


def test_batched_errors_equal_the_core_metric(trial):
    q = np.stack([trial.opt_quat, np.roll(trial.opt_quat, 7, axis=0)])[:, :3000]
    q = np.where(np.isfinite(q), q, 1.0)
    batch = runs.errors_deg(q, trial.opt_quat[:3000])
    for i in range(2):
        ref = np.degrees(np.stack(metrics.orientation_errors(q[i], trial.opt_quat[:3000])))
        np.testing.assert_allclose(batch[:, i], ref, atol=1e-9, equal_nan=True)
    # the inclination alone (what the twin reads) is the same numbers, bit for bit, batched and single
    only = runs.errors_deg(q, trial.opt_quat[:3000], inclination_only=True)
    assert only.shape == (1, 2, 3000) and np.array_equal(only[0], batch[2], equal_nan=True)
    single = runs.errors_deg(q[0], trial.opt_quat[:3000])
    assert np.array_equal(runs.errors_deg(q[0], trial.opt_quat[:3000], inclination_only=True)[0], single[2],
                          equal_nan=True)
    qf = np.stack([trial.opt_quat, np.roll(trial.opt_quat, 7, axis=0)])
    qf = np.where(np.isfinite(qf), qf, 1.0)
    assert np.array_equal(runs.rmse_deg(qf, trial, inclination_only=True), runs.rmse_deg(qf, trial)[2:])


def test_madgwick_6d_matches_the_ahrs_anchor_adapter(trial):
    pytest.importorskip("ahrs")
    from mtcal.filters.anchors import run_attitude_filter

    g, a = trial.gyro_rad_s[:1500], trial.accel_m_s2[:1500]
    ours = runs.run_6d("madgwick", g, a, trial.dt_s)
    anchor = run_attitude_filter("madgwick", g[None], a[None], trial.dt_s, reference=True)[0]   # ahrs itself
    assert np.abs(ours - anchor).max() < 1e-10


def test_run_6d_every_filter_small_record(trial):
    g, a = trial.gyro_rad_s[:2000], trial.accel_m_s2[:2000]
    for f in scenario.FILTERS_6D:
        q = runs.run_6d(f, g, a, trial.dt_s)
        assert q.shape == (2000, 4) and np.allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-5)
    with pytest.raises(ValueError, match="name must be one of"):
        runs.run_6d("kalman", g, a, trial.dt_s)


def test_twin_is_blind_and_deterministic(trial, monkeypatch):
    p1 = error_model.predict_real_error(trial, "mahony", n_draws=2, seed=5)
    p2 = error_model.predict_real_error(trial, "mahony", n_draws=2, seed=5)
    assert np.array_equal(p1.rmse_deg, p2.rmse_deg) and p1.band["kind"] == "range"
    # blind: garbage in the IMU samples of the movement phase leaves the prediction unchanged
    moving = ~np.zeros(trial.n, bool)
    moving[runs.initial_rest(trial)] = False
    g = trial.gyro_rad_s.copy(); g[moving] = 5.0
    a = trial.accel_m_s2.copy(); a[moving] = -30.0
    spoiled = scenario.Trial(trial.name, g, a, trial.mag_uT, trial.opt_quat, trial.opt_pos_m, trial.movement,
                             trial.fs_hz, trial.groups)
    p3 = error_model.predict_real_error(spoiled, "mahony", n_draws=2, seed=5)
    assert np.array_equal(p1.rmse_deg, p3.rmse_deg)
    other = error_model.predict_real_error(trial, "mahony", n_draws=2, seed=6)
    assert not np.array_equal(p1.rmse_deg, other.rmse_deg)


def test_rest_model_identifies_injected_bias(trial):
    g = trial.gyro_rad_s + np.array([0.01, -0.02, 0.0])
    shifted = scenario.Trial(trial.name, g, trial.accel_m_s2, trial.mag_uT, trial.opt_quat, trial.opt_pos_m,
                             trial.movement, trial.fs_hz, trial.groups)
    d = error_model.identify_rest_model(shifted).gyro_bias_rad_s - error_model.identify_rest_model(trial).gyro_bias_rad_s
    np.testing.assert_allclose(d, [0.01, -0.02, 0.0], atol=1e-12)
    short = scenario.Trial("s", trial.gyro_rad_s[:500], trial.accel_m_s2[:500], trial.mag_uT[:500],
                           trial.opt_quat[:500], trial.opt_pos_m[:500], np.ones(500, bool), trial.fs_hz)
    with pytest.raises(ValueError, match="initial rest shorter than 1 s"):
        error_model.identify_rest_model(short)


def test_run_study_ci_slice_and_producers():
    sc = scenario.scenario_from_parameters(trials=scenario.trial_names()[:2], filters=["mahony", "vqf", "qncf_paper"],
                                           n_draws=2, max_samples=16000)
    run = artifacts.run_study(sc, 1)
    rep = b.table_published_vs_ours(run)
    assert rep.artifact_id == "broad2021_extra_published_vs_ours" and len(rep.rows) == 12 + 1
    assert all(r["role"] == "heldout" for r in rep.rows)
    # one claim for the case study, the 12 numbers as checks (a failing one is shown, never counted as a claim)
    claims = [r for r in rep.rows if r["kind"] == "claim"]
    assert len(claims) == 1 and claims[0]["check"](12) and not claims[0]["check"](11)
    assert all(r["kind"] == "" and r["holds"] is not None for r in rep.rows[:-1])
    rk = b.extra_rankings(run)
    assert {"verdict", "holds_in", "wilson_low"} <= set(rk.table.columns)
    # the QNCF/VQF pair is one claim (the order flips with vibration); its two directions are shown, not counted
    members = {m for _, ms, _ in artifacts.RANKING_PAIRS for m in ms}
    assert all(r["kind"] == "" for r in rk.rows if r["quantity"].split(":")[0] in members)
    for pid, ms, _ in artifacts.RANKING_PAIRS:
        pair = [r for r in rk.rows if r["quantity"].startswith(f"{pid}:")]
        verdict = dict(zip(rk.table.ranking, rk.table.verdict))
        if all(m in verdict for m in ms):
            assert len(pair) == 1 and pair[0]["kind"] == "claim"
            assert pair[0]["holds"] == all(verdict[m] == "holds" for m in ms)
    tw = b.extra_twin(run)
    assert set(tw.table["filter"]) == {"mahony", "vqf", "qncf_paper"}
    assert isinstance(b.extra_bakeoff_6d(run).table, pd.DataFrame)
    with pytest.raises(ValueError, match="seed must be a non-negative integer"):
        artifacts.run_study(sc, -1)


def test_twin_mount_tilt_keeps_noise_and_validates(trial):
    short = scenario.trial_head(trial, 12000)
    r0, _, _ = error_model.simulate_twin(short, 2, 3)
    r1, _, _ = error_model.simulate_twin(short, 2, 3, mount_tilt_rad=0.0)
    assert np.array_equal(r0.gyro_rad_s, r1.gyro_rad_s)
    r2, _, _ = error_model.simulate_twin(short, 2, 3, mount_tilt_rad=np.radians(0.3))
    assert r2.gyro_rad_s.shape == r0.gyro_rad_s.shape and not np.array_equal(r0.accel_m_s2, r2.accel_m_s2)
    with pytest.raises(ValueError, match="mount_tilt_rad must be finite and >= 0"):
        error_model.simulate_twin(short, 2, 3, mount_tilt_rad=-1.0)
    with pytest.raises(TypeError, match="time_offset_samples must be integers"):
        error_model.simulate_twin(short, 2, 3, time_offset_samples=0.5)
    # a per-draw time offset shifts that draw only; its noise numbers stay those of the blind twin's draw
    r3, _, _ = error_model.simulate_twin(short, 2, 3, time_offset_samples=np.array([0, -2]))
    assert np.array_equal(r3.gyro_rad_s[0], r0.gyro_rad_s[0])
    assert np.array_equal(r3.gyro_rad_s[1, 2:], r0.gyro_rad_s[1, :-2])


def test_twin_gaps_find_injected_scale_and_offset(trial):
    from mtcal.core.simulate import Trajectory, body_rates

    short = scenario.trial_head(trial, 20000)
    truth = error_model.twin_truth(short)
    w = body_rates(Trajectory(np.arange(short.n) * short.dt_s, truth.q_ws))
    a = np.diag([1.01, 0.99, 1.0])
    g = (w @ a.T)[np.clip(np.arange(short.n) - 3, 0, short.n - 1)]
    fake = scenario.Trial(short.name, g, short.accel_m_s2, short.mag_uT, short.opt_quat, short.opt_pos_m,
                          short.movement, short.fs_hz, short.groups)
    gaps = error_model.twin_gaps(fake)
    assert abs(gaps["gyro_scale_pct"] - 2.0 / 3.0) < 0.05 and abs(gaps["time_offset_ms"] + 3000 * short.dt_s) < 1e-9


def test_hdf5_trials_load_like_the_mat_ones(tmp_path):
    """BROAD ships every trial as .mat and as .hdf5 (same data): a folder of .hdf5 trials (here the first
    2000 samples of trial 01 written with h5py, the rate as a root attribute) loads with its groups."""
    import shutil

    h5py = pytest.importorskip("h5py")
    from mtcal.core.arrayfile import read_arrays

    name = "01_undisturbed_slow_rotation_A"
    src = scenario.data_dir()
    arrays = read_arrays(src / "trials" / f"{name}.mat")
    (tmp_path / "trials").mkdir()
    shutil.copy(src / "trials.json", tmp_path / "trials.json")
    with h5py.File(tmp_path / "trials" / f"{name}.hdf5", "w") as f:
        for k, v in arrays.items():
            if k != "sampling_rate":
                f[k] = v[:2000]
        f.attrs["sampling_rate"] = float(arrays["sampling_rate"])
    assert scenario.trial_names(tmp_path) == [name]
    (h5,) = scenario.load_trials(folder=tmp_path)
    mat = scenario.trial_head(scenario.load_trials([name])[0], 2000)
    assert h5.groups == mat.groups and h5.fs_hz == mat.fs_hz
    for field in ("gyro_rad_s", "accel_m_s2", "mag_uT", "opt_quat", "opt_pos_m", "movement"):
        np.testing.assert_array_equal(getattr(h5, field), getattr(mat, field))


def _errors_deg_numpy(q, r, inclination_only=False):
    """The numpy expressions of the batch branch of runs.errors_deg (reference for its compiled pass)."""
    r = r / np.linalg.norm(r, axis=-1, keepdims=True)
    q = q / np.sqrt(np.einsum("...i,...i->...", q, q))[..., None]
    w = np.einsum("...i,...i->...", q, r)
    z = -q[..., 0] * r[:, 3] - q[..., 1] * r[:, 2] + q[..., 2] * r[:, 1] + q[..., 3] * r[:, 0]
    nrm = np.sqrt(w * w + z * z)
    with np.errstate(invalid="ignore", divide="ignore"):
        incl = 2.0 * np.arccos(np.clip(nrm, 0.0, 1.0))
        if inclination_only:
            return np.degrees(incl[None])
        total = 2.0 * np.arccos(np.clip(np.abs(w), 0.0, 1.0))
        heading = 2.0 * np.arctan(np.abs(z / w))
    return np.degrees(np.stack([total, heading, incl]))


@pytest.mark.parametrize("order", ["C", "F"])       # F: a MATLAB trial's optical quaternions
@pytest.mark.parametrize("inclination_only", [False, True])
def test_errors_deg_compiled_pass_bit_identical(order, inclination_only):
    rng = np.random.default_rng(6)
    n = 3000
    ref = np.asarray(rng.normal(size=(n, 4)), order=order)
    ref[10:20] = np.nan                                          # optical gaps
    q = rng.normal(size=(3, n, 4)) * np.exp(rng.normal(size=(3, n, 1)))
    q[0, :3] = 0.0                                               # 0/0: numpy's NaN
    q[1, 30], ref[30] = [0.0, 0.0, 0.0, 1.0], [1.0, 0.0, 0.0, 0.0]   # w = 0: heading 180 deg
    with np.errstate(invalid="ignore", divide="ignore"):
        got = runs.errors_deg(q, ref, inclination_only=inclination_only)
        want = _errors_deg_numpy(q, ref, inclination_only)
    assert got.tobytes() == want.tobytes()


def test_rmse_deg_rows_equal_rmse_over_phase(trial):
    rng = np.random.default_rng(8)
    q = np.ascontiguousarray(trial.opt_quat[None] + 0.02 * rng.normal(size=(2,) + trial.opt_quat.shape))
    q = np.where(np.isfinite(q), q, 1.0)
    got = runs.rmse_deg(q, trial)
    e = runs.errors_deg(q, trial.opt_quat)
    want = np.array([[metrics.rmse_over_phase(e[m, lane], trial.movement) for lane in range(2)] for m in range(3)])
    assert got.tobytes() == want.tobytes()
