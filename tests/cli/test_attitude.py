"""``mtcal attitude`` = :func:`mtcal.systems.attitude.estimate_attitude` bit for bit (Parquet keeps float64).

The command only parses options, reads the log, calls the system and writes; the system is called here
on the same arrays as a library user would (no log reader), on a BROAD slice with a jittered time column
(so the per-sample-dt gyro weighting is exercised), for the paper's filter and a registry filter.
"""

import numpy as np
import pandas as pd
import pytest

from mtcal.core.arrayfile import read_arrays
from mtcal.systems import plausibility
from mtcal.systems.attitude import AttitudeConfig, estimate_attitude
from mtcal.systems.rests import RestsConfig

from .test_broad import TRIALS
from .test_realistic_logs import _run

COLS = [f"gyro_{c}_rad_s" for c in "xyz"] + [f"accel_{c}_m_s2" for c in "xyz"]


@pytest.fixture(scope="module")
def jittered(tmp_path_factory):
    """BROAD trial 01's first 30 s as a Parquet log with a jittered time column; (path, time, gyro, accel)."""
    arr = read_arrays(TRIALS[0])
    fs = float(arr["sampling_rate"])
    n = int(30 * fs)
    g, a = np.ascontiguousarray(arr["imu_gyr"][:n]), np.ascontiguousarray(arr["imu_acc"][:n])
    t = np.arange(n) / fs + 2e-4 / fs * np.sin(np.arange(n))      # jitter 2e-4 of a step: weights on
    path = tmp_path_factory.mktemp("att") / "log.parquet"
    pd.DataFrame({"time_s": t, **{c: v for c, v in zip(COLS, np.hstack([g, a]).T)}}).to_parquet(path)
    return path, t, g, a


def _system(t, g, a, config):
    dt, weights = plausibility.time_base(t.size, time_s=t)
    assert weights is not None      # the jitter is seen
    return estimate_attitude(g, a, dt, config, time_s=t, skip=plausibility.clipped_samples(g)[0],
                             unit_stated="header gyro_x_rad_s")


@pytest.mark.parametrize("name", ["qncf", "mahony"])
def test_cli_attitude_equals_system(name, jittered, tmp_path, capsys):
    path, t, g, a = jittered
    code, out, err = _run(["attitude", path, "--filter", name, "--out", tmp_path / "att.parquet"], capsys)
    assert code == 0, err
    df = pd.read_parquet(tmp_path / "att.parquet")
    res = _system(t, g, a, AttitudeConfig.cli_defaults(name))
    np.testing.assert_array_equal(df[["q0", "q1", "q2", "q3"]].to_numpy(), res.q_ws)
    np.testing.assert_array_equal(df["is_static"].to_numpy(), res.rests.is_static.astype(np.int8))
    assert f"gyro units check ({res.units_check['method']})" in out
    if name == "qncf":
        assert f"K_p {res.setup.params.kp_rad_s:.4g} /s" in out


def test_cli_paper_detector_equals_system(jittered, tmp_path, capsys):
    """``--rest-detector paper``: the QNCF as the paper states it (default gains, no initial bias)."""
    path, t, g, a = jittered
    code, out, err = _run(["attitude", path, "--rest-detector", "paper", "--out", tmp_path / "att.parquet"], capsys)
    assert code == 0, err
    res = _system(t, g, a, AttitudeConfig.paper())
    assert res.setup.levelled_from.startswith("first 100 samples") and not res.setup.bias_rad_s.any()
    np.testing.assert_array_equal(pd.read_parquet(tmp_path / "att.parquet")[["q0", "q1", "q2", "q3"]].to_numpy(),
                                  res.q_ws)


def test_cli_options_build_the_config(jittered, tmp_path, capsys):
    """Rest options reach the system's config: a stated gravity and noise factor change the result alike."""
    path, t, g, a = jittered
    code, out, err = _run(["attitude", path, "--gravity", "9.8", "--noise-factor", "4",
                           "--out", tmp_path / "att.parquet"], capsys)
    assert code == 0, err
    config = AttitudeConfig(rests=RestsConfig(min_rest_s=0.2, noise_factor=4.0, gravity_m_s2=9.8))
    res = _system(t, g, a, config)
    assert res.setup.params.gravity_m_s2 == 9.8
    np.testing.assert_array_equal(pd.read_parquet(tmp_path / "att.parquet")[["q0", "q1", "q2", "q3"]].to_numpy(),
                                  res.q_ws)


@pytest.mark.parametrize("trial", ["01_undisturbed_slow_rotation_A", "04_undisturbed_slow_rotation_with_breaks_A"])
def test_cli_attitude_equals_the_broad2021_study(trial, tmp_path, capsys):
    """``mtcal attitude TRIAL.mat`` (the shipped BROAD file as a user gives it) writes exactly the study's
    ``qncf_cli`` attitude (:func:`mtcal.studies.broad2021.runs.run_6d` on the study's loaded trial), bit for bit."""
    from mtcal.studies.broad2021 import runs, scenario

    tr = scenario.load_trials([trial])[0]
    path = next(p for p in TRIALS if p.stem == trial)
    code, out, err = _run(["attitude", path, "--out", tmp_path / "att.parquet"], capsys)
    assert code == 0, err
    df = pd.read_parquet(tmp_path / "att.parquet")
    study = runs.run_6d("qncf_cli", tr.gyro_rad_s, tr.accel_m_s2, tr.dt_s)
    np.testing.assert_array_equal(df[["q0", "q1", "q2", "q3"]].to_numpy(), study)
    assert len(df) == tr.n and "levelled from the first rest" in out


@pytest.mark.parametrize("name,package", [("vqf", "vqf"), ("basicvqf", "vqf"), ("madgwick", "ahrs"),
                                          ("fusion", "imufusion")])
def test_missing_optional_filter_names_the_bench_extra(jittered, tmp_path, monkeypatch, capsys, name, package):
    """--filter with its library missing: one line naming --filter, the package and the extra that installs it."""
    import sys

    monkeypatch.setitem(sys.modules, package, None)                # `import package` raises ImportError
    path = jittered[0]
    code, out, err = _run(["attitude", path, "--filter", name, "--out", tmp_path / "att.csv"], capsys)
    assert code == 2 and err.count("\n") == 1
    assert err.startswith(f"mtcal: error: --filter {name} needs the optional {package} package: "
                          f"pip install 'mtcal[bench]'")
    assert not (tmp_path / "att.csv").exists()
