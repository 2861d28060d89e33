"""Filter registry: one registration makes a filter available to the anchors, the sweep and the bake-off."""

import numpy as np
import pytest

from mtcal.filters import registry
from mtcal.filters.anchors import run_attitude_filter, run_axis_angle_filter
from mtcal.filters.registry import (AxisContext, filter_names, get_filter, register_filter, require_filter,
                                    unregister_filter)
from mtcal.sweep import bakeoff
from mtcal.sweep.evaluators import filter_gain, get_evaluator

G = 9.80665


def _hold(gyro_rad_s, accel_m_s2, dt_s, gain, q0):
    """An attitude 'filter' that keeps its initial attitude."""
    return np.broadcast_to(q0[:, None, :], gyro_rad_s.shape[:2] + (4,)).copy()


def _zero_angle(gyro_rad_s, accel_m_s2, dt_s, gain, context):
    return np.zeros(gyro_rad_s.shape[:2])


@pytest.fixture
def hold_filter():
    register_filter("hold", _hold, output="attitude", default_gain=0.7, gain_unit="none (1)", origin="ours",
                    description="test filter")
    yield "hold"
    unregister_filter("hold")


@pytest.fixture
def zero_angle_filter():
    register_filter("zero", _zero_angle, output="angle", default_gain=1.5, gain_unit="none (1)", origin="ours")
    yield "zero"
    unregister_filter("zero")


def test_builtins_registered_with_origin_and_output():
    assert filter_names(output="attitude") == ["qncf", "mahony", "madgwick", "vqf", "fusion"]
    assert filter_names(output="angle") == ["rams_ekf"]
    assert set(filter_names(origin="anchor")) == {"madgwick", "vqf", "fusion"}
    assert get_filter("rams_ekf").default_gain == 2.0
    assert get_filter("vqf").requires == "vqf" and get_filter("qncf").requires is None
    assert require_filter("qncf") is None


def test_registering_a_filter_makes_it_available_to_anchors_sweep_and_bakeoff(hold_filter):
    acc = np.tile([0.0, 0.0, G], (2, 20, 1))
    q = run_attitude_filter(hold_filter, np.zeros((2, 20, 3)), acc, 0.01)
    assert q.shape == (2, 20, 4) and np.allclose(q, [1.0, 0, 0, 0])
    # sweep: the attitude and surface evaluators accept it and its gain key
    att = get_evaluator("attitude").resolve({"filters": [hold_filter, "qncf"], "gain_hold": 2.0})
    assert att["gain_hold"] == 2.0 and filter_gain(att, hold_filter) == 2.0
    assert filter_gain({}, hold_filter) == 0.7
    assert "hold.tilt_rmse_deg" in get_evaluator("attitude").metrics(att)
    get_evaluator("surface").resolve({"filters": [hold_filter]})
    # bake-off: a valid choice, carried into every family's sweep
    p = bakeoff.bakeoff_params(filters=[hold_filter])
    spec = bakeoff.family_specs(p, "turntable", seed=1, trials=2, gains={"hold": 0.5})
    assert spec.fixed["filters"] == [hold_filter] and spec.fixed["gain_hold"] == 0.5
    get_evaluator(spec.evaluator).resolve({**spec.fixed, "motion": "aoa", "grade": "industrial"})


def test_angle_filters_join_the_surface_family_without_special_casing(zero_angle_filter):
    p = bakeoff.bakeoff_params(filters=["qncf"])
    spec = bakeoff.family_specs(p, "surface", seed=1, trials=2)
    assert spec.fixed["filters"] == ["qncf", "rams_ekf", "zero"]
    assert bakeoff.family_specs(p, "turntable", seed=1, trials=2).fixed["filters"] == ["qncf"]
    with pytest.raises(ValueError, match="filters must be a non-empty list"):
        bakeoff.bakeoff_params(filters=["zero"])      # an angle filter is not an attitude filter
    with pytest.raises(ValueError, match="filters must be a non-empty list"):
        get_evaluator("attitude").resolve({"filters": ["zero"]})


