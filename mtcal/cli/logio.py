"""The one log reader and writer of the ``mtcal`` command line (CSV, Parquet, MATLAB .mat, HDF5).

Input schema (header row, one row per sample; extra columns are ignored)::

    time_s                                   sample time (s), strictly increasing
    gyro_x_rad_s, gyro_y_rad_s, gyro_z_rad_s angular rate (rad/s), sensor frame,
                                             mean rate over [t_k, t_(k+1)]
    accel_x_m_s2, accel_y_m_s2, accel_z_m_s2 specific force (m/s²), sensor frame;
                                             a level sensor at rest reads ≈ +g on z
    q0, q1, q2, q3                           (optional) attitude quaternion, scalar-first,
                                             sensor → world (``calibrate``/``apply``)

Adapters (all commands): ``--time-unit {s,ms,us}``, ``--gyro-unit {rad/s,deg/s}``,
``--accel-unit {m/s2,g}``, ``--gyro-scale``/``--accel-scale`` (one factor or three
per-axis factors, applied first: raw counts → the unit), and
``--columns time_s=Time,gyro_x_rad_s=GyrX,…`` to map other header names
(header whitespace is stripped; short keys ``time, gyro_x, accel_x`` also work).
Headers that carry their unit are recognised without options: ``time_ms``,
``time_us``, ``gyro_x_deg_s``, ``accel_x_g``.

Jittered timestamps (e.g. whole milliseconds, 3–7 ms steps) are handled by
**per-sample dt**: the filters run at the mean rate, and gyro sample k is
weighted by its own interval, ``ω_k (t_(k+1) − t_k) / dt_mean``, so every
integrated angle uses the recorded time; no resampling, no interpolation of
the accelerometer.

Files ending in ``.parquet``/``.pq`` are Parquet, ``.mat`` (v5 or v7.3) and ``.h5``/``.hdf5``
hold named arrays (read by :func:`mtcal.core.arrayfile.read_arrays`), anything else CSV (comma,
semicolon or tab, sniffed from the header). An array file's N×3 arrays are mapped with
``--columns gyro=NAME,accel=NAME[,time=NAME]``; without a time array the sample rate is a
scalar ``sampling_rate`` (Hz) in the file or ``--fs-hz``. A file holding ``imu_gyr``, ``imu_acc``
and ``sampling_rate`` (the BROAD benchmark's layout: rad/s, m/s², Hz) opens with no option; its
other arrays (optical reference, magnetometer) are ignored. Outputs are written to a
temporary file in the target directory and renamed over the target
(``os.replace``), so a failed write never leaves a truncated file and never
touches an existing one.
"""

from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

__all__ = ["InputOptions", "ImuLog", "read_log", "write_table", "check_output_path", "TABLE_SUFFIXES",
           "CANONICAL", "MIN_FS_HZ", "MAX_FS_HZ", "parse_scale", "parse_columns", "ARRAY_KEYS", "ARRAY_LAYOUT"]

GYRO_COLS = ("gyro_x_rad_s", "gyro_y_rad_s", "gyro_z_rad_s")
ACCEL_COLS = ("accel_x_m_s2", "accel_y_m_s2", "accel_z_m_s2")
QUAT_COLS = ("q0", "q1", "q2", "q3")
CANONICAL = ("time_s",) + GYRO_COLS + ACCEL_COLS + QUAT_COLS
#: header spellings that carry a unit: canonical name → [(alias, unit)]
_UNIT_ALIASES = {
    "time_s": [("time_ms", "ms"), ("time_us", "us")],
    **{c: [(c.replace("_rad_s", "_deg_s"), "deg/s")] for c in GYRO_COLS},
    **{c: [(c.replace("_m_s2", "_g"), "g")] for c in ACCEL_COLS},
}
TIME_UNITS = {"s": 1.0, "ms": 1e-3, "us": 1e-6}
GYRO_UNITS = {"rad/s": 1.0, "deg/s": np.pi / 180.0}
ACCEL_UNITS = {"m/s2": 1.0, "g": 9.80665}
#: --columns keys naming an N×3 array of a .mat/.h5 file
ARRAY_KEYS = ("gyro", "accel")
#: array names recognised without --columns (the BROAD benchmark's layout: rad/s, m/s², sample rate in Hz)
ARRAY_LAYOUT = {"gyro": "imu_gyr", "accel": "imu_acc", "fs_hz": "sampling_rate"}
#: plausible IMU sample rates (Hz): outside, the time column is in another unit or mislabelled
MIN_FS_HZ = 5.0
MAX_FS_HZ = 20000.0


def parse_scale(text: str | None, name: str) -> np.ndarray | None:
    """``"0.001"`` or ``"a,b,c"`` → per-axis factors (3,), finite and non-zero."""
    if text is None:
        return None
    try:
        vals = np.array([float(x) for x in str(text).split(",")])
    except ValueError:
        raise ValueError(f"{name} must be one number or three comma-separated numbers, got {text!r}") from None
    if vals.size == 1:
        vals = np.repeat(vals, 3)
    if vals.size != 3 or not np.all(np.isfinite(vals)) or np.any(vals == 0):
        raise ValueError(f"{name} must be one or three finite non-zero numbers, got {text!r}")
    if np.any(np.abs(vals) < SCALE_RANGE[0]) or np.any(np.abs(vals) > SCALE_RANGE[1]):
        raise ValueError(f"{name} must be a factor counts -> unit of magnitude {SCALE_RANGE[0]:g} to "
                         f"{SCALE_RANGE[1]:g} (one or three numbers), got {text!r}")
    return vals


#: Magnitudes ``--gyro-scale``/``--accel-scale`` accept: a count of any 8- to 32-bit sensor in any unit the
#: options name (a 32-bit gyro count of 0.1 mdeg/s is ~2e-6 rad/s; a raw mg count 1e-3 g) lies well inside.
SCALE_RANGE = (1e-9, 1e9)


