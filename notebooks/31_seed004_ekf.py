# %% [markdown]
# # 31 — Seed 004: RAMS EKF, ref. [16] and the AHRS stand-in
#
# Wang et al., *Sensors* 2022 (RAMS), Sec. 3.3, 5 and 7: the EKF with ZVD
# covariance switching (F004-9), the simulation of Fig. 11, Table 5
# (T004-5), the drift test of Fig. 13 and the per-angle maximum error of
# Fig. 14, plus the sensitivity to Table 3's ambiguous rows.
#
# Set-up (`mtcal.scenarios004`): Table 3 IMU at 200 Hz, 0.1 mg residual
# accelerometer bias, lever arm 0.2 m, turntable steps at 20 °/s with 1 s
# holds. RAMS = Algorithm A1 axis + EKF. "ZVD" below is Table 1 plus the
# optional gyro condition ‖ω − b̂0‖ < 2 °/s unless marked "Table 1 only"
# (notebook 30, F004-6, shows why). The AHRS stand-in is a 9-axis
# complementary filter on Ellipse2-N-class sensors in a magnetic field whose
# heading wanders by 5° (1σ, τ = 20 s).

# %% tags=["parameters"]
import os

SEED = 4031
SIZE = os.environ.get("MTCAL_SIZE", "full")  # "ci" under `make test`
SWEEP_TRIALS = 16 if SIZE == "full" else 2   # Table 5 sweeps per axis
FIG11_REPS = 14 if SIZE == "full" else 1     # x 73 angles = trials of the Fig. 11 Monte Carlo
DRIFT_RUN_S = 600.0 if SIZE == "full" else 60.0
DRIFT_TRIALS = 4 if SIZE == "full" else 2
SENS_REPS = 4 if SIZE == "full" else 1

# %%
import dataclasses

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from IPython.display import display

from mtcal import metrics, paper, profiles, report, rotations
from mtcal.filters.rams_ekf import initial_state, run_rams_ekf
from mtcal.scenarios004 import (Imu004, RotationSetup, run_drift, run_fig11, run_sweep,
                                simulate_rotation, table4_axes)
from mtcal.zvd import ZvdParams, detect_static, rest_intervals

report.setup_matplotlib()
rng = np.random.default_rng(SEED)
imu = Imu004()
GYRO_ZVD = np.radians(2.0)
rows = []
deg = np.degrees

# %% [markdown]
# ## F004-9 — EKF with and without ZVD switching
#
# 0–1 s still, 1–2 s rotating 60° (lever arm 0.2 m: tangential + centripetal
# acceleration), 2–3 s still. The standard EKF (always V_z) reads the
# lever-arm acceleration as angle; with ZVD switching the gyro carries the
# motion and the error stays small; both agree at rest.

# %%
setup = RotationSetup()
prof = profiles.step_schedule(np.radians([0.0, 60.0]), np.radians(60.0), 1.0, imu.fs_hz)
rec = simulate_rotation(prof.angle_rad[:, 0], prof.rate_rad_s[:, 0], prof.accel_rad_s2[:, 0],
                        prof.is_static, setup, imu.error_model(), imu.fs_hz, rng)
a0, b0 = initial_state(rec.gyro_rad_s, rec.accel_m_s2, 180)
st = detect_static(rec.accel_m_s2, imu.fs_hz, dataclasses.replace(setup.zvd, gyro_max_rad_s=GYRO_ZVD),
                   rec.gyro_rad_s - b0[:, None, :])
v = setup.unit_axis()
res_z = run_rams_ekf(rec.gyro_rad_s, rec.accel_m_s2, st, v, a0, imu.dt_s, imu.ekf_params(), bias0_rad_s=b0)
res_n = run_rams_ekf(rec.gyro_rad_s, rec.accel_m_s2, st, v, a0, imu.dt_s, imu.ekf_params(), bias0_rad_s=b0,
                     use_zvd=False)
