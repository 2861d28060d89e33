"""Paper-vs-mtcal comparison rows, Monte Carlo bands, and scenario tables for display.

Every notebook reports its results through :func:`comparison_table`, with the
columns :data:`COMPARISON_COLUMNS`: ``artifact | quantity | paper | mtcal |
mc_band | paper_in_band | prior_band | prior_in_band | claim | holds | kind |
role | source | note | enforced | ref`` and the numeric band ends (``mc_low,
mc_high, prior_median, prior_low, prior_high``). The band columns are filled where
the mtcal number comes from a Monte Carlo: posterior-predictive median in
``mtcal``, its 95 % interval in ``mc_band``; the prior-predictive interval (the
baseline, parameters drawn from the prior) in ``prior_band``.

``role`` is the split role of the paper number (:data:`ROLES`: ``train``,
``heldout``, ``input``, ``erratum``, ``not-compared`` as in
``paper_data/<key>_split.csv``, plus ``finding`` for our own results). ``kind``
says what a tested row is: ``claim`` (the paper's statement with its threshold
quoted in ``claim``) or ``consistency`` (true by construction: a model fitted to
the same numbers, a prior containing the grid, a bounded transform) -- consistency
rows never count as claims.

>>> row = comparison_row("wang2023cja_table06", "roll RMSE (deg)", 0.009, 0.0071, "<= 0.01", True,
...                      band=(0.005, 0.010))
>>> row["paper_in_band"], row["kind"], row["role"]
(True, 'claim', 'heldout')
"""

from __future__ import annotations

from dataclasses import fields

import numpy as np
import pandas as pd

from mtcal.core import metrics
from mtcal.core.validate import merge_parameters

__all__ = ["COMPARISON_COLUMNS", "DISPLAY_COLUMNS", "comparison_row", "comparison_table", "band_summary", "claims_summary",
           "band_record", "band_row", "band_text", "describe", "claim", "consistency",
           "ROLES", "KINDS", "SOURCES", "at_paper_settings", "check_claims", "role_summary", "prediction_summary"]

COMPARISON_COLUMNS = ["artifact", "quantity", "paper", "mtcal", "mc_band", "paper_in_band", "prior_band",
                      "prior_in_band", "claim", "holds", "kind", "role", "source", "note", "enforced", "ref",
                      "mc_low", "mc_high", "prior_median", "prior_low", "prior_high"]

#: The columns a notebook prints (the numeric band ends and bookkeeping stay in the saved CSV).
DISPLAY_COLUMNS = ["artifact", "quantity", "paper", "mtcal", "mc_band", "prior_band", "claim", "holds", "kind",
                   "role"]
#: What the paper number of a row is: its split role (``paper_data/<key>_split.csv``) or ``finding``
#: (a result of ours the paper does not state).
ROLES = ("train", "heldout", "input", "erratum", "not-compared", "finding")
#: What a tested row is: the paper's claim, or a check that holds by construction.
KINDS = ("claim", "consistency")
#: Who makes the claim in the row.
SOURCES = ("paper claim", "mtcal finding")


def _band(band, name):
    """(median or nan, low, high) of a band given as a dict or a pair; validated."""
    if isinstance(band, dict):
        low, high, med = band["low"], band["high"], band.get("median", np.nan)
    else:
        low, high = band
        med = np.nan
    low, high, med = float(low), float(high), float(med)
    if not (np.isfinite(low) and np.isfinite(high)) or low > high:
        raise ValueError(f"{name} must be a finite (low, high) with low <= high, got ({low}, {high})")
    return med, low, high


def _inside(paper, low, high):
    try:
        return bool(low <= float(paper) <= high)
    except (TypeError, ValueError):
        return None  # the paper gives no number to place in the band


