"""Tests for mtcal.studies.tan2022: parameters → scenarios, artifact producers, error-model fits."""

import numpy as np
import pytest

from mtcal.reporting import compare
from mtcal.studies import tan2022 as t


# ---------------------------------------------------------------- parameters and validation
def test_defaults_are_the_papers():
    sc = t.accel_scenario()
    assert (sc.delta_accel_g, sc.lambda1_deg, sc.lambda2_deg) == (1e-4, 45.0, -135.0)
    st = t.gyro_study()
    assert st.gyro.error_deg_s == (0.2, 0.2, 0.2)
    assert st.uniform.pitch_rates_deg_s == (10.0, 20.0, 60.0)
    assert (st.oscillation.amplitude_deg, st.oscillation.freq_hz, st.oscillation.threshold_deg_s) == (40.0, 0.5, 0.5)
    assert compare.at_paper_settings(dict(t.ACCEL_PARAMETER_DEFAULTS), t.PARAMETER_DEFAULTS)


@pytest.mark.parametrize("builder, kwargs, match", [
    (t.accel_scenario, {"accel_error": 1e-3}, r"unknown tan2022 parameter\(s\) \['accel_error'\]; valid"),
    (t.accel_scenario, {"accel_error_g": 0.5}, "must be <= 0.1"),
    (t.accel_scenario, {"accel_error_g": -1e-4}, "delta_accel_g must be > 0"),
    (t.accel_scenario, {"lambda1_deg": 400.0}, r"lambda1_deg must be a number of degrees within \[-180, 180\]"),
    (t.gyro_study, {"fs_hz": 0.0}, "fs_hz must be > 0"),
    (t.gyro_study, {"gyro_error_z_deg_s": float("nan")}, "gyro_error_z_deg_s must be a finite error"),
    (t.gyro_study, {"oscillation_amplitude_deg": 95.0}, "amplitude_deg must be < 90"),
    (t.gyro_study, {"pitch_rates_deg_s": (10.0, -5.0)}, "pitch_rates_deg_s must be positive"),
    (t.gyro_study, {"threshold": 0.5}, r"unknown tan2022 parameter\(s\) \['threshold'\]"),
])
def test_invalid_parameter_is_rejected_with_one_line(builder, kwargs, match):
    with pytest.raises(ValueError, match=match) as info:
        builder(**kwargs)
    assert "\n" not in str(info.value)


# ---------------------------------------------------------------- propagation into labels and tables
def test_accel_error_propagates_into_labels_and_tables():
    a1 = t.fig02(t.AccelScenario(delta_accel_g=1e-4, grid_step_deg=10.0))
    a3 = t.fig02(t.AccelScenario(delta_accel_g=1e-3, grid_step_deg=10.0))
    assert a1.data["label"] == "ΔA = 1e-04 g" and a3.data["label"] == "ΔA = 1e-03 g"
    ratio = a3.table["dtheta_simulated_deg"].abs().max() / a1.table["dtheta_simulated_deg"].abs().max()
    assert ratio == pytest.approx(10.0, rel=2e-3)  # linear in ΔA to first order
    assert "1e-03 g" in a3.lines[0]
    # the claim text derives its expected value from ΔA
    assert f"{np.degrees(np.sqrt(3) * 1e-3):.3g}°" in a3.rows[1]["claim"]


def test_figure_labels_follow_the_parameters():
    pytest.importorskip("matplotlib")
    from mtcal.studies.tan2022 import plots

    fig = plots.fig02(t.fig02(t.AccelScenario(delta_accel_g=1e-3, grid_step_deg=10.0)))
    texts = [fig.axes[0].get_title(), fig.axes[1].get_ylabel()]
    assert all("ΔA = 1e-03 g" in s for s in texts) and "Fig 2" in texts[0] and "tan2022_fig02" in texts[0]
    assert fig.axes[0].get_xlabel() == "roll φ (deg)" and fig.axes[0].get_ylabel() == "pitch θ (deg)"


