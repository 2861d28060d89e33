"""Shared numba plumbing of the compiled filter kernels (private).

``jit(...)`` is ``numba.njit(cache=True, ...)`` that degrades gracefully: when
no cache locator can write (read-only install and no writable user cache
directory), numba raises at decoration time; the function is then compiled
without caching instead of failing the import. Kernels are float64, never
``fastmath`` (no reassociation, no FMA contraction), so their arithmetic is the
numpy reference's operation by operation.

The engine used by the public filters is chosen by ``engine=`` arguments:
``"numba"`` (default) or ``"numpy"`` (the readable reference implementations).
"""

from __future__ import annotations

import os
import tempfile
import warnings

__all__ = ["jit", "ENGINES", "check_engine", "use_parallel", "record", "check_scanned", "check_kernel_scan"]

ENGINES = ("numba", "numpy")

if not os.environ.get("NUMBA_CACHE_DIR"):
    # numba falls back from the package's __pycache__ to a user-wide cache dir on its own; if neither is
    # writable, point it at a temporary directory before numba reads its config (mtcal.core.simulate,
    # usually imported first, does the same); if numba was configured already, jit() still falls back
    # to compiling without a cache
    _here, _home = os.path.dirname(os.path.abspath(__file__)), os.path.expanduser("~")
    _home_cache = os.path.join(_home, ".cache")
    if not os.access(_here, os.W_OK) and not os.access(_home_cache if os.path.isdir(_home_cache) else _home,
                                                       os.W_OK):
        os.environ["NUMBA_CACHE_DIR"] = os.path.join(tempfile.gettempdir(), "mtcal-numba-cache")

# numba's OpenMP threading layer spins its workers after every parallel region (GNU OpenMP's active
# wait policy); on a loaded machine a spinning worker steals the core the next region or the serial
# code needs (measured: a 0.2 ms parallel pass took 17 ms with one busy core). Passive waiting,
# unless the user chose otherwise; it must be set before the OpenMP runtime starts.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

import numba  # noqa: E402


def jit(parallel: bool = False):
    """Decorator: ``numba.njit(cache=True, parallel=parallel)``, or uncached if caching is impossible."""
    def deco(fn):
        try:
            return numba.njit(cache=True, parallel=parallel, nogil=True)(fn)
        except RuntimeError as exc:  # "cannot cache function ...: no locator available"
            warnings.warn(f"numba cannot cache {fn.__name__} ({exc}); compiling without a cache",
                          RuntimeWarning, stacklevel=2)
            return numba.njit(cache=False, parallel=parallel, nogil=True)(fn)
    return deco


def check_engine(engine: str) -> str:
    """Validate an ``engine=`` argument ("numba" or "numpy")."""
    if engine not in ENGINES:
        raise ValueError(f"engine must be one of {ENGINES}, got {engine!r}")
    return engine


#: Work (trial-samples) from which the trial-parallel (prange) kernels are used: below it a
#: parallel region costs more than it saves.
PARALLEL_MIN_WORK = 200_000


def use_parallel(trials: int, samples: int) -> bool:
    """Whether to run the trial-parallel kernel (≥ 2 trials, enough work, > 1 numba thread)."""
    return trials >= 2 and trials * samples >= PARALLEL_MIN_WORK and numba.get_num_threads() > 1


# ----------------------------------------------------------------------------- fast input checks
import numpy as np  # noqa: E402
from numba import prange  # noqa: E402

from mtcal.core.validate import MAX_GYRO_RAD_S, MIN_MEDIAN_ACCEL_M_S2  # noqa: E402

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
    if isinstance(value, (str, bytes)) or value is None:
        raise TypeError(f"{name} must be a numeric array, got {type(value).__name__}")
    try:
        arr = np.ascontiguousarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be a numeric array: {exc}") from None
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


def warm_up_all() -> dict[str, float]:
    """Compile (or load from numba's cache) every compiled kernel of mtcal; seconds per group.

    E.g. once after installing (``python -c "from mtcal.filters._kernels_common import
    warm_up_all; print(warm_up_all())"``), so that the first notebook or CLI call does not pay
    the compile time (~10-20 s cold on 2 cores).
    """
    import time

    from mtcal.core import montecarlo, simulate
    from mtcal.filters import _kernels_ekf, _kernels_marg, _kernels_qncf

    out = {}
    for name, fn in (("qncf", _kernels_qncf.warm_up), ("rams_ekf", _kernels_ekf.warm_up),
                     ("marg", _kernels_marg.warm_up)):
        t0 = time.perf_counter()
        fn()
        out[name] = time.perf_counter() - t0
    t0 = time.perf_counter()
    every = simulate.SensorErrors(bias_sigma=1e-4, noise_density=1e-4, bias_random_walk=1e-5, bias_instability=1e-5,
                                  warmup_bias=1e-4, quantization=1e-6, vibration_amplitude=1e-4,
                                  vibration_freq_hz=10.0)
    t = np.arange(300) * 1e-3
    simulate.simulate_imu(simulate.Trajectory(t, np.tile([1.0, 0.0, 0.0, 0.0], (t.size, 1))),
                          simulate.ImuErrorModel(gyro=every), np.random.default_rng(0), trials=2)
    out["simulate"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    montecarlo._euler_error_stats(np.tile([1.0, 0.0, 0.0, 0.0], (2, 2, 1)), np.zeros((1, 2, 3)), np.zeros((2, 3)),
                                  np.zeros((2, 3)), np.zeros((2, 3)))
    out["metrics"] = time.perf_counter() - t0
    return out
