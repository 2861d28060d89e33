import numpy as np
import pytest

from mtcal.methods import quaternion_lsq
from mtcal.core import rotations

SIX_POSITIONS_DEG = np.array([[8, 0, 0], [-8, 0, 0], [0, -12, 0], [0, 23, 0], [0, 0, 90], [0, 0, -90]], float)


def body_quats(angles_deg):
    a = np.radians(angles_deg)
    return rotations.quat_from_euler_zxy(a[:, 0], a[:, 1], a[:, 2])


@pytest.fixture
def pairs():
    q_bs = rotations.quat_from_euler_zxy(0.01, -0.02, 0.005)
    q_b = body_quats(SIX_POSITIONS_DEG)
    return rotations.quat_multiply(q_b, q_bs), q_b, q_bs


def test_noise_free_recovery(pairs, rng):
    q_s, q_b, q_bs = pairs
    q_mat = quaternion_lsq.least_squares_error_matrix(q_s, q_b)
    np.testing.assert_allclose(q_mat, rotations.right_matrix(rotations.quat_conjugate(q_bs)), atol=1e-9)
    test_b = body_quats(np.column_stack([rng.uniform(-8, 8, 50), rng.uniform(-12, 23, 50),
                                         rng.uniform(-90, 90, 50)]))
    test_s = rotations.quat_multiply(test_b, q_bs)
    est = rotations.euler_zxy_from_quat(quaternion_lsq.apply_error_matrix(q_mat, test_s))
    np.testing.assert_allclose(est, rotations.euler_zxy_from_quat(test_b), atol=1e-9)


def test_sign_flips_do_not_change_solution(pairs):
    q_s, q_b, _ = pairs
    ref = quaternion_lsq.least_squares_error_matrix(q_s, q_b)
    flip = np.array([1, -1, 1, -1, -1, 1.0])[:, None]
    np.testing.assert_allclose(quaternion_lsq.least_squares_error_matrix(q_s * flip, q_b), ref, atol=1e-12)
    np.testing.assert_allclose(quaternion_lsq.least_squares_error_matrix(q_s, -q_b), ref, atol=1e-12)


@pytest.mark.parametrize("deg", [30.0, 100.0, 150.0, 179.0])
def test_an_exact_rotation_of_quaternion_space_is_recovered_whatever_its_size(deg):
    """q_b = L(p) R(r) q_s with both factors ``deg`` about random axes, random signs on both sides: Eq 13 on
    consistent pairs gives ±L(p)R(r) exactly. The dot rule alone (dot(q_b, q_s) >= 0) fails here beyond ~90°:
    that product changes sign from one position to the next; the pairs' inner products fix the signs."""
    rng = np.random.default_rng(int(deg))

    def turn():                                    # ``deg`` about a random axis
        v = rng.normal(size=3)
        return rotations.quat_from_rotvec(v / np.linalg.norm(v) * np.radians(deg))
    for _ in range(20):
        m = rotations.left_matrix(turn()) @ rotations.right_matrix(turn())
        q_s = rotations.quat_normalize(rng.normal(size=(6, 4)))
        q_b = (q_s @ m.T) * rng.choice([-1.0, 1.0], size=(6, 1))
        q_hat = quaternion_lsq.least_squares_error_matrix(q_s * rng.choice([-1.0, 1.0], size=(6, 1)), q_b)
        assert min(np.abs(q_hat - m).max(), np.abs(q_hat + m).max()) < 1e-9


def test_the_pair_signs_change_nothing_where_the_dot_rule_is_consistent(pairs):
    """Small installation errors (every pair within 90°) with noise: the pairs come back as the dot rule made
    them, bit for bit (the calibrations of the studies keep their numbers); positions whose quaternions are
    nearly orthogonal (roll ±90°) give noise-sized inner products, never a contradiction."""
    q_s, q_b, _ = pairs
    rng = np.random.default_rng(3)
    noisy = rotations.quat_normalize(q_s + rng.normal(scale=1e-4, size=(200, 6, 4)))
    s_al, b_al = quaternion_lsq.align_pairs(noisy, q_b)
    dot_s = np.where(noisy[..., :1] < 0.0, -noisy, noisy)
    dot_b = np.where(np.sum(q_b * dot_s, axis=-1, keepdims=True) < 0.0, -q_b, np.broadcast_to(q_b, dot_s.shape))
    assert s_al.tobytes() == dot_s.tobytes() and b_al.tobytes() == dot_b.tobytes()
    assert quaternion_lsq._consistent_signs(dot_s, dot_b) is None