def test_gyro_parameters_propagate_into_labels_and_rows():
    st = t.gyro_study(gyro_error_z_deg_s=0.001, gyro_noise_density_deg_s_rthz=0.0, threshold_deg_s=2.0,
                      oscillation_duration_s=4.0)
    assert "[0.2, 0.2, 0.001]" in t.gyro_label(st) and "noise 0 " in t.gyro_label(st)
    art = t.fig12(st, seed=1, trials=2)
    assert "θ̇_t = 2 °/s" in art.rows[0]["quantity"]
    # with a negligible z error (and φ0 = 0) the projection is nearly exact: the hybrid is accurate,
    # so the paper's Fig 12 claim holds; at the paper's 0.2 °/s it fails (reported, not enforced)
    assert art.rows[0]["holds"] is True and art.rows[0]["kind"] == "claim"
    paper = t.fig12(t.gyro_study(oscillation_duration_s=4.0), seed=1, trials=2).rows[0]
    assert paper["holds"] is False and paper["enforced"] is False and "0.2 °/s" in paper["note"]


# ---------------------------------------------------------------- producers at the paper's settings
def test_accel_producers_claims_hold_at_paper_settings():
    sc = t.AccelScenario(grid_step_deg=5.0)
    rows = []
    for producer in (t.eq3_erratum, t.fig02, t.extra_roll_error, t.fig05, t.fig08):
        art = producer(sc)
        assert not art.table.empty
        rows += art.rows
    table = compare.comparison_table(rows)
    assert set(table["role"]) <= set(compare.ROLES)
    compare.check_claims(table, enforce=True)


def test_roles_and_sources_are_honest():
    """Our own findings are never counted as the paper's claims."""
    sc = t.AccelScenario(grid_step_deg=10.0)
    for row in t.fig08(sc).rows[1:]:
        assert (row["role"], row["source"]) == ("finding", "mtcal finding")
    for row in t.eq3_erratum(sc).rows:
        assert row["role"] == "erratum"


def test_threshold_check_reports_the_paper_threshold_problem():
    art = t.threshold_check(t.gyro_study())
    worst = art.table.set_index("quantity").loc["exact arctan worst over φ", "roll_error_deg"]
    assert worst == pytest.approx(34.45, abs=0.05)
    row = art.rows[0]
    assert row["holds"] is False and row["kind"] == "claim" and row["enforced"] is False
    assert "too low" in row["note"] and row["check"](0.5) is True


def test_grid_posterior():
    r = t.grid_posterior([1.0, 3.0, 0.0], [0.0, 1.0, 2.0])
    assert r["ml"] == 1.0 and r["median"] == 1.0 and r["low"] == 0.0
    with pytest.raises(ValueError, match="not all zero"):
        t.grid_posterior([0.0, 0.0], [0.0, 1.0])


def test_accel_fit_prefers_common_mode_and_predicts_eq9_angles():
    fit = t.fit_accel_error_model(t.AccelScenario(), t.AccelErrorPrior(n_grid=9), seed=3, trials=100, step_deg=10.0)
    like = fit.posterior["likelihood"]
    assert like[0] == pytest.approx(1.0) and like[-1] < 0.5  # the paper's statements favour r → 0
    p = fit.parameters.iloc[0]
    assert 0.0 <= p["low_2.5"] <= p["median"] <= p["high_97.5"] <= 2.0
    lam = [r for r in fit.rows if "preset angle" in r["quantity"]]
    # λ1/λ2 are inputs the r fit reads: our own statement (no kind), never a claim, never "true by construction"
    assert len(lam) == 2 and all(r["paper_in_band"] and r["kind"] == "" and r["role"] == "input"
                                 and r["source"] == "mtcal finding" and "not by construction" in r["note"] for r in lam)
    # the statements the likelihood is fitted to: in-sample, role train; the label comes from the role, no suffix
    fitted = [r for r in fit.rows if r["kind"] == "in-sample"]
    assert len(fitted) == 4 and all(r["role"] == "train" and not r["enforced"] for r in fitted)
    assert not any("[training]" in r["quantity"] for r in fit.rows)
    assert list(fit.predictions["role"]) == [r["role"] for r in fit.rows]
    # Fig 8's "clear improvement" is implied by the statements the likelihood is fitted to (in the prior predictive
    # it holds in every draw where they hold): checked in-sample with the computed reason, never a claim
    gain = [r for r in fit.rows if r["artifact"] == "tan2022_fig08"][0]
    assert gain["kind"] == "in-sample" and gain["holds"] is True and gain["prior_band"]
    assert "implied by the statements the likelihood is fitted to" in gain["note"] and "no independent test" in gain["note"]


