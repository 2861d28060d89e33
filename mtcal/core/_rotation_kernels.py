"""Compiled loops behind :mod:`mtcal.core.rotations` and ``metrics.angle_difference`` (large float64, private).

Every kernel performs the numpy reference's arithmetic operation by operation, in the same
order (sums of 3 or 4 terms left to right, as numpy reduces a short last axis; no
``fastmath``, no FMA contraction: :func:`mtcal.core.compiled.jit`), so its output is
bit-identical to the numpy expressions it replaces. Transcendental functions (sin, cos,
arctan2, arcsin) stay in numpy: the wrappers in :mod:`mtcal.core.rotations` call them between
kernels, so the results do not depend on which libm numba would link.

Imported lazily (on the first large array): ``import mtcal`` does not load numba.
"""

from __future__ import annotations

import numpy as np

from mtcal.core.compiled import jit

__all__ = ["hamilton3", "continuous3", "rotvec_prepare", "rotvec_finish", "normalize2", "rotvec_angle",
           "quat_from_rotvec_finish", "euler_zxy_arguments", "euler_zxy_products", "dcm_entries", "matrix_from_quat",
           "all_unit", "wrap_difference", "wrap_difference3", "all_finite", "conjugate2",
           "apply_row", "pitch_after", "rows_times_matrix3"]


@jit
def hamilton3(p, q, out):  # pragma: no cover - compiled
    """``out = p ⊗ q`` for (A, B, 4) arrays (p, q may be broadcast views)."""
    for i in range(out.shape[0]):
        for j in range(out.shape[1]):
            p0, p1, p2, p3 = p[i, j, 0], p[i, j, 1], p[i, j, 2], p[i, j, 3]
            q0, q1, q2, q3 = q[i, j, 0], q[i, j, 1], q[i, j, 2], q[i, j, 3]
            out[i, j, 0] = p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3
            out[i, j, 1] = p0 * q1 + p1 * q0 + p2 * q3 - p3 * q2
            out[i, j, 2] = p0 * q2 - p1 * q3 + p2 * q0 + p3 * q1
            out[i, j, 3] = p0 * q3 + p1 * q2 - p2 * q1 + p3 * q0


@jit
def continuous3(q, out):  # pragma: no cover - compiled
    """Sign flips along axis 0 of (N, M, 4) so consecutive dots are >= 0 (cumulative parity)."""
    n, m = q.shape[0], q.shape[1]
    for j in range(m):
        flip = False
        for c in range(4):
            out[0, j, c] = q[0, j, c]
        for i in range(1, n):
            dot = (q[i, j, 0] * q[i - 1, j, 0] + q[i, j, 1] * q[i - 1, j, 1] + q[i, j, 2] * q[i - 1, j, 2]
                   + q[i, j, 3] * q[i - 1, j, 3])
            if dot < 0.0:
                flip = not flip
            if flip:
                for c in range(4):
                    out[i, j, c] = -q[i, j, c]
            else:
                for c in range(4):
                    out[i, j, c] = q[i, j, c]


@jit
def rotvec_prepare(q, qf, vnorm):  # pragma: no cover - compiled
    """(M, 4) → sign-aligned ``qf`` (q0 >= 0) and ``vnorm = |qf[1:]|``."""
    for i in range(q.shape[0]):
        s = -1.0 if q[i, 0] < 0.0 else 1.0
        if s < 0.0:
            for c in range(4):
                qf[i, c] = -q[i, c]
        else:
            for c in range(4):
                qf[i, c] = q[i, c]
        vnorm[i] = np.sqrt(qf[i, 1] * qf[i, 1] + qf[i, 2] * qf[i, 2] + qf[i, 3] * qf[i, 3])


@jit
def rotvec_finish(qf, vnorm, angle, out):  # pragma: no cover - compiled
    """``out = k · qf[1:]`` with ``k = 2`` where ``vnorm < 1e-12``, else ``angle / vnorm``."""
    for i in range(qf.shape[0]):
        k = 2.0 if vnorm[i] < 1e-12 else angle[i] / vnorm[i]
        out[i, 0] = k * qf[i, 1]
        out[i, 1] = k * qf[i, 2]
        out[i, 2] = k * qf[i, 3]


@jit
def normalize2(q, out, norm):  # pragma: no cover - compiled
    """(M, 4): ``norm = |q|`` and ``out = q / norm`` (rows of norm < 1e-12 left unset)."""
    for i in range(q.shape[0]):
        n = np.sqrt(q[i, 0] * q[i, 0] + q[i, 1] * q[i, 1] + q[i, 2] * q[i, 2] + q[i, 3] * q[i, 3])
        norm[i] = n
        if n < 1e-12:   # the caller raises on it (numba would raise ZeroDivisionError)
            continue
        for c in range(4):
            out[i, c] = q[i, c] / n


@jit
def rotvec_angle(v, angle, half):  # pragma: no cover - compiled
    """(M, 3): ``angle = |v|``, ``half = 0.5 · angle``."""
    for i in range(v.shape[0]):
        a = np.sqrt(v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1] + v[i, 2] * v[i, 2])
        angle[i] = a
        half[i] = 0.5 * a


