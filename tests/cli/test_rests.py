"""``mtcal rests --out`` = :func:`mtcal.systems.rests.find_rests` + :func:`~mtcal.systems.rests.rests_table`, bit for bit."""

import numpy as np
import pandas as pd
import pytest

from mtcal.systems import plausibility
from mtcal.systems.rests import RestsConfig, find_rests, rests_table

from .test_attitude import jittered  # noqa: F401 - the shared fixture
from .test_realistic_logs import _run


@pytest.mark.parametrize("extra,config", [
    ((), RestsConfig()),
    (("--accel-only",), RestsConfig(use_gyro=False)),
    (("--rest-detector", "shoe"), RestsConfig(detector="shoe")),
    (("--rest-detector", "paper", "--min-rest-s", "0.5"), RestsConfig(detector="paper", min_rest_s=0.5)),
])
def test_cli_rests_equals_system(extra, config, jittered, tmp_path, capsys):  # noqa: F811
    path, t, g, a = jittered
    code, out, err = _run(["rests", path, *extra, "--out", tmp_path / "rests.parquet"], capsys)
    assert code == 0, err
    dt = plausibility.time_base(t.size, time_s=t)[0]
    rep = find_rests(a, dt, config, gyro_rad_s=g, time_s=t)
    want = rests_table(t, a, rep, gyro_rad_s=g if config.use_gyro else None)
    got = pd.read_parquet(tmp_path / "rests.parquet")
    assert list(got.columns) == list(want) and len(got) == len(rep.rests)
    assert rep.rests or config.detector == "paper"      # BROAD's |a| at rest (9.89) is outside the paper's band
    for name, col in want.items():
        np.testing.assert_array_equal(got[name].to_numpy(), col, err_msg=name)
    assert f"rests: {len(rep.rests)} of >= {config.min_rest_s:g} s" in out
