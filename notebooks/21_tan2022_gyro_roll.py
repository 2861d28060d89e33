# %% [markdown]
# # 21 — tan2022: roll from gyros at large pitch (Euler differential, decoupled integration, projection, hybrid)
#
# Tan et al. (2022), Sec. 1.2, 2.2, 3.2, Figs 6, 9–12. The wind-tunnel model
# pitches and rolls (ψ ≡ 0), so the body rates are Eq 11:
# `ω = [φ̇, θ̇ cosφ, −θ̇ sinφ]`. Roll can be obtained by
#
# * **Eq 5** Euler-differential integration — singular at θ = ±90°;
# * **Eq 12** decoupled integration `φ = φ0 + ∫ω_x dt` — drifts;
# * **Eq 13** angular-velocity projection `φ = arctan(−ω_z/ω_y)` — no drift,
#   error Eq 14 `Δφ = −(Δω_z cosφ + Δω_y sinφ)/θ̇` ∝ 1/θ̇;
# * **Fig 7** hybrid: projection if |θ̇| > θ̇_t, else integration.
#
# Gyro data come from `mtcal.core.simulate` through `gyroroll.simulate_two_dof_imu`
# (mapping: `q_wb = from_euler('ZYX', [0, θ, φ])` in the simulator's z-up
# world reproduces tan2022 Eq 2 and Eq 11 exactly; see the `mtcal.methods.gyro_roll`
# docstring). Gyro errors (`tan2022.GyroErrors`): the paper's constant
# 0.2 °/s on every axis (the paper prints x and z only, but Eq 14 needs y) plus
# white noise 0.0025 °/s/√Hz (ADIS16465 class; our choice), sampled at 1 kHz.

# %% tags=["parameters"]
import os

SEED = 2023
SIZE = os.environ.get("MTCAL_SIZE", "full")  # "ci" under `make test`
FS_HZ = 1000.0  # gyro sample rate, both sizes: the θ̇_t = 0.5 °/s switch needs it (see tan2022_fig12)
N_TRIALS = 100 if SIZE == "full" else 20  # Monte Carlo trials over noise seeds
UNI_TRIALS = 20 if SIZE == "full" else 5  # trials of the uniform rotations (tan2022_fig09)
OSC_DURATION_S = 20.0 if SIZE == "full" else 10.0  # oscillation record length
N_THRESHOLDS = 60 if SIZE == "full" else 25  # θ̇_t sweep points

# %%
from dataclasses import replace

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from IPython.display import display

from mtcal.methods import gyro_roll as gr
from mtcal.reporting import compare
from mtcal.core import metrics
from mtcal.reporting import paper_numbers as paper, output as report
from mtcal.studies.tan2022.scenario import GyroErrors, Oscillation, ProjectionSweep, UniformRotation

report.setup_matplotlib()
deg, rad = np.degrees, np.radians
gyro = GyroErrors(fs_hz=FS_HZ)
rng = np.random.default_rng(SEED)
rows = []
print(f"gyro error {gyro.error_deg_s} °/s, noise {gyro.noise_density_deg_s_rthz} °/s/√Hz, fs = {gyro.fs_hz:.0f} Hz")

# %% [markdown]
# ## tan2022_fig06 — projection roll error vs pitch rate (gyro error 0.2 °/s)
#
# Formula: Eq 14 at φ = 0 (the paper's φ0), `|Δφ| = Δω_z/θ̇`, and its worst case
# over roll `√2 Δω/θ̇`; exact: arctan of Eq 13 with the constant errors;
# simulation: constant-rate pitch for 1 s per rate, bias + noise, per-trial
# mean roll error — median and 95 % band over trials. The slope of the
# simulated error in log-log above 5 °/s tests "error ∝ 1/θ̇".

# %%
sweep = ProjectionSweep(gyro=gyro)
rates = sweep.rates_rad_s
t_win = np.arange(0.0, sweep.window_s, gyro.dt_s)
sim_mean = np.empty((N_TRIALS, rates.size))
for j, r in enumerate(rates):  # loop over scenarios (rates); trials are vectorised
    rec = gr.simulate_two_dof_imu(t_win, r * t_win, np.full_like(t_win, rad(sweep.roll_deg)),
                                  gyro_bias_rad_s=gyro.error_rad_s, gyro_noise_density=gyro.noise_density_rad_s_rthz,
                                  rng=rng, trials=N_TRIALS)
    sim_mean[:, j] = np.mean(gr.roll_projection(rec.gyro_rad_s) - rad(sweep.roll_deg), axis=-1)
