"""tools/per_hold_cv.py: the drift normals are a unit-RMS random walk; a fold's scores can fail; bad input exits 2."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from mtcal.core.units import DEG
from mtcal.studies.wang2023cja import error_model as em

ROOT = Path(__file__).resolve().parents[2]
SPEC = importlib.util.spec_from_file_location("per_hold_cv", ROOT / "tools" / "per_hold_cv.py")
tool = importlib.util.module_from_spec(SPEC)
SPEC.loader.exec_module(tool)
TIMES = em.rest_times_s(em.paper_positions(), 20 * DEG, 3.0, 100.0)


def test_drift_normals_are_a_unit_rms_random_walk_and_leave_the_other_normals():
    z = np.random.default_rng(1).standard_normal((20000, em.N_NORMALS))
    d = tool.drift_normals(z, TIMES)
    walk = d[:, :39].reshape(-1, 13, 3)
    var = walk.var(axis=0).mean(axis=1)                       # per rest, grows with time
    assert np.all(np.diff(var) > 0)
    assert np.sqrt(var.mean()) == pytest.approx(1.0, rel=0.02)
    np.testing.assert_array_equal(d[:, 39:], z[:, 39:])
    inc = np.diff(walk[:, :, 0], axis=1)                      # independent increments
    assert abs(np.corrcoef(inc[:, 0], inc[:, 1])[0, 1]) < 0.03


def test_score_counts_inside_and_penalises_a_wrong_model():
    tests = tool.linear_tests("white", 300, 1)
    good = em.ErrorModel(position_error_arcsec=50.0, compliance_gasket_deg_g=0.34, gasket_load_tilt_deg_g=0.2)
    bad = em.ErrorModel(position_error_arcsec=2.0)
    s_good, s_bad = tool.score(good, tests["T2"]), tool.score(bad, tests["T2"])
    assert s_good["n"] == 18 and s_good["inside"] > s_bad["inside"]
    assert s_good["loglik"] > s_bad["loglik"] and s_good["interval_score_deg"] < s_bad["interval_score_deg"]


def test_bad_n_mc_exits_2(capsys):
    assert tool.main(["--n-mc", "10"]) == 2
    assert "per_hold_cv: error: --n-mc must be >= 100" in capsys.readouterr().err
