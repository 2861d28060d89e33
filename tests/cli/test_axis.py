"""Tests of ``mtcal axis`` / ``mtcal angle`` (wang2022sensors CLI)."""

import re

import numpy as np
import pandas as pd
import pytest

from mtcal import cli
from mtcal.core import profiles
from mtcal.studies.wang2022sensors.runs import ImuSpec, RotationSetup, simulate_rotation


@pytest.fixture
def log(tmp_path, rng):
    imu = ImuSpec()
    prof = profiles.step_schedule(np.radians([0, 90, 180, 30]), np.radians(60), 1.5, imu.fs_hz)
    setup = RotationSetup()
    rec = simulate_rotation(prof.angle_rad[:, 0], prof.rate_rad_s[:, 0], prof.accel_rad_s2[:, 0],
                            prof.is_static, setup, imu.error_model(), imu.dt_s, 12345)
    df = pd.DataFrame({"time_s": rec.time_s})
    for i, ax in enumerate("xyz"):
        df[f"gyro_{ax}_rad_s"] = rec.gyro_rad_s[0, :, i]
    for i, ax in enumerate("xyz"):
        df[f"accel_{ax}_m_s2"] = rec.accel_m_s2[0, :, i]
    path = tmp_path / "log.csv"
    df.to_csv(path, index=False)
    return path, df, setup.unit_axis(), rec.theta_rad[0]


def test_axis_happy_path(log, capsys, tmp_path):
    path, _, v, _ = log
    fig = tmp_path / "q.png"
    assert cli.main(["axis", str(path), "--figure", str(fig)]) == 0
    out = capsys.readouterr().out
    est = np.array([float(x) for x in out.split("axis v = ")[1].split()[0].split(",")])
    assert np.degrees(np.arccos(min(est @ v, 1.0))) < 0.05
    assert fig.is_file() and len(re.findall(r"^rest \d+: ", out, re.M)) == 4


def test_angle_happy_path(log, tmp_path):
    path, _, v, theta = log
    out = tmp_path / "angle.csv"
    assert cli.main(["angle", str(path), "--axis", ",".join(f"{x:.8f}" for x in v), "--out", str(out)]) == 0
    res = pd.read_csv(out)
    assert list(res.columns) == ["time_s", "angle_deg", "is_static"]
    assert abs(res.angle_deg.iloc[-1] - np.degrees(theta[-1])) < 0.1
    # whole record, moves included: the adaptive rests never flag a moving sample as static
    assert np.sqrt(np.mean((res.angle_deg - np.degrees(theta)) ** 2)) < 0.1


def test_angle_paper_detector_keeps_the_old_path(log, tmp_path):
    """--rest-detector paper: Table 1 ZVD flags and the first --init-s seconds, as the CLI always did."""
    from mtcal.methods.zero_velocity import detect_static

    path, df, v, theta = log
    out = tmp_path / "angle.csv"
    assert cli.main(["angle", str(path), "--axis", ",".join(f"{x:.8f}" for x in v), "--out", str(out),
                     "--rest-detector", "paper"]) == 0
    res = pd.read_csv(out)
    acc = df[["accel_x_m_s2", "accel_y_m_s2", "accel_z_m_s2"]].to_numpy()
    assert np.array_equal(res.is_static.to_numpy(bool), detect_static(acc, np.diff(df.time_s).mean()))
    assert abs(res.angle_deg.iloc[-1] - np.degrees(theta[-1])) < 0.1


@pytest.mark.parametrize("mutate,msg", [
    (lambda d: d.drop(columns=["accel_y_m_s2"]), "missing column"),
    (lambda d: d.assign(accel_x_m_s2=d.accel_x_m_s2.where(d.index != 5)), "NaN"),
    (lambda d: d.iloc[::-1], "not strictly increasing"),
    (lambda d: d.iloc[:250], "found only"),
])
def test_bad_files_exit_2(log, tmp_path, capsys, mutate, msg):
    _, df, _, _ = log
    bad = tmp_path / "bad.csv"
    mutate(df).to_csv(bad, index=False)
    assert cli.main(["axis", str(bad)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("mtcal: error: ") and msg in err and err.count("\n") == 1


def test_angle_bad_axis_exit_2(log, capsys):
    path, _, _, _ = log
    assert cli.main(["angle", str(path), "--axis", "1,2"]) == 2
    assert "--axis" in capsys.readouterr().err


def test_report_lines_are_what_print_report_prints(log, capsys):
    from mtcal.cli import common, logio
    from mtcal.systems.rests import RestsConfig, find_rests

    path = log[0]
    imu_log = logio.read_log(path, logio.InputOptions(), need="raw")
    rep = find_rests(imu_log.accel_m_s2, imu_log.dt_mean_s, RestsConfig(), gyro_rad_s=imu_log.gyro_rad_s,
                     time_s=imu_log.time_s)
    extra = {"x_deg": np.arange(len(rep.rests), dtype=float)}
    common.print_report(imu_log, rep, angle_deg=np.zeros(imu_log.n), extra=extra)
    printed = capsys.readouterr().out
    assert printed == "\n".join(common.report_lines(imu_log, rep, angle_deg=np.zeros(imu_log.n), extra=extra)) + "\n"
    chk = {"method": "rest pairs", "evidence": "3 pairs"}
    common.print_units_check(chk)
    common.print_units_check({"warning": "undecided"})
    assert capsys.readouterr().out == (common.units_check_line(chk) + "\n"
                                       + common.units_check_line({"warning": "undecided"}) + "\n")
