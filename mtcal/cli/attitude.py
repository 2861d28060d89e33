"""``mtcal attitude LOG`` — QNCF attitude (wang2023cja Eq 5–8) of a log to CSV/Parquet (or ``--filter`` another).

The filter runs at the mean sample rate with per-sample-dt weighted gyro; its
AMD gate uses the **measured** |a| at rest (not 9.80665) and a threshold no
tighter than the rest band, so a sensor reading 1–3 % off g still gets its
accelerometer corrections. The start attitude is levelled from the first rest
(yaw 0) and that rest's mean gyro is removed as the initial bias. Output columns: ``time_s, q0, q1, q2, q3`` (scalar-first, sensor →
world), ``yaw_deg, pitch_deg, roll_deg`` (Eq 8: yaw about z, pitch about x,
roll about y; exact at pitch ±90° with roll 0 there), ``is_static``.

``--filter {qncf,vqf,basicvqf,mahony,madgwick,fusion}`` runs another filter on the same log
(same checks, same output schema), each at its documented default gains: ``vqf`` is exactly
``vqf.VQF(dt).updateBatch(gyr, acc)["quat6D"]`` and ``basicvqf`` ``vqf.BasicVQF(dt)…`` (Laidig &
Seel 2023; gyro sample k integrated over t_(k-1)..t_k as their convention; heading free, z up),
``mahony``, ``madgwick`` (``ahrs``' filter, run by its compiled equivalent, β 0.033) and ``fusion``
(``imufusion``, gain 0.5) through :func:`mtcal.filters.anchors.run_attitude_filter`, levelled from the
first 100 samples.

The command parses the options into one :class:`mtcal.systems.attitude.AttitudeConfig`
(:func:`mtcal.cli.common.attitude_config`), reads the log, calls the attitude system once
(:func:`mtcal.systems.attitude.attitude_record`: rests, clipped gyro, units check, filter), prints and writes.
"""

from __future__ import annotations

import argparse

import numpy as np

from mtcal.cli import common, logio
from mtcal.systems.attitude import FILTERS

EXAMPLE = """output columns: time_s (s), q0, q1, q2, q3 (sensor -> world, scalar-first),
  yaw_deg, pitch_deg, roll_deg (wang2023cja Eq 8 ZXY), is_static (0/1)
example:
  mtcal attitude flight.csv --out attitude.parquet --figure attitude.png
  mtcal attitude datasets/broad2021/trials/01_undisturbed_slow_rotation_A.mat --filter vqf
  mtcal attitude raw.csv --gyro-scale 0.0175 --gyro-unit deg/s --accel-scale 0.000244 --accel-unit g"""


def run(args: argparse.Namespace) -> int:
    fig = common.DiagnosticsFigure(args.figure, f"mtcal attitude {args.log}", inputs=[args.log])
    out = common.table_output(args, [args.log])

    def body() -> int:
        from mtcal.systems.attitude import attitude_record

        log = logio.read_log(args.log, common.input_options(args), need="raw")
        fig.log = log
        config = common.attitude_config(args)
        try:
            res = attitude_record(log.gyro_rad_s, log.accel_m_s2, log.dt_mean_s, config, time_s=log.time_s,
                                  unit_stated=log.gyro_unit_stated)
        except (ValueError, ImportError) as exc:  # what the refusal saw: the rests (figure), the clipping warning
            fig.report = getattr(exc, "rests", None)
            _print_clipping(*getattr(exc, "clipped", (np.zeros(0, bool), 0.0)))
            if isinstance(exc, ImportError):
                raise ValueError(_missing_package(args.filter, exc)) from None
            raise
        rep = fig.report = res.rests
        _print_clipping(res.clipped, res.clip_level_rad_s)
        e = common.euler_deg(res.q_ws)
        if fig.path is not None:
            fig.series = {"pitch/roll (deg)": np.maximum(np.abs(e[:, 1]), np.abs(e[:, 2]))}
        common.write_attitude(out, log.time_s, res.q_ws, e, is_static=rep.is_static.astype(np.int8))
        common.print_report(log, rep, angle_deg=e[:, 1], angle_name="pitch_deg")
        common.print_units_check(res.units_check)
        if res.setup is not None:
            info = common.qncf_info(log, res.setup)
            print(f"qncf: g {info['gravity_m_s2']:.4f} m/s^2, AMD threshold {info['amd_threshold_pct']:.2f} %, "
                  f"K_p {info['kp_rad_s']:.4g} /s, K_i {info['ki_rad_s2']:.4g} /s^2, levelled from the "
                  f"{info['levelled_from']}")
            if "gyro_bias_text" in info:
                print(info["gyro_bias_text"])
            if res.setup.gate_warning:
                print(f"warning: {res.setup.gate_warning}")
        else:
            print(f"{args.filter}: {res.gain_text}")
        print(f"attitude: {log.n} samples written to {out}; final yaw/pitch/roll "
              f"{e[-1, 0]:.3f}/{e[-1, 1]:.3f}/{e[-1, 2]:.3f} deg")
        return 0

    return common.run_with_figure(fig, body)


def _print_clipping(clipped: np.ndarray, level_rad_s: float) -> None:
    """The warning line for gyro samples on a full-scale plateau (none: nothing printed)."""
    if clipped.any():
        print(f"warning: gyro clipped at {np.degrees(level_rad_s):.1f} deg/s in {int(clipped.sum())} samples")


def _missing_package(name: str, exc: ImportError) -> str:
    """The one-line message for a ``--filter`` whose library is not installed."""
    from mtcal.filters import registry

    package = "vqf" if name in ("vqf", "basicvqf") else registry.get_filter(name).requires
    return (f"--filter {name} needs the optional {package} package: pip install 'mtcal[bench]' "
            f"(from a source checkout: pip install '.[bench]')")


__all__ = ["register", "run", "FILTERS"]


def register(subparsers) -> None:
    """Add the ``attitude`` subcommand."""
    p = subparsers.add_parser("attitude", help="QNCF attitude of a log (wang2023cja) to CSV/Parquet",
                              description=common.description_with_schema(__doc__, 2), epilog=EXAMPLE)
    p.add_argument("log", help=f"IMU log ({common.LOG_FORMATS})")
    p.add_argument("--out", default="attitude.csv", help="output table (.csv or .parquet)")
    p.add_argument("--filter", choices=FILTERS, default="qncf",
                   help="attitude filter: qncf (wang2023cja), vqf/basicvqf (vqf), mahony, madgwick (ahrs), "
                        "fusion (imufusion) at their default gains; those four need the optional bench extra "
                        "(pip install 'mtcal[bench]', from a checkout '.[bench]')")
    common.add_input_options(p)
    common.add_rest_options(p, min_rest_s=0.2)
    p.set_defaults(func=run)
