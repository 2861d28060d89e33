# %% [markdown]
# # 31 — wang2022sensors: RAMS EKF, ref. [16] and the AHRS stand-in
#
# Wang et al., *Sensors* 2022 (RAMS), Sec. 3.3, 5 and 7: the EKF with ZVD
# covariance switching (wang2022sensors_fig09), the simulation of Fig. 11, Table 5
# (wang2022sensors_table05), the drift test of Fig. 13 and the per-angle maximum error of
# Fig. 14, plus the sensitivity to Table 3's ambiguous rows.
#
# Set-up (`mtcal.studies.wang2022sensors.runs`): Table 3 IMU at 200 Hz, 0.1 mg residual
# accelerometer bias, lever arm 0.2 m, turntable steps at 20 °/s with 1 s
# holds. RAMS = Algorithm A1 axis + EKF. "ZVD" below is Table 1 plus the
# optional gyro condition ‖ω − b̂0‖ < 2 °/s unless marked "Table 1 only"
# (notebook 30, wang2022sensors_fig06, shows why). The AHRS stand-in is a 9-axis
# complementary filter on Ellipse2-N-class sensors in a magnetic field whose
# heading wanders by 5° (1σ, τ = 20 s).

# %% tags=["parameters"]
import os

SEED = 4031
SIZE = os.environ.get("MTCAL_SIZE", "full")  # "ci" under `make test`
F9_TRIALS = 50 if SIZE == "full" else 20     # Monte Carlo trials of the Fig. 9 record (3 s each)
SWEEP_TRIALS = 16 if SIZE == "full" else 8   # Table 5 sweeps per axis (noise seeds)
SWEEP_STEP_DEG = 10.0  # Sec. 7 (both sizes: the move profile sets the lever-arm errors, see wang2022sensors_table05)
FIG11_REPS = 14 if SIZE == "full" else 2     # x 73 angles = trials of the Fig. 11 Monte Carlo
DRIFT_RUN_S = 600.0 if SIZE == "full" else 60.0
DRIFT_TRIALS = 16 if SIZE == "full" else 8  # noise seeds (trials cost little: the loops run over time)
SENS_REPS = 4 if SIZE == "full" else 1

# %%
import dataclasses

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from IPython.display import display

from mtcal.core import metrics, profiles, rotations
from mtcal.reporting import compare
from mtcal.reporting import paper_numbers as paper, output as report
from mtcal.filters.rams_ekf import initial_state, run_rams_ekf
from mtcal.studies.wang2022sensors.runs import (ImuSpec, RotationSetup, run_drift, run_fig11, run_sweep,
                                simulate_rotation, table4_axes)
from mtcal.methods.zero_velocity import ZvdParams, detect_static, rest_intervals

report.setup_matplotlib()
rng = np.random.default_rng(SEED)
imu = ImuSpec()
GYRO_ZVD = np.radians(2.0)
rows = []
deg = np.degrees

# %% [markdown]
# ## wang2022sensors_fig09 — EKF with and without ZVD switching
#
# 0–1 s still, 1–2 s rotating 60° (lever arm 0.2 m: tangential + centripetal
# acceleration), 2–3 s still. The standard EKF (always V_z) reads the
# lever-arm acceleration as angle; with ZVD switching the gyro carries the
# motion and the error stays small; both agree at rest. Figure: one trial;
# numbers: median and 95 % band over `F9_TRIALS` noise seeds (claims are
# asserted on the 97.5 % end, i.e. for almost every seed).

# %%
setup = RotationSetup()
prof = profiles.step_schedule(np.radians([0.0, 60.0]), np.radians(60.0), 1.0, imu.fs_hz)
th9 = np.broadcast_to(prof.angle_rad[:, 0], (F9_TRIALS, prof.time_s.size))
rec = simulate_rotation(th9, np.broadcast_to(prof.rate_rad_s[:, 0], th9.shape),
                        np.broadcast_to(prof.accel_rad_s2[:, 0], th9.shape), prof.is_static, setup,
                        imu.error_model(), imu.fs_hz, rng)
