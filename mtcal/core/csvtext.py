"""CSV text of rounded numeric columns, byte for byte what Arrow's CSV writer prints, ~4x faster.

A table whose float columns are rounded to a fixed number of decimals (``np.round(x, d)``)
and written by ``pyarrow.csv.write_csv`` (shortest round-trip digits; exponent notation
below 1e-6 and from 1e10, ``-0`` for a negative zero, an empty field for NaN) can be
printed without the general shortest-digits algorithm: the rounded value is the double
nearest to ``K·10^-d`` with the integer ``K = rint(x·10^d)``, and as long as
``|K| < 2^52`` its spacing is below ``10^-d``, so its shortest round-trip digits are
those of ``K`` with trailing zeros dropped. :func:`write_csv` prints them from
``K`` in a compiled loop, blocks of rows on all cores; :func:`can_format` says when
a table qualifies (otherwise the caller uses Arrow's writer, which prints every
double). Integer columns print as integers.

Examples
--------
>>> import io
>>> import numpy as np
>>> cols = {"t": np.array([0.0, 0.001, 1e-7]), "q": np.array([-1e-12, 0.5, 3.25e-8]), "k": np.array([0, 1, 1], np.int8)}
>>> can_format(cols, {"q": 9})
True
>>> buf = io.BytesIO()
>>> write_csv(buf, cols, {"q": 9})
36
>>> print(buf.getvalue().decode(), end="")
t,q,k
0,-0,0
0.001,0.5,1
0,3.2e-8,1
"""

from __future__ import annotations

import os

import numpy as np

__all__ = ["can_format", "write_csv", "warm_up", "DEFAULT_DECIMALS", "MAX_DECIMALS"]

#: Decimals of a float column not named in ``decimals``.
DEFAULT_DECIMALS = 6
#: Most decimals :func:`write_csv` prints (10^d exact, K < 2^52 leaves room for the integer part).
MAX_DECIMALS = 15
#: Rows per block (formatted by one thread; a block's text is ~100 bytes a row).
BLOCK_ROWS = 65_536
#: Arrow switches to exponent notation from this magnitude (``1e+10``).
_EXP_HIGH = 1e10
_K_MAX = 2.0**52


def _kernel():
    from mtcal.core import _csvtext_kernel

    return _csvtext_kernel.format_block


def can_format(columns: dict, decimals: dict | None = None) -> bool:
    """Whether :func:`write_csv` prints ``columns`` exactly as Arrow's writer prints the rounded table.

    Parameters
    ----------
    columns : dict of str to ndarray (N,)
        Float (rounded to ``decimals[name]``, default :data:`DEFAULT_DECIMALS`) or integer columns,
        all of length N.
    decimals : dict of str to int, optional

    Returns
    -------
    bool
        False for another dtype (bool, strings, …), an infinite value, decimals outside
        0 … :data:`MAX_DECIMALS`, or a magnitude at which the shortest digits are not those of
        ``K`` (``|x| 10^d ≥ 2^52``) or Arrow prints an exponent (``|x| ≥ 1e10``).
    """
    dec = decimals or {}
    n = None
    for name, arr in columns.items():
        a = np.asarray(arr)
        if a.ndim != 1 or (n is not None and a.shape[0] != n):
            return False
        n = a.shape[0]
        if a.dtype.kind in "iu":
            if a.size and a.dtype.itemsize == 8 and max(abs(int(a.max())), abs(int(a.min()))) >= 2**53:
                return False
            continue
        if a.dtype.kind != "f":
            return False
        d = dec.get(name, DEFAULT_DECIMALS)
        if not isinstance(d, (int, np.integer)) or not 0 <= d <= MAX_DECIMALS:
            return False
        if a.size:
            with np.errstate(invalid="ignore"):
                peak = max(float(np.nanmax(a, initial=0.0)), -float(np.nanmin(a, initial=0.0)))
            if not (peak < _EXP_HIGH / 2 and peak * 10.0**d < _K_MAX / 2):  # inf fails too
                return False
    return n is not None


