"""IMU simulator: exact truth kinematics plus a MEMS sensor error model.

Hardware is replaced by simulation with known truth (docs/conventions.md). A
:class:`Trajectory` holds the body attitude history ``q_wb`` (scalar-first,
body → world) and the linear acceleration of the sensor point; a
:class:`ImuErrorModel` holds the sensor errors; :func:`simulate_imu` draws one
or many Monte Carlo trials from a seeded ``numpy.random.Generator``.

Truth kinematics
----------------
The world frame is z-up with gravity ``g_w = [0, 0, −9.80665] m/s²`` by
default, so a level accelerometer at rest reads ``[0, 0, +g]``.

* Gyro (body-frame rate, rad/s). Sample ``k`` is the *mean rate over the
  interval* ``[t_k, t_{k+1}]``: ``ω_k = rotvec(q_k⁻¹ ⊗ q_{k+1}) / Δt_k`` — what
  an integrating (angular-increment) gyro reports. Integrating it with wang2023cja
  Eq 6–7 (``q_{k+1} = q_k ⊗ q(ω_k Δt)``) reproduces the attitude to rounding
  error. The last sample repeats the last interval.
* Accelerometer (specific force, m/s²): ``f_b = C_wbᵀ (a_w − g_w)`` at each
  sample.

Sensor error model (per axis, per sensor; units of the sensor)
--------------------------------------------------------------
``y = (I + S + M) x_true + b_const + b_turn_on + b_warm-up(t) + b_RW(t)
+ b_GM(t) + n_white + vibration``, then quantised; with

* ``S`` diagonal scale-factor error, ``M`` misalignment (off-diagonal);
* ``b_turn_on ~ N(0, bias_sigma²)`` once per trial;
* ``b_warm-up(t) = warmup_bias · exp(−(t + t_on)/warmup_tau_s)`` (bias
  settling after power-on; ``t_on`` = time already powered, e.g. 300 s);
* ``b_RW``: random walk with density ``bias_random_walk`` (unit/s/√Hz, i.e.
  the rate random walk K of an Allan plot: σ_A(τ) = K √(τ/3));
* ``b_GM``: first-order Gauss–Markov bias instability, 1σ
  ``bias_instability`` and correlation time ``bias_instability_tau_s``;
* ``n_white``: density ``noise_density`` (unit/√Hz): per-sample standard
  deviation ``noise_density · √fs`` (Allan σ_A(τ) = N/√τ);
* vibration: sinusoid ``amplitude · sin(2π f t + φ)``, φ uniform per trial
  and axis.

Each error source draws from its own generators (keyed by sensor, source
and a fixed block of samples, derived from ``rng``), so switching one source
on or off leaves the others' draws unchanged (common random numbers for
error-budget tables), and :class:`ImuStream` delivers the same numbers in
chunks of any size (bounded-memory Monte Carlo).

Two engines produce bit-identical output (tested): ``"numba"`` (default) draws
each block's normals with numba's port of numpy's PCG64 + ziggurat sampler
(same stream, ~3× faster than ``Generator.standard_normal``) and applies every
error term, the bias random walk and the Gauss–Markov recursion in one
compiled pass per block segment, in the reference's operation order;
``"numpy"`` is the readable reference (array operations, ``np.cumsum``,
``scipy.signal.lfilter``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


from mtcal.core import rotations
from mtcal.core.compiled import jit
from mtcal.core.validate import (STANDARD_GRAVITY_M_S2, as_float_array, positive_int,
                             positive_scalar, time_vector, unit_quaternion)

__all__ = ["Trajectory", "SensorErrors", "ImuErrorModel", "ImuRecord", "ImuStream", "body_rates",
           "specific_force", "simulate_imu", "apply_sensor_errors", "integrate_gyro", "GRAVITY_W_M_S2"]

#: Default world gravity vector, z-up frame (m/s²).
GRAVITY_W_M_S2 = (0.0, 0.0, -STANDARD_GRAVITY_M_S2)

_SOURCES = ("turn_on", "white", "random_walk", "instability", "vibration")


def _frozen(arr: np.ndarray) -> np.ndarray:
    arr.setflags(write=False)
    return arr


def uniform_dt(time_s: np.ndarray, name: str = "time_s") -> float:
    """Sample interval of a uniformly sampled time vector (relative jitter < 1e-6)."""
    dt = np.diff(time_s)
    mean_dt = float(np.mean(dt))
    if np.max(np.abs(dt - mean_dt)) > 1e-6 * mean_dt:
        raise ValueError(f"{name} must be uniformly sampled (noise density is scaled by "
                         f"the sample rate); got dt in [{dt.min():.6g}, {dt.max():.6g}] s")
    return mean_dt


@dataclass(frozen=True)
class Trajectory:
    """Truth motion of the body carrying the IMU.

    Parameters
    ----------
    time_s : array_like, shape (N,)
        Strictly increasing, uniformly sampled time in s.
    q_wb : array_like, shape (N, 4)
        Scalar-first unit quaternion of the body attitude (body → world).
    accel_w_m_s2 : array_like, shape (N, 3), optional
        Linear acceleration of the sensor point in the world frame (m/s²);
        zero (no translation) by default.
    """

    time_s: np.ndarray
    q_wb: np.ndarray
    accel_w_m_s2: np.ndarray | None = None

    def __post_init__(self) -> None:
        t = time_vector(self.time_s)
        q = unit_quaternion(self.q_wb, "q_wb")
        if q.ndim != 2 or q.shape[0] != t.size:
            raise ValueError(f"q_wb must have shape ({t.size}, 4) to match time_s, got {q.shape}")
        acc = (np.zeros((t.size, 3)) if self.accel_w_m_s2 is None
               else as_float_array(self.accel_w_m_s2, "accel_w_m_s2", ndim=2, last_dim=3))
        if acc.shape[0] != t.size:
            raise ValueError(f"accel_w_m_s2 must have shape ({t.size}, 3), got {acc.shape}")
        uniform_dt(t)
        object.__setattr__(self, "time_s", _frozen(t))
        object.__setattr__(self, "q_wb", _frozen(rotations.make_continuous(q, axis=0)))
        object.__setattr__(self, "accel_w_m_s2", _frozen(acc))

    @property
    def dt_s(self) -> float:
        """Sample interval (s)."""
        return float(self.time_s[1] - self.time_s[0])

    @property
    def fs_hz(self) -> float:
        """Sample rate (Hz)."""
        return 1.0 / uniform_dt(self.time_s)

    def __len__(self) -> int:
        return int(self.time_s.size)


def body_rates(trajectory: Trajectory) -> np.ndarray:
    """Interval-mean body rates ``ω_k = rotvec(q_k⁻¹ ⊗ q_{k+1}) / Δt`` (rad/s), shape (N, 3)."""
    q = trajectory.q_wb
    dq = rotations.quat_multiply(rotations.quat_conjugate(q[:-1]), q[1:])
    omega = rotations.rotvec_from_quat(rotations.quat_normalize(dq)) / np.diff(trajectory.time_s)[:, None]
    return np.concatenate([omega, omega[-1:]], axis=0)


def specific_force(trajectory: Trajectory, gravity_w_m_s2=GRAVITY_W_M_S2) -> np.ndarray:
    """Specific force in the body frame ``f_b = C_wbᵀ (a_w − g_w)`` (m/s²), shape (N, 3)."""
    g = as_float_array(gravity_w_m_s2, "gravity_w_m_s2", ndim=1, last_dim=3)
    c_wb = rotations.quat_to_matrix(trajectory.q_wb)
    return np.einsum("nji,nj->ni", c_wb, trajectory.accel_w_m_s2 - g)


def integrate_gyro(q0, gyro_rad_s, dt_s: float) -> np.ndarray:
    """wang2023cja Eq 6–7 without correction: ``Q_{k+1} = Q_k ⊗ q(ω_k Δt)``.

    Parameters
    ----------
    q0 : array_like, shape (4,) or (T, 4)
        Initial scalar-first unit quaternion(s).
    gyro_rad_s : array_like, shape (N, 3) or (T, N, 3)
        Body rates (rad/s); sample k acts over ``[t_k, t_{k+1}]``.
    dt_s : float
        Sample interval (s).

    Returns
    -------
    ndarray, shape (N, 4) or (T, N, 4)
        Attitude at every sample time (``Q_0 = q0``).
    """
    dt = positive_scalar(dt_s, "dt_s")
    w = as_float_array(gyro_rad_s, "gyro_rad_s", ndim=(2, 3), last_dim=3)
    q = unit_quaternion(q0, "q0")
    inc = rotations.quat_from_rotvec(w * dt)
    out = np.empty(w.shape[:-1] + (4,))
    out[..., 0, :] = q
    for k in range(w.shape[-2] - 1):  # recursive: loop over time, vectorised over trials
        out[..., k + 1, :] = rotations.hamilton(out[..., k, :], inc[..., k, :])
    return out


def _vec3(value, name: str) -> np.ndarray:
    arr = as_float_array(value, name)
    if arr.shape not in ((), (3,)):
        raise ValueError(f"{name} must be a scalar or a 3-vector, got shape {arr.shape}")
    return np.broadcast_to(arr, (3,)).copy()


@dataclass(frozen=True)
class SensorErrors:
    """Error parameters of one sensor triad, in the sensor's unit ``u`` (rad/s or m/s²).

    Parameters
    ----------
    bias : float or 3-tuple
        Constant bias (u).
    bias_sigma : float
        1σ of the turn-on bias drawn once per trial (u).
    noise_density : float
        White-noise density (u/√Hz); gyro: angle random walk in rad/s/√Hz.
    bias_random_walk : float
        Bias random-walk density (u/s/√Hz = u/√s); gyro: rate random walk.
    bias_instability : float
        1σ of the first-order Gauss–Markov bias (u).
    bias_instability_tau_s : float
        Correlation time of that bias (s).
    warmup_bias : float or 3-tuple
        Extra bias at power-on (u), decaying with ``warmup_tau_s``.
    warmup_tau_s : float
        Warm-up settling time constant (s).
    scale_factor : float or 3-tuple
        Scale-factor error (dimensionless, 1e-3 = 1000 ppm).
    misalignment : 3×3 nested tuple
        Off-diagonal misalignment (rad, diagonal ignored).
    quantization : float
        Output resolution (u); 0 for none.
    vibration_amplitude : float or 3-tuple
        Sinusoidal vibration amplitude (u).
    vibration_freq_hz : float
        Vibration frequency (Hz).
    """

    bias: float | tuple = 0.0
    bias_sigma: float = 0.0
    noise_density: float = 0.0
    bias_random_walk: float = 0.0
    bias_instability: float = 0.0
    bias_instability_tau_s: float = 100.0
    warmup_bias: float | tuple = 0.0
    warmup_tau_s: float = 60.0
    scale_factor: float | tuple = 0.0
    misalignment: tuple = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    quantization: float = 0.0
    vibration_amplitude: float | tuple = 0.0
    vibration_freq_hz: float = 0.0

    def __post_init__(self) -> None:
        for name in ("bias_sigma", "noise_density", "bias_random_walk", "bias_instability",
                     "quantization", "vibration_freq_hz"):
            positive_scalar(getattr(self, name), name, allow_zero=True)
        for name in ("bias_instability_tau_s", "warmup_tau_s"):
            positive_scalar(getattr(self, name), name)
        for name in ("bias", "warmup_bias", "scale_factor", "vibration_amplitude"):
            _vec3(getattr(self, name), name)
        mis = as_float_array(self.misalignment, "misalignment")
        if mis.shape != (3, 3):
            raise ValueError(f"misalignment must be 3x3, got shape {mis.shape}")

    def matrix(self) -> np.ndarray:
        """``I + S + M``: scale factor on the diagonal, misalignment off it."""
        mis = np.array(self.misalignment, dtype=float)
        np.fill_diagonal(mis, 0.0)
        return np.eye(3) + np.diag(_vec3(self.scale_factor, "scale_factor")) + mis


@dataclass(frozen=True)
class ImuErrorModel:
    """Error model of a whole IMU plus its mounting on the body.

    Parameters
    ----------
    gyro : SensorErrors
        Gyro errors in rad/s units.
    accel : SensorErrors
        Accelerometer errors in m/s² units.
    q_mount : 4-tuple
        Scalar-first quaternion ``q_bs`` of the sensor frame relative to the
        body (``v_b = C(q_bs) v_s``); identity by default.
    time_since_power_on_s : float
        Time the IMU has been on when the record starts (s); 300 s = the
        5-minute warm-up of wang2023cja.
    """

    gyro: SensorErrors = field(default_factory=SensorErrors)
    accel: SensorErrors = field(default_factory=SensorErrors)
    q_mount: tuple = (1.0, 0.0, 0.0, 0.0)
    time_since_power_on_s: float = 0.0

    def __post_init__(self) -> None:
        for name in ("gyro", "accel"):
            if not isinstance(getattr(self, name), SensorErrors):
                raise TypeError(f"{name} must be a SensorErrors, got {type(getattr(self, name)).__name__}")
        q = unit_quaternion(self.q_mount, "q_mount")
        if q.shape != (4,):
            raise ValueError(f"q_mount must have shape (4,), got {q.shape}")
        positive_scalar(self.time_since_power_on_s, "time_since_power_on_s", allow_zero=True)
        if self.accel.noise_density > 1.0 or np.max(np.abs(_vec3(self.accel.bias, "bias"))) > 5.0:
            raise ValueError("accel errors look too large for m/s² (noise_density > 1 m/s²/√Hz or "
                             "|bias| > 5 m/s²); were they given in the wrong unit?")
        if self.gyro.noise_density > 0.1 or np.max(np.abs(_vec3(self.gyro.bias, "bias"))) > 1.0:
            raise ValueError("gyro errors look too large for rad/s (noise_density > 0.1 rad/s/√Hz or "
                             "|bias| > 1 rad/s); were degrees passed as radians?")


@dataclass(frozen=True)
class ImuRecord:
    """Simulated IMU output. Arrays are (N, 3) for one trial or (T, N, 3) for many.

    Attributes
    ----------
    time_s : ndarray (N,)
    gyro_rad_s : ndarray
        Body rates in the sensor frame (rad/s).
    accel_m_s2 : ndarray
        Specific force in the sensor frame (m/s²).
    q_ws_true : ndarray (N, 4)
        True sensor attitude (sensor → world), scalar-first.
    gyro_true_rad_s, accel_true_m_s2 : ndarray (N, 3)
        Error-free sensor outputs.
    """

    time_s: np.ndarray
    gyro_rad_s: np.ndarray
    accel_m_s2: np.ndarray
    q_ws_true: np.ndarray
    gyro_true_rad_s: np.ndarray
    accel_true_m_s2: np.ndarray


# ----------------------------------------------------------------------------- compiled engine
@jit
def _fill_standard_normal(gen, out):
    """``out[...] = gen.standard_normal(out.shape)`` (same draws, C order; numba's port of numpy's ziggurat)."""
    flat = out.reshape(-1)
    for i in range(flat.size):
        flat[i] = gen.standard_normal()


@jit
def _apply_errors(out, off, n, base, per_trial_base, bias, warm, turn_on, white, white_scale, rw, rw_scale,
                  rw_state, gm, gm_sigma, gm_c, gm_a, gm_state, gm_first, vib, quant, roff, flags,
                  gen_white, gen_rw, gen_gm, fused):
    """Samples ``off … off+n`` of a chunk of :meth:`_SensorStream.process`, in the reference's order.

    ``out``, ``base`` ((1 or T), C, 3), ``warm`` (C, 3) and ``vib`` are chunk-aligned; the random
    blocks ``white``, ``rw``, ``gm`` (T, B, 3) are read from ``roff``, or, with ``fused`` (a whole
    block inside the chunk: ``n`` = B), drawn here from the blocks' generators ``gen_*`` in the
    block's C order (trial, sample, axis) — the same numbers, without the block buffers' memory
    traffic. ``flags`` bits: 1 warm-up,
    2 turn-on, 4 white, 8 random walk, 16 Gauss–Markov, 32 vibration, 64 quantisation.
    ``rw_state`` / ``gm_state`` (T, 3) carry the walk and the last Gauss–Markov output;
    ``gm_first``: sample ``off`` is global sample 0 (stationary start ``w_0 / c``).
    """
    walk = np.empty(3)
    y = np.empty(3)
    z = np.empty(3)
    for t in range(out.shape[0]):
        tb = t if per_trial_base else 0
        for j in range(3):
            walk[j] = rw_state[t, j]
            y[j] = gm_state[t, j]
            z[j] = gm_a * y[j]                 # lfilter's delay state zi = a · b_{k-1}
        for i in range(n):
            for j in range(3):                 # three independent recursions side by side
                x = base[tb, off + i, j] + bias[j]
                if flags & 1:
                    x = x + warm[off + i, j]
                if flags & 2:
                    x = x + turn_on[t, j]
                if flags & 4:
                    nw = gen_white.standard_normal() if fused else white[t, roff + i, j]
                    x = x + white_scale * nw
                if flags & 8:
                    nr = gen_rw.standard_normal() if fused else rw[t, roff + i, j]
                    walk[j] = walk[j] + nr * rw_scale   # np.cumsum, continued
                    x = x + walk[j]
                if flags & 16:                 # scipy lfilter([c], [1, -a]) (direct form II transposed)
                    ng = gen_gm.standard_normal() if fused else gm[t, roff + i, j]
                    w = ng * gm_sigma
                    if gm_first and i == 0:
                        w = w / gm_c
                    yj = z[j] + gm_c * w
                    z[j] = w * 0.0 - yj * (-gm_a)
                    y[j] = yj
                    x = x + yj
                if flags & 32:
                    x = x + vib[t, off + i, j]
                if flags & 64:
                    x = np.rint(x / quant) * quant
                out[t, off + i, j] = x
        for j in range(3):
            rw_state[t, j] = walk[j]
            gm_state[t, j] = y[j]


#: Stand-in for the generator arguments of :func:`_apply_errors` that a call does not draw from.
_DUMMY_GENERATOR = np.random.Generator(np.random.PCG64(0))


class _SensorStream:
    """Applies one triad's :class:`SensorErrors` chunk by chunk.

    Random numbers come in fixed blocks of ``block_samples`` samples, each
    block from its own generator keyed by (sensor, source, block index), so
    the output does not depend on how the record is cut into chunks.
    Random-walk and Gauss–Markov states carry over between chunks.
    """

    def __init__(self, errors: SensorErrors, seed_seq: np.random.SeedSequence | None, sensor_index: int,
                 trials: int, dt_s: float, time_since_power_on_s: float, block_samples: int,
                 engine: str = "numba"):
        self.engine = engine
        self.e, self.seed_seq, self.sensor_index = errors, seed_seq, sensor_index
        self.trials, self.dt, self.t_on, self.block = trials, dt_s, time_since_power_on_s, block_samples
        self.matrix_t = errors.matrix().T
        self.bias = _vec3(errors.bias, "bias")
        self.warm = _vec3(errors.warmup_bias, "warmup_bias")
        self.vib = _vec3(errors.vibration_amplitude, "vibration_amplitude")
        self.rw_state = np.zeros((trials, 1, 3))
        self.gm_a = np.exp(-dt_s / errors.bias_instability_tau_s)
        self.gm_state = None
        self._cache: dict[str, tuple[int, np.ndarray]] = {}
        self.turn_on = (errors.bias_sigma * self._generator("turn_on", 0).standard_normal((trials, 1, 3))
                        if errors.bias_sigma else None)
        self.phase = (self._generator("vibration", 0).uniform(0.0, 2 * np.pi, (trials, 1, 3))
                      if np.any(self.vib) and errors.vibration_freq_hz else None)
        self._rw = np.zeros((trials, 3))       # numba engine: walk and Gauss–Markov output carried over
        self._gm = np.zeros((trials, 3))

    def _generator(self, source: str, block: int) -> np.random.Generator:
        key = self.seed_seq.spawn_key + (self.sensor_index, _SOURCES.index(source), block)
        return np.random.Generator(np.random.PCG64(np.random.SeedSequence(self.seed_seq.entropy, spawn_key=key)))

    def _block(self, source: str, b: int) -> np.ndarray:
        """Standard normal draws (T, block, 3) of block ``b`` of ``source`` (the last block is cached)."""
        cached = self._cache.get(source)
        if cached is None or cached[0] != b:
            gen = self._generator(source, b)
            if self.engine == "numba":  # blocks are consumed one at a time: refill one buffer per source
                arr = cached[1] if cached is not None else np.empty((self.trials, self.block, 3))
                _fill_standard_normal(gen, arr)
            else:
                arr = gen.standard_normal((self.trials, self.block, 3))
            cached = (b, arr)
            self._cache[source] = cached
        return cached[1]

    def _normal(self, source: str, start: int, stop: int) -> np.ndarray:
        """Standard normal draws (T, stop − start, 3) for global samples [start, stop)."""
        b0, b1 = start // self.block, (stop - 1) // self.block
        parts = [self._block(source, b) for b in range(b0, b1 + 1)]
        blocks = parts[0] if len(parts) == 1 else np.concatenate(parts, axis=1)
        return blocks[:, start - b0 * self.block: stop - b0 * self.block]

    def process(self, truth: np.ndarray, time_s: np.ndarray, start: int) -> np.ndarray:
        """Measurements (T, n, 3) for truth samples (n, 3) at global index ``start``."""
        if self.engine == "numba":
            return self._process_numba(truth, time_s, start)
        e, n = self.e, truth.shape[-2]  # truth: (n, 3) shared or (T, n, 3) per trial
        stop = start + n
        out = np.empty((self.trials, n, 3))
        out[:] = truth @ self.matrix_t
        out += self.bias
        if np.any(self.warm):
            out += np.exp(-(time_s + self.t_on) / e.warmup_tau_s)[:, None] * self.warm
        if self.turn_on is not None:
            out += self.turn_on
        if e.noise_density:
            out += (e.noise_density / np.sqrt(self.dt)) * self._normal("white", start, stop)
        if e.bias_random_walk:
            steps = self._normal("random_walk", start, stop) * (e.bias_random_walk * np.sqrt(self.dt))
            steps[:, :1, :] += self.rw_state  # carry the walk: same summation order as one long cumsum
            walk = np.cumsum(steps, axis=1)
            self.rw_state = walk[:, -1:, :].copy()
            out += walk
        if e.bias_instability:
            out += self._gauss_markov(start, stop)
        if self.phase is not None:
            out += self.vib * np.sin(2 * np.pi * e.vibration_freq_hz * time_s[None, :, None] + self.phase)
        if e.quantization:
            np.round(out / e.quantization, out=out)
            out *= e.quantization
        return out

    def _process_numba(self, truth: np.ndarray, time_s: np.ndarray, start: int) -> np.ndarray:
        """:meth:`process` with the compiled engine: one :func:`_apply_errors` pass per random block
        overlapping the chunk, reading the blocks in place (no concatenation)."""
        e, n = self.e, truth.shape[-2]
        stop = start + n
        out = np.empty((self.trials, n, 3))
        base = truth @ self.matrix_t          # same product as the reference
        base = np.ascontiguousarray(base if base.ndim == 3 else base[None])
        none2, none3 = np.zeros((1, 3)), np.zeros((1, 1, 3))
        flags = 0
        warm = none2
        if np.any(self.warm):
            warm, flags = np.ascontiguousarray(np.exp(-(time_s + self.t_on) / e.warmup_tau_s)[:, None] * self.warm), 1
        turn_on = none2 if self.turn_on is None else np.ascontiguousarray(self.turn_on[:, 0, :])
        flags |= 0 if self.turn_on is None else 2
        flags |= (4 if e.noise_density else 0) | (8 if e.bias_random_walk else 0) | (16 if e.bias_instability else 0)
        vib = none3
        if self.phase is not None:
            vib = np.ascontiguousarray(self.vib * np.sin(2 * np.pi * e.vibration_freq_hz * time_s[None, :, None]
                                                         + self.phase))
            flags |= 32
        flags |= 64 if e.quantization else 0
        white_scale = e.noise_density / np.sqrt(self.dt)
        rw_scale = e.bias_random_walk * np.sqrt(self.dt)
        gm_a = float(self.gm_a)
        gm_c = float(np.sqrt(1.0 - gm_a * gm_a))
        sources = [(4, "white"), (8, "random_walk"), (16, "instability")]
        for b in range(start // self.block, (stop - 1) // self.block + 1):
            lo, hi = max(start, b * self.block), min(stop, (b + 1) * self.block)
            fused = hi - lo == self.block     # a whole block inside this chunk: draw while applying
            arrays, gens = [], []
            for bit, source in sources:
                on = bool(flags & bit)
                arrays.append(self._block(source, b) if on and not fused else none3)
                gens.append(self._generator(source, b) if on and fused else _DUMMY_GENERATOR)
            _apply_errors(out, lo - start, hi - lo, base, base.shape[0] > 1, self.bias, warm, turn_on, arrays[0],
                          float(white_scale), arrays[1], float(rw_scale), self._rw, arrays[2],
                          float(e.bias_instability), gm_c, gm_a, self._gm, lo == 0, vib, float(e.quantization),
                          lo - b * self.block, flags, gens[0], gens[1], gens[2], fused)
        return out

    def _gauss_markov(self, start: int, stop: int) -> np.ndarray:
        """First-order Gauss–Markov bias ``b_k = a b_{k−1} + √(1−a²) σ w_k``, stationary from k = 0."""
        a, sigma = self.gm_a, self.e.bias_instability
        w = self._normal("instability", start, stop) * sigma
        c = np.sqrt(1.0 - a * a)
        if start == 0:
            w = w.copy()
            w[:, 0, :] /= c  # b_0 = σ w_0 ~ N(0, σ²)
        zi = np.zeros((self.trials, 1, 3)) if self.gm_state is None else a * self.gm_state
        b, _ = _lfilter([c], [1.0, -a], w, axis=1, zi=zi)
        self.gm_state = b[:, -1:, :].copy()
        return b


class ImuStream:
    """Simulated IMU output delivered in time chunks, in bounded memory.

    ``ImuStream(...).chunks(n)`` yields :class:`ImuRecord` pieces of ``n``
    samples (the last may be shorter). The random draws do not depend on the
    chunk size: concatenating the chunks gives exactly :func:`simulate_imu`'s
    output for the same generator state, whatever ``n`` is. Use it for Monte
    Carlo runs where only metrics are kept (never all trials × all samples).

    Parameters
    ----------
    trajectory, model, rng, trials, gravity_w_m_s2
        As for :func:`simulate_imu`.
    block_samples : int
        Size of the fixed random-number blocks (memory per block:
        ``trials × block_samples × 3 × 8`` bytes per error source).
    engine : {"numba", "numpy"}
        Compiled error model (default) or the numpy reference; bit-identical output.
    """

    def __init__(self, trajectory: Trajectory, model: ImuErrorModel | None = None,
                 rng: np.random.Generator | None = None, trials: int | None = None,
                 gravity_w_m_s2=GRAVITY_W_M_S2, block_samples: int = 256, *, engine: str = "numba"):
        if not isinstance(trajectory, Trajectory):
            raise TypeError(f"trajectory must be a Trajectory, got {type(trajectory).__name__}")
        model = ImuErrorModel() if model is None else model
        if not isinstance(model, ImuErrorModel):
            raise TypeError(f"model must be an ImuErrorModel, got {type(model).__name__}")
        if rng is not None and not isinstance(rng, np.random.Generator):
            raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
        if rng is None and _has_random_errors(model):
            raise ValueError("rng must be a numpy.random.Generator when the error model has random errors")
        self.trajectory, self.model, self.single = trajectory, model, trials is None
        self.trials = 1 if trials is None else positive_int(trials, "trials")
        block = positive_int(block_samples, "block_samples")
        engine = _check_engine(engine)
        q_bs = np.asarray(model.q_mount, dtype=float)
        self.q_ws = rotations.quat_multiply(trajectory.q_wb, q_bs)
        c_sb = rotations.quat_to_matrix(q_bs).T
        self.gyro_true = body_rates(trajectory) @ c_sb.T
        self.accel_true = specific_force(trajectory, gravity_w_m_s2) @ c_sb.T
        seed_seq = rng.spawn(1)[0].bit_generator.seed_seq if rng is not None else None
        dt, t_on = trajectory.dt_s, model.time_since_power_on_s
        self._gyro = _SensorStream(model.gyro, seed_seq, 0, self.trials, dt, t_on, block, engine)
        self._accel = _SensorStream(model.accel, seed_seq, 1, self.trials, dt, t_on, block, engine)
        self._next = 0

    def chunks(self, chunk_samples: int):
        """Yield consecutive :class:`ImuRecord` chunks of ``chunk_samples`` samples."""
        size = positive_int(chunk_samples, "chunk_samples")
        if self._next != 0:
            raise ValueError("chunks() can be iterated once per ImuStream (the noise states advance)")
        n = len(self.trajectory)
        for start in range(0, n, size):
            stop = min(start + size, n)
            self._next = stop
            t = self.trajectory.time_s[start:stop]
            gyro = self._gyro.process(self.gyro_true[start:stop], t, start)
            accel = self._accel.process(self.accel_true[start:stop], t, start)
            if self.single:
                gyro, accel = gyro[0], accel[0]
            yield ImuRecord(t, gyro, accel, self.q_ws[start:stop], self.gyro_true[start:stop],
                            self.accel_true[start:stop])


def apply_sensor_errors(errors: SensorErrors, truth, time_s, rng: np.random.Generator | None = None, *,
                        time_since_power_on_s: float = 0.0, engine: str = "numba") -> np.ndarray:
    """Corrupt an error-free triad signal with one sensor's :class:`SensorErrors`.

    For batches where every trial has its own truth (e.g. wang2022sensors's per-trial
    angle histories); :func:`simulate_imu` is the usual entry point.

    Parameters
    ----------
    errors : SensorErrors
        Error model (units of the signal: rad/s or m/s²).
    truth : array_like, shape (N, 3) or (T, N, 3)
        Error-free signal; a leading axis gives per-trial truth.
    time_s : array_like, shape (N,)
        Uniformly sampled, strictly increasing time (s).
    rng : numpy.random.Generator
        Required when ``errors`` has random terms.
    time_since_power_on_s : float
        Time already powered at ``time_s[0]`` (s), for the warm-up bias.
    engine : {"numba", "numpy"}
        Compiled error model (default) or the numpy reference; bit-identical output.

    Returns
    -------
    ndarray, same shape as ``truth``
    """
    if not isinstance(errors, SensorErrors):
        raise TypeError(f"errors must be a SensorErrors, got {type(errors).__name__}")
    x = as_float_array(truth, "truth", ndim=(2, 3), last_dim=3)
    t = time_vector(time_s)
    if x.shape[-2] != t.size:
        raise ValueError(f"truth must have {t.size} samples on axis -2 to match time_s, got {x.shape}")
    if rng is not None and not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    if rng is None and _is_random(errors):
        raise ValueError("rng must be a numpy.random.Generator when errors has random terms")
    trials = 1 if x.ndim == 2 else x.shape[0]
    seed_seq = rng.spawn(1)[0].bit_generator.seed_seq if rng is not None else None
    stream = _SensorStream(errors, seed_seq, 0, trials, uniform_dt(t),
                           positive_scalar(time_since_power_on_s, "time_since_power_on_s", allow_zero=True),
                           block_samples=256, engine=_check_engine(engine))
    out = stream.process(x, t, 0)
    return out[0] if x.ndim == 2 else out


def simulate_imu(trajectory: Trajectory, model: ImuErrorModel | None = None,
                 rng: np.random.Generator | None = None, trials: int | None = None,
                 gravity_w_m_s2=GRAVITY_W_M_S2, *, engine: str = "numba") -> ImuRecord:
    """Simulate gyro and accelerometer outputs along a trajectory.

    Parameters
    ----------
    trajectory : Trajectory
        Truth body motion.
    model : ImuErrorModel, optional
        Sensor errors and mounting; error-free and identity mounting if None.
    rng : numpy.random.Generator
        Source of every random draw (required when the model has random errors).
    trials : int, optional
        Number of Monte Carlo trials; output arrays get a leading trial axis.
        ``None`` gives a single trial without the leading axis.
    gravity_w_m_s2 : 3-vector
        World gravity (m/s²), default z-up ``[0, 0, −9.80665]``.
    engine : {"numba", "numpy"}
        Compiled error model (default) or the numpy reference; bit-identical output.

    Returns
    -------
    ImuRecord

    See Also
    --------
    ImuStream : the same output in time chunks (bounded memory).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(0, 1, 0.01)
    >>> q = np.tile([1.0, 0, 0, 0], (t.size, 1))
    >>> rec = simulate_imu(Trajectory(t, q))
    >>> rec.accel_m_s2[0].round(5)
    array([0.     , 0.     , 9.80665])
    """
    stream = ImuStream(trajectory, model, rng, trials, gravity_w_m_s2, engine=engine)
    return next(stream.chunks(len(trajectory)))


def _check_engine(engine: str) -> str:
    if engine not in ("numba", "numpy"):
        raise ValueError(f"engine must be one of ('numba', 'numpy'), got {engine!r}")
    return engine


def _has_random_errors(model: ImuErrorModel) -> bool:
    return _is_random(model.gyro) or _is_random(model.accel)


def _is_random(s: SensorErrors) -> bool:
    """Whether a triad's error model draws random numbers."""
    if s.bias_sigma or s.noise_density or s.bias_random_walk or s.bias_instability:
        return True
    return bool(np.any(_vec3(s.vibration_amplitude, "vibration_amplitude")) and s.vibration_freq_hz)


def _lfilter(*args, **kwargs):
    """``scipy.signal.lfilter``, imported on first use (scipy.signal costs ~0.5-1 s of import time)."""
    from scipy.signal import lfilter

    return lfilter(*args, **kwargs)
