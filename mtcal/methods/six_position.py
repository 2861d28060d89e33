"""Six-position installation-error calibration procedure (wang2023cja §3.2).

Workflow (paper §3.2, steps 1–7, with Eq 13–15):

1. the IMU has been powered for 5 min (warm-up, modelled through
   ``ImuErrorModel.time_since_power_on_s`` and ``SensorErrors.warmup_bias``);
2. the mechanism visits yaw ±, pitch ±, roll ± (others zero) and rests 3 s at
   each position, sampled at 1 kHz, the whole run within 1 min
   (:func:`six_positions_rad`, :func:`schedule_profile`);
3. the rests are found **from the data** — a stillness detector on the gyro
   norm (:func:`stillness_from_gyro`) or on the quaternion rate
   (:func:`stillness_from_quaternions`), then :func:`find_rests`; the known
   schedule is never used;
4. the middle section of each rest is averaged (:func:`mean_quaternion`, a
   sign-aligned chordal mean) → the columns of ``A_q^s`` (Eq 14);
5. rests are matched to the reference positions (``A_e^b`` of Eq 15,
   converted with Eq 9) by nearest attitude (:func:`match_rests`);
6. Eq 13 is solved by least squares (:mod:`mtcal.methods.quaternion_lsq`, vectorised over a
   leading trial axis for Monte Carlo).

Time base: the detectors take the sample interval ``dt_s`` (s); only the
schedule generator :func:`schedule_profile` takes a rate, like the
:mod:`mtcal.core.profiles` generators it wraps.

Shapes: a record is (N, …) or (T, N, …) with a leading Monte Carlo trial
axis. All trials of one simulation share the mechanism schedule, so a sample
counts as "still" only if it is still in every trial (one set of rests).

The schedule generators (:func:`six_positions_rad`, :func:`schedule_profile`) check their
arguments; the data steps (stillness, rests, means, matching: :func:`rest_attitudes` strings
them together) trust their inputs and document their preconditions — the procedure that
checks a record once, at its edge, and calls them is
:func:`mtcal.systems.installation.calibrate_installation`, the one six-position procedure.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import linear_sum_assignment

from mtcal.core import rotations
from mtcal.core.compiled import jit
from mtcal.core.validate import as_float_array
from mtcal.core.profiles import AngleProfile, step_schedule

__all__ = ["six_positions_rad", "schedule_profile", "stillness_from_gyro",
           "stillness_from_quaternions", "find_rests", "middle_slices", "mean_quaternion",
           "rest_means", "match_rests", "rest_attitudes"]

#: Paper §3.2: rest at each position (s).
REST_S = 3.0
#: Paper §3.2: the whole calibration completes within 1 min.
MAX_RUN_S = 60.0


def six_positions_rad(yaw_rad=(np.radians(8.0), np.radians(-8.0)),
                      pitch_rad=(np.radians(-12.0), np.radians(23.0)),
                      roll_rad=(np.radians(90.0), np.radians(-90.0))) -> np.ndarray:
    """Reference positions of Eq 15: rows ``[ψ, θ, γ]`` (rad), shape (6, 3).

    Defaults are the turntable ranges of §4.1 (yaw ±8°, pitch −12°/+23°,
    roll ±90°). Order: yaw α1, α1′, pitch, pitch′, roll, roll′.
    """
    out = np.zeros((6, 3))
    for i, pair in enumerate((yaw_rad, pitch_rad, roll_rad)):
        vals = as_float_array(pair, ("yaw_rad", "pitch_rad", "roll_rad")[i], ndim=1)
        if vals.shape != (2,):
            raise ValueError(f"each range must hold 2 angles, got {vals.shape}")
        out[2 * i:2 * i + 2, i] = vals
    return out


def schedule_profile(positions_rad, *, rate_rad_s: float = np.radians(20.0), rest_s: float = REST_S,
                     initial_rest_s: float = 5.0, final_rest_s: float = 3.0,
                     fs_hz: float = 1000.0) -> AngleProfile:
    """Mechanism schedule: zero → each position (rest) → zero, minimum-jerk moves.

    Parameters
    ----------
    positions_rad : array_like, shape (K, 3)
        ``[ψ, θ, γ]`` per position (rad).
    rate_rad_s : float
        Mean move rate of the mechanism (rad/s); default 20 °/s (assumed).
    rest_s : float
        Rest at each position (s); paper 3 s.
    initial_rest_s, final_rest_s : float
        Rests at zero before and after (s); the initial one lets the QNCF level.
    fs_hz : float
        Sample rate (Hz); paper 1000 Hz.
    """
    pos = as_float_array(positions_rad, "positions_rad", ndim=2, last_dim=3)
    wp = np.vstack([np.zeros(3), pos, np.zeros(3)])
    holds = np.r_[initial_rest_s, np.full(pos.shape[0], rest_s), final_rest_s]
    return step_schedule(wp, rate_rad_s, holds, fs_hz, min_move_s=0.5)


def _moving_mean(x: np.ndarray, win: int, axis: int = -1) -> np.ndarray:
    """Centred moving mean along ``axis`` (edges use the available samples)."""
    x = np.moveaxis(x, axis, -1)
    c = np.cumsum(np.concatenate([np.zeros(x.shape[:-1] + (1,)), x], axis=-1), axis=-1)
    n = x.shape[-1]
    idx = np.arange(n)
    lo = np.clip(idx - win // 2, 0, n)
    hi = np.clip(idx - win // 2 + win, 0, n)
    out = (c[..., hi] - c[..., lo]) / (hi - lo)
    return np.moveaxis(out, -1, axis)


@jit
def _moving_mean_kernel(w, win, out):  # pragma: no cover - compiled
    """:func:`_moving_mean` of (T, N, 3) along N into ``out`` (T, 3, N): the same operations.

    The running sum is ``np.cumsum`` of ``[0, x_0, x_1, …]`` (left to right), then
    ``(c[hi] − c[lo]) / (hi − lo)`` with the clipped window bounds.
    """
    n = w.shape[1]
    c = np.empty(n + 1)
    half = win // 2
    for t in range(w.shape[0]):
        for j in range(3):
            c[0] = 0.0
            for k in range(n):
                c[k + 1] = c[k] + w[t, k, j]
            for i in range(n):
                lo = min(max(i - half, 0), n)
                hi = min(max(i - half + win, 0), n)
                out[t, j, i] = (c[hi] - c[lo]) / np.float64(hi - lo)


#: Samples from which :func:`stillness_from_gyro` runs its moving mean compiled.
_KERNEL_MIN_SAMPLES = 2048


def stillness_from_gyro(gyro_rad_s: np.ndarray, dt_s: float, window_s: float = 0.1,
                        threshold_rad_s: float = np.radians(0.2)) -> np.ndarray:
    """Still where the moving-mean gyro norm is below a threshold.

    Trusts its inputs (preconditions below; :func:`mtcal.systems.installation.detect_rests`
    checks a record and calls this).

    Parameters
    ----------
    gyro_rad_s : ndarray, shape (N, 3) or (T, N, 3)
        Angular rate (rad/s), finite float64.
    dt_s : float
        Sample interval (s), 0 < dt_s ≤ 1.
    window_s : float
        Moving-mean window (s) > 0, ``round(window_s / dt_s)`` samples; averages white noise down.
    threshold_rad_s : float
        Threshold on ‖ω‖ (rad/s) > 0; default 0.2 °/s (far above a tactical
        gyro's 0.1 s-averaged noise ≈ 0.003 °/s, far below a move).

    Returns
    -------
    ndarray of bool, shape (N,) — still in every trial.

    Examples
    --------
    >>> gyro = np.zeros((10, 3)); gyro[4:6, 0] = 1.0
    >>> stillness_from_gyro(gyro, 0.01, window_s=0.01).astype(int).tolist()
    [1, 1, 1, 1, 0, 0, 1, 1, 1, 1]
    """
    w, dt = gyro_rad_s, dt_s
    win = max(1, int(round(window_s / dt)))
    if w.dtype == np.float64 and w.shape[-2] >= _KERNEL_MIN_SAMPLES:   # one pass, no temporaries; bit-identical
        w3 = w if w.ndim == 3 else w[None]
        mean = np.empty((w3.shape[0], 3, w3.shape[1]))                 # _moving_mean's memory layout
        _moving_mean_kernel(w3, win, mean)
        mean = np.moveaxis(mean, 1, 2)
        norm = np.linalg.norm(mean if w.ndim == 3 else mean[0], axis=-1)
    else:
        norm = np.linalg.norm(_moving_mean(w, win, axis=-2), axis=-1)
    still = norm < threshold_rad_s
    return still if still.ndim == 1 else np.all(still, axis=0)



def stillness_from_quaternions(q: np.ndarray, dt_s: float, window_s: float = 0.1,
                               threshold_rad_s: float = np.radians(0.2)) -> np.ndarray:
    """Still where the mean rotation rate over a window (from the quaternions) is small.

    Rate ≈ angle(q[k − w/2], q[k + w/2]) / (w dt_s), with ``w = window_s / dt_s`` samples.
    Trusts its inputs: ``q`` float64 unit quaternions (N, 4) or (T, N, 4), scalar-first;
    ``dt_s`` the sample interval (s), 0 < dt_s ≤ 1; ``window_s`` (s) and ``threshold_rad_s``
    (rad/s) > 0.

    Returns
    -------
    ndarray of bool, shape (N,) — still in every trial.

    Examples
    --------
    >>> from mtcal.core import rotations
    >>> q = rotations.quat_from_rotvec(np.outer(np.r_[np.zeros(5), np.arange(5) * 0.1], [0.0, 0.0, 1.0]))
    >>> stillness_from_quaternions(q, 0.01, window_s=0.02).astype(int).tolist()
    [1, 1, 1, 1, 1, 0, 0, 0, 0, 0]
    """
    half = max(1, int(round(window_s / dt_s / 2)))
    n = q.shape[-2]
    idx = np.arange(n)
    lo, hi = np.clip(idx - half, 0, n - 1), np.clip(idx + half, 0, n - 1)
    ang = _angle_between(q[..., lo, :], q[..., hi, :])
    rate = ang / np.maximum(hi - lo, 1) / dt_s
    still = rate < threshold_rad_s
    return still if still.ndim == 1 else np.all(still, axis=0)


def find_rests(still: np.ndarray, dt_s: float, min_rest_s: float = 2.0) -> list[slice]:
    """Contiguous still runs lasting at least ``min_rest_s`` (s), as sample slices in time order.

    Trusts its inputs: ``still`` a 1-D boolean array sampled every ``dt_s`` (s, 0 < dt_s ≤ 1);
    a run counts if it holds at least ``min_rest_s / dt_s`` samples.

    Examples
    --------
    >>> find_rests(np.r_[np.ones(300, bool), np.zeros(10, bool), np.ones(100, bool)], 0.01)
    [slice(0, 300, None)]
    """
    edges = np.diff(np.concatenate([[0], still.astype(np.int8), [0]]))
    starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    keep = (stops - starts) >= min_rest_s / dt_s
    return [slice(int(a), int(b)) for a, b in zip(starts[keep], stops[keep])]


def middle_slices(rests: list[slice], fraction: float = 0.5) -> list[slice]:
    """The central ``fraction`` (0 < fraction ≤ 1, trusted) of each rest ("middle section", §3.2).

    Examples
    --------
    >>> middle_slices([slice(1000, 4000)], 0.5)
    [slice(1750, 3250, None)]
    """
    out = []
    for r in rests:
        n = r.stop - r.start
        m = max(1, int(round(n * fraction)))
        a = r.start + (n - m) // 2
        out.append(slice(a, a + m))
    return out


def mean_quaternion(q: np.ndarray, axis: int = -2) -> np.ndarray:
    """Sign-aligned chordal mean of unit quaternions along ``axis`` (normalised).

    Each quaternion is flipped to agree in sign with the first one along
    ``axis`` (q and −q are the same attitude), averaged, and renormalised.
    Exact for identical inputs; for a spread of a few 0.01° it equals the
    rotation-averaging mean to second order. Trusts ``q``: float64 unit quaternions (..., 4).

    Examples
    --------
    >>> mean_quaternion(np.array([[1.0, 0.0, 0.0, 0.0], [-1.0, 0.0, 0.0, 0.0]])).tolist()
    [1.0, 0.0, 0.0, 0.0]
    """
    ax = axis % q.ndim
    ref = np.take(q, [0], axis=ax)
    dot = np.sum(q * ref, axis=-1, keepdims=True)
    m = np.mean(np.where(dot < 0, -q, q), axis=ax)
    return m / np.linalg.norm(m, axis=-1, keepdims=True)


def rest_means(q_ws: np.ndarray, rests: list[slice], fraction: float = 0.5) -> np.ndarray:
    """Mean attitude over the middle ``fraction`` of each rest: (N, 4) → (K, 4), (T, N, 4) → (T, K, 4).

    Trusts its inputs: ``q_ws`` float64 unit quaternions, ``rests`` slices within its N samples,
    0 < fraction ≤ 1.

    Examples
    --------
    >>> rest_means(np.tile([1.0, 0.0, 0.0, 0.0], (10, 1)), [slice(0, 4), slice(6, 10)]).shape
    (2, 4)
    """
    return np.stack([mean_quaternion(q_ws[..., s, :], axis=-2) for s in middle_slices(rests, fraction)], axis=-2)


def match_rests(q_rest: np.ndarray, q_ref: np.ndarray, max_angle_rad: float = np.radians(5.0)) -> np.ndarray:
    """Assign one detected rest to each reference position (nearest attitude, Hungarian).

    Parameters
    ----------
    q_rest : ndarray, shape (R, 4) or (T, R, 4)
        Mean sensor attitude of each detected rest (trials: distances averaged); unit, float64.
    q_ref : ndarray, shape (K, 4) or (T, K, 4)
        Reference attitudes (Eq 9 of Eq 15's angles); unit, float64.
    max_angle_rad : float
        Largest accepted distance (rad) between a rest and its position; must
        exceed installation error + yaw offset, and stay below half the
        spacing of the positions.

    Returns
    -------
    ndarray of int, shape (K,)
        Index of the rest used for each reference position.

    Raises
    ------
    ValueError
        Fewer rests than positions, or a position without a rest within ``max_angle_rad``.

    Examples
    --------
    >>> from mtcal.core import rotations
    >>> ref = rotations.quat_from_euler_zxy(np.radians([0.0, 10.0]), np.zeros(2), np.zeros(2))
    >>> match_rests(ref[::-1], ref).tolist()
    [1, 0]
    """
    k, r = q_ref.shape[-2], q_rest.shape[-2]
    if r < k:
        raise ValueError(f"found {r} rests in the record but {k} reference positions were given; "
                         f"each position needs a rest of at least min_rest_s")
    dist = _angle_between(q_rest[..., :, None, :], q_ref[..., None, :, :])
    if dist.ndim == 3:
        dist = dist.mean(axis=0)
    rows, cols = linear_sum_assignment(dist.T)  # rows: reference, cols: rest
    worst = dist[cols, rows].max()
    if worst > max_angle_rad:
        bad = int(rows[np.argmax(dist[cols, rows])])
        raise ValueError(f"reference position {bad + 1} has no rest within "
                         f"{np.degrees(max_angle_rad):.1f} deg (nearest {np.degrees(worst):.2f} deg); "
                         f"check the positions file or the installation error")
    out = np.empty(k, dtype=int)
    out[rows] = cols
    return out


def _angle_between(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Attitude difference (rad) of checked unit quaternions (same arithmetic as ``rotations.quat_angle_between``)."""
    d = rotations.hamilton(p * _CONJ, q)
    return 2.0 * np.arctan2(np.linalg.norm(d[..., 1:], axis=-1), np.abs(d[..., 0]))


_CONJ = np.array([1.0, -1.0, -1.0, -1.0])


def rest_attitudes(q_ws: np.ndarray, q_ref: np.ndarray, dt_s: float, *, gyro_rad_s: np.ndarray | None = None,
                   rests: list | None = None, fraction: float = 0.5, min_rest_s: float = 2.0,
                   threshold_rad_s: float = np.radians(0.2), window_s: float = 0.1,
                   max_match_rad: float = np.radians(5.0), q_detect: np.ndarray | None = None,
                   in_order: bool = False):
    """Rests → middle-section means → matched to the references (steps 3–5 of §3.2, Eq 14 columns).

    Trusts its inputs (the procedure :func:`mtcal.systems.installation.calibrate_installation`
    checks them): ``q_ws`` (N, 4) or (T, N, 4) float64 unit quaternions sampled every ``dt_s``
    (s, 0 < dt_s ≤ 1); ``q_ref`` (K, 4) or (T, K, 4) unit quaternions; ``gyro_rad_s`` like
    ``q_ws[..., :3]``; ``rests`` slices within the N samples; settings positive, 0 < fraction ≤ 1.

    Rests are ``rests`` if given, else :func:`find_rests` of :func:`stillness_from_gyro` on
    ``gyro_rad_s`` if given, else of :func:`stillness_from_quaternions` on ``q_detect`` (default
    ``q_ws``). ``in_order``: the rests are known by construction (a simulated schedule) — rest k
    belongs to position k, no matching by attitude (and no ``max_match_rad`` window); else
    :func:`match_rests`.

    Returns
    -------
    rests : list of slice
        Every rest (time order).
    matched : ndarray (K,) of int
        Index into ``rests`` for each position.
    q_sensor : ndarray (K, 4) or (T, K, 4)
        Middle-section mean of ``q_ws`` at each matched rest.

    Raises
    ------
    ValueError
        Fewer rests than positions; a position without a rest (see :func:`match_rests`).

    Examples
    --------
    >>> from mtcal.core import rotations
    >>> ref = rotations.quat_from_euler_zxy(np.radians([0.0, 10.0]), np.zeros(2), np.zeros(2))
    >>> q = np.repeat(ref[::-1], 300, axis=0)
    >>> rests, matched, q_s = rest_attitudes(q, ref, 0.01, rests=[slice(0, 300), slice(300, 600)])
    >>> matched.tolist(), bool(np.allclose(q_s, ref))
    ([1, 0], True)
    """
    if rests is None:
        if gyro_rad_s is not None:
            still = stillness_from_gyro(gyro_rad_s, dt_s, window_s, threshold_rad_s)
        else:
            still = stillness_from_quaternions(q_ws if q_detect is None else q_detect, dt_s, window_s,
                                               threshold_rad_s)
        rests = find_rests(still, dt_s, min_rest_s)
    if len(rests) < q_ref.shape[-2]:
        raise ValueError(f"too few rests: found {len(rests)} still periods of >= {min_rest_s:g} s, "
                         f"need one for each of the {q_ref.shape[-2]} reference positions")
    means = rest_means(q_ws, rests, fraction)
    if in_order:
        if len(rests) != q_ref.shape[-2]:
            raise ValueError(f"rests in schedule order: got {len(rests)} rests for {q_ref.shape[-2]} positions")
        matched = np.arange(len(rests))
    else:
        matched = match_rests(means, q_ref, max_match_rad)
    return rests, matched, means[..., matched, :]
