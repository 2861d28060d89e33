"""Tests for mtcal.methods.constrained_fit: SO(4) and mounting-only installation-error calibration."""

import numpy as np
import pytest

from mtcal.methods import quaternion_lsq, constrained_fit
from mtcal.core import rotations


def _random_unit(rng, n=None):
    q = rng.normal(size=(4,) if n is None else (n, 4))
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def _small_rotation(rng, sigma_rad, n=None):
    return rotations.quat_from_rotvec(rng.normal(0.0, sigma_rad, (3,) if n is None else (n, 3)))


def _positions(angles_deg):
    a = np.radians(np.asarray(angles_deg, dtype=float))
    return rotations.quat_from_euler_zxy(a[:, 0], a[:, 1], a[:, 2])


PAPER6 = np.array([[8.0, 0.0, 0.0], [-8.0, 0.0, 0.0], [0.0, -12.0, 0.0],
                   [0.0, 23.0, 0.0], [0.0, 0.0, 90.0], [0.0, 0.0, -90.0]])   # a six-position layout


def _sensor(q_b, w, c):
    """q_s = w ⊗ q_b ⊗ c (reference offset w, mounting c)."""
    return rotations.quat_multiply(rotations.quat_multiply(w, q_b), c)


# --------------------------------------------------------------------------
# SO(4) algebra
# --------------------------------------------------------------------------
def test_associate_map_is_scaled_orthogonal_and_gives_outer_product(rng):
    t = constrained_fit._T
    np.testing.assert_allclose(t.T @ t, 4.0 * np.eye(16), atol=1e-14)
    p, r = _random_unit(rng), _random_unit(rng)
    np.testing.assert_allclose(constrained_fit.associate_matrix(constrained_fit.so4_from_quaternions(p, r)),
                               np.outer(p, r), atol=1e-14)


def test_factor_so4_round_trip_and_uniqueness_up_to_sign(rng):
    p, r = _random_unit(rng, 50), _random_unit(rng, 50)
    m = constrained_fit.so4_from_quaternions(p, r)
    np.testing.assert_allclose(np.swapaxes(m, -1, -2) @ m, np.broadcast_to(np.eye(4), m.shape), atol=1e-13)
    np.testing.assert_allclose(np.linalg.det(m), 1.0, atol=1e-13)
    pp, rr = constrained_fit.factor_so4(m)
    np.testing.assert_allclose(constrained_fit.so4_from_quaternions(pp, rr), m, atol=1e-12)
    sign = np.sign(np.sum(pp * p, axis=-1, keepdims=True))
    np.testing.assert_allclose(pp, sign * p, atol=1e-12)
    np.testing.assert_allclose(rr, sign * r, atol=1e-12)
    assert np.all(pp[:, 0] >= 0.0)


def test_factor_so4_rejects_improper_and_non_orthogonal():
    with pytest.raises(ValueError, match="SO\\(4\\)"):
        constrained_fit.factor_so4(np.diag([1.0, 1.0, -1.0, 1.0]))
    with pytest.raises(ValueError, match="SO\\(4\\)"):
        constrained_fit.factor_so4(np.diag([1.0, 1.01, 1.0, 1.0]))


def test_projection_svd_route_equals_associate_route_and_is_nearest(rng):
    x = rng.normal(size=(20, 4, 4))
    proj = constrained_fit.project_to_so4(x)
    # independent derivation: the nearest L(p)R(r) is the top singular pair of the associate matrix
    u, s, vt = np.linalg.svd(constrained_fit.associate_matrix(x))
    via_associate = constrained_fit.so4_from_quaternions(u[..., :, 0], vt[..., 0, :])
    np.testing.assert_allclose(proj.matrix, via_associate, atol=1e-10)
    np.testing.assert_allclose(constrained_fit.so4_from_quaternions(proj.p, proj.r), proj.matrix, atol=1e-10)
    np.testing.assert_allclose(np.linalg.det(proj.matrix), 1.0, atol=1e-12)
    np.testing.assert_allclose(proj.distance**2,
                               np.sum(x**2, axis=(-2, -1)) - 8.0 * s[..., 0] + 4.0, atol=1e-10)
    # no random rotation of quaternion space is closer
    others = constrained_fit.so4_from_quaternions(_random_unit(rng, 500), _random_unit(rng, 500))
    for xi, di in zip(x[:3], proj.distance[:3]):
        assert di <= np.min(np.linalg.norm(xi - others, axis=(-2, -1)))


