"""One call for every attitude filter of the bake-off, in mtcal's units, frames and timing.

:func:`run_attitude_filter` runs QNCF, the IMU-only Mahony filter, and three
well-kept open-source filters an engineer would try first, on the same
(T, N, 3) record, and returns the sensor attitude ``q_ws`` (T, N, 4) in mtcal's
convention: scalar-first ``[q0, q1, q2, q3]``, sensor → world, z-up world
(a level sensor at rest reads ``[0, 0, +g]``), and ``q_ws[:, k]`` = attitude at
``t_k`` *before* sample k is applied (gyro sample k is the mean rate over
``[t_k, t_{k+1}]``, see :mod:`mtcal.core.simulate`).

=========  ===========================  ======================  ======================  ===========
name       implementation               input units             quaternion / frame      gain tuned
=========  ===========================  ======================  ======================  ===========
qncf       mtcal.filters.qncf           rad/s, m/s²             w,x,y,z; s → w, z up    K_p (1/s)
mahony     mtcal.filters.mahony         rad/s, m/s²             w,x,y,z; s → w, z up    K_p (1/s)
madgwick   ``ahrs.filters.Madgwick``ᶜ   rad/s, m/s² (normed)    w,x,y,z; s → earth      β (rad/s)
vqf        ``vqf.VQF`` (C++)            rad/s, m/s²             w,x,y,z; IMU → ENU-z    τ_acc (s)
fusion     ``imufusion.Ahrs`` (C)       **°/s and g**           w,x,y,z; NWU (z up)     gain (1)
=========  ===========================  ======================  ======================  ===========

ᶜ computed by mtcal's compiled equivalent of ``ahrs``' per-sample Python loop
(:func:`mtcal.filters.xio_ahrs.madgwick`, ``timing="before"``, ``hold_zero_rate=True``,
the start normalised as ``ahrs`` does): the same IEEE operations up to the order of a few
sums and ``ahrs``' repeated renormalisation of ``q``, so the two agree to ≈ 1e-12 per
quaternion component (measured: :func:`reference_difference`, tested in
``tests/filters/test_anchors.py``; the bake-off re-checks it on one record per family,
:func:`mtcal.sweep.bakeoff.reference_check`) at ≈ 1/500 of the CPU (issue #37: ``ahrs``'
loop was 32 % of notebook 50). ``ahrs`` is still required: the registry keeps its runner
as the entry's ``reference``, and :func:`run_attitude_filter` runs it with
``reference=True``.

Adapters:

* Timing. mtcal applies gyro sample k over ``[t_k, t_{k+1}]``, accelerometer
  sample k being at ``t_k``. ``vqf`` integrates gyro sample ``k`` over
  ``t_{k−1} → t_k`` and then corrects with the accelerometer at ``t_k``: the adapter
  delays the gyro by one sample (accelerometer unshifted); its first step is a
  priming step (zero rate, accelerometer sample 0) that runs VQF's first-sample
  inclination initialisation at ``t_0``; its inclination state (``accQuat``) is
  seeded with ``q0``; rest detection and bias estimation stay at the library's
  defaults. ``ahrs`` Madgwick's step ``t−1 → t`` uses gyro *and* accelerometer sample
  ``t`` with the gradient evaluated at the previous attitude: the adapter delays
  both. Row k of every output is then the attitude at ``t_k``, like QNCF's.
  Measured on a 30 °/s rotation at 100 Hz (``tests/filters/test_anchors.py``): a
  wrong shift gives 0.3° (one sample of rotation); the adapters give < 0.04°
  (Madgwick's residual is its first-order integration).
* ``ahrs`` leaves q unchanged when a gyro sample is exactly zero (a quantised
  gyro at rest); simulated records always carry noise.
* ``imufusion`` takes the gyro in °/s and the accelerometer in g (converted
  here), returns float32 quaternions (≈ 1e-7 resolution, ~1e-5°), uses the NWU
  convention (z up, as mtcal), starts from ``q0`` with the start-up ramp
  skipped; acceleration rejection stays at the library default (10°, 5 s).
* The QNCF and Mahony integral gains follow K_p: ``K_i = K_p / 50 s`` (QNCF's
  default ratio).

Each filter is one entry of :data:`mtcal.filters.registry.BUILTIN_FILTERS` (name, runner
by module and function — the batch runners of this module — output,
default gain and its unit, ours/anchor, optional package); the RAMS EKF is declared there
too, as an ``output="angle"`` filter (angle about a known axis), run through
:func:`run_axis_angle_filter`. Everything else looks filters up in the registry.

Every filter starts from the same ``q0``: levelled from the mean of the first
``init_samples`` accelerometer samples, yaw 0. The three external libraries
are the optional ``bench`` extra (``pip install 'mtcal[bench]'``; ``dev`` includes them); they are imported on first
use and :func:`available_filters` lists what is installed.

References
----------
.. [1] S. O. H. Madgwick, A. J. L. Harrison, R. Vaidyanathan, "Estimation of IMU and
   MARG orientation using a gradient descent algorithm", IEEE ICORR 2011.
   doi:10.1109/ICORR.2011.5975346 (``ahrs`` 0.4: M. Garcia, https://ahrs.readthedocs.io)
.. [2] D. Laidig, T. Seel, "VQF: Highly accurate IMU orientation estimation with bias
   estimation and magnetic disturbance rejection", Information Fusion 91, 187–204, 2023.
   doi:10.1016/j.inffus.2022.10.014
.. [3] S. O. H. Madgwick, "Fusion" AHRS library (x-io Technologies), imufusion 1.3,
   https://github.com/xioTechnologies/Fusion
.. [4] R. Mahony, T. Hamel, J.-M. Pflimlin, IEEE TAC 53(5), 2008. doi:10.1109/TAC.2008.923738

Examples
--------
>>> import numpy as np
>>> acc = np.tile([0.0, 0.0, 9.80665], (1, 50, 1))
>>> gyr = np.full((1, 50, 3), 1e-6)
>>> q = run_attitude_filter("mahony", gyr, acc, 0.01)
>>> q.shape
(1, 50, 4)
>>> float(tilt_error_rad(q, np.array([1.0, 0, 0, 0])).max()) < 1e-5
True
"""

