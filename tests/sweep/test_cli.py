"""``mtcal sweep``: runs a spec into a run folder, resumes, and reports bad input as one line (exit 2)."""

import pytest

from mtcal import cli

SPEC = """
[sweep]
name = "cli"
evaluator = "gaussian_check"
seed = 1
trials = 8
block_trials = 4
[grid]
sigma = [1.0, 2.0]
"""


def test_sweep_runs_and_resumes(tmp_path, capsys):
    spec = tmp_path / "s.toml"
    spec.write_text(SPEC)
    out = tmp_path / "run"
    assert cli.main(["sweep", str(spec), "--workers", "1", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "2 cells x 8 trials" in text and "2 cells computed, 0 already stored" in text
    assert (out / "table.csv").read_text().startswith("cell,sigma,metric,median,low,high,trials,band\n")
    assert cli.main(["sweep", str(spec), "--workers", "1", "--out", str(out)]) == 0
    assert "0 cells computed, 2 already stored" in capsys.readouterr().out


def test_default_out_folder(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text(SPEC)
    assert cli.main(["sweep", "s.toml", "--workers", "1"]) == 0
    assert (tmp_path / "runs" / "sweeps" / "cli" / "table.csv").is_file()


def test_list_evaluators(capsys):
    assert cli.main(["sweep", "--list"]) == 0
    text = capsys.readouterr().out
    assert "attitude:" in text and "six_position:" in text and '    grade = "wang2023cja"' in text


@pytest.mark.parametrize("args,content,match", [
    (["--workers", "1"], SPEC.replace("trials = 8", "trials = 0"), "sweep.trials must be an integer in [1, 10000000]"),
    (["--workers", "1"], SPEC.replace("sigma = [1.0, 2.0]", "sigma = [1.0, -2.0]"), "grid.sigma must be"),
    (["--workers", "1"], "[sweep\n", "is not valid TOML"),
    (["--workers", "2", "--scheduler", "tcp://127.0.0.1:1"], SPEC, "either --workers"),
    (["--scheduler", "127.0.0.1:1"], SPEC, "scheduler must be an address"),
])
def test_errors_are_one_line_exit_2(tmp_path, capsys, args, content, match):
    spec = tmp_path / "s.toml"
    spec.write_text(content)
    assert cli.main(["sweep", str(spec), "--out", str(tmp_path / "o"), *args]) == 2
    err = capsys.readouterr().err
    assert err.startswith("mtcal: error: ") and match in err and err.count("\n") == 1
    assert not (tmp_path / "o").exists()                      # refused before the run folder is made


def test_unreadable_spec_and_out_under_a_file_name_the_input(tmp_path, capsys):
    (tmp_path / "bin.toml").write_bytes(b"\xff\xfe\x00binary")
    assert cli.main(["sweep", str(tmp_path / "bin.toml"), "--workers", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "bin.toml is not a TOML text file (not UTF-8" in err
    (tmp_path / "s.toml").write_text(SPEC)
    (tmp_path / "file").write_text("x")
    assert cli.main(["sweep", str(tmp_path / "s.toml"), "--workers", "1", "--out", str(tmp_path / "file" / "o")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--out " in err and "cannot make the run folder" in err


def test_missing_spec_and_bad_workers(tmp_path, capsys):
    assert cli.main(["sweep", str(tmp_path / "nope.toml")]) == 2
    assert "spec file not found" in capsys.readouterr().err
    assert cli.main(["sweep"]) == 2
    assert "a spec file is required" in capsys.readouterr().err
    with pytest.raises(SystemExit) as exc:
        cli.main(["sweep", "x.toml", "--workers", "0"])
    assert exc.value.code == 2
    assert "must be a positive integer" in capsys.readouterr().err


def test_other_sweep_in_folder(tmp_path, capsys):
    spec = tmp_path / "s.toml"
    spec.write_text(SPEC)
    out = tmp_path / "o"
    assert cli.main(["sweep", str(spec), "--workers", "1", "--out", str(out)]) == 0
    spec.write_text(SPEC.replace("seed = 1", "seed = 2"))
    assert cli.main(["sweep", str(spec), "--workers", "1", "--out", str(out)]) == 2
    assert "holds a different sweep" in capsys.readouterr().err
    (tmp_path / "file").write_text("x")
    assert cli.main(["sweep", str(spec), "--workers", "1", "--out", str(tmp_path / "file")]) == 2
    assert "is not a folder" in capsys.readouterr().err


def test_sweep_writes_a_figure_of_the_table_and_shows_progress(tmp_path, capsys, monkeypatch):
    spec = tmp_path / "s.toml"
    spec.write_text(SPEC.replace("sigma = [1.0, 2.0]", "sigma = [1.0, 2.0, 3.0]\nn_samples = [10, 20]"))
    monkeypatch.setenv("MTCAL_PROGRESS", "1")
    assert cli.main(["sweep", str(spec), "--workers", "1", "--out", str(tmp_path / "a")]) == 0
    captured = capsys.readouterr()
    png = tmp_path / "a" / "table.png"
    assert f"figure: {png}" in captured.out and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "sweep cli" in captured.err and "6/6" in captured.err  # the progress bar over cells
    assert cli.main(["sweep", str(spec), "--workers", "1", "--out", str(tmp_path / "b"), "--no-progress"]) == 0
    assert capsys.readouterr().err == ""
    assert (tmp_path / "b" / "table.png").read_bytes() == png.read_bytes()  # byte-stable


def test_sweep_figure_panels_bands_and_errors():
    import pandas as pd

    from mtcal.sweep.plots import sweep_figure

    table = pd.DataFrame({"grade": ["a", "b", "a", "b"], "metric": ["rms", "rms", "max", "max"],
                          "median": [1.0, 2.0, 3.0, 4.0], "low": [0.5, 1.5, 2.5, 3.5], "high": [1.5, 2.5, 3.5, 4.5]})
    fig = sweep_figure(table, ["grade"], title="t")
    assert [ax.get_title() for ax in fig.axes] == ["rms", "max"]
    assert [t.get_text() for t in fig.axes[0].get_xticklabels()] == ["a", "b"]
    assert len(fig.axes[0].collections) == 1  # the band
    assert "spread of the trials" in fig._suptitle.get_text()
    fig = sweep_figure(table.assign(trials=12), ["grade"])
    assert fig._suptitle.get_text() == "median and range of 12 trials per grid cell"
    # the numeric swept parameter goes on x, whatever the grid order
    both = pd.concat([table.assign(vib=0.0), table.assign(vib=3.0)], ignore_index=True)
    fig = sweep_figure(both, ["grade", "vib"])
    assert fig.axes[0].get_xlabel() == "vib" and len(fig.axes[0].get_lines()) == 2
    assert "95 % band (>= 1000 trials)" in sweep_figure(table.assign(trials=1000), ["grade"])._suptitle.get_text()
    with pytest.raises(ValueError, match="table is empty"):
        sweep_figure(table.iloc[0:0], ["grade"])
    with pytest.raises(ValueError, match=r"table lacks columns \['high'\]"):
        sweep_figure(table.drop(columns="high"), ["grade"])


def test_scheduler_without_the_sweep_extra_names_it(tmp_path, monkeypatch, capsys):
    """Without dask.distributed, --scheduler is refused in one line that says which extra installs it."""
    import sys

    monkeypatch.setitem(sys.modules, "distributed", None)          # `import distributed` raises ImportError
    spec = tmp_path / "s.toml"
    spec.write_text(SPEC)
    assert cli.main(["sweep", str(spec), "--out", str(tmp_path / "o"), "--scheduler", "tcp://127.0.0.1:1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("mtcal: error: --scheduler tcp://127.0.0.1:1: ")
    assert "pip install 'mtcal[sweep]'" in err
    assert not (tmp_path / "o").exists()
