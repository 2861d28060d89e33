"""mtcal.runs.notebooks: build, execute and what-if-run notebooks."""

import json
import subprocess
from pathlib import Path

import pandas as pd
import pytest

from mtcal.runs import notebooks

ROOT = Path(__file__).resolve().parents[2]


def _git_state():
    out = subprocess.run(["git", "status", "--porcelain", "--", "data", "figures", "notebooks"], cwd=ROOT,
                         capture_output=True, text=True)
    return out.stdout if out.returncode == 0 else None


def test_parse_parameter_types():
    assert notebooks.parse_parameter("SEED=7") == ("SEED", 7)
    assert notebooks.parse_parameter("SIZE=ci") == ("SIZE", "ci")
    assert notebooks.parse_parameter("x = (1, 2.5)") == ("x", (1, 2.5))
    assert notebooks.parse_parameter("label='a=b'") == ("label", "a=b")
    with pytest.raises(ValueError, match="key=value"):
        notebooks.parse_parameter("SEED 7")
    with pytest.raises(ValueError, match="identifier"):
        notebooks.parse_parameter("1x=2")
    with pytest.raises(ValueError, match="must be a number, bool"):
        notebooks.parse_parameter("s={1, 2}")


def test_resolve_and_parameters(tiny_notebooks):
    src = notebooks.resolve_notebook(99, tiny_notebooks)
    assert src.name == "99_tiny.py" and notebooks.resolve_notebook("99_tiny", tiny_notebooks) == src
    with pytest.raises(ValueError, match=r"notebook must be one of \['99_tiny'\]"):
        notebooks.resolve_notebook("12", tiny_notebooks)
    valid = notebooks.notebook_parameters(src)
    assert list(valid) == ["SIZE", "SEED", "gain", "label", "FAIL"]
    with pytest.raises(ValueError, match="unknown parameter 'gian' for 99_tiny; valid: SIZE, SEED, gain, label, FAIL"):
        notebooks.check_parameters({"gian": 1.0}, valid, "99_tiny")
    with pytest.raises(ValueError, match="parameter gain of 99_tiny must be like its default 2.0"):
        notebooks.check_parameters({"gain": "big"}, valid, "99_tiny")
    assert notebooks.check_parameters({"gain": 3, "SIZE": "ci", "SEED": 5}, valid) == {"gain": 3, "SIZE": "ci", "SEED": 5}


@pytest.mark.parametrize("name,value,match", [
    ("N_TRIALS", -5, r"parameter N_TRIALS of nb must be an integer >= 1 \(or None\), got -5"),
    ("N_TRIALS", 2.5, r"parameter N_TRIALS of nb must be an integer >= 1"),
    ("gyro_grade", "bogus", r"parameter gyro_grade of nb must be one of consumer, industrial, .*, got 'bogus'"),
])
def test_counts_and_sensor_grades_are_checked_before_a_run(name, value, match):
    """The values every notebook shares a range for: refused before a run folder is made (not at cell 7)."""
    valid = {"N_TRIALS": {"default": "None"}, "gyro_grade": {"default": "'wang2023cja'"}}
    with pytest.raises(ValueError, match=match):
        notebooks.check_parameters({name: value}, valid, "nb")
    assert notebooks.check_parameters({"N_TRIALS": None, "gyro_grade": "industrial"}, valid, "nb") == {
        "N_TRIALS": None, "gyro_grade": "industrial"}


def test_what_if_run_goes_to_its_folder_and_never_touches_committed_files(tiny_notebooks, tmp_path):
    before = _git_state()
    result = notebooks.run_notebook(99, name="steep", parameters={"gain": 3.0, "label": "what-if"}, size="ci",
                               runs_dir=tmp_path / "runs", notebooks_dir=tiny_notebooks)
    folder = tmp_path / "runs" / "steep"
    assert result.folder == folder and result.notebook == folder / "99_tiny.ipynb"
    table = pd.read_csv(folder / "data" / "tiny_table.csv")
    assert table["y"].tolist() == [3.0, 6.0] and set(table["label"]) == {"what-if"}
    record = json.loads((folder / "params.json").read_text())
    assert record["status"] == "completed" and record["parameters"] == {"gain": 3.0, "label": "what-if"}
    assert record["size"] == "ci" and record["defaults"]["gain"] == "2.0"
    assert "1 of 2 claims hold" in result.claims and "y(2) = 4" in result.claims
    text = result.notebook.read_text()
    assert "size=ci gain=3.0 label=what-if" in text and "injected-parameters" in text
    assert '"papermill"' not in text and '"execution"' not in text
    # committed results untouched: nothing written into the repository
    assert not (ROOT / "data" / "tiny_table.csv").exists() and not (ROOT / "data" / "tiny_comparison.csv").exists()
    assert _git_state() == before
    # byte-stable: the same run again gives the same notebook bytes
    first = result.notebook.read_bytes()
    with pytest.raises(ValueError, match="exists; choose another name"):
        notebooks.run_notebook(99, name="steep", runs_dir=tmp_path / "runs", notebooks_dir=tiny_notebooks)
    again = notebooks.run_notebook(99, name="steep", parameters={"gain": 3.0, "label": "what-if"}, size="ci",
                              runs_dir=tmp_path / "runs", notebooks_dir=tiny_notebooks, overwrite=True)
    assert again.notebook.read_bytes() == first


