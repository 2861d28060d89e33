# %% [markdown]
# # Seed 000 — installation-error calibration on the turntable (Tables 1–8, Figs 7–8)
#
# Wang et al. (CJA 2023): QNCF attitude (Eq 5–8, PI correction gated by the AMD), least-squares
# error quaternion matrix (Eq 10–13), six-position procedure (§3.2). Hardware is replaced by
# simulation (`mtcal.scenarios000`): the turntable is a truth trajectory, the IMU is
# `mtcal.simulate` with a named error budget, the installation error is a mounting rotation whose
# angles are **fitted to the paper's "before" columns**. Rests are found from the data
# (`mtcal.sixpos`), never from the schedule.

# %% tags=["parameters"]
import os
SEED = 2023
SIZE = os.environ.get("MTCAL_SIZE", "full")   # "ci" under make test
N_MC = 100 if SIZE == "full" else 10          # Monte Carlo seeds for the bands
N_BUDGET = 8 if SIZE == "full" else 1         # trials per error-budget row
BUDGET_SWEEPS = SIZE == "full"                # budget also evaluates the AoA sweep (slow)

# %%
import numpy as np
import pandas as pd
import matplotlib.pyplot as plt
from IPython.display import display
from mtcal import report, paper, metrics, rotations, scenarios000 as s
report.setup_matplotlib()
P = s.PAPER_SIGN
sc = s.TurntableScenario()
rng = np.random.default_rng(SEED)
rng_main, rng_mc, rng_budget = rng.spawn(3)
deg = np.degrees

# %% [markdown]
# ## Scenario and sensor model (every value with unit and source)

# %%
report.show_table(s.describe(sc.imu))
report.show_table(s.describe(sc))

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
report.save_table(fit_table, "T000-fit")
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
Qp = paper.load("seed000_matrix_qbs_turntable")[["col_1", "col_2", "col_3", "col_4"]].to_numpy(float)
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

# %%
# Monte Carlo over N_MC seeds; trial 0 is the "single run" shown in the tables and figures
mc = {"T1": s.run_turntable_mc(sc, "T1", rng_mc.spawn(1)[0], N_MC, with_sweeps=True, keep_trace=True)}
for test in ("T2", "T3", "T4"):
    mc[test] = s.run_turntable_mc(sc, test, rng_mc.spawn(1)[0], N_MC)
runs = mc


# %%
def position_table(test):
    table = s.TABLES_1_TO_4[test]
    df = paper.load(table)
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


rows_cmp = []
tables = {}
for i, test in enumerate(("T1", "T2", "T3", "T4"), start=1):
    tables[test] = position_table(test)

# %% [markdown]
# ## T000-1 — six positions, normal installation (Table 1)

# %%
def show_positions(test, art):
    t = tables[test]
    report.save_table(t, art)
    report.show_table(t, "{:.3f}")
    pb, pa = rms_err(t.paper_before, t.reference), rms_err(t.paper_after, t.reference)
    mb, ma = rms_err(t.mtcal_before, t.reference), rms_err(t.mtcal_after, t.reference)
    band = metrics.percentile_band(np.sqrt(np.mean((mc[test].cal_after - mc[test].reference) ** 2, axis=(1, 2))) * 180 / np.pi)
    print(f"RMS error over 18 angles: paper before {pb:.4f} after {pa:.4f} | mtcal before {mb:.4f} after {ma:.4f} "
          f"| MC after median {band['median']:.4f} [{band['low']:.4f}, {band['high']:.4f}] deg")
    rows_cmp.append(paper.comparison_row(art, "RMS |before-ref| (deg)", pb, mb, "-", None))
    rows_cmp.append(paper.comparison_row(art, "RMS |after-ref| (deg)", pa, ma, "after closer to reference than before", bool(ma < mb)))
    return ma < mb

assert show_positions("T1", "T000-1")

# %% [markdown]
# ## T000-2 — large pitch installation error (Table 2)

# %%
assert show_positions("T2", "T000-2")

# %% [markdown]
# ## T000-3 — large pitch and roll installation errors (Table 3)

# %%
assert show_positions("T3", "T000-3")

# %% [markdown]
# ## T000-4 — all three installation errors large (Table 4)

# %%
assert show_positions("T4", "T000-4")

