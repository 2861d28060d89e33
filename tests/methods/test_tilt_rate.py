"""Gravity-referenced gyro scale (mtcal.methods.tilt_rate) and the filters' edge check that uses it."""

import warnings

import numpy as np
import pytest

from mtcal.methods import tilt_rate
from tests.code_paths import run_on_the_other_code_path

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


def test_deg_s_gyro_refused_at_the_public_edge():
    """qncf checks at its edge; the RAMS EKF trusts its inputs and the surface-angle system checks for it."""
    from mtcal.filters.qncf import qncf
    from mtcal.filters.rams_ekf import RamsEkfParams
    from mtcal.systems.surface_angle import SurfaceAngleConfig, surface_angle

    gyro, accel = _tilting()
    with warnings.catch_warnings():
        warnings.simplefilter("error", UserWarning)
        qncf(gyro, accel, DT)  # rad/s: accepted
    with pytest.raises(ValueError, match="--gyro-unit deg/s"):
        qncf(np.degrees(gyro), accel, DT)
    static = np.zeros(len(gyro), bool)
    with pytest.raises(ValueError, match="gyro implausible for rad/s"):
        surface_angle(np.degrees(gyro), accel, [1.0, 0.0, 0.0], SurfaceAngleConfig(RamsEkfParams()),
                      is_static=static, init=slice(0, 100), dt_s=DT)


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


def test_fewer_than_three_windows_decide_nothing():
    gyro, accel = _tilting()
    short = tilt_rate.tilt_rate_scale(gyro[:12], accel[:12], DT)
    assert short["windows"] == 0 and np.isnan(short["scale"])


def test_trusted_filter_entries_match_the_public_ones_bit_for_bit():
    from mtcal.filters.qncf import qncf, qncf_trusted

    gyro, accel = _tilting()
    pub, trusted = qncf(gyro, accel, DT), qncf_trusted(gyro, accel, DT)
    assert np.array_equal(pub.q_ws, trusted.q_ws) and np.array_equal(pub.euler_rad, trusted.euler_rad)
    with pytest.raises(ValueError, match="gyro_rad_s must be in rad/s"):  # the kernel's scan still runs
        qncf_trusted(np.full_like(gyro, 90.0), accel, DT)


def _numpy_glue(gyro, accel, dt_s, window_s=0.05, band_fraction=0.05, skip=None):
    """The numpy code the compiled ``window_fit`` replaces (kept verbatim as the reference)."""
    from mtcal.methods._tilt_rate_kernels import window_stats

    w, a = np.ascontiguousarray(gyro, float), np.ascontiguousarray(accel, float)
    n = a.shape[0]
    m = max(3, int(round(window_s / dt_s)))
    skip_arr = np.ascontiguousarray(skip, np.bool_) if skip is not None else np.zeros(0, np.bool_)
    am, a_std, wm, skipped, _, _ = window_stats(w, a, min(m, n + 1), skip_arr, skip is not None)
    nb = am.shape[0]
    nan = {"scale": float("nan"), "correlation": float("nan"), "accel_tilt_rad": 0.0, "gyro_tilt_rad": 0.0,
           "windows": 0, "accel_spread_rad": 0.0}
    if nb < 3:
        return nan
    norm = np.linalg.norm(am, axis=1)
    g = float(np.median(norm))
    if not g > 0:
        return nan
    ok = (np.abs(norm - g) < band_fraction * g) & (a_std < band_fraction * g) & ~skipped
    ah = am / np.maximum(norm, 1e-12)[:, None]
    u = np.cross(ah[:-1], ah[1:])
    du = np.linalg.norm(u, axis=1)
    pair = ok[:-1] & ok[1:]
    if np.count_nonzero(pair) < 2:
        return nan
    still = pair & (du <= np.percentile(du[pair], 25))
    b = np.median(0.5 * (wm[:-1] + wm[1:])[still], axis=0)
    ab = 0.5 * (ah[:-1] + ah[1:])
    ab /= np.maximum(np.linalg.norm(ab, axis=1), 1e-12)[:, None]
    wr = 0.5 * (wm[:-1] + wm[1:]) - b
    wperp = wr - np.einsum("ij,ij->i", wr, ab)[:, None] * ab
    p = -wperp * (m * dt_s)
    ref = ah[ok].mean(axis=0)
    ref /= max(float(np.linalg.norm(ref)), 1e-12)
    spread = float(np.percentile(np.arccos(np.clip(ah[ok] @ ref, -1.0, 1.0)), 99))
    nan["accel_spread_rad"] = spread
    dp = np.linalg.norm(p, axis=1)
    moving = (du > 3.0 * np.median(du[still])) | (dp > 3.0 * np.median(dp[still]))
    use = pair & moving
    if np.count_nonzero(use) < 2:
        return nan
    u, p = u[use], p[use]
    up, pp, uu = float(np.sum(u * p)), float(np.sum(p * p)), float(np.sum(u * u))
    return {"scale": up / pp if pp > 0 else float("nan"),
            "correlation": float(up / np.sqrt(pp * uu)) if pp > 0 and uu > 0 else float("nan"),
            "accel_tilt_rad": float(np.linalg.norm(u, axis=1).sum()),
            "gyro_tilt_rad": float(np.linalg.norm(p, axis=1).sum()), "windows": int(u.shape[0]),
            "accel_spread_rad": spread}


