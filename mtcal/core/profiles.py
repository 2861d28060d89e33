"""Motion profiles: turntable/mechanism schedules, sweeps, oscillations, fixed-axis rotation.

An :class:`AngleProfile` holds angles (rad) with their exact first and second
time derivatives, so that truth rates and lever-arm accelerations are
analytic. Moves between waypoints follow the quintic minimum-jerk blend
``s(τ) = 10τ³ − 15τ⁴ + 6τ⁵`` (zero rate and acceleration at both ends), a
good model of a servo turntable or a wind-tunnel support mechanism.

Builders:

* :func:`step_schedule` — hold, move, hold … through a list of waypoints
  (turntable positions, AoA sweeps, the six-position procedure);
* :func:`sinusoid` — ``θ(t) = offset + A sin(2π f t + φ)``;
* :func:`constant_rate` — uniform rotation between two angles;
* :func:`join_profiles` — profiles end to end as one session (a calibration run, then sweeps …);
* :func:`trajectory_from_euler_zxy` — wang2023cja Euler angles (Eq 9) → :class:`~mtcal.core.simulate.Trajectory`;
* :func:`fixed_axis_trajectory` — rotation about a fixed axis with a lever arm
  (tangential + centripetal acceleration), wang2022sensors, as an attitude trajectory;
* :func:`fixed_axis_imu_truth` — the same rotation as the ideal gyro and accelerometer
  readings, batched over trials (each with its own angle history, axis and lever arm).

Both fixed-axis forms share :func:`lever_arm_accel_b` (the one lever-arm model).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mtcal.core import rotations
from mtcal.core.validate import as_float_array, positive_scalar, unit_quaternion
from mtcal.core.simulate import Trajectory

__all__ = ["AngleProfile", "middle_slices", "step_schedule", "sinusoid", "constant_rate", "join_profiles",
           "trajectory_from_euler_zxy", "fixed_axis_trajectory", "fixed_axis_imu_truth", "lever_arm_accel_b"]


@dataclass(frozen=True)
class AngleProfile:
    """Angles with analytic derivatives on a uniform time grid.

    Attributes
    ----------
    time_s : ndarray (N,)
    angle_rad, rate_rad_s, accel_rad_s2 : ndarray (N, D)
        Angle, rate and angular acceleration for D channels.
    is_static : ndarray (N,) of bool
        True where every channel is at rest (inside a hold).
    segment : ndarray (N,) of int
        Index of the hold (even numbers 0, 2, …) or move (odd) each sample is in;
        hold ``k`` (waypoint ``k``) has segment ``2k``.
    """

    time_s: np.ndarray
    angle_rad: np.ndarray
    rate_rad_s: np.ndarray
    accel_rad_s2: np.ndarray
    is_static: np.ndarray
    segment: np.ndarray

    @property
    def fs_hz(self) -> float:
        """Sample rate (Hz)."""
        return 1.0 / float(self.time_s[1] - self.time_s[0])

    def hold_slices(self, span: slice | None = None, fraction: float = 1.0) -> list[slice]:
        """Sample slices of each hold, in waypoint order: those inside ``span`` (default all), each cut to its
        central ``fraction`` (0 < fraction ≤ 1, :func:`middle_slices`).

        Examples
        --------
        >>> prof = step_schedule(np.radians([[0, 0, 0], [0, 10, 0], [0, 0, 0]]), np.radians(10.0), [1.0, 2.0, 1.0], 10.0)
        >>> prof.hold_slices(), prof.hold_slices(slice(5, 40), 0.5)
        ([slice(0, 10, None), slice(20, 40, None), slice(50, 60, None)], [slice(6, 8, None), slice(25, 35, None)])
        """
        seg_all = self.segment if span is None else self.segment[span]
        start = 0 if span is None else span.start
        out = []
        for seg in np.unique(seg_all[seg_all % 2 == 0]):
            idx = np.flatnonzero(seg_all == seg) + start
            out.append(slice(int(idx[0]), int(idx[-1]) + 1))
        return out if fraction == 1.0 else middle_slices(out, fraction)


def middle_slices(windows: list[slice], fraction: float = 0.5) -> list[slice]:
    """The central ``fraction`` (0 < fraction ≤ 1, trusted) of each window: ``max(1, round(n · fraction))``
    samples, centred (the "middle section" of a rest or hold).

    Examples
    --------
    >>> middle_slices([slice(1000, 4000)], 0.5)
    [slice(1750, 3250, None)]
    """
    out = []
    for r in windows:
        n = r.stop - r.start
        m = max(1, int(round(n * fraction)))
        a = r.start + (n - m) // 2
        out.append(slice(a, a + m))
    return out


def _quintic(tau: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Minimum-jerk blend s(τ), s'(τ), s''(τ) for τ ∈ [0, 1]."""
    s = tau**3 * (10 - 15 * tau + 6 * tau**2)
    ds = 30 * tau**2 * (1 - tau) ** 2
    dds = 60 * tau * (1 - tau) * (1 - 2 * tau)
    return s, ds, dds


