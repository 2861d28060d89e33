"""numpy's ``Generator(PCG64).standard_normal`` fill, compiled (private): the same numbers, bit for bit.

The study draws every trial's noise from ``trial_rng(seed, stream, trial)`` (:mod:`mtcal.core.rng`: a
``numpy.random.Generator`` on ``PCG64``). numpy fills ``standard_normal(out=x)`` element by element in
C order with ``random_standard_normal`` (``numpy/random/src/distributions/distributions.c``):

* ``PCG64`` (XSL-RR 128/64, ``pcg64.h``): ``state = state · M + inc (mod 2¹²⁸)``, then the output
  ``rotr64(hi ^ lo, hi >> 58)`` of the new state; ``next_double = (next_uint64 >> 11) · 2⁻⁵³``;
* the 256-layer ziggurat: ``r = next_uint64``, ``idx = r & 0xff``, ``r >>= 8``, sign bit ``r & 1``,
  ``rabs = (r >> 1) & (2⁵² − 1)``, ``x = ±rabs · wi[idx]``, accepted when ``rabs < ki[idx]``; else the
  tail (``idx = 0``: ``xx = −log1p(−U)/r``, ``yy = −log1p(−U)`` until ``2yy > xx²``) or the wedge test
  ``(fi[idx−1] − fi[idx]) · U + fi[idx] < exp(−x²/2)``, with the tables ``ki``/``wi``/``fi`` of numpy's
  ``ziggurat_constants.h`` (:data:`mtcal.core.philox.KI` …).

The 128-bit product is done in 64-bit words (the high word of the 64 × 64 product is one LLVM
``mul i128``). The kernel starts from the generator's state (``bit_generator.state``), so the keyed streams
stay those of :mod:`mtcal.core.rng`; checked bit for bit against numpy over millions of draws in
``tests/studies/test_wang2022sensors.py``. float64 without ``fastmath`` (no FMA contraction), libm's
``log1p``/``exp`` as numpy's.
"""

from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from mtcal.core.compiled import jit
from mtcal.core.philox import FI, KI, WI

__all__ = ["generator_state", "fill_normals", "warm_up"]

_M_HI = np.uint64(2549297995355413924)
_M_LO = np.uint64(4865540595714422341)
_U58 = np.uint64(58)
_U63 = np.uint64(63)
_U64 = np.uint64(64)
_U0 = np.uint64(0)
_U1 = np.uint64(1)
_U8 = np.uint64(8)
_U11 = np.uint64(11)
_UFF = np.uint64(0xFF)
_M52 = np.uint64(0x000FFFFFFFFFFFFF)
_R = 3.654152885361009            # ziggurat_nor_r (numpy's ziggurat_constants.h)
_INV_R = 0.27366123732975828      # ziggurat_nor_inv_r
_TWO_M53 = 1.0 / 9007199254740992.0


def generator_state(rng: np.random.Generator) -> tuple[int, int, int, int]:
    """(state_hi, state_lo, inc_hi, inc_lo) of a PCG64 generator, as unsigned 64-bit words."""
    st = rng.bit_generator.state
    if st["bit_generator"] != "PCG64" or st["has_uint32"]:
        raise ValueError("a fresh PCG64 generator is required")
    s, inc = st["state"]["state"], st["state"]["inc"]
    mask = (1 << 64) - 1
    return s >> 64, s & mask, inc >> 64, inc & mask


@intrinsic
def _mulhi(typingctx, a, b):
    """High 64 bits of the 128-bit product of two unsigned 64-bit words (one ``mul i128``)."""
    def codegen(context, builder, signature, args):
        i128 = ir.IntType(128)
        prod = builder.mul(builder.zext(args[0], i128), builder.zext(args[1], i128))
        return builder.trunc(builder.lshr(prod, ir.Constant(i128, 64)), ir.IntType(64))
    return types.uint64(types.uint64, types.uint64), codegen


@jit
def _next(hi, lo, inc_hi, inc_lo):
    """PCG64 step of the state (hi, lo) with increment (inc_hi, inc_lo): the new state and the XSL-RR output
    of the new state."""
    new_lo = lo * _M_LO
    new_hi = hi * _M_LO + lo * _M_HI + _mulhi(lo, _M_LO)
    s_lo = new_lo + inc_lo
    s_hi = new_hi + inc_hi + (_U1 if s_lo < new_lo else _U0)
    v = s_hi ^ s_lo
    rot = s_hi >> _U58
    return s_hi, s_lo, (v >> rot) | (v << ((_U64 - rot) & _U63))


@jit
def _double(r):
    """``next_double`` of an output word: (r >> 11) · 2⁻⁵³."""
    return np.float64(r >> _U11) * _TWO_M53


@jit
def fill_normals(states, out, ki, wi, fi):
    """Row ``b`` of ``out`` (B, M) ← the first M standard normals (numpy's ``random_standard_normal``) of the
    PCG64 state ``states[b]`` (B, 4) uint64: state hi, lo, increment hi, lo."""
    for b in range(out.shape[0]):
        hi, lo, inc_hi, inc_lo = states[b, 0], states[b, 1], states[b, 2], states[b, 3]
        for i in range(out.shape[1]):
            while True:
                hi, lo, r = _next(hi, lo, inc_hi, inc_lo)
                idx = np.int64(r & _UFF)
                r = r >> _U8
                rabs = (r >> _U1) & _M52
                x = np.float64(rabs) * wi[idx]
                if (r & _U1) == _U1:
                    x = -x
                if rabs < ki[idx]:
                    break
                if idx == 0:  # the tail
                    while True:
                        hi, lo, r1 = _next(hi, lo, inc_hi, inc_lo)
                        xx = -_INV_R * math.log1p(-_double(r1))
                        hi, lo, r2 = _next(hi, lo, inc_hi, inc_lo)
                        yy = -math.log1p(-_double(r2))
                        if yy + yy > xx * xx:
                            x = -(_R + xx) if ((rabs >> _U8) & _U1) == _U1 else _R + xx
                            break
                    break
                hi, lo, r1 = _next(hi, lo, inc_hi, inc_lo)  # the wedge
                if (fi[idx - 1] - fi[idx]) * _double(r1) + fi[idx] < math.exp(-0.5 * x * x):
                    break
            out[b, i] = x


def normals(states: np.ndarray, out: np.ndarray) -> None:
    """:func:`fill_normals` with numpy's ziggurat tables."""
    fill_normals(states, out, KI, WI, FI)


def warm_up() -> None:
    """Compile (or load from the cache) the kernel on a tiny input: a C-contiguous output and a strided one (the
    leading columns of a wider buffer, as :func:`~.runs.simulate_batch` fills)."""
    normals(np.ones((1, 4), np.uint64), np.empty((1, 2)))
    normals(np.ones((2, 4), np.uint64), np.empty((2, 3))[:, :2])