e_z = deg(rotations.wrap_angle(res_z.theta_rad[0] - rec.theta_rad[0]))
e_n = deg(rotations.wrap_angle(res_n.theta_rad[0] - rec.theta_rad[0]))
t = rec.time_s
fig, axs = plt.subplots(4, 1, figsize=(8, 8), sharex=True)
axs[0].plot(t, deg(rec.theta_rad[0]))
axs[0].set_ylabel("(a) θ ref (deg)")
axs[1].plot(t, e_z, label="EKF with ZVD")
axs[1].plot(t, e_n, "--", label="EKF")
axs[1].set_ylabel("(b) error (deg)")
axs[1].legend()
axs[2].plot(t, np.linalg.norm(rec.accel_m_s2[0], axis=1))
axs[2].set_ylabel("(c) ‖a‖ (m/s²)")
axs[3].plot(t, deg(np.linalg.norm(rec.gyro_rad_s[0], axis=1)))
axs[3].set_ylabel("(d) ‖ω‖ (°/s)")
axs[3].set_xlabel("time (s)")
display(report.save_figure(fig, "F004-9"))
moving = ~prof.is_static
still1 = t < 1.0
still2 = t > 2.5
rm_z, rm_n = float(metrics.rmse(e_z, mask=moving)), float(metrics.rmse(e_n, mask=moving))
print(f"moving RMSE: with ZVD {rm_z:.4f} deg, without {rm_n:.4f} deg")
print(f"still 1 max |difference| between the two: {np.max(np.abs(e_z - e_n)[still1]):.5f} deg")
print(f"last 0.5 s max |error| with ZVD: {np.max(np.abs(e_z[still2])):.4f} deg")
rows.append(paper.comparison_row("F004-9", "moving RMSE with / without ZVD (deg)", "figure",
                                 f"{rm_z:.4f} / {rm_n:.4f}", "ZVD EKF better in motion", rm_z < rm_n))
rows.append(paper.comparison_row("F004-9", "still period 1: |with - without| max (deg)", "almost same",
                                 float(np.max(np.abs(e_z - e_n)[still1])), "same while still",
                                 bool(np.max(np.abs(e_z - e_n)[still1]) < 0.005)))

# %%
assert rm_z < 0.2 * rm_n
assert np.max(np.abs(e_z - e_n)[still1]) < 0.005 and np.max(np.abs(e_z[still2])) < 0.05

# %% [markdown]
# ## F004-11 — maximum error vs angle, proposed vs ref. [16] (Sec. 5)
#
# Axis v = [0.1734, 0.9835, 0.0523]; −180…180° in 5° steps; at each angle
# "1000 measurements" = 1000 consecutive outputs (5 s at 200 Hz) after the
# move. One batched Monte Carlo: a trial = (angle, repetition), each with its
# own axis estimate from three rests. Curves: median over repetitions of the
# per-angle maximum error, with the 95 % band.

# %%
f11 = run_fig11(RotationSetup(), imu, FIG11_REPS, rng)
ang = deg(f11.angles_rad)
b_r = metrics.percentile_band(deg(f11.max_err_rams), axis=0)
b_16 = metrics.percentile_band(deg(f11.max_err_ref16), axis=0)
fig, ax = plt.subplots(figsize=(8, 4))
for b, lab in ((b_r, "proposed (RAMS EKF)"), (b_16, "ref. [16] (accelerometer only)")):
    ax.fill_between(ang, b["low"], b["high"], alpha=0.25)
    ax.plot(ang, b["median"], "o-", ms=3, label=lab)
ax.set_xlabel("rotation angle (deg)")
ax.set_ylabel("max error over 1000 measurements (deg)")
ax.legend()
display(report.save_figure(fig, "F004-11"))
better = float(np.mean(b_r["median"] < b_16["median"]))
print(f"angles where the proposed median max error is below ref. [16]: {better:.0%}")
print(f"proposed: median of per-angle max {np.median(b_r['median']):.4f} deg, worst {np.max(deg(f11.max_err_rams)):.4f} deg")
print(f"ref. [16]: median of per-angle max {np.median(b_16['median']):.4f} deg, worst {np.max(deg(f11.max_err_ref16)):.4f} deg")
rows.append(paper.comparison_row("F004-11", "share of angles where proposed < ref. [16]", "all (figure)",
                                 better, "proposed superior to ref. [16]", better > 0.9))

