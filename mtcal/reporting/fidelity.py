"""Fidelity scores of the held-out (and, apart, the tuned) paper numbers: calibration and sharpness of our bands.

For every held-out printed number with a 95 % band (a row of
:func:`mtcal.reporting.compare.comparison_table` with ``role == "heldout"``, a
numeric ``paper`` value and band ends ``mc_low/mc_high`` or
``prior_low/prior_high``), two predictive distributions are scored:
``fitted`` (posterior predictive: each trial's parameters drawn from the fitted
posterior) and ``prior`` (prior predictive: parameters drawn from the prior, the
baseline). Per baseline:

* ``n`` held-out numbers with a band, ``inside`` of them inside the band, the
  coverage ``inside / n`` with its **Wilson score** 95 % interval
  (:func:`mtcal.reporting.binomial.wilson_interval`, re-exported here);
* the median band width relative to ``|paper value|``;
* the interval score (Gneiting & Raftery 2007, Eq 43, α = 0.05,
  :func:`interval_score`) relative to ``|paper value|``: mean and median;
* ``within_25pct``: paper values within ±25 % of our median (``|x − m| ≤ 0.25 |m|``).

Relative measures skip paper values equal to 0 (no scale). The same scores are computed, in a row of
their own (``role`` ``tuned``), for the ``tuned`` numbers: no fit reads them, but a mechanism or
setting was chosen while comparing with them, so they are in-sample -- shown beside the held-out
scores, never pooled with them (:data:`SCORED_ROLES`).

Each record carries the draw count and kind of both bands (``fitted_draws, fitted_kind,
prior_draws, prior_kind``: a ``"95 % band"`` from >= ``metrics.MIN_BAND_DRAWS`` draws, or a
``"range"`` with its count); the table is audited (:func:`mtcal.reporting.compare.check_bands`)
before it is scored, so no score rests on a "95 % band" of too few draws.

:func:`score_block` is the text every study notebook ends with; :func:`write_scores`
writes one notebook's per-number records to ``data/fidelity_records_<notebook>.csv``
and rewrites the per-paper and overall scores ``data/fidelity_scores.csv``
(:func:`aggregate_scores`, byte-stable, also run by ``make reproduce`` after all
notebooks).

References
----------
Gneiting T., Raftery A. E., "Strictly proper scoring rules, prediction, and
estimation", J. Am. Stat. Assoc. 2007, 102(477):359–378, Eq (43).
Wilson E. B., "Probable inference, the law of succession, and statistical
inference", J. Am. Stat. Assoc. 1927, 22(158):209–212.

Examples
--------
>>> from mtcal.reporting.compare import comparison_row, comparison_table
>>> band = lambda lo, hi: {"low": lo, "high": hi, "n": 1000, "kind": "95 % band"}
>>> t = comparison_table([comparison_row("a", "x", 1.0, 1.1, "", None, band=band(0.9, 1.2), prior_band=band(0.0, 5.0)),
...                       comparison_row("a", "y", 2.0, 1.0, "", None, band=band(0.5, 1.5), prior_band=band(0.0, 5.0))])
>>> s = score(t, "fitted")
>>> s["n"], s["inside"], s["within_25pct"]
(2, 1, 1)
"""

from __future__ import annotations

import os
import re
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from . import paper_numbers
from .binomial import wilson_interval  # re-exported: the coverage interval of the scores
from .compare import cell_text, check_bands, draw_count
from .output import output_dir

__all__ = ["BASELINES", "SCORED_ROLES", "SCORE_COLUMNS", "RECORD_COLUMNS", "wilson_interval", "interval_score", "score",
           "score_records", "score_block", "aggregate", "within_25pct", "write_scores", "aggregate_scores",
           "quantile_mc_se", "RECORDS_PREFIX", "CV_ROLE", "CV_BASELINES", "CV_PREFIX", "CV_RECORD_COLUMNS",
           "write_cv_records"]

#: Predictive distributions scored: posterior predictive and prior predictive.
BASELINES = ("fitted", "prior")
#: Split roles scored, each on its own: the out-of-sample test and the in-sample tuned numbers.
SCORED_ROLES = ("heldout", "tuned")
#: Per-notebook records files: ``data/fidelity_records_<notebook>.csv``.
RECORDS_PREFIX = "fidelity_records_"
#: Per-number record columns (``data/fidelity_records_<notebook>.csv``).
RECORD_COLUMNS = ["notebook", "paper_key", "artifact", "quantity", "ref", "paper_value", "fitted_median",
                  "fitted_low", "fitted_high", "prior_median", "prior_low", "prior_high", "fitted_draws",
                  "fitted_kind", "prior_draws", "prior_kind", "role"]
