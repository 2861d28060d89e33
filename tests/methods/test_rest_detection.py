"""Adaptive rest detection: levels measured from the data, overrides, reasons, the paper's ZVD beside it."""

import numpy as np
import pytest

from mtcal.methods import rest_detection
from mtcal.methods.zero_velocity import detect_static
from tests.code_paths import run_on_the_other_code_path

FS = 200.0


def _record(rng, *, g=9.80665 * 1.03, bias_deg_s=(3.0, -2.0, 1.0), turn_z_deg_s=0.0):
    """rest 0-2 s, tilt move 2-3 s, rest 3-5 s, (optional slow turn about z 5-6 s), rest to 8 s."""
    t = np.arange(int(8 * FS)) / FS
    gyro = rng.normal(0, 0.003, (t.size, 3)) + np.radians(bias_deg_s)
    accel = rng.normal(0, 0.01, (t.size, 3)) + [0.0, 0.0, g]
    move = (t >= 2) & (t < 3)
    gyro[move, 0] += np.radians(60.0) * np.sin(np.pi * (t[move] - 2)) ** 2
    tilt = np.radians(30.0) * np.clip(t - 2.0, 0, 1)
    accel[:, 1] += g * np.sin(tilt)
    accel[:, 2] -= g * (1 - np.cos(tilt))
    turn = (t >= 5) & (t < 6)
    gyro[turn, 2] += np.radians(turn_z_deg_s)
    return t, gyro, accel


def test_finds_rests_where_the_paper_band_does_not(rng):
    t, gyro, accel = _record(rng)
    rep = rest_detection.detect_rests(accel, 1.0 / FS, gyro_rad_s=gyro)
    assert len(rep.rests) == 2
    assert abs(rep.gravity_m_s2 - 9.80665 * 1.03) < 0.01
    np.testing.assert_allclose(np.degrees(rep.gyro_bias_rad_s), [3.0, -2.0, 1.0], atol=0.05)
    assert 0.005 < rep.accel_noise_m_s2 < 0.02 and np.degrees(rep.gyro_noise_rad_s) < 0.5
    r0, r1 = rep.rests
    assert t[r0.start] == 0.0 and 1.8 < t[r0.stop - 1] < 2.0 and 3.0 < t[r1.start] < 3.2
    assert not detect_static(accel, 1.0 / FS).any()  # 9.76-9.84 excludes a sensor reading 10.10
    paper = rest_detection.paper_rest_report(accel, 1.0 / FS, gyro_rad_s=gyro)
    assert paper.rests == [] and abs(paper.extra["measured_gravity_m_s2"] - rep.gravity_m_s2) < 1e-9


def test_slow_turn_about_vertical_rejected_with_reason(rng):
    t, gyro, accel = _record(rng, turn_z_deg_s=20.0)
    rep = rest_detection.detect_rests(accel, 1.0 / FS, gyro_rad_s=gyro)
    assert len(rep.rests) == 3
    assert any("turning" in r.reason for r in rep.rejected)
    assert not rep.is_static[(t > 5.1) & (t < 5.9)].any()
    only_accel = rest_detection.detect_rests(accel, 1.0 / FS)  # without the gyro the turn is invisible
    assert only_accel.is_static[(t > 5.1) & (t < 5.9)].all()


def test_overrides(rng):
    t, gyro, accel = _record(rng)
    params = rest_detection.RestDetectorParams(gravity_m_s2=9.80665, accel_band_m_s2=0.05)
    rep = rest_detection.detect_rests(accel, 1.0 / FS, gyro_rad_s=gyro, params=params)
    assert rep.band_m_s2 == pytest.approx((9.75665, 9.85665)) and rep.rests == []
    assert rep.rejected and all("outside band" in r.reason for r in rep.rejected)
    rep = rest_detection.detect_rests(accel, 1.0 / FS, gyro_rad_s=gyro,
                                      params=rest_detection.RestDetectorParams(gyro_level_max_rad_s=np.radians(0.001)))
    assert rep.rests == [] and rep.gyro_level_max_rad_s == pytest.approx(np.radians(0.001))
    params = rest_detection.RestDetectorParams(min_rest_s=2.5)
    rep = rest_detection.detect_rests(accel, 1.0 / FS, gyro_rad_s=gyro, params=params)
    assert len(rep.rests) == 1 and "too short" in rep.rejected[0].reason


