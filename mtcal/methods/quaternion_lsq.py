"""Installation-error calibration by least squares over quaternions (wang2023cja §3.1).

Model (Eq 10): the true body attitude quaternion is a linear map of the
sensor attitude quaternion, ``A_q^b = Q_s^b A_q^s``, with a general 4×4
matrix ``Q_s^b``. Stacking K ≥ 4 calibration positions as columns of
``A_q^s`` and ``A_q^b`` (Eq 14, 4×K), the least-squares solution (Eq 11–13) is

    Q̂_s^b = A_q^b (A_q^s)ᵀ (A_q^s (A_q^s)ᵀ)⁻¹

which exists only if ``A_q^s`` has full row rank 4.

Sign rule: q and −q are the same attitude, so before solving every sensor
quaternion is flipped to ``q0 ≥ 0`` and every body quaternion is flipped so
that it agrees in sign with its sensor partner (``dot(q_b, q_s) ≥ 0``). This
makes the equations consistent while the map moves every quaternion by less
than 90° (installation errors). For a larger map (a sensor frame far from the
reference frame, ``L(p) R(r)`` with large factors) that dot product changes
sign from one position to the next, so the pairs are then made consistent with
each other instead: a rotation of quaternion space keeps every inner product,
``q_bi·q_bj = σ_i σ_j q_si·q_sj``, so the signs ``σ`` are those of the leading
eigenvector of ``(q_bi·q_bj)(q_si·q_sj)`` (a non-negative matrix when the signs
agree: its Perron vector is positive), the overall sign the one most pairs
have under the dot rule. Where the dot rule is already consistent nothing
changes (the same numbers).

Examples
--------
>>> import numpy as np
>>> from mtcal.core import rotations
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

from mtcal.core import rotations
from mtcal.core.validate import unit_quaternion

__all__ = ["least_squares_error_matrix", "apply_error_matrix", "align_pairs"]

#: Condition number of ``A_q^s (A_q^s)ᵀ`` above which positions are called degenerate.
MAX_CONDITION = 1e10


def align_pairs(q_sensor, q_body) -> tuple[np.ndarray, np.ndarray]:
    """Apply the sign rule to pairs (..., K, 4): ``q_s0 ≥ 0`` and ``dot(q_b, q_s) ≥ 0``.

    ``q_body`` may be (K, 4) and is then shared by every batch member.
    """
    q_s = unit_quaternion(q_sensor, "q_sensor")
    q_b = unit_quaternion(q_body, "q_body")
    if q_s.ndim < 2 or q_b.ndim < 2 or q_b.shape[-2:] != q_s.shape[-2:]:
        raise ValueError(f"q_sensor and q_body must both have shape (K, 4) or (..., K, 4), "
                         f"got {q_s.shape} and {q_b.shape}")
    try:
        np.broadcast_shapes(q_b.shape, q_s.shape)
    except ValueError:
        raise ValueError(f"q_body of shape {q_b.shape} must broadcast to q_sensor {q_s.shape}") from None
    if np.broadcast_shapes(q_b.shape, q_s.shape) != q_s.shape:
        raise ValueError(f"q_body of shape {q_b.shape} must broadcast to q_sensor {q_s.shape}")
    return _align_pairs(q_s, q_b)


def _flip(q: np.ndarray, ref: np.ndarray) -> np.ndarray:
    """Sign rule ``dot(q, ref) >= 0`` on float arrays (same arithmetic as ``rotations.align_signs``)."""
    dot = np.sum(q * ref, axis=-1, keepdims=True)
    return np.where(dot < 0.0, -q, q)


_IDENTITY = np.array([1.0, 0.0, 0.0, 0.0])


def _align_pairs(q_s: np.ndarray, q_b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`align_pairs` on checked unit quaternions, ``q_b`` broadcastable to ``q_s`` (trusted)."""
    q_s = _flip(q_s, _IDENTITY)
    q_b = _flip(np.broadcast_to(q_b, q_s.shape), q_s)
    sigma = _consistent_signs(q_s, q_b)
    if sigma is None:                      # the dot rule is consistent: the pairs as they are
        return q_s, q_b
    return q_s, q_b * sigma[..., None]