#: Cross-validation: role of its rows in the scores, the bands it scores (the model, the prior predictive and a
#: band with no physics), its per-number records ``data/fidelity_cv_<notebook>.csv`` and their columns.
CV_ROLE = "cv-heldout"
CV_BASELINES = ("fitted", "prior", "no-physics")
CV_PREFIX = "fidelity_cv_"
CV_RECORD_COLUMNS = (["notebook", "paper_key", "artifact", "quantity", "ref", "paper_value"]
                     + [f"{b}_{c}" for b in CV_BASELINES for c in ("median", "low", "high")] + ["draws"])
#: Score columns (``data/fidelity_scores.csv``).
SCORE_COLUMNS = ["scope", "role", "baseline", "n", "inside", "coverage", "coverage_low", "coverage_high",
                 "median_rel_width", "mean_rel_interval_score", "median_rel_interval_score", "within_25pct"]
_ALPHA = 0.05


def interval_score(low, high, x, alpha: float = _ALPHA) -> np.ndarray:
    """Interval score of central ``(1 − alpha)`` intervals (Gneiting & Raftery 2007, Eq 43).

    ``IS = (u − l) + (2/α)(l − x)·1[x < l] + (2/α)(x − u)·1[x > u]`` (same unit as ``x``;
    smaller is better; width plus a penalty for missing).

    Parameters
    ----------
    low, high, x : array_like (n,)
        Interval ends and observed (paper) values, broadcastable, ``low <= high``.
    alpha : float
        1 − nominal coverage, in (0, 1).

    >>> interval_score([0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [0.5, -1.0, 3.0]).tolist()
    [1.0, 41.0, 81.0]
    """
    lo, hi, xx = (np.asarray(v, dtype=float) for v in (low, high, x))
    if not 0 < alpha < 1:
        raise ValueError(f"alpha must be in (0, 1), got {alpha}")
    if np.any(lo > hi):
        raise ValueError("interval score needs low <= high for every interval")
    return (hi - lo) + (2 / alpha) * (lo - xx) * (xx < lo) + (2 / alpha) * (xx - hi) * (xx > hi)


def quantile_mc_se(samples, q: float, n_boot: int = 200, seed: int = 0) -> float:
    """Monte Carlo standard error of the ``q`` quantile of ``samples`` (bootstrap, ``n_boot`` resamples).

    >>> se = quantile_mc_se(np.linspace(0.0, 1.0, 1001), 0.975)
    >>> 0.0 < se < 0.02
    True
    """
    from mtcal.core.rng import stream_rng

    x = np.asarray(samples, dtype=float).ravel()
    if x.size < 2 or not np.all(np.isfinite(x)):
        raise ValueError(f"samples must be >= 2 finite values, got {x.size}")
    if not 0 < q < 1:
        raise ValueError(f"q must be in (0, 1), got {q}")
    rng = stream_rng(seed, 2107)
    idx = rng.integers(0, x.size, size=(int(n_boot), x.size))
    return float(np.std(np.quantile(x[idx], q, axis=1), ddof=1))


def _numeric(v) -> float:
    try:
        return float(v)
    except (TypeError, ValueError):
        return np.nan


def score_records(table: pd.DataFrame, paper_key: str, notebook: str) -> pd.DataFrame:
    """Per-number records of the held-out and tuned rows of a comparison table (:data:`RECORD_COLUMNS`).

    Only rows with ``role`` in :data:`SCORED_ROLES`, a numeric paper value and at least one band are kept.
    """
    if paper_key not in paper_numbers.KEYS:
        raise ValueError(f"paper_key must be one of {paper_numbers.KEYS}, got {paper_key!r}")
    if not isinstance(notebook, str) or not re.fullmatch(r"[A-Za-z0-9_]+", notebook):
        raise ValueError(f"notebook must be a non-empty str of letters, digits and '_' (a notebook stem), "
                         f"got {notebook!r}")
    return _records(table, paper_key, notebook)


