"""wang2022sensors figures, drawn from the data the :mod:`.artifacts` producers return.

Same quantity, axes and units (degrees) as the paper's figure; the title names the
paper's figure and our artifact ID; legends sit outside the data; labels derive
from the scenario values (``labels``). Each function returns a matplotlib Figure.

References
----------
Wang C., Tu X., Chen Q., Yang Q., Fang T., Sensors 2022, 22, 8996, doi:10.3390/s22228996.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.ticker import FixedLocator, NullFormatter, NullLocator

__all__ = ["plot_fig06", "plot_fig09", "plot_fig11", "plot_fig12", "plot_axis_error_vs_rest", "plot_fig13",
           "plot_fig14", "plot_error_model"]


def _legend_below(ax, ncol: int = 2, y: float = -0.22) -> None:
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, y), ncol=ncol, frameon=False, fontsize=9)


def plot_fig06(data: dict):
    """Fig. 6 — θ, ‖a‖ with Table 1's band, and the static flags (true, Table 1 ZVD, ZVD + gyro)."""
    d = data["demo"]
    fig, axs = plt.subplots(3, 1, figsize=(8, 6.5), sharex=True)
    axs[0].plot(d.time_s, d.theta_deg)
    axs[0].set_ylabel("θ (deg)")
    axs[1].plot(d.time_s, d.accel_norm_m_s2, lw=0.6, label=f"‖a‖, median trial {d.trial + 1} of {d.trials}")
    axs[1].set_ylabel("‖a‖ (m/s²)")
    if d.share_table1 is None:  # a record without the ensemble: the drawn trial's flags
        axs[2].step(d.time_s, d.true_static + 0.0, "k", lw=2, where="post", label="true rest")
        axs[2].step(d.time_s, d.flags_table1 * 0.9, where="post", label="Table 1 ZVD")
        axs[2].step(d.time_s, d.flags_gyro * 0.8, where="post", label="ZVD + gyro (mtcal)")
        axs[2].set_ylabel("static flag")
    else:
        axs[2].fill_between(d.time_s, 0.0, d.true_static + 0.0, step="post", color="0.85", label="true rest")
        axs[2].step(d.time_s, d.share_table1, where="post", label="Table 1 ZVD")
        axs[2].step(d.time_s, d.share_gyro, "--", where="post", label="ZVD + gyro (mtcal)")
        axs[2].set_ylabel(f"share of {d.trials}\ntrials flagged static")
    axs[2].set_yticks([0, 1])
    axs[2].set_xlabel("time (s)")
    axs[1].axhspan(9.76, 9.84, color="tab:green", alpha=0.15, label="Table 1 ‖a‖ band")
    axs[1].legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False, fontsize=9)
    axs[2].legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False, fontsize=9)
    axs[0].set_title(f"Paper Fig. 6 (wang2022sensors_fig06): ZVD on a rotate/hold record\n{data['labels']['rig']}\n"
                     f"‖a‖: median trial {d.trial + 1} of {d.trials} (by Table 1 false-static share); flags: all trials",
                     fontsize=10)
    fig.tight_layout()
    return fig


def plot_fig09(data: dict):
    """Fig. 9 — (a) reference angle, (b) error with / without ZVD, (c) ‖a‖, (d) ‖ω‖."""
    r = data["run"]
    fig, axs = plt.subplots(4, 1, figsize=(8, 8), sharex=True)
    axs[0].plot(r.time_s, r.theta_deg)
    axs[0].set_ylabel("(a) θ ref (deg)")
    if "err_zvd" in data:  # the ensemble: median and band (or range) over all trials
        for b, style, lab in ((data["err_zvd"], "-", "EKF with ZVD"), (data["err_std"], "--", "standard EKF")):
            line, = axs[1].plot(r.time_s, b["median"], style, label=f"{lab}: {b['label']}")
            axs[1].fill_between(r.time_s, b["low"], b["high"], color=line.get_color(), alpha=0.25)
    else:
        axs[1].plot(r.time_s, r.err_zvd_deg, label="EKF with ZVD")
        axs[1].plot(r.time_s, r.err_std_deg, "--", label="standard EKF")
    axs[1].set_ylabel("(b) error (deg)")
    axs[1].legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False, fontsize=9)
    axs[2].plot(r.time_s, r.accel_norm_m_s2)
    axs[2].set_ylabel("(c) ‖a‖ (m/s²)")
    axs[3].plot(r.time_s, r.gyro_norm_deg_s)
    axs[3].set_ylabel("(d) ‖ω‖ (°/s)")
    axs[3].set_xlabel("time (s)")
    axs[0].set_title(f"Paper Fig. 9 (wang2022sensors_fig09): EKF with / without ZVD switching\n"
                     f"{data['labels']['zvd']}\n(a, c, d): median trial {r.trial + 1} of {r.trials} (by the moving RMSE "
                     "ratio with/without ZVD); (b): all trials",
                     fontsize=10)
    fig.tight_layout()
    return fig


