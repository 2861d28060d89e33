"""Plausibility checks of a log before a command trusts it (units, time base, clipping, axis).

Each check turns a case that would silently give a wrong number into a
one-line ``ValueError`` that names what was measured and the likely fix.

* :func:`gyro_tilt_consistency` — between two rests the gyro, integrated
  (bias from the first rest removed), must rotate the first rest's gravity
  direction onto the second's. A deg/s log read as rad/s turns it 57× too far;
  a time column 10× too fast integrates to a tenth. The scale that fits
  best is reported (π/180 → ``--gyro-unit deg/s``; 10, 0.1, 1000 … → time unit).
* :func:`clipped_samples` — samples at the gyro's full-scale plateau.
* :func:`rotation_axis_from_gyro` — principal rotation axis of the moving
  samples, compared with a user's ``--axis``.
"""

from __future__ import annotations

import numpy as np

from mtcal.core import rotations

__all__ = ["gyro_tilt_consistency", "clipped_samples", "rotation_axis_from_gyro", "cumulative_rotation"]

_CANDIDATES = {np.pi / 180: "gyro looks like deg/s read as rad/s: use --gyro-unit deg/s",
               180 / np.pi: "gyro looks like rad/s read as deg/s: drop --gyro-unit deg/s",
               10.0: "integrated gyro is 10x too small: time column 10x too fast? (check --time-unit / time_s)",
               0.1: "integrated gyro is 10x too large: time column 10x too slow? (check --time-unit / time_s)",
               1000.0: "integrated gyro is 1000x too small: time in s labelled ms? (check --time-unit)",
               0.001: "integrated gyro is 1000x too large: time in ms read as s? use --time-unit ms"}


#: Largest mean rate (rad/s, about the median rest's) of a rest used by :func:`gyro_tilt_consistency`.
MAX_REST_RATE_RAD_S = np.radians(2.0)


def cumulative_rotation(gyro_rad_s: np.ndarray, dt_s: float) -> np.ndarray:
    """``q_k = Δq_0 ⊗ … ⊗ Δq_k`` with ``Δq = exp(ω dt / 2)`` by a parallel prefix scan, (M, 4)."""
    q = rotations.quat_from_rotvec(gyro_rad_s * dt_s)
    d = 1
    while d < q.shape[0]:
        q[d:] = rotations.hamilton(q[:-d].copy(), q[d:])
        d *= 2
    return q


def clipped_samples(gyro_rad_s: np.ndarray, *, min_run: int = 3) -> tuple[np.ndarray, float]:
    """Samples on a full-scale plateau (≥ ``min_run`` equal samples at the axis' max |value|).

    Returns the boolean mask (N,) and the clipping level (rad/s, 0 if none).
    """
    mask = np.zeros(gyro_rad_s.shape[0], bool)
    level = 0.0
    for ax in range(3):
        col = gyro_rad_s[:, ax]
        peak = float(np.max(np.abs(col)))
        if peak == 0:
            continue
        at = np.abs(np.abs(col) - peak) <= 1e-9 * peak
        if np.count_nonzero(at) < min_run:
            continue
        same = at[1:] & at[:-1]
        if np.count_nonzero(same) >= min_run - 1:
            mask |= at
            level = max(level, peak)
    return mask, level