def test_projection_of_so4_is_identity_and_improper_is_far():
    m = constrained_fit.so4_from_quaternions([0.6, 0.8, 0.0, 0.0], [0.8, 0.0, 0.0, 0.6])
    proj = constrained_fit.project_to_so4(m)
    np.testing.assert_allclose(proj.matrix, m, atol=1e-14)
    assert float(proj.distance) < 1e-12
    reflect = np.diag([1.0, 1.0, -1.0, 1.0])
    assert float(constrained_fit.project_to_so4(reflect).distance) == pytest.approx(2.0)
    assert float(constrained_fit.project_to_so4(reflect).determinant) == pytest.approx(-1.0)
    assert float(constrained_fit.distance_to_orthogonal(reflect)) == pytest.approx(0.0, abs=1e-14)
    assert float(constrained_fit.distance_to_orthogonal(np.diag([1, 1.004, 1, 1]))) == pytest.approx(0.004)


# --------------------------------------------------------------------------
# estimators: noise-free truth recovery
# --------------------------------------------------------------------------
@pytest.fixture
def truth(rng):
    c = _small_rotation(rng, np.radians(2.0))
    w = _small_rotation(rng, np.radians(2.0))
    return c, w


def test_noise_free_recovery_all_methods_paper_six(truth):
    c, w = truth
    q_b = _positions(PAPER6)
    # shared reference frame: all three recover R(c*)
    q_s = _sensor(q_b, np.array([1.0, 0, 0, 0]), c)
    target = rotations.right_matrix(rotations.quat_conjugate(c))
    np.testing.assert_allclose(quaternion_lsq.least_squares_error_matrix(q_s, q_b), target, atol=1e-9)
    np.testing.assert_allclose(constrained_fit.so4_error_matrix(q_s, q_b), target, atol=1e-9)
    np.testing.assert_allclose(constrained_fit.mounting_error_matrix(q_s, q_b), target, atol=1e-9)
    np.testing.assert_allclose(constrained_fit.fit_mounting(q_s, q_b).c, c, atol=1e-9)
    # with a reference offset: Eq 13 and SO(4) recover L(w*) R(c*); SO(4) factors give w*, c*
    q_s = _sensor(q_b, w, c)
    target = constrained_fit.so4_from_quaternions(rotations.quat_conjugate(w), rotations.quat_conjugate(c))
    np.testing.assert_allclose(quaternion_lsq.least_squares_error_matrix(q_s, q_b), target, atol=1e-9)
    fit = constrained_fit.fit_so4(q_s, q_b)
    np.testing.assert_allclose(fit.matrix, target, atol=1e-9)
    np.testing.assert_allclose(fit.p, rotations.quat_conjugate(w), atol=1e-9)
    np.testing.assert_allclose(fit.r, rotations.quat_conjugate(c), atol=1e-9)
    assert np.max(fit.residual_rad) < 1e-9


def test_batched_eq13_matches_member_by_member_on_noisy_data(rng, truth):
    c, _ = truth
    q_b = _positions(PAPER6)
    q_s = rotations.quat_multiply(_sensor(q_b, np.array([1.0, 0, 0, 0]), c),
                                  _small_rotation(rng, np.radians(0.05), 6))
    q_s2 = rotations.quat_multiply(q_s, _small_rotation(rng, np.radians(0.05), 6))
    stacked = quaternion_lsq.least_squares_error_matrix(np.stack([q_s, q_s2]), q_b)  # shared q_body
    assert stacked.shape == (2, 4, 4)
    np.testing.assert_allclose(stacked[0], quaternion_lsq.least_squares_error_matrix(q_s, q_b), atol=1e-12)
    np.testing.assert_allclose(stacked[1], quaternion_lsq.least_squares_error_matrix(q_s2, q_b), atol=1e-12)
    assert not np.allclose(stacked[0], stacked[1], atol=1e-6)


