"""broad2021 figures (the only module importing matplotlib); each takes an Artifact's data."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.ticker import FuncFormatter, NullFormatter

__all__ = ["bakeoff_groups", "median_trial", "twin_coverage", "grids"]


def bakeoff_groups(art):
    """One panel per BROAD group category: median inclination RMSE per filter and group (bars: min-max)."""
    g = art.data["groups"]
    filters = art.data["filters"]
    cats = list(dict.fromkeys(g.category))
    fig, axes = plt.subplots(1, len(cats), figsize=(4.2 * len(cats), 3.8), squeeze=False, sharey=True)
    width = 0.8 / len(filters)
    for ax, cat in zip(axes[0], cats):
        sub = g[g.category == cat]
        names = list(dict.fromkeys(sub.group))
        x = np.arange(len(names))
        for i, f in enumerate(filters):
            s = sub[sub["filter"] == f].set_index("group").reindex(names)
            med = s.median_inclination_rmse_deg.to_numpy()
            err = np.vstack([med - s.min_deg.to_numpy(), s.max_deg.to_numpy() - med])
            ax.bar(x + (i - (len(filters) - 1) / 2) * width, med, width, yerr=err, capsize=1.5, label=f,
                   error_kw={"lw": 0.6})
        count = lambda n: int(sub[sub.group == n].trials.iloc[0])  # noqa: E731
        ax.set_xticks(x, [f"{n.replace('_', ' ')}\n({count(n)} trial{'s' if count(n) != 1 else ''})" for n in names],
                      fontsize=7, rotation=20, ha="right")
        ax.set_yscale("log")
        ax.set_title(cat)
        ax.grid(True, axis="y", alpha=0.3)
    axes[0][0].set_ylabel("inclination RMSE (deg), median; bars min-max")
    axes[0][-1].legend(fontsize=7)
    fig.suptitle("broad2021: 6D filters on the real trials (BROAD groups)")
    fig.tight_layout()
    return fig


def median_trial(art):
    """Inclination error of every filter over time on the median trial (movement phase shaded off)."""
    s = art.data
    filters = [k for k in s if k not in ("trial", "time_s", "movement")]
    fig, ax = plt.subplots(figsize=(9, 4.4))
    t = s["time_s"]
    for f in filters:
        ax.plot(t, s[f], lw=0.6, label=f)
    still = ~s["movement"]
    ax.fill_between(t, 0, 1, where=still, transform=ax.get_xaxis_transform(), color="0.9", label="not movement phase")
    ax.set_yscale("log")
    ax.set_ylim(1e-3, None)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("inclination error (deg)")
    ax.set_title(f"broad2021 median trial {s['trial']} (by the filters' median inclination RMSE)")
    ax.legend(fontsize=7, ncol=4, loc="upper center", bbox_to_anchor=(0.5, -0.18), frameon=False)   # off the data
    fig.tight_layout()
    return fig


def twin_coverage(art):
    """Real inclination RMSE against the twin's predicted range, per trial, one panel per filter."""
    tw = art.data["twin"]
    filters = list(dict.fromkeys(tw["filter"]))
    fig, axes = plt.subplots(1, len(filters), figsize=(2.6 * len(filters), 4.2), squeeze=False, sharey=True)
    for ax, f in zip(axes[0], filters):
        s = tw[tw["filter"] == f].reset_index(drop=True)
        y = np.arange(len(s))
        ax.hlines(y, s.twin_low_deg, s.twin_high_deg, color="tab:blue", lw=3, label=f"twin range (n={int(s.n.iloc[0])})")
        ax.plot(s.real_deg, y, "o", ms=3.5, color="k", label="real")
        miss = ~s.inside
        ax.plot(s.real_deg[miss], y[miss], "o", ms=3.5, color="tab:red", label="real, outside")
        ax.set_xscale("log")
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        ax.set_title(f"{f}\n{int(s.inside.sum())}/{len(s)} inside", fontsize=8)
        ax.set_yticks(y, [t[:2] for t in s.trial], fontsize=7)
        ax.set_xlabel("inclination RMSE (deg)", fontsize=7)
        ax.grid(True, axis="x", alpha=0.3)
    axes[0][0].set_ylabel("trial")
    axes[0][0].legend(fontsize=6, loc="lower left")
    fig.suptitle("broad2021: the simulated twin asked to predict each real trial")
    fig.tight_layout()
    return fig


def grids(art):
    """Published vs ours over BROAD's grids (inclination RMSE), every trial: one panel per filter."""
    g = art.data["grids"]
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.6))
    for ax, f, unit in zip(axes, ("madgwick", "mahony"), ("beta (rad/s)", "K_p (1/s)")):
        s = g[g["filter"] == f]
        for trial, t in s.groupby("trial", sort=True):
            ax.plot(t.gain, t.published_inclination_deg, "-", lw=2.5, alpha=0.35)
            ax.plot(t.gain, t.ours_inclination_deg, "k:", lw=0.7)
        ax.set_yscale("log")
        ax.yaxis.set_minor_formatter(FuncFormatter(lambda v, _: f"{v:g}" if f"{v:g}"[0] in "1235" else ""))
        ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        ax.tick_params(axis="y", which="minor", labelsize=7)
        ax.set_xlabel(unit)
        ax.set_ylabel("inclination RMSE (deg)")
        ax.set_title(f"{f} 9D: published (thick) vs ours (dotted)", fontsize=9)
    fig.tight_layout()
    return fig
