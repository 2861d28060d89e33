import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mtcal.core import rotations as r


@pytest.fixture
def angles(rng):
    n = 200
    return np.stack([rng.uniform(-np.pi, np.pi, n), rng.uniform(-1.5, 1.5, n),
                     rng.uniform(-np.pi, np.pi, n)], axis=1)


def test_eq9_equals_scipy_zxy(angles):
    q = r.quat_from_euler_zxy(angles[:, 0], angles[:, 1], angles[:, 2])
    ref = Rotation.from_euler("ZXY", angles).as_quat(scalar_first=True)
    np.testing.assert_allclose(r.align_signs(q), r.align_signs(ref), atol=1e-14)


def test_eq9_equals_printed_component_formulas():
    psi, theta, gamma = 0.3, -0.7, 1.1
    c, s = np.cos, np.sin
    printed = [c(theta / 2) * c(psi / 2) * c(gamma / 2) - s(theta / 2) * s(psi / 2) * s(gamma / 2),
               s(theta / 2) * c(psi / 2) * c(gamma / 2) - c(theta / 2) * s(psi / 2) * s(gamma / 2),
               s(theta / 2) * s(psi / 2) * c(gamma / 2) + c(theta / 2) * c(psi / 2) * s(gamma / 2),
               c(theta / 2) * s(psi / 2) * c(gamma / 2) + s(theta / 2) * c(psi / 2) * s(gamma / 2)]
    np.testing.assert_allclose(r.quat_from_euler_zxy(psi, theta, gamma), printed, atol=1e-15)


def test_eq8_inverts_eq9(angles):
    q = r.quat_from_euler_zxy(angles[:, 0], angles[:, 1], angles[:, 2])
    np.testing.assert_allclose(r.euler_zxy_from_quat(q), angles, atol=1e-12)
    np.testing.assert_allclose(r.euler_zxy_from_quat(-q), angles, atol=1e-12)  # sign-invariant


def test_eq8_matches_scipy_as_euler(angles):
    q = r.quat_from_euler_zxy(angles[:, 0], angles[:, 1], angles[:, 2])
    ref = Rotation.from_quat(q, scalar_first=True).as_euler("ZXY")
    np.testing.assert_allclose(r.euler_zxy_from_quat(q), ref, atol=1e-12)


def test_hamilton_product_matches_scipy(rng):
    p = r.quat_normalize(rng.normal(size=(50, 4)))
    q = r.quat_normalize(rng.normal(size=(50, 4)))
    ref = (Rotation.from_quat(p, scalar_first=True) * Rotation.from_quat(q, scalar_first=True)).as_quat(
        scalar_first=True)
    np.testing.assert_allclose(r.align_signs(r.quat_multiply(p, q)), r.align_signs(ref), atol=1e-14)


def test_left_right_matrices(rng):
    p = rng.normal(size=(10, 4))
    q = rng.normal(size=(10, 4))
    pq = r.quat_multiply(p, q)
    np.testing.assert_allclose(np.einsum("nij,nj->ni", r.left_matrix(p), q), pq, atol=1e-14)
    np.testing.assert_allclose(np.einsum("nij,nj->ni", r.right_matrix(q), p), pq, atol=1e-14)


def test_conjugate_is_inverse(rng):
    q = r.quat_normalize(rng.normal(size=(5, 4)))
    np.testing.assert_allclose(r.quat_multiply(q, r.quat_conjugate(q)), np.tile([1.0, 0, 0, 0], (5, 1)),
                               atol=1e-15)


def test_align_signs_and_continuity(rng):
    q = r.quat_normalize(rng.normal(size=(100, 4)))
    assert np.all(r.align_signs(q)[:, 0] >= 0)
    smooth = r.quat_from_rotvec(np.linspace(0, 1, 100)[:, None] * np.array([0.0, 0.0, 6.0]))
    flipped = smooth * np.where(rng.random(100) < 0.5, -1.0, 1.0)[:, None]
    cont = r.make_continuous(flipped, axis=0)
    assert np.all(np.sum(cont[1:] * cont[:-1], axis=1) > 0)
    np.testing.assert_allclose(cont * np.sign(cont[:1, 0]), smooth * np.sign(smooth[:1, 0]), atol=1e-15)


def test_rotvec_round_trip(rng):
    v = rng.normal(size=(100, 3))
    v *= (rng.uniform(0, 3.0, 100) / np.linalg.norm(v, axis=1))[:, None]
    np.testing.assert_allclose(r.rotvec_from_quat(r.quat_from_rotvec(v)), v, atol=1e-12)
    tiny = np.array([[1e-12, -2e-12, 3e-12]])
    np.testing.assert_allclose(r.rotvec_from_quat(r.quat_from_rotvec(tiny)), tiny, rtol=1e-9)
    ref = Rotation.from_rotvec(v).as_quat(scalar_first=True)
    np.testing.assert_allclose(r.align_signs(r.quat_from_rotvec(v)), r.align_signs(ref), atol=1e-14)