band = metrics.percentile_band(np.abs(sim_mean))
ey, ez = gyro.error_rad_s[1], gyro.error_rad_s[2]
eq14 = gr.projection_roll_error_eq14(rad(sweep.roll_deg), rates, ey, ez)
exact = gr.projection_roll_error_exact(rad(sweep.roll_deg), rates, ey, ez)
fit = rates >= rad(sweep.fit_min_deg_s)
slope_trials = metrics.percentile_band(gr.loglog_slope(rates[fit], sim_mean[:, fit]))  # one slope per trial
slope_sim = float(slope_trials["median"])
slope_eq14 = gr.loglog_slope(rates, eq14)
print(f"log-log slope: simulation (θ̇ ≥ {sweep.fit_min_deg_s:.0f} °/s) median over trials {slope_sim:.3f} "
      f"[{slope_trials['low']:.3f}, {slope_trials['high']:.3f}], Eq 14 {slope_eq14:.3f}")
gap_trials = metrics.percentile_band(np.max(np.abs(np.abs(sim_mean[:, fit]) - np.abs(eq14[fit])) / np.abs(eq14[fit]),
                                            axis=1))
gap = float(gap_trials["median"])
print(f"max relative gap simulation vs Eq 14 (θ̇ ≥ {sweep.fit_min_deg_s:.0f} °/s): median {gap:.3f} "
      f"[{gap_trials['low']:.3f}, {gap_trials['high']:.3f}]")

fig, ax = plt.subplots(figsize=(7.5, 4.5))
ax.loglog(deg(rates), deg(np.abs(eq14)), "k-", label="Eq 14, φ = 0: Δω/θ̇")
ax.loglog(deg(rates), deg(np.sqrt(2) * gyro.error_rad_s[2] / rates), "k:", label="Eq 14 worst over φ: √2 Δω/θ̇")
ax.loglog(deg(rates), deg(np.abs(exact)), "C1--", label="exact arctan (constant error)")
ax.fill_between(deg(rates), deg(band["low"]), deg(band["high"]), color="C0", alpha=0.3, label="simulation 95 % band")
ax.loglog(deg(rates), deg(band["median"]), "C0o", ms=4, label=f"simulation median (slope {slope_sim:.2f})")
ax.axvline(Oscillation().threshold_deg_s, color="C3", lw=0.8, label="θ̇_t = 0.5 °/s")
ax.set(xlabel="pitch rate θ̇ (deg/s)", ylabel="|roll error| (deg)", title="Projection method: roll error vs pitch rate")
ax.legend(fontsize=8)
display(report.save_figure(fig, "tan2022_fig06"))

# %%
report.save_table(pd.DataFrame({"pitch_rate_deg_s": deg(rates), "eq14_deg": deg(eq14), "exact_deg": deg(exact),
                                "sim_median_abs_deg": deg(band["median"]), "sim_low_deg": deg(band["low"]),
                                "sim_high_deg": deg(band["high"])}), "tan2022_fig06")
rows.append(compare.comparison_row("tan2022_fig06", "log-log slope of projection error vs θ̇ (simulation)", "error falls as θ̇ rises",
                                 slope_sim, "≈ −1 (−1.1…−0.9)", bool(-1.1 < slope_sim < -0.9), band=slope_trials))
rows.append(compare.comparison_row("tan2022_fig06", "simulation vs Eq 14, max rel. gap (θ̇ ≥ 5 °/s)", "-", gap,
                                 "< 0.1", bool(gap < 0.1), band=gap_trials))

# %%
assert -1.1 < slope_sim < -0.9
assert gap < 0.1

# %% [markdown]
# ### Is θ̇_t = 0.5 °/s plausible? (paper README tan2022 item 5)
#
# Just above the threshold the projection method is used, and its error is
# Eq 14 evaluated at θ̇ = 0.5 °/s:

