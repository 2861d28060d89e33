# %% [markdown]
# # wang2023cja — hypersonic wind tunnel (Tables 9–11, Figs 10–11)
#
# The support mechanism is simulated with the errors the paper names (§4.2): transmission-ratio
# error, transmission gap (backlash) and servo stop error, non-orthogonality, repeatability. The
# six-position calibration runs wind-off; the wind-off AoA sweep that follows is a separate run
# (Tables 9, 11); five wind-on sweeps (Table 10) add an elastic pitch deflection and model vibration
# that trips the AMD (the QNCF then runs on the gyro alone). Group 5 uses a different mechanism rate.
#
# **What is identified from what.** The paper prints no wind-tunnel geometry. The installation
# angles and the mechanism's pitch-ratio error are taken from the printed wind-tunnel matrix
# (training data, `w.windtunnel_geometry`); the IMU error model is the one identified on the turntable
# Tables 1–4 (notebook 10, `w.fit_error_model`); the tunnel's elastic model is taken from Table 10's
# Mean and elastic-corrected rows (those rows are `fitted`). Everything else — Table 9, Table 10's
# Std, Table 11 — is **predicted** and compared with 95 % Monte Carlo bands, beside the prior-only model.

# %% tags=["parameters"]
SIZE = None          # "ci" or "full"; None → $MTCAL_SIZE, else "full"
SEED = 2023          # RNG seed
N_TRIALS = None      # None → the size's default (Monte Carlo trials per model)
# scenario (defaults = the paper's setting; names carry units)
gyro_grade = "wang2023cja"       # a mtcal.core.sensor_grades name
accel_grade = "wang2023cja"      # a mtcal.core.sensor_grades name
fs_hz = 1000.0                   # sample rate (§3.2)
rest_s = 3.0                     # rest per calibration position (§3.2)
mechanism_rate_deg_s = 2.0       # mechanism AoA rate, groups 1–4 (assumed)
group5_rate_deg_s = 1.0          # Group 5's different rate (§4.2, value not given)
vibration_accel_m_s2 = 3.0       # model vibration with wind on (assumed; trips the AMD)

# %% [markdown]
# ## Scenario (every value with unit and source)
#
# The IMU is resolved once from the sensor grades in the parameters cell; the hardware error model
# is the one identified on the turntable tables (fitted) or its datasheet nominal (prior-only). The
# mechanism's transmission gap (0.02°), servo stop error (2 ms × rate), non-orthogonality and
# repeatability are stated priors (§4.2 names the error types, not their sizes) and are **not**
# fitted: the paper gives no wind-tunnel number that isolates them. Only the pitch-ratio error and
# the installation angles are identified, from the printed matrix. Changing a parameter (e.g.
# `gyro_grade = "industrial"`) re-resolves all of this; titles and labels follow the values.

# %%
import numpy as np
from mtcal.reporting import compare, output
from mtcal.studies import wang2023cja as w

SIZE = output.run_size(SIZE)
N_TRIALS = N_TRIALS or {"ci": 4, "full": 40}[SIZE]
params = dict(gyro_grade=gyro_grade, accel_grade=accel_grade, fs_hz=fs_hz, rest_s=rest_s,
              mechanism_rate_deg_s=mechanism_rate_deg_s, group5_rate_deg_s=group5_rate_deg_s,
              vibration_accel_m_s2=vibration_accel_m_s2)
AT_PAPER = compare.at_paper_settings(params, w.WINDTUNNEL_DEFAULTS)
output.setup_matplotlib()
fit = w.fit_error_model(seed=SEED)
scenarios = {"fitted": w.windtunnel_scenario(errors=fit.model, **params),
             "prior": w.windtunnel_scenario(errors=w.ErrorModel(), **params)}
sc = scenarios["fitted"]
output.show_table(compare.describe(sc))

# %% [markdown]
# ## Runs (fitted model and prior-only model; trials in blocks of 10 to bound memory)
# Both comparison tables are built here; each section shows its artifact and evaluates its rows.

# %%
runs = {name: w.run_windtunnel(s, np.random.default_rng(np.random.SeedSequence([SEED, 11])), N_TRIALS)
        for name, s in scenarios.items()}
tables = {name: compare.comparison_table(w.windtunnel_rows(r, scenarios[name].pitch_ratio_error))
          for name, r in runs.items()}
run = runs["fitted"]

# %% [markdown]
# ## wang2023cja_extra_windtunnel_matrix — Q(2,2) = 1.0045: one cause, computed
#
# The printed wind-tunnel matrix is not orthogonal: Q(2,2) = 1.004462. Two explanations were on
# offer in this suite — a mechanism pitch-ratio error (this notebook) and noise absorbed by the
# 16-parameter fit (notebook 40). Both are computed here, once:
#
# * **noise alone**: Eq 13 on the wind-tunnel positions with the identified per-rest errors and *no*
#   ratio error gives the Q(2,2) band printed below — far from 1.0045 (asserted);
# * **ratio error**: if the mechanism's actual pitch is (1 + ε) × the commanded one, Eq 13 scales the
#   pitch-axis component by ≈ 1/(1 + ε). ε is *fitted* so that the noise-free calibration returns
#   the printed Q(2,2) (with the mechanism's backlash and the mount compliance included), and then
#   *predicts* Table 9's before-slope (held out) — the `slope of before-ref` row below.
#
# So Q(2,2) is a physical scale of the mechanism; what noise adds is the off-diagonal scatter.

# %%
# NBVAL_CHECK_OUTPUT
print(f"installation angles from the printed matrix's SO(4) part: {sc.alpha_deg} deg")

