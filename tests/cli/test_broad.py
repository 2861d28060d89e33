"""The command line on BROAD's real recordings (broad2021, datasets/broad2021/trials): units, formats, filters, rests.

Every shipped trial in the right units is accepted; the same trial mislabelled (deg/s or mrad/s under rad/s
headers, time in ms under time_s) is refused with one ``mtcal: error:`` line naming the option. Rests are
compared with the optical reference. Full trials where the check needs them, slices elsewhere (speed).
"""

import argparse
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from mtcal import cli
from mtcal.cli import attitude, common, logio
from mtcal.core.arrayfile import read_arrays
from mtcal.systems import plausibility

from .test_realistic_logs import _refused, _run

TRIALS = sorted((Path(__file__).resolve().parents[2] / "datasets" / "broad2021" / "trials").glob("*.mat"))
BREAKS = [p for p in TRIALS if "with_breaks" in p.name]


def _defaults(extra=()):
    p = argparse.ArgumentParser()
    common.add_input_options(p)
    common.add_rest_options(p, min_rest_s=0.2)
    return p.parse_args(list(extra))


def _csv(path, arrays, *, gyro_factor=1.0, time_factor=1.0, rows=None):
    g, a = arrays["imu_gyr"], arrays["imu_acc"]
    sl = slice(None) if rows is None else slice(0, rows)
    t = np.arange(g.shape[0]) / float(arrays["sampling_rate"]) * time_factor
    df = pd.DataFrame({"time_s": t[sl], **{f"gyro_{c}_rad_s": g[sl, i] * gyro_factor for i, c in enumerate("xyz")},
                       **{f"accel_{c}_m_s2": a[sl, i] for i, c in enumerate("xyz")}})
    df.to_csv(path, index=False)
    return path


def test_broad_trials_ship():
    assert len(TRIALS) == 14 and len(BREAKS) == 3


@pytest.mark.parametrize("path", TRIALS, ids=lambda p: p.name[:2])
def test_units_check_right_both_ways(path):
    """Right units accepted (decided, or warned as stated); deg/s and mrad/s under rad/s refused naming the option."""
    log = logio.read_log(path)
    assert log.gyro_unit_stated and "imu_gyr" in log.gyro_unit_stated
    rep = common.detect(_defaults(), log)
    args = (log.accel_m_s2, log.dt_mean_s, rep.rests)
    ok = plausibility.check_units(log.gyro_rad_s, *args, unit_stated=log.gyro_unit_stated)
    assert ok["method"] in ("rest pairs", "tilt rate", "gravity tracking", "stated unit (unchecked)"), ok
    assert ("warning" in ok) == (ok["method"] == "stated unit (unchecked)")
    with pytest.raises(ValueError, match="gyro (units|implausible).*(--gyro-unit deg/s|--gyro-scale 0.001)"):
        plausibility.check_units(np.degrees(log.gyro_rad_s), *args, unit_stated="header gyro_x_rad_s")
    with pytest.raises(ValueError, match="gyro (units|implausible).*(--gyro-scale 0.001|time in ms read as s)"):
        plausibility.check_units(1e3 * log.gyro_rad_s, *args, unit_stated="header gyro_x_rad_s")


@pytest.mark.parametrize("path", TRIALS[:1] + TRIALS[5:6], ids=lambda p: p.name[:2])
def test_cli_accepts_and_refuses_mislabelled_csv(path, tmp_path, capsys):
    arrays = read_arrays(path)
    good = _csv(tmp_path / "good.csv", arrays)
    code, out, err = _run(["attitude", good, "--out", tmp_path / "att.csv"], capsys)
    assert code == 0, err
    assert re.search(r"gyro units check \((tilt rate|gravity tracking|rest pairs)\)|warning: gyro unit as stated", out)
    code, out, err = _run(["rests", good], capsys)
    assert code == 0, err
    _refused(*_run(["attitude", _csv(tmp_path / "deg.csv", arrays, gyro_factor=180 / np.pi), "--out",
                    tmp_path / "o.csv"], capsys)[::2], "--gyro-unit deg/s")
    _refused(*_run(["attitude", _csv(tmp_path / "mrad.csv", arrays, gyro_factor=1e3), "--out",
                    tmp_path / "o.csv"], capsys)[::2], "--gyro-scale (0.001 for mrad/s")
    _refused(*_run(["attitude", _csv(tmp_path / "ms.csv", arrays, time_factor=1e3), "--out",
                    tmp_path / "o.csv"], capsys)[::2], "--time-unit ms")
    assert not (tmp_path / "o.csv").exists()


