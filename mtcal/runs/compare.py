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

__all__ = ["load_comparisons", "compare_runs", "flip_text", "run_metadata", "comparability_problems"]

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
        df = pd.read_csv(path, dtype=str, keep_default_na=False)
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
    record = json.loads(path.read_text(encoding="utf-8"))
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
        ``allow_mismatch``; also printed on the figure); only the comparison tables (notebooks)
        present in every run.
    csv_path, png_path : Path
        Saved table and figure (figure: every numeric quantity relative to the first run,
        flipped claims marked; ``None`` when ``figure=False`` or nothing is numeric).
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

    if out_dir is None:
        first = runs[0] if str(runs[0]) != "committed" else (runs[1] if len(runs) > 1 else "runs/x")
        out_dir = Path(first).parent if str(first) != "committed" else Path("runs")
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    slug = re.sub(r"[^A-Za-z0-9_.=+,-]+", "", "_vs_".join(names))[:120]
    csv_path = out_dir / f"compare_{slug}.csv"
    merged.to_csv(csv_path, index=False, lineterminator="\n")
    png_path = _compare_figure(merged, names, out_dir / f"compare_{slug}.png") if figure else None
    return merged, csv_path, png_path


def _compare_figure(table: pd.DataFrame, names: list[str], path: Path, max_rows: int = 30) -> Path | None:
    """Dot plot: each numeric quantity of every run divided by the first run's value."""
    ref = table[f"mtcal [{names[0]}]"].map(_as_float).to_numpy()
    values = np.column_stack([table[f"mtcal [{n}]"].map(_as_float).to_numpy() for n in names])
    usable = np.isfinite(ref) & (ref != 0) & np.isfinite(values).all(axis=1)
    if not usable.any():
        return None
    ratio = values[usable] / ref[usable, None]
    labels = (table.loc[usable, "table"].str.replace("_comparison", "") + ": "
              + table.loc[usable, "quantity"]).str.slice(0, 70).to_numpy()
    flips = table.loc[usable, "flips"].to_numpy() != ""
    # the quantities that moved most (and every flipped claim) first
    spread = np.nanmax(np.abs(np.log10(np.abs(ratio) + 1e-300)), axis=1) + 10.0 * flips
    keep = np.argsort(-spread, kind="stable")[:max_rows][::-1]
    setup_matplotlib()
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9.0, 0.28 * len(keep) + 1.6))
    y = np.arange(len(keep))
    for j, name in enumerate(names):
        ax.plot(ratio[keep, j], y, "o" if j else "|", ms=6 if j else 12, label=name)
    for k, idx in enumerate(keep):
        if flips[idx]:
            ax.annotate("claim flips", (1.0, k), xytext=(4, -3), textcoords="offset points", fontsize=7, color="C3")
    ax.set_yticks(y, labels[keep], fontsize=7)
    shown = ratio[keep]
    if np.all(shown > 0):
        ax.set_xscale("log")
        ax.set_xlim(shown.min() / 1.6, shown.max() * 1.6)
    else:
        ax.set_xscale("symlog", linthresh=1e-2)
    ax.axvline(1.0, color="k", lw=0.6)
    ax.set_xlabel(f"mtcal value / value in run '{names[0]}'")
    ax.set_title(f"comparison-table quantities: {' vs '.join(names)}")
    mismatch = str(table["comparability"].iloc[0]) if "comparability" in table and len(table) else "comparable"
    if mismatch != "comparable":
        fig.suptitle(f"NOT COMPARABLE: {mismatch}"[:160], fontsize=8, color="C3")
    ax.legend(fontsize=8, loc="lower right")
    fig.savefig(path, metadata={"Software": None}, bbox_inches="tight")
    plt.close(fig)
    return path
