"""Compiled loops behind :mod:`mtcal.core.metrics` (large float64, private).

Every kernel performs the numpy reference's arithmetic operation by operation, in the same order
(no ``fastmath``, no FMA contraction: :func:`mtcal.core.compiled.jit`), so its output is
bit-identical to the numpy expression it replaces. Reductions (means, sums) stay in numpy: the
kernels fill the array numpy would have built, and numpy reduces it as before.

Imported lazily (on the first large array): ``import mtcal`` does not load numba.
"""

from __future__ import annotations

from mtcal.core.compiled import jit

__all__ = ["allan_second_difference_squared3"]


@jit
def allan_second_difference_squared3(theta, m, out):  # pragma: no cover - compiled
    """``out[:, k] = (θ[:, k + 2m] − 2 θ[:, k + m] + θ[:, k])²``: time on axis 1 of (A, M + 2m, B) ``theta``.

    The numpy expression's operations in its order: ``((θ_{k+2m} − 2·θ_{k+m}) + θ_k)``, then squared
    (``d**2`` is ``d * d`` in numpy). Any strides; axis 2 is stepped innermost.
    """
    for i in range(out.shape[0]):
        for k in range(out.shape[1]):
            for j in range(out.shape[2]):
                d = (theta[i, k + 2 * m, j] - 2.0 * theta[i, k + m, j]) + theta[i, k, j]
                out[i, k, j] = d * d