def test_accel_claim_stays_a_claim_when_the_training_does_not_imply_it():
    # training statements that hold in every draw condition on nothing: Fig 8 is then a test of its own
    loose = t.AccelErrorPrior(n_grid=9, asymmetry_max=1e3, large_pitch_max=1e3, comparable_max=1e300)
    fit = t.fit_accel_error_model(t.AccelScenario(), loose, seed=3, trials=100, step_deg=10.0)
    gain = [r for r in fit.rows if r["artifact"] == "tan2022_fig08"][0]
    assert gain["kind"] == "claim" and gain["role"] == "finding" and "of the 100 draws" in gain["note"]
    # the claim can fail: no gain from the preset rotation (gain 1.0) violates "clear improvement"
    assert gain["check"](1.0) is False


def test_implied_by_training():
    r = t.implied_by_training([True, False, True, True], [True, True, False, False])
    assert (r["p_given"], r["n_given"], r["p_else"], r["n_else"], r["implied"]) == (0.5, 2, 1.0, 2, False)
    r = t.implied_by_training([True] * 19 + [False], [True] * 20)
    assert r["p_given"] == 0.95 and r["implied"] is True and np.isnan(r["p_else"])
    assert t.implied_by_training([True], [False])["implied"] is False   # nothing to condition on


def test_rms_optimal_preset_angle_is_not_inside_by_construction():
    # the search window is centred on the scenario's λ, but the optimum is not: a wrong λ1 = 80° is not found
    from mtcal.studies.tan2022 import runs
    for lam1 in (45.0, 80.0):
        p = runs.accel_predictions(t.AccelScenario(lambda1_deg=lam1), np.zeros(3), np.random.default_rng(0), 10.0)
        assert np.all(p["lambda1"] == 45.0) and np.all(p["lambda2"] == -135.0)  # common mode: Eq 9's angles


def test_a_failing_training_check_prints_fails():
    row = compare.in_sample("tan2022_fig02", "Fig 2 asymmetry", "small vs large", 0.9, "< 0.7", False,
                            on="the likelihood is P(this statement holds | r): fitted to the same statement")
    report = compare.check_claims(compare.comparison_table([row]), enforce=True)  # in-sample: never enforced
    assert "FAILS: tan2022_fig02 | Fig 2 asymmetry" in report and "0 of 0 claims hold" in report


def test_gyro_fit_recovers_the_stated_error_and_flags_fig12():
    st = t.gyro_study(oscillation_duration_s=4.0)
    fit = t.fit_gyro_error_model(st, t.GyroErrorPrior(n_bias=51, n_noise=3), seed=3, trials=6, fit_trials=3)
    b = fit.parameters.iloc[0]
    assert b["low_2.5"] <= 0.2 + 1e-9 and b["high_97.5"] >= 0.2 - 1e-9
    hybrid = [r for r in fit.rows if r["artifact"] == "tan2022_fig12" and "hybrid" in r["quantity"]][0]
    # Fig 12's sentence fails under the model fitted to Fig 6 too; it is judged once (fig12), here only shown
    assert hybrid["holds"] is None and hybrid["kind"] == "" and hybrid["mtcal"] > 5
    assert hybrid["note"].startswith("the Fig 12 sentence is judged once") and "above the 1° made" in hybrid["note"]
    fig6 = [r for r in fit.rows if r["artifact"] == "tan2022_fig06"][0]
    assert (fig6["kind"], fig6["role"], fig6["ref"]) == ("in-sample", "train", "tan2022_params:7:value")
    assert not any("[training]" in r["quantity"] for r in fit.rows)
    assert not any(r["role"] == "heldout" for r in fit.rows)  # tan2022 prints no result number
    drift = [r for r in fit.rows if r["artifact"] == "tan2022_fig09"]
    assert drift and all(r["paper"] == "—" and r["holds"] is None for r in drift)  # no circular "prediction"
    spike = [r for r in fit.rows if r["artifact"] == "tan2022_fig11"][0]
    # the spikes follow from Eq 14 for any constant error: they hold across the prior, so they are no claim
    assert spike["holds"] is True and spike["kind"] == "consistency" and "prior-predictive draws" in spike["note"]
    need = [r for r in fit.rows if "largest constant" in r["quantity"]][0]
    assert need["mtcal"] == pytest.approx(0.5 * np.tan(np.radians(1.0)))


