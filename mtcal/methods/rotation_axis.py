"""Rotation-axis estimation from three static accelerometer means (wang2022sensors Eq 15/23, Algorithm A1).

While the surface rests, the accelerometer reads gravity ``R(θ, v)ᵀ ā0``: as θ
changes, the reading moves on a circle perpendicular to the axis v (Sec. 2.2,
Fig. 4). Three rest means ā0, ā1, ā2 on that circle give (Eq 23)

    v = ± (ā1 − ā0) × (ā2 − ā1) / ‖(ā1 − ā0) × (ā2 − ā1)‖.

Sign convention (Sec. 2.1): ``v_x ≥ 0``, and if ``v_x = 0`` then ``v_y > 0``
(and, mtcal's completion, if both are 0 then ``v_z > 0``). A constant
accelerometer bias cancels in the differences; white noise does not (see
:func:`axis_error_std`).

Degenerate geometry raises ``ValueError``: fewer than three rests, means that
are (nearly) identical or collinear, or an axis too close to vertical (the
rotation then barely changes the measured gravity).

Two front ends: :class:`AxisEstimator` is Algorithm A1 as a streaming state
machine fed one sample (acceleration + ZVD flag) at a time; :func:`estimate_axis`
runs the same logic over a whole record and returns identical results.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from mtcal.core.validate import as_float_array, positive_scalar
from mtcal.methods.zero_velocity import ZvdParams, detect_static, rest_intervals

__all__ = ["axis_from_means", "apply_sign_convention", "axis_elevation", "angle_between",
           "AxisEstimator", "AxisResult", "estimate_axis", "axis_error_std",
           "gravity_change_norm", "distinct_positions", "AxisPlaneFit", "fit_axis_plane", "angles_about_axis",
           "AxisEstimate"]

DEFAULT_MIN_SEPARATION_DEG = 0.5
DEFAULT_MAX_ELEVATION_DEG = 85.0


def angle_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Angle (rad) between vectors a and b (..., 3), robust near 0 (atan2 form).

    Preconditions
    -------------
    The caller guarantees (not checked here): ``a``, ``b`` finite float64 ndarrays (..., 3) that broadcast.

    Examples
    --------
    >>> import numpy as np
    >>> round(float(np.degrees(angle_between(np.array([1.0, 0, 0]), np.array([0, 2.0, 0])))), 6)
    90.0
    """
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), np.sum(a * b, axis=-1))


def apply_sign_convention(v: np.ndarray) -> np.ndarray:
    """Flip v (..., 3) so that ``v_x ≥ 0`` (``v_y > 0`` if ``v_x = 0``, then ``v_z > 0``).

    Preconditions
    -------------
    The caller guarantees (not checked here): ``v`` a finite float64 ndarray (..., 3).

    Examples
    --------
    >>> import numpy as np
    >>> (apply_sign_convention(np.array([[-0.6, 0.0, 0.8], [0.0, -1.0, 0.0]])) + 0.0).tolist()
    [[0.6, 0.0, -0.8], [0.0, 1.0, 0.0]]
    """
    key = np.where(v[..., 0] != 0, v[..., 0], np.where(v[..., 1] != 0, v[..., 1], v[..., 2]))
    return np.where((key < 0)[..., None], -v, v)


def axis_elevation(v: np.ndarray, gravity_s: np.ndarray) -> np.ndarray:
    """Angle γ (rad) between the axis v and the horizontal plane, ``asin(|v·ĝ|)``.

    ``gravity_s`` is any static accelerometer reading (sensor frame, m/s²): it
    points along the vertical.

    Preconditions
    -------------
    The caller guarantees (not checked here): ``v``, ``gravity_s`` finite, non-zero float64 ndarrays
    (..., 3) that broadcast (neither needs unit length).

    Examples
    --------
    >>> import numpy as np
    >>> round(float(np.degrees(axis_elevation(np.array([0.6, 0, 0.8]), np.array([0, 0, 9.81])))), 6)
    53.130102
    """
    g = gravity_s
    gn = g / np.linalg.norm(g, axis=-1, keepdims=True)
    vn = v / np.linalg.norm(v, axis=-1, keepdims=True)
    return np.arcsin(np.clip(np.abs(np.sum(vn * gn, axis=-1)), 0.0, 1.0))


