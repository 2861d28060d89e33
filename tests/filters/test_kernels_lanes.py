"""Lane-vector helpers of the batched kernels (mtcal.filters._kernels_lanes).

Every lane operation must be the scalar IEEE-754 operation bit for bit (the batched
filters promise results identical to one trial run alone), for tuples and for the
``VecType`` vectors (4 and 8 lanes); gathers and scatters must address the rows given.
"""

import math

import numba
import numpy as np
import pytest
from numba.core.errors import TypingError

from mtcal.filters._kernels_lanes import (add, all_le, all_lt, choose, cos, div, fabs, fill, lane_ids, mul, pack, put,
                                          put1, put3, put_lt, rows4, rows8, simd_lanes, sin, sqrt, sub, take, take1,
                                          take3, unpack, vmax, where_le, where_lt)


@numba.njit
def _ops4(x, y):
    a = pack((x[0], x[1], x[2], x[3]))
    b = pack((y[0], y[1], y[2], y[3]))
    return (unpack(add(a, b)), unpack(sub(a, b)), unpack(mul(a, b)), unpack(div(a, b)), unpack(sqrt(fabs(a))),
            unpack(vmax(a, b)), unpack(where_lt(a, b, a, b)), unpack(where_le(a, b, fill(a, 1.0), fill(a, 0.0))),
            unpack(cos(a)), unpack(sin(a)))


@numba.njit
def _ops8(x, y):
    a = pack((x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7]))
    b = pack((y[0], y[1], y[2], y[3], y[4], y[5], y[6], y[7]))
    return (unpack(add(a, b)), unpack(sub(a, b)), unpack(mul(a, b)), unpack(div(a, b)), unpack(sqrt(fabs(a))),
            unpack(vmax(a, b)), unpack(where_lt(a, b, a, b)), unpack(where_le(a, b, fill(a, 1.0), fill(a, 0.0))),
            unpack(cos(a)), unpack(sin(a)))


@numba.njit(error_model="numpy")   # x / 0 is IEEE inf/NaN, as in the vector lanes
def _scalar_ops(x, y):
    return (x + y, x - y, x * y, x / y, math.sqrt(abs(x)), max(x, y), x if x < y else y, 1.0 if x <= y else 0.0,
            math.cos(x), math.sin(x))


@pytest.mark.parametrize("lanes", [4, 8])
def test_vector_lanes_equal_the_scalar_operations_bit_for_bit(lanes):
    rng = np.random.default_rng(3)
    x = rng.normal(0.0, 2.0, 64)
    y = rng.normal(0.0, 2.0, 64)
    x[:4] = [np.nan, 1.0, -0.0, 3.0]        # NaN and signed-zero semantics of max and the comparisons
    y[:4] = [1.0, np.nan, 0.0, 3.0]
    ops = _ops4 if lanes == 4 else _ops8
    for i in range(0, 64, lanes):
        got = ops(x[i:i + lanes], y[i:i + lanes])
        for j in range(lanes):
            want = _scalar_ops(x[i + j], y[i + j])
            for k, (g, w) in enumerate(zip(got, want)):
                assert np.array_equal(np.float64(g[j]), np.float64(w), equal_nan=True), (i + j, k)
                assert math.copysign(1.0, g[j]) == math.copysign(1.0, w) or math.isnan(w), (i + j, k)


@numba.njit
def _gather_scatter(x2, x3, x1, flags, rows, k):
    a = take(x2, rows, 1)
    b = take3(x3, rows, k, 2)
    c = take1(x1, rows)
    d = choose(flags, rows, k, 10.0, 20.0)
    out2 = np.zeros(x2.shape)
    out3 = np.zeros(x3.shape)
    out1 = np.zeros(x1.shape)
    put(out2, rows, 1, a)
    put3(out3, rows, k, 2, b)
    put1(out1, rows, c)
    return unpack(a), unpack(b), unpack(c), unpack(d), out2, out3, out1


@pytest.mark.parametrize("rows", [(0, 2, 4, 4), (5, 4, 3, 2, 1, 0, 0, 0)])
def test_gathers_and_scatters_address_the_given_rows(rows):
    rng = np.random.default_rng(4)
    x2 = rng.normal(size=(6, 3))
    x3 = rng.normal(size=(6, 5, 3))
    x1 = rng.normal(size=6)
    flags = rng.random((6, 5)) < 0.5
    a, b, c, d, out2, out3, out1 = _gather_scatter(x2, x3, x1, flags, rows, 3)
    r = list(rows)
    assert np.array_equal(a, x2[r, 1]) and np.array_equal(b, x3[r, 3, 2]) and np.array_equal(c, x1[r])
    assert np.array_equal(d, np.where(flags[r, 3], 10.0, 20.0))
    touched = sorted(set(r))
    assert np.array_equal(out2[touched, 1], x2[touched, 1]) and not out2[:, [0, 2]].any()
    assert np.array_equal(out3[touched, 3, 2], x3[touched, 3, 2]) and np.count_nonzero(out3) == len(touched)
    assert np.array_equal(out1[touched], x1[touched]) and np.count_nonzero(out1) == len(touched)


