"""Gravity tracking: the stated gyro scale against unit/time-base rivals, on a simulated tilting record."""

import numpy as np
import pytest

from mtcal.methods import gravity_tracking as gt


def _tilting(n=4000, dt=0.01, seed=0, lin_acc=0.0):
    rng = np.random.default_rng(seed)
    t = np.arange(n) * dt
    rate_x = 0.8 * np.sin(2 * np.pi * 0.23 * t)
    rate_y = 0.5 * np.sin(2 * np.pi * 0.31 * t + 1.0)
    gyro = np.column_stack([rate_x, rate_y, np.zeros(n)])
    # gravity in the sensor frame, propagated exactly with the gyro (constant rate per sample)
    v = np.array([0.0, 0.0, 1.0])
    up = np.empty((n, 3))
    for k in range(n):
        up[k] = v
        v = gt._rotate_back(v[None], gyro[k][None], dt)[0]
    accel = 9.81 * up + rng.normal(0, 0.02, (n, 3)) + lin_acc * rng.normal(0, 1, (n, 3))
    return gyro + rng.normal(0, 1e-3, (n, 3)), accel, dt


def test_right_units_confirmed():
    gyro, accel, dt = _tilting()
    res = gt.gravity_tracking(gyro, accel, dt)
    assert res["decision"] == "stated" and res["margin"] >= gt.CONFIRM_FRACTION
    assert "gravity tracking" in res["evidence"]


@pytest.mark.parametrize("factor,name", [(180 / np.pi, "deg/s read as rad/s"), (1e3, "mrad/s read as rad/s"),
                                         (np.pi / 180, "rad/s read as deg/s"), (0.1, "time column 10x too fast")])
def test_wrong_scale_found(factor, name):
    gyro, accel, dt = _tilting()
    res = gt.gravity_tracking(gyro * factor, accel, dt)
    assert res["decision"] == "rival" and res["winner"].startswith(name)
    assert res["margin"] >= gt.CONTRADICT_FRACTION


def test_time_base_wrong_by_10_found():
    gyro, accel, dt = _tilting()
    res = gt.gravity_tracking(gyro, accel, dt * 10)   # time column 10x too slow: integrates 10x too far
    # refused; on this slow record 57x smaller fits as well as 10x smaller, so both are named as contradicting
    assert res["decision"] == "rival"
    assert 1.0 - res["rivals"]["time column 10x too slow"]["win_fraction"] >= gt.CONTRADICT_FRACTION


def test_no_motion_undecided():
    n = 3000
    res = gt.gravity_tracking(np.zeros((n, 3)), np.tile([0.0, 0.0, 9.81], (n, 1)), 0.01)
    assert res["decision"] == "undecided" and all(r["windows"] == 0 for r in res["rivals"].values())


def test_edge_errors():
    with pytest.raises(ValueError, match=r"must be \(N, 3\) alike"):
        gt.gravity_tracking(np.zeros((10, 3)), np.zeros((9, 3)), 0.01)
    with pytest.raises(ValueError, match="must be finite"):
        gt.gravity_tracking(np.full((10, 3), np.nan), np.ones((10, 3)), 0.01)
    with pytest.raises(ValueError, match="dt_s"):
        gt.gravity_tracking(np.zeros((10, 3)), np.ones((10, 3)), 0.0)
    short = gt.gravity_tracking(np.zeros((3, 3)), np.ones((3, 3)), 0.01)
    assert short["decision"] == "undecided" and short["windows"] == 0