# %% [markdown]
# ## T000-5 — AoA sweep, mean pitch (Table 5)

# %%
sw = runs["T1"].sweeps["aoa"]
p5 = paper.load("seed000_table05_aoa_sweep_mean_pitch")
t5 = pd.DataFrame({"reference": p5.reference_mean_pitch_deg, "paper_before": p5.before_mean_pitch_deg,
                   "mtcal_before": deg(sw["before_mean"][0]), "paper_after": p5.after_mean_pitch_deg,
                   "mtcal_after": deg(sw["after_mean"][0])})
report.save_table(t5, "T000-5")
report.show_table(t5, "{:.3f}")
mb5 = np.abs(t5.mtcal_before - t5.reference).max(); ma5 = np.abs(t5.mtcal_after - t5.reference).max()
rows_cmp.append(paper.comparison_row("T000-5", "max |before-ref| pitch (deg)", 0.04, mb5, "before up to 0.04 deg", bool(mb5 <= 0.045)))
rows_cmp.append(paper.comparison_row("T000-5", "max |after-ref| pitch (deg)", 0.025, ma5, "after within 0.03 deg", bool(ma5 <= 0.03)))
assert ma5 <= 0.03

# %% [markdown]
# ## F000-7 — roll and yaw errors during the AoA sweep, before vs after

# %%
tr = runs["T1"].trace
fig, axes = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
for ax, j, name in ((axes[0], 2, "roll"), (axes[1], 0, "yaw")):
    ax.plot(tr["aoa_time_s"], deg(tr["aoa_before_err"][:, j]), label="before", lw=0.8)
    ax.plot(tr["aoa_time_s"], deg(tr["aoa_after_err"][:, j]), label="after", lw=0.8)
    ax.set_ylabel(f"{name} error (deg)")
axes[0].legend(); axes[1].set_xlabel("time in AoA sweep (s)")
fig.suptitle("F000-7: stepwise coupling errors (pitch motion into roll/yaw)")
report.save_figure(fig, "F000-7")

# %% [markdown]
# ## T000-6 — MaxAE / RMSE of roll and yaw in the AoA sweep (Table 6), with Monte Carlo band

# %%
p6 = paper.load("seed000_table06_aoa_sweep_roll_yaw_errors")
msw = mc["T1"].sweeps["aoa"]
rows6 = []
for metric in ("MaxAE", "RMSE"):
    for state in ("before", "after"):
        key = "maxae" if metric == "MaxAE" else "rmse"
        for j, ang in ((2, "roll"), (0, "yaw")):
            pv = float(p6.loc[(p6.metric == metric) & (p6.calibration_state == state), f"{ang}_deg"].iloc[0])
            band = metrics.percentile_band(deg(msw[f"{state}_{key}_{j}"]))
            rows6.append({"metric": metric, "state": state, "angle": ang, "paper": pv,
                          "mtcal": deg(sw[f"{state}_{key}_{j}"][0]), "mc_median": band["median"],
                          "mc_low": band["low"], "mc_high": band["high"],
                          "paper_in_band": bool(band["low"] <= pv <= band["high"])})
t6 = pd.DataFrame(rows6)
report.save_table(t6, "T000-6")
report.show_table(t6)
after_rmse = t6[(t6.metric == "RMSE") & (t6.state == "after")]
for _, r in after_rmse.iterrows():
    rows_cmp.append(paper.comparison_row("T000-6", f"{r.angle} RMSE after (deg, MC median)", r.paper, r.mc_median,
                                         "after RMSE <= 0.01 deg", bool(r.mc_median <= 0.01)))
roll_red = t6[(t6.metric == "RMSE") & (t6.angle == "roll")].set_index("state").mtcal
yaw_ok = float(np.mean(deg(msw["after_rmse_0"]) <= 0.01))
print(f"fraction of seeds with yaw RMSE after <= 0.01 deg: {yaw_ok:.2f}")
rows_cmp.append(paper.comparison_row("T000-6", "roll RMSE before -> after (deg)", 0.029, roll_red["before"],
                                     "after < before", bool(roll_red["after"] < roll_red["before"])))
assert roll_red["after"] < roll_red["before"]

