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
.. [broad2021] Laidig D., Caruso M., Cereatti A., Seel T., "BROAD — A Benchmark for Robust Inertial
   Orientation Estimation", Data 2021, 6(7):72, doi:10.3390/data6070072 (published per-trial RMSE of its
   Madgwick/Mahony case study, ``datasets/broad2021/published``).
"""

from __future__ import annotations

import functools
import io
import os
import re
from importlib import resources
from pathlib import Path

import numpy as np
import pandas as pd

__all__ = ["paper_dir", "available", "load", "value", "KEYS", "SPLIT_ROLES", "SPLIT_COLUMNS", "NON_NUMBER_COLUMNS",
           "is_printed_number", "printed_cells", "paper_tables", "split", "training", "heldout"]

#: The paper keys (file-name prefixes in ``paper_data``): three papers and the BROAD benchmark.
KEYS = ("wang2023cja", "tan2022", "wang2022sensors", "broad2021")
#: Roles of a printed number in the pre-registered split (``<key>_split.csv``).
SPLIT_ROLES = ("train", "heldout", "input", "erratum", "not-compared")
#: Columns of a split file.
SPLIT_COLUMNS = ["file", "row", "column", "role", "reason"]
#: Roles whose ``reason`` must not be empty.
_REASON_REQUIRED = ("input", "erratum", "not-compared")
#: Columns never holding printed numbers: the row ordinal and our own annotations / labels.
NON_NUMBER_COLUMNS = frozenset({"row_index", "notes", "my_check", "my_check_against_tables", "quote", "source",
                                "location", "extracted_cell_text", "unit_as_extracted", "claim_id"})
# a cell is "numeric-looking" when it has a digit and only digits, signs, decimal points, exponents,
# intervals and pi: 8.006, -0.013, 10^-4, ±5, 0-1, (-π/2, π/2), 1e-05; or nan (written by the leak test)
_NUMBER_RE = re.compile(r"[\s\d.+\-−±^()π/,eE]*\d[\s\d.+\-−±^()π/,eE]*|[+-]?(nan|NaN|inf)")


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
    return _parsed(path.read_bytes(), as_text).copy()


@functools.lru_cache(maxsize=512)
def _parsed(content: bytes, as_text: bool) -> pd.DataFrame:
    """One CSV's table, parsed once per distinct file content (a notebook reads the same tables hundreds of
    times; keyed on the bytes, not the file's time stamp, so an edited file is never served stale)."""
    df = pd.read_csv(io.BytesIO(content), dtype=str, keep_default_na=False)
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




def is_printed_number(column: str, text: str) -> bool:
    """Whether one cell of a paper CSV is a printed number (the mechanical rule of ``paper_data/README.md``).

    A cell is a printed number when its column is not one of :data:`NON_NUMBER_COLUMNS`
    (row ordinal, annotations) and its stripped text is non-empty and numeric-looking:
    it contains a digit and only digits, signs, ``.``, ``^``, ``±``, ``π``, ``/``, ``,``,
    ``e``/``E``, parentheses and spaces (or is ``nan``/``inf``, which only the leak test
    writes). Label columns (``Test 1``, ``Bv1``, ``group_1``) contain
    letters and are therefore never numbers.

    >>> is_printed_number("value", "10^-4"), is_printed_number("value", "Bv1"), is_printed_number("row_index", "3")
    (True, False, False)
    """
    text = str(text).strip()
    return column not in NON_NUMBER_COLUMNS and bool(text) and _NUMBER_RE.fullmatch(text) is not None


def paper_tables(key: str) -> list[str]:
    """Stems of one paper's CSV files (``<key>_*.csv``), the split file excluded, sorted.

    >>> paper_tables("tan2022")
    ['tan2022_params']
    """
    if key not in KEYS:
        raise ValueError(f"key must be one of {KEYS}, got {key!r}")
    return [n for n in available() if n.startswith(f"{key}_") and not n.endswith("_split")]


def printed_cells(name: str) -> pd.DataFrame:
    """Every printed number of one paper CSV: columns ``file, row, column, text`` (``row`` 1-based).

    >>> printed_cells("wang2022sensors_table05_rmse").shape
    (18, 4)
    """
    df = load(name, as_text=True)
    rows = [{"file": name, "row": i + 1, "column": col, "text": v}
            for col in df.columns for i, v in enumerate(df[col]) if is_printed_number(col, v)]
    return pd.DataFrame(rows, columns=["file", "row", "column", "text"])


