# %% [markdown]
# # 30 — wang2022sensors: zero-velocity detection and rotation-axis estimation
#
# Wang et al., *Sensors* 2022, 22, 8996 (RAMS). This notebook covers the ZVD
# (Sec. 3.1, Table 1: wang2022sensors_fig06, wang2022sensors_table01), the sensor table (wang2022sensors_table02), the axis
# geometry of Sec. 6 (wang2022sensors_fig12), the axis estimates of Table 4 (wang2022sensors_table04), and,
# beyond the paper, the axis-estimate error against rest duration and axis
# elevation γ (Monte Carlo vs the first-order formula).
#
# Simulation choices (all in `mtcal.studies.wang2022sensors.runs`): Table 3 IMU at 200 Hz,
# accelerometer bias left after the ref. [30] calibration 0.1 mg (Table 3's
# 50 mg taken literally is shown as a sensitivity in notebook 31), Table 3
# random-walk rows read as u·√Hz = u/√s, IMU level at θ = 0, lever arm 0.2 m.

# %% tags=["parameters"]
import os

SEED = 4004
SIZE = os.environ.get("MTCAL_SIZE", "full")  # "ci" under `make test`
N_TRIALS = 1000 if SIZE == "full" else 300  # Monte Carlo trials for axis estimates
ZVD_TRIALS = 50 if SIZE == "full" else 20  # noise seeds of the wang2022sensors_fig06 record
N_BOOT = 1000 if SIZE == "full" else 500  # bootstrap resamples for ratios / slopes of MC medians

# %%
import dataclasses

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from IPython.display import display

from mtcal.methods import rotation_axis as axis
from mtcal.reporting import compare
from mtcal.core import metrics, profiles
from mtcal.reporting import paper_numbers as paper, output as report
from mtcal.core.units import UG
from mtcal.studies.wang2022sensors.runs import (PAPER_AXIS_FIG11, ImuSpec, RotationSetup, run_axis_mc,
                                simulate_rotation, table4_axes)
from mtcal.methods.zero_velocity import ZvdParams, detect_static, rest_intervals

report.setup_matplotlib()
rng = np.random.default_rng(SEED)
rng_boot = np.random.default_rng([SEED, 1])  # bootstrap draws kept apart from the simulation's
imu = ImuSpec()
rows = []


def angle_deg(a, b):
    return np.degrees(axis.angle_between(a, b))


# %% [markdown]
# ## wang2022sensors_table01 — ZVD parameters (Table 1)
#
# `ZvdParams.from_paper()` reads the transcribed Table 1; mtcal's only addition
# is a minimum window of 3 samples (at 200 Hz, t_w = 0.01 s is 2 samples).

# %%
# NBVAL_CHECK_OUTPUT
zp = ZvdParams.from_paper()
t1 = pd.DataFrame({"parameter": ["th_a_min (m/s^2)", "th_a_max (m/s^2)", "th_zeta_a (m^2/s^4)",
                                 "t_w (s)", "th_t (s)", "n_w at 200 Hz", "n_h at 200 Hz"],
                   "value": [zp.accel_min_m_s2, zp.accel_max_m_s2, zp.var_threshold_m2_s4,
                             zp.window_s, zp.min_duration_s, zp.window_samples(imu.fs_hz),
                             zp.duration_samples(imu.fs_hz)]})
report.save_table(t1, "wang2022sensors_table01")
report.show_table(t1)

# %% [markdown]
# ## wang2022sensors_fig06 — ZVD on a rotate/hold acceleration record
#
# Steps of 30° at 20°/s with 1 s holds, lever arm 0.2 m. The ZVD of Table 1
# looks only at ‖a‖, which a rotation about an axis through the sensor does
# not change; it sees motion only through the lever-arm (tangential +
# centripetal) acceleration. So it misses the slow ends of every move. The
# optional gyro condition (‖ω − b̂‖ < 2°/s, mtcal) closes most of that gap.
# Figure: one noise seed; numbers: median and 95 % band over `ZVD_TRIALS` seeds.

# %%
prof = profiles.step_schedule(np.radians([0, 30, 60, 30, -30, 0]), np.radians(20.0), 1.0, imu.fs_hz)
setup = RotationSetup()
th6 = np.broadcast_to(prof.angle_rad[:, 0], (ZVD_TRIALS, prof.time_s.size))
rec = simulate_rotation(th6, np.broadcast_to(prof.rate_rad_s[:, 0], th6.shape),
                        np.broadcast_to(prof.accel_rad_s2[:, 0], th6.shape), prof.is_static, setup,
                        imu.error_model(), imu.fs_hz, rng)
