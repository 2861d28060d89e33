import json
import shutil
from pathlib import Path

import pytest

from mtcal import cli

TINY = Path(__file__).resolve().parents[1] / "runs" / "conftest.py"


@pytest.fixture
def tiny_notebooks(tmp_path):
    import importlib.util

    spec = importlib.util.spec_from_file_location("tiny_conftest", TINY)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    folder = tmp_path / "notebooks"
    folder.mkdir()
    (folder / "99_tiny.py").write_text(mod.TINY, encoding="utf-8")
    return folder


def test_run_invalid_parameter_is_one_line_error(tiny_notebooks, tmp_path, capsys):
    code = cli.main(["run", "99", "--notebooks-dir", str(tiny_notebooks), "--runs-dir", str(tmp_path / "runs"),
                     "-p", "gian=3"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert err.startswith("mtcal: error: unknown parameter 'gian' for 99_tiny; valid: SIZE, SEED, gain, label, FAIL")
    assert cli.main(["run", "7", "--notebooks-dir", str(tiny_notebooks)]) == 2
    assert "notebook must be one of ['99_tiny']" in capsys.readouterr().err
    assert cli.main(["run", "99", "--notebooks-dir", str(tiny_notebooks), "-p", "SEED 7"]) == 2
    assert "parameter must be written key=value" in capsys.readouterr().err


def test_run_list_parameters(tiny_notebooks, capsys):
    assert cli.main(["run", "99", "--notebooks-dir", str(tiny_notebooks), "--list"]) == 0
    out = capsys.readouterr().out
    assert "gain = 2.0" in out and 'label = "base"' in out


def test_failed_run_keeps_partial_notebook(tiny_notebooks, tmp_path, capsys):
    code = cli.main(["run", "99_tiny", "--name", "broken", "-p", "FAIL=True", "--size", "ci",
                     "--notebooks-dir", str(tiny_notebooks), "--runs-dir", str(tmp_path / "runs")])
    err = capsys.readouterr().err
    assert code == 1 and "mtcal: error: 99_tiny failed in cell" in err and "AssertionError: asked to fail" in err
    folder = tmp_path / "runs" / "broken"
    nb = json.loads((folder / "99_tiny.ipynb").read_text())
    outputs = "".join("".join(o.get("text", "")) for c in nb["cells"] if c["cell_type"] == "code" for o in c["outputs"])
    assert "size=ci gain=2.0 label=base" in outputs  # cells before the failure were executed and kept
    assert json.loads((folder / "params.json").read_text())["status"] == "failed"
    assert (folder / "data" / "tiny_table.csv").is_file() and not (folder / "data" / "tiny_comparison.csv").exists()


def test_run_list_gives_valid_grade_names():
    from mtcal.cli.run import _valid_values
    from mtcal.core.sensor_grades import grade_names

    text = _valid_values("gyro_grade", {"help": "a mtcal.core.sensor_grades name"})
    assert text.startswith("; valid: ") and all(g in text for g in grade_names())
    assert _valid_values("fs_hz", {"help": "Hz"}) == ""


def test_run_prints_progress_per_cell_when_stderr_is_not_a_terminal(tiny_notebooks, tmp_path, capsys):
    """Issue #36: a full-size run takes minutes; it must not be silent when its output goes to a log."""
    code = cli.main(["run", "99", "--name", "progress", "--size", "ci", "--notebooks-dir", str(tiny_notebooks),
                     "--runs-dir", str(tmp_path / "runs")])
    out, err = capsys.readouterr()
    assert code == 0, err
    cells = [ln for ln in err.splitlines() if ln.startswith("99_tiny: cell ")]
    n_cells = len(json.loads((tmp_path / "runs" / "progress" / "99_tiny.ipynb").read_text())["cells"])
    assert [c.split(" [")[0] for c in cells] == [f"99_tiny: cell {k}/{n_cells}" for k in range(n_cells + 1)]
    assert "running notebook 99 at size ci" in out and "tiny_comparison: 2 of 2 claims hold" in out


@pytest.mark.parametrize("notebook,param,expected", [
    ("20", "accel_error_g=-1", "-p accel_error_g=-1: must be > 0"),                 # internal delta_accel_g
    ("20", "accel_error_g=0.5", "-p accel_error_g=0.5: accel_error_g and independent_sigma_g are in g and must be"),
    ("21", "oscillation_amplitude_deg=120.0", "-p oscillation_amplitude_deg=120.0: must be < 90"),   # amplitude_deg
    ("21", "fs_hz=-1.0", "-p fs_hz=-1.0: must be > 0"),
    ("40", "k_max=3", "-p k_max=3: must be an int in [6, 12]"),
    ("60", "smooth_quat_s=-1.0", "-p smooth_quat_s=-1.0: must be > 0"),
])
def test_run_refuses_an_out_of_range_scenario_value_before_running(tmp_path, capsys, notebook, param, expected):
    """docs/study_template.md: a bad value is one line naming the parameter as typed (not the builder's internal
    name), exit 2, checked by the study's builder before the run folder is made and the notebook starts."""
    code = cli.main(["run", notebook, "--name", "bad", "-p", param, "--size", "ci", "--runs-dir", str(tmp_path / "runs")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert err.startswith("mtcal: error: " + expected)
    assert "delta_accel_g" not in err and not (tmp_path / "runs").exists()