from __future__ import annotations

from contextlib import contextmanager

import numpy as np

from mtcal.core import rotations
from mtcal.core.validate import (STANDARD_GRAVITY_M_S2, as_float_array, check_accel_units, check_gyro_units,
                                 positive_scalar, unit_quaternion)

from mtcal.filters.registry import (RAMS_EKF_DEFAULT_GAIN, AxisContext, available_filters, get_filter, register_filter,
                                    require_filter)

__all__ = ["available_filters", "require_filter", "run_attitude_filter", "run_axis_angle_filter",
           "attitude_filter", "axis_angle_filter", "levelled_start", "reference_difference", "reference_runs",
           "tilt_error_rad", "twist_angle_rad", "RAMS_EKF_DEFAULT_GAIN"]

_KI_RATIO_S = 50.0


def _level_q0(accel: np.ndarray, init_samples: int) -> np.ndarray:
    from mtcal.filters.qncf import initial_attitude_from_accel

    n0 = max(1, min(int(init_samples), accel.shape[1]))
    # per-trial means: a trial's levelling must not depend on its batch-mates (summation order)
    return initial_attitude_from_accel(np.stack([np.mean(row[:n0], axis=0) for row in accel]))


def run_attitude_filter(name: str, gyro_rad_s, accel_m_s2, dt_s: float, gain: float | None = None, *,
                        q0=None, init_samples: int = 100, reference: bool = False) -> np.ndarray:
    """Run one bake-off filter on a batch of records; attitude in mtcal's convention.

    Parameters
    ----------
    name : str
        A registered attitude filter (:func:`mtcal.filters.registry.filter_names`, see module table).
    gyro_rad_s : array_like, shape (T, N, 3)
        Sensor-frame rate (rad/s); sample k is the mean over ``[t_k, t_{k+1}]``.
    accel_m_s2 : array_like, shape (T, N, 3)
        Sensor-frame specific force (m/s²).
    dt_s : float
        Sample interval (s).
    gain : float, optional
        The filter's tuned gain (its registry ``gain_unit``); default its ``default_gain``.
    q0 : array_like, shape (4,) or (T, 4), optional
        Initial attitude; default levelled from the first ``init_samples`` samples.
    init_samples : int
        Samples averaged for the default levelling.
    reference : bool
        Run the external library's own runner of an anchor that mtcal computes with a
        compiled equivalent (the registry entry's ``reference``; e.g. ``ahrs``' Madgwick).

    Returns
    -------
    ndarray, shape (T, N, 4)
        ``q_ws`` at each ``t_k`` (scalar-first, sensor → world, z up).

    Raises
    ------
    ValueError
        Unknown filter, bad shapes, values not finite, a gyro not in rad/s or an accelerometer
        in g, non-positive gain/dt, or ``reference=True`` for a filter without a reference runner.
    ImportError
        The filter's optional library is not installed.

    Notes
    -----
    The records, ``dt_s``, the gain and ``q0`` are checked here, once (the public edge of the filter
    family) and go to the registry entry's runner, which trusts them (finite float64 (T, N, 3), units
    checked, ``dt_s`` and gain > 0, ``q0`` unit (T, 4)), as :func:`attitude_filter` does for records a
    caller made itself.
    """
    entry = get_filter(name)
    if entry.output != "attitude":
        raise ValueError(f"filter {name!r} returns an {entry.output}, not an attitude")
    if reference and entry.reference is None:
        raise ValueError(f"filter {name!r} has no reference runner (reference=True needs one of "
                         f"{[n for n in available_filters(output='attitude') if get_filter(n).reference]})")
    require_filter(name)
    w = as_float_array(gyro_rad_s, "gyro_rad_s", ndim=3, last_dim=3, copy=False)
    a = as_float_array(accel_m_s2, "accel_m_s2", ndim=3, last_dim=3, copy=False)
    if w.shape != a.shape:
        raise ValueError(f"gyro_rad_s and accel_m_s2 must have the same shape, got {w.shape} and {a.shape}")
    check_gyro_units(w)
    if w.shape[1] > 1:
        check_accel_units(a)
    dt = positive_scalar(dt_s, "dt_s")
    g = positive_scalar(entry.default_gain if gain is None else gain, "gain")
    trials = w.shape[0]
    q_init = _level_q0(a, init_samples) if q0 is None else unit_quaternion(q0, "q0")
    if q_init.shape not in ((4,), (trials, 4)):
        raise ValueError(f"q0 must have shape (4,) or ({trials}, 4), got {q_init.shape}")
    q_init = np.broadcast_to(q_init, (trials, 4))
    return (entry.reference if reference else entry.run)(w, a, dt, g, q_init)


