"""RAMS rotation-angle EKF of seed 004 (Sec. 3.3, Eq 24–33), reference and fast versions.

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

Two implementations, equal to 1e-9 on the same data:

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
  Arrays are preallocated and updated in place.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mtcal._validate import as_float_array, positive_scalar

__all__ = ["RamsEkfParams", "RamsEkfReference", "RamsEkfResult", "run_rams_ekf",
           "measurement_model", "initial_state"]


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


def run_rams_ekf(gyro_rad_s, accel_m_s2, is_static, axis, accel0_m_s2, dt_s: float,
                 params: RamsEkfParams, *, theta0_rad=0.0, bias0_rad_s=0.0,
                 use_zvd: bool = True, keep_innovation: bool = True) -> RamsEkfResult:
    """Fast RAMS EKF vectorised over trials (closed-form 4-state algebra, in place).

    Parameters
    ----------
    gyro_rad_s, accel_m_s2 : array_like, shape (T, N, 3) or (N, 3)
        Gyro (rad/s; sample k acts over [t_k, t_{k+1}]) and accelerometer (m/s²).
    is_static : array_like of bool, shape (T, N) or (N,)
        ZVD flags (ignored when ``use_zvd`` is False).
    axis : array_like, shape (3,) or (T, 3)
        Unit rotation axis v per trial.
    accel0_m_s2 : array_like, shape (3,) or (T, 3)
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

    Returns
    -------
    RamsEkfResult
        With a leading trial axis (T = 1 for 2-D input).
    """
    g = as_float_array(gyro_rad_s, "gyro_rad_s", ndim=(2, 3), last_dim=3)
    a = as_float_array(accel_m_s2, "accel_m_s2", ndim=(2, 3), last_dim=3)
    if g.ndim == 2:
        g = g[None]
    if a.ndim == 2:
        a = a[None]
    if g.shape != a.shape:
        raise ValueError(f"gyro_rad_s and accel_m_s2 must have the same shape, got {g.shape} and {a.shape}")
    t_n, n = a.shape[0], a.shape[1]
    st = _static_flags(is_static, (t_n, n)) if use_zvd else np.ones((t_n, n), bool)
    v = np.broadcast_to(_check_axis(axis), (t_n, 3))
    a0 = np.broadcast_to(as_float_array(accel0_m_s2, "accel0_m_s2", last_dim=3), (t_n, 3))
    dt = positive_scalar(dt_s, "dt_s")
    if not isinstance(params, RamsEkfParams):
        raise TypeError(f"params must be a RamsEkfParams, got {type(params).__name__}")

    # constant per trial: pieces of h(θ) and the prediction row f = ∂θ⁻/∂x
    par = v * np.sum(v * a0, axis=1, keepdims=True)
    perp = a0 - par
    w = np.cross(v, a0)
    f = np.zeros((t_n, 4))
    f[:, 1:] = -v * dt
    q_theta = params.sigma_theta_rad_s**2 * dt * dt
    q_b = params.sigma_b_rad_s2**2 * dt * dt
    var_z = params.sigma_a_static_m_s2**2
    var_m = params.sigma_a_moving_m_s2**2
    var_k = np.where(st, var_z, var_m)                 # (T, N)
    omega_v = np.einsum("tnj,tj->tn", g, v) * dt       # vᵀω Δt, (T, N)

    theta = np.broadcast_to(as_float_array(theta0_rad, "theta0_rad"), (t_n,)).copy()
    bias = np.broadcast_to(as_float_array(bias0_rad_s, "bias0_rad_s"), (t_n, 3)).copy()
    P = np.broadcast_to(params.initial_covariance(), (t_n, 4, 4)).copy()
    out_theta = np.empty((t_n, n))
    out_bias = np.empty((t_n, n, 3))
    out_p = np.empty((t_n, n))
    out_y = np.empty((t_n, n, 3)) if keep_innovation else None
    u = np.empty((t_n, 4))
    c = np.empty((t_n, 4))
    hp = np.empty((t_n, 3))
    y = np.empty((t_n, 3))
    diag_b = (slice(None), [1, 2, 3], [1, 2, 3])
    for k in range(n):
        if k:  # --- prediction with gyro sample k−1 (Eq 24–25)
            theta += omega_v[:, k - 1] - dt * np.einsum("tj,tj->t", v, bias)
            np.einsum("tij,tj->ti", P, f, out=u)       # u = P f
            fu = np.einsum("ti,ti->t", f, u)
            P[:, 0, :] += u                             # F P Fᵀ = P + e0uᵀ + ue0ᵀ + (fᵀPf) e0e0ᵀ
            P[:, :, 0] += u
            P[:, 0, 0] += fu + q_theta
            P[diag_b] += q_b
        # --- correction (Eq 28–32), scalar-information form
        cs, sn = np.cos(theta)[:, None], np.sin(theta)[:, None]
        np.subtract(a[:, k], par + cs * perp - sn * w, out=y)
        np.multiply(-sn, perp, out=hp)
        hp -= cs * w
        hh = np.einsum("ti,ti->t", hp, hp)
        c[:] = P[:, :, 0]
        s = var_k[:, k] + c[:, 0] * hh
        gain = np.einsum("ti,ti->t", hp, y) / s
        theta += c[:, 0] * gain
        bias += c[:, 1:] * gain[:, None]
        P -= (hh / s)[:, None, None] * (c[:, :, None] * c[:, None, :])
        out_theta[:, k] = theta
        out_bias[:, k] = bias
        out_p[:, k] = P[:, 0, 0]
        if keep_innovation:
            out_y[:, k] = y
    S = c[:, 0, None, None] * (hp[:, :, None] * hp[:, None, :]) + var_k[:, -1, None, None] * np.eye(3)
    K = c[:, :, None] * hp[:, None, :] / s[:, None, None]
    return RamsEkfResult(out_theta, out_bias, out_p, out_y, P, S, K)
