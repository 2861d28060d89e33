"""compare: split roles, claim/consistency kinds, prior bands, claims that can fail."""

import numpy as np
import pandas as pd
import pytest

from mtcal.core import metrics
from mtcal.reporting import compare


def test_roles_are_the_split_roles_plus_finding():
    assert compare.ROLES == ("train", "tuned", "heldout", "input", "erratum", "not-compared", "finding")
    with pytest.raises(ValueError, match="role must be one of"):
        compare.comparison_row("a", "b", 1, 1, "", None, role="predicted")
    with pytest.raises(ValueError, match="kind must be one of"):
        compare.comparison_row("a", "b", 1, 1, "", True, kind="band")
    with pytest.raises(ValueError, match="needs holds"):
        compare.comparison_row("a", "b", 1, 1, "", None, kind="claim")
    with pytest.raises(ValueError, match="band must be a finite"):
        compare.comparison_row("a", "b", 1, 1, "", None, band=(2.0, 1.0))
    with pytest.raises(ValueError, match="prior_band must be a finite"):
        compare.comparison_row("a", "b", 1, 1, "", None, prior_band=(0.0, float("nan")))


def test_prior_band_columns():
    r = compare.comparison_row("a", "b", 1.0, 1.0, "", None, band={"low": 0.5, "high": 0.9, "n": 1000},
                               prior_band=metrics.band_or_range([0.0, 1.0, 2.0]))
    assert r["paper_in_band"] is False and r["prior_in_band"] is True and r["prior_band"] == "range [0, 2] (n=3)"
    assert (r["mc_draws"], r["mc_kind"], r["prior_draws"], r["prior_kind"]) == (1000, "95 % band", 3, "range")
    t = compare.comparison_table([r])
    assert list(t.columns) == compare.COMPARISON_COLUMNS
    assert t["mc_draws"].dtype == "Int64" and t.loc[0, "prior_draws"] == 3


def _row(name, band=None, prior_band=None):
    return compare.comparison_row("art", name, 1.0, 1.0, "", None, band=band, prior_band=prior_band)


def _frame(*rows):
    """A table built without comparison_table (whose own audit would raise first)."""
    return pd.DataFrame(list(rows), columns=compare.COMPARISON_COLUMNS)


def test_band_rule_audit_threshold_is_min_band_draws():
    assert metrics.MIN_BAND_DRAWS == 1000
    ok = _row("x", band=metrics.percentile_band(np.arange(1000.0)))          # 1000 draws: a 95 % band
    assert ok["mc_draws"] == 1000 and ok["mc_kind"] == "95 % band"
    assert compare.check_bands(compare.comparison_table([ok])).startswith("bands: 1 95 % bands")
    short = _row("x", band=metrics.percentile_band(np.arange(999.0)))        # 999 draws called a 95 % band
    with pytest.raises(ValueError, match=r"art \| x: mc_band is a 95 % band from 999 draws"):
        compare.check_bands(_frame(short))
    with pytest.raises(ValueError, match="95 % band from 999 draws"):
        compare.comparison_table([short])                                     # no table is built with it
    with pytest.raises(ValueError, match=r"art \| x: prior_band is a 95 % band from 999 draws"):
        compare.check_bands(_frame(_row("x", prior_band=metrics.percentile_band(np.arange(999.0)))))


def test_band_rule_audit_accepts_a_labelled_range():
    r = _row("x", band=metrics.band_or_range([1.0, 2.0, 3.0, 4.0]))
    assert (r["mc_band"], r["mc_draws"], r["mc_kind"]) == ("range [1, 4] (n=4)", 4, "range")
    assert compare.check_bands(compare.comparison_table([r])) == "bands: 0 95 % bands (>= 1000 draws), 1 ranges with their count"


def test_band_rule_audit_rejects_unknown_counts_and_kinds():
    pair = _row("x", band=(0.5, 1.5))                                         # a bare pair: unknown draws
    assert pair["mc_draws"] is None and pair["mc_kind"] == "95 % band"
    with pytest.raises(ValueError, match=r"art \| x: mc_band has no known draw count"):
        compare.check_bands(_frame(pair))
    with pytest.raises(ValueError, match="no known draw count"):
        compare.comparison_table([_row("y", prior_band={"low": 0.0, "high": 1.0})])
    bad_kind = dict(_row("x", band=metrics.band_or_range(np.arange(1000.0))), mc_kind="90 % band")
    with pytest.raises(ValueError, match=r"mc_band has kind '90 % band', expected one of"):
        compare.check_bands(_frame(bad_kind))
    legacy = _frame(_row("x", band=metrics.band_or_range(np.arange(1000.0)))).drop(columns=["mc_draws", "mc_kind"])
    with pytest.raises(ValueError, match="mc_band has no mc_draws/mc_kind columns"):   # a table from before them
        compare.check_bands(legacy)
    with pytest.raises(TypeError, match="table must be a pandas DataFrame"):
        compare.check_bands([pair])


