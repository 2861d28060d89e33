"""One verdict per paper artifact: the rule (a case per verdict), the evidence counted, every catalogue artifact a row."""

import re
from pathlib import Path

import pandas as pd
import pytest

from mtcal.reporting import artifact_verdicts as av
from mtcal.reporting.compare import claim, comparison_row, comparison_table, consistency, in_sample

ROOT = Path(__file__).resolve().parents[2]
BAND = {"low": 0.9, "high": 1.1, "n": 1000, "kind": "95 % band"}


@pytest.mark.parametrize("counts, expected", [
    ((3, 3, 1, 0), "reproduced"),           # every held-out number inside, every claim holds
    ((0, 0, 2, 0), "reproduced"),           # claims only
    ((3, 2, 1, 0), "partly reproduced"),    # one number outside
    ((3, 3, 1, 1), "partly reproduced"),    # one claim fails
    ((0, 0, 1, 1), "partly reproduced"),
    ((4, 0, 0, 0), "not reproduced"),       # nothing inside, no claim
    ((4, 0, 0, 2), "not reproduced"),
    ((0, 0, 0, 3), "not reproduced"),
    ((0, 0, 0, 0), "not comparable"),       # no held-out evidence at all
])
def test_rule_has_a_case_for_each_verdict(counts, expected):
    assert av.verdict(*counts) == expected
    assert set(av.VERDICTS) == {"reproduced", "partly reproduced", "not reproduced", "not comparable"}


def test_rule_rejects_impossible_counts():
    with pytest.raises(ValueError, match="must not exceed numbers_compared"):
        av.verdict(2, 3, 0, 0)
    with pytest.raises(ValueError, match="non-negative integers"):
        av.verdict(-1, 0, 0, 0)


def _table(rows):
    t = comparison_table(rows)
    return pd.read_csv(pd.io.common.StringIO(t.to_csv(index=False)), dtype=str, keep_default_na=False,
                       na_values=[""])  # as read back from data/*_comparison.csv


def test_only_heldout_numbers_and_claims_are_evidence():
    rows = [comparison_row("p2020_table01", "a", 1.0, 1.0, "", None, band=BAND, role="heldout"),
            comparison_row("p2020_table01", "b", 2.0, 1.0, "", None, band=BAND, role="heldout"),
            comparison_row("p2020_table01", "c", 1.0, 1.0, "", None, band=BAND, role="train"),
            comparison_row("p2020_table01", "d", 1.0, 1.0, "", None, band=BAND, role="tuned"),
            claim("p2020_table01", "e", 0.5, 0.4, "below 0.5", lambda v: v < 0.5),
            in_sample("p2020_table01", "f", 0.5, 0.7, "below 0.5", False, on="tuned on it", role="tuned"),
            comparison_row("p2020_fig02", "g", 1.0, 1.0, "", None, band=BAND, role="tuned")]
    arts = pd.DataFrame([{"artifact_id": "p2020_table01", "paper": "p2020", "paper_item": "Table 1",
                          "notebook_section": "s1"},
                         {"artifact_id": "p2020_fig02", "paper": "p2020", "paper_item": "Fig. 2",
                          "notebook_section": "s2"},
                         {"artifact_id": "p2020_fig03", "paper": "p2020", "paper_item": "Fig. 3",
                          "notebook_section": "s3"}])
    out = av.artifact_rows(_table(rows), arts).set_index("artifact_id")
    t1 = out.loc["p2020_table01"]
    assert (t1.numbers_compared, t1.numbers_inside, t1.claims_holding, t1.claims_failing) == (2, 1, 1, 0)
    assert t1.verdict == "partly reproduced" and "farthest b: paper 2" in t1.cause and "4.5 band widths" in t1.cause
    assert out.loc["p2020_fig02"].verdict == "not comparable" and "in-sample only" in out.loc["p2020_fig02"].cause
    assert out.loc["p2020_fig03"].verdict == "not comparable" and "no comparison row" in out.loc["p2020_fig03"].cause
    assert list(out.reset_index().columns) == av.VERDICT_COLUMNS


