"""Tests for mtcal.studies.wang2023cja.runs (mapping, installation fit, budget plumbing, runners)."""

import numpy as np
import pytest

from mtcal.core import rotations
from mtcal.reporting import compare
from mtcal.studies import wang2023cja as s


def test_mount_quaternion_matches_eq1():
    a = np.radians([1.0, -2.0, 3.0])
    c_bs = rotations.installation_matrix(*a)
    assert np.allclose(rotations.quat_to_matrix(rotations.mount_quaternion(a)), c_bs.T, atol=1e-12)


def test_true_error_matrix_maps_sensor_to_body():
    a = np.radians([0.5, 0.2, -0.4])
    ref = np.radians([[8, 0, 0], [0, 23, 0], [0, 0, 90]])
    q_s = rotations.quat_from_euler_zxy(*s.predicted_before(a, ref).T)
    q_b = rotations.align_signs(q_s @ s.true_error_matrix(a).T)
    assert np.allclose(q_b, rotations.align_signs(rotations.quat_from_euler_zxy(*ref.T)), atol=1e-12)


@pytest.mark.parametrize("test", ["T1", "T2", "T3", "T4"])
def test_stored_alphas_are_the_fit(test):
    fit = s.fit_installation_angles(s.TABLES_1_TO_4[test])
    assert np.allclose(np.degrees(fit.alpha_rad), s.TurntableScenario().alpha_deg[test], atol=2e-4)
    assert fit.rms_deg < fit.raw_rms_deg


def test_handedness_flip_explains_tables_better():
    for table in s.TABLES_1_TO_4.values():
        proper = s.fit_installation_angles(table, sign=(1, 1, 1))
        flipped = s.fit_installation_angles(table)
        assert flipped.rms_deg < 0.4 * proper.rms_deg


def test_error_model_sources():
    spec = s.ImuSpec()
    m = spec.error_model((1.0, 0, 0, 0), sources=["gyro_white"])
    assert m.gyro.noise_density > 0 and m.accel.noise_density == 0 and m.gyro.bias_sigma == 0
    assert m.time_since_power_on_s == 300.0
    with pytest.raises(ValueError, match="sources"):
        spec.error_model((1.0, 0, 0, 0), sources=["bogus"])
    df = compare.describe(spec)
    assert (df["source"].str.len() > 0).all()


def test_turntable_noise_free_is_exact():
    sc = s.TurntableScenario()
    run = s.run_turntable(sc, "T2", np.random.default_rng(0), 1, sources=())
    assert np.abs(run.cal_after - run.reference).max() < 1e-8
    assert np.abs(run.q_matrix[0] - s.true_error_matrix(sc.alpha_rad("T2"))).max() < 1e-8


def test_turntable_with_errors_improves(rng):
    sc = s.TurntableScenario()
    run = s.run_turntable(sc, "T1", rng, 2)
    before = np.abs(run.cal_before - run.reference).max(axis=(1, 2))
    after = np.abs(run.cal_after - run.reference).max(axis=(1, 2))
    assert np.all(after < before) and np.all(after > 0)


def test_mechanism_backlash_depends_on_direction():
    sc = s.WindTunnelScenario()
    from mtcal.core.profiles import step_schedule
    prof = step_schedule(np.radians([[0, 0, 0], [0, 4, 0], [0, 0, 0]]), np.radians(2), 2.0, 100.0)
    act = s.mechanism_actual(sc, prof, np.radians(2))
    up = act[prof.segment == 2, 1].mean() - np.radians(4) * (1 + sc.pitch_ratio_error)
    down = act[prof.segment == 4, 1].mean()
    assert up < 0 < down
    assert np.isclose(down - up, sc.transmission_gap_rad + 2 * sc.servo_lag_s * np.radians(2))


# ---- stacked Monte Carlo jobs and notebook helpers ----
def test_jobs_stacking_does_not_change_numbers():
    from dataclasses import replace
    sc = replace(s.TurntableScenario(), turntable_rate_rad_s=np.radians(60.0))   # shorter record
    jobs = [s.TurntableJob("T2", np.random.default_rng(1), 3),
            s.TurntableJob("T3", np.random.default_rng(2), 1, ("gyro_white",), fraction=0.3)]
    stacked = s.run_turntable_jobs(sc, jobs, block=2)            # 3 pieces, one QNCF run
    alone = [s.run_turntable_mc(sc, "T2", np.random.default_rng(1), 3, batch=2),
             s.run_turntable_mc(sc, "T3", np.random.default_rng(2), 1, ("gyro_white",), fraction=0.3)]
    for a, b in zip(stacked, alone):
        assert a.cal_after.shape == b.cal_after.shape
        assert np.allclose(a.cal_after, b.cal_after, atol=1e-12, rtol=0)
        assert np.allclose(a.q_matrix, b.q_matrix, atol=1e-12, rtol=0)
    assert not np.allclose(stacked[0].cal_after[0], stacked[0].cal_after[1])   # blocks draw independently


