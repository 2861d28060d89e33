"""The engineer's calibrate → apply workflow on logs written by a plain numpy script (issue #36).

The logs come from :mod:`tests.cli.numpy_logs` — its own quaternion algebra, no mtcal import —
so truth is independent of mtcal's simulator and rotation code: mounting yaw +0.3°, pitch −0.5°,
roll +0.8° (ZXY of q_bs), gyro bias, white noise, 1 kHz, a flight log parked at yaw 30°,
pitch 2°, roll −1.5°.
"""

import json

import numpy as np
import pandas as pd
import pytest

from mtcal import cli
from tests.cli import numpy_logs as nl


def _errors(body_csv, truth_ypr_deg) -> np.ndarray:
    """Output minus truth (deg), yaw relative to the first sample, wrapped."""
    e = pd.read_csv(body_csv)[["yaw_deg", "pitch_deg", "roll_deg"]].to_numpy() - truth_ypr_deg
    e[:, 0] -= e[0, 0]
    return (e + 180.0) % 360.0 - 180.0


@pytest.fixture(scope="module")
def calibrated(tmp_path_factory):
    d = tmp_path_factory.mktemp("workflow")
    tt, pos = nl.turntable_log()
    tt.write(d / "turntable.csv")
    pos.to_csv(d / "pos.csv", index=False)
    code = cli.main(["calibrate", str(d / "turntable.csv"), "--positions", str(d / "pos.csv"),
                     "--out", str(d / "Q.json"), "--comment", "numpy rig, IMU #7"])
    assert code == 0
    return d


def test_calibration_recovers_the_mounting_and_states_what_alpha_means(calibrated):
    doc = json.loads((calibrated / "Q.json").read_text())
    m = doc["mounting_ypr_deg"]
    np.testing.assert_allclose([m["yaw_z"], m["pitch_x"], m["roll_y"]], nl.MOUNT_DEG, atol=0.04)
    a = doc["installation_angles_deg"]
    # Eq 1 angles describe the body relative to the sensor: about the negative of the mounting
    np.testing.assert_allclose([a["alpha1_z"], a["alpha2_y"], a["alpha3_x"]],
                               [-nl.MOUNT_DEG[0], -nl.MOUNT_DEG[2], -nl.MOUNT_DEG[1]], atol=0.04)
    sig = doc["installation_angles_1sigma_deg"]
    assert all(0 < v < 0.2 for v in sig.values())
    assert "body relative to the sensor" in doc["installation_angles_meaning"]
    assert doc["format"] == "mtcal-calibration/2" and doc["mtcal_version"] and doc["comment"] == "numpy rig, IMU #7"
    assert doc["input"]["gyro_unit"] == "rad/s" and doc["input"]["sample_rate_hz"] == pytest.approx(1000.0)
    assert "q_ws (x) conj(q_bs)" in doc["mounting_meaning"]


def test_flight_log_absolute_pitch_roll_within_005_deg(calibrated, capsys):
    d = calibrated
    fl = nl.flight_log()
    fl.write(d / "flight.csv")
    capsys.readouterr()
    assert cli.main(["apply", str(d / "Q.json"), str(d / "flight.csv"), "--out", str(d / "body.csv")]) == 0
    out = capsys.readouterr().out
    assert "absolute: pitch and roll referenced to gravity" in out and "heading (yaw) zeroed" in out
    assert "warning" not in out
    err = _errors(d / "body.csv", fl.ypr_deg)
    assert np.abs(err[:, 1:]).max() < 0.05
    # another filter's sensor attitude with the file's q_bs: q_wb = q_ws (x) conj(q_bs)
    q_bs = np.array(json.loads((d / "Q.json").read_text())["mounting_quaternion_q_bs"])
    q_ws = nl.qmul(fl.q_wb, nl.q_from_ypr_deg(*nl.MOUNT_DEG))
    ypr = nl.ypr_deg_from_q(nl.qmul(q_ws, nl.qconj(q_bs)))
    assert np.abs(ypr[:, 1:] - fl.ypr_deg[:, 1:]).max() < 0.05