def test_matrix_round_trip(angles):
    q = r.align_signs(r.quat_from_euler_zxy(angles[:, 0], angles[:, 1], angles[:, 2]))
    np.testing.assert_allclose(r.quat_from_matrix(r.quat_to_matrix(q)), q, atol=1e-12)


def test_quat_angle_between_is_precise_near_zero():
    q = r.quat_from_rotvec([0.0, 0.0, 1e-10])
    assert r.quat_angle_between([1.0, 0, 0, 0], q) == pytest.approx(1e-10, rel=1e-6)


def test_eq1_equals_scipy_zyx():
    a = np.array([0.02, -0.03, 0.01])
    ref = Rotation.from_euler("ZYX", a).as_matrix()
    np.testing.assert_allclose(r.installation_matrix(*a), ref, atol=1e-15)


@pytest.mark.parametrize("scale", [1e-2, 1e-3])
def test_eq1_small_angle_is_first_order(scale):
    a = scale * np.array([1.0, -2.0, 1.5])
    diff = np.max(np.abs(r.installation_matrix(*a) - r.installation_matrix_small_angle(*a)))
    assert diff < 5 * scale**2


def test_eq4_corrected_matches_eq1_to_second_order():
    """Δ = s − C_s^b s (Eq 3) with the exact Eq 1 matrix vs the corrected Eq 4."""
    s = np.radians([8.0, -12.0, 30.0])
    for scale in (1e-2, 1e-3):
        a = scale * np.array([1.0, -0.5, 0.7])
        exact = s - r.installation_matrix(*a).T @ s
        approx = r.coupling_error_eq4(a, s)
        assert np.max(np.abs(exact - approx)) < 2 * scale**2 * np.max(np.abs(s))
        np.testing.assert_allclose(r.coupling_error_eq4(a, s, printed=True), -approx)
        assert np.max(np.abs(exact + approx)) > 0.5 * np.max(np.abs(exact))  # printed sign is wrong


def test_zyx_dcm_and_specific_force():
    theta, phi = 0.4, -0.3
    c_nb = r.dcm_zyx(0.2, theta, phi)
    np.testing.assert_allclose(c_nb @ c_nb.T, np.eye(3), atol=1e-15)
    f = r.specific_force_zyx(theta, phi)
    np.testing.assert_allclose(f, c_nb @ np.array([0.0, 0.0, 1.0]), atol=1e-15)
    np.testing.assert_allclose(r.pitch_roll_from_specific_force(f), [theta, phi], atol=1e-15)
    np.testing.assert_allclose(r.specific_force_zyx(0.0, 0.0, g=9.8), [0, 0, 9.8])


def test_axis_angle_matrix_matches_scipy(rng):
    v = rng.normal(size=3)
    v /= np.linalg.norm(v)
    th = np.linspace(-np.pi, np.pi, 7)
    ref = Rotation.from_rotvec(th[:, None] * v).as_matrix()
    np.testing.assert_allclose(r.axis_angle_matrix(th, v), ref, atol=1e-14)


def test_wrap_angle():
    np.testing.assert_allclose(r.wrap_angle([np.pi, -np.pi, 3 * np.pi / 2, 0.1]),
                               [-np.pi, -np.pi, -np.pi / 2, 0.1])


@pytest.mark.parametrize("func,args,match", [
    (r.quat_from_euler_zxy, (0.1, np.nan, 0.0), "pitch must be finite"),
    (r.quat_from_euler_zxy, (0.1, 45.0, 0.0), "degrees passed as radians"),
    (r.euler_zxy_from_quat, ([1.0, 0.1, 0, 0],), "unit quaternions"),
    (r.euler_zxy_from_quat, ([1.0, 0, 0],), "last dimension 4"),
    (r.quat_multiply, ("abc", [1.0, 0, 0, 0]), "numeric array"),
    (r.axis_angle_matrix, (0.1, [1.0, 1.0, 0.0]), "unit vector"),
    (r.quat_normalize, ([0.0, 0, 0, 0],), "zero-norm"),
    (r.make_continuous, ([[1.0, 0, 0, 0]], -1), "axis must index time"),
])
def test_bad_input_raises(func, args, match):
    with pytest.raises((ValueError, TypeError), match=match):
        func(*args)
