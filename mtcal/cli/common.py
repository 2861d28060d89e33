"""Shared pieces of the ``mtcal`` subcommands: input/rest options, summaries, the diagnostics figure."""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

from mtcal.cli import logio
from mtcal.methods import rest_detection

__all__ = ["add_input_options", "add_rest_options", "input_options", "rests_config", "attitude_config", "detect", "log_arrays",
           "qncf_info", "rest_table", "print_report", "report_lines", "units_check_line",
           "finite_float", "table_output", "LOG_FORMATS", "DiagnosticsFigure", "run_with_figure", "SCHEMA_HELP", "description_with_schema",
           "QUATERNION_DECIMALS", "write_attitude", "euler_deg", "rest_bias_text",
           "print_units_check"]

SCHEMA_HELP = """log schema (CSV, comma/semicolon/tab, or Parquet .parquet/.pq: header row, one row per sample; extra
columns ignored; or N x 3 arrays of a MATLAB .mat (v5, v7.3) / HDF5 .h5/.hdf5 file: --columns
gyro=NAME,accel=NAME[,time=NAME], rate from 'sampling_rate' or --fs-hz; BROAD's imu_gyr/imu_acc/sampling_rate
opens as is):
  time_s                                    time (s), strictly increasing (jitter allowed)
  gyro_x_rad_s, gyro_y_rad_s, gyro_z_rad_s  angular rate (rad/s), sensor frame
  accel_x_m_s2, accel_y_m_s2, accel_z_m_s2  specific force (m/s^2); level at rest ~ +g on z
other units: --time-unit ms|us, --gyro-unit deg/s, --accel-unit g, --gyro-scale/--accel-scale
(counts -> unit, 1 or 3 factors), --columns time_s=Time,gyro_x=GyrX,... (or headers time_ms,
gyro_x_deg_s, accel_x_g); no time column: --fs-hz. Jittered timestamps: per-sample dt. Rests: measured from the data
(--rest-detector adaptive, default), the paper's fixed ZVD band (--rest-detector paper) or quasi-static
stance phases (--rest-detector shoe, Skog et al. 2010; level with --gyro-threshold-deg-s or --shoe-threshold).
Gyro units and time base are checked against the accelerometer (rest pairs, tilt rate, gravity tracking);
a stated unit (--gyro-unit, a unit header, BROAD's layout) that no check can decide is used with a warning."""


#: The files the log reader (:func:`mtcal.cli.logio.read_log`) accepts, for the LOG argument's help.
LOG_FORMATS = "CSV or Parquet (.parquet/.pq) table, or a MATLAB .mat (v5, v7.3) / HDF5 .h5/.hdf5 file's arrays"


def description_with_schema(doc: str, paragraphs: int) -> str:
    """A subcommand's ``--help`` description: the first ``paragraphs`` paragraphs of ``doc``, then :data:`SCHEMA_HELP`."""
    return "\n\n".join(doc.split("\n\n")[:paragraphs] + [SCHEMA_HELP])


#: Decimals of the quaternion columns in an attitude table (``logio.write_table``).
QUATERNION_DECIMALS = {"q0": 9, "q1": 9, "q2": 9, "q3": 9}


def write_attitude(path, time_s: np.ndarray, q: np.ndarray, euler_deg: np.ndarray, **extra) -> None:
    """Write an attitude table: ``time_s, q0..q3, yaw_deg, pitch_deg, roll_deg``, then ``extra`` columns in order.

    ``q`` (N, 4) scalar-first, ``euler_deg`` (N, 3) yaw/pitch/roll (deg, wang2023cja Eq 8).
    """
    cols = {"time_s": time_s, "q0": q[:, 0], "q1": q[:, 1], "q2": q[:, 2], "q3": q[:, 3],
            "yaw_deg": euler_deg[:, 0], "pitch_deg": euler_deg[:, 1], "roll_deg": euler_deg[:, 2], **extra}
    logio.write_table(path, cols, decimals=QUATERNION_DECIMALS)


def euler_deg(q: np.ndarray) -> np.ndarray:
    """Yaw/pitch/roll (deg, wang2023cja Eq 8 ZXY) of filter quaternions ``q`` (N, 4), unit by construction.

    Exactly ``np.degrees(rotations.euler_zxy_unchecked(q))``, in row blocks without full-length
    temporaries (:func:`mtcal.core.rotations.euler_zxy_rows_trusted`), converted in place.
    """
    from mtcal.core.rotations import euler_zxy_rows_trusted

    out = euler_zxy_rows_trusted(q)
    return np.degrees(out, out=out)


