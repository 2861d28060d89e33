"""One random-number keying rule for every Monte Carlo in mtcal.

Rule
----
Every random stream is identified by an integer key ``(seed, stream, trial, ...)``:

* ``seed`` — the run's seed (a notebook's ``SEED``, a CLI/sweep ``--seed``);
* ``stream`` — a small integer naming *what* is drawn (one constant per use,
  declared next to the code that draws, e.g. ``STREAM_AXIS_TILTS = 12``);
* ``trial`` — the Monte Carlo trial index (0-based), so trial ``t`` gets the
  same numbers whether trials run in one batch, in chunks, on threads or on
  Dask workers;
* further integers (a block index, a row) where one trial needs several
  independent streams of one kind.

The generator is ``numpy.random.Generator(PCG64(SeedSequence(key)))``: the
SeedSequence hashes the whole key, so streams with different keys are
statistically independent (O'Neill 2015; numpy NEP 19).

>>> a = trial_rng(7, 3, 0).standard_normal(2)
>>> b = trial_rng(7, 3, 0).standard_normal(2)
>>> bool((a == b).all())
True
>>> bool((trial_rng(7, 3, 1).standard_normal(2) == a).any())
False
"""

from __future__ import annotations

import numpy as np

__all__ = ["stream_key", "trial_rng", "stream_rng"]


def stream_key(seed: int, stream: int, *more: int) -> tuple[int, ...]:
    """The integer key ``(seed, stream, *more)`` of a random stream (all entries ``int >= 0``).

    Parameters
    ----------
    seed, stream : int
        Run seed and stream number, each ``>= 0``.
    *more : int
        Trial index, block index … (each ``>= 0``).

    Returns
    -------
    tuple of int

    Examples
    --------
    >>> stream_key(1, 2, 3)
    (1, 2, 3)
    """
    key = (seed, stream) + tuple(more)
    for k in key:
        if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or k < 0:
            raise ValueError(f"random stream key: expected integers >= 0, got {key!r}")
    return tuple(int(k) for k in key)


def stream_rng(seed: int, stream: int, *more: int) -> np.random.Generator:
    """Generator of the stream ``(seed, stream, *more)`` (see the module rule).

    Examples
    --------
    >>> float(stream_rng(0, 1).uniform()) == float(stream_rng(0, 1).uniform())
    True
    """
    return np.random.Generator(np.random.PCG64(np.random.SeedSequence(stream_key(seed, stream, *more))))


def trial_rng(seed: int, stream: int, trial: int, *more: int) -> np.random.Generator:
    """Generator of trial ``trial`` of stream ``stream`` of run ``seed``: ``stream_rng(seed, stream, trial, *more)``.

    Examples
    --------
    >>> int(trial_rng(1, 2, 3).integers(10**6)) == int(stream_rng(1, 2, 3).integers(10**6))
    True
    """
    return stream_rng(seed, stream, trial, *more)
