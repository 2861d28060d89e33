"""Execute notebooks in place, in order, with outputs saved (used by ``make reproduce``).

Usage: ``python tools/run_notebooks.py notebooks/00_*.ipynb ...``

Each notebook runs in a fresh kernel of the current environment (the
``python3`` kernel of the interpreter running this script) with its folder as
working directory. Timing metadata is not recorded, so re-running gives the
same file when the computation is deterministic. Any cell error stops the run
with a non-zero exit code.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import nbformat
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError


def run(path: Path) -> None:
    nb = nbformat.read(path, as_version=4)
    client = NotebookClient(nb, timeout=1800, kernel_name="python3", record_timing=False,
                            resources={"metadata": {"path": str(path.parent)}})
    client.execute()
    nb.metadata.pop("widgets", None)
    nbformat.write(nb, path)


def main(argv: list[str]) -> int:
    paths = [Path(p) for p in argv] or sorted(Path("notebooks").glob("[0-9][0-9]_*.ipynb"))
    if not paths:
        print("run_notebooks: no notebooks given", file=sys.stderr)
        return 2
    for path in sorted(paths):
        start = time.perf_counter()
        try:
            run(path)
        except CellExecutionError as exc:
            print(f"run_notebooks: {path} failed:\n{exc}", file=sys.stderr)
            return 1
        print(f"{path}: executed in {time.perf_counter() - start:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
