"""tan2022 (Tan et al., 2022) — accelerometer pitch/roll and the preset Euler rotation.

Static three-axis accelerometer attitude (Eq 2), its first-order error
(Eq 3 as printed and corrected, Eq 4 for roll), and the *preset Euler
rotation* (Eq 6–10): a second triad turned by λ about the body x axis so that
the two terms of the pitch error cancel instead of adding.

Conventions
-----------
Aerospace Z-Y-X angles (ψ, θ, φ), static specific force
``f = g [−sinθ, cosθ sinφ, cosθ cosφ]`` (Eq 2, :func:`mtcal.core.rotations.specific_force_zyx`).
A triad preset by λ about x reads ``f^{b1} = g [−sinθ, cosθ sin(φ+λ), cosθ cos(φ+λ)]``
(Eq 7); the matrix that produces Eq 7 is ``[[1,0,0],[0,cosλ,sinλ],[0,−sinλ,cosλ]]``,
the *transpose* of Eq 6 as printed (which would give φ−λ; paper README tan2022 item 3).
We follow Eq 7–10, which agree with each other.

Errata, docs/errata.md
----------------------
Eq 3 as printed, ``Δθ = −(ΔA/g)cosθ − (ΔA/g)√2 sin(φ+45°)``, drops a ``sinθ``;
differentiating Eq 2 gives ``Δθ = −(ΔA/g)[cosθ + √2 sinθ sin(φ+45°)]``, which
is Eq 8 with λ = 0 and the ``Δθ_T`` of Sec. 3.1. :func:`pitch_error_eq3_printed`
keeps the printed form for comparison.

Units: angles in rad, specific force and its errors in m/s² (``g`` defaults to
standard gravity, pass ``g=1.0`` to work in units of g).
"""

from __future__ import annotations

import numpy as np

from mtcal.core import rotations
from mtcal.core.validate import STANDARD_GRAVITY_M_S2, angle_rad, as_float_array, positive_scalar

__all__ = ["LAMBDA1_RAD", "LAMBDA2_RAD", "pitch_roll_eq2", "pitch_error_first_order", "max_abs_pitch_error_first_order",
           "pitch_error_eq3_printed", "pitch_error_eq8", "roll_error_eq4", "preset_lambda",
           "pitch_error_eq10", "preset_matrix", "preset_specific_force",
           "pitch_roll_from_preset_triad", "select_preset_pitch", "perturbed_errors",
           "perturbed_preset_pitch_error", "monte_carlo_pitch_errors", "bias_moment_matrix",
           "rms_pitch_error_from_moments", "warm_up"]

#: Preset angle for −90° ≤ θ ≤ 0° (Eq 9, triad A1–A3).
LAMBDA1_RAD = float(np.radians(45.0))
#: Preset angle for 0° ≤ θ ≤ 90° (Eq 9, triad A4–A6).
LAMBDA2_RAD = float(np.radians(-135.0))

_HALF_PI = 0.5 * np.pi


# --------------------------------------------------------------------------
# validation
# --------------------------------------------------------------------------
def _pitch(value, name: str = "pitch") -> np.ndarray:
    """Pitch in rad, |θ| ≤ π/2 (the range of Eq 2)."""
    theta = angle_rad(value, name)
    if np.any(np.abs(theta) > _HALF_PI + 1e-12):
        raise ValueError(f"{name} must be within [-pi/2, pi/2] rad (Eq 2 range); got max |{name}| = "
                         f"{np.max(np.abs(theta)):.6g} rad")
    return theta


def _roll(value, name: str = "roll") -> np.ndarray:
    """Roll in rad, |φ| ≤ π."""
    phi = angle_rad(value, name)
    if np.any(np.abs(phi) > np.pi + 1e-12):
        raise ValueError(f"{name} must be within [-pi, pi] rad; got max |{name}| = "
                         f"{np.max(np.abs(phi)):.6g} rad")
    return phi


def _gravity(g: float) -> float:
    return positive_scalar(g, "g")


def _delta(value, name: str = "delta_accel_m_s2") -> np.ndarray:
    return as_float_array(value, name)


