"""Rests of a recorded log: the static intervals and the levels the detector measured.

The one procedure behind ``mtcal rests`` and the rest detection of every ``mtcal`` command that
reads raw data (``attitude``, ``apply``, ``calibrate``, ``axis``, ``angle``), and of the real-data
study's ``qncf_cli`` filter (through :mod:`mtcal.systems.attitude`): one of three detectors
(:data:`DETECTORS`) set by one frozen :class:`RestsConfig`, then rests listed shorter than the
stated minimum moved to the rejected list (:func:`drop_short_rests`). :func:`rests_table` gives the
per-rest levels ``mtcal rests --out`` writes. The arrays and the configuration are checked once, here.

References
----------
Wang Y. et al., "A movable surface angle measurement method based on MEMS IMU", Sensors 2022
(wang2022sensors), Table 1: the paper's ZVD band (``detector="paper"``).
Skog I. et al., "Zero-velocity detection — an algorithm evaluation", IEEE TBME 57 (2010): the SHOE
statistic (``detector="shoe"``).
"""

from __future__ import annotations

import dataclasses
import math
from typing import TYPE_CHECKING

import numpy as np

from mtcal.core.validate import as_float_array, check_accel_units, sample_interval

if TYPE_CHECKING:  # imported when a procedure runs (``mtcal --help`` stays light)
    from mtcal.methods import rest_detection

__all__ = ["DETECTORS", "RestsConfig", "find_rests", "find_rests_trusted", "checked_record", "drop_short_rests",
           "rests_table", "default_rests", "no_rests_evidence", "rests_record",
           "MAX_ACCEL_BAND_M_S2", "MAX_GYRO_THRESHOLD_RAD_S"]

#: Rest detectors: measured levels (default), the paper's fixed band, SHOE quasi-static stance phases.
DETECTORS = ("adaptive", "paper", "shoe")


#: Largest half-width of the |a| rest band (m/s^2; half of g: wider, any motion passes the gate).
MAX_ACCEL_BAND_M_S2 = 5.0
#: Largest gyro rest threshold / SHOE quasi-static level (rad/s; 180 deg/s: a faster rate is no rest).
MAX_GYRO_THRESHOLD_RAD_S = float(np.pi)


def _optional_positive(value, name: str) -> None:
    if value is not None and not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
        raise ValueError(f"{name} must be None or a finite number > 0, got {value!r}")


