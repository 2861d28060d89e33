"""wang2023cja figures (matplotlib imported here only): same quantities, axes and units as the paper's.

References
----------
wang2023cja Figs 7–8 (§4.1), Figs 10–11 (§4.2) (full citation: :mod:`mtcal.studies.wang2023cja`).
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from mtcal.core import metrics

__all__ = ["before_after_figure", "wind_on_figure", "amd_figure", "error_vs_positions_figure", "error_vs_noise_figure",
           "noise_distance_figure", "ensemble_figure", "fig07", "fig08", "fig10", "fig11", "extra_amd"]


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


def wind_on_figure(trace: dict, *, title: str, n_groups: int = 5, smooth_s: float = 0.2):
    """Paper Fig 10 (made readable): pitch after calibration minus the commanded AoA (deg), per wind-on group.

    Plotting pitch − reference instead of pitch makes the elastic offset (≈ +0.1–0.2° at 12°) and the
    group-to-group scatter (≈ 0.01°) visible; a ``smooth_s`` moving mean removes the model vibration.
    Each group on its own time axis (Group 5 moves at a different rate).
    """
    fig, ax = plt.subplots(figsize=(7.5, 4.2), constrained_layout=True)
    for g in range(n_groups):
        t = trace[f"wind_time_s_{g}"]
        y = np.degrees(trace[f"wind_pitch_{g}"] - trace[f"wind_reference_{g}"])
        n = max(1, int(round(smooth_s / (t[1] - t[0]))))
        y = np.convolve(y, np.ones(n) / n, mode="same")
        ax.plot(t[n:-n], y[n:-n], lw=1.0, label=f"Group {g + 1}")
    ax.set_xlabel("time (s)")
    ax.set_ylabel(f"pitch − reference AoA (°), {smooth_s:g} s mean")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    ax.set_title(title, fontsize=10)
    return fig


def amd_figure(trace: dict, threshold_pct: float, *, title: str, flow_start_s: float | None = None,
               counted_from_s: float | None = None):
    """Beyond the paper: the QNCF's AMD statistic (% of g) in wind-on Group 1 against its threshold."""
    fig, ax = plt.subplots(figsize=(7.5, 3.6), constrained_layout=True)
    ax.plot(trace["wind_time_s_0"], trace["amd_pct"], lw=0.5, color="0.3", label="AMD")
    ax.axhline(threshold_pct, color="tab:red", ls="--", label=f"threshold {threshold_pct:g} %")
    if flow_start_s is not None:
        ax.axvspan(0.0, flow_start_s, color="0.9", label=f"wind off (flow starts at {flow_start_s:g} s)")
    if counted_from_s is not None:
        ax.axvline(counted_from_s, color="k", ls=":", lw=0.8, label=f"gate fraction counted from {counted_from_s:g} s")
    ax.set_yscale("log")
    ax.set_xlabel("time (s), Group 1")
    ax.set_ylabel("AMD (% of g)")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    ax.set_title(title, fontsize=10)
    return fig


def _spaced_ticks(values, min_ratio: float = 1.4) -> list:
    """Values kept as log-axis ticks so that neighbours differ by at least ``min_ratio`` (no overprint)."""
    out = []
    for v in sorted(values):
        if not out or v / out[-1] >= min_ratio:
            out.append(v)
    return out


_COLOR = {"eq13": "tab:red", "so4": "tab:blue", "mounting": "tab:green"}
_LABEL = {"eq13": "Eq 13 (16 par.)", "so4": "SO(4) (6 par.)", "mounting": "mounting (3 par.)"}


def error_vs_positions_figure(table, *, title: str, paper_k: int = 6):
    """Beyond the paper: attitude RMSE after calibration (deg) vs number of positions, 2×2 panels."""
    truths, layouts = list(dict.fromkeys(table.truth)), ("symmetric", "random")
    fig, axes = plt.subplots(2, 2, figsize=(10, 7), sharex=True, sharey=True, constrained_layout=True)
    for i, truth in enumerate(truths):
        for j, layout in enumerate(layouts):
            ax = axes[i, j]
            for m in _COLOR:
                d = table[(table.truth == truth) & (table.layout == layout) & (table.method == m)]
                ax.plot(d.K, d.median_deg, "o-", color=_COLOR[m], label=_LABEL[m], ms=4)
                ax.fill_between(d.K, d.low_deg, d.high_deg, color=_COLOR[m], alpha=0.15)
            ax.axvline(paper_k, color="0.5", ls=":", lw=1)
            ax.set_yscale("log")
            ax.set_title(f"{truth}, {layout} layout", fontsize=10)
            if j == 0:
                ax.set_ylabel("attitude RMSE after calibration (°)")
            if i == 1:
                ax.set_xlabel("number of calibration positions K")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=3, fontsize=8)
    fig.suptitle(title, fontsize=10)
    return fig


