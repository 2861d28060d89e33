"""Inclination RMSE of every ``mtcal attitude --filter`` on BROAD's shipped trials (broad2021), against optics.

Each trial is read by the command line's own log reader (``mtcal.cli.logio.read_log`` on the original
``.mat``: BROAD's layout, ``imu_gyr``/``imu_acc``/``sampling_rate``), its rests detected and units checked
as ``mtcal attitude`` does at default options, and every filter run through the same functions the command
calls (:func:`mtcal.cli.attitude.sensor_attitude` for QNCF, :func:`~mtcal.cli.attitude.other_filter_attitude`
for the others). The error is BROAD's inclination error (heading-free, earth frame; a 6D filter is judged
fairly) via :func:`mtcal.core.metrics.orientation_errors`, RMSE over the ``movement`` phase with
:func:`mtcal.core.metrics.rmse_over_phase`. The optical arrays are read separately with
:func:`mtcal.core.arrayfile.read_arrays`; no filter sees them.

Frames: BROAD's ``opt_quat`` is IMU (sensor) → ENU earth, scalar-first; mtcal's filters output sensor →
world (z up, heading arbitrary). The inclination error does not depend on a heading offset between the
two earth frames (a rotation about the vertical), so no alignment is needed.

Usage: ``python benchmarks/broad_accuracy.py [--csv data/broad2021_accuracy.csv]`` (``make bench`` runs it).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
TRIALS = ROOT / "datasets" / "broad2021" / "trials"


def trial_rows(filters=None, trials=None):
    """One dict per (trial, filter): inclination RMSE (deg) over the movement phase, units check, time."""
    from mtcal.cli import attitude, common, logio
    from mtcal.core.arrayfile import read_arrays
    from mtcal.core.metrics import orientation_errors, rmse_over_phase
    from mtcal.systems import plausibility

    filters = list(attitude.FILTERS if filters is None else filters)
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
        rep = common.detect(parser.parse_args([]), log)
        clipped, _ = plausibility.clipped_samples(log.gyro_rad_s)
        for name in filters:
            t0 = time.perf_counter()
            if name == "qncf":
                q, info = attitude.sensor_attitude(log, rep, skip=clipped)
                chk = info["units_check"]
            else:
                chk = plausibility.check_units(log.gyro_for_filter(), log.accel_m_s2, log.dt_mean_s, rep.rests,
                                               time_s=log.time_s, skip=clipped, unit_stated=log.gyro_unit_stated)
                q, info = attitude.other_filter_attitude(name, log)
            secs = time.perf_counter() - t0
            err = orientation_errors(q, arrays["opt_quat"])
            rmse = float(np.degrees(rmse_over_phase(err.inclination_rad, arrays["movement"])))
            rows.append({"trial": path.name[:2], "name": path.stem, "filter": name, "inclination_rmse_deg": rmse,
                         "units_check": chk["method"], "seconds": secs})
    return rows


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


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--csv", help="write the per-trial rows here")
    ap.add_argument("--filters", help="comma-separated subset")
    ap.add_argument("--trials", help="comma-separated trial numbers (e.g. 01,10)")
    args = ap.parse_args(argv)
    rows = trial_rows(args.filters.split(",") if args.filters else None,
                      args.trials.split(",") if args.trials else None)
    names = list(dict.fromkeys(r["filter"] for r in rows))
    print("BROAD (broad2021) inclination RMSE (deg) over the movement phase vs optical reference")
    print(f"{'trial':<46}" + "".join(f"{n:>10}" for n in names) + "  units check")
    for trial in dict.fromkeys(r["trial"] for r in rows):
        rs = {r["filter"]: r for r in rows if r["trial"] == trial}
        first = next(iter(rs.values()))
        print(f"{first['name']:<46}" + "".join(f"{rs[n]['inclination_rmse_deg']:>10.3f}" for n in names)
              + f"  {first['units_check']}")
    for s in summary(rows):
        print(f"median {s['filter']:<10} {s['median_rmse_deg']:.3f} deg over {s['trials']} trials; median ratio "
              f"to vqf {s['median_ratio_to_vqf']:.2f}")
    if args.csv:
        import csv

        with open(args.csv, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(rows[0]))
            w.writeheader()
            for r in rows:
                w.writerow({k: (f"{v:.4f}" if isinstance(v, float) else v) for k, v in r.items()})
    return 0


if __name__ == "__main__":
    sys.exit(main())
