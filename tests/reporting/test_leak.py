"""Leak test: each paper's fit + predictions are bit-identical when every held-out value is garbage."""

import importlib

import numpy as np
import pandas as pd
import pytest

from mtcal.reporting import leak, paper_numbers

#: Every paper registers a fit_and_predict for the leak test.
STUDIES = ("tan2022", "wang2022sensors", "wang2023cja", "broad2021")


@pytest.mark.parametrize("key", STUDIES)
def test_study_fit_does_not_leak(key):
    importlib.import_module(f"mtcal.studies.{key}")
    assert key in leak.registered(), f"mtcal.studies.{key} registers no fit_and_predict"
    out = leak.check_no_leak(key, size="ci", seed=0)
    assert out and all(isinstance(v, np.ndarray) for v in out.values())


def _fake_leaky_fit(size="ci", seed=0):
    v = paper_numbers.load("wang2022sensors_table05_rmse")["rmse_dynamic_deg"].to_numpy()
    return {"fitted": v[:1].copy(), "band": v.copy()}


def _fake_clean_fit(size="ci", seed=0):
    t = paper_numbers.training("wang2022sensors")["wang2022sensors_table05_rmse"]
    return {"fitted": t["rmse_static_deg"].to_numpy()}


def test_harness_catches_a_leak():
    with pytest.raises(AssertionError, match="leak in wang2022sensors: .* these outputs changed: \\['band'\\]"):
        leak.check_no_leak("wang2022sensors", _fake_leaky_fit)
    assert leak.check_no_leak("wang2022sensors", _fake_clean_fit)["fitted"].size == 9


@pytest.mark.parametrize("mode", leak.PERTURBATIONS)
def test_every_perturbation_changes_every_heldout_value(tmp_path, mode):
    path = leak.perturbed_copy(tmp_path / f"pd_{mode}", mode)
    before = {k: paper_numbers.heldout(k) for k in paper_numbers.KEYS}
    with leak.paper_dir_override(path):
        for k in paper_numbers.KEYS:
            after = paper_numbers.heldout(k)
            assert not (after["text"] == before[k]["text"]).any(), (k, mode)
            assert len(paper_numbers.split(k)) == len(paper_numbers.split(k))


def test_harness_errors(tmp_path):
    with pytest.raises(ValueError, match="no fit_and_predict registered"):
        leak.check_no_leak("wang2022sensors" if "wang2022sensors" not in leak.registered() else "tan2022x")
    with pytest.raises(ValueError, match="perturbations must not be empty"):
        leak.check_no_leak("tan2022", _fake_clean_fit, perturbations=())
    with pytest.raises(TypeError, match="must return a non-empty dict"):
        leak.check_no_leak("tan2022", lambda size, seed: {})
    with pytest.raises(ValueError, match="mode must be one of"):
        leak.perturb_text("1", "double")
    with pytest.raises(ValueError, match="key must be one of"):
        leak.register("x2020")
    (tmp_path / "full").mkdir()
    (tmp_path / "full" / "a").write_text("x")
    with pytest.raises(ValueError, match="dst must be empty"):
        leak.perturbed_copy(tmp_path / "full", "nan")


def test_override_restores_environment(monkeypatch):
    monkeypatch.delenv("MTCAL_PAPER_DIR", raising=False)
    with leak.paper_dir_override("/nonexistent"):
        with pytest.raises(FileNotFoundError, match="paper data folder not found"):
            paper_numbers.paper_dir()
    assert isinstance(paper_numbers.paper_dir(), type(paper_numbers.paper_dir()))
    pd.testing.assert_frame_equal(paper_numbers.heldout("tan2022"), paper_numbers.heldout("tan2022"))