def _records(table: pd.DataFrame, paper_key: str = "", notebook: str = "") -> pd.DataFrame:
    missing = {"role", "paper", "mtcal", "mc_low", "mc_high", "prior_low", "prior_high"} - set(table.columns)
    if missing:
        raise ValueError(f"table is not a comparison table (missing columns {sorted(missing)})")
    check_bands(table)
    rows = []
    for r in table[table["role"].isin(SCORED_ROLES)].to_dict("records"):
        x = _numeric(r["paper"])
        has_band = np.isfinite(_numeric(r["mc_low"])) or np.isfinite(_numeric(r["prior_low"]))
        if not np.isfinite(x) or not has_band:
            continue
        rows.append({"notebook": notebook, "paper_key": paper_key, "artifact": r["artifact"],
                     "quantity": r["quantity"], "ref": r.get("ref", ""), "paper_value": x,
                     "fitted_median": _numeric(r["mtcal"]), "fitted_low": _numeric(r["mc_low"]),
                     "fitted_high": _numeric(r["mc_high"]), "prior_median": _numeric(r.get("prior_median")),
                     "prior_low": _numeric(r["prior_low"]), "prior_high": _numeric(r["prior_high"]),
                     "fitted_draws": draw_count(r.get("mc_draws")), "fitted_kind": cell_text(r.get("mc_kind")),
                     "prior_draws": draw_count(r.get("prior_draws")), "prior_kind": cell_text(r.get("prior_kind")),
                     "role": r["role"]})
    out = pd.DataFrame(rows, columns=RECORD_COLUMNS)
    for col in ("fitted_draws", "prior_draws"):
        out[col] = out[col].astype("Int64")
    return out


def within_25pct(paper, median):
    """Whether each paper value lies within ±25 % of our median: ``|x − m| ≤ 0.25 |m|`` (False for a NaN median).

    Parameters
    ----------
    paper, median : float or array_like
        Paper values ``x`` and our medians ``m`` (broadcast).

    Returns
    -------
    bool or ndarray of bool

    Examples
    --------
    >>> within_25pct(1.0, 1.1), within_25pct(2.0, 1.0), within_25pct([0.0, 1.0], [0.0, np.nan]).tolist()
    (True, False, [True, False])
    """
    x, m = np.asarray(paper, dtype=float), np.asarray(median, dtype=float)
    ok = np.isfinite(m) & (np.abs(x - m) <= 0.25 * np.abs(m))
    return bool(ok) if ok.ndim == 0 else ok


def aggregate(records: pd.DataFrame, baseline: str) -> dict:
    """Scores of per-number records for one baseline (keys: :data:`SCORE_COLUMNS` without scope/baseline)."""
    if baseline not in CV_BASELINES:
        raise ValueError(f"baseline must be one of {CV_BASELINES}, got {baseline!r}")
    lo, hi, med = (records[f"{baseline}_{c}"].to_numpy(float) for c in ("low", "high", "median"))
    x = records["paper_value"].to_numpy(float)
    ok = np.isfinite(lo) & np.isfinite(hi) & np.isfinite(x)
    lo, hi, med, x = lo[ok], hi[ok], med[ok], x[ok]
    n = int(ok.sum())
    out = {"n": n, "inside": 0, "coverage": np.nan, "coverage_low": np.nan, "coverage_high": np.nan,
           "median_rel_width": np.nan, "mean_rel_interval_score": np.nan, "median_rel_interval_score": np.nan,
           "within_25pct": 0}
    if n == 0:
        return out
    inside = int(np.sum((lo <= x) & (x <= hi)))
    cl, ch = wilson_interval(inside, n)
    scale = np.abs(x)
    rel = scale > 0
    rel_is = interval_score(lo, hi, x)[rel] / scale[rel]
    out.update(inside=inside, coverage=inside / n, coverage_low=cl, coverage_high=ch,
               within_25pct=int(np.sum(within_25pct(x, med))))
    if rel.any():
        out.update(median_rel_width=float(np.median((hi - lo)[rel] / scale[rel])),
                   mean_rel_interval_score=float(np.mean(rel_is)), median_rel_interval_score=float(np.median(rel_is)))
    return out


def score(table: pd.DataFrame, baseline: str = "fitted", role: str = "heldout") -> dict:
    """Scores of the ``role`` rows (default the held-out ones) of one comparison table (see module docstring)."""
    if role not in SCORED_ROLES:
        raise ValueError(f"role must be one of {SCORED_ROLES}, got {role!r}")
    recs = _records(table)
    return aggregate(recs[recs["role"] == role], baseline)


def _fmt(v, pct=False):
    if isinstance(v, float) and not np.isfinite(v):
        return "n/a"
    return f"{100 * v:.0f} %" if pct else f"{v:.3g}"


