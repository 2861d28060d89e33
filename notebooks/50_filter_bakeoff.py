# %% [markdown]
# # 50 — Filter × sensor bake-off on the papers' scenarios
#
# Which attitude filter, for which sensor and which tunnel vibration? This notebook
# runs the wang2023cja QNCF (the paper's filter), an IMU-only Mahony filter
# (`mtcal.filters.mahony`, Mahony, Hamel & Pflimlin, IEEE TAC 2008), Madgwick
# (`ahrs`), VQF (`vqf`, Laidig & Seel 2023) and Fusion (`imufusion`) on **the same
# simulated records** of the papers' scenarios:
#
# * **turntable** — wang2023cja AoA sweep (−4 … 13°) and roll sweep (±90°);
# * **wind tunnel** — the wang2023cja AoA sweep with the running-tunnel model
#   vibration (amplitude and frequency are parameters; 0 m/s² = wind off);
# * **movable surface** — wang2022sensors rotations about a hinge axis, the RAMS EKF
#   (`mtcal.filters.rams_ekf.run_rams_ekf`) beside the attitude filters, judged on
#   the angle about the axis;
#
# across sensor grades of the catalogue `mtcal.core.sensor_grades`. Everything runs
# through the sweep engine (`mtcal.sweep`): random streams keyed by (seed, cell,
# trial), so the numbers do not depend on the number of worker processes.
#
# Adapters (`mtcal.filters.anchors`) handle each library's units (imufusion takes
# °/s and g; ahrs and vqf rad/s and m/s²), quaternion order, frame and sample timing;
# all filters start from the same levelled attitude. The external libraries are an
# optional extra: a missing one is skipped with a message.
#
# Errors are medians over the trials with a band whose kind and count every table
# states (`trials`, `band` columns; legends and labels): mtcal's own filters (QNCF,
# Mahony, RAMS EKF: batched, compiled) run `N_TRIALS` = 1000 trials per scenario and get
# a **95 % band**; the third-party anchors run fewer trials (`ANCHOR_TRIALS`: VQF and Fusion 12,
# Madgwick 3 — the count set when it ran through `ahrs`' pure-Python loop, ~25 µs per sample;
# it now runs through mtcal's compiled equivalent of that loop, checked against `ahrs` below)
# and get the **range** (min–max) of their trials, never called a 95 % band. Trial j is the same
# simulated record for every filter that runs it. The metric is the RMS tilt error
# (angle between estimated and true "up", yaw-free) after the 3 s settling rest, and
# for the surface the RMS error of the angle about the hinge axis.

# %% tags=["parameters"]
SIZE = None          # "ci" or "full"; None → $MTCAL_SIZE, else "full"
SEED = 2026          # RNG seed of the evaluation runs (tuning uses SEED + 1)
N_TRIALS = None      # None → the size's default (evaluation trials per scenario of every filter ...)
N_TUNING_TRIALS = None  # None → the size's default (tuning trials per cell)
ANCHOR_TRIALS = None    # ... except these: {filter: trials}; None → the size's default (slow third-party anchors)
ANCHOR_TUNING_TRIALS = None  # {filter: tuning trials}; None → the size's default
WORKERS = None       # local worker processes; None → every core
# scenario (defaults = mtcal.sweep.bakeoff.BAKEOFF_DEFAULTS; names carry units)
filters = ["qncf", "mahony", "madgwick", "vqf", "fusion"]
turntable_motions = ["aoa", "roll"]
turntable_grades = ["wang2023cja", "industrial", "consumer"]
windtunnel_grades = ["wang2023cja", "industrial"]
vibration_levels_m_s2 = [0.0, 1.0, 3.0]
vibration_hz = 45.0
surface_grades = ["wang2022sensors", "industrial"]
surface_vibration_m_s2 = [0.0, 2.0]
fs_hz = 200.0
gain_scales = [0.1, 0.3, 1.0, 3.0, 10.0]

# %%
import os

from IPython.display import display

from mtcal.filters.anchors import available_filters
from mtcal.reporting import compare
from mtcal.reporting import output
from mtcal.sweep import bakeoff
from mtcal.sweep.executors import make_executor

