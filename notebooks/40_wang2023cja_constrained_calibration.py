# %% [markdown]
# # 40 — Constrained installation-error calibration (beyond wang2023cja)
#
# wang2023cja calibrates the installation error with a general 4×4 matrix fitted by least squares
# over quaternion components (Eq 10–13): 16 free numbers. The true relation between body and sensor
# attitude quaternions is a rotation of quaternion space. With mounting quaternion `c`
# (`q_s = q_b ⊗ c`) and a possible offset `w` of the sensor's reference frame
# (`q_s = w ⊗ q_b ⊗ c`), `q_b = w* ⊗ q_s ⊗ c* = L(p) R(r) q_s` with `p = w*`, `r = c*`: an element of
# SO(4) with 6 degrees of freedom, or 3 (`R(c*)` only) when the reference frame is shared.
# `mtcal.methods.constrained_fit` fits **Eq 13** (16 parameters), **SO(4)** (orthogonal Procrustes in
# 4-D, factored into unit quaternions `p`, `r`) and **mounting** (`c` alone, q-method).
#
# This notebook asks (1) how many positions each method needs, (2) how accurate the calibrated
# attitude is on unseen attitudes vs the number of positions and the noise (Monte Carlo, 95 % bands),
# and (3) what the constrained view says about the two matrices printed in the paper. The study's
# producers are in `mtcal.studies.wang2023cja.constrained`.

# %% tags=["parameters"]
SIZE = None          # "ci" or "full"; None → $MTCAL_SIZE, else "full"
SEED = 2023          # RNG seed
N_TRIALS = None      # None → the size's default (Monte Carlo trials per configuration)
N_TEST = None        # None → the size's default (unseen test attitudes per trial)
# study settings
k_max = 12                                   # largest number of calibration positions
noise_levels_deg = (0.005, 0.01, 0.02, 0.05)  # per-position error σ per axis (deg)

# %%
import numpy as np
from IPython.display import display
from mtcal.reporting import compare, fidelity, output
from mtcal.studies import wang2023cja as w
from mtcal.studies.wang2023cja import constrained

SIZE = output.run_size(SIZE)
N_TRIALS = N_TRIALS or {"ci": 200, "full": 2000}[SIZE]
N_TEST = N_TEST or {"ci": 40, "full": 100}[SIZE]
params = constrained.check_parameters(k_max, noise_levels_deg)
AT_PAPER = compare.at_paper_settings(params, constrained.PARAMETER_DEFAULTS)
output.setup_matplotlib()

# %% [markdown]
# ## Noise level: the per-position error of the identified error model
#
# Each mean sensor quaternion of a calibration position is perturbed by a small random rotation,
# `q_s ← q_s ⊗ exp(n/2)`, `n ~ N(0, σ² I₃)`. σ is not chosen here: it is the per-axis RMS of the
# "after − reference" residual of a separate verification run under the hardware error model
# identified on Tables 1–4 (`w.fit_error_model`, notebook 10) — one number for the whole study. (It
# used to be 0.02° here, from the RMS of Table 1, and 0.002° in the turntable notebook, whose old
# error model was fitted to nothing and evaluated in-sample; both are superseded by this value.)

# %%
fit = w.fit_error_model(seed=SEED)
SIGMA_DEG = round(w.position_noise_deg(fit.model, seed=SEED), 3)
print(f"identified per-position error sigma = {SIGMA_DEG:.3f} deg per axis")
assert 0.005 < SIGMA_DEG < 0.05
levels = tuple(sorted(set(noise_levels_deg) | {SIGMA_DEG}))

# %% [markdown]
# The identified σ is dominated by the per-rest angle error, ≈ 49″ ± 4″ (notebook 10; its prior now
# reaches 5′ and the ML lies inside the old 60″ cap — the paper's six-position residuals scatter
# ten times more than a ±5″ turntable explains). The gasket terms do not enter: the constrained study
# assumes a rigid mount, as Eq 13 does.

# %% [markdown]
# ## wang2023cja_extra_min_positions — minimum number of positions per method
#
# Noise-free recovery: for K = 1…6 positions, does each estimator return the true matrix (attitude
# error < 1e-9 rad on unseen attitudes)? Layouts: 50 random layouts in the paper's envelope, the
# interleaved symmetric layout (yaw +8°, pitch −12°, roll +90°, yaw −8°, pitch +23°, roll −90°), and
# the first K rows of Table 1 in the paper's order. The paper (§3.1) says "at least three positions"
# because of the unit-norm constraint. For Eq 13 as printed that is wrong: `A_s` is 4×K, so
# `A_s A_sᵀ` is singular for K = 3 whatever the positions. Three is the minimum of the SO(4) fit; the
# mounting fit needs one.

# %%
# NBVAL_CHECK_OUTPUT
b1 = w.extra_min_positions(SEED).table
output.save_table(b1, "wang2023cja_extra_min_positions")
output.show_table(b1)
assert dict(zip(("eq13", "so4", "mounting"), b1["min_K_generic"])) == {"eq13": 4, "so4": 3, "mounting": 1}
assert b1.loc[0, "min_K_paper_order"] == 5  # paper's order: first 4 rows span only 3 quaternion directions