def score_block(table: pd.DataFrame, key: str) -> str:
    """The closing text of a study notebook.

    ``"<key>: N printed numbers: K train, H held out, h inside; C claims: c hold"``
    (N, K, H from the paper's split; h: held-out rows of ``table`` inside our
    fitted 95 % band; C, c: rows of kind ``claim``), then one line per baseline
    with coverage (Wilson 95 % interval), median relative width, relative
    interval score and the ±25 % count, and whether the fit beats the prior; where
    the paper has ``tuned`` numbers, the same lines for them, marked in-sample.

    >>> from mtcal.reporting.compare import comparison_row, comparison_table
    >>> t = comparison_table([comparison_row("a", "x", 1.0, 1.0, "x < 2", True)])
    >>> score_block(t, "tan2022").splitlines()[0]
    'tan2022: 16 printed numbers: 1 train, 0 held out, 0 inside; 1 claims: 1 hold'
    """
    sp = paper_numbers.split(key)
    counts = sp["role"].value_counts()
    recs = _records(table, key)
    held = recs[recs["role"] == "heldout"]
    fitted, prior = aggregate(held, "fitted"), aggregate(held, "prior")
    kind = table["kind"].fillna("") if "kind" in table else pd.Series("", index=table.index)
    claims = table[(kind == "claim") & table["holds"].notna()]
    cons = table[(kind == "consistency") & table["holds"].notna()]
    insample = table[(kind == "in-sample") & table["holds"].notna()]
    n_tuned = counts.get("tuned", 0)
    lines = [f"{key}: {len(sp)} printed numbers: {counts.get('train', 0)} train, "
             + (f"{n_tuned} tuned, " if n_tuned else "")
             + f"{counts.get('heldout', 0)} held out, {fitted['inside']} inside; {len(claims)} claims: "
             f"{int(claims['holds'].astype(bool).sum())} hold",
             f"  (also {counts.get('input', 0)} input, {counts.get('erratum', 0)} erratum, "
             f"{counts.get('not-compared', 0)} not compared; "
             + (f"{len(insample)} in-sample checks, {int(insample['holds'].astype(bool).sum())} hold; "
                if len(insample) else "")
             + f"{len(cons)} consistency checks, not claims)"]
    lines += _score_lines(fitted, prior, "held-out")
    tuned = recs[recs["role"] == "tuned"]
    if len(tuned):
        lines += _score_lines(aggregate(tuned, "fitted"), aggregate(tuned, "prior"), "tuned (in-sample)")
    return "\n".join(lines)


def _score_lines(fitted: dict, prior: dict, what: str) -> list[str]:
    lines = []
    prefix = "" if what == "held-out" else f"{what} "
    for name, s in (("fitted (posterior predictive)", fitted), ("prior predictive", prior)):
        if s["n"] == 0:
            lines.append(f"  {prefix}{name}: no {what} number with a band")
            continue
        lines.append(f"  {prefix}{name}: {s['inside']} of {s['n']} inside, coverage {_fmt(s['coverage'], True)} "
                     f"[{_fmt(s['coverage_low'], True)}, {_fmt(s['coverage_high'], True)}] (Wilson 95 %); "
                     f"median width / |paper| {_fmt(s['median_rel_width'])}; interval score / |paper| "
                     f"mean {_fmt(s['mean_rel_interval_score'])}, median {_fmt(s['median_rel_interval_score'])}; "
                     f"within ±25 % of our median: {s['within_25pct']}")
    if fitted["n"] and prior["n"]:
        better = fitted["mean_rel_interval_score"] < prior["mean_rel_interval_score"]
        lines.append(f"  {prefix}the fit " + ("beats" if better else "does NOT beat") + " the prior predictive on "
                     "the mean relative interval score")
    return lines