output.setup_matplotlib()
SIZE = output.run_size(SIZE)
N_TRIALS = N_TRIALS or {"ci": 2, "full": 1000}[SIZE]
N_TUNING_TRIALS = N_TUNING_TRIALS or {"ci": 1, "full": 20}[SIZE]
ANCHOR_TRIALS = ANCHOR_TRIALS or {"ci": {}, "full": {"vqf": 12, "fusion": 12, "madgwick": 3}}[SIZE]
ANCHOR_TUNING_TRIALS = ANCHOR_TUNING_TRIALS or {"ci": {}, "full": {"vqf": 4, "fusion": 4, "madgwick": 1}}[SIZE]
HOLD_S = {"ci": 0.5, "full": None}[SIZE]          # CI: 0.5 s holds (None → each motion's own holds)
WORKERS = WORKERS or (1 if SIZE == "ci" else os.cpu_count())
values = dict(filters=filters, turntable_motions=turntable_motions, turntable_grades=turntable_grades,
              windtunnel_grades=windtunnel_grades, vibration_levels_m_s2=vibration_levels_m_s2,
              vibration_hz=vibration_hz, surface_grades=surface_grades,
              surface_vibration_m_s2=surface_vibration_m_s2, fs_hz=fs_hz, gain_scales=gain_scales)
at_defaults = compare.at_paper_settings(values, bakeoff.BAKEOFF_DEFAULTS)
missing = [f for f in filters if f not in available_filters()]
if missing:
    print(f"skipped (optional library not installed): {missing}; pip install 'mtcal[dev]' to include them")
values["filters"] = [f for f in filters if f not in missing]
params = bakeoff.bakeoff_params(**values)
scales = params["gain_scales"] if SIZE == "full" else [s for s in params["gain_scales"] if 0.3 <= s <= 3.0]
tuning_params = {**params, "gain_scales": scales}

# %% [markdown]
# ## Fair tuning — wang2023cja_extra_bakeoff_tuning
#
# Every filter has one gain (QNCF and Mahony: K_p with K_i = K_p/50 s; Madgwick: β;
# VQF: τ_acc; Fusion: gain; RAMS EKF: σa,moving). A tuning sweep on a **separate seed**
# (`SEED + 1`) multiplies each filter's default gain by each of the gain scales, on the
# family's reference conditions (the paper's sensor; wind off and the strongest
# vibration for the tunnel); for every filter and family independently the scale
# with the smallest summed median error is kept (`tuning_trials` trials per cell: 20
# for mtcal's filters, fewer for the slow anchors; at CI size only the scales
# 0.3 … 3 and one tuning trial are used). The AMD threshold of QNCF stays at the
# paper's 0.3 % g; the other libraries keep their defaults (VQF's rest detection and
# bias estimation, Fusion's 10° acceleration rejection).

# %%
executor = make_executor(WORKERS)   # one set of worker processes for the tuning and the evaluation runs
gains, tuning = bakeoff.tune_gains(tuning_params, seed=SEED + 1, trials=N_TUNING_TRIALS,
                                   filter_trials=ANCHOR_TUNING_TRIALS, hold_s=HOLD_S, executor=executor)
output.save_table(tuning, "wang2023cja_extra_bakeoff_tuning")
chosen = tuning[tuning.chosen][["family", "filter", "gain_unit", "gain_scale", "gain", "tuning_error_deg",
                                "tuning_trials", "at_grid_edge"]]
output.show_table(chosen)
print(f"{int(chosen.at_grid_edge.sum())} of {len(chosen)} chosen gains sit at an end of the scale grid "
      f"{scales} (the optimum may lie beyond it)")

# %% [markdown]
# ## Evaluation runs
#
# Each family's grid (scenario × sensor grade × vibration) runs every filter with its
# tuned gain on records drawn from `SEED`, `N_TRIALS` trials per scenario (the anchors:
# `ANCHOR_TRIALS`); all filters see the same record in a trial, so the *paired*
# comparison (share of the trials both filters ran in which one beats the other) is
# meaningful.

# %%
result = bakeoff.run_bakeoff(params, gains, seed=SEED, trials=N_TRIALS, filter_trials=ANCHOR_TRIALS, hold_s=HOLD_S,
                             executor=executor)
executor.close()
counts = {f: ANCHOR_TRIALS.get(f, N_TRIALS) for f in params["filters"] + ["rams_ekf"]}
print("trials per scenario: " + ", ".join(f"{f} {n}" for f, n in counts.items()) + " (rams_ekf: surface only); "
      f"band = 95 % band from >= {bakeoff.BAND_MIN_TRIALS} trials, else the range (min-max)")

