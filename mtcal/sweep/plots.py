"""Figure of a sweep table: each metric against the grid, one panel per metric, with its band.

:func:`sweep_figure` draws ``table.csv`` of :func:`mtcal.sweep.engine.run_sweep` (one row per
cell and metric: the grid parameters, ``metric``, ``median``, ``low``, ``high``, ``trials``):
the first grid parameter on the x axis (numeric values on a numeric axis, anything else as
categories), one line per combination of the other grid parameters, the median with markers
and the band shaded. ``mtcal sweep`` saves it beside the table (``table.png``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from mtcal.core.metrics import MIN_BAND_DRAWS

__all__ = ["sweep_figure", "band_text", "x_parameter"]


def _numeric(values: pd.Series) -> np.ndarray | None:
    try:
        out = pd.to_numeric(values).to_numpy(float)
    except (TypeError, ValueError):
        return None
    return out if np.isfinite(out).all() else None


def band_text(table: pd.DataFrame) -> str:
    """What the table's ``low``/``high`` are, with the trial count: a "95 % band" only from >= 1000 trials.

    The engine gives the 2.5/97.5 percentiles from at least 1000 trials, else the min–max range
    (``band`` column; docs/conventions.md, Bands).

    Examples
    --------
    >>> band_text(pd.DataFrame({"trials": [50, 50]}))
    'range of 50 trials'
    >>> band_text(pd.DataFrame({"trials": [1000, 2000]}))
    '95 % band (>= 1000 trials)'
    """
    if "trials" not in table.columns or table.empty:
        return "spread of the trials"
    n_min, n_max = int(table["trials"].min()), int(table["trials"].max())
    if n_min >= MIN_BAND_DRAWS:
        return f"95 % band (>= {n_min} trials)"
    count = f"{n_min}" if n_min == n_max else f"{n_min}-{n_max}"
    return f"range of {count} trials"


def x_parameter(table: pd.DataFrame, grid: list[str]) -> str | None:
    """The grid parameter for the x axis: the first numeric one with more than one value, else the first."""
    for name in grid:
        if name in table and table[name].nunique() > 1 and _numeric(table[name]) is not None:
            return name
    return grid[0] if grid else None


def sweep_figure(table: pd.DataFrame, grid: list[str], path: str | Path | None = None, *, title: str = ""):
    """Metric vs grid, one panel per metric, median and band (:func:`band_text` names it, with the count).

    Parameters
    ----------
    table : DataFrame
        Sweep table: the ``grid`` columns, ``metric``, ``median``, ``low``, ``high``.
    grid : list of str
        Grid parameter names in spec order; the first is the x axis, the others label the lines.
    path : path, optional
        PNG to write (byte-stable: no timestamp metadata); the figure is closed after saving.
    title : str
        Figure title (e.g. the sweep name).

    Returns
    -------
    Path or matplotlib.figure.Figure
        ``path`` when saved, else the open figure.

    Examples
    --------
    >>> t = pd.DataFrame({"sigma": [1.0, 2.0], "metric": ["rms", "rms"], "median": [1.0, 2.0],
    ...                   "low": [0.8, 1.6], "high": [1.2, 2.4]})
    >>> fig = sweep_figure(t, ["sigma"])
    >>> [ax.get_title() for ax in fig.axes], fig.axes[0].get_xlabel()
    (['rms'], 'sigma')
    >>> sweep_figure(t, ["gain"])
    Traceback (most recent call last):
    ...
    ValueError: table lacks columns ['gain'] (grid parameters and metric, median, low, high)
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    grid = list(grid)
    missing = [c for c in [*grid, "metric", "median", "low", "high"] if c not in table.columns]
    if missing:
        raise ValueError(f"table lacks columns {missing} (grid parameters and metric, median, low, high)")
    if table.empty:
        raise ValueError("table is empty: nothing to plot")
    metrics = list(dict.fromkeys(table["metric"]))
    x_name = x_parameter(table, grid)                  # a numeric swept parameter on x when there is one
    others = [g for g in grid if g != x_name]
    n = len(metrics)
    cols = min(n, 3)
    rows = int(np.ceil(n / cols))
    with plt.rc_context({"figure.dpi": 100, "savefig.dpi": 110, "axes.grid": True, "grid.alpha": 0.3}):
        fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.2 * rows), squeeze=False)
        for ax, metric in zip(axes.ravel(), metrics):
            part = table[table["metric"] == metric]
            groups = part.groupby(others, sort=False, dropna=False) if others else [((), part)]
            for key, sub in groups:
                key = key if isinstance(key, tuple) else (key,)
                label = ", ".join(f"{k}={v}" for k, v in zip(others, key)) if others else None
                if x_name is None:
                    x, ticks = np.arange(len(sub)), None
                else:
                    x = _numeric(sub[x_name])
                    ticks = None
                    if x is None:
                        ticks = [str(v) for v in sub[x_name]]
                        x = np.arange(len(sub), dtype=float)
                order = np.argsort(x, kind="stable")
                med = sub["median"].to_numpy(float)[order]
                lo, hi = sub["low"].to_numpy(float)[order], sub["high"].to_numpy(float)[order]
                line, = ax.plot(x[order], med, "o-", label=label, ms=4)
                ax.fill_between(x[order], lo, hi, color=line.get_color(), alpha=0.2, lw=0)
                if ticks is not None:
                    ax.set_xticks(x[order], [ticks[i] for i in order], rotation=30, ha="right", fontsize=8)
            ax.set_title(metric)
            ax.set_xlabel(x_name or "cell")
            if others:
                ax.legend(fontsize=7)
        for ax in axes.ravel()[n:]:
            ax.set_visible(False)
        fig.suptitle(f"{title + ': ' if title else ''}median and {band_text(table)} per grid cell", fontsize=10)
        fig.tight_layout()
        if path is None:
            return fig
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path, metadata={"Software": None})
        plt.close(fig)
    return path