# %%
# NBVAL_CHECK_OUTPUT
thr = rad(0.5)
e02 = rad(0.2)
phi_grid = rad(np.linspace(-90, 90, 3601))
just_above = {
    "Eq 14, φ = 0 (Δω_z/θ̇)": deg(abs(gr.projection_roll_error_eq14(0.0, thr, e02, e02))),
    "Eq 14, worst over φ (√2 Δω/θ̇)": deg(np.max(np.abs(gr.projection_roll_error_eq14(phi_grid, thr, e02, e02)))),
    "exact arctan, φ = 0, Δω_y = Δω_z = 0.2": deg(abs(gr.projection_roll_error_exact(0.0, thr, e02, e02))),
    "exact arctan, worst over φ": deg(np.max(np.abs(gr.projection_roll_error_exact(phi_grid, thr, e02, e02)))),
    "exact arctan, φ = 0, printed axes (Δω_y = 0)": deg(abs(gr.projection_roll_error_exact(0.0, thr, 0.0, e02))),
    "Eq 14 at 10 °/s, worst over φ": deg(np.sqrt(2) * e02 / rad(10.0)),
}
for k, v in just_above.items():
    print(f"{k:48s}: {v:6.2f}°")
rows.append(compare.comparison_row("θ̇_t", "projection error just above θ̇_t = 0.5 °/s, worst (deg)",
                                 "'high SNR' above θ̇_t", just_above["exact arctan, worst over φ"],
                                 "small error above the threshold", bool(just_above["exact arctan, worst over φ"] < 1.0)))

# %% [markdown]
# Tens of degrees: at 0.5 °/s the "high signal-to-noise ratio" the paper
# claims does not exist for a 0.2 °/s gyro error. Where the threshold should
# be is quantified by the sweep (tan2022_extra_threshold_sweep) below.

# %% [markdown]
# ## tan2022_fig09 — uniform pitch rotation at 10, 20, 60 °/s through ±90°
#
# One revolution (0° → 360°, passing +90° and 270° ≡ −90°), roll 0, gyro
# error 0.2 °/s (+ noise); figure: one noise seed, numbers: median and 95 %
# band over `UNI_TRIALS` seeds. Errors are relative to the
# mechanism roll (0°), wrapped to ±180°. Top: Eq 5 jumps at the singularity
# (the integrated Euler angles switch to the other branch ψ+180°, 180°−θ,
# φ+180°, so "roll" jumps by ≈ 180° — the algorithmic singularity). Bottom:
# Eq 12 drifts linearly (0.2 °/s × t); Eq 13 stays at ≈ −Δω/θ̇.

# %%
uni = UniformRotation(gyro=gyro)
fig, axes = plt.subplots(2, 3, figsize=(15, 6.5), sharex=True)
f9, per_trial = [], []
for j, rate in enumerate(uni.pitch_rates_deg_s):
    t, theta_m = uni.profile(rate)
    rec = gr.simulate_two_dof_imu(t, theta_m, np.zeros_like(t), gyro_bias_rad_s=gyro.error_rad_s,
                                  gyro_noise_density=gyro.noise_density_rad_s_rthz, rng=rng, trials=UNI_TRIALS)
    w = rec.gyro_rad_s  # (trials, N, 3)
    e_E = metrics.angle_difference(gr.euler_differential(w, gyro.dt_s, pitch0=theta_m[0])[..., 2], 0.0)
    e_I = gr.roll_decoupled_integration(w, gyro.dt_s, roll0=gyro.roll0_rad)
    e_P = gr.roll_projection(w)
    th_deg = deg(theta_m)
    dist90 = np.minimum(np.abs(th_deg - 90), np.abs(th_deg - 270))
    axes[0, j].plot(th_deg, deg(e_E[0]), "C3", lw=0.8)
    axes[0, j].set(title=f"θ̇ = {rate:.0f} °/s: Eq 5 Euler differential", ylabel="roll error (deg)", ylim=(-200, 200))
    axes[1, j].plot(th_deg, deg(e_I[0]), "C0", label="Eq 12 decoupled integration")
    axes[1, j].plot(th_deg, deg(e_P[0]), "C2", lw=0.6, label="Eq 13 projection")
    axes[1, j].set(xlabel="mechanism pitch θ (deg)", ylabel="roll error (deg)")
    for ax in axes[:, j]:
        for x in (90, 270):
            ax.axvline(x, color="k", lw=0.6, ls=":")
    trial = {"euler_lt60": deg(np.max(np.abs(e_E[:, th_deg < 60]), axis=1)),
             "euler_near90": deg(np.max(np.abs(e_E[:, dist90 < 2]), axis=1)),
             "euler_final": deg(e_E[:, -1]), "integration_final": deg(e_I[:, -1]),
             "projection_mean": deg(np.mean(e_P, axis=1)), "projection_rms": deg(metrics.rmse(e_P))}
    per_trial.append(trial)
    f9.append({"pitch_rate_deg_s": rate,
               "euler_max_abs_err_deg_theta_lt_60": float(np.median(trial["euler_lt60"])),
               "euler_max_abs_err_deg_within_2deg_of_90": float(np.median(trial["euler_near90"])),
               "euler_final_err_deg": float(np.median(trial["euler_final"])),
               "integration_final_err_deg": float(np.median(trial["integration_final"])),
               "integration_drift_expected_deg": float(gyro.error_deg_s[0] * t[-1]),
               "projection_mean_err_deg": float(np.median(trial["projection_mean"])),
               "projection_eq14_deg": float(deg(gr.projection_roll_error_eq14(0.0, rad(rate), *gyro.error_rad_s[1:]))),
               "projection_rms_err_deg": float(np.median(trial["projection_rms"]))})