# %%
assert better > 0.9

# %% [markdown]
# ## T004-5 — static and dynamic RMSE: RAMS vs ref. [16] vs AHRS stand-in
#
# Sweep −180…180° in 10° steps, 1 s pauses, after the three axis-estimation
# rests; static/dynamic from the turntable schedule (the simulation knows it;
# the paper used its ZVD). Three RAMS variants: ZVD as used here (Table 1 +
# gyro), Table 1 only, and an oracle that switches the EKF by the true
# schedule (isolates ZVD errors from filter errors).

# %%
p5 = paper.load("seed004_table05_rmse")
sysmap = {"RAMS": "RAMS", "Ellipse2-N": "AHRS stand-in", "Method in ref. [16]": "ref. [16]"}
t5_rows, all_stat = [], {}
for name, v_true in table4_axes().items():
    s = RotationSetup(axis=tuple(v_true))
    r_main = run_sweep(s, imu, SWEEP_TRIALS, rng, zvd_gyro_max_rad_s=GYRO_ZVD)
    r_t1 = run_sweep(s, imu, SWEEP_TRIALS, rng, with_ahrs=False)
    r_or = run_sweep(s, imu, SWEEP_TRIALS, rng, with_ahrs=False, zvd_gyro_max_rad_s=GYRO_ZVD, ekf_switch="truth")
    stat, dyn = r_main.sweep & r_main.true_static, r_main.sweep & ~r_main.true_static
    variants = {"RAMS": r_main.err_rams, "RAMS (Table 1 ZVD only)": r_t1.err_rams,
                "RAMS (oracle switching)": r_or.err_rams, "ref. [16]": r_main.err_ref16,
                "AHRS stand-in": r_main.err_ahrs}
    all_stat[name] = r_main
    for sysname, err in variants.items():
        bs = metrics.percentile_band(deg(metrics.rmse(err, mask=stat)))
        bd = metrics.percentile_band(deg(metrics.rmse(err, mask=dyn)))
        prow = p5[(p5.rotation_axis == name) & (p5.system.map(sysmap) == sysname)]
        ps = float(prow.rmse_static_deg.iloc[0]) if len(prow) else np.nan
        pdy = float(prow.rmse_dynamic_deg.iloc[0]) if len(prow) else np.nan
        t5_rows.append({"axis": name, "system": sysname, "paper_static": ps, "mtcal_static_median": bs["median"],
                        "static_low": bs["low"], "static_high": bs["high"], "paper_dynamic": pdy,
                        "mtcal_dynamic_median": bd["median"], "dynamic_low": bd["low"], "dynamic_high": bd["high"]})
t5 = pd.DataFrame(t5_rows)
report.save_table(t5, "T004-5")
report.show_table(t5)

# %%
def _get(axis_name, sysname, col):
    return float(t5[(t5.axis == axis_name) & (t5.system == sysname)][col].iloc[0])


for name in table4_axes():
    for sysname, claim, col, ok in (
            ("RAMS", "RAMS static RMSE < 0.02 deg", "static", lambda x: x < 0.02),
            ("RAMS (oracle switching)", "(mtcal) oracle-switched RAMS static < 0.02 deg", "static", lambda x: x < 0.02),
            ("RAMS", "RAMS dynamic RMSE < 0.5 deg", "dynamic", lambda x: x < 0.5),
            ("ref. [16]", "ref. [16] static RMSE < 0.1 deg", "static", lambda x: x < 0.1),
            ("ref. [16]", "ref. [16] fails dynamically (> 1 deg)", "dynamic", lambda x: x > 1.0),
            ("AHRS stand-in", "AHRS static RMSE > 0.1 deg", "static", lambda x: x > 0.1)):
        val = _get(name, sysname, f"mtcal_{col}_median")
        lo, hi = _get(name, sysname, f"{col}_low"), _get(name, sysname, f"{col}_high")
        pv = _get(name, sysname, f"paper_{col}")
        inside = "" if np.isnan(pv) else (" (paper inside band)" if lo <= pv <= hi else " (paper outside band)")
        rows.append(paper.comparison_row("T004-5", f"{name} {sysname} {col} RMSE (deg){inside}",
                                         "n/a" if np.isnan(pv) else pv,
                                         f"{val:.4f} [{lo:.4f}, {hi:.4f}]", claim, bool(ok(val))))

