"""The one log reader/writer of the CLI: adapters, checks, atomic outputs, one-line errors."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from mtcal import cli
from mtcal.cli import logio

from . import logs

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def base():
    return logs.hinge_log(angles_deg=(0, 40, 80, 20), hold_s=1.0)


def _read(tmp_path, df, name="x.csv", **kw):
    p = tmp_path / name
    if name.endswith(".parquet"):
        df.to_parquet(p, index=False)
    else:
        df.to_csv(p, index=False)
    return logio.read_log(p, logio.InputOptions(**kw))


def test_units_scales_and_headers_agree(base, tmp_path):
    ref = _read(tmp_path, base.df)
    df = base.df.copy()
    df[[c for c in df if c.startswith("gyro")]] = np.degrees(df[[c for c in df if c.startswith("gyro")]])
    df[[c for c in df if c.startswith("accel")]] /= 9.80665
    df["time_s"] *= 1000.0
    got = _read(tmp_path, df, time_unit="ms", gyro_unit="deg/s", accel_unit="g")
    np.testing.assert_allclose(got.gyro_rad_s, ref.gyro_rad_s, rtol=1e-12)
    np.testing.assert_allclose(got.accel_m_s2, ref.accel_m_s2, rtol=1e-12)
    np.testing.assert_allclose(got.time_s, ref.time_s, rtol=1e-12)
    # unit-carrying headers, whitespace, and a column map with short keys
    renamed = df.rename(columns=lambda c: " " + c.replace("_rad_s", "_deg_s").replace("_m_s2", "_g")
                        .replace("time_s", "time_ms") + " ")
    got = _read(tmp_path, renamed)
    np.testing.assert_allclose(got.gyro_rad_s, ref.gyro_rad_s, rtol=1e-12)
    assert any("deg/s" in n for n in got.notes) and any("ms" in n for n in got.notes)
    custom = base.df.rename(columns={"time_s": "T", "gyro_x_rad_s": "GyrX", "accel_z_m_s2": "AccZ"})
    got = _read(tmp_path, custom, columns=logio.parse_columns("time=T, gyro_x = GyrX,accel_z_m_s2=AccZ"))
    np.testing.assert_array_equal(got.accel_m_s2, ref.accel_m_s2)


def test_per_axis_counts_scale(base, tmp_path):
    ref = _read(tmp_path, base.df)
    df = base.df.copy()
    lsb = np.array([0.001, 0.002, 0.004])
    for i, ax in enumerate("xyz"):
        df[f"accel_{ax}_m_s2"] = df[f"accel_{ax}_m_s2"] / lsb[i]
    got = _read(tmp_path, df, accel_scale=logio.parse_scale("0.001,0.002,0.004", "--accel-scale"))
    np.testing.assert_allclose(got.accel_m_s2, ref.accel_m_s2, rtol=1e-12)


def test_parquet_in_equals_csv_in(base, tmp_path):
    a = _read(tmp_path, base.df, "x.csv")
    b = _read(tmp_path, base.df, "x.parquet")
    np.testing.assert_allclose(a.gyro_rad_s, b.gyro_rad_s, rtol=1e-15)


def test_semicolon_and_string_columns(base, tmp_path):
    p = tmp_path / "semi.csv"
    df = base.df.copy()
    df.to_csv(p, index=False, sep=";")
    got = logio.read_log(p)
    assert got.n == len(df)
    df2 = df.astype({"accel_x_m_s2": str})
    df2.loc[7, "accel_x_m_s2"] = "n/a"
    df2.to_csv(p, index=False)
    with pytest.raises(ValueError, match=r"non-numeric or NaN value in column 'accel_x_m_s2' at data row 8"):
        logio.read_log(p)


def test_jitter_per_sample_dt(tmp_path):
    log = logs.hinge_log(jitter_ms=(3, 7))
    got = _read(tmp_path, log.df)
    assert got.jitter > 0.3 and any("per-sample dt" in n for n in got.notes)
    w = got.gyro_for_filter()
    # integrated angle uses the recorded intervals: sum(w_eff * dt_mean) == sum(w * dt_k)
    np.testing.assert_allclose(w.sum(axis=0) * got.dt_mean_s, (got.gyro_rad_s * got.dt_s[:, None]).sum(axis=0),
                               rtol=1e-12)


@pytest.mark.parametrize("mutate,match", [
    (lambda d: d.assign(time_s=d.time_s * 1000), "implausible.*--time-unit ms"),
    (lambda d: d.assign(time_s=d.time_s / 1000), "implausible"),
    (lambda d: d.drop(columns=["gyro_y_rad_s"]), "missing columns gyro_y_rad_s"),
    (lambda d: d.iloc[:5], "at least 10 samples"),
    (lambda d: d.assign(time_s=d.time_s.where(d.index != 20, 0.0)), "not strictly increasing at data row 21"),
    (lambda d: d.assign(accel_x_m_s2=d.accel_x_m_s2 / 9.80665, accel_y_m_s2=d.accel_y_m_s2 / 9.80665,
                        accel_z_m_s2=d.accel_z_m_s2 / 9.80665), "--accel-unit g"),
    (lambda d: d.assign(gyro_x_rad_s=d.gyro_x_rad_s * 57.3 * 16.4), "--gyro-unit deg/s"),
    (lambda d: d.assign(accel_z_m_s2=d.accel_z_m_s2.where(d.index != 3, 1e308)),
     "accel_z = 1e\\+308 m/s\\^2 at data row 4 is beyond"),
])
def test_bad_logs(base, tmp_path, mutate, match):
    with pytest.raises(ValueError, match=match):
        _read(tmp_path, mutate(base.df))


def test_bad_options():
    with pytest.raises(ValueError, match="--gyro-scale must be one or three"):
        logio.parse_scale("1,2", "--gyro-scale")
    with pytest.raises(ValueError, match="one or three finite non-zero"):
        logio.parse_scale("0", "--gyro-scale")
    with pytest.raises(ValueError, match="unknown name 'gyro_w'"):
        logio.parse_columns("gyro_w=A")
    with pytest.raises(ValueError, match="name=header"):
        logio.parse_columns("gyro_x")
    with pytest.raises(ValueError, match="--time-unit must be one of"):
        logio.InputOptions(time_unit="min")


def test_columns_map_to_missing_header(base, tmp_path):
    with pytest.raises(ValueError, match="--columns maps time_s to 'Zeit'"):
        _read(tmp_path, base.df, columns={"time_s": "Zeit"})


def test_empty_and_garbage_files(tmp_path):
    (tmp_path / "empty.csv").write_text("")
    with pytest.raises(ValueError, match="empty file"):
        logio.read_log(tmp_path / "empty.csv")
    (tmp_path / "bad.parquet").write_bytes(b"not parquet at all")
    with pytest.raises(ValueError, match="not a readable Parquet"):
        logio.read_log(tmp_path / "bad.parquet")
    (tmp_path / "bin.csv").write_bytes(bytes(range(256)) * 10)
    with pytest.raises(ValueError):
        logio.read_log(tmp_path / "bin.csv")
    with pytest.raises(ValueError, match="not a regular file"):
        logio.read_log(tmp_path)


# ------------------------------------------------------------------ outputs
def test_write_csv_and_parquet_round_trip(tmp_path):
    t = np.arange(5) / 100.0
    cols = {"time_s": t, "angle_deg": np.array([0.1234567891, 1, 2, 3, 4.0]), "is_static": np.int8([1, 0, 0, 1, 1])}
    logio.write_table(tmp_path / "a.csv", cols)
    text = (tmp_path / "a.csv").read_text()
    assert text.splitlines()[0] == "time_s,angle_deg,is_static" and "0.123457" in text
    logio.write_table(tmp_path / "a.parquet", cols)
    back = pd.read_parquet(tmp_path / "a.parquet")
    assert back.angle_deg.iloc[0] == 0.1234567891
    assert sorted(os.listdir(tmp_path)) == ["a.csv", "a.parquet"]  # no temp files left


@pytest.mark.parametrize("target,match", [
    ("{d}", "is a directory"),
    ("{d}/nodir/x.csv", "does not exist"),
    ("{d}/file.txt/x.csv", "is not a directory"),
    ("/dev/full", "not a regular file"),
])
def test_bad_output_paths(tmp_path, target, match):
    (tmp_path / "file.txt").write_text("keep")
    with pytest.raises(ValueError, match=match):
        logio.write_table(target.format(d=tmp_path), {"a": np.zeros(3)})


def test_out_equal_to_input_refused(base, tmp_path, capsys):
    p = tmp_path / "log.csv"
    base.df.to_csv(p, index=False)
    before = p.read_bytes()
    for out in (p, tmp_path / "." / "log.csv"):
        assert cli.main(["angle", str(p), "--axis", "0.6,0,0.8", "--out", str(out)]) == 2
        assert "is an input file" in capsys.readouterr().err
    assert p.read_bytes() == before


def test_failed_write_keeps_existing_output(base, tmp_path):
    """A write that hits the file-size limit leaves the old output intact and no temp file (subprocess)."""
    p = tmp_path / "log.csv"
    base.df.to_csv(p, index=False)
    out = tmp_path / "angle.csv"
    out.write_text("old result\n")
    code = ("import resource, sys; resource.setrlimit(resource.RLIMIT_FSIZE, (4000, 4000)); "
            "from mtcal.cli import main; sys.exit(main(sys.argv[1:]))")
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    env.pop("MTCAL_DEBUG", None)
    proc = subprocess.run([sys.executable, "-c", code, "angle", str(p), "--axis", "0.6,0,0.8", "--out", str(out)],
                          capture_output=True, text=True, env=env, timeout=120)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.startswith("mtcal: error: cannot write") and proc.stderr.count("\n") == 1
    assert "Traceback" not in proc.stderr
    assert out.read_text() == "old result\n"
    assert sorted(os.listdir(tmp_path)) == ["angle.csv", "log.csv"]


def test_fs_hz_for_a_log_without_time(base, tmp_path):
    ref = _read(tmp_path, base.df)
    got = _read(tmp_path, base.df.drop(columns=["time_s"]), fs_hz=200.0)
    np.testing.assert_allclose(got.time_s, ref.time_s - ref.time_s[0], atol=1e-9)
    assert got.fs_hz == pytest.approx(200.0) and "time from --fs-hz 200" in got.notes
    with pytest.raises(ValueError, match="or give --fs-hz"):
        _read(tmp_path, base.df.drop(columns=["time_s"]))
    with pytest.raises(ValueError, match="--fs-hz must be a sample rate"):
        logio.InputOptions(fs_hz=1e6)


def test_only_needed_columns_parsed_and_all_listed_in_errors(base, tmp_path):
    df = base.df.rename(columns={"time_s": "T"}).assign(mag_x=1.0, note="text")
    p = tmp_path / "extra.csv"
    df.to_csv(p, index=False)
    with pytest.raises(ValueError, match="missing column time_s \\(columns: T, gyro_x_rad_s.*mag_x, note\\)"):
        logio.read_log(p)
    got = logio.read_log(p, logio.InputOptions(columns={"time_s": "T"}))
    np.testing.assert_array_equal(got.accel_m_s2, _read(tmp_path, base.df).accel_m_s2)


def test_parallel_csv_writer_gives_the_bytes_of_one_pyarrow_write(tmp_path):
    import pyarrow as pa
    import pyarrow.csv as pcsv

    from mtcal.cli import logio

    n = 10_007
    table = pa.table({"time_s": np.round(np.arange(n) / 1000.0, 6),
                      "x": pa.array(np.where(np.arange(n) % 97 == 0, np.nan, np.sin(np.arange(n))), from_pandas=True),
                      "is_static": np.arange(n) % 3 == 0})
    logio._write_csv_parallel(table, tmp_path / "blocks.csv", block_rows=1000)
    pcsv.write_csv(table, tmp_path / "one.csv",
                   write_options=pcsv.WriteOptions(quoting_style="none", quoting_header="none"))
    assert (tmp_path / "blocks.csv").read_bytes() == (tmp_path / "one.csv").read_bytes()


def _columns_of_every_kind():
    rng = np.random.default_rng(3)
    x = rng.normal(size=1001)
    x[[0, 17, 999]] = np.nan
    return {"f64": rng.normal(size=1001), "f64_nan": x, "f64_strided": np.repeat(x, 2)[::2],
            "f32": x.astype(np.float32), "i8": (x > 0).astype(np.int8), "i64": np.arange(1001),
            "u16": np.arange(1001, dtype=np.uint16), "bool": x > 0, "reversed": x[::-1]}


def test_arrow_columns_are_those_of_pyarrows_numpy_conversion():
    import pyarrow as pa

    for name, a in _columns_of_every_kind().items():
        ref = pa.array(a, from_pandas=True) if a.dtype.kind == "f" else pa.array(a)
        got = logio._arrow_array(a)
        assert got.type == ref.type and got.null_count == ref.null_count and got.equals(ref), name
    allnan = logio._arrow_array(np.full(9, np.nan))
    assert allnan.null_count == 9 and len(logio._arrow_array(np.zeros(0))) == 0


def test_parquet_and_csv_bytes_are_those_of_the_numpy_conversion(tmp_path):
    """write_table wraps numeric columns from their buffers: the files are byte for byte those written from
    ``pa.array(a, from_pandas=True)`` columns (the conversion used before), Parquet and CSV."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    cols = _columns_of_every_kind()
    logio.write_table(tmp_path / "got.parquet", cols)
    ref = pa.table({k: pa.array(a, from_pandas=True) if a.dtype.kind == "f" else a for k, a in cols.items()})
    pq.write_table(ref, tmp_path / "ref.parquet", use_dictionary=False)
    assert (tmp_path / "got.parquet").read_bytes() == (tmp_path / "ref.parquet").read_bytes()
    back = pq.read_table(tmp_path / "got.parquet")
    assert back.equals(ref) and back.column("f64_nan").null_count == 3
    logio.write_table(tmp_path / "got.csv", cols)
    rounded = {k: np.round(a, 6) if a.dtype.kind == "f" else a for k, a in cols.items()}
    ref = pa.table({k: pa.array(a, from_pandas=True) if a.dtype.kind == "f" else a for k, a in rounded.items()})
    logio._write_csv_parallel(ref, tmp_path / "ref.csv")
    assert (tmp_path / "got.csv").read_bytes() == (tmp_path / "ref.csv").read_bytes()


