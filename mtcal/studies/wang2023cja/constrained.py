"""wang2023cja beyond the paper: constrained (SO(4), mounting-only) calibration vs Eq 13 — producers.

The paper-independent estimators live in :mod:`mtcal.methods.constrained_fit`; this module holds
the study's layout (the paper's six positions and envelope), its noise level — the per-position
error of the hardware error model identified on Tables 1–4 (:func:`.error_model.position_noise_deg`),
one number shared with the turntable notebook — and one producer per artifact of notebook 40.

References
----------
wang2023cja Eq 13 (least squares), §3.2 (six positions), Tables 1–4 (full citation: :mod:`mtcal.studies.wang2023cja`).

Examples
--------
>>> paper_six_positions_deg()[4].tolist()
[0.0, 0.0, 90.0]
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from mtcal.core import metrics, rotations
from mtcal.core.rng import stream_rng
from mtcal.methods import constrained_fit
from mtcal.methods.quaternion_lsq import apply_error_matrix
from mtcal.reporting import paper_numbers

__all__ = ["ENVELOPE_DEG", "METHOD_LABEL", "paper_six_positions_deg", "symmetric_layout_rad", "min_positions_table",
           "error_vs_positions_table", "error_vs_noise_table", "headline", "printed_matrices_so4_table",
           "q33_variants_table", "noise_vs_so4_distance_table", "printed_matrices", "constrained_rows",
           "sigma_matching_distance", "PARAMETER_DEFAULTS", "check_parameters", "headline_text"]

#: The paper's calibration envelope (§4.1): yaw ±8°, pitch −12…23°, roll ±90°.
ENVELOPE_DEG = ((-8.0, 8.0), (-12.0, 23.0), (-90.0, 90.0))
METHOD_LABEL = {"eq13": "Eq 13 (16 par.)", "so4": "SO(4) (6 par.)", "mounting": "mounting (3 par.)"}

# random streams of this module (mtcal.core.rng rule). A key (s, 0) hashes as the bare integer s
# (SeedSequence zero-pads to its pool; mtcal.core.rng), the keys these tables were first drawn with.
STREAM_CALIBRATION = 0        # key (seed + k, 0): noise of the K-position calibrations; (seed, 0) per σ level
STREAM_LAYOUT = 0             # key (seed + LAYOUT_SEED_OFFSET + k, 0): random K-position layouts
LAYOUT_SEED_OFFSET = 100      # the layouts' seed offset, so layouts and noise of one K never share a key
MIN_POSITIONS_SEED = 0        # key (K, 0): the fixed generic layouts of the noise-free minimum-K search


def paper_six_positions_deg() -> np.ndarray:
    """The six positions of Table 1 as ``[yaw, pitch, roll]`` (deg, paper order), (6, 3)."""
    t1 = paper_numbers.load("wang2023cja_table01_positions")
    return t1[["yaw_reference_deg", "pitch_reference_deg", "roll_reference_deg"]].to_numpy(float)


def symmetric_layout_rad(k: int) -> np.ndarray:
    """First ``k`` positions of the paper's six, interleaved and extended at half amplitude (rad)."""
    return constrained_fit.symmetric_layout_rad(k, np.radians(paper_six_positions_deg()))


def _scenario(sigma_deg: float, offset: bool, n_test: int) -> constrained_fit.CalibrationScenario:
    return constrained_fit.CalibrationScenario(noise_sigma_rad=float(np.radians(sigma_deg)), reference_offset=offset,
                                               n_test=n_test, envelope_deg=ENVELOPE_DEG)


def _band(err_rad, **keys) -> dict:
    finite = err_rad[np.isfinite(err_rad)]
    if finite.size == 0:
        return dict(keys, median_deg=np.nan, low_deg=np.nan, high_deg=np.nan, n_valid=0, kind="")
    b = metrics.band_or_range(np.degrees(finite))      # 95 % band from >= 1000 values, else the range
    return dict(keys, median_deg=float(b["median"]), low_deg=float(b["low"]), high_deg=float(b["high"]),
                n_valid=int(finite.size), kind=b["kind"])


