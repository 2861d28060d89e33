"""Sweep engine: identical numbers for any partition of the trials, resume, run folder, statistics."""

import json

import numpy as np
import pandas as pd
import pytest

from mtcal.sweep import engine
from mtcal.sweep.engine import run_block, run_sweep, summarize, trial_rngs
from mtcal.sweep.executors import SerialExecutor
from mtcal.sweep.spec import parse_spec

from .conftest import windtunnel_spec_text


def small_text(block=2, filters='["mahony", "vqf"]'):
    return windtunnel_spec_text(name="small", seed=11, trials=5, block=block, filters=filters, vibration="[0.0, 2.0]")


def small(block=2, filters='["mahony", "vqf"]'):
    return parse_spec(small_text(block, filters))


def test_trial_streams_are_keyed_by_cell_and_trial_index():
    a = trial_rngs(5, 2, 0, 4)
    b = trial_rngs(5, 2, 3, 4)
    assert a[3].standard_normal(4).tobytes() == b[0].standard_normal(4).tobytes()
    c = trial_rngs(5, 3, 3, 4)[0]
    assert not np.array_equal(trial_rngs(5, 2, 3, 4)[0].standard_normal(4), c.standard_normal(4))


@pytest.mark.parametrize("evaluator,params", [
    ("gaussian_check", {"sigma": 2.0, "n_samples": 300, }),
    ("attitude", {"motion": "windtunnel", "filters": ["mahony", "vqf", "fusion", "madgwick"], "fs_hz": 100.0,
                  "hold_s": 0.5, "speed": 5.0, "vibration_m_s2": 2.0, "vibration_hz": 20.0}),
    ("surface", {"filters": ["rams_ekf", "mahony"], "fs_hz": 50.0, "step_deg": 60.0, "vibration_hz": 10.0}),
    ("attitude", {"motion": "roll", "filters": ["qncf"], "fs_hz": 100.0, "hold_s": 0.5, "speed": 5.0}),
    ("six_position", {"fs_hz": 100.0, "n_positions": 5}),
])
def test_any_partition_of_trials_gives_identical_per_trial_numbers(evaluator, params):
    from mtcal.sweep.evaluators import get_evaluator

    p = get_evaluator(evaluator).resolve(params)
    whole = run_block(evaluator, p, 9, 4, 0, 6)
    for cuts in ([0, 1, 6], [0, 4, 5, 6], [0, 2, 4, 6]):
        parts = [run_block(evaluator, p, 9, 4, a, b) for a, b in zip(cuts[:-1], cuts[1:])]
        for name, values in whole.items():
            joined = np.concatenate([q[name] for q in parts])
            assert joined.tobytes() == values.tobytes(), (evaluator, name, cuts)


def test_block_size_does_not_change_tables_for_per_trial_filters():
    tables = [run_sweep(small(block=b), workers=1, progress=False).table for b in (1, 2, 5)]
    for t in tables[1:]:
        assert t.to_csv(index=False) == tables[0].to_csv(index=False)


def test_table_is_tidy_with_median_and_band():
    res = run_sweep(small(), workers=1, progress=False)
    t = res.table
    assert list(t.columns) == ["cell", "grade", "vibration_m_s2", "metric", "median", "low", "high", "trials", "band"]
    assert len(t) == 4 * 6 and set(t.trials) == {5}
    assert (t["low"] <= t["median"]).all() and (t["median"] <= t["high"]).all()
    row = t[(t.cell == 3) & (t.metric == "vqf.tilt_max_deg")].iloc[0]
    values = res.per_trial[3]["vqf.tilt_max_deg"]
    assert row["median"] == float(np.median(values))
    # 5 trials: the min-max range with its count, never a "95 % band" (docs/conventions.md, Bands)
    assert row["low"] == float(values.min()) and row["high"] == float(values.max()) and row["band"] == "range"
    frame = res.trials_frame()
    assert len(frame) == 4 * 5 and "mahony.tilt_rmse_deg" in frame
    # the consumer grade (20 mg accelerometer bias) tilts far more than the industrial one (2 mg)
    med = t[t.metric == "mahony.hold_tilt_rmse_deg"].set_index(["grade", "vibration_m_s2"])["median"]
    # (a median of 5 trials scatters: 2.6x with the batched sensor streams, > 3x with the old per-trial ones)
    assert med["consumer", 0.0] > 2 * med["industrial", 0.0]


