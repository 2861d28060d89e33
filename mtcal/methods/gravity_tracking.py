"""Which gyro scale tracks gravity: unit and time-base hypotheses tested on short windows of real motion.

Wherever the specific force is gravity, its direction ``â`` in the sensor frame
turns with the body: ``â(t1) = R(t0→t1)ᵀ â(t0)``, with ``R`` the gyro's
integrated rotation. A gyro read in the wrong unit or on the wrong time base
integrates to ``s`` times the true rotation (``s = 180/π`` for deg/s read as
rad/s, ``1000`` for mrad/s, ``1000`` for a time column in ms read as s …).
So over short windows each hypothesis ``s`` predicts where gravity ends:

``v_s = R_s(t0→t1)ᵀ â(t0)``,  ``R_s`` integrated from ``s·(ω − b)``,

and the accelerometer says where it did end (``â(t1)``). A window
**discriminates** two hypotheses when their predictions differ by at least
``min_difference_deg`` (2°); there, the hypothesis whose prediction lies closer to
``â(t1)`` wins the window. The evidence between the stated scale (1) and a rival
is the fraction of discriminating windows the stated scale wins. Unlike a check
between rests this needs no rest, no tilt *between* rests and no correlation
over the whole record: any stretch that turns the sensor away from the vertical
counts, and a window spoiled by linear acceleration is one vote, not a bias in
a fitted scale.

Windows are ``window_s`` long (0.5 s; shorter on a record of fewer than 40 such windows, down
to 4 samples, so a short record still has 40), their ends are ``avg_s`` (0.05 s)
accelerometer means, and a window is used only when both ends read ``‖a‖``
within ``band_fraction`` (10 %) of the record's median ``‖a‖`` (linear
acceleration). The gyro bias ``b`` is the median of the 10 % quietest samples
(over a 0.5 s window a bias of 1°/s moves the prediction by 0.5°, below the
2° that discriminates).

References
----------
wang2022sensors Sec. 2.2 (static gravity reading ``R(θ, v)ᵀ ā0``: a rotation shows as a change of the
accelerometer direction); wang2023cja Eq 5–7 (the QNCF propagates the same gravity direction with the gyro).

Examples
--------
>>> import numpy as np
>>> dt = 0.01
>>> t = np.arange(3000) * dt
>>> rate = 0.8 * np.sin(2 * np.pi * 0.3 * t)                    # rad/s about x
>>> angle = np.cumsum(rate) * dt
>>> accel = 9.81 * np.column_stack([np.zeros_like(t), np.sin(angle), np.cos(angle)])
>>> gyro = np.column_stack([rate, np.zeros_like(t), np.zeros_like(t)])
>>> res = gravity_tracking(gyro, accel, dt)
>>> res["decision"], res["rivals"]["deg/s read as rad/s"]["win_fraction"]
('stated', 1.0)
>>> gravity_tracking(np.degrees(gyro), accel, dt)["winner"]       # deg/s under a rad/s header
'deg/s read as rad/s'
"""

from __future__ import annotations

import numpy as np

from mtcal.core.validate import float64_array, positive_scalar

__all__ = ["gravity_tracking", "HYPOTHESES", "MIN_WINDOWS", "CONFIRM_FRACTION", "CONTRADICT_FRACTION"]

#: Rival hypotheses: name → factor the *given* gyro must be multiplied by to be right
#: (gyro unit or time base; each name says what was mislabelled).
HYPOTHESES = {
    "deg/s read as rad/s": np.pi / 180.0,
    "rad/s read as deg/s": 180.0 / np.pi,
    "mrad/s read as rad/s (or time in ms read as s)": 1e-3,
    "rad/s read as mrad/s (or time in s read as ms)": 1e3,
    "time column 10x too fast": 10.0,
    "time column 10x too slow": 0.1,
}
#: Fewest discriminating windows for a verdict between the stated scale and a rival.
MIN_WINDOWS = 5
#: The stated scale is confirmed when it wins at least this fraction of the discriminating windows
#: against every rival.
CONFIRM_FRACTION = 0.8
#: A rival contradicts the stated scale when it wins at least this fraction of the discriminating windows.
#: Higher than :data:`CONFIRM_FRACTION` on purpose: linear acceleration tilts the accelerometer without a
#: rotation, which favours whichever hypothesis predicts the *smaller* rotation (on real hand-held slow
#: translation recordings in correct rad/s, a 57x smaller rotation was measured to win up to 72 % of the
#: few discriminating windows).
CONTRADICT_FRACTION = 0.9


