"""Shared numba plumbing of the compiled filter kernels (private).

``jit`` is :func:`mtcal.core.compiled.jit` (``numba.njit(cache=True)`` that compiles
uncached when no cache directory is writable; numba's settings are made there, before
numba loads). Kernels are float64, never ``fastmath``, so their arithmetic is the numpy
reference's operation by operation. Here: the ``engine=`` check, the parallel-kernel
switch and the fast input checks of the records the kernels read.

The engine used by the public filters is chosen by ``engine=`` arguments:
``"numba"`` (default) or ``"numpy"`` (the readable reference implementations).
"""

from __future__ import annotations

import sys
import threading

import numba
import numpy as np
from numba import prange
from numba.core import types
from numba.extending import intrinsic

from mtcal.core.compiled import jit
from mtcal.core.validate import MAX_GYRO_RAD_S, MIN_MEDIAN_ACCEL_M_S2, float64_array

__all__ = ["jit", "ENGINES", "check_engine", "use_parallel", "fetch_add", "claim", "schedule", "record",
           "check_scanned", "check_kernel_scan", "OutputPool", "RECYCLE_MIN_BYTES"]

ENGINES = ("numba", "numpy")


def check_engine(engine: str) -> str:
    """Validate an ``engine=`` argument ("numba" or "numpy")."""
    if engine not in ENGINES:
        raise ValueError(f"engine must be one of {ENGINES}, got {engine!r}")
    return engine


#: Work (trial-samples) from which the trial-parallel (prange) kernels are used: below it a
#: parallel region costs more than it saves.
PARALLEL_MIN_WORK = 200_000


#: Whether ``sys.getrefcount`` counts every holder (CPython): elsewhere :class:`OutputPool` never reuses.
_COUNTS_REFERENCES = sys.implementation.name == "cpython"

#: Output histories at least this large (bytes) are recycled by :class:`OutputPool`.
RECYCLE_MIN_BYTES = 16 << 20


class OutputPool:
    """The large output arrays of a filter's last call, handed out again once nobody else holds them.

    A batched call writes every element of its (T, M, …) histories, so an array the caller has
    dropped can take the next call's results instead of a fresh allocation. Fresh memory is paid
    for by first-touch page faults inside the parallel kernel (zeroing, and on a VM host faults:
    0.03-0.9 s per 400 MB measured on the 2-vCPU bench machine, ~4x the CPU when two threads fault
    at once), as much as the filtering itself at 1000 trials x 10 s. Reuse needs the exact shape and
    that the pool's reference is the only one (``sys.getrefcount``: no result, view or alias of the
    array is alive; compared with the count of an object only the pool's frame holds, so an
    interpreter that borrows references counts both alike; not CPython: never reused), so a result
    the caller still holds is never overwritten. At most one array per role is retained between
    calls (freed by the next call that cannot reuse it, or by :meth:`clear`).
    """

    def __init__(self, min_bytes: int | None = None) -> None:
        self._slots: dict = {}
        self._lock = threading.Lock()
        self._min_bytes = min_bytes

    def take(self, role: str, shape: tuple) -> np.ndarray:
        """A float64 array of ``shape``: the retained one for ``role`` if free and of that shape, else new."""
        with self._lock:
            arr = self._slots.pop(role, None)
        probe = object()                    # held by this frame only: the count of an array nobody else holds
        if arr is not None and arr.shape == tuple(shape) and _COUNTS_REFERENCES and (
                sys.getrefcount(arr) == sys.getrefcount(probe)):  # any other holder (result, view's base) adds one
            return arr
        del arr
        return np.empty(shape)

    def keep(self, role: str, arr: np.ndarray) -> None:
        """Retain ``arr`` (just returned to a caller) for ``role`` when it is large enough to be worth it
        (``min_bytes`` of the pool; None: :data:`RECYCLE_MIN_BYTES`)."""
        if arr.nbytes >= (RECYCLE_MIN_BYTES if self._min_bytes is None else self._min_bytes):
            with self._lock:
                self._slots[role] = arr

    def clear(self) -> None:
        """Drop every retained array."""
        with self._lock:
            self._slots.clear()


