"""Rest (zero-velocity) detection that adapts to the sensor: levels measured from the data.

A fixed acceleration band such as wang2022sensors Table 1 (9.76–9.84 m/s²,
:mod:`mtcal.methods.zero_velocity`) fits a simulator whose accelerometer reads
exactly 9.80665 m/s² at rest. Real sensors read 0.5–3 % off (scale factor and
bias errors, local gravity), and their gyros carry biases of 0.5–3 °/s, far
above a fixed stillness threshold of 0.2 °/s. This detector measures what the
sensor reads when it is still and sets every threshold from that:

1. The record is cut into non-overlapping windows of ``window_s``. For each
   window the per-axis standard deviations of the accelerometer and of the gyro
   are computed (a standard deviation is blind to a constant gyro bias).
2. The quietest ``quiet_fraction`` of the windows (ranked on accelerometer and
   gyro together) define the rest levels: the local gravity magnitude
   ``g`` is the median of their mean ``‖a‖``, the noise levels ``σ_a``, ``σ_ω``
   the medians of their standard deviations, and the gyro bias ``b`` the
   median of their mean rates.
3. A sample is static when, over a centred window of ``window_s``,

   * the accelerometer standard deviation (rms over axes) is below
     ``max(k σ_a, √(σ_a m_a))``, with ``m_a`` the 90th percentile of the window
     standard deviations (the motion level): rests that are noisier than the
     quietest ones (a foot's stance after a still stand) stay rests as long as
     they are far quieter than the motion (geometric middle of the two levels),
   * the gyro standard deviation is below ``max(k σ_ω, √(σ_ω m_ω))`` likewise,
   * the mean ``‖a‖`` is within ``g ± max(k σ_a, band_fraction g)`` (the band
     allows the few-tenths-of-a-percent change of ``‖a‖`` with orientation
     that accelerometer scale errors cause),
   * the mean rate differs from the bias by less than
     ``max(k σ_ω, min_gyro_level_rad_s)`` (a slow turn about the vertical is
     invisible to the accelerometer; only this condition sees it),

   and runs of static samples shorter than ``min_rest_s`` are dropped.

Every threshold can be overridden. The returned :class:`RestReport` carries the
measured levels, the thresholds used, the rests found and, for each quiet
stretch that was *not* accepted, the reason (outside the band, turning, too
short), so a user sees why a rest was or was not found.

The statistics use centred windows (the detector is for recorded logs, not
causal); sums over blocks of samples and cumulative sums over the blocks make it
O(N). The block sums are compiled (:mod:`mtcal.methods._rest_kernels`, one pass
over the record, no temporaries of its size) and add in numpy's order, so the
levels, rests and report are bit for bit those of the numpy expressions.

References
----------
Wang C., Chen Z., Liu Z., Zhou X., Li X., "Movable surface rotation angle
measurement using inertial sensors", Sensors 22 (2022) 8996,
doi:10.3390/s22228996 (fixed-band ZVD this detector generalises).
Skog I., Händel P., Nilsson J.-O., Rantakokko J., "Zero-velocity detection — an
algorithm evaluation", IEEE Trans. Biomed. Eng. 57 (2010) 2657–2666,
doi:10.1109/TBME.2010.2060723 (accelerometer + gyro rest statistics).

Examples
--------
>>> import numpy as np
>>> rng = np.random.default_rng(0)
>>> fs = 200.0
>>> t = np.arange(int(6 * fs)) / fs
>>> gyro = rng.normal(0, 0.002, (t.size, 3)) + np.radians([1.5, -0.8, 2.0])   # MEMS bias
>>> accel = rng.normal(0, 0.01, (t.size, 3)) + [0.0, 0.0, 9.93]                # |g| 1.3 % high
>>> moving = (t > 2) & (t < 3.5)
>>> gyro[moving, 0] += 1.0
>>> accel[moving, 1] += 2.0 * np.sin(2 * np.pi * t[moving])
>>> rep = detect_rests(accel, 1.0 / fs, gyro_rad_s=gyro)
>>> len(rep.rests), round(rep.gravity_m_s2, 2)
(2, 9.93)
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from mtcal.core.validate import as_float_array, check_accel_units, positive_scalar, sample_interval

__all__ = ["RestDetectorParams", "RestReport", "RejectedRest", "detect_rests", "paper_rest_report", "ShoeParams",
           "shoe_statistic", "detect_rests_shoe", "format_ordered", "warm_up", "QuietCore", "quiet_core"]

DEG = np.pi / 180.0


@dataclass(frozen=True)
class RestDetectorParams:
    """Settings of :func:`detect_rests` (every level is measured unless overridden).

    Parameters
    ----------
    window_s : float
        Analysis window (s); default 0.1 s (long enough to average noise, short
        enough for 0.3 s foot stances).
    quiet_fraction : float
        Fraction of windows taken as the quietest (rest reference), (0, 0.5].
    noise_factor : float
        k: a statistic must stay below k × its rest level.
    min_rest_s : float
        Shortest accepted rest (s).
    band_fraction : float
        Smallest half-width of the ``‖a‖`` band as a fraction of g (0.015 = 1.5 %).
    min_gyro_level_rad_s : float
        Smallest allowed ``|ω̄ − b|`` threshold (rad/s); default 1.5 °/s.
    gravity_m_s2 : float or None
        Override of the measured ``‖a‖`` at rest (m/s²).
    accel_band_m_s2 : float or None
        Override of the band half-width (m/s²).
    accel_std_max_m_s2, gyro_std_max_rad_s, gyro_level_max_rad_s : float or None
        Overrides of the three other thresholds.
    """

    window_s: float = 0.1
    quiet_fraction: float = 0.1
    noise_factor: float = 5.0
    min_rest_s: float = 0.2
    band_fraction: float = 0.015
    min_gyro_level_rad_s: float = 1.5 * DEG
    gravity_m_s2: float | None = None
    accel_band_m_s2: float | None = None
    accel_std_max_m_s2: float | None = None
    gyro_std_max_rad_s: float | None = None
    gyro_level_max_rad_s: float | None = None

    def __post_init__(self) -> None:
        for name in ("window_s", "quiet_fraction", "noise_factor", "band_fraction", "min_gyro_level_rad_s"):
            positive_scalar(getattr(self, name), name)
        positive_scalar(self.min_rest_s, "min_rest_s", allow_zero=True)
        if self.quiet_fraction > 0.5:
            raise ValueError(f"quiet_fraction must be in (0, 0.5], got {self.quiet_fraction}")
        for name in ("gravity_m_s2", "accel_band_m_s2", "accel_std_max_m_s2", "gyro_std_max_rad_s",
                     "gyro_level_max_rad_s"):
            if getattr(self, name) is not None:
                positive_scalar(getattr(self, name), name)
        if self.gravity_m_s2 is not None and not 2.0 < self.gravity_m_s2 < 50.0:
            raise ValueError(f"gravity_m_s2 must be in m/s² (2 … 50), got {self.gravity_m_s2}")


@dataclass(frozen=True)
class RejectedRest:
    """A quiet stretch that was not accepted as a rest: sample range and reason."""

    span: slice
    reason: str


@dataclass(frozen=True)
class RestReport:
    """Outcome of a rest detector: flags, rests, measured levels and thresholds.

    Attributes
    ----------
    is_static : ndarray (N,) of bool
        Static flag per sample (only samples inside accepted rests).
    rests : list of slice
        Accepted rests, in time order.
    rejected : list of RejectedRest
        Quiet stretches not accepted, with the reason.
    method : str
        ``"adaptive"`` or ``"paper"`` (wang2022sensors Table 1 ZVD).
    gravity_m_s2 : float
        ``‖a‖`` at rest used as the band centre (measured or overridden).
    accel_noise_m_s2, gyro_noise_rad_s : float
        Measured per-sample noise std at rest (gyro NaN without gyro).
    gyro_bias_rad_s : ndarray (3,)
        Measured mean rate at rest (NaN without gyro).
    band_m_s2 : tuple of float
        ``(low, high)`` band of ``‖a‖``.
    accel_std_max_m_s2, gyro_std_max_rad_s, gyro_level_max_rad_s : float
        Thresholds used (NaN when not applicable).
    min_rest_s, window_s : float
    n_short : int
        Number of static fragments shorter than ``min_rest_s``.
    extra : dict
        Detector specifics; ``decision_statistic`` (N,) is the statistic that decides
        (static below 1: the largest statistic/threshold ratio, or SHOE ``T/γ``) and
        ``decision_label`` names it; ``measured_gravity_m_s2`` is ``‖a‖`` measured over the
        stillest windows of the record, whatever band the detector used (every detector).
    noise_factor : float
        The detector's factor K of its noise-derived thresholds (``--noise-factor``; 5 for the
        paper's fixed-band detector); the quiet core of a rest (:func:`quiet_core`) uses the same K.
    """

    is_static: np.ndarray
    rests: list
    rejected: list
    method: str
    gravity_m_s2: float
    accel_noise_m_s2: float
    gyro_noise_rad_s: float
    gyro_bias_rad_s: np.ndarray
    band_m_s2: tuple
    accel_std_max_m_s2: float
    gyro_std_max_rad_s: float
    gyro_level_max_rad_s: float
    min_rest_s: float
    window_s: float
    n_short: int = 0
    extra: dict = field(default_factory=dict)
    noise_factor: float = 5.0

    def levels_text(self) -> str:
        """One line with the measured levels and the thresholds (display units)."""
        txt = f"rest detector {self.method}: |a| at rest {self.gravity_m_s2:.4f} m/s^2, "
        if self.method == "shoe":
            txt += (f"SHOE threshold gamma {self.extra['threshold']:.4g} ({self.extra['threshold_source']}; "
                    f"a still accelerometer with |w - bias| {self.extra['rate_equivalent_deg_s']:.2f} deg/s), "
                    f"window {self.window_s:.3f} s, ")
        else:
            txt += f"band {self.band_m_s2[0]:.3f}-{self.band_m_s2[1]:.3f} m/s^2, "
        txt += f"accel noise {self.accel_noise_m_s2:.4f} m/s^2"
        if np.isfinite(self.gyro_noise_rad_s):
            b = np.degrees(self.gyro_bias_rad_s)
            txt += (f", gyro noise {np.degrees(self.gyro_noise_rad_s):.3f} deg/s, "
                    f"gyro bias [{b[0]:+.2f}, {b[1]:+.2f}, {b[2]:+.2f}] deg/s")
        return txt


def centred_moving_mean(x: np.ndarray, window: int) -> np.ndarray:
    """Centred moving mean along axis 0 (edges: the available samples), via cumulative sums.

    Sample i averages ``x[i − window//2 : i − window//2 + window]`` clipped to the record.
    """
    n = x.shape[0]
    c = np.empty((n + 1,) + x.shape[1:])
    c[0] = 0.0
    np.cumsum(x, axis=0, out=c[1:])
    lo_off, hi_off = window // 2, window - window // 2
    out = np.empty(c.shape[:1] + x.shape[1:])[:n]
    i0, i1 = lo_off, n - hi_off + 1
    if i1 > i0:  # interior: full windows, plain slices (no gather)
        np.subtract(c[i0 + hi_off:i1 + hi_off], c[i0 - lo_off:i1 - lo_off], out=out[i0:i1])
        out[i0:i1] /= window
        edges = np.r_[0:i0, i1:n]
    else:
        edges = np.arange(n)
    lo = np.clip(edges - lo_off, 0, n)
    hi = np.clip(edges + hi_off, 0, n)
    cnt = (hi - lo).reshape((-1,) + (1,) * (x.ndim - 1)).astype(float)
    out[edges] = (c[hi] - c[lo]) / cnt
    return out


class _Blocks:
    """Sums over sub-blocks of ``sub`` samples: every statistic then costs one pass over the record.

    Windows are whole numbers of sub-blocks (``k`` ≈ window / sub), centred on each
    sub-block; flags are decided per sub-block (``sub`` ≈ window / 4, e.g. 25 ms at
    1 kHz) and expanded to samples.
    """

    def __init__(self, n: int, w: int):
        self.n = n
        self.sub = max(1, w // 4)
        self.k = max(1, int(round(w / self.sub)))
        self.idx = np.arange(0, n, self.sub)
        self.count = np.diff(np.r_[self.idx, n]).astype(float)
        self.win_count = self.window(self.count)

    def window(self, s: np.ndarray) -> np.ndarray:
        """Centred moving sum over k sub-blocks (clipped at the ends)."""
        nb = s.shape[0]
        c = np.zeros((nb + 1,) + s.shape[1:])
        np.cumsum(s, axis=0, out=c[1:])
        i = np.arange(nb)
        lo = np.clip(i - self.k // 2, 0, nb)
        hi = np.clip(i - self.k // 2 + self.k, 0, nb)
        return c[hi] - c[lo]

    def stats(self, x: np.ndarray):
        """Centred-window mean (nb, d) and rms-over-axes std (nb,) of x (N, d)."""
        from mtcal.methods._rest_kernels import reduceat_sums  # here: importing numba is for callers only

        off = x[: min(self.n, 1000)].mean(axis=0)  # centred: the sums keep their precision
        s1, s2 = reduceat_sums(x, self.idx, off)  # np.add.reduceat of x - off and its square, bit for bit
        c = self.win_count[:, None]
        m1 = self.window(s1) / c
        var = np.maximum(self.window(s2) / c - m1 * m1, 0.0)
        return m1 + off, np.sqrt(var.mean(axis=1))

    def to_samples(self, b: int) -> int:
        return int(self.idx[b]) if b < self.idx.size else self.n


def warm_up() -> None:
    """Compile (or load from numba's cache) the compiled block sums of :func:`detect_rests`, the compiled
    ZVD it calls (:func:`mtcal.methods.zero_velocity.detect_static`) and the batched rest means of
    the axis estimate that follows it (:func:`mtcal.methods.rotation_axis.axes_from_rests`).

    Examples
    --------
    >>> warm_up()
    """
    from mtcal.methods import _axis_kernels, _rest_kernels, _zvd_kernels

    _rest_kernels.warm_up()
    _zvd_kernels.warm_up()
    _axis_kernels.warm_up()


def runs(flag: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Start and stop indices of the runs of True in a 1-D boolean array."""
    d = np.diff(np.concatenate([[0], flag.astype(np.int8), [0]]))
    return np.flatnonzero(d == 1), np.flatnonzero(d == -1)


def _block_levels(accel: np.ndarray, norm: np.ndarray, gyro: np.ndarray | None, w: int,
                  quiet_fraction: float):
    """Rest levels from the quietest non-overlapping windows (medians); sums, not per-block calls."""
    nb = accel.shape[0] // w
    if nb < 3:
        raise ValueError(f"record too short for rest detection: {accel.shape[0]} samples, need at least "
                         f"3 windows of {w} samples")

    from mtcal.methods._rest_kernels import block_sums, row_block_sums  # here: numba only when called

    def block_stats(x):
        # sums of d = x - (the block's first sample) (a per-block offset keeps them precise) and of d²
        if x.flags.c_contiguous:
            s1, s2 = block_sums(x, w)  # compiled, bit for bit numpy's sums over axis 1 below
        else:  # numpy's summation order follows the memory layout: the numpy expression itself
            b = x[: nb * w].reshape(nb, w, -1)
            b = b - b[:, :1]
            s1 = b.sum(axis=1)
            b *= b
            s2 = b.sum(axis=1)
        m1 = s1 / w
        var = np.maximum(s2 / w - m1 * m1, 0.0)
        return np.sqrt(var.mean(axis=1)), m1 + x[: nb * w: w]

    a_std, _ = block_stats(accel)
    a_norm = row_block_sums(norm, w) / w  # = norm[: nb * w].reshape(nb, w).mean(axis=1), bit for bit
    score = np.argsort(np.argsort(a_std)).astype(float)
    if gyro is not None:
        g_std, g_mean = block_stats(gyro)
        score += np.argsort(np.argsort(g_std))
    m = max(3, int(np.ceil(quiet_fraction * nb)))
    quiet = np.argpartition(score, m - 1)[:m]
    out = {"gravity": float(np.median(a_norm[quiet])), "accel_noise": float(np.median(a_std[quiet])),
           "accel_motion": float(np.percentile(a_std, 90))}
    if gyro is not None:
        out["gyro_noise"] = float(np.median(g_std[quiet]))
        out["gyro_bias"] = np.median(g_mean[quiet], axis=0)
        out["gyro_motion"] = float(np.percentile(g_std, 90))
    return out


#: Floors of the measured noise (quantised sensors can read a constant at rest).
ACCEL_NOISE_FLOOR_M_S2 = 2e-3
GYRO_NOISE_FLOOR_RAD_S = 2e-4


def detect_rests(accel_m_s2: np.ndarray, dt_s: float, *, gyro_rad_s: np.ndarray | None = None,
                 params: RestDetectorParams | None = None) -> RestReport:
    """Adaptive rest detection (see the module docstring for the statistics).

    Parameters
    ----------
    accel_m_s2 : ndarray, shape (N, 3)
        Specific force (m/s²).
    dt_s : float
        Sample interval (s), ≤ 1 s.
    gyro_rad_s : ndarray, shape (N, 3), optional
        Angular rate (rad/s); without it only the accelerometer decides.
    params : RestDetectorParams, optional

    Returns
    -------
    RestReport

    Raises
    ------
    ValueError
        A record shorter than three windows.

    Preconditions
    -------------
    The caller guarantees (not checked here): ``accel_m_s2`` finite float64 (N, 3) in m/s², not g
    (:func:`mtcal.core.validate.check_accel_units`); ``dt_s`` a sample interval in (0, 1] s;
    ``gyro_rad_s`` None or finite float64 (N, 3) in rad/s; ``params`` None or a
    :class:`RestDetectorParams`. :func:`mtcal.systems.rests.find_rests` checks a record once at its edge.
    """
    a, g = accel_m_s2, gyro_rad_s
    p = RestDetectorParams() if params is None else params
    fs = 1.0 / dt_s  # the rate: exact for the rates mtcal uses (1 / (1 / fs) == fs)
    w = max(3, int(round(p.window_s * fs)))
    norm = np.einsum("ij,ij->i", a, a)
    np.sqrt(norm, out=norm)  # in place: one record-sized array fewer (fresh pages cost ~2 ms/MB to fault in)
    lv = _block_levels(a, norm, g, w, p.quiet_fraction)
    k = p.noise_factor
    grav = p.gravity_m_s2 if p.gravity_m_s2 is not None else lv["gravity"]
    sig_a = max(lv["accel_noise"], ACCEL_NOISE_FLOOR_M_S2)
    a_std_max = (p.accel_std_max_m_s2 if p.accel_std_max_m_s2 is not None
                 else max(k * sig_a, np.sqrt(sig_a * lv["accel_motion"])))
    half = p.accel_band_m_s2 if p.accel_band_m_s2 is not None else max(k * sig_a, p.band_fraction * grav)
    band = (grav - half, grav + half)

    blk = _Blocks(a.shape[0], w)
    norm_mean = blk.stats(norm[:, None])[0][:, 0]
    _, a_std = blk.stats(a)
    quiet = a_std < a_std_max
    in_band = (norm_mean > band[0]) & (norm_mean < band[1])
    sig_w = bias = np.nan
    g_std_max = g_lvl_max = np.nan
    level = None
    if g is not None:
        sig_w = max(lv["gyro_noise"], GYRO_NOISE_FLOOR_RAD_S)
        bias = lv["gyro_bias"]
        g_std_max = (p.gyro_std_max_rad_s if p.gyro_std_max_rad_s is not None
                     else max(k * sig_w, np.sqrt(sig_w * lv["gyro_motion"])))
        g_lvl_max = (p.gyro_level_max_rad_s if p.gyro_level_max_rad_s is not None
                     else max(k * sig_w, p.min_gyro_level_rad_s))
        g_mean, g_std = blk.stats(g)
        quiet_a = quiet.copy()
        quiet &= g_std < g_std_max
        level = np.linalg.norm(g_mean - bias, axis=1)
        still = level < g_lvl_max
    else:
        still = np.ones_like(quiet)
        quiet_a, g_std = quiet, None
    static = quiet & in_band & still
    ratio = np.maximum(a_std / a_std_max, np.abs(norm_mean - 0.5 * (band[0] + band[1])) / (0.5 * (band[1] - band[0])))
    if g is not None:
        ratio = np.maximum(ratio, np.maximum(g_std / g_std_max, level / g_lvl_max))
    noise = {"accel": (a_std, a_std_max, quiet_a), "gyro": (g_std, g_std_max)}
    rests, rejected, n_short, static = _classify(blk, static, quiet, in_band, still, norm_mean, level, band,
                                                 g_lvl_max, int(round(p.min_rest_s * fs)), w, fs, noise)
    return RestReport(is_static=static, rests=rests, rejected=rejected, method="adaptive",
                      gravity_m_s2=float(grav), accel_noise_m_s2=float(sig_a),
                      gyro_noise_rad_s=float(sig_w),
                      gyro_bias_rad_s=np.full(3, np.nan) if g is None else np.asarray(bias, float),
                      band_m_s2=(float(band[0]), float(band[1])), accel_std_max_m_s2=float(a_std_max),
                      gyro_std_max_rad_s=float(g_std_max), gyro_level_max_rad_s=float(g_lvl_max),
                      min_rest_s=float(p.min_rest_s), window_s=float(w / fs), n_short=n_short,
                      noise_factor=float(p.noise_factor),
                      extra={"decision_statistic": np.repeat(ratio, blk.count.astype(int)),
                             "decision_label": "max(statistic / threshold)",
                             "measured_gravity_m_s2": lv["gravity"]})


def _classify(blk, static, quiet, in_band, still, norm_mean, level, band, g_lvl_max, n_min, w, fs, noise):
    """Accept static runs ≥ n_min samples; explain every quiet stretch that holds no accepted rest.

    Inputs are per sub-block; rests are returned as sample slices and per-sample flags.
    """
    bs, be = runs(static)
    s0 = np.array([blk.to_samples(b) for b in bs], dtype=int)
    s1 = np.array([blk.to_samples(b) for b in be], dtype=int)
    keep = (s1 - s0) >= max(n_min, 1)
    rests = [slice(int(a), int(b)) for a, b in zip(s0[keep], s1[keep])]
    flags = np.zeros(blk.n, bool)
    for r in rests:
        flags[r] = True
    rejected = []
    n_short = int(np.count_nonzero(~keep))
    qs, qe = runs(quiet | (in_band & still))  # candidates: quiet, or at the rest level
    has_rest = np.zeros(qs.size, bool)
    if np.any(keep):
        pos = np.searchsorted(qs, bs[keep], side="right") - 1
        has_rest[pos[pos >= 0]] = True
    q0 = np.array([blk.to_samples(b) for b in qs], dtype=int)
    q1 = np.array([blk.to_samples(b) for b in qe], dtype=int)
    long_enough = (q1 - q0) >= w
    min_s = n_min / fs
    for i in np.flatnonzero(long_enough & ~has_rest):
        sl = slice(int(q0[i]), int(q1[i]))
        bsl = slice(int(qs[i]), int(qe[i]))
        out_band = 1.0 - in_band[bsl].mean()
        turning = 0.0 if level is None else 1.0 - still[bsl].mean()
        noisy = 1.0 - quiet[bsl].mean()
        rs, re_ = runs(static[bsl])
        cnt = blk.count[bsl]
        longest = max((float(cnt[x:y].sum()) / fs for x, y in zip(rs, re_)), default=0.0)
        lo, hi = format_ordered(longest, min_s, 3)
        tail = f"; longest static run {lo} s < {hi} s (--min-rest-s)"
        if static[bsl].mean() >= 0.5:
            reason = f"too short: longest static run {lo} s < {hi} s (--min-rest-s)"
        elif noisy > max(out_band, turning):
            a_std, a_max, quiet_a = noise["accel"]
            fail_a = ~quiet_a[bsl]
            if fail_a.mean() >= 0.5 * noisy:
                v, m = format_ordered(a_max, float(np.median(a_std[bsl][fail_a])), 4)
                reason = (f"not still: accel std {m} > {v} m/s^2 (median of the {100 * fail_a.mean():.0f} % of "
                          f"the stretch above the limit; --noise-factor raises it){tail}")
            else:
                g_std, g_max = noise["gyro"]
                fail_g = ~(g_std[bsl] < g_max)
                v, m = format_ordered(np.degrees(g_max), float(np.degrees(np.median(g_std[bsl][fail_g]))), 3)
                reason = (f"not still: gyro std {m} > {v} deg/s (median of the {100 * fail_g.mean():.0f} % of "
                          f"the stretch above the limit; --noise-factor raises it){tail}")
        elif out_band >= turning and out_band > 0:
            vals = norm_mean[bsl][~in_band[bsl]]
            high = vals >= band[1]
            if high.mean() >= 0.5:
                v, m = format_ordered(band[1], float(np.median(vals[high])), 3)
                cmp = f"|a| {m} > {v} m/s^2"
            else:
                m, v = format_ordered(float(np.median(vals[~high])), band[0], 3)
                cmp = f"|a| {m} < {v} m/s^2"
            reason = (f"outside band: {cmp} (band {band[0]:.3f} to {band[1]:.3f}; median of the "
                      f"{100 * out_band:.0f} % of the stretch outside; --accel-band widens it){tail}")
        elif turning > 0:
            fail = ~still[bsl]
            v, m = format_ordered(np.degrees(g_lvl_max), float(np.degrees(np.median(level[bsl][fail]))), 2)
            reason = (f"turning: |w - bias| {m} > {v} deg/s (median of the {100 * turning:.0f} % of the "
                      f"stretch above the limit; --gyro-threshold-deg-s raises it){tail}")
        else:
            reason = f"too short: longest static run {lo} s < {hi} s (--min-rest-s)"
        rejected.append(RejectedRest(sl, reason))
    return rests, rejected, n_short, flags


def format_ordered(low: float, high: float, decimals: int) -> tuple[str, str]:
    """``low < high`` formatted with at least ``decimals`` decimals, more when needed to keep the order.

    Examples
    --------
    >>> format_ordered(0.1996, 0.2, 3)
    ('0.1996', '0.2000')
    """
    for d in range(decimals, 12):
        a, b = f"{low:.{d}f}", f"{high:.{d}f}"
        if float(a) < float(b):
            return a, b
    return repr(float(low)), repr(float(high))


def paper_rest_report(accel_m_s2: np.ndarray, dt_s: float, *, gyro_rad_s: np.ndarray | None = None,
                      min_rest_s: float = 0.5, zvd=None) -> RestReport:
    """wang2022sensors Table 1 ZVD (:func:`mtcal.methods.zero_velocity.detect_static`) as a :class:`RestReport`.

    The flags are the paper's, unchanged (``is_static``); ``rests`` are its
    runs of at least ``min_rest_s``. The measured levels are reported beside
    the fixed band so a user sees when the band misses the sensor. ``dt_s`` is the sample
    interval (s), ≤ 1 s; ``zvd`` the :class:`~mtcal.methods.zero_velocity.ZvdParams` (Table 1 by default).

    Preconditions
    -------------
    The caller guarantees (not checked here): ``accel_m_s2`` finite float64 (N, 3) in m/s², not g; ``dt_s``
    a sample interval in (0, 1] s; ``gyro_rad_s`` None or finite float64 (N, 3) in rad/s; ``min_rest_s`` ≥ 0
    (s); ``zvd`` None or a ZvdParams. :func:`mtcal.systems.rests.find_rests` and
    :func:`mtcal.systems.surface_angle.surface_axis_record` check a record once at their edge.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.tile([0.0, 0.0, 9.80665], (300, 1)); a[100:150] += 1.0
    >>> paper_rest_report(a, 0.01, min_rest_s=0.2).rests
    [slice(0, 100, None), slice(152, 300, None)]
    """
    from mtcal.methods.zero_velocity import ZvdParams, detect_static

    a, g, dt = accel_m_s2, gyro_rad_s, dt_s
    zp = ZvdParams() if zvd is None else zvd
    fs = 1.0 / dt
    flags = detect_static(a, dt, zp)
    w = max(3, int(round(0.1 * fs)))
    lv = _block_levels(a, np.linalg.norm(a, axis=1), g, w, 0.1)
    starts, stops = runs(flags)
    keep = (stops - starts) >= max(int(round(min_rest_s * fs)), 1)
    rests = [slice(int(s), int(e)) for s, e in zip(starts[keep], stops[keep])]
    return RestReport(is_static=flags, rests=rests, rejected=[], method="paper",
                      gravity_m_s2=0.5 * (zp.accel_min_m_s2 + zp.accel_max_m_s2),
                      accel_noise_m_s2=lv["accel_noise"],
                      gyro_noise_rad_s=lv.get("gyro_noise", np.nan),
                      gyro_bias_rad_s=np.asarray(lv.get("gyro_bias", np.full(3, np.nan)), float),
                      band_m_s2=(zp.accel_min_m_s2, zp.accel_max_m_s2),
                      accel_std_max_m_s2=float(np.sqrt(zp.var_threshold_m2_s4)), gyro_std_max_rad_s=np.nan,
                      gyro_level_max_rad_s=np.nan, min_rest_s=float(min_rest_s), window_s=zp.window_s,
                      n_short=int(np.count_nonzero(~keep)),
                      extra={"measured_gravity_m_s2": lv["gravity"]})


@dataclass(frozen=True)
class ShoeParams:
    """Settings of :func:`detect_rests_shoe` (SHOE / GLRT stance detector, Skog et al. 2010).

    Parameters
    ----------
    window_s : float
        Window ``W`` of the test statistic (s); default 0.05 s (60 samples at 1200 Hz).
    min_rest_s : float
        Shortest accepted rest (s).
    quiet_fraction : float
        Share of the quietest 0.1 s windows that measure σa, σω, g and the gyro bias.
    noise_factor : float
        ``k`` of the smallest adaptive threshold ``γ_min = 6 (1 + k/√W)`` (W in
        samples): ``T`` of a still sensor averages 6 with a spread of about 6/√W.
    threshold : float or None
        ``γ`` itself (dimensionless); overrides everything below.
    rate_level_rad_s : float or None
        Quasi-static level: ``γ = 6 + (ω_qs / σω)²``, the statistic of a window turning
        steadily at ``ω_qs`` with a still accelerometer (e.g. 30 °/s for a foot's stance).
    gravity_m_s2 : float or None
        Override of the measured ``‖a‖`` at rest.
    """

    window_s: float = 0.05
    min_rest_s: float = 0.2
    quiet_fraction: float = 0.1
    noise_factor: float = 5.0
    threshold: float | None = None
    rate_level_rad_s: float | None = None
    gravity_m_s2: float | None = None

    def __post_init__(self) -> None:
        for name in ("window_s", "quiet_fraction", "noise_factor"):
            positive_scalar(getattr(self, name), name)
        positive_scalar(self.min_rest_s, "min_rest_s", allow_zero=True)
        for name in ("threshold", "rate_level_rad_s", "gravity_m_s2"):
            if getattr(self, name) is not None:
                positive_scalar(getattr(self, name), name)


def shoe_statistic(accel_m_s2: np.ndarray, gyro_rad_s: np.ndarray, window: int, *, gravity_m_s2: float,
                   accel_noise_m_s2: float, gyro_noise_rad_s: float, gyro_bias_rad_s=0.0) -> np.ndarray:
    """SHOE test statistic per sample over a centred window (Skog et al. 2010, Eq 11).

    ``T_k = (1/W) Σ_{j ∈ W_k} [ ‖y_a,j − g ȳ_a/‖ȳ_a‖‖² / σa² + ‖y_ω,j − b‖² / σω² ]``

    with ``ȳ_a`` the window's mean specific force, ``g`` the gravity magnitude at
    rest and ``b`` the gyro bias (Skog et al. use raw rates; a MEMS bias of a
    few °/s would dominate ``T``, so the measured bias is removed). Using
    ``Σ‖y − c‖² = Σ‖y − ȳ‖² + W‖ȳ − c‖²`` it costs a few moving sums.

    Parameters
    ----------
    accel_m_s2, gyro_rad_s : ndarray (N, 3)
    window : int
        ``W`` (samples).
    gravity_m_s2, accel_noise_m_s2, gyro_noise_rad_s : float
        ``g``, ``σa`` (m/s²), ``σω`` (rad/s).
    gyro_bias_rad_s : array_like (3,) or float

    Returns
    -------
    ndarray (N,)
        ``T`` (dimensionless; about 6 for a still sensor, the sum of two χ²₃ means).
    """
    a = accel_m_s2
    w = gyro_rad_s - np.asarray(gyro_bias_rad_s, float)
    ma = centred_moving_mean(a, window)
    ma2 = centred_moving_mean(np.einsum("ij,ij->i", a, a)[:, None], window)[:, 0]
    mw2 = centred_moving_mean(np.einsum("ij,ij->i", w, w)[:, None], window)[:, 0]
    norm = np.sqrt(np.einsum("ij,ij->i", ma, ma))
    # (1/W) Σ ‖y − c‖² with c = g ȳ/‖ȳ‖: mean square − 2 c·ȳ + ‖c‖² = ma2 − 2 g ‖ȳ‖ + g²
    acc_term = np.maximum(ma2 - 2.0 * gravity_m_s2 * norm + gravity_m_s2 ** 2, 0.0)
    return acc_term / accel_noise_m_s2 ** 2 + mw2 / gyro_noise_rad_s ** 2


def detect_rests_shoe(accel_m_s2: np.ndarray, dt_s: float, *, gyro_rad_s: np.ndarray,
                      params: ShoeParams | None = None) -> RestReport:
    """Quasi-static rests (e.g. a foot's stance phases) by the SHOE detector of Skog et al. (2010).

    The stance hypothesis test of Skog et al. (GLRT "SHOE", their Eq 11) flags a
    sample static when :func:`shoe_statistic` ``T < γ``. Adapted to the sensor:

    * ``σa``, ``σω``, ``g`` and the gyro bias are measured on the quietest
      0.1 s windows (as :func:`detect_rests`), not taken from a data sheet;
    * ``γ`` is, in order: ``params.threshold``; ``6 + (ω_qs/σω)²`` from the
      quasi-static level ``params.rate_level_rad_s``; or the geometric mean of
      the quiet level (median ``T`` of the quietest windows) and the motion level
      (90th percentile of ``T``), never below ``6 (1 + k/√W)``;
    * runs of ``T < γ`` shorter than ``min_rest_s`` are rejected ("too short").

    Parameters
    ----------
    accel_m_s2, gyro_rad_s : array_like, shape (N, 3)
        Specific force (m/s²) and angular rate (rad/s).
    dt_s : float
        Sample interval (s).
    params : ShoeParams, optional

    Returns
    -------
    RestReport
        ``method == "shoe"``; ``band_m_s2`` is ``g ± max(k σa, 1.5 % g)`` for
        consumers that gate on ``‖a‖`` (SHOE itself uses no band); ``extra`` holds ``statistic`` (``T`` per sample),
        ``threshold`` (``γ``), ``decision_statistic`` (``T/γ``, static below 1)
        and ``decision_label``.

    References
    ----------
    Skog I., Händel P., Nilsson J.-O., Rantakokko J., "Zero-velocity detection —
    an algorithm evaluation", IEEE Trans. Biomed. Eng. 57(11) (2010) 2657–2666,
    Eq 11 (SHOE statistic), Sec. IV (window W, threshold γ).

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(1)
    >>> fs = 400.0
    >>> t = np.arange(int(4 * fs)) / fs
    >>> gyro = rng.normal(0, 0.003, (t.size, 3)) + np.radians([1.0, -2.0, 0.5])
    >>> accel = rng.normal(0, 0.02, (t.size, 3)) + [0.0, 0.0, 9.9]
    >>> swing = (t > 1.5) & (t < 2.0)
    >>> gyro[swing, 1] += 6.0 * np.sin(np.pi * (t[swing] - 1.5) / 0.5)
    >>> accel[swing, 0] += 15.0 * np.sin(2 * np.pi * (t[swing] - 1.5) / 0.5)
    >>> rep = detect_rests_shoe(accel, 1 / fs, gyro_rad_s=gyro)
    >>> len(rep.rests), rep.method
    (2, 'shoe')

    Preconditions
    -------------
    The caller guarantees (not checked here): ``accel_m_s2`` finite float64 (N, 3) in m/s², not g; ``dt_s``
    a sample interval in (0, 1] s; ``gyro_rad_s`` finite float64 (N, 3) in rad/s; ``params`` None or a
    :class:`ShoeParams`. :func:`mtcal.systems.rests.find_rests` checks a record once at its edge.
    """
    a, g = accel_m_s2, gyro_rad_s
    p = ShoeParams() if params is None else params
    fs = 1.0 / dt_s
    w_lv = max(3, int(round(0.1 * fs)))
    norm = np.einsum("ij,ij->i", a, a)
    np.sqrt(norm, out=norm)  # in place: one record-sized array fewer (fresh pages cost ~2 ms/MB to fault in)
    lv = _block_levels(a, norm, g, w_lv, p.quiet_fraction)
    grav = p.gravity_m_s2 if p.gravity_m_s2 is not None else lv["gravity"]
    sig_a = max(lv["accel_noise"], ACCEL_NOISE_FLOOR_M_S2)
    sig_w = max(lv["gyro_noise"], GYRO_NOISE_FLOOR_RAD_S)
    bias = lv["gyro_bias"]
    w = max(3, int(round(p.window_s * fs)))
    stat = shoe_statistic(a, g, w, gravity_m_s2=grav, accel_noise_m_s2=sig_a, gyro_noise_rad_s=sig_w,
                          gyro_bias_rad_s=bias)
    floor = 6.0 * (1.0 + p.noise_factor / np.sqrt(w))
    if p.threshold is not None:
        gamma, how = float(p.threshold), "given"
    elif p.rate_level_rad_s is not None:
        gamma = 6.0 + (p.rate_level_rad_s / sig_w) ** 2
        how = f"quasi-static level {np.degrees(p.rate_level_rad_s):g} deg/s"
    else:
        nb = stat.size // w_lv
        tb = stat[: nb * w_lv].reshape(nb, w_lv).mean(axis=1)
        quiet = float(np.median(np.sort(tb)[: max(3, int(np.ceil(p.quiet_fraction * nb)))]))
        motion = float(np.percentile(tb, 90))
        gamma, how = max(floor, float(np.sqrt(max(quiet, 1e-12) * motion))), "adaptive"
    below = stat < gamma
    n_min = max(int(round(p.min_rest_s * fs)), 1)
    s0, s1 = runs(below)
    keep = (s1 - s0) >= n_min
    rests = [slice(int(x), int(y)) for x, y in zip(s0[keep], s1[keep])]
    flags = np.zeros(a.shape[0], bool)
    for r in rests:
        flags[r] = True
    rejected = []
    for x, y in zip(s0[~keep], s1[~keep]):
        if y - x >= w:
            seg = stat[x:y]
            lo, hi = format_ordered((y - x) / fs, p.min_rest_s, 3)
            t_med, t_max = format_ordered(float(np.median(seg)), gamma, 1)
            rejected.append(RejectedRest(slice(int(x), int(y)),
                                         f"too short: {lo} s < {hi} s (--min-rest-s) below the SHOE threshold "
                                         f"(median T {t_med} < gamma {t_max})"))
    rate_eq = float(np.degrees(sig_w * np.sqrt(max(gamma - 6.0, 0.0))))
    half = max(p.noise_factor * sig_a, 0.015 * grav)  # |a| band for consumers (e.g. a QNCF gate); SHOE uses none
    return RestReport(is_static=flags, rests=rests, rejected=rejected, method="shoe", gravity_m_s2=float(grav),
                      accel_noise_m_s2=float(sig_a), gyro_noise_rad_s=float(sig_w),
                      gyro_bias_rad_s=np.asarray(bias, float),
                      band_m_s2=(float(grav - half), float(grav + half)),
                      accel_std_max_m_s2=np.nan, gyro_std_max_rad_s=np.nan, gyro_level_max_rad_s=np.nan,
                      min_rest_s=float(p.min_rest_s), window_s=float(w / fs), n_short=int(np.count_nonzero(~keep)),
                      noise_factor=float(p.noise_factor),
                      extra={"statistic": stat, "threshold": float(gamma), "threshold_source": how,
                             "rate_equivalent_deg_s": rate_eq, "decision_statistic": stat / gamma,
                             "decision_label": "SHOE T / gamma", "measured_gravity_m_s2": lv["gravity"]})


@dataclass(frozen=True)
class QuietCore:
    """Outcome of :func:`quiet_core`: the quiet part of a rest and the gyro bias measured over it.

    Attributes
    ----------
    core : slice
        Samples of the record (a sub-slice of the rest) whose moving-mean rate stays within the
        threshold of the bias.
    rest : slice
        The rest it was cut from.
    bias_rad_s : ndarray (3,)
        Mean gyro rate over ``core`` (rad/s).
    threshold_rad_s : float
        Largest accepted per-axis deviation of the moving mean from the bias (rad/s),
        ``noise_factor · σ_ω / √window``.
    window : int
        Moving-mean window (samples).
    noise_rad_s, noise_factor : float
        The per-sample noise std (rad/s) and the factor the threshold was made of.
    """

    core: slice
    rest: slice
    bias_rad_s: np.ndarray
    threshold_rad_s: float
    window: int
    noise_rad_s: float
    noise_factor: float


def quiet_core(gyro_rad_s, rest: slice, dt_s: float, gyro_noise_rad_s: float, *, noise_factor: float = 5.0,
               window_s: float = 0.05) -> QuietCore:
    """The quiet core of a rest and the gyro bias over it (threshold from the measured noise).

    A rest found with a rate threshold of a few °/s can run into a slow start of motion
    (a taxiing aircraft, a minimum-jerk turntable move): its mean rate then carries part
    of the motion, and a yaw integrated with that "bias" drifts. Here the bias is measured
    only where the rate is indistinguishable from white noise about it:

    1. ``b`` = median rate over the rest;
    2. moving mean ``m`` of ``ω − b`` over ``window_s``; its white-noise std per axis is
       ``σ_ω / √W`` (``W`` samples), so a sample is quiet when every axis of ``m`` is within
       ``noise_factor · σ_ω / √W`` — a threshold derived from the measured noise, not a
       fixed floor;
    3. the core is the longest quiet run, shortened by ``W/2`` at each end (the moving mean
       spreads the first motion over half a window); ``b`` = its mean, and steps 2–3 are
       repeated once with that ``b``.

    A core shorter than ``2 W`` samples (a rest too noisy for its stated noise) falls back to
    the whole rest.

    Parameters
    ----------
    gyro_rad_s : ndarray, shape (N, 3)
        Angular rate (rad/s).
    rest : slice
        The rest (sample slice) to examine.
    dt_s : float
        Sample interval (s).
    gyro_noise_rad_s : float
        Per-sample gyro noise std at rest (rad/s), e.g. :attr:`RestReport.gyro_noise_rad_s`.
    noise_factor : float
        Threshold in noise standard deviations of the moving mean (default 5).
    window_s : float
        Moving-mean window (s), at least 5 samples.

    Returns
    -------
    QuietCore

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> t = np.arange(4000) / 1000.0
    >>> gyro = rng.normal(0.0, 1e-3, (t.size, 3)) + [0.005, -0.003, 0.004]
    >>> gyro[3000:, 2] += 0.05 * (t[3000:] - 3.0)             # a slow start of motion at 3 s
    >>> qc = quiet_core(gyro, slice(0, 4000), 1e-3, 1e-3)
    >>> qc.core.stop < 3100, bool(np.abs(qc.bias_rad_s[2] - 0.004) < 1e-4)
    (True, True)
    """
    w = np.asarray(gyro_rad_s, float)[rest]
    n = w.shape[0]
    win = max(5, int(round(float(window_s) / float(dt_s))))
    thr = float(noise_factor) * float(gyro_noise_rad_s) / np.sqrt(win)
    start, stop = 0, n
    bias = np.median(w, axis=0)
    if n >= 3 * win and thr > 0:
        for _ in range(2):
            quiet = np.all(np.abs(centred_moving_mean(w - bias, win)) < thr, axis=1)
            a, b = runs(quiet)
            if a.size == 0:
                start, stop = 0, n
                break
            i = int(np.argmax(b - a))
            s0, s1 = int(a[i]) + (win // 2 if a[i] > 0 else 0), int(b[i]) - (win // 2 if b[i] < n else 0)
            if s1 - s0 < 2 * win:
                start, stop = 0, n
                break
            start, stop = s0, s1
            bias = w[start:stop].mean(axis=0)
    bias = w[start:stop].mean(axis=0)
    r0 = 0 if rest.start is None else rest.start
    return QuietCore(core=slice(r0 + start, r0 + stop), rest=rest, bias_rad_s=bias, threshold_rad_s=thr,
                     window=win, noise_rad_s=float(gyro_noise_rad_s), noise_factor=float(noise_factor))
