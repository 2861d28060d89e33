"""IMU simulator: exact truth kinematics plus a MEMS sensor error model.

Hardware is replaced by simulation with known truth (docs/conventions.md). A
:class:`Trajectory` holds the body attitude history ``q_wb`` (scalar-first,
body → world) and the linear acceleration of the sensor point; a
:class:`ImuErrorModel` holds the sensor errors; :func:`simulate_imu` draws one
or many Monte Carlo trials keyed by a seeded ``numpy.random.Generator``.

Truth kinematics
----------------
The world frame is z-up with gravity ``g_w = [0, 0, −9.80665] m/s²`` by
default, so a level accelerometer at rest reads ``[0, 0, +g]``.

* Gyro (body-frame rate, rad/s). Sample ``k`` is the *mean rate over the
  interval* ``[t_k, t_{k+1}]``: ``ω_k = rotvec(q_k⁻¹ ⊗ q_{k+1}) / Δt_k`` — what
  an integrating (angular-increment) gyro reports. Integrating it with wang2023cja
  Eq 6–7 (``q_{k+1} = q_k ⊗ q(ω_k Δt)``) reproduces the attitude to rounding
  error. The last sample repeats the last interval.
* Accelerometer (specific force, m/s²): ``f_b = C_wbᵀ (a_w − g_w)`` at each
  sample.

Sensor error model (per axis, per sensor; units of the sensor)
--------------------------------------------------------------
``y = (I + S + M) x_true + b_const + b_turn_on + b_warm-up(t) + b_RW(t)
+ b_GM(t) + n_white + vibration``, then quantised; with

* ``S`` diagonal scale-factor error, ``M`` misalignment (off-diagonal);
* ``b_turn_on ~ N(0, bias_sigma²)`` once per trial;
* ``b_warm-up(t) = warmup_bias · exp(−(t + t_on)/warmup_tau_s)`` (bias
  settling after power-on; ``t_on`` = time already powered, e.g. 300 s);
* ``b_RW``: random walk with density ``bias_random_walk`` (unit/s/√Hz, i.e.
  the rate random walk K of an Allan plot: σ_A(τ) = K √(τ/3));
* ``b_GM``: first-order Gauss–Markov bias instability, 1σ
  ``bias_instability`` and correlation time ``bias_instability_tau_s``;
* ``n_white``: density ``noise_density`` (unit/√Hz): per-sample standard
  deviation ``noise_density · √fs`` (Allan σ_A(τ) = N/√τ);
* vibration: sinusoid ``amplitude · sin(2π f t + φ)``, φ uniform per trial
  and axis.

Random numbers (changed: numpy PCG64 streams → counter-based Philox4x32-10)
---------------------------------------------------------------------------
Every draw is a Philox4x32-10 number addressed by its coordinates
(:mod:`mtcal.core.philox`, key rule in :mod:`mtcal.core.rng`): the key is hashed once
from ``rng`` (:func:`mtcal.core.rng.spawn_philox_key`), the counter holds the sample pair
``k // 2``, the trial id, the stream word (sensor, error source, axis) and the draw index.
Normals are ziggurat normals, uniforms 53-bit. Hence

* switching one source on or off leaves the others' draws unchanged (common random
  numbers for error-budget tables);
* the output is the same for any chunk size (:class:`ImuStream`), kernel block size,
  thread count or worker;
* trial ``t``'s numbers do not depend on which other trials run: pass ``trial_ids`` to
  simulate a subset (a worker's share) of a larger run.

Until issue #24 the simulator drew from numpy ``Generator`` (PCG64) streams; every
Monte Carlo number of the suite moved within its band when the streams changed.

Two engines produce bit-identical output (tested): ``"numba"`` (default) draws the
noise inside one compiled kernel, trials in parallel (``prange``), where it is
consumed — per trial, a block of Philox words in a branch-free loop, the ziggurat, then
every error term, the bias random walk and the Gauss–Markov recursion in the
reference's operation order — never materialising per-sample noise arrays;
``"numpy"`` is the readable reference (a numpy Philox and ziggurat, array operations,
``np.cumsum``, ``scipy.signal.lfilter``).
"""

from __future__ import annotations

import math
import sys
import threading
from dataclasses import dataclass, field

import numba
import numpy as np
from numba import prange

from mtcal.core import _rotation_kernels, philox, rotations
from mtcal.core.compiled import jit
from mtcal.core.rng import spawn_philox_key
from mtcal.core.validate import (STANDARD_GRAVITY_M_S2, as_float_array, positive_int,
                             positive_scalar, time_vector, unit_quaternion)

__all__ = ["Trajectory", "SensorErrors", "ImuErrorModel", "ImuRecord", "ImuStream", "body_rates",
           "specific_force", "simulate_imu", "apply_sensor_errors", "integrate_gyro", "tilted_trajectory",
           "TiltedTrajectories", "GRAVITY_W_M_S2", "fill_streams", "fill_streams_grouped", "noise_mismatch",
           "load_tilt_outputs", "gravity_lateral_axis", "RecordPiece", "RecordSource"]

#: Default world gravity vector, z-up frame (m/s²).
GRAVITY_W_M_S2 = (0.0, 0.0, -STANDARD_GRAVITY_M_S2)

_SOURCES = ("turn_on", "white", "random_walk", "instability", "vibration")


def _frozen(arr: np.ndarray) -> np.ndarray:
    arr.setflags(write=False)
    return arr


def uniform_dt(time_s: np.ndarray, name: str = "time_s") -> float:
    """Sample interval of a uniformly sampled time vector (relative jitter < 1e-6)."""
    dt = np.diff(time_s)
    mean_dt = float(np.mean(dt))
    if np.max(np.abs(dt - mean_dt)) > 1e-6 * mean_dt:
        raise ValueError(f"{name} must be uniformly sampled (noise density is scaled by "
                         f"the sample rate); got dt in [{dt.min():.6g}, {dt.max():.6g}] s")
    return mean_dt


@dataclass(frozen=True)
class Trajectory:
    """Truth motion of the body carrying the IMU.

    Parameters
    ----------
    time_s : array_like, shape (N,)
        Strictly increasing, uniformly sampled time in s.
    q_wb : array_like, shape (N, 4)
        Scalar-first unit quaternion of the body attitude (body → world).
    accel_w_m_s2 : array_like, shape (N, 3), optional
        Linear acceleration of the sensor point in the world frame (m/s²);
        zero (no translation) by default.
    """

    time_s: np.ndarray
    q_wb: np.ndarray
    accel_w_m_s2: np.ndarray | None = None

    def __post_init__(self) -> None:
        t = time_vector(self.time_s)
        q = unit_quaternion(self.q_wb, "q_wb", copy=False)   # only read: _continuous returns a new array
        if q.ndim != 2 or q.shape[0] != t.size:
            raise ValueError(f"q_wb must have shape ({t.size}, 4) to match time_s, got {q.shape}")
        acc = (np.zeros((t.size, 3)) if self.accel_w_m_s2 is None
               else as_float_array(self.accel_w_m_s2, "accel_w_m_s2", ndim=2, last_dim=3))
        if acc.shape[0] != t.size:
            raise ValueError(f"accel_w_m_s2 must have shape ({t.size}, 3), got {acc.shape}")
        uniform_dt(t)
        object.__setattr__(self, "time_s", _frozen(t))
        object.__setattr__(self, "q_wb", _frozen(_continuous(q)))
        object.__setattr__(self, "accel_w_m_s2", _frozen(acc))
        object.__setattr__(self, "_truth", {})   # memo of :func:`_truth_outputs` (not a field: eq/repr ignore it)

    def __getstate__(self) -> dict:
        return {k: v for k, v in self.__dict__.items() if k != "_truth"}   # pickles carry no memo

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)
        self.__dict__["_truth"] = {}

    @property
    def dt_s(self) -> float:
        """Sample interval (s)."""
        return float(self.time_s[1] - self.time_s[0])

    @property
    def fs_hz(self) -> float:
        """Sample rate (Hz)."""
        return 1.0 / uniform_dt(self.time_s)

    def __len__(self) -> int:
        return int(self.time_s.size)


def _continuous(q: np.ndarray) -> np.ndarray:
    """``rotations.make_continuous(q, axis=0)`` of a checked (N, 4) float64 array, always a new array.

    A large array goes straight to the compiled loop make_continuous runs (no copy, no re-check)."""
    if q.dtype == np.float64 and q.ndim == 2 and q.shape[0] >= rotations._KERNEL_MIN_ROWS:
        out = np.empty((q.shape[0], 1, 4))
        rotations._kernels().continuous3(q.reshape(q.shape[0], 1, 4), out)
        return out.reshape(q.shape[0], 4)
    return rotations.make_continuous(q, axis=0)


@jit
def _relative_unit(q, i):  # pragma: no cover - compiled
    """Sign-aligned ``normalize(conj(q_i) ⊗ q_{i+1})`` of the (N, 4) quaternions ``q``: the operations of
    ``quat_conjugate`` (× −1), ``hamilton``, ``quat_normalize`` and ``rotvec_from_quat``'s sign alignment."""
    p0, p1, p2, p3 = q[i, 0], q[i, 1] * -1.0, q[i, 2] * -1.0, q[i, 3] * -1.0
    q0, q1, q2, q3 = q[i + 1, 0], q[i + 1, 1], q[i + 1, 2], q[i + 1, 3]
    d0 = p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3
    d1 = p0 * q1 + p1 * q0 + p2 * q3 - p3 * q2
    d2 = p0 * q2 - p1 * q3 + p2 * q0 + p3 * q1
    d3 = p0 * q3 + p1 * q2 - p2 * q1 + p3 * q0
    n = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2 + d3 * d3)
    d0, d1, d2, d3 = d0 / n, d1 / n, d2 / n, d3 / n
    if d0 < 0.0:
        d0, d1, d2, d3 = -d0, -d1, -d2, -d3
    return d0, d1, d2, d3


@jit
def _relative_rotations(q, qf, vnorm):  # pragma: no cover - compiled
    """Sign-aligned ``qf = normalize(conj(q_k) ⊗ q_{k+1})`` (M = N − 1 rows) and ``vnorm = |qf[1:]|``.

    The operations of ``quat_conjugate`` (× −1), ``hamilton``, ``quat_normalize`` and
    ``rotvec_from_quat``'s sign alignment, fused into one pass (mtcal.core._rotation_kernels).
    """
    for i in range(qf.shape[0]):
        d0, d1, d2, d3 = _relative_unit(q, i)
        qf[i, 0], qf[i, 1], qf[i, 2], qf[i, 3] = d0, d1, d2, d3
        vnorm[i] = np.sqrt(d1 * d1 + d2 * d2 + d3 * d3)


@jit
def _rates_finish(qf, vnorm, angle, time_s, out):  # pragma: no cover - compiled
    """``out[k] = rotvec_k / (t_{k+1} − t_k)`` (``rotvec_from_quat``'s finish), last row repeated."""
    m = qf.shape[0]
    for i in range(m):
        k = 2.0 if vnorm[i] < 1e-12 else angle[i] / vnorm[i]
        dt = time_s[i + 1] - time_s[i]
        out[i, 0] = (k * qf[i, 1]) / dt
        out[i, 1] = (k * qf[i, 2]) / dt
        out[i, 2] = (k * qf[i, 3]) / dt
    for c in range(3):
        out[m, c] = out[m - 1, c]


@jit
def _specific_force_kernel(q, v, out):  # pragma: no cover - compiled
    """``out[n] = C(q_n)ᵀ v_n``: ``quat_to_matrix``'s arithmetic, then einsum's ``0 + Σ_j C_ji v_j`` (j in order)."""
    for i in range(q.shape[0]):
        c00, c10, c20, c01, c11, c21, c02, c12, c22 = _rotation_kernels.dcm_entries(q[i, 0], q[i, 1], q[i, 2],
                                                                                   q[i, 3])
        v0, v1, v2 = v[i, 0], v[i, 1], v[i, 2]
        out[i, 0] = ((0.0 + c00 * v0) + c10 * v1) + c20 * v2
        out[i, 1] = ((0.0 + c01 * v0) + c11 * v1) + c21 * v2
        out[i, 2] = ((0.0 + c02 * v0) + c12 * v1) + c22 * v2


