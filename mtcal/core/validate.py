"""Input validation shared by every public function of mtcal.

Each helper raises ``TypeError`` for a value of the wrong kind and
``ValueError`` for a value of the right kind but wrong content, and always
names the argument and what was expected, so that bad input never turns into a
silent wrong answer.
"""

from __future__ import annotations

from numbers import Real

import numpy as np

__all__ = ["STANDARD_GRAVITY_M_S2", "float64_array", "as_float_array", "positive_scalar", "sample_interval", "MAX_SAMPLE_INTERVAL_S", "positive_int", "time_vector", "angle_rad",
           "unit_quaternion", "same_leading_shape", "MAX_GYRO_RAD_S", "check_gyro_units", "check_accel_units",
           "number_in_range", "angle_pair_deg", "choice", "merge_parameters"]

#: Standard gravity in m/s² (used to detect g passed where m/s² is expected).
STANDARD_GRAVITY_M_S2 = 9.80665


def float64_array(value, name: str, *, copy: bool = False, contiguous: bool = False) -> np.ndarray:
    """``value`` as a float64 array, or a ``TypeError`` naming ``name``: the type check of every array input.

    ``copy`` returns a new array; otherwise a view where possible (C-contiguous with ``contiguous``).
    Nothing about shape or values is checked.

    >>> float64_array([1, 2], "x").dtype
    dtype('float64')
    >>> float64_array("1", "x")
    Traceback (most recent call last):
    ...
    TypeError: x must be a numeric array, got str
    """
    if isinstance(value, (str, bytes)) or value is None:
        raise TypeError(f"{name} must be a numeric array, got {type(value).__name__}")
    try:
        if copy:
            return np.array(value, dtype=np.float64, copy=True)
        return (np.ascontiguousarray if contiguous else np.asarray)(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be a numeric array: {exc}") from None


def as_float_array(value, name: str, *, ndim: int | tuple[int, ...] | None = None,
                   last_dim: int | None = None, allow_empty: bool = False, copy: bool = True) -> np.ndarray:
    """Return ``value`` as a finite float64 array (by default a copy that never aliases the caller's).

    Parameters
    ----------
    value : array_like
        Input to check.
    name : str
        Argument name used in error messages.
    ndim : int or tuple of int, optional
        Allowed numbers of dimensions.
    last_dim : int, optional
        Required length of the last axis (e.g. 3 for vectors, 4 for quaternions).
    allow_empty : bool
        Whether a zero-size array is accepted.
    copy : bool
        ``False`` returns float64 input as a read-only-by-convention view
        (no copy of large filter records); the caller must not modify it.
    """
    arr = float64_array(value, name, copy=copy)
    if ndim is not None:
        allowed = (ndim,) if isinstance(ndim, int) else tuple(ndim)
        if arr.ndim not in allowed:
            raise ValueError(f"{name} must have ndim in {allowed}, got shape {arr.shape}")
    if last_dim is not None and (arr.ndim == 0 or arr.shape[-1] != last_dim):
        raise ValueError(f"{name} must have last dimension {last_dim}, got shape {arr.shape}")
    if arr.size == 0 and not allow_empty:
        raise ValueError(f"{name} must not be empty, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite (no NaN or inf)")
    return arr


def positive_scalar(value, name: str, *, allow_zero: bool = False) -> float:
    """Return ``value`` as a float, checking it is a finite positive number."""
    if isinstance(value, bool) or not isinstance(value, (Real, np.floating, np.integer)):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__}")
    out = float(value)
    if not np.isfinite(out):
        raise ValueError(f"{name} must be finite, got {out}")
    if out < 0 or (out == 0 and not allow_zero):
        bound = ">= 0" if allow_zero else "> 0"
        raise ValueError(f"{name} must be {bound}, got {out}")
    return out


#: Largest sample interval accepted (s): a larger ``dt_s`` is a sample *rate* in Hz passed by mistake.
MAX_SAMPLE_INTERVAL_S = 1.0


