"""``mtcal axis`` and ``mtcal angle``: wang2022sensors rotation-axis and EKF angle on a recorded log.

* ``mtcal axis LOG`` — rests (adaptive detector, or the paper's ZVD with
  ``--rest-detector paper``), rests at the same tilt merged into one position,
  and the axis v (``v_x ≥ 0``) as the normal of the plane through the
  positions (Eq 23 for exactly three). Refused, with the measured numbers,
  when fewer than three distinct tilts exist (e.g. a turn about the vertical),
  when the axis is nearly vertical, or when its uncertainty exceeds
  ``--max-axis-error-deg``. Prints ``axis v = x,y,z``, the uncertainty and a
  per-rest summary (time span, |a|, tilt, angle about v).
* ``mtcal angle LOG --axis vx,vy,vz`` — RAMS EKF angle per sample to
  ``--out`` (``time_s,angle_deg,is_static``, CSV or Parquet), 0 at the first
  rest, which gives ā0 and the gyro bias (its first ``--init-s`` seconds);
  a log that starts moving gets empty angles before that rest. Refused when the axis is nearly parallel to gravity, when the
  gyro turns about another axis than ``--axis``, or when the gyro's units or
  time base disagree with the accelerometer's tilt change between rests.
"""

from __future__ import annotations

import argparse

import numpy as np

from mtcal.cli import checks, common, logio

AXIS_EXAMPLE = """\
prints: 'axis v = x,y,z' (unit, v_x >= 0), its 1-sigma uncertainty, one line per rest
example:
  mtcal axis hinge.csv --figure axis.png
  mtcal axis hinge.parquet --gyro-unit deg/s --accel-unit g --min-separation-deg 5"""

ANGLE_EXAMPLE = """\
output columns (--out, CSV or Parquet): time_s (s), angle_deg (deg, about --axis, 0 at the
  first rest; empty before it if the log starts moving), is_static (0/1, rest flag used by the EKF)
example:
  mtcal angle hinge.csv --axis 0.6,0,0.8 --out angle.csv --figure angle.png
  mtcal angle hinge.csv --axis -0.3,0.1,0.95 --time-unit ms --gyro-unit deg/s --out angle.parquet"""

#: Floor on the std of a rest mean (m/s²): ~0.1° of tilt (accelerometer cross-axis/nonlinearity, play).
SIGMA_MEAN_FLOOR_M_S2 = 0.017


def _parse_axis(text: str) -> np.ndarray:
    try:
        v = np.array([float(x) for x in str(text).split(",")])
    except ValueError:
        raise ValueError(f"--axis must be three numbers vx,vy,vz, got {text!r}") from None
    if v.size != 3 or not np.all(np.isfinite(v)) or np.linalg.norm(v) < 1e-9:
        raise ValueError(f"--axis must be three finite numbers, not all zero, got {text!r}")
    return v / np.linalg.norm(v)


def _angles_about(v: np.ndarray, a0: np.ndarray, means: np.ndarray) -> np.ndarray:
    """Rotation angle (deg) of each static mean about v relative to a0 (a = R(θ, v)ᵀ a0)."""
    p0 = a0 - v * (v @ a0)
    p = means - np.outer(means @ v, v)
    phi = np.arctan2(np.cross(p0, p) @ v, p @ p0)
    return -np.degrees(phi)


