"""Tests for mtcal.studies.wang2023cja.runs: sessions with verification runs, mechanism, wind tunnel."""

from dataclasses import replace

import numpy as np
import pytest

from mtcal.core import montecarlo, rotations
from mtcal.core.simulate import TiltedTrajectories
from mtcal.studies import wang2023cja as w


@pytest.fixture(scope="module")
def fast_sc():
    sc = w.turntable_scenario(turntable_rate_deg_s=60.0, fs_hz=200.0)
    return replace(sc, errors=w.ErrorModel(compliance_gasket_deg_g=0.3, gasket_load_tilt_deg_g=0.2))


def test_turntable_noise_free_is_exact(fast_sc):
    run = w.run_turntable(fast_sc, "T2", np.random.default_rng(0), 1, sources=())
    assert np.abs(w.position_errors_deg(run, "after")).max() < 1e-6
    assert np.abs(run.q_matrix[0] - w.true_error_matrix(fast_sc.alpha_rad("T2"))).max() < 1e-8


def test_compliance_alone_matches_rest_model(fast_sc):
    sc = replace(fast_sc, errors=replace(fast_sc.errors, gasket_load_tilt_deg_g=0.0))
    run = w.run_turntable(sc, "T2", np.random.default_rng(0), 1, sources=("mount_compliance",))
    sim = w.position_errors_deg(run, "after")[0]
    res = w.rest_residuals(sc.alpha_rad("T2"), sc.errors, "gasket", np.zeros((1, w.N_NORMALS)))
    expected = np.degrees(res["after"][0] - w.paper_positions())
    assert abs(expected[4, 2]) > 0.1 and np.allclose(sim, expected, atol=2e-3)


def test_verification_run_differs_from_in_sample(fast_sc):
    run = w.run_turntable(fast_sc, "T1", np.random.default_rng(3), 2)
    ins = np.sqrt(np.mean(w.position_errors_deg(run, "after_in_sample") ** 2))
    ver = np.sqrt(np.mean(w.position_errors_deg(run, "after") ** 2))
    before = np.sqrt(np.mean(w.position_errors_deg(run, "before") ** 2))
    assert ins < ver < before
    with pytest.raises(ValueError, match="state"):
        w.position_errors_deg(run, "during")


def test_jobs_stacking_does_not_change_numbers(fast_sc):
    jobs = [w.TurntableJob("T2", np.random.default_rng(1), 3),
            w.TurntableJob("T3", np.random.default_rng(2), 1, ("gyro_white",), fraction=0.3)]
    stacked = w.run_turntable_jobs(fast_sc, jobs, block=2)
    alone = [w.run_turntable_jobs(fast_sc, [j], block=2)[0]
             for j in (w.TurntableJob("T2", np.random.default_rng(1), 3),
                       w.TurntableJob("T3", np.random.default_rng(2), 1, ("gyro_white",), fraction=0.3))]
    for a, b in zip(stacked, alone):
        assert np.allclose(a.ver_after, b.ver_after, atol=1e-12, rtol=0)
        assert np.allclose(a.q_matrix, b.q_matrix, atol=1e-12, rtol=0)
    assert not np.allclose(stacked[0].ver_after[0], stacked[0].ver_after[1])


def test_jobs_validation(fast_sc):
    rng = np.random.default_rng(0)
    with pytest.raises(ValueError, match="jobs"):
        w.run_turntable_jobs(fast_sc, [])
    with pytest.raises(TypeError, match="jobs"):
        w.run_turntable_jobs(fast_sc, [("T1", rng, 1)])
    with pytest.raises(ValueError, match="test"):
        w.run_turntable_jobs(fast_sc, [w.TurntableJob("T9", rng, 1)])
    with pytest.raises(ValueError, match="trials"):
        w.run_turntable_jobs(fast_sc, [w.TurntableJob("T1", rng, 0)])
    with pytest.raises(ValueError, match="sources"):
        w.run_turntable_jobs(fast_sc, [w.TurntableJob("T1", rng, 1, ("bogus",))])
    with pytest.raises(ValueError, match="block"):
        w.run_turntable_jobs(fast_sc, [w.TurntableJob("T1", rng, 1)], block=0)