st_paper = detect_static(rec.accel_m_s2, imu.fs_hz, zp)  # (trials, N)
b0 = rec.gyro_rad_s[:, :150].mean(axis=1)
st_gyro = detect_static(rec.accel_m_s2, imu.fs_hz, dataclasses.replace(zp, gyro_max_rad_s=np.radians(2.0)),
                        rec.gyro_rad_s - b0[:, None, :])
a = rec.accel_m_s2[0]
fig, axs = plt.subplots(3, 1, figsize=(8, 6), sharex=True)
axs[0].plot(rec.time_s, np.degrees(rec.theta_rad[0]))
axs[0].set_ylabel("θ (deg)")
axs[1].plot(rec.time_s, np.linalg.norm(a, axis=1), lw=0.6)
axs[1].axhspan(zp.accel_min_m_s2, zp.accel_max_m_s2, color="tab:green", alpha=0.15, label="Table 1 band")
axs[1].set_ylabel("‖a‖ (m/s²)")
axs[1].legend(loc="lower right")
axs[2].plot(rec.time_s, prof.is_static + 0.0, "k", lw=2, label="true rest")
axs[2].plot(rec.time_s, st_paper[0] * 0.9, label="ZVD Table 1")
axs[2].plot(rec.time_s, st_gyro[0] * 0.8, label="ZVD + gyro (mtcal)")
axs[2].set_ylabel("static")
axs[2].set_xlabel("time (s)")
axs[2].legend(loc="lower right", fontsize=8)
display(report.save_figure(fig, "wang2022sensors_fig06"))
moving = ~prof.is_static
fp_paper = metrics.percentile_band(np.mean(st_paper & moving, axis=1) / np.mean(moving))  # per trial
fp_gyro = metrics.percentile_band(np.mean(st_gyro & moving, axis=1) / np.mean(moving))
miss = metrics.percentile_band(np.mean(~st_paper & prof.is_static, axis=1) / np.mean(prof.is_static))
holds = prof.hold_slices()
rests_found = np.sum([np.mean(st_gyro[:, sl], axis=1) > 0.5 for sl in holds], axis=0)  # per trial
all_found = float(np.mean(rests_found == len(holds)))
print(f"moving samples flagged static (median over {ZVD_TRIALS} seeds): Table 1 ZVD {fp_paper['median']:.1%}, "
      f"with gyro condition {fp_gyro['median']:.1%}")
print(f"rest samples missed by Table 1 ZVD: median {miss['median']:.1%}, 97.5 % {miss['high']:.1%}; static "
      f"intervals in trial 0: Table 1 {len(rest_intervals(st_paper[0]))}, with gyro "
      f"{len(rest_intervals(st_gyro[0]))} (true rests: {len(holds)})")
print(f"trials in which all {len(holds)} true rests are more than half flagged static (ZVD + gyro): {all_found:.0%}")
rows.append(compare.comparison_row("wang2022sensors_fig06", "share of seeds with every true rest detected (ZVD + gyro)", "6 (figure)",
                                 all_found, "every rest detected", all_found == 1.0))
rows.append(compare.comparison_row("wang2022sensors_fig06", "moving samples flagged static, Table 1 ZVD", "n/a",
                                 float(fp_paper["median"]), "", None, band=fp_paper))
rows.append(compare.comparison_row("wang2022sensors_fig06", "moving samples flagged static, ZVD + gyro", "n/a",
                                 float(fp_gyro["median"]), "(mtcal finding) gyro condition reduces misses",
                                 bool(fp_gyro["high"] < fp_paper["low"]), band=fp_gyro))

# %%
assert all_found == 1.0 and len(holds) == 6
assert fp_gyro["high"] < fp_paper["low"] and miss["high"] < 0.05

# %% [markdown]
# ## wang2022sensors_table02 — sensors (Table 2 + Table 3) with a derived column
#
# Derived: the per-sample angle noise of an accelerometer-only reading at rest
# (ref. [16]), σθ = N·√fs / (g cos γ), at 200 Hz and γ = 0; and the same after
# averaging a 1 s rest (÷ √fs).