axes[1, 0].legend(fontsize=8)
display(report.save_figure(fig, "tan2022_fig09"))

# %%
f9 = pd.DataFrame(f9)
report.show_table(f9.T.reset_index().rename(columns={"index": "quantity"}), "{:.3f}")
report.save_table(f9, "tan2022_fig09")
# per trial: the weakest blow-up over the three rates, the worst drift mismatch, the slope over the rates
blow = metrics.percentile_band(np.min([p["euler_near90"] / p["euler_lt60"] for p in per_trial], axis=0))
drift_dev = metrics.percentile_band(np.max([np.abs(p["integration_final"] / r["integration_drift_expected_deg"] - 1)
                                            for p, r in zip(per_trial, f9.to_dict("records"))], axis=0))
slope9 = metrics.percentile_band(gr.loglog_slope(f9["pitch_rate_deg_s"].to_numpy(),
                                                 np.stack([p["projection_mean"] for p in per_trial], axis=1)))
print(f"over {UNI_TRIALS} noise seeds: Eq 5 blow-up ratio {blow['median']:.1f} [{blow['low']:.1f}, {blow['high']:.1f}]; "
      f"Eq 12 drift mismatch {drift_dev['median']:.4f} [{drift_dev['low']:.4f}, {drift_dev['high']:.4f}]; "
      f"Eq 13 slope {slope9['median']:.3f} [{slope9['low']:.3f}, {slope9['high']:.3f}]")
rows.append(compare.comparison_row("tan2022_fig09", "Eq 5: max|Δφ_E| near ±90° / max for θ < 60° (min over rates)",
                                 "roll jumps at θ = ±90°", float(blow["median"]), "> 10", bool(blow["median"] > 10),
                                 band=blow))
rows.append(compare.comparison_row("tan2022_fig09", "Eq 12: final error / (0.2 °/s × T) − 1, worst rate",
                                 "error accumulates", float(drift_dev["median"]), "linear drift (< 0.1)",
                                 bool(drift_dev["median"] < 0.1), band=drift_dev))
rows.append(compare.comparison_row("tan2022_fig09", "Eq 13: log-log slope of mean error over 10/20/60 °/s",
                                 "larger θ̇ → smaller error", float(slope9["median"]), "≈ −1 (−1.1…−0.9)",
                                 bool(-1.1 < slope9["median"] < -0.9), band=slope9))

# %%
assert blow["median"] > 10, "Euler differential must blow up near ±90°"
assert drift_dev["median"] < 0.1
assert -1.1 < slope9["median"] < -0.9

# %% [markdown]
# ## tan2022_fig10 — pitch rate in the oscillation θ = 40° sin(2π·0.5 t)
#
# Eq 17 (true rate, peak 2π·0.5·40 = 125.7 °/s) and the rate magnitude the
# hybrid sees, `√(ω_y² + ω_z²)` from the noisy gyros, with θ̇_t = 0.5 °/s.
# Note that the oscillation never comes near θ = ±90°, so it does not
# exercise the singularity that motivates the method.

