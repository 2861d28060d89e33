"""core.sensors.SensorSpec: one SI sensor spec owning the sample rate; the one error_model conversion."""

import numpy as np
import pytest

from mtcal.core.sensor_grades import GRADES, sensor_grade, sensor_spec
from mtcal.core.sensors import SENSOR_SOURCES, SensorSpec
from mtcal.core.units import DEG_H, MG


def test_grade_error_model_goes_through_the_spec():
    for name in GRADES:
        g = sensor_grade(name)
        m = g.error_model((1.0, 0, 0, 0), time_since_power_on_s=120.0)
        assert m.gyro.bias_sigma == pytest.approx(g.gyro_bias_repeatability_deg_h * DEG_H)
        assert m.accel.bias_sigma == pytest.approx(g.accel_bias_repeatability_mg * MG)
        assert m.time_since_power_on_s == 120.0
        sf = g.gyro_scale_factor_ppm * 1e-6
        assert np.allclose(m.gyro.scale_factor, (sf, -sf, sf))


def test_mixed_grades_and_sample_rate():
    s = sensor_spec("consumer", "navigation", fs_hz=250.0)
    assert s.fs_hz == 250.0 and s.dt_s == pytest.approx(0.004)
    assert s.gyro_noise_rad_s_rt_hz == sensor_grade("consumer").gyro_noise_density_rad_s_rt_hz
    assert s.accel_noise_m_s2_rt_hz == sensor_grade("navigation").accel_noise_density_m_s2_rt_hz
    assert s.accel_noise_per_sample_m_s2 == pytest.approx(s.accel_noise_m_s2_rt_hz * np.sqrt(250.0))
    with pytest.raises(ValueError, match="grade must be one of"):
        sensor_spec("nope")


def test_sources_switch_each_error_and_run_bias_adds_in_quadrature():
    s = SensorSpec(fs_hz=100.0, gyro_noise_rad_s_rt_hz=1e-4, gyro_bias_sigma_rad_s=3e-5, gyro_lsb_rad_s=1e-6,
                   accel_bias_m_s2=(0.01, 0.0, 0.0), accel_rw_m_s2_rt_s=1e-5)
    none = s.error_model(sources=())
    assert none.gyro.noise_density == 0 and none.accel.bias == 0 and none.gyro.quantization == 0
    full = s.error_model(sources=SENSOR_SOURCES)
    assert full.accel.bias == (0.01, 0.0, 0.0) and full.accel.bias_random_walk == 1e-5

    class Run:
        gyro_run_bias_rad_s = 4e-5
    assert s.error_model(errors=Run()).gyro.bias_sigma == pytest.approx(5e-5)


@pytest.mark.parametrize("kwargs, match", [
    ({"fs_hz": -1.0}, "fs_hz must be > 0"),
    ({"fs_hz": 100.0, "gyro_noise_rad_s_rt_hz": -1.0}, "gyro_noise_rad_s_rt_hz must be a finite value >= 0"),
    ({"fs_hz": 100.0, "gyro_bias_rad_s": (1.0, 2.0)}, "gyro_bias_rad_s must be a finite 3-vector"),
    ({"fs_hz": 100.0, "gyro_scale_factor": (1.0, np.nan, 0.0)}, "gyro_scale_factor must be a number or a finite"),
    ({"fs_hz": 100.0, "gyro_warmup_tau_s": 0.0}, "gyro_warmup_tau_s must be > 0"),
])
def test_validation(kwargs, match):
    with pytest.raises(ValueError, match=match):
        SensorSpec(**kwargs)


def test_label_type_and_sources_type():
    with pytest.raises(TypeError, match="label must be a str"):
        SensorSpec(fs_hz=1.0, label=3)
    with pytest.raises(TypeError, match="sources must be an iterable of names"):
        SensorSpec(fs_hz=1.0).error_model(sources="gyro_white")
