"""Tests for mtcal.systems.installation: the six-position calibration procedure shared by CLI, study and sweep."""

import json
from dataclasses import fields, replace

import numpy as np
import pandas as pd
import pytest

from mtcal import cli
from mtcal.core import rotations
from mtcal.core.profiles import trajectory_from_euler_zxy
from mtcal.core.simulate import ImuErrorModel, simulate_imu
from mtcal.filters.qncf import QncfParams, qncf
from mtcal.methods import six_position
from mtcal.methods.six_position import schedule_profile, six_positions_rad
from mtcal.systems import installation
from mtcal.systems.rests import RestsConfig

FS = 100.0
DT_S = 1.0 / FS
ALPHA = np.radians([0.5, -0.3, 0.4])
Config = installation.InstallationConfig
PAPER = Config.paper()


@pytest.fixture(scope="module")
def stream():
    """Noise-free six-position record: positions (6, 3), truth q_wb (N, 4), sensor q_ws (N, 4), q_bs."""
    pos = six_positions_rad()
    q_wb = trajectory_from_euler_zxy(schedule_profile(pos, fs_hz=FS)).q_wb
    q_bs = rotations.mount_quaternion(ALPHA)
    return pos, q_wb, rotations.quat_multiply(q_wb, q_bs), q_bs


def test_closed_form_mounting_is_recovered(stream):
    pos, _, q_ws, q_bs = stream
    cal = installation.calibrate_installation(PAPER, pos, DT_S, q_ws=q_ws)
    # zeroed sensor = q_bs* ⊗ q_b ⊗ q_bs (the body starts level), so Q = L(q_bs) R(q_bs*)
    expected = rotations.left_matrix(q_bs) @ rotations.right_matrix(rotations.quat_conjugate(q_bs))
    assert np.allclose(cal.q_hat, expected, atol=1e-12)
    assert np.allclose(cal.installation_angles_rad, ALPHA, atol=1e-12)
    assert np.allclose(np.abs(cal.mounting_quaternion_q_bs @ q_bs), 1.0, atol=1e-12)
    assert cal.residual_rad.max() < 1e-12 and float(cal.so4_distance) < 1e-12
    assert np.abs(cal.error_after_rad).max() < 1e-12 and np.abs(cal.error_before_rad).max() > np.radians(0.3)
    assert [cal.rests[i] for i in cal.matched] == cal.matched_rests and len(cal.matched_rests) == 6
    assert np.allclose(cal.positions_rad, pos) and cal.condition < installation.MAX_CONDITION


def test_apply_round_trip_gives_the_body_attitude(stream):
    pos, q_wb, q_ws, _ = stream
    cal = installation.calibrate_installation(PAPER, pos, DT_S, q_ws=q_ws)
    att = installation.apply_installation(PAPER, cal.q_hat, q_ws=q_ws)
    assert rotations.quat_angle_between(att.q_body, q_wb).max() < 1e-10
    assert np.allclose(att.q_sensor[0], [1, 0, 0, 0], atol=1e-15)          # zeroed at the first sample
    assert np.all(np.sum(att.q_body[1:] * att.q_body[:-1], axis=-1) >= 0)  # sign-continuous


def test_raw_data_runs_the_qncf_and_equals_given_attitude(stream):
    pos, q_wb, _, q_bs = stream
    from mtcal.core.simulate import Trajectory

    rec = simulate_imu(Trajectory(np.arange(len(q_wb)) / FS, q_wb), ImuErrorModel(q_mount=tuple(q_bs)))
    raw = installation.calibrate_installation(PAPER, pos, DT_S, gyro_rad_s=rec.gyro_rad_s, accel_m_s2=rec.accel_m_s2)
    q = qncf(rec.gyro_rad_s, rec.accel_m_s2, 1 / FS, QncfParams(), return_euler=False).q_ws
    given = installation.calibrate_installation(PAPER, pos, DT_S, q_ws=q, gyro_rad_s=rec.gyro_rad_s)
    assert np.array_equal(raw.q_hat, given.q_hat)
    assert np.degrees(np.abs(raw.installation_angles_rad - ALPHA)).max() < 0.01
    body = installation.apply_installation(PAPER, raw.q_hat, DT_S, gyro_rad_s=rec.gyro_rad_s,
                                           accel_m_s2=rec.accel_m_s2)
    assert np.array_equal(body.q_body, installation.apply_installation(PAPER, raw.q_hat, q_ws=q).q_body)


def test_trial_axis_and_per_trial_positions_match_single_runs(stream):
    pos, _, q_ws, _ = stream
    shift = np.zeros((2, 6, 3))
    shift[1, 2, 1] = np.radians(0.01)
    stack = installation.calibrate_installation(PAPER, pos + shift, DT_S, q_ws=np.stack([q_ws, q_ws]))
    for t in range(2):
        one = installation.calibrate_installation(PAPER, pos + shift[t], DT_S, q_ws=q_ws)
        assert np.allclose(stack.q_hat[t], one.q_hat, atol=1e-14, rtol=0)
        assert np.allclose(stack.residual_rad[t], one.residual_rad, atol=1e-14)
    assert stack.q_hat.shape == (2, 4, 4) and stack.installation_angles_rad.shape == (2, 3)


def test_detect_rests_gyro_and_quaternions(stream):
    pos, _, q_ws, _ = stream
    from_q = installation.detect_rests(PAPER, DT_S, q_ws=q_ws)
    assert len(from_q) == 8                                # start, six positions, end
    gyro = np.zeros((1000, 3))
    gyro[300:500, 2] = 0.5
    assert installation.detect_rests(PAPER, 1.0 / 100.0, gyro_rad_s=gyro) == [slice(0, 296), slice(505, 1000)]
    assert installation.detect_rests(Config(min_rest_s=4.0), 1.0 / 100.0, gyro_rad_s=gyro) == [slice(505, 1000)]


def test_given_rests_are_used(stream):
    pos, _, q_ws, _ = stream
    rests = installation.detect_rests(PAPER, DT_S, q_ws=q_ws)
    a = installation.calibrate_installation(PAPER, pos, DT_S, q_ws=q_ws, rests=rests)
    b = installation.calibrate_installation(PAPER, pos, DT_S, q_ws=q_ws)
    assert np.array_equal(a.q_hat, b.q_hat)


CONFIG_FIELDS = {f.name for f in fields(installation.InstallationConfig)}