def levelled_start(accel_m_s2: np.ndarray, init_samples: int) -> np.ndarray:
    """The common start of every filter (T, 4): levelled from each record's first ``init_samples`` samples, yaw 0.

    What :func:`run_attitude_filter` uses when ``q0`` is None; a caller that runs several filters on
    the same records (the sweep evaluators) computes it once for :func:`attitude_filter`.
    """
    return _level_q0(accel_m_s2, init_samples)


def attitude_filter(name: str, gyro_rad_s: np.ndarray, accel_m_s2: np.ndarray, dt_s: float, gain: float,
                    q_init: np.ndarray) -> np.ndarray:
    """One registered attitude filter (its registry runner) on a batch of records, ``q_ws`` (T, N, 4).

    The registry runner :func:`run_attitude_filter` reaches after checking raw records once, for a
    caller with its own records (the sweep evaluators' simulated blocks, several filters on one block)
    and the start computed once (:func:`levelled_start`). Inside :func:`reference_runs` a named filter
    runs its library reference.

    Parameters
    ----------
    name : str
        A registered attitude filter.
    gyro_rad_s, accel_m_s2 : ndarray, shape (T, N, 3)
        Sensor-frame rate (rad/s) and specific force (m/s²).
    dt_s : float
        Sample interval (s).
    gain : float
        The filter's tuned gain (its registry ``gain_unit``).
    q_init : ndarray, shape (T, 4)
        Start attitude of each record.

    Returns
    -------
    ndarray, shape (T, N, 4)
        ``q_ws`` at each ``t_k``: :func:`run_attitude_filter`'s with ``q0=q_init``.

    Preconditions
    -------------
    The caller guarantees (not checked here): ``name`` a registered attitude filter; ``gyro_rad_s`` and
    ``accel_m_s2`` finite float64 arrays of one shape (T, N, 3) in rad/s (not deg/s) and m/s² (not g);
    ``dt_s`` and ``gain`` finite > 0; ``q_init`` unit quaternions (T, 4).

    Examples
    --------
    >>> acc = np.tile([0.0, 0.0, 9.80665], (2, 50, 1))
    >>> attitude_filter("mahony", np.zeros((2, 50, 3)), acc, 0.01, 1.0, levelled_start(acc, 10)).shape
    (2, 50, 4)
    """
    entry = get_filter(name)
    require_filter(name)
    return entry.run(gyro_rad_s, accel_m_s2, float(dt_s), float(gain), q_init)


