"""Gravity-referenced gyro scale (mtcal.methods.tilt_rate) and the filters' edge check that uses it."""

import warnings

import numpy as np
import pytest

from mtcal.methods import tilt_rate

DT = 0.01


def _tilting(n=3000, amp_rad_s=0.6, seed=0):
    rng = np.random.default_rng(seed)
    t = np.arange(n) * DT
    rate = amp_rad_s * np.sin(2 * np.pi * 0.25 * t) * (t > 2)
    angle = np.cumsum(rate) * DT
    accel = 9.81 * np.column_stack([np.zeros(n), np.sin(angle), np.cos(angle)]) + rng.normal(0, 0.01, (n, 3))
    gyro = np.column_stack([rate, np.zeros(n), np.zeros(n)]) + rng.normal(0, 0.002, (n, 3)) + 0.01
    return gyro, accel


@pytest.mark.parametrize("factor, dt_factor, expect", [(1.0, 1.0, 1.0), (180 / np.pi, 1.0, np.pi / 180),
                                                       (1.0, 10.0, 0.1), (1.0, 0.1, 10.0)])
def test_scale_found(factor, dt_factor, expect):
    gyro, accel = _tilting()
    res = tilt_rate.tilt_rate_scale(gyro * factor, accel, DT * dt_factor)
    assert res["scale"] == pytest.approx(expect, rel=0.15)
    assert res["correlation"] > 0.9


def test_check_refuses_deg_s_and_time_scale_and_names_the_fix():
    gyro, accel = _tilting()
    assert tilt_rate.check_tilt_rate_scale(gyro, accel, DT)["decided"]
    with pytest.raises(ValueError, match="--gyro-unit deg/s"):
        tilt_rate.check_tilt_rate_scale(np.degrees(gyro), accel, DT)
    with pytest.raises(ValueError, match="time column 10x too slow"):
        tilt_rate.check_tilt_rate_scale(gyro, accel, DT * 10)


def test_check_undecided_without_tilt():
    rng = np.random.default_rng(1)
    accel = np.tile([0.0, 0.0, 9.81], (2000, 1)) + rng.normal(0, 0.01, (2000, 3))
    gyro = np.zeros((2000, 3))
    gyro[500:1500, 2] = 1.0  # about gravity: invisible to the accelerometer
    assert not tilt_rate.check_tilt_rate_scale(gyro, accel, DT)["decided"]


def test_excess_tilt_warns_when_asked():
    rng = np.random.default_rng(2)
    accel = np.tile([0.0, 0.0, 9.81], (3000, 1)) + rng.normal(0, 0.01, (3000, 3))
    gyro = np.zeros((3000, 3))
    gyro[1000:2000, 0] = 0.5 * np.sin(np.linspace(0, 4 * np.pi, 1000))  # the gyro tilts, the accel does not
    with pytest.warns(UserWarning, match="gyro implausible for rad/s"):
        tilt_rate.check_tilt_rate_scale(gyro, accel, DT, excess="warn")
    with pytest.raises(ValueError, match="gyro implausible for rad/s"):
        tilt_rate.check_tilt_rate_scale(gyro, accel, DT)