def print_units_check(chk: dict) -> None:
    """Print a :func:`mtcal.systems.plausibility.check_units` result: which evidence decided, or its one warning."""
    print(units_check_line(chk))


def units_check_line(chk: dict) -> str:
    """The line :func:`print_units_check` prints: which evidence decided, or the check's one warning."""
    return f"warning: {chk['warning']}" if chk.get("warning") else f"gyro units check ({chk['method']}): {chk['evidence']}"


def finite_float(text: str, name: str, *, positive: bool = True, high: float | None = None) -> float:
    """Parse a finite (positive) number for option ``name``, at most ``high`` when given (one-line ValueError
    otherwise)."""
    try:
        val = float(text)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {text!r}") from None
    if high is not None and not (math.isfinite(val) and (val > 0 or not positive) and val <= high):
        raise ValueError(f"{name} must be a number in {'(0' if positive else '(-inf'}, {high:g}], got {text!r}")
    if not math.isfinite(val) or (positive and val <= 0):
        raise ValueError(f"{name} must be a finite number{' > 0' if positive else ''}, got {text!r}")
    return val


def table_output(args, inputs) -> Path:
    """``--out`` of a command writing a table (CSV or Parquet by suffix): checked against the inputs and the
    command's ``--figure``, before any work."""
    return logio.check_output_path(args.out, inputs, suffixes=logio.TABLE_SUFFIXES,
                                   others=(("--figure", getattr(args, "figure", None)),))


