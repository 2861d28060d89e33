"""Every command: help shows schema/units/example, one-line errors, figure always written, gates."""

import importlib
import json

import numpy as np
import pandas as pd
import pytest

from mtcal import cli

from . import logs

main_mod = importlib.import_module("mtcal.cli.main")

COMMANDS = ["rests", "calibrate", "axis", "angle", "attitude", "apply"]


@pytest.fixture(scope="module")
def hinge(tmp_path_factory):
    d = tmp_path_factory.mktemp("cmd")
    log = logs.hinge_log(hold_s=1.2)
    return log, log.write(d / "hinge.csv")


@pytest.mark.parametrize("command", COMMANDS)
def test_help_shows_schema_units_example(command, capsys):
    with pytest.raises(SystemExit) as exc:
        cli.main([command, "--help"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    assert "example:" in out and "mtcal " + command in out
    assert "time_s" in out and ("rad/s" in out or "rad_s" in out) and ("m/s" in out or "m_s2" in out)
    assert "--rest-detector" in out and "--time-unit" in out


def test_argparse_errors_are_one_line(capsys):
    with pytest.raises(SystemExit) as exc:
        cli.main(["angle", "log.csv"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("mtcal: error: ") and err.count("\n") == 1 and "--axis" in err


@pytest.mark.parametrize("argv,match", [
    (["--init-s", "inf"], "--init-s must be a finite number"),
    (["--init-s", "nan"], "--init-s must be a finite number"),
    (["--init-s", "-1"], "--init-s must be a finite number > 0"),
    (["--axis", "1,2"], "--axis must be three"),
    (["--axis", "0,0,0"], "not all zero"),
    (["--axis", "a,b,c"], "--axis must be three numbers"),
    (["--noise-factor", "inf"], "--noise-factor must be a finite"),
    (["--gravity", "0.98"], "--gravity must be in m/s"),
    (["--gravity", "1e308"], "--gravity must be in m/s"),
    (["--max-elevation-deg", "200"], r"--max-elevation-deg must be a number in \(0, 90\]"),
    (["--init-s", "1e9"], "--init-s 1e9 s is not shorter than the log"),
    (["--out", "angle.xlsx"], "the file type must be .csv or .parquet"),
    (["--columns", "foo=bar"], "unknown name 'foo'"),
])
def test_bad_arguments_one_line(hinge, tmp_path, capsys, argv, match):
    _, path = hinge
    args = ["angle", path] + ([] if "--out" in argv else ["--out", str(tmp_path / "a.csv")])
    if "--axis" not in argv:
        args += ["--axis", "0.6,0,0.8"]
    assert cli.main(args + argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("mtcal: error: ") and err.count("\n") == 1
    assert pytest.importorskip("re").search(match, err), err


def test_rests_command_table_and_levels(hinge, tmp_path, capsys):
    log, path = hinge
    assert cli.main(["rests", path, "--out", str(tmp_path / "r.parquet")]) == 0
    out = capsys.readouterr().out
    assert "|a| at rest" in out and "gyro bias" in out and "rests: 4 of" in out
    tab = pd.read_parquet(tmp_path / "r.parquet")
    assert len(tab) == 4 and {"start_s", "stop_s", "accel_norm_m_s2", "tilt_deg", "gyro_x_deg_s"} <= set(tab.columns)
    np.testing.assert_allclose(tab.gyro_x_deg_s, 1.2, atol=0.1)  # the bias is measured, not a threshold problem


def test_rests_overrides_change_the_band(hinge, capsys):
    _, path = hinge
    assert cli.main(["rests", path, "--gravity", "9.81", "--accel-band", "0.04"]) == 0
    out = capsys.readouterr().out
    assert "band 9.770-9.850" in out and "rests: 0 of" in out and "outside band" in out


def test_figure_written_on_failure(tmp_path, capsys):
    log = logs.turn_about_vertical_log()
    path = log.write(tmp_path / "turn.csv")
    fig = tmp_path / "fig.png"
    assert cli.main(["axis", path, "--figure", str(fig), *log.options]) == 2
    assert fig.stat().st_size > 10_000
    assert "figure:" in capsys.readouterr().out
    fig2 = tmp_path / "fig2.png"
    assert cli.main(["angle", str(tmp_path / "missing.csv"), "--axis", "1,0,0", "--figure", str(fig2)]) == 2
    assert fig2.stat().st_size > 5_000


def test_attitude_columns(hinge, tmp_path, capsys):
    _, path = hinge
    assert cli.main(["attitude", path, "--out", str(tmp_path / "att.csv")]) == 0
    att = pd.read_csv(tmp_path / "att.csv")
    assert list(att.columns) == ["time_s", "q0", "q1", "q2", "q3", "yaw_deg", "pitch_deg", "roll_deg", "is_static"]
    np.testing.assert_allclose(np.linalg.norm(att[["q0", "q1", "q2", "q3"]], axis=1), 1.0, atol=1e-8)


def test_unexpected_exception_is_one_line_without_debug(hinge, monkeypatch, capsys):
    _, path = hinge
    monkeypatch.delenv("MTCAL_DEBUG")

    def boom(*a, **k):
        raise RuntimeError("kaboom\nsecond line")

    monkeypatch.setattr("mtcal.cli.logio.read_log", boom)
    assert cli.main(["rests", path]) == 2
    err = capsys.readouterr().err
    assert err.startswith("mtcal: error: cannot process this input (RuntimeError: kaboom second line)")
    assert err.count("\n") == 1
    monkeypatch.setenv("MTCAL_DEBUG", "1")
    with pytest.raises(RuntimeError):  # real bugs stay visible in tests
        cli.main(["rests", path])


def test_negative_vector_options_are_joined():
    assert main_mod._join_negative_vectors(["angle", "x", "--axis", "-0.3,0,1", "--gyro-scale", "-1"]) == [
        "angle", "x", "--axis=-0.3,0,1", "--gyro-scale=-1"]
    assert main_mod._join_negative_vectors(["--axis", "--out"]) == ["--axis", "--out"]


def test_calibrate_four_positions_note_and_three_refused(tmp_path, capsys):
    df, pos, _ = logs.six_position_log(positions_deg=[[8, 0, 0], [0, -12, 0], [0, 0, 90], [0, 23, 0]])
    df.to_csv(tmp_path / "log.csv", index=False)
    pos.to_csv(tmp_path / "pos.csv", index=False)
    assert cli.main(["calibrate", str(tmp_path / "log.csv"), "--positions", str(tmp_path / "pos.csv")]) == 0
    assert "residuals are 0 by construction" in capsys.readouterr().out
    pos.iloc[:3].to_csv(tmp_path / "pos3.csv", index=False)
    assert cli.main(["calibrate", str(tmp_path / "log.csv"), "--positions", str(tmp_path / "pos3.csv")]) == 2
    assert "at least 4 positions" in capsys.readouterr().err


@pytest.mark.parametrize("content,match", [
    ("not json", "not a JSON calibration"),
    (json.dumps({"format": "other"}), "not an mtcal calibration"),
    (json.dumps({"format": "mtcal-calibration/1", "q_hat": [[1, 0], [0, 1]]}), "q_hat must be a 4x4 array"),
    (json.dumps({"format": "mtcal-calibration/1", "q_hat": [[float("nan")] * 4] * 4}), "q_hat must be finite"),
    (json.dumps({"format": "mtcal-calibration/1", "q_hat": [[0.0] * 4] * 4}), "not an installation calibration"),
    (json.dumps({"format": "mtcal-calibration/1", "q_hat": (10 * np.eye(4)).tolist()}), "18 from the nearest rotation"),
    (json.dumps({"format": "mtcal-calibration/1", "q_hat": [[True, False, False, False]] * 4}),
     "q_hat must be a 4x4 array of numbers, not true/false"),
])
def test_apply_bad_calibration_file(hinge, tmp_path, capsys, content, match):
    _, path = hinge
    (tmp_path / "Q.json").write_text(content)
    assert cli.main(["apply", str(tmp_path / "Q.json"), path, "--out", str(tmp_path / "b.csv")]) == 2
    assert match in capsys.readouterr().err


def test_positions_file_with_a_repeated_column_is_refused(tmp_path, capsys):
    (tmp_path / "pos.csv").write_text("yaw_deg,pitch_deg,roll_deg,yaw_deg\n" + "0,0,0,1\n" * 6)
    (tmp_path / "log.csv").write_text("time_s,q0,q1,q2,q3\n" + "".join(f"{k / 100},1,0,0,0\n" for k in range(50)))
    assert cli.main(["calibrate", str(tmp_path / "log.csv"), "--positions", str(tmp_path / "pos.csv")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "column 'yaw_deg' appears 2 times in the header" in err


def test_apply_accepts_a_calibration_within_its_own_recorded_gate(hinge, tmp_path, capsys):
    """A Q̂ 0.1 from SO(4) (calibrated with a wider --max-so4-distance, which the file records) is applied; the
    same Q̂ in a file that records no such distance is refused by the default gate (0.05)."""
    _, path = hinge
    q_hat = np.diag([1.0, 1.1, 1.0, 1.0]).tolist()
    for doc, code in (({"so4_distance": 0.1}, 0), ({}, 2)):
        (tmp_path / "Q.json").write_text(json.dumps({"format": "mtcal-calibration/1", "q_hat": q_hat, **doc}))
        assert cli.main(["apply", str(tmp_path / "Q.json"), path, "--out", str(tmp_path / "b.csv")]) == code
    assert "0.1 from the nearest rotation of quaternion space (SO(4)), more than 0.05" in capsys.readouterr().err


def test_apply_reads_a_calibration_saved_with_a_byte_order_mark(hinge, tmp_path, capsys):
    _, path = hinge
    doc = json.dumps({"format": "mtcal-calibration/1", "q_hat": np.eye(4).tolist()})
    (tmp_path / "Q.json").write_bytes(b"\xef\xbb\xbf" + doc.encode())
    assert cli.main(["apply", str(tmp_path / "Q.json"), path, "--out", str(tmp_path / "b.csv")]) == 0


def test_rests_on_accelerometer_only_log(hinge, tmp_path, capsys):
    log, _ = hinge
    df = log.df[[c for c in log.df if not c.startswith("gyro")]]
    df.to_csv(tmp_path / "acc.csv", index=False)
    assert cli.main(["rests", str(tmp_path / "acc.csv")]) == 0
    out = capsys.readouterr().out
    assert "rests: 4 of" in out and "gyro bias" not in out


def test_attitude_units_check_scans_the_record_once(tmp_path, capsys, monkeypatch):
    """check_units decides by the tilt rate (no rest pair); the QNCF then runs without scanning again."""
    from mtcal.methods import tilt_rate

    calls = []
    scale = tilt_rate.tilt_rate_scale  # every scan runs through it
    monkeypatch.setattr(tilt_rate, "tilt_rate_scale", lambda *a, **k: calls.append(1) or scale(*a, **k))
    path = tmp_path / "walk.csv"
    logs.walking_log(n_steps=4)[0].to_csv(path, index=False)
    code = cli.main(["attitude", str(path), "--rest-detector", "shoe", "--out", str(tmp_path / "att.csv")])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert "gyro units check (tilt rate)" in out and len(calls) == 1


def test_angle_ekf_does_not_repeat_the_units_check(hinge, tmp_path, capsys, monkeypatch):
    """Rest pairs decide the units check; the EKF (run_rams_ekf, trusting its inputs) adds no tilt-rate scan."""
    from mtcal.methods import tilt_rate

    calls = []
    scale = tilt_rate.tilt_rate_scale  # every scan runs through it
    monkeypatch.setattr(tilt_rate, "tilt_rate_scale", lambda *a, **k: calls.append(1) or scale(*a, **k))
    code = cli.main(["angle", str(hinge[1]), "--axis", "0.6,0,0.8", "--out", str(tmp_path / "a.csv")])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert "gyro units check (rest pairs)" in out and not calls


def test_csv_output_is_what_arrows_writer_prints(tmp_path):
    """The fast CSV path (mtcal.core.csvtext) writes the bytes of pyarrow's writer of the rounded table."""
    import pyarrow as pa
    import pyarrow.csv as pcsv

    from mtcal.cli import common, logio

    rng = np.random.default_rng(5)
    n = 5000
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1)[:, None]
    q[::97, 1] = rng.normal(0, 1e-8, q[::97, 1].shape)  # exponent notation below 1e-6, and -0
    e = rng.uniform(-180, 180, (n, 3))
    e[::50, 2] = np.nan
    t = np.arange(n) / 1000.0
    static = (rng.random(n) < 0.3).astype(np.int8)
    common.write_attitude(tmp_path / "fast.csv", t, q, e, is_static=static)
    cols = {"time_s": t, "q0": q[:, 0], "q1": q[:, 1], "q2": q[:, 2], "q3": q[:, 3], "yaw_deg": e[:, 0],
            "pitch_deg": e[:, 1], "roll_deg": e[:, 2]}
    arrays = {k: pa.array(np.round(v, common.QUATERNION_DECIMALS.get(k, 6)), from_pandas=True) for k, v in cols.items()}
    arrays["is_static"] = static
    pcsv.write_csv(pa.table(arrays), tmp_path / "arrow.csv",
                   write_options=pcsv.WriteOptions(quoting_style="none", quoting_header="none"))
    assert (tmp_path / "fast.csv").read_bytes() == (tmp_path / "arrow.csv").read_bytes()
    logio.write_table(tmp_path / "inf.csv", {"x": np.array([1.0, np.inf])})  # not printable by csvtext: Arrow
    assert (tmp_path / "inf.csv").read_text() == "x\n1\ninf\n"