@intrinsic
def fetch_add(typingctx, counter, step):
    """Atomically ``old = counter[0]; counter[0] += step``; returns ``old`` (1-D int64 array, sequentially
    consistent). Threads of a ``prange`` loop take work items from a shared counter this way: a real
    dynamic schedule (numba's OpenMP layer hands out ``prange`` iterations in fixed contiguous shares, whatever
    :func:`numba.set_parallel_chunksize` says, so one thread slowed by other load holds half the work)."""
    if not (isinstance(counter, types.Array) and counter.ndim == 1 and counter.dtype == types.int64):
        raise numba.core.errors.TypingError(f"fetch_add needs a 1-D int64 array, got {counter}")
    if not isinstance(step, types.Integer):
        raise numba.core.errors.TypingError(f"fetch_add step must be an integer, got {step}")

    def codegen(context, builder, sig, args):
        ary = context.make_array(sig.args[0])(context, builder, args[0])
        inc = context.cast(builder, args[1], sig.args[1], types.int64)
        return builder.atomic_rmw("add", ary.data, inc, "seq_cst")
    return types.int64(counter, step), codegen


@numba.njit(inline="always")
def claim(counters, v, lo, hi, own):
    """The next block of range ``v`` = blocks ``[lo, hi)`` for a worker, or -1 when none is left.

    ``counters`` (3 W,) int64, zeros at the start: per range the blocks claimed, taken from the front
    (by the range's own worker, ``own``) and taken from the back (by the others once their own range is
    done). A claim first counts itself against the range's size, so front and back never meet: every
    block is handed out once. The owner walks its range in order and a helper starts at the far end,
    so two threads seldom write neighbouring rows at the same time (first-touch page faults of the same
    huge page from two threads cost the bench VM ~10x the CPU of one thread's).
    """
    w = counters.size // 3
    if fetch_add(counters[v:v + 1], 1) >= hi - lo:
        return -1
    if own:
        return lo + fetch_add(counters[w + v:w + v + 1], 1)
    return hi - 1 - fetch_add(counters[2 * w + v:2 * w + v + 1], 1)


def schedule(workers: int) -> np.ndarray:
    """Zeroed counters of :func:`claim` for ``workers`` ranges."""
    return np.zeros(3 * workers, np.int64)


def use_parallel(trials: int, samples: int) -> bool:
    """Whether to run the trial-parallel kernel (≥ 2 trials, enough work, > 1 numba thread)."""
    return trials >= 2 and trials * samples >= PARALLEL_MIN_WORK and numba.get_num_threads() > 1


# ----------------------------------------------------------------------------- fast input checks

_BLOCKS = 16


@jit(parallel=True)
def _finite_max_abs(flat):
    """(all finite, max |x|) of a 1-D array in one pass, blocks spread over threads."""
    n = flat.size
    size = (n + _BLOCKS - 1) // _BLOCKS
    oks = np.ones(_BLOCKS, np.bool_)
    mxs = np.zeros(_BLOCKS)
    for b in prange(_BLOCKS):
        oks[b], mxs[b] = _scan(flat, b * size, min((b + 1) * size, n))
    return oks.all(), mxs.max()


@jit()
def _finite_max_abs_serial(flat):
    """Serial :func:`_finite_max_abs` (small arrays: no thread start-up)."""
    return _scan(flat, 0, flat.size)


@numba.njit(inline="always")
def _scan(flat, lo, hi):
    """(all finite, max |v|) over ``flat[lo:hi]``, one pass."""
    ok = True
    mx = 0.0
    for i in range(lo, hi):
        v = flat[i]
        if not np.isfinite(v):
            ok = False
        av = abs(v)
        if av > mx:
            mx = av
    return ok, mx


