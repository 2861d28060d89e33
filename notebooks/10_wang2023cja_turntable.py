# %% [markdown]
# # wang2023cja — installation-error calibration on the turntable (Tables 1–8, Figs 7–8)
#
# Wang et al. (CJA 2023): QNCF attitude (Eq 5–8, PI correction gated by the AMD), least-squares
# error quaternion matrix (Eq 10–13), six-position procedure (§3.2). Hardware is replaced by
# simulation (`mtcal.studies.wang2023cja.runs`): the turntable is a truth trajectory, the IMU is
# `mtcal.core.simulate` with a named error budget, the installation error is a mounting rotation whose
# angles are **fitted to the paper's "before" columns**. Rests are found from the data
# (`mtcal.methods.six_position`), never from the schedule.

# %% tags=["parameters"]
import os
SEED = 2023
SIZE = os.environ.get("MTCAL_SIZE", "full")   # "ci" under make test
N_MC = 100 if SIZE == "full" else 10          # Monte Carlo seeds per test (bands of every MC row)
N_BUDGET = 8 if SIZE == "full" else 1         # trials per error-budget row
BUDGET_SWEEPS = SIZE == "full"                # budget also evaluates the AoA sweep (one extra long QNCF run)

# %%
import numpy as np
import pandas as pd
from mtcal.reporting import output as report, paper_numbers as paper
from mtcal.reporting import compare
from mtcal.core import metrics, rotations
from mtcal.studies import wang2023cja as s
report.setup_matplotlib()
P = s.PAPER_SIGN
sc = s.TurntableScenario()
rng = np.random.default_rng(SEED)
rng_main, rng_mc, rng_budget = rng.spawn(3)
deg = np.degrees
mc_records = []   # Monte Carlo bands of the key numbers (wang2023cja_extra_mc_bands)
rows_cmp = []     # paper-vs-mtcal rows

# %% [markdown]
# ## Scenario and sensor model (every value with unit and source)

# %%
report.show_table(compare.describe(sc.imu))
report.show_table(compare.describe(sc))

# %% [markdown]
# ## Installation angles fitted to the "before" columns of Tables 1–4
#
# Model: zeroed QNCF output `q_s = q_bs⁻¹ ⊗ q_wb ⊗ q_bs` (the paper's initial attitude angles are 0°),
# Eq 1 angles α1 (yaw axis z), α2 (roll axis y), α3 (pitch axis x). With Eq 8/9 as printed the fit
# explains almost nothing; with the paper's roll sign flipped (a handedness change — the same
# family as the printed Q(3,3) = −1) the residual drops several-fold. That is itself a result.

# %%
# NBVAL_CHECK_OUTPUT
rows = []
for test, table in s.TABLES_1_TO_4.items():
    proper = s.fit_installation_angles(table, sign=(1, 1, 1))
    flipped = s.fit_installation_angles(table)
    a = deg(flipped.alpha_rad)
    rows.append({"test": test, "raw_rms_deg": flipped.raw_rms_deg, "fit_rms_eq8_as_printed_deg": proper.rms_deg,
                 "fit_rms_roll_flipped_deg": flipped.rms_deg, "alpha1_deg": a[0], "alpha2_deg": a[1], "alpha3_deg": a[2]})
fit_table = pd.DataFrame(rows)
report.save_table(fit_table, "wang2023cja_extra_installation_fit")
report.show_table(fit_table)
assert (fit_table.fit_rms_roll_flipped_deg < 0.4 * fit_table.fit_rms_eq8_as_printed_deg).all()

# %% [markdown]
# ## The printed turntable matrix: Q(3,3) = −1.000355
# Computed facts: its determinant is negative (an improper map of quaternion space), and applied
# to Eq 9 quaternions of pure roll ±90° it returns roll ∓90° (180° off), while with +1.000355 roll is
# kept. The q2 row is the roll-axis (y) component: negating it is exactly a roll sign flip — the
# same handedness change the installation fit above needs.