def add_input_options(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("input units and columns")
    g.add_argument("--time-unit", choices=sorted(logio.TIME_UNITS), help="unit of the time column (default: s, or "
                   "as a time_ms/time_us header says)")
    g.add_argument("--gyro-unit", choices=list(logio.GYRO_UNITS), help="gyro unit (default: rad/s, or as a "
                   "gyro_x_deg_s header or BROAD's layout says)")
    g.add_argument("--accel-unit", choices=list(logio.ACCEL_UNITS), help="accelerometer unit (default: m/s2, "
                   "or as an accel_x_g header says)")
    g.add_argument("--gyro-scale", metavar="S|SX,SY,SZ", help="multiply gyro columns first (counts -> unit) "
                   "(default: 1, no scaling)")
    g.add_argument("--accel-scale", metavar="S|SX,SY,SZ", help="multiply accel columns first (counts -> unit) "
                   "(default: 1, no scaling)")
    g.add_argument("--columns", metavar="NAME=HEADER,...", help="map schema names to your headers (default: "
                   "the schema's names, or BROAD's imu_gyr/imu_acc arrays)")
    g.add_argument("--fs-hz", metavar="HZ", help="uniform sample rate for a log without a "
                   "time column (Hz) (default: from the time column, or a .mat/.h5 file's sampling_rate)")


def add_rest_options(p: argparse.ArgumentParser, *, min_rest_s: float | None, figure: bool = True) -> None:
    g = p.add_argument_group("rest detection")
    g.add_argument("--rest-detector", choices=["adaptive", "paper", "shoe"], default="adaptive",
                   help="adaptive (levels measured from the data), paper "
                        "(wang2022sensors Table 1 band 9.76-9.84 m/s^2) or shoe (SHOE/GLRT quasi-static "
                        "detector, Skog et al. 2010: finds a foot's stance phases; needs the gyro)")
    g.add_argument("--shoe-threshold", metavar="GAMMA", help="shoe: threshold gamma of the SHOE statistic T "
                   "(dimensionless, ~6 when still) (default: measured, or from --gyro-threshold-deg-s)")
    g.add_argument("--gravity", metavar="M_S2", help="|a| at rest (m/s^2) (default: measured)")
    g.add_argument("--accel-band", metavar="M_S2", help="half-width of the |a| band (m/s^2) (default: "
                   "max(K x accel noise, 1.5 %% of g), K = --noise-factor)")
    g.add_argument("--gyro-threshold-deg-s", metavar="DEG_S", help="max |w - bias| at rest (deg/s); "
                   "with --rest-detector shoe the quasi-static level (e.g. 30 for a foot's stance: gamma = 6 + "
                   "(level / gyro noise)^2) (default: max(K x gyro noise, 1.5), K = --noise-factor)")
    g.add_argument("--noise-factor", metavar="K", default="5",
                   help="thresholds = K x measured noise: rest detection and the quiet core of "
                        "the first rest that gives the gyro bias")
    g.add_argument("--min-rest-s", metavar="S", default=None if min_rest_s is None else str(min_rest_s),
                   help="shortest rest (s)" + (" (default: 1 with the adaptive or shoe detector, 2 with the "
                                               "paper detector or a q0..q3 log)" if min_rest_s is None else ""))
    if figure:
        p.add_argument("--figure", metavar="PNG", help="diagnostics figure (written also when the command fails) "
                                                      "(default: none)")


def input_options(args) -> logio.InputOptions:
    return logio.InputOptions(time_unit=args.time_unit, gyro_unit=args.gyro_unit, accel_unit=args.accel_unit,
                              gyro_scale=logio.parse_scale(args.gyro_scale, "--gyro-scale"),
                              accel_scale=logio.parse_scale(args.accel_scale, "--accel-scale"),
                              columns=logio.parse_columns(args.columns),
                              fs_hz=None if args.fs_hz is None else finite_float(args.fs_hz, "--fs-hz"))


def rests_config(args, *, has_gyro: bool = True):
    """The :class:`mtcal.systems.rests.RestsConfig` the rest options state (one-line ValueError naming the option).

    ``has_gyro``: the rests may use the log's gyro (it has one and ``--accel-only`` is not given).
    """
    from mtcal.systems.rests import RestsConfig

    min_rest = finite_float(args.min_rest_s, "--min-rest-s")
    opt = lambda v, n: None if v is None else finite_float(v, n)  # noqa: E731
    thr = opt(args.gyro_threshold_deg_s, "--gyro-threshold-deg-s")
    shoe_thr = opt(getattr(args, "shoe_threshold", None), "--shoe-threshold")
    if shoe_thr is not None and args.rest_detector != "shoe":
        raise ValueError("--shoe-threshold needs --rest-detector shoe")
    if args.rest_detector == "paper":
        return RestsConfig(detector="paper", min_rest_s=min_rest, use_gyro=has_gyro)
    if args.rest_detector == "shoe" and not has_gyro:
        raise ValueError("--rest-detector shoe needs the gyro columns (and not --accel-only)")
    noise = finite_float(args.noise_factor, "--noise-factor")
    gravity = opt(args.gravity, "--gravity")
    band = None if args.rest_detector == "shoe" else opt(args.accel_band, "--accel-band")
    try:
        return RestsConfig(detector=args.rest_detector, min_rest_s=min_rest, noise_factor=noise, gravity_m_s2=gravity,
                           accel_band_m_s2=band, gyro_threshold_rad_s=None if thr is None else np.radians(thr),
                           shoe_threshold=shoe_thr, use_gyro=has_gyro)
    except ValueError as exc:           # the config names its fields: say the options the user typed
        message = str(exc)
        for field, option in _REST_OPTIONS:
            message = message.replace(field, option)
        raise ValueError(message) from None


#: RestsConfig fields → the rest options that set them (for the config's refusals).
_REST_OPTIONS = (("gravity_m_s2", "--gravity"), ("accel_band_m_s2", "--accel-band"), ("min_rest_s", "--min-rest-s"),
                 ("noise_factor", "--noise-factor"), ("shoe_threshold", "--shoe-threshold"),
                 ("gyro_threshold_rad_s must be at most", "--gyro-threshold-deg-s must be at most"),
                 ("gyro_threshold_rad_s", "--gyro-threshold-deg-s (in rad/s)"))


def attitude_config(args):
    """The :class:`mtcal.systems.attitude.AttitudeConfig` that ``--filter`` and the rest options state."""
    from mtcal.systems.attitude import AttitudeConfig

    return AttitudeConfig(filter=args.filter, rests=rests_config(args))


def detect(args, log: logio.ImuLog, *, use_gyro: bool = True) -> rest_detection.RestReport:
    """Rests of a log by the rest options: :func:`mtcal.systems.rests.find_rests` with :func:`rests_config`.

    Rests whose listed duration (``t[stop-1] − t[start]``) is below ``--min-rest-s`` are moved to the
    rejected list, so a listing never shows a rest shorter than the stated minimum.
    """
    from mtcal.systems.rests import find_rests

    has_gyro = use_gyro and log.gyro_rad_s is not None
    config = rests_config(args, has_gyro=has_gyro)
    return find_rests(log.accel_m_s2, log.dt_mean_s, config, gyro_rad_s=log.gyro_rad_s if has_gyro else None,
                      time_s=log.time_s)


def log_arrays(log: logio.ImuLog) -> dict:
    """A log's arrays as the systems' log procedures take them (:func:`mtcal.systems.installation.calibrate_record`)."""
    raw = log.gyro_rad_s is not None
    return {"time_s": log.time_s, "accel_m_s2": log.accel_m_s2, "gyro_rad_s": log.gyro_rad_s,
            "filter_gyro_rad_s": log.gyro_for_filter() if raw else None, "q_ws": None if raw else log.q_ws,
            "gyro_unit_stated": log.gyro_unit_stated}


def qncf_info(log: logio.ImuLog, setup) -> dict:
    """What the commands print of a :class:`mtcal.systems.attitude.QncfLogSetup`: gains, start, bias line."""
    params = setup.params
    info = {"filter": "qncf", "gravity_m_s2": params.gravity_m_s2,
            "amd_threshold_pct": params.amd_threshold_pct, "kp_rad_s": params.kp_rad_s,
            "ki_rad_s2": params.ki_rad_s2, "levelled_from": setup.levelled_from,
            "initial_gyro_bias_rad_s": setup.bias_rad_s.tolist()}
    if setup.quiet_core is not None:
        info["gyro_bias_text"] = rest_bias_text(log, setup.quiet_core)
    return info


def rest_bias_text(log: logio.ImuLog, qc: rest_detection.QuietCore) -> str:
    """One line: which rest and which part of it gave the gyro bias, the bias and the threshold."""
    t = log.time_s
    b = np.degrees(qc.bias_rad_s)
    return (f"gyro bias {b[0]:+.4f} {b[1]:+.4f} {b[2]:+.4f} deg/s from the quiet core "
            f"{t[qc.core.start]:.3f}-{t[qc.core.stop - 1]:.3f} s of the first rest "
            f"{t[qc.rest.start]:.3f}-{t[qc.rest.stop - 1]:.3f} s (moving mean over {qc.window} samples within "
            f"{np.degrees(qc.threshold_rad_s):.4f} deg/s of the bias: {qc.noise_factor:g} x measured noise "
            f"{np.degrees(qc.noise_rad_s):.4f} deg/s / sqrt({qc.window}))")


def rest_table(log: logio.ImuLog, report: rest_detection.RestReport, angle_deg: np.ndarray | None = None,
               angle_name: str = "angle_deg", extra: dict | None = None) -> list[str]:
    """Per-rest summary lines: time span, duration, |a|, tilt from sensor z, mean gyro, angle, extras.

    The per-rest levels are :func:`mtcal.systems.rests.rests_table`'s (``mtcal rests --out``); ``|w|``
    is the norm of its mean gyro columns. ``angle_deg`` (N,) gives each rest's median angle;
    ``extra`` maps a column name to one value per rest.
    """
    from mtcal.systems.rests import rests_table

    cols = rests_table(log.time_s, log.accel_m_s2, report, gyro_rad_s=log.gyro_rad_s)
    has_gyro = log.gyro_rad_s is not None
    head = f"{'rest':>4} {'start_s':>10} {'stop_s':>10} {'dur_s':>7} {'|a|_m_s2':>9} {'tilt_deg':>9}"
    if has_gyro:
        head += f" {'|w|_deg_s':>9}"
        w_deg_s = np.linalg.norm(np.column_stack([cols[f"gyro_{ax}_deg_s"] for ax in "xyz"]), axis=1)
    if angle_deg is not None:
        head += f" {angle_name:>10}"
    for name in extra or {}:
        head += f" {name:>{max(10, len(name))}}"
    lines = [head]
    for i, r in enumerate(report.rests):
        line = (f"{i:>4} {cols['start_s'][i]:>10.3f} {cols['stop_s'][i]:>10.3f} {cols['duration_s'][i]:>7.3f} "
                f"{cols['accel_norm_m_s2'][i]:>9.4f} {cols['tilt_deg'][i]:>9.2f}")
        if has_gyro:
            line += f" {w_deg_s[i]:>9.3f}"
        if angle_deg is not None:
            line += f" {float(np.median(angle_deg[r])):>10.3f}"
        for name, vals in (extra or {}).items():
            line += f" {float(vals[i]):>{max(10, len(name))}.3f}"
        lines.append(line)
    return lines


def print_report(log: logio.ImuLog, report: rest_detection.RestReport, angle_deg=None, angle_name="angle_deg",
                 extra: dict | None = None) -> None:
    """Print :func:`report_lines` (log, rest levels, per-rest table, rejected stretches)."""
    print("\n".join(report_lines(log, report, angle_deg, angle_name, extra)))


def report_lines(log: logio.ImuLog, report: rest_detection.RestReport, angle_deg=None, angle_name="angle_deg",
                 extra: dict | None = None) -> list[str]:
    """The lines :func:`print_report` prints (log, rest levels, per-rest table, rejected stretches), as a list.

    Built from the finished report, the table first, so a command computes its summary and prints it after.
    """
    from mtcal.systems.rests import no_rests_evidence

    table = ["  " + line for line in rest_table(log, report, angle_deg, angle_name, extra)]
    # without rests: one warning line with the evidence (not a refusal: the user configured the detector; the
    # commands say what they did instead, e.g. the QNCF levelled from the first 100 samples, no gyro bias removed)
    warn = ([] if report.rests else
            [f"warning: no rest found by the {report.method} detector: {no_rests_evidence(report, log.time_s)}"])
    rejected = [f"  rejected {log.time_s[rej.span.start]:.3f}-{log.time_s[rej.span.stop - 1]:.3f} s: {rej.reason}"
                for rej in report.rejected[:10]]
    if len(report.rejected) > 10:
        rejected.append(f"  ... {len(report.rejected) - 10} more rejected stretches")
    n_rej = f", {len(report.rejected)} quiet stretches rejected" if report.rejected else ""
    head = [f"log: {log.path} ({log.n} samples at {log.fs_hz:.2f} Hz, {log.time_s[-1] - log.time_s[0]:.2f} s)"
            + (f"; {'; '.join(log.notes)}" if log.notes else ""),
            report.levels_text(),
            f"rests: {len(report.rests)} of >= {report.min_rest_s:g} s (duration stop_s - start_s){n_rej}"]
    return head + table + rejected + warn


def _envelope(t: np.ndarray, y: np.ndarray, buckets: int = 3000):
    """Min/max envelope (every sample inside one of ~``buckets`` buckets) for plotting long records fast."""
    if t.size <= 2 * buckets:
        return t, y, y
    idx = np.arange(0, t.size, -(-t.size // buckets))
    return t[idx], np.minimum.reduceat(y, idx), np.maximum.reduceat(y, idx)


def _trace(ax, t: np.ndarray, y: np.ndarray, **kw) -> None:
    """A long record as its min/max envelope, a short one as a line."""
    tt, lo, hi = _envelope(t, y)
    if lo is hi:
        ax.plot(tt, y, lw=0.7, **kw)
    else:
        ax.fill_between(tt, lo, hi, lw=0.5, **kw)


class DiagnosticsFigure:
    """Collects what a command learned and writes the figure in ``finally`` (also on failure)."""

    def __init__(self, path, title: str, inputs=()):
        self.path = None if path is None else logio.check_output_path(path, inputs, option="--figure")
        self.title = title
        self.log: logio.ImuLog | None = None
        self.report: rest_detection.RestReport | None = None
        self.used: list = []          # rests used by the method (slices)
        self.series: dict = {}        # extra panel: name -> (N,) array
        self.error: str | None = None

    def write(self) -> None:
        if self.path is None:
            return
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        has_gyro = self.log is not None and self.log.gyro_rad_s is not None
        stat = None if self.report is None else self.report.extra.get("decision_statistic")
        n_panels = 1 + has_gyro + bool(self.series) + (stat is not None and self.log is not None)
        fig, axes = plt.subplots(n_panels, 1, figsize=(9, 2.4 * n_panels + 0.6), sharex=True, squeeze=False)
        axes = axes[:, 0]
        status = "FAILED: " + self.error if self.error else "ok"
        fig.suptitle(f"{self.title} — {status}"[:160], fontsize=9)
        if self.log is None or self.log.accel_m_s2 is None:
            axes[0].text(0.5, 0.5, "log not loaded\n" + (self.error or ""), ha="center", va="center",
                         wrap=True, fontsize=8, transform=axes[0].transAxes)
        else:
            t = self.log.time_s
            norm = np.linalg.norm(self.log.accel_m_s2, axis=1)
            _, lo, hi = _envelope(t, norm)
            ax = axes[0]
            _trace(ax, t, norm, color="tab:blue", label="|a|")
            rep = self.report
            if rep is not None:
                ax.axhspan(rep.band_m_s2[0], rep.band_m_s2[1], color="tab:green", alpha=0.15,
                           label=f"rest band ({rep.method})")
                ax.axhline(rep.gravity_m_s2, color="tab:green", lw=0.6)
                for r in rep.rests:
                    ax.axvspan(t[r.start], t[r.stop - 1], color="tab:green", alpha=0.25, lw=0)
                for rej in rep.rejected:
                    ax.axvspan(t[rej.span.start], t[rej.span.stop - 1], color="tab:red", alpha=0.2, lw=0)
                    ax.text(t[rej.span.start], rep.band_m_s2[1], rej.reason[:40], fontsize=5, rotation=90,
                            va="bottom", color="tab:red")
            for r in self.used:
                ax.axvspan(t[r.start], t[r.stop - 1], color="tab:orange", alpha=0.35, lw=0)
            lo_all, hi_all = float(np.percentile(lo, 1)), float(np.percentile(hi, 99))
            if rep is not None:
                lo_all, hi_all = min(lo_all, rep.band_m_s2[0]), max(hi_all, rep.band_m_s2[1])
            pad = 0.2 * (hi_all - lo_all) + 0.05
            ax.set_ylim(lo_all - pad, hi_all + pad)
            ax.set_ylabel("|a| (m/s²)")
            ax.legend(loc="upper right", fontsize=7)
            ax.set_title("green: rests, red: rejected quiet stretches, orange: rests used", fontsize=8)
            k = 1
            if has_gyro:
                _trace(axes[k], t, np.degrees(np.linalg.norm(self.log.gyro_rad_s, axis=1)), color="tab:purple")
                if rep is not None and np.isfinite(rep.gyro_level_max_rad_s):
                    axes[k].axhline(np.degrees(rep.gyro_level_max_rad_s + np.linalg.norm(rep.gyro_bias_rad_s)),
                                    color="tab:green", lw=0.6, label="rest threshold (bias + level)")
                    axes[k].legend(loc="upper right", fontsize=7)
                axes[k].set_yscale("symlog", linthresh=1.0)
                axes[k].set_ylim(bottom=0)
                axes[k].set_ylabel("|ω| (°/s)")
                k += 1
            if stat is not None:
                ax = axes[k]
                _trace(ax, t, np.maximum(np.asarray(stat, float), 1e-3), color="tab:gray")
                ax.axhline(1.0, color="tab:red", lw=0.8, label="threshold" if rep.method != "shoe"
                           else f"threshold gamma {rep.extra['threshold']:.4g}")
                ax.set_yscale("log")
                ax.set_ylabel(rep.extra.get("decision_label", "statistic / threshold"), fontsize=7)
                ax.set_title(f"{rep.method} detector: statistic / threshold (static below 1)", fontsize=8)
                ax.legend(loc="upper right", fontsize=6)
                k += 1
            for name, y in self.series.items():
                _trace(axes[k], t, np.asarray(y, float), color="tab:red", label=name)
                axes[k].set_ylabel(name)
            axes[-1].set_xlabel("time (s)")
        out = self.path

        def save(tmp):
            fig.savefig(tmp, format="png", dpi=110, metadata={"Software": None})

        try:
            logio._atomic(out, save)
        except OSError as exc:
            raise OSError(f"--figure: {exc}") from None
        finally:
            plt.close(fig)
        print(f"figure: {out}")


def run_with_figure(fig: DiagnosticsFigure, body) -> int:
    """Run ``body()``; write the figure whatever happens (the command's error wins)."""
    try:
        return body()
    except Exception as exc:
        fig.error = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        try:
            fig.write()
        except Exception:  # noqa: BLE001 - the command's own error is the one to report
            pass
        raise
    finally:
        if fig.error is None:
            fig.write()
