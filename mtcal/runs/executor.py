"""Parallel-safe notebook execution: every notebook in its own process, cwd and environment.

``make reproduce`` (``tools/notebooks.py execute``), ``mtcal run`` and ``mtcal reproduce``
execute notebooks through :func:`execute_jobs`. Each :class:`NotebookJob` runs in a
separate Python process (``python -m mtcal.runs._runner``) started with its own working
directory and its own environment, which starts the notebook's kernel: nothing of one
job (papermill's ``chdir``, environment variables) can leak into another, so ``--jobs 2``
gives the same files as ``--jobs 1``. A failing notebook is reported as **one line**
naming its partially executed notebook and the error's last line — never a traceback —
and no new job starts after the first failure (``stop_on_failure``).
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import tempfile
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

__all__ = ["NotebookJob", "JobResult", "execute_jobs", "failure_line", "longest_first", "PROGRESS_PREFIX"]

#: Prefix of the child's progress lines on its stderr (:attr:`NotebookJob.progress`).
PROGRESS_PREFIX = "mtcal-progress: "


@dataclass(frozen=True)
class NotebookJob:
    """One notebook to execute.

    Parameters
    ----------
    source : path
        ``NN_x.py`` py:percent source (the ``.ipynb`` inputs are rebuilt from it).
    output : path
        Executed notebook to write (also written, partially, when a cell fails).
    parameters : dict
        Papermill parameters (injected after the ``parameters`` cell).
    env : dict
        Environment of this job's process and kernel on top of the caller's (a ``None``
        value unsets a variable), e.g. ``{"MTCAL_OUTPUT_DIR": "/path", "MTCAL_SIZE": "ci"}``.
    cwd : path, optional
        Working directory of the job's process and kernel (default: the source's folder).
    timeout_s : float
        Per-cell execution timeout, s.
    mode : {"kernel", "script"}
        ``kernel``: papermill with a Jupyter kernel, the executed notebook written to ``output``
        (``make reproduce``, ``mtcal run``); ``script``: the code cells executed in the job's
        process, no kernel, nothing written to ``output`` (``mtcal reproduce``: seconds faster;
        the files a notebook saves are the same bytes — tested).
    progress : bool
        Print a line per executed cell on this process's stderr while the job runs
        (``NN_x: cell 12/40 [01:23]``, papermill's progress as lines, also when stderr is not a
        terminal: ``mtcal run``). The executed notebook and the files are the same either way.
    """

    source: Path
    output: Path
    parameters: dict = field(default_factory=dict)
    env: dict = field(default_factory=dict)
    cwd: Path | None = None
    timeout_s: float = 3600.0
    mode: str = "kernel"
    progress: bool = False


@dataclass(frozen=True)
class JobResult:
    """Outcome of a :class:`NotebookJob`: ``status`` is ``ok``, ``failed`` or ``skipped`` (not started
    after an earlier failure); ``error`` the one-line message (``""`` when ok); ``seconds`` the wall
    time; ``peak_rss_mb`` the peak resident memory of the largest single process of the job's tree
    (its kernel; MiB, from ``wait4``; NaN when not started). Linux counts a child from its parent's
    size at ``fork``, so the figure is at least the calling process's size: call from a small process
    (``tools/notebooks.py``) to measure the notebooks."""

    job: NotebookJob
    status: str
    error: str = ""
    seconds: float = 0.0
    peak_rss_mb: float = math.nan

    @property
    def ok(self) -> bool:
        return self.status == "ok"


def failure_line(stem: str, output: Path | str, stderr: str) -> str:
    """One line for a failed notebook: the runner's own line, else the stem, the last line of the
    process's stderr and the partial notebook's path.

    >>> failure_line("10_x", "nb/10_x.ipynb", "Traceback (most recent call last):\\n  ...\\nKeyError: 'a'\\n")
    "10_x stopped: KeyError: 'a'; the partially executed notebook is nb/10_x.ipynb"
    >>> failure_line("10_x", "nb/10_x.ipynb", "mtcal-runner: 10_x failed in cell 3: ValueError: v; the ...\\n")
    '10_x failed in cell 3: ValueError: v; the ...'
    """
    lines = [ln.strip() for ln in stderr.splitlines() if ln.strip()]
    if lines and lines[-1].startswith("mtcal-runner: "):
        return lines[-1].removeprefix("mtcal-runner: ")
    last = lines[-1] if lines else "the notebook process ended without a message"
    return f"{stem} stopped: {last}; the partially executed notebook is {output}"


def _child_env(job: NotebookJob) -> dict[str, str]:
    from mtcal.runs.environment import numerics_env

    env = dict(os.environ)
    # the child imports the same mtcal as this process (a checkout run with PYTHONPATH, or an install)
    package_root = str(Path(__file__).resolve().parents[2])
    env["PYTHONPATH"] = os.pathsep.join([package_root] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep)
                                                          if p and p != package_root])
    env.update(numerics_env())
    env.update({"MTCAL_PROGRESS": "0", "PYDEVD_DISABLE_FILE_VALIDATION": "1"})
    for key, value in job.env.items():
        if value is None:
            env.pop(key, None)
        else:
            env[key] = str(value)
    return env


def _run_one(job: NotebookJob) -> JobResult:
    source = Path(job.source).resolve().with_suffix(".py")
    output = Path(job.output).resolve()
    cwd = Path(job.cwd).resolve() if job.cwd else source.parent
    spec = {"source": str(source), "output": str(output), "parameters": job.parameters, "cwd": str(cwd),
            "timeout_s": job.timeout_s, "mode": job.mode, "progress": bool(job.progress)}
    start = time.perf_counter()
    # output to files and the child reaped by wait4: its rusage (ru_maxrss covers the child and its
    # reaped descendants, i.e. the notebook's kernel) is the job's peak memory
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        child = subprocess.Popen([sys.executable, "-m", "mtcal.runs._runner", json.dumps(spec)], cwd=cwd,
                                 env=_child_env(job), stdin=subprocess.DEVNULL, stdout=out,
                                 stderr=subprocess.PIPE if job.progress else err, text=True)
        reader = None
        if job.progress:  # progress lines go on at once, everything else is kept for the failure line
            reader = threading.Thread(target=_forward_progress, args=(child.stderr, err), daemon=True)
            reader.start()
        _, wait_status, usage = os.wait4(child.pid, 0)
        child.returncode = os.waitstatus_to_exitcode(wait_status)
        if reader is not None:
            reader.join()
            child.stderr.close()
        err.seek(0)
        stderr = err.read()
    seconds = time.perf_counter() - start
    peak_mb = usage.ru_maxrss / 1024.0
    if child.returncode == 0:
        return JobResult(job, "ok", "", seconds, peak_mb)
    return JobResult(job, "failed", failure_line(source.stem, job.output, stderr), seconds, peak_mb)


def _forward_progress(stream, keep) -> None:
    """Copy the child's stderr: ``mtcal-progress: …`` lines to this process's stderr at once
    (without the prefix), every other line to ``keep``."""
    for line in stream:
        if line.startswith(PROGRESS_PREFIX):
            print(line.removeprefix(PROGRESS_PREFIX).rstrip("\n"), file=sys.stderr, flush=True)
        else:
            keep.write(line)


def longest_first(jobs: list[NotebookJob], seconds: dict[str, float]) -> list[NotebookJob]:
    """``jobs`` reordered by a previous run's wall time, longest first (the shortest makespan for
    parallel jobs of known length, greedily); jobs without a time keep their order, after the timed ones.

    The outputs do not depend on the order (each job in its own process, seeded), only the wall time.

    Parameters
    ----------
    jobs : list of NotebookJob
    seconds : dict of str → float
        Previous wall time (s) per source stem (``10_x`` for ``notebooks/10_x.py``).

    Returns
    -------
    list of NotebookJob

    Examples
    --------
    >>> jobs = [NotebookJob(Path(f"{s}.py"), Path(f"{s}.ipynb")) for s in ("a", "b", "c")]
    >>> [j.source.stem for j in longest_first(jobs, {"a": 5.0, "c": 40.0})]
    ['c', 'a', 'b']
    """
    timed = [j for j in jobs if Path(j.source).stem in seconds]
    timed.sort(key=lambda j: -float(seconds[Path(j.source).stem]))   # stable: ties keep their order
    return timed + [j for j in jobs if Path(j.source).stem not in seconds]


def execute_jobs(jobs: list[NotebookJob], *, n_jobs: int = 2, stop_on_failure: bool = True,
                 on_result=None) -> list[JobResult]:
    """Execute notebooks, ``n_jobs`` at a time, each in its own process (see module docstring).

    Parameters
    ----------
    jobs : list of NotebookJob
        Notebooks to execute, started in this order.
    n_jobs : int
        Notebooks executed at the same time (≥ 1).
    stop_on_failure : bool
        Start no new job after the first failure (those are returned as ``skipped``).
    on_result : callable, optional
        Called with each :class:`JobResult` as it finishes (e.g. to print progress).

    Returns
    -------
    list of JobResult
        One per job, in the order of ``jobs``.

    Examples
    --------
    >>> execute_jobs([], n_jobs=2)
    []
    >>> execute_jobs([], n_jobs=0)
    Traceback (most recent call last):
    ...
    ValueError: n_jobs must be an integer >= 1, got 0
    """
    if isinstance(n_jobs, bool) or not isinstance(n_jobs, int) or n_jobs < 1:
        raise ValueError(f"n_jobs must be an integer >= 1, got {n_jobs!r}")
    jobs = list(jobs)
    for job in jobs:
        if not isinstance(job, NotebookJob):
            raise TypeError(f"jobs must be NotebookJob instances, got {type(job).__name__}")
        if job.mode not in ("kernel", "script"):
            raise ValueError(f"NotebookJob.mode must be 'kernel' or 'script', got {job.mode!r}")
    failed = threading.Event()

    def guarded(job: NotebookJob) -> JobResult:
        if stop_on_failure and failed.is_set():
            return JobResult(job, "skipped", f"{Path(job.source).stem}: not started after an earlier failure")
        result = _run_one(job)
        if not result.ok:
            failed.set()
        if on_result is not None:
            on_result(result)
        return result

    with ThreadPoolExecutor(max_workers=n_jobs) as pool:  # threads only wait on child processes
        return list(pool.map(guarded, jobs))