@pytest.mark.parametrize("kwargs, exc, match", [
    (dict(positions_rad=six_positions_rad()[:3]), ValueError, "at least 4 positions"),
    (dict(dt_s=-1.0), ValueError, "dt_s must be > 0"),
    (dict(dt_s=100.0), ValueError, r"dt_s must be the sample interval in s .* pass 1 / fs_hz"),
    (dict(q_ws=None), ValueError, "a sensor attitude is needed"),
    (dict(accel_m_s2=np.zeros((10, 3))), ValueError, "either q_ws"),
    (dict(q_ws=np.ones((10, 4))), ValueError, "unit quaternions"),
    (dict(q_ws=np.tile([1.0, 0, 0, 0], (2, 2, 3, 1))), ValueError, r"\(N, 4\) or \(T, N, 4\)"),
    (dict(gyro_rad_s=np.zeros((7, 3))), ValueError, "gyro_rad_s has 7 samples"),
    (dict(rests=[slice(0, 10**7)]), ValueError, "rests must be slices"),
    (dict(fraction=1.5), ValueError, r"fraction must be in \(0, 1\]"),
    (dict(max_condition=0.0), ValueError, "max_condition must be a positive number"),
    (dict(max_so4_distance="big"), ValueError, "max_so4_distance must be a positive number"),
    (dict(max_residual_rad=-1.0), ValueError, "max_residual_rad must be a positive number"),
    (dict(positions_rad=np.zeros((2, 6, 3))), ValueError, "needs a record with 2 trials"),
    (dict(min_rest_s=100.0), ValueError, "too few rests"),
    (dict(max_match_rad=np.radians(1e-6), positions_rad=six_positions_rad() + 0.001), ValueError,
     "has no rest within"),
])
def test_calibrate_errors(stream, kwargs, exc, match):
    pos, _, q_ws, _ = stream
    args = dict(positions_rad=pos, dt_s=DT_S, q_ws=q_ws)
    args.update(kwargs)
    settings = {k: args.pop(k) for k in list(args) if k in CONFIG_FIELDS}
    with pytest.raises(exc, match=match):      # a setting is refused when the config is made, data at the call
        installation.calibrate_installation(Config(**settings), args.pop("positions_rad"),
                                            args.pop("dt_s"), **args)


def test_raw_data_errors(stream):
    pos = stream[0]
    g = np.zeros((50, 3))
    with pytest.raises(ValueError, match="same shape"):
        installation.calibrate_installation(PAPER, pos, DT_S, gyro_rad_s=g, accel_m_s2=np.zeros((49, 3)))
    with pytest.raises(TypeError, match="qncf_params must be a QncfParams"):
        Config(qncf_params={"kp": 1})
    with pytest.raises(ValueError, match="a sensor attitude is needed"):
        installation.calibrate_installation(PAPER, pos, DT_S, gyro_rad_s=g)


def test_gates_refuse_with_their_messages(stream):
    pos, _, q_ws, _ = stream
    with pytest.raises(ValueError, match="ill-conditioned for Eq 13"):
        installation.calibrate_installation(Config(max_condition=1.0), pos, DT_S, q_ws=q_ws)
    with pytest.raises(ValueError, match="Q_hat is not a calibration: distance"):
        installation.calibrate_installation(Config(max_so4_distance=1e-300), pos, DT_S, q_ws=q_ws)
    bent = pos.copy()
    bent[2, 1] += np.radians(0.5)                            # the reference of position 3 is off by 0.5 deg
    with pytest.raises(ValueError, match=r"residual 0\.\d+ deg at position \d exceeds max_residual_rad \(0\.01 deg\)"):
        installation.calibrate_installation(Config(max_residual_rad=np.radians(0.01)), bent, DT_S,
                                            q_ws=q_ws)
    ok = installation.calibrate_installation(Config(max_residual_rad=np.inf), bent, DT_S, q_ws=q_ws)
    assert np.degrees(ok.residual_rad.max()) > 0.01


def _rest_fit(q_hat, q_s, q_ref, gate=True):
    """A fit of :func:`six_position._fit_rests`' shape, for the core steps after it."""
    from mtcal.methods.constrained_fit import project_to_so4

    return six_position._RestFit(q_hat, project_to_so4(q_hat), np.ones(()), np.zeros((q_s.shape[0], 3)), q_ref,
                                 [slice(0, 1)] * q_s.shape[0], np.arange(q_s.shape[0]), q_s, q_s, q_s, gate)


def test_gate_refuses_zero_row_matrix_and_large_residual():
    bad = np.eye(4)
    bad[2] = 0.0
    bad[0, 1] = 10.0
    from mtcal.methods.constrained_fit import project_to_so4

    q = np.tile([1.0, 0.0, 0.0, 0.0], (6, 1))
    with pytest.raises(ValueError, match="Q_hat is not a calibration: distance .* min row norm 0"):
        six_position._gate_distance(bad, project_to_so4(bad).distance, installation.MAX_SO4_DISTANCE)
    six_position._gate_distance(bad, project_to_so4(bad).distance, installation.MAX_SO4_DISTANCE, gate=False)
    six_position._gate_distance(np.eye(4), project_to_so4(np.eye(4)).distance, installation.MAX_SO4_DISTANCE)
    ok = six_position._position_calibration(_rest_fit(np.eye(4), q, q), installation.MAX_RESIDUAL_RAD)
    assert not np.any(ok.residual_rad)
    turned = rotations.quat_from_rotvec(np.tile([0.0, 0.0, np.radians(2.0)], (6, 1)))      # 2 deg off each
    with pytest.raises(six_position.PositionsRefused, match="residual 2.000 deg at position 1"):
        six_position._position_calibration(_rest_fit(np.eye(4), q, turned), installation.MAX_RESIDUAL_RAD)
    ungated = six_position._position_calibration(_rest_fit(bad, q, turned, gate=False), installation.MAX_RESIDUAL_RAD)
    assert np.allclose(np.degrees(ungated.residual_rad), 2.0)        # a verification measures, never refuses


PM_G_DEG = [[0, 0, 0], [0, 0, 180], [0, 90, 0], [0, -90, 0], [0, 0, 90], [0, 0, -90]]   # the classic +-g set


@pytest.fixture(scope="module")
def pm_g_record():
    from mtcal.core.profiles import trajectory_from_euler_zxy
    from mtcal.methods.six_position import schedule_profile

    pos = np.radians(PM_G_DEG)
    q_wb = trajectory_from_euler_zxy(schedule_profile(pos, fs_hz=100.0)).q_wb
    alpha = np.radians([0.3, -0.8, 0.5])
    return pos, rotations.quat_multiply(q_wb, rotations.mount_quaternion(alpha)), alpha