# --------------------------------------------------------------------------
# minimum number of positions
# --------------------------------------------------------------------------
def test_eq13_needs_four_positions_not_three(rng):
    """The paper's 'at least three positions' fails for Eq 13: A_s A_sᵀ has rank ≤ 3."""
    q_b = rotations.quat_normalize(_random_unit(rng, 3))
    q_s = rotations.quat_multiply(q_b, _small_rotation(rng, 0.01))
    with pytest.raises(ValueError, match="at least 4 positions"):
        quaternion_lsq.least_squares_error_matrix(q_s, q_b)
    # four random positions suffice
    q_b4 = _random_unit(rng, 4)
    c = _small_rotation(rng, 0.01)
    q_s4 = rotations.quat_multiply(q_b4, c)
    np.testing.assert_allclose(quaternion_lsq.least_squares_error_matrix(q_s4, q_b4),
                               rotations.right_matrix(rotations.quat_conjugate(c)), atol=1e-9)


def test_eq13_four_positions_spanning_three_directions_is_degenerate():
    q_b = _positions([[8, 0, 0], [-8, 0, 0], [0, -12, 0], [0, 23, 0]])  # span {e0, e1, e3}
    with pytest.raises(ValueError, match="degenerate"):
        quaternion_lsq.least_squares_error_matrix(q_b, q_b)
    out = quaternion_lsq.least_squares_error_matrix(q_b, q_b, on_degenerate="nan")
    assert np.all(np.isnan(out))
    # the SO(4) fit only needs rank 3: the same four positions recover the truth
    c = rotations.quat_from_rotvec([0.01, -0.02, 0.005])
    q_s = rotations.quat_multiply(q_b, c)
    np.testing.assert_allclose(constrained_fit.so4_error_matrix(q_s, q_b),
                               rotations.right_matrix(rotations.quat_conjugate(c)), atol=1e-9)


def test_so4_three_positions_suffice_two_do_not(rng, truth):
    c, w = truth
    q_b = _random_unit(rng, 3)
    q_s = _sensor(q_b, w, c)
    target = constrained_fit.so4_from_quaternions(rotations.quat_conjugate(w), rotations.quat_conjugate(c))
    np.testing.assert_allclose(constrained_fit.so4_error_matrix(q_s, q_b), target, atol=1e-9)
    # two positions: a second SO(4) matrix fits them exactly -> not identifiable
    q_b2, q_s2 = q_b[:2], q_s[:2]
    basis, _ = np.linalg.qr(np.concatenate([q_s2.T, rng.normal(size=(4, 2))], axis=1))
    rot = np.eye(4)
    rot[2:, 2:] = [[np.cos(0.3), -np.sin(0.3)], [np.sin(0.3), np.cos(0.3)]]
    other = target @ basis @ rot @ basis.T  # rotates only the plane orthogonal to both q_s
    np.testing.assert_allclose(other @ q_s2.T, target @ q_s2.T, atol=1e-12)
    assert np.linalg.norm(other - target) > 0.1
    with pytest.raises(ValueError, match="at least 3 positions"):
        constrained_fit.fit_so4(q_s2, q_b2)


def test_so4_degenerate_positions_about_one_axis():
    q_b = _positions([[8, 0, 0], [-8, 0, 0], [4, 0, 0]])  # span {e0, e3}
    with pytest.raises(ValueError, match="degenerate"):
        constrained_fit.fit_so4(q_b, q_b)
    fit = constrained_fit.fit_so4(q_b, q_b, on_degenerate="nan")
    assert np.all(np.isnan(fit.matrix)) and np.all(np.isnan(fit.p))


def test_mounting_one_position_suffices(rng, truth):
    c, _ = truth
    q_b = _random_unit(rng, 1)
    fit = constrained_fit.fit_mounting(rotations.quat_multiply(q_b, c), q_b)
    np.testing.assert_allclose(fit.c, c, atol=1e-12)
    with pytest.raises(ValueError, match="empty"):
        constrained_fit.fit_mounting(np.empty((0, 4)), np.empty((0, 4)))


