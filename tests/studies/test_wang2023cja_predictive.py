"""wang2023cja joint posterior draws, the variance split of a band, and the Table 8 candidate causes."""

import math

import numpy as np
import pandas as pd
import pytest

from mtcal.studies import wang2023cja as w
from mtcal.studies.wang2023cja import predictive, table08_causes, verdicts
from mtcal.studies.wang2023cja.error_model import FITTED_PARAMETERS, ErrorModel, ErrorModelFit

FREE = ("position_error_arcsec", "compliance_gasket_deg_g", "gasket_load_tilt_deg_g")
# a covariance with strong correlations, far from every prior bound at ±4σ
SD = np.array([10.0, 0.05, 0.03])
CORR = np.array([[1.0, 0.8, -0.5], [0.8, 1.0, -0.3], [-0.5, -0.3, 1.0]])
COV = CORR * np.outer(SD, SD)
ALPHA_COV = np.radians(np.array([[0.02, 0.01, 0.0], [0.01, 0.05, -0.01], [0.0, -0.01, 0.03]])) ** 2 * np.sign(
    np.array([[1, 1, 0], [1, 1, -1], [0, -1, 1]]))


def _fit(cov=COV, alpha_cov=True):
    model = ErrorModel(accel_run_bias_mg=0.02, position_error_arcsec=100.0, compliance_gasket_deg_g=0.1,
                       gasket_load_tilt_deg_g=0.2)
    at_bound = {n: n not in FREE for n in FITTED_PARAMETERS}
    std = {n: (float(SD[FREE.index(n)]) if n in FREE else math.nan) for n in FITTED_PARAMETERS}
    limit = {n: math.nan for n in FITTED_PARAMETERS}
    limit["accel_run_bias_mg"] = 0.5
    alpha = {t: np.radians([0.1, -0.2, 0.3]) for t in w.TABLES_1_TO_4}
    return ErrorModelFit(model, std, at_bound, 0.0, 0.0, alpha, 72, limit, cov,
                         {t: ALPHA_COV for t in w.TABLES_1_TO_4} if alpha_cov else None)


def test_alpha_cov_is_positive_definite():
    assert np.all(np.linalg.eigvalsh(ALPHA_COV) > 0)


def test_joint_draws_reproduce_the_covariance():
    draws = predictive.posterior_draws(_fit(), 20000, seed=3)
    x = np.array([[getattr(m, n) for n in FREE] for m, _ in draws])
    c = np.cov(x, rowvar=False)
    np.testing.assert_allclose(np.sqrt(np.diag(c)), SD, rtol=0.03)
    np.testing.assert_allclose(c / np.outer(np.sqrt(np.diag(c)), np.sqrt(np.diag(c))), CORR, atol=0.03)
    assert np.all(np.abs(x.mean(axis=0) - [100.0, 0.1, 0.2]) < 4 * SD / np.sqrt(20000))
    a = np.radians(np.array([d["T2"] for _, d in draws]))
    np.testing.assert_allclose(np.cov(a, rowvar=False), ALPHA_COV, atol=0.05 * ALPHA_COV.max())
    np.testing.assert_allclose(a.mean(axis=0), np.radians([0.1, -0.2, 0.3]), atol=1e-4)


def test_independent_draws_lose_the_correlation_and_fixed_angles_stay():
    draws = predictive.posterior_draws(_fit(cov=None, alpha_cov=False), 4000, seed=3)
    x = np.array([[getattr(m, n) for n in FREE] for m, _ in draws])
    assert abs(np.corrcoef(x, rowvar=False)[0, 1]) < 0.08           # the joint draws give 0.8
    assert {d["T1"] for _, d in draws} == {tuple(np.degrees(np.radians([0.1, -0.2, 0.3])))}


def test_a_value_on_its_bound_is_drawn_one_sided_to_its_profile_limit():
    draws = predictive.posterior_draws(_fit(), 20000, seed=4)
    v = np.array([m.accel_run_bias_mg for m, _ in draws])
    assert v.min() >= 0.02
    assert np.quantile(v, 0.95) == pytest.approx(0.5, rel=0.03)
    # no profile limit (NaN): the half-normal reaches the far prior bound at its 95 % point
    g = np.array([m.gyro_run_bias_deg_h for m, _ in draws])
    assert g.min() >= 0.3 and np.quantile(g, 0.95) == pytest.approx(20.0, rel=0.05)


def test_posterior_draws_reject_bad_n():
    with pytest.raises(ValueError, match="n must be >= 1"):
        predictive.posterior_draws(_fit(), 0, seed=1)


def test_variance_parts_recover_known_parts_and_sum_to_the_band_variance():
    rng = np.random.default_rng(5)
    for per_draw in (2, 5):
        theta = rng.normal(0.0, 0.3, 3000)
        y = np.repeat(theta, per_draw) + rng.normal(0.0, 0.4, 3000 * per_draw)
        p = predictive.variance_parts(y, per_draw)
        assert p["parameter"] == pytest.approx(0.09, rel=0.1)
        assert p["sampling"] == pytest.approx(0.16, rel=0.1)
        # the parts sum to the sample variance within Monte Carlo error (sd of a variance ≈ var·√(2/n) ×2)
        assert abs(p["total"] - np.var(y, ddof=1)) < 3 * 0.25 * np.sqrt(2 / 3000)
        assert p["parameter_share"] == pytest.approx(0.09 / 0.25, abs=0.05)
    p = predictive.variance_parts(rng.normal(size=4000), 2)        # no parameter part
    assert abs(p["parameter"]) < 0.08 and p["sampling"] == pytest.approx(1.0, rel=0.08)


