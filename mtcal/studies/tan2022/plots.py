"""tan2022 figures from the :mod:`.artifacts` / :mod:`.error_model` results (the only module importing matplotlib).

Conventions shared with notebook 00 (``conventions_eq3_erratum``): error maps
have roll φ on x and pitch θ on y, in degrees; errors are shown in degrees;
every title carries the paper's figure number and our artifact ID; labels
derive from the scenario values carried by the results.

References
----------
Tan Q., Cheng Y., Tang B., Liu X., Zhou H., Li Y., "Large-angle attitude measurement
algorithm with pitch/roll coupling" (in Chinese), J. Terahertz Sci. Electron. Inf.
Technol. 2022, 20(9):946–952, doi:10.11805/TKYDA2020404.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import LogNorm

__all__ = ["error_map", "eq3_erratum", "fig02", "extra_roll_error", "fig05", "fig08", "extra_independent_errors",
           "accel_error_model", "fig06", "fig09", "fig10", "fig11", "fig12", "extra_threshold_sweep",
           "gyro_error_model", "gyro_error_pattern"]


def error_map(ax, theta_deg, phi_deg, field_deg, levels, *, log=False, cmap="viridis"):
    """Filled contour of ``field_deg[θ, φ]`` with roll φ on x and pitch θ on y, black labelled contour lines."""
    norm = LogNorm(levels[0], levels[-1]) if log else None
    z = np.clip(field_deg, levels[0], levels[-1]) if log else field_deg
    cs = ax.contourf(phi_deg, theta_deg, z, levels=levels, cmap=cmap, norm=norm, extend="neither")
    interior = np.where((np.abs(np.asarray(theta_deg)) <= 89.0)[:, None], z, np.nan)  # pole row: fill only
    lines = ax.contour(phi_deg, theta_deg, interior, levels=levels[2:-1:3], colors="k", linewidths=0.6, norm=norm)
    ax.clabel(lines, fmt="%.3g" if log else "%.4f", fontsize=7, inline_spacing=2)
    ax.set(xlabel="roll φ (deg)", ylabel="pitch θ (deg)", xticks=np.arange(-90, 91, 30), yticks=np.arange(-90, 91, 30))
    ax.grid(False)
    return cs


def _levels(*fields, n=13):
    top = max(float(np.max(f)) for f in fields)
    return np.linspace(0.0, top * 1.0001, n)


def eq3_erratum(art):
    """tan2022_extra_eq3_erratum: printed Eq 3 beside the corrected form (deg), same colour scale."""
    d = art.data
    lv = _levels(np.abs(d["printed"]), np.abs(d["corrected"]))
    fig, axes = plt.subplots(1, 2, figsize=(11.5, 4.6), sharey=True, constrained_layout=True)
    for ax, key, title in ((axes[0], "printed", "Eq 3 as printed (no sinθ)"),
                           (axes[1], "corrected", "corrected Eq 3 (= simulated triad)")):
        cs = error_map(ax, d["theta_deg"], d["phi_deg"], np.abs(d[key]), lv)
        ax.set_title(title, fontsize=10)
    axes[1].set_ylabel("")
    fig.colorbar(cs, ax=axes, label=f"|Δθ| (deg), {d['label']}", format="%.4f")
    fig.suptitle(f"tan2022 Eq 3 erratum (tan2022_extra_eq3_erratum): pitch error, {d['label']}", fontsize=11)
    return fig


def _single_map(art, title, cbar):
    d = art.data
    fig, ax = plt.subplots(figsize=(7.2, 5.4), constrained_layout=True)
    cs = error_map(ax, d["theta_deg"], d["phi_deg"], d["abs_dtheta_deg"], _levels(d["abs_dtheta_deg"]))
    fig.colorbar(cs, ax=ax, label=cbar, format="%.4f")
    ax.set_title(title, fontsize=10)
    return fig


def fig02(art):
    """tan2022_fig02: |Δθ| (deg) of the plain triad, roll on x, pitch on y."""
    lab = art.data["label"]
    return _single_map(art, f"tan2022 Fig 2 (tan2022_fig02): pitch error of a three-axis accelerometer, {lab}",
                       f"|Δθ| (deg), {lab} on every axis")


def fig05(art):
    """tan2022_fig05: |Δθ| (deg) with the preset Euler rotation."""
    lab = art.data["label"]
    l1, l2 = art.data["lambda_deg"]
    return _single_map(art, f"tan2022 Fig 5 (tan2022_fig05): pitch error with preset rotation\n"
                            f"λ1 = {l1:g}° (θ ≤ 0), λ2 = {l2:g}° (θ > 0), {lab}", f"|Δθ| (deg), {lab} on every axis")


def extra_roll_error(art):
    """tan2022_extra_roll_error: |Δφ| (deg), log colour scale."""
    d = art.data
    top = float(np.max(d["abs_droll_deg"]))
    lv = np.geomspace(top / 1e3, top, 13)
    fig, ax = plt.subplots(figsize=(7.2, 5.4), constrained_layout=True)
    cs = error_map(ax, d["theta_deg"], d["phi_deg"], d["abs_droll_deg"], lv, log=True, cmap="magma")
    fig.colorbar(cs, ax=ax, label=f"|Δφ| (deg), {d['label']} on every axis", format="%.2g")
    ax.set_title(f"tan2022 Eq 4 (tan2022_extra_roll_error): roll error of a three-axis accelerometer\n"
                 f"|θ| ≤ 89°, {d['label']}", fontsize=10)
    return fig


def fig08(art):
    """tan2022_fig08: plain vs preset, worst and RMS over roll, vs pitch (deg)."""
    d = art.data
    fig, ax = plt.subplots(figsize=(8.0, 4.6), constrained_layout=True)
    ax.plot(d["theta_deg"], d["worst_T"], "C0-", label="Δθ_T plain triad, worst over φ")
    ax.plot(d["theta_deg"], d["worst_p"], "C1-", label="Δθ_p preset rotation, worst over φ")
    ax.plot(d["theta_deg"], d["rms_T"], "C0--", label="Δθ_T RMS over φ")
    ax.plot(d["theta_deg"], d["rms_p"], "C1--", label="Δθ_p RMS over φ")
    ax.set(xlabel="pitch θ (deg)", ylabel="|Δθ| (deg)", xticks=np.arange(-90, 91, 30), xlim=(-90, 90),
           title=f"tan2022 Fig 8 (tan2022_fig08): plain triad vs preset rotation, {d['label']}")
    ax.title.set_fontsize(10)
    ax.yaxis.set_major_formatter("{x:.4f}")
    ax.legend(fontsize=8, loc="upper center", ncol=2)
    ax.set_ylim(0, 1.3 * max(np.max(d["worst_T"]), np.max(d["worst_p"])))
    return fig


def extra_independent_errors(art):
    """tan2022_extra_independent_errors: each trial's RMS over roll per pitch, independent axis errors (deg):
    median and 95 % band over the trials (the range with its count from fewer than 1000)."""
    d = art.data
    fig, ax = plt.subplots(figsize=(8.0, 4.6), constrained_layout=True)
    for key, lab, c in (("single", "plain triad", "C0"), ("preset", "preset rotation (Eq 9 selection)", "C1"),
                        ("mean_of_two", "mean of the two preset triads", "C2")):
        b = d["per_trial"][key]
        ax.fill_between(d["theta_deg"], b["low"], b["high"], color=c, alpha=0.2, lw=0)
        ax.plot(d["theta_deg"], b["median"], c + "-o", ms=3, label=f"{lab}: median, {b['label']}")
    ax.set(xlabel="pitch θ (deg)", ylabel="RMS |Δθ| over φ (deg)", xlim=(-90, 90), xticks=np.arange(-90, 91, 30),
           title=f"tan2022_extra_independent_errors: independent axis errors σ = {d['sigma_g']:.0e} g, "
                 f"{d['trials']} trials")
    ax.title.set_fontsize(10)
    ax.yaxis.set_major_formatter("{x:.4f}")
    ax.set_ylim(0, None)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.14), frameon=False)   # off the data
    return fig


def accel_error_model(fit):
    """tan2022_extra_error_model_accel: likelihood and posterior of r."""
    p = fit.posterior
    fig, ax = plt.subplots(figsize=(7.0, 4.0), constrained_layout=True)
    ax.plot(p["grid"], p["likelihood"], "C0-o", ms=3, label="likelihood P(equal-error assumption, Fig 2, Fig 5 statements | r)")
    ax2 = ax.twinx()
    ax2.bar(p["grid"], p["posterior"], width=0.8 * (p["grid"][1] - p["grid"][0]), color="C1", alpha=0.4,
            label="posterior (uniform prior)")
    ax2.grid(False)
    ax.set(xlabel=p["xlabel"], ylabel="likelihood", ylim=(0, 1.05),
           title="tan2022_extra_error_model_accel: accelerometer bias model fitted to the paper's statements")
    ax2.set_ylabel("posterior probability")
    ax.title.set_fontsize(10)
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, fontsize=8, loc="upper right")
    return fig


def gyro_error_model(fit):
    """tan2022_extra_error_model_gyro: marginal posteriors of b and N."""
    p = fit.posterior
    fig, axes = plt.subplots(1, 2, figsize=(11.0, 3.8), constrained_layout=True)
    axes[0].plot(p["bias_grid"], p["posterior_b"], "C0-")
    prm = fit.parameters.set_index("unit")
    b_med = float(prm.loc["deg/s", "median"])
    axes[0].set(xlabel="constant gyro error b (deg/s)", ylabel="posterior probability",
                xlim=(max(0.0, b_med - 0.05), b_med + 0.05), title=f"b (prior {prm.loc['deg/s', 'prior']} °/s)")
    axes[1].bar(p["noise_grid"], p["posterior_n"], width=0.8 * (p["noise_grid"][1] - p["noise_grid"][0]), color="C1")
    axes[1].set(xlabel="noise density N (deg/s/√Hz)",
                title=f"N (prior {prm.loc['deg/s/√Hz', 'prior']} °/s/√Hz, on the grid)")
    fig.suptitle("tan2022_extra_error_model_gyro: gyro error model fitted to the Fig 6 curve", fontsize=11)
    return fig


def fig06(art):
    """tan2022_fig06: projection roll error vs pitch rate (deg, log-log)."""
    d = art.data
    fig, ax = plt.subplots(figsize=(7.8, 4.8), constrained_layout=True)
    ax.loglog(d["rate_deg_s"], d["eq14"], "k-", label="Eq 14 at φ0")
    ax.loglog(d["rate_deg_s"], d["exact"], "C1--", label="exact arctan (constant error)")
    ax.fill_between(d["rate_deg_s"], d["band"]["low"], d["band"]["high"], color="C0", alpha=0.3,
                    label=f"simulation: {d['band']['label']}")
    ax.loglog(d["rate_deg_s"], d["band"]["median"], "C0o", ms=4, label=f"simulation median (slope {d['slope']:.2f})")
    ax.axvline(d["threshold_deg_s"], color="C3", lw=0.8, label=f"θ̇_t = {d['threshold_deg_s']:g} °/s")
    ax.set(xlabel="pitch rate θ̇ (deg/s)", ylabel="|roll error Δφ| (deg)",
           title=f"tan2022 Fig 6 (tan2022_fig06): projection roll error vs pitch rate\n{d['label']}")
    ax.title.set_fontsize(10)
    ax.legend(fontsize=8, loc="upper right")
    return fig


def fig09(art):
    """tan2022_fig09: roll errors vs time for the uniform rotations (one column per rate)."""
    curves = art.data["curves"]
    fig, axes = plt.subplots(2, len(curves), figsize=(4.2 * len(curves), 6.2), sharey="row", constrained_layout=True)
    axes = np.atleast_2d(axes.T).T
    for j, c in enumerate(curves):
        t = c["time_s"]
        top, bot = axes[0, j], axes[1, j]
        top.plot(t, c["euler"], "C3", lw=0.8, label="Δφ_E Euler differential (Eq 5)")
        bot.plot(t, c["integration"], "C0", label="Δφ_I decoupled integration (Eq 12)")
        bot.plot(t, c["projection"], "C2", lw=0.6, label="Δφ_P projection (Eq 13)")
        for ax in (top, bot):
            for crossing in (90.0, 270.0):
                ax.axvline(crossing / c["rate"], color="k", lw=0.6, ls=":")
        top.set_title(f"θ̇ = {c['rate']:g} °/s (dotted: θ = ±90°)\nmedian trial {c['trial'] + 1} of {c['trials']} "
                      "(by final |Δφ_I|)", fontsize=10)
        bot.set_xlabel("time (s)")
        top.set_ylim(-200, 200)
    axes[0, 0].set_ylabel("roll error (deg)")
    axes[1, 0].set_ylabel("roll error (deg)")
    axes[0, 0].legend(fontsize=8, loc="lower left")
    axes[1, 0].legend(fontsize=8, loc="upper left")
    fig.suptitle(f"tan2022 Fig 9 (tan2022_fig09): roll errors under uniform pitch rotation, {art.data['label']}",
                 fontsize=11)
    return fig


def fig10(art):
    """tan2022_fig10: pitch rate under oscillation vs time (deg/s)."""
    d = art.data
    fig, ax = plt.subplots(figsize=(8.0, 3.8), constrained_layout=True)
    ax.plot(d["time_s"], d["true"], "k", label="θ̇ (Eq 17)")
    ax.fill_between(d["time_s"], d["band"]["low"], d["band"]["high"], color="C0", alpha=0.3, lw=0,
                    label=f"|θ̇| from gyros √(ω_y² + ω_z²): {d['band']['label']}")
    ax.plot(d["time_s"], d["band"]["median"], "C0", lw=0.6, label="|θ̇| from gyros, median")
    ax.axhline(d["threshold"], color="C3", lw=0.8, label=f"θ̇_t = {d['threshold']:g} °/s")
    ax.set(xlabel="time (s)", ylabel="pitch rate (deg/s)", xlim=(0, d["time_s"][-1]),
           title=f"tan2022 Fig 10 (tan2022_fig10): pitch rate, θ = {d['amplitude']:g}° sin(2π·{d['freq']:g} t)")
    ax.title.set_fontsize(10)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=3)  # off the data
    return fig


def _oscillation_roll_figure(d: dict, number: int, method: str, symbol: str, lines) -> plt.Figure:
    """Roll error (deg) vs time under oscillation: ``lines`` are ``(key of d, plot args, plot kwargs)``."""
    fig, ax = plt.subplots(figsize=(8.0, 3.8), constrained_layout=True)
    for key, args, kwargs in lines:
        ax.plot(d["time_s"], d[key], *args, **kwargs)
    ax.set(xlabel="time (s)", ylabel="roll error (deg)",
           title=f"tan2022 Fig {number} (tan2022_fig{number}): {method} roll error under oscillation\n{d['label']}; "
                 f"median trial {d['trial'] + 1} of {d['trials']} (by {d.get('by', f'max |{symbol}|')})")
    ax.title.set_fontsize(10)
    ax.legend(fontsize=8, loc="lower left")
    return fig


def fig11(art):
    """tan2022_fig11: projection roll error under oscillation vs time (deg)."""
    return _oscillation_roll_figure(art.data, 11, "projection", "Δφ_P", (
        ("projection", ("C2",), dict(lw=0.6, label="Δφ_P projection (Eq 13)")),
        ("integration", ("C0",), dict(label="Δφ_I integration (Eq 12)"))))


def fig12(art):
    """tan2022_fig12: hybrid roll error under oscillation vs time (deg)."""
    d = art.data
    return _oscillation_roll_figure(d, 12, "hybrid", "Δφ_G", (
        ("projection", (), dict(color="0.75", lw=0.5, label="projection (Eq 13), for reference")),
        ("hybrid", ("C1",), dict(lw=0.6, label=f"Δφ_G hybrid θ̇_t = {d['threshold']:g} °/s, with noise")),
        ("hybrid_det", ("k",), dict(lw=0.8, label="Δφ_G hybrid, constant errors only (paper)"))))


def extra_threshold_sweep(art):
    """tan2022_extra_threshold_sweep: hybrid roll RMSE vs threshold (deg)."""
    d = art.data
    fig, ax = plt.subplots(figsize=(8.0, 4.6), constrained_layout=True)
    ax.fill_between(d["thresholds"], d["band"]["low"], d["band"]["high"], color="C1", alpha=0.3,
                    label=d['band']['label'])
    ax.loglog(d["thresholds"], d["band"]["median"], "C1-", label="median roll RMSE (errors + noise)")
    ax.loglog(d["thresholds"], d["det"], "k--", label="constant errors only")
    ax.axvline(d["optimum"], color="C3", lw=1.0, label=f"optimum (median over trials) {d['optimum']:.0f} °/s")
    ax.axvline(d["paper"], color="C3", lw=0.8, ls=":", label=f"paper θ̇_t = {d['paper']:g} °/s")
    ax.axvline(d["peak"], color="k", lw=0.6, ls=":", label=f"peak rate {d['peak']:.1f} °/s")
    ax.set(xlabel="threshold θ̇_t (deg/s)", ylabel="roll RMSE (deg)",
           title=f"tan2022_extra_threshold_sweep: hybrid roll RMSE vs threshold\n{d['label']}")
    ax.title.set_fontsize(10)
    ax.legend(fontsize=8, loc="upper center")
    return fig


def gyro_error_pattern(fit):
    """tan2022_extra_error_pattern_gyro: likelihood of (b_z, N) given the Fig 11 and Fig 12 statements."""
    p = fit.posterior
    fig, ax = plt.subplots(figsize=(8.0, 5.0), constrained_layout=True)
    mesh = ax.pcolormesh(np.arange(p["noise_grid"].size + 1), np.arange(p["bias_grid"].size + 1), p["likelihood"],
                         cmap="Greys", vmin=0, vmax=1, edgecolors="0.8", linewidth=0.3)
    ax.set_xticks(np.arange(p["noise_grid"].size) + 0.5, [f"{v:g}" for v in p["noise_grid"]], rotation=45)
    ax.set_yticks(np.arange(p["bias_grid"].size) + 0.5, [f"{v:g}" for v in p["bias_grid"]])
    paper = int(np.argmin(np.abs(p["bias_grid"] - 0.2)))
    ax.axhline(paper + 0.5, color="C3", lw=1.2, label="the paper's z error 0.2 °/s")
    ax.grid(False)
    ax.set(xlabel="noise density N (deg/s/√Hz)", ylabel="constant z-gyro error b_z (deg/s)",
           title="tan2022_extra_error_pattern_gyro: P(Fig 11 spikes and Fig 12 accurate | b_z, N)\n"
                 f"x and y gyros keep 0.2 °/s; {p.get('trials', '?')} noise trials per cell; grid cells not to scale")
    ax.title.set_fontsize(10)
    ax.legend(fontsize=8, loc="upper right")
    fig.colorbar(mesh, ax=ax, label="likelihood")
    return fig
