"""Sweep specification: a grid of scenario parameters × N Monte Carlo trials per cell.

A spec is a small TOML file (parsed with :mod:`tomllib`)::

    [sweep]
    name = "turntable_grades"        # run-folder name and table label
    evaluator = "attitude"           # a registered scenario evaluator (mtcal.sweep.evaluators)
    seed = 2023                      # root of every random stream
    trials = 200                     # Monte Carlo trials per grid cell
    block_trials = 25                # trials per task (memory bound; optional)

    [fixed]                          # parameters held constant (any TOML value)
    motion = "aoa"

    [grid]                           # parameters swept: each a non-empty array
    grade = ["industrial", "tactical"]
    vibration_m_s2 = [0.0, 3.0]

The cells are the Cartesian product of the ``[grid]`` arrays, in the order the
keys are written (the last key varies fastest). Every error names the key:
``ValueError: sweep.trials must be an integer in [1, 10000000], got -3``; at most 100 000 cells in one sweep.

Examples
--------
>>> spec = parse_spec('''
... [sweep]
... name = "demo"
... evaluator = "gaussian_check"
... seed = 1
... trials = 4
... [grid]
... sigma = [1.0, 2.0]
... ''')
>>> spec.n_cells, [c["sigma"] for c in spec.cells()]
(2, [1.0, 2.0])
"""

from __future__ import annotations

import hashlib
import itertools
import json
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

__all__ = ["SweepSpec", "parse_spec", "load_spec", "MAX_TRIALS", "MAX_CELLS"]

_NAME_RE = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]*$")
_SWEEP_KEYS = ("name", "evaluator", "seed", "trials", "block_trials")


def _int(value, key: str, minimum: int, maximum: int | None = None) -> int:
    if (isinstance(value, bool) or not isinstance(value, int) or value < minimum
            or (maximum is not None and value > maximum)):
        what = ("a positive integer" if minimum == 1 else f"an integer >= {minimum}") if maximum is None else \
            f"an integer in [{minimum}, {maximum}]"
        raise ValueError(f"{key} must be {what}, got {value!r}")
    return int(value)


#: Largest trials per cell and cells per sweep: beyond them a spec is a typo, not a plan (a sweep of that size
#: is several specs, each resumable on its own).
MAX_TRIALS = 10_000_000
MAX_CELLS = 100_000


def _scalar_ok(value) -> bool:
    if isinstance(value, (bool, int, float, str)):
        return True
    if isinstance(value, list):
        return all(_scalar_ok(v) for v in value)
    return False


