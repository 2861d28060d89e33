# %% [markdown]
# # 31 — wang2022sensors: RAMS EKF, ref. [16], the AHRS stand-in, and the identified error model
#
# Wang et al., *Sensors* 2022 (RAMS), Sec. 3.3, 5 and 7: the EKF with ZVD covariance
# switching (Fig. 9), the simulation of Fig. 11, the turntable results of Table 5, the
# drift test of Fig. 13 and the per-angle maximum error of Fig. 14.
#
# Table 5 is hardware data. Our simulated IMU follows Table 3, but the rig is not in the
# paper: lever arm, turntable accelerations, the sensor-to-reference latency, the
# accelerometer noise actually reached and the AHRS's magnetic environment are unknown.
# We therefore **identify** five such parameters from the `train` rows of the
# declared split (`mtcal/reporting/paper_data/wang2022sensors_split.csv`, read
# through `paper_numbers.training`: the six RAMS numbers, the six ref. [16] numbers —
# Bv2/Bv3 are near-copies of Bv1 in our axis-independent ref. [16] model, so they are
# training replicates, not a test — and the AHRS's Bv1 static number) and compare the
# five held-out Ellipse2-N numbers and the Fig. 14 text claims (c01, c08, c10; c02) with the
# **posterior-predictive** 95 % band (each draw: parameters from the fitted posterior,
# a Monte Carlo repetition, the declared model discrepancy) and the **prior-predictive**
# band (parameters drawn from the prior). `kind` separates the paper's `claim`s (threshold
# quoted; a failing claim is reported with its computed reason) from `in-sample` checks
# (a statement on rows the model was fitted to, or judged with a window chosen after a
# failure: shown holding or FAILING, never counted) and `consistency` checks that hold by
# construction (a grid inside its prior). Each sentence of the paper counts once.
# Everything is computed in `mtcal.studies.wang2022sensors`.

# %% tags=["parameters"]
SIZE = None            # "ci" or "full"; None -> $MTCAL_SIZE, else "full"
SEED = 4031            # RNG seed
GRID_REPS = None       # Monte Carlo repetitions per error-model grid cell; None -> size default
# scenario (defaults = the paper's setting, else mtcal's stated choice; names carry units)
sensor_grade = "wang2022sensors"   # mtcal.core.sensor_grades name (Table 3)
fs_hz = 200.0                      # sample rate (not stated; BMI088 gyro rate)
fig11_axis = (0.1734, 0.9835, 0.0523)  # Sec. 5 axis, IMU frame
lever_arm_m = 0.2                  # IMU distance from the hinge line (m), Fig. 9 record
move_rate_deg_s = 20.0             # turntable cruise rate (deg/s)
move_accel_deg_s2 = 1000.0         # turntable acceleration limit (deg/s^2)
hold_s = 1.0                       # Sec. 7: 1 s pause per step
step_deg = 10.0                    # Sec. 7: 10 deg steps
latency_s = 0.0                    # sensor-to-reference latency (s); identified below for Table 5
zvd_accel_min_m_s2 = 9.76          # Table 1
zvd_accel_max_m_s2 = 9.84          # Table 1
zvd_var_threshold_m2_s4 = 0.001    # Table 1
zvd_gyro_max_deg_s = 2.0           # optional gyro condition (mtcal; None = Table 1 only)

# %% [markdown]
# The next cell resolves the run size and builds (and validates) the scenario. The
# error-model grid (`FIT_GRID`) is coarser at CI size; its lever arm, acceleration,
# accelerometer noise and latency override the values above for Table 5 and Fig. 14.

# %%

from mtcal.reporting import compare, fidelity, output
from mtcal.studies import wang2022sensors as w
from mtcal.studies.wang2022sensors import error_model, plots