def test_surface_evaluator_runs_a_registered_angle_filter(zero_angle_filter):
    ev = get_evaluator("surface")
    p = ev.resolve({"filters": ["zero", "rams_ekf"], "fs_hz": 50.0, "span_deg": 30.0, "step_deg": 30.0,
                    "hold_s": 0.5, "vibration_hz": 10.0})
    out = ev(p, [np.random.default_rng(0)])
    assert out["zero.angle_rmse_deg"].shape == (1,) and out["zero.angle_rmse_deg"][0] > 1.0
    assert out["rams_ekf.angle_rmse_deg"][0] < out["zero.angle_rmse_deg"][0]


def test_axis_angle_of_an_attitude_filter_is_its_twist(hold_filter):
    acc = np.tile([0.0, 0.0, G], (1, 10, 1))
    ctx = AxisContext(np.array([0.0, 1.0, 0.0]), np.ones((1, 10), bool), acc[:, 0], 1e-4, 1e-3)
    th = run_axis_angle_filter(hold_filter, np.zeros((1, 10, 3)), acc, 0.01, None, ctx)
    assert th.shape == (1, 10) and np.allclose(th, 0.0)


def test_register_errors():
    with pytest.raises(ValueError, match="already registered"):
        register_filter("qncf", _hold, output="attitude", default_gain=1.0, gain_unit="", origin="ours")
    with pytest.raises(ValueError, match="output must be one of"):
        register_filter("x", _hold, output="euler", default_gain=1.0, gain_unit="", origin="ours")
    with pytest.raises(ValueError, match="origin must be one of"):
        register_filter("x", _hold, output="attitude", default_gain=1.0, gain_unit="", origin="theirs")
    with pytest.raises(ValueError, match="default_gain must be"):
        register_filter("x", _hold, output="attitude", default_gain=0.0, gain_unit="", origin="ours")
    with pytest.raises(ValueError, match="non-empty str"):
        register_filter("a.b", _hold, output="attitude", default_gain=1.0, gain_unit="", origin="ours")
    with pytest.raises(TypeError, match="run must be callable"):
        register_filter("x", None, output="attitude", default_gain=1.0, gain_unit="", origin="ours")
    with pytest.raises(TypeError, match="reference must be callable or None, got str"):
        register_filter("x", _hold, output="attitude", default_gain=1.0, gain_unit="", origin="anchor",
                        reference="ahrs")
    assert "x" not in filter_names()
    with pytest.raises(ValueError, match="filter must be one of"):
        get_filter("nope")
    with pytest.raises(ValueError, match="filter must be one of"):
        unregister_filter("nope")
    with pytest.raises(ValueError, match="output must be one of"):
        filter_names(output="euler")
    with pytest.raises(ValueError, match="origin must be one of"):
        filter_names(origin="theirs")
    with pytest.raises(ValueError, match="returns an angle"):
        run_attitude_filter("rams_ekf", np.zeros((1, 5, 3)), np.ones((1, 5, 3)), 0.01)
    assert "x" not in registry.filter_names()


def test_every_filter_is_declared_once_and_listing_imports_none_of_them():
    """The declaration (registry.BUILTIN_FILTERS) names runners by module and function: no module registers
    by being imported, and listing or describing filters imports neither the anchors nor the systems."""
    import subprocess
    import sys

    assert [e.name for e in registry.BUILTIN_FILTERS] == filter_names()
    for entry in registry.BUILTIN_FILTERS:
        assert isinstance(entry.run, registry.Deferred) and callable(entry.run.resolve())
        assert entry.reference is None or callable(entry.reference.resolve())
    assert bakeoff.BAKEOFF_DEFAULTS["filters"] == registry.builtin_filter_names(output="attitude")
    code = ("import sys; from mtcal.filters.registry import filter_names, get_filter; "
            "names = filter_names(); units = [get_filter(n).gain_unit for n in names]; "
            "print(names, sorted(m for m in sys.modules if m in ('mtcal.filters.anchors', 'mtcal.systems.surface_angle')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "['qncf', 'mahony', 'madgwick', 'vqf', 'fusion', 'rams_ekf'] []"


def test_builtin_names_ignore_what_a_session_registered(hold_filter):
    assert hold_filter in filter_names(output="attitude")
    assert hold_filter not in registry.builtin_filter_names(output="attitude")
    with pytest.raises(ValueError, match="output must be one of"):
        registry.builtin_filter_names(output="euler")
