"""A reviewer's CLI failures (s18): every field of a calibration file is checked when it is read (one line naming
the file and the field, the existing output untouched); ``calibrate --out`` writes only a .json file."""

import numpy as np
import pytest

from mtcal.cli.apply import check_calibration_fields
from tests.cli.runner import calibration_file as _calibration, refused as _refused, run as _run


# -- 2. calibration files: every field checked when read, the output untouched ---------------------------------

@pytest.mark.parametrize("fields,needle", [
    ({"residual_deg": "x"}, "field 'residual_deg' must be a list of finite numbers >= 0"),
    ({"installation_angles_1sigma_deg": {"alpha1_z": None, "alpha2_y": 0.1, "alpha3_x": 0.1}},
     "field 'installation_angles_1sigma_deg' must be null or an object"),
    ({"installation_angles_1sigma_deg": {"a": "x"}}, "field 'installation_angles_1sigma_deg'"),
    ({"mounting_quaternion_q_bs": [0.5, 0.5, 0.5, 0.6]}, "field 'mounting_quaternion_q_bs' must be a unit quaternion"),
    ({"so4_distance": "small"}, "field 'so4_distance' must be a finite number >= 0"),
    ({"input": {"sample_rate_hz": -1}}, "field 'input.sample_rate_hz' must be a finite number > 0"),
    ({"residual_deg": [0.01] * 5}, "field 'residual_deg' has 5 values for 6 positions_deg"),
])
@pytest.mark.parametrize("mode", ["absolute", "relative"])
def test_apply_bad_calibration_field_refused_before_writing(heavy, tmp_path, capsys, fields, needle, mode):
    q = _calibration(tmp_path, **fields)
    out = tmp_path / "b.csv"
    out.write_text("SENTINEL\n")
    code, _, err = _run(["apply", q, heavy, "--mode", mode, "--out", out], capsys)
    _refused(code, err, str(q), needle)
    assert out.read_text() == "SENTINEL\n"


def test_check_calibration_fields_accepts_a_minimal_and_a_null_sigma_file():
    check_calibration_fields({"format": "mtcal-calibration/1", "q_hat": np.eye(4).tolist()}, "Q.json")
    check_calibration_fields({"installation_angles_1sigma_deg": None, "unknown_future_field": 1}, "Q.json")
    with pytest.raises(ValueError, match=r"Q.json: field 'rests_s' must be a list of \[start, stop\]"):
        check_calibration_fields({"rests_s": [[0.0, float("nan")]]}, "Q.json")


def test_calibrate_out_must_be_json(tmp_path, capsys):
    (tmp_path / "log.csv").write_text("time_s,q0,q1,q2,q3\n" + "".join(f"{k / 100},1,0,0,0\n" for k in range(50)))
    (tmp_path / "pos.csv").write_text("yaw_deg,pitch_deg,roll_deg\n" + "0,0,0\n" * 6)
    code, _, err = _run(["calibrate", tmp_path / "log.csv", "--positions", tmp_path / "pos.csv",
                         "--out", tmp_path / "Q.csv"], capsys)
    _refused(code, err, "--out", "Q.csv", "the file type must be .json")
    assert not (tmp_path / "Q.csv").exists()


def test_apply_refuses_a_recorded_so4_distance_that_is_not_q_hats(heavy, tmp_path, capsys):
    """A file recording so4_distance 1e9 would widen apply's SO(4) gate to anything (q_hat = 3 I accepted)."""
    q = _calibration(tmp_path, q_hat=(3 * np.eye(4)).tolist(), so4_distance=1e9)
    out = tmp_path / "b.csv"
    out.write_text("SENTINEL\n")
    code, _, err = _run(["apply", q, heavy, "--out", out], capsys)
    _refused(code, err, "field 'so4_distance' (1e+09) is not the distance of the file's q_hat from SO(4) (4)")
    assert out.read_text() == "SENTINEL\n"