def test_load_tilt_outputs_rotate_gravity():
    q_wb = np.tile([1.0, 0, 0, 0], (5, 1))
    acc = np.tile([0.0, 0.0, 9.8], (1, 5, 1))
    gyro = np.zeros((1, 5, 3))
    w.load_tilt_outputs(gyro, acc, q_wb, 0.01, (1.0, 0, 0, 0), np.array([[0.01, 0.0, 0.0]]))
    assert np.allclose(acc[0, :, 1], 0.098) and np.allclose(gyro, 0.0)   # level: constant tilt, no rate


def test_mechanism_backlash_depends_on_direction():
    sc = w.WindTunnelScenario(pitch_ratio_error=-0.003, alpha_deg=(0.0, 0.0, 0.0))
    from mtcal.core.profiles import step_schedule
    prof = step_schedule(np.radians([[0, 0, 0], [0, 4, 0], [0, 0, 0]]), np.radians(2), 2.0, 100.0)
    act = w.mechanism_actual(sc, prof, np.radians(2))
    up = act[prof.segment == 2, 1].mean() - np.radians(4) * (1 + sc.pitch_ratio_error)
    down = act[prof.segment == 4, 1].mean()
    assert up < 0 < down
    assert np.isclose(down - up, sc.transmission_gap_rad + 2 * sc.servo_lag_s * np.radians(2))


def test_mechanism_stop_directions_shared_give_the_same_bits():
    """``mechanism_actual(..., stops=stop_directions(prof))`` equals the per-axis formula it replaced
    (``act[:, axis] -= last · stop · ¬moving``) bit for bit, signed zeros included."""
    from mtcal.core.profiles import step_schedule
    from mtcal.studies.wang2023cja.scenario import stop_directions
    sc = w.WindTunnelScenario(pitch_ratio_error=-0.003, alpha_deg=(0.0, 0.0, 0.0))
    wp = np.radians([[0, 0, 0], [0, 4, -2], [3, 4, -2], [3, -1, 5], [0, 0, 0]])
    prof = step_schedule(wp, np.radians(2), 1.5, 100.0, min_move_s=0.5)
    rate = np.radians(2)
    ref = prof.angle_rad.copy()
    ref[:, 1] *= 1.0 + sc.pitch_ratio_error
    stop = 0.5 * sc.transmission_gap_rad + sc.servo_lag_s * rate
    for axis in range(3):
        r = prof.rate_rad_s[:, axis]
        moving = np.abs(r) > 1e-9
        idx = np.where(moving, np.arange(r.size), 0)
        np.maximum.accumulate(idx, out=idx)
        last = np.where(moving, np.sign(r), 0.0)[idx]
        last[~moving & (idx == 0) & ~moving[0]] = 0.0
        ref[:, axis] -= last * stop * ~moving
    ref[:, 0] += sc.non_orthogonality_rad[0] * prof.angle_rad[:, 1]
    ref[:, 2] += sc.non_orthogonality_rad[1] * prof.angle_rad[:, 1]
    stops = stop_directions(prof)
    for act in (w.mechanism_actual(sc, prof, rate), w.mechanism_actual(sc, prof, rate, stops=stops)):
        assert act.tobytes() == ref.tobytes()
    assert set(np.unique(stops)) <= {-1.0, 0.0, 1.0} and not stops[0].any()


def test_identified_ratio_reproduces_printed_q22():
    sc = w.windtunnel_scenario(fs_hz=200.0)
    run = w.run_windtunnel(sc, np.random.default_rng(0), 1, sources=(), wind_on=False)
    assert run.q_matrix[0, 1, 1] == pytest.approx(w.PRINTED_WINDTUNNEL_Q22, abs=2e-5)
    two = w.run_windtunnel(sc, np.random.default_rng(0), 3, sources=("gyro_white",), wind_on=False, block=2)
    assert two.q_matrix.shape == (3, 4, 4) and two.nowind["before_mean"].shape[0] == 3
    with pytest.raises(ValueError, match="block"):
        w.run_windtunnel(sc, np.random.default_rng(0), 1, block=0)