def parse_columns(text: str | None) -> dict:
    """``"time_s=Time, gyro_x=GyrX"`` → {canonical: header}; short keys accepted."""
    if not text:
        return {}
    out = {}
    short = {c.split("_rad_s")[0].split("_m_s2")[0]: c for c in CANONICAL}
    short["time"] = "time_s"
    for item in str(text).split(","):
        if not item.strip():
            continue
        if "=" not in item:
            raise ValueError(f"--columns entries must look like name=header, got {item.strip()!r}")
        key, val = (s.strip() for s in item.split("=", 1))
        key = short.get(key, key)
        if key not in CANONICAL and key not in ARRAY_KEYS:
            raise ValueError(f"--columns: unknown name {key!r}; known: {', '.join(CANONICAL + ARRAY_KEYS)}")
        out[key] = val
    return out


@dataclass(frozen=True)
class InputOptions:
    """How to interpret a log's columns (see the module docstring)."""

    time_unit: str | None = None
    gyro_unit: str | None = None
    accel_unit: str | None = None
    gyro_scale: np.ndarray | None = None
    accel_scale: np.ndarray | None = None
    columns: dict = field(default_factory=dict)
    fs_hz: float | None = None

    def __post_init__(self) -> None:
        if self.fs_hz is not None and not (np.isfinite(self.fs_hz) and MIN_FS_HZ <= self.fs_hz <= MAX_FS_HZ):
            raise ValueError(f"--fs-hz must be a sample rate in {MIN_FS_HZ:g}-{MAX_FS_HZ:g} Hz, got {self.fs_hz}")
        for name, table in (("time_unit", TIME_UNITS), ("gyro_unit", GYRO_UNITS), ("accel_unit", ACCEL_UNITS)):
            val = getattr(self, name)
            if val is not None and val not in table:
                raise ValueError(f"--{name.replace('_', '-')} must be one of {', '.join(table)}, got {val!r}")


@dataclass
class ImuLog:
    """A loaded log in SI units.

    Attributes
    ----------
    path : str
    time_s : ndarray (N,)
    gyro_rad_s, accel_m_s2 : ndarray (N, 3) or None
    q_ws : ndarray (N, 4) or None
    fs_hz : float
        Mean sample rate ``(N − 1) / (t_last − t_first)``.
    dt_s : ndarray (N,)
        Per-sample interval ``t_(k+1) − t_k`` (last: the mean).
    jitter : float
        ``max |dt − dt_mean| / dt_mean``.
    notes : list of str
        What was adapted (units, per-sample dt, gaps).
    gyro_unit_stated : str or None
        Where the gyro unit was stated (``--gyro-unit``, a unit-carrying header such as
        ``gyro_x_rad_s``, a recognised array layout); None when only assumed (e.g. ``--columns``
        without ``--gyro-unit``). A units check that cannot decide warns instead of refusing then.
    """

    path: str
    time_s: np.ndarray
    gyro_rad_s: np.ndarray | None
    accel_m_s2: np.ndarray | None
    q_ws: np.ndarray | None
    fs_hz: float
    dt_s: np.ndarray
    jitter: float
    notes: list
    gyro_unit_stated: str | None = None
    _gyro_filter: tuple | None = field(default=None, repr=False, compare=False)

    @property
    def n(self) -> int:
        return int(self.time_s.size)

    @property
    def dt_mean_s(self) -> float:
        return 1.0 / self.fs_hz

    def gyro_for_filter(self) -> np.ndarray:
        """Gyro weighted by per-sample dt for a fixed-step filter at ``dt_mean_s`` (rad/s); computed once.

        The caller must not modify the array returned (it is the log's gyro for a uniform time base).
        """
        from mtcal.systems.plausibility import time_base

        if self.gyro_rad_s is None:
            raise ValueError(f"{self.path}: no gyro columns")
        cached = self._gyro_filter
        if cached is None or cached[0] is not self.gyro_rad_s or cached[1] is not self.time_s:
            _, weights = time_base(self.n, time_s=self.time_s)
            gyro = self.gyro_rad_s if weights is None else self.gyro_rad_s * weights[:, None]
            cached = self._gyro_filter = (self.gyro_rad_s, self.time_s, gyro)
        return cached[2]