# %% [markdown]
# **Reading T004-5.** ref. [16]'s static RMSE (~0.04°) is its per-sample
# noise N√fs/g (T004-2) and it fails in motion (lever-arm acceleration read as
# angle), as in the paper. The AHRS stand-in exceeds 0.1° because the
# wandering field heading leaks into the angle about a near-horizontal axis.
# RAMS: the dynamic claim holds easily (the simulation has no sensor-to-
# reference latency; the paper's 0.41–0.46° most likely includes one — 0.4°
# at ~40 °/s peak rate is ~10 ms). The static claim < 0.02° **fails** with the
# ZVD-switched EKF (≈ 0.03°) but **holds** with oracle switching (≈ 0.01°):
# Table 1's 0.01 s windows flag the slow ends of every move as static, where
# the tangential lever-arm acceleration is read as angle, and the EKF, whose
# covariance is small after a long rest, takes a while to recover. With the
# ZVD of Table 1 alone (no gyro condition) it is much worse (≈ 0.1–0.2°).

# %%
for name in table4_axes():
    assert _get(name, "RAMS (oracle switching)", "mtcal_static_median") < 0.02
    assert _get(name, "RAMS", "mtcal_dynamic_median") < 0.5
    assert _get(name, "ref. [16]", "mtcal_static_median") < 0.1
    assert _get(name, "ref. [16]", "mtcal_dynamic_median") > 1.0
    assert _get(name, "AHRS stand-in", "mtcal_static_median") > 0.1
    assert _get(name, "RAMS", "mtcal_static_median") < _get(name, "RAMS (Table 1 ZVD only)", "mtcal_static_median")

# %% [markdown]
# ## F004-13 — standing still for 1 min after running
#
# After `DRIFT_RUN_S` of random steps (10 min at full size) both systems stand
# still for 60 s. RAMS is held by the accelerometer; the AHRS stand-in's
# angle follows the wandering magnetic heading.

# %%
dr = run_drift(RotationSetup(), imu, DRIFT_TRIALS, rng, run_s=DRIFT_RUN_S, stand_s=60.0)
ts = dr.time_s[dr.standing] - dr.time_s[dr.standing][0]
fig, ax = plt.subplots(figsize=(8, 4))
for k in range(DRIFT_TRIALS):
    ax.plot(ts, deg(dr.err_ahrs[k, dr.standing]), color="tab:red", lw=0.8, label="AHRS stand-in" if k == 0 else None)
    ax.plot(ts, deg(dr.err_rams[k, dr.standing]), color="tab:blue", lw=0.8, label="RAMS" if k == 0 else None)
ax.set_xlabel("time standing (s)")
ax.set_ylabel("angle error (deg)")
ax.legend()
display(report.save_figure(fig, "F004-13"))
# drift = change of the 1-s mean from the first to the last second of the stand
n1 = int(imu.fs_hz)
def drift(e):
    s = deg(e[:, dr.standing])
    return np.abs(s[:, -n1:].mean(axis=1) - s[:, :n1].mean(axis=1))
d_r, d_a = drift(dr.err_rams), drift(dr.err_ahrs)
print(f"1-min drift, RAMS: max {d_r.max():.4f} deg; AHRS stand-in: median {np.median(d_a):.4f} deg")
rows.append(paper.comparison_row("F004-13", "1-min drift RAMS / AHRS (deg)", "constant / shifts",
                                 f"{d_r.max():.4f} / {np.median(d_a):.4f}", "RAMS holds, AHRS drifts",
                                 bool(d_r.max() < 0.02 and np.median(d_a) > 5 * d_r.max())))

