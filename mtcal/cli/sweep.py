"""``mtcal sweep SPEC.toml``: a parameter sweep on local cores or a Dask cluster.

* ``mtcal sweep SPEC.toml`` — every cell of the spec's grid × its trials on all
  local cores; the run folder (default ``runs/sweeps/<name>``) gets
  ``sweep.json``, one ``cells/cell_NNNNN.npz`` per finished cell and ``table.csv``
  (one row per cell and metric: median, low/high — the 95 % band from >= 1000 trials, else
  the min–max range, named in ``band`` — and trials) and ``table.png`` (each
  metric vs the numeric swept parameter, one panel per metric, with its band or range); a progress bar over cells
  on a terminal (``--no-progress``). Run the same command again after an
  interruption: stored cells are skipped.
* ``--workers N`` — N local processes (1 = in this process).
* ``--scheduler tcp://host:8786`` — run the tasks on a running Dask cluster
  instead; the numbers are identical.
* ``--out DIR`` — the run folder.
* ``--list`` — list the scenario evaluators and their parameters (defaults).

Spec format: see ``examples/sweeps/*.toml`` and :mod:`mtcal.sweep.spec`.
Errors (bad spec key or value, a folder holding another sweep, an unreachable
scheduler) print ``mtcal: error: …`` and exit with status 2.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

__all__ = ["register", "cmd_sweep"]


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a positive integer, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be a positive integer, got {text!r}")
    return value


def _list_evaluators() -> int:
    from mtcal.sweep.evaluators import evaluator_names, get_evaluator, parameter_help

    for name in evaluator_names():
        ev = get_evaluator(name)
        print(f"{name}: {ev.description}")
        for key, value in ev.defaults.items():
            print(f"    {key + ' = ' + json.dumps(value):<44} # {parameter_help(key)}")
    return 0


def cmd_sweep(args: argparse.Namespace) -> int:
    """Run the sweep and print where the table went plus a short summary."""
    from mtcal.sweep.engine import run_sweep
    from mtcal.sweep.spec import load_spec

    if args.list:
        return _list_evaluators()
    if args.spec is None:
        raise ValueError("a spec file is required (or --list)")
    if args.scheduler is not None and args.workers is not None:
        raise ValueError("give either --workers (local processes) or --scheduler (Dask cluster), not both")
    spec = load_spec(args.spec)
    out = Path(args.out) if args.out else Path("runs") / "sweeps" / spec.name
    if out.exists() and not out.is_dir():
        raise ValueError(f"--out {out} exists and is not a folder")
    progress = False if args.no_progress else None  # None: a bar over cells on a terminal unless MTCAL_PROGRESS=0
    try:
        res = run_sweep(spec, out, workers=args.workers, scheduler=args.scheduler, progress=progress)
    except ImportError as exc:      # an optional extra missing: one line naming the option and the extra
        raise ValueError(f"--scheduler {args.scheduler}: {exc}" if args.scheduler is not None else str(exc)) from None
    from mtcal.sweep.plots import sweep_figure

    from mtcal.sweep.plots import x_parameter, band_text

    figure = sweep_figure(res.table, list(spec.grid), out / "table.png", title=spec.name)
    print(f"sweep {spec.name}: {spec.n_cells} cells x {spec.trials} trials, evaluator {spec.evaluator}, "
          f"seed {spec.seed}")
    print(f"ran on {res.executor}: {len(res.computed)} cells computed, {len(res.skipped)} already stored")
    print(f"table: {out / 'table.csv'} ({len(res.table)} rows)")
    print(f"figure: {figure} (each metric vs {x_parameter(res.table, list(spec.grid)) or 'cell'}, median and "
          f"{band_text(res.table)})")
    return 0


def register(subparsers) -> None:
    """Add the ``sweep`` subcommand to the ``mtcal`` dispatcher."""
    p = subparsers.add_parser("sweep", help="parameter sweep (grid x Monte Carlo trials) on local cores or Dask",
                              description=__doc__.split("\n\n")[0])
    p.add_argument("spec", nargs="?", help="sweep spec (TOML)")
    p.add_argument("--workers", type=_positive_int, help="local worker processes (default: every core)")
    p.add_argument("--scheduler", help="Dask scheduler address, e.g. tcp://host:8786 (needs the optional sweep "
                   "extra: pip install 'mtcal[sweep]', from a checkout '.[sweep]') (default: none, local "
                   "processes)")
    p.add_argument("--out", help="run folder (default: runs/sweeps/<name>)")
    p.add_argument("--list", action="store_true", help="list the evaluators and their parameters")
    p.add_argument("--no-progress", action="store_true",
                   help="no progress bar (default: a bar over cells on a terminal, unless MTCAL_PROGRESS=0)")
    p.set_defaults(func=cmd_sweep)