def test_mounting_tie_is_degenerate():
    q_b = np.array([[1.0, 0, 0, 0], [1.0, 0, 0, 0]])
    q_s = np.array([[1.0, 0, 0, 0], [0.0, 1.0, 0, 0]])  # the two positions imply mountings 180° apart
    with pytest.raises(ValueError, match="degenerate"):
        constrained_fit.fit_mounting(q_s, q_b)


# --------------------------------------------------------------------------
# properties on noisy data
# --------------------------------------------------------------------------
def test_constrained_outputs_are_rotations_eq13_is_not(rng, truth):
    c, w = truth
    q_b = _positions(PAPER6)
    q_s = rotations.quat_multiply(_sensor(q_b, w, c), _small_rotation(rng, np.radians(0.05), 6))
    for m in (constrained_fit.so4_error_matrix(q_s, q_b), constrained_fit.mounting_error_matrix(q_s, q_b)):
        np.testing.assert_allclose(m.T @ m, np.eye(4), atol=1e-12)
        assert np.linalg.det(m) == pytest.approx(1.0, abs=1e-12)
    eq13 = quaternion_lsq.least_squares_error_matrix(q_s, q_b)
    assert float(constrained_fit.distance_to_orthogonal(eq13)) > 1e-5  # noise leaks in as scale/shear


def test_sign_flipped_inputs_give_same_result(rng, truth):
    c, w = truth
    q_b = _positions(PAPER6)
    q_s = rotations.quat_multiply(_sensor(q_b, w, c), _small_rotation(rng, np.radians(0.05), 6))
    flip_s = np.array([[-1.0], [1.0], [-1.0], [1.0], [1.0], [-1.0]])
    flip_b = np.array([[1.0], [-1.0], [-1.0], [1.0], [-1.0], [1.0]])
    for fn in (quaternion_lsq.least_squares_error_matrix, constrained_fit.so4_error_matrix,
               constrained_fit.mounting_error_matrix):
        np.testing.assert_allclose(fn(flip_s * q_s, flip_b * q_b), fn(q_s, q_b), atol=1e-12)


def test_apply_error_matrix_batched_matches_single(rng):
    m = constrained_fit.so4_from_quaternions(_small_rotation(rng, 0.01), _small_rotation(rng, 0.01))
    m2 = constrained_fit.so4_from_quaternions(_small_rotation(rng, 0.01), _small_rotation(rng, 0.01))
    q, q2 = _random_unit(rng, 7), _random_unit(rng, 7)
    both = quaternion_lsq.apply_error_matrix(np.stack([m, m2]), np.stack([q, q2]))
    np.testing.assert_allclose(both[0], quaternion_lsq.apply_error_matrix(m, q), atol=1e-14)
    np.testing.assert_allclose(both[1], quaternion_lsq.apply_error_matrix(m2, q2), atol=1e-14)
    out = quaternion_lsq.apply_error_matrix(np.stack([m, np.full((4, 4), np.nan)]), np.stack([q, q]))
    assert out.shape == (2, 7, 4) and np.all(np.isnan(out[1])) and np.all(np.isfinite(out[0]))


@pytest.mark.parametrize("fn", [quaternion_lsq.least_squares_error_matrix, constrained_fit.fit_so4,
                                constrained_fit.fit_mounting])
def test_input_errors(fn):
    q = _positions(PAPER6)
    bad = q.copy()
    bad[0, 0] = np.nan
    with pytest.raises(ValueError, match="finite"):
        fn(bad, q)
    with pytest.raises(ValueError, match="shape"):
        fn(q, q[:5])
    with pytest.raises(ValueError, match="shape"):
        fn(q[0], q[0])
    with pytest.raises(ValueError, match="unit quaternions"):
        fn(2.0 * q, q)
    with pytest.raises(ValueError, match="on_degenerate"):
        fn(q, q, on_degenerate="ignore")