def _common_or_vector(delta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Split an accelerometer error into x, y, z parts.

    A scalar (or any array whose last axis is not 3) is a common-mode error ΔA
    on all three axes (the paper's assumption); an array with last axis 3 is a
    per-axis error vector.
    """
    if delta.ndim >= 1 and delta.shape[-1] == 3:
        return delta[..., 0], delta[..., 1], delta[..., 2]
    return delta, delta, delta


# --------------------------------------------------------------------------
# Eq 2 and its first-order errors
# --------------------------------------------------------------------------
def pitch_roll_eq2(accel) -> np.ndarray:
    """tan2022 Eq 2: pitch and roll of a static triad, ``[θ, φ]`` in rad along the last axis.

    Parameters
    ----------
    accel : array_like, shape (..., 3)
        Specific force in any unit (m/s² or g).
    """
    return _eq2(as_float_array(accel, "accel", last_dim=3))


def _eq2(f: np.ndarray, name: str = "accel") -> np.ndarray:
    """:func:`pitch_roll_eq2` of a checked (finite, float64, (..., 3)) specific force; a zero vector is refused."""
    if np.any(np.linalg.norm(f, axis=-1) == 0.0):
        raise ValueError(f"{name} must not contain a zero vector (attitude undefined)")
    return rotations.pitch_roll_from_specific_force(f)


def pitch_error_first_order(pitch, roll, delta_accel_m_s2, *, preset_rad=0.0,
                            g: float = STANDARD_GRAVITY_M_S2) -> np.ndarray:
    """First-order pitch error of Eq 2 for a triad preset by λ (derivative of Eq 2).

    ``Δθ = −[cosθ Δf_x + sinθ (sin(φ+λ) Δf_y + cos(φ+λ) Δf_z)] / g``; with
    ``Δf_x = Δf_y = Δf_z = ΔA`` this is the corrected Eq 3 (λ = 0) or Eq 8.

    Parameters
    ----------
    pitch, roll : array_like
        θ (|θ| ≤ π/2) and φ in rad (broadcast).
    delta_accel_m_s2 : array_like
        Accelerometer error in m/s²: scalar/array = common-mode ΔA, or (..., 3)
        per-axis errors in the (preset) triad frame.
    preset_rad : array_like
        Preset rotation λ about x in rad (0 = plain triad).
    g : float
        Gravity in m/s².

    Returns
    -------
    ndarray
        Δθ in rad.
    """
    theta, phi = _pitch(pitch), _roll(roll)
    lam = angle_rad(preset_rad, "preset_rad")
    dx, dy, dz = _common_or_vector(_delta(delta_accel_m_s2))
    gg = _gravity(g)
    a = phi + lam
    return -(np.cos(theta) * dx + np.sin(theta) * (np.sin(a) * dy + np.cos(a) * dz)) / gg


def max_abs_pitch_error_first_order(pitch, roll, delta_accel_m_s2, *, preset_rad=0.0,
                                    g: float = STANDARD_GRAVITY_M_S2) -> np.ndarray:
    """Per error draw, the largest |first-order pitch error| over the attitudes (rad), one compiled pass.

    Bit-identical to ``np.max(np.abs(pitch_error_first_order(pitch, roll, delta[:, None, :],
    preset_rad=preset_rad, g=g)), axis=1)`` without the (n, P) error array.

    Parameters
    ----------
    pitch, roll : array_like (P,)
        θ (|θ| ≤ π/2) and φ in rad, P ≥ 1 attitudes.
    delta_accel_m_s2 : array_like (n, 3)
        Per-axis accelerometer errors (m/s²), one row per draw, in the (preset) triad frame.
    preset_rad : float or array_like (P,)
        Preset rotation λ about x in rad (0 = plain triad).
    g : float
        Gravity in m/s².

    Returns
    -------
    ndarray (n,)
        max over the P attitudes of |Δθ| (rad).

    Examples
    --------
    >>> th, ph = np.radians([-60.0, 0.0, 70.0]), np.radians([10.0, -30.0, 120.0])
    >>> d = np.array([[1e-3, -2e-3, 5e-4], [0.0, 1e-3, 1e-3]])
    >>> ref = np.max(np.abs(pitch_error_first_order(th, ph, d[:, None, :], preset_rad=0.3)), axis=1)
    >>> bool(np.array_equal(max_abs_pitch_error_first_order(th, ph, d, preset_rad=0.3), ref))
    True
    """
    from mtcal.methods import _large_angle_kernels  # here: numba is imported only when called

    theta, phi = _pitch(pitch), _roll(roll)
    lam = angle_rad(preset_rad, "preset_rad")
    d = as_float_array(delta_accel_m_s2, "delta_accel_m_s2", ndim=2, last_dim=3)
    gg = _gravity(g)
    if theta.ndim != 1:
        raise ValueError(f"pitch must be 1-D with at least one attitude, got shape {theta.shape}")
    a = phi + lam
    theta, a = np.broadcast_arrays(theta, a)
    if a.ndim != 1:
        raise ValueError(f"pitch, roll and preset_rad must broadcast to ({theta.size},), got {np.shape(phi)} and "
                         f"{np.shape(lam)}")
    trig = (np.cos(theta), np.sin(theta), np.sin(a), np.cos(a))
    return _large_angle_kernels.max_abs_first_order(*(np.ascontiguousarray(v, dtype=float) for v in trig),
                                                    np.ascontiguousarray(d), gg)


def pitch_error_eq3_printed(pitch, roll, delta_accel_m_s2, *, g: float = STANDARD_GRAVITY_M_S2) -> np.ndarray:
    """tan2022 Eq 3 **as printed** (missing ``sinθ``): ``−(ΔA/g)cosθ − (ΔA/g)√2 sin(φ+45°)`` (rad).

    Kept only to show the erratum; use :func:`pitch_error_eq8` (λ = 0) for the
    correct first-order error.
    """
    theta, phi = _pitch(pitch), _roll(roll)
    da = _delta(delta_accel_m_s2)
    gg = _gravity(g)
    return -(da / gg) * np.cos(theta) - (da / gg) * np.sqrt(2.0) * np.sin(phi + np.pi / 4)


def pitch_error_eq8(pitch, roll, delta_accel_m_s2, *, preset_rad=0.0,
                    g: float = STANDARD_GRAVITY_M_S2) -> np.ndarray:
    """tan2022 Eq 8 (= corrected Eq 3 for λ = 0), common-mode error ΔA (rad).

    ``Δθ = −(ΔA/g)[cosθ + √2 sinθ sin(φ + λ + 45°)]``.
    """
    return _eq8(_pitch(pitch), _roll(roll), angle_rad(preset_rad, "preset_rad"), _delta(delta_accel_m_s2),
                _gravity(g))


def _eq8(theta: np.ndarray, phi: np.ndarray, lam: np.ndarray, da: np.ndarray, gg: float) -> np.ndarray:
    """:func:`pitch_error_eq8` of checked inputs (θ, φ, λ in range, rad; ΔA finite; g > 0)."""
    return -(da / gg) * (np.cos(theta) + np.sqrt(2.0) * np.sin(theta) * np.sin(phi + lam + np.pi / 4))


def roll_error_eq4(pitch, roll, delta_accel_m_s2, *, g: float = STANDARD_GRAVITY_M_S2) -> np.ndarray:
    """tan2022 Eq 4: first-order roll error of Eq 2 (rad).

    ``Δφ = (cosφ Δf_y − sinφ Δf_z) / (g cosθ)``; common-mode ΔA gives the
    printed ``ΔA (cosφ − sinφ) / (g cosθ)``. Diverges as θ → ±90°.
    """
    theta, phi = _pitch(pitch), _roll(roll)
    _, dy, dz = _common_or_vector(_delta(delta_accel_m_s2))
    gg = _gravity(g)
    with np.errstate(divide="ignore", invalid="ignore"):
        return (np.cos(phi) * dy - np.sin(phi) * dz) / (gg * np.cos(theta))


# --------------------------------------------------------------------------
# preset Euler rotation (Eq 6-10)
# --------------------------------------------------------------------------
def preset_lambda(pitch, *, lambda1_rad: float = LAMBDA1_RAD, lambda2_rad: float = LAMBDA2_RAD) -> np.ndarray:
    """tan2022 Eq 9: λ1 = 45° for θ ≤ 0, λ2 = −135° for θ > 0 (rad).

    At θ = 0 both ranges of Eq 9 apply; λ1 is used. The choice is immaterial
    there: the λ-dependent term of Eq 8 carries ``sinθ = 0``.

    Parameters
    ----------
    pitch : array_like
        θ in rad (|θ| ≤ π/2).
    lambda1_rad, lambda2_rad : float
        Preset angles for θ ≤ 0 and θ > 0 (rad); defaults are Eq 9's.

    Examples
    --------
    >>> np.degrees(preset_lambda(np.radians([-30.0, 30.0])))
    array([  45., -135.])
    """
    return _preset_lambda(_pitch(pitch), lambda1_rad, lambda2_rad)


def _preset_lambda(theta: np.ndarray, lambda1_rad, lambda2_rad) -> np.ndarray:
    """:func:`preset_lambda` of a checked pitch θ (rad, |θ| ≤ π/2); the preset angles are checked here."""
    l1, l2 = angle_rad(lambda1_rad, "lambda1_rad"), angle_rad(lambda2_rad, "lambda2_rad")
    return np.where(theta <= 0.0, l1, l2)


def pitch_error_eq10(pitch, roll, delta_accel_m_s2, *, g: float = STANDARD_GRAVITY_M_S2,
                     lambda1_rad: float = LAMBDA1_RAD, lambda2_rad: float = LAMBDA2_RAD) -> np.ndarray:
    """tan2022 Eq 10: pitch error with the preset triad chosen by Eq 9 (rad).

    ``Δθ = −ΔA (cosθ + √2 sinθ sin(φ ∓ 90°)) / g`` (−90° for θ ≥ 0) for the
    default preset angles.

    Examples
    --------
    >>> round(float(pitch_error_eq10(np.pi / 2, 0.0, 1.0, g=1.0)), 6)   # √2 ΔA/g at the pole
    1.414214
    """
    theta = _pitch(pitch)
    return _eq8(theta, _roll(roll), _preset_lambda(theta, lambda1_rad, lambda2_rad), _delta(delta_accel_m_s2),
                _gravity(g))


def preset_matrix(preset_rad, *, printed: bool = False) -> np.ndarray:
    """Rotation ``C_b^{b1}`` of a triad preset by λ about body x, shape (..., 3, 3).

    Parameters
    ----------
    preset_rad : array_like
        λ in rad.
    printed : bool
        False (default): the matrix that yields Eq 7 (``sin(φ+λ)``),
        ``[[1,0,0],[0,cosλ,sinλ],[0,−sinλ,cosλ]]``. True: Eq 6 as printed
        (``−sinλ`` at (2,3)), which yields ``sin(φ−λ)``.
    """
    return _preset_matrix(angle_rad(preset_rad, "preset_rad"), printed)


def _preset_matrix(lam: np.ndarray, printed: bool = False) -> np.ndarray:
    """:func:`preset_matrix` of a checked λ (rad)."""
    c, s = np.cos(lam), np.sin(lam)
    if printed:
        s = -s
    one, zero = np.ones_like(c), np.zeros_like(c)
    return np.stack([np.stack([one, zero, zero], -1), np.stack([zero, c, s], -1),
                     np.stack([zero, -s, c], -1)], axis=-2)


def preset_specific_force(pitch, roll, preset_rad, *, g: float = STANDARD_GRAVITY_M_S2) -> np.ndarray:
    """tan2022 Eq 7: error-free output of a triad preset by λ, ``g[−sinθ, cosθ sin(φ+λ), cosθ cos(φ+λ)]``.

    Computed as ``C_b^{b1} f^b`` with :func:`preset_matrix` and
    :func:`mtcal.core.rotations.specific_force_zyx`; shape (..., 3) in the unit of ``g``.
    """
    return _preset_force(_pitch(pitch), _roll(roll), angle_rad(preset_rad, "preset_rad"), _gravity(g))


def _preset_force(theta: np.ndarray, phi: np.ndarray, lam: np.ndarray, gg: float) -> np.ndarray:
    """:func:`preset_specific_force` of checked θ, φ, λ (rad, in range) and g > 0."""
    f_b = rotations.specific_force_zyx(theta, phi, gg)
    return np.einsum("...ij,...j->...i", _preset_matrix(lam), f_b)


def pitch_roll_from_preset_triad(accel_b1, preset_rad) -> np.ndarray:
    """Eq 2 applied to a preset triad: ``θ = atan2(−f_x, √(f_y²+f_z²))``, ``φ = atan2(f_y, f_z) − λ``.

    Returns ``[θ, φ]`` (rad, φ wrapped to [−π, π)) along the last axis.
    """
    return _from_preset_triad(as_float_array(accel_b1, "accel_b1", last_dim=3), angle_rad(preset_rad, "preset_rad"))


def _from_preset_triad(f: np.ndarray, lam: np.ndarray) -> np.ndarray:
    """:func:`pitch_roll_from_preset_triad` of a checked specific force (..., 3) and λ (rad)."""
    out = _eq2(f, "accel_b1")
    roll = rotations.wrap_angle(out[..., 1] - lam)
    return np.stack([out[..., 0], roll], axis=-1)


def select_preset_pitch(accel_lambda1, accel_lambda2) -> tuple[np.ndarray, np.ndarray]:
    """Pitch from the triad selected by Eq 9, choosing by the sign of the measured pitch.

    The true θ is unknown when measuring, so the selector uses the pitch of
    triad λ1 (θ̂₁ ≤ 0 → triad λ1, else triad λ2). Near θ = 0 a wrong choice
    costs nothing to first order (both errors equal −ΔA/g there).

    Parameters
    ----------
    accel_lambda1, accel_lambda2 : array_like, shape (..., 3)
        Outputs of the triads preset by λ1 = 45° and λ2 = −135° (any unit).

    Returns
    -------
    pitch_rad : ndarray
        Selected pitch (rad).
    uses_lambda1 : ndarray of bool
        True where triad λ1 was used.
    """
    return _select(as_float_array(accel_lambda1, "accel_lambda1", last_dim=3),
                   as_float_array(accel_lambda2, "accel_lambda2", last_dim=3))


def _select(f1: np.ndarray, f2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`select_preset_pitch` of checked outputs (..., 3) of the two triads."""
    return _select_pitch(_eq2(f1, "accel_lambda1")[..., 0], _eq2(f2, "accel_lambda2")[..., 0])


def _select_pitch(theta1: np.ndarray, theta2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eq 9 selection from the two triads' Eq 2 pitches: θ̂₁ where θ̂₁ ≤ 0, else θ̂₂."""
    use1 = theta1 <= 0.0
    return np.where(use1, theta1, theta2), use1


# --------------------------------------------------------------------------
# errors by perturbing simulated outputs (no linearisation)
# --------------------------------------------------------------------------
def perturbed_errors(pitch, roll, delta_accel_m_s2, *, preset_rad=0.0,
                     g: float = STANDARD_GRAVITY_M_S2) -> tuple[np.ndarray, np.ndarray]:
    """Pitch and roll errors of Eq 2 when the simulated triad output is perturbed.

    ``f̃ = C_b^{b1}(λ) f^b(θ, φ) + Δf``, then Eq 2 (roll minus λ), minus truth.

    Parameters
    ----------
    pitch, roll : array_like
        True θ (|θ| ≤ π/2) and φ in rad.
    delta_accel_m_s2 : array_like
        Scalar/array common-mode ΔA or (..., 3) per-axis errors, m/s².
    preset_rad : array_like
        λ (rad); 0 = plain triad.
    g : float
        Gravity (m/s²).

    Returns
    -------
    (dpitch_rad, droll_rad) : tuple of ndarray
        Exact errors; roll error wrapped to [−π, π).
    """
    theta, phi = _pitch(pitch), _roll(roll)
    lam = angle_rad(preset_rad, "preset_rad")
    dx, dy, dz = _common_or_vector(_delta(delta_accel_m_s2))
    f = _preset_force(theta, phi, lam, _gravity(g))
    f_err = f + np.stack(np.broadcast_arrays(dx, dy, dz), axis=-1)
    est = _from_preset_triad(f_err, lam)
    return est[..., 0] - theta, rotations.wrap_angle(est[..., 1] - phi)


def perturbed_preset_pitch_error(pitch, roll, delta_lambda1_m_s2, delta_lambda2_m_s2, *,
                                 g: float = STANDARD_GRAVITY_M_S2, lambda1_rad: float = LAMBDA1_RAD,
                                 lambda2_rad: float = LAMBDA2_RAD) -> np.ndarray:
    """Exact pitch error of the two-triad preset method (Eq 9 selection by measured sign).

    Parameters
    ----------
    pitch, roll : array_like
        True θ and φ (rad).
    delta_lambda1_m_s2, delta_lambda2_m_s2 : array_like
        Errors of triad λ1 and triad λ2 (common-mode scalar or (..., 3)), m/s².
    g : float
        Gravity (m/s²).
    lambda1_rad, lambda2_rad : float
        Preset angles of the two triads (rad); defaults are Eq 9's.

    Returns
    -------
    ndarray
        Δθ (rad) of the selected triad.

    Examples
    --------
    >>> err = perturbed_preset_pitch_error(np.radians(60.0), 0.0, 1e-4, 1e-4, g=1.0)
    >>> bool(abs(err - pitch_error_eq10(np.radians(60.0), 0.0, 1e-4, g=1.0)) < 1e-7)
    True
    """
    theta, phi = _pitch(pitch), _roll(roll)
    d1 = np.stack(np.broadcast_arrays(*_common_or_vector(_delta(delta_lambda1_m_s2, "delta_lambda1_m_s2"))), -1)
    d2 = np.stack(np.broadcast_arrays(*_common_or_vector(_delta(delta_lambda2_m_s2, "delta_lambda2_m_s2"))), -1)
    gg = _gravity(g)
    f1 = _preset_force(theta, phi, angle_rad(lambda1_rad, "lambda1_rad"), gg) + d1
    f2 = _preset_force(theta, phi, angle_rad(lambda2_rad, "lambda2_rad"), gg) + d2
    est, _ = _select(f1, f2)
    return est - theta


def monte_carlo_pitch_errors(pitch, roll, sigma_m_s2: float, rng: np.random.Generator, trials: int, *,
                             g: float = STANDARD_GRAVITY_M_S2) -> dict[str, np.ndarray]:
    """Pitch errors under *independent* per-axis accelerometer errors (beyond the paper).

    Every axis of every triad gets its own error ``N(0, σ²)`` (one draw per
    trial and grid point: a static bias or a white-noise sample alike).

    Parameters
    ----------
    pitch, roll : array_like
        True θ and φ (rad), broadcast to the grid shape S.
    sigma_m_s2 : float
        1σ of each axis' error (m/s²).
    rng : numpy.random.Generator
        Source of the draws.
    trials : int
        Number of Monte Carlo trials (leading axis).
    g : float
        Gravity (m/s²).

    Returns
    -------
    dict of ndarray, each shape (trials, *S), rad
        ``"single"`` plain triad (Eq 2), ``"preset"`` Eq 9 selection of the
        two preset triads, ``"mean_of_two"`` average of the two preset triads'
        pitch (uses the redundancy for averaging instead).
    """
    from mtcal.core.validate import positive_int

    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    sigma = positive_scalar(sigma_m_s2, "sigma_m_s2")
    n = positive_int(trials, "trials")
    theta, phi = np.broadcast_arrays(_pitch(pitch), _roll(roll))
    shape = (n,) + theta.shape + (3,)
    d0, d1, d2 = (sigma * rng.standard_normal(shape) for _ in range(3))
    gg = _gravity(g)
    single = _eq2(rotations.specific_force_zyx(theta, phi, gg) + d0)[..., 0] - theta
    f1 = _preset_force(theta, phi, np.asarray(LAMBDA1_RAD, float), gg) + d1
    f2 = _preset_force(theta, phi, np.asarray(LAMBDA2_RAD, float), gg) + d2
    theta1, theta2 = _eq2(f1, "accel_lambda1")[..., 0], _eq2(f2, "accel_lambda2")[..., 0]  # each triad's Eq 2 once
    preset = _select_pitch(theta1, theta2)[0]
    mean2 = 0.5 * (theta1 + theta2)
    return {"single": single, "preset": preset - theta, "mean_of_two": mean2 - theta}


# --------------------------------------------------------------------------
# grid RMS of the first-order pitch error for static per-axis biases
# --------------------------------------------------------------------------
def bias_moment_matrix(pitch, roll) -> np.ndarray:
    """Second moments over a grid of the features of the first-order pitch error, shape (3, 3).

    With static per-axis biases ``d = [d_x, d_y, d_z]`` of a triad preset by λ,
    the first-order error is ``g Δθ = −(cosθ d_x + sinθ sinφ u + sinθ cosφ v)``
    with ``u = cosλ d_y − sinλ d_z`` and ``v = sinλ d_y + cosλ d_z`` (the
    derivative of Eq 2 applied to Eq 7). Its mean square over the grid is
    ``wᵀ M w`` with ``w = [d_x, u, v]`` and ``M`` the mean of the outer products
    of ``[cosθ, sinθ sinφ, sinθ cosφ]`` returned here.

    Parameters
    ----------
    pitch, roll : array_like
        Grid of θ (|θ| ≤ π/2) and φ (rad), broadcast together.

    Examples
    --------
    >>> th, ph = np.meshgrid(np.radians([-60.0, 0.0, 60.0]), np.radians([-90.0, 0.0, 90.0]), indexing="ij")
    >>> bias_moment_matrix(th, ph).shape
    (3, 3)
    """
    theta, phi = np.broadcast_arrays(_pitch(pitch), _roll(roll))
    feats = np.stack([np.cos(theta), np.sin(theta) * np.sin(phi), np.sin(theta) * np.cos(phi)], -1).reshape(-1, 3)
    return feats.T @ feats / feats.shape[0]


def rms_pitch_error_from_moments(moments, bias_m_s2, preset_rad, *, g: float = STANDARD_GRAVITY_M_S2) -> np.ndarray:
    """Grid-RMS first-order pitch error (rad) of triads with static biases, from :func:`bias_moment_matrix`.

    Parameters
    ----------
    moments : array_like, shape (3, 3)
        Output of :func:`bias_moment_matrix` for the grid of interest.
    bias_m_s2 : array_like, shape (..., 3)
        Static per-axis bias of each triad (m/s², in the triad's own frame).
    preset_rad : array_like
        Preset angle λ (rad), broadcast against the leading shape of ``bias_m_s2``.
    g : float
        Gravity (m/s²).

    Returns
    -------
    ndarray
        RMS of Δθ over the grid (rad), the broadcast leading shape.

    Examples
    --------
    A common-mode bias ΔA over the θ ≤ 0 half of the grid is smallest at the Eq 9 angle λ1 = 45°:

    >>> th, ph = np.meshgrid(np.radians(np.arange(-90.0, 0.1, 5.0)), np.radians(np.arange(-90.0, 90.1, 5.0)),
    ...                      indexing="ij")
    >>> lam = np.radians(np.arange(-180.0, 180.0, 1.0))
    >>> rms = rms_pitch_error_from_moments(bias_moment_matrix(th, ph), np.ones(3), lam, g=1.0)
    >>> float(np.degrees(lam[np.argmin(rms)]))
    45.0
    """
    m = as_float_array(moments, "moments")
    if m.shape != (3, 3):
        raise ValueError(f"moments must have shape (3, 3), got {m.shape}")
    d = as_float_array(bias_m_s2, "bias_m_s2", last_dim=3)
    lam = angle_rad(preset_rad, "preset_rad")
    c, s = np.cos(lam), np.sin(lam)
    u = c * d[..., 1] - s * d[..., 2]
    v = s * d[..., 1] + c * d[..., 2]
    w = np.stack(np.broadcast_arrays(d[..., 0] + 0 * c, u, v), axis=-1)
    ms = np.einsum("...i,ij,...j->...", w, m, w)
    return np.sqrt(np.maximum(ms, 0.0)) / _gravity(g)


def warm_up() -> None:
    """Compile (or load from numba's cache) the compiled pass of :func:`max_abs_pitch_error_first_order`.

    For ``make venv`` (:func:`mtcal.filters.kernels.warm_up_all`), so that notebook 20 does not pay
    the compile time on a fresh clone.

    Examples
    --------
    >>> warm_up()
    """
    from mtcal.methods._large_angle_kernels import max_abs_first_order

    one = np.ones(1)
    max_abs_first_order(one, one, one, one, np.zeros((1, 3)), 9.8)