def test_stated_deg_s_gives_the_rad_s_attitude(tmp_path, capsys):
    arrays = read_arrays(TRIALS[6])   # 14: slow translation, no check decides
    rad = _csv(tmp_path / "rad.csv", arrays)
    deg = _csv(tmp_path / "deg.csv", arrays, gyro_factor=180 / np.pi)
    code, out, err = _run(["attitude", rad, "--out", tmp_path / "a.csv"], capsys)
    assert code == 0, err
    code, out, err = _run(["attitude", deg, "--gyro-unit", "deg/s", "--out", tmp_path / "b.csv"], capsys)
    assert code == 0, err
    assert out.count("warning: gyro unit as stated (--gyro-unit deg/s)") <= 1
    a, b = pd.read_csv(tmp_path / "a.csv"), pd.read_csv(tmp_path / "b.csv")
    dot = np.abs(np.sum(a[["q0", "q1", "q2", "q3"]].to_numpy() * b[["q0", "q1", "q2", "q3"]].to_numpy(), axis=1))
    assert float(np.degrees(2 * np.arccos(np.minimum(dot, 1.0))).max()) < 0.05


def test_angle_units_check_accepts_broad(tmp_path, capsys):
    """`mtcal angle` runs the same units check: a BROAD trial is not refused for its units (it is no hinge, so
    the axis mismatch check is relaxed here)."""
    code, out, err = _run(["angle", TRIALS[0], "--axis", "1,0,0", "--max-axis-mismatch-deg", "180",
                           "--out", tmp_path / "angle.csv"], capsys)
    assert code == 0, err
    assert "gyro units check (" in out or "warning: gyro unit as stated" in out


# ----------------------------------------------------------------------------------------- file formats
def _h5(path, **arrays):
    import h5py

    with h5py.File(path, "w") as f:
        for k, v in arrays.items():
            f[k] = v
    return path


@pytest.fixture(scope="module")
def broad_slice():
    arr = read_arrays(TRIALS[0])
    n = int(40 * float(arr["sampling_rate"]))   # 40 s: rest, then rotation
    return {"imu_gyr": arr["imu_gyr"][:n], "imu_acc": arr["imu_acc"][:n], "sampling_rate": arr["sampling_rate"],
            "opt_quat": arr["opt_quat"][:n]}


def test_broad_mat_opens_without_options(tmp_path, capsys):
    code, out, err = _run(["attitude", TRIALS[0], "--out", tmp_path / "att.csv"], capsys)
    assert code == 0, err
    df = pd.read_csv(tmp_path / "att.csv")
    assert list(df.columns) == ["time_s", "q0", "q1", "q2", "q3", "yaw_deg", "pitch_deg", "roll_deg", "is_static"]
    assert len(df) == read_arrays(TRIALS[0])["imu_gyr"].shape[0]
    assert "time from sampling_rate 285.714" in out