def axis_from_means(a0: np.ndarray, a1: np.ndarray, a2: np.ndarray, *,
                    min_separation_deg: float = DEFAULT_MIN_SEPARATION_DEG,
                    max_elevation_deg: float = DEFAULT_MAX_ELEVATION_DEG) -> np.ndarray:
    """Rotation axis from three static means, wang2022sensors Eq 23 (Eq 15 with averages).

    Parameters
    ----------
    a0, a1, a2 : ndarray, shape (..., 3)
        Mean accelerometer readings (m/s²) at three rest positions; leading
        axes are trials (vectorised).
    min_separation_deg : float
        Smallest allowed angle (deg) between any two means, and between the
        chords ``ā1 − ā0`` and ``ā2 − ā1`` (collinearity).
    max_elevation_deg : float
        Largest allowed axis elevation γ above the horizontal (deg).

    Returns
    -------
    ndarray, shape (..., 3)
        Unit axis v with ``v_x ≥ 0``.

    Raises
    ------
    ValueError
        Identical/collinear means or a nearly vertical axis (message gives the angle).

    Preconditions
    -------------
    The caller guarantees (not checked here): ``a0``, ``a1``, ``a2`` finite float64 ndarrays (..., 3) of one
    shape (m/s²); ``min_separation_deg``, ``max_elevation_deg`` finite > 0 (deg). The systems check them at
    their edge (:func:`mtcal.systems.surface_angle.estimate_surface_axis`).

    Examples
    --------
    >>> import numpy as np
    >>> axis_from_means(np.array([0, 0, 9.8]), np.array([0, -9.8, 0]), np.array([0, 0, -9.8])).tolist()
    [1.0, 0.0, 0.0]
    """
    m0, m1, m2 = a0, a1, a2
    min_sep = np.radians(float(min_separation_deg))
    max_el = np.radians(float(max_elevation_deg))
    seps = np.stack([angle_between(m0, m1), angle_between(m1, m2), angle_between(m0, m2)])
    smallest = float(np.min(seps))
    if smallest < min_sep:
        raise ValueError(f"axis estimation needs three distinct rest positions: two static means "
                         f"are only {np.degrees(smallest):.4f} deg apart (minimum "
                         f"{min_separation_deg:g} deg); rotate further between rests")
    d1 = m1 - m0
    d2 = m2 - m1
    n = np.cross(d1, d2)
    chord_angle = np.arctan2(np.linalg.norm(n, axis=-1), np.abs(np.sum(d1 * d2, axis=-1)))
    if float(np.min(chord_angle)) < min_sep:
        raise ValueError(f"static means are nearly collinear: angle between a1-a0 and a2-a1 is "
                         f"{np.degrees(float(np.min(chord_angle))):.4f} deg (minimum "
                         f"{min_separation_deg:g} deg)")
    v = apply_sign_convention(n / np.linalg.norm(n, axis=-1, keepdims=True))
    elev = axis_elevation(v, m0)
    if float(np.max(elev)) > max_el:
        raise ValueError(f"rotation axis is nearly vertical: elevation "
                         f"{np.degrees(float(np.max(elev))):.2f} deg above the horizontal "
                         f"(maximum {max_elevation_deg:g} deg); rotation barely changes gravity")
    return v


def angles_about_axis(axis, accel0_m_s2, means_m_s2) -> np.ndarray:
    """Rotation angle (rad) of each static mean about v relative to ā0, with ``a = R(θ, v)ᵀ ā0`` (wang2022sensors Eq 16).

    Parameters
    ----------
    axis : array_like (3,)
        Unit axis v.
    accel0_m_s2 : array_like (3,)
        Reference rest mean ā0 (m/s²).
    means_m_s2 : array_like (R, 3)
        Rest means (m/s²).

    Returns
    -------
    ndarray (R,)
        Angles (rad) in (−π, π].

    Examples
    --------
    >>> import numpy as np
    >>> round(float(np.degrees(angles_about_axis([1.0, 0, 0], [0, 0, 9.8], [[0, 9.8, 0]])[0])), 6)
    90.0
    """
    v = np.asarray(axis, float)
    a0 = np.asarray(accel0_m_s2, float)
    means = np.asarray(means_m_s2, float).reshape(-1, 3)
    p0 = a0 - v * (v @ a0)
    p = means - np.outer(means @ v, v)
    return -np.arctan2(np.cross(p0, p) @ v, p @ p0)


def gravity_change_norm(elevation_rad, angle_rad: float, g_m_s2: float = 9.8) -> np.ndarray:
    """‖g1 − g0‖ for ``g1 = R(θ, v)ᵀ g0`` and an axis at elevation γ (Fig. 12, Sec. 6).

    Only the component of gravity perpendicular to v rotates, so
    ``‖g1 − g0‖ = 2 g cos γ sin(θ/2)``: γ = 60° halves it (cos 60° = ½).
    """
    gam = as_float_array(elevation_rad, "elevation_rad")
    return 2.0 * g_m_s2 * np.cos(gam) * np.abs(np.sin(0.5 * float(angle_rad)))


