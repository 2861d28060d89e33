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
6. Eq 13 is solved with :func:`mtcal.methods.quaternion_lsq.least_squares_error_matrix`
   (vectorised over a leading trial axis for Monte Carlo).

Time base: the detectors take the sample interval ``dt_s`` (s); only the
schedule generator :func:`schedule_profile` takes a rate, like the
:mod:`mtcal.core.profiles` generators it wraps.

Shapes: a record is (N, …) or (T, N, …) with a leading Monte Carlo trial
axis. All trials of one simulation share the mechanism schedule, so a sample
counts as "still" only if it is still in every trial (one set of rests).

Every public function validates its inputs; the private ``_…`` twins take
already-checked arrays and are what :mod:`mtcal.systems.installation` (and
:func:`calibrate`) call after validating once at their own edge.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from mtcal.core import rotations
from mtcal.core.compiled import jit
from mtcal.methods import quaternion_lsq
from mtcal.core.validate import as_float_array, positive_scalar, sample_interval, unit_quaternion
from mtcal.core.profiles import AngleProfile, step_schedule

__all__ = ["six_positions_rad", "schedule_profile", "stillness_from_gyro",
           "stillness_from_quaternions", "find_rests", "middle_slices", "mean_quaternion",
           "rest_means", "match_rests", "SixPositionResult", "calibrate"]

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


def stillness_from_gyro(gyro_rad_s, dt_s: float, *, window_s: float = 0.1,
                        threshold_rad_s: float = np.radians(0.2)) -> np.ndarray:
    """Still where the moving-mean gyro norm is below a threshold.

    Parameters
    ----------
    gyro_rad_s : array_like, shape (N, 3) or (T, N, 3)
        Angular rate (rad/s).
    dt_s : float
        Sample interval (s), ≤ 1 s.
    window_s : float
        Moving-mean window (s), ``round(window_s / dt_s)`` samples; averages white noise down.
    threshold_rad_s : float
        Threshold on ‖ω‖ (rad/s); default 0.2 °/s (far above a tactical
        gyro's 0.1 s-averaged noise ≈ 0.003 °/s, far below a move).

    Returns
    -------
    ndarray of bool, shape (N,) — still in every trial.
    """
    w = as_float_array(gyro_rad_s, "gyro_rad_s", ndim=(2, 3), last_dim=3)
    return _stillness_from_gyro(w, sample_interval(dt_s), positive_scalar(window_s, "window_s"),
                                positive_scalar(threshold_rad_s, "threshold_rad_s"))


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


#: Samples from which :func:`_stillness_from_gyro` runs its moving mean compiled.
_KERNEL_MIN_SAMPLES = 2048


def _stillness_from_gyro(w: np.ndarray, dt: float, window_s: float, threshold_rad_s: float) -> np.ndarray:
    """:func:`stillness_from_gyro` on checked arrays (trusted)."""
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


def stillness_from_quaternions(q, dt_s: float, *, window_s: float = 0.1,
                               threshold_rad_s: float = np.radians(0.2)) -> np.ndarray:
    """Still where the mean rotation rate over a window (from the quaternions) is small.

    Rate ≈ angle(q[k − w/2], q[k + w/2]) / (w dt_s), with ``w = window_s / dt_s`` samples and
    ``dt_s`` the sample interval (s). Shapes (N, 4) or (T, N, 4) → (N,) bool (still in every trial).
    """
    qq = unit_quaternion(q, "q")
    if qq.ndim not in (2, 3):
        raise ValueError(f"q must have shape (N, 4) or (T, N, 4), got {qq.shape}")
    return _stillness_from_quaternions(qq, sample_interval(dt_s), positive_scalar(window_s, "window_s"),
                                       positive_scalar(threshold_rad_s, "threshold_rad_s"))


def _stillness_from_quaternions(qq: np.ndarray, dt: float, window_s: float, threshold_rad_s: float) -> np.ndarray:
    """:func:`stillness_from_quaternions` on checked unit quaternions (trusted)."""
    half = max(1, int(round(window_s / dt / 2)))
    n = qq.shape[-2]
    idx = np.arange(n)
    lo, hi = np.clip(idx - half, 0, n - 1), np.clip(idx + half, 0, n - 1)
    ang = rotations.quat_angle_between(qq[..., lo, :], qq[..., hi, :])
    rate = ang / np.maximum(hi - lo, 1) / dt
    still = rate < threshold_rad_s
    return still if still.ndim == 1 else np.all(still, axis=0)