a0, b0 = initial_state(rec.gyro_rad_s, rec.accel_m_s2, 180)
st = detect_static(rec.accel_m_s2, imu.fs_hz, dataclasses.replace(setup.zvd, gyro_max_rad_s=GYRO_ZVD),
                   rec.gyro_rad_s - b0[:, None, :])
v = setup.unit_axis()
res_z = run_rams_ekf(rec.gyro_rad_s, rec.accel_m_s2, st, v, a0, imu.dt_s, imu.ekf_params(), bias0_rad_s=b0)
res_n = run_rams_ekf(rec.gyro_rad_s, rec.accel_m_s2, st, v, a0, imu.dt_s, imu.ekf_params(), bias0_rad_s=b0,
                     use_zvd=False)
e_z = deg(rotations.wrap_angle(res_z.theta_rad - rec.theta_rad))  # (trials, N)
e_n = deg(rotations.wrap_angle(res_n.theta_rad - rec.theta_rad))
t = rec.time_s
fig, axs = plt.subplots(4, 1, figsize=(8, 8), sharex=True)
axs[0].plot(t, deg(rec.theta_rad[0]))
axs[0].set_ylabel("(a) θ ref (deg)")
axs[1].plot(t, e_z[0], label="EKF with ZVD")
axs[1].plot(t, e_n[0], "--", label="EKF")
axs[1].set_ylabel("(b) error (deg)")
axs[1].legend()
axs[2].plot(t, np.linalg.norm(rec.accel_m_s2[0], axis=1))
axs[2].set_ylabel("(c) ‖a‖ (m/s²)")
axs[3].plot(t, deg(np.linalg.norm(rec.gyro_rad_s[0], axis=1)))
axs[3].set_ylabel("(d) ‖ω‖ (°/s)")
axs[3].set_xlabel("time (s)")
display(report.save_figure(fig, "wang2022sensors_fig09"))
moving = ~prof.is_static
still1 = t < 1.0
still2 = t > 2.5
rm_z, rm_n = metrics.rmse(e_z, mask=moving), metrics.rmse(e_n, mask=moving)  # per trial
ratio9 = metrics.percentile_band(rm_z / rm_n)
same1 = metrics.percentile_band(np.max(np.abs(e_z - e_n)[:, still1], axis=1))
end2 = metrics.percentile_band(np.max(np.abs(e_z[:, still2]), axis=1))
print(f"moving RMSE (median over {F9_TRIALS} trials): with ZVD {np.median(rm_z):.4f} deg, "
      f"without {np.median(rm_n):.4f} deg; ratio {ratio9['median']:.4f} [{ratio9['low']:.4f}, {ratio9['high']:.4f}]")
print(f"still 1 max |difference| between the two: median {same1['median']:.5f} deg, 97.5 % {same1['high']:.5f} deg")
print(f"last 0.5 s max |error| with ZVD: median {end2['median']:.4f} deg, 97.5 % {end2['high']:.4f} deg")
rows.append(compare.comparison_row("wang2022sensors_fig09", "moving RMSE with / without ZVD (ratio)", "figure",
                                 float(ratio9["median"]), "ZVD EKF better in motion (< 0.2)",
                                 bool(ratio9["high"] < 0.2), band=ratio9))
rows.append(compare.comparison_row("wang2022sensors_fig09", "still period 1: |with - without| max (deg)", "almost same",
                                 float(same1["median"]), "same while still (< 0.005)",
                                 bool(same1["high"] < 0.005), band=same1))
rows.append(compare.comparison_row("wang2022sensors_fig09", "last 0.5 s still: max |error| with ZVD (deg)", "figure",
                                 float(end2["median"]), "(mtcal) back at rest (< 0.05)",
                                 bool(end2["high"] < 0.05), band=end2))

