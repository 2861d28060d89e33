"""broad2021 runs: the 6D filters and BROAD's 9D Madgwick/Mahony on real trials, errors against optical truth.

* :func:`run_6d` — one of :data:`~.scenario.FILTERS_6D` on one or a batch of records (rad/s, m/s²),
  attitude in mtcal's convention (sensor → z-up world, row k = attitude at ``t_k``). Every filter
  starts levelled from the first 100 samples (yaw 0) except ``qncf_cli``, which is the attitude
  system ``mtcal attitude`` runs (:func:`mtcal.systems.attitude.estimate_attitude` with
  :meth:`~mtcal.systems.attitude.AttitudeConfig.real_data_study`: adaptive rest detector, gravity and
  AMD threshold from the measured rest level, start levelled from the first rest and that rest's mean
  rate removed).
  Gains: the registry defaults (QNCF/Mahony K_p = 1 /s, K_i = K_p/50 s; Madgwick β = 0.033 rad/s;
  VQF/BasicVQF τ_acc = 3 s; Fusion gain 0.5) — the same for every trial, nothing tuned on BROAD.
* :func:`errors_deg` — BROAD's total / heading / inclination error series
  (:func:`mtcal.core.metrics.orientation_errors`) and :func:`rmse_deg` their RMSE over the movement
  phase (optical NaN samples excluded, :func:`mtcal.core.metrics.rmse_over_phase`).
* :func:`run_9d` — BROAD's case study: Madgwick (β) and Mahony (K_p, K_i) 9D as BROAD ran them
  (:mod:`mtcal.filters.xio_ahrs`: start from the first accelerometer/magnetometer sample, output after
  each sample, rotated +90° about the vertical into ENU), RMSE per gain setting.

Madgwick 6D is the compiled x-io kernel with the ``ahrs`` anchor's timing (tests check it against
``ahrs.filters.Madgwick`` through :func:`mtcal.filters.anchors.run_attitude_filter`).
"""

from __future__ import annotations

import numpy as np

from mtcal.core import metrics, rotations
from mtcal.filters import xio_ahrs
from mtcal.filters.anchors import run_attitude_filter
from mtcal.filters.qncf import initial_attitude_from_accel
from mtcal.filters.registry import get_filter
from mtcal.systems.attitude import AttitudeConfig, estimate_attitude

from .scenario import FILTERS_6D, Trial

__all__ = ["run_6d", "errors_deg", "rmse_deg", "run_9d", "initial_rest", "NinedResult",
           "INIT_SAMPLES"]

#: Samples averaged by the common levelled start (as :func:`mtcal.filters.anchors.run_attitude_filter`).
INIT_SAMPLES = 100


def initial_rest(trial: Trial, margin_s: float = 0.5) -> slice:
    """Samples of the trial's initial rest: from 0 to ``margin_s`` before BROAD's first movement sample.

    Raises
    ------
    ValueError
        The trial starts moving within ``margin_s + 1 s`` (no usable initial rest).
    """
    moving = np.flatnonzero(trial.movement)
    first = int(moving[0]) if moving.size else trial.n
    stop = first - int(round(margin_s * trial.fs_hz))
    if stop < int(round(1.0 * trial.fs_hz)):
        raise ValueError(f"trial {trial.name!r}: initial rest shorter than 1 s before the movement phase")
    return slice(0, stop)


def _basicvqf(w: np.ndarray, a: np.ndarray, dt: float, tau_acc_s: float, q0: np.ndarray) -> np.ndarray:
    import vqf

    filt = vqf.BasicVQF(dt, tauAcc=tau_acc_s)
    state = filt.state
    state["accQuat"] = np.array(q0, dtype=float)
    filt.state = state
    gyr = np.concatenate([np.zeros((1, 3)), w[:-1]], axis=0)   # as the VQF adapter: rate over [t_{k-1}, t_k]
    return filt.updateBatch(np.ascontiguousarray(gyr), np.ascontiguousarray(a))["quat6D"]


