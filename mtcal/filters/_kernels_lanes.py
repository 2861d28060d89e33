"""SIMD lane arithmetic for the batched filter kernels: tuples of float64 and LLVM vectors (private).

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

The same helpers also take :class:`VecType` values (:data:`vec4`, :data:`vec8`: numba types
whose LLVM representation *is* ``<4 x double>`` / ``<8 x double>``; build one with :func:`pack`,
:func:`fill` or the gathers :func:`take1` / :func:`take` / :func:`take3` / :func:`choose`, read it
with :func:`unpack` or the scatters :func:`put1` / :func:`put` / :func:`put3`; :func:`cos` and
:func:`sin` call numba's scalar ``math.cos`` / ``math.sin`` lowering once per lane, i.e. the same
libm calls as scalar code). A tuple is four scalars to LLVM: a tuple carried from one loop
iteration to the next becomes four scalar ``phi`` nodes, re-packed into a vector before every
operation and split after it (shuffles and scalar spills around every libm call). A vector loop
variable stays one register (or one spill slot); the arithmetic per lane is the same IEEE-754
operation. Branching on lanes: :func:`all_le` / :func:`all_lt` (every lane's ordered comparison
holds), :func:`put_lt` (store each lane's ``<`` into a boolean array); a vector is handed to per-lane
scalar code through a ``(lanes, k)`` scratch array addressed by :func:`lane_ids`. Block size:
:func:`simd_lanes` (8 on an AVX-512 host, else 4), block rows :func:`rows4` / :func:`rows8`.

Examples
--------
>>> import numba, numpy as np
>>> @numba.njit
... def demo(x):
...     v = pack((x[0], x[1], x[2], x[3]))
...     return unpack(mul(add(v, v), fill(v, 0.5)))
>>> demo(np.array([1.0, -2.0, 3.5, 0.0]))
(1.0, -2.0, 3.5, 0.0)
"""

from __future__ import annotations

import math

import numba  # after mtcal.core.compiled (imported with the package): numba settings first
from llvmlite import ir
from numba.core import cgutils, types
from numba.extending import intrinsic, models, register_model

__all__ = ["LANES", "bc", "add", "sub", "mul", "div", "adds", "muls", "divs", "sqrt", "fabs", "maxs", "vmax",
           "where_lt", "where_le", "VecType", "vec4", "vec8", "pack", "unpack", "fill", "take1", "take", "take3",
           "put1", "put", "put3", "choose", "cos", "sin", "all_le", "all_lt", "put_lt", "lane_ids", "simd_lanes",
           "rows4", "rows8"]

#: Trials stepped together by the batched kernels.
LANES = 4

_V4 = ir.VectorType(ir.DoubleType(), LANES)
_I32 = ir.IntType(32)


class VecType(types.Type):
    """``count`` float64 lanes held as one LLVM ``<count x double>`` value."""

    def __init__(self, count: int) -> None:
        self.count = int(count)
        super().__init__(name=f"Vec{self.count}(float64)")


#: The numba types of 4- and 8-lane float64 vectors.
vec4 = VecType(4)
vec8 = VecType(8)


@register_model(VecType)
class _VecModel(models.PrimitiveModel):
    def __init__(self, dmm, fe_type):
        super().__init__(dmm, fe_type, ir.VectorType(ir.DoubleType(), fe_type.count))


def _all_vec(*tys) -> bool:
    """True when every type is the same vector type; a TypingError for a mix of vectors and tuples."""
    n = sum(isinstance(ty, VecType) for ty in tys)
    if n and (n != len(tys) or len(set(tys)) != 1):
        raise numba.core.errors.TypingError(f"lane vectors of one vector type expected, got {tys}")
    return n > 0


def _vec_of(ty):
    """The vector type of a UniTuple(float64, n) (n = 4 or 8), else a TypingError."""
    if not (isinstance(ty, types.UniTuple) and ty.count in (4, 8) and ty.dtype == types.float64):
        raise numba.core.errors.TypingError(f"expected a UniTuple(float64, 4 or 8), got {ty}")
    return VecType(ty.count)


def _rows_of(rows):
    """Lane count of a UniTuple of integer rows (4 or 8), else a TypingError."""
    if not (isinstance(rows, types.UniTuple) and rows.count in (4, 8) and isinstance(rows.dtype, types.Integer)):
        raise numba.core.errors.TypingError(f"rows must be a UniTuple of 4 or 8 integers, got {rows}")
    return rows.count