def find_rests(still, dt_s: float, *, min_rest_s: float = 2.0) -> list[slice]:
    """Contiguous still runs lasting at least ``min_rest_s`` (s), as sample slices in time order.

    ``still`` is a 1-D boolean array sampled every ``dt_s`` (s); a run counts if it holds at
    least ``min_rest_s / dt_s`` samples.
    """
    s = np.asarray(still)
    if s.dtype != bool or s.ndim != 1:
        raise TypeError(f"still must be a 1-D boolean array, got dtype {s.dtype} shape {s.shape}")
    return _find_rests(s, sample_interval(dt_s), positive_scalar(min_rest_s, "min_rest_s"))


def _find_rests(s: np.ndarray, dt: float, min_rest_s: float) -> list[slice]:
    """:func:`find_rests` on a checked 1-D boolean array (trusted)."""
    edges = np.diff(np.concatenate([[0], s.astype(np.int8), [0]]))
    starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    keep = (stops - starts) >= min_rest_s / dt
    return [slice(int(a), int(b)) for a, b in zip(starts[keep], stops[keep])]


def middle_slices(rests: list[slice], fraction: float = 0.5) -> list[slice]:
    """The central ``fraction`` of each rest ("middle section", §3.2)."""
    f = positive_scalar(fraction, "fraction")
    if f > 1:
        raise ValueError(f"fraction must be in (0, 1], got {f}")
    return _middle_slices(rests, f)


def _middle_slices(rests: list[slice], f: float) -> list[slice]:
    """:func:`middle_slices` with a checked fraction (trusted)."""
    out = []
    for r in rests:
        n = r.stop - r.start
        m = max(1, int(round(n * f)))
        a = r.start + (n - m) // 2
        out.append(slice(a, a + m))
    return out


def mean_quaternion(q, axis: int = -2) -> np.ndarray:
    """Sign-aligned chordal mean of unit quaternions along ``axis`` (normalised).

    Each quaternion is flipped to agree in sign with the first one along
    ``axis`` (q and −q are the same attitude), averaged, and renormalised.
    Exact for identical inputs; for a spread of a few 0.01° it equals the
    rotation-averaging mean to second order.
    """
    return _mean_quaternion(unit_quaternion(q, "q"), axis)


def _mean_quaternion(qq: np.ndarray, axis: int = -2) -> np.ndarray:
    """:func:`mean_quaternion` of checked unit quaternions (trusted)."""
    ax = axis % qq.ndim
    ref = np.take(qq, [0], axis=ax)
    dot = np.sum(qq * ref, axis=-1, keepdims=True)
    m = np.mean(np.where(dot < 0, -qq, qq), axis=ax)
    return m / np.linalg.norm(m, axis=-1, keepdims=True)


def rest_means(q_ws, rests: list[slice], fraction: float = 0.5) -> np.ndarray:
    """Mean attitude over the middle of each rest: (N, 4) → (K, 4), (T, N, 4) → (T, K, 4)."""
    qq = unit_quaternion(q_ws, "q_ws")
    if qq.ndim not in (2, 3):
        raise ValueError(f"q_ws must have shape (N, 4) or (T, N, 4), got {qq.shape}")
    mids = middle_slices(rests, fraction)
    return _rest_means(qq, mids)


def _rest_means(qq: np.ndarray, mids: list[slice]) -> np.ndarray:
    """Mean attitude over each (already trimmed) slice of checked quaternions (trusted)."""
    return np.stack([_mean_quaternion(qq[..., s, :], axis=-2) for s in mids], axis=-2)


def match_rests(q_rest, q_ref, *, max_angle_rad: float = np.radians(5.0)) -> np.ndarray:
    """Assign one detected rest to each reference position (nearest attitude, Hungarian).

    Parameters
    ----------
    q_rest : array_like, shape (R, 4) or (T, R, 4)
        Mean sensor attitude of each detected rest (trials: distances averaged).
    q_ref : array_like, shape (K, 4)
        Reference attitudes (Eq 9 of Eq 15's angles).
    max_angle_rad : float
        Largest accepted distance (rad) between a rest and its position; must
        exceed installation error + yaw offset, and stay below half the
        spacing of the positions.

    Returns
    -------
    ndarray of int, shape (K,)
        Index of the rest used for each reference position.
    """
    qr = unit_quaternion(q_rest, "q_rest")
    qb = unit_quaternion(q_ref, "q_ref")
    if qb.ndim != 2:
        raise ValueError(f"q_ref must have shape (K, 4), got {qb.shape}")
    return _match_rests(qr, qb, float(max_angle_rad))


