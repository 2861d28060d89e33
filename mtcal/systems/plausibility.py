"""Plausibility checks of an IMU record before a procedure trusts it (units, time base, clipping, axis).

Each check turns a case that would silently give a wrong number into a
one-line ``ValueError`` that names what was measured and the likely fix.
The messages name the ``mtcal`` options that fix a log (``--gyro-unit``,
``--time-unit``), since a log read by the CLI is where these cases arise.

* :func:`gyro_tilt_consistency` — between two rests the gyro, integrated
  (bias from the first rest removed), must rotate the first rest's gravity
  direction onto the second's. A deg/s log read as rad/s turns it 57× too far;
  a time column 10× too fast integrates to a tenth. The scale that fits
  best is reported (π/180 → ``--gyro-unit deg/s``; 10, 0.1, 1000 … → time unit).
* :func:`clipped_samples` — samples at the gyro's full-scale plateau.
* :func:`rotation_axis_from_gyro` — principal rotation axis of the moving
  samples, compared with a user's ``--axis``.
* :func:`cumulative_rotation` — integrated attitude change of a gyro record.
* :func:`time_base` — the fixed filter step of a time column and the gyro weights
  that keep a jittered record's integral right.
* :func:`check_units` — the units check every procedure runs: the rest pairs
  above, then (no pair) every rest without the turning-rest filter, then the
  gravity-referenced tilt rate over quasi-static stretches
  (:mod:`mtcal.methods.tilt_rate`), then gravity tracking on short windows
  (:mod:`mtcal.methods.gravity_tracking`: which unit/time-base hypothesis
  carries the accelerometer's direction), then a rate bound for rotations about
  gravity; a record whose rotation none of them can check is refused with a
  one-line error naming ``--gyro-unit`` and the evidence — unless the unit was
  stated (option or unit-carrying header), which is accepted with a warning naming
  the evidence, or refused when the tilt rate leans against it (likeliest cause first).

References
----------
wang2022sensors Sec. 2.2 (static gravity reading ``R(θ, v)ᵀ ā0``: a rotation
between two rests shows as the angle between their accelerometer means).

Examples
--------
>>> import numpy as np
>>> gyro = np.zeros((100, 3)); gyro[40:60, 0] = np.radians(90.0)   # 20 samples at 90 deg/s
>>> q = cumulative_rotation(gyro, 0.05)[-1]                          # 20 x 0.05 s x 90 deg/s = 90 deg
>>> round(float(np.degrees(2 * np.arccos(q[0]))), 6)
90.0
>>> mask, level = clipped_samples(gyro)
>>> int(mask.sum()), round(float(np.degrees(level)), 1)
(20, 90.0)
"""

from __future__ import annotations

import numpy as np

from mtcal.core import rotations
from mtcal.core.validate import MAX_GYRO_RAD_S, as_float_array, positive_scalar
from mtcal.methods import gravity_tracking, tilt_rate

__all__ = ["gyro_tilt_consistency", "clipped_samples", "rotation_axis_from_gyro", "cumulative_rotation",
           "time_base", "check_units", "MAX_REST_RATE_RAD_S", "MAX_UNCHECKED_ROTATION_DEG",
           "MAX_GRAVITY_AXIS_RATE_RAD_S", "MIN_FULL_SCALE_RAD_S", "MIN_GRAVITY_AXIS_SHARE", "TRACKING_HINTS",
           "MIN_LEAN_CORRELATION", "MAX_LEAN_RATIO"]

_CANDIDATES = {np.pi / 180: "gyro looks like deg/s read as rad/s: use --gyro-unit deg/s",
               180 / np.pi: "gyro looks like rad/s read as deg/s: drop --gyro-unit deg/s",
               10.0: "integrated gyro is 10x too small: time column 10x too fast? (check --time-unit / time_s)",
               0.1: "integrated gyro is 10x too large: time column 10x too slow? (check --time-unit / time_s)",
               1000.0: "integrated gyro is 1000x too small: time in s labelled ms? (check --time-unit)",
               0.001: "integrated gyro is 1000x too large: time in ms read as s? use --time-unit ms"}


#: Largest mean rate (rad/s, about the median rest's) of a rest used by :func:`gyro_tilt_consistency`.
MAX_REST_RATE_RAD_S = np.radians(2.0)