@jit
def quat_from_rotvec_finish(v, angle, sin_half, cos_half, out):  # pragma: no cover - compiled
    """``out = [cos(|v|/2), k v]``, ``k = 0.5 − |v|²/48`` below 1e-8 rad, else ``sin(|v|/2) / |v|``."""
    for i in range(v.shape[0]):
        a = angle[i]
        k = 0.5 - a * a / 48.0 if a < 1e-8 else sin_half[i] / a
        out[i, 0] = cos_half[i]
        out[i, 1] = k * v[i, 0]
        out[i, 2] = k * v[i, 1]
        out[i, 3] = k * v[i, 2]


@jit
def euler_zxy_arguments(q, y0, x0, sin_pitch, y2, x2):  # pragma: no cover - compiled
    """Eq 8's atan2/asin arguments of (M, 4) unit quaternions (sin_pitch clipped to [−1, 1])."""
    for i in range(q.shape[0]):
        q0, q1, q2, q3 = q[i, 0], q[i, 1], q[i, 2], q[i, 3]
        s00, s11, s22, s33 = q0 * q0, q1 * q1, q2 * q2, q3 * q3
        sp = 2.0 * (q2 * q3 + q0 * q1)
        sin_pitch[i] = min(max(sp, -1.0), 1.0)
        y0[i] = -2.0 * (q1 * q2 - q0 * q3)
        x0[i] = s00 - s11 + s22 - s33
        y2[i] = -2.0 * (q1 * q3 - q0 * q2)
        x2[i] = s00 - s11 - s22 + s33


@jit
def euler_zxy_products(cp, sp, ct, st, cg, sg, out):  # pragma: no cover - compiled
    """Eq 9 from the half-angle cosines/sines (M,) → (M, 4)."""
    for i in range(out.shape[0]):
        out[i, 0] = ct[i] * cp[i] * cg[i] - st[i] * sp[i] * sg[i]
        out[i, 1] = st[i] * cp[i] * cg[i] - ct[i] * sp[i] * sg[i]
        out[i, 2] = st[i] * sp[i] * cg[i] + ct[i] * cp[i] * sg[i]
        out[i, 3] = ct[i] * sp[i] * cg[i] + st[i] * cp[i] * sg[i]


@jit
def dcm_entries(w, x, y, z):  # pragma: no cover - compiled
    """Direction-cosine matrix of one scalar-first quaternion as ``(c00, c10, c20, c01, c11, c21, c02, c12, c22)``.

    The same operations as scipy's Cython ``from_quat(...).as_matrix()``: normalise by
    ``sqrt(x² + y² + z² + w²)`` (scalar last, divided), then the products below.
    """
    n = np.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / n, y / n, z / n, w / n
    x2, y2, z2, w2 = x * x, y * y, z * z, w * w
    xy, zw, xz, yw, yz, xw = x * y, z * w, x * z, y * w, y * z, x * w
    return (x2 - y2 - z2 + w2, 2.0 * (xy + zw), 2.0 * (xz - yw),
            2.0 * (xy - zw), -x2 + y2 - z2 + w2, 2.0 * (yz + xw),
            2.0 * (xz + yw), 2.0 * (yz - xw), -x2 - y2 + z2 + w2)


@jit
def rows_times_matrix3(a, m, out):  # pragma: no cover - compiled
    """``out = a @ m`` for rows ``a`` (M, 3) and a matrix ``m`` (3, 3): each entry
    ``(a0·m0j + a1·m1j) + a2·m2j``, the order numpy's matmul sums a length-3 inner axis in (so the
    same numbers; tested against ``a @ m`` for many row counts), ~10× faster than the BLAS call
    on such thin arrays."""
    m00, m01, m02 = m[0, 0], m[0, 1], m[0, 2]
    m10, m11, m12 = m[1, 0], m[1, 1], m[1, 2]
    m20, m21, m22 = m[2, 0], m[2, 1], m[2, 2]
    for i in range(a.shape[0]):
        a0, a1, a2 = a[i, 0], a[i, 1], a[i, 2]
        out[i, 0] = (a0 * m00 + a1 * m10) + a2 * m20
        out[i, 1] = (a0 * m01 + a1 * m11) + a2 * m21
        out[i, 2] = (a0 * m02 + a1 * m12) + a2 * m22


@jit
def matrix_from_quat(q, out):  # pragma: no cover - compiled
    """Direction-cosine matrices (M, 3, 3) of scalar-first (M, 4): scipy's ``from_quat(...).as_matrix()``
    (:func:`dcm_entries` per row)."""
    for i in range(q.shape[0]):
        c00, c10, c20, c01, c11, c21, c02, c12, c22 = dcm_entries(q[i, 0], q[i, 1], q[i, 2], q[i, 3])
        out[i, 0, 0], out[i, 1, 0], out[i, 2, 0] = c00, c10, c20
        out[i, 0, 1], out[i, 1, 1], out[i, 2, 1] = c01, c11, c21
        out[i, 0, 2], out[i, 1, 2], out[i, 2, 2] = c02, c12, c22