SIZE = output.run_size(SIZE)
GRID_REPS = GRID_REPS or {"full": 2, "ci": 2}[SIZE]
AHRS_REPS = {"full": error_model.AHRS_REPS_FULL, "ci": 2}[SIZE]   # full: each AHRS band on 4 × 250 = 1000 runs
GRID = {"full": error_model.FIT_GRID, "ci": error_model.FIT_GRID_CI}[SIZE]
F9_TRIALS = {"full": 1000, "ci": 20}[SIZE]
FIG11_REPS = {"full": 14, "ci": 2}[SIZE]           # x 73 angles: 1022 trials at full size
SENS_REPS = {"full": 3, "ci": 1}[SIZE]            # repetitions per Table 3 reading
DRIFT_RUN_S = {"full": 120.0, "ci": 10.0}[SIZE]   # Sec. 7: 10 min (see the Fig. 13 section)
DRIFT_TRIALS = {"full": 300, "ci": 2}[SIZE]       # 120 s runs: 1000 do not fit the time budget
STAND_S = {"full": 60.0, "ci": 20.0}[SIZE]        # Sec. 7: 1 min standing still
params = dict(sensor_grade=sensor_grade, fs_hz=fs_hz, fig11_axis=fig11_axis, lever_arm_m=lever_arm_m,
              move_rate_deg_s=move_rate_deg_s, move_accel_deg_s2=move_accel_deg_s2, hold_s=hold_s,
              step_deg=step_deg, latency_s=latency_s, zvd_accel_min_m_s2=zvd_accel_min_m_s2,
              zvd_accel_max_m_s2=zvd_accel_max_m_s2, zvd_var_threshold_m2_s4=zvd_var_threshold_m2_s4,
              zvd_gyro_max_deg_s=zvd_gyro_max_deg_s)
sc = w.scenario_from_parameters(**params)
AT_PAPER = compare.at_paper_settings(params, w.PARAMETER_DEFAULTS)
output.setup_matplotlib()
rows = []
print(w.labels(sc))

# %% [markdown]
# ## wang2022sensors_fig09 — EKF with and without ZVD switching
#
# 0–1 s still, 1–2 s rotating 60° (lever arm: tangential + centripetal acceleration),
# 2–3 s still. The standard EKF (always V_z) reads the lever-arm acceleration as angle;
# with ZVD switching the gyro carries the motion. **Claims (paper):** the switched EKF
# is better in motion and both agree at rest. Figure: the error panel (b) shows the
# ensemble (median and 95 % band over all `F9_TRIALS` trials); θ, ‖a‖ and ‖ω‖ are the
# median trial (by moving RMSE ratio), an example. Numbers: median and 95 % band over
# `F9_TRIALS` trials (1000 at full size), claims on the 97.5 % end; with fewer than 1000
# trials (CI size) the band becomes the range with its count and the claims use its ends.

# %%
a = w.fig09_ekf_switching(sc, F9_TRIALS, SEED)
display(output.save_figure(plots.plot_fig09(a.data), "wang2022sensors_fig09"))
rows += a.rows
print(compare.check_claims(compare.comparison_table(a.rows), enforce=AT_PAPER))

# %% [markdown]
# ## wang2022sensors_fig11 — maximum error vs angle, proposed vs ref. [16] (Sec. 5)
#
# The paper's simulation: Table 3 IMU, no lever arm, −180…180° in 5° steps, "1000
# measurements" = 1000 consecutive outputs after each move. A trial = (angle,
# repetition), each with its own axis estimate from three rests: `FIG11_REPS` = 14
# repetitions × 73 angles = 1022 trials at full size. The max-error rows give the median
# and 95 % band over all trials; what is counted per repetition (the share of angles, the
# worst angle) or per angle (the figure) rests on 14 repetitions only, so those give the
# range with its count (the figure shades it) and the share claim must hold in every
# repetition. **Claim (paper):** the proposed method is more accurate than ref. [16] — one
# sentence, one claim: both readings (share of angles; pooled max errors) must hold.
# The legend sits below the axes, off the data.

# %%
a = w.fig11_max_error(sc, FIG11_REPS, SEED)
display(output.save_figure(plots.plot_fig11(a.data), "wang2022sensors_fig11"))
rows += a.rows
print(compare.check_claims(compare.comparison_table(a.rows), enforce=AT_PAPER))

# %% [markdown]
# ## wang2022sensors_extra_table3_sensitivity — Table 3's ambiguous rows
#
# Table 3's random-walk units are ambiguous (paper-data README item 4) and its 50 mg
# accelerometer bias is the uncalibrated part (Sec. 4 calibrates with ref. [30]). The
# Fig. 11 set-up (15° steps) under each reading: the random-walk reading changes the
# proposed method's error little; the uncompensated bias breaks Eq 28's bias-free model.

# %%
a = w.extra_table3_sensitivity(sc, SENS_REPS, SEED)
output.save_table(a.table, "wang2022sensors_extra_table3_sensitivity")
output.show_table(a.table)
rows += a.rows

