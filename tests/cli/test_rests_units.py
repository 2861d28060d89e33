"""``mtcal rests`` checks the gyro's units and time base as ``attitude``/``axis`` do (its --help says so): a
rad/s log stated as deg/s, a time column in ms under a ``time_s`` header, a gyro scale of 1e-300 are refused with
one line, the --out table not written; a correct log prints its units check line."""

import pytest

from tests.cli import logs
from tests.cli.runner import refused as _refused, run as _run


@pytest.fixture(scope="module")
def hinge(tmp_path_factory):
    return logs.hinge_log().write(tmp_path_factory.mktemp("rests_units") / "hinge.csv")


def test_rests_prints_the_units_check(hinge, capsys):
    code, out, err = _run(["rests", hinge], capsys)
    assert code == 0 and "gyro units check (rest pairs)" in out


@pytest.mark.parametrize("opts,needle", [
    (["--gyro-unit", "deg/s"], "drop --gyro-unit deg/s"),
    (["--gyro-scale", "1e-300"], "--gyro-scale must be a factor counts -> unit of magnitude 1e-09 to 1e+09"),
])
def test_rests_refuses_a_gyro_the_units_check_refuses(hinge, tmp_path, capsys, opts, needle):
    code, _, err = _run(["rests", hinge, "--out", tmp_path / "r.csv", *opts], capsys)
    _refused(code, err, needle)
    assert not (tmp_path / "r.csv").exists()


def test_rests_accel_only_skips_the_gyro_check(hinge, capsys):
    code, out, err = _run(["rests", hinge, "--gyro-unit", "deg/s", "--accel-only"], capsys)
    assert code == 0 and "gyro units check" not in out


def test_rests_refuses_a_time_column_in_ms_under_a_seconds_header(tmp_path, capsys):
    """An 8 kHz log with time in ms under time_s reads as 8 Hz; attitude and rests refuse it alike."""
    path = logs.hinge_log(fs_hz=8000.0, time_unit="ms").write(tmp_path / "fast.csv")
    code, _, err_rests = _run(["rests", path, "--out", tmp_path / "r.csv"], capsys)
    _refused(code, err_rests)
    # the likeliest cause first: at 8 "Hz" a ~1000x rotation is a ms time column, not a deg/s or mrad/s gyro
    assert err_rests.index("time in ms? use --time-unit ms") < err_rests.find("--gyro-unit deg/s"), err_rests
    code, _, err_att = _run(["attitude", path, "--out", tmp_path / "a.csv"], capsys)
    assert code == 2 and err_att == err_rests
    assert not (tmp_path / "r.csv").exists()
