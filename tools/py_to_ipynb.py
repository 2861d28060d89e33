"""Build ``notebooks/NN_*.ipynb`` from their ``py:percent`` sources ``notebooks/NN_*.py``.

The ``.py`` file is the reviewed source (clean diffs); the ``.ipynb`` is what
``make reproduce`` executes and commits with outputs, and what nbval checks.
Cell markers (jupytext-compatible subset)::

    # %% [markdown]          markdown cell; each line starts with "# "
    # %% tags=["parameters"] code cell carrying the papermill parameters tag
    # %%                     code cell

Outputs of an existing notebook are kept for cells whose source is unchanged,
so regenerating does not discard results. Usage:
``python tools/py_to_ipynb.py notebooks/00_conventions_and_errata.py ...``
(no argument: every ``notebooks/[0-9][0-9]_*.py``).
"""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

import nbformat

_MARKER = re.compile(r"^# %%(?P<md> \[markdown\])?(?: tags=(?P<tags>\[.*\]))?\s*$")


def parse(text: str) -> list[nbformat.NotebookNode]:
    cells, kind, tags, lines = [], None, [], []

    def flush():
        if kind is None:
            return
        body = "\n".join(lines).strip("\n")
        if kind == "markdown":
            body = "\n".join(re.sub(r"^# ?", "", ln) for ln in body.splitlines())
            cells.append(nbformat.v4.new_markdown_cell(body))
        else:
            cell = nbformat.v4.new_code_cell(body)
            if tags:
                cell.metadata["tags"] = tags
            cells.append(cell)

    for line in text.splitlines():
        m = _MARKER.match(line)
        if m:
            flush()
            kind = "markdown" if m.group("md") else "code"
            tags = json.loads(m.group("tags")) if m.group("tags") else []
            lines = []
        elif kind is not None:
            lines.append(line)
    flush()
    return cells


def build(src: Path) -> Path:
    dst = src.with_suffix(".ipynb")
    cells = parse(src.read_text(encoding="utf-8"))
    old = {}
    if dst.exists():
        for c in nbformat.read(dst, as_version=4).cells:
            if c.cell_type == "code":
                old.setdefault(c.source, c)
    for i, c in enumerate(cells):
        c.id = f"cell-{i:03d}"
        if c.cell_type == "code" and c.source in old:
            c.outputs = old[c.source].outputs
            c.execution_count = old[c.source].execution_count
    nb = nbformat.v4.new_notebook(cells=cells)
    nb.metadata = {"kernelspec": {"display_name": "Python 3", "language": "python", "name": "python3"},
                   "language_info": {"name": "python"}}
    nbformat.write(nb, dst)
    return dst


def main(argv: list[str]) -> int:
    srcs = [Path(a) for a in argv] or sorted(Path("notebooks").glob("[0-9][0-9]_*.py"))
    for src in srcs:
        print(f"{src} -> {build(src)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
