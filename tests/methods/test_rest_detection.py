"""Adaptive rest detection: levels measured from the data, overrides, reasons, the paper's ZVD beside it."""

import numpy as np
import pytest

from mtcal.methods import rest_detection as rd
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
    rep = rd.detect_rests(accel, 1.0 / FS, gyro_rad_s=gyro)
    assert len(rep.rests) == 2
    assert abs(rep.gravity_m_s2 - 9.80665 * 1.03) < 0.01
    np.testing.assert_allclose(np.degrees(rep.gyro_bias_rad_s), [3.0, -2.0, 1.0], atol=0.05)
    assert 0.005 < rep.accel_noise_m_s2 < 0.02 and np.degrees(rep.gyro_noise_rad_s) < 0.5
    r0, r1 = rep.rests
    assert t[r0.start] == 0.0 and 1.8 < t[r0.stop - 1] < 2.0 and 3.0 < t[r1.start] < 3.2
    assert not detect_static(accel, 1.0 / FS).any()  # 9.76-9.84 excludes a sensor reading 10.10
    paper = rd.paper_rest_report(accel, 1.0 / FS, gyro_rad_s=gyro)
    assert paper.rests == [] and abs(paper.extra["measured_gravity_m_s2"] - rep.gravity_m_s2) < 1e-9


def test_slow_turn_about_vertical_rejected_with_reason(rng):
    t, gyro, accel = _record(rng, turn_z_deg_s=20.0)
    rep = rd.detect_rests(accel, 1.0 / FS, gyro_rad_s=gyro)
    assert len(rep.rests) == 3
    assert any("turning" in r.reason for r in rep.rejected)
    assert not rep.is_static[(t > 5.1) & (t < 5.9)].any()
    only_accel = rd.detect_rests(accel, 1.0 / FS)  # without the gyro the turn is invisible
    assert only_accel.is_static[(t > 5.1) & (t < 5.9)].all()


def test_overrides(rng):
    t, gyro, accel = _record(rng)
    rep = rd.detect_rests(accel, 1.0 / FS, gyro_rad_s=gyro, params=rd.RestDetectorParams(gravity_m_s2=9.80665,
                                                                                   accel_band_m_s2=0.05))
    assert rep.band_m_s2 == pytest.approx((9.75665, 9.85665)) and rep.rests == []
    assert rep.rejected and all("outside band" in r.reason for r in rep.rejected)
    rep = rd.detect_rests(accel, 1.0 / FS, gyro_rad_s=gyro,
                          params=rd.RestDetectorParams(gyro_level_max_rad_s=np.radians(0.001)))
    assert rep.rests == [] and rep.gyro_level_max_rad_s == pytest.approx(np.radians(0.001))
    rep = rd.detect_rests(accel, 1.0 / FS, gyro_rad_s=gyro, params=rd.RestDetectorParams(min_rest_s=2.5))
    assert len(rep.rests) == 1 and "too short" in rep.rejected[0].reason


def test_levels_text_reports_measured_values(rng):
    t, gyro, accel = _record(rng)
    txt = rd.detect_rests(accel, 1.0 / FS, gyro_rad_s=gyro).levels_text()
    assert "|a| at rest 10.10" in txt and "gyro bias [+3.00, -2.00, +" in txt


def test_paper_report_keeps_the_paper_flags(rng):
    t, gyro, accel = _record(rng, g=9.80665)
    rep = rd.paper_rest_report(accel, 1.0 / FS, min_rest_s=0.5)
    assert np.array_equal(rep.is_static, detect_static(accel, 1.0 / FS))
    assert rep.band_m_s2 == (9.76, 9.84) and rep.method == "paper"
    assert all(r.stop - r.start >= 0.5 * FS for r in rep.rests)


def test_centred_moving_mean_matches_direct_sum(rng):
    x = rng.normal(size=(57, 2))
    for w in (1, 2, 5, 8, 57, 80):
        got = rd.centred_moving_mean(x, w)
        ref = np.array([x[max(i - w // 2, 0):min(i - w // 2 + w, 57)].mean(axis=0) for i in range(57)])
        np.testing.assert_allclose(got, ref, atol=1e-12)


def test_quantised_constant_rest_uses_noise_floor():
    tilt = np.radians(np.r_[np.zeros(1000), np.linspace(0, 20, 100), np.full(900, 20.0)])
    accel = 9.9 * np.column_stack([np.sin(tilt), np.zeros(2000), np.cos(tilt)])
    rep = rd.detect_rests(accel, 1.0 / FS, gyro_rad_s=np.zeros((2000, 3)))
    assert rep.accel_noise_m_s2 == rd.ACCEL_NOISE_FLOOR_M_S2 and len(rep.rests) == 2


@pytest.mark.parametrize("kwargs,exc,match", [
    (dict(params=rd.RestDetectorParams), TypeError, "params must be a RestDetectorParams"),
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
        rd.detect_rests(accel, dt_s, **args)


def test_bad_params_and_short_records():
    with pytest.raises(ValueError, match="quiet_fraction must be in"):
        rd.RestDetectorParams(quiet_fraction=0.8)
    with pytest.raises(ValueError, match="gravity_m_s2 must be in m/s"):
        rd.RestDetectorParams(gravity_m_s2=1.0)
    with pytest.raises(ValueError, match="noise_factor must be > 0"):
        rd.RestDetectorParams(noise_factor=0.0)
    with pytest.raises(ValueError, match="record too short"):
        rd.detect_rests(np.tile([0, 0, 9.8], (30, 1)), 1.0 / FS)
    with pytest.raises(ValueError, match="looks like it is in g"):
        rd.detect_rests(np.tile([0, 0, 1.0], (300, 1)), 1.0 / FS)


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
    rep = rd.detect_rests(np.vstack(acc), 1.0 / fs, gyro_rad_s=np.vstack(gyr))
    assert len(rep.rests) == 1 + 8
    assert rep.accel_std_max_m_s2 > 0.15 > 5 * rep.accel_noise_m_s2  # relaxed towards the motion level
