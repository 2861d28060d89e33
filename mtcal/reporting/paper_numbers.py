"""The papers' printed numbers, shipped inside the package (``mtcal/reporting/paper_data/*.csv``).

Values are kept as the strings the papers print (``load(..., as_text=True)``)
or parsed to numbers where a column is numeric. ``paper_data/README.md``
describes each file. The comparison of these numbers with ours lives in
:mod:`mtcal.reporting.compare`.

References
----------
.. [wang2023cja] Wang X., Zhao X., Zhou B., Wei Q., Zhang R., "Installation error
   calibration for MEMS angular measurement system in hypersonic wind tunnel",
   Chin. J. Aeronaut. 2023, doi:10.1016/j.cja.2022.12.006.
.. [tan2022] Tan Q., Cheng Y., Tang B., Liu X., Zhou H., Li Y., "Large-angle attitude
   measurement algorithm with pitch/roll coupling" (in Chinese), J. Terahertz Sci.
   Electron. Inf. Technol. 2022, 20(9):946–952.
.. [wang2022sensors] Wang C., Tu X., Chen Q., Yang Q., Fang T., "Movable Surface Rotation
   Angle Measurement System Using IMU", Sensors 2022, 22, 8996, doi:10.3390/s22228996.
"""

from __future__ import annotations

import os
from importlib import resources
from pathlib import Path

import numpy as np
import pandas as pd

__all__ = ["paper_dir", "available", "load", "value"]


def paper_dir() -> Path:
    """Folder with the papers' CSV files: ``$MTCAL_PAPER_DIR`` or the package data ``paper_data/``.

    >>> "wang2023cja_table01_positions" in available()
    True
    """
    env = os.environ.get("MTCAL_PAPER_DIR")
    path = Path(env) if env else Path(str(resources.files("mtcal.reporting") / "paper_data"))
    if not path.is_dir():
        raise FileNotFoundError(f"paper data folder not found: {path} (set MTCAL_PAPER_DIR)")
    return path


def available() -> list[str]:
    """Names (file stems) of every paper table, sorted."""
    return sorted(p.stem for p in paper_dir().glob("*.csv"))


def load(name: str, *, as_text: bool = False) -> pd.DataFrame:
    """Load one paper table by file stem, e.g. ``"wang2023cja_table01_positions"``.

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

    >>> value("wang2023cja_table06_aoa_sweep_roll_yaw_errors", "roll_after_deg", type="RMSE")  # doctest: +SKIP
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


