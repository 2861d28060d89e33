"""Compiled block sums of :mod:`mtcal.methods.rest_detection`, bit for bit numpy's.

The rest detector's statistics are sums over blocks of samples. numpy computes them
with three different summation orders, and a plain loop sum differs from two of them
in the last bits, so each kernel here reproduces the order of the numpy expression it
replaces (checked bit for bit against numpy in ``tests/methods/test_rest_detection.py``,
on the generic and the native code path):

* ``x.reshape(nb, w, d).sum(axis=1)`` of a C-contiguous ``x`` (the reduced axis is not
  the inner one): a sequential sum, ``((0 + x_0) + x_1) + …``, one running sum per column
  (numpy's order follows the memory layout: other layouts keep the numpy expression);
* ``x.reshape(nb, w).sum(axis=1)`` (contiguous reduced axis): ``0 + pairwise(x_0 … x_(w-1))``,
  numpy's pairwise summation (``pairwise_sum`` in numpy's ``loops_utils.h.src``: fewer
  than 8 terms summed in order from −0.0; up to 128 terms in 8 interleaved running sums
  combined as ``((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))`` and the remainder
  added in order; more terms split in two halves at a multiple of 8 and summed
  recursively);
* ``np.add.reduceat(x, idx, axis=0)``: ``x_start + pairwise(x_(start+1) … x_(stop-1))``
  per column.

Every other operation is elementwise (a difference, a square), exact in any order.
Kernels are float64 without ``fastmath`` (:func:`mtcal.core.compiled.jit`): no
reassociation and no FMA contraction, so each floating-point operation is the one
numpy performs.
"""

from __future__ import annotations

import numpy as np

from mtcal.core.compiled import jit

__all__ = ["block_sums", "reduceat_sums", "row_block_sums", "warm_up"]

#: numpy's pairwise-summation block (``PW_BLOCKSIZE``): longer runs are split in two.
_PW_BLOCK = 128


@jit
def _pairwise(x, col, off, start, n):
    """numpy's ``pairwise_sum`` of ``v_i = x[start + i, col] - off`` and of ``v_i²``, i < n (both in one pass)."""
    if n < 8:
        s = -0.0
        q = -0.0
        for i in range(start, start + n):
            v = x[i, col] - off
            s += v
            q += v * v
        return s, q
    if n <= _PW_BLOCK:
        v0 = x[start, col] - off
        v1 = x[start + 1, col] - off
        v2 = x[start + 2, col] - off
        v3 = x[start + 3, col] - off
        v4 = x[start + 4, col] - off
        v5 = x[start + 5, col] - off
        v6 = x[start + 6, col] - off
        v7 = x[start + 7, col] - off
        r0, r1, r2, r3, r4, r5, r6, r7 = v0, v1, v2, v3, v4, v5, v6, v7
        q0, q1, q2, q3 = v0 * v0, v1 * v1, v2 * v2, v3 * v3
        q4, q5, q6, q7 = v4 * v4, v5 * v5, v6 * v6, v7 * v7
        m = n - n % 8
        i = 8
        while i < m:
            k = start + i
            v0 = x[k, col] - off
            v1 = x[k + 1, col] - off
            v2 = x[k + 2, col] - off
            v3 = x[k + 3, col] - off
            v4 = x[k + 4, col] - off
            v5 = x[k + 5, col] - off
            v6 = x[k + 6, col] - off
            v7 = x[k + 7, col] - off
            r0 += v0
            r1 += v1
            r2 += v2
            r3 += v3
            r4 += v4
            r5 += v5
            r6 += v6
            r7 += v7
            q0 += v0 * v0
            q1 += v1 * v1
            q2 += v2 * v2
            q3 += v3 * v3
            q4 += v4 * v4
            q5 += v5 * v5
            q6 += v6 * v6
            q7 += v7 * v7
            i += 8
        s = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
        q = ((q0 + q1) + (q2 + q3)) + ((q4 + q5) + (q6 + q7))
        while i < n:
            v = x[start + i, col] - off
            s += v
            q += v * v
            i += 1
        return s, q
    n2 = n // 2
    n2 -= n2 % 8
    sa, qa = _pairwise(x, col, off, start, n2)
    sb, qb = _pairwise(x, col, off, start + n2, n - n2)
    return sa + sb, qa + qb


@jit
def _block_sums(x, w, nb, s1, s2):
    for b in range(nb):
        r0 = b * w
        for j in range(x.shape[1]):
            first = x[r0, j]
            a1 = 0.0
            a2 = 0.0
            for i in range(r0, r0 + w):
                v = x[i, j] - first
                a1 += v
                a2 += v * v
            s1[b, j] = a1
            s2[b, j] = a2