def test_writing_a_table_does_not_import_pandas(tmp_path):
    """pyarrow's numpy conversion imports pandas (~0.2 s of a CLI call); write_table's numeric columns do not."""
    code = ("import sys, numpy as np; from mtcal.cli import logio; "
            "cols = {'t': np.arange(5) / 10, 'x': np.array([1.0, np.nan, 2, 3, 4]), 'k': np.int8([1, 0, 0, 1, 1])}; "
            "logio.write_table(sys.argv[1] + '/a.parquet', cols); logio.write_table(sys.argv[1] + '/a.csv', cols); "
            "print('pandas' in sys.modules)")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT)] + [p for p in os.environ.get("PYTHONPATH", "").split(
        os.pathsep) if p]))
    res = subprocess.run([sys.executable, "-c", code, str(tmp_path)], env=env, capture_output=True, text=True)
    assert res.returncode == 0 and res.stdout.strip() == "False", res.stderr[-2000:]
    assert sorted(os.listdir(tmp_path)) == ["a.csv", "a.parquet"]


def test_arrow_columns_with_infinities_but_no_nan():
    a = np.array([np.inf, -np.inf, 1.0, np.nan])
    got = logio._arrow_array(a[:3])  # inf - inf sums to NaN: no null all the same
    assert got.null_count == 0 and got.to_pylist() == [np.inf, -np.inf, 1.0]
    assert logio._arrow_array(a).null_count == 1


