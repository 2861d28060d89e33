"""wang2023cja Table 8: candidate causes of the paper's small reduction, computed on Tables 1–4 only.

The paper's calibration removes 37–67 % of the pitch/yaw coupling error of the roll sweep (Table 8,
held out); our posterior predictive removes 86–95 %. Each candidate below is a mechanism that would
leave more of the coupling after calibration. For each, this module computes — from the training
numbers only (Tables 1–4 and the printed turntable matrix, read through
:func:`mtcal.reporting.paper_numbers.training`; Table 8 is never read here) — the reduction fraction
``1 − after/before`` of the pitch and yaw MaxAE it predicts over the roll sweep, with a 95 % band,
and whether Tables 1–4 support the mechanism at the size it needs.

The roll sweep is modelled at the level of its *coupling*: the T1 sensor (installation angles
fitted to Table 1's "before" columns) turned through roll −90…90° in 1° steps at zero pitch and
yaw (the Table 7 range); "before" is the zeroed sensor attitude, "after" the same with the
candidate's calibration matrix applied (Eq 10). Without noise a perfect matrix removes 100 %, so
every fraction here is the reduction the mechanism alone leaves room for (the sensor noise of the
full simulation takes a few per cent more).

Candidates (:func:`candidate_fractions`):

* ``printed matrix`` — the paper's own printed turntable matrix (Q(3,3) sign fixed) applied to the
  sensor whose angles Table 1's "before" columns give: do the paper's matrix and the paper's
  "before" columns describe the same installation?
* ``installation-angle uncertainty`` — the true angles differ from the fitted ones by their
  least-squares covariance while the matrix is the one of the fitted angles.
* ``Table 1 after-columns misalignment`` — the rotation left after calibration that Table 1's
  "after − reference" columns show (least squares with its covariance), put on the sweep.
* ``per-rest angle error (ML)`` / ``(95 % upper)`` — turntable/mechanism angle errors at the six
  calibration rests (``position_error_arcsec``, the rest-level model :func:`.error_model.rest_residuals`
  with all fitted sources) at the ML value, at the upper end of its 95 % Laplace interval and at the
  prior maximum (300″, which Tables 1–4 exclude).
* ``four positions`` — the least squares of Eq 13 on four of the six positions (one yaw and one
  roll rest dropped: the fewest that keep it determined), all fitted sources at their ML values.
* ``printed-matrix quantisation`` — the true matrix rounded to the printed 6 decimals.

References
----------
wang2023cja §3.2 Eq 10–13, §4.1 Tables 1, 7, 8 and the printed turntable matrix.

Examples
--------
>>> [float(x) for x in ROLL_SWEEP_DEG[[0, -1]]]
[-90.0, 90.0]
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pandas as pd

from mtcal.core import metrics, rotations
from mtcal.core.rng import stream_rng
from mtcal.core.units import DEG
from mtcal.methods import quaternion_lsq
from mtcal.reporting import paper_numbers
from .error_model import (N_NORMALS, PAPER_SIGN, PRIOR_RANGES, TABLES_1_TO_4, ErrorModelFit, fit_installation_angles,
                          paper_positions, rest_residuals, rest_times_s, true_error_matrix)

__all__ = ["ROLL_SWEEP_DEG", "PRINTED_DECIMALS", "roll_sweep_maxae_deg", "printed_matrix", "candidate_fractions"]

STREAM_CAUSES = 230           # random stream of this module (mtcal.core.rng rule)
#: The roll sweep of Tables 7/8 as a grid (deg): roll −90…90° at zero pitch and yaw.
ROLL_SWEEP_DEG = np.arange(-90.0, 90.5, 1.0)
#: Decimals of the printed turntable matrix.
PRINTED_DECIMALS = 6


def _sweep_reference() -> np.ndarray:
    ref = np.zeros((ROLL_SWEEP_DEG.size, 3))
    ref[:, 2] = PAPER_SIGN[2] * np.radians(ROLL_SWEEP_DEG)     # Eq 8 frame, as runs.turntable_profile
    return ref


def _sensor_quaternions(alpha_rad, ref) -> np.ndarray:
    """Zeroed sensor quaternions at body angles ``ref`` (K, 3): ``q_bs⁻¹ ⊗ q_wb ⊗ q_bs``, (…, K, 4)."""
    q_bs = rotations.mount_quaternion(alpha_rad)
    q_wb = rotations.quat_from_euler_zxy(ref[:, 0], ref[:, 1], ref[:, 2])
    return rotations.quat_multiply(rotations.quat_conjugate(q_bs), rotations.quat_multiply(q_wb, q_bs))


def roll_sweep_maxae_deg(alpha_rad, q_matrix=None) -> np.ndarray:
    """Pitch and yaw MaxAE (deg) over the roll sweep of a sensor with installation angles ``alpha_rad``.

    Parameters
    ----------
    alpha_rad : (3,)
        True installation angles (rad).
    q_matrix : (4, 4) or (n, 4, 4), optional
        Calibration matrix applied (Eq 10); ``None``: before calibration.

    Returns
    -------
    ndarray (2,) or (n, 2): MaxAE of (pitch, yaw), deg.

    Examples
    --------
    >>> a = np.radians([-0.243, -0.036, 0.052])
    >>> bool(roll_sweep_maxae_deg(a)[0] > 0.2), float(roll_sweep_maxae_deg(a, true_error_matrix(a)).max()) < 1e-9
    (True, True)
    """
    ref = _sweep_reference()
    q_s = _sensor_quaternions(np.asarray(alpha_rad, float), ref)
    if q_matrix is not None:
        q_mat = np.asarray(q_matrix, float)
        q_s = quaternion_lsq.apply_error_matrix(q_mat, q_s if q_mat.ndim == 2 else np.broadcast_to(
            q_s, q_mat.shape[:-2] + q_s.shape))
    err = metrics.angle_difference(rotations.euler_zxy_from_quat(q_s), ref)
    return np.degrees(np.abs(err[..., [1, 0]]).max(axis=-2))


def printed_matrix() -> np.ndarray:
    """The paper's printed turntable matrix with the Q(3,3) sign fixed, (4, 4).

    Fifteen entries are ``train``; Q(3,3) is the ``erratum`` −1.000355 (``training`` masks it), read as
    printed and used with its sign fixed (the ``wang2023cja_extra_q33_roll`` check).
    """
    df = paper_numbers.load("wang2023cja_matrix_qbs_turntable")
    q = df[["col_1", "col_2", "col_3", "col_4"]].to_numpy(float).copy()
    q[2, 2] = abs(q[2, 2])
    return q


def _fractions(before, after) -> np.ndarray:
    return 1.0 - np.atleast_2d(after) / before


def _rest_matrices(model, alpha, z, positions=None) -> np.ndarray:
    pos = paper_positions() if positions is None else positions
    times = rest_times_s(pos, 20 * DEG, 3.0, 100.0)
    return rest_residuals(alpha, model, "screw", z, positions_rad=pos, times_s=times)["q_matrix"]


def _sample_rotations(alpha, cov, z3) -> np.ndarray:
    vals, vecs = np.linalg.eigh(0.5 * (cov + cov.T))
    return alpha + z3 @ (vecs * np.sqrt(np.clip(vals, 0.0, None))).T


def candidate_fractions(fit: ErrorModelFit, *, n: int = 2000, seed: int = 2023) -> pd.DataFrame:
    """Each candidate's predicted pitch/yaw MaxAE reduction over the roll sweep (Tables 1–4 only).

    Parameters
    ----------
    fit : ErrorModelFit
        The fit to Tables 1–4 (:func:`.error_model.fit_error_model`).
    n : int
        Monte Carlo draws of a random candidate.
    seed : int

    Returns
    -------
    DataFrame, one row per candidate: ``candidate``, ``setting`` (what was put in), ``supported``
    (True where Tables 1–4 allow the mechanism at that size), ``support_reason``, and for ``pitch`` and
    ``yaw``: ``<axis>_after_deg`` (median MaxAE after), ``<axis>_fraction`` (median reduction 1 − after/before)
    with its 95 % band ``<axis>_fraction_low``/``_high`` (equal to the median for a fixed candidate).
    """
    n = int(n)
    if n < 2:
        raise ValueError(f"n must be >= 2, got {n}")
    rng = stream_rng(int(seed), STREAM_CAUSES)
    inst = fit_installation_angles(TABLES_1_TO_4["T1"])
    alpha = inst.alpha_rad
    before = roll_sweep_maxae_deg(alpha)
    rows = []

    def add(name, setting, after, supported, reason, before_=before):
        after = np.atleast_2d(after)
        frac = _fractions(before_, after)
        row = {"candidate": name, "setting": setting, "supported": bool(supported), "support_reason": reason}
        for j, ax in enumerate(("pitch", "yaw")):
            lo, med, hi = np.quantile(frac[:, j], [0.025, 0.5, 0.975])
            row.update({f"{ax}_before_deg": float(np.median(np.atleast_2d(before_)[:, j])),
                        f"{ax}_after_deg": float(np.median(after[:, j])), f"{ax}_fraction": float(med),
                        f"{ax}_fraction_low": float(lo), f"{ax}_fraction_high": float(hi)})
        rows.append(row)

    q_print = printed_matrix()
    add("printed matrix", "the paper's printed matrix (Q33 sign fixed) on the Table 1 'before' installation",
        roll_sweep_maxae_deg(alpha, q_print), True, "both are train numbers of the same session")

    z3 = rng.standard_normal((n, 3))
    a_true = _sample_rotations(alpha, inst.cov_rad2, z3)
    q_fit = true_error_matrix(alpha)
    after_u = np.array([roll_sweep_maxae_deg(a, q_fit) for a in a_true])
    before_u = np.array([roll_sweep_maxae_deg(a) for a in a_true])
    sd = np.degrees(np.sqrt(np.diag(inst.cov_rad2)))
    add("installation-angle uncertainty", f"true angles ~ N(fit, LS covariance), 1σ {sd[0]:.3f}/{sd[1]:.3f}/{sd[2]:.3f}°",
        after_u, True, "the LS covariance of the Table 1 'before' fit", before_=before_u)

    after_fit = fit_installation_angles(TABLES_1_TO_4["T1"], columns="after")
    d_rot = _sample_rotations(after_fit.alpha_rad, after_fit.cov_rad2, rng.standard_normal((n, 3)))
    after_d = np.array([roll_sweep_maxae_deg(d) for d in d_rot])   # a residual rotation δ couples as angles δ
    dd = np.degrees(after_fit.alpha_rad)
    add("Table 1 after-columns misalignment", f"residual rotation fitted to Table 1 'after − reference': "
        f"{dd[0]:+.3f}/{dd[1]:+.3f}/{dd[2]:+.3f}° (with its LS covariance)", after_d, True,
        "fitted to Table 1's own after columns")

    z = rng.standard_normal((n, N_NORMALS))
    sigma_ml = fit.model.position_error_arcsec
    sigma_hi = sigma_ml + 1.96 * fit.std["position_error_arcsec"]
    sigma_max = PRIOR_RANGES["position_error_arcsec"][1]
    for label, sig in (("ML", sigma_ml), ("95 % upper", sigma_hi), ("prior maximum", sigma_max)):
        m = replace(fit.model, position_error_arcsec=float(sig))
        add(f"per-rest angle error ({label})", f"position_error_arcsec = {sig:.1f}″ with the other fitted sources",
            roll_sweep_maxae_deg(alpha, _rest_matrices(m, alpha, z)), sig <= sigma_hi,
            f"Tables 1–4: {sigma_ml:.1f}″ ± {fit.std['position_error_arcsec']:.1f}″ (Laplace 1σ)"
            + ("" if sig <= sigma_hi else f"; {sig:.0f}″ lies {(sig - sigma_ml) / fit.std['position_error_arcsec']:.0f}σ "
               "above the ML: excluded"))
    keep = [0, 2, 3, 5]            # paper order yaw ±8°, pitch −12/+23°, roll ∓90°: one yaw and one roll rest dropped
    add("four positions", "Eq 13 on yaw +8°, pitch −12° and +23°, one roll 90° rest (4 of 6), fitted sources",
        roll_sweep_maxae_deg(alpha, _rest_matrices(fit.model, alpha, z, paper_positions()[keep])), False,
        "Tables 1–4 print six positions, each used by the paper's six-position procedure")
    add("printed-matrix quantisation", f"the true matrix rounded to {PRINTED_DECIMALS} decimals",
        roll_sweep_maxae_deg(alpha, np.round(q_fit, PRINTED_DECIMALS)), True,
        "the printed matrix has 6 decimals")
    return pd.DataFrame(rows)
