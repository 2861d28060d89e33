"""Runs: executing the notebooks (``make reproduce``, what-if runs) and comparing runs.

The top layer below the command line: it executes notebooks that use every other
layer, so ``import mtcal`` does not load it (``from mtcal import runs`` does).

* :mod:`mtcal.runs.environment` — the pinned numerics environment of every run
* :mod:`mtcal.runs.notebooks` — build, sync and execute notebooks; what-if runs (``mtcal run``)
* :mod:`mtcal.runs.executor` — notebooks executed in parallel, each in its own process (cwd, environment)
* :mod:`mtcal.runs.compare` — comparison tables of several runs side by side (``mtcal compare``)
"""

from mtcal.runs import compare, environment, executor, notebooks
from mtcal.runs.compare import compare_runs, flip_text, load_comparisons
from mtcal.runs.environment import numerics_env, repo_root
from mtcal.runs.executor import JobResult, NotebookJob, execute_jobs
from mtcal.runs.notebooks import (NotebookRunError, RunResult, build_notebook, check_parameters, execute_notebook,
                                  normalise_notebook, notebook_parameters, notebook_sources, parse_parameter,
                                  resolve_notebook, run_notebook, sync_notebook)

__all__ = ["compare", "environment", "executor", "notebooks", "NotebookJob", "JobResult", "execute_jobs",
           "NotebookRunError", "numerics_env", "repo_root", "notebook_sources", "resolve_notebook",
           "parse_parameter", "notebook_parameters", "check_parameters", "build_notebook",
           "normalise_notebook", "sync_notebook", "execute_notebook", "run_notebook", "RunResult",
           "load_comparisons", "compare_runs", "flip_text"]