def test_every_failing_check_and_every_own_threshold_is_in_the_cause_whatever_the_evidence():
    """A failing check of any kind (in-sample, consistency, a finding) is named in the cause even when held-out
    evidence decides the verdict; claims on an mtcal threshold say so."""
    rows = [comparison_row("p2020_table01", "a", 1.0, 1.0, "", None, band=BAND, prior_band=BAND, role="heldout"),
            comparison_row("p2020_table01", "c", 5.0, 1.0, "", None, band=BAND, role="train"),
            in_sample("p2020_table01", "f", 0.5, 0.7, "within 0.5 (in-sample)", False, on="tuned on it", role="tuned"),
            consistency("p2020_table01", "g", 1, 2, "equal by construction", False, by="same formula", enforce=False),
            claim("p2020_table01", "e", 0.5, 0.4, "below 0.5", lambda v: v < 0.5),
            claim("p2020_fig02", "h", "-", 0.4, "(mtcal) below 0.5", lambda v: v < 0.5, role="finding")]
    arts = pd.DataFrame([{"artifact_id": a, "paper": "p2020", "paper_item": i, "notebook_section": "s"}
                         for a, i in (("p2020_table01", "Table 1"), ("p2020_fig02", "Fig. 2"))])
    out = av.artifact_rows(_table(rows), arts).set_index("artifact_id")
    t1 = out.loc["p2020_table01"]
    assert t1.verdict == "reproduced"                                       # decided by the held-out evidence
    assert "prior predictive (nothing fitted): 1 of 1 held-out inside" in t1.cause
    assert "in-sample (fitted or tuned on): 0 of 1 numbers inside; 0 of 1 in-sample checks hold" in t1.cause
    assert "in-sample check fails: within 0.5 (in-sample)" in t1.cause
    assert "consistency check fails: equal by construction" in t1.cause
    f2 = out.loc["p2020_fig02"]
    assert f2.verdict == "reproduced" and f2.cause == "every claim is tested on an mtcal threshold (the paper states none)"
    # a held-out number judged with a tolerance of ours says so too (the statement names it)
    own = [claim("p2020_fig03", "n", 3, 3, "all 3 within 0.01 (mtcal tolerance)", lambda v: v == 3)]
    arts3 = pd.DataFrame([{"artifact_id": "p2020_fig03", "paper": "p2020", "paper_item": "Fig. 3", "notebook_section": "s"}])
    f3 = av.artifact_rows(_table(own), arts3).set_index("artifact_id").loc["p2020_fig03"]
    assert f3.verdict == "reproduced" and "every claim is tested on an mtcal threshold" in f3.cause


def test_every_paper_number_compared_belongs_to_a_catalogue_artifact():
    """Each comparison row that holds a paper number with its role (train, tuned, held out) or a claim lands
    in the verdict of an artifact the catalogue lists: none is left out of data/verdicts.csv."""
    arts = set(av.paper_artifacts(ROOT / "docs" / "artifacts.md").artifact_id)
    rows = av._comparisons(ROOT / "data")
    paper_rows = rows[rows["role"].isin(("train", "tuned", "heldout")) | (rows["kind"] == "claim")]
    orphans = sorted(set(paper_rows["artifact"]) - arts)
    assert not orphans, f"comparison rows of no catalogue artifact: {orphans}"


def test_committed_verdicts_cover_every_catalogue_artifact_and_follow_the_rule():
    arts = av.paper_artifacts(ROOT / "docs" / "artifacts.md")
    table = pd.read_csv(ROOT / "data" / "verdicts.csv", keep_default_na=False)
    assert list(table.columns) == av.VERDICT_COLUMNS
    assert sorted(table.artifact_id) == sorted(arts.artifact_id) and len(arts) > 20
    assert set(table.paper) >= {"wang2023cja", "tan2022", "wang2022sensors"}
    for r in table.itertuples():
        assert r.verdict == av.verdict(r.numbers_compared, r.numbers_inside, r.claims_holding, r.claims_failing)
    # the committed file is what the code makes from the committed comparison tables
    fresh = av.artifact_rows(av._comparisons(ROOT / "data"), arts)
    pd.testing.assert_frame_equal(fresh.reset_index(drop=True), table.reset_index(drop=True), check_dtype=False)


def test_main_refuses_bad_arguments(capsys):
    assert av.main(["only-one"]) == 2
    assert av.main(["/nonexistent", "x.md"]) == 2
    assert "mtcal: error: DATA_FOLDER /nonexistent does not exist" in capsys.readouterr().err


# ---------------------------------------------------------------- each paper sentence counts once
_PLACEHOLDERS = {"", "-", "—", "figure", "all (figure)"}


