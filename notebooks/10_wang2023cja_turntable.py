# %% [markdown]
# # wang2023cja — installation-error calibration on the turntable (Tables 1–8, Figs 7–8)
#
# Wang et al. (Chin. J. Aeronaut. 2023): QNCF attitude (Eq 5–8), least-squares error quaternion
# matrix (Eq 10–13), six-position procedure (§3.2). Hardware is replaced by simulation with known
# truth (`mtcal.studies.wang2023cja`). Three rules make the comparison with the paper honest:
#
# 1. **"After" is measured on a separate verification run**, as the paper did: the matrix is fitted
#    on one six-position run and applied to a later run of the same power-on session (new rests,
#    new noise, a changed accelerometer bias). In-sample residuals are shown, labelled as such.
# 2. **The hardware error model is identified** from a declared training subset — Tables 1–4 and the
#    printed matrices — and the held-out Tables 5–8 are **predicted** with 95 % Monte Carlo bands.
#    The prior-only model (datasheet nominal values) is run beside the fitted one.
# 3. **Every comparison row has a role** (`fitted`, `predicted`, `finding`, `erratum`) and a source
#    (`paper claim`, `mtcal finding`); fitted rows are never counted as confirmations.

# %% tags=["parameters"]
SIZE = None          # "ci" or "full"; None → $MTCAL_SIZE, else "full"
SEED = 2023          # RNG seed
N_TRIALS = None      # None → the size's default (Monte Carlo trials per test and model)
# scenario (defaults = the paper's setting; names carry units)
gyro_grade = "wang2023cja"            # a mtcal.core.sensor_grades name
accel_grade = "wang2023cja"           # a mtcal.core.sensor_grades name
fs_hz = 1000.0                        # sample rate (§4.1)
rest_s = 3.0                          # rest per position (§3.2)
yaw_positions_deg = (8.0, -8.0)       # §4.1 ranges, Table 1
pitch_positions_deg = (-12.0, 23.0)
roll_positions_deg = (90.0, -90.0)
turntable_rate_deg_s = 20.0           # assumed mean move rate

# %%
import numpy as np
from mtcal.reporting import compare, output
from mtcal.studies import wang2023cja as w

SIZE = output.run_size(SIZE)
N_TRIALS = N_TRIALS or {"ci": 4, "full": 40}[SIZE]
N_BUDGET = {"ci": 1, "full": 4}[SIZE]
params = dict(gyro_grade=gyro_grade, accel_grade=accel_grade, fs_hz=fs_hz, rest_s=rest_s,
              yaw_positions_deg=yaw_positions_deg, pitch_positions_deg=pitch_positions_deg,
              roll_positions_deg=roll_positions_deg, turntable_rate_deg_s=turntable_rate_deg_s)
AT_PAPER = compare.at_paper_settings(params, w.TURNTABLE_DEFAULTS)
output.setup_matplotlib()

# %% [markdown]
# ## wang2023cja_extra_installation_fit — installation angles from the "before" columns of Tables 1–4
#
# Model: zeroed QNCF output `q_s = q_bs⁻¹ ⊗ q_wb ⊗ q_bs` (the paper's initial angles are 0°), Eq 1 angles
# α1 (yaw axis z), α2 (roll axis y), α3 (pitch axis x). With Eq 8/9 as printed the fit explains
# almost nothing; with the paper's roll sign flipped — a handedness change, the same family as the
# printed Q(3,3) = −1 (next section) — the residual drops several-fold. These twelve angles are
# geometry fitted to the training tables (role `fitted`).

# %%
# NBVAL_CHECK_OUTPUT
fit_table = w.installation_fit_table()
output.save_table(fit_table, "wang2023cja_extra_installation_fit")
output.show_table(fit_table)
assert (fit_table.fit_rms_roll_flipped_deg < 0.4 * fit_table.fit_rms_eq8_as_printed_deg).all()

# %% [markdown]
# ## wang2023cja_extra_q33_roll — the printed turntable matrix: Q(3,3) = −1.000355 (erratum)
# Its determinant is negative and applied to pure roll ±90° it returns roll ∓90° (180° off); with
# +1.000355 roll is kept. Negating the q2 row is exactly a roll sign flip.

