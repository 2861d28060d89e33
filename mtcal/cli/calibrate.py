"""``mtcal calibrate LOG --positions POS.csv`` — wang2023cja six-position installation-error calibration.

LOG (CSV or Parquet table, header row, one row per sample; or arrays of a .mat/.h5/.hdf5 file)
---------------------------------------------------------------------------------------------
* ``time_s`` — sample time (s), strictly increasing (jitter allowed: per-sample dt);
* either raw inertial data ``gyro_x_rad_s, gyro_y_rad_s, gyro_z_rad_s`` (rad/s)
  and ``accel_x_m_s2, accel_y_m_s2, accel_z_m_s2`` (m/s²), run through the QNCF
  (``mtcal attitude``), or the sensor attitude ``q0, q1, q2, q3`` (scalar-first,
  sensor → world) of the logger; raw data wins when both are present;
* or a MATLAB .mat (v5, v7.3) / HDF5 .h5/.hdf5 file: N x 3 gyro and accel arrays mapped
  with ``--columns gyro=NAME,accel=NAME[,time=NAME]``, the rate from its ``sampling_rate``
  or ``--fs-hz`` (BROAD's imu_gyr/imu_acc/sampling_rate opens as is); raw data only.
The attitude is zeroed at the first sample ("initial attitude angles 0°", §4.1).

POS.csv (one row per calibration position, any order, at least 4)
-----------------------------------------------------------------
``yaw_deg, pitch_deg, roll_deg`` — the mechanism's reference angles (Eq 15; Eq 8/9
convention: yaw about z, pitch about x, roll about y). Eq 13 fits 16 numbers, so it
needs ≥ 4 positions with linearly independent quaternions (the paper's "3" relies
on a norm constraint the linear fit does not use); 6 (§3.2) leave residuals to check.

Rests are found by the adaptive detector (raw logs) or from the quaternion rate
(attitude logs), their middle halves averaged, matched to the positions by
nearest attitude, and Eq 13 is solved. The fit is refused when Q̂ is far from a
rotation of quaternion space (an all-zero row, entries like 10), when the
positions are ill-conditioned, or when a residual exceeds ``--max-residual-deg``.
Prints Q̂, the installation angles (inverse of Eq 1 of the mounting part of Q̂),
the residual per position and the before/after errors (yaw/pitch/roll differences and the
rotation angle between the reference and the measured attitude; the summary's max |error| is
that angle, which stays defined at pitch +-90 deg where ZXY yaw and roll are not); ``--out
Q.json`` saves it for ``mtcal apply``.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from mtcal.cli import common, logio

POS_COLS = ["yaw_deg", "pitch_deg", "roll_deg"]
FORMAT = "mtcal-calibration/2"
#: Calibration-file formats ``mtcal apply`` reads (version 1: no units, version, direction or uncertainty).
KNOWN_FORMATS = ("mtcal-calibration/1", FORMAT)
#: The default of ``--max-so4-distance`` as its help prints it: ``mtcal.systems.installation.MAX_SO4_DISTANCE``
#: (not imported for ``--help``, which loads no numba/scipy; equality tested).
MAX_SO4_DISTANCE_TEXT = "0.05"

#: What the installation angles mean (wang2023cja Eq 1), printed with the numbers and saved in the file.
ALPHA_MEANING = ("installation angles (wang2023cja Eq 1, C_b^s = Rz(alpha1) Ry(alpha2) Rx(alpha3)): alpha1 about z "
                 "(yaw), alpha2 about y (roll), alpha3 about x (pitch) in the positions' naming; alpha describes the "
                 "body relative to the sensor, to first order the negative of the sensor's misalignment")
#: What the mounting quaternion means, and how another filter uses it.
MOUNTING_MEANING = ("q_bs, scalar-first: sensor attitude = body attitude (x) q_bs (q_ws = q_wb (x) q_bs, "
                    "v_body = C(q_bs) v_sensor); body attitude from any filter's sensor attitude q_ws (z-up world): "
                    "q_wb = q_ws (x) conj(q_bs)")

EXAMPLE = """installation angles (wang2023cja Eq 1): C_b^s = Rz(alpha1) Ry(alpha2) Rx(alpha3), alpha1 about z
  (yaw), alpha2 about y (roll), alpha3 about x (pitch); alpha describes the body relative to the
  sensor, to first order the negative of the sensor's misalignment (printed beside them: the
  mounting as yaw/pitch/roll of q_bs, Eq 8 ZXY).
