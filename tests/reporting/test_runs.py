import json
import subprocess
from pathlib import Path

import pandas as pd
import pytest

from mtcal.reporting import runs

ROOT = Path(__file__).resolve().parents[2]


def _git_state():
    out = subprocess.run(["git", "status", "--porcelain", "--", "data", "figures", "notebooks"], cwd=ROOT,
                         capture_output=True, text=True)
    return out.stdout if out.returncode == 0 else None


def test_parse_parameter_types():
    assert runs.parse_parameter("SEED=7") == ("SEED", 7)
    assert runs.parse_parameter("SIZE=ci") == ("SIZE", "ci")
    assert runs.parse_parameter("x = (1, 2.5)") == ("x", (1, 2.5))
    assert runs.parse_parameter("label='a=b'") == ("label", "a=b")
    with pytest.raises(ValueError, match="key=value"):
        runs.parse_parameter("SEED 7")
    with pytest.raises(ValueError, match="identifier"):
        runs.parse_parameter("1x=2")
    with pytest.raises(ValueError, match="must be a number, bool"):
        runs.parse_parameter("s={1, 2}")


def test_resolve_and_parameters(tiny_notebooks):
    src = runs.resolve_notebook(99, tiny_notebooks)
    assert src.name == "99_tiny.py" and runs.resolve_notebook("99_tiny", tiny_notebooks) == src
    with pytest.raises(ValueError, match=r"notebook must be one of \['99_tiny'\]"):
        runs.resolve_notebook("12", tiny_notebooks)
    valid = runs.notebook_parameters(src)
    assert list(valid) == ["SIZE", "SEED", "gain", "label", "FAIL"]
    with pytest.raises(ValueError, match="unknown parameter 'gian' for 99_tiny; valid: SIZE, SEED, gain, label, FAIL"):
        runs.check_parameters({"gian": 1.0}, valid, "99_tiny")
    with pytest.raises(ValueError, match="parameter gain of 99_tiny must be like its default 2.0"):
        runs.check_parameters({"gain": "big"}, valid, "99_tiny")
    assert runs.check_parameters({"gain": 3, "SIZE": "ci", "SEED": 5}, valid) == {"gain": 3, "SIZE": "ci", "SEED": 5}


