"""RAMS rotation-angle EKF of wang2022sensors (Sec. 3.3, Eq 24–33), reference and fast versions.

State ``x = [θ, b_x, b_y, b_z]`` (rotation angle about the known axis v in rad,
gyro bias in rad/s).

Prediction (Eq 24–27), gyro sample ω (rad/s) acting over Δt::

    θ⁻ = θ + vᵀ(ω − b) Δt,   b⁻ = b,
    F = [[1, −vᵀΔt], [0, I]],
    Q = B diag(σθ² I, σb² I) Bᵀ,  B = [[vᵀΔt, 0], [0, Δt I]]
      = diag(σθ² Δt², σb² Δt² I)          (since vᵀv = 1).

Correction (Eq 28–32), accelerometer sample a (m/s²)::

    h(θ) = R(θ, v)ᵀ ā0 = (v vᵀ) ā0 + cosθ ā0⊥ − sinθ (v × ā0),
    H = [h′(θ), 0, 0, 0],  h′ = −sinθ ā0⊥ − cosθ (v × ā0),
    S = H P Hᵀ + V,  K = P Hᵀ S⁻¹,  x ← x + K (a − h),
    P ← (I − KH) P (I − KH)ᵀ + K V Kᵀ   (Joseph form).

Covariance switching (Sec. 3.3.3): the ZVD flag selects ``V_z = σ_az² I``
(static) or ``V = σ_am² I`` (moving; large, because lever-arm tangential and
centripetal accelerations violate the gravity-only model). mtcal's
interpretation of the paper's "two state covariances P and P_z": with one state
vector the covariance must describe that state's error, so a single P is
carried through mode changes while V switches; with ``use_zvd=False`` the
filter always uses V_z (the "standard EKF" of Fig. 9).

Implementations, equal to 1e-9 on the same data:

* :class:`RamsEkfReference` — readable, one trial, built on
  ``filterpy.kalman.ExtendedKalmanFilter`` (``predict(u=ω)`` with F, B=control
  matrix; ``update(z, HJacobian, Hx, R=V)``, which uses the Joseph form);
  exposes ``y`` (innovation), ``S``, ``K``, ``P`` like filterpy.
* :func:`run_rams_ekf` — vectorised over a leading trial axis (loop over time
  only). H has one non-zero column, so with V = σ²I:
  ``S⁻¹ = (I − p₀₀ h′h′ᵀ / s)/σ²`` with ``s = σ² + p₀₀‖h′‖²`` (Sherman–Morrison),
  ``K = c h′ᵀ / s`` with ``c = P[:, 0]``, the state update is the scalar
  ``x += c (h′ᵀ y)/s``, and the Joseph form collapses exactly to the rank-1
  downdate ``P ← P − (‖h′‖²/s) c cᵀ``. The downdate is symmetric by
  construction and keeps ``p₀₀ ← p₀₀ σ²/s > 0``, so it has the Joseph form's
  numerical safety for this model (no cancellation of large terms: ‖h′‖²p₀₀/s < 1).
  Arrays are preallocated and updated in place. Two engines (``engine=``):
  ``"numba"`` (default) — compiled float64 kernels
  (:mod:`mtcal.filters._kernels_ekf`, one trial serially or trials in
  parallel with ``prange``; bit-identical for any thread count and chunking) —
  and ``"numpy"``, the readable vectorised reference; they agree to rounding
  (≤ 1e-12 rad; tested).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from mtcal.core.compiled import component_major
from mtcal.core.validate import as_float_array, check_accel_units, check_gyro_units, positive_scalar
from mtcal.filters._kernels_common import OutputPool, check_engine, check_kernel_scan, record, use_parallel

__all__ = ["RamsEkfParams", "RamsEkfReference", "RamsEkfResult", "RamsEkfFilter", "run_rams_ekf",
           "run_rams_ekf_restarts", "run_rams_ekf_batch_restarts", "measurement_model", "initial_state"]


@dataclass(frozen=True)
class RamsEkfParams:
    """Noise parameters of the RAMS EKF (all SI).

    Parameters
    ----------
    sigma_theta_rad_s : float
        σθ, gyro white-noise std per sample (rad/s) in Q (Eq 26).
    sigma_b_rad_s2 : float
        σb, bias-walk std in Q (rad/s²): bias variance grows by σb² Δt² per step.
    sigma_a_static_m_s2 : float
        √ of V_z diagonal (static), accelerometer noise per sample (m/s²).
    sigma_a_moving_m_s2 : float
        √ of V diagonal (moving) (m/s²).
    p0_theta_rad2 : float
        Initial θ variance (rad²).
    p0_bias_rad2_s2 : float
        Initial bias variance per axis ((rad/s)²).
    """

    sigma_theta_rad_s: float = 1e-2
    sigma_b_rad_s2: float = 1e-4
    sigma_a_static_m_s2: float = 0.02
    sigma_a_moving_m_s2: float = 2.0
    p0_theta_rad2: float = 1e-6
    p0_bias_rad2_s2: float = 1e-6

    def __post_init__(self) -> None:
        for name in ("sigma_theta_rad_s", "sigma_b_rad_s2", "sigma_a_static_m_s2",
                     "sigma_a_moving_m_s2", "p0_theta_rad2", "p0_bias_rad2_s2"):
            positive_scalar(getattr(self, name), name)

    def process_noise(self, axis, dt_s: float) -> np.ndarray:
        """Q = B diag(σθ² I, σb² I) Bᵀ (Eq 26–27), 4×4."""
        v = np.asarray(axis, float)
        b = np.zeros((4, 6))
        b[0, :3] = v * dt_s
        b[1:, 3:] = dt_s * np.eye(3)
        d = np.diag([self.sigma_theta_rad_s**2] * 3 + [self.sigma_b_rad_s2**2] * 3)
        return b @ d @ b.T

    def initial_covariance(self) -> np.ndarray:
        """P0 = diag(p0_θ, p0_b, p0_b, p0_b)."""
        return np.diag([self.p0_theta_rad2] + [self.p0_bias_rad2_s2] * 3)


def _check_axis(axis, name: str = "axis") -> np.ndarray:
    v = as_float_array(axis, name, last_dim=3)
    norm = np.linalg.norm(v, axis=-1)
    if np.any(np.abs(norm - 1.0) > 1e-6):
        raise ValueError(f"{name} must be a unit vector, got |{name}| = {np.atleast_1d(norm)[0]:.6g}")
    return v


def measurement_model(theta_rad, axis, accel0_m_s2) -> tuple[np.ndarray, np.ndarray]:
    """``h(θ) = R(θ, v)ᵀ ā0`` (Eq 28 / Eq 16) and ``h′(θ) = ∂h/∂θ``, shape (..., 3) each."""
    th = np.asarray(theta_rad, float)[..., None]
    v = np.asarray(axis, float)
    a0 = np.asarray(accel0_m_s2, float)
    par = v * np.sum(v * a0, axis=-1, keepdims=True)
    perp = a0 - par
    w = np.cross(v, a0)
    c, s = np.cos(th), np.sin(th)
    return par + c * perp - s * w, -s * perp - c * w


def initial_state(gyro_rad_s, accel_m_s2, n_init: int) -> tuple[np.ndarray, np.ndarray]:
    """ā0 and the initial bias from the first ``n_init`` (static) samples (means), (..., 3) each.

    Sec. 2.2: ā0 is "the mean value of the acceleration measurements over an
    initialization period with no motion"; mtcal also starts the bias state at
    the mean gyro reading of that period (the paper does not say).
    """
    g = as_float_array(gyro_rad_s, "gyro_rad_s", last_dim=3)
    a = as_float_array(accel_m_s2, "accel_m_s2", last_dim=3)
    if not 1 <= n_init <= a.shape[-2]:
        raise ValueError(f"n_init must be in [1, {a.shape[-2]}], got {n_init}")
    return a[..., :n_init, :].mean(axis=-2), g[..., :n_init, :].mean(axis=-2)


class RamsEkfReference:
    """Readable single-trial RAMS EKF on ``filterpy.kalman.ExtendedKalmanFilter``.

    Parameters
    ----------
    axis : 3-vector
        Unit rotation axis v (sensor frame).
    accel0_m_s2 : 3-vector
        ā0, static accelerometer mean at θ = 0 (m/s²).
    dt_s : float
        Sample interval (s).
    params : RamsEkfParams
    theta0_rad : float
        Initial angle (rad).
    bias0_rad_s : 3-vector
        Initial bias estimate (rad/s).

    Attributes (filterpy style, after :meth:`step`)
    ------------------------------------------------
    x, P : state (4, 1) and covariance (4, 4)
    y, S, K : innovation (3, 1), its covariance (3, 3), gain (4, 3)
    """

    def __init__(self, axis, accel0_m_s2, dt_s: float, params: RamsEkfParams,
                 theta0_rad: float = 0.0, bias0_rad_s=(0.0, 0.0, 0.0)) -> None:
        from filterpy.kalman import ExtendedKalmanFilter

        self.v = _check_axis(axis)
        self.a0 = as_float_array(accel0_m_s2, "accel0_m_s2", ndim=1, last_dim=3)
        self.dt = positive_scalar(dt_s, "dt_s")
        self.params = params
        ekf = ExtendedKalmanFilter(dim_x=4, dim_z=3)
        ekf.x = np.array([[float(theta0_rad)], *[[float(b)] for b in bias0_rad_s]])
        ekf.P = params.initial_covariance()
        ekf.F = np.eye(4)
        ekf.F[0, 1:] = -self.v * self.dt          # ∂θ⁻/∂b
        ekf.B = np.zeros((4, 3))
        ekf.B[0, :] = self.v * self.dt            # control input u = ω
        ekf.Q = params.process_noise(self.v, self.dt)
        self.ekf = ekf
        self._started = False

    def _hx(self, x: np.ndarray) -> np.ndarray:
        return measurement_model(x[0, 0], self.v, self.a0)[0].reshape(3, 1)

    def _hjac(self, x: np.ndarray) -> np.ndarray:
        h = np.zeros((3, 4))
        h[:, 0] = measurement_model(x[0, 0], self.v, self.a0)[1]
        return h

    def step(self, gyro_prev_rad_s, accel_m_s2, is_static: bool) -> float:
        """Predict with the previous gyro sample (skipped at the first call), update with accel."""
        if self._started:
            self.ekf.predict(u=np.asarray(gyro_prev_rad_s, float).reshape(3, 1))
        self._started = True
        sig = self.params.sigma_a_static_m_s2 if is_static else self.params.sigma_a_moving_m_s2
        self.ekf.update(np.asarray(accel_m_s2, float).reshape(3, 1), self._hjac, self._hx,
                        R=sig**2 * np.eye(3))
        return float(self.ekf.x[0, 0])

    @property
    def x(self) -> np.ndarray:
        return self.ekf.x

    @property
    def P(self) -> np.ndarray:
        return self.ekf.P

    @property
    def y(self) -> np.ndarray:
        return self.ekf.y

    @property
    def S(self) -> np.ndarray:
        return self.ekf.S

    @property
    def K(self) -> np.ndarray:
        return self.ekf.K

    def run(self, gyro_rad_s, accel_m_s2, is_static) -> "RamsEkfResult":
        """Filter a whole record (N, 3); returns a :class:`RamsEkfResult` without trial axis."""
        g = as_float_array(gyro_rad_s, "gyro_rad_s", ndim=2, last_dim=3)
        a = as_float_array(accel_m_s2, "accel_m_s2", ndim=2, last_dim=3)
        st = _static_flags(is_static, a.shape[:1])
        n = a.shape[0]
        theta, bias, p_th, innov = np.empty(n), np.empty((n, 3)), np.empty(n), np.empty((n, 3))
        for k in range(n):
            self.step(g[k - 1] if k else None, a[k], bool(st[k]))
            theta[k] = self.ekf.x[0, 0]
            bias[k] = self.ekf.x[1:, 0]
            p_th[k] = self.ekf.P[0, 0]
            innov[k] = self.ekf.y[:, 0]
        return RamsEkfResult(theta, bias, p_th, innov, self.ekf.P.copy(), self.ekf.S.copy(),
                             self.ekf.K.copy())


@dataclass(frozen=True)
class RamsEkfResult:
    """Output of the RAMS EKF; arrays carry a leading trial axis T for :func:`run_rams_ekf`.

    Attributes
    ----------
    theta_rad : (T, N)
        Estimated angle (continuous, not wrapped).
    bias_rad_s : (T, N, 3)
        Estimated gyro bias.
    p_theta_rad2 : (T, N)
        Posterior θ variance.
    innovation_m_s2 : (T, N, 3)
        Innovation ``y = a − h(θ⁻)``.
    P, S, K : (T, 4, 4), (T, 3, 3), (T, 4, 3)
        Posterior covariance, innovation covariance and gain of the last step.
    """

    theta_rad: np.ndarray
    bias_rad_s: np.ndarray
    p_theta_rad2: np.ndarray
    innovation_m_s2: np.ndarray
    P: np.ndarray
    S: np.ndarray
    K: np.ndarray


def _static_flags(is_static, shape) -> np.ndarray:
    st = np.asarray(is_static)
    if st.dtype != bool:
        raise TypeError(f"is_static must be boolean, got dtype {st.dtype}")
    try:
        return np.broadcast_to(st, shape)
    except ValueError:
        raise ValueError(f"is_static of shape {st.shape} must broadcast to {shape}") from None


def _float_view(value, name: str) -> np.ndarray:
    """``value`` as float64 (T, N, 3) or (N, 3) without copying float64 input."""
    return as_float_array(value, name, ndim=(2, 3), last_dim=3, copy=False)


def _record(gyro_rad_s, accel_m_s2, fast: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Validated gyro and accel records as (T, N, 3) float64 arrays (views of float64 input).

    ``fast``: type and shape only; the numba kernel scans the values (finite, units) while it
    filters and the results are kept only if the scan passes (same messages).
    """
    if fast:
        g = record(gyro_rad_s, "gyro_rad_s", (2, 3), scan=False)
        a = record(accel_m_s2, "accel_m_s2", (2, 3), scan=False)
        g, a = (g[None] if g.ndim == 2 else g), (a[None] if a.ndim == 2 else a)
        if g.shape != a.shape:
            raise ValueError(f"gyro_rad_s and accel_m_s2 must have the same shape, got {g.shape} and {a.shape}")
        return g, a
    g = _float_view(gyro_rad_s, "gyro_rad_s")
    a = _float_view(accel_m_s2, "accel_m_s2")
    if g.ndim == 2:
        g = g[None]
    if a.ndim == 2:
        a = a[None]
    if g.shape != a.shape:
        raise ValueError(f"gyro_rad_s and accel_m_s2 must have the same shape, got {g.shape} and {a.shape}")
    check_gyro_units(g)
    if g.shape[1] > 1:  # a single sample may legitimately be small: judge records only
        check_accel_units(a)
    return g, a