# %%
t2 = paper.load("wang2022sensors_table02_accel_noise_prices")
fs = imu.fs_hz
t2["sigma_theta_per_sample_deg"] = np.degrees(t2.accel_noise_density_ug_per_sqrt_hz * UG * np.sqrt(fs) / 9.80665)
t2["sigma_theta_1s_mean_deg"] = np.degrees(t2.accel_noise_density_ug_per_sqrt_hz * UG / 9.80665)
t2 = pd.concat([t2.drop(columns="extracted_cell_text"),
                pd.DataFrame({"ic": ["Table 3 sim IMU"], "accel_noise_density_ug_per_sqrt_hz": [50.0],
                              "unit_price_usd": [np.nan],
                              "sigma_theta_per_sample_deg": [np.degrees(imu.predicted_static_angle_noise_rad())],
                              "sigma_theta_1s_mean_deg": [np.degrees(imu.predicted_static_angle_noise_rad() / np.sqrt(fs))]})],
               ignore_index=True)
report.save_table(t2, "wang2022sensors_table02")
report.show_table(t2)
rows.append(compare.comparison_row("wang2022sensors_table02", "ADXL355+BMI088 cost (USD)", "< 100", f"{52.14 + 28.75:.2f}",
                                 "sensor cost under USD 100", 52.14 + 28.75 < 100))

# %% [markdown]
# ## wang2022sensors_fig12 — ‖g1 − g0‖ vs axis elevation γ (Sec. 6)
#
# `g1 = R(30°, v)ᵀ g0`. Only the gravity component perpendicular to v turns, so
# ‖g1 − g0‖ = 2 g cos γ sin 15°: γ = 60° halves it. The right panel is what
# that does to the axis estimate (Monte Carlo of Eq 23 vs the first-order
# formula `axis.axis_error_std`, ∝ 1/cos γ), rests at 0/90/180°, 1 s each.
# The band of a ratio (or slope) of Monte Carlo medians is its bootstrap 95 %
# interval (`metrics.bootstrap_medians`).

# %%
gam_deg = np.arange(0, 86, 5.0)
gnorm = axis.gravity_change_norm(np.radians(gam_deg), np.radians(30.0), 9.8)
# direct check with rotation matrices
from mtcal.core.rotations import axis_angle_matrix

g0 = np.array([0, 0, 9.8])
direct = [np.linalg.norm(axis_angle_matrix(np.radians(30), [np.cos(np.radians(x)), 0, np.sin(np.radians(x))]).T @ g0 - g0)
          for x in gam_deg]
np.testing.assert_allclose(gnorm, direct, atol=1e-12)
ratio = float(gnorm[gam_deg == 60][0] / gnorm[0])
gam_mc = np.array([0.0, 30.0, 45.0, 60.0, 70.0, 80.0])
sig_mean = imu.accel_noise_per_sample_m_s2 / np.sqrt(fs * 1.0)
mc_med, mc_lo, mc_hi, mc_err = [], [], [], []
for gm in gam_mc:  # one batched Monte Carlo per display elevation
    vv = np.array([np.cos(np.radians(gm)) * 0.2, np.cos(np.radians(gm)) * np.sqrt(0.96), np.sin(np.radians(gm))])
    v_est, _ = run_axis_mc(RotationSetup(axis=tuple(vv)), imu, N_TRIALS, rng, rest_s=1.0)
    mc_err.append(angle_deg(v_est, vv))
    band = metrics.percentile_band(mc_err[-1])
    mc_med.append(band["median"]); mc_lo.append(band["low"]); mc_hi.append(band["high"])
pred = np.degrees(axis.axis_error_std(sig_mean, np.radians(gam_mc), np.radians([0, 90, 180])))
fig, axs = plt.subplots(1, 2, figsize=(10, 3.8))
axs[0].plot(gam_deg, gnorm / 9.8, "o-")
axs[0].axvline(60, color="k", ls=":")
axs[0].set_xlabel("axis elevation γ (deg)")
axs[0].set_ylabel("‖g1 − g0‖ (g)")
axs[1].fill_between(gam_mc, mc_lo, mc_hi, alpha=0.3, label="MC 95 % band")
axs[1].plot(gam_mc, mc_med, "o-", label="MC median")
axs[1].plot(gam_mc, pred * np.sqrt(np.log(2)), "k--",
            label="formula (Rayleigh median)")