def step_schedule(waypoints_rad, rate_rad_s: float, hold_s, fs_hz: float,
                  *, min_move_s: float = 0.0) -> AngleProfile:
    """Hold at each waypoint, moving between them with a minimum-jerk blend.

    Takes ``fs_hz``, not ``dt_s`` (the exception of the study template's time-base rule): the samples are
    made at ``t_k = k / fs_hz`` (the time base :mod:`mtcal.core.simulate` reads from the trajectory; the sensor
    spec owns the rate), and their count is ``floor(duration · fs_hz)``; ``1 / (1 / fs)`` is not ``fs`` exactly for
    640 of the integer rates 1–5000 Hz, so a rate rebuilt from ``dt_s`` would move sample times by an ulp and could change a
    count at a tie.

    Parameters
    ----------
    waypoints_rad : array_like, shape (K,) or (K, D)
        Angle vectors (rad) to visit in order; the profile starts in a hold
        at ``waypoints[0]``.
    rate_rad_s : float
        Mean rate of each move (rad/s) on the channel moving the most; the
        peak rate of the quintic blend is 1.875× this.
    hold_s : float or array_like, shape (K,)
        Hold duration at each waypoint (s).
    fs_hz : float
        Sample rate (Hz).
    min_move_s : float
        Lower bound on a move's duration (s), e.g. for zero-length moves.

    Returns
    -------
    AngleProfile
    """
    wp = as_float_array(waypoints_rad, "waypoints_rad", ndim=(1, 2))
    wp = wp[:, None] if wp.ndim == 1 else wp
    rate = positive_scalar(rate_rad_s, "rate_rad_s")
    fs = positive_scalar(fs_hz, "fs_hz")
    positive_scalar(min_move_s, "min_move_s", allow_zero=True)
    holds = np.broadcast_to(as_float_array(hold_s, "hold_s"), (wp.shape[0],)).astype(float)
    if np.any(holds <= 0):
        raise ValueError("hold_s must be > 0 at every waypoint")
    moves = np.maximum(np.max(np.abs(np.diff(wp, axis=0)), axis=1) / rate, min_move_s)
    moves = np.maximum(moves, 1.0 / fs)
    durations = np.empty(2 * wp.shape[0] - 1)
    durations[0::2] = holds
    durations[1::2] = moves
    edges = np.concatenate([[0.0], np.cumsum(durations)])
    n = int(np.floor(edges[-1] * fs + 1e-9))
    t = np.arange(n) / fs
    seg = np.clip(np.searchsorted(edges, t, side="right") - 1, 0, durations.size - 1)
    k = seg // 2
    start = wp[k]
    is_move = seg % 2 == 1
    delta = np.where(is_move[:, None], wp[np.minimum(k + 1, wp.shape[0] - 1)] - start, 0.0)
    dur = durations[seg]
    tau = np.clip((t - edges[seg]) / dur, 0.0, 1.0)
    s, ds, dds = _quintic(tau)
    angle = start + delta * np.where(is_move, s, 0.0)[:, None]
    rate_out = delta * np.where(is_move, ds / dur, 0.0)[:, None]
    accel = delta * np.where(is_move, dds / dur**2, 0.0)[:, None]
    return AngleProfile(t, angle, rate_out, accel, ~is_move, seg)