# %% [markdown]
# ## wang2023cja_extra_error_vs_positions — attitude error after calibration vs number of positions
#
# `N_TRIALS` trials per point, vectorised. Each draws a mounting (σ 0.3° per axis), perturbs the K
# calibration quaternions by σ, fits the three estimators and evaluates the RMS attitude error over
# `N_TEST` unseen noise-free attitudes in the paper's envelope. Two truths: **shared frame** (3-DOF)
# and **heading offset** (the sensor's yaw reference differs by β ~ N(0, 0.3°): within SO(4), outside
# the mounting-only model). Lines: median; bands: 95 %.

# %%
b2 = w.extra_error_vs_positions(SIGMA_DEG, N_TRIALS, N_TEST, SEED, range(2, k_max + 1)).table
output.save_table(b2, "wang2023cja_extra_error_vs_positions")
from mtcal.studies.wang2023cja import plots
display(output.save_figure(plots.error_vs_positions_figure(b2, title=(
    f"wang2023cja_extra_error_vs_positions: σ = {SIGMA_DEG:.3f}° per axis, {N_TRIALS} trials; dotted: paper's K = 6")),
    "wang2023cja_extra_error_vs_positions"))

# %% [markdown]
# ## wang2023cja_extra_error_vs_noise — attitude error after calibration vs σ (paper's six positions)

# %%
b3 = w.extra_error_vs_noise(levels, N_TRIALS, N_TEST, SEED).table
output.save_table(b3, "wang2023cja_extra_error_vs_noise")
display(output.save_figure(plots.error_vs_noise_figure(b3, sigma_deg=SIGMA_DEG, title=(
    f"wang2023cja_extra_error_vs_noise: paper's six positions, {N_TRIALS} trials; dotted: identified σ")),
    "wang2023cja_extra_error_vs_noise"))

# %% [markdown]
# ## wang2023cja_extra_constrained_headline — six paper positions at the identified noise level

# %%
art = w.extra_constrained_headline(b3, b2, SIGMA_DEG)
head, info = art.table, art.data
output.save_table(head, "wang2023cja_extra_constrained_headline")
output.show_table(head)
print(*art.lines, sep="\n")
assert all(g > 20.0 for g in info["gain_so4_pct"].values()) and info["gain_mount_pct"] > 0
assert info["ratio_mount_biased"] > 3.0 and info["so4_k"] <= 5

# %% [markdown]
# **When each method is better.** At the identified per-position error and the paper's six positions,
# SO(4) lowers the median attitude RMSE after calibration by about a third relative to Eq 13 whatever
# the truth, and it is defined from three positions on (Eq 13 from four, and not at all for the first
# four rows of the paper's order). Eq 13 spends 10 extra parameters on scale and shear that are pure
# noise. The mounting-only fit is better by another third *if* sensor and tunnel share the reference
# frame; if the sensor's heading reference is offset (a yaw-zeroed filter) it is biased and the worst
# of the three — use SO(4) unless the frames are known to coincide. Errors scale linearly with σ in
# this range, so the percentages hold at every noise level shown.

# %% [markdown]
# ## wang2023cja_extra_printed_matrices_so4 — the paper's printed matrices projected onto SO(4)
#
# Read as Eq 10 maps (`q_b = Q q_s`); the turntable matrix also with Q(3,3) sign-corrected. From
# `Q ≈ L(p) R(r)`: mounting `c = r*` and reference offset `w = p*` (Eq 8 angles, deg).

# %%
# NBVAL_CHECK_OUTPUT
b5 = w.extra_printed_matrices_so4().table
output.save_table(b5, "wang2023cja_extra_printed_matrices_so4")
output.show_table(b5.iloc[:, :5])
output.show_table(b5[["matrix"] + [c for c in b5.columns if c.startswith(("c_", "w_", "angle"))]])
bt, bf, bw = (b5.set_index("matrix").loc[k] for k in constrained.printed_matrices())
assert bt.det < 0 and abs(bt.det + 1.0) < 1e-3 and bt.dist_O4 < 0.002 and bt.dist_SO4 > 1.99
assert 0 < bf.det and bf.dist_SO4 < 0.01 and bf.c_angle_deg < 0.1
assert bw.det > 1.005 and 0.005 < bw.dist_SO4 < 0.006

# %% [markdown]
# The corrected turntable matrix is a rotation of quaternion space to 0.006 and implies a mounting of
# only ≈ 0.05°. The wind-tunnel matrix is 0.0054 from SO(4), mostly its 1.004462 diagonal.

# %% [markdown]
# ## wang2023cja_extra_q33_sign — what Q(3,3) = −1.000355 does to roll ±90°
#
# Table 1 "before" angles → quaternions (Eq 9) → matrix variants (Eq 10) → angles (Eq 8), compared with
# Table 1 "after". Variants: printed; Q(3,3) sign fixed; row/column 3 negated; transposes/inverse; the
# SO(4) projection of the fixed matrix.

