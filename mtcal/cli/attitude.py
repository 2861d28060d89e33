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
  mtcal attitude datasets/broad2021/trials/01_undisturbed_slow_rotation_A.mat --filter vqf
  mtcal attitude raw.csv --gyro-scale 0.0175 --gyro-unit deg/s --accel-scale 0.000244 --accel-unit g"""


def qncf_params(rep):
    """QNCF parameters from the rests' levels and noise: :func:`mtcal.systems.attitude.qncf_params_from_rests`."""
    from mtcal.systems.attitude import qncf_params_from_rests

    return qncf_params_from_rests(rep)


def qncf_settings(log: logio.ImuLog, rep) -> tuple[np.ndarray, object, np.ndarray | None, dict]:
    """How ``mtcal`` runs the QNCF on a raw log: filter gyro (rad/s), parameters, start attitude, description.

    With the paper's rest detector (``rep.method == "paper"``) the QNCF runs exactly
    as before the adaptive detector existed: default :class:`QncfParams`, levelled
    from the first 100 samples, no initial bias removed. Otherwise the parameters
    follow the measured rest level, the start is levelled from the first rest and
    that rest's mean gyro is removed.
    """
    from mtcal.systems.attitude import qncf_log_setup

    setup = qncf_log_setup(log.gyro_for_filter(), log.accel_m_s2, log.dt_mean_s, rep, gyro_rad_s=log.gyro_rad_s)
    params = setup.params
    info = {"filter": "qncf", "gravity_m_s2": params.gravity_m_s2,
            "amd_threshold_pct": params.amd_threshold_pct, "kp_rad_s": params.kp_rad_s,
            "ki_rad_s2": params.ki_rad_s2, "levelled_from": setup.levelled_from,
            "initial_gyro_bias_rad_s": setup.bias_rad_s.tolist()}
    if setup.quiet_core is not None:
        info["gyro_bias_text"] = common.rest_bias_text(log, setup.quiet_core)
    return setup.gyro_rad_s, params, setup.q0, info


#: ``--filter`` choices; ``qncf`` (the paper's filter) is the default.
FILTERS = ("qncf", "vqf", "basicvqf", "mahony", "madgwick", "fusion")


def other_filter_attitude(name: str, log: logio.ImuLog) -> tuple[np.ndarray, dict]:
    """Sensor attitude (N, 4; scalar-first, sensor → world, z up) of a log by a non-QNCF filter at its defaults.

    ``vqf``/``basicvqf``: ``vqf.VQF(dt).updateBatch(gyr, acc)["quat6D"]`` (resp. ``BasicVQF``) on the
    log's gyro (rad/s, per-sample-dt weighted) and accelerometer (m/s²), ``dt`` the mean step; the
    others through :func:`mtcal.filters.anchors.run_attitude_filter` with the registry's default gain.
    """
    gyro = np.ascontiguousarray(log.gyro_for_filter(), dtype=float)
    acc = np.ascontiguousarray(log.accel_m_s2, dtype=float)
    if name in ("vqf", "basicvqf"):
        try:
            import vqf
        except ImportError:
            raise ValueError(f"--filter {name} needs the vqf package (pip install vqf)") from None
        cls = vqf.VQF if name == "vqf" else vqf.BasicVQF
        q = cls(log.dt_mean_s).updateBatch(gyro, acc)["quat6D"]
        return q, {"filter": name, "gain": f"{cls.__name__} defaults (tauAcc 3 s)"}
    from mtcal.filters import anchors, registry

    entry = registry.get_filter(name)
    try:
        q = anchors.run_attitude_filter(name, gyro[None], acc[None], log.dt_mean_s)[0]
    except ImportError as exc:
        raise ValueError(f"--filter {name} needs the {entry.requires} package ({exc})") from None
    return q, {"filter": name, "gain": f"{entry.gain_unit} {entry.default_gain:g} (default)"}


def sensor_attitude(log: logio.ImuLog, rep, *, skip=None) -> tuple[np.ndarray, dict]:
    """QNCF sensor attitude (N, 4) of a raw log and a description of how it was made (:func:`qncf_settings`).

    The gyro's units and time base are checked first (:func:`mtcal.systems.plausibility.check_units`
    on the rests of ``rep``, ``skip``: e.g. clipped samples; its result is ``info["units_check"]``);
    the filter then runs without repeating that check.
    """
    from mtcal.filters.qncf import qncf_trusted

    gyro, params, q0, info = qncf_settings(log, rep)
    info["units_check"] = plausibility.check_units(log.gyro_for_filter(), log.accel_m_s2, log.dt_mean_s,
                                                   rep.rests, time_s=log.time_s, skip=skip,
                                                   unit_stated=log.gyro_unit_stated)
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
        if args.filter == "qncf":
            q, info = sensor_attitude(log, rep, skip=clipped)
            chk = info["units_check"]
        else:
            chk = plausibility.check_units(log.gyro_for_filter(), log.accel_m_s2, log.dt_mean_s, rep.rests,
                                           time_s=log.time_s, skip=clipped, unit_stated=log.gyro_unit_stated)
            q, info = other_filter_attitude(args.filter, log)
        e = common.euler_deg(q)
        if fig.path is not None:
            fig.series = {"pitch/roll (deg)": np.maximum(np.abs(e[:, 1]), np.abs(e[:, 2]))}
        common.write_attitude(out, log.time_s, q, e, is_static=rep.is_static.astype(np.int8))
        common.print_report(log, rep, angle_deg=e[:, 1], angle_name="pitch_deg")
        common.print_units_check(chk)
        if args.filter == "qncf":
            print(f"qncf: g {info['gravity_m_s2']:.4f} m/s^2, AMD threshold {info['amd_threshold_pct']:.2f} %, "
                  f"K_p {info['kp_rad_s']:.4g} /s, K_i {info['ki_rad_s2']:.4g} /s^2, levelled from the "
                  f"{info['levelled_from']}")
        else:
            print(f"{info['filter']}: {info['gain']}")
        if "gyro_bias_text" in info:
            print(info["gyro_bias_text"])
        print(f"attitude: {log.n} samples written to {out}; final yaw/pitch/roll "
              f"{e[-1, 0]:.3f}/{e[-1, 1]:.3f}/{e[-1, 2]:.3f} deg")
        return 0

    return common.run_with_figure(fig, body)


__all__ = ["register", "run", "sensor_attitude", "qncf_settings", "qncf_params", "other_filter_attitude", "FILTERS"]


def register(subparsers) -> None:
    """Add the ``attitude`` subcommand."""
    p = subparsers.add_parser("attitude", help="QNCF attitude of a log (wang2023cja) to CSV/Parquet",
                              description=common.description_with_schema(__doc__, 2), epilog=EXAMPLE,
                              formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("log", help="IMU log (CSV, Parquet, .mat or .h5)")
    p.add_argument("--out", default="attitude.csv", help="output table (.csv or .parquet)")
    p.add_argument("--filter", choices=FILTERS, default="qncf",
                   help="attitude filter (default qncf, wang2023cja); vqf/basicvqf (vqf), mahony, madgwick (ahrs), "
                        "fusion (imufusion) at their default gains")
    common.add_input_options(p)
    common.add_rest_options(p, min_rest_s=0.2)
    p.set_defaults(func=run)