def _read_table(path: Path, select=None, dropped: list | None = None):
    """Column name (stripped) → Arrow column, from CSV or Parquet.

    A CSV whose **last** row has fewer fields than the header (a logger stopped mid-row) is read without
    that row, a note appended to ``dropped`` (when given; otherwise it is refused as before); a short
    row anywhere else is refused as not a readable CSV, with its text.

    ``select(names) -> names`` picks the columns read: a CSV read parses them as
    float64 (no type inference, no unused columns; a value that is not a number makes
    the read fall back to inferring every column so the error can name its row), a
    Parquet read decodes only them. Also returns every column name, for messages.
    """
    import pyarrow as pa

    csv_file = path.suffix.lower() not in (".parquet", ".pq")
    if not csv_file:
        import pyarrow.parquet as pq

        try:  # ParquetFile, not read_table: no pyarrow.dataset (which imports pandas, ~0.5 s)
            pf = pq.ParquetFile(path)
            names = pf.schema_arrow.names
            every = [str(n).strip() for n in names if not str(n).startswith(_UNNAMED)]
            want = None
            if select is not None:
                stripped = {str(n).strip(): n for n in names}
                want = list(dict.fromkeys(stripped[n] for n in select(list(stripped)) if n in stripped))
                want = want if want and len(stripped) == len(names) else None
            table = pf.read(columns=want)
        except (pa.ArrowException, OSError) as exc:
            raise ValueError(f"{path}: not a readable Parquet file ({str(exc).splitlines()[0]})") from None
    else:
        import pyarrow.csv as pcsv

        with open(path, "rb") as fh:
            head = fh.readline(65536).decode("utf-8", "replace").lstrip("\ufeff")  # a UTF-8 byte-order mark
            second = fh.readline(65536).decode("utf-8", "replace")
        if not head.strip():
            raise ValueError(f"{path}: empty file (a header row is required)")
        delim = "," if "," in head else ";" if ";" in head else "\t" if "\t" in head else ","
        raw = _header_names(head, second, delim)
        parse = pcsv.ParseOptions(delimiter=delim)
        read = pcsv.ReadOptions(column_names=raw, skip_rows=1)
        table = None
        if select is not None:
            want = list(dict.fromkeys(n for n in select(raw) if n in raw))   # a column read for two names: once
            if want and len(set(raw)) == len(raw):
                try:
                    table = pcsv.read_csv(path, read_options=read, parse_options=parse,
                                          convert_options=pcsv.ConvertOptions(
                                              include_columns=want, column_types={w: pa.float64() for w in want}))
                except (pa.ArrowException, UnicodeDecodeError):
                    table = None  # e.g. a non-numeric value: the full read below names its row
        if table is None:
            source = path
            for attempt in range(2):
                try:
                    table = pcsv.read_csv(source, read_options=read, parse_options=parse,
                                          convert_options=pcsv.ConvertOptions(strings_can_be_null=True))
                    break
                except (pa.ArrowException, UnicodeDecodeError) as exc:
                    cut = None if attempt or dropped is None else _truncated_last_row(path, str(exc))
                    if cut is None:
                        raise ValueError(f"{path}: not a readable CSV ({str(exc).splitlines()[0][:200]})") from None
                    source, note = cut
            if source is not path:
                dropped.append(note + f", {table.num_rows} rows read")
        every = [n for n in raw if not n.startswith(_UNNAMED)]
    header = [str(n).strip() for n in (raw if csv_file else names)]
    if select is not None:                   # a column read twice under one name: which copy is meant is unknown
        used = set(select(list(dict.fromkeys(header))))
        twice = [n for n in dict.fromkeys(header) if n in used and header.count(n) > 1]
        if twice:
            raise ValueError(f"{path}: column {twice[0]!r} appears {header.count(twice[0])} times in the header; "
                             f"rename the copies so that each column has its own name")
    out = {str(name).strip(): col for name, col in zip(table.column_names, table.columns)
           if not str(name).startswith(_UNNAMED)}
    return out, (every if len(out) < len(every) else list(out))  # every header of the file, for messages


_UNNAMED = "_unnamed_"


def _truncated_last_row(path: Path, error: str):
    """A CSV parse error caused only by a last row with too few fields (a logger stopped mid-row): ``(the file
    without that row as an Arrow buffer reader, a note)``; None for any other error."""
    import re

    import pyarrow as pa

    m = re.match(r"CSV parse error: Expected (\d+) columns, got (\d+): (.*)", error, re.S)
    if m is None or int(m.group(2)) >= int(m.group(1)):
        return None
    size = path.stat().st_size
    with open(path, "rb") as fh:
        fh.seek(max(0, size - 65536))
        tail = fh.read()
    body = tail.rstrip(b"\r\n \t")
    start = body.rfind(b"\n") + 1                 # the last non-empty line starts here (in tail)
    last = body[start:].decode("utf-8", "replace").strip()
    if not last or last != m.group(3).strip() or size - len(tail) + start <= 0:
        return None
    buf = pa.memory_map(str(path)).read_buffer(size - len(tail) + start)
    return pa.BufferReader(buf), (f"last row dropped: it has {m.group(2)} of {m.group(1)} fields (logger stopped "
                                  f"mid-row?)")


def _header_names(head: str, second: str, delim: str) -> list[str]:
    """Column names of a CSV header: quotes and surrounding blanks removed, empty names (trailing
    separators) and data fields beyond the header named ``_unnamed_<i>`` so the rows still parse."""
    import csv

    def split(line: str) -> list[str]:
        line = line.rstrip("\r\n")
        try:
            return next(csv.reader([line], delimiter=delim))
        except (csv.Error, StopIteration):  # e.g. a binary file: the read below reports it
            return line.split(delim)

    names = [n.strip().strip('"').strip() for n in split(head)]
    if second.strip():
        names += [""] * max(0, len(split(second)) - len(names))
    return [n if n else f"{_UNNAMED}{i}" for i, n in enumerate(names)]


_PREWARM: list = []


def _load_compiler() -> None:
    """Import numba and load its CPU target's typing/lowering registries (what the first cached kernel of a
    command would do: ~0.8 s, mostly ``numba.np.arraymath``, which imports ``scipy.linalg``)."""
    try:
        import mtcal.core.compiled  # noqa: F401 - numba's settings before numba loads
        import numba  # noqa: F401
        from numba.core.compiler_lock import global_compiler_lock
        from numba.core.registry import cpu_target

        with global_compiler_lock:
            cpu_target.target_context.refresh()
    except BaseException:  # noqa: BLE001 - only a head start: the command itself reports any real problem
        pass


def prewarm_compiled() -> None:
    """Start loading the compiled kernels' machinery (numba) in a background thread, once per process.

    The log is read meanwhile (pyarrow and numpy release the GIL), so the two overlap instead of
    running one after the other; a command waits for nothing it would not have waited for anyway
    (numba's compile lock and Python's import locks serialise the shared parts). The thread is not
    a daemon: the interpreter lets it finish before exiting. Results cannot differ (no kernel runs).
    """
    import sys
    import threading

    if _PREWARM or "numba.np.arraymath" in sys.modules:
        return
    thread = threading.Thread(target=_load_compiler, name="mtcal-prewarm")
    _PREWARM.append(thread)
    thread.start()