# %%
osc = Oscillation(duration_s=OSC_DURATION_S, gyro=gyro)
t_osc = osc.time_s()
rec_osc = gr.simulate_two_dof_imu(t_osc, osc.pitch_rad(t_osc), np.zeros_like(t_osc), gyro_bias_rad_s=gyro.error_rad_s,
                                  gyro_noise_density=gyro.noise_density_rad_s_rthz, rng=rng, trials=N_TRIALS)
w_osc = rec_osc.gyro_rad_s  # (trials, N, 3)
rate_meas = gr.pitch_rate_magnitude(w_osc[0])
fig, ax = plt.subplots(figsize=(8, 3.8))
ax.plot(t_osc, deg(osc.pitch_rate_rad_s(t_osc)), "k", label="θ̇ (Eq 17)")
ax.plot(t_osc, deg(rate_meas), "C0", lw=0.6, label="|θ̇| from gyros √(ω_y²+ω_z²)")
ax.axhline(osc.threshold_deg_s, color="C3", lw=0.8, label="θ̇_t = 0.5 °/s")
ax.set(xlabel="time (s)", ylabel="pitch rate (deg/s)", xlim=(0, min(4.0, OSC_DURATION_S)),
       title="Pitch rate under oscillation (first 4 s)")
ax.legend(fontsize=8)
display(report.save_figure(fig, "tan2022_fig10"))
print(f"peak pitch rate {osc.peak_rate_deg_s:.1f} °/s; fraction of samples with true |θ̇| ≤ θ̇_t: "
      f"{np.mean(np.abs(osc.pitch_rate_rad_s(t_osc)) <= osc.threshold_rad_s):.4f}")

# %% [markdown]
# ## tan2022_fig11 — projection roll error under oscillation
#
# Spikes wherever θ̇ → 0 (twice per period, at θ = ±40°), as the paper shows.

# %%
e_proj = gr.roll_projection(w_osc)
e_int = gr.roll_decoupled_integration(w_osc, gyro.dt_s, roll0=gyro.roll0_rad)
fig, ax = plt.subplots(figsize=(8, 3.8))
ax.plot(t_osc, deg(e_proj[0]), "C2", lw=0.6, label="Eq 13 projection")
ax.plot(t_osc, deg(e_int[0]), "C0", label="Eq 12 integration")
ax.set(xlabel="time (s)", ylabel="roll error (deg)", title="Projection method under oscillation: spikes at θ̇ ≈ 0")
ax.legend(fontsize=8)
display(report.save_figure(fig, "tan2022_fig11"))
slow = np.abs(osc.pitch_rate_rad_s(t_osc)) < rad(5.0)
spike = metrics.percentile_band(metrics.max_abs_error(e_proj, mask=np.broadcast_to(slow, e_proj.shape)) /
                                metrics.max_abs_error(e_proj, mask=np.broadcast_to(~slow, e_proj.shape)))
spike_ratio = float(spike["median"])
print(f"max|Δφ_P| where |θ̇| < 5 °/s vs elsewhere: ratio median {spike_ratio:.1f} "
      f"[{spike['low']:.1f}, {spike['high']:.1f}] over {N_TRIALS} trials")

# %% [markdown]
# ## tan2022_fig12 — hybrid (θ̇_t = 0.5 °/s) under oscillation
#
# Paper: the hybrid avoids the projection spikes and stays accurate for a long
# time. Two cases: the paper's setting (constant 0.2 °/s error only, no noise)
# and with white noise; RMSE and max error, median and 95 % band over trials.

# %%
hyb, use = gr.roll_hybrid(w_osc, gyro.dt_s, osc.threshold_rad_s, roll0=gyro.roll0_rad)
rec_det = gr.simulate_two_dof_imu(t_osc, osc.pitch_rad(t_osc), np.zeros_like(t_osc), gyro_bias_rad_s=gyro.error_rad_s)
hyb_det, _ = gr.roll_hybrid(rec_det.gyro_rad_s, gyro.dt_s, osc.threshold_rad_s, roll0=gyro.roll0_rad)
proj_det = gr.roll_projection(rec_det.gyro_rad_s)
fig, ax = plt.subplots(figsize=(8, 3.8))
ax.plot(t_osc, deg(hyb[0]), "C1", lw=0.6, label="hybrid θ̇_t = 0.5 °/s, with noise")
ax.plot(t_osc, deg(hyb_det), "k", lw=0.8, label="hybrid θ̇_t = 0.5 °/s, constant error only (paper)")
ax.set(xlabel="time (s)", ylabel="roll error (deg)", title="Hybrid projection/integration under oscillation")
ax.legend(fontsize=8)
display(report.save_figure(fig, "tan2022_fig12"))

