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
"""

from __future__ import annotations

import argparse

import numpy as np

from mtcal.cli import common, logio
from mtcal.systems import plausibility

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

        limits = dict(min_separation_deg=common.finite_float(args.min_separation_deg, "--min-separation-deg"),
                      max_axis_error_deg=common.finite_float(args.max_axis_error_deg, "--max-axis-error-deg"),
                      max_elevation_deg=common.finite_float(args.max_elevation_deg, "--max-elevation-deg"))
        log = logio.read_log(args.log, common.input_options(args), need="accel")
        fig.log = log
        if args.rest_detector == "paper":
            return _axis_paper(args, log, fig, limits)
        rep = common.detect(args, log, use_gyro=log.gyro_rad_s is not None)
        fig.report = rep
        common.print_report(log, rep)
        if log.gyro_rad_s is not None:  # the rests used gyro: its units and the time base must fit
            chk = plausibility.check_units(log.gyro_for_filter(), log.accel_m_s2, log.dt_mean_s, rep.rests,
                                           time_s=log.time_s, skip=plausibility.clipped_samples(log.gyro_rad_s)[0],
                                           unit_stated=log.gyro_unit_stated)
            common.print_units_check(chk)
        if len(rep.rests) == 0:
            raise ValueError(f"found only 0 rests of >= {rep.min_rest_s:g} s ({rep.levels_text()}); "
                             f"the axis needs rests at three distinct tilts")
        config = surface_angle.AxisConfig.cli(rep.accel_noise_m_s2, rep.window_s * log.fs_hz, **limits)
        est = surface_angle.estimate_surface_axis(log.accel_m_s2, rep.rests, config)
        fig.used = [rep.rests[m[0]] for m in est.members]
        v, means = est.axis, est.rest_means_m_s2
        print(f"axis v = {v[0]:.6f},{v[1]:.6f},{v[2]:.6f}")
        print(f"axis uncertainty +-{np.degrees(est.sigma_rad):.3f} deg (1 sigma), elevation "
              f"{np.degrees(est.elevation_rad):.2f} deg, from {est.positions_m_s2.shape[0]} distinct positions "
              f"of {len(rep.rests)} rests")
        ang = np.degrees(est.rest_angles_rad)
        for i, r in enumerate(rep.rests):
            print(f"rest {i}: {log.time_s[r.start]:.3f}-{log.time_s[r.stop - 1]:.3f} s, angle about v "
                  f"{ang[i]:+.3f} deg, mean accel [{means[i][0]:.5f}, {means[i][1]:.5f}, {means[i][2]:.5f}] m/s^2")
        return 0

    return common.run_with_figure(fig, body)


def _axis_paper(args, log, fig, limits: dict) -> int:
    """The paper's path: Table 1 ZVD + Algorithm A1 (first three distinct rests); ``limits``: the parsed
    ``--min-separation-deg``, ``--max-axis-error-deg``, ``--max-elevation-deg``."""
    from mtcal.methods.rest_detection import paper_rest_report
    from mtcal.methods.rotation_axis import estimate_axis
    from mtcal.systems import surface_angle

    min_rest = common.finite_float(args.min_rest_s, "--min-rest-s")
    rep = paper_rest_report(log.accel_m_s2, 1.0 / log.fs_hz, min_rest_s=min_rest)
    fig.report = rep
    print(rep.levels_text() + f" (measured |a| at rest {rep.extra['measured_gravity_m_s2']:.4f} m/s^2)")
    try:
        res = estimate_axis(log.accel_m_s2, 1.0 / log.fs_hz, min_rest_s=min_rest, is_static=rep.is_static,
                            min_separation_deg=limits["min_separation_deg"],
                            max_elevation_deg=limits["max_elevation_deg"])
    except ValueError as exc:
        raise ValueError(f"{exc} [paper ZVD band {rep.band_m_s2[0]:g}-{rep.band_m_s2[1]:g} m/s^2, measured |a| "
                         f"at rest {rep.extra['measured_gravity_m_s2']:.4f} m/s^2; --rest-detector adaptive "
                         f"measures the band from the data]") from None
    fig.used = list(res.rests)
    surface_angle.axis_uncertainty(res.means, np.array([r.stop - r.start for r in res.rests], float),
                                   accel_noise_m_s2=rep.accel_noise_m_s2, window_samples=rep.window_s * log.fs_hz,
                                   max_axis_error_deg=limits["max_axis_error_deg"])
    print(f"axis v = {res.v[0]:.6f},{res.v[1]:.6f},{res.v[2]:.6f}")
    t = log.time_s
    for i, sl in enumerate(res.rests):
        print(f"rest {i}: {t[sl.start]:.3f}-{t[sl.stop - 1]:.3f} s, mean accel "
              f"[{res.means[i][0]:.5f}, {res.means[i][1]:.5f}, {res.means[i][2]:.5f}] m/s^2")
    return 0


def cmd_angle(args: argparse.Namespace) -> int:
    fig = common.DiagnosticsFigure(args.figure, f"mtcal angle {args.log}", inputs=[args.log])
    out = logio.check_output_path(args.out, [args.log])

    def body() -> int:
        # numba/scipy: loaded when the command runs, not for --help
        from mtcal.systems.surface_angle import SurfaceRecordConfig, surface_angle_record

        v = _parse_axis(args.axis)
        init_s = common.finite_float(args.init_s, "--init-s")
        max_el = common.finite_float(args.max_elevation_deg, "--max-elevation-deg")
        max_mismatch = common.finite_float(args.max_axis_mismatch_deg, "--max-axis-mismatch-deg")
        log = logio.read_log(args.log, common.input_options(args), need="raw")
        fig.log = log
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
        acc_ang = np.degrees(found.rest_accel_angles_rad)  # each rest's tilt angle
        if res.clipped.any():
            print(f"warning: gyro clipped at {np.degrees(res.clip_level_rad_s):.1f} deg/s in "
                  f"{int(res.clipped.sum())} samples; angles through those moves rely on the following rest")
        check, k0 = res.unit_check, res.start
        elev = float(np.degrees(res.elevation_rad))
        angle = np.degrees(res.angle_rad)
        if found.late:
            print(f"note: the log starts moving; angles are measured from the first rest at "
                  f"{t[k0] - t[0]:.2f} s (angle 0 there, empty before)")
        fig.series = {"angle (deg)": angle}
        logio.write_table(out, {"time_s": t, "angle_deg": angle, "is_static": rep.is_static.astype(np.int8)})
        ekf_ang = np.array([np.nanmedian(angle[r]) if np.isfinite(angle[r]).any() else np.nan for r in rep.rests])
        acc_ang = acc_ang + 360.0 * np.round((ekf_ang - acc_ang) / 360.0)  # same turn as the EKF
        units_line = common.units_check_line(check)
        print("\n".join(common.report_lines(log, rep, angle_deg=angle, extra={"accel_angle_deg": acc_ang})))
        off = np.abs(ekf_ang - acc_ang)
        if np.nanmax(off, initial=0.0) > 2.0 and np.cos(np.radians(elev)) > 0.2:
            i = int(np.nanargmax(off))
            print(f"warning: at rest {i} the EKF angle differs from the accelerometer's by {off[i]:.2f} deg "
                  f"(axis or accelerometer errors; check --axis)")
        print(units_line)
        print(f"angle: {t.size} samples written to {out}; final angle {angle[-1]:.3f} deg")
        return 0

    return common.run_with_figure(fig, body)


__all__ = ["register", "cmd_axis", "cmd_angle"]


def _bullet(i: int) -> str:
    return __doc__.split("\n\n")[1].split("\n* ")[i].lstrip("* ")


def register(subparsers) -> None:
    """Add the ``axis`` and ``angle`` subcommands to the ``mtcal`` dispatcher."""
    fmt = argparse.RawDescriptionHelpFormatter
    p = subparsers.add_parser("axis", help="rotation axis from rests at three tilts (wang2022sensors Eq 23)",
                              description=_bullet(0) + "\n\n" + common.SCHEMA_HELP
                              + "\n(axis needs only the accelerometer columns)",
                              epilog=AXIS_EXAMPLE, formatter_class=fmt)
    p.add_argument("log", help="IMU log (CSV, Parquet, .mat or .h5)")
    p.add_argument("--min-separation-deg", default="3", help="rests closer in tilt are one position (deg)")
    p.add_argument("--max-axis-error-deg", default="2", help="refuse an axis less certain than this (deg, 1 sigma)")
    p.add_argument("--max-elevation-deg", default="85", help="refuse an axis steeper than this (deg)")
    common.add_input_options(p)
    common.add_rest_options(p, min_rest_s=0.5)
    p.set_defaults(func=cmd_axis)
    q = subparsers.add_parser("angle", help="EKF rotation angle about a known axis (wang2022sensors)",
                              description=_bullet(1) + "\n\n" + common.SCHEMA_HELP,
                              epilog=ANGLE_EXAMPLE, formatter_class=fmt)
    q.add_argument("log", help="IMU log (CSV, Parquet, .mat or .h5)")
    q.add_argument("--axis", required=True, help="axis vx,vy,vz in the sensor frame (from `mtcal axis`)")
    q.add_argument("--out", default="angle.csv", help="output table (.csv or .parquet)")
    q.add_argument("--init-s", default="1.0", help="initial rest used for a0 and the bias (s)")
    q.add_argument("--max-elevation-deg", default="85", help="refuse an axis steeper than this (deg)")
    q.add_argument("--max-axis-mismatch-deg", default="10",
                   help="refuse when the gyro turns about an axis this far from --axis (deg)")
    common.add_input_options(q)
    common.add_rest_options(q, min_rest_s=0.2)
    q.set_defaults(func=cmd_angle)