def axis_error_std(sigma_mean_m_s2: float, elevation_rad, rest_angles_rad,
                   g_m_s2: float = 9.80665) -> np.ndarray:
    """First-order std (rad) of the Eq 23 axis direction (total over both tilt axes).

    The three means lie on a circle of radius ``r = g cos γ`` (γ = axis
    elevation) at rotation angles φ_i. Noise along the axis (out of the circle's
    plane), σ per mean, tilts the plane through the three points; in-plane noise
    does not tilt it to first order. Writing the out-of-plane offsets as
    ``z_i = c + δᵀ p_i`` with ``p_i = r [cos φ_i, sin φ_i]`` gives
    ``cov(δ) = σ² [(AᵀA)⁻¹]_tilt`` with rows ``A_i = [1, p_iᵀ]``, so

        σ_v = σ √(tr[(AᵀA)⁻¹]_tilt) ∝ σ / (g cos γ):

    halving ‖g1 − g0‖ (γ = 60°) doubles the axis error.

    Parameters
    ----------
    sigma_mean_m_s2 : float
        Std of each component of each rest mean (m/s²), e.g. ``N √(fs) / √n``.
    elevation_rad : array_like
        Axis elevation γ (rad), any shape.
    rest_angles_rad : array_like, shape (3,)
        Rotation angles of the three rests (rad).
    g_m_s2 : float
        Gravity (m/s²).
    """
    sig = positive_scalar(sigma_mean_m_s2, "sigma_mean_m_s2")
    gam = as_float_array(elevation_rad, "elevation_rad")
    phi = as_float_array(rest_angles_rad, "rest_angles_rad", ndim=1, last_dim=3)
    a = np.stack([np.ones(3), np.cos(phi), np.sin(phi)], axis=1)
    cov = np.linalg.inv(a.T @ a)
    unit = np.sqrt(cov[1, 1] + cov[2, 2])  # tilt std for r = 1 and σ = 1
    return sig * unit / (positive_scalar(g_m_s2, "g_m_s2") * np.cos(gam))


@dataclass
class AxisEstimator:
    """Algorithm A1 (Appendix A) as a streaming state machine.

    Feed samples with :meth:`push`; a rest is buffered while the ZVD says
    static and closed (averaged) at the first moving sample after it, as in
    A1 lines 5–13. mtcal additions, both off by default-compatible values:
    rests shorter than ``min_rest_samples`` are discarded (Sec. 3.2 asks for
    ≥ 1 s, so a ZVD flicker during motion is not a "rest"), and a rest whose
    mean is within ``min_separation_deg`` of an earlier rest is merged into
    it (same position seen twice, e.g. a ZVD dropout splitting one rest);
    ``min_rest_samples`` applies to the merged total.
    Running sums replace A1's sample buffer (same mean, O(1) memory).

    Attributes
    ----------
    means : list of ndarray (3,)
        Accepted rest means ā0, ā1, ā2 (m/s²).
    rests : list of [start, stop)
        Sample index ranges ``[first start, stop at acceptance)`` of the accepted rests.
    v : ndarray (3,) or None
        Axis once three rests are accepted.
    """

    min_rest_samples: int = 1
    min_separation_deg: float = DEFAULT_MIN_SEPARATION_DEG
    max_elevation_deg: float = DEFAULT_MAX_ELEVATION_DEG
    means: list = field(default_factory=list)
    rests: list = field(default_factory=list)
    v: np.ndarray | None = None
    _groups: list = field(default_factory=list)
    _accepted: list = field(default_factory=list)
    _buf_sum: np.ndarray = field(default_factory=lambda: np.zeros(3))
    _buf_n: int = 0
    _buf_start: int = 0
    _k: int = 0

    @property
    def count(self) -> int:
        """Number of accepted rests (A1's ``count``)."""
        return len(self.means)

    def push(self, accel_m_s2, is_static: bool) -> bool:
        """Feed one sample; return True once the axis is available (A1 lines 4–22)."""
        if self.v is None:
            if bool(is_static):
                if self._buf_n == 0:
                    self._buf_start = self._k
                self._buf_sum += accel_m_s2
                self._buf_n += 1
            elif self._buf_n:
                self._close_rest()
            if len(self.means) == 3:
                self.v = axis_from_means(*self.means, min_separation_deg=self.min_separation_deg,
                                         max_elevation_deg=self.max_elevation_deg)
        self._k += 1
        return self.v is not None

    def _close_rest(self) -> None:
        n, total, start = self._buf_n, self._buf_sum, self._buf_start
        self._buf_sum = np.zeros(3)
        self._buf_n = 0
        mean = total / n
        for grp in self._groups:  # same position seen again (e.g. ZVD dropout): merge
            if angle_between(grp[0] / grp[1], mean) < np.radians(self.min_separation_deg):
                grp[0] = grp[0] + total
                grp[1] += n
                break
        else:
            grp = [total.copy(), n, start, self._k, False]
            self._groups.append(grp)
        if not grp[4] and grp[1] >= self.min_rest_samples and len(self.means) < 3:
            grp[4] = True
            self._accepted.append(grp)
            self.rests.append((grp[2], self._k))
        self.means = [g[0] / g[1] for g in self._accepted]


