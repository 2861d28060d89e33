import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mtcal.core import rotations


@pytest.fixture
def angles(rng):
    n = 200
    return np.stack([rng.uniform(-np.pi, np.pi, n), rng.uniform(-1.5, 1.5, n),
                     rng.uniform(-np.pi, np.pi, n)], axis=1)


def test_eq9_equals_scipy_zxy(angles):
    q = rotations.quat_from_euler_zxy(angles[:, 0], angles[:, 1], angles[:, 2])
    ref = Rotation.from_euler("ZXY", angles).as_quat(scalar_first=True)
    np.testing.assert_allclose(rotations.align_signs(q), rotations.align_signs(ref), atol=1e-14)


def test_eq9_equals_printed_component_formulas():
    psi, theta, gamma = 0.3, -0.7, 1.1
    c, s = np.cos, np.sin
    printed = [c(theta / 2) * c(psi / 2) * c(gamma / 2) - s(theta / 2) * s(psi / 2) * s(gamma / 2),
               s(theta / 2) * c(psi / 2) * c(gamma / 2) - c(theta / 2) * s(psi / 2) * s(gamma / 2),
               s(theta / 2) * s(psi / 2) * c(gamma / 2) + c(theta / 2) * c(psi / 2) * s(gamma / 2),
               c(theta / 2) * s(psi / 2) * c(gamma / 2) + s(theta / 2) * c(psi / 2) * s(gamma / 2)]
    np.testing.assert_allclose(rotations.quat_from_euler_zxy(psi, theta, gamma), printed, atol=1e-15)


def test_eq8_inverts_eq9(angles):
    q = rotations.quat_from_euler_zxy(angles[:, 0], angles[:, 1], angles[:, 2])
    np.testing.assert_allclose(rotations.euler_zxy_from_quat(q), angles, atol=1e-12)
    np.testing.assert_allclose(rotations.euler_zxy_from_quat(-q), angles, atol=1e-12)  # sign-invariant


def test_eq8_matches_scipy_as_euler(angles):
    q = rotations.quat_from_euler_zxy(angles[:, 0], angles[:, 1], angles[:, 2])
    ref = Rotation.from_quat(q, scalar_first=True).as_euler("ZXY")
    np.testing.assert_allclose(rotations.euler_zxy_from_quat(q), ref, atol=1e-12)


def test_hamilton_product_matches_scipy(rng):
    p = rotations.quat_normalize(rng.normal(size=(50, 4)))
    q = rotations.quat_normalize(rng.normal(size=(50, 4)))
    ref = (Rotation.from_quat(p, scalar_first=True) * Rotation.from_quat(q, scalar_first=True)).as_quat(
        scalar_first=True)
    np.testing.assert_allclose(rotations.align_signs(rotations.quat_multiply(p, q)), rotations.align_signs(ref),
                               atol=1e-14)


def test_left_right_matrices(rng):
    p = rng.normal(size=(10, 4))
    q = rng.normal(size=(10, 4))
    pq = rotations.quat_multiply(p, q)
    np.testing.assert_allclose(np.einsum("nij,nj->ni", rotations.left_matrix(p), q), pq, atol=1e-14)
    np.testing.assert_allclose(np.einsum("nij,nj->ni", rotations.right_matrix(q), p), pq, atol=1e-14)


def test_conjugate_is_inverse(rng):
    q = rotations.quat_normalize(rng.normal(size=(5, 4)))
    np.testing.assert_allclose(rotations.quat_multiply(q, rotations.quat_conjugate(q)), np.tile([1.0, 0, 0, 0], (5, 1)),
                               atol=1e-15)


def test_align_signs_and_continuity(rng):
    q = rotations.quat_normalize(rng.normal(size=(100, 4)))
    assert np.all(rotations.align_signs(q)[:, 0] >= 0)
    smooth = rotations.quat_from_rotvec(np.linspace(0, 1, 100)[:, None] * np.array([0.0, 0.0, 6.0]))
    flipped = smooth * np.where(rng.random(100) < 0.5, -1.0, 1.0)[:, None]
    cont = rotations.make_continuous(flipped, axis=0)
    assert np.all(np.sum(cont[1:] * cont[:-1], axis=1) > 0)
    np.testing.assert_allclose(cont * np.sign(cont[:1, 0]), smooth * np.sign(smooth[:1, 0]), atol=1e-15)


