"""Compiled loops of the wang2023cja runs (private; imported lazily, numba loads on first use).

Each kernel performs the numpy reference's operations element by element in the same order (no
``fastmath``, no FMA contraction: :func:`mtcal.core.compiled.jit`), so its output is bit-identical.
"""

from __future__ import annotations

from mtcal.core.compiled import jit

__all__ = ["load_tilt"]


@jit
def load_tilt(gyro, accel, s, s_dot, tilt_s):  # pragma: no cover - compiled
    """In place, per trial k: ``d = s·tilt_s[k]``, ``accel −= d × accel``, ``gyro += ṡ·tilt_s[k] − d × gyro``.

    The cross products as ``numpy.cross`` forms them (``a1 b2 − a2 b1``, ``a2 b0 − a0 b2``,
    ``a0 b1 − a1 b0``), from the values before the update. Shapes: gyro, accel (T, N, 3);
    s, s_dot (N,); tilt_s (T, 3).
    """
    for k in range(gyro.shape[0]):
        t0, t1, t2 = tilt_s[k, 0], tilt_s[k, 1], tilt_s[k, 2]
        for n in range(gyro.shape[1]):
            d0, d1, d2 = s[n] * t0, s[n] * t1, s[n] * t2
            a0, a1, a2 = accel[k, n, 0], accel[k, n, 1], accel[k, n, 2]
            accel[k, n, 0] = a0 - (d1 * a2 - d2 * a1)
            accel[k, n, 1] = a1 - (d2 * a0 - d0 * a2)
            accel[k, n, 2] = a2 - (d0 * a1 - d1 * a0)
            w0, w1, w2 = gyro[k, n, 0], gyro[k, n, 1], gyro[k, n, 2]
            sd = s_dot[n]
            gyro[k, n, 0] = w0 + (sd * t0 - (d1 * w2 - d2 * w1))
            gyro[k, n, 1] = w1 + (sd * t1 - (d2 * w0 - d0 * w2))
            gyro[k, n, 2] = w2 + (sd * t2 - (d0 * w1 - d1 * w0))