def test_skip_drops_windows():
    gyro, accel = _tilting()
    skip = np.ones(len(gyro), bool)
    assert tilt_rate.tilt_rate_scale(gyro, accel, DT, skip=skip)["windows"] == 0
    skip[: len(gyro) // 2] = False
    half = tilt_rate.tilt_rate_scale(gyro, accel, DT, skip=skip)["windows"]
    assert 0 < half < tilt_rate.tilt_rate_scale(gyro, accel, DT)["windows"]


def test_filters_refuse_deg_s_gyro_at_their_public_edge():
    from mtcal.filters.qncf import qncf
    from mtcal.filters.rams_ekf import RamsEkfParams, run_rams_ekf

    gyro, accel = _tilting()
    with warnings.catch_warnings():
        warnings.simplefilter("error", UserWarning)
        qncf(gyro, accel, DT)  # rad/s: accepted
    with pytest.raises(ValueError, match="--gyro-unit deg/s"):
        qncf(np.degrees(gyro), accel, DT)
    static = np.zeros(len(gyro), bool)
    with pytest.raises(ValueError, match="gyro implausible for rad/s"):
        run_rams_ekf(np.degrees(gyro), accel, static, [1.0, 0.0, 0.0], accel[0], DT, RamsEkfParams())


@pytest.mark.parametrize("measured, decided", [
    # a 1-hour rad/s hinge log (benchmarks/cli_case.py): long rests dilute the correlation, the scale is exact
    (dict(scale=0.997, correlation=0.47, windows=3000, accel_tilt_rad=np.radians(543.5),
          gyro_tilt_rad=np.radians(193.8), accel_spread_rad=np.radians(33.5)), True),
    # a time column 10x too slow: a weak correlation on 1.6 deg of tilt must not count as agreement
    (dict(scale=1.19, correlation=0.32, windows=40, accel_tilt_rad=np.radians(1.6),
          gyro_tilt_rad=np.radians(0.4), accel_spread_rad=np.radians(67.8)), False),
])
def test_long_record_agreement_needs_tilt_in_both_sensors(monkeypatch, measured, decided):
    monkeypatch.setattr(tilt_rate, "tilt_rate_scale", lambda *a, **k: dict(measured))
    res = tilt_rate.check_tilt_rate_scale(np.zeros((10, 3)), np.tile([0.0, 0.0, 9.81], (10, 1)), 0.01)
    assert res["decided"] is decided


@pytest.mark.parametrize("m", [3, 5, 42, 43, 50, 200, 1001, 20_000])
def test_window_pass_is_bit_identical_to_the_numpy_expressions(m):
    from mtcal.methods._tilt_rate_kernels import window_stats

    rng = np.random.default_rng(m)
    n = 4 * m + 7
    a = rng.normal(9.8, 3.0, (n, 3))
    w = rng.normal(0.0, 1.0, (n, 3))
    skip = rng.random(n) < 0.01
    nb = n // m
    blocks = a[: nb * m].reshape(nb, m, 3)
    am = blocks.mean(axis=1)
    a_std = np.sqrt(((blocks - am[:, None, :]) ** 2).mean(axis=(1, 2)))  # numpy's pairwise sum over 3m values
    wm = w[: nb * m].reshape(nb, m, 3).mean(axis=1)
    got_am, got_std, got_wm, got_skip, w_ok, a_ok = window_stats(w, a, m, skip, True)
    assert np.array_equal(got_am, am) and np.array_equal(got_std, a_std) and np.array_equal(got_wm, wm)
    assert np.array_equal(got_skip, skip[: nb * m].reshape(nb, m).any(axis=1)) and w_ok and a_ok


@pytest.mark.parametrize("where", ["window", "tail"])
def test_non_finite_values_are_refused_at_the_edge(where):
    gyro, accel = _tilting()
    row = 10 if where == "window" else len(gyro) - 1  # the tail after the last window is checked too
    bad = gyro.copy()
    bad[row, 1] = np.nan
    with pytest.raises(ValueError, match="gyro_rad_s must be finite"):
        tilt_rate.tilt_rate_scale(bad, accel, DT)
    bad = accel.copy()
    bad[row, 2] = -np.inf
    with pytest.raises(ValueError, match="accel_m_s2 must be finite"):
        tilt_rate.check_tilt_rate_scale(gyro, bad, DT)


def test_shapes_and_scalars_are_checked_at_the_edge():
    gyro, accel = _tilting()
    with pytest.raises(ValueError, match=r"gyro_rad_s must have shape \(N, 3\)"):
        tilt_rate.tilt_rate_scale(gyro[:, :2], accel, DT)
    with pytest.raises(ValueError, match="must have the same shape"):
        tilt_rate.tilt_rate_scale(gyro[:-1], accel, DT)
    with pytest.raises(TypeError, match="accel_m_s2 must be a numeric array"):
        tilt_rate.tilt_rate_scale(gyro, "accel", DT)
    with pytest.raises(ValueError, match="dt_s must be > 0"):
        tilt_rate.tilt_rate_scale(gyro, accel, 0.0)
    with pytest.raises(ValueError, match="window_s must be > 0"):
        tilt_rate.tilt_rate_scale(gyro, accel, DT, window_s=-1.0)
    with pytest.raises(ValueError, match="skip must be a boolean array of 3000 samples"):
        tilt_rate.tilt_rate_scale(gyro, accel, DT, skip=np.zeros(10, bool))
    short = tilt_rate.tilt_rate_scale(gyro[:12], accel[:12], DT)  # fewer than 3 windows: nothing to decide
    assert short["windows"] == 0 and np.isnan(short["scale"])


def test_trusted_filter_entries_match_the_public_ones_bit_for_bit():
    from mtcal.filters.qncf import qncf, qncf_trusted
    from mtcal.filters.rams_ekf import RamsEkfParams, run_rams_ekf, run_rams_ekf_trusted

    gyro, accel = _tilting()
    pub, trusted = qncf(gyro, accel, DT), qncf_trusted(gyro, accel, DT)
    assert np.array_equal(pub.q_ws, trusted.q_ws) and np.array_equal(pub.euler_rad, trusted.euler_rad)
    static = np.zeros(len(gyro), bool)
    static[:200] = True
    args = (gyro, accel, static, [1.0, 0.0, 0.0], accel[:200].mean(axis=0), DT, RamsEkfParams())
    assert np.array_equal(run_rams_ekf(*args).theta_rad, run_rams_ekf_trusted(*args).theta_rad)
    with pytest.raises(ValueError, match="gyro_rad_s must be in rad/s"):  # the kernel's scan still runs
        qncf_trusted(np.full_like(gyro, 90.0), accel, DT)
