"""Attitude of a recorded log with the paper's filter: the QNCF set up from the data (wang2023cja).

The one procedure behind ``mtcal attitude``/``apply``/``calibrate`` (their default QNCF) and the
real-data study's ``qncf_cli`` filter: rests found with the adaptive detector, rests shorter than
the stated minimum dropped, the filter's gravity, AMD threshold and gains from the rest levels and
the measured noise (:func:`qncf_params_from_rests`), the start levelled from the first rest and the
gyro bias of that rest's quiet core removed (:func:`qncf_log_setup`). No reference attitude is read.

References
----------
Wang X. et al., "Installation error calibration for MEMS angular measurement system in hypersonic
wind tunnel", Chin. J. Aeronaut. 2023, doi:10.1016/j.cja.2022.12.006, §3.1 (QNCF, AMD gate, Eq 5–8).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from mtcal.filters.qncf import QncfParams, initial_attitude_from_accel
from mtcal.methods import rest_detection

__all__ = ["KP_RANGE_RAD_S", "qncf_params_from_rests", "QncfLogSetup", "qncf_log_setup", "drop_short_rests",
           "default_rests"]

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
    """

    gyro_rad_s: np.ndarray
    params: QncfParams
    q0: np.ndarray | None
    bias_rad_s: np.ndarray
    quiet_core: rest_detection.QuietCore | None
    levelled_from: str


def qncf_log_setup(filter_gyro_rad_s, accel_m_s2, dt_s: float, rep: rest_detection.RestReport, *,
                   gyro_rad_s=None) -> QncfLogSetup:
    """The QNCF's gyro, parameters and start attitude for one log.

    With the paper's rest detector (``rep.method == "paper"``) the QNCF runs as the paper states it:
    default :class:`QncfParams`, levelled from the first 100 samples, no initial bias removed.
    Otherwise the parameters follow the measured rest level and noise (:func:`qncf_params_from_rests`)
    and, when the first rest starts within 0.25 s, the start is levelled from that rest's quiet core
    (:func:`mtcal.methods.rest_detection.quiet_core`, its threshold the rest detector's noise factor
    ``rep.noise_factor`` times the measured noise) and the core's mean gyro removed as the bias.

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
    raw = filter_gyro_rad_s if gyro_rad_s is None else gyro_rad_s
    paper = rep.method == "paper"
    params = QncfParams() if paper else qncf_params_from_rests(rep)
    first = rep.rests[0] if rep.rests and not paper else None
    if first is not None and first.start <= max(int(0.25 / dt_s + 1e-9), 1):
        core = rest_detection.quiet_core(raw, first, dt_s, rep.gyro_noise_rad_s, noise_factor=rep.noise_factor)
        q0 = initial_attitude_from_accel(accel_m_s2[core.core].mean(axis=0))
        bias = core.bias_rad_s
        return QncfLogSetup(filter_gyro_rad_s - bias, params, q0, bias, core,
                            "first rest (gyro bias of its quiet core removed)")
    return QncfLogSetup(filter_gyro_rad_s, params, None, np.zeros(3), None,
                        "first 100 samples (log does not start at rest)")


def drop_short_rests(rep: rest_detection.RestReport, time_s) -> rest_detection.RestReport:
    """Move rests listed shorter than ``rep.min_rest_s`` (by their span ``t[stop-1] − t[start]``) to ``rejected``."""
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


def default_rests(accel_m_s2, dt_s: float, gyro_rad_s, *, min_rest_s: float = 0.2) -> rest_detection.RestReport:
    """Rests as ``mtcal attitude`` finds them at its defaults: adaptive detector, rests ≥ ``min_rest_s``.

    Uniform sampling (time = k·dt_s) is assumed for the listed-span rule.
    """
    rep = rest_detection.detect_rests(accel_m_s2, dt_s, gyro_rad_s=gyro_rad_s,
                                      params=rest_detection.RestDetectorParams(min_rest_s=min_rest_s))
    return drop_short_rests(rep, np.arange(len(accel_m_s2)) * dt_s)
