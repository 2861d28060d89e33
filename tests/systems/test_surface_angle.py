"""wang2022sensors surface-angle system: axis from rests (Eq 23), ZVD-switched EKF with clipping restarts,
and the bit-identity of the study path and the ``mtcal axis`` / ``mtcal angle`` commands."""

import re
from dataclasses import replace

import numpy as np
import pandas as pd
import pytest

from mtcal.cli.main import main
from mtcal.core import profiles
from mtcal.core.rotations import axis_angle_matrix
from mtcal.filters.rams_ekf import RamsEkfParams, run_rams_ekf
from mtcal.systems.surface_angle import AxisConfig, SurfaceAngleConfig
from mtcal.methods import rest_detection
from mtcal.systems import plausibility
from mtcal.systems import surface_angle

FS_HZ = 100.0
DT_S = 1.0 / FS_HZ
AXIS = np.array([0.6, 0.0, 0.8])
G0 = np.array([0.0, 0.0, 9.81])
PARAMS = RamsEkfParams(sigma_theta_rad_s=1e-3, sigma_a_static_m_s2=0.01, sigma_a_moving_m_s2=5.0)
CONFIG = SurfaceAngleConfig(PARAMS)


def _rests_at(angles_deg, n=40, axis=AXIS):
    accel = np.concatenate([np.tile(axis_angle_matrix(np.radians(d), axis).T @ G0, (n, 1)) for d in angles_deg])
    return accel, [slice(k * n, (k + 1) * n) for k in range(len(angles_deg))]


def _hinge(angles_deg=(0.0, 60.0, 120.0, 30.0), rate_deg_s=60.0, hold_s=1.0, trials=1):
    prof = profiles.step_schedule(np.radians(angles_deg), np.radians(rate_deg_s), hold_s, FS_HZ)
    th = np.tile(prof.angle_rad[:, 0], (trials, 1))
    w, f = profiles.fixed_axis_imu_truth(th, np.tile(prof.rate_rad_s[:, 0], (trials, 1)),
                                         np.tile(prof.accel_rad_s2[:, 0], (trials, 1)), np.tile(AXIS, (trials, 1)),
                                         np.zeros((trials, 3)), G0, DT_S)
    return prof, w, f


# --------------------------------------------------------------------------- axis
@pytest.mark.parametrize("fit", ["plane", "eq23"])
def test_axis_of_a_known_hinge(fit):
    accel, rests = _rests_at([0.0, 70.0, 140.0, 70.0])
    est = surface_angle.estimate_surface_axis(accel, rests, AxisConfig(0.001, fit=fit))
    np.testing.assert_allclose(est.axis, AXIS, atol=1e-12)
    assert est.positions_m_s2.shape == (3, 3) and est.members == ((0,), (1, 3), (2,))
    np.testing.assert_allclose(np.degrees(est.rest_angles_rad), [0.0, 70.0, 140.0, 70.0], atol=1e-9)
    assert np.degrees(est.elevation_rad) == pytest.approx(np.degrees(np.arcsin(0.8)), abs=1e-9)
    # three positions 70 deg apart on a circle of radius g cos(53 deg): first-order error of the floor noise
    assert est.sigma_mean_m_s2 == surface_angle.SIGMA_MEAN_FLOOR_M_S2 and 0 < est.sigma_rad < np.radians(0.5)


def test_axis_sign_convention_and_eq23_equals_the_plane_for_three():
    accel, rests = _rests_at([0.0, -50.0, -100.0], axis=-AXIS)
    a = surface_angle.estimate_surface_axis(accel, rests, AxisConfig(0.0, fit="eq23"))
    b = surface_angle.estimate_surface_axis(accel, rests, AxisConfig(0.0, fit="plane"))
    assert a.axis[0] > 0 and np.allclose(a.axis, b.axis, atol=1e-12)


def test_axis_rests_as_masks_equal_rests_as_slices():
    accel, rests = _rests_at([0.0, 70.0, 140.0])
    masks = [np.zeros(accel.shape[0], bool) for _ in rests]
    for m, r in zip(masks, rests):
        m[r] = True
    a = surface_angle.estimate_surface_axis(accel, rests, AxisConfig(0.01))
    b = surface_angle.estimate_surface_axis(accel, masks, AxisConfig(0.01))
    assert np.array_equal(a.axis, b.axis) and a.sigma_rad == b.sigma_rad


@pytest.mark.parametrize("angles,kw,match", [
    ([0.0, 70.0, 140.0], dict(fit="lsq"), "fit must be 'plane' or 'eq23'"),
    ([0.0, 1.0, 2.0], dict(), r"found only 1 distinct tilt\(s\) among 3 rest\(s\).*rotation about the vertical"),
    ([0.0, 90.0], dict(), r"found only 2 distinct tilt\(s\) among 2 rest\(s\)"),
    ([0.0, 8.0, 16.0], dict(accel_noise_m_s2=2.0), "axis too uncertain: .* rotate further between rests"),
    ([0.0, 70.0, 140.0], dict(max_axis_error_deg=-1.0), "max_axis_error_deg must be > 0"),
])
def test_axis_refusals(angles, kw, match):
    accel, rests = _rests_at(angles)
    kw = {"accel_noise_m_s2": 0.001, **kw}
    with pytest.raises(ValueError, match=match):
        surface_angle.estimate_surface_axis(accel, rests, AxisConfig(**kw))


