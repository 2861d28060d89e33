"""The notebook executor: each notebook in its own process, cwd and environment; one-line failures."""

import json
import os
from pathlib import Path

import pytest

from mtcal.runs.executor import JobResult, NotebookJob, execute_jobs, failure_line

WRITER = '''# %% tags=["parameters"]
NAME = "x"
FAIL = False

# %%
import os, time
from pathlib import Path
out = Path(os.environ["MTCAL_OUTPUT_DIR"])
out.mkdir(parents=True, exist_ok=True)
time.sleep(1.0)  # both jobs are running at the same time here
(out / f"{NAME}.json").write_text(__import__("json").dumps(
    {"cwd": os.getcwd(), "tag": os.environ.get("JOB_TAG"), "name": NAME}))
Path("relative.txt").write_text(NAME)  # relative to the job's own cwd

# %%
if FAIL:
    raise ValueError("asked to fail\\nsecond line of the message")
'''


def _tree(root: Path) -> set[str]:
    return {str(p.relative_to(root)) for p in root.rglob("*") if p.is_file() and "__pycache__" not in p.parts}


def test_parallel_jobs_own_cwd_env_outputs_and_one_line_failure(tmp_path):
    src = tmp_path / "src"
    src.mkdir()
    (src / "01_writer.py").write_text(WRITER, encoding="utf-8")
    jobs = []
    for name, fail in (("a", False), ("b", True), ("c", False)):
        (tmp_path / name / "cwd").mkdir(parents=True)
        jobs.append(NotebookJob(src / "01_writer.py", tmp_path / name / "nb.ipynb", {"NAME": name, "FAIL": fail},
                                env={"MTCAL_OUTPUT_DIR": str(tmp_path / name / "out"), "JOB_TAG": f"tag-{name}"},
                                cwd=tmp_path / name / "cwd"))
    cwd_before, env_before = os.getcwd(), dict(os.environ)
    seen = []
    results = execute_jobs(jobs, n_jobs=2, stop_on_failure=False, on_result=seen.append)
    assert os.getcwd() == cwd_before and dict(os.environ) == env_before  # the caller's process untouched
    assert [r.status for r in results] == ["ok", "failed", "ok"] and len(seen) == 3
    for name in "abc":  # each job saw its own cwd and environment, wrote only its own folder
        record = json.loads((tmp_path / name / "out" / f"{name}.json").read_text())
        assert record == {"cwd": str(tmp_path / name / "cwd"), "tag": f"tag-{name}", "name": name}
        assert (tmp_path / name / "cwd" / "relative.txt").read_text() == name
        assert "injected-parameters" in (tmp_path / name / "nb.ipynb").read_text()
    err = results[1].error
    assert "\n" not in err and "Traceback" not in err
    assert err.startswith("01_writer failed in cell") and "ValueError" in err and "asked to fail" in err
    assert str(tmp_path / "b" / "nb.ipynb") in err and "second line" not in err
    assert _tree(tmp_path) == {"src/01_writer.py"} | {
        f"{n}/{f}" for n in "abc" for f in ("nb.ipynb", f"out/{n}.json", "cwd/relative.txt")}


def test_no_job_starts_after_a_failure(tmp_path):
    src = tmp_path / "02_fails.py"
    src.write_text('# %% tags=["parameters"]\nA = 1\n\n# %%\nraise ValueError("boom")\n', encoding="utf-8")
    jobs = [NotebookJob(src, tmp_path / "one.ipynb"), NotebookJob(src, tmp_path / "two.ipynb")]
    results = execute_jobs(jobs, n_jobs=1)
    assert [r.status for r in results] == ["failed", "skipped"]
    assert "ValueError: boom" in results[0].error and not (tmp_path / "two.ipynb").exists()
    assert "not started after an earlier failure" in results[1].error and not results[1].ok


def test_missing_source_is_one_line(tmp_path):
    result = execute_jobs([NotebookJob(tmp_path / "03_missing.py", tmp_path / "o.ipynb", cwd=tmp_path)])[0]
    assert result.status == "failed" and "\n" not in result.error
    assert result.error.startswith("03_missing stopped: FileNotFoundError")


def test_bad_arguments():
    with pytest.raises(ValueError, match="n_jobs must be an integer >= 1, got 0"):
        execute_jobs([], n_jobs=0)
    with pytest.raises(TypeError, match="jobs must be NotebookJob instances, got str"):
        execute_jobs(["x.py"])


def test_failure_line_from_a_crash_without_runner_line():
    line = failure_line("10_x", "nb/10_x.ipynb", "Traceback (most recent call last):\n  File...\nMemoryError\n")
    assert line == "10_x stopped: MemoryError; the partially executed notebook is nb/10_x.ipynb"
    assert "without a message" in failure_line("10_x", "o", "")
    assert JobResult(NotebookJob(Path("a.py"), Path("a.ipynb")), "ok").ok


