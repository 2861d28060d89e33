"""Zero-velocity detection (ZVD) of wang2022sensors (Wang et al., Sensors 2022, Sec. 3.1, Table 1).

A sample is *static* when, for at least ``th_t`` seconds,

1. the acceleration magnitude lies in a band ``th_a_min < ‖a‖ < th_a_max`` (Eq 21), and
2. the local variance of ‖a‖ over a window of ``t_w`` seconds is below
   ``th_ζa`` (Eq 22).

Everything is **causal** (trailing windows), so the batch function
:func:`detect_static` gives, sample for sample, what a streaming detector fed
one sample at a time would give: the window at sample k covers samples
``k − n_w + 1 … k`` (fewer at the start of a record), and a sample is flagged
once both conditions have held for ``n_h`` consecutive samples. The moving
variance uses cumulative sums of ``‖a‖ − g`` (centred first so the cumsum does
not lose precision), vectorised over samples and any leading trial axes.

Edge behaviour (what the tests allow): the first ``max(n_w, n_h) − 1``
samples of a rest are not yet flagged, and the last samples of a move, where a
minimum-jerk blend has almost no rate or acceleration, may already be flagged.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mtcal.core.validate import (STANDARD_GRAVITY_M_S2, as_float_array, check_accel_units, positive_scalar,
                                 sample_interval)

__all__ = ["ZvdParams", "moving_variance", "detect_static", "rest_intervals"]


@dataclass(frozen=True)
class ZvdParams:
    """ZVD thresholds; defaults are wang2022sensors Table 1 (checked against the transcribed table by
    :func:`mtcal.studies.wang2022sensors.scenario.table1_zvd_params`).

    Parameters
    ----------
    accel_min_m_s2, accel_max_m_s2 : float
        Acceleration-magnitude band ``th_a_min``, ``th_a_max`` (m/s²): 9.76, 9.84.
    var_threshold_m2_s4 : float
        Local-variance threshold ``th_ζa`` (m²/s⁴): 0.001.
    window_s : float
        Variance window ``t_w`` (s): 0.01.
    min_duration_s : float
        Minimum duration ``th_t`` (s): 0.01.
    min_window_samples : int
        Lower bound on the window length in samples (a variance over fewer
        than 2 samples is 0); mtcal's choice, not the paper's.
    gyro_max_rad_s : float or None
        Optional angular-rate condition ``‖ω‖ < gyro_max`` (rad/s), the
        "angular velocity condition" Sec. 3.1 cites from [20] but does not use;
        None (paper) disables it. ‖a‖ is blind to a pure rotation about an
        axis through the sensor, so without it the ZVD sees rotation only
        through lever-arm acceleration.
    """

    accel_min_m_s2: float = 9.76
    accel_max_m_s2: float = 9.84
    var_threshold_m2_s4: float = 0.001
    window_s: float = 0.01
    min_duration_s: float = 0.01
    min_window_samples: int = 3
    gyro_max_rad_s: float | None = None

    def __post_init__(self) -> None:
        for name in ("accel_min_m_s2", "accel_max_m_s2", "var_threshold_m2_s4", "window_s",
                     "min_duration_s"):
            positive_scalar(getattr(self, name), name)
        if self.accel_min_m_s2 >= self.accel_max_m_s2:
            raise ValueError(f"accel_min_m_s2 ({self.accel_min_m_s2}) must be < accel_max_m_s2 "
                             f"({self.accel_max_m_s2})")
        if self.accel_max_m_s2 > 100:
            raise ValueError("accel_max_m_s2 must be in m/s² (got > 100; mg passed?)")
        if self.gyro_max_rad_s is not None:
            positive_scalar(self.gyro_max_rad_s, "gyro_max_rad_s")
        if int(self.min_window_samples) < 2:
            raise ValueError(f"min_window_samples must be >= 2, got {self.min_window_samples}")

    def window_samples(self, dt_s: float) -> int:
        """Variance window ``n_w = max(round(t_w / Δt), min_window_samples)`` for sample interval ``dt_s`` (s)."""
        return max(int(round(self.window_s * (1.0 / sample_interval(dt_s)))),
                   int(self.min_window_samples))

    def duration_samples(self, dt_s: float) -> int:
        """Minimum run ``n_h = max(ceil(th_t / Δt − 1e-9), 1)`` samples for sample interval ``dt_s`` (s)."""
        return max(int(np.ceil(self.min_duration_s * (1.0 / sample_interval(dt_s)) - 1e-9)), 1)


def moving_variance(x, window: int) -> np.ndarray:
    """Trailing moving (population) variance along the last axis, via cumulative sums.

    Sample k uses ``x[k − window + 1 … k]`` (fewer samples for k < window − 1).

    Parameters
    ----------
    x : array_like, shape (..., N)
    window : int
        Window length in samples (≥ 1).
    """
    arr = as_float_array(x, "x")
    if isinstance(window, bool) or not isinstance(window, (int, np.integer)) or window < 1:
        raise ValueError(f"window must be an integer >= 1, got {window!r}")
    return _moving_variance(arr, window)


def _moving_variance(arr: np.ndarray, window: int) -> np.ndarray:
    """:func:`moving_variance` of a checked (finite float64, non-empty) array and window (int ≥ 1)."""
    arr = arr - arr[..., :1]  # centre on the first sample: cumsum keeps precision
    zeros = np.zeros(arr.shape[:-1] + (1,))
    c1 = np.concatenate([zeros, np.cumsum(arr, axis=-1)], axis=-1)
    c2 = np.concatenate([zeros, np.cumsum(arr * arr, axis=-1)], axis=-1)
    n = arr.shape[-1]
    stop = np.arange(1, n + 1)
    start = np.maximum(stop - window, 0)
    count = (stop - start).astype(float)
    s1 = c1[..., stop] - c1[..., start]
    s2 = c2[..., stop] - c2[..., start]
    mean = s1 / count
    return np.maximum(s2 / count - mean * mean, 0.0)


def detect_static(accel_m_s2: np.ndarray, dt_s: float, params: ZvdParams | None = None,
                  gyro_rad_s: np.ndarray | None = None, *,
                  gyro_offset_rad_s: np.ndarray | None = None) -> np.ndarray:
    """wang2022sensors ZVD (Sec. 3.1, Eq 21–22, Table 1): static flag per sample.

    Parameters
    ----------
    accel_m_s2 : ndarray, shape (..., N, 3)
        Accelerometer specific force (m/s²); leading axes are trials.
    dt_s : float
        Sample interval (s), ≤ 1 s.
    params : ZvdParams, optional
        Thresholds; Table 1 by default.
    gyro_rad_s : ndarray, shape (..., N, 3), optional
        Gyro record (rad/s); required when ``params.gyro_max_rad_s`` is set.
    gyro_offset_rad_s : ndarray, shape (..., 3), optional
        One offset per record (e.g. the initial bias): the gyro condition then reads ``‖ω − offset‖``,
        as when ``gyro_rad_s - offset[..., None, :]`` is passed.

    Returns
    -------
    ndarray of bool, shape (..., N)

    Raises
    ------
    ValueError
        ``params.gyro_max_rad_s`` set without ``gyro_rad_s``.

    Preconditions
    -------------
    The caller guarantees (not checked here): ``accel_m_s2`` finite float64 (..., N, 3) in m/s², not g
    (:func:`mtcal.core.validate.check_accel_units`); ``dt_s`` a sample interval in (0, 1] s
    (:func:`mtcal.core.validate.sample_interval`); ``params`` None or a :class:`ZvdParams`;
    ``gyro_rad_s`` None or finite float64 of the shape of ``accel_m_s2`` (rad/s); ``gyro_offset_rad_s``
    None or finite float64 (..., 3). The systems check a record once at their edge
    (:func:`mtcal.systems.surface_angle.surface_angle_batch`, :func:`mtcal.systems.rests.find_rests`).

    C-contiguous records run through one compiled pass per record (:mod:`mtcal.methods._zvd_kernels`,
    the same operations in the same order, so the same flags bit for bit); other layouts through
    the numpy expression.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.tile([0.0, 0.0, 9.80665], (20, 1)); a[8:12] += 1.0
    >>> detect_static(a, 0.01).astype(int).tolist()
    [1, 1, 1, 1, 1, 1, 1, 1, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1]
    """
    params = ZvdParams() if params is None else params
    use_gyro = params.gyro_max_rad_s is not None
    if use_gyro and gyro_rad_s is None:
        raise ValueError("gyro_rad_s is required when params.gyro_max_rad_s is set")
    if accel_m_s2.ndim >= 2 and accel_m_s2.shape[-2] > 0 and accel_m_s2.flags.c_contiguous \
            and (not use_gyro or (gyro_rad_s.flags.c_contiguous and gyro_rad_s.shape == accel_m_s2.shape)):
        from mtcal.methods import _zvd_kernels

        lead, n = accel_m_s2.shape[:-2], accel_m_s2.shape[-2]
        a = accel_m_s2.reshape(-1, n, 3)
        g = gyro_rad_s.reshape(-1, n, 3) if use_gyro else a
        off = (np.ascontiguousarray(np.broadcast_to(gyro_offset_rad_s, lead + (3,)), dtype=float).reshape(-1, 3)
               if use_gyro and gyro_offset_rad_s is not None else None)
        out = np.empty(a.shape[:2], bool)
        _zvd_kernels.zvd_flags(a, g, use_gyro, off is not None, np.zeros((1, 3)) if off is None else off,
                               STANDARD_GRAVITY_M_S2, float(params.accel_min_m_s2), float(params.accel_max_m_s2),
                               float(params.var_threshold_m2_s4), params.window_samples(dt_s),
                               params.duration_samples(dt_s), float(params.gyro_max_rad_s or 0.0), out)
        return out.reshape(lead + (n,))
    if use_gyro and gyro_offset_rad_s is not None:
        gyro_rad_s = gyro_rad_s - np.asarray(gyro_offset_rad_s)[..., None, :]
    mag = np.linalg.norm(accel_m_s2, axis=-1)
    band = (mag > params.accel_min_m_s2) & (mag < params.accel_max_m_s2)
    var = _moving_variance(mag - STANDARD_GRAVITY_M_S2, params.window_samples(dt_s))
    cond = band & (var < params.var_threshold_m2_s4)
    if use_gyro:
        cond &= np.linalg.norm(gyro_rad_s, axis=-1) < params.gyro_max_rad_s
    return _min_run(cond, params.duration_samples(dt_s))



def zvd_params(params: ZvdParams | None) -> ZvdParams:
    """``params``, or Table 1's :class:`ZvdParams` for None (TypeError for anything else)."""
    p = ZvdParams() if params is None else params
    if not isinstance(p, ZvdParams):
        raise TypeError(f"params must be a ZvdParams, got {type(p).__name__}")
    return p


