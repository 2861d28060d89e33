"""``mtcal axis`` and ``mtcal angle``: wang2022sensors RAMS methods on a recorded IMU log.

CSV schema (header row required, one row per sample, uniform sampling)::

    time_s,gyro_x_rad_s,gyro_y_rad_s,gyro_z_rad_s,accel_x_m_s2,accel_y_m_s2,accel_z_m_s2

``time_s`` strictly increasing (s); gyro in rad/s; accelerometer specific force
in m/s² (a level sensor at rest reads about +9.81 on z). Extra columns are
ignored. ``mtcal axis`` needs only the accelerometer columns.

* ``mtcal axis LOG.csv [--figure PATH]`` — ZVD (Table 1) + Algorithm A1:
  prints the axis v (v_x ≥ 0), the rests used, and optionally saves a quality
  figure (‖a‖ with the ZVD flags and the rests).
* ``mtcal angle LOG.csv --axis vx,vy,vz [--out PATH] [--init-s S]`` — EKF
  angle (deg) per sample to a CSV ``time_s,angle_deg,is_static``; the first
  ``--init-s`` seconds must be at rest (ā0 and the gyro bias).

Bad files (missing columns, NaN, unsorted time, fewer than three rests) raise
``ValueError`` with a one-line message; the dispatcher prints
``mtcal: error: …`` and exits with status 2.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

GYRO_COLS = ["gyro_x_rad_s", "gyro_y_rad_s", "gyro_z_rad_s"]
ACCEL_COLS = ["accel_x_m_s2", "accel_y_m_s2", "accel_z_m_s2"]


def read_log(path: str, need_gyro: bool = True) -> tuple[np.ndarray, np.ndarray | None, np.ndarray, float]:
    """Read and check a log; return time (s), gyro (rad/s) or None, accel (m/s²), fs (Hz)."""
    import pandas as pd

    p = Path(path)
    if not p.is_file():
        raise FileNotFoundError(f"log file not found: {path}")
    try:
        df = pd.read_csv(p)
    except Exception as exc:  # parser errors of any kind become one line
        raise ValueError(f"{path}: not a readable CSV ({type(exc).__name__})") from None
    need = ["time_s"] + (GYRO_COLS if need_gyro else []) + ACCEL_COLS
    missing = [c for c in need if c not in df.columns]
    if missing:
        raise ValueError(f"{path}: missing column(s) {', '.join(missing)}")
    data = df[need].apply(pd.to_numeric, errors="coerce").to_numpy(float)
    bad = ~np.isfinite(data)
    if bad.any():
        row, col = np.argwhere(bad)[0]
        raise ValueError(f"{path}: non-numeric or NaN value in column {need[col]} at data row {row + 1}")
    t = data[:, 0]
    if t.size < 3:
        raise ValueError(f"{path}: needs at least 3 samples, got {t.size}")
    dt = np.diff(t)
    if np.any(dt <= 0):
        k = int(np.argmax(dt <= 0))
        raise ValueError(f"{path}: time_s is not strictly increasing at data row {k + 2}")
    if np.max(np.abs(dt - dt.mean())) > 0.05 * dt.mean():
        raise ValueError(f"{path}: time_s is not uniformly sampled (dt from {dt.min():.6g} to {dt.max():.6g} s)")
    gyro = data[:, 1:4] if need_gyro else None
    accel = data[:, -3:]
    return t, gyro, accel, 1.0 / float(dt.mean())


def _parse_axis(text: str) -> np.ndarray:
    try:
        v = np.array([float(x) for x in text.split(",")])
    except ValueError:
        raise ValueError(f"--axis must be three numbers vx,vy,vz, got {text!r}") from None
    if v.size != 3 or not np.all(np.isfinite(v)) or np.linalg.norm(v) < 1e-9:
        raise ValueError(f"--axis must be three finite numbers, not all zero, got {text!r}")
    return v / np.linalg.norm(v)


def cmd_axis(args: argparse.Namespace) -> int:
    from mtcal.methods.rotation_axis import estimate_axis

    t, _, accel, fs = read_log(args.log, need_gyro=False)
    res = estimate_axis(accel, fs, min_rest_s=args.min_rest_s)
    print(f"axis v = {res.v[0]:.6f},{res.v[1]:.6f},{res.v[2]:.6f}")
    for i, sl in enumerate(res.rests):
        print(f"rest {i}: {t[sl.start]:.3f}-{t[sl.stop - 1]:.3f} s, mean accel "
              f"[{res.means[i][0]:.5f}, {res.means[i][1]:.5f}, {res.means[i][2]:.5f}] m/s^2")
    if args.figure:
        _quality_figure(t, accel, res, args.figure)
        print(f"figure: {args.figure}")
    return 0


def _quality_figure(t, accel, res, path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 3.5))
    ax.plot(t, np.linalg.norm(accel, axis=1), lw=0.6, label="|a|")
    ymin, ymax = ax.get_ylim()
    ax.fill_between(t, ymin, ymax, where=res.is_static, color="tab:green", alpha=0.15, label="ZVD static")
    for sl in res.rests:
        ax.axvspan(t[sl.start], t[sl.stop - 1], color="tab:orange", alpha=0.3)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("|a| (m/s²)")
    ax.set_title("mtcal axis: ZVD and the three rests used (orange)")
    ax.legend(loc="upper right")
    fig.savefig(path, bbox_inches="tight", metadata={"Software": None})
    plt.close(fig)


def cmd_angle(args: argparse.Namespace) -> int:
    import pandas as pd

    from mtcal.filters.rams_ekf import RamsEkfParams, initial_state, run_rams_ekf
    from mtcal.methods.zero_velocity import detect_static

    v = _parse_axis(args.axis)
    t, gyro, accel, fs = read_log(args.log)
    n0 = int(round(args.init_s * fs))
    if n0 < 1 or n0 >= t.size:
        raise ValueError(f"--init-s {args.init_s:g} s must cover at least one sample and leave data")
    st = detect_static(accel, fs)
    if not st[min(n0, st.size - 1) // 2:n0].any():
        raise ValueError(f"the first {args.init_s:g} s are not at rest by ZVD; record a rest first")
    a0, b0 = initial_state(gyro, accel, n0)
    sig_a = max(float(np.std(accel[:n0], axis=0).mean()), 1e-4)
    sig_w = max(float(np.std(gyro[:n0], axis=0).mean()), 1e-5)
    params = RamsEkfParams(sigma_theta_rad_s=sig_w, sigma_b_rad_s2=1e-4, sigma_a_static_m_s2=sig_a,
                           sigma_a_moving_m_s2=5.0, p0_theta_rad2=1e-8, p0_bias_rad2_s2=1e-8)
    res = run_rams_ekf(gyro, accel, st, v, a0, 1.0 / fs, params, bias0_rad_s=b0, keep_innovation=False)
    out = pd.DataFrame({"time_s": t, "angle_deg": np.degrees(res.theta_rad[0]), "is_static": st.astype(int)})
    out.to_csv(args.out, index=False, float_format="%.6f")
    print(f"angle: {t.size} samples written to {args.out}")
    return 0


__all__ = ["register"]


def register(subparsers) -> None:
    """Add the ``axis`` and ``angle`` subcommands to the ``mtcal`` dispatcher."""
    p = subparsers.add_parser("axis", help="rotation axis from three rests (wang2022sensors Algorithm A1)",
                              description=__doc__.split("\n\n")[0])
    p.add_argument("log", help="CSV log (schema: time_s, gyro_*_rad_s, accel_*_m_s2)")
    p.add_argument("--figure", help="save a ZVD/rest quality figure (PNG) here")
    p.add_argument("--min-rest-s", type=float, default=0.5, help="shortest rest counted (s)")
    p.set_defaults(func=cmd_axis)
    q = subparsers.add_parser("angle", help="EKF rotation angle about a known axis (wang2022sensors)")
    q.add_argument("log", help="CSV log (schema: time_s, gyro_*_rad_s, accel_*_m_s2)")
    q.add_argument("--axis", required=True, help="unit axis vx,vy,vz (from `mtcal axis`)")
    q.add_argument("--out", default="angle.csv", help="output CSV (time_s, angle_deg, is_static)")
    q.add_argument("--init-s", type=float, default=1.0, help="initial rest used for a0 and bias (s)")
    q.set_defaults(func=cmd_angle)
