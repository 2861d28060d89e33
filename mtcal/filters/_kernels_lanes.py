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

The same helpers also take :data:`vec4` values (a numba type whose LLVM representation *is*
``<4 x double>``; build one with :func:`pack` or :func:`splat`, read it with :func:`unpack`).
A tuple is four scalars to LLVM: a tuple carried from one loop iteration to the next becomes
four scalar ``phi`` nodes, re-packed into a vector before every operation and split after it
(shuffles and scalar spills around every libm call). A ``vec4`` loop variable stays one vector
register (or one 32-byte spill slot); the arithmetic per lane is the same IEEE-754 operation.
"""

from __future__ import annotations

import numba  # after mtcal.core.compiled (imported with the package): numba settings first
from llvmlite import ir
from numba.core import cgutils, types
from numba.extending import intrinsic, models, register_model

__all__ = ["LANES", "bc", "add", "sub", "mul", "div", "adds", "muls", "divs", "sqrt", "fabs", "maxs", "vmax",
           "where_lt", "where_le", "vec4", "pack", "splat", "unpack", "load4"]

#: Trials stepped together by the batched kernels.
LANES = 4

_V4 = ir.VectorType(ir.DoubleType(), LANES)
_I32 = ir.IntType(32)


class Vec4Type(types.Type):
    """Four float64 lanes held as one LLVM ``<4 x double>`` value."""

    def __init__(self) -> None:
        super().__init__(name="Vec4(float64)")


#: The numba type of a 4-lane float64 vector.
vec4 = Vec4Type()


@register_model(Vec4Type)
class _Vec4Model(models.PrimitiveModel):
    def __init__(self, dmm, fe_type):
        super().__init__(dmm, fe_type, _V4)


def _all_vec(*tys) -> bool:
    """True when every type is :data:`vec4`; a TypingError for a mix of vectors and tuples."""
    n = sum(isinstance(ty, Vec4Type) for ty in tys)
    if n and n != len(tys):
        raise numba.core.errors.TypingError(f"cannot mix vec4 and tuple lane vectors: {tys}")
    return n > 0


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
        if _all_vec(a, b):
            return a(a, b), lambda context, builder, sig, args: getattr(builder, op)(args[0], args[1])
        _check(a, b)

        def codegen(context, builder, sig, args):
            res = getattr(builder, op)(_to_vec(builder, args[0]), _to_vec(builder, args[1]))
            return _from_vec(builder, res, context.get_value_type(sig.return_type))
        return a(a, b), codegen
    return fn


def _unary(name: str):
    @intrinsic
    def fn(typingctx, a):
        if _all_vec(a):
            def vcodegen(context, builder, sig, args):
                f = cgutils.get_or_insert_function(builder.module, ir.FunctionType(_V4, [_V4]), f"{name}.v4f64")
                return builder.call(f, [args[0]])
            return a(a), vcodegen
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
        if _all_vec(x, y, a, b):
            def vcodegen(context, builder, sig, args):
                return builder.select(builder.fcmp_ordered(pred, args[0], args[1]), args[2], args[3])
            return a(x, y, a, b), vcodegen
        _check(x, y, a, b)

        def codegen(context, builder, sig, args):
            vx, vy, va, vb = (_to_vec(builder, v) for v in args)
            res = builder.select(builder.fcmp_ordered(pred, vx, vy), va, vb)
            return _from_vec(builder, res, context.get_value_type(sig.return_type))
        return a(x, y, a, b), codegen
    return fn


@intrinsic
def pack(typingctx, x0, x1, x2, x3):
    """The :data:`vec4` (x0, x1, x2, x3) of four float64 scalars."""
    for ty in (x0, x1, x2, x3):
        if ty != types.float64:
            raise numba.core.errors.TypingError(f"pack takes float64 scalars, got {ty}")

    def codegen(context, builder, sig, args):
        vec = ir.Constant(_V4, ir.Undefined)
        for i, x in enumerate(args):
            vec = builder.insert_element(vec, x, ir.Constant(_I32, i))
        return vec
    return vec4(x0, x1, x2, x3), codegen


@intrinsic
def unpack(typingctx, v):
    """The four lanes of a :data:`vec4` as a UniTuple(float64, 4)."""
    if not isinstance(v, Vec4Type):
        raise numba.core.errors.TypingError(f"unpack takes a vec4, got {v}")
    tup = types.UniTuple(types.float64, LANES)

    def codegen(context, builder, sig, args):
        return _from_vec(builder, args[0], context.get_value_type(tup))
    return tup(v), codegen


@intrinsic
def load4(typingctx, arr, start):
    """:data:`vec4` of ``arr[start:start + 4]`` (1-D C-contiguous float64 array; no bounds check)."""
    if not (isinstance(arr, types.Array) and arr.ndim == 1 and arr.dtype == types.float64 and arr.layout == "C"):
        raise numba.core.errors.TypingError(f"load4 takes a 1-D C-contiguous float64 array, got {arr}")
    if not isinstance(start, types.Integer):
        raise numba.core.errors.TypingError(f"load4 takes an integer start, got {start}")

    def codegen(context, builder, sig, args):
        ary = context.make_array(sig.args[0])(context, builder, args[0])
        ptr = builder.gep(ary.data, [context.cast(builder, args[1], sig.args[1], types.intp)])
        vptr = builder.bitcast(ptr, _V4.as_pointer())
        return builder.load(vptr, align=8)
    return vec4(arr, start), codegen


@numba.njit(inline="always")
def splat(x):
    """:data:`vec4` (x, x, x, x) of a float64."""
    return pack(x, x, x, x)


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
