"""Test logs with the quirks real sensors show, built from mtcal's simulator (small and fast).

Quirks available (each a keyword of :func:`hinge_log`):

* ``g_error`` — accelerometer scale error: |a| at rest 0.5–3 % off 9.81, plus a
  per-axis bias so |a| changes slightly with orientation;
* ``gyro_bias_deg_s`` — 0.5–3 °/s MEMS gyro bias, ``bias_step_deg_s`` a bias
  step after every move;
* ``jitter_ms`` — whole-millisecond timestamps with random steps (e.g. 3–7 ms),
  gyro = mean rate over each recorded interval (simulated at 1 kHz first);
* ``clip_deg_s`` — gyro clipping at a full scale;
* ``counts`` — integer counts instead of SI (with the LSB sizes returned);
* any rate (110, 150, 1200 Hz), any rest lengths (0.3–0.8 s "stances").

Every builder returns a :class:`Log` with the DataFrame a user would have, the
truth (axis, final angle, rest spans) and how to read it (CLI options).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from mtcal.core import profiles, rotations
from mtcal.core.simulate import ImuErrorModel, SensorErrors, simulate_imu

G = 9.80665
DEG = np.pi / 180


@dataclass
class Log:
    df: pd.DataFrame
    axis: np.ndarray                  # true rotation axis (sensor frame), v_x >= 0
    final_angle_deg: float            # true angle about axis at the end, from the initial rest
    rest_spans_s: list                # true holds (start, stop) in s
    options: list = field(default_factory=list)   # CLI options needed to read it

    def write(self, path) -> str:
        if str(path).endswith(".parquet"):
            self.df.to_parquet(path, index=False)
        else:
            self.df.to_csv(path, index=False)
        return str(path)


def _holds(prof) -> list:
    t = prof.time_s
    return [(float(t[s.start]), float(t[s.stop - 1])) for s in prof.hold_slices()]


def hinge_log(angles_deg=(0, 60, 120, 30), *, axis=(0.6, 0.0, 0.8), fs_hz=200.0, hold_s=2.0,
              rate_deg_s=90.0, g_error=0.012, accel_bias_m_s2=(0.03, -0.02, 0.04),
              gyro_bias_deg_s=(1.2, -0.7, 2.1), bias_step_deg_s=0.0, gyro_noise=2e-4, accel_noise=1.5e-3,
              jitter_ms=None, clip_deg_s=None, counts=False, gyro_unit="rad/s", accel_unit="m/s2",
              time_unit="s", lever_arm_m=(0.1, 0.05, 0.0), q_wb0=None, seed=7) -> Log:
    """A rotation about a fixed axis with rests (wang2022sensors set-up) and real-sensor quirks."""
    rng = np.random.default_rng(seed)
    v = np.asarray(axis, float)
    v /= np.linalg.norm(v)
    sim_fs = 1000.0 if jitter_ms else fs_hz
    holds = hold_s if np.ndim(hold_s) else np.full(len(angles_deg), hold_s)
    prof = profiles.step_schedule(np.radians(np.asarray(angles_deg, float))[:, None], np.radians(rate_deg_s),
                                  holds, sim_fs, min_move_s=0.3)
    if q_wb0 is None:  # tilt the rig so the axis is not vertical and gravity is not along it
        q_wb0 = rotations.quat_from_euler_zxy(0.0, np.radians(10.0), np.radians(-20.0))
    traj = profiles.fixed_axis_trajectory(prof, v, lever_arm_b_m=lever_arm_m, q_wb0=q_wb0)
    model = ImuErrorModel(gyro=SensorErrors(bias=tuple(np.radians(gyro_bias_deg_s)), noise_density=gyro_noise),
                          accel=SensorErrors(bias=tuple(accel_bias_m_s2), noise_density=accel_noise,
                                             scale_factor=g_error))
    rec = simulate_imu(traj, model, rng)
    t, gyro, accel = rec.time_s, rec.gyro_rad_s.copy(), rec.accel_m_s2.copy()
    if bias_step_deg_s:
        moving = ~prof.is_static
        ends = np.flatnonzero(moving[:-1] & ~moving[1:]) + 1
        for k, e in enumerate(ends):
            gyro[e:] += np.radians(bias_step_deg_s) * np.array([1.0, -0.5, 0.7]) * (1 if k % 2 else -1)
    if jitter_ms:
        steps = rng.integers(jitter_ms[0], jitter_ms[1] + 1, size=t.size)
        idx = np.cumsum(np.r_[0, steps])
        idx = idx[idx < t.size]
        c = np.vstack([np.zeros(3), np.cumsum(gyro, axis=0)])
        nxt = np.r_[idx[1:], t.size]
        gyro = (c[nxt] - c[idx]) / (nxt - idx)[:, None]
        accel = accel[idx]
        t = idx / 1000.0  # whole milliseconds
    if clip_deg_s:
        gyro = np.clip(gyro, -np.radians(clip_deg_s), np.radians(clip_deg_s))
    df = _frame(t, gyro, accel, counts=counts, gyro_unit=gyro_unit, accel_unit=accel_unit, time_unit=time_unit)
    opts = []
    if counts:
        opts += ["--gyro-scale", f"{GYRO_LSB_DEG_S}", "--gyro-unit", "deg/s",
                 "--accel-scale", f"{1 / ACCEL_LSB_PER_G}", "--accel-unit", "g"]
    else:
        if gyro_unit != "rad/s":
            opts += ["--gyro-unit", gyro_unit]
        if accel_unit != "m/s2":
            opts += ["--accel-unit", accel_unit]
    if time_unit != "s":
        opts += ["--time-unit", time_unit]
    return Log(df, v if v[0] >= 0 else -v, float(angles_deg[-1] - angles_deg[0]), _holds(prof), opts)


#: raw-count scales of the "counts" quirk: gyro 1 LSB = 0.061 deg/s (±2000 deg/s, 16 bit), accel 4096 LSB/g
GYRO_LSB_DEG_S = 0.061
ACCEL_LSB_PER_G = 4096.0


def _frame(t, gyro, accel, *, counts=False, gyro_unit="rad/s", accel_unit="m/s2", time_unit="s"):
    if counts:
        g = np.round(np.degrees(gyro) / GYRO_LSB_DEG_S).astype(np.int64)
        a = np.round(accel / G * ACCEL_LSB_PER_G).astype(np.int64)
    else:
        g = np.degrees(gyro) if gyro_unit == "deg/s" else gyro
        a = accel / G if accel_unit == "g" else accel
    scale = {"s": 1.0, "ms": 1e3, "us": 1e6}[time_unit]
    df = pd.DataFrame({"time_s": t * scale})
    for i, ax in enumerate("xyz"):
        df[f"gyro_{ax}_rad_s"] = g[:, i]
    for i, ax in enumerate("xyz"):
        df[f"accel_{ax}_m_s2"] = a[:, i]
    return df


def turn_about_vertical_log(**kw) -> Log:
    """~178° turn about the vertical (level sensor, 150 Hz, whole-ms timestamps, counts):
    no tilt change, so no axis can be estimated from the accelerometer."""
    base = dict(angles_deg=(0, 178), axis=(0.0, 0.0, 1.0), q_wb0=(1.0, 0.0, 0.0, 0.0), fs_hz=150.0,
                hold_s=3.0, jitter_ms=(6, 7), counts=True, g_error=0.009, lever_arm_m=(0, 0, 0))
    base.update(kw)
    return hinge_log(**base)


def two_flips_log(**kw) -> Log:
    """110 Hz sensor flipped twice by ~180° about its x axis (rests at 0, 180, 360°)."""
    base = dict(angles_deg=(0, 181, 359), axis=(1.0, 0.0, 0.0), q_wb0=(1.0, 0.0, 0.0, 0.0), fs_hz=110.0,
                hold_s=2.5, g_error=-0.006, rate_deg_s=150.0, lever_arm_m=(0, 0.03, 0.02))
    base.update(kw)
    return hinge_log(**base)


def stance_log(n_steps=10, **kw) -> Log:
    """1200 Hz foot-like record: short 0.3–0.8 s rests between fast swings, |a| at rest 2.7 % high."""
    rng = np.random.default_rng(kw.pop("seed", 3))
    ang = np.where(np.arange(n_steps + 1) % 2 == 0, 0.0, 40.0) + rng.uniform(-3, 3, n_steps + 1)
    ang[0] = 0.0
    holds = np.r_[1.0, rng.uniform(0.3, 0.8, n_steps)]
    base = dict(angles_deg=tuple(ang), axis=(0.0, 1.0, 0.2), fs_hz=1200.0, hold_s=holds, rate_deg_s=300.0,
                g_error=0.027, gyro_bias_deg_s=(2.5, -3.0, 0.8), lever_arm_m=(0.0, 0.0, 0.4))
    base.update(kw)
    return hinge_log(**base)


def six_position_log(alpha_deg=(0.5, -0.3, 0.4), *, fs_hz=200.0, g_error=0.011, gyro_bias_deg_s=(0.8, -1.1, 1.6),
                     gyro_noise=2e-4, accel_noise=1.5e-3, positions_deg=None, seed=11):
    """wang2023cja §3.2 six-position schedule with a mounting error and MEMS quirks.

    Returns (DataFrame of the log, DataFrame of the positions, mounting angles in deg).
    """
    from mtcal.methods import six_position

    rng = np.random.default_rng(seed)
    pos = six_position.six_positions_rad() if positions_deg is None else np.radians(np.asarray(positions_deg, float))
    prof = six_position.schedule_profile(pos, fs_hz=fs_hz)
    model = ImuErrorModel(gyro=SensorErrors(bias=tuple(np.radians(gyro_bias_deg_s)), noise_density=gyro_noise),
                          accel=SensorErrors(noise_density=accel_noise, scale_factor=g_error),
                          q_mount=tuple(rotations.mount_quaternion(np.radians(alpha_deg))))
    rec = simulate_imu(profiles.trajectory_from_euler_zxy(prof), model, rng)
    df = _frame(rec.time_s, rec.gyro_rad_s, rec.accel_m_s2)
    positions = pd.DataFrame(np.degrees(pos), columns=["yaw_deg", "pitch_deg", "roll_deg"])
    return df, positions, np.asarray(alpha_deg, float)


def walking_log(n_steps=10, *, fs_hz=1200.0, stance_s=(0.2, 0.8), swing_s=0.4, heel_toe_deg_s=30.0,
                swing_deg_s=400.0, stand_s=1.5, gyro_bias_deg_s=(1.5, -2.0, 0.7), g_error=0.02, seed=5):
    """Foot-mounted IMU while walking: standing start and end, stance phases of ``stance_s`` s with a
    heel roll and a toe roll of up to ``heel_toe_deg_s`` (first/last 0.06 s), heel-strike impacts,
    swings turning up to ``swing_deg_s`` about the foot's y axis with large accelerations.

    Returns (DataFrame, stance spans [(t0, t1)] including the standing start and end, swing spans).
    """
    rng = np.random.default_rng(seed)
    segs = [("stand", stand_s)]
    for _ in range(n_steps):
        segs += [("swing", swing_s * rng.uniform(0.85, 1.15)), ("stance", rng.uniform(*stance_s))]
    segs += [("swing", swing_s), ("stand", stand_s)]
    rate = []
    lin = []
    kinds = []
    for kind, dur in segs:
        n = int(round(dur * fs_hz))
        tt = np.arange(n) / fs_hz
        r = np.zeros(n)
        la = np.zeros((n, 3))
        if kind == "swing":  # net zero rotation: the foot lands as flat as it left
            r = np.radians(swing_deg_s) * np.sin(2 * np.pi * tt / dur)
            la[:, 0] = 12.0 * np.sin(2 * np.pi * tt / dur + 0.3)
            la[:, 2] = 6.0 * np.sin(4 * np.pi * tt / dur)
        elif kind == "stance":
            edge = min(0.06, dur / 4)
            heel = tt < edge
            toe = tt > dur - edge
            r[heel] = -np.radians(heel_toe_deg_s) * np.sin(np.pi * tt[heel] / edge)
            r[toe] = np.radians(heel_toe_deg_s) * np.sin(np.pi * (tt[toe] - (dur - edge)) / edge)
            imp = tt < 0.03
            la[imp, 2] = 25.0 * np.exp(-tt[imp] / 0.008) * np.cos(2 * np.pi * 60 * tt[imp])
            la[imp, 0] = -10.0 * np.exp(-tt[imp] / 0.008)
        rate.append(r)
        lin.append(la)
        kinds += [kind] * n
    r = np.concatenate(rate)
    la = np.concatenate(lin)
    t = np.arange(r.size) / fs_hz
    pitch = np.cumsum(r) / fs_hz
    gmag = G * (1 + g_error)
    accel = np.column_stack([-gmag * np.sin(pitch), np.zeros_like(pitch), gmag * np.cos(pitch)]) + la
    gyro = np.column_stack([np.zeros_like(r), r, np.zeros_like(r)]) + np.radians(gyro_bias_deg_s)
    gyro += rng.normal(0, 0.004, gyro.shape)
    accel += rng.normal(0, 0.03, accel.shape)
    df = _frame(t, gyro, accel)
    kinds = np.array(kinds)
    spans = {}
    for k in ("stand", "stance", "swing"):
        flag = kinds == k
        d = np.diff(np.r_[0, flag.astype(int), 0])
        spans[k] = [(float(t[s]), float(t[e - 1])) for s, e in zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1))]
    stances = sorted(spans["stand"] + spans["stance"])
    return df, stances, spans["swing"]