# %%
# NBVAL_CHECK_OUTPUT
Qp = paper.load("wang2023cja_matrix_qbs_turntable")[["col_1", "col_2", "col_3", "col_4"]].to_numpy(float)
Qfix = Qp.copy(); Qfix[2, 2] = -Qfix[2, 2]
print(f"det(printed) = {np.linalg.det(Qp):+.6f}, det(Q33 sign fixed) = {np.linalg.det(Qfix):+.6f}")
for roll in (90.0, -90.0):
    q = rotations.quat_from_euler_zxy(0.0, 0.0, np.radians(roll))
    for name, Q in (("printed", Qp), ("Q33 +", Qfix)):
        out = Q @ q
        e = deg(rotations.euler_zxy_from_quat(out / np.linalg.norm(out)))
        print(f"roll {roll:+5.0f} deg -> {name:8s}: yaw {e[0]:+8.3f} pitch {e[1]:+8.3f} roll {e[2]:+8.3f}")

# %% [markdown]
# ## Runs: T1 with the AoA and roll sweeps after calibration, T2–T4 calibration only (Monte Carlo; trial 0 shown)
# All Monte Carlo sets that share a trajectory share one QNCF run (`s.run_turntable_jobs` stacks them
# along the trial axis; each set keeps its own generator). The error-budget sets of the last section
# are run here too.

# %%
# Monte Carlo over N_MC seeds per test; trial 0 is the "single run" shown in the tables and figures
rng_tests = {test: rng_mc.spawn(1)[0] for test in ("T1", "T2", "T3", "T4")}
budget_configs = [("none", ())] + [(src, (src,)) for src in s.SOURCES] + [("all", s.SOURCES)]
budget_jobs = [s.TurntableJob("T1", rng_budget.spawn(1)[0], N_BUDGET, srcs) for _, srcs in budget_configs]
FRACTIONS = (0.1, 0.9)
fraction_jobs = [s.TurntableJob("T1", rng_budget.spawn(1)[0], N_BUDGET, s.SOURCES, frac) for frac in FRACTIONS]
cal_jobs = [s.TurntableJob(test, rng_tests[test], N_MC) for test in ("T2", "T3", "T4")] + fraction_jobs
if not BUDGET_SWEEPS:
    cal_jobs += budget_jobs
mc = {"T1": s.run_turntable_jobs(sc, [s.TurntableJob("T1", rng_tests["T1"], N_MC)], with_sweeps=True,
                                 keep_trace=True)[0]}
cal_runs = s.run_turntable_jobs(sc, cal_jobs)
mc.update(zip(("T2", "T3", "T4"), cal_runs[:3]))
fraction_runs = cal_runs[3:3 + len(FRACTIONS)]
budget_runs = (s.run_turntable_jobs(sc, budget_jobs, with_sweeps=True) if BUDGET_SWEEPS
               else cal_runs[3 + len(FRACTIONS):])
runs = mc


# %%
def position_table(test):
    df = paper.load(s.TABLES_1_TO_4[test])
    r = runs[test]
    rows = []
    for k in range(6):
        for j, ang in enumerate(("yaw", "pitch", "roll")):
            rows.append({"pos": k + 1, "angle": ang, "reference": df[f"{ang}_reference_deg"][k],
                         "paper_before": df[f"{ang}_before_deg"][k], "mtcal_before": P[j] * deg(r.cal_before[0, k, j]),
                         "paper_after": df[f"{ang}_after_deg"][k], "mtcal_after": P[j] * deg(r.cal_after[0, k, j])})
    return pd.DataFrame(rows)


def rms_err(x, ref):
    return float(np.sqrt(np.mean((x - ref) ** 2)))


tables = {test: position_table(test) for test in ("T1", "T2", "T3", "T4")}

# %% [markdown]
# ## wang2023cja_table01 — six positions, normal installation (Table 1)
# The table shows trial 0; the comparison rows use the Monte Carlo median of the RMS error over the
# 18 angles with its 95 % band. "After closer to reference" is tested on the bands: the whole after
# band must lie below the before band.