def cmd_axis(args: argparse.Namespace) -> int:
    fig = common.DiagnosticsFigure(args.figure, f"mtcal axis {args.log}", inputs=[args.log])

    def body() -> int:
        log = logio.read_log(args.log, common.input_options(args), need="accel")
        fig.log = log
        if args.rest_detector == "paper":
            return _axis_paper(args, log, fig)
        rep = common.detect(args, log, use_gyro=log.gyro_rad_s is not None)
        fig.report = rep
        sep = common.finite_float(args.min_separation_deg, "--min-separation-deg")
        means = np.array([log.accel_m_s2[r].mean(axis=0) for r in rep.rests]).reshape(-1, 3)
        counts = np.array([r.stop - r.start for r in rep.rests], float)
        common.print_report(log, rep)
        from mtcal.methods import rotation_axis as ra

        if len(rep.rests) == 0:
            raise ValueError(f"found only 0 rests of >= {rep.min_rest_s:g} s ({rep.levels_text()}); "
                             f"the axis needs rests at three distinct tilts")
        pos, w, members = ra.distinct_positions(means, counts, min_separation_deg=sep)
        if pos.shape[0] < 3:
            spread = max((np.degrees(ra.angle_between(means[i], means[j]))
                          for i in range(len(means)) for j in range(i)), default=0.0)
            why = (" — a rotation about the vertical does not change the tilt, so the accelerometer "
                   "cannot see its axis" if len(rep.rests) >= 2 and spread < sep else "")
            raise ValueError(f"found only {pos.shape[0]} distinct tilt(s) among {len(rep.rests)} rest(s) "
                             f"(largest tilt difference {spread:.2f} deg, positions must be >= {sep:g} deg "
                             f"apart); the axis needs rests at three distinct tilts{why}")
        fig.used = [rep.rests[m[0]] for m in members]
        max_el = common.finite_float(args.max_elevation_deg, "--max-elevation-deg")
        fit = _check_uncertainty(args, pos, rep, w, log.fs_hz)
        if np.degrees(fit.elevation_rad) > max_el:
            raise ValueError(f"rotation axis is nearly vertical: elevation {np.degrees(fit.elevation_rad):.2f} "
                             f"deg above the horizontal (maximum {max_el:g} deg); rotation about it barely "
                             f"changes gravity")
        err = np.degrees(fit.sigma_rad)
        v = fit.v
        print(f"axis v = {v[0]:.6f},{v[1]:.6f},{v[2]:.6f}")
        print(f"axis uncertainty +-{err:.3f} deg (1 sigma), elevation {np.degrees(fit.elevation_rad):.2f} deg, "
              f"from {pos.shape[0]} distinct positions of {len(rep.rests)} rests")
        ang = _angles_about(v, means[0], means)
        for i, r in enumerate(rep.rests):
            print(f"rest {i}: {log.time_s[r.start]:.3f}-{log.time_s[r.stop - 1]:.3f} s, angle about v "
                  f"{ang[i]:+.3f} deg, mean accel [{means[i][0]:.5f}, {means[i][1]:.5f}, {means[i][2]:.5f}] m/s^2")
        return 0

    return common.run_with_figure(fig, body)


def _check_uncertainty(args, positions, rep, counts, fs_hz):
    """Plane fit of the positions; refuse when the axis is less certain than --max-axis-error-deg."""
    from mtcal.methods import rotation_axis as ra

    n_eff = float(np.min(counts)) / max(1.0, rep.window_s * fs_hz)  # ~independent windows per rest
    sig = max(rep.accel_noise_m_s2 / np.sqrt(max(n_eff, 1.0)), SIGMA_MEAN_FLOOR_M_S2)
    fit = ra.fit_axis_plane(positions, sig)
    max_err = common.finite_float(args.max_axis_error_deg, "--max-axis-error-deg")
    err = np.degrees(fit.sigma_rad)
    if not err <= max_err:
        spread = max(np.degrees(ra.angle_between(positions[i], positions[j]))
                     for i in range(len(positions)) for j in range(i))
        raise ValueError(f"axis too uncertain: +-{err:.2f} deg (1 sigma) > {max_err:g} deg from "
                         f"{len(positions)} positions at most {spread:.2f} deg apart in tilt (rest-mean noise "
                         f"{sig:.4f} m/s^2, out-of-plane rms {fit.rms_out_of_plane_m_s2:.4f} m/s^2); "
                         f"rotate further between rests")
    return fit


