"""Notebook hygiene: each committed .ipynb is the jupytext pairing of its py:percent source, executed,
with run-independent metadata; the Makefile pins the same numerics as the library's runs."""

import json
import re
import sys
from pathlib import Path

import jupytext
import pytest

from mtcal import runs

ROOT = Path(__file__).resolve().parent.parent
SOURCES = runs.notebook_sources(ROOT / "notebooks")


def _cells(nb):
    return [(c["cell_type"], "".join(c["source"]).rstrip("\n"), tuple(c.get("metadata", {}).get("tags", [])))
            for c in nb["cells"]]


#: an absolute path printed by a notebook (a repr of a Path, or a temporary/home/work folder)
_MACHINE_PATH = re.compile(r"PosixPath\(|WindowsPath\(|(?<![\w.])/(?:tmp|home|work|root|Users)/")


def test_machine_path_check_can_fail():
    assert _MACHINE_PATH.search("PosixPath('/work/main/data/x.csv')") and _MACHINE_PATH.search("saved /tmp/a.png")
    assert not _MACHINE_PATH.search("data/wang2023cja_table05.csv, 0.5 deg/s")


@pytest.mark.parametrize("src", SOURCES, ids=[p.stem for p in SOURCES])
def test_ipynb_in_sync_with_source_and_executed(src):
    nb_path = src.with_suffix(".ipynb")
    assert nb_path.exists(), f"{nb_path.name} missing: run make reproduce"
    expected = _cells(jupytext.read(src, fmt="py:percent"))
    nb = json.loads(nb_path.read_text(encoding="utf-8"))
    assert _cells(nb) == expected, f"{nb_path.name} is out of sync with {src.name}: run make sync / make reproduce"
    code = [c for c in nb["cells"] if c["cell_type"] == "code"]
    assert code and all(c["execution_count"] is not None for c in code), f"{nb_path.name} was not executed"
    assert "parameters" in code[0].get("metadata", {}).get("tags", []), "first code cell must be tagged 'parameters'"
    # byte-stable: no papermill durations, no execution timestamps, no progress-bar widgets
    assert "papermill" not in nb["metadata"] and "widgets" not in nb["metadata"]
    for cell in nb["cells"]:
        assert not {"papermill", "execution", "ExecuteTime"} & set(cell.get("metadata", {})), cell.get("id")
        for out in cell.get("outputs", []):
            assert "application/vnd.jupyter.widget-view+json" not in out.get("data", {}), "progress bar in outputs"
            # no machine-dependent path: the committed outputs must be the same bytes in every checkout
            found = _MACHINE_PATH.search(json.dumps(out))
            assert not found, f"{nb_path.name} cell {cell.get('id')}: a path of this machine in the outputs ({found[0]!r})"


def test_jupytext_pairing_config():
    text = (ROOT / "jupytext.toml").read_text(encoding="utf-8")
    assert re.search(r'^formats\s*=\s*"ipynb,py:percent"', text, re.M)


def test_makefile_pins_the_same_numerics_as_runs():
    make = (ROOT / "Makefile").read_text(encoding="utf-8")
    exported = dict(re.findall(r"^export (\w+) := (.*)$", make, re.M))
    expected = runs.numerics_env()
    assert {k: exported.get(k) for k in expected} == expected


def test_build_notebook_is_deterministic(tmp_path):
    src = tmp_path / "99_tiny.py"
    src.write_text('# %% [markdown]\n# # Title\n\n# %% tags=["parameters"]\nA = 1\n\n# %%\nprint(A)\n')
    a, b = runs.build_notebook(src), runs.build_notebook(src)
    assert [c.id for c in a.cells] == ["cell-000", "cell-001", "cell-002"] == [c.id for c in b.cells]
    assert a.cells[1].metadata["tags"] == ["parameters"]
    assert runs.sync_notebook(src) is True and runs.sync_notebook(src) is False


def test_artifact_catalogue_is_complete_and_current():
    import importlib.util

    spec = importlib.util.spec_from_file_location("artifact_catalogue", ROOT / "tools" / "artifact_catalogue.py")
    cat = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = cat  # dataclasses look their module up
    spec.loader.exec_module(cat)
    assert cat.paper_artifact("tan2022_fig06") == "tan2022 Fig. 6"
    assert cat.problems() == []
    # a file's producer is the one named after its ID, not another producer of claims under that ID
    producers = cat.registered_producers()
    assert producers["tan2022_fig12"] == "`mtcal.studies.tan2022.fig12`"
    assert producers["tan2022_fig06"] == "`mtcal.studies.tan2022.fig06`"


#: run-dependent values a notebook must never print (outputs are committed and must be byte-identical per run)
_CLOCKS = re.compile(r"\b(time\.(perf_counter|time|monotonic|process_time)|datetime\.now|date\.today)\s*\(")


@pytest.mark.parametrize("src", SOURCES, ids=[p.stem for p in SOURCES])
def test_notebook_prints_no_clock(src):
    """A notebook reads no clock: a printed run time would change the committed .ipynb on every run."""
    hits = [f"{src.name}:{i}: {line.strip()}" for i, line in enumerate(src.read_text(encoding="utf-8").splitlines(), 1)
            if _CLOCKS.search(line)]
    assert not hits, "notebooks must not read a clock (outputs are committed byte-identically):\n" + "\n".join(hits)


def test_clock_check_can_fail():
    assert _CLOCKS.search("t0 = time.perf_counter()") and not _CLOCKS.search("dt_s = 1 / fs_hz")