def test_pm_g_set_refused_by_eq13_with_the_missing_axis_and_the_models_that_work(pm_g_record):
    pos, q_ws, _ = pm_g_record
    with pytest.raises(ValueError, match=r"no rotation about z \(yaw\).*model=\"so4\" \(6\) or model=\"mounting\""):
        installation.calibrate_installation(PAPER, pos, 0.01, q_ws=q_ws)
    assert installation.missing_rotation_axis(rotations.quat_from_euler_zxy(*pos.T)) == "z (yaw)"
    six = np.radians([[8, 0, 0], [-8, 0, 0], [0, -12, 0], [0, 23, 0], [0, 0, 90], [0, 0, -90]])
    assert installation.missing_rotation_axis(rotations.quat_from_euler_zxy(*six.T)) is None


@pytest.mark.parametrize("model", ["so4", "mounting"])
def test_constrained_models_calibrate_the_pm_g_set(pm_g_record, model):
    pos, q_ws, alpha = pm_g_record
    cal = installation.calibrate_installation(Config(model=model), pos, 0.01, q_ws=q_ws)
    np.testing.assert_allclose(cal.installation_angles_rad, alpha, atol=1e-10)
    assert cal.residual_rad.max() < 1e-10 and cal.so4_distance < 1e-10
    assert np.all(installation.installation_angles_sigma(cal, model) < 1e-9)


def test_mounting_model_refuses_rotations_about_one_axis():
    from mtcal.core.profiles import trajectory_from_euler_zxy
    from mtcal.methods.six_position import schedule_profile

    pos = np.radians([[10, 0, 0], [-10, 0, 0], [20, 0, 0], [-20, 0, 0]])
    q_wb = trajectory_from_euler_zxy(schedule_profile(pos, fs_hz=100.0)).q_wb
    with pytest.raises(ValueError, match="do not determine the mounting .* single axis"):
        installation.calibrate_installation(Config(model="mounting"), pos, 0.01, q_ws=q_wb)
    with pytest.raises(ValueError, match="model must be one of eq13, so4, mounting"):
        Config(model="svd")


def test_config_constructors_name_the_settings_of_each_caller():
    cfg = installation.InstallationConfig
    assert cfg.paper() == cfg() and cfg.paper(0.3).fraction == 0.3
    gates = ("max_condition", "max_so4_distance", "max_residual_rad")
    assert all(np.isinf(getattr(cfg.monte_carlo(), g)) for g in gates) and not cfg.monte_carlo().rests_in_order
    assert cfg.sweep_cell().rests_in_order and all(np.isinf(getattr(cfg.sweep_cell(), g)) for g in gates)
    cli_cfg = cfg.command_line(model="so4", fraction=0.25, max_residual_rad=0.01)
    assert (cli_cfg.model, cli_cfg.fraction, cli_cfg.max_residual_rad) == ("so4", 0.25, 0.01)
    assert cli_cfg.max_so4_distance == installation.MAX_SO4_DISTANCE and cli_cfg.qncf_params == QncfParams()
    with pytest.raises(AttributeError, match="cannot assign"):
        cli_cfg.fraction = 0.5                                              # frozen: resolved once
    with pytest.raises(ValueError, match="min_rest_s must be"):
        cfg(min_rest_s=0.0)
    with pytest.raises(TypeError, match="config must be an InstallationConfig"):
        installation.calibrate_installation({"fraction": 0.5}, six_positions_rad(), DT_S,
                                            q_ws=np.tile([1.0, 0, 0, 0], (9, 1)))


def test_verify_is_the_calibration_procedure_with_q_hat_given(stream):
    """Steps 1–5 as the calibration runs them; Eq 10 with the given Q̂ at the verification's positions."""
    pos, q_wb, q_ws, _ = stream
    cal = installation.calibrate_installation(PAPER, pos, DT_S, q_ws=q_ws)
    same = installation.verify_installation(PAPER, cal.q_hat, pos, DT_S, q_ws=q_ws)
    for name in ("q_sensor", "euler_before_rad", "euler_after_rad", "residual_rad", "matched", "q_hat"):
        assert np.array_equal(getattr(same, name), getattr(cal, name)), name
    # a record already zeroed at its session's start is not zeroed again
    tilted = rotations.quat_multiply(rotations.quat_from_euler_zxy(0.0, np.radians(2.0), 0.0), q_ws)
    as_is = replace(PAPER, zero_at_first_sample=False)
    ver = installation.verify_installation(as_is, np.eye(4), pos, DT_S, q_ws=tilted)
    assert np.allclose(ver.q_sensor, six_position.rest_means(tilted, ver.matched_rests), atol=1e-15)
    # no gate refuses a verification: a bad Q̂ is measured, not refused
    bad = installation.verify_installation(PAPER, 2 * np.eye(4), pos, DT_S, q_ws=q_ws)
    assert np.degrees(bad.residual_rad.max()) > 0.3
    with pytest.raises(ValueError, match="4x4"):
        installation.verify_installation(PAPER, np.eye(3), pos, DT_S, q_ws=q_ws)


def test_a_refusal_carries_the_attitude_it_was_made_from(stream):
    """InstallationRefused (a ValueError) hands the caller the un-zeroed sensor attitude: no second QNCF run."""
    pos, q_wb, _, q_bs = stream
    from mtcal.core.simulate import Trajectory

    rec = simulate_imu(Trajectory(np.arange(len(q_wb)) / FS, q_wb), ImuErrorModel(q_mount=tuple(q_bs)))
    wrong = pos * [1.0, -1.0, 1.0]                                        # pitch sign flipped
    with pytest.raises(installation.InstallationRefused, match="has no rest within") as info:
        installation.calibrate_installation(PAPER, wrong, DT_S, gyro_rad_s=rec.gyro_rad_s, accel_m_s2=rec.accel_m_s2)
    assert np.array_equal(info.value.q_ws, qncf(rec.gyro_rad_s, rec.accel_m_s2, DT_S, QncfParams(),
                                               return_euler=False).q_ws)
    with pytest.raises(ValueError, match="dt_s must be > 0") as info:                   # bad input: not a refusal
        installation.calibrate_installation(PAPER, pos, -1.0, q_ws=q_wb)
    assert not isinstance(info.value, installation.InstallationRefused)


def test_apply_errors(stream):
    q_ws = stream[2]
    with pytest.raises(ValueError, match="4x4"):
        installation.apply_installation(PAPER, np.eye(3), q_ws=q_ws)
    with pytest.raises(ValueError, match="finite"):
        installation.apply_installation(PAPER, np.full((4, 4), np.nan), q_ws=q_ws)
    with pytest.raises(ValueError, match="needs a record with as many trials"):
        installation.apply_installation(PAPER, np.stack([np.eye(4)] * 2), q_ws=q_ws)
    with pytest.raises(ValueError, match="dt_s is needed"):
        installation.apply_installation(PAPER, np.eye(4), gyro_rad_s=np.zeros((9, 3)), accel_m_s2=np.zeros((9, 3)))
    with pytest.raises(ValueError, match="give gyro_rad_s or q_ws"):
        installation.detect_rests(PAPER, DT_S)
    with pytest.raises(ValueError, match=r"\(N, 4\) or \(T, N, 4\)"):
        installation.detect_rests(PAPER, DT_S, q_ws=[1.0, 0.0, 0.0, 0.0])