def _min_run(cond: np.ndarray, n_h: int) -> np.ndarray:
    """True where ``cond`` has held for the last ``n_h`` samples (causal run length)."""
    idx = np.arange(cond.shape[-1])
    last_false = np.maximum.accumulate(np.where(cond, -1, idx), axis=-1)
    return (idx - last_false) >= n_h


def rest_intervals(is_static) -> list[slice]:
    """Slices of the runs of True in a 1-D static flag, in order."""
    s = np.asarray(is_static)
    if s.dtype != bool or s.ndim != 1:
        raise ValueError(f"is_static must be a 1-D boolean array, got dtype {s.dtype}, shape {s.shape}")
    d = np.diff(np.concatenate([[0], s.astype(np.int8), [0]]))
    starts = np.flatnonzero(d == 1)
    stops = np.flatnonzero(d == -1)
    return [slice(int(a), int(b)) for a, b in zip(starts, stops)]


def rest_masks(is_static: np.ndarray, rests: list[slice], min_share: float) -> list[np.ndarray]:
    """Static flags restricted to each known rest slice, the whole rest where they flag fewer than
    ``min_share`` of it: one (T, N) boolean mask per rest.

    Preconditions
    -------------
    The caller guarantees (not checked here): ``is_static`` bool ndarray (T, N); ``rests`` slices with
    explicit ``start`` < ``stop`` within N; ``min_share`` in [0, 1]
    (:func:`mtcal.systems.surface_angle.surface_angle_batch` checks them).

    Examples
    --------
    >>> import numpy as np
    >>> [m.astype(int).tolist() for m in rest_masks(np.array([[True, False, False, False]]),
    ...                                             [slice(0, 2), slice(2, 4)], 0.1)]
    [[[1, 0, 0, 0]], [[0, 0, 1, 1]]]
    """
    out = []
    for sl in rests:
        m = np.zeros(is_static.shape, bool)
        m[:, sl] = is_static[:, sl]
        few = m.sum(axis=1) < min_share * (sl.stop - sl.start)
        m[few, sl] = True
        out.append(m)
    return out
