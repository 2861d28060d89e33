"""Tests for ``mtcal calibrate`` (mtcal.cli.calibrate) through the dispatcher."""

import numpy as np
import pandas as pd
import pytest

from mtcal import cli
from mtcal.core import rotations
from mtcal.methods import six_position
from mtcal.core.profiles import trajectory_from_euler_zxy
from mtcal.core.simulate import ImuErrorModel, simulate_imu
from mtcal.systems import installation

FS = 200.0
ALPHA = np.radians([0.5, -0.3, 0.4])


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("cal")
    pos = six_position.six_positions_rad()
    prof = six_position.schedule_profile(pos, fs_hz=FS)
    rec = simulate_imu(trajectory_from_euler_zxy(prof),
                       ImuErrorModel(q_mount=tuple(rotations.mount_quaternion(ALPHA))))
    quat = pd.DataFrame(rec.q_ws_true, columns=["q0", "q1", "q2", "q3"])
    quat.insert(0, "time_s", rec.time_s)
    raw = pd.DataFrame(np.hstack([rec.gyro_rad_s, rec.accel_m_s2]),
                       columns=["gyro_x_rad_s", "gyro_y_rad_s", "gyro_z_rad_s",
                                "accel_x_m_s2", "accel_y_m_s2", "accel_z_m_s2"])
    raw.insert(0, "time_s", rec.time_s)
    positions = pd.DataFrame(np.degrees(pos), columns=["yaw_deg", "pitch_deg", "roll_deg"])
    paths = {"quat": d / "quat.csv", "raw": d / "raw.csv", "pos": d / "pos.csv"}
    quat.to_csv(paths["quat"], index=False)
    raw.to_csv(paths["raw"], index=False)
    positions.to_csv(paths["pos"], index=False)
    return paths, quat, raw


@pytest.mark.parametrize("kind", ["quat", "raw"])
def test_happy_path(files, capsys, kind):
    paths, _, _ = files
    assert cli.main(["calibrate", str(paths[kind]), "--positions", str(paths["pos"])]) == 0
    out = capsys.readouterr().out
    assert "Q_hat" in out and "8 rests found" in out
    after = float(out.strip().splitlines()[-1].split("after")[1].split()[0])
    assert after < 1e-6


def _run_bad(tmp_path, capsys, df, paths, name="bad.csv"):
    p = tmp_path / name
    df.to_csv(p, index=False)
    code = cli.main(["calibrate", str(p), "--positions", str(paths["pos"])])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("mtcal: error: ") and len(err.strip().splitlines()) == 1
    return err


def test_missing_columns(files, tmp_path, capsys):
    paths, quat, _ = files
    err = _run_bad(tmp_path, capsys, quat.drop(columns=["q2"]), paths)
    assert "missing columns" in err and "q2" in err
    err = _run_bad(tmp_path, capsys, quat.drop(columns=["time_s"]), paths)
    assert "time_s" in err


def test_nan_rows(files, tmp_path, capsys):
    paths, quat, _ = files
    bad = quat.copy()
    bad.loc[100, "q1"] = np.nan
    err = _run_bad(tmp_path, capsys, bad, paths)
    assert "NaN" in err and "'q1'" in err and "row 101" in err


def test_unsorted_time(files, tmp_path, capsys):
    paths, quat, _ = files
    bad = quat.copy()
    bad.loc[[50, 51], "time_s"] = bad.loc[[51, 50], "time_s"].to_numpy()
    err = _run_bad(tmp_path, capsys, bad, paths)
    assert "not strictly increasing" in err


def test_too_few_rests(files, tmp_path, capsys):
    paths, quat, _ = files
    err = _run_bad(tmp_path, capsys, quat.iloc[:3000], paths)
    assert "too few rests" in err


def test_missing_file(files, tmp_path, capsys):
    paths, _, _ = files
    code = cli.main(["calibrate", str(tmp_path / "nope.csv"), "--positions", str(paths["pos"])])
    assert code == 2 and "not found" in capsys.readouterr().err


def test_positions_too_few(files, tmp_path, capsys):
    paths, _, _ = files
    p = tmp_path / "pos2.csv"
    pd.DataFrame({"yaw_deg": [8, -8], "pitch_deg": [0, 0], "roll_deg": [0, 0]}).to_csv(p, index=False)
    code = cli.main(["calibrate", str(paths["quat"]), "--positions", str(p)])
    assert code == 2 and "at least 4 positions" in capsys.readouterr().err


def test_paper_detector_reproduces_the_library_procedure(files, capsys):
    """--rest-detector paper: §3.2 stillness detector (0.2 deg/s, 2 s), default QNCF — the library's numbers."""
    from mtcal.filters.qncf import qncf

    paths, _, raw = files
    assert cli.main(["calibrate", str(paths["raw"]), "--positions", str(paths["pos"]), "--rest-detector", "paper"]) == 0
    out = capsys.readouterr().out
    gyro = raw[["gyro_x_rad_s", "gyro_y_rad_s", "gyro_z_rad_s"]].to_numpy()
    acc = raw[["accel_x_m_s2", "accel_y_m_s2", "accel_z_m_s2"]].to_numpy()
    q = qncf(gyro, acc, 1 / FS, return_euler=False).q_ws
    ref = installation.calibrate_installation(installation.InstallationConfig.paper(), six_position.six_positions_rad(),
                                              1 / FS, q_ws=q, gyro_rad_s=gyro)
    block = out.split("q_sensor):\n")[1].splitlines()[:4]
    assert block == ["  " + "  ".join(f"{v:+.6f}" for v in row) for row in ref.q_hat]
