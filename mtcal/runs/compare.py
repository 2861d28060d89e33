"""Run comparison: the comparison tables (``data/*_comparison.csv``) of several runs side by side.

``mtcal compare`` (:func:`compare_runs`) joins the comparison tables of what-if runs
(:func:`mtcal.runs.notebooks.run_notebook`) and/or the committed results on
(table, artifact, quantity), with each run's value, Monte Carlo band and claim, and
marks the claims that flip.
"""

from __future__ import annotations

import ast
import json
import re
from pathlib import Path

import numpy as np
import pandas as pd

from mtcal.reporting.output import setup_matplotlib
from mtcal.runs.environment import repo_root

__all__ = ["load_comparisons", "compare_runs", "flip_text", "run_metadata", "comparability_problems",
           "claim_threshold", "threshold_holds", "threshold_text", "compare_figure"]

_KEY = ["table", "artifact", "key"]
_NUMBER_RE = re.compile(r"[-+−]?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")


def load_comparisons(run: str | Path) -> pd.DataFrame:
    """Every ``data/*_comparison.csv`` of a run folder (or ``"committed"``: the repository's ``data/``),
    stacked with a ``table`` column (the file stem)."""
    if str(run) == "committed":
        root = repo_root() or Path.cwd()
        folder = root / "data"
    else:
        folder = Path(run) / "data"
    if not folder.is_dir():
        raise FileNotFoundError(f"run {str(run)!r} has no data/ folder ({folder})")
    frames = []
    for path in sorted(folder.glob("*_comparison.csv")):
        try:
            df = pd.read_csv(path, dtype=str, keep_default_na=False)
        except (UnicodeDecodeError, pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
            raise ValueError(f"{path} is not a readable comparison table (CSV: {str(exc).splitlines()[0][:120]})") \
                from None
        missing = {"artifact", "quantity", "mtcal", "holds"} - set(df.columns)
        if missing:
            raise ValueError(f"{path} is not a comparison table (missing columns {sorted(missing)})")
        df.insert(0, "table", path.stem)
        frames.append(df)
    if not frames:
        raise FileNotFoundError(f"run {str(run)!r} has no data/*_comparison.csv")
    out = pd.concat(frames, ignore_index=True)
    for col in ("paper", "mc_band", "claim", "role", "source"):
        if col not in out:
            out[col] = ""
    # join key: the quantity with its numbers blanked (labels carry parameter values, e.g.
    # "hybrid (θ̇_t = 0.5 °/s)" vs "(θ̇_t = 10 °/s)"), repeats numbered in order
    out["key"] = out["quantity"].map(lambda q: _NUMBER_RE.sub("#", q))
    out["key"] = out["key"] + out.groupby(["table", "artifact", "key"]).cumcount().map(lambda n: f" [{n + 1}]")
    return out


def _literal(text) -> str:
    try:
        return repr(ast.literal_eval(str(text)))
    except (ValueError, SyntaxError, TypeError):
        return str(text)


def run_metadata(run: str | Path) -> dict:
    """Size and seed of a run: ``{"size": "full"|"ci"|None, "seeds": {table: seed repr}, "known": bool}``.

    A what-if run reads its ``params.json`` (size, the notebook's ``SEED`` override or default);
    ``"committed"`` is ``make reproduce``'s full-size run at every notebook's default ``SEED``;
    a folder without ``params.json`` is unknown (``known=False``).
    """
    if str(run) == "committed":
        from mtcal.runs.notebooks import notebook_parameters, notebook_sources

        seeds = {}
        try:
            sources = notebook_sources()
        except FileNotFoundError:
            sources = []
        for source in sources:
            seed = notebook_parameters(source).get("SEED", {}).get("default")
            seeds[f"{source.stem[3:]}_comparison"] = _literal(seed) if seed is not None else None
        return {"size": "full", "seeds": seeds, "known": True}
    path = Path(run) / "params.json"
    if not path.is_file():
        return {"size": None, "seeds": {}, "known": False}
    try:
        record = json.loads(path.read_text(encoding="utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ValueError(f"{path} is not a run's parameter record (JSON: {str(exc)[:120]})") from None
    if not isinstance(record, dict):
        raise ValueError(f"{path} is not a run's parameter record (a JSON object), got {type(record).__name__}")
    stem = str(record.get("notebook", ""))
    seed = record.get("parameters", {}).get("SEED", record.get("defaults", {}).get("SEED"))
    # a what-if run executes one notebook: its seed holds for every table of the run
    return {"size": record.get("size"), "seeds": {"*": _literal(seed) if seed is not None else None},
            "notebook": stem, "known": True}


def comparability_problems(runs: list, names: list[str], tables=None) -> tuple[list[str], list[str]]:
    """Differences in run size or seed between runs (``problems``) and runs whose metadata is unknown (``notes``).

    >>> comparability_problems(["a", "b"], ["a", "b"])
    ([], ['run a has no params.json: its size and seed are unknown', 'run b has no params.json: its size and seed are unknown'])
    """
    meta = [run_metadata(r) for r in runs]
    problems, notes = [], []
    for m, n in zip(meta, names):
        if not m["known"]:
            notes.append(f"run {n} has no params.json: its size and seed are unknown")
    known = [(m, n) for m, n in zip(meta, names) if m["known"]]
    sizes = {m["size"] for m, _ in known}
    if len(sizes) > 1:
        problems.append("runs differ in size (" + ", ".join(f"{n}: {m['size']}" for m, n in known) +
                        "): Monte Carlo bands and values are not comparable")
    if tables is None:
        tables = sorted({t for m, _ in known for t in m["seeds"] if t != "*"}) or ["*"]
    for table in sorted(tables):
        seeds = [m["seeds"].get(table, m["seeds"].get("*")) for m, _ in known]
        if len(set(seeds)) > 1:
            label = table.removesuffix("_comparison") if table != "*" else "the runs"
            problems.append(f"runs differ in seed policy for {label} (" +
                            ", ".join(f"{n}: SEED={s}" for (m, n), s in zip(known, seeds)) +
                            "): differences mix the change with Monte Carlo noise")
    return problems, notes


def flip_text(states: list[str], names: list[str]) -> str:
    """How a claim's ``holds`` changes across runs, e.g. ``"holds True→False (B)"``; "" when unchanged.

    >>> flip_text(["True", "False", "True"], ["paper", "industrial", "noisy"])
    'True→False (industrial)'
    >>> flip_text(["True", "True"], ["a", "b"])
    ''
    """
    base = states[0]
    changed = [f"{base or '-'}→{s or '-'} ({n})" for s, n in zip(states[1:], names[1:]) if s != base]
    return "; ".join(changed)


def _as_float(text) -> float:
    try:
        return float(text)
    except (TypeError, ValueError):
        return float("nan")


def compare_runs(runs: list[str | Path], *, names: list[str] | None = None, out_dir: str | Path | None = None,
                 figure: bool = True, allow_mismatch: bool = False) -> tuple[pd.DataFrame, Path, Path | None]:
    """Side-by-side table of every comparison-table quantity of several runs, with bands and claim flips.

    Parameters
    ----------
    runs : list of paths or "committed"
        Run folders (each with ``data/*_comparison.csv``); ``"committed"`` is the
        repository's committed results. The first run is the reference for flips.
    names : list of str, optional
        Column labels (default: the folder names).
    out_dir : path, optional
        Where ``compare_<names>.csv`` and ``.png`` go (default: the first run folder's parent,
        or ``runs/`` for ``committed``).
    allow_mismatch : bool
        Compare runs that differ in size (``ci`` vs ``full``) or seed (else ValueError); the
        differences are listed in ``table.attrs["warnings"]`` either way.

    Returns
    -------
    table : DataFrame
        ``table, artifact, quantity, paper, claim, role`` then ``mtcal``, ``band`` and
        ``holds`` per run (``<column> [<name>]``), ``flips`` (e.g. ``True→False (B)``) and
        ``comparability`` (``"comparable"``, or the size/seed differences compared anyway with
        ``allow_mismatch``; also printed on the figure), ``threshold`` (read from the claim text,
        :func:`claim_threshold`) and ``threshold_check`` (whether that reading reproduces every
        run's ``holds``); only the comparison tables (notebooks) present in every run.
    csv_path, png_path : Path
        Saved table and figure (:func:`compare_figure`: claim quantities against their
        thresholds, flipped claims first, then every numeric quantity relative to the first run;
        ``None`` when ``figure=False`` or nothing is numeric).
    """
    if not isinstance(runs, (list, tuple)) or len(runs) < 2:
        raise ValueError(f"runs must list at least two run folders (or 'committed'), got {runs!r}")
    names = list(names) if names else [("committed" if str(r) == "committed" else Path(r).resolve().name)
                                       for r in runs]
    if len(names) != len(runs) or len(set(names)) != len(names):
        raise ValueError(f"names must be {len(runs)} distinct labels, got {names}")
    tables = [load_comparisons(run) for run in runs]
    # compare only the notebooks every run executed (a what-if run usually runs one notebook)
    common = set.intersection(*(set(df["table"]) for df in tables))
    if not common:
        raise ValueError(f"runs {names} have no comparison table in common "
                         f"({'; '.join(f'{n}: {sorted(set(df.table))}' for n, df in zip(names, tables))})")
    problems, notes = comparability_problems(runs, names, common)
    if problems and not allow_mismatch:
        raise ValueError("runs are not comparable: " + "; ".join(problems) +
                         " (allow_mismatch=True / --allow-mismatch compares them anyway)")
    merged = None
    for df, name in zip(tables, names):
        df = df[df["table"].isin(common)]
        part = df[_KEY + ["quantity", "paper", "claim", "role"]].copy()
        part[f"mtcal [{name}]"] = df["mtcal"]
        part[f"band [{name}]"] = df["mc_band"]
        part[f"holds [{name}]"] = df["holds"]
        if merged is None:
            merged = part
        else:
            merged = merged.merge(part, on=_KEY, how="outer", suffixes=("", "_new"))
            for col in ("quantity", "paper", "claim", "role"):
                merged[col] = merged[col].where(merged[col].notna(), merged.pop(f"{col}_new"))
    merged = merged.fillna("")
    holds_cols = [f"holds [{n}]" for n in names]
    merged["flips"] = [flip_text([str(r[c]) for c in holds_cols], names) for _, r in merged.iterrows()]
    merged = merged.sort_values(_KEY, kind="stable").reset_index(drop=True)
    order = ["table", "artifact", "quantity", "paper", "claim", "role"] + [
        f"{c} [{n}]" for n in names for c in ("mtcal", "band", "holds")]
    merged = merged[order + ["flips"]]
    merged.attrs["warnings"] = problems + notes
    # a size/seed mismatch is part of the result: recorded in the saved table (and the figure)
    merged["comparability"] = "; ".join(problems) if problems else "comparable"
    # the claim's threshold read from its text, kept only where it reproduces every run's verdict
    merged["threshold"], merged["threshold_check"] = _claim_thresholds(merged, names)

    if out_dir is None:
        first = runs[0] if str(runs[0]) != "committed" else (runs[1] if len(runs) > 1 else "runs/x")
        out_dir = Path(first).parent if str(first) != "committed" else Path("runs")
    out_dir = Path(out_dir)
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ValueError(f"--out {out_dir}: cannot make the folder ({exc.strerror}: {exc.filename})") from None
    slug = re.sub(r"[^A-Za-z0-9_.=+,-]+", "", "_vs_".join(names))[:120]
    csv_path = out_dir / f"compare_{slug}.csv"
    merged.to_csv(csv_path, index=False, lineterminator="\n")
    png_path = _compare_figure(merged, names, out_dir / f"compare_{slug}.png") if figure else None
    return merged, csv_path, png_path


_OP_RE = re.compile(r"(?:^|(?<=[\s(\"':]))(<=|>=|≤|≥|<|>|=)\s*([-+−]?\d+(?:\.(\d+))?(?:[eE][-+]?\d+)?)\s*(%?)")
_RANGE_RE = re.compile(r"\(\s*([-+−]?\d+(?:\.\d+)?)\s*(?:…|\.\.\.)\s*([-+−]?\d+(?:\.\d+)?)\s*\)")
_BAND_RE = re.compile(r"\[\s*([-+−]?[\d.]+(?:[eE][-+]?\d+)?),\s*([-+−]?[\d.]+(?:[eE][-+]?\d+)?)\s*\]")
_OPS = {"≤": "<=", "≥": ">="}


def _number(text: str) -> float:
    return float(text.replace("−", "-"))


def claim_threshold(claim: str) -> dict | None:
    """The threshold of a claim, read from its text: the first comparison with a number
    (``<= 0.04``, ``> 80 %``, ``= 0.04`` at print precision) or a range ``(−1.1…−0.9)``; None when
    the text has neither (e.g. "max error after < max error before").

    The claim columns quote the paper's statement with its threshold verbatim; this reads that
    threshold back for the comparison figure. Whether the reading is right is checked against the
    row's recorded ``holds`` (:func:`threshold_holds`, :func:`compare_runs`), never assumed.

    Returns
    -------
    dict or None
        ``{"op", "value", "percent", "decimals"}`` (``op`` one of ``<=, >=, <, >, =``; ``percent``:
        the number is followed by ``%``), or ``{"op": "in", "low", "high"}``.

    Examples
    --------
    >>> claim_threshold('"The results after calibration are all within 0.03°" (<= 0.03 deg)')
    {'op': '<=', 'value': 0.03, 'percent': False, 'decimals': 2}
    >>> claim_threshold('Fig. 11: superior (> 90 % of angles in 97.5 % of repetitions)')["value"]
    90.0
    >>> claim_threshold("≈ −1 (−1.1…−0.9)")
    {'op': 'in', 'low': -1.1, 'high': -0.9}
    >>> claim_threshold("(max error after < max error before)") is None
    True
    """
    op = _OP_RE.search(str(claim))
    rng = _RANGE_RE.search(str(claim))
    if rng is not None and (op is None or rng.start() < op.start()):
        low, high = sorted((_number(rng.group(1)), _number(rng.group(2))))
        return {"op": "in", "low": low, "high": high}
    if op is None:
        return None
    return {"op": _OPS.get(op.group(1), op.group(1)), "value": _number(op.group(2)), "percent": op.group(4) == "%",
            "decimals": len(op.group(3) or "")}


def threshold_holds(threshold: dict, value: float, scale: float = 1.0) -> bool:
    """Whether ``value`` meets ``threshold`` (:func:`claim_threshold`); the threshold's number times
    ``scale`` (0.01: a percentage read as a fraction). ``=`` is equality at the threshold's print
    precision (half a unit of its last decimal).

    >>> threshold_holds(claim_threshold("(<= 0.04 deg)"), 0.0412), threshold_holds(claim_threshold("(= 0.04)"), 0.043)
    (False, True)
    """
    if threshold["op"] == "in":
        return bool(threshold["low"] <= value <= threshold["high"])
    t = threshold["value"] * scale
    op = threshold["op"]
    if op == "=":
        return bool(abs(value - t) <= 0.5 * 10.0 ** -threshold["decimals"] * scale * (1 + 1e-9))
    return bool({"<=": value <= t, ">=": value >= t, "<": value < t, ">": value > t}[op])


def threshold_text(threshold: dict | None, scale: float = 1.0) -> str:
    """``"<= 0.04"``, ``"> 0.9 (90 %)"``, ``"in [-1.1, -0.9]"``; ``""`` for None.

    >>> threshold_text(claim_threshold("(> 90 % of angles)"), 0.01)
    '> 0.9 (90 %)'
    """
    if threshold is None:
        return ""
    if threshold["op"] == "in":
        return f"in [{threshold['low']:g}, {threshold['high']:g}]"
    text = f"{threshold['op']} {threshold['value'] * scale:g}"
    if threshold["percent"]:
        text += f" ({threshold['value']:g} %)" if scale != 1.0 else " %"
    return text


def _claim_thresholds(table: pd.DataFrame, names: list[str]) -> tuple[list[str], list[str]]:
    """Per row: the threshold read from the claim (``threshold`` column) and whether that reading
    reproduces the recorded ``holds`` of every run with a number and a verdict (``threshold_check``:
    ``reproduces holds``, ``does not reproduce holds (claim judged otherwise)`` or ``""``)."""
    texts, checks = [], []
    for _, row in table.iterrows():
        threshold = claim_threshold(row["claim"]) if str(row["claim"]) else None
        judged = [(_as_float(row[f"mtcal [{n}]"]), str(row[f"holds [{n}]"])) for n in names]
        judged = [(v, h == "True") for v, h in judged if np.isfinite(v) and h in ("True", "False")]
        if threshold is None or not judged:
            texts.append(threshold_text(threshold))
            checks.append("")
            continue
        scales = [1.0]
        if threshold["op"] != "in" and threshold["percent"] and "%" not in str(row["quantity"]):
            scales.append(0.01)  # "> 90 %" of a share printed as a fraction
        found = next((s for s in scales if all(threshold_holds(threshold, v, s) == h for v, h in judged)), None)
        texts.append(threshold_text(threshold, found or 1.0))
        checks.append("reproduces holds" if found is not None else
                      "does not reproduce holds (the claim is judged on another number or rule)")
    return texts, checks


def _compare_figure(table: pd.DataFrame, names: list[str], path: Path, max_rows: int = 30,
                    max_claims: int = 20) -> Path | None:
    """Save :func:`compare_figure` to ``path`` (byte-stable: fixed rc settings, no metadata); None when empty."""
    fig = compare_figure(table, names, max_rows=max_rows, max_claims=max_claims)
    if fig is None:
        return None
    import matplotlib.pyplot as plt

    fig.savefig(path, metadata={"Software": None}, bbox_inches="tight")
    plt.close(fig)
    return path


def compare_figure(table: pd.DataFrame, names: list[str], *, max_rows: int = 30, max_claims: int = 20):
    """The comparison figure of :func:`compare_runs`: claim quantities against their thresholds, and
    every numeric quantity relative to the first run.

    Top: one panel per claim (rows with a ``holds`` verdict in some run and a number in every run;
    flipped claims first, then claims failing in some run, at most ``max_claims``): each run's value (its band as a bar), marked
    holds/FAILS, and the claim's threshold as a dashed line with the passing side shaded — drawn
    only where the threshold read from the claim text (:func:`claim_threshold`) reproduces the
    recorded verdicts (``threshold_check``), else the panel says so. Bottom: each numeric quantity
    divided by the first run's value (the ``max_rows`` that moved most, flipped claims first).

    Parameters
    ----------
    table : DataFrame
        :func:`compare_runs`' table (with ``threshold`` and ``threshold_check`` columns).
    names : list of str
        The runs' labels, the first the reference.

    Returns
    -------
    matplotlib Figure or None
        None when no row is numeric.
    """
    setup_matplotlib()
    import matplotlib.pyplot as plt

    values = np.column_stack([table[f"mtcal [{n}]"].map(_as_float).to_numpy() for n in names])
    finite = np.isfinite(values).all(axis=1)
    flips = table["flips"].to_numpy() != ""
    # claim panels: a verdict in some run, a number in every run
    verdict = np.column_stack([table[f"holds [{n}]"].isin(["True", "False"]).to_numpy() for n in names]).any(axis=1)
    claim_rows = np.flatnonzero(finite & verdict)
    fails = np.column_stack([table[f"holds [{n}]"].eq("False").to_numpy() for n in names]).any(axis=1)
    order = np.lexsort((~fails[claim_rows], ~flips[claim_rows]))   # flipped, then failing somewhere, then the rest
    claim_rows = claim_rows[order][:max_claims]
    # ratio panel
    ref = values[:, 0]
    usable = finite & (ref != 0)
    ratio = values[usable] / ref[usable, None] if usable.any() else np.empty((0, len(names)))
    if not len(claim_rows) and not usable.any():
        return None
    spread = np.nanmax(np.abs(np.log10(np.abs(ratio) + 1e-300)), axis=1) + 10.0 * flips[usable] if len(ratio) else []
    keep = np.argsort(-np.asarray(spread), kind="stable")[:max_rows][::-1]
    heights = [0.55 + 0.16 * len(names)] * len(claim_rows) + ([0.28 * len(keep) + 1.0] if len(keep) else [])
    fig = plt.figure(figsize=(9.0, sum(heights) + 0.9), layout="constrained")
    # claims and ratios in separate subfigures: the ratio panel's long labels do not narrow the claim panels
    parts = [heights[:len(claim_rows)], heights[len(claim_rows):]]
    parts = [h for h in parts if h]
    subfigs = fig.subfigures(len(parts), 1, height_ratios=[sum(h) for h in parts], squeeze=False)[:, 0]
    axes = [ax for sub, h in zip(subfigs, parts)
            for ax in sub.subplots(len(h), 1, gridspec_kw={"height_ratios": h}, squeeze=False)[:, 0]]
    n_claims = int((finite & verdict).sum())
    for ax, idx in zip(axes, claim_rows):
        _claim_panel(ax, table.iloc[idx], values[idx], names)
    if len(claim_rows):
        shown = f" ({len(claim_rows)} of {n_claims}; all in the CSV)" if n_claims > len(claim_rows) else ""
        axes[0].set_title(f"CLAIMS AGAINST THEIR THRESHOLDS{shown}\n" + axes[0].get_title(loc="left"), fontsize=7,
                          loc="left")
    if len(keep):
        ax = axes[-1]
        labels = (table.loc[usable, "table"].str.replace("_comparison", "") + ": "
                  + table.loc[usable, "quantity"]).str.slice(0, 70).to_numpy()
        flipped = flips[usable]
        y = np.arange(len(keep))
        for j, name in enumerate(names):
            ax.plot(ratio[keep, j], y, "o" if j else "|", ms=6 if j else 12, color=f"C{j}", label=name)
        for k, idx in enumerate(keep):
            if flipped[idx]:
                ax.annotate("claim flips", (1.0, k), xytext=(4, -3), textcoords="offset points", fontsize=7,
                            color="C3")
        ax.set_yticks(y, labels[keep], fontsize=7)
        shown_ratio = ratio[keep]
        if np.all(shown_ratio > 0):
            ax.set_xscale("log")
            ax.set_xlim(shown_ratio.min() / 1.6, shown_ratio.max() * 1.6)
        else:
            ax.set_xscale("symlog", linthresh=1e-2)
        ax.axvline(1.0, color="k", lw=0.6)
        ax.set_xlabel(f"mtcal value / value in run '{names[0]}'", fontsize=8)
        ax.set_title(f"comparison-table quantities: {' vs '.join(names)}", fontsize=8)
        ax.legend(fontsize=7, loc="lower right")
    mismatch = str(table["comparability"].iloc[0]) if "comparability" in table and len(table) else "comparable"
    if mismatch != "comparable":
        fig.suptitle(f"NOT COMPARABLE: {mismatch}"[:160], fontsize=8, color="C3")
    return fig


def _claim_panel(ax, row: pd.Series, values: np.ndarray, names: list[str]) -> None:
    """One claim: each run's value and band, holds/FAILS, the threshold line and its passing side."""
    y = np.arange(len(names))
    xs = list(values)
    for j, name in enumerate(names):
        band = _BAND_RE.search(str(row[f"band [{name}]"]))
        if band:
            low, high = _number(band.group(1)), _number(band.group(2))
            ax.hlines(j, low, high, color=f"C{j}", lw=3, alpha=0.35)
            xs += [low, high]
        holds = str(row[f"holds [{name}]"])
        ax.plot(values[j], j, "o" if holds != "False" else "X", color=f"C{j}", ms=6)
        mark = {"True": "holds", "False": "FAILS"}.get(holds, "")
        ax.annotate(mark, (values[j], j), xytext=(6, -3), textcoords="offset points", fontsize=7,
                    color="C2" if holds == "True" else "C3")
    threshold = claim_threshold(row["claim"]) if row.get("threshold_check") == "reproduces holds" else None
    lines = []
    if threshold is not None:
        scale = 0.01 if "(" in str(row["threshold"]) and threshold.get("percent") else 1.0
        lines = [threshold["low"], threshold["high"]] if threshold["op"] == "in" else [threshold["value"] * scale]
        xs += lines
    lo, hi = float(np.min(xs)), float(np.max(xs))
    pad = 0.12 * (hi - lo) if hi > lo else 0.1 * max(abs(lo), 1e-6)
    ax.set_xlim(lo - pad, hi + pad)
    for x in lines:
        ax.axvline(x, color="C3", ls="--", lw=1.0)
    if threshold is not None:
        left, right = ax.get_xlim()
        op = threshold["op"]
        if op == "in":
            ax.axvspan(lines[0], lines[1], color="C2", alpha=0.08, lw=0)
        elif op in ("<", "<="):
            ax.axvspan(left, lines[0], color="C2", alpha=0.08, lw=0)
        elif op in (">", ">="):
            ax.axvspan(lines[0], right, color="C2", alpha=0.08, lw=0)
        ax.set_xlim(left, right)
        ax.annotate(f"threshold {row['threshold']}", (lines[-1], len(names) - 0.5), xytext=(3, 0),
                    textcoords="offset points", fontsize=7, color="C3", va="top")
    verdict = "" if threshold is not None else (
        " [threshold not drawn: not read from the claim text]" if not row.get("threshold") else
        f" [threshold {row['threshold']} read from the text does not reproduce the verdicts: not drawn]")
    title = f"{str(row['table']).removesuffix('_comparison')}: {row['quantity']}"[:80]
    claim = str(row["claim"])
    ax.set_title(f"{title}{'  — CLAIM FLIPS' if row['flips'] else ''}\nclaim: "
                 f"{claim[:120] + ('…' if len(claim) > 120 else '')}{verdict}", fontsize=7, loc="left")
    ax.set_yticks(y, names, fontsize=7)
    ax.set_ylim(-0.7, len(names) - 0.3)
    ax.tick_params(axis="x", labelsize=7)