def sample_interval(dt_s, name: str = "dt_s") -> float:
    """Return the sample interval ``dt_s`` (s) as a float: finite, > 0 and ≤ 1 s.

    The time-base rule of mtcal (``docs/conventions.md``): functions take the sample
    interval, never a rate; a value above :data:`MAX_SAMPLE_INTERVAL_S` is refused as a
    rate in Hz passed where an interval belongs.

    >>> sample_interval(1.0 / 200.0)
    0.005
    >>> sample_interval(200.0)
    Traceback (most recent call last):
    ...
    ValueError: dt_s must be the sample interval in s (<= 1 s), got 200 (a sample rate in Hz? pass 1 / fs_hz)
    """
    dt = positive_scalar(dt_s, name)
    if dt > MAX_SAMPLE_INTERVAL_S:
        raise ValueError(f"{name} must be the sample interval in s (<= {MAX_SAMPLE_INTERVAL_S:g} s), got {dt:g} "
                         f"(a sample rate in Hz? pass 1 / fs_hz)")
    return dt


def positive_int(value, name: str, *, minimum: int = 1) -> int:
    """Return ``value`` as an int, checking ``value >= minimum``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an integer, got {type(value).__name__}")
    if value < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {value}")
    return int(value)


def time_vector(time_s, name: str = "time_s", *, min_samples: int = 2) -> np.ndarray:
    """Check a 1-D, finite, strictly increasing time vector in seconds."""
    t = as_float_array(time_s, name, ndim=1)
    if t.size < min_samples:
        raise ValueError(f"{name} must have at least {min_samples} samples, got {t.size}")
    if np.any(np.diff(t) <= 0):
        k = int(np.argmax(np.diff(t) <= 0))
        raise ValueError(f"{name} must be strictly increasing; sample {k + 1} "
                         f"({t[k + 1]!r}) does not exceed sample {k} ({t[k]!r})")
    return t


def angle_rad(value, name: str, *, limit_rad: float = 2 * np.pi, **kwargs) -> np.ndarray:
    """Check an angle array in radians; reject magnitudes that look like degrees.

    An angle whose magnitude exceeds ``limit_rad`` (default 2π) is almost
    certainly in degrees: the error says so.
    """
    arr = as_float_array(value, name, **kwargs)
    if arr.size and np.max(np.abs(arr)) > limit_rad + 1e-12:
        raise ValueError(f"{name} must be in radians with |{name}| <= {limit_rad:.6g}; "
                         f"got max |{name}| = {np.max(np.abs(arr)):.6g} (degrees passed as radians?)")
    return arr


#: Quaternions from which :func:`unit_quaternion` checks in one compiled pass (numba loads on first use).
_COMPILED_CHECK_MIN_ROWS = 2048


def unit_quaternion(value, name: str, *, atol: float = 1e-6, copy: bool = True) -> np.ndarray:
    """Check an array of scalar-first unit quaternions of shape (..., 4).

    A large float64 array is checked in one compiled pass (finite, ``abs(|q| − 1) <= atol``)
    without temporaries; anything else, or a failing check, goes through the numpy checks
    (same errors).

    Parameters
    ----------
    value : array_like, shape (..., 4)
        Quaternions to check.
    name : str
        Argument name used in error messages.
    atol : float
        Tolerance on the norm.
    copy : bool
        ``False`` returns float64 input itself (read-only by convention, as
        :func:`as_float_array`); the caller must not modify it.

    Returns
    -------
    ndarray, shape (..., 4)
        float64 quaternions (a copy unless ``copy=False``).

    Examples
    --------
    >>> unit_quaternion([1.0, 0.0, 0.0, 0.0], "q").tolist()
    [1.0, 0.0, 0.0, 0.0]
    >>> unit_quaternion([2.0, 0.0, 0.0, 0.0], "q")
    Traceback (most recent call last):
    ...
    ValueError: q must hold unit quaternions (|q| = 1 within 1e-06); got |q| in [2, 2]
    """
    if (isinstance(value, np.ndarray) and value.dtype == np.float64 and value.ndim >= 1
            and value.shape[-1] == 4 and value.size >= 4 * _COMPILED_CHECK_MIN_ROWS):
        from mtcal.core._rotation_kernels import all_unit  # lazy: numba loads on the first large array

        if all_unit(value.reshape(-1, 4), float(atol)):
            return np.array(value, dtype=np.float64, copy=True) if copy else np.asarray(value, dtype=np.float64)
    q = as_float_array(value, name, last_dim=4, copy=copy)
    norm = np.linalg.norm(q, axis=-1)
    if np.any(np.abs(norm - 1.0) > atol):
        raise ValueError(f"{name} must hold unit quaternions (|q| = 1 within {atol:g}); "
                         f"got |q| in [{norm.min():.6g}, {norm.max():.6g}]")
    return q


def same_leading_shape(a: np.ndarray, b: np.ndarray, name_a: str, name_b: str) -> None:
    """Raise if two arrays differ in all but their last axis."""
    if a.shape[:-1] != b.shape[:-1]:
        raise ValueError(f"{name_a} and {name_b} must have matching leading shapes, "
                         f"got {a.shape} and {b.shape}")


#: Largest plausible angular rate (rad/s): beyond any MEMS gyro's full scale (2000 °/s ≈ 35 rad/s).
MAX_GYRO_RAD_S = 40.0
#: A specific-force record whose median magnitude is below this (m/s²) is taken to be in g.
MIN_MEDIAN_ACCEL_M_S2 = 2.0


def check_gyro_units(gyro_rad_s: np.ndarray, name: str = "gyro_rad_s") -> None:
    """Raise if a gyro record (…, 3) cannot be in rad/s (degrees per second passed as rad/s)."""
    if gyro_rad_s.size and np.max(np.abs(gyro_rad_s)) > MAX_GYRO_RAD_S:
        raise ValueError(f"{name} must be in rad/s; max |{name}| = {np.max(np.abs(gyro_rad_s)):.4g} "
                         f"exceeds {MAX_GYRO_RAD_S:g} rad/s (degrees per second passed as rad/s?)")


def check_accel_units(accel_m_s2: np.ndarray, name: str = "accel_m_s2") -> None:
    """Raise if an accelerometer record (…, 3) looks like it is in g rather than m/s².

    Decided on the median magnitude so that a few free-fall or vibration
    samples do not trigger it; a zero record (e.g. a specific-force-free
    simulation) is not flagged.
    """
    if not accel_m_s2.size:
        return
    flat = accel_m_s2.reshape(-1, accel_m_s2.shape[-1])
    flat = flat[::max(1, flat.shape[0] // 20_000)]  # a strided subset decides it: cheap on 1e7-sample records
    med = float(np.median(np.linalg.norm(flat, axis=-1)))
    if 0.0 < med < MIN_MEDIAN_ACCEL_M_S2:
        raise ValueError(f"{name} looks like it is in g, not m/s² (median |a| = {med:.4g} < "
                         f"{MIN_MEDIAN_ACCEL_M_S2:g} m/s²); multiply by 9.80665")


# --------------------------------------------------------------------------
# parameters-cell values (the studies' scenario builders)
# --------------------------------------------------------------------------
def number_in_range(name: str, value, lo: float, hi: float, unit: str) -> float:
    """Return ``value`` as a float, checking it is a finite real number in ``[lo, hi]``.

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    value : int or float
        Value to check (``bool`` is rejected; numpy scalars are accepted).
    lo, hi : float
        Inclusive bounds, in ``unit``.
    unit : str
        Unit shown in the error message (e.g. ``"Hz"``, ``"deg/s"``).

    Returns
    -------
    float
        ``float(value)``.

    Raises
    ------
    ValueError
        Naming the parameter, the range with its unit and the bad value.

    Examples
    --------
    >>> number_in_range("fs_hz", 1000, 100.0, 10000.0, "Hz")
    1000.0
    >>> number_in_range("fs_hz", -1.0, 100.0, 10000.0, "Hz")
    Traceback (most recent call last):
    ...
    ValueError: fs_hz must be a number in [100.0, 10000.0] Hz, got -1.0
    """
    if (isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating))
            or not np.isfinite(value) or not lo <= float(value) <= hi):
        raise ValueError(f"{name} must be a number in [{lo}, {hi}] {unit}, got {value!r}")
    return float(value)


def angle_pair_deg(name: str, value, lo: float, hi: float) -> tuple[float, float]:
    """Return ``value`` as two different finite angles (deg), each in ``[lo, hi]``.

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    value : iterable of two numbers
        The two angles (deg).
    lo, hi : float
        Inclusive bounds (deg).

    Returns
    -------
    tuple of float
        ``(a, b)`` in degrees.

    Raises
    ------
    ValueError
        Naming the parameter, the range and the bad value (not two numbers, out of
        range, non-finite or equal).

    Examples
    --------
    >>> angle_pair_deg("yaw_positions_deg", (8, -8), -30.0, 30.0)
    (8.0, -8.0)
    >>> angle_pair_deg("yaw_positions_deg", (8.0, 8.0), -30.0, 30.0)
    Traceback (most recent call last):
    ...
    ValueError: yaw_positions_deg must be two different angles in [-30.0, 30.0] deg, got (8.0, 8.0)
    """
    try:
        v = tuple(float(x) for x in value)
    except (TypeError, ValueError):
        v = ()
    if len(v) != 2 or not all(np.isfinite(v)) or not all(lo <= x <= hi for x in v) or v[0] == v[1]:
        raise ValueError(f"{name} must be two different angles in [{lo}, {hi}] deg, got {value!r}")
    return v


def choice(name: str, value, choices):
    """Return ``value``, checking it is one of ``choices``.

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    value : object
        Value to check.
    choices : sequence
        The valid values, shown (as a list, in the order given) in the error message.

    Returns
    -------
    object
        ``value`` unchanged.

    Raises
    ------
    ValueError
        Naming the parameter, the valid choices and the bad value.

    Examples
    --------
    >>> choice("grade", "tactical", ["consumer", "tactical"])
    'tactical'
    >>> choice("grade", "bogus", ["consumer", "tactical"])
    Traceback (most recent call last):
    ...
    ValueError: grade must be one of ['consumer', 'tactical'], got 'bogus'
    """
    if value not in choices:
        raise ValueError(f"{name} must be one of {list(choices)}, got {value!r}")
    return value


def merge_parameters(params: dict, defaults: dict, *, what: str = "parameter") -> dict:
    """Return ``defaults`` updated with ``params``, rejecting names not in ``defaults``.

    Parameters
    ----------
    params : dict
        Parameters-cell values (a subset of the names of ``defaults``).
    defaults : dict
        Every valid name with its default value.
    what : str
        What the names are, for the error message (e.g. ``"tan2022 parameter"``).

    Returns
    -------
    dict
        ``{**defaults, **params}`` (a new dict; neither input is modified).

    Raises
    ------
    ValueError
        ``unknown parameter(s) [...]; valid: [...]`` (both lists sorted).

    Examples
    --------
    >>> merge_parameters({"fs_hz": 200.0}, {"fs_hz": 100.0, "rest_s": 3.0})
    {'fs_hz': 200.0, 'rest_s': 3.0}
    >>> merge_parameters({"fs": 200.0}, {"fs_hz": 100.0, "rest_s": 3.0})
    Traceback (most recent call last):
    ...
    ValueError: unknown parameter(s) ['fs']; valid: ['fs_hz', 'rest_s']
    """
    unknown = sorted(set(params) - set(defaults))
    if unknown:
        raise ValueError(f"unknown {what}(s) {unknown}; valid: {sorted(defaults)}")
    return {**defaults, **params}
