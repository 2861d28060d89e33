"""wang2022sensors movable-surface angle system: rotation axis from rests, then the ZVD-switched RAMS EKF.

The measurement procedure of the paper (Sec. 2–3, Algorithm A1) as two steps and their batch
over plain arrays, the same code for the ``mtcal axis`` / ``mtcal angle``
commands, the study's Monte Carlo runs and the sweep evaluator:

1. :func:`estimate_surface_axis` — the accelerometer means of ≥ 3 rests lie on a
   circle perpendicular to the hinge axis v (Sec. 2.2), so v is the normal of
   their plane (Eq 23 for exactly three means, ``fit="eq23"``; the least-squares
   plane through all distinct positions, ``fit="plane"``), with its first-order
   1σ uncertainty and the gates a user needs: fewer than three distinct tilts,
   an axis too uncertain, an axis nearly vertical (rotation barely changes
   gravity).
2. :func:`surface_angle` — the RAMS EKF (Eq 24–33) about a known axis, ā0 and
   the initial gyro bias from a rest (Sec. 2.2), V switched by the ZVD flags
   (Sec. 3.3.3), refused for an axis nearly along gravity; restarted with a wide
   angle prior at each rest that follows clipped gyro samples (mtcal addition:
   a clipped gyro under-reports the move, and the rest's accelerometer must set
   the angle again). Optional plausibility gates (gyro units/time base against
   the accelerometer's tilt change, gyro turning about another axis) come from
   :mod:`mtcal.systems.plausibility`.
3. :func:`surface_angle_batch` — the whole procedure on T stacked trials (the study's
   Monte Carlo): ā0 and bias from the initial rest, the Table 1 ZVD (Sec. 3.1), Eq 23 on
   the ZVD-flagged rests, the ZVD-switched EKF.
4. :func:`surface_angle_record` — the procedure on one recorded log (``mtcal angle``): its
   rests (:func:`mtcal.systems.rests.find_rests`), the initial rest, the checked EKF and each
   rest's EKF and accelerometer angles, in one call.
5. :func:`surface_axis_record` — the axis of one recorded log (``mtcal axis``), for either rest
   detector: adaptive/SHOE rests, the units check and the gated plane through every position,
   or the paper's Table 1 ZVD and Algorithm A1, in one call.

Each procedure checks its inputs, then goes down once: the axis estimate and its gates are
methods (:func:`mtcal.methods.rotation_axis.axis_from_rests`,
:func:`~mtcal.methods.rotation_axis.gated_elevation`), the EKF a filter call
(:func:`mtcal.filters.rams_ekf.run_rams_ekf_restarts` /
:func:`~mtcal.filters.rams_ekf.run_rams_ekf_batch_restarts`).

Each procedure takes the data arrays and ONE frozen, resolved config —
:class:`AxisConfig`, :class:`SurfaceAngleConfig`, :class:`SurfaceBatchConfig`, :class:`SurfaceRecordConfig`,
:class:`AxisRecordConfig` — with constructors for the paper's settings (``paper``), the CLI defaults
(``cli``) and a sweep cell (:meth:`SurfaceAngleConfig.sweep_cell`, :meth:`SurfaceBatchConfig.sweep_cell`). A config is checked when it is made, the
arrays once at the procedure's edge; the methods and the filter below run on the checked
arrays (each states the preconditions its caller guarantees).

References
----------
wang2022sensors: Wang C., Tu X., Chen Q., Yang Q., Fang T., Sensors 2022, 22, 8996
(Sec. 2.2 Eq 15/16 static model, Eq 23 axis, Algorithm A1, Sec. 3.3 Eq 24–33 EKF,
Table 1 ZVD).

Examples
--------
>>> import numpy as np
>>> from mtcal.core.rotations import axis_angle_matrix
>>> v = np.array([0.6, 0.0, 0.8]); a0 = np.array([0.0, 0.0, 9.81])
>>> accel = np.concatenate([np.tile(axis_angle_matrix(np.radians(d), v).T @ a0, (50, 1)) for d in (0, 90, 135)])
>>> est = estimate_surface_axis(accel, [slice(0, 50), slice(50, 100), slice(100, 150)], AxisConfig(0.01))
>>> (np.round(est.axis, 9) + 0.0).tolist(), (np.round(np.degrees(est.rest_angles_rad), 6) + 0.0).tolist()
([0.6, 0.0, 0.8], [0.0, 90.0, 135.0])
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from mtcal.core.validate import as_float_array, check_accel_units, positive_scalar, sample_interval
from mtcal.filters.rams_ekf import RamsEkfParams, run_rams_ekf_batch_restarts, run_rams_ekf_restarts
from mtcal.filters.registry import AxisContext
from mtcal.methods import rotation_axis
from mtcal.methods.rotation_axis import AxisEstimate, angles_about_axis
from mtcal.methods.tilt_rate import check_tilt_rate_scale
from mtcal.methods import zero_velocity
from mtcal.methods.zero_velocity import ZvdParams
from mtcal.systems import plausibility
from mtcal.systems.rests import RestsConfig, find_rests

if TYPE_CHECKING:
    from mtcal.methods.rest_detection import RestReport

__all__ = ["AxisConfig", "AxisEstimate", "estimate_surface_axis", "estimate_surface_axes", "axis_uncertainty",
           "AxisRecordConfig", "SurfaceAxisRecord", "surface_axis_record",
           "angles_about_axis", "rest_ekf_params",
           "SurfaceAngleConfig", "SurfaceAngle", "surface_angle",
           "SurfaceRecordConfig", "SurfaceRecordAngle", "surface_angle_record",
           "SurfaceBatchConfig", "SurfaceAngleBatch", "surface_angle_batch", "rest_masks",
           "SIGMA_MEAN_FLOOR_M_S2", "CLIPPED_P0_THETA_RAD", "MIN_TURN_FOR_AXIS_CHECK_DEG", "MIN_REST_ZVD_SHARE",
           "MAX_REST_ANGLE_MISMATCH_DEG"]

#: Floor on the std of a rest mean (m/s²): ~0.1° of tilt (accelerometer cross-axis/nonlinearity, play).
SIGMA_MEAN_FLOOR_M_S2 = 0.017
#: Prior angle std (rad) at the first rest after clipped gyro samples: the rest's accelerometer decides.
CLIPPED_P0_THETA_RAD = np.radians(30.0)
#: The gyro's rotation axis is compared with the given axis once the moves add up to this (deg).
MIN_TURN_FOR_AXIS_CHECK_DEG = 20.0
#: A known rest where the ZVD flags fewer than this share of samples is used whole for the axis (batched procedure).
MIN_REST_ZVD_SHARE = 0.1
#: One record: a rest whose EKF angle differs from the accelerometer's by more than this (deg) is reported.
MAX_REST_ANGLE_MISMATCH_DEG = 2.0


def axis_uncertainty(positions_m_s2, counts, *, accel_noise_m_s2: float, window_samples: float = 1.0,
                     max_axis_error_deg: float = np.inf) -> rotation_axis.AxisPlaneFit:
    """Plane fit of rest positions with its 1σ uncertainty; refused above ``max_axis_error_deg``.

    The std of a rest mean is the accelerometer noise over ``√n_eff`` with
    ``n_eff = min(counts) / max(1, window_samples)`` ~independent windows per rest
    (floor :data:`SIGMA_MEAN_FLOOR_M_S2`); the axis error follows from the plane
    tilt (:func:`mtcal.methods.rotation_axis.fit_axis_plane`, Eq 23 generalised).

    Parameters
    ----------
    positions_m_s2 : array_like (P, 3), P ≥ 3
        Distinct rest positions (m/s²).
    counts : array_like (P,)
        Samples per position.
    accel_noise_m_s2 : float
        Accelerometer noise per sample (m/s²).
    window_samples : float
        Correlation length of the noise estimate (samples), e.g. the rest detector's window.
    max_axis_error_deg : float
        Largest accepted 1σ axis error (deg).

    Returns
    -------
    mtcal.methods.rotation_axis.AxisPlaneFit

    Raises
    ------
    ValueError
        ``axis too uncertain: …`` with the spread of the positions and the noise.

    Examples
    --------
    >>> import numpy as np
    >>> fit = axis_uncertainty([[0, 0, 9.8], [0, -9.8, 0], [0, 0, -9.8]], [100, 100, 100], accel_noise_m_s2=0.01)
    >>> fit.v.tolist(), bool(fit.sigma_rad < 0.01)
    ([1.0, 0.0, 0.0], True)
    """
    positions = as_float_array(positions_m_s2, "positions_m_s2", ndim=2, last_dim=3)
    if positions.shape[0] < 3:
        raise ValueError(f"positions_m_s2 must hold at least 3 positions, got {positions.shape[0]}")
    n = as_float_array(counts, "counts", ndim=1)
    noise = positive_scalar(accel_noise_m_s2, "accel_noise_m_s2", allow_zero=True)
    return rotation_axis.gated_plane_fit(positions, n, noise, window_samples, max_axis_error_deg,
                                         SIGMA_MEAN_FLOOR_M_S2)


def _limit(value, name: str) -> float:
    """A positive finite limit (deg), or ``inf`` for None (no gate)."""
    return np.inf if value is None else positive_scalar(value, name)


@dataclass(frozen=True)
class AxisConfig:
    """Resolved settings of :func:`estimate_surface_axis` / :func:`estimate_surface_axes`, checked once when made.

    Attributes
    ----------
    accel_noise_m_s2 : float
        Accelerometer noise per sample (m/s², ≥ 0).
    window_samples : float
        Correlation length of the noise estimate (samples, > 0), e.g. the rest detector's window.
    fit : {"plane", "eq23"}
        Least-squares plane through all distinct positions, or Eq 23 on the first three (Algorithm A1).
    min_separation_deg : float
        Rests closer in tilt are one position (deg).
    max_axis_error_deg : float or None
        Refuse an axis less certain than this (deg, 1σ); None: no gate (Monte Carlo).
    max_elevation_deg : float
        Refuse an axis steeper than this above the horizontal (deg).

    Examples
    --------
    >>> AxisConfig.paper(0.01).fit, AxisConfig.cli(0.01, 5.0).max_axis_error_deg
    ('eq23', 2.0)
    >>> AxisConfig(0.01, fit="lsq")
    Traceback (most recent call last):
    ...
    ValueError: fit must be 'plane' or 'eq23', got 'lsq'
    """

    accel_noise_m_s2: float
    window_samples: float = 1.0
    fit: str = "plane"
    min_separation_deg: float = 3.0
    max_axis_error_deg: float | None = 2.0
    max_elevation_deg: float = rotation_axis.DEFAULT_MAX_ELEVATION_DEG

    def __post_init__(self) -> None:
        if self.fit not in ("plane", "eq23"):
            raise ValueError(f"fit must be 'plane' or 'eq23', got {self.fit!r}")
        positive_scalar(self.accel_noise_m_s2, "accel_noise_m_s2", allow_zero=True)
        positive_scalar(self.window_samples, "window_samples")
        positive_scalar(self.min_separation_deg, "min_separation_deg")
        positive_scalar(self.max_elevation_deg, "max_elevation_deg")
        _limit(self.max_axis_error_deg, "max_axis_error_deg")

    @classmethod
    def paper(cls, accel_noise_m_s2: float) -> "AxisConfig":
        """The study's Monte Carlo: Eq 23 on the first three rests (Algorithm A1), the method's separation and
        elevation defaults, no uncertainty gate."""
        return cls(accel_noise_m_s2, fit="eq23", min_separation_deg=rotation_axis.DEFAULT_MIN_SEPARATION_DEG,
                   max_axis_error_deg=None, max_elevation_deg=rotation_axis.DEFAULT_MAX_ELEVATION_DEG)

    @classmethod
    def cli(cls, accel_noise_m_s2: float, window_samples: float, *, min_separation_deg: float = 3.0,
            max_axis_error_deg: float = 2.0, max_elevation_deg: float = 85.0) -> "AxisConfig":
        """``mtcal axis``: the plane through every distinct rest position, gated (defaults = the command's)."""
        return cls(accel_noise_m_s2, window_samples, "plane", min_separation_deg, max_axis_error_deg,
                   max_elevation_deg)


def _axis_settings(config: AxisConfig) -> dict:
    """The keywords of :func:`mtcal.methods.rotation_axis.axis_from_rests` a checked config states."""
    return dict(fit=config.fit, min_separation_deg=float(config.min_separation_deg),
                max_elevation_deg=float(config.max_elevation_deg),
                max_axis_error_deg=np.inf if config.max_axis_error_deg is None else float(config.max_axis_error_deg),
                accel_noise_m_s2=config.accel_noise_m_s2, window_samples=config.window_samples,
                sigma_floor_m_s2=SIGMA_MEAN_FLOOR_M_S2)


def estimate_surface_axis(accel_m_s2, rests, config: AxisConfig) -> AxisEstimate:
    """Hinge axis from the accelerometer means of ≥ 3 rests (wang2022sensors Eq 23, Sec. 2.2).

    Rests closer in tilt than ``config.min_separation_deg`` are one position (sample-weighted
    mean). ``fit="plane"``: v is the normal of the least-squares plane through all
    positions (equal to Eq 23 for three). ``fit="eq23"``: Eq 23,
    ``v = (ā1 − ā0) × (ā2 − ā1)``, on the first three positions (Algorithm A1). Both
    report the plane-tilt 1σ uncertainty (:func:`axis_uncertainty`).

    Parameters
    ----------
    accel_m_s2 : array_like (N, 3)
        Accelerometer record (m/s²).
    rests : sequence of slice or boolean mask (N,)
        Rest samples, in time order.
    config : AxisConfig

    Returns
    -------
    AxisEstimate

    Raises
    ------
    ValueError
        Fewer than three distinct tilts (a rotation about the vertical is named);
        axis too uncertain; axis nearly vertical.

    References
    ----------
    wang2022sensors Eq 15/16 (static model), Eq 23 (axis), Algorithm A1.

    Examples
    --------
    >>> import numpy as np
    >>> acc = np.repeat([[0, 0, 9.8], [0, -9.8, 0], [0, 0, -9.8]], 40, axis=0).astype(float)
    >>> est = estimate_surface_axis(acc, [slice(0, 40), slice(40, 80), slice(80, 120)],
    ...                             AxisConfig(0.01, fit="eq23"))
    >>> est.axis.tolist(), round(float(np.degrees(est.elevation_rad)), 6)
    ([1.0, 0.0, 0.0], 0.0)
    """
    if not isinstance(config, AxisConfig):
        raise TypeError(f"config must be an AxisConfig, got {type(config).__name__}")
    settings = _axis_settings(config)
    a = as_float_array(accel_m_s2, "accel_m_s2", ndim=2, last_dim=3)
    rests = [r if isinstance(r, slice) else np.asarray(r) for r in rests]
    if not rests:
        raise ValueError("found no rest; the axis needs rests at three distinct tilts")
    for m in rests:
        if not isinstance(m, slice) and (m.dtype != bool or m.shape != a.shape[:1]):
            raise ValueError(f"each rest must be a slice or a boolean mask of shape {a.shape[:1]}, "
                             f"got {m.dtype} {m.shape}")
    return rotation_axis.axis_from_rests(a, rests, **settings)


def estimate_surface_axes(accel_m_s2, rest_masks, config: AxisConfig) -> np.ndarray:
    """:func:`estimate_surface_axis` on a batch of T records: the hinge axis of each, (T, 3).

    The same procedure per trial (wang2022sensors Eq 23, Algorithm A1), vectorised where it
    can be: with ``fit="eq23"``, no uncertainty gate (``max_axis_error_deg=None``, a Monte
    Carlo) and rests that are all ≥ ``min_separation_deg`` apart in tilt, the rest means and
    Eq 23 (:func:`mtcal.methods.rotation_axis.axis_from_means`) run on all such trials at
    once; every other trial (rests to merge, a plane fit, a gate) goes through
    :func:`estimate_surface_axis` itself. Results equal the per-trial call bit for bit.

    Parameters
    ----------
    accel_m_s2 : array_like (T, N, 3)
        Accelerometer records (m/s²).
    rest_masks : sequence of array_like of bool (T, N)
        Rest samples per trial, one mask per rest, in time order (R ≥ 1).
    config : AxisConfig

    Returns
    -------
    ndarray (T, 3)
        Unit axes (``v_x ≥ 0``).

    Raises
    ------
    ValueError
        A mask of the wrong shape or dtype, and every error of :func:`estimate_surface_axis`
        for the first trial that fails.

    References
    ----------
    wang2022sensors Eq 23 (axis), Algorithm A1.

    Examples
    --------
    >>> import numpy as np
    >>> acc = np.repeat([[0, 0, 9.8], [0, -9.8, 0], [0, 0, -9.8]], 40, axis=0).astype(float)
    >>> masks = [np.zeros((2, 120), bool) for _ in range(3)]
    >>> for k, m in enumerate(masks):
    ...     m[:, 40 * k:40 * k + 40] = True
    >>> estimate_surface_axes(np.stack([acc, acc]), masks, AxisConfig(0.01, fit="eq23",
    ...                       max_axis_error_deg=None)).tolist()
    [[1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]
    """
    if not isinstance(config, AxisConfig):
        raise TypeError(f"config must be an AxisConfig, got {type(config).__name__}")
    settings = _axis_settings(config)
    a = as_float_array(accel_m_s2, "accel_m_s2", ndim=3, last_dim=3, copy=False)
    masks = [np.asarray(m) for m in rest_masks]
    if not masks:
        raise ValueError("found no rest; the axis needs rests at three distinct tilts")
    for m in masks:
        if m.dtype != bool or m.shape != a.shape[:2]:
            raise ValueError(f"each rest mask must be boolean of shape {a.shape[:2]}, got {m.dtype} {m.shape}")
    return rotation_axis.axes_from_rests(a, masks, **settings)


# --------------------------------------------------------------------------- one record (a log): rests → axis
@dataclass(frozen=True)
class AxisRecordConfig:
    """Resolved settings of :func:`surface_axis_record` (``mtcal axis``), checked once when made.

    Attributes
    ----------
    rests : RestsConfig
        How the log's rests are found. ``detector="paper"``: the paper's path, accelerometer only — Table 1
        ZVD flags (rests ≥ ``min_rest_s``, none dropped by their listed span) and Algorithm A1 (Eq 23 on
        the first three distinct rests, :func:`mtcal.methods.rotation_axis.estimate_axis`). Otherwise the
        rests of :func:`mtcal.systems.rests.find_rests` and the plane through every distinct position
        (:meth:`AxisConfig.cli`), the gyro's units checked when the log has one.
    min_separation_deg : float
        Rests closer in tilt are one position (deg).
    max_axis_error_deg : float or None
        Refuse an axis less certain than this (deg, 1σ); None: no gate.
    max_elevation_deg : float
        Refuse an axis steeper than this above the horizontal (deg).

    Examples
    --------
    >>> AxisRecordConfig.cli(RestsConfig.cli_defaults(0.5)).max_axis_error_deg
    2.0
    >>> AxisRecordConfig(RestsConfig(), min_separation_deg=0.0)
    Traceback (most recent call last):
    ...
    ValueError: min_separation_deg must be > 0, got 0.0
    """

    rests: RestsConfig
    min_separation_deg: float = 3.0
    max_axis_error_deg: float | None = 2.0
    max_elevation_deg: float = 85.0

    def __post_init__(self) -> None:
        if not isinstance(self.rests, RestsConfig):
            raise TypeError(f"rests must be a RestsConfig, got {type(self.rests).__name__}")
        positive_scalar(self.min_separation_deg, "min_separation_deg")
        _limit(self.max_axis_error_deg, "max_axis_error_deg")
        positive_scalar(self.max_elevation_deg, "max_elevation_deg")

    @classmethod
    def cli(cls, rests: RestsConfig, *, min_separation_deg: float = 3.0, max_axis_error_deg: float = 2.0,
            max_elevation_deg: float = 85.0) -> "AxisRecordConfig":
        """``mtcal axis`` (defaults = the command's): the given rests, gated."""
        return cls(rests, min_separation_deg, max_axis_error_deg, max_elevation_deg)


@dataclass(frozen=True)
class SurfaceAxisRecord:
    """Result of :func:`surface_axis_record`.

    Attributes
    ----------
    rests : mtcal.methods.rest_detection.RestReport
        The log's rests.
    axis : AxisEstimate
        The hinge axis, its uncertainty and the rests' means and angles about it. With the paper's
        detector the rest means are those of Algorithm A1's three rests (``used``).
    used : tuple of slice
        The rests the axis used (one per distinct position; with the paper's detector A1's three).
    units_check : dict or None
        :func:`mtcal.systems.plausibility.check_units`' result (a log with a gyro, not the paper's path).
    """

    rests: RestReport
    axis: AxisEstimate
    used: tuple
    units_check: dict | None


def surface_axis_record(accel_m_s2, config: AxisRecordConfig, *, fs_hz: float, time_s, gyro_rad_s=None,
                        unit_stated: str | None = None) -> SurfaceAxisRecord:
    """The hinge axis of one recorded log (``mtcal axis``): rests, units check, gated axis (wang2022sensors Eq 23).

    Adaptive or SHOE rests (:func:`mtcal.systems.rests.find_rests`), the gyro's units and time base checked
    against the accelerometer when a gyro is given (clipped samples skipped), then the plane through every
    distinct rest position (:meth:`AxisConfig.cli` with the noise and window the rests measured). The
    paper's detector (``config.rests.detector == "paper"``): Table 1 ZVD and Algorithm A1 on the
    accelerometer, then the plane-tilt uncertainty of its three means (as :func:`axis_uncertainty`). Inputs
    are checked here once.

    Parameters
    ----------
    accel_m_s2 : array_like (N, 3)
        Accelerometer (m/s²).
    config : AxisRecordConfig
    fs_hz : float
        Sample rate of the log (Hz), a rate, not ``dt_s``: the rests run at the mean step ``1 / fs_hz`` and
        the noise window is counted in samples of this rate (``window_s · fs_hz``), as ``mtcal axis`` always
        did (taking ``dt_s`` would move the uncertainty's last bits).
    time_s : array_like (N,)
        Sample times (s): the rests' listed spans and the units check's time base.
    gyro_rad_s : array_like (N, 3), optional
        Gyro (rad/s): used by the rests (``config.rests.use_gyro``) and checked for its units; ignored
        by the paper's path.
    unit_stated : str, optional
        Where the gyro unit was stated (a units check that cannot decide then warns).

    Returns
    -------
    SurfaceAxisRecord

    Raises
    ------
    ValueError
        Bad arrays; no rest; fewer than three distinct tilts; axis too uncertain or nearly vertical; a gyro
        the units check refuses. A refusal after the rests were found carries them as ``exc.rests`` and the
        units check (or None) as ``exc.units_check``; a refusal of the paper's uncertainty gate also A1's three
        rests as ``exc.used``.

    References
    ----------
    wang2022sensors Sec. 2.2 (Eq 15/16), Eq 23, Algorithm A1, Table 1 (ZVD).

    Examples
    --------
    >>> from mtcal.core.profiles import fixed_axis_imu_truth, step_schedule
    >>> prof = step_schedule(np.radians([0.0, 60.0, 120.0, 30.0]), np.radians(60.0), 1.5, 100.0)
    >>> v = np.array([0.6, 0.0, 0.8])
    >>> w, f = fixed_axis_imu_truth(prof.angle_rad.T, prof.rate_rad_s.T, prof.accel_rad_s2.T, [v], [[0.0, 0, 0]],
    ...                             [0.0, 0.0, 9.81], 0.01)
    >>> rng = np.random.default_rng(0)
    >>> res = surface_axis_record(f[0] + 1e-2 * rng.standard_normal(f[0].shape),
    ...                           AxisRecordConfig.cli(RestsConfig.cli_defaults(0.5)), fs_hz=100.0,
    ...                           time_s=prof.time_s, gyro_rad_s=w[0] + 1e-3 * rng.standard_normal(w[0].shape))
    >>> len(res.rests.rests), bool(np.degrees(np.arccos(res.axis.axis @ v)) < 0.5)
    (4, True)
    """
    if not isinstance(config, AxisRecordConfig):
        raise TypeError(f"config must be an AxisRecordConfig, got {type(config).__name__}")
    from mtcal.systems.rests import checked_record, find_rests_trusted

    fs = positive_scalar(fs_hz, "fs_hz")
    paper = config.rests.detector == "paper"
    a, g, dt, t = checked_record(accel_m_s2, 1.0 / fs, None if paper else gyro_rad_s, time_s)
    if paper:
        return _axis_record_paper(a, dt, fs, config)
    rep = find_rests_trusted(a, g, dt, t, config.rests)
    chk = None
    try:
        if g is not None:  # the rests used the gyro: its units and the time base must fit
            chk = plausibility.check_record_units(g, a, dt, t, rep.rests, unit_stated=unit_stated)
        if len(rep.rests) == 0:
            raise ValueError(f"found only 0 rests of >= {rep.min_rest_s:g} s ({rep.levels_text()}); "
                             f"the axis needs rests at three distinct tilts")
        settings = _axis_settings(AxisConfig.cli(rep.accel_noise_m_s2, rep.window_s * fs,
                                                 min_separation_deg=config.min_separation_deg,
                                                 max_axis_error_deg=config.max_axis_error_deg,
                                                 max_elevation_deg=config.max_elevation_deg))
        est = rotation_axis.axis_from_rests(a, list(rep.rests), **settings)
    except ValueError as exc:
        exc.rests, exc.units_check = rep, chk  # the caller's diagnostics show what the refusal saw
        raise
    return SurfaceAxisRecord(rep, est, tuple(rep.rests[m[0]] for m in est.members), chk)


def _axis_record_paper(a: np.ndarray, dt: float, fs: float, config: AxisRecordConfig) -> SurfaceAxisRecord:
    """:func:`surface_axis_record` with the paper's detector, on the checked accelerometer: Table 1 ZVD flags
    (no rest dropped by its listed span: A1 counts rests by its own minimum), Algorithm A1, the
    uncertainty gate on A1's three means."""
    from mtcal.methods.rest_detection import paper_rest_report

    min_rest = float(config.rests.min_rest_s)
    rep = paper_rest_report(a, dt, min_rest_s=min_rest, zvd=ZvdParams())
    try:
        res = rotation_axis.estimate_axis(a, dt, min_rest_s=min_rest, is_static=rep.is_static,
                                          min_separation_deg=config.min_separation_deg,
                                          max_elevation_deg=config.max_elevation_deg)
    except ValueError as exc:
        err = ValueError(f"{exc} [paper ZVD band {rep.band_m_s2[0]:g}-{rep.band_m_s2[1]:g} m/s^2, measured "
                         f"|a| at rest {rep.extra['measured_gravity_m_s2']:.4f} m/s^2; --rest-detector "
                         f"adaptive measures the band from the data]")
        err.rests, err.units_check = rep, None
        raise err from None
    counts = np.array([r.stop - r.start for r in res.rests], float)
    window = rep.window_s * fs
    try:  # axis_uncertainty on A1's means (float (3, 3)) and the noise the ZVD report measured on its blocks
        fit = rotation_axis.gated_plane_fit(res.means, counts, rep.accel_noise_m_s2, window,
                                            np.inf if config.max_axis_error_deg is None
                                            else float(config.max_axis_error_deg), SIGMA_MEAN_FLOOR_M_S2)
    except ValueError as exc:
        exc.rests, exc.units_check, exc.used = rep, None, tuple(res.rests)
        raise
    v, means = res.v, res.means
    n_eff = float(np.min(counts)) / max(1.0, float(window))       # as axis_uncertainty's rest-mean noise
    sig = max(rep.accel_noise_m_s2 / np.sqrt(max(n_eff, 1.0)), SIGMA_MEAN_FLOOR_M_S2)
    est = AxisEstimate(v, float(fit.sigma_rad), float(np.mean(rotation_axis.axis_elevation(v, means))),
                       means, ((0,), (1,), (2,)), means, angles_about_axis(v, means[0], means), float(sig), "eq23")
    return SurfaceAxisRecord(rep, est, tuple(res.rests), None)


def rest_ekf_params(gyro_rad_s, accel_m_s2, init: slice) -> RamsEkfParams:
    """RAMS EKF noise measured on a rest: σθ, σa,static = mean per-axis std there (floors 1e-5, 1e-4).

    σb = 1e-4 rad/s², σa,moving = 5 m/s² (lever arm and hand-held moves), P0 = 1e-8
    for angle and bias (the rest fixes both). mtcal choices (the paper gives no values).

    Parameters
    ----------
    gyro_rad_s, accel_m_s2 : array_like (N, 3)
    init : slice
        The rest.

    Returns
    -------
    RamsEkfParams

    Examples
    --------
    >>> import numpy as np
    >>> p = rest_ekf_params(np.zeros((10, 3)), np.tile([0, 0, 9.8], (10, 1)), slice(0, 10))
    >>> p.sigma_theta_rad_s, p.sigma_a_static_m_s2
    (1e-05, 0.0001)
    """
    sig_a = max(float(np.std(np.asarray(accel_m_s2)[init], axis=0).mean()), 1e-4)
    sig_w = max(float(np.std(np.asarray(gyro_rad_s)[init], axis=0).mean()), 1e-5)
    return RamsEkfParams(sigma_theta_rad_s=sig_w, sigma_b_rad_s2=1e-4, sigma_a_static_m_s2=sig_a,
                         sigma_a_moving_m_s2=5.0, p0_theta_rad2=1e-8, p0_bias_rad2_s2=1e-8)


@dataclass(frozen=True)
class SurfaceAngleConfig:
    """Resolved settings of :func:`surface_angle`, checked once when made.

    Attributes
    ----------
    params : RamsEkfParams or None
        EKF noise; None: measured on the initial rest (:func:`rest_ekf_params`, one record only).
    max_elevation_deg : float
        Refuse an axis steeper than this (deg): a rotation about the vertical does
        not change the accelerometer reading.
    check_units : bool
        One record: check the gyro's units/time base against the accelerometer's tilt
        change (:func:`~mtcal.systems.plausibility.check_units`: rest pairs, else the tilt rate).
    max_axis_mismatch_deg : float or None
        One record: once moves add up to 20°, refuse when the gyro turns about an axis
        further than this from ``axis`` (deg).
    gyro_noise_rad_s : float
        Gyro noise per sample (rad/s, ≥ 0) for the moving-sample threshold of that check.
    unit_stated : str or None
        Where the gyro unit was stated (:func:`~mtcal.systems.plausibility.check_units`: a stated unit
        that no check can decide is accepted with a ``warning`` in ``unit_check``).

    Examples
    --------
    >>> SurfaceAngleConfig().check_units, SurfaceAngleConfig.cli(gyro_noise_rad_s=1e-3).check_units
    (False, True)
    >>> SurfaceAngleConfig(max_elevation_deg=0.0)
    Traceback (most recent call last):
    ...
    ValueError: max_elevation_deg must be > 0, got 0.0
    """

    params: RamsEkfParams | None = None
    max_elevation_deg: float = rotation_axis.DEFAULT_MAX_ELEVATION_DEG
    check_units: bool = False
    max_axis_mismatch_deg: float | None = None
    gyro_noise_rad_s: float = 0.0
    unit_stated: str | None = None

    def __post_init__(self) -> None:
        if self.params is not None and not isinstance(self.params, RamsEkfParams):
            raise TypeError(f"params must be a RamsEkfParams or None, got {type(self.params).__name__}")
        positive_scalar(self.max_elevation_deg, "max_elevation_deg")
        _limit(self.max_axis_mismatch_deg, "max_axis_mismatch_deg")
        positive_scalar(self.gyro_noise_rad_s, "gyro_noise_rad_s", allow_zero=True)
        if not isinstance(self.check_units, bool):
            raise TypeError(f"check_units must be a bool, got {type(self.check_units).__name__}")

    @classmethod
    def paper(cls, params: RamsEkfParams) -> "SurfaceAngleConfig":
        """The study's Monte Carlo: the EKF noise of the simulated IMU, no record checks (a batch)."""
        return cls(params=params)

    @classmethod
    def cli(cls, *, max_elevation_deg: float = 85.0, max_axis_mismatch_deg: float = 10.0,
            gyro_noise_rad_s: float = 0.0, unit_stated: str | None = None) -> "SurfaceAngleConfig":
        """``mtcal angle``: noise measured on the initial rest, units and gyro axis checked (defaults = the
        command's)."""
        return cls(None, max_elevation_deg, True, max_axis_mismatch_deg, gyro_noise_rad_s, unit_stated)

    @classmethod
    def sweep_cell(cls, *, gyro_noise_rad_s_rt_hz: float, accel_noise_m_s2_rt_hz: float, dt_s: float,
                   gain_m_s2: float) -> "SurfaceAngleConfig":
        """A sweep cell (the filter registry's ``rams_ekf`` entry): σθ = gyro noise per sample,
        σa,static = accelerometer noise per sample (floors 1e-5 rad/s and 1e-2 m/s²), σa,moving = ``gain_m_s2``."""
        return cls(RamsEkfParams(sigma_theta_rad_s=max(gyro_noise_rad_s_rt_hz / np.sqrt(dt_s), 1e-5),
                                 sigma_a_static_m_s2=max(accel_noise_m_s2_rt_hz / np.sqrt(dt_s), 1e-2),
                                 sigma_a_moving_m_s2=gain_m_s2))


@dataclass(frozen=True)
class SurfaceAngle:
    """Result of :func:`surface_angle`; arrays have a leading trial axis T only for batched input.

    Attributes
    ----------
    angle_rad : ndarray (N,) or (T, N)
        Angle about v (rad, continuous), 0 at ``init.start``; NaN before it.
    start : int
        First filtered sample (``init.start``).
    accel0_m_s2, bias0_rad_s : ndarray (3,) or (T, 3)
        ā0 and the initial gyro bias (means over ``init``).
    elevation_rad : float or ndarray (T,)
        Axis elevation above the horizontal at ā0 (rad).
    params : RamsEkfParams
    dt_s : float
        Filter step (s).
    clipped : ndarray (N,) or (T, N) of bool
        Gyro samples on a full-scale plateau.
    clip_level_rad_s : float or ndarray (T,)
        Clipping level (rad/s, 0 if none).
    restarts : tuple
        Sample indices where the EKF restarted (per trial for batched input).
    unit_check : dict or None
        :func:`mtcal.systems.plausibility.check_units` result (``check_units``).
    gyro_axis : ndarray (3,) or None
        The gyro's principal rotation axis when it was checked against ``axis``.
    """

    angle_rad: np.ndarray
    start: int
    accel0_m_s2: np.ndarray
    bias0_rad_s: np.ndarray
    elevation_rad: float | np.ndarray
    params: RamsEkfParams
    dt_s: float
    clipped: np.ndarray
    clip_level_rad_s: float | np.ndarray
    restarts: tuple
    unit_check: dict | None
    gyro_axis: np.ndarray | None


def _restart_cuts(clipped: np.ndarray, rests, n: int) -> list[int]:
    """Segment bounds: 0, each rest start (after the first) preceded by clipping since the last, n."""
    cuts = [0]
    if clipped.any():
        last = 0
        for r in rests[1:]:
            if clipped[last:r.start].any():
                cuts.append(r.start)
            last = r.start
    cuts.append(n)
    return cuts


def _checked_axis(axis) -> np.ndarray:
    v = as_float_array(axis, "axis", ndim=(1, 2), last_dim=3)
    if np.any(np.abs(np.linalg.norm(v, axis=-1) - 1.0) > 1e-6):
        raise ValueError(f"axis must be a unit vector, got |axis| = {np.linalg.norm(v, axis=-1).max():.6g}")
    return v


def _checked_record(gyro_rad_s, accel_m_s2, ndim) -> tuple[np.ndarray, np.ndarray]:
    g = as_float_array(gyro_rad_s, "gyro_rad_s", ndim=ndim, last_dim=3, copy=False)
    a = as_float_array(accel_m_s2, "accel_m_s2", ndim=ndim, last_dim=3, copy=False)
    if g.shape != a.shape:
        raise ValueError(f"gyro_rad_s and accel_m_s2 must have the same shape, got {g.shape} and {a.shape}")
    return g, a


def surface_angle(gyro_rad_s, accel_m_s2, axis, config: SurfaceAngleConfig | None = None, *, is_static,
                  init: slice, dt_s=None, time_s=None, rests=()) -> SurfaceAngle:
    """Angle about a known hinge axis: ZVD-switched RAMS EKF from a rest (wang2022sensors Sec. 2.2–3.3).

    ā0 and the initial bias are the means over ``init`` (Sec. 2.2); the EKF
    (Eq 24–33) runs from ``init.start`` with θ = 0 there, V switched by
    ``is_static`` (Sec. 3.3.3). Gyro samples on a full-scale plateau
    (:func:`~mtcal.systems.plausibility.clipped_samples`) restart the EKF at the
    next rest in ``rests`` with ``p0_θ = (30°)²`` (angle and bias carried over),
    so that rest's accelerometer reading sets the angle again. Without clipping
    this is one EKF run; a batch (T, N, 3) runs all trials in one call. Inputs are
    checked here once; the filter below runs on the checked arrays. A single record
    without ``config.check_units`` is still checked against the accelerometer's tilt
    rate (:func:`mtcal.methods.tilt_rate.check_tilt_rate_scale`, a gyro off by > 5× is refused).

    Parameters
    ----------
    gyro_rad_s, accel_m_s2 : array_like (N, 3) or (T, N, 3)
        Gyro (rad/s) and accelerometer (m/s²).
    axis : array_like (3,) or (T, 3)
        Unit axis v (sensor frame).
    config : SurfaceAngleConfig, optional
        Resolved settings (default ``SurfaceAngleConfig()``).
    is_static : array_like of bool (N,) or (T, N)
        ZVD flags.
    init : slice
        The initial rest (ā0, bias, and angle 0 at its start).
    dt_s : float, optional
        Uniform step (s); or ``time_s`` (N,), see :func:`~mtcal.systems.plausibility.time_base`
        (a jittered time column weights the gyro by each sample's interval).
    rests : sequence of slice
        Rests (time order) where the EKF may restart after clipping.

    Returns
    -------
    SurfaceAngle

    Raises
    ------
    ValueError
        Axis nearly along gravity; empty ``init``; checks failing (messages name
        the measured numbers and the likely fix).

    References
    ----------
    wang2022sensors Sec. 2.2 (ā0), Eq 24–33 (EKF), Sec. 3.3.3 (covariance switching).

    Examples
    --------
    >>> import numpy as np
    >>> from mtcal.core.profiles import fixed_axis_imu_truth, step_schedule
    >>> prof = step_schedule(np.radians([0.0, 40.0]), np.radians(40.0), 1.0, 100.0)
    >>> v = np.array([0.6, 0.0, 0.8]); n = prof.time_s.size
    >>> w, f = fixed_axis_imu_truth(prof.angle_rad.T, prof.rate_rad_s.T, prof.accel_rad_s2.T, [v], [[0.0, 0, 0]],
    ...                             [0.0, 0.0, 9.81], 0.01)
    >>> res = surface_angle(w[0], f[0], v, SurfaceAngleConfig(RamsEkfParams()), is_static=prof.is_static,
    ...                     init=slice(0, 90), dt_s=0.01)
    >>> round(float(np.degrees(res.angle_rad[-1])), 3)
    40.0
    """
    cfg = SurfaceAngleConfig() if config is None else config
    if not isinstance(cfg, SurfaceAngleConfig):
        raise TypeError(f"config must be a SurfaceAngleConfig, got {type(cfg).__name__}")
    g, a = _checked_record(gyro_rad_s, accel_m_s2, (2, 3))
    batch = a.ndim == 3
    n = a.shape[-2]
    dt, weights = plausibility.time_base(n, dt_s=dt_s, time_s=time_s)
    v = _checked_axis(axis)
    static = np.asarray(is_static)
    if static.dtype != bool or static.shape[-1] != n:
        raise ValueError(f"is_static must be boolean with {n} samples, got {static.dtype} {static.shape}")
    if not isinstance(init, slice) or not 0 <= (init.start or 0) < (init.stop or 0) <= n:
        raise ValueError(f"init must be a non-empty slice of the {n} samples, got {init!r}")
    if (cfg.check_units or cfg.max_axis_mismatch_deg is not None) and batch:
        raise ValueError("check_units and max_axis_mismatch_deg check one record, not a batch")
    if cfg.params is None and batch:
        raise ValueError("params must be given for a batch")
    return _surface_angle_steps(g, a, v, static, init, dt, weights, time_s, list(rests), cfg)


def _surface_angle_steps(g, a, v, static, init: slice, dt: float, weights, time_s, rests: list,
                         cfg: SurfaceAngleConfig) -> SurfaceAngle:
    """The steps of :func:`surface_angle` (ā0 and bias, clipping, the axis gate, the units or tilt-rate
    check, the EKF with its restarts), shared by its two edges (:func:`surface_angle`,
    :func:`surface_angle_record`), which check the record first: (N, 3) or (T, N, 3) finite float64, bool
    flags, a unit axis, a non-empty ``init``, ``dt`` and gyro ``weights`` from
    :func:`~mtcal.systems.plausibility.time_base`."""
    batch = a.ndim == 3
    n = a.shape[-2]
    gyro_f = g if weights is None else g * weights[:, None]
    k0 = init.start or 0
    a0 = a[..., init, :].mean(axis=-2)
    b0 = g[..., init, :].mean(axis=-2)
    if batch:
        clip = [plausibility.clipped_samples(row) for row in g]
        clipped = np.stack([c[0] for c in clip])
        level = np.array([c[1] for c in clip])
    else:
        clipped, level = plausibility.clipped_samples(g)
    elev = rotation_axis.gated_elevation(v, a0, cfg.max_elevation_deg)
    check, u = None, None
    if cfg.check_units:
        check = plausibility.check_units(gyro_f, a, dt, rests, time_s=time_s, skip=clipped,
                                         unit_stated=cfg.unit_stated)
    elif not batch:  # the gyro's tilt-rate scale (run_rams_ekf's precondition), once for the record
        check_tilt_rate_scale(gyro_f[k0:], a[k0:], dt, excess="warn")
    if cfg.max_axis_mismatch_deg is not None:
        u = _gyro_axis_check(g, static, b0, v, dt, cfg)
    params = rest_ekf_params(g, a, init) if cfg.params is None else cfg.params
    local = [slice(r.start - k0, r.stop - k0) for r in rests]
    angle = np.full(a.shape[:-1], np.nan)
    if not batch:
        cuts = _restart_cuts(clipped[k0:], local, n - k0)
        angle[k0:] = run_rams_ekf_restarts(gyro_f[k0:], a[k0:], static[k0:], cuts, v, a0, b0, dt, params,
                                           CLIPPED_P0_THETA_RAD**2)
        restarts = tuple(c + k0 for c in cuts[1:-1])
    else:
        st = np.broadcast_to(static, a.shape[:-1])
        cuts = [_restart_cuts(c[k0:], local, n - k0) for c in clipped]
        angle[:, k0:] = run_rams_ekf_batch_restarts(gyro_f[:, k0:], a[:, k0:], st[:, k0:], cuts, v, a0, b0,
                                                    dt, params, CLIPPED_P0_THETA_RAD**2)
        restarts = tuple(tuple(x + k0 for x in c[1:-1]) for c in cuts)
    return SurfaceAngle(angle, k0, a0, b0, elev if batch else float(elev), params, dt, clipped,
                        level if batch else float(level), restarts, check, u)


def _gyro_axis_check(g, static, b0, v, dt: float, cfg: SurfaceAngleConfig) -> np.ndarray | None:
    """The gyro's principal rotation axis once the moves add up to :data:`MIN_TURN_FOR_AXIS_CHECK_DEG`;
    refused further than ``cfg.max_axis_mismatch_deg`` from ``v`` (one record)."""
    moving = ~static & (np.linalg.norm(g - b0, axis=1) > max(5 * cfg.gyro_noise_rad_s, np.radians(2.0)))
    turned = float(np.degrees(np.sum(np.linalg.norm(g[moving] - b0, axis=1)) * dt))
    if turned <= MIN_TURN_FOR_AXIS_CHECK_DEG:
        return None
    u, share = plausibility.rotation_axis_from_gyro(g, b0, moving)
    mis = float(np.degrees(np.arccos(min(1.0, abs(float(u @ v))))))
    if mis > cfg.max_axis_mismatch_deg:
        u = u if u[0] >= 0 else -u
        raise ValueError(f"the gyro turns about [{u[0]:.3f}, {u[1]:.3f}, {u[2]:.3f}] "
                         f"({share * 100:.0f} % of the rotation), {mis:.1f} deg from --axis "
                         f"(max {cfg.max_axis_mismatch_deg:g}); pass the right axis (mtcal axis LOG) or "
                         f"check the axes")
    return u


# --------------------------------------------------------------------------- one record (a log): rests → EKF
@dataclass(frozen=True)
class SurfaceRecordConfig:
    """Resolved settings of :func:`surface_angle_record` (``mtcal angle``), checked once when made.

    Attributes
    ----------
    rests : RestsConfig
        How the log's rests are found (the initial rest, the EKF's V switch, the restarts).
    init_s : float
        Initial rest for ā0 and the gyro bias (s, > 0): with the paper's detector the first ``init_s``
        seconds of the log (they must be at rest, Sec. 2.2), else the first ``init_s`` seconds of the
        first rest found.
    max_elevation_deg : float
        Refuse an axis steeper than this (deg), :class:`SurfaceAngleConfig`.
    max_axis_mismatch_deg : float or None
        Refuse a gyro turning about an axis this far from the given one (deg); None: not checked.

    Examples
    --------
    >>> SurfaceRecordConfig(RestsConfig.cli_defaults()).init_s
    1.0
    >>> SurfaceRecordConfig(RestsConfig(), init_s=0.0)
    Traceback (most recent call last):
    ...
    ValueError: init_s must be > 0, got 0.0
    """

    rests: RestsConfig
    init_s: float = 1.0
    max_elevation_deg: float = 85.0
    max_axis_mismatch_deg: float | None = 10.0

    def __post_init__(self) -> None:
        if not isinstance(self.rests, RestsConfig):
            raise TypeError(f"rests must be a RestsConfig, got {type(self.rests).__name__}")
        positive_scalar(self.init_s, "init_s")
        positive_scalar(self.max_elevation_deg, "max_elevation_deg")
        _limit(self.max_axis_mismatch_deg, "max_axis_mismatch_deg")


@dataclass(frozen=True)
class SurfaceRecordAngle:
    """Result of :func:`surface_angle_record`.

    Attributes
    ----------
    rests : mtcal.methods.rest_detection.RestReport
        The log's rests.
    angle : SurfaceAngle
        The EKF angle (NaN before the initial rest), its checks and set-up.
    late : bool
        The log starts moving: the angle is measured from the first rest, not from sample 0.
    rest_accel_angles_rad : ndarray (R,)
        The accelerometer's angle of each rest about the axis from ā0 (rad, Eq 16), on the same turn as the
        EKF's angle there (``+ 2πk``; in (−π, π] where the EKF has no angle).
    rest_ekf_angles_rad : ndarray (R,)
        The EKF's median angle over each rest (rad; NaN for a rest before the initial one).
    rest_mismatch : tuple (int, float) or None
        The rest whose EKF and accelerometer angles differ most and by how much (rad), when that exceeds
        :data:`MAX_REST_ANGLE_MISMATCH_DEG` and the axis is not steep (cos elevation > 0.2): axis or
        accelerometer errors.
    """

    rests: RestReport
    angle: SurfaceAngle
    late: bool
    rest_accel_angles_rad: np.ndarray
    rest_ekf_angles_rad: np.ndarray
    rest_mismatch: tuple | None


def surface_angle_record(gyro_rad_s, accel_m_s2, axis, config: SurfaceRecordConfig, *, fs_hz: float, time_s,
                         unit_stated: str | None = None) -> SurfaceRecordAngle:
    """The surface angle of one recorded log (``mtcal angle``): rests, initial rest, checked EKF.

    The rests (:func:`mtcal.systems.rests.find_rests` with ``config.rests``, at the mean step
    ``1 / fs_hz``) give the EKF's V switch and its restarts; the initial rest (``config.init_s``)
    gives ā0, the gyro bias and angle 0; the gyro's units and time base and its rotation axis are
    checked (:meth:`SurfaceAngleConfig.cli` with the gyro noise the rests measured), then the
    ZVD-switched RAMS EKF runs (:func:`surface_angle`). Each rest's accelerometer angle about the
    axis (Eq 16) is returned on the EKF's turn beside the EKF's median angle there, and the worst
    disagreement above :data:`MAX_REST_ANGLE_MISMATCH_DEG`. Inputs are checked here once.

    Parameters
    ----------
    gyro_rad_s, accel_m_s2 : array_like (N, 3)
        Gyro (rad/s) and accelerometer (m/s²).
    axis : array_like (3,)
        Unit hinge axis v (sensor frame).
    config : SurfaceRecordConfig
    fs_hz : float
        Sample rate of the log (Hz), a rate, not ``dt_s``: the rests run at the mean step ``1 / fs_hz`` and
        the initial rest and the late-start limit are counted in samples of this rate (``init_s · fs_hz``), as
        ``mtcal angle`` always did (``1 / (1 / fs)`` is not ``fs`` for 640 of the integer rates 1–5000 Hz, so
        a count could change at a tie).
    time_s : array_like (N,)
        Sample times (s): the EKF's time base (:func:`~mtcal.systems.plausibility.time_base`).
    unit_stated : str, optional
        Where the gyro unit was stated (a units check that cannot decide then warns).

    Returns
    -------
    SurfaceRecordAngle

    Raises
    ------
    ValueError
        No initial rest (messages name the rest levels), and every refusal of :func:`surface_angle`;
        a refusal after the rests were found carries them as ``exc.rests``.

    References
    ----------
    wang2022sensors Sec. 2.2 (ā0, Eq 16), Sec. 3.1 (ZVD), Eq 24–33 (EKF).

    Examples
    --------
    >>> from mtcal.core.profiles import fixed_axis_imu_truth, step_schedule
    >>> prof = step_schedule(np.radians([0.0, 40.0]), np.radians(40.0), 2.0, 100.0)
    >>> v = np.array([0.6, 0.0, 0.8])
    >>> w, f = fixed_axis_imu_truth(prof.angle_rad.T, prof.rate_rad_s.T, prof.accel_rad_s2.T, [v], [[0.0, 0, 0]],
    ...                             [0.0, 0.0, 9.81], 0.01)
    >>> rng = np.random.default_rng(0)
    >>> res = surface_angle_record(w[0] + 1e-3 * rng.standard_normal(w[0].shape),
    ...                            f[0] + 1e-2 * rng.standard_normal(f[0].shape), v,
    ...                            SurfaceRecordConfig(RestsConfig.cli_defaults()), fs_hz=100.0, time_s=prof.time_s)
    >>> len(res.rests.rests), round(float(np.degrees(res.angle.angle_rad[-1])), 1)
    (2, 40.0)
    """
    if not isinstance(config, SurfaceRecordConfig):
        raise TypeError(f"config must be a SurfaceRecordConfig, got {type(config).__name__}")
    g, a = _checked_record(gyro_rad_s, accel_m_s2, 2)
    fs = positive_scalar(fs_hz, "fs_hz")
    dt, weights = plausibility.time_base(a.shape[0], time_s=time_s)
    rep = find_rests(a, 1.0 / fs, config.rests, gyro_rad_s=g, time_s=time_s)
    try:
        n, init_s = a.shape[0], float(config.init_s)
        if config.rests.detector == "paper":  # the paper's set-up: the first init_s seconds are the rest
            n0 = int(round(init_s * fs))
            if n0 < 1 or n0 >= n:
                raise ValueError(f"--init-s {init_s:g} s must cover at least one sample and leave data")
            if not rep.is_static[min(n0, n - 1) // 2:n0].any():
                raise ValueError(f"the first {init_s:g} s are not at rest by the paper ZVD ({rep.levels_text()}; "
                                 f"measured |a| at rest {rep.extra['measured_gravity_m_s2']:.4f} m/s^2); "
                                 f"--rest-detector adaptive measures the band from the data")
            late, init = False, slice(0, n0)
        else:
            if not rep.rests:
                rej = rep.rejected[0] if rep.rejected else None
                why = ("" if rej is None else f"; {len(rep.rejected)} quiet stretch(es) rejected, the first "
                       f"{time_s[rej.span.start]:.3f}-{time_s[rej.span.stop - 1]:.3f} s: {rej.reason}")
                raise ValueError(f"no rest found: the angle is measured from a rest (reference and gyro bias); "
                                 f"{rep.levels_text()}{why}")
            first = rep.rests[0]
            late = first.start > max(0.25 * fs, rep.window_s * fs)
            n0 = min(int(round(init_s * fs)), first.stop - first.start)
            if n0 < max(3, int(0.1 * fs)):
                raise ValueError(f"initial rest too short: {n0} samples ({n0 / fs:.2f} s), need >= 0.1 s")
            init = slice(first.start, first.start + n0)
        means = np.array([a[r].mean(axis=0) for r in rep.rests]).reshape(-1, 3)
        v = _checked_axis(axis)
        cfg = SurfaceAngleConfig.cli(max_elevation_deg=config.max_elevation_deg,
                                     max_axis_mismatch_deg=config.max_axis_mismatch_deg,
                                     gyro_noise_rad_s=rep.gyro_noise_rad_s, unit_stated=unit_stated)
        res = _surface_angle_steps(g, a, v, rep.is_static, init, dt, weights, time_s, list(rep.rests), cfg)
    except ValueError as exc:
        exc.rests = rep  # the caller's diagnostics show the rests the refusal saw
        raise
    # each rest: the EKF's median angle, the accelerometer's (Eq 16) on the same turn, the worst disagreement
    ekf = np.array([np.nanmedian(res.angle_rad[r]) if np.isfinite(res.angle_rad[r]).any() else np.nan
                    for r in rep.rests])
    accel_rad = angles_about_axis(v, res.accel0_m_s2, means)
    accel_rad = accel_rad + 2.0 * np.pi * np.round((ekf - accel_rad) / (2.0 * np.pi))
    off = np.abs(ekf - accel_rad)
    worst = None
    if np.degrees(np.nanmax(off, initial=0.0)) > MAX_REST_ANGLE_MISMATCH_DEG and np.cos(res.elevation_rad) > 0.2:
        i = int(np.nanargmax(off))
        worst = (i, float(off[i]))
    return SurfaceRecordAngle(rep, res, bool(late), accel_rad, ekf, worst)


# --------------------------------------------------------------------------- batched: ZVD → axis → EKF
@dataclass(frozen=True)
class SurfaceBatchConfig:
    """Resolved settings of :func:`surface_angle_batch`, checked once when made.

    Attributes
    ----------
    zvd : ZvdParams or None
        The paper's ZVD (Table 1, Sec. 3.1); None: the caller's known rest flags are the rest flags.
    axis : AxisConfig or None
        Hinge axis from the first ``axis_rests`` rests (Eq 23); None: the caller gives the axis.
    angle : SurfaceAngleConfig or None
        The EKF (``params`` required); None: no angle (ZVD and axis only).
    ekf_switch : {"zvd", "known"}
        The EKF's V/V_z switch: the rest flags, or the caller's known flags (an oracle, or all-static for
        the "standard EKF").
    axis_rests : int
        How many of the given rests the axis uses (≥ 3).

    Examples
    --------
    >>> from mtcal.filters.rams_ekf import RamsEkfParams
    >>> cfg = SurfaceBatchConfig.paper(ZvdParams(), 0.01, RamsEkfParams())
    >>> cfg.axis.fit, cfg.ekf_switch, cfg.axis_rests
    ('eq23', 'zvd', 3)
    """

    zvd: ZvdParams | None
    axis: AxisConfig | None
    angle: SurfaceAngleConfig | None
    ekf_switch: str = "zvd"
    axis_rests: int = 3

    def __post_init__(self) -> None:
        for name, kind in (("zvd", ZvdParams), ("axis", AxisConfig), ("angle", SurfaceAngleConfig)):
            value = getattr(self, name)
            if value is not None and not isinstance(value, kind):
                raise TypeError(f"{name} must be a {kind.__name__} or None, got {type(value).__name__}")
        if self.ekf_switch not in ("zvd", "known"):
            raise ValueError(f"ekf_switch must be 'zvd' or 'known', got {self.ekf_switch!r}")
        if isinstance(self.axis_rests, bool) or not isinstance(self.axis_rests, int) or self.axis_rests < 3:
            raise ValueError(f"axis_rests must be an integer >= 3, got {self.axis_rests!r}")
        if self.angle is not None:
            if self.angle.params is None:
                raise ValueError("angle.params must be given for a batch")
            if self.angle.check_units or self.angle.max_axis_mismatch_deg is not None:
                raise ValueError("check_units and max_axis_mismatch_deg check one record, not a batch")

    @classmethod
    def paper(cls, zvd: ZvdParams, accel_noise_m_s2: float, params: RamsEkfParams, *,
              ekf_switch: str = "zvd") -> "SurfaceBatchConfig":
        """The study's Monte Carlo (wang2022sensors Algorithm A1 and Sec. 3): Table 1 ZVD, Eq 23 axis on the
        first three rests (:meth:`AxisConfig.paper`), ZVD-switched EKF with the simulated IMU's noise."""
        return cls(zvd, AxisConfig.paper(accel_noise_m_s2), SurfaceAngleConfig.paper(params), ekf_switch)

    @classmethod
    def sweep_cell(cls, *, gyro_noise_rad_s_rt_hz: float, accel_noise_m_s2_rt_hz: float, dt_s: float,
                   gain_m_s2: float) -> "SurfaceBatchConfig":
        """A sweep cell (the filter registry's ``rams_ekf`` entry): the schedule's known rest flags as the rest
        flags and the EKF's switch (no ZVD), the given axis (no estimate), the EKF of
        :meth:`SurfaceAngleConfig.sweep_cell` (noise from the sensors, σa,moving = ``gain_m_s2``)."""
        return cls(None, None, SurfaceAngleConfig.sweep_cell(gyro_noise_rad_s_rt_hz=gyro_noise_rad_s_rt_hz,
                                                              accel_noise_m_s2_rt_hz=accel_noise_m_s2_rt_hz,
                                                              dt_s=dt_s, gain_m_s2=gain_m_s2))


@dataclass(frozen=True)
class SurfaceAngleBatch:
    """Result of :func:`surface_angle_batch` (T trials, N samples).

    Attributes
    ----------
    accel0_m_s2, bias0_rad_s : ndarray (T, 3)
        ā0 and the initial gyro bias (means over the initial rest).
    is_static : ndarray of bool (T, N)
        Rest flags (the ZVD's, or the known ones when ``config.zvd`` is None).
    axis : ndarray (T, 3) or (3,)
        The estimated axes, or the given one.
    angle_rad : ndarray (T, N) or None
        Angle about the axis (rad), 0 at sample 0; None without ``config.angle``.
    """

    accel0_m_s2: np.ndarray
    bias0_rad_s: np.ndarray
    is_static: np.ndarray
    axis: np.ndarray | None
    angle_rad: np.ndarray | None


def rest_masks(is_static, rests) -> list[np.ndarray]:
    """Rest flags restricted to each known rest slice; the whole rest where they flag < 10 % of it
    (:data:`MIN_REST_ZVD_SHARE`): one (T, N) boolean mask per rest.

    Examples
    --------
    >>> import numpy as np
    >>> [m.astype(int).tolist() for m in rest_masks(np.array([[True, False, False, False]]),
    ...                                             [slice(0, 2), slice(2, 4)])]
    [[[1, 0, 0, 0]], [[0, 0, 1, 1]]]
    """
    return zero_velocity.rest_masks(np.asarray(is_static, bool), rests, MIN_REST_ZVD_SHARE)


def surface_angle_batch(gyro_rad_s, accel_m_s2, dt_s: float, config: SurfaceBatchConfig, *, init_samples: int,
                        rests, axis=None, known_static=None) -> SurfaceAngleBatch:
    """The surface-angle procedure on T stacked trials: ZVD → Eq 23 axis → ZVD-switched RAMS EKF.

    ā0 and the initial gyro bias are the means of the first ``init_samples`` samples (Sec. 2.2);
    the ZVD (Table 1, with the gyro condition on the bias-removed gyro when ``zvd.gyro_max_rad_s``
    is set) flags the rests; the axis is Eq 23 on the ZVD-flagged samples of the first
    ``config.axis_rests`` known rests (:func:`rest_masks`, :func:`estimate_surface_axes`) unless
    ``axis`` is given; the EKF (:func:`surface_angle`) runs from sample 0, restarting after clipped
    gyro samples at the next of ``rests``. Inputs are checked here once.

    Parameters
    ----------
    gyro_rad_s, accel_m_s2 : array_like (T, N, 3)
        Gyro (rad/s) and accelerometer (m/s²).
    dt_s : float
        Sample interval (s).
    config : SurfaceBatchConfig
    init_samples : int
        Length of the initial rest (samples, from sample 0).
    rests : sequence of slice
        The known rests (time order) of the schedule.
    axis : array_like (3,) or (T, 3), optional
        The hinge axis (unit); required when ``config.axis`` is None and an angle is asked for.
    known_static : array_like of bool (N,) or (T, N), optional
        The known rest flags: the rest flags when ``config.zvd`` is None, the EKF switch when
        ``config.ekf_switch == "known"``.

    Returns
    -------
    SurfaceAngleBatch

    References
    ----------
    wang2022sensors Sec. 2.2, Sec. 3.1 (ZVD, Table 1), Eq 23 (axis), Algorithm A1, Eq 24–33 (EKF).

    Examples
    --------
    >>> import numpy as np
    >>> from mtcal.core.profiles import fixed_axis_imu_truth, step_schedule
    >>> from mtcal.filters.rams_ekf import RamsEkfParams
    >>> prof = step_schedule(np.radians([0.0, 90.0, 180.0, 40.0]), np.radians(90.0), 1.0, 100.0)
    >>> v = np.array([0.6, 0.0, 0.8])
    >>> w, f = fixed_axis_imu_truth(prof.angle_rad.T, prof.rate_rad_s.T, prof.accel_rad_s2.T, [v], [[0.0, 0, 0]],
    ...                             [0.0, 0.0, 9.81], 0.01)
    >>> cfg = SurfaceBatchConfig(None, AxisConfig.paper(0.01), SurfaceAngleConfig(RamsEkfParams()))
    >>> res = surface_angle_batch(w, f, 0.01, cfg, init_samples=90, rests=prof.hold_slices(),
    ...                           known_static=prof.is_static)
    >>> (np.round(res.axis[0], 6) + 0.0).tolist(), round(float(np.degrees(res.angle_rad[0, -1])), 3)
    ([0.6, 0.0, 0.8], 40.0)
    """
    if not isinstance(config, SurfaceBatchConfig):
        raise TypeError(f"config must be a SurfaceBatchConfig, got {type(config).__name__}")
    settings = None if config.axis is None else _axis_settings(config.axis)  # the config was checked when made
    g, a = _checked_record(gyro_rad_s, accel_m_s2, 3)
    t_n, n = a.shape[:2]
    dt = positive_scalar(dt_s, "dt_s")
    if config.zvd is not None:  # the ZVD's own edge (mtcal.methods.zero_velocity.detect_static), checked here once
        sample_interval(dt_s)
        check_accel_units(a)
    if isinstance(init_samples, bool) or not isinstance(init_samples, (int, np.integer)) \
            or not 1 <= init_samples <= n:
        raise ValueError(f"init_samples must be an integer in [1, {n}], got {init_samples!r}")
    rests = list(rests)
    if not all(isinstance(r, slice) and 0 <= (r.start or 0) < (r.stop or 0) <= n for r in rests):
        raise ValueError(f"rests must be non-empty slices of the {n} samples, got {rests!r}")
    known = None
    if known_static is not None:
        known = np.asarray(known_static)
        if known.dtype != bool or known.shape[-1] != n:
            raise ValueError(f"known_static must be boolean with {n} samples, got {known.dtype} {known.shape}")
        known = np.broadcast_to(known, (t_n, n))
    if known is None and (config.zvd is None or (config.angle is not None and config.ekf_switch == "known")):
        raise ValueError("known_static must be given when config.zvd is None or ekf_switch is 'known'")
    v = None if axis is None else _checked_axis(axis)
    if v is None and config.axis is None and config.angle is not None:
        raise ValueError("give axis, or config.axis to estimate it")
    if v is None and config.axis is not None and len(rests) < config.axis_rests:
        raise ValueError(f"the axis needs {config.axis_rests} rests, got {len(rests)}")
    a0 = a[:, :init_samples].mean(axis=-2)
    b0 = g[:, :init_samples].mean(axis=-2)
    cuts = None
    if config.angle is not None:  # the EKF restarts at the next rest after clipped gyro samples
        cuts = [_restart_cuts(plausibility.clipped_samples(row)[0], rests, n) for row in g]
    # then one chain down: the ZVD, the Eq 23 axes (methods), the axis gate, the EKF (filter)
    if config.zvd is None:
        flags = known
    else:
        with_gyro = config.zvd.gyro_max_rad_s is not None  # the gyro condition on ω − b0
        flags = zero_velocity.detect_static(a, dt, config.zvd, g if with_gyro else None,
                                            gyro_offset_rad_s=b0 if with_gyro else None)
    if v is None and settings is not None:
        masks = zero_velocity.rest_masks(flags, rests[:config.axis_rests], MIN_REST_ZVD_SHARE)
        v = rotation_axis.axes_from_rests(a, masks, **settings)
    angle = None
    if config.angle is not None:
        rotation_axis.gated_elevation(v, a0, config.angle.max_elevation_deg)
        switch = np.broadcast_to(flags if config.ekf_switch == "zvd" else known, a.shape[:2])
        angle = run_rams_ekf_batch_restarts(g, a, switch, cuts, v, a0, b0, dt, config.angle.params,
                                            CLIPPED_P0_THETA_RAD**2)
    return SurfaceAngleBatch(a0, b0, flags, v, angle)


def _registered_rams_ekf(w, a, dt, gain, ctx: AxisContext):
    """The filter registry's ``rams_ekf`` runner (declared in :data:`mtcal.filters.registry.BUILTIN_FILTERS`, imported
    on its first call): the batched procedure :func:`surface_angle_batch` (the study's) with the sweep cell's config
    (:meth:`SurfaceBatchConfig.sweep_cell`: the known rest flags, the given axis, noise from the sensors,
    σa,moving = ``gain`` m/s²), ā0 and the gyro bias from ``ctx.init`` (default: the first 0.5 s), restarted after
    clipped gyro samples at the next of ``ctx.rests``.

    Raises
    ------
    ValueError
        ``ctx.init`` does not start at sample 0 (the batched procedure's initial rest).
    """
    config = SurfaceBatchConfig.sweep_cell(gyro_noise_rad_s_rt_hz=ctx.gyro_noise_rad_s_rt_hz,
                                           accel_noise_m_s2_rt_hz=ctx.accel_noise_m_s2_rt_hz, dt_s=dt, gain_m_s2=gain)
    init = ctx.init if ctx.init is not None else slice(0, max(1, int(round(0.5 / dt))))
    if (init.start or 0) != 0:
        raise ValueError(f"the rams_ekf entry initialises from a rest at sample 0, got init {init!r}")
    return surface_angle_batch(w, a, dt, config, init_samples=init.stop, rests=ctx.rests, axis=ctx.axis_s,
                               known_static=ctx.is_static).angle_rad
