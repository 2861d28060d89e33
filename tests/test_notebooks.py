"""Notebook hygiene: each committed .ipynb matches its py:percent source and was executed."""

import json
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
import py_to_ipynb  # noqa: E402

SOURCES = sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.py"))


@pytest.mark.parametrize("src", SOURCES, ids=[p.stem for p in SOURCES])
def test_ipynb_matches_source_and_has_outputs(src):
    nb_path = src.with_suffix(".ipynb")
    assert nb_path.exists(), f"{nb_path.name} missing: run tools/py_to_ipynb.py and make reproduce"
    expected = [(c.cell_type, c.source) for c in py_to_ipynb.parse(src.read_text(encoding="utf-8"))]
    nb = json.loads(nb_path.read_text(encoding="utf-8"))
    actual = [(c["cell_type"], "".join(c["source"])) for c in nb["cells"]]
    assert actual == expected, f"{nb_path.name} is out of date with {src.name}"
    code = [c for c in nb["cells"] if c["cell_type"] == "code"]
    assert code and all(c["execution_count"] is not None for c in code), f"{nb_path.name} was not executed"
    first = code[0]
    assert "parameters" in first.get("metadata", {}).get("tags", []), "first code cell must be tagged 'parameters'"


def test_parser_handles_markers():
    cells = py_to_ipynb.parse('# %% [markdown]\n# # Title\n# text\n\n# %% tags=["parameters"]\nA = 1\n\n# %%\nprint(A)\n')
    assert [c.cell_type for c in cells] == ["markdown", "code", "code"]
    assert cells[0].source == "# Title\ntext"
    assert cells[1].metadata["tags"] == ["parameters"]
