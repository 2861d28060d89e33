"""``mtcal attitude LOG`` — QNCF attitude (wang2023cja Eq 5–8) of a log to CSV/Parquet.

The filter runs at the mean sample rate with per-sample-dt weighted gyro; its
AMD gate uses the **measured** |a| at rest (not 9.80665) and a threshold no
tighter than the rest band, so a sensor reading 1–3 % off g still gets its
accelerometer corrections. The start attitude is levelled from the first rest
(yaw 0) and that rest's mean gyro is removed as the initial bias. Output columns: ``time_s, q0, q1, q2, q3`` (scalar-first, sensor →
world), ``yaw_deg, pitch_deg, roll_deg`` (Eq 8: yaw about z, pitch about x,
roll about y; exact at pitch ±90° with roll 0 there), ``is_static``.
"""

from __future__ import annotations

import argparse

import numpy as np

from mtcal.cli import common, logio
from mtcal.systems import plausibility

EXAMPLE = """output columns: time_s (s), q0, q1, q2, q3 (sensor -> world, scalar-first),
  yaw_deg, pitch_deg, roll_deg (wang2023cja Eq 8 ZXY), is_static (0/1)
example:
  mtcal attitude flight.csv --out attitude.parquet --figure attitude.png
  mtcal attitude raw.csv --gyro-scale 0.0175 --gyro-unit deg/s --accel-scale 0.000244 --accel-unit g"""


def qncf_params(rep):
    """QNCF parameters adapted to the measured rest level (gravity and AMD threshold)."""
    from mtcal.filters.qncf import QncfParams

    half = 0.5 * (rep.band_m_s2[1] - rep.band_m_s2[0])
    return QncfParams(gravity_m_s2=rep.gravity_m_s2,
                      amd_threshold_pct=max(0.3, 100.0 * half / rep.gravity_m_s2))


def qncf_settings(log: logio.ImuLog, rep) -> tuple[np.ndarray, object, np.ndarray | None, dict]:
    """How ``mtcal`` runs the QNCF on a raw log: filter gyro (rad/s), parameters, start attitude, description.

    With the paper's rest detector (``rep.method == "paper"``) the QNCF runs exactly
    as before the adaptive detector existed: default :class:`QncfParams`, levelled
    from the first 100 samples, no initial bias removed. Otherwise the parameters
    follow the measured rest level, the start is levelled from the first rest and
    that rest's mean gyro is removed.
    """
    from mtcal.filters.qncf import QncfParams, initial_attitude_from_accel

    paper = rep.method == "paper"
    params = QncfParams() if paper else qncf_params(rep)
    first = rep.rests[0] if rep.rests and not paper else None
    gyro = log.gyro_for_filter()
    core = None
    if first is not None and first.start <= max(int(0.25 * log.fs_hz), 1):
        core = common.rest_bias(log, rep, first)
        q0 = initial_attitude_from_accel(log.accel_m_s2[core.core].mean(axis=0))
        bias = core.bias_rad_s
        gyro = gyro - bias  # the QNCF's integral term cannot see a bias about the vertical
        init = "first rest (gyro bias of its quiet core removed)"
    else:
        q0, bias = None, np.zeros(3)
        init = "first 100 samples (log does not start at rest)"
    info = {"filter": "qncf", "gravity_m_s2": params.gravity_m_s2,
            "amd_threshold_pct": params.amd_threshold_pct, "kp_rad_s": params.kp_rad_s,
            "ki_rad_s2": params.ki_rad_s2, "levelled_from": init,
            "initial_gyro_bias_rad_s": bias.tolist()}
    if core is not None:
        info["gyro_bias_text"] = common.rest_bias_text(log, core)
    return gyro, params, q0, info


def sensor_attitude(log: logio.ImuLog, rep, *, skip=None) -> tuple[np.ndarray, dict]:
    """QNCF sensor attitude (N, 4) of a raw log and a description of how it was made (:func:`qncf_settings`).

    The gyro's units and time base are checked first (:func:`mtcal.systems.plausibility.check_units`
    on the rests of ``rep``, ``skip``: e.g. clipped samples; its result is ``info["units_check"]``);
    the filter then runs without repeating that check.
    """
    from mtcal.filters.qncf import qncf_trusted

    gyro, params, q0, info = qncf_settings(log, rep)
    info["units_check"] = plausibility.check_units(log.gyro_for_filter(), log.accel_m_s2, log.dt_mean_s,
                                                   rep.rests, time_s=log.time_s, skip=skip)
    res = qncf_trusted(gyro, log.accel_m_s2, log.dt_mean_s, params, q0=q0, return_euler=False)
    return res.q_ws, info


def run(args: argparse.Namespace) -> int:
    fig = common.DiagnosticsFigure(args.figure, f"mtcal attitude {args.log}", inputs=[args.log])
    out = logio.check_output_path(args.out, [args.log])

    def body() -> int:
        log = logio.read_log(args.log, common.input_options(args), need="raw")
        fig.log = log
        rep = common.detect(args, log)
        fig.report = rep
        clipped, level = plausibility.clipped_samples(log.gyro_rad_s)
        if clipped.any():
            print(f"warning: gyro clipped at {np.degrees(level):.1f} deg/s in {int(clipped.sum())} samples")
        q, info = sensor_attitude(log, rep, skip=clipped)
        chk = info["units_check"]
        e = common.euler_deg(q)
        if fig.path is not None:
            fig.series = {"pitch/roll (deg)": np.maximum(np.abs(e[:, 1]), np.abs(e[:, 2]))}
        common.write_attitude(out, log.time_s, q, e, is_static=rep.is_static.astype(np.int8))
        common.print_report(log, rep, angle_deg=e[:, 1], angle_name="pitch_deg")
        print(f"gyro units check ({chk['method']}): {chk['evidence']}")
        print(f"qncf: g {info['gravity_m_s2']:.4f} m/s^2, AMD threshold {info['amd_threshold_pct']:.2f} %, "
              f"levelled from the {info['levelled_from']}")
        if "gyro_bias_text" in info:
            print(info["gyro_bias_text"])
        print(f"attitude: {log.n} samples written to {out}; final yaw/pitch/roll "
              f"{e[-1, 0]:.3f}/{e[-1, 1]:.3f}/{e[-1, 2]:.3f} deg")
        return 0

    return common.run_with_figure(fig, body)


__all__ = ["register", "run", "sensor_attitude", "qncf_settings", "qncf_params"]


def register(subparsers) -> None:
    """Add the ``attitude`` subcommand."""
    p = subparsers.add_parser("attitude", help="QNCF attitude of a log (wang2023cja) to CSV/Parquet",
                              description=common.description_with_schema(__doc__, 2), epilog=EXAMPLE,
                              formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("log", help="IMU log (CSV or Parquet)")
    p.add_argument("--out", default="attitude.csv", help="output table (.csv or .parquet)")
    common.add_input_options(p)
    common.add_rest_options(p, min_rest_s=0.2)
    p.set_defaults(func=run)