def _axis_paper(args, log, fig) -> int:
    """The paper's path: Table 1 ZVD + Algorithm A1 (first three distinct rests)."""
    from mtcal.methods.rest_detection import paper_rest_report
    from mtcal.methods.rotation_axis import estimate_axis

    min_rest = common.finite_float(args.min_rest_s, "--min-rest-s")
    rep = paper_rest_report(log.accel_m_s2, 1.0 / log.fs_hz, min_rest_s=min_rest)
    fig.report = rep
    print(rep.levels_text() + f" (measured |a| at rest {rep.extra['measured_gravity_m_s2']:.4f} m/s^2)")
    sep = common.finite_float(args.min_separation_deg, "--min-separation-deg")
    try:
        res = estimate_axis(log.accel_m_s2, 1.0 / log.fs_hz, min_rest_s=min_rest, is_static=rep.is_static,
                            min_separation_deg=sep,
                            max_elevation_deg=common.finite_float(args.max_elevation_deg, "--max-elevation-deg"))
    except ValueError as exc:
        raise ValueError(f"{exc} [paper ZVD band {rep.band_m_s2[0]:g}-{rep.band_m_s2[1]:g} m/s^2, measured |a| "
                         f"at rest {rep.extra['measured_gravity_m_s2']:.4f} m/s^2; --rest-detector adaptive "
                         f"measures the band from the data]") from None
    fig.used = list(res.rests)
    _check_uncertainty(args, res.means, rep, np.array([r.stop - r.start for r in res.rests], float), log.fs_hz)
    print(f"axis v = {res.v[0]:.6f},{res.v[1]:.6f},{res.v[2]:.6f}")
    t = log.time_s
    for i, sl in enumerate(res.rests):
        print(f"rest {i}: {t[sl.start]:.3f}-{t[sl.stop - 1]:.3f} s, mean accel "
              f"[{res.means[i][0]:.5f}, {res.means[i][1]:.5f}, {res.means[i][2]:.5f}] m/s^2")
    return 0