def body_rates(trajectory: Trajectory) -> np.ndarray:
    """Interval-mean body rates ``ω_k = rotvec(q_k⁻¹ ⊗ q_{k+1}) / Δt`` (rad/s), shape (N, 3)."""
    q = trajectory.q_wb
    if q.shape[0] - 1 >= rotations._KERNEL_MIN_ROWS:   # fused passes, bit-identical to the expression below
        m = q.shape[0] - 1
        qf, vnorm = np.empty((m, 4)), np.empty(m)
        _relative_rotations(q, qf, vnorm)
        out = np.empty((m + 1, 3))
        _rates_finish(qf, vnorm, 2.0 * np.arctan2(vnorm, qf[:, 0]), trajectory.time_s, out)
        return out
    dq = rotations.quat_multiply(rotations.quat_conjugate(q[:-1]), q[1:])
    omega = rotations.rotvec_from_quat(rotations.quat_normalize(dq)) / np.diff(trajectory.time_s)[:, None]
    return np.concatenate([omega, omega[-1:]], axis=0)


def specific_force(trajectory: Trajectory, gravity_w_m_s2=GRAVITY_W_M_S2) -> np.ndarray:
    """Specific force in the body frame ``f_b = C_wbᵀ (a_w − g_w)`` (m/s²), shape (N, 3)."""
    g = as_float_array(gravity_w_m_s2, "gravity_w_m_s2", ndim=1, last_dim=3)
    if len(trajectory) >= rotations._KERNEL_MIN_ROWS:   # one pass, bit-identical to the einsum below
        out = np.empty((len(trajectory), 3))
        _specific_force_kernel(trajectory.q_wb, trajectory.accel_w_m_s2 - g, out)
        return out
    c_wb = rotations.quat_to_matrix(trajectory.q_wb)
    return np.einsum("nji,nj->ni", c_wb, trajectory.accel_w_m_s2 - g)


def _rows_at(a: np.ndarray, m: np.ndarray) -> np.ndarray:
    """``a @ m`` for rows ``a`` (..., 3) and a (3, 3) matrix, the same numbers: a large C-contiguous float64
    ``a`` through one compiled pass (:func:`mtcal.core._rotation_kernels.rows_times_matrix3`, ~10× faster
    than the BLAS call on such thin arrays), otherwise the matmul itself."""
    if a.dtype == np.float64 and a.flags.c_contiguous and a.size >= 3 * rotations._KERNEL_MIN_ROWS:
        out = np.empty(a.shape)
        _rotation_kernels.rows_times_matrix3(a.reshape(-1, 3), np.ascontiguousarray(m, dtype=float),
                                             out.reshape(-1, 3))
        return out
    return a @ m


def _truth_outputs(trajectory: Trajectory, gravity_w_m_s2) -> tuple[np.ndarray, np.ndarray]:
    """Read-only :func:`body_rates` and :func:`specific_force` of ``trajectory``, computed once per Trajectory.

    A Trajectory is frozen (its arrays are read-only), so simulating the same object again (sweeps,
    blocks of trials on a shared truth) reuses its truth outputs; the memo keeps the last gravity only.
    """
    g = as_float_array(gravity_w_m_s2, "gravity_w_m_s2", ndim=1, last_dim=3)
    memo = trajectory._truth
    if "rates" not in memo:
        memo["rates"] = _frozen(body_rates(trajectory))
    key = g.tobytes()
    if memo.get("gravity") != key:
        memo["force"], memo["gravity"] = _frozen(specific_force(trajectory, g)), key
    return memo["rates"], memo["force"]


@jit
def _tilted_truth_kernel(q_base, axis, gain, time_s, v, q_out, rates, force):  # pragma: no cover - compiled
    """One pass per output of :func:`tilted_trajectory`, with the operations of the expressions it replaces.

    ``q_out = continuous(q_base ⊗ quat_from_rotvec(gain · axis))`` (``rotvec_angle``, sin/cos of the
    half angle, ``quat_from_rotvec_finish``, ``hamilton3``, ``continuous3``; a row whose axis equals
    the previous one reuses its rotation quaternion: equal inputs, equal outputs), then
    :func:`body_rates` (``_relative_rotations``, ``2·atan2``, ``_rates_finish``) and
    :func:`specific_force` (``_specific_force_kernel`` with ``v = accel_w − g``).
    """
    n = q_base.shape[0]
    r0 = r1 = r2 = 0.0
    c = x = y = z = 0.0
    a0 = a1 = a2 = a3 = 0.0
    flip = False
    for i in range(n):
        if i == 0 or not (axis[i, 0] == axis[i - 1, 0] and axis[i, 1] == axis[i - 1, 1]
                          and axis[i, 2] == axis[i - 1, 2]):
            r0, r1, r2 = gain * axis[i, 0], gain * axis[i, 1], gain * axis[i, 2]
            ang = np.sqrt(r0 * r0 + r1 * r1 + r2 * r2)
            half = 0.5 * ang
            k = 0.5 - ang * ang / 48.0 if ang < 1e-8 else np.sin(half) / ang
            c, x, y, z = np.cos(half), k * r0, k * r1, k * r2
        p0, p1, p2, p3 = q_base[i, 0], q_base[i, 1], q_base[i, 2], q_base[i, 3]
        b0 = p0 * c - p1 * x - p2 * y - p3 * z
        b1 = p0 * x + p1 * c + p2 * z - p3 * y
        b2 = p0 * y - p1 * z + p2 * c + p3 * x
        b3 = p0 * z + p1 * y - p2 * x + p3 * c
        if i > 0 and b0 * a0 + b1 * a1 + b2 * a2 + b3 * a3 < 0.0:
            flip = not flip
        a0, a1, a2, a3 = b0, b1, b2, b3
        if flip:
            q_out[i, 0], q_out[i, 1], q_out[i, 2], q_out[i, 3] = -b0, -b1, -b2, -b3
        else:
            q_out[i, 0], q_out[i, 1], q_out[i, 2], q_out[i, 3] = b0, b1, b2, b3
    for i in range(n - 1):
        d0, d1, d2, d3 = _relative_unit(q_out, i)
        vn = np.sqrt(d1 * d1 + d2 * d2 + d3 * d3)
        k = 2.0 if vn < 1e-12 else (2.0 * np.arctan2(vn, d0)) / vn
        dt = time_s[i + 1] - time_s[i]
        rates[i, 0] = (k * d1) / dt
        rates[i, 1] = (k * d2) / dt
        rates[i, 2] = (k * d3) / dt
    for j in range(3):
        rates[n - 1, j] = rates[n - 2, j]
    v0, v1, v2 = v[0], v[1], v[2]
    for i in range(n):
        c00, c10, c20, c01, c11, c21, c02, c12, c22 = _rotation_kernels.dcm_entries(q_out[i, 0], q_out[i, 1],
                                                                                   q_out[i, 2], q_out[i, 3])
        force[i, 0] = ((0.0 + c00 * v0) + c10 * v1) + c20 * v2
        force[i, 1] = ((0.0 + c01 * v0) + c11 * v1) + c21 * v2
        force[i, 2] = ((0.0 + c02 * v0) + c12 * v1) + c22 * v2


def tilted_trajectory(time_s, q_base, axis, gain: float, gravity_w_m_s2=GRAVITY_W_M_S2) -> Trajectory:
    """A base attitude tilted by ``gain · axis(t)``, with its truth outputs computed in one pass.

    ``Trajectory(time_s, hamilton(q_base, quat_from_rotvec(gain · axis)))`` — e.g. a compliant
    mount that tilts by ``gain`` rad per unit of a load direction ``axis`` — whose :func:`body_rates`
    and :func:`specific_force` (no translation, ``gravity_w_m_s2``) are computed in the same
    compiled pass and kept on the returned Trajectory (:func:`simulate_imu` reuses them). The
    numbers are those of the expressions, bit for bit (a sample whose axis equals the previous
    one reuses its rotation quaternion). A Monte Carlo whose trials differ only in ``gain`` shares
    ``q_base`` and ``axis``.

    Parameters
    ----------
    time_s : array_like, shape (N,)
        Uniformly sampled, strictly increasing time (s).
    q_base : array_like, shape (N, 4)
        Scalar-first unit quaternions of the untilted body attitude (body → world).
    axis : array_like, shape (N, 3)
        Tilt direction and size per unit gain, body axes (rad per unit gain).
    gain : float
        Tilt gain (0: the base attitude itself).
    gravity_w_m_s2 : 3-vector
        World gravity (m/s²) of the specific force kept on the trajectory.

    Returns
    -------
    Trajectory

    References
    ----------
    wang2023cja §4.1 (compliant gasket mounts tilt with the lateral load).

    Examples
    --------
    >>> t = np.arange(5000) * 1e-3
    >>> q = np.tile([1.0, 0.0, 0.0, 0.0], (t.size, 1))
    >>> axis = np.tile([0.0, 1.0, 0.0], (t.size, 1))
    >>> traj = tilted_trajectory(t, q, axis, 0.01)
    >>> bool(np.allclose(traj.q_wb[0], [np.cos(0.005), 0.0, np.sin(0.005), 0.0]))
    True
    """
    return TiltedTrajectories(time_s, q_base, axis, gravity_w_m_s2)(gain)


class TiltedTrajectories:
    """The trajectories of :func:`tilted_trajectory` of one base for any gain, the inputs checked once.

    ``TiltedTrajectories(time_s, q_base, axis)(gain)`` is ``tilted_trajectory(time_s, q_base, axis, gain)``,
    bit for bit. A Monte Carlo whose trials differ only in the gain (a compliant mount per trial) builds
    one and calls it per trial: the shared time, attitude and axis are checked on construction, not
    per trial.

    Parameters
    ----------
    time_s, q_base, axis, gravity_w_m_s2
        As for :func:`tilted_trajectory` (shapes (N,), (N, 4), (N, 3), (3,); s, unit quaternions,
        rad per unit gain, m/s²).

    Examples
    --------
    >>> t = np.arange(5000) * 1e-3
    >>> family = TiltedTrajectories(t, np.tile([1.0, 0.0, 0.0, 0.0], (t.size, 1)), np.tile([0.0, 1.0, 0.0], (t.size, 1)))
    >>> bool(np.array_equal(family(0.01).q_wb, tilted_trajectory(t, family.q_base, family.axis, 0.01).q_wb))
    True
    """

    def __init__(self, time_s, q_base, axis, gravity_w_m_s2=GRAVITY_W_M_S2):
        t = time_vector(time_s)
        q = unit_quaternion(q_base, "q_base", copy=False)
        ax = as_float_array(axis, "axis", ndim=2, last_dim=3)
        if q.ndim != 2 or q.shape[0] != t.size or ax.shape[0] != t.size:
            raise ValueError(f"q_base (N, 4) and axis (N, 3) must match time_s (N = {t.size}), "
                             f"got {q.shape} and {ax.shape}")
        self._compiled = t.size - 1 >= max(rotations._KERNEL_MIN_ROWS, 1)
        self._gravity = None
        if self._compiled:          # one compiled pass per gain (the truth outputs kept on the trajectory)
            self._gravity = as_float_array(gravity_w_m_s2, "gravity_w_m_s2", ndim=1, last_dim=3)
            uniform_dt(t)
            t = t if not t.flags.writeable else _frozen(t.copy())
        self.time_s, self.q_base, self.axis = t, q, ax

    def __call__(self, gain: float) -> Trajectory:
        """The base tilted by ``gain · axis(t)`` (``gain`` finite; 0: the base attitude itself)."""
        gain = float(gain)
        if not np.isfinite(gain):
            raise ValueError(f"gain must be finite, got {gain}")
        t, q = self.time_s, self.q_base
        if not self._compiled or gain == 0.0:
            return Trajectory(t, q if gain == 0.0 else rotations.hamilton(q, rotations.quat_from_rotvec(gain * self.axis)))
        n = t.size
        q_out, rates, force = np.empty((n, 4)), np.empty((n, 3)), np.empty((n, 3))
        _tilted_truth_kernel(q, self.axis, gain, t, 0.0 - self._gravity, q_out, rates, force)
        traj = object.__new__(Trajectory)
        object.__setattr__(traj, "time_s", t)
        object.__setattr__(traj, "q_wb", _frozen(q_out))
        object.__setattr__(traj, "accel_w_m_s2", _frozen(np.zeros((n, 3))))
        object.__setattr__(traj, "_truth", {"rates": _frozen(rates), "force": _frozen(force),
                                            "gravity": self._gravity.tobytes()})
        return traj


