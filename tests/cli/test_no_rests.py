"""A reviewer's CLI failures (s18): a log in which the rest options find no rest is not answered silently:
one ``warning:`` line with the evidence, and the commands say what they did instead (attitude, apply, rests)."""

import pytest

from tests.cli.runner import calibration_file as _calibration, run as _run


def _warnings(out):
    return [line for line in out.splitlines() if line.startswith("warning: no rest found")]


# -- 1. no rest found: one warning with the evidence, no false reason ------------------------------------------

@pytest.mark.parametrize("opts,needles", [
    (["--gravity", "9.80665"], ["about --gravity 9.8066", "measured in the stillest stretch", "drop --gravity"]),
    (["--min-rest-s", "1e9"], ["shorter than --min-rest-s 1e+09 s", "lower --min-rest-s"]),
    (["--rest-detector", "paper"], ["the paper's fixed |a| band 9.760-9.840", "--rest-detector adaptive"]),
])
def test_attitude_without_rests_warns_with_the_evidence(heavy, tmp_path, capsys, opts, needles):
    code, out, err = _run(["attitude", heavy, "--out", tmp_path / "a.csv", *opts], capsys)
    assert code == 0 and err == "", err
    warn = _warnings(out)
    assert len(warn) == 1, out
    for n in needles:
        assert n in warn[0], warn[0]
    assert "does not start at rest" not in out
    if "paper" in opts:
        assert "levelled from the first 100 samples (the paper's QNCF: default gains; no initial gyro bias removed)" in out
    else:
        assert "levelled from the first 100 samples (no rest found; no initial gyro bias removed)" in out


def test_attitude_with_rests_prints_no_rest_warning(heavy, tmp_path, capsys):
    code, out, err = _run(["attitude", heavy, "--out", tmp_path / "a.csv"], capsys)
    assert code == 0 and not _warnings(out) and "levelled from the first rest" in out


def test_apply_without_rests_says_what_it_did(heavy, tmp_path, capsys):
    """apply behaves as attitude: the warning, and the QNCF's real start (not 'levelled from the first rest')."""
    q = _calibration(tmp_path)
    code, out, err = _run(["apply", q, heavy, "--rest-detector", "paper", "--out", tmp_path / "b.csv"], capsys)
    assert code == 0 and err == "", err
    assert len(_warnings(out)) == 1 and "the paper's fixed |a| band" in out
    assert "QNCF levelled from the first 100 samples (the paper's QNCF" in out
    assert "QNCF levelled from the first rest" not in out
    code, out, err = _run(["apply", q, heavy, "--out", tmp_path / "b.csv"], capsys)
    assert code == 0 and not _warnings(out) and "QNCF levelled from the first rest" in out


def test_rests_without_rests_warns(heavy, capsys):
    code, out, err = _run(["rests", heavy, "--gravity", "9.80665"], capsys)
    assert code == 0 and len(_warnings(out)) == 1


# -- the QNCF's AMD gate shut at rest: said, with the evidence ---------------------------------------------------

@pytest.mark.parametrize("opts,fix", [
    (["--rest-detector", "paper"], "--rest-detector adaptive sets g and the gate from the data"),
    (["--gravity", "9.80665"], "drop --gravity"),
])
def test_attitude_warns_when_the_amd_gate_shuts_out_the_rest_level(heavy, tmp_path, capsys, opts, fix):
    code, out, err = _run(["attitude", heavy, "--out", tmp_path / "a.csv", *opts], capsys)
    assert code == 0 and err == "", err
    gate = [line for line in out.splitlines() if line.startswith("warning: the QNCF's AMD gate")]
    assert len(gate) == 1 and "measured in the stillest stretch" in gate[0] and fix in gate[0], out
    code, out, err = _run(["apply", _calibration(tmp_path), heavy, "--out", tmp_path / "b.csv", *opts], capsys)
    assert code == 0 and out.count("warning: the QNCF's AMD gate") == 1, out


def test_no_amd_gate_warning_at_the_defaults(heavy, tmp_path, capsys):
    code, out, err = _run(["attitude", heavy, "--out", tmp_path / "a.csv"], capsys)
    assert code == 0 and "AMD gate" not in out