def _noisy_batch(angles_deg, trials=4, n=40, seed=0):
    accel, rests = _rests_at(angles_deg, n=n)
    rng = np.random.default_rng(seed)
    batch = accel + 0.02 * rng.standard_normal((trials,) + accel.shape)
    masks = [np.zeros((trials, accel.shape[0]), bool) for _ in rests]
    for m, r in zip(masks, rests):
        m[:, r] = True
    masks[1][0, rests[1].start:rests[1].start + n // 2] = False  # trial 0: a shorter second rest
    return batch, masks


@pytest.mark.parametrize("angles,kw", [
    ([0.0, 70.0, 140.0], dict(fit="eq23", max_axis_error_deg=None)),           # vectorised path
    ([0.0, 70.0, 140.0, 70.0], dict(fit="eq23", max_axis_error_deg=None)),     # rests to merge: per trial
    ([0.0, 70.0, 140.0, 200.0], dict(fit="eq23", max_axis_error_deg=None)),    # first three of four
    ([0.0, 70.0, 140.0], dict(fit="plane")),                                    # plane fit with a gate
])
def test_batched_axes_equal_the_per_trial_procedure(angles, kw):
    batch, masks = _noisy_batch(angles)
    got = surface_angle.estimate_surface_axes(batch, masks, AxisConfig(0.02, **kw))
    for t in range(batch.shape[0]):
        one = surface_angle.estimate_surface_axis(batch[t], [m[t] for m in masks], AxisConfig(0.02, **kw))
        assert np.array_equal(got[t], one.axis)
    assert np.degrees(np.arccos(np.min(got @ AXIS))) < 2.0


def test_batched_axes_refusals():
    batch, masks = _noisy_batch([0.0, 70.0, 140.0])
    with pytest.raises(ValueError, match="fit must be 'plane' or 'eq23'"):
        surface_angle.estimate_surface_axes(batch, masks, AxisConfig(0.02, fit="lsq"))
    with pytest.raises(ValueError, match="found no rest"):
        surface_angle.estimate_surface_axes(batch, [], AxisConfig(0.02))
    with pytest.raises(ValueError, match="each rest mask must be boolean of shape"):
        surface_angle.estimate_surface_axes(batch, [m[:, :5] for m in masks], AxisConfig(0.02))
    with pytest.raises(ValueError, match="accel_m_s2 must"):
        surface_angle.estimate_surface_axes(batch[0], masks, AxisConfig(0.02))
    # a trial whose rests are one tilt fails as the per-trial procedure does
    same, masks1 = _noisy_batch([0.0, 1.0, 2.0], trials=2)
    with pytest.raises(ValueError, match=r"found only 1 distinct tilt\(s\) among 3 rest\(s\)"):
        surface_angle.estimate_surface_axes(same, masks1, AxisConfig(0.02, fit="eq23", max_axis_error_deg=None))


@pytest.mark.parametrize("fit,match", [
    ("plane", "rotation axis is nearly vertical: .* rotation about it barely changes gravity"),
    ("eq23", "rotation axis is nearly vertical: .* rotation barely changes gravity"),
])
def test_nearly_vertical_axis_refused(fit, match):
    steep = np.array([np.cos(np.radians(87.0)), 0.0, np.sin(np.radians(87.0))])
    accel, rests = _rests_at([0.0, 120.0, 240.0], axis=steep)
    with pytest.raises(ValueError, match=match):
        surface_angle.estimate_surface_axis(accel, rests, AxisConfig(0.0, fit=fit, min_separation_deg=0.5,
                                            max_axis_error_deg=None))


def test_axis_input_refusals():
    accel, rests = _rests_at([0.0, 70.0, 140.0])
    with pytest.raises(ValueError, match="found no rest"):
        surface_angle.estimate_surface_axis(accel, [], AxisConfig(0.01))
    with pytest.raises(ValueError, match="boolean mask of shape"):
        surface_angle.estimate_surface_axis(accel, [np.ones(5, bool)] * 3, AxisConfig(0.01))
    with pytest.raises(ValueError, match="boolean mask of shape"):   # the system's edge checks the masks' dtype
        surface_angle.estimate_surface_axis(accel, [np.ones(accel.shape[0], int)] * 3, AxisConfig(0.01))
    with pytest.raises(ValueError, match="min_separation_deg must be > 0"):   # checked once, when the config is made
        AxisConfig(0.01, min_separation_deg=0.0)
    with pytest.raises(ValueError, match="positions_m_s2 must hold at least 3 positions, got 2"):
        surface_angle.axis_uncertainty(np.array([[0, 0, 9.8], [0, 9.8, 0]]), [10, 10], accel_noise_m_s2=0.01)
    with pytest.raises(ValueError, match="finite"):
        surface_angle.axis_uncertainty(np.full((3, 3), np.nan), [10, 10, 10], accel_noise_m_s2=0.01)


def test_axis_uncertainty_scales_with_noise_over_root_n():
    accel, rests = _rests_at([0.0, 70.0, 140.0])
    pos = np.array([accel[r].mean(axis=0) for r in rests])
    a = surface_angle.axis_uncertainty(pos, [400, 400, 400], accel_noise_m_s2=2.0)
    b = surface_angle.axis_uncertainty(pos, [1600, 1600, 1600], accel_noise_m_s2=2.0)
    assert a.sigma_rad == pytest.approx(2.0 * b.sigma_rad, rel=1e-12)
    c = surface_angle.axis_uncertainty(pos, [400, 400, 400], accel_noise_m_s2=2.0, window_samples=4.0)
    assert c.sigma_rad == pytest.approx(2.0 * a.sigma_rad, rel=1e-12)


# --------------------------------------------------------------------------- angle
def test_angle_of_a_known_rotation():
    prof, w, f = _hinge()
    res = surface_angle.surface_angle(w[0], f[0], AXIS, CONFIG, is_static=prof.is_static, init=slice(0, 90), dt_s=DT_S,
                                      rests=prof.hold_slices())
    for sl, target in zip(prof.hold_slices(), [0.0, 60.0, 120.0, 30.0]):
        np.testing.assert_allclose(np.degrees(res.angle_rad[sl]), target, atol=1e-6)
    assert res.start == 0 and res.restarts == () and not res.clipped.any() and res.clip_level_rad_s == 0.0
    np.testing.assert_allclose(res.accel0_m_s2, G0, atol=1e-12)
    assert res.elevation_rad == pytest.approx(np.arcsin(0.8), abs=1e-12)


def test_angle_from_a_later_rest_is_nan_before_it_and_measured_params():
    rng = np.random.default_rng(3)
    prof, w, f = _hinge()
    w, f = w[0] + rng.normal(0, 1e-3, w[0].shape), f[0] + rng.normal(0, 0.01, f[0].shape)
    hold = prof.hold_slices()[1]
    res = surface_angle.surface_angle(w, f, AXIS, is_static=prof.is_static, init=hold, dt_s=DT_S,
                                      rests=prof.hold_slices())
    assert np.isnan(res.angle_rad[:hold.start]).all() and res.angle_rad[hold.start] == pytest.approx(0, abs=0.01)
    assert np.degrees(res.angle_rad[prof.hold_slices()[2]]).mean() == pytest.approx(60.0, abs=0.2)
    assert res.params.sigma_theta_rad_s == pytest.approx(1e-3, rel=0.2)


def test_batch_equals_each_trial_alone():
    rng = np.random.default_rng(1)
    prof, w, f = _hinge(trials=3)
    w, f = w + rng.normal(0, 1e-3, w.shape), f + rng.normal(0, 0.01, f.shape)
    w[1, 150:170, 2] = np.abs(w[1, :, 2]).max()                               # trial 1 clipped in move 1
    batch = surface_angle.surface_angle(w, f, AXIS, CONFIG, is_static=prof.is_static, init=slice(0, 90), dt_s=DT_S,
                                        rests=prof.hold_slices())
    assert batch.restarts[0] == () and batch.restarts[1] != ()
    for t in range(3):
        one = surface_angle.surface_angle(w[t], f[t], AXIS, CONFIG, is_static=prof.is_static, init=slice(0, 90),
                                          dt_s=DT_S,
                                          rests=prof.hold_slices())
        assert np.array_equal(batch.angle_rad[t], one.angle_rad)


def test_clipped_gyro_restarts_the_ekf_at_the_next_rest():
    """A gyro clipped at 40 deg/s under-reports the 60 deg moves; the restart lets the rest's accelerometer
    set the angle again, the single EKF run keeps most of the gyro's error."""
    prof, w, f = _hinge(rate_deg_s=60.0)
    clip = np.radians(40.0)
    w = np.clip(w[0], -clip, clip)
    res = surface_angle.surface_angle(w, f[0], AXIS, CONFIG, is_static=prof.is_static, init=slice(0, 90), dt_s=DT_S,
                                      rests=prof.hold_slices())
    holds = prof.hold_slices()
    assert res.clipped.any() and res.clip_level_rad_s == pytest.approx(clip)
    assert res.restarts == tuple(h.start for h in holds[1:])
    single = run_rams_ekf(w, f[0], prof.is_static, AXIS, res.accel0_m_s2, DT_S, PARAMS,
                          bias0_rad_s=res.bias0_rad_s).theta_rad[0]
    end = slice(holds[-1].stop - 10, holds[-1].stop)
    assert abs(np.degrees(res.angle_rad[end]).mean() - 30.0) < 0.05
    assert abs(np.degrees(single[end]).mean() - 30.0) > 1.0


def test_jittered_time_base_weights_the_gyro():
    t = np.cumsum(np.r_[0.0, np.full(99, DT_S)])
    t[50:] += 0.3 * DT_S                                                      # one long interval
    dt, weights = plausibility.time_base(100, time_s=t)
    assert dt == pytest.approx((t[-1] - t[0]) / 99, rel=1e-15) and weights[49] == pytest.approx(1.3 * DT_S / dt)
    assert plausibility.time_base(100, dt_s=DT_S) == (DT_S, None)


@pytest.mark.parametrize("kwargs,match", [
    (dict(), "give exactly one of dt_s and time_s"),
    (dict(dt_s=0.01, time_s=np.arange(5.0)), "give exactly one of dt_s and time_s"),
    (dict(time_s=np.arange(4.0)), "time_s must be 5 strictly increasing times"),
    (dict(time_s=np.array([0.0, 1.0, 1.0, 2.0, 3.0])), "time_s must be 5 strictly increasing times"),
    (dict(dt_s=-1.0), "dt_s must be > 0"),
])
def test_time_base_refusals(kwargs, match):
    with pytest.raises(ValueError, match=match):
        plausibility.time_base(5, **kwargs)


def _angle_kwargs(prof):
    return dict(is_static=prof.is_static, init=slice(0, 90), dt_s=DT_S, rests=prof.hold_slices())


@pytest.mark.parametrize("change,match", [
    (lambda w, f, kw: (w[:, :2], f, AXIS, kw), "accel_m_s2 must have the same shape|must have shape|last dim"),
    (lambda w, f, kw: (w, f, 2 * AXIS, kw), r"axis must be a unit vector, got \|axis\| = 2"),
    (lambda w, f, kw: (w, f, AXIS, {**kw, "is_static": kw["is_static"].astype(int)}), "is_static must be boolean"),
    (lambda w, f, kw: (w, f, AXIS, {**kw, "init": slice(5, 5)}), "init must be a non-empty slice"),
    (lambda w, f, kw: (w, f, [0.0, 0.0, 1.0], kw), r"--axis is 0.00 deg from gravity .* non-vertical axis"),
    (lambda w, f, kw: (w * 0.1, f, AXIS, {**kw, "config": SurfaceAngleConfig(PARAMS, check_units=True)}),
     "gyro and accelerometer disagree: .* 10x"),
    (lambda w, f, kw: (w, f, [1.0, 0.0, 0.0], {**kw, "config": SurfaceAngleConfig(PARAMS, max_axis_mismatch_deg=10.0)}),
     r"the gyro turns about \[0.600, -?0.000, 0.800\] \(100 % of the rotation\), 53.1 deg from --axis"),
])
def test_angle_refusals(change, match):
    prof, w, f = _hinge()
    args = change(w[0], f[0], {"config": CONFIG, **_angle_kwargs(prof)})
    with pytest.raises(ValueError, match=match):
        surface_angle.surface_angle(*args[:3], **args[3])


@pytest.mark.parametrize("kw,match", [
    (dict(max_elevation_deg=0.0), "max_elevation_deg must be > 0"),
    (dict(max_axis_mismatch_deg=-1.0), "max_axis_mismatch_deg must be > 0"),
    (dict(gyro_noise_rad_s=-1.0), "gyro_noise_rad_s must be >= 0"),
])
def test_angle_config_refusals(kw, match):
    with pytest.raises(ValueError, match=match):
        SurfaceAngleConfig(**kw)
    with pytest.raises(TypeError, match="params must be a RamsEkfParams or None"):
        SurfaceAngleConfig(params={"sigma": 1.0})


def test_batch_refuses_single_record_options():
    prof, w, f = _hinge(trials=2)
    kw = _angle_kwargs(prof)
    with pytest.raises(ValueError, match="check one record, not a batch"):
        surface_angle.surface_angle(w, f, AXIS, SurfaceAngleConfig(PARAMS, check_units=True), **kw)
    with pytest.raises(ValueError, match="params must be given for a batch"):
        surface_angle.surface_angle(w, f, AXIS, **kw)


def test_gyro_checks_pass_on_a_consistent_record():
    prof, w, f = _hinge()
    res = surface_angle.surface_angle(w[0], f[0], AXIS, SurfaceAngleConfig(PARAMS, check_units=True,
                                                                           max_axis_mismatch_deg=1.0),
                                      **_angle_kwargs(prof))
    assert res.unit_check["pairs"] == 3 and abs(res.gyro_axis @ AXIS) == pytest.approx(1.0, abs=1e-12)


# --------------------------------------------------------------------------- the CLI runs the same system
def _hinge_log(tmp_path, seed: int):
    """A hinge record (rests at 0/60/120/30/90 deg, lever arm) from the study's simulator and its lossless
    Parquet log: (imu, sim, time_s, path)."""
    from mtcal.studies.wang2022sensors import ImuSpec, lever_arm_vector
    from mtcal.studies.wang2022sensors.runs import simulate_batch, trapezoid_profile

    imu = ImuSpec().resolve()
    prof = trapezoid_profile(np.radians([0.0, 60.0, 120.0, 30.0, 90.0]), np.radians(40.0), np.radians(200.0),
                             2.0, imu.dt_s)
    sim = simulate_batch(prof.angle_rad[:, 0], prof.rate_rad_s[:, 0], prof.accel_rad_s2[:, 0], AXIS[None],
                         lever_arm_vector(AXIS, 0.2, 0.02)[None], imu, seed, 0, [0])
    t = np.arange(sim.gyro_rad_s.shape[1]) / imu.fs_hz
    cols = {"time_s": t}
    cols.update({f"gyro_{a}_rad_s": sim.gyro_rad_s[0, :, i] for i, a in enumerate("xyz")})
    cols.update({f"accel_{a}_m_s2": sim.accel_m_s2[0, :, i] for i, a in enumerate("xyz")})
    log = tmp_path / "hinge.parquet"
    pd.DataFrame(cols).to_parquet(log)
    return imu, sim, t, log


def test_cli_axis_and_angle_are_bit_identical_to_the_procedures(tmp_path, capsys):
    """A hinge log from the study's simulator, written losslessly (Parquet); ``mtcal axis`` and ``mtcal angle``
    print/write exactly what the procedures return on the same arrays with the same rests."""
    v = AXIS
    imu, sim, t, log = _hinge_log(tmp_path, 11)
    gyro, accel = sim.gyro_rad_s[0], sim.accel_m_s2[0]

    dt, _ = plausibility.time_base(t.size, time_s=t)
    fs = 1.0 / dt
    # mtcal axis (adaptive rests, accelerometer + gyro, min rest 0.5 s)
    rep = rest_detection.detect_rests(accel, 1.0 / ((t.size - 1) / (t[-1] - t[0])), gyro_rad_s=gyro,
                                      params=rest_detection.RestDetectorParams(min_rest_s=0.5, noise_factor=5.0))
    est = surface_angle.estimate_surface_axis(accel, rep.rests, AxisConfig(rep.accel_noise_m_s2,
                                              window_samples=rep.window_s * (t.size - 1) / (t[-1] - t[0])))
    assert main(["axis", str(log)]) == 0
    out = capsys.readouterr().out
    assert re.search(r"^axis v = (.*)$", out, re.M).group(1) == f"{est.axis[0]:.6f},{est.axis[1]:.6f},{est.axis[2]:.6f}"
    assert np.degrees(np.arccos(est.axis @ v)) < 0.5
    # mtcal angle (adaptive rests, min rest 0.2 s, a0 and bias from the first 1 s of the first rest)
    axis_text = ",".join(repr(float(x)) for x in est.axis)
    angle_out = tmp_path / "angle.parquet"
    assert main(["angle", str(log), "--axis", axis_text, "--out", str(angle_out)]) == 0
    rep = rest_detection.detect_rests(accel, 1.0 / ((t.size - 1) / (t[-1] - t[0])), gyro_rad_s=gyro,
                                      params=rest_detection.RestDetectorParams(min_rest_s=0.2, noise_factor=5.0))
    first = rep.rests[0]
    n0 = min(int(round(1.0 * fs)), first.stop - first.start)
    axis_parsed = np.array([float(x) for x in axis_text.split(",")])
    res = surface_angle.surface_angle(gyro, accel, axis_parsed / np.linalg.norm(axis_parsed), is_static=rep.is_static,
                                      init=slice(first.start, first.start + n0), time_s=t, rests=rep.rests)
    table = pd.read_parquet(angle_out)
    assert list(table.columns) == ["time_s", "angle_deg", "is_static"]
    assert np.array_equal(table.time_s.to_numpy(), t)
    assert np.array_equal(table.angle_deg.to_numpy(), np.degrees(res.angle_rad), equal_nan=True)
    assert np.array_equal(table.is_static.to_numpy(bool), rep.is_static)
    assert abs(table.angle_deg.iloc[-1] - 90.0) < 0.5


def test_cli_angle_is_bit_identical_to_the_study_procedure(tmp_path):
    """``mtcal angle --rest-detector paper`` on a log of the study's simulator equals the study's batched
    procedure (:func:`~mtcal.studies.wang2022sensors.runs.paper_procedure`: Table 1 ZVD, EKF switched by
    it, a0 and bias from the first second) bit for bit, with the CLI's settings: the given axis and the EKF
    noise measured on the initial rest."""
    from mtcal.methods.zero_velocity import ZvdParams
    from mtcal.studies.wang2022sensors.runs import paper_procedure

    imu, sim, t, log = _hinge_log(tmp_path, 12)
    gyro, accel = sim.gyro_rad_s[0], sim.accel_m_s2[0]
    out = tmp_path / "angle.parquet"
    assert main(["angle", str(log), "--axis", ",".join(repr(float(x)) for x in AXIS), "--out", str(out),
                 "--rest-detector", "paper"]) == 0
    table = pd.read_parquet(out)

    dt, weights = plausibility.time_base(t.size, time_s=t)
    assert weights is None                                                   # a uniform time column
    n0 = int(round(1.0 / dt))                                                # --init-s 1.0
    rests = rest_detection.paper_rest_report(accel, dt, min_rest_s=0.2).rests
    proc = replace(paper_procedure(imu, ZvdParams()), axis=None,
                   angle=SurfaceAngleConfig.paper(surface_angle.rest_ekf_params(gyro, accel, slice(0, n0))))
    study = surface_angle.surface_angle_batch(sim.gyro_rad_s, sim.accel_m_s2, dt, proc, init_samples=n0,
                                              rests=rests, axis=AXIS)
    assert np.array_equal(table.is_static.to_numpy(bool), study.is_static[0])
    assert np.array_equal(table.angle_deg.to_numpy(), np.degrees(study.angle_rad[0]))
    assert abs(table.angle_deg.iloc[-1] - 90.0) < 0.5


def test_batched_procedure_refusals():
    prof, w, f = _hinge(trials=2)
    cfg = surface_angle.SurfaceBatchConfig(None, AxisConfig(0.01, fit="eq23", max_axis_error_deg=None), CONFIG)
    kw = dict(init_samples=90, rests=prof.hold_slices(), known_static=prof.is_static)
    with pytest.raises(ValueError, match="init_samples must be an integer in"):
        surface_angle.surface_angle_batch(w, f, DT_S, cfg, **{**kw, "init_samples": 0})
    with pytest.raises(ValueError, match="known_static must be given"):
        surface_angle.surface_angle_batch(w, f, DT_S, cfg, **{**kw, "known_static": None})
    with pytest.raises(ValueError, match="rests must be non-empty slices"):
        surface_angle.surface_angle_batch(w, f, DT_S, cfg, **{**kw, "rests": [slice(5, 5)]})
    with pytest.raises(ValueError, match="the axis needs 3 rests, got 2"):
        surface_angle.surface_angle_batch(w, f, DT_S, cfg, **{**kw, "rests": prof.hold_slices()[:2]})
    with pytest.raises(ValueError, match="give axis, or config.axis"):
        surface_angle.surface_angle_batch(w, f, DT_S, replace(cfg, axis=None), **kw)
    with pytest.raises(ValueError, match="accel_m_s2 must"):
        surface_angle.surface_angle_batch(w, f[0], DT_S, cfg, **kw)
    from mtcal.methods.zero_velocity import ZvdParams

    zvd = replace(cfg, zvd=ZvdParams())   # the ZVD's checks (mtcal.methods.zero_velocity.detect_static), here once
    with pytest.raises(ValueError, match="in g"):
        surface_angle.surface_angle_batch(w, f / 9.80665, DT_S, zvd, **kw)
    with pytest.raises(ValueError, match="accel_m_s2 must be finite"):
        surface_angle.surface_angle_batch(w, np.where(np.arange(f.shape[1])[:, None] == 3, np.nan, f), DT_S, zvd, **kw)
    with pytest.raises(ValueError, match="dt_s must be the sample interval"):
        surface_angle.surface_angle_batch(w, f, 100.0, zvd, **kw)
    with pytest.raises(ValueError, match="angle.params must be given for a batch"):
        surface_angle.SurfaceBatchConfig(None, None, SurfaceAngleConfig())
    with pytest.raises(ValueError, match="ekf_switch must be 'zvd' or 'known'"):
        surface_angle.SurfaceBatchConfig(None, None, CONFIG, ekf_switch="truth")
    with pytest.raises(ValueError, match="axis_rests must be an integer >= 3"):
        surface_angle.SurfaceBatchConfig(None, None, CONFIG, axis_rests=2)


def test_batched_procedure_equals_its_steps():
    """ZVD flags, Eq 23 axes on the masked rests and the EKF: the batched procedure is the per-step systems."""
    from mtcal.methods.zero_velocity import ZvdParams, detect_static

    rng = np.random.default_rng(3)
    prof, w, f = _hinge(angles_deg=(0.0, 90.0, 180.0, 40.0), trials=3)
    w, f = w + rng.normal(0, 1e-3, w.shape), f + rng.normal(0, 0.01, f.shape)
    axis_cfg = AxisConfig(0.01, fit="eq23", min_separation_deg=0.5, max_axis_error_deg=None)
    cfg = surface_angle.SurfaceBatchConfig(ZvdParams(), axis_cfg, CONFIG)
    res = surface_angle.surface_angle_batch(w, f, DT_S, cfg, init_samples=90, rests=prof.hold_slices())
    flags = detect_static(f, DT_S, ZvdParams())
    assert np.array_equal(res.is_static, flags)
    axes = surface_angle.estimate_surface_axes(f, surface_angle.rest_masks(flags, prof.hold_slices()[:3]), axis_cfg)
    assert np.array_equal(res.axis, axes)
    one = surface_angle.surface_angle(w, f, axes, CONFIG, is_static=flags, init=slice(0, 90), dt_s=DT_S,
                                      rests=prof.hold_slices())
    assert np.array_equal(res.angle_rad, one.angle_rad)
    assert np.array_equal(res.accel0_m_s2, one.accel0_m_s2) and np.array_equal(res.bias0_rad_s, one.bias0_rad_s)
    assert np.max(np.abs(np.degrees(res.angle_rad[:, -1]) - 40.0)) < 0.5


def test_sweep_cell_config_is_the_registry_entry():
    """The sweep cell's config (:meth:`SurfaceAngleConfig.sweep_cell`) runs the filter registry's ``rams_ekf``
    entry bit for bit."""
    from mtcal.filters.registry import AxisContext, get_filter

    rng = np.random.default_rng(4)
    prof, w, f = _hinge(trials=2)
    w, f = w + rng.normal(0, 1e-3, w.shape), f + rng.normal(0, 0.01, f.shape)
    static = np.broadcast_to(prof.is_static, f.shape[:2])
    ctx = AxisContext(AXIS, static, f[:, :90].mean(axis=1), 2e-4, 3e-3, init=slice(0, 90),
                      rests=tuple(prof.hold_slices()))
    entry = get_filter("rams_ekf")
    got = entry.run(w, f, DT_S, 2.0, ctx)
    cfg = SurfaceAngleConfig.sweep_cell(gyro_noise_rad_s_rt_hz=2e-4, accel_noise_m_s2_rt_hz=3e-3, dt_s=DT_S,
                                        gain_m_s2=2.0)
    res = surface_angle.surface_angle(w, f, AXIS, cfg, is_static=static, init=slice(0, 90), dt_s=DT_S,
                                      rests=prof.hold_slices())
    assert np.array_equal(got, res.angle_rad)
    batch = surface_angle.SurfaceBatchConfig.sweep_cell(gyro_noise_rad_s_rt_hz=2e-4, accel_noise_m_s2_rt_hz=3e-3,
                                                        dt_s=DT_S, gain_m_s2=2.0)
    assert batch.zvd is None and batch.axis is None and batch.angle == cfg
    study = surface_angle.surface_angle_batch(w, f, DT_S, batch, init_samples=90, rests=prof.hold_slices(),
                                              axis=AXIS, known_static=prof.is_static)
    assert np.array_equal(got, study.angle_rad)            # the entry is the study's batched procedure
    with pytest.raises(ValueError, match="the rams_ekf entry initialises from a rest at sample 0"):
        entry.run(w, f, DT_S, 2.0, replace(ctx, init=slice(5, 90)))


def test_cli_defaults_are_the_configs_cli_defaults():
    """``mtcal axis`` / ``mtcal angle`` option defaults equal those of :meth:`AxisConfig.cli`,
    :meth:`AxisRecordConfig.cli` and :meth:`SurfaceAngleConfig.cli` (one set of CLI defaults)."""
    import inspect

    from mtcal.cli.main import build_parser

    axis_args = build_parser().parse_args(["axis", "log.csv"])
    angle_args = build_parser().parse_args(["angle", "log.csv", "--axis", "1,0,0"])
    for cfg, args in ((AxisConfig.cli, axis_args), (surface_angle.AxisRecordConfig.cli, axis_args),
                      (SurfaceAngleConfig.cli, angle_args)):
        for name, par in inspect.signature(cfg).parameters.items():
            if par.kind is par.KEYWORD_ONLY and hasattr(args, name) and par.default is not None:
                assert float(getattr(args, name)) == par.default, name
    assert float(axis_args.max_elevation_deg) == AxisConfig.cli(0.0, 1.0).max_elevation_deg
    assert float(angle_args.max_axis_mismatch_deg) == SurfaceAngleConfig.cli().max_axis_mismatch_deg


def _fs_of(t):
    return (t.size - 1) / (t[-1] - t[0])


def test_record_procedure_is_the_rests_then_the_checked_ekf(tmp_path):
    """``surface_angle_record`` (``mtcal angle``'s one system call) equals its steps bit for bit: the rests,
    the first ``init_s`` of the first rest, :func:`surface_angle` with the command's checks, Eq 16 per rest."""
    from mtcal.systems.rests import RestsConfig, find_rests

    _, sim, t, _ = _hinge_log(tmp_path, 13)
    gyro, accel = sim.gyro_rad_s[0], sim.accel_m_s2[0]
    fs = _fs_of(t)
    config = surface_angle.SurfaceRecordConfig(RestsConfig.cli_defaults(0.2))
    found = surface_angle.surface_angle_record(gyro, accel, AXIS, config, fs_hz=fs, time_s=t)
    rep = find_rests(accel, 1.0 / fs, config.rests, gyro_rad_s=gyro, time_s=t)
    first = rep.rests[0]
    n0 = min(int(round(config.init_s * fs)), first.stop - first.start)
    res = surface_angle.surface_angle(gyro, accel, AXIS, SurfaceAngleConfig.cli(gyro_noise_rad_s=rep.gyro_noise_rad_s),
                                      is_static=rep.is_static, init=slice(first.start, first.start + n0), time_s=t,
                                      rests=rep.rests)
    assert found.rests.rests == rep.rests and not found.late
    assert np.array_equal(found.angle.angle_rad, res.angle_rad, equal_nan=True)
    assert found.angle.unit_check == res.unit_check
    means = np.array([accel[r].mean(axis=0) for r in rep.rests])
    assert np.array_equal(found.rest_accel_angles_rad, surface_angle.angles_about_axis(AXIS, res.accel0_m_s2, means))
    # a log that starts moving: measured from the first rest, angle NaN before it
    k = int(2.5 * fs)
    late = surface_angle.surface_angle_record(gyro[k:], accel[k:], AXIS, config, fs_hz=fs, time_s=t[k:])
    assert late.late and np.isnan(late.angle.angle_rad[0]) and late.angle.start == late.rests.rests[0].start


def test_record_procedure_refusals(tmp_path):
    from mtcal.systems.rests import RestsConfig

    _, sim, t, _ = _hinge_log(tmp_path, 14)
    gyro, accel = sim.gyro_rad_s[0], sim.accel_m_s2[0]
    fs = _fs_of(t)
    paper = surface_angle.SurfaceRecordConfig(RestsConfig.paper(0.2))
    with pytest.raises(ValueError, match="--init-s 1000 s must cover at least one sample and leave data"):
        surface_angle.surface_angle_record(gyro, accel, AXIS, replace(paper, init_s=1000.0), fs_hz=fs, time_s=t)
    with pytest.raises(ValueError, match="from gravity") as exc:
        surface_angle.surface_angle_record(gyro, accel, [0.0, 0.0, 1.0], paper, fs_hz=fs, time_s=t)
    assert len(exc.value.rests.rests) >= 3               # the refusal carries the rests it saw
    tt = np.arange(2000) / 100.0                         # |a| swinging 9.81 +- 3 m/s^2: never at rest
    s = np.sin(2 * np.pi * 0.7 * tt)
    moving, turning = np.c_[2 * s, 2 * np.cos(2 * np.pi * 0.7 * tt), 9.81 + 3 * s], np.c_[0.5 + 0.3 * s, 0.2 * s, s]
    with pytest.raises(ValueError, match="no rest found: the angle is measured from a rest"):
        surface_angle.surface_angle_record(turning, moving, AXIS, surface_angle.SurfaceRecordConfig(RestsConfig()),
                                           fs_hz=100.0, time_s=tt)
    with pytest.raises(ValueError, match=r"no rest found: .* quiet stretch\(es\) rejected, the first [0-9.]+-[0-9.]+ s: "):
        surface_angle.surface_angle_record(turning, moving, AXIS, surface_angle.SurfaceRecordConfig(
            RestsConfig(min_rest_s=1.0)), fs_hz=100.0, time_s=tt)   # the reason a quiet stretch is no rest
    with pytest.raises(ValueError, match="are not at rest by the paper ZVD") as exc:
        surface_angle.surface_angle_record(turning, moving, AXIS, paper, fs_hz=100.0, time_s=tt)
    assert exc.value.rests.method == "paper"
    with pytest.raises(TypeError, match="config must be a SurfaceRecordConfig"):
        surface_angle.surface_angle_record(gyro, accel, AXIS, SurfaceAngleConfig(), fs_hz=fs, time_s=t)
    with pytest.raises(TypeError, match="rests must be a RestsConfig"):
        surface_angle.SurfaceRecordConfig("adaptive")
    with pytest.raises(ValueError, match="max_axis_mismatch_deg must be"):
        surface_angle.SurfaceRecordConfig(RestsConfig(), max_axis_mismatch_deg=-1.0)


# --------------------------------------------------------------------------- the axis of one record (mtcal axis)
def test_cli_axis_is_bit_identical_to_the_study_procedure(tmp_path, capsys):
    """``mtcal axis --rest-detector paper`` with the paper's 1 s rests and the study's separation on a log of the
    study's simulator prints the axis of the study's batched procedure (:func:`~mtcal.studies.wang2022sensors.runs.
    paper_procedure` without the EKF: Table 1 ZVD flags masked by the schedule's rests, Eq 23), and the system it
    calls (:func:`~mtcal.systems.surface_angle.surface_axis_record`: ZVD, Algorithm A1) returns it bit for bit."""
    from mtcal.methods.rotation_axis import DEFAULT_MAX_ELEVATION_DEG, DEFAULT_MIN_SEPARATION_DEG
    from mtcal.methods.zero_velocity import ZvdParams
    from mtcal.studies.wang2022sensors.runs import paper_procedure, trapezoid_profile
    from mtcal.systems.rests import RestsConfig

    for seed in (11, 13):
        imu, sim, t, log = _hinge_log(tmp_path, seed)
        prof = trapezoid_profile(np.radians([0.0, 60.0, 120.0, 30.0, 90.0]), np.radians(40.0), np.radians(200.0),
                                 2.0, imu.dt_s)
        rests = prof.hold_slices()
        proc = replace(paper_procedure(imu, ZvdParams()), angle=None)
        study = surface_angle.surface_angle_batch(sim.gyro_rad_s, sim.accel_m_s2, imu.dt_s, proc,
                                                  init_samples=rests[0].stop, rests=rests).axis[0]
        assert main(["axis", str(log), "--rest-detector", "paper", "--min-rest-s", "1",
                     "--min-separation-deg", f"{DEFAULT_MIN_SEPARATION_DEG:g}"]) == 0
        out = capsys.readouterr().out
        assert re.search(r"^axis v = (.*)$", out, re.M).group(1) == f"{study[0]:.6f},{study[1]:.6f},{study[2]:.6f}"
        config = surface_angle.AxisRecordConfig.cli(RestsConfig(detector="paper", min_rest_s=1.0, use_gyro=False),
                                                    min_separation_deg=DEFAULT_MIN_SEPARATION_DEG,
                                                    max_elevation_deg=DEFAULT_MAX_ELEVATION_DEG)
        found = surface_angle.surface_axis_record(sim.accel_m_s2[0], config, fs_hz=imu.fs_hz, time_s=t)
        np.testing.assert_array_equal(found.axis.axis, study)
        assert [r.start // 10 for r in found.used] == [r.start // 10 for r in rests[:3]]   # the schedule's rests
        with pytest.raises(ValueError, match="axis too uncertain") as info:       # the gate names A1's rests
            surface_angle.surface_axis_record(sim.accel_m_s2[0], replace(config, max_axis_error_deg=1e-6),
                                              fs_hz=imu.fs_hz, time_s=t)
        assert info.value.used == found.used and info.value.rests.method == "paper"


def test_axis_record_adaptive_equals_its_steps():
    """Adaptive rests → units check → the gated plane (AxisConfig.cli with the measured noise): the system's steps."""
    from mtcal.systems.rests import RestsConfig, find_rests

    prof, w, f = _hinge((0.0, 60.0, 120.0, 30.0))
    rng = np.random.default_rng(5)
    gyro, accel = w[0] + 1e-3 * rng.standard_normal(w[0].shape), f[0] + 1e-2 * rng.standard_normal(f[0].shape)
    rests = RestsConfig.cli_defaults(0.5)
    found = surface_angle.surface_axis_record(accel, surface_angle.AxisRecordConfig.cli(rests), fs_hz=FS_HZ,
                                              time_s=prof.time_s, gyro_rad_s=gyro, unit_stated="header")
    rep = find_rests(accel, DT_S, rests, gyro_rad_s=gyro, time_s=prof.time_s)
    est = surface_angle.estimate_surface_axis(accel, rep.rests, AxisConfig.cli(rep.accel_noise_m_s2,
                                                                               rep.window_s * FS_HZ))
    assert found.rests.rests == rep.rests and found.units_check["pairs"] >= 2
    np.testing.assert_array_equal(found.axis.axis, est.axis)
    assert found.axis.sigma_rad == est.sigma_rad and len(found.used) == est.positions_m_s2.shape[0] == 4
    accel_only = surface_angle.surface_axis_record(accel, surface_angle.AxisRecordConfig.cli(
        RestsConfig(min_rest_s=0.5, use_gyro=False)), fs_hz=FS_HZ, time_s=prof.time_s)
    assert accel_only.units_check is None


def test_axis_record_refusals_carry_what_they_saw():
    from mtcal.systems.rests import RestsConfig

    prof, w, f = _hinge((0.0, 60.0))
    config = surface_angle.AxisRecordConfig.cli(RestsConfig(min_rest_s=0.5, use_gyro=False))
    with pytest.raises(TypeError, match="config must be an AxisRecordConfig, got RestsConfig"):
        surface_angle.surface_axis_record(f[0], RestsConfig(), fs_hz=FS_HZ, time_s=prof.time_s)
    with pytest.raises(TypeError, match="rests must be a RestsConfig, got dict"):
        surface_angle.AxisRecordConfig({})
    with pytest.raises(ValueError, match="max_axis_error_deg must be > 0"):
        surface_angle.AxisRecordConfig(RestsConfig(), max_axis_error_deg=0.0)
    with pytest.raises(ValueError, match="fs_hz must be > 0"):
        surface_angle.surface_axis_record(f[0], config, fs_hz=0.0, time_s=prof.time_s)
    with pytest.raises(ValueError, match="time_s must have"):
        surface_angle.surface_axis_record(f[0], config, fs_hz=FS_HZ, time_s=prof.time_s[:-1])
    with pytest.raises(ValueError, match=r"found only 2 distinct tilt\(s\) among 2 rest\(s\)") as info:
        surface_angle.surface_axis_record(f[0], config, fs_hz=FS_HZ, time_s=prof.time_s)
    assert len(info.value.rests.rests) == 2 and info.value.units_check is None
    with pytest.raises(ValueError, match=r"found only 0 rests of >= 0.5 s") as info:
        surface_angle.surface_axis_record(f[0][:40], config, fs_hz=FS_HZ, time_s=prof.time_s[:40])
    assert info.value.rests.rests == []
    paper = surface_angle.AxisRecordConfig.cli(RestsConfig(detector="paper", min_rest_s=0.5, use_gyro=False))
    with pytest.raises(ValueError, match=r"found only \d distinct rest\(s\).*\[paper ZVD band 9.76-9.84") as info:
        surface_angle.surface_axis_record(f[0], paper, fs_hz=FS_HZ, time_s=prof.time_s)
    assert info.value.rests.method == "paper"


def test_angle_record_reports_the_rest_mismatch():
    """The EKF's median angle per rest beside the accelerometer's on the same turn; a wrong axis shows as a mismatch."""
    from mtcal.systems.rests import RestsConfig

    prof, w, f = _hinge((0.0, 60.0, 120.0, 30.0), hold_s=1.5)
    rng = np.random.default_rng(2)
    gyro, accel = w[0] + 1e-3 * rng.standard_normal(w[0].shape), f[0] + 1e-2 * rng.standard_normal(f[0].shape)
    config = surface_angle.SurfaceRecordConfig(RestsConfig.cli_defaults(), max_axis_mismatch_deg=None)
    good = surface_angle.surface_angle_record(gyro, accel, AXIS, config, fs_hz=FS_HZ, time_s=prof.time_s)
    np.testing.assert_allclose(np.degrees(good.rest_ekf_angles_rad), [0, 60, 120, 30], atol=0.3)
    np.testing.assert_allclose(good.rest_accel_angles_rad, good.rest_ekf_angles_rad, atol=np.radians(0.3))
    assert good.rest_mismatch is None
    tilted = axis_angle_matrix(np.radians(8.0), [0.0, 1.0, 0.0]) @ AXIS
    bad = surface_angle.surface_angle_record(gyro, accel, tilted, config, fs_hz=FS_HZ, time_s=prof.time_s)
    i, off = bad.rest_mismatch
    assert np.degrees(off) > surface_angle.MAX_REST_ANGLE_MISMATCH_DEG
    assert off == np.nanmax(np.abs(bad.rest_ekf_angles_rad - bad.rest_accel_angles_rad))