def test_matrix_input_errors():
    with pytest.raises(ValueError, match="unit quaternions"):
        constrained_fit.so4_from_quaternions([1.0, 1.0, 0, 0], [1.0, 0, 0, 0])


# --------------------------------------------------------------------------
# Monte Carlo helpers
# --------------------------------------------------------------------------
def test_symmetric_layout_contains_paper_six():
    six = np.degrees(constrained_fit.symmetric_layout_rad(6, np.radians(PAPER6)))
    assert sorted(map(tuple, six.round(9))) == sorted(map(tuple, PAPER6))
    assert constrained_fit.symmetric_layout_rad(12, np.radians(PAPER6)).shape == (12, 3)
    with pytest.raises(ValueError, match="k must be <= 12"):
        constrained_fit.symmetric_layout_rad(13, np.radians(PAPER6))


def test_monte_carlo_noise_free_and_minimum_positions():
    sc0 = constrained_fit.CalibrationScenario(noise_sigma_rad=0.0, reference_offset=True, n_test=20)
    out = constrained_fit.simulate_calibration_errors(np.radians(PAPER6), sc0, 30,
                                                      np.random.default_rng(1))
    assert np.max(out["eq13"]) < 1e-9 and np.max(out["so4"]) < 1e-9
    assert np.min(out["mounting"]) > 1e-6  # heading offset biases the 3-DOF model
    layout3 = constrained_fit.symmetric_layout_rad(3, np.radians(PAPER6))
    out3 = constrained_fit.simulate_calibration_errors(layout3, sc0, 30, np.random.default_rng(1))
    assert np.all(np.isnan(out3["eq13"])) and np.max(out3["so4"]) < 1e-9
    sc_shared = constrained_fit.CalibrationScenario(noise_sigma_rad=0.0, n_test=20)
    layout1 = constrained_fit.symmetric_layout_rad(1, np.radians(PAPER6))
    out1 = constrained_fit.simulate_calibration_errors(layout1, sc_shared, 30, np.random.default_rng(1))
    assert np.all(np.isnan(out1["so4"])) and np.max(out1["mounting"]) < 1e-9


def test_monte_carlo_constrained_fits_beat_eq13_with_noise():
    sc = constrained_fit.CalibrationScenario(n_test=30)
    out = constrained_fit.simulate_calibration_errors(np.radians(PAPER6), sc, 400,
                                                      np.random.default_rng(7))
    med = {k: np.median(v) for k, v in out.items()}
    assert med["mounting"] < med["so4"] < med["eq13"]
    # mounting-fit error does not depend on where the positions are (noise is in the sensor frame)
    rand = constrained_fit.random_layout_rad(np.random.default_rng(3), 400, 6)
    out_r = constrained_fit.simulate_calibration_errors(rand, sc, 400, np.random.default_rng(7))
    np.testing.assert_allclose(out_r["mounting"], out["mounting"], rtol=1e-9)


def test_monte_carlo_input_errors():
    sc = constrained_fit.CalibrationScenario()
    with pytest.raises(ValueError, match="radians"):
        constrained_fit.simulate_calibration_errors(PAPER6, sc, 5,
                                                    np.random.default_rng(0))
    with pytest.raises(ValueError, match="layout_rad must have shape"):
        constrained_fit.simulate_calibration_errors(np.zeros((4, 6, 3)), sc, 5, np.random.default_rng(0))
    with pytest.raises(TypeError, match="scenario"):
        constrained_fit.simulate_calibration_errors(np.zeros((6, 3)), {}, 5, np.random.default_rng(0))
    with pytest.raises(ValueError, match="noise_sigma_rad"):
        constrained_fit.CalibrationScenario(noise_sigma_rad=-1.0)
    with pytest.raises(ValueError, match="envelope_deg"):
        constrained_fit.CalibrationScenario(envelope_deg=((1, 0), (0, 1), (0, 1)))


