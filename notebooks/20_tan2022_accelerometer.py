# %% [markdown]
# # 20 — tan2022: accelerometer pitch/roll at large angles and the preset Euler rotation
#
# Tan et al. (2022), *Pitch/roll coupled large-angle attitude measurement
# algorithm*, Sec. 1.1, 2.1, 3.1, Figs 2, 5, 8. A static triad gives pitch and
# roll through Eq 2. With the same error ΔA on every axis the first-order pitch
# error is (Eq 3 corrected, = Eq 8 with λ = 0)
#
# `Δθ = −(ΔA/g)[cosθ + √2 sinθ sin(φ+45°)]`,
#
# and the paper adds two triads turned about x by λ1 = 45° (used for θ ≤ 0)
# and λ2 = −135° (θ > 0) so that the two terms cancel (Eq 6–10).
#
# **How the maps are made.** Every map is the *simulated* triad: the error-free
# specific force of Eq 2/Eq 7 plus the error, solved through Eq 2 without
# linearisation. That the first-order formulas agree with it is a unit test
# (`tests/methods/test_large_angle.py`), valid for small ΔA, not a claim
# asserted here on every input. Errors are shown in **degrees**; maps have
# roll φ on x and pitch θ on y, as in notebook 00.
#
# **Why the paper's numbers were never inside our bands.** tan2022 prints no
# result numbers: its figures are contour plots and curves whose only numbers
# are the settings (ΔA = 1e-4 g) and the derived preset angles λ1, λ2. The
# old comparison rows had "small vs large" or "-" in the paper column, so no
# band could contain them. The declared split
# (`mtcal/reporting/paper_data/tan2022_split.csv`) therefore has no held-out
# number: the presets λ1, λ2 are `input` (the paper derives them from its own
# model, Eq 9, and our search window is centred on them). Each row below has a
# `kind`: a paper statement checked at the paper's own settings follows from
# its equations and is `consistency` (not counted as a claim); a `claim` is a
# statement tested under our identified error model, with the threshold we
# had to choose quoted (the paper prints none).
#
# Library: `mtcal.studies.tan2022` (scenario, one producer per artifact, error
# model, plots), methods in `mtcal.methods.large_angle`.

# %% tags=["parameters"]
SIZE = None  # "ci" or "full"; None → $MTCAL_SIZE, else "full"
SEED = 2023  # RNG seed
N_TRIALS = None  # Monte Carlo trials; None → the size's default
# scenario (defaults = the paper's setting; names carry units)
accel_error_g = 1e-4  # ΔA on every axis (g), Sec. 1.1 "10^-4 g 量级"
lambda1_deg = 45.0  # preset angle for θ ≤ 0 (deg), Eq 9
lambda2_deg = -135.0  # preset angle for θ > 0 (deg), Eq 9

# %%
from IPython.display import display

from mtcal.reporting import compare, fidelity
from mtcal.reporting import output
from mtcal.studies import tan2022
from mtcal.studies.tan2022 import plots

output.setup_matplotlib()
SIZE = output.run_size(SIZE)
N_TRIALS = N_TRIALS or {"ci": 100, "full": 1000}[SIZE]
params = {"accel_error_g": accel_error_g, "lambda1_deg": lambda1_deg, "lambda2_deg": lambda2_deg}
sc = tan2022.accel_scenario(grid_step_deg={"ci": 3.0, "full": 1.0}[SIZE], **params)
AT_PAPER = compare.at_paper_settings(params, tan2022.PARAMETER_DEFAULTS)
rows = []
print(f"{tan2022.accel_label(sc)} = {sc.delta_accel_m_s2:.4e} m/s²; λ1 = {sc.lambda1_deg:g}°, "
      f"λ2 = {sc.lambda2_deg:g}°; paper settings: {AT_PAPER}")

# %% [markdown]
# ## tan2022_extra_eq3_erratum — Eq 3 drops a `sinθ`
#
# Printed: `Δθ = −(ΔA/g)cosθ − (ΔA/g)√2 sin(φ+45°)`. Differentiating Eq 2
# gives the `sinθ` on the second term — the form the paper itself uses in
# Eq 8 (λ = 0) and for Δθ_T in Sec. 3.1. The printed form is wrong at first
# order (it puts the roll term at θ = 0, where it vanishes) and is symmetric
# in θ, so it cannot have drawn the asymmetric Fig 2 the paper describes:
# the figure was drawn with the correct formula. This panel is kept out of
# Fig 2 (notebook 00 shows the same erratum with the same axes).