# %%
assert ratio9["high"] < 0.2, "ZVD switching must beat the standard EKF in motion in (almost) every trial"
assert same1["high"] < 0.005 and end2["high"] < 0.05

# %% [markdown]
# ## wang2022sensors_fig11 — maximum error vs angle, proposed vs ref. [16] (Sec. 5)
#
# Axis v = [0.1734, 0.9835, 0.0523]; −180…180° in 5° steps; at each angle
# "1000 measurements" = 1000 consecutive outputs (5 s at 200 Hz) after the
# move. One batched Monte Carlo: a trial = (angle, repetition), each with its
# own axis estimate from three rests. Curves: median over repetitions of the
# per-angle maximum error, with the 95 % band.

# %%
f11 = run_fig11(RotationSetup(), imu, FIG11_REPS, rng)
ang = deg(f11.angles_rad)
b_r = metrics.percentile_band(deg(f11.max_err_rams), axis=0)
b_16 = metrics.percentile_band(deg(f11.max_err_ref16), axis=0)
fig, ax = plt.subplots(figsize=(8, 4))
for b, lab in ((b_r, "proposed (RAMS EKF)"), (b_16, "ref. [16] (accelerometer only)")):
    ax.fill_between(ang, b["low"], b["high"], alpha=0.25)
    ax.plot(ang, b["median"], "o-", ms=3, label=lab)
ax.set_xlabel("rotation angle (deg)")
ax.set_ylabel("max error over 1000 measurements (deg)")
ax.legend()
display(report.save_figure(fig, "wang2022sensors_fig11"))
# per repetition (one simulated Fig. 11 experiment): share of angles won, and the
# median / largest per-angle max error over the 73 angles
share = metrics.percentile_band(np.mean(f11.max_err_rams < f11.max_err_ref16, axis=1))
med11_r = metrics.percentile_band(np.median(deg(f11.max_err_rams), axis=1))
med11_16 = metrics.percentile_band(np.median(deg(f11.max_err_ref16), axis=1))
worst11_r = metrics.percentile_band(np.max(deg(f11.max_err_rams), axis=1))
print(f"share of angles where proposed < ref. [16], per experiment: median {share['median']:.0%} "
      f"[{share['low']:.0%}, {share['high']:.0%}] over {FIG11_REPS} repetitions")
for lab, b in (("proposed, median over angles", med11_r), ("proposed, worst angle", worst11_r),
               ("ref. [16], median over angles", med11_16)):
    print(f"{lab:30s}: {b['median']:.4f} deg [{b['low']:.4f}, {b['high']:.4f}]")
rows.append(compare.comparison_row("wang2022sensors_fig11", "share of angles where proposed < ref. [16]", "all (figure)",
                                 float(share["median"]), "proposed superior to ref. [16] (> 0.9)",
                                 bool(share["low"] > 0.9), band=share))
rows.append(compare.comparison_row("wang2022sensors_fig11", "proposed: per-angle max error, median over angles (deg)", "figure",
                                 float(med11_r["median"]), "(mtcal) below ref. [16]",
                                 bool(med11_r["high"] < med11_16["low"]), band=med11_r))
rows.append(compare.comparison_row("wang2022sensors_fig11", "ref. [16]: per-angle max error, median over angles (deg)", "figure",
                                 float(med11_16["median"]), "", None, band=med11_16))
rows.append(compare.comparison_row("wang2022sensors_fig11", "proposed: worst per-angle max error (deg)", "figure",
                                 float(worst11_r["median"]), "", None, band=worst11_r))

# %%
assert share["low"] > 0.9, "the proposed method must beat ref. [16] at > 90 % of the angles in every experiment"
assert med11_r["high"] < med11_16["low"]

