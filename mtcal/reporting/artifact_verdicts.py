"""One verdict per artifact (``data/verdicts.csv``), from the committed comparison tables and the catalogue.

Every figure and table of a paper that the artifact catalogue lists (``docs/artifacts.md``, rows whose
paper column reads ``<key> Fig. N`` or ``<key> Table N``) and every addition of ours (``<key> (ours:
slug)``, notebook 00's ``conventions/errata (ours: slug)``) gets one row, whatever the paper key — the
bookkeeping files (comparison tables, fidelity records and scores, benchmarks, this file) get none — so a
new study that saves its comparison table the standard way (``data/<key>_<topic>_comparison.csv``,
:func:`mtcal.reporting.compare.comparison_table`) gets its rows without code here.

The evidence of an artifact is read from every comparison table row whose ``artifact`` is its id:

* **numbers**: rows with ``role`` ``heldout``, a numeric paper value and a band (``paper_in_band``
  not empty), not a tested row: ``numbers_compared``, of them ``numbers_inside`` inside our band;
* **claims**: rows of ``kind`` ``claim`` with a verdict (``holds``): ``claims_holding``,
  ``claims_failing``. In-sample checks, consistency checks, our own findings and numbers a fit read
  or a setting was chosen against (``train``, ``tuned``) are no evidence: they enter only the cause.

The rule (:func:`verdict`, stated once in ``docs/conventions.md``, "One verdict per artifact"):

* ``not comparable``: no held-out number with a band and no claim tested;
* ``reproduced``: every held-out number inside its band and every claim holding;
* ``not reproduced``: no held-out number inside and no claim holding;
* ``partly reproduced``: anything else.

``cause`` is one computed line: the held-out number farthest outside its band (in band widths), the
failing claims with their computed reason, how many of the held-out numbers the prior predictive
(nothing fitted) puts inside as well, whether the claims are tested on thresholds of ours (the
paper states none), and — whatever the verdict, since they are no evidence — the in-sample numbers
inside and checks holding and every failing check of another kind (in-sample, consistency, erratum,
finding) with its reason; "nothing compared" only when there is none of these.

References
----------
Issue #33 item 7.

Examples
--------
>>> verdict(4, 4, 2, 0), verdict(4, 3, 2, 0), verdict(4, 0, 0, 1), verdict(0, 0, 0, 0)
('reproduced', 'partly reproduced', 'not reproduced', 'not comparable')
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from .compare import cell_text, is_missing

__all__ = ["VERDICTS", "VERDICT_COLUMNS", "verdict", "has_verdict", "paper_artifacts", "artifact_rows", "write_verdicts"]

#: The four verdicts, best first.
VERDICTS = ("reproduced", "partly reproduced", "not reproduced", "not comparable")
#: Columns of ``data/verdicts.csv`` (rendered by the documentation site: keep the names).
VERDICT_COLUMNS = ["artifact_id", "paper", "paper_item", "verdict", "numbers_compared", "numbers_inside",
                   "claims_holding", "claims_failing", "cause", "notebook_section"]
_PAPER_ITEM = re.compile(r"^(?P<key>[a-z]+\d{4}[a-z]*) (?P<item>(Fig\.|Table) \d+)$")
#: our additions: ``<key> (ours: slug)`` and notebook 00's ``conventions/errata (ours: slug)``
_EXTRA_ITEM = re.compile(r"^(?P<key>[a-z]+\d{4}[a-z]*|conventions)(?:/errata)? \((?P<item>ours: [^)]+)\)$")
_ROW = re.compile(r"^\|\s*`(?P<file>[^`]+)`\s*\|\s*(?P<paper>[^|]*?)\s*\|\s*(?P<section>[^|]*?)\s*\|")


def verdict(numbers_compared: int, numbers_inside: int, claims_holding: int, claims_failing: int) -> str:
    """The verdict of one artifact from its held-out evidence (rule in the module docstring).

    Raises
    ------
    ValueError
        Negative counts, or more numbers inside than compared.

    >>> verdict(0, 0, 1, 0), verdict(0, 0, 1, 1), verdict(3, 0, 0, 2)
    ('reproduced', 'partly reproduced', 'not reproduced')
    """
    counts = (numbers_compared, numbers_inside, claims_holding, claims_failing)
    if any(int(c) != c or c < 0 for c in counts):
        raise ValueError(f"counts must be non-negative integers, got {counts}")
    if numbers_inside > numbers_compared:
        raise ValueError(f"numbers_inside ({numbers_inside}) must not exceed numbers_compared ({numbers_compared})")
    if numbers_compared + claims_holding + claims_failing == 0:
        return "not comparable"
    if numbers_inside == numbers_compared and claims_failing == 0:
        return "reproduced"
    if numbers_inside == 0 and claims_holding == 0:
        return "not reproduced"
    return "partly reproduced"


def has_verdict(paper_column: str) -> bool:
    """True for a catalogue row that gets a verdict: a paper's figure or table, or an addition of ours.

    >>> has_verdict("abc2020 Table 2"), has_verdict("abc2020 (ours: y)"), has_verdict("paper vs mtcal table")
    (True, True, False)
    """
    text = str(paper_column).strip()
    return bool(_PAPER_ITEM.match(text) or _EXTRA_ITEM.match(text))


def paper_artifacts(catalogue_md: str | Path) -> pd.DataFrame:
    """The artifacts of the catalogue: ``artifact_id, paper, paper_item, notebook_section``.

    The papers' figures and tables (paper item ``Table 2``) and our additions (paper item ``ours: y``).

    One row per artifact id (a figure and its table share one), in catalogue order.

    >>> import tempfile, os
    >>> md = ("| file | paper | notebook § section | produced by |\\n|---|---|---|---|\\n"
    ...       "| `data/abc2020_table02.csv` | abc2020 Table 2 | `10_abc` § abc2020_table02 — x | `f` |\\n"
    ...       "| `data/abc2020_extra_y.csv` | abc2020 (ours: y) | `10_abc` § y | `g` |\\n")
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = Path(d) / "a.md"; _ = p.write_text(md)
    ...     paper_artifacts(p).iloc[0].tolist()
    ['abc2020_table02', 'abc2020', 'Table 2', '`10_abc` § abc2020_table02 — x']
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = Path(d) / "a.md"; _ = p.write_text(md)
    ...     paper_artifacts(p).iloc[1].tolist()
    ['abc2020_extra_y', 'abc2020', 'ours: y', '`10_abc` § y']
    """
    rows = {}
    for line in Path(catalogue_md).read_text(encoding="utf-8").splitlines():
        m = _ROW.match(line)
        if not m:
            continue
        p = _PAPER_ITEM.match(m["paper"]) or _EXTRA_ITEM.match(m["paper"])
        if not p:
            continue
        ident = Path(m["file"]).stem
        rows.setdefault(ident, {"artifact_id": ident, "paper": p["key"], "paper_item": p["item"],
                                "notebook_section": m["section"]})
    return pd.DataFrame(list(rows.values()), columns=["artifact_id", "paper", "paper_item", "notebook_section"])


def _bool(v) -> bool | None:
    if is_missing(v):
        return None
    return str(v).strip().lower() in ("true", "1", "1.0")


def _float(v) -> float:
    try:
        return float(v)
    except (TypeError, ValueError):
        return np.nan


def _evidence(rows: pd.DataFrame) -> dict:
    """Counts and the cause of one artifact's comparison rows."""
    kind = rows["kind"].map(cell_text) if "kind" in rows else pd.Series("", index=rows.index)
    holds = rows["holds"].map(_bool)
    inside = rows["paper_in_band"].map(_bool)
    tested = holds.notna()
    numbers = rows[(rows["role"] == "heldout") & inside.notna() & ~tested]
    n_inside = int(inside[numbers.index].astype(bool).sum())
    claims = rows[(kind == "claim") & tested]
    c_hold = int(holds[claims.index].astype(bool).sum())
    parts = []
    outside = numbers[~inside[numbers.index].astype(bool)]
    if len(outside):
        lo, hi, x = (outside[c].map(_float) for c in ("mc_low", "mc_high", "paper"))
        miss = np.maximum(lo - x, x - hi) / np.maximum(hi - lo, 1e-12)
        r = outside.loc[miss.idxmax()]
        parts.append(f"{len(outside)} held-out outside; farthest {cell_text(r['quantity'])}: paper {x[r.name]:.4g}, "
                     f"ours {_float(r['mtcal']):.4g} [{lo[r.name]:.4g}, {hi[r.name]:.4g}] "
                     f"({miss[r.name]:.1f} band widths out)")
    if len(numbers) and "prior_in_band" in rows:    # what the fit adds: the prior predictive on the same numbers
        prior = rows.loc[numbers.index, "prior_in_band"].map(_bool)
        if prior.notna().all():
            parts.append(f"prior predictive (nothing fitted): {int(prior.astype(bool).sum())} of {len(prior)} "
                         f"held-out inside")
    failing: dict[str, list] = {}                 # one line per claim text (rows of one claim kept together)
    for r in claims[~holds[claims.index].astype(bool)].itertuples():
        failing.setdefault(cell_text(r.claim), []).append(r)
    for claim, group in failing.items():
        why = cell_text(getattr(group[0], "note", ""))
        if len(group) == 1:
            parts.append(f"fails: {claim}" + (f" ({why})" if why else ""))
        else:
            names = ", ".join(cell_text(g.quantity).split(":")[0] for g in group)
            parts.append(f"fails in {len(group)} rows ({names}): {claim}" + (f" (first: {why})" if why else ""))
    # ours: a claim of role finding, or one whose statement names its threshold or tolerance as mtcal's
    own_threshold = int(((claims["role"] == "finding")
                         | claims["claim"].map(cell_text).str.contains("mtcal threshold|mtcal tolerance")).sum())
    if own_threshold:
        parts.append("every claim is tested on an mtcal threshold (the paper states none)" if own_threshold == len(claims)
                     else f"{own_threshold} of {len(claims)} claims are tested on mtcal thresholds (the paper states none)")
    # not evidence, shown whatever the verdict: the in-sample numbers and checks, every failing check of any kind
    own = rows[rows["role"].isin(("train", "tuned")) & inside.notna() & ~tested]
    checks = rows[(kind == "in-sample") & tested]
    counts = ([f"{int(inside[own.index].astype(bool).sum())} of {len(own)} numbers inside"] if len(own) else []) + (
        [f"{int(holds[checks.index].astype(bool).sum())} of {len(checks)} in-sample checks hold"] if len(checks) else [])
    if counts:
        parts.append(("in-sample only (fitted or tuned on): " if not len(numbers) and not len(claims)
                      else "in-sample (fitted or tuned on): ") + "; ".join(counts))
    other = rows[tested & (kind != "claim") & ~holds.astype(bool)]
    label = pd.Series([cell_text(k) or cell_text(r) or "check" for k, r in zip(kind[other.index], other["role"])],
                      index=other.index)
    for (k, claim), group in other.groupby([label, other["claim"].map(cell_text)], sort=False):
        why = cell_text(group["note"].iloc[0]) if "note" in group else ""
        parts.append(f"{k} check fails{f' in {len(group)} rows' if len(group) > 1 else ''}: {claim}"
                     + (f" ({why})" if why else ""))
    if not len(numbers) and not len(claims) and not counts and not len(other):
        parts.append("no held-out paper number or claim compared (our own findings or figure only)")
    return {"numbers_compared": len(numbers), "numbers_inside": n_inside, "claims_holding": c_hold,
            "claims_failing": len(claims) - c_hold, "cause": "; ".join(parts)}