def test_band_rule_audit_reads_tables_back_from_csv(tmp_path):
    rows = [_row("x", band=metrics.band_or_range(np.arange(1000.0))), _row("y", band=metrics.band_or_range([1.0, 2.0])),
            _row("z")]
    path = tmp_path / "t_comparison.csv"
    compare.comparison_table(rows).to_csv(path, index=False)
    back = pd.read_csv(path, dtype=str, keep_default_na=False)
    assert back["mc_draws"].tolist() == ["1000", "2", ""]
    assert compare.check_bands(back) == "bands: 1 95 % bands (>= 1000 draws), 1 ranges with their count"
    back.loc[0, "mc_draws"] = "999"
    with pytest.raises(ValueError, match="95 % band from 999 draws"):
        compare.check_bands(back)


def test_check_claims_runs_the_band_audit_even_in_a_what_if_run():
    t = _frame(compare.comparison_row("a", "x", 1.0, 1.0, "x = 1", True, band=metrics.percentile_band([0.5, 1.5])))
    for enforce in (True, False):
        with pytest.raises(ValueError, match=r"a \| x: mc_band is a 95 % band from 2 draws"):
            compare.check_claims(t, enforce=enforce)


def test_band_validation_errors():
    with pytest.raises(ValueError, match=r"band\['n'\] must be a positive int"):
        _row("x", band={"low": 0.0, "high": 1.0, "n": 0})
    with pytest.raises(ValueError, match=r"prior_band\['n'\] must be a positive int"):
        _row("x", prior_band={"low": 0.0, "high": 1.0, "n": 2.5})
    with pytest.raises(ValueError, match=r"band\['n'\] must be a positive int"):
        _row("x", band={"low": 0.0, "high": 1.0, "n": True})
    with pytest.raises(ValueError, match=r"band\['kind'\] must be one of"):
        _row("x", band={"low": 0.0, "high": 1.0, "n": 5, "kind": "interval"})


def test_band_record_follows_the_rule():
    few = compare.band_record("a", "x", 2.0, [1.0, 2.0, 3.0])
    assert (few["n"], few["kind"]) == (3, "range")
    assert compare.band_row(few, "", None)["mc_band"] == "range [1, 3] (n=3)"
    assert "range [1.0000, 3.0000] (n=3)" in compare.band_text(few)
    many = compare.band_record("a", "x", 2.0, np.linspace(0.0, 4.0, 1000))
    assert (many["n"], many["kind"]) == (1000, "95 % band") and compare.band_row(many, "", None)["mc_draws"] == 1000


def test_claim_carries_its_check_and_can_fail():
    row = compare.claim("t", "static RMSE (deg)", 0.05, 0.012, "less than 0.05°", lambda v: v < 0.05)
    assert row["holds"] is True and row["kind"] == "claim"
    assert row["check"](0.07) is False
    with pytest.raises(TypeError, match="check must be callable"):
        compare.claim("t", "q", 1, 1, "x", True)


def test_consistency_rows_are_not_claims():
    rows = [compare.consistency("t", "inside prior", 0.2, 0.2, "inside", True, by="grid inside prior"),
            compare.claim("t", "q", 1.0, 0.5, "< 1", lambda v: v < 1.0),
            compare.claim("t", "q2", 1.0, 2.0, "< 1", lambda v: v < 1.0, enforce=False, note="2 > 1")]
    t = compare.comparison_table(rows)
    assert compare.claims_summary(t) == "1 of 2 claims hold"
    text = compare.check_claims(t, enforce=True)  # the failing claim is reported, not enforced
    assert "2 > 1" in text and "consistency checks (true by construction, not claims): 1 of 1 hold" in text
    with pytest.raises(ValueError, match="by must say why"):
        compare.consistency("t", "q", 1, 1, "s", True, by="")


def test_enforced_failing_row_raises():
    t = compare.comparison_table([compare.claim("t", "q", 1.0, 2.0, "< 1", lambda v: v < 1.0)])
    with pytest.raises(AssertionError, match="every enforced claim"):
        compare.check_claims(t, enforce=True)
    assert compare.check_claims(t, enforce=False).startswith("0 of 1 claims hold")


