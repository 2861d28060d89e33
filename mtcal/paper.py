"""The papers' printed numbers (``data/paper/*.csv``) and the paper-vs-mtcal table.

Values are kept as the strings the papers print (``load(..., as_text=True)``)
or parsed to numbers where a column is numeric. Every notebook reports its
results through :func:`comparison_table`, with the columns
``artifact | quantity | paper | mtcal | mc_band | paper_in_band | claim | holds``
(the band columns are filled where the mtcal number comes from a Monte
Carlo: median in ``mtcal``, 95 % interval in ``mc_band``).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pandas as pd

__all__ = ["paper_dir", "available", "load", "value", "comparison_row", "comparison_table",
           "claims_summary", "band_summary", "COMPARISON_COLUMNS"]

COMPARISON_COLUMNS = ["artifact", "quantity", "paper", "mtcal", "mc_band", "paper_in_band", "claim", "holds"]


def paper_dir() -> Path:
    """Folder with the papers' CSV files: ``$MTCAL_PAPER_DIR`` or ``<repo>/data/paper``."""
    env = os.environ.get("MTCAL_PAPER_DIR")
    path = Path(env) if env else Path(__file__).resolve().parent.parent / "data" / "paper"
    if not path.is_dir():
        raise FileNotFoundError(f"paper data folder not found: {path} (set MTCAL_PAPER_DIR)")
    return path


def available() -> list[str]:
    """Names (file stems) of every paper table, sorted."""
    return sorted(p.stem for p in paper_dir().glob("*.csv"))


def load(name: str, *, as_text: bool = False) -> pd.DataFrame:
    """Load one paper table by file stem, e.g. ``"seed000_table01_positions"``.

    Parameters
    ----------
    name : str
        File stem (without ``.csv``); see :func:`available`.
    as_text : bool
        Keep every cell as the printed string (default: parse numeric columns).
    """
    if not isinstance(name, str):
        raise TypeError(f"name must be a str, got {type(name).__name__}")
    path = paper_dir() / f"{name.removesuffix('.csv')}.csv"
    if not path.is_file():
        raise ValueError(f"name must be one of the paper tables {available()}, got {name!r}")
    df = pd.read_csv(path, dtype=str, keep_default_na=False)
    if as_text:
        return df
    for col in df.columns:
        parsed = pd.to_numeric(df[col], errors="coerce")
        if parsed.notna().all() and len(df):
            df[col] = parsed
    return df


def value(name: str, column: str, **where) -> float:
    """One numeric cell of a paper table selected by equality on other columns.

    >>> value("seed000_table06_aoa_sweep_roll_yaw_errors", "roll_after_deg", type="RMSE")  # doctest: +SKIP
    """
    df = load(name)
    if column not in df.columns:
        raise ValueError(f"column must be one of {list(df.columns)}, got {column!r}")
    mask = np.ones(len(df), dtype=bool)
    for key, val in where.items():
        if key not in df.columns:
            raise ValueError(f"selector {key!r} must be one of {list(df.columns)}")
        mask &= (df[key] == val).to_numpy()
    if mask.sum() != 1:
        raise ValueError(f"selection {where} must match exactly one row of {name}, matched {mask.sum()}")
    return float(df.loc[mask, column].iloc[0])


def comparison_row(artifact: str, quantity: str, paper, mtcal, claim: str, holds: bool | None,
                   *, band=None) -> dict:
    """One row of the paper-vs-mtcal table.

    Parameters
    ----------
    artifact, quantity : str
        Artifact ID (``"T000-6"``) and what is compared, with its unit.
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
    """
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
            "holds": None if holds is None else bool(holds)}


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