@jit
def _row_block_sums(x, w, nb, out):
    for b in range(nb):
        out[b] = 0.0 + _pairwise(x, 0, 0.0, b * w, w)[0]


@jit
def _reduceat_sums(x, idx, off, s1, s2):
    n = x.shape[0]
    for b in range(idx.size):
        lo = idx[b]
        hi = idx[b + 1] if b + 1 < idx.size else n
        for j in range(x.shape[1]):
            v = x[lo, j] - off[j]
            a1 = v
            a2 = v * v
            if hi - lo > 1:
                p1, p2 = _pairwise(x, j, off[j], lo + 1, hi - lo - 1)
                a1 += p1
                a2 += p2
            s1[b, j] = a1
            s2[b, j] = a2


def _c2d(x: np.ndarray) -> np.ndarray:
    """``x`` as a C-contiguous 2-D float64 array (one compiled signature for every caller)."""
    x = np.ascontiguousarray(x, dtype=np.float64)
    return x.reshape(x.shape[0], -1)


def block_sums(x: np.ndarray, w: int) -> tuple[np.ndarray, np.ndarray]:
    """Sums of ``d = x − x_first`` and ``d²`` over the ``nb = N // w`` whole blocks of ``w`` rows.

    Bit for bit ``b = x[:nb*w].reshape(nb, w, -1); b = b - b[:, :1]; b.sum(axis=1)`` and,
    after ``b *= b``, ``b.sum(axis=1)`` for a C-contiguous ``x`` (numpy sums in another
    order when ``x`` is laid out otherwise, e.g. Fortran-ordered: then the rows of a block
    are contiguous and numpy sums them pairwise).

    Parameters
    ----------
    x : ndarray, shape (N, d)
    w : int
        Rows per block, ≥ 1.

    Returns
    -------
    s1, s2 : ndarray, shape (nb, d)

    Examples
    --------
    >>> s1, s2 = block_sums(np.array([[1.0], [2.0], [4.0], [5.0], [5.0]]), 2)
    >>> s1[:, 0].tolist(), s2[:, 0].tolist()
    ([1.0, 1.0], [1.0, 1.0])
    """
    x = _c2d(x)
    nb = x.shape[0] // w
    s1, s2 = np.empty((nb, x.shape[1])), np.empty((nb, x.shape[1]))
    _block_sums(x, int(w), nb, s1, s2)
    return s1, s2


def row_block_sums(x: np.ndarray, w: int) -> np.ndarray:
    """Sums of the ``nb = N // w`` whole blocks of ``w`` samples of ``x`` (N,), bit for bit
    ``x[:nb*w].reshape(nb, w).sum(axis=1)`` (numpy's pairwise summation).

    Examples
    --------
    >>> row_block_sums(np.arange(7.0), 3).tolist()
    [3.0, 12.0]
    """
    x = _c2d(x)
    nb = x.shape[0] // w
    out = np.empty(nb)
    _row_block_sums(x, int(w), nb, out)
    return out


def reduceat_sums(x: np.ndarray, idx: np.ndarray, off: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Sums of ``d = x − off`` and ``d²`` over the row ranges starting at ``idx`` (each to the next, the last
    to the end), bit for bit ``np.add.reduceat(d, idx, axis=0)`` and ``np.add.reduceat(d * d, idx, axis=0)``.

    Parameters
    ----------
    x : ndarray, shape (N, d)
    idx : ndarray of int, shape (nb,)
        Strictly increasing row indices, ``idx[0] == 0``, all < N.
    off : ndarray, shape (d,)

    Returns
    -------
    s1, s2 : ndarray, shape (nb, d)

    Examples
    --------
    >>> s1, s2 = reduceat_sums(np.array([[1.0], [2.0], [4.0]]), np.array([0, 2]), np.array([1.0]))
    >>> s1[:, 0].tolist(), s2[:, 0].tolist()
    ([1.0, 3.0], [1.0, 9.0])
    """
    x = _c2d(x)
    idx = np.ascontiguousarray(idx, dtype=np.int64)
    off = np.ascontiguousarray(off, dtype=np.float64).reshape(-1)
    s1, s2 = np.empty((idx.size, x.shape[1])), np.empty((idx.size, x.shape[1]))
    _reduceat_sums(x, idx, off, s1, s2)
    return s1, s2


def warm_up() -> None:
    """Compile (or load from numba's cache) the three kernels."""
    x = np.arange(30.0).reshape(10, 3)
    block_sums(x, 3)
    row_block_sums(x[:, 0], 3)
    reduceat_sums(x, np.array([0, 4]), np.zeros(3))