def min_positions_table(seed: int) -> pd.DataFrame:
    """wang2023cja_extra_min_positions: fewest positions for noise-free recovery, per method and layout."""
    def recovered(layout_rad, method):
        sc = constrained_fit.CalibrationScenario(noise_sigma_rad=0.0, reference_offset=(method != "mounting"),
                                                 n_test=20, envelope_deg=ENVELOPE_DEG)
        n = layout_rad.shape[0] if layout_rad.ndim == 3 else 20
        err = constrained_fit.simulate_calibration_errors(layout_rad, sc, n, stream_rng(seed, STREAM_CALIBRATION))[method]
        return bool(np.all(np.isfinite(err)) and np.max(err) < 1e-9)

    paper_order = np.radians(paper_six_positions_deg())
    rows = []
    for method, dof in (("eq13", 16), ("so4", 6), ("mounting", 3)):
        ks = range(1, 7)
        generic = [k for k in ks
                   if recovered(constrained_fit.random_layout_rad(stream_rng(MIN_POSITIONS_SEED + k, STREAM_LAYOUT), 50, k,
                                                               ENVELOPE_DEG), method)]
        symmetric = [k for k in ks if recovered(symmetric_layout_rad(k), method)]
        in_order = [k for k in ks if recovered(paper_order[:k], method)]
        rows.append({"method": METHOD_LABEL[method], "parameters": dof, "min_K_generic": min(generic),
                     "min_K_symmetric_interleaved": min(symmetric), "min_K_paper_order": min(in_order),
                     "library_MIN_POSITIONS": constrained_fit.MIN_POSITIONS[method]})
    return pd.DataFrame(rows)


TRUTHS = {"shared frame": False, "heading offset": True}


def error_vs_positions_table(sigma_deg: float, n_trials: int, n_test: int, seed: int, k_range) -> pd.DataFrame:
    """wang2023cja_extra_error_vs_positions: attitude RMSE after calibration vs K (median, 95 % band)."""
    rows = []
    for truth, offset in TRUTHS.items():
        sc = _scenario(sigma_deg, offset, n_test)
        for layout in ("symmetric", "random"):
            for k in k_range:
                lay = (symmetric_layout_rad(k) if layout == "symmetric"
                       else constrained_fit.random_layout_rad(stream_rng(seed + LAYOUT_SEED_OFFSET + k, STREAM_LAYOUT),
                                                              n_trials, k,
                                                              ENVELOPE_DEG))
                err = constrained_fit.simulate_calibration_errors(lay, sc, n_trials,
                                                                 stream_rng(seed + k, STREAM_CALIBRATION))
                rows += [_band(err[m], truth=truth, layout=layout, K=k, method=m) for m in constrained_fit.METHODS]
    return pd.DataFrame(rows)


def error_vs_noise_table(levels_deg, n_trials: int, n_test: int, seed: int) -> pd.DataFrame:
    """wang2023cja_extra_error_vs_noise: attitude RMSE after calibration vs σ, paper's six positions."""
    six = np.radians(paper_six_positions_deg())
    rows = []
    for truth, offset in TRUTHS.items():
        for sigma in levels_deg:
            err = constrained_fit.simulate_calibration_errors(six, _scenario(sigma, offset, n_test), n_trials,
                                                              stream_rng(seed, STREAM_CALIBRATION))
            rows += [_band(err[m], truth=truth, sigma_deg=sigma, method=m) for m in constrained_fit.METHODS]
    return pd.DataFrame(rows)


def headline(noise_table: pd.DataFrame, positions_table: pd.DataFrame, sigma_deg: float) -> tuple[pd.DataFrame, dict]:
    """wang2023cja_extra_constrained_headline and its derived numbers (gains in %, ratios, K needed)."""
    head = noise_table[np.isclose(noise_table.sigma_deg, sigma_deg)].drop(columns="sigma_deg").reset_index(drop=True)
    med = {(r.truth, r.method): r.median_deg for r in head.itertuples()}
    sym = positions_table[(positions_table.truth == "shared frame") & (positions_table.layout == "symmetric")]
    eq13_at6 = float(sym[(sym.method == "eq13") & (sym.K == 6)].median_deg.iloc[0])
    out = {"gain_so4_pct": {t: 100.0 * (1.0 - med[(t, "so4")] / med[(t, "eq13")]) for t in TRUTHS},
           "gain_mount_pct": 100.0 * (1.0 - med[("shared frame", "mounting")] / med[("shared frame", "so4")]),
           "ratio_mount_biased": med[("heading offset", "mounting")] / med[("heading offset", "so4")],
           "eq13_at6_deg": eq13_at6,
           "so4_k": int(sym[(sym.method == "so4") & (sym.median_deg <= eq13_at6)].K.min()),
           "mount_k": int(sym[(sym.method == "mounting") & (sym.median_deg <= eq13_at6)].K.min()),
           "median": med}
    return head, out


