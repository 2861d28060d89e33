"""``mtcal axis`` and ``mtcal angle``: wang2022sensors rotation-axis and EKF angle on a recorded log.

* ``mtcal axis LOG`` — rests (adaptive detector, or the paper's ZVD with
  ``--rest-detector paper``), rests at the same tilt merged into one position,
  and the axis v (``v_x ≥ 0``) as the normal of the plane through the
  positions (Eq 23 for exactly three). Refused, with the measured numbers,
  when fewer than three distinct tilts exist (e.g. a turn about the vertical),
  when the axis is nearly vertical, or when its uncertainty exceeds
  ``--max-axis-error-deg``. Prints ``axis v = x,y,z``, the uncertainty and a
  per-rest summary (time span, |a|, tilt, angle about v).
* ``mtcal angle LOG --axis vx,vy,vz`` — RAMS EKF angle per sample to
  ``--out`` (``time_s,angle_deg,is_static``, CSV or Parquet), 0 at the first
  rest, which gives ā0 and the gyro bias (its first ``--init-s`` seconds);
  a log that starts moving gets empty angles before that rest. Refused when the axis is nearly parallel to gravity, when the
  gyro turns about another axis than ``--axis``, or when the gyro's units or
  time base disagree with the accelerometer's tilt change between rests.

Each command parses its options into one config, reads the log, calls one system
(:func:`mtcal.systems.surface_angle.surface_axis_record` for both rest detectors,
:func:`~mtcal.systems.surface_angle.surface_angle_record`), prints and writes.
"""

from __future__ import annotations

import argparse

import numpy as np

from mtcal.cli import common, logio

AXIS_EXAMPLE = """prints: 'axis v = x,y,z' (unit, v_x >= 0), its 1-sigma uncertainty, one line per rest
example:
  mtcal axis hinge.csv --figure axis.png
  mtcal axis hinge.parquet --gyro-unit deg/s --accel-unit g --min-separation-deg 5"""

ANGLE_EXAMPLE = """output columns (--out, CSV or Parquet): time_s (s), angle_deg (deg, about --axis, 0 at the
  first rest; empty before it if the log starts moving), is_static (0/1, rest flag used by the EKF)
example:
  mtcal angle hinge.csv --axis 0.6,0,0.8 --out angle.csv --figure angle.png
  mtcal angle hinge.csv --axis -0.3,0.1,0.95 --time-unit ms --gyro-unit deg/s --out angle.parquet"""

def _parse_axis(text: str) -> np.ndarray:
    try:
        v = np.array([float(x) for x in str(text).split(",")])
    except ValueError:
        raise ValueError(f"--axis must be three numbers vx,vy,vz, got {text!r}") from None
    if v.size != 3 or not np.all(np.isfinite(v)) or np.linalg.norm(v) < 1e-9:
        raise ValueError(f"--axis must be three finite numbers, not all zero, got {text!r}")
    return v / np.linalg.norm(v)


