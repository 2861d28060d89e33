"""Gravity-referenced gyro scale: the accelerometer's tilt rate against the gyro's, sample window by window.

Wherever the specific force is gravity (``‖ā‖ ≈ g``), its direction ``â`` in the
sensor frame turns with the body: ``dâ/dt = â × ω``, so over a window of length
``T`` the direction change ``â_k × â_(k+1) ≈ −ω⊥ T`` with ``ω⊥`` the part of
the rate perpendicular to gravity. Regressing the accelerometer's change
``u_k = â_k × â_(k+1)`` on the gyro's prediction ``p_k = −(ω̄_k − b)⊥ T``
gives the gyro's scale as the accelerometer sees it:

``s = Σ u·p / Σ p·p``   (1 for rad/s and the right time base, π/180 for
deg/s read as rad/s, 0.1 for a time column 10× too slow …)

and the correlation ``r = Σ u·p / √(Σ u·u Σ p·p)`` says whether the record
holds enough tilting motion to decide. Only consecutive windows whose mean
``‖ā‖`` lies within ``band_fraction`` of the median are used (linear
acceleration tilts ``â`` without a rotation; windows whose accelerometer varies
by more than that fraction are dropped too), and the gyro bias ``b`` is the
median rate of the windows whose ``â`` does not move. Unlike a check between
rests this needs no rest pair: slow moves and quasi-static stretches count.

References
----------
wang2022sensors Sec. 2.2 (static gravity reading ``R(θ, v)ᵀ ā0``: a rotation
shows as a change of the accelerometer direction); wang2023cja Eq 5 (the same
gravity reference corrects the QNCF's gyro integration).

Examples
--------
>>> import numpy as np
>>> dt = 0.01
>>> t = np.arange(2000) * dt
>>> rate = 0.5 * np.sin(2 * np.pi * 0.2 * t)                    # rad/s about x
>>> angle = np.cumsum(rate) * dt
>>> accel = 9.81 * np.column_stack([np.zeros_like(t), np.sin(angle), np.cos(angle)])
>>> gyro = np.column_stack([rate, np.zeros_like(t), np.zeros_like(t)])
>>> res = tilt_rate_scale(gyro, accel, dt)
>>> round(res["scale"], 2), bool(res["correlation"] > 0.9)
(1.0, True)
>>> round(tilt_rate_scale(np.degrees(gyro), accel, dt)["scale"] * 180 / np.pi, 2)  # deg/s read as rad/s
1.0
"""

from __future__ import annotations

import warnings

import numpy as np

__all__ = ["tilt_rate_scale", "check_tilt_rate_scale", "scale_hint", "tilt_seen", "warm_up", "MIN_CORRELATION",
           "MIN_AGREEMENT_CORRELATION", "MIN_LONG_AGREEMENT_CORRELATION",
           "MIN_TILT_RAD", "MIN_WINDOWS", "MIN_STRONG_TILT_RAD", "SCALE_HINTS"]

#: Correlation above which the scale is trusted.
MIN_CORRELATION = 0.7
#: Correlation above which a scale in [0.5, 2] counts as agreement.
MIN_AGREEMENT_CORRELATION = 0.5
#: Lower correlation that still counts as agreement when both sensors tilt ≥ MIN_TILT_RAD over the windows
#: used: long records with long rests dilute the correlation with windows of pure noise (a 1-hour hinge log
#: in rad/s: scale 0.997, correlation 0.47, 540° / 190° of tilt), while a unit or time-base error moves the
#: *scale* (57×, 10×, 1000×) far outside [0.5, 2]; a scale fitted on little tilt is never trusted this way.
MIN_LONG_AGREEMENT_CORRELATION = 0.3
#: Fewest window pairs, and least accelerometer tilt (rad), for a decision on a high correlation alone.
MIN_WINDOWS = 5
MIN_STRONG_TILT_RAD = np.radians(1.0)
#: Least total accelerometer tilt (rad, summed over the windows used) for a decision.
MIN_TILT_RAD = np.radians(10.0)
#: Scale → what it means (the mtcal options that fix it).
SCALE_HINTS = {np.pi / 180: "gyro looks like deg/s read as rad/s: use --gyro-unit deg/s",
               180 / np.pi: "gyro looks like rad/s read as deg/s: drop --gyro-unit deg/s",
               10.0: "time column 10x too fast? (check --time-unit / time_s)",
               0.1: "time column 10x too slow? (check --time-unit / time_s)",
               1000.0: "time in s labelled ms? (check --time-unit)",
               0.001: "time in ms read as s? use --time-unit ms"}


