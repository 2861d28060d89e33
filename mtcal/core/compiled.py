"""Compiled-code plumbing shared by :mod:`mtcal.core` and :mod:`mtcal.filters`.

* The numba settings read when numba is first imported, set here once (every mtcal
  module that compiles imports numba through this module): passive OpenMP waiting
  (numba's OpenMP threading layer otherwise spins its workers after every parallel
  region, and on a loaded machine a spinning worker steals the core the next region or
  the serial code needs: a 0.2 ms parallel pass measured 17 ms with one busy core),
  unless the user chose otherwise; and a writable cache directory when neither the
  package's ``__pycache__`` nor ``~/.cache`` can take numba's cache (read-only installs).
* :func:`jit` — ``numba.njit(cache=True, nogil=True)`` that degrades gracefully: when no
  cache locator can write, numba raises at decoration time; the function is then
  compiled without caching instead of failing the import. Kernels are float64, never
  ``fastmath`` (no reassociation, no FMA contraction), so their arithmetic is the numpy
  reference's operation by operation.
* :func:`component_major` — the (C, 3, T) copy of a (T, C, 3) record chunk that the
  trial-vectorised numpy engines of the filters step through.
"""

from __future__ import annotations

import os
import tempfile
import warnings

import numpy as np

__all__ = ["jit", "component_major"]

os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
if not os.environ.get("NUMBA_CACHE_DIR"):
    _here, _home = os.path.dirname(os.path.abspath(__file__)), os.path.expanduser("~")
    _home_cache = os.path.join(_home, ".cache")
    if not os.access(_here, os.W_OK) and not os.access(_home_cache if os.path.isdir(_home_cache) else _home,
                                                       os.W_OK):
        os.environ["NUMBA_CACHE_DIR"] = os.path.join(tempfile.gettempdir(), "mtcal-numba-cache")


def jit(fn=None, *, parallel: bool = False):
    """``numba.njit(cache=True, nogil=True, parallel=parallel)``, uncached when caching is impossible.

    Use as ``@jit``, ``@jit()`` or ``@jit(parallel=True)``.

    Parameters
    ----------
    fn : callable, optional
        The function to compile (``@jit`` without parentheses).
    parallel : bool
        Compile with ``parallel=True`` (``numba.prange`` loops spread over threads).

    Returns
    -------
    numba dispatcher, or a decorator when ``fn`` is None.

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")  # a function typed at a prompt has no file to cache against
    ...     twice = jit(lambda x: 2.0 * x)
    >>> twice(1.5)
    3.0
    """
    import numba  # here, not at import: ``import mtcal`` (a CLI call) does not load numba; settings above

    def deco(f):
        try:
            return numba.njit(cache=True, nogil=True, parallel=parallel)(f)
        except RuntimeError as exc:  # "cannot cache function ...: no locator available"
            warnings.warn(f"numba cannot cache {f.__name__} ({exc}); compiling without a cache", RuntimeWarning,
                          stacklevel=2)
            return numba.njit(cache=False, nogil=True, parallel=parallel)(f)
    return deco if fn is None else deco(fn)


def component_major(x: np.ndarray, out: np.ndarray, block: int = 64) -> np.ndarray:
    """Copy ``x`` (T, C, 3) into ``out`` (C, 3, T), in blocks of trials (a cache-friendly transpose).

    Parameters
    ----------
    x : ndarray, shape (T, C, 3)
        A chunk of C samples of T trials (trial-major, as records are stored); a time slice
        of a C-contiguous record is read as a view.
    out : ndarray, shape (C, 3, T), C-contiguous
        Destination buffer (returned).
    block : int
        Trials copied per block.

    Returns
    -------
    out : ndarray, shape (C, 3, T)

    Examples
    --------
    >>> x = np.arange(12.0).reshape(2, 2, 3)
    >>> component_major(x, np.empty((2, 3, 2)))[1, 2].tolist()  # sample 1, axis z, both trials
    [5.0, 11.0]
    """
    trials, c = x.shape[0], x.shape[1] * x.shape[2]
    src = x.reshape(trials, c)
    dst = out.reshape(c, trials)
    for b in range(0, trials, block):
        dst[:, b:b + block] = src[b:b + block].T
    return out