def reference_difference(name: str, gyro_rad_s, accel_m_s2, dt_s: float, gain: float | None = None, *,
                         q0=None, init_samples: int = 100) -> float:
    """Largest |Δ| over all quaternion components between a filter's runner and its library reference.

    For an anchor computed by mtcal's compiled equivalent of an external library's loop
    (registry ``reference``), both run on the same records and start; the sign of each
    quaternion is taken as returned (both keep ``q0``'s hemisphere).

    Parameters
    ----------
    name, gyro_rad_s, accel_m_s2, dt_s, gain, q0, init_samples
        As :func:`run_attitude_filter`.

    Returns
    -------
    float
        ``max |q_run − q_reference|`` (dimensionless).

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> acc = np.tile([0.0, 0.0, 9.80665], (1, 300, 1)) + rng.normal(0, 0.05, (1, 300, 3))
    >>> gyr = rng.normal(0, 0.01, (1, 300, 3))
    >>> reference_difference("madgwick", gyr, acc, 0.01) < 1e-13
    True
    """
    run = run_attitude_filter(name, gyro_rad_s, accel_m_s2, dt_s, gain, q0=q0, init_samples=init_samples,
                              reference=False)
    ref = run_attitude_filter(name, gyro_rad_s, accel_m_s2, dt_s, gain, q0=q0, init_samples=init_samples,
                              reference=True)
    return float(np.max(np.abs(run - ref)))


@contextmanager
def reference_runs(*names: str):
    """Within the block, the named filters run their library reference (this process only).

    For checks that go through code which looks filters up by name (the sweep evaluators,
    :func:`mtcal.sweep.bakeoff.reference_check`); restored on exit, also on error.

    Examples
    --------
    >>> with reference_runs("madgwick"):
    ...     get_filter("madgwick").run is get_filter("madgwick").reference
    True
    >>> get_filter("madgwick").run is get_filter("madgwick").reference
    False
    """
    saved = [get_filter(n) for n in names]
    missing = [e.name for e in saved if e.reference is None]
    if missing:
        raise ValueError(f"filters without a reference runner: {missing}")
    try:
        for e in saved:
            _reregister(e, e.reference)
        yield
    finally:
        for e in saved:
            _reregister(e, e.run)


