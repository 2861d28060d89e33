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


def test_a_wind_tunnel_session_figure_refuses_a_trace_without_its_median_session():
    """No silent trial 0: a wind-on time-series figure titles the median session by its rule, and a run traced
    without one (run_windtunnel's default trace_trial=0) is refused rather than labelled "session 1"."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from types import SimpleNamespace
    from mtcal.studies.wang2023cja import plots
    t = np.linspace(0.0, 10.0, 50)
    trace = {"wind_time_s_0": t, "amd_pct": np.full(50, 0.1)}
    run = SimpleNamespace(trace=trace, q_matrix=np.zeros((7, 4, 4)))
    with pytest.raises(ValueError, match="run.trace has no median_trial"):
        plots.extra_amd(run, 0.3, 3.0)
    trace["median_trial"] = 3
    fig = plots.extra_amd(run, 0.3, 3.0)
    assert "median session (4 of 7, by Table 10's group Std)" in fig.axes[0].get_title()
    labels = fig.axes[0].get_legend_handles_labels()[1]
    assert "wind off (flow starts at 5 s)" in labels and "gate fraction counted from 8 s" in labels
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


# --- one producer per artifact (mtcal.core.artifacts.produces): the Artifact's table is the building block's


def _paper_sweep(artifact, angle):
    """A 2-trial sweep on the reference points of the paper's table ``artifact`` (metrics as in _fake_sweep)."""
    from mtcal.reporting import paper_numbers

    ref = np.radians(paper_numbers.load(w.artifacts._TABLE_FILES[artifact])[f"reference_mean_{angle}_deg"].to_numpy(float))
    noise = np.radians(np.linspace(-0.05, 0.05, 2 * ref.size)).reshape(2, -1)
    return {**_fake_sweep(), "reference": ref, "before_mean": ref + noise, "after_mean": ref + 0.1 * noise}


def _fake_turntable_run():
    z = np.zeros((2, 6, 3))
    ref = w.paper_positions()
    run = w.TurntableRun(np.zeros((2, 4, 4)), z, z, ref + np.radians(0.5), ref + np.radians(0.01), ref, z, z)
    run.sweeps = {"aoa": _paper_sweep("wang2023cja_table05", "pitch"), "roll": _paper_sweep("wang2023cja_table07", "roll")}
    return run


def test_every_producer_is_registered_under_its_id():
    from mtcal.core.artifacts import Artifact

    assert len(w.PRODUCERS) == 23
    for ident, fn in w.PRODUCERS.items():
        assert fn.artifact_id == ident and ident.startswith("wang2023cja_")
        assert getattr(w, fn.__name__) is fn                     # re-exported by the package
    art = w.table03(_fake_turntable_run())
    assert isinstance(art, Artifact) and (art.artifact_id, art.kind, art.paper_item) == ("wang2023cja_table03", "table",
                                                                                       "Table 3")
    assert art.producer == "mtcal.studies.wang2023cja.artifacts.table03"


def test_turntable_producers_give_the_building_block_tables():
    run = _fake_turntable_run()
    for i, test in enumerate(("T1", "T2", "T3", "T4")):
        assert w.PRODUCERS[f"wang2023cja_table{i + 1:02d}"](run).table.equals(w.positions_table(test, run))
    sweep = run.sweeps
    assert w.table05(run).table.equals(w.sweep_mean_table("wang2023cja_table05", sweep["aoa"], "pitch"))
    assert w.table06(run).table.equals(w.error_metric_table("wang2023cja_table06", sweep["aoa"],
                                                            ((2, "roll"), (0, "yaw"))))
    assert w.table07(run).table.equals(w.sweep_mean_table("wang2023cja_table07", sweep["roll"], "roll",
                                                          sign=w.PAPER_SIGN[2]))
    assert w.table08(run).table.equals(w.error_metric_table("wang2023cja_table08", sweep["roll"],
                                                            ((1, "pitch"), (0, "yaw"))))
    assert w.extra_installation_fit().table.equals(w.installation_fit_table())
    assert w.extra_q33_roll().table.equals(w.printed_matrix_check())


def test_windtunnel_producers_give_the_building_block_tables():
    from types import SimpleNamespace

    run = SimpleNamespace(nowind=_paper_sweep("wang2023cja_table09", "pitch"), q_matrix=np.tile(np.eye(4), (3, 1, 1)))
    assert w.table09(run).table.equals(w.sweep_mean_table("wang2023cja_table09", run.nowind, "pitch"))
    assert w.table11(run).table.equals(w.error_metric_table("wang2023cja_table11", run.nowind,
                                                            ((2, "roll"), (0, "yaw"))))
    assert w.extra_windtunnel_matrix(run).table.equals(w.windtunnel_matrix_table(run))


def test_constrained_producers_give_the_building_block_tables():
    noise = w.extra_error_vs_noise((0.01, 0.02), 20, 5, 3)
    assert noise.table.equals(constrained.error_vs_noise_table((0.01, 0.02), 20, 5, 3))
    positions = w.extra_error_vs_positions(0.02, 20, 5, 3, range(3, 7))
    assert positions.table.equals(constrained.error_vs_positions_table(0.02, 20, 5, 3, range(3, 7)))
    head = w.extra_constrained_headline(noise.table, positions.table, 0.02)
    table, info = constrained.headline(noise.table, positions.table, 0.02)
    assert head.table.equals(table) and head.lines == [constrained.headline_text(info)]
    q33 = w.extra_q33_sign()
    assert q33.table.equals(constrained.q33_variants_table()[0]) and "after_roll_deg" in q33.data
    assert w.extra_printed_matrices_so4().table.equals(constrained.printed_matrices_so4_table())
    assert w.extra_noise_vs_so4_distance((0.01,), 20, 3).table.equals(
        constrained.noise_vs_so4_distance_table((0.01,), 20, 3))
    assert w.extra_min_positions(3).kind == "table"