def _write_atomic(df: pd.DataFrame, path: Path, float_format: str) -> None:
    """Write a CSV through a temporary file in the same folder and rename it (never a half-written file)."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    df.to_csv(tmp, index=False, float_format=float_format, lineterminator="\n")
    os.replace(tmp, path)


def write_scores(table: pd.DataFrame, key: str, notebook: str, folder: str | Path | None = None) -> Path:
    """Write one notebook's held-out records to ``data/fidelity_records_<notebook>.csv``; rewrite the scores.

    Each notebook owns its records file, so notebooks run in parallel processes
    never write the same records; the per-paper and overall scores
    ``data/fidelity_scores.csv`` are then recomputed from every records file in
    the folder (:func:`aggregate_scores`; ``make reproduce`` runs it once more
    after all notebooks, so the committed file does not depend on their order).
    Both files are written atomically, byte-stable. Returns the scores path.

    Parameters
    ----------
    folder : path, optional
        The ``data`` folder (default ``output_dir() / "data"``).
    """
    folder = Path(folder) if folder is not None else output_dir() / "data"
    folder.mkdir(parents=True, exist_ok=True)
    new = score_records(table, key, notebook)
    new = new.sort_values(["paper_key", "notebook", "artifact", "quantity", "ref"], kind="stable")
    _write_atomic(new[RECORD_COLUMNS], folder / f"{RECORDS_PREFIX}{notebook}.csv", "%.6g")
    return aggregate_scores(folder)


def write_cv_records(records: pd.DataFrame, notebook: str, folder: str | Path | None = None) -> Path:
    """Write one notebook's cross-validation records to ``data/fidelity_cv_<notebook>.csv``; rewrite the scores.

    ``records`` has :data:`CV_RECORD_COLUMNS`: one row per held-out number of a fold (``artifact`` = the
    held-out table) with the bands of every baseline of :data:`CV_BASELINES`. Returns the scores path.
    """
    if not isinstance(notebook, str) or not re.fullmatch(r"[A-Za-z0-9_]+", notebook):
        raise ValueError(f"notebook must be a non-empty str of letters, digits and '_' (a notebook stem), "
                         f"got {notebook!r}")
    missing = set(CV_RECORD_COLUMNS) - set(records.columns)
    if missing:
        raise ValueError(f"records must have the columns CV_RECORD_COLUMNS (missing {sorted(missing)})")
    bad = set(records["paper_key"]) - set(paper_numbers.KEYS)
    if bad:
        raise ValueError(f"paper_key must be one of {paper_numbers.KEYS}, got {sorted(bad)}")
    folder = Path(folder) if folder is not None else output_dir() / "data"
    folder.mkdir(parents=True, exist_ok=True)
    _write_atomic(records[CV_RECORD_COLUMNS], folder / f"{CV_PREFIX}{notebook}.csv", "%.6g")
    return aggregate_scores(folder)


def _cv_rows(folder: Path) -> list[dict]:
    """Score rows of the cross-validation records: per held-out table and per paper, each baseline."""
    parts = [pd.read_csv(p, keep_default_na=False, na_values=[""]) for p in sorted(folder.glob(f"{CV_PREFIX}*.csv"))]
    parts = [p for p in parts if len(p)]
    if not parts:
        return []
    recs = pd.concat(parts, ignore_index=True)
    rows = []
    for key in sorted(set(recs["paper_key"])):
        part = recs[recs["paper_key"] == key]
        for scope, sub in [(a, part[part["artifact"] == a]) for a in sorted(set(part["artifact"]))] + [(key, part)]:
            for b in CV_BASELINES:
                rows.append({"scope": scope, "role": CV_ROLE, "baseline": b, **aggregate(sub, b)})
    return rows


def aggregate_scores(folder: str | Path | None = None) -> Path:
    """Recompute ``fidelity_scores.csv`` from every ``fidelity_records_*.csv`` in ``folder`` (sorted by name).

    One row per (paper, role, baseline) for every paper key and role of :data:`SCORED_ROLES` (``n = 0``
    where the paper has no such number) and per (overall, role, baseline), fixed float format (byte-stable);
    then, from every ``fidelity_cv_*.csv`` (:func:`write_cv_records`), role :data:`CV_ROLE` rows per held-out
    table (scope = its artifact id) and per paper, one per baseline of :data:`CV_BASELINES`.
    """
    folder = Path(folder) if folder is not None else output_dir() / "data"
    parts = [pd.read_csv(p, dtype={"ref": str, "notebook": str}, keep_default_na=False, na_values=[""])
             for p in sorted(folder.glob(f"{RECORDS_PREFIX}*.csv"))]
    parts = [p for p in parts if len(p)]
    recs = pd.concat(parts, ignore_index=True) if parts else pd.DataFrame(columns=RECORD_COLUMNS)
    rows = []
    # every paper has its rows (n = 0 when it has no held-out number with a band, e.g. tan2022)
    # a records file from before the tuned role holds held-out records only
    recs["role"] = recs["role"].fillna("heldout") if "role" in recs else "heldout"
    scopes = [(k, recs[recs["paper_key"] == k]) for k in sorted(paper_numbers.KEYS)] + [("overall", recs)]
    for scope, part in scopes:
        for role in SCORED_ROLES:
            for b in BASELINES:
                rows.append({"scope": scope, "role": role, "baseline": b, **aggregate(part[part["role"] == role], b)})
    rows += _cv_rows(folder)
    out = folder / "fidelity_scores.csv"
    _write_atomic(pd.DataFrame(rows, columns=SCORE_COLUMNS), out, "%.4f")
    return out


def main(argv: list[str] | None = None) -> int:
    """``python -m mtcal.reporting.fidelity [DATA_FOLDER]``: rewrite the scores from the records files."""
    argv = sys.argv[1:] if argv is None else argv
    path = aggregate_scores(argv[0] if argv else None)
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
