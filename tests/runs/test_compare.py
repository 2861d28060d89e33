"""mtcal.runs.compare: comparison tables of several runs side by side."""

from pathlib import Path

import pandas as pd
import pytest

from mtcal.runs.compare import compare_runs


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
    table, csv_path, png_path = compare_runs([tmp_path / "runs" / "paper", tmp_path / "runs" / "industrial"])
    assert csv_path == tmp_path / "runs" / "compare_paper_vs_industrial.csv" and csv_path.is_file()
    assert png_path is not None and png_path.read_bytes()[:4] == b"\x89PNG"
    assert len(table) == 3  # repeated quantity kept apart
    roll = table[table["quantity"] == "roll RMSE (deg)"].iloc[0]
    assert roll["mtcal [paper]"] == "0.0071" and roll["mtcal [industrial]"] == "0.031"
    assert roll["band [industrial]"] == "[0.02, 0.05]" and roll["flips"] == "True→False (industrial)"
    assert (table["flips"] != "").sum() == 1
    with pytest.raises(ValueError, match="at least two run folders"):
        compare_runs([tmp_path / "runs" / "paper"])
    with pytest.raises(FileNotFoundError, match="has no data/ folder"):
        compare_runs([tmp_path / "runs" / "paper", tmp_path / "nowhere"])
    with pytest.raises(ValueError, match="distinct labels"):
        compare_runs([tmp_path / "runs" / "paper", tmp_path / "runs" / "industrial"], names=["a", "a"])
    (tmp_path / "file").write_text("x")
    with pytest.raises(ValueError, match=r"--out .*file: cannot make the folder"):
        compare_runs([tmp_path / "runs" / "paper", tmp_path / "runs" / "industrial"], out_dir=tmp_path / "file")


def test_compare_runs_names_an_unreadable_table_or_record(tmp_path):
    _fake_run(tmp_path / "a", [("t06", "roll RMSE (deg)", 0.009, 0.0071, "", "<= 0.01", True)])
    _fake_run(tmp_path / "b", [("t06", "roll RMSE (deg)", 0.009, 0.0071, "", "<= 0.01", True)])
    (tmp_path / "b" / "data" / "10_x_comparison.csv").write_bytes(b"\xff\xfe\x00\x01binary")
    with pytest.raises(ValueError, match=r"10_x_comparison.csv is not a readable comparison table"):
        compare_runs([tmp_path / "a", tmp_path / "b"])
    _fake_run(tmp_path / "c", [("t06", "roll RMSE (deg)", 0.009, 0.0071, "", "<= 0.01", True)])
    (tmp_path / "c" / "params.json").write_text("{bad json")
    with pytest.raises(ValueError, match=r"params.json is not a run's parameter record \(JSON"):
        compare_runs([tmp_path / "a", tmp_path / "c"])


def test_compare_runs_keeps_tables_common_to_all_runs(tmp_path):
    _fake_run(tmp_path / "a", [("t06", "roll", 1, 1.0, "", "c", True)])
    _fake_run(tmp_path / "b", [("t06", "roll", 1, 2.0, "", "c", False)])
    pd.DataFrame({"artifact": ["x"], "quantity": ["q"], "mtcal": [1], "holds": [True]}).to_csv(
        tmp_path / "a" / "data" / "20_y_comparison.csv", index=False)
    table, _, _ = compare_runs([tmp_path / "a", tmp_path / "b"], out_dir=tmp_path, figure=False)
    assert set(table["table"]) == {"10_x_comparison"}
    (tmp_path / "b" / "data" / "10_x_comparison.csv").rename(tmp_path / "b" / "data" / "30_z_comparison.csv")
    with pytest.raises(ValueError, match="no comparison table in common"):
        compare_runs([tmp_path / "a", tmp_path / "b"], out_dir=tmp_path)


def test_compare_runs_matches_quantities_labelled_with_parameter_values(tmp_path):
    _fake_run(tmp_path / "a", [("f12", "hybrid (θ̇_t = 0.5 °/s) max error (deg)", 1, 0.4, "", "< 1", True),
                               ("f12", "error at gamma = 0 deg", "-", 1.0, "", "-", True),
                               ("f12", "error at gamma = 60 deg", "-", 2.0, "", "-", True)])
    _fake_run(tmp_path / "b", [("f12", "hybrid (θ̇_t = 10 °/s) max error (deg)", 1, 2.1, "", "< 1", False),
                               ("f12", "error at gamma = 0 deg", "-", 1.5, "", "-", True),
                               ("f12", "error at gamma = 60 deg", "-", 2.5, "", "-", True)])
    table, _, _ = compare_runs([tmp_path / "a", tmp_path / "b"], out_dir=tmp_path, figure=False)
    assert len(table) == 3
    hybrid = table.iloc[[i for i, q in enumerate(table["quantity"]) if q.startswith("hybrid")][0]]
    assert hybrid["quantity"] == "hybrid (θ̇_t = 0.5 °/s) max error (deg)"
    assert (hybrid["mtcal [a]"], hybrid["mtcal [b]"], hybrid["flips"]) == ("0.4", "2.1", "True→False (b)")
    assert table.set_index("quantity").loc["error at gamma = 60 deg", "mtcal [b]"] == "2.5"


def test_compare_runs_three_runs(tmp_path):
    # regression: a third run used to collide on the merged 'quantity' column
    for name, value, holds in (("a", 1.0, True), ("b", 2.0, False), ("c", 3.0, True)):
        _fake_run(tmp_path / name, [("t06", "roll (deg)", 1, value, "", "c", holds)])
    table, _, _ = compare_runs([tmp_path / n for n in "abc"], out_dir=tmp_path, figure=False)
    assert len(table) == 1 and list(table.filter(like="mtcal [").iloc[0]) == ["1.0", "2.0", "3.0"]
    assert table["flips"].iloc[0] != ""


