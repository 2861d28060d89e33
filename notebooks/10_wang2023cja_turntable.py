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
# 2. **The hardware error model is identified** on a declared training split
#    (`mtcal/reporting/paper_data/wang2023cja_split.csv`: Tables 1–4 and the printed matrices are
#    `train`) and Tables 5–8 are **predicted** with 95 % posterior-predictive bands (6 and 8 held out;
#    5 and 7 `tuned` since ledger D10: the per-hold angle error was added after their numbers were seen):
#    every parameter draw from the fit's joint posterior runs two sessions. Beside it runs the
#    **prior predictive**: every trial draws the error model from its prior ranges and the
#    installation angles from their prior (`w.predictive.ALPHA_PRIOR_SIGMA_DEG`) — nothing fitted
#    on Tables 1–4 is used.
# 3. **Every printed number is compared one to one** with its split role; scores (coverage with its
#    binomial interval, relative width, interval score, ±25 %) count held-out numbers only, and the
#    paper's claims are tested with the paper's own thresholds — failing ones are listed with the
#    computed reason; checks on numbers the model was fitted on are labelled `in-sample` (shown holding
#    or failing, never counted as claims).

# %% tags=["parameters"]
SIZE = None          # "ci" or "full"; None → $MTCAL_SIZE, else "full"
SEED = 2023          # RNG seed
N_TRIALS = None      # None → the size's default (trials = parameter draws of the T1 session, per model)
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
import pandas as pd
from IPython.display import display
from mtcal.reporting import compare, fidelity, output
from mtcal.studies import wang2023cja as w
from mtcal.studies.wang2023cja import predictive, verdicts

SIZE = output.run_size(SIZE)
# full: 1000 T1 sessions per model and 1000 per training test, so every printed band rests on 1000 draws
# (docs/conventions.md, Bands); ≈ 190 s of CPU, the largest share of `make reproduce`
N_TRIALS = N_TRIALS or {"ci": 4, "full": 1000}[SIZE]
N_TRAIN_TRIALS = N_TRIALS                  # T2–T4 sessions (train tables only: consistency, not held out), fitted model
N_BUDGET = {"ci": 1, "full": 2}[SIZE]
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
fit_table = w.extra_installation_fit().table
output.save_table(fit_table, "wang2023cja_extra_installation_fit")
output.show_table(fit_table)
assert (fit_table.fit_rms_roll_flipped_deg < 0.4 * fit_table.fit_rms_eq8_as_printed_deg).all()

# %% [markdown]
# ## wang2023cja_extra_q33_roll — the printed turntable matrix: Q(3,3) = −1.000355 (erratum)
# Its determinant is negative and applied to pure roll ±90° it returns roll ∓90° (180° off); with
# +1.000355 roll is kept. Negating the q2 row is exactly a roll sign flip.

# %%
# NBVAL_CHECK_OUTPUT
q33 = w.extra_q33_roll().table
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
em_table = w.extra_error_model(fit).table
output.save_table(em_table, "wang2023cja_extra_error_model")
output.show_table(em_table.drop(columns="source"), "{:.4g}")
print(f"log-likelihood of the {fit.n_train} training numbers: fitted {fit.loglik:.1f}, prior nominal {fit.loglik_prior:.1f}")
# consistency (true by construction, not claims): the ML beats the nominal, and values lie in their
# prior ranges because the optimiser works through a logistic transform of each range.
print("fields on a prior bound:", [n for n, b in fit.at_bound.items() if b])
assert not fit.at_bound["compliance_gasket_deg_g"] and not fit.at_bound["gasket_load_tilt_deg_g"]
assert not fit.at_bound["position_error_arcsec"]