def test_relative_mode_warns_about_a_tilted_start(calibrated, capsys):
    d = calibrated
    fl = nl.flight_log()
    fl.write(d / "flight_rel.csv")
    capsys.readouterr()
    assert cli.main(["apply", str(d / "Q.json"), str(d / "flight_rel.csv"), "--mode", "relative",
                     "--out", str(d / "body_rel.csv")]) == 0
    out = capsys.readouterr().out
    warn = [ln for ln in out.splitlines() if ln.startswith("warning: --mode relative")]
    assert len(warn) == 1 and "pitch +2.0" in warn[0] and "roll -1.4" in warn[0]
    err = _errors(d / "body_rel.csv", fl.ypr_deg)
    assert np.abs(err[:, 1]).max() > 1.5            # relative to the tilted start, as stated


def test_slow_start_of_motion_does_not_leak_into_the_gyro_bias(calibrated, capsys):
    d = calibrated
    fl = nl.flight_log(slow_start_s=3.0, seed=3)
    fl.write(d / "slow.csv")
    capsys.readouterr()
    assert cli.main(["apply", str(d / "Q.json"), str(d / "slow.csv"), "--out", str(d / "body_slow.csv")]) == 0
    out = capsys.readouterr().out
    line = next(ln for ln in out.splitlines() if ln.startswith("gyro bias"))
    core_end = float(line.split("quiet core ")[1].split("-")[1].split()[0])
    assert core_end < 5.4                           # the motion starts at 5 s; the whole first rest ran past 6 s
    bias = [float(v) for v in line.split()[2:5]]
    np.testing.assert_allclose(bias, nl.GYRO_BIAS_DEG_S, atol=0.005)
    err = _errors(d / "body_slow.csv", fl.ypr_deg)
    assert abs(err[-1, 0]) < 0.2                    # yaw drift over 60 s (whole-rest mean: 0.9 deg)


def test_apply_refuses_an_unknown_calibration_format(calibrated, tmp_path, capsys):
    doc = json.loads((calibrated / "Q.json").read_text())
    doc["format"] = "mtcal-calibration/99"
    bad = tmp_path / "Q99.json"
    bad.write_text(json.dumps(doc))
    fl = nl.flight_log(duration_s=12.0)
    fl.write(tmp_path / "f.csv")
    code = cli.main(["apply", str(bad), str(tmp_path / "f.csv"), "--out", str(tmp_path / "b.csv")])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "unknown calibration format 'mtcal-calibration/99'" in err


def test_apply_reads_a_version_1_file(calibrated, tmp_path, capsys):
    doc = json.loads((calibrated / "Q.json").read_text())
    old = {k: doc[k] for k in ("q_hat", "installation_angles_deg", "mounting_quaternion_q_bs", "residual_deg")}
    old["format"] = "mtcal-calibration/1"
    (tmp_path / "Q1.json").write_text(json.dumps(old))
    fl = nl.flight_log(duration_s=12.0)
    fl.write(tmp_path / "f.csv")
    assert cli.main(["apply", str(tmp_path / "Q1.json"), str(tmp_path / "f.csv"), "--out", str(tmp_path / "b.csv")]) == 0
    err = _errors(tmp_path / "b.csv", fl.ypr_deg)
    assert np.abs(err[:, 1:]).max() < 0.05


PM_G_DEG = ((0, 0, 0), (0, 0, 180), (0, 90, 0), (0, -90, 0), (0, 0, 90), (0, 0, -90))


@pytest.fixture(scope="module")
def pm_g(tmp_path_factory):
    d = tmp_path_factory.mktemp("pmg")
    wp = [(0, 0, 0)] + [p for pos in PM_G_DEG[1:] for p in (pos, (0, 0, 0))]
    log = nl.imu_log(nl.waypoint_path(wp, hold_s=3.0, move_s=3.0), seed=11)
    log.write(d / "pmg.csv")
    pd.DataFrame(PM_G_DEG, columns=["yaw_deg", "pitch_deg", "roll_deg"]).to_csv(d / "pos.csv", index=False)
    return d


def test_pm_g_set_refused_by_eq13_with_a_hint(pm_g, capsys):
    code = cli.main(["calibrate", str(pm_g / "pmg.csv"), "--positions", str(pm_g / "pos.csv")])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "no rotation about z (yaw)" in err and "--model so4 (6) or --model mounting (3)" in err


@pytest.mark.parametrize("model", ["so4", "mounting"])
def test_pm_g_set_calibrates_with_a_constrained_model(pm_g, capsys, model):
    out = pm_g / f"Q_{model}.json"
    assert cli.main(["calibrate", str(pm_g / "pmg.csv"), "--positions", str(pm_g / "pos.csv"),
                     "--model", model, "--out", str(out)]) == 0
    doc = json.loads(out.read_text())
    assert doc["model"] == model
    m = doc["mounting_ypr_deg"]
    np.testing.assert_allclose([m["yaw_z"], m["pitch_x"], m["roll_y"]], nl.MOUNT_DEG, atol=0.05)
    assert all(np.isfinite(v) for v in doc["installation_angles_1sigma_deg"].values())