def test_committed_metadata_is_full_size_at_the_default_seeds():
    from mtcal.runs.compare import run_metadata

    meta = run_metadata("committed")
    assert meta["size"] == "full" and meta["known"]
    assert meta["seeds"]["wang2023cja_turntable_comparison"] == "2023"


def test_compare_runs_refuses_size_mismatch(tmp_path):
    import json

    rows = [("t06", "roll RMSE (deg)", 0.009, 0.0071, "[0.005, 0.01]", "<= 0.01", True)]
    for name, size in (("a", "full"), ("b", "ci")):
        _fake_run(tmp_path / name, rows)
        (tmp_path / name / "params.json").write_text(json.dumps({"notebook": "10_x", "size": size, "parameters": {},
                                                                 "defaults": {"SEED": "1"}}))
    with pytest.raises(ValueError, match=r"runs are not comparable: runs differ in size \(a: full, b: ci\)"):
        compare_runs([tmp_path / "a", tmp_path / "b"], figure=False)
    table, _, _ = compare_runs([tmp_path / "a", tmp_path / "b"], figure=False, allow_mismatch=True)
    assert table.attrs["warnings"][0].startswith("runs differ in size")


def test_compare_figure_shows_claims_against_their_thresholds(tmp_path):
    """Issue #36: the figure shows each claim quantity against the claim's threshold (read from the
    claim text, drawn only where that reading reproduces every run's recorded verdict), byte-stable."""
    from mtcal.runs.compare import claim_threshold, compare_figure, threshold_holds

    rows_a = [("t06", "roll RMSE (deg)", 0.009, 0.0071, "[0.005, 0.01]", '"within 0.01°" (<= 0.01 deg)', True),
              ("t07", "share of angles better", "-", 1.0, "", "superior (> 90 % of angles)", True),
              ("t08", "slope", "-", -0.99, "", "≈ −1 (−1.1…−0.9)", True),
              ("t09", "gain at 60 deg", "-", 2.4, "", "> 2", False),      # a verdict the text cannot give
              ("t10", "after − before (deg)", "-", -0.1, "", "after < before", True)]
    rows_b = [("t06", "roll RMSE (deg)", 0.009, 0.031, "[0.02, 0.05]", '"within 0.01°" (<= 0.01 deg)', False),
              ("t07", "share of angles better", "-", 0.8, "", "superior (> 90 % of angles)", False),
              ("t08", "slope", "-", -1.05, "", "≈ −1 (−1.1…−0.9)", True),
              ("t09", "gain at 60 deg", "-", 2.5, "", "> 2", True),
              ("t10", "after − before (deg)", "-", -0.2, "", "after < before", True)]
    _fake_run(tmp_path / "runs" / "paper", rows_a)
    _fake_run(tmp_path / "runs" / "industrial", rows_b)
    runs = [tmp_path / "runs" / "paper", tmp_path / "runs" / "industrial"]
    table, csv_path, png_path = compare_runs(runs)
    by = table.set_index("artifact")
    assert by.loc["t06", "threshold"] == "<= 0.01" and by.loc["t06", "threshold_check"] == "reproduces holds"
    assert by.loc["t07", "threshold"] == "> 0.9 (90 %)"          # a percentage of a share printed as a fraction
    assert by.loc["t08", "threshold"] == "in [-1.1, -0.9]" and by.loc["t08", "threshold_check"] == "reproduces holds"
    assert by.loc["t09", "threshold_check"].startswith("does not reproduce holds")
    assert by.loc["t10", "threshold"] == "" and by.loc["t10", "threshold_check"] == ""
    saved = pd.read_csv(csv_path, dtype=str, keep_default_na=False)
    assert list(saved["threshold"]) == list(table["threshold"])
    first = png_path.read_bytes()
    assert compare_runs(runs)[2].read_bytes() == first               # byte-stable
    fig = compare_figure(table, ["paper", "industrial"])
    panels = {next(ln for ln in ax.get_title(loc="left").split("\n") if ln.startswith("10_x:")).split("  —")[0]: ax
              for ax in fig.axes[:-1]}
    assert len(fig.axes) == 6                                        # five claims, then the ratio panel
    titles = [ax.get_title(loc="left") for ax in fig.axes[:5]]
    assert all("CLAIM FLIPS" in t for t in titles[:3]) and "roll RMSE" in titles[0]   # flipped claims first
    assert not any("CLAIM FLIPS" in t for t in titles[3:])

    def dashed(ax):
        return sorted(round(float(ln.get_xdata()[0]), 6) for ln in ax.get_lines() if ln.get_linestyle() == "--")

    assert dashed(panels["10_x: roll RMSE (deg)"]) == [0.01]
    assert dashed(panels["10_x: share of angles better"]) == [0.9]
    assert dashed(panels["10_x: slope"]) == [-1.1, -0.9]
    assert dashed(panels["10_x: gain at 60 deg"]) == [] and "not drawn" in panels["10_x: gain at 60 deg"].get_title(
        loc="left")
    assert "CLAIM FLIPS" in panels["10_x: roll RMSE (deg)"].get_title(loc="left")
    assert threshold_holds(claim_threshold("(<= 0.01 deg)"), 0.0071)
    import matplotlib.pyplot as plt

    plt.close(fig)