# %% [markdown]
# **Reading the fit** (numbers in the table above).
#
# * *Gasket compliance* (≈ 0.34°/g, ±0.02°/g): Tables 2–4 were mounted on gaskets (Figs 4–6) and show
#   a roll overshoot of 0.12–0.14° at roll ±90° that the screwed mount of Table 1 does not show.
# * *Gasket load tilt* (≈ 0.2°/g per axis): the tilt under the 1 g normal load present when level and
#   released at roll ±90°; Eq 13 leaves +1/3 of it at the small-angle rests and −2/3 at ±90° — the
#   −2 : 1 ratio of the common roll offsets of Tables 3 and 4.
# * *Per-rest angle error* (≈ 49″ ± 4″, 1σ per axis per rest). **The bound, and what changed.** Its
#   prior used to end at 60″ and the fit reported it pinned there (≥ 38″ at 95 %), which made the
#   Tables 5/7 bands ≈ 0.07° wide. Two things were tried. (a) *The model term it stands in for*: a
#   common angle offset of the whole verification run (turntable re-homing, the QNCF state at the
#   run's start — T1's after-columns share −0.016° yaw and +0.017° roll offsets) was added as a
#   seventh source and fitted: its ML went to 0 (95 % limit ≈ 23″): the data do not want it, so it
#   was removed again. (b) *Widening*: with the range opened to 5′ the ML is 49″ ± 4″ — **inside**
#   the old cap, with a higher likelihood than the old "pinned" point: the cap was hit by the
#   optimiser, not by the data. The value is ten times a ±5″ turntable; it stands for what the
#   rest-level model does not resolve — the paper's own explanation (§4.1): "The random drift errors
#   of the gyro increase with time, which makes the yaw angle errors increase and cannot be
#   eliminated. Due to the installation errors, the yaw angle errors are also projected in the other
#   two directions". The source string of the field quotes it.
# * *Other bounds*: the screwed-mount compliance sits at −0.05°/g (T1's ±90° rows undershoot by
#   ≈ 0.02°; rigid bracket class, left); the run-to-run accelerometer-bias change and the gyro bias
#   sit on their *lower* bounds (the data do not need them; their 95 % limits in the table). The
#   posterior predictive draws a value on a bound from a half-normal reaching its 95 % limit (one-sided,
#   independent of the others: no Hessian row exists at a bound), the free values jointly (full
#   inverse-Hessian covariance).

# %% [markdown]
# ## Runs: posterior predictive and prior predictive
#
# One session per trial: calibration six positions, then verification six positions (Tables 1–4
# "after") and, for T1, the AoA sweep and the roll sweep (Tables 5–8). **Each pair of trials draws its
# own parameters** (`w.predictive`): from the fit's joint posterior (fitted: the free error-model values
# jointly normal with the full inverse-Hessian covariance, a value on its prior bound one-sided to its
# profile limit, the installation angles of each test normal about their fit with their least-squares
# covariance) or from the prior (prior predictive: error model from its prior ranges, installation
# angles from their prior — not the angles fitted on Tables 1–4). Every draw runs two sessions
# (`predictive.TURNTABLE_PER_DRAW`), so each band's variance splits into a parameter part and a
# sampling part. T2–T4 (training tables only) run with the fitted model.

# %%
sc = w.turntable_scenario(errors=fit.model, **params)
runs = predictive.turntable_predictive_kinds(sc, fit, predictive.KINDS, N_TRIALS, SEED, tests=("T1",))
runs["fitted"].update(predictive.turntable_predictive(sc, fit, "fitted", N_TRAIN_TRIALS, SEED + 1,
                                                      tests=("T2", "T3", "T4")))
print(f"{N_TRIALS} T1 trials per model, {N_TRAIN_TRIALS} T2–T4 trials")
one = {name: verdicts.one_to_one(verdicts.printed_samples(r), seed=SEED, per_draw=predictive.TURNTABLE_PER_DRAW)
       for name, r in runs.items()}
claims = verdicts.claims(runs["fitted"])
claims_prior = verdicts.claims(runs["prior"])
run = runs["fitted"]


def section(artifact_prefix, table=None):
    """One-to-one rows and claims of one artifact (fitted model)."""
    t = one["fitted"] if table is None else table
    rows = t[t.file.str.startswith(artifact_prefix)]
    if len(rows):
        output.show_table(rows[["quantity", "role", "paper", "median", "low", "high", "kind", "n", "inside"]], "{:.4f}")
    c = claims[claims.artifact == artifact_prefix[:19]]
    if len(c):
        print(verdicts.claim_block(c))

# %% [markdown]
# ## wang2023cja_table01 — six positions, normal (screwed) installation (Table 1)
# One session of the verification run beside the paper (`mtcal_*`: the median session by its largest
# after-calibration error, never trial 0), plus the Monte Carlo median of "after"; then
# every printed number one to one (all `train`: the error model was fitted on them).

# %%
for art in (w.table01(run["T1"]), w.table02(run["T2"]), w.table03(run["T3"]), w.table04(run["T4"])):
    output.save_table(art.table, art.artifact_id)
output.show_table(w.table01(run["T1"]).table, "{:.3f}")
section("wang2023cja_table01")

# %% [markdown]
# ## wang2023cja_table02 — large pitch installation error, gasket mount (Table 2)
# The roll rows at ±90° carry the mount compliance: the paper's +0.139/−0.136 overshoot.

