"""Installation-error calibration by least squares over quaternions (seed 000 §3.1).

Model (Eq 10): the true body attitude quaternion is a linear map of the
sensor attitude quaternion, ``A_q^b = Q_s^b A_q^s``, with a general 4×4
matrix ``Q_s^b``. Stacking K ≥ 4 calibration positions as columns of
``A_q^s`` and ``A_q^b`` (Eq 14, 4×K), the least-squares solution (Eq 11–13) is

    Q̂_s^b = A_q^b (A_q^s)ᵀ (A_q^s (A_q^s)ᵀ)⁻¹

which exists only if ``A_q^s`` has full row rank 4.

Sign rule: q and −q are the same attitude, so before solving every sensor
quaternion is flipped to ``q0 ≥ 0`` and every body quaternion is flipped so
that it agrees in sign with its sensor partner (``dot(q_b, q_s) ≥ 0``). This
makes the equations consistent for installation errors below 90°.

Examples
--------
>>> import numpy as np
>>> from mtcal import rotations
>>> q_bs = rotations.quat_from_euler_zxy(0.01, -0.02, 0.005)
>>> ang = np.radians([[8, 0, 0], [-8, 0, 0], [0, -12, 0], [0, 23, 0], [0, 0, 90], [0, 0, -90]])
>>> q_b = rotations.quat_from_euler_zxy(ang[:, 0], ang[:, 1], ang[:, 2])
>>> q_s = rotations.quat_multiply(q_b, q_bs)          # sensor = body ⊗ mounting
>>> Q = least_squares_error_matrix(q_s, q_b)
>>> bool(np.allclose(apply_error_matrix(Q, q_s), q_b))
True
"""

from __future__ import annotations

import numpy as np

from mtcal import rotations
from mtcal._validate import unit_quaternion

__all__ = ["least_squares_error_matrix", "apply_error_matrix", "align_pairs"]

#: Condition number of ``A_q^s (A_q^s)ᵀ`` above which positions are called degenerate.
MAX_CONDITION = 1e10


def align_pairs(q_sensor, q_body) -> tuple[np.ndarray, np.ndarray]:
    """Apply the sign rule: ``q_s0 ≥ 0`` and ``dot(q_b, q_s) ≥ 0`` for each pair (K, 4)."""
    q_s = rotations.align_signs(unit_quaternion(q_sensor, "q_sensor"))
    q_b = unit_quaternion(q_body, "q_body")
    if q_s.shape != q_b.shape or q_s.ndim != 2:
        raise ValueError(f"q_sensor and q_body must both have shape (K, 4), got {q_s.shape} and {q_b.shape}")
    return q_s, rotations.align_signs(q_b, q_s)


def least_squares_error_matrix(q_sensor, q_body) -> np.ndarray:
    """Seed 000 Eq 13: least-squares installation-error matrix ``Q̂_s^b`` (4×4).

    Parameters
    ----------
    q_sensor : array_like, shape (K, 4)
        Mean sensor attitude quaternion at each of K ≥ 4 positions (scalar-first).
        The paper (§3.1) says 3 positions suffice because of the norm
        constraint, but Eq 13 is linear and unconstrained: ``A_q^s (A_q^s)ᵀ``
        has rank ≤ K, so K ≥ 4 linearly independent quaternions are needed.
    q_body : array_like, shape (K, 4)
        Reference (true) body attitude quaternion at the same positions.

    Returns
    -------
    ndarray, shape (4, 4)
        ``Q̂`` such that ``q_body ≈ Q̂ q_sensor`` (column vectors).

    Raises
    ------
    ValueError
        If fewer than 4 positions are given or ``A_q^s (A_q^s)ᵀ`` is
        rank-deficient (condition number reported), e.g. all positions about
        one axis.
    """
    q_s, q_b = align_pairs(q_sensor, q_body)
    k = q_s.shape[0]
    if k < 4:
        raise ValueError(f"q_sensor must hold at least 4 positions, got {k}: A_q^s (A_q^s)^T is 4x4 "
                         f"with rank <= {k}, so Eq 13 has no unique solution (the paper's '3 positions' "
                         f"relies on the unit-norm constraint, which the linear LS does not use)")
    a_s, a_b = q_s.T, q_b.T  # Eq 14 layout: 4 × K
    gram = a_s @ a_s.T
    cond = np.linalg.cond(gram)
    if not np.isfinite(cond) or cond > MAX_CONDITION:
        raise ValueError(f"q_sensor positions are degenerate: A_q^s (A_q^s)^T is rank-deficient "
                         f"(condition number {cond:.3g} > {MAX_CONDITION:.0e}); use at least 3 "
                         f"distinct positions about more than one axis")
    return np.linalg.solve(gram, a_s @ a_b.T).T  # = A_b A_sᵀ (A_s A_sᵀ)⁻¹ (gram is symmetric)


def apply_error_matrix(q_matrix, q_sensor, *, normalize: bool = True) -> np.ndarray:
    """Seed 000 Eq 10: calibrated body quaternions ``Q̂ q_s`` for a stream (..., 4).

    The sensor stream is sign-aligned to ``q0 ≥ 0`` first (the rule used when
    solving). With ``normalize`` the result is rescaled to unit norm (the
    16-parameter LS map does not preserve the norm exactly).
    """
    q_mat = np.asarray(q_matrix, dtype=float)
    if q_mat.shape != (4, 4) or not np.all(np.isfinite(q_mat)):
        raise ValueError(f"q_matrix must be a finite 4x4 array, got shape {q_mat.shape}")
    q_s = rotations.align_signs(unit_quaternion(q_sensor, "q_sensor"))
    q_b = q_s @ q_mat.T
    return rotations.quat_normalize(q_b) if normalize else q_b
