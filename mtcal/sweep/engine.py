"""Sweep engine: grid × N trials per cell → one tidy table, identical on any executor.

Determinism
-----------
Trial ``j`` of cell ``i`` draws every random number from
``numpy.random.SeedSequence([seed, i, j])``, or — the built-in evaluators' batched
sensor simulation — from the counter-based stream keyed by ``SeedSequence([seed, i])``
at trial index ``j`` (:class:`TrialStreams`): keyed by index, not by execution
order, so its random inputs do not depend on the number of workers, on which
worker runs it, or on which trials share its task. Tasks are fixed blocks of
``block_trials`` consecutive trials of one cell; results are put back in trial
order before any statistic is formed; every per-trial reduction (RMS, means)
is computed row by row, because numpy's ``mean(axis=1)`` of a (T, N) array sums
in an order that depends on T. The tables are therefore byte-identical for 1
worker, N local processes or a Dask cluster, and — for the built-in evaluators —
for any ``block_trials`` (both tested). One caveat is kept in the fingerprint:
QNCF chooses its increment series per time chunk from the largest increment of
all trials in the call, so in principle a trial's last bit could depend on its
block-mates; ``block_trials`` is therefore part of a run folder's identity.

Memory
------
A task holds one block: ``block_trials × samples × 3`` floats per signal. Only
per-trial metrics leave a task; the driver keeps per-trial metrics of the cells
in flight and a bounded number of pending tasks.

Run folder (``out_dir``)
------------------------
``sweep.json`` (the spec and its fingerprint), ``cells/cell_NNNNN.npz`` (the
per-trial metrics of one finished cell, written atomically: temp file +
``os.replace``) and ``table.csv`` (the tidy table). A sweep interrupted and run
again with the same spec and folder skips the cells already stored; a different
spec in the same folder is an error.

Examples
--------
>>> from mtcal.sweep.spec import parse_spec
>>> spec = parse_spec('''
... [sweep]
... name = "demo"
... evaluator = "gaussian_check"
... seed = 7
... trials = 50
... block_trials = 20
... [grid]
... sigma = [1.0, 3.0]
... ''')
>>> res = run_sweep(spec, workers=1, progress=False)
>>> rms = res.table[res.table.metric == "rms"]
>>> [round(float(v), 1) for v in rms["median"]], list(rms["trials"])
([1.0, 3.0], [50, 50])
"""

from __future__ import annotations

import json
import os
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from mtcal.core.metrics import band_or_range
from mtcal.sweep.evaluators import get_evaluator
from mtcal.sweep.spec import SweepSpec, load_spec

__all__ = ["SweepResult", "run_sweep", "run_block", "trial_rngs", "TrialStreams", "summarize", "TABLE_COLUMNS"]

#: Columns of the tidy table after the grid columns.
TABLE_COLUMNS = ("metric", "median", "low", "high", "trials", "band")
_FORMAT = 1


def trial_rngs(seed: int, cell: int, start: int, stop: int) -> list[np.random.Generator]:
    """Generators of trials ``start … stop−1`` of a cell: ``SeedSequence([seed, cell, j])`` each."""
    return [np.random.Generator(np.random.PCG64(np.random.SeedSequence([int(seed), int(cell), j])))
            for j in range(int(start), int(stop))]


class TrialStreams(list):
    """The generators of trials ``start … stop−1`` of a cell (:func:`trial_rngs`), plus keyed batch streams.

    A list of ``numpy.random.Generator`` (what an evaluator's ``rngs`` is), with
    ``trial_ids`` (the trials' indices in the cell) and :meth:`cell_rng`: a fresh generator
    of ``SeedSequence([seed, cell])``, the key of a counter-based batched simulation in which
    trial ``trial_ids[i]`` draws by its index (``simulate_imu(..., trial_ids=...)``), so that its
    numbers do not depend on which trials share the block either.

    Examples
    --------
    >>> s = TrialStreams(7, 1, 3, 5)
    >>> len(s), s.trial_ids.tolist(), bool(s.cell_rng().integers(1 << 30) == s.cell_rng().integers(1 << 30))
    (2, [3, 4], True)
    """

    def __init__(self, seed: int, cell: int, start: int, stop: int):
        super().__init__(trial_rngs(seed, cell, start, stop))
        self.seed, self.cell = int(seed), int(cell)
        self.trial_ids = np.arange(int(start), int(stop), dtype=np.int64)

    def cell_rng(self) -> np.random.Generator:
        """Generator of ``SeedSequence([seed, cell])`` (the same in every block of the cell)."""
        return np.random.Generator(np.random.PCG64(np.random.SeedSequence([self.seed, self.cell])))