@numba.njit
def _reductions(x2, rows):
    a, b = take(x2, rows, 0), take(x2, rows, 1)
    flags = np.zeros((x2.shape[0], 2), np.bool_)
    put_lt(flags, rows, 1, a, b)
    spill = np.zeros((len(rows), 1))
    put(spill, lane_ids(a), 0, a)
    return all_le(a, b), all_lt(a, b), flags, spill, lane_ids(a)


@pytest.mark.parametrize("rows", [(0, 1, 2, 3), (7, 6, 5, 4, 3, 2, 1, 0)])
def test_all_lane_tests_put_lt_and_lane_ids(rows):
    """all_le / all_lt are the scalar ordered comparisons of every lane (one NaN lane: False), put_lt stores
    each lane's ``<`` at its row, lane_ids addresses a (lanes, k) scratch array."""
    x2 = np.zeros((8, 2))
    x2[:, 0] = np.arange(8.0)
    x2[:, 1] = np.arange(8.0) + 1.0
    assert _reductions(x2, rows)[:2] == (True, True)
    x2[rows[-1], 1] = x2[rows[-1], 0]         # equal in one lane: <= still holds, < does not
    le, lt, flags, spill, ids = _reductions(x2, rows)
    assert (le, lt) == (True, False)
    r = list(rows)
    assert np.array_equal(flags[r, 1], x2[r, 0] < x2[r, 1]) and not flags[:, 0].any()
    assert ids == tuple(range(len(rows))) and np.array_equal(spill[:, 0], x2[r, 0])
    x2[rows[1], 1] = np.nan
    le, lt, flags, _, _ = _reductions(x2, rows)
    assert (le, lt) == (False, False) and not flags[rows[1], 1]


@numba.njit
def _rows(t0, nl):
    return rows4(t0, nl), rows8(t0, nl)


def test_block_rows_repeat_the_last_trial_and_lane_count():
    assert _rows(8, 4) == ((8, 9, 10, 11), (8, 9, 10, 11, 11, 11, 11, 11))
    assert _rows(3, 2) == ((3, 4, 4, 4), (3, 4, 4, 4, 4, 4, 4, 4))
    assert simd_lanes() in (4, 8)
    if numba.config.CPU_NAME == "generic":
        assert simd_lanes() == 4     # the pinned target: 4 lanes (results are the same for either width)


@numba.njit
def _all_tuple(x):
    return all_le((x[0], x[1], x[2], x[3]), (x[0], x[1], x[2], x[3]))


@numba.njit
def _put_lt_width(x2):
    flags = np.zeros((4, 2), np.bool_)
    put_lt(flags, (0, 1, 2, 3), 0, pack((1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0)),
           pack((1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0)))


@numba.njit
def _lane_ids_tuple(x):
    return lane_ids((x[0], x[1], x[2], x[3]))


@numba.njit
def _mixed(x):
    return add(pack((x[0], x[1], x[2], x[3])), (x[0], x[1], x[2], x[3]))


@numba.njit
def _widths(x):
    return add(pack((x[0], x[1], x[2], x[3])), pack((x[0], x[1], x[2], x[3], x[0], x[1], x[2], x[3])))


@numba.njit
def _pack3(x):
    return pack((x[0], x[1], x[2]))


@numba.njit
def _take_rows3(x2):
    return take(x2, (0, 1, 2), 0)


@numba.njit
def _put_width(x2):
    put(x2, (0, 1, 2, 3), 0, pack((1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0)))


@numba.njit
def _take_1d(x1):
    return take(x1, (0, 1, 2, 3), 0)


@pytest.mark.parametrize("fn, arg, message", [
    (_mixed, np.ones(4), "lane vectors of one vector type expected"),
    (_widths, np.ones(4), "lane vectors of one vector type expected"),
    (_pack3, np.ones(4), r"expected a UniTuple\(float64, 4 or 8\)"),
    (_take_rows3, np.ones((4, 3)), "rows must be a UniTuple of 4 or 8 integers"),
    (_put_width, np.ones((4, 3)), r"put takes a Vec4\(float64\) value"),
    (_take_1d, np.ones(4), "expected a 2-D float64 array"),
    (_all_tuple, np.ones(4), "expected two lane vectors"),
    (_put_lt_width, np.ones((4, 3)), r"put_lt takes two Vec4\(float64\) values"),
    (_lane_ids_tuple, np.ones(4), "lane_ids takes a lane vector"),
])
def test_misuse_is_a_typing_error(fn, arg, message):
    with pytest.raises(TypingError, match=message):
        fn(arg)