# %%
assert d_r.max() < 0.02 and np.median(d_a) > 5 * d_r.max()

# %% [markdown]
# ## F004-14 — maximum RAMS error per angle (sweep holds)
#
# Per 10° hold of the T004-5 sweeps (all three axes), the maximum |error|
# over the settled second half of each 1 s hold (mtcal's reading of "the
# measurement error for various angles"); median and 95 % band over trials.
# Over the *whole* hold the maximum is dominated by the first samples after
# each move, where the ZVD-switched filter is still pulling back the error
# picked up at the slow end of the move (see T004-5): reported, not claimed.

# %%
def per_hold_max(res, err, settled=True):
    holds = [sl for sl in rest_intervals(res.true_static & res.sweep)]
    use = [slice((sl.start + sl.stop) // 2, sl.stop) if settled else sl for sl in holds]
    return np.stack([np.max(np.abs(deg(err[:, sl])), axis=1) for sl in use], axis=1), holds


fig, ax = plt.subplots(figsize=(8, 4))
worst = []
for name, res in all_stat.items():
    mx, holds = per_hold_max(res, res.err_rams)
    angles = deg(res.theta_true_rad[0, [sl.start for sl in holds]])
    b = metrics.percentile_band(mx, axis=0)
    ax.fill_between(angles, b["low"], b["high"], alpha=0.2)
    ax.plot(angles, b["median"], "o-", ms=3, label=name)
    worst.append(float(np.max(b["median"])))
ax.axhline(0.05, color="k", ls=":", label="0.05° (paper)")
ax.set_xlabel("rotation angle (deg)")
ax.set_ylabel("max |error| in hold (deg)")
ax.legend()
display(report.save_figure(fig, "F004-14"))
whole = max(float(np.max(np.median(per_hold_max(res, res.err_rams, settled=False)[0], axis=0)))
            for res in all_stat.values())
print(f"largest median per-hold max error, settled half: {max(worst):.4f} deg; whole hold: {whole:.4f} deg")
rows.append(paper.comparison_row("F004-14", "max per-angle error, settled half-hold, median (deg)", "< 0.05",
                                 max(worst), "max error per angle < 0.05 deg", max(worst) < 0.05))
rows.append(paper.comparison_row("F004-14", "max per-angle error, whole hold, median (deg)", "< 0.05",
                                 whole, "(not claimed: includes post-move transient)", None))

# %%
assert max(worst) < 0.05

# %% [markdown]
# ## Sensitivity — Table 3's ambiguous rows and the 50 mg bias
#
# Fig. 11 set-up, proposed method, median of the per-angle maximum error.
# Random-walk rows read as u·√Hz (default), as a per-sample step (×√fs), or
# off; and Table 3's 50 mg accelerometer bias applied literally (no ref. [30]
# calibration): Eq 28 assumes no bias, so the model is off by (I − Rᵀ) b.

# %%
variants = {"RW as u*sqrt(Hz) (default)": imu,
            "RW as per-sample step": Imu004(random_walk_interpretation="per_sample"),
            "RW off": Imu004(random_walk_interpretation="none"),
            "50 mg bias uncompensated": Imu004(accel_bias_compensated=False)}
sens = []
for lab, im in variants.items():
    r = run_fig11(RotationSetup(), im, SENS_REPS, rng, step_deg=15.0)
    sens.append({"variant": lab, "median_max_err_deg": float(np.median(deg(r.max_err_rams))),
                 "worst_max_err_deg": float(np.max(deg(r.max_err_rams))),
                 "ref16_median_max_err_deg": float(np.median(deg(r.max_err_ref16)))})
sens = pd.DataFrame(sens)
report.save_table(sens, "B004-2")
report.show_table(sens)

# %%
assert sens.median_max_err_deg.iloc[3] > 10 * sens.median_max_err_deg.iloc[0]

# %% [markdown]
# ## Paper vs mtcal

# %%
table = paper.comparison_table(rows)
table.to_csv(report.output_dir() / "data" / "31_seed004_ekf_comparison.csv", index=False)
report.show_table(table)
print(paper.claims_summary(table))
