"""Bake-off producers: fair tuning on a separate seed, tables, headline, findings, figure, validation."""

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import pytest  # noqa: E402

from mtcal.sweep.bakeoff import (BAKEOFF_DEFAULTS, BAND_MIN_TRIALS, band_label, band_summary,  # noqa: E402
                                 bakeoff_figure, bakeoff_params, family_specs, findings, headline_table, run_bakeoff,
                                 tune_gains)

SMALL = dict(filters=["qncf", "mahony", "vqf"], turntable_motions=["aoa"], turntable_grades=["wang2023cja"],
             windtunnel_grades=["wang2023cja"], vibration_levels_m_s2=[0.0, 3.0], vibration_hz=20.0,
             surface_grades=["wang2022sensors"], surface_vibration_m_s2=[0.0], fs_hz=100.0,
             gain_scales=[0.3, 1.0, 3.0])


@pytest.fixture(scope="module")
def small_run():
    gains, tuning = tune_gains(SMALL, seed=1, trials=2, filter_trials={"vqf": 1}, hold_s=0.5)
    res = run_bakeoff(SMALL, gains, seed=2, trials=3, hold_s=0.5)
    return gains, tuning, res


def test_tuning_picks_each_filters_best_scale_independently(small_run):
    gains, tuning, _ = small_run
    assert set(gains) == {"turntable", "windtunnel", "surface"}
    assert set(gains["surface"]) == {"qncf", "mahony", "vqf", "rams_ekf"}
    for (family, f), g in tuning.groupby(["family", "filter"]):
        assert g["chosen"].sum() == 1
        best = g.loc[g["tuning_error_deg"].idxmin()]
        assert bool(best["chosen"]) and gains[family][f] == best["gain"]
    assert set(tuning[tuning["filter"] == "vqf"].tuning_trials) == {1}
    assert set(tuning[tuning["filter"] != "vqf"].tuning_trials) == {2}
    vqf = tuning[(tuning["filter"] == "vqf") & (tuning.gain_scale == 1.0)]
    assert (vqf["gain"] == 3.0).all() and (vqf["gain_unit"] == "tau_acc (s)").all()


def test_evaluation_tables_headline_and_findings(small_run):
    gains, _, res = small_run
    t = res.tables["windtunnel"]
    assert list(t.columns) == ["vibration_m_s2", "grade", "filter", "quantity", "median", "low", "high", "trials",
                               "band"]
    assert set(t["filter"]) == {"qncf", "mahony", "vqf"} and set(t.trials) == {3} and set(t.band) == {"range"}
    tr = res.trials["windtunnel"]
    row = t[(t["filter"] == "vqf") & (t.quantity == "tilt_rmse_deg") & (t.vibration_m_s2 == 3.0)].iloc[0]
    vals = tr.loc[tr.vibration_m_s2 == 3.0, "vqf.tilt_rmse_deg"]
    assert (row["low"], row["high"]) == (vals.min(), vals.max())      # 3 trials: the range, not a "95 % band"
    assert (t["low"] <= t["median"]).all() and (t["median"] <= t["high"]).all()
    h = headline_table(res)
    assert len(h) == 1 + 2 + 1
    assert (h["ratio"] >= 1).all() and h["paired_win_fraction"].between(0, 1).all()
    wind3 = h[h.scenario == "vibration 3 m/s², wang2023cja"].iloc[0]
    assert wind3["winner"] != "mahony"          # ungated PI law loses under vibration
    rows = findings(res, h)
    assert {r["artifact"] for r in rows} == {"wang2023cja_extra_bakeoff_windtunnel",
                                             "wang2023cja_extra_bakeoff_turntable",
                                             "wang2022sensors_extra_bakeoff_surface"}
    assert all(r["role"] == "finding" and isinstance(r["holds"], bool) for r in rows)
    fig = bakeoff_figure(res, "surface")
    legend = [x.get_text() for x in fig.legends[0].get_texts()]
    assert fig.axes[0].get_yscale() == "log" and "rams_ekf: range of 3 trials" in legend
    assert "95 %" not in fig.axes[0].get_title()
    assert (h["paired_trials"] == 3).all() and (h["winner_band"] == "range of 3 trials").all()
    # tuning and evaluation draw from different seeds: different data
    spec_t = family_specs(SMALL, "surface", seed=1, trials=2, tuning=True)
    spec_e = family_specs(SMALL, "surface", seed=2, trials=3, gains=gains["surface"])
    assert spec_t.seed != spec_e.seed and "gain_scale" in spec_t.grid and "gain_scale" not in spec_e.grid
    assert spec_e.fixed["gain_rams_ekf"] == gains["surface"]["rams_ekf"]