def cmd_angle(args: argparse.Namespace) -> int:
    fig = common.DiagnosticsFigure(args.figure, f"mtcal angle {args.log}", inputs=[args.log])
    out = logio.check_output_path(args.out, [args.log])

    def body() -> int:
        from mtcal.filters.rams_ekf import RamsEkfParams
        from mtcal.methods.rotation_axis import axis_elevation

        v = _parse_axis(args.axis)
        init_s = common.finite_float(args.init_s, "--init-s")
        log = logio.read_log(args.log, common.input_options(args), need="raw")
        fig.log = log
        rep = common.detect(args, log)
        fig.report = rep
        fs, t = log.fs_hz, log.time_s
        if args.rest_detector == "paper":  # the paper's set-up: the first --init-s seconds are the rest
            n0 = int(round(init_s * fs))
            if n0 < 1 or n0 >= t.size:
                raise ValueError(f"--init-s {init_s:g} s must cover at least one sample and leave data")
            if not rep.is_static[min(n0, t.size - 1) // 2:n0].any():
                raise ValueError(f"the first {init_s:g} s are not at rest by the paper ZVD ({rep.levels_text()}; "
                                 f"measured |a| at rest {rep.extra['measured_gravity_m_s2']:.4f} m/s^2); "
                                 f"--rest-detector adaptive measures the band from the data")
            first, late, init = slice(0, n0), False, slice(0, n0)
        else:
            if not rep.rests:
                common.print_report(log, rep)
                raise ValueError(f"no rest found: the angle is measured from a rest (reference and gyro bias); "
                                 f"{rep.levels_text()}")
            late = rep.rests[0].start > max(0.25 * fs, rep.window_s * fs)
            first = rep.rests[0]
            n0 = min(int(round(init_s * fs)), first.stop - first.start)
            if n0 < max(3, int(0.1 * fs)):
                raise ValueError(f"initial rest too short: {n0} samples ({n0 / fs:.2f} s), need >= 0.1 s")
            init = slice(first.start, first.start + n0)
        a0 = log.accel_m_s2[init].mean(axis=0)
        b0 = log.gyro_rad_s[init].mean(axis=0)
        elev = float(np.degrees(axis_elevation(v, a0)))
        max_el = common.finite_float(args.max_elevation_deg, "--max-elevation-deg")
        if elev > max_el:
            raise ValueError(f"--axis is {90 - elev:.2f} deg from gravity (elevation {elev:.2f} deg > {max_el:g}): "
                             f"a rotation about the vertical does not change the accelerometer reading, so the "
                             f"EKF cannot correct the gyro; measure the angle with a non-vertical axis")
        gyro_f = log.gyro_for_filter()
        clipped, clip_level = checks.clipped_samples(log.gyro_rad_s)
        if clipped.any():
            print(f"warning: gyro clipped at {np.degrees(clip_level):.1f} deg/s in {int(clipped.sum())} samples; "
                  f"angles through those moves rely on the following rest")
        check = checks.gyro_tilt_consistency(gyro_f, log.accel_m_s2, log.dt_mean_s, rep.rests, time_s=t,
                                             skip=clipped)
        moving = ~rep.is_static & (np.linalg.norm(log.gyro_rad_s - b0, axis=1) > max(
            5 * rep.gyro_noise_rad_s, np.radians(2.0)))
        turned = float(np.degrees(np.sum(np.linalg.norm(log.gyro_rad_s[moving] - b0, axis=1)) / fs))
        if turned > 20.0:
            u, share = checks.rotation_axis_from_gyro(log.gyro_rad_s, b0, moving)
            mis = float(np.degrees(np.arccos(min(1.0, abs(float(u @ v))))))
            max_mis = common.finite_float(args.max_axis_mismatch_deg, "--max-axis-mismatch-deg")
            if mis > max_mis:
                u = u if u[0] >= 0 else -u
                raise ValueError(f"the gyro turns about [{u[0]:.3f}, {u[1]:.3f}, {u[2]:.3f}] "
                                 f"({share * 100:.0f} % of the rotation), {mis:.1f} deg from --axis "
                                 f"(max {max_mis:g}); pass the right axis (mtcal axis LOG) or check the axes")
        sig_a = max(float(np.std(log.accel_m_s2[init], axis=0).mean()), 1e-4)
        sig_w = max(float(np.std(log.gyro_rad_s[init], axis=0).mean()), 1e-5)
        params = RamsEkfParams(sigma_theta_rad_s=sig_w, sigma_b_rad_s2=1e-4, sigma_a_static_m_s2=sig_a,
                               sigma_a_moving_m_s2=5.0, p0_theta_rad2=1e-8, p0_bias_rad2_s2=1e-8)
        k0 = first.start
        angle = np.full(t.size, np.nan)
        angle[k0:] = np.degrees(_ekf_pieces(gyro_f[k0:], log.accel_m_s2[k0:], rep.is_static[k0:],
                                            [slice(r.start - k0, r.stop - k0) for r in rep.rests], v, a0, b0,
                                            log.dt_mean_s, params, clipped[k0:]))
        if late:
            print(f"note: the log starts moving; angles are measured from the first rest at "
                  f"{t[k0] - t[0]:.2f} s (angle 0 there, empty before)")
        fig.series = {"angle (deg)": angle}
        logio.write_table(out, {"time_s": t, "angle_deg": angle, "is_static": rep.is_static.astype(np.int8)})
        means = np.array([log.accel_m_s2[r].mean(axis=0) for r in rep.rests]).reshape(-1, 3)
        acc_ang = _angles_about(v, a0, means)
        ekf_ang = np.array([np.nanmedian(angle[r]) if np.isfinite(angle[r]).any() else np.nan for r in rep.rests])
        acc_ang = acc_ang + 360.0 * np.round((ekf_ang - acc_ang) / 360.0)  # same turn as the EKF
        common.print_report(log, rep, angle_deg=angle, extra={"accel_angle_deg": acc_ang})
        off = np.abs(ekf_ang - acc_ang)
        if np.nanmax(off, initial=0.0) > 2.0 and np.cos(np.radians(elev)) > 0.2:
            i = int(np.nanargmax(off))
            print(f"warning: at rest {i} the EKF angle differs from the accelerometer's by {off[i]:.2f} deg "
                  f"(axis or accelerometer errors; check --axis)")
        if check["pairs"]:
            print(f"gyro/accelerometer check: {check['pairs']} rest pair(s), rotation/tilt ratio "
                  f"{check['ratio']:.3f}, worst misfit {check['worst_deg']:.2f} deg")
        else:
            print("gyro/accelerometer check: no pair of rests with a tilt change >= 5 deg (units not checked)")
        print(f"angle: {t.size} samples written to {out}; final angle {angle[-1]:.3f} deg")
        return 0

    return common.run_with_figure(fig, body)


#: Prior angle std (rad) at the first rest after clipped gyro samples: the rest's accelerometer decides.
CLIPPED_P0_THETA_RAD = np.radians(30.0)


def _ekf_pieces(gyro, accel, static, rests, v, a0, b0, dt_s, params, clipped) -> np.ndarray:
    """RAMS EKF over the record; restarted with a wide angle prior at each rest that follows clipping.

    A clipped gyro under-reports the move, and the EKF's process noise (gyro white
    noise) would keep the wrong angle; restarting at the next rest with
    ``p0_θ = (30°)²`` (angle and bias carried over) lets the rest's
    accelerometer reading set the angle again. Without clipping this is one run.
    """
    from dataclasses import replace

    from mtcal.filters.rams_ekf import run_rams_ekf

    cuts = [0]
    if clipped.any():
        last = 0
        for r in rests[1:]:
            if clipped[last:r.start].any():
                cuts.append(r.start)
            last = r.start
    cuts.append(accel.shape[0])
    theta = np.empty(accel.shape[0])
    th0, bias0, p = 0.0, b0, params
    for lo, hi in zip(cuts[:-1], cuts[1:]):
        res = run_rams_ekf(gyro[lo:hi], accel[lo:hi], static[lo:hi], v, a0, dt_s, p,
                           theta0_rad=th0, bias0_rad_s=bias0, keep_innovation=False)
        theta[lo:hi] = res.theta_rad[0]
        th0, bias0 = float(res.theta_rad[0, -1]), res.bias_rad_s[0, -1]
        p = replace(params, p0_theta_rad2=CLIPPED_P0_THETA_RAD**2)
    return theta


__all__ = ["register", "cmd_axis", "cmd_angle"]


def _bullet(i: int) -> str:
    return __doc__.split("\n\n")[1].split("\n* ")[i].lstrip("* ")


def register(subparsers) -> None:
    """Add the ``axis`` and ``angle`` subcommands to the ``mtcal`` dispatcher."""
    fmt = argparse.RawDescriptionHelpFormatter
    p = subparsers.add_parser("axis", help="rotation axis from rests at three tilts (wang2022sensors Eq 23)",
                              description=_bullet(0) + "\n\n" + common.SCHEMA_HELP
                              + "\n(axis needs only the accelerometer columns)",
                              epilog=AXIS_EXAMPLE, formatter_class=fmt)
    p.add_argument("log", help="IMU log (CSV or Parquet)")
    p.add_argument("--min-separation-deg", default="3", help="rests closer in tilt are one position (deg)")
    p.add_argument("--max-axis-error-deg", default="2", help="refuse an axis less certain than this (deg, 1 sigma)")
    p.add_argument("--max-elevation-deg", default="85", help="refuse an axis steeper than this (deg)")
    common.add_input_options(p)
    common.add_rest_options(p, min_rest_s=0.5)
    p.set_defaults(func=cmd_axis)
    q = subparsers.add_parser("angle", help="EKF rotation angle about a known axis (wang2022sensors)",
                              description=_bullet(1) + "\n\n" + common.SCHEMA_HELP,
                              epilog=ANGLE_EXAMPLE, formatter_class=fmt)
    q.add_argument("log", help="IMU log (CSV or Parquet)")
    q.add_argument("--axis", required=True, help="axis vx,vy,vz in the sensor frame (from `mtcal axis`)")
    q.add_argument("--out", default="angle.csv", help="output table (.csv or .parquet)")
    q.add_argument("--init-s", default="1.0", help="initial rest used for a0 and the bias (s)")
    q.add_argument("--max-elevation-deg", default="85", help="refuse an axis steeper than this (deg)")
    q.add_argument("--max-axis-mismatch-deg", default="10",
                   help="refuse when the gyro turns about an axis this far from --axis (deg)")
    common.add_input_options(q)
    common.add_rest_options(q, min_rest_s=0.2)
    q.set_defaults(func=cmd_angle)
