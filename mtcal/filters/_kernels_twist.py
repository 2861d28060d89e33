"""Compiled twist of a batch of attitudes about a sensor-fixed axis (numba, float64; private).

:func:`twist_rows` is :func:`mtcal.filters.anchors.twist_angle_rad`'s numpy expression
``wrap_angle(2 atan2(q_rel,vec · u, q_rel,0))`` with ``q_rel = q[ref]⁻¹ ⊗ q[k]``, one pass per trial with
the same IEEE operations in the same order (the conjugate's negation, the Hamilton product of
:func:`mtcal.core.rotations.hamilton`, the dot product summed left to right as numpy's matmul does,
Python's float ``%`` as numpy's ``remainder``), so its output is that expression's bit for bit (tested in
``tests/filters/test_anchors.py``) with no (T, N, 4) temporaries.
"""

from __future__ import annotations

import math

import numpy as np

from mtcal.filters._kernels_common import jit

__all__ = ["twist_rows"]


@jit
def twist_rows(q, ref, u, out):  # pragma: no cover - compiled
    """``out[j, k]`` = wrapped twist (rad) about unit ``u`` (3,) of ``q[j, k]`` relative to ``q[j, ref]``."""
    n_trials, n = q.shape[0], q.shape[1]
    two_pi = 2.0 * np.pi
    for j in range(n_trials):
        p0, p1, p2, p3 = q[j, ref, 0], -q[j, ref, 1], -q[j, ref, 2], -q[j, ref, 3]
        for k in range(n):
            q0, q1, q2, q3 = q[j, k, 0], q[j, k, 1], q[j, k, 2], q[j, k, 3]
            r0 = p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3
            r1 = p0 * q1 + p1 * q0 + p2 * q3 - p3 * q2
            r2 = p0 * q2 - p1 * q3 + p2 * q0 + p3 * q1
            r3 = p0 * q3 + p1 * q2 - p2 * q1 + p3 * q0
            theta = 2.0 * math.atan2(r1 * u[0] + r2 * u[1] + r3 * u[2], r0)
            out[j, k] = (theta + np.pi) % two_pi - np.pi
