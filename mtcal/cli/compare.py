"""``mtcal compare``: comparison tables of several runs side by side, with bands and claim flips.

``mtcal compare runs/A runs/B [runs/C ...]`` (``committed`` stands for the
committed results in the repository's ``data/``) joins every
``data/*_comparison.csv`` of the runs on (table, artifact, quantity), prints the
claims that flip first (holds True→False …, "none" when none), then the
quantities whose value or claim differs (``--all``: every quantity), and saves the full table to
``compare_<names>.csv`` (with each claim's threshold read from its text and
whether that reading reproduces every run's verdict) and a figure to
``compare_<names>.png`` — each claim quantity of every run against the claim's
threshold (flipped claims first), then the numeric quantities relative to the
first run (in ``--out``, default: the first run's parent folder). Runs that
differ in size (``--size ci`` vs the full-size committed results) or seed
(``params.json``) are refused unless ``--allow-mismatch``, which compares them
with a warning.
"""

from __future__ import annotations

import sys


def cmd_compare(args) -> int:
    import pandas as pd

    from mtcal.runs.compare import compare_runs

    names = args.names.split(",") if args.names else None
    if len(args.runs) < 2:
        raise ValueError(f"runs must list at least two run folders (or 'committed'), got {args.runs}")
    table, csv_path, png_path = compare_runs(args.runs, names=names, out_dir=args.out,
                                             allow_mismatch=args.allow_mismatch)
    for warning in table.attrs.get("warnings", []):  # loud: before and after the table
        print(f"mtcal: WARNING: {warning}", file=sys.stderr)
    labels = [c.split("[", 1)[1][:-1] for c in table.columns if c.startswith("mtcal [")]
    values = table[[f"mtcal [{n}]" for n in labels]]
    holds = table[[f"holds [{n}]" for n in labels]]
    differs = (values.nunique(axis=1) > 1) | (holds.nunique(axis=1) > 1)
    shown = (table if args.all else table[differs]).copy()
    view = pd.DataFrame({"notebook": shown["table"].str.replace("_comparison", "", regex=False),
                         "artifact": shown["artifact"], "quantity": shown["quantity"].str.slice(0, 60),
                         "paper": shown["paper"]})
    mark = {"True": " ✓", "False": " ✗"}
    for n in labels:  # one column per run: value [95 % band] and whether the claim holds
        view[n] = [f"{v}{' ' + b if b else ''}{mark.get(h, '')}" for v, b, h in
                   zip(shown[f"mtcal [{n}]"], shown[f"band [{n}]"], shown[f"holds [{n}]"])]
    flips = table[table["flips"] != ""]          # the headline first: claims that flip, "none" when none
    print(f"claims that flip ({len(flips)}):" if len(flips) else "claims that flip: none")
    for r in flips.itertuples():
        print(f"  {r.table} | {r.artifact} | {r.quantity} | {r.claim} | {r.flips}")
    with pd.option_context("display.width", 250, "display.max_columns", 50, "display.max_rows", 1000,
                           "display.max_colwidth", 60):
        print(f"{int(differs.sum())} of {len(table)} quantities differ between {', '.join(labels)}"
              f" (value [95 % band], ✓/✗ claim holds/fails)")
        if len(view):
            print(view.to_string(index=False))
    print(f"saved: {csv_path}" + (f", {png_path}" if png_path else ""))
    if table.attrs.get("warnings"):
        print(f"WARNING: {len(table.attrs['warnings'])} comparability warning(s), see stderr")
    return 0


def register(subparsers) -> None:
    """Add the ``compare`` subcommand to the ``mtcal`` dispatcher."""
    p = subparsers.add_parser("compare", help="comparison tables of runs side by side (bands, claim flips)",
                              description=__doc__.split("\n\n")[0])
    p.add_argument("runs", nargs="+", help="run folders (runs/NAME) or 'committed'")
    p.add_argument("--names", help="comma-separated labels for the runs (default: folder names)")
    p.add_argument("--out", help="folder for compare_<names>.csv/.png (default: the first run's parent)")
    p.add_argument("--all", action="store_true", help="print every quantity, not only those that differ")
    p.add_argument("--allow-mismatch", action="store_true",
                   help="compare runs that differ in size (ci/full) or seed, with a warning (default: refuse)")
    p.set_defaults(func=cmd_compare)
