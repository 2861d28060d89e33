"""Inclination RMSE of every ``mtcal attitude --filter`` on BROAD's shipped trials (broad2021), against optics.

Each trial is read by the command line's own log reader (``mtcal.cli.logio.read_log`` on the original
``.mat``: BROAD's layout, ``imu_gyr``/``imu_acc``/``sampling_rate``), its rests detected and units checked
as ``mtcal attitude`` does at default options, and every filter run through the procedure the command
calls (:func:`mtcal.systems.attitude.estimate_attitude` with
:meth:`~mtcal.systems.attitude.AttitudeConfig.cli_defaults`). The error is BROAD's inclination error (heading-free, earth frame; a 6D filter is judged
fairly) via :func:`mtcal.core.metrics.orientation_errors`, RMSE over the ``movement`` phase with
:func:`mtcal.core.metrics.rmse_over_phase`. The optical arrays are read separately with
:func:`mtcal.core.arrayfile.read_arrays`; no filter sees them.

Frames: BROAD's ``opt_quat`` is IMU (sensor) → ENU earth, scalar-first; mtcal's filters output sensor →
world (z up, heading arbitrary). The inclination error does not depend on a heading offset between the
two earth frames (a rotation about the vertical), so no alignment is needed.

Target (issue #31): QNCF's median inclination RMSE at most 1.25x VQF's (the median over trials of the per-trial
ratio, same run). The run also computes the cause when it is missed: the share of the movement phase during
which QNCF's AMD gate (wang2023cja §3.1: PI correction only while the AMD statistic is below Thr) is closed,
so the filter integrates the gyro alone, and the same QNCF with the gate always open (a diagnostic, not the
paper's filter: the accelerometer then enters with every linear acceleration).

Usage: ``python benchmarks/broad_accuracy.py [--csv build/bench/broad2021_accuracy.csv]`` (``make bench`` runs it).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
TRIALS = ROOT / "datasets" / "broad2021" / "trials"
#: issue #31: QNCF's median inclination RMSE relative to VQF's
TARGET_RATIO = 1.25


def trial_rows(filters=None, trials=None):
    """One dict per (trial, filter): inclination RMSE (deg) over the movement phase, units check, time."""
    from mtcal.cli import common, logio
    from mtcal.core.arrayfile import read_arrays
    from mtcal.core.metrics import orientation_errors, rmse_over_phase
    from mtcal.systems import plausibility
    from mtcal.systems.attitude import FILTERS, AttitudeConfig, estimate_attitude
    from mtcal.systems.rests import find_rests

    filters = list(FILTERS if filters is None else filters)
    paths = sorted(TRIALS.glob("*.mat"))
    if trials:
        paths = [p for p in paths if p.name[:2] in trials]
    parser = argparse.ArgumentParser()
    common.add_input_options(parser)
    common.add_rest_options(parser, min_rest_s=0.2)
    rows = []
    for path in paths:
        arrays = read_arrays(path)
        log = logio.read_log(path, common.input_options(parser.parse_args([])), need="raw")
        rests = AttitudeConfig.cli_defaults().rests
        rep = find_rests(log.accel_m_s2, log.dt_mean_s, rests, gyro_rad_s=log.gyro_rad_s, time_s=log.time_s)
        clipped, _ = plausibility.clipped_samples(log.gyro_rad_s)
        for name in filters:
            t0 = time.perf_counter()
            res = estimate_attitude(log.gyro_rad_s, log.accel_m_s2, log.dt_mean_s, AttitudeConfig.cli_defaults(name),
                                    time_s=log.time_s, rests=rep, skip=clipped, unit_stated=log.gyro_unit_stated)
            secs = time.perf_counter() - t0
            err = orientation_errors(res.q_ws, arrays["opt_quat"])
            rmse = float(np.degrees(rmse_over_phase(err.inclination_rad, arrays["movement"])))
            rows.append({"trial": path.name[:2], "name": path.stem, "filter": name, "inclination_rmse_deg": rmse,
                         "units_check": res.units_check["method"], "seconds": secs})
            if name == "qncf":
                rows.extend(_qncf_cause(log, res.setup, arrays, path))
    return rows


def _qncf_cause(log, setup, arrays, path) -> list[dict]:
    """Diagnostics of QNCF (not a ``--filter``): share of the movement phase with the AMD gate closed, the
    inclination RMSE of the same QNCF with the gate always open, and of its output read one row later (mtcal's
    schema integrates gyro sample k over [t_k, t_k+1], BROAD's gyro, like VQF, over [t_k-1, t_k])."""
    import dataclasses

    from mtcal.core.metrics import orientation_errors, rmse_over_phase
    from mtcal.filters.qncf import amd_statistic, qncf_trusted

    gyro, params, q0 = setup.gyro_rad_s, setup.params, setup.q0
    move = np.asarray(arrays["movement"]).astype(bool)
    closed = float(np.mean(amd_statistic(log.accel_m_s2, log.dt_mean_s, params)[move] >= params.amd_threshold_pct))
    open_gate = dataclasses.replace(params, amd_threshold_pct=1e9)
    q = qncf_trusted(gyro, log.accel_m_s2, log.dt_mean_s, open_gate, q0=q0, return_euler=False).q_ws
    err = orientation_errors(q, arrays["opt_quat"])
    base = {"trial": path.name[:2], "name": path.stem, "units_check": "", "seconds": float("nan")}
    q_def = qncf_trusted(gyro, log.accel_m_s2, log.dt_mean_s, params, q0=q0, return_euler=False).q_ws
    nxt = orientation_errors(np.vstack([q_def[1:], q_def[-1:]]), arrays["opt_quat"])   # row k+1 against t_k
    return [{**base, "filter": "qncf_gate_open*", "inclination_rmse_deg":
             float(np.degrees(rmse_over_phase(err.inclination_rad, arrays["movement"])))},
            {**base, "filter": "qncf_next_row*", "inclination_rmse_deg":
             float(np.degrees(rmse_over_phase(nxt.inclination_rad, arrays["movement"])))},
            {**base, "filter": "qncf_gate_closed_share*", "inclination_rmse_deg": closed}]


def summary(rows) -> list[dict]:
    """Per filter: median over trials of the inclination RMSE and of its ratio to VQF's on the same trial."""
    vqf = {r["trial"]: r["inclination_rmse_deg"] for r in rows if r["filter"] == "vqf"}
    out = []
    for name in dict.fromkeys(r["filter"] for r in rows):
        mine = [r for r in rows if r["filter"] == name]
        ratios = [r["inclination_rmse_deg"] / vqf[r["trial"]] for r in mine if r["trial"] in vqf]
        out.append({"filter": name, "trials": len(mine),
                    "median_rmse_deg": float(np.median([r["inclination_rmse_deg"] for r in mine])),
                    "median_ratio_to_vqf": float(np.median(ratios)) if ratios else float("nan")})
    return out


def summary_share(rows) -> float:
    """Median over trials of the share of the movement phase with QNCF's AMD gate closed."""
    return float(np.median([r["inclination_rmse_deg"] for r in rows if r["filter"] == "qncf_gate_closed_share*"]))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--csv", help="write the per-trial rows here")
    ap.add_argument("--filters", help="comma-separated subset")
    ap.add_argument("--trials", help="comma-separated trial numbers (e.g. 01,10)")
    args = ap.parse_args(argv)
    rows = trial_rows(args.filters.split(",") if args.filters else None,
                      args.trials.split(",") if args.trials else None)
    names = [n for n in dict.fromkeys(r["filter"] for r in rows) if n != "qncf_gate_closed_share*"]
    print("BROAD (broad2021) inclination RMSE (deg) over the movement phase vs optical reference")
    print(f"{'trial':<46}" + "".join(f"{n:>17}" for n in names) + "  units check")
    for trial in dict.fromkeys(r["trial"] for r in rows):
        rs = {r["filter"]: r for r in rows if r["trial"] == trial}
        first = next(iter(rs.values()))
        print(f"{first['name']:<46}" + "".join(f"{rs[n]['inclination_rmse_deg']:>17.3f}" for n in names)
              + f"  {first['units_check']}")
    for s in summary(rows):
        if s["filter"] == "qncf_gate_closed_share*":
            print(f"median share of the movement phase with QNCF's AMD gate closed: {s['median_rmse_deg']:.2f}")
            continue
        print(f"median {s['filter']:<16} {s['median_rmse_deg']:.3f} deg over {s['trials']} trials; median ratio "
              f"to vqf {s['median_ratio_to_vqf']:.2f}")
    ratio = {s["filter"]: s["median_ratio_to_vqf"] for s in summary(rows)}
    if "qncf" in ratio and "vqf" in ratio:
        ok = ratio["qncf"] <= TARGET_RATIO
        print(f"target QNCF median inclination RMSE <= {TARGET_RATIO:g} x VQF: {'MET' if ok else 'MISSED'} "
              f"({ratio['qncf']:.2f} x)" + ("" if ok else
              f"; cause: QNCF's AMD gate is closed over a median {summary_share(rows):.0%} of the movement phase "
              f"(gyro alone), and opening it lets linear acceleration in ({ratio.get('qncf_gate_open*', np.nan):.2f} x "
              f"with the gate always open); one sample of timing convention ({ratio.get('qncf_next_row*', np.nan):.2f} x "
              f"with QNCF's rows read one sample later); VQF filters the accelerometer in a quasi-inertial frame and estimates "
              f"the gyro bias in motion, which the paper's QNCF structure has no place for"))
    if args.csv:
        import csv

        Path(args.csv).parent.mkdir(parents=True, exist_ok=True)
        with open(args.csv, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(rows[0]))
            w.writeheader()
            for r in rows:
                w.writerow({k: (f"{v:.4f}" if isinstance(v, float) else v) for k, v in r.items()})
    return 0


if __name__ == "__main__":
    sys.exit(main())
