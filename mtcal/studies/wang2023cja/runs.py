"""wang2023cja simulation runs: turntable sessions T1–T4 with sweeps, and the wind tunnel.

A run turns a resolved scenario (:mod:`.scenario`) into per-trial results; the artifact
producers (:mod:`.artifacts`) turn those into the paper's tables. As in the paper, "after
calibration" is measured on a **separate verification run**: the six-position calibration
run is followed, in the same power-on session (QNCF zeroed once at the start), by a second
six-position run (Tables 1–4) and, for T1, the AoA and roll sweeps (Tables 5–8). Between the
calibration and the verification runs the accelerometer bias changes (warm-up/temperature,
``ErrorModel.accel_run_bias_mg``), every rest has its own turntable angle error, and the IMU
tilts on a compliant mount with the lateral gravity (``ErrorModel.compliance_*``).

Frames: body (b) = turntable, attitude from the reference angles with Eq 9 (ZXY); sensor (s)
= IMU, ``q_mount = q_bs`` from Eq 1 (:func:`mtcal.core.rotations.mount_quaternion`). Angles
are in the Eq 8 frame; the paper's are ``PAPER_SIGN ·`` ours (roll sign, see
:func:`.error_model.fit_installation_angles`).

References
----------
wang2023cja §3.2 (procedure), §4.1 (turntable T1–T4), §4.2 (wind tunnel), Eq 1, 8, 9 (full citation: :mod:`mtcal.studies.wang2023cja`).
"""

from __future__ import annotations

import functools
import threading
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, replace

import numba

import numpy as np

from mtcal.core.cache import cached
from mtcal.core.montecarlo import progress
from mtcal.core import metrics, rotations
from mtcal.core.allocator import keep_freed_memory
from mtcal.core.profiles import AngleProfile, join_profiles, step_schedule
from mtcal.core.rng import child_rngs, stream_rng
from mtcal.core.rotations import mount_quaternion
from mtcal.core.simulate import RecordPiece, RecordSource, gravity_lateral_axis, load_tilt_outputs
from mtcal.core.units import DEG, MG
from mtcal.methods import six_position
from mtcal.systems import installation
from .error_model import MOUNT_TYPE, PAPER_SIGN
from .scenario import (SOURCES, TurntableScenario, WindTunnelScenario, _positions_rad, compliance_trajectory,
                       mechanism_actual, stop_directions)

#: Every trial's sweep error series is kept at every TRACE_DECIMATION-th sample (ensemble figures).
TRACE_DECIMATION = 20
#: Key of a T1 run's sweep scores holding the turntable angle error (T, holds) at each hold of the averaged
#: angle (rad), subtracted from its hold means (deviations ledger D6).
HOLD_ERROR_KEY = "hold_error_rad"

#: Gates of :func:`mtcal.systems.installation.calibrate_installation` in the Monte Carlo runs: all off
#: (``inf``, :meth:`~mtcal.systems.installation.InstallationConfig.monte_carlo`). The procedure and its
#: numbers are the CLI's; a Monte Carlo reports the spread of every trial instead of refusing the set
#: because one trial would be refused at the bench.
MONTE_CARLO_GATES = {k: getattr(installation.InstallationConfig.monte_carlo(), k)
                     for k in ("max_condition", "max_so4_distance", "max_residual_rad")}

__all__ = ["turntable_runs", "turntable_profile", "six_position_reference", "TurntableRun", "TurntableJob",
           "calibration_step", "run_turntable", "run_turntable_jobs", "run_turntable_jobs_kinds", "position_errors_deg", "load_tilt_outputs",
           "WindTunnelRun", "run_windtunnel", "run_windtunnel_kinds", "windtunnel_median_trial", "elastic_deflection_rad", "MONTE_CARLO_GATES",
           "TRACE_DECIMATION", "WIND_LEAD_S", "WIND_FLOW_START_S"]


def _euler(q: np.ndarray) -> np.ndarray:
    """Eq 8 angles (rad) of QNCF outputs, unit by construction: ``euler_zxy_from_quat`` unvalidated, same numbers.

    A non-finite angle (a failed calibration matrix applied to the attitude) raises instead of
    entering a band as NaN.
    """
    euler = rotations.euler_zxy_unchecked(np.asarray(q, dtype=float))
    if not np.isfinite(euler).all():
        raise FloatingPointError("Eq 8 angles are not finite: a calibration matrix or attitude of this run is NaN/inf")
    return euler


# --------------------------------------------------------------------------
# turntable session
# --------------------------------------------------------------------------
def turntable_profile(sc: TurntableScenario, with_sweeps: bool) -> tuple[AngleProfile, dict]:
    """Session schedule: calibration run, verification run (+ AoA sweep + roll sweep), Eq 8 frame."""
    return _session_schedule(sc, with_sweeps)[:2]


def _session_schedule(sc: TurntableScenario, with_sweeps: bool) -> tuple[AngleProfile, dict, np.ndarray]:
    """:func:`turntable_profile` and the six positions it visits (:func:`six_position_reference`)."""
    pos = six_position_reference(sc)
    cal = six_position.schedule_profile(pos, rate_rad_s=sc.turntable_rate_rad_s, rest_s=sc.rest_s, fs_hz=sc.fs_hz)
    parts, names = [cal, cal], ["calibration", "verification"]
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
    prof, spans = join_profiles(parts)
    return prof, dict(zip(names, spans)), pos


def six_position_reference(sc: TurntableScenario) -> np.ndarray:
    """Six reference positions in the Eq 8 frame (paper order, roll sign per PAPER_SIGN), (6, 3) rad."""
    return six_position.six_positions_rad(np.radians(sc.yaw_positions_deg), np.radians(sc.pitch_positions_deg),
                                          np.radians(sc.roll_positions_deg)) * PAPER_SIGN


@dataclass
class TurntableRun:
    """Per-trial results of a turntable session (angles rad, Eq 8 frame; display with PAPER_SIGN).

    ``cal_*`` are the calibration run's own rest means (in-sample); ``ver_*`` the separate
    verification run's; ``ref_err_*`` the turntable angle errors at those rests (truth − command).
    """

    q_matrix: np.ndarray          # (T, 4, 4)
    cal_before: np.ndarray        # (T, 6, 3)
    cal_after: np.ndarray         # (T, 6, 3)
    ver_before: np.ndarray        # (T, 6, 3)
    ver_after: np.ndarray         # (T, 6, 3)
    reference: np.ndarray         # (6, 3)
    ref_err_cal: np.ndarray       # (T, 6, 3)
    ref_err_ver: np.ndarray       # (T, 6, 3)
    sweeps: dict | None = None    # filled for with_sweeps
    trace: dict | None = None     # trial-0 time series for figures