def _element_ptr(context, builder, arrty, arr, inds):
    """Pointer to ``arr[inds]`` (integer index values; no wraparound, no bounds check)."""
    ary = context.make_array(arrty)(context, builder, arr)
    shape = cgutils.unpack_tuple(builder, ary.shape, arrty.ndim)
    strides = cgutils.unpack_tuple(builder, ary.strides, arrty.ndim)
    return cgutils.get_item_pointer2(context, builder, ary.data, shape, strides, arrty.layout, inds,
                                     wraparound=False, boundscheck=False)


def _index_values(context, builder, sig_args, args, rows_pos):
    """The rows tuple argument of an intrinsic call as a list of intp values."""
    rows = [context.cast(builder, builder.extract_value(args[rows_pos], j), sig_args[rows_pos].dtype, types.intp)
            for j in range(sig_args[rows_pos].count)]
    return rows


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
                vt = ir.VectorType(ir.DoubleType(), a.count)
                f = cgutils.get_or_insert_function(builder.module, ir.FunctionType(vt, [vt]), f"{name}.v{a.count}f64")
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
def pack(typingctx, tup):
    """The lane vector of a UniTuple(float64, 4 or 8)."""
    vt = _vec_of(tup)

    def codegen(context, builder, sig, args):
        vec = ir.Constant(ir.VectorType(ir.DoubleType(), vt.count), ir.Undefined)
        for i in range(vt.count):
            vec = builder.insert_element(vec, builder.extract_value(args[0], i), ir.Constant(_I32, i))
        return vec
    return vt(tup), codegen


@intrinsic
def unpack(typingctx, v):
    """The lanes of a lane vector as a UniTuple(float64, n)."""
    if not isinstance(v, VecType):
        raise numba.core.errors.TypingError(f"unpack takes a lane vector, got {v}")
    tup = types.UniTuple(types.float64, v.count)

    def codegen(context, builder, sig, args):
        agg = ir.Constant(context.get_value_type(tup), ir.Undefined)
        for i in range(v.count):
            agg = builder.insert_value(agg, builder.extract_element(args[0], ir.Constant(_I32, i)), i)
        return agg
    return tup(v), codegen


@intrinsic
def fill(typingctx, like, x):
    """A lane vector of ``like``'s type with every lane ``x`` (float64)."""
    if not isinstance(like, VecType) or x != types.float64:
        raise numba.core.errors.TypingError(f"fill takes a lane vector and a float64, got {like}, {x}")

    def codegen(context, builder, sig, args):
        vec = ir.Constant(ir.VectorType(ir.DoubleType(), like.count), ir.Undefined)
        for i in range(like.count):
            vec = builder.insert_element(vec, args[1], ir.Constant(_I32, i))
        return vec
    return like(like, x), codegen


def _check_array(arr, ndim, dtype=types.float64):
    if not (isinstance(arr, types.Array) and arr.ndim == ndim and arr.dtype == dtype):
        raise numba.core.errors.TypingError(f"expected a {ndim}-D {dtype} array, got {arr}")


def _check_ints(*tys):
    for ty in tys:
        if not isinstance(ty, types.Integer):
            raise numba.core.errors.TypingError(f"expected an integer index, got {ty}")


@intrinsic
def take(typingctx, arr, rows, col):
    """Lane vector ``(arr[rows[0], col], …, arr[rows[n-1], col])`` of a 2-D float64 array (no bounds check)."""
    _check_array(arr, 2)
    n = _rows_of(rows)
    _check_ints(col)

    def codegen(context, builder, sig, args):
        c = context.cast(builder, args[2], sig.args[2], types.intp)
        vec = ir.Constant(ir.VectorType(ir.DoubleType(), n), ir.Undefined)
        for j, r in enumerate(_index_values(context, builder, sig.args, args, 1)):
            x = builder.load(_element_ptr(context, builder, sig.args[0], args[0], [r, c]))
            vec = builder.insert_element(vec, x, ir.Constant(_I32, j))
        return vec
    return VecType(n)(arr, rows, col), codegen


@intrinsic
def take1(typingctx, arr, rows):
    """Lane vector ``(arr[rows[0]], …, arr[rows[n-1]])`` of a 1-D float64 array (no bounds check)."""
    _check_array(arr, 1)
    n = _rows_of(rows)

    def codegen(context, builder, sig, args):
        vec = ir.Constant(ir.VectorType(ir.DoubleType(), n), ir.Undefined)
        for j, r in enumerate(_index_values(context, builder, sig.args, args, 1)):
            x = builder.load(_element_ptr(context, builder, sig.args[0], args[0], [r]))
            vec = builder.insert_element(vec, x, ir.Constant(_I32, j))
        return vec
    return VecType(n)(arr, rows), codegen