# %% [markdown]
# ## wang2022sensors_table05 — static and dynamic RMSE: RAMS vs ref. [16] vs AHRS stand-in
#
# Sweep −180…180° in 10° steps, 1 s pauses, after the three axis-estimation
# rests; static/dynamic from the turntable schedule (the simulation knows it;
# the paper used its ZVD). Three RAMS variants: ZVD as used here (Table 1 +
# gyro), Table 1 only, and an oracle that switches the EKF by the true
# schedule (isolates ZVD errors from filter errors).

# %%
p5 = paper.load("wang2022sensors_table05_rmse")
sysmap = {"RAMS": "RAMS", "Ellipse2-N": "AHRS stand-in", "Method in ref. [16]": "ref. [16]"}
t5_rows, all_stat = [], {}
for name, v_true in table4_axes().items():
    s = RotationSetup(axis=tuple(v_true))
    r_main = run_sweep(s, imu, SWEEP_TRIALS, rng, step_deg=SWEEP_STEP_DEG, zvd_gyro_max_rad_s=GYRO_ZVD)
    r_t1 = run_sweep(s, imu, SWEEP_TRIALS, rng, step_deg=SWEEP_STEP_DEG, with_ahrs=False)
    r_or = run_sweep(s, imu, SWEEP_TRIALS, rng, step_deg=SWEEP_STEP_DEG, with_ahrs=False,
                     zvd_gyro_max_rad_s=GYRO_ZVD, ekf_switch="truth")
    stat, dyn = r_main.sweep & r_main.true_static, r_main.sweep & ~r_main.true_static
    variants = {"RAMS": r_main.err_rams, "RAMS (Table 1 ZVD only)": r_t1.err_rams,
                "RAMS (oracle switching)": r_or.err_rams, "ref. [16]": r_main.err_ref16,
                "AHRS stand-in": r_main.err_ahrs}
    all_stat[name] = r_main
    for sysname, err in variants.items():
        bs = metrics.percentile_band(deg(metrics.rmse(err, mask=stat)))
        bd = metrics.percentile_band(deg(metrics.rmse(err, mask=dyn)))
        prow = p5[(p5.rotation_axis == name) & (p5.system.map(sysmap) == sysname)]
        ps = float(prow.rmse_static_deg.iloc[0]) if len(prow) else np.nan
        pdy = float(prow.rmse_dynamic_deg.iloc[0]) if len(prow) else np.nan
        t5_rows.append({"axis": name, "system": sysname, "paper_static": ps, "mtcal_static_median": bs["median"],
                        "static_low": bs["low"], "static_high": bs["high"], "paper_dynamic": pdy,
                        "mtcal_dynamic_median": bd["median"], "dynamic_low": bd["low"], "dynamic_high": bd["high"]})
t5 = pd.DataFrame(t5_rows)
report.save_table(t5, "wang2022sensors_table05")
report.show_table(t5)

# %%
def _get(axis_name, sysname, col):
    return float(t5[(t5.axis == axis_name) & (t5.system == sysname)][col].iloc[0])


T5_CLAIMS = (  # (system, static/dynamic, claim, test on the median)
    ("RAMS", "static", "RAMS static RMSE < 0.02 deg", lambda x: x < 0.02),
    ("RAMS", "dynamic", "RAMS dynamic RMSE < 0.5 deg", lambda x: x < 0.5),
    ("RAMS (oracle switching)", "static", "(mtcal) oracle-switched RAMS static < 0.02 deg", lambda x: x < 0.02),
    ("ref. [16]", "static", "ref. [16] static RMSE < 0.1 deg", lambda x: x < 0.1),
    ("ref. [16]", "dynamic", "ref. [16] fails dynamically (> 1 deg)", lambda x: x > 1.0),
    ("AHRS stand-in", "static", "AHRS static RMSE > 0.1 deg", lambda x: x > 0.1),
    ("AHRS stand-in", "dynamic", "AHRS moving RMSE > 0.1 deg", lambda x: x > 0.1))