def test_cli_calibrate_is_bit_identical_to_the_study_path(tmp_path, monkeypatch):
    """A six-position turntable log simulated by the study's scenario code, written losslessly (Parquet):
    ``mtcal calibrate --rest-detector paper`` returns the study's Q_hat bit for bit."""
    from mtcal.core.rotations import mount_quaternion
    from mtcal.studies import wang2023cja as w

    monkeypatch.setenv("MTCAL_DEBUG", "1")
    sc = w.turntable_scenario(fs_hz=200.0, turntable_rate_deg_s=40.0)
    prof, spans = w.turntable_profile(sc, with_sweeps=False)
    cal_span = spans["calibration"]
    traj = w.compliance_trajectory(prof.time_s, prof.angle_rad, 0.0)
    model = sc.imu.error_model(mount_quaternion(sc.alpha_rad("T1")), w.SOURCES, sc.errors)
    rec = simulate_imu(traj, model, rng=np.random.default_rng(7), trials=1)
    n = 1 + int(sc.fs_hz) * ((cal_span.stop - 1) // int(sc.fs_hz))   # whole seconds: the log's mean rate is exact
    gyro, accel = rec.gyro_rad_s[:, :n], rec.accel_m_s2[:, :n]
    pos = w.six_position_reference(sc)
    # the study path: session QNCF as in installation.measure_session, then its calibration step
    q_ws = qncf(gyro, accel, 1.0 / sc.fs_hz, sc.qncf, return_euler=False).q_ws
    study = w.calibration_step(sc, q_ws, gyro, pos, sc.averaging_fraction)
    # the CLI path
    cols = ["gyro_x_rad_s", "gyro_y_rad_s", "gyro_z_rad_s", "accel_x_m_s2", "accel_y_m_s2", "accel_z_m_s2"]
    log = pd.DataFrame(np.hstack([gyro[0], accel[0]]), columns=cols)
    log.insert(0, "time_s", np.arange(n) / sc.fs_hz)
    log.to_parquet(tmp_path / "turntable.parquet")
    pd.DataFrame(np.degrees(pos).round(12), columns=["yaw_deg", "pitch_deg", "roll_deg"]).to_csv(
        tmp_path / "pos.csv", index=False)
    assert np.array_equal(np.radians(pd.read_csv(tmp_path / "pos.csv").to_numpy()), pos)
    code = cli.main(["calibrate", str(tmp_path / "turntable.parquet"), "--positions", str(tmp_path / "pos.csv"),
                     "--rest-detector", "paper", "--fraction", repr(sc.averaging_fraction),
                     "--out", str(tmp_path / "q.json")])
    assert code == 0
    doc = json.loads((tmp_path / "q.json").read_text())
    q_cli = np.array(doc["q_hat"])
    assert np.array_equal(q_cli, study.q_hat[0])
    # and every number derived from it: residuals, installation angles, mounting
    assert doc["residual_deg"] == np.degrees(study.residual_rad[0]).tolist()
    assert list(doc["installation_angles_deg"].values()) == np.degrees(study.installation_angles_rad[0]).tolist()
    assert doc["mounting_quaternion_q_bs"] == study.mounting_quaternion_q_bs[0].tolist()
    assert not np.array_equal(study.q_hat[0], np.eye(4))


# --------------------------------------------------------------------------- whole records (the CLI's procedures)
def test_calibrate_record_of_a_quaternion_log_is_the_calibration(stream):
    pos, _, q_ws, _ = stream
    t = np.arange(q_ws.shape[0]) * DT_S
    cfg = Config.command_line()
    res = installation.calibrate_record(cfg, pos, DT_S, time_s=t, q_ws=q_ws)
    cal = installation.calibrate_installation(cfg, pos, DT_S, q_ws=q_ws, rests=res.rests)
    assert res.refusal is None and res.report is None and res.units_check is None
    np.testing.assert_array_equal(res.calibration.q_hat, cal.q_hat)
    np.testing.assert_array_equal(res.mounting_euler_rad, rotations.euler_zxy_from_quat(cal.mounting_quaternion_q_bs))


def test_calibrate_record_names_a_convention_mistake(stream):
    pos, _, q_ws, _ = stream
    t = np.arange(q_ws.shape[0]) * DT_S
    cfg = Config.command_line()
    res = installation.calibrate_record(cfg, pos[:, [0, 2, 1]], DT_S, time_s=t, q_ws=q_ws)
    assert res.calibration is None and "likely mistake: pitch and roll swapped" in res.refusal
    assert res.diagnosis.measured_rad.shape == (6, 3) and len(res.diagnosis.nearest) == 6
    conj = installation.calibrate_record(cfg, pos, DT_S, time_s=t, q_ws=q_ws * [1.0, -1.0, -1.0, -1.0])
    assert "would match every position if they were conjugated" in conj.refusal and conj.diagnosis is None


def test_calibrate_record_with_too_few_rests_leaves_the_wording_to_the_caller(stream):
    pos, _, q_ws, _ = stream
    t = np.arange(q_ws.shape[0]) * DT_S
    res = installation.calibrate_record(Config.command_line(min_rest_s=100.0), pos, DT_S, time_s=t, q_ws=q_ws)
    assert res.calibration is None and res.refusal is None and len(res.rests) < pos.shape[0]


def test_apply_record_modes_are_the_application_functions(stream):
    pos, _, q_ws, q_bs = stream
    t = np.arange(q_ws.shape[0]) * DT_S
    cal = installation.calibrate_installation(PAPER, pos, DT_S, q_ws=q_ws)
    cfg = Config.command_line()
    rel = installation.apply_record(cfg, cal.q_hat, DT_S, mode="relative", time_s=t, q_ws=q_ws)
    np.testing.assert_array_equal(rel.attitude.q_body, installation.apply_installation(cfg, cal.q_hat, q_ws=q_ws).q_body)
    assert rel.start_rest is None and rel.start_euler_rad.shape == (3,)
    ab = installation.apply_record(cfg, cal.q_hat, DT_S, time_s=t, q_ws=q_ws)
    np.testing.assert_array_equal(ab.attitude.q_body,
                                  installation.absolute_body_attitude(cfg, ab.q_bs, q_ws=q_ws).q_body)
    assert ab.start_euler_rad is None
    np.testing.assert_array_equal(ab.q_bs, installation.mounting_from_q_hat(cal.q_hat))
    proj = installation.constrained_fit.project_to_so4(cal.q_hat)          # what the system calls: the same bits
    np.testing.assert_array_equal(ab.q_bs, np.copysign(1.0, proj.r[0]) * rotations.quat_conjugate(proj.r))
    with pytest.raises(ValueError, match="mode must be 'absolute' or 'relative'"):
        installation.apply_record(cfg, cal.q_hat, DT_S, mode="sideways", time_s=t, q_ws=q_ws)
    with pytest.raises(ValueError, match=r"q_hat must be a 4x4 array, got shape \(3, 3\)"):
        installation.apply_record(cfg, np.eye(3), DT_S, time_s=t, q_ws=q_ws)
    with pytest.raises(ValueError, match=r"q_hat must be finite \(no NaN or inf\)"):
        installation.apply_record(cfg, np.full((4, 4), np.nan), DT_S, time_s=t, q_ws=q_ws)
    bad = cal.q_hat.copy()
    bad[2] = 0.0                                                      # a zero row: no calibration gives one
    for q_hat in (bad, np.zeros((4, 4)), 10 * np.eye(4)):
        with pytest.raises(ValueError, match=r"from the nearest rotation of quaternion space \(SO\(4\)\), more "
                                             r"than 0.05: it is not an installation calibration"):
            installation.apply_record(cfg, q_hat, DT_S, time_s=t, q_ws=q_ws)
    wide = replace(cfg, max_so4_distance=np.inf)                     # the gate is the config's
    assert installation.apply_record(wide, 10 * np.eye(4), DT_S, time_s=t, q_ws=q_ws).q_bs.shape == (4,)


@pytest.mark.parametrize("model", ["eq13", "so4", "mounting"])
def test_the_calibration_carries_the_1_sigma_of_its_fit(stream, model):
    pos, _, q_ws, _ = stream
    rng = np.random.default_rng(5)
    q = q_ws + 1e-5 * rng.standard_normal(q_ws.shape)              # scatter at the rests: a 1-sigma to estimate
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    cfg = Config(model=model)
    cal = installation.calibrate_installation(cfg, pos, DT_S, q_ws=q, sigma=True)
    sigma = installation.installation_angles_sigma(cal, model)
    assert np.all(np.isfinite(sigma)) and np.all(sigma > 0)
    np.testing.assert_array_equal(cal.angles_sigma_rad, sigma)
    assert installation.calibrate_installation(cfg, pos, DT_S, q_ws=q).angles_sigma_rad is None
    with pytest.raises(ValueError, match="one calibration"):
        installation.calibrate_installation(cfg, pos, DT_S, q_ws=np.stack([q, q]), sigma=True)


@pytest.mark.parametrize("mode", ["absolute", "relative"])
def test_apply_record_of_a_raw_log_is_the_checked_procedure_bit_for_bit(mode):
    """After its units check the log procedure runs the QNCF trusted: the same bits as the public functions."""
    from tests.cli.logs import six_position_log

    df, pos_df, _ = six_position_log()
    t = df["time_s"].to_numpy()
    g = df[["gyro_x_rad_s", "gyro_y_rad_s", "gyro_z_rad_s"]].to_numpy()
    a = df[["accel_x_m_s2", "accel_y_m_s2", "accel_z_m_s2"]].to_numpy()
    dt = float(np.mean(np.diff(t)))
    cfg = Config.command_line(rest_detector=RestsConfig.cli_defaults(0.2))
    q_hat = installation.calibrate_record(cfg, np.radians(pos_df.to_numpy()), dt, time_s=t, accel_m_s2=a,
                                          gyro_rad_s=g).calibration.q_hat
    res = installation.apply_record(cfg, q_hat, dt, mode=mode, time_s=t, accel_m_s2=a, gyro_rad_s=g)
    assert res.units_check is not None
    run = replace(cfg, qncf_params=res.qncf.params)
    raw = dict(gyro_rad_s=res.qncf.gyro_rad_s, accel_m_s2=a, q0=res.qncf.q0)
    want = (installation.absolute_body_attitude(run, res.q_bs, dt, **raw) if mode == "absolute" else
            installation.apply_installation(run, q_hat, dt, **raw))
    np.testing.assert_array_equal(res.attitude.q_body, want.q_body)
    np.testing.assert_array_equal(res.attitude.q_sensor, want.q_sensor)


def test_the_rest_detector_of_a_config_is_a_rests_config():
    with pytest.raises(TypeError, match="rest_detector must be a RestsConfig or None"):
        Config(rest_detector=[slice(0, 10)])


def test_calibrate_record_checks_its_inputs_once(stream):
    """The log procedure's edge: positions (finite, K >= 4) and the logged attitude checked once."""
    pos, _, q_ws, _ = stream
    cfg = Config.command_line()
    with pytest.raises(ValueError, match="at least 4 positions"):
        installation.calibrate_record(cfg, pos[:3], DT_S, q_ws=q_ws)
    with pytest.raises(ValueError, match="positions_rad"):
        installation.calibrate_record(cfg, np.where(pos == 0.0, np.nan, pos), DT_S, q_ws=q_ws)
    with pytest.raises(ValueError, match=r"q_ws must have shape \(N, 4\)"):
        installation.calibrate_record(cfg, pos, DT_S, q_ws=np.stack([q_ws, q_ws]))
    with pytest.raises(ValueError, match="q_ws"):
        installation.calibrate_record(cfg, pos, DT_S, q_ws=2 * q_ws)
    with pytest.raises(TypeError, match="config must be an InstallationConfig"):
        installation.calibrate_record({"model": "eq13"}, pos, DT_S, q_ws=q_ws)
    res = installation.calibrate_record(cfg, pos, DT_S, q_ws=q_ws)
    assert np.degrees(np.abs(res.calibration.installation_angles_rad - ALPHA)).max() < 1e-6



@pytest.fixture(scope="module")
def session():
    """Two six-position runs of a mounted sensor, three trials with noise: (records, runs, positions)."""
    from mtcal.core.profiles import join_profiles

    pos = six_positions_rad()
    run = schedule_profile(pos, rate_rad_s=np.radians(40.0), fs_hz=200.0)
    prof, (cal_run, ver_run) = join_profiles([run, run])
    from mtcal.core.simulate import SensorErrors

    model = ImuErrorModel(gyro=SensorErrors(noise_density=1e-4), accel=SensorErrors(noise_density=1e-3),
                          q_mount=tuple(rotations.mount_quaternion(ALPHA)))
    rec = simulate_imu(trajectory_from_euler_zxy(prof), model, rng=np.random.default_rng(7), trials=3)
    return rec.gyro_rad_s, rec.accel_m_s2, cal_run, ver_run, pos


def test_measure_session_is_the_calibration_and_verification_of_each_piece(session):
    """One stacked QNCF, the session zeroed once; each piece = calibrate_installation on the calibration run
    (zeroed there) and verify_installation on the zeroed verification run, bit for bit, on any map."""
    from concurrent.futures import ThreadPoolExecutor

    gyro, accel, cal_run, ver_run, pos = session
    cfg = Config.monte_carlo(qncf_params=QncfParams())
    fed = pos[None] + np.radians([[[0.01, 0.0, -0.02]], [[0.0, 0.03, 0.0]]])              # per trial, rows 1-2
    pieces = [installation.SessionPiece(slice(0, 1), pos, 0.5), installation.SessionPiece(slice(1, 3), fed, 0.4)]
    with ThreadPoolExecutor(2) as pool:
        threaded = installation.measure_session(cfg, gyro, accel, 1 / 200.0, calibration_run=cal_run,
                                                verification_run=ver_run, reference_rad=pos, pieces=pieces,
                                                map_pieces=pool.map)
    got = installation.measure_session(cfg, gyro, accel, 1 / 200.0, calibration_run=cal_run, verification_run=ver_run,
                                       reference_rad=pos, pieces=pieces)
    q_ws = qncf(gyro, accel, 1 / 200.0, QncfParams(), return_euler=False).q_ws
    q_zeroed = rotations.relative_to_initial(q_ws)
    assert np.array_equal(got.q_ws, q_zeroed) and np.array_equal(threaded.q_ws, q_zeroed)
    for k, piece in enumerate(pieces):
        rows = piece.rows
        cal = installation.calibrate_installation(Config.monte_carlo(piece.fraction), piece.reference_rad, 1 / 200.0,
                                                  q_ws=q_ws[rows, cal_run], gyro_rad_s=gyro[rows, cal_run])
        ver = installation.verify_installation(Config.monte_carlo(piece.fraction, zero_at_first_sample=False),
                                               cal.q_hat, pos, 1 / 200.0, q_ws=q_zeroed[rows, ver_run],
                                               gyro_rad_s=gyro[rows, ver_run])
        for m in (got, threaded):
            for name in ("q_hat", "euler_before_rad", "euler_after_rad", "residual_rad", "matched"):
                assert np.array_equal(getattr(m.calibrations[k], name), getattr(cal, name)), name
                assert np.array_equal(getattr(m.verifications[k], name), getattr(ver, name)), name
    assert np.degrees(np.abs(got.calibrations[0].installation_angles_rad - ALPHA)).max() < 0.05
    alone = installation.measure_session(cfg, gyro, accel, 1 / 200.0, calibration_run=cal_run, pieces=pieces[:1])
    assert alone.verifications is None and np.array_equal(alone.calibrations[0].q_hat, got.calibrations[0].q_hat)


def test_measure_session_checks_its_inputs_once_at_its_edge(session):
    gyro, accel, cal_run, ver_run, pos = session
    cfg = Config.monte_carlo()
    piece = installation.SessionPiece(slice(0, 3), pos, 0.5)
    ok = dict(calibration_run=cal_run, verification_run=ver_run, reference_rad=pos, pieces=[piece])

    def measure(config=cfg, g=gyro, a=accel, dt=1 / 200.0, **changes):
        return installation.measure_session(config, g, a, dt, **{**ok, **changes})

    with pytest.raises(TypeError, match="config must be an InstallationConfig"):
        measure(config={"fraction": 0.5})
    with pytest.raises(TypeError, match="pieces must be a non-empty sequence of SessionPiece"):
        measure(pieces=[])
    with pytest.raises(TypeError, match="pieces must be a non-empty sequence of SessionPiece"):
        measure(pieces=[(slice(0, 3), pos, 0.5)])
    with pytest.raises(ValueError, match="a verification run needs reference_rad"):
        measure(reference_rad=None)
    with pytest.raises(ValueError, match="at least 4 positions"):
        measure(pieces=[installation.SessionPiece(slice(0, 3), pos[:3], 0.5)])
    with pytest.raises(ValueError, match=r"stacked records of one shape \(T, N, 3\)"):
        measure(g=gyro[0], a=accel[0])
    with pytest.raises(ValueError, match=r"stacked records of one shape \(T, N, 3\)"):
        measure(a=accel[:2])
    with pytest.raises(TypeError, match="gyro_rad_s must be a numeric array"):
        measure(g="gyro")
    with pytest.raises(ValueError, match="dt_s must be the sample interval"):
        measure(dt=200.0)
    with pytest.raises(ValueError, match="verification_run must be a slice"):
        measure(verification_run=slice(0, gyro.shape[1] + 1))
    with pytest.raises(ValueError, match="calibration_run must be a slice"):
        measure(calibration_run=[0, 10])
    with pytest.raises(ValueError, match="a piece's rows must be a slice"):
        measure(pieces=[installation.SessionPiece(slice(2, 5), pos, 0.5)])
    with pytest.raises(ValueError, match=r"a piece's reference_rad of shape \(2, 6, 3\) needs 2 rows"):
        measure(pieces=[installation.SessionPiece(slice(0, 3), np.stack([pos, pos]), 0.5)])
    with pytest.raises(ValueError, match=r"a piece's fraction must be in \(0, 1\]"):
        measure(pieces=[installation.SessionPiece(slice(0, 3), pos, 1.5)])
    with pytest.raises(ValueError, match="a piece's fraction must be > 0"):
        measure(pieces=[installation.SessionPiece(slice(0, 3), pos, 0.0)])


def test_measure_simulated_session_pulls_its_records_and_equals_measure_session():
    """The source's blocks measured by the procedure that pulls them: measure_session of the same records, bit for
    bit; its blocks and groups checked before any record is simulated."""
    from mtcal.core.profiles import join_profiles
    from mtcal.core.simulate import RecordPiece, RecordSource, SensorErrors

    pos = six_positions_rad()
    run = schedule_profile(pos, rate_rad_s=np.radians(40.0), fs_hz=200.0)
    prof, (cal_run, ver_run) = join_profiles([run, run])
    q_wb = trajectory_from_euler_zxy(prof).q_wb
    model = ImuErrorModel(gyro=SensorErrors(noise_density=1e-4), accel=SensorErrors(noise_density=1e-3),
                          q_mount=tuple(rotations.mount_quaternion(ALPHA)))
    source = lambda: RecordSource(prof.time_s, q_wb, [RecordPiece(2, model, np.random.default_rng(s))  # noqa: E731
                                                      for s in (3, 4)], 1 / 200.0)
    pieces = [installation.SessionPiece(slice(0, 2), pos, 0.5), installation.SessionPiece(slice(2, 4), pos, 0.4)]
    cfg = Config.monte_carlo()
    got = installation.measure_simulated_session(cfg, source(), [1, 0], [[0], [1]], calibration_run=cal_run,
                                                 verification_run=ver_run, reference_rad=pos, pieces=pieces)
    gyro, accel = (x.copy() for x in source().fill([1, 0], [[0, 1]]))
    ref = installation.measure_session(cfg, gyro, accel, 1 / 200.0, calibration_run=cal_run, verification_run=ver_run,
                                       reference_rad=pos, pieces=pieces)
    assert np.array_equal(got.q_ws, ref.q_ws)
    for a, b in zip(got.calibrations + got.verifications, ref.calibrations + ref.verifications):
        assert np.array_equal(a.q_hat, b.q_hat) and np.array_equal(a.euler_after_rad, b.euler_after_rad)
    assert np.degrees(np.abs(got.calibrations[0].installation_angles_rad - ALPHA)).max() < 0.05
    src = source()
    measure = lambda blocks, groups, **kw: installation.measure_simulated_session(  # noqa: E731
        kw.pop("config", cfg), kw.pop("source", src), blocks, groups, calibration_run=cal_run, pieces=pieces[:1], **kw)
    with pytest.raises(TypeError, match="source must be a RecordSource"):
        measure([0], [[0]], source=(np.zeros((2, 10, 3)), np.zeros((2, 10, 3))))
    with pytest.raises(ValueError, match="blocks must be a non-empty sequence of the source's 2 blocks"):
        measure([2], [[0]])
    with pytest.raises(ValueError, match=r"groups must partition the positions 0 … 1 of blocks"):
        measure([0, 1], [[0]])
    with pytest.raises(TypeError, match="config must be an InstallationConfig"):
        measure([0], [[0]], config={"fraction": 0.5})
    with pytest.raises(ValueError, match="a piece's rows must be a slice"):
        installation.measure_simulated_session(cfg, src, [0], [[0]], calibration_run=cal_run, pieces=pieces[1:])
    assert src._gyro is None                                     # refused before a record was simulated


def test_measure_applied_runs_is_eq10_on_the_zeroed_qncf_attitude_at_each_hold():
    """Runs of unequal length stacked in one QNCF: each run's hold means are those of its own QNCF attitude, zeroed
    at its first sample, through Eq 10 with its rows' Q̂; the traced row's series and gate; inputs checked first."""
    from mtcal.core.simulate import RecordPiece, RecordSource, SensorErrors, Trajectory

    t = np.arange(0.0, 6.0, 0.01)
    q_long = rotations.quat_from_euler_zxy(np.zeros(t.size), np.radians(5.0) * np.minimum(t, 3.0) / 3.0, np.zeros(t.size))
    model = ImuErrorModel(gyro=SensorErrors(noise_density=1e-4), accel=SensorErrors(noise_density=1e-3),
                          q_mount=tuple(rotations.mount_quaternion(ALPHA)))
    trajs = [Trajectory(t, q_long), Trajectory(t[:400], q_long[:400])]
    source = lambda: RecordSource(None, None, [RecordPiece(2, model, np.random.default_rng(s), trajectory=tr)  # noqa: E731
                                               for s, tr in zip((5, 6), trajs)], 0.01)
    q_hat = np.stack([rotations.right_matrix(rotations.quat_conjugate(rotations.mount_quaternion(ALPHA)))] * 2)
    holds = ([slice(400, 500), slice(500, 590)], [slice(350, 390)])
    runs = [installation.AppliedRun(slice(0, 2), q_hat, holds[0], t.size, 1),
            installation.AppliedRun(slice(2, 4), q_hat, holds[1], 400)]
    cfg = Config.monte_carlo()
    got = installation.measure_applied_runs(cfg, source(), [0, 1], [[0], [1]], runs=runs)
    gyro, accel = (x.copy() for x in source().fill([0, 1], [[0, 1]]))
    res = qncf(gyro, accel, 0.01, cfg.qncf_params, return_euler=False)
    for k, (run, hs) in enumerate(zip(runs, holds)):
        q = rotations.relative_to_initial(res.q_ws[run.rows])
        ref = np.stack([rotations.mapped_pitch_trusted(q_hat, q[:, h]).mean(axis=1) for h in hs], axis=1)
        assert np.array_equal(got.hold_pitch_rad[k], ref)
    q1 = rotations.relative_to_initial(res.q_ws[1:2])
    assert np.array_equal(got.traces[0]["pitch_rad"], rotations.mapped_pitch_trusted(q_hat[1:2], q1)[0])
    assert np.array_equal(got.traces[0]["gate"], res.gate[1]) and got.traces[1] == {}
    assert np.abs(np.degrees(got.hold_pitch_rad[0][:, 1]) - 5.0).max() < 1.0       # the calibrated pitch near 5°
    src = source()
    bad = lambda **kw: installation.measure_applied_runs(cfg, src, [0, 1], [[0, 1]], runs=[replace(runs[0], **kw)])  # noqa: E731
    with pytest.raises(TypeError, match="runs must be a non-empty sequence of AppliedRun"):
        installation.measure_applied_runs(cfg, src, [0, 1], [[0, 1]], runs=[])
    with pytest.raises(ValueError, match="a run's rows must be a slice"):
        bad(rows=slice(3, 5))
    with pytest.raises(ValueError, match=r"a run's q_hat must be finite, of shape \(2, 4, 4\)"):
        bad(q_hat=q_hat[:1])
    with pytest.raises(ValueError, match=r"a run's samples must be an integer in \[1, 600\]"):
        bad(samples=601)
    with pytest.raises(ValueError, match="a run's holds must be slices within its 400 samples"):
        bad(samples=400)
    with pytest.raises(ValueError, match="a run's trace_row must be a row of its 2 trials"):
        bad(trace_row=2)
    with pytest.raises(TypeError, match="config must be an InstallationConfig"):
        installation.measure_applied_runs({"qncf": None}, src, [0], [[0]], runs=runs[:1])
    assert src._gyro is None                                     # refused before a record was simulated


def _verification_sweep(session, fractions=(0.5, 0.4), decimation=7):
    """The verification run scored as a sweep: its pitch averaged over the middle of each rest."""
    from mtcal.core.profiles import join_profiles
    from mtcal.methods.six_position import middle_slices

    gyro, accel, cal_run, ver_run, pos = session
    run = schedule_profile(pos, rate_rad_s=np.radians(40.0), fs_hz=200.0)
    prof, _ = join_profiles([run, run])
    seg = prof.segment[ver_run]
    rests = [np.flatnonzero(seg == s) for s in np.unique(seg[seg % 2 == 0])]
    windows = [slice(int(r[0]), int(r[-1]) + 1) for r in rests]
    return installation.SessionSweep("ver", ver_run, prof.angle_rad[ver_run], 1, (1, 2),
                                     {f: middle_slices(windows, f) for f in fractions}, decimation)


def test_measure_session_scores_each_sweep_with_each_pieces_q_hat(session):
    """A sweep's scores are the Eq 8 errors of channel_errors_before_after with the piece's own Q̂: hold means
    minus the piece's hold errors, MaxAE/RMSE equal to the metrics', the decimated float32 series and the
    trace row; on threads the same numbers."""
    from concurrent.futures import ThreadPoolExecutor

    from mtcal.core import metrics, montecarlo

    gyro, accel, cal_run, ver_run, pos = session
    sweep = _verification_sweep(session)
    n_holds = len(sweep.holds[0.4])
    hold_err = np.arange(2.0 * n_holds).reshape(2, n_holds) * 1e-4
    pieces = [installation.SessionPiece(slice(0, 1), pos, 0.5, trace_row=0),
              installation.SessionPiece(slice(1, 3), pos, 0.4, hold_errors_rad={"ver": hold_err})]
    cfg = Config.monte_carlo()
    got = installation.measure_session(cfg, gyro, accel, 1 / 200.0, calibration_run=cal_run, pieces=pieces,
                                       sweeps=[sweep])
    with ThreadPoolExecutor(2) as pool:
        threaded = installation.measure_session(cfg, gyro, accel, 1 / 200.0, calibration_run=cal_run, pieces=pieces,
                                                sweeps=[sweep], map_pieces=pool.map)
    assert got.verifications is None and len(got.sweeps) == len(got.traces) == 2
    for k, piece in enumerate(pieces):
        q_hat = got.calibrations[k].q_hat
        before, after, errs = montecarlo.channel_errors_before_after(got.q_ws[piece.rows, ver_run], q_hat,
                                                                     sweep.reference_rad, 1)
        holds = sweep.holds[piece.fraction]
        s = got.sweeps[k]["ver"]
        e = 0.0 if piece.hold_errors_rad is None else hold_err
        assert np.array_equal(s["reference"], [sweep.reference_rad[h, 1].mean() for h in holds])
        assert np.array_equal(s["before_mean"], np.stack([before[:, h].mean(axis=1) for h in holds], axis=1) - e)
        assert np.array_equal(s["after_mean"], np.stack([after[:, h].mean(axis=1) for h in holds], axis=1) - e)
        for state in ("before", "after"):
            for c in (1, 2):
                assert np.array_equal(s[f"{state}_maxae_{c}"], metrics.max_abs_error(errs[state][..., c], axis=-1))
                assert np.array_equal(s[f"{state}_rmse_{c}"], metrics.rmse(errs[state][..., c], axis=-1))
            assert f"{state}_maxae_0" not in s
            assert s[f"{state}_err_dec"].dtype == np.float32
            assert np.array_equal(s[f"{state}_err_dec"], errs[state][:, ::7].astype(np.float32))
        for key, value in s.items():
            assert np.array_equal(value, threaded.sweeps[k]["ver"][key]), key
    assert np.array_equal(got.traces[0]["ver_after_err"], errs_first_row(got, pieces[0], sweep, ver_run))
    assert got.traces[1] == {}
    # a calibrated, nearly noise-free sensor holds the commanded pitch at every rest
    s = got.sweeps[0]["ver"]
    assert np.degrees(np.abs(s["after_mean"] - s["reference"])).max() < 0.05
    assert np.degrees(np.abs(s["before_mean"] - s["reference"])).max() > 0.1     # the installation error shows


def errs_first_row(m, piece, sweep, run):
    from mtcal.core import montecarlo

    _, _, errs = montecarlo.channel_errors_before_after(m.q_ws[piece.rows, run], m.calibrations[0].q_hat,
                                                        sweep.reference_rad, 1)
    return errs["after"][0]


def test_measure_session_checks_its_sweeps_at_its_edge(session):
    from dataclasses import replace

    gyro, accel, cal_run, ver_run, pos = session
    sweep = _verification_sweep(session, fractions=(0.5,))
    piece = installation.SessionPiece(slice(0, 3), pos, 0.5)

    def measure(sweeps=(sweep,), pieces=(piece,)):
        return installation.measure_session(Config.monte_carlo(), gyro, accel, 1 / 200.0, calibration_run=cal_run,
                                            pieces=pieces, sweeps=sweeps)

    with pytest.raises(TypeError, match="sweeps must be a sequence of SessionSweep"):
        measure(sweeps=[{"name": "ver"}])
    with pytest.raises(ValueError, match="sweep 'ver''s span must be a slice"):
        measure(sweeps=[replace(sweep, span=slice(0, gyro.shape[1] + 1))])
    with pytest.raises(ValueError, match=r"sweep 'ver''s reference_rad must be finite, of shape \(\d+, 3\)"):
        measure(sweeps=[replace(sweep, reference_rad=sweep.reference_rad[:-1])])
    with pytest.raises(ValueError, match="sweep 'ver''s reference_rad must be finite"):
        measure(sweeps=[replace(sweep, reference_rad=np.full_like(sweep.reference_rad, np.nan))])
    with pytest.raises(ValueError, match="channel and scored_channels must be 0, 1 or 2"):
        measure(sweeps=[replace(sweep, scored_channels=(3,))])
    with pytest.raises(ValueError, match="decimation must be an integer >= 1"):
        measure(sweeps=[replace(sweep, decimation=0)])
    with pytest.raises(ValueError, match="holds must give, for fraction 0.3, hold windows"):
        measure(pieces=[installation.SessionPiece(slice(0, 3), pos, 0.3)])
    with pytest.raises(ValueError, match="holds must give, for fraction 0.5, hold windows"):
        measure(sweeps=[replace(sweep, holds={0.5: [slice(0, 10**9)]})])
    n = len(sweep.holds[0.5])
    with pytest.raises(ValueError, match=rf"hold_errors_rad must hold sweep 'ver' of shape \(3, {n}\)"):
        measure(pieces=[installation.SessionPiece(slice(0, 3), pos, 0.5, hold_errors_rad={"ver": np.zeros((3, 5))})])
    with pytest.raises(ValueError, match=rf"hold_errors_rad must hold sweep 'ver' of shape \(3, {n}\), got None"):
        measure(pieces=[installation.SessionPiece(slice(0, 3), pos, 0.5, hold_errors_rad={})])
    with pytest.raises(ValueError, match="trace_row must be a row of its 3 trials"):
        measure(pieces=[installation.SessionPiece(slice(0, 3), pos, 0.5, trace_row=3)])