@dataclass(frozen=True)
class AxisResult:
    """Result of :func:`estimate_axis`.

    Attributes
    ----------
    v : ndarray (3,)
        Unit axis (``v_x ≥ 0``).
    means : ndarray (3, 3)
        Rest means ā0, ā1, ā2 (m/s²), rows.
    rests : list of slice
        Sample ranges of the three accepted rests.
    is_static : ndarray (N,) of bool
        ZVD flags used.
    n_rests_found : int
        Distinct rests found in the whole record (≥ 3).
    """

    v: np.ndarray
    means: np.ndarray
    rests: list
    is_static: np.ndarray
    n_rests_found: int


def estimate_axis(accel_m_s2: np.ndarray, dt_s: float, *, zvd: ZvdParams | None = None,
                  is_static: np.ndarray | None = None, min_rest_s: float = 0.5, min_separation_deg: float = DEFAULT_MIN_SEPARATION_DEG,
                  max_elevation_deg: float = DEFAULT_MAX_ELEVATION_DEG) -> AxisResult:
    """Algorithm A1 over a whole record: ZVD, rest means, Eq 23 from the first three rests.

    Parameters
    ----------
    accel_m_s2 : ndarray, shape (N, 3)
        Accelerometer record (m/s²).
    dt_s : float
        Sample interval (s), ≤ 1 s.
    zvd : ZvdParams, optional
        ZVD thresholds (Table 1 by default).
    is_static : ndarray of bool (N,), optional
        Precomputed ZVD flags (otherwise computed with ``zvd``).
    min_rest_s : float
        Shortest rest (s) counted; Sec. 3.2 asks for ≥ 1 s of rest.
    min_separation_deg, max_elevation_deg : float
        Degeneracy limits, see :func:`axis_from_means`.

    Returns
    -------
    AxisResult

    Raises
    ------
    ValueError
        Fewer than three distinct rests, or degenerate geometry.

    Preconditions
    -------------
    The caller guarantees (not checked here): ``accel_m_s2`` finite float64 (N, 3) in m/s², not g
    (:func:`mtcal.core.validate.check_accel_units`); ``dt_s`` a sample interval in (0, 1] s; ``zvd`` None
    or a :class:`ZvdParams`; ``is_static`` None or a boolean ndarray (N,); ``min_rest_s`` ≥ 0 (s);
    ``min_separation_deg``, ``max_elevation_deg`` finite > 0 (deg).
    :func:`mtcal.systems.surface_angle.surface_axis_record` (``mtcal axis --rest-detector paper``) checks a
    log once at its edge.

    Examples
    --------
    >>> import numpy as np
    >>> rest = [[0, 0, 9.8], [0, -9.8, 0], [0, 0, -9.8], [0, 0, 9.8]]
    >>> acc = np.repeat(np.array(rest, float), 60, axis=0)
    >>> flags = np.ones(240, bool); flags[[59, 119, 179]] = False      # a moving sample closes each rest
    >>> res = estimate_axis(acc, 0.01, is_static=flags)
    >>> res.v.tolist(), res.rests
    ([1.0, 0.0, 0.0], [slice(0, 59, None), slice(60, 119, None), slice(120, 179, None)])
    """
    a, dt = accel_m_s2, dt_s
    fs = 1.0 / dt  # the rate: exact for the rates mtcal uses (1 / (1 / fs) == fs)
    static = detect_static(a, dt, zvd) if is_static is None else is_static
    est = AxisEstimator(min_rest_samples=max(int(round(min_rest_s * fs)), 1),
                        min_separation_deg=min_separation_deg, max_elevation_deg=max_elevation_deg)
    # A rest only counts once motion follows it (A1): drop a rest running to the end.
    for sl in rest_intervals(static):
        if sl.stop >= a.shape[0]:
            break
        est._buf_start, est._k = sl.start, sl.stop
        est._buf_sum = a[sl].sum(axis=0)
        est._buf_n = sl.stop - sl.start
        est._close_rest()
        if len(est.means) == 3:
            break
    n_found = len(est.means)
    if n_found < 3:
        raise ValueError(f"found only {n_found} distinct rest(s) of >= {min_rest_s:g} s in the record; "
                         f"axis estimation needs three (hold still >= 1 s at three positions)")
    v = axis_from_means(*est.means, min_separation_deg=min_separation_deg,   # means of the checked record
                        max_elevation_deg=max_elevation_deg)
    rests = [slice(s, e) for s, e in est.rests]
    return AxisResult(v, np.array(est.means), rests, static, n_found)