def test_error_budget_rows(fast_sc):
    b = w.error_budget_table(fast_sc, "T2", 1, 7).set_index("source")
    assert list(b.index[[0, -1]]) == ["none", "all"] and len(b) == len(w.SOURCES) + 2
    assert b.loc["none", "after_max_deg"] < 1e-6
    # one trial: the white-noise row is one draw of a wide distribution (16 seeds: 0.002-0.012 deg)
    assert b.loc["mount_compliance", "after_rms_deg"] > 3 * b.loc["gyro_white", "after_rms_deg"]
    assert b.loc["accel_run_change", "in_sample_rms_deg"] < 1e-6 < b.loc["accel_run_change", "after_rms_deg"]


def test_calibration_step_is_the_systems_procedure(fast_sc):
    """The study's calibration step is systems.installation.calibrate_installation with the gates off."""
    from mtcal.core.rotations import mount_quaternion
    from mtcal.core.simulate import simulate_imu
    from mtcal.filters.qncf import qncf
    from mtcal.systems import installation

    prof, spans = w.turntable_profile(fast_sc, with_sweeps=False)
    traj = w.compliance_trajectory(prof.time_s, prof.angle_rad, 0.0)
    model = fast_sc.imu.error_model(mount_quaternion(fast_sc.alpha_rad("T1")), ("gyro_white",), fast_sc.errors)
    rec = simulate_imu(traj, model, rng=np.random.default_rng(2), trials=2)
    cal = spans["calibration"]
    q_ws = qncf(rec.gyro_rad_s, rec.accel_m_s2, 1 / fast_sc.fs_hz, fast_sc.qncf, return_euler=False).q_ws[:, cal]
    pos = w.six_position_reference(fast_sc)
    got = w.calibration_step(fast_sc, q_ws, rec.gyro_rad_s[:, cal], pos, 0.5)
    ref = installation.calibrate_installation(installation.InstallationConfig(**w.MONTE_CARLO_GATES), pos,
                                              1.0 / fast_sc.fs_hz, q_ws=q_ws, gyro_rad_s=rec.gyro_rad_s[:, cal])
    assert np.array_equal(got.q_hat, ref.q_hat) and got.q_hat.shape == (2, 4, 4)
    assert all(np.isinf(v) for v in w.MONTE_CARLO_GATES.values())


def test_scenario_does_not_import_runs():
    """identify_pitch_ratio lives with the mechanism model in scenario: imports go runs -> scenario only."""
    import ast
    import inspect

    from mtcal.studies.wang2023cja import runs, scenario

    def imported(mod):
        return {n.module for n in ast.walk(ast.parse(inspect.getsource(mod))) if isinstance(n, ast.ImportFrom)}

    assert "runs" not in imported(scenario) and "scenario" in imported(runs)
    assert w.identify_pitch_ratio is scenario.identify_pitch_ratio


def _arrays(obj, prefix=""):
    """Every array of a run, by field path (the pinned-hash test's flattening)."""
    from tests.studies.test_wang2023cja_bitexact import _flatten

    out = {}
    _flatten(obj, prefix, out)
    return out