def cmd_axis(args: argparse.Namespace) -> int:
    fig = common.DiagnosticsFigure(args.figure, f"mtcal axis {args.log}", inputs=[args.log])

    def body() -> int:
        from mtcal.systems import surface_angle  # numba/scipy: loaded when the command runs, not for --help
        from mtcal.systems.rests import RestsConfig

        limits = dict(min_separation_deg=common.finite_float(args.min_separation_deg, "--min-separation-deg"),
                      max_axis_error_deg=common.finite_float(args.max_axis_error_deg, "--max-axis-error-deg"),
                      max_elevation_deg=common.finite_float(args.max_elevation_deg, "--max-elevation-deg", high=90.0))
        log = logio.read_log(args.log, common.input_options(args), need="accel")
        fig.log = log
        paper = args.rest_detector == "paper"   # the paper's path (Table 1 ZVD, Algorithm A1): accelerometer only
        rests = (RestsConfig(detector="paper", min_rest_s=common.finite_float(args.min_rest_s, "--min-rest-s"),
                             use_gyro=False) if paper
                 else common.rests_config(args, has_gyro=log.gyro_rad_s is not None))
        config = surface_angle.AxisRecordConfig.cli(rests, **limits)
        try:
            found = surface_angle.surface_axis_record(log.accel_m_s2, config, fs_hz=log.fs_hz, time_s=log.time_s,
                                                      gyro_rad_s=log.gyro_rad_s, unit_stated=log.gyro_unit_stated)
        except ValueError as exc:  # what the refusal saw: its rests and units check, printed, then the error
            if getattr(exc, "rests", None) is not None:
                fig.report, fig.used = exc.rests, list(getattr(exc, "used", ()))
                _print_axis_rests(log, exc.rests, exc.units_check, paper)
            raise
        rep, est = found.rests, found.axis
        fig.report, fig.used = rep, list(found.used)
        _print_axis_rests(log, rep, found.units_check, paper)
        v, means, t = est.axis, est.rest_means_m_s2, log.time_s
        print(f"axis v = {v[0]:.6f},{v[1]:.6f},{v[2]:.6f}")
        if paper:
            for i, sl in enumerate(found.used):
                print(f"rest {i}: {t[sl.start]:.3f}-{t[sl.stop - 1]:.3f} s, mean accel "
                      f"[{means[i][0]:.5f}, {means[i][1]:.5f}, {means[i][2]:.5f}] m/s^2")
            return 0
        print(f"axis uncertainty +-{np.degrees(est.sigma_rad):.3f} deg (1 sigma), elevation "
              f"{np.degrees(est.elevation_rad):.2f} deg, from {est.positions_m_s2.shape[0]} distinct positions "
              f"of {len(rep.rests)} rests")
        ang = np.degrees(est.rest_angles_rad)
        for i, r in enumerate(rep.rests):
            print(f"rest {i}: {t[r.start]:.3f}-{t[r.stop - 1]:.3f} s, angle about v "
                  f"{ang[i]:+.3f} deg, mean accel [{means[i][0]:.5f}, {means[i][1]:.5f}, {means[i][2]:.5f}] m/s^2")
        return 0

    return common.run_with_figure(fig, body)


def _print_axis_rests(log, rep, units_check, paper: bool) -> None:
    """What ``mtcal axis`` prints of the rests: the paper ZVD's levels line, or the rest report and the units check."""
    if paper:
        print(rep.levels_text() + f" (measured |a| at rest {rep.extra['measured_gravity_m_s2']:.4f} m/s^2)")
        return
    common.print_report(log, rep)
    if units_check is not None:
        common.print_units_check(units_check)


