"""``mtcal apply Q.json LOG`` — calibrated body attitude of a log (absolute by default, or wang2023cja Eq 10).

Reads the calibration written by ``mtcal calibrate --out Q.json`` and builds the
sensor attitude of LOG as ``calibrate`` did (QNCF of the raw columns, levelled from
the first rest with the gyro bias of its quiet core removed, or the log's own q0..q3).
As ``mtcal attitude``, a log in which the rest options find no rest is not refused: one
``warning:`` line gives the evidence and the QNCF starts from the first 100 samples
without a gyro bias removed (the output says so).
``--mode absolute`` (default): pitch and roll referenced to gravity, ``q_body =
q_sensor ⊗ conj(q_bs)`` with the calibration's mounting, heading (yaw) zeroed at the
first sample — right for a log that starts anywhere (a parked aircraft).
``--mode relative``: the paper's Eq 10, ``q_body = normalize(Q̂ q_sensor)`` with the
sensor attitude zeroed at the first sample — angles relative to where the log starts,
right only when it starts at the mechanism zero (a turntable); a log whose first rest is
tilted more than the calibration's accuracy gets a warning. Output columns: ``time_s,
q0, q1, q2, q3`` (body → world), ``yaw_deg, pitch_deg, roll_deg`` (Eq 8), the
uncalibrated ``sensor_yaw_deg, sensor_pitch_deg, sensor_roll_deg`` and, for a raw gyro/accel log,
``is_static`` (0/1: the sample lies in a rest found by the rest detector).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from mtcal.cli import common, logio

EXAMPLE = """output columns: time_s, q0..q3 (calibrated body attitude), yaw_deg, pitch_deg, roll_deg,
  sensor_yaw_deg, sensor_pitch_deg, sensor_roll_deg (before calibration); Eq 8 ZXY angles
  (yaw about z, pitch about x, roll about y); is_static (0/1, in a detected rest; raw gyro/accel logs)
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
        doc = json.loads(p.read_text(encoding="utf-8-sig"))    # (a byte-order mark, as an editor may save it)
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
    if q.shape != (4, 4):
        raise ValueError(f"{path}: q_hat must be a 4x4 array, got shape {q.shape}")
    if not np.all(np.isfinite(q)):
        raise ValueError(f"{path}: q_hat must be finite (no NaN or inf)")
    if any(isinstance(x, bool) for row in doc["q_hat"] for x in row):
        raise ValueError(f"{path}: q_hat must be a 4x4 array of numbers, not true/false")
    check_calibration_fields(doc, path)
    _check_recorded_so4_distance(q, doc, path)
    return q, doc


def _check_recorded_so4_distance(q: np.ndarray, doc: dict, path) -> None:
    """A recorded ``so4_distance`` above the default gate widens the gate :func:`max_so4_distance` applies, so it must
    be the distance of the file's own ``q_hat`` (as ``mtcal calibrate`` writes it): an edited value is refused."""
    from mtcal.methods.constrained_fit import project_to_so4
    from mtcal.systems.installation import MAX_SO4_DISTANCE

    recorded = doc.get("so4_distance")
    if recorded is None or recorded <= MAX_SO4_DISTANCE:
        return
    actual = float(project_to_so4(q).distance)
    if abs(actual - recorded) > 1e-6 * max(1.0, recorded):
        raise ValueError(f"{path}: field 'so4_distance' ({recorded:.6g}) is not the distance of the file's q_hat from "
                         f"SO(4) ({actual:.6g}); the file was edited (recalibrate, or restore the value)")


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and bool(np.isfinite(v))


def _numbers(v, shape: tuple) -> bool:
    """``v`` a nested list of finite numbers (not booleans) of ``shape`` (``None`` in it: any length)."""
    if not shape:
        return _is_number(v)
    return (isinstance(v, list) and (shape[0] is None or len(v) == shape[0])
            and all(_numbers(x, shape[1:]) for x in v))


#: The fields of a calibration file (``mtcal calibrate --out``; all but ``format`` and ``q_hat`` optional, a
#: version-1 file has fewer) → (what they must be, the check). ``input`` and ``attitude`` are checked per key below.
_STR = ("a string", lambda v: isinstance(v, str))
_ANGLES = lambda keys: (f"an object of finite numbers {', '.join(keys)}",  # noqa: E731
                        lambda v: isinstance(v, dict) and sorted(v) == sorted(keys) and all(map(_is_number, v.values())))