def test_threaded_pieces_and_draws_give_the_same_numbers_for_any_thread_count(fast_sc):
    import numba

    from mtcal.studies.wang2023cja import predictive, runs

    fit = w.fit_error_model(n_mc=200, seed=1)
    sc = replace(fast_sc, errors=fit.model)

    def produce():
        tt = predictive.turntable_predictive(sc, fit, "prior", 3, 5, tests=("T1", "T3"))
        wt = predictive.windtunnel_predictive(lambda m: w.windtunnel_scenario(errors=m, fs_hz=100.0), fit, "fitted",
                                              3, 5, per_draw=1)
        return _arrays(tt, "tt"), _arrays(wt, "wt")

    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        assert runs._workers() == 1
        serial = produce()
        numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))
        assert runs._workers() == numba.get_num_threads() or numba.threading_layer() == "workqueue"
        threaded = produce()
    finally:
        numba.set_num_threads(before)
    for a, b in zip(serial, threaded):
        assert sorted(a) == sorted(b)
        assert [k for k in a if not np.array_equal(a[k], b[k], equal_nan=a[k].dtype.kind == "f")] == []



def test_compiled_pitch_and_sweep_angles_match_the_expressions():
    from mtcal.methods import quaternion_lsq
    from mtcal.studies.wang2023cja import runs

    rng = np.random.default_rng(11)
    q = rotations.quat_normalize(np.array([1.0, 0.1, -0.05, 0.02]) + 0.2 * rng.normal(size=(3, 1500, 4)))
    q[:, ::7] *= -1.0                                                     # both signs of q0
    q_mat = np.eye(4) + 2e-3 * rng.normal(size=(3, 4, 4))
    ref = 0.3 * rng.normal(size=(1500, 3))
    after = runs._euler(quaternion_lsq.apply_error_matrix(q_mat, q))
    assert np.array_equal(rotations.mapped_pitch_trusted(q_mat, q), after[..., 1])
    before = runs._euler(q)
    from mtcal.core import metrics

    from mtcal.core.montecarlo import ERROR_BOUND_RAD

    def gap(x, y):
        return np.abs(metrics.angle_difference(x, y)).max()

    for chan in (0, 1, 2):     # the series pass: within its stated bound of the expressions
        before_k, after_k, errs = montecarlo.channel_errors_before_after(q, q_mat, ref, chan)
        assert gap(before_k, before[..., chan]) <= ERROR_BOUND_RAD + np.spacing(np.pi)
        assert gap(after_k, after[..., chan]) <= ERROR_BOUND_RAD + np.spacing(np.pi)
        assert gap(errs["before"], metrics.angle_difference(before, ref)) <= ERROR_BOUND_RAD
        assert gap(errs["after"], metrics.angle_difference(after, ref)) <= ERROR_BOUND_RAD
    bad = q_mat.copy()
    bad[1, 0, 0] = np.nan
    with pytest.raises(FloatingPointError, match="not finite"):
        rotations.mapped_pitch_trusted(bad, q)


def test_windtunnel_trace_is_the_chosen_trial_and_changes_no_number():
    from mtcal.studies.wang2023cja.runs import TRACE_DECIMATION, windtunnel_median_trial

    sc = w.windtunnel_scenario(fs_hz=200.0)
    runs = [w.run_windtunnel(sc, np.random.default_rng(5), 3, wind_on=True, block=2, trace_trial=t) for t in (0, 2)]
    assert np.array_equal(runs[0].q_matrix, runs[1].q_matrix)
    assert np.array_equal(runs[0].wind_on["group_means"], runs[1].wind_on["group_means"])
    for t, run in zip((0, 2), runs):          # the trace is trial t's (second block for t = 2)
        dec = run.trace["nowind_before_err"][::TRACE_DECIMATION].astype(np.float32)
        assert np.array_equal(dec, run.nowind["before_err_dec"][t])
    assert not np.array_equal(runs[0].trace["wind_pitch_0"], runs[1].trace["wind_pitch_0"])
    m = windtunnel_median_trial(runs[0])
    std = np.degrees(runs[0].wind_on["group_means"]).std(axis=0, ddof=1).max(axis=-1)
    assert std[m] == np.sort(std)[1]          # the median of three
    with pytest.raises(ValueError, match="trace_trial"):
        w.run_windtunnel(sc, np.random.default_rng(5), 3, trace_trial=3)