@dataclasses.dataclass(frozen=True)
class RestsConfig:
    """How rests are found (:func:`find_rests`); checked when built.

    Attributes
    ----------
    detector : {"adaptive", "paper", "shoe"}
        :func:`mtcal.methods.rest_detection.detect_rests` (levels measured from the data),
        :func:`~mtcal.methods.rest_detection.paper_rest_report` (wang2022sensors Table 1 band) or
        :func:`~mtcal.methods.rest_detection.detect_rests_shoe` (needs the gyro).
    min_rest_s : float
        Shortest rest (s), by its listed span ``t[stop-1] − t[start]``.
    noise_factor : float
        Thresholds = ``noise_factor`` × measured noise (adaptive, shoe; also the quiet core of the
        first rest, :func:`mtcal.systems.attitude.qncf_log_setup`).
    gravity_m_s2, accel_band_m_s2 : float or None
        ``|a|`` at rest and the half-width of its band (m/s², at most :data:`MAX_ACCEL_BAND_M_S2`); None: measured.
    gyro_threshold_rad_s : float or None
        Max ``|ω − bias|`` at rest (rad/s; adaptive), or the quasi-static rate level (shoe), at most
        :data:`MAX_GYRO_THRESHOLD_RAD_S`; None: measured.
    shoe_threshold : float or None
        SHOE threshold γ (dimensionless); None: measured or from ``gyro_threshold_rad_s``.
    use_gyro : bool
        Use the gyro when given (False: accelerometer only).

    Examples
    --------
    >>> RestsConfig.cli_defaults().min_rest_s, RestsConfig().detector
    (0.2, 'adaptive')
    """

    detector: str = "adaptive"
    min_rest_s: float = 0.2
    noise_factor: float = 5.0
    gravity_m_s2: float | None = None
    accel_band_m_s2: float | None = None
    gyro_threshold_rad_s: float | None = None
    shoe_threshold: float | None = None
    use_gyro: bool = True

    def __post_init__(self):
        if self.detector not in DETECTORS:
            raise ValueError(f"detector must be one of {DETECTORS}, got {self.detector!r}")
        for name in ("min_rest_s", "noise_factor"):
            if getattr(self, name) is None:
                raise ValueError(f"{name} must be a finite number > 0, got None")
            _optional_positive(getattr(self, name), name)
        for name in ("gravity_m_s2", "accel_band_m_s2", "gyro_threshold_rad_s", "shoe_threshold"):
            _optional_positive(getattr(self, name), name)
        if self.accel_band_m_s2 is not None and self.accel_band_m_s2 > MAX_ACCEL_BAND_M_S2:
            raise ValueError(f"accel_band_m_s2 must be at most {MAX_ACCEL_BAND_M_S2:g} m/s^2 (a wider |a| band "
                             f"accepts any motion as rest), got {self.accel_band_m_s2:g}")
        if self.gyro_threshold_rad_s is not None and self.gyro_threshold_rad_s > MAX_GYRO_THRESHOLD_RAD_S:
            raise ValueError(f"gyro_threshold_rad_s must be at most {np.degrees(MAX_GYRO_THRESHOLD_RAD_S):g} deg/s "
                             f"(a faster rate is no rest), got {np.degrees(self.gyro_threshold_rad_s):.4g} deg/s")
        if self.shoe_threshold is not None and self.detector != "shoe":
            raise ValueError("shoe_threshold needs detector 'shoe'")
        self.detector_params()                       # the detector's own checks (e.g. gravity's range), once, here

    def detector_params(self):
        """The parameters of the adaptive or SHOE detector this config states (None for the paper's fixed band)."""
        from mtcal.methods import rest_detection

        if self.detector == "shoe":
            return rest_detection.ShoeParams(min_rest_s=self.min_rest_s, noise_factor=self.noise_factor,
                                             threshold=self.shoe_threshold, rate_level_rad_s=self.gyro_threshold_rad_s,
                                             gravity_m_s2=self.gravity_m_s2)
        if self.detector == "adaptive":
            return rest_detection.RestDetectorParams(min_rest_s=self.min_rest_s, noise_factor=self.noise_factor,
                                                     gravity_m_s2=self.gravity_m_s2,
                                                     accel_band_m_s2=self.accel_band_m_s2,
                                                     gyro_level_max_rad_s=self.gyro_threshold_rad_s)
        return None

    @classmethod
    def cli_defaults(cls, min_rest_s: float = 0.2) -> "RestsConfig":
        """``mtcal rests``/``attitude`` at their defaults: adaptive detector, rests ≥ ``min_rest_s``, 5 × noise."""
        return cls(min_rest_s=min_rest_s)

    @classmethod
    def paper(cls, min_rest_s: float = 0.2) -> "RestsConfig":
        """wang2022sensors' fixed ZVD band (Table 1, 9.76–9.84 m/s²) with the gyro's stillness check."""
        return cls(detector="paper", min_rest_s=min_rest_s)


def drop_short_rests(rep: rest_detection.RestReport, time_s) -> rest_detection.RestReport:
    """Move rests listed shorter than ``rep.min_rest_s`` (by their span ``t[stop-1] − t[start]``) to ``rejected``.

    Examples
    --------
    >>> import numpy as np
    >>> acc = np.tile([0.0, 0.0, 9.81], (50, 1))
    >>> from mtcal.methods import rest_detection
    >>> rep = rest_detection.detect_rests(acc, 0.01, params=rest_detection.RestDetectorParams(min_rest_s=0.2))
    >>> len(drop_short_rests(rep, np.arange(50) * 0.01).rests)
    1
    """
    from mtcal.methods import rest_detection

    t = np.asarray(time_s)
    short = [r for r in rep.rests if t[r.stop - 1] - t[r.start] < rep.min_rest_s]
    if not short:
        return rep
    flags = rep.is_static.copy()
    rejected = list(rep.rejected)
    for r in short:
        flags[r] = False
        lo, hi = rest_detection.format_ordered(t[r.stop - 1] - t[r.start], rep.min_rest_s, 3)
        rejected.append(rest_detection.RejectedRest(r, f"too short: {lo} s < {hi} s (--min-rest-s)"))
    rejected.sort(key=lambda x: x.span.start)
    return dataclasses.replace(rep, rests=[r for r in rep.rests if r not in short], rejected=rejected,
                               is_static=flags, n_short=rep.n_short + len(short))