# %%
output.show_table(w.table02(run["T2"]).table, "{:.3f}")
section("wang2023cja_table02")

# %% [markdown]
# ## wang2023cja_table03 — large pitch and roll installation errors (Table 3)

# %%
output.show_table(w.table03(run["T3"]).table, "{:.3f}")
section("wang2023cja_table03")

# %% [markdown]
# ## wang2023cja_table04 — all three installation errors large (Table 4)

# %%
output.show_table(w.table04(run["T4"]).table, "{:.3f}")
section("wang2023cja_table04")

# %% [markdown]
# ## wang2023cja_table05 — AoA sweep, mean pitch (Table 5, tuned)
# The sweep follows the verification run in the same session, with an angle error per hold. The
# compared number is printed − reference. Tuned since ledger D10: the per-hold angle error (D6) was
# added to the model after these numbers had been compared, so they are in-sample (its size is fitted
# on Tables 1–4). The paper's statements, with its thresholds, as in-sample checks: "The maximum pitch
# angle error before calibration is 0.04°", "The results after calibration are all within 0.03°"
# and "there is a significant improvement in the pitch angle after calibration".

# %%
t5 = w.table05(run["T1"]).table
output.save_table(t5, "wang2023cja_table05")
output.show_table(t5, "{:.3f}")
section("wang2023cja_table05")

# %% [markdown]
# ## wang2023cja_fig07 — roll and yaw errors in the AoA sweep, before vs after (paper Fig 7)
# Median and 95 % band over all trials (posterior predictive), the paper's Table 6 MaxAE as dashed
# ± lines. The stepwise roll error before calibration is the pitch motion coupled through the
# installation angles (fitted to Table 1).

# %%
from mtcal.studies.wang2023cja import plots
display(output.save_figure(plots.fig07(run["T1"], sc.imu.label), "wang2023cja_fig07"))

# %% [markdown]
# ## wang2023cja_table06 — MaxAE / RMSE of roll and yaw in the AoA sweep (Table 6, held out)
# Claims: "Roll and yaw errors are within 0.03°", "The RMSE of roll and yaw are within 0.01°" and
# "the calibration method significantly reduces the roll and yaw errors" (our reading of "significantly", the
# paper gives no threshold: all four smaller after in at least 95 % of the runs, judged on the 5 % point).

# %%
t6 = w.table06(run["T1"]).table
output.save_table(t6, "wang2023cja_table06")
output.show_table(t6)
section("wang2023cja_table06")

# %% [markdown]
# ## wang2023cja_table07 — roll sweep, mean roll (Table 7, tuned)
# Tuned since ledger D10, as Table 5. The paper's statements as in-sample checks: "Except for 0°, the
# other angle errors are reduced by at least 17 %" (the paper's own
# Table 7 gives 15.6 % at −90°: split role `erratum`), "over 80%" at 90°, and "within 0.06° before
# calibration and 0.04° after" (the text says pitch; Table 7 is roll).

# %%
t7 = w.table07(run["T1"]).table
output.save_table(t7, "wang2023cja_table07")
output.show_table(t7, "{:.3f}")
section("wang2023cja_table07")

# %% [markdown]
# ## wang2023cja_fig08 — pitch and yaw errors in the roll sweep, before vs after (paper Fig 8)

# Median and 95 % band over all trials, the paper's Table 8 MaxAE as dashed ± lines.

# %%
display(output.save_figure(plots.fig08(run["T1"], sc.imu.label), "wang2023cja_fig08"))

# %% [markdown]
# ## wang2023cja_table08 — MaxAE / RMSE of pitch and yaw in the roll sweep (Table 8, held out)
# Claim: "the pitch-yaw errors are reduced by at least 30 %" (smallest of the four reductions).

# %%
t8 = w.table08(run["T1"]).table
output.save_table(t8, "wang2023cja_table08")
output.show_table(t8)
section("wang2023cja_table08")

# %% [markdown]
# ## wang2023cja_extra_error_budget — one source at a time (T2, gasket mount, fitted model)
# Each row switches on a single named source (its own generator), `all` is the full model; `none`
# is noise-free and must be exact. The verification-run residual is dominated by the per-rest angle
# error and the two gasket terms, i.e. by what was identified on Tables 1–4; sensor noise, biases,
# scale factor and quantisation of the paper's grade each stay near 0.001–0.01°.

# %%
budget = w.extra_error_budget(sc, "T2", N_BUDGET, SEED).table
output.save_table(budget, "wang2023cja_extra_error_budget")
output.show_table(budget, "{:.5f}")
assert budget.set_index("source").loc["none", "after_max_deg"] < 1e-6