@dataclass(frozen=True)
class TurntableJob:
    """One Monte Carlo set for :func:`run_turntable_jobs`.

    Attributes
    ----------
    test : {"T1", "T2", "T3", "T4"}
        Installation angles (fitted to Tables 1–4) and mount type.
    rng : numpy.random.Generator
        The set's own generator (split into blocks of ``block`` trials).
    trials : int
        Monte Carlo trials.
    sources : tuple of str
        Error sources switched on (names from :data:`SOURCES`).
    fraction : float, optional
        Averaging fraction of each rest (default ``sc.averaging_fraction``).
    errors : ErrorModel, optional
        The set's own hardware error model (default ``sc.errors``): one parameter draw of a
        predictive band.
    alpha_deg : 3-tuple, optional
        The set's own installation angles (deg; default ``sc.alpha_deg[test]``).
    """

    test: str
    rng: np.random.Generator
    trials: int
    sources: tuple = SOURCES
    fraction: float | None = None
    errors: object = None
    alpha_deg: tuple | None = None


def _check_sources(sources) -> tuple:
    src = tuple(sources)
    unknown = set(src) - set(SOURCES)
    if unknown:
        raise ValueError(f"sources must be names from {SOURCES}, got {sorted(unknown)}")
    return src


def _draws(rng, trials: int, k: int, sigma: float, on: bool) -> np.ndarray:
    e = rng.standard_normal((trials, k, 3)) * sigma
    return e if on else np.zeros_like(e)


def _workers() -> int:
    """Threads of the per-piece work: numba's thread count (``NUMBA_NUM_THREADS``, ``numba.set_num_threads``).

    One thread unless numba's threading layer takes parallel kernels launched from several threads
    at once (``omp``, ``tbb``; ``workqueue`` would abort the process).
    """
    n = int(numba.get_num_threads())
    if n < 2:
        return 1
    try:
        from numba.np.ufunc.parallel import _launch_threads   # starts (once) the layer a parallel kernel uses

        _launch_threads()
        layer = numba.threading_layer()
    except Exception:                                          # noqa: BLE001 - no usable layer: stay serial
        return 1
    return n if layer in ("omp", "tbb") else 1


def _map(fn, items: list) -> list:
    """``[fn(x) for x in items]``, the items spread over :func:`_workers` threads, results in item order.

    Every item owns its generator and writes only its own slice of the shared buffers, and the
    compiled kernels release the GIL: the numbers do not depend on the thread count.
    """
    n = min(_workers(), len(items))
    if n < 2:
        return [fn(x) for x in items]
    with ThreadPoolExecutor(n) as pool:
        return list(pool.map(fn, items))


@dataclass(frozen=True)
class _PieceSettings:
    """What a piece of a turntable run takes from its scenario (:func:`_piece_settings`), before its draws."""

    sources: tuple
    rng: np.random.Generator
    trials: int
    fraction: float
    alpha_rad: np.ndarray          # installation angles (rad)
    compliance_rad_g: float        # mount compliance (rad per g of lateral load; 0 without the source)
    imu: object                    # ImuSpec of the scenario (its error_model)
    errors: object                 # ErrorModel of the piece
    reference_sigma_rad: float     # turntable angle error (1σ, rad)
    accel_step_sigma_m_s2: float   # run-to-run accelerometer bias change (1σ, m/s²)
    load_tilt_sigma_rad: float     # gasket load tilt (1σ per g, rad)
    switched: tuple                # (turntable angle error, run change, load tilt) on; off: zeros, not drawn
    sweep_holds: tuple             # holds of each sweep of :data:`_SWEEPS` (with the sweeps), else ()


def _piece_settings(piece, with_sweeps: bool) -> _PieceSettings:
    """A piece ``(test, sources, rng, trials, fraction, scenario)`` of :func:`_job_pieces` resolved to the numbers
    its simulation takes (the mount compliance 0 when switched off)."""
    test, sources, rng, trials, _, sc = piece
    on = set(sources)
    gasket = MOUNT_TYPE[test] == "gasket"
    return _PieceSettings(
        sources, rng, trials, _fraction(piece), sc.alpha_rad(test),
        sc.errors.compliance_deg_g(MOUNT_TYPE[test]) * DEG if "mount_compliance" in on else 0.0, sc.imu, sc.errors,
        sc.reference_angle_sigma_rad, sc.errors.accel_run_bias_mg * MG, sc.errors.gasket_load_tilt_deg_g * DEG,
        ("reference_angle" in on, "accel_run_change" in on, "mount_compliance" in on and gasket),
        tuple(len(getattr(sc, f"{name}_sweep_deg")) for name, _, _ in _SWEEPS) if with_sweeps else ())


#: The sweeps of a T1 session: (name, channel averaged at the holds, channels whose errors are scored).
_SWEEPS = (("aoa", 1, (2, 0)), ("roll", 2, (1, 0)))


def _fraction(piece) -> float:
    return piece[5].averaging_fraction if piece[4] is None else piece[4]


def _session_runs(session, draws: list, pos: np.ndarray, sweeps: list | None, traced: set, prof: AngleProfile) -> list:
    """The :class:`TurntableRun` of each piece of a measured session (:func:`mtcal.systems.installation.measure_simulated_session`):
    its calibration and verification, its turntable angle errors (``draws``: :func:`run_turntable_jobs_kinds`) and — with
    ``sweeps`` — each sweep's scores with the hold errors its hold means carry; pieces in ``traced`` keep the
    sweeps' time series of their first trial."""
    runs = [TurntableRun(cal.q_hat, cal.euler_before_rad, cal.euler_after_rad, ver.euler_before_rad,
                         ver.euler_after_rad, pos, -e_cal, -e_ver)
            for cal, ver, (e_cal, e_ver, _) in zip(session.calibrations, session.verifications, draws)]
    for i, run in enumerate(runs):
        if sweeps:                     # each sweep's scores, with the hold errors its hold means carry
            run.sweeps = {name: {**d, HOLD_ERROR_KEY: draws[i][2][name]} for name, d in session.sweeps[i].items()}
            run.trace = {}
            if i in traced:
                for sw in sweeps:
                    run.trace.update({f"{sw.name}_{state}_err": session.traces[i][f"{sw.name}_{state}_err"]
                                      for state in ("before", "after")})
                    run.trace[f"{sw.name}_time_s"] = prof.time_s[sw.span] - prof.time_s[sw.span.start]
                    run.trace[f"{sw.name}_reference"] = sw.reference_rad
    return runs