def distinct_positions(means: np.ndarray, counts: np.ndarray, *,
                       min_separation_deg: float) -> tuple[np.ndarray, np.ndarray, list]:
    """Merge rest means whose directions are within ``min_separation_deg`` (same position seen again).

    Parameters
    ----------
    means : ndarray, shape (R, 3)
        Rest mean accelerations (m/s²), time order.
    counts : ndarray, shape (R,)
        Samples per rest (weights of the merged mean).
    min_separation_deg : float
        Rests closer than this (deg) are one position.

    Returns
    -------
    positions : ndarray (P, 3)
        Sample-weighted mean of each position (m/s²), in order of first visit.
    weights : ndarray (P,)
        Samples per position.
    members : list of list of int
        Rest indices merged into each position.

    Preconditions
    -------------
    The caller guarantees (not checked here): ``means`` finite float64 (R, 3) (m/s²), ``counts`` finite
    float64 (R,) > 0, ``min_separation_deg`` finite > 0 (deg).

    Examples
    --------
    >>> import numpy as np
    >>> pos, w, members = distinct_positions(np.array([[0, 0, 9.8], [0, 0.01, 9.8], [0, 9.8, 0]]),
    ...                                      np.array([10.0, 10.0, 5.0]), min_separation_deg=1.0)
    >>> w.tolist(), members
    ([20.0, 5.0], [[0, 1], [2]])
    """
    m, n = means, counts
    tol = np.radians(min_separation_deg)
    sums, weights, members = [], [], []
    for i, (mi, ni) in enumerate(zip(m, n)):
        for k in range(len(sums)):
            if angle_between(sums[k] / weights[k], mi) < tol:
                sums[k] = sums[k] + mi * ni
                weights[k] += ni
                members[k].append(i)
                break
        else:
            sums.append(mi * ni)
            weights.append(float(ni))
            members.append([i])
    w = np.array(weights)
    return np.array(sums).reshape(-1, 3) / w[:, None], w, members


@dataclass(frozen=True)
class AxisPlaneFit:
    """Result of :func:`fit_axis_plane`.

    Attributes
    ----------
    v : ndarray (3,)
        Unit axis, sign convention ``v_x ≥ 0``.
    sigma_rad : float
        First-order 1σ direction uncertainty (rad), total over both tilt axes.
    rms_out_of_plane_m_s2 : float
        RMS distance of the positions from the fitted plane (0 for three).
    elevation_rad : float
        Axis elevation above the horizontal (rad).
    """

    v: np.ndarray
    sigma_rad: float
    rms_out_of_plane_m_s2: float
    elevation_rad: float


def gated_plane_fit(positions_m_s2: np.ndarray, counts: np.ndarray, accel_noise_m_s2: float,
                    window_samples: float, max_axis_error_deg: float, sigma_floor_m_s2: float) -> "AxisPlaneFit":
    """:func:`fit_axis_plane` with the rest-mean noise from the sample counts, refused when too uncertain.

    The std of a position's mean is ``max(σ / √n_eff, sigma_floor_m_s2)`` with ``n_eff`` the smallest
    count over ``window_samples`` (~independent windows per rest); a fit whose 1σ exceeds
    ``max_axis_error_deg`` raises ``ValueError`` naming the tilt spread of the positions. The
    procedure of :func:`mtcal.systems.surface_angle.axis_uncertainty`, which checks its inputs.

    Preconditions
    -------------
    The caller guarantees (not checked here): ``positions_m_s2`` finite float64 (P, 3), P ≥ 3 (m/s²);
    ``counts`` float (P,) > 0; ``accel_noise_m_s2`` ≥ 0 (m/s², per sample); ``window_samples`` > 0;
    ``max_axis_error_deg`` > 0 or inf; ``sigma_floor_m_s2`` > 0 (m/s²).

    Examples
    --------
    >>> import numpy as np
    >>> fit = gated_plane_fit(np.array([[0, 0, 9.8], [0, -9.8, 0], [0, 0, -9.8]]), np.array([100.0] * 3),
    ...                       0.01, 1.0, 2.0, 0.017)
    >>> fit.v.tolist(), bool(np.degrees(fit.sigma_rad) < 2.0)
    ([1.0, 0.0, 0.0], True)
    """
    positions, n, noise = positions_m_s2, counts, accel_noise_m_s2
    n_eff = float(np.min(n)) / max(1.0, float(window_samples))  # ~independent windows per rest
    sig = max(noise / np.sqrt(max(n_eff, 1.0)), sigma_floor_m_s2)
    fit = fit_axis_plane(positions, float(sig))
    err = np.degrees(fit.sigma_rad)
    if not err <= max_axis_error_deg:
        spread = max(np.degrees(angle_between(positions[i], positions[j]))
                     for i in range(len(positions)) for j in range(i))
        raise ValueError(f"axis too uncertain: +-{err:.2f} deg (1 sigma) > {max_axis_error_deg:g} deg from "
                         f"{len(positions)} positions at most {spread:.2f} deg apart in tilt (rest-mean noise "
                         f"{sig:.4f} m/s^2, out-of-plane rms {fit.rms_out_of_plane_m_s2:.4f} m/s^2); "
                         f"rotate further between rests")
    return fit


