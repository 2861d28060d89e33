"""The CLI on logs with real-sensor quirks: the right answer, or a one-line refusal (never a wrong number).

Logs come from tests/cli/logs.py (mtcal's simulator + |g| off 9.81, gyro bias and bias
steps, whole-millisecond jittered timestamps, clipping, counts, 110/150/1200 Hz).
"""

import json
import re

import numpy as np
import pandas as pd
import pytest

from mtcal.core import rotations

from . import logs
from tests.cli.runner import refused as _refused, run as _run

TOL_DEG = 1.5


def _axis(out):
    return np.array([float(x) for x in re.search(r"axis v = (\S+)", out).group(1).split(",")])


def _angle_deg(a, b):
    return float(np.degrees(np.arccos(min(1.0, abs(float(a @ b))))))


CASES = {
    "g_1.2pct_bias": dict(),
    "g_3pct_low": dict(g_error=-0.03, gyro_bias_deg_s=(3.0, 0.5, -2.0)),
    "bias_steps": dict(bias_step_deg_s=0.5),
    "whole_ms_3_7": dict(jitter_ms=(3, 7), bias_step_deg_s=0.3),
    "clipped": dict(clip_deg_s=60.0),
    "counts_150hz": dict(counts=True, fs_hz=150.0),
    "110hz": dict(fs_hz=110.0),
    "deg_s_time_ms": dict(gyro_unit="deg/s", time_unit="ms"),
    "accel_g": dict(accel_unit="g", g_error=0.005),
}


@pytest.fixture(scope="module")
def hinge_logs(tmp_path_factory):
    d = tmp_path_factory.mktemp("hinge")
    out = {}
    for k, kw in CASES.items():
        log = logs.hinge_log(**kw)
        out[k] = (log, log.write(d / f"{k}.csv"))
    return out


@pytest.mark.parametrize("case", list(CASES))
def test_axis_and_angle_right_on_quirky_logs(case, hinge_logs, tmp_path, capsys):
    log, path = hinge_logs[case]
    code, out, err = _run(["axis", path, *log.options], capsys)
    assert code == 0, err
    assert _angle_deg(_axis(out), log.axis) < TOL_DEG
    assert len(re.findall(r"^rest \d+: ", out, re.M)) == len(log.rest_spans_s)  # every visible rest
    dest = tmp_path / "angle.csv"
    v = ",".join(f"{x:.6f}" for x in log.axis)
    code, out, err = _run(["angle", path, "--axis", v, "--out", dest, *log.options], capsys)
    assert code == 0, err
    res = pd.read_csv(dest)
    assert list(res.columns) == ["time_s", "angle_deg", "is_static"]
    assert abs(res.angle_deg.iloc[-1] - log.final_angle_deg) < TOL_DEG
    # per-rest summary: every rest's angle right
    holds = np.array(log.rest_spans_s)
    for t0, t1 in holds:
        inside = res[(res.time_s > t0 + 0.3 * (t1 - t0)) & (res.time_s < t1 - 0.3 * (t1 - t0))]
        assert inside.is_static.mean() > 0.9
    assert "final angle" in out and re.search(r"^\s+rest\s+start_s.*angle_deg accel_angle_deg$", out, re.M)


def test_short_stances_at_1200hz_all_found(tmp_path, capsys):
    log = logs.stance_log()
    path = log.write(tmp_path / "walk.csv")
    code, out, err = _run(["rests", path, "--out", tmp_path / "rests.csv"], capsys)
    assert code == 0, err
    found = pd.read_csv(tmp_path / "rests.csv")
    assert len(found) == len(log.rest_spans_s) == 11
    for (t0, t1), (s0, s1) in zip(log.rest_spans_s, found[["start_s", "stop_s"]].to_numpy()):
        assert t0 - 0.01 <= s0 and s1 <= t1 + 0.01 and (s1 - s0) > 0.6 * (t1 - t0) - 0.1
    assert abs(found.accel_norm_m_s2.median() - 9.80665 * 1.027) < 0.05  # |a| 2.7 % high is measured


def test_paper_detector_misses_offset_sensor_and_says_why(tmp_path, capsys):
    log = logs.stance_log()
    path = log.write(tmp_path / "walk.csv")
    code, out, err = _run(["axis", path, "--rest-detector", "paper"], capsys)
    _refused(code, err, "paper ZVD band 9.76-9.84", "measured |a|")


