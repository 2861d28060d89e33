"""s18: a correct rad/s log whose headers state no unit (--columns) and whose units no check can decide is
accepted in the documented default rad/s with one warning giving the evidence (it was refused with a '(deg/s?)'
hint the evidence did not support); a weak lean of the tilt rate is named in the warning, not hidden."""

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
    assert plausibility.check_units(gyro, accel, dt, [])["method"] == "default unit (unchecked)"
    df = pd.DataFrame({"t": np.arange(n) * dt, "GyrX": gyro[:, 0], "GyrY": gyro[:, 1], "GyrZ": gyro[:, 2],
                       "AccX": accel[:, 0], "AccY": accel[:, 1], "AccZ": accel[:, 2]})
    path = tmp_path / "custom.csv"
    df.to_csv(path, index=False)
    return path


def test_custom_columns_rad_s_accepted_with_a_warning(tmp_path, capsys):
    path = _undecidable(tmp_path)
    code = cli.main(["attitude", str(path), "--columns", COLUMNS, "--out", str(tmp_path / "a.csv")])
    out, err = capsys.readouterr()
    assert code == 0 and err == "", err
    warn = [line for line in out.splitlines() if line.startswith("warning: gyro unit")]
    assert len(warn) == 1, out
    assert warn[0].startswith("warning: gyro unit rad/s (the documented default; no unit stated) not checked: "
                              "no check decides ("), warn[0]
    assert "(deg/s?)" not in out
    assert (tmp_path / "a.csv").exists()