# %%
def show_positions(test, art):
    t = tables[test]
    report.save_table(t, art)
    report.show_table(t, "{:.3f}")
    rms = {state: np.sqrt(np.mean(s.position_errors_deg(mc[test], state) ** 2, axis=(1, 2))) for state in ("before", "after")}
    rec_b = compare.band_record(art, "RMS |before-ref| (deg)", rms_err(t.paper_before, t.reference), rms["before"])
    rec_a = compare.band_record(art, "RMS |after-ref| (deg)", rms_err(t.paper_after, t.reference), rms["after"])
    print(compare.band_text(rec_b)); print(compare.band_text(rec_a))
    holds = rec_a["high"] < rec_b["low"]
    rows_cmp.append(compare.band_row(rec_b, "-", None))
    rows_cmp.append(compare.band_row(rec_a, "after closer to reference than before (95 % bands apart)", holds))
    mc_records.append(compare.band_record(art, "max |after-ref| at 6 positions (deg)",
                                    np.abs(t.paper_after - t.reference).max(),
                                    np.abs(s.position_errors_deg(mc[test], "after")).max(axis=(1, 2))))
    return holds

assert show_positions("T1", "wang2023cja_table01")

# %% [markdown]
# ## wang2023cja_table02 — large pitch installation error (Table 2)

# %%
assert show_positions("T2", "wang2023cja_table02")

# %% [markdown]
# ## wang2023cja_table03 — large pitch and roll installation errors (Table 3)

# %%
assert show_positions("T3", "wang2023cja_table03")

# %% [markdown]
# ## wang2023cja_table04 — all three installation errors large (Table 4)

# %%
assert show_positions("T4", "wang2023cja_table04")

# %% [markdown]
# ## wang2023cja_table05 — AoA sweep, mean pitch (Table 5)

# %%
def sweep_mean_section(art, table, angle, name, paper_max, claims, sign=1.0):
    """Hold-mean table (trial 0) and Monte Carlo bands of max |mean-ref|; claims: state -> (text, limit deg)."""
    t = s.sweep_mean_table(table, angle, runs["T1"].sweeps[name], sign=sign)
    report.save_table(t, art)
    report.show_table(t, "{:.3f}")
    recs = s.sweep_mean_records(art, angle, paper_max, mc["T1"].sweeps[name])
    for state, (claim, limit) in claims.items():
        print(compare.band_text(recs[state]))
        rows_cmp.append(compare.band_row(recs[state], claim, recs[state]["median"] <= limit))
    mc_records.append(recs["after"])
    return recs


sw, msw = runs["T1"].sweeps["aoa"], mc["T1"].sweeps["aoa"]
recs5 = sweep_mean_section("wang2023cja_table05", "wang2023cja_table05_aoa_sweep_mean_pitch", "pitch", "aoa", {"before": 0.04, "after": 0.025},
                           {"before": ("before up to 0.04 deg", 0.045), "after": ("after within 0.03 deg", 0.03)})
assert recs5["after"]["median"] <= 0.03

# %% [markdown]
# ## wang2023cja_fig07 — roll and yaw errors during the AoA sweep, before vs after

# %%
tr = runs["T1"].trace
fig = s.plot_before_after(tr, "aoa", ((2, "roll"), (0, "yaw")), xlabel="time in AoA sweep (s)",
                          title="wang2023cja_fig07: stepwise coupling errors (pitch motion into roll/yaw)")
report.save_figure(fig, "wang2023cja_fig07")

# %% [markdown]
# ## wang2023cja_table06 — MaxAE / RMSE of roll and yaw in the AoA sweep (Table 6), with Monte Carlo band

# %%
t6 = s.show_error_metric_table("wang2023cja_table06", "wang2023cja_table06_aoa_sweep_roll_yaw_errors", msw, ((2, "roll"), (0, "yaw")))
for j, ang in ((2, "roll"), (0, "yaw")):
    pv = t6[(t6.metric == "RMSE") & (t6.state == "after") & (t6.angle == ang)].paper.iloc[0]
    rec = compare.band_record("wang2023cja_table06", f"{ang} RMSE after (deg)", pv, deg(msw[f"after_rmse_{j}"]))
    rows_cmp.append(compare.band_row(rec, "after RMSE <= 0.01 deg", rec["median"] <= 0.01))