def _reregister(entry, run) -> None:
    register_filter(entry.name, run, output=entry.output, default_gain=entry.default_gain, gain_unit=entry.gain_unit,
                    origin=entry.origin, description=entry.description, requires=entry.requires,
                    reference=entry.reference, replace=True)


def run_axis_angle_filter(name: str, gyro_rad_s, accel_m_s2, dt_s: float, gain: float | None,
                          context: AxisContext, *, ref_index: int = 0, init_samples: int = 100) -> np.ndarray:
    """Angle (rad) about ``context.axis_s`` since sample ``ref_index``, for any registered filter, shape (T, N).

    An angle filter (``output="angle"``, e.g. the RAMS EKF) runs on the records and
    ``context``; an attitude filter's angle is the twist of its attitude about the
    axis (:func:`twist_angle_rad`). Both are referred to sample ``ref_index``.

    Parameters
    ----------
    name : str
        Any registered filter.
    gyro_rad_s, accel_m_s2 : array_like, shape (T, N, 3)
        Records (rad/s, m/s²).
    dt_s : float
        Sample interval (s).
    gain : float or None
        Tuned gain (None: the registry default).
    context : AxisContext
    ref_index : int
        Reference sample (angle 0).
    init_samples : int
        Levelling samples of an attitude filter.

    Returns
    -------
    ndarray, shape (T, N)

    Examples
    --------
    >>> acc = np.tile([0.0, 0.0, 9.80665], (1, 50, 1))
    >>> ctx = AxisContext(np.array([0.0, 1.0, 0.0]), np.ones((1, 50), bool), acc[:, 0], 1e-4, 1e-3)
    >>> th = run_axis_angle_filter("rams_ekf", np.zeros((1, 50, 3)), acc, 0.01, None, ctx)
    >>> th.shape, float(np.abs(th).max()) < 1e-6
    ((1, 50), True)
    """
    entry = get_filter(name)
    require_filter(name)
    if entry.output == "attitude":
        q = run_attitude_filter(name, gyro_rad_s, accel_m_s2, dt_s, gain, init_samples=init_samples)
        return _twist(q, as_float_array(context.axis_s, "axis_s", ndim=1, last_dim=3), ref_index)
    w = as_float_array(gyro_rad_s, "gyro_rad_s", ndim=3, last_dim=3, copy=False)
    a = as_float_array(accel_m_s2, "accel_m_s2", ndim=3, last_dim=3, copy=False)
    g = positive_scalar(entry.default_gain if gain is None else gain, "gain")
    theta = entry.run(w, a, positive_scalar(dt_s, "dt_s"), g, context)
    return theta - theta[:, ref_index:ref_index + 1]


def axis_angle_filter(name: str, gyro_rad_s: np.ndarray, accel_m_s2: np.ndarray, dt_s: float, gain: float,
                      context: AxisContext, ref_index: int, q_init: np.ndarray) -> np.ndarray:
    """Angle (rad) about ``context.axis_s`` since sample ``ref_index`` for any registered filter, shape (T, N).

    :func:`run_axis_angle_filter` without its checks, for records a caller made itself: an angle
    filter's runner on the records and ``context``, or the twist of an attitude filter's
    :func:`attitude_filter` about the axis (:func:`twist_angle_rad`'s operations, compiled).

    Parameters
    ----------
    name, gyro_rad_s, accel_m_s2, dt_s, context
        As :func:`run_axis_angle_filter` (the records float64 arrays).
    gain : float
        Tuned gain, resolved (not None).
    ref_index : int
        Reference sample (angle 0).
    q_init : ndarray, shape (T, 4)
        Start of an attitude filter (unused by an angle filter).

    Returns
    -------
    ndarray, shape (T, N)
        :func:`run_axis_angle_filter`'s angles.

    Preconditions
    -------------
    As :func:`attitude_filter` (not checked here), and ``context.axis_s`` a finite float (3,) array,
    ``0 <= ref_index < N``.

    Examples
    --------
    >>> acc = np.tile([0.0, 0.0, 9.80665], (1, 50, 1))
    >>> ctx = AxisContext(np.array([0.0, 1.0, 0.0]), np.ones((1, 50), bool), acc[:, 0], 1e-4, 1e-3)
    >>> th = axis_angle_filter("mahony", np.zeros((1, 50, 3)), acc, 0.01, 1.0, ctx, 0, levelled_start(acc, 10))
    >>> th.shape, float(np.abs(th).max())
    ((1, 50), 0.0)
    """
    entry = get_filter(name)
    if entry.output == "attitude":
        return _twist(attitude_filter(name, gyro_rad_s, accel_m_s2, dt_s, gain, q_init), context.axis_s,
                      ref_index)
    require_filter(name)
    theta = entry.run(gyro_rad_s, accel_m_s2, float(dt_s), float(gain), context)
    return theta - theta[:, ref_index:ref_index + 1]


