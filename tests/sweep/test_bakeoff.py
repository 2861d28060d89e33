"""Bake-off producers: fair tuning on a separate seed, tables, headline, findings, figure, validation."""

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

from mtcal.sweep.bakeoff import (BAKEOFF_DEFAULTS, bakeoff_figure, bakeoff_params, family_specs,  # noqa: E402
                                 findings, headline_table, run_bakeoff, tune_gains)

SMALL = dict(filters=["qncf", "mahony", "vqf"], turntable_motions=["aoa"], turntable_grades=["wang2023cja"],
             windtunnel_grades=["wang2023cja"], vibration_levels_m_s2=[0.0, 3.0], vibration_hz=20.0,
             surface_grades=["wang2022sensors"], surface_vibration_m_s2=[0.0], fs_hz=100.0,
             gain_scales=[0.3, 1.0, 3.0])


@pytest.fixture(scope="module")
def small_run():
    gains, tuning = tune_gains(SMALL, seed=1, trials=2, hold_s=0.5)
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
    vqf = tuning[(tuning["filter"] == "vqf") & (tuning.gain_scale == 1.0)]
    assert (vqf["gain"] == 3.0).all() and (vqf["gain_unit"] == "tau_acc (s)").all()


def test_evaluation_tables_headline_and_findings(small_run):
    gains, _, res = small_run
    t = res.tables["windtunnel"]
    assert list(t.columns) == ["vibration_m_s2", "grade", "filter", "quantity", "median", "low", "high", "trials"]
    assert set(t["filter"]) == {"qncf", "mahony", "vqf"} and set(t.trials) == {3}
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
    assert fig.axes[0].get_yscale() == "log" and "3 trials" in fig.axes[0].get_title()
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