# %%
art = tan2022.eq3_erratum(sc)
print(*art.lines, sep="\n")
rows += art.rows
output.save_table(art.table, "tan2022_extra_eq3_erratum", float_format="%.8f")
display(output.save_figure(plots.eq3_erratum(art), "tan2022_extra_eq3_erratum"))

# %% [markdown]
# ## tan2022_fig02 — pitch error |Δθ| of a three-axis accelerometer
#
# Paper (Sec. 1.1): "for −90° ≤ θ ≤ 0°, |Δθ| is small; for 0° ≤ θ, φ ≤ 90°,
# |Δθ| is large". Tested as the ratio of the mean |Δθ| over the two regions
# (φ ≥ 0). Our finding: the maximum is √3 ΔA/g, at θ = 54.7°, φ = 45°.

# %%
art = tan2022.fig02(sc)
print(*art.lines, sep="\n")
rows += art.rows
output.save_table(art.table, "tan2022_fig02", float_format="%.8f")
display(output.save_figure(plots.fig02(art), "tan2022_fig02"))

# %% [markdown]
# ## tan2022_extra_roll_error — roll error of the same triad (Eq 4)
#
# Paper (after Eq 4): as θ → ±90° the accelerometer cannot give roll. The map
# stops at |θ| = 89° (Eq 4 diverges at ±90°); log colour scale.

# %%
art = tan2022.extra_roll_error(sc)
print(*art.lines, sep="\n")
rows += art.rows
output.save_table(art.table, "tan2022_extra_roll_error", float_format="%.8f")
display(output.save_figure(plots.extra_roll_error(art), "tan2022_extra_roll_error"))

# %% [markdown]
# ## tan2022_fig05 — pitch error with the preset Euler rotation (Eq 9–10)
#
# Two triads preset by λ1 and λ2 about x (Eq 7 outputs), each with ΔA on every
# axis; the pitch is taken from the triad selected by the sign of the pitch
# that triad λ1 measures (the true θ is unknown). Paper (Sec. 2.1): the preset
# rotation suppresses the error surge at large pitch. Eq 6 as printed would
# give `sin(φ−λ)`; we follow Eq 7–10, which agree with each other.

# %%
art = tan2022.fig05(sc)
print(*art.lines, sep="\n")
rows += art.rows
output.save_table(art.table, "tan2022_fig05", float_format="%.8f")
display(output.save_figure(plots.fig05(art), "tan2022_fig05"))

# %% [markdown]
# ## tan2022_fig08 — Δθ_T (plain triad) vs Δθ_p (preset rotation)
#
# Worst case and RMS over roll per pitch. Paper (Sec. 3.1): a clear
# improvement. Our findings: the gain is large at mid pitch (≈ 2.4× in the
# worst case at θ = 60°) but **zero at θ = ±90°**, where both methods have the
# worst case √2 ΔA/g (for any fixed λ, `√2 sin(φ+λ+45°)` reaches ±√2 over a
# 180° roll range); and the preset triad is worse on part of the grid.

# %%
art = tan2022.fig08(sc)
print(*art.lines, sep="\n")
rows += art.rows
output.save_table(art.table, "tan2022_fig08", float_format="%.8f")
display(output.save_figure(plots.fig08(art), "tan2022_fig08"))

# %% [markdown]
# ## tan2022_extra_independent_errors (beyond the paper) — independent axis errors
#
# The paper assumes the same error on every axis. With *independent* errors of
# 1σ = ΔA per axis and per triad, the first-order pitch-error variance is
# `σ²[cos²θ + sin²θ] / g² = σ²/g²` for any λ: the cancellation disappears.
# Monte Carlo over the grid (per-trial RMS ratio, median and 95 % band; the figure: each
# trial's RMS over φ per pitch, median and 95 % band over the trials);
# averaging the two triads instead gives √2.

# %%
art = tan2022.extra_independent_errors(sc, SEED, N_TRIALS)
print(*art.lines, sep="\n")
rows += art.rows
output.save_table(art.table, "tan2022_extra_independent_errors", float_format="%.8f")
display(output.save_figure(plots.extra_independent_errors(art), "tan2022_extra_independent_errors"))

