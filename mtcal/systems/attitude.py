"""Attitude of a recorded log: the paper's QNCF set up from the data (wang2023cja), or another filter.

The one procedure behind ``mtcal attitude`` (every ``--filter``), the default QNCF of ``mtcal
apply``/``calibrate`` (:func:`qncf_log_setup`) and the real-data study's ``qncf_cli`` filter:
:func:`estimate_attitude` takes one frozen :class:`AttitudeConfig` and the arrays;
:func:`attitude_record` is the whole record in one call (rests, clipped gyro, units check, filter:
the command's procedure), its arrays checked once at its edge. Rests come from
:func:`mtcal.systems.rests.find_rests` (adaptive detector, rests shorter than the stated minimum
dropped); the QNCF's gravity, AMD threshold and gains follow the rest levels and the measured noise
(:func:`qncf_params_from_rests`), the start is levelled from the first rest and the gyro bias of
that rest's quiet core removed (:func:`qncf_log_setup`); the gyro's units and time base are checked
against the accelerometer once (:func:`mtcal.systems.plausibility.check_units`). No reference
attitude is read.

References
----------
Wang X. et al., "Installation error calibration for MEMS angular measurement system in hypersonic
wind tunnel", Chin. J. Aeronaut. 2023, doi:10.1016/j.cja.2022.12.006, §3.1 (QNCF, AMD gate, Eq 5–8).
Laidig D., Seel T., "VQF: Highly accurate IMU orientation estimation with bias estimation and magnetic
disturbance rejection", Information Fusion 91 (2023) (``vqf``, ``basicvqf``).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from typing import TYPE_CHECKING

from mtcal.core.validate import as_float_array, sample_interval
from mtcal.systems.rests import RestsConfig, find_rests

if TYPE_CHECKING:  # numba-compiled modules, imported when a procedure runs (``mtcal --help`` stays light)
    from mtcal.filters.qncf import QncfParams
    from mtcal.methods import rest_detection

__all__ = ["KP_RANGE_RAD_S", "FILTERS", "AttitudeConfig", "AttitudeResult", "estimate_attitude", "attitude_record",
           "qncf_params_from_rests", "QncfLogSetup", "qncf_log_setup", "amd_gate_evidence"]

#: Range of the QNCF proportional gain from :func:`qncf_params_from_rests`' noise rule (1/s).
KP_RANGE_RAD_S = (0.05, 5.0)


def qncf_params_from_rests(rep: rest_detection.RestReport) -> QncfParams:
    """QNCF parameters from the data: gravity and AMD threshold from the rest level, gains from the noise.

    * ``gravity_m_s2``: the measured ``|a|`` at rest; ``amd_threshold_pct``: the rest band's half
      width in % of g, at least the paper's 0.3 (wang2023cja §3.1).
    * ``kp_rad_s = g σ_ω / σ_a`` (clipped to :data:`KP_RANGE_RAD_S`), σ_ω (rad/s) and σ_a (m/s²) the
      per-sample gyro and accelerometer noise measured at rest: the complementary filter's crossover
      at which the tilt variance from accelerometer noise, ``(σ_a/g)² Δt K_p / 2``, equals the one from
      gyro noise, ``σ_ω² Δt / (2 K_p)``; their sum is smallest there. The sample interval cancels: the
      rule holds at any sample rate for per-sample noise. ``ki_rad_s2 = K_p / 50 s`` (QNCF's default
      ratio, bias time constant 50 s). The paper gives no gains; no optical or other reference is used.

    Parameters
    ----------
    rep : mtcal.methods.rest_detection.RestReport
        Rests and measured levels of the log (``gravity_m_s2``, ``band_m_s2``, ``gyro_noise_rad_s``,
        ``accel_noise_m_s2``).

    Returns
    -------
    mtcal.filters.qncf.QncfParams

    Examples
    --------
    >>> import numpy as np
    >>> from mtcal.methods.rest_detection import detect_rests
    >>> rng = np.random.default_rng(0)
    >>> acc = np.array([0.0, 0.0, 9.81]) + 0.02 * rng.standard_normal((2000, 3))
    >>> gyr = 0.002 * rng.standard_normal((2000, 3))
    >>> p = qncf_params_from_rests(detect_rests(acc, 0.01, gyro_rad_s=gyr))
    >>> round(p.gravity_m_s2, 2), 0.5 < p.kp_rad_s < 1.5, p.ki_rad_s2 == p.kp_rad_s / 50
    (9.81, True, True)
    """
    from mtcal.filters.qncf import QncfParams

    half = 0.5 * (rep.band_m_s2[1] - rep.band_m_s2[0])
    kp = QncfParams.kp_rad_s
    if rep.gyro_noise_rad_s > 0 and rep.accel_noise_m_s2 > 0:
        kp = float(np.clip(rep.gravity_m_s2 * rep.gyro_noise_rad_s / rep.accel_noise_m_s2, *KP_RANGE_RAD_S))
    return QncfParams(gravity_m_s2=rep.gravity_m_s2, kp_rad_s=kp, ki_rad_s2=kp / 50.0,
                      amd_threshold_pct=max(0.3, 100.0 * half / rep.gravity_m_s2))


@dataclasses.dataclass(frozen=True)
class QncfLogSetup:
    """How the QNCF runs on one log (:func:`qncf_log_setup`).

    Attributes
    ----------
    gyro_rad_s : ndarray, shape (N, 3)
        Gyro for the filter (rad/s), the initial bias removed.
    params : QncfParams
    q0 : ndarray, shape (4,), or None
        Start attitude (sensor → world, yaw 0), or None (the filter levels from its first 100 samples).
    bias_rad_s : ndarray, shape (3,)
        Initial gyro bias removed (rad/s); zeros when none.
    quiet_core : QuietCore or None
        The rest part the bias came from.
    levelled_from : str
        Where the start attitude came from, in words.
    gate_warning : str
        :func:`amd_gate_evidence` of ``params`` and the rests: why the AMD gate shuts the accelerometer out
        even at rest, or ``""``.
    """

    gyro_rad_s: np.ndarray
    params: QncfParams
    q0: np.ndarray | None
    bias_rad_s: np.ndarray
    quiet_core: rest_detection.QuietCore | None
    levelled_from: str
    gate_warning: str = ""


def qncf_log_setup(filter_gyro_rad_s, accel_m_s2, dt_s: float, rep: rest_detection.RestReport, *,
                   gyro_rad_s=None) -> QncfLogSetup:
    """The QNCF's gyro, parameters and start attitude for one log.

    With the paper's rest detector (``rep.method == "paper"``) the QNCF runs as the paper states it:
    default :class:`QncfParams`, levelled from the first 100 samples, no initial bias removed.
    Otherwise the parameters follow the measured rest level and noise (:func:`qncf_params_from_rests`)
    and, when the first rest starts within 0.25 s, the start is levelled from that rest's quiet core
    (:func:`mtcal.methods.rest_detection.quiet_core`, its threshold the rest detector's noise factor
    ``rep.noise_factor`` times the measured noise) and the core's mean gyro removed as the bias.
    ``levelled_from`` says which, and why the first 100 samples when they are used (the paper's QNCF,
    no rest found, or a first rest that starts late).

    Parameters
    ----------
    filter_gyro_rad_s : ndarray, shape (N, 3)
        Gyro the filter integrates (rad/s; e.g. per-sample-dt weighted).
    accel_m_s2 : ndarray, shape (N, 3)
        Specific force (m/s²).
    dt_s : float
        Mean sample interval (s).
    rep : RestReport
        Rests of the log.
    gyro_rad_s : ndarray, shape (N, 3), optional
        Raw gyro for the quiet core (default ``filter_gyro_rad_s``).

    Returns
    -------
    QncfLogSetup

    Examples
    --------
    >>> import numpy as np
    >>> from mtcal.methods.rest_detection import detect_rests
    >>> rng = np.random.default_rng(1)
    >>> acc = np.array([0.0, 0.0, 9.81]) + 0.02 * rng.standard_normal((2000, 3))
    >>> gyr = np.radians([0.3, -0.2, 0.1]) + 0.002 * rng.standard_normal((2000, 3))
    >>> s = qncf_log_setup(gyr, acc, 0.01, detect_rests(acc, 0.01, gyro_rad_s=gyr))
    >>> np.degrees(s.bias_rad_s).round(2), s.levelled_from.startswith("first rest")
    (array([ 0.3, -0.2,  0.1]), True)
    """
    from mtcal.core.rotations import level_quat_zxy
    from mtcal.filters.qncf import QncfParams
    from mtcal.methods import rest_detection

    raw = filter_gyro_rad_s if gyro_rad_s is None else gyro_rad_s
    paper = rep.method == "paper"
    params = QncfParams() if paper else qncf_params_from_rests(rep)
    first = rep.rests[0] if rep.rests and not paper else None
    if first is not None and first.start <= max(int(0.25 / dt_s + 1e-9), 1):
        core = rest_detection.quiet_core(raw, first, dt_s, rep.gyro_noise_rad_s, noise_factor=rep.noise_factor)
        q0 = level_quat_zxy(accel_m_s2[core.core].mean(axis=0))  # the QNCF's levelling (Eq 9)
        bias = core.bias_rad_s
        return QncfLogSetup(filter_gyro_rad_s - bias, params, q0, bias, core,
                            "first rest (gyro bias of its quiet core removed)", amd_gate_evidence(params, rep))
    if paper:
        why = "the paper's QNCF: default gains"
    elif not rep.rests:
        why = "no rest found"
    else:
        why = f"the log does not start at rest: its first rest starts at sample {first.start}"
    return QncfLogSetup(filter_gyro_rad_s, params, None, np.zeros(3), None,
                        f"first 100 samples ({why}; no initial gyro bias removed)", amd_gate_evidence(params, rep))


def amd_gate_evidence(params: QncfParams, rep: rest_detection.RestReport) -> str:
    """Why the QNCF's AMD gate shuts the accelerometer out even at rest, in one line; ``""`` when it does not.

    The gate passes a sample when ``100 |‖a‖ / g − 1|`` (smoothed) is below ``params.amd_threshold_pct``
    (wang2023cja §3.1). When the ``‖a‖`` measured over the stillest windows of the record
    (``rep.extra["measured_gravity_m_s2"]``) is outside that gate — the paper's default ``g`` 9.80665 ±
    0.3 % on a sensor reading 9.85, or a stated ``--gravity`` — the filter integrates the gyro alone.

    Examples
    --------
    >>> import numpy as np
    >>> from mtcal.filters.qncf import QncfParams
    >>> from mtcal.methods.rest_detection import paper_rest_report
    >>> rep = paper_rest_report(np.tile([0.0, 0.0, 9.89], (500, 1)), 0.01)
    >>> amd_gate_evidence(QncfParams(), rep)[:60]
    "the QNCF's AMD gate (g 9.80665 m/s^2 +- 0.30 %) excludes the"
    >>> amd_gate_evidence(QncfParams(gravity_m_s2=9.89), rep)
    ''
    """
    measured = rep.extra.get("measured_gravity_m_s2")
    if measured is None:
        return ""
    off = 100.0 * abs(measured / params.gravity_m_s2 - 1.0)
    if off < params.amd_threshold_pct:
        return ""
    fix = ("--rest-detector adaptive sets g and the gate from the data" if rep.method == "paper"
           else "drop --gravity (default: measured) or widen --accel-band")
    return (f"the QNCF's AMD gate (g {params.gravity_m_s2:.6g} m/s^2 +- {params.amd_threshold_pct:.2f} %) excludes the "
            f"|a| {measured:.4f} m/s^2 measured in the stillest stretch of the log ({off:.2f} % off): the "
            f"accelerometer does not correct the attitude even at rest (gyro only); {fix}")


#: Filters of :func:`estimate_attitude`; ``qncf`` (the paper's filter, set up from the rests) is the default.
FILTERS = ("qncf", "vqf", "basicvqf", "mahony", "madgwick", "fusion")


@dataclasses.dataclass(frozen=True)
class AttitudeConfig:
    """How :func:`estimate_attitude` runs; checked when built.

    Attributes
    ----------
    filter : str
        One of :data:`FILTERS`. ``qncf``: :func:`qncf_log_setup` then the QNCF. ``vqf``/``basicvqf``:
        ``vqf.VQF(dt).updateBatch(gyr, acc)["quat6D"]`` (resp. ``BasicVQF``) at the library's defaults and
        timing (gyro sample k over ``[t_(k-1), t_k]``, start from its own state). ``mahony``,
        ``madgwick``, ``fusion``: :func:`mtcal.filters.anchors.run_attitude_filter` at the registry's
        default gain, levelled from the first 100 samples.
    rests : RestsConfig
        How rests are found when :func:`estimate_attitude` is not given them.
    check_units : bool
        Check the gyro's units and time base against the accelerometer once
        (:func:`mtcal.systems.plausibility.check_units`); False: only the tilt-rate scan the QNCF's public
        edge runs on a record (:func:`mtcal.methods.tilt_rate.check_tilt_rate_scale`: a scale off by > 5×
        refused, a gyro tilt above 5× the accelerometer's warns), once, before the trusted filter.

    Examples
    --------
    >>> AttitudeConfig.cli_defaults().filter, AttitudeConfig.real_data_study().check_units
    ('qncf', False)
    """

    filter: str = "qncf"
    rests: RestsConfig = RestsConfig()
    check_units: bool = True

    def __post_init__(self):
        if self.filter not in FILTERS:
            raise ValueError(f"filter must be one of {FILTERS}, got {self.filter!r}")
        if not isinstance(self.rests, RestsConfig):
            raise TypeError(f"rests must be a RestsConfig, got {type(self.rests).__name__}")
        if not isinstance(self.check_units, bool):
            raise TypeError(f"check_units must be a bool, got {type(self.check_units).__name__}")

    @classmethod
    def cli_defaults(cls, filter: str = "qncf") -> "AttitudeConfig":
        """``mtcal attitude`` at its defaults: adaptive rests ≥ 0.2 s, units checked, QNCF from the rests."""
        return cls(filter=filter, rests=RestsConfig.cli_defaults(0.2))

    @classmethod
    def real_data_study(cls) -> "AttitudeConfig":
        """broad2021's ``qncf_cli``: the command's QNCF set from the log's rests, the filter's own unit check."""
        return cls(filter="qncf", rests=RestsConfig.cli_defaults(0.2), check_units=False)

    @classmethod
    def paper(cls, min_rest_s: float = 0.2) -> "AttitudeConfig":
        """The QNCF as wang2023cja states it: default :class:`QncfParams`, levelled from the first 100 samples.

        Rests by wang2022sensors' fixed band (``--rest-detector paper``); no initial bias removed.
        """
        return cls(filter="qncf", rests=RestsConfig.paper(min_rest_s))


@dataclasses.dataclass(frozen=True)
class AttitudeResult:
    """What :func:`estimate_attitude` found.

    Attributes
    ----------
    q_ws : ndarray, shape (N, 4)
        Sensor attitude at each sample (scalar-first, sensor → world, z up).
    rests : RestReport
        The rests used.
    setup : QncfLogSetup or None
        The QNCF's gyro, parameters and start (``filter == "qncf"``).
    units_check : dict or None
        :func:`mtcal.systems.plausibility.check_units`' result (``config.check_units``).
    gain_text : str
        The filter's gains in words.
    clipped : ndarray (N,) of bool or None
        Gyro samples on a full-scale plateau (:func:`mtcal.systems.plausibility.clipped_samples`), skipped by
        the units check (:func:`attitude_record`); None when not looked for.
    clip_level_rad_s : float
        Their clipping level (rad/s; 0 if none).
    """

    q_ws: np.ndarray
    rests: rest_detection.RestReport
    setup: QncfLogSetup | None
    units_check: dict | None
    gain_text: str
    clipped: np.ndarray | None = None
    clip_level_rad_s: float = 0.0


def _library_vqf(name: str, gyro: np.ndarray, acc: np.ndarray, dt_s: float) -> tuple[np.ndarray, str]:
    import vqf

    cls = vqf.VQF if name == "vqf" else vqf.BasicVQF
    return cls(dt_s).updateBatch(gyro, acc)["quat6D"], f"{cls.__name__} defaults (tauAcc 3 s)"


def _registry_filter(name: str, gyro: np.ndarray, acc: np.ndarray, dt_s: float) -> tuple[np.ndarray, str]:
    from mtcal.filters import anchors, registry

    entry = registry.get_filter(name)
    q = anchors.run_attitude_filter(name, gyro[None], acc[None], dt_s)[0]
    return q, f"{entry.gain_unit} {entry.default_gain:g} (default)"


def _row_major(x: np.ndarray) -> np.ndarray:
    """A checked record row-major (C-contiguous; a copy only when it is not): the attitude does not depend on
    the caller's memory layout (a column-major record, e.g. from a MATLAB file, gives the same bits)."""
    return x if x.flags.c_contiguous else x.copy(order="C")


def estimate_attitude(gyro_rad_s, accel_m_s2, dt_s: float, config: AttitudeConfig, *, time_s=None, rests=None,
                      skip=None, unit_stated: str | None = None) -> AttitudeResult:
    """Sensor attitude of one record by the configured filter (wang2023cja §3.1 QNCF by default).

    Parameters
    ----------
    gyro_rad_s : array_like, shape (N, 3)
        Angular rate (rad/s), sample k the mean over ``[t_k, t_{k+1}]``.
    accel_m_s2 : array_like, shape (N, 3)
        Specific force (m/s²).
    dt_s : float
        Mean sample interval (s); the filters run at this fixed step.
    config : AttitudeConfig
    time_s : array_like, shape (N,), optional
        Sample times (s). With jitter (:func:`mtcal.systems.plausibility.time_base`) each gyro sample is
        weighted by its own interval over ``dt_s``; default uniform ``k · dt_s``.
    rests : RestReport, optional
        Rests already found (:func:`mtcal.systems.rests.find_rests`); default found by ``config.rests``.
    skip : ndarray of bool, shape (N,), optional
        Samples the units check ignores (e.g. clipped, :func:`mtcal.systems.plausibility.clipped_samples`).
    unit_stated : str, optional
        Where the gyro's unit was stated (a check that cannot decide then warns instead of refusing).

    Returns
    -------
    AttitudeResult

    Notes
    -----
    The arrays are taken row-major (C-contiguous) at this edge: a column-major record (e.g. read from a
    MATLAB file) gives the same attitude, bit for bit, as the same numbers row-major (the rest means'
    summation order follows the memory layout).

    Raises
    ------
    ValueError
        Bad shapes, ``dt_s`` or time base; a gyro the units check refuses.
    ImportError
        The filter's optional library is missing.

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(2)
    >>> acc = np.array([0.0, 0.0, 9.81]) + 0.02 * rng.standard_normal((1500, 3))
    >>> gyr = 0.002 * rng.standard_normal((1500, 3))
    >>> res = estimate_attitude(gyr, acc, 0.01, AttitudeConfig.cli_defaults())
    >>> res.q_ws.shape, res.setup.levelled_from.startswith("first rest"), float(abs(res.q_ws[-1, 0])) > 0.9999
    ((1500, 4), True, True)
    """
    if not isinstance(config, AttitudeConfig):
        raise TypeError(f"config must be an AttitudeConfig, got {type(config).__name__}")
    from mtcal.systems import plausibility

    g = _row_major(as_float_array(gyro_rad_s, "gyro_rad_s", ndim=2, last_dim=3, copy=False))
    a = _row_major(as_float_array(accel_m_s2, "accel_m_s2", ndim=2, last_dim=3, copy=False))
    if g.shape != a.shape:
        raise ValueError(f"gyro_rad_s and accel_m_s2 must have the same shape, got {g.shape} and {a.shape}")
    dt = sample_interval(dt_s)
    weights = None if time_s is None else plausibility.time_base(g.shape[0], time_s=time_s)[1]
    rep = find_rests(a, dt, config.rests, gyro_rad_s=g, time_s=time_s) if rests is None else rests
    return _attitude_trusted(g, a, dt, weights, time_s, config, rep, skip, unit_stated)


def attitude_record(gyro_rad_s, accel_m_s2, dt_s: float, config: AttitudeConfig, *, time_s=None,
                    unit_stated: str | None = None) -> AttitudeResult:
    """The attitude of one recorded log (``mtcal attitude``): rests, clipped gyro, units check, filter.

    One call for a record: its rests (:func:`mtcal.systems.rests.find_rests` with ``config.rests``),
    the gyro samples on a full-scale plateau (:func:`mtcal.systems.plausibility.clipped_samples`, skipped
    by the units check), then :func:`estimate_attitude` with those rests. The arrays are checked here
    once (shapes, finite, accelerometer in m/s², ``dt_s``, time column); the steps below trust them.

    Parameters
    ----------
    gyro_rad_s : array_like, shape (N, 3)
        Angular rate (rad/s), sample k the mean over ``[t_k, t_{k+1}]``.
    accel_m_s2 : array_like, shape (N, 3)
        Specific force (m/s²).
    dt_s : float
        Mean sample interval (s); the rests and the filters run at this step.
    config : AttitudeConfig
    time_s : array_like, shape (N,), optional
        Sample times (s): the rests' listed spans and the gyro's per-sample weights; default ``k · dt_s``.
    unit_stated : str, optional
        Where the gyro's unit was stated (a units check that cannot decide then warns instead of refusing).

    Returns
    -------
    AttitudeResult
        With ``clipped`` and ``clip_level_rad_s`` set.

    Raises
    ------
    ValueError
        Bad arrays, ``dt_s`` or time column; a gyro the units check refuses. A refusal after the rests
        were found carries them as ``exc.rests`` and the clipped samples as ``exc.clipped``
        (``(mask, level_rad_s)``), so a caller can show what the refusal saw.
    ImportError
        The filter's optional library is missing (``exc.rests``, ``exc.clipped`` as above).

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(2)
    >>> acc = np.array([0.0, 0.0, 9.81]) + 0.02 * rng.standard_normal((1500, 3))
    >>> gyr = 0.002 * rng.standard_normal((1500, 3))
    >>> res = attitude_record(gyr, acc, 0.01, AttitudeConfig.cli_defaults(), time_s=np.arange(1500) * 0.01)
    >>> len(res.rests.rests), bool(res.clipped.any()), res.setup.levelled_from.startswith("first rest")
    (1, False, True)
    """
    if not isinstance(config, AttitudeConfig):
        raise TypeError(f"config must be an AttitudeConfig, got {type(config).__name__}")
    from mtcal.systems import plausibility
    from mtcal.systems.rests import checked_record, find_rests_trusted

    if gyro_rad_s is None:
        raise ValueError("gyro_rad_s must be given: the attitude needs the gyro")
    a, g, dt, t = checked_record(accel_m_s2, dt_s, gyro_rad_s, time_s)
    a, g = _row_major(a), _row_major(g)                           # as estimate_attitude takes them
    weights = None if time_s is None else plausibility.time_base(g.shape[0], time_s=t)[1]
    rep = find_rests_trusted(a, g, dt, t, config.rests)
    clipped, level = plausibility.clipped_samples(g)
    try:
        res = _attitude_trusted(g, a, dt, weights, time_s, config, rep, clipped, unit_stated)
    except (ValueError, ImportError) as exc:
        exc.rests, exc.clipped = rep, (clipped, level)   # what the refusal saw, for the caller's diagnostics
        raise
    return dataclasses.replace(res, clipped=clipped, clip_level_rad_s=level)


def _attitude_trusted(g: np.ndarray, a: np.ndarray, dt: float, weights: np.ndarray | None, time_s,
                      config: AttitudeConfig, rep: rest_detection.RestReport, skip,
                      unit_stated: str | None) -> AttitudeResult:
    """:func:`estimate_attitude` on checked arrays (float64 (N, 3), ``dt`` checked, ``weights`` the time base's)."""
    from mtcal.systems import plausibility

    filter_gyro = g if weights is None else g * weights[:, None]
    setup = qncf_log_setup(filter_gyro, a, dt, rep, gyro_rad_s=g) if config.filter == "qncf" else None
    chk = None
    if config.check_units:
        chk = plausibility.check_units(filter_gyro, a, dt, rep.rests, time_s=time_s, skip=skip,
                                       unit_stated=unit_stated)
    if setup is not None:
        from mtcal.filters.qncf import qncf_trusted
        from mtcal.methods.tilt_rate import check_tilt_rate_scale

        if not config.check_units:   # no units check: the tilt-rate scan the QNCF's public edge runs on a record
            check_tilt_rate_scale(setup.gyro_rad_s, a, dt, excess="warn")
        q = qncf_trusted(setup.gyro_rad_s, a, dt, setup.params, q0=setup.q0, return_euler=False).q_ws
        return AttitudeResult(q, rep, setup, chk, "")
    runner = _library_vqf if config.filter in ("vqf", "basicvqf") else _registry_filter
    q, gain_text = runner(config.filter, np.ascontiguousarray(filter_gyro), np.ascontiguousarray(a), dt)
    return AttitudeResult(q, rep, None, chk, gain_text)
