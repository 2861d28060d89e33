"""Four-lane SIMD arithmetic on tuples of float64 (private).

Structure-of-arrays over trials for the batched filter kernels: a lane vector is a
``UniTuple(float64, 4)`` (one value per trial of a block of four). Every helper is one
IEEE-754 operation per lane, emitted as an LLVM ``<4 x double>`` instruction (``fadd``,
``fsub``, ``fmul``, ``fdiv``, ``llvm.sqrt``, ``llvm.fabs``, ``fcmp`` + ``select``), so
numba's code generator produces packed SIMD (2 × SSE2 on the pinned generic target,
one AVX2 register natively) instead of relying on its SLP vectoriser (off by default in
numba). Each lane's result is bit-identical to the scalar operation with the same operands:
no fast-math flags, no contraction into FMA, correctly rounded division and square root.
Comparisons reproduce numba's scalar semantics (ordered ``<``, ``<=``, ``>``: False with a
NaN operand; ``max(x, y)`` is ``y if y > x else x``).
"""

from __future__ import annotations

import numba  # after mtcal.core.compiled (imported with the package): numba settings first
from llvmlite import ir
from numba.core import cgutils, types
from numba.extending import intrinsic

__all__ = ["LANES", "bc", "add", "sub", "mul", "div", "adds", "muls", "divs", "sqrt", "fabs", "maxs", "vmax",
           "where_lt", "where_le"]

#: Trials stepped together by the batched kernels.
LANES = 4

_V4 = ir.VectorType(ir.DoubleType(), LANES)
_I32 = ir.IntType(32)


def _check(*tys) -> None:
    for ty in tys:
        if not (isinstance(ty, types.UniTuple) and ty.count == LANES and ty.dtype == types.float64):
            raise numba.core.errors.TypingError(f"expected a UniTuple(float64, {LANES}), got {ty}")


def _to_vec(builder, agg):
    vec = ir.Constant(_V4, ir.Undefined)
    for i in range(LANES):
        vec = builder.insert_element(vec, builder.extract_value(agg, i), ir.Constant(_I32, i))
    return vec


def _from_vec(builder, vec, aggty):
    agg = ir.Constant(aggty, ir.Undefined)
    for i in range(LANES):
        agg = builder.insert_value(agg, builder.extract_element(vec, ir.Constant(_I32, i)), i)
    return agg


def _binary(op: str):
    @intrinsic
    def fn(typingctx, a, b):
        _check(a, b)

        def codegen(context, builder, sig, args):
            res = getattr(builder, op)(_to_vec(builder, args[0]), _to_vec(builder, args[1]))
            return _from_vec(builder, res, context.get_value_type(sig.return_type))
        return a(a, b), codegen
    return fn


def _unary(name: str):
    @intrinsic
    def fn(typingctx, a):
        _check(a)

        def codegen(context, builder, sig, args):
            f = cgutils.get_or_insert_function(builder.module, ir.FunctionType(_V4, [_V4]), f"{name}.v4f64")
            res = builder.call(f, [_to_vec(builder, args[0])])
            return _from_vec(builder, res, context.get_value_type(sig.return_type))
        return a(a), codegen
    return fn


def _where(pred: str):
    @intrinsic
    def fn(typingctx, x, y, a, b):
        _check(x, y, a, b)

        def codegen(context, builder, sig, args):
            vx, vy, va, vb = (_to_vec(builder, v) for v in args)
            res = builder.select(builder.fcmp_ordered(pred, vx, vy), va, vb)
            return _from_vec(builder, res, context.get_value_type(sig.return_type))
        return a(x, y, a, b), codegen
    return fn


add = _binary("fadd")
sub = _binary("fsub")
mul = _binary("fmul")
div = _binary("fdiv")
sqrt = _unary("llvm.sqrt")
fabs = _unary("llvm.fabs")
_where_gt = _where(">")
#: Per lane ``a if x < y else b``.
where_lt = _where("<")
#: Per lane ``a if x <= y else b``.
where_le = _where("<=")

_inl = numba.njit(inline="always")


@_inl
def bc(x):
    """(x, x, x, x)."""
    return (x, x, x, x)


@_inl
def adds(a, s):
    return add(a, (s, s, s, s))


@_inl
def muls(a, s):
    return mul(a, (s, s, s, s))


@_inl
def divs(a, s):
    return div(a, (s, s, s, s))


@_inl
def vmax(a, b):
    """Per lane ``max(a, b)`` as numba computes it: ``b if b > a else a``."""
    return _where_gt(b, a, b, a)


@_inl
def maxs(a, s):
    """Per lane ``max(a, s)``."""
    v = (s, s, s, s)
    return _where_gt(v, a, v, a)
