"""``mtcal apply Q.json LOG`` — calibrated body attitude of a log (absolute by default, or wang2023cja Eq 10).

Reads the calibration written by ``mtcal calibrate --out Q.json`` and builds the
sensor attitude of LOG as ``calibrate`` did (QNCF of the raw columns, levelled from
the first rest with the gyro bias of its quiet core removed, or the log's own q0..q3).
``--mode absolute`` (default): pitch and roll referenced to gravity, ``q_body =
q_sensor ⊗ conj(q_bs)`` with the calibration's mounting, heading (yaw) zeroed at the
first sample — right for a log that starts anywhere (a parked aircraft).
``--mode relative``: the paper's Eq 10, ``q_body = normalize(Q̂ q_sensor)`` with the
sensor attitude zeroed at the first sample — angles relative to where the log starts,
right only when it starts at the mechanism zero (a turntable); a log whose first rest is
tilted more than the calibration's accuracy gets a warning. Output columns: ``time_s,
q0, q1, q2, q3`` (body → world), ``yaw_deg, pitch_deg, roll_deg`` (Eq 8), and the
uncalibrated ``sensor_yaw_deg, sensor_pitch_deg, sensor_roll_deg``.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from mtcal.cli import common, logio
from mtcal.systems import plausibility

EXAMPLE = """output columns: time_s, q0..q3 (calibrated body attitude), yaw_deg, pitch_deg, roll_deg,
  sensor_yaw_deg, sensor_pitch_deg, sensor_roll_deg (before calibration); Eq 8 ZXY angles
  (yaw about z, pitch about x, roll about y)
example:
  mtcal calibrate turntable.csv --positions pos.csv --out Q.json
  mtcal apply Q.json flight.csv --out body.parquet"""


def load_calibration_file(path) -> tuple[np.ndarray, dict]:
    """Q̂ (4, 4) and the whole document of a ``mtcal calibrate --out`` JSON file (checked).

    A file whose ``format`` is not one ``mtcal apply`` knows (``KNOWN_FORMATS``) is refused.
    """
    from mtcal.cli.calibrate import KNOWN_FORMATS

    p = Path(path)
    if not p.is_file():
        raise ValueError(f"calibration file not found: {path}")
    try:
        doc = json.loads(p.read_text(encoding="utf-8"))
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: not a JSON calibration ({exc.__class__.__name__}: {str(exc)[:80]})") from None
    if not isinstance(doc, dict) or "q_hat" not in doc:
        raise ValueError(f"{path}: not an mtcal calibration (expected format 'mtcal-calibration/2' with q_hat)")
    if doc.get("format") not in KNOWN_FORMATS:
        raise ValueError(f"{path}: unknown calibration format {doc.get('format')!r}; this mtcal reads "
                         f"{', '.join(KNOWN_FORMATS)} (recalibrate with this version, or use the mtcal that wrote it)")
    try:
        q = np.array(doc["q_hat"], dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{path}: q_hat must be a 4x4 array of numbers") from None
    if q.shape != (4, 4) or not np.all(np.isfinite(q)):
        raise ValueError(f"{path}: q_hat must be a finite 4x4 array, got shape {q.shape}")
    return q, doc


def load_calibration(path) -> np.ndarray:
    """Q̂ (4, 4) from a ``mtcal calibrate --out`` JSON file (checked)."""
    return load_calibration_file(path)[0]


def _accuracy_deg(doc: dict) -> float:
    """The calibration's stated accuracy (deg): largest residual, or 3 x the largest 1-sigma if larger."""
    acc = float(np.max(doc.get("residual_deg") or [0.0]))
    sig = doc.get("installation_angles_1sigma_deg")
    if isinstance(sig, dict) and sig:
        acc = max(acc, 3.0 * max(float(v) for v in sig.values()))
    return max(acc, 0.01)