def _numeric(col, header: str, path: Path, out: np.ndarray | None = None) -> np.ndarray:
    """A column as float64 (into ``out``, e.g. a column of an (N, 3) array); the first non-numeric/NaN row is
    named in the error.

    Numeric columns are copied chunk by chunk from their Arrow buffers (no intermediate array, and no
    ``to_numpy``, which imports pandas: ~0.3 s of a CLI call).
    """
    import pyarrow as pa

    if pa.types.is_integer(col.type) or pa.types.is_floating(col.type) or pa.types.is_boolean(col.type):
        import pyarrow.compute as pc

        out = np.empty(len(col)) if out is None else out
        off = 0
        for chunk in (col.chunks if isinstance(col, pa.ChunkedArray) else [col]):
            if chunk.type != pa.float64():
                chunk = pc.cast(chunk, pa.float64(), safe=False)  # as numpy's astype(float64)
            if chunk.null_count:
                chunk = pc.fill_null(chunk, float("nan"))
            n = len(chunk)
            out[off:off + n] = np.frombuffer(chunk.buffers()[1], dtype=np.float64, count=n, offset=8 * chunk.offset)
            off += n
        arr = out
    else:
        import pyarrow.compute as pc

        try:
            arr = pc.cast(pc.utf8_trim_whitespace(col.cast(pa.string())), pa.float64()).to_numpy(
                zero_copy_only=False)
        except (pa.ArrowException, TypeError):
            import pandas as pd

            arr = pd.to_numeric(pd.Series(col.to_pylist(), dtype=object).astype(str).str.strip(),
                                errors="coerce").to_numpy(float)
        if out is not None:
            out[:] = arr
            arr = out
    if not np.isfinite(np.sum(arr)):  # a NaN or inf makes the sum non-finite (so may an overflow: looked at below)
        bad = ~np.isfinite(arr)
        if bad.any():
            row = int(np.argmax(bad))
            hint = ""
            if not (pa.types.is_integer(col.type) or pa.types.is_floating(col.type)):
                import re

                value = str(col[row].as_py()).strip()
                if re.fullmatch(r"[+-]?\d+,\d+([eE][+-]?\d+)?", value):
                    hint = (f" ({value!r}: a decimal comma? write the log with a decimal point, e.g. "
                            f"{value.replace(',', '.')!r})")
            raise ValueError(f"{path}: non-numeric or NaN value in column {header!r} at data row {row + 1}{hint}")
    return arr


def _resolve(names: dict, want: tuple, opts: InputOptions) -> tuple[dict, dict]:
    """Canonical name → header in the file, and units implied by unit-carrying headers."""
    found, units = {}, {}
    for c in want:
        if c in opts.columns:
            found[c] = opts.columns[c]
        elif c in names:
            found[c] = c
        else:
            for alias, unit in _UNIT_ALIASES.get(c, []):
                if alias in names:
                    found[c], units[c] = alias, unit
    return found, units