summary = []
for name, err in (("projection Eq 13", e_proj), ("integration Eq 12", e_int), ("hybrid θ̇_t = 0.5 °/s", hyb)):
    r = metrics.percentile_band(deg(metrics.rmse(err)))
    m = metrics.percentile_band(deg(metrics.max_abs_error(err)))
    summary.append({"method": name, "RMSE median": float(r["median"]), "RMSE low": float(r["low"]),
                    "RMSE high": float(r["high"]), "MaxAE median": float(m["median"]), "MaxAE high": float(m["high"])})
summary.append({"method": "projection, constant error only", "RMSE median": float(deg(metrics.rmse(proj_det))),
                "MaxAE median": float(deg(metrics.max_abs_error(proj_det)))})
summary.append({"method": "hybrid 0.5 °/s, constant error only", "RMSE median": float(deg(metrics.rmse(hyb_det))),
                "MaxAE median": float(deg(metrics.max_abs_error(hyb_det)))})
summary = pd.DataFrame(summary)
report.show_table(summary, "{:.3f}")
report.save_table(summary, "tan2022_fig12")
rmse_p, rmse_h = summary.loc[0, "RMSE median"], summary.loc[2, "RMSE median"]
max_p, max_h = summary.loc[0, "MaxAE median"], summary.loc[2, "MaxAE median"]
max_h_det = summary.loc[4, "MaxAE median"]
band_max_h = metrics.percentile_band(deg(metrics.max_abs_error(hyb)))
band_max_ratio = metrics.percentile_band(metrics.max_abs_error(hyb) / metrics.max_abs_error(e_proj))
switched = metrics.percentile_band(np.mean(~use, axis=-1))
print(f"fraction of samples where the hybrid integrates (θ̇_t = 0.5 °/s): median {switched['median']:.4f} "
      f"[{switched['low']:.4f}, {switched['high']:.4f}]")
rows.append(compare.comparison_row("tan2022_fig11", "max|Δφ_P| near θ̇ = 0 / elsewhere", "error spikes as θ̇ → 0",
                                 spike_ratio, "> 5", bool(spike_ratio > 5), band=spike))
rows.append(compare.comparison_row("tan2022_fig12", "share of samples integrated by the hybrid (0.5 °/s)", "-",
                                 float(switched["median"]), "(mtcal) the switch fires", bool(switched["low"] > 0),
                                 band=switched))
rows.append(compare.comparison_row("tan2022_fig12", "MaxAE hybrid(0.5 °/s) / projection", "hybrid avoids the spikes",
                                 float(band_max_ratio["median"]), "", None, band=band_max_ratio))
rows.append(compare.comparison_row("tan2022_fig12", "hybrid(0.5 °/s) MaxAE with noise (deg)", "accurate for a long time",
                                 max_h, "< 1°", bool(max_h < 1.0), band=band_max_h))
rows.append(compare.comparison_row("tan2022_fig12", "hybrid(0.5 °/s) MaxAE, constant error only (deg)", "accurate for a long time",
                                 max_h_det, "< 1°", bool(max_h_det < 1.0)))

# %% [markdown]
# **The tan2022_fig12 claim does not hold with θ̇_t = 0.5 °/s.** The hybrid switches
# to integration only on the few samples whose gyro-derived rate magnitude is
# below 0.5 °/s: near a rate reversal θ̇ changes at θ̈ = (2πf)²θm ≈ 395 °/s², so
# |θ̇| < 0.5 °/s lasts ≈ 2.5 ms — a fraction of order 1e-3 of the record at
# 1 kHz. (At 200 Hz no sample would ever switch: the reversals fall on the
# sample grid and a 5 ms interval-mean rate there is ≈ 1 °/s; CI therefore
# runs at 1 kHz too, with fewer trials and a shorter record.) This removes the
# very worst samples (projection MaxAE ≈ 89° → hybrid ≈ 40° with noise, ≈ 14°
# with the constant error only), but
# the samples just above the threshold still use projection, whose error there
# is tens of degrees (Eq 14, above): the hybrid is bounded, not accurate. The
# simulation-level facts are asserted instead: the hybrid is never worse than
# projection, and its maximum error stays well above 5°. tan2022_extra_threshold_sweep shows that
# the algorithm itself works — with a threshold near the peak rate.