def sinusoid(amplitude_rad: float, freq_hz: float, duration_s: float, fs_hz: float,
             *, phase_rad: float = 0.0, offset_rad: float = 0.0) -> AngleProfile:
    """Single-channel oscillation ``θ(t) = offset + A sin(2π f t + φ)``, sampled on ``[0, duration_s)``.

    Takes ``fs_hz``, not ``dt_s`` (the exception of the study template's time-base rule): the samples are
    made at ``t_k = k / fs_hz`` (the time base :mod:`mtcal.core.simulate` reads from the trajectory; the sensor
    spec owns the rate), and their count is ``floor(duration_s · fs_hz)``; ``1 / (1 / fs)`` is not ``fs`` exactly for
    640 of the integer rates 1–5000 Hz, so a rate rebuilt from ``dt_s`` would move sample times by an ulp and could change a
    count at a tie.

    >>> sinusoid(0.1, 1.0, 1.0, 100.0).angle_rad.shape
    (100, 1)
    """
    amp = positive_scalar(amplitude_rad, "amplitude_rad", allow_zero=True)
    f = positive_scalar(freq_hz, "freq_hz")
    fs = positive_scalar(fs_hz, "fs_hz")
    n = int(np.floor(positive_scalar(duration_s, "duration_s") * fs + 1e-9))
    t = np.arange(n) / fs
    w = 2 * np.pi * f
    arg = w * t + float(phase_rad)
    angle = offset_rad + amp * np.sin(arg)
    return AngleProfile(t, angle[:, None], (amp * w * np.cos(arg))[:, None],
                        (-amp * w * w * np.sin(arg))[:, None], np.zeros(n, bool), np.ones(n, int))


def constant_rate(start_rad: float, stop_rad: float, rate_rad_s: float, fs_hz: float) -> AngleProfile:
    """Single-channel uniform rotation from ``start`` to ``stop`` (inclusive).

    Takes ``fs_hz``, not ``dt_s`` (the exception of the study template's time-base rule): the samples are
    made at ``t_k = k / fs_hz`` (the time base :mod:`mtcal.core.simulate` reads from the trajectory; the sensor
    spec owns the rate), and their count is ``floor(|span| / rate · fs_hz) + 1``; ``1 / (1 / fs)`` is not ``fs`` exactly for
    640 of the integer rates 1–5000 Hz, so a rate rebuilt from ``dt_s`` would move sample times by an ulp and could change a
    count at a tie.

    >>> import numpy as np
    >>> float(constant_rate(0.0, np.radians(10.0), np.radians(10.0), 100.0).time_s[-1])
    1.0
    """
    rate = positive_scalar(rate_rad_s, "rate_rad_s")
    fs = positive_scalar(fs_hz, "fs_hz")
    span = float(stop_rad) - float(start_rad)
    if span == 0:
        raise ValueError("stop_rad must differ from start_rad")
    n = int(np.floor(abs(span) / rate * fs + 1e-9)) + 1
    t = np.arange(n) / fs
    signed = np.sign(span) * rate
    angle = start_rad + signed * t
    return AngleProfile(t, angle[:, None], np.full((n, 1), signed), np.zeros((n, 1)),
                        np.zeros(n, bool), np.ones(n, int))


def join_profiles(parts) -> tuple[AngleProfile, list[slice]]:
    """Profiles end to end as one session on one time grid, and each part's sample span in it.

    Each part's first sample follows the previous part's last by one sample interval (the time base is
    ``k · dt`` with the first part's interval); the angles are joined as they are, not blended, so parts
    that end and start at the same angles (schedules from and back to zero) join without a jump. Segments are renumbered so that they stay distinct and keep their parity
    (holds even, moves odd): part ``j``'s segments are shifted by the sum over the earlier parts of
    ``max(segment) + 2``.

    Parameters
    ----------
    parts : sequence of AngleProfile
        At least one profile, all with the same channels and sample rate.

    Returns
    -------
    profile : AngleProfile
        The joined session.
    spans : list of slice
        Part ``j``'s samples in ``profile``.

    Examples
    --------
    >>> a = step_schedule([0.0, 0.1], 1.0, 1.0, 10.0)
    >>> prof, spans = join_profiles([a, a])
    >>> prof.time_s.size == 2 * a.time_s.size, spans[1].start == a.time_s.size
    (True, True)
    >>> sorted(set(prof.segment[spans[1]].tolist()))          # the second part's holds stay even
    [4, 5, 6]
    """
    parts = list(parts)
    if not parts or not all(isinstance(p, AngleProfile) for p in parts):
        raise TypeError("parts must be a non-empty sequence of AngleProfile")
    dt = 1.0 / parts[0].fs_hz
    fields_ = {k: [] for k in ("angle_rad", "rate_rad_s", "accel_rad_s2", "is_static", "segment")}
    spans, n, seg0 = [], 0, 0
    for p in parts:
        for k in fields_:
            v = getattr(p, k)
            fields_[k].append(v + seg0 if k == "segment" else v)
        spans.append(slice(n, n + p.time_s.size))
        n += p.time_s.size
        seg0 += int(p.segment.max()) + 2
    t = np.arange(n) * dt
    return AngleProfile(t, *(np.concatenate(fields_[k], axis=0) for k in fields_)), spans