def error_vs_noise_figure(table, *, sigma_deg: float, title: str):
    """Beyond the paper: attitude RMSE after calibration (deg) vs sensor-quaternion noise σ (deg)."""
    from matplotlib.ticker import NullFormatter

    truths = list(dict.fromkeys(table.truth))
    levels = sorted(set(table.sigma_deg))
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.4), sharey=True, constrained_layout=True)
    for ax, truth in zip(axes, truths):
        for m in _COLOR:
            d = table[(table.truth == truth) & (table.method == m)]
            ax.plot(d.sigma_deg, d.median_deg, "o-", color=_COLOR[m], label=_LABEL[m], ms=4)
            ax.fill_between(d.sigma_deg, d.low_deg, d.high_deg, color=_COLOR[m], alpha=0.15)
        ax.axvline(sigma_deg, color="0.5", ls=":", lw=1)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ticks = _spaced_ticks(levels)
        ax.set_xticks(ticks, [f"{s:g}" for s in ticks])
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.set_xlabel("per-position error σ per axis (°)")
        ax.set_title(f"{truth}, paper's six positions", fontsize=10)
    axes[0].set_ylabel("attitude RMSE after calibration (°)")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=3, fontsize=8)
    fig.suptitle(title, fontsize=10)
    return fig


def noise_distance_figure(table, lines: dict, *, sigma_deg: float, title: str):
    """Beyond the paper: distance of the Eq 13 estimate to O(4) vs σ, with the printed matrices' distances."""
    from matplotlib.ticker import NullFormatter

    fig, ax = plt.subplots(figsize=(7.5, 4.4), constrained_layout=True)
    spread = ("95 % band" if (table["kind"] == "95 % band").all() else "range") if "kind" in table else "95 % band"
    n = f" of {int(table['n'].min())} trials" if "n" in table else ""
    ax.plot(table.sigma_deg, table["median"], "o-", color=_COLOR["eq13"], label=f"Eq 13 estimate (median, {spread}{n})")
    ax.fill_between(table.sigma_deg, table.low, table.high, color=_COLOR["eq13"], alpha=0.15)
    for (name, value), style in zip(lines.items(), ("--", ":")):
        ax.axhline(value, color="k", ls=style, lw=1, label=name)
    ax.axvline(sigma_deg, color="0.5", ls="-", lw=0.5)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ticks = _spaced_ticks(list(table.sigma_deg))
    ax.set_xticks(ticks, [f"{s:g}" for s in ticks])
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("per-position error σ per axis (°)")
    ax.set_ylabel("distance of Eq 13 matrix to O(4)")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    ax.set_title(title, fontsize=10)
    return fig


def ensemble_figure(time_s, err_before_rad, err_after_rad, channels, paper_maxae_deg: dict, *, title: str,
                    xlabel: str = "time (s)"):
    """Paper Figs 7, 8, 11 over the ensemble: median and 95 % band over trials of the error (deg) vs time
    (from fewer than ``metrics.MIN_BAND_DRAWS`` trials the min–max range, labelled with its count).

    Parameters
    ----------
    time_s : ndarray (N,)
        Time (s) of the kept samples.
    err_before_rad, err_after_rad : ndarray (T, N, 3)
        Every trial's error series (rad, Eq 8 frame).
    channels : sequence of (index, label)
    paper_maxae_deg : dict label → (before, after)
        The paper's printed MaxAE (deg), drawn as ± dashed lines.
    """
    fig, axes = plt.subplots(len(channels), 1, sharex=True, figsize=(7.5, 5.5), squeeze=False,
                             constrained_layout=True)
    axes = axes[:, 0]
    n = min(len(time_s), err_before_rad.shape[1])
    t = np.asarray(time_s)[:n]
    for ax, (j, label) in zip(axes, channels):
        for k, (state, err, color) in enumerate((("before", err_before_rad, "tab:red"),
                                                 ("after", err_after_rad, "tab:blue"))):
            e = np.degrees(np.asarray(err, float)[:, :n, j])
            b = metrics.band_or_range(e, axis=0)       # 95 % band from >= 1000 trials, else the range
            ax.fill_between(t, b["low"], b["high"], color=color, alpha=0.2, lw=0)
            ax.plot(t, b["median"], color=color, lw=0.8, label=f"{state} calibration: median, {b['label']}")
            pv = paper_maxae_deg.get(label)
            if pv is not None:    # dashes offset between before and after: equal values stay visible
                dash = (4 * k, (4, 4))
                ax.axhline(pv[k], color=color, ls=dash, lw=0.8,
                           label=f"paper MaxAE {state} ±{pv[k]:g}°")
                ax.axhline(-pv[k], color=color, ls=dash, lw=0.8)
        ax.set_ylabel(f"{label} error (°)")
        ax.grid(alpha=0.3)
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7)   # each panel its own values
    axes[-1].set_xlabel(xlabel)
    fig.suptitle(title, fontsize=10)
    return fig