#: An inner-product sign contradiction ``(q_bi·q_bj)(q_si·q_sj)`` below −this is evidence against the dot rule (far
#: beyond what measurement noise gives positions whose quaternions are nearly orthogonal).
SIGN_CONTRADICTION = 1e-3


def _consistent_signs(q_s: np.ndarray, q_b: np.ndarray) -> np.ndarray | None:
    """Signs σ (..., K) that make dot-rule-aligned pairs consistent with one map (module docstring), or None
    when no batch member contradicts the dot rule (nothing to flip: the pairs as they are).

    ``M_ij = (q_bi·q_bj)(q_si·q_sj)`` is non-negative for consistent pairs of a rotation of quaternion space.
    A member with an entry below −:data:`SIGN_CONTRADICTION` gets the sign pattern of ``M``'s leading
    eigenvector, oriented so that most pairs keep their dot-rule sign — when that pattern removes every
    contradiction; otherwise (no pattern explains the pairs: not one map) the dot rule stands.
    """
    g_b = q_b @ np.swapaxes(q_b, -1, -2)
    g_s = q_s @ np.swapaxes(q_s, -1, -2)
    m = g_b * g_s
    bad = np.any(m < -SIGN_CONTRADICTION, axis=(-2, -1))
    if not np.any(bad):
        return None
    _, vec = np.linalg.eigh(np.where(bad[..., None, None], m, np.abs(m)))
    sigma = np.where(vec[..., -1] < 0.0, -1.0, 1.0)
    sigma = np.where(np.sum(sigma, axis=-1, keepdims=True) < 0.0, -sigma, sigma)   # most pairs as the dot rule
    fixed = np.all(m * sigma[..., :, None] * sigma[..., None, :] >= -SIGN_CONTRADICTION, axis=(-2, -1))
    return np.where((bad & fixed)[..., None], sigma, 1.0)


def least_squares_error_matrix(q_sensor, q_body, *, on_degenerate: str = "raise") -> np.ndarray:
    """wang2023cja Eq 13: least-squares installation-error matrix ``Q̂_s^b`` (4×4).

    Vectorised over any leading batch axes (Monte Carlo trials).

    Parameters
    ----------
    q_sensor : array_like, shape (K, 4) or (..., K, 4)
        Mean sensor attitude quaternion at each of K ≥ 4 positions (scalar-first).
        The paper (§3.1) says 3 positions suffice because of the norm
        constraint, but Eq 13 is linear and unconstrained: ``A_q^s (A_q^s)ᵀ``
        has rank ≤ K, so K ≥ 4 linearly independent quaternions are needed.
    q_body : array_like, shape (K, 4) or (..., K, 4)
        Reference (true) body attitude quaternion at the same positions.
    on_degenerate : {"raise", "nan"}
        Raise for rank-deficient positions, or return NaN matrices for those
        batch members (for Monte Carlo studies over random layouts).

    Returns
    -------
    ndarray, shape (..., 4, 4)
        ``Q̂`` such that ``q_body ≈ Q̂ q_sensor`` (column vectors).

    Raises
    ------
    ValueError
        If fewer than 4 positions are given or ``A_q^s (A_q^s)ᵀ`` is
        rank-deficient (condition number reported), e.g. all positions about
        one axis.
    """
    if on_degenerate not in ("raise", "nan"):
        raise ValueError(f"on_degenerate must be 'raise' or 'nan', got {on_degenerate!r}")
    return _least_squares(*align_pairs(q_sensor, q_body), on_degenerate)