def _twist(q: np.ndarray, v: np.ndarray, ref_index: int) -> np.ndarray:
    """Twist (rad) of ``q`` (T, N, 4) about ``v`` (3,) since sample ``ref_index`` (:func:`twist_angle_rad`)."""
    from mtcal.filters._kernels_twist import twist_rows

    # one compiled pass: twist_angle_rad's operations in its order, bit for bit, without its temporaries
    out = np.empty(q.shape[:2])
    twist_rows(np.ascontiguousarray(q, dtype=np.float64), int(ref_index),
               np.ascontiguousarray(v / np.linalg.norm(v), dtype=np.float64), out)
    return out


def _qncf(w, a, dt, gain, q0):
    from mtcal.filters.qncf import QncfParams, qncf

    return qncf(w, a, dt, QncfParams(kp_rad_s=gain, ki_rad_s2=gain / _KI_RATIO_S), q0=q0, return_euler=False).q_ws


def _mahony(w, a, dt, gain, q0):
    from mtcal.filters.mahony import MahonyParams, mahony_imu

    return mahony_imu(w, a, dt, MahonyParams(kp_rad_s=gain, ki_rad_s2=gain / _KI_RATIO_S), q0=q0).q_ws


def _per_record(runner):
    """Batch runner of a library that takes one record at a time."""
    def run(w, a, dt, gain, q0):
        out = np.empty(w.shape[:2] + (4,))
        for t in range(w.shape[0]):
            out[t] = runner(w[t], a[t], dt, gain, q0[t])
        return out
    return run


def _delayed(x: np.ndarray) -> np.ndarray:
    return np.concatenate([x[:1], x[:-1]], axis=0)


def _madgwick(w: np.ndarray, a: np.ndarray, dt: float, beta: float, q0: np.ndarray) -> np.ndarray:
    from ahrs.filters import Madgwick

    return Madgwick(gyr=_delayed(w), acc=_delayed(a), frequency=1.0 / dt, beta=beta, q0=q0.copy()).Q


def _madgwick_compiled(w: np.ndarray, a: np.ndarray, dt: float, beta: float, q0: np.ndarray) -> np.ndarray:
    """:func:`_madgwick` without the Python loop: ahrs' row t (inputs delayed) is the attitude before sample t."""
    from mtcal.filters.xio_ahrs import madgwick

    return madgwick(w, a, dt, beta, q0=q0 / np.linalg.norm(q0), timing="before", hold_zero_rate=True)[0]


def _vqf(w: np.ndarray, a: np.ndarray, dt: float, tau_acc_s: float, q0: np.ndarray) -> np.ndarray:
    import vqf

    filt = vqf.VQF(dt, tauAcc=tau_acc_s)
    state = filt.state
    state["accQuat"] = np.array(q0, dtype=float)
    filt.state = state
    # VQF's step k integrates a rate over [t_{k-1}, t_k] and corrects with the accelerometer at t_k
    gyr = np.concatenate([np.zeros((1, 3)), w[:-1]], axis=0)
    return filt.updateBatch(np.ascontiguousarray(gyr), np.ascontiguousarray(a))["quat6D"]