def _banded(name, band, role="heldout", paper=1.0):
    return compare.comparison_row("a", name, paper, 1.0, "", None, band=band, role=role)


@pytest.mark.parametrize(("band", "words"), [
    ({"low": 0.9, "high": 1.2, "n": 1000}, "95 % band of 1000 draws"),
    ({"low": 0.9, "high": 1.2, "n": 4, "kind": "range"}, "range of 4 draws"),
    ({"low": 0.9, "high": 1.2, "n": 1, "kind": "range"}, "range of 1 draw"),
    (compare.credible_interval(0.9, 1.2), "credible interval"),
])
def test_summaries_name_the_band_kind_and_draws(band, words):
    t = compare.comparison_table([_banded("x", band), _banded("y", band, role="train", paper=5.0)])
    assert compare.band_description(t) == words
    assert compare.band_summary(t) == f"paper value inside the mtcal {words}: 1 of 2"
    assert compare.role_summary(t) == f"paper inside our {words}: train 0 of 1, heldout 1 of 1"


def test_summaries_list_each_kind_of_a_mixed_table():
    rows = [_banded("x", {"low": 0.9, "high": 1.2, "n": 4, "kind": "range"}),
            _banded("y", {"low": 0.9, "high": 1.2, "n": 12, "kind": "range"}),
            _banded("z", {"low": 0.9, "high": 1.2, "n": 2000}, role="train"),
            _banded("w", {"low": 0.9, "high": 1.2, "n": 1000}, role="train"),
            _banded("v", compare.credible_interval(0.0, 0.5)),
            compare.comparison_row("a", "no band", 1.0, 1.0, "", None)]
    t = compare.comparison_table(rows)
    words = "band (95 % band of 1000–2000 draws; range of 4–12 draws; credible interval)"
    assert compare.band_description(t) == words
    assert compare.role_summary(t) == f"paper inside our {words}: train 2 of 2, heldout 2 of 3"
    assert compare.band_summary(t) == f"paper value inside the mtcal {words}: 4 of 5"
    # only the rows counted are described: the prior bands here are all ranges
    prior = compare.comparison_table([compare.comparison_row("a", "x", 1.0, 1.0, "", None,
                                                             prior_band=metrics.band_or_range([0.0, 2.0]))])
    assert compare.band_description(prior, "prior") == "range of 2 draws"
    assert compare.band_description(prior) == "band"
    assert compare.role_summary(prior) == "paper inside our band: no banded rows"


def test_band_description_unknown_counts_and_errors():
    t = pd.DataFrame([_banded("x", (0.9, 1.2))])           # a bare pair: unknown count (check_bands rejects it)
    assert compare.band_description(t) == "95 % band of ? draws"
    assert compare.band_description(t.drop(columns="mc_kind")) == "band"
    with pytest.raises(ValueError, match=r"which must be one of \('mc', 'prior'\), got 'posterior'"):
        compare.band_description(t, "posterior")


def test_spread_text_is_the_one_band_formatter():
    assert compare.spread_text(0.0051234, 0.01, "95 % band", 1000) == "[0.005123, 0.01]"
    assert compare.spread_text(1.0, 3.0, "range", None, digits=2) == "range [1.00, 3.00] (n=?)"
    assert compare.spread_text(0.1, 0.3, "credible interval") == "credible [0.1, 0.3]"
    rec = compare.band_record("a", "x", 2.0, [1.0, 2.0, 3.0])
    assert compare.band_row(rec, "", None)["mc_band"] == compare.spread_text(1.0, 3.0, "range", 3)
    assert compare.spread_text(1.0, 3.0, "range", 3, digits=4) in compare.band_text(rec)
    with pytest.raises(ValueError, match=r"kind must be one of \('95 % band', 'range', 'credible interval'\), "
                                         r"got 'interval'"):
        compare.spread_text(0.0, 1.0, "interval")


def test_cell_helpers_read_csv_cells():
    assert [compare.is_missing(v) for v in (None, np.nan, pd.NA, "", "nan", "None", 0, 0.0, "0")] == \
        [True] * 6 + [False] * 3
    assert [compare.draw_count(v) for v in (4, 4.0, "1000", "1000.0", pd.NA, "", 0, -3, 2.5, "x")] == \
        [4, 4, 1000, 1000, None, None, None, None, None, None]
    assert [compare.cell_text(v) for v in ("range", None, np.nan, 3)] == ["range", "", "", "3"]
