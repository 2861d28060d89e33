"""s18: a log whose headers state no unit (--columns) and whose units no check can decide is refused with one
line asking for the unit, guessing none the evidence does not support (it said '(deg/s?)'); with the unit stated
it is accepted, one warning giving the evidence."""

import numpy as np
import pandas as pd

from mtcal import cli
from mtcal.systems import plausibility

COLUMNS = "time=t,gyro_x=GyrX,gyro_y=GyrY,gyro_z=GyrZ,accel_x=AccX,accel_y=AccY,accel_z=AccZ"


def _undecidable(tmp_path):
    """Rests at one tilt, then a gyro tilting while the accelerometer is shaken: no check decides."""
    rng = np.random.default_rng(0)
    n, dt = 4000, 0.01
    accel = np.tile([0.0, 0.0, 9.81], (n, 1)) + rng.normal(0, 0.02, (n, 3))
    gyro = rng.normal(0, 1e-3, (n, 3))
    gyro[1000:3000, 0] += 0.5 * np.sin(np.linspace(0, 6 * np.pi, 2000))
    accel[1000:3000] += rng.normal(0, 3.0, (2000, 3))
    assert plausibility.check_units(gyro, accel, dt, [], unit_stated="rad/s")["method"] == "stated unit (unchecked)"
    df = pd.DataFrame({"t": np.arange(n) * dt, "GyrX": gyro[:, 0], "GyrY": gyro[:, 1], "GyrZ": gyro[:, 2],
                       "AccX": accel[:, 0], "AccY": accel[:, 1], "AccZ": accel[:, 2]})
    path = tmp_path / "custom.csv"
    df.to_csv(path, index=False)
    return path


def test_custom_columns_undecided_unit_refused_without_a_guess(tmp_path, capsys):
    path = _undecidable(tmp_path)
    code = cli.main(["attitude", str(path), "--columns", COLUMNS, "--out", str(tmp_path / "a.csv")])
    out, err = capsys.readouterr()
    assert code == 2 and err.startswith("mtcal: error: cannot check the gyro units: state the unit with "
                                        "--gyro-unit (rad/s, the default, or deg/s)") and err.count("\n") == 1, err
    assert "(deg/s?)" not in err and not (tmp_path / "a.csv").exists()


def test_custom_columns_stated_unit_accepted_with_a_warning(tmp_path, capsys):
    path = _undecidable(tmp_path)
    code = cli.main(["attitude", str(path), "--columns", COLUMNS, "--gyro-unit", "rad/s",
                     "--out", str(tmp_path / "a.csv")])
    out, err = capsys.readouterr()
    assert code == 0 and err == "", err
    warn = [line for line in out.splitlines() if line.startswith("warning: gyro unit")]
    assert len(warn) == 1 and "not checked: no check decides (" in warn[0], out
    assert (tmp_path / "a.csv").exists()
