"""Compiled loop behind :func:`mtcal.studies.broad2021.runs.errors_deg` (batches of estimates, private).

The kernel performs the numpy reference's arithmetic operation by operation, in the same order (no
``fastmath``, no FMA contraction: :func:`mtcal.core.compiled.jit`), so its output is bit-identical to
the numpy expressions it replaces: ``np.einsum("...i,...i->...", a, b)`` over a last axis of 4 adds its
products as ``(a0 b0 + a2 b2) + (a1 b1 + a3 b3)`` (numpy's two-lane accumulation) when both operands are
C-ordered, and left to right when ``b`` (N, 4) is Fortran-ordered (a MATLAB file's columns; the
summation then runs over the component axis outermost) — tests compare both;
``np.clip(x, 0, 1)`` of a value ≥ 0 or NaN is ``1`` above 1 and ``x`` otherwise, a division by zero
gives IEEE's ±inf or the x86-64 default NaN as numpy's does. The transcendental ``arccos``/``arctan``
stay in numpy (the caller applies them), so the results do not depend on which libm numba would link.

Imported lazily: ``import mtcal`` does not load numba.
"""

from __future__ import annotations

import math

import numpy as np

from mtcal.core.compiled import jit

__all__ = ["error_angle_arguments"]

#: The NaN an x86-64 division 0/0 makes (sign bit set), what numpy's ``divide`` returns for it.
_DEFAULT_NAN = float(np.array([0xFFF8000000000000], dtype=np.uint64).view(np.float64)[0])


@jit
def _divide(a, b):  # pragma: no cover - compiled
    """``a / b`` with numpy's IEEE result for ``b == 0`` (numba's Python error model would raise)."""
    if b != 0.0:
        return a / b
    if a != a:
        return a
    if a == 0.0:
        return _DEFAULT_NAN
    return math.copysign(np.inf, a) * math.copysign(1.0, b)


@jit
def error_angle_arguments(q, r, r_fortran, incl_arg, total_arg, heading_arg, full):  # pragma: no cover - compiled
    """Arguments of BROAD's error angles for C-ordered (L, N, 4) estimates ``q`` and (N, 4) unit references ``r``.

    ``q̂ = q / sqrt(q·q)``; the error quaternion's ``w = q̂·r`` (summed as numpy's einsum sums it: in pairs, or left
    to right when ``r_fortran``), ``z = −q̂0 r3 − q̂1 r2 + q̂2 r1 + q̂3 r0``;
    ``incl_arg = clip(sqrt(w² + z²), 0, 1)`` and, with ``full``, ``total_arg = clip(|w|, 0, 1)`` and
    ``heading_arg = |z / w|``; each (L, N).
    """
    for lane in range(q.shape[0]):
        for n in range(q.shape[1]):
            q0, q1, q2, q3 = q[lane, n, 0], q[lane, n, 1], q[lane, n, 2], q[lane, n, 3]
            s = np.sqrt((q0 * q0 + q2 * q2) + (q1 * q1 + q3 * q3))
            a0, a1, a2, a3 = _divide(q0, s), _divide(q1, s), _divide(q2, s), _divide(q3, s)
            r0, r1, r2, r3 = r[n, 0], r[n, 1], r[n, 2], r[n, 3]
            if r_fortran:
                w = ((a0 * r0 + a1 * r1) + a2 * r2) + a3 * r3
            else:
                w = (a0 * r0 + a2 * r2) + (a1 * r1 + a3 * r3)
            z = -a0 * r3 - a1 * r2 + a2 * r1 + a3 * r0
            nrm = np.sqrt(w * w + z * z)
            incl_arg[lane, n] = 1.0 if nrm > 1.0 else nrm
            if full:
                aw = abs(w)
                total_arg[lane, n] = 1.0 if aw > 1.0 else aw
                heading_arg[lane, n] = abs(_divide(z, w))