def test_turn_about_vertical_axis_refused(tmp_path, capsys):
    log = logs.turn_about_vertical_log()
    path = log.write(tmp_path / "turn.csv")
    code, out, err = _run(["axis", path, *log.options], capsys)
    _refused(code, err, "distinct tilt", "rotation about the vertical")
    code, out, err = _run(["angle", path, "--axis", "0,0,1", "--out", tmp_path / "a.csv", *log.options], capsys)
    _refused(code, err, "from gravity")
    assert not (tmp_path / "a.csv").exists()


def test_turn_about_vertical_attitude_yaw_right(tmp_path, capsys):
    log = logs.turn_about_vertical_log()
    path = log.write(tmp_path / "turn.csv")
    code, out, err = _run(["attitude", path, "--out", tmp_path / "att.parquet", *log.options], capsys)
    assert code == 0, err
    att = pd.read_parquet(tmp_path / "att.parquet")
    assert abs(rotations.wrap_angle(np.radians(att.yaw_deg.iloc[-1] - 178.0))) < np.radians(TOL_DEG)


def test_two_flips(tmp_path, capsys):
    log = logs.two_flips_log()
    path = log.write(tmp_path / "flips.csv")
    code, out, err = _run(["axis", path], capsys)
    _refused(code, err, "found only 2 distinct tilt")
    code, out, err = _run(["angle", path, "--axis", "1,0,0", "--out", tmp_path / "a.csv"], capsys)
    assert code == 0, err
    assert abs(pd.read_csv(tmp_path / "a.csv").angle_deg.iloc[-1] - 359.0) < TOL_DEG
    code, out, err = _run(["attitude", path, "--out", tmp_path / "att.csv"], capsys)
    assert code == 0, err
    att = pd.read_csv(tmp_path / "att.csv")
    q_end = att[["q0", "q1", "q2", "q3"]].to_numpy()[-1]
    truth = rotations.quat_from_rotvec(np.radians(359.0) * np.array([1.0, 0, 0]))
    assert np.degrees(rotations.quat_angle_between(q_end, truth)) < TOL_DEG


@pytest.mark.parametrize("mutate,needles", [
    (dict(gyro_unit="deg/s", rate_deg_s=15.0), ["gyro and accelerometer disagree", "--gyro-unit deg/s"]),
    (dict(gyro_unit="deg/s"), ["deg/s"]),
    (dict(time_unit="ms"), ["implausible", "--time-unit ms"]),
    (dict(time_unit="us"), ["implausible", "--time-unit"]),
    (dict(counts=True), ["accel"]),
])
def test_wrong_units_refused(mutate, needles, tmp_path, capsys):
    log = logs.hinge_log(**mutate)
    path = log.write(tmp_path / "x.csv")
    code, out, err = _run(["angle", path, "--axis", "0.6,0,0.8", "--out", tmp_path / "a.csv"], capsys)
    _refused(code, err, *needles)
    assert not (tmp_path / "a.csv").exists()


def test_time_labelled_10x_fast_refused(tmp_path, capsys):
    log = logs.hinge_log()
    df = log.df.copy()
    df["time_s"] /= 10.0
    path = tmp_path / "fast.csv"
    df.to_csv(path, index=False)
    code, out, err = _run(["angle", path, "--axis", "0.6,0,0.8", "--out", tmp_path / "a.csv",
                           "--min-rest-s", "0.05"], capsys)
    _refused(code, err, "10x too small")


@pytest.mark.parametrize("axis,needle", [("0.338,0.171,0.925", "from gravity"),
                                         ("-0.8,0,0.6", "the gyro turns about"),
                                         ("0,1,0", "the gyro turns about")])
def test_wrong_axis_refused(axis, needle, hinge_logs, tmp_path, capsys):
    _, path = hinge_logs["g_1.2pct_bias"]
    code, out, err = _run(["angle", path, "--axis", axis, "--out", tmp_path / "a.csv"], capsys)
    _refused(code, err, needle)


def test_negative_axis_both_spellings(hinge_logs, tmp_path, capsys):
    log, path = hinge_logs["g_1.2pct_bias"]
    for argv in (["--axis", "-0.6,0,-0.8"], ["--axis=-0.6,0,-0.8"]):
        code, out, err = _run(["angle", path, *argv, "--out", tmp_path / "a.csv"], capsys)
        assert code == 0, err
        assert abs(pd.read_csv(tmp_path / "a.csv").angle_deg.iloc[-1] + log.final_angle_deg) < TOL_DEG


