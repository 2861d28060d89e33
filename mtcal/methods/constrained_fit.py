"""Constrained installation-error calibration: SO(4) and mounting-only fits beside the 16-parameter LS.

wang2023cja fits the map ``A_q^b = Q_s^b A_q^s`` (Eq 10) with a general 4×4
matrix: 16 free numbers (Eq 11–13). The physical relation is narrower. If the
sensor is mounted with quaternion ``c`` (``q_s = q_b ⊗ c``, the convention of
:mod:`mtcal.methods.quaternion_lsq`) and the sensor's attitude solution refers to a
reference frame rotated by ``w`` from the turntable/tunnel frame,

    q_s = w ⊗ q_b ⊗ c    ⇔    q_b = w* ⊗ q_s ⊗ c* = L(p) R(r) q_s,
    p = w*,  r = c*,

with ``L``/``R`` the left/right product matrices of :mod:`mtcal.core.rotations`
(``q ⊗ x = L(q) x``, ``x ⊗ q = R(q) x``). ``L(p) R(r)`` is a rotation of
quaternion space, an element of SO(4) (orthogonal, det +1), and every element
of SO(4) has this form, unique up to ``(p, r) → (−p, −r)`` (left/right
isoclinic factorisation, van Elfrinkhof 1897). So the true error matrix has 6
degrees of freedom, and 3 if the reference frame is shared (``w = 1``:
``q_b = q_s ⊗ c*``, ``Q = R(c*)``).

Estimators (same inputs and output as :func:`mtcal.methods.quaternion_lsq.least_squares_error_matrix`:
``q_sensor`` and ``q_body`` of shape (K, 4), scalar-first, and a 4×4 matrix
for :func:`mtcal.methods.quaternion_lsq.apply_error_matrix`; all also accept a leading
batch axis (..., K, 4) for Monte Carlo):

=====================  =====  =====================================================
estimator              DOF    minimum positions (noise-free identifiability)
=====================  =====  =====================================================
Eq 13 (16-param LS)    16     4 with linearly independent quaternions (rank A_s = 4)
:func:`fit_so4`        6      3 with linearly independent quaternions (rank A_s ≥ 3)
:func:`fit_mounting`   3      1 (any position)
=====================  =====  =====================================================

The paper (§3.1) says Eq 13 needs "at least three positions". That count is
wrong for Eq 13 as printed: ``A_s`` is 4×K, so ``A_s A_sᵀ`` has rank ≤ K and
is singular for K = 3 whatever the positions; the unit-norm constraint holds
for the data, it removes no unknowns from ``Q``. Three positions are the
minimum of the SO(4) fit, not of Eq 13.

Sign rule: :func:`mtcal.methods.quaternion_lsq.align_pairs` (``q_s0 ≥ 0``,
``dot(q_b, q_s) ≥ 0``) is applied before every fit. It makes the equations
consistent when the error map is within 180° in total, ``θ_p + θ_r < 180°``
(the symmetric part of ``L(p) R(r)`` is then positive definite, so
``q_sᵀ M q_s > 0``). The mounting fit is sign-invariant by construction.

References
----------
.. [1] Wang X., Zhao X., Zhou B., Wei Q., Zhang R., "Installation error calibration for MEMS
   angular measurement system in hypersonic wind tunnel", Chin. J. Aeronaut. 2023,
   doi:10.1016/j.cja.2022.12.006 (Eq 10–13, the 16-parameter LS).
.. [2] van Elfrinkhof L., "Eene eigenschap van de orthogonale substitutie van de vierde orde",
   Handelingen van het 6e Nederlandsch Natuurkundig en Geneeskundig Congres, Delft, 1897.
.. [3] Horn B. K. P., "Closed-form solution of absolute orientation using unit quaternions",
   J. Opt. Soc. Am. A 4(4), 629–642, 1987, doi:10.1364/JOSAA.4.000629 (q-method).

Examples
--------
>>> import numpy as np
>>> from mtcal.core import rotations
>>> c = rotations.quat_from_euler_zxy(0.01, -0.02, 0.005)          # mounting q_bs
>>> ang = np.radians([[8, 0, 0], [-8, 0, 0], [0, -12, 0], [0, 23, 0], [0, 0, 90], [0, 0, -90]])
>>> q_b = rotations.quat_from_euler_zxy(ang[:, 0], ang[:, 1], ang[:, 2])
>>> q_s = rotations.quat_multiply(q_b, c)
>>> fit = fit_mounting(q_s, q_b)
>>> bool(np.allclose(fit.c, c))
True
>>> bool(np.allclose(so4_error_matrix(q_s, q_b), rotations.right_matrix(rotations.quat_conjugate(c))))
True
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from mtcal.core import rotations
from mtcal.core.validate import as_float_array, positive_int, positive_scalar, unit_quaternion
from mtcal.methods import quaternion_lsq  # its trusted cores (_align_pairs, _least_squares)
from mtcal.methods.quaternion_lsq import MAX_CONDITION

__all__ = [
    "MIN_POSITIONS", "so4_from_quaternions", "associate_matrix", "factor_so4", "project_to_so4",
    "distance_to_orthogonal", "so4_error_matrix", "fit_so4",
    "mounting_error_matrix", "fit_mounting", "So4Fit", "MountingFit",
    "So4Projection", "CalibrationScenario",
    "symmetric_layout_rad", "random_layout_rad", "simulate_calibration_errors", "METHODS",
]

#: Minimum number of calibration positions per estimator (noise-free identifiability).
MIN_POSITIONS = {"eq13": 4, "so4": 3, "mounting": 1}
#: Estimator names used by :func:`simulate_calibration_errors`.
METHODS = ("eq13", "so4", "mounting")
#: Relative singular-value / eigen-gap threshold below which positions are degenerate
#: (``1/sqrt(MAX_CONDITION)`` of :mod:`mtcal.methods.quaternion_lsq`, i.e. the same rank test).
_REL_TOL = 1.0 / np.sqrt(MAX_CONDITION)
#: Elements from which :func:`_angle` runs a compiled loop (bit-identical to its numpy expressions).
_KERNEL_MIN_SIZE = 8192
#: Tolerance for "is in SO(4)" checks (Frobenius norm of ``MᵀM − I``).
SO4_ATOL = 1e-6


def _basis_tensor() -> np.ndarray:
    """T (16×16) with ``vec(L(p) R(r)) = T vec(p rᵀ)`` (row-major vec)."""
    e = np.eye(4)
    t = np.empty((16, 16))
    for a in range(4):
        for b in range(4):
            t[:, 4 * a + b] = (rotations.left_matrix(e[a]) @ rotations.right_matrix(e[b])).ravel()
    return t


_T = _basis_tensor()  # satisfies Tᵀ T = 4 I (tested)


# --------------------------------------------------------------------------
# SO(4) algebra
# --------------------------------------------------------------------------
def so4_from_quaternions(p, r) -> np.ndarray:
    """Rotation of quaternion space ``M = L(p) R(r)``: ``M x = p ⊗ x ⊗ r``.

    Parameters
    ----------
    p, r : array_like, shape (..., 4)
        Unit quaternions (scalar-first, dimensionless), broadcast together.

    Returns
    -------
    ndarray, shape (..., 4, 4)
        Orthogonal matrix with determinant +1.
    """
    p = unit_quaternion(p, "p")
    r = unit_quaternion(r, "r")
    return rotations.left_matrix(p) @ rotations.right_matrix(r)


def associate_matrix(matrix) -> np.ndarray:
    """Associate matrix ``P`` of a 4×4 matrix: ``P = p rᵀ`` when ``matrix = L(p) R(r)``.

    Derivation: every entry of ``L(p) R(r)`` is bilinear in ``(p, r)``, so
    ``vec(L(p) R(r)) = T vec(p rᵀ)`` with the fixed 16×16 matrix
    ``T[:, 4a+b] = vec(L(e_a) R(e_b))``. T is a scaled orthogonal matrix,
    ``Tᵀ T = 4 I``, hence ``vec(P) = Tᵀ vec(M) / 4``. For ``M`` in SO(4)
    ``P`` has rank 1 and singular value 1; for any ``M``,
    ``‖M − L(p) R(r)‖²_F = ‖M‖²_F − 8 pᵀ P r + 4``.

    Parameters
    ----------
    matrix : array_like, shape (..., 4, 4)

    Returns
    -------
    ndarray, shape (..., 4, 4)
    """
    return _associate(_matrix(matrix, "matrix"))


def _associate(m: np.ndarray) -> np.ndarray:
    """:func:`associate_matrix` of a checked float array (..., 4, 4)."""
    flat = m.reshape(m.shape[:-2] + (16,))
    return (flat @ _T / 4.0).reshape(m.shape)


def _factor(m: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Top singular pair of the associate matrix of a checked ``m``: (p, r, σ1), p0 ≥ 0."""
    u, s, vt = np.linalg.svd(_associate(m))
    p, r = u[..., :, 0], vt[..., 0, :]
    flip = np.where(p[..., :1] < 0.0, -1.0, 1.0)
    return p * flip, r * flip, s[..., 0]