def run(args: argparse.Namespace) -> int:
    fig = common.DiagnosticsFigure(args.figure, f"mtcal apply {args.log}", inputs=[args.log, args.calibration])
    out = logio.check_output_path(args.out, [args.log, args.calibration])

    def body() -> int:
        from mtcal.core import rotations
        from mtcal.systems import installation  # numba/scipy: loaded when the command runs, not for --help

        q_hat, doc = load_calibration_file(args.calibration)
        q_bs = installation.mounting_from_q_hat(q_hat)
        log = logio.read_log(args.log, common.input_options(args), need="raw_or_quat")
        fig.log = log if log.accel_m_s2 is not None else None
        static, rep, info = None, None, {}
        if log.gyro_rad_s is not None:
            rep = common.detect(args, log)
            fig.report = rep
            chk = plausibility.check_units(log.gyro_for_filter(), log.accel_m_s2, log.dt_mean_s, rep.rests,
                                           time_s=log.time_s, skip=plausibility.clipped_samples(log.gyro_rad_s)[0],
                                           unit_stated=log.gyro_unit_stated)
            common.print_units_check(chk)
            gyro, params, q0, info = common.qncf_settings(log, rep)
            source = dict(gyro_rad_s=gyro, accel_m_s2=log.accel_m_s2, dt_s=log.dt_mean_s, qncf_params=params, q0=q0)
            static = rep.is_static
        else:
            source = dict(q_ws=log.q_ws)
        if args.mode == "absolute":
            att = installation.absolute_body_attitude(q_bs, **source)
            how = ("absolute: pitch and roll referenced to gravity (" +
                   ("QNCF levelled from the first rest" if rep is not None else "the log's q0..q3, z-up world") +
                   "), q_body = q_sensor (x) conj(q_bs) with the calibration's mounting; heading (yaw) zeroed at "
                   "the first sample (gravity gives no heading)")
        else:
            att = installation.apply_installation(q_hat, **source)
            how = ("relative (wang2023cja Eq 10): q_body = normalize(Q_hat q_sensor), sensor attitude zeroed at the "
                   "first sample: angles relative to where the log starts")
            _warn_if_tilted(log, rep, q_bs, doc)
        qb = att.q_body
        eb = common.euler_deg(qb)
        es = common.euler_deg(att.q_sensor)
        extra = {"sensor_yaw_deg": es[:, 0], "sensor_pitch_deg": es[:, 1], "sensor_roll_deg": es[:, 2]}
        if static is not None:
            extra["is_static"] = static.astype(np.int8)
            common.print_report(log, rep, angle_deg=eb[:, 1], angle_name="pitch_deg")
        if "gyro_bias_text" in info:
            print(info["gyro_bias_text"])
        mount = np.degrees(rotations.euler_zxy_from_quat(q_bs))
        print(f"body attitude {how}")
        print(f"mounting q_bs = [{', '.join(f'{v:+.6f}' for v in q_bs)}] (sensor on the body at yaw {mount[0]:+.4f}, "
              f"pitch {mount[1]:+.4f}, roll {mount[2]:+.4f} deg) from {args.calibration}"
              + (f" ({doc['comment']})" if doc.get("comment") else ""))
        common.write_attitude(out, log.time_s, qb, eb, **extra)
        print(f"apply: {log.n} samples written to {out}; first body yaw/pitch/roll "
              f"{eb[0, 0]:.3f}/{eb[0, 1]:.3f}/{eb[0, 2]:.3f} deg, final {eb[-1, 0]:.3f}/{eb[-1, 1]:.3f}/{eb[-1, 2]:.3f} deg")
        return 0

    return common.run_with_figure(fig, body)


def _warn_if_tilted(log, rep, q_bs: np.ndarray, doc: dict) -> None:
    """Relative mode: one warning line when the log's first rest is tilted beyond the calibration's accuracy."""
    from mtcal.core import rotations
    from mtcal.filters.qncf import initial_attitude_from_accel

    if log.accel_m_s2 is not None and rep is not None and rep.rests:
        q_s0 = initial_attitude_from_accel(log.accel_m_s2[rep.rests[0]].mean(axis=0))
        where = f"at the first rest ({log.time_s[rep.rests[0].start]:.2f} s)"
    elif log.q_ws is not None:
        q_s0 = log.q_ws[0]
        where = "at the first sample (log's q0..q3)"
    else:
        return
    e = np.degrees(rotations.euler_zxy_from_quat(rotations.quat_multiply(q_s0, rotations.quat_conjugate(q_bs))))
    acc = _accuracy_deg(doc)
    if max(abs(e[1]), abs(e[2])) > acc:
        print(f"warning: --mode relative: the body is tilted {where}: pitch {e[1]:+.3f}, roll {e[2]:+.3f} deg from "
              f"gravity, more than the calibration's accuracy {acc:.3f} deg; the output pitch/roll are relative to that "
              f"start and are off by about that much from gravity-referenced angles (use --mode absolute)")


__all__ = ["register", "run", "load_calibration", "load_calibration_file"]


def register(subparsers) -> None:
    """Add the ``apply`` subcommand."""
    p = subparsers.add_parser("apply", help="apply a calibration (Q.json) to a log: calibrated attitude",
                              description=common.description_with_schema(__doc__, 2), epilog=EXAMPLE,
                              formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("calibration", help="JSON written by `mtcal calibrate --out`")
    p.add_argument("log", help="IMU log (CSV or Parquet): raw gyro/accel or q0..q3")
    p.add_argument("--out", default="body_attitude.csv", help="output table (.csv or .parquet)")
    p.add_argument("--mode", choices=["absolute", "relative"], default="absolute",
                   help="absolute (default): pitch/roll referenced to gravity, heading zeroed at the first sample; "
                        "relative: the paper's Eq 10, angles relative to where the log starts (turntable zero)")
    common.add_input_options(p)
    common.add_rest_options(p, min_rest_s=0.2)
    p.set_defaults(func=run)