#: Packed storage of the symmetric 4×4 covariance: row r of the (10, T) array holds P[i, j].
PACKED_INDEX = ((0, 0), (0, 1), (0, 2), (0, 3), (1, 1), (2, 2), (3, 3), (1, 2), (1, 3), (2, 3))
#: Trial-samples per internal time block (keeps the block buffers cache-resident).
_CACHE_BLOCK = 65536


class RamsEkfFilter:
    """Stateful fast RAMS EKF vectorised over trials; :meth:`run` processes a time chunk and continues.

    Same model and algebra as :func:`run_rams_ekf` (which is this class run once
    over a whole record); a long record can be filtered chunk by chunk in
    bounded memory, with results identical to one call on the whole record.

    Parameters
    ----------
    axis : array_like, shape (3,) or (T, 3)
        Unit rotation axis v per trial.
    accel0_m_s2 : array_like, shape (3,) or (T, 3)
        ā0 per trial (m/s²).
    dt_s : float
        Sample interval (s).
    params : RamsEkfParams
    trials : int
        Number of trials T.
    theta0_rad : float or (T,)
        Initial angle (rad).
    bias0_rad_s : float, (3,) or (T, 3)
        Initial bias estimate (rad/s).
    use_zvd : bool
        Switch V_z/V by the ZVD flag (Sec. 3.3.3); False = always V_z.
    engine : {"numba", "numpy"}
        Compiled kernels (default) or the numpy reference implementation.

    Notes
    -----
    Storage is component-major, like :class:`mtcal.filters.qncf.QncfFilter`:
    the state is θ (T,) and b (3, T), the symmetric covariance its 10 unique
    entries as (10, T) rows (order :data:`PACKED_INDEX`), so every operation of
    the step is a contiguous row (block) operation on preallocated buffers.
    The first sample of the first :meth:`run` is corrected without prediction;
    every later sample is predicted with the previous gyro sample (carried over
    chunk boundaries). Sums of three or four products are formed in the same
    order as the ``einsum`` calls of the earlier (T, 4, 4) implementation, so
    the outputs are bit-identical to it on x86-64.
    """

    def __init__(self, axis, accel0_m_s2, dt_s: float, params: "RamsEkfParams", *, trials: int,
                 theta0_rad=0.0, bias0_rad_s=0.0, use_zvd: bool = True, engine: str = "numba") -> None:
        engine = check_engine(engine)
        n = int(trials)
        if n < 1:
            raise ValueError(f"trials must be >= 1, got {trials}")
        v = _check_axis(axis)
        a0 = as_float_array(accel0_m_s2, "accel0_m_s2", last_dim=3)
        dt = positive_scalar(dt_s, "dt_s")
        if not isinstance(params, RamsEkfParams):
            raise TypeError(f"params must be a RamsEkfParams, got {type(params).__name__}")
        self._setup(v, a0, dt, params, n, as_float_array(theta0_rad, "theta0_rad"),
                    as_float_array(bias0_rad_s, "bias0_rad_s"), use_zvd, engine)

    @classmethod
    def trusted(cls, axis: np.ndarray, accel0_m_s2: np.ndarray, dt_s: float, params: "RamsEkfParams", *,
                trials: int, theta0_rad=0.0, bias0_rad_s=0.0, use_zvd: bool = True,
                engine: str = "numba") -> "RamsEkfFilter":
        """The filter built from inputs a caller validated at its own edge (same filter as the constructor).

        Preconditions (not checked again): ``axis`` finite float64 unit vector(s) (3,) or (T, 3);
        ``accel0_m_s2`` finite float64 (3,) or (T, 3) (m/s²); ``dt_s`` finite > 0 (s); ``params`` a
        :class:`RamsEkfParams`; ``trials`` ≥ 1; ``theta0_rad``, ``bias0_rad_s`` finite, broadcasting
        to (T,) and (T, 3); ``engine`` one of ``"numba"``, ``"numpy"``.
        """
        filt = cls.__new__(cls)
        filt._setup(axis, accel0_m_s2, float(dt_s), params, int(trials), np.asarray(theta0_rad, float),
                    np.asarray(bias0_rad_s, float), use_zvd, engine)
        return filt

    def _setup(self, v: np.ndarray, a0: np.ndarray, dt: float, params: "RamsEkfParams", n: int,
               theta0: np.ndarray, bias0: np.ndarray, use_zvd: bool, engine: str) -> None:
        """The state and constants from checked inputs (see :meth:`trusted`)."""
        self.engine = engine
        v = np.broadcast_to(v, (n, 3))
        a0 = np.broadcast_to(a0, (n, 3))
        self.dt_s = dt
        self.params, self.trials, self.use_zvd = params, n, bool(use_zvd)
        par = v * np.sum(v * a0, axis=1, keepdims=True)     # constant per trial, as in Eq 28
        self._par = np.array(par.T, order="C")
        self._perp = np.array((a0 - par).T, order="C")
        self._nperp = -self._perp                               # (−sinθ) perp = sinθ (−perp), exactly
        self._w = np.array(np.cross(v, a0).T, order="C")
        self._v = np.array(v.T, order="C")
        f = np.array((-v * dt).T, order="C")       # f = ∂θ⁻/∂b, rows f1 f2 f3
        self._f = f
        self._fa = np.array(f[[0, 0, 1]])         # f1 f1 f2 (pairs with p12 p13 p23)
        self._fb = np.array(f[[1, 2, 2]])         # f2 f3 f3
        self._q_theta = params.sigma_theta_rad_s**2 * dt * dt
        self._q_b = params.sigma_b_rad_s2**2 * dt * dt
        self._var = (params.sigma_a_static_m_s2**2, params.sigma_a_moving_m_s2**2)
        self._theta = np.broadcast_to(theta0, (n,)).copy()
        self._bias = np.array(np.broadcast_to(bias0, (n, 3)).T, order="C")
        p0 = params.initial_covariance()
        self._p = np.empty((10, n))
        for r, (i, j) in enumerate(PACKED_INDEX):
            self._p[r] = p0[i, j]
        self._omega_prev = None                                # vᵀω Δt of the last gyro sample seen
        self._kern = None                                      # trial-major constants of the numba engine
        # scratch rows
        self._c = np.empty((4, n))
        self._hp = np.empty((3, n))
        self._y = np.empty((3, n))
        self._s = np.empty(n)
        r = self._r = np.empty((5, n))
        cc = self._cc = np.empty((10, n))
        t = self._t = np.empty((3, n))
        x = self._x = np.empty((3, n))
        o1, o2 = self._o1, self._o2 = np.empty((3, n)), np.empty((3, n))
        self._u = np.empty((4, n))
        P, u, c, y, hp = self._p, self._u, self._c, self._y, self._hp
        self._views = (self._theta, self._bias, P, P[0], P[1:4], P[4:7], P[7:10], u, u[0], u[1], u[2], u[3],
                       u[1:4], c, c[0], c[1], c[2], c[3], c[0:4], c[1:4], c[2:4], y, hp, self._s,
                       t, t[0], t[1], t[2], x, o1, o2, r[0], r[1], r[2], r[3], r[4], cc, cc[0:4], cc[4:7],
                       cc[7:9], cc[9])

    # ------------------------------------------------------------------ state
    @property
    def theta_rad(self) -> np.ndarray:
        """Current angle estimate (T,) (rad)."""
        return self._theta.copy()

    @property
    def bias_rad_s(self) -> np.ndarray:
        """Current bias estimate (T, 3) (rad/s)."""
        return self._bias.T.copy()

    @property
    def P(self) -> np.ndarray:
        """Current covariance (T, 4, 4)."""
        return _unpack(self._p)

    # ------------------------------------------------------------------ core
    def _step(self, omega: np.ndarray | None, a_k: np.ndarray, var: np.ndarray) -> None:
        """Predict with ``omega`` = vᵀω Δt of the previous gyro sample (T,) unless None, then
        correct with accel ``a_k`` (3, T) and measurement variance ``var`` (T,)."""
        mul, add, sub = np.multiply, np.add, np.subtract
        (theta, bias, P, p00, p0b, pdiag, poff, u, u0, u1, u2, u3, ub, c, c0, c1, c2, c3, c03, c13, c23,
         y, hp, s, t, t0, t1, t2, x, o1, o2, r0, r1, r2, r3, r4, cc, cc0, cc1, cc2, cc3) = self._views
        if omega is not None:  # --- prediction with the previous gyro sample (Eq 24–27)
            f = self._f
            mul(self._v, bias, t)                      # θ += vᵀω Δt − Δt vᵀb
            add(t0, t2, r0)
            add(r0, t1, r0)
            mul(r0, self.dt_s, r0)
            sub(omega, r0, r0)
            add(theta, r0, theta)
            mul(p0b, f, t)                             # u = P f (f = [0, −vΔt])
            add(t0, t2, u0)
            add(u0, t1, u0)
            mul(pdiag, f, t)                           # p11 f1, p22 f2, p33 f3
            mul(poff, self._fa, o1)                    # p12 f1, p13 f1, p23 f2
            mul(poff, self._fb, o2)                    # p12 f2, p13 f3, p23 f3
            add(t0, o2[1], u1); add(u1, o2[0], u1)     # u1 = p12 f2 + (p11 f1 + p13 f3)
            add(o1[0], o2[2], u2); add(u2, t1, u2)     # u2 = p22 f2 + (p12 f1 + p23 f3)
            add(o1[1], t2, u3); add(u3, o1[2], u3)     # u3 = p23 f2 + (p13 f1 + p33 f3)
            mul(f, ub, t)                              # fᵀu
            add(t0, t2, r1)
            add(r1, t1, r1)
            # F P Fᵀ + Q = P + e0uᵀ + ue0ᵀ + (fᵀu + qθ) e0e0ᵀ + q_b diag(0, 1, 1, 1)
            add(p00, u0, p00)
            add(p00, u0, p00)
            add(r1, self._q_theta, r1)
            add(p00, r1, p00)
            add(p0b, ub, p0b)
            add(pdiag, self._q_b, pdiag)
        # --- correction (Eq 28–32), scalar-information form
        np.cos(theta, out=r2)
        np.sin(theta, out=r3)
        mul(self._perp, r2, t)                         # y = a − h(θ), h = par + cosθ perp − sinθ w
        add(self._par, t, t)
        mul(self._w, r3, x)
        sub(t, x, t)
        sub(a_k, t, y)
        mul(self._nperp, r3, hp)                       # h′ = −sinθ perp − cosθ w
        mul(self._w, r2, x)
        sub(hp, x, hp)
        mul(hp, hp, t)                                 # ‖h′‖²
        add(t0, t2, r4)
        add(r4, t1, r4)
        c[...] = P[0:4]                                # c = P e0
        mul(c0, r4, s)                                 # s = V + p00 ‖h′‖²
        add(var, s, s)
        mul(hp, y, t)                                  # gain = h′ᵀy / s
        add(t0, t2, r0)
        add(r0, t1, r0)
        np.divide(r0, s, r0)
        mul(c0, r0, r1)                                # x += c gain
        add(theta, r1, theta)
        mul(c13, r0, t)
        add(bias, t, bias)
        np.divide(r4, s, r4)                           # Joseph form = P − (‖h′‖²/s) c cᵀ
        mul(c03, c0, cc0)
        mul(c13, c13, cc1)
        mul(c23, c1, cc2)
        mul(c3, c2, cc3)
        mul(cc, r4, cc)
        sub(P, cc, P)

    def run(self, gyro_rad_s, accel_m_s2, is_static, *, keep_innovation: bool = True,
            chunk: int = 2048) -> RamsEkfResult:
        """Filter the next samples of every trial, continuing the state.

        Parameters
        ----------
        gyro_rad_s, accel_m_s2 : array_like, shape (T, M, 3) (or (M, 3) when T = 1)
            Gyro (rad/s; sample k acts over [t_k, t_{k+1}]) and accelerometer (m/s²).
        is_static : array_like of bool, shape (T, M) or (M,)
            ZVD flags (ignored when ``use_zvd`` is False).
        keep_innovation : bool
            Store the innovation history (T, M, 3).
        chunk : int
            Upper bound of the internal time block (samples); with many trials
            the block is shortened to ~65 000 trial-samples to stay in cache.

        Returns
        -------
        RamsEkfResult
            Histories of this call (leading trial axis) and P, S, K after its last sample.
        """
        g, a = _record(gyro_rad_s, accel_m_s2, fast=self.engine == "numba")
        if a.shape[0] != self.trials:
            raise ValueError(f"gyro_rad_s and accel_m_s2 must have {self.trials} trials, got shape {a.shape}")
        return self._run(g, a, is_static, keep_innovation, chunk)

    def _run(self, g: np.ndarray, a: np.ndarray, is_static, keep_innovation: bool, chunk: int) -> RamsEkfResult:
        """:meth:`run` on validated (T, M, 3) float64 arrays."""
        if self.engine == "numba":
            return self._run_numba(g, a, is_static, keep_innovation)

        n, m = self.trials, a.shape[1]
        st = _static_flags(is_static, (n, m)) if self.use_zvd else np.ones((1, m), bool)
        out_theta, out_bias, out_p = np.empty((n, m)), np.empty((n, m, 3)), np.empty((n, m))
        out_y = np.empty((n, m, 3)) if keep_innovation else None
        size = max(1, min(int(chunk), m, max(_CACHE_BLOCK // n, 16)))
        g_buf, a_buf = np.empty((size, 3, n)), np.empty((size, 3, n))
        om_buf = np.empty((size + 1, n))
        var_buf = np.empty((size, n))
        th_buf, b_buf, p_buf = np.empty((size, n)), np.empty((size, 3, n)), np.empty((size, n))
        y_buf = np.empty((size, 3, n)) if keep_innovation else None
        theta, bias, p00, y = self._theta, self._bias, self._p[0], self._y
        var_z, var_m = self._var
        step = self._step
        for c0 in range(0, m, size):
            c1 = min(c0 + size, m)
            nk = c1 - c0
            gt = component_major(g[:, c0:c1], g_buf[:nk])
            at = component_major(a[:, c0:c1], a_buf[:nk])
            np.multiply(gt, self._v, out=gt)            # vᵀω Δt, summed like einsum("tnj,tj->tn")
            om = om_buf[:nk + 1]
            if self._omega_prev is not None:
                om[0] = self._omega_prev
            np.add(gt[:, 0], gt[:, 2], out=om[1:])
            om[1:] += gt[:, 1]
            om[1:] *= self.dt_s
            var = var_buf[:nk]
            var[...] = var_m
            np.copyto(var, var_z, where=st[:, c0:c1].T)
            for k in range(nk):  # recursive filter: loop over time only
                step(om[k] if (k or self._omega_prev is not None) else None, at[k], var[k])
                th_buf[k] = theta
                b_buf[k] = bias
                p_buf[k] = p00
                if keep_innovation:
                    y_buf[k] = y
            self._omega_prev = om[nk].copy()
            out_theta[:, c0:c1] = th_buf[:nk].T
            out_bias[:, c0:c1] = b_buf[:nk].transpose(2, 0, 1)
            out_p[:, c0:c1] = p_buf[:nk].T
            if keep_innovation:
                out_y[:, c0:c1] = y_buf[:nk].transpose(2, 0, 1)
        c, hp, s = self._c.T, self._hp.T, self._s
        S = c[:, 0, None, None] * (hp[:, :, None] * hp[:, None, :]) + var[-1][:, None, None] * np.eye(3)
        K = c[:, :, None] * hp[:, None, :] / s[:, None, None]
        return RamsEkfResult(out_theta, out_bias, out_p, out_y, self.P, S, K)


    def _run_numba(self, g: np.ndarray, a: np.ndarray, is_static, keep_innovation: bool) -> RamsEkfResult:
        """:meth:`_run` with the compiled kernels (the whole call in one kernel launch)."""
        from mtcal.filters import _kernels_ekf

        n, m = self.trials, a.shape[1]
        if self.use_zvd:
            st = _static_flags(is_static, (n, m))      # checks dtype and shape
            raw = np.asarray(is_static)
            st = np.ascontiguousarray(raw.reshape(1, m) if raw.shape in ((m,), (1, m)) else st)
        else:
            st = np.ones((1, 1), bool)
        if self._kern is None:  # per-trial constants, trial-major
            self._kern = tuple(np.ascontiguousarray(x.T) for x in (self._v, self._par, self._perp, self._nperp,
                                                                  self._w, self._f))
        v, par, perp, nperp, wv, f = self._kern
        theta = self._theta.copy()                        # copies: the state is written back only
        bias = np.ascontiguousarray(self._bias.T)          # once the kernel's input scan has passed
        p = np.ascontiguousarray(self._p.T)
        chk = np.empty((n, 4))
        has_prev = self._omega_prev is not None
        om = np.array(self._omega_prev) if has_prev else np.zeros(n)
        # histories: every element is written by the kernel; large ones recycled from a dropped result
        out_theta, out_p = _POOL.take("theta", (n, m)), _POOL.take("p", (n, m))
        out_bias = _POOL.take("bias", (n, m, 3))
        out_y = _POOL.take("y", (n, m, 3)) if keep_innovation else np.empty((1, 1, 3))
        last_c, last_hp, last_s = self._c.T.copy(), self._hp.T.copy(), self._s.copy()
        var_z, var_m = self._var
        fn = (_kernels_ekf.ekf_parallel if use_parallel(n, m)
              else _kernels_ekf.ekf_one if n == 1 else _kernels_ekf.ekf_serial)
        fn(g, a, st, v, par, perp, nperp, wv, f, theta, bias, p, om, has_prev, self.use_zvd,
           float(var_z), float(var_m), float(self.dt_s), float(self._q_theta), float(self._q_b), out_theta,
           out_bias, out_p, out_y, bool(keep_innovation), last_c, last_hp, last_s, chk)
        if m:
            check_kernel_scan(chk, g, a, accel_units=m > 1)
        self._theta[:] = theta
        self._bias[:] = bias.T
        self._p[:] = p.T
        self._omega_prev = om
        self._c[:], self._hp[:], self._s[:] = last_c.T, last_hp.T, last_s
        var_last = np.where(st[:, -1], var_z, var_m) if self.use_zvd else np.full(n, var_z)
        var_last = np.broadcast_to(var_last, (n,))
        c, hp, s = last_c, last_hp, last_s
        S = c[:, 0, None, None] * (hp[:, :, None] * hp[:, None, :]) + var_last[:, None, None] * np.eye(3)
        K = c[:, :, None] * hp[:, None, :] / s[:, None, None]
        for role, arr in (("theta", out_theta), ("bias", out_bias), ("p", out_p), ("y", out_y)):
            if keep_innovation or role != "y":
                _POOL.keep(role, arr)
        return RamsEkfResult(out_theta, out_bias, out_p, out_y if keep_innovation else None, self.P, S, K)


#: Output histories of the compiled engine's last call, reused once the caller drops them (no page faults).
_POOL = OutputPool()


def _unpack(p: np.ndarray) -> np.ndarray:
    """(10, T) packed rows → (T, 4, 4) symmetric matrices."""
    out = np.empty((p.shape[1], 4, 4))
    for r, (i, j) in enumerate(PACKED_INDEX):
        out[:, i, j] = out[:, j, i] = p[r]
    return out


def run_rams_ekf(gyro_rad_s: np.ndarray, accel_m_s2: np.ndarray, is_static: np.ndarray, axis: np.ndarray,
                 accel0_m_s2: np.ndarray, dt_s: float, params: RamsEkfParams, *, theta0_rad=0.0, bias0_rad_s=0.0,
                 use_zvd: bool = True, keep_innovation: bool = True, engine: str = "numba") -> RamsEkfResult:
    """Fast RAMS EKF vectorised over trials (closed-form 4-state algebra, in place).

    Runs :class:`RamsEkfFilter` once over the whole record (wang2022sensors Eq 24–33).

    Parameters
    ----------
    gyro_rad_s, accel_m_s2 : ndarray, shape (T, N, 3) or (N, 3)
        Gyro (rad/s; sample k acts over [t_k, t_{k+1}]) and accelerometer (m/s²).
    is_static : ndarray of bool, shape (T, N) or (N,)
        ZVD flags (ignored when ``use_zvd`` is False).
    axis : ndarray, shape (3,) or (T, 3)
        Unit rotation axis v per trial.
    accel0_m_s2 : ndarray, shape (3,) or (T, 3)
        ā0 per trial (m/s²).
    dt_s : float
        Sample interval (s).
    params : RamsEkfParams
    theta0_rad : float or (T,)
    bias0_rad_s : float, (3,) or (T, 3)
    use_zvd : bool
        Switch V_z/V by the ZVD flag (Sec. 3.3.3); False = always V_z.
    keep_innovation : bool
        Store the innovation history (T, N, 3).
    engine : {"numba", "numpy"}
        Compiled kernels (default; trials in parallel over numba's threads) or
        the numpy reference (they agree to rounding, ≤ 1e-12 rad).

    Returns
    -------
    RamsEkfResult
        With a leading trial axis (T = 1 for 2-D input).

    Raises
    ------
    ValueError
        ``engine="numba"``: the kernel's scan of the values while it filters (a value not finite, a
        gyro not in rad/s, an accelerometer in g), with the messages of :class:`RamsEkfFilter`.
    TypeError
        ``is_static`` not boolean.

    Preconditions
    -------------
    The caller guarantees (not checked here, as :meth:`RamsEkfFilter.trusted`): ``gyro_rad_s``,
    ``accel_m_s2`` finite float64 ndarrays of one shape (T, N, 3) or (N, 3), the gyro in rad/s and
    plausible against the accelerometer's tilt rate (:func:`mtcal.methods.tilt_rate.check_tilt_rate_scale`),
    the accelerometer in m/s²; ``is_static`` bool broadcasting to (T, N); ``axis`` finite float64 unit
    vector(s) (3,) or (T, 3); ``accel0_m_s2`` finite float64 (3,) or (T, 3); ``dt_s`` finite > 0 (s);
    ``params`` a :class:`RamsEkfParams`; ``theta0_rad``, ``bias0_rad_s`` finite, broadcasting to (T,) and
    (T, 3). The surface-angle system checks a record once at its edge, tilt rate included
    (:func:`mtcal.systems.surface_angle.surface_angle`); :class:`RamsEkfFilter` checks its own inputs.

    Examples
    --------
    >>> import numpy as np
    >>> acc = np.tile([0.0, 0.0, 9.81], (100, 1))
    >>> res = run_rams_ekf(np.zeros((100, 3)), acc, np.ones(100, bool), np.array([1.0, 0.0, 0.0]), acc[0], 0.01,
    ...                    RamsEkfParams())
    >>> res.theta_rad.shape, float(np.abs(res.theta_rad).max())
    ((1, 100), 0.0)
    """
    check_engine(engine)
    g = np.ascontiguousarray(gyro_rad_s)
    a = np.ascontiguousarray(accel_m_s2)
    g, a = (g[None] if g.ndim == 2 else g), (a[None] if a.ndim == 2 else a)
    filt = RamsEkfFilter.trusted(axis, accel0_m_s2, dt_s, params, trials=a.shape[0], theta0_rad=theta0_rad,
                                 bias0_rad_s=bias0_rad_s, use_zvd=use_zvd, engine=engine)
    return filt._run(g, a, is_static, keep_innovation, 2048)


def run_rams_ekf_restarts(gyro_rad_s: np.ndarray, accel_m_s2: np.ndarray, is_static: np.ndarray, cuts,
                          axis: np.ndarray, accel0_m_s2: np.ndarray, bias0_rad_s: np.ndarray, dt_s: float,
                          params: RamsEkfParams, p0_theta_after_cut_rad2: float) -> np.ndarray:
    """One record's EKF over the segments ``cuts[k]:cuts[k+1]``: angle and bias carried over each cut, the
    angle prior widened to ``p0_theta_after_cut_rad2`` there (a restart; e.g. after clipped gyro samples).

    Returns the angle (N,) (rad).

    Preconditions
    -------------
    The caller guarantees (not checked here): those of :func:`run_rams_ekf` for one record (N, 3);
    ``cuts`` increasing sample indices from 0 to N; ``p0_theta_after_cut_rad2`` > 0 (rad²).
    :func:`mtcal.systems.surface_angle.surface_angle` checks a record once at its edge.

    Examples
    --------
    >>> import numpy as np
    >>> acc = np.tile([0.0, 0.0, 9.81], (100, 1))
    >>> theta = run_rams_ekf_restarts(np.zeros((100, 3)), acc, np.ones(100, bool), [0, 40, 100],
    ...                               np.array([1.0, 0.0, 0.0]), acc[0], np.zeros(3), 0.01, RamsEkfParams(), 0.1)
    >>> theta.shape, float(np.abs(theta).max())
    ((100,), 0.0)
    """
    theta = np.empty(accel_m_s2.shape[0])
    th0, bias0, p = 0.0, bias0_rad_s, params
    for lo, hi in zip(cuts[:-1], cuts[1:]):
        res = run_rams_ekf(gyro_rad_s[lo:hi], accel_m_s2[lo:hi], is_static[lo:hi], axis, accel0_m_s2, dt_s, p,
                           theta0_rad=th0, bias0_rad_s=bias0, keep_innovation=False)
        theta[lo:hi] = res.theta_rad[0]
        th0, bias0 = float(res.theta_rad[0, -1]), res.bias_rad_s[0, -1]
        p = replace(params, p0_theta_rad2=p0_theta_after_cut_rad2)
    return theta


def run_rams_ekf_batch_restarts(gyro_rad_s: np.ndarray, accel_m_s2: np.ndarray, is_static: np.ndarray, cuts,
                                axis: np.ndarray, accel0_m_s2: np.ndarray, bias0_rad_s: np.ndarray, dt_s: float,
                                params: RamsEkfParams, p0_theta_after_cut_rad2: float) -> np.ndarray:
    """T records' EKF in one run; a record with inner cuts (``len(cuts[t]) > 2``) runs again over its
    segments (:func:`run_rams_ekf_restarts`). Returns the angle (T, N) (rad).

    Preconditions
    -------------
    The caller guarantees (not checked here): those of :func:`run_rams_ekf` for a batch (T, N, 3) with
    ``is_static`` (T, N), ``axis`` (3,) or (T, 3), ``accel0_m_s2`` and ``bias0_rad_s`` (T, 3); ``cuts``
    one increasing index list from 0 to N per record; ``p0_theta_after_cut_rad2`` > 0 (rad²).
    :func:`mtcal.systems.surface_angle.surface_angle_batch` checks the records once at its edge.

    Examples
    --------
    >>> import numpy as np
    >>> acc = np.tile([0.0, 0.0, 9.81], (2, 100, 1))
    >>> theta = run_rams_ekf_batch_restarts(np.zeros((2, 100, 3)), acc, np.ones((2, 100), bool),
    ...                                     [[0, 100], [0, 40, 100]], np.array([1.0, 0.0, 0.0]), acc[:, 0],
    ...                                     np.zeros((2, 3)), 0.01, RamsEkfParams(), 0.1)
    >>> theta.shape, float(np.abs(theta).max())
    ((2, 100), 0.0)
    """
    theta = run_rams_ekf(gyro_rad_s, accel_m_s2, is_static, axis, accel0_m_s2, dt_s, params,
                         bias0_rad_s=bias0_rad_s, keep_innovation=False).theta_rad
    for t, c in enumerate(cuts):
        if len(c) > 2:
            vt = axis if axis.ndim == 1 else axis[t]
            theta[t] = run_rams_ekf_restarts(gyro_rad_s[t], accel_m_s2[t], is_static[t], c, vt, accel0_m_s2[t],
                                             bias0_rad_s[t], dt_s, params, p0_theta_after_cut_rad2)
    return theta