def tilt_rate_scale(gyro_rad_s: np.ndarray, accel_m_s2: np.ndarray, dt_s: float, *, window_s: float = 0.05,
                    band_fraction: float = 0.05, skip: np.ndarray | None = None) -> dict:
    """Gyro scale seen by the accelerometer's tilt rate (see the module docstring).

    Parameters
    ----------
    gyro_rad_s : ndarray, shape (N, 3)
        Angular rate (rad/s), sensor frame.
    accel_m_s2 : ndarray, shape (N, 3)
        Specific force (m/s²), sensor frame.
    dt_s : float
        Sample interval (s).
    window_s : float
        Window length ``T`` (s); at least 3 samples.
    band_fraction : float
        Windows with ``|‖ā‖ − g| > band_fraction g``, or an accelerometer standard deviation
        (rms over axes) above ``band_fraction g``, are not used (linear acceleration).
    skip : ndarray (N,) of bool, optional
        Samples not to trust (e.g. a clipped gyro); windows holding one are not used.

    Returns
    -------
    dict
        ``scale`` (accelerometer tilt / gyro tilt, NaN without motion),
        ``correlation`` (−1 … 1), ``accel_tilt_rad`` and ``gyro_tilt_rad``
        (summed ``‖u‖`` and ``‖p‖`` over the windows used), ``windows`` (pairs used),
        ``accel_spread_rad`` (99th percentile of the angle between a quasi-static
        window's gravity direction and their mean: how far the record tilts).

    Raises
    ------
    ValueError
        A value not finite: checked in the same compiled pass that forms the window means (one
        pass over the record, no numpy temporaries), so it costs nothing of its own.

    Preconditions
    -------------
    The caller guarantees (not checked here): ``gyro_rad_s`` and ``accel_m_s2`` float64 arrays of one
    shape (N, 3) (rad/s, m/s²; C-contiguous arrays are used as they are, others copied);
    ``dt_s``, ``window_s`` and ``band_fraction`` finite and > 0; ``skip`` None or a boolean (N,) array.
    The edges that check a record once: :func:`mtcal.filters.qncf.qncf`,
    :func:`mtcal.systems.plausibility.check_units` (via :func:`check_tilt_rate_scale`) and
    :func:`mtcal.systems.surface_angle.surface_angle_record`.

    References
    ----------
    wang2022sensors Sec. 2.2 (gravity direction turns with the body).
    """
    w = np.ascontiguousarray(gyro_rad_s, dtype=np.float64)
    a = np.ascontiguousarray(accel_m_s2, dtype=np.float64)
    skip = None if skip is None else np.ascontiguousarray(skip, dtype=np.bool_)
    # numba: loaded on first use, not by import
    from mtcal.methods._tilt_rate_kernels import percentile_linear, window_fit, window_stats

    n = a.shape[0]
    m = max(3, int(round(window_s / dt_s)))
    # one compiled pass: window means and accelerometer spread, skipped windows, finiteness of every value
    am, a_std, wm, skipped, gyro_finite, accel_finite = window_stats(
        w, a, min(m, n + 1), skip if skip is not None else np.zeros(0, np.bool_), skip is not None)
    if not gyro_finite:
        raise ValueError("gyro_rad_s must be finite (no NaN or inf)")
    if not accel_finite:
        raise ValueError("accel_m_s2 must be finite (no NaN or inf)")
    nb = am.shape[0]
    nan = {"scale": float("nan"), "correlation": float("nan"), "accel_tilt_rad": 0.0, "gyro_tilt_rad": 0.0,
           "windows": 0, "accel_spread_rad": 0.0}
    if nb < 3:
        return nan
    # the glue on the window means, compiled in numpy's arithmetic (bit-identical to the numpy expressions)
    status, ah_ok, ref, up, pp, uu, accel_tilt, gyro_tilt, count = window_fit(am, a_std, wm, skipped, m, dt_s,
                                                                            band_fraction)
    if status == 0:
        return nan
    ref /= max(float(np.linalg.norm(ref)), 1e-12)  # accelerometer spread: BLAS product, numpy's arccos
    spread = float(percentile_linear(np.arccos(np.clip(ah_ok @ ref, -1.0, 1.0)), 99 / 100))
    nan["accel_spread_rad"] = spread
    if status == 1:
        return nan
    out = {"scale": up / pp if pp > 0 else float("nan"),
           "correlation": float(up / np.sqrt(pp * uu)) if pp > 0 and uu > 0 else float("nan"),
           "accel_tilt_rad": float(accel_tilt), "gyro_tilt_rad": float(gyro_tilt), "windows": int(count),
           "accel_spread_rad": spread}
    return out