def factor_so4(matrix, *, atol: float = SO4_ATOL) -> tuple[np.ndarray, np.ndarray]:
    """Factor an SO(4) matrix into unit quaternions ``(p, r)`` with ``M = L(p) R(r)``.

    ``p rᵀ`` is the associate matrix (see :func:`associate_matrix`); p and r
    are its leading left/right singular vectors. The pair is unique up to
    ``(−p, −r)``; the sign is chosen so that ``p0 ≥ 0``.

    Parameters
    ----------
    matrix : array_like, shape (..., 4, 4)
        Proper orthogonal matrix: ``‖MᵀM − I‖_F ≤ atol`` and ``det M > 0``.
        Use :func:`project_to_so4` for a matrix that is only near SO(4).
    atol : float
        Orthogonality tolerance.

    Returns
    -------
    p, r : ndarray, shape (..., 4)

    Examples
    --------
    >>> import numpy as np
    >>> p, r = np.array([0.6, 0.8, 0, 0]), np.array([0.8, 0, 0.6, 0])
    >>> pp, rr = factor_so4(so4_from_quaternions(p, r))
    >>> bool(np.allclose(pp, p) and np.allclose(rr, r))
    True
    """
    m = _matrix(matrix, "matrix")
    atol = positive_scalar(atol, "atol")
    ortho = np.linalg.norm(np.swapaxes(m, -1, -2) @ m - np.eye(4), axis=(-2, -1))
    if np.any(ortho > atol) or np.any(np.linalg.det(m) <= 0.0):
        raise ValueError(f"matrix must be in SO(4) (|M^T M - I| <= {atol:g} and det > 0); got "
                         f"max |M^T M - I| = {np.max(ortho):.3g}, min det = {np.min(np.linalg.det(m)):.6g}; "
                         f"use project_to_so4 first")
    p, r, _ = _factor(m)
    return p, r