def read_log(path, opts: InputOptions | None = None, *, need: str = "raw", min_samples: int = 10) -> ImuLog:
    """Read, convert to SI and check a log (the only log reader of the CLI).

    Parameters
    ----------
    path : str or Path
        CSV or Parquet file.
    opts : InputOptions
        Units, scales and column mapping.
    need : {"raw", "accel", "raw_or_quat"}
        Columns required: gyro + accel, accel (gyro read too when present),
        or gyro + accel or q0..q3.
    min_samples : int

    Raises
    ------
    ValueError
        Missing file/columns, non-numeric values, unsorted time, an implausible
        sample rate (time unit) — always one line naming the file and the fix.
    """
    opts = InputOptions() if opts is None else opts
    p = Path(path)
    if not p.exists():
        raise ValueError(f"log file not found: {path}")
    if not p.is_file():
        raise ValueError(f"log {path} is not a regular file")
    from mtcal.core.arrayfile import is_array_file

    fs_opt, stated, array_file = opts.fs_hz, None, is_array_file(p)
    dropped: list = []     # a truncated last CSV row (_read_table), noted on the log line
    if array_file:  # read first: scipy.io/h5py imported before the prewarm thread imports scipy (import race)
        cols, all_names, fs_opt, stated = _array_columns(p, opts)
        opts = InputOptions(**{**opts.__dict__, "columns": {}})
        prewarm_compiled()
    else:
        prewarm_compiled()
        array_keys = [k for k in ARRAY_KEYS if k in opts.columns]
        if array_keys:
            raise ValueError(f"--columns {array_keys[0]}=… names an N x 3 array of a .mat/.h5 file; map the "
                             f"columns of {path} with {array_keys[0]}_x=HEADER,{array_keys[0]}_y=…")
        cols, all_names = _read_table(p, select=lambda names: list(_resolve(set(names), CANONICAL, opts)[0].values()),
                                      dropped=dropped)
    for c, header in opts.columns.items():
        if header not in cols:
            raise ValueError(f"{path}: --columns maps {c} to {header!r}, which is not a column "
                             f"(columns: {', '.join(all_names[:20])})")
    found, implied = _resolve(cols, CANONICAL, opts)
    readers = {}
    for c, header in found.items():
        if header in readers:
            first = readers[header]
            mapped = next((k for k in (c, first) if k in opts.columns), None)
            if mapped is None:
                raise ValueError(f"{path}: column {header!r} would be read as both {first} and {c}")
            raise ValueError(f"{path}: --columns maps {mapped} to {header!r}, which is also read as "
                             f"{first if mapped == c else c}; map each quantity to its own column")
        readers[header] = c
    has_raw = all(c in found for c in GYRO_COLS + ACCEL_COLS)
    has_acc = all(c in found for c in ACCEL_COLS)
    has_q = all(c in found for c in QUAT_COLS)
    if "time_s" not in found and fs_opt is None:
        raise ValueError(f"{path}: missing column time_s (columns: {', '.join(all_names[:20])}); "
                         f"map yours with --columns time_s=NAME, or give --fs-hz for a uniformly sampled log")
    required = {"raw": GYRO_COLS + ACCEL_COLS, "accel": ACCEL_COLS, "raw_or_quat": QUAT_COLS}[need]
    ok = {"raw": has_raw, "accel": has_acc, "raw_or_quat": has_raw or has_q}[need]
    if not ok:
        missing = [c for c in required if c not in found]
        extra = f" (or the raw set {', '.join(GYRO_COLS + ACCEL_COLS)})" if need == "raw_or_quat" else ""
        raise ValueError(f"{path}: missing columns {', '.join(missing)}{extra}; columns present: "
                         f"{', '.join(all_names[:20])}; map yours with --columns NAME=HEADER")
    notes = list(dropped)
    partial = [c for c in GYRO_COLS if c in found]
    if partial and len(partial) < len(GYRO_COLS):       # (need "raw" refused above: here the gyro is optional)
        notes.append(f"gyro not used: {', '.join(c for c in GYRO_COLS if c not in found)} missing "
                     f"(only {', '.join(found[c] for c in partial)} in the log)")
    time_unit = opts.time_unit or implied.get("time_s", "s")
    if fs_opt is not None:  # --fs-hz (or an array file's sample rate): uniform time, any time column ignored
        t = np.arange(len(next(iter(cols.values())))) / fs_opt
        source = "--fs-hz" if opts.fs_hz is not None else ARRAY_LAYOUT["fs_hz"]
        found["time_s"] = source
        notes.append(f"time from {source} {fs_opt:g}")
    else:
        t = _numeric(cols[found["time_s"]], found["time_s"], p)
        if TIME_UNITS[time_unit] != 1.0:  # (s: no copy)
            t = t * TIME_UNITS[time_unit]
    if time_unit != "s":
        notes.append(f"time in {time_unit}")
    if t.size < min_samples:
        raise ValueError(f"{path}: needs at least {min_samples} samples, got {t.size}")
    dt_full = np.empty(t.size)  # per-sample dt; the last sample takes the mean (set below)
    dt = np.subtract(t[1:], t[:-1], out=dt_full[:-1])  # = np.diff(t), a view
    dt_min, dt_max = float(dt.min()), float(dt.max())
    if dt_min <= 0:
        k = int(np.argmax(dt <= 0))
        raise ValueError(f"{path}: {found['time_s']} is not strictly increasing at data row {k + 2} "
                         f"({float(t[k + 1])!r} after {float(t[k])!r}); sort the log by time and drop duplicates")
    fs = (t.size - 1) / (t[-1] - t[0])
    if not MIN_FS_HZ <= fs <= MAX_FS_HZ:
        hint = ("is time in ms or us? use --time-unit ms or --time-unit us" if fs < MIN_FS_HZ
                else "is time in s labelled as ms? check --time-unit")
        raise ValueError(f"{path}: mean sample rate {fs:.4g} Hz from {found['time_s']} (time unit "
                         f"{time_unit}) is implausible for an IMU ({MIN_FS_HZ:g}-{MAX_FS_HZ:g} Hz); {hint}")
    dt_mean = 1.0 / fs
    jitter = float(max(dt_mean - dt_min, dt_max - dt_mean) / dt_mean)
    dt_full[-1] = dt_mean
    if jitter > 1e-3:
        notes.append(f"jittered timestamps (dt {dt_min * 1e3:.3g}-{dt_max * 1e3:.3g} ms, mean "
                     f"{dt_mean * 1e3:.4g} ms): per-sample dt used")
    if dt_max > 5.0 * dt_mean:
        gaps = dt > 5.0 * np.median(dt)
        notes.append(f"{int(gaps.sum())} gap(s) > 5x the median dt (largest {dt_max:.3g} s)")

    def vec(names, unit_name, unit_opt, table, scale, scale_name):
        unit = unit_opt or implied.get(names[0], next(iter(table)))
        arr = np.empty((t.size, 3))
        for i, c in enumerate(names):
            _numeric(cols.pop(found[c]), found[c], p, out=arr[:, i])  # pop: free the Arrow column early
        if scale is not None:
            arr *= scale
            notes.append(f"{scale_name} {','.join(f'{s:g}' for s in scale)}")
        if unit != next(iter(table)):
            notes.append(f"{unit_name} in {unit}")
            arr *= table[unit]
        return arr

    gyro = accel = q = None
    if has_raw or (need == "accel" and has_acc):
        accel = vec(ACCEL_COLS, "accel", opts.accel_unit, ACCEL_UNITS, opts.accel_scale, "accel scale")
        _check_accel(accel, p)
    if has_raw:
        gyro = vec(GYRO_COLS, "gyro", opts.gyro_unit, GYRO_UNITS, opts.gyro_scale, "gyro scale")
        _check_gyro(gyro, p, accel, dt_mean)
        if dt_max > 5.0 * dt_mean:
            _check_gaps(gyro, dt_full, dt_mean, t, p, found["time_s"])
        if opts.gyro_unit is not None:
            stated = f"--gyro-unit {opts.gyro_unit}"
        elif array_file:
            pass  # stated only by the recognised layout (above) or --gyro-unit
        elif GYRO_COLS[0] in implied:
            stated = f"header {found[GYRO_COLS[0]]}"
        elif found[GYRO_COLS[0]] == GYRO_COLS[0] and GYRO_COLS[0] not in opts.columns:
            stated = f"header {GYRO_COLS[0]}"
    if has_q and need == "raw_or_quat":
        q = np.column_stack([_numeric(cols[found[c]], found[c], p) for c in QUAT_COLS])
        norm = np.linalg.norm(q, axis=1)
        if np.any(np.abs(norm - 1.0) > 1e-3):
            raise ValueError(f"{path}: q0..q3 are not unit quaternions (|q| in [{norm.min():.4g}, "
                             f"{norm.max():.4g}])")
        q = q / norm[:, None]
    return ImuLog(str(path), t, gyro, accel, q, float(fs), dt_full, jitter, notes, gyro_unit_stated=stated)