def cmd_angle(args: argparse.Namespace) -> int:
    fig = common.DiagnosticsFigure(args.figure, f"mtcal angle {args.log}", inputs=[args.log])
    out = common.table_output(args, [args.log])

    def body() -> int:
        # numba/scipy: loaded when the command runs, not for --help
        from mtcal.systems.surface_angle import SurfaceRecordConfig, surface_angle_record

        v = _parse_axis(args.axis)
        init_s = 1.0 if args.init_s is None else common.finite_float(args.init_s, "--init-s")
        max_el = common.finite_float(args.max_elevation_deg, "--max-elevation-deg", high=90.0)
        max_mismatch = common.finite_float(args.max_axis_mismatch_deg, "--max-axis-mismatch-deg")
        log = logio.read_log(args.log, common.input_options(args), need="raw")
        fig.log = log
        if args.init_s is not None and init_s >= log.time_s[-1] - log.time_s[0]:   # a stated value: not clamped
            raise ValueError(f"--init-s {args.init_s} s is not shorter than the log "
                             f"({log.time_s[-1] - log.time_s[0]:.4g} s): the initial rest is part of the log")
        config = SurfaceRecordConfig(common.rests_config(args), init_s, max_el, max_mismatch)
        # computed first (one system call), printed and written after
        try:
            found = surface_angle_record(log.gyro_rad_s, log.accel_m_s2, v, config, fs_hz=log.fs_hz,
                                         time_s=log.time_s, unit_stated=log.gyro_unit_stated)
        except ValueError as exc:
            fig.report = getattr(exc, "rests", None)
            raise
        rep, res, t = found.rests, found.angle, log.time_s
        fig.report = rep
        if res.clipped.any():
            print(f"warning: gyro clipped at {np.degrees(res.clip_level_rad_s):.1f} deg/s in "
                  f"{int(res.clipped.sum())} samples; angles through those moves rely on the following rest")
        angle = np.degrees(res.angle_rad)
        if found.late:
            print(f"note: the log starts moving; angles are measured from the first rest at "
                  f"{t[res.start] - t[0]:.2f} s (angle 0 there, empty before)")
        fig.series = {"angle (deg)": angle}
        logio.write_table(out, {"time_s": t, "angle_deg": angle, "is_static": rep.is_static.astype(np.int8)})
        print("\n".join(common.report_lines(log, rep, angle_deg=angle,
                                            extra={"accel_angle_deg": np.degrees(found.rest_accel_angles_rad)})))
        if found.rest_mismatch is not None:
            i, off = found.rest_mismatch
            print(f"warning: at rest {i} the EKF angle differs from the accelerometer's by {np.degrees(off):.2f} deg "
                  f"(axis or accelerometer errors; check --axis)")
        print(common.units_check_line(res.unit_check))
        print(f"angle: {t.size} samples written to {out}; final angle {angle[-1]:.3f} deg")
        return 0

    return common.run_with_figure(fig, body)


__all__ = ["register", "cmd_axis", "cmd_angle"]


def _bullet(i: int) -> str:
    return __doc__.split("\n\n")[1].split("\n* ")[i].lstrip("* ")


def register(subparsers) -> None:
    """Add the ``axis`` and ``angle`` subcommands to the ``mtcal`` dispatcher."""
    p = subparsers.add_parser("axis", help="rotation axis from rests at three tilts (wang2022sensors Eq 23)",
                              description=_bullet(0) + "\n\n" + common.SCHEMA_HELP
                              + "\n(axis needs only the accelerometer columns)",
                              epilog=AXIS_EXAMPLE)
    p.add_argument("log", help=f"IMU log ({common.LOG_FORMATS})")
    p.add_argument("--min-separation-deg", default="3", help="rests closer in tilt are one position (deg)")
    p.add_argument("--max-axis-error-deg", default="2", help="refuse an axis less certain than this (deg, 1 sigma)")
    p.add_argument("--max-elevation-deg", default="85", help="refuse an axis steeper than this (deg)")
    common.add_input_options(p)
    common.add_rest_options(p, min_rest_s=0.5)
    p.set_defaults(func=cmd_axis)
    q = subparsers.add_parser("angle", help="EKF rotation angle about a known axis (wang2022sensors)",
                              description=_bullet(1) + "\n\n" + common.SCHEMA_HELP,
                              epilog=ANGLE_EXAMPLE)
    q.add_argument("log", help=f"IMU log ({common.LOG_FORMATS})")
    q.add_argument("--axis", required=True, help="axis vx,vy,vz in the sensor frame (from `mtcal axis`)")
    q.add_argument("--out", default="angle.csv", help="output table (.csv or .parquet)")
    q.add_argument("--init-s", default=None, help="initial rest used for a0 and the bias (s) (default: 1)")
    q.add_argument("--max-elevation-deg", default="85", help="refuse an axis steeper than this (deg)")
    q.add_argument("--max-axis-mismatch-deg", default="10",
                   help="refuse when the gyro turns about an axis this far from --axis (deg)")
    common.add_input_options(q)
    common.add_rest_options(q, min_rest_s=0.2)
    q.set_defaults(func=cmd_angle)