def checked_record(accel_m_s2, dt_s, gyro_rad_s=None, time_s=None):
    """A record checked at a system's edge: ``(accel, gyro or None, dt, time_s)``.

    ``accel_m_s2`` and ``gyro_rad_s`` finite float (N, 3) of equal shape, the accelerometer in m/s²
    (:func:`mtcal.core.validate.check_accel_units`); ``dt_s`` a sample interval (s); ``time_s`` N times
    (default ``k · dt_s``). One-line ``ValueError`` naming the array otherwise.

    Examples
    --------
    >>> a, g, dt, t = checked_record(np.tile([0.0, 0.0, 9.81], (3, 1)), 0.5)
    >>> g is None, dt, t.tolist()
    (True, 0.5, [0.0, 0.5, 1.0])
    """
    a = as_float_array(accel_m_s2, "accel_m_s2", ndim=2, last_dim=3, copy=False)
    check_accel_units(a)
    g = None if gyro_rad_s is None else as_float_array(gyro_rad_s, "gyro_rad_s", ndim=2, last_dim=3, copy=False)
    if g is not None and g.shape != a.shape:
        raise ValueError(f"gyro_rad_s and accel_m_s2 must have the same shape, got {g.shape} and {a.shape}")
    dt = sample_interval(dt_s)
    if time_s is None:
        t = np.arange(a.shape[0]) * dt
    else:
        t = as_float_array(time_s, "time_s", ndim=1, copy=False)
        if t.size != a.shape[0]:
            raise ValueError(f"time_s must have {a.shape[0]} samples, got {t.size}")
    return a, g, dt, t


def find_rests(accel_m_s2, dt_s: float, config: RestsConfig, *, gyro_rad_s=None,
               time_s=None) -> rest_detection.RestReport:
    """Rests of one record by the configured detector, rests shorter than ``config.min_rest_s`` rejected.

    Parameters
    ----------
    accel_m_s2 : array_like, shape (N, 3)
        Specific force (m/s²).
    dt_s : float
        Mean sample interval (s).
    config : RestsConfig
    gyro_rad_s : array_like, shape (N, 3), optional
        Angular rate (rad/s); ignored when ``config.use_gyro`` is False; required by ``"shoe"``.
    time_s : array_like, shape (N,), optional
        Sample times (s) for the listed-span rule; default ``k · dt_s``.

    Returns
    -------
    mtcal.methods.rest_detection.RestReport

    Raises
    ------
    ValueError
        Bad shapes or ``dt_s``; ``"shoe"`` without a gyro.

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> acc = np.array([0.0, 0.0, 9.81]) + 0.02 * rng.standard_normal((1000, 3))
    >>> gyr = 0.002 * rng.standard_normal((1000, 3))
    >>> len(find_rests(acc, 0.01, RestsConfig.cli_defaults(), gyro_rad_s=gyr).rests)
    1
    """
    if not isinstance(config, RestsConfig):
        raise TypeError(f"config must be a RestsConfig, got {type(config).__name__}")
    a, g, dt, t = checked_record(accel_m_s2, dt_s, gyro_rad_s, time_s)
    return find_rests_trusted(a, g, dt, t, config)


