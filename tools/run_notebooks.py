"""Execute notebooks in place, in order, with outputs saved (used by ``make reproduce``).

Usage: ``python tools/run_notebooks.py [-p NAME=VALUE ...] [--output-dir DIR] notebooks/00_*.ipynb ...``

``-p NAME=VALUE`` overrides a parameter papermill-style: a cell tagged
``injected-parameters`` with ``NAME = VALUE`` (a Python literal) is inserted
after the ``parameters`` cell. ``--output-dir DIR`` writes the executed
notebooks there instead of in place (use it with ``-p`` so the committed
notebooks keep their default parameters).

Each notebook runs in a fresh kernel of the current environment (the
``python3`` kernel of the interpreter running this script) with its folder as
working directory. Timing metadata is not recorded, so re-running gives the
same file when the computation is deterministic. Any cell error stops the run
with a non-zero exit code.
"""

from __future__ import annotations

import argparse
import ast
import sys
import time
from pathlib import Path

import nbformat
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError


def inject(nb, params: dict[str, str]) -> None:
    """Insert ``NAME = VALUE`` lines after the cell tagged ``parameters``."""
    if not params:
        return
    idx = next((i for i, c in enumerate(nb.cells) if "parameters" in c.get("metadata", {}).get("tags", [])), None)
    if idx is None:
        raise ValueError("notebook has no cell tagged 'parameters'")
    for name, value in params.items():
        ast.literal_eval(value)  # only literals
        if not name.isidentifier():
            raise ValueError(f"parameter name must be an identifier, got {name!r}")
    cell = nbformat.v4.new_code_cell("\n".join(f"{k} = {v}" for k, v in params.items()))
    cell.metadata["tags"] = ["injected-parameters"]
    nb.cells.insert(idx + 1, cell)


def run(path: Path, params: dict[str, str] | None = None, output: Path | None = None) -> None:
    nb = nbformat.read(path, as_version=4)
    inject(nb, params or {})
    client = NotebookClient(nb, timeout=1800, kernel_name="python3", record_timing=False,
                            resources={"metadata": {"path": str(path.parent)}})
    client.execute()
    nb.metadata.pop("widgets", None)
    nbformat.write(nb, output or path)


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("notebooks", nargs="*", type=Path)
    parser.add_argument("-p", "--parameter", action="append", default=[], metavar="NAME=VALUE")
    parser.add_argument("--output-dir", type=Path)
    args = parser.parse_args(argv)
    params = dict(p.split("=", 1) for p in args.parameter)
    paths = args.notebooks or sorted(Path("notebooks").glob("[0-9][0-9]_*.ipynb"))
    if not paths:
        print("run_notebooks: no notebooks given", file=sys.stderr)
        return 2
    for path in sorted(paths):
        start = time.perf_counter()
        try:
            out = None
            if args.output_dir:
                args.output_dir.mkdir(parents=True, exist_ok=True)
                out = args.output_dir / path.name
            run(path, params, out)
        except CellExecutionError as exc:
            print(f"run_notebooks: {path} failed:\n{exc}", file=sys.stderr)
            return 1
        print(f"{path}: executed in {time.perf_counter() - start:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
