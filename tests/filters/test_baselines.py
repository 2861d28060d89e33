"""Tests of mtcal.filters.baselines (ref. [16] angle, AHRS stand-in)."""

import numpy as np
import pytest

from mtcal.core import rotations
from mtcal.filters.baselines import (MagneticDisturbance, accel_only_angle, angle_from_orientation,
                             mahony_marg, simulate_magnetometer, triad_quaternion)

V = np.array([0.1734, 0.9835, 0.0523]) / np.linalg.norm([0.1734, 0.9835, 0.0523])
A0 = np.array([0.0, 0.0, 9.80665])


def test_accel_only_angle_exact_and_sign_convention():
    th = np.radians(np.arange(-175.0, 180.0, 5.0))
    a = np.einsum("nji,j->ni", rotations.axis_angle_matrix(th, V), A0)  # R(θ, v)ᵀ ā0
    np.testing.assert_allclose(accel_only_angle(a, V, A0), th, atol=1e-12)
    # −v describes the same rotation with the opposite angle
    np.testing.assert_allclose(accel_only_angle(a, -V, A0), -th, atol=1e-12)


def test_accel_only_angle_vertical_axis_raises():
    with pytest.raises(ValueError, match="parallel to gravity"):
        accel_only_angle(np.tile(A0, (3, 1)), [0, 0, 1.0], A0)


def test_triad_and_noise_free_marg_track_rotation(rng):
    n, dt = 400, 0.01
    th = np.radians(np.linspace(0, 60, n))[None]
    dist = MagneticDisturbance(heading_sigma_deg=1e-9)
    mag = simulate_magnetometer(th, V, (1, 0, 0, 0), dist, dt, rng, noise_fraction=0.0)
    acc = np.einsum("nji,j->ni", rotations.axis_angle_matrix(th[0], V), A0)[None]
    gyro = np.broadcast_to((np.gradient(th[0], dt))[:, None] * V, (1, n, 3))
    q0 = triad_quaternion(acc[:, 0], mag[:, 0])
    up = rotations.quat_to_matrix(q0[0]) @ (acc[0, 0] / 9.80665)
    np.testing.assert_allclose(up, [0, 0, 1], atol=1e-12)
    q = mahony_marg(gyro, acc, mag, dt, q0=q0)
    ang = angle_from_orientation(q, V, 0)
    assert np.max(np.abs(np.degrees(ang - th))) < 1e-6


def test_disturbed_field_moves_ahrs_at_rest(rng):
    """Fig. 13 mechanism: at rest, a wandering field heading moves the AHRS angle."""
    n, dt = 3000, 0.05
    th = np.zeros((2, n))
    mag = simulate_magnetometer(th, V, (1, 0, 0, 0), MagneticDisturbance(heading_sigma_deg=10.0), dt, rng)
    acc = np.broadcast_to(A0, (2, n, 3)).copy()
    q = mahony_marg(np.zeros((2, n, 3)), acc, mag, dt)
    ang = np.degrees(angle_from_orientation(q, V, 0))
    assert np.all(np.ptp(ang, axis=1) > 0.05)
