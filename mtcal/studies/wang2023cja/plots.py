"""wang2023cja figures (matplotlib imported here only): same quantities, axes and units as the paper's.

References
----------
Wang X., Zhao X., Zhou B., Wei Q., Zhang R., "Installation error calibration for MEMS
angular measurement system in hypersonic wind tunnel", Chin. J. Aeronaut. 2023,
doi:10.1016/j.cja.2022.12.006.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

__all__ = ["before_after_figure", "wind_on_figure", "amd_figure"]


def before_after_figure(trace: dict, name: str, channels, *, title: str, xlabel: str = "time (s)"):
    """Paper Figs 7, 8, 11: angle errors (deg) before and after calibration vs time, one panel per channel.

    ``trace`` holds ``<name>_time_s`` (s) and ``<name>_before_err`` / ``<name>_after_err`` (N, 3) rad.
    """
    fig, axes = plt.subplots(len(channels), 1, sharex=True, figsize=(7.5, 5.5), squeeze=False,
                             constrained_layout=True)
    axes = axes[:, 0]
    t = trace[f"{name}_time_s"]
    for ax, (j, label) in zip(axes, channels):
        for state, color in (("before", "tab:red"), ("after", "tab:blue")):
            ax.plot(t, np.degrees(trace[f"{name}_{state}_err"][:, j]), color=color, lw=0.8,
                    label=f"{state} calibration")
        ax.set_ylabel(f"{label} error (°)")
        ax.grid(alpha=0.3)
    axes[0].legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    axes[-1].set_xlabel(xlabel)
    fig.suptitle(title, fontsize=10)
    return fig


def wind_on_figure(trace: dict, *, title: str, n_groups: int = 5):
    """Paper Fig 10 (beside it): pitch after calibration minus the commanded AoA (deg), per wind-on group.

    Plotting pitch − reference makes the elastic offset (≈ +0.1° at 12°) and the group-to-group
    scatter (≈ 0.01°) visible; the groups are offset in time to their own schedule.
    """
    fig, ax = plt.subplots(figsize=(7.5, 4.2), constrained_layout=True)
    for g in range(n_groups):
        t = trace[f"wind_time_s_{g}"]
        ax.plot(t, np.degrees(trace[f"wind_pitch_{g}"] - trace[f"wind_reference_{g}"]), lw=0.7,
                label=f"Group {g + 1}")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("pitch − reference AoA (°)")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    ax.set_title(title, fontsize=10)
    return fig


def amd_figure(trace: dict, threshold_pct: float, *, title: str):
    """Beyond the paper: the QNCF's AMD statistic (% of g) in wind-on Group 1 against its threshold."""
    fig, ax = plt.subplots(figsize=(7.5, 3.6), constrained_layout=True)
    ax.plot(trace["wind_time_s_0"], trace["amd_pct"], lw=0.5, color="0.3", label="AMD")
    ax.axhline(threshold_pct, color="tab:red", ls="--", label=f"threshold {threshold_pct:g} %")
    ax.set_yscale("log")
    ax.set_xlabel("time (s), Group 1")
    ax.set_ylabel("AMD (% of g)")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    ax.set_title(title, fontsize=10)
    return fig
