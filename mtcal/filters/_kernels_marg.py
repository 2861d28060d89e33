"""Compiled kernel of the MARG explicit complementary filter (numba, float64; private).

Same recursion as :func:`mtcal.filters.baselines.mahony_marg` with
``engine="numpy"`` (the reference), per scalar, each sum formed in the order
numpy forms it (``np.cross``, the 3-term reductions and ``einsum``
contractions left to right, :func:`mtcal.core.rotations.hamilton`,
:func:`mtcal.core.rotations.quat_from_rotvec`). Trials are independent:
bit-identical results for any numba thread count.
"""

from __future__ import annotations

import math

import numpy as np
from numba import prange

from mtcal.filters._kernels_common import jit

__all__ = ["marg_serial", "marg_parallel"]


@jit()
def _trial(g, an, mn, q_init, t, out, kp_a, kp_m, kidt, dt):
    w, x, y, z = q_init[t, 0], q_init[t, 1], q_init[t, 2], q_init[t, 3]
    i0 = i1 = i2 = 0.0
    for i in range(g.shape[1]):
        out[t, i, 0] = w
        out[t, i, 1] = x
        out[t, i, 2] = y
        out[t, i, 3] = z
        # body→earth DCM (baselines._quat_matrix)
        c00 = 1.0 - 2.0 * (y * y + z * z)
        c01 = 2.0 * (x * y - w * z)
        c02 = 2.0 * (x * z + w * y)
        c10 = 2.0 * (x * y + w * z)
        c11 = 1.0 - 2.0 * (x * x + z * z)
        c12 = 2.0 * (y * z - w * x)
        c20 = 2.0 * (x * z - w * y)
        c21 = 2.0 * (y * z + w * x)
        c22 = 1.0 - 2.0 * (x * x + y * y)
        ax, ay, az = an[t, i, 0], an[t, i, 1], an[t, i, 2]
        mx, my, mz = mn[t, i, 0], mn[t, i, 1], mn[t, i, 2]
        # e_acc = â × up_b, up_b = third row of C
        ea0 = ay * c22 - az * c21
        ea1 = az * c20 - ax * c22
        ea2 = ax * c21 - ay * c20
        # field in the earth frame, its horizontal/vertical reference, predicted body field
        h0 = (c00 * mx + c01 * my) + c02 * mz
        h1 = (c10 * mx + c11 * my) + c12 * mz
        h2 = (c20 * mx + c21 * my) + c22 * mz
        bh = math.hypot(h0, h1)
        p0 = (c00 * bh + c10 * 0.0) + c20 * h2
        p1 = (c01 * bh + c11 * 0.0) + c21 * h2
        p2 = (c02 * bh + c12 * 0.0) + c22 * h2
        em0 = my * p2 - mz * p1
        em1 = mz * p0 - mx * p2
        em2 = mx * p1 - my * p0
        proj = (em0 * c20 + em1 * c21) + em2 * c22   # heading only: projection on up_b
        em0 = c20 * proj
        em1 = c21 * proj
        em2 = c22 * proj
        i0 = i0 + kidt * (ea0 + em0)
        i1 = i1 + kidt * (ea1 + em1)
        i2 = i2 + kidt * (ea2 + em2)
        r0 = ((g[t, i, 0] + (kp_a * ea0 + kp_m * em0)) + i0) * dt
        r1 = ((g[t, i, 1] + (kp_a * ea1 + kp_m * em1)) + i1) * dt
        r2 = ((g[t, i, 2] + (kp_a * ea2 + kp_m * em2)) + i2) * dt
        # quat_from_rotvec
        ang = math.sqrt((r0 * r0 + r1 * r1) + r2 * r2)
        half = 0.5 * ang
        if ang < 1e-8:
            k = 0.5 - ang ** 2 / 48.0
        else:
            k = math.sin(half) / ang
        d0 = math.cos(half)
        d1 = k * r0
        d2 = k * r1
        d3 = k * r2
        # hamilton(q, dq), renormalised
        n0 = ((w * d0 - x * d1) - y * d2) - z * d3
        n1 = ((w * d1 + x * d0) + y * d3) - z * d2
        n2 = ((w * d2 - x * d3) + y * d0) + z * d1
        n3 = ((w * d3 + x * d2) - y * d1) + z * d0
        nq = math.sqrt(((n0 * n0 + n1 * n1) + n2 * n2) + n3 * n3)
        w = n0 / nq
        x = n1 / nq
        y = n2 / nq
        z = n3 / nq


@jit()
def marg_serial(g, an, mn, q_init, out, kp_a, kp_m, kidt, dt):
    """Trials one after the other."""
    for t in range(g.shape[0]):
        _trial(g, an, mn, q_init, t, out, kp_a, kp_m, kidt, dt)


@jit(parallel=True)
def marg_parallel(g, an, mn, q_init, out, kp_a, kp_m, kidt, dt):
    """Trials spread over numba's threads (``prange``)."""
    for t in prange(g.shape[0]):
        _trial(g, an, mn, q_init, t, out, kp_a, kp_m, kidt, dt)


def warm_up() -> None:
    """Compile (or load from the cache) both kernels on a tiny input."""
    g = np.zeros((2, 2, 3))
    v = np.tile([0.0, 0.0, 1.0], (2, 2, 1))
    for fn in (marg_serial, marg_parallel):
        fn(g, v, v, np.tile([1.0, 0, 0, 0], (2, 1)), np.empty((2, 2, 4)), 0.5, 0.5, 5e-6, 1e-3)