# %%
assert spike_ratio > 5
assert switched["low"] > 0, "the 0.5 °/s switch must fire in every trial (same code path at CI and full size)"
assert rmse_h <= rmse_p + 1e-12, "the hybrid must never be worse than pure projection"
assert band_max_h["low"] > 5.0 and max_h_det > 5.0, "with θ̇_t = 0.5 °/s the projection spikes survive"

# %% [markdown]
# ## tan2022_extra_threshold_sweep (beyond the paper) — roll RMSE vs threshold θ̇_t, Monte Carlo over noise seeds
#
# Same oscillation, same trials (common random numbers across thresholds).
# Median and 95 % band of the per-trial RMSE; the optimum (minimum median)
# is marked. Above the peak rate (125.7 °/s) the hybrid degenerates into pure
# integration and drifts.

# %%
thresholds = np.unique(np.concatenate([np.geomspace(0.1, 200.0, N_THRESHOLDS), [0.5]]))
rmse_thr = np.empty((N_TRIALS, thresholds.size))
rmse_thr_det = np.empty(thresholds.size)
for j, thr_deg in enumerate(thresholds):  # loop over the swept parameter; trials vectorised
    rmse_thr[:, j] = metrics.rmse(gr.roll_hybrid(w_osc, gyro.dt_s, rad(thr_deg))[0])
    rmse_thr_det[j] = metrics.rmse(gr.roll_hybrid(rec_det.gyro_rad_s, gyro.dt_s, rad(thr_deg))[0])
bt = metrics.percentile_band(deg(rmse_thr))
k_opt = int(np.argmin(bt["median"]))
thr_opt, rmse_opt = float(thresholds[k_opt]), float(bt["median"][k_opt])
k05 = int(np.flatnonzero(thresholds == 0.5)[0])
rmse_05 = float(bt["median"][k05])
print(f"optimum θ̇_t = {thr_opt:.1f} °/s: roll RMSE median {rmse_opt:.3f}° "
      f"[{bt['low'][k_opt]:.3f}, {bt['high'][k_opt]:.3f}]; at 0.5 °/s: {rmse_05:.3f}° "
      f"[{bt['low'][k05]:.3f}, {bt['high'][k05]:.3f}]")
print(f"constant error only: optimum θ̇_t = {thresholds[np.argmin(rmse_thr_det)]:.1f} °/s, "
      f"RMSE {deg(rmse_thr_det.min()):.3f}°; at 0.5 °/s {deg(rmse_thr_det[k05]):.3f}°")

fig, ax = plt.subplots(figsize=(8, 4.5))
ax.fill_between(thresholds, bt["low"], bt["high"], color="C1", alpha=0.3, label="95 % band over noise seeds")
ax.loglog(thresholds, bt["median"], "C1-", label="median roll RMSE (bias + noise)")
ax.loglog(thresholds, deg(rmse_thr_det), "k--", label="constant 0.2 °/s error only")
ax.plot([thr_opt], [rmse_opt], "C3*", ms=14, label=f"optimum {thr_opt:.0f} °/s → {rmse_opt:.3f}°")
ax.axvline(0.5, color="C3", lw=0.8, ls=":", label="paper θ̇_t = 0.5 °/s")
ax.axvline(osc.peak_rate_deg_s, color="k", lw=0.6, ls=":", label="peak rate 125.7 °/s")
ax.set(xlabel="threshold θ̇_t (deg/s)", ylabel="roll RMSE (deg)", title="Hybrid roll RMSE vs pitch-rate threshold")
ax.legend(fontsize=8)
display(report.save_figure(fig, "tan2022_extra_threshold_sweep"))

# %%
report.save_table(pd.DataFrame({"threshold_deg_s": thresholds, "rmse_median_deg": bt["median"],
                                "rmse_low_deg": bt["low"], "rmse_high_deg": bt["high"],
                                "rmse_constant_error_deg": deg(rmse_thr_det)}), "tan2022_extra_threshold_sweep")