def test_h5_and_mat_v73_and_column_mapping(tmp_path, broad_slice, capsys):
    import scipy.io

    s = broad_slice
    rec = _h5(tmp_path / "rec.h5", **s)
    mapped = _h5(tmp_path / "mapped.hdf5", gyr=s["imu_gyr"], acc=s["imu_acc"],
                 t=np.arange(s["imu_gyr"].shape[0]) / float(s["sampling_rate"]))
    v5 = tmp_path / "v5.mat"
    scipy.io.savemat(v5, {"G": s["imu_gyr"], "A": s["imu_acc"]})
    outs = []
    for args in ([rec], [mapped, "--columns", "gyro=gyr,accel=acc,time=t", "--gyro-unit", "rad/s"],
                 [v5, "--columns", "gyro=G,accel=A", "--fs-hz", str(float(s["sampling_rate"])), "--gyro-unit",
                  "rad/s"]):
        out = tmp_path / f"o{len(outs)}.csv"
        code, text, err = _run(["attitude", *args, "--out", out], capsys)
        assert code == 0, err
        outs.append(pd.read_csv(out)[["q0", "q1", "q2", "q3"]].to_numpy())
    assert np.allclose(outs[0], outs[1], atol=1e-6) and np.allclose(outs[0], outs[2], atol=1e-6)
    # MATLAB v7.3 (HDF5 with a 512-byte header, column-major): the reader transposes back
    v73 = tmp_path / "v73.mat"
    import h5py

    with h5py.File(v73, "w", userblock_size=512) as f:
        f["imu_gyr"], f["imu_acc"], f["sampling_rate"] = s["imu_gyr"].T, s["imu_acc"].T, s["sampling_rate"]
    code, text, err = _run(["rests", v73], capsys)
    assert code == 0, err


@pytest.mark.parametrize("arrays,extra,needle", [
    ({"imu_gyr": np.zeros((50, 3))}, [], "no array 'imu_acc' for the accel; map yours with --columns accel=NAME"),
    ({"imu_gyr": np.zeros((50, 3)), "imu_acc": np.zeros((50, 2)), "sampling_rate": 100.0}, [],
     "array 'imu_acc' (accel) must be N x 3, got shape (50, 2)"),
    ({"imu_gyr": np.zeros((50, 3)), "imu_acc": np.ones((49, 3)), "sampling_rate": 100.0}, [],
     "arrays of different lengths: 'imu_gyr' has 50 rows, 'imu_acc' 49"),
    ({"imu_gyr": np.where(np.arange(150)[:, None] == 37, np.nan, 0.0) * np.ones((1, 3)),
      "imu_acc": np.ones((150, 3)), "sampling_rate": 100.0}, [], "array 'imu_gyr' has a non-finite value (NaN or inf) "
                                                                  "at row 38"),
    ({"imu_gyr": np.zeros((50, 3)), "imu_acc": np.ones((50, 3))}, [], "give --fs-hz"),
    ({"g": np.zeros((50, 3)), "a": np.ones((50, 3))}, ["--columns", "gyro=g,accel=a,time=tt"], "no array 'tt'"),
    ({"g": np.zeros((50, 3)), "a": np.ones((50, 3))}, ["--columns", "gyro_x=g"], "map N x 3 arrays"),
    ({"imu_gyr": np.zeros((50, 3)), "imu_acc": np.ones((50, 3)), "sampling_rate": 1e6}, [],
     "'sampling_rate' must be one sample rate"),
])
def test_array_file_errors(tmp_path, capsys, arrays, extra, needle):
    path = _h5(tmp_path / "bad.h5", **arrays)
    out = tmp_path / "keep.csv"
    out.write_text("untouched")
    code, text, err = _run(["attitude", path, *extra, "--out", out], capsys)
    _refused(code, err, needle)
    assert out.read_text() == "untouched"
    with pytest.raises(ValueError, match=re.escape(needle)):
        logio.read_log(path, common.input_options(_defaults(extra)))


def test_array_keys_refused_for_csv(tmp_path, capsys):
    path = tmp_path / "x.csv"
    path.write_text("time_s,a\n0,1\n")
    _refused(*_run(["rests", path, "--columns", "gyro=imu_gyr"], capsys)[::2], "gyro_x=HEADER")


