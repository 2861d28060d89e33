"""Paper-vs-mtcal comparison rows, Monte Carlo bands, and scenario tables for display.

Every notebook reports its results through :func:`comparison_table`, with the
columns ``artifact | quantity | paper | mtcal | mc_band | paper_in_band |
claim | holds`` (the band columns are filled where the mtcal number comes
from a Monte Carlo: median in ``mtcal``, 95 % interval in ``mc_band``).

>>> row = comparison_row("wang2023cja_table06", "roll RMSE (deg)", 0.009, 0.0071, "<= 0.01", True,
...                      band=(0.005, 0.010))
>>> row["paper_in_band"]
True
"""

from __future__ import annotations

from dataclasses import fields

import numpy as np
import pandas as pd

from mtcal.core import metrics
from mtcal.core.validate import merge_parameters

__all__ = ["COMPARISON_COLUMNS", "comparison_row", "comparison_table", "band_summary", "claims_summary",
           "band_record", "band_row", "band_text", "describe",
           "ROLES", "SOURCES", "at_paper_settings", "check_claims", "prediction_summary"]

COMPARISON_COLUMNS = ["artifact", "quantity", "paper", "mtcal", "mc_band", "paper_in_band", "claim", "holds",
                      "role", "source"]

#: What a row is: a number fitted to the paper (never a confirmation), a prediction
#: checked against a paper number it was not fitted to, our own finding, or an erratum.
ROLES = ("fitted", "predicted", "finding", "erratum")
#: Who makes the claim in the row.
SOURCES = ("paper claim", "mtcal finding")


def comparison_row(artifact: str, quantity: str, paper, mtcal, claim: str, holds: bool | None,
                   *, band=None, role: str = "predicted", source: str = "paper claim") -> dict:
    """One row of the paper-vs-mtcal table.

    Parameters
    ----------
    artifact, quantity : str
        Artifact ID (``"wang2023cja_table06"``) and what is compared, with its unit.
    paper, mtcal : float or str
        The paper's printed value and ours (for a Monte Carlo: our median).
    claim : str
        The paper's statement made testable.
    holds : bool or None
        Whether the claim holds in simulation (``None``: nothing tested).
    band : dict or (low, high), optional
        Monte Carlo 95 % band of the mtcal number (``metrics.percentile_band``
        output or a pair). The row then records the band as
        ``"[low, high]"`` and whether a numeric paper value lies inside it.
    role : {"fitted", "predicted", "finding", "erratum"}
        ``fitted``: the mtcal number was fitted to (or taken from) this paper
        number, so agreement is not a confirmation. ``predicted``: computed
        without using this number. ``finding``: a result of ours the paper does
        not state. ``erratum``: a computed check of a printed equation/number.
    source : {"paper claim", "mtcal finding"}
        Whose claim the ``claim`` column states.
    """
    if role not in ROLES:
        raise ValueError(f"role must be one of {ROLES}, got {role!r}")
    if source not in SOURCES:
        raise ValueError(f"source must be one of {SOURCES}, got {source!r}")
    if holds is not None and not isinstance(holds, (bool, np.bool_)):
        raise TypeError(f"holds must be bool or None, got {type(holds).__name__}")
    band_text, inside = "", None
    if band is not None:
        low, high = (band["low"], band["high"]) if isinstance(band, dict) else band
        low, high = float(low), float(high)
        if not (np.isfinite(low) and np.isfinite(high)) or low > high:
            raise ValueError(f"band must be a finite (low, high) with low <= high, got ({low}, {high})")
        band_text = f"[{low:.4g}, {high:.4g}]"
        try:
            inside = bool(low <= float(paper) <= high)
        except (TypeError, ValueError):
            inside = None  # the paper gives no number to place in the band
    return {"artifact": artifact, "quantity": quantity, "paper": paper, "mtcal": mtcal,
            "mc_band": band_text, "paper_in_band": inside, "claim": claim,
            "holds": None if holds is None else bool(holds), "role": role, "source": source}


def comparison_table(rows: list[dict], digits: int = 4) -> pd.DataFrame:
    """Build the comparison table; float cells are rounded to ``digits`` for stable output."""
    df = pd.DataFrame(rows, columns=COMPARISON_COLUMNS)
    df["mc_band"] = df["mc_band"].fillna("")

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
    """``"k of n claims hold"`` over the rows that test a claim."""
    tested = table["holds"].dropna()
    return f"{int(tested.sum())} of {len(tested)} claims hold"


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
    """Evaluate every tested claim of a comparison table; fail only when ``enforce``.

    Parameters
    ----------
    table : DataFrame
        Output of :func:`comparison_table`.
    enforce : bool
        True at the paper's settings: raise ``AssertionError`` listing each claim
        that does not hold (so CI fails when a reproduction breaks). False in a
        what-if run: never raise, return the report.

    Returns
    -------
    str
        ``"k of n claims hold"`` followed by one line per failing claim.

    >>> t = comparison_table([comparison_row("a", "x", 1.0, 1.0, "x = 1", True),
    ...                       comparison_row("b", "y", 1.0, 2.0, "y = 1", False)])
    >>> print(check_claims(t, enforce=False))
    1 of 2 claims hold; not holding:
      b | y | y = 1 | paper 1.0000 | mtcal 2.0000
    """
    tested = table[table["holds"].notna()]
    failing = tested[~tested["holds"].astype(bool)]
    text = f"{len(tested) - len(failing)} of {len(tested)} claims hold"
    if len(failing):
        text += "; not holding:\n" + "\n".join(
            f"  {r.artifact} | {r.quantity} | {r.claim} | paper {r.paper} | mtcal {r.mtcal}"
            for r in failing.itertuples())
    if enforce and len(failing):
        raise AssertionError("at the paper's settings every claim must hold; " + text)
    return text


def prediction_summary(table: pd.DataFrame) -> str:
    """Paper-inside-band counts split by role (``predicted`` rows are the out-of-sample test).

    >>> t = comparison_table([comparison_row("a", "x", 1.0, 1.1, "", None, band=(0.9, 1.2)),
    ...                       comparison_row("b", "y", 1.0, 1.1, "", None, band=(1.05, 1.2), role="fitted")])
    >>> prediction_summary(t)
    'paper inside our 95 % band: predicted 1 of 1, fitted 0 of 1'
    """
    parts = []
    for role in ("predicted", "fitted", "finding", "erratum"):
        rows = table[(table["role"] == role) & table["paper_in_band"].notna()]
        if len(rows):
            parts.append(f"{role} {int(rows['paper_in_band'].astype(bool).sum())} of {len(rows)}")
    return "paper inside our 95 % band: " + (", ".join(parts) if parts else "no banded rows")