_ALPHAS = ("alpha1_z", "alpha2_y", "alpha3_x")
CALIBRATION_FIELDS = {
    "format_version": ("an integer", lambda v: isinstance(v, int) and not isinstance(v, bool)),
    "mtcal_version": _STR, "comment": _STR, "log": _STR, "positions_file": _STR,
    "model": ("one of eq13, so4, mounting", lambda v: v in ("eq13", "so4", "mounting")),
    "so4_distance": ("a finite number >= 0", lambda v: _is_number(v) and v >= 0),
    "installation_angles_deg": _ANGLES(_ALPHAS),
    "installation_angles_1sigma_deg": ("null or an object of finite numbers >= 0 alpha1_z, alpha2_y, alpha3_x",
                                       lambda v: v is None or (_ANGLES(_ALPHAS)[1](v) and min(v.values()) >= 0)),
    "installation_angles_uncertainty": _STR, "installation_angles_meaning": _STR,
    "mounting_quaternion_q_bs": ("a unit quaternion of 4 finite numbers",
                                 lambda v: _numbers(v, (4,)) and abs(float(np.linalg.norm(v)) - 1.0) < 1e-6),
    "mounting_meaning": _STR,
    "mounting_ypr_deg": _ANGLES(("yaw_z", "pitch_x", "roll_y")),
    "reference_offset_quaternion": ("a unit quaternion of 4 finite numbers",
                                    lambda v: _numbers(v, (4,)) and abs(float(np.linalg.norm(v)) - 1.0) < 1e-6),
    "positions_deg": ("a list of [yaw, pitch, roll] finite numbers", lambda v: _numbers(v, (None, 3))),
    "positions_convention": _STR,
    "residual_deg": ("a list of finite numbers >= 0", lambda v: _numbers(v, (None,)) and all(x >= 0 for x in v)),
    "residual_max_deg": ("a finite number >= 0", lambda v: _is_number(v) and v >= 0),
    "rests_s": ("a list of [start, stop] finite numbers", lambda v: _numbers(v, (None, 2))),
    "convention": _STR,
}
_OPTIONAL_NUMBER = ("null or a finite number", lambda v: v is None or _is_number(v))
_SCALE = ("null or a list of 1 or 3 finite numbers",
          lambda v: v is None or (_numbers(v, (None,)) and len(v) in (1, 3)))
#: The keys of the ``input`` and ``attitude`` objects that ``mtcal calibrate`` writes.
CALIBRATION_SUBFIELDS = {
    "input": {"time_unit": _STR, "gyro_unit": _STR, "accel_unit": _STR, "gyro_scale": _SCALE, "accel_scale": _SCALE,
              "columns": ("an object of strings", lambda v: isinstance(v, dict)
                          and all(isinstance(x, str) for x in v.values())),
              "fs_hz_option": _OPTIONAL_NUMBER,
              "sample_rate_hz": ("a finite number > 0", lambda v: _is_number(v) and v > 0),
              "interpretation": ("a list of strings", lambda v: isinstance(v, list)
                                 and all(isinstance(x, str) for x in v)),
              "attitude_source": _STR},
    "attitude": {"filter": _STR, "gravity_m_s2": ("a finite number > 0", lambda v: _is_number(v) and v > 0),
                 "amd_threshold_pct": _OPTIONAL_NUMBER, "kp_rad_s": _OPTIONAL_NUMBER, "ki_rad_s2": _OPTIONAL_NUMBER,
                 "levelled_from": _STR, "gyro_bias_text": _STR,
                 "initial_gyro_bias_rad_s": ("a list of 3 finite numbers", lambda v: _numbers(v, (3,))),
                 "zeroed_at_first_sample": ("true or false", lambda v: isinstance(v, bool))},
}