axs[1].set_xlabel("axis elevation γ (deg)")
axs[1].set_ylabel("axis error (deg)")
axs[1].set_yscale("log")
axs[1].legend(fontsize=8)
display(report.save_figure(fig, "wang2022sensors_fig12"))
print(f"||g1-g0||(60 deg) / ||g1-g0||(0 deg) = {ratio:.4f}")
boot = metrics.bootstrap_medians([mc_err[0], mc_err[3]], rng_boot, N_BOOT)
ratio_axis = metrics.percentile_band(boot[:, 1] / boot[:, 0])  # bootstrap 95 % interval of the ratio of medians
ratio_med = float(mc_med[3] / mc_med[0])
print(f"axis-error median 60/0 deg: MC {ratio_med:.2f} [{ratio_axis['low']:.2f}, {ratio_axis['high']:.2f}], "
      f"formula {pred[3] / pred[0]:.2f}")
rows.append(compare.comparison_row("wang2022sensors_fig12", "||g1-g0|| ratio gamma=60/0", 0.5, ratio,
                                 "gamma = 60 deg halves ||g1-g0||", abs(ratio - 0.5) < 1e-12))
for k in (0, 3):
    rows.append(compare.comparison_row("wang2022sensors_fig12", f"axis error at gamma = {gam_mc[k]:.0f} deg, 1 s rests (deg)", "n/a",
                                     float(mc_med[k]), "", None, band=(mc_lo[k], mc_hi[k])))
rows.append(compare.comparison_row("wang2022sensors_fig12", "axis error ratio gamma=60/0 (MC medians)", "n/a", ratio_med,
                                 "(mtcal) axis error doubles at 60 deg (1.6-2.5)", 1.6 < ratio_med < 2.5,
                                 band=ratio_axis))

# %%
# NBVAL_CHECK_OUTPUT
assert abs(ratio - 0.5) < 1e-12
print("gamma = 60 deg halves ||g1 - g0||: True")

# %% [markdown]
# ## wang2022sensors_table04 — axis estimates for axes near X, near Y and tilted
#
# The Table 4 vectors are used as the *true* axes (signs as extracted; see
# README), IMU level at θ = 0, three 2 s rests at 0/90/180° per trial, Eq 23 on
# the ZVD-masked rest means. Paper: one estimate each, printed to 4 decimals.
# mtcal: median estimate and the 95 % band of the angular error.

# %%
t4_rows = []
for name, v_true in table4_axes().items():
    v_est, _ = run_axis_mc(RotationSetup(axis=tuple(v_true)), imu, N_TRIALS, rng, rest_s=2.0)
    err = angle_deg(v_est, v_true)
    band = metrics.percentile_band(err)
    med = np.median(v_est, axis=0)
    p = paper.load("wang2022sensors_table04_rotation_axes").set_index("axis_symbol").loc[name]
    t4_rows.append({"axis": name, "paper_vx": p.bv_x, "paper_vy": p.bv_y, "paper_vz": p.bv_z,
                    "mtcal_vx": med[0], "mtcal_vy": med[1], "mtcal_vz": med[2],
                    "err_median_deg": band["median"], "err_low_deg": band["low"], "err_high_deg": band["high"]})
    rows.append(compare.comparison_row("wang2022sensors_table04", f"{name} axis error (deg)", "n/a (4 decimals)",
                                     float(band["median"]),
                                     "median error below the 4-decimal print step (1e-4 = 0.0057 deg)",
                                     bool(band["median"] < 0.0057), band=band))
t4 = pd.DataFrame(t4_rows)
report.save_table(t4, "wang2022sensors_table04")
report.show_table(t4, "{:.5f}")

# %%
assert all(r["err_median_deg"] < 0.0057 for r in t4_rows)

# %% [markdown]
# ## Beyond — axis error vs rest duration (γ = 3°, Fig. 11 axis)
#
# Averaging n = fs·t samples divides the mean's noise by √n, so the axis error
# falls as 1/√t (formula line: the median of a Rayleigh error with the
# formula's total std). A constant accelerometer bias cancels exactly in Eq 23's
# differences, so white noise is the only term and the Monte Carlo follows the
# formula.