def _rotate_back(v: np.ndarray, w: np.ndarray, dt_s: float) -> np.ndarray:
    """``R(ω dt)ᵀ v`` for rows ``v`` (W, 3) and rates ``w`` (W, 3) (Rodrigues, exact for a constant rate)."""
    th = w * dt_s
    ang = np.sqrt(np.einsum("ij,ij->i", th, th))[:, None]
    k = th / np.maximum(ang, 1e-300)
    c, s = np.cos(ang), np.sin(ang)
    return v * c - np.cross(k, v) * s + k * np.einsum("ij,ij->i", k, v)[:, None] * (1.0 - c)


def _angle_deg(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), np.einsum("...i,...i->...", a, b)))


def gravity_tracking(gyro_rad_s, accel_m_s2, dt_s: float, *, window_s: float = 0.5, avg_s: float = 0.05,
                     band_fraction: float = 0.1, min_difference_deg: float = 2.0,
                     max_windows: int = 2000, hypotheses: dict | None = None) -> dict:
    """Test the gyro's stated scale against unit/time-base rivals by how each tracks gravity.

    Parameters
    ----------
    gyro_rad_s : array_like (N, 3)
        Angular rate as read (rad/s under the stated unit), for the fixed step ``dt_s``.
    accel_m_s2 : array_like (N, 3)
        Specific force (m/s²).
    dt_s : float
        Sample interval (s) under the stated time base.
    window_s, avg_s : float
        Window length and the accelerometer averaging at each end (s).
    band_fraction : float
        A window end is used only when its mean ``‖a‖`` is within this fraction of the median ``‖a‖``.
    min_difference_deg : float
        Two predictions closer than this (deg) do not discriminate the two hypotheses in that window.
    max_windows : int
        At most this many windows, evenly spread over the record (bounded time on long records).
    hypotheses : dict, optional
        Rivals, name → factor (default :data:`HYPOTHESES`).

    Returns
    -------
    dict
        ``windows`` (used), ``rivals`` (name → ``factor``, ``windows`` discriminating, ``win_fraction`` of the
        stated scale, NaN without windows), ``decision`` (``"stated"``: the stated scale wins ≥
        :data:`CONFIRM_FRACTION` against every rival on ≥ :data:`MIN_WINDOWS` windows; ``"rival"``: a rival
        wins ≥ :data:`CONTRADICT_FRACTION` on ≥ :data:`MIN_WINDOWS`; else ``"undecided"``), ``winner``
        (the contradicting rival that wins most windows head to head against the other contradicting ones,
        or None), ``margin`` (the stated scale's smallest win fraction
        against the rivals it was tested against — or, for ``"rival"``, the rival's) and ``evidence``
        (one line).

    Raises
    ------
    ValueError
        Shapes not (N, 3) alike, values not finite, ``dt_s`` not positive.
    """
    w = float64_array(gyro_rad_s, "gyro_rad_s")
    a = float64_array(accel_m_s2, "accel_m_s2")
    if w.ndim != 2 or w.shape[1] != 3 or w.shape != a.shape:
        raise ValueError(f"gyro_rad_s and accel_m_s2 must be (N, 3) alike, got {w.shape} and {a.shape}")
    if not (np.isfinite(w).all() and np.isfinite(a).all()):
        raise ValueError("gyro_rad_s and accel_m_s2 must be finite")
    dt_s = positive_scalar(dt_s, "dt_s")
    hyp = dict(HYPOTHESES if hypotheses is None else hypotheses)
    n = a.shape[0]
    m = max(4, min(int(round(window_s / dt_s)), n // 40))  # a short record still gets 40 windows
    h = max(1, min(int(round(avg_s / dt_s)), m // 4))
    nw = n // m
    empty = {"windows": 0, "rivals": {k: {"factor": f, "windows": 0, "win_fraction": float("nan")}
                                      for k, f in hyp.items()},
             "decision": "undecided", "winner": None, "margin": float("nan"),
             "evidence": "gravity tracking: record shorter than one window"}
    if nw < 1:
        return empty
    starts = np.arange(nw) * m
    if nw > max_windows:
        starts = starts[np.linspace(0, nw - 1, max_windows).round().astype(int)]
    idx = starts[:, None] + np.arange(m)[None, :]
    A, W = a[idx], w[idx]
    norm_all = np.linalg.norm(a, axis=1)
    g = float(np.median(norm_all))
    rate = np.linalg.norm(w, axis=1)
    bias = np.median(w[rate <= np.percentile(rate, 10)], axis=0)
    a0, a1 = A[:, :h].mean(axis=1), A[:, -h:].mean(axis=1)
    n0, n1 = np.linalg.norm(a0, axis=1), np.linalg.norm(a1, axis=1)
    ok = (np.abs(n0 - g) <= band_fraction * g) & (np.abs(n1 - g) <= band_fraction * g)
    u0, u1 = a0 / np.maximum(n0, 1e-12)[:, None], a1 / np.maximum(n1, 1e-12)[:, None]
    u0, u1, W = u0[ok], u1[ok], W[ok] - bias
    used = int(ok.sum())
    if used == 0:
        return {**empty, "evidence": f"gravity tracking: no window whose ends read |a| within "
                                     f"{100 * band_fraction:g} % of {g:.3f} m/s^2"}
    # gravity from the middle of the first end-average to the middle of the last one
    steps = range(h // 2, m - (h + 1) // 2)
    pred = {}
    for name, f in {"stated": 1.0, **hyp}.items():
        v = u0.copy()
        for k in steps:
            v = _rotate_back(v, f * W[:, k], dt_s)
        pred[name] = v
    err = {name: _angle_deg(v, u1) for name, v in pred.items()}
    rivals = {}
    for name, f in hyp.items():
        dis = _angle_deg(pred["stated"], pred[name]) >= min_difference_deg
        nd = int(dis.sum())
        frac = float(np.mean(err["stated"][dis] < err[name][dis])) if nd else float("nan")
        rivals[name] = {"factor": f, "windows": nd, "win_fraction": frac}
    tested = {k: r for k, r in rivals.items() if r["windows"] >= MIN_WINDOWS}
    against = {k: 1.0 - r["win_fraction"] for k, r in tested.items()}
    decision, winner, margin = "undecided", None, float("nan")
    contra = [k for k, f in against.items() if f >= CONTRADICT_FRACTION]
    if contra:  # several rivals can beat the stated scale (57x and 1000x both shrink it): head to head
        def head_to_head(k: str) -> float:
            fr = []
            for o in contra:
                dis = _angle_deg(pred[k], pred[o]) >= min_difference_deg
                if o != k and dis.any():
                    fr.append(float(np.mean(err[k][dis] < err[o][dis])))
            return min(fr, default=1.0)

        winner = max(contra, key=head_to_head)
        decision, margin = "rival", against[winner]
    elif tested:
        margin = min(r["win_fraction"] for r in tested.values())
        if len(tested) == len(rivals) and margin >= CONFIRM_FRACTION:
            decision = "stated"
    parts = ", ".join(f"x{r['factor']:.3g} {r['win_fraction']:.2f}/{r['windows']}" for r in rivals.values())
    ev = (f"gravity tracking, {used} windows of {m * dt_s:.2f} s, stated unit's wins/windows vs gyro scale {parts} "
          f"(decides at {CONFIRM_FRACTION:g} vs every scale, a scale at {CONTRADICT_FRACTION:g}, "
          f">= {MIN_WINDOWS} windows)")
    return {"windows": used, "rivals": rivals, "decision": decision, "winner": winner, "margin": margin,
            "evidence": ev}
