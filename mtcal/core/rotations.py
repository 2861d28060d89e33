"""Rotation conventions of the three seed papers, in one tested place.

All angles are in radians and all quaternions are **scalar-first**
``[q0, q1, q2, q3]`` (the papers' order). scipy's ``Rotation`` is
scalar-last by default; conversion happens only here, with
``scalar_first=True``.

Conventions, docs/conventions.md
--------------------------------
wang2023cja (Wang et al., CJA 2023)
    Eq 9 builds ``q = qz(ψ) ⊗ qx(θ) ⊗ qy(γ)``: yaw ψ about z, pitch θ about
    x, roll γ about y. It equals ``Rotation.from_euler('ZXY', [ψ, θ, γ])``.
    Eq 8 is its inverse. The frame is z-up, y forward (nose), x to the right.
    (§3.2 of the paper says "x yaw, y pitch, z roll"; Eq 8/9 are implemented
    as printed, see notebook 00.)
    Eq 1: installation matrix ``C_b^s = Rz(α1) Ry(α2) Rx(α3)``.
    Eq 4: small-angle coupling of installation errors into the attitude.
tan2022 (Tan et al., 2022)
    Aerospace Z-Y-X Euler angles (ψ, θ, φ); static specific force
    ``f = g [−sinθ, cosθ sinφ, cosθ cosφ]`` (Eq 2).
wang2022sensors (Wang et al., Sensors 2022)
    Rotation about unit axis v by θ: ``R(θ, v)`` (Rodrigues), measurement
    ``a = R(θ, v)ᵀ ā0``.

Quaternion sign rule
--------------------
q and −q are the same rotation. Before any least squares over quaternion
components, :func:`align_signs` flips each quaternion so that its dot product
with a reference quaternion is non-negative (default reference: identity for
:func:`align_signs`, the previous sample for :func:`make_continuous`).

Examples
--------
>>> import numpy as np
>>> q = quat_from_euler_zxy(np.radians(10.0), np.radians(20.0), np.radians(30.0))
>>> np.degrees(euler_zxy_from_quat(q)).round(6)
array([10., 20., 30.])
"""

from __future__ import annotations

import numpy as np

from mtcal.core.validate import angle_rad, as_float_array, unit_quaternion

__all__ = ["mount_quaternion", "relative_to_initial", "installation_angles", "installation_angles_from_mount",
    "GIMBAL_LOCK_COS",
    "hamilton", "quat_multiply", "quat_conjugate", "quat_normalize", "left_matrix", "right_matrix",
    "align_signs", "make_continuous", "quat_from_rotvec", "rotvec_from_quat",
    "quat_from_euler_zxy", "level_quat_zxy", "euler_zxy_from_quat", "euler_zxy_unchecked", "quat_to_matrix", "quat_from_matrix",
    "installation_matrix", "installation_matrix_small_angle", "coupling_error_eq4",
    "dcm_zyx", "specific_force_zyx", "pitch_roll_from_specific_force",
    "axis_angle_matrix", "wrap_angle", "quat_angle_between", "apply_quat_matrix_trusted", "mapped_pitch_trusted",
]


#: Quaternions (rows) from which the float64 helpers below run a compiled loop
#: (:mod:`mtcal.core._rotation_kernels`, bit-identical to the numpy expressions) instead of numpy
#: temporaries; smaller arrays (filters' per-step calls, doctests) stay in numpy and never load numba.
_KERNEL_MIN_ROWS = 2048


def _kernels():
    from mtcal.core import _rotation_kernels  # lazy: numba is loaded on the first large array only

    return _rotation_kernels


def _unit(q, name: str) -> np.ndarray:
    """``validate.unit_quaternion(q, name)`` for read-only use: a large float64 array is checked in
    one compiled pass and returned as is (no copy); anything else, or a failing check, goes through
    ``unit_quaternion`` (same errors)."""
    if (isinstance(q, np.ndarray) and q.dtype == np.float64 and q.ndim >= 1 and q.shape[-1] == 4
            and q.size >= 4 * _KERNEL_MIN_ROWS and _kernels().all_unit(q.reshape(-1, 4), 1e-6)):
        return q
    return unit_quaternion(q, name)


def _quats(q, name: str) -> np.ndarray:
    """``as_float_array(q, name, last_dim=4)`` for read-only use: a large float64 array is checked for
    finiteness in one compiled pass and returned as is (no copy); anything else goes through
    ``as_float_array`` (same errors)."""
    if (isinstance(q, np.ndarray) and q.dtype == np.float64 and q.ndim >= 1 and q.shape[-1] == 4
            and q.size >= 4 * _KERNEL_MIN_ROWS and _kernels().all_finite(q.reshape(-1, 4))):
        return q
    return as_float_array(q, name, last_dim=4)


def _large(*arrays) -> bool:
    return all(isinstance(a, np.ndarray) and a.dtype == np.float64 for a in arrays) and max(
        a.size for a in arrays) >= 4 * _KERNEL_MIN_ROWS