# %% [markdown]
# ## Paper vs mtcal — every printed number, posterior predictive and prior predictive
#
# One row per printed number of Tables 1–8 and the turntable matrix (split role beside it; the
# matrix's Q(3,3) is an `erratum`). `se_low`/`se_high`: Monte Carlo standard error of the band ends
# (bootstrap over trials; empty where a row prints a range). Scores count held-out numbers only.

# %%
output.save_table(one["fitted"], "wang2023cja_extra_turntable_one_to_one")
output.save_table(one["prior"], "wang2023cja_extra_turntable_one_to_one_prior_predictive")
held = one["fitted"][one["fitted"].role == "heldout"]
output.show_table(held[["quantity", "paper", "median", "low", "high", "se_low", "se_high", "inside"]], "{:.4f}")
if held.se_low.notna().any():
    print(f"median MC standard error of the band ends: low {held.se_low.median():.4f}°, "
          f"high {held.se_high.median():.4f}° (median band width {(held.high - held.low).median():.4f}°)")
else:  # CI size: too few draws for a 95 % band, the rows print ranges (no quantile standard error)
    n_draws = f"{held.n.min()}" if held.n.min() == held.n.max() else f"{held.n.min()}–{held.n.max()}"
    print(f"band ends are ranges of {n_draws} draws: no Monte Carlo standard error")

# %% [markdown]
# ### Where the width of a band comes from
# Law of total variance over the pairs of sessions that share one parameter draw
# (`predictive.variance_parts`): `var_parameter` is the variance of the conditional mean over the
# posterior draws, `var_sampling` the mean variance between sessions of one draw (noise, biases, per-rest
# angle errors); they sum to `var_band` within Monte Carlo error. Columns of
# `wang2023cja_extra_turntable_one_to_one.csv` (deg²).

# %%
var_cols = ["quantity", "var_band", "var_parameter", "var_sampling", "parameter_share"]
output.show_table(held[var_cols], "{:.3g}")
print(f"held-out rows: median parameter share {held.parameter_share.median():.2f}; "
      f"sum of parts / band variance, median {((held.var_parameter + held.var_sampling) / held.var_band).median():.3f}")

# %% [markdown]
# ## wang2023cja_extra_table08_causes — why the paper removes less of the Table 8 coupling
# Our calibration removes 86–95 % of the roll-sweep pitch/yaw coupling, the paper's 37–67 % (Table 8).
# Each candidate cause is computed on Tables 1–4 and the printed matrix only (`w.table08_causes`; Table 8
# is never read there): the pitch and yaw MaxAE reduction 1 − after/before over the roll sweep that the
# mechanism alone leaves (coupling only; noise takes a few per cent more), with a 95 % band, and whether
# Tables 1–4 support it at that size. The comparison with the paper's fractions comes last.

# %%
from mtcal.studies.wang2023cja import table08_causes
causes = table08_causes.candidate_fractions(fit, n={"ci": 300, "full": 2000}[SIZE], seed=SEED)
output.save_table(causes, "wang2023cja_extra_table08_causes")
output.show_table(causes.drop(columns=["setting", "support_reason"]), "{:.3f}")
table08_note = verdicts.table08_cause(causes)
print(table08_note)

# %% [markdown]
# ## The paper's claims, with its thresholds
#
# `claim` rows are tested against held-out numbers; the notebook enforces (at the paper's settings)
# only the claims that hold, and lists every failing one with its computed reason. `in-sample`
# rows are checked against numbers the model was fitted or tuned on (Tables 1–4; Tables 5 and 7 since
# ledger D10); they are reported (a failing one says FAILS), never counted as claims. A verdict is taken on the median trial; where the share of trials for which
# the claim holds is within Monte Carlo error of one half, the reason says "not resolved": our model
# cannot tell whether the paper's threshold is met, and another seed may flip that verdict.

# %%
output.save_table(claims, "wang2023cja_extra_turntable_claims")
print(verdicts.claim_block(claims))
print("prior predictive:")
print(verdicts.claim_block(claims_prior[claims_prior.kind == "claim"]))
ENFORCED = ("c16",)                # held-out claims that hold in the full run; the others fail (listed above)
if AT_PAPER and SIZE == "full":                 # 4 CI trials are too few for a verdict
    held_claims = claims.set_index("claim_id").loc[list(ENFORCED)]
    assert held_claims.holds.all(), held_claims[~held_claims.holds]