@dataclass(frozen=True)
class So4Projection:
    """Nearest SO(4) matrix to a given 4×4 matrix, in the Frobenius norm.

    Attributes
    ----------
    matrix : ndarray (..., 4, 4)   projected matrix ``L(p) R(r)``
    distance : ndarray (...)       ``‖input − matrix‖_F`` (dimensionless)
    p, r : ndarray (..., 4)        left/right unit quaternions, ``p0 ≥ 0``
    determinant : ndarray (...)    determinant of the input
    """

    matrix: np.ndarray
    distance: np.ndarray
    p: np.ndarray
    r: np.ndarray
    determinant: np.ndarray


def _project(m: np.ndarray) -> np.ndarray:
    """Nearest SO(4) by SVD with determinant fix (Kabsch/Umeyama in 4-D)."""
    u, _, vt = np.linalg.svd(m)
    d = np.sign(np.linalg.det(u @ vt))
    d = np.where(d == 0.0, 1.0, d)
    u = u.copy()
    u[..., :, 3] *= d[..., None]
    return u @ vt


def project_to_so4(matrix: np.ndarray) -> So4Projection:
    """Project any 4×4 matrix onto SO(4) and factor the result.

    ``argmin_{M ∈ SO(4)} ‖X − M‖_F = U diag(1, 1, 1, det(U Vᵀ)) Vᵀ`` with
    ``X = U S Vᵀ``. For an improper input (det X < 0, e.g. the printed seed-000
    turntable matrix) the last singular direction is reflected, so the
    distance is ≥ 2·σ4 ≈ 2: the input is then near O(4) but not near SO(4)
    (see :func:`distance_to_orthogonal`).

    Parameters
    ----------
    matrix : ndarray, shape (..., 4, 4)
        Real matrix (dimensionless), e.g. an Eq 13 estimate.

    Returns
    -------
    So4Projection

    Preconditions
    -------------
    The caller guarantees (not checked here): ``matrix`` a finite float array of shape (..., 4, 4), e.g. an
    Eq 13 estimate a procedure made from quaternions it checked at its edge
    (:func:`mtcal.systems.installation.calibrate_record` through :mod:`mtcal.methods.six_position`).

    Examples
    --------
    >>> import numpy as np
    >>> proj = project_to_so4(np.diag([1.0, 1.004, 1.0, 1.0]))
    >>> print(f"{float(proj.distance):.4f}")
    0.0040
    """
    m = np.asarray(matrix, dtype=np.float64)
    proj = _project(m)
    p, r, _ = _factor(proj)
    return So4Projection(matrix=proj, distance=np.linalg.norm(m - proj, axis=(-2, -1)), p=p, r=r,
                         determinant=np.linalg.det(m))


