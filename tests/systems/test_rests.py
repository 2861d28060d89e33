"""mtcal.systems.rests: the config is checked when built, the arrays once at find_rests; short rests rejected."""

import numpy as np
import pytest

from mtcal.systems.rests import DETECTORS, RestsConfig, default_rests, drop_short_rests, find_rests, rests_table

DT_S = 0.01


def _record(n_rest=300, n_move=200, seed=3):
    """Rest, a 90 deg turn about sensor x (accelerometer following gravity, pushed along x), rest; (gyro rad/s, accel m/s^2)."""
    from mtcal.core.rng import stream_rng

    rng = stream_rng(seed, 0)
    n = 2 * n_rest + n_move
    u = np.concatenate([np.zeros(n_rest), np.linspace(0.0, 1.0, n_move), np.ones(n_rest)])
    theta = np.pi / 4 * (1.0 - np.cos(np.pi * u))                  # smooth start and stop
    rate = np.append(np.diff(theta) / DT_S, 0.0)                   # sample k: the mean over [t_k, t_k+1]
    acc = 9.81 * np.stack([np.zeros(n), np.sin(theta), np.cos(theta)], axis=1)
    acc[n_rest:n_rest + n_move, 0] += np.sin(np.linspace(0.0, np.pi, n_move))   # the hand's push: |a| leaves g
    gyr = np.stack([rate, np.zeros(n), np.zeros(n)], axis=1)
    return gyr + 0.0003 * rng.standard_normal((n, 3)), acc + 0.005 * rng.standard_normal((n, 3))


@pytest.mark.parametrize("kw,match", [
    ({"detector": "zvd"}, r"detector must be one of \('adaptive', 'paper', 'shoe'\), got 'zvd'"),
    ({"min_rest_s": 0.0}, "min_rest_s must be None or a finite number > 0, got 0.0"),
    ({"min_rest_s": None}, "min_rest_s must be a finite number > 0, got None"),
    ({"noise_factor": float("nan")}, "noise_factor must be None or a finite number > 0"),
    ({"gravity_m_s2": -9.8}, "gravity_m_s2 must be None or a finite number > 0"),
    ({"shoe_threshold": 6.0}, "shoe_threshold needs detector 'shoe'"),
])
def test_config_checked_when_built(kw, match):
    with pytest.raises(ValueError, match=match):
        RestsConfig(**kw)


def test_arrays_checked_once_at_the_edge():
    gyr, acc = _record()
    with pytest.raises(TypeError, match="config must be a RestsConfig, got dict"):
        find_rests(acc, DT_S, {"detector": "adaptive"})
    with pytest.raises(ValueError, match="gyro_rad_s and accel_m_s2 must have the same shape"):
        find_rests(acc, DT_S, RestsConfig(), gyro_rad_s=gyr[:-1])
    with pytest.raises(ValueError, match="time_s must have 800 samples, got 799"):
        find_rests(acc, DT_S, RestsConfig(), time_s=np.arange(799) * DT_S)
    with pytest.raises(ValueError, match="dt_s"):
        find_rests(acc, 100.0, RestsConfig())                 # a rate in Hz passed as the interval
    # the checks the detectors (mtcal.methods.rest_detection) held: now here, once, for every detector
    for detector in DETECTORS:
        cfg = RestsConfig(detector=detector)
        with pytest.raises(ValueError, match="dt_s must be > 0"):
            find_rests(acc, -1.0, cfg, gyro_rad_s=gyr)
        with pytest.raises(ValueError, match=r"dt_s must be the sample interval in s \(<= 1 s\), got 200 \(a sample rate"):
            find_rests(acc, 200.0, cfg, gyro_rad_s=gyr)
        with pytest.raises(ValueError, match="looks like it is in g"):
            find_rests(acc / 9.81, DT_S, cfg, gyro_rad_s=gyr)
        with pytest.raises(ValueError, match="accel_m_s2 must be finite"):
            find_rests(np.where(np.arange(acc.shape[0])[:, None] == 5, np.nan, acc), DT_S, cfg, gyro_rad_s=gyr)
        with pytest.raises(ValueError, match="gyro_rad_s must be finite"):
            find_rests(acc, DT_S, cfg, gyro_rad_s=np.full_like(gyr, np.inf))
        with pytest.raises(ValueError, match="accel_m_s2 must"):
            find_rests(acc[:, :2], DT_S, cfg, gyro_rad_s=gyr)
    with pytest.raises(ValueError, match="detector 'shoe' needs gyro_rad_s"):
        find_rests(acc, DT_S, RestsConfig(detector="shoe"))
    with pytest.raises(ValueError, match="detector 'shoe' needs gyro_rad_s"):
        find_rests(acc, DT_S, RestsConfig(detector="shoe", use_gyro=False), gyro_rad_s=gyr)


@pytest.mark.parametrize("detector", DETECTORS)
def test_two_rests_found_by_every_detector(detector):
    gyr, acc = _record()
    rep = find_rests(acc, DT_S, RestsConfig(detector=detector, min_rest_s=1.0), gyro_rad_s=gyr)
    assert len(rep.rests) == 2 and rep.rests[0].start < 30 and rep.rests[1].stop > 770
    table = rests_table(np.arange(acc.shape[0]) * DT_S, acc, rep, gyro_rad_s=gyr)
    if detector == "paper":     # |a| in the paper's band only: the slow ends of the turn count as rest
        np.testing.assert_allclose(table["tilt_deg"], [0.0, 90.0], atol=5.0)
        return
    np.testing.assert_allclose(table["tilt_deg"], [0.0, 90.0], atol=1.0)
    np.testing.assert_allclose(table["accel_norm_m_s2"], 9.81, atol=0.01)
    assert np.all(np.abs(table["gyro_x_deg_s"]) < 0.1)


def test_short_rests_rejected_by_listed_span():
    gyr, acc = _record()
    rep = find_rests(acc, DT_S, RestsConfig(min_rest_s=2.95), gyro_rad_s=gyr)
    # each rest spans ~3 s by its samples; listed span t[stop-1] - t[start] is one step shorter
    spans = [(r.stop - 1 - r.start) * DT_S for r in rep.rests]
    assert all(s >= 2.95 for s in spans)
    assert all("too short" in r.reason for r in rep.rejected if "too short" in r.reason)
    kept = drop_short_rests(rep, np.arange(acc.shape[0]) * DT_S)
    assert kept is rep                                        # nothing left to drop: the same report
    assert default_rests(acc, DT_S, gyr).rests == find_rests(acc, DT_S, RestsConfig(), gyro_rad_s=gyr).rests