# %% [markdown]
# ## Shape predictions that can fail
# Beyond each number inside its band: does our model get the *shape* of the tables? Table 5's
# error trend over the 8 holds (Kendall τ between the paper's and our median errors, one-sided p < 0.05),
# Table 7's slope of the roll error against the reference roll, and Table 8's reduction fraction
# 1 − after/before, each against our band of per-trial values. Our thresholds (`mtcal finding`): Table 8's
# are shown, not counted (functions of the same held-out numbers, each compared once one to one; a failing
# one is still named in the verdict's cause); Tables 5 and 7's are in-sample checks (tuned since ledger D10).

# %%
shape = verdicts.shape_predictions(verdicts.printed_samples(runs["fitted"]), table08_note)
shape_table = compare.comparison_table(shape)
output.show_table(shape_table[["artifact", "quantity", "paper", "mtcal", "mc_band", "holds", "note"]])
print(compare.claims_summary(shape_table))

# %% [markdown]
# ## wang2023cja_extra_baselines — the fit against a band with no physics
# The angle errors of Tables 5 and 7 (held out until ledger D10 made them tuned: an in-sample comparison
# since) scored three ways on the same rows: our posterior predictive,
# the prior predictive, and a band with no physics — 0 ± 1.96 × the RMS of Table 1's 18 "after − reference"
# residuals (train numbers). A model that does not beat the no-physics band on a table adds nothing there.

# %%
baselines = verdicts.no_physics_baseline(one)
output.save_table(baselines, "wang2023cja_extra_baselines")
output.show_table(baselines, "{:.3g}")

# %% [markdown]
# ## wang2023cja_extra_crossval — leave-one-table-out cross-validation over Tables 1–4
# Blind by construction (`w.crossval`): each fold fits the error model on three of Tables 1–4 and predicts the
# 18 "after − reference" numbers of the fourth; the fold's fit never opens the held-out table (its installation
# angles are drawn from their prior, its "before" columns are not read either; a parameter the three tables cannot
# identify — the screwed-mount compliance without Table 1 — is drawn from its prior). Predictions at the rest level
# (`w.error_model.rest_residuals`, the fit's own session model), 2000 parameter draws per fold. Scored on the same
# rows with the interval score (Gneiting & Raftery 2007, α = 0.05, in degrees; smaller is better) against the prior
# predictive and a band with no physics: 0 ± 1.96 × the RMS of the fold's three *training* tables' residuals.
# Skill = 1 − mean interval score / the baseline's (> 0: the model is better). Any fold where the model loses to a
# baseline is listed below as such.

# %%
cv_rows = w.crossval.cross_validate(seed=SEED)
cv_scores = w.crossval.fold_scores(cv_rows)
output.save_table(cv_scores, "wang2023cja_extra_crossval")
for fold, part in cv_rows.groupby("fold", sort=True):
    print(f"{w.crossval.fold_artifact(fold)} held out (fit on {', '.join(w.crossval.training_tests(fold))}; "
          f"no-physics band 0 ± {part['no-physics_high'].iloc[0]:.4f}°):")
    output.show_table(part[["quantity", "paper", "fitted_median", "fitted_low", "fitted_high", "fitted_inside",
                            "fitted_interval_score", "no-physics_interval_score", "prior_interval_score"]], "{:.4f}")
output.show_table(cv_scores, "{:.3g}")
for r in cv_scores[cv_scores.baseline == "fitted"].itertuples():
    words = [f"{'beats' if skill > 0 else 'does NOT beat'} {name} ({skill:+.0%})"
             for name, skill in (("no-physics", r.skill_vs_no_physics), ("the prior predictive", r.skill_vs_prior))]
    print(f"{r.scope}: {r.inside} of {r.n} inside; mean interval score {r.mean_interval_score_deg:.3f}°; "
          f"the model {' and '.join(words)}")
cv_scores_csv = fidelity.write_cv_records(w.crossval.cv_records(cv_rows, "10_wang2023cja_turntable"),
                                          "10_wang2023cja_turntable")

# %% [markdown]
# ## Score block
# The comparison table (every printed number with its posterior- and prior-predictive band, then
# the claims and the shape predictions) is scored by `mtcal.reporting.fidelity` and merged into
# `data/fidelity_scores.csv`.

# %%
table = verdicts.comparison(one, claims, shape)
output.save_table(table, "wang2023cja_turntable_comparison")
scores_csv = fidelity.write_scores(table, "wang2023cja", "10_wang2023cja_turntable")
print(fidelity.score_block(table, "wang2023cja"))
print(f"size {SIZE}: {N_TRIALS} trials per model")
