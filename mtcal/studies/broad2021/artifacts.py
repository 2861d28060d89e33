"""broad2021 artifacts: one producer per table/figure of notebook 60, from one :func:`run_study`.

* :func:`table_published_vs_ours` — BROAD's published 9D RMSE (Madgwick, Mahony at BROAD's chosen
  parameters) beside ours from the raw data; tolerance **0.01°** per number, stated before comparing
  (the C code runs in float32, ours in float64: a few 1e-3° expected). Also the grids (slices) and
  the computed effect of BROAD's start and of the C field-reference issue (dlaidig/broad#1).
* :func:`extra_bakeoff_6d` — inclination RMSE of every 6D filter per trial and per BROAD group.
* :func:`extra_median_trial` — the error time series of the median trial.
* :func:`extra_rankings` — notebook 50's simulated rankings tested on the real trials (paired, Wilson).
* :func:`extra_twin` — the simulated twin's predicted range against the real RMSE: coverage
  (Wilson) and width per filter and group, and what the twin lacks.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from scipy.signal import lfilter

from mtcal.core.artifacts import Artifact, produces
from mtcal.core.rng import trial_rng
from mtcal.reporting import compare, paper_numbers
from mtcal.reporting.binomial import coin_flip, wilson_interval

from . import error_model, runs
from .scenario import GROUP_CATEGORIES, BroadScenario, load_trials, trial_head

__all__ = ["StudyRun", "run_study", "table_published_vs_ours", "extra_bakeoff_6d", "extra_median_trial",
           "extra_rankings", "extra_twin", "TOLERANCE_DEG", "LOTO_FILTERS", "RANKINGS", "BETA_GRID", "KP_GRID"]

#: Reproduction tolerance per published number (deg), stated before comparing.
TOLERANCE_DEG = 0.01
#: Slices of BROAD's grids (process_data.py: β 0.01…0.30 step 0.01; K_p 0.02…2.00 step 0.02, K_i 0…0.004
#: step 1e-4) run at full size for the cost limit: every 3rd β, every 5th K_p at BROAD's K_i, each BROAD's value.
BETA_GRID = np.round(np.arange(0.03, 0.300001, 0.03), 8)
KP_GRID = np.round(np.arange(0.1, 2.000001, 0.1), 8)
_METRICS = ("total", "heading", "inclination")
#: Filters of the leave-one-trial-out twin (mount tilt added), a subset for the notebook's cost limit.
LOTO_FILTERS = ("mahony", "madgwick", "vqf")


@dataclass
class StudyRun:
    """Everything notebook 60 shows, computed once (:func:`run_study`)."""

    scenario: BroadScenario
    trials: list
    real: pd.DataFrame            # trial, groups, filter, inclination_rmse_deg
    series: dict                  # median trial: {"trial", "time_s", filter: inclination error deg (N,)}
    nined: pd.DataFrame           # trial, filter, variant, metric columns
    grids: pd.DataFrame           # trial, filter, gain, ours/published inclination and total RMSE
    twin: pd.DataFrame            # trial, filter, real, low, median, high, n, inside
    rest: pd.DataFrame            # per trial: rest length, offsets, gate-open share, rest tilt offset
    seed: int = 0
    extra: dict = field(default_factory=dict)


def _amd(accel: np.ndarray, dt: float, g: float, tau_s: float = 0.05) -> np.ndarray:
    """QNCF's AMD statistic (% of g) by the filter's recursion (mtcal.filters.qncf.amd_statistic, as a linear filter)."""
    d = 100.0 * np.abs(np.linalg.norm(accel, axis=-1) / g - 1.0)
    alpha = min(dt / tau_s, 1.0)
    return lfilter([alpha], [1.0, alpha - 1.0], d, zi=[(1.0 - alpha) * d[0]])[0]


def _rest_row(trial, sc: BroadScenario, q_paper_gate: float, gaps: dict) -> dict:
    from mtcal.core import rotations

    model = error_model.identify_rest_model(trial, sc.rest_margin_s, sc.local_gravity_m_s2)
    rest = runs.initial_rest(trial, sc.rest_margin_s)
    q = trial.opt_quat[rest]
    ok = np.isfinite(q[:, 0])
    up_opt = rotations.quat_to_matrix(q[ok])[:, 2, :].mean(axis=0)          # world z in the sensor frame
    cosang = np.dot(up_opt / np.linalg.norm(up_opt), model.gravity_dir_s)
    amd = _amd(trial.accel_m_s2, trial.dt_s, 9.80665)
    norm = np.linalg.norm(trial.accel_m_s2[rest].mean(axis=0))
    return {**{"trial": trial.name, "rest_s": model.rest_s, "accel_norm_at_rest_m_s2": norm,
            "norm_offset_pct_of_standard_g": 100.0 * (norm / 9.80665 - 1.0),
            "qncf_paper_gate_open_movement_pct": 100.0 * float(np.mean(amd[trial.movement] < q_paper_gate)),
            "gyro_bias_deg_s": float(np.degrees(np.linalg.norm(model.gyro_bias_rad_s))),
            "gyro_noise_deg_s_rthz": float(np.degrees(model.gyro_noise_density_rad_s_rthz)),
            "accel_noise_m_s2_rthz": model.accel_noise_density_m_s2_rthz,
            "rest_tilt_imu_vs_optical_deg": float(np.degrees(np.arccos(np.clip(cosang, -1, 1))))}, **gaps}


def run_study(sc: BroadScenario, seed: int) -> StudyRun:
    """Run notebook 60's computations once: 6D bake-off, 9D reproduction (+ grids at full size), the twin.

    Parameters
    ----------
    sc : BroadScenario
    seed : int
        Seed of the twin's keyed stream.
    """
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
    trials = [trial_head(t, sc.max_samples) for t in load_trials(sc.trials)]
    published = paper_numbers.load("broad2021_published_rmse")
    import scipy.io as sio
    from .scenario import data_dir

    pub_grid = {f: sio.loadmat(str(data_dir() / "published" / f"results_{f}.mat"), squeeze_me=True)
                for f in ("madgwick", "mahony")}
    ki_index = int(np.argmin(np.abs(np.round(np.arange(0.0, 0.0040001, 0.0001), 8) - sc.mahony_ki)))
    real, nined, grids, twin, rest = [], [], [], [], []
    qs, truths, mats = {}, {}, {}
    for tr in trials:
        for f in sc.filters:
            q = runs.run_6d(f, tr.gyro_rad_s, tr.accel_m_s2, tr.dt_s)
            qs[(tr.name, f)] = q
            real.append({"trial": tr.name, "filter": f,
                         "inclination_rmse_deg": float(runs.rmse_deg(q, tr, inclination_only=True)[0])})
        full = sc.max_samples is None
        betas = np.union1d(BETA_GRID, [sc.madgwick_beta]) if full else np.array([sc.madgwick_beta])
        kps = np.union1d(KP_GRID, [sc.mahony_kp]) if full else np.array([sc.mahony_kp])
        res = runs.run_9d(tr, betas, kps, [sc.mahony_ki] * len(kps))
        ib = int(np.argmin(np.abs(np.asarray(betas) - sc.madgwick_beta)))
        ik = int(np.argmin(np.abs(np.asarray(kps) - sc.mahony_kp)))
        variants = {"broad": res}
        if full:
            variants["paper_field"] = runs.run_9d(tr, [sc.madgwick_beta], [sc.mahony_kp], [sc.mahony_ki],
                                                  field_reference="paper")
            variants["optical_start"] = runs.run_9d(tr, [sc.madgwick_beta], [sc.mahony_kp], [sc.mahony_ki],
                                                    initial="optical")
        for v, r in variants.items():
            for f, i in (("madgwick", ib if v == "broad" else 0), ("mahony", ik if v == "broad" else 0)):
                nined.append({"trial": tr.name, "filter": f, "variant": v,
                              **{f"{m}_rmse_deg": float(r[f][j, i]) for j, m in enumerate(_METRICS)}})
        if full:
            for f, gains, col, (g0, step) in (("madgwick", betas, None, (0.01, 0.01)),
                                               ("mahony", kps, ki_index, (0.02, 0.02))):
                pub = pub_grid[f]["inclination_rmse_deg"][f"trial_{tr.name}"].item()
                pub_tot = pub_grid[f]["total_rmse_deg"][f"trial_{tr.name}"].item()
                for i, gval in enumerate(gains):
                    j = int(round((gval - g0) / step))          # index in BROAD's grid
                    grids.append({"trial": tr.name, "filter": f, "gain": float(gval),
                                  "ours_inclination_deg": float(res[f][2, i]),
                                  "published_inclination_deg": float(pub[j] if col is None else pub[j, col]),
                                  "ours_total_deg": float(res[f][0, i]),
                                  "published_total_deg": float(pub_tot[j] if col is None else pub_tot[j, col])})
        # the twin's truth and the measured gaps, once per trial (the blind and the leave-one-out twins share them)
        truths[tr.name] = error_model.twin_truth(tr, sc.smooth_quat_s, sc.smooth_pos_s)
        gaps_row, mats[tr.name] = error_model._gaps(tr, truths[tr.name], 10)
        preds = error_model.twin_predictions(tr, sc.twin_filters, sc.n_draws, seed, margin_s=sc.rest_margin_s,
                                             smooth_quat_s=sc.smooth_quat_s, smooth_pos_s=sc.smooth_pos_s,
                                             local_gravity_m_s2=sc.local_gravity_m_s2, truth=truths[tr.name])
        for f, p in preds.items():
            r = next(x["inclination_rmse_deg"] for x in real if x["trial"] == tr.name and x["filter"] == f)
            b = p.band
            twin.append({"trial": tr.name, "filter": f, "real_deg": r, "twin_low_deg": float(b["low"]),
                         "twin_median_deg": float(b["median"]), "twin_high_deg": float(b["high"]), "n": b["n"],
                         "kind": b["kind"], "inside": bool(b["low"] <= r <= b["high"]),
                         "real_over_twin_median": r / float(b["median"])})
        rest.append(_rest_row(tr, sc, 0.3, gaps_row))
    rest_df = pd.DataFrame(rest)
    # leave-one-trial-out fix of what the twin lacks, measured on the OTHER trials only (never on the trial it
    # predicts): each draw borrows one other trial (keyed stream) and takes its rest tilt (IMU-to-marker, random
    # direction) and its IMU-vs-optical time offset; the gyro scale/misalignment matrix is the element-wise median
    # of the other trials' fits (robust to the two translation trials whose fits give 15-18 % x scale)
    twin_loto = []
    loto_filters = [f for f in LOTO_FILTERS if f in sc.twin_filters]
    if len(trials) > 1 and loto_filters:
        gaps = rest_df.set_index("trial")
        for tr in trials:
            others = [t.name for t in trials if t.name != tr.name]
            pick = [others[i] for i in trial_rng(seed, error_model.STREAM_TWIN_LOTO,
                                                 error_model.trial_number(tr)).integers(0, len(others), sc.n_draws)]
            tilt_deg = gaps.loc[pick, "rest_tilt_imu_vs_optical_deg"].to_numpy(float)
            lags = np.rint(gaps.loc[pick, "time_offset_ms"].to_numpy(float) / 1000.0 / tr.dt_s).astype(np.int64)
            preds = error_model.twin_predictions(tr, loto_filters, sc.n_draws, seed, margin_s=sc.rest_margin_s,
                                                 smooth_quat_s=sc.smooth_quat_s, smooth_pos_s=sc.smooth_pos_s,
                                                 local_gravity_m_s2=sc.local_gravity_m_s2,
                                                 mount_tilt_rad=np.radians(tilt_deg),
                                                 gyro_matrix=np.median(np.stack([mats[n] for n in others]), axis=0),
                                                 time_offset_samples=lags, truth=truths[tr.name])
            tilt_deg = float(np.median(tilt_deg))
            for f, p in preds.items():
                r = next(x["inclination_rmse_deg"] for x in real if x["trial"] == tr.name and x["filter"] == f)
                b = p.band
                twin_loto.append({"trial": tr.name, "filter": f, "mount_tilt_deg": tilt_deg, "real_deg": r,
                                  "twin_low_deg": float(b["low"]), "twin_median_deg": float(b["median"]),
                                  "twin_high_deg": float(b["high"]), "n": b["n"], "kind": b["kind"],
                                  "inside": bool(b["low"] <= r <= b["high"]),
                                  "real_over_twin_median": r / float(b["median"])})
    real_df = pd.DataFrame(real)
    groups = {t.name: t.groups for t in trials}
    # the median trial: median (over trials) of the trial's median inclination RMSE over filters
    per_trial = real_df.groupby("trial", sort=True)["inclination_rmse_deg"].median()
    order = per_trial.sort_values(kind="stable")
    med_name = order.index[(len(order) - 1) // 2]
    tr = next(t for t in trials if t.name == med_name)
    series = {"trial": med_name, "time_s": np.arange(tr.n) * tr.dt_s, "movement": tr.movement,
              **{f: runs.errors_deg(qs[(med_name, f)], tr.opt_quat, inclination_only=True)[0] for f in sc.filters}}
    return StudyRun(scenario=sc, trials=[(t.name, t.groups) for t in trials], real=real_df, series=series,
                    nined=pd.DataFrame(nined), grids=pd.DataFrame(grids), twin=pd.DataFrame(twin),
                    rest=rest_df, seed=int(seed), extra={"groups": groups, "published": published,
                                                         "twin_loto": pd.DataFrame(twin_loto)})


@produces("broad2021_extra_published_vs_ours", "table", "BROAD case study (results_*.mat)")
def table_published_vs_ours(run: StudyRun) -> Artifact:
    """BROAD's published per-trial 9D RMSE beside ours: one held-out check per number and one claim for the case
    study (every number within :data:`TOLERANCE_DEG`; each published result counts once)."""
    pub = run.extra["published"]
    ours = run.nined[run.nined.variant == "broad"]
    rows, table = [], []
    ref_rows = {(r.filter, r.trial): i + 1 for i, r in enumerate(pub.itertuples())}
    for r in ours.itertuples():
        p = pub[(pub["filter"] == r.filter) & (pub["trial"] == r.trial)].iloc[0]
        rec = {"trial": r.trial, "filter": r.filter, "parameters": p["parameters"]}
        for m in _METRICS:
            col = f"{m}_rmse_deg"
            mine, theirs = getattr(r, col), float(p[col])
            rec[f"{m}_published_deg"], rec[f"{m}_ours_deg"] = theirs, mine
            # one check per published number (shown failing if it fails); the case study is one claim, below
            rows.append(compare.comparison_row(
                "broad2021_extra_published_vs_ours", f"{r.filter} {r.trial} {m} RMSE (deg)", theirs, mine,
                f"|ours - published| <= {TOLERANCE_DEG} deg (tolerance stated before comparing)",
                bool(abs(mine - theirs) <= TOLERANCE_DEG), source="mtcal finding",
                ref=f"broad2021_published_rmse:{ref_rows[(r.filter, r.trial)]}:{col}"))
        rec["max_abs_diff_deg"] = max(abs(rec[f"{m}_published_deg"] - rec[f"{m}_ours_deg"]) for m in _METRICS)
        table.append(rec)
    df = pd.DataFrame(table)
    held, n_numbers = sum(r["holds"] for r in rows), len(rows)
    # the published case study is one result: one claim, holding when every number is within the tolerance
    rows.append(compare.claim("broad2021_extra_published_vs_ours", "published 9D RMSEs reproduced within the "
                              f"tolerance (of {n_numbers})", n_numbers, held,
                              f"BROAD's case study (its per-trial 9D RMSE at its chosen parameters) reproduces from "
                              f"the raw data: every published number within {TOLERANCE_DEG} deg (mtcal tolerance, "
                              "stated before comparing; BROAD states none)", lambda v, n=n_numbers: v == n,
                              note=("" if held == n_numbers else f"{n_numbers - held} of {n_numbers} outside; ")
                              + f"largest difference {df.max_abs_diff_deg.max():.4f} deg",
                              ref=";".join(r["ref"] for r in rows)))
    lines = [f"BROAD 9D case study reproduced from the raw data: {held} of {n_numbers} published numbers within "
             f"{TOLERANCE_DEG} deg; largest difference {df.max_abs_diff_deg.max():.4f} deg "
             "(BROAD's C code runs in float32, ours in float64)"]
    var = run.nined.pivot_table(index=["trial", "filter"], columns="variant", values="total_rmse_deg")
    if "paper_field" in var:
        mad = var.xs("madgwick", level="filter")
        lines.append("computed effects at BROAD's parameters (mean total RMSE over trials, Madgwick): BROAD's run "
                     f"{mad['broad'].mean():.3f} deg; with Madgwick 2010 Eq 46's field reference instead of the C "
                     f"code's half (dlaidig/broad#1) {mad['paper_field'].mean():.3f} deg; started from the optical "
                     f"attitude instead of BROAD's first-sample acc/mag quaternion {mad['optical_start'].mean():.3f} deg")
        mah = var.xs("mahony", level="filter")
        lines.append(f"Mahony: BROAD's run {mah['broad'].mean():.3f} deg; from the optical start "
                     f"{mah['optical_start'].mean():.3f} deg")
    if len(run.grids):
        g = run.grids
        d = np.abs(g.ours_inclination_deg - g.published_inclination_deg)
        dt = np.abs(g.ours_total_deg - g.published_total_deg)
        lines.append(f"over grid slices (Madgwick beta {BETA_GRID[0]}-{BETA_GRID[-1]} step 0.03, Mahony K_p "
                     f"{KP_GRID[0]}-{KP_GRID[-1]} step 0.1 at K_i = {run.scenario.mahony_ki}; {len(g)} settings x trials): largest |ours - published| "
                     f"inclination {d.max():.4f} deg, total {dt.max():.4f} deg")
    return Artifact(table=df, rows=rows, lines=lines, data={"grids": run.grids})


def _group_table(real: pd.DataFrame, groups: dict) -> pd.DataFrame:
    rows = []
    for cat, names in GROUP_CATEGORIES.items():
        for g in names:
            members = [t for t, gs in groups.items() if g in gs]
            if not members:
                continue
            sub = real[real.trial.isin(members)]
            for f, s in sub.groupby("filter", sort=False):
                rows.append({"category": cat, "group": g, "filter": f, "trials": len(s),
                             "median_inclination_rmse_deg": float(s.inclination_rmse_deg.median()),
                             "mean_inclination_rmse_deg": float(s.inclination_rmse_deg.mean()),
                             "min_deg": float(s.inclination_rmse_deg.min()),
                             "max_deg": float(s.inclination_rmse_deg.max())})
    return pd.DataFrame(rows)


@produces("broad2021_extra_bakeoff_6d", "figure")
def extra_bakeoff_6d(run: StudyRun) -> Artifact:
    """Inclination RMSE of every 6D filter per trial and per BROAD group (figure: one panel per category)."""
    wide = run.real.pivot(index="trial", columns="filter", values="inclination_rmse_deg")[list(run.scenario.filters)]
    groups = _group_table(run.real, run.extra["groups"])
    med = run.real.groupby("filter", sort=False).inclination_rmse_deg.median()
    lines = ["median inclination RMSE over the trials (deg): " + ", ".join(f"{f} {v:.2f}" for f, v in med.items())]
    return Artifact(table=groups, data={"per_trial": wide, "groups": groups, "filters": list(run.scenario.filters)},
                    lines=lines)


@produces("broad2021_extra_median_trial", "figure")
def extra_median_trial(run: StudyRun) -> Artifact:
    """Inclination error time series of every 6D filter on the median trial."""
    s = run.series
    rms = {f: float(np.sqrt(np.nanmean(s[f][s["movement"]] ** 2))) for f in run.scenario.filters}
    table = pd.DataFrame({"filter": list(rms), "inclination_rmse_deg": list(rms.values())})
    return Artifact(table=table, data=s, lines=[f"median trial: {s['trial']} (median over trials of the filters' "
                                                "median inclination RMSE)"])


#: notebook 50's rankings (simulation) as claims on the real trials: (id, better, worse, groups or None, statement).
RANKINGS = (
    ("qncf_over_vqf_no_vibration", "qncf_paper", "vqf", ("rotation",),
     "nb50 wind tunnel, wind off: VQF's median about 4-5x QNCF's (QNCF better without vibration)"),
    ("vqf_over_qncf_vibration", "vqf", "qncf_paper", ("translation", "combined", "tapping", "vibration"),
     "nb50 wind tunnel, wind on: VQF about an order of magnitude below QNCF (VQF better under vibration)"),
    ("vqf_over_mahony_vibration", "vqf", "mahony", ("translation", "combined", "tapping", "vibration"),
     "nb50: Mahony rectifies vibration into a tilt error, VQF low-pass filters it (VQF better under vibration)"),
    ("qncf_last_when_gate_shut", None, "qncf_paper", None,
     "nb50 consumer grade: QNCF last when the accelerometer's own offset exceeds Thr (gate shut)"),
)
#: Rankings judged together, as one claim: (id, rankings, statement). Notebook 50's QNCF/VQF result is that the order
#: flips with vibration; one direction holding alone (VQF better everywhere) does not support it.
RANKING_PAIRS = (
    ("qncf_vqf_order_flips_with_vibration", ("qncf_over_vqf_no_vibration", "vqf_over_qncf_vibration"),
     "nb50 wind tunnel: QNCF better than VQF without vibration and VQF better with it (the order flips with "
     "vibration)"),
)


@produces("broad2021_extra_rankings", "table")
def extra_rankings(run: StudyRun) -> Artifact:
    """Notebook 50's simulated rankings tested on the real trials: paired wins with a Wilson interval."""
    wide = run.real.pivot(index="trial", columns="filter", values="inclination_rmse_deg")
    groups = run.extra["groups"]
    rest = run.rest.set_index("trial")
    rows, table, lines = [], [], []
    paired = {r: pid for pid, members, _ in RANKING_PAIRS for r in members}
    for rid, better, worse, gsel, statement in RANKINGS:
        names = [t for t in wide.index if gsel is None or any(g in groups[t] for g in gsel)]
        if not names or worse not in wide or (better is not None and better not in wide):
            continue
        sub = wide.loc[names]
        if better is None:
            others = sub.drop(columns=[worse])
            wins = int((sub[worse] >= others.max(axis=1)).sum())
            what = f"{worse} has the largest RMSE of {sub.shape[1]} filters"
        else:
            wins = int((sub[better] < sub[worse]).sum())
            what = f"{better} < {worse}"
        cf = coin_flip(wins, len(names), counted="holds in", of="trials")
        verdict = "holds" if cf.low > 0.5 else "flips" if cf.high < 0.5 else "unresolved"
        gate = rest.loc[names, "qncf_paper_gate_open_movement_pct"].median()
        offs = rest.loc[names, "norm_offset_pct_of_standard_g"]
        cause = ""
        if verdict != "holds" and "qncf" in f"{better}{worse}":
            cause = (f"QNCF's AMD gate (Thr 0.3 % of 9.80665) is open in a median {gate:.1f} % of the movement "
                     f"samples: the accelerometer reads |a| {offs.min():+.2f} to {offs.max():+.2f} % off standard g at "
                     "rest and hand-held motion adds more, so QNCF integrates the gyro (bias and noise) where the "
                     "simulated tunnel kept |a| within Thr")
        elif verdict != "holds":
            cause = "see the per-trial table"
        table.append({"ranking": rid, "simulated": statement, "real_test": what, "trials": len(names), "holds_in": wins,
                      "wilson_low": cf.low, "wilson_high": cf.high, "verdict": verdict, "cause": cause})
        in_pair = rid in paired               # judged with its pair as one claim (below): shown, not counted
        rows.append(compare.comparison_row("broad2021_extra_rankings", f"{rid}: share of trials where {what}",
                                           "", wins / len(names), f"simulated ranking holds on real data: Wilson 95 % "
                                           "interval of the share above 1/2", verdict == "holds", role="finding",
                                           source="mtcal finding", kind=None if in_pair else "claim",
                                           note="; ".join(x for x in (cause or cf.verdict, f"judged with its pair as "
                                                                      f"one claim: {paired[rid]}" if in_pair else "")
                                                          if x), enforce=False))
        lines.append(f"{rid}: {what} in {wins} of {len(names)} trials -> {verdict} ({cf.verdict})"
                     + (f"; cause: {cause}" if cause else ""))
    done = {t["ranking"]: t for t in table}
    for pid, members, statement in RANKING_PAIRS:
        if not all(m in done for m in members):
            continue
        failing = [m for m in members if done[m]["verdict"] != "holds"]
        holds = not failing
        note = "; ".join(f"{m} {done[m]['verdict']} ({done[m]['holds_in']} of {done[m]['trials']} trials)"
                         + (f": {done[m]['cause']}" if done[m]["cause"] else "") for m in failing)
        rows.append(compare.comparison_row("broad2021_extra_rankings", f"{pid}: every ranking of the pair holds "
                                           f"({', '.join(members)})", "", float(len(members) - len(failing)),
                                           f"{statement}: both hold on real data", holds, role="finding",
                                           source="mtcal finding", kind="claim", note=note, enforce=False))
        lines.append(f"{pid}: {'holds' if holds else 'fails'}" + (f" ({note})" if note else ""))
    return Artifact(table=pd.DataFrame(table), rows=rows, lines=lines)