def run_block(evaluator: str, params: dict, seed: int, cell: int, start: int, stop: int) -> dict[str, np.ndarray]:
    """One task: evaluate trials ``[start, stop)`` of a cell → per-trial metrics (runs on a worker)."""
    ev = get_evaluator(evaluator)
    try:
        return ev(params, TrialStreams(seed, cell, start, stop))
    except ValueError as exc:
        raise ValueError(f"cell {cell} (evaluator {evaluator}, {_cell_text(params)}), trials {start}-{stop - 1}: "
                         f"{exc}") from None


def _cell_text(params: dict) -> str:
    """``key=value`` of a cell's parameters, short."""
    return ", ".join(f"{k}={v}" for k, v in params.items())[:200]


def summarize(values: np.ndarray) -> dict:
    """Median and spread of per-trial values by the band rule (``metrics.band_or_range``).

    ``low``/``high`` are the 95 % band (2.5/97.5 percentiles) from at least 1000 trials, else
    the min–max range; ``band`` says which (``"95 % band"`` or ``"range"``, docs/conventions.md).
    """
    b = band_or_range(np.asarray(values, float), axis=0)
    return {"median": float(b["median"]), "low": float(b["low"]), "high": float(b["high"]), "band": b["kind"]}


@dataclass
class SweepResult:
    """Outcome of :func:`run_sweep`.

    Attributes
    ----------
    spec : SweepSpec
    table : pandas.DataFrame
        One row per cell and metric: ``cell``, the grid parameters, ``metric``,
        ``median``, ``low``, ``high`` (2.5 and 97.5 percentiles: a 95 % band when ``trials`` >= 1000),
        ``trials``.
    per_trial : dict
        ``{cell index: {metric: ndarray (trials,)}}`` in trial order.
    out_dir : Path or None
    computed, skipped : list of int
        Cells computed in this call / found already stored.
    executor : str
        Description of where the tasks ran.
    """

    spec: SweepSpec
    table: pd.DataFrame
    per_trial: dict
    out_dir: Path | None = None
    computed: list = field(default_factory=list)
    skipped: list = field(default_factory=list)
    executor: str = ""

    def trials_frame(self) -> pd.DataFrame:
        """Long per-trial frame: ``cell``, grid parameters, ``trial``, one column per metric."""
        rows = []
        for cell in sorted(self.per_trial):
            metrics = self.per_trial[cell]
            n = len(next(iter(metrics.values())))
            frame = pd.DataFrame({"cell": cell, **_grid_columns(self.spec, cell), "trial": np.arange(n)})
            for name, values in metrics.items():
                frame[name] = values
            rows.append(frame)
        return pd.concat(rows, ignore_index=True)


def _grid_columns(spec: SweepSpec, cell: int) -> dict:
    return {k: (json.dumps(v) if isinstance(v, list) else v) for k, v in spec.grid_values(cell).items()}


def _atomic_write_bytes(path: Path, data: bytes) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def _cell_path(out: Path, cell: int) -> Path:
    return out / "cells" / f"cell_{cell:05d}.npz"


def _save_cell(out: Path, spec: SweepSpec, cell: int, metrics: dict[str, np.ndarray]) -> None:
    import io

    buf = io.BytesIO()
    meta = json.dumps({"format": _FORMAT, "fingerprint": spec.cell_fingerprint(cell),
                       "block_trials": spec.block_trials, "metrics": list(metrics)})
    np.savez(buf, __meta__=np.array(meta), **{f"m{i}": v for i, v in enumerate(metrics.values())})
    _atomic_write_bytes(_cell_path(out, cell), buf.getvalue())


def _load_cell(out: Path, spec: SweepSpec, cell: int) -> dict[str, np.ndarray] | None:
    path = _cell_path(out, cell)
    if not path.exists():
        return None
    try:
        with np.load(path, allow_pickle=False) as data:
            meta = json.loads(str(data["__meta__"]))
            metrics = {name: data[f"m{i}"].copy() for i, name in enumerate(meta["metrics"])}
    except (OSError, ValueError, KeyError) as exc:
        raise ValueError(f"stored cell file {path} is unreadable ({exc}); delete it to recompute the cell") from None
    if meta.get("fingerprint") != spec.cell_fingerprint(cell) or meta.get("block_trials") != spec.block_trials:
        raise ValueError(f"stored cell file {path} belongs to a different sweep; use another output folder")
    return metrics


