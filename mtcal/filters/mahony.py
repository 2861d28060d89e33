"""IMU-only Mahony explicit complementary filter with gyro-bias estimation, batched over trials.

The filter of Mahony, Hamel & Pflimlin (2008), "explicit complementary filter
with bias correction" (their Eq 32 with a single vectorial measurement, the
gravity direction), without a magnetometer::

    v̂_k  = C(q_k)ᵀ e_z                       predicted "up" in the sensor frame
    ω_mes = â_k × v̂_k,   â_k = a_k / ‖a_k‖    tilt error (rad, small angle)
    b̂_{k+1} = b̂_k − K_i ω_mes Δt              gyro-bias estimate (rad/s)
    Ω_k  = ω_k − b̂_{k+1} + K_p ω_mes          corrected rate (rad/s)
    q_{k+1} = q_k ⊗ exp(½ Ω_k Δt)             exact increment (cf. wang2023cja Eq 6–7)

``q`` is the scalar-first attitude of the sensor frame in a z-up world frame
(sensor → world, ``v_w = C(q) v_s``): the convention of
:mod:`mtcal.filters.qncf`. Yaw is unobservable without a magnetometer and is
integrated from the gyro only.

Relation to QNCF: :func:`mtcal.filters.qncf.qncf` is this same PI law (its
integral ``I = −b̂``) plus the Acceleration Magnitude Detector, which opens
the correction only while ‖a‖ ≈ g. The filter bake-off therefore measures
what the AMD gate buys (or costs) under vibration and motion.

Implementation: a numba-compiled loop over time (no Python loop), trials stepped
four at a time in SIMD lanes (:mod:`mtcal.filters._kernels_mahony`); each trial's
arithmetic is the scalar recursion's and independent of the others, so a trial's
output does not depend on which or how many trials share the call (bit for bit).

References
----------
.. [1] R. Mahony, T. Hamel, J.-M. Pflimlin, "Nonlinear complementary filters on
   the special orthogonal group", IEEE Transactions on Automatic Control 53(5),
   1203–1218, 2008. doi:10.1109/TAC.2008.923738

Examples
--------
>>> import numpy as np
>>> acc = np.tile([0.0, 0.0, 9.80665], (200, 1))
>>> res = mahony_imu(np.zeros((200, 3)), acc, 0.01)
>>> res.q_ws[-1].round(12).tolist()
[1.0, 0.0, 0.0, 0.0]
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mtcal.core.validate import positive_scalar
from mtcal.filters._kernels_common import OutputPool

__all__ = ["MahonyParams", "MahonyResult", "mahony_imu"]


@dataclass(frozen=True)
class MahonyParams:
    """Gains of the explicit complementary filter.

    Parameters
    ----------
    kp_rad_s : float
        Proportional gain K_p (1/s: rad/s of correction per rad of tilt error);
        the tilt time constant is ≈ 1/K_p. Default 1.0 /s (same as QNCF's default).
    ki_rad_s2 : float
        Integral (bias) gain K_i (1/s²); 0 disables bias estimation. Default 0.02 /s².
    """

    kp_rad_s: float = 1.0
    ki_rad_s2: float = 0.02

    def __post_init__(self) -> None:
        positive_scalar(self.kp_rad_s, "kp_rad_s", allow_zero=True)
        positive_scalar(self.ki_rad_s2, "ki_rad_s2", allow_zero=True)


@dataclass(frozen=True)
class MahonyResult:
    """Output of :func:`mahony_imu`; a leading trial axis iff the input had one.

    Attributes
    ----------
    q_ws : ndarray (..., N, 4)
        Attitude at t_k, before sample k is applied (scalar-first, sensor → world).
    bias_rad_s : ndarray (..., 3)
        Final gyro-bias estimate b̂ (rad/s).
    """

    q_ws: np.ndarray
    bias_rad_s: np.ndarray


def mahony_imu(gyro_rad_s: np.ndarray, accel_m_s2: np.ndarray, dt_s: float, params: MahonyParams = MahonyParams(), *,
               q0: np.ndarray | None = None, init_samples: int = 100) -> MahonyResult:
    """Run the IMU-only Mahony filter (Mahony 2008 Eq 32, gravity only) over a record.

    Parameters
    ----------
    gyro_rad_s : ndarray, shape (N, 3) or (T, N, 3)
        Sensor-frame angular rate (rad/s); sample k acts over ``[t_k, t_{k+1}]``.
    accel_m_s2 : ndarray, same shape
        Sensor-frame specific force (m/s²).
    dt_s : float
        Sample interval (s).
    params : MahonyParams
        Gains.
    q0 : ndarray, shape (4,) or (T, 4), optional
        Initial attitude (scalar-first, sensor → world); default levelled from
        the mean of the first ``init_samples`` accelerometer samples, yaw 0
        (:func:`mtcal.filters.qncf.initial_attitude_from_accel`).
    init_samples : int
        Samples averaged for the default levelling.

    Returns
    -------
    MahonyResult
        ``q_ws`` (…, N, 4) and ``bias_rad_s`` (…, 3), with a leading trial axis T iff the records had one.

    Preconditions
    -------------
    The caller guarantees (not checked here): ``gyro_rad_s`` and ``accel_m_s2`` finite float64 arrays of
    one shape, (N, 3) or (T, N, 3), in rad/s (not deg/s) and m/s² (not g); ``dt_s`` > 0 (s); ``params`` a
    :class:`MahonyParams`; ``q0`` None or unit quaternions (4,) or (T, 4); ``init_samples`` ≥ 1.
    :func:`mtcal.filters.anchors.run_attitude_filter` (``"mahony"``) checks records once at its edge.

    Examples
    --------
    >>> import numpy as np
    >>> acc = np.tile([0.0, 0.0, 9.80665], (2, 100, 1))
    >>> res = mahony_imu(np.zeros((2, 100, 3)), acc, 0.01, q0=np.array([1.0, 0.0, 0.0, 0.0]))
    >>> res.q_ws.shape, res.bias_rad_s.shape
    ((2, 100, 4), (2, 3))
    """
    from mtcal.filters._kernels_mahony import mahony_batch

    single = gyro_rad_s.ndim == 2
    w3, a3 = (gyro_rad_s[None], accel_m_s2[None]) if single else (gyro_rad_s, accel_m_s2)
    trials = w3.shape[0]
    if q0 is None:
        from mtcal.filters.qncf import initial_attitude_from_accel

        n0 = max(1, min(int(init_samples), w3.shape[1]))
        q0 = initial_attitude_from_accel(np.stack([np.mean(row[:n0], axis=0) for row in a3]))
    q = np.ascontiguousarray(np.broadcast_to(q0, (trials, 4)), dtype=np.float64)
    q_out = _POOL.take("q", w3.shape[:2] + (4,))   # every element is written by the kernel
    bias = np.empty((trials, 3))
    mahony_batch(np.ascontiguousarray(w3, dtype=np.float64), np.ascontiguousarray(a3, dtype=np.float64), q,
                 float(dt_s), float(params.kp_rad_s), float(params.ki_rad_s2), q_out, bias)
    _POOL.keep("q", q_out)
    return MahonyResult(q_out[0], bias[0]) if single else MahonyResult(q_out, bias)


#: The attitude history of the last batch call, reused once the caller drops it (no page faults: a sweep
#: block of 50 trials × 12 000 samples is 19 MB per call).
_POOL = OutputPool(min_bytes=1 << 20)