def _match_rests(qr: np.ndarray, qb: np.ndarray, max_angle_rad: float) -> np.ndarray:
    """:func:`match_rests` on checked quaternions (trusted); ``qb`` may also be (T, K, 4) per trial."""
    k, r = qb.shape[-2], qr.shape[-2]
    if r < k:
        raise ValueError(f"found {r} rests in the record but {k} reference positions were given; "
                         f"each position needs a rest of at least min_rest_s")
    dist = _angle_between(qr[..., :, None, :], qb[..., None, :, :])
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


@dataclass(frozen=True)
class SixPositionResult:
    """Outcome of :func:`calibrate` (trial axis T present iff the input had one).

    Attributes
    ----------
    q_matrix : ndarray (4, 4) or (T, 4, 4)
        Q̂_s^b (Eq 13).
    rests : list of slice
        All detected rests (time order).
    matched : ndarray (K,) of int
        Rest index used for each reference position.
    q_sensor : ndarray (K, 4) or (T, K, 4)
        Middle-section mean sensor quaternions (Eq 14 columns).
    q_reference : ndarray (K, 4)
        Reference quaternions (Eq 9 of the reference angles).
    euler_before_rad, euler_after_rad : ndarray (K, 3) or (T, K, 3)
        Eq 8 angles of the sensor means and of ``Q̂ q_s`` (rad).
    residual_rad : ndarray (K,) or (T, K)
        Angle between ``Q̂ q_s`` and the reference (rad).
    """

    q_matrix: np.ndarray
    rests: list
    matched: np.ndarray
    q_sensor: np.ndarray
    q_reference: np.ndarray
    euler_before_rad: np.ndarray
    euler_after_rad: np.ndarray
    residual_rad: np.ndarray


def calibrate(q_ws, reference_euler_rad, dt_s: float, *, gyro_rad_s=None, fraction: float = 0.5,
              min_rest_s: float = 2.0, threshold_rad_s: float = np.radians(0.2),
              window_s: float = 0.1, max_match_rad: float = np.radians(5.0),
              rests: list | None = None) -> SixPositionResult:
    """Six-position calibration from a recorded sensor-attitude stream (§3.2, Eq 13–15).

    Parameters
    ----------
    q_ws : array_like, shape (N, 4) or (T, N, 4)
        Sensor attitude stream (QNCF output), scalar-first.
    reference_euler_rad : array_like, shape (K, 3)
        Reference ``[ψ, θ, γ]`` of each position (rad), K ≥ 3.
    dt_s : float
        Sample interval (s), ≤ 1 s.
    gyro_rad_s : array_like, shape like q_ws[..., :3], optional
        If given, rests are detected on the gyro norm, else on the quaternions.
    fraction : float
        Middle fraction of each rest that is averaged (0.5 → the central 1.5 s
        of a 3 s rest).
    min_rest_s : float
        Shortest still run accepted as a rest (s).
    threshold_rad_s, window_s : float
        Stillness detector threshold (rad/s) and window (s).
    max_match_rad : float
        Matching tolerance (rad), see :func:`match_rests`.
    rests : list of slice, optional
        Rests found by another detector (e.g.
        :func:`mtcal.methods.rest_detection.detect_rests`); when given, the
        stillness detector above is not run and ``min_rest_s`` is not applied.

    Raises
    ------
    ValueError
        Too few rests, a position without a matching rest, or degenerate
        positions (condition number in the message).
    """
    qq = unit_quaternion(q_ws, "q_ws", copy=False)      # only read (the result holds new arrays)
    if qq.ndim not in (2, 3):
        raise ValueError(f"q_ws must have shape (N, 4) or (T, N, 4), got {qq.shape}")
    ref = as_float_array(reference_euler_rad, "reference_euler_rad", ndim=2, last_dim=3)
    if ref.shape[0] < 3:
        raise ValueError(f"reference_euler_rad must hold at least 3 positions, got {ref.shape[0]}")
    dt = sample_interval(dt_s)
    frac = positive_scalar(fraction, "fraction")
    if frac > 1:
        raise ValueError(f"fraction must be in (0, 1], got {frac}")
    gyro = None
    if rests is not None:
        rests = list(rests)
        if any(not isinstance(r, slice) or r.stop > qq.shape[-2] for r in rests):
            raise ValueError(f"rests must be slices within the {qq.shape[-2]} samples of q_ws")
    elif gyro_rad_s is not None:
        gyro = as_float_array(gyro_rad_s, "gyro_rad_s", ndim=(2, 3), last_dim=3, copy=False)   # only read
        if gyro.shape[-2] != qq.shape[-2]:
            raise ValueError(f"gyro_rad_s has {gyro.shape[-2]} samples but q_ws has {qq.shape[-2]}")
    q_ref = rotations.quat_from_euler_zxy(ref[:, 0], ref[:, 1], ref[:, 2])
    rests, matched, q_s = _rest_attitudes(
        qq, q_ref, dt, gyro=gyro, rests=rests, fraction=frac, min_rest_s=positive_scalar(min_rest_s, "min_rest_s"),
        threshold_rad_s=positive_scalar(threshold_rad_s, "threshold_rad_s"),
        window_s=positive_scalar(window_s, "window_s"), max_match_rad=float(max_match_rad))
    q_mat = quaternion_lsq._least_squares(*quaternion_lsq._align_pairs(q_s, q_ref))  # (4, 4) or (T, 4, 4)
    after = quaternion_lsq._apply(q_mat, q_s)
    residual = _angle_between(after, q_ref)
    return SixPositionResult(q_mat, rests, matched, q_s, q_ref, rotations.euler_zxy_unchecked(q_s),
                             rotations.euler_zxy_unchecked(after), residual)