def test_gyro_what_if_without_projection_errors_completes():
    """x/y errors only, no noise: the projection is exact at φ0 = 0; every producer still reports."""
    st = t.gyro_study(gyro_error_z_deg_s=0.0, gyro_noise_density_deg_s_rthz=0.0, oscillation_duration_s=2.0)
    rows = []
    for producer, args in ((t.fig06, (1, 2)), (t.fig11, (1, 2)), (t.fig12, (1, 2)), (t.extra_threshold_sweep, (1, 2, 5))):
        rows += producer(st, *args).rows
    table = compare.comparison_table(rows)
    slope = table[table["quantity"].str.startswith("log-log slope")].iloc[0]
    assert slope["mtcal"] == "undefined (zero error)" and not slope["holds"]
    report = compare.check_claims(table, enforce=False)
    assert "claims hold" in report


def test_gyro_pattern_fit_excludes_the_printed_z_error():
    st = t.gyro_study(oscillation_duration_s=4.0)
    fit = t.fit_gyro_error_pattern(st, t.GyroErrorPrior(), seed=2, trials=3)
    bz = fit.parameters.iloc[0]
    assert 0.0 <= bz["low_2.5"] <= bz["high_97.5"] <= 0.02  # far below the paper's 0.2 °/s on z
    like = fit.posterior["likelihood"]
    assert like[list(t.PATTERN_BIAS_GRID_DEG_S).index(0.2)].max() == 0.0
    finding = [r for r in fit.rows if r["source"] == "mtcal finding" and r["artifact"] == "tan2022_fig12"][0]
    assert finding["holds"] and finding["paper_in_band"] is False
    fitted = fit.rows[0]  # the likelihood is P(Fig 11 and Fig 12 statements): checked in-sample, role train
    assert (fitted["kind"], fitted["role"], fitted["enforced"]) == ("in-sample", "train", False)
    # Fig 9 (c) is judged once, at the paper's settings: the pattern model's slope band is shown, never
    # labelled "by construction" (with the fitted noise it could fail)
    slope = [r for r in fit.rows if r["artifact"] == "tan2022_fig09"][0]
    assert slope["kind"] == "" and slope["holds"] is None and slope["note"].startswith("shown, not counted")


def test_producers_return_the_core_artifact_with_its_id():
    from mtcal.core.artifacts import Artifact
    a = t.fig02(t.AccelScenario(grid_step_deg=15.0))
    assert isinstance(a, Artifact)
    assert (a.artifact_id, a.kind, a.paper_item) == ("tan2022_fig02", "figure", "Fig. 2")
    assert a.producer == "mtcal.studies.tan2022.artifacts.fig02"


