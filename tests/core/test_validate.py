import numpy as np
import pytest

from mtcal.core import validate


def test_as_float_array_copies_and_checks():
    src = np.array([1.0, 2.0])
    out = validate.as_float_array(src, "x")
    out[0] = 5.0
    assert src[0] == 1.0  # never aliases the caller's array
    with pytest.raises(ValueError, match="x must have ndim in"):
        validate.as_float_array([[1.0]], "x", ndim=1)
    with pytest.raises(ValueError, match="x must have last dimension 3"):
        validate.as_float_array([1.0, 2.0], "x", last_dim=3)
    with pytest.raises(ValueError, match="x must not be empty"):
        validate.as_float_array([], "x")
    with pytest.raises(ValueError, match="x must be finite"):
        validate.as_float_array([np.inf], "x")
    with pytest.raises(TypeError, match="x must be a numeric array"):
        validate.as_float_array(None, "x")


def test_scalars():
    assert validate.positive_scalar(2, "fs_hz") == 2.0
    with pytest.raises(ValueError, match="fs_hz must be > 0"):
        validate.positive_scalar(0.0, "fs_hz")
    with pytest.raises(TypeError, match="fs_hz must be a real number"):
        validate.positive_scalar("100", "fs_hz")
    with pytest.raises(TypeError, match="fs_hz must be a real number"):
        validate.positive_scalar(True, "fs_hz")
    with pytest.raises(ValueError, match="fs_hz must be finite"):
        validate.positive_scalar(np.nan, "fs_hz")
    with pytest.raises(ValueError, match="trials must be >= 1"):
        validate.positive_int(0, "trials")
    with pytest.raises(TypeError, match="trials must be an integer"):
        validate.positive_int(2.0, "trials")


def test_sample_interval_refuses_a_rate():
    assert validate.sample_interval(0.005) == 0.005 and validate.sample_interval(1) == 1.0
    with pytest.raises(ValueError, match=r"dt_s must be the sample interval in s \(<= 1 s\), got 1000 \(a sample rate"):
        validate.sample_interval(1000.0)
    with pytest.raises(ValueError, match="dt_s must be > 0"):
        validate.sample_interval(0.0)
    with pytest.raises(TypeError, match="gap must be a real number"):
        validate.sample_interval("0.01", "gap")


def test_time_vector_and_angles():
    with pytest.raises(ValueError, match="strictly increasing; sample 2"):
        validate.time_vector([0.0, 1.0, 0.5])
    with pytest.raises(ValueError, match="at least 2 samples"):
        validate.time_vector([0.0])
    with pytest.raises(ValueError, match="degrees passed as radians"):
        validate.angle_rad([0.1, 90.0], "pitch")
    with pytest.raises(ValueError, match="unit quaternions"):
        validate.unit_quaternion([0.5, 0.5, 0.5, 0.4], "q")


def test_unit_plausibility_checks():
    validate.check_gyro_units(np.full((10, 3), 30.0))  # 30 rad/s is a possible rate
    with pytest.raises(ValueError, match="degrees per second passed as rad/s"):
        validate.check_gyro_units(np.full((10, 3), 90.0))
    validate.check_accel_units(np.tile([0.0, 0.0, 9.8], (10, 1)))
    validate.check_accel_units(np.zeros((10, 3)))  # an all-zero record is not flagged
    with pytest.raises(ValueError, match="looks like it is in g"):
        validate.check_accel_units(np.tile([0.0, 0.0, 1.0], (100_000, 1)))


def test_filters_reject_wrong_units():
    from mtcal.filters.qncf import qncf
    from mtcal.filters.rams_ekf import RamsEkfParams, run_rams_ekf

    gyro, acc_g = np.zeros((200, 3)), np.tile([0.0, 0.0, 1.0], (200, 1))
    with pytest.raises(ValueError, match="looks like it is in g"):
        qncf(gyro, acc_g, 1e-3)
    with pytest.raises(ValueError, match="degrees per second"):
        qncf(np.full((200, 3), 100.0), 9.80665 * acc_g, 1e-3)
    with pytest.raises(ValueError, match="looks like it is in g"):
        run_rams_ekf(gyro, acc_g, np.ones(200, bool), [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], 1e-3, RamsEkfParams())