# %% [markdown]
# ### The compiled anchor against its library
#
# `ahrs`' Madgwick filter is a per-sample Python loop; the bake-off runs mtcal's compiled
# equivalent of it (`mtcal.filters.xio_ahrs.madgwick`: the same update, inputs and start,
# ≈ 1/500 of the CPU). Here `ahrs` itself runs again on the first scenario cell of every
# family — trial 0, the bake-off's own record — and every metric must agree within
# `REFERENCE_TOLERANCE_DEG`, so the comparison is still with the library's filter.

# %%
check = bakeoff.reference_check(params, gains, seed=SEED, hold_s=HOLD_S)
print(f"compiled anchors re-run through their library: {sorted(set(check['filter']))} on "
      f"{check.scenario.nunique()} scenario cells; {int(check.equal.sum())} of {len(check)} metrics equal within "
      f"{bakeoff.REFERENCE_TOLERANCE_DEG:g} deg")
assert check.equal.all(), check[~check.equal].to_string()

# %% [markdown]
# ## wang2023cja_extra_bakeoff_turntable — AoA and roll sweeps across sensor grades
#
# wang2023cja's turntable: 8-position AoA sweep at 4 °/s and roll sweep at 20 °/s with
# holds; the paper's sensor (`wang2023cja`, tactical MEMS) and the catalogue's
# industrial and consumer grades. On a turntable ‖a‖ ≈ g throughout, so QNCF's
# AMD gate stays open and QNCF behaves as the same PI law without it (Mahony) —
# unless the accelerometer's bias alone exceeds the 0.3 % g threshold (consumer
# grade: 20 mg turn-on bias), which keeps the gate shut and leaves QNCF integrating
# the gyro.

# %%
output.save_table(result.tables["turntable"], "wang2023cja_extra_bakeoff_turntable")
display(output.save_figure(bakeoff.bakeoff_figure(result, "turntable"), "wang2023cja_extra_bakeoff_turntable"))

# %% [markdown]
# ## wang2023cja_extra_bakeoff_windtunnel — with and without the running-tunnel vibration
#
# The same AoA mechanism (2 °/s, wind-tunnel angles −4 … 12°) with a sinusoidal model
# vibration on the accelerometer (`vibration_levels_m_s2` at `vibration_hz`, random
# phase per axis and trial). The vibration averages to zero, but a filter that
# normalises each accelerometer sample and feeds the direction error straight into
# its correction (Mahony, Fusion without rejection) rectifies it into a tilt bias;
# QNCF's AMD gate switches the correction off; VQF low-pass filters the acceleration
# *before* using its direction.

# %%
output.save_table(result.tables["windtunnel"], "wang2023cja_extra_bakeoff_windtunnel")
display(output.save_figure(bakeoff.bakeoff_figure(result, "windtunnel"), "wang2023cja_extra_bakeoff_windtunnel"))

# %% [markdown]
# ## wang2022sensors_extra_bakeoff_surface — angle about a hinge axis
#
# wang2022sensors' movable surface: steps of 30° between −60° and +60° about the Fig. 11
# axis at 20 °/s, 1 s holds, sensor 0.2 m from the hinge (tangential and centripetal
# acceleration while moving). The RAMS EKF knows the axis (its A1 estimate is
# replaced by the true axis here), takes ā0 from the settling rest and the schedule's
# rest flags as its ZVD input; the attitude filters are judged on the twist of their
# attitude about the same axis.

# %%
output.save_table(result.tables["surface"], "wang2022sensors_extra_bakeoff_surface")
display(output.save_figure(bakeoff.bakeoff_figure(result, "surface"), "wang2022sensors_extra_bakeoff_surface"))

# %% [markdown]
# ## wang2023cja_extra_bakeoff_headline — who wins where, and by how much
#
# Per scenario: the filter with the smallest median error, its band (`winner_band`
# names it: 95 % band or range, and its trial count), the runner-up, the ratio of their
# medians and the paired win fraction over the trials both ran (`paired_trials`, same
# records), plus QNCF's median and rank. A winner decided against an anchor rests on the
# anchor's few trials (`runner_up_trials`). **`resolved`** says whether the ranking is more than a
# coin flip: the Wilson 95 % interval of the paired win fraction lies above ½ (`verdict` gives
# the count and the interval); an unresolved winner is only the smaller median, not a win.