thr_trials = metrics.percentile_band(thresholds[np.argmin(rmse_thr, axis=1)])  # each trial's own optimum
gain_trials = metrics.percentile_band(rmse_thr[:, k_opt] / rmse_thr[:, k05])
print(f"per-trial optimum θ̇_t: median {thr_trials['median']:.1f} °/s [{thr_trials['low']:.1f}, "
      f"{thr_trials['high']:.1f}]; RMSE(optimum) / RMSE(0.5 °/s) {gain_trials['median']:.4f} "
      f"[{gain_trials['low']:.4f}, {gain_trials['high']:.4f}]")
rows.append(compare.comparison_row("tan2022_extra_threshold_sweep", "optimal θ̇_t (deg/s) for the oscillation", 0.5,
                                 float(thr_trials["median"]), "optimum far above 0.5 °/s (> 10)",
                                 bool(thr_trials["low"] > 10), band=thr_trials))
rows.append(compare.comparison_row("tan2022_extra_threshold_sweep", "roll RMSE at optimum / at 0.5 °/s", "-", float(gain_trials["median"]),
                                 "< 0.5", bool(gain_trials["high"] < 0.5), band=gain_trials))
h_opt = gr.roll_hybrid(w_osc, gyro.dt_s, rad(thr_opt), roll0=gyro.roll0_rad)[0]
b_max_opt = metrics.percentile_band(deg(metrics.max_abs_error(h_opt)))
max_opt = float(b_max_opt["median"])
vs_int = metrics.percentile_band(metrics.rmse(h_opt) / metrics.rmse(e_int))
print(f"hybrid at the optimum: MaxAE median {max_opt:.3f}° [{b_max_opt['low']:.3f}, {b_max_opt['high']:.3f}] "
      f"(projection {max_p:.3f}°, integration {summary.loc[1, 'MaxAE median']:.3f}°)")
rows.append(compare.comparison_row("tan2022_extra_threshold_sweep", "hybrid at optimum θ̇_t: MaxAE (deg)", "bounded, accurate",
                                 max_opt, "< 1° and < projection / 10", bool(max_opt < 1.0 and max_opt < max_p / 10),
                                 band=b_max_opt))
rows.append(compare.comparison_row("tan2022_extra_threshold_sweep", "hybrid at optimum: RMSE / integration-only RMSE", "beats integration",
                                 float(vs_int["median"]), "< 0.5", bool(vs_int["median"] < 0.5), band=vs_int))
rows.append(compare.comparison_row("tan2022_extra_threshold_sweep", "0.5 °/s RMSE inside the MC band at optimum?", "-",
                                 bool(bt["low"][k_opt] <= rmse_05 <= bt["high"][k_opt]), "no", None))

# %%
assert thr_opt > 10 and thr_trials["low"] > 10 and gain_trials["high"] < 0.5
assert max_opt < 1.0 and max_opt < max_p / 10 and vs_int["median"] < 0.5

# %% [markdown]
# ## Paper vs mtcal

# %%
table = compare.comparison_table(rows)
report.show_table(table)
report.save_table(table, "tan2022_gyro_roll_comparison")
print(compare.claims_summary(table))
print(compare.band_summary(table))

# %%
# Claims that fail in simulation are reported, not faked: the θ̇_t = 0.5 °/s rows.
failed = table[table["holds"] == False]  # noqa: E712
print(failed[["artifact", "quantity"]].to_string(index=False))
assert set(failed["artifact"]) <= {"θ̇_t", "tan2022_fig12"}, "an unexpected claim failed"

# %% [markdown]
# **Summary.** Eq 14 is confirmed: the projection error falls as 1/θ̇
# (log-log slope ≈ −1 in simulation). Under uniform rotation the three methods
# behave as the paper says: Eq 5 jumps at θ = ±90° (branch switch of the Euler
# angles), Eq 12 drifts at the x-gyro error rate, Eq 13 stays at ≈ Δω/θ̇. Under
# oscillation the projection spikes where θ̇ → 0. With the paper's
# θ̇_t = 0.5 °/s the hybrid barely differs from projection: its error remains
# tens of degrees near the rate reversals (Eq 14 gives ≈ 23–32° just above the
# threshold), so Fig 12 is not reproduced. The idea works with a sensible
# threshold: the sweep puts the optimum near the peak pitch rate, more than two
# orders of magnitude above 0.5 °/s, where the hybrid beats both projection and
# integration by a large factor.
