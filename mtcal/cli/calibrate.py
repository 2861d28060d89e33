"""``mtcal calibrate LOG.csv --positions POS.csv`` — wang2023cja six-position calibration of a real log.

LOG.csv (comma-separated, header row, one row per sample, uniformly sampled)
-----------------------------------------------------------------------------
* ``time_s`` — sample time in s, strictly increasing (required);
* either the sensor attitude quaternion ``q0, q1, q2, q3`` (scalar-first,
  s-frame → world, e.g. the QNCF output of the logger),
* or raw inertial data ``gyro_x_rad_s, gyro_y_rad_s, gyro_z_rad_s`` (rad/s,
  mean rate over each sample interval) and ``accel_x_m_s2, accel_y_m_s2,
  accel_z_m_s2`` (m/s²), which are run through the QNCF first
  (:func:`mtcal.filters.qncf.qncf`, default gains, AMD Thr 0.3).
If both are present the quaternions are used. The attitude is zeroed at the
first sample ("initial attitude angles 0°", wang2023cja §4.1).

POS.csv (one row per calibration rest, in any order)
----------------------------------------------------
``yaw_deg, pitch_deg, roll_deg`` — the mechanism's reference angles (Eq 15;
wang2023cja Eq 8/9 convention: yaw about z, pitch about x, roll about y), at
least 3 rows (Eq 13), typically the six of §3.2.

Rests are detected from the data (gyro norm, or quaternion rate when only
quaternions are given), their middle halves averaged, matched to the
positions by nearest attitude, and Eq 13 is solved. Prints Q̂, the residual
per position and the before/after errors. Bad files (missing columns, NaN,
unsorted time, too few rests) raise ``ValueError`` with a one-line message;
the dispatcher prints ``mtcal: error: …`` and exits with status 2.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pandas as pd

from mtcal.methods import six_position as sixpos
from mtcal.filters.qncf import qncf

QUAT_COLS = ["q0", "q1", "q2", "q3"]
GYRO_COLS = ["gyro_x_rad_s", "gyro_y_rad_s", "gyro_z_rad_s"]
ACCEL_COLS = ["accel_x_m_s2", "accel_y_m_s2", "accel_z_m_s2"]
POS_COLS = ["yaw_deg", "pitch_deg", "roll_deg"]


def register(subparsers) -> None:
    """Add the ``calibrate`` subcommand to the ``mtcal`` dispatcher."""
    p = subparsers.add_parser("calibrate", help="six-position installation-error calibration (wang2023cja)",
                              description=__doc__.splitlines()[0])
    p.add_argument("log", type=Path, help="IMU log CSV (time_s + q0..q3 or gyro/accel columns)")
    p.add_argument("--positions", type=Path, required=True, help="reference positions CSV (yaw/pitch/roll deg)")
    p.add_argument("--fraction", type=float, default=0.5, help="middle fraction of each rest averaged")
    p.add_argument("--min-rest", type=float, default=2.0, help="shortest rest in s (default 2)")
    p.set_defaults(func=run)


def _read_csv(path: Path, what: str) -> pd.DataFrame:
    if not Path(path).is_file():
        raise FileNotFoundError(f"{what} file not found: {path}")
    try:
        df = pd.read_csv(path)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise ValueError(f"{what} {path}: not a readable CSV ({str(exc).splitlines()[0]})") from None
    df.columns = [str(c).strip() for c in df.columns]
    return df


def _numeric(df: pd.DataFrame, cols: list[str], path: Path) -> np.ndarray:
    arr = df[cols].apply(pd.to_numeric, errors="coerce").to_numpy(float)
    bad = ~np.isfinite(arr)
    if bad.any():
        row = int(np.argmax(bad.any(axis=1)))
        col = cols[int(np.argmax(bad[row]))]
        raise ValueError(f"{path}: non-numeric or NaN value in column {col!r} at data row {row + 1}")
    return arr


def load_log(path: Path) -> dict:
    """Read and check a log; returns time_s, fs_hz and q_ws or gyro/accel arrays."""
    df = _read_csv(path, "log")
    if "time_s" not in df.columns:
        raise ValueError(f"{path}: missing column 'time_s' (columns: {', '.join(df.columns)})")
    has_q = all(c in df.columns for c in QUAT_COLS)
    has_raw = all(c in df.columns for c in GYRO_COLS + ACCEL_COLS)
    if not (has_q or has_raw):
        missing = [c for c in QUAT_COLS if c not in df.columns]
        raise ValueError(f"{path}: missing columns {missing} (or the raw set {GYRO_COLS + ACCEL_COLS})")
    t = _numeric(df, ["time_s"], path)[:, 0]
    if t.size < 10:
        raise ValueError(f"{path}: only {t.size} samples")
    dt = np.diff(t)
    if np.any(dt <= 0):
        k = int(np.argmax(dt <= 0))
        raise ValueError(f"{path}: time_s is not strictly increasing at data row {k + 2} "
                         f"({t[k + 1]!r} after {t[k]!r}); sort the log by time")
    if np.max(np.abs(dt - dt.mean())) > 0.01 * dt.mean():
        raise ValueError(f"{path}: time_s is not uniformly sampled (dt between {dt.min():.6g} and {dt.max():.6g} s)")
    out = {"time_s": t, "fs_hz": 1.0 / float(dt.mean())}
    if has_q:
        q = _numeric(df, QUAT_COLS, path)
        norm = np.linalg.norm(q, axis=1)
        if np.any(np.abs(norm - 1.0) > 1e-3):
            raise ValueError(f"{path}: q0..q3 are not unit quaternions (|q| in [{norm.min():.4g}, {norm.max():.4g}])")
        out["q_ws"] = q / norm[:, None]
    if has_raw:
        out["gyro_rad_s"] = _numeric(df, GYRO_COLS, path)
        out["accel_m_s2"] = _numeric(df, ACCEL_COLS, path)
    return out


def load_positions(path: Path) -> np.ndarray:
    """Reference positions (K, 3) in rad from a CSV with yaw_deg, pitch_deg, roll_deg."""
    df = _read_csv(path, "positions")
    missing = [c for c in POS_COLS if c not in df.columns]
    if missing:
        raise ValueError(f"{path}: missing columns {missing}")
    ang = _numeric(df, POS_COLS, path)
    if ang.shape[0] < 3:
        raise ValueError(f"{path}: need at least 3 positions (Eq 13), got {ang.shape[0]}")
    return np.radians(ang)


def calibrate_log(log: dict, positions_rad: np.ndarray, *, fraction: float = 0.5,
                  min_rest_s: float = 2.0) -> sixpos.SixPositionResult:
    """Run the §3.2 procedure on a loaded log (QNCF first when only raw data is given)."""
    fs = log["fs_hz"]
    gyro = log.get("gyro_rad_s")
    if "q_ws" in log:
        q = log["q_ws"]
    else:
        q = qncf(gyro, log["accel_m_s2"], 1.0 / fs, return_euler=False).q_ws
    from mtcal.core.rotations import hamilton, quat_conjugate
    q = hamilton(quat_conjugate(q[0])[None, :], q)  # zero the start (§4.1)
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    return sixpos.calibrate(q, positions_rad, fs, gyro_rad_s=gyro, fraction=fraction, min_rest_s=min_rest_s)


def run(args: argparse.Namespace) -> int:
    """Entry point of ``mtcal calibrate``."""
    log = load_log(args.log)
    pos = load_positions(args.positions)
    res = calibrate_log(log, pos, fraction=args.fraction, min_rest_s=args.min_rest)
    print(f"log: {args.log} ({log['time_s'].size} samples at {log['fs_hz']:.1f} Hz); "
          f"{len(res.rests)} rests found, {pos.shape[0]} positions")
    print("Q_hat (Eq 13, q_body = Q_hat q_sensor):")
    for row in res.q_matrix:
        print("  " + "  ".join(f"{v:+.6f}" for v in row))
    print(f"{'pos':>3} {'ref yaw/pitch/roll (deg)':>27} {'before error (deg)':>27} "
          f"{'after error (deg)':>27} {'residual':>9}")
    ref_deg = np.degrees(pos)
    for k in range(pos.shape[0]):
        b = np.degrees(res.euler_before_rad[k]) - ref_deg[k]
        a = np.degrees(res.euler_after_rad[k]) - ref_deg[k]
        b, a = (b + 180) % 360 - 180, (a + 180) % 360 - 180
        fmt = lambda v: " ".join(f"{x:+8.4f}" for x in v)  # noqa: E731
        print(f"{k + 1:>3} {fmt(ref_deg[k]):>27} {fmt(b):>27} {fmt(a):>27} "
              f"{np.degrees(res.residual_rad[k]):9.5f}")
    print(f"max |error| before {np.max(np.abs(((np.degrees(res.euler_before_rad) - ref_deg) + 180) % 360 - 180)):.4f} deg, "
          f"after {np.max(np.abs(((np.degrees(res.euler_after_rad) - ref_deg) + 180) % 360 - 180)):.4f} deg")
    return 0
