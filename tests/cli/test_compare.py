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
    assert (tmp_path / "runs" / "compare_paper_vs_industrial.csv").is_file()
    assert (tmp_path / "runs" / "compare_paper_vs_industrial.png").is_file()


def test_compare_errors_are_one_line(tmp_path, capsys):
    _fake_run(tmp_path / "runs" / "paper", 0.0071, True)
    assert cli.main(["compare", str(tmp_path / "runs" / "paper")]) == 2
    assert "mtcal: error: runs must list at least two run folders" in capsys.readouterr().err
    assert cli.main(["compare", str(tmp_path / "runs" / "paper"), str(tmp_path / "missing")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("mtcal: error: run") and "has no data/ folder" in err and err.count("\n") == 1