def _fusion(w: np.ndarray, a: np.ndarray, dt: float, gain: float, q0: np.ndarray) -> np.ndarray:
    import imufusion

    ahrs = imufusion.Ahrs()
    ahrs.set_settings(imufusion.AhrsSettings(sample_rate=1.0 / dt, convention=imufusion.CONVENTION_NWU,
                                             gain=gain, gyroscope_range=2000.0, acceleration_rejection=10.0,
                                             magnetic_rejection=0.0, rejection_timeout=int(round(5.0 / dt))))
    ahrs.skip_startup()
    ahrs.set_quaternion(np.array(q0, dtype=float))
    # imufusion: °/s and g, read as C floats ((float) of each double: round to nearest, as numpy's cast to
    # float32, so the rows are handed over already in float32: the same inputs, less than half the per-sample cost)
    gyro_deg_s = np.degrees(w).astype(np.float32)
    accel_g = (a / STANDARD_GRAVITY_M_S2).astype(np.float32)
    out = []
    keep, update, get = out.append, ahrs.update_no_magnetometer, ahrs.get_quaternion
    for g_k, a_k in zip(list(gyro_deg_s), list(accel_g)):
        keep(get())
        update(g_k, a_k)
    out = np.array(out, dtype=np.float64)                # float32 output (exact in float64) ...
    out /= np.linalg.norm(out, axis=-1, keepdims=True)   # ... renormalised in float64
    return out


def tilt_error_rad(q_est, q_true) -> np.ndarray:
    """Angle (rad) between the estimated and true "up" directions in the sensor frame, shape (...).

    Yaw-free: the attitude error left after removing any rotation about the
    vertical, i.e. the error an accelerometer-aided filter can be asked about.
    """
    qe = as_float_array(q_est, "q_est", last_dim=4, copy=False)
    qt = as_float_array(q_true, "q_true", last_dim=4, copy=False)
    ue, ut = _up_in_sensor(qe), _up_in_sensor(qt)
    cross = np.linalg.norm(np.cross(ue, ut), axis=-1)
    return np.arctan2(cross, np.sum(ue * ut, axis=-1))


def _up_in_sensor(q: np.ndarray) -> np.ndarray:
    """Third row of C(q): world z expressed in the sensor frame."""
    q0, q1, q2, q3 = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.stack([2.0 * (q1 * q3 - q0 * q2), 2.0 * (q2 * q3 + q0 * q1),
                     q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3], axis=-1)


def twist_angle_rad(q_ws, axis_s, ref_index: int = 0) -> np.ndarray:
    """Rotation angle about a sensor-fixed axis since sample ``ref_index`` (swing–twist), shape (..., N).

    ``q_rel = q_ws[ref]⁻¹ ⊗ q_ws[k]`` is the rotation in the sensor frame; its twist
    about the unit axis ``v`` is ``2 atan2(q_rel,vec · v, q_rel,0)`` (wrapped to (−π, π]).
    """
    q = as_float_array(q_ws, "q_ws", ndim=(2, 3), last_dim=4, copy=False)
    v = as_float_array(axis_s, "axis_s", ndim=1, last_dim=3)
    rel = rotations.hamilton(rotations.quat_conjugate(np.broadcast_to(q[..., ref_index:ref_index + 1, :], q.shape)), q)
    return rotations.wrap_angle(2.0 * np.arctan2(rel[..., 1:] @ (v / np.linalg.norm(v)), rel[..., 0]))


# --------------------------------------------------------------------------- the registry's runners
# declared in mtcal.filters.registry.BUILTIN_FILTERS (by module and function, imported on first call)
_madgwick_batch = _per_record(_madgwick_compiled)
_madgwick_ahrs_batch = _per_record(_madgwick)
_vqf_batch = _per_record(_vqf)
_fusion_batch = _per_record(_fusion)