def check_tilt_rate_scale(gyro_rad_s: np.ndarray, accel_m_s2: np.ndarray, dt_s: float, *, max_ratio: float = 5.0,
                          excess: str = "raise", skip: np.ndarray | None = None) -> dict:
    """Raise when the accelerometer's tilt rate shows the gyro off by more than ``max_ratio``.

    Decides when the record tilts (:func:`tilt_seen` ≥ :data:`MIN_TILT_RAD`) or
    when the evidence is strong (correlation ≥ :data:`MIN_CORRELATION` over ≥
    :data:`MIN_WINDOWS` windows and ≥ :data:`MIN_STRONG_TILT_RAD` of accelerometer
    tilt): a correlation ≥ :data:`MIN_CORRELATION` with a scale outside
    ``[1/max_ratio, max_ratio]``, or (tilting record) a gyro that predicts more
    than ``max_ratio`` times the tilt the accelerometer shows, is refused; a scale
    in ``[0.5, 2]`` with strong evidence, or with a correlation ≥
    :data:`MIN_AGREEMENT_CORRELATION` on a tilting record, decides that the units fit.

    Parameters
    ----------
    gyro_rad_s, accel_m_s2 : ndarray, shape (N, 3)
        Angular rate (rad/s) and specific force (m/s²), sensor frame.
    dt_s : float
        Sample interval (s).
    max_ratio : float
    excess : {"raise", "warn"}
        What a gyro tilt above ``max_ratio`` times the accelerometer's does when
        the correlation does not also show the scale (``warn``: ``UserWarning``).
    skip : ndarray (N,) of bool, optional
        Samples not to use (:func:`tilt_rate_scale`).

    Returns
    -------
    dict
        :func:`tilt_rate_scale` result plus ``decided`` (bool).

    Raises
    ------
    ValueError
        The gyro is implausible for rad/s at the sample rate given; the message
        names the scale found and its likely cause; a value not finite (:func:`tilt_rate_scale`).

    Preconditions
    -------------
    As :func:`tilt_rate_scale` (not checked here); ``max_ratio`` > 0; ``excess`` one of the two words.

    Examples
    --------
    >>> import numpy as np
    >>> check_tilt_rate_scale(np.zeros((300, 3)), np.tile([0, 0, 9.81], (300, 1)), 0.01)["decided"]
    False
    """
    res = tilt_rate_scale(gyro_rad_s, accel_m_s2, dt_s, skip=skip)
    res["decided"] = False
    if res["windows"] == 0:
        return res
    s, r = res["scale"], res["correlation"]
    big = tilt_seen(res) >= MIN_TILT_RAD
    strong = (np.isfinite(r) and r >= MIN_CORRELATION and res["windows"] >= MIN_WINDOWS
              and res["accel_tilt_rad"] >= MIN_STRONG_TILT_RAD)
    over = big and res["gyro_tilt_rad"] > max_ratio * res["accel_tilt_rad"]
    off = bool(np.isfinite(s) and (big or strong) and r >= MIN_CORRELATION
               and not (1.0 / max_ratio <= s <= max_ratio))
    long_motion = (r >= MIN_LONG_AGREEMENT_CORRELATION and res["accel_tilt_rad"] >= MIN_TILT_RAD
                   and res["gyro_tilt_rad"] >= MIN_TILT_RAD)
    fits = bool(np.isfinite(s) and 0.5 <= s <= 2.0
                and (strong or (big and (r >= MIN_AGREEMENT_CORRELATION or long_motion))))
    res["decided"] = bool(over or off or fits)
    if excess == "warn" and over and not off:
        warnings.warn(f"gyro implausible for rad/s at dt {dt_s:.4g} s: it predicts "
                      f"{np.degrees(res['gyro_tilt_rad']):.1f} deg of tilt where the accelerometer shows "
                      f"{np.degrees(res['accel_tilt_rad']):.1f} deg", UserWarning, stacklevel=3)
        return res
    if over or off:
        hint = scale_hint(s if off else res["accel_tilt_rad"] / max(res["gyro_tilt_rad"], 1e-300))
        raise ValueError(f"gyro implausible for rad/s at dt {dt_s:.4g} s: where the accelerometer reads gravity "
                         f"it tilts {np.degrees(res['accel_tilt_rad']):.1f} deg in total but the gyro "
                         f"{np.degrees(res['gyro_tilt_rad']):.1f} deg (tilt-rate scale {s:.3g}, correlation "
                         f"{r:.2f}, limit {max_ratio:g}x); {hint}")
    return res


def tilt_seen(res: dict) -> float:
    """How much the record tilts (rad): the accelerometer's spread or the gyro's tilt, and the accelerometer's
    summed tilt when it correlates with the gyro (≥ :data:`MIN_CORRELATION`, so it is motion, not noise)."""
    seen = max(res["accel_spread_rad"], res["gyro_tilt_rad"])
    if np.isfinite(res["correlation"]) and res["correlation"] >= MIN_CORRELATION:
        seen = max(seen, res["accel_tilt_rad"])
    return float(seen)


def scale_hint(scale: float) -> str:
    """The likely cause of a gyro scale (``SCALE_HINTS`` entry within a factor 2, else a generic hint)."""
    if np.isfinite(scale) and scale > 0:
        best = min(SCALE_HINTS, key=lambda k: abs(np.log(scale / k)))
        if abs(np.log(scale / best)) < np.log(2.0):
            return SCALE_HINTS[best]
    return "check --gyro-unit, --gyro-scale and the time column"


def warm_up() -> None:
    """Compile (or load from numba's cache) the compiled window pass of :func:`tilt_rate_scale`.

    Examples
    --------
    >>> warm_up()
    """
    from mtcal.methods._tilt_rate_kernels import warm_up as warm

    warm()