def rests_record(accel_m_s2, dt_s: float, config: RestsConfig, *, gyro_rad_s=None, time_s=None,
                 unit_stated: str | None = None) -> tuple[rest_detection.RestReport, dict | None]:
    """The rests of one recorded log (``mtcal rests``) and, when they used the gyro, its units check.

    :func:`find_rests`, then the gyro's units and time base checked against the accelerometer as
    ``mtcal attitude``/``axis`` check them (:func:`mtcal.systems.plausibility.check_record_units`: rest pairs,
    tilt rate, gravity tracking; a stated unit that no check decides is used with a warning). Returns
    ``(report, units check or None)``; the check is None without a gyro or with ``config.use_gyro`` False.

    Raises
    ------
    ValueError
        Bad arrays; a gyro the units check refuses (with the rests found as ``exc.rests``).

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> acc = np.array([0.0, 0.0, 9.81]) + 0.02 * rng.standard_normal((1000, 3))
    >>> rep, chk = rests_record(acc, 0.01, RestsConfig(), gyro_rad_s=0.002 * rng.standard_normal((1000, 3)))
    >>> len(rep.rests), chk["method"]
    (1, 'no rotation')
    """
    from mtcal.systems import plausibility

    if not isinstance(config, RestsConfig):
        raise TypeError(f"config must be a RestsConfig, got {type(config).__name__}")
    a, g, dt, t = checked_record(accel_m_s2, dt_s, gyro_rad_s if config.use_gyro else None, time_s)
    rep = find_rests_trusted(a, g, dt, t, config)
    if g is None:
        return rep, None
    try:
        return rep, plausibility.check_record_units(g, a, dt, t, rep.rests, unit_stated=unit_stated)
    except ValueError as exc:
        exc.rests = rep
        raise


def find_rests_trusted(a: np.ndarray, g: np.ndarray | None, dt: float, t: np.ndarray,
                       config: RestsConfig) -> rest_detection.RestReport:
    """:func:`find_rests` on a record a system checked at its edge (:func:`checked_record`): the same report.

    Preconditions (not checked again): ``(a, g, dt, t)`` as :func:`checked_record` returns them; ``config`` a
    :class:`RestsConfig`.
    """
    from mtcal.methods import rest_detection
    from mtcal.methods.zero_velocity import ZvdParams

    gyro = g if config.use_gyro else None
    params = config.detector_params()          # the config's detector, resolved before the detection runs
    if config.detector == "paper":
        rep = rest_detection.paper_rest_report(a, dt, gyro_rad_s=gyro, min_rest_s=float(config.min_rest_s),
                                               zvd=ZvdParams())
    elif config.detector == "shoe":
        if gyro is None:
            raise ValueError("detector 'shoe' needs gyro_rad_s")
        rep = rest_detection.detect_rests_shoe(a, dt, gyro_rad_s=gyro, params=params)
    else:
        rep = rest_detection.detect_rests(a, dt, gyro_rad_s=gyro, params=params)
    return drop_short_rests(rep, t)


def default_rests(accel_m_s2, dt_s: float, gyro_rad_s, *, min_rest_s: float = 0.2) -> rest_detection.RestReport:
    """Rests as ``mtcal attitude`` finds them at its defaults (:meth:`RestsConfig.cli_defaults`), time ``k · dt_s``."""
    return find_rests(accel_m_s2, dt_s, RestsConfig.cli_defaults(min_rest_s), gyro_rad_s=gyro_rad_s)