def printed_matrices() -> dict:
    """The printed matrices (read as Eq 10 maps) and the turntable one with Q(3,3) sign fixed."""
    q_turn = paper_numbers.load("wang2023cja_matrix_qbs_turntable").iloc[:, 1:].to_numpy(float)
    q_wind = paper_numbers.load("wang2023cja_matrix_qbs_windtunnel").iloc[:, 1:].to_numpy(float)
    q_fix = q_turn.copy()
    q_fix[2, 2] = -q_fix[2, 2]
    return {"turntable (printed)": q_turn, "turntable (Q33 sign fixed)": q_fix, "wind tunnel (printed)": q_wind}


def printed_matrices_so4_table() -> pd.DataFrame:
    """wang2023cja_extra_printed_matrices_so4: det, distances, implied mounting c and offset w (deg)."""
    rows = []
    for name, mat in printed_matrices().items():
        proj = constrained_fit.project_to_so4(mat)
        c, w = rotations.quat_conjugate(proj.r), rotations.quat_conjugate(proj.p)
        ec, ew = np.degrees(rotations.euler_zxy_from_quat(c)), np.degrees(rotations.euler_zxy_from_quat(w))
        rows.append({
            "matrix": name, "det": float(proj.determinant), "dist_SO4": float(proj.distance),
            "dist_O4": float(constrained_fit.distance_to_orthogonal(mat)),
            "max_abs_diag_minus_1": float(np.max(np.abs(np.abs(np.diag(mat)) - 1.0))),
            "c_yaw_deg": ec[0], "c_pitch_deg": ec[1], "c_roll_deg": ec[2],
            "c_angle_deg": float(np.degrees(rotations.quat_angle_between(c, [1.0, 0, 0, 0]))),
            "w_yaw_deg": ew[0], "w_pitch_deg": ew[1], "w_roll_deg": ew[2],
            "w_angle_deg": float(np.degrees(rotations.quat_angle_between(w, [1.0, 0, 0, 0]))),
            "angle_p_rconj_deg": float(np.degrees(rotations.quat_angle_between(proj.p, c)))})
    return pd.DataFrame(rows)


def q33_variants_table() -> tuple[pd.DataFrame, dict]:
    """wang2023cja_extra_q33_sign: Table 1 "before" through variants of the printed matrix vs Table 1 "after"."""
    t1 = paper_numbers.load("wang2023cja_table01_positions")
    before = np.radians(t1[["yaw_before_deg", "pitch_before_deg", "roll_before_deg"]].to_numpy(float))
    after = t1[["yaw_after_deg", "pitch_after_deg", "roll_after_deg"]].to_numpy(float)
    q_before = rotations.quat_from_euler_zxy(before[:, 0], before[:, 1], before[:, 2])
    m = printed_matrices()
    q_turn, q_fix = m["turntable (printed)"], m["turntable (Q33 sign fixed)"]
    d3 = np.diag([1.0, 1.0, -1.0, 1.0])
    variants = {"printed Q": q_turn, "Q33 sign fixed": q_fix, "row 3 negated": d3 @ q_turn,
                "column 3 negated": q_turn @ d3, "printed Q^T": q_turn.T, "fixed Q^T": q_fix.T,
                "fixed Q^-1": np.linalg.inv(q_fix),
                "SO(4) projection of fixed": constrained_fit.project_to_so4(q_fix).matrix}
    rows = []
    for name, mat in variants.items():
        ang = np.degrees(rotations.euler_zxy_from_quat(apply_error_matrix(mat, q_before)))
        diff = np.degrees(rotations.wrap_angle(np.radians(ang - after)))
        rows.append({"variant": name, "det": float(np.linalg.det(mat)),
                     "max_abs_diff_rows1_4_deg": float(np.max(np.abs(diff[:4]))),
                     "max_abs_diff_rows5_6_deg": float(np.max(np.abs(diff[4:]))),
                     "roll_at_+90_deg": ang[4, 2], "roll_at_-90_deg": ang[5, 2],
                     "yaw_at_+90_deg": ang[4, 0], "pitch_at_+90_deg": ang[4, 1]})
    ang_fix = rotations.euler_zxy_from_quat(apply_error_matrix(q_fix, q_before))
    ang_proj = rotations.euler_zxy_from_quat(apply_error_matrix(variants["SO(4) projection of fixed"], q_before))
    change = np.degrees(np.abs(rotations.wrap_angle(ang_proj - ang_fix)))
    return pd.DataFrame(rows), {"proj_change_rows1_4_deg": float(change[:4].max()),
                                "proj_change_rows5_6_deg": float(change[4:].max()),
                                "after_roll_deg": (float(after[4, 2]), float(after[5, 2]))}