# %% [markdown]
# ## wang2022sensors_extra_error_model — identifying the rig from Table 5
#
# The error sources Table 5 points to, each a scenario field with a prior range and its
# source (`w.ERROR_PRIORS`): sensor-to-reference **latency** (the RAMS dynamic RMSE of
# 0.41–0.46° is ≈ 20 times the EKF's own), the **lever arm** and the turntable's
# **move acceleration** (ref. [16]'s 2.8–3.7° dynamic error is lever-arm acceleration
# read as angle; abrupt trapezoidal stops are also what keeps the ZVD from flagging the
# ends of moves, the reason an earlier quintic-move model could not fit RAMS static and
# ref. [16] dynamic with one lever arm), the **accelerometer noise** actually reached
# (ref. [16] static is the per-sample noise), and the AHRS stand-in's **magnetic heading
# disturbance**. Held at stated values: cruise rate (only latency × rate is
# identified), SGT320E ±5″, gyro scale factor.
#
# Fit: uniform prior on a grid; likelihood of each training number as one draw of our
# simulated RMSE (log-normal: Monte Carlo spread plus a declared 15 % model
# discrepancy). The table gives each parameter's posterior mean ± sd, 95 % interval and
# MAP beside its prior range.

# %%
output.show_table(w.error_model_priors_table())
fit = w.fit_error_model(sc, GRID_REPS, SEED, grid=GRID, ahrs_reps=AHRS_REPS)
a = w.extra_error_model(fit)
output.save_table(a.table, "wang2022sensors_extra_error_model")
output.show_table(a.table.drop(columns="source"), "{:.4g}")
rows += a.rows
print(f"RAMS dynamic RMSE at the MAP rig: {a.data['dynamic_without_latency_deg']:.3f} deg without latency, "
      f"{a.data['dynamic_with_latency_deg']:.3f} deg with it (Table 5: 0.41-0.46 deg)")
print("RAMS static RMSE at the MAP lever arm by move acceleration: " + ", ".join(
    f"{k:g} deg/s^2: {v:.4f} deg" for k, v in a.data["static_by_accel_deg"].items()))

# %% [markdown]
# ## wang2022sensors_table05 — static and dynamic RMSE: RAMS vs ref. [16] vs AHRS stand-in
#
# Sec. 7 in simulation, per Table 4 axis: three axis-estimation rests, then −180…180°
# in 10° steps with 1 s pauses; static/dynamic split by the RAMS's ZVD (as the paper);
# RAMS and ref. [16] outputs lag the turntable log by the latency. Every printed number
# (all 18) stands beside its posterior-predictive median and 95 % band and its
# prior-predictive band (4000 draws each; the table gives the Monte Carlo standard
# error of the 2.5 % and 97.5 % quantiles); `role` is the split role (`train`: in the
# fit, never a confirmation; `heldout`: never seen by it).

# %%
a = w.table05_rmse(fit, SEED)
output.save_table(a.table, "wang2022sensors_table05")
output.show_table(a.table)
rows += a.rows
s5 = a.data["summary"]
print(f"held-out Table 5 numbers inside the 95 % band: posterior predictive {s5['fitted_inside']} of "
      f"{s5['n_heldout']}, prior predictive {s5['prior_inside']} of {s5['n_heldout']}; posterior bands are "
      f"{s5['band_width_ratio']:.0%} as wide as the prior ones (median, log scale); largest Monte Carlo "
      f"standard error of a held-out band end: {s5['max_quantile_mc_se']:.4f} deg")
display(output.save_figure(plots.plot_error_model(a.table), "wang2022sensors_extra_error_model"))

# %% [markdown]
# **Reading Table 5.** With the identified rig the paper's RAMS static RMSE
# (0.012–0.018°) and ref. [16]'s dynamic error (≈ 3°) come out of *one* model: a
# lever arm of ≈ 0.2 m, turntable accelerations of ≈ 1000 °/s² (stops so abrupt that
# the ZVD never sees a slow end of a move) and a latency of ≈ 20 ms at 20 °/s, which
# alone makes the RAMS "dynamic" RMSE ≈ 0.4°: the filter is accurate in motion, its
# output is late. The fitted accelerometer noise (≈ 70 µg/√Hz at 200 Hz) lies between
# Table 3's 50 and the BMI088's 175. The prior-predictive bands span an order of
# magnitude, so its "inside" count says little — the fitted bands are the test. The
# held-out numbers that fall outside, and their computed reasons, are listed in the
# summary cell at the end.
#
# **Claims.** Each sentence of the text is tested once, on the worst of the Table 5 rows
# it covers (our posterior-predictive medians). RAMS static < 0.02°, moving < 0.5° and
# ref. [16] static < 0.1° are statements about training rows: `in-sample`, not claims.
# "Both the static and moving RMSEs of Ellipse2-N exceed 0.1°" covers the Bv1 static
# training row and five held-out rows, so it is `in-sample` too, and it fails: the
# paper's own Table 5 has 0.0827° for Bv3 (erratum row).

# %%
print(compare.check_claims(compare.comparison_table(a.rows), enforce=AT_PAPER))

