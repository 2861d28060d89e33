import numpy as np
import pytest

from mtcal.reporting import paper_numbers
from mtcal.reporting import compare


def test_every_table_loads():
    names = paper_numbers.available()
    assert "wang2023cja_table01_positions" in names and len(names) >= 20
    for name in names:
        assert len(paper_numbers.load(name)) > 0


def test_numeric_parsing_keeps_printed_text_available():
    df = paper_numbers.load("wang2023cja_table01_positions")
    assert df["pitch_reference_deg"].dtype.kind == "f" or df["pitch_reference_deg"].dtype.kind == "i"
    text = paper_numbers.load("wang2023cja_table01_positions", as_text=True)
    assert text.loc[1, "pitch_after_deg"] == "-0.013"


def test_value_selects_one_cell():
    v = paper_numbers.value("wang2022sensors_table05_rmse", "rmse_static_deg", rotation_axis="Bv1", system="RAMS")
    assert v == pytest.approx(0.0145)
    with pytest.raises(ValueError, match="exactly one row"):
        paper_numbers.value("wang2022sensors_table05_rmse", "rmse_static_deg", system="RAMS")


def test_comparison_table_formats_and_counts():
    rows = [compare.comparison_row("wang2023cja_table06", "roll RMSE after (deg)", 0.009, 0.0071234, "<= 0.01", True),
            compare.comparison_row("wang2023cja_table06", "yaw RMSE after (deg)", 0.009, 0.012, "<= 0.01", False),
            compare.comparison_row("wang2023cja_table06", "note", "-", "-", "", None)]
    table = compare.comparison_table(rows)
    assert list(table.columns) == compare.COMPARISON_COLUMNS
    assert table.loc[0, "mtcal"] == "0.0071"
    assert compare.claims_summary(table) == "1 of 2 claims hold"


def test_bad_names_raise():
    with pytest.raises(ValueError, match="must be one of the paper tables"):
        paper_numbers.load("no_such_table")
    with pytest.raises(TypeError, match="name must be a str"):
        paper_numbers.load(3)
    with pytest.raises(TypeError, match="holds must be bool"):
        compare.comparison_row("a", "b", 1, 2, "c", "yes")


def test_printed_matrices_are_4x4():
    for name in ("wang2023cja_matrix_qbs_turntable", "wang2023cja_matrix_qbs_windtunnel"):
        m = paper_numbers.load(name).select_dtypes("number").to_numpy()
        assert m.shape[1] >= 4 and np.all(np.isfinite(m))


def test_band_columns_and_summary():
    band = {"low": 0.003, "high": 0.03, "n": 1000}
    rows = [compare.comparison_row("T", "a", 0.009, 0.011, "<= 0.01", False, band=band),
            compare.comparison_row("T", "b", 0.05, 0.011, "<= 0.01", True, band=band),
            compare.comparison_row("T", "c", "n/a", 0.011, "", None, band=band),
            compare.comparison_row("T", "d", 0.05, 0.011, "", None)]
    table = compare.comparison_table(rows)
    assert table.loc[0, "mc_band"] == "[0.003, 0.03]"
    assert table["paper_in_band"].tolist()[:3] == [True, False, None]
    assert table.loc[3, "mc_band"] == ""
    assert compare.band_summary(table) == "paper value inside the mtcal 95 % band of 1000 draws: 1 of 2"
    with pytest.raises(ValueError, match="band must be"):
        compare.comparison_row("T", "a", 1.0, 1.0, "", None, band=(2.0, 1.0))


def test_load_rereads_an_edited_file_and_hands_out_copies(tmp_path, monkeypatch):
    """The parse cache is keyed on the content: an edit of the same size and time stamp is seen (the leak
    tests perturb files in place), and changing a returned table does not change the next one."""
    import os
    import shutil

    src = paper_numbers.paper_dir() / "wang2023cja_table01_positions.csv"
    shutil.copy(src, tmp_path / src.name)
    monkeypatch.setenv("MTCAL_PAPER_DIR", str(tmp_path))
    first = paper_numbers.load("wang2023cja_table01_positions", as_text=True)
    col = next(c for c in first.columns if any(ch.isdigit() for ch in first[c].iloc[0]))
    cell = first[col].iloc[0]
    swapped = cell.replace(next(ch for ch in cell if ch.isdigit()), "9" if "9" not in cell[:1] else "8", 1)
    assert swapped != cell and len(swapped) == len(cell)
    stat = (tmp_path / src.name).stat()
    text = (tmp_path / src.name).read_text().replace(cell, swapped, 1)
    (tmp_path / src.name).write_text(text)
    os.utime(tmp_path / src.name, ns=(stat.st_atime_ns, stat.st_mtime_ns))
    again = paper_numbers.load("wang2023cja_table01_positions", as_text=True)
    assert again[col].iloc[0] == swapped
    again.iloc[0, 0] = "changed by the caller"
    assert paper_numbers.load("wang2023cja_table01_positions", as_text=True).iloc[0, 0] != "changed by the caller"
