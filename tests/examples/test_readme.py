"""The README's command-line block runs as written (issue #36): every ``mtcal`` command of the
"Command line" section, on generated logs with the file names, units and options it shows.

Logs: foot/walk/hinge records from :mod:`tests.cli.logs` (mtcal's simulator, with real-sensor
quirks; the hinge record also as ``rec.h5`` arrays), turntable and flight logs from
:mod:`tests.cli.numpy_logs` (a plain numpy script), and the shipped BROAD trials (``datasets/``).
"""

import re
import shlex
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from mtcal import cli
from tests.cli import logs, numpy_logs as nl

README = Path(__file__).resolve().parents[2] / "README.md"
G = 9.80665


def readme_cli_block() -> list[str]:
    """The ``mtcal`` command lines of the README's sh block that starts with ``mtcal rests walk.csv``."""
    blocks = re.findall(r"```sh\n(.*?)```", README.read_text(encoding="utf-8"), flags=re.S)
    block = next(b for b in blocks if b.startswith("mtcal rests walk.csv"))
    lines = []
    for line in block.splitlines():
        code = line.split("  #")[0].strip()
        lines += [part.strip() for part in code.split("&&") if part.strip()]
    return lines


def _write_logs(d: Path) -> None:
    walk = logs.walking_log()[0]
    walk.to_csv(d / "foot.csv", index=False)
    wdf = walk.copy()                      # the same walk logged in deg/s and g
    for c in wdf.columns:
        if c.startswith("gyro_"):
            wdf[c] = np.degrees(wdf[c])
        elif c.startswith("accel_"):
            wdf[c] = wdf[c] / G
    wdf.to_csv(d / "walk.csv", index=False)
    logs.hinge_log(axis=(-0.3, 0.1, 0.95)).write(d / "hinge.csv")
    raw = logs.hinge_log().df.copy()       # counts: 0.061 deg/s and 0.000244 g per LSB
    for c in raw.columns:
        if c.startswith("gyro_"):
            raw[c] = np.round(np.degrees(raw[c]) / 0.061).astype(np.int64)
        elif c.startswith("accel_"):
            raw[c] = np.round(raw[c] / G / 0.000244).astype(np.int64)
    raw.to_csv(d / "raw.csv", index=False)
    tt, pos = nl.turntable_log()
    tt.write(d / "turntable.csv")
    tt.write(d / "turntable_check.csv")
    pos.to_csv(d / "pos.csv", index=False)
    nl.flight_log().write(d / "flight.csv")
    pm_g = ((0, 0, 0), (0, 0, 180), (0, 90, 0), (0, -90, 0), (0, 0, 90), (0, 0, -90))
    wp = [(0, 0, 0)] + [p for q in pm_g[1:] for p in (q, (0, 0, 0))]
    nl.imu_log(nl.waypoint_path(wp, hold_s=3.0, move_s=3.0), seed=11).write(d / "pm_g.csv")
    pd.DataFrame(pm_g, columns=["yaw_deg", "pitch_deg", "roll_deg"]).to_csv(d / "pm_g_pos.csv", index=False)
    (d / "datasets").symlink_to(README.parent / "datasets")      # the shipped BROAD trials
    import h5py

    hinge = logs.hinge_log().df                                  # an HDF5 log with its own array names
    with h5py.File(d / "rec.h5", "w") as f:
        f["t"] = hinge["time_s"].to_numpy()
        f["gyr"] = hinge[[f"gyro_{a}_rad_s" for a in "xyz"]].to_numpy()
        f["acc"] = hinge[[f"accel_{a}_m_s2" for a in "xyz"]].to_numpy()


def test_readme_block_is_found():
    lines = readme_cli_block()
    assert len(lines) >= 8 and all(ln.startswith("mtcal ") for ln in lines)


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    d = tmp_path_factory.mktemp("readme")
    _write_logs(d)
    return d


@pytest.mark.parametrize("line", readme_cli_block())
def test_readme_command_runs(folder, monkeypatch, capsys, line):
    monkeypatch.chdir(folder)
    argv = shlex.split(line)[1:]
    code = cli.main(argv)
    assert code == 0, capsys.readouterr().err