def comparison_row(artifact: str, quantity: str, paper, mtcal, claim: str, holds: bool | None,
                   *, band=None, prior_band=None, role: str = "heldout", source: str = "paper claim",
                   kind: str | None = None, note: str = "", enforce: bool = True, ref: str = "") -> dict:
    """One row of the paper-vs-mtcal table.

    Parameters
    ----------
    artifact, quantity : str
        Artifact ID (``"wang2023cja_table06"``) and what is compared, with its unit.
    paper, mtcal : float or str
        The paper's printed value and ours (for a Monte Carlo: the posterior-predictive median).
    claim : str
        The paper's statement with its threshold, quoted (or the consistency statement).
    holds : bool or None
        Whether the claim holds in simulation (``None``: nothing tested).
    band : dict or (low, high), optional
        Posterior-predictive 95 % band of the mtcal number (``metrics.percentile_band``
        output or a pair). The row records it as ``"[low, high]"`` and whether a
        numeric paper value lies inside it.
    prior_band : dict or (low, high), optional
        Prior-predictive 95 % band (parameters drawn from the prior): the baseline.
    role : {"train", "heldout", "input", "erratum", "not-compared", "finding"}
        Split role of the paper number (``finding``: our own result).
    source : {"paper claim", "mtcal finding"}
        Whose claim the ``claim`` column states.
    kind : {"claim", "consistency"}, optional
        Default ``"claim"`` when ``holds`` is given and ``source`` is the paper,
        else empty (our own findings are never the paper's claims).
    note : str
        Computed reason a claim fails, or what makes a consistency row true by construction.
    enforce : bool
        Whether :func:`check_claims` enforces the row at the paper's settings
        (False for a claim reported as failing with its reason).
    ref : str
        The split cell(s) compared, ``"file:row:column"`` (``;``-separated).
    """
    if role not in ROLES:
        raise ValueError(f"role must be one of {ROLES}, got {role!r}")
    if source not in SOURCES:
        raise ValueError(f"source must be one of {SOURCES}, got {source!r}")
    if holds is not None and not isinstance(holds, (bool, np.bool_)):
        raise TypeError(f"holds must be bool or None, got {type(holds).__name__}")
    if kind is None:
        kind = "claim" if holds is not None and source == "paper claim" else ""
    elif kind not in KINDS:
        raise ValueError(f"kind must be one of {KINDS}, got {kind!r}")
    if kind and holds is None:
        raise ValueError(f"a {kind!r} row needs holds (bool), got None")
    out = {"artifact": artifact, "quantity": quantity, "paper": paper, "mtcal": mtcal,
           "mc_band": "", "paper_in_band": None, "prior_band": "", "prior_in_band": None, "claim": claim,
           "holds": None if holds is None else bool(holds), "kind": kind, "role": role, "source": source,
           "note": note, "enforced": bool(enforce) if holds is not None else None, "ref": ref,
           "mc_low": np.nan, "mc_high": np.nan, "prior_median": np.nan, "prior_low": np.nan, "prior_high": np.nan}
    if band is not None:
        _, low, high = _band(band, "band")
        out.update(mc_band=f"[{low:.4g}, {high:.4g}]", paper_in_band=_inside(paper, low, high), mc_low=low,
                   mc_high=high)
    if prior_band is not None:
        med, low, high = _band(prior_band, "prior_band")
        out.update(prior_band=f"[{low:.4g}, {high:.4g}]", prior_in_band=_inside(paper, low, high),
                   prior_median=med, prior_low=low, prior_high=high)
    return out


def claim(artifact: str, quantity: str, paper, mtcal, quote: str, check, *, band=None, prior_band=None,
          role: str = "heldout", enforce: bool = True, note: str = "", ref: str = "", value=None) -> dict:
    """A paper claim tested with its own threshold; the row carries ``check`` so a test can re-run it.

    Parameters
    ----------
    quote : str
        The paper's statement with its threshold, verbatim.
    check : callable
        ``check(value) -> bool``, the claim evaluated on our number; the row's
        ``holds`` is ``check(value)``, ``row["check"]`` is ``check`` and
        ``row["value"]`` the number it was evaluated on (tests perturb it and see
        the check return False).
    value : float, optional
        The number the claim is evaluated on when it is not ``mtcal`` (e.g. a
        97.5 % band end); default ``mtcal``.
    enforce : bool
        False for a claim our model fails (reported with ``note``, the computed reason).

    >>> r = claim("t", "static RMSE (deg)", 0.05, 0.012, "less than 0.05°", lambda v: v < 0.05)
    >>> r["holds"], r["kind"], r["check"](0.06)
    (True, 'claim', False)
    """
    if not callable(check):
        raise TypeError(f"check must be callable, got {type(check).__name__}")
    value = mtcal if value is None else value
    holds = bool(check(value))
    row = comparison_row(artifact, quantity, paper, mtcal, quote, holds, band=band, prior_band=prior_band,
                         role=role, kind="claim", note=note, enforce=enforce, ref=ref)
    row["check"], row["value"] = check, value
    return row