def test_run_rejects_bad_input_before_running(tiny_notebooks, tmp_path):
    kw = dict(runs_dir=tmp_path / "runs", notebooks_dir=tiny_notebooks)
    with pytest.raises(ValueError, match="unknown parameter 'nope'"):
        notebooks.run_notebook(99, parameters={"nope": 1}, **kw)
    with pytest.raises(ValueError, match="size must be 'ci' or 'full'"):
        notebooks.run_notebook(99, size="huge", **kw)
    with pytest.raises(ValueError, match="name must be a plain folder name"):
        notebooks.run_notebook(99, name="../escape", **kw)
    with pytest.raises(ValueError, match="runs_dir must not be inside the committed"):
        notebooks.run_notebook(99, runs_dir=ROOT / "data", notebooks_dir=tiny_notebooks)
    assert not (tmp_path / "runs").exists() or not any((tmp_path / "runs").iterdir())


def test_timeout_keeps_the_partial_notebook(tmp_path):
    src = tmp_path / "98_slow.py"
    src.write_text('# %% tags=["parameters"]\nA = 1\n\n# %%\nprint("before", A)\n\n# %%\nimport time\ntime.sleep(60)\n')
    with pytest.raises(notebooks.NotebookRunError, match="98_slow .*partially executed notebook") as info:
        notebooks.execute_notebook(src, tmp_path / "out.ipynb", timeout_s=3)
    text = info.value.notebook.read_text()
    assert "before 1" in text and '"papermill"' not in text


def test_normalise_notebook_merges_stream_outputs_split_by_timing():
    import nbformat

    def nb_with(outputs):
        nb = nbformat.v4.new_notebook()
        nb.cells.append(nbformat.v4.new_code_cell("print('a'); print('b')", outputs=outputs))
        return notebooks.normalise_notebook(nb)

    split = nb_with([nbformat.v4.new_output("stream", name="stdout", text="a\n"),
                     nbformat.v4.new_output("stream", name="stdout", text="b\n")])
    whole = nb_with([nbformat.v4.new_output("stream", name="stdout", text="a\nb\n")])
    assert nbformat.writes(split) == nbformat.writes(whole)
    mixed = nb_with([nbformat.v4.new_output("stream", name="stdout", text="a\n"),
                     nbformat.v4.new_output("stream", name="stderr", text="w\n"),
                     nbformat.v4.new_output("stream", name="stdout", text="b\n")])
    assert [o["name"] for o in mixed.cells[0].outputs] == ["stdout", "stderr", "stdout"]


def test_normalise_notebook_drops_empty_tags_so_executed_and_synced_notebooks_agree():
    import nbformat

    nb = nbformat.v4.new_notebook()
    nb.cells.append(nbformat.v4.new_markdown_cell("# t", metadata={"tags": []}))          # as papermill leaves it
    nb.cells.append(nbformat.v4.new_code_cell("x = 1", metadata={"tags": ["parameters"]}))
    nb.cells.append(nbformat.v4.new_code_cell("y = 2"))
    out = notebooks.normalise_notebook(nb)
    assert [dict(c.metadata) for c in out.cells] == [{}, {"tags": ["parameters"]}, {}]


def test_committed_notebooks_carry_no_empty_tags():
    """``make reproduce`` (execute) and ``make sync`` write the same metadata: no ``"tags": []`` left."""
    root = Path(__file__).resolve().parents[2]
    for path in sorted((root / "notebooks").glob("*.ipynb")):
        cells = json.loads(path.read_text(encoding="utf-8"))["cells"]
        assert [c["id"] for c in cells if c["metadata"].get("tags") == []] == [], path.name
