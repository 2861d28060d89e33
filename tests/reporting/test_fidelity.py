"""Fidelity scores: Wilson interval, interval score closed forms, aggregation, score block, writer."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from mtcal.core import metrics
from mtcal.reporting import compare, fidelity


def _b(low, high, median=None, n=1000, kind="95 % band"):
    out = {"low": low, "high": high, "n": n, "kind": kind}
    return out if median is None else {**out, "median": median}


def _table():
    r = compare.comparison_row
    return compare.comparison_table([
        r("a", "x", 1.0, 1.1, "", None, band=_b(0.9, 1.2), prior_band=_b(0.0, 5.0, 2.0, n=4, kind="range")),
        r("a", "y", 2.0, 1.0, "", None, band=_b(0.5, 1.5), prior_band=_b(0.0, 5.0, 2.0, n=4, kind="range")),
        r("a", "z", 0.0, 0.1, "", None, band=_b(-1.0, 1.0)),           # zero paper value: no relative scale
        r("a", "t", 3.0, 3.0, "", None, band=_b(2.0, 4.0), role="train"),  # not held out: not scored
        r("a", "c", 1.0, 0.5, "< 2", True),                             # claim without band: not scored
    ])


def test_records_carry_draws_and_kind():
    rec = fidelity.score_records(_table(), "tan2022", "20_x")
    assert list(rec.columns) == fidelity.RECORD_COLUMNS
    assert rec["fitted_draws"].tolist() == [1000, 1000, 1000] and rec["fitted_kind"].tolist() == ["95 % band"] * 3
    assert rec["prior_draws"].tolist()[:2] == [4, 4] and rec["prior_kind"].tolist() == ["range", "range", ""]
    assert rec["prior_draws"].isna().tolist() == [False, False, True]


def test_scoring_audits_the_band_rule():
    row = compare.comparison_row("a", "x", 1.0, 1.1, "", None, band=_b(0.9, 1.2, n=999))
    t = pd.DataFrame([row], columns=compare.COMPARISON_COLUMNS)     # not through comparison_table
    with pytest.raises(ValueError, match=r"a \| x: mc_band is a 95 % band from 999 draws"):
        fidelity.score_records(t, "tan2022", "20_x")
    with pytest.raises(ValueError, match="95 % band from 999 draws"):
        fidelity.score(t)


def test_interval_score_closed_forms():
    alpha = 0.05
    # inside: the width; below: width + (2/α)(l − x); above: width + (2/α)(x − u)
    assert fidelity.interval_score(1.0, 3.0, 2.0) == pytest.approx(2.0)
    assert fidelity.interval_score(1.0, 3.0, 0.5) == pytest.approx(2.0 + 2 / alpha * 0.5)
    assert fidelity.interval_score(1.0, 3.0, 4.0) == pytest.approx(2.0 + 2 / alpha * 1.0)
    assert fidelity.interval_score(0.0, 1.0, 2.0, alpha=0.5) == pytest.approx(1.0 + 4.0)


def test_interval_score_errors():
    with pytest.raises(ValueError, match="alpha must be in"):
        fidelity.interval_score(0, 1, 0, alpha=1.5)
    with pytest.raises(ValueError, match="low <= high"):
        fidelity.interval_score(2.0, 1.0, 0.0)


def test_score_fitted_and_prior():
    s = fidelity.score(_table(), "fitted")
    assert s["n"] == 3 and s["inside"] == 2 and s["coverage"] == pytest.approx(2 / 3)
    # relative widths: 0.3/1 and 1.0/2 (zero paper value skipped) -> median 0.4
    assert s["median_rel_width"] == pytest.approx(0.4)
    is_y = (1.0 + 40 * 0.5) / 2.0
    assert s["mean_rel_interval_score"] == pytest.approx((0.3 + is_y) / 2)
    assert s["within_25pct"] == 1  # x: |1 − 1.1| <= 0.275; y: |2 − 1| > 0.25; z: |0 − 0.1| > 0.025
    p = fidelity.score(_table(), "prior")
    assert p["n"] == 2 and p["inside"] == 2 and p["median_rel_width"] == pytest.approx(3.75)
    with pytest.raises(ValueError, match="baseline must be one of"):
        fidelity.score(_table(), "nominal")


def test_quantile_mc_se_errors():
    with pytest.raises(ValueError, match="q must be in"):
        fidelity.quantile_mc_se(np.arange(10.0), 1.0)
    with pytest.raises(ValueError, match="samples must be"):
        fidelity.quantile_mc_se([1.0], 0.5)


def test_score_block_text():
    text = fidelity.score_block(_table(), "wang2022sensors")
    first = text.splitlines()[0]
    assert first == "wang2022sensors: 86 printed numbers: 13 train, 9 held out, 2 inside; 1 claims: 1 hold"
    assert "Wilson 95 %" in text and "prior predictive: 2 of 2 inside" in text
    assert "does NOT beat" in text or "beats" in text


def test_write_scores_merges_and_is_byte_stable(tmp_path):
    t = _table()
    path = fidelity.write_scores(t, "tan2022", "20_x", folder=tmp_path)
    fidelity.write_scores(t, "wang2022sensors", "30_y", folder=tmp_path)
    first = path.read_bytes()
    fidelity.write_scores(t, "tan2022", "20_x", folder=tmp_path)  # re-run replaces its own records
    assert path.read_bytes() == first
    df = pd.read_csv(path)
    assert list(df.columns) == fidelity.SCORE_COLUMNS
    assert list(zip(df.scope, df.role, df.baseline)) == [
        (scope, role, b) for scope in ("broad2021", "tan2022", "wang2022sensors", "wang2023cja", "overall")
        for role in ("heldout", "tuned") for b in ("fitted", "prior")]
    assert df.loc[df.scope == "wang2023cja", "n"].tolist() == [0, 0, 0, 0]
    assert df.loc[df.scope == "overall", "n"].tolist() == [6, 4, 0, 0]
    assert df.loc[df.scope == "broad2021", "n"].tolist() == [0, 0, 0, 0]
    assert sorted(p.name for p in tmp_path.glob("fidelity_records_*.csv")) == ["fidelity_records_20_x.csv",
                                                                            "fidelity_records_30_y.csv"]
    assert fidelity.aggregate_scores(tmp_path).read_bytes() == first   # the final make-reproduce step
    assert not list(tmp_path.glob(".*.tmp"))                            # atomic writes leave no temporary file
    with pytest.raises(ValueError, match="paper_key must be one of"):
        fidelity.write_scores(t, "x2020", "n", folder=tmp_path)
    with pytest.raises(ValueError, match="notebook must be a non-empty str"):
        fidelity.write_scores(t, "tan2022", "", folder=tmp_path)
    with pytest.raises(ValueError, match="notebook must be a non-empty str"):
        fidelity.write_scores(t, "tan2022", "../x", folder=tmp_path)
    with pytest.raises(ValueError, match="not a comparison table"):
        fidelity.score_records(pd.DataFrame({"role": []}), "tan2022", "n")


DATA = Path(__file__).resolve().parents[2] / "data"


def test_committed_results_follow_the_band_rule():
    """The committed full-size results (make reproduce): every band rests on >= 1000 draws or is a labelled range.

    Needs ``data/`` regenerated by ``make reproduce`` after the band columns were added (``mc_draws``,
    ``mc_kind``, ``prior_draws``, ``prior_kind``; records ``fitted_draws`` … ``prior_kind``).
    """
    tables = sorted(DATA.glob("*comparison*.csv"))
    records = sorted(DATA.glob(f"{fidelity.RECORDS_PREFIX}*.csv"))
    assert tables and records
    for path in tables:
        t = pd.read_csv(path, dtype=str, keep_default_na=False)
        try:
            compare.check_bands(t)
        except ValueError as e:
            raise AssertionError(f"{path.name}: {e}") from None
    for path in records:
        rec = pd.read_csv(path, dtype=str, keep_default_na=False)
        missing = set(fidelity.RECORD_COLUMNS) - set(rec.columns)
        assert not missing, f"{path.name}: no columns {sorted(missing)} (regenerate data/ with make reproduce)"
        for base in fidelity.BASELINES:
            has = rec[f"{base}_low"].str.strip() != ""
            kinds = rec.loc[has, f"{base}_kind"]
            draws = pd.to_numeric(rec.loc[has, f"{base}_draws"], errors="coerce")
            bad = rec.loc[has][~kinds.isin(compare.BAND_KINDS) | draws.isna()
                               | ((kinds == "95 % band") & (draws < metrics.MIN_BAND_DRAWS))]
            assert bad.empty, f"{path.name}: {base} bands break the rule in rows {bad['quantity'].tolist()[:5]}"


def test_committed_results_check_fails_on_a_short_band(tmp_path):
    """The scan above catches a 999-draw band and an unlabelled count (its checks can fail)."""
    t = compare.comparison_table([compare.comparison_row("a", "x", 1.0, 1.0, "", None,
                                                         band=metrics.band_or_range(np.arange(1000.0)))])
    t.to_csv(tmp_path / "x_comparison.csv", index=False)
    back = pd.read_csv(tmp_path / "x_comparison.csv", dtype=str, keep_default_na=False)
    back.loc[0, "mc_draws"] = "999"
    with pytest.raises(ValueError, match="95 % band from 999 draws"):
        compare.check_bands(back)
    back.loc[0, "mc_draws"] = ""
    with pytest.raises(ValueError, match="no known draw count"):
        compare.check_bands(back)


def test_tuned_numbers_are_scored_beside_the_heldout_ones_never_pooled(tmp_path):
    from mtcal.reporting.compare import comparison_row, comparison_table

    band = lambda lo, hi: {"low": lo, "high": hi, "n": 1000, "kind": "95 % band"}
    t = comparison_table([comparison_row("a", "x", 1.0, 1.0, "", None, band=band(0.9, 1.1), role="heldout"),
                          comparison_row("a", "y", 2.0, 1.0, "", None, band=band(0.9, 1.1), role="tuned"),
                          comparison_row("a", "z", 1.0, 1.0, "", None, band=band(0.9, 1.1), role="tuned"),
                          comparison_row("a", "w", 5.0, 1.0, "", None, band=band(0.9, 1.1), role="train")])
    assert (fidelity.score(t)["n"], fidelity.score(t)["inside"]) == (1, 1)
    tuned = fidelity.score(t, role="tuned")
    assert (tuned["n"], tuned["inside"]) == (2, 1)
    with pytest.raises(ValueError, match="role must be one of"):
        fidelity.score(t, role="train")
    fidelity.write_scores(t, "wang2023cja", "10_x", folder=tmp_path)
    df = pd.read_csv(tmp_path / "fidelity_scores.csv").set_index(["scope", "role", "baseline"])
    assert df.loc[("wang2023cja", "heldout", "fitted"), "n"] == 1 and df.loc[("wang2023cja", "tuned", "fitted"), "n"] == 2
    assert "tuned (in-sample) fitted (posterior predictive): 1 of 2 inside" in fidelity.score_block(t, "wang2023cja")


def _cv_records(n=4):
    recs = pd.DataFrame({"notebook": "10_x", "paper_key": "wang2023cja", "artifact": ["t1", "t1", "t2", "t2"][:n],
                         "quantity": list("abcd")[:n], "ref": list("abcd")[:n], "paper_value": [0.1, -0.2, 0.05, 0.3][:n]})
    for b, half in (("fitted", 0.15), ("prior", 1.0), ("no-physics", 0.25)):
        recs[f"{b}_median"], recs[f"{b}_low"], recs[f"{b}_high"] = 0.0, -half, half
    recs["draws"] = 1000
    return recs[fidelity.CV_RECORD_COLUMNS]


def test_cross_validation_rows_follow_the_existing_ones_per_table_and_baseline(tmp_path):
    from mtcal.reporting.compare import comparison_row, comparison_table

    t = comparison_table([comparison_row("a", "x", 1.0, 1.0, "", None, band=_b(0.9, 1.1), role="heldout")])
    fidelity.write_scores(t, "wang2023cja", "10_x", folder=tmp_path)
    before = (tmp_path / "fidelity_scores.csv").read_text().splitlines()
    fidelity.write_cv_records(_cv_records(), "10_x", folder=tmp_path)
    after = (tmp_path / "fidelity_scores.csv").read_text().splitlines()
    assert after[:len(before)] == before                           # existing rows unchanged, the CV rows appended
    df = pd.read_csv(tmp_path / "fidelity_scores.csv")
    cv = df[df.role == fidelity.CV_ROLE].set_index(["scope", "baseline"])
    assert len(cv) == 3 * 3 and set(cv.index.get_level_values(0)) == {"t1", "t2", "wang2023cja"}
    # t1: paper 0.1 and -0.2 against ±0.15 (fitted): 1 inside; ±0.25 (no physics): 2 inside
    assert cv.loc[("t1", "fitted"), "inside"] == 1 and cv.loc[("t1", "no-physics"), "inside"] == 2
    is_t1 = fidelity.interval_score([-0.15, -0.15], [0.15, 0.15], [0.1, -0.2]) / np.array([0.1, 0.2])
    assert cv.loc[("t1", "fitted"), "mean_rel_interval_score"] == pytest.approx(is_t1.mean(), abs=1e-4)
    assert cv.loc[("wang2023cja", "prior"), "n"] == 4


def test_cross_validation_records_errors(tmp_path):
    with pytest.raises(ValueError, match="missing \\['draws'\\]"):
        fidelity.write_cv_records(_cv_records().drop(columns="draws"), "10_x", folder=tmp_path)
    with pytest.raises(ValueError, match="notebook must be a non-empty str"):
        fidelity.write_cv_records(_cv_records(), "10 x", folder=tmp_path)
    with pytest.raises(ValueError, match="paper_key must be one of"):
        fidelity.write_cv_records(_cv_records().assign(paper_key="x2020"), "10_x", folder=tmp_path)
    with pytest.raises(ValueError, match="baseline must be one of"):
        fidelity.aggregate(_cv_records(), "posterior")