def _angle_between(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Attitude difference (rad) of checked unit quaternions (same arithmetic as ``rotations.quat_angle_between``)."""
    d = rotations.hamilton(p * _CONJ, q)
    return 2.0 * np.arctan2(np.linalg.norm(d[..., 1:], axis=-1), np.abs(d[..., 0]))


_CONJ = np.array([1.0, -1.0, -1.0, -1.0])


def _rest_attitudes(qq: np.ndarray, q_ref: np.ndarray, dt: float, *, gyro: np.ndarray | None,
                    rests: list | None, fraction: float, min_rest_s: float, threshold_rad_s: float,
                    window_s: float, max_match_rad: float, q_detect: np.ndarray | None = None,
                    in_order: bool = False):
    """Rests → middle-section means → matched to the references (steps 3–5 of §3.2; trusted).

    ``in_order``: the rests are known by construction (a simulated schedule) — rest k belongs to
    position k, no matching by attitude (and no ``max_match_rad`` window).

    ``qq`` (N, 4) or (T, N, 4) checked unit quaternions sampled every ``dt`` (s); ``q_ref`` (K, 4) or (T, K, 4);
    rests are ``rests`` if given, else detected on ``gyro`` if given, else on the
    quaternion rate of ``q_detect`` (default ``qq``). Returns ``(rests, matched, q_s)``.
    """
    if rests is None:
        if gyro is not None:
            still = _stillness_from_gyro(gyro, dt, window_s, threshold_rad_s)
        else:
            still = _stillness_from_quaternions(qq if q_detect is None else q_detect, dt, window_s, threshold_rad_s)
        rests = _find_rests(still, dt, min_rest_s)
    if len(rests) < q_ref.shape[-2]:
        raise ValueError(f"too few rests: found {len(rests)} still periods of >= {min_rest_s:g} s, "
                         f"need one for each of the {q_ref.shape[-2]} reference positions")
    means = _rest_means(qq, _middle_slices(rests, fraction))
    if in_order:
        if len(rests) != q_ref.shape[-2]:
            raise ValueError(f"rests in schedule order: got {len(rests)} rests for {q_ref.shape[-2]} positions")
        matched = np.arange(len(rests))
    else:
        matched = _match_rests(means, q_ref, max_match_rad)
    return rests, matched, means[..., matched, :]