def _summary_deg(out: str) -> tuple[float, float]:
    """The before/after numbers of calibrate's last line ``max |error| (rotation angle …) before B deg, after A deg``."""
    line = out.strip().splitlines()[-1]
    assert line.startswith("max |error| (rotation angle to the reference) before ")
    return float(line.split(" before ")[1].split()[0]), float(line.split(", after ")[1].split()[0])


def test_pm_g_summary_is_the_rotation_angle_not_euler_differences(pm_g, capsys):
    """At pitch ±90° ZXY yaw/roll are undefined (gimbal lock): the summary is the rotation angle between reference
    and measured attitude (after ≈ the residuals, ~0.01°; it printed 109.87° from Euler differences), and the
    table marks yaw/roll errors n/a there."""
    capsys.readouterr()
    assert cli.main(["calibrate", str(pm_g / "pmg.csv"), "--positions", str(pm_g / "pos.csv"), "--model", "so4"]) == 0
    out = capsys.readouterr().out
    before, after = _summary_deg(out)
    assert after < 0.1 and 0.5 < before < 2.0          # the 1° mounting error before, the residuals after
    rows = [ln.split() for ln in out.splitlines() if ln[:3].strip().isdigit() and len(ln.split()) == 12]
    pitch_rows = [r for r in rows if r[2] in ("+90.0000", "-90.0000")]      # pos, ref y/p/r, before y/p/r, angle, …
    assert len(rows) == 6 and all(r[4] != "n/a" for r in rows if r not in pitch_rows)
    assert len(pitch_rows) == 2 and all(r[4] == "n/a" and r[6] == "n/a" and r[8] == "n/a" and r[10] == "n/a"
                                        for r in pitch_rows)
    assert "n/a: yaw/roll error undefined within 5 deg of pitch +-90 deg" in out


def test_wrong_calibration_still_shows_a_large_error(pm_g, tmp_path, capsys):
    """Positions that do not match the log (pitch ±86° for ±90°), let through a loose --max-residual-deg: the
    summary's 'after' stays large (≈ 4°)."""
    wrong = [(y, 86.0 * np.sign(p), r) for y, p, r in PM_G_DEG]
    pd.DataFrame(wrong, columns=["yaw_deg", "pitch_deg", "roll_deg"]).to_csv(tmp_path / "wrong.csv", index=False)
    capsys.readouterr()
    assert cli.main(["calibrate", str(pm_g / "pmg.csv"), "--positions", str(tmp_path / "wrong.csv"), "--model", "so4",
                     "--max-residual-deg", "30"]) == 0
    before, after = _summary_deg(capsys.readouterr().out)
    assert after > 3.0 and before > 3.0


def _frd(df: pd.DataFrame) -> pd.DataFrame:
    """The same log from a sensor with FRD axes (x forward, y right, z down)."""
    out = df.copy()
    for k, u in (("gyro", "rad_s"), ("accel", "m_s2")):
        x, y, z = (df[f"{k}_{a}_{u}"].to_numpy() for a in "xyz")
        out[f"{k}_x_{u}"], out[f"{k}_y_{u}"], out[f"{k}_z_{u}"] = y, x, -z
    return out


@pytest.mark.parametrize("mistake,expected", [
    ("radians", "likely mistake: radians"),
    ("pitch_sign", "likely mistake: pitch sign flipped"),
    ("swap", "likely mistake: pitch and roll swapped"),
    ("frd", "reads -g on z at its first rest"),
    ("start", "does not start at the mechanism zero — with the attitude zeroed at the rest at 4.7 s"),
])
def test_convention_mistakes_are_diagnosed(calibrated, tmp_path, capsys, mistake, expected):
    tt, pos = nl.turntable_log()
    df = tt.df
    if mistake == "radians":
        pos = np.radians(pos)
    elif mistake == "pitch_sign":
        pos = pos.assign(pitch_deg=-pos.pitch_deg)
    elif mistake == "swap":
        pos = pos.assign(pitch_deg=pos.roll_deg, roll_deg=pos.pitch_deg)
    elif mistake == "frd":
        df = _frd(df)
    else:
        wp = [(0, 5, 0), (0, 0, 0)] + [p for q in nl.SIX_POSITIONS_DEG for p in (q, (0, 0, 0))]
        df = nl.imu_log(nl.waypoint_path(wp, hold_s=3.0, move_s=2.0)).df
    df.to_csv(tmp_path / "log.csv", index=False)
    pos.to_csv(tmp_path / "pos.csv", index=False)
    capsys.readouterr()
    code = cli.main(["calibrate", str(tmp_path / "log.csv"), "--positions", str(tmp_path / "pos.csv")])
    cap = capsys.readouterr()
    assert code == 2 and len(cap.err.strip().splitlines()) == 1 and expected in cap.err
    table = cap.out.split("nearest rest (zeroed sensor attitude")[1].splitlines()
    assert len([ln for ln in table if ln.strip()[:1].isdigit()]) == len(pos)     # one row per reference position


