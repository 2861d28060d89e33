"""Tests for mtcal.filters.qncf (wang2023cja QNCF, Eq 5–8 + PI/AMD)."""

import numpy as np
import pytest

from mtcal.core import profiles, rotations, simulate
from mtcal.filters.qncf import QncfFilter, QncfParams, amd_statistic, initial_attitude_from_accel, qncf, qncf_trusted

FS = 1000.0


def _record(rng=None, model=None, trials=None):
    wp = np.radians([[0, 0, 0], [8, 0, 0], [0, 20, 0], [0, 0, 60]])
    prof = profiles.step_schedule(wp, np.radians(20), 1.0, FS)
    traj = profiles.trajectory_from_euler_zxy(prof)
    return simulate.simulate_imu(traj, model, rng=rng, trials=trials)


def test_zero_noise_tracks_truth():
    rec = _record()
    res = qncf(rec.gyro_rad_s, rec.accel_m_s2, 1 / FS)
    err = rotations.quat_angle_between(res.q_ws, rec.q_ws_true)
    assert err.max() < 1e-9
    assert np.allclose(res.euler_rad, rotations.euler_zxy_from_quat(rec.q_ws_true), atol=1e-9)
    assert res.gate.all()


def test_tilted_start_is_levelled_and_corrected():
    q_mount = rotations.quat_from_euler_zxy(0.0, np.radians(2.0), np.radians(-3.0))
    rec = _record(model=simulate.ImuErrorModel(q_mount=tuple(q_mount)))
    # start from a wrong attitude: the PI loop pulls pitch/roll back to gravity
    res = qncf(rec.gyro_rad_s, rec.accel_m_s2, 1 / FS, q0=[1.0, 0, 0, 0])
    e = rotations.euler_zxy_from_quat(res.q_ws) - rotations.euler_zxy_from_quat(rec.q_ws_true)
    assert abs(e[0, 1]) > np.radians(1.5)            # initially wrong by ~2 deg in pitch
    assert np.abs(e[3000:3500, 1:]).max() < np.radians(0.3)  # e^-3 after 3 s (Kp = 1/s)


def test_batch_equals_per_step(rng):
    model = simulate.ImuErrorModel(gyro=simulate.SensorErrors(noise_density=1e-4),
                                   accel=simulate.SensorErrors(noise_density=1e-3))
    rec = _record(rng, model, trials=3)
    g, a = rec.gyro_rad_s[:, :400], rec.accel_m_s2[:, :400]
    q0 = np.tile([1.0, 0, 0, 0], (3, 1))
    batch = qncf(g, a, 1 / FS, q0=q0)
    filt = QncfFilter(q0, 1 / FS)
    steps = [filt.update(g[:, k], a[:, k]) for k in range(g.shape[1])]
    assert np.allclose(np.stack(steps, axis=1)[:, :-1], batch.q_ws[:, 1:], atol=1e-14, rtol=0)
    # chunked run continues the state exactly
    f2 = QncfFilter(q0, 1 / FS)
    r1 = f2.run(g[:, :150], a[:, :150])
    r2 = f2.run(g[:, 150:], a[:, 150:], chunk=64)
    assert np.array_equal(np.concatenate([r1.q_ws, r2.q_ws], axis=1), batch.q_ws)


def test_trusted_entry_is_qncf_bit_for_bit(rng):
    """The trusted entry (stacked records or one record, default or given q0) returns qncf's numbers."""
    model = simulate.ImuErrorModel(gyro=simulate.SensorErrors(noise_density=1e-4),
                                   accel=simulate.SensorErrors(noise_density=1e-3))
    rec = _record(rng, model, trials=3)
    p = QncfParams(kp_rad_s=2.0)
    for g, a in ((rec.gyro_rad_s, rec.accel_m_s2), (rec.gyro_rad_s[1], rec.accel_m_s2[1])):
        for q0 in (None, rotations.quat_from_euler_zxy(0.1, 0.02, -0.03)):
            ref = qncf(g, a, 1 / FS, p, q0=q0, init_samples=50)
            got = qncf_trusted(g, a, 1 / FS, p, q0=q0, init_samples=50)
            for name in ("q_ws", "euler_rad", "amd_pct", "gate"):
                assert np.array_equal(getattr(got, name), getattr(ref, name)), name
    # no tilt-rate scan (deg/s passed as rad/s is not refused by it), but the kernel's value scan stays
    bad = rec.gyro_rad_s.copy()
    bad[0, 5, 0] = np.nan
    with pytest.raises(ValueError, match="gyro_rad_s must be finite"):
        qncf_trusted(bad, rec.accel_m_s2, 1 / FS)
    with pytest.raises(ValueError, match="accel_m_s2 looks like it is in g"):
        qncf_trusted(rec.gyro_rad_s, rec.accel_m_s2 / 9.80665, 1 / FS)