def test_error_model_does_not_import_artifacts():
    import ast
    import inspect

    from mtcal.studies.tan2022 import error_model
    tree = ast.parse(inspect.getsource(error_model))
    imported = {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
    assert "artifacts" not in imported and "runs" in imported


def test_hybrid_avoids_spikes_claim_can_fail():
    rows = t.fig12(t.gyro_study(oscillation_duration_s=4.0), seed=1, trials=2).rows
    # one sentence (avoids the jumps, accurate for a long time): one claim on the paper's own simulation, both parts
    claims = [r for r in rows if r["kind"] == "claim"]
    assert len(claims) == 1 and claims[0]["holds"] is False and claims[0]["enforced"] is False
    assert "ratio" in claims[0]["quantity"] and "the jumps are avoided" in claims[0]["note"]
    assert claims[0]["check"](0.9) is True and claims[0]["check"](1.5) is False  # worse than the projection fails
    noisy = [r for r in rows if "with noise" in r["quantity"]]
    assert len(noisy) == 2 and all(r["holds"] is None and r["mc_band"] for r in noisy)
    assert all(r["note"].startswith("the Fig 12 sentence is judged once") for r in noisy)
    # a hybrid accurate with constant errors: a gyro error far below the threshold's tolerance (tan 1° × 0.5 °/s)
    good = t.fig12(t.gyro_study(oscillation_duration_s=4.0, gyro_error_y_deg_s=0.001, gyro_error_z_deg_s=0.001),
                   seed=1, trials=2).rows
    assert [r["holds"] for r in good if r["kind"] == "claim"] == [True]


def test_paper_statements_at_paper_settings_are_consistency():
    rows = t.fig02(t.AccelScenario(grid_step_deg=15.0)).rows
    assert rows[0]["kind"] == "consistency" and rows[0]["note"] == t.artifacts.ANALYTIC


def test_fit_and_predict_is_deterministic_and_validated():
    a, b = t.error_model.fit_and_predict("ci", seed=3), t.error_model.fit_and_predict("ci", seed=3)
    assert all(np.array_equal(a[k], b[k]) for k in a)
    with pytest.raises(ValueError, match="size must be 'ci' or 'full'"):
        t.error_model.fit_and_predict("huge")


# ---------------------------------------------------------------- trial blocks (1000-trial runs in bounded memory)
def test_gyro_trials_equal_the_one_shot_simulation_in_any_blocks():
    from mtcal.core.rng import stream_rng
    from mtcal.studies.tan2022.runs import GyroTrials, simulate_gyro

    st = t.gyro_study(oscillation_duration_s=1.0)
    time_s, pitch = st.uniform.profile(60.0)
    a, b = stream_rng(4, 9), stream_rng(4, 9)
    one_shot = simulate_gyro(st, time_s, pitch, a, 5)
    runs = GyroTrials(st, time_s, pitch, b, 5)
    assert np.array_equal(np.concatenate([w for _, w in runs.blocks(2)]), one_shot)
    for sl, w in runs.blocks(2, reuse=True):  # one pair of buffers for every block: each valid until the next step
        assert np.array_equal(w, one_shot[sl])
    assert np.array_equal(runs.records([3])[0], one_shot[3])  # any trial regenerated alone
    assert np.array_equal(simulate_gyro(st, time_s, pitch, a, 2), simulate_gyro(st, time_s, pitch, b, 2))  # rng moved on alike


def test_fig09_draws_the_median_trial_of_the_ensemble():
    st = t.gyro_study(pitch_rates_deg_s=(60.0, 120.0))
    art = t.fig09(st, 1, 5)
    for curve, rec in zip(art.data["curves"], art.table.to_dict("records")):
        assert curve["trials"] == 5 and 0 <= curve["trial"] < 5
        assert abs(curve["integration"][-1]) == pytest.approx(rec["integration_final_median_deg"], rel=1e-12)


def test_fig10_shows_the_band_over_trials():
    art = t.fig10(t.gyro_study(oscillation_duration_s=2.0), 1, 7)
    band, n = art.data["band"], art.data["trials"]
    assert n == 7 and band["low"].shape == art.data["true"].shape
    assert np.all(band["low"] <= band["median"]) and np.all(band["median"] <= band["high"])
    with pytest.raises(ValueError, match="trials"):
        t.fig10(t.gyro_study(oscillation_duration_s=2.0), 1, 0)


def test_pattern_claims_early_stop_keeps_the_decision():
    from mtcal.core.rng import stream_rng
    from mtcal.studies.tan2022.runs import oscillation_claims

    st = t.gyro_study(oscillation_duration_s=4.0)
    z = stream_rng(1, 220).standard_normal((4, st.oscillation.time_s().size, 3))
    for b_z in (0.0, 0.2):
        full = oscillation_claims(st, b_z, 1e-4, None, 4, normals=z)
        fast = oscillation_claims(st, b_z, 1e-4, None, 4, normals=z, accurate_deg=1.0)
        assert np.array_equal((full[0] > 5) & (full[1] < 1.0), (fast[0] > 5) & (fast[1] < 1.0))


def test_gyro_predictions_drift_without_noise_is_bias_times_duration():
    from mtcal.core.rng import stream_rng
    from mtcal.studies.tan2022.runs import gyro_predictions

    st = t.gyro_study(oscillation_duration_s=1.0)
    out = gyro_predictions(st, np.array([0.2, 0.1]), np.zeros(2), stream_rng(1, 210))
    for r in st.uniform.pitch_rates_deg_s:
        np.testing.assert_allclose(out[f"drift_{r:g}"], np.array([0.2, 0.1]) * 360.0 / r, rtol=1e-9)


def test_gyro_samples_dt_s_gives_the_fs_hz_numbers():
    # #35 item 3: the time base in seconds; σ = N·√(1/dt_s) equals the former N·√fs_hz bit for bit at the paper's rate
    from mtcal.core.rng import stream_rng
    from mtcal.studies.tan2022.runs import gyro_samples

    rate, b, nd = np.linspace(0.0, 1.0, 50), np.array([1e-3, 2e-3]), np.array([4e-5, 5e-5])
    new = gyro_samples(rate, 0.3, b, nd, 1.0 / 1000.0, stream_rng(1, 2), (2, 50))
    w = np.zeros((2, 50, 3))
    w[..., 1], w[..., 2] = rate * np.cos(0.3), -rate * np.sin(0.3)
    w += b.reshape(-1, 1, 1)
    old = w + (nd * np.sqrt(1000.0)).reshape(-1, 1, 1) * stream_rng(1, 2).standard_normal(w.shape)
    assert np.array_equal(new, old)
