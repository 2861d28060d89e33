"""tools/ledger_effects.py: the two ledger switches are scoped (restored on exit) and D6's add-back is exact."""

import importlib.util
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from mtcal.studies.wang2023cja import error_model, runs

ROOT = Path(__file__).resolve().parents[2]
SPEC = importlib.util.spec_from_file_location("ledger_effects", ROOT / "tools" / "ledger_effects.py")
tool = importlib.util.module_from_spec(SPEC)
SPEC.loader.exec_module(tool)


def test_position_error_range_is_set_inside_and_restored_after_an_error():
    before = error_model.PRIOR_RANGES["position_error_arcsec"]
    with pytest.raises(RuntimeError, match="inside"):
        with tool.position_error_range((1.0, 60.0)):
            assert error_model.PRIOR_RANGES["position_error_arcsec"] == (1.0, 60.0)
            raise RuntimeError("inside")
    assert error_model.PRIOR_RANGES["position_error_arcsec"] == before


def test_without_hold_errors_adds_the_subtracted_term_back_and_leaves_the_run_alone():
    e = np.array([[0.1, -0.2], [0.3, 0.0]])
    d = {"reference": np.zeros(2), "before_mean": np.ones((2, 2)), "after_mean": np.full((2, 2), 2.0),
         "before_rmse_2": np.ones(2), tool.HOLD_ERROR_KEY: e}
    out = tool.without_hold_errors(SimpleNamespace(sweeps={"aoa": d}))
    np.testing.assert_allclose(out["aoa"]["before_mean"], 1.0 + e)
    np.testing.assert_allclose(out["aoa"]["after_mean"], 2.0 + e)
    assert out["aoa"]["before_rmse_2"] is d["before_rmse_2"]           # MaxAE/RMSE carry no hold error
    np.testing.assert_allclose(d["before_mean"], 1.0)                   # the input is not modified


def test_too_few_trials_is_one_error_line(capsys):
    assert tool.main(["--trials", "1"]) == 2
    assert capsys.readouterr().err.strip() == "ledger_effects: error: --trials must be >= 2, got 1"