def test_as_float_array_without_copy_is_a_view_of_float64_input():
    src = np.ones((4, 3))
    assert np.shares_memory(validate.as_float_array(src, "x", copy=False), src)
    assert not np.shares_memory(validate.as_float_array(src, "x"), src)
    with pytest.raises(ValueError, match="x must be finite"):
        validate.as_float_array([np.nan, 1.0, 2.0], "x", copy=False)


def test_number_in_range_names_parameter_range_unit_and_value():
    assert validate.number_in_range("fs_hz", np.int64(200), 100.0, 10000.0, "Hz") == 200.0
    assert validate.number_in_range("rest_s", 2.5, 2.5, 30.0, "s") == 2.5  # bounds are inclusive
    with pytest.raises(ValueError, match=r"^fs_hz must be a number in \[100.0, 10000.0\] Hz, got 99.0$"):
        validate.number_in_range("fs_hz", 99.0, 100.0, 10000.0, "Hz")
    with pytest.raises(ValueError, match=r"rate must be a number in \[1.0, 100.0\] deg/s, got nan"):
        validate.number_in_range("rate", float("nan"), 1.0, 100.0, "deg/s")
    with pytest.raises(ValueError, match=r"got True"):
        validate.number_in_range("rate", True, 0.0, 100.0, "deg/s")
    with pytest.raises(ValueError, match=r"got '200'"):
        validate.number_in_range("fs_hz", "200", 100.0, 10000.0, "Hz")


def test_angle_pair_deg_checks_two_different_angles_in_range():
    assert validate.angle_pair_deg("pitch", [-12, 23.0], -60.0, 60.0) == (-12.0, 23.0)
    for bad in [(8.0, 8.0), (8.0,), (8.0, 70.0), (np.inf, 1.0), "ab", 5.0]:
        with pytest.raises(ValueError, match=r"^pitch must be two different angles in \[-60.0, 60.0\] deg, got "):
            validate.angle_pair_deg("pitch", bad, -60.0, 60.0)


def test_choice_names_parameter_choices_and_value():
    assert validate.choice("grade", "tactical", ["consumer", "tactical"]) == "tactical"
    with pytest.raises(ValueError, match=r"^grade must be one of \['consumer', 'tactical'\], got 'navy'$"):
        validate.choice("grade", "navy", ("consumer", "tactical"))


def test_merge_parameters_fills_defaults_and_rejects_unknown_names():
    defaults = {"b": 2, "a": 1}
    params = {"a": 5}
    assert validate.merge_parameters(params, defaults) == {"b": 2, "a": 5}
    assert defaults == {"b": 2, "a": 1} and params == {"a": 5}  # inputs untouched
    with pytest.raises(ValueError, match=r"^unknown parameter\(s\) \['x', 'y'\]; valid: \['a', 'b'\]$"):
        validate.merge_parameters({"y": 0, "x": 0, "a": 0}, defaults)
    with pytest.raises(ValueError, match=r"^unknown tan2022 parameter\(s\) \['x'\]; valid: \['a', 'b'\]$"):
        validate.merge_parameters({"x": 0}, defaults, what="tan2022 parameter")


def test_unit_quaternion_compiled_check_of_large_arrays():
    rng = np.random.default_rng(3)
    q = rng.normal(size=(3000, 4))
    q /= np.linalg.norm(q, axis=-1, keepdims=True)
    out = validate.unit_quaternion(q, "q")
    assert out is not q and np.array_equal(out, q)          # a copy by default
    assert validate.unit_quaternion(q, "q", copy=False) is q  # or the checked input itself
    bad = q.copy()
    bad[2500] *= 1.001
    with pytest.raises(ValueError, match=r"q must hold unit quaternions .* got \|q\| in \[1, 1.001\]"):
        validate.unit_quaternion(bad, "q")
    bad[2500] = np.nan
    with pytest.raises(ValueError, match="q must be finite"):
        validate.unit_quaternion(bad, "q", copy=False)


def test_unit_quaternion_copy_false_small_and_list_input():
    q = np.array([[1.0, 0.0, 0.0, 0.0]])
    assert validate.unit_quaternion(q, "q", copy=False) is q
    assert validate.unit_quaternion([0.0, 1.0, 0.0, 0.0], "q", copy=False).tolist() == [0.0, 1.0, 0.0, 0.0]
    with pytest.raises(ValueError, match="q must hold unit quaternions"):
        validate.unit_quaternion([[0.5, 0.0, 0.0, 0.0]], "q", copy=False)