def cumulative_rotation(gyro_rad_s: np.ndarray, dt_s: float) -> np.ndarray:
    """``q_k = Δq_0 ⊗ … ⊗ Δq_k`` with ``Δq = exp(ω dt / 2)`` by a parallel prefix scan.

    Parameters
    ----------
    gyro_rad_s : ndarray (M, 3)
        Angular rate (rad/s), constant over each step.
    dt_s : float
        Step (s).

    Returns
    -------
    ndarray (M, 4)
        Scalar-first attitude change after each sample.
    """
    q = rotations.quat_from_rotvec(gyro_rad_s * dt_s)
    d = 1
    while d < q.shape[0]:
        q[d:] = rotations.hamilton(q[:-d].copy(), q[d:])
        d *= 2
    return q


def clipped_samples(gyro_rad_s: np.ndarray, *, min_run: int = 3) -> tuple[np.ndarray, float]:
    """Samples on a full-scale plateau (≥ ``min_run`` equal samples at the axis' max |value|).

    Parameters
    ----------
    gyro_rad_s : ndarray (N, 3)
        Angular rate (rad/s).
    min_run : int
        Shortest plateau (samples).

    Returns
    -------
    mask : ndarray (N,) of bool
        Samples on a plateau of any axis.
    level : float
        Clipping level (rad/s), 0 if none.
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
                          max_pairs: int = 8, max_gap_s: float = 120.0, drop_turning: bool = True) -> dict:
    """Check the gyro's units/time base against the accelerometer's tilt change between rests.

    Parameters
    ----------
    gyro_rad_s : (N, 3) rate for a fixed step ``dt_s`` (per-sample-dt weighted).
    accel_m_s2 : (N, 3)
    dt_s : float
    rests : list of slice
    time_s : (N,), optional — for messages.
    skip : (N,) bool, optional — e.g. clipped samples; pairs containing them are not used.
    drop_turning : bool
        Drop rests whose mean rate is more than :data:`MAX_REST_RATE_RAD_S` from the median rest's.

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
    cand = _tilt_pairs(gyro_rad_s, accel_m_s2, dt_s, rests, skip, min_tilt_deg, max_pairs, max_gap_s, drop_turning)
    if not cand:
        return {"pairs": 0, "worst_deg": float("nan"), "ratio": float("nan")}
    return _pair_misfits(cand, gyro_rad_s, dt_s, np.arange(accel_m_s2.shape[0]) * dt_s if time_s is None else time_s)


def _tilt_pairs(gyro_rad_s, accel_m_s2, dt_s: float, rests: list, skip, min_tilt_deg: float = 5.0,
                max_pairs: int = 8, max_gap_s: float = 120.0, drop_turning: bool = True) -> list:
    """The rest pairs :func:`gyro_tilt_consistency` checks (largest tilt first): (tilt deg, r0, r1, ā0, ā1)."""
    if len(rests) >= 2 and drop_turning:  # a "rest" that turns (accelerometer-only ZVD in a pure rotation) is no rest
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
    return cand[:max_pairs]


def _pair_misfits(cand: list, gyro_rad_s, dt_s: float, t) -> dict:
    """:func:`gyro_tilt_consistency` on its (non-empty) rest pairs; ``t`` sample times (s) for messages."""
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


#: What to do when gravity tracking finds a rival unit/time base (:data:`gravity_tracking.HYPOTHESES`).
TRACKING_HINTS = {
    "deg/s read as rad/s": "use --gyro-unit deg/s",
    "rad/s read as deg/s": "drop --gyro-unit deg/s (the gyro is in rad/s)",
    "mrad/s read as rad/s (or time in ms read as s)": "time in ms? use --time-unit ms; gyro in mrad/s? use "
                                                        "--gyro-scale 0.001",
    "rad/s read as mrad/s (or time in s read as ms)": "time in s read as ms? check --time-unit; or check "
                                                        "--gyro-scale",
    "time column 10x too fast": "check --time-unit / time_s (integrated gyro 10x too small)",
    "time column 10x too slow": "check --time-unit / time_s (integrated gyro 10x too large)",
}


#: A stated unit that no check decides is still refused when the tilt rate, with at least this correlation,
#: puts the gyro scale outside 1/MAX_LEAN_RATIO … MAX_LEAN_RATIO (weak evidence, but against the unit).
#: The ratio sits between what a correct hand-held log shows and what the smallest mistake gives: linear
#: acceleration biases the tilt-rate scale of a correct BROAD translation trial by up to 2.7x (trial 15,
#: correlation 0.40), while a walking log with a 10x time base leans by 6.7x (correlation 0.34;
#: tests/cli/test_round_two.py) and unit mistakes by 57x (deg/s) or 1000x (mrad/s, time in ms).
MIN_LEAN_CORRELATION = 0.3
MAX_LEAN_RATIO = 5.0


