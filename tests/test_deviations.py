"""The deviations ledger (docs/deviations.csv, rendered in docs/deviations.md) is complete: every split role and every
prior range changed after a paper's split was first committed has an entry (read from git history)."""

import io
import re
import subprocess
from pathlib import Path

import pandas as pd
import pytest

from mtcal.reporting import paper_numbers

ROOT = Path(__file__).resolve().parents[1]
LEDGER = ROOT / "docs" / "deviations.csv"
#: The commit that first added each paper's split file.
FIRST = {"wang2023cja": "d7ec46d", "tan2022": "9984795", "wang2022sensors": "9984795"}


def _git_show(rev: str, path: str) -> str:
    try:
        return subprocess.run(["git", "show", f"{rev}:{path}"], cwd=ROOT, check=True, capture_output=True,
                              text=True).stdout
    except (OSError, subprocess.CalledProcessError):
        pytest.skip(f"git history not available ({rev}:{path}): a shallow clone or no git")


def _ledger() -> pd.DataFrame:
    return pd.read_csv(LEDGER, dtype=str, keep_default_na=False)


def _tokens(kind: str) -> set:
    out = set()
    for cells in _ledger()["cells"]:
        for tok in cells.split(";"):
            parts = tok.split(":")
            if parts[0] != kind:
                continue
            if kind == "role":
                _, file, rows, column = parts
                lo, _, hi = rows.partition("-")
                out |= {(file, str(r), column) for r in range(int(lo), int(hi or lo) + 1)}
            else:
                out.add(tuple(parts[1:]))
    return out


def test_ledger_is_well_formed_and_rendered():
    led = _ledger()
    assert list(led.columns) == ["id", "date", "commit", "paper", "change", "cells", "effect_on_scores"]
    assert led["id"].is_unique and (led["effect_on_scores"].str.len() > 0).all()
    assert not led["effect_on_scores"].str.contains("PENDING").any()
    assert led["date"].str.fullmatch(r"\d{4}-\d{2}-\d{2}").all()
    md = (ROOT / "docs" / "deviations.md").read_text(encoding="utf-8")
    for r in led.itertuples():
        assert f"| {r.id} |" in md and r.commit.split()[0] in md, r.id


@pytest.mark.parametrize("key", sorted(FIRST))
def test_every_role_changed_since_the_first_split_commit_is_in_the_ledger(key):
    path = f"mtcal/reporting/paper_data/{key}_split.csv"
    old = pd.read_csv(io.StringIO(_git_show(FIRST[key], path)), dtype=str, keep_default_na=False)
    old["file"] = old["file"].str.removesuffix(".csv")
    new = paper_numbers.split(key).astype({"row": str})
    both = new.merge(old, on=["file", "row", "column"], how="left", suffixes=("", "_first"))
    changed = both[both["role"] != both["role_first"]]
    listed = _tokens("role")
    missing = [f"{r.file}:{r.row}:{r.column} ({r.role_first} -> {r.role})" for r in changed.itertuples()
               if (r.file, r.row, r.column) not in listed]
    assert not missing, f"{len(missing)} role changes of {key} have no ledger entry, e.g. {missing[:3]}"


_OLD_PRIOR = re.compile(r"(\w+): float = _p\(\s*[-+\d.eE]+,\s*\"[^\"]*\",\s*\(([-+\d.eE]+),\s*([-+\d.eE]+)\)")


def test_every_wang2023cja_prior_range_changed_since_the_first_split_commit_is_in_the_ledger():
    from mtcal.studies.wang2023cja.error_model import PRIOR_RANGES

    old = {m[0]: (float(m[1]), float(m[2])) for m in
           _OLD_PRIOR.findall(_git_show(FIRST["wang2023cja"], "mtcal/studies/wang2023cja/error_model.py"))}
    assert old, "no prior range parsed from the first split commit"
    changed = {name for name, rng in PRIOR_RANGES.items() if old.get(name) != tuple(map(float, rng))}
    assert "position_error_arcsec" in changed        # 60″ -> 300″, the known change
    assert not changed - {name for _, name in _tokens("prior") if _ == "wang2023cja"} - set(), \
        f"prior ranges changed without a ledger entry: {sorted(changed)}"


def test_every_wang2022sensors_prior_range_changed_since_the_first_split_commit_is_in_the_ledger():
    from mtcal.studies.wang2022sensors.error_model import ERROR_PRIORS

    src = _git_show(FIRST["wang2022sensors"], "mtcal/studies/wang2022sensors/error_model.py")
    old = {m[0]: (float(m[1]), float(m[2])) for m in
           re.findall(r"\"(\w+)\": dict\(low=([-+\d.eE]+), high=([-+\d.eE]+)", src)}
    assert old
    changed = {k for k, v in ERROR_PRIORS.items() if old.get(k) != (float(v["low"]), float(v["high"]))}
    listed = {name for paper, name in _tokens("prior") if paper == "wang2022sensors"}
    assert not changed - listed, f"prior ranges changed without a ledger entry: {sorted(changed - listed)}"