@jit()
def _row_norms(x2, step):
    """‖x2[i]‖ for every ``step``-th row of an (R, 3) array."""
    n = (x2.shape[0] + step - 1) // step
    out = np.empty(n)
    for i in range(n):
        r = i * step
        out[i] = np.sqrt((x2[r, 0] * x2[r, 0] + x2[r, 1] * x2[r, 1]) + x2[r, 2] * x2[r, 2])
    return out


def record(value, name: str, ndim: tuple, kind: str | None = None, scan: bool = True) -> np.ndarray:
    """Float64 C-contiguous view/copy of a (…, 3) record, checked like ``validate.as_float_array``
    (same messages) plus the gyro (``kind="gyro"``) or accelerometer (``kind="accel"``) unit
    checks of :mod:`mtcal.core.validate`, in one compiled pass instead of several numpy passes.

    ``scan=False`` checks type and shape only: the caller's kernel scans the values while it
    filters and calls :func:`check_scanned` before it keeps any result.
    """
    arr = float64_array(value, name, contiguous=True)
    if arr.ndim not in ndim:
        raise ValueError(f"{name} must have ndim in {tuple(ndim)}, got shape {arr.shape}")
    if arr.ndim == 0 or arr.shape[-1] != 3:
        raise ValueError(f"{name} must have last dimension 3, got shape {arr.shape}")
    if arr.size == 0:
        raise ValueError(f"{name} must not be empty, got shape {arr.shape}")
    if scan:
        flat1 = arr.reshape(-1)
        ok, max_abs = (_finite_max_abs if flat1.size >= 4_000_000 else _finite_max_abs_serial)(flat1)
        check_scanned(arr, name, kind, ok, max_abs)
    return arr


def check_scanned(arr: np.ndarray, name: str, kind: str | None, finite: bool, max_abs: float) -> None:
    """The value checks of :func:`record` from a finished scan (all finite, max |x|) of ``arr``."""
    if not finite:
        raise ValueError(f"{name} must be finite (no NaN or inf)")
    if kind == "gyro" and max_abs > MAX_GYRO_RAD_S:
        raise ValueError(f"{name} must be in rad/s; max |{name}| = {max_abs:.4g} "
                         f"exceeds {MAX_GYRO_RAD_S:g} rad/s (degrees per second passed as rad/s?)")
    if kind == "accel" and arr.ndim >= 2 and arr.shape[-2] > 1:  # one sample may be small: judge records only
        flat = arr.reshape(-1, 3)
        med = float(np.median(_row_norms(flat, max(1, flat.shape[0] // 20_000))))
        if 0.0 < med < MIN_MEDIAN_ACCEL_M_S2:
            raise ValueError(f"{name} looks like it is in g, not m/s² (median |a| = {med:.4g} < "
                             f"{MIN_MEDIAN_ACCEL_M_S2:g} m/s²); multiply by 9.80665")


def check_kernel_scan(chk: np.ndarray, gyro: np.ndarray, accel: np.ndarray, accel_units: bool) -> None:
    """Raise like :func:`record` from a kernel's per-trial scan ``chk`` (T, 4) = (Σ 0·gyro, max |gyro|,
    Σ 0·accel, number of samples with |a| < MIN_MEDIAN_ACCEL_M_S2): a sum is 0 exactly when every
    value was finite (inf·0 and NaN·0 are NaN); with no low sample the median |a| cannot be low, so
    the (exact, strided-subset) median check of ``validate.check_accel_units`` runs only otherwise."""
    check_scanned(gyro, "gyro_rad_s", "gyro", bool(np.all(chk[:, 0] == 0.0)), float(chk[:, 1].max()))
    units = accel_units and bool(np.any(chk[:, 3] > 0.0))
    check_scanned(accel, "accel_m_s2", "accel" if units else None, bool(np.all(chk[:, 2] == 0.0)), 0.0)