def test_windtunnel_predictive_traces_its_median_session():
    from mtcal.studies.wang2023cja import predictive
    from mtcal.studies.wang2023cja.runs import TRACE_DECIMATION, windtunnel_median_trial

    fit = w.fit_error_model(n_mc=400, seed=1)
    run = predictive.windtunnel_predictive(lambda m: w.windtunnel_scenario(errors=m, fs_hz=200.0), fit, "fitted",
                                           5, 1, per_draw=2)
    m = windtunnel_median_trial(run)
    assert run.trace["median_trial"] == m
    dec = run.trace["nowind_before_err"][::TRACE_DECIMATION].astype(np.float32)
    assert np.array_equal(dec, run.nowind["before_err_dec"][m])


def test_windtunnel_kinds_side_by_side_equal_separate_runs_and_share_the_vibration(monkeypatch):
    """Fitted and prior side by side: each kind's run equals its own call bit for bit, and every draw's
    wind-on vibration is computed by the first kind and reused (equal phases) by the second."""
    from mtcal.studies.wang2023cja import predictive, runs

    fit = w.fit_error_model(n_mc=200, seed=1)
    make = lambda m: w.windtunnel_scenario(errors=m, fs_hz=100.0)  # noqa: E731
    separate = {kind: _arrays(predictive.windtunnel_predictive(make, fit, kind, 3, 4, per_draw=2), kind)
                for kind in predictive.KINDS}
    reused, orig = [], runs._vibration_accel

    def spy(sc, t, ramp, vib, shared, g):
        before = None if shared is None else shared.get(g)
        out = orig(sc, t, ramp, vib, shared, g)
        reused.append(before is not None and out is before[4])
        return out

    monkeypatch.setattr(runs, "_vibration_accel", spy)
    from mtcal.core import simulate

    filled, fill = [], simulate.fill_streams        # (the groups of simulate.fill_streams_grouped)

    def fill_spy(streams, outputs):
        filled.append(len(streams))
        return fill(streams, outputs)

    monkeypatch.setattr(simulate, "fill_streams", fill_spy)
    joint = predictive.windtunnel_predictive_kinds(make, fit, predictive.KINDS, 3, 4, per_draw=2)
    assert list(joint) == list(predictive.KINDS)
    assert all(set(r.trace) == {"median_trial"} for r in joint.values())    # the bands' runs: no series kept
    # 2 draws × 5 groups: the fitted run computes, the prior run reuses
    assert reused.count(True) == 10 and reused.count(False) == 10
    # 2 draws × (wind off + 5 groups): both kinds' records from one noise draw
    assert filled == [2] * 12
    for kind in predictive.KINDS:               # each kind's median session re-run for its series (one scenario)
        joint[kind].trace = predictive.windtunnel_median_trace(make, fit, kind, joint[kind], 4, per_draw=2)
    assert reused.count(False) == 20 and filled == [2] * 12 + [1] * 12
    for kind in predictive.KINDS:
        arrays = _arrays(joint[kind], kind)
        assert sorted(arrays) == sorted(separate[kind])
        assert [k for k in arrays if not np.array_equal(arrays[k], separate[kind][k], equal_nan=True)] == []


def test_shared_vibration_is_recomputed_when_phases_or_settings_differ():
    from mtcal.studies.wang2023cja import runs

    sc = w.windtunnel_scenario(fs_hz=100.0)
    t = np.arange(0.0, 2.0, 0.01)
    ramp = np.clip(t - 0.5, 0.0, 1.0)
    vib = np.random.default_rng(0).uniform(0, 2 * np.pi, (2, 1, 3))
    shared = {}
    first = runs._vibration_accel(sc, t, ramp, vib, shared, 0)
    assert runs._vibration_accel(sc, t, ramp, vib.copy(), shared, 0) is first
    other = runs._vibration_accel(sc, t, ramp, vib + 1e-9, shared, 0)
    assert other is not first and not np.array_equal(other, first)
    faster = replace(sc, vibration_freq_hz=2 * sc.vibration_freq_hz)
    assert runs._vibration_accel(faster, t, ramp, vib + 1e-9, shared, 0) is not other
    expected = ramp[None, :, None] * sc.vibration_accel_m_s2 * np.sin(2 * np.pi * sc.vibration_freq_hz
                                                                      * t[None, :, None] + vib)
    assert np.array_equal(first, expected)


