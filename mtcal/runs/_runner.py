"""Child process of :func:`mtcal.runs.executor.execute_jobs`: execute one notebook, report one line.

``python -m mtcal.runs._runner '<json spec>'`` with keys ``source``, ``output``, ``parameters``,
``cwd``, ``timeout_s``, ``mode``, ``progress`` (a line per executed cell on stderr, prefixed
``mtcal-progress: ``; the parent forwards them). Exit 0 when the notebook ran; else exit 1 with one line on stderr
(``mtcal-runner: <error>``), never a traceback. The process's cwd and environment were set by
the parent for this notebook only.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

PROGRESS_PREFIX = "mtcal-progress: "   # = mtcal.runs.executor.PROGRESS_PREFIX (tested)


class _ProgressLines:
    """A file for papermill's tqdm bar that writes each update as one line on stderr.

    tqdm redraws its bar in place with ``\\r`` (no newline when stderr is not a terminal, so a log
    or a pipe would get nothing until the end); here every redraw becomes a prefixed line.
    """

    def __init__(self, stem: str):
        self.stem = stem
        self.last = ""

    def write(self, text: str) -> None:
        for part in text.replace("\n", "\r").split("\r"):
            part = part.strip()
            if part and part.split(" [")[0] != self.last:   # one line per cell (not tqdm's final refresh)
                self.last = part.split(" [")[0]
                sys.stderr.write(f"{PROGRESS_PREFIX}{self.stem}: {part}\n")
                sys.stderr.flush()

    def flush(self) -> None:
        sys.stderr.flush()


def _progress_bar(stem: str) -> dict:
    """papermill ``progress_bar`` settings: a line per executed cell, ``cell 12/40 [01:23]``."""
    return {"file": _ProgressLines(stem), "bar_format": "cell {n_fmt}/{total_fmt} [{elapsed}]",
            "mininterval": 0, "miniters": 1, "ascii": True, "dynamic_ncols": False}


def _run_script(spec: dict) -> None:
    """Execute the notebook's code cells in this process, in order (no kernel: ``mode="script"``).

    Parameters are assigned after the ``parameters`` cell as papermill would inject them; the
    cells run in one namespace with IPython's ``display``; the executed notebook is not written
    (``output`` gets the cell sources only). A failing cell raises NotebookRunError with one line.
    """
    import os

    import jupytext
    from IPython.display import display

    from mtcal.runs.notebooks import NotebookRunError

    source = Path(spec["source"])
    os.chdir(spec.get("cwd") or source.parent)  # this process runs this one notebook only
    nb = jupytext.read(source, fmt="py:percent")
    namespace = {"__name__": "__main__", "display": display}
    parameters = spec.get("parameters") or {}
    number = 0
    total = sum(cell.cell_type == "code" for cell in nb.cells)
    start = time.perf_counter()
    for cell in nb.cells:
        if cell.cell_type != "code":
            continue
        number += 1
        if spec.get("progress"):
            minutes, seconds = divmod(int(time.perf_counter() - start), 60)
            print(f"{PROGRESS_PREFIX}{source.stem}: cell {number}/{total} [{minutes:02d}:{seconds:02d}]",
                  file=sys.stderr, flush=True)
        try:
            exec(compile(cell.source, f"{source.name}:cell{number}", "exec"), namespace)  # noqa: S102
        except Exception as exc:  # noqa: BLE001 - one line, as execute_notebook reports it
            first = str(exc).splitlines()[0] if str(exc) else ""
            raise NotebookRunError(f"{source.stem} failed in cell {number}: {type(exc).__name__}: {first}; "
                                   f"the cells ran as a script ({source})", source) from None
        if "parameters" in cell.metadata.get("tags", []):
            namespace.update(parameters)


def main(argv: list[str]) -> int:
    spec = None
    try:
        spec = json.loads(argv[0])
        from mtcal.runs.notebooks import NotebookRunError, execute_notebook

        if spec.get("mode", "kernel") == "script":
            _run_script(spec)
        else:
            progress = _progress_bar(Path(spec["source"]).stem) if spec.get("progress") else False
            execute_notebook(spec["source"], spec["output"], parameters=spec.get("parameters") or None,
                             cwd=spec.get("cwd"), timeout_s=float(spec.get("timeout_s", 3600.0)),
                             progress_bar=progress)
    except NotebookRunError as exc:
        print(f"mtcal-runner: {str(exc).splitlines()[0]}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("mtcal-runner: interrupted", file=sys.stderr)
        return 1
    except Exception as exc:  # noqa: BLE001 - the one-line contract: never a traceback
        text = str(exc).splitlines()[0] if str(exc) else ""
        stem = Path(str(spec.get("source", "notebook"))).stem if isinstance(spec, dict) else "notebook"
        where = spec.get("output", "?") if isinstance(spec, dict) else "?"
        print(f"mtcal-runner: {stem} stopped: {type(exc).__name__}: {text}; the partially executed notebook is "
              f"{where}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
