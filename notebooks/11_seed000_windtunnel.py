# %% [markdown]
# # Seed 000 — hypersonic wind tunnel (Tables 9–11, Figs 10–11)
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
from mtcal import report, paper, metrics, scenarios000 as s
report.setup_matplotlib()
deg = np.degrees
sc = s.WindTunnelScenario()
report.show_table(s.describe(sc))

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
Qp = paper.load("seed000_matrix_qbs_windtunnel")[["col_1", "col_2", "col_3", "col_4"]].to_numpy(float)
Qs = run.q_matrix[0]
print("printed:"); print(np.array2string(Qp, precision=6, suppress_small=True))
print("mtcal (trial 0):"); print(np.array2string(Qs, precision=6, suppress_small=True))
band = metrics.percentile_band(run.q_matrix[:, 1, 1])
print(f"printed det {np.linalg.det(Qp):.4f}, Q(2,2) {Qp[1, 1]:.6f}; mtcal Q(2,2) median {band['median']:.6f} "
      f"[{band['low']:.6f}, {band['high']:.6f}], 1/(1+ratio error) = {1 / (1 + sc.pitch_ratio_error):.6f}")
rows_cmp.append(paper.comparison_row("matrix", "Q(2,2) (non-orthogonal pitch scale)", Qp[1, 1], band["median"],
                                     "diag(2,2) > 1.003 from mechanism ratio error", bool(band["median"] > 1.003)))
assert band["median"] > 1.003

# %% [markdown]
# ## T000-9 — wind-off AoA sweep, mean pitch (Table 9)

# %%
nw = run.nowind
p9 = paper.load("seed000_table09_windtunnel_nowind_mean_pitch")
t9 = pd.DataFrame({"reference": p9.reference_mean_pitch_deg, "paper_before": p9.before_mean_pitch_deg,
                   "mtcal_before": deg(nw["before_mean"][0]), "paper_after": p9.after_mean_pitch_deg,
                   "mtcal_after": deg(nw["after_mean"][0])})
report.save_table(t9, "T000-9")
report.show_table(t9, "{:.3f}")
ref = deg(nw["reference"])
bmax = metrics.percentile_band(deg(np.abs(nw["before_mean"] - nw["reference"])).max(axis=1))
amax = metrics.percentile_band(deg(np.abs(nw["after_mean"] - nw["reference"])).max(axis=1))
print(f"max |before-ref| MC median {bmax['median']:.4f} [{bmax['low']:.4f}, {bmax['high']:.4f}] (paper 0.050)")
print(f"max |after-ref|  MC median {amax['median']:.4f} [{amax['low']:.4f}, {amax['high']:.4f}] (paper 0.017)")
rows_cmp.append(paper.comparison_row("T000-9", "max |before-ref| pitch (deg, MC median)", 0.050, bmax["median"],
                                     "before within 0.05 deg", bool(bmax["median"] <= 0.0505)))
rows_cmp.append(paper.comparison_row("T000-9", "max |after-ref| pitch (deg, MC median)", 0.017, amax["median"],
                                     "after within 0.02 deg", bool(amax["median"] <= 0.02)))
assert amax["median"] <= 0.02 and amax["median"] < bmax["median"]

# %% [markdown]
# "Before within 0.05°" is borderline in simulation (median ≈ 0.05°) exactly as in the paper, which
# prints 0.050 at 13° (12.95): the before error is dominated by the mechanism ratio error chosen to
# match Table 9's slope, so the claim holds or fails by a few thousandths depending on the seed.
#
# ## F000-10 — pitch in the five wind-on sweeps

# %%
tr = run.trace
fig, axes = plt.subplots(2, 1, figsize=(7, 5.5), sharex=False)
for g in range(5):
    axes[0].plot(tr[f"wind_time_s_{g}"], deg(tr[f"wind_pitch_{g}"]), lw=0.7, label=f"Group {g + 1}")
axes[0].set_ylabel("pitch after calibration (deg)"); axes[0].legend(fontsize=7); axes[0].set_xlabel("time (s)")
t_amd = tr["wind_time_s_0"]
axes[1].plot(t_amd, tr["amd_pct"], lw=0.5); axes[1].axhline(sc.qncf.amd_threshold_pct, color="r", ls="--", label="Thr 0.3 %")
axes[1].set_yscale("log"); axes[1].set_ylabel("AMD (% of g)"); axes[1].set_xlabel("time (s), Group 1"); axes[1].legend()
fig.suptitle("F000-10: wind-on AoA sweeps (vibration trips the AMD: gyro-only QNCF)")
report.save_figure(fig, "F000-10")

# %% [markdown]
# ## T000-10 — five wind-on groups: Mean, elastic-corrected, Std (Table 10)

# %%
w = run.wind_on
p10 = paper.load("seed000_table10_windtunnel_wind_pitch")
gm = deg(w["group_means"][:, 0])                   # (5 groups, 5 angles), trial 0
rows10 = []
labels = [f"group_{g + 1}" for g in range(5)] + ["mean", "after_elastic_angle_correction", "std"]
vals = list(gm) + [gm.mean(axis=0), deg(w["elastic_corrected"]), gm.std(axis=0, ddof=1)]
for lab, v in zip(labels, vals):
    pv = p10[p10.row_key == lab].value_deg.to_numpy(float)
    for j, a in enumerate(sc.wind_on_sweep_deg):
        rows10.append({"row": lab, "reference": a, "paper": pv[j], "mtcal": v[j]})