for name in table4_axes():
    for sysname, col, claim, ok in T5_CLAIMS:
        val = _get(name, sysname, f"mtcal_{col}_median")
        band = (_get(name, sysname, f"{col}_low"), _get(name, sysname, f"{col}_high"))
        pv = _get(name, sysname, f"paper_{col}")
        rows.append(compare.comparison_row("wang2022sensors_table05", f"{name} {sysname} {col} RMSE (deg)",
                                         "n/a" if np.isnan(pv) else pv, val, claim, bool(ok(val)), band=band))

# %% [markdown]
# **Reading wang2022sensors_table05** (numbers from the full-size run). Three of the 18 printed
# numbers fall inside our 95 % bands, all of them AHRS numbers (Bv1 dynamic,
# Bv2 static and dynamic): the stand-in's bands are wide because its magnetic
# disturbance is random, and it is a stand-in, not the Ellipse2-N. The others
# lie outside for reasons that can be named:
#
# * ref. [16] static ≈ 0.041° (its per-sample noise N√fs/g, wang2022sensors_table02) vs the
#   paper's 0.067–0.080°: the real sensor is noisier than Table 3 at our
#   assumed 200 Hz. The claim < 0.1° holds.
# * ref. [16] dynamic ≈ 2.41° vs 2.8–3.7°: lever-arm acceleration read as
#   angle, scaled by the unknown lever arm and move profile. It fails in
#   motion, as in the paper.
# * RAMS dynamic ≈ 0.08° vs 0.41–0.46°: the simulation has no sensor-to-
#   reference latency; the paper's value most likely includes one (0.4° at
#   ~40 °/s peak rate is ~10 ms). The claim < 0.5° holds.
# * RAMS static: the claim < 0.02° **fails** with the ZVD-switched EKF
#   (≈ 0.032°, band ≈ 0.028–0.042°, every axis and seed) but **holds** with
#   oracle switching (≈ 0.012°) — and the paper's 0.0145, 0.0182 and 0.0118
#   all lie inside the oracle-switched bands. Table 1's 0.01 s windows flag the
#   slow ends of every move as static, where the tangential lever-arm
#   acceleration is read as angle, and the EKF, whose covariance is small
#   after a long rest, takes a while to recover. With the ZVD of Table 1 alone
#   (no gyro condition) it is much worse (≈ 0.12°).

# %%
for name in table4_axes():
    assert _get(name, "RAMS (oracle switching)", "mtcal_static_median") < 0.02
    assert _get(name, "RAMS", "mtcal_dynamic_median") < 0.5
    assert _get(name, "ref. [16]", "mtcal_static_median") < 0.1
    assert _get(name, "ref. [16]", "mtcal_dynamic_median") > 1.0
    assert _get(name, "AHRS stand-in", "mtcal_static_median") > 0.1
    assert _get(name, "AHRS stand-in", "mtcal_dynamic_median") > 0.1
    assert _get(name, "RAMS", "mtcal_static_median") < _get(name, "RAMS (Table 1 ZVD only)", "mtcal_static_median")
    # the simulation-level fact behind the failed static claim: the ZVD switching, not the filter, costs it
    assert _get(name, "RAMS", "static_low") > _get(name, "RAMS (oracle switching)", "static_high")

# %% [markdown]
# ## wang2022sensors_fig13 — standing still for 1 min after running
#
# After `DRIFT_RUN_S` of random steps (10 min at full size) both systems stand
# still for 60 s. RAMS is held by the accelerometer; the AHRS stand-in's
# angle follows the wandering magnetic heading.

# %%
dr = run_drift(RotationSetup(), imu, DRIFT_TRIALS, rng, run_s=DRIFT_RUN_S, stand_s=60.0)
ts = dr.time_s[dr.standing] - dr.time_s[dr.standing][0]
fig, ax = plt.subplots(figsize=(8, 4))
for k in range(min(DRIFT_TRIALS, 4)):
    ax.plot(ts, deg(dr.err_ahrs[k, dr.standing]), color="tab:red", lw=0.8, label="AHRS stand-in" if k == 0 else None)
    ax.plot(ts, deg(dr.err_rams[k, dr.standing]), color="tab:blue", lw=0.8, label="RAMS" if k == 0 else None)