def test_rotvec_round_trip(rng):
    v = rng.normal(size=(100, 3))
    v *= (rng.uniform(0, 3.0, 100) / np.linalg.norm(v, axis=1))[:, None]
    np.testing.assert_allclose(rotations.rotvec_from_quat(rotations.quat_from_rotvec(v)), v, atol=1e-12)
    tiny = np.array([[1e-12, -2e-12, 3e-12]])
    np.testing.assert_allclose(rotations.rotvec_from_quat(rotations.quat_from_rotvec(tiny)), tiny, rtol=1e-9)
    ref = Rotation.from_rotvec(v).as_quat(scalar_first=True)
    np.testing.assert_allclose(rotations.align_signs(rotations.quat_from_rotvec(v)), rotations.align_signs(ref),
                               atol=1e-14)


def test_matrix_round_trip(angles):
    q = rotations.align_signs(rotations.quat_from_euler_zxy(angles[:, 0], angles[:, 1], angles[:, 2]))
    np.testing.assert_allclose(rotations.quat_from_matrix(rotations.quat_to_matrix(q)), q, atol=1e-12)


def test_quat_angle_between_is_precise_near_zero():
    q = rotations.quat_from_rotvec([0.0, 0.0, 1e-10])
    assert rotations.quat_angle_between([1.0, 0, 0, 0], q) == pytest.approx(1e-10, rel=1e-6)


def test_eq1_equals_scipy_zyx():
    a = np.array([0.02, -0.03, 0.01])
    ref = Rotation.from_euler("ZYX", a).as_matrix()
    np.testing.assert_allclose(rotations.installation_matrix(*a), ref, atol=1e-15)


@pytest.mark.parametrize("scale", [1e-2, 1e-3])
def test_eq1_small_angle_is_first_order(scale):
    a = scale * np.array([1.0, -2.0, 1.5])
    diff = np.max(np.abs(rotations.installation_matrix(*a) - rotations.installation_matrix_small_angle(*a)))
    assert diff < 5 * scale**2


def test_eq4_corrected_matches_eq1_to_second_order():
    """Δ = s − C_s^b s (Eq 3) with the exact Eq 1 matrix vs the corrected Eq 4."""
    s = np.radians([8.0, -12.0, 30.0])
    for scale in (1e-2, 1e-3):
        a = scale * np.array([1.0, -0.5, 0.7])
        exact = s - rotations.installation_matrix(*a).T @ s
        approx = rotations.coupling_error_eq4(a, s)
        assert np.max(np.abs(exact - approx)) < 2 * scale**2 * np.max(np.abs(s))
        np.testing.assert_allclose(rotations.coupling_error_eq4(a, s, printed=True), -approx)
        assert np.max(np.abs(exact + approx)) > 0.5 * np.max(np.abs(exact))  # printed sign is wrong


def test_zyx_dcm_and_specific_force():
    theta, phi = 0.4, -0.3
    c_nb = rotations.dcm_zyx(0.2, theta, phi)
    np.testing.assert_allclose(c_nb @ c_nb.T, np.eye(3), atol=1e-15)
    f = rotations.specific_force_zyx(theta, phi)
    np.testing.assert_allclose(f, c_nb @ np.array([0.0, 0.0, 1.0]), atol=1e-15)
    np.testing.assert_allclose(rotations.pitch_roll_from_specific_force(f), [theta, phi], atol=1e-15)
    np.testing.assert_allclose(rotations.specific_force_zyx(0.0, 0.0, g=9.8), [0, 0, 9.8])


def test_axis_angle_matrix_matches_scipy(rng):
    v = rng.normal(size=3)
    v /= np.linalg.norm(v)
    th = np.linspace(-np.pi, np.pi, 7)
    ref = Rotation.from_rotvec(th[:, None] * v).as_matrix()
    np.testing.assert_allclose(rotations.axis_angle_matrix(th, v), ref, atol=1e-14)


def test_wrap_angle():
    np.testing.assert_allclose(rotations.wrap_angle([np.pi, -np.pi, 3 * np.pi / 2, 0.1]),
                               [-np.pi, -np.pi, -np.pi / 2, 0.1])