def calibration_step(sc: TurntableScenario | WindTunnelScenario, q_ws, gyro_rad_s, reference_rad,
                     fraction: float) -> installation.InstallationCalibration:
    """The studies' six-position calibration: :func:`mtcal.systems.installation.calibrate_installation`.

    Exactly the procedure ``mtcal calibrate --rest-detector paper`` runs on a log (the §3.2
    stillness detector on ``gyro_rad_s``, zeroing at the first sample, Eq 13), with the
    gates off (:meth:`~mtcal.systems.installation.InstallationConfig.monte_carlo`).

    Parameters
    ----------
    sc : TurntableScenario or WindTunnelScenario
        Gives the sample interval ``sc.imu.dt_s = 1 / sc.fs_hz`` (s).
    q_ws : ndarray (T, N, 4)
        QNCF sensor attitude of the calibration run, as logged (not zeroed).
    gyro_rad_s : ndarray (T, N, 3)
        Gyro of the same samples (rad/s), for rest detection.
    reference_rad : ndarray (6, 3) or (T, 6, 3)
        Reference angles fed to Eq 13 (rad, Eq 8 frame).
    fraction : float
        Averaged middle fraction of each rest.

    Returns
    -------
    InstallationCalibration
        Trial axis T throughout (``q_hat`` (T, 4, 4), ``euler_before_rad`` (T, 6, 3), …).

    References
    ----------
    wang2023cja §3.2, Eq 13–15; §4.1 (zeroed start).

    Examples
    --------
    >>> import numpy as np
    >>> from mtcal.core.profiles import trajectory_from_euler_zxy
    >>> from mtcal.core.simulate import ImuErrorModel, simulate_imu
    >>> from mtcal.studies.wang2023cja import turntable_scenario
    >>> sc = turntable_scenario(fs_hz=100.0, turntable_rate_deg_s=60.0)
    >>> rec = simulate_imu(trajectory_from_euler_zxy(turntable_profile(sc, False)[0]), ImuErrorModel())
    >>> cal = calibration_step(sc, rec.q_ws_true[None], rec.gyro_rad_s[None], six_position_reference(sc), 0.5)
    >>> cal.q_hat.shape, bool(np.abs(cal.q_hat[0] - np.eye(4)).max() < 1e-9)
    ((1, 4, 4), True)
    """
    return installation.calibrate_installation(installation.InstallationConfig.monte_carlo(fraction), reference_rad,
                                               sc.imu.dt_s, q_ws=q_ws, gyro_rad_s=gyro_rad_s)


def run_turntable(sc: TurntableScenario, test: str, rng: np.random.Generator, trials: int,
                  sources=SOURCES, *, with_sweeps: bool = False, fraction: float | None = None,
                  keep_trace: bool = False) -> TurntableRun:
    """Simulate one turntable session end to end: IMU → QNCF → six-position LS → verification run.

    Parameters
    ----------
    sc : TurntableScenario
    test : {"T1", "T2", "T3", "T4"}
        Installation angles (fitted to Tables 1–4) and mount type (T1 screwed, T2–T4 gaskets).
    rng : numpy.random.Generator
    trials : int
        Monte Carlo trials (vectorised).
    sources : iterable of str
        Error sources switched on (error budget).
    with_sweeps : bool
        Append the AoA and roll sweeps (Tables 5–8) after the verification run.
    fraction : float, optional
        Averaging fraction of each rest (default ``sc.averaging_fraction``).
    keep_trace : bool
        Keep trial-0 error time series of the sweeps (figures).
    """
    return run_turntable_jobs(sc, [TurntableJob(test, rng, int(trials), _check_sources(sources), fraction)],
                              with_sweeps=with_sweeps, keep_trace=keep_trace)[0]


def _concat_runs(runs: list) -> TurntableRun:
    cat = lambda xs: np.concatenate(xs, axis=0)  # noqa: E731
    names = ("q_matrix", "cal_before", "cal_after", "ver_before", "ver_after")
    out = TurntableRun(*(cat([getattr(r, n) for r in runs]) for n in names), runs[0].reference,
                       cat([r.ref_err_cal for r in runs]), cat([r.ref_err_ver for r in runs]), None, runs[0].trace)
    if runs[0].sweeps is not None:
        out.sweeps = {name: {k: (v if k == "reference" else cat([r.sweeps[name][k] for r in runs]))
                             for k, v in d.items()} for name, d in runs[0].sweeps.items()}
    return out


def run_turntable_jobs(sc: TurntableScenario, jobs: list[TurntableJob], *, with_sweeps: bool = False,
                       keep_trace: bool = False, block: int = 10,
                       max_trial_samples: int = 4_000_000) -> list[TurntableRun]:
    """Several Monte Carlo sets (tests, error budgets, averaging fractions) sharing QNCF runs.

    Each job is split into blocks of ``block`` trials, block ``i`` drawing from
    ``child_rngs(job.rng, n_blocks)[i]``. Consecutive blocks are stacked into one QNCF run while
    trials × samples stays below ``max_trial_samples`` (memory bound: ≈ 1 GB peak at the default).
    :func:`run_turntable_jobs_kinds` runs several aligned job lists side by side.

    Returns
    -------
    list of TurntableRun
        One per job, trials in job order.
    """
    return run_turntable_jobs_kinds(sc, [jobs], with_sweeps=with_sweeps, keep_trace=keep_trace, block=block,
                                    max_trial_samples=max_trial_samples)[0]