@intrinsic
def put1(typingctx, arr, rows, v):
    """``arr[rows[j]] = v[j]`` for every lane, in lane order (1-D float64 array, no bounds check)."""
    _check_array(arr, 1)
    n = _rows_of(rows)
    if v != VecType(n):
        raise numba.core.errors.TypingError(f"put1 takes a Vec{n}(float64) value, got {v}")

    def codegen(context, builder, sig, args):
        for j, r in enumerate(_index_values(context, builder, sig.args, args, 1)):
            x = builder.extract_element(args[2], ir.Constant(_I32, j))
            builder.store(x, _element_ptr(context, builder, sig.args[0], args[0], [r]))
        return context.get_dummy_value()
    return types.none(arr, rows, v), codegen


@intrinsic
def take3(typingctx, arr, rows, k, i):
    """Lane vector ``(arr[rows[j], k, i])_j`` of a 3-D float64 array (no bounds check)."""
    _check_array(arr, 3)
    n = _rows_of(rows)
    _check_ints(k, i)

    def codegen(context, builder, sig, args):
        kk = context.cast(builder, args[2], sig.args[2], types.intp)
        ii = context.cast(builder, args[3], sig.args[3], types.intp)
        vec = ir.Constant(ir.VectorType(ir.DoubleType(), n), ir.Undefined)
        for j, r in enumerate(_index_values(context, builder, sig.args, args, 1)):
            x = builder.load(_element_ptr(context, builder, sig.args[0], args[0], [r, kk, ii]))
            vec = builder.insert_element(vec, x, ir.Constant(_I32, j))
        return vec
    return VecType(n)(arr, rows, k, i), codegen


@intrinsic
def put(typingctx, arr, rows, col, v):
    """``arr[rows[j], col] = v[j]`` for every lane, in lane order (2-D float64 array, no bounds check)."""
    _check_array(arr, 2)
    n = _rows_of(rows)
    _check_ints(col)
    if v != VecType(n):
        raise numba.core.errors.TypingError(f"put takes a Vec{n}(float64) value, got {v}")

    def codegen(context, builder, sig, args):
        c = context.cast(builder, args[2], sig.args[2], types.intp)
        for j, r in enumerate(_index_values(context, builder, sig.args, args, 1)):
            x = builder.extract_element(args[3], ir.Constant(_I32, j))
            builder.store(x, _element_ptr(context, builder, sig.args[0], args[0], [r, c]))
        return context.get_dummy_value()
    return types.none(arr, rows, col, v), codegen


@intrinsic
def put3(typingctx, arr, rows, k, i, v):
    """``arr[rows[j], k, i] = v[j]`` for every lane, in lane order (3-D float64 array, no bounds check)."""
    _check_array(arr, 3)
    n = _rows_of(rows)
    _check_ints(k, i)
    if v != VecType(n):
        raise numba.core.errors.TypingError(f"put3 takes a Vec{n}(float64) value, got {v}")

    def codegen(context, builder, sig, args):
        kk = context.cast(builder, args[2], sig.args[2], types.intp)
        ii = context.cast(builder, args[3], sig.args[3], types.intp)
        for j, r in enumerate(_index_values(context, builder, sig.args, args, 1)):
            x = builder.extract_element(args[4], ir.Constant(_I32, j))
            builder.store(x, _element_ptr(context, builder, sig.args[0], args[0], [r, kk, ii]))
        return context.get_dummy_value()
    return types.none(arr, rows, k, i, v), codegen


@intrinsic
def choose(typingctx, flags, rows, k, a, b):
    """Lane vector ``(a if flags[rows[j], k] else b)_j`` of a 2-D boolean array and two float64 scalars."""
    _check_array(flags, 2, types.boolean)
    n = _rows_of(rows)
    _check_ints(k)
    if a != types.float64 or b != types.float64:
        raise numba.core.errors.TypingError(f"choose takes float64 alternatives, got {a}, {b}")

    def codegen(context, builder, sig, args):
        kk = context.cast(builder, args[2], sig.args[2], types.intp)
        vec = ir.Constant(ir.VectorType(ir.DoubleType(), n), ir.Undefined)
        for j, r in enumerate(_index_values(context, builder, sig.args, args, 1)):
            raw = builder.load(_element_ptr(context, builder, sig.args[0], args[0], [r, kk]))
            flag = context.data_model_manager[types.boolean].from_data(builder, raw)
            vec = builder.insert_element(vec, builder.select(flag, args[3], args[4]), ir.Constant(_I32, j))
        return vec
    return VecType(n)(flags, rows, k, a, b), codegen