def test_close_rests_axis_refused_or_uncertain(tmp_path, capsys):
    """Three rests only 1.7-3.4 deg apart in tilt: refuse (axis uncertainty), not a confident wrong axis."""
    log = logs.hinge_log(angles_deg=(0, 4, 8), axis=(1.0, 0.0, 0.0), q_wb0=(1.0, 0.0, 0.0, 0.0))
    path = log.write(tmp_path / "close.csv")
    code, out, err = _run(["axis", path], capsys)
    _refused(code, err, "axis too uncertain")
    code, out, err = _run(["axis", path, "--rest-detector", "paper", "--gravity", "9.9"], capsys)
    assert code == 2


def test_calibrate_apply_round_trip_on_mems_log(tmp_path, capsys):
    df, pos, alpha = logs.six_position_log()
    df.to_csv(tmp_path / "six.csv", index=False)
    pos.to_csv(tmp_path / "pos.csv", index=False)
    code, out, err = _run(["calibrate", tmp_path / "six.csv", "--positions", tmp_path / "pos.csv",
                           "--out", tmp_path / "Q.json", "--figure", tmp_path / "cal.png"], capsys)
    assert code == 0, err
    assert "Q_hat (Eq 13, q_body = Q_hat q_sensor):" in out
    doc = json.loads((tmp_path / "Q.json").read_text())
    got = [doc["installation_angles_deg"][k] for k in ("alpha1_z", "alpha2_y", "alpha3_x")]
    np.testing.assert_allclose(got, alpha, atol=0.1)
    assert (tmp_path / "cal.png").stat().st_size > 10_000
    code, out, err = _run(["apply", tmp_path / "Q.json", tmp_path / "six.csv", "--out", tmp_path / "b.parquet"],
                          capsys)
    assert code == 0, err
    body = pd.read_parquet(tmp_path / "b.parquet")
    assert {"time_s", "q0", "yaw_deg", "pitch_deg", "roll_deg", "sensor_pitch_deg"} <= set(body.columns)
    assert abs(body.pitch_deg.iloc[-1]) < 0.1 and abs(body.roll_deg.iloc[-1]) < 0.1


def test_calibrate_paper_stillness_fails_with_levels(tmp_path, capsys):
    df, pos, _ = logs.six_position_log()
    df.to_csv(tmp_path / "six.csv", index=False)
    pos.to_csv(tmp_path / "pos.csv", index=False)
    code, out, err = _run(["calibrate", tmp_path / "six.csv", "--positions", tmp_path / "pos.csv",
                           "--rest-detector", "paper"], capsys)
    _refused(code, err, "too few rests", "measured gyro bias")


def test_calibrate_degenerate_positions_refused(tmp_path, capsys):
    yaw_only = [[8, 0, 0], [-8, 0, 0], [16, 0, 0], [-16, 0, 0]]
    df, pos, _ = logs.six_position_log(positions_deg=yaw_only)
    df.to_csv(tmp_path / "six.csv", index=False)
    pos.to_csv(tmp_path / "pos.csv", index=False)
    code, out, err = _run(["calibrate", tmp_path / "six.csv", "--positions", tmp_path / "pos.csv"], capsys)
    _refused(code, err, "positions")


def test_log_starting_in_motion_measured_from_first_rest(tmp_path, capsys):
    log = logs.hinge_log(angles_deg=(-20, 0, 60, 120, 30), hold_s=[0.05, 1.5, 1.5, 1.5, 1.5])
    path = log.write(tmp_path / "late.csv")
    code, out, err = _run(["angle", path, "--axis", "0.6,0,0.8", "--out", tmp_path / "a.csv"], capsys)
    assert code == 0, err
    assert "angles are measured from the first rest" in out
    res = pd.read_csv(tmp_path / "a.csv")
    t_first = log.rest_spans_s[1][0]
    assert res.angle_deg[res.time_s < t_first - 0.05].isna().all()
    assert abs(res.angle_deg.iloc[-1] - 30.0) < TOL_DEG


def test_calibrate_refuses_deg_s_gyro(tmp_path, capsys):
    df, pos, _ = logs.six_position_log()
    gy = [c for c in df if c.startswith("gyro")]
    df[gy] = np.degrees(df[gy])
    df.to_csv(tmp_path / "six.csv", index=False)
    pos.to_csv(tmp_path / "pos.csv", index=False)
    code, out, err = _run(["calibrate", tmp_path / "six.csv", "--positions", tmp_path / "pos.csv"], capsys)
    _refused(code, err, "--gyro-unit deg/s")
    code, out, err = _run(["calibrate", tmp_path / "six.csv", "--positions", tmp_path / "pos.csv",
                           "--gyro-unit", "deg/s"], capsys)
    assert code == 0, err