def test_params_validation():
    assert bakeoff_params()["filters"] == BAKEOFF_DEFAULTS["filters"]
    with pytest.raises(ValueError, match=r"unknown bake-off parameter\(s\) \['colour'\]"):
        bakeoff_params(colour=1)
    with pytest.raises(ValueError, match="filters must be a non-empty list"):
        bakeoff_params(filters=["qncf", "kalman"])
    with pytest.raises(ValueError, match="turntable_grades must be"):
        bakeoff_params(turntable_grades=["gold"])
    with pytest.raises(ValueError, match="gain_scales must be > 0"):
        bakeoff_params(gain_scales=[0.0, 1.0])
    with pytest.raises(ValueError, match=r"vibration_hz must be <= 0.45 fs_hz = 36 Hz"):
        bakeoff_params(fs_hz=80.0)
    with pytest.raises(ValueError, match="family must be one of"):
        family_specs({}, "ocean", seed=1, trials=1)
    with pytest.raises(ValueError, match="vibration_levels_m_s2"):
        bakeoff_params(vibration_levels_m_s2=[-1.0])
    assert np.isclose(bakeoff_params(fs_hz=100.0, vibration_hz=45.0)["vibration_hz"], 45.0)


def test_filters_with_their_own_trial_count_share_the_records(small_run):
    gains, _, full = small_run
    res = run_bakeoff(SMALL, gains, seed=2, trials=3, filter_trials={"vqf": 2}, hold_s=0.5,
                      families=("windtunnel",))
    t = res.tables["windtunnel"]
    assert set(t[t["filter"] == "vqf"].trials) == {2} and set(t[t["filter"] != "vqf"].trials) == {3}
    tr, ref = res.trials["windtunnel"], full.trials["windtunnel"]
    assert tr["vqf.tilt_rmse_deg"].isna().sum() == 2                  # trial 2 of both cells: not run for vqf
    first = tr.trial < 2
    assert np.array_equal(tr.loc[first, "vqf.tilt_rmse_deg"], ref.loc[first, "vqf.tilt_rmse_deg"])   # same records
    assert np.array_equal(tr["qncf.tilt_rmse_deg"], ref["qncf.tilt_rmse_deg"])
    h = headline_table(res)
    assert set(h.paired_trials) <= {2, 3}
    with pytest.raises(ValueError, match=r"filter_trials\['vqf'\] must be a positive integer, got 0"):
        run_bakeoff(SMALL, gains, seed=2, trials=3, filter_trials={"vqf": 0}, families=("windtunnel",))
    with pytest.raises(ValueError, match="trials must be a positive integer, got -1"):
        tune_gains(SMALL, seed=1, trials=-1, families=("windtunnel",))
    with pytest.raises(ValueError, match=r"only=\['kalman'\] leaves no filter"):
        family_specs(SMALL, "surface", seed=1, trials=2, only=["kalman"])


def test_band_summary_names_its_band():
    few = band_summary([3.0, 1.0, np.nan, 2.0])
    assert few == {"median": 2.0, "low": 1.0, "high": 3.0, "trials": 3, "band": "range"}
    x = np.random.default_rng(0).normal(size=BAND_MIN_TRIALS)
    many = band_summary(x)
    assert many["band"] == "95 % band" and many["trials"] == BAND_MIN_TRIALS
    assert np.isclose(many["low"], np.percentile(x, 2.5)) and many["low"] > x.min()
    assert band_summary([np.nan])["trials"] == 0
    assert band_label("95 % band", 1000) == "95 % band of 1000 trials"


def test_a_ranking_is_resolved_only_beyond_a_coin_flip():
    from mtcal.sweep.bakeoff import _resolution

    assert _resolution(863, 1000) == (True, "resolved: wins 863 of 1000 paired trials (Wilson 95 % 0.84–0.88)")
    assert _resolution(12, 12)[0] and not _resolution(3, 3)[0] and not _resolution(6, 12)[0]
    assert _resolution(530, 1000)[0] is False           # 53 %: within Monte Carlo error of ½
    assert _resolution(0, 0) == (False, "not resolved: no trial ran both filters")
    # n = 12: 10 wins is the smallest count that resolves (Wilson 0.55–0.95); 9 does not (0.47–0.91)
    assert _resolution(10, 12) == (True, "resolved: wins 10 of 12 paired trials (Wilson 95 % 0.55–0.95)")
    assert _resolution(9, 12) == (False, "not resolved: wins 9 of 12 paired trials "
                                         "(Wilson 95 % 0.47–0.91 includes ½)")
    # the runner-up wins the paired trials beyond a coin flip: not a resolved ranking for the winner
    assert _resolution(2, 12) == (False, "resolved: wins 2 of 12 paired trials (Wilson 95 % 0.05–0.45 below ½)")
    with pytest.raises(ValueError, match="need n >= 1 and 0 <= k <= n"):
        _resolution(5, 3)
    with pytest.raises(TypeError, match="k and n must be int"):
        _resolution(7.0, 12)