def test_read_log_prewarms_numba_once_and_swallows_its_failures(base, tmp_path, monkeypatch):
    """read_log starts one background load of numba's machinery per process; a failure there is not the
    command's (the command reports its own errors), and a bad log still fails with its own message."""
    import threading

    from numba.core.registry import cpu_target

    csv = tmp_path / "log.csv"
    base.write(csv)
    calls = []

    def boom():
        calls.append(threading.current_thread().name)
        raise RuntimeError("registry failure")

    monkeypatch.setattr(logio, "_PREWARM", [])
    monkeypatch.setattr(cpu_target.target_context, "refresh", boom)
    monkeypatch.delitem(sys.modules, "numba.np.arraymath")
    log = logio.read_log(csv)
    logio.read_log(csv)
    assert len(logio._PREWARM) == 1
    logio._PREWARM[0].join()
    assert calls == ["mtcal-prewarm"] and log.n == len(base.df)
    with pytest.raises(ValueError, match="log file not found"):
        logio.read_log(tmp_path / "missing.csv")


@pytest.mark.parametrize("name", ["x.csv", "x.parquet"])
def test_a_column_read_twice_under_one_name_is_refused(base, tmp_path, name):
    """Two headers named accel_x_m_s2: which copy is meant is unknown, so the log is refused (not the last copy)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    df = base.df
    cols = [pa.array(df[c].to_numpy()) for c in df.columns] + [pa.array(np.full(len(df), 5.0))]
    table = pa.Table.from_arrays(cols, names=list(df.columns) + ["accel_x_m_s2"])
    p = tmp_path / name
    pq.write_table(table, p) if name.endswith(".parquet") else pa.csv.write_csv(table, p)
    with pytest.raises(ValueError, match="column 'accel_x_m_s2' appears 2 times in the header; rename the copies"):
        logio.read_log(p, need="raw")
    extra = table.rename_columns(list(df.columns) + ["temperature"]).append_column("temperature",
                                                                                  pa.array(np.ones(len(df))))
    q = tmp_path / ("t_" + name)
    pq.write_table(extra, q) if name.endswith(".parquet") else pa.csv.write_csv(extra, q)
    assert logio.read_log(q, need="raw").n == len(df)          # a repeated column the reader does not use: read


@pytest.mark.parametrize("columns,match", [
    ({"gyro_x_rad_s": "gyro_y_rad_s"}, "--columns maps gyro_x_rad_s to 'gyro_y_rad_s', which is also read as "
                                       "gyro_y_rad_s; map each quantity to its own column"),
    ({"gyro_x_rad_s": "accel_x_m_s2"}, "--columns maps gyro_x_rad_s to 'accel_x_m_s2', which is also read as "
                                       "accel_x_m_s2"),
])
def test_columns_mapping_one_header_to_two_quantities_is_refused(base, tmp_path, columns, match):
    p = tmp_path / "x.csv"
    base.df.to_csv(p, index=False)
    with pytest.raises(ValueError, match=match):
        logio.read_log(p, logio.InputOptions(columns=columns), need="accel")


def test_a_partial_gyro_set_is_named_not_dropped_silently(base, tmp_path):
    p = tmp_path / "x.csv"
    base.df.drop(columns=["gyro_z_rad_s"]).to_csv(p, index=False)
    log = logio.read_log(p, need="accel")
    assert log.gyro_rad_s is None
    assert "gyro not used: gyro_z_rad_s missing (only gyro_x_rad_s, gyro_y_rad_s in the log)" in log.notes
    with pytest.raises(ValueError, match="missing columns gyro_z_rad_s"):
        logio.read_log(p, need="raw")


def test_a_gap_the_gyro_cannot_have_turned_across_is_named(base, tmp_path):
    """A 0.5 s hole while the gyro reads over 0.4 rad/s: per-sample dt would ask the filter for > 40 rad/s, so the
    reader names the gap (not the gyro's unit); the same hole during a rest is read (the rotation is known: none)."""
    df = base.df.copy()
    w = np.abs(df[["gyro_x_rad_s", "gyro_y_rad_s", "gyro_z_rad_s"]].to_numpy()).max(axis=1)
    moving, still = int(np.argmax(w)), int(np.argmin(w[: len(w) // 2]))
    for k, ok in ((moving, False), (still, True)):
        gap = df.copy()
        gap.loc[k + 1:, "time_s"] += 0.5
        p = tmp_path / f"gap{k}.csv"
        gap.to_csv(p, index=False)
        if ok:
            assert any("gap(s) > 5x the median dt" in n for n in logio.read_log(p, need="raw").notes)
            continue
        with pytest.raises(ValueError, match=rf"time_s jumps by 0.5\d* s between data rows {k + 1} and {k + 2} "
                                             r"\(.* the mean step\) while the gyro reads .* rad/s: the rotation "
                                             r"across the gap is not in the log"):
            logio.read_log(p, need="raw")


def test_out_must_be_a_table_and_not_the_figure(base, tmp_path, capsys):
    p = tmp_path / "x.csv"
    base.df.to_csv(p, index=False)
    for extra, match in ((["--out", str(tmp_path / "a.xlsx")], "--out .*a.xlsx: the file type must be .csv or "
                                                                 ".parquet or .pq"),
                         (["--out", str(tmp_path / "a.csv"), "--figure", str(tmp_path / "a.csv")],
                          "--out .*a.csv is also the --figure path; give the two outputs different paths")):
        assert cli.main(["attitude", str(p)] + extra) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and pytest.importorskip("re").search(match, err), err
    assert not (tmp_path / "a.xlsx").exists() and not (tmp_path / "a.csv").exists()
