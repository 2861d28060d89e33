"""mtcal.core.arrayfile: named arrays from .mat (v5, v7.3) and HDF5 files."""

import numpy as np
import pytest
import scipy.io

from mtcal.core.arrayfile import is_array_file, read_arrays

h5py = pytest.importorskip("h5py")


def _arrays():
    rng = np.random.default_rng(0)
    return {"imu_gyr": rng.normal(size=(7, 3)), "imu_acc": rng.normal(size=(7, 3)),
            "movement": np.array([0, 1, 1, 1, 1, 1, 0], dtype=np.uint8), "sampling_rate": 285.7}


def test_mat_v5_round_trip(tmp_path):
    p = tmp_path / "r.mat"
    scipy.io.savemat(p, {**_arrays(), "info": "some text"})
    got = read_arrays(p)
    assert sorted(got) == ["imu_acc", "imu_gyr", "movement", "sampling_rate"]
    np.testing.assert_array_equal(got["imu_gyr"], _arrays()["imu_gyr"])
    assert got["movement"].shape == (7,) and got["sampling_rate"].shape == ()


def test_mat_v73_is_hdf5_with_matlab_header_and_column_major(tmp_path):
    """A v7.3 file: 512-byte user block, arrays stored transposed, text marked MATLAB_class char."""
    p = tmp_path / "r73.mat"
    with h5py.File(p, "w", userblock_size=512) as f:
        for k, v in _arrays().items():
            d = f.create_dataset(k, data=np.atleast_2d(np.asarray(v, dtype=float)).T)
            d.attrs["MATLAB_class"] = b"double"
        t = f.create_dataset("info", data=np.frombuffer(b"ab", dtype=np.uint8)[None, :].astype(np.uint16))
        t.attrs["MATLAB_class"] = b"char"
    with open(p, "r+b") as f:
        f.write(b"MATLAB 7.3 MAT-file")
    got = read_arrays(p)
    assert "info" not in got
    np.testing.assert_array_equal(got["imu_acc"], _arrays()["imu_acc"])
    assert got["movement"].shape == (7,) and float(got["sampling_rate"]) == 285.7


def test_hdf5_as_stored_with_groups(tmp_path):
    p = tmp_path / "r.hdf5"
    with h5py.File(p, "w") as f:
        for k, v in _arrays().items():
            f[k] = v
        f.create_group("g")["x"] = np.arange(3.0)
        f["name"] = "text"
        f.attrs["fs_hz"] = 100.0
        f.attrs["sampling_rate"] = 1.0         # a dataset of that name wins
        f.attrs["note"] = "text"
    got = read_arrays(p)
    assert "name" not in got
    np.testing.assert_array_equal(got["g/x"], [0.0, 1.0, 2.0])
    np.testing.assert_array_equal(got["imu_gyr"], _arrays()["imu_gyr"])
    assert float(got["fs_hz"]) == 100.0 and float(got["sampling_rate"]) == 285.7 and "note" not in got


def test_errors(tmp_path):
    assert is_array_file("a.H5") and not is_array_file("a.csv")
    with pytest.raises(ValueError, match="not a .mat/.h5/.hdf5 file"):
        read_arrays(tmp_path / "a.csv")
    with pytest.raises(FileNotFoundError, match="no such file"):
        read_arrays(tmp_path / "missing.mat")
    bad = tmp_path / "bad.mat"
    bad.write_bytes(b"not a mat file at all" * 10)
    with pytest.raises(ValueError, match="not a readable MATLAB file"):
        read_arrays(bad)
    bad_h5 = tmp_path / "bad.h5"
    bad_h5.write_bytes(b"x" * 100)
    with pytest.raises(ValueError, match="not an HDF5 file"):
        read_arrays(bad_h5)