def trajectory_from_euler_zxy(profile: AngleProfile) -> Trajectory:
    """Body trajectory from a 3-channel profile of wang2023cja angles [ψ, θ, γ] (Eq 9)."""
    if profile.angle_rad.shape[1] != 3:
        raise ValueError(f"profile must have 3 channels [yaw, pitch, roll], "
                         f"got {profile.angle_rad.shape[1]}")
    a = profile.angle_rad
    return Trajectory(profile.time_s, rotations.quat_from_euler_zxy(a[:, 0], a[:, 1], a[:, 2]))


def fixed_axis_trajectory(profile: AngleProfile, axis_b, *, lever_arm_b_m=(0.0, 0.0, 0.0),
                          q_wb0=(1.0, 0.0, 0.0, 0.0)) -> Trajectory:
    """Rotation by θ(t) about a body-fixed axis through a fixed point (wang2022sensors).

    The attitude is ``C_wb(t) = C_wb0 R(θ(t), v)`` so the static specific force is
    ``f_b = R(θ, v)ᵀ ā0`` with ``ā0 = C_wb0ᵀ (−g_w)`` (Eq 15 measurement model).
    The sensor sits at ``r`` (body frame, m) from a point on the axis; its
    acceleration is ``C_wb0 R [θ̈ (v × r) + θ̇² v × (v × r)]`` (tangential +
    centripetal).

    Parameters
    ----------
    profile : AngleProfile
        Single-channel rotation angle (rad) with derivatives.
    axis_b : 3-vector
        Unit rotation axis v in the body frame.
    lever_arm_b_m : 3-vector
        Sensor position from the axis (m).
    q_wb0 : 4-vector
        Body attitude at θ = 0 (scalar-first).
    """
    if profile.angle_rad.shape[1] != 1:
        raise ValueError(f"profile must have 1 channel, got {profile.angle_rad.shape[1]}")
    v = as_float_array(axis_b, "axis_b", ndim=1, last_dim=3)
    if abs(np.linalg.norm(v) - 1.0) > 1e-6:
        raise ValueError(f"axis_b must be a unit vector, got |axis_b| = {np.linalg.norm(v):.6g}")
    r = as_float_array(lever_arm_b_m, "lever_arm_b_m", ndim=1, last_dim=3)
    q0 = unit_quaternion(q_wb0, "q_wb0")
    theta = profile.angle_rad[:, 0]
    q_rel = rotations.quat_from_rotvec(theta[:, None] * v)
    q_wb = rotations.quat_multiply(q0, q_rel)
    acc_b0 = lever_arm_accel_b(profile.rate_rad_s[:, 0], profile.accel_rad_s2[:, 0], v, r)
    c_wb = rotations.quat_to_matrix(q_wb)
    acc_w = np.einsum("nij,nj->ni", c_wb, acc_b0)
    return Trajectory(profile.time_s, q_wb, acc_w)


def lever_arm_accel_b(rate_rad_s, accel_rad_s2, axis_b, lever_arm_b_m) -> np.ndarray:
    """Acceleration ``θ̈ (v × r) + θ̇² v × (v × r)`` of a point at ``r`` from a fixed axis v (rotating frame).

    Tangential plus centripetal term (wang2022sensors Sec. 3.3.3: the lever-arm
    accelerations that violate the gravity-only measurement model while moving).

    Parameters
    ----------
    rate_rad_s, accel_rad_s2 : array_like (..., N)
        θ̇ (rad/s) and θ̈ (rad/s²).
    axis_b, lever_arm_b_m : array_like (3,) or (..., 3)
        Unit axis v and lever arm r (m), broadcast against the leading axes.

    Returns
    -------
    ndarray (..., N, 3)
        Acceleration (m/s²) in the rotating (body) frame.

    Examples
    --------
    >>> lever_arm_accel_b([2.0], [0.0], [0.0, 0.0, 1.0], [0.5, 0.0, 0.0]).tolist()   # ω² r inward
    [[-2.0, 0.0, 0.0]]
    """
    rate = np.asarray(rate_rad_s, float)
    acc = np.asarray(accel_rad_s2, float)
    v = np.asarray(axis_b, float)
    vxr = np.cross(v, np.asarray(lever_arm_b_m, float))
    vxvxr = np.cross(v, vxr)
    if v.ndim > 1:
        vxr, vxvxr = vxr[..., None, :], vxvxr[..., None, :]
    return acc[..., None] * vxr + (rate**2)[..., None] * vxvxr


