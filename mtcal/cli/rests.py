"""``mtcal rests LOG`` — static intervals of a log and the levels the detector measured.

Prints the measured rest levels (|a| at rest, accelerometer and gyro noise, gyro
bias), the band and thresholds used, one line per rest (time span, duration,
|a|, tilt from the sensor z axis, mean |ω|) and the quiet stretches that were
rejected with the reason. ``--out`` writes the rests as a table.
"""

from __future__ import annotations

import argparse

import numpy as np

from mtcal.cli import common, logio

EXAMPLE = """output columns (--out, CSV or Parquet): rest, start_s, stop_s, duration_s, accel_norm_m_s2,
  tilt_deg, accel_x_m_s2, accel_y_m_s2, accel_z_m_s2, gyro_x_deg_s, gyro_y_deg_s, gyro_z_deg_s
example:
  mtcal rests walk.csv --gyro-unit deg/s --accel-unit g --figure rests.png --out rests.csv"""


def register(subparsers) -> None:
    """Add the ``rests`` subcommand."""
    p = subparsers.add_parser("rests", help="static intervals and the measured rest levels",
                              description=common.description_with_schema(__doc__, 1),
                              epilog=EXAMPLE, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("log", help="IMU log (CSV, Parquet, .mat or .h5)")
    p.add_argument("--out", help="write the rests table here (.csv or .parquet)")
    p.add_argument("--accel-only", action="store_true",
                   help="ignore the gyro columns (a log without them is accelerometer-only anyway)")
    common.add_input_options(p)
    common.add_rest_options(p, min_rest_s=0.2)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    fig = common.DiagnosticsFigure(args.figure, f"mtcal rests {args.log}", inputs=[args.log])
    out = None if args.out is None else logio.check_output_path(args.out, [args.log])

    def body() -> int:
        log = logio.read_log(args.log, common.input_options(args), need="accel")  # gyro used when present
        use_gyro = log.gyro_rad_s is not None and not args.accel_only
        fig.log = log
        rep = common.detect(args, log, use_gyro=use_gyro)
        fig.report = rep
        common.print_report(log, rep)
        if out is not None:
            t, a = log.time_s, log.accel_m_s2
            means = np.array([a[r].mean(axis=0) for r in rep.rests]).reshape(-1, 3)
            cols = {"rest": np.arange(len(rep.rests)),
                    "start_s": np.array([t[r.start] for r in rep.rests]),
                    "stop_s": np.array([t[r.stop - 1] for r in rep.rests])}
            cols["duration_s"] = cols["stop_s"] - cols["start_s"]
            cols["accel_norm_m_s2"] = np.linalg.norm(means, axis=1)
            cols["tilt_deg"] = np.degrees(np.arctan2(np.hypot(means[:, 0], means[:, 1]), means[:, 2]))
            for i, ax in enumerate("xyz"):
                cols[f"accel_{ax}_m_s2"] = means[:, i]
            if use_gyro:
                gm = np.degrees(np.array([log.gyro_rad_s[r].mean(axis=0) for r in rep.rests]).reshape(-1, 3))
                for i, ax in enumerate("xyz"):
                    cols[f"gyro_{ax}_deg_s"] = gm[:, i]
            logio.write_table(out, cols)
            print(f"rests table: {out}")
        return 0

    return common.run_with_figure(fig, body)