# %% [markdown]
# ## wang2022sensors_fig13 — standing still for 1 min after running
#
# After `DRIFT_RUN_S` of random 10–30° steps both systems stand still (60 s at full size), on the
# identified rig (MAP values). The figure shows what the claim is about: each trial's angle change
# since its first second standing (the offsets between trials would hide it). The paper ran 10 min first; our simulated sensors have no
# thermal drift, so the run only sets the filters' state, and 2 min (full size) is
# already six correlation times of the heading disturbance. `DRIFT_TRIALS` runs (300 at
# full size: 1000 three-minute runs do not fit the notebook's time budget), so the figure
# and the rows give the median and the range with its count, not a 95 % band.
# **Claim (paper):** RAMS is held by the accelerometer; the AHRS's angle shifts with its
# magnetic heading. One sentence, one claim: both parts must hold. The mtcal threshold for
# the first is "every trial < 0.02°": a claim that fails it says how many trials pass 0.02°
# and the computed reason.

# %%
a = w.fig13_drift(sc, fit, DRIFT_TRIALS, SEED, DRIFT_RUN_S, STAND_S)
display(output.save_figure(plots.plot_fig13(a.data), "wang2022sensors_fig13"))
rows += a.rows
print(compare.check_claims(compare.comparison_table(a.rows), enforce=AT_PAPER))

# %% [markdown]
# ## wang2022sensors_fig14 — maximum RAMS error per angle
#
# Per 10° hold of the Table 5 sweeps, the maximum |error| over the whole hold (red: the
# claim's reading) and over its settled second half (blue: tuned), from the same grid Monte
# Carlo, weighted by the posterior (Fig. 14 was not
# in the training set): median and posterior-weighted 2.5–97.5 % of the grid runs per
# angle (360 runs at full size — fewer than 1000, the legend gives the count; more need
# more `GRID_REPS`). The paper's bound (c01 abstract "static measurement error of less
# than 0.05°", c08 Sec. 7 "did not exceed 0.05°", c10 conclusions "maximum static
# measurement error is less than 0.05°": one statement, tested once per reading) is about
# one experiment, so the number compared is an experiment's largest per-angle error
# (median and 95 % band of 4000 posterior-predictive draws), beside its prior-predictive
# band. The paper does not say which part of a 1 s hold Fig. 14 measures, so both
# readings are shown with their verdicts: the **whole hold** (the claim) and the
# **settled second half** (`in-sample`, role `tuned`: this window was chosen after the
# whole-hold reading failed). Claim c02, "a dynamic measurement error of less than 1° in
# the range of ±180°", is tested on an experiment's largest error while moving (ZVD
# dynamic samples, with the identified latency). It shares its error source (latency × rate)
# with the RAMS dynamic Table 5 RMSEs the latency is fitted to: the row prints how often it
# holds in the prior runs that reproduce them and in the others, and it is checked
# `in-sample` when they imply it (≥ 95 %, `compare.IMPLIED_MIN`). The legend sits below the axes.

# %%
a = w.fig14_max_error_per_angle(fit, SEED)
display(output.save_figure(plots.plot_fig14(a.data), "wang2022sensors_fig14"))
rows += a.rows
print(compare.check_claims(compare.comparison_table(a.rows), enforce=AT_PAPER))

# %% [markdown]
# ## Paper vs mtcal
#
# Every row with its split role, kind and source; the role summary counts the paper
# numbers inside our 95 % bands per role (the `heldout` count is the out-of-sample
# test). The last lines name each held-out number outside its band with the computed
# reason.

# %%
table = compare.comparison_table(rows)
output.save_table(table, "wang2022sensors_ekf_comparison")
output.show_table(table[compare.DISPLAY_COLUMNS])
print(compare.role_summary(table))
print(w.outside_reasons(sc, fit, SEED))

# %% [markdown]
# At the paper's settings every enforced claim and consistency check must hold (this
# cell raises otherwise); claims our model fails are listed with their computed reason,
# never rewritten. In a what-if run it reports which claims changed.

# %%
print(compare.check_claims(table, enforce=AT_PAPER))

# %% [markdown]
# ## Fidelity score
#
# Held-out printed numbers with a band (the five Ellipse2-N rows; the Fig. 14 claims
# compare with a threshold, not a value): coverage of the 95 % band with its Wilson
# interval, median width and interval score (Gneiting & Raftery 2007, α = 0.05)
# relative to |paper value|, for the posterior predictive and the prior predictive.

# %%
print(fidelity.score_block(table, "wang2022sensors"))
scores_csv = fidelity.write_scores(table, "wang2022sensors", "31_wang2022sensors_ekf")