# ----------------------------------------------------------------------------------------- --filter
@pytest.mark.parametrize("name", attitude.FILTERS)
def test_every_filter_same_schema(name, tmp_path, broad_slice, capsys):
    pytest.importorskip({"vqf": "vqf", "basicvqf": "vqf", "madgwick": "ahrs", "fusion": "imufusion"}.get(name, "numpy"))
    s = broad_slice
    n = int(12 * float(s["sampling_rate"]))
    rec = _h5(tmp_path / "rec.h5", imu_gyr=s["imu_gyr"][:n], imu_acc=s["imu_acc"][:n], sampling_rate=s["sampling_rate"])
    code, out, err = _run(["attitude", rec, "--filter", name, "--out", tmp_path / "att.csv"], capsys)
    assert code == 0, err
    df = pd.read_csv(tmp_path / "att.csv")
    assert list(df.columns) == ["time_s", "q0", "q1", "q2", "q3", "yaw_deg", "pitch_deg", "roll_deg", "is_static"]
    q = df[["q0", "q1", "q2", "q3"]].to_numpy()
    assert len(df) == n and np.allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-6)
    # the first 10 s are a rest: every filter's inclination there is the accelerometer's within 2 deg
    from mtcal.core.metrics import orientation_errors

    err_rest = orientation_errors(q[: int(5 * float(s["sampling_rate"]))], s["opt_quat"][: int(5 * float(
        s["sampling_rate"]))]).inclination_rad
    assert float(np.degrees(np.nanmax(err_rest[200:]))) < 2.0


def test_filter_vqf_equals_vqf_update_batch(tmp_path, broad_slice, capsys):
    vqf = pytest.importorskip("vqf")
    s = broad_slice
    rec = _h5(tmp_path / "rec.h5", **{k: s[k] for k in ("imu_gyr", "imu_acc", "sampling_rate")})
    code, out, err = _run(["attitude", rec, "--filter", "vqf", "--out", tmp_path / "att.parquet"], capsys)
    assert code == 0, err
    got = pd.read_parquet(tmp_path / "att.parquet")[["q0", "q1", "q2", "q3"]].to_numpy()
    want = vqf.VQF(1.0 / float(s["sampling_rate"])).updateBatch(np.ascontiguousarray(s["imu_gyr"]),
                                                                 np.ascontiguousarray(s["imu_acc"]))["quat6D"]
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)


def test_unknown_filter_refused(capsys):
    with pytest.raises(SystemExit) as exc:
        cli.main(["attitude", str(TRIALS[0]), "--filter", "kalman"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("mtcal: error: argument --filter: invalid choice: 'kalman'") and err.count("\n") == 1


# ----------------------------------------------------------------------------------------- rests vs optics
def _optical_rests(arrays, fs, *, rate_deg_s=2.0, span_s=0.5, min_s=5.0):
    """Optical rests: rotation over 0.5 s (centred) below 2 deg/s, runs of at least 5 s; ``valid``: optics seen
    (BROAD's markers lost: NaN, not judged)."""
    q = arrays["opt_quat"]
    k = int(round(span_s * fs))
    dot = np.abs(np.sum(q[k:] * q[:-k], axis=1))
    ang = np.degrees(2 * np.arccos(np.minimum(dot, 1.0)))
    still = np.zeros(q.shape[0], bool)
    valid = np.zeros(q.shape[0], bool)
    h = k // 2
    still[h:h + ang.size] = np.nan_to_num(ang, nan=np.inf) / span_s < rate_deg_s
    valid[h:h + ang.size] = np.isfinite(ang)
    runs, start = [], None
    for i, s in enumerate(np.append(still, False)):
        if s and start is None:
            start = i
        elif not s and start is not None:
            if (i - start) / fs >= min_s:
                runs.append(slice(start, i))
            start = None
    return runs, still, valid


@pytest.mark.parametrize("path", BREAKS, ids=lambda p: p.name[:2])
def test_rests_against_optical_truth(path):
    arrays = read_arrays(path)
    log = logio.read_log(path)
    rep = common.detect(_defaults(), log)   # `mtcal rests` at its defaults
    listed = rep.is_static
    runs, still, valid = _optical_rests(arrays, log.fs_hz)
    assert len(runs) >= 3
    for r in runs:
        assert listed[r].mean() >= 0.8, (r, listed[r].mean())
    assert still[listed & valid].mean() >= 0.9