def integrate_gyro(q0, gyro_rad_s, dt_s: float) -> np.ndarray:
    """wang2023cja Eq 6–7 without correction: ``Q_{k+1} = Q_k ⊗ q(ω_k Δt)``.

    Parameters
    ----------
    q0 : array_like, shape (4,) or (T, 4)
        Initial scalar-first unit quaternion(s).
    gyro_rad_s : array_like, shape (N, 3) or (T, N, 3)
        Body rates (rad/s); sample k acts over ``[t_k, t_{k+1}]``.
    dt_s : float
        Sample interval (s).

    Returns
    -------
    ndarray, shape (N, 4) or (T, N, 4)
        Attitude at every sample time (``Q_0 = q0``).
    """
    dt = positive_scalar(dt_s, "dt_s")
    w = as_float_array(gyro_rad_s, "gyro_rad_s", ndim=(2, 3), last_dim=3)
    q = unit_quaternion(q0, "q0")
    inc = rotations.quat_from_rotvec(w * dt)
    out = np.empty(w.shape[:-1] + (4,))
    out[..., 0, :] = q
    for k in range(w.shape[-2] - 1):  # recursive: loop over time, vectorised over trials
        out[..., k + 1, :] = rotations.hamilton(out[..., k, :], inc[..., k, :])
    return out


def _vec3(value, name: str) -> np.ndarray:
    arr = as_float_array(value, name)
    if arr.shape not in ((), (3,)):
        raise ValueError(f"{name} must be a scalar or a 3-vector, got shape {arr.shape}")
    return np.broadcast_to(arr, (3,)).copy()


@dataclass(frozen=True)
class SensorErrors:
    """Error parameters of one sensor triad, in the sensor's unit ``u`` (rad/s or m/s²).

    Parameters
    ----------
    bias : float or 3-tuple
        Constant bias (u).
    bias_sigma : float
        1σ of the turn-on bias drawn once per trial (u).
    noise_density : float
        White-noise density (u/√Hz); gyro: angle random walk in rad/s/√Hz.
    bias_random_walk : float
        Bias random-walk density (u/s/√Hz = u/√s); gyro: rate random walk.
    bias_instability : float
        1σ of the first-order Gauss–Markov bias (u).
    bias_instability_tau_s : float
        Correlation time of that bias (s).
    warmup_bias : float or 3-tuple
        Extra bias at power-on (u), decaying with ``warmup_tau_s``.
    warmup_tau_s : float
        Warm-up settling time constant (s).
    scale_factor : float or 3-tuple
        Scale-factor error (dimensionless, 1e-3 = 1000 ppm).
    misalignment : 3×3 nested tuple
        Off-diagonal misalignment (rad, diagonal ignored).
    quantization : float
        Output resolution (u); 0 for none.
    vibration_amplitude : float or 3-tuple
        Sinusoidal vibration amplitude (u).
    vibration_freq_hz : float
        Vibration frequency (Hz).
    """

    bias: float | tuple = 0.0
    bias_sigma: float = 0.0
    noise_density: float = 0.0
    bias_random_walk: float = 0.0
    bias_instability: float = 0.0
    bias_instability_tau_s: float = 100.0
    warmup_bias: float | tuple = 0.0
    warmup_tau_s: float = 60.0
    scale_factor: float | tuple = 0.0
    misalignment: tuple = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    quantization: float = 0.0
    vibration_amplitude: float | tuple = 0.0
    vibration_freq_hz: float = 0.0

    def __post_init__(self) -> None:
        for name in ("bias_sigma", "noise_density", "bias_random_walk", "bias_instability",
                     "quantization", "vibration_freq_hz"):
            positive_scalar(getattr(self, name), name, allow_zero=True)
        for name in ("bias_instability_tau_s", "warmup_tau_s"):
            positive_scalar(getattr(self, name), name)
        for name in ("bias", "warmup_bias", "scale_factor", "vibration_amplitude"):
            _vec3(getattr(self, name), name)
        mis = as_float_array(self.misalignment, "misalignment")
        if mis.shape != (3, 3):
            raise ValueError(f"misalignment must be 3x3, got shape {mis.shape}")

    def matrix(self) -> np.ndarray:
        """``I + S + M``: scale factor on the diagonal, misalignment off it."""
        mis = np.array(self.misalignment, dtype=float)
        np.fill_diagonal(mis, 0.0)
        return np.eye(3) + np.diag(_vec3(self.scale_factor, "scale_factor")) + mis


@dataclass(frozen=True)
class ImuErrorModel:
    """Error model of a whole IMU plus its mounting on the body.

    Parameters
    ----------
    gyro : SensorErrors
        Gyro errors in rad/s units.
    accel : SensorErrors
        Accelerometer errors in m/s² units.
    q_mount : 4-tuple
        Scalar-first quaternion ``q_bs`` of the sensor frame relative to the
        body (``v_b = C(q_bs) v_s``); identity by default.
    time_since_power_on_s : float
        Time the IMU has been on when the record starts (s); 300 s = the
        5-minute warm-up of wang2023cja.
    """

    gyro: SensorErrors = field(default_factory=SensorErrors)
    accel: SensorErrors = field(default_factory=SensorErrors)
    q_mount: tuple = (1.0, 0.0, 0.0, 0.0)
    time_since_power_on_s: float = 0.0

    def __post_init__(self) -> None:
        for name in ("gyro", "accel"):
            if not isinstance(getattr(self, name), SensorErrors):
                raise TypeError(f"{name} must be a SensorErrors, got {type(getattr(self, name)).__name__}")
        q = unit_quaternion(self.q_mount, "q_mount")
        if q.shape != (4,):
            raise ValueError(f"q_mount must have shape (4,), got {q.shape}")
        positive_scalar(self.time_since_power_on_s, "time_since_power_on_s", allow_zero=True)
        if self.accel.noise_density > 1.0 or np.max(np.abs(_vec3(self.accel.bias, "bias"))) > 5.0:
            raise ValueError("accel errors look too large for m/s² (noise_density > 1 m/s²/√Hz or "
                             "|bias| > 5 m/s²); were they given in the wrong unit?")
        if self.gyro.noise_density > 0.1 or np.max(np.abs(_vec3(self.gyro.bias, "bias"))) > 1.0:
            raise ValueError("gyro errors look too large for rad/s (noise_density > 0.1 rad/s/√Hz or "
                             "|bias| > 1 rad/s); were degrees passed as radians?")


@dataclass(frozen=True)
class ImuRecord:
    """Simulated IMU output. Arrays are (N, 3) for one trial or (T, N, 3) for many.

    Attributes
    ----------
    time_s : ndarray (N,)
    gyro_rad_s : ndarray
        Body rates in the sensor frame (rad/s).
    accel_m_s2 : ndarray
        Specific force in the sensor frame (m/s²).
    q_ws_true : ndarray (N, 4)
        True sensor attitude (sensor → world), scalar-first.
    gyro_true_rad_s, accel_true_m_s2 : ndarray (N, 3)
        Error-free sensor outputs.
    """

    time_s: np.ndarray
    gyro_rad_s: np.ndarray
    accel_m_s2: np.ndarray
    q_ws_true: np.ndarray
    gyro_true_rad_s: np.ndarray
    accel_true_m_s2: np.ndarray


# ----------------------------------------------------------------------------- counter-based draws
_SENSOR_SOURCES = ("white", "random_walk", "instability")  # per-sample normal streams, flags 4, 8, 16


def _stream_words(sensor_index: int, source: str) -> tuple[int, int, int]:
    """Counter word ``c2`` of each axis of one sensor's error source (:func:`mtcal.core.philox.stream_word`)."""
    return tuple(philox.stream_word(sensor_index, philox.SOURCE_IDS[source], j) for j in range(3))


# numpy reference of the draws: the same Philox words and ziggurat, array by array
def _np_philox_words(c0, c1, c2, c3, k0: int, k1: int):
    """Philox4x32-10 on broadcast uint64 arrays of 32-bit words → lane-0 and lane-1 64-bit words."""
    m0, m1, mask, s32 = np.uint64(0xD2511F53), np.uint64(0xCD9E8D57), np.uint64(0xFFFFFFFF), np.uint64(32)
    c0, c1, c2, c3 = np.broadcast_arrays(*(np.asarray(c, dtype=np.uint64) for c in (c0, c1, c2, c3)))
    ka, kb = np.uint64(k0), np.uint64(k1)
    for r in range(10):
        if r:
            ka = np.uint64((int(ka) + 0x9E3779B9) & 0xFFFFFFFF)
            kb = np.uint64((int(kb) + 0xBB67AE85) & 0xFFFFFFFF)
        p0, p1 = m0 * c0, m1 * c2
        c0, c1, c2, c3 = (p1 >> s32) ^ c1 ^ ka, p1 & mask, (p0 >> s32) ^ c3 ^ kb, p0 & mask
    return c0 | (c1 << s32), c2 | (c3 << s32)


def _np_uniform(w):
    return (w >> np.uint64(11)).astype(np.int64).astype(np.float64) * 2.0 ** -53


def _py_zig_slow(r: int, c0: int, c1: int, c2: int, lane: int, k0: int, k1: int) -> float:
    """Ziggurat after a rejected first word, on the rejection stream (plain Python ints, the reference)."""
    j = 0

    def words():
        nonlocal j
        a, b = _np_philox_words(c0, c1, c2, 1 + lane + 2 * j, k0, k1)
        j += 1
        return int(a), int(b)

    def unif(w: int) -> float:
        return float(w >> 11) * 2.0 ** -53

    while True:
        idx, r8 = r & 0xFF, r >> 8
        rabs = (r8 >> 1) & 0x000FFFFFFFFFFFFF
        x = float(rabs) * float(philox.WI[idx])
        if r8 & 1:
            x = -x
        if rabs < int(philox.KI[idx]):
            return x
        if idx == 0:
            while True:
                a, b = words()
                xx = -philox._INV_R * math.log1p(-unif(a))
                yy = -math.log1p(-unif(b))
                if yy + yy > xx * xx:
                    return -(philox._R + xx) if (rabs >> 8) & 1 else philox._R + xx
        a, b = words()
        f_lo, f_hi = float(philox.FI[idx]), float(philox.FI[idx - 1])
        if (f_hi - f_lo) * unif(a) + f_lo < math.exp(-0.5 * x * x):
            return x
        r = b


def _np_ziggurat(words, c0, c1, c2: int, lane: int, k0: int, k1: int) -> np.ndarray:
    """Standard normals of 64-bit ``words`` (any shape; ``c0``, ``c1`` broadcast to it)."""
    idx = (words & np.uint64(0xFF)).astype(np.intp)
    r8 = words >> np.uint64(8)
    rabs = (r8 >> np.uint64(1)) & np.uint64(0x000FFFFFFFFFFFFF)
    x = rabs.astype(np.int64).astype(np.float64) * philox.WI[idx]
    x = np.where((r8 & np.uint64(1)).astype(bool), -x, x)
    c0, c1 = np.broadcast_to(c0, words.shape), np.broadcast_to(c1, words.shape)
    for pos in zip(*np.nonzero(rabs >= philox.KI[idx])):
        x[pos] = _py_zig_slow(int(words[pos]), int(c0[pos]), int(c1[pos]), c2, lane, k0, k1)
    return x


