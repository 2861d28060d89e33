"""``mtcal calibrate LOG --positions POS.csv`` — wang2023cja six-position installation-error calibration.

LOG (CSV or Parquet, header row, one row per sample)
----------------------------------------------------
* ``time_s`` — sample time (s), strictly increasing (jitter allowed: per-sample dt);
* either raw inertial data ``gyro_x_rad_s, gyro_y_rad_s, gyro_z_rad_s`` (rad/s)
  and ``accel_x_m_s2, accel_y_m_s2, accel_z_m_s2`` (m/s²), run through the QNCF
  (``mtcal attitude``), or the sensor attitude ``q0, q1, q2, q3`` (scalar-first,
  sensor → world) of the logger; raw data wins when both are present.
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
the residual per position and the before/after errors; ``--out Q.json`` saves it
for ``mtcal apply``.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from mtcal.cli import common, logio
from mtcal.systems import plausibility

POS_COLS = ["yaw_deg", "pitch_deg", "roll_deg"]
FORMAT = "mtcal-calibration/2"
#: Calibration-file formats ``mtcal apply`` reads (version 1: no units, version, direction or uncertainty).
KNOWN_FORMATS = ("mtcal-calibration/1", FORMAT)

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
                              epilog=EXAMPLE, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("log", type=Path, help="IMU log (time_s + gyro/accel columns or q0..q3)")
    p.add_argument("--positions", type=Path, required=True, help="reference positions CSV (yaw/pitch/roll deg, >= 4)")
    p.add_argument("--out", help="write the calibration (JSON) here, for `mtcal apply`")
    p.add_argument("--comment", default="", help="free text saved in the calibration file (e.g. rig, IMU serial)")
    p.add_argument("--model", choices=["eq13", "so4", "mounting"], default="eq13",
                   help="error map fitted: eq13 (wang2023cja's 16-parameter least squares, default; needs "
                        "rotations about all three axes), so4 (nearest rotation of quaternion space L(p) R(r), "
                        "6 parameters) or mounting (q_body = q_bs q_sensor q_bs*, 3 parameters); so4 and "
                        "mounting also serve sets about two axes such as the classic +-g six positions")
    p.add_argument("--fraction", default="0.5", help="middle fraction of each rest averaged")
    p.add_argument("--max-residual-deg", default="1.0", help="refuse a fit with a larger residual (deg)")
    p.add_argument("--max-so4-distance", default=None,  # None: mtcal.systems.installation.MAX_SO4_DISTANCE
                   help="refuse a Q_hat farther than this from a rotation of quaternion space")
    p.add_argument("--still-deg-s", default="0.2", help="quaternion-rate rest threshold for q0..q3 logs (deg/s)")
    common.add_input_options(p)
    common.add_rest_options(p, min_rest_s=None)
    p.add_argument("--min-rest", dest="min_rest_s", help=argparse.SUPPRESS)  # old spelling
    p.set_defaults(func=run)


def _read_positions(path: Path) -> np.ndarray:
    """Reference positions (K, 3) in rad from a CSV with yaw_deg, pitch_deg, roll_deg (K ≥ 4)."""
    if not Path(path).is_file():
        raise ValueError(f"--positions: file not found: {path}")
    cols, _ = logio._read_table(Path(path))
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


def run(args: argparse.Namespace) -> int:
    """Entry point of ``mtcal calibrate``: read the log, run the procedure, print and write."""
    fig = common.DiagnosticsFigure(args.figure, f"mtcal calibrate {args.log}", inputs=[args.log, args.positions])
    out = None if args.out is None else logio.check_output_path(args.out, [args.log, args.positions])

    def body() -> int:
        from mtcal.systems import installation  # numba/scipy: loaded when the command runs, not for --help

        log = logio.read_log(args.log, common.input_options(args), need="raw_or_quat")
        fig.log = log if log.accel_m_s2 is not None else None
        pos = _read_positions(args.positions)
        fraction = common.finite_float(args.fraction, "--fraction")
        if args.min_rest_s is None:  # defaults: 1 s (adaptive), 2 s (paper's stillness detector, as before)
            args.min_rest_s = "2.0" if args.rest_detector == "paper" or log.gyro_rad_s is None else "1.0"
        min_rest = common.finite_float(args.min_rest_s, "--min-rest-s")
        so4 = args.max_so4_distance
        gates = {"max_so4_distance": (installation.MAX_SO4_DISTANCE if so4 is None
                                      else common.finite_float(so4, "--max-so4-distance")),
                 "max_residual_rad": np.radians(common.finite_float(args.max_residual_deg, "--max-residual-deg"))}
        rep = None
        if log.gyro_rad_s is not None:
            rep = common.detect(args, log)
            fig.report = rep
            if args.rest_detector == "paper":
                rests = installation.detect_rests(log.dt_mean_s, gyro_rad_s=log.gyro_rad_s, min_rest_s=min_rest)
            else:
                rests = rep.rests
            chk = plausibility.check_units(log.gyro_for_filter(), log.accel_m_s2, log.dt_mean_s, rests,
                                           time_s=log.time_s, skip=plausibility.clipped_samples(log.gyro_rad_s)[0],
                                           unit_stated=log.gyro_unit_stated)
            common.print_units_check(chk)
            gyro, params, q0, info = common.qncf_settings(log, rep)
            source = {"gyro_rad_s": gyro, "accel_m_s2": log.accel_m_s2, "qncf_params": params, "q0": q0}
        else:
            still_rad_s = np.radians(common.finite_float(args.still_deg_s, "--still-deg-s"))
            rests = installation.detect_rests(log.dt_mean_s, q_ws=log.q_ws, min_rest_s=min_rest,
                                              threshold_rad_s=still_rad_s)
            source, info = {"q_ws": log.q_ws}, {"filter": "none (q0..q3 from the log)"}
        print(f"log: {args.log} ({log.n} samples at {log.fs_hz:.1f} Hz); "
              f"{len(rests)} rests found, {pos.shape[0]} positions")
        if rep is not None:
            print(rep.levels_text())
        if "gyro_bias_text" in info:
            print(info["gyro_bias_text"])
        if len(rests) < pos.shape[0]:
            if rep is None:
                lv = "quaternion-rate threshold --still-deg-s"
            elif args.rest_detector == "paper":
                lv = (f"paper stillness threshold |w| < 0.2 deg/s; measured gyro bias "
                      f"{np.degrees(np.linalg.norm(rep.gyro_bias_rad_s)):.2f} deg/s, noise "
                      f"{np.degrees(rep.gyro_noise_rad_s):.3f} deg/s")
            else:
                lv = rep.levels_text()
            raise ValueError(f"too few rests: found {len(rests)} rests of >= {min_rest:g} s for "
                             f"{pos.shape[0]} positions ({lv}); see --figure for the rejected stretches")
        try:
            cal = installation.calibrate_installation(pos, log.dt_mean_s, rests=rests, fraction=fraction, **source,
                                                      model=args.model, **gates)
        except ValueError as exc:
            tiny = np.max(np.abs(np.degrees(pos))) <= np.pi / 2 + 1e-9        # values that may be radians
            if not (any(m in str(exc) for m in MISMATCH_MESSAGES) or (tiny and "ill-conditioned" in str(exc))):
                raise
            hint = _quaternion_hint(pos, log, rests, fraction, gates, args.model) if "q_ws" in source else ""
            if not hint:
                hint = _diagnose(args, pos, log, rests, fraction, gates, source)
            raise ValueError(f"{exc}{hint}") from None
        fig.used = cal.matched_rests
        _print_and_write(args, out, log, rests, cal, info)
        return 0

    return common.run_with_figure(fig, body)


#: Refusals that mean "the rests do not match the positions" (a convention mistake is then looked for).
MISMATCH_MESSAGES = ("has no rest within", "Q_hat is not a calibration", "a rest does not match its reference")

#: Position-file mistakes tried on refusal: name → (transform of the positions in rad, what to do).
POSITION_MISTAKES = {
    "radians": (np.degrees, "the positions file holds radians: write degrees (yaw_deg, pitch_deg, roll_deg)"),
    "pitch sign flipped": (lambda p: p * [1.0, -1.0, 1.0], "negate pitch_deg (pitch is positive about +x, nose up)"),
    "roll sign flipped": (lambda p: p * [1.0, 1.0, -1.0], "negate roll_deg (roll is positive about +y)"),
    "yaw sign flipped": (lambda p: p * [-1.0, 1.0, 1.0], "negate yaw_deg (yaw is positive about +z, up)"),
    "pitch and roll swapped": (lambda p: p[:, [0, 2, 1]], "swap the pitch_deg and roll_deg columns "
                               "(pitch about x, roll about y: wang2023cja Eq 8/9)"),
}


def _diagnose(args, pos, log, rests, fraction, gates, source) -> str:
    """Why the rests do not match the positions: per position the nearest rest's attitude, and the likely mistake.

    Prints the table (stdout) and returns the hint appended to the one-line error.
    """
    from mtcal.methods import six_position
    from mtcal.systems import installation

    dt = log.dt_mean_s
    q_abs = installation.absolute_body_attitude(np.array([1.0, 0.0, 0.0, 0.0]), zero_heading=False,
                                                **({"dt_s": dt} if "q_ws" not in source else {}), **source).q_sensor
    q_rel = installation.apply_installation(np.eye(4), q_ws=q_abs).q_sensor
    means = six_position.rest_means(q_rel, rests, fraction)
    t = log.time_s
    from mtcal.core import rotations

    q_ref = rotations.quat_from_euler_zxy(pos[:, 0], pos[:, 1], pos[:, 2])
    dist = np.degrees(rotations.quat_angle_between(means[:, None, :], q_ref[None, :, :]))      # (R, K)
    print("calibration refused; per reference position the nearest rest (zeroed sensor attitude, Eq 8 ZXY deg):")
    print(f"  {'pos':>3} {'ref yaw/pitch/roll':>26} {'nearest rest':>14} {'measured yaw/pitch/roll':>26} {'dist':>7}")
    for k in range(pos.shape[0]):
        r = int(np.argmin(dist[:, k]))
        e = np.degrees(rotations.euler_zxy_from_quat(means[r]))
        ref = np.degrees(pos[k])
        print(f"  {k + 1:>3} {' '.join(f'{v:+8.2f}' for v in ref):>26} "
              f"{t[rests[r].start]:>6.1f}-{t[rests[r].stop - 1]:<6.1f}s {' '.join(f'{v:+8.2f}' for v in e):>26} "
              f"{dist[r, k]:7.2f}")

    def fits(p, q=q_abs, rr=rests) -> bool:
        try:
            installation.calibrate_installation(p, dt, q_ws=q, rests=rr, fraction=fraction, model=args.model, **gates)
        except ValueError:
            return False
        return True

    if log.accel_m_s2 is not None and rests:
        a0 = log.accel_m_s2[rests[0]].mean(axis=0)
        if a0[2] < -0.5 * np.linalg.norm(a0):
            return (f"; likely mistake: the sensor reads -g on z at its first rest (a = [{a0[0]:+.2f}, {a0[1]:+.2f}, "
                    f"{a0[2]:+.2f}] m/s^2): FRD/NED axes (z down)? mtcal expects x right, y forward, z up (+g on z "
                    f"when level); map FRD to it with --columns gyro_x=<gyro y>,gyro_y=<gyro x>,accel_x=<accel y>,"
                    f"accel_y=<accel x> --gyro-scale 1,1,-1 --accel-scale 1,1,-1")
    for name, (fn, fix) in POSITION_MISTAKES.items():
        cand = fn(pos)
        if name == "radians" and np.max(np.abs(cand)) > 2 * np.pi:
            continue
        if fits(cand):
            return f"; likely mistake: {name} — every position matches after that change: {fix}"
    for i, r in enumerate(rests[1:], start=1):
        shifted = [slice(x.start - r.start, x.stop - r.start) for x in rests[i:]]
        if len(shifted) >= pos.shape[0] and fits(pos, q_abs[r.start:], shifted):
            return (f"; likely mistake: the log does not start at the mechanism zero — with the attitude zeroed at the "
                    f"rest at {t[r.start]:.1f} s every position matches: trim the log to start at the zero "
                    f"(the positions are relative to where the log starts)")
    if np.max(np.abs(pos)) <= np.pi / 2 + 1e-9 and np.max(np.abs(pos)) > 0:
        return ("; the positions are all within +-1.571 deg: if they are radians, write degrees "
                "(the table above shows what each rest measured)")
    return "; no single convention mistake (radians, sign, pitch/roll swap, FRD axes, start) explains it: see the table above"


#: Other quaternion conventions tried when a q0..q3 log matches no position: name → (transform, fix).
QUATERNION_CONVENTIONS = {
    "scalar-last (x, y, z, w)": (lambda q: q[:, [3, 0, 1, 2]],
                                 "map the scalar column to q0 with --columns q0=W,q1=X,q2=Y,q3=Z"),
    "conjugated (world -> sensor)": (lambda q: q * np.array([1.0, -1.0, -1.0, -1.0]),
                                     "give the sensor -> world attitude (negate q1..q3)"),
    "scalar-last and conjugated": (lambda q: q[:, [3, 0, 1, 2]] * np.array([1.0, -1.0, -1.0, -1.0]),
                                   "map the scalar column to q0 with --columns and negate q1..q3"),
}


def _quaternion_hint(pos, log, rests, fraction, gates, model="eq13") -> str:
    """A hint naming the quaternion convention under which the log would match the positions ('' if none)."""
    from mtcal.systems import installation

    for name, (fn, fix) in QUATERNION_CONVENTIONS.items():
        q = fn(log.q_ws)
        try:
            installation.calibrate_installation(pos, log.dt_mean_s, q_ws=q, rests=rests, fraction=fraction,
                                                model=model, **gates)
        except ValueError:
            continue
        return f"; the log's q0..q3 would match every position if they were {name}: {fix}"
    return ""


def _print_and_write(args, out, log, rests, cal, info: dict) -> None:
    """The ``Q_hat`` block, the per-position table, the installation angles and the JSON (``--out``)."""
    from mtcal.core import rotations
    from mtcal.systems import installation

    alpha = np.degrees(cal.installation_angles_rad)
    model_name = {"eq13": "Eq 13", "so4": "SO(4) fit L(p) R(r), 6 parameters",
                  "mounting": "mounting fit L(q_bs) R(q_bs*), 3 parameters"}[getattr(args, "model", "eq13")]
    print(f"Q_hat ({model_name}, q_body = Q_hat q_sensor):")
    for row in cal.q_hat:
        print("  " + "  ".join(f"{v:+.6f}" for v in row))
    print(f"{'pos':>3} {'ref yaw/pitch/roll (deg)':>27} {'before error (deg)':>27} "
          f"{'after error (deg)':>27} {'residual':>9}")
    ref_deg = np.degrees(cal.positions_rad)
    before, after = np.degrees(cal.error_before_rad), np.degrees(cal.error_after_rad)
    fmt = lambda v: " ".join(f"{x:+8.4f}" for x in v)  # noqa: E731
    for k in range(ref_deg.shape[0]):
        print(f"{k + 1:>3} {fmt(ref_deg[k]):>27} {fmt(before[k]):>27} {fmt(after[k]):>27} "
              f"{np.degrees(cal.residual_rad[k]):9.5f}")
    model = getattr(args, "model", "eq13")
    sigma = np.degrees(installation.installation_angles_sigma(cal, model))
    mount = np.degrees(rotations.euler_zxy_from_quat(cal.mounting_quaternion_q_bs))
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
    print(f"max |error| before {np.max(np.abs(before)):.4f} deg, after {np.max(np.abs(after)):.4f} deg")