def _comparisons(data_dir: Path) -> pd.DataFrame:
    parts = [pd.read_csv(p, dtype=str, keep_default_na=False, na_values=[""])
             for p in sorted(Path(data_dir).glob("*_comparison.csv"))]
    parts = [p for p in parts if {"artifact", "role", "paper_in_band", "holds"} <= set(p.columns)]
    return pd.concat(parts, ignore_index=True) if parts else pd.DataFrame(
        columns=["artifact", "role", "paper_in_band", "holds", "kind", "quantity", "paper", "mtcal", "mc_low",
                 "mc_high", "claim", "note"])


def artifact_rows(comparisons: pd.DataFrame, artifacts: pd.DataFrame) -> pd.DataFrame:
    """One verdict row (:data:`VERDICT_COLUMNS`) per artifact of ``artifacts`` (:func:`paper_artifacts`)."""
    out = []
    for a in artifacts.itertuples(index=False):
        rows = comparisons[comparisons["artifact"] == a.artifact_id]
        ev = _evidence(rows) if len(rows) else {"numbers_compared": 0, "numbers_inside": 0, "claims_holding": 0,
                                                 "claims_failing": 0,
                                                 "cause": "no comparison row (figure or table shown, no paper "
                                                          "number compared)"}
        out.append({"artifact_id": a.artifact_id, "paper": a.paper, "paper_item": a.paper_item,
                    "verdict": verdict(ev["numbers_compared"], ev["numbers_inside"], ev["claims_holding"],
                                       ev["claims_failing"]),
                    **{k: ev[k] for k in ("numbers_compared", "numbers_inside", "claims_holding", "claims_failing",
                                          "cause")},
                    "notebook_section": a.notebook_section})
    return pd.DataFrame(out, columns=VERDICT_COLUMNS)


