"""Counter-based random numbers: Philox4x32-10, 53-bit uniforms and ziggurat normals, compiled.

A counter-based generator is a keyed bijection ``x = f_k(c)`` of a 128-bit counter ``c``:
the numbers of any (seed, stream, trial, sample) are computed directly from their
coordinates, with no state to carry, split or skip ahead. That is what lets the
simulator draw its noise *inside* the compiled kernels, trials in parallel, with the
same numbers for any chunking, thread count or worker and for any subset of trials
(Salmon, Moraes, Dror & Shaw, SC'11, "Parallel random numbers: as easy as 1, 2, 3").

Generator
---------
Philox4x32-10 exactly as in Random123 (``philox4x32_R`` with R = 10): four 32-bit counter
words ``(c0, c1, c2, c3)``, two 32-bit key words ``(k0, k1)``; each round
``(hi0, lo0) = M0·c0``, ``(hi1, lo1) = M1·c2`` (32×32 → 64-bit products, M0 = 0xD2511F53,
M1 = 0xCD9E8D57) and ``c ← (hi1 ⊕ c1 ⊕ k0, lo1, hi0 ⊕ c3 ⊕ k1, lo0)``; the key is bumped by
the Weyl constants (0x9E3779B9, 0xBB67AE85) before rounds 2…10. Verified against the
published known-answer vectors of Random123's ``tests/kat_vectors`` (tests/core/test_philox.py).
Integer arithmetic only (uint64 products of uint32 words), so the words are the same on
every CPU, SIMD width and thread count.

Transforms (stated once, used everywhere)
-----------------------------------------
* 64-bit words: one Philox call gives two, ``w_a = x0 | x1 << 32`` (lane 0) and
  ``w_b = x2 | x3 << 32`` (lane 1).
* Uniform double in [0, 1): ``(w >> 11) · 2⁻⁵³`` (the top 53 bits; every multiple of 2⁻⁵³).
* Standard normal: the 256-layer ziggurat of Marsaglia & Tsang (2000) in numpy's
  ``random_standard_normal`` form (same tables: numpy's ``ziggurat_constants.h``, as vendored by
  numba): of a word ``w``, the low 8 bits pick the layer, the next bit is the sign, the next 52 bits
  the abscissa; ~99 % of words are accepted at once. A rejected word continues on its own
  *rejection stream*: Philox calls with the same ``(c0, c1, c2)`` and ``c3 = 1 + lane + 2j``,
  j = 0, 1, … (lane 0 / 1 of the primary call never share a rejection stream), whose lane-0 word gives
  the uniform(s) of the wedge/tail test and whose lane-1 word is the next candidate. The ziggurat is an
  exact rejection sampler, so every normal is exact given its 53/52-bit uniforms.

Key layout (the simulator's; :mod:`mtcal.core.rng` states the general rule)
------------------------------------------------------------------------------
* key ``(k0, k1)`` — 64 bits hashed from the run's seed (and its stream), see
  :func:`mtcal.core.rng.philox_key`;
* ``c0`` — sample block: the pair index ``m = k // 2`` of sample ``k`` (the pair's two normals are
  lanes 0 and 1, sample ``2m`` and ``2m + 1``); 0 for once-per-trial draws;
* ``c1`` — the trial index as named by the caller (not the position in a batch);
* ``c2`` — the stream word ``sensor << 8 | source << 4 | axis`` (:func:`stream_word`);
* ``c3`` — draw index: 0 for the primary call, ``1 + lane + 2j`` on the ziggurat's rejection stream.

Examples
--------
>>> [f"{w:08x}" for w in philox4x32_10(0, 0, 0, 0, 0, 0)]
['6627e8d5', 'e169c58d', 'bc57ac4c', '9b00dbd8']
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba.np.random._constants import fi_double as _FI_SRC
from numba.np.random._constants import ki_double as _KI_SRC
from numba.np.random._constants import wi_double as _WI_SRC
from numba.np.random._constants import ziggurat_nor_inv_r as _ZIG_INV_R
from numba.np.random._constants import ziggurat_nor_r as _ZIG_R

from mtcal.core.compiled import jit

# Compiled building blocks for kernels (not in __all__, called from numba code only): philox_words,
# uniform_from_word, normal_pair, uniform_pair (and the ziggurat's _zig/_zig_slow).
__all__ = ["philox4x32_10", "stream_word", "standard_normals", "uniforms", "SOURCE_IDS", "KI", "WI", "FI"]

_M0 = np.uint64(0xD2511F53)
_M1 = np.uint64(0xCD9E8D57)
_W0 = np.uint64(0x9E3779B9)
_W1 = np.uint64(0xBB67AE85)
_MASK32 = np.uint64(0xFFFFFFFF)
_MASK52 = np.uint64(0x000FFFFFFFFFFFFF)
_U32 = np.uint64(32)
_U11 = np.uint64(11)
_U8 = np.uint64(8)
_U1 = np.uint64(1)
_UFF = np.uint64(0xFF)
_TWO_M53 = 2.0 ** -53

#: Ziggurat tables (256 layers), numpy's ``ziggurat_constants.h`` values (copied, read-only).
KI = np.array(_KI_SRC, dtype=np.uint64)
WI = np.array(_WI_SRC, dtype=np.float64)
FI = np.array(_FI_SRC, dtype=np.float64)
for _a in (KI, WI, FI):
    _a.setflags(write=False)
_R = float(_ZIG_R)
_INV_R = float(_ZIG_INV_R)

#: Error-source numbers of the simulator's stream word (``source`` bits 4–7 of ``c2``).
SOURCE_IDS = {"turn_on": 0, "white": 1, "random_walk": 2, "instability": 3, "vibration": 4}


def stream_word(sensor: int, source: int, axis: int) -> int:
    """Counter word ``c2 = sensor << 8 | source << 4 | axis`` of the simulator (see the key layout).

    Parameters
    ----------
    sensor : int
        0 gyro, 1 accelerometer (0…255).
    source : int
        Error source, :data:`SOURCE_IDS` (0…15).
    axis : int
        Sensor axis 0, 1, 2 (0…15).

    Returns
    -------
    int

    References
    ----------
    Salmon et al., SC'11 (a counter word per independent stream).

    Examples
    --------
    >>> stream_word(1, SOURCE_IDS["white"], 2)
    274
    """
    for name, v, hi in (("sensor", sensor, 255), ("source", source, 15), ("axis", axis, 15)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 0 <= v <= hi:
            raise ValueError(f"{name} must be an integer in [0, {hi}], got {v!r}")
    return int(sensor) << 8 | int(source) << 4 | int(axis)


@numba.njit(inline="always")
def _round(c0, c1, c2, c3, k0, k1):
    p0 = _M0 * c0
    p1 = _M1 * c2
    return ((p1 >> _U32) ^ c1 ^ k0, p1 & _MASK32, (p0 >> _U32) ^ c3 ^ k1, p0 & _MASK32)


@numba.njit(inline="always")
def _philox(c0, c1, c2, c3, k0, k1):
    """Philox4x32-10 on uint64 values holding 32-bit words (returns four uint64 holding 32-bit words).

    The counter words are masked to 32 bits first (the identity on valid words): it tells the compiler
    every product is 32 × 32 bits, so a vectorised loop uses ``vpmuludq`` instead of a 64-bit multiply."""
    c0, c1, c2, c3 = c0 & _MASK32, c1 & _MASK32, c2 & _MASK32, c3 & _MASK32
    c0, c1, c2, c3 = _round(c0, c1, c2, c3, k0, k1)
    for _ in range(9):
        k0 = (k0 + _W0) & _MASK32
        k1 = (k1 + _W1) & _MASK32
        c0, c1, c2, c3 = _round(c0, c1, c2, c3, k0, k1)
    return c0, c1, c2, c3


@jit
def _philox_jit(c0, c1, c2, c3, k0, k1):
    return _philox(np.uint64(c0), np.uint64(c1), np.uint64(c2), np.uint64(c3), np.uint64(k0), np.uint64(k1))


def _word32(v, name: str) -> int:
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 0 <= v <= 0xFFFFFFFF:
        raise ValueError(f"{name} must be a 32-bit unsigned integer, got {v!r}")
    return int(v)


def philox4x32_10(c0: int, c1: int, c2: int, c3: int, k0: int, k1: int) -> tuple[int, int, int, int]:
    """One Philox4x32-10 block: counter ``(c0, c1, c2, c3)``, key ``(k0, k1)`` → four 32-bit words.

    Parameters
    ----------
    c0, c1, c2, c3 : int
        Counter words, each in [0, 2³²).
    k0, k1 : int
        Key words, each in [0, 2³²).

    Returns
    -------
    tuple of 4 int
        The output words (Random123 ``philox4x32_R(10, ctr, key)``).

    References
    ----------
    Salmon, Moraes, Dror & Shaw, SC'11 (Philox); Random123 ``tests/kat_vectors``.

    Examples
    --------
    >>> [f"{w:08x}" for w in philox4x32_10(*(0xFFFFFFFF,) * 6)]
    ['408f276d', '41c83b0e', 'a20bc7c6', '6d5451fd']
    """
    words = [_word32(v, n) for v, n in zip((c0, c1, c2, c3, k0, k1), ("c0", "c1", "c2", "c3", "k0", "k1"))]
    return tuple(int(w) for w in _philox_jit(*words))


@numba.njit(inline="always")
def philox_words(c0, c1, c2, c3, k0, k1):
    """Compiled: the two 64-bit words (lane 0, lane 1) of one Philox call (uint64 arguments)."""
    x0, x1, x2, x3 = _philox(c0, c1, c2, c3, k0, k1)
    return x0 | (x1 << _U32), x2 | (x3 << _U32)


@numba.njit(inline="always")
def uniform_from_word(w):
    """Compiled: uniform double in [0, 1) from the top 53 bits of a uint64 word."""
    return np.float64(np.int64(w >> _U11)) * _TWO_M53


@numba.njit
def _zig_slow(r, c0, c1, c2, lane, k0, k1):
    """Ziggurat after a rejected first word ``r``: continues on the rejection stream of ``lane``."""
    j = np.uint64(0)
    while True:
        idx = r & _UFF
        r8 = r >> _U8
        rabs = (r8 >> _U1) & _MASK52
        x = np.float64(np.int64(rabs)) * WI[idx]
        if r8 & _U1:
            x = -x
        if rabs < KI[idx]:
            return x
        if idx == 0:
            while True:
                a, b = philox_words(c0, c1, c2, np.uint64(1) + lane + np.uint64(2) * j, k0, k1)
                j += np.uint64(1)
                xx = -_INV_R * math.log1p(-uniform_from_word(a))
                yy = -math.log1p(-uniform_from_word(b))
                if yy + yy > xx * xx:
                    return -(_R + xx) if (rabs >> _U8) & _U1 else _R + xx
        a, b = philox_words(c0, c1, c2, np.uint64(1) + lane + np.uint64(2) * j, k0, k1)
        j += np.uint64(1)
        if (FI[idx - _U1] - FI[idx]) * uniform_from_word(a) + FI[idx] < math.exp(-0.5 * x * x):
            return x
        r = b


@numba.njit(inline="always")
def _zig(r, c0, c1, c2, lane, k0, k1):
    idx = r & _UFF
    r8 = r >> _U8
    rabs = (r8 >> _U1) & _MASK52
    x = np.float64(np.int64(rabs)) * WI[idx]
    if r8 & _U1:
        x = -x
    if rabs < KI[idx]:
        return x
    return _zig_slow(r, c0, c1, c2, lane, k0, k1)


@numba.njit(inline="always")
def normal_pair(c0, c1, c2, k0, k1):
    """Compiled: the two standard normals (lane 0, lane 1) of counter ``(c0, c1, c2, 0)`` (uint64 args)."""
    a, b = philox_words(c0, c1, c2, np.uint64(0), k0, k1)
    return _zig(a, c0, c1, c2, np.uint64(0), k0, k1), _zig(b, c0, c1, c2, np.uint64(1), k0, k1)


@numba.njit(inline="always")
def uniform_pair(c0, c1, c2, k0, k1):
    """Compiled: the two uniforms in [0, 1) (lane 0, lane 1) of counter ``(c0, c1, c2, 0)``."""
    a, b = philox_words(c0, c1, c2, np.uint64(0), k0, k1)
    return uniform_from_word(a), uniform_from_word(b)


@jit
def _fill_range(out, kind, c0_start, c1, c2, k0, k1, lo, hi):
    for p in range(lo, hi):
        c0 = np.uint64(c0_start) + np.uint64(p)
        if kind == 0:
            z0, z1 = normal_pair(c0, np.uint64(c1), np.uint64(c2), np.uint64(k0), np.uint64(k1))
        else:
            z0, z1 = uniform_pair(c0, np.uint64(c1), np.uint64(c2), np.uint64(k0), np.uint64(k1))
        out[2 * p] = z0
        out[2 * p + 1] = z1


@jit(parallel=True)
def _fill_parallel(out, kind, c0_start, c1, c2, k0, k1):
    m = out.shape[0] // 2
    size = 4096
    for b in numba.prange((m + size - 1) // size):
        _fill_range(out, kind, c0_start, c1, c2, k0, k1, b * size, min((b + 1) * size, m))


def _fill(out, kind, c0_start, c1, c2, k0, k1) -> None:
    """Pairs of draws into ``out``; threads only for large fills (a small one never starts OpenMP)."""
    if out.size >= 200_000 and numba.get_num_threads() > 1:
        _fill_parallel(out, kind, c0_start, c1, c2, k0, k1)
    else:
        _fill_range(out, kind, c0_start, c1, c2, k0, k1, 0, out.shape[0] // 2)


def _draws(kind: int, n: int, key, c1: int, c2: int, c0_start: int) -> np.ndarray:
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
        raise ValueError(f"n must be an integer >= 0, got {n!r}")
    if len(key) != 2:
        raise ValueError(f"key must be two 32-bit words, got {key!r}")
    k0, k1 = _word32(key[0], "key[0]"), _word32(key[1], "key[1]")
    c1, c2, c0_start = _word32(c1, "c1"), _word32(c2, "c2"), _word32(c0_start, "c0_start")
    pairs = -(-int(n) // 2)
    if c0_start + pairs > 2 ** 32:
        raise ValueError(f"c0_start + n/2 must stay below 2**32, got {c0_start} + {pairs}")
    out = np.empty(2 * pairs)
    _fill(out, kind, c0_start, c1, c2, k0, k1)
    return out[:n]


def standard_normals(n: int, key=(0, 0), c1: int = 0, c2: int = 0, c0_start: int = 0) -> np.ndarray:
    """``n`` standard normals of the counters ``(c0_start + i // 2, c1, c2, ·)``, lane ``i % 2``.

    Parameters
    ----------
    n : int
        Number of draws.
    key : pair of int
        Key words ``(k0, k1)``, each in [0, 2³²).
    c1, c2 : int
        Fixed counter words (e.g. trial and stream word).
    c0_start : int
        First value of the counter word ``c0``.

    Returns
    -------
    ndarray, shape (n,)
        Ziggurat normals (see the module's transforms), computed in parallel for large ``n``.

    References
    ----------
    Salmon et al., SC'11 (Philox4x32-10); Marsaglia & Tsang, J. Stat. Softw. 5(8), 2000
    (ziggurat), in numpy's 256-layer form.

    Examples
    --------
    >>> z = standard_normals(4, key=(1, 2))
    >>> bool(np.array_equal(z[2:], standard_normals(2, key=(1, 2), c0_start=1)))
    True
    """
    return _draws(0, n, key, c1, c2, c0_start)


def uniforms(n: int, key=(0, 0), c1: int = 0, c2: int = 0, c0_start: int = 0) -> np.ndarray:
    """``n`` uniforms in [0, 1) (53-bit) of the counters of :func:`standard_normals`.

    Parameters
    ----------
    n, key, c1, c2, c0_start
        As for :func:`standard_normals`.

    Returns
    -------
    ndarray, shape (n,)
        ``(w >> 11) · 2⁻⁵³`` of each 64-bit word ``w``.

    References
    ----------
    Salmon et al., SC'11 (Philox4x32-10).

    Examples
    --------
    >>> u = uniforms(1000, key=(3, 4))
    >>> bool((u >= 0).all() and (u < 1).all())
    True
    """
    return _draws(1, n, key, c1, c2, c0_start)