# %%
headline = bakeoff.headline_table(result)
output.save_table(headline, "wang2023cja_extra_bakeoff_headline")
output.show_table(headline)

# %%
for _, r in headline.iterrows():
    print(f"{r.family:10s} {r.scenario:40s} {r.winner:8s} wins ({r.winner_median_deg:.4f} deg, "
          f"{r.winner_band} [{r.winner_low_deg:.4f}, {r.winner_high_deg:.4f}]) by {r.ratio:.2f}x over "
          f"{r.runner_up} ({r.runner_up_trials} trials; paired {100 * r.paired_win_fraction:.0f} % of "
          f"{r.paired_trials}); QNCF rank {r.qncf_rank}; {r.verdict}")
print(f"resolved rankings: {int(headline.resolved.sum())} of {len(headline)}")

# %% [markdown]
# Reading the table (full size: mtcal's filters over 1000 trials with 95 % bands; VQF and
# Fusion over 12 and Madgwick over 3 trials, with their ranges — a ranking decided against
# an anchor rests on those few trials; at CI size, with 2 trials, the close races change
# order). "Smallest median" is not "wins": only the cells whose `resolved` is true beat
# their runner-up on the same records beyond a coin flip (the last line above counts them;
# a 3-trial anchor never resolves a ranking):
#
# * **Turntable, tactical sensors** (`wang2023cja`): QNCF, Mahony, VQF and Fusion are
#   within about 25 % of each other (a few thousandths of a degree; Fusion has the
#   smallest median, on 12 trials), Madgwick about 1.5× higher (3 trials). QNCF and
#   Mahony give the same number when tuned alike: on a turntable the AMD gate stays open.
# * **Industrial grade**: the 2 mg accelerometer bias (≈ 0.1°) sets the error of every
#   filter (medians 0.11–0.19°).
# * **Consumer grade**: the sensor sets the error (≈ 1° from the 20 mg accelerometer
#   bias) for Mahony, Madgwick, VQF and Fusion alike — but QNCF is last: its gate
#   threshold (0.3 % g = 3 mg) is below the accelerometer's own bias, so the gate
#   stays shut and QNCF integrates the 0.1 °/s gyro bias. QNCF's Thr assumes a
#   calibrated tactical accelerometer.
# * **Running tunnel**: Mahony's tilt error grows by two orders of magnitude with the
#   vibration (rectification of the normalised accelerometer direction); QNCF's gate
#   removes most of it (gyro-only during the run), and VQF — which low-pass filters the
#   acceleration before taking its direction — removes it while keeping the
#   correction: VQF has the smallest wind-on median with the paper's sensor, about an
#   order of magnitude below QNCF's at 3 m/s² (12 VQF trials; against the runner-up
#   Madgwick, 3 trials, the ranking is not resolved). **Wind off**, VQF's median is about
#   4–5× QNCF's: its rest detector (default 2 °/s) flags about 30 % of the 2 °/s
#   mechanism moves as rest and learns their rate as gyro bias (with VQF's rest bias
#   estimation off its wind-off error drops from 0.020° to 0.0035°; checked outside
#   this notebook on 4 trials). The "gate wins by ≥ 3× in every trial" finding, drawn
#   from 12 trials, does not hold over 1000: the comparison table gives the share.
# * **Movable surface**: with the paper's sensor the 1-DOF RAMS EKF (which knows the
#   hinge axis) has the smallest median with and without vibration (resolved against
#   VQF's 12 trials without vibration only: see `verdict`); under vibration
#   QNCF's gate shuts and the 0.7 °/s gyro bias of the wang2022sensors sensor puts it
#   among the worst, whereas with the industrial gyro (30 °/h) gyro-only integration
#   is the best choice.

# %% [markdown]
# ## Comparison table (mtcal findings)
#
# The bake-off has no paper numbers; its robust statements are mtcal findings
# (`role = finding`), asserted at the default parameters and reported in a what-if run.

# %%
rows = bakeoff.findings(result, headline)
table = compare.comparison_table(rows)
output.save_table(table, "wang2023cja_extra_bakeoff_comparison")
output.show_table(table[["artifact", "quantity", "mtcal", "claim", "holds"]])
print(compare.claims_summary(table))
for r in table[table.holds.notna() & ~table.holds.fillna(True).astype(bool)].itertuples():
    print(f"not holding: {r.quantity}: {r.claim} — {r.note}")

# %%
print(compare.check_claims(table, enforce=at_defaults))