ax.set_xlabel("time standing (s)")
ax.set_ylabel("angle error (deg)")
ax.legend()
display(report.save_figure(fig, "wang2022sensors_fig13"))
# drift = change of the 1-s mean from the first to the last second of the stand
n1 = int(imu.fs_hz)
def drift(e):
    s = deg(e[:, dr.standing])
    return np.abs(s[:, -n1:].mean(axis=1) - s[:, :n1].mean(axis=1))
d_r, d_a = drift(dr.err_rams), drift(dr.err_ahrs)
b_dr, b_da = metrics.percentile_band(d_r), metrics.percentile_band(d_a)
print(f"1-min drift over {DRIFT_TRIALS} trials, RAMS: median {b_dr['median']:.4f} deg, max {d_r.max():.4f} deg; "
      f"AHRS stand-in: median {b_da['median']:.4f} deg [{b_da['low']:.4f}, {b_da['high']:.4f}]")
rows.append(compare.comparison_row("wang2022sensors_fig13", "1-min drift RAMS (deg)", "constant", float(b_dr["median"]),
                                 "RAMS holds (every trial < 0.02 deg)", bool(d_r.max() < 0.02), band=b_dr))
rows.append(compare.comparison_row("wang2022sensors_fig13", "1-min drift AHRS stand-in (deg)", "shifts", float(b_da["median"]),
                                 "AHRS drifts (median > 5 x RAMS max)", bool(b_da["median"] > 5 * d_r.max()),
                                 band=b_da))

# %%
assert d_r.max() < 0.02 and b_da["median"] > 5 * d_r.max()

# %% [markdown]
# ## wang2022sensors_fig14 — maximum RAMS error per angle (sweep holds)
#
# Per 10° hold of the wang2022sensors_table05 sweeps (all three axes), the maximum |error|
# over the settled second half of each 1 s hold (mtcal's reading of "the
# measurement error for various angles"); curves: median and 95 % band over
# trials. The paper's claim is about one experiment, so the number compared is
# each experiment's (trial × axis) largest per-angle error over the whole
# sweep, median and 95 % band over experiments. The claim holds in the median
# (≈ 0.034°); the band's upper end is ≈ 0.05°, so a few per cent of simulated
# experiments just reach the paper's bound.
# Over the *whole* hold the maximum is dominated by the first samples after
# each move, where the ZVD-switched filter is still pulling back the error
# picked up at the slow end of the move (see wang2022sensors_table05): reported, not claimed.