def plot_fig11(data: dict):
    """Fig. 11 — max error over 1000 measurements vs rotation angle, proposed vs ref. [16] (deg)."""
    ang = data["result"].angles_deg
    fig, ax = plt.subplots(figsize=(8, 4.2))
    for b, lab in ((data["rams"], "proposed (RAMS EKF)"), (data["ref16"], "ref. [16] (accelerometer only)")):
        ax.fill_between(ang, b["low"], b["high"], alpha=0.25)
        ax.plot(ang, b["median"], "o-", ms=3, label=f"{lab}: {b['label']}")
    ax.set_xlabel("rotation angle (deg)")
    ax.set_ylabel("max error over 1000 measurements (deg)")
    ax.set_xticks(np.arange(-180, 181, 45))
    ax.set_title(f"Paper Fig. 11 (wang2022sensors_fig11): {data['labels']['axis']}", fontsize=10)
    _legend_below(ax, ncol=1)
    fig.tight_layout()
    return fig


def plot_fig12(data: dict):
    """Fig. 12 — ‖g1 − g0‖ vs axis elevation γ, and the axis-estimate error vs γ (beyond the paper)."""
    fig, axs = plt.subplots(1, 2, figsize=(10, 4.2))
    axs[0].plot(data["gamma_deg"], data["gnorm_g"], "o-")
    axs[0].axvline(60, color="k", ls=":")
    axs[0].set_xlabel("axis elevation γ (deg)")
    axs[0].set_ylabel("‖g1 − g0‖ (g)")
    axs[0].set_title("Paper Fig. 12 (wang2022sensors_fig12)", fontsize=10)
    g = data["gamma_mc_deg"]
    axs[1].fill_between(g, data["mc_low"], data["mc_high"], alpha=0.3,
                        label=f"Monte Carlo {data['band_label'].replace('median, ', '')}")
    axs[1].plot(g, data["mc_median"], "o-", label="Monte Carlo median")
    axs[1].plot(g, data["formula_median"], "k--", label="first-order formula (median)")
    axs[1].set_yscale("log")
    axs[1].set_xlabel("axis elevation γ (deg)")
    axs[1].set_ylabel("axis error (deg)")
    axs[1].set_title("beyond the paper: axis error, 1 s rests", fontsize=10)
    _legend_below(axs[1], ncol=1, y=-0.18)
    fig.tight_layout()
    return fig


def plot_axis_error_vs_rest(data: dict):
    """Axis error vs rest duration (log-log), ticks only at the simulated durations (no overprint)."""
    r = data["rest_s"]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.fill_between(r, data["zvd_low"], data["zvd_high"], alpha=0.3,
                    label=f"{data['band_label'].replace('median, ', '')} (ZVD rests, IMU walks)")
    ax.plot(r, data["zvd_median"], "o-", label=f"median (ZVD rests), slope {data['slope_zvd']:.2f}")
    ax.plot(r, data["white_median"], "s-", label=f"median (true rests, white noise), slope {data['slope_white']:.2f}")
    ax.plot(r, data["formula_median"], "k--", label="first-order formula, slope −0.50")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.xaxis.set_major_locator(FixedLocator(r))
    ax.xaxis.set_major_formatter(plt.FuncFormatter(lambda x, _: f"{x:g}"))
    ax.xaxis.set_minor_locator(NullLocator())
    ax.yaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("rest duration per position (s)")
    ax.set_ylabel("axis error (deg)")
    ax.set_title(f"wang2022sensors_extra_axis_error_vs_rest (beyond the paper)\n{data['labels']['axis']}",
                 fontsize=10)
    _legend_below(ax, ncol=1, y=-0.16)
    fig.tight_layout()
    return fig