def run_6d(name: str, gyro_rad_s, accel_m_s2, dt_s: float) -> np.ndarray:
    """One 6D filter of :data:`~.scenario.FILTERS_6D` on records (N, 3) or (T, N, 3); q_ws (…, N, 4).

    Examples
    --------
    >>> acc = np.tile([0.0, 0.0, 9.81], (300, 1)); gyr = np.full((300, 3), 1e-5)
    >>> q = run_6d("madgwick", gyr, acc, 0.01)
    >>> q.shape, float(np.abs(q[-1] - [1, 0, 0, 0]).max()) < 1e-3
    ((300, 4), True)
    """
    if name not in FILTERS_6D:
        raise ValueError(f"name must be one of {FILTERS_6D}, got {name!r}")
    w = np.asarray(gyro_rad_s, dtype=float)
    a = np.asarray(accel_m_s2, dtype=float)
    single = w.ndim == 2
    w3, a3 = (w[None], a[None]) if single else (w, a)
    if name in ("qncf_paper", "mahony", "vqf", "fusion"):
        out = run_attitude_filter({"qncf_paper": "qncf"}.get(name, name), w3, a3, dt_s, init_samples=INIT_SAMPLES)
    else:
        # the common start of run_attitude_filter: levelled from each record's first INIT_SAMPLES samples
        q0s = initial_attitude_from_accel(np.stack([np.mean(r[:INIT_SAMPLES], axis=0) for r in a3]))
        out = np.empty(w3.shape[:2] + (4,))
        for t in range(w3.shape[0]):
            if name == "madgwick":
                out[t] = xio_ahrs.madgwick(w3[t], a3[t], dt_s, get_filter("madgwick").default_gain, q0=q0s[t],
                                           timing="before")[0]
            elif name == "basicvqf":
                out[t] = _basicvqf(w3[t], a3[t], dt_s, get_filter("vqf").default_gain, q0s[t])
            else:  # qncf_cli: the attitude system as the command runs it (no optical data read)
                out[t] = estimate_attitude(w3[t], a3[t], dt_s, AttitudeConfig.real_data_study()).q_ws
    return out[0] if single else out


def errors_deg(q_est, opt_quat, *, inclination_only: bool = False) -> np.ndarray:
    """BROAD's total, heading and inclination error (deg) of estimates against optical truth, shape (3, …, N).

    One record (N, 4): :func:`mtcal.core.metrics.orientation_errors`. A batch (L, N, 4) (gain lanes,
    twin draws): the same definitions from the two components of ``q_e = q ⊗ q_ref⁻¹`` they need
    (``w_e = q·q_ref``, ``z_e``), vectorised (tests check it against ``orientation_errors``).
    ``inclination_only``: the inclination row alone, shape (1, …, N) — the same numbers, without the
    total and heading errors' ``arccos``/``arctan`` over every sample (the twin's predictions read
    only the inclination).
    """
    q = np.asarray(q_est, dtype=float)
    if q.ndim == 2:
        if inclination_only:
            return np.degrees(metrics.inclination_error(q, opt_quat)[None])
        return np.degrees(np.stack(metrics.orientation_errors(q, opt_quat)))
    r = np.asarray(opt_quat, dtype=float)
    r = r / np.linalg.norm(r, axis=-1, keepdims=True)
    if (q.ndim == 3 and q.flags.c_contiguous and r.shape == q.shape[1:]
            and r.flags.c_contiguous != r.flags.f_contiguous):     # the two layouts whose einsum order is known
        return _errors_deg_compiled(q, r, inclination_only)
    q = q / np.sqrt(np.einsum("...i,...i->...", q, q))[..., None]
    w = np.einsum("...i,...i->...", q, r)
    z = -q[..., 0] * r[:, 3] - q[..., 1] * r[:, 2] + q[..., 2] * r[:, 1] + q[..., 3] * r[:, 0]
    nrm = np.sqrt(w * w + z * z)      # |q_e| = 1, so w² + z² <= 1
    with np.errstate(invalid="ignore", divide="ignore"):
        incl = 2.0 * np.arccos(np.clip(nrm, 0.0, 1.0))
        if inclination_only:
            return np.degrees(incl[None])
        total = 2.0 * np.arccos(np.clip(np.abs(w), 0.0, 1.0))
        heading = 2.0 * np.arctan(np.abs(z / w))
    return np.degrees(np.stack([total, heading, incl]))