def write_csv(file, columns: dict, decimals: dict | None = None, *, header: bool = True,
              block_rows: int = BLOCK_ROWS, threads: int | None = None) -> int:
    """Write the CSV text of ``columns`` to the binary ``file``: header line, then blocks of rows, in order.

    Byte-identical to ``pyarrow.csv.write_csv`` (``quoting_style="none"``,
    ``quoting_header="none"``) of the table whose float columns are ``np.round(x, d)``
    (NaN as an empty field); the caller checks :func:`can_format` first.

    Parameters
    ----------
    file : binary file object
        Anything with ``write(bytes-like)`` (a file opened ``"wb"``, ``io.BytesIO``).
    columns : dict of str to ndarray (N,)
        Float or integer columns, in output order.
    decimals : dict of str to int, optional
        Decimals per float column (default :data:`DEFAULT_DECIMALS`).
    header : bool
        Start with the column names.
    block_rows : int
        Rows per block (one block is formatted by one thread).
    threads : int, optional
        Threads formatting blocks (default: the CPU count); at most two blocks per thread
        wait, in buffers reused from block to block (memory stays bounded, no fresh pages).

    Returns
    -------
    int
        Bytes written.
    """
    from concurrent.futures import ThreadPoolExecutor

    fmt = _kernel()
    dec = decimals or {}
    names = list(columns)
    arrays = [np.asarray(columns[k]) for k in names]
    n = arrays[0].shape[0] if arrays else 0
    is_int = np.array([a.dtype.kind in "iu" for a in arrays], np.bool_)
    d = np.array([0 if i else dec.get(k, DEFAULT_DECIMALS) for k, i in zip(names, is_int)], np.int64)
    factor = np.array([10.0 ** int(x) for x in d])          # numpy's power_of_ten: exact up to 1e22
    p10 = np.array([10 ** int(x) for x in d], np.int64)
    # longest field: sign, 10 integer digits, '.', d decimals, separator; exponent form (d >= 7): sign,
    # 16 digits, '.', 'e-NN', separator; an integer: sign, 19 digits, separator; plus the newline
    row_bytes = 1 + sum(22 if i else max(14 + int(x), 24) for i, x in zip(is_int, d))
    written = 0
    if header:
        written += file.write((",".join(names) + "\n").encode("utf-8"))
    starts = list(range(0, n, block_rows))
    if not starts:
        return written
    workers = max(1, min(threads or os.cpu_count() or 1, len(starts)))
    rows = min(block_rows, n)
    slots = [(np.empty((rows, len(arrays))), np.empty(rows * row_bytes, np.uint8))
             for _ in range(2 * workers + 1)]  # in flight: 2 x workers blocks, one more being written

    def block(i: int) -> memoryview:
        start = starts[i]
        stop = min(start + block_rows, n)
        vals, out = slots[i % len(slots)]
        vals = vals[: stop - start]
        for j, a in enumerate(arrays):
            vals[:, j] = a[start:stop]
        return memoryview(out[: fmt(vals, factor, p10, d, is_int, out)])

    if workers == 1:
        for i in range(len(starts)):
            written += file.write(block(i))
        return written
    with ThreadPoolExecutor(max_workers=workers) as pool:
        pending = []
        for i in range(len(starts)):
            pending.append(pool.submit(block, i))
            if len(pending) >= 2 * workers:
                written += file.write(pending.pop(0).result())
        for fut in pending:
            written += file.write(fut.result())
    return written


def warm_up() -> None:
    """Compile (or load from numba's cache) the formatting kernel."""
    import io

    cols = {"x": np.array([0.5, -1e-8, np.nan]), "k": np.array([1, 0, -2], np.int8)}
    write_csv(io.BytesIO(), cols, {"x": 9})