Q.json (--out, format mtcal-calibration/2): format, mtcal_version, comment, input (units, scales,
  column mapping, sample rate), q_hat (4x4, q_body = Q_hat q_sensor), installation_angles_deg and
  installation_angles_1sigma_deg (fit covariance) with their meaning, mounting_quaternion_q_bs
  (q_ws = q_wb (x) q_bs: another filter's body attitude is q_ws (x) conj(q_bs)), mounting_ypr_deg,
  reference_offset_quaternion, positions_deg with their convention, residual_deg, rests_s,
  attitude settings; see README "Calibration file".
example:
  mtcal calibrate turntable.csv --positions pos.csv --out Q.json --figure cal.png
  mtcal apply Q.json flight.csv --out body_attitude.csv"""

def register(subparsers) -> None:
    """Add the ``calibrate`` subcommand to the ``mtcal`` dispatcher."""
    p = subparsers.add_parser("calibrate", help="six-position installation-error calibration (wang2023cja)",
                              description=__doc__.split("\n\n")[0] + "\n\n" + "\n\n".join(__doc__.split("\n\n")[1:4]),
                              epilog=EXAMPLE)
    p.add_argument("log", type=Path, help=f"IMU log ({common.LOG_FORMATS}): time_s + gyro/accel, or q0..q3 "
                                                "columns of a table")
    p.add_argument("--positions", type=Path, required=True, help="reference positions CSV (yaw/pitch/roll deg, >= 4)")
    p.add_argument("--out", help="write the calibration (JSON, a .json file) here, for `mtcal apply` (default: "
                   "none, the result is only printed)")
    p.add_argument("--comment", default="", help="free text saved in the calibration file (e.g. rig, IMU serial) "
                                                "(default: empty)")
    p.add_argument("--model", choices=["eq13", "so4", "mounting"], default="eq13",
                   help="error map fitted: eq13 (wang2023cja's 16-parameter least squares; needs "
                        "rotations about all three axes), so4 (nearest rotation of quaternion space L(p) R(r), "
                        "6 parameters) or mounting (q_body = q_bs q_sensor q_bs*, 3 parameters); so4 and "
                        "mounting also serve sets about two axes such as the classic +-g six positions")
    p.add_argument("--fraction", default="0.5", help="middle fraction of each rest averaged, in (0, 1]")
    p.add_argument("--max-residual-deg", default="1.0", help="refuse a fit with a larger residual (deg)")
    p.add_argument("--max-so4-distance", default=None,  # None: mtcal.systems.installation.MAX_SO4_DISTANCE
                   help="refuse a Q_hat farther than this from a rotation of quaternion space (Frobenius "
                        f"norm) (default: {MAX_SO4_DISTANCE_TEXT})")
    p.add_argument("--still-deg-s", default="0.2", help="quaternion-rate rest threshold for q0..q3 logs (deg/s)")
    common.add_input_options(p)
    common.add_rest_options(p, min_rest_s=None)
    p.add_argument("--min-rest", dest="min_rest_s", help=argparse.SUPPRESS)  # old spelling
    p.set_defaults(func=run)


def _read_positions(path: Path) -> np.ndarray:
    """Reference positions (K, 3) in rad from a CSV with yaw_deg, pitch_deg, roll_deg (K ≥ 4)."""
    if not Path(path).is_file():
        raise ValueError(f"--positions: file not found: {path}")
    cols, _ = logio._read_table(Path(path), select=lambda names: list(POS_COLS))   # (a repeated one: refused)
    missing = [c for c in POS_COLS if c not in cols]
    if missing:
        raise ValueError(f"--positions {path}: missing columns {missing} (need {', '.join(POS_COLS)})")
    ang = np.column_stack([logio._numeric(cols[c], c, Path(path)) for c in POS_COLS])
    if ang.shape[0] < 4:
        raise ValueError(f"--positions {path}: need at least 4 positions for Eq 13 (16 unknowns), got {ang.shape[0]}; "
                         f"the six positions of wang2023cja §3.2 are recommended")
    if np.max(np.abs(ang)) > 360:
        raise ValueError(f"--positions {path}: angles must be in degrees within +-360, got {np.max(np.abs(ang)):.4g}")
    return np.radians(ang)


def _config(args: argparse.Namespace, quaternion_log: bool):
    """The procedure's one config from the options (SI): :meth:`InstallationConfig.command_line`.

    ``--still-deg-s`` is the quaternion-rate detector's threshold: read for a q0..q3 log only; the
    rest options make the raw log's rest detector.
    """
    from mtcal.systems.installation import InstallationConfig

    so4 = args.max_so4_distance
    still = np.radians(common.finite_float(args.still_deg_s, "--still-deg-s"))   # checked for any log
    out = {"model": args.model, "fraction": common.finite_float(args.fraction, "--fraction", high=1.0),
           "min_rest_s": common.finite_float(args.min_rest_s, "--min-rest-s"),
           "max_residual_rad": np.radians(common.finite_float(args.max_residual_deg, "--max-residual-deg")),
           "max_so4_distance": None if so4 is None else common.finite_float(so4, "--max-so4-distance")}
    if quaternion_log:
        out["still_threshold_rad_s"] = still
    else:
        out["rest_detector"] = common.rests_config(args)
    return InstallationConfig.command_line(**out)


def run(args: argparse.Namespace) -> int:
    """Entry point of ``mtcal calibrate``: options → one config, read the log, one procedure, print and write."""
    fig = common.DiagnosticsFigure(args.figure, f"mtcal calibrate {args.log}", inputs=[args.log, args.positions])
    out = None if args.out is None else logio.check_output_path(args.out, [args.log, args.positions],
                                                                suffixes=(".json",),
                                                                others=(("--figure", args.figure),))

    def body() -> int:
        # numba/scipy: loaded when the command runs, not for --help
        from mtcal.systems.installation import RecordRefused, calibrate_record

        log = logio.read_log(args.log, common.input_options(args), need="raw_or_quat")
        fig.log = log if log.accel_m_s2 is not None else None
        pos = _read_positions(args.positions)
        if args.min_rest_s is None:  # defaults: 1 s (adaptive), 2 s (paper's stillness detector, as before)
            args.min_rest_s = "2.0" if args.rest_detector == "paper" or log.gyro_rad_s is None else "1.0"
        cfg = _config(args, quaternion_log=log.gyro_rad_s is None)
        try:
            res = calibrate_record(cfg, pos, log.dt_mean_s, **common.log_arrays(log))
        except RecordRefused as exc:
            fig.report = exc.report
            raise
        fig.report = res.report
        _print_result(args, out, log, pos, res, fig)
        return 0

    return common.run_with_figure(fig, body)


def _print_result(args, out, log, pos, res, fig) -> None:
    """What ``mtcal calibrate`` prints of a :class:`~mtcal.systems.installation.RecordCalibration`, and ``--out``."""
    rep = res.report
    if res.units_check is not None:
        common.print_units_check(res.units_check)
    info = {"filter": "none (q0..q3 from the log)"} if res.qncf is None else common.qncf_info(log, res.qncf)
    print(f"log: {args.log} ({log.n} samples at {log.fs_hz:.1f} Hz); "
          f"{len(res.rests)} rests found, {pos.shape[0]} positions")
    if rep is not None:
        print(rep.levels_text())
    if "gyro_bias_text" in info:
        print(info["gyro_bias_text"])
    if len(res.rests) < pos.shape[0]:
        if rep is None:
            lv = "quaternion-rate threshold --still-deg-s"
        elif args.rest_detector == "paper":
            lv = (f"paper stillness threshold |w| < 0.2 deg/s; measured gyro bias "
                  f"{np.degrees(np.linalg.norm(rep.gyro_bias_rad_s)):.2f} deg/s, noise "
                  f"{np.degrees(rep.gyro_noise_rad_s):.3f} deg/s")
        else:
            lv = rep.levels_text()
        raise ValueError(f"too few rests: found {len(res.rests)} rests of >= {res.config.min_rest_s:g} s for "
                         f"{pos.shape[0]} positions ({lv}); see --figure for the rejected stretches")
    if res.diagnosis is not None:
        _print_diagnosis(log, pos, res.diagnosis)
    if res.refusal is not None:
        raise ValueError(_with_options(res.refusal))
    fig.used = res.calibration.matched_rests
    _print_and_write(args, res, out, log, info)


#: The procedure's parameters as this command's options, for its refusals (the methods name their own
#: parameters: ``model="so4"``, ``max_residual_rad``; the command names what the user types).
_OPTION_OF = (('model="so4"', "--model so4"), ('model="mounting"', "--model mounting"),
              ("max_residual_rad (", "--max-residual-deg ("))


def _with_options(message: str) -> str:
    """A refusal of the calibration procedure with its parameters named as this command's options."""
    for parameter, option in _OPTION_OF:
        message = message.replace(parameter, option)
    return message


def _print_diagnosis(log, pos, diag) -> None:
    """The table of a refusal looked into: per reference position the nearest rest (Eq 8 ZXY deg)."""
    t = log.time_s
    print("calibration refused; per reference position the nearest rest (zeroed sensor attitude, Eq 8 ZXY deg):")
    print(f"  {'pos':>3} {'ref yaw/pitch/roll':>26} {'nearest rest':>14} {'measured yaw/pitch/roll':>26} {'dist':>7}")
    for k in range(pos.shape[0]):
        r = diag.nearest[k]
        e = np.degrees(diag.measured_rad[k])
        ref = np.degrees(pos[k])
        print(f"  {k + 1:>3} {' '.join(f'{v:+8.2f}' for v in ref):>26} "
              f"{t[r.start]:>6.1f}-{t[r.stop - 1]:<6.1f}s {' '.join(f'{v:+8.2f}' for v in e):>26} "
              f"{np.degrees(diag.distance_rad[k]):7.2f}")


def _print_and_write(args, res, out, log, info: dict) -> None:
    """The ``Q_hat`` block, the per-position table, the installation angles and the JSON (``--out``)."""
    from mtcal.systems import installation

    cfg, cal, sigma_rad = res.config, res.calibration, res.sigma_rad

    alpha = np.degrees(cal.installation_angles_rad)
    model_name = {"eq13": "Eq 13", "so4": "SO(4) fit L(p) R(r), 6 parameters",
                  "mounting": "mounting fit L(q_bs) R(q_bs*), 3 parameters"}[cfg.model]
    print(f"Q_hat ({model_name}, q_body = Q_hat q_sensor):")
    for row in cal.q_hat:
        print("  " + "  ".join(f"{v:+.6f}" for v in row))
    ref_deg = np.degrees(cal.positions_rad)
    angle_before, angle_after = attitude_errors_deg(cal)
    locked_before, locked_after = (_near_gimbal_lock(ref_deg, e) for e in (cal.euler_before_rad, cal.euler_after_rad))
    print(f"{'pos':>3} {'ref yaw/pitch/roll (deg)':>29} {'before error yaw/pitch/roll':>29} {'angle':>8} "
          f"{'after error yaw/pitch/roll':>29} {'angle':>8}")
    for k in range(ref_deg.shape[0]):
        print(f"{k + 1:>3} {_fmt(ref_deg[k]):>29} {_fmt(np.degrees(cal.error_before_rad[k]), locked_before[k]):>29} "
              f"{angle_before[k]:8.4f} {_fmt(np.degrees(cal.error_after_rad[k]), locked_after[k]):>29} "
              f"{angle_after[k]:8.5f}")
    print("  angle: rotation angle between the reference and the measured attitude (deg; after = the fit residual)"
          + (f"; n/a: yaw/roll error undefined within {GIMBAL_LOCK_TOL_DEG:g} deg of pitch +-90 deg "
             f"(gimbal lock of the ZXY angles)" if np.any(locked_before | locked_after) else ""))
    model = cfg.model
    sigma = np.degrees(sigma_rad)
    mount = np.degrees(res.mounting_euler_rad)
    sig_txt = ("1-sigma not estimable (4 positions leave no degrees of freedom)" if not np.all(np.isfinite(sigma))
               else "1-sigma " + " ".join(f"{v:.4f}" for v in sigma) + f" deg ({model} fit covariance)")
    print(f"installation angles alpha1 (z) alpha2 (y) alpha3 (x): {alpha[0]:+.4f} {alpha[1]:+.4f} {alpha[2]:+.4f} deg, "
          f"{sig_txt}; |Q_hat - SO(4)| {float(cal.so4_distance):.2e}")
    print(f"  meaning: {ALPHA_MEANING}")
    print(f"  mounting q_bs = [{', '.join(f'{v:+.6f}' for v in cal.mounting_quaternion_q_bs)}]: the sensor on the "
          f"body at yaw {mount[0]:+.4f}, pitch {mount[1]:+.4f}, roll {mount[2]:+.4f} deg (Eq 8 ZXY of q_bs)")
    if ref_deg.shape[0] == 4 and model == "eq13":
        print("note: 4 positions determine Eq 13 exactly — residuals are 0 by construction and check "
              "nothing; record 6 positions")
    if out is not None:
        t = log.time_s
        import mtcal

        opts = common.input_options(args)
        doc = {"format": FORMAT, "format_version": 2, "mtcal_version": mtcal.__version__, "comment": args.comment,
               "log": str(args.log), "positions_file": str(args.positions),
               "input": {"time_unit": opts.time_unit or "s", "gyro_unit": opts.gyro_unit or "rad/s",
                         "accel_unit": opts.accel_unit or "m/s2",
                         "gyro_scale": None if opts.gyro_scale is None else np.ravel(opts.gyro_scale).tolist(),
                         "accel_scale": None if opts.accel_scale is None else np.ravel(opts.accel_scale).tolist(),
                         "columns": dict(opts.columns), "fs_hz_option": opts.fs_hz,
                         "sample_rate_hz": float(log.fs_hz), "interpretation": list(log.notes),
                         "attitude_source": "q0..q3 columns" if log.gyro_rad_s is None else "gyro/accel (QNCF)"},
               "model": model,
               "q_hat": cal.q_hat.tolist(), "so4_distance": float(cal.so4_distance),
               "installation_angles_deg": {"alpha1_z": alpha[0], "alpha2_y": alpha[1], "alpha3_x": alpha[2]},
               "installation_angles_1sigma_deg": (None if not np.all(np.isfinite(sigma)) else
                                                  {"alpha1_z": sigma[0], "alpha2_y": sigma[1], "alpha3_x": sigma[2]}),
               "installation_angles_uncertainty": f"1-sigma from the {model} fit covariance (residual variance of the "
                                                  f"4K quaternion components, 4K-{installation.MODELS[model][0]} "
                                                  f"degrees of freedom) propagated through the SO(4) projection",
               "installation_angles_meaning": ALPHA_MEANING,
               "mounting_quaternion_q_bs": cal.mounting_quaternion_q_bs.tolist(),
               "mounting_meaning": MOUNTING_MEANING,
               "mounting_ypr_deg": {"yaw_z": mount[0], "pitch_x": mount[1], "roll_y": mount[2]},
               "reference_offset_quaternion": cal.projection.p.tolist(),
               "positions_deg": ref_deg.tolist(),
               "positions_convention": "rows yaw_deg, pitch_deg, roll_deg: wang2023cja Eq 8/9 ZXY, q = qz(yaw) qx(pitch) "
                                       "qy(roll), z up, y forward (nose), x right; relative to the mechanism zero "
                                       "at which the log starts",
               "residual_deg": np.degrees(cal.residual_rad).tolist(),
               "residual_max_deg": float(np.degrees(np.max(cal.residual_rad))),
               "rests_s": [[float(t[r.start]), float(t[r.stop - 1])] for r in cal.matched_rests],
               "attitude": {**info, "zeroed_at_first_sample": True},
               "convention": "q_body = normalize(Q_hat q_sensor), q scalar-first; sensor attitude zeroed "
                             "at the first sample; Euler wang2023cja Eq 8 (yaw z, pitch x, roll y)"}
        logio.write_text(out, json.dumps(doc, indent=2, default=float) + "\n")
        print(f"calibration written to {out}")
    print(f"max |error| (rotation angle to the reference) before {np.max(angle_before):.4f} deg, "
          f"after {np.max(angle_after):.4f} deg")


#: Within this many degrees of pitch ±90° (reference or measured) the ZXY yaw and roll errors are printed as n/a:
#: there an attitude error moves yaw and roll by up to 1/cos(pitch) (≥ 11×) its size, and at ±90° they are undefined.
GIMBAL_LOCK_TOL_DEG = 5.0


def attitude_errors_deg(cal) -> tuple[np.ndarray, np.ndarray]:
    """Rotation angle (deg) between each reference attitude and the measured one, before and after ``Q_hat``.

    Unlike per-angle Euler differences this is defined at pitch ±90° too (where ZXY yaw and roll are not):
    :func:`mtcal.core.rotations.quat_angle_between` of the reference quaternion and the zeroed sensor
    attitude at the rest (before) or ``normalize(Q_hat q_sensor)`` (after; equal to ``residual_rad``).
    """
    from mtcal.core import rotations

    after_q = rotations.apply_quat_matrix_trusted(cal.q_hat, cal.q_sensor)
    before = rotations.quat_angle_between(cal.q_reference, cal.q_sensor)
    after = rotations.quat_angle_between(cal.q_reference, after_q)
    return np.degrees(before), np.degrees(after)


def _near_gimbal_lock(ref_deg: np.ndarray, euler_rad: np.ndarray) -> np.ndarray:
    """(K,) bool: the reference or the measured pitch is within :data:`GIMBAL_LOCK_TOL_DEG` of ±90°."""
    lim = 90.0 - GIMBAL_LOCK_TOL_DEG
    return (np.abs(ref_deg[:, 1]) >= lim) | (np.abs(np.degrees(euler_rad[:, 1])) >= lim)


def _fmt(v: np.ndarray, locked: bool = False) -> str:
    """Yaw/pitch/roll (deg) for the per-position table; yaw and roll as n/a at gimbal lock."""
    return " ".join("n/a".rjust(9) if locked and i != 1 else f"{x:+9.4f}" for i, x in enumerate(v))