def fixed_axis_imu_truth(theta_rad, rate_rad_s, accel_rad_s2, axes_b, lever_arms_b_m, accel0_m_s2,
                         dt_s: float) -> tuple[np.ndarray, np.ndarray]:
    """Ideal gyro and accelerometer for T rotations θ(t) about fixed axes (wang2022sensors truth).

    Angular rate ``ω = θ̇ v`` taken as the interval mean ``Δθ/Δt`` (exact for a
    gyro sample acting over ``[t_k, t_k+1]``; the last sample repeats), and
    specific force ``f = R(θ, v)ᵀ ā0 + θ̈ (v × r) + θ̇² v × (v × r)`` with
    ``R(θ, v)ᵀ ā0 = (v vᵀ) ā0 + cos θ ā0⊥ − sin θ (v × ā0)`` (Eq 15/16 measurement
    model plus :func:`lever_arm_accel_b`).

    Parameters
    ----------
    theta_rad, rate_rad_s, accel_rad_s2 : array_like (T, N)
        Angle (rad) and its exact derivatives per trial.
    axes_b, lever_arms_b_m : array_like (T, 3)
        Unit axis v and lever arm r (body frame, m) per trial.
    accel0_m_s2 : array_like (3,)
        ā0, the static specific force at θ = 0 (m/s²).
    dt_s : float
        Sample interval (s).

    Returns
    -------
    gyro_rad_s, accel_m_s2 : ndarray (T, N, 3)

    Examples
    --------
    >>> th = np.radians([[0.0, 90.0, 180.0]])
    >>> w, f = fixed_axis_imu_truth(th, 0 * th, 0 * th, [[1.0, 0.0, 0.0]], [[0.0, 0.0, 0.0]], [0.0, 0.0, 9.8], 1.0)
    >>> np.round(f[0], 9).tolist(), round(float(w[0, 0, 0]), 6)
    ([[0.0, 0.0, 9.8], [0.0, 9.8, 0.0], [0.0, 0.0, -9.8]], 1.570796)
    """
    th = as_float_array(theta_rad, "theta_rad", ndim=2)
    rate = as_float_array(rate_rad_s, "rate_rad_s", ndim=2)
    acc = as_float_array(accel_rad_s2, "accel_rad_s2", ndim=2)
    v = as_float_array(axes_b, "axes_b", ndim=2, last_dim=3)
    r = as_float_array(lever_arms_b_m, "lever_arms_b_m", ndim=2, last_dim=3)
    a0 = as_float_array(accel0_m_s2, "accel0_m_s2", ndim=1, last_dim=3)
    dt = positive_scalar(dt_s, "dt_s")
    if not th.shape == rate.shape == acc.shape or v.shape != (th.shape[0], 3) or r.shape != v.shape:
        raise ValueError(f"theta_rad, rate_rad_s, accel_rad_s2 must be (T, N) and axes_b, lever_arms_b_m (T, 3), "
                         f"got {th.shape}, {rate.shape}, {acc.shape}, {v.shape}, {r.shape}")
    if np.any(np.abs(np.linalg.norm(v, axis=1) - 1.0) > 1e-6):
        raise ValueError("axes_b must be unit vectors")
    dth = np.diff(th, axis=1) / dt
    w_rate = np.concatenate([dth, dth[:, -1:]], axis=1)
    par = v * (v @ a0)[:, None]
    perp = a0 - par
    w0 = np.cross(v, a0)
    vxr = np.cross(v, r)
    # the lever-arm terms of lever_arm_accel_b, summed in one expression (keeps the study's outputs bit-identical)
    f = (par[:, None] + np.cos(th)[..., None] * perp[:, None] - np.sin(th)[..., None] * w0[:, None]
         + acc[..., None] * vxr[:, None] + (rate**2)[..., None] * np.cross(v, vxr)[:, None])
    return w_rate[..., None] * v[:, None], f