def test_compliance_trajectory_is_the_base_tilted_about_the_lateral_load_axis():
    from mtcal.core.simulate import gravity_lateral_axis, tilted_trajectory

    t = np.arange(3000) * 1e-3
    angle = np.zeros((t.size, 3))
    angle[:, 2] = np.linspace(0.0, np.pi / 2, t.size)
    q_wb = rotations.quat_from_euler_zxy(angle[:, 0], angle[:, 1], angle[:, 2])
    for k in (1e-3, -2e-3):
        got, ref = w.compliance_trajectory(t, angle, k), tilted_trajectory(t, q_wb, gravity_lateral_axis(q_wb), k)
        assert np.array_equal(got.q_wb, ref.q_wb) and np.array_equal(got._truth["rates"], ref._truth["rates"])
    assert np.array_equal(w.compliance_trajectory(t, angle, 0.0).q_wb, q_wb)
    # level: no tilt; rolled 90°: the mount tilts by k about a horizontal body axis
    assert np.array_equal(gravity_lateral_axis(q_wb[:1]) + 0.0, [[0.0, 0.0, 0.0]])
    assert np.allclose(gravity_lateral_axis(q_wb[-1:]), [[0.0, 1.0, 0.0]], atol=1e-12)


def test_interleaved_t2_to_t4_equal_one_call_per_test_and_share_their_truth(fast_sc, monkeypatch):
    """turntable_predictive runs a draw's T2–T4 sessions side by side: the numbers of one call per test
    (each job its own generator), and one compliant truth trajectory per draw instead of three."""
    from mtcal.studies.wang2023cja import predictive, runs

    fit = w.fit_error_model(n_mc=200, seed=1)
    sc = replace(fast_sc, errors=fit.model)
    calls = []
    tilted = TiltedTrajectories.__call__
    monkeypatch.setattr(TiltedTrajectories, "__call__", lambda self, k: calls.append(k) or tilted(self, k))
    got = predictive.turntable_predictive(sc, fit, "fitted", 3, 7, tests=("T2", "T3", "T4"), per_draw=1)
    assert list(got) == ["T2", "T3", "T4"]
    assert len(calls) == len(set(calls)) == 3                    # one trajectory per draw (gasket: equal k)
    draws = predictive.posterior_draws(fit, 3, 7)
    for i, test in enumerate(("T2", "T3", "T4")):
        rngs = np.random.default_rng(np.random.SeedSequence([7, 300 + i])).spawn(3)
        jobs = [runs.TurntableJob(test, r, 1, errors=m, alpha_deg=a[test]) for r, (m, a) in zip(rngs, draws)]
        alone = runs._concat_runs(runs.run_turntable_jobs(sc, jobs, block=1))
        a, b = _arrays(alone), _arrays(got[test])
        assert sorted(a) == sorted(b) and all(np.array_equal(a[k], b[k]) for k in a)


