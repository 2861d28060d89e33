"""Logs an engineer would write with plain numpy — no mtcal import, its own quaternion algebra.

Independent of mtcal's simulator and rotation code on purpose: the calibrate → apply workflow
is checked against truth that mtcal did not produce. Conventions of the script (its own,
stated): quaternions scalar-first Hamilton; the body attitude is ``q = qz(yaw) ⊗ qx(pitch) ⊗
qy(roll)`` (yaw about z, pitch about x, roll about y, z up, y forward); the sensor is mounted
with ``q_ws = q_wb ⊗ q_bs``, ``q_bs`` from the mounting yaw/pitch/roll the same way; a level
accelerometer at rest reads +g on z; the gyro sample k is the mean rate over [t_k, t_k+1]
(the rotation increment divided by dt).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

G = 9.80665
FS_HZ = 1000.0
MOUNT_DEG = (0.3, -0.5, 0.8)                  # mounting yaw, pitch, roll (deg) of q_bs
GYRO_BIAS_DEG_S = (0.35, -0.25, 0.3)
GYRO_NOISE_DEG_S = 0.05                        # per-sample std at 1 kHz
ACCEL_NOISE_M_S2 = 0.01
SIX_POSITIONS_DEG = ((8, 0, 0), (-8, 0, 0), (0, -12, 0), (0, 23, 0), (0, 0, 90), (0, 0, -90))


def qmul(p, q):
    p0, p1, p2, p3 = np.moveaxis(p, -1, 0)
    q0, q1, q2, q3 = np.moveaxis(q, -1, 0)
    return np.stack([p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3, p0 * q1 + p1 * q0 + p2 * q3 - p3 * q2,
                     p0 * q2 - p1 * q3 + p2 * q0 + p3 * q1, p0 * q3 + p1 * q2 - p2 * q1 + p3 * q0], axis=-1)


def qconj(q):
    return q * np.array([1.0, -1.0, -1.0, -1.0])


def qaxis(angle, axis: int):
    a = np.asarray(angle, float)
    q = np.zeros(a.shape + (4,))
    q[..., 0] = np.cos(a / 2)
    q[..., 1 + axis] = np.sin(a / 2)
    return q


def q_from_ypr_deg(yaw, pitch, roll):
    """``qz(yaw) ⊗ qx(pitch) ⊗ qy(roll)`` of angles in degrees (broadcast)."""
    y, p, r = np.broadcast_arrays(*(np.radians(np.asarray(v, float)) for v in (yaw, pitch, roll)))
    return qmul(qmul(qaxis(y, 2), qaxis(p, 0)), qaxis(r, 1))


def ypr_deg_from_q(q):
    """Inverse of :func:`q_from_ypr_deg` (away from pitch ±90°)."""
    q0, q1, q2, q3 = np.moveaxis(q, -1, 0)
    pitch = np.arcsin(np.clip(2 * (q2 * q3 + q0 * q1), -1, 1))
    roll = np.arctan2(-2 * (q1 * q3 - q0 * q2), q0**2 - q1**2 - q2**2 + q3**2)
    yaw = np.arctan2(-2 * (q1 * q2 - q0 * q3), q0**2 - q1**2 + q2**2 - q3**2)
    return np.degrees(np.stack([yaw, pitch, roll], axis=-1))


def rotate_inverse(q, v):
    """``C(q)ᵀ v``: a world vector in the frame of q."""
    vq = np.concatenate([np.zeros(v.shape[:-1] + (1,)), v], axis=-1)
    return qmul(qmul(qconj(q), vq), q)[..., 1:]


def rate_from_increments(q, dt):
    """Mean body rate over each interval (rad/s), from ``q_k⁻¹ ⊗ q_k+1``; the last sample repeats."""
    d = qmul(qconj(q[:-1]), q[1:])
    d *= np.sign(d[:, :1] + 1e-300)
    s = np.linalg.norm(d[:, 1:], axis=1, keepdims=True)
    ang = 2 * np.arctan2(s, d[:, :1])
    w = np.where(s > 1e-15, d[:, 1:] / np.maximum(s, 1e-300) * ang, 2 * d[:, 1:]) / dt
    return np.vstack([w, w[-1:]])


def smooth_step(u):
    """Minimum-jerk 0 → 1 for u in [0, 1]."""
    u = np.clip(u, 0.0, 1.0)
    return u**3 * (10 - 15 * u + 6 * u**2)


@dataclass
class NumpyLog:
    df: pd.DataFrame
    q_wb: np.ndarray          # true body attitude (N, 4)
    ypr_deg: np.ndarray       # true body yaw/pitch/roll (N, 3) in the script's convention

    def write(self, path) -> str:
        self.df.to_csv(path, index=False)
        return str(path)


def imu_log(ypr_deg: np.ndarray, *, mount_deg=MOUNT_DEG, gyro_bias_deg_s=GYRO_BIAS_DEG_S,
            gyro_noise_deg_s=GYRO_NOISE_DEG_S, accel_noise_m_s2=ACCEL_NOISE_M_S2, fs_hz=FS_HZ,
            seed=0) -> NumpyLog:
    """The IMU log of a body following ``ypr_deg`` (N, 3) with the sensor mounted at ``mount_deg``."""
    rng = np.random.default_rng(seed)
    dt = 1.0 / fs_hz
    q_wb = q_from_ypr_deg(ypr_deg[:, 0], ypr_deg[:, 1], ypr_deg[:, 2])
    q_ws = qmul(q_wb, q_from_ypr_deg(*mount_deg))
    n = q_ws.shape[0]
    gyro = rate_from_increments(q_ws, dt) + np.radians(gyro_bias_deg_s)
    gyro += rng.normal(0.0, np.radians(gyro_noise_deg_s), (n, 3))
    accel = rotate_inverse(q_ws, np.broadcast_to([0.0, 0.0, G], (n, 3)))
    accel = accel + rng.normal(0.0, accel_noise_m_s2, (n, 3))
    t = np.arange(n) * dt
    df = pd.DataFrame({"time_s": t, "gyro_x_rad_s": gyro[:, 0], "gyro_y_rad_s": gyro[:, 1],
                       "gyro_z_rad_s": gyro[:, 2], "accel_x_m_s2": accel[:, 0], "accel_y_m_s2": accel[:, 1],
                       "accel_z_m_s2": accel[:, 2]})
    return NumpyLog(df, q_wb, ypr_deg)


def waypoint_path(waypoints_deg, hold_s, move_s, fs_hz=FS_HZ) -> np.ndarray:
    """Yaw/pitch/roll (N, 3): hold at each waypoint ``hold_s`` seconds, minimum-jerk moves of ``move_s``."""
    wp = np.asarray(waypoints_deg, float)
    n_hold, n_move = int(round(hold_s * fs_hz)), int(round(move_s * fs_hz))
    parts = []
    for i, w in enumerate(wp):
        parts.append(np.tile(w, (n_hold, 1)))
        if i + 1 < len(wp):
            u = smooth_step(np.arange(n_move) / n_move)[:, None]
            parts.append(w + u * (wp[i + 1] - w))
    return np.vstack(parts)


def turntable_log(**kw) -> tuple[NumpyLog, pd.DataFrame]:
    """Six-position turntable log (start and end at the mechanism zero) and its positions table."""
    wp = [(0, 0, 0)] + [p for pos in SIX_POSITIONS_DEG for p in (pos, (0, 0, 0))]
    path = waypoint_path(wp, hold_s=3.0, move_s=2.0)
    log = imu_log(path, **kw)
    pos = pd.DataFrame(SIX_POSITIONS_DEG, columns=["yaw_deg", "pitch_deg", "roll_deg"])
    return log, pos


def flight_log(start_deg=(30.0, 2.0, -1.5), *, parked_s=5.0, duration_s=60.0, slow_start_s=0.0, seed=1,
               **kw) -> NumpyLog:
    """Parked at ``start_deg`` (yaw, pitch, roll), then a manoeuvre; back to rest for the last 3 s.

    ``slow_start_s`` > 0: the manoeuvre's amplitude grows as ``(t / slow_start_s)²`` at first,
    so the rate rises slowly out of the rest (a taxiing start), as real logs do.
    """
    fs = FS_HZ
    t = np.arange(int(round(duration_s * fs))) / fs
    tm = np.clip(t - parked_s, 0.0, None)
    end = duration_s - 3.0 - parked_s
    env = smooth_step(tm / 4.0) * smooth_step((end - tm) / 4.0)
    if slow_start_s > 0:
        env = np.where(tm < slow_start_s, (tm / slow_start_s) ** 2 * smooth_step(tm / 4.0), env)
    env = np.where(tm >= end, 0.0, env)
    ypr = np.stack([start_deg[0] + 40.0 * env * np.sin(2 * np.pi * tm / 40.0),
                    start_deg[1] + 12.0 * env * np.sin(2 * np.pi * tm / 9.0),
                    start_deg[2] + 25.0 * env * np.sin(2 * np.pi * tm / 13.0 + 0.5)], axis=1)
    return imu_log(ypr, seed=seed, **kw)