#: Below this sample rate (Hz, from the time column) a 1000x tracking rival is named first as "time in ms read as
#: s" when gravity tracking cannot tell it from the other rivals (an 8 kHz log with ms stamps reads as 8 Hz).
LOW_RATE_HZ = 50.0


#: Largest gyro rotation (deg, bias removed, integrated |ω|) accepted without any units check.
MAX_UNCHECKED_ROTATION_DEG = 10.0
#: Smallest gyro full scale (rad/s; 30 °/s): a clipping plateau between this and 40 rad/s is a rad/s full scale.
MIN_FULL_SCALE_RAD_S = np.radians(30.0)
#: Share of the gyro's rotation about gravity above which a rotation counts as "about gravity only".
MIN_GRAVITY_AXIS_SHARE = 0.7
#: Rotation about gravity faster than this (rad/s, one turn per second) with |a| at the rest level is refused.
MAX_GRAVITY_AXIS_RATE_RAD_S = 2 * np.pi


def check_units(gyro_rad_s: np.ndarray, accel_m_s2: np.ndarray, dt_s: float, rests: list, *, time_s=None,
                skip=None, unit_stated: str | None = None) -> dict:
    """Check the gyro's units and time base, or refuse: no procedure answers without this.

    In order, the first check that can decide does:

    1. :func:`gyro_tilt_consistency` on the rest pairs (turning rests dropped);
    2. the same on every rest (rests whose mean rate is off the median kept: a
       deg/s log read as rad/s has rests 57× noisier than the filter expects);
    3. the gravity-referenced tilt rate over all quasi-static stretches
       (:func:`mtcal.methods.tilt_rate.check_tilt_rate_scale`, slow moves count);
    4. gravity tracking (:func:`mtcal.methods.gravity_tracking.gravity_tracking`): the gyro
       under the stated unit and under each rival (deg/s, mrad/s, time in ms …) carries the
       accelerometer's direction over 0.5 s windows; the stated unit is confirmed when it wins
       ≥ 80 % of the discriminating windows against every rival, refused when a rival wins
       ≥ 90 % (the message names the option);
    5. no tilt to compare: a gyro that turns less than
       :data:`MAX_UNCHECKED_ROTATION_DEG` in total needs no check; a rotation
       only about gravity (no tilt seen, ≥ :data:`MIN_GRAVITY_AXIS_SHARE` of the
       integrated rate along the accelerometer's direction) passes unless it is faster than
       :data:`MAX_GRAVITY_AXIS_RATE_RAD_S` while ``‖a‖`` stays at the rest level
       (no centripetal acceleration: a deg/s rate read as rad/s); a gyro clipped
       (``skip``) at a plateau of :data:`MIN_FULL_SCALE_RAD_S` … 40 rad/s has a
       full scale that only rad/s explains (read as deg/s it would be > 40
       rad/s and refused on reading); anything else is refused (the hint guesses
       no unit) — unless ``unit_stated``: a stated unit is accepted, the result's
       ``warning`` naming the evidence (method ``"stated unit (unchecked)"``), not
       when the tilt rate leans against it: correlation ≥ :data:`MIN_LEAN_CORRELATION`
       with a scale off by more than :data:`MAX_LEAN_RATIO` (the hint names the
       scale's likeliest cause).

    The records are the checked arrays of the caller's edge (a system's, or the log reader's): finite
    float64 (N, 3) of one shape, ``dt_s`` finite > 0; they are not checked again here.

    Parameters
    ----------
    gyro_rad_s : ndarray (N, 3)
        Rate (rad/s) for the fixed step ``dt_s`` (per-sample-dt weighted).
    accel_m_s2 : ndarray (N, 3)
        Specific force (m/s²).
    dt_s : float
        Step (s).
    rests : list of slice
        Rests found by the detector.
    time_s : ndarray (N,), optional
        For messages.
    skip : ndarray (N,) of bool, optional
        Samples not to use between rests (e.g. clipped).
    unit_stated : str, optional
        Where the user stated the gyro unit (e.g. ``"--gyro-unit deg/s"``, ``"header gyro_x_rad_s"``);
        None: not stated (a check must decide).

    Returns
    -------
    dict
        ``method`` (which check decided), ``pairs``, ``worst_deg``, ``ratio``
        (rest-pair checks; 0/NaN otherwise), ``evidence`` (one line) and, when no
        check could decide a stated unit, ``warning`` (one line).

    Raises
    ------
    ValueError
        A check finds the gyro off (the message names the scale that fits and
        ``--gyro-unit``/``--time-unit``), nothing can check a rotating gyro whose unit was not stated, or no
        check decides a stated unit and the tilt rate leans against it.

    References
    ----------
    wang2022sensors Sec. 2.2 (a rotation shows as a change of the accelerometer direction).

    Examples
    --------
    >>> import numpy as np
    >>> acc = np.tile([0.0, 0.0, 9.81], (500, 1))
    >>> check_units(np.zeros((500, 3)), acc, 0.01, [slice(0, 100), slice(400, 500)])["method"]
    'no rotation'
    """
    if skip is not None:
        skip = np.asarray(skip, bool)
        if skip.shape != (accel_m_s2.shape[0],):
            raise ValueError(f"skip must be a boolean array of {accel_m_s2.shape[0]} samples, got shape {skip.shape}")
    # the rest pairs (turning rests dropped, else all rests), then one pass of their misfits
    method, cand = "rest pairs", _tilt_pairs(gyro_rad_s, accel_m_s2, dt_s, rests, skip)
    if not cand:
        method, cand = "rest pairs (all rests)", _tilt_pairs(gyro_rad_s, accel_m_s2, dt_s, rests, skip,
                                                             drop_turning=False)
    if cand:
        res = _pair_misfits(cand, gyro_rad_s, dt_s,
                            np.arange(accel_m_s2.shape[0]) * dt_s if time_s is None else time_s)
        return {**res, "method": method,
                "evidence": f"{res['pairs']} rest pair(s), rotation/tilt ratio {res['ratio']:.3f}"}
    out = {"pairs": 0, "worst_deg": float("nan"), "ratio": float("nan")}
    refused = tr = None
    try:
        tr = tilt_rate.check_tilt_rate_scale(gyro_rad_s, accel_m_s2, dt_s, skip=skip)
    except ValueError as exc:  # refused: gravity tracking, when it finds the scale, names the option that fits
        refused = exc
    if tr is not None:
        ev = (f"accelerometer tilts {np.degrees(tr['accel_spread_rad']):.1f} deg from its mean direction and "
              f"{np.degrees(tr['accel_tilt_rad']):.1f} deg in total, gyro tilt "
              f"{np.degrees(tr['gyro_tilt_rad']):.1f} deg, tilt-rate scale {tr['scale']:.3g}, correlation "
              f"{tr['correlation']:.2f}")
        if tr["decided"]:
            return {**out, "method": "tilt rate", "evidence": ev}
        seen, lean_hint = tilt_rate.tilt_seen(tr), tilt_rate.scale_hint(tr["scale"])
    gt = gravity_tracking.gravity_tracking(gyro_rad_s, accel_m_s2, dt_s)
    if gt["decision"] == "rival":
        contra = [k for k, r in gt["rivals"].items() if r["windows"] >= gravity_tracking.MIN_WINDOWS
                  and 1.0 - r["win_fraction"] >= gravity_tracking.CONTRADICT_FRACTION]
        ms = "mrad/s read as rad/s (or time in ms read as s)"
        if (ms in contra and ms != gt["winner"] and 1.0 / dt_s < LOW_RATE_HZ and 1.0 - gt["rivals"][ms]["win_fraction"]
                >= 1.0 - gt["rivals"][gt["winner"]]["win_fraction"] - 0.01):
            # tracking cannot part them, the rate can: an IMU below LOW_RATE_HZ whose gyro integrates ~1000x too
            # far is, far more often, a time column in ms read as s (8 kHz read as 8 Hz) than a mrad/s gyro
            gt = {**gt, "winner": ms, "margin": 1.0 - gt["rivals"][ms]["win_fraction"]}
        others = [k for k in contra if k != gt["winner"]]
        also = "".join(f"; or {k} ({1.0 - gt['rivals'][k]['win_fraction']:.2f}): {TRACKING_HINTS.get(k, '')}"
                       for k in others)
        raise ValueError(f"gyro units: {gt['winner']}? {TRACKING_HINTS.get(gt['winner'], '')} (gravity tracking: "
                         f"that hypothesis carries the accelerometer's gravity direction better in {gt['margin']:.2f}"
                         f" of {gt['rivals'][gt['winner']]['windows']} discriminating windows, refused at >= "
                         f"{gravity_tracking.CONTRADICT_FRACTION:g}){also}") from refused
    if refused is not None:
        raise refused
    if gt["decision"] == "stated":
        return {**out, "method": "gravity tracking", "margin": gt["margin"], "evidence": gt["evidence"]}
    ev = f"{ev}; {gt['evidence']}"
    if rests:
        bias = np.median(np.array([gyro_rad_s[r].mean(axis=0) for r in rests]), axis=0)
    else:
        bias = np.median(gyro_rad_s, axis=0)
    rate = np.linalg.norm(gyro_rad_s - bias, axis=1)
    turned = float(np.degrees(rate.sum() * dt_s))
    if turned < MAX_UNCHECKED_ROTATION_DEG:
        return {**out, "method": "no rotation", "evidence": f"gyro turns {turned:.1f} deg in total"}
    if skip is not None and np.any(skip):  # a full-scale plateau is itself a units check (not of the time base)
        level = float(np.max(np.abs(gyro_rad_s[np.asarray(skip, bool)])))
        if MIN_FULL_SCALE_RAD_S <= level <= MAX_GYRO_RAD_S:
            return {**out, "method": "full-scale plateau",
                    "evidence": f"the moves clip at {np.degrees(level):.0f} deg/s, a gyro full scale in rad/s "
                                f"({ev})"}
    norm = np.linalg.norm(accel_m_s2, axis=1)
    mv = rate > max(3.0 * float(np.median(rate)), np.radians(2.0))  # moving samples (rest noise has no axis)
    w_along = np.einsum("ij,ij->i", gyro_rad_s[mv] - bias, accel_m_s2[mv]) / np.maximum(norm[mv], 1e-12)
    along = float(np.abs(w_along).sum())
    share = along / max(float(rate[mv].sum()), 1e-300)
    if seen < tilt_rate.MIN_TILT_RAD and share >= MIN_GRAVITY_AXIS_SHARE:
        g = float(np.median(norm))
        fast = rate > MAX_GRAVITY_AXIS_RATE_RAD_S
        if fast.any() and float(np.max(np.abs(norm[fast] - g))) < 0.05 * g:
            raise ValueError(f"gyro implausible for rad/s: it turns about gravity at up to {rate.max():.3g} rad/s "
                             f"({int(fast.sum())} samples above {MAX_GRAVITY_AXIS_RATE_RAD_S:.3g} rad/s) while |a| "
                             f"stays within 5 % of {g:.3f} m/s^2 (no centripetal acceleration); deg/s read as "
                             f"rad/s? use --gyro-unit deg/s")
        return {**out, "method": "rotation about gravity",
                "evidence": f"gyro turns {turned:.1f} deg about gravity only (accelerometer cannot check the "
                            f"units; peak rate {rate.max():.3g} rad/s)"}
    detail = (f"no rest pair with a tilt change; {ev}; gyro turns {turned:.1f} deg in total, "
              f"{100 * share:.0f} % of it about gravity")
    lean = (np.isfinite(tr["scale"]) and np.isfinite(tr["correlation"])
            and tr["correlation"] >= MIN_LEAN_CORRELATION
            and not 1.0 / MAX_LEAN_RATIO <= tr["scale"] <= MAX_LEAN_RATIO)
    if lean:
        raise ValueError(f"gyro units doubtful: {lean_hint}; no check decides but the tilt "
                         f"rate leans to a scale of {tr['scale']:.3g} (correlation {tr['correlation']:.2f} >= "
                         f"{MIN_LEAN_CORRELATION:g}, outside 1/{MAX_LEAN_RATIO:g}..{MAX_LEAN_RATIO:g}); {detail}")
    weak = ""   # a scale off by more than MAX_LEAN_RATIO on a weak correlation: said, not decided
    if np.isfinite(tr["scale"]) and not 1.0 / MAX_LEAN_RATIO <= tr["scale"] <= MAX_LEAN_RATIO:
        weak = (f"; the tilt rate leans weakly (correlation {tr['correlation']:.2f} < {MIN_LEAN_CORRELATION:g}) to "
                f"a scale of {tr['scale']:.3g}: {lean_hint}?")
    if unit_stated:
        return {**out, "method": "stated unit (unchecked)", "evidence": detail,
                "warning": f"gyro unit as stated ({unit_stated}) not checked: no check decides ({detail}){weak}"}
    # no unit stated and nothing decides: refused (a deg/s log read as rad/s would be 57x off); the hint guesses no
    # unit the evidence does not support
    raise ValueError(f"cannot check the gyro units: state the unit with --gyro-unit (rad/s, the default, or deg/s) "
                     f"and check --time-unit, or record rests at different tilts; {detail}{weak}")


