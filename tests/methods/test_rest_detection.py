"""Adaptive rest detection: levels measured from the data, overrides, reasons, the paper's ZVD beside it."""

import numpy as np
import pytest

from mtcal.methods import rest_detection
from mtcal.methods.zero_velocity import detect_static

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


@pytest.mark.parametrize("kwargs,exc,match", [
    (dict(params=rest_detection.RestDetectorParams), TypeError, "params must be a RestDetectorParams"),
    (dict(gyro_rad_s=np.zeros((10, 3))), ValueError, "gyro_rad_s must have the shape"),
    (dict(dt_s=-1.0), ValueError, "dt_s must be > 0"),
    (dict(dt_s=200.0), ValueError, r"dt_s must be the sample interval in s \(<= 1 s\), got 200 \(a sample rate"),
])
def test_bad_input(rng, kwargs, exc, match):
    t, gyro, accel = _record(rng)
    args = dict(dt_s=1.0 / FS)
    args.update(kwargs)
    dt_s = args.pop("dt_s")
    with pytest.raises(exc, match=match):
        rest_detection.detect_rests(accel, dt_s, **args)


def test_bad_params_and_short_records():
    with pytest.raises(ValueError, match="quiet_fraction must be in"):
        rest_detection.RestDetectorParams(quiet_fraction=0.8)
    with pytest.raises(ValueError, match="gravity_m_s2 must be in m/s"):
        rest_detection.RestDetectorParams(gravity_m_s2=1.0)
    with pytest.raises(ValueError, match="noise_factor must be > 0"):
        rest_detection.RestDetectorParams(noise_factor=0.0)
    with pytest.raises(ValueError, match="record too short"):
        rest_detection.detect_rests(np.tile([0, 0, 9.8], (30, 1)), 1.0 / FS)
    with pytest.raises(ValueError, match="looks like it is in g"):
        rest_detection.detect_rests(np.tile([0, 0, 1.0], (300, 1)), 1.0 / FS)


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


def test_shoe_input_errors(rng):
    accel = rng.normal(0, 0.01, (500, 3)) + [0, 0, 9.8]
    with pytest.raises(ValueError, match="gyro_rad_s must have the shape"):
        rest_detection.detect_rests_shoe(accel, 0.01, gyro_rad_s=np.zeros((400, 3)))
    with pytest.raises(TypeError, match="params must be a ShoeParams"):
        rest_detection.detect_rests_shoe(accel, 0.01, gyro_rad_s=np.zeros((500, 3)),
                                         params=rest_detection.RestDetectorParams())


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