@dataclass(frozen=True)
class SweepSpec:
    """A validated sweep: evaluator, seed, trials per cell, fixed values and grid axes.

    Parameters
    ----------
    name : str
        Label of the sweep (letters, digits, ``_ . -``).
    evaluator : str
        Name of a registered scenario evaluator (:func:`mtcal.sweep.evaluators.evaluator_names`).
    seed : int
        Root seed (>= 0); trial ``j`` of cell ``i`` draws from
        ``SeedSequence([seed, i, j])``.
    trials : int
        Monte Carlo trials per cell.
    block_trials : int
        Trials per task (one evaluator call); bounds the memory of a task.
    fixed : dict
        Parameters held constant.
    grid : dict of str → tuple
        Swept parameters (each a non-empty tuple of values).
    """

    name: str
    evaluator: str
    seed: int
    trials: int
    block_trials: int = 16
    fixed: dict = field(default_factory=dict)
    grid: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        from mtcal.sweep.evaluators import get_evaluator

        if not isinstance(self.name, str) or not _NAME_RE.match(self.name):
            raise ValueError(f"sweep.name must be letters, digits, '_', '.', '-' (no spaces), got {self.name!r}")
        ev = get_evaluator(self.evaluator)  # raises naming the valid ones
        _int(self.seed, "sweep.seed", 0)
        _int(self.trials, "sweep.trials", 1, MAX_TRIALS)
        _int(self.block_trials, "sweep.block_trials", 1)
        if not isinstance(self.fixed, dict) or not isinstance(self.grid, dict):
            raise TypeError("fixed and grid must be dicts")
        both = sorted(set(self.fixed) & set(self.grid))
        if both:
            raise ValueError(f"grid.{both[0]} is also in [fixed]; give each parameter in one table only")
        for table, values in (("fixed", self.fixed), ("grid", self.grid)):
            for key, value in values.items():
                if key not in ev.defaults:
                    raise ValueError(f"{table}.{key} is not a parameter of evaluator {ev.name!r}; "
                                     f"valid: {sorted(ev.defaults)}")
                if table == "grid":
                    if not isinstance(value, (list, tuple)) or len(value) == 0:
                        raise ValueError(f"grid.{key} must be a non-empty array of values, got {value!r}")
                    if len(set(map(json.dumps, value))) != len(value):
                        raise ValueError(f"grid.{key} has repeated values: {list(value)!r}")
                    bad = [v for v in value if not _scalar_ok(v)]
                else:
                    bad = [] if _scalar_ok(value) else [value]
                if bad:
                    raise ValueError(f"{table}.{key} must hold numbers, strings, booleans or arrays of "
                                     f"them, got {bad[0]!r}")
        object.__setattr__(self, "grid", {k: tuple(v) for k, v in self.grid.items()})
        if self.n_cells > MAX_CELLS:
            raise ValueError(f"[grid] makes {self.n_cells} cells ({' x '.join(str(len(v)) for v in self.grid.values())}"
                             f"), more than {MAX_CELLS} in one sweep; split the grid into several specs")
        for params in self.cells():  # each cell validated by the evaluator (key named in the error)
            try:
                ev.resolve(params)
            except ValueError as exc:
                msg = str(exc)
                key = msg.split(" ", 1)[0]
                table = "grid" if key in self.grid else "fixed" if key in self.fixed else None
                if table is None:
                    raise ValueError(f"{msg} (evaluator default; set it in [fixed])") from None
                raise ValueError(f"{table}.{msg}") from None

    @property
    def n_cells(self) -> int:
        """Number of grid cells (1 for an empty grid)."""
        n = 1
        for values in self.grid.values():
            n *= len(values)
        return n

    def cells(self) -> list[dict]:
        """Parameter dict of every cell (fixed values + one grid point), in grid order."""
        keys = list(self.grid)
        out = []
        for combo in itertools.product(*(self.grid[k] for k in keys)):
            params = dict(self.fixed)
            params.update(zip(keys, combo))
            out.append(params)
        return out

    def grid_values(self, index: int) -> dict:
        """Only the swept values of cell ``index``."""
        cell = self.cells()[index]
        return {k: cell[k] for k in self.grid}

    def as_dict(self) -> dict:
        """Plain-JSON form (written to the run folder; compared on resume)."""
        return {"name": self.name, "evaluator": self.evaluator, "seed": self.seed, "trials": self.trials,
                "block_trials": self.block_trials, "fixed": dict(self.fixed),
                "grid": {k: list(v) for k, v in self.grid.items()}}

    def fingerprint(self) -> str:
        """SHA-256 of what determines the numbers (``block_trials`` excluded: it does not change them)."""
        d = self.as_dict()
        d.pop("block_trials")
        return hashlib.sha256(json.dumps(d, sort_keys=True).encode()).hexdigest()

    def cell_fingerprint(self, index: int) -> str:
        """SHA-256 of (evaluator, seed, trials, cell index, the cell's parameters)."""
        d = {"evaluator": self.evaluator, "seed": self.seed, "trials": self.trials, "cell": int(index),
             "params": self.cells()[index]}
        return hashlib.sha256(json.dumps(d, sort_keys=True).encode()).hexdigest()


def parse_spec(text: str, *, source: str = "spec") -> SweepSpec:
    """Parse and validate TOML text into a :class:`SweepSpec`.

    Raises
    ------
    ValueError
        Invalid TOML (with the parser's line/column), a missing or unknown key, or
        a bad value; the message names the key (``sweep.trials``, ``grid.grade`` …).
    """
    if not isinstance(text, str):
        raise TypeError(f"text must be a str, got {type(text).__name__}")
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{source} is not valid TOML: {exc}") from None
    unknown = sorted(set(doc) - {"sweep", "fixed", "grid"})
    if unknown:
        raise ValueError(f"{source}: unknown table [{unknown[0]}]; valid tables: [sweep], [fixed], [grid]")
    head = doc.get("sweep")
    if not isinstance(head, dict):
        raise ValueError(f"{source}: missing [sweep] table (name, evaluator, seed, trials)")
    extra = sorted(set(head) - set(_SWEEP_KEYS))
    if extra:
        raise ValueError(f"sweep.{extra[0]} is not a valid key; valid: {list(_SWEEP_KEYS)}")
    for key in ("name", "evaluator", "seed", "trials"):
        if key not in head:
            raise ValueError(f"sweep.{key} is missing")
    for table in ("fixed", "grid"):
        if table in doc and not isinstance(doc[table], dict):
            raise ValueError(f"[{table}] must be a table")
    return SweepSpec(name=head["name"], evaluator=head["evaluator"], seed=head["seed"], trials=head["trials"],
                     block_trials=head.get("block_trials", 16), fixed=doc.get("fixed", {}),
                     grid=doc.get("grid", {}))


def load_spec(path) -> SweepSpec:
    """Read and validate a spec file (see :func:`parse_spec`)."""
    p = Path(path)
    if not p.is_file():
        raise FileNotFoundError(f"spec file not found: {p}")
    try:
        text = p.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise ValueError(f"{p} is not a TOML text file (not UTF-8: {exc.reason} at byte {exc.start})") from None
    return parse_spec(text, source=str(p))