def _errors_deg_compiled(q: np.ndarray, r: np.ndarray, inclination_only: bool) -> np.ndarray:
    """The batch branch of :func:`errors_deg` for a C-contiguous (L, N, 4) ``q`` and unit (N, 4) ``r``: the arguments
    of ``arccos``/``arctan`` in one compiled pass (the same operations), the functions in numpy, written in place."""
    from ._kernels import error_angle_arguments

    out = np.empty((1 if inclination_only else 3,) + q.shape[:2])
    args = out if inclination_only else np.empty((2,) + q.shape[:2])
    error_angle_arguments(q, r, r.flags.f_contiguous, out[-1], args[0], args[-1], not inclination_only)
    with np.errstate(invalid="ignore"):
        np.arccos(out[-1], out=out[-1])
        if not inclination_only:
            np.arccos(args[0], out=out[0])
            np.arctan(args[1], out=out[1])
    out *= 2.0
    return np.degrees(out, out=out)


def rmse_deg(q_est, trial: Trial, *, inclination_only: bool = False) -> np.ndarray:
    """RMSE (deg) over the movement phase of total, heading, inclination error, shape (3, …).

    ``q_est`` (…, N, 4); optical NaN samples are excluded (BROAD's rule). ``inclination_only``:
    the inclination row alone, shape (1, …) (:func:`errors_deg`).
    """
    e = errors_deg(q_est, trial.opt_quat, inclination_only=inclination_only)
    flat = e.reshape(-1, e.shape[-1])
    # metrics.rmse_over_phase of every row, its checks made once for all rows: the same arithmetic per row
    if np.isinf(flat).any():
        raise ValueError("error must not contain infinite values")
    phase = np.asarray(trial.movement)
    if phase.shape != flat.shape[1:]:
        raise ValueError(f"phase must have the shape of error {flat.shape[1:]}, got {phase.shape}")
    keep = np.isfinite(flat)
    keep &= phase.astype(bool)
    if not keep.any(axis=1).all():
        raise ValueError("no finite error sample in the phase")
    return np.array([float(np.sqrt(np.mean(x[k] ** 2))) for x, k in zip(flat, keep)]).reshape(e.shape[:-1])


class NinedResult(dict):
    """``{"madgwick": (3, L) RMSE deg per β, "mahony": (3, L) per (K_p, K_i)}`` plus the grids (``grids``)."""


def run_9d(trial: Trial, betas, kps, kis, *, field_reference: str = "c", initial: str = "broad") -> NinedResult:
    """BROAD's 9D case study on one trial: RMSE (total, heading, inclination; deg) per gain setting.

    Parameters
    ----------
    trial : Trial
    betas : array_like, shape (L1,)
        Madgwick β values (rad/s).
    kps, kis : array_like, shape (L2,)
        Mahony (K_p, K_i) pairs (1/s, 1/s²).
    field_reference : {"c", "paper"}
        Madgwick's field reference (:func:`mtcal.filters.xio_ahrs.madgwick`): BROAD's C code or Eq 46.
    initial : {"broad", "optical"}
        Start from BROAD's first-sample accelerometer/magnetometer quaternion, or from the optical attitude
        at the first sample with a reference (a diagnosis of the start's share of the error).
    """
    if initial == "broad":
        q0 = xio_ahrs.initial_quaternion_acc_mag(trial.accel_m_s2[0], trial.mag_uT[0])
    elif initial == "optical":
        k = int(np.flatnonzero(np.isfinite(trial.opt_quat[:, 0]))[0])
        q0 = rotations.quat_multiply(rotations.quat_conjugate(xio_ahrs.NWU_TO_ENU), trial.opt_quat[k])
    else:
        raise ValueError(f"initial must be 'broad' or 'optical', got {initial!r}")
    args = (trial.gyro_rad_s, trial.accel_m_s2, trial.dt_s)
    out = NinedResult()
    qm = xio_ahrs.madgwick(*args, betas, mag_uT=trial.mag_uT, q0=q0, field_reference=field_reference)
    out["madgwick"] = rmse_deg(rotations.quat_multiply(xio_ahrs.NWU_TO_ENU, qm), trial)
    qh = xio_ahrs.mahony(*args, kps, kis, mag_uT=trial.mag_uT, q0=q0)
    out["mahony"] = rmse_deg(rotations.quat_multiply(xio_ahrs.NWU_TO_ENU, qh), trial)
    return out