# %% [markdown]
# ## tan2022_extra_error_model_accel — an error model identified from the paper's statements
#
# Real triads have per-axis biases, not one common ΔA. The model: every axis
# of every triad has the static bias `ΔA (1 + r ε)`, `ε ~ N(0, 1)`, with one
# parameter `r` = independent / common part (prior uniform on [0, 2]: MEMS
# datasheets specify offsets per axis; the paper assumes r = 0).
#
# * **Training** (`in-sample` rows, role `train`: fitted to the same statements,
#   shown failing if they fail, never claims): the
#   paper's own error assumption (Sec. 1.1, 2.1: the axes' output errors are
#   "comparable", tested as max/min within a factor 2 on every triad), the
#   Fig 2 statement (θ ≤ 0 small, θ, φ ≥ 0 large) and the Fig 5 statement
#   (large-pitch error suppressed); likelihood = Monte Carlo probability that
#   all three hold at `r`.
# * **Not independently tested**: Fig 8's "clear improvement" (gain > 1.3, our threshold) is implied by
#   the training statements — in the prior predictive it holds in nearly every draw where the three hold
#   (the row prints the computed fractions; rule `tan2022.IMPLIED_MIN`) — so it is checked `in-sample`
#   (role `train`), never counted as a claim.
# * **Inputs** (role `input`, our own statement): λ1 = 45° and λ2 = −135° (Eq 9).
#   The RMS-optimal preset angle per trial is searched over the whole circle (the
#   360° window centred on the paper's value only picks its representation), so
#   "λ inside the band" can fail; but the r fit reads λ (the Fig 5 statement), so
#   it is no independent evidence and never a claim.
#
# Every row carries the posterior-predictive band (`mc_band`: r drawn from the
# posterior, one sensor set per trial) and the prior-predictive band
# (`prior_band`: r drawn from the prior U[0, 2]).

# %%
fit = tan2022.fit_accel_error_model(sc, tan2022.AccelErrorPrior(), SEED, 2 * N_TRIALS)
print(*fit.lines, sep="\n")
output.show_table(fit.parameters, "{:.3f}")
output.show_table(fit.predictions, "{:.3f}")
rows += fit.rows
output.save_table(fit.parameters, "tan2022_extra_error_model_accel_parameters")
output.save_table(fit.predictions, "tan2022_extra_error_model_accel")
display(output.save_figure(plots.accel_error_model(fit), "tan2022_extra_error_model_accel"))

# %% [markdown]
# The statements favour a mostly common-mode error: `r` ≈ 0.1, 95 % interval
# about [0, 0.5], inside the prior. With that model the optimal preset angles
# scatter by about ±15° around the paper's λ1 = 45° and λ2 = −135° (inside
# the bands, no independent evidence, see above) and the Fig 8 gain stays ≈ 1.5 (its
# band reaches down to ≈ 1: for some sensor sets the preset rotation barely
# helps): what the fitted statements imply, so no test of Fig 8 (above). With r drawn from the prior the bands for λ span most of the circle
# and the median gain is ≈ 1.2: the paper's statements carry real
# information, and its angles are only optimal because it assumes
# common-mode errors.
#
# ## Paper vs mtcal

# %%
table = compare.comparison_table(rows)
output.show_table(table[compare.DISPLAY_COLUMNS])
output.save_table(table, "tan2022_accelerometer_comparison")
print(compare.check_claims(table, enforce=AT_PAPER))

# %% [markdown]
# **Summary.** The printed Eq 3 is an erratum (missing `sinθ`); the corrected
# form matches the simulated triad and reproduces the asymmetry the paper
# describes for Fig 2. Under the paper's common-mode assumption the preset
# rotation lowers the grid maximum from √3 to √2 ΔA/g, the grid RMS by ≈ 1.5×
# and the worst case at θ = 60° by ≈ 2.4×, but not the worst case at
# θ = ±90°. With independent axis errors the gain vanishes. The paper's
# presets λ1 and λ2 are inputs, not results: they are RMS-optimal only under
# the common-mode error model fitted to its error assumption and Fig 2/Fig 5
# statements (independent share of the bias r ≈ 0.1, at most ≈ 0.5).
#
# ## Fidelity score
#
# tan2022 prints no result number, so nothing is held out: the score block
# counts its printed numbers by role and the claims tested here.

# %%
print(fidelity.score_block(table, "tan2022"))
scores_csv = fidelity.write_scores(table, "tan2022", "20_tan2022_accelerometer")