def split(key: str) -> pd.DataFrame:
    """The pre-registered split of one paper's printed numbers, validated.

    Parameters
    ----------
    key : {"wang2023cja", "tan2022", "wang2022sensors"}
        Paper key; reads ``paper_data/<key>_split.csv``.

    Returns
    -------
    DataFrame
        Columns ``file, row, column, role, reason, text`` (``text``: the printed
        string), one row per printed number, in the split file's order.

    Raises
    ------
    ValueError
        Unknown role, duplicate cell, a printed number missing from the split, a
        split row naming no printed number (extra), or an empty reason where
        one is required -- each naming the file, row and column.

    References
    ----------
    Issue #21 item 1 (a pre-registered split of every printed number).

    >>> s = split("wang2022sensors")
    >>> int((s["role"] == "heldout").sum()), list(s.columns)
    (8, ['file', 'row', 'column', 'role', 'reason', 'text'])
    """
    if key not in KEYS:
        raise ValueError(f"key must be one of {KEYS}, got {key!r}")
    path = paper_dir() / f"{key}_split.csv"
    if not path.is_file():
        raise ValueError(f"split file not found: {path}")
    sp = pd.read_csv(path, dtype=str, keep_default_na=False)
    if list(sp.columns) != SPLIT_COLUMNS:
        raise ValueError(f"{path.name}: columns must be {SPLIT_COLUMNS}, got {list(sp.columns)}")
    sp["row"] = pd.to_numeric(sp["row"], errors="coerce")
    for r in sp.itertuples():
        where = f"{path.name}: {r.file} row {r.row} column {r.column}"
        if r.role not in SPLIT_ROLES:
            raise ValueError(f"{where}: role must be one of {SPLIT_ROLES}, got {r.role!r}")
        if r.role in _REASON_REQUIRED and not r.reason.strip():
            raise ValueError(f"{where}: role {r.role!r} needs a reason")
    dup = sp.duplicated(["file", "row", "column"], keep=False)
    if dup.any():
        r = sp[dup].iloc[0]
        raise ValueError(f"{path.name}: duplicate cell {r.file} row {r.row} column {r.column}")
    cells = pd.concat([printed_cells(n) for n in paper_tables(key)], ignore_index=True)
    merged = sp.merge(cells, on=["file", "row", "column"], how="outer", indicator=True)
    extra = merged[merged["_merge"] == "left_only"]
    if len(extra):
        r = extra.iloc[0]
        raise ValueError(f"{path.name}: extra cell {r.file} row {r.row} column {r.column} is not a printed number")
    missing = merged[merged["_merge"] == "right_only"]
    if len(missing):
        r = missing.iloc[0]
        raise ValueError(f"{path.name}: missing cell {r.file} row {int(r.row)} column {r.column} "
                         f"(printed {r.text!r}) has no role")
    out = sp.merge(cells, on=["file", "row", "column"], how="left")
    out["row"] = out["row"].astype(int)
    return out[SPLIT_COLUMNS + ["text"]]


def training(key: str) -> dict[str, pd.DataFrame]:
    """The paper's tables as fitting code may see them: only ``train`` and ``input`` numbers.

    The only loader a fit (``studies/*/error_model.py``, ``studies/*/runs.py``) may use.
    Every printed number whose split role is not ``train`` or ``input`` is replaced by
    NaN; labels and annotations are kept. Numeric columns are parsed as in :func:`load`
    (after masking), so a masked column stays numeric.

    Parameters
    ----------
    key : {"wang2023cja", "tan2022", "wang2022sensors"}

    Returns
    -------
    dict of str -> DataFrame
        One table per file stem of the paper (:func:`paper_tables`).

    >>> t = training("wang2022sensors")["wang2022sensors_table05_rmse"]
    >>> bool(t["rmse_static_deg"].isna().any())
    True
    """
    sp = split(key)
    out = {}
    for name in paper_tables(key):
        df = load(name, as_text=True).astype(object)
        hide = sp[(sp["file"] == name) & ~sp["role"].isin(("train", "input"))]
        for r in hide.itertuples():
            df.at[r.row - 1, r.column] = np.nan
        for col in df.columns:
            if not any(is_printed_number(col, v) for v in df[col] if isinstance(v, str)):
                continue
            parsed = pd.to_numeric(df[col], errors="coerce")
            if (parsed.notna() | df[col].isna()).all() and len(df):
                df[col] = parsed.astype(float)
        out[name] = df
    return out


def heldout(key: str) -> pd.DataFrame:
    """The held-out printed numbers of one paper (comparison layer only, never a fit).

    Returns
    -------
    DataFrame
        Columns ``file, row, column, text, value`` (``value``: float, NaN when the
        printed text is not a plain number), one row per ``heldout`` cell.

    >>> h = heldout("wang2022sensors")
    >>> bool((h["file"] == "wang2022sensors_table05_rmse").any())
    True
    """
    sp = split(key)
    h = sp[sp["role"] == "heldout"][["file", "row", "column", "text"]].reset_index(drop=True)
    h["value"] = pd.to_numeric(h["text"], errors="coerce").astype(float)
    return h