def test_jobs_validation():
    sc = s.TurntableScenario()
    rng = np.random.default_rng(0)
    with pytest.raises(ValueError, match="jobs"):
        s.run_turntable_jobs(sc, [])
    with pytest.raises(TypeError, match="jobs"):
        s.run_turntable_jobs(sc, [("T1", rng, 1)])
    with pytest.raises(ValueError, match="test"):
        s.run_turntable_jobs(sc, [s.TurntableJob("T9", rng, 1)])
    with pytest.raises(ValueError, match="trials"):
        s.run_turntable_jobs(sc, [s.TurntableJob("T1", rng, 0)])
    with pytest.raises(ValueError, match="sources"):
        s.run_turntable_jobs(sc, [s.TurntableJob("T1", rng, 1, ("bogus",))])
    with pytest.raises(ValueError, match="block"):
        s.run_turntable_jobs(sc, [s.TurntableJob("T1", rng, 1)], block=0)


def test_band_record_and_row():
    rec = compare.band_record("wang2023cja_table05", "x (deg)", 50.5, np.arange(101.0))
    assert np.allclose([rec["median"], rec["low"], rec["high"]], [50.0, 2.5, 97.5]) and rec["paper_in_band"]
    assert not compare.band_record("a", "q", 99.0, np.arange(101.0))["paper_in_band"]
    row = compare.band_row(rec, "claim", True)
    assert row["mtcal"] == 50.0 and row["mc_band"] == "[2.5, 97.5]" and row["paper_in_band"] is True
    assert compare.band_text(rec, digits=1) == "x (deg): MC median 50.0 [2.5, 97.5] (paper 50.5)"
    with pytest.raises(ValueError, match="samples"):
        compare.band_record("a", "q", 1.0, np.zeros((2, 2)))


def _fake_sweep():
    ref = np.radians([1.0, 2.0])
    sweep = {"reference": ref, "before_mean": ref + np.radians([[0.1, -0.3], [0.0, 0.2]]),
             "after_mean": ref + np.radians([[0.01, 0.0], [-0.02, 0.0]])}
    for state, k in (("before", 2.0), ("after", 1.0)):
        for key in ("maxae", "rmse"):
            for j in (2, 0):
                sweep[f"{state}_{key}_{j}"] = np.radians(k * np.array([0.01, 0.03]))
    return sweep


def test_sweep_helpers():
    sw = _fake_sweep()
    assert np.allclose(s.sweep_mean_max_error_deg(sw, "before"), [0.3, 0.2])
    assert np.allclose(s.sweep_mean_max_error_deg(sw, "after"), [0.01, 0.02])
    with pytest.raises(ValueError, match="state"):
        s.sweep_mean_max_error_deg(sw, "during")
    recs = s.sweep_mean_records("wang2023cja_table09", "pitch", {"before": 0.25, "after": 0.05}, sw)
    assert np.isclose(recs["before"]["median"], 0.25) and recs["before"]["paper_in_band"]
    assert recs["after"]["quantity"] == "max |after-ref| mean pitch (deg)" and not recs["after"]["paper_in_band"]
    t = s.error_metric_table("wang2023cja_table11_windtunnel_nowind_roll_yaw_errors", sw, ((2, "roll"), (0, "yaw")))
    assert len(t) == 8 and set(t.metric) == {"MaxAE", "RMSE"}
    row = t[(t.metric == "RMSE") & (t.state == "before") & (t.angle == "yaw")].iloc[0]
    assert np.isclose(row.mtcal, 0.02) and np.isclose(row.mc_median, 0.04) and row.paper == 0.012


def test_position_errors_and_plot():
    run = s.TurntableRun(np.zeros((1, 4, 4)), np.zeros((1, 6, 3)) + np.radians(0.5), np.zeros((1, 6, 3)),
                         np.zeros((6, 3)))
    assert np.allclose(s.position_errors_deg(run, "before"), 0.5)
    with pytest.raises(ValueError, match="state"):
        s.position_errors_deg(run, "x")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    t = np.linspace(0, 1, 5)
    trace = {"x_time_s": t, "x_before_err": np.zeros((5, 3)), "x_after_err": np.ones((5, 3))}
    fig = s.plot_before_after(trace, "x", ((2, "roll"), (0, "yaw")), xlabel="t", title="x")
    assert len(fig.axes) == 2 and fig.axes[0].get_ylabel() == "roll error (deg)"
    plt.close(fig)
