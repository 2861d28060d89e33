"""CSV text of rounded columns (mtcal.core.csvtext): byte-identical to Arrow's writer of the rounded table."""

import io

import numpy as np
import pyarrow as pa
import pyarrow.csv as pcsv
import pytest

from mtcal.core import csvtext


def _arrow(cols: dict, dec: dict) -> bytes:
    arrays = {k: pa.array(np.round(a, dec.get(k, 6)), from_pandas=True) if a.dtype.kind == "f" else a
              for k, a in cols.items()}
    sink = pa.BufferOutputStream()
    pcsv.write_csv(pa.table(arrays), sink, write_options=pcsv.WriteOptions(quoting_style="none",
                                                                           quoting_header="none"))
    return sink.getvalue().to_pybytes()


def _ours(cols: dict, dec: dict, **kw) -> bytes:
    assert csvtext.can_format(cols, dec)
    buf = io.BytesIO()
    n = csvtext.write_csv(buf, cols, dec, **kw)
    assert n == len(buf.getvalue())
    return buf.getvalue()


@pytest.mark.parametrize("seed", range(4))
def test_random_magnitudes_signs_zeros_nan_and_ties_match_arrow(seed):
    rng = np.random.default_rng(seed)
    n = 20_000
    cols, dec = {}, {}
    for j in range(6):
        d = int(rng.integers(0, 13))
        x = 10.0 ** rng.uniform(-14, 8.5, n) * rng.choice([-1.0, 1.0], n)
        x[rng.random(n) < 0.02] = 0.0
        x[rng.random(n) < 0.02] = -0.0
        x[rng.random(n) < 0.02] = np.nan
        tie = rng.random(n) < 0.05  # exact halves: numpy's round-half-even
        x[tie] = (rng.integers(-10**6, 10**6, tie.sum()) + 0.5) / 10.0**d
        limit = min(4.9e9, 2.0**51 / 10.0**d)
        cols[f"c{j}"] = np.where(np.abs(x) < limit, x, x % 1.0)
        dec[f"c{j}"] = d
    cols["flag"] = rng.integers(-100, 100, n).astype(np.int8)
    cols["count"] = rng.integers(-2**40, 2**40, n)
    assert _ours(cols, dec, block_rows=3001, threads=2) == _arrow(cols, dec)


def test_exponent_boundaries_and_negative_zero():
    x = np.array([1e-6, 9.99e-7, 1.5e-6, 1.2e-7, 5e-9, 4e-10, -4e-10, -1e-7, 12345.678901234, 999.5, 0.1, 2.5e-9])
    cols = {"x": x, "y": -x}
    dec = {"x": 9, "y": 9}
    text = _ours(cols, dec)
    assert text == _arrow(cols, dec)
    assert b"\n0.000001,-0.000001\n9.99e-7,-9.99e-7\n" in text
    assert b"\n-0,0\n" in text  # -4e-10 rounds to -0 at 9 decimals


def test_header_only_and_block_order():
    empty = {"a": np.zeros(0), "b": np.zeros(0, np.int64)}
    assert _ours(empty, {}) == b"a,b\n" == _arrow(empty, {})
    t = {"time_s": np.arange(10_000) / 1000.0}
    assert _ours(t, {}, block_rows=7, threads=2) == _arrow(t, {})


@pytest.mark.parametrize("cols, dec, why", [
    ({"x": np.array([1.0, np.inf])}, {}, "infinite"),
    ({"x": np.array([2e10])}, {}, "exponent notation from 1e10"),
    ({"x": np.array([1e7])}, {"x": 9}, "|K| >= 2^52"),
    ({"x": np.array([1.0])}, {"x": 16}, "too many decimals"),
    ({"x": np.array([True])}, {}, "bool prints true/false"),
    ({"x": np.zeros(3), "y": np.zeros(2)}, {}, "ragged"),
    ({"x": np.zeros((2, 2))}, {}, "not 1-D"),
    ({}, {}, "no columns"),
])
def test_can_format_refuses_what_it_cannot_print_exactly(cols, dec, why):
    assert not csvtext.can_format(cols, dec), why