# %%
def per_hold_max(res, err, settled=True):
    holds = [sl for sl in rest_intervals(res.true_static & res.sweep)]
    use = [slice((sl.start + sl.stop) // 2, sl.stop) if settled else sl for sl in holds]
    return np.stack([np.max(np.abs(deg(err[:, sl])), axis=1) for sl in use], axis=1), holds


fig, ax = plt.subplots(figsize=(8, 4))
worst = []
for name, res in all_stat.items():
    mx, holds = per_hold_max(res, res.err_rams)
    angles = deg(res.theta_true_rad[0, [sl.start for sl in holds]])
    b = metrics.percentile_band(mx, axis=0)
    ax.fill_between(angles, b["low"], b["high"], alpha=0.2)
    ax.plot(angles, b["median"], "o-", ms=3, label=name)
    worst.append(float(np.max(b["median"])))
ax.axhline(0.05, color="k", ls=":", label="0.05° (paper)")
ax.set_xlabel("rotation angle (deg)")
ax.set_ylabel("max |error| in hold (deg)")
ax.legend()
display(report.save_figure(fig, "wang2022sensors_fig14"))
# one experiment = one trial on one axis: its largest per-angle max error over the sweep
exp_settled = np.concatenate([per_hold_max(res, res.err_rams)[0].max(axis=1) for res in all_stat.values()])
exp_whole = np.concatenate([per_hold_max(res, res.err_rams, settled=False)[0].max(axis=1)
                            for res in all_stat.values()])
b14, b14w = metrics.percentile_band(exp_settled), metrics.percentile_band(exp_whole)
print(f"largest median per-hold max error (curves above), settled half: {max(worst):.4f} deg")
print(f"per experiment, max over angles, settled half: median {b14['median']:.4f} deg "
      f"[{b14['low']:.4f}, {b14['high']:.4f}]; whole hold: median {b14w['median']:.4f} deg "
      f"[{b14w['low']:.4f}, {b14w['high']:.4f}] ({exp_settled.size} experiments)")
rows.append(compare.comparison_row("wang2022sensors_fig14", "max error over all angles, settled half-hold, per experiment (deg)",
                                 "< 0.05", float(b14["median"]), "max error per angle < 0.05 deg",
                                 bool(b14["median"] < 0.05), band=b14))
rows.append(compare.comparison_row("wang2022sensors_fig14", "max error over all angles, whole hold, per experiment (deg)", "< 0.05",
                                 float(b14w["median"]), "(not claimed: includes post-move transient)", None,
                                 band=b14w))

# %%
assert b14["median"] < 0.05

# %% [markdown]
# ## Sensitivity — Table 3's ambiguous rows and the 50 mg bias
#
# Fig. 11 set-up, proposed method, median of the per-angle maximum error.
# Random-walk rows read as u·√Hz (default), as a per-sample step (×√fs), or
# off; and Table 3's 50 mg accelerometer bias applied literally (no ref. [30]
# calibration): Eq 28 assumes no bias, so the model is off by (I − Rᵀ) b.

# %%
variants = {"RW as u*sqrt(Hz) (default)": imu,
            "RW as per-sample step": ImuSpec(random_walk_interpretation="per_sample"),
            "RW off": ImuSpec(random_walk_interpretation="none"),
            "50 mg bias uncompensated": ImuSpec(accel_bias_compensated=False)}
sens = []
for lab, im in variants.items():
    r = run_fig11(RotationSetup(), im, SENS_REPS, rng, step_deg=15.0)
    sens.append({"variant": lab, "median_max_err_deg": float(np.median(deg(r.max_err_rams))),
                 "worst_max_err_deg": float(np.max(deg(r.max_err_rams))),
                 "ref16_median_max_err_deg": float(np.median(deg(r.max_err_ref16)))})
sens = pd.DataFrame(sens)
report.save_table(sens, "wang2022sensors_extra_accel_bias_sensitivity")
report.show_table(sens)

sens_ratio = float(sens.median_max_err_deg.iloc[3] / sens.median_max_err_deg.iloc[0])
rows.append(compare.comparison_row("wang2022sensors_extra_accel_bias_sensitivity", "50 mg uncompensated / calibrated: median max error", "n/a", sens_ratio,
                                 "(mtcal) Eq 28 needs the ref. [30] calibration (> 10)", sens_ratio > 10))

# %%
assert sens_ratio > 10

# %% [markdown]
# ## Paper vs mtcal

# %%
table = compare.comparison_table(rows)
table.to_csv(report.output_dir() / "data" / "wang2022sensors_ekf_comparison.csv", index=False)
report.show_table(table)
print(compare.claims_summary(table))
print(compare.band_summary(table))

# %%
# Claims that fail in simulation are reported, not faked: only the RAMS static < 0.02 deg rows (see wang2022sensors_table05).
failed = table[table["holds"] == False]  # noqa: E712
print(failed[["artifact", "quantity"]].to_string(index=False))
assert set(failed["claim"]) <= {"RAMS static RMSE < 0.02 deg"}, "an unexpected claim failed"