for _, r in t6[t6.state == "after"].iterrows():
    mc_records.append({"artifact": "wang2023cja_table06", "quantity": f"{r.angle} {r.metric} after (deg)", "paper": r.paper,
                       "median": r.mc_median, "low": r.mc_low, "high": r.mc_high, "paper_in_band": r.paper_in_band})
yaw_ok = float(np.mean(deg(msw["after_rmse_0"]) <= 0.01))
print(f"fraction of seeds with yaw RMSE after <= 0.01 deg: {yaw_ok:.2f}")
rec_roll = compare.band_record("wang2023cja_table06", "roll RMSE before (deg)", 0.029, deg(msw["before_rmse_2"]))
roll_after_median = float(np.median(deg(msw["after_rmse_2"])))
rows_cmp.append(compare.band_row(rec_roll, "after < before (MC medians)", roll_after_median < rec_roll["median"]))
assert roll_after_median < rec_roll["median"]

# %% [markdown]
# **Where the claim fails:** the after-calibration *yaw* RMSE is ≈ 0.01° (MC median 0.010–0.017°
# depending on the seeds; the fraction of runs meeting 0.01° is printed above), so the claim holds in
# some runs and not in others and is not asserted.
# Yaw is not observable by the accelerometer; it integrates gyro white noise, bias instability and
# the residual turn-on/warm-up bias from the QNCF start through calibration into the sweep (about
# 1.5 min). With the assumed 0.1 °/√h ARW and 0.8 °/h instability, the paper's 0.009° is inside
# our band but the median is not below 0.01°: the claim is sensor-grade dependent, not a property
# of the calibration. Roll (accelerometer-referenced) meets it with a wide margin.

# %% [markdown]
# ## wang2023cja_table07 — roll sweep, mean roll (Table 7)

# %%
sr, msr = runs["T1"].sweeps["roll"], mc["T1"].sweeps["roll"]
recs7 = sweep_mean_section("wang2023cja_table07", "wang2023cja_table07_roll_sweep_mean_roll", "roll", "roll", {"before": 0.052, "after": 0.038},
                           {"before": ("before within 0.06 deg", 0.06), "after": ("after within 0.04 deg", 0.04)}, sign=P[2])
assert recs7["after"]["median"] <= 0.04

# %% [markdown]
# ## wang2023cja_fig08 — pitch and yaw errors in the roll sweep, before vs after

# %%
fig = s.plot_before_after(tr, "roll", ((1, "pitch"), (0, "yaw")), xlabel="time in roll sweep (s)",
                          title="wang2023cja_fig08: roll motion coupled into pitch and yaw")
report.save_figure(fig, "wang2023cja_fig08")

# %% [markdown]
# ## wang2023cja_table08 — MaxAE / RMSE of pitch and yaw in the roll sweep (Table 8)
# Reductions (1 − after/before) per seed. The claim is tested per run on the smallest of the four
# reductions of that run: the median run must reduce all four errors by 30 % or more, and so must
# at least 80 % of the runs. Not every run does: when the gyro-only yaw drifts strongly during the
# sweep, the yaw reduction of that run falls below 30 % (1 run in 10 for two of the four CI seeds
# tried; the fraction of runs is printed). The 2.5 % point of the band is therefore not asserted —
# with the 10 CI seeds it is an interpolation next to the worst seed.

# %%
p8 = paper.load("wang2023cja_table08_roll_sweep_pitch_yaw_errors")
rows8, red_runs = [], []
for metric, key in (("MaxAE", "maxae"), ("RMSE", "rmse")):
    for j, ang in ((1, "pitch"), (0, "yaw")):
        pb = float(p8.loc[(p8.metric == metric) & (p8.calibration_state == "before"), f"{ang}_deg"].iloc[0])
        pa = float(p8.loc[(p8.metric == metric) & (p8.calibration_state == "after"), f"{ang}_deg"].iloc[0])
        red = 100 * (1 - msr[f"after_{key}_{j}"] / msr[f"before_{key}_{j}"])
        red_runs.append(red)
        band = metrics.percentile_band(red)
        rows8.append({"metric": metric, "angle": ang, "paper_before": pb, "paper_after": pa,
                      "mtcal_before": deg(sr[f"before_{key}_{j}"][0]), "mtcal_after": deg(sr[f"after_{key}_{j}"][0]),
                      "paper_reduction_pct": 100 * (1 - pa / pb), "mc_reduction_median_pct": band["median"],
                      "mc_reduction_low_pct": band["low"]})
