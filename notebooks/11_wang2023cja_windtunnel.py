# %% [markdown]
# # wang2023cja — hypersonic wind tunnel (Tables 9–11, Figs 10–11)
#
# The support mechanism is simulated with the errors the paper names (§4.2): transmission-ratio
# error, transmission gap (backlash) and servo stop error, non-orthogonality, repeatability. The
# six-position calibration runs wind-off; the wind-off AoA sweep that follows is a separate run
# (Tables 9, 11); five wind-on sweeps (Table 10) add an elastic pitch deflection and model vibration
# that trips the AMD (the QNCF then runs on the gyro alone). Group 5 uses a different mechanism rate.
#
# **What is identified from what** (declared in `paper_data/wang2023cja_split.csv`). The
# installation angles and the mechanism's pitch-ratio error come from the printed wind-tunnel matrix
# (`train`); the IMU error model is the one identified on Tables 1–4 (notebook 10); the elastic
# constants were chosen to match Table 10's Mean and elastic-corrected rows. The mechanism's gap, servo
# stop error and non-orthogonality were chosen while comparing with Tables 9–11, and the vibration/gate
# scenario while viewing Table 10, so **every number of Tables 9–11 is `tuned`**: no fit reads it (the
# leak test perturbs it), but it is in-sample, scored apart from the held-out numbers and never a
# prediction (Table 9's before-slope is also −(Q(2,2) − 1) of the training matrix; Table 10's Std row is
# the sample SD of the tuned group rows). **No wind-tunnel number is held out.** Every printed number is
# still compared one to one. Bands: each trial block draws its
# error model from the fit's posterior (fitted) or from the prior (prior predictive; the geometry
# still comes from the printed wind-tunnel matrix, which is not from Tables 1–4).

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
import pandas as pd
from IPython.display import display
from mtcal.reporting import compare, fidelity, output
from mtcal.studies import wang2023cja as w
from mtcal.studies.wang2023cja import predictive, verdicts

SIZE = output.run_size(SIZE)
# full: 1000 trials per model (200 parameter draws × 5), so every printed band rests on 1000 draws
# (docs/conventions.md, Bands); ≈ 150 s of CPU
N_TRIALS = N_TRIALS or {"ci": 4, "full": 1000}[SIZE]
PER_DRAW = {"ci": 2, "full": 5}[SIZE]      # trials per parameter draw
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
# ## Runs: posterior predictive and prior predictive
# Every block of `PER_DRAW` trials draws its own error model; the one-to-one tables and the claims
# are built here, each section shows its rows.

# %%
make_scenario = lambda m: w.windtunnel_scenario(errors=m, **params)  # noqa: E731 - one parameter draw's scenario
runs = predictive.windtunnel_predictive_kinds(make_scenario, fit, predictive.KINDS, N_TRIALS, SEED, per_draw=PER_DRAW)
print(f"{N_TRIALS} trials per model ({PER_DRAW} per draw)")
one = {name: verdicts.one_to_one(verdicts.printed_samples(windtunnel=r), seed=SEED, per_draw=PER_DRAW)
       for name, r in runs.items()}
claims = verdicts.claims(windtunnel=runs["fitted"])
run = runs["fitted"]
# the figures' time series: the median session, re-run with its trace
run.trace = predictive.windtunnel_median_trace(make_scenario, fit, "fitted", run, SEED, per_draw=PER_DRAW)


def section(prefix):
    """One-to-one rows and claims of one artifact (posterior predictive)."""
    t = one["fitted"]
    rows = t[t.file.str.startswith(prefix)]
    if len(rows):
        output.show_table(rows[["quantity", "role", "paper", "median", "low", "high", "kind", "n", "inside"]], "{:.4f}")
    c = claims[claims.artifact == prefix]
    if len(c):
        print(verdicts.claim_block(c))

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
#   the printed Q(2,2) (with the mechanism's backlash and the mount compliance included). Table 9's
#   before-slope then follows arithmetically (≈ −(Q(2,2) − 1)): it is not a prediction.
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
matrix = w.extra_windtunnel_matrix(run).table
output.save_table(matrix, "wang2023cja_extra_windtunnel_matrix")
output.show_table(matrix, "{:+.6f}")
section("wang2023cja_matrix_qbs_windtunnel")

# %% [markdown]
# ## wang2023cja_table09 — wind-off AoA sweep, mean pitch (Table 9, tuned)
# "the pitch errors before and after calibration are within 0.05° and 0.02°" is checked with those
# thresholds, `in-sample`: the mechanism was tuned on this table, so holding confirms nothing, and a
# failing check is shown failing. One sentence, one check (both thresholds must hold; both statistics
# are printed).

# %%
t9 = w.table09(run).table
output.save_table(t9, "wang2023cja_table09")
output.show_table(t9, "{:.3f}")
section("wang2023cja_table09")

# %% [markdown]
# ## wang2023cja_fig10 — pitch minus the commanded AoA in the five wind-on sweeps (paper Fig 10)
# The paper plots pitch; the five curves then overlay at the scale of the 12° sweep. Pitch −
# reference (0.2 s mean, removing the 45 Hz model vibration) shows what Table 10 is about: the
# elastic offset growing with AoA, and the ≈ 0.01° group-to-group scatter. One session — the median
# one by Table 10's largest group-to-group Std, never trial 0; the ensemble of every Table 10 number
# is in the table below.

