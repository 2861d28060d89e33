"""``mtcal rests LOG`` — static intervals of a log and the levels the detector measured.

Prints the measured rest levels (|a| at rest, accelerometer and gyro noise, gyro
bias), the band and thresholds used, one line per rest (time span, duration,
|a|, tilt from the sensor z axis, mean |ω|) and the quiet stretches that were
rejected with the reason. ``--out`` writes the rests as a table.

The command parses the options into one :class:`mtcal.systems.rests.RestsConfig`
(:func:`mtcal.cli.common.rests_config`), reads the log, calls :func:`mtcal.systems.rests.rests_record`
(the rests, and the gyro's units and time base checked as ``attitude`` and ``axis`` check them, unless
``--accel-only``) and writes :func:`mtcal.systems.rests.rests_table`.
"""

from __future__ import annotations

import argparse

from mtcal.cli import common, logio

EXAMPLE = """output columns (--out, CSV or Parquet): rest, start_s, stop_s, duration_s, accel_norm_m_s2,
  tilt_deg, accel_x_m_s2, accel_y_m_s2, accel_z_m_s2, gyro_x_deg_s, gyro_y_deg_s, gyro_z_deg_s
example:
  mtcal rests walk.csv --gyro-unit deg/s --accel-unit g --figure rests.png --out rests.csv"""


def register(subparsers) -> None:
    """Add the ``rests`` subcommand."""
    p = subparsers.add_parser("rests", help="static intervals and the measured rest levels",
                              description=common.description_with_schema(__doc__, 1),
                              epilog=EXAMPLE)
    p.add_argument("log", help=f"IMU log ({common.LOG_FORMATS})")
    p.add_argument("--out", help="write the rests table here (.csv or .parquet) (default: none, the table is "
                   "only printed)")
    p.add_argument("--accel-only", action="store_true",
                   help="ignore the gyro columns (a log without them is accelerometer-only anyway)")
    common.add_input_options(p)
    common.add_rest_options(p, min_rest_s=0.2)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    fig = common.DiagnosticsFigure(args.figure, f"mtcal rests {args.log}", inputs=[args.log])
    out = None if args.out is None else common.table_output(args, [args.log])

    def body() -> int:
        from mtcal.systems.rests import rests_record, rests_table

        log = logio.read_log(args.log, common.input_options(args), need="accel")  # gyro used when present
        gyro = None if args.accel_only else log.gyro_rad_s
        fig.log = log
        config = common.rests_config(args, has_gyro=gyro is not None)
        try:   # the gyro the rests use: its units and time base checked as attitude/axis check them
            rep, chk = rests_record(log.accel_m_s2, log.dt_mean_s, config, gyro_rad_s=gyro, time_s=log.time_s,
                                    unit_stated=log.gyro_unit_stated)
        except ValueError as exc:
            fig.report = getattr(exc, "rests", None)
            raise
        fig.report = rep
        common.print_report(log, rep)
        if chk is not None:
            common.print_units_check(chk)
        if out is not None:
            logio.write_table(out, rests_table(log.time_s, log.accel_m_s2, rep, gyro_rad_s=gyro))
            print(f"rests table: {out}")
        return 0

    return common.run_with_figure(fig, body)
