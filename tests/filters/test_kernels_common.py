"""Tests of mtcal.filters._kernels_common.OutputPool (recycled output histories of the batched filters)."""

import weakref

import numpy as np
import pytest

from mtcal.filters import _kernels_common
from mtcal.filters._kernels_common import OutputPool


@pytest.fixture
def pool(monkeypatch):
    """A pool that keeps arrays of any size."""
    monkeypatch.setattr(_kernels_common, "RECYCLE_MIN_BYTES", 0)
    return OutputPool()


def test_dropped_array_is_reused(pool):
    arr = pool.take("theta", (3, 5))
    pool.keep("theta", arr)
    ref = weakref.ref(arr)
    del arr
    again = pool.take("theta", (3, 5))
    assert ref() is again and again.shape == (3, 5) and again.dtype == np.float64


@pytest.mark.parametrize("holder", ["array", "view", "other shape", "other role"])
def test_array_still_held_or_unfit_is_not_reused(pool, holder):
    arr = pool.take("theta", (3, 5))
    arr[:] = 7.0
    pool.keep("theta", arr)
    held = {"array": arr, "view": arr[1:]}.get(holder)
    ref = weakref.ref(arr)
    del arr
    shape = (5, 3) if holder == "other shape" else (3, 5)
    got = pool.take("bias" if holder == "other role" else "theta", shape)
    got[:] = -1.0
    assert ref() is not got
    if held is not None:
        assert np.all(held == 7.0)           # what the caller holds is never overwritten


def test_small_arrays_are_not_retained_and_clear_drops(monkeypatch):
    p = OutputPool()
    small = p.take("theta", (2, 2))
    p.keep("theta", small)                    # below RECYCLE_MIN_BYTES: not retained
    assert p._slots == {}
    monkeypatch.setattr(_kernels_common, "RECYCLE_MIN_BYTES", 0)
    p.keep("theta", small)
    assert set(p._slots) == {"theta"}
    p.clear()
    assert p._slots == {}


def test_fetch_add_hands_out_every_item_once_across_threads():
    import numba
    from numba import prange

    from mtcal.filters._kernels_common import fetch_add

    @numba.njit(parallel=True)
    def take_all(counter, owner, workers):
        for w in prange(workers):
            i = fetch_add(counter, 1)
            while i < owner.size:
                owner[i] += 1 + w
                i = fetch_add(counter, 1)

    counter = np.zeros(1, np.int64)
    owner = np.zeros(5000, np.int64)
    take_all(counter, owner, max(2, numba.get_num_threads()))
    assert np.all(owner >= 1) and counter[0] >= owner.size           # every item taken, by exactly one worker
    assert np.all(owner <= max(2, numba.get_num_threads()))


def test_fetch_add_rejects_other_types():
    import numba

    from mtcal.filters._kernels_common import fetch_add

    @numba.njit
    def bump(counter):
        return fetch_add(counter, 1)

    assert bump(np.array([41], np.int64)) == 41
    with pytest.raises(numba.core.errors.TypingError, match="1-D int64 array"):
        bump(np.zeros(1))


def test_no_reuse_where_reference_counts_say_nothing(pool, monkeypatch):
    monkeypatch.setattr(_kernels_common, "_COUNTS_REFERENCES", False)
    arr = pool.take("theta", (3, 5))
    pool.keep("theta", arr)
    ref = weakref.ref(arr)
    del arr
    assert ref() is not pool.take("theta", (3, 5))


@pytest.mark.parametrize("blocks, workers, present", [(125, 2, 2), (7, 2, 2), (1, 2, 2), (10, 3, 1), (0, 2, 2)])
def test_claim_hands_out_every_block_once(blocks, workers, present):
    """Ranges split among ``workers``; only ``present`` of them run (numba may start fewer): still every block
    exactly once, the owner front to back, helpers from the far end."""
    import numba
    from numba import prange

    from mtcal.filters._kernels_common import claim, schedule

    @numba.njit(parallel=True)
    def run(counter, taken, order, workers, present):
        nb = taken.size
        for w in prange(present):
            n = 0
            for j in range(workers):
                r = (w + j) % workers
                lo, hi = r * nb // workers, (r + 1) * nb // workers
                b = claim(counter, r, lo, hi, j == 0)
                while b >= 0:
                    taken[b] += 1
                    order[w, n] = b
                    n += 1
                    b = claim(counter, r, lo, hi, j == 0)

    taken = np.zeros(blocks, np.int64)
    order = np.full((present, blocks + 1), -1)
    run(schedule(workers), taken, order, workers, present)
    assert np.all(taken == 1)
    first = order[0][order[0] >= 0]
    own = first[: blocks // workers]
    assert np.array_equal(own, np.arange(own.size))          # worker 0 walks its own range in order first


def test_a_pool_may_set_its_own_size_threshold():
    p = OutputPool(min_bytes=64)
    p.keep("q", np.empty(4))                  # 32 bytes: below the pool's 64
    assert p._slots == {}
    big = np.empty(8)
    p.keep("q", big)
    assert p._slots["q"] is big