def check_record_units(gyro_rad_s: np.ndarray, accel_m_s2: np.ndarray, dt_s: float, time_s: np.ndarray, rests: list,
                       *, unit_stated: str | None = None) -> dict:
    """:func:`check_units` of one checked record as the systems run it: the gyro weighted by its time column
    (:func:`time_base`), the samples on a full-scale plateau skipped (:func:`clipped_samples`).

    The arrays are a system's checked record (:func:`mtcal.systems.rests.checked_record`); ``time_s`` its N
    sample times. Used by :func:`mtcal.systems.rests.rests_record` and
    :func:`mtcal.systems.surface_angle.surface_axis_record`.

    Examples
    --------
    >>> acc = np.tile([0.0, 0.0, 9.81], (500, 1))
    >>> check_record_units(np.zeros((500, 3)), acc, 0.01, np.arange(500) * 0.01, [])["method"]
    'no rotation'
    """
    weights = time_base(accel_m_s2.shape[0], time_s=time_s)[1]
    return check_units(gyro_rad_s if weights is None else gyro_rad_s * weights[:, None], accel_m_s2, dt_s, rests,
                       time_s=time_s, skip=clipped_samples(gyro_rad_s)[0], unit_stated=unit_stated)


def rotation_axis_from_gyro(gyro_rad_s: np.ndarray, bias_rad_s: np.ndarray, moving: np.ndarray):
    """Principal rotation axis of the bias-corrected gyro over ``moving`` samples.

    Parameters
    ----------
    gyro_rad_s : ndarray (N, 3)
        Angular rate (rad/s).
    bias_rad_s : ndarray (3,)
        Gyro bias (rad/s), e.g. a rest's mean.
    moving : ndarray (N,) of bool
        Samples to use.

    Returns
    -------
    axis : ndarray (3,) or None
        Unit eigenvector of ``Σ ω ωᵀ`` with the largest eigenvalue (None for < 3 samples).
    share : float
        That eigenvalue's share of the total (1 for a rotation about one axis).
    """
    w = gyro_rad_s[moving] - bias_rad_s
    if w.shape[0] < 3:
        return None, np.nan
    m = w.T @ w
    vals, vecs = np.linalg.eigh(m)
    share = float(vals[-1] / max(vals.sum(), 1e-300))
    return vecs[:, -1], share