def rests_table(time_s, accel_m_s2, report: rest_detection.RestReport, *, gyro_rad_s=None) -> dict:
    """Per-rest levels, one value per rest: the columns of ``mtcal rests --out``.

    ``rest, start_s, stop_s, duration_s`` (s; ``stop_s`` the time of the rest's last sample),
    ``accel_norm_m_s2``, ``tilt_deg`` (from the sensor z axis), ``accel_{x,y,z}_m_s2`` (mean specific
    force) and, with ``gyro_rad_s``, ``gyro_{x,y,z}_deg_s`` (mean rate, deg/s — the display edge).

    Examples
    --------
    >>> import numpy as np
    >>> acc = np.tile([0.0, 0.0, 9.81], (50, 1))
    >>> cols = rests_table(np.arange(50) * 0.01, acc, find_rests(acc, 0.01, RestsConfig()))
    >>> float(cols["duration_s"][0]), float(cols["tilt_deg"][0])
    (0.49, 0.0)
    """
    t, a = time_s, accel_m_s2
    means = np.array([a[r].mean(axis=0) for r in report.rests]).reshape(-1, 3)
    cols = {"rest": np.arange(len(report.rests)),
            "start_s": np.array([t[r.start] for r in report.rests]),
            "stop_s": np.array([t[r.stop - 1] for r in report.rests])}
    cols["duration_s"] = cols["stop_s"] - cols["start_s"]
    cols["accel_norm_m_s2"] = np.linalg.norm(means, axis=1)
    cols["tilt_deg"] = np.degrees(np.arctan2(np.hypot(means[:, 0], means[:, 1]), means[:, 2]))
    for i, ax in enumerate("xyz"):
        cols[f"accel_{ax}_m_s2"] = means[:, i]
    if gyro_rad_s is not None:
        gm = np.degrees(np.array([gyro_rad_s[r].mean(axis=0) for r in report.rests]).reshape(-1, 3))
        for i, ax in enumerate("xyz"):
            cols[f"gyro_{ax}_deg_s"] = gm[:, i]
    return cols


def no_rests_evidence(report: rest_detection.RestReport, time_s=None) -> str:
    """Why a detector found no rest, in one line with the evidence and the rest options that would find one.

    Checked in order: the ``‖a‖`` band misses the level measured over the stillest windows of the record
    (``report.extra["measured_gravity_m_s2"]``: the paper's fixed band, or a stated ``--gravity``); still
    stretches shorter than ``--min-rest-s``; otherwise the first rejected stretch's reason, or no still
    stretch at all. A report with rests gives ``""``.

    Examples
    --------
    >>> import numpy as np
    >>> acc = np.tile([0.0, 0.0, 9.89], (500, 1))
    >>> rep = find_rests(acc, 0.01, RestsConfig.paper())
    >>> no_rests_evidence(rep)[:73]
    "the paper's fixed |a| band 9.760-9.840 m/s^2, misses the |a| 9.8900 m/s^2"
    """
    if report.rests:
        return ""
    measured = report.extra.get("measured_gravity_m_s2")
    lo, hi = report.band_m_s2
    if measured is not None and report.method != "shoe" and not lo < measured < hi:
        if report.method == "paper":
            what, fix = "the paper's fixed |a| band", ("--rest-detector adaptive (the default) measures the level; "
                                                     "the paper's band fits only a sensor reading 9.76-9.84 m/s^2")
        elif abs(report.gravity_m_s2 - measured) > 1e-9 * measured:
            what = f"the |a| band about --gravity {report.gravity_m_s2:.5g} m/s^2,"
            fix = "drop --gravity (default: measured) or state the |a| this sensor reads at rest"
        else:
            what, fix = "the |a| band", "widen --accel-band"
        return (f"{what} {lo:.3f}-{hi:.3f} m/s^2, misses the |a| {measured:.4f} m/s^2 measured in the stillest "
                f"stretch of the log; {fix}")
    short = [r for r in report.rejected if r.reason.startswith("too short")]
    if short or (report.n_short and not report.rejected):
        if short and time_s is not None:
            t = np.asarray(time_s)
            longest = max(float(t[r.span.stop - 1] - t[r.span.start]) for r in short)
            seen = f"{len(short)} still stretch(es) up to {longest:.3g} s"
        else:
            seen = f"{max(len(short), report.n_short)} still stretch(es)"
        return f"{seen} shorter than --min-rest-s {report.min_rest_s:g} s; lower --min-rest-s"
    if report.rejected:
        return (f"{len(report.rejected)} quiet stretch(es) rejected, the first because {report.rejected[0].reason}")
    if report.method == "shoe":
        return (f"the SHOE statistic never stays below gamma {report.extra.get('threshold', float('nan')):.4g} for "
                f"--min-rest-s {report.min_rest_s:g} s; raise --shoe-threshold or --gyro-threshold-deg-s")
    return (f"no still stretch of >= --min-rest-s {report.min_rest_s:g} s (|a| at rest {report.gravity_m_s2:.4f} "
            f"m/s^2, band {lo:.3f}-{hi:.3f} m/s^2); the log never rests")