# %%
# NBVAL_CHECK_OUTPUT
q33 = w.printed_matrix_check()
output.save_table(q33, "wang2023cja_extra_q33_roll")
output.show_table(q33, "{:+.3f}")
flipped = q33[q33.matrix == "printed"]
assert (flipped.det < 0).all() and (np.abs(np.abs(flipped.roll_deg) - 90) < 0.1).all()
assert (np.sign(flipped.roll_deg) != np.sign(flipped.roll_in_deg)).all()

# %% [markdown]
# ## wang2023cja_extra_error_model — the hardware error model, identified on Tables 1–4
#
# Six named sources (unit, datasheet-style prior range and source in the table), fitted by maximum
# likelihood to the 72 "after − reference" numbers of Tables 1–4. The likelihood comes from a
# rest-level model of a calibration run followed by a separate verification run in the same session
# (`w.error_model.rest_residuals`: QNCF static equilibrium — tilt from the accelerometer, yaw from the
# gyro), linearised in the small errors: each test's 18 residuals are Gaussian with the model's mean
# (mount compliance) and Monte Carlo covariance (random sources) plus the 0.001° printing round-off.
# Values are kept inside their prior ranges; a value on its bound means the data push it further.

# %%
fit = w.fit_error_model(seed=SEED)
em_table = w.error_model_table(fit)
output.save_table(em_table, "wang2023cja_extra_error_model")
output.show_table(em_table.drop(columns="source"), "{:.4g}")
print(f"log-likelihood of the {fit.n_train} training numbers: fitted {fit.loglik:.1f}, prior nominal {fit.loglik_prior:.1f}")
assert fit.loglik > fit.loglik_prior
assert ((em_table.fitted >= em_table.prior_low) & (em_table.fitted <= em_table.prior_high)).all()
assert not fit.at_bound["compliance_gasket_deg_g"] and not fit.at_bound["gasket_load_tilt_deg_g"]

# %% [markdown]
# **Reading the fit** (numbers in the table above).
#
# * *Gasket compliance* (≈ 0.3°/g, identified to ±0.02°/g): Tables 2–4 were mounted on gaskets
#   (Figs 4–6) and show a roll overshoot of 0.12–0.14° at roll ±90° that the screwed mount of
#   Table 1 does not show — gravity pulling the IMU sideways on its soft mount.
# * *Gasket load tilt* (≈ 0.2°/g per axis): a gasket-raised installation also sits differently under
#   the 1 g normal load present when level and released at roll ±90°. Eq 13 spreads that
#   position-dependent tilt over the six rests, leaving +1/3 of it at the four small-angle rests and
#   −2/3 at ±90° — exactly the −2 : 1 ratio of the common roll offsets of Table 3 (−0.062°, +0.12°)
#   and Table 4 (+0.077°, −0.15°). It is the same in the calibration and verification runs.
# * *Sitting on a bound* — a finding about the paper, with the one-sided 95 % profile limit in the
#   table: the per-rest angle error runs to its 60″ upper bound (≥ ≈ 40″): after the structure
#   above, the paper's cells still scatter by ≈ 0.017° (T1 has, e.g., a common yaw offset of −0.016°
#   and roll offset of +0.017° at all six rests), many times what a ±5″ turntable gives. The
#   screwed-mount compliance runs to its −0.05°/g bound (T1's ±90° rows undershoot by ≈ 0.02°).
#   The run-to-run accelerometer-bias change (≤ ≈ 0.15 mg) and the gyro bias (≤ ≈ 1 °/h) go to their
#   lower bounds: the data do not need them — the common roll offsets of Tables 3–4 that first
#   suggested a 0.35–1.3 mg bias change are explained by the gasket load tilt instead.

# %% [markdown]
# ## Runs: calibration run → separate verification run (+ AoA and roll sweeps for T1)
#
# One session per trial: calibration six positions, then verification six positions (Tables 1–4
# "after") and, for T1, the AoA sweep and the roll sweep (Tables 5–8). The same trials are run with
# the fitted model and with the prior-nominal model, and both comparison tables are built here; each
# section below shows its artifact and evaluates its rows. Rows from Tables 1–4 are `fitted` (the
# model was identified on them), rows from Tables 5–8 are `predicted`.