def _per_lane(fn):
    @intrinsic
    def lanewise(typingctx, v):
        if not isinstance(v, VecType):
            raise numba.core.errors.TypingError(f"expected a lane vector, got {v}")

        def codegen(context, builder, sig, args):
            impl = context.get_function(fn, types.float64(types.float64))
            vec = ir.Constant(ir.VectorType(ir.DoubleType(), v.count), ir.Undefined)
            for j in range(v.count):
                x = impl(builder, [builder.extract_element(args[0], ir.Constant(_I32, j))])
                vec = builder.insert_element(vec, x, ir.Constant(_I32, j))
            return vec
        return v(v), codegen
    return lanewise


def _all(pred: str):
    @intrinsic
    def fn(typingctx, x, y):
        if not (_all_vec(x, y) and isinstance(x, VecType)):
            raise numba.core.errors.TypingError(f"expected two lane vectors, got {x}, {y}")

        def codegen(context, builder, sig, args):
            mask = builder.fcmp_ordered(pred, args[0], args[1])
            bits = builder.bitcast(mask, ir.IntType(x.count))
            return builder.icmp_unsigned("==", bits, ir.Constant(ir.IntType(x.count), (1 << x.count) - 1))
        return types.boolean(x, y), codegen
    return fn


#: True when ``x[j] <= y[j]`` for every lane (ordered: False for a lane with a NaN operand).
all_le = _all("<=")
#: True when ``x[j] < y[j]`` for every lane (ordered: False for a lane with a NaN operand).
all_lt = _all("<")


@intrinsic
def put_lt(typingctx, flags, rows, col, x, y):
    """``flags[rows[j], col] = x[j] < y[j]`` for every lane, in lane order (2-D boolean array, ordered ``<``)."""
    _check_array(flags, 2, types.boolean)
    n = _rows_of(rows)
    _check_ints(col)
    if x != VecType(n) or y != VecType(n):
        raise numba.core.errors.TypingError(f"put_lt takes two Vec{n}(float64) values, got {x}, {y}")

    def codegen(context, builder, sig, args):
        c = context.cast(builder, args[2], sig.args[2], types.intp)
        mask = builder.fcmp_ordered("<", args[3], args[4])
        for j, r in enumerate(_index_values(context, builder, sig.args, args, 1)):
            bit = builder.extract_element(mask, ir.Constant(_I32, j))
            raw = context.data_model_manager[types.boolean].as_data(builder, bit)
            builder.store(raw, _element_ptr(context, builder, sig.args[0], args[0], [r, c]))
        return context.get_dummy_value()
    return types.none(flags, rows, col, x, y), codegen


@intrinsic
def lane_ids(typingctx, v):
    """``(0, 1, …, n-1)`` (a UniTuple of intp constants) for a lane vector of ``n`` lanes: rows of a
    (n, k) scratch array for :func:`take` / :func:`put` (a vector spilled for per-lane scalar code)."""
    if not isinstance(v, VecType):
        raise numba.core.errors.TypingError(f"lane_ids takes a lane vector, got {v}")
    tup = types.UniTuple(types.intp, v.count)

    def codegen(context, builder, sig, args):
        return context.make_tuple(builder, tup, [context.get_constant(types.intp, j) for j in range(v.count)])
    return tup(v), codegen


#: Per lane ``math.cos`` / ``math.sin``: numba's scalar lowering of each (the same libm calls as scalar code).
cos = _per_lane(math.cos)
sin = _per_lane(math.sin)


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


def simd_lanes() -> int:
    """Trials per SIMD block of the batched kernels: 8 (one AVX-512 register) when numba compiles for this
    host and it has AVX-512F, else 4 (one AVX2 register, or 2 × SSE2 on the pinned ``generic`` target).
    Every trial's arithmetic is the same for any block size (bit-identical results); only the speed differs."""
    if numba.config.CPU_NAME not in (None, "host") or numba.config.CPU_FEATURES:
        return 4
    try:
        from llvmlite import binding

        return 8 if binding.get_host_cpu_features().get("avx512f", False) else 4
    except Exception:  # pragma: no cover - llvmlite without host feature detection
        return 4


@_inl
def rows4(t0, nl):
    """Trial rows of a block of 4 lanes starting at ``t0`` with ``nl`` real trials (the rest repeat the last)."""
    return (t0, t0 + min(1, nl - 1), t0 + min(2, nl - 1), t0 + min(3, nl - 1))


@_inl
def rows8(t0, nl):
    """Trial rows of a block of 8 lanes (see :func:`rows4`)."""
    return (t0, t0 + min(1, nl - 1), t0 + min(2, nl - 1), t0 + min(3, nl - 1), t0 + min(4, nl - 1),
            t0 + min(5, nl - 1), t0 + min(6, nl - 1), t0 + min(7, nl - 1))