def distance_to_orthogonal(matrix) -> np.ndarray:
    """Frobenius distance (dimensionless) from a 4×4 matrix to the nearest orthogonal matrix (O(4)).

    ``‖X − U Vᵀ‖_F = ‖S − I‖_F`` with ``X = U S Vᵀ``; the determinant sign is
    not constrained (compare :func:`project_to_so4`).
    """
    m = _matrix(matrix, "matrix")
    s = np.linalg.svd(m, compute_uv=False)
    return np.linalg.norm(s - 1.0, axis=-1)


# --------------------------------------------------------------------------
# estimators
# --------------------------------------------------------------------------
def _pairs(q_sensor, q_body, minimum: int, method: str) -> tuple[np.ndarray, np.ndarray]:
    """Validate (..., K, 4) unit-quaternion pairs (once), apply the sign rule of :func:`align_pairs`."""
    q_s = unit_quaternion(q_sensor, "q_sensor")
    q_b = unit_quaternion(q_body, "q_body")
    if q_s.ndim < 2 or q_s.shape != q_b.shape:
        raise ValueError(f"q_sensor and q_body must both have shape (K, 4) or (..., K, 4), "
                         f"got {q_s.shape} and {q_b.shape}")
    k = q_s.shape[-2]
    if k < minimum:
        raise ValueError(f"q_sensor must hold at least {minimum} positions for {method}, got {k}")
    return quaternion_lsq._align_pairs(q_s, q_b)


def _degenerate(bad: np.ndarray, out: np.ndarray, on_degenerate: str, message: str) -> np.ndarray:
    if on_degenerate not in ("raise", "nan"):
        raise ValueError(f"on_degenerate must be 'raise' or 'nan', got {on_degenerate!r}")
    if np.any(bad):
        if on_degenerate == "raise":
            raise ValueError(message)
        out = np.where(bad[..., None, None], np.nan, out)
    return out


@dataclass(frozen=True)
class So4Fit:
    """SO(4) calibration result.

    Attributes
    ----------
    matrix : ndarray (..., 4, 4)   ``Q̂ = L(p) R(r)``, usable with ``apply_error_matrix``
    p, r : ndarray (..., 4)        left / right unit quaternions (``q_b = p ⊗ q_s ⊗ r``)
    residual_rad : ndarray (..., K)  angle between ``Q̂ q_s`` and ``q_b`` at each position (rad)
    """

    matrix: np.ndarray
    p: np.ndarray
    r: np.ndarray
    residual_rad: np.ndarray = field(repr=False)


def fit_so4(q_sensor, q_body, *, on_degenerate: str = "raise") -> So4Fit:
    """Nearest rotation of quaternion space: orthogonal Procrustes in 4-D (6 DOF).

    Model: ``q_b,k = M q_s,k + e_k`` with ``M = L(p) R(r)`` ∈ SO(4). Least
    squares over SO(4)::

        min_M Σ_k ‖q_b,k − M q_s,k‖²  ⇔  max_M tr(Mᵀ B),   B = A_b A_sᵀ = Σ_k q_b,k q_s,kᵀ

    (the quadratic term ``‖M q_s‖² = ‖q_s‖²`` is constant on SO(4)). With
    ``B = U S Vᵀ``: ``M = U diag(1, 1, 1, det(U Vᵀ)) Vᵀ`` (Kabsch/Umeyama), then
    ``(p, r)`` by :func:`factor_so4`. The maximiser is unique iff
    ``rank B ≥ 3``; noise-free ``rank B = rank A_s``, so K ≥ 3 positions
    with linearly independent quaternions are required (2 positions leave a
    rotation of the orthogonal 2-plane free).

    Parameters
    ----------
    q_sensor, q_body : array_like, shape (K, 4) or (..., K, 4)
        Mean sensor attitude quaternions and reference body quaternions at K
        positions (scalar-first, unit norm within 1e-6, dimensionless).
    on_degenerate : {"raise", "nan"}
        Behaviour when ``σ3(B)/σ1(B) < 1e-5`` (the Eq 13 rank threshold).

    Returns
    -------
    So4Fit

    Raises
    ------
    ValueError
        NaN/inf, shape mismatch, non-unit quaternions, K < 3, or degenerate
        positions (with ``on_degenerate="raise"``).

    Examples
    --------
    >>> import numpy as np
    >>> from mtcal.core import rotations
    >>> p = rotations.quat_from_rotvec([0.0, 0.0, 0.004])              # reference yaw offset
    >>> c = rotations.quat_from_rotvec([0.003, -0.002, 0.001])         # mounting
    >>> ang = np.radians([[8, 0, 0], [0, -12, 0], [0, 0, 90]])         # 3 positions suffice
    >>> q_b = rotations.quat_from_euler_zxy(ang[:, 0], ang[:, 1], ang[:, 2])
    >>> q_s = rotations.quat_multiply(rotations.quat_multiply(rotations.quat_conjugate(p), q_b), c)
    >>> fit = fit_so4(q_s, q_b)
    >>> bool(np.allclose(fit.p, p) and np.allclose(fit.r, rotations.quat_conjugate(c)))
    True
    """
    return _fit_so4(*_pairs(q_sensor, q_body, MIN_POSITIONS["so4"], "the SO(4) fit (6 unknowns)"), on_degenerate)