def _angle(a, b) -> float:
    return float(np.arctan2(np.linalg.norm(np.cross(a, b)), np.dot(a, b)))


def time_base(n: int, *, dt_s=None, time_s=None) -> tuple[float, np.ndarray | None]:
    """Fixed filter step and per-sample weights from ``dt_s`` or a time column.

    A time column gives the mean step ``1 / fs`` with ``fs = (N − 1)/(t_N−1 − t_0)``;
    when its jitter ``max |Δt − Δt̄| / Δt̄`` reaches 1e-6 the
    gyro is weighted by ``Δt_k / Δt̄`` so a fixed-step filter integrates each
    sample over its own interval (the last sample takes the mean).

    Parameters
    ----------
    n : int
        Samples.
    dt_s : float, optional
        Uniform step (s).
    time_s : array_like (n,), optional
        Strictly increasing sample times (s).

    Returns
    -------
    dt_s : float
    weights : ndarray (n,) or None
        None when the time base is uniform.

    Raises
    ------
    ValueError
        Neither or both given, or a time column of the wrong length / not increasing.

    Examples
    --------
    >>> dt, w = time_base(3, time_s=[0.0, 0.5, 1.0]); float(dt), w
    (0.5, None)
    """
    if (dt_s is None) == (time_s is None):
        raise ValueError("give exactly one of dt_s and time_s")
    if dt_s is not None:
        return positive_scalar(dt_s, "dt_s"), None
    t = as_float_array(time_s, "time_s", ndim=1)
    if t.size != n or n < 2 or not np.all(np.diff(t) > 0):
        raise ValueError(f"time_s must be {n} strictly increasing times, got {t.size} samples")
    fs = (n - 1) / (t[-1] - t[0])
    dt_mean = 1.0 / fs
    dt = np.diff(t)
    jitter = float(max(dt_mean - dt.min(), dt.max() - dt_mean) / dt_mean)
    return dt_mean, (None if jitter < 1e-6 else np.append(dt, dt_mean) * fs)
