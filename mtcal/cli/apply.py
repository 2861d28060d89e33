"""``mtcal apply Q.json LOG`` — calibrated body attitude (wang2023cja Eq 10) of a log.

Reads the calibration written by ``mtcal calibrate --out Q.json``, builds the
sensor attitude of LOG exactly as ``calibrate`` did (QNCF of the raw columns, or
the log's own q0..q3; zeroed at the first sample) and applies
``q_body = normalize(Q̂ q_sensor)``. Output columns: ``time_s, q0, q1, q2, q3``
(body → world), ``yaw_deg, pitch_deg, roll_deg`` (Eq 8), and the uncalibrated
``sensor_yaw_deg, sensor_pitch_deg, sensor_roll_deg``.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from mtcal.cli import common, logio
from mtcal.systems import plausibility

EXAMPLE = """output columns: time_s, q0..q3 (calibrated body attitude), yaw_deg, pitch_deg, roll_deg,
  sensor_yaw_deg, sensor_pitch_deg, sensor_roll_deg (before calibration)
example:
  mtcal calibrate turntable.csv --positions pos.csv --out Q.json
  mtcal apply Q.json flight.csv --out body.parquet"""


def load_calibration(path) -> np.ndarray:
    """Q̂ (4, 4) from a ``mtcal calibrate --out`` JSON file (checked)."""
    p = Path(path)
    if not p.is_file():
        raise ValueError(f"calibration file not found: {path}")
    try:
        doc = json.loads(p.read_text(encoding="utf-8"))
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: not a JSON calibration ({exc.__class__.__name__}: {str(exc)[:80]})") from None
    if not isinstance(doc, dict) or doc.get("format") != "mtcal-calibration/1" or "q_hat" not in doc:
        raise ValueError(f"{path}: not an mtcal calibration (expected format 'mtcal-calibration/1' with q_hat)")
    try:
        q = np.array(doc["q_hat"], dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{path}: q_hat must be a 4x4 array of numbers") from None
    if q.shape != (4, 4) or not np.all(np.isfinite(q)):
        raise ValueError(f"{path}: q_hat must be a finite 4x4 array, got shape {q.shape}")
    return q


def run(args: argparse.Namespace) -> int:
    fig = common.DiagnosticsFigure(args.figure, f"mtcal apply {args.log}", inputs=[args.log, args.calibration])
    out = logio.check_output_path(args.out, [args.log, args.calibration])

    def body() -> int:
        from mtcal.cli.attitude import qncf_settings
        from mtcal.systems import installation  # numba/scipy: loaded when the command runs, not for --help

        q_hat = load_calibration(args.calibration)
        log = logio.read_log(args.log, common.input_options(args), need="raw_or_quat")
        fig.log = log if log.accel_m_s2 is not None else None
        if log.gyro_rad_s is not None:
            rep = common.detect(args, log)
            fig.report = rep
            plausibility.check_units(log.gyro_for_filter(), log.accel_m_s2, log.dt_mean_s, rep.rests,
                                     time_s=log.time_s, skip=plausibility.clipped_samples(log.gyro_rad_s)[0])
            gyro, params, q0, _ = qncf_settings(log, rep)
            att = installation.apply_installation(q_hat, gyro_rad_s=gyro, accel_m_s2=log.accel_m_s2,
                                                  dt_s=log.dt_mean_s, qncf_params=params, q0=q0)
            static = rep.is_static
        else:
            att, static = installation.apply_installation(q_hat, q_ws=log.q_ws), None
        qb = att.q_body
        eb = common.euler_deg(qb)
        es = common.euler_deg(att.q_sensor)
        extra = {"sensor_yaw_deg": es[:, 0], "sensor_pitch_deg": es[:, 1], "sensor_roll_deg": es[:, 2]}
        if static is not None:
            extra["is_static"] = static.astype(np.int8)
            common.print_report(log, rep, angle_deg=eb[:, 1], angle_name="pitch_deg")
        common.write_attitude(out, log.time_s, qb, eb, **extra)
        print(f"apply: {log.n} samples written to {out}; final body yaw/pitch/roll "
              f"{eb[-1, 0]:.3f}/{eb[-1, 1]:.3f}/{eb[-1, 2]:.3f} deg")
        return 0

    return common.run_with_figure(fig, body)


__all__ = ["register", "run", "load_calibration"]


def register(subparsers) -> None:
    """Add the ``apply`` subcommand."""
    p = subparsers.add_parser("apply", help="apply a calibration (Q.json) to a log: calibrated attitude",
                              description=common.description_with_schema(__doc__, 2), epilog=EXAMPLE,
                              formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("calibration", help="JSON written by `mtcal calibrate --out`")
    p.add_argument("log", help="IMU log (CSV or Parquet): raw gyro/accel or q0..q3")
    p.add_argument("--out", default="body_attitude.csv", help="output table (.csv or .parquet)")
    common.add_input_options(p)
    common.add_rest_options(p, min_rest_s=0.2)
    p.set_defaults(func=run)