def test_surface_finding_fails_when_the_ranking_is_not_resolved(small_run):
    _, _, res = small_run
    h = headline_table(res)
    assert {"paired_wins", "resolved", "verdict"} <= set(h.columns)
    assert (h["paired_wins"] <= h["paired_trials"]).all()
    assert (~h["resolved"]).all()                         # 3 paired trials never resolve a ranking
    surf = [r for r in findings(res, h) if r["artifact"] == "wang2022sensors_extra_bakeoff_surface"]
    assert surf and all(r["holds"] is False and r["enforced"] is False and r["note"].startswith("fails")
                        for r in surf)
    forced = h.copy()
    forced.loc[forced.family == "surface", ["winner", "resolved"]] = ["rams_ekf", True]
    assert all(r["holds"] for r in findings(res, forced) if r["artifact"] == "wang2022sensors_extra_bakeoff_surface")


def test_reference_check_reruns_the_compiled_anchor_through_its_library_on_the_bakeoffs_own_records():
    pytest.importorskip("ahrs")
    from mtcal.sweep.bakeoff import REFERENCE_TOLERANCE_DEG, reference_check
    from mtcal.sweep.evaluators import filter_gain

    p = {**SMALL, "filters": ["qncf", "madgwick"], "vibration_levels_m_s2": [3.0, 0.0]}
    gains = {fam: {f: filter_gain({"gain_scale": 1.0}, f) for f in ("qncf", "madgwick", "rams_ekf")}
             for fam in ("turntable", "windtunnel", "surface")}
    check = reference_check(p, gains, seed=2, hold_s=0.5, trials=2)
    assert set(check["filter"]) == {"madgwick"} and set(check.trial) == {0, 1}       # only filters with a reference
    assert set(check.scenario) == {"aoa sweep, wang2023cja", "vibration 3 m/s², wang2023cja",
                                   "vibration 0 m/s², wang2022sensors"}              # the first cell of each family
    assert len(check) == 3 * 3 * 2 and check.equal.all()
    assert (check.difference_deg <= REFERENCE_TOLERANCE_DEG).all() and (check.compiled_deg > 0).all()
    # trial j of the check is the bake-off's own trial j of that cell
    res = run_bakeoff(p, gains, seed=2, trials=2, hold_s=0.5, families=("windtunnel",))
    tr = res.trials["windtunnel"]
    own = tr.loc[tr.vibration_m_s2 == 3.0, "madgwick.tilt_rmse_deg"].to_numpy()
    got = check[(check.family == "windtunnel") & (check.quantity == "tilt_rmse_deg")].compiled_deg.to_numpy()
    assert np.array_equal(own, got)
    assert reference_check({**p, "filters": ["qncf"]}, gains, seed=2, hold_s=0.5).empty


def test_a_shared_executor_gives_the_same_numbers_and_stays_open(small_run):
    """tune_gains and run_bakeoff on one caller's executor (one set of worker processes): same tables."""
    from mtcal.sweep.executors import SerialExecutor

    gains, tuning, res = small_run
    ex = SerialExecutor()
    closed = []
    ex.close = lambda: closed.append(True)
    g2, t2 = tune_gains(SMALL, seed=1, trials=2, filter_trials={"vqf": 1}, hold_s=0.5, families=("windtunnel",),
                        executor=ex)
    r2 = run_bakeoff(SMALL, gains, seed=2, trials=3, hold_s=0.5, families=("windtunnel",), executor=ex)
    assert g2["windtunnel"] == gains["windtunnel"]
    pd.testing.assert_frame_equal(t2, tuning[tuning.family == "windtunnel"].reset_index(drop=True))
    pd.testing.assert_frame_equal(r2.tables["windtunnel"], res.tables["windtunnel"])
    assert closed == []