def test_gaussian_check_statistics_match_closed_form():
    spec = parse_spec('[sweep]\nname="g"\nevaluator="gaussian_check"\nseed=1\ntrials=1000\nblock_trials=250\n'
                      '[fixed]\nn_samples=100\n[grid]\nsigma=[0.5, 4.0]\n')
    t = run_sweep(spec, workers=1, progress=False).table.set_index(["sigma", "metric"])
    for sigma in (0.5, 4.0):
        assert abs(t.loc[(sigma, "rms"), "median"] / sigma - 1) < 0.02
        # mean of 100 draws: 95 % band ≈ ±1.96 σ/√100
        assert abs(t.loc[(sigma, "mean"), "high"] / (1.96 * sigma / 10) - 1) < 0.15
    assert set(t["band"]) == {"95 % band"}
    assert summarize(np.arange(1001.0)) == pytest.approx({"median": 500.0, "low": 25.0, "high": 975.0,
                                                          "band": "95 % band"}, abs=1e-12)
    assert summarize(np.arange(101.0)) == {"median": 50.0, "low": 0.0, "high": 100.0, "band": "range"}


class _Interrupt(Exception):
    pass


class _StopAfter(SerialExecutor):
    """Runs tasks in-process and raises after ``n`` tasks (a Ctrl-C / killed job)."""

    def __init__(self, n):
        self.n = n

    def run(self, tasks):
        for k, (key, fn, args) in enumerate(tasks):
            if k == self.n:
                raise _Interrupt()
            yield key, fn(*args)


def test_interrupted_sweep_resumes_skipping_stored_cells(tmp_path):
    spec = small(block=3)          # 2 tasks per cell
    out = tmp_path / "run"
    with pytest.raises(_Interrupt):
        run_sweep(spec, out, executor=_StopAfter(5), progress=False)
    stored = sorted(p.name for p in (out / "cells").iterdir())
    assert stored == ["cell_00000.npz", "cell_00001.npz"]      # finished cells only, no temp files
    assert not (out / "table.csv").exists()
    res = run_sweep(spec, out, workers=1, progress=False)
    assert res.skipped == [0, 1] and res.computed == [2, 3]
    fresh = run_sweep(spec, tmp_path / "fresh", workers=1, progress=False)
    assert (out / "table.csv").read_bytes() == (tmp_path / "fresh" / "table.csv").read_bytes()
    again = run_sweep(spec, out, workers=1, progress=False)
    assert again.computed == [] and again.skipped == [0, 1, 2, 3]
    assert again.table.equals(res.table)
    head = json.loads((out / "sweep.json").read_text())
    assert head["spec"]["name"] == "small" and head["fingerprint"] == spec.fingerprint()
    assert pd.read_csv(out / "table.csv").shape == res.table.shape


def test_other_sweep_in_the_same_folder_is_an_error(tmp_path):
    out = tmp_path / "run"
    run_sweep(small(), out, workers=1, progress=False)
    with pytest.raises(ValueError, match="holds a different sweep"):
        run_sweep(small(filters='["mahony"]'), out, workers=1, progress=False)
    with pytest.raises(ValueError, match="holds a different sweep"):
        run_sweep(small(block=4), out, workers=1, progress=False)
    cell = out / "cells" / "cell_00001.npz"
    cell.write_bytes(b"truncated")
    with pytest.raises(ValueError, match="cell_00001.npz is unreadable"):
        run_sweep(small(), out, workers=1, progress=False)


def test_atomic_write_leaves_no_partial_file(tmp_path, monkeypatch):
    target = tmp_path / "x.bin"
    target.write_bytes(b"old")

    def boom(*a, **k):
        raise OSError("disk full")

    monkeypatch.setattr(engine.os, "replace", boom)
    with pytest.raises(OSError, match="disk full"):
        engine._atomic_write_bytes(target, b"new content")
    assert target.read_bytes() == b"old"
    assert [p.name for p in tmp_path.iterdir()] == ["x.bin"]


def test_spec_path_and_errors(tmp_path):
    p = tmp_path / "s.toml"
    p.write_text(small_text(block=5, filters='["vqf"]'))
    res = run_sweep(p, workers=1, progress=False)
    assert res.spec.name == "small" and res.executor.startswith("serial")
    with pytest.raises(ValueError, match="workers must be a positive integer"):
        run_sweep(p, workers=0, progress=False)
    with pytest.raises(ValueError, match="either workers"):
        run_sweep(p, workers=2, scheduler="tcp://127.0.0.1:1", progress=False)


def test_an_evaluator_error_names_the_cell_and_trials(monkeypatch):
    from mtcal.sweep import engine, evaluators

    monkeypatch.setattr(evaluators, "_REGISTRY", dict(evaluators._REGISTRY))

    @evaluators.register_evaluator("fails", defaults={"x": 1.0}, metrics=lambda p: ["m"])
    def _fails(p, rngs):
        raise ValueError("reference position 4 has no rest")

    with pytest.raises(ValueError, match=r"^cell 3 \(evaluator fails, x=2.0\), trials 4-7: reference position 4"):
        engine.run_block("fails", {"x": 2.0}, 1, 3, 4, 8)