def test_levels_text_reports_measured_values(rng):
    t, gyro, accel = _record(rng)
    txt = rest_detection.detect_rests(accel, 1.0 / FS, gyro_rad_s=gyro).levels_text()
    assert "|a| at rest 10.10" in txt and "gyro bias [+3.00, -2.00, +" in txt


def test_paper_report_keeps_the_paper_flags(rng):
    t, gyro, accel = _record(rng, g=9.80665)
    rep = rest_detection.paper_rest_report(accel, 1.0 / FS, min_rest_s=0.5)
    assert np.array_equal(rep.is_static, detect_static(accel, 1.0 / FS))
    assert rep.band_m_s2 == (9.76, 9.84) and rep.method == "paper"
    assert all(r.stop - r.start >= 0.5 * FS for r in rep.rests)


def test_centred_moving_mean_matches_direct_sum(rng):
    x = rng.normal(size=(57, 2))
    for w in (1, 2, 5, 8, 57, 80):
        got = rest_detection.centred_moving_mean(x, w)
        ref = np.array([x[max(i - w // 2, 0):min(i - w // 2 + w, 57)].mean(axis=0) for i in range(57)])
        np.testing.assert_allclose(got, ref, atol=1e-12)


def test_quantised_constant_rest_uses_noise_floor():
    tilt = np.radians(np.r_[np.zeros(1000), np.linspace(0, 20, 100), np.full(900, 20.0)])
    accel = 9.9 * np.column_stack([np.sin(tilt), np.zeros(2000), np.cos(tilt)])
    rep = rest_detection.detect_rests(accel, 1.0 / FS, gyro_rad_s=np.zeros((2000, 3)))
    assert rep.accel_noise_m_s2 == rest_detection.ACCEL_NOISE_FLOOR_M_S2 and len(rep.rests) == 2


def test_bad_params_and_short_records():
    with pytest.raises(ValueError, match="quiet_fraction must be in"):
        rest_detection.RestDetectorParams(quiet_fraction=0.8)
    with pytest.raises(ValueError, match="gravity_m_s2 must be in m/s"):
        rest_detection.RestDetectorParams(gravity_m_s2=1.0)
    with pytest.raises(ValueError, match="noise_factor must be > 0"):
        rest_detection.RestDetectorParams(noise_factor=0.0)
    with pytest.raises(ValueError, match="record too short"):
        rest_detection.detect_rests(np.tile([0, 0, 9.8], (30, 1)), 1.0 / FS)


def test_noisier_rests_after_a_still_stand_are_rests(rng):
    """Stances 10x noisier than a long still stand: far quieter than the swings, so still rests."""
    fs = 400.0
    seg = [("stand", 8.0)] + [("swing", 0.5), ("stance", 0.5)] * 8
    acc, gyr, truth = [], [], []
    for kind, dur in seg:
        n = int(dur * fs)
        tt = np.arange(n) / fs
        a = np.tile([0.0, 0.0, 10.07], (n, 1))
        g = np.tile(np.radians([2.5, -3.0, 0.8]), (n, 1))
        if kind == "swing":
            a[:, 0] += 15 * np.sin(2 * np.pi * tt / dur)
            g[:, 1] += np.radians(300) * np.sin(np.pi * tt / dur)
        sa, sg = (0.01, np.radians(0.1)) if kind == "stand" else (0.1, np.radians(1.0))
        acc.append(a + rng.normal(0, sa, (n, 3)))
        gyr.append(g + rng.normal(0, sg, (n, 3)))
        truth.append(kind != "swing")
    rep = rest_detection.detect_rests(np.vstack(acc), 1.0 / fs, gyro_rad_s=np.vstack(gyr))
    assert len(rep.rests) == 1 + 8
    assert rep.accel_std_max_m_s2 > 0.15 > 5 * rep.accel_noise_m_s2  # relaxed towards the motion level


# -- SHOE / GLRT detector (Skog et al. 2010) -----------------------------------------------------------------

def test_shoe_statistic_is_about_six_when_still(rng):
    n = 20000
    accel = rng.normal(0, 0.02, (n, 3)) + [0.0, 0.0, 9.9]
    gyro = rng.normal(0, 0.004, (n, 3)) + 0.01
    stat = rest_detection.shoe_statistic(accel, gyro, 50, gravity_m_s2=9.9, accel_noise_m_s2=0.02,
                                         gyro_noise_rad_s=0.004, gyro_bias_rad_s=0.01)
    assert 5.0 < float(np.median(stat[100:-100])) < 6.5
    turning = gyro + [0.0, 0.1, 0.0]  # 0.1 rad/s = 25 sigma: T rises by (0.1 / 0.004)^2
    stat2 = rest_detection.shoe_statistic(accel, turning, 50, gravity_m_s2=9.9, accel_noise_m_s2=0.02,
                                          gyro_noise_rad_s=0.004, gyro_bias_rad_s=0.01)
    assert abs(float(np.median(stat2[100:-100])) - float(np.median(stat[100:-100])) - 625.0) < 30.0


def test_shoe_matches_the_direct_sum(rng):
    accel = rng.normal(0, 0.5, (40, 3)) + [0.0, 0.0, 9.8]
    gyro = rng.normal(0, 0.2, (40, 3))
    stat = rest_detection.shoe_statistic(accel, gyro, 5, gravity_m_s2=9.8, accel_noise_m_s2=0.3, gyro_noise_rad_s=0.1)
    k = 20
    ya, yw = accel[k - 2:k + 3], gyro[k - 2:k + 3]
    m = ya.mean(axis=0)
    direct = np.mean(np.sum((ya - 9.8 * m / np.linalg.norm(m)) ** 2, axis=1) / 0.3 ** 2
                     + np.sum(yw ** 2, axis=1) / 0.1 ** 2)
    assert stat[k] == pytest.approx(direct, rel=1e-9)


def _walk():
    from tests.cli import logs

    df, stances, swings = logs.walking_log()
    t = df["time_s"].to_numpy()
    gyro = df[[f"gyro_{a}_rad_s" for a in "xyz"]].to_numpy()
    accel = df[[f"accel_{a}_m_s2" for a in "xyz"]].to_numpy()
    return t, gyro, accel, stances, swings


def _hits(t, rests, spans, margin):
    return [any(t[r.start] < b - margin and t[r.stop - 1] > a + margin for r in rests) for a, b in spans]


def test_shoe_walking_stances_found_swings_not_flagged():
    t, gyro, accel, stances, swings = _walk()
    params = rest_detection.ShoeParams(rate_level_rad_s=np.radians(30.0), min_rest_s=0.15)
    rep = rest_detection.detect_rests_shoe(accel, 1 / 1200.0, gyro_rad_s=gyro, params=params)
    assert all(_hits(t, rep.rests, stances, 0.05)), [(t[r.start], t[r.stop - 1]) for r in rep.rests]
    assert not any(_hits(t, rep.rests, swings, 0.02))
    assert rep.extra["threshold"] == pytest.approx(6.0 + (np.radians(30.0) / rep.gyro_noise_rad_s) ** 2)
    default = rest_detection.detect_rests_shoe(accel, 1 / 1200.0, gyro_rad_s=gyro)
    adaptive = rest_detection.detect_rests(accel, 1 / 1200.0, gyro_rad_s=gyro)
    assert not any(_hits(t, default.rests, swings, 0.02))
    assert sum(_hits(t, default.rests, stances, 0.05)) >= sum(_hits(t, adaptive.rests, stances, 0.05))


def test_shoe_threshold_override_and_rejections():
    t, gyro, accel, _, _ = _walk()
    params = rest_detection.ShoeParams(threshold=50.0)
    rep = rest_detection.detect_rests_shoe(accel, 1 / 1200.0, gyro_rad_s=gyro, params=params)
    assert rep.extra["threshold"] == 50.0 and rep.extra["threshold_source"] == "given"
    assert np.all(rep.extra["statistic"][rep.is_static] < 50.0)
    for rej in rep.rejected:
        assert rej.reason.startswith("too short: ") and "< gamma 50.0" in rej.reason


@pytest.mark.parametrize("kw, match", [(dict(window_s=0.0), "window_s"), (dict(threshold=-1.0), "threshold"),
                                       (dict(rate_level_rad_s=0.0), "rate_level_rad_s"),
                                       (dict(min_rest_s=-1.0), "min_rest_s")])
def test_shoe_params_validated(kw, match):
    with pytest.raises(ValueError, match=match):
        rest_detection.ShoeParams(**kw)


def test_adaptive_rejection_reasons_hold_for_their_numbers(rng):
    import re

    t, gyro, accel = _record(rng, turn_z_deg_s=4.0)
    params = rest_detection.RestDetectorParams(min_rest_s=1.5)
    rep = rest_detection.detect_rests(accel, 1.0 / FS, gyro_rad_s=gyro, params=params)
    assert rep.rejected
    for rej in rep.rejected:
        pairs = re.findall(r"([-\d.]+) (?:s |m/s\^2 |deg/s )?([<>]) ([-\d.]+)", rej.reason)
        assert pairs, rej.reason
        for a, op, b in pairs:
            assert (float(a) < float(b)) if op == "<" else (float(a) > float(b)), rej.reason
    assert np.all(rep.extra["decision_statistic"][rep.is_static] < 1.0)


# -- compiled block sums: bit for bit the numpy expressions they replace ------------------------------------

def _numpy_block_levels(accel, norm, gyro, w, quiet_fraction):
    """The numpy code of ``_block_levels`` before the compiled sums (reference)."""
    nb = accel.shape[0] // w

    def block_stats(x):
        b = x[: nb * w].reshape(nb, w, -1)
        first = b[:, :1].copy()
        b = b - first
        m1 = b.sum(axis=1) / w
        b *= b
        var = np.maximum(b.sum(axis=1) / w - m1 * m1, 0.0)
        return np.sqrt(var.mean(axis=1)), m1 + first[:, 0]

    a_std, _ = block_stats(accel)
    a_norm = norm[: nb * w].reshape(nb, w).mean(axis=1)
    score = np.argsort(np.argsort(a_std)).astype(float)
    if gyro is not None:
        g_std, g_mean = block_stats(gyro)
        score += np.argsort(np.argsort(g_std))
    m = max(3, int(np.ceil(quiet_fraction * nb)))
    quiet = np.argpartition(score, m - 1)[:m]
    out = {"gravity": float(np.median(a_norm[quiet])), "accel_noise": float(np.median(a_std[quiet])),
           "accel_motion": float(np.percentile(a_std, 90))}
    if gyro is not None:
        out["gyro_noise"] = float(np.median(g_std[quiet]))
        out["gyro_bias"] = np.median(g_mean[quiet], axis=0)
        out["gyro_motion"] = float(np.percentile(g_std, 90))
    return out


def _numpy_blocks_stats(blk, x):
    """The numpy code of ``_Blocks.stats`` before the compiled sums (reference)."""
    off = x[: min(blk.n, 1000)].mean(axis=0)
    xc = x - off
    s1 = np.add.reduceat(xc, blk.idx, axis=0)
    xc *= xc
    s2 = np.add.reduceat(xc, blk.idx, axis=0)
    c = blk.win_count[:, None]
    m1 = blk.window(s1) / c
    var = np.maximum(blk.window(s2) / c - m1 * m1, 0.0)
    return m1 + off, np.sqrt(var.mean(axis=1))


def _assert_bits(got, ref):
    """Same shape and the same float64 values bit for bit (NaN matched as NaN, the sign of zero checked)."""
    got, ref = np.asarray(got, float), np.asarray(ref, float)
    assert got.shape == ref.shape
    assert np.array_equal(got, ref, equal_nan=True), np.flatnonzero(got != ref)[:5]
    finite = ~np.isnan(ref)
    assert np.array_equal(np.signbit(got[finite]), np.signbit(ref[finite]))


def _wide_record(rng, n, d=3):
    """Values spread over 12 decades around an offset: every rounding of a sum order shows."""
    return rng.normal(size=(n, d)) * 10 ** rng.uniform(-6, 6, size=(n, d)) + 10 * rng.normal(size=d)


def _kernel_cases(rng):
    """(x, w) pairs: every pairwise-summation regime (< 8, 8..128, > 128 split recursively), ragged ends."""
    for w in list(range(1, 34)) + [63, 64, 65, 100, 127, 128, 129, 136, 255, 256, 257, 300, 1000, 1201]:
        yield _wide_record(rng, 7 * w + int(rng.integers(0, w))), w


def _check_kernels_against_numpy(seed=0):
    from mtcal.methods import _rest_kernels

    rng = np.random.default_rng(seed)
    for x, w in _kernel_cases(rng):
        nb = x.shape[0] // w
        b = x[: nb * w].reshape(nb, w, -1)
        b = b - b[:, :1]
        s1, s2 = _rest_kernels.block_sums(x, w)
        _assert_bits(s1, b.sum(axis=1))
        _assert_bits(s2, (b * b).sum(axis=1))
        _assert_bits(_rest_kernels.row_block_sums(x[:, 1], w), x[: nb * w, 1].reshape(nb, w).sum(axis=1))
        for sub in {1, max(1, w // 4), w}:
            idx = np.arange(0, x.shape[0], sub)
            off = x[:1000].mean(axis=0)
            r1, r2 = _rest_kernels.reduceat_sums(x, idx, off)
            xc = x - off
            _assert_bits(r1, np.add.reduceat(xc, idx, axis=0))
            _assert_bits(r2, np.add.reduceat(xc * xc, idx, axis=0))


def test_compiled_block_sums_match_numpy_bit_for_bit():
    _check_kernels_against_numpy()


@pytest.mark.parametrize("special", [np.nan, np.inf, -np.inf, 0.0, -0.0, 1e300])
def test_compiled_block_sums_special_values_as_numpy(rng, special):
    from mtcal.methods import _rest_kernels

    x = _wide_record(rng, 1000)
    x[rng.integers(0, 1000, 7), rng.integers(0, 3, 7)] = special
    x[:25, 0] = -0.0  # a block of negative zeros: numpy's sums keep or drop the sign, so must the kernel
    for w in (4, 25, 100, 200):
        nb = x.shape[0] // w
        with np.errstate(invalid="ignore", over="ignore"):
            b = x[: nb * w].reshape(nb, w, -1)
            b = b - b[:, :1]
            s1, s2 = _rest_kernels.block_sums(x, w)
            _assert_bits(s1, b.sum(axis=1))
            _assert_bits(s2, (b * b).sum(axis=1))
            _assert_bits(_rest_kernels.row_block_sums(x[:, 0], w), x[: nb * w, 0].reshape(nb, w).sum(axis=1))
            idx = np.arange(0, x.shape[0], max(1, w // 4))
            off = np.array([0.0, -0.0, 3.5])
            r1, r2 = _rest_kernels.reduceat_sums(x, idx, off)
            xc = x - off
            _assert_bits(r1, np.add.reduceat(xc, idx, axis=0))
            _assert_bits(r2, np.add.reduceat(xc * xc, idx, axis=0))


def test_compiled_block_sums_take_any_layout(rng):
    from mtcal.methods import _rest_kernels

    x = _wide_record(rng, 600)
    fortran, strided = np.asfortranarray(x), np.repeat(x, 2, axis=0)[::2]
    for y in (fortran, strided, x.astype(np.float32)):
        _assert_bits(_rest_kernels.block_sums(y, 25)[1], _rest_kernels.block_sums(np.array(y, float), 25)[1])
    _assert_bits(_rest_kernels.row_block_sums(x[:, 2], 10), x[:, 2].reshape(60, 10).sum(axis=1))


def _real_looking_records():
    """IMU records as the detector meets them: rests and moves, biases, quantised and constant rests."""
    rng = np.random.default_rng(2023)
    t, gyro, accel = _record(rng, turn_z_deg_s=20.0)
    yield "tilt and turn 200 Hz", accel, gyro, 1.0 / FS
    yield "accelerometer only", accel, None, 1.0 / FS
    yield "strided views 100 Hz", accel[::2], gyro[::2], 2.0 / FS
    yield "Fortran-ordered", np.asfortranarray(accel), np.asfortranarray(gyro), 1.0 / FS
    _, gyro, accel, _, _ = _walk()
    yield "walking 1200 Hz", accel, gyro, 1 / 1200.0
    n = 7_777
    tilt = np.radians(np.r_[np.zeros(3000), np.linspace(0, 20, 777), np.full(4000, 20.0)])
    accel = np.round(9.9 * np.column_stack([np.sin(tilt), np.zeros(n), np.cos(tilt)]) / 0.0024) * 0.0024
    yield "quantised, constant rests 1 kHz", accel, np.round(rng.normal(0, 1e-3, (n, 3)) / 1e-3) * 1e-3, 1e-3
    for fs in (50.0, 333.0, 1000.0, 3000.0):
        n = int(rng.integers(int(0.4 * fs), int(20 * fs)))
        gyro = rng.normal(0, 10 ** rng.uniform(-4, -2), (n, 3)) + np.radians(rng.uniform(-3, 3, 3))
        accel = rng.normal(0, 10 ** rng.uniform(-3, -1), (n, 3)) + [0, 0, 9.8 * rng.uniform(0.97, 1.03)]
        for _ in range(4):
            s = int(rng.integers(0, n))
            e = min(n, s + int(rng.integers(1, 2 * fs)))
            gyro[s:e, rng.integers(0, 3)] += rng.normal(0, 1)
            accel[s:e, rng.integers(0, 3)] += rng.normal(0, 2) * np.sin(np.arange(e - s) / fs * 6)
        yield f"random moves {fs:g} Hz", accel, gyro, 1 / fs


def _check_detector_against_numpy():
    for name, accel, gyro, dt in _real_looking_records():
        w = max(3, int(round(0.1 / dt)))
        norm = np.sqrt(np.einsum("ij,ij->i", accel, accel))
        got = rest_detection._block_levels(accel, norm, gyro, w, 0.1)
        ref = _numpy_block_levels(accel, norm, gyro, w, 0.1)
        assert got.keys() == ref.keys(), name
        for key in ref:
            _assert_bits(got[key], ref[key])
        blk = rest_detection._Blocks(accel.shape[0], w)
        for x in (norm[:, None], accel) + (() if gyro is None else (gyro,)):
            for g, r in zip(blk.stats(x), _numpy_blocks_stats(blk, x)):
                _assert_bits(g, r)


def test_detector_statistics_match_the_numpy_code_bit_for_bit():
    _check_detector_against_numpy()


def test_compiled_sums_match_numpy_on_the_other_code_path():
    """The same checks in a fresh process on the other numba/numpy code path (generic <-> native)."""
    code = ("from tests.methods import test_rest_detection as t; t._check_kernels_against_numpy(1); "
            "t._check_detector_against_numpy(); print('same bits')")
    res = run_on_the_other_code_path(code)
    assert res.returncode == 0 and res.stdout.strip() == "same bits", res.stderr[-2000:]


def test_quiet_core_keeps_a_slow_start_of_motion_out_of_the_bias():
    from mtcal.methods.rest_detection import quiet_core

    rng = np.random.default_rng(5)
    fs, sigma = 1000.0, np.radians(0.05)
    t = np.arange(int(8 * fs)) / fs
    bias = np.radians([0.35, -0.25, 0.3])
    gyro = rng.normal(0.0, sigma, (t.size, 3)) + bias
    ramp = t > 5.0
    gyro[ramp, 2] += np.radians(1.0) * (t[ramp] - 5.0) ** 2       # rate below 1.5 deg/s for 1.2 s
    rest = slice(0, int(6.2 * fs))                                 # a 1.5 deg/s detector's rest
    qc = quiet_core(gyro, rest, 1.0 / fs, sigma)
    assert qc.core.start == 0 and 5.0 * fs < qc.core.stop < 5.6 * fs
    assert abs(np.degrees(qc.bias_rad_s[2] - bias[2])) < 0.003
    assert np.degrees(gyro[rest, 2].mean() - bias[2]) > 0.05       # the whole rest's mean leaks the ramp
    assert qc.threshold_rad_s == pytest.approx(5 * sigma / np.sqrt(50))
    # a rest too noisy for the stated noise falls back to the whole rest
    qc2 = quiet_core(gyro, rest, 1.0 / fs, sigma / 100)
    assert qc2.core == slice(0, rest.stop)


def test_detectors_trust_their_inputs_no_twins():
    """One function per detector (documented preconditions); mtcal.systems.rests.find_rests checks at its edge."""
    from mtcal.methods import rest_detection as rd

    assert not [n for n, f in vars(rd).items() if n.endswith("_trusted") and getattr(f, "__module__", "") == rd.__name__]
    for f in (rd.detect_rests, rd.paper_rest_report, rd.detect_rests_shoe):
        assert "Preconditions" in f.__doc__, f.__name__