t8 = pd.DataFrame(rows8)
report.save_table(t8, "wang2023cja_table08")
report.show_table(t8, "{:.3f}")
rec8 = compare.band_record("wang2023cja_table08", "smallest of 4 reductions per run (%)", t8.paper_reduction_pct.min(),
                     np.min(red_runs, axis=0))
print(compare.band_text(rec8, digits=1))
frac_ok8 = float(np.mean(np.min(red_runs, axis=0) >= 30))
print(f"fraction of runs with all four reductions >= 30 %: {frac_ok8:.2f}")
holds8 = bool(rec8["median"] >= 30 and frac_ok8 >= 0.8)
rows_cmp.append(compare.band_row(rec8, ">= 30 % reduction (all four; median run, >= 80 % of runs)", holds8))
for j, ang in ((1, "pitch"), (0, "yaw")):
    pa = float(t8[(t8.metric == "RMSE") & (t8.angle == ang)].paper_after.iloc[0])
    mc_records.append(compare.band_record("wang2023cja_table08", f"{ang} RMSE after (deg)", pa, deg(msr[f"after_rmse_{j}"])))
assert holds8

# %% [markdown]
# ## Monte Carlo bands of the key after-calibration numbers
# Median and 95 % interval over N_MC seeds (sensor noise, turn-on biases, turntable positioning),
# and whether the paper's number lies inside.

# %%
bands = pd.DataFrame(mc_records)
report.save_table(bands, "wang2023cja_extra_mc_bands")
report.show_table(bands)
print(f"{int(bands.paper_in_band.sum())} of {len(bands)} paper numbers inside the 95 % band")

# %% [markdown]
# ## Error budget — one source at a time (T1)
# Each row switches on a single named source (independent child generators per source, so the
# draws of the other sources do not change). "all" is the full model. The averaging-window rows
# repeat "all" with a different middle fraction of each 3 s rest. (Runs: see the Runs cell.)

# %%
def budget_row(name, r):
    err = np.abs(s.position_errors_deg(r, "after"))
    row = {"source": name, "cal_after_rms_deg": float(np.sqrt(np.mean(err**2))), "cal_after_max_deg": float(err.max())}
    if r.sweeps is not None:
        row["aoa_roll_rmse_after_deg"] = float(np.median(deg(r.sweeps["aoa"]["after_rmse_2"])))
        row["aoa_yaw_rmse_after_deg"] = float(np.median(deg(r.sweeps["aoa"]["after_rmse_0"])))
    return row


budget = pd.DataFrame([budget_row(name, r) for (name, _), r in zip(budget_configs, budget_runs)]
                      + [budget_row(f"all, averaging fraction {frac}", r) for frac, r in zip(FRACTIONS, fraction_runs)])
report.save_table(budget, "wang2023cja_extra_error_budget")
report.show_table(budget, "{:.5f}")
assert budget.loc[budget.source == "none", "cal_after_max_deg"].iloc[0] < 1e-6   # noise-free is exact

# %% [markdown]
# Reading the budget: gyro white noise and bias instability dominate (yaw is gyro-only and leaks
# into the other channels through Q̂), then turntable positioning (5″) and accelerometer bias. The
# 0.01–0.27° "after" residuals of the paper's Tables 1–4 are 3–50× larger than any modelled source:
# our bands do not contain most of them. The paper's residuals must contain effects not modelled
# here (turntable axis wobble, IMU mounting flexure when the gaskets are used in T2–T4, yaw drift
# over a longer procedure, or the sign-convention issue above).
#
# ## Paper vs mtcal
# `mtcal` is the Monte Carlo median where a band is given (95 % interval in `mc_band`).

# %%
cmp = compare.comparison_table(rows_cmp)
report.save_table(cmp, "wang2023cja_turntable_comparison")
report.show_table(cmp)
print(compare.claims_summary(cmp))
print(compare.band_summary(cmp))