def run_turntable_jobs_kinds(sc: TurntableScenario, kinds_jobs: list, *, with_sweeps: bool = False,
                             keep_trace: bool = False, block: int = 10,
                             max_trial_samples: int = 4_000_000) -> list[list[TurntableRun]]:
    """:func:`run_turntable_jobs` of several aligned job lists (the predictive kinds), side by side.

    Job ``j`` of every list has the same test and trial count; its blocks (pieces) are stacked next to
    the same blocks of the other lists in one QNCF run (the stack stays below ``max_trial_samples``,
    rounded up to a multiple of the lists: each list gets an equal share) and their IMU records are filled together
    (:func:`mtcal.core.simulate.fill_streams`: generators with equal keys and sensors with equal noise
    scales draw the white, random-walk and Gauss–Markov noise once; others are filled apart). Every
    run equals the one of a separate :func:`run_turntable_jobs` call bit for bit (with ``keep_trace``
    each list's first job keeps its trace).

    Parameters
    ----------
    sc : TurntableScenario
    kinds_jobs : list of list of TurntableJob
        Aligned job lists (equal length, job ``j`` of equal test and trials in each).
    with_sweeps, keep_trace, block, max_trial_samples
        As for :func:`run_turntable_jobs`.

    Returns
    -------
    list of list of TurntableRun
        Per list, one run per job.
    """
    kinds_jobs = [list(jobs) for jobs in kinds_jobs]
    if not kinds_jobs or not kinds_jobs[0]:
        raise ValueError("jobs must hold at least one TurntableJob")
    for jobs in kinds_jobs:
        for job in jobs:
            if not isinstance(job, TurntableJob):
                raise TypeError(f"jobs must hold TurntableJob items, got {type(job).__name__}")
            if int(job.trials) < 1:
                raise ValueError(f"job trials must be >= 1, got {job.trials}")
            if job.test not in sc.alpha_deg:
                raise ValueError(f"job test must be one of {sorted(sc.alpha_deg)}, got {job.test!r}")
        if [(j.test, int(j.trials)) for j in jobs] != [(j.test, int(j.trials)) for j in kinds_jobs[0]]:
            raise ValueError("kinds_jobs must be aligned: job j of every list with the same test and trials")
    if int(block) < 1:
        raise ValueError(f"block must be >= 1, got {block}")
    keep_freed_memory()                          # the per-call arrays below reuse freed heap, not fresh zeroed pages
    # the study's part: each piece's settings from its scenario (kind-major: block m·P + p is piece p of kind m),
    # then the session's schedule; below it, the session is the source's and the installation system's
    pieces = [_job_pieces(sc, jobs, int(block)) for jobs in kinds_jobs]   # per kind: (job index, piece)
    settings = [_piece_settings(piece, with_sweeps) for kind in pieces for _, piece in kind]
    prof, spans, pos = _session_schedule(sc, with_sweeps)
    # each piece's draws, in this order from child_rngs(its generator, 3) = (IMU, turntable, run change): its
    # turntable angle errors (truth − command) at the calibration run's rests (T, 6, 3), at the verification run's
    # and — with the sweeps — at each sweep's holds of the averaged channel; the run change's accelerometer bias
    # step, then the gasket load tilt; its sensor. Its records are simulated on demand over the compliant truth.
    blocks, draws = [], []
    for st in settings:
        rng_imu, rng_ref, rng_change = child_rngs(st.rng, 3)
        (ref_on, step_on, tilt_on), t = st.switched, st.trials
        errs = [rng_ref.standard_normal((t, k, 3)) * st.reference_sigma_rad for k in (6, 6, *st.sweep_holds)]
        e_cal, e_ver, *e_holds = errs if ref_on else [np.zeros_like(e) for e in errs]
        draws.append((e_cal, e_ver, {name: e[..., chan] for (name, chan, _), e in zip(_SWEEPS, e_holds)}
                      if st.sweep_holds else None))
        blocks.append(RecordPiece(t, st.imu.error_model(mount_quaternion(st.alpha_rad), st.sources, st.errors), rng_imu,
                                  st.compliance_rad_g,
                                  st.accel_step_sigma_m_s2 * rng_change.standard_normal((t, 1, 3)) if step_on else None,
                                  st.load_tilt_sigma_rad * rng_change.standard_normal((t, 3)) * [1.0, 1.0, 0.0]
                                  if tilt_on else None))
    q_wb = rotations.quat_from_euler_zxy(prof.angle_rad[:, 0], prof.angle_rad[:, 1], prof.angle_rad[:, 2])
    source = RecordSource(prof.time_s, q_wb, blocks, sc.imu.dt_s,
                          tilt_axis=gravity_lateral_axis(q_wb) if any(b.tilt_gain != 0.0 for b in blocks) else None,
                          step_start=spans["verification"].start)
    n_kinds, n_pieces = len(kinds_jobs), len(pieces[0])
    per_call = max(int(block), int(max_trial_samples) // prof.time_s.size)
    per_call = -(-per_call // n_kinds) * n_kinds   # each kind an equal share (rounded up: 18 for 17 at 1000 Hz)
    calls, count = [[]], 0                       # piece positions p (the same in every kind) per call
    for p in range(n_pieces):
        if calls[-1] and count + n_kinds * settings[p].trials > per_call:
            calls.append([])
            count = 0
        calls[-1].append(p)
        count += n_kinds * settings[p].trials
    # each sweep's hold windows relative to its span, per averaging fraction (the rests before and after it dropped);
    # the session measured by the installation system: one stacked QNCF per call, each piece's calibration and
    # verification (fed the commanded reference; the turntable stood at command + e_cal) and sweeps' scores
    holds = {name: {f: [slice(h.start - spans[name].start, h.stop - spans[name].start)
                        for h in prof.hold_slices(spans[name], f)][1:-1] for f in dict.fromkeys(st.fraction for st in settings)}
             for name, _, _ in (_SWEEPS if with_sweeps else ())}
    config = installation.InstallationConfig.monte_carlo(qncf_params=sc.qncf)
    sweeps = ([installation.SessionSweep(name, spans[name], prof.angle_rad[spans[name]], chan, chans, holds[name],
                                         TRACE_DECIMATION) for name, chan, chans in _SWEEPS] if with_sweeps else None)
    per_job = [[[] for _ in jobs] for jobs in kinds_jobs]
    for c, call in enumerate(progress(calls, desc="turntable Monte Carlo")):
        n = len(call)                            # kind-major: the call's pieces of kind 0, then of kind 1, …
        stack = [m * n_pieces + p for m in range(n_kinds) for p in call]
        starts = np.cumsum([0] + [settings[b].trials for b in stack]).tolist()
        traced = {m * n for m in range(n_kinds)} if keep_trace and c == 0 else set()
        session = installation.measure_simulated_session(
            config, source, stack, [[m * n + k for m in range(n_kinds)] for k in range(n)],
            calibration_run=spans["calibration"], verification_run=spans["verification"], reference_rad=pos,
            pieces=[installation.SessionPiece(slice(starts[i], starts[i + 1]), pos - draws[b][0], settings[b].fraction,
                                              hold_errors_rad=draws[b][2], trace_row=0 if i in traced else None)
                    for i, b in enumerate(stack)],
            sweeps=sweeps or (), map_pieces=_map)
        runs = _session_runs(session, [draws[b] for b in stack], pos, sweeps, traced, prof)
        for b, run in zip(stack, runs):
            m, p = divmod(b, n_pieces)
            per_job[m][pieces[m][p][0]].append(run)
        del session
    for jobs in per_job:                         # each job's pieces dropped as soon as joined (peak: one copy)
        for i, pieces_run in enumerate(jobs):
            jobs[i] = _concat_runs(pieces_run)
    return per_job


def _job_pieces(sc: TurntableScenario, jobs: list, block: int) -> list:
    """``(job index, (test, sources, rng, trials, fraction, scenario))`` of every block of ``block`` trials of
    the jobs, in job order; block ``i`` of a job draws from ``child_rngs(job.rng, n_blocks)[i]``."""
    pieces = []
    for i, job in enumerate(jobs):
        src = _check_sources(job.sources)
        sizes = [min(block, job.trials - k) for k in range(0, job.trials, block)]
        sc_job = sc
        if job.errors is not None or job.alpha_deg is not None:
            sc_job = replace(sc, errors=sc.errors if job.errors is None else job.errors,
                             alpha_deg={**sc.alpha_deg, **({} if job.alpha_deg is None else {job.test: tuple(job.alpha_deg)})})
        pieces += [(i, (job.test, src, r, n, job.fraction, sc_job)) for r, n in zip(child_rngs(job.rng, len(sizes)), sizes)]
    return pieces


def position_errors_deg(run: TurntableRun, state: str) -> np.ndarray:
    """Per-trial errors (T, 6, 3) in deg (Eq 8 frame) at the six positions.

    ``state``: "before" / "after" — the separate verification run against the turntable's true
    angles; "after_in_sample" — the calibration run's own rest means after its own matrix.
    """
    sel = {"before": (run.ver_before, run.ref_err_ver), "after": (run.ver_after, run.ref_err_ver),
           "after_in_sample": (run.cal_after, run.ref_err_cal)}.get(state)
    if sel is None:
        raise ValueError(f"state must be 'before', 'after' or 'after_in_sample', got {state!r}")
    est, err = sel
    return np.degrees(metrics.angle_difference_trusted(est, run.reference + err))


# --------------------------------------------------------------------------
# wind tunnel
# --------------------------------------------------------------------------
def _key(values) -> tuple:
    return tuple(np.asarray(values, float).ravel().tolist())


def _wt_waypoints(waypoints_deg) -> np.ndarray:
    """Pitch waypoints (rad) of a wind-tunnel sweep, from and back to zero, (K + 2, 3)."""
    wp = np.zeros((len(waypoints_deg) + 2, 3))
    wp[1:-1, 1] = np.radians(waypoints_deg)
    return wp


def _wt_holds_s(waypoints_deg, lead_s, hold) -> np.ndarray:
    """Hold times (s) of :func:`_wt_waypoints`: ``lead_s`` first, ``hold`` at each point, 1 s at the end."""
    return np.r_[lead_s, np.full(len(waypoints_deg), hold), 1.0]


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
                   *, wind_on: bool = True, block: int = 10, keep_trace: bool = True,
                   trace_trial: int = 0, shared: dict | None = None) -> WindTunnelRun:
    """Wind-off calibration + AoA sweep (Tables 9, 11) and five wind-on groups (Table 10), in trial blocks.

    Block ``i`` of ``block`` trials draws from ``child_rngs(rng, n_blocks)[i]``; peak memory is set by
    ``block`` (≈ 0.6 GB at 10), not by ``trials``. The time series of trial ``trace_trial`` are kept
    for figures (``keep_trace``; off: ``trace`` is empty, a caller that keeps another run's does not
    hold ~10 MB per run); the trials' numbers do not depend on which one is traced. Each block is one
    session of the scenario (:func:`_run_windtunnel_blocks`), written straight into its trial rows of the run's
    arrays (:func:`_windtunnel_outputs`: no per-block results kept and joined afterwards). It is
    :func:`run_windtunnel_kinds` of the one scenario.

    ``shared`` (a dict, empty on the first of several runs from equal generators): the wind-on
    accelerometer vibration of each block and group is kept there and reused by a later run whose
    phases, time base and vibration settings are equal (checked, else computed afresh), so runs of
    two error models on one key compute it once — the same numbers as separate runs.
    :func:`run_windtunnel_kinds` runs several scenarios on equal generators side by side (the same
    numbers as one call each).
    """
    return run_windtunnel_kinds([sc], [rng], trials, sources, wind_on=wind_on, block=block, keep_trace=keep_trace,
                                trace_trial=trace_trial, shared=shared)[0]


def _windtunnel_block_sizes(trials: int, block: int, trace_trial: int) -> tuple[list, int, int]:
    """Checked ``trials``, ``block`` and ``trace_trial``: the block sizes, and the traced trial's block and row."""
    trials = int(trials)
    if trials < 1:
        raise ValueError(f"trials must be >= 1, got {trials}")
    if int(block) < 1:
        raise ValueError(f"block must be >= 1, got {block}")
    if not 0 <= int(trace_trial) < trials:
        raise ValueError(f"trace_trial must be in [0, {trials}), got {trace_trial}")
    return [min(int(block), trials - k) for k in range(0, trials, int(block))], *divmod(int(trace_trial), int(block))


def _block_rows(sizes: list) -> list[slice]:
    """The trial rows of each block of ``sizes`` trials, in order."""
    starts = np.cumsum([0] + list(sizes)).tolist()
    return [slice(a, b) for a, b in zip(starts[:-1], starts[1:])]


def run_windtunnel_kinds(scenarios, rngs, trials: int, sources=SOURCES, *, wind_on: bool = True, block: int = 10,
                         keep_trace: bool = True, trace_trial: int = 0, shared: dict | None = None) -> list:
    """:func:`run_windtunnel` of each scenario with its generator, block by block side by side.

    The scenarios' blocks are set up one by one, their IMU records filled together
    (:func:`mtcal.core.simulate.fill_streams`: generators with equal keys and sensors with equal noise
    scales — the predictive kinds of one parameter draw — draw the white, random-walk and
    Gauss–Markov noise once; others are filled apart), then measured one by one. Every run equals
    ``run_windtunnel(scenarios[m], rngs[m], ...)`` bit for bit; peak memory: the records of all
    scenarios' blocks at once.

    Parameters
    ----------
    scenarios : sequence of WindTunnelScenario
    rngs : sequence of numpy.random.Generator
        One per scenario.
    trials, sources, wind_on, block, keep_trace, trace_trial, shared
        As for :func:`run_windtunnel` (``shared``: the wind-on vibration, computed by the first scenario).

    Returns
    -------
    list of WindTunnelRun
        One per scenario.
    """
    scenarios, rngs = list(scenarios), list(rngs)
    if not scenarios or len(rngs) != len(scenarios):
        raise ValueError(f"scenarios and rngs must be non-empty and of equal length, got {len(scenarios)} and "
                         f"{len(rngs)}")
    sources = _check_sources(sources)
    sizes, b_trace, i_trace = _windtunnel_block_sizes(trials, block, trace_trial)
    keep_freed_memory()                          # the per-block arrays reuse freed heap, not fresh zeroed pages
    block_rngs = list(zip(*(child_rngs(rng, len(sizes)) for rng in rngs)))   # [block][scenario]
    outs = [None] * len(scenarios)               # each run's arrays, made by its first block (_windtunnel_outputs)
    gates = [_run_windtunnel_blocks(scenarios, list(r), n, sources, wind_on=wind_on,
                                    keep_trace=keep_trace and i == b_trace, trace_index=i_trace,
                                    shared=None if shared is None else shared.setdefault(i, {}), outs=outs, rows=rows,
                                    total=sum(sizes))
             for i, (r, n, rows) in enumerate(progress(list(zip(block_rngs, sizes, _block_rows(sizes))),
                                                       desc="wind-tunnel Monte Carlo"))]
    for m, out in enumerate(outs):
        if wind_on:                              # the trial-weighted mean of the blocks' gate fractions
            out.wind_on["gate_fraction_on"] = float(np.average([g[m] for g in gates], weights=sizes))
    return outs


def _windtunnel_outputs(b: "_WindTunnelBlock", trials: int, wind_on: bool) -> WindTunnelRun:
    """The arrays of a run of ``trials`` trials of block ``b``'s scenario, empty: each block writes its trial rows
    (:func:`_wt_nowind`, :func:`_wind_on_scores`); the sweeps' references (equal in every block) come from the first
    block, the trace from the traced block, ``gate_fraction_on`` from the caller (the blocks' trial-weighted mean)."""
    sc, ses = b.sc, b.session
    prof, spans, holds = ses.prof, ses.spans, ses.holds
    span = spans["aoa"]
    dec = (trials, len(range(span.start, span.stop, TRACE_DECIMATION)), 3)
    nowind = {"reference": None, "before_mean": np.empty((trials, len(holds))),
              "after_mean": np.empty((trials, len(holds)))}
    for state in ("before", "after"):
        for c in (2, 0):
            nowind[f"{state}_maxae_{c}"], nowind[f"{state}_rmse_{c}"] = np.empty(trials), np.empty(trials)
        nowind[f"{state}_err_dec"] = np.empty(dec, dtype=np.float32)
    wind = None
    if wind_on:
        wind = {"reference": None, "group_means": np.empty((5, trials, len(sc.wind_on_sweep_deg))),
                "elastic_corrected": None, "gate_fraction_on": None, "gate_fraction_on_trials": np.empty(trials)}
    return WindTunnelRun(np.empty((trials, 4, 4)), np.empty((trials, 6, 3)), np.empty((trials, 6, 3)), nowind, wind, {})


@dataclass(frozen=True)
class _WtSession:
    """A wind-tunnel session's schedule (:func:`_wt_session`), shared read-only by every block on its settings."""

    pos: np.ndarray           # the six calibration positions (6, 3) rad
    prof: AngleProfile        # calibration run, then the wind-off AoA sweep
    spans: dict               # {"calibration", "aoa"}: their samples of ``prof``
    holds: list               # hold windows of the AoA sweep, relative to its span (first and last dropped)
    groups: tuple             # per wind-on group: (profile, rate rad/s, hold windows (first and last dropped))
    stops: dict               # id(profile) → its stop directions (:func:`_stops`, found on first use)


def _wt_session(sc: WindTunnelScenario) -> _WtSession:
    """A scenario's session schedule, built once per process for its settings (every Monte Carlo block, each
    parameter draw with its own scenario, reuses it): the positions, the session profile (calibration then AoA
    sweep), the five wind-on groups' sweeps (group 5 at its own rate), their hold windows and stop directions."""
    with _SCHEDULE_LOCK:                     # one object per settings, whichever thread builds it first
        return _wt_schedule(_key(sc.cal_yaw_deg), _key(sc.cal_pitch_deg), _key(sc.cal_roll_deg), float(sc.rest_s),
                            float(sc.fs_hz), _key(sc.aoa_sweep_deg), float(sc.mechanism_rate_rad_s), float(sc.hold_s),
                            _key(sc.wind_on_sweep_deg), float(sc.group5_rate_rad_s), float(sc.wind_on_hold_s))


_SCHEDULE_LOCK = threading.Lock()


@functools.lru_cache(maxsize=32)
def _wt_schedule(cal_yaw_deg, cal_pitch_deg, cal_roll_deg, rest_s, fs_hz, aoa_sweep_deg, rate_rad_s, hold_s,
                 wind_on_sweep_deg, group5_rate_rad_s, wind_on_hold_s) -> _WtSession:
    """:func:`_wt_session` of these settings (their arrays made read-only: no user can change a shared one)."""
    aoa_wp, aoa_holds_s = _wt_waypoints(aoa_sweep_deg), _wt_holds_s(aoa_sweep_deg, 1.0, hold_s)
    won_rates = [group5_rate_rad_s if g == 4 else rate_rad_s for g in range(5)]
    won_wp, won_holds_s = _wt_waypoints(wind_on_sweep_deg), _wt_holds_s(wind_on_sweep_deg, WIND_LEAD_S, wind_on_hold_s)
    pos = _positions_rad(cal_yaw_deg, cal_pitch_deg, cal_roll_deg)
    cal_prof = six_position.schedule_profile(pos, rate_rad_s=5 * DEG, rest_s=rest_s, fs_hz=fs_hz)
    aoa_prof = step_schedule(aoa_wp, rate_rad_s, aoa_holds_s, fs_hz, min_move_s=0.5)
    by_rate = {r: step_schedule(won_wp, r, won_holds_s, fs_hz, min_move_s=0.5) for r in dict.fromkeys(won_rates)}
    prof, (cal_span, span) = join_profiles([cal_prof, aoa_prof])
    holds = {id(p): p.hold_slices(slice(0, p.time_s.size), 0.5)[1:-1] for p in by_rate.values()}
    for p in (prof, *by_rate.values()):
        for f in ("time_s", "angle_rad", "rate_rad_s", "accel_rad_s2", "is_static", "segment"):
            getattr(p, f).setflags(write=False)
    return _WtSession(pos, prof, {"calibration": cal_span, "aoa": span},
                      [slice(h.start - span.start, h.stop - span.start) for h in prof.hold_slices(span, 0.5)][1:-1],
                      tuple((by_rate[r], r, holds[id(by_rate[r])]) for r in won_rates), {})


def _stops(ses: _WtSession, prof: AngleProfile) -> np.ndarray:
    """:func:`mtcal.studies.wang2023cja.scenario.stop_directions` of one of the session's profiles, found once for
    every scenario on it (read-only)."""
    hit = ses.stops.get(id(prof))
    if hit is None:
        hit = stop_directions(prof)
        hit.setflags(write=False)
        ses.stops[id(prof)] = hit            # (a race writes the same numbers)
    return hit


@dataclass
class _WindTunnelBlock:
    """One scenario's block of :func:`_run_windtunnel_blocks`: its session, draws, truth and records (:func:`_wt_setup`)."""

    sc: WindTunnelScenario
    trials: int
    session: _WtSession
    ref_err: np.ndarray       # (trials, 6, 3) mechanism reference errors at the calibration positions
    piece: RecordPiece        # the wind-off session's records (its truth, sensor, run-to-run bias change)
    groups: list              # the wind-on groups' RecordPiece (their truth, sensor, vibration); [] with the wind off


def _run_windtunnel_blocks(scenarios, rngs, trials: int, sources, *, wind_on: bool, keep_trace: bool,
                           trace_index: int = 0, shared: dict | None = None, outs: list, rows: slice,
                           total: int) -> list:
    """Wind-off calibration + AoA sweep (Tables 9, 11) and five wind-on groups (Table 10) of one block per
    scenario, the scenarios side by side: each set up (:func:`_wt_setup`: settings, draws, schedule, truth, its
    blocks of records), then the installation system measures them in one call
    (:func:`mtcal.systems.installation.measure_simulated_session`): the wind-off sessions (one stacked QNCF, each
    scenario's calibration and AoA sweep), then the wind-on groups with each scenario's Q̂ (one stacked QNCF), their
    records pulled from core sources (:class:`mtcal.core.simulate.RecordSource`: the scenarios' records filled
    together, the noise drawn once where shared).

    Truth = actual mechanism angles (:func:`mechanism_actual`) + elastic
    deflection with wind on; reference = commanded angles. With wind on the
    model vibrates (accelerometer ``vibration_accel_m_s2`` at
    ``vibration_freq_hz`` plus angular pitch vibration), which trips the AMD:
    the QNCF runs on the gyro alone.

    Scenario ``m``'s block is written into the trial ``rows`` of ``outs[m]`` (:func:`_windtunnel_outputs` of ``total``
    trials, made by the first block when None). Returns per scenario the block's gate fraction with the wind on
    (None with it off).
    """
    blocks = [_wt_setup(sc, rng, trials, sources, wind_on, shared) for sc, rng in zip(scenarios, rngs)]
    b0, k = blocks[0], len(blocks)
    if any(b.session is not b0.session or b.sc.qncf != b0.sc.qncf for b in blocks[1:]):
        raise ValueError("scenarios side by side must share their session (schedule, positions, sample rate) and "
                         "QNCF parameters: their records are measured in one stack")
    ses, frac, dt_s = b0.session, 0.5, b0.sc.imu.dt_s
    span = ses.spans["aoa"]
    # the records: the wind-off sessions (the run change from the AoA sweep on), the wind-on groups (kind-major:
    # block m·5 + g; each scenario's groups filled with the other scenarios' same group)
    records = RecordSource(None, None, [b.piece for b in blocks], dt_s, step_start=span.start)
    later = RecordSource(None, None, [p for b in blocks for p in b.groups], dt_s) if wind_on else None
    # the wind-off sessions, each zeroed at its first sample, its calibration run's calibration fed the commanded
    # positions (the mechanism stood at command + error), its AoA sweep scored against its command; then the
    # wind-on groups measured with each scenario's Q̂
    session = installation.measure_simulated_session(
        installation.InstallationConfig.monte_carlo(qncf_params=b0.sc.qncf), records, range(k), [list(range(k))],
        calibration_run=ses.spans["calibration"],
        pieces=[installation.SessionPiece(slice(m * trials, (m + 1) * trials), ses.pos + b.ref_err, frac,
                                          trace_row=trace_index if keep_trace else None) for m, b in enumerate(blocks)],
        sweeps=[installation.SessionSweep("aoa", span, ses.prof.angle_rad[span], 1, (2, 0), {frac: ses.holds},
                                          TRACE_DECIMATION)],
        applied=None if later is None else installation.AppliedRuns(
            later, tuple(range(5 * k)),
            tuple([m * 5 + g for m in range(k)] for g in range(5)),
            tuple(installation.AppliedRun(slice((m * 5 + g) * trials, (m * 5 + g + 1) * trials), None, holds,
                                          prof.time_s.size, trace_index if keep_trace else None, piece=m)
                  for m in range(k) for g, (prof, _, holds) in enumerate(ses.groups))))
    for m, b in enumerate(blocks):
        if outs[m] is None:
            outs[m] = _windtunnel_outputs(b, total, wind_on)
    traces = [_wt_nowind(b, session, m, keep_trace, outs[m], rows) for m, b in enumerate(blocks)]
    if not wind_on:
        return [None] * k
    return [_wind_on_scores(b, session.applied, m, traces[m], keep_trace, outs[m].wind_on, rows)
            for m, b in enumerate(blocks)]


def _wt_setup(sc: WindTunnelScenario, rng: np.random.Generator, trials: int, sources, wind_on: bool,
              shared: dict | None) -> _WindTunnelBlock:
    """One scenario's block up to its records: the draws (each from its own generator), the session's schedule
    (:func:`_wt_session`), the truth (the mechanism's actual angles, with the wind on plus elastic deflection and
    angular vibration, tilted by the mount's compliance) and the blocks of records (sensor, run-to-run bias change,
    wind-on accelerometer vibration: ``shared`` as for :func:`run_windtunnel`)."""
    rng_imu, rng_ref, rng_wind, rng_change = child_rngs(rng, 4)
    on = set(sources)
    k_mount = sc.errors.compliance_deg_g(MOUNT_TYPE["windtunnel"]) * DEG if "mount_compliance" in on else 0.0
    ref_err = _draws(rng_ref, trials, 6, sc.repeatability_rad, "reference_angle" in on)   # its own generator
    step = None                          # the run-to-run bias change between the calibration and the sweep
    if "accel_run_change" in on:
        step = sc.errors.accel_run_bias_mg * MG * rng_change.standard_normal((trials, 1, 3))
    draws = _wind_on_draws(sc, rng_wind, trials) if wind_on else []
    ses = _wt_session(sc)
    # truth: the mechanism's actual angles (wind on: + elastic deflection and angular vibration, the accelerometer
    # vibrating), tilted by the mount; then the sensor (core)
    actual = mechanism_actual(sc, ses.prof, sc.mechanism_rate_rad_s, stops=_stops(ses, ses.prof))
    groups = [_wind_on_truth(sc, ses, group, draw, shared, g) for g, (group, draw) in enumerate(zip(ses.groups, draws))]
    traj, *group_trajs = [compliance_trajectory(t, a, k_mount) for t, a in
                          [(ses.prof.time_s, actual)] + [(prof.time_s, a) for (prof, *_), (a, _) in zip(ses.groups, groups)]]
    model = sc.imu.error_model(mount_quaternion(np.radians(sc.alpha_deg)), sources, sc.errors)
    return _WindTunnelBlock(sc, trials, ses, ref_err, RecordPiece(trials, model, rng_imu, trajectory=traj,
                                                                  accel_step_m_s2=step),
                            [RecordPiece(trials, replace(model, time_since_power_on_s=model.time_since_power_on_s
                                                         + sc.group_interval_s * (g + 1)), draw[0],
                                         trajectory=group_traj, accel_offset_m_s2=shake)
                             for g, (draw, group_traj, (_, shake)) in enumerate(zip(draws, group_trajs, groups))])


def _wt_nowind(b: _WindTunnelBlock, session, m: int, keep_trace: bool, out: WindTunnelRun, rows: slice) -> dict:
    """Scenario ``m``'s wind-off session of the measured ``session``: its calibration and the AoA sweep's errors,
    written into the trial ``rows`` of ``out`` (:func:`_windtunnel_outputs`; the sweep's reference by the first
    block). Returns the block's trace (empty without ``keep_trace``; the traced block's is ``out.trace``)."""
    prof, span = b.session.prof, b.session.spans["aoa"]
    cal, scores, nowind = session.calibrations[m], session.sweeps[m]["aoa"], out.nowind
    out.q_matrix[rows], out.cal_before[rows], out.cal_after[rows] = cal.q_hat, cal.euler_before_rad, cal.euler_after_rad
    if rows.start == 0:
        nowind["reference"] = scores["reference"]
    for key, value in scores.items():
        if key != "reference":
            nowind[key][rows] = value
    trace = {}
    if keep_trace:
        trace = out.trace = {"nowind_time_s": prof.time_s[span] - prof.time_s[span.start],
                             "nowind_before_err": session.traces[m]["aoa_before_err"],
                             "nowind_after_err": session.traces[m]["aoa_after_err"]}
    return trace


def windtunnel_median_trial(run: WindTunnelRun) -> int:
    """The median session of a wind-tunnel run: median of Table 10's largest group-to-group Std over
    the AoA points (wind on), else of the wind-off sweep's largest MaxAE after calibration.

    Table 10 and the wind-on figures show this session, never trial 0.
    """
    if run.wind_on is not None:
        return metrics.median_trial(np.degrees(run.wind_on["group_means"]).std(axis=0, ddof=1).max(axis=-1))
    nw = run.nowind
    return metrics.median_trial(np.max([nw[f"after_maxae_{c}"] for c in (2, 0)], axis=0))


def elastic_deflection_rad(coeffs_deg, alpha_rad) -> np.ndarray:
    """Linear elastic pitch deflection ``c0 + c1·α`` (deg, deg/deg coefficients) in rad."""
    c0, c1 = coeffs_deg
    return np.radians(c0) + c1 * np.asarray(alpha_rad)


def _vibration_accel(sc, t, ramp, vib, shared, g) -> np.ndarray:
    """``ramp · a · sin(2π f t + vib)`` (trials, N, 3) of wind-on group ``g``, taken from ``shared`` when an
    earlier run stored it for equal phases, time base and settings (read-only there), else computed
    (and stored when ``shared`` is a dict)."""
    settings = (float(sc.vibration_freq_hz), float(sc.vibration_accel_m_s2))
    hit = None if shared is None else shared.get(g)
    if (hit is not None and hit[0] == settings and np.array_equal(hit[1], vib)
            and (hit[2] is t or np.array_equal(hit[2], t)) and np.array_equal(hit[3], ramp)):
        return hit[4]
    # with fewer temporaries than the expression (the same operations)
    shake = 2 * np.pi * sc.vibration_freq_hz * t[None, :, None] + vib
    np.sin(shake, out=shake)
    shake *= ramp[None, :, None] * sc.vibration_accel_m_s2
    if shared is not None:
        shared[g] = (settings, vib, t, ramp, shake)
    return shake


#: Wind-on groups: lead before the sweep (s), from which the AMD gate's open fraction is counted; the flow starts
#: 3 s before the sweep.
WIND_LEAD_S = 8.0
WIND_FLOW_START_S = WIND_LEAD_S - 3.0


def _wind_on_draws(sc: WindTunnelScenario, rng: np.random.Generator, trials: int) -> list[tuple]:
    """The five wind-on groups' draws, each group from its own generators ``child_rngs(child_rngs(rng, 5)[g], 3)``
    (dynamic pressure, IMU, vibration): ``(IMU generator, dynamic-pressure factor, angular vibration phase (rad),
    accelerometer vibration phases (trials, 1, 3) rad)``."""
    out = []
    for group_rng in child_rngs(rng, 5):
        r_q, r_imu, r_vib = child_rngs(group_rng, 3)
        q_factor = 1.0 + sc.dynamic_pressure_sigma * r_q.standard_normal()
        phase = r_vib.uniform(0, 2 * np.pi)
        out.append((r_imu, q_factor, phase, r_vib.uniform(0, 2 * np.pi, (trials, 1, 3))))
    return out


def _wind_on_truth(sc: WindTunnelScenario, ses: _WtSession, group: tuple, draw: tuple, shared: dict | None,
                   g: int) -> tuple:
    """Wind-on group ``g``'s truth angles (N, 3) rad — the mechanism's actual angles + the elastic deflection times
    the dynamic-pressure factor + the angular vibration, ramped in with the flow (3 s before the sweep); the caller
    tilts them by the mount — and its accelerometer vibration (trials, N, 3) m/s² (:func:`_vibration_accel`).
    ``group``: its session entry (:class:`_WtSession`), ``draw``: its draws (:func:`_wind_on_draws`)."""
    prof, rate, _ = group
    _, q_factor, phase, vib = draw
    actual = mechanism_actual(sc, prof, rate, stops=_stops(ses, prof))
    t = prof.time_s
    ramp = np.clip((t - WIND_FLOW_START_S) / 1.0, 0.0, 1.0)          # flow starts 3 s before the sweep
    actual[:, 1] += ramp * (q_factor * elastic_deflection_rad(sc.elastic_true_deg, prof.angle_rad[:, 1])
                            + sc.vibration_angle_rad * np.sin(2 * np.pi * sc.vibration_freq_hz * t + phase))
    return actual, _vibration_accel(sc, t, ramp, vib, shared, g)


def _wind_on_scores(b: _WindTunnelBlock, wind, m: int, trace: dict, keep_trace: bool, out: dict, rows: slice) -> float:
    """Scenario ``m``'s five wind-on AoA sweeps of the measured ``wind`` (:func:`mtcal.systems.installation.measure_applied_runs`,
    kind-major runs): the pitch after calibration at each group's holds, written into the trial ``rows`` of the
    run's ``wind_on`` arrays ``out`` (:func:`_windtunnel_outputs`; the references by the first block), the
    groups' series into ``trace`` with ``keep_trace``. Returns the block's gate fraction with the wind on
    (from :data:`WIND_LEAD_S` on)."""
    sc, trials, lead = b.sc, b.trials, int(WIND_LEAD_S * b.sc.fs_hz)
    ref = np.radians(np.asarray(sc.wind_on_sweep_deg, float))
    elastic_corrected = ref + elastic_deflection_rad(sc.elastic_model_deg, ref)
    means = out["group_means"][:, rows]                             # (a view: written in place)
    for g, (prof, *_) in enumerate(b.session.groups):
        means[g] = wind.hold_pitch_rad[m * 5 + g]
        if not keep_trace:
            continue
        tr = wind.traces[m * 5 + g]
        if g == 0:
            trace["amd_pct"], trace["gate"] = tr["amd_pct"], tr["gate"]
        trace[f"wind_time_s_{g}"] = prof.time_s.copy()            # the profile is shared (read-only)
        trace[f"wind_reference_{g}"] = prof.angle_rad[:, 1].copy()
        trace[f"wind_pitch_{g}"] = tr["pitch_rad"]
    if rows.start == 0:
        out["reference"], out["elastic_corrected"] = ref, elastic_corrected
    gate = wind.gate[m * 5 * trials:(m + 1) * 5 * trials, lead:]
    out["gate_fraction_on_trials"][rows] = gate.reshape(5, trials, -1).mean(axis=(0, 2))
    return float(gate.mean())




# random streams of turntable_runs (mtcal.core.rng rule)
STREAM_TESTS = 0              # key (seed, 0 + i): test i (T1 … T4); its children, one per block of trials


@cached  # Monte Carlo result cached under $MTCAL_CACHE_DIR (make reproduce/artifact)
def turntable_runs(sc: TurntableScenario, trials: int, seed: int) -> dict:
    """The notebook's Monte Carlo: T1 session with sweeps, T2–T4 sessions, ``trials`` each.

    Test ``i`` (T1 … T4) draws from ``stream_rng(seed, STREAM_TESTS + i)``, so results do not depend
    on the order or on the chunking; T2–T4 share stacked QNCF runs.
    """
    gens = {t: stream_rng(int(seed), STREAM_TESTS + i) for i, t in enumerate(("T1", "T2", "T3", "T4"))}
    out = {"T1": run_turntable_jobs(sc, [TurntableJob("T1", gens["T1"], int(trials))], with_sweeps=True,
                                    keep_trace=True)[0]}
    rest = run_turntable_jobs(sc, [TurntableJob(t, gens[t], int(trials)) for t in ("T2", "T3", "T4")])
    out.update(zip(("T2", "T3", "T4"), rest))
    return out