# %%
sc = w.turntable_scenario(errors=fit.model, **params)
runs = {"fitted": w.turntable_runs(sc, N_TRIALS, SEED),
        "prior": w.turntable_runs(w.turntable_scenario(errors=w.ErrorModel(), **params), N_TRIALS, SEED)}
tables = {name: compare.comparison_table(w.turntable_rows(r)) for name, r in runs.items()}
run = runs["fitted"]

# %% [markdown]
# ## wang2023cja_table01 — six positions, normal (screwed) installation (Table 1)
# Trial 0 of the verification run beside the paper, plus the Monte Carlo median of "after". The
# comparison rows use the RMS over the 18 cells, and show the in-sample residual (the calibration
# run's own rests) separately: it is what the old notebook reported as "after", 5–10× below the paper.

# %%
for i, test in enumerate(("T1", "T2", "T3", "T4")):
    output.save_table(w.positions_table(test, run[test]), f"wang2023cja_table{i + 1:02d}")
output.show_table(w.positions_table("T1", run["T1"]), "{:.3f}")
print(w.section_claims(tables["fitted"], "wang2023cja_table01", enforce=AT_PAPER))

# %% [markdown]
# ## wang2023cja_table02 — large pitch installation error, gasket mount (Table 2)
# The roll rows at ±90° carry the mount compliance: the paper's +0.139/−0.136 overshoot.

# %%
output.show_table(w.positions_table("T2", run["T2"]), "{:.3f}")
print(w.section_claims(tables["fitted"], "wang2023cja_table02", enforce=AT_PAPER))

# %% [markdown]
# ## wang2023cja_table03 — large pitch and roll installation errors (Table 3)

# %%
output.show_table(w.positions_table("T3", run["T3"]), "{:.3f}")
print(w.section_claims(tables["fitted"], "wang2023cja_table03", enforce=AT_PAPER))

# %% [markdown]
# ## wang2023cja_table04 — all three installation errors large (Table 4)

# %%
output.show_table(w.positions_table("T4", run["T4"]), "{:.3f}")
print(w.section_claims(tables["fitted"], "wang2023cja_table04", enforce=AT_PAPER))

# %% [markdown]
# ## wang2023cja_table05 — AoA sweep, mean pitch (Table 5, predicted)
# The sweep follows the verification run in the same session, with a turntable angle error per
# hold. "Before up to 0.04°" could not fail when our "before" was 8× smaller than the paper's; it is
# now tested as "the paper's 0.040 lies inside our band", and "after within 0.03°" on our median.
# Both are `reported:` claims: whether they hold depends on the identified error level (the per-hold
# error and the run-to-run offsets), not on the calibration method, so they are not asserted.

# %%
t5 = w.sweep_mean_table("wang2023cja_table05", run["T1"].sweeps["aoa"], "pitch")
output.save_table(t5, "wang2023cja_table05")
output.show_table(t5, "{:.3f}")
print(w.section_claims(tables["fitted"], "wang2023cja_table05", enforce=AT_PAPER))

# %% [markdown]
# ## wang2023cja_fig07 — roll and yaw errors in the AoA sweep, before vs after (paper Fig 7)
# Asserted: the pitch steps couple into roll as stepwise errors (correlation with sin pitch).

# %%
from mtcal.studies.wang2023cja import plots
output.save_figure(plots.fig07(run["T1"], sc.imu.label), "wang2023cja_fig07")
print(w.section_claims(tables["fitted"], "wang2023cja_fig07", enforce=AT_PAPER))

# %% [markdown]
# ## wang2023cja_table06 — MaxAE / RMSE of roll and yaw in the AoA sweep (Table 6, predicted)
# Asserted: calibration reduces the roll error. Reported: "RMSE within 0.01°" for roll and yaw —
# yaw is gyro-only and drifts between the calibration and the sweep, so after calibration it is
# no better than before in our runs.

# %%
t6 = w.error_metric_table("wang2023cja_table06", run["T1"].sweeps["aoa"], ((2, "roll"), (0, "yaw")))
output.save_table(t6, "wang2023cja_table06")
output.show_table(t6)
print(w.section_claims(tables["fitted"], "wang2023cja_table06", enforce=AT_PAPER))

