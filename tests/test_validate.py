import numpy as np
import pytest

from mtcal import _validate as v


def test_as_float_array_copies_and_checks():
    src = np.array([1.0, 2.0])
    out = v.as_float_array(src, "x")
    out[0] = 5.0
    assert src[0] == 1.0  # never aliases the caller's array
    with pytest.raises(ValueError, match="x must have ndim in"):
        v.as_float_array([[1.0]], "x", ndim=1)
    with pytest.raises(ValueError, match="x must have last dimension 3"):
        v.as_float_array([1.0, 2.0], "x", last_dim=3)
    with pytest.raises(ValueError, match="x must not be empty"):
        v.as_float_array([], "x")
    with pytest.raises(ValueError, match="x must be finite"):
        v.as_float_array([np.inf], "x")
    with pytest.raises(TypeError, match="x must be a numeric array"):
        v.as_float_array(None, "x")


def test_scalars():
    assert v.positive_scalar(2, "fs_hz") == 2.0
    with pytest.raises(ValueError, match="fs_hz must be > 0"):
        v.positive_scalar(0.0, "fs_hz")
    with pytest.raises(TypeError, match="fs_hz must be a real number"):
        v.positive_scalar("100", "fs_hz")
    with pytest.raises(TypeError, match="fs_hz must be a real number"):
        v.positive_scalar(True, "fs_hz")
    with pytest.raises(ValueError, match="fs_hz must be finite"):
        v.positive_scalar(np.nan, "fs_hz")
    with pytest.raises(ValueError, match="trials must be >= 1"):
        v.positive_int(0, "trials")
    with pytest.raises(TypeError, match="trials must be an integer"):
        v.positive_int(2.0, "trials")


def test_time_vector_and_angles():
    with pytest.raises(ValueError, match="strictly increasing; sample 2"):
        v.time_vector([0.0, 1.0, 0.5])
    with pytest.raises(ValueError, match="at least 2 samples"):
        v.time_vector([0.0])
    with pytest.raises(ValueError, match="degrees passed as radians"):
        v.angle_rad([0.1, 90.0], "pitch")
    with pytest.raises(ValueError, match="unit quaternions"):
        v.unit_quaternion([0.5, 0.5, 0.5, 0.4], "q")