def fit_axis_plane(positions_m_s2: np.ndarray, sigma_mean_m_s2: float) -> AxisPlaneFit:
    """Rotation axis as the normal of the plane through ≥ 3 rest means (Eq 23 generalised).

    The static readings ``R(θ, v)ᵀ ā0`` lie on a circle in a plane
    perpendicular to v (wang2022sensors Sec. 2.2); the normal of the
    least-squares plane through the positions (smallest right-singular vector
    of the centred means) is v. For exactly three positions it equals Eq 23,
    ``(ā1 − ā0) × (ā2 − ā1)``, up to sign. The uncertainty is that of the plane
    tilt for out-of-plane noise σ per position (see :func:`axis_error_std`):
    ``σ_v = σ √tr[(AᵀA)⁻¹]_tilt`` with rows ``A_i = [1, p_i]`` of in-plane
    coordinates; σ is the larger of ``sigma_mean_m_s2`` and the fit's own
    out-of-plane RMS (for ≥ 4 positions).

    Parameters
    ----------
    positions_m_s2 : ndarray, shape (P, 3), P ≥ 3
    sigma_mean_m_s2 : float
        Std of each position's mean (m/s²).

    Preconditions
    -------------
    The caller guarantees (not checked here): ``positions_m_s2`` finite float64 (P, 3) with P ≥ 3 (m/s²);
    ``sigma_mean_m_s2`` finite > 0 (m/s²).

    Examples
    --------
    >>> import numpy as np
    >>> from mtcal.core.rotations import axis_angle_matrix
    >>> v = np.array([0.6, 0.0, 0.8]); a0 = np.array([0.0, 0.0, 9.81])
    >>> pts = np.array([axis_angle_matrix(np.radians(d), v).T @ a0 for d in (0, 90, 180)])
    >>> fit = fit_axis_plane(pts, 0.001)
    >>> bool(np.allclose(fit.v, v)) and fit.sigma_rad < 1e-3
    True
    """
    p, sig = positions_m_s2, sigma_mean_m_s2
    c = p - p.mean(axis=0)
    _, sv, vt = np.linalg.svd(c)
    v = apply_sign_convention(vt[2])
    rms = float(sv[2] / np.sqrt(p.shape[0])) if p.shape[0] > 3 else 0.0
    plane = c @ vt[:2].T
    a = np.column_stack([np.ones(p.shape[0]), plane])
    gram = a.T @ a
    if np.linalg.cond(gram) > 1e12:
        sigma = np.inf
    else:
        cov = np.linalg.inv(gram)
        sigma = float(max(sig, rms) * np.sqrt(cov[1, 1] + cov[2, 2]))
    return AxisPlaneFit(v, sigma, rms, float(axis_elevation(v, p.mean(axis=0))))


@dataclass(frozen=True)
class AxisEstimate:
    """Result of :func:`axis_from_rests` (:func:`mtcal.systems.surface_angle.estimate_surface_axis`).

    Attributes
    ----------
    axis : ndarray (3,)
        Unit hinge axis v in the sensor frame (``v_x ≥ 0``).
    sigma_rad : float
        First-order 1σ direction uncertainty (rad).
    elevation_rad : float
        Axis elevation above the horizontal (rad), ``asin |v·â|`` averaged over the rest means.
    positions_m_s2 : ndarray (P, 3)
        Distinct rest positions used (m/s²).
    members : tuple of tuple of int
        Rest indices merged into each position.
    rest_means_m_s2 : ndarray (R, 3)
        Mean of every rest (m/s²).
    rest_angles_rad : ndarray (R,)
        Angle of each rest about v from the first rest (rad, Eq 16).
    sigma_mean_m_s2 : float
        Std of one position mean used for the uncertainty (m/s²).
    fit : str
        ``"plane"`` or ``"eq23"``.
    """

    axis: np.ndarray
    sigma_rad: float
    elevation_rad: float
    positions_m_s2: np.ndarray
    members: tuple
    rest_means_m_s2: np.ndarray
    rest_angles_rad: np.ndarray
    sigma_mean_m_s2: float
    fit: str


def rest_means(accel: np.ndarray, rests: list) -> tuple[np.ndarray, np.ndarray]:
    """Means (R, 3) and sample counts (R,) of rests given as slices or boolean masks (N,).

    Preconditions
    -------------
    The caller guarantees (not checked here): ``accel`` finite float64 (N, 3); each rest a slice or a
    boolean ndarray (N,) (:func:`mtcal.systems.surface_angle.estimate_surface_axis` checks the masks).

    Examples
    --------
    >>> import numpy as np
    >>> means, counts = rest_means(np.arange(12.0).reshape(4, 3), [slice(0, 2), np.array([0, 0, 1, 1], bool)])
    >>> means.tolist(), counts.tolist()
    ([[1.5, 2.5, 3.5], [7.5, 8.5, 9.5]], [2.0, 2.0])
    """
    means, counts = [], []
    for r in rests:
        if isinstance(r, slice):
            means.append(accel[r].mean(axis=0))
            counts.append(float(len(range(*r.indices(accel.shape[0])))))
        else:
            means.append(accel[r].mean(axis=0))
            counts.append(float(np.count_nonzero(r)))
    return np.array(means).reshape(-1, 3), np.array(counts)