def test_does_not_mutate_inputs():
    rec = _record()
    g, a = rec.gyro_rad_s.copy(), rec.accel_m_s2.copy()
    qncf(g, a, 1 / FS)
    assert np.array_equal(g, rec.gyro_rad_s) and np.array_equal(a, rec.accel_m_s2)


def test_amd_gate_switches_off_accelerometer_under_vibration():
    t = np.arange(0, 4.0, 1 / FS)
    accel = np.tile([0.0, 0.0, 9.80665], (t.size, 1))
    vib = (t > 2.0)[:, None] * 3.0 * np.sin(2 * np.pi * 45 * t)[:, None] * np.array([1.0, 0.5, 1.0])
    accel_v = accel + vib
    gyro = np.zeros_like(accel)
    res = qncf(gyro, accel_v, 1 / FS, QncfParams(ki_rad_s2=0.0), q0=rotations.quat_from_euler_zxy(0.0, 0.01, 0.0))
    assert res.gate[: int(1.9 * FS)].all()
    assert not res.gate[int(2.5 * FS):].any()
    # gyro-only after the gate closes: attitude frozen (gyro zero, no integral term)
    assert np.allclose(res.q_ws[int(2.5 * FS)], res.q_ws[-1], atol=1e-12)
    amd = amd_statistic(accel_v, 1 / FS)
    assert np.allclose(amd, res.amd_pct)
    assert amd[int(3 * FS):].min() > 0.3 > amd[: int(1.9 * FS)].max()


def test_initial_attitude_from_accel_round_trip():
    q = rotations.quat_from_euler_zxy(0.0, 0.3, -1.2)
    f = rotations.quat_to_matrix(q).T @ np.array([0, 0, 9.81])
    assert np.allclose(initial_attitude_from_accel(f), q, atol=1e-12)


@pytest.mark.parametrize("bad, msg", [
    (np.full((10, 3), np.nan), "finite"),
    (np.zeros((10, 2)), "shape"),
])
def test_bad_inputs(bad, msg):
    with pytest.raises(ValueError, match=msg):
        qncf(bad, np.zeros((10, 3)) + 9.8, 1e-3)


def test_record_and_dt_checked_at_the_edge_before_the_tilt_rate_scan():
    """qncf checks a record and dt_s once at its edge (moved from the trusting tilt_rate_scale, same messages)."""
    gyro, accel = np.zeros((3000, 3)), np.tile([0.0, 0.0, 9.81], (3000, 1))
    with pytest.raises(ValueError, match=r"gyro_rad_s must have last dimension 3"):
        qncf(gyro[:, :2], accel, 0.01)
    with pytest.raises(ValueError, match="must have the same shape"):
        qncf(gyro[:-1], accel, 0.01)
    with pytest.raises(TypeError, match="accel_m_s2 must be a numeric array"):
        qncf(gyro, "accel", 0.01)
    for dt in (0.0, -0.01):  # before the scan: no ZeroDivisionError, no misleading units refusal
        with pytest.raises(ValueError, match="dt_s must be > 0"):
            qncf(gyro, accel, dt)


def test_bad_params():
    with pytest.raises(ValueError, match="amd_threshold_pct"):
        QncfParams(amd_threshold_pct=0.0)
    with pytest.raises(ValueError, match="dt_s"):
        QncfFilter([1.0, 0, 0, 0], -1.0)


# --------------------------------------------------------------------------- regression of the fast step
def _regression_input():
    """Deterministic 3-trial record: smooth rates + noise, trial 1 vibrates after 0.3 s (gate closes)."""
    rng = np.random.default_rng(2024)
    n, dt = 600, 1e-3
    t = np.arange(n) * dt
    rate = np.stack([0.8 * np.sin(2 * np.pi * 1.5 * t), 0.5 * np.cos(2 * np.pi * 0.7 * t), 0.3 * np.ones(n)], -1)
    gyro = rate[None] * np.array([1.0, -0.5, 2.0])[:, None, None] + 1e-3 * rng.standard_normal((3, n, 3))
    accel = np.array([0.3, -0.2, 9.78]) + 2e-2 * rng.standard_normal((3, n, 3))
    accel[1] += (t > 0.3)[:, None] * 2.0 * np.sin(2 * np.pi * 40 * t)[:, None]
    q0 = rotations.quat_from_euler_zxy(np.array([0.1, -0.2, 0.0]), np.array([0.02, 0.0, -0.03]),
                                       np.array([0.0, 0.01, 0.02]))
    return gyro, accel, q0, dt