def _np_normals(key, trial_ids, c2: int, start: int, stop: int) -> np.ndarray:
    """Reference normals (T, stop − start) of samples [start, stop): pair ``k // 2``, lane ``k % 2``."""
    m = np.arange(start // 2, (stop - 1) // 2 + 1, dtype=np.uint64)[None, :]
    tid = np.asarray(trial_ids, dtype=np.uint64)[:, None]
    a, b = _np_philox_words(m, tid, c2, 0, *key)
    pairs = np.stack([_np_ziggurat(a, m, tid, c2, 0, *key), _np_ziggurat(b, m, tid, c2, 1, *key)], axis=-1)
    flat = pairs.reshape(pairs.shape[0], -1)
    lo = start - 2 * (start // 2)
    return flat[:, lo:lo + stop - start]


@jit
def _per_trial_draws(key0, key1, trial_ids, c2, uniform, out):
    """``out[t, j]``: lane 0 of counter (0, trial_ids[t], c2[j], 0), a normal or (``uniform``) a uniform."""
    for t in range(trial_ids.shape[0]):
        for j in range(c2.shape[0]):
            a, b = philox.philox_words(np.uint64(0), np.uint64(trial_ids[t]), np.uint64(c2[j]), np.uint64(0),
                                       np.uint64(key0), np.uint64(key1))
            if uniform:
                out[t, j] = philox.uniform_from_word(a)
            else:
                out[t, j] = philox._zig(a, np.uint64(0), np.uint64(trial_ids[t]), np.uint64(c2[j]), np.uint64(0),
                                        np.uint64(key0), np.uint64(key1))


# ----------------------------------------------------------------------------- compiled engine
@jit
def _block_noise(tid, k, b0, b1, stop, key0, key1, c2s, flags, rw_scale, gm_sigma, gm_c, gm_a, walk, y, words,
                 normals, rejected, flags8):  # pragma: no cover - compiled
    """The noise of one block (global samples ``k … min(b1, stop)``, pairs from ``b0``) of trial id ``tid`` into
    ``normals`` (3, 3, block): the Philox words of each enabled source and axis in one branch-free, vectorised
    loop, the ziggurat's fast path (also vectorised) and the ~1 % rejections; then the random walk (state
    ``walk``) and the Gauss–Markov recursion (state ``y``) over the block, three axes side by side in
    registers, overwriting their normals. Indices are unsigned (no negative-index wraparound per access)."""
    m0 = np.uint64(b0 // 2)
    npairs = (b1 - b0) // 2
    hi = min(b1, stop)
    for s in range(3):
        if flags & (4 << s):
            for j in range(3):
                c2 = np.uint64(c2s[s, j])
                for p in range(npairs):            # branch-free: vectorised across sample pairs
                    wa, wb = philox.philox_words(m0 + np.uint64(p), np.uint64(tid), c2, np.uint64(0),
                                                 np.uint64(key0), np.uint64(key1))
                    words[2 * p] = wa                  # sample order: lane 0, lane 1 of each pair
                    words[2 * p + 1] = wb
                for q in range(k - b0, hi - b0):   # ziggurat fast path, branch-free: vectorised (gathers)
                    r = words[q]
                    idx = r & _UFF
                    r8 = r >> _U8
                    rabs = (r8 >> _U1) & _MASK52
                    sign = 1.0 - 2.0 * np.float64(np.int64(r8 & _U1))   # ±1: x · sign == ±x exactly,
                    normals[s, j, q] = np.float64(np.int64(rabs)) * _WI[idx] * sign   # without a branch
                    rejected[q] = rabs >= _KI[idx]
                for w8 in range((k - b0) // 8, (hi - b0 + 7) // 8):   # ~1 % rejected: 8 flags per test
                    if flags8[w8]:
                        for q in range(max(8 * w8, k - b0), min(8 * w8 + 8, hi - b0)):
                            if rejected[q]:            # continue on the word's rejection stream
                                normals[s, j, q] = philox._zig_slow(words[q], m0 + np.uint64(q // 2),
                                                                    np.uint64(tid), c2, np.uint64(q & 1),
                                                                    np.uint64(key0), np.uint64(key1))
    if flags & 8:             # random-walk values over the block in place of their normals (np.cumsum, continued)
        va, vb, vc = walk[0], walk[1], walk[2]
        for q in range(k - b0, hi - b0):
            va = va + normals[1, 0, q] * rw_scale
            vb = vb + normals[1, 1, q] * rw_scale
            vc = vc + normals[1, 2, q] * rw_scale
            normals[1, 0, q], normals[1, 1, q], normals[1, 2, q] = va, vb, vc
        walk[0], walk[1], walk[2] = va, vb, vc
    if flags & 16:            # Gauss–Markov outputs over the block in place of their normals, three axes
        ya, yb, yc = y[0], y[1], y[2]                 # side by side in registers (lfilter: y = c w + a y_prev)
        for q in range(k - b0, hi - b0):
            wa = normals[2, 0, q] * gm_sigma
            wb = normals[2, 1, q] * gm_sigma
            wc = normals[2, 2, q] * gm_sigma
            if b0 + q == 0:                           # stationary start: y_0 = σ n_0
                wa, wb, wc = wa / gm_c, wb / gm_c, wc / gm_c
            ya = gm_a * ya + gm_c * wa
            yb = gm_a * yb + gm_c * wb
            yc = gm_a * yc + gm_c * wc
            normals[2, 0, q], normals[2, 1, q], normals[2, 2, q] = ya, yb, yc
        y[0], y[1], y[2] = ya, yb, yc


@jit
def _block_apply(out, t, k, b0, hi, start, base, tb, bias, warm, turn_on, vib, flags, white_scale, quant,
                 normals):  # pragma: no cover - compiled
    """Measurements ``out[t]`` of global samples ``k … hi`` from the block's noise (:func:`_block_noise`):
    every error term added in the reference's order, then the quantisation. ``bias`` (2, 3): the constant
    bias and the warm-up bias; ``warm`` (n,): the warm-up decay, whose term ``warm[i] · bias[1, j]`` is the
    reference's ``(decay[:, None] * warmup_bias)[i, j]`` (one product: the same number, no (n, 3) array)."""
    for kk in range(k, hi):
        q = np.uint64(kk - b0)                        # unsigned: no negative-index wraparound per access
        i = np.uint64(kk - start)
        for j in range(3):                             # three independent recursions side by side
            x = base[tb, i, j] + bias[0, j]
            if flags & 1:
                x = x + warm[i] * bias[1, j]
            if flags & 2:
                x = x + turn_on[t, j]
            if flags & 4:
                x = x + white_scale * normals[0, j, q]
            if flags & 8:                              # random-walk value of this sample (_block_noise)
                x = x + normals[1, j, q]
            if flags & 16:                             # Gauss–Markov output of this sample (_block_noise)
                x = x + normals[2, j, q]
            if flags & 32:
                x = x + vib[t, i, j]
            if flags & 64:
                x = np.rint(x / quant) * quant
            out[t, i, j] = x


@jit
def _trial_errors(outs, t, tid, start, bases, tbs, biases, warms, turn_ons, vibs, key0, key1, c2s, flags,
                  model_flags, white_scale, rw_scale, gm_sigma, gm_c, gm_a, quants, rw_state, gm_state, words,
                  normals, rejected, flags8):  # pragma: no cover - compiled
    """One trial of :func:`_sensor_errors_parallel` for K error models sharing their noise: the chunk in blocks of
    ``normals.shape[2]`` samples, each block's noise drawn once (:func:`_block_noise`, source flags ``flags``),
    then every error term of each model ``m`` (its own ``outs[m]``, base, bias, warm-up, turn-on bias,
    vibration, flags ``model_flags[m]`` and quantisation) applied in the reference's order
    (:func:`_block_apply`): output ``m`` is the one of model ``m`` alone, bit for bit."""
    stop = start + outs[0].shape[1]
    block = normals.shape[2]
    y = np.empty(3)
    walk = np.empty(3)
    for j in range(3):
        walk[j] = rw_state[t, j]
        y[j] = gm_state[t, j]
    k = start
    while k < stop:
        b0 = k - (k & 1)                                  # blocks start on a sample pair
        b1 = min(b0 + block, stop + (stop & 1))
        hi = min(b1, stop)
        _block_noise(tid, k, b0, b1, stop, key0, key1, c2s, flags, rw_scale, gm_sigma, gm_c, gm_a, walk, y, words,
                     normals, rejected, flags8)
        for m in range(len(outs)):
            _block_apply(outs[m], t, k, b0, hi, start, bases[m], tbs[m], biases[m], warms[m], turn_ons[m], vibs[m],
                         model_flags[m], white_scale, quants[m], normals)
        k = hi
    for j in range(3):
        rw_state[t, j] = walk[j]
        gm_state[t, j] = y[j]


@jit
def _sensor_errors_group(g, outs, start, bases, biases, warms, turn_ons, vibs, trial_ids, key0, key1, c2s, flags,
                         model_flags, white_scale, rw_scale, gm_sigma, gm_c, gm_a, quants, rw_state, gm_state, block,
                         group):  # pragma: no cover - compiled
    """Trials ``g·group … (g+1)·group`` of :func:`_sensor_errors_parallel`, sharing one scratch buffer."""
    trials = outs[0].shape[0]
    per_trial_base = np.empty(len(bases), np.int64)
    tbs = np.zeros(len(bases), np.int64)
    for m in range(len(bases)):
        per_trial_base[m] = bases[m].shape[0] > 1
    words = np.empty(block, np.uint64)
    rejected = np.zeros(8 * (block // 8 + 1), np.uint8)   # rejection flags, read 8 at a time through flags8
    flags8 = rejected.view(np.uint64)
    normals = np.empty((3, 3, block))
    for t in range(g * group, min((g + 1) * group, trials)):
        for m in range(len(bases)):
            tbs[m] = t if per_trial_base[m] else 0
        _trial_errors(outs, t, trial_ids[t], start, bases, tbs, biases, warms, turn_ons, vibs, key0, key1, c2s, flags,
                      model_flags, white_scale, rw_scale, gm_sigma, gm_c, gm_a, quants, rw_state, gm_state, words,
                      normals, rejected, flags8)


@jit(parallel=True)
def _sensor_errors_parallel(outs, start, bases, biases, warms, turn_ons, vibs, trial_ids, key0, key1, c2s, flags,
                            model_flags, white_scale, rw_scale, gm_sigma, gm_c, gm_a, quants, rw_state, gm_state,
                            block, group):  # pragma: no cover - compiled
    """Measurements ``outs[m]`` (T, n, 3) of K error models sharing their noise (:func:`_trial_errors`), global
    samples ``start … start+n``, groups of trials in parallel. Each trial's numbers are a function of its id
    only, so the thread count does not change them."""
    for g in prange((outs[0].shape[0] + group - 1) // group):
        _sensor_errors_group(g, outs, start, bases, biases, warms, turn_ons, vibs, trial_ids, key0, key1, c2s, flags,
                             model_flags, white_scale, rw_scale, gm_sigma, gm_c, gm_a, quants, rw_state, gm_state,
                             block, group)


@jit
def _sensor_errors_serial(outs, start, bases, biases, warms, turn_ons, vibs, trial_ids, key0, key1, c2s, flags,
                          model_flags, white_scale, rw_scale, gm_sigma, gm_c, gm_a, quants, rw_state, gm_state,
                          block, group):  # pragma: no cover - compiled
    """:func:`_sensor_errors_parallel` on the calling thread (small work: no OpenMP start-up)."""
    for g in range((outs[0].shape[0] + group - 1) // group):
        _sensor_errors_group(g, outs, start, bases, biases, warms, turn_ons, vibs, trial_ids, key0, key1, c2s, flags,
                             model_flags, white_scale, rw_scale, gm_sigma, gm_c, gm_a, quants, rw_state, gm_state,
                             block, group)


#: Trial-samples of a chunk from which the trial-parallel kernel is used (as the filters'
#: ``PARALLEL_MIN_WORK``): below it a parallel region costs more than it saves, and a process
#: that never starts numba's OpenMP threads can still ``fork`` worker processes safely.
PARALLEL_MIN_WORK = 200_000


def _use_parallel(trials: int, samples: int) -> bool:
    return trials >= 2 and trials * samples >= PARALLEL_MIN_WORK and numba.get_num_threads() > 1


#: Recent warm-up decays ``(t_on, tau, time_s, decay)`` of long chunks, newest first (see :func:`_warmup_decay`).
_WARMUP_MEMO: list = []
_WARMUP_MEMO_SIZE = 4


def _warmup_decay(time_s: np.ndarray, t_on: float, tau_s: float) -> np.ndarray:
    """``np.exp(-(time_s + t_on) / tau_s)``, reused while equal time samples come back (read-only).

    A Monte Carlo simulating one trial per call on the same time base (each with its own draw, so
    its own Trajectory) recomputes this exponential every call; an exact comparison of the time
    samples (equal inputs give equal outputs) is ~20× cheaper than the ``exp``.
    """
    if time_s.size < 2048:
        return np.exp(-(time_s + t_on) / tau_s)
    for a, b, t, decay in list(_WARMUP_MEMO):
        if a == t_on and b == tau_s and t.shape == time_s.shape and np.array_equal(t, time_s):
            return decay
    decay = _frozen(np.exp(-(time_s + t_on) / tau_s))
    _WARMUP_MEMO.insert(0, (t_on, tau_s, _frozen(time_s.copy()), decay))
    del _WARMUP_MEMO[_WARMUP_MEMO_SIZE:]
    return decay


class _SensorStream:
    """Applies one triad's :class:`SensorErrors` chunk by chunk.

    Every random number is a Philox draw addressed by (key, sample pair, trial id, sensor/source/axis)
    (:mod:`mtcal.core.philox`), so the output does not depend on how the record is cut into chunks,
    on threads, or on which other trials run. Random-walk and Gauss–Markov states carry over between chunks.
    """

    def __init__(self, errors: SensorErrors, key: tuple[int, int] | None, sensor_index: int,
                 trial_ids: np.ndarray, dt_s: float, time_since_power_on_s: float, block_samples: int,
                 engine: str = "numba"):
        self.engine = engine
        self.e, self.key, self.sensor_index = errors, key, sensor_index
        self.trial_ids = trial_ids
        self.trials, self.dt, self.t_on = trial_ids.size, dt_s, time_since_power_on_s
        self.block = max(2, block_samples + (block_samples & 1))
        self.matrix_t = errors.matrix().T
        self.bias = _vec3(errors.bias, "bias")
        self.warm = _vec3(errors.warmup_bias, "warmup_bias")
        self.vib = _vec3(errors.vibration_amplitude, "vibration_amplitude")
        self.rw_state = np.zeros((self.trials, 1, 3))
        self.gm_a = np.exp(-dt_s / errors.bias_instability_tau_s)
        self.gm_state = None
        self.c2s = np.array([_stream_words(sensor_index, s) for s in _SENSOR_SOURCES], dtype=np.int64)
        self.turn_on = (errors.bias_sigma * self._per_trial("turn_on", False)[:, None, :]
                        if errors.bias_sigma else None)
        self.phase = (2 * np.pi * self._per_trial("vibration", True)[:, None, :]
                      if np.any(self.vib) and errors.vibration_freq_hz else None)
        self._rw = np.zeros((self.trials, 3))   # numba engine: walk and Gauss–Markov output carried over
        self._gm = np.zeros((self.trials, 3))

    def _per_trial(self, source: str, uniform: bool) -> np.ndarray:
        """(T, 3) once-per-trial draws: lane 0 of counter (0, trial id, stream word of each axis, 0)."""
        c2 = np.array(_stream_words(self.sensor_index, source), dtype=np.int64)
        if self.engine == "numpy":
            tid = self.trial_ids.astype(np.uint64)[:, None]
            a, _ = _np_philox_words(0, tid, c2[None, :].astype(np.uint64), 0, *self.key)
            if uniform:
                return _np_uniform(a)
            return np.stack([_np_ziggurat(a[:, j], 0, tid[:, 0], int(c2[j]), 0, *self.key) for j in range(3)], -1)
        out = np.empty((self.trials, 3))
        _per_trial_draws(self.key[0], self.key[1], self.trial_ids, c2, uniform, out)
        return out

    def _normal(self, source: str, start: int, stop: int) -> np.ndarray:
        """Reference standard normal draws (T, stop − start, 3) for global samples [start, stop)."""
        words = _stream_words(self.sensor_index, source)
        return np.stack([_np_normals(self.key, self.trial_ids, words[j], start, stop) for j in range(3)], axis=-1)

    def process(self, truth: np.ndarray, time_s: np.ndarray, start: int, out: np.ndarray | None = None) -> np.ndarray:
        """Measurements (T, n, 3) for truth samples (n, 3) at global index ``start`` (into ``out`` if given)."""
        if self.engine == "numba":
            return self._process_numba(truth, time_s, start, out)
        e, n = self.e, truth.shape[-2]  # truth: (n, 3) shared or (T, n, 3) per trial
        stop = start + n
        out = np.empty((self.trials, n, 3)) if out is None else out
        out[:] = truth @ self.matrix_t
        out += self.bias
        if np.any(self.warm):
            out += np.exp(-(time_s + self.t_on) / e.warmup_tau_s)[:, None] * self.warm
        if self.turn_on is not None:
            out += self.turn_on
        if e.noise_density:
            out += (e.noise_density / np.sqrt(self.dt)) * self._normal("white", start, stop)
        if e.bias_random_walk:
            steps = self._normal("random_walk", start, stop) * (e.bias_random_walk * np.sqrt(self.dt))
            steps[:, :1, :] += self.rw_state  # carry the walk: same summation order as one long cumsum
            walk = np.cumsum(steps, axis=1)
            self.rw_state = walk[:, -1:, :].copy()
            out += walk
        if e.bias_instability:
            out += self._gauss_markov(start, stop)
        if self.phase is not None:
            out += self.vib * np.sin(2 * np.pi * e.vibration_freq_hz * time_s[None, :, None] + self.phase)
        if e.quantization:
            np.round(out / e.quantization, out=out)
            out *= e.quantization
        return out

    def _kernel_args(self, truth: np.ndarray, time_s: np.ndarray, out: np.ndarray | None):
        """``(out, base, warm, turn_on, vib, flags)`` of the compiled kernel for truth samples (n, 3) or (T, n, 3)."""
        e, n = self.e, truth.shape[-2]
        out = np.empty((self.trials, n, 3)) if out is None else out
        base = _rows_at(truth, self.matrix_t)  # same product as the reference
        base = np.ascontiguousarray(base if base.ndim == 3 else base[None])
        none2, none3 = np.zeros((1, 3)), np.zeros((1, 1, 3))
        flags = 0
        warm = np.zeros(1)
        if np.any(self.warm):       # the decay; the kernel multiplies it by the warm-up bias sample by sample
            warm, flags = np.ascontiguousarray(_warmup_decay(time_s, self.t_on, e.warmup_tau_s)), 1
        warm = warm.view()
        warm.flags.writeable = False  # one array type for every stream's decay (the memo's are read-only)
        turn_on = none2 if self.turn_on is None else np.ascontiguousarray(self.turn_on[:, 0, :])
        flags |= 0 if self.turn_on is None else 2
        flags |= self._noise_flags()
        vib = none3
        if self.phase is not None:
            vib = np.ascontiguousarray(self.vib * np.sin(2 * np.pi * e.vibration_freq_hz * time_s[None, :, None]
                                                         + self.phase))
            flags |= 32
        flags |= 64 if e.quantization else 0
        return out, base, warm, turn_on, vib, flags

    def _noise_flags(self) -> int:
        """Kernel flags of the per-sample noise sources switched on (white 4, random walk 8, instability 16)."""
        e = self.e
        return (4 if e.noise_density else 0) | (8 if e.bias_random_walk else 0) | (16 if e.bias_instability else 0)

    def _noise_scales(self) -> tuple[float, float, float, float, float]:
        """``(white_scale, rw_scale, gm_sigma, gm_c, gm_a)`` of the compiled kernel."""
        e, gm_a = self.e, float(self.gm_a)
        return (float(e.noise_density / np.sqrt(self.dt)), float(e.bias_random_walk * np.sqrt(self.dt)),
                float(e.bias_instability), float(np.sqrt(1.0 - gm_a * gm_a)), gm_a)

    def _process_numba(self, truth: np.ndarray, time_s: np.ndarray, start: int,
                       out: np.ndarray | None = None) -> np.ndarray:
        """:meth:`process` with the compiled engine: one parallel pass, noise drawn where it is consumed."""
        return self.process_shared([self], [truth], time_s, [out], start)[0]

    @staticmethod
    def process_shared(streams: list, truths: list, time_s: np.ndarray, outs: list, start: int = 0) -> list:
        """:meth:`process` (compiled engine) of several streams whose noise is equal (same key, trial ids,
        sensor, sample interval, noise scales and block: the caller checks), the noise drawn once.

        Output ``m`` equals ``streams[m].process(truths[m], time_s, start, outs[m])`` bit for bit."""
        first = streams[0]
        args = [s._kernel_args(x, time_s, o) for s, x, o in zip(streams, truths, outs)]
        key = first.key if first.key is not None else (0, 0)
        kernel = _sensor_errors_parallel if _use_parallel(first.trials, time_s.size) else _sensor_errors_serial
        kernel(tuple(a[0] for a in args), start, tuple(a[1] for a in args), tuple(np.stack([s.bias, s.warm]) for s in streams),
               tuple(a[2] for a in args), tuple(a[3] for a in args), tuple(a[4] for a in args), first.trial_ids,
               key[0], key[1], first.c2s, first._noise_flags(), np.array([a[5] for a in args], np.int64),
               *first._noise_scales(), np.array([float(s.e.quantization) for s in streams]), first._rw, first._gm,
               first.block, _TRIAL_GROUP)
        for s in streams[1:]:
            s._rw[:], s._gm[:] = first._rw, first._gm
        return [a[0] for a in args]

    def _gauss_markov(self, start: int, stop: int) -> np.ndarray:
        """First-order Gauss–Markov bias ``b_k = a b_{k−1} + √(1−a²) σ w_k``, stationary from k = 0."""
        a, sigma = self.gm_a, self.e.bias_instability
        w = self._normal("instability", start, stop) * sigma
        c = np.sqrt(1.0 - a * a)
        if start == 0:
            w = w.copy()
            w[:, 0, :] /= c  # b_0 = σ w_0 ~ N(0, σ²)
        zi = np.zeros((self.trials, 1, 3)) if self.gm_state is None else a * self.gm_state
        b, _ = _lfilter([c], [1.0, -a], w, axis=1, zi=zi)
        self.gm_state = b[:, -1:, :].copy()
        return b


_UFF, _U8, _U1, _MASK52 = np.uint64(0xFF), np.uint64(8), np.uint64(1), np.uint64(0x000FFFFFFFFFFFFF)
_KI, _WI = philox.KI, philox.WI

#: Trials per scratch buffer of :func:`_sensor_errors_parallel` (a prange work item).
_TRIAL_GROUP = 8


def _trial_ids(trial_ids, trials: int | None) -> tuple[np.ndarray, bool]:
    """Validated trial ids (int64 array in [0, 2³²)) and whether the output is a single trial."""
    if trial_ids is None:
        n = 1 if trials is None else positive_int(trials, "trials")
        return np.arange(n, dtype=np.int64), trials is None
    ids = np.asarray(trial_ids)
    if ids.ndim != 1 or ids.size == 0 or ids.dtype.kind not in "iu":
        raise ValueError(f"trial_ids must be a non-empty 1-D sequence of integers, got {trial_ids!r}")
    if ids.min() < 0 or ids.max() > 0xFFFFFFFF or np.unique(ids).size != ids.size:
        raise ValueError("trial_ids must be distinct integers in [0, 2**32)")
    if trials is not None and positive_int(trials, "trials") != ids.size:
        raise ValueError(f"trials ({trials}) must equal len(trial_ids) ({ids.size})")
    return ids.astype(np.int64), False


class ImuStream:
    """Simulated IMU output delivered in time chunks, in bounded memory.

    ``ImuStream(...).chunks(n)`` yields :class:`ImuRecord` pieces of ``n``
    samples (the last may be shorter). The random draws do not depend on the
    chunk size: concatenating the chunks gives exactly :func:`simulate_imu`'s
    output for the same generator state, whatever ``n`` is. Use it for Monte
    Carlo runs where only metrics are kept (never all trials × all samples).

    Parameters
    ----------
    trajectory, model, rng, trials, gravity_w_m_s2
        As for :func:`simulate_imu`.
    block_samples : int
        Samples whose normals the compiled kernel draws at a time per trial (scratch memory per
        thread ``≈ 80 × block_samples`` bytes); the numbers do not depend on it.
    engine : {"numba", "numpy"}
        Compiled error model (default) or the numpy reference; bit-identical output.
    trial_ids : sequence of int, optional
        Names of the trials (distinct, in [0, 2³²)); trial ``i`` of the output draws the numbers of
        trial ``trial_ids[i]``, whichever other trials run with it (a worker running trials
        500…999 passes ``range(500, 1000)``). Default ``range(trials)``. With ``trials=None`` a
        trial axis is added.
    """

    def __init__(self, trajectory: Trajectory, model: ImuErrorModel | None = None,
                 rng: np.random.Generator | None = None, trials: int | None = None,
                 gravity_w_m_s2=GRAVITY_W_M_S2, block_samples: int = 256, *, engine: str = "numba",
                 trial_ids=None):
        if not isinstance(trajectory, Trajectory):
            raise TypeError(f"trajectory must be a Trajectory, got {type(trajectory).__name__}")
        model = ImuErrorModel() if model is None else model
        if not isinstance(model, ImuErrorModel):
            raise TypeError(f"model must be an ImuErrorModel, got {type(model).__name__}")
        if rng is not None and not isinstance(rng, np.random.Generator):
            raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
        if rng is None and _has_random_errors(model):
            raise ValueError("rng must be a numpy.random.Generator when the error model has random errors")
        ids, self.single = _trial_ids(trial_ids, trials)
        self.trajectory, self.model, self.trials, self.trial_ids = trajectory, model, ids.size, ids
        block = positive_int(block_samples, "block_samples")
        if len(trajectory) > 2 ** 33:
            raise ValueError(f"trajectory has {len(trajectory)} samples; the counter allows at most 2**33")
        engine = _check_engine(engine)
        q_bs = np.asarray(model.q_mount, dtype=float)
        self._q_bs, self._q_ws = q_bs, None
        c_sb = rotations.quat_to_matrix(q_bs).T
        rates, force = _truth_outputs(trajectory, gravity_w_m_s2)
        self.gyro_true = _rows_at(rates, c_sb.T)
        self.accel_true = _rows_at(force, c_sb.T)
        key = spawn_philox_key(rng) if rng is not None else (0, 0)
        dt, t_on = trajectory.dt_s, model.time_since_power_on_s
        self._gyro = _SensorStream(model.gyro, key, 0, ids, dt, t_on, block, engine)
        self._accel = _SensorStream(model.accel, key, 1, ids, dt, t_on, block, engine)
        self._next = 0

    @property
    def q_ws(self) -> np.ndarray:
        """True sensor attitude (N, 4) ``q_wb ⊗ q_bs``, computed on first use."""
        if self._q_ws is None:
            self._q_ws = rotations.hamilton(self.trajectory.q_wb, self._q_bs)   # both checked on construction
        return self._q_ws

    def fill(self, gyro_out: np.ndarray, accel_out: np.ndarray) -> None:
        """Write the whole record's measurements into ``gyro_out`` and ``accel_out`` (no :class:`ImuRecord`).

        The numbers are :func:`simulate_imu`'s ``gyro_rad_s`` and ``accel_m_s2`` for the same
        arguments, bit for bit; a Monte Carlo that stacks trials into a preallocated buffer fills its
        slice directly (no per-call arrays, no copy, no truth attitude).

        Parameters
        ----------
        gyro_out, accel_out : ndarray (T, N, 3)
            C-contiguous float64, ``T`` = trials of this stream, ``N`` = trajectory samples
            (rad/s and m/s²).

        Examples
        --------
        >>> t = np.arange(0, 1, 0.01)
        >>> stream = ImuStream(Trajectory(t, np.tile([1.0, 0, 0, 0], (t.size, 1))), trials=1)
        >>> g, a = np.empty((1, t.size, 3)), np.empty((1, t.size, 3))
        >>> stream.fill(g, a)
        >>> a[0, 0].round(5).tolist()
        [0.0, 0.0, 9.80665]
        """
        self._check_fill(gyro_out, accel_out)
        self._next = n = len(self.trajectory)
        t = self.trajectory.time_s
        self._gyro.process(self.gyro_true, t, 0, gyro_out)
        self._accel.process(self.accel_true, t, 0, accel_out)

    def _check_fill(self, gyro_out, accel_out, name: str = "") -> None:
        """Refuse outputs :meth:`fill` cannot write, or a stream that already ran."""
        n = len(self.trajectory)
        for label, arr in (("gyro_out", gyro_out), ("accel_out", accel_out)):
            if (not isinstance(arr, np.ndarray) or arr.dtype != np.float64 or arr.shape != (self.trials, n, 3)
                    or not arr.flags.c_contiguous or not arr.flags.writeable):
                raise ValueError(f"{name}{label} must be a writeable C-contiguous float64 array of shape "
                                 f"{(self.trials, n, 3)}, got {getattr(arr, 'dtype', None)} {getattr(arr, 'shape', None)}")
        if self._next != 0:
            raise ValueError(f"{name}fill() and chunks() can run once per ImuStream (the noise states advance)")

    def chunks(self, chunk_samples: int):
        """Yield consecutive :class:`ImuRecord` chunks of ``chunk_samples`` samples."""
        size = positive_int(chunk_samples, "chunk_samples")
        if self._next != 0:
            raise ValueError("chunks() can be iterated once per ImuStream (the noise states advance)")
        n = len(self.trajectory)
        pool = _BufferPool()
        for start in range(0, n, size):
            stop = min(start + size, n)
            self._next = stop
            t = self.trajectory.time_s[start:stop]
            shape = (self.trials, stop - start, 3)
            gyro = self._gyro.process(self.gyro_true[start:stop], t, start, pool.take(shape))
            accel = self._accel.process(self.accel_true[start:stop], t, start, pool.take(shape))
            if self.single:
                gyro, accel = gyro[0], accel[0]
            record = ImuRecord(t, gyro, accel, self.q_ws[start:stop], self.gyro_true[start:stop],
                               self.accel_true[start:stop])
            del gyro, accel
            yield record
            del record


#: Fields of a triad's :class:`SensorErrors` that set its per-sample noise (equal in streams that share it).
_NOISE_FIELDS = ("noise_density", "bias_random_walk", "bias_instability", "bias_instability_tau_s")


def noise_mismatch(stream: ImuStream, other: ImuStream) -> str | None:
    """Why two :class:`ImuStream` do not draw the same noise (:func:`fill_streams`), or None when they do.

    Parameters
    ----------
    stream, other : ImuStream

    Returns
    -------
    str or None
        e.g. ``"has another generator key"``; None when key, trial ids, time samples, engine, block size
        and each triad's :data:`_NOISE_FIELDS` are equal.

    Examples
    --------
    >>> t = np.arange(0, 1, 0.01)
    >>> traj = Trajectory(t, np.tile([1.0, 0, 0, 0], (t.size, 1)))
    >>> noise_mismatch(ImuStream(traj, trials=2), ImuStream(traj, trials=3))
    'has other trial ids'
    """
    if other._gyro.key != stream._gyro.key:
        return "draws from another generator key"
    if not np.array_equal(other.trial_ids, stream.trial_ids):
        return "has other trial ids"
    t, t0 = other.trajectory.time_s, stream.trajectory.time_s
    if not (t is t0 or (t.shape == t0.shape and np.array_equal(t, t0))):
        return "has another time base"
    if (other._gyro.engine, other._gyro.block) != (stream._gyro.engine, stream._gyro.block):
        return "has another engine or block size"
    for sensor in ("gyro", "accel"):
        for name in _NOISE_FIELDS:
            a, b = getattr(getattr(other.model, sensor), name), getattr(getattr(stream.model, sensor), name)
            if a != b:
                return f"has {sensor}.{name} = {a!r}, not {b!r} (the noise scales must be equal)"
    return None


def fill_streams(streams, outputs) -> None:
    """:meth:`ImuStream.fill` of several streams that draw the same noise, the noise drawn once.

    Streams on the same generator key, trial ids and time base whose triads have the same noise
    scales (white-noise density, bias random walk, bias instability and its correlation time) draw
    the same white, random-walk and Gauss–Markov numbers; they may differ in everything else (truth
    trajectory, mounting, scale factor, misalignment, constant, turn-on and warm-up bias, vibration,
    quantisation, time since power-on). The compiled kernel draws each block's noise once and
    applies it to every stream in the order of :meth:`ImuStream.fill`: ``outputs[m]`` equals
    ``streams[m].fill(*outputs[m])`` bit for bit (the numpy engine fills stream by stream).

    Parameters
    ----------
    streams : sequence of ImuStream
        Fresh streams (not yet filled or chunked) with equal key, trial ids, time samples, engine,
        block size and, per triad, the :data:`_NOISE_FIELDS`.
    outputs : sequence of (gyro_out, accel_out)
        Per stream, C-contiguous float64 arrays (T, N, 3) (rad/s, m/s²), as for :meth:`ImuStream.fill`.

    Raises
    ------
    ValueError
        When the streams do not share their noise (naming what differs) or an output is unusable.

    Examples
    --------
    >>> from dataclasses import replace
    >>> from mtcal.core.rng import stream_rng
    >>> t = np.arange(0, 1, 0.01)
    >>> traj = Trajectory(t, np.tile([1.0, 0, 0, 0], (t.size, 1)))
    >>> noisy = SensorErrors(noise_density=1e-3)
    >>> a_model = ImuErrorModel(gyro=noisy, accel=noisy)
    >>> b_model = ImuErrorModel(gyro=replace(noisy, bias=1e-3), accel=noisy)
    >>> outs = [(np.empty((2, t.size, 3)), np.empty((2, t.size, 3))) for _ in range(2)]
    >>> fill_streams([ImuStream(traj, m, stream_rng(1, 0), trials=2) for m in (a_model, b_model)], outs)
    >>> g, a = np.empty((2, t.size, 3)), np.empty((2, t.size, 3))
    >>> ImuStream(traj, b_model, stream_rng(1, 0), trials=2).fill(g, a)
    >>> bool(np.array_equal(outs[1][0], g) and np.array_equal(outs[1][1], a))
    True
    """
    streams, outputs = list(streams), list(outputs)
    if not streams or len(outputs) != len(streams):
        raise ValueError(f"streams and outputs must be non-empty and of equal length, got {len(streams)} and "
                         f"{len(outputs)}")
    for i, (stream, out) in enumerate(zip(streams, outputs)):
        if not isinstance(stream, ImuStream):
            raise TypeError(f"streams[{i}] must be an ImuStream, got {type(stream).__name__}")
        if not (isinstance(out, (tuple, list)) and len(out) == 2):
            raise ValueError(f"outputs[{i}] must be a pair (gyro_out, accel_out)")
        stream._check_fill(*out, name=f"streams[{i}]: ")
    first = streams[0]
    for i, stream in enumerate(streams[1:], 1):
        reason = noise_mismatch(first, stream)
        if reason is not None:
            raise ValueError(f"streams[{i}] {reason} than streams[0]: no shared noise")
    if len(streams) == 1 or first._gyro.engine != "numba":
        for stream, out in zip(streams, outputs):
            stream.fill(*out)
        return
    for stream in streams:
        stream._next = len(stream.trajectory)
    t = first.trajectory.time_s
    for sensor, truth, k in (("_gyro", "gyro_true", 0), ("_accel", "accel_true", 1)):
        _SensorStream.process_shared([getattr(s, sensor) for s in streams], [getattr(s, truth) for s in streams], t,
                                     [out[k] for out in outputs])


class _BufferPool:
    """Output arrays of :meth:`ImuStream.chunks`, recycled once nothing refers to them any more.

    A fresh (T, n, 3) array per chunk and sensor costs more than filling it: numpy asks the kernel
    for transparent huge pages on large allocations, so each chunk's new 24 MB (1000 trials × 1000
    samples) is faulted in and zeroed again (~3 ms, ~0.4 s CPU over a 1000 × 60 s run). An array is
    handed out again only when the pool's own reference is the last one (CPython reference count:
    a chunk still held by a consumer, or any view of its arrays, keeps them out of the pool), so a
    consumer that keeps chunks (e.g. to concatenate them) sees its data untouched.
    """

    #: Arrays kept for reuse (a prefetching consumer has at most ~3 chunks × 2 sensors alive).
    SIZE = 8

    def __init__(self):
        self.arrays: list[np.ndarray] = []

    @staticmethod
    def _free_refcount() -> int:
        """``sys.getrefcount`` of a pooled array nothing else refers to, seen from the loop in :meth:`take`."""
        probe = [np.empty(0)]
        for arr in probe:
            return sys.getrefcount(arr)
        raise AssertionError

    def take(self, shape: tuple[int, int, int]) -> np.ndarray:
        """A free pooled array of ``shape``, else a new one (pooled while there is room)."""
        free = _FREE_REFCOUNT
        for arr in self.arrays:
            if arr.shape == shape and sys.getrefcount(arr) <= free:
                return arr
        arr = np.empty(shape)
        if len(self.arrays) < self.SIZE:
            self.arrays.append(arr)
        return arr


_FREE_REFCOUNT = _BufferPool._free_refcount()


def apply_sensor_errors(errors: SensorErrors, truth, time_s, rng: np.random.Generator | None = None, *,
                        time_since_power_on_s: float = 0.0, engine: str = "numba", trial_ids=None) -> np.ndarray:
    """Corrupt an error-free triad signal with one sensor's :class:`SensorErrors`.

    For batches where every trial has its own truth (e.g. wang2022sensors's per-trial
    angle histories); :func:`simulate_imu` is the usual entry point.

    Parameters
    ----------
    errors : SensorErrors
        Error model (units of the signal: rad/s or m/s²).
    truth : array_like, shape (N, 3) or (T, N, 3)
        Error-free signal; a leading axis gives per-trial truth.
    time_s : array_like, shape (N,)
        Uniformly sampled, strictly increasing time (s).
    rng : numpy.random.Generator
        Required when ``errors`` has random terms.
    time_since_power_on_s : float
        Time already powered at ``time_s[0]`` (s), for the warm-up bias.
    engine : {"numba", "numpy"}
        Compiled error model (default) or the numpy reference; bit-identical output.
    trial_ids : sequence of int, optional
        Trial names for a (T, N, 3) ``truth`` (default ``range(T)``), as for :class:`ImuStream`.

    Returns
    -------
    ndarray, same shape as ``truth``

    Examples
    --------
    >>> t = np.arange(4) * 0.01
    >>> apply_sensor_errors(SensorErrors(bias=0.5), np.zeros((4, 3)), t)[0].tolist()
    [0.5, 0.5, 0.5]
    """
    if not isinstance(errors, SensorErrors):
        raise TypeError(f"errors must be a SensorErrors, got {type(errors).__name__}")
    x = as_float_array(truth, "truth", ndim=(2, 3), last_dim=3)
    t = time_vector(time_s)
    if x.shape[-2] != t.size:
        raise ValueError(f"truth must have {t.size} samples on axis -2 to match time_s, got {x.shape}")
    if rng is not None and not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    if rng is None and _is_random(errors):
        raise ValueError("rng must be a numpy.random.Generator when errors has random terms")
    if x.ndim == 2 and trial_ids is not None:
        raise ValueError("trial_ids needs a per-trial truth of shape (T, N, 3)")
    ids, _ = _trial_ids(trial_ids, 1 if x.ndim == 2 else x.shape[0])
    key = spawn_philox_key(rng) if rng is not None else (0, 0)
    stream = _SensorStream(errors, key, 0, ids, uniform_dt(t),
                           positive_scalar(time_since_power_on_s, "time_since_power_on_s", allow_zero=True),
                           block_samples=256, engine=_check_engine(engine))
    out = stream.process(x, t, 0)
    return out[0] if x.ndim == 2 else out


def simulate_imu(trajectory: Trajectory, model: ImuErrorModel | None = None,
                 rng: np.random.Generator | None = None, trials: int | None = None,
                 gravity_w_m_s2=GRAVITY_W_M_S2, *, engine: str = "numba", trial_ids=None) -> ImuRecord:
    """Simulate gyro and accelerometer outputs along a trajectory.

    Parameters
    ----------
    trajectory : Trajectory
        Truth body motion.
    model : ImuErrorModel, optional
        Sensor errors and mounting; error-free and identity mounting if None.
    rng : numpy.random.Generator
        Source of every random draw (required when the model has random errors).
    trials : int, optional
        Number of Monte Carlo trials; output arrays get a leading trial axis.
        ``None`` gives a single trial without the leading axis.
    gravity_w_m_s2 : 3-vector
        World gravity (m/s²), default z-up ``[0, 0, −9.80665]``.
    engine : {"numba", "numpy"}
        Compiled error model (default) or the numpy reference; bit-identical output.
    trial_ids : sequence of int, optional
        Names of the trials (default ``range(trials)``): trial ``trial_ids[i]`` gets the same
        numbers whichever other trials are simulated with it (see :class:`ImuStream`).

    Returns
    -------
    ImuRecord

    See Also
    --------
    ImuStream : the same output in time chunks (bounded memory).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(0, 1, 0.01)
    >>> q = np.tile([1.0, 0, 0, 0], (t.size, 1))
    >>> rec = simulate_imu(Trajectory(t, q))
    >>> rec.accel_m_s2[0].round(5)
    array([0.     , 0.     , 9.80665])
    """
    stream = ImuStream(trajectory, model, rng, trials, gravity_w_m_s2, engine=engine, trial_ids=trial_ids)
    return next(stream.chunks(len(trajectory)))


def fill_streams_grouped(streams, outputs) -> None:
    """:meth:`ImuStream.fill` of every stream, those that share their noise with an earlier one
    (:func:`noise_mismatch` is None) together (:func:`fill_streams`: the noise drawn once): ``outputs[m]``
    equals ``streams[m].fill(*outputs[m])`` bit for bit.

    Parameters
    ----------
    streams : sequence of ImuStream
        Fresh streams (not yet filled or chunked).
    outputs : sequence of (gyro_out, accel_out)
        Per stream, C-contiguous float64 arrays (T, N, 3) (rad/s, m/s²).

    Examples
    --------
    >>> from mtcal.core.rng import stream_rng
    >>> t = np.arange(0, 1, 0.01)
    >>> traj = Trajectory(t, np.tile([1.0, 0, 0, 0], (t.size, 1)))
    >>> noisy = ImuErrorModel(gyro=SensorErrors(noise_density=1e-3), accel=SensorErrors(noise_density=1e-3))
    >>> outs = [(np.empty((2, t.size, 3)), np.empty((2, t.size, 3))) for _ in range(3)]
    >>> fill_streams_grouped([ImuStream(traj, noisy, stream_rng(1, k), trials=2) for k in (0, 0, 1)], outs)
    >>> bool(np.array_equal(outs[0][0], outs[1][0])), bool(np.array_equal(outs[0][0], outs[2][0]))
    (True, False)
    """
    groups = []
    for stream, out in zip(streams, outputs):
        for group in groups:
            if noise_mismatch(group[0][0], stream) is None:
                group.append((stream, out))
                break
        else:
            groups.append([(stream, out)])
    for group in groups:
        fill_streams(*zip(*group))


def load_tilt_outputs(gyro_rad_s, accel_m_s2, q_wb, dt_s: float, q_mount, tilt_rad) -> None:
    """Add, in place, a per-trial mount tilt proportional to the load normal to the mount plate.

    The installation tilts by ``δ(t) = tilt · s(t)`` (body axes, rad) with ``s = −ĝ_z`` the
    normal load in g (1 when level, 0 at roll ±90°). To first order in δ the sensor then reads
    ``f' = f − δ_s × f`` and ``ω' = ω − δ_s × ω + δ̇_s`` (``δ_s`` in sensor axes).

    Parameters
    ----------
    gyro_rad_s, accel_m_s2 : ndarray (T, N, 3)
        Sensor outputs, modified in place.
    q_wb : ndarray (N, 4)
        Truth body attitude.
    dt_s : float
        Sample interval (s); ``ṡ`` is the central difference of ``s`` times ``1 / dt_s``.
    q_mount : 4-sequence
        ``q_bs``.
    tilt_rad : ndarray (T, 3)
        Tilt per g of normal load (rad), per trial.
    """
    s = rotations.quat_to_matrix(q_wb)[:, 2, 2]          # −ĝ_z: 1 when level
    s_dot = np.gradient(s) * (1.0 / dt_s)
    tilt_s = np.asarray(tilt_rad, float) @ rotations.quat_to_matrix(np.asarray(q_mount, float))  # C(q_bs)ᵀ δ
    if (all(isinstance(x, np.ndarray) and x.dtype == np.float64 and x.ndim == 3 for x in (gyro_rad_s, accel_m_s2))
            and tilt_s.shape == (gyro_rad_s.shape[0], 3)):
        _load_tilt_kernel(gyro_rad_s, accel_m_s2, s, s_dot, tilt_s)   # the loop below in one pass, bit-identical
        return
    for k in range(gyro_rad_s.shape[0]):
        d = s[:, None] * tilt_s[k]
        accel_m_s2[k] -= np.cross(d, accel_m_s2[k])
        gyro_rad_s[k] += s_dot[:, None] * tilt_s[k] - np.cross(d, gyro_rad_s[k])


def gravity_lateral_axis(q_wb) -> np.ndarray:
    """The lateral load axis ``ẑ_b × ĝ_b`` (N, 3) of a body attitude ``q_wb`` (N, 4), ĝ_b unit gravity in body axes.

    Zero when level, unit about the lateral axis at 90° of roll or pitch: the axis a compliant mount
    tilts about in proportion to the lateral load (:func:`tilted_trajectory` with it).

    Examples
    --------
    >>> q = np.array([[1.0, 0.0, 0.0, 0.0], [np.cos(np.pi / 4), np.sin(np.pi / 4), 0.0, 0.0]])
    >>> (gravity_lateral_axis(q).round(12) + 0.0).tolist()
    [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]
    """
    g_b = -rotations.quat_to_matrix(q_wb)[:, 2, :]
    return np.stack([-g_b[:, 1], g_b[:, 0], np.zeros(len(g_b))], axis=-1)


@dataclass(frozen=True)
class RecordPiece:
    """One block of trials of a :class:`RecordSource`: its sensor, its generator, its truth and its own changes.

    Attributes
    ----------
    trials : int
        Trials of the block (≥ 1).
    model : ImuErrorModel
        The block's sensor (mounting, error values).
    rng : numpy.random.Generator
        The block's IMU noise generator (:class:`ImuStream`; None for a sensor without random errors).
    tilt_gain : float
        Gain of the source's tilt axis for this block's truth (rad per unit; 0: the base attitude).
    accel_step_m_s2 : ndarray, shape (trials, 1, 3), optional
        An accelerometer bias change per trial (m/s²), added from the source's ``step_start`` sample on
        (a run-to-run change between two runs of one session).
    load_tilt_rad : ndarray, shape (trials, 3), optional
        A per-trial mount tilt per g of normal load (rad, body axes; :func:`load_tilt_outputs`).
    trajectory : Trajectory, optional
        The block's own truth instead of the source's base (its time base may be shorter than the stack:
        the records are then held at their last sample to the stack's length).
    accel_offset_m_s2 : ndarray, shape (trials or 1, N, 3), optional
        An additive accelerometer disturbance (m/s², e.g. a vibration) over the block's own N samples.
    """

    trials: int
    model: ImuErrorModel
    rng: np.random.Generator | None
    tilt_gain: float = 0.0
    accel_step_m_s2: np.ndarray | None = None
    load_tilt_rad: np.ndarray | None = None
    trajectory: Trajectory | None = None
    accel_offset_m_s2: np.ndarray | None = None


class RecordSource:
    """Stacked IMU records of Monte Carlo blocks, simulated when a consumer asks for them.

    Each :class:`RecordPiece` is a block of trials with its own sensor and generator, its truth its own
    trajectory or the source's base attitude tilted by its ``tilt_gain`` about ``tilt_axis``
    (:class:`TiltedTrajectories`). A consumer (a measurement procedure) asks for some blocks at a time
    (:meth:`fill`): they are simulated into one reused buffer (:meth:`ImuStream.fill`; blocks of a group
    that draw the same noise together, :func:`fill_streams_grouped`), then each block's bias step,
    additive disturbance and load tilt are added, in that order; a block shorter than the stack is held at
    its last sample. Blocks of equal gain share one truth trajectory (its outputs computed once), dropped
    after its last block took it. The numbers of a block depend on its own settings alone: the same bits
    whichever blocks are filled with it, in whatever groups, on whatever threads.

    Parameters
    ----------
    time_s : ndarray, shape (N,) or None
        Uniform time grid (s) of the base truth (None when every block has its own trajectory).
    q_base : ndarray, shape (N, 4) or None
        Base body attitude (body → world, unit).
    pieces : sequence of RecordPiece
    dt_s : float
        Sample interval (s) of the load tilt's rate (:func:`load_tilt_outputs`).
    tilt_axis : ndarray, shape (N, 3), optional
        Tilt axis per unit gain (e.g. :func:`gravity_lateral_axis`), needed when a gain is not 0.
    step_start : int, optional
        First sample of the blocks' accelerometer bias steps, needed when a block has one.

    Examples
    --------
    >>> from mtcal.core.rng import stream_rng
    >>> t = np.arange(0, 1, 0.01)
    >>> q = np.tile([1.0, 0.0, 0.0, 0.0], (t.size, 1))
    >>> noisy = ImuErrorModel(accel=SensorErrors(noise_density=1e-3))
    >>> step = np.full((2, 1, 3), 0.5)
    >>> src = RecordSource(t, q, [RecordPiece(2, noisy, stream_rng(1, 0)), RecordPiece(2, noisy, stream_rng(1, 0),
    ...                    accel_step_m_s2=step)], 0.01, step_start=50)
    >>> gyro, accel = src.fill([0, 1], [[0, 1]])
    >>> gyro.shape, bool(np.allclose(accel[2:, 50:] - accel[:2, 50:], 0.5)), bool(np.array_equal(accel[2:, :50], accel[:2, :50]))
    ((4, 100, 3), True, True)
    """

    def __init__(self, time_s, q_base, pieces, dt_s: float, *, tilt_axis=None, step_start: int | None = None):
        self.pieces = tuple(pieces)
        if not self.pieces or not all(isinstance(p, RecordPiece) for p in self.pieces):
            raise TypeError(f"pieces must be a non-empty sequence of RecordPiece, got {[type(p).__name__ for p in self.pieces]}")
        for p in self.pieces:
            if not isinstance(p.trials, (int, np.integer)) or p.trials < 1:
                raise ValueError(f"a piece's trials must be an integer >= 1, got {p.trials!r}")
            if p.trajectory is not None and not isinstance(p.trajectory, Trajectory):
                raise TypeError(f"a piece's trajectory must be a Trajectory, got {type(p.trajectory).__name__}")
        self.time_s, self.q_base, self.step_start = time_s, q_base, step_start
        self.dt_s = positive_scalar(dt_s, "dt_s")
        based = [p for p in self.pieces if p.trajectory is None]
        if based and (time_s is None or q_base is None):
            raise ValueError("time_s and q_base are needed when a piece has no trajectory of its own")
        gains = [float(p.tilt_gain) for p in based]
        if any(g != 0.0 for g in gains) and tilt_axis is None:
            raise ValueError("tilt_axis is needed when a piece's tilt_gain is not 0")
        if any(p.accel_step_m_s2 is not None for p in self.pieces) and step_start is None:
            raise ValueError("step_start is needed when a piece has an accel_step_m_s2")
        self._family = None if tilt_axis is None else TiltedTrajectories(time_s, q_base, tilt_axis)
        #: Per block, its trials and its samples (a consumer sizes a stack from them before asking).
        self.trial_counts = tuple(int(p.trials) for p in self.pieces)
        self.sample_counts = tuple(len(time_s) if p.trajectory is None else len(p.trajectory) for p in self.pieces)
        self._uses = {}
        for g in gains:
            self._uses[g] = self._uses.get(g, 0) + 1
        self._memo, self._lock = {}, threading.Lock()
        self._gyro = self._accel = None

    def samples(self, indices) -> int:
        """Samples of the blocks ``indices`` stacked: the longest block's."""
        return max(self.sample_counts[i] for i in indices)

    def trials(self, indices) -> int:
        """Trials of the blocks ``indices`` stacked."""
        return sum(self.trial_counts[i] for i in indices)

    def _trajectory(self, piece: RecordPiece) -> Trajectory:
        """The block's truth: its own, or the base's of its gain, computed by its first block (the others wait)
        and dropped after its last."""
        if piece.trajectory is not None:
            return piece.trajectory
        gain = float(piece.tilt_gain)
        with self._lock:
            entry = self._memo.get(gain)
            if entry is None:
                entry = self._memo[gain] = [threading.Lock(), None]
        with entry[0]:
            if entry[1] is None:
                entry[1] = (Trajectory(self.time_s, self.q_base) if gain == 0.0 else self._family(gain))
            traj = entry[1]
        with self._lock:
            self._uses[gain] -= 1
            if self._uses[gain] == 0:
                del self._memo[gain]
        return traj

    def fill(self, indices, groups, map_groups=None) -> tuple[np.ndarray, np.ndarray]:
        """The records of blocks ``indices``, stacked in that order: ``(gyro_rad_s, accel_m_s2)``, each (T, N, 3).

        ``groups`` partitions the positions ``0 … len(indices) − 1``: the blocks of a group are filled
        together (their noise drawn once where shared); ``map_groups(fn, groups)`` (default: one after
        the other) may spread the groups over threads. The arrays are views of a buffer this source
        reuses at its next call (no fresh arrays per call): read them before asking again.
        """
        indices = list(indices)
        total, n = self.trials(indices), self.samples(indices)
        if self._gyro is None or self._gyro.shape[0] < total or self._gyro.shape[1] != n:
            self._gyro, self._accel = np.empty((total, n, 3)), np.empty((total, n, 3))
        gyro, accel = self._gyro[:total], self._accel[:total]
        starts = np.cumsum([0] + [self.pieces[i].trials for i in indices]).tolist()
        rows = [(gyro[a:b], accel[a:b]) for a, b in zip(starts[:-1], starts[1:])]

        def simulate(group):
            pieces = [self.pieces[indices[p]] for p in group]
            trajs = [self._trajectory(piece) for piece in pieces]
            # a block as long as the stack is simulated straight into its rows, a shorter one into its own arrays
            outs = [rows[p] if len(traj) == n else (np.empty((piece.trials, len(traj), 3)),
                                                    np.empty((piece.trials, len(traj), 3)))
                    for p, piece, traj in zip(group, pieces, trajs)]
            streams = [ImuStream(traj, piece.model, rng=piece.rng, trials=piece.trials)
                       for piece, traj in zip(pieces, trajs)]
            fill_streams_grouped(streams, outs)
            del streams
            for p, piece, traj, (g, acc) in zip(group, pieces, trajs, outs):
                if piece.accel_step_m_s2 is not None:
                    acc[:, self.step_start:] += piece.accel_step_m_s2
                if piece.accel_offset_m_s2 is not None:
                    acc += piece.accel_offset_m_s2
                if piece.load_tilt_rad is not None:
                    load_tilt_outputs(g, acc, traj.q_wb, self.dt_s, piece.model.q_mount, piece.load_tilt_rad)
                m = len(traj)
                if m < n:                        # held at its last sample to the stack's length
                    for x, out in ((g, rows[p][0]), (acc, rows[p][1])):
                        out[:, :m] = x
                        out[:, m:] = x[:, -1:]

        if map_groups is None:
            for group in groups:
                simulate(group)
        else:
            list(map_groups(simulate, list(groups)))
        return gyro, accel


@jit
def _load_tilt_kernel(gyro, accel, s, s_dot, tilt_s):  # pragma: no cover - compiled
    """In place, per trial k: ``d = s·tilt_s[k]``, ``accel −= d × accel``, ``gyro += ṡ·tilt_s[k] − d × gyro``.

    The cross products as ``numpy.cross`` forms them (``a1 b2 − a2 b1``, ``a2 b0 − a0 b2``,
    ``a0 b1 − a1 b0``), from the values before the update, element by element in the same order (no
    ``fastmath``, no FMA contraction: bit-identical). Shapes: gyro, accel (T, N, 3); s, s_dot (N,); tilt_s (T, 3).
    """
    for k in range(gyro.shape[0]):
        t0, t1, t2 = tilt_s[k, 0], tilt_s[k, 1], tilt_s[k, 2]
        for n in range(gyro.shape[1]):
            d0, d1, d2 = s[n] * t0, s[n] * t1, s[n] * t2
            a0, a1, a2 = accel[k, n, 0], accel[k, n, 1], accel[k, n, 2]
            accel[k, n, 0] = a0 - (d1 * a2 - d2 * a1)
            accel[k, n, 1] = a1 - (d2 * a0 - d0 * a2)
            accel[k, n, 2] = a2 - (d0 * a1 - d1 * a0)
            w0, w1, w2 = gyro[k, n, 0], gyro[k, n, 1], gyro[k, n, 2]
            sd = s_dot[n]
            gyro[k, n, 0] = w0 + (sd * t0 - (d1 * w2 - d2 * w1))
            gyro[k, n, 1] = w1 + (sd * t1 - (d2 * w0 - d0 * w2))
            gyro[k, n, 2] = w2 + (sd * t2 - (d0 * w1 - d1 * w0))


def _check_engine(engine: str) -> str:
    if engine not in ("numba", "numpy"):
        raise ValueError(f"engine must be one of ('numba', 'numpy'), got {engine!r}")
    return engine


def _has_random_errors(model: ImuErrorModel) -> bool:
    return _is_random(model.gyro) or _is_random(model.accel)


def _is_random(s: SensorErrors) -> bool:
    """Whether a triad's error model draws random numbers."""
    if s.bias_sigma or s.noise_density or s.bias_random_walk or s.bias_instability:
        return True
    return bool(np.any(_vec3(s.vibration_amplitude, "vibration_amplitude")) and s.vibration_freq_hz)


def _lfilter(*args, **kwargs):
    """``scipy.signal.lfilter``, imported on first use (scipy.signal costs ~0.5-1 s of import time)."""
    from scipy.signal import lfilter

    return lfilter(*args, **kwargs)
