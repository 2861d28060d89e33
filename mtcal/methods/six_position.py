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
   leading trial axis for Monte Carlo), gated and turned into installation angles:
   :func:`calibrate_from_rests` strings steps 3–6 together on a sensor attitude.

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

from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from mtcal.core import metrics, rotations
from mtcal.core.compiled import jit
from mtcal.core.validate import as_float_array
from mtcal.core.profiles import AngleProfile, middle_slices, step_schedule
from mtcal.methods import constrained_fit, quaternion_lsq
from mtcal.methods.constrained_fit import So4Projection

__all__ = ["six_positions_rad", "schedule_profile", "stillness_from_gyro",
           "stillness_from_quaternions", "find_rests", "still_rests", "middle_slices", "mean_quaternion",
           "rest_means", "match_rests", "rest_attitudes", "MAX_CONDITION", "MODELS", "PositionCalibration",
           "PositionsRefused", "calibrate_from_rests", "calibrate_session", "missing_rotation_axis", "angles_sigma"]

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

    Preconditions (trusted, not checked here): each of ``yaw_rad``, ``pitch_rad``, ``roll_rad`` is
    two finite angles (rad). The public edges that take positions check them where they enter
    (:func:`schedule_profile`; the procedures of :mod:`mtcal.systems.installation`; a study's
    scenario checks its position settings when it is made).

    References
    ----------
    wang2023cja §3.2 (six positions), §4.1 (turntable ranges), Eq 15.

    Examples
    --------
    >>> np.degrees(six_positions_rad()).round(6)[[0, 3, 4]].tolist()
    [[8.0, 0.0, 0.0], [0.0, 23.0, 0.0], [0.0, 0.0, 90.0]]
    """
    out = np.zeros((6, 3))
    for i, pair in enumerate((yaw_rad, pitch_rad, roll_rad)):
        out[2 * i:2 * i + 2, i] = pair
    return out


def schedule_profile(positions_rad, *, rate_rad_s: float = np.radians(20.0), rest_s: float = REST_S,
                     initial_rest_s: float = 5.0, final_rest_s: float = 3.0,
                     fs_hz: float = 1000.0) -> AngleProfile:
    """Mechanism schedule: zero → each position (rest) → zero, minimum-jerk moves.

    Takes ``fs_hz``, not ``dt_s`` (the exception of the study template's time-base rule): it makes the
    samples of :func:`mtcal.core.profiles.step_schedule`, at ``t_k = k / fs_hz`` (the sensor spec owns the
    rate), their count ``floor(duration · fs_hz)``; ``1 / (1 / fs)`` is not ``fs`` exactly for 640 of the
    integer rates 1–5000 Hz, so a rate rebuilt from ``dt_s`` would move sample times by an ulp and could
    change a count at a tie.

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


def still_rests(dt_s: float, min_rest_s: float = 2.0, window_s: float = 0.1,
                threshold_rad_s: float = np.radians(0.2), *, gyro_rad_s: np.ndarray | None = None,
                q: np.ndarray | None = None) -> list[slice]:
    """Rests of a record (§3.2 step 3): :func:`find_rests` of :func:`stillness_from_gyro` on ``gyro_rad_s``
    if given, else of :func:`stillness_from_quaternions` on ``q``.

    Trusts its inputs, as those functions (``gyro_rad_s`` (N, 3) or (T, N, 3) finite float64, or ``q``
    float64 unit quaternions (N, 4) or (T, N, 4); settings positive, ``dt_s`` ≤ 1 s).

    Examples
    --------
    >>> gyro = np.zeros((1000, 3)); gyro[300:500, 2] = 0.5
    >>> still_rests(0.01, gyro_rad_s=gyro)
    [slice(0, 296, None), slice(505, 1000, None)]
    """
    if gyro_rad_s is not None:
        still = stillness_from_gyro(gyro_rad_s, dt_s, window_s, threshold_rad_s)
    else:
        still = stillness_from_quaternions(q, dt_s, window_s, threshold_rad_s)
    return find_rests(still, dt_s, min_rest_s)




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
    slices = middle_slices(rests, fraction)
    if q_ws.dtype == np.float64 and q_ws.ndim in (2, 3) and q_ws.flags.c_contiguous and slices:
        q3 = q_ws if q_ws.ndim == 3 else q_ws[None]
        sums = np.empty((q3.shape[0], len(slices), 4))
        _rest_sums_kernel(q3, np.array([s.start for s in slices], np.int64),
                          np.array([s.stop for s in slices], np.int64), sums)
        m = sums / np.array([s.stop - s.start for s in slices], np.float64)[:, None]   # np.mean: sum / count
        means = m / np.linalg.norm(m, axis=-1, keepdims=True)
        return means if q_ws.ndim == 3 else means[0]
    return np.stack([mean_quaternion(q_ws[..., s, :], axis=-2) for s in slices], axis=-2)


@jit
def _rest_sums_kernel(q, starts, stops, out):  # pragma: no cover - compiled
    """Sums (T, K, 4) of :func:`mean_quaternion`'s sign-aligned quaternions over ``q[t, starts[k]:stops[k]]``
    (T, N, 4): numpy's operations — the dot with the window's first quaternion summed left to right (an
    axis of 4), ``−q`` where it is negative, the window summed sample by sample from +0 (numpy's
    outer-axis reduction: an all −0 component sums to +0) — so :func:`rest_means` gives ``mean_quaternion``'s numbers (tested)."""
    for t in range(q.shape[0]):
        for k in range(starts.size):
            a, b = starts[k], stops[k]
            r0, r1, r2, r3 = q[t, a, 0], q[t, a, 1], q[t, a, 2], q[t, a, 3]
            s0 = s1 = s2 = s3 = 0.0
            for i in range(a, b):
                q0, q1, q2, q3 = q[t, i, 0], q[t, i, 1], q[t, i, 2], q[t, i, 3]
                if ((q0 * r0 + q1 * r1) + q2 * r2) + q3 * r3 < 0.0:
                    q0, q1, q2, q3 = -q0, -q1, -q2, -q3
                s0, s1, s2, s3 = s0 + q0, s1 + q1, s2 + q2, s3 + q3
            out[t, k, 0], out[t, k, 1], out[t, k, 2], out[t, k, 3] = s0, s1, s2, s3


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
    """Attitude difference (rad) of checked unit quaternions, broadcast against each other.

    ``2 atan2(‖d[1:]‖, |d[0]|)`` of ``d = p* ⊗ q``: the arithmetic of ``rotations.quat_angle_between``
    (the Hamilton product's terms in :func:`mtcal.core.rotations.hamilton`'s order, numpy's norm of 3),
    in one compiled pass over the pairs (:func:`mtcal.methods._constrained_kernels.angle_arguments`, no
    (…, 4) temporaries), ``arctan2`` by numpy: the same numbers (tested bit for bit).
    """
    from mtcal.methods._constrained_kernels import angle_arguments   # lazy: numba loads on first use

    shape = np.broadcast_shapes(p.shape, q.shape)
    pairs = [np.ascontiguousarray(np.broadcast_to(x, shape), dtype=np.float64).reshape(-1, 4) for x in (p, q)]
    rows = pairs[0].shape[0]
    vec_norm, scalar_abs, has_nan = np.empty(rows), np.empty(rows), np.empty(rows, dtype=np.bool_)
    angle_arguments(pairs[0], pairs[1], vec_norm, scalar_abs, has_nan)
    ang = 2.0 * np.arctan2(vec_norm, scalar_abs)
    ang[has_nan] = np.nan                                       # a NaN in p propagates, as through the product
    return ang.reshape(shape[:-1])[()]


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
    rests, means = _rests_and_means(q_ws, q_ref.shape[-2], dt_s, gyro_rad_s, rests, fraction, min_rest_s,
                                    threshold_rad_s, window_s, q_detect)
    matched = _matched(means, q_ref, max_match_rad, in_order)
    return rests, matched, means[..., matched, :]


def _rests_and_means(q_ws, k, dt_s, gyro_rad_s, rests, fraction, min_rest_s, threshold_rad_s, window_s, q_detect):
    """:func:`rest_attitudes`' first steps: the rests (given, or :func:`still_rests`; at least ``k``) and the
    middle-section mean attitude of each, ``(rests, means (R, 4) or (T, R, 4))``."""
    if rests is None:
        rests = still_rests(dt_s, min_rest_s, window_s, threshold_rad_s, gyro_rad_s=gyro_rad_s,
                            q=q_ws if q_detect is None else q_detect)
    if len(rests) < k:
        raise ValueError(f"too few rests: found {len(rests)} still periods of >= {min_rest_s:g} s, "
                         f"need one for each of the {k} reference positions")
    return rests, rest_means(q_ws, rests, fraction)


def _matched(means, q_ref, max_match_rad: float, in_order: bool) -> np.ndarray:
    """:func:`rest_attitudes`' last step: the rest of each position, in schedule order or by :func:`match_rests`."""
    if not in_order:
        return match_rests(means, q_ref, max_match_rad)
    if means.shape[-2] != q_ref.shape[-2]:
        raise ValueError(f"rests in schedule order: got {means.shape[-2]} rests for {q_ref.shape[-2]} positions")
    return np.arange(means.shape[-2])


# --------------------------------------------------------------------------- the calibration from rests
#: Gate: condition number of ``A_q^s (A_q^s)ᵀ`` (Eq 13) above which the positions are refused.
MAX_CONDITION = 1e4

#: Error-map models of :func:`calibrate_from_rests`: name → (parameters, what the positions must span).
MODELS = {"eq13": (16, "rotations about all three axes (4 linearly independent quaternions)"),
          "so4": (6, "rotations about two axes (3 linearly independent quaternions)"),
          "mounting": (3, "rotations about two axes")}


@dataclass(frozen=True)
class PositionCalibration:
    """Outcome of :func:`calibrate_from_rests` (leading trial axis T iff the input had one).

    Attributes
    ----------
    q_hat : ndarray (4, 4) or (T, 4, 4)
        Q̂_s^b of Eq 13: ``q_body ≈ normalize(Q̂ q_sensor)`` (sensor attitude zeroed at its first sample).
    projection : So4Projection
        Nearest SO(4) matrix ``L(p) R(r)`` of Q̂ and its distance (dimensionless).
    mounting_quaternion_q_bs : ndarray (4,) or (T, 4)
        ``q_bs = r*`` (sensor = body ⊗ q_bs), scalar-first.
    installation_angles_rad : ndarray (3,) or (T, 3)
        ``[α1 about z, α2 about y, α3 about x]`` (rad), inverse of Eq 1 of ``q_bs``.
    condition : float or ndarray (T,)
        Condition number of the aligned ``A_q^s (A_q^s)ᵀ`` (dimensionless).
    positions_rad : ndarray (K, 3) or (T, K, 3)
        Reference ``[ψ, θ, γ]`` (rad, Eq 8 frame) fed to Eq 13.
    q_reference : ndarray (K, 4) or (T, K, 4)
        Eq 9 quaternions of ``positions_rad``.
    rests : list of slice
        Every rest used for matching (time order, sample indices).
    matched : ndarray (K,) of int
        Index into ``rests`` of the rest used for each position.
    q_sensor : ndarray (K, 4) or (T, K, 4)
        Middle-section mean of the zeroed sensor attitude at each matched rest (Eq 14 columns).
    euler_before_rad, euler_after_rad : ndarray (K, 3) or (T, K, 3)
        Eq 8 angles of ``q_sensor`` and of ``Q̂ q_sensor`` (rad).
    error_before_rad, error_after_rad : ndarray (K, 3) or (T, K, 3)
        Those angles minus ``positions_rad``, wrapped to [−π, π) (rad).
    residual_rad : ndarray (K,) or (T, K)
        Rotation angle between ``Q̂ q_sensor`` and the reference (rad).
    angles_sigma_rad : ndarray (3,) or None
        1σ of ``installation_angles_rad`` from the fit covariance (:func:`angles_sigma`), when asked for.
    """

    q_hat: np.ndarray
    projection: So4Projection
    mounting_quaternion_q_bs: np.ndarray
    installation_angles_rad: np.ndarray
    condition: np.ndarray
    positions_rad: np.ndarray
    q_reference: np.ndarray
    rests: list
    matched: np.ndarray
    q_sensor: np.ndarray
    euler_before_rad: np.ndarray
    euler_after_rad: np.ndarray
    error_before_rad: np.ndarray
    error_after_rad: np.ndarray
    residual_rad: np.ndarray
    angles_sigma_rad: np.ndarray | None = None

    @property
    def so4_distance(self) -> np.ndarray:
        """``‖Q̂ − L(p) R(r)‖_F`` (dimensionless)."""
        return self.projection.distance

    @property
    def matched_rests(self) -> list[slice]:
        """The rest (sample slice) used for each position, in position order."""
        return [self.rests[i] for i in self.matched]


class PositionsRefused(ValueError):
    """:func:`calibrate_from_rests` refused a record (no rest for a position, a gate); the message says why.

    Made as ``PositionsRefused(message, q_ws, rest_means=None)``; ``args`` holds the three (an exception that
    keeps its data in ``args`` pickles as it was made, e.g. across processes) and ``str()`` is the message.

    Attributes
    ----------
    q_ws : ndarray (N, 4) or (T, N, 4)
        The sensor attitude the calibration was given, before zeroing: a caller looking for the
        cause (a convention mistake) starts from it instead of making it again.
    rest_means : ndarray (R, 4) or (T, R, 4), or None
        The middle-section mean of the (zeroed) attitude at every rest, when the refusal came after
        they were made (a position without a rest, a gate): what each rest measured, for the same reason.

    Examples
    --------
    >>> exc = PositionsRefused("too few rests", np.zeros((3, 4)))
    >>> str(exc), exc.q_ws.shape, exc.rest_means is None
    ('too few rests', (3, 4), True)
    >>> exc
    PositionsRefused('too few rests')
    """

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ""

    def __repr__(self) -> str:
        """The message only (the arrays in ``args`` are data, not part of the exception's name)."""
        return f"{type(self).__name__}({str(self)!r})"

    @property
    def q_ws(self) -> np.ndarray | None:
        return self.args[1] if len(self.args) > 1 else None

    @property
    def rest_means(self) -> np.ndarray | None:
        return self.args[2] if len(self.args) > 2 else None


def calibrate_from_rests(q_ws: np.ndarray, positions_rad: np.ndarray, q_reference: np.ndarray, dt_s: float, *,
                         model: str = "eq13",
                         q_hat: np.ndarray | None = None, zero: bool = True, gyro_rad_s: np.ndarray | None = None,
                         rests: list | None = None, fraction: float = 0.5, min_rest_s: float = 2.0,
                         threshold_rad_s: float = np.radians(0.2), window_s: float = 0.1,
                         max_match_rad: float = np.radians(5.0), in_order: bool = False,
                         max_condition: float = MAX_CONDITION, max_so4_distance: float = np.inf,
                         max_residual_rad: float = np.inf, sigma: bool = False) -> PositionCalibration:
    """Steps 2–6 of the six-position procedure on a sensor attitude: zeroing → rests → Eq 13 → gates → angles.

    The sensor attitude zeroed at its first sample (``zero``; §4.1 "initial angles 0°"), its rests
    found or given, their middle sections averaged and matched to the references ``q_reference``
    (Eq 9 of ``positions_rad``, :func:`rest_attitudes`); then the error map of ``model`` fitted (Eq 13's 16-parameter
    least squares, the nearest SO(4) map ``L(p) R(r)`` or the mounting alone ``L(c) R(c*)``) — or ``q_hat``
    taken as given (a verification: no gate) — its SO(4) projection, Eq 10 at the rests, the installation
    angles of the mounting ``q_bs = r*`` (inverse of Eq 1), and the gates (conditioning of the positions,
    distance from SO(4), residual).

    Trusts its inputs (:func:`mtcal.systems.installation.calibrate_installation` checks them): ``q_ws``
    float64 unit quaternions (N, 4) or (T, N, 4) sampled every ``dt_s`` (s, 0 < dt_s ≤ 1);
    ``positions_rad`` (K, 3) or (T, K, 3) finite, K ≥ 4, and ``q_reference`` their Eq 9 attitudes
    (:func:`mtcal.core.rotations.quat_from_euler_zxy` of yaw, pitch, roll: made once, where the
    positions are checked); ``q_hat`` finite (4, 4) or (T, 4, 4);
    ``gyro_rad_s`` like ``q_ws[..., :3]``; ``rests`` slices within the N samples; settings positive,
    0 < fraction ≤ 1; ``model`` one of :data:`MODELS`; a gate of ``inf`` is off.

    Returns
    -------
    PositionCalibration
        ``angles_sigma_rad`` (:func:`angles_sigma`) with ``sigma`` (one record, no trial axis).

    Raises
    ------
    PositionsRefused
        Too few rests; a position without a rest; degenerate positions; a gate refusing Q̂ (the message
        names the measured value and the limit).

    Examples
    --------
    A sensor mounted without error, its attitude logged at six positions (rest k = position k):

    >>> from mtcal.core import profiles, rotations
    >>> pos = six_positions_rad()
    >>> prof = schedule_profile(pos, fs_hz=50.0)
    >>> q = profiles.trajectory_from_euler_zxy(prof).q_wb
    >>> q_ref = rotations.quat_from_euler_zxy(pos[:, 0], pos[:, 1], pos[:, 2])            # Eq 9
    >>> cal = calibrate_from_rests(q, pos, q_ref, 0.02, rests=prof.hold_slices()[1:-1], in_order=True)
    >>> bool(np.allclose(cal.q_hat, np.eye(4))), float(cal.residual_rad.max()) < 1e-12
    (True, True)
    """
    q_zeroed = q_ws
    if zero:
        q_zeroed = rotations.relative_to_initial(q_ws[None])[0] if q_ws.ndim == 2 else rotations.relative_to_initial(q_ws)
    fit = _fit_rests(q_zeroed, q_ws, positions_rad, q_reference, dt_s, model=model, q_hat=q_hat,
                     gyro_rad_s=gyro_rad_s, rests=rests, fraction=fraction, min_rest_s=min_rest_s,
                     threshold_rad_s=threshold_rad_s, window_s=window_s, max_match_rad=max_match_rad,
                     in_order=in_order, max_condition=max_condition, max_so4_distance=max_so4_distance)
    del q_zeroed                                   # the record's zeroed copy: only its rest means are kept
    sig = angles_sigma(fit.q_sensor, fit.q_reference, fit.q_hat, model) if sigma else None
    return _position_calibration(fit, max_residual_rad, sig)


@dataclass(frozen=True)
class _RestFit:
    """Steps 3–5 and the fit of :func:`calibrate_from_rests` (:func:`_fit_rests`), before Eq 10 at the rests."""

    q_hat: np.ndarray
    projection: So4Projection
    condition: np.ndarray
    positions_rad: np.ndarray
    q_reference: np.ndarray
    rests: list
    matched: np.ndarray
    q_sensor: np.ndarray
    means: np.ndarray
    q_given: np.ndarray
    gate: bool


def _fit_rests(q_zeroed, q_given, positions_rad, q_reference, dt_s, *, model, q_hat, gyro_rad_s, rests, fraction,
               min_rest_s, threshold_rad_s, window_s, max_match_rad, in_order, max_condition,
               max_so4_distance) -> _RestFit:
    """The methods-level steps of :func:`calibrate_from_rests` on a zeroed attitude ``q_zeroed``: rests → means →
    matching (steps 3–5), the fit of ``model`` (or ``q_hat`` given: no gate), its SO(4) projection and the
    distance gate. ``q_given`` is the attitude the caller was given (a refusal carries it); rests from
    ``gyro_rad_s``, else from the rotation rate of ``q_given``."""
    q_ref = q_reference
    means = None
    try:                                           # steps 3–5 (:func:`rest_attitudes`), then Eq 13 and the gates
        rests, means = _rests_and_means(q_zeroed, q_ref.shape[-2], dt_s, gyro_rad_s, rests, fraction, min_rest_s,
                                        threshold_rad_s, window_s, q_given)
        matched = _matched(means, q_ref, max_match_rad, in_order)
        q_s = means[..., matched, :]
        q_s_al, q_b_al = quaternion_lsq._align_pairs(q_s, q_ref)
        sv = np.linalg.svd(np.swapaxes(q_s_al, -1, -2) @ q_s_al, compute_uv=False)
        cond = sv[..., 0] / np.maximum(sv[..., 3], 1e-300)
        gate = q_hat is None
        if not gate:
            mat = q_hat
        elif model == "eq13":
            _gate_condition(cond, max_condition, q_ref)
            mat = quaternion_lsq._least_squares(q_s_al, q_b_al)                      # Eq 13
        elif model == "so4":
            mat = constrained_fit._fit_so4(q_s_al, q_b_al, "raise").matrix            # aligned, K >= 4 (trusted)
        else:
            mat = _fit_conjugation(q_s_al, q_b_al)
        proj = constrained_fit.project_to_so4(mat)
        _gate_distance(mat, proj.distance, max_so4_distance, gate)
    except ValueError as exc:
        raise PositionsRefused(str(exc), q_given, means) from None
    return _RestFit(mat, proj, cond, positions_rad, q_ref, rests, matched, q_s, means, q_given, gate)


def _position_calibration(fit: _RestFit, max_residual_rad: float, sigma_rad: np.ndarray | None = None
                          ) -> PositionCalibration:
    """The core steps after :func:`_fit_rests`: Eq 10 at the rests and their residual, the mounting ``q_bs = r*``,
    its installation angles (inverse of Eq 1), the Eq 8 angles before and after and their errors; then the
    residual gate (with ``fit.gate``). ``sigma_rad``: the angles' 1σ (:func:`angles_sigma`), when asked for."""
    q_s, q_ref, pos, mat = fit.q_sensor, fit.q_reference, fit.positions_rad, fit.q_hat
    after = rotations.apply_quat_matrix_trusted(mat, q_s)                         # Eq 10 at the rests
    residual = _angle_between(after, q_ref)
    q_bs = rotations.quat_conjugate(fit.projection.r)
    alpha = rotations.installation_angles_from_mount_trusted(q_bs)
    before_e = rotations.euler_zxy_unchecked(q_s)
    after_e = rotations.euler_zxy_unchecked(after)
    error_before = metrics.angle_difference_trusted(before_e, pos)
    error_after = metrics.angle_difference_trusted(after_e, pos)
    worst = float(np.max(residual))
    if fit.gate and not worst <= max_residual_rad:
        kk = int(np.unravel_index(np.argmax(residual), residual.shape)[-1])
        raise PositionsRefused(f"calibration residual {np.degrees(worst):.3f} deg at position {kk + 1} exceeds "
                               f"max_residual_rad ({np.degrees(max_residual_rad):g} deg); a rest does not match its "
                               f"reference position", fit.q_given, fit.means)
    return PositionCalibration(
        q_hat=mat, projection=fit.projection, mounting_quaternion_q_bs=q_bs, installation_angles_rad=alpha,
        condition=fit.condition, positions_rad=pos, q_reference=q_ref, rests=fit.rests, matched=fit.matched,
        q_sensor=q_s, euler_before_rad=before_e, euler_after_rad=after_e, error_before_rad=error_before,
        error_after_rad=error_after, residual_rad=residual, angles_sigma_rad=sigma_rad)


def calibrate_session(q_calibration: np.ndarray, positions_rad: np.ndarray, q_reference: np.ndarray, dt_s: float, *,
                      gyro_calibration: np.ndarray | None = None, q_verification: np.ndarray | None = None,
                      gyro_verification: np.ndarray | None = None, verification_positions_rad: np.ndarray | None = None,
                      verification_q_reference: np.ndarray | None = None, model: str = "eq13", fraction: float = 0.5,
                      min_rest_s: float = 2.0, threshold_rad_s: float = np.radians(0.2), window_s: float = 0.1,
                      max_match_rad: float = np.radians(5.0), in_order: bool = False,
                      max_condition: float = MAX_CONDITION, max_so4_distance: float = np.inf,
                      max_residual_rad: float = np.inf) -> tuple[PositionCalibration, PositionCalibration | None]:
    """A session's calibration run and its separate verification run: Q̂ fitted on the one, checked on the other.

    The session's attitude is zeroed once at its first sample (§4.1) by the caller; then
    :func:`calibrate_from_rests`' steps on the calibration run (rests from ``gyro_calibration``, Eq 13 or the
    ``model`` fitted, the gates) and — with ``q_verification`` — on the verification run with that Q̂ given
    (not fitted, no gate), its rests from ``gyro_verification``, measured against
    ``verification_positions_rad``. The settings are :func:`calibrate_from_rests`' and the same for both runs.
    The same numbers as ``calibrate_from_rests(q_calibration, …, zero=False)`` and
    ``calibrate_from_rests(q_verification, …, q_hat=cal.q_hat, zero=False)``.

    Trusts its inputs (:func:`mtcal.systems.installation.measure_session` checks a session once, at its
    edge), as :func:`calibrate_from_rests` for each run: ``q_calibration`` and ``q_verification`` float64
    unit quaternions (N, 4) or (T, N, 4) (the same T), the gyros like their ``[..., :3]``;
    ``positions_rad`` (K, 3) or (T, K, 3) and ``q_reference`` their Eq 9 attitudes;
    ``verification_positions_rad`` (K, 3) with ``verification_q_reference``; settings as there.

    Parameters
    ----------
    q_calibration : ndarray (N, 4) or (T, N, 4)
        Sensor attitude of the calibration run, zeroed at the session's first sample.
    positions_rad : ndarray (K, 3) or (T, K, 3)
        Reference ``[ψ, θ, γ]`` fed to Eq 13 (rad, Eq 8 frame).
    q_reference : ndarray (K, 4) or (T, K, 4)
        Eq 9 quaternions of ``positions_rad``.
    dt_s : float
        Sample interval (s).
    gyro_calibration, gyro_verification : ndarray (N, 3) or (T, N, 3), optional
        Gyro of each run (rad/s), for rest detection (else the attitude's rotation rate).
    q_verification : ndarray (M, 4) or (T, M, 4), optional
        Sensor attitude of the verification run, zeroed at the session's first sample.
    verification_positions_rad, verification_q_reference : ndarray (K, 3), (K, 4), optional
        The positions the verification is measured against and their Eq 9 quaternions (default: the
        calibration's).
    model, fraction, min_rest_s, threshold_rad_s, window_s, max_match_rad, in_order
        As for :func:`calibrate_from_rests`.
    max_condition, max_so4_distance, max_residual_rad
        The calibration's gates, as for :func:`calibrate_from_rests` (``inf`` switches one off).

    Returns
    -------
    calibration : PositionCalibration
    verification : PositionCalibration or None
        ``q_hat`` the calibration's; ``euler_before_rad`` / ``euler_after_rad`` the Eq 8 angles of the
        verification rest means before and after Eq 10. None without ``q_verification``.

    Raises
    ------
    PositionsRefused
        As :func:`calibrate_from_rests` (the verification refuses only for too few or unmatched rests).

    References
    ----------
    wang2023cja §3.2 (procedure, Eq 13–15), §4.1 (zeroed start, separate verification run), Eq 10.

    Examples
    --------
    A sensor mounted without error, calibrated on one run and verified on a second:

    >>> from mtcal.core import profiles, rotations
    >>> pos = six_positions_rad()
    >>> q = profiles.trajectory_from_euler_zxy(schedule_profile(pos, fs_hz=50.0)).q_wb
    >>> q_ref = rotations.quat_from_euler_zxy(pos[:, 0], pos[:, 1], pos[:, 2])            # Eq 9
    >>> cal, ver = calibrate_session(q, pos, q_ref, 0.02, q_verification=q)
    >>> bool(np.allclose(cal.q_hat, np.eye(4))), float(ver.residual_rad.max()) < 1e-12
    (True, True)
    """
    settings = dict(model=model, rests=None, fraction=fraction, min_rest_s=min_rest_s, threshold_rad_s=threshold_rad_s,
                    window_s=window_s, max_match_rad=max_match_rad, in_order=in_order, max_condition=max_condition,
                    max_so4_distance=max_so4_distance)
    # the methods-level steps of both runs, then the core steps of both (Eq 10 at the rests, angles)
    cal = _fit_rests(q_calibration, q_calibration, positions_rad, q_reference, dt_s, q_hat=None,
                     gyro_rad_s=gyro_calibration, **settings)
    ver = None
    if q_verification is not None:
        if verification_positions_rad is None:
            verification_positions_rad, verification_q_reference = positions_rad, q_reference
        ver = _fit_rests(q_verification, q_verification, verification_positions_rad, verification_q_reference, dt_s,
                         q_hat=cal.q_hat, gyro_rad_s=gyro_verification, **settings)
    calibration = _position_calibration(cal, max_residual_rad)
    return calibration, (None if ver is None else _position_calibration(ver, max_residual_rad))


_AXIS_NAMES = {1: "x (pitch)", 2: "y (roll)", 3: "z (yaw)"}


def missing_rotation_axis(q_ref) -> str | None:
    """The rotation axis a set of reference quaternions (K, 4) lacks, e.g. ``"z (yaw)"``; None if none.

    The weakest direction of ``A Aᵀ`` (its last singular vector) is the quaternion component no
    position reaches; a vector part component ``q1, q2, q3`` names the axis x, y, z.

    Examples
    --------
    >>> from mtcal.core import rotations
    >>> pm_g = np.radians([[0, 0, 0], [0, 0, 180], [0, 90, 0], [0, -90, 0], [0, 0, 90], [0, 0, -90]])
    >>> missing_rotation_axis(rotations.quat_from_euler_zxy(*pm_g.T))      # the classic +-g set
    'z (yaw)'
    """
    q = rotations.align_signs(np.asarray(q_ref, float))
    _, sv, vt = np.linalg.svd(q.T @ q)
    if sv[3] * MAX_CONDITION > sv[0]:                 # the Eq 13 gate's condition number
        return None
    weak = np.abs(vt[3])
    i = int(np.argmax(weak))
    return _AXIS_NAMES.get(i) if weak[i] > 0.9 else None


def _gate_condition(cond, max_condition: float, q_ref) -> None:
    """Refuse positions that leave Eq 13 ill-conditioned; name the missing axis and a model that works."""
    worst_cond = float(np.max(cond))
    if worst_cond <= max_condition:
        return
    ref = q_ref if q_ref.ndim == 2 else q_ref[0]
    axis = missing_rotation_axis(ref)
    sv = np.linalg.svd(rotations.align_signs(ref), compute_uv=False)
    rank3 = sv.size >= 3 and sv[2] > sv[0] / np.sqrt(MAX_CONDITION)
    what = f"they contain no rotation about {axis}" if axis else "their quaternions span fewer than 4 directions"
    fix = ("; add a position rotated about that axis (the six of §3.2 rotate about all three), or fit fewer "
           "parameters: model=\"so4\" (6) or model=\"mounting\" (3) work with these positions" if rank3 else
           "; use positions about more than one axis (the six of §3.2)")
    raise ValueError(f"calibration positions are ill-conditioned for Eq 13 (condition number {worst_cond:.3g} "
                     f"> {max_condition:.0e}): {what}{fix}")


def _fit_conjugation(q_s: np.ndarray, q_b: np.ndarray) -> np.ndarray:
    """Mounting-only map of a zeroed record, ``q_b = c ⊗ q_s ⊗ c*`` (3 parameters): Q̂ = L(c) R(c*).

    ``c ⊗ q_s − q_b ⊗ c = (R(q_s) − L(q_b)) c = 0`` for every position: ``c`` is the eigenvector of
    the smallest eigenvalue of ``Σ Mₖᵀ Mₖ``, ``Mₖ = R(q_s,k) − L(q_b,k)`` (closed form, sign-free).
    Positions about a single axis leave ``c`` free about it: refused.
    """
    m = rotations.right_matrix_trusted(q_s) - rotations.left_matrix_trusted(q_b)               # (..., K, 4, 4)
    k = np.einsum("...kij,...kil->...jl", m, m)
    lam, vec = np.linalg.eigh(k)
    if np.any(lam[..., 1] - lam[..., 0] <= 1e-10 * np.maximum(lam[..., 3], 1e-300)):
        raise ValueError("calibration positions do not determine the mounting (model=\"mounting\"): they rotate "
                         "about a single axis; use positions about two axes")
    c = vec[..., :, 0]
    c = np.where(c[..., :1] < 0, -c, c)
    return rotations.left_matrix_trusted(c) @ rotations.right_matrix_trusted(rotations.quat_conjugate(c))


def _gate_distance(q_hat, dist, max_dist: float, gate: bool = True) -> None:
    """With ``gate``, refuse Q̂ when farther than ``max_dist`` from SO(4) (distance ``dist``; ``inf`` switches
    the gate off)."""
    worst_dist = float(np.max(dist))
    if gate and not worst_dist <= max_dist:
        t = int(np.argmax(dist)) if np.ndim(dist) else None
        q = q_hat if t is None else q_hat[t]
        raise ValueError(f"Q_hat is not a calibration: distance {worst_dist:.3g} from a rotation of quaternion "
                         f"space (> {max_dist:g}; max |entry| {np.abs(q).max():.3g}, min row norm "
                         f"{np.linalg.norm(q, axis=1).min():.3g}); rests do not match the positions")


def angles_sigma(q_sensor: np.ndarray, q_reference: np.ndarray, q_hat: np.ndarray, model: str = "eq13") -> np.ndarray:
    """1σ uncertainty (rad) of the installation angles ``[α1, α2, α3]`` of a fit, from its covariance.

    The fit is least squares over the K positions' quaternion components, ``A_b ≈ Q(θ) A_s``
    (4K equations; θ: the 16 entries of Q̂ for Eq 13, 6 rotation parameters for ``"so4"``, 3 for
    ``"mounting"``). Its covariance is ``σ² (JᵀJ)⁻¹`` with ``σ²`` the residual variance
    ``‖A_b − Q̂ A_s‖² / (4K − n)`` and ``J`` the Jacobian of the residuals (for Eq 13, linear:
    row i of Q̂ has covariance ``σ² (A_s A_sᵀ)⁻¹``); the angles (SO(4) projection → mounting →
    inverse of Eq 1) get ``G cov Gᵀ`` with ``G`` their central-difference Jacobian. With no
    degrees of freedom left (K = 4 for Eq 13) the result is NaN.

    Trusts its inputs: ``q_sensor`` and ``q_reference`` unit quaternions (K, 4) (one record, no trial
    axis: a ValueError otherwise), ``q_hat`` the finite (4, 4) map ``model`` fitted to them.

    Returns
    -------
    ndarray (3,)
        1σ of ``[α1, α2, α3]`` (rad); NaN when not estimable.

    Examples
    --------
    >>> q = np.eye(4)                                     # four positions fitted exactly by the identity
    >>> angles_sigma(q, q, np.eye(4), "eq13").tolist()    # 4K - 16 = 0 degrees of freedom
    [nan, nan, nan]
    """
    q_s, q_b = quaternion_lsq._align_pairs(np.asarray(q_sensor), np.asarray(q_reference))
    if q_s.ndim != 2:
        raise ValueError("installation_angles_sigma takes one calibration (no trial axis)")
    fun, n = _model_matrix(model, np.asarray(q_hat, float))
    dof = 4 * q_s.shape[0] - n
    if dof <= 0:
        return np.full(3, np.nan)
    zero = np.zeros(n)
    resid = lambda d: (q_b.T - fun(d) @ q_s.T).ravel()              # noqa: E731
    h = 1e-6
    eye = np.eye(n) * h
    jac = np.stack([(resid(e) - resid(-e)) / (2 * h) for e in eye], axis=1)      # (4K, n)
    sigma2 = float(np.sum(resid(zero) ** 2)) / dof
    try:
        cov = sigma2 * np.linalg.inv(jac.T @ jac)
    except np.linalg.LinAlgError:
        return np.full(3, np.nan)
    g = np.stack([(_angles_of(fun(e)) - _angles_of(fun(-e))) / (2 * h) for e in eye], axis=1)  # (3, n)
    return np.sqrt(np.clip(np.diag(g @ cov @ g.T), 0.0, None))


def _angles_of(q_hat: np.ndarray) -> np.ndarray:
    r = constrained_fit.project_to_so4(q_hat).r
    return rotations.installation_angles_from_mount_trusted(rotations.quat_conjugate(r))


def _model_matrix(model: str, q_hat: np.ndarray):
    """The fitted map as a function of a small parameter perturbation δ, and the number of parameters."""
    if model == "eq13":
        return (lambda d: q_hat + d.reshape(4, 4)), 16
    proj = constrained_fit.project_to_so4(q_hat)
    p, r = proj.p, proj.r
    if model == "so4":
        return (lambda d: rotations.left_matrix_trusted(rotations.quat_multiply(p, rotations.quat_from_rotvec(d[:3])))
                @ rotations.right_matrix_trusted(rotations.quat_multiply(rotations.quat_from_rotvec(d[3:]), r))), 6
    c = rotations.quat_conjugate(r)

    def conj(d):
        cc = rotations.quat_multiply(c, rotations.quat_from_rotvec(d))
        return rotations.left_matrix_trusted(cc) @ rotations.right_matrix_trusted(rotations.quat_conjugate(cc))
    return conj, 3