# %%
noise_only = w.q22_noise_band(fit.model, w.windtunnel_positions(sc), seed=SEED)
print(f"pitch-ratio error fitted to the printed Q(2,2): {sc.pitch_ratio_error:+.6f}")
print(f"Q(2,2) from rest errors alone: median {noise_only['median']:.5f} [{noise_only['low']:.5f}, {noise_only['high']:.5f}]")
assert not noise_only["low"] <= 1.004462 <= noise_only["high"]
output.save_table(w.windtunnel_matrix_table(run), "wang2023cja_extra_windtunnel_matrix")
output.show_table(w.windtunnel_matrix_table(run), "{:+.6f}")
print(w.section_claims(tables["fitted"], "wang2023cja_matrix_qbs_windtunnel", enforce=AT_PAPER))

# %% [markdown]
# ## wang2023cja_table09 — wind-off AoA sweep, mean pitch (Table 9, predicted)
# The before-slope is the ratio error's prediction; "after within 0.02° and below before" is a
# threshold on a predicted number (`reported:`).

# %%
t9 = w.sweep_mean_table("wang2023cja_table09", run.nowind, "pitch")
output.save_table(t9, "wang2023cja_table09")
output.show_table(t9, "{:.3f}")
print(w.section_claims(tables["fitted"], "wang2023cja_table09", enforce=AT_PAPER))

# %% [markdown]
# ## wang2023cja_fig10 — pitch minus the commanded AoA in the five wind-on sweeps (paper Fig 10)
# The paper plots pitch; the five curves then overlay at the scale of the 12° sweep. Pitch −
# reference (0.2 s mean, removing the 45 Hz model vibration) shows what Table 10 is about: the
# elastic offset growing with AoA, and the ≈ 0.01° group-to-group scatter. Asserted: the pitch error
# with wind exceeds 0.1° at the largest AoA (the paper's "even more than 0.1°"; the elastic model is
# taken from Table 10, so the row is `fitted`).

# %%
from mtcal.studies.wang2023cja import plots
output.save_figure(plots.fig10(run, sc.imu.label, (mechanism_rate_deg_s, group5_rate_deg_s)), "wang2023cja_fig10")
print(w.section_claims(tables["fitted"], "wang2023cja_fig10", enforce=AT_PAPER))

# %% [markdown]
# ## wang2023cja_extra_amd — the AMD statistic with wind on (beyond the paper)
# Vibration of `vibration_accel_m_s2` keeps the acceleration-magnitude detector above its threshold,
# so the QNCF runs gyro-only during the wind-on sweeps (the `AMD gate` row of Table 10).

# %%
output.save_figure(plots.extra_amd(run, sc.qncf.amd_threshold_pct, vibration_accel_m_s2), "wang2023cja_extra_amd")

# %% [markdown]
# ## wang2023cja_table10 — five wind-on groups: Mean, elastic-corrected, Std (Table 10)
# Mean vs elastic-corrected is `fitted` (both elastic models come from this table); the Std over
# the five groups is predicted.

# %%
t10 = w.table10(run, sc.wind_on_sweep_deg)
output.save_table(t10, "wang2023cja_table10")
output.show_table(t10.pivot(index="row", columns="reference", values="mtcal").reset_index(), "{:.3f}")
print(w.section_claims(tables["fitted"], "wang2023cja_table10", enforce=AT_PAPER))

# %% [markdown]
# ## wang2023cja_fig11 — roll and yaw errors in the wind-off sweep, before vs after (paper Fig 11)

# %%
output.save_figure(plots.fig11(run, sc.imu.label), "wang2023cja_fig11")

# %% [markdown]
# ## wang2023cja_table11 — MaxAE / RMSE of roll and yaw, wind off (Table 11, predicted)
# The paper's roll got slightly *worse* after calibration (RMSE 0.007° → 0.010°). In our runs too:
# every mechanism axis stops short by half its transmission gap plus the servo stop error, so the
# roll positions of the calibration (±30°) feed Eq 13 a roll reference that is off by that amount,
# and the sweep after calibration inherits it. Yaw is gyro-only and drifts.

# %%
t11 = w.error_metric_table("wang2023cja_table11", run.nowind, ((2, "roll"), (0, "yaw")))
output.save_table(t11, "wang2023cja_table11")
output.show_table(t11)
print(w.section_claims(tables["fitted"], "wang2023cja_table11", enforce=AT_PAPER))

# %% [markdown]
# ## Paper vs mtcal — fitted model, and the prior-only model beside it
# `mtcal` is the Monte Carlo median, `mc_band` its 95 % interval; the prediction summary counts the
# held-out rows whose paper number lies inside our band. The wind tunnel is mostly set by the
# mechanism (prior values, not fitted): the identified IMU error model changes little here.

# %%
output.save_table(tables["fitted"], "wang2023cja_windtunnel_comparison")
output.save_table(tables["prior"], "wang2023cja_extra_windtunnel_comparison_prior_only")
output.show_table(tables["fitted"])
for name, table in tables.items():
    print(f"{name:7s} model: {compare.prediction_summary(table)}")

# %% [markdown]
# ## Paper numbers outside our band, and the claims
# Threshold claims on predicted numbers (`reported:`) are evaluated and reported; the others are
# asserted at the paper's settings. Reasons for the numbers outside (full size): the Table 9 slope
# from the ratio error identified on Q(2,2) is ≈ 4 % shallower than the paper's, because the
# sweep's backlash (approach directions differ from the calibration's) also tilts the slope; the
# roll RMSE rows of Table 11 are set by the assumed transmission gap (0.02°) and servo stop error
# on the roll axis (priors, not fitted): the paper's 0.007°/0.010° suggest a roll gap about half
# that size.

# %%
output.show_table(w.outside_rows(tables["fitted"]))
print(compare.check_claims(tables["fitted"], enforce=False))
print(compare.check_claims(w.asserted(tables["fitted"]), enforce=AT_PAPER))