# %%
from mtcal.studies.wang2023cja import plots
display(output.save_figure(plots.fig10(run, sc.imu.label, (mechanism_rate_deg_s, group5_rate_deg_s)),
                           "wang2023cja_fig10"))

# %% [markdown]
# ## wang2023cja_extra_amd — the AMD statistic with wind on (beyond the paper)
# Vibration of `vibration_accel_m_s2` keeps the acceleration-magnitude detector above its threshold,
# so the QNCF runs gyro-only during the wind-on sweeps. The amplitude is an assumption chosen to trip
# the gate, so the gate check is `in-sample`, not a finding.

# %%
display(output.save_figure(plots.extra_amd(run, sc.qncf.amd_threshold_pct, vibration_accel_m_s2),
                           "wang2023cja_extra_amd"))

# %% [markdown]
# ## wang2023cja_table10 — five wind-on groups: Mean, elastic-corrected, Std (Table 10)
# All 40 printed numbers one to one, all `tuned` (both elastic constants and the vibration/gate scenario
# were chosen against this table; the Std row is the sample SD of the group rows). "The standard
# deviation of the five wind-on tests is [...] within 0.01°", "even more than 0.1°" and "within 0.03°"
# are `in-sample` checks.

# %%
t10 = w.table10(run, sc.wind_on_sweep_deg).table
output.save_table(t10, "wang2023cja_table10")
output.show_table(t10.pivot(index="row", columns="reference", values="mtcal").reset_index(), "{:.3f}")
section("wang2023cja_table10")

# %% [markdown]
# ## wang2023cja_fig11 — roll and yaw errors in the wind-off sweep, before vs after (paper Fig 11)
# Median and 95 % band over all trials, the paper's Table 11 MaxAE as dashed ± lines.

# %%
display(output.save_figure(plots.fig11(run, sc.imu.label), "wang2023cja_fig11"))

# %% [markdown]
# ## wang2023cja_table11 — MaxAE / RMSE of roll and yaw, wind off (Table 11, tuned)
# The paper's roll got slightly *worse* after calibration (RMSE 0.007° → 0.010°). In our runs too:
# every mechanism axis stops short by half its transmission gap plus the servo stop error, so the
# roll positions of the calibration (±30°) feed Eq 13 a roll reference that is off by that amount,
# and the sweep after calibration inherits it. Yaw is gyro-only and drifts.

# %%
t11 = w.table11(run).table
output.save_table(t11, "wang2023cja_table11")
output.show_table(t11)
section("wang2023cja_table11")

# %% [markdown]
# ## Paper vs mtcal — every printed number, posterior predictive and prior predictive
# One row per printed number of Tables 9–11 and the wind-tunnel matrix, with its split role;
# `se_low`/`se_high` are the Monte Carlo standard errors of the band ends (empty where a row prints a range).

# %%
output.save_table(one["fitted"], "wang2023cja_extra_windtunnel_one_to_one")
output.save_table(one["prior"], "wang2023cja_extra_windtunnel_one_to_one_prior_predictive")
output.show_table(one["fitted"][["quantity", "role", "paper", "median", "low", "high", "se_low", "se_high", "inside"]],
                  "{:.4f}")

# %% [markdown]
# ### Where the width of a band comes from
# Law of total variance over the `PER_DRAW` sessions sharing one parameter draw
# (`predictive.variance_parts`): `var_parameter` (variance of the conditional mean over the posterior
# draws) plus `var_sampling` (mean variance between sessions of one draw) ≈ `var_band` (deg² or 1²).
# The wind-tunnel geometry comes from the printed matrix (train), so no installation-angle draw enters here.

# %%
output.show_table(one["fitted"][["quantity", "role", "var_band", "var_parameter", "var_sampling", "parameter_share"]],
                  "{:.3g}")
print(f"median parameter share {one['fitted'].parameter_share.median():.2f}")

# %% [markdown]
# ## The paper's claims, with its thresholds
# No wind-tunnel statement is a `claim`: every one is an `in-sample` check against numbers a mechanism
# or setting was tuned on, shown holding or FAILING with the computed reason, never enforced and never
# counted as a claim. A verdict whose share of holding trials is within Monte Carlo error of one
# half is marked "not resolved".

# %%
output.save_table(claims, "wang2023cja_extra_windtunnel_claims")
print(verdicts.claim_block(claims))

# %% [markdown]
# ## Score block
# The comparison table (every printed number with its posterior- and prior-predictive band, then
# the claims) is scored by `mtcal.reporting.fidelity` and merged into `data/fidelity_scores.csv`.

# %%
table = verdicts.comparison(one, claims)
output.save_table(table, "wang2023cja_windtunnel_comparison")
scores_csv = fidelity.write_scores(table, "wang2023cja", "11_wang2023cja_windtunnel")
print(fidelity.score_block(table, "wang2023cja"))
print(f"size {SIZE}: {N_TRIALS} trials per model")