def test_script_mode_runs_the_cells_in_the_job_process(tmp_path):
    src = tmp_path / "04_script.py"
    src.write_text(WRITER, encoding="utf-8")
    (tmp_path / "cwd").mkdir()
    env = {"MTCAL_OUTPUT_DIR": str(tmp_path / "out"), "JOB_TAG": "s"}
    ok, bad = execute_jobs([NotebookJob(src, src, {"NAME": "s"}, env=env, cwd=tmp_path / "cwd", mode="script"),
                            NotebookJob(src, src, {"NAME": "t", "FAIL": True}, env=env, cwd=tmp_path / "cwd",
                                        mode="script")], n_jobs=2, stop_on_failure=False)
    assert ok.ok and json.loads((tmp_path / "out" / "s.json").read_text())["cwd"] == str(tmp_path / "cwd")
    assert bad.error.startswith("04_script failed in cell 3: ValueError: asked to fail; the cells ran as a script")
    assert src.read_text(encoding="utf-8") == WRITER  # the source is never written in script mode
    with pytest.raises(ValueError, match="NotebookJob.mode must be 'kernel' or 'script', got 'thread'"):
        execute_jobs([NotebookJob(src, src, mode="thread")])


MEMORY = '''# %% tags=["parameters"]
MB = 0

# %%
import numpy as np
block = np.ones(MB * 2**17)  # MB MiB of float64, touched
'''


def test_peak_memory_of_the_job_is_recorded(tmp_path):
    import subprocess
    import sys

    (tmp_path / "01_mem.py").write_text(MEMORY, encoding="utf-8")
    # from a small parent process: ru_maxrss of a child starts at its parent's size at fork (this test's
    # pytest process can hold ~1 GB), as for `make reproduce`'s tools/notebooks.py
    code = ("import json, sys; from pathlib import Path; from mtcal.runs.executor import NotebookJob, execute_jobs; "
            "d = Path(sys.argv[1]); r = execute_jobs([NotebookJob(d / '01_mem.py', d / f'{n}.ipynb', {'MB': mb}) "
            "for n, mb in (('small', 1), ('large', 300))], n_jobs=2); "
            "print(json.dumps([[x.status, x.peak_rss_mb, x.error] for x in r]))")
    out = subprocess.run([sys.executable, "-c", code, str(tmp_path)], capture_output=True, text=True, check=True)
    (s_status, small, s_error), (l_status, large, l_error) = json.loads(out.stdout.splitlines()[-1])
    assert s_status == l_status == "ok", (s_error, l_error, out.stderr[-2000:])
    # the peak is the largest process of the job's tree: the large job's kernel (300 MiB of data on
    # top of numpy), the small job's runner or kernel (~150 MiB); both measured, neither NaN
    assert 300 < large < 800 and 50 < small < large - 150


def test_longest_first_orders_by_previous_time_and_keeps_untimed_jobs():
    from mtcal.runs.executor import longest_first

    jobs = [NotebookJob(Path(f"nb/{s}.py"), Path(f"nb/{s}.ipynb")) for s in ("00_a", "10_b", "11_c", "20_d")]
    order = longest_first(jobs, {"11_c": 60.0, "00_a": 8.0, "10_b": 80.0, "gone": 99.0})
    assert [j.source.stem for j in order] == ["10_b", "11_c", "00_a", "20_d"]
    assert longest_first(jobs, {}) == jobs


def test_progress_lines_are_forwarded_and_kept_out_of_the_failure_line(tmp_path, capsys):
    """A job with ``progress=True`` prints one line per executed cell on the caller's stderr while it
    runs (stderr is not a terminal under pytest); the failure line is still the runner's one line."""
    from mtcal.runs import _runner, executor

    assert _runner.PROGRESS_PREFIX == executor.PROGRESS_PREFIX
    src = tmp_path / "05_progress.py"
    src.write_text(WRITER.replace("time.sleep(1.0)", "pass"), encoding="utf-8")
    env = {"MTCAL_OUTPUT_DIR": str(tmp_path / "out")}
    ok, bad = execute_jobs([NotebookJob(src, src, {"NAME": "p"}, env=env, mode="script", progress=True),
                            NotebookJob(src, src, {"FAIL": True}, env=env, mode="script", progress=True)],
                           n_jobs=1, stop_on_failure=False)
    err = capsys.readouterr().err
    assert ok.ok and [ln for ln in err.splitlines() if ln.startswith("05_progress: cell 1/3")] != []
    assert "05_progress: cell 3/3 [00:0" in err and executor.PROGRESS_PREFIX not in err
    assert bad.error.startswith("05_progress failed in cell 3: ValueError: asked to fail")
    quiet = execute_jobs([NotebookJob(src, src, {"NAME": "q"}, env=env, mode="script")])[0]
    assert quiet.ok and capsys.readouterr().err == ""


def test_progress_lines_from_papermill_one_per_cell():
    """papermill's tqdm redraws (``\\r``, no newline off a terminal) become one prefixed line per cell."""
    import io
    import sys

    from mtcal.runs import _runner

    buffer, saved = io.StringIO(), sys.stderr
    sys.stderr = buffer
    try:
        lines = _runner._ProgressLines("10_x")
        for text in ("\rcell 0/3 [00:00]", "\rcell 1/3 [00:01]", "\rcell 1/3 [00:01]", "\rcell 3/3 [00:04]",
                     "\rcell 3/3 [00:05]\n"):
            lines.write(text)
    finally:
        sys.stderr = saved
    assert buffer.getvalue().splitlines() == ["mtcal-progress: 10_x: cell 0/3 [00:00]",
                                              "mtcal-progress: 10_x: cell 1/3 [00:01]",
                                              "mtcal-progress: 10_x: cell 3/3 [00:04]"]