def axis_from_rests(a: np.ndarray, rests: list, *, fit: str, min_separation_deg: float,
                    max_elevation_deg: float, max_axis_error_deg: float, accel_noise_m_s2: float,
                    window_samples: float, sigma_floor_m_s2: float) -> AxisEstimate:
    """Hinge axis from the accelerometer means of ≥ 3 rests (wang2022sensors Eq 23, Sec. 2.2), gated.

    Rests closer in tilt than ``min_separation_deg`` are one position (:func:`distinct_positions`);
    ``fit="plane"``: the normal of the least-squares plane through all positions, refused above
    ``max_elevation_deg``; ``fit="eq23"``: Eq 23 on the first three positions
    (:func:`axis_from_means`); both refused above ``max_axis_error_deg`` of 1σ plane-tilt
    uncertainty (:func:`gated_plane_fit`, rest-mean noise floor ``sigma_floor_m_s2``).
    The procedure of :func:`mtcal.systems.surface_angle.estimate_surface_axis`, which checks its inputs.

    Raises
    ------
    ValueError
        A rest without samples; fewer than three distinct tilts; axis too uncertain; axis nearly vertical.

    Preconditions
    -------------
    The caller guarantees (not checked here): ``a`` finite float64 (N, 3) (m/s²); ``rests`` a non-empty
    list of slices or boolean ndarray (N,) masks in time order; ``fit`` "plane" or "eq23"; the limits
    finite > 0 (``max_axis_error_deg`` may be inf); ``accel_noise_m_s2`` ≥ 0 (m/s²); ``window_samples`` > 0;
    ``sigma_floor_m_s2`` > 0 (m/s²).

    Examples
    --------
    >>> import numpy as np
    >>> acc = np.repeat([[0, 0, 9.8], [0, -9.8, 0], [0, 0, -9.8]], 40, axis=0).astype(float)
    >>> est = axis_from_rests(acc, [slice(0, 40), slice(40, 80), slice(80, 120)], fit="eq23",
    ...                       min_separation_deg=0.5, max_elevation_deg=85.0, max_axis_error_deg=np.inf,
    ...                       accel_noise_m_s2=0.01, window_samples=1.0, sigma_floor_m_s2=0.017)
    >>> est.axis.tolist(), len(est.members)
    ([1.0, 0.0, 0.0], 3)
    """
    sep, max_el, max_err = float(min_separation_deg), float(max_elevation_deg), float(max_axis_error_deg)
    means, counts = rest_means(a, rests)
    if not np.all(counts > 0):
        raise ValueError(f"rest {int(np.argmin(counts > 0))} holds no sample; each rest needs samples")
    pos, w, members = distinct_positions(means, counts, min_separation_deg=sep)
    if pos.shape[0] < 3:
        spread = max((np.degrees(angle_between(means[i], means[j]))
                      for i in range(len(means)) for j in range(i)), default=0.0)
        why = (" — a rotation about the vertical does not change the tilt, so the accelerometer "
               "cannot see its axis" if len(rests) >= 2 and spread < sep else "")
        raise ValueError(f"found only {pos.shape[0]} distinct tilt(s) among {len(rests)} rest(s) "
                         f"(largest tilt difference {spread:.2f} deg, positions must be >= {sep:g} deg "
                         f"apart); the axis needs rests at three distinct tilts{why}")
    if fit == "eq23":
        pos, w, members = pos[:3], w[:3], members[:3]
        v = axis_from_means(pos[0], pos[1], pos[2], min_separation_deg=sep, max_elevation_deg=max_el)
    plane = gated_plane_fit(pos, w, float(accel_noise_m_s2), float(window_samples), max_err, sigma_floor_m_s2)
    if fit == "plane":
        v = plane.v
        # v·a is the same at every rest (rotation about v keeps it), so each rest mean gives the elevation;
        # the centroid of the positions is shorter than g and would overstate it.
        elev = float(np.degrees(np.mean(axis_elevation(v, means))))
        if elev > max_el:
            raise ValueError(f"rotation axis is nearly vertical: elevation {elev:.2f} "
                             f"deg above the horizontal (maximum {max_el:g} deg); rotation about it barely "
                             f"changes gravity")
    n_eff = float(np.min(w)) / max(1.0, float(window_samples))
    sig = max(accel_noise_m_s2 / np.sqrt(max(n_eff, 1.0)), sigma_floor_m_s2)
    return AxisEstimate(v, float(plane.sigma_rad), float(np.mean(axis_elevation(v, means))), pos,
                        tuple(tuple(m) for m in members), means, angles_about_axis(v, means[0], means), float(sig),
                        fit)