@pytest.mark.parametrize("func,args,match", [
    (rotations.quat_from_euler_zxy, (0.1, np.nan, 0.0), "pitch must be finite"),
    (rotations.quat_from_euler_zxy, (0.1, 45.0, 0.0), "degrees passed as radians"),
    (rotations.euler_zxy_from_quat, ([1.0, 0.1, 0, 0],), "unit quaternions"),
    (rotations.euler_zxy_from_quat, ([1.0, 0, 0],), "last dimension 4"),
    (rotations.quat_multiply, ("abc", [1.0, 0, 0, 0]), "numeric array"),
    (rotations.axis_angle_matrix, (0.1, [1.0, 1.0, 0.0]), "unit vector"),
    (rotations.quat_normalize, ([0.0, 0, 0, 0],), "zero-norm"),
    (rotations.make_continuous, ([[1.0, 0, 0, 0]], -1), "axis must index time"),
])
def test_bad_input_raises(func, args, match):
    with pytest.raises((ValueError, TypeError), match=match):
        func(*args)


# ---------------------------------------------------------------- gimbal lock (Eq 8 at pitch ±90°)
from hypothesis import given, settings, strategies as st  # noqa: E402


def _round_trip_error(q):
    e = rotations.euler_zxy_from_quat(q)
    back = rotations.quat_from_euler_zxy(e[..., 0], e[..., 1], e[..., 2])
    return rotations.quat_angle_between(back, q)


def test_euler_exact_at_lock_example():
    e = rotations.euler_zxy_from_quat([0.5, 0.5, 0.5, 0.5])
    np.testing.assert_allclose(np.degrees(e), [90.0, 90.0, 0.0], atol=1e-12)
    assert _round_trip_error(np.array([0.5, 0.5, 0.5, 0.5])) < 1e-14


@pytest.mark.parametrize("pitch_deg", [90.0, -90.0])
def test_euler_lock_convention_roll_zero(pitch_deg):
    yaw, roll = np.radians(30.0), np.radians(-50.0)
    q = rotations.quat_from_euler_zxy(yaw, np.radians(pitch_deg), roll)
    e = rotations.euler_zxy_from_quat(q)
    assert abs(e[2]) < 1e-12  # roll 0, rotation about the vertical goes to yaw
    expected_yaw = yaw + roll if pitch_deg > 0 else yaw - roll
    assert abs(rotations.wrap_angle(e[0] - expected_yaw)) < 1e-12
    assert _round_trip_error(q) < 1e-12


_angle = st.floats(-np.pi, np.pi, allow_nan=False)
_offset = st.sampled_from([0.0, 1e-14, -1e-14, 1e-10, 1e-7, 1e-5, 1e-3, 0.01, 0.3, 1.0, 1.5])


@settings(max_examples=400, deadline=None)
@given(yaw=_angle, roll=_angle, offset=_offset, sign=st.sampled_from([1.0, -1.0]), flip=st.booleans())
def test_euler_round_trip_whole_sphere_including_lock(yaw, roll, offset, sign, flip):
    pitch = sign * (np.pi / 2 - abs(offset))
    q = rotations.quat_from_euler_zxy(yaw, pitch, roll)
    q = q / np.linalg.norm(q)
    if flip:
        q = -q
    assert _round_trip_error(q) < 1e-12
    np.testing.assert_allclose(rotations.euler_zxy_unchecked(q[None])[0], rotations.euler_zxy_from_quat(q),
                               rtol=0, atol=0)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.floats(-1, 1, allow_nan=False), min_size=4, max_size=4).filter(
    lambda v: np.linalg.norm(v) > 1e-3))
def test_euler_round_trip_random_quaternions(v):
    q = np.asarray(v) / np.linalg.norm(v)
    assert _round_trip_error(q) < 1e-12


