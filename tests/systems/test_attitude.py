"""mtcal.systems.attitude: one config, one call; the real-data study's QNCF is the command's QNCF."""

import numpy as np
import pytest

from mtcal.systems.attitude import FILTERS, AttitudeConfig, estimate_attitude
from mtcal.systems.rests import RestsConfig

from .test_rests import DT_S, _record


@pytest.mark.parametrize("kw,exc,match", [
    ({"filter": "kalman"}, ValueError, r"filter must be one of \('qncf', 'vqf'"),
    ({"rests": {"detector": "paper"}}, TypeError, "rests must be a RestsConfig, got dict"),
    ({"check_units": 1}, TypeError, "check_units must be a bool, got int"),
])
def test_config_checked_when_built(kw, exc, match):
    with pytest.raises(exc, match=match):
        AttitudeConfig(**kw)


def test_arrays_checked_once_at_the_edge():
    gyr, acc = _record()
    with pytest.raises(TypeError, match="config must be an AttitudeConfig, got RestsConfig"):
        estimate_attitude(gyr, acc, DT_S, RestsConfig())
    with pytest.raises(ValueError, match="gyro_rad_s and accel_m_s2 must have the same shape"):
        estimate_attitude(gyr[:-1], acc, DT_S, AttitudeConfig())
    with pytest.raises(ValueError, match="accel_m_s2 must be finite"):
        estimate_attitude(gyr, np.where(np.arange(800)[:, None] == 5, np.nan, acc), DT_S, AttitudeConfig())
    with pytest.raises(ValueError, match="time_s must be 800 strictly increasing times"):
        estimate_attitude(gyr, acc, DT_S, AttitudeConfig(), time_s=np.zeros(800))


def test_units_refused_when_checked():
    gyr, acc = _record()
    with pytest.raises(ValueError, match="gyro"):
        estimate_attitude(np.degrees(gyr), acc, DT_S, AttitudeConfig.cli_defaults())


def test_qncf_from_the_rests_and_the_turn_recovered():
    gyr, acc = _record()
    gyr = gyr + np.radians([0.3, -0.2, 0.1])                     # a constant bias the first rest gives
    res = estimate_attitude(gyr, acc, DT_S, AttitudeConfig.cli_defaults())
    assert res.setup.levelled_from.startswith("first rest") and len(res.rests.rests) == 2
    np.testing.assert_allclose(np.degrees(res.setup.bias_rad_s), [0.3, -0.2, 0.1], atol=0.02)
    assert res.units_check is not None and res.setup.params.gravity_m_s2 == pytest.approx(9.81, abs=0.01)
    paper = estimate_attitude(gyr, acc, DT_S, AttitudeConfig.paper())
    assert paper.setup.levelled_from.startswith("first 100 samples") and not paper.setup.bias_rad_s.any()


@pytest.mark.parametrize("name", [f for f in FILTERS if f not in ("vqf", "basicvqf", "fusion", "madgwick")])
def test_every_filter_same_result_type(name):
    gyr, acc = _record()
    res = estimate_attitude(gyr, acc, DT_S, AttitudeConfig.cli_defaults(name))
    assert res.q_ws.shape == (800, 4) and np.allclose(np.linalg.norm(res.q_ws, axis=1), 1.0)
    assert (res.setup is None) == (name != "qncf") and (res.gain_text == "") == (name == "qncf")


def test_study_qncf_is_the_command_qncf():
    """broad2021's ``qncf_cli`` (filter's own unit check) = the command's QNCF (units checked once) bit for bit."""
    from mtcal.studies.broad2021 import runs, scenario

    tr = scenario.trial_head(scenario.load_trials(["01_undisturbed_slow_rotation_A"])[0], 6000)
    study = runs.run_6d("qncf_cli", tr.gyro_rad_s, tr.accel_m_s2, tr.dt_s)
    command = estimate_attitude(tr.gyro_rad_s, tr.accel_m_s2, tr.dt_s, AttitudeConfig.cli_defaults())
    np.testing.assert_array_equal(study, command.q_ws)
