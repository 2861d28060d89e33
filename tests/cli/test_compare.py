from pathlib import Path

import pandas as pd

from mtcal import cli


def _fake_run(folder: Path, roll: float, holds: bool):
    (folder / "data").mkdir(parents=True)
    pd.DataFrame({"artifact": ["t06", "t06"], "quantity": ["roll RMSE (deg)", "points"], "paper": [0.009, 2],
                  "mtcal": [roll, 2], "mc_band": ["[0.005, 0.01]", ""], "paper_in_band": [True, ""],
                  "claim": ["<= 0.01", "two"], "holds": [holds, True], "role": "predicted",
                  "source": "paper claim"}).to_csv(folder / "data" / "10_x_comparison.csv", index=False)


def test_compare_prints_flips_and_saves(tmp_path, capsys):
    _fake_run(tmp_path / "runs" / "paper", 0.0071, True)
    _fake_run(tmp_path / "runs" / "industrial", 0.031, False)
    code = cli.main(["compare", str(tmp_path / "runs" / "paper"), str(tmp_path / "runs" / "industrial")])
    out = capsys.readouterr().out
    assert code == 0
    assert "1 of 2 quantities differ between paper, industrial" in out
    assert "claims that flip (1):" in out and "roll RMSE (deg) | <= 0.01 | True→False (industrial)" in out
    assert out.index("claims that flip") < out.index("quantities differ")          # the headline first
    assert (tmp_path / "runs" / "compare_paper_vs_industrial.csv").is_file()
    assert (tmp_path / "runs" / "compare_paper_vs_industrial.png").is_file()


def test_compare_errors_are_one_line(tmp_path, capsys):
    _fake_run(tmp_path / "runs" / "paper", 0.0071, True)
    assert cli.main(["compare", str(tmp_path / "runs" / "paper")]) == 2
    assert "mtcal: error: runs must list at least two run folders" in capsys.readouterr().err
    assert cli.main(["compare", str(tmp_path / "runs" / "paper"), str(tmp_path / "missing")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("mtcal: error: run") and "has no data/ folder" in err and err.count("\n") == 1


def _params(folder: Path, size: str, seed=None):
    import json

    record = {"notebook": "10_x", "size": size, "parameters": {} if seed is None else {"SEED": seed},
              "defaults": {"SEED": "2023"}, "status": "completed"}
    (folder / "params.json").write_text(json.dumps(record))


def test_compare_refuses_runs_of_different_size_unless_allowed(tmp_path, capsys):
    _fake_run(tmp_path / "runs" / "full", 0.0071, True)
    _fake_run(tmp_path / "runs" / "small", 0.0072, True)
    _params(tmp_path / "runs" / "full", "full")
    _params(tmp_path / "runs" / "small", "ci")
    argv = ["compare", str(tmp_path / "runs" / "full"), str(tmp_path / "runs" / "small")]
    assert cli.main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "mtcal: error: runs are not comparable: runs differ in size (full: full, small: ci)" in err
    assert "--allow-mismatch" in err
    assert cli.main(argv + ["--allow-mismatch"]) == 0
    captured = capsys.readouterr()
    assert "mtcal: WARNING: runs differ in size (full: full, small: ci)" in captured.err
    assert "comparability warning(s)" in captured.out and "claims that flip: none" in captured.out
    saved = pd.read_csv(tmp_path / "runs" / "compare_full_vs_small.csv")
    assert saved["comparability"].str.startswith("runs differ in size (full: full, small: ci)").all()


def test_compare_refuses_runs_of_different_seed(tmp_path, capsys):
    _fake_run(tmp_path / "runs" / "a", 0.0071, True)
    _fake_run(tmp_path / "runs" / "b", 0.0072, True)
    _params(tmp_path / "runs" / "a", "ci")
    _params(tmp_path / "runs" / "b", "ci", seed=7)
    assert cli.main(["compare", str(tmp_path / "runs" / "a"), str(tmp_path / "runs" / "b")]) == 2
    assert "runs differ in seed policy for 10_x (a: SEED=2023, b: SEED=7)" in capsys.readouterr().err


def test_compare_warns_when_metadata_is_unknown(tmp_path, capsys):
    _fake_run(tmp_path / "runs" / "a", 0.0071, True)
    _fake_run(tmp_path / "runs" / "b", 0.0072, True)
    _params(tmp_path / "runs" / "a", "ci")
    assert cli.main(["compare", str(tmp_path / "runs" / "a"), str(tmp_path / "runs" / "b")]) == 0
    assert "mtcal: WARNING: run b has no params.json: its size and seed are unknown" in capsys.readouterr().err