# --------------------------------------------------------------------------
# quaternion algebra (scalar-first, broadcasting over leading axes)
# --------------------------------------------------------------------------
def hamilton(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Unchecked Hamilton product ``p ⊗ q`` for hot loops (float arrays (..., 4)).

    Filters call this inside their time loop; public callers should use
    :func:`quat_multiply`, which validates its inputs first. Large float64 inputs
    (at most 3 axes after broadcasting) run one compiled loop, bit-identical.
    """
    if _large(p, q) and p.shape[-1] == 4 and q.shape[-1] == 4:
        shape = np.broadcast_shapes(p.shape, q.shape)
        if len(shape) <= 3:
            shape3 = (1,) * (3 - len(shape)) + shape
            out = np.empty(shape3)
            _kernels().hamilton3(np.broadcast_to(p, shape3), np.broadcast_to(q, shape3), out)
            return out.reshape(shape)
    p0, p1, p2, p3 = p[..., 0], p[..., 1], p[..., 2], p[..., 3]
    q0, q1, q2, q3 = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.stack([
        p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3,
        p0 * q1 + p1 * q0 + p2 * q3 - p3 * q2,
        p0 * q2 - p1 * q3 + p2 * q0 + p3 * q1,
        p0 * q3 + p1 * q2 - p2 * q1 + p3 * q0,
    ], axis=-1)


def quat_multiply(p, q) -> np.ndarray:
    """Hamilton product ``p ⊗ q`` of scalar-first quaternions, shape (..., 4).

    Broadcasts over leading axes. Neither input needs to be unit norm.
    """
    return hamilton(_quats(p, "p"), _quats(q, "q"))     # hamilton only reads its inputs


def quat_conjugate(q) -> np.ndarray:
    """Conjugate ``[q0, −q1, −q2, −q3]`` (the inverse of a unit quaternion), a new array."""
    q = _quats(q, "q")
    if q.size >= 4 * _KERNEL_MIN_ROWS:
        out = np.empty(q.shape)
        _kernels().conjugate2(q.reshape(-1, 4), out.reshape(-1, 4))
        return out
    q[..., 1:] *= -1.0                                # q is as_float_array's copy here
    return q


def quat_normalize(q) -> np.ndarray:
    """Return ``q / |q|``; raises if any quaternion has (near) zero norm."""
    q = _quats(q, "q")
    if q.size >= 4 * _KERNEL_MIN_ROWS:
        flat = q.reshape(-1, 4)
        out, norm = np.empty_like(flat), np.empty(flat.shape[0])
        _kernels().normalize2(flat, out, norm)
        if np.any(norm < 1e-12):
            raise ValueError("q must not contain zero-norm quaternions")
        return out.reshape(q.shape)
    norm = np.linalg.norm(q, axis=-1, keepdims=True)
    if np.any(norm < 1e-12):
        raise ValueError("q must not contain zero-norm quaternions")
    return q / norm


def left_matrix(q) -> np.ndarray:
    """Left product matrix ``L(q)`` with ``q ⊗ p = L(q) p``; shape (..., 4, 4)."""
    return left_matrix_trusted(as_float_array(q, "q", last_dim=4))


def left_matrix_trusted(q: np.ndarray) -> np.ndarray:
    """:func:`left_matrix` without input validation (not public API).

    Precondition: ``q`` is a finite float64 array (..., 4) (e.g. made by a procedure that checked
    its inputs at its edge). Bit-identical to :func:`left_matrix` on such input.
    """
    q0, q1, q2, q3 = np.moveaxis(q, -1, 0)
    rows = [[q0, -q1, -q2, -q3],
            [q1, q0, -q3, q2],
            [q2, q3, q0, -q1],
            [q3, -q2, q1, q0]]
    return np.stack([np.stack(r, axis=-1) for r in rows], axis=-2)


def right_matrix(q) -> np.ndarray:
    """Right product matrix ``R(q)`` with ``p ⊗ q = R(q) p``; shape (..., 4, 4)."""
    return right_matrix_trusted(as_float_array(q, "q", last_dim=4))


def right_matrix_trusted(q: np.ndarray) -> np.ndarray:
    """:func:`right_matrix` without input validation (not public API).

    Precondition: ``q`` is a finite float64 array (..., 4). Bit-identical to :func:`right_matrix`.
    """
    q0, q1, q2, q3 = np.moveaxis(q, -1, 0)
    rows = [[q0, -q1, -q2, -q3],
            [q1, q0, q3, -q2],
            [q2, -q3, q0, q1],
            [q3, q2, -q1, q0]]
    return np.stack([np.stack(r, axis=-1) for r in rows], axis=-2)


def align_signs(q, reference=None) -> np.ndarray:
    """Flip quaternions so that ``dot(q, reference) >= 0``.

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Scalar-first quaternions.
    reference : array_like, shape (4,) or broadcastable to q, optional
        Reference quaternion(s); default identity ``[1, 0, 0, 0]`` (i.e. make
        ``q0 >= 0``).

    Returns
    -------
    ndarray, shape (..., 4)
        Same rotations, consistent signs (a new array).
    """
    q = as_float_array(q, "q", last_dim=4)
    ref = (np.array([1.0, 0.0, 0.0, 0.0]) if reference is None
           else as_float_array(reference, "reference", last_dim=4))
    dot = np.sum(q * ref, axis=-1, keepdims=True)
    return np.where(dot < 0.0, -q, q)


def make_continuous(q, axis: int = -2) -> np.ndarray:
    """Flip signs along a time axis so consecutive quaternions have ``dot >= 0``.

    Parameters
    ----------
    q : array_like, shape (..., N, ..., 4)
        Quaternion time series; ``axis`` indexes time (default: the axis just
        before the component axis).
    """
    q = as_float_array(q, "q", last_dim=4)
    ax = axis % q.ndim
    if ax == q.ndim - 1:
        raise ValueError("axis must index time, not the quaternion component axis")
    qt = np.moveaxis(q, ax, 0)
    if q.size >= 4 * _KERNEL_MIN_ROWS and qt.shape[0] > 0:
        q3 = qt.reshape(qt.shape[0], -1, 4)
        out = np.empty(q3.shape)
        _kernels().continuous3(q3, out)
        return np.moveaxis(out.reshape(qt.shape), 0, ax)
    dots = np.sum(qt[1:] * qt[:-1], axis=-1)
    flips = np.concatenate([np.zeros((1,) + dots.shape[1:], dtype=bool), dots < 0], axis=0)
    parity = np.cumsum(flips, axis=0) % 2 == 1
    qt = np.where(parity[..., None], -qt, qt)
    return np.moveaxis(qt, 0, ax)


def quat_from_rotvec(rotvec) -> np.ndarray:
    """Quaternion of a rotation vector (Eq 7 of wang2023cja with Δθ = rotvec).

    ``q = [cos(|Δθ|/2), Δθ/|Δθ| sin(|Δθ|/2)]``, with the limit ``[1, Δθ/2]``
    handled without division by zero; shape (..., 3) → (..., 4).
    """
    v = as_float_array(rotvec, "rotvec", last_dim=3)
    if v.size >= 3 * _KERNEL_MIN_ROWS:
        k = _kernels()
        flat = v.reshape(-1, 3)
        angle, half = np.empty(flat.shape[0]), np.empty(flat.shape[0])
        k.rotvec_angle(flat, angle, half)
        out = np.empty((flat.shape[0], 4))
        k.quat_from_rotvec_finish(flat, angle, np.sin(half), np.cos(half), out)
        return out.reshape(v.shape[:-1] + (4,))
    angle = np.linalg.norm(v, axis=-1, keepdims=True)
    half = 0.5 * angle
    # sin(x/2)/x, series for small x avoids 0/0
    small = angle < 1e-8
    safe = np.where(small, 1.0, angle)
    k = np.where(small, 0.5 - angle**2 / 48.0, np.sin(half) / safe)
    return np.concatenate([np.cos(half), k * v], axis=-1)


def rotvec_from_quat(q) -> np.ndarray:
    """Rotation vector (axis × angle, angle in [0, π]) of unit quaternions."""
    q = _unit(q, "q")
    if q.size >= 4 * _KERNEL_MIN_ROWS:
        k = _kernels()
        flat = q.reshape(-1, 4)
        qf, vnorm = np.empty_like(flat), np.empty(flat.shape[0])
        k.rotvec_prepare(flat, qf, vnorm)
        out = np.empty((flat.shape[0], 3))
        k.rotvec_finish(qf, vnorm, 2.0 * np.arctan2(vnorm, qf[:, 0]), out)
        return out.reshape(q.shape[:-1] + (3,))
    q = align_signs(q)
    vnorm = np.linalg.norm(q[..., 1:], axis=-1, keepdims=True)
    angle = 2.0 * np.arctan2(vnorm, q[..., :1])
    small = vnorm < 1e-12
    k = np.where(small, 2.0, angle / np.where(small, 1.0, vnorm))
    return k * q[..., 1:]


def quat_angle_between(p, q) -> np.ndarray:
    """Rotation angle (rad, in [0, π]) of ``p⁻¹ ⊗ q`` — the attitude difference."""
    p = unit_quaternion(p, "p")
    q = unit_quaternion(q, "q")
    d = hamilton(quat_conjugate(p), q)  # atan2 keeps full precision near zero (arccos does not)
    return 2.0 * np.arctan2(np.linalg.norm(d[..., 1:], axis=-1), np.abs(d[..., 0]))


def quat_to_matrix(q) -> np.ndarray:
    """Direction-cosine matrix of scalar-first unit quaternions, (..., 4) → (..., 3, 3).

    The matrix maps vectors from the rotated frame to the reference frame
    (``v_ref = C v_body``), as scipy's ``Rotation.as_matrix``.
    """
    return quat_to_matrix_trusted(_unit(q, "q"))


def quat_to_matrix_trusted(q: np.ndarray) -> np.ndarray:
    """:func:`quat_to_matrix` without input validation (not public API).

    Precondition: ``q`` is a float64 array (..., 4) of unit quaternions (to 1e-6). Bit-identical to
    :func:`quat_to_matrix` on such input.
    """
    shape = q.shape[:-1]
    if q.size >= 4 * _KERNEL_MIN_ROWS:   # the same arithmetic as scipy's loop, bit for bit
        mat = np.empty((q.size // 4, 3, 3))
        _kernels().matrix_from_quat(q.reshape(-1, 4), mat)
        return mat.reshape(shape + (3, 3))
    from scipy.spatial.transform import Rotation  # lazy: scipy costs ~0.5 s of every CLI call's start-up

    mat = Rotation.from_quat(q.reshape(-1, 4), scalar_first=True).as_matrix()
    return mat.reshape(shape + (3, 3))


def quat_from_matrix(matrix) -> np.ndarray:
    """Scalar-first unit quaternion (q0 >= 0) of rotation matrices (..., 3, 3)."""
    m = as_float_array(matrix, "matrix")
    if m.ndim < 2 or m.shape[-2:] != (3, 3):
        raise ValueError(f"matrix must have shape (..., 3, 3), got {m.shape}")
    from scipy.spatial.transform import Rotation  # lazy, see quat_to_matrix

    shape = m.shape[:-2]
    q = Rotation.from_matrix(m.reshape(-1, 3, 3)).as_quat(scalar_first=True)
    return align_signs(q.reshape(shape + (4,)))


# --------------------------------------------------------------------------
# wang2023cja: Eq 8 / Eq 9 (ZXY), Eq 1, Eq 4
# --------------------------------------------------------------------------
def quat_from_euler_zxy(yaw, pitch, roll) -> np.ndarray:
    """wang2023cja Eq 9: scalar-first quaternion from yaw ψ, pitch θ, roll γ (rad).

    ``q = qz(ψ) ⊗ qx(θ) ⊗ qy(γ)``, i.e. ``Rotation.from_euler('ZXY',
    [ψ, θ, γ])``::

        q0 = cθ/2 cψ/2 cγ/2 − sθ/2 sψ/2 sγ/2
        q1 = sθ/2 cψ/2 cγ/2 − cθ/2 sψ/2 sγ/2
        q2 = sθ/2 sψ/2 cγ/2 + cθ/2 cψ/2 sγ/2
        q3 = cθ/2 sψ/2 cγ/2 + sθ/2 cψ/2 sγ/2

    Parameters
    ----------
    yaw, pitch, roll : array_like
        Angles in radians, broadcast against each other.

    Returns
    -------
    ndarray, shape (..., 4)
    """
    psi = angle_rad(yaw, "yaw", allow_empty=True)
    theta = angle_rad(pitch, "pitch", allow_empty=True)
    gamma = angle_rad(roll, "roll", allow_empty=True)
    return quat_from_euler_zxy_trusted(psi, theta, gamma)


def level_quat_zxy(accel_m_s2, yaw_rad: float = 0.0) -> np.ndarray:
    """Levelling: the ZXY quaternion (wang2023cja Eq 9) whose pitch/roll explain a static specific force.

    For the ZXY convention a static sensor reads ``f = g [−sinγ cosθ, sinθ, cosγ cosθ]``, so
    ``θ = asin(f_y/‖f‖)`` and ``γ = atan2(−f_x, f_z)``; the yaw is assigned.

    Parameters
    ----------
    accel_m_s2 : array_like, shape (..., 3)
        Mean static specific force (m/s², any scale).
    yaw_rad : float
        Yaw to assign (rad), default 0.

    Returns
    -------
    ndarray, shape (..., 4)
        Scalar-first quaternion, sensor → world.

    Raises
    ------
    ValueError
        A zero specific force (no gravity to level on).

    Examples
    --------
    >>> q = level_quat_zxy([0.0, 0.0, 9.81])
    >>> q.tolist()
    [1.0, 0.0, 0.0, 0.0]
    """
    f = as_float_array(accel_m_s2, "accel_m_s2", last_dim=3)
    norm = np.linalg.norm(f, axis=-1)
    if np.any(norm < 1e-6):
        raise ValueError("accel_m_s2 must not be zero (cannot level without gravity)")
    pitch = np.arcsin(np.clip(f[..., 1] / norm, -1.0, 1.0))
    roll = np.arctan2(-f[..., 0], f[..., 2])
    return quat_from_euler_zxy(np.full_like(pitch, yaw_rad), pitch, roll)


def quat_from_euler_zxy_trusted(yaw: np.ndarray, pitch: np.ndarray, roll: np.ndarray) -> np.ndarray:
    """wang2023cja Eq 9 without input validation (not public API; users call :func:`quat_from_euler_zxy`).

    Preconditions: ``yaw``, ``pitch``, ``roll`` are finite float64 arrays (rad) that broadcast against
    each other — e.g. columns of positions a procedure checked at its edge. Bit-identical to
    :func:`quat_from_euler_zxy` on such input; shape (..., 4).
    """
    psi, theta, gamma = np.broadcast_arrays(yaw, pitch, roll)
    cp, sp = np.cos(psi / 2), np.sin(psi / 2)
    ct, st = np.cos(theta / 2), np.sin(theta / 2)
    cg, sg = np.cos(gamma / 2), np.sin(gamma / 2)
    if psi.size >= _KERNEL_MIN_ROWS:
        out = np.empty((psi.size, 4))
        _kernels().euler_zxy_products(*(np.ravel(x) for x in (cp, sp, ct, st, cg, sg)), out)
        return out.reshape(psi.shape + (4,))
    return np.stack([
        ct * cp * cg - st * sp * sg,
        st * cp * cg - ct * sp * sg,
        st * sp * cg + ct * cp * sg,
        ct * sp * cg + st * cp * sg,
    ], axis=-1)


def euler_zxy_from_quat(q) -> np.ndarray:
    """wang2023cja Eq 8: yaw ψ, pitch θ, roll γ (rad) from scalar-first unit quaternions.

    ::

        ψ = atan2(−2(q1q2 − q0q3), q0² − q1² + q2² − q3²)   ∈ [−π, π]
        θ = asin(2(q2q3 + q0q1))                            ∈ [−π/2, π/2]
        γ = atan2(−2(q1q3 − q0q2), q0² − q1² − q2² + q3²)   ∈ [−π, π]

    Gimbal lock (θ = ±90°): Eq 8's atan2 arguments vanish there and lose
    accuracy as ~1e-16/cos θ near it, so where cos θ < :data:`GIMBAL_LOCK_COS`
    the half-angle form (ψ ± γ from ``q0 ± q1``, ``q3 ± q2``) is used; at
    exact lock roll is 0 and all rotation about the vertical is yaw. The
    result always reconstructs ``q`` through Eq 9 (to ~1e-15); elsewhere it
    is the printed Eq 8, bit for bit.

    Returns
    -------
    ndarray, shape (..., 3)
        ``[ψ, θ, γ]`` along the last axis.

    Examples
    --------
    >>> import numpy as np
    >>> np.degrees(euler_zxy_from_quat([0.5, 0.5, 0.5, 0.5])).round(9).tolist()  # exact lock
    [90.0, 90.0, 0.0]
    """
    return euler_zxy_unchecked(_unit(q, "q"))


def euler_zxy_unchecked(q: np.ndarray) -> np.ndarray:
    """Eq 8 without input validation, for filter outputs that are unit by construction.

    Same formulas as :func:`euler_zxy_from_quat` (which calls it after
    checking ``q``); ``q`` must be a float array (..., 4) of unit quaternions.
    Within :data:`GIMBAL_LOCK_COS` of pitch ±90° the half-angle form is used
    (see :func:`euler_zxy_from_quat`), elsewhere the printed Eq 8.
    """
    out = np.empty(q.shape[:-1] + (3,))
    if _large(q):
        flat = q.reshape(-1, 4)
        y0, x0, sin_pitch, y2, x2 = (np.empty(flat.shape[0]) for _ in range(5))
        _kernels().euler_zxy_arguments(flat, y0, x0, sin_pitch, y2, x2)
        o = out.reshape(-1, 3)
        np.arctan2(y0, x0, out=o[:, 0])
        np.arcsin(sin_pitch, out=o[:, 1])
        np.arctan2(y2, x2, out=o[:, 2])
        near = np.abs(sin_pitch) > _LOCK_SIN
        if np.any(near):
            o[near] = _euler_zxy_near_lock(flat[near])
        return out
    q0, q1, q2, q3 = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    s00, s11, s22, s33 = q0 * q0, q1 * q1, q2 * q2, q3 * q3
    sin_pitch = np.clip(2.0 * (q2 * q3 + q0 * q1), -1.0, 1.0)
    np.arctan2(-2.0 * (q1 * q2 - q0 * q3), s00 - s11 + s22 - s33, out=out[..., 0])
    np.arcsin(sin_pitch, out=out[..., 1])
    np.arctan2(-2.0 * (q1 * q3 - q0 * q2), s00 - s11 - s22 + s33, out=out[..., 2])
    near = np.abs(sin_pitch) > _LOCK_SIN
    if np.any(near):
        out[near] = _euler_zxy_near_lock(q[near])
    return out



#: Rows per block of :func:`euler_zxy_rows_trusted` (cache-sized temporaries; blocks run on all cores).
EULER_BLOCK_ROWS = 65_536


def euler_zxy_rows_trusted(q: np.ndarray) -> np.ndarray:
    """:func:`euler_zxy_unchecked` of a long record ``q`` (N, 4) in row blocks on a thread pool (rad, (N, 3)).

    Elementwise, so the blocks change no bit; without full-length temporaries (a log of millions of
    samples). Trusts ``q``: float64 (N, 4), unit by construction (a filter's output).

    Examples
    --------
    >>> q = quat_from_euler_zxy(np.full(3, 0.1), np.full(3, -0.2), np.full(3, 0.3))
    >>> np.round(euler_zxy_rows_trusted(q), 12).tolist()
    [[0.1, -0.2, 0.3], [0.1, -0.2, 0.3], [0.1, -0.2, 0.3]]
    """
    import os
    from concurrent.futures import ThreadPoolExecutor

    out = np.empty((q.shape[0], 3))

    def block(start: int) -> None:
        stop = min(start + EULER_BLOCK_ROWS, q.shape[0])
        out[start:stop] = euler_zxy_unchecked(q[start:stop])

    starts = range(0, q.shape[0], EULER_BLOCK_ROWS)
    if len(starts) <= 1:
        for s in starts:
            block(s)
        return out
    with ThreadPoolExecutor(max_workers=min(len(starts), os.cpu_count() or 1)) as pool:
        list(pool.map(block, starts))
    return out

#: cos(pitch) below which Eq 8's yaw/roll atan2 pair is replaced by the half-angle form
#: (there Eq 8 loses ~1e-16/cos θ rad; 1e-3 keeps every result above it bit-identical).
GIMBAL_LOCK_COS = 1e-3
_LOCK_SIN = float(np.sqrt(1.0 - GIMBAL_LOCK_COS**2))


def _euler_zxy_near_lock(q: np.ndarray) -> np.ndarray:
    """Half-angle ZXY extraction, exact at and near pitch ±90° (q: (M, 4) unit).

    With half angles a = ψ/2, b = γ/2, t = θ/2, Eq 9 gives
    ``q0 ± q1 = (cos t ± sin t) cos(a ± b)`` and ``q3 ± q2 = (cos t ± sin t) sin(a ± b)``,
    so ψ + γ and ψ − γ come from two well-conditioned atan2 and
    ``θ = π/2 − 2 atan2(‖(q0 − q1, q3 − q2)‖, ‖(q0 + q1, q3 + q2)‖)``.
    At exact lock one of the two pairs is (0, 0): roll is set to 0 and the whole
    rotation about the vertical goes to yaw (θ = +90°: ψ = ψ+γ; θ = −90°: ψ = ψ−γ).
    """
    q0, q1, q2, q3 = q[:, 0], q[:, 1], q[:, 2], q[:, 3]
    sp, cp = q0 + q1, q3 + q2      # (cos t + sin t) · (cos, sin)(a + b)
    sm, cm = q0 - q1, q3 - q2      # (cos t − sin t) · (cos, sin)(a − b)
    plus = np.hypot(sp, cp)
    minus = np.hypot(sm, cm)
    theta = 0.5 * np.pi - 2.0 * np.arctan2(minus, plus)
    half_sum = np.arctan2(cp, sp)   # a + b
    half_diff = np.arctan2(cm, sm)  # a − b
    tiny = 1e-15
    half_diff = np.where(minus <= tiny, half_sum, half_diff)   # θ = +90°: roll 0
    half_sum = np.where(plus <= tiny, half_diff, half_sum)     # θ = −90°: roll 0
    psi = half_sum + half_diff
    gamma = half_sum - half_diff
    out = np.stack([psi, theta, gamma], axis=-1)
    out[:, [0, 2]] = (out[:, [0, 2]] + np.pi) % (2.0 * np.pi) - np.pi
    return out


def installation_matrix(alpha1, alpha2, alpha3) -> np.ndarray:
    """wang2023cja Eq 1: installation-error matrix ``C_b^s = Rz(α1) Ry(α2) Rx(α3)``.

    Parameters
    ----------
    alpha1, alpha2, alpha3 : array_like
        Installation angles (rad) about z, y and x.

    Returns
    -------
    ndarray, shape (..., 3, 3)
    """
    a1 = angle_rad(alpha1, "alpha1")
    a2 = angle_rad(alpha2, "alpha2")
    a3 = angle_rad(alpha3, "alpha3")
    a1, a2, a3 = np.broadcast_arrays(a1, a2, a3)
    c1, s1, c2, s2, c3, s3 = np.cos(a1), np.sin(a1), np.cos(a2), np.sin(a2), np.cos(a3), np.sin(a3)
    rows = [[c1 * c2, -c3 * s1 + s3 * c1 * s2, s3 * s1 + c3 * c1 * s2],
            [s1 * c2, c3 * c1 + s3 * s1 * s2, -s3 * c1 + c3 * s1 * s2],
            [-s2, s3 * c2, c3 * c2]]
    return np.stack([np.stack(r, axis=-1) for r in rows], axis=-2)


def installation_matrix_small_angle(alpha1, alpha2, alpha3) -> np.ndarray:
    """wang2023cja Eq 1, small-angle form ``[[1, −α1, α2], [α1, 1, −α3], [−α2, α3, 1]]``."""
    a1 = angle_rad(alpha1, "alpha1")
    a2 = angle_rad(alpha2, "alpha2")
    a3 = angle_rad(alpha3, "alpha3")
    a1, a2, a3 = np.broadcast_arrays(a1, a2, a3)
    one = np.ones_like(a1)
    rows = [[one, -a1, a2], [a1, one, -a3], [-a2, a3, one]]
    return np.stack([np.stack(r, axis=-1) for r in rows], axis=-2)


def coupling_error_eq4(alphas, angles_s, *, printed: bool = False) -> np.ndarray:
    """wang2023cja Eq 4: attitude error caused by small installation errors.

    Δ = ``[ψs, θs, γs] − [ψ, θ, γ]`` with ``[ψ, θ, γ] = C_s^b [ψs, θs, γs]``
    (Eq 3). From Eq 1, ``I − C_s^b ≈ [[0, −α1, α2], [α1, 0, −α3], [−α2, α3, 0]]``::

        Δψ = −α1 θs + α2 γs
        Δθ =  α1 ψs − α3 γs
        Δγ = −α2 ψs + α3 θs

    The paper prints the negative of each term (``printed=True``), which is
    *true − measured* (erratum 7 in ``docs/errata.md``).

    Parameters
    ----------
    alphas : array_like, shape (..., 3)
        Installation angles ``[α1, α2, α3]`` in rad.
    angles_s : array_like, shape (..., 3)
        Angles solved in the sensor frame ``[ψs, θs, γs]`` in rad.
    printed : bool
        Return the formula as printed in the paper instead of the corrected one.
    """
    a = angle_rad(alphas, "alphas", last_dim=3)
    s = angle_rad(angles_s, "angles_s", last_dim=3)
    a1, a2, a3 = np.moveaxis(a, -1, 0)
    ps, ts, gs = np.moveaxis(s, -1, 0)
    delta = np.stack([-a1 * ts + a2 * gs, a1 * ps - a3 * gs, -a2 * ps + a3 * ts], axis=-1)
    return -delta if printed else delta


# --------------------------------------------------------------------------
# tan2022: aerospace Z-Y-X
# --------------------------------------------------------------------------
def dcm_zyx(yaw, pitch, roll) -> np.ndarray:
    """Aerospace Z-Y-X direction-cosine matrix ``C_n^b`` (navigation → body).

    ``C_n^b = Rx(φ)ᵀ Ry(θ)ᵀ Rz(ψ)ᵀ``, the transpose of
    ``Rotation.from_euler('ZYX', [ψ, θ, φ]).as_matrix()``. This is the
    corrected form of tan2022 Eq 1 (the printed one has θ where φ belongs).
    """
    from scipy.spatial.transform import Rotation  # lazy, see quat_to_matrix

    psi = angle_rad(yaw, "yaw")
    theta = angle_rad(pitch, "pitch")
    phi = angle_rad(roll, "roll")
    psi, theta, phi = np.broadcast_arrays(psi, theta, phi)
    angles = np.stack([psi, theta, phi], axis=-1)
    shape = angles.shape[:-1]
    mat = Rotation.from_euler("ZYX", angles.reshape(-1, 3)).as_matrix()
    return np.swapaxes(mat, -1, -2).reshape(shape + (3, 3))


def specific_force_zyx(pitch, roll, g: float = 1.0) -> np.ndarray:
    """tan2022 Eq 2: static accelerometer triad ``g [−sinθ, cosθ sinφ, cosθ cosφ]``.

    Parameters
    ----------
    pitch, roll : array_like
        θ and φ in rad (broadcast).
    g : float
        Gravity magnitude in the output unit (1.0 → output in g).
    """
    theta = angle_rad(pitch, "pitch")
    phi = angle_rad(roll, "roll")
    theta, phi = np.broadcast_arrays(theta, phi)
    return g * np.stack([-np.sin(theta), np.cos(theta) * np.sin(phi),
                         np.cos(theta) * np.cos(phi)], axis=-1)


def pitch_roll_from_specific_force(f) -> np.ndarray:
    """tan2022 Eq 2 inverted: ``θ = atan2(−fx, √(fy² + fz²))``, ``φ = atan2(fy, fz)``.

    Returns ``[θ, φ]`` in rad along the last axis; ``f`` in any unit, shape (..., 3).
    """
    f = as_float_array(f, "f", last_dim=3)
    theta = np.arctan2(-f[..., 0], np.hypot(f[..., 1], f[..., 2]))
    phi = np.arctan2(f[..., 1], f[..., 2])
    return np.stack([theta, phi], axis=-1)


# --------------------------------------------------------------------------
# wang2022sensors: rotation about a unit axis
# --------------------------------------------------------------------------
def axis_angle_matrix(angle, axis) -> np.ndarray:
    """Rodrigues rotation ``R(θ, v) = I + sinθ [v]× + (1 − cosθ) [v]×²``.

    Parameters
    ----------
    angle : array_like, shape (...)
        θ in rad.
    axis : array_like, shape (3,) or (..., 3)
        Unit rotation axis v (|v| = 1 within 1e-6).

    Returns
    -------
    ndarray, shape (..., 3, 3)
    """
    theta = as_float_array(angle, "angle")
    v = as_float_array(axis, "axis", last_dim=3)
    norm = np.linalg.norm(v, axis=-1)
    if np.any(np.abs(norm - 1.0) > 1e-6):
        raise ValueError(f"axis must be a unit vector, got |axis| = {np.atleast_1d(norm)[0]:.6g}")
    vx, vy, vz = np.moveaxis(v, -1, 0)
    zero = np.zeros_like(vx)
    k = np.stack([np.stack([zero, -vz, vy], -1), np.stack([vz, zero, -vx], -1),
                  np.stack([-vy, vx, zero], -1)], axis=-2)
    s = np.sin(theta)[..., None, None]
    c = np.cos(theta)[..., None, None]
    return np.eye(3) + s * k + (1.0 - c) * (k @ k)


def wrap_angle(angle) -> np.ndarray:
    """Wrap angles (rad) to ``[−π, π)``."""
    a = as_float_array(angle, "angle", allow_empty=True)
    return (a + np.pi) % (2.0 * np.pi) - np.pi


def mount_quaternion(alpha_rad) -> np.ndarray:
    """``q_bs`` (simulator ``q_mount``) of Eq 1 angles ``[α1, α2, α3]`` (rad, shape (..., 3)): C(q_bs) = (C_b^s)ᵀ.

    Returns shape (..., 4): one quaternion per row of angles (e.g. one per Monte Carlo draw).
    """
    a = np.asarray(alpha_rad, dtype=float)
    return quat_from_matrix(np.swapaxes(installation_matrix(a[..., 0], a[..., 1], a[..., 2]), -1, -2))


def installation_angles(matrix) -> np.ndarray:
    """Inverse of wang2023cja Eq 1: ``[α1, α2, α3]`` (rad) from ``C_b^s = Rz(α1) Ry(α2) Rx(α3)``.

    ``α2 = −asin(C[2,0])`` (via atan2 of the column norms, accurate near ±90°),
    ``α1 = atan2(C[1,0], C[0,0])``, ``α3 = atan2(C[2,1], C[2,2])``; at
    α2 = ±90° (not an installation error) α3 is set to 0.

    Parameters
    ----------
    matrix : array_like, shape (..., 3, 3)
        Rotation matrix (orthonormal to ~1e-6).

    Returns
    -------
    ndarray, shape (..., 3)

    Examples
    --------
    >>> import numpy as np
    >>> a = np.radians([0.5, -0.3, 0.4])
    >>> bool(np.allclose(installation_angles(installation_matrix(*a)), a, atol=1e-15))
    True
    """
    m = as_float_array(matrix, "matrix")
    if m.ndim < 2 or m.shape[-2:] != (3, 3):
        raise ValueError(f"matrix must have shape (..., 3, 3), got {m.shape}")
    ortho = np.abs(np.swapaxes(m, -1, -2) @ m - np.eye(3)).max() if m.size else 0.0
    if ortho > 1e-6 or np.any(np.linalg.det(m) <= 0):
        raise ValueError(f"matrix must be a rotation matrix (|M^T M - I| = {ortho:.3g}, det > 0)")
    return _installation_angles(m)


def _installation_angles(m: np.ndarray) -> np.ndarray:
    """Inverse Eq 1 of checked rotation matrices (..., 3, 3) (see :func:`installation_angles`)."""
    a2 = np.arctan2(-m[..., 2, 0], np.hypot(m[..., 2, 1], m[..., 2, 2]))
    lock = np.hypot(m[..., 0, 0], m[..., 1, 0]) < 1e-12
    a1 = np.where(lock, np.arctan2(-m[..., 0, 1], m[..., 1, 1]), np.arctan2(m[..., 1, 0], m[..., 0, 0]))
    a3 = np.where(lock, 0.0, np.arctan2(m[..., 2, 1], m[..., 2, 2]))
    return np.stack([a1, a2, a3], axis=-1)


def installation_angles_from_mount(q_bs) -> np.ndarray:
    """Inverse of :func:`mount_quaternion`: Eq 1 angles ``[α1, α2, α3]`` (rad) of a mounting ``q_bs``.

    ``C(q_bs) = (C_b^s)ᵀ``, so ``α = installation_angles(C(q_bs)ᵀ)``; q and −q give
    the same angles.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.radians([1.0, -2.0, 0.5])
    >>> bool(np.allclose(installation_angles_from_mount(mount_quaternion(a)), a, atol=1e-14))
    True
    """
    q = unit_quaternion(q_bs, "q_bs")
    return installation_angles(np.swapaxes(quat_to_matrix(q), -1, -2))


def installation_angles_from_mount_trusted(q_bs: np.ndarray) -> np.ndarray:
    """:func:`installation_angles_from_mount` without input validation (not public API).

    Precondition: ``q_bs`` is a float64 array (..., 4) of unit quaternions (to 1e-6), e.g. the
    right factor of an SO(4) projection. Bit-identical to :func:`installation_angles_from_mount`
    on such input (the matrix of a unit quaternion is a rotation, so the rotation check is skipped).
    """
    return _installation_angles(np.swapaxes(quat_to_matrix_trusted(q_bs), -1, -2))


def relative_to_initial(q_est: np.ndarray, n0: int = 1, *, out: np.ndarray | None = None,
                        start: int = 0, windows=None) -> np.ndarray:
    """Zero the attitude at the start: ``q_est(0)⁻¹ ⊗ q_est(t)`` (§4.1 initial angles 0°), (T, N, 4).

    ``q_est(0)`` is the normalised mean of the first ``n0`` samples. ``out`` (float64, shape of
    ``q_est``, may be ``q_est`` itself: in place) receives the result instead of a new array.
    ``start`` (with ``out``): only samples ``start:`` are written (each sample's product does not
    depend on the others); the earlier samples of ``out`` are left as they are — with
    ``out=q_est`` a session keeps its first part as logged and zeroes the rest, without a copy.
    ``windows`` (with ``out``, instead of ``start``): a list of disjoint sample slices; only the
    samples inside them are written (a caller that reads a few windows of a long record zeroes
    only those; each written sample equals the full computation's bit for bit).

    Examples
    --------
    >>> import numpy as np
    >>> q = np.array([[[0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]]])
    >>> relative_to_initial(q)[0].tolist()
    [[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, -1.0]]
    >>> relative_to_initial(q.copy(), out=q, start=1)[0].tolist()     # sample 0 kept as logged
    [[0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, -1.0]]
    >>> q = np.array([[[0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 1.0, 0.0]]])
    >>> relative_to_initial(q.copy(), out=q, windows=[slice(2, 3)])[0].tolist()   # only sample 2
    [[0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, -1.0]]
    """
    start = int(start)
    if start < 0 or start >= max(q_est.shape[-2], 1) or (start and out is None):
        raise ValueError(f"start must be in [0, {q_est.shape[-2]}) and needs out=, got start={start}")
    if windows is not None:
        windows = _disjoint_windows(windows, q_est.shape[-2])
        if out is None or start:
            raise ValueError("windows needs out= and no start")
    q0 = q_est[:, :n0].mean(axis=1)
    q0 /= np.linalg.norm(q0, axis=-1, keepdims=True)
    p = quat_conjugate(q0)[:, None, :]
    if out is None:
        return hamilton(p, q_est)
    if out.shape != q_est.shape or out.dtype != np.float64:
        raise ValueError(f"out must be a float64 array of shape {q_est.shape}, got {out.dtype} {out.shape}")
    for w in [slice(start, None)] if windows is None else windows:
        src, dst = q_est[:, w], out[:, w]
        if q_est.ndim == 3 and q_est.dtype == np.float64:
            _kernels().hamilton3(np.broadcast_to(p, src.shape), src, dst)   # element by element: may alias
        else:
            dst[...] = hamilton(p, src)
    return out


def _disjoint_windows(windows, n: int) -> list[slice]:
    """``windows`` as a list of step-1 slices inside ``[0, n)`` that do not overlap (ValueError otherwise)."""
    out = []
    for w in windows:
        if not isinstance(w, slice) or w.step not in (None, 1):
            raise ValueError(f"windows must be slices of step 1, got {w!r}")
        a, b, _ = w.indices(n)
        out.append(slice(a, max(a, b)))
    edges = sorted((w.start, w.stop) for w in out if w.stop > w.start)
    for (_, b0), (a1, _) in zip(edges[:-1], edges[1:]):
        if a1 < b0:
            raise ValueError(f"windows must not overlap, got {windows!r}")
    return out


# --------------------------------------------------------------------------
# linear maps of quaternions (the installation-error calibration's Eq 10)
# --------------------------------------------------------------------------
def apply_quat_matrix_trusted(q_matrix: np.ndarray, q: np.ndarray, normalize: bool = True) -> np.ndarray:
    """``Q q`` of every quaternion ``q`` by a 4×4 matrix (stack), normalised (Eq 10 of the calibration).

    The sign of ``q`` does not matter for the map (``Q(−q) = −Q q``); each ``q`` is aligned to
    ``q0 ≥ 0`` first (the result's sign is then the one the least-squares fit was made with).
    Trusts its inputs (the checks are :func:`mtcal.methods.quaternion_lsq.apply_error_matrix`'s).

    Parameters
    ----------
    q_matrix : ndarray, shape (4, 4) or (..., 4, 4)
        Float matrices without inf (a NaN matrix gives NaN rows).
    q : ndarray, shape (..., N, 4)
        Float64 unit quaternions (scalar-first) whose batch axes broadcast with ``q_matrix``'s.
    normalize : bool
        Rescale each result to unit norm (a general 4×4 map does not keep the norm).

    Returns
    -------
    ndarray, shape (..., N, 4)
        A new array: ``q_matrix @ q`` per row, divided by its norm (rows of norm below 1e-12 by
        numpy's division).

    Examples
    --------
    >>> q = quat_from_euler_zxy(np.zeros(2), np.zeros(2), np.radians([10.0, -20.0]))
    >>> m = left_matrix(quat_from_euler_zxy(0.0, 0.0, np.radians(5.0)))
    >>> np.degrees(euler_zxy_unchecked(apply_quat_matrix_trusted(m, q))[:, 2]).round(9).tolist()
    [15.0, -15.0]
    """
    # the sign rule dot(q, [1, 0, 0, 0]) >= 0: for finite q, q0 + (±0) + (±0) + (±0) has the sign of q0
    if q.dtype == np.float64 and q.size >= 4 * _KERNEL_MIN_ROWS:
        flat = q.reshape(-1, 4)
        flipped = np.empty(flat.shape)
        _kernels().rotvec_prepare(flat, flipped, np.empty(flat.shape[0]))   # −q where q0 < 0, in one pass
        q = flipped.reshape(q.shape)
    else:
        q = np.where(q[..., :1] < 0.0, -q, q)
    mapped = q @ np.swapaxes(q_matrix, -1, -2)
    if not normalize:
        return mapped
    if mapped.dtype == np.float64 and mapped.size >= 4 * _KERNEL_MIN_ROWS and mapped.flags.c_contiguous:
        flat = mapped.reshape(-1, 4)
        out, norm = np.empty_like(flat), np.empty(flat.shape[0])
        _kernels().normalize2(flat, out, norm)     # q / |q| as below, row by row (rows of |q| < 1e-12 skipped)
        small = ~(norm >= 1e-12)                   # NaN matrices give NaN rows: redone below, as numpy does
        if np.any(small):
            with np.errstate(invalid="ignore", divide="ignore"):
                out[small] = flat[small] / norm[small, None]
        return out.reshape(mapped.shape)
    with np.errstate(invalid="ignore"):
        return mapped / np.linalg.norm(mapped, axis=-1, keepdims=True)


def _finite_angles(*angles: np.ndarray) -> None:
    if not all(np.isfinite(a).all() for a in angles):
        raise FloatingPointError("Eq 8 angles are not finite: a calibration matrix or attitude is NaN/inf")


def mapped_pitch_trusted(q_matrix: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Eq 8 pitch (rad) of :func:`apply_quat_matrix_trusted` ``(q_matrix, q)``: the attitude after calibration.

    ``euler_zxy_unchecked(apply_quat_matrix_trusted(q_matrix, q))[..., 1]``; a large float64 input
    (T, N, 4) with finite matrices (T, 4, 4) in one compiled pass computing the pitch only (the
    same operations, bit-identical); near gimbal lock or with a non-finite matrix, the expression
    itself. Trusts its inputs (unit quaternions, as for :func:`apply_quat_matrix_trusted`).

    Returns
    -------
    ndarray, shape (..., N)

    Raises
    ------
    FloatingPointError
        If a pitch is not finite (a NaN matrix or attitude).

    Examples
    --------
    >>> q = quat_from_euler_zxy(np.zeros(2), np.radians([10.0, -20.0]), np.zeros(2))
    >>> m = left_matrix(quat_from_euler_zxy(0.0, np.radians(5.0), 0.0))
    >>> np.degrees(mapped_pitch_trusted(m, q)).round(9).tolist()
    [15.0, -15.0]
    """
    q_matrix = np.asarray(q_matrix, float)
    if (q.dtype == np.float64 and q.ndim == 3 and q.shape[0] * q.shape[1] >= _KERNEL_MIN_ROWS
            and q_matrix.shape == (q.shape[0], 4, 4) and np.isfinite(q_matrix).all()):
        out = np.empty(q.shape[:-1])
        if _kernels().pitch_after(q, np.ascontiguousarray(q_matrix), _LOCK_SIN, out) == 0:
            _finite_angles(out)
            return out
    euler = euler_zxy_unchecked(apply_quat_matrix_trusted(q_matrix, q))
    _finite_angles(euler)
    return euler[..., 1]
