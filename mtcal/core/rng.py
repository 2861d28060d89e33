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

Counter-based rule (compiled kernels)
-------------------------------------
Code that draws *inside* compiled kernels (the IMU simulator, :mod:`mtcal.core.simulate`)
uses the same key, split in two: the part fixed for a run — ``(seed, stream, …)``, or a
caller's ``numpy.random.Generator`` — is hashed once by SeedSequence into a 64-bit Philox
key (:func:`philox_key`, :func:`spawn_philox_key`); the parts that vary inside a kernel —
the trial index, a stream word, the sample block — are the Philox4x32-10 *counter*
(:mod:`mtcal.core.philox` documents which 32-bit word holds what). Every number is then a
pure function of its coordinates: the same for any chunking, thread count or worker, and
trial ``t``'s numbers do not depend on which other trials run. (Salmon et al., SC'11.)

>>> a = trial_rng(7, 3, 0).standard_normal(2)
>>> b = trial_rng(7, 3, 0).standard_normal(2)
>>> bool((a == b).all())
True
>>> bool((trial_rng(7, 3, 1).standard_normal(2) == a).any())
False
"""

from __future__ import annotations

import numpy as np

__all__ = ["stream_key", "trial_rng", "stream_rng", "child_rngs", "rng_copy", "philox_key", "spawn_philox_key"]


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


def child_rngs(rng: np.random.Generator, n: int) -> list[np.random.Generator]:
    """The next ``n`` independent child generators of ``rng`` (numpy NEP 19 ``Generator.spawn``).

    Child ``i`` is keyed by ``rng``'s SeedSequence with spawn key ``(…, c + i)``, ``c`` the number
    of children spawned before; the call advances that count, not ``rng``'s own stream. For a
    generator fresh from ``stream_rng(seed, stream)`` child ``i`` equals
    ``stream_rng(seed, stream, 0, 0, i)`` (see "Keys that look different but are equal"): block
    ``i`` of a Monte Carlo drawing from child ``i`` gets its numbers whichever other blocks run.

    Parameters
    ----------
    rng : numpy.random.Generator
        Made from a SeedSequence (:func:`stream_rng`, :func:`trial_rng`, another child).
    n : int
        Number of children, ``>= 0``.

    Returns
    -------
    list of numpy.random.Generator, length ``n``

    References
    ----------
    numpy NEP 19 (``SeedSequence.spawn``); O'Neill 2015 (PCG64).

    Examples
    --------
    >>> a, b = child_rngs(stream_rng(7, 300), 2)
    >>> float(b.uniform()) == float(stream_rng(7, 300, 0, 0, 1).uniform())
    True
    >>> child_rngs(stream_rng(7, 300), -1)
    Traceback (most recent call last):
    ...
    ValueError: n must be an integer >= 0, got -1
    """
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
        raise ValueError(f"n must be an integer >= 0, got {n!r}")
    return rng.spawn(int(n))


def rng_copy(rng: np.random.Generator) -> np.random.Generator:
    """A fresh generator on a copy of ``rng``'s SeedSequence (entropy, spawn key, pool size and the
    count of children spawned so far).

    Its children (:func:`child_rngs`, :func:`spawn_philox_key`, :func:`mtcal.core.simulate.simulate_imu`)
    are the ones ``rng`` would spawn next, and spawning from the copy leaves ``rng`` untouched: a
    caller keeps one copy and replays any trial's numbers from a further copy of it. The copy's own
    stream starts at the SeedSequence's first state, not at ``rng``'s current state.

    Parameters
    ----------
    rng : numpy.random.Generator
        Made from a SeedSequence.

    Returns
    -------
    numpy.random.Generator (PCG64)

    References
    ----------
    numpy NEP 19 (``SeedSequence``).

    Examples
    --------
    >>> g = stream_rng(1, 2)
    >>> c = rng_copy(g)
    >>> float(child_rngs(c, 1)[0].uniform()) == float(child_rngs(g, 1)[0].uniform())
    True
    """
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    ss = rng.bit_generator.seed_seq
    return np.random.Generator(np.random.PCG64(np.random.SeedSequence(
        ss.entropy, spawn_key=ss.spawn_key, pool_size=ss.pool_size, n_children_spawned=ss.n_children_spawned)))


def philox_key(seed: int, stream: int, *more: int) -> tuple[int, int]:
    """The 64-bit Philox key ``(k0, k1)`` of the stream ``(seed, stream, *more)`` (see the counter-based rule).

    The two 32-bit words of ``SeedSequence(stream_key(seed, stream, *more)).generate_state(2)``.

    Parameters
    ----------
    seed, stream : int
        Run seed and stream number, each ``>= 0``.
    *more : int
        Further fixed key parts (each ``>= 0``); the trial index belongs in the counter.

    Returns
    -------
    tuple of 2 int
        Key words, each in [0, 2³²).

    References
    ----------
    Salmon et al., SC'11 (Philox keys); numpy NEP 19 (SeedSequence hashing).

    Examples
    --------
    >>> philox_key(1, 2) == philox_key(1, 2) != philox_key(1, 3)
    True
    """
    state = np.random.SeedSequence(stream_key(seed, stream, *more)).generate_state(2, dtype=np.uint32)
    return int(state[0]), int(state[1])


def spawn_philox_key(rng: np.random.Generator) -> tuple[int, int]:
    """A Philox key ``(k0, k1)`` for a caller's generator: the hash of ``rng``'s next spawned SeedSequence.

    Like ``rng.spawn(1)`` it advances ``rng``'s spawn counter (not its stream), so two calls with
    one generator give two independent keys and equal-seeded generators give equal keys.

    Parameters
    ----------
    rng : numpy.random.Generator
        A generator made from a SeedSequence (``np.random.default_rng(seed)``, :func:`stream_rng`).

    Returns
    -------
    tuple of 2 int

    References
    ----------
    numpy NEP 19 (``SeedSequence.spawn``); Salmon et al., SC'11.

    Examples
    --------
    >>> spawn_philox_key(np.random.default_rng(5)) == spawn_philox_key(np.random.default_rng(5))
    True
    >>> g = np.random.default_rng(5)
    >>> spawn_philox_key(g) != spawn_philox_key(g)
    True
    """
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    seq = rng.spawn(1)[0].bit_generator.seed_seq
    state = seq.generate_state(2, dtype=np.uint32)
    return int(state[0]), int(state[1])