def _array_columns(path: Path, opts: InputOptions):
    """The log-schema columns of a .mat/.h5 file: named arrays mapped by ``--columns gyro=…,accel=…,time=…``.

    Returns ``(columns, names, fs_hz, stated)``: canonical name → Arrow column, the file's array names
    (for messages), the sample rate (``--fs-hz``, else the file's ``sampling_rate`` scalar when no time
    array is mapped, else None) and where the gyro unit was stated (the recognised layout) or None.
    """
    from mtcal.core.arrayfile import read_arrays

    try:
        arrays = read_arrays(path)
    except (OSError, ValueError) as exc:
        raise ValueError(str(exc).splitlines()[0] if str(exc) else f"{path}: not readable") from None
    names = sorted(arrays)
    mapped = {k: opts.columns[k] for k in ARRAY_KEYS if k in opts.columns}
    other = [k for k in opts.columns if k not in ARRAY_KEYS and k != "time_s"]
    if other:
        raise ValueError(f"--columns {other[0]}=… maps a table column; in the array file {path} map N x 3 arrays "
                         f"with --columns gyro=NAME,accel=NAME[,time=NAME] (arrays: {', '.join(names[:20])})")
    layout = all(ARRAY_LAYOUT[k] in arrays for k in ARRAY_KEYS) and not mapped
    for k in ARRAY_KEYS:
        mapped.setdefault(k, ARRAY_LAYOUT[k])
    out, n_rows = {}, None
    for key in ARRAY_KEYS:
        name = mapped[key]
        if name not in arrays:
            raise ValueError(f"{path}: no array {name!r} for the {key}; map yours with --columns {key}=NAME "
                             f"(arrays: {', '.join(names[:20])})")
        arr = arrays[name]
        if arr.ndim != 2 or arr.shape[1] != 3:
            raise ValueError(f"{path}: array {name!r} ({key}) must be N x 3, got shape {arr.shape}")
        n_rows = arr.shape[0] if n_rows is None else n_rows
        if arr.shape[0] != n_rows:
            raise ValueError(f"{path}: arrays of different lengths: {mapped['gyro']!r} has {n_rows} rows, "
                             f"{name!r} {arr.shape[0]}")
        _finite_rows(arr, name, path)
        cols = GYRO_COLS if key == "gyro" else ACCEL_COLS
        for i, c in enumerate(cols):
            out[c] = _arrow_array(np.ascontiguousarray(arr[:, i]))
    fs = opts.fs_hz
    if "time_s" in opts.columns:
        name = opts.columns["time_s"]
        if name not in arrays:
            raise ValueError(f"{path}: no array {name!r} for the time; map yours with --columns time=NAME "
                             f"(arrays: {', '.join(names[:20])})")
        tarr = arrays[name]
        if tarr.ndim != 1 or tarr.shape[0] != n_rows:
            raise ValueError(f"{path}: time array {name!r} must have {n_rows} values (one per row of "
                             f"{mapped['gyro']!r}), got shape {tarr.shape}")
        _finite_rows(tarr, name, path)
        out["time_s"] = _arrow_array(np.ascontiguousarray(tarr))
    elif fs is None and ARRAY_LAYOUT["fs_hz"] in arrays:
        rate = arrays[ARRAY_LAYOUT["fs_hz"]]
        if rate.ndim != 0 or not (np.isfinite(rate) and MIN_FS_HZ <= float(rate) <= MAX_FS_HZ):
            raise ValueError(f"{path}: {ARRAY_LAYOUT['fs_hz']!r} must be one sample rate in {MIN_FS_HZ:g}-"
                             f"{MAX_FS_HZ:g} Hz, got {rate!r}; give --fs-hz")
        fs = float(rate)
    elif fs is None:
        raise ValueError(f"{path}: no sample rate: the file has no scalar {ARRAY_LAYOUT['fs_hz']!r}; give --fs-hz "
                         f"or map a time array with --columns time=NAME (arrays: {', '.join(names[:20])})")
    stated = (f"array layout {ARRAY_LAYOUT['gyro']}/{ARRAY_LAYOUT['accel']}/{ARRAY_LAYOUT['fs_hz']} "
              f"(the BROAD benchmark's, gyro in rad/s)") if layout else None
    return out, names, fs, stated


def _finite_rows(arr: np.ndarray, name: str, path: Path) -> None:
    """Refuse an array with a NaN/inf, naming the array and its first bad row (1-based)."""
    if not np.isfinite(arr).all():
        bad = ~np.isfinite(arr.reshape(arr.shape[0], -1)).all(axis=1)
        raise ValueError(f"{path}: array {name!r} has a non-finite value (NaN or inf) at row {int(np.argmax(bad)) + 1}")


#: Largest plausible specific force (m/s²): beyond any accelerometer's full scale (~200 g).
MAX_ACCEL_M_S2 = 2000.0


