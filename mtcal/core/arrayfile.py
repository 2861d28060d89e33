"""Named numeric arrays from MATLAB (.mat v5 and v7.3) and HDF5 (.h5/.hdf5) files.

One low-level reader for recordings stored as named arrays (e.g. ``imu_gyr`` N×3,
``sampling_rate`` scalar) rather than as a table with a header row. It returns plain
float arrays keyed by name; mapping names to the log schema (gyro, accel, time) and
checking units is the caller's job (the command line's log reader, a study's trial loader).

* MATLAB v5/v6/v7 files are read with :func:`scipy.io.loadmat`.
* MATLAB v7.3 files are HDF5 files with a 512-byte header; they, and ``.h5``/``.hdf5``
  files, are read with h5py. MATLAB writes column-major, so a v7.3 array of MATLAB shape
  N×3 appears as 3×N in HDF5 and is transposed back here; plain HDF5 datasets are returned
  as stored; a numeric scalar attribute of the file's root (e.g. ``sampling_rate`` kept as an
  attribute) is returned like a scalar dataset unless a dataset has its name.
* Scalars (a MATLAB 1×1 array, an HDF5 scalar dataset) come back as 0-d arrays; an N×1 or
  1×N array as shape (N,). Text, cell and struct variables are skipped; datasets inside
  HDF5 groups are keyed by their path (``group/name``).

Examples
--------
>>> import numpy as np, scipy.io, tempfile, os
>>> path = os.path.join(tempfile.mkdtemp(), "rec.mat")
>>> scipy.io.savemat(path, {"imu_gyr": np.zeros((5, 3)), "sampling_rate": 100.0, "info": "text"})
>>> arrays = read_arrays(path)
>>> sorted(arrays), arrays["imu_gyr"].shape, float(arrays["sampling_rate"])
(['imu_gyr', 'sampling_rate'], (5, 3), 100.0)
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

__all__ = ["ARRAY_FILE_SUFFIXES", "is_array_file", "read_arrays"]

#: file name endings read by :func:`read_arrays` (lower case)
ARRAY_FILE_SUFFIXES = (".mat", ".h5", ".hdf5")
_HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"


def is_array_file(path) -> bool:
    """True when ``path`` ends in one of :data:`ARRAY_FILE_SUFFIXES` (case-insensitive)."""
    return Path(path).suffix.lower() in ARRAY_FILE_SUFFIXES


def _is_hdf5(path: Path) -> bool:
    with open(path, "rb") as f:
        head = f.read(1024)
    # plain HDF5 at offset 0; MATLAB v7.3 puts its 512-byte header first
    return head[:8] == _HDF5_SIGNATURE or head[512:520] == _HDF5_SIGNATURE


def _squeeze(a: np.ndarray) -> np.ndarray:
    if a.ndim == 2 and 1 in a.shape:
        return a.reshape(-1) if a.size != 1 else a.reshape(())
    return a


def _numeric(a) -> np.ndarray | None:
    arr = np.asarray(a)
    if arr.dtype.kind not in "biuf":
        return None
    return arr.astype(float, copy=False)      # a float64 array just read is the caller's already: no second copy


def _read_mat_v5(path: Path) -> dict[str, np.ndarray]:
    import scipy.io

    try:
        raw = scipy.io.loadmat(str(path), squeeze_me=False)
    except (ValueError, TypeError, OSError) as exc:
        raise ValueError(f"{path}: not a readable MATLAB file ({exc})") from None
    out = {}
    for name, value in raw.items():
        if name.startswith("__"):
            continue
        arr = _numeric(value)
        if arr is not None:
            out[name] = _squeeze(arr)
    return out


def _read_hdf5(path: Path, matlab: bool) -> dict[str, np.ndarray]:
    import h5py

    out = {}
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise ValueError(f"{path}: not a readable HDF5 file ({exc})") from None
    with f:
        def visit(name, obj):
            if not isinstance(obj, h5py.Dataset) or name.startswith("#"):
                return
            cls = obj.attrs.get("MATLAB_class", b"")
            cls = cls.decode() if isinstance(cls, bytes) else str(cls)
            if matlab and cls in ("char", "cell", "struct"):
                return
            arr = _numeric(obj[()])
            if arr is None:
                return
            if matlab and arr.ndim == 2:
                arr = arr.T                       # MATLAB is column-major
            out[name] = _squeeze(arr)
        f.visititems(visit)
        for name, value in f.attrs.items():        # numeric root attributes (e.g. a sampling rate)
            arr = _numeric(value)
            if arr is not None and arr.size == 1 and name not in out and not name.startswith("MATLAB"):
                out[name] = arr.reshape(())
    return out


def read_arrays(path) -> dict[str, np.ndarray]:
    """Every numeric array of a .mat or HDF5 file, by name, as float64.

    Parameters
    ----------
    path : str or os.PathLike
        A MATLAB file (``.mat``, v5 or v7.3) or an HDF5 file (``.h5``, ``.hdf5``).

    Returns
    -------
    dict of str to numpy.ndarray
        Name → array (float64). Scalars are 0-d, vectors (N,), matrices as stored
        (MATLAB N×3 stays N×3). Non-numeric variables are left out.

    Raises
    ------
    ValueError
        If the file ending is not one of :data:`ARRAY_FILE_SUFFIXES` or the file cannot be
        parsed in that format.
    FileNotFoundError
        If the file does not exist.

    References
    ----------
    MathWorks, "MAT-File Versions" (v7.3 = HDF5 with a 512-byte header);
    SciPy ``scipy.io.loadmat``; h5py ``File``/``Dataset``.
    """
    p = Path(path)
    if not is_array_file(p):
        raise ValueError(f"{p}: not a .mat/.h5/.hdf5 file")
    if not p.is_file():
        raise FileNotFoundError(f"{p}: no such file")
    hdf5 = _is_hdf5(p)
    if p.suffix.lower() == ".mat" and not hdf5:
        return _read_mat_v5(p)
    if not hdf5:
        raise ValueError(f"{p}: not an HDF5 file (no HDF5 signature)")
    return _read_hdf5(p, matlab=p.suffix.lower() == ".mat")