# %%
# NBVAL_CHECK_OUTPUT
art = w.extra_q33_sign()
b6, q33 = art.table, art.data
output.save_table(b6, "wang2023cja_extra_q33_sign")
output.show_table(b6, float_format="{:.3f}")
print(f"Table 1 after: roll {q33['after_roll_deg'][0]:.3f} / {q33['after_roll_deg'][1]:.3f}; SO(4) projection vs fixed: "
      f"max change rows 1-4 {q33['proj_change_rows1_4_deg']:.3f} deg, rows 5-6 {q33['proj_change_rows5_6_deg']:.3f} deg")
v = b6.set_index("variant")
assert v.loc["printed Q", "roll_at_+90_deg"] < -89.9 and v.loc["printed Q", "max_abs_diff_rows5_6_deg"] > 179.0
assert v.loc["Q33 sign fixed", "max_abs_diff_rows1_4_deg"] < 0.06 and v["max_abs_diff_rows5_6_deg"].min() > 0.25

# %% [markdown]
# The printed matrix sends roll ±90° 180° off Table 1; fixing the sign of Q(3,3) restores roll and
# reproduces rows 1–4 within 0.06°, but no variant reproduces the ±90° rows better than ≈ 0.3°: the
# paper's "after" values are not its matrix applied to its "before" values. They come from separate
# verification runs — which is how notebooks 10 and 11 now measure "after".

# %% [markdown]
# ## wang2023cja_extra_noise_vs_so4_distance — can noise make the printed matrices non-orthogonal?
#
# Distance of the Eq 13 estimate to O(4) vs σ (paper's six positions, shared frame, Monte Carlo), with
# the printed wind-tunnel matrix and the sign-fixed turntable matrix as horizontal lines.

# %%
b7 = w.extra_noise_vs_so4_distance(levels + (0.1, 0.2, 0.5), N_TRIALS, SEED).table
output.save_table(b7, "wang2023cja_extra_noise_vs_so4_distance")
display(output.save_figure(plots.noise_distance_figure(
    b7, {"printed wind-tunnel matrix": bw.dist_O4, "turntable matrix, Q33 fixed": bf.dist_O4}, sigma_deg=SIGMA_DEG,
    title=f"wang2023cja_extra_noise_vs_so4_distance: {N_TRIALS} trials; vertical line: identified σ"),
    "wang2023cja_extra_noise_vs_so4_distance"))
output.show_table(b7, float_format="{:.5f}")
need = {name: constrained.sigma_matching_distance(b7, d)
        for name, d in (("wind tunnel", bw.dist_O4), ("turntable", bf.dist_O4))}
print(", ".join(f"{name}: median Eq 13 distance equals the printed one at sigma = {s:.3f} deg" for name, s in need.items()))
assert (b7[b7.sigma_deg <= 0.05].q22_minus_1_high < 0.0045).all()   # noise does not make Q(2,2) = 1.0045

# %% [markdown]
# **One story for Q(2,2) = 1.004462.** Both printed matrices sit about twice as far from O(4) as the
# Eq 13 estimate at the identified per-position error (the σ printed above is ≈ 2× the identified
# one). For the turntable matrix that is the remaining per-rest scatter the error model could not
# resolve (notebook 10). For the wind-tunnel matrix the non-orthogonality is concentrated on one
# entry: Q(2,2) − 1 = 0.0045, while noise at the identified level keeps |Q(2,2)| − 1 below the
# `q22_minus_1_high` column (its 97.5 % point) — even at σ = 0.05° it is below 0.0045. So Q(2,2) is not
# absorbed noise. Its cause is computed in notebook 11: a mechanism pitch-ratio error, identified from
# this diagonal; Table 9's before-slope then follows from it (not a prediction: the slope is
# ≈ −(Q(2,2) − 1) of the training matrix).

# %% [markdown]
# ## Paper vs mtcal
# Roles: the paper's "three positions suffice" is an `erratum` (computed: four are needed for Eq 13);
# the SO(4)/mounting results are our `finding`s (the paper states nothing about them); no row here is
# a prediction of a paper number, so the prediction summary has no banded paper rows. At the study's
# default settings every tested claim is asserted; with other `k_max`/noise levels they are reported.

# %%
table = compare.comparison_table(constrained.constrained_rows(b1, head, info, b5, b6, b7, SIGMA_DEG))
output.save_table(table, "wang2023cja_constrained_calibration_comparison")
output.show_table(table)
print(compare.prediction_summary(table))
print(compare.check_claims(table, enforce=AT_PAPER))

# %% [markdown]
# ## Score block
# No held-out printed number is predicted here (the printed matrices are `train`, Q(3,3) an
# `erratum`); the block gives the paper's split and the rows tested in this notebook.

# %%
print(fidelity.score_block(table, "wang2023cja"))