def _check_accel(accel: np.ndarray, path: Path) -> None:
    if accel.size and max(float(accel.max()), -float(accel.min())) > MAX_ACCEL_M_S2:  # no temporaries unless bad
        row, col = np.argwhere(np.abs(accel) > MAX_ACCEL_M_S2)[0]
        raise ValueError(f"{path}: accel_{'xyz'[col]} = {accel[row, col]:.4g} m/s^2 at data row {row + 1} is beyond "
                         f"any accelerometer's range ({MAX_ACCEL_M_S2:g} m/s^2): corrupt row or wrong "
                         f"--accel-scale/--accel-unit")
    sub = accel[:: max(1, accel.shape[0] // 20000)]
    med = float(np.median(np.linalg.norm(sub, axis=1)))
    if med < 2.0:
        raise ValueError(f"{path}: median |accel| is {med:.4g} after conversion, not ~9.8 m/s^2: "
                         f"accelerometer in g? use --accel-unit g (or --accel-scale for counts)")
    if med > 50.0:
        raise ValueError(f"{path}: median |accel| is {med:.4g} after conversion, not ~9.8 m/s^2: "
                         f"raw counts or mg? use --accel-scale (e.g. 1/LSB per g with --accel-unit g)")


def _check_gyro(gyro: np.ndarray, path: Path, accel: np.ndarray | None = None, dt_s: float | None = None) -> None:
    peak = max(float(gyro.max()), -float(gyro.min())) if gyro.size else 0.0  # max |gyro| without a temporary
    if peak > 40.0:
        hint = (f"gyro in mrad/s or counts? use --gyro-scale (0.001 for mrad/s; read as deg/s it would still peak "
                f"at {np.radians(peak):.4g} rad/s)")
        if peak <= 40.0 * 180.0 / np.pi:  # deg/s and mrad/s both plausible: say which tracks gravity
            hint = ("gyro in deg/s (use --gyro-unit deg/s) or mrad/s (use --gyro-scale 0.001)? "
                    + _tracking_hint(gyro, accel, dt_s))
        raise ValueError(f"{path}: peak |gyro| {peak:.4g} rad/s exceeds any MEMS full scale (~35 rad/s): {hint}")


def _check_gaps(gyro: np.ndarray, dt: np.ndarray, dt_mean: float, t: np.ndarray, path: Path, time_name: str) -> None:
    """Refuse a gap in the time column across which the per-sample dt (``ω_k dt_k / dt_mean``, module docstring)
    asks the filters for a rate no gyro measures: the rotation across the gap is not in the log."""
    from mtcal.core.validate import MAX_GYRO_RAD_S

    rate = np.abs(gyro).max(axis=1)
    k = int(np.argmax(rate * (dt / dt_mean)))
    if rate[k] * dt[k] / dt_mean > MAX_GYRO_RAD_S:
        raise ValueError(f"{path}: {time_name} jumps by {dt[k]:.4g} s between data rows {k + 1} and {k + 2} "
                         f"({float(t[k])!r} to {float(t[k + 1])!r}, {dt[k] / dt_mean:.0f}x the mean step) while the gyro reads "
                         f"{rate[k]:.3g} rad/s: the rotation across the gap is not in the log; split the log at the "
                         f"gap (or fill it)")


def _tracking_hint(gyro: np.ndarray, accel: np.ndarray | None, dt_s: float | None) -> str:
    """Which of deg/s and mrad/s carries the accelerometer's gravity direction (gravity tracking), for a message."""
    if accel is None or dt_s is None:
        return ""
    from mtcal.methods import gravity_tracking

    res = gravity_tracking.gravity_tracking(gyro, accel, dt_s, hypotheses={"deg/s": np.pi / 180, "mrad/s": 1e-3})
    if res["decision"] != "rival":
        return "gravity tracking cannot tell"
    r = res["rivals"][res["winner"]]
    return (f"gravity tracking favours {res['winner']} ({1.0 - r['win_fraction']:.2f} of {r['windows']} windows "
            f"against the stated unit; windows with linear acceleration favour the smaller rate)")


#: suffixes of the tables :func:`write_table` writes (CSV, or Parquet by suffix)
TABLE_SUFFIXES = (".csv", ".parquet", ".pq")


def check_output_path(out, inputs=(), option: str = "--out", *, suffixes=None, others=()) -> Path:
    """Refuse an output that would destroy an input or cannot be a regular file; return it as a Path.

    Messages name ``option`` (``--out``, ``--figure``), the command-line option that gave the path.
    ``suffixes``: the file types the option writes (e.g. :data:`TABLE_SUFFIXES`); ``others``: ``(option,
    path)`` of the command's other outputs, which this one must not overwrite.
    """
    o = Path(out)
    if suffixes is not None and o.suffix.lower() not in suffixes:
        raise ValueError(f"{option} {out}: the file type must be {' or '.join(dict.fromkeys(suffixes))} "
                         f"(by its suffix)")
    for other, path in others:
        if path is not None and os.path.realpath(o) == os.path.realpath(path):
            raise ValueError(f"{option} {out} is also the {other} path; give the two outputs different paths")
    for i in inputs:
        if i is None:
            continue
        try:
            same = o.exists() and Path(i).exists() and os.path.samefile(o, i)
        except OSError:
            same = False
        if same or os.path.realpath(o) == os.path.realpath(i):
            raise ValueError(f"{option} {out} is an input file ({i}); choose another output path")
    if o.exists() and o.is_dir():
        raise ValueError(f"{option}: cannot write {out}: it is a directory")
    if o.exists() and not o.is_file():
        raise ValueError(f"{option}: cannot write {out}: not a regular file")
    parent = o.parent if str(o.parent) else Path(".")
    if not parent.exists():
        raise ValueError(f"{option}: cannot write {out}: directory {parent} does not exist")
    if not parent.is_dir():
        raise ValueError(f"{option}: cannot write {out}: {parent} is not a directory")
    return o


def _atomic(path: Path, write) -> None:
    """Run ``write(tmp_path)`` then rename over ``path``; remove the temp file on any failure."""
    parent = path.parent if str(path.parent) else Path(".")
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=parent)
    except OSError as exc:
        raise OSError(f"cannot write {path}: {exc.strerror or exc}") from None
    os.close(fd)
    try:
        write(tmp)
        mode = 0o666 & ~_umask()
        os.chmod(tmp, mode)
        os.replace(tmp, path)
    except BaseException as exc:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        if isinstance(exc, OSError):
            raise OSError(f"cannot write {path}: {exc.strerror or exc}") from None
        raise


def _umask() -> int:
    m = os.umask(0)
    os.umask(m)
    return m


def write_table(path, columns: dict, *, decimals: dict | None = None) -> None:
    """Write named 1-D arrays as CSV or Parquet (by suffix), atomically.

    Floats are rounded to ``decimals[name]`` (default 6) in CSV, which the
    pyarrow writer then prints in shortest form; Parquet keeps float64. NaN
    is written as an empty field (CSV) or null (Parquet). A CSV of float and
    integer columns is printed by :mod:`mtcal.core.csvtext` (the same bytes,
    ~4x less CPU) when it can (:func:`mtcal.core.csvtext.can_format`).

    Parquet: pyarrow's defaults (snappy, statistics, 1 Mi-row groups) without dictionary
    encoding. Measured on a 1-hour 1 kHz attitude table (3.6 M rows, 9 columns, 201 MB):
    writing takes ~0.33 s of CPU (one thread; pyarrow offers no parallel column writer);
    no statistics would save ~0.05 s, no compression ~0.14 s (234 MB), lz4 ~0.07 s
    (205 MB), zstd level 1 with byte-stream split costs the same (137 MB). None is worth
    a different file: the format stays as it was.
    """
    import pyarrow as pa

    p = check_output_path(path)
    dec = decimals or {}
    parquet = p.suffix.lower() in (".parquet", ".pq")
    if not parquet and _arrow_header_unquoted():
        from mtcal.core import csvtext

        plain = {name: np.asarray(arr) for name, arr in columns.items()}
        if csvtext.can_format(plain, dec):
            def write(tmp):
                with open(tmp, "wb") as fh:
                    csvtext.write_csv(fh, plain, dec)

            _atomic(p, write)
            return
    arrays = {}
    for name, arr in columns.items():
        a = np.asarray(arr)
        if a.dtype.kind == "f" and not parquet:
            a = np.round(a, dec.get(name, 6))
        arrays[name] = _arrow_array(a)  # NaN → empty/null
    table = pa.table(arrays)
    if parquet:
        import pyarrow.parquet as pq

        # float columns do not repeat: dictionary encoding would be tried and dropped (half the write time)
        _atomic(p, lambda tmp: pq.write_table(table, tmp, use_dictionary=False))
    else:
        _atomic(p, lambda tmp: _write_csv_parallel(table, tmp))


def _arrow_array(a: np.ndarray):
    """A 1-D numpy column as an Arrow array, float NaN as null (as ``pa.array(a, from_pandas=True)``).

    Numeric columns are wrapped from their buffers (``pa.Array.from_buffers``; a contiguous
    column without a copy): pyarrow's numpy conversion imports pandas on its first call, ~0.2 s
    of a CLI call. The table, and so the written file, is the same: same type, same values,
    same nulls (byte for byte, tested).
    """
    import pyarrow as pa

    if a.ndim != 1 or a.dtype.kind not in "iuf" or not a.dtype.isnative:
        return pa.array(a, from_pandas=True) if a.dtype.kind == "f" else pa.array(a)
    if a.flags.c_contiguous:
        values = pa.py_buffer(a)  # no copy
    else:  # e.g. a column of an (N, 4) array: copied into Arrow's memory pool, which reuses the pages freed
        values = pa.allocate_buffer(a.nbytes)  # by the log reader's Arrow table (fresh numpy pages fault in)
        np.copyto(np.frombuffer(values, dtype=a.dtype), a)
    validity, nulls = None, 0
    with np.errstate(invalid="ignore", over="ignore"):
        maybe_nan = a.dtype.kind == "f" and bool(np.isnan(np.sum(a)))  # a NaN makes the sum NaN (so may inf - inf)
    if maybe_nan:  # the mask (a fresh temporary of the column's size) only then
        nan = np.isnan(a)
        nulls = int(np.count_nonzero(nan))
        if nulls:
            validity = pa.py_buffer(np.packbits(~nan, bitorder="little"))
    return pa.Array.from_buffers(pa.from_numpy_dtype(a.dtype), a.size, [validity, values], null_count=nulls)


def _arrow_header_unquoted() -> bool:
    """Whether this pyarrow writes the CSV header unquoted (``quoting_header``, pyarrow >= 19), as csvtext does."""
    import pyarrow.csv as pcsv

    try:
        pcsv.WriteOptions(quoting_header="none")
    except TypeError:
        return False
    return True


#: Rows per CSV block formatted by one thread (pyarrow's CSV writer releases the GIL).
_CSV_BLOCK_ROWS = 262_144


def _write_csv_parallel(table, path, block_rows: int = _CSV_BLOCK_ROWS) -> None:
    """Write ``table`` as CSV: blocks of rows are formatted on all cores and written in order.

    At most two blocks per core are held in memory at once, so memory stays bounded; the
    bytes are exactly those of one ``pyarrow.csv.write_csv`` call (header once, same format).
    """
    import pyarrow as pa
    import pyarrow.csv as pcsv
    from concurrent.futures import ThreadPoolExecutor

    def options(header: bool):
        try:
            return pcsv.WriteOptions(include_header=header, quoting_style="none", quoting_header="none")
        except TypeError:  # pyarrow < 19 has no quoting_header (the header is then quoted; readers accept it)
            return pcsv.WriteOptions(include_header=header, quoting_style="none")

    def block(start: int) -> bytes:
        sink = pa.BufferOutputStream()
        pcsv.write_csv(table.slice(start, block_rows), sink, write_options=options(start == 0))
        return sink.getvalue().to_pybytes()

    starts = list(range(0, max(table.num_rows, 1), block_rows))
    workers = max(1, min(os.cpu_count() or 1, len(starts)))
    with open(path, "wb") as fh, ThreadPoolExecutor(max_workers=workers) as pool:
        pending = []
        for start in starts:
            pending.append(pool.submit(block, start))
            if len(pending) >= 2 * workers:
                fh.write(pending.pop(0).result())
        for fut in pending:
            fh.write(fut.result())


def write_text(path, text: str) -> None:
    """Write a text file atomically (JSON outputs)."""
    p = check_output_path(path)

    def w(tmp):
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())

    _atomic(p, w)