def test_variance_parts_errors():
    with pytest.raises(ValueError, match="per_draw must be >= 2"):
        predictive.variance_parts(np.zeros(10), 1)
    with pytest.raises(ValueError, match="samples must be 1-D"):
        predictive.variance_parts(np.zeros((4, 2)), 2)
    with pytest.raises(ValueError, match="at least 2 complete groups"):
        predictive.variance_parts(np.zeros(3), 2)


def test_one_to_one_splits_each_rows_variance():
    rng = np.random.default_rng(6)
    key = ("wang2023cja_table08_roll_sweep_pitch_yaw_errors", 2, "pitch_deg")
    s = np.repeat(rng.normal(0.02, 0.01, 1000), 2) + rng.normal(0, 0.005, 2000)
    t = verdicts.one_to_one({key: (0.0, s)}, per_draw=2)
    r = t.iloc[0]
    assert r.var_band == pytest.approx(np.var(s, ddof=1))
    assert abs(r.var_parameter + r.var_sampling - r.var_band) < 0.1 * r.var_band
    assert r.parameter_share == pytest.approx(1e-4 / 1.25e-4, abs=0.05)
    assert "var_band" not in verdicts.one_to_one({key: (0.0, s)}).columns


def test_turntable_predictive_rejects_bad_per_draw():
    sc = w.turntable_scenario(fs_hz=100.0)
    with pytest.raises(ValueError, match="per_draw must be >= 1"):
        predictive.turntable_predictive(sc, _fit(), "fitted", 2, 0, tests=("T2",), per_draw=0)


# --------------------------------------------------------------------------
# Table 8 candidate causes (Tables 1–4 only)
# --------------------------------------------------------------------------
A_T1 = np.radians([-0.243, -0.036, 0.052])


def test_roll_sweep_coupling_before_and_with_an_exact_or_rounded_matrix():
    before = table08_causes.roll_sweep_maxae_deg(A_T1)
    assert 0.2 < before[0] < 0.4 and 0.2 < before[1] < 0.4      # the paper's Table 8 before: 0.316 / 0.272
    q = w.error_model.true_error_matrix(A_T1)
    assert table08_causes.roll_sweep_maxae_deg(A_T1, q).max() < 1e-9
    assert table08_causes.roll_sweep_maxae_deg(A_T1, np.round(q, 6)).max() < 1e-3
    # a matrix of the wrong installation leaves coupling: half the angles → about half the error
    half = table08_causes.roll_sweep_maxae_deg(A_T1, w.error_model.true_error_matrix(A_T1 / 2))
    np.testing.assert_allclose(half, before / 2, rtol=0.05)
    stack = table08_causes.roll_sweep_maxae_deg(A_T1, np.stack([q, np.eye(4)]))
    assert stack.shape == (2, 2) and np.allclose(stack[1], before)


def test_after_columns_fit_of_table1_is_small_and_rejects_bad_columns():
    f = w.fit_installation_angles(w.TABLES_1_TO_4["T1"], columns="after")
    assert np.degrees(np.abs(f.alpha_rad)).max() < 0.05
    assert f.cov_rad2.shape == (3, 3) and np.all(np.linalg.eigvalsh(f.cov_rad2) > 0)
    with pytest.raises(ValueError, match="columns must be 'before' or 'after'"):
        w.fit_installation_angles(w.TABLES_1_TO_4["T1"], columns="reference")


@pytest.fixture(scope="module")
def causes():
    return table08_causes.candidate_fractions(w.fit_error_model(n_mc=1000), n=300, seed=1)


def test_candidate_fractions_each_cause_computed(causes):
    c = causes.set_index("candidate")
    assert len(c) == 8 and c.index.is_unique
    assert c.loc["printed-matrix quantisation", "pitch_fraction"] > 0.999
    # a larger per-rest angle error leaves more coupling: the fraction falls monotonically with σ
    f = c.loc[["per-rest angle error (ML)", "per-rest angle error (95 % upper)", "per-rest angle error (prior maximum)"],
              "pitch_fraction_low"].to_numpy()
    assert f[0] > f[1] > f[2]
    assert not c.loc["per-rest angle error (prior maximum)", "supported"]
    assert not c.loc["four positions", "supported"]
    for ax in ("pitch", "yaw"):
        assert (c[f"{ax}_fraction_low"] <= c[f"{ax}_fraction"] + 1e-12).all()
        assert (c[f"{ax}_fraction"] <= c[f"{ax}_fraction_high"] + 1e-12).all()
    with pytest.raises(ValueError, match="n must be >= 2"):
        table08_causes.candidate_fractions(w.fit_error_model(n_mc=1000), n=1)


def test_table08_cause_text_names_an_explaining_candidate_or_none():
    base = {"setting": "", "support_reason": "", "pitch_fraction": 0.9, "yaw_fraction": 0.9}
    none = pd.DataFrame([{**base, "candidate": "a", "supported": True, "pitch_fraction_low": 0.8,
                          "pitch_fraction_high": 0.99, "yaw_fraction_low": 0.8, "yaw_fraction_high": 0.99}])
    assert "none explains it" in verdicts.table08_cause(none)
    wide = pd.DataFrame([{**base, "candidate": "b", "supported": True, "pitch_fraction_low": 0.1,
                          "pitch_fraction_high": 0.99, "yaw_fraction_low": 0.1, "yaw_fraction_high": 0.99}])
    assert verdicts.table08_cause(wide).endswith("explained by b")
    text = verdicts.table08_cause(pd.concat([none, wide.assign(supported=False, support_reason="excluded")]))
    assert "none explains it (the supported ones leave at least pitch 80%, yaw 80%: lowest a)" in text
    assert "reaching the paper's fractions needs b (excluded)" in text