def _least_squares(q_s: np.ndarray, q_b: np.ndarray, on_degenerate: str = "raise") -> np.ndarray:
    """Eq 13 on sign-aligned pairs from :func:`_align_pairs` (trusted)."""
    k = q_s.shape[-2]
    if k < 4:
        raise ValueError(f"q_sensor must hold at least 4 positions, got {k}: A_q^s (A_q^s)^T is 4x4 "
                         f"with rank <= {k}, so Eq 13 has no unique solution (the paper's '3 positions' "
                         f"relies on the unit-norm constraint, which the linear LS does not use)")
    a_s = np.swapaxes(q_s, -1, -2)  # Eq 14 layout: 4 × K
    gram = a_s @ q_s
    sv = np.linalg.svd(gram, compute_uv=False)
    cond = sv[..., 0] / np.maximum(sv[..., 3], np.finfo(float).tiny)
    bad = cond > MAX_CONDITION
    if np.any(bad) and on_degenerate == "raise":
        raise ValueError(f"q_sensor positions are degenerate: A_q^s (A_q^s)^T is rank-deficient "
                         f"(condition number {np.max(cond):.3g} > {MAX_CONDITION:.0e}); use at least 4 "
                         f"positions whose quaternions are linearly independent (more than one axis)")
    safe = np.where(bad[..., None, None], np.eye(4), gram)
    # Q̂ᵀ = (A_s A_sᵀ)⁻¹ A_s A_bᵀ  (the Gram matrix is symmetric)
    q_mat = np.swapaxes(np.linalg.solve(safe, a_s @ q_b), -1, -2)
    return np.where(bad[..., None, None], np.nan, q_mat)


def apply_error_matrix(q_matrix, q_sensor, *, normalize: bool = True) -> np.ndarray:
    """wang2023cja Eq 10: calibrated body quaternions ``Q̂ q_s`` for a stream.

    Parameters
    ----------
    q_matrix : array_like, shape (4, 4) or (..., 4, 4)
        Calibration matrix/matrices; NaN matrices (degenerate fits returned with
        ``on_degenerate="nan"``) give NaN output.
    q_sensor : array_like, shape (4,), (N, 4) or (..., N, 4)
        Sensor quaternions; batch axes must match those of ``q_matrix``.
    normalize : bool
        Rescale to unit norm (the 16-parameter LS map does not preserve the
        norm exactly).

    The sign of ``q_s`` does not matter (``Q̂`` is linear: ``Q̂(−q) = −Q̂ q``);
    streams are aligned to ``q0 ≥ 0`` for readability.
    """
    q_mat = np.array(q_matrix, dtype=float)
    if q_mat.ndim < 2 or q_mat.shape[-2:] != (4, 4) or np.any(np.isinf(q_mat)):
        raise ValueError(f"q_matrix must be a finite 4x4 array or a stack (..., 4, 4), got shape {q_mat.shape}")
    q_s = unit_quaternion(q_sensor, "q_sensor", copy=False)   # only read: the map returns new arrays
    if q_mat.ndim > 2 and q_s.ndim < 2:
        raise ValueError(f"q_sensor must have shape (..., N, 4) for a stack of matrices, got {q_s.shape}")
    try:
        np.broadcast_shapes(q_s.shape[:-2], q_mat.shape[:-2])
    except ValueError:
        raise ValueError(f"q_matrix {q_mat.shape} and q_sensor {q_s.shape} batch axes do not match") from None
    return rotations.apply_quat_matrix_trusted(q_mat, q_s, normalize)


#: Eq 10 on a checked matrix (stack) and checked unit quaternions: the trusted twin of
#: :func:`apply_error_matrix`, for procedures that checked or made their inputs. The map itself is core's
#: (:func:`mtcal.core.rotations.apply_quat_matrix_trusted`, with its preconditions), where the compiled
#: scoring passes of :mod:`mtcal.core.montecarlo` find it too.
_apply = rotations.apply_quat_matrix_trusted