# %% [markdown]
# **Where the claim fails:** the after-calibration *yaw* RMSE is ≈ 0.01° (median slightly above).
# Yaw is not observable by the accelerometer; it integrates gyro white noise, bias instability and
# the residual turn-on/warm-up bias from the QNCF start through calibration into the sweep (about
# 1.5 min). With the assumed 0.1 °/√h ARW and 0.8 °/h instability, the paper's 0.009° is inside
# our band but the median is not below 0.01°: the claim is sensor-grade dependent, not a property
# of the calibration. Roll (accelerometer-referenced) meets it with a wide margin.

# %% [markdown]
# ## T000-7 — roll sweep, mean roll (Table 7)

# %%
sr = runs["T1"].sweeps["roll"]
p7 = paper.load("seed000_table07_roll_sweep_mean_roll")
t7 = pd.DataFrame({"reference": p7.reference_mean_roll_deg, "paper_before": p7.before_mean_roll_deg,
                   "mtcal_before": P[2] * deg(sr["before_mean"][0]), "paper_after": p7.after_mean_roll_deg,
                   "mtcal_after": P[2] * deg(sr["after_mean"][0])})
report.save_table(t7, "T000-7")
report.show_table(t7, "{:.3f}")
mb7 = np.abs(t7.mtcal_before - t7.reference).max(); ma7 = np.abs(t7.mtcal_after - t7.reference).max()
rows_cmp.append(paper.comparison_row("T000-7", "max |roll before-ref| (deg)", 0.052, mb7, "before within 0.06 deg", bool(mb7 <= 0.06)))
rows_cmp.append(paper.comparison_row("T000-7", "max |roll after-ref| (deg)", 0.038, ma7, "after within 0.04 deg", bool(ma7 <= 0.04)))
assert ma7 <= 0.04

# %% [markdown]
# ## F000-8 — pitch and yaw errors in the roll sweep, before vs after

# %%
fig, axes = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
for ax, j, name in ((axes[0], 1, "pitch"), (axes[1], 0, "yaw")):
    ax.plot(tr["roll_time_s"], deg(tr["roll_before_err"][:, j]), label="before", lw=0.8)
    ax.plot(tr["roll_time_s"], deg(tr["roll_after_err"][:, j]), label="after", lw=0.8)
    ax.set_ylabel(f"{name} error (deg)")
axes[0].legend(); axes[1].set_xlabel("time in roll sweep (s)")
fig.suptitle("F000-8: roll motion coupled into pitch and yaw")
report.save_figure(fig, "F000-8")

# %% [markdown]
# ## T000-8 — MaxAE / RMSE of pitch and yaw in the roll sweep (Table 8)

# %%
p8 = paper.load("seed000_table08_roll_sweep_pitch_yaw_errors")
msr = mc["T1"].sweeps["roll"]
rows8 = []
for metric in ("MaxAE", "RMSE"):
    key = "maxae" if metric == "MaxAE" else "rmse"
    for j, ang in ((1, "pitch"), (0, "yaw")):
        pb = float(p8.loc[(p8.metric == metric) & (p8.calibration_state == "before"), f"{ang}_deg"].iloc[0])
        pa = float(p8.loc[(p8.metric == metric) & (p8.calibration_state == "after"), f"{ang}_deg"].iloc[0])
        red = 1 - msr[f"after_{key}_{j}"] / msr[f"before_{key}_{j}"]
        band = metrics.percentile_band(100 * red)
        rows8.append({"metric": metric, "angle": ang, "paper_before": pb, "paper_after": pa,
                      "mtcal_before": deg(sr[f"before_{key}_{j}"][0]), "mtcal_after": deg(sr[f"after_{key}_{j}"][0]),
                      "paper_reduction_pct": 100 * (1 - pa / pb), "mc_reduction_median_pct": band["median"],
                      "mc_reduction_low_pct": band["low"]})
t8 = pd.DataFrame(rows8)
report.save_table(t8, "T000-8")
report.show_table(t8, "{:.3f}")
min_red = t8.mc_reduction_low_pct.min()
rows_cmp.append(paper.comparison_row("T000-8", "smallest reduction, MC 2.5 % (%)", 37.1, min_red, ">= 30 % reduction", bool(min_red >= 30)))
assert min_red >= 30