def _fit_so4(q_s: np.ndarray, q_b: np.ndarray, on_degenerate: str) -> So4Fit:
    """:func:`fit_so4` of sign-aligned unit-quaternion pairs (..., K, 4), K ≥ 3 (from :func:`_pairs`)."""
    m, bad = _so4_matrix(q_s, q_b, on_degenerate)
    p, r, _ = _factor(np.where(np.isnan(m), 0.0, m))
    p = np.where(bad[..., None], np.nan, p)
    r = np.where(bad[..., None], np.nan, r)
    return So4Fit(matrix=m, p=p, r=r, residual_rad=_residual(m, q_s, q_b))


def _so4_matrix(q_s: np.ndarray, q_b: np.ndarray, on_degenerate: str) -> tuple[np.ndarray, np.ndarray]:
    """The matrix of :func:`_fit_so4` (NaN where degenerate) and the degenerate flags, without p, r, residuals."""
    b = np.swapaxes(q_b, -1, -2) @ q_s
    s = np.linalg.svd(b, compute_uv=False)
    bad = s[..., 2] <= _REL_TOL * s[..., 0]
    m = _degenerate(bad, _project(b), on_degenerate,
                    f"q_sensor positions are degenerate for the SO(4) fit: rank(A_b A_s^T) < 3 "
                    f"(sigma3/sigma1 = {np.min(s[..., 2] / s[..., 0]):.3g}); use at least 3 positions "
                    f"whose quaternions are linearly independent")
    return m, bad


def so4_error_matrix(q_sensor, q_body) -> np.ndarray:
    """SO(4) error matrix ``Q̂`` (4×4) from K ≥ 3 positions; see :func:`fit_so4`."""
    return fit_so4(q_sensor, q_body).matrix


@dataclass(frozen=True)
class MountingFit:
    """Mounting-only (3-DOF) calibration result.

    Attributes
    ----------
    matrix : ndarray (..., 4, 4)   ``Q̂ = R(c*)`` (``q_b = q_s ⊗ c*``)
    c : ndarray (..., 4)           mounting quaternion ``q_bs`` (``q_s = q_b ⊗ c``), ``c0 ≥ 0``
    residual_rad : ndarray (..., K)  angle between ``q_s,k ⊗ c*`` and ``q_b,k`` (rad)
    """

    matrix: np.ndarray
    c: np.ndarray
    residual_rad: np.ndarray = field(repr=False)


def fit_mounting(q_sensor, q_body, *, on_degenerate: str = "raise") -> MountingFit:
    """Mounting quaternion only (3 DOF), for a reference frame shared by sensor and body.

    Model: ``q_s,k = q_b,k ⊗ c`` (``c = q_bs``). Each position gives a direct
    estimate ``v_k = q_b,k* ⊗ q_s,k = L(q_b,k)ᵀ q_s,k = ±c``. The q-method
    (Davenport) criterion, invariant to the sign of every ``v_k``::

        max_{|c|=1} Σ_k (cᵀ v_k)² = cᵀ K c,   K = Σ_k v_k v_kᵀ = Σ_k L(q_b,k)ᵀ q_s,k q_s,kᵀ L(q_b,k)

    so ``c`` is the dominant eigenvector of the symmetric 4×4 ``K``. Since
    ``1 − (cᵀ v_k)² = sin²(δ_k / 2)`` with ``δ_k`` the rotation angle between
    ``c`` and ``v_k``, this minimises the sum of squared half-angle sines
    (the quaternion average of Markley et al., 2007). One position determines
    ``c`` (K = v vᵀ, eigen-gap 1); more positions average the noise. The
    error matrix is ``Q̂ = R(c*)``: ``q_b = q_s ⊗ c*``.

    Parameters
    ----------
    q_sensor, q_body : array_like, shape (K, 4) or (..., K, 4)
        K ≥ 1 positions (scalar-first unit quaternions, dimensionless).
    on_degenerate : {"raise", "nan"}
        Behaviour when the two largest eigenvalues of K tie
        (``(λ1 − λ2)/λ1 < 1e-5``): the data then support two mountings.

    Returns
    -------
    MountingFit

    Examples
    --------
    >>> import numpy as np
    >>> from mtcal.core import rotations
    >>> c = rotations.quat_from_rotvec([0.003, -0.002, 0.001])
    >>> q_b = rotations.quat_from_euler_zxy(0.1, 0.2, 0.3)[None]       # one position
    >>> fit = fit_mounting(rotations.quat_multiply(q_b, c), q_b)
    >>> bool(np.allclose(fit.c, c))
    True
    """
    return _fit_mounting(*_pairs(q_sensor, q_body, MIN_POSITIONS["mounting"], "the mounting fit (3 unknowns)"),
                         on_degenerate)