def check_calibration_fields(doc: dict, path) -> None:
    """Every known field of a calibration document (:data:`CALIBRATION_FIELDS`), checked when the file is read,
    before anything is computed or written: one-line ValueError naming the file and the field. Unknown fields
    (a newer writer's) are ignored; missing optional ones are fine (a version-1 file has fewer).

    Examples
    --------
    >>> check_calibration_fields({"residual_deg": [0.01, 0.02], "installation_angles_1sigma_deg": None}, "Q.json")
    >>> check_calibration_fields({"residual_deg": "x"}, "Q.json")
    Traceback (most recent call last):
    ...
    ValueError: Q.json: field 'residual_deg' must be a list of finite numbers >= 0, got "x"
    """
    def bad(name, what, value):
        text = json.dumps(value, default=str)
        return ValueError(f"{path}: field {name!r} must be {what}, got {text if len(text) <= 60 else text[:57] + '...'}")

    for name, (what, ok) in CALIBRATION_FIELDS.items():
        if name in doc and not ok(doc[name]):
            raise bad(name, what, doc[name])
    for name, fields in CALIBRATION_SUBFIELDS.items():
        if name not in doc:
            continue
        if not isinstance(doc[name], dict):
            raise bad(name, "an object", doc[name])
        for key, (what, ok) in fields.items():
            if key in doc[name] and not ok(doc[name][key]):
                raise bad(f"{name}.{key}", what, doc[name][key])
    if "residual_deg" in doc and "positions_deg" in doc and len(doc["residual_deg"]) != len(doc["positions_deg"]):
        raise ValueError(f"{path}: field 'residual_deg' has {len(doc['residual_deg'])} values for "
                         f"{len(doc['positions_deg'])} positions_deg")


def max_so4_distance(doc: dict) -> float:
    """The largest distance of Q̂ from SO(4) that ``mtcal apply`` accepts for a calibration file: the default gate
    of ``mtcal calibrate`` (:data:`mtcal.systems.installation.MAX_SO4_DISTANCE`), or the distance the file records
    (a calibration made with a wider ``--max-so4-distance``), whichever is larger."""
    from mtcal.systems.installation import MAX_SO4_DISTANCE

    recorded = doc.get("so4_distance")
    ok = isinstance(recorded, (int, float)) and not isinstance(recorded, bool) and np.isfinite(recorded)
    return max(MAX_SO4_DISTANCE, float(recorded) * (1.0 + 1e-9) if ok else 0.0)


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
    """Entry point of ``mtcal apply``: read the calibration and the log, one procedure, print and write."""
    fig = common.DiagnosticsFigure(args.figure, f"mtcal apply {args.log}", inputs=[args.log, args.calibration])
    out = common.table_output(args, [args.log, args.calibration])

    def body() -> int:
        # numba/scipy: loaded when the command runs, not for --help
        from mtcal.systems.installation import InstallationConfig, RecordRefused, apply_record

        q_hat, doc = load_calibration_file(args.calibration)
        log = logio.read_log(args.log, common.input_options(args), need="raw_or_quat")
        fig.log = log if log.accel_m_s2 is not None else None
        raw = log.gyro_rad_s is not None
        cfg = InstallationConfig.command_line(rest_detector=common.rests_config(args) if raw else None,
                                              max_so4_distance=max_so4_distance(doc))
        try:
            res = apply_record(cfg, q_hat, log.dt_mean_s, mode=args.mode, **common.log_arrays(log))
        except RecordRefused as exc:
            fig.report = exc.report
            raise
        fig.report = res.report
        _print_result(args, out, log, doc, res)
        return 0

    return common.run_with_figure(fig, body)


