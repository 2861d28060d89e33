"""Error metrics: RMSE, MaxAE, wrapped angle differences, static/moving split, Allan deviation, bands, variance split.

All reductions act over the sample axis (``axis=-1`` by default for 1-D
series; pass ``axis`` for other layouts) and are vectorised over trials.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from mtcal.core.validate import as_float_array, positive_int, positive_scalar, sample_interval

__all__ = ["angle_difference", "rmse", "max_abs_error", "split_static_moving",
           "allan_deviation", "fit_allan_noise", "percentile_band", "bootstrap_medians",
           "MIN_BAND_DRAWS", "band_or_range", "band_label", "median_trial",
           "OrientationErrors", "orientation_errors", "inclination_error", "rmse_over_phase", "variance_parts"]


#: Elements from which :func:`angle_difference` runs a compiled loop (bit-identical to numpy's).
_KERNEL_MIN_SIZE = 8192


def angle_difference(estimate_rad, truth_rad) -> np.ndarray:
    """Wrapped difference ``estimate − truth`` in ``[−π, π)`` (rad)."""
    e = as_float_array(estimate_rad, "estimate_rad", allow_empty=True, copy=False)
    t = as_float_array(truth_rad, "truth_rad", allow_empty=True, copy=False)
    try:
        shape = np.broadcast_shapes(e.shape, t.shape)
    except ValueError:
        raise ValueError(f"estimate_rad and truth_rad must broadcast, got {e.shape} and {t.shape}") from None
    return _wrapped_difference(e, t, shape)


def angle_difference_trusted(estimate_rad: np.ndarray, truth_rad: np.ndarray) -> np.ndarray:
    """:func:`angle_difference` without input validation (not public API; users call it).

    Preconditions: ``estimate_rad`` and ``truth_rad`` are float64 arrays (rad) that broadcast against
    each other (e.g. angles a procedure computed from inputs it checked at its edge). Bit-identical
    to :func:`angle_difference` on such input.
    """
    return _wrapped_difference(estimate_rad, truth_rad, np.broadcast_shapes(estimate_rad.shape, truth_rad.shape))


def _wrapped_difference(e: np.ndarray, t: np.ndarray, shape: tuple) -> np.ndarray:
    """``(e − t + π) mod 2π − π`` over the broadcast ``shape`` (a compiled pass for large inputs)."""
    size = int(np.prod(shape))
    if 1 <= len(shape) <= 3 and size >= _KERNEL_MIN_SIZE:   # one compiled pass, the same operations
        from mtcal.core import _rotation_kernels

        shape3 = (1,) * (3 - len(shape)) + shape
        out = np.empty(shape3)
        _rotation_kernels.wrap_difference3(np.broadcast_to(e, shape3), np.broadcast_to(t, shape3), out)
        return out.reshape(shape)
    d = e - t
    if not isinstance(d, np.ndarray):         # 0-d inputs give a scalar
        return (d + np.pi) % (2 * np.pi) - np.pi
    d += np.pi                                # (d + π) mod 2π − π, in place (the same operations)
    np.remainder(d, 2 * np.pi, out=d)
    d -= np.pi
    return d


def _errors(error, mask) -> np.ndarray:
    err = as_float_array(error, "error")
    if mask is None:
        return err
    m = np.asarray(mask)
    if m.dtype != bool:
        raise TypeError(f"mask must be boolean, got dtype {m.dtype}")
    try:
        m = np.broadcast_to(m, err.shape)
    except ValueError:
        raise ValueError(f"mask of shape {m.shape} must broadcast to error of shape {err.shape}") from None
    if not np.any(m):
        raise ValueError("mask must select at least one sample")
    return np.where(m, err, np.nan)


def rmse(error, axis: int = -1, mask=None) -> np.ndarray:
    """Root-mean-square of ``error`` along ``axis``, optionally over ``mask`` only."""
    err = _errors(error, mask)
    return np.sqrt(np.nanmean(err**2, axis=axis))


class OrientationErrors(NamedTuple):
    """Total, heading and inclination error (rad) of :func:`orientation_errors`, each shape (N,)."""

    total_rad: np.ndarray
    heading_rad: np.ndarray
    inclination_rad: np.ndarray


def orientation_errors(q_est, q_ref) -> OrientationErrors:
    """Earth-frame orientation errors of an estimate against a reference.

    The error quaternion in the earth (reference) frame is ``q_e = q_est ⊗ q_ref⁻¹``
    (both quaternions sensor → earth, scalar-first, z vertical). It splits into a rotation
    about the vertical (heading) and one about a horizontal axis (inclination):

    * total error       ``2·arccos|w_e|``
    * heading error     ``2·arctan(|z_e| / |w_e|)``
    * inclination error ``2·arccos √(w_e² + z_e²)``

    The inclination error does not depend on a heading offset, so a 6D filter
    (gyroscope + accelerometer, heading free) is judged on it alone. Rows where the
    reference is NaN (e.g. optical markers lost) give NaN errors; :func:`rmse_over_phase`
    skips them.

    Parameters
    ----------
    q_est, q_ref : array_like, shape (N, 4) or (4,)
        Estimated and reference orientation, unit quaternions, scalar-first, sensor → earth.
        Sign and normalisation do not matter (both are normalised here).

    Returns
    -------
    OrientationErrors
        ``total_rad``, ``heading_rad``, ``inclination_rad``, each shape (N,) (rad), in [0, π].

    References
    ----------
    D. Laidig, M. Caruso, A. Cereatti, T. Seel, "BROAD — A Benchmark for Robust Inertial
    Orientation Estimation", Data 6(7):72, 2021, doi:10.3390/data6070072, Sec. 4 (error metrics).

    Examples
    --------
    A pure heading offset gives no inclination error; a 10° tilt about a horizontal axis
    gives 10° of inclination error and no heading error:

    >>> import numpy as np
    >>> half = np.radians(10) / 2
    >>> ref = np.array([1.0, 0, 0, 0])
    >>> e = orientation_errors([np.cos(half), 0, 0, np.sin(half)], ref)
    >>> np.degrees([e.total_rad[0], e.heading_rad[0], e.inclination_rad[0]]).round(12) + 0
    array([10., 10.,  0.])
    >>> e = orientation_errors([np.cos(half), np.sin(half), 0, 0], ref)
    >>> np.degrees([e.total_rad[0], e.heading_rad[0], e.inclination_rad[0]]).round(12) + 0
    array([10.,  0., 10.])
    """
    w, z = _error_wz(q_est, q_ref)
    aw, az = np.abs(w), np.abs(z)
    total = 2.0 * np.arccos(np.clip(aw, 0.0, 1.0))
    heading = 2.0 * np.arctan2(az, aw)
    inclination = 2.0 * np.arccos(np.clip(np.sqrt(w * w + z * z), 0.0, 1.0))
    return OrientationErrors(total, heading, inclination)


def inclination_error(q_est, q_ref) -> np.ndarray:
    """The ``inclination_rad`` field of :func:`orientation_errors` alone: the same numbers, without the total
    and heading errors' ``arccos``/``arctan2`` over every sample (a 6D filter is judged on it alone).

    Parameters
    ----------
    q_est, q_ref : array_like, shape (N, 4) or (4,)
        As :func:`orientation_errors` (scalar-first, sensor → earth; NaN reference rows give NaN).

    Returns
    -------
    ndarray, shape (N,)
        Inclination error ``2·arccos √(w_e² + z_e²)`` (rad), in [0, π].

    References
    ----------
    BROAD (Laidig et al., Data 6(7):72, 2021), Sec. 4, as :func:`orientation_errors`.

    Examples
    --------
    >>> half = np.radians(10) / 2
    >>> float(np.degrees(inclination_error([np.cos(half), np.sin(half), 0, 0], [1.0, 0, 0, 0])[0]).round(12))
    10.0
    """
    w, z = _error_wz(q_est, q_ref)
    return 2.0 * np.arccos(np.clip(np.sqrt(w * w + z * z), 0.0, 1.0))


def _error_wz(q_est, q_ref) -> tuple[np.ndarray, np.ndarray]:
    """Checked inputs of :func:`orientation_errors`; w and z of ``q_e = q_est ⊗ conj(q_ref)``, each (N,)."""
    est = np.atleast_2d(as_float_array(q_est, "q_est"))
    ref = np.atleast_2d(np.asarray(q_ref, dtype=float))      # NaN rows allowed (reference lost)
    if np.isinf(ref).any():
        raise ValueError("q_ref must not contain infinite values")
    if est.shape[-1] != 4 or ref.shape[-1] != 4 or est.ndim != 2 or ref.ndim != 2:
        raise ValueError(f"q_est and q_ref must have shape (N, 4), got {est.shape} and {ref.shape}")
    if est.shape[0] != ref.shape[0] and 1 not in (est.shape[0], ref.shape[0]):
        raise ValueError(f"q_est and q_ref must have the same length, got {est.shape[0]} and {ref.shape[0]}")
    est = est / np.linalg.norm(est, axis=1, keepdims=True)
    ref = ref / np.linalg.norm(ref, axis=1, keepdims=True)
    # q_e = q_est ⊗ conj(q_ref): only w and z are needed
    w1, x1, y1, z1 = est.T
    w2, x2, y2, z2 = ref.T
    w = w1 * w2 + x1 * x2 + y1 * y2 + z1 * z2
    z = -w1 * z2 + z1 * w2 - x1 * y2 + y1 * x2
    return w, z


def rmse_over_phase(error, phase=None) -> float:
    """RMSE of a 1-D error series over a phase, samples with NaN error (reference lost) excluded.

    Parameters
    ----------
    error : array_like, shape (N,)
        Error series (any unit; e.g. :func:`orientation_errors` fields in rad). NaN marks a
        sample without reference; infinite values are refused.
    phase : array_like of bool or {0, 1}, shape (N,), optional
        Samples that belong to the phase (e.g. BROAD's ``movement`` flag); all samples if omitted.

    Returns
    -------
    float
        ``sqrt(mean(error²))`` over the finite samples of the phase, in the unit of ``error``.

    Raises
    ------
    ValueError
        If the shapes differ, ``error`` holds an infinite value, or no finite sample is in the phase.

    Examples
    --------
    >>> rmse_over_phase([3.0, float("nan"), 4.0, 100.0], [1, 1, 1, 0])
    3.5355339059327378
    """
    err = np.asarray(error, dtype=float)
    if err.ndim != 1:
        raise ValueError(f"error must be 1-D, got shape {err.shape}")
    if np.isinf(err).any():
        raise ValueError("error must not contain infinite values")
    keep = np.isfinite(err)
    if phase is not None:
        ph = np.asarray(phase)
        if ph.shape != err.shape:
            raise ValueError(f"phase must have the shape of error {err.shape}, got {ph.shape}")
        keep &= ph.astype(bool)
    if not keep.any():
        raise ValueError("no finite error sample in the phase")
    return float(np.sqrt(np.mean(err[keep] ** 2)))


def max_abs_error(error, axis: int = -1, mask=None) -> np.ndarray:
    """Maximum absolute error (MaxAE) along ``axis``, optionally over ``mask`` only."""
    err = _errors(error, mask)
    return np.nanmax(np.abs(err), axis=axis)


def split_static_moving(error, is_static, axis: int = -1) -> dict[str, np.ndarray]:
    """RMSE and MaxAE separately over static and moving samples.

    Returns a dict with keys ``static_rmse``, ``static_max``, ``moving_rmse``,
    ``moving_max`` (NaN where a class has no samples).
    """
    s = np.asarray(is_static)
    if s.dtype != bool:
        raise TypeError(f"is_static must be boolean, got dtype {s.dtype}")
    out = {}
    for name, m in (("static", s), ("moving", ~s)):
        if np.any(m):
            out[f"{name}_rmse"] = rmse(error, axis, m)
            out[f"{name}_max"] = max_abs_error(error, axis, m)
        else:
            out[f"{name}_rmse"] = out[f"{name}_max"] = np.nan
    return out


def allan_deviation(rate, dt_s: float, taus_s=None) -> tuple[np.ndarray, np.ndarray]:
    """Overlapping Allan deviation of a rate signal.

    ``σ²(τ) = 1 / (2 τ² (M − 2m)) Σ_k (Θ_{k+2m} − 2 Θ_{k+m} + Θ_k)²`` with
    ``Θ`` the integrated signal, ``m = τ / Δt`` and M samples (IEEE Std 952).

    Parameters
    ----------
    rate : array_like, shape (N,) or (..., N)
        Rate samples (e.g. rad/s); the last axis is time. Leading axes are
        independent records, averaged in the Allan variance.
    dt_s : float
        Sample interval (s), ≤ 1 s.
    taus_s : array_like, optional
        Cluster times (s); default ~10 per decade from Δt to N Δt / 3.

    Returns
    -------
    taus_s : ndarray
        Cluster times actually used (rounded to whole samples).
    adev : ndarray
        Allan deviation at each τ (unit of ``rate``).
    """
    x = as_float_array(rate, "rate")
    fs = 1.0 / sample_interval(dt_s)  # the rate: exact for the rates mtcal uses (1 / (1 / fs) == fs)
    n = x.shape[-1]
    if n < 9:
        raise ValueError(f"rate must have at least 9 samples along its last axis, got {n}")
    if taus_s is None:
        m = np.unique(np.round(np.logspace(0, np.log10(n / 3), 60)).astype(int))
    else:
        tau = as_float_array(taus_s, "taus_s", ndim=1)
        m = np.unique(np.round(tau * fs).astype(int))
        if np.any(m < 1) or np.any(2 * m >= n):
            raise ValueError(f"taus_s must lie in [1/fs, N/(2 fs)) = [{1 / fs:g}, {n / (2 * fs):g}) s")
    theta = np.concatenate([np.zeros(x.shape[:-1] + (1,)), np.cumsum(x, axis=-1)], axis=-1) / fs
    avar = np.empty(m.size)
    scratch = np.empty(theta[..., 2 * int(m[0]):].size) if theta.ndim <= 3 else None   # m ascending: the largest
    for i, mi in enumerate(m):
        avar[i] = _second_difference_mean(theta, int(mi), scratch) / (2.0 * (mi / fs) ** 2)
    return m / fs, np.sqrt(avar)


def _time_middle(a: np.ndarray) -> list[np.ndarray]:
    """Views (A, T, B) of ``a`` (…, T), time on axis 1, whose innermost axis is the fastest in memory
    where the layout allows (one view per leading index of a C-ordered 3-D array); [] for ndim > 3."""
    if a.ndim == 1:
        return [a[None, :, None]]
    if a.ndim == 2:
        return [a[:, :, None]]
    if a.ndim == 3:
        if a.strides[1] < a.strides[2]:       # e.g. records (trials, N, 3) with the axis moved: (trials, 3, N)
            return [a.transpose(0, 2, 1)]
        return [a[p][:, :, None] for p in range(a.shape[0])]
    return []


def _second_difference_mean(theta: np.ndarray, m: int, scratch: np.ndarray | None) -> float:
    """``np.mean((θ[..., 2m:] − 2 θ[..., m:−m] + θ[..., :−2m])**2)``, bit-identical: for large inputs the
    squared differences are made by one compiled pass (the same operations) into ``scratch``, in the memory
    layout numpy gives its elementwise result, so ``np.mean`` sums the same values in the same order."""
    view = theta[..., 2 * m:]
    if scratch is None or view.size < _KERNEL_MIN_SIZE:
        d = view - 2 * theta[..., m:-m] + theta[..., :-2 * m]
        return np.mean(d**2)
    from mtcal.core import _metrics_kernels

    out = _like(view, scratch)            # the layout numpy's elementwise result takes (order "K")
    for src, dst in zip(_time_middle(theta), _time_middle(out)):
        _metrics_kernels.allan_second_difference_squared3(src, m, dst)
    return np.mean(out)


def _like(a: np.ndarray, buffer: np.ndarray) -> np.ndarray:
    """A dense array of ``a``'s shape in the first ``a.size`` elements of the flat ``buffer``, its axes in ``a``'s
    memory order: the layout ``np.empty_like(a)`` and numpy's elementwise results (order "K") take."""
    perm = sorted(range(a.ndim), key=lambda ax: -abs(a.strides[ax]))     # stable: ties keep axis order
    dense = buffer[:a.size].reshape([a.shape[ax] for ax in perm])
    return dense.transpose(np.argsort(perm))


def fit_allan_noise(taus_s, adev, *, flat_term: bool = True) -> dict[str, float]:
    """Fit ``σ²(τ) = N²/τ + B_f² + K² τ/3`` to an Allan curve (LS on relative residuals).

    Returns the white-noise density ``N`` (unit·s^½ = unit/√Hz, read at
    τ = 1 s), the rate random walk ``K`` (unit/√s, read at τ = 3 s) and the
    flat term ``B_f`` (≈ 0.664 × bias instability), each ≥ 0. With
    ``flat_term=False`` the flat term is fixed to 0 (a sensor model without
    bias instability), which makes N and K better determined.
    """
    tau = as_float_array(taus_s, "taus_s", ndim=1)
    sig = as_float_array(adev, "adev", ndim=1)
    if tau.shape != sig.shape:
        raise ValueError(f"taus_s and adev must have the same shape, got {tau.shape} and {sig.shape}")
    if tau.size < 3:
        raise ValueError("taus_s must have at least 3 points to fit 3 noise terms")
    from scipy.optimize import nnls

    a = np.stack([1.0 / tau, np.ones_like(tau) * float(flat_term), tau / 3.0], axis=1) / sig[:, None] ** 2
    coef, _ = nnls(a, np.ones_like(tau))  # relative residuals: (model − σ²)/σ²
    n2, b2, k2 = coef
    return {"N": float(np.sqrt(n2)), "B_flat": float(np.sqrt(b2)), "K": float(np.sqrt(k2))}


def percentile_band(samples, axis: int = 0, level: float = 0.95) -> dict:
    """Median and central ``level`` interval of Monte Carlo samples along ``axis``, with the draw count.

    It is called a "95 % band" only from ≥ :data:`MIN_BAND_DRAWS` draws; :func:`band_or_range`
    applies that rule (with fewer draws it gives the min–max range), and the comparison tables
    audit it through ``n`` (:func:`mtcal.reporting.compare.check_bands`).

    Returns
    -------
    dict
        ``median, low, high`` (ndarray or float) and ``n`` (int, draws along ``axis``).

    Examples
    --------
    >>> b = percentile_band(np.arange(1001.0))
    >>> round(float(b["low"]), 6), float(b["median"]), float(b["high"]), b["n"]
    (25.0, 500.0, 975.0, 1001)
    """
    x = as_float_array(samples, "samples")
    if not 0 < level < 1:
        raise ValueError(f"level must be in (0, 1), got {level}")
    if x.ndim == 0:
        raise ValueError("samples must have at least one dimension (the draw axis)")
    lo, med, hi = np.percentile(x, [50 * (1 - level), 50, 50 * (1 + level)], axis=axis)
    return {"median": med, "low": lo, "high": hi, "n": int(x.shape[axis])}


def bootstrap_medians(samples, rng: np.random.Generator, n_boot: int = 1000) -> np.ndarray:
    """Medians of bootstrap resamples of K Monte Carlo sample sets, shape (n_boot, K).

    For a statistic built from several Monte Carlo medians (a ratio of two
    medians, a log-log slope through K medians) the spread of the statistic
    over the resamples gives its 95 % interval
    (``percentile_band(stat(bootstrap_medians(...)))``).

    Parameters
    ----------
    samples : sequence of array_like (n_k,)
        K one-dimensional sample sets (e.g. axis errors per set-up, one value per trial).
    rng : numpy.random.Generator
        Source of the resampling indices.
    n_boot : int
        Number of bootstrap resamples.
    """
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    n = positive_int(n_boot, "n_boot")
    sets = [as_float_array(x, f"samples[{k}]", ndim=1) for k, x in enumerate(samples)]
    if not sets or any(x.size < 2 for x in sets):
        raise ValueError("samples must hold at least one set of >= 2 values")
    return np.stack([np.median(x[rng.integers(0, x.size, (n, x.size))], axis=1) for x in sets], axis=1)


def variance_parts(samples, per_draw: int) -> dict:
    """Split the variance of ``samples`` into a parameter part and a sampling part (law of total variance).

    ``samples`` (T,) are draw-major: consecutive groups of ``per_draw`` sessions share one parameter
    draw θ (an incomplete last group is left out). One-way random-effects analysis of variance:

    * ``sampling`` = E[Var(Y | θ)], estimated by the mean within-group variance (ddof 1);
    * ``parameter`` = Var(E[Y | θ]), estimated by the variance of the group means (ddof 1) minus
      ``sampling / per_draw`` (unbiased; it can come out slightly negative by Monte Carlo error when the
      parameters contribute little);
    * ``total`` = ``parameter + sampling``, an unbiased estimate of Var(Y) (compare the sample variance);
    * ``parameter_share`` = ``parameter / total`` clipped to [0, 1].

    Parameters
    ----------
    samples : array_like (T,)
    per_draw : int
        Sessions per parameter draw (≥ 2).

    Returns
    -------
    dict with ``parameter``, ``sampling``, ``total`` (unit of ``samples`` squared), ``parameter_share`` and
    ``draws`` (complete groups used).

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> y = np.repeat(rng.normal(0, 2, 4000), 2) + rng.normal(0, 1, 8000)
    >>> p = variance_parts(y, 2)
    >>> round(p["parameter"]), round(p["sampling"]), p["draws"]
    (4, 1, 4000)
    """
    per_draw = int(per_draw)
    if per_draw < 2:
        raise ValueError(f"per_draw must be >= 2 to split the variance, got {per_draw}")
    x = np.asarray(samples, float)
    if x.ndim != 1:
        raise ValueError(f"samples must be 1-D, got shape {x.shape}")
    g = x.size // per_draw
    if g < 2:
        raise ValueError(f"samples must hold at least 2 complete groups of {per_draw}, got {x.size} values")
    groups = x[:g * per_draw].reshape(g, per_draw)
    sampling = float(np.mean(np.var(groups, axis=1, ddof=1)))
    parameter = float(np.var(groups.mean(axis=1), ddof=1)) - sampling / per_draw
    total = parameter + sampling
    share = float(np.clip(parameter / total, 0.0, 1.0)) if total > 0 else float("nan")
    return {"parameter": parameter, "sampling": sampling, "total": total, "parameter_share": share, "draws": g}


#: Fewest Monte Carlo draws behind an interval reported as a "95 % band" (docs/conventions.md). With
#: fewer, the 2.5 % and 97.5 % points are about the smallest and largest draw (from 20 draws, the
#: interval between them holds a new draw with probability 19/21 ≈ 90 %, not 95 %), and their
#: Monte Carlo error is of the order of the band's width: such a spread is reported as the
#: min–max range with its count, never as a 95 % band.
MIN_BAND_DRAWS = 1000


def band_label(n: int, what: str = "trials") -> str:
    """What a spread of ``n`` draws is called: ``"95 % band of n …"`` or ``"range of n …"``.

    Parameters
    ----------
    n : int
        Draws behind the spread (≥ 1).
    what : str
        What a draw is (``"trials"``, ``"repetitions"``, ``"draws"``).

    Returns
    -------
    str

    Examples
    --------
    >>> band_label(1000)
    '95 % band of 1000 trials'
    >>> band_label(12, "repetitions")
    'range of 12 repetitions (fewer than 1000: no 95 % band)'
    """
    n = positive_int(n, "n")
    if n >= MIN_BAND_DRAWS:
        return f"95 % band of {n} {what}"
    return f"range of {n} {what} (fewer than {MIN_BAND_DRAWS}: no 95 % band)"


def band_or_range(samples, axis: int = 0, *, what: str = "trials", finite_only: bool = False) -> dict:
    """Median and spread of Monte Carlo draws along ``axis``: the 95 % band from ≥ :data:`MIN_BAND_DRAWS`
    draws, else the min–max range (the rule every printed band follows).

    Parameters
    ----------
    samples : array_like
        Draws along ``axis`` (one per trial).
    axis : int
        Draw axis; ``None`` with ``finite_only``: all values, flattened.
    what : str
        What a draw is, for ``label`` (:func:`band_label`).
    finite_only : bool
        Drop non-finite values first (they mark draws that were not run); needs a 1-D result
        (``samples`` flattened). Otherwise a non-finite value is an error.

    Returns
    -------
    dict
        ``median, low, high`` (ndarray or float; the 2.5/97.5 % points, or min and max), ``n``
        (draws), ``kind`` (``"95 % band"`` or ``"range"``), ``label`` (:func:`band_label`).

    Examples
    --------
    >>> b = band_or_range([3.0, 1.0, 2.0])
    >>> float(b["low"]), float(b["high"]), b["kind"], b["n"]
    (1.0, 3.0, 'range', 3)
    >>> band_or_range(np.arange(1000.0))["kind"]
    '95 % band'
    >>> band_or_range([1.0, float("nan")], finite_only=True)["n"]
    1
    """
    if finite_only:
        x = np.asarray(samples, dtype=float).ravel()
        x = x[np.isfinite(x)]
        if x.size == 0:
            raise ValueError("samples must hold at least one finite value")
        axis = 0
    else:
        x = as_float_array(samples, "samples", copy=False)
        if x.ndim == 0:
            raise ValueError("samples must have at least one dimension (the draw axis)")
    n = x.shape[axis]
    if n >= MIN_BAND_DRAWS:
        out = {**percentile_band(x, axis=axis), "kind": "95 % band"}
    else:
        out = {"median": np.median(x, axis=axis), "low": np.min(x, axis=axis), "high": np.max(x, axis=axis),
               "kind": "range"}
    return {**out, "n": int(n), "label": band_label(n, what)}


def median_trial(score) -> int:
    """Index of the median trial: the trial whose ``score`` (one value per trial) is the lower median.

    Figures and "one session" table columns show this trial, never trial 0 (a lucky or unlucky draw),
    and say so.

    Parameters
    ----------
    score : array_like (T,)
        One value per trial (e.g. its maximum error; NaN sorts last).

    Returns
    -------
    int

    Examples
    --------
    >>> median_trial([3.0, 1.0, 2.0, 5.0])
    2
    """
    x = np.asarray(score, dtype=float)
    if x.ndim != 1 or x.size == 0:
        raise ValueError(f"score must be a non-empty 1-D array (one value per trial), got shape {x.shape}")
    return int(np.argsort(x, kind="stable")[(x.size - 1) // 2])     # a NaN score sorts last