# %%
rest_s = np.array([0.25, 0.5, 1.0, 2.0, 4.0])
med_r, lo_r, hi_r, med_oracle, err_r, err_oracle = [], [], [], [], [], []
imu_white = dataclasses.replace(imu, random_walk_interpretation="none")  # white noise only
v11 = np.array(PAPER_AXIS_FIG11) / np.linalg.norm(PAPER_AXIS_FIG11)
for rs in rest_s:
    v_est, _ = run_axis_mc(RotationSetup(axis=tuple(v11)), imu, N_TRIALS, rng, rest_s=float(rs))
    err_r.append(angle_deg(v_est, v11))
    b = metrics.percentile_band(err_r[-1])
    med_r.append(b["median"]); lo_r.append(b["low"]); hi_r.append(b["high"])
    v_oracle, _ = run_axis_mc(RotationSetup(axis=tuple(v11)), imu_white, N_TRIALS, rng, rest_s=float(rs),
                              use_zvd=False)
    err_oracle.append(angle_deg(v_oracle, v11))
    med_oracle.append(float(np.median(err_oracle[-1])))
pred_r = np.degrees(axis.axis_error_std(imu.accel_noise_per_sample_m_s2 / np.sqrt(fs),
                                        np.arcsin(v11[2]), np.radians([0, 90, 180]))) / np.sqrt(rest_s)
fig, ax = plt.subplots()
ax.fill_between(rest_s, lo_r, hi_r, alpha=0.3, label="MC 95 % band (ZVD rests)")
ax.loglog(rest_s, med_r, "o-", label="MC median (ZVD rests)")
ax.loglog(rest_s, med_oracle, "s-", label="MC median (true rests, no random walk)")
ax.loglog(rest_s, pred_r * np.sqrt(np.log(2)), "k--", label="formula (median)")
ax.set_xlabel("rest duration per position (s)")
ax.set_ylabel("axis error (deg)")
ax.legend()
display(report.save_figure(fig, "wang2022sensors_extra_axis_error_vs_rest"))
slope = float(np.polyfit(np.log(rest_s), np.log(med_oracle), 1)[0])
slope_zvd = float(np.polyfit(np.log(rest_s), np.log(med_r), 1)[0])
boot_slopes = {k: np.polyfit(np.log(rest_s), np.log(metrics.bootstrap_medians(e, rng_boot, N_BOOT).T), 1)[0]
               for k, e in (("white", err_oracle), ("zvd", err_r))}
b_slope, b_slope_zvd = (metrics.percentile_band(boot_slopes[k]) for k in ("white", "zvd"))
b_diff = metrics.percentile_band(boot_slopes["zvd"] - boot_slopes["white"])
print(f"log-log slope of the median axis error vs rest time: white noise only {slope:.2f} "
      f"[{b_slope['low']:.2f}, {b_slope['high']:.2f}], Table 3 IMU with ZVD rests {slope_zvd:.2f} "
      f"[{b_slope_zvd['low']:.2f}, {b_slope_zvd['high']:.2f}] (theory for white noise -0.50)")
rows.append(compare.comparison_row("wang2022sensors_extra_axis_error_vs_rest", "axis error slope vs rest time (white noise, true rests)", "n/a",
                                 slope, "(mtcal) error falls as 1/sqrt(t) (|slope + 0.5| < 0.1)",
                                 abs(slope + 0.5) < 0.1, band=b_slope))
rows.append(compare.comparison_row("wang2022sensors_extra_axis_error_vs_rest", "axis error slope vs rest time (Table 3 IMU, ZVD)", "n/a",
                                 slope_zvd, "(mtcal finding) shallower: bias random walk",
                                 bool(b_diff["low"] > 0), band=b_slope_zvd))

# %% [markdown]
# With white noise only, the error follows 1/√t (slope −0.5). With Table 3's
# accelerometer random walk (read as µg·√Hz) the slope is shallower (about
# −0.42): the bias wanders between the three rests and does not cancel in
# Eq 23's differences, and longer rests also mean a longer schedule, so
# lengthening the rests buys less than √t. (The ZVD adds little: checked
# separately, true rests with the random walk on give about −0.43.)

# %%
assert abs(slope + 0.5) < 0.1  # ≈ 5 bootstrap sigmas at CI size: not a lucky-seed test
assert b_diff["low"] > 0, "with the random walk the slope must be shallower (bootstrap 95 % interval of the difference)"

# %% [markdown]
# ## Paper vs mtcal

# %%
table = compare.comparison_table(rows)
table.to_csv(report.output_dir() / "data" / "wang2022sensors_axis_zvd_comparison.csv", index=False)
report.show_table(table)
print(compare.claims_summary(table))
print(compare.band_summary(table))

# %%
assert table["holds"].dropna().all(), "a reproduced claim failed"