def test_expression_paths_of_the_angles_equal_euler(monkeypatch):
    from mtcal.methods import quaternion_lsq
    from mtcal.studies.wang2023cja import runs

    monkeypatch.setattr(rotations, "_KERNEL_MIN_ROWS", 10 ** 12)    # the numpy expressions, not the compiled pass
    rng = np.random.default_rng(12)
    q = rotations.quat_normalize(np.array([1.0, 0.1, -0.05, 0.02]) + 0.2 * rng.normal(size=(2, 300, 4)))
    q_mat = np.eye(4) + 2e-3 * rng.normal(size=(2, 4, 4))
    after = runs._euler(quaternion_lsq.apply_error_matrix(q_mat, q))
    before_k, after_k, _ = montecarlo.channel_errors_before_after(q, q_mat, np.zeros((300, 3)), 1)
    assert np.array_equal(before_k, runs._euler(q)[..., 1]) and np.array_equal(after_k, after[..., 1])
    assert np.array_equal(rotations.mapped_pitch_trusted(q_mat, q), after[..., 1])
    bad = q_mat.copy()
    bad[0, 1, 1] = np.inf                  # refused: the trusted Eq 10 gives non-finite angles, caught after it
    with pytest.raises(FloatingPointError, match="Eq 8 angles are not finite"):
        rotations.mapped_pitch_trusted(bad, q)
    with pytest.raises(FloatingPointError, match="Eq 8 angles are not finite"):
        montecarlo.channel_errors_before_after(q, bad, np.zeros((300, 3)), 1)


def test_windtunnel_session_holds_the_wind_on_sweeps_read_only():
    from mtcal.core.profiles import step_schedule
    from mtcal.studies.wang2023cja import runs

    sc = w.windtunnel_scenario(fs_hz=200.0)
    ses = runs._wt_session(sc)
    assert runs._wt_session(replace(sc, errors=w.ErrorModel(compliance_gasket_deg_g=0.1))) is ses   # one per settings
    won = [group[0] for group in ses.groups]
    assert len(won) == 5 and won[0] is won[3] and won[4] is not won[0]     # groups 1–4 share one sweep
    assert np.array_equal(ses.pos, w.windtunnel_positions(sc))
    for prof, rate in ((won[0], sc.mechanism_rate_rad_s), (won[4], sc.group5_rate_rad_s)):
        ref = step_schedule(runs._wt_waypoints(sc.wind_on_sweep_deg), rate,
                            runs._wt_holds_s(sc.wind_on_sweep_deg, runs.WIND_LEAD_S, sc.wind_on_hold_s),
                            sc.fs_hz, min_move_s=0.5)
        assert np.array_equal(prof.angle_rad, ref.angle_rad) and np.array_equal(prof.time_s, ref.time_s)
        assert not prof.angle_rad.flags.writeable


def test_windtunnel_kinds_without_shared_noise_fill_apart_with_the_same_numbers():
    """Scenarios whose sensors differ in their noise (another gyro grade) or generators on other keys are
    not refused: their records are filled apart, each run equal to its own run_windtunnel call."""
    from mtcal.studies.wang2023cja import runs

    scs = [w.windtunnel_scenario(fs_hz=100.0), w.windtunnel_scenario(fs_hz=100.0, gyro_grade="industrial"),
           w.windtunnel_scenario(fs_hz=100.0)]
    seeds = [3, 3, 4]
    joint = runs.run_windtunnel_kinds(scs, [np.random.default_rng(s) for s in seeds], 2, block=1)
    for sc, seed, run in zip(scs, seeds, joint):
        alone = _arrays(w.run_windtunnel(sc, np.random.default_rng(seed), 2, block=1))
        arrays = _arrays(run)
        assert sorted(arrays) == sorted(alone)
        assert [k for k in arrays if not np.array_equal(arrays[k], alone[k], equal_nan=True)] == []
    with pytest.raises(ValueError, match="scenarios and rngs must be non-empty and of equal length"):
        runs.run_windtunnel_kinds(scs, [np.random.default_rng(1)], 2)
    # measured in one stack: scenarios side by side share their session and QNCF settings
    for other in (w.windtunnel_scenario(fs_hz=100.0, rest_s=12.0), replace(scs[0], qncf=replace(scs[0].qncf, kp_rad_s=0.5))):
        with pytest.raises(ValueError, match="must share their session .* and QNCF parameters"):
            runs.run_windtunnel_kinds([scs[0], other], [np.random.default_rng(1)] * 2, 1)