def _records():
    """Realistic and adversarial records: (gyro, accel, dt_s, kwargs) — rests, tilts, 3-axis rotations, linear
    acceleration, skip masks, deg/s and time-base errors, tiny records, zero and constant accelerometers."""
    rng = np.random.default_rng(24)
    out = []
    for seed in range(12):
        g, a = _tilting(n=int(rng.integers(200, 4000)), amp_rad_s=float(rng.uniform(0.05, 2.0)), seed=seed)
        out.append((g, a, DT, {}))
        out.append((np.degrees(g), a, DT, {"skip": rng.random(len(g)) < 0.02}))
        out.append((g, a, DT * float(rng.choice([0.1, 10.0, 0.3])), {"band_fraction": float(rng.uniform(0.01, 0.2))}))
    for seed in range(10):  # rotation about a random axis with rests and linear acceleration bursts
        r = np.random.default_rng(100 + seed)
        n, dt = int(r.integers(500, 6000)), float(r.choice([1e-3, 5e-3, 0.01]))
        t = np.arange(n) * dt
        axis = r.normal(size=3)
        axis /= np.linalg.norm(axis)
        rate = r.uniform(0.1, 3.0) * np.sin(2 * np.pi * r.uniform(0.1, 2.0) * t) * (r.random(n) > 0.001)
        rate[: n // 4] = 0.0  # a rest
        ang = np.cumsum(rate) * dt
        g0 = np.array([0.0, 0.0, 9.81])
        acc = np.empty((n, 3))
        for i in range(n):  # Rodrigues rotation of gravity into the sensor frame
            c, s = np.cos(ang[i]), np.sin(ang[i])
            acc[i] = g0 * c - np.cross(axis, g0) * s + axis * (axis @ g0) * (1 - c)
        burst = r.random(n) < 0.02
        acc += r.normal(0, r.uniform(0.001, 0.1), (n, 3)) + burst[:, None] * r.normal(0, 5.0, (n, 3))
        gyro = rate[:, None] * axis + r.normal(0, 0.003, (n, 3)) + r.normal(0, 0.02, 3)
        out.append((gyro, acc, dt, {"skip": r.random(n) < r.uniform(0, 0.05), "window_s": float(r.uniform(0.01, 0.2))}))
    for n in (5, 8, 9, 10, 12, 15, 20, 31):  # tiny records: fewer than 3 windows, or just enough
        out.append((rng.normal(0, 1, (n, 3)), rng.normal(0, 1, (n, 3)) + [0, 0, 9.81], 0.01, {"window_s": 0.03}))
    z = np.zeros((300, 3))
    out.append((z, z, 0.01, {}))  # zero accelerometer: median norm 0
    out.append((z, np.tile([0.0, 0.0, 9.81], (300, 1)), 0.01, {}))  # still and noiseless: no moving pair
    out.append((rng.normal(0, 1, (900, 3)), rng.normal(0, 20, (900, 3)), 0.01, {}))  # no gravity band
    from mtcal.core import profiles
    from mtcal.core.simulate import simulate_imu
    from mtcal.studies.wang2023cja import ImuSpec

    for seed, (fs_hz, dur_s) in enumerate([(1000.0, 20.0), (200.0, 30.0), (100.0, 8.0)]):  # the bench pitch steps
        wp = np.radians([0.0, 30.0, -20.0, 45.0, 10.0, 0.0])
        prof = profiles.step_schedule(wp, float(np.abs(np.diff(wp)).sum()) / (0.3 * dur_s), 0.7 * dur_s / 6, fs_hz)
        rec = simulate_imu(profiles.fixed_axis_trajectory(prof, (1.0, 0.0, 0.0)),
                           ImuSpec().error_model((1.0, 0.0, 0.0, 0.0)), np.random.default_rng(2023 + seed))
        out.append((rec.gyro_rad_s, rec.accel_m_s2, 1.0 / fs_hz, {}))
        out.append((rec.gyro_rad_s, rec.accel_m_s2, 1.0 / fs_hz, {"skip": np.abs(rec.gyro_rad_s).max(axis=1) > 0.3}))
    step = np.tile([0.0, 0.0, 9.81], (300, 1))
    step[150:] = [0.0, 9.81 * np.sin(0.1), 9.81 * np.cos(0.1)]  # one tilt step: a spread but a single moving pair
    out.append((z, step, 0.01, {}))
    return out


def _same(got, want):
    assert got.keys() == want.keys()
    for key, value in want.items():
        assert type(got[key]) is type(value), key
        assert got[key] == value or (np.isnan(value) and np.isnan(got[key])), (key, got[key], value)


def _check_against_numpy():
    """Every record of :func:`_records`: the compiled glue returns exactly the numpy code's dict."""
    from mtcal.methods._tilt_rate_kernels import percentile_linear

    statuses = set()
    for gyro, accel, dt_s, kw in _records():
        want = _numpy_glue(gyro, accel, dt_s, **kw)
        _same(tilt_rate.tilt_rate_scale(gyro, accel, dt_s, **kw), want)
        statuses.add((want["windows"] > 0, want["accel_spread_rad"] > 0))
    assert statuses == {(False, False), (False, True), (True, True)}  # all three exits are exercised
    rng = np.random.default_rng(7)
    for n in (1, 2, 3, 4, 5, 8, 101, 1000, 1201):
        x = rng.normal(size=n)
        x[rng.random(n) < 0.3] = 0.5  # ties
        for q in (0, 25, 50, 99, 100, 33.3):
            assert percentile_linear(x, q / 100) == np.percentile(x, q)
    for _ in range(300):  # gamma exactly 0.5 (n = 3, 7 at the 25th percentile): numpy interpolates from b
        x = rng.normal(size=int(rng.choice([3, 7]))) * 10.0 ** rng.integers(-3, 4)
        assert percentile_linear(x, 0.25) == np.percentile(x, 25)


def test_compiled_glue_returns_exactly_the_numpy_result():
    _check_against_numpy()


def test_compiled_glue_matches_numpy_on_the_other_code_path():
    """The same check in a fresh process on the other numba/numpy code path (generic <-> native)."""
    code = "from tests.methods import test_tilt_rate as t; t._check_against_numpy(); print('same bits')"
    res = run_on_the_other_code_path(code)
    assert res.returncode == 0 and res.stdout.strip() == "same bits", res.stderr[-2000:]


def test_one_function_per_step_no_trusted_twins():
    """The scan and its judgement trust their inputs (documented preconditions); qncf and the systems check."""
    assert not [n for n, f in vars(tilt_rate).items()
                if n.endswith("_trusted") and getattr(f, "__module__", "") == tilt_rate.__name__]
    assert "_judge" not in vars(tilt_rate) and "_record" not in vars(tilt_rate)
    for name in ("tilt_rate_scale", "check_tilt_rate_scale"):
        assert "Preconditions" in getattr(tilt_rate, name).__doc__, name
