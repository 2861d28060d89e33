"""``mtcal run``: run one notebook with changed parameters into its own folder (a what-if run).

``mtcal run NN [--name NAME] [-p key=value ...] [--size ci|full]`` executes
notebook NN (number or stem, e.g. ``10`` or ``10_wang2023cja_turntable``) with
papermill, injecting the parameters after its ``parameters`` cell, into
``runs/NAME/``: the executed notebook, its ``data/`` and ``figures/`` and
``params.json``. The committed notebooks, ``data/`` and ``figures/`` are never
written (only ``make reproduce`` writes them). Values are Python literals
(``-p N_TRIALS=200 -p fs_hz=500.0 -p positions_deg="(8, -8)" -p flag=True``);
anything else is a string (``-p gyro_grade=industrial``). An unknown name or a
value of the wrong type is rejected before anything runs, with the valid names.
At the paper's settings the notebook asserts its claims; in a what-if run it
reports them, and this command prints which claims hold. While the notebook runs,
a line per executed cell goes to stderr (``NN_x: cell 12/40 [01:23]``, also when
stderr is not a terminal; ``--no-progress``: none).
"""

from __future__ import annotations

import sys
import time


def cmd_run(args) -> int:
    try:
        from mtcal.runs import notebooks
        import papermill  # noqa: F401
        import jupytext  # noqa: F401
    except ImportError as exc:
        raise ValueError(f"mtcal run needs papermill and jupytext (pip install 'mtcal[notebooks]'): {exc}")
    params = dict(notebooks.parse_parameter(p) for p in args.parameter)
    if args.list:
        source = notebooks.resolve_notebook(args.notebook, args.notebooks_dir)
        for name, p in notebooks.notebook_parameters(source).items():
            print(f"{name} = {p['default']}" + (f"  # {p['help']}" if p.get("help") else "")
                  + _valid_values(name, p))
        return 0
    print(f"running notebook {args.notebook} at size {args.size}"
          + (" (full size: minutes; '--size ci' for a quick run, and compare runs of the same size)"
             if args.size == "full" else "") + " ...", flush=True)
    start = time.perf_counter()
    try:
        result = notebooks.run_notebook(args.notebook, name=args.name, parameters=params, size=args.size,
                                        runs_dir=args.runs_dir, notebooks_dir=args.notebooks_dir,
                                        overwrite=args.force, progress_bar=not args.no_progress)
    except notebooks.NotebookRunError as exc:
        print(f"mtcal: error: {exc}", file=sys.stderr)
        return 1
    print(f"run folder: {result.folder} (finished in {time.perf_counter() - start:.0f} s)")
    print(f"notebook:   {result.notebook}")
    print(result.claims)
    return 0


def _valid_values(name: str, p: dict) -> str:
    """``; valid: …`` for a parameter whose values come from a catalogue (sensor grades), else ''."""
    if name.endswith("grade") or "sensor_grades" in p.get("help", ""):
        from mtcal.core.sensor_grades import grade_names

        return f"; valid: {', '.join(grade_names())}"
    return ""


def register(subparsers) -> None:
    """Add the ``run`` subcommand to the ``mtcal`` dispatcher."""
    p = subparsers.add_parser("run", help="run a notebook with changed parameters into runs/NAME/ (what-if run)",
                              description=__doc__.split("\n\n")[0])
    p.add_argument("notebook", help="notebook number or stem, e.g. 10 or 10_wang2023cja_turntable")
    p.add_argument("--name", help="run folder name under --runs-dir (default: NN_<parameters>)")
    p.add_argument("-p", "--parameter", action="append", default=[], metavar="KEY=VALUE",
                   help="parameter override (Python literal, else a string); repeatable")
    p.add_argument("--size", choices=("ci", "full"), default="full", help="run size (default: full)")
    p.add_argument("--runs-dir", default="runs", help="parent folder of the runs (default: ./runs)")
    p.add_argument("--notebooks-dir", help="folder with the NN_*.py notebook sources (default: the checkout's)")
    p.add_argument("--force", action="store_true", help="replace an existing run folder of the same name")
    p.add_argument("--list", action="store_true", help="list the notebook's parameters and defaults, run nothing")
    p.add_argument("--no-progress", action="store_true",
                   help="no progress lines (default: a line per executed cell on stderr, 'NN_x: cell 12/40 [01:23]')")
    p.set_defaults(func=cmd_run)


def cmd_reproduce(args) -> int:
    """``mtcal reproduce ID``: rebuild one figure/table from the Monte Carlo cache."""
    start = time.perf_counter()
    try:
        from mtcal.runs import artifact
        from mtcal.runs.notebooks import NotebookRunError
    except ImportError as exc:
        raise ValueError(f"mtcal reproduce needs papermill and jupytext (pip install 'mtcal[notebooks]'): {exc}")
    try:
        result = artifact.rebuild_artifact(args.artifact, size=args.size, out_dir=args.out, cache_dir=args.cache)
    except NotebookRunError as exc:
        print(f"mtcal: error: {exc}", file=sys.stderr)
        return 1
    for path, status in result.files.items():
        print(f"{path}: {status}" + (" (byte-identical to the file it replaces)" if status == "identical" else ""))
    print(f"rebuilt {args.artifact} in {time.perf_counter() - start:.1f} s (cells of {result.notebook})")
    if args.check and any(s != "identical" for s in result.files.values()):
        print(f"mtcal: error: {args.artifact} differs from the file it replaces", file=sys.stderr)
        return 1
    return 0


def register_reproduce(subparsers) -> None:
    """Add the ``reproduce`` subcommand (one artifact from the cache) to the ``mtcal`` dispatcher."""
    p = subparsers.add_parser("reproduce", help="rebuild one figure or table from the Monte Carlo cache",
                              description="Rebuild one artifact (catalogue ID, e.g. wang2023cja_fig07) by running "
                                          "its notebook up to its section with the Monte Carlo results cached by "
                                          "`make reproduce` (build/cache); byte-identical to the full run.")
    p.add_argument("artifact", help="artifact ID from docs/artifacts.md, e.g. wang2023cja_fig07")
    p.add_argument("--size", choices=("ci", "full"), default="full", help="run size (default: full, as committed)")
    p.add_argument("--out", help="root folder receiving figures/ and data/ (default: the checkout)")
    p.add_argument("--cache", help="Monte Carlo cache folder (default: build/cache of the checkout)")
    p.add_argument("--check", action="store_true", help="exit 1 when the rebuilt file differs from the existing one")
    p.set_defaults(func=cmd_reproduce)