def _prepare_folder(out: Path, spec: SweepSpec) -> None:
    try:
        (out / "cells").mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ValueError(f"--out {out}: cannot make the run folder ({exc.strerror}: {exc.filename})") from None
    head = {"format": _FORMAT, "fingerprint": spec.fingerprint(), "spec": spec.as_dict()}
    path = out / "sweep.json"
    if path.exists():
        try:
            old = json.loads(path.read_text(encoding="utf-8"))
        except ValueError:
            raise ValueError(f"{path} is not valid JSON; use another output folder") from None
        if old.get("fingerprint") != head["fingerprint"] or old.get("spec", {}).get("block_trials") != spec.block_trials:
            raise ValueError(f"output folder {out} holds a different sweep ({old.get('spec', {}).get('name')!r}, "
                             f"other parameters); use another --out or delete it")
        return
    _atomic_write_bytes(path, (json.dumps(head, indent=2, sort_keys=True) + "\n").encode())


def _table(spec: SweepSpec, per_trial: dict) -> pd.DataFrame:
    rows = []
    for cell in range(spec.n_cells):
        grid = _grid_columns(spec, cell)
        for name, values in per_trial[cell].items():
            rows.append({"cell": cell, **grid, "metric": name, **summarize(values), "trials": int(values.size)})
    return pd.DataFrame(rows, columns=["cell", *spec.grid, *TABLE_COLUMNS])


def run_sweep(spec, out_dir=None, *, workers: int | None = None, scheduler=None, executor=None,
              progress: bool | None = None) -> SweepResult:
    """Run a sweep: every cell × ``spec.trials`` trials, in blocks, on the chosen executor.

    Parameters
    ----------
    spec : SweepSpec or path-like
        The sweep (a TOML path is loaded with :func:`mtcal.sweep.spec.load_spec`).
    out_dir : path-like, optional
        Run folder (created); finished cells are stored there and skipped when the
        same sweep is run again. None keeps everything in memory.
    workers : int, optional
        Local processes; 1 = in this process; default every core.
    scheduler : str or distributed.Client, optional
        Run on a Dask cluster instead (address ``tcp://…`` or a Client).
    executor : object, optional
        A ready executor (:mod:`mtcal.sweep.executors`); not closed here.
    progress : bool, optional
        Progress bar over cells; default :func:`mtcal.core.montecarlo.progress_enabled`.

    Returns
    -------
    SweepResult
    """
    from mtcal.core.montecarlo import progress_enabled
    from mtcal.sweep.executors import make_executor

    if not isinstance(spec, SweepSpec):
        spec = load_spec(spec)
    ev = get_evaluator(spec.evaluator)
    cells = spec.cells()
    params = [ev.resolve(c) for c in cells]
    out = None if out_dir is None else Path(out_dir)
    per_trial: dict[int, dict] = {}
    skipped = []
    own = executor is None
    ex = make_executor(workers, scheduler) if own else executor   # an unreachable scheduler: before any folder
    bar = None
    computed = []
    try:
        if out is not None:
            _prepare_folder(out, spec)
            for i in range(spec.n_cells):
                stored = _load_cell(out, spec, i)
                if stored is not None:
                    per_trial[i] = stored
                    skipped.append(i)
        todo = [i for i in range(spec.n_cells) if i not in per_trial]
        blocks = {i: [(s, min(s + spec.block_trials, spec.trials)) for s in range(0, spec.trials, spec.block_trials)]
                  for i in todo}
        task_iter = (((i, s), run_block, (spec.evaluator, params[i], spec.seed, i, s, e))
                     for i in todo for s, e in blocks[i])
        if (progress_enabled() if progress is None else progress) and todo:
            from tqdm.auto import tqdm

            bar = tqdm(total=spec.n_cells, initial=len(skipped), desc=f"sweep {spec.name}", unit="cell")
        partial: dict[int, dict[int, dict]] = {}
        for (i, start), result in ex.run(task_iter):
            partial.setdefault(i, {})[start] = result
            if len(partial[i]) == len(blocks[i]):
                parts = partial.pop(i)
                ordered = [parts[s] for s, _ in blocks[i]]          # trial order, whatever finished first
                metrics = {name: np.concatenate([p[name] for p in ordered]) for name in ordered[0]}
                if out is not None:
                    _save_cell(out, spec, i, metrics)
                per_trial[i] = metrics
                computed.append(i)
                if bar is not None:
                    bar.update(1)
    finally:
        if bar is not None:
            bar.close()
        if own:
            ex.close()
    table = _table(spec, per_trial)
    if out is not None:
        _atomic_write_bytes(out / "table.csv", table.to_csv(index=False, lineterminator="\n").encode())
    return SweepResult(spec, table, per_trial, out, sorted(computed), skipped, ex.description)