# %% [markdown]
# ## wang2023cja_table07 — roll sweep, mean roll (Table 7, predicted)
# Asserted: after calibration the mean roll is closer to the reference than before (MC medians).

# %%
t7 = w.sweep_mean_table("wang2023cja_table07", run["T1"].sweeps["roll"], "roll", sign=w.PAPER_SIGN[2])
output.save_table(t7, "wang2023cja_table07")
output.show_table(t7, "{:.3f}")
print(w.section_claims(tables["fitted"], "wang2023cja_table07", enforce=AT_PAPER))

# %% [markdown]
# ## wang2023cja_fig08 — pitch and yaw errors in the roll sweep, before vs after (paper Fig 8)

# %%
output.save_figure(plots.fig08(run["T1"], sc.imu.label), "wang2023cja_fig08")
print(w.section_claims(tables["fitted"], "wang2023cja_fig08", enforce=AT_PAPER))

# %% [markdown]
# ## wang2023cja_table08 — MaxAE / RMSE of pitch and yaw in the roll sweep (Table 8, predicted)
# The paper's claim — a ≥ 30 % reduction of all four numbers — is asserted on the median run's
# smallest reduction.

# %%
t8 = w.error_metric_table("wang2023cja_table08", run["T1"].sweeps["roll"], ((1, "pitch"), (0, "yaw")))
output.save_table(t8, "wang2023cja_table08")
output.show_table(t8)
print(w.section_claims(tables["fitted"], "wang2023cja_table08", enforce=AT_PAPER))

# %% [markdown]
# ## wang2023cja_extra_error_budget — one source at a time (T2, gasket mount, fitted model)
# Each row switches on a single named source (its own generator), `all` is the full model; `none`
# is noise-free and must be exact. The verification-run residual is dominated by the per-rest angle
# error and the two gasket terms, i.e. by what was identified on Tables 1–4; sensor noise, biases,
# scale factor and quantisation of the paper's grade each stay near 0.001–0.01°.

# %%
budget = w.error_budget_table(sc, "T2", N_BUDGET, SEED)
output.save_table(budget, "wang2023cja_extra_error_budget")
output.show_table(budget, "{:.5f}")
assert budget.set_index("source").loc["none", "after_max_deg"] < 1e-6

# %% [markdown]
# ## Paper vs mtcal — fitted model, and the prior-only model beside it
# `mtcal` is the Monte Carlo median, `mc_band` its 95 % interval. The prediction summary counts the
# held-out (`predicted`) rows whose paper number lies inside our band; the prior-only model (the
# datasheet nominal values, no mount compliance) is the same simulation before seeing Tables 1–4.

# %%
output.save_table(tables["fitted"], "wang2023cja_turntable_comparison")
output.save_table(tables["prior"], "wang2023cja_extra_turntable_comparison_prior_only")
output.show_table(tables["fitted"])
for name, table in tables.items():
    print(f"{name:7s} model: {compare.prediction_summary(table)}")

# %% [markdown]
# ## Paper numbers outside our band, and why
#
# The table lists them (at full size, 40 trials). The computed reasons:
#
# * **Tables 6 and 8, "before" rows** — deterministic: the installation angles fitted to Table 1
#   (α1 ≈ −0.24° about yaw) fix the coupling (≈ α1 · sin of the moving angle), so the band is
#   narrow; where it misses, it is 5–30 % off the paper's number — the sweeps were not run with
#   exactly Table 1's mounting, or the coupling was partly compensated.
# * **Table 8, "after" pitch/yaw** — the paper keeps 35–45 % of the roll-sweep coupling after
#   calibration (MaxAE 0.127°/0.140°), ours removes 80–95 %: none of the six identified sources
#   leaves that much coupling behind in a roll sweep. The paper's "≥ 30 %" reduction claim still
#   holds in our runs (asserted), but its after-values are not predicted.
# * With the CI size (4 trials) the bands are much narrower than at full size and more rows fall
#   outside; the counts quoted in the closing note are those of the full run.

# %%
output.show_table(w.outside_rows(tables["fitted"]))
print(compare.check_claims(tables["fitted"], enforce=False))
print(compare.check_claims(w.asserted(tables["fitted"]), enforce=AT_PAPER))