@jit
def all_unit(q, atol):  # pragma: no cover - compiled
    """True when every row of (M, 4) is finite with ``abs(|q| − 1) <= atol`` (``validate.unit_quaternion``'s test)."""
    for i in range(q.shape[0]):
        for c in range(4):
            if not np.isfinite(q[i, c]):
                return False
        n = np.sqrt(q[i, 0] * q[i, 0] + q[i, 1] * q[i, 1] + q[i, 2] * q[i, 2] + q[i, 3] * q[i, 3])
        if np.abs(n - 1.0) > atol:
            return False
    return True


@jit
def wrap_difference(e, t):  # pragma: no cover - compiled
    """``(e − t + π) mod 2π − π`` of one pair: ``x = (e − t) + π``, ``m = fmod(x, 2π)`` (``x`` itself when in
    [0, 2π): no division), ``m + 2π`` when ``m < 0``, ``+0`` when ``m == 0`` — numpy's float ``remainder``
    by ``2π``, so :func:`mtcal.core.metrics.angle_difference`'s numbers."""
    two_pi = 2.0 * np.pi
    x = (e - t) + np.pi
    m = x if 0.0 <= x < two_pi else np.fmod(x, two_pi)   # fmod(x, b) is x itself there
    if m != 0.0:
        if m < 0.0:
            m += two_pi
    else:
        m = 0.0
    return m - np.pi


@jit
def wrap_difference3(e, t, out):  # pragma: no cover - compiled
    """``out = (e − t + π) mod 2π − π`` for (A, B, C) arrays (broadcast views allowed).

    numpy's float ``remainder`` by ``b = 2π > 0``: ``m = fmod(x, b)`` (exact in every libm),
    ``m + b`` when ``m < 0``, ``+0`` when ``m == 0`` — the same operations.
    """
    for i in range(out.shape[0]):
        for j in range(out.shape[1]):
            for k in range(out.shape[2]):
                out[i, j, k] = wrap_difference(e[i, j, k], t[i, j, k])


@jit
def all_finite(x):  # pragma: no cover - compiled
    """True when every element of the 2-D ``x`` is finite."""
    for i in range(x.shape[0]):
        for c in range(x.shape[1]):
            if not np.isfinite(x[i, c]):
                return False
    return True


@jit
def conjugate2(q, out):  # pragma: no cover - compiled
    """``out = [q0, q1·(−1), q2·(−1), q3·(−1)]`` for (M, 4)."""
    for i in range(q.shape[0]):
        out[i, 0] = q[i, 0]
        for c in range(1, 4):
            out[i, c] = q[i, c] * -1.0


@jit
def apply_row(q0, q1, q2, q3, m):  # pragma: no cover - compiled
    """``_apply``'s operations on one quaternion before ``normalize2``'s division: sign alignment
    (q0 ≥ 0), ``q @ mᵀ`` summed in index order, and the norm. Returns (b0, b1, b2, b3, norm)."""
    if q0 < 0.0:
        q0, q1, q2, q3 = -q0, -q1, -q2, -q3
    b0 = ((q0 * m[0, 0] + q1 * m[0, 1]) + q2 * m[0, 2]) + q3 * m[0, 3]
    b1 = ((q0 * m[1, 0] + q1 * m[1, 1]) + q2 * m[1, 2]) + q3 * m[1, 3]
    b2 = ((q0 * m[2, 0] + q1 * m[2, 1]) + q2 * m[2, 2]) + q3 * m[2, 3]
    b3 = ((q0 * m[3, 0] + q1 * m[3, 1]) + q2 * m[3, 2]) + q3 * m[3, 3]
    return b0, b1, b2, b3, np.sqrt(b0 * b0 + b1 * b1 + b2 * b2 + b3 * b3)


@jit
def pitch_after(q, q_mat, lock_sin, out):  # pragma: no cover - compiled
    """Eq 8 pitch of ``_apply(q_mat, q)`` for (T, N, 4) ``q`` and (T, 4, 4) ``q_mat``, into ``out`` (T, N).

    The operations of the sign alignment, ``q @ q_matᵀ`` (index order), ``normalize2`` and
    ``euler_zxy_unchecked``'s ``arcsin`` of the clipped argument. Returns the number of rows left
    unset for the caller (norm below 1e-12, or |sin pitch| above ``lock_sin``: the half-angle form).
    """
    bad = 0
    for t in range(q.shape[0]):
        m = q_mat[t]
        for i in range(q.shape[1]):
            q0, q1, q2, q3 = q[t, i, 0], q[t, i, 1], q[t, i, 2], q[t, i, 3]
            b0, b1, b2, b3, n = apply_row(q0, q1, q2, q3, m)
            if n < 1e-12:
                bad += 1
                continue
            b0, b1, b2, b3 = b0 / n, b1 / n, b2 / n, b3 / n
            sp = min(max(2.0 * (b2 * b3 + b0 * b1), -1.0), 1.0)
            if abs(sp) > lock_sin:
                bad += 1
                continue
            out[t, i] = np.arcsin(sp)
    return bad
