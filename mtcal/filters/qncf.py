"""Quaternion Nonlinear Complementary Filter (QNCF) with an Acceleration Magnitude Detector.

wang2023cja (Wang et al., CJA 2023) §3 solves the attitude of the IMU (s-frame)
with the QNCF of its ref. 18. The paper gives the gyro update (Eq 5–7), the
Euler extraction (Eq 8) and the gating rule "the PI controller works when
Thr < 0.3", but neither the PI law nor the AMD statistic. Both are defined
here explicitly.

Derivation
----------
Attitude: ``q`` is the scalar-first unit quaternion of the sensor frame with
respect to the world frame (s → w, z up), ``v_w = C(q) v_s``.

1. Kinematics (Eq 5): ``q̇ = ½ q ⊗ [0, ω]`` with ω the body (s-frame) rate.
2. Discrete update with angular increments (Eq 6–7): over one sample
   ``Δθ_k = ω̃_k Δt`` (rad) and ::

       q_{k+1} = q_k ⊗ q(h),   q(h) = [cos(|Δθ|/2), Δθ/|Δθ| · sin(|Δθ|/2)]

   which is exact when ω̃_k is the mean rate over the interval (what an
   integrating gyro reports, see :mod:`mtcal.core.simulate`).
3. Accelerometer correction (Mahony-type PI on the gravity direction): the
   predicted "up" direction in the s-frame is the third row of ``C(q)``::

       v̂ = C(q)ᵀ e_z = [2(q1q3 − q0q2), 2(q2q3 + q0q1), q0² − q1² − q2² + q3²]

   (its y and z components are the arguments of Eq 8's pitch and roll). The
   measured one is ``â = a / ‖a‖`` (at rest a level accelerometer reads +g
   up). The error ``e = â × v̂`` (rad, small-angle tilt error) drives a PI
   controller that corrects the rate before the increment is formed::

       I_k   = I_{k−1} + K_i e_k Δt          (integral state, rad/s; gated)
       ω̃_k  = ω_k + K_p e_k + I_k           (corrected rate, rad/s)

   With ``e = 0`` (gate closed) the update is pure gyro integration and the
   integral (a horizontal-axis gyro-bias estimate) is frozen but still
   applied. Yaw (rotation about gravity) is unobservable by the
   accelerometer and is integrated from the gyro only.
4. Acceleration Magnitude Detector (AMD). The paper only says "AMD parameter
   Thr … reflects the magnitude of the vibration; when it is smaller than
   0.3 the PI controller can work". Defined here as the exponentially
   smoothed relative deviation of the specific-force magnitude from gravity,
   **in percent of g**::

       d_k   = 100 · | ‖a_k‖ / g − 1 |                       (%)
       AMD_k = AMD_{k−1} + (Δt / τ_AMD) (d_k − AMD_{k−1}),   AMD_0 = d_0

   and the PI correction is enabled when ``AMD_k < Thr`` (``Thr = 0.3`` %,
   i.e. a mean deviation of 0.003 g ≈ 0.03 m/s²). With this scaling the
   threshold is meaningful: a static tactical MEMS accelerometer (25 µg/√Hz
   at 1 kHz: per-sample σ ≈ 0.08 %) stays well below 0.3, slow turntable
   moves (centripetal ≲ 0.01 %) stay below, and model vibration in a running
   hypersonic tunnel (≳ 0.5 m/s² at tens of Hz: AMD ≳ 3 %) trips it.
5. Euler angles are extracted with Eq 8
   (:func:`mtcal.core.rotations.euler_zxy_from_quat`).

Implementation: two engines behind the same API (``engine=``).

* ``"numba"`` (default): compiled float64 kernels
  (:mod:`mtcal.filters._kernels_qncf`), a single-trial kernel and a
  trial-parallel one (``prange`` over trials); each trial is computed
  independently, so results are bit-identical for any numba thread count and
  any chunking of the record.
* ``"numpy"``: the readable reference — the time loop is the only Python
  loop; every step is vectorised over Monte Carlo trials (leading axis), works
  in place on preallocated component-major buffers.

Both compute the same operations in the same order; they agree to a few
1e-16 rad per sample (the reference picks the increment series order per time
block from a bound, the kernel per sample; both series are exact to double
precision). Neither mutates the caller's arrays. :class:`QncfFilter` keeps the
state so a long record can be processed in chunks (bounded memory);
:func:`qncf` runs a whole record in one call.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mtcal.core import rotations
from mtcal.core.compiled import component_major
from mtcal.filters._kernels_common import check_engine, check_kernel_scan, record, use_parallel
from mtcal.core.validate import (STANDARD_GRAVITY_M_S2, as_float_array, check_accel_units, check_gyro_units,
                             positive_scalar, unit_quaternion)
from mtcal.methods.tilt_rate import check_tilt_rate_scale

__all__ = ["QncfParams", "QncfResult", "QncfFilter", "qncf", "amd_statistic",
           "initial_attitude_from_accel"]


@dataclass(frozen=True)
class QncfParams:
    """QNCF tuning.

    Parameters
    ----------
    kp_rad_s : float
        Proportional gain K_p (1/s; rad/s of correction per rad of tilt error).
        Default 1.0 /s: tilt time constant 1 s, settled within a 3 s rest
        (wang2023cja §3.2) — chosen here, the paper gives no gains.
    ki_rad_s2 : float
        Integral gain K_i (1/s²). Default 0.02 /s² (bias-estimate time
        constant K_p/K_i = 50 s) — chosen here. The integral has no
        anti-windup: a start far from the true tilt (a given ``q0`` tens of
        degrees off) loads it during the transient, and the tilt then
        settles with the 50 s time constant (an independent check: 0.70° off
        after 10 s, 0.09° after 110 s from a 20–35° start; 0.002° within
        10 s with ``ki_rad_s2=0``). The default start, levelled from the
        accelerometer, is not affected.
    amd_threshold_pct : float
        Thr of the AMD (percent of g, see module docstring). Paper: 0.3.
    amd_tau_s : float
        Smoothing time constant of the AMD statistic (s). Default 0.05 s
        (50 samples at 1 kHz) — chosen here.
    gravity_m_s2 : float
        Gravity magnitude g used by the AMD (m/s²).
    """

    kp_rad_s: float = 1.0
    ki_rad_s2: float = 0.02
    amd_threshold_pct: float = 0.3
    amd_tau_s: float = 0.05
    gravity_m_s2: float = STANDARD_GRAVITY_M_S2

    def __post_init__(self) -> None:
        positive_scalar(self.kp_rad_s, "kp_rad_s", allow_zero=True)
        positive_scalar(self.ki_rad_s2, "ki_rad_s2", allow_zero=True)
        positive_scalar(self.amd_threshold_pct, "amd_threshold_pct")
        positive_scalar(self.amd_tau_s, "amd_tau_s")
        positive_scalar(self.gravity_m_s2, "gravity_m_s2")


@dataclass(frozen=True)
class QncfResult:
    """Output of :func:`qncf`; arrays have a leading trial axis iff the input had one.

    Attributes
    ----------
    q_ws : ndarray (..., N, 4)
        Sensor attitude at each sample time t_k, i.e. before sample k's
        increment is applied (scalar-first; continuous in sign by
        construction, the update never flips it).
    euler_rad : ndarray (..., N, 3)
        Eq 8 yaw ψ, pitch θ, roll γ of ``q_ws`` (rad).
    amd_pct : ndarray (..., N)
        AMD statistic (percent of g).
    gate : ndarray (..., N) of bool
        True where the accelerometer correction was active (AMD < Thr).
    """

    q_ws: np.ndarray
    euler_rad: np.ndarray
    amd_pct: np.ndarray
    gate: np.ndarray


def amd_statistic(accel_m_s2, dt_s: float, params: QncfParams = QncfParams()) -> np.ndarray:
    """AMD statistic (percent of g) of an accelerometer record (..., N, 3), shape (..., N).

    Same recursion as inside the filter (module docstring, item 4); provided
    for plots and tests.
    """
    acc = as_float_array(accel_m_s2, "accel_m_s2", ndim=(2, 3), last_dim=3)
    dt = positive_scalar(dt_s, "dt_s")
    d = 100.0 * np.abs(np.linalg.norm(acc, axis=-1) / params.gravity_m_s2 - 1.0)
    alpha = min(dt / params.amd_tau_s, 1.0)
    out = np.empty_like(d)
    state = d[..., 0].copy()
    for k in range(d.shape[-1]):
        state += alpha * (d[..., k] - state)
        out[..., k] = state
    return out


def initial_attitude_from_accel(accel_m_s2, yaw_rad: float = 0.0) -> np.ndarray:
    """Levelling: Eq 9 quaternion with pitch/roll from a static specific force (:func:`mtcal.core.rotations.level_quat_zxy`).

    For the ZXY convention a static sensor reads ``f = g [−sinγ cosθ, sinθ,
    cosγ cosθ]``, so ``θ = asin(f_y/‖f‖)`` and ``γ = atan2(−f_x, f_z)``.

    Parameters
    ----------
    accel_m_s2 : array_like, shape (..., 3)
        Mean static specific force (m/s², any scale).
    yaw_rad : float
        Yaw to assign (rad), default 0 (gyro heading starts at zero).

    Returns
    -------
    ndarray, shape (..., 4)
    """
    return rotations.level_quat_zxy(accel_m_s2, yaw_rad)


#: Largest increment angle |Δθ| (rad per sample) for which the increment quaternion uses the
#: truncated Taylor series of degree 3 / degree 2 in |Δθ|² (see :meth:`QncfFilter._step`);
#: above the first, the cos/sin path is used.
TAYLOR_MAX_INCREMENT_RAD = 0.04
TAYLOR2_MAX_INCREMENT_RAD = 0.004
# cos(x/2) and sin(x/2)/x as polynomials in u = x²: coefficients of u⁰ … u³
_COS_HALF = (1.0, -1.0 / 8.0, 1.0 / 384.0, -1.0 / 46080.0)
_SINC_HALF = (0.5, -1.0 / 48.0, 1.0 / 3840.0, -1.0 / 645120.0)
#: Trial-samples per internal time block: keeps the block buffers (a few MB) cache-resident.
_CACHE_BLOCK = 65536


class QncfFilter:
    """Stateful QNCF, vectorised over trials; ``update`` = one sample, ``run`` = a chunk.

    Parameters
    ----------
    q0 : array_like, shape (4,) or (T, 4)
        Initial sensor attitude (scalar-first unit quaternion).
    dt_s : float
        Sample interval (s).
    params : QncfParams
        Gains and AMD settings.
    trials : int, optional
        Number of trials T (default: from ``q0``, 1 when ``q0`` is (4,)).
    engine : {"numba", "numpy"}
        Compiled kernels (default) or the numpy reference implementation.

    Notes
    -----
    State is stored component-major ((6, T) quaternion rows ``q0 q1 q2 q3 q1 q2``
    — the last two repeat the vector part so that a cross product is two
    contiguous row-block products — and (3, T) integral) so that every
    operation in the step acts on contiguous rows; the step allocates nothing.

    What depends on the accelerometer only (its norm, the AMD statistic, the
    gate and the gated unit vector ``gate · a/‖a‖``) is computed for a whole
    time chunk at once before the step loop; the AMD recursion itself stays
    sample by sample (same formula, same rounding as the per-step form).
    """

    def __init__(self, q0, dt_s: float, params: QncfParams = QncfParams(), trials: int | None = None,
                 *, engine: str = "numba"):
        self.engine = check_engine(engine)
        q = unit_quaternion(q0, "q0")
        if q.ndim not in (1, 2):
            raise ValueError(f"q0 must have shape (4,) or (T, 4), got {q.shape}")
        self._single = q.ndim == 1 and trials is None
        n = q.shape[0] if q.ndim == 2 else (1 if trials is None else int(trials))
        if q.ndim == 2 and trials is not None and trials != n:
            raise ValueError(f"trials={trials} does not match q0 with {n} rows")
        if not isinstance(params, QncfParams):
            raise TypeError(f"params must be a QncfParams, got {type(params).__name__}")
        self._start(q, positive_scalar(dt_s, "dt_s"), params, n)

    @classmethod
    def _trusted(cls, q0: np.ndarray, dt_s: float, params: QncfParams) -> QncfFilter:
        """A numba-engine filter from checked values (for :func:`qncf_trusted`): ``q0`` unit quaternions
        (4,) (one record) or (T, 4), ``dt_s`` > 0, ``params`` a :class:`QncfParams`; nothing re-checked."""
        filt = cls.__new__(cls)
        filt.engine = "numba"
        filt._single = q0.ndim == 1
        filt._start(q0, float(dt_s), params, 1 if q0.ndim == 1 else q0.shape[0])
        return filt

    def _start(self, q: np.ndarray, dt_s: float, params: QncfParams, n: int) -> None:
        """The state at the first sample: attitude ``q`` (4,) or (n, 4), zero integral, AMD not yet started."""
        self.params = params
        self.dt_s = dt_s
        self.trials = n
        self._qx = np.empty((6, n))                       # q0 q1 q2 q3 q1 q2
        self._qx[:4] = np.broadcast_to(q, (n, 4)).T
        self._qx[4:] = self._qx[1:3]
        self._q = self._qx[:4]
        self._integral = np.zeros((3, n))
        self._amd = np.full(n, np.nan)
        self._gate = np.ones(n, dtype=bool)
        self._alpha = min(self.dt_s / params.amd_tau_s, 1.0)
        if self.engine == "numpy":
            self._numpy_scratch(n)

    def _numpy_scratch(self, n: int) -> None:
        """Scratch buffers of the numpy engine (reused every step) and their row views, bound once."""
        self._v = np.empty((5, n))                        # v̂0 v̂1 v̂2 v̂0 v̂1
        self._pair = np.empty((2, n))
        self._sq = np.empty((4, n))
        self._e = np.empty((3, n))
        self._x = np.empty((3, n))
        self._w = np.empty((3, n))
        self._hv = np.empty((5, n))                       # sin(|Δθ|/2) Δθ/|Δθ|, extended like q
        self._qn = np.empty((4, n))
        self._r = np.empty((2, n))                        # |Δθ|² twice (rows for the series)
        self._cs = np.empty((2, n))                       # cos(|Δθ|/2), sin(|Δθ|/2)/|Δθ|
        self._nrm = np.empty(n)
        self._coef = tuple(np.array([[a] * n, [b] * n]) for a, b in zip(_COS_HALF, _SINC_HALF))
        qx, v, pr, sq, e, x, w, hv, qn, r, cs = (self._qx, self._v, self._pair, self._sq, self._e, self._x,
                                                 self._w, self._hv, self._qn, self._r, self._cs)
        self._views = (qx[0], qx[:4], qx[1:4], qx[2:0:-1], qx[1:3], qx[2:5], qx[3:6], qx[4:6], qx[3],
                       v, v[0:2], v[3:5], v[1:4], v[2:5], v[2], pr, pr[0], sq, sq[0], sq[1], sq[2], sq[3],
                       e, e[0], e[1], e[2], x, w, hv, hv[0:3], hv[3:5], hv[0:2], hv[1:4], hv[2:5],
                       qn, qn[0], qn[1:4], r, r[0], cs, cs[0], cs[1], self._nrm, self._integral)

    # ------------------------------------------------------------------ state
    @property
    def q_ws(self) -> np.ndarray:
        """Current attitude, shape (T, 4) (or (4,) for a single-trial filter)."""
        q = self._q.T.copy()
        return q[0] if self._single else q

    @property
    def gyro_bias_estimate_rad_s(self) -> np.ndarray:
        """Integral state I (rad/s), the negative of the estimated horizontal gyro bias."""
        out = self._integral.T.copy()
        return out[0] if self._single else out

    # ------------------------------------------------------------------ core
    def _step(self, w_in: np.ndarray, a_in: np.ndarray, order: int) -> None:
        """One sample: gyro ``w_in`` (3, T) rad/s and gated unit accel ``a_in`` (5, T), not modified.

        ``a_in`` holds ``gate · a/‖a‖`` extended like the state (rows x y z x y),
        see :meth:`_accel_chunk`. With ``order`` 3 or 2 the increment quaternion
        uses the alternating series in u = |Δθ|² up to u³ / u² (the caller,
        :meth:`_increment_order`, guarantees |Δθ| ≤ 0.04 / 0.004 rad)::

            cos(|Δθ|/2)      = 1 − u/8 + u²/384 − u³/46080 + R
            sin(|Δθ|/2)/|Δθ| = 1/2 − u/48 + u²/3840 − u³/645120 + R′

        with |R| ≤ (|Δθ|/2)⁸/8! ≤ 6.4e-19 and |R′| ≤ (|Δθ|/2)⁸/(2·9!) ≤ 3.6e-20
        for order 3, |R| ≤ (|Δθ|/2)⁶/6! ≤ 8.9e-20 and |R′| ≤ (|Δθ|/2)⁶/(2·7!)
        ≤ 6.4e-21 for order 2: exact to double precision (half an ulp of 1 is
        1.1e-16); only the rounding of the polynomial evaluation differs from
        cos/sin. ``order`` 0 uses cos/sin.
        """
        p = self.params
        mul, add, sub = np.multiply, np.add, np.subtract
        (q0, q4, qv, q21, q12, q234, q345, qext, q3, v, v01, vext, v123, v234, v2, pr, pr0, sq, s0, s1, s2,
         s3, e, e0, e1, e2, x, w, hv, hv3, hvext, hv01, hv123, hv234, qn, qn0, qnv, u2, u, cs, c, s, nrm,
         integral) = self._views
        # predicted up direction v̂ = C(q)ᵀ e_z = [2(q1q3 − q0q2), 2(q2q3 + q0q1), q0² − q1² − q2² + q3²]
        mul(q12, q3, v01)                  # q1q3, q2q3
        mul(q21, q0, pr)                   # q0q2, q0q1
        np.negative(pr0, pr0)
        add(v01, pr, v01)
        mul(v01, 2.0, v01)
        mul(q4, q4, sq)
        add(s0, s3, v2)
        sub(v2, s1, v2)
        sub(v2, s2, v2)
        v[3:5] = v01
        # error e = (gate a/|a|) × v̂ (rows i+1, i+2 of the extended arrays)
        mul(a_in[1:4], v234, e)
        mul(a_in[2:5], v123, x)
        sub(e, x, e)
        # PI: I += Ki e dt ; ω̃ = ω + Kp e + I ; Δθ = ω̃ dt
        if p.ki_rad_s2:
            mul(e, p.ki_rad_s2 * self.dt_s, w)
            add(integral, w, integral)
        mul(e, p.kp_rad_s, w)
        add(w, w_in, w)
        add(w, integral, w)
        mul(w, self.dt_s, w)
        # Eq 7: q(h) = [cos(|Δθ|/2), Δθ sin(|Δθ|/2)/|Δθ|]
        mul(w, w, e)
        add(e0, e1, u2)                    # u = |Δθ|² in both rows of u2
        add(u2, e2, u2)
        if order:                          # Horner on both series at once: rows cos, sinc
            k0, k1, k2, k3 = self._coef
            if order == 3:
                mul(u2, k3, cs)
                add(cs, k2, cs)
                mul(cs, u2, cs)
            else:
                mul(u2, k2, cs)
            add(cs, k1, cs)
            mul(cs, u2, cs)
            add(cs, k0, cs)
        else:
            self._trig_increment(u, c, s)
        mul(w, s, hv3)
        hvext[...] = hv01
        # Eq 6: q ← q ⊗ q(h) = [q0 c − qv·hv, q0 hv + c qv + qv × hv], renormalised
        mul(qv, hv3, e)
        add(e0, e1, qn0)
        add(qn0, e2, qn0)
        mul(q0, c, nrm)
        sub(nrm, qn0, qn0)
        mul(hv3, q0, qnv)
        mul(qv, c, e)
        add(qnv, e, qnv)
        mul(q234, hv234, e)
        mul(q345, hv123, x)
        sub(e, x, e)
        add(qnv, e, qnv)
        mul(qn, qn, sq)
        add(s0, s1, nrm)
        add(nrm, s2, nrm)
        add(nrm, s3, nrm)
        np.sqrt(nrm, nrm)
        np.divide(qn, nrm, q4)
        qext[...] = q12

    @staticmethod
    def _trig_increment(u: np.ndarray, c: np.ndarray, s: np.ndarray) -> None:
        """cos(|Δθ|/2) into ``c`` and sin(|Δθ|/2)/|Δθ| into ``s`` from u = |Δθ|² (any angle)."""
        ang = np.sqrt(u)
        half = 0.5 * ang
        np.cos(half, out=c)
        small = ang < 1e-8
        np.divide(np.sin(half), np.where(small, 1.0, ang), out=s)
        if small.any():
            s[small] = 0.5 - ang[small] ** 2 / 48.0

    def _accel_chunk(self, at: np.ndarray, amd_out: np.ndarray, gate_out: np.ndarray,
                     a_out: np.ndarray, sq: np.ndarray, norm: np.ndarray, d: np.ndarray) -> None:
        """AMD statistic, gate and gated unit accel for a chunk of accel samples ``at`` (C, 3, T).

        Fills ``amd_out`` (C, T), ``gate_out`` (C, T) and ``a_out`` (C, 5, T) =
        ``gate · a/max(‖a‖, 1e-12)`` with rows x y z x y; carries the AMD state.
        ``sq`` (C, 3, T), ``norm`` and ``d`` (C, T) are scratch.
        """
        p = self.params
        np.multiply(at, at, out=sq)
        np.add(sq[:, 0], sq[:, 1], out=norm)
        norm += sq[:, 2]
        np.sqrt(norm, out=norm)
        np.divide(norm, p.gravity_m_s2, out=d)
        d -= 1.0
        np.abs(d, out=d)
        d *= 100.0
        amd = self._amd
        first = np.isnan(amd)
        if first.any():
            amd[first] = d[0, first]
        alpha, sub, mul, add = self._alpha, np.subtract, np.multiply, np.add
        prev = amd
        for dk, out in zip(d, amd_out):   # AMD_k = AMD_{k−1} + α (d_k − AMD_{k−1})
            sub(dk, prev, dk)
            mul(dk, alpha, dk)
            add(prev, dk, out)
            prev = out
        amd[:] = prev
        np.less(amd_out, p.amd_threshold_pct, out=gate_out)
        self._gate[:] = gate_out[-1]
        np.maximum(norm, 1e-12, out=norm)
        np.divide(gate_out, norm, out=norm)
        fac = norm[:, None]
        np.multiply(at, fac, out=a_out[:, :3])
        np.multiply(at[:, :2], fac, out=a_out[:, 3:])   # not a copy within a_out: numpy would buffer it

    def _increment_order(self, wt: np.ndarray) -> int:
        """Series order usable for every sample of the chunk ``wt`` (C, 3, T): 3, 2 or 0 (cos/sin).

        From a bound on the increment: |Δθ| ≤ Δt (|ω| + K_p|e| + |I_0| + K_i Δt C |e|)
        with |e| ≤ 1 (cross product of the gated unit accel and the unit v̂) and
        |ω| ≤ √3 max|ω_i|; order 2 if the bound is ≤ TAYLOR2_MAX_INCREMENT_RAD,
        3 if ≤ TAYLOR_MAX_INCREMENT_RAD.
        """
        p, dt = self.params, self.dt_s
        w_max = max(float(wt.max()), -float(wt.min())) * np.sqrt(3.0)
        i_max = float(np.sqrt(np.max(np.einsum("it,it->t", self._integral, self._integral))))
        bound = dt * (w_max + (p.kp_rad_s + p.ki_rad_s2 * dt * wt.shape[0]) * (1.0 + 1e-9) + i_max)
        return 2 if bound <= TAYLOR2_MAX_INCREMENT_RAD else (3 if bound <= TAYLOR_MAX_INCREMENT_RAD else 0)

    def _prepare(self, x, name: str, ndim_single: int, kind: str | None = None) -> np.ndarray:
        # numba engine: record() checks type and shape only; the kernel scans the values (finite,
        # units) while it filters and raises with the numpy path's messages before keeping anything
        arr = record(x, name, (1, 2, 3), kind, scan=False) if self.engine == "numba" else _as_input(x, name)
        if self._single and arr.ndim == ndim_single:
            arr = arr[None]
        if arr.ndim != ndim_single + 1 or arr.shape[0] != self.trials:
            raise ValueError(f"{name} must have a leading trial axis of length {self.trials}, "
                             f"got shape {arr.shape}")
        return arr

    def update(self, gyro_rad_s, accel_m_s2) -> np.ndarray:
        """Process one sample: gyro (rad/s) and accel (m/s²), shape (T, 3) or (3,).

        The accel sample is taken at ``t_k`` (it corrects the current state),
        the gyro sample is the mean rate over ``[t_k, t_{k+1}]``. Returns the
        attitude at ``t_{k+1}``, shape (T, 4) or (4,).
        """
        w = self._prepare(gyro_rad_s, "gyro_rad_s", 1, "gyro")
        a = self._prepare(accel_m_s2, "accel_m_s2", 1)
        if self._single:
            w, a = w[0], a[0]
        self.run(w[..., None, :], a[..., None, :], return_euler=False)
        return self.q_ws

    def run(self, gyro_rad_s, accel_m_s2, *, return_euler: bool = True,
            chunk: int = 2048) -> QncfResult:
        """Process a record (T, M, 3) (or (M, 3) for a single-trial filter), continuing the state.

        numpy engine: inputs are read in time chunks of at most ``chunk``
        samples (transposed to a component-major scratch copy; with many
        trials the chunk is shortened to ~65 000 trial-samples so that it
        stays in cache), so the working set stays small. numba engine: one
        kernel call over the whole call's samples (``chunk`` is ignored; the
        result does not depend on it). The caller's arrays are never modified.
        ``q_ws[k]`` is the attitude at ``t_k`` (before sample k's increment).
        """
        fast = self.engine == "numba"
        w = self._prepare(gyro_rad_s, "gyro_rad_s", 2, "gyro")
        a = self._prepare(accel_m_s2, "accel_m_s2", 2, "accel")
        if w.shape != a.shape:
            raise ValueError(f"gyro_rad_s and accel_m_s2 must have the same shape, got {w.shape} and {a.shape}")
        if fast:  # values (finite, units) are checked by the kernel's scan
            return self._run_numba(w, a, return_euler)
        check_gyro_units(w)
        if w.shape[1] > 1:  # one sample may legitimately be small (free fall, vibration): judge records only
            check_accel_units(a)
        m, n = w.shape[1], self.trials
        q_out = np.empty((n, m, 4))
        amd_out = np.empty((n, m))
        gate_out = np.empty((n, m), dtype=bool)
        size = max(1, min(int(chunk), m, max(_CACHE_BLOCK // n, 16)))
        q_buf = np.empty((size, 4, n))
        amd_buf = np.empty((size, n))
        gate_buf = np.empty((size, n), dtype=bool)
        a_buf = np.empty((size, 5, n))
        w_buf, w_buf2, sq_buf = np.empty((size, 3, n)), np.empty((size, 3, n)), np.empty((size, 3, n))
        norm_buf, d_buf = np.empty((size, n)), np.empty((size, n))
        q, step = self._q, self._step
        for c0 in range(0, m, size):
            c1 = min(c0 + size, m)
            nk = c1 - c0
            wt = component_major(w[:, c0:c1], w_buf[:nk])        # (chunk, 3, T)
            at = a_buf[:nk]
            self._accel_chunk(component_major(a[:, c0:c1], w_buf2[:nk]), amd_buf[:nk], gate_buf[:nk], at,
                              sq_buf[:nk], norm_buf[:nk], d_buf[:nk])
            order = self._increment_order(wt)
            for k in range(nk):  # recursive filter: loop over time only
                q_buf[k] = q             # attitude at t_k (before sample k's increment)
                step(wt[k], at[k], order)
            q_out[:, c0:c1] = q_buf[:nk].transpose(2, 0, 1)
            amd_out[:, c0:c1] = amd_buf[:nk].T
            gate_out[:, c0:c1] = gate_buf[:nk].T
        euler = rotations.euler_zxy_from_quat(q_out) if return_euler else np.empty((n, m, 0))
        if self._single:
            return QncfResult(q_out[0], euler[0], amd_out[0], gate_out[0])
        return QncfResult(q_out, euler, amd_out, gate_out)

    def run_error_stats(self, gyro_rad_s, accel_m_s2, truth_euler_rad, errors) -> None:
        """Advance the filter over a chunk and fold its Eq 8 errors into ``errors``, keeping no history.

        For streaming Monte Carlo runs that only need metrics: equivalent to
        ``errors.add_euler_zxy_errors(self.run(gyro, accel, return_euler=False).q_ws, truth_euler_rad)``
        (the wrapped yaw/pitch/roll errors of the attitude at each t_k, bit for bit),
        computed inside the compiled kernel without materialising the (T, M, 4)
        quaternions (numba engine only). Each error agrees with
        ``metrics.angle_difference(rotations.euler_zxy_from_quat(q), truth)`` within
        :data:`mtcal.core.montecarlo.ERROR_BOUND_RAD` away from gimbal lock (the small
        errors of a converged filter by an odd series instead of 2 atan2 + 1 asin, see
        :func:`mtcal.core.montecarlo.euler_errors_cs`).

        Parameters
        ----------
        gyro_rad_s, accel_m_s2 : array_like, shape (T, M, 3)
            As for :meth:`run`.
        truth_euler_rad : array_like, shape (M, 3) or (T, M, 3)
            True Eq 8 yaw ψ, pitch θ, roll γ at t_k (rad).
        errors : mtcal.core.montecarlo.ErrorAccumulator
            Accumulator of shape (T, 3).
        """
        from mtcal.core.montecarlo import ErrorAccumulator, truth_table

        if self.engine != "numba":
            raise ValueError("run_error_stats needs engine='numba' (use run() with the numpy engine)")
        if not isinstance(errors, ErrorAccumulator) or errors.shape != (self.trials, 3):
            raise TypeError(f"errors must be an ErrorAccumulator of shape ({self.trials}, 3)")
        w = self._prepare(gyro_rad_s, "gyro_rad_s", 2, "gyro")
        a = self._prepare(accel_m_s2, "accel_m_s2", 2, "accel")
        if w.shape != a.shape:
            raise ValueError(f"gyro_rad_s and accel_m_s2 must have the same shape, got {w.shape} and {a.shape}")
        tr = as_float_array(truth_euler_rad, "truth_euler_rad", ndim=(2, 3), last_dim=3, copy=False)
        tr = np.ascontiguousarray(tr if tr.ndim == 3 else tr[None])
        if tr.shape[1] != w.shape[1] or tr.shape[0] not in (1, self.trials):
            raise ValueError(f"truth_euler_rad of shape {tr.shape} does not match the records {w.shape}")
        stats = errors._stats_block()
        self._launch(w, a, None, truth_table(tr), stats)
        errors._stats_block_done(stats, w.shape[1])

    def _launch(self, w, a, outputs, truth, stats) -> None:
        """Run the kernel over validated (T, M, 3) records and write the state back."""
        from mtcal.filters import _kernels_qncf

        p, n, m = self.params, self.trials, w.shape[1]
        q = np.ascontiguousarray(self._q.T)              # copies: the state is written back only
        integ = np.ascontiguousarray(self._integral.T)   # once the input scan has passed
        amd = self._amd.copy()
        chk = np.empty((n, 4))
        if outputs is None:
            q_out, amd_out, gate_out = np.empty((1, 1, 4)), np.empty((1, 1)), np.empty((1, 1), dtype=bool)
        else:
            q_out, amd_out, gate_out = outputs
        with_stats = stats is not None
        if not with_stats:
            truth, stats = np.empty((1, 1, 3)), np.empty((1, 9))
        fn = (_kernels_qncf.qncf_parallel if use_parallel(n, m)
              else _kernels_qncf.qncf_one if n == 1 else _kernels_qncf.qncf_serial)
        fn(np.ascontiguousarray(w), np.ascontiguousarray(a), q, integ, amd, q_out, amd_out, gate_out,
           float(p.kp_rad_s), float(p.ki_rad_s2 * self.dt_s), bool(p.ki_rad_s2), float(self.dt_s),
           float(self._alpha), float(p.gravity_m_s2), float(p.amd_threshold_pct), outputs is not None, truth,
           stats, with_stats, chk)
        if m:  # raise (state untouched) if the inputs were not finite or not in rad/s and m/s²
            check_kernel_scan(chk, w, a, accel_units=m > 1)
        self._amd[:] = amd
        self._qx[:4] = q.T
        self._qx[4:] = self._qx[1:3]
        self._integral[:] = integ.T
        if m:
            self._gate[:] = self._amd < p.amd_threshold_pct   # = gate of the last sample

    def _run_numba(self, w: np.ndarray, a: np.ndarray, return_euler: bool) -> QncfResult:
        """:meth:`run` with the compiled kernels on validated (T, M, 3) float64 arrays."""
        n, m = self.trials, w.shape[1]
        q_out = np.empty((n, m, 4))
        amd_out = np.empty((n, m))
        gate_out = np.empty((n, m), dtype=bool)
        self._launch(w, a, (q_out, amd_out, gate_out), None, None)
        euler = rotations.euler_zxy_from_quat(q_out) if return_euler else np.empty((n, m, 0))
        if self._single:
            return QncfResult(q_out[0], euler[0], amd_out[0], gate_out[0])
        return QncfResult(q_out, euler, amd_out, gate_out)


def _as_input(x, name: str) -> np.ndarray:
    """Float64 view (no copy when already float64) checked for shape (3,), (N, 3) or (T, N, 3)."""
    return as_float_array(x, name, ndim=(1, 2, 3), last_dim=3, copy=False)


def qncf(gyro_rad_s, accel_m_s2, dt_s: float, params: QncfParams = QncfParams(), *,
         q0=None, init_samples: int = 100, return_euler: bool = True, engine: str = "numba") -> QncfResult:
    """Run the QNCF over a whole record (wang2023cja Eq 5–8 + PI/AMD), vectorised over trials.

    Parameters
    ----------
    gyro_rad_s : array_like, shape (N, 3) or (T, N, 3)
        Sensor-frame angular rate (rad/s); sample k is the mean over
        ``[t_k, t_{k+1}]``, so ``Δθ_k = ω_k Δt`` (Eq 7). A single record is
        checked against the accelerometer's tilt rate
        (:func:`mtcal.methods.tilt_rate.check_tilt_rate_scale`): a scale off
        by more than 5× (deg/s passed as rad/s, a wrong ``dt_s``) raises
        ``ValueError``, a gyro tilt above 5× the accelerometer's warns.
    accel_m_s2 : array_like, same shape
        Sensor-frame specific force (m/s²).
    dt_s : float
        Sample interval (s).
    params : QncfParams
        Gains and AMD threshold.
    q0 : array_like, shape (4,) or (T, 4), optional
        Initial attitude; default: levelled from the mean of the first
        ``init_samples`` accelerometer samples with yaw 0
        (:func:`initial_attitude_from_accel`).
    init_samples : int
        Samples averaged for the default levelling.
    return_euler : bool
        Also compute Eq 8 Euler angles.
    engine : {"numba", "numpy"}
        Compiled kernels (default; trials in parallel over numba's threads) or
        the numpy reference implementation (agree to ~1e-15 rad).

    Returns
    -------
    QncfResult

    Examples
    --------
    >>> import numpy as np
    >>> acc = np.tile([0.0, 0.0, 9.80665], (100, 1))
    >>> res = qncf(np.zeros((100, 3)), acc, 1e-3)
    >>> res.q_ws[-1].round(12).tolist()
    [1.0, 0.0, 0.0, 0.0]
    """
    check_engine(engine)
    fast = engine == "numba"
    # numba engine: type and shape here, values scanned by the kernel (same messages)
    w = record(gyro_rad_s, "gyro_rad_s", (1, 2, 3), scan=False) if fast else _as_input(gyro_rad_s, "gyro_rad_s")
    a = record(accel_m_s2, "accel_m_s2", (1, 2, 3), scan=False) if fast else _as_input(accel_m_s2, "accel_m_s2")
    if w.ndim == 1:
        raise ValueError(f"gyro_rad_s must have shape (N, 3) or (T, N, 3), got {w.shape}")
    if w.shape != a.shape:
        raise ValueError(f"gyro_rad_s and accel_m_s2 must have the same shape, got {w.shape} and {a.shape}")
    dt_s = positive_scalar(dt_s, "dt_s")
    single = w.ndim == 2  # unit plausibility is checked once, in QncfFilter.run
    if single:  # a gyro the accelerometer's tilt rate shows off by > 5x (deg/s, time base) is refused
        check_tilt_rate_scale(w, a, dt_s, excess="warn")
    if q0 is not None:
        q0 = unit_quaternion(q0, "q0")
        if single and q0.shape != (4,):
            raise ValueError(f"q0 must have shape (4,) for a single-trial record, got {q0.shape}")
    if fast:  # checked: the trusted entry (the kernel checks finiteness and units before the results are kept)
        return qncf_trusted(w, a, dt_s, params, q0=q0, init_samples=init_samples, return_euler=return_euler)
    q0 = _start_attitude(a, q0, init_samples)
    filt = QncfFilter(q0 if single else np.broadcast_to(q0, (w.shape[0], 4)), dt_s, params, engine=engine)
    return filt.run(w, a, return_euler=return_euler)


def _start_attitude(accel: np.ndarray, q0, init_samples: int) -> np.ndarray:
    """``q0``, or the levelled attitude of the mean of the first ``init_samples`` samples of each record."""
    if q0 is not None:
        return q0
    n0 = max(1, min(int(init_samples), accel.shape[-2]))
    return initial_attitude_from_accel(np.mean(accel[..., :n0, :], axis=-2))


def qncf_trusted(gyro_rad_s, accel_m_s2, dt_s: float, params: QncfParams = QncfParams(), *,
                 q0=None, init_samples: int = 100, return_euler: bool = True) -> QncfResult:
    """Trusted entry: :func:`qncf` (numba engine) on one record or a stack of records its caller built or checked.

    For procedures below a public edge that already holds the checks (:func:`qncf` itself,
    :mod:`mtcal.systems` procedures after :func:`mtcal.systems.plausibility.check_units`, Monte
    Carlo runs on the records they simulated): the same filter, the same numbers as :func:`qncf`,
    without its edge checks (types and shapes, ``q0``, and for one record the tilt-rate scan
    :func:`mtcal.methods.tilt_rate.check_tilt_rate_scale`). Not part of the public API (not in
    ``__all__``); users call :func:`qncf`.

    Preconditions (not checked here)
    --------------------------------
    * ``gyro_rad_s`` and ``accel_m_s2`` are float arrays of one shape, (N, 3) (one record) or
      (T, N, 3) (T records of N samples each, filtered as independent trials), N ≥ 1;
      float64 C-contiguous arrays are used as they are (no copy), anything else is converted;
    * the gyro is in rad/s and its scale and time base agree with the accelerometer's tilt rate
      (for a log: :func:`mtcal.systems.plausibility.check_units` ran on it); ``dt_s`` > 0 is the
      records' sample interval (s);
    * ``q0`` is None (each record levelled from the mean of its first ``init_samples``
      accelerometer samples, yaw 0) or a unit quaternion (4,) — for a stack also (T, 4);
    * ``params`` is a :class:`QncfParams`.

    What stays checked costs no pass of its own: the compiled kernel scans the values while it
    filters (finite; gyro within ``MAX_GYRO_RAD_S``, accelerometer not in g:
    :mod:`mtcal.core.validate`) and raises, with :func:`qncf`'s
    messages, before anything is kept.

    Parameters
    ----------
    gyro_rad_s, accel_m_s2 : ndarray, shape (N, 3) or (T, N, 3)
        Sensor-frame rate (rad/s; sample k the mean over ``[t_k, t_{k+1}]``) and specific force (m/s²).
    dt_s : float
        Sample interval (s).
    params, q0, init_samples, return_euler
        As for :func:`qncf`.

    Returns
    -------
    QncfResult
        With a leading trial axis T iff the records had one (as :func:`qncf`).

    Examples
    --------
    >>> import numpy as np
    >>> acc = np.tile([0.0, 0.0, 9.80665], (2, 100, 1))
    >>> res = qncf_trusted(np.zeros((2, 100, 3)), acc, 1e-3, return_euler=False)
    >>> res.q_ws.shape, bool(np.array_equal(res.q_ws, qncf(np.zeros((2, 100, 3)), acc, 1e-3).q_ws))
    ((2, 100, 4), True)
    """
    w = np.ascontiguousarray(gyro_rad_s, dtype=np.float64)
    a = np.ascontiguousarray(accel_m_s2, dtype=np.float64)
    q0 = np.asarray(_start_attitude(a, q0, init_samples), dtype=np.float64)
    if w.ndim == 2:
        return QncfFilter._trusted(q0, dt_s, params)._run_numba(w[None], a[None], return_euler)
    return QncfFilter._trusted(np.broadcast_to(q0, (w.shape[0], 4)), dt_s, params)._run_numba(w, a, return_euler)