t10 = pd.DataFrame(rows10)
report.save_table(t10, "T000-10")
report.show_table(t10.pivot(index="row", columns="reference", values="mtcal").loc[labels].reset_index(), "{:.3f}")
dev = metrics.percentile_band(deg(np.abs(w["group_means"].mean(axis=0) - w["elastic_corrected"])).max(axis=1))
std = metrics.percentile_band(deg(w["group_means"].std(axis=0, ddof=1)).max(axis=1))
print(f"max |mean - elastic corrected| MC median {dev['median']:.4f} [{dev['low']:.4f}, {dev['high']:.4f}] (paper 0.029)")
print(f"max Std over groups            MC median {std['median']:.4f} [{std['low']:.4f}, {std['high']:.4f}] (paper 0.010)")
print(f"fraction of wind-on samples with the accelerometer used (AMD < Thr): {w['gate_fraction_on']:.3f}")
rows_cmp.append(paper.comparison_row("T000-10", "max |mean - elastic corrected| (deg, MC median)", 0.029, dev["median"],
                                     "within 0.03 deg", bool(dev["median"] <= 0.03)))
rows_cmp.append(paper.comparison_row("T000-10", "max Std over 5 groups (deg, MC median)", 0.010, std["median"],
                                     "Std within 0.01 deg", bool(std["median"] <= 0.01)))
rows_cmp.append(paper.comparison_row("T000-10", "AMD gate open with wind (fraction)", 0.0, w["gate_fraction_on"],
                                     "vibration switches the accelerometer off", bool(w["gate_fraction_on"] < 0.01)))
assert w["gate_fraction_on"] < 0.01
assert dev["median"] <= 0.03

# %% [markdown]
# The mean-vs-elastic deviation is largely an *input*: the true deflection and the tunnel's
# correction model are fitted to Table 10's rows. What the simulation tests is that the IMU,
# gyro-only under vibration, measures the deflected attitude well enough for that 0.02–0.03°
# difference to be visible, and how large the group-to-group scatter is. The Std claim (≤ 0.01°)
# is borderline in simulation as in the paper (0.010 printed): the scatter comes from dynamic-
# pressure variation (2 %), gyro drift during the ≈ 25 s of gyro-only flight, and the tilt kick the
# filter takes while the AMD is still open as the vibration ramps up.

# %% [markdown]
# **Where claims fail.** Std ≤ 0.01°: our median scatter is above 0.01° — mostly Group 5, whose
# slower mechanism keeps the QNCF gyro-only (AMD tripped) for longer, so gyro bias drift (0.3 °/h
# residual + 0.8 °/h instability assumed) accumulates; the paper's 0.010 is inside our band.
#
# ## F000-11 — roll and yaw errors, wind-off AoA sweep

# %%
fig, axes = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
for ax, j, name in ((axes[0], 2, "roll"), (axes[1], 0, "yaw")):
    ax.plot(tr["nowind_time_s"], deg(tr["nowind_before_err"][:, j]), lw=0.8, label="before")
    ax.plot(tr["nowind_time_s"], deg(tr["nowind_after_err"][:, j]), lw=0.8, label="after")
    ax.set_ylabel(f"{name} error (deg)")
axes[0].legend(); axes[1].set_xlabel("time in sweep (s)")
fig.suptitle("F000-11: roll/yaw errors without wind")
report.save_figure(fig, "F000-11")

# %% [markdown]
# ## T000-11 — MaxAE / RMSE of roll and yaw, wind-off (Table 11)

# %%
p11 = paper.load("seed000_table11_windtunnel_nowind_roll_yaw_errors")
rows11 = []
for metric, key in (("MaxAE", "maxae"), ("RMSE", "rmse")):
    for state in ("before", "after"):
        for j, ang in ((2, "roll"), (0, "yaw")):
            pv = float(p11.loc[(p11.metric == metric) & (p11.calibration_state == state), f"{ang}_deg"].iloc[0])
            b = metrics.percentile_band(deg(nw[f"{state}_{key}_{j}"]))
            rows11.append({"metric": metric, "state": state, "angle": ang, "paper": pv, "mtcal": deg(nw[f"{state}_{key}_{j}"][0]),
                           "mc_median": b["median"], "mc_low": b["low"], "mc_high": b["high"],
                           "paper_in_band": bool(b["low"] <= pv <= b["high"])})
t11 = pd.DataFrame(rows11)
report.save_table(t11, "T000-11")
report.show_table(t11)
mx = t11[t11.metric == "MaxAE"].mc_median.max()
rows_cmp.append(paper.comparison_row("T000-11", "max roll/yaw MaxAE before & after (deg, MC median)", 0.030, mx,
                                     "both within 0.03 deg", bool(mx <= 0.03)))
print(f"{int(t11.paper_in_band.sum())} of {len(t11)} paper numbers inside the 95 % band")

# %% [markdown]
# Yaw is gyro-only: its MaxAE (before and after) grows with the time since the QNCF start and
# exceeds 0.03° in many seeds, so "both within 0.03°" holds for roll but not always for yaw; roll
# after calibration is *better* here, while the paper's roll got slightly worse (Table 11) — our
# mechanism errors are partly absorbed by Q̂, the paper's were not.

# %% [markdown]
# ## Paper vs mtcal

# %%
cmp = paper.comparison_table(rows_cmp)
report.save_table(cmp, "11_seed000_windtunnel_comparison")
report.show_table(cmp)
print(paper.claims_summary(cmp))