def write_verdicts(data_dir: str | Path, catalogue_md: str | Path) -> Path:
    """Write ``<data_dir>/verdicts.csv`` from ``<data_dir>/*_comparison.csv`` and the catalogue (byte-stable)."""
    data_dir = Path(data_dir)
    table = artifact_rows(_comparisons(data_dir), paper_artifacts(catalogue_md))
    path = data_dir / "verdicts.csv"
    table.to_csv(path, index=False, lineterminator="\n")
    return path


def main(argv: list[str] | None = None) -> int:
    """``python -m mtcal.reporting.artifact_verdicts DATA_FOLDER CATALOGUE_MD``: write ``verdicts.csv``."""
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 2:
        print("mtcal: error: usage: python -m mtcal.reporting.artifact_verdicts DATA_FOLDER CATALOGUE_MD",
              file=sys.stderr)
        return 2
    for name, p in (("DATA_FOLDER", argv[0]), ("CATALOGUE_MD", argv[1])):
        if not Path(p).exists():
            print(f"mtcal: error: {name} {p} does not exist", file=sys.stderr)
            return 2
    path = write_verdicts(argv[0], argv[1])
    counts = pd.read_csv(path)["verdict"].value_counts()
    print(f"wrote {path}: " + ", ".join(f"{v} {int(counts.get(v, 0))}" for v in VERDICTS))
    return 0


if __name__ == "__main__":
    sys.exit(main())
