"""Every shipped example runs (issue #36): the sweeps of ``examples/sweeps/`` at a small size.

Each spec is run as written — evaluator, grid, fixed values — with its trial count cut to 2
(``trials`` / ``block_trials`` only: the scenario is the shipped one), through ``mtcal sweep``.
"""

import re
from pathlib import Path

import pandas as pd
import pytest

from mtcal import cli

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
SWEEPS = sorted((EXAMPLES / "sweeps").glob("*.toml"))


def test_there_are_examples():
    assert len(SWEEPS) >= 2


@pytest.mark.parametrize("spec", SWEEPS, ids=[p.stem for p in SWEEPS])
def test_shipped_sweep_runs_at_small_size(spec, tmp_path, capsys):
    text = spec.read_text()
    small = re.sub(r"(?m)^trials\s*=\s*\d+", "trials = 2", text)
    small = re.sub(r"(?m)^block_trials\s*=\s*\d+", "block_trials = 2", small)
    assert small != text
    p = tmp_path / spec.name
    p.write_text(small)
    out = tmp_path / "run"
    assert cli.main(["sweep", str(p), "--workers", "1", "--out", str(out), "--no-progress"]) == 0, capsys.readouterr()
    table = pd.read_csv(out / "table.csv")
    assert len(table) > 0 and table["median"].notna().all() and (table["trials"] == 2).all()
