"""compare: split roles, claim/consistency kinds, prior bands, claims that can fail."""

import pytest

from mtcal.reporting import compare


def test_roles_are_the_split_roles_plus_finding():
    assert compare.ROLES == ("train", "heldout", "input", "erratum", "not-compared", "finding")
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
    r = compare.comparison_row("a", "b", 1.0, 1.0, "", None, band=(0.5, 0.9), prior_band=(0.0, 2.0))
    assert r["paper_in_band"] is False and r["prior_in_band"] is True and r["prior_band"] == "[0, 2]"
    t = compare.comparison_table([r])
    assert list(t.columns) == compare.COMPARISON_COLUMNS


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