def plot_fig13(data: dict, n_show: int = 4):
    """Fig. 13 — each trial's angle change since its first second standing still, for 1 min after running, RAMS
    vs AHRS stand-in (deg): median over trials and the 95 % band (≥ 1000 trials) or the range (fewer) (``n_show``
    is kept for callers and unused)."""
    d = data["run"]
    fig, ax = plt.subplots(figsize=(8, 4.2))
    for b, color, lab in ((data["ahrs"], "tab:red", "AHRS stand-in"), (data["rams"], "tab:blue", "RAMS")):
        ax.fill_between(d.time_s, b["low"], b["high"], color=color, alpha=0.25,
                        label=f"{lab}: {b['label'].replace('median, ', '')}")
        ax.plot(d.time_s, b["median"], color=color, lw=0.9, label=f"{lab}: median")
    ax.set_xlabel("time standing still (s)")
    ax.set_ylabel("angle change since the first 1 s (deg)")
    ax.set_title(f"Paper Fig. 13 (wang2022sensors_fig13): {data['rams']['label']}\n"
                 f"{data['labels']['rig']}", fontsize=10)
    _legend_below(ax)
    fig.tight_layout()
    return fig


def plot_fig14(data: dict):
    """Fig. 14 — RAMS max |error| per angle under both readings of the hold, fitted-model median and
    posterior-weighted 2.5–97.5 % of the grid runs (deg): the whole hold (the claim's reading, held out) and the
    settled second half (a window chosen after the whole-hold reading failed: tuned), each with its verdict."""
    ang = data["angle_deg"]
    fig, ax = plt.subplots(figsize=(8, 4.2))
    for key, window, color, name in (("whole_", "whole hold", "tab:red", "whole hold (the claim's reading)"),
                                     ("", "settled half", "tab:blue", "settled 2nd half (window chosen after: tuned)")):
        ax.fill_between(ang, data[f"{key}low"], data[f"{key}high"], color=color, alpha=0.25,
                        label=f"{name}: 2.5–97.5 % of {data['n_runs']} grid runs")
        ax.plot(ang, data[f"{key}median"], "o-", color=color, ms=3,
                label=f"{name}: median — claim {data['verdicts'][window]}")
    ax.axhline(0.05, color="k", ls=":", label="0.05° (paper's bound)")
    ax.set_xticks(np.arange(-180, 181, 45))
    ax.set_ylim(0, max(0.06, float(np.max([data["high"], data["whole_high"]])) * 1.1))
    ax.set_xlabel("rotation angle (deg)")
    ax.set_ylabel("max |error| in the hold (deg)")
    ax.set_title("Paper Fig. 14 (wang2022sensors_fig14): RAMS maximum error per angle", fontsize=10)
    _legend_below(ax, ncol=2)
    fig.tight_layout()
    return fig


def plot_error_model(table):
    """Table 5 numbers (paper) beside the posterior- and prior-predictive 95 % bands (log scale)."""
    t = table.reset_index(drop=True)
    y = np.arange(len(t))[::-1]
    fig, ax = plt.subplots(figsize=(8, 0.32 * len(t) + 1.6))
    ax.hlines(y + 0.15, t.prior_low, t.prior_high, color="0.6", lw=4, label="prior-predictive 95 % band")
    ax.hlines(y - 0.15, t.fitted_low, t.fitted_high, color="tab:blue", lw=4, label="fitted 95 % band")
    fit = t.role == "train"
    ax.plot(t.paper_deg[fit], y[fit], "kx", ms=7, label="paper (training)")
    ax.plot(t.paper_deg[~fit], y[~fit], "o", color="tab:red", ms=6, label="paper (held out)")
    ax.set_yticks(y)
    ax.set_yticklabels([f"{r.axis} {r.system} {r.kind}" for r in t.itertuples()], fontsize=8)
    ax.set_xscale("log")
    ax.set_xlabel("RMSE (deg)")
    ax.set_title("Paper Table 5 vs the identified error model (wang2022sensors_extra_error_model)", fontsize=10)
    _legend_below(ax, ncol=2, y=-0.8 / (0.32 * len(t) + 1.6))
    fig.tight_layout()
    return fig