def _fit_mounting(q_s: np.ndarray, q_b: np.ndarray, on_degenerate: str) -> MountingFit:
    """:func:`fit_mounting` of sign-aligned unit-quaternion pairs (..., K, 4), K ≥ 1 (from :func:`_pairs`)."""
    m, c, bad = _mounting_matrix(q_s, q_b, on_degenerate)
    c = np.where(bad[..., None], np.nan, c)
    return MountingFit(matrix=m, c=c, residual_rad=_residual(m, q_s, q_b))


def _mounting_matrix(q_s: np.ndarray, q_b: np.ndarray, on_degenerate: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The matrix of :func:`_fit_mounting` (NaN where degenerate), ``c`` (not yet NaN-masked) and the degenerate
    flags, without residuals."""
    v = rotations.hamilton(rotations.quat_conjugate(q_b), q_s)          # (..., K, 4) = ±c
    kmat = np.swapaxes(v, -1, -2) @ v
    lam, vec = np.linalg.eigh(kmat)
    c = vec[..., :, 3]
    c = np.where(c[..., :1] < 0.0, -c, c)
    bad = (lam[..., 3] - lam[..., 2]) <= _REL_TOL * lam[..., 3]
    m = _degenerate(bad, rotations.right_matrix(rotations.quat_conjugate(c)), on_degenerate,
                    "q_sensor/q_body are degenerate for the mounting fit: the two largest eigenvalues "
                    "of K tie (the positions disagree on the mounting by ~180 deg)")
    return m, c, bad


def mounting_error_matrix(q_sensor, q_body) -> np.ndarray:
    """Mounting-only error matrix ``Q̂ = R(c*)`` (4×4) from K ≥ 1 positions; see :func:`fit_mounting`."""
    return fit_mounting(q_sensor, q_body).matrix


def _residual(m: np.ndarray, q_s: np.ndarray, q_b: np.ndarray) -> np.ndarray:
    return _angle(rotations.apply_quat_matrix_trusted(np.ascontiguousarray(m), q_s), q_b)


def _angle(q1: np.ndarray, q2: np.ndarray) -> np.ndarray:
    """Rotation angle (rad) between quaternions, NaN-propagating (no validation).

    Large float64 inputs of one shape: one compiled pass for everything but ``arctan2`` (bit-identical)."""
    if (q1.shape == q2.shape and q1.dtype == np.float64 and q2.dtype == np.float64
            and q1.size >= _KERNEL_MIN_SIZE and q1.flags.c_contiguous and q2.flags.c_contiguous):
        from mtcal.methods._constrained_kernels import angle_arguments   # lazy: numba loads on a large array

        rows = q1.size // 4
        num, den, nan = np.empty(rows), np.empty(rows), np.empty(rows, dtype=np.bool_)
        angle_arguments(q1.reshape(rows, 4), q2.reshape(rows, 4), num, den, nan)
        ang = np.arctan2(num, den, out=num)
        ang *= 2.0
        ang[nan] = np.nan
        return ang.reshape(q1.shape[:-1])
    d = rotations.hamilton(rotations.quat_conjugate(np.nan_to_num(q1)), q2)
    ang = 2.0 * np.arctan2(np.linalg.norm(d[..., 1:], axis=-1), np.abs(d[..., 0]))
    return np.where(np.any(np.isnan(q1), axis=-1), np.nan, ang)


# --------------------------------------------------------------------------
# Monte Carlo study
# --------------------------------------------------------------------------
def symmetric_layout_rad(k: int, base_rad) -> np.ndarray:
    """First ``k`` (1…12) positions of a symmetric six-position layout, extended; (k, 3) rad.

    ``base_rad`` holds six positions in the six-position order (yaw +, yaw −, pitch +, pitch −,
    roll +, roll −; rows ``[ψ, θ, γ]``, rad). Order of the result: yaw +, pitch +, roll +,
    yaw −, pitch −, roll − (so k = 6 is the base set), then the same six at half amplitude.
    Interleaving the axes keeps every prefix as well spread as possible (k = 3 already spans
    three independent quaternion directions, k = 4 all four).

    >>> base = np.radians([[8, 0, 0], [-8, 0, 0], [0, -12, 0], [0, 23, 0], [0, 0, 90], [0, 0, -90]])
    >>> symmetric_layout_rad(7, base).shape
    (7, 3)
    """
    k = positive_int(k, "k")
    if k > 12:
        raise ValueError(f"k must be <= 12, got {k}")
    base = as_float_array(base_rad, "base_rad", ndim=2, last_dim=3)
    if base.shape != (6, 3):
        raise ValueError(f"base_rad must have shape (6, 3), got {base.shape}")
    ring = base[[0, 2, 4, 1, 3, 5]]
    return np.concatenate([ring, ring / 2.0])[:k]


@dataclass(frozen=True)
class CalibrationScenario:
    """Monte Carlo scenario for the constrained-calibration study.

    Attributes
    ----------
    noise_sigma_rad : float
        σ (rad, per axis) of the random rotation perturbing each mean sensor
        quaternion: ``q_s ← q_s ⊗ exp(n/2)``, ``n ~ N(0, σ² I₃)``. Default
        0.02° (a per-position error of a tactical MEMS calibration; studies pass
        their identified value).
    mount_sigma_rad : float
        σ (rad, per axis) of the true mounting rotation vector. Default 0.3°:
        a careful screwed installation.
    reference_offset : bool
        False: sensor and body share the reference frame (3-DOF truth,
        ``q_s = q_b ⊗ c``). True: the sensor's attitude solution also carries
        a heading offset ``w = qz(β)``, ``β ~ N(0, mount_sigma²)``
        (``q_s = w ⊗ q_b ⊗ c``; e.g. a filter whose yaw is zeroed at power-on,
        tilt levelled by gravity) — the mounting-only fit is then biased.
    envelope_deg : tuple
        (min, max) of yaw, pitch, roll (degrees) for unseen test attitudes and
        random layouts (default: a wind-tunnel model envelope ±8°, −12…23°, ±90°).
    n_test : int
        Test attitudes per trial (uniform in the envelope, noise-free).
    """

    noise_sigma_rad: float = float(np.radians(0.02))
    mount_sigma_rad: float = float(np.radians(0.3))
    reference_offset: bool = False
    envelope_deg: tuple = ((-8.0, 8.0), (-12.0, 23.0), (-90.0, 90.0))
    n_test: int = 100

    def __post_init__(self) -> None:
        positive_scalar(self.noise_sigma_rad, "noise_sigma_rad", allow_zero=True)
        positive_scalar(self.mount_sigma_rad, "mount_sigma_rad", allow_zero=True)
        positive_int(self.n_test, "n_test")
        env = as_float_array(self.envelope_deg, "envelope_deg")
        if env.shape != (3, 2) or np.any(env[:, 1] < env[:, 0]):
            raise ValueError(f"envelope_deg must be 3 (min, max) pairs with min <= max, got {env.tolist()}")


def random_layout_rad(rng: np.random.Generator, n_trials: int, k: int,
                      envelope_deg=CalibrationScenario.envelope_deg) -> np.ndarray:
    """Random calibration layouts, (n_trials, k, 3) [yaw, pitch, roll] rad, uniform in the envelope."""
    n_trials = positive_int(n_trials, "n_trials")
    k = positive_int(k, "k")
    env = np.radians(as_float_array(envelope_deg, "envelope_deg"))
    return rng.uniform(env[:, 0], env[:, 1], size=(n_trials, k, 3))


def _euler_quat(angles: np.ndarray) -> np.ndarray:
    return rotations.quat_from_euler_zxy(angles[..., 0], angles[..., 1], angles[..., 2])


def simulate_calibration_errors(layout_rad, scenario: CalibrationScenario, n_trials: int,
                                rng: np.random.Generator, *, return_matrices: bool = False, methods=METHODS,
                                errors: bool = True):
    """Calibrated-attitude RMSE of Eq 13, SO(4) and mounting-only fits over Monte Carlo trials.

    Per trial (all vectorised over the leading trial axis): draw a mounting
    ``c`` (and heading offset ``w`` if ``scenario.reference_offset``), form
    the sensor quaternions of the layout, ``q_s = w ⊗ q_b ⊗ c``, perturb them
    by the noise rotation, fit the three estimators, then apply each fitted
    matrix (Eq 10, normalised) to the noise-free sensor quaternions of
    ``scenario.n_test`` unseen attitudes and take the RMS of the rotation angle
    to the true attitude. The result isolates the calibration error.

    Parameters
    ----------
    layout_rad : array_like, shape (K, 3) or (n_trials, K, 3)
        Calibration positions [yaw, pitch, roll] in rad (Eq 9 angles).
    scenario : CalibrationScenario
    n_trials : int
        Number of Monte Carlo seeds.
    rng : numpy.random.Generator

    return_matrices : bool
        Also return the fitted matrices.
    methods : sequence of str
        Estimators to fit (a subset of :data:`METHODS`); the others are not computed. The draws do not
        depend on it, so each estimator's numbers are the same whichever others are fitted beside it.
    errors : bool
        Compute the attitude RMSE on the test attitudes. ``False`` (with ``return_matrices``): only the
        fitted matrices, the test attitudes are neither drawn nor evaluated (the first dict is empty).

    Returns
    -------
    dict
        ``{"eq13", "so4", "mounting"}`` → attitude RMSE per trial (rad),
        shape (n_trials,); NaN where the layout is degenerate (or has too few
        positions, see :data:`MIN_POSITIONS`) for that estimator.
    dict, optional
        With ``return_matrices``: the same keys → fitted matrices (n_trials, 4, 4).
    """
    if not isinstance(scenario, CalibrationScenario):
        raise TypeError(f"scenario must be a CalibrationScenario, got {type(scenario).__name__}")
    methods = tuple(methods)
    if not methods or any(m not in METHODS for m in methods):
        raise ValueError(f"methods must be a non-empty subset of {METHODS}, got {methods}")
    if not errors and not return_matrices:
        raise ValueError("errors=False needs return_matrices=True (nothing would be returned)")
    n_trials = positive_int(n_trials, "n_trials")
    lay = as_float_array(layout_rad, "layout_rad", last_dim=3)
    if lay.ndim == 2:
        lay = np.broadcast_to(lay, (n_trials,) + lay.shape)
    if lay.ndim != 3 or lay.shape[0] != n_trials:
        raise ValueError(f"layout_rad must have shape (K, 3) or ({n_trials}, K, 3), got {lay.shape}")
    if np.max(np.abs(lay)) > np.pi:
        raise ValueError("layout_rad must be in radians (|angle| <= pi); degrees passed?")
    k = lay.shape[1]

    c = rotations.quat_from_rotvec(rng.normal(0.0, scenario.mount_sigma_rad, (n_trials, 3)))
    if scenario.reference_offset:
        beta = rng.normal(0.0, scenario.mount_sigma_rad, n_trials)
        w = rotations.quat_from_rotvec(np.stack([0 * beta, 0 * beta, beta], axis=-1))
    else:
        w = np.tile([1.0, 0.0, 0.0, 0.0], (n_trials, 1))

    def sensor(q_b: np.ndarray) -> np.ndarray:
        return rotations.hamilton(rotations.hamilton(w[:, None], q_b), c[:, None])

    q_b = _euler_quat(lay)
    noise = rotations.quat_from_rotvec(rng.normal(0.0, scenario.noise_sigma_rad, (n_trials, k, 3)))
    q_s = rotations.hamilton(sensor(q_b), noise)

    nan = np.full((n_trials, 4, 4), np.nan)
    pairs = quaternion_lsq._align_pairs(q_s, q_b)          # unit quaternions made here: no second check
    fits = {  # matrices only: no p, r, residuals here
        "eq13": lambda: quaternion_lsq._least_squares(*pairs, "nan") if k >= MIN_POSITIONS["eq13"] else nan,
        "so4": lambda: _so4_matrix(*pairs, "nan")[0] if k >= MIN_POSITIONS["so4"] else nan,
        "mounting": lambda: _mounting_matrix(*pairs, "nan")[0],
    }
    mats = {name: fit() for name, fit in fits.items() if name in methods}
    out = {}
    if not errors:
        return out, mats
    test = random_layout_rad(rng, n_trials, scenario.n_test, scenario.envelope_deg)   # drawn after the fits' draws
    qb_test = _euler_quat(test)
    qs_test = sensor(qb_test)
    for name, m in mats.items():
        err = _angle(rotations.apply_quat_matrix_trusted(np.ascontiguousarray(m), qs_test), qb_test)
        out[name] = np.sqrt(np.mean(err**2, axis=-1))
    return (out, mats) if return_matrices else out


# --------------------------------------------------------------------------
# small validators
# --------------------------------------------------------------------------
def _matrix(matrix, name: str) -> np.ndarray:
    m = as_float_array(matrix, name)
    if m.ndim < 2 or m.shape[-2:] != (4, 4):
        raise ValueError(f"{name} must have shape (..., 4, 4), got {m.shape}")
    return m
