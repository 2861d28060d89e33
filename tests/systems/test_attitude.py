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


# --------------------------------------------------------------------------- one record in one call
def test_attitude_record_is_rests_clipping_and_the_filter_in_one_call():
    """attitude_record = find_rests → clipped_samples → estimate_attitude (the command's old chain), bit for bit."""
    from mtcal.systems import plausibility
    from mtcal.systems.attitude import attitude_record
    from mtcal.systems.rests import find_rests

    gyr, acc = _record()
    gyr = gyr + np.radians([0.3, -0.2, 0.1])
    t = np.arange(800) * DT_S + 1e-4 * DT_S * np.sin(np.arange(800))       # jittered: the gyro weighted
    for name in ("qncf", "mahony"):
        config = AttitudeConfig.cli_defaults(name)
        rep = find_rests(acc, DT_S, config.rests, gyro_rad_s=gyr, time_s=t)
        clipped, level = plausibility.clipped_samples(gyr)
        want = estimate_attitude(gyr, acc, DT_S, config, time_s=t, rests=rep, skip=clipped, unit_stated="header")
        got = attitude_record(gyr, acc, DT_S, config, time_s=t, unit_stated="header")
        np.testing.assert_array_equal(got.q_ws, want.q_ws)
        assert got.rests.rests == rep.rests and got.units_check == want.units_check
        assert not got.clipped.any() and got.clip_level_rad_s == level == 0.0


def test_attitude_record_clipped_gyro_reported():
    from mtcal.systems.attitude import attitude_record

    gyr, acc = _record()
    peak = np.abs(gyr).max()
    gyr = np.clip(gyr, -0.5 * peak, 0.5 * peak)                               # a full-scale plateau
    res = attitude_record(gyr, acc, DT_S, AttitudeConfig.cli_defaults())
    assert res.clipped.any() and res.clip_level_rad_s == pytest.approx(0.5 * peak)


def test_attitude_record_checked_at_its_edge_and_refusals_carry_the_rests():
    from mtcal.systems.attitude import attitude_record

    gyr, acc = _record()
    with pytest.raises(TypeError, match="config must be an AttitudeConfig, got RestsConfig"):
        attitude_record(gyr, acc, DT_S, RestsConfig())
    with pytest.raises(ValueError, match="gyro_rad_s must be given: the attitude needs the gyro"):
        attitude_record(None, acc, DT_S, AttitudeConfig())
    with pytest.raises(ValueError, match="gyro_rad_s and accel_m_s2 must have the same shape"):
        attitude_record(gyr[:-1], acc, DT_S, AttitudeConfig())
    with pytest.raises(ValueError, match="time_s must have 800 samples"):
        attitude_record(gyr, acc, DT_S, AttitudeConfig(), time_s=np.arange(10.0))
    with pytest.raises(ValueError, match="gyro") as info:
        attitude_record(np.degrees(gyr), acc, DT_S, AttitudeConfig.cli_defaults())
    assert len(info.value.rests.rests) == 2 and not info.value.clipped[0].any()


def test_column_major_record_same_attitude():
    """The edge takes the arrays row-major: a column-major copy (as a MATLAB file gives) is the same attitude."""
    from mtcal.systems.attitude import attitude_record

    gyr, acc = _record()
    want = estimate_attitude(gyr, acc, DT_S, AttitudeConfig.real_data_study()).q_ws
    np.testing.assert_array_equal(estimate_attitude(np.asfortranarray(gyr), np.asfortranarray(acc), DT_S,
                                                    AttitudeConfig.real_data_study()).q_ws, want)
    np.testing.assert_array_equal(attitude_record(np.asfortranarray(gyr), np.asfortranarray(acc), DT_S,
                                                  AttitudeConfig.real_data_study()).q_ws, want)
