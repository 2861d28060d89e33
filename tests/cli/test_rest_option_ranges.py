"""s18: --accel-band and --gyro-threshold-deg-s have ranges (as --gravity has): a value that switches the rest gate
off is refused with one line naming the option, by every subcommand that takes the rest options."""

import json

import numpy as np
import pytest

from mtcal import cli
from mtcal.systems.rests import MAX_ACCEL_BAND_M_S2, MAX_GYRO_THRESHOLD_RAD_S, RestsConfig
from tests.cli import logs


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("ranges")
    log = logs.hinge_log().write(d / "hinge.csv")
    (d / "Q.json").write_text(json.dumps({"format": "mtcal-calibration/1", "q_hat": np.eye(4).tolist()}))
    (d / "pos.csv").write_text("yaw_deg,pitch_deg,roll_deg\n" + "0,0,0\n" * 6)
    return d, log


def _commands(d, log):
    return {"rests": ["rests", log], "attitude": ["attitude", log, "--out", d / "a.csv"],
            "apply": ["apply", d / "Q.json", log, "--out", d / "b.csv"],
            "angle": ["angle", log, "--axis", "0.6,0,0.8", "--out", d / "c.csv"], "axis": ["axis", log],
            "calibrate": ["calibrate", log, "--positions", d / "pos.csv"]}


@pytest.mark.parametrize("command", ["rests", "attitude", "apply", "angle", "axis", "calibrate"])
@pytest.mark.parametrize("opts,needle", [
    (["--accel-band", "1e9"], "--accel-band must be at most 5 m/s^2"),
    (["--gyro-threshold-deg-s", "1e12"], "--gyro-threshold-deg-s must be at most 180 deg/s"),
    (["--rest-detector", "shoe", "--gyro-threshold-deg-s", "1e12"], "--gyro-threshold-deg-s must be at most 180"),
])
def test_rest_gate_options_out_of_range_refused(files, capsys, command, opts, needle):
    d, log = files
    code = cli.main([str(a) for a in _commands(d, log)[command] + opts])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("mtcal: error: ") and err.count("\n") == 1 and needle in err, err


def test_rest_gate_limits_in_the_config():
    RestsConfig(accel_band_m_s2=MAX_ACCEL_BAND_M_S2, gyro_threshold_rad_s=MAX_GYRO_THRESHOLD_RAD_S)
    with pytest.raises(ValueError, match="accel_band_m_s2 must be at most 5 m/s"):
        RestsConfig(accel_band_m_s2=5.01)
    with pytest.raises(ValueError, match="gyro_threshold_rad_s must be at most 180 deg/s"):
        RestsConfig(detector="shoe", gyro_threshold_rad_s=4.0)
