"""Tests for mtcal.studies.wang2023cja.scenario: builders from parameters-cell values."""

import numpy as np
import pytest

from mtcal.core.units import DEG_H
from mtcal.reporting import compare
from mtcal.studies import wang2023cja as w


def test_defaults_are_the_paper_settings():
    sc = w.turntable_scenario(**w.TURNTABLE_DEFAULTS)
    assert sc.fs_hz == 1000.0 and sc.rest_s == 3.0 and sc.pitch_positions_deg == (-12.0, 23.0)
    assert compare.at_paper_settings(dict(w.TURNTABLE_DEFAULTS), w.TURNTABLE_DEFAULTS)
    assert (compare.describe(sc.imu)["source"].str.len() > 0).all()


def test_parameter_change_propagates_into_labels_and_values():
    sc = w.turntable_scenario(gyro_grade="industrial", roll_positions_deg=(60.0, -60.0))
    assert sc.imu.label == "gyro industrial, accel wang2023cja"
    assert np.isclose(sc.imu.gyro_bias_sigma_rad_s, 30.0 * DEG_H)
    assert np.allclose(np.degrees(w.six_position_reference(sc))[4:, 2], [-60.0, 60.0])  # Eq 8 frame: roll flipped
    assert not compare.at_paper_settings({"gyro_grade": "industrial"}, w.TURNTABLE_DEFAULTS)


@pytest.mark.parametrize("params, match", [
    ({"gyro_grade": "bogus"}, r"gyro_grade must be one of \["),
    ({"fs_hz": 0.0}, r"fs_hz must be a number in \[100.0, 10000.0\] Hz"),
    ({"yaw_positions_deg": (8.0, 8.0)}, "yaw_positions_deg must be two different angles"),
    ({"sample_rate": 100.0}, r"unknown parameter\(s\) \['sample_rate'\]; valid:"),
])
def test_invalid_parameter_is_rejected_in_one_line(params, match):
    with pytest.raises(ValueError, match=match) as err:
        w.turntable_scenario(**params)
    assert "\n" not in str(err.value)


def test_windtunnel_geometry_from_printed_matrix():
    alpha, eps = w.windtunnel_geometry()
    assert len(alpha) == 3 and max(map(abs, alpha)) < 1.0
    assert eps == pytest.approx(1 / 1.004462 - 1, abs=1e-6)
    with pytest.raises(ValueError, match="vibration_accel_m_s2"):
        w.windtunnel_scenario(vibration_accel_m_s2=-1.0)


def test_default_imu_is_the_papers_grade():
    from dataclasses import fields

    from mtcal.core.sensors import SensorSpec
    a, b = w.TurntableScenario().imu, w.paper_imu("wang2023cja", "wang2023cja")
    assert isinstance(w.ImuSpec(), SensorSpec) and isinstance(a, SensorSpec)
    for f in fields(SensorSpec):
        va, vb = getattr(a, f.name), getattr(b, f.name)
        assert va == vb if isinstance(va, str) else np.allclose(va, vb, rtol=1e-12, atol=0), f.name
    assert a.fs_hz == 1000.0 and w.TurntableScenario().fs_hz == 1000.0
    assert w.turntable_scenario(fs_hz=500.0).fs_hz == 500.0
    assert a.gyro_lsb_rad_s == pytest.approx(np.radians(0.00625))
    with pytest.raises(ValueError, match="gyro_grade must be one of"):
        w.paper_imu("nope")


def test_error_model_switches_sources_and_adds_the_run_bias():
    sc = w.TurntableScenario()
    full = sc.imu.error_model((1.0, 0, 0, 0), w.SOURCES, sc.errors)
    assert full.gyro.bias_sigma == pytest.approx(np.hypot(sc.imu.gyro_bias_sigma_rad_s, sc.errors.gyro_run_bias_rad_s))
    assert full.accel.bias_instability == 0.0          # not a wang2023cja source
    only = sc.imu.error_model((1.0, 0, 0, 0), ("gyro_white", "reference_angle"))
    assert only.gyro.noise_density > 0 and only.gyro.bias_sigma == 0 and only.accel.noise_density == 0
    with pytest.raises(TypeError, match="sources must be an iterable of names"):
        sc.imu.error_model((1.0, 0, 0, 0), "gyro_white")