def test_euler_bit_identical_away_from_lock(rng):
    """Away from lock the result is the printed Eq 8 formula, bit for bit."""
    q = rng.normal(size=(5000, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    q0, q1, q2, q3 = q.T
    sp = np.clip(2 * (q2 * q3 + q0 * q1), -1, 1)
    keep = np.sqrt(1 - sp**2) >= rotations.GIMBAL_LOCK_COS
    printed = np.stack([np.arctan2(-2 * (q1 * q2 - q0 * q3), q0**2 - q1**2 + q2**2 - q3**2),
                        np.arcsin(sp),
                        np.arctan2(-2 * (q1 * q3 - q0 * q2), q0**2 - q1**2 - q2**2 + q3**2)], axis=-1)
    assert np.array_equal(rotations.euler_zxy_from_quat(q)[keep], printed[keep])


# ---------------------------------------------------------------- inverse of Eq 1
@settings(max_examples=100, deadline=None)
@given(st.lists(st.floats(-1.5, 1.5, allow_nan=False), min_size=3, max_size=3))
def test_installation_angles_invert_eq1(a):
    a = np.asarray(a)
    np.testing.assert_allclose(rotations.installation_angles(rotations.installation_matrix(*a)), a, atol=1e-12)
    np.testing.assert_allclose(rotations.installation_angles_from_mount(rotations.mount_quaternion(a)), a, atol=1e-12)
    np.testing.assert_allclose(rotations.installation_angles_from_mount(-rotations.mount_quaternion(a)), a, atol=1e-12)


def test_installation_angles_rejects_non_rotation():
    with pytest.raises(ValueError, match="rotation matrix"):
        rotations.installation_angles(np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(ValueError, match=r"shape \(\.\.\., 3, 3\)"):
        rotations.installation_angles(np.eye(4))


# ---------------------------------------------------------------- compiled loops (issue #24)
def _unit_quats(rng, n):
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    q[:8] = [1, 0, 0, 0]
    q[8:16] = [-1, 0, 0, 0]
    q[16:24] = [0.5, 0.5, 0.5, 0.5]          # gimbal lock
    q[24:32] = [0.5, -0.5, 0.5, -0.5]
    q[32] = [-0.0, 1.0, 0.0, 0.0]
    q[40:48] = [np.cos(1e-13), np.sin(1e-13), 0.0, 0.0]   # tiny angle
    return q


def _numpy_reference(monkeypatch, fn, *args):
    with monkeypatch.context() as m:
        m.setattr(rotations, "_KERNEL_MIN_ROWS", 10 ** 12)
        return fn(*args)


@pytest.mark.parametrize("case", ["hamilton", "hamilton_broadcast", "hamilton_strided", "normalize", "continuous",
                                  "continuous_axis0", "from_rotvec", "to_rotvec", "euler", "euler_view",
                                  "from_euler", "to_matrix", "relative", "conjugate", "conjugate_strided",
                                  "multiply"])
def test_compiled_loops_equal_the_numpy_expressions_bit_for_bit(case, rng, monkeypatch):
    n = 3 * rotations._KERNEL_MIN_ROWS
    q, p = _unit_quats(rng, n), _unit_quats(rng, n)[::-1].copy()
    q3 = q.reshape(3, -1, 4)
    v = rng.normal(size=(n, 3)) * np.exp(rng.uniform(-25, 1, (n, 1)))
    v[:4] = 0.0
    a = rng.uniform(-1.5, 1.5, (3, n))
    fn, args = {
        "hamilton": (rotations.hamilton, (p, q)),
        "hamilton_broadcast": (rotations.hamilton, (p.reshape(3, -1, 4)[:, :1], q3)),
        "hamilton_strided": (rotations.hamilton, (p[::2], q[1::2])),
        "normalize": (rotations.quat_normalize, (3.3 * q,)),
        "continuous": (rotations.make_continuous, (q * np.sign(rng.normal(size=(n, 1))), 0)),
        "continuous_axis0": (rotations.make_continuous, (q3, 0)),
        "from_rotvec": (rotations.quat_from_rotvec, (v,)),
        "to_rotvec": (rotations.rotvec_from_quat, (q3,)),
        "euler": (rotations.euler_zxy_from_quat, (q,)),
        "euler_view": (rotations.euler_zxy_unchecked, (q3[:, 5:-5],)),
        "from_euler": (rotations.quat_from_euler_zxy, tuple(a)),
        "to_matrix": (rotations.quat_to_matrix, (q3 * (1 + 1e-7),)),
        "relative": (rotations.relative_to_initial, (q3, 3)),
        "conjugate": (rotations.quat_conjugate, (q,)),
        "conjugate_strided": (rotations.quat_conjugate, (q3[:, ::2],)),
        "multiply": (rotations.quat_multiply, (p.reshape(3, -1, 4)[:, :1], q3)),
    }[case]
    got, ref = fn(*args), _numpy_reference(monkeypatch, fn, *args)
    assert got.shape == ref.shape
    assert np.array_equal(got, ref) and np.array_equal(np.signbit(got), np.signbit(ref))


def test_quat_to_matrix_is_scipys_bit_for_bit(rng):
    q = _unit_quats(rng, 2 * rotations._KERNEL_MIN_ROWS) * (1 + 1e-7)
    assert np.array_equal(rotations.quat_to_matrix(q), Rotation.from_quat(q, scalar_first=True).as_matrix())


def test_large_inputs_are_validated_like_small_ones(rng):
    q = _unit_quats(rng, 2 * rotations._KERNEL_MIN_ROWS)
    q[7, 0] = 1.1
    for fn in (rotations.quat_to_matrix, rotations.rotvec_from_quat, rotations.euler_zxy_from_quat):
        with pytest.raises(ValueError, match=r"unit quaternions .* got \|q\| in \[1, 1.1\]"):
            fn(q)
    q[7, 0] = np.nan
    with pytest.raises(ValueError, match="finite"):
        rotations.quat_to_matrix(q)
    with pytest.raises(ValueError, match="zero-norm"):
        rotations.quat_normalize(np.zeros((2 * rotations._KERNEL_MIN_ROWS, 4)))
    with pytest.raises(ValueError, match="p must be finite"):
        rotations.quat_multiply(q, np.ones(4))
    with pytest.raises(ValueError, match="q must be finite"):
        rotations.quat_conjugate(q)
    ok = _unit_quats(rng, 2 * rotations._KERNEL_MIN_ROWS)
    assert rotations.quat_conjugate(ok) is not ok and rotations.quat_multiply(ok, ok) is not ok


def test_relative_to_initial_in_place(rng):
    q = _unit_quats(rng, 3 * 1000).reshape(3, 1000, 4)
    expected = rotations.relative_to_initial(q, 2)
    out = q.copy()
    assert rotations.relative_to_initial(out, 2, out=out) is out
    assert np.array_equal(out, expected)
    big = _unit_quats(rng, 3 * rotations._KERNEL_MIN_ROWS).reshape(3, -1, 4)
    expected = rotations.relative_to_initial(big)
    assert np.array_equal(rotations.relative_to_initial(big, out=big), expected)
    with pytest.raises(ValueError, match=r"out must be a float64 array of shape \(3, 1000, 4\)"):
        rotations.relative_to_initial(q, out=np.empty((3, 999, 4)))


def test_relative_to_initial_from_a_start_sample_keeps_the_earlier_ones():
    rng = np.random.default_rng(0)
    q = rotations.quat_normalize(rng.normal(size=(2, 50, 4)))
    full = rotations.relative_to_initial(q)
    part = q.copy()
    rotations.relative_to_initial(part, out=part, start=20)
    assert np.array_equal(part[:, :20], q[:, :20]) and np.array_equal(part[:, 20:], full[:, 20:])
    with pytest.raises(ValueError, match="start must be"):
        rotations.relative_to_initial(q, start=3)


def test_relative_to_initial_in_windows_writes_only_them_bit_for_bit(rng):
    q = _unit_quats(rng, 2 * rotations._KERNEL_MIN_ROWS).reshape(2, -1, 4)
    full = q.copy()
    rotations.relative_to_initial(full, n0=3, out=full)
    part = q.copy()
    windows = [slice(40, 90), slice(5, 12), slice(200, 200), slice(-30, None)]
    assert rotations.relative_to_initial(part, n0=3, out=part, windows=windows) is part
    inside = np.zeros(q.shape[1], bool)
    for w in windows:
        inside[w] = True
    assert np.array_equal(part[:, inside], full[:, inside])       # the same kernel, the same bits
    assert np.array_equal(part[:, ~inside], q[:, ~inside])        # the rest as logged
    with pytest.raises(ValueError, match="windows must not overlap"):
        rotations.relative_to_initial(q, out=q.copy(), windows=[slice(0, 10), slice(9, 12)])
    with pytest.raises(ValueError, match="windows must be slices of step 1"):
        rotations.relative_to_initial(q, out=q.copy(), windows=[slice(0, 10, 2)])
    with pytest.raises(ValueError, match="windows needs out= and no start"):
        rotations.relative_to_initial(q, windows=[slice(0, 10)])
    with pytest.raises(ValueError, match="windows needs out= and no start"):
        rotations.relative_to_initial(q, out=q.copy(), start=2, windows=[slice(0, 10)])


def test_wrap_difference_equals_numpy_remainder_at_and_around_pi():
    """Differences at and around ±π (x = (e − t) + π at 0, just below 0, at and beyond 2π, ±3π) wrap
    bit for bit as ``np.remainder(e − t + π, 2π) − π`` (the rare ``fmod`` path included)."""
    from mtcal.core._rotation_kernels import wrap_difference3

    rng = np.random.default_rng(5)
    e = rng.uniform(-np.pi, np.pi, (1, 120, 10))
    ulp = np.spacing(np.pi)
    offsets = np.array([np.pi, -np.pi, np.pi + ulp, -np.pi - ulp, np.pi - ulp, -np.pi + ulp, 3 * np.pi, -3 * np.pi,
                        2 * np.pi, 0.0, 1e-3, -1e-3])
    t = e - offsets[np.arange(e.size).reshape(e.shape) % offsets.size]
    t[0, ::5] = e[0, ::5] + np.pi                                        # (e − t) + π = 0 exactly or ±ulp
    out = np.empty_like(e)
    wrap_difference3(e, t, out)
    ref = np.remainder(e - t + np.pi, 2.0 * np.pi) - np.pi
    assert out.tobytes() == ref.tobytes()
    assert (np.abs(out) <= np.pi).all()


@pytest.mark.parametrize("n", [7, 3000])   # numpy path and the compiled path
def test_trusted_twins_bit_identical_to_checked(n):
    """The trusted twins (systems call them after their edge checks) equal the checked calls bit for bit."""
    rng = np.random.default_rng(35)
    ang = rng.uniform(-np.pi, np.pi, (n, 3)) * [1.0, 0.5, 1.0]
    q = rotations.quat_from_euler_zxy(ang[:, 0], ang[:, 1], ang[:, 2])
    assert np.array_equal(rotations.quat_from_euler_zxy_trusted(ang[:, 0], ang[:, 1], ang[:, 2]), q)
    assert np.array_equal(rotations.quat_from_euler_zxy_trusted(ang[:, 0], np.float64(0.1), ang[:, 2]),
                          rotations.quat_from_euler_zxy(ang[:, 0], 0.1, ang[:, 2]))
    assert np.array_equal(rotations.left_matrix_trusted(q), rotations.left_matrix(q))
    assert np.array_equal(rotations.right_matrix_trusted(q), rotations.right_matrix(q))
    assert np.array_equal(rotations.quat_to_matrix_trusted(q), rotations.quat_to_matrix(q))
    assert np.array_equal(rotations.installation_angles_from_mount_trusted(q),
                          rotations.installation_angles_from_mount(q))


def test_trusted_twins_not_public():
    for name in ("quat_from_euler_zxy_trusted", "left_matrix_trusted", "right_matrix_trusted",
                 "quat_to_matrix_trusted", "installation_angles_from_mount_trusted"):
        assert name not in rotations.__all__ and callable(getattr(rotations, name))
    with pytest.raises(ValueError, match="yaw"):   # the public call keeps its check
        rotations.quat_from_euler_zxy(np.nan, 0.0, 0.0)


def test_level_quat_zxy_is_the_qncf_levelling_bit_for_bit():
    from mtcal.core.rotations import level_quat_zxy
    from mtcal.filters.qncf import initial_attitude_from_accel

    rng = np.random.default_rng(7)
    f = rng.normal(size=(50, 3)) + [0.0, 0.0, 9.81]
    assert np.array_equal(level_quat_zxy(f), initial_attitude_from_accel(f))
    assert np.array_equal(level_quat_zxy(f[0], 0.3), initial_attitude_from_accel(f[0], 0.3))
    with pytest.raises(ValueError, match="cannot level without gravity"):
        level_quat_zxy([0.0, 0.0, 0.0])