def test_turntable_kinds_side_by_side_equal_separate_calls_and_share_the_noise(monkeypatch):
    """Fitted and prior T1 sessions side by side (turntable_predictive_kinds): each kind's runs, sweeps and
    trace equal its own turntable_predictive call bit for bit, and every piece pair fills from one noise draw."""
    from mtcal.studies.wang2023cja import predictive, runs

    fit = w.fit_error_model(n_mc=200, seed=1)
    sc = w.turntable_scenario(errors=fit.model, fs_hz=200.0)
    separate = {kind: _arrays(predictive.turntable_predictive(sc, fit, kind, 3, 5, tests=("T1", "T2")), kind)
                for kind in predictive.KINDS}
    from mtcal.core import simulate

    filled, fill = [], simulate.fill_streams        # (the groups of simulate.fill_streams_grouped)
    monkeypatch.setattr(simulate, "fill_streams", lambda streams, outputs: filled.append(len(streams))
                        or fill(streams, outputs))
    joint = predictive.turntable_predictive_kinds(sc, fit, predictive.KINDS, 3, 5, tests=("T1", "T2"))
    assert filled[:3] == [2, 2, 2]        # T1: 3 pieces of one trial per kind, pairs filled together
    for kind in predictive.KINDS:
        arrays = _arrays(joint[kind], kind)
        assert sorted(arrays) == sorted(separate[kind])
        assert any(k.startswith(f"{kind}.T1.trace.aoa") for k in arrays)
        assert [k for k in arrays if not np.array_equal(arrays[k], separate[kind][k], equal_nan=True)] == []


def test_turntable_jobs_kinds_over_several_calls_equal_separate_runs(fast_sc):
    """Aligned job lists over several stacked QNCF calls (each call holding each list's share), with traces:
    the runs of separate run_turntable_jobs calls; misaligned lists refused."""
    from mtcal.studies.wang2023cja import runs

    n = runs.turntable_profile(fast_sc, True)[0].time_s.size
    errors = [fast_sc.errors, replace(fast_sc.errors, gyro_run_bias_deg_h=3.0)]
    make = lambda m: [runs.TurntableJob("T1", np.random.default_rng(s), 2, errors=errors[m]) for s in (1, 2)]  # noqa: E731
    kw = dict(with_sweeps=True, keep_trace=True, block=1, max_trial_samples=int(3 * n))
    joint = runs.run_turntable_jobs_kinds(fast_sc, [make(0), make(1)], **kw)
    for m in range(2):
        alone = runs.run_turntable_jobs(fast_sc, make(m), **kw)
        for got, ref in zip(joint[m], alone):
            a, b = _arrays(got), _arrays(ref)
            assert sorted(a) == sorted(b) and any(k.startswith(".trace") for k in a) == any(k.startswith(".trace") for k in b)
            assert [k for k in a if not np.array_equal(a[k], b[k], equal_nan=True)] == []
    with pytest.raises(ValueError, match="kinds_jobs must be aligned"):
        runs.run_turntable_jobs_kinds(fast_sc, [make(0), make(1)[:1]])


def test_run_windtunnel_and_its_kinds_form_check_their_arguments():
    """run_windtunnel is run_windtunnel_kinds of one scenario (one code path); both refuse the same arguments."""
    from mtcal.studies.wang2023cja import runs

    sc = w.windtunnel_scenario(fs_hz=100.0)
    for bad, match in (({"trials": 0}, "trials must be >= 1"), ({"block": 0}, "block must be >= 1"),
                       ({"trace_trial": 3}, r"trace_trial must be in \[0, 3\)"), ({"sources": ("x",)}, "sources")):
        args = {"trials": 3, **bad}
        with pytest.raises(ValueError, match=match):
            runs.run_windtunnel(sc, np.random.default_rng(7), args.pop("trials"), **args)
        with pytest.raises(ValueError, match=match):
            runs.run_windtunnel_kinds([sc], [np.random.default_rng(7)], 3 if "trials" not in bad else 0,
                                      **{k: v for k, v in bad.items() if k != "trials"})