def gyro_tilt_consistency(gyro_rad_s: np.ndarray, accel_m_s2: np.ndarray, dt_s: float, rests: list,
                          *, time_s=None, skip=None, min_tilt_deg: float = 5.0,
                          max_pairs: int = 8, max_gap_s: float = 120.0) -> dict:
    """Check the gyro's units/time base against the accelerometer's tilt change between rests.

    Parameters
    ----------
    gyro_rad_s : (N, 3) rate for a fixed step ``dt_s`` (per-sample-dt weighted).
    accel_m_s2 : (N, 3)
    dt_s : float
    rests : list of slice
    time_s : (N,), optional — for messages.
    skip : (N,) bool, optional — e.g. clipped samples; pairs containing them are not used.

    Returns
    -------
    dict with ``pairs`` (number checked), ``worst_deg`` (largest misfit) and
    ``ratio`` (median integrated/tilt angle).

    Raises
    ------
    ValueError
        The gyro misses the tilt change by more than max(3°, 25 % of it) on the
        majority of the checked pairs; the message names the scale that fits.
    """
    t = np.arange(accel_m_s2.shape[0]) * dt_s if time_s is None else time_s
    if len(rests) >= 2:  # a "rest" that turns (e.g. an accelerometer-only ZVD during a pure rotation) is no rest
        means = np.array([gyro_rad_s[r].mean(axis=0) for r in rests])
        ref = np.median(means, axis=0)
        rests = [r for r, m in zip(rests, means) if np.linalg.norm(m - ref) < MAX_REST_RATE_RAD_S]
    cand = []
    for r0, r1 in zip(rests[:-1], rests[1:]):
        if (r1.start - r0.stop) * dt_s > max_gap_s:
            continue
        if skip is not None and skip[r0.start:r1.stop].any():
            continue
        a0, a1 = accel_m_s2[r0].mean(axis=0), accel_m_s2[r1].mean(axis=0)
        tilt = float(np.degrees(_angle(a0, a1)))
        if tilt >= min_tilt_deg:
            cand.append((tilt, r0, r1, a0, a1))
    cand.sort(key=lambda c: -c[0])
    cand = cand[:max_pairs]
    if not cand:
        return {"pairs": 0, "worst_deg": float("nan"), "ratio": float("nan")}
    misfits = {s: [] for s in [1.0, *_CANDIDATES]}
    ratios = []
    for tilt, r0, r1, a0, a1 in cand:
        mid0 = (r0.start + r0.stop) // 2
        mid1 = (r1.start + r1.stop) // 2
        bias = gyro_rad_s[r0].mean(axis=0)
        w = gyro_rad_s[mid0:mid1] - bias
        for s in misfits:
            q = cumulative_rotation(w * s, dt_s)[-1]
            pred = rotations.quat_to_matrix(q / np.linalg.norm(q)).T @ a0
            misfits[s].append(float(np.degrees(_angle(pred, a1))))
            if s == 1.0:
                q1 = q
                if misfits[1.0][-1] <= max(3.0, 0.25 * tilt):  # units fine: skip the alternatives
                    for other in _CANDIDATES:
                        misfits[other].append(np.inf)
                    break
        ratios.append(float(np.degrees(2 * np.arctan2(np.linalg.norm(q1[1:]), abs(q1[0])))) / tilt)
    tol = [max(3.0, 0.25 * c[0]) for c in cand]
    bad = [m > tl for m, tl in zip(misfits[1.0], tol)]
    out = {"pairs": len(cand), "worst_deg": float(max(misfits[1.0])), "ratio": float(np.median(ratios))}
    if sum(bad) * 2 > len(cand):
        k = int(np.argmax(np.array(misfits[1.0]) - np.array(tol)))
        tilt, r0, r1 = cand[k][:3]
        best = min(_CANDIDATES, key=lambda s: np.median(misfits[s]))
        fits = np.median(misfits[best]) <= np.median(tol)
        hint = _CANDIDATES[best] if fits else "check gyro units, scale, axis order/signs and the time column"
        raise ValueError(f"gyro and accelerometer disagree: between the rests at {t[r0.start]:.2f} s and "
                         f"{t[r1.start]:.2f} s the accelerometer tilts by {tilt:.1f} deg but the integrated "
                         f"gyro misses it by {misfits[1.0][k]:.1f} deg (rotation/tilt ratio "
                         f"{out['ratio']:.3g}); {hint}")
    return out


def rotation_axis_from_gyro(gyro_rad_s: np.ndarray, bias_rad_s: np.ndarray, moving: np.ndarray):
    """Principal rotation axis of the bias-corrected gyro over ``moving`` samples; (axis, energy share)."""
    w = gyro_rad_s[moving] - bias_rad_s
    if w.shape[0] < 3:
        return None, np.nan
    m = w.T @ w
    vals, vecs = np.linalg.eigh(m)
    share = float(vals[-1] / max(vals.sum(), 1e-300))
    return vecs[:, -1], share


def _angle(a, b) -> float:
    return float(np.arctan2(np.linalg.norm(np.cross(a, b)), np.dot(a, b)))