def consistency(artifact: str, quantity: str, paper, mtcal, statement: str, holds: bool, *, by: str,
                band=None, prior_band=None, role: str = "train", ref: str = "", enforce: bool = True) -> dict:
    """A check that holds by construction (never counted as a claim); ``by`` says why it must hold.

    ``enforce=False`` for a fit diagnostic (a statement about a training number the
    approximate fit need not reproduce exactly): reported, never raised.

    >>> r = consistency("t", "b inside prior", 0.2, 0.21, "inside the prior", True, by="the grid lies in the prior")
    >>> r["kind"], r["note"]
    ('consistency', 'the grid lies in the prior')
    """
    if not by:
        raise ValueError("by must say why the check holds by construction")
    return comparison_row(artifact, quantity, paper, mtcal, statement, holds, band=band, prior_band=prior_band,
                          role=role, kind="consistency", note=by, ref=ref, enforce=enforce)


def comparison_table(rows: list[dict], digits: int = 4) -> pd.DataFrame:
    """Build the comparison table; float cells are rounded to ``digits`` for stable output."""
    df = pd.DataFrame(rows, columns=COMPARISON_COLUMNS)
    for col in ("mc_band", "prior_band", "kind", "note", "ref"):
        df[col] = df[col].fillna("")

    def fmt(x):
        if isinstance(x, (float, np.floating)):
            return f"{x:.{digits}f}"
        return x
    for col in ("paper", "mtcal"):
        df[col] = df[col].map(fmt)
    return df


def band_summary(table: pd.DataFrame) -> str:
    """``"paper inside our 95 % band: k of n"`` over rows with a band and a numeric paper value."""
    placed = table["paper_in_band"].dropna()
    return f"paper value inside the mtcal 95 % Monte Carlo band: {int(placed.sum())} of {len(placed)}"


def claims_summary(table: pd.DataFrame) -> str:
    """``"k of n claims hold"`` over the rows of kind ``claim`` (consistency rows are not claims)."""
    tested = table.loc[_kind(table) == "claim", "holds"].dropna()
    return f"{int(tested.astype(bool).sum())} of {len(tested)} claims hold"


def _kind(table: pd.DataFrame) -> pd.Series:
    if "kind" in table:
        return table["kind"].fillna("")
    return pd.Series(np.where(table["holds"].notna(), "claim", ""), index=table.index)


def describe(obj) -> pd.DataFrame:
    """Table of a scenario's fields: name, value, unit, source."""
    rows = []
    for f in fields(obj):
        v = getattr(obj, f.name)
        if hasattr(v, "__dataclass_fields__"):
            continue
        rows.append({"field": f.name, "value": str(v) if not isinstance(v, float) else f"{v:.6g}",
                     "unit": f.metadata.get("unit", ""), "source": f.metadata.get("source", "")})
    return pd.DataFrame(rows)


def band_record(artifact: str, quantity: str, paper_value: float, samples) -> dict:
    """Median and 95 % band of Monte Carlo ``samples`` (1-D, display unit) next to the paper's value.

    Returns a dict with ``artifact, quantity, paper, median, low, high,
    paper_in_band`` (floats and a bool); it is also a valid ``band=`` for
    :func:`mtcal.reporting.paper_numbers.comparison_row` (see :func:`band_row`).
    """
    x = np.asarray(samples, dtype=float)
    if x.ndim != 1 or x.size < 1:
        raise ValueError(f"samples must be a non-empty 1-D array (one value per trial), got shape {x.shape}")
    b = metrics.percentile_band(x)
    med, low, high, pv = float(b["median"]), float(b["low"]), float(b["high"]), float(paper_value)
    return {"artifact": artifact, "quantity": quantity, "paper": pv, "median": med, "low": low, "high": high,
            "paper_in_band": bool(low <= pv <= high)}


def band_row(record: dict, claim: str, holds: bool | None) -> dict:
    """Comparison row from a :func:`band_record`: MC median as the mtcal value, its 95 % band."""
    return comparison_row(record["artifact"], record["quantity"], record["paper"], record["median"],
                          claim, holds, band=record)


def band_text(record: dict, digits: int = 4) -> str:
    """``"<quantity>: MC median m [low, high] (paper p)"`` with fixed precision."""
    d = digits
    return (f"{record['quantity']}: MC median {record['median']:.{d}f} [{record['low']:.{d}f}, "
            f"{record['high']:.{d}f}] (paper {record['paper']:.{d}f})")