def _print_result(args, out, log, doc: dict, res) -> None:
    """What ``mtcal apply`` writes and prints of a :class:`~mtcal.systems.installation.RecordApplication`.

    The table is written first, then every line is printed (units check, the relative mode's tilt
    warning, the rest report, the gyro-bias line, how the body attitude was made, the mounting, the summary).
    """
    rep = res.report
    eb = np.degrees(res.body_euler_rad, out=res.body_euler_rad)     # in place (a long log): rad not read after
    es = np.degrees(res.sensor_euler_rad, out=res.sensor_euler_rad)
    extra = {"sensor_yaw_deg": es[:, 0], "sensor_pitch_deg": es[:, 1], "sensor_roll_deg": es[:, 2]}
    if rep is not None:
        extra["is_static"] = rep.is_static.astype(np.int8)
    common.write_attitude(out, log.time_s, res.attitude.q_body, eb, **extra)
    lines = [] if res.units_check is None else [common.units_check_line(res.units_check)]
    if args.mode == "absolute":
        how = ("absolute: pitch and roll referenced to gravity (" +
               (f"QNCF levelled from the {res.qncf.levelled_from}" if res.qncf is not None
                else "the log's q0..q3, z-up world") +
               "), q_body = q_sensor (x) conj(q_bs) with the calibration's mounting; heading (yaw) zeroed at "
               "the first sample (gravity gives no heading)")
    else:
        how = ("relative (wang2023cja Eq 10): q_body = normalize(Q_hat q_sensor), sensor attitude zeroed at the "
               "first sample: angles relative to where the log starts")
        lines += _tilt_warning(log, res, doc)
    bias = (common.rest_bias_text(log, res.qncf.quiet_core)      # printed after the rests, made first
            if res.qncf is not None and res.qncf.quiet_core is not None else None)
    if rep is not None:
        lines += common.report_lines(log, rep, angle_deg=eb[:, 1], angle_name="pitch_deg")
    if bias is not None:
        lines.append(bias)
    if res.qncf is not None and res.qncf.gate_warning:
        lines.append(f"warning: {res.qncf.gate_warning}")
    mount = np.degrees(res.mounting_euler_rad)
    lines += [f"body attitude {how}",
              f"mounting q_bs = [{', '.join(f'{v:+.6f}' for v in res.q_bs)}] (sensor on the body at yaw {mount[0]:+.4f}, "
              f"pitch {mount[1]:+.4f}, roll {mount[2]:+.4f} deg) from {args.calibration}"
              + (f" ({doc['comment']})" if doc.get("comment") else ""),
              f"apply: {log.n} samples written to {out}; first body yaw/pitch/roll "
              f"{eb[0, 0]:.3f}/{eb[0, 1]:.3f}/{eb[0, 2]:.3f} deg, final {eb[-1, 0]:.3f}/{eb[-1, 1]:.3f}/{eb[-1, 2]:.3f} deg"]
    print("\n".join(lines))


def _tilt_warning(log, res, doc: dict) -> list[str]:
    """Relative mode: one warning line when the log's start is tilted beyond the calibration's accuracy."""
    if res.start_euler_rad is None:
        return []
    if res.start_rest is not None:
        where = f"at the first rest ({log.time_s[res.start_rest.start]:.2f} s)"
    else:
        where = "at the first sample (log's q0..q3)"
    e = np.degrees(res.start_euler_rad)
    acc = _accuracy_deg(doc)
    if max(abs(e[1]), abs(e[2])) <= acc:
        return []
    return [f"warning: --mode relative: the body is tilted {where}: pitch {e[1]:+.3f}, roll {e[2]:+.3f} deg from "
            f"gravity, more than the calibration's accuracy {acc:.3f} deg; the output pitch/roll are relative to that "
            f"start and are off by about that much from gravity-referenced angles (use --mode absolute)"]


__all__ = ["register", "run", "load_calibration", "load_calibration_file", "max_so4_distance",
           "check_calibration_fields", "CALIBRATION_FIELDS"]


def register(subparsers) -> None:
    """Add the ``apply`` subcommand."""
    p = subparsers.add_parser("apply", help="apply a calibration (Q.json) to a log: calibrated attitude",
                              description=common.description_with_schema(__doc__, 2), epilog=EXAMPLE)
    p.add_argument("calibration", help="JSON written by `mtcal calibrate --out`")
    p.add_argument("log", help=f"IMU log ({common.LOG_FORMATS}): raw gyro/accel, or q0..q3 columns of a table")
    p.add_argument("--out", default="body_attitude.csv", help="output table (.csv or .parquet)")
    p.add_argument("--mode", choices=["absolute", "relative"], default="absolute",
                   help="absolute: pitch/roll referenced to gravity, heading zeroed at the first sample; "
                        "relative: the paper's Eq 10, angles relative to where the log starts (turntable zero)")
    common.add_input_options(p)
    common.add_rest_options(p, min_rest_s=0.2)
    p.set_defaults(func=run)