def _readable_qncf(gyro, accel, q0, dt, p: QncfParams):
    """Straightforward QNCF (module docstring items 1–4), one formula per line, trig increment."""
    trials, n, _ = gyro.shape
    q, integral = q0.copy(), np.zeros((trials, 3))
    amd = None
    alpha = min(dt / p.amd_tau_s, 1.0)
    q_out, amd_out, gate_out = np.empty((trials, n, 4)), np.empty((trials, n)), np.empty((trials, n), bool)
    for k in range(n):
        q_out[:, k] = q
        a = accel[:, k]
        norm = np.linalg.norm(a, axis=-1)
        d = 100.0 * np.abs(norm / p.gravity_m_s2 - 1.0)
        amd = d.copy() if amd is None else amd
        amd = amd + alpha * (d - amd)
        gate = amd < p.amd_threshold_pct
        q0_, q1, q2, q3 = q.T
        v = np.stack([2 * (q1 * q3 - q0_ * q2), 2 * (q2 * q3 + q0_ * q1), q0_**2 - q1**2 - q2**2 + q3**2], -1)
        e = np.cross(a / np.maximum(norm, 1e-12)[:, None], v) * gate[:, None]
        integral = integral + p.ki_rad_s2 * e * dt
        dtheta = (gyro[:, k] + p.kp_rad_s * e + integral) * dt
        ang = np.linalg.norm(dtheta, axis=-1)
        scale = np.where(ang > 0, np.sin(ang / 2) / np.where(ang > 0, ang, 1.0), 0.5)
        qh = np.concatenate([np.cos(ang / 2)[:, None], dtheta * scale[:, None]], axis=-1)
        q = rotations.quat_multiply(q, qh)
        q = q / np.linalg.norm(q, axis=-1, keepdims=True)
        amd_out[:, k], gate_out[:, k] = amd, gate
    return q_out, amd_out, gate_out


# increment series of order 2 (|Δθ| ≤ 0.004 rad), order 3 (≤ 0.04 rad) and cos/sin (|Δθ| up to 0.16 rad)
# (the cos/sin case uses a 16x longer sample interval, not an implausible > 40 rad/s rate)
@pytest.mark.parametrize("rate_scale, dt_scale, order", [(1.0, 1, 2), (5.0, 1, 3), (5.0, 16, 0)])
def test_fast_step_equals_readable_implementation(rate_scale, dt_scale, order):
    gyro, accel, q0, dt = _regression_input()
    gyro, dt = gyro * rate_scale, dt * dt_scale
    p = QncfParams(ki_rad_s2=0.5)
    q_ref, amd_ref, gate_ref = _readable_qncf(gyro, accel, q0, dt, p)
    filt = QncfFilter(q0, dt, p)
    assert filt._increment_order(np.ascontiguousarray(gyro[:, :256].transpose(1, 2, 0))) == order
    res = filt.run(gyro, accel, return_euler=False, chunk=256)
    assert gate_ref.any() and not gate_ref.all()
    assert np.array_equal(res.gate, gate_ref)
    np.testing.assert_allclose(res.amd_pct, amd_ref, rtol=1e-13, atol=0)
    np.testing.assert_allclose(res.q_ws, q_ref, rtol=0, atol=2e-14)


def test_fast_step_regression_literals():
    """Values computed with the pre-optimisation step (commit 1bea4b9, trig increment)."""
    gyro, accel, q0, dt = _regression_input()
    res = QncfFilter(q0, dt, QncfParams(ki_rad_s2=0.5)).run(gyro, accel, return_euler=False)
    q_end = [[0.9900473619551211, -0.01206758949115207, -0.0082558346916493, 0.1399729815468782],
             [0.9894951035263192, -0.00149679664970309, -0.01182071922778717, -0.14407453034511736],
             [0.9838753609384874, -0.02808212896250793, -0.01063298365773614, 0.17631678260911177]]
    q_mid = [[0.9917447440791285, 0.07436975821285578, 0.04552251360566446, 0.09401703255159359],
             [0.991462050498936, -0.04093926154413429, -0.01950321293723718, -0.12225630441736382],
             [0.9830614547045957, 0.13164067380391953, 0.09809440364557412, 0.08147636005586792]]
    np.testing.assert_allclose(res.q_ws[:, -1], q_end, rtol=0, atol=1e-14)
    np.testing.assert_allclose(res.q_ws[:, 299], q_mid, rtol=0, atol=1e-14)
    assert res.gate.sum(axis=1).tolist() == [600, 301, 556]
    np.testing.assert_allclose(res.amd_pct[:, -1], [0.2314957353794017, 12.568706166958945,
                                                    0.21977667923042524], rtol=1e-14, atol=0)