def noise_vs_so4_distance_table(levels_deg, n_trials: int, seed: int) -> pd.DataFrame:
    """wang2023cja_extra_noise_vs_so4_distance: distance of the Eq 13 estimate to O(4) vs σ (median, band: the 95 %
    band from ≥ 1000 trials, else the min–max range; ``n``, ``kind``), and the median and 97.5 % quantile of
    |Q(2,2)| − 1."""
    six = np.radians(paper_six_positions_deg())
    rows = []
    for sigma in levels_deg:
        _, mats = constrained_fit.simulate_calibration_errors(six, _scenario(sigma, False, 5), n_trials,
                                                              stream_rng(seed, STREAM_CALIBRATION), return_matrices=True)
        b = metrics.band_or_range(constrained_fit.distance_to_orthogonal(mats["eq13"]))
        # a one-sided 97.5 % quantile (the assertion "noise does not reach Q(2,2) = 1.0045"), not a band
        q22 = metrics.percentile_band(np.abs(mats["eq13"][:, 1, 1]) - 1.0)
        rows.append({"sigma_deg": sigma, "median": float(b["median"]), "low": float(b["low"]), "high": float(b["high"]),
                     "q22_minus_1_median": float(q22["median"]), "q22_minus_1_high": float(q22["high"]),
                     "n": b["n"], "kind": b["kind"]})
    return pd.DataFrame(rows)


def sigma_matching_distance(distance_table: pd.DataFrame, distance: float) -> float:
    """σ (deg) at which the median Eq 13 distance to O(4) equals ``distance`` (log-log interpolation)."""
    return float(np.exp(np.interp(np.log(distance), np.log(distance_table["median"]),
                                  np.log(distance_table.sigma_deg))))