# %% [markdown]
# ## Monte Carlo bands of the key after-calibration numbers
# Median and 95 % interval over N_MC seeds (sensor noise, turn-on biases, turntable positioning),
# and whether the paper's number lies inside.

# %%
band_rows = []
for test, art, table in (("T1", "T000-1", None), ("T2", "T000-2", None), ("T3", "T000-3", None), ("T4", "T000-4", None)):
    pt = tables[test]
    x = deg(np.abs(mc[test].cal_after - mc[test].reference)).max(axis=(1, 2))
    b = metrics.percentile_band(x)
    pv = float(np.abs(pt.paper_after - pt.reference).max())
    band_rows.append({"artifact": art, "quantity": "max |after-ref| at 6 positions", "paper": pv, **b})
x = deg(np.abs(mc["T1"].sweeps["aoa"]["after_mean"] - mc["T1"].sweeps["aoa"]["reference"])).max(axis=1)
band_rows.append({"artifact": "T000-5", "quantity": "max |after-ref| mean pitch", "paper": 0.025, **metrics.percentile_band(x)})
for _, r in t6[t6.state == "after"].iterrows():
    band_rows.append({"artifact": "T000-6", "quantity": f"{r.angle} {r.metric} after", "paper": r.paper,
                      "median": r.mc_median, "low": r.mc_low, "high": r.mc_high})
x = deg(np.abs(mc["T1"].sweeps["roll"]["after_mean"] - mc["T1"].sweeps["roll"]["reference"])).max(axis=1)
band_rows.append({"artifact": "T000-7", "quantity": "max |after-ref| mean roll", "paper": 0.038, **metrics.percentile_band(x)})
for key, j, ang in (("rmse", 1, "pitch"), ("rmse", 0, "yaw")):
    pa = float(p8.loc[(p8.metric == "RMSE") & (p8.calibration_state == "after"), f"{ang}_deg"].iloc[0])
    band_rows.append({"artifact": "T000-8", "quantity": f"{ang} RMSE after", "paper": pa,
                      **metrics.percentile_band(deg(msr[f"after_{key}_{j}"]))})
bands = pd.DataFrame(band_rows)
bands["paper_in_band"] = (bands.low <= bands.paper) & (bands.paper <= bands.high)
report.save_table(bands, "T000-mc-bands")
report.show_table(bands)
print(f"{int(bands.paper_in_band.sum())} of {len(bands)} paper numbers inside the 95 % band")

# %% [markdown]
# ## Error budget — one source at a time (T1)
# Each row switches on a single named source (independent child generators per source, so the
# draws of the other sources do not change). "all" is the full model. The averaging-window rows
# repeat "all" with a different middle fraction of each 3 s rest.

# %%
budget_rows = []
configs = [("none", ())] + [(src, (src,)) for src in s.SOURCES] + [("all", s.SOURCES)]
for name, srcs in configs:
    r = s.run_turntable_mc(sc, "T1", rng_budget.spawn(1)[0], N_BUDGET, srcs, with_sweeps=BUDGET_SWEEPS)
    err = deg(np.abs(r.cal_after - r.reference))
    row = {"source": name, "cal_after_rms_deg": float(np.sqrt(np.mean(err**2))), "cal_after_max_deg": float(err.max())}
    if BUDGET_SWEEPS:
        row["aoa_roll_rmse_after_deg"] = float(np.median(deg(r.sweeps["aoa"]["after_rmse_2"])))
        row["aoa_yaw_rmse_after_deg"] = float(np.median(deg(r.sweeps["aoa"]["after_rmse_0"])))
    budget_rows.append(row)
for frac in (0.1, 0.9):
    r = s.run_turntable_mc(sc, "T1", rng_budget.spawn(1)[0], N_BUDGET, s.SOURCES, fraction=frac)
    err = deg(np.abs(r.cal_after - r.reference))
    budget_rows.append({"source": f"all, averaging fraction {frac}", "cal_after_rms_deg": float(np.sqrt(np.mean(err**2))),
                        "cal_after_max_deg": float(err.max())})
budget = pd.DataFrame(budget_rows)
report.save_table(budget, "T000-budget")
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

# %%
cmp = paper.comparison_table(rows_cmp)
report.save_table(cmp, "10_seed000_turntable_comparison")
report.show_table(cmp)
print(paper.claims_summary(cmp))