def test_what_if_run_goes_to_its_folder_and_never_touches_committed_files(tiny_notebooks, tmp_path):
    before = _git_state()
    result = runs.run_notebook(99, name="steep", parameters={"gain": 3.0, "label": "what-if"}, size="ci",
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
        runs.run_notebook(99, name="steep", runs_dir=tmp_path / "runs", notebooks_dir=tiny_notebooks)
    again = runs.run_notebook(99, name="steep", parameters={"gain": 3.0, "label": "what-if"}, size="ci",
                              runs_dir=tmp_path / "runs", notebooks_dir=tiny_notebooks, overwrite=True)
    assert again.notebook.read_bytes() == first


def test_run_rejects_bad_input_before_running(tiny_notebooks, tmp_path):
    kw = dict(runs_dir=tmp_path / "runs", notebooks_dir=tiny_notebooks)
    with pytest.raises(ValueError, match="unknown parameter 'nope'"):
        runs.run_notebook(99, parameters={"nope": 1}, **kw)
    with pytest.raises(ValueError, match="size must be 'ci' or 'full'"):
        runs.run_notebook(99, size="huge", **kw)
    with pytest.raises(ValueError, match="name must be a plain folder name"):
        runs.run_notebook(99, name="../escape", **kw)
    with pytest.raises(ValueError, match="runs_dir must not be inside the committed"):
        runs.run_notebook(99, runs_dir=ROOT / "data", notebooks_dir=tiny_notebooks)
    assert not (tmp_path / "runs").exists() or not any((tmp_path / "runs").iterdir())


def _fake_run(folder: Path, rows: list[tuple]):
    (folder / "data").mkdir(parents=True)
    df = pd.DataFrame(rows, columns=["artifact", "quantity", "paper", "mtcal", "mc_band", "claim", "holds"])
    df["role"], df["source"], df["paper_in_band"] = "predicted", "paper claim", ""
    df.to_csv(folder / "data" / "10_x_comparison.csv", index=False)


def test_compare_runs_table_flips_and_files(tmp_path):
    _fake_run(tmp_path / "runs" / "paper", [("t06", "roll RMSE (deg)", 0.009, 0.0071, "[0.005, 0.01]", "<= 0.01", True),
                                            ("t06", "yaw RMSE (deg)", 0.02, 0.015, "", "<= 0.03", True),
                                            ("t06", "yaw RMSE (deg)", 0.02, 0.016, "", "<= 0.03", True)])
    _fake_run(tmp_path / "runs" / "industrial", [("t06", "roll RMSE (deg)", 0.009, 0.031, "[0.02, 0.05]", "<= 0.01",
                                                  False),
                                                 ("t06", "yaw RMSE (deg)", 0.02, 0.015, "", "<= 0.03", True),
                                                 ("t06", "yaw RMSE (deg)", 0.02, 0.016, "", "<= 0.03", True)])
    table, csv_path, png_path = runs.compare_runs([tmp_path / "runs" / "paper", tmp_path / "runs" / "industrial"])
    assert csv_path == tmp_path / "runs" / "compare_paper_vs_industrial.csv" and csv_path.is_file()
    assert png_path is not None and png_path.read_bytes()[:4] == b"\x89PNG"
    assert len(table) == 3  # repeated quantity kept apart
    roll = table[table["quantity"] == "roll RMSE (deg)"].iloc[0]
    assert roll["mtcal [paper]"] == "0.0071" and roll["mtcal [industrial]"] == "0.031"
    assert roll["band [industrial]"] == "[0.02, 0.05]" and roll["flips"] == "True→False (industrial)"
    assert (table["flips"] != "").sum() == 1
    with pytest.raises(ValueError, match="at least two run folders"):
        runs.compare_runs([tmp_path / "runs" / "paper"])
    with pytest.raises(FileNotFoundError, match="has no data/ folder"):
        runs.compare_runs([tmp_path / "runs" / "paper", tmp_path / "nowhere"])
    with pytest.raises(ValueError, match="distinct labels"):
        runs.compare_runs([tmp_path / "runs" / "paper", tmp_path / "runs" / "industrial"], names=["a", "a"])


def test_compare_runs_keeps_tables_common_to_all_runs(tmp_path):
    _fake_run(tmp_path / "a", [("t06", "roll", 1, 1.0, "", "c", True)])
    _fake_run(tmp_path / "b", [("t06", "roll", 1, 2.0, "", "c", False)])
    pd.DataFrame({"artifact": ["x"], "quantity": ["q"], "mtcal": [1], "holds": [True]}).to_csv(
        tmp_path / "a" / "data" / "20_y_comparison.csv", index=False)
    table, _, _ = runs.compare_runs([tmp_path / "a", tmp_path / "b"], out_dir=tmp_path, figure=False)
    assert set(table["table"]) == {"10_x_comparison"}
    (tmp_path / "b" / "data" / "10_x_comparison.csv").rename(tmp_path / "b" / "data" / "30_z_comparison.csv")
    with pytest.raises(ValueError, match="no comparison table in common"):
        runs.compare_runs([tmp_path / "a", tmp_path / "b"], out_dir=tmp_path)


def test_compare_runs_matches_quantities_labelled_with_parameter_values(tmp_path):
    _fake_run(tmp_path / "a", [("f12", "hybrid (θ̇_t = 0.5 °/s) max error (deg)", 1, 0.4, "", "< 1", True),
                               ("f12", "error at gamma = 0 deg", "-", 1.0, "", "-", True),
                               ("f12", "error at gamma = 60 deg", "-", 2.0, "", "-", True)])
    _fake_run(tmp_path / "b", [("f12", "hybrid (θ̇_t = 10 °/s) max error (deg)", 1, 2.1, "", "< 1", False),
                               ("f12", "error at gamma = 0 deg", "-", 1.5, "", "-", True),
                               ("f12", "error at gamma = 60 deg", "-", 2.5, "", "-", True)])
    table, _, _ = runs.compare_runs([tmp_path / "a", tmp_path / "b"], out_dir=tmp_path, figure=False)
    assert len(table) == 3
    hybrid = table.iloc[[i for i, q in enumerate(table["quantity"]) if q.startswith("hybrid")][0]]
    assert hybrid["quantity"] == "hybrid (θ̇_t = 0.5 °/s) max error (deg)"
    assert (hybrid["mtcal [a]"], hybrid["mtcal [b]"], hybrid["flips"]) == ("0.4", "2.1", "True→False (b)")
    assert table.set_index("quantity").loc["error at gamma = 60 deg", "mtcal [b]"] == "2.5"


def test_timeout_keeps_the_partial_notebook(tmp_path):
    src = tmp_path / "98_slow.py"
    src.write_text('# %% tags=["parameters"]\nA = 1\n\n# %%\nprint("before", A)\n\n# %%\nimport time\ntime.sleep(60)\n')
    with pytest.raises(runs.NotebookRunError, match="98_slow .*partially executed notebook") as info:
        runs.execute_notebook(src, tmp_path / "out.ipynb", timeout_s=3)
    text = info.value.notebook.read_text()
    assert "before 1" in text and '"papermill"' not in text


def test_compare_runs_three_runs(tmp_path):
    # regression: a third run used to collide on the merged 'quantity' column
    for name, value, holds in (("a", 1.0, True), ("b", 2.0, False), ("c", 3.0, True)):
        _fake_run(tmp_path / name, [("t06", "roll (deg)", 1, value, "", "c", holds)])
    table, _, _ = runs.compare_runs([tmp_path / n for n in "abc"], out_dir=tmp_path, figure=False)
    assert len(table) == 1 and list(table.filter(like="mtcal [").iloc[0]) == ["1.0", "2.0", "3.0"]
    assert table["flips"].iloc[0] != ""


def test_normalise_notebook_merges_stream_outputs_split_by_timing():
    import nbformat

    def nb_with(outputs):
        nb = nbformat.v4.new_notebook()
        nb.cells.append(nbformat.v4.new_code_cell("print('a'); print('b')", outputs=outputs))
        return runs.normalise_notebook(nb)

    split = nb_with([nbformat.v4.new_output("stream", name="stdout", text="a\n"),
                     nbformat.v4.new_output("stream", name="stdout", text="b\n")])
    whole = nb_with([nbformat.v4.new_output("stream", name="stdout", text="a\nb\n")])
    assert nbformat.writes(split) == nbformat.writes(whole)
    mixed = nb_with([nbformat.v4.new_output("stream", name="stdout", text="a\n"),
                     nbformat.v4.new_output("stream", name="stderr", text="w\n"),
                     nbformat.v4.new_output("stream", name="stdout", text="b\n")])
    assert [o["name"] for o in mixed.cells[0].outputs] == ["stdout", "stderr", "stdout"]
