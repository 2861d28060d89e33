"""Child process of :func:`mtcal.runs.executor.execute_jobs`: execute one notebook, report one line.

``python -m mtcal.runs._runner '<json spec>'`` with keys ``source``, ``output``, ``parameters``,
``cwd``, ``timeout_s``. Exit 0 when the notebook ran; else exit 1 with one line on stderr
(``mtcal-runner: <error>``), never a traceback. The process's cwd and environment were set by
the parent for this notebook only.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path


def main(argv: list[str]) -> int:
    spec = None
    try:
        spec = json.loads(argv[0])
        from mtcal.runs.notebooks import NotebookRunError, execute_notebook

        execute_notebook(spec["source"], spec["output"], parameters=spec.get("parameters") or None,
                         cwd=spec.get("cwd"), timeout_s=float(spec.get("timeout_s", 3600.0)))
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
