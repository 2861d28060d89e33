"""Leave-one-table-out cross-validation over wang2023cja Tables 1–4 (mtcal.studies.wang2023cja.crossval)."""

import functools
import shutil

import numpy as np
import pandas as pd
import pytest

from mtcal.reporting import fidelity, leak, paper_numbers
from mtcal.studies.wang2023cja import crossval as cv
from mtcal.studies.wang2023cja import error_model as em
from mtcal.studies.wang2023cja.error_model import TABLES_1_TO_4, ErrorModel

N_MC, N_DRAWS, SEED = 400, 1000, 7   # small fit, a 95 % band from 1000 draws


@functools.lru_cache(maxsize=None)
def _clean_fit(heldout):
    """A fold's fit on the unperturbed paper data (shared by the tests: a fit takes seconds)."""
    return cv.fold_fit(heldout, n_mc=N_MC, seed=SEED)


def _fold_outputs(heldout, alpha_source, fit=None):
    """Everything a fold produces before its held-out numbers are read: the fit, then the bands."""
    fit = cv.fold_fit(heldout, n_mc=N_MC, seed=SEED) if fit is None else fit
    draws = {"fitted": cv.fold_draws(heldout, fit, N_DRAWS, SEED, alpha_source=alpha_source),
             "no-physics": 0.05}
    bands = cv.predict_fold(heldout, draws, SEED)
    params = np.array([getattr(fit.model, n) for n in em.FITTED_PARAMETERS]
                      + [fit.std[n] for n in em.FITTED_PARAMETERS] + [fit.loglik]
                      + [x for t in sorted(fit.alpha_rad) for x in fit.alpha_rad[t]])
    return params, np.concatenate([bands["fitted"][k] for k in ("median", "low", "high")])


def _perturbed_paper_dir(tmp_path, heldout, columns):
    """A copy of the paper data with the held-out table's ``columns`` (yaw/pitch/roll) shifted by 0.5°."""
    dst = tmp_path / "paper_data"
    shutil.copytree(paper_numbers.paper_dir(), dst)
    path = dst / f"{TABLES_1_TO_4[heldout]}.csv"
    df = pd.read_csv(path, dtype=str, keep_default_na=False)
    for kind in columns:
        for a in ("yaw", "pitch", "roll"):
            col = f"{a}_{kind}_deg"
            df[col] = [f"{float(v) + 0.5 + 0.01 * i:.3f}" for i, v in enumerate(df[col])]
    df.to_csv(path, index=False, lineterminator="\n")
    return dst


@pytest.mark.parametrize("heldout, alpha_source, columns", [
    ("T1", "prior", ("after", "before")),     # blind: nothing of the held-out table is read
    ("T3", "prior", ("after", "before")),
    ("T4", "before", ("after",)),            # its "before" columns are an input; "after" never read
])
def test_fold_fit_and_bands_do_not_read_the_heldout_table(tmp_path, monkeypatch, heldout, alpha_source, columns):
    monkeypatch.delenv("MTCAL_CACHE_DIR", raising=False)
    clean = _fold_outputs(heldout, alpha_source, _clean_fit(heldout))
    perturbed_dir = _perturbed_paper_dir(tmp_path, heldout, columns)
    with leak.paper_dir_override(perturbed_dir):
        keys, paper = cv._paper_after(heldout)
        perturbed = _fold_outputs(heldout, alpha_source)
    _, paper_clean = cv._paper_after(heldout)
    assert np.all(np.abs(paper - paper_clean) > 0.4)           # the perturbation reached the scored numbers
    for a, b in zip(clean, perturbed):
        np.testing.assert_array_equal(a, b)                     # bit-identical fit and bands


def test_a_training_table_does_change_the_fold():                  # the leak test above can fail
    fit = _clean_fit("T1")
    other = em.fit_error_model(n_mc=N_MC, seed=SEED, tables=("T2", "T3"))
    assert fit.model != other.model


def test_cross_validate_scores_every_number_of_every_fold():
    rows = cv.cross_validate(n_draws=N_DRAWS, n_mc=N_MC, seed=SEED)
    assert len(rows) == 72 and list(rows.groupby("fold").size()) == [18] * 4
    assert (rows["n"] == N_DRAWS).all() and (rows["kind"] == "95 % band").all()
    for b in cv.CV_BASELINES:
        assert (rows[f"{b}_low"] <= rows[f"{b}_high"]).all()
        is_ = fidelity.interval_score(rows[f"{b}_low"], rows[f"{b}_high"], rows["paper"])
        np.testing.assert_allclose(rows[f"{b}_interval_score"], is_)
    t1 = TABLES_1_TO_4["T1"]
    df = paper_numbers.load(t1)
    np.testing.assert_allclose(rows[rows.fold == "T1"]["paper"].iloc[:3],
                               [df[f"{a}_after_deg"][0] - df[f"{a}_reference_deg"][0] for a in ("yaw", "pitch", "roll")])
    # the no-physics band uses the fold's training tables only
    half = cv.no_physics_halfwidth_deg(("T2", "T3", "T4"))
    np.testing.assert_allclose(rows[rows.fold == "T1"]["no-physics_high"], half)
    s = cv.fold_scores(rows)
    assert len(s) == 5 * 3 and set(s.scope) == {"wang2023cja_table01", "wang2023cja_table02", "wang2023cja_table03",
                                                 "wang2023cja_table04", "Tables 1–4"}
    pooled = s[(s.scope == "Tables 1–4") & (s.baseline == "fitted")].iloc[0]
    assert pooled.n == 72 and pooled.coverage > 0.8                # the model's bands are calibrated enough