def _sentence(row) -> tuple:
    """What a counted row tests: a printed number compared within a tolerance (numeric paper cell with its split
    ref) is keyed by that cell; a paper sentence by its quote (the leading "…" of the claim), else the paper cell's
    phrase, else the claim text, each cut before its parenthesis."""
    c, p, ref = (str(row.get(k, "")).strip() for k in ("claim", "paper", "ref"))
    if ref and re.fullmatch(r"[-+]?\d+(\.\d+)?([eE][-+]?\d+)?", p):
        return ("number", ref)
    if c.startswith('"'):
        return ("sentence", c[1:].split('"')[0].strip())
    if re.search(r"[^\W\d_]", p) and p.lower() not in _PLACEHOLDERS and not re.match(r"^[<>=≤≥]", p):
        return ("sentence", p.split(" (")[0].strip())
    return ("sentence", c.split(" (")[0].strip())


def _counted_twice(table: pd.DataFrame) -> list[str]:
    """Paper sentences (or printed numbers) tested by two counted rows of one kind (claim, in-sample) of one paper.

    Counted rows are the paper's statements (``source`` ``paper claim``) of kind ``claim`` or ``in-sample``: they
    enter the claims tallies, ``data/verdicts.csv`` and the site's counts. Two readings of one ambiguous sentence are
    one ``claim`` and one ``in-sample`` row (docs/conventions.md), so each kind is checked on its own.
    """
    rows = table[table["kind"].isin(["claim", "in-sample"]) & (table["source"] == "paper claim")]
    keys = pd.DataFrame({"paper": rows["artifact"].str.split("_").str[0], "kind": rows["kind"],
                         "what": [_sentence(r) for r in rows.to_dict("records")], "artifact": rows["artifact"]})
    twice = keys[keys.duplicated(["paper", "kind", "what"], keep=False)]
    return sorted({f"{r.paper} {r.kind} {r.what[1]!r} ({r.artifact})" for r in twice.itertuples()})


def test_a_sentence_counted_twice_is_found():
    q = "the pitch errors before and after calibration are within 0.05° and 0.02°"
    rows = [in_sample("p2020_table09", s, "<= 0.05", 0.06, f'"{q}" ({s} <= 0.05 deg)', False, on="tuned",
                      role="tuned") for s in ("before", "after")]
    assert _counted_twice(_table(rows)) == [f"p2020 in-sample {q!r} (p2020_table09)"]
    # tan2022's paraphrases: one sentence in the paper cell, whatever the threshold text
    rows = [claim("p2020_fig12", x, f"accurate for a long time (Sec. 3.2{tail})", 14.0, f"{x} made testable: < 1°",
                  lambda v: v < 1) for x, tail in (("a", ""), ("b", ", Fig 12"))]
    assert len(_counted_twice(_table(rows))) == 1
    # one printed number compared twice within a tolerance, keyed by its cell
    rows = [claim("p2020_extra", x, 2.3, 2.3, "|ours - published| <= 0.01 deg", lambda v: True, ref="p:1:v")
            for x in ("a", "b")]
    assert len(_counted_twice(_table(rows))) == 1
    # two readings of one sentence (a claim and an in-sample check) and distinct printed numbers are fine
    rows = [claim("p2020_fig14", "whole", "< 0.05", 0.2, "did not exceed 0.05°", lambda v: v < 0.05),
            in_sample("p2020_fig14", "settled", "< 0.05", 0.04, "did not exceed 0.05°", True, on="window tuned",
                      role="tuned")]
    rows += [claim("p2020_extra", x, 2.3, 2.3, "|ours - published| <= 0.01 deg", lambda v: True, ref=f"p:{i}:v")
             for i, x in enumerate("ab")]
    assert _counted_twice(_table(rows)) == []


def test_each_paper_sentence_counts_once_in_the_committed_tables():
    """Every data/*_comparison.csv (all papers and broad2021): no sentence in two counted rows of one kind; the
    wang2023cja claims files: no quote twice per kind."""
    parts = [pd.read_csv(p, dtype=str, keep_default_na=False) for p in sorted((ROOT / "data").glob("*_comparison.csv"))]
    table = pd.concat([p for p in parts if {"kind", "source", "claim", "paper", "ref"} <= set(p.columns)],
                      ignore_index=True)
    assert {"wang2023cja", "tan2022", "wang2022sensors", "broad2021"} <= set(table["artifact"].str.split("_").str[0])
    assert _counted_twice(table) == []
    for path in sorted((ROOT / "data").glob("*_claims.csv")):
        claims = pd.read_csv(path, dtype=str, keep_default_na=False)
        assert not claims.duplicated(["quote", "kind"]).any(), path.name
