"""wang2023cja scenarios: turntable tests T1–T4, sweeps, wind tunnel — with a named error budget.

Everything the seed-000 notebooks simulate is defined here as frozen
dataclasses whose every value carries a unit and a source (field
``metadata``), plus the runners that turn a scenario into the paper's
tables (notebooks only call these).

Frames and the installation error
---------------------------------
* Body (b) = turntable / model, attitude ``q_wb`` from the reference angles
  with Eq 9 (ZXY: yaw ψ about z, pitch θ about x, roll γ about y).
* Sensor (s) = IMU. Eq 1 gives ``C_b^s = Rz(α1) Ry(α2) Rx(α3)`` (b → s, i.e.
  ``v_s = C_b^s v_b``: the b-frame is the s-frame rotated about z_s by α1,
  then y by α2, then x by α3). The simulator's ``q_mount`` is ``q_bs`` with
  ``v_b = C(q_bs) v_s``, hence ``C(q_bs) = (C_b^s)ᵀ`` (:func:`mount_quaternion`).
  In the ZXY frame α1 is a yaw-axis, α3 a pitch-axis and α2 a roll-axis
  installation angle.
* The QNCF output is zeroed at the start (§4.1 "the three initial attitude
  angles are 0°"): ``q_s(t) = q_est(0)⁻¹ ⊗ q_est(t)``; with the body starting
  at zero this is ``q_bs⁻¹ ⊗ q_wb(t) ⊗ q_bs`` (:func:`predicted_before`).
  The exact map to the body is then linear, ``q_wb = L(q_bs) R(q_bs⁻¹) q_s``
  (:func:`true_error_matrix`) — what Eq 13 has to recover.

Fit of the installation angles (REPRODUCTION.md §1)
---------------------------------------------------
:func:`fit_installation_angles` fits α1..α3 to the "before − reference"
columns of Tables 1–4 (18 numbers each). With Eq 8/9 exactly as printed the
fit explains almost nothing (rms 0.12/0.57/0.46/1.22° vs 0.12/0.57/0.46/1.23°
raw). If the paper's roll is measured with the opposite sign of Eq 8 (any
odd number of axis sign flips fits equally — a handedness change; cf. the
printed turntable matrix with Q(3,3) = −1.000355, whose q2 = roll-axis row is
negated, and the §3.2 axis conflict), the fit drops to 0.02/0.15/0.17/0.17°
and gives physically sensible angles (T2: −1.15° about the pitch axis, T4:
−2.49° about the yaw axis). :data:`PAPER_SIGN` holds that mapping: the paper's
angles are ``PAPER_SIGN · (Eq 8 angles)``; simulations run in the proper
Eq 8/9 frame at positions ``PAPER_SIGN · reference`` and are displayed in the
paper's sign.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace

import numpy as np
import pandas as pd
from scipy.optimize import least_squares

from mtcal.methods import quaternion_lsq as calibration, six_position as sixpos
from mtcal.core import metrics, rotations
from mtcal.core.rotations import mount_quaternion, relative_to_initial
from mtcal.core.units import ARCSEC, DEG, DEG_H, UG
from mtcal.reporting.compare import band_record
from mtcal.reporting import paper_numbers as paper
from mtcal.filters.qncf import QncfParams, qncf
from mtcal.core.profiles import AngleProfile, step_schedule, trajectory_from_euler_zxy
from mtcal.core.simulate import ImuErrorModel, ImuRecord, SensorErrors, Trajectory, simulate_imu

__all__ = ["PAPER_SIGN", "TABLES_1_TO_4", "true_error_matrix", "predicted_before", "fit_installation_angles",
           "ImuSpec", "SOURCES", "TurntableScenario", "WindTunnelScenario", "run_turntable", "TurntableJob",
           "run_turntable_jobs", "run_turntable_mc", "run_windtunnel", "position_errors_deg",
           "sweep_mean_table", "sweep_mean_max_error_deg", "sweep_mean_records", "error_metric_table",
           "show_error_metric_table", "plot_before_after", "InstallationFit",
           "turntable_profile", "six_position_reference", "TurntableRun", "mechanism_actual", "WindTunnelRun",
           "elastic_deflection_rad"]

#: Paper angle = PAPER_SIGN · Eq 8 angle (roll sign flipped; see module docstring).
PAPER_SIGN = np.array([1.0, 1.0, -1.0])

TABLES_1_TO_4 = {
    "T1": "wang2023cja_table01_positions",
    "T2": "wang2023cja_table02_positions_large_pitch_error",
    "T3": "wang2023cja_table03_positions_large_pitch_roll_error",
    "T4": "wang2023cja_table04_positions_all_large_errors",
}



def _f(value, unit: str, source: str):
    """Dataclass field with unit and source metadata."""
    return field(default=value, metadata={"unit": unit, "source": source})


# --------------------------------------------------------------------------
# installation error: mapping and fit
# --------------------------------------------------------------------------


def true_error_matrix(alpha_rad) -> np.ndarray:
    """Exact Q_s^b (4×4) for the zeroed QNCF output: ``q_wb = L(q_bs) R(q_bs⁻¹) q_s``."""
    q_bs = mount_quaternion(alpha_rad)
    return rotations.left_matrix(q_bs) @ rotations.right_matrix(rotations.quat_conjugate(q_bs))


def predicted_before(alpha_rad, reference_rad) -> np.ndarray:
    """Noise-free zeroed sensor angles (Eq 8, rad) at body angles ``reference_rad`` (K, 3)."""
    ref = np.asarray(reference_rad, dtype=float)
    q_bs = mount_quaternion(alpha_rad)
    q_wb = rotations.quat_from_euler_zxy(ref[:, 0], ref[:, 1], ref[:, 2])
    q_s = rotations.quat_multiply(rotations.quat_conjugate(q_bs), rotations.quat_multiply(q_wb, q_bs))
    return rotations.euler_zxy_from_quat(q_s)


def _table_angles(table: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    df = paper.load(table)
    cols = lambda kind: [f"{a}_{kind}_deg" for a in ("yaw", "pitch", "roll")]  # noqa: E731
    return tuple(np.radians(df[cols(k)].to_numpy(float)) for k in ("reference", "before", "after"))


@dataclass(frozen=True)
class InstallationFit:
    """Result of :func:`fit_installation_angles` (angles in rad, residuals in deg)."""

    alpha_rad: np.ndarray
    residual_deg: np.ndarray
    rms_deg: float
    raw_rms_deg: float


def fit_installation_angles(table: str, sign=PAPER_SIGN) -> InstallationFit:
    """Fit α1..α3 to a paper table's "before − reference" (Tables 1–4), least squares in deg.

    Model: paper_before = sign · predicted_before(α, sign · reference).
    ``sign=(1, 1, 1)`` is Eq 8/9 as printed.
    """
    ref, before, _ = _table_angles(table)
    s = np.asarray(sign, dtype=float)

    def resid(a):
        return np.degrees(metrics.angle_difference(s * predicted_before(a, ref * s), before)).ravel()
    best = None
    for x0 in (np.zeros(3), np.radians([1, 1, 1]), np.radians([-1, 1, -1]), np.radians([1, -1, 1])):
        r = least_squares(resid, x0, xtol=1e-14, ftol=1e-14, gtol=1e-14)
        if best is None or r.cost < best.cost:
            best = r
    raw = np.degrees(metrics.angle_difference(before, ref))
    return InstallationFit(best.x, best.fun.reshape(-1, 3), float(np.sqrt(np.mean(best.fun**2))),
                           float(np.sqrt(np.mean(raw**2))))


# --------------------------------------------------------------------------
# IMU error budget
# --------------------------------------------------------------------------
#: Error sources that can be switched individually (error-budget table).
SOURCES = ("gyro_white", "gyro_bias_instability", "gyro_residual_bias", "gyro_warmup",
           "gyro_scale_factor", "accel_white", "accel_bias", "quantisation", "reference_angle")


@dataclass(frozen=True)
class ImuSpec:
    """Tactical MEMS IMU of wang2023cja (the paper gives no sensor numbers: plausible values).

    Every field: value, unit and source in ``metadata`` (:func:`describe`).
    """

    gyro_arw_rad_s_rthz: float = _f(0.1 / 60 * DEG, "rad/s/√Hz",
                                    "ARW 0.1 °/√h: high-precision MEMS gyro class (ADIS16495: 0.12 °/√h)")
    gyro_bias_instability_rad_s: float = _f(0.8 * DEG_H, "rad/s",
                                            "0.8 °/h, τ = 100 s (ADIS16495 in-run stability class)")
    gyro_residual_bias_rad_s: float = _f(0.3 * DEG_H, "rad/s",
                                         "1σ turn-on bias left after factory compensation (§2: 'calibrated and "
                                         "compensated before use'); drives the yaw drift between calibration and test")
    gyro_warmup_bias_rad_s: tuple = _f((18 * DEG_H, -12 * DEG_H, 15 * DEG_H), "rad/s",
                                       "bias at power-on, decaying with τ = 90 s; after the 5-min warm-up "
                                       "(§3.2 step 1) ≈ 0.6 °/h remains")
    gyro_warmup_tau_s: float = _f(90.0, "s", "assumed thermal settling time constant")
    gyro_scale_factor: tuple = _f((8e-5, -6e-5, 1e-4), "1", "residual scale factor after factory "
                                  "calibration (≈ 100 ppm); tilt error made during a move decays with the "
                                  "QNCF time constant 1/K_p (QNCF settling)")
    gyro_lsb_rad_s: float = _f(0.00625 * DEG, "rad/s", "16-bit output LSB 0.00625 °/s (ADIS1649x)")
    accel_vrw_m_s2_rthz: float = _f(25 * UG, "m/s²/√Hz", "25 µg/√Hz: high-stability MEMS accelerometer "
                                    "(ADXL355: 22.5 µg/√Hz, wang2022sensors Table 2)")
    accel_residual_bias_m_s2: float = _f(50 * UG, "m/s²", "1σ residual bias after compensation (tactical class)")
    accel_lsb_m_s2: float = _f(3.9 * UG, "m/s²", "20-bit LSB at ±2 g (ADXL355: 3.9 µg)")
    time_since_power_on_s: float = _f(300.0, "s", "§3.2 step (1): 5 min warm-up")

    def error_model(self, q_mount, sources=SOURCES) -> ImuErrorModel:
        """``ImuErrorModel`` with only ``sources`` switched on (names from :data:`SOURCES`)."""
        on = set(sources)
        unknown = on - set(SOURCES)
        if unknown:
            raise ValueError(f"sources must be names from {SOURCES}, got {sorted(unknown)}")
        q = "quantisation" in on
        gyro = SensorErrors(
            noise_density=self.gyro_arw_rad_s_rthz if "gyro_white" in on else 0.0,
            bias_instability=self.gyro_bias_instability_rad_s if "gyro_bias_instability" in on else 0.0,
            bias_instability_tau_s=100.0,
            bias_sigma=self.gyro_residual_bias_rad_s if "gyro_residual_bias" in on else 0.0,
            warmup_bias=self.gyro_warmup_bias_rad_s if "gyro_warmup" in on else 0.0,
            warmup_tau_s=self.gyro_warmup_tau_s,
            scale_factor=self.gyro_scale_factor if "gyro_scale_factor" in on else 0.0,
            quantization=self.gyro_lsb_rad_s if q else 0.0)
        accel = SensorErrors(
            noise_density=self.accel_vrw_m_s2_rthz if "accel_white" in on else 0.0,
            bias_sigma=self.accel_residual_bias_m_s2 if "accel_bias" in on else 0.0,
            quantization=self.accel_lsb_m_s2 if q else 0.0)
        return ImuErrorModel(gyro=gyro, accel=accel, q_mount=tuple(np.asarray(q_mount, float)),
                             time_since_power_on_s=self.time_since_power_on_s)


# --------------------------------------------------------------------------
# scenarios
# --------------------------------------------------------------------------
@dataclass(frozen=True)
class TurntableScenario:
    """High-precision three-axis turntable (§4.1): tests T1–T4, AoA sweep, roll sweep."""

    imu: ImuSpec = field(default_factory=ImuSpec)
    qncf: QncfParams = field(default_factory=QncfParams)
    alpha_deg: dict = _f(None, "deg", "fit_installation_angles(Tables 1–4, PAPER_SIGN), rounded to 1e-4°")
    fs_hz: float = _f(1000.0, "Hz", "§4.1 data sampling frequency")
    rest_s: float = _f(3.0, "s", "§3.2 rest per position")
    turntable_rate_rad_s: float = _f(20 * DEG, "rad/s", "assumed mean move rate of the turntable")
    reference_angle_sigma_rad: float = _f(5 * ARCSEC, "rad", "turntable positioning accuracy ±5″ class "
                                          "(cf. SGT320E in wang2022sensors), 1σ per axis per position")
    averaging_fraction: float = _f(0.5, "1", "middle half of each rest is averaged (§3.2 'middle section')")
    aoa_sweep_deg: tuple = _f((-4, 0, 4, 8, 12, 13, -5, 13), "deg", "Table 5 reference order")
    aoa_rate_rad_s: float = _f(4 * DEG, "rad/s", "assumed AoA sweep rate")
    sweep_hold_s: float = _f(5.0, "s", "assumed hold per sweep position")
    roll_sweep_deg: tuple = _f((90, 60, 30, 0, -30, -60, -90, 90), "deg", "Table 7 reference order")
    roll_rate_rad_s: float = _f(20 * DEG, "rad/s", "assumed roll sweep rate")

    def __post_init__(self) -> None:
        if self.alpha_deg is None:
            object.__setattr__(self, "alpha_deg", {
                "T1": (-0.2434, -0.0359, 0.0521), "T2": (-0.0130, 0.0184, -1.1484),
                "T3": (-0.2833, 0.2903, -0.8426), "T4": (-2.4856, -0.3096, -0.2227)})

    def alpha_rad(self, test: str) -> np.ndarray:
        return np.radians(self.alpha_deg[test])


@dataclass(frozen=True)
class WindTunnelScenario:
    """Hypersonic wind tunnel (§4.2): support mechanism, wind-off sweep, five wind-on groups."""

    imu: ImuSpec = field(default_factory=ImuSpec)
    qncf: QncfParams = field(default_factory=QncfParams)
    alpha_deg: tuple = _f((0.08, -0.05, 0.01), "deg", "chosen so that wind-off roll/yaw errors before "
                          "calibration are of Table 11's size (paper gives no installation data)")
    fs_hz: float = _f(1000.0, "Hz", "§4.1/§3.2 1 kHz")
    rest_s: float = _f(3.0, "s", "§3.2")
    cal_yaw_deg: tuple = _f((4.0, -4.0), "deg", "assumed mechanism yaw range")
    cal_pitch_deg: tuple = _f((-5.0, 13.0), "deg", "AoA range of Tables 9/10")
    cal_roll_deg: tuple = _f((30.0, -30.0), "deg", "assumed mechanism roll range")
    mechanism_rate_rad_s: float = _f(2 * DEG, "rad/s", "assumed mechanism rate (groups 1–4)")
    group5_rate_rad_s: float = _f(1 * DEG, "rad/s", "Group 5: different rate (§4.2, value not given)")
    pitch_ratio_error: float = _f(-0.0038, "1", "mechanism pitch transmission-ratio error; Table 9's before "
                                  "slope is −0.0045 °/°, reduced so the simulated max before error ≈ 0.05° "
                                  "(other terms add); explains the printed non-orthogonal diag 1.004462")
    transmission_gap_rad: float = _f(0.02 * DEG, "rad", "backlash: actual lags command by ±gap/2 "
                                     "depending on approach direction (§4.2 'transmission gap')")
    servo_lag_s: float = _f(0.002, "s", "servo following error: stops short by lag × mean move rate")
    non_orthogonality_rad: tuple = _f((0.0008, -0.0005), "rad/rad", "yaw and roll picked up per rad of "
                                      "pitch (mechanism non-orthogonality, §4.2)")
    repeatability_rad: float = _f(0.004 * DEG, "rad", "1σ mechanism repeatability per hold")
    aoa_sweep_deg: tuple = _f((-4, 0, 4, 8, 12, 13, -5, 13), "deg", "Table 9 reference order")
    wind_on_sweep_deg: tuple = _f((-4, 0, 4, 8, 12), "deg", "Table 10 reference angles")
    hold_s: float = _f(5.0, "s", "assumed hold per AoA position")
    elastic_true_deg: tuple = _f((0.0151, 0.01478), "deg, deg/deg", "true deflection c0 + c1·α, fitted to "
                                 "Table 10 Mean row (measured ≈ true after calibration)")
    elastic_model_deg: tuple = _f((-0.0050, 0.01413), "deg, deg/deg", "tunnel's elastic-correction model, "
                                  "fitted to Table 10 'After elastic angle correction' row")
    dynamic_pressure_sigma: float = _f(0.02, "1", "run-to-run dynamic-pressure scatter (assumed 2 %)")
    vibration_accel_m_s2: float = _f(3.0, "m/s²", "model vibration with wind on (assumed; trips the AMD)")
    vibration_freq_hz: float = _f(45.0, "Hz", "assumed first bending mode of model + sting")
    vibration_angle_rad: float = _f(0.01 * DEG, "rad", "angular pitch vibration amplitude (assumed)")
    wind_on_hold_s: float = _f(3.0, "s", "assumed hold per AoA with wind (short hypersonic run)")
    group_interval_s: float = _f(600.0, "s", "assumed time between wind-on runs (IMU stays powered)")


# --------------------------------------------------------------------------
# helpers
# --------------------------------------------------------------------------


def _concat_profiles(parts: list[AngleProfile]) -> tuple[AngleProfile, list[slice]]:
    """Join profiles end to end (each starts where the previous ended); return spans."""
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
    prof = AngleProfile(t, *(np.concatenate(fields_[k], axis=0) for k in fields_))
    return prof, spans


def _holds(prof: AngleProfile, span: slice, fraction: float) -> list[slice]:
    """Middle ``fraction`` of each hold inside ``span`` (evaluation windows, schedule known)."""
    seg = prof.segment[span]
    out = []
    for s in np.unique(seg[seg % 2 == 0]):
        idx = np.flatnonzero(seg == s) + span.start
        out.append(slice(int(idx[0]), int(idx[-1]) + 1))
    return sixpos.middle_slices(out, fraction)


# --------------------------------------------------------------------------
# turntable runner
# --------------------------------------------------------------------------
def turntable_profile(sc: TurntableScenario, with_sweeps: bool) -> tuple[AngleProfile, dict]:
    """Six-position calibration (+ AoA sweep + roll sweep) on the turntable, Eq 8 frame."""
    pos = six_position_reference(sc)
    cal = sixpos.schedule_profile(pos, rate_rad_s=sc.turntable_rate_rad_s, rest_s=sc.rest_s, fs_hz=sc.fs_hz)
    parts, names = [cal], ["calibration"]
    if with_sweeps:
        aoa = np.zeros((len(sc.aoa_sweep_deg) + 2, 3))
        aoa[1:-1, 1] = np.radians(sc.aoa_sweep_deg)
        parts.append(step_schedule(aoa, sc.aoa_rate_rad_s, np.r_[1.0, np.full(len(sc.aoa_sweep_deg),
                                   sc.sweep_hold_s), 1.0], sc.fs_hz, min_move_s=0.5))
        roll = np.zeros((len(sc.roll_sweep_deg) + 2, 3))
        roll[1:-1, 2] = PAPER_SIGN[2] * np.radians(sc.roll_sweep_deg)
        parts.append(step_schedule(roll, sc.roll_rate_rad_s, np.r_[1.0, np.full(len(sc.roll_sweep_deg),
                                   sc.sweep_hold_s), 1.0], sc.fs_hz, min_move_s=0.5))
        names += ["aoa", "roll"]
    prof, spans = _concat_profiles(parts)
    return prof, dict(zip(names, spans))


def six_position_reference(sc) -> np.ndarray:
    """Six reference positions in the Eq 8 frame (paper order, roll sign per PAPER_SIGN), (6, 3) rad."""
    return sixpos.six_positions_rad() * PAPER_SIGN


def _reference_draws(rng, trials: int, k: int, sigma: float, on: bool) -> np.ndarray:
    e = rng.standard_normal((trials, k, 3)) * sigma
    return e if on else np.zeros_like(e)


@dataclass
class TurntableRun:
    """Per-trial results of :func:`run_turntable` (angles rad, Eq 8 frame; display with PAPER_SIGN)."""

    q_matrix: np.ndarray          # (T, 4, 4)
    cal_before: np.ndarray        # (T, 6, 3)
    cal_after: np.ndarray         # (T, 6, 3)
    reference: np.ndarray         # (6, 3)
    sweeps: dict | None = None    # filled for with_sweeps
    trace: dict | None = None     # trial-0 time series for figures


@dataclass(frozen=True)
class TurntableJob:
    """One Monte Carlo set for :func:`run_turntable_jobs`.

    Attributes
    ----------
    test : {"T1", "T2", "T3", "T4"}
        Installation angles (fitted to Tables 1–4).
    rng : numpy.random.Generator
        The set's own generator (split into blocks of ``block`` trials).
    trials : int
        Monte Carlo trials.
    sources : tuple of str
        Error sources switched on (names from :data:`SOURCES`).
    fraction : float, optional
        Averaging fraction of each rest (default ``sc.averaging_fraction``).
    """

    test: str
    rng: np.random.Generator
    trials: int
    sources: tuple = SOURCES
    fraction: float | None = None


def _check_sources(sources) -> tuple:
    src = tuple(sources)
    unknown = set(src) - set(SOURCES)
    if unknown:
        raise ValueError(f"sources must be names from {SOURCES}, got {sorted(unknown)}")
    return src


def _run_pieces(sc: TurntableScenario, prof: AngleProfile, spans: dict, pieces: list, with_sweeps: bool,
                keep_trace: bool) -> list[TurntableRun]:
    """Simulate every piece ``(test, sources, rng, trials, fraction)``, run ONE stacked QNCF, finish each.

    The QNCF cost is dominated by its loop over time, so stacking the pieces
    along the trial axis costs about one run, whatever their number. Each
    piece keeps its own generator, so its numbers do not depend on the stacking.
    """
    traj = trajectory_from_euler_zxy(prof)
    gyro, accel, rng_refs = [], [], []
    for test, sources, rng, trials, _ in pieces:
        rng_imu, rng_ref = rng.spawn(2)
        model = sc.imu.error_model(mount_quaternion(sc.alpha_rad(test)), sources)
        rec = simulate_imu(traj, model, rng=rng_imu, trials=trials)
        gyro.append(rec.gyro_rad_s)
        accel.append(rec.accel_m_s2)
        rng_refs.append(rng_ref)
    del rec
    gyro = np.concatenate(gyro, axis=0)
    res = qncf(gyro, np.concatenate(accel, axis=0), 1.0 / sc.fs_hz, sc.qncf, return_euler=False)
    del accel
    q_s = relative_to_initial(res.q_ws)
    del res
    pos = six_position_reference(sc)
    cal_span = spans["calibration"]
    out, start = [], 0
    for i, ((_, sources, _, trials, fraction), rng_ref) in enumerate(zip(pieces, rng_refs)):
        sl = slice(start, start + trials)
        start += trials
        frac = sc.averaging_fraction if fraction is None else fraction
        cal = sixpos.calibrate(q_s[sl, cal_span], pos, sc.fs_hz, gyro_rad_s=gyro[sl, cal_span], fraction=frac)
        # reference-angle (turntable positioning) errors: the reference the LS is fed differs from truth
        ref_err = _reference_draws(rng_ref, trials, 6, sc.reference_angle_sigma_rad, "reference_angle" in sources)
        ref_used = pos + ref_err
        q_ref = rotations.quat_from_euler_zxy(ref_used[..., 0], ref_used[..., 1], ref_used[..., 2])
        q_mat = calibration.least_squares_error_matrix(cal.q_sensor, q_ref)
        after = calibration.apply_error_matrix(q_mat, cal.q_sensor)
        run = TurntableRun(q_mat, rotations.euler_zxy_from_quat(cal.q_sensor),
                           rotations.euler_zxy_from_quat(after), pos)
        if with_sweeps:
            run.sweeps, run.trace = _evaluate_sweeps(sc, prof, spans, q_s[sl], q_mat, frac, keep_trace and i == 0)
        out.append(run)
    return out


def run_turntable(sc: TurntableScenario, test: str, rng: np.random.Generator, trials: int,
                  sources=SOURCES, *, with_sweeps: bool = False, fraction: float | None = None,
                  keep_trace: bool = False) -> TurntableRun:
    """Simulate one turntable test end to end: IMU → QNCF → six-position LS → evaluation.

    Parameters
    ----------
    sc : TurntableScenario
    test : {"T1", "T2", "T3", "T4"}
        Installation angles to use (fitted to Tables 1–4).
    rng : numpy.random.Generator
        Split into independent children: IMU (one child per simulator error
        source), reference-angle errors.
    trials : int
        Monte Carlo trials (vectorised).
    sources : iterable of str
        Error sources switched on (error budget).
    with_sweeps : bool
        Append the AoA and roll sweeps (Tables 5–8) after the calibration.
    fraction : float, optional
        Averaging fraction of each rest (default ``sc.averaging_fraction``).
    keep_trace : bool
        Keep trial-0 error time series of the sweeps (figures).
    """
    prof, spans = turntable_profile(sc, with_sweeps)
    piece = (test, _check_sources(sources), rng, int(trials), fraction)
    return _run_pieces(sc, prof, spans, [piece], with_sweeps, keep_trace)[0]


def _concat_runs(runs: list) -> "TurntableRun":
    cat = lambda xs: np.concatenate(xs, axis=0)  # noqa: E731
    out = TurntableRun(cat([r.q_matrix for r in runs]), cat([r.cal_before for r in runs]),
                       cat([r.cal_after for r in runs]), runs[0].reference, None, runs[0].trace)
    if runs[0].sweeps is not None:
        out.sweeps = {name: {k: (v if k == "reference" else cat([r.sweeps[name][k] for r in runs]))
                             for k, v in d.items()} for name, d in runs[0].sweeps.items()}
    return out


def run_turntable_jobs(sc: TurntableScenario, jobs: list[TurntableJob], *, with_sweeps: bool = False,
                       keep_trace: bool = False, block: int = 50,
                       max_trial_samples: int = 9_000_000) -> list[TurntableRun]:
    """Several Monte Carlo sets (tests, error budgets, averaging fractions) sharing QNCF runs.

    Each job is split into blocks of ``block`` trials, block ``i`` drawing
    from ``job.rng.spawn(n_blocks)[i]`` (the same streams as
    :func:`run_turntable_mc`). Consecutive blocks are stacked into one QNCF
    run as long as trials × samples stays below ``max_trial_samples`` (memory
    bound, ≈ 1.5 GB peak at the default).

    Parameters
    ----------
    sc : TurntableScenario
    jobs : list of TurntableJob
    with_sweeps : bool
        Append the AoA and roll sweeps (Tables 5–8) to every job.
    keep_trace : bool
        Keep trial-0 sweep time series of the first job (figures).
    block : int
        Trials per generator block.
    max_trial_samples : int
        Largest trials × samples of one stacked QNCF run.

    Returns
    -------
    list of TurntableRun
        One per job, trials in job order.
    """
    if not jobs:
        raise ValueError("jobs must hold at least one TurntableJob")
    for job in jobs:
        if not isinstance(job, TurntableJob):
            raise TypeError(f"jobs must hold TurntableJob items, got {type(job).__name__}")
        if int(job.trials) < 1:
            raise ValueError(f"job trials must be >= 1, got {job.trials}")
        if job.test not in sc.alpha_deg:
            raise ValueError(f"job test must be one of {sorted(sc.alpha_deg)}, got {job.test!r}")
    if int(block) < 1:
        raise ValueError(f"block must be >= 1, got {block}")
    prof, spans = turntable_profile(sc, with_sweeps)
    per_call = max(int(block), int(max_trial_samples) // prof.time_s.size)
    pieces = []                                  # (job index, piece)
    for i, job in enumerate(jobs):
        src = _check_sources(job.sources)
        sizes = [min(block, job.trials - k) for k in range(0, job.trials, block)]
        pieces += [(i, (job.test, src, r, n, job.fraction)) for r, n in zip(job.rng.spawn(len(sizes)), sizes)]
    calls, count = [[]], 0
    for item in pieces:
        if calls[-1] and count + item[1][3] > per_call:
            calls.append([])
            count = 0
        calls[-1].append(item)
        count += item[1][3]
    per_job = [[] for _ in jobs]
    for c, call in enumerate(calls):
        runs = _run_pieces(sc, prof, spans, [p for _, p in call], with_sweeps, keep_trace and c == 0)
        for (i, _), run in zip(call, runs):
            per_job[i].append(run)
    return [_concat_runs(r) for r in per_job]


def run_turntable_mc(sc: TurntableScenario, test: str, rng: np.random.Generator, trials: int,
                     sources=SOURCES, *, batch: int = 50, with_sweeps: bool = False,
                     fraction: float | None = None, keep_trace: bool = False) -> "TurntableRun":
    """:func:`run_turntable` over many trials in memory-bounded blocks (independent child rngs)."""
    job = TurntableJob(test, rng, int(trials), tuple(sources), fraction)
    return run_turntable_jobs(sc, [job], with_sweeps=with_sweeps, keep_trace=keep_trace, block=batch)[0]


def _evaluate_sweeps(sc, prof, spans, q_s, q_mat, frac, keep_trace):
    truth = prof.angle_rad
    sweeps, trace = {}, {}
    for name, chan_mean, chans_err in (("aoa", 1, (2, 0)), ("roll", 2, (1, 0))):
        span = spans[name]
        before = rotations.euler_zxy_from_quat(q_s[:, span])
        after = rotations.euler_zxy_from_quat(calibration.apply_error_matrix(q_mat, q_s[:, span]))
        ref = truth[span]
        holds = [slice(h.start - span.start, h.stop - span.start) for h in _holds(prof, span, frac)][1:-1]
        sweeps[name] = {
            "reference": np.array([ref[h, chan_mean].mean() for h in holds]),
            "before_mean": np.stack([before[:, h, chan_mean].mean(axis=1) for h in holds], axis=1),
            "after_mean": np.stack([after[:, h, chan_mean].mean(axis=1) for h in holds], axis=1),
        }
        for state, est in (("before", before), ("after", after)):
            err = metrics.angle_difference(est, ref)
            for c in chans_err:
                sweeps[name][f"{state}_maxae_{c}"] = metrics.max_abs_error(err[..., c], axis=-1)
                sweeps[name][f"{state}_rmse_{c}"] = metrics.rmse(err[..., c], axis=-1)
            if keep_trace:
                trace[f"{name}_{state}_err"] = err[0]
        if keep_trace:
            trace[f"{name}_time_s"] = prof.time_s[span] - prof.time_s[span.start]
            trace[f"{name}_reference"] = ref
    return sweeps, trace


# --------------------------------------------------------------------------
# wind-tunnel runner
# --------------------------------------------------------------------------
def mechanism_actual(sc: WindTunnelScenario, prof: AngleProfile, rate_rad_s: float) -> np.ndarray:
    """Actual mechanism angles (N, 3) from commanded ones: ratio error, backlash + servo lag, non-orthogonality."""
    cmd = prof.angle_rad
    act = cmd.copy()
    act[:, 1] *= 1.0 + sc.pitch_ratio_error
    rate = prof.rate_rad_s[:, 1]
    moving = np.abs(rate) > 1e-9
    direction = np.where(moving, np.sign(rate), 0.0)
    idx = np.where(moving, np.arange(rate.size), 0)
    np.maximum.accumulate(idx, out=idx)
    last = direction[idx]
    last[~moving & (idx == 0)] = 1.0
    act[:, 1] -= last * (0.5 * sc.transmission_gap_rad + sc.servo_lag_s * rate_rad_s) * ~moving
    act[:, 0] += sc.non_orthogonality_rad[0] * cmd[:, 1]
    act[:, 2] += sc.non_orthogonality_rad[1] * cmd[:, 1]
    return act


def _wt_schedule(sc, waypoints_deg, rate, lead_s=8.0, hold_s=None):
    wp = np.zeros((len(waypoints_deg) + 2, 3))
    wp[1:-1, 1] = np.radians(waypoints_deg)
    hold = sc.hold_s if hold_s is None else hold_s
    return step_schedule(wp, rate, np.r_[lead_s, np.full(len(waypoints_deg), hold), 1.0], sc.fs_hz,
                         min_move_s=0.5)


def _traj_from_angles(t, angles) -> Trajectory:
    return Trajectory(t, rotations.quat_from_euler_zxy(angles[:, 0], angles[:, 1], angles[:, 2]))


@dataclass
class WindTunnelRun:
    """Per-trial wind-tunnel results (rad, Eq 8 frame)."""

    q_matrix: np.ndarray
    cal_before: np.ndarray
    cal_after: np.ndarray
    nowind: dict
    wind_on: dict | None
    trace: dict


def run_windtunnel(sc: WindTunnelScenario, rng: np.random.Generator, trials: int, sources=SOURCES,
                   *, wind_on: bool = True) -> WindTunnelRun:
    """Wind-off calibration + AoA sweep (Tables 9, 11) and five wind-on groups (Table 10).

    Truth = actual mechanism angles (:func:`mechanism_actual`) + elastic
    deflection with wind on; reference = commanded angles. With wind on the
    model vibrates (accelerometer ``vibration_accel_m_s2`` at
    ``vibration_freq_hz`` plus angular pitch vibration), which trips the AMD:
    the QNCF runs on the gyro alone.
    """
    rng_imu, rng_ref, rng_wind = rng.spawn(3)
    frac = 0.5
    on = set(sources)
    model = sc.imu.error_model(mount_quaternion(np.radians(sc.alpha_deg)), sources)
    # --- wind-off session: calibration then AoA sweep
    pos = sixpos.six_positions_rad(np.radians(sc.cal_yaw_deg), np.radians(sc.cal_pitch_deg),
                                   np.radians(sc.cal_roll_deg))
    cal_prof = sixpos.schedule_profile(pos, rate_rad_s=5 * DEG, rest_s=sc.rest_s, fs_hz=sc.fs_hz)
    aoa_prof = _wt_schedule(sc, sc.aoa_sweep_deg, sc.mechanism_rate_rad_s, lead_s=1.0)
    prof, spans = _concat_profiles([cal_prof, aoa_prof])
    spans = dict(zip(("calibration", "aoa"), spans))
    actual = mechanism_actual(sc, prof, sc.mechanism_rate_rad_s)
    rec = simulate_imu(_traj_from_angles(prof.time_s, actual), model, rng=rng_imu, trials=trials)
    res = qncf(rec.gyro_rad_s, rec.accel_m_s2, 1.0 / sc.fs_hz, sc.qncf, return_euler=False)
    q_s = relative_to_initial(res.q_ws)
    cal = sixpos.calibrate(q_s[:, spans["calibration"]], pos, sc.fs_hz,
                           gyro_rad_s=rec.gyro_rad_s[:, spans["calibration"]], fraction=frac)
    ref_err = _reference_draws(rng_ref, trials, 6, sc.repeatability_rad, "reference_angle" in on)
    ref_used = pos + ref_err
    q_mat = calibration.least_squares_error_matrix(
        cal.q_sensor, rotations.quat_from_euler_zxy(ref_used[..., 0], ref_used[..., 1], ref_used[..., 2]))
    after_cal = calibration.apply_error_matrix(q_mat, cal.q_sensor)
    span = spans["aoa"]
    before = rotations.euler_zxy_from_quat(q_s[:, span])
    after = rotations.euler_zxy_from_quat(calibration.apply_error_matrix(q_mat, q_s[:, span]))
    cmd = prof.angle_rad[span]
    holds = [slice(h.start - span.start, h.stop - span.start) for h in _holds(prof, span, frac)][1:-1]
    nowind = {"reference": np.array([cmd[h, 1].mean() for h in holds]),
              "before_mean": np.stack([before[:, h, 1].mean(axis=1) for h in holds], axis=1),
              "after_mean": np.stack([after[:, h, 1].mean(axis=1) for h in holds], axis=1)}
    for state, est in (("before", before), ("after", after)):
        err = metrics.angle_difference(est, cmd)
        for c in (2, 0):
            nowind[f"{state}_maxae_{c}"] = metrics.max_abs_error(err[..., c], axis=-1)
            nowind[f"{state}_rmse_{c}"] = metrics.rmse(err[..., c], axis=-1)
    trace = {"nowind_time_s": prof.time_s[span] - prof.time_s[span.start],
             "nowind_before_err": metrics.angle_difference(before[0], cmd),
             "nowind_after_err": metrics.angle_difference(after[0], cmd)}
    out = WindTunnelRun(q_mat, rotations.euler_zxy_from_quat(cal.q_sensor),
                        rotations.euler_zxy_from_quat(after_cal), nowind, None, trace)
    if wind_on:
        out.wind_on = _wind_on_groups(sc, model, q_mat, rng_wind, trials, out.trace)
    return out


def elastic_deflection_rad(coeffs_deg, alpha_rad) -> np.ndarray:
    """Linear elastic pitch deflection ``c0 + c1·α`` (deg, deg/deg coefficients) in rad."""
    c0, c1 = coeffs_deg
    return np.radians(c0) + c1 * np.asarray(alpha_rad)


def _wind_on_groups(sc, model, q_mat, rng, trials, trace):
    """Five wind-on AoA sweeps; each group its own record; all groups stacked as trials for the QNCF."""
    lead_s = 8.0
    group_rngs = rng.spawn(5)
    g_all, a_all, profs = [], [], []
    for g in range(5):
        r_q, r_imu, r_vib = group_rngs[g].spawn(3)
        rate = sc.group5_rate_rad_s if g == 4 else sc.mechanism_rate_rad_s
        prof = _wt_schedule(sc, sc.wind_on_sweep_deg, rate, lead_s=lead_s, hold_s=sc.wind_on_hold_s)
        actual = mechanism_actual(sc, prof, rate)
        q_factor = 1.0 + sc.dynamic_pressure_sigma * r_q.standard_normal()
        t = prof.time_s
        ramp = np.clip((t - (lead_s - 3.0)) / 1.0, 0.0, 1.0)          # flow starts 3 s before the sweep
        phase = r_vib.uniform(0, 2 * np.pi)
        actual[:, 1] += ramp * (q_factor * elastic_deflection_rad(sc.elastic_true_deg, prof.angle_rad[:, 1])
                                + sc.vibration_angle_rad * np.sin(2 * np.pi * sc.vibration_freq_hz * t + phase))
        model_g = replace(model, time_since_power_on_s=model.time_since_power_on_s + sc.group_interval_s * (g + 1))
        rec = simulate_imu(_traj_from_angles(t, actual), model_g, rng=r_imu, trials=trials)
        vib = r_vib.uniform(0, 2 * np.pi, (trials, 1, 3))
        accel = rec.accel_m_s2 + (ramp[None, :, None] * sc.vibration_accel_m_s2
                                  * np.sin(2 * np.pi * sc.vibration_freq_hz * t[None, :, None] + vib))
        g_all.append(rec.gyro_rad_s)
        a_all.append(accel)
        profs.append(prof)
    n = max(p.time_s.size for p in profs)
    pad = lambda x: np.concatenate([x, np.repeat(x[:, -1:], n - x.shape[1], axis=1)], axis=1)  # noqa: E731
    gyro = np.concatenate([pad(x) for x in g_all], axis=0)
    accel = np.concatenate([pad(x) for x in a_all], axis=0)
    del g_all, a_all
    res = qncf(gyro, accel, 1.0 / sc.fs_hz, sc.qncf, return_euler=False)
    q_s = relative_to_initial(res.q_ws, n0=1)
    q_rep = np.concatenate([q_mat] * 5, axis=0)
    means = np.empty((5, trials, len(sc.wind_on_sweep_deg)))
    for g, prof in enumerate(profs):
        sl = slice(g * trials, (g + 1) * trials)
        span = slice(0, prof.time_s.size)
        holds = _holds(prof, span, 0.5)[1:-1]
        q_g = q_s[sl]
        for j, h in enumerate(holds):
            after = rotations.euler_zxy_from_quat(calibration.apply_error_matrix(q_rep[sl], q_g[:, h]))
            means[g, :, j] = after[..., 1].mean(axis=1)
        if g == 0:
            trace["amd_pct"] = res.amd_pct[0, :prof.time_s.size]
            trace["gate"] = res.gate[0, :prof.time_s.size]
        trace[f"wind_time_s_{g}"] = prof.time_s
        trace[f"wind_pitch_{g}"] = rotations.euler_zxy_from_quat(
            calibration.apply_error_matrix(q_rep[sl][:1], q_g[:1, :prof.time_s.size]))[0, :, 1]
    ref = np.radians(np.asarray(sc.wind_on_sweep_deg, float))
    return {"reference": ref, "group_means": means,
            "elastic_corrected": ref + elastic_deflection_rad(sc.elastic_model_deg, ref),
            "gate_fraction_on": float(res.gate[:, int(lead_s * sc.fs_hz):].mean()),
            "gate_fraction_on_trials": res.gate[:, int(lead_s * sc.fs_hz):].reshape(5, trials, -1).mean(axis=(0, 2))}


# --------------------------------------------------------------------------
# notebook helpers: Monte Carlo bands, paper tables, figures (display only)
# --------------------------------------------------------------------------


def position_errors_deg(run: TurntableRun, state: str) -> np.ndarray:
    """Per-trial errors (T, 6, 3) in deg of the six calibration positions, ``state`` "before"/"after"."""
    est = {"before": run.cal_before, "after": run.cal_after}.get(state)
    if est is None:
        raise ValueError(f"state must be 'before' or 'after', got {state!r}")
    return np.degrees(metrics.angle_difference(est, run.reference))


def sweep_mean_table(table: str, angle: str, sweep: dict, sign: float = 1.0, trial: int = 0) -> pd.DataFrame:
    """Paper vs mtcal hold means of a sweep (Tables 5, 7, 9), deg, paper sign; one trial shown.

    ``table`` is a paper file stem with columns ``{reference,before,after}_mean_<angle>_deg``;
    ``sweep`` holds ``before_mean``/``after_mean`` (T, K) in rad (Eq 8 frame, multiplied by ``sign``).
    """
    p = paper.load(table)
    col = lambda kind: p[f"{kind}_mean_{angle}_deg"].to_numpy(float)  # noqa: E731
    return pd.DataFrame({"reference": col("reference"),
                         "paper_before": col("before"), "mtcal_before": sign * np.degrees(sweep["before_mean"][trial]),
                         "paper_after": col("after"), "mtcal_after": sign * np.degrees(sweep["after_mean"][trial])})


def sweep_mean_max_error_deg(sweep: dict, state: str) -> np.ndarray:
    """Per-trial max |hold mean − reference| (deg) of a sweep, ``state`` "before"/"after", shape (T,)."""
    if state not in ("before", "after"):
        raise ValueError(f"state must be 'before' or 'after', got {state!r}")
    return np.degrees(np.abs(sweep[f"{state}_mean"] - sweep["reference"])).max(axis=1)


def sweep_mean_records(artifact: str, angle: str, paper_max_deg: dict, sweep: dict) -> dict:
    """Band records of the per-trial max |hold mean − reference| before and after calibration (deg).

    ``paper_max_deg`` maps ``"before"``/``"after"`` to the paper's largest deviation in the table.
    """
    return {state: band_record(artifact, f"max |{state}-ref| mean {angle} (deg)", paper_max_deg[state],
                               sweep_mean_max_error_deg(sweep, state)) for state in ("before", "after")}


def error_metric_table(table: str, sweep: dict, channels, trial: int = 0) -> pd.DataFrame:
    """MaxAE / RMSE table (Tables 6, 11): paper, one trial, MC median and 95 % band per row (deg).

    ``channels`` are ``(index, name)`` pairs, e.g. ``((2, "roll"), (0, "yaw"))``; ``sweep`` holds
    ``<state>_<maxae|rmse>_<index>`` arrays (T,) in rad.
    """
    p = paper.load(table)
    rows = []
    for metric, key in (("MaxAE", "maxae"), ("RMSE", "rmse")):
        for state in ("before", "after"):
            for j, ang in channels:
                pv = float(p.loc[(p.metric == metric) & (p.calibration_state == state), f"{ang}_deg"].iloc[0])
                x = np.degrees(sweep[f"{state}_{key}_{j}"])
                rec = band_record("", "", pv, x)
                rows.append({"metric": metric, "state": state, "angle": ang, "paper": pv, "mtcal": float(x[trial]),
                             "mc_median": rec["median"], "mc_low": rec["low"], "mc_high": rec["high"],
                             "paper_in_band": rec["paper_in_band"]})
    return pd.DataFrame(rows)


def show_error_metric_table(artifact: str, table: str, sweep: dict, channels) -> pd.DataFrame:
    """:func:`error_metric_table`, saved as ``artifact`` and shown, with the count of paper values in band."""
    from mtcal.reporting import output as report

    t = error_metric_table(table, sweep, channels)
    report.save_table(t, artifact)
    report.show_table(t)
    print(f"{int(t.paper_in_band.sum())} of {len(t)} paper numbers of {artifact} inside the 95 % band")
    return t


def plot_before_after(trace: dict, name: str, channels, *, xlabel: str, title: str):
    """Stacked before/after error panels (deg) of trace ``name`` for ``channels`` ``(index, name)``.

    ``trace`` holds ``<name>_time_s`` (s) and ``<name>_before_err`` / ``<name>_after_err`` (N, 3) in
    rad (the ``trace`` of a turntable or wind-tunnel run). Returns the Figure.
    """
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(len(channels), 1, sharex=True, figsize=(7, 5), squeeze=False)
    axes = axes[:, 0]
    for ax, (j, label) in zip(axes, channels):
        for state in ("before", "after"):
            ax.plot(trace[f"{name}_time_s"], np.degrees(trace[f"{name}_{state}_err"][:, j]), label=state, lw=0.8)
        ax.set_ylabel(f"{label} error (deg)")
    axes[0].legend()
    axes[-1].set_xlabel(xlabel)
    fig.suptitle(title)
    return fig