def test_rank_deficient_positions_raise():
    q_b = body_quats(np.array([[0, 0, a] for a in (-90, -30, 30, 90)], float))  # roll only
    with pytest.raises(ValueError, match="condition number"):
        quaternion_lsq.least_squares_error_matrix(q_b, q_b)
    three = body_quats(SIX_POSITIONS_DEG[[0, 2, 4]])
    with pytest.raises(ValueError, match="at least 4 positions"):  # the paper's "3" is not enough (rank <= 3)
        quaternion_lsq.least_squares_error_matrix(three, three)
    with pytest.raises(ValueError, match="shape"):
        quaternion_lsq.least_squares_error_matrix(q_b, q_b[:3])
    with pytest.raises(ValueError, match="q_matrix must be a finite 4x4"):
        quaternion_lsq.apply_error_matrix(np.eye(3), q_b)


@pytest.mark.parametrize("stack", [False, True])
def test_apply_compiled_normalisation_is_bit_identical(stack):
    rng = np.random.default_rng(7)
    shape = (2, 3000, 4) if stack else (3000, 4)
    q = rng.normal(size=shape)
    q[..., ::5, 0] = -0.0                                   # q0 = -0: the sign rule keeps q
    q /= np.linalg.norm(q, axis=-1, keepdims=True)
    mat = np.eye(4) + 0.01 * rng.normal(size=(2, 4, 4) if stack else (4, 4))
    ref_q = np.where(np.sum(q * [1.0, 0.0, 0.0, 0.0], axis=-1, keepdims=True) < 0.0, -q, q)   # the _flip rule
    ref = ref_q @ np.swapaxes(mat, -1, -2)
    ref = ref / np.linalg.norm(ref, axis=-1, keepdims=True)
    assert quaternion_lsq.apply_error_matrix(mat, q).tobytes() == ref.tobytes()
    nan_mat = mat.copy()
    nan_mat[..., 0, 0] = np.nan
    assert np.isnan(quaternion_lsq.apply_error_matrix(nan_mat, q)).all()
    assert np.isnan(quaternion_lsq.apply_error_matrix(np.zeros_like(mat), q)).all()   # 0 / 0 rows, as numpy


def test_apply_error_matrix_never_aliases_or_modifies_its_input():
    q = -body_quats(SIX_POSITIONS_DEG)              # q0 < 0: the sign rule flips every row
    before = q.copy()
    for normalize in (True, False):
        out = quaternion_lsq.apply_error_matrix(np.eye(4), q, normalize=normalize)
        assert not np.shares_memory(out, q) and np.array_equal(q, before)
        assert np.allclose(out, -before)


def test_the_trusted_eq10_is_cores_map_and_equals_the_checked_one():
    """Eq 10 lives once, in core (:func:`rotations.apply_quat_matrix_trusted`); ``_apply`` (the methods'
    and systems' trusted entry) is that function, and ``apply_error_matrix`` checks, then calls it."""
    assert quaternion_lsq._apply is rotations.apply_quat_matrix_trusted
    rng = np.random.default_rng(8)
    q = rng.normal(size=(2, 3000, 4))
    q /= np.linalg.norm(q, axis=-1, keepdims=True)
    mat = np.eye(4) + 0.01 * rng.normal(size=(2, 4, 4))
    for normalize in (True, False):
        assert (rotations.apply_quat_matrix_trusted(mat, q, normalize).tobytes()
                == quaternion_lsq.apply_error_matrix(mat, q, normalize=normalize).tobytes())