@produces("broad2021_extra_twin", "figure")
def extra_twin(run: StudyRun) -> Artifact:
    """The twin's predicted range of each filter's inclination RMSE against the real one; coverage and width."""
    tw = run.twin
    groups = run.extra["groups"]
    n = int(tw.n.iloc[0])
    nominal = (n - 1) / (n + 1)
    summary, rows, lines = [], [], []
    scopes = [("all", None)] + [(g, g) for names in GROUP_CATEGORIES.values() for g in names]
    for scope, g in scopes:
        sub = tw if g is None else tw[tw.trial.map(lambda t: g in groups[t])]
        for f, s in sub.groupby("filter", sort=False):
            k, m = int(s.inside.sum()), len(s)
            lo, hi = wilson_interval(k, m)
            summary.append({"scope": scope, "filter": f, "trials": m, "inside": k, "coverage": k / m,
                            "coverage_low": lo, "coverage_high": hi, "nominal": nominal,
                            "median_width_deg": float((s.twin_high_deg - s.twin_low_deg).median()),
                            "median_real_over_twin": float(s.real_over_twin_median.median())})
    summary = pd.DataFrame(summary)
    rest = run.rest.set_index("trial")
    for r in summary[summary.scope == "all"].itertuples():
        ok = r.coverage_low <= nominal <= r.coverage_high
        note = ("the twin under-predicts: real/twin median ratio " f"{r.median_real_over_twin:.2f}; the real trials "
                f"start with a median {rest.rest_tilt_imu_vs_optical_deg.median():.2f} deg tilt between the "
                "accelerometer's and the optical 'up' at rest (IMU-to-marker misalignment + accelerometer bias); "
                f"on the movement phase the gyro fits the optical rate with a median {rest.gyro_scale_pct.median():.2f} % "
                f"scale error, {rest.gyro_misalignment_deg.median():.2f} deg misalignment and a "
                f"{rest.time_offset_ms.median():.1f} ms IMU-vs-optical time offset: none of them is in the twin "
                "(identity mount, error model from the rest)")
        rows.append(compare.comparison_row("broad2021_extra_twin", f"{r.filter}: twin range covers the real "
                                           "inclination RMSE (share of trials)", "", r.coverage,
                                           f"Wilson 95 % interval of the coverage contains the nominal {nominal:.2f} "
                                           f"of a min-max range of {n} draws", ok, role="finding",
                                           source="mtcal finding", kind="claim", note="" if ok else note,
                                           enforce=False))
        lines.append(f"{r.filter:10s} coverage {r.inside}/{r.trials} = {r.coverage:.2f} (Wilson {r.coverage_low:.2f}-"
                     f"{r.coverage_high:.2f}; nominal {nominal:.2f}), median width {r.median_width_deg:.3f} deg, "
                     f"median real/twin {r.median_real_over_twin:.2f}")
    loto = run.extra.get("twin_loto")
    if loto is not None and len(loto):
        lines.append("leave-one-trial-out fix: each draw borrows another trial's IMU-to-marker tilt at rest (random "
                     "direction) and IMU-vs-optical time offset; gyro scale/misalignment = median fit of the other trials:")
        for f, s in loto.groupby("filter", sort=False):
            k, m = int(s.inside.sum()), len(s)
            lo, hi = wilson_interval(k, m)
            summary = pd.concat([summary, pd.DataFrame([{
                "scope": "all, twin + other trials' gaps (LOTO)", "filter": f, "trials": m, "inside": k, "coverage": k / m,
                "coverage_low": lo, "coverage_high": hi, "nominal": nominal,
                "median_width_deg": float((s.twin_high_deg - s.twin_low_deg).median()),
                "median_real_over_twin": float(s.real_over_twin_median.median())}])], ignore_index=True)
            lines.append(f"  {f:10s} coverage {k}/{m} = {k / m:.2f} (Wilson {lo:.2f}-{hi:.2f}), median real/twin "
                         f"{float(s.real_over_twin_median.median()):.2f}")
    return Artifact(table=summary, rows=rows, lines=lines, data={"twin": tw, "nominal": nominal})
