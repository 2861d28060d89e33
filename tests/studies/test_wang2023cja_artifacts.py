"""Tests for mtcal.studies.wang2023cja artifacts, plots and the constrained-calibration producers."""

import numpy as np
import pytest

from mtcal.reporting import compare
from mtcal.studies import wang2023cja as w
from mtcal.studies.wang2023cja import constrained


def _fake_sweep():
    ref = np.radians([1.0, 2.0])
    sweep = {"reference": ref, "before_mean": ref + np.radians([[0.1, -0.3], [0.0, 0.2]]),
             "after_mean": ref + np.radians([[0.01, 0.0], [-0.02, 0.0]])}
    for state, k in (("before", 2.0), ("after", 1.0)):
        for key in ("maxae", "rmse"):
            for j in (2, 0, 1):
                sweep[f"{state}_{key}_{j}"] = np.radians(k * np.array([0.01, 0.03]))
    return sweep


def test_error_metric_table_and_bands():
    t = w.error_metric_table("wang2023cja_table11", _fake_sweep(), ((2, "roll"), (0, "yaw")))
    assert len(t) == 8 and set(t.metric) == {"MaxAE", "RMSE"}
    row = t[(t.metric == "RMSE") & (t.state == "before") & (t.angle == "yaw")].iloc[0]
    assert np.isclose(row.mtcal, 0.02) and np.isclose(row.mc_median, 0.04) and row.paper == 0.012


def test_positions_table_uses_verification_run():
    z = np.zeros((2, 6, 3))
    ref = w.paper_positions()
    run = w.TurntableRun(np.zeros((2, 4, 4)), z, z, ref + np.radians(0.5), ref + np.radians(0.01), ref, z, z)
    t = w.positions_table("T1", run)
    assert len(t) == 18
    yaw = t[t.angle == "yaw"]
    assert np.allclose(yaw.mtcal_after - yaw.reference, 0.01) and np.allclose(yaw.mtcal_before - yaw.reference, 0.5)


def test_roles_and_outside_rows():
    rows = [w.banded("a", "x", 1.0, np.linspace(0.5, 1.5, 41), role="train"),
            w.banded("b", "y", 5.0, np.linspace(0.5, 1.5, 41)),
            w.banded("c", "z", 1.0, np.linspace(0.5, 1.5, 41))]
    t = compare.comparison_table(rows)
    assert list(t.role) == ["train", "heldout", "heldout"]
    assert list(w.outside_rows(t).artifact) == ["b"]
    assert compare.prediction_summary(t) == "paper inside our range of 41 draws: train 1 of 1, heldout 1 of 2"
    with pytest.raises(ValueError, match="role must be one of"):
        w.banded("a", "x", 1.0, np.ones(3), role="predicted")


def test_installation_fit_table_and_q33_check():
    t = w.installation_fit_table()
    assert list(t.test) == ["T1", "T2", "T3", "T4"] and (t.fit_rms_roll_flipped_deg < t.raw_rms_deg).all()
    q = w.printed_matrix_check()
    printed = q[q.matrix == "printed"]
    assert (printed.det < 0).all() and (np.sign(printed.roll_deg) != np.sign(printed.roll_in_deg)).all()


def test_constrained_min_positions_and_q22_noise():
    t = constrained.min_positions_table(1)
    assert dict(zip(("eq13", "so4", "mounting"), t.min_K_generic)) == {"eq13": 4, "so4": 3, "mounting": 1}
    band = w.q22_noise_band(w.ErrorModel(), constrained.symmetric_layout_rad(6), n_mc=200)
    assert band["low"] < 1.0 < band["high"] < 1.004


def test_figures_take_labels_from_values():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mtcal.studies.wang2023cja import plots
    t = np.linspace(0, 1, 5)
    trace = {"x_time_s": t, "x_before_err": np.zeros((5, 3)), "x_after_err": np.ones((5, 3))}
    fig = plots.before_after_figure(trace, "x", ((2, "roll"), (0, "yaw")), title="Fig. 7 gyro industrial")
    assert len(fig.axes) == 2 and fig.axes[0].get_ylabel() == "roll error (°)"
    assert "industrial" in fig._suptitle.get_text()
    plt.close(fig)


def test_stepwise_coupling_detects_sine_coupling():
    ref = np.zeros((100, 3))
    ref[:, 1] = np.radians(np.repeat([0.0, 4.0, 8.0, 12.0], 25))
    trace = {"aoa_before_err": np.zeros((100, 3)), "aoa_reference": ref}
    trace["aoa_before_err"][:, 2] = -0.004 * np.sin(ref[:, 1]) + 1e-6 * np.cos(np.arange(100))
    assert w.stepwise_coupling(trace, "aoa", 2, 1) < -0.99


def test_constrained_parameters_are_validated():
    assert constrained.check_parameters(12, (0.01, 0.02)) == {"k_max": 12, "noise_levels_deg": (0.01, 0.02)}
    with pytest.raises(ValueError, match=r"k_max must be an int in \[6, 12\]"):
        constrained.check_parameters(13, (0.01,))
    with pytest.raises(ValueError, match="noise_levels_deg must be angles"):
        constrained.check_parameters(12, (-0.01,))
