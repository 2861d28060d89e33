"""tools/notebooks.py execute --resources: per-notebook wall time and peak RSS, longest first next time."""

import csv
import importlib.util
import math
from pathlib import Path

from mtcal.runs.executor import JobResult, NotebookJob

ROOT = Path(__file__).resolve().parents[2]
SPEC = importlib.util.spec_from_file_location("notebooks_tool", ROOT / "tools" / "notebooks.py")
tool = importlib.util.module_from_spec(SPEC)
SPEC.loader.exec_module(tool)


def _result(stem, status, seconds, mb):
    return JobResult(NotebookJob(Path(f"notebooks/{stem}.py"), Path(f"notebooks/{stem}.ipynb")), status, "", seconds, mb)


def test_resources_file_round_trip(tmp_path, monkeypatch):
    monkeypatch.setenv("MTCAL_SIZE", "full")
    path = tmp_path / "sub" / "resources.csv"
    results = [_result("11_b", "ok", 61.24, 1650.4), _result("00_a", "ok", 8.0, 700.0),
               _result("20_c", "skipped", 0.0, math.nan)]
    tool._write_resources(path, results, 70.5, 2)
    text = path.read_text()
    assert text.startswith("# tools/notebooks.py execute --jobs 2 MTCAL_SIZE=full:")
    rows = list(csv.DictReader(ln for ln in text.splitlines() if not ln.startswith("#")))
    assert [r["notebook"] for r in rows] == ["00_a", "11_b", "20_c", "total"]
    assert rows[1]["wall_s"] == "61.2" and rows[1]["peak_rss_kernel_mb"] == "1650"
    assert rows[2]["peak_rss_kernel_mb"] == "" and rows[3]["status"] == "failed"
    assert rows[3]["wall_s"] == "70.5" and rows[3]["peak_rss_kernel_mb"] == "1650"
    # the next run starts the longest notebooks first; skipped and total rows carry no time
    assert tool._previous_seconds(path) == {"00_a": 8.0, "11_b": 61.2}


def test_previous_seconds_of_a_missing_or_broken_file_is_empty(tmp_path):
    assert tool._previous_seconds(None) == {}
    assert tool._previous_seconds(tmp_path / "none.csv") == {}
    bad = tmp_path / "bad.csv"
    bad.write_text("notebook,status,wall_s\n00_a,ok,not-a-number\n")
    assert tool._previous_seconds(bad) == {}