def test_monte_carlo_returns_matrices_eq13_not_orthogonal_with_noise():
    sc = constrained_fit.CalibrationScenario(n_test=10)
    out, mats = constrained_fit.simulate_calibration_errors(np.radians(PAPER6), sc, 50,
                                                            np.random.default_rng(2), return_matrices=True)
    assert mats["eq13"].shape == (50, 4, 4) and out["eq13"].shape == (50,)
    assert np.all(constrained_fit.distance_to_orthogonal(mats["eq13"]) > 1e-6)
    assert np.all(constrained_fit.distance_to_orthogonal(mats["so4"]) < 1e-12)


def test_project_to_so4_one_function_trusting_its_input():
    """No checked twin: project_to_so4 documents its preconditions (systems call it on an Eq 13 estimate they
    made from checked quaternions); on (..., 4, 4) stacks each matrix is projected as alone (to rounding)."""
    assert "project_to_so4_trusted" not in vars(constrained_fit)
    assert "Preconditions" in constrained_fit.project_to_so4.__doc__
    rng = np.random.default_rng(35)
    m = np.eye(4) + 0.05 * rng.standard_normal((6, 4, 4))
    stack = constrained_fit.project_to_so4(m)
    one = constrained_fit.project_to_so4(m[2])
    assert np.allclose(stack.matrix[2], one.matrix, atol=1e-14, rtol=0)
    assert np.all(np.abs(np.linalg.det(stack.matrix) - 1.0) < 1e-12)


def _angle_numpy(q1, q2):
    """The numpy expressions of constrained_fit._angle (reference for its compiled pass)."""
    d = rotations.hamilton(rotations.quat_conjugate(np.nan_to_num(q1)), q2)
    ang = 2.0 * np.arctan2(np.linalg.norm(d[..., 1:], axis=-1), np.abs(d[..., 0]))
    return np.where(np.any(np.isnan(q1), axis=-1), np.nan, ang)


def test_angle_compiled_pass_bit_identical():
    rng = np.random.default_rng(4)
    q1 = rng.normal(size=(40, 300, 4))
    q1 /= np.linalg.norm(q1, axis=-1, keepdims=True)
    q2 = rotations.hamilton(q1, rotations.quat_from_rotvec(rng.normal(0.0, 0.01, (40, 300, 3))))
    q1[3, 5, 2] = np.nan                 # NaN rows (degenerate fits) stay NaN
    q1[7] = np.nan
    q2[9] = q1[9]                        # zero angle
    assert q1.size >= constrained_fit._KERNEL_MIN_SIZE
    got = constrained_fit._angle(q1, q2)
    assert got.tobytes() == _angle_numpy(q1, q2).tobytes()
    assert np.isnan(got[7]).all() and np.isnan(got[3, 5]) and not np.isnan(got[3, 4])


def test_simulate_calibration_errors_methods_subset_and_matrices_only():
    sc = constrained_fit.CalibrationScenario(n_test=10)
    lay = np.radians([[8, 0, 0], [-8, 0, 0], [0, -12, 0], [0, 23, 0], [0, 0, 90], [0, 0, -90]])
    from mtcal.core.rng import stream_rng
    err, mats = constrained_fit.simulate_calibration_errors(lay, sc, 50, stream_rng(1, 2), return_matrices=True)
    e1, m1 = constrained_fit.simulate_calibration_errors(lay, sc, 50, stream_rng(1, 2), return_matrices=True,
                                                         methods=("eq13",))
    assert list(m1) == ["eq13"] and m1["eq13"].tobytes() == mats["eq13"].tobytes()
    assert e1["eq13"].tobytes() == err["eq13"].tobytes()
    e2, m2 = constrained_fit.simulate_calibration_errors(lay, sc, 50, stream_rng(1, 2), return_matrices=True,
                                                         methods=("eq13",), errors=False)
    assert e2 == {} and m2["eq13"].tobytes() == mats["eq13"].tobytes()
    with pytest.raises(ValueError, match="methods must be a non-empty subset"):
        constrained_fit.simulate_calibration_errors(lay, sc, 5, stream_rng(1, 2), methods=("qmethod",))
    with pytest.raises(ValueError, match="errors=False needs return_matrices=True"):
        constrained_fit.simulate_calibration_errors(lay, sc, 5, stream_rng(1, 2), errors=False)