def constrained_rows(min_table, head_table, info, so4_table, q33_table, distance_table, sigma_deg: float) -> list:
    """Comparison rows of notebook 40 (role/source set; paper claims vs our findings)."""
    from mtcal.reporting import compare

    row = compare.comparison_row
    min_k = dict(zip(("eq13", "so4", "mounting"), min_table["min_K_generic"]))
    rows = [
        row("wang2023cja_extra_min_positions", "minimum positions, Eq 13", "3", str(min_k["eq13"]),
            "paper §3.1: Eq 13 needs at least three positions — fails: Eq 13 needs four", None, role="erratum"),
        row("wang2023cja_extra_min_positions", "minimum positions, Eq 13 (computed)", "-", str(min_k["eq13"]),
            "A_s A_s^T is singular for K = 3 whatever the positions", min_k["eq13"] == 4, role="erratum",
            source="mtcal finding"),
        row("wang2023cja_extra_min_positions", "minimum positions, SO(4) / mounting", "-",
            f"{min_k['so4']} / {min_k['mounting']}", "constrained fits need fewer positions than Eq 13",
            bool(min_k["so4"] < min_k["eq13"] and min_k["mounting"] < min_k["so4"]), role="finding",
            source="mtcal finding")]
    med = info["median"]
    for r in head_table.itertuples():
        holds = bool(med[(r.truth, "so4")] < med[(r.truth, "eq13")]) if r.method == "so4" else None
        rows.append(row("wang2023cja_extra_constrained_headline",
                        f"attitude RMSE, 6 positions, {r.truth}, {METHOD_LABEL[r.method]} (deg)", "-",
                        float(r.median_deg), "SO(4) beats Eq 13" if r.method == "so4" else "", holds,
                        band=None if r.n_valid == 0 else {"low": r.low_deg, "high": r.high_deg, "n": int(r.n_valid),
                                                          "kind": r.kind},
                        role="finding", source="mtcal finding"))
    rows.append(row("wang2023cja_extra_constrained_headline", "mounting-only vs SO(4), heading offset (ratio of medians)",
                    "-", info["ratio_mount_biased"], "mounting-only fit is biased when the reference frame differs",
                    bool(info["ratio_mount_biased"] > 3.0), role="finding", source="mtcal finding"))
    so4 = so4_table.set_index("matrix")
    bt, bf, bw = (so4.loc[k] for k in printed_matrices())
    rows += [
        row("wang2023cja_extra_printed_matrices_so4", "det, printed turntable matrix", "-1.000355 at (3,3)",
            float(bt.det), "printed turntable matrix is improper (sign typo)", bool(bt.det < 0), role="erratum",
            source="mtcal finding"),
        row("wang2023cja_extra_printed_matrices_so4", "distance to SO(4), turntable Q33 fixed", "-", float(bf.dist_SO4),
            "sign-corrected matrix is a rotation up to 0.01", bool(bf.dist_SO4 < 0.01), role="finding",
            source="mtcal finding")]
    v = q33_table.set_index("variant")
    rows += [
        row("wang2023cja_extra_q33_sign", "roll at +90 / -90 with printed matrix (deg)", "89.993 / -89.971",
            f"{v.loc['printed Q', 'roll_at_+90_deg']:.3f} / {v.loc['printed Q', 'roll_at_-90_deg']:.3f}",
            "printed Q33 flips roll +-90 by 180 deg", bool(v.loc["printed Q", "max_abs_diff_rows5_6_deg"] > 179.0),
            role="erratum", source="mtcal finding"),
        row("wang2023cja_extra_q33_sign", "max |after - recomputed|, rows 1-4, Q33 fixed (deg)", "0",
            float(v.loc["Q33 sign fixed", "max_abs_diff_rows1_4_deg"]),
            "paper's after is not its matrix applied to its before (verified on separate runs)",
            bool(v.loc["Q33 sign fixed", "max_abs_diff_rows1_4_deg"] > 0.01), role="finding", source="mtcal finding")]
    need_wind = sigma_matching_distance(distance_table, float(bw.dist_O4))
    need_turn = sigma_matching_distance(distance_table, float(bf.dist_O4))
    rows.append(row("wang2023cja_extra_noise_vs_so4_distance",
                    "sigma (deg) at which Eq 13's median distance to O(4) equals wind tunnel / turntable", "-",
                    f"{need_wind:.3f} / {need_turn:.3f}",
                    f"noise at the identified {sigma_deg:.3f} deg does not make the wind-tunnel matrix's distance",
                    bool(need_wind > 1.5 * sigma_deg), role="finding", source="mtcal finding"))
    return rows


#: Notebook 40 parameters (the study's default setting).
PARAMETER_DEFAULTS = {"k_max": 12, "noise_levels_deg": (0.005, 0.01, 0.02, 0.05)}


def check_parameters(k_max, noise_levels_deg) -> dict:
    """Validate notebook 40's parameters; return them as a dict (one-line ValueError otherwise)."""
    if isinstance(k_max, bool) or not isinstance(k_max, (int, np.integer)) or not 6 <= int(k_max) <= 12:
        raise ValueError(f"k_max must be an int in [6, 12], got {k_max!r}")
    try:
        levels = tuple(float(x) for x in noise_levels_deg)
    except (TypeError, ValueError):
        levels = ()
    if not levels or not all(0.0 < x <= 1.0 for x in levels):
        raise ValueError(f"noise_levels_deg must be angles in (0, 1] deg, got {noise_levels_deg!r}")
    return {"k_max": int(k_max), "noise_levels_deg": levels}


def headline_text(info: dict) -> str:
    """The headline numbers of :func:`headline` as three lines of text."""
    gains = ", ".join(f"{t}: SO(4) {g:.0f} % below Eq 13" for t, g in info["gain_so4_pct"].items())
    return (f"{gains}\nshared frame: mounting-only {info['gain_mount_pct']:.0f} % below SO(4); heading offset: "
            f"mounting-only {info['ratio_mount_biased']:.1f} x worse than SO(4)\n"
            f"SO(4) reaches Eq 13's 6-position median ({info['eq13_at6_deg']:.4f} deg) with K = {info['so4_k']}; "
            f"mounting-only with K = {info['mount_k']}")