def test_quiet_core_threshold_honours_noise_factor(calibrated, capsys):
    """--noise-factor K sets every noise-derived threshold, the quiet core's K σ/√W included (one meaning
    of K): the printed threshold scales with K, and a looser K lets more of the slow start into the core."""
    d = calibrated
    nl.flight_log(slow_start_s=3.0, seed=3, duration_s=20.0).write(d / "slow_k.csv")
    lines = {}
    for k in ("3", "5", "12"):
        capsys.readouterr()
        argv = ["apply", str(d / "Q.json"), str(d / "slow_k.csv"), "--out", str(d / f"body_k{k}.csv")]
        assert cli.main(argv + ([] if k == "5" else ["--noise-factor", k])) == 0
        lines[k] = next(ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("gyro bias"))
        assert f": {k} x measured noise" in lines[k]
    thr = {k: float(v.split(" deg/s of the bias")[0].split()[-1]) for k, v in lines.items()}
    assert thr["3"] == pytest.approx(0.6 * thr["5"], rel=0.01) and thr["12"] == pytest.approx(2.4 * thr["5"], rel=0.01)
    end = {k: float(v.split("quiet core ")[1].split("-")[1].split()[0]) for k, v in lines.items()}
    assert end["3"] <= end["5"] <= end["12"] < 5.6   # the motion starts at 5 s


def test_residual_refusal_names_the_option(calibrated, capsys):
    """The procedure names its parameter (max_residual_rad); the command names the option the user types."""
    d = calibrated
    code = cli.main(["calibrate", str(d / "turntable.csv"), "--positions", str(d / "pos.csv"),
                     "--max-residual-deg", "0.0001"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert "exceeds --max-residual-deg (0.0001 deg); a rest does not match its reference position" in err
    assert "max_residual_rad" not in err


def test_apply_columns_as_documented_is_static_for_raw_logs(calibrated, tmp_path, capsys):
    """apply writes the documented columns: is_static (0/1, the detected rests) for a raw log, none for q0..q3."""
    fl = nl.flight_log(duration_s=12.0)
    fl.write(tmp_path / "f.csv")
    assert cli.main(["apply", str(calibrated / "Q.json"), str(tmp_path / "f.csv"), "--out", str(tmp_path / "b.csv")]) == 0
    df = pd.read_csv(tmp_path / "b.csv")
    angles = ["yaw_deg", "pitch_deg", "roll_deg", "sensor_yaw_deg", "sensor_pitch_deg", "sensor_roll_deg"]
    assert list(df.columns) == ["time_s", "q0", "q1", "q2", "q3", *angles, "is_static"]
    assert set(df["is_static"].unique()) <= {0, 1} and df["is_static"].iloc[0] == 1      # parked at the start
    df[["time_s", "q0", "q1", "q2", "q3"]].to_csv(tmp_path / "q.csv", index=False)
    assert cli.main(["apply", str(calibrated / "Q.json"), str(tmp_path / "q.csv"), "--out", str(tmp_path / "bq.csv")]) == 0
    assert list(pd.read_csv(tmp_path / "bq.csv").columns) == ["time_s", "q0", "q1", "q2", "q3", *angles]
    capsys.readouterr()
    for command in ("apply", "calibrate"):
        with pytest.raises(SystemExit):
            cli.main([command, "--help"])
        text = " ".join(capsys.readouterr().out.split())
        assert ".mat (v5, v7.3) / HDF5 .h5/.hdf5" in text and "Parquet" in text
        assert command == "calibrate" or "is_static (0/1" in text