def axes_from_rests(a: np.ndarray, masks: list[np.ndarray], **settings) -> np.ndarray:
    """:func:`axis_from_rests` on a batch of T records: the hinge axis of each, (T, 3).

    Vectorised where it can be: with ``fit="eq23"``, no uncertainty gate (``max_axis_error_deg``
    inf, a Monte Carlo) and rests all ≥ ``min_separation_deg`` apart in tilt, the rest means and
    Eq 23 (:func:`axis_from_means`) run on all such trials at once; every other trial goes
    through :func:`axis_from_rests` itself. Results equal the per-trial call bit for bit.
    The procedure of :func:`mtcal.systems.surface_angle.estimate_surface_axes`, which checks its inputs.

    Preconditions
    -------------
    The caller guarantees (not checked here): ``a`` finite float64 (T, N, 3) (m/s²); ``masks`` a non-empty
    list of boolean ndarray (T, N) rest masks in time order; ``settings`` the keywords of
    :func:`axis_from_rests`, as it requires them.

    Examples
    --------
    >>> import numpy as np
    >>> acc = np.repeat([[[0.0, 0, 9.8], [0, -9.8, 0], [0, 0, -9.8]]], 10, axis=1)   # one trial, (1, 30, 3)
    >>> masks = [np.arange(30)[None] // 10 == k for k in range(3)]
    >>> axes_from_rests(acc, masks, fit="eq23", min_separation_deg=0.5, max_elevation_deg=85.0,
    ...                 max_axis_error_deg=np.inf, accel_noise_m_s2=0.01, window_samples=1.0,
    ...                 sigma_floor_m_s2=0.017).tolist()
    [[1.0, 0.0, 0.0]]
    """
    sep = float(settings["min_separation_deg"])
    t_n = a.shape[0]
    out = np.empty((t_n, 3))
    fast = np.zeros(t_n, bool)
    if settings["fit"] == "eq23" and settings["max_axis_error_deg"] == np.inf and len(masks) >= 3:
        counts = np.stack([m.sum(axis=1) for m in masks]).astype(float)          # (R, T)
        means = np.full((len(masks), t_n, 3), np.nan)
        from mtcal.methods import _axis_kernels

        for k, m in enumerate(masks):  # the rest means exactly as axis_from_rests takes them
            _axis_kernels.masked_means(a, np.ascontiguousarray(m), means[k])
        # as distinct_positions weights them (mean * n / n), so Eq 23 sees the same numbers
        with np.errstate(invalid="ignore"):
            means = means * counts[..., None] / counts[..., None]
            r_n = len(masks)
            pair = np.stack([angle_between(means[i], means[j])
                             for i in range(r_n) for j in range(i)])
        # strictly apart (a margin for rounding), so per trial no rests would merge
        fast = np.all(counts > 0, axis=0) & np.all(pair > np.radians(sep) * (1 + 1e-9), axis=0)
        if fast.any():
            out[fast] = axis_from_means(*means[:3, fast], min_separation_deg=sep,
                                        max_elevation_deg=float(settings["max_elevation_deg"]))
    for t in np.flatnonzero(~fast):
        out[t] = axis_from_rests(a[t], [m[t] for m in masks], **settings).axis
    return out


def gated_elevation(v: np.ndarray, accel0_m_s2: np.ndarray, max_elevation_deg: float) -> np.ndarray:
    """Elevation of the axis above the horizontal at ā0 (rad, :func:`axis_elevation`), refused above the limit.

    A rotation about the vertical does not change the accelerometer reading, so the RAMS EKF
    (wang2022sensors Eq 24–33) cannot correct the gyro about a nearly vertical axis.

    Raises
    ------
    ValueError
        ``--axis is … deg from gravity`` for the steepest trial above ``max_elevation_deg``.

    Preconditions
    -------------
    The caller guarantees (not checked here): ``v`` unit float64 (3,) or (T, 3); ``accel0_m_s2`` finite
    non-zero float64 (3,) or (T, 3) (m/s²); ``max_elevation_deg`` finite > 0 (deg).

    Examples
    --------
    >>> import numpy as np
    >>> round(float(np.degrees(gated_elevation(np.array([0.6, 0, 0.8]), np.array([0, 0, 9.81]), 85.0))), 6)
    53.130102
    """
    elev = axis_elevation(v, accel0_m_s2)
    max_el = float(max_elevation_deg)
    worst = float(np.degrees(np.max(elev)))
    if worst > max_el:
        raise ValueError(f"--axis is {90 - worst:.2f} deg from gravity (elevation {worst:.2f} deg > {max_el:g}): "
                         f"a rotation about the vertical does not change the accelerometer reading, so the "
                         f"EKF cannot correct the gyro; measure the angle with a non-vertical axis")
    return elev