def test_a_wrong_model_fails_the_cross_validation():
    """A model with no mount compliance and a 1″ rest error: narrow bands that miss, worse than no physics."""
    wrong = ErrorModel(position_error_arcsec=1.0, accel_run_bias_mg=0.02, gyro_run_bias_deg_h=0.1)
    out = []
    for heldout in ("T2", "T3"):
        fit = _clean_fit(heldout)
        _, alpha = cv.fold_draws(heldout, fit, N_DRAWS, SEED)
        good = cv.fold_draws(heldout, fit, N_DRAWS, SEED)
        half = cv.no_physics_halfwidth_deg(cv.training_tests(heldout))
        bands = cv.predict_fold(heldout, {"wrong": ([wrong] * N_DRAWS, alpha), "fitted": good, "no-physics": half},
                                SEED)
        _, paper = cv._paper_after(heldout)
        out.append({k: (np.mean((b["low"] <= paper) & (paper <= b["high"])),
                        np.mean(fidelity.interval_score(b["low"], b["high"], paper))) for k, b in bands.items()})
    for o in out:
        assert o["wrong"][0] < 0.5                               # coverage collapses
        assert o["wrong"][1] > 2 * max(o["no-physics"][1], o["fitted"][1])   # and scores far worse than both


def test_unidentified_fields_come_from_the_prior():
    fit = _clean_fit("T1")
    assert np.isnan(fit.std["compliance_screw_deg_g"]) and "T1" not in fit.alpha_rad
    models, alpha = cv.fold_draws("T1", fit, 50, SEED)
    k = np.array([m.compliance_screw_deg_g for m in models])
    assert k.std() > 0.01 and np.all(np.abs(k) <= 0.05)           # uniform over the prior range, not the nominal 0
    assert np.std([m.position_error_arcsec for m in models]) > 0  # fitted fields: posterior draws
    assert alpha.shape == (50, 3) and np.std(np.degrees(alpha)) > 0.1


def test_vectorised_rest_residuals_equal_one_model_at_a_time():
    rng = np.random.default_rng(3)
    models = [ErrorModel(position_error_arcsec=p, compliance_gasket_deg_g=c, gasket_load_tilt_deg_g=0.1)
              for p, c in ((10.0, 0.2), (60.0, -0.1), (30.0, 0.4))]
    alpha = np.radians([[0.3, -1.0, 0.5], [1.2, 0.1, -0.4], [0.0, 0.0, 0.0]])
    z = rng.standard_normal((3, em.N_NORMALS))
    batch = cv.predicted_after_deg(models, alpha, "gasket", z)
    for i in range(3):
        one = em.rest_residuals(alpha[i], models[i], "gasket", z[i:i + 1])["after"]
        ref = em.PAPER_SIGN * np.degrees(em.metrics.angle_difference(one, em.paper_positions()[None]))
        np.testing.assert_allclose(batch[i], ref[0], atol=1e-12)


def test_errors():
    with pytest.raises(ValueError, match="heldout must be one of"):
        cv.training_tests("T5")
    with pytest.raises(ValueError, match="alpha_source must be one of"):
        cv.fold_draws("T1", None, 2, 0, alpha_source="table")
    with pytest.raises(ValueError, match="the fit read the held-out test 'T1'"):
        cv.fold_draws("T1", _clean_fit("T2"), 2, 0)
    with pytest.raises(ValueError, match="n_draws must be >= 1"):
        cv.cross_validate(n_draws=0)
    with pytest.raises(ValueError, match="tables must be distinct test names"):
        em.fit_error_model(n_mc=N_MC, tables=("T1", "T1"))
    with pytest.raises(ValueError, match="tables must be a sequence of test names"):
        em.fit_error_model(n_mc=N_MC, tables="T1")
    with pytest.raises(ValueError, match="models must be a non-empty sequence of ErrorModel"):
        em.ErrorModelDraws.stack([])
    with pytest.raises(ValueError, match="tests must be names from"):
        cv.no_physics_halfwidth_deg(("T9",))