def at_paper_settings(values: dict, defaults: dict) -> bool:
    """True when every parameter in ``values`` equals its paper default in ``defaults``.

    A notebook passes its parameters-cell values and their defaults; the claims are
    then enforced (CI fails on a broken reproduction) only at the paper's settings,
    and merely reported in a what-if run. Run size (``SIZE``, trial counts) and the
    RNG seed are not scenario parameters and should not be passed.

    >>> at_paper_settings({"gyro_grade": "wang2023cja"}, {"gyro_grade": "wang2023cja"})
    True
    >>> at_paper_settings({"gyro_grade": "industrial"}, {"gyro_grade": "wang2023cja"})
    False
    """
    merge_parameters(values, defaults)  # rejects names not in defaults

    def same(a, b):
        try:
            return bool(np.all(np.asarray(a) == np.asarray(b))) and np.shape(a) == np.shape(b)
        except (TypeError, ValueError):
            return a == b
    return all(same(values[k], defaults[k]) for k in values)


def check_claims(table: pd.DataFrame, *, enforce: bool) -> str:
    """Evaluate every tested row of a comparison table; fail only when ``enforce``.

    Parameters
    ----------
    table : DataFrame
        Output of :func:`comparison_table`.
    enforce : bool
        True at the paper's settings: raise ``AssertionError`` listing each
        enforced row (``enforced`` True: claims we assert, consistency checks)
        that does not hold, so CI fails when a reproduction breaks. Claims
        reported as failing (``enforced`` False) are listed, never raised.
        False in a what-if run: never raise, return the report.

    Returns
    -------
    str
        ``"k of n claims hold"`` (kind ``claim``), one line per failing claim with
        its computed reason, and the consistency count when there are any.

    >>> t = comparison_table([comparison_row("a", "x", 1.0, 1.0, "x = 1", True),
    ...                       comparison_row("b", "y", 1.0, 2.0, "y = 1", False, note="y is 2")])
    >>> print(check_claims(t, enforce=False))
    1 of 2 claims hold; not holding:
      b | y | y = 1 | paper 1.0000 | mtcal 2.0000 | y is 2
    """
    kind = _kind(table)
    tested = table[table["holds"].notna() & (kind == "claim")]
    failing = tested[~tested["holds"].astype(bool)]
    text = f"{len(tested) - len(failing)} of {len(tested)} claims hold"
    if len(failing):
        text += "; not holding:\n" + "\n".join(
            f"  {r.artifact} | {r.quantity} | {r.claim} | paper {r.paper} | mtcal {r.mtcal}"
            + (f" | {r.note}" if getattr(r, "note", "") else "") for r in failing.itertuples())
    cons = table[table["holds"].notna() & (kind == "consistency")]
    if len(cons):
        n_ok = int(cons["holds"].astype(bool).sum())
        text += f"\nconsistency checks (true by construction, not claims): {n_ok} of {len(cons)} hold"
        bad = cons[~cons["holds"].astype(bool)]
        text += "".join(f"\n  not holding: {r.artifact} | {r.quantity} | {r.claim} | mtcal {r.mtcal} | {r.note}"
                        for r in bad.itertuples())
    own = table[table["holds"].notna() & (kind == "")]
    if len(own):
        n_ok = int(own["holds"].astype(bool).sum())
        text += f"\nour own findings: {n_ok} of {len(own)} hold"
    checked = table[table["holds"].notna()]
    if "enforced" in checked:
        enforced = checked["enforced"].fillna(True).astype(bool)
    else:
        enforced = pd.Series(True, index=checked.index)
    broken = checked[enforced & ~checked["holds"].astype(bool)]
    if enforce and len(broken):
        raise AssertionError("at the paper's settings every enforced claim and consistency check must hold; "
                             + "; ".join(f"{r.artifact} | {r.quantity}" for r in broken.itertuples()))
    return text


def role_summary(table: pd.DataFrame) -> str:
    """Paper-inside-band counts split by role (``heldout`` rows are the out-of-sample test).

    >>> t = comparison_table([comparison_row("a", "x", 1.0, 1.1, "", None, band=(0.9, 1.2)),
    ...                       comparison_row("b", "y", 1.0, 1.1, "", None, band=(1.05, 1.2), role="train")])
    >>> role_summary(t)
    'paper inside our 95 % band: train 0 of 1, heldout 1 of 1'
    """
    parts = []
    for role in ROLES:
        rows = table[(table["role"] == role) & table["paper_in_band"].notna()]
        if len(rows):
            parts.append(f"{role} {int(rows['paper_in_band'].astype(bool).sum())} of {len(rows)}")
    return "paper inside our 95 % band: " + (", ".join(parts) if parts else "no banded rows")


#: Former name of :func:`role_summary` (kept for the notebooks that call it).
prediction_summary = role_summary