def _paper_maxae(table: str, labels) -> dict:
    from mtcal.reporting import paper_numbers

    p = paper_numbers.load(table)
    out = {}
    for lab in labels:
        v = [float(p.loc[(p.metric == "MaxAE") & (p.calibration_state == s), f"{lab}_deg"].iloc[0])
             for s in ("before", "after")]
        out[lab] = tuple(v)
    return out


def _sweep_ensemble(run, sweep: str, channels, table: str, title: str):
    """:func:`ensemble_figure` of one sweep of ``run`` (``"aoa"`` or ``"roll"``), ``table``'s MaxAE marked."""
    from .runs import TRACE_DECIMATION

    sw = run.sweeps[sweep]
    return ensemble_figure(run.trace[f"{sweep}_time_s"][::TRACE_DECIMATION], sw["before_err_dec"], sw["after_err_dec"],
                           channels, _paper_maxae(table, tuple(name for _, name in channels)), title=title)


def fig07(run, grade_label: str):
    """wang2023cja_fig07 (paper Fig 7): roll and yaw errors in the AoA sweep, median and 95 % band over trials,
    the paper's Table 6 MaxAE marked."""
    return _sweep_ensemble(run, "aoa", ((2, "roll"), (0, "yaw")), "wang2023cja_table06_aoa_sweep_roll_yaw_errors",
                           f"Fig. 7 (wang2023cja_fig07): roll/yaw errors, AoA sweep — {grade_label}")


def fig08(run, grade_label: str):
    """wang2023cja_fig08 (paper Fig 8): pitch and yaw errors in the roll sweep, median and 95 % band over trials,
    the paper's Table 8 MaxAE marked."""
    return _sweep_ensemble(run, "roll", ((1, "pitch"), (0, "yaw")), "wang2023cja_table08_roll_sweep_pitch_yaw_errors",
                           f"Fig. 8 (wang2023cja_fig08): pitch/yaw errors, roll sweep — {grade_label}")


def _session(run) -> str:
    """Which session a time-series figure draws (the predictive runs trace their median session)."""
    k = run.trace.get("median_trial")
    if k is None:      # no silent trial 0: a figure of one session shows the median one, by a stated rule
        raise ValueError("run.trace has no median_trial: a wind-tunnel time-series figure draws the median session "
                         "(run it through predictive.windtunnel_predictive, which traces it)")
    return f"median session ({k + 1} of {run.q_matrix.shape[0]}, by Table 10's group Std)"


def fig10(run, grade_label: str, rates_deg_s: tuple):
    """wang2023cja_fig10 (paper Fig 10): pitch − reference in the five wind-on sweeps of the median session."""
    return wind_on_figure(run.trace, title=(f"Fig. 10 (wang2023cja_fig10): pitch − reference, wind-on groups — "
                                            f"{grade_label}, {rates_deg_s[0]:g}/{rates_deg_s[1]:g} °/s\n"
                                            f"{_session(run)}"))


def fig11(run, grade_label: str):
    """wang2023cja_fig11 (paper Fig 11): roll and yaw errors in the wind-off AoA sweep, median and 95 % band over
    trials, the paper's Table 11 MaxAE marked."""
    from .runs import TRACE_DECIMATION

    nw = run.nowind
    return ensemble_figure(run.trace["nowind_time_s"][::TRACE_DECIMATION], nw["before_err_dec"], nw["after_err_dec"],
                           ((2, "roll"), (0, "yaw")),
                           _paper_maxae("wang2023cja_table11_windtunnel_nowind_roll_yaw_errors", ("roll", "yaw")),
                           title=f"Fig. 11 (wang2023cja_fig11): roll/yaw errors, wind-off sweep — {grade_label}")


def extra_amd(run, threshold_pct: float, vibration_accel_m_s2: float):
    """wang2023cja_extra_amd (beyond the paper): the AMD statistic in wind-on Group 1 of the median session."""
    from .runs import WIND_FLOW_START_S, WIND_LEAD_S

    return amd_figure(run.trace, threshold_pct, flow_start_s=WIND_FLOW_START_S, counted_from_s=WIND_LEAD_S,
                      title=f"wang2023cja_extra_amd: AMD, wind-on Group 1 — vibration {vibration_accel_m_s2:g} m/s²\n"
                            f"{_session(run)}")
