"""Notebook plumbing: run size, output folders, byte-stable figures and tables.

Notebooks write figures to ``figures/<ID>.png`` and tables to
``data/<ID>.csv`` under :func:`output_dir`: ``$MTCAL_OUTPUT_DIR`` when set
(``make test`` points it to ``build/ci``, a what-if run ``mtcal run`` to
``runs/<name>``), else the repository root when mtcal runs from its source
checkout (``make reproduce`` rewrites the committed artifacts), else the
current directory — never the install location.
"""

from __future__ import annotations

import os
from pathlib import Path

import pandas as pd

__all__ = ["run_size", "output_dir", "setup_matplotlib", "save_figure", "save_table", "show_table"]

_SIZES = ("ci", "full")


def run_size(size: str | None = None) -> str:
    """Resolve a notebook's ``SIZE`` parameter: ``size`` if given, else ``$MTCAL_SIZE``, else ``"full"``.

    A notebook's parameters cell holds ``SIZE = None`` and the next cell calls
    ``SIZE = report.run_size(SIZE)``, so ``make test`` (``MTCAL_SIZE=ci``) and a
    papermill/``mtcal run`` parameter (``-p SIZE=ci``) both work.

    >>> run_size("ci")
    'ci'
    """
    if size is None:
        size = os.environ.get("MTCAL_SIZE") or "full"
        if size not in _SIZES:
            raise ValueError(f"MTCAL_SIZE must be one of {_SIZES}, got {size!r}")
    elif size not in _SIZES:
        raise ValueError(f"SIZE must be one of {_SIZES} or None, got {size!r}")
    return size


def output_dir() -> Path:
    """Root for ``figures/`` and ``data/``.

    ``$MTCAL_OUTPUT_DIR`` if set; else the repository root when mtcal runs from its
    source checkout (so ``make reproduce`` rewrites the committed artifacts); else the
    current directory — never the install location.
    """
    env = os.environ.get("MTCAL_OUTPUT_DIR")
    if env:
        return Path(env)
    root = Path(__file__).resolve().parents[2]
    if (root / "pyproject.toml").is_file() and (root / "notebooks").is_dir():
        return root  # source checkout (editable install or PYTHONPATH)
    return Path.cwd()  # installed package: never site-packages


def _target(kind: str, artifact_id: str, suffix: str) -> Path:
    if not isinstance(artifact_id, str) or not artifact_id or "/" in artifact_id:
        raise ValueError(f"artifact_id must be a plain name like 'wang2023cja_fig07', got {artifact_id!r}")
    folder = output_dir() / kind
    folder.mkdir(parents=True, exist_ok=True)
    return folder / f"{artifact_id}{suffix}"


def setup_matplotlib() -> None:
    """Agg backend and fixed rc settings so figure files are byte-stable."""
    import matplotlib

    matplotlib.use("Agg")
    matplotlib.rcParams.update({"svg.hashsalt": "mtcal", "figure.dpi": 100,
                                "savefig.dpi": 110, "figure.figsize": (7.0, 4.0),
                                "axes.grid": True, "grid.alpha": 0.3})


def save_figure(fig, artifact_id: str):
    """Save ``fig`` to ``figures/<artifact_id>.png`` (no timestamp metadata), close it,
    and return an ``IPython.display.Image`` of the file for inline display."""
    import matplotlib.pyplot as plt

    path = _target("figures", artifact_id, ".png")
    fig.savefig(path, metadata={"Software": None}, bbox_inches="tight")
    plt.close(fig)
    try:
        from IPython.display import Image
    except ImportError:  # pragma: no cover - outside Jupyter
        return path
    return Image(filename=str(path))


def save_table(df: pd.DataFrame, artifact_id: str, float_format: str = "%.6f") -> Path:
    """Write ``df`` to ``data/<artifact_id>.csv`` with a fixed float format; return the path."""
    if not isinstance(df, pd.DataFrame):
        raise TypeError(f"df must be a pandas DataFrame, got {type(df).__name__}")
    path = _target("data", artifact_id, ".csv")
    df.to_csv(path, index=False, float_format=float_format, lineterminator="\n")
    return path


def show_table(df: pd.DataFrame, float_format: str = "{:.4f}") -> None:
    """Print a DataFrame with fixed float precision (stable notebook output)."""
    with pd.option_context("display.width", 200, "display.max_columns", 50, "display.max_rows", 500):
        print(df.to_string(index=False, float_format=float_format.format))
