"""Notebook runs: build from py:percent (jupytext), execute with parameters (papermill).

The notebooks' sources are ``notebooks/NN_<key>_<topic>.py`` (py:percent);
the executed ``.ipynb`` beside each is derived from it. Three kinds of run:

* ``make reproduce`` (:func:`execute_notebook` in place, via ``tools/notebooks.py``)
  rewrites the committed notebooks, ``data/`` and ``figures/`` at full size;
* ``make test`` runs the committed ``.ipynb`` with nbval at CI size into ``build/ci``;
* a *what-if* run (:func:`run_notebook`, ``mtcal run``) executes one notebook with
  changed parameters into ``runs/<name>/`` (the executed notebook, its ``data/``
  and ``figures/`` via ``$MTCAL_OUTPUT_DIR``, and ``params.json``) and never touches
  the committed files. :func:`mtcal.runs.compare.compare_runs` (``mtcal compare``)
  puts the comparison tables (``data/*_comparison.csv``) of several runs side by side.

Every executed notebook is normalised (:func:`normalise_notebook`): papermill's
timing metadata and nbclient's execution timestamps are removed and cell ids
are numbered, so a re-run with the same numbers gives identical bytes. A
failed run still writes the partially executed notebook (papermill marks the
failing cell), for inspection. Every kernel runs under
:func:`mtcal.runs.environment.numerics_env`.
"""

from __future__ import annotations

import ast
import hashlib
import json
import re
import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from mtcal.reporting.compare import check_claims
from mtcal.runs.environment import environment, numerics_env, repo_root

__all__ = ["NotebookRunError", "notebook_sources", "resolve_notebook", "parse_parameter", "notebook_parameters",
           "check_parameters", "check_scenario", "SCENARIO_CHECKS", "build_notebook", "normalise_notebook", "sync_notebook", "execute_notebook",
           "run_notebook", "RunResult"]

_NOTEBOOK_RE = re.compile(r"^(\d\d)_[A-Za-z0-9_]+$")
_NAME_RE = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.=+,-]*$")


class NotebookRunError(RuntimeError):
    """A notebook cell raised; ``notebook`` is the partially executed notebook kept for inspection."""

    def __init__(self, message: str, notebook: Path):
        super().__init__(message)
        self.notebook = Path(notebook)


def _notebooks_dir(notebooks_dir: str | Path | None) -> Path:
    if notebooks_dir is not None:
        path = Path(notebooks_dir)
    elif repo_root() is not None:
        path = repo_root() / "notebooks"
    else:
        path = Path.cwd() / "notebooks"
    if not path.is_dir():
        raise FileNotFoundError(f"notebooks_dir {str(path)!r} does not exist (the notebook sources are in "
                                f"the mtcal repository's notebooks/ folder; pass its path)")
    return path


def notebook_sources(notebooks_dir: str | Path | None = None) -> list[Path]:
    """The ``NN_*.py`` notebook sources, in order."""
    folder = _notebooks_dir(notebooks_dir)
    return sorted(p for p in folder.glob("[0-9][0-9]_*.py") if _NOTEBOOK_RE.match(p.stem))


def resolve_notebook(notebook: str | int | Path, notebooks_dir: str | Path | None = None) -> Path:
    """The source ``.py`` of a notebook given by number (``10``, ``"00"``), stem or path.

    Raises ValueError listing the available notebooks when nothing matches.
    """
    if isinstance(notebook, Path) or (isinstance(notebook, str) and notebook.endswith((".py", ".ipynb"))):
        path = Path(notebook).with_suffix(".py")
        if not path.is_file():
            raise FileNotFoundError(f"notebook source {str(path)!r} not found")
        return path
    sources = notebook_sources(notebooks_dir)
    if isinstance(notebook, (int, np.integer)) and not isinstance(notebook, bool):
        key = f"{int(notebook):02d}"
    elif isinstance(notebook, str) and notebook.strip():
        key = notebook.strip()
        if key.isdigit():
            key = f"{int(key):02d}"
    else:
        raise TypeError(f"notebook must be a number, a stem or a path, got {notebook!r}")
    matches = [p for p in sources if p.stem == key or p.stem[:2] == key]
    if len(matches) != 1:
        raise ValueError(f"notebook must be one of {[p.stem for p in sources]} (or its number), got {notebook!r}")
    return matches[0]


def parse_parameter(text: str) -> tuple[str, object]:
    """``"key=value"`` → ``(key, value)``, the value typed as a Python literal, else kept as a string.

    >>> parse_parameter("N_TRIALS=200"), parse_parameter("fs_hz=1e3"), parse_parameter("gyro_grade=industrial")
    (('N_TRIALS', 200), ('fs_hz', 1000.0), ('gyro_grade', 'industrial'))
    >>> parse_parameter("positions_deg=(8, -8)"), parse_parameter("N_TRIALS=None"), parse_parameter("flag=True")
    (('positions_deg', (8, -8)), ('N_TRIALS', None), ('flag', True))
    """
    if not isinstance(text, str) or "=" not in text:
        raise ValueError(f"parameter must be written key=value, got {text!r}")
    key, raw = (s.strip() for s in text.split("=", 1))
    if not key.isidentifier():
        raise ValueError(f"parameter name must be a Python identifier, got {key!r}")
    try:
        value = ast.literal_eval(raw)
    except (ValueError, SyntaxError, TypeError, MemoryError, RecursionError):
        value = raw
    if isinstance(value, (set, frozenset, bytes, complex)):
        raise ValueError(f"parameter {key} must be a number, bool, None, str, tuple or list, got {raw!r}")
    return key, value


def build_notebook(source: str | Path):
    """Read a py:percent source with jupytext into a notebook with numbered cell ids (no outputs)."""
    import jupytext

    nb = jupytext.read(Path(source), fmt="py:percent")
    nb.metadata["kernelspec"] = {"display_name": "Python 3", "language": "python", "name": "python3"}
    return normalise_notebook(nb)


def notebook_parameters(source: str | Path) -> dict[str, dict]:
    """Parameters of a notebook's ``parameters`` cell: every top-level assignment, in cell order.

    Returns ``{name: {"name", "inferred_type_name", "default", "help"}}`` like papermill's
    ``inspect_notebook`` (``default`` is the source text of the value, ``help`` the trailing
    comment), read with :mod:`ast`, so a comment containing ``=`` or ``;`` or a
    conditional default is handled (papermill's line parser skips such lines).
    """
    nb = build_notebook(source)
    cells = [c for c in nb.cells if c.cell_type == "code" and "parameters" in c.metadata.get("tags", [])]
    if not cells:
        raise ValueError(f"notebook {Path(source).name} has no cell tagged 'parameters'")
    text = cells[0].source
    try:
        tree = ast.parse(text)
    except SyntaxError as exc:
        raise ValueError(f"parameters cell of {Path(source).name} is not valid Python: {exc}") from None
    lines = text.splitlines()
    out: dict[str, dict] = {}
    for node in tree.body:
        targets = node.targets if isinstance(node, ast.Assign) else (
            [node.target] if isinstance(node, ast.AnnAssign) and node.value is not None else [])
        for target in targets:
            if not isinstance(target, ast.Name):
                continue
            default = ast.get_source_segment(text, node.value) or ""
            line = lines[node.end_lineno - 1]
            comment = line[node.value.end_col_offset:].partition("#")[2].strip() if "#" in line else ""
            value = _literal_default(default)
            kind = "None" if value is None else type(value).__name__
            out[target.id] = {"name": target.id, "inferred_type_name": kind, "default": default, "help": comment}
    return out


def _literal_default(text: str):
    try:
        return ast.literal_eval(text)
    except (ValueError, SyntaxError, TypeError):
        return None  # an expression (allowed before the convention applies): accept any type


def check_parameters(parameters: dict, valid: dict[str, dict], notebook: str = "notebook") -> dict:
    """Check names (and the type where the default is a literal) against a notebook's parameters.

    Numbers may replace numbers (int ↔ float), lists/tuples each other; a default of
    ``None`` accepts anything. Returns the parameters ready for papermill (tuples as lists).

    >>> valid = {"SEED": {"default": "2023"}, "fs_hz": {"default": "1000.0"}, "grade": {"default": "'x'"}}
    >>> check_parameters({"fs_hz": 500, "grade": "industrial"}, valid)
    {'fs_hz': 500, 'grade': 'industrial'}
    >>> check_parameters({"fs": 500}, valid)
    Traceback (most recent call last):
    ...
    ValueError: unknown parameter 'fs' for notebook; valid: SEED, fs_hz, grade
    """
    out = {}
    for name, value in parameters.items():
        if name not in valid:
            raise ValueError(f"unknown parameter {name!r} for {notebook}; valid: {', '.join(valid)}")
        default = _literal_default(valid[name].get("default", "None"))
        number = (int, float, np.integer, np.floating)
        if default is not None and value is not None:
            if isinstance(default, bool) or isinstance(value, bool):
                ok = isinstance(default, bool) == isinstance(value, bool)
            elif isinstance(default, number):
                ok = isinstance(value, number)
            elif isinstance(default, (list, tuple)):
                ok = isinstance(value, (list, tuple))
            else:
                ok = isinstance(value, type(default))
            if not ok:
                raise ValueError(f"parameter {name} of {notebook} must be like its default "
                                 f"{valid[name].get('default')} ({type(default).__name__}), got {value!r}")
        _check_catalogued(name, value, notebook)
        out[name] = list(value) if isinstance(value, tuple) else value
    return out


def _check_catalogued(name: str, value, notebook: str) -> None:
    """Values whose range every notebook shares, checked before a run starts: a count ``N_*`` (None: the size's
    default) is an integer >= 1, a ``*grade`` one of the sensor grades."""
    if value is None:
        return
    if name.startswith("N_") and (isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1):
        raise ValueError(f"parameter {name} of {notebook} must be an integer >= 1 (or None), got {value!r}")
    if name.endswith("grade"):
        from mtcal.core.sensor_grades import grade_names

        if value not in grade_names():
            raise ValueError(f"parameter {name} of {notebook} must be one of {', '.join(grade_names())}, "
                             f"got {value!r}")


#: Notebooks whose scenario parameters are validated before a run starts, by the study's own validating
#: builder (the one the notebook's set-up cell calls): stem → (module, builder, its defaults, the builder's
#: internal names → the parameters-cell names, for its messages).
SCENARIO_CHECKS: dict[str, tuple[str, str, str, dict[str, str]]] = {
    "20_tan2022_accelerometer": ("mtcal.studies.tan2022", "accel_scenario", "ACCEL_PARAMETER_DEFAULTS",
                                 {"delta_accel_g": "accel_error_g"}),
    "21_tan2022_gyro_roll": ("mtcal.studies.tan2022", "gyro_study", "GYRO_PARAMETER_DEFAULTS",
                             {"noise_density_deg_s_rthz": "gyro_noise_density_deg_s_rthz",
                              "amplitude_deg": "oscillation_amplitude_deg", "freq_hz": "oscillation_freq_hz"}),
    "40_wang2023cja_constrained_calibration": ("mtcal.studies.wang2023cja.constrained", "check_parameters",
                                               "PARAMETER_DEFAULTS", {}),
    "60_broad2021_real_data": ("mtcal.studies.broad2021", "scenario_from_parameters", "PARAMETER_DEFAULTS", {}),
}


def check_scenario(notebook: str, parameters: dict) -> None:
    """Validate a run's scenario parameters with the study's builder before the notebook runs.

    For a notebook in :data:`SCENARIO_CHECKS` given any of its scenario parameters, the builder is called
    with the defaults and those values; its refusal becomes one ``ValueError`` naming the parameter as
    typed, ``-p accel_error_g=-1: must be > 0`` (the builder's internal names mapped back). Other
    notebooks validate in their set-up cell (a refusal is then a failed run).

    >>> check_scenario("20_tan2022_accelerometer", {"accel_error_g": -1})
    Traceback (most recent call last):
    ...
    ValueError: -p accel_error_g=-1: must be > 0
    >>> check_scenario("20_tan2022_accelerometer", {"accel_error_g": 1e-3, "SEED": 1})   # valid: nothing
    """
    if notebook not in SCENARIO_CHECKS:
        return
    module, builder, defaults_name, aliases = SCENARIO_CHECKS[notebook]
    import importlib

    mod = importlib.import_module(module)
    defaults = getattr(mod, defaults_name)
    given = {k: v for k, v in parameters.items() if k in defaults}
    if not given:
        return
    try:
        getattr(mod, builder)(**{**defaults, **given})
    except (ValueError, TypeError) as exc:
        raise ValueError(_scenario_refusal(str(exc), given, aliases)) from None


def _scenario_refusal(message: str, given: dict, aliases: dict[str, str]) -> str:
    """A builder's refusal as ``-p NAME=VALUE: reason`` (internal names → parameter names)."""
    text = lambda v: v if isinstance(v, str) else repr(v)  # noqa: E731
    for internal, name in aliases.items():
        message = re.sub(rf"\b{internal}\b", name, message)
    m = re.match(r"(\w+) (must .*)$", message)
    if m and m.group(1) in given:
        reason = re.sub(r", got .*$", "", m.group(2))
        return f"-p {m.group(1)}={text(given[m.group(1)])}: {reason}"
    named = [k for k in given if re.search(rf"\b{k}\b", message)] or list(given)
    return f"{' '.join(f'-p {k}={text(given[k])}' for k in named)}: {message}"


def _coalesce_streams(outputs: list) -> list:
    """Merge consecutive stream outputs of the same stream: how the kernel splits printed text
    into messages depends on timing (machine load), the text itself does not."""
    merged = []
    for out in outputs:
        if (merged and out.get("output_type") == "stream" and merged[-1].get("output_type") == "stream"
                and merged[-1].get("name") == out.get("name")):
            text = out.get("text", "")
            merged[-1]["text"] = merged[-1].get("text", "") + ("".join(text) if isinstance(text, list) else text)
        else:
            if out.get("output_type") == "stream" and isinstance(out.get("text"), list):
                out["text"] = "".join(out["text"])
            merged.append(out)
    return merged


def normalise_notebook(nb):
    """Drop run-dependent metadata (papermill durations/paths, nbclient timestamps, widgets, the
    empty ``tags`` lists papermill adds), merge stream outputs split by timing, and number the cell
    ids, so that re-running a deterministic notebook gives identical bytes, and an executed notebook
    and one whose inputs were re-synced from its ``.py`` (:func:`sync_notebook`) have the same
    metadata. Returns ``nb``."""
    nb.metadata.pop("papermill", None)
    nb.metadata.pop("widgets", None)
    for i, cell in enumerate(nb.cells):
        cell["id"] = f"cell-{i:03d}"
        cell.metadata.pop("papermill", None)
        cell.metadata.pop("execution", None)
        cell.metadata.pop("ExecuteTime", None)
        if "tags" in cell.metadata and not cell.metadata["tags"]:
            cell.metadata.pop("tags")
        if cell.get("cell_type") == "code":
            cell["outputs"] = _coalesce_streams(cell.get("outputs", []))
    return nb


def sync_notebook(source: str | Path) -> bool:
    """Update ``NN_x.ipynb``'s inputs from its ``NN_x.py`` (jupytext), keeping outputs of unchanged
    cells. Returns True when the ``.ipynb`` was (re)written."""
    import nbformat
    from jupytext.combine import combine_inputs_with_outputs

    source = Path(source)
    target = source.with_suffix(".ipynb")
    nb = build_notebook(source)
    if target.is_file():
        old = nbformat.read(target, as_version=4)
        nb = combine_inputs_with_outputs(nb, old, fmt="py:percent")
        nb.metadata["kernelspec"] = old.metadata.get("kernelspec", nb.metadata["kernelspec"])
        normalise_notebook(nb)
    text = nbformat.writes(nb) + "\n"
    if target.is_file() and target.read_text(encoding="utf-8") == text:
        return False
    target.write_text(text, encoding="utf-8")
    return True


def execute_notebook(source: str | Path, output: str | Path, *, parameters: dict | None = None,
                     env: dict[str, str | None] | None = None, cwd: str | Path | None = None,
                     progress_bar: bool = False, timeout_s: float = 3600.0):
    """Execute a py:percent notebook with papermill into ``output`` (normalised ``.ipynb``).

    Parameters
    ----------
    source : path
        ``NN_x.py`` source (read with jupytext) or an ``.ipynb`` (its inputs are rebuilt
        from the ``.py`` beside it).
    output : path
        Executed notebook to write. Written also when a cell fails (then
        :class:`NotebookRunError` is raised after writing).
    parameters : dict, optional
        Papermill parameters (injected after the ``parameters`` cell).
    env : dict, optional
        Extra environment for the kernel (``None`` values unset a variable); the
        :func:`numerics_env` pins and ``MTCAL_PROGRESS=0`` are always applied.
    cwd : path, optional
        Kernel working directory (default: the source's folder).
    progress_bar : bool or dict
        papermill's progress bar (a dict: tqdm settings, e.g. a ``file``); off by default.
    """
    import nbformat
    import papermill
    from papermill.exceptions import PapermillExecutionError

    source = Path(source).with_suffix(".py")
    output = Path(output)
    output.parent.mkdir(parents=True, exist_ok=True)
    nb = build_notebook(source)
    kernel_env = {**numerics_env(), "MTCAL_PROGRESS": "0", "PYDEVD_DISABLE_FILE_VALIDATION": "1", **(env or {})}
    failure = None
    with environment(kernel_env):
        try:  # saved after every cell, so a timeout, dead kernel or Ctrl-C also leaves the partial notebook
            papermill.execute_notebook(nb, str(output), parameters=parameters or None, kernel_name="python3",
                                       progress_bar=progress_bar, request_save_on_cell_execute=True,
                                       cwd=str(cwd or source.parent), execution_timeout=timeout_s)
        except PapermillExecutionError as exc:
            failure = (f"failed in cell {exc.exec_count}: {exc.ename}: "
                       f"{str(exc.evalue).splitlines()[0] if exc.evalue else ''}")
        except BaseException as exc:  # noqa: BLE001 - normalise what was saved, then re-raise
            if output.is_file():
                partial = normalise_notebook(nbformat.read(output, as_version=4))
                output.write_text(nbformat.writes(partial) + "\n", encoding="utf-8")
            if not isinstance(exc, Exception):
                raise
            failure = f"stopped: {type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}"
            if not output.is_file():
                raise NotebookRunError(f"{source.stem} {failure} (no notebook written)", output) from exc
    executed = normalise_notebook(nbformat.read(output, as_version=4))
    output.write_text(nbformat.writes(executed) + "\n", encoding="utf-8")
    if failure is not None:
        raise NotebookRunError(f"{source.stem} {failure}; the partially executed notebook is {output}", output)
    return executed


@dataclass(frozen=True)
class RunResult:
    """A finished what-if run: its folder, executed notebook, parameters and claims report."""

    folder: Path
    notebook: Path
    parameters: dict
    size: str
    claims: str


def _run_name(stem: str, parameters: dict, size: str) -> str:
    if not parameters:
        return f"{stem[:2]}_{size}"
    text = "_".join(f"{k}={v}" for k, v in parameters.items())
    text = re.sub(r"[^A-Za-z0-9_.=+,-]+", "", text)[:60]
    return f"{stem[:2]}_{text}" if text else f"{stem[:2]}_{hashlib.sha1(repr(parameters).encode()).hexdigest()[:8]}"


def run_notebook(notebook: str | int | Path, *, name: str | None = None, parameters: dict | None = None,
                 size: str = "full", runs_dir: str | Path = "runs", notebooks_dir: str | Path | None = None,
                 overwrite: bool = False, progress_bar: bool = False) -> RunResult:
    """Run one notebook with changed parameters into ``runs_dir/name/`` (a what-if run).

    The folder receives the executed notebook, ``data/`` and ``figures/`` (through
    ``$MTCAL_OUTPUT_DIR``) and ``params.json``; the committed notebooks, ``data/`` and
    ``figures/`` are never written. Parameter names are checked against the
    notebook's ``parameters`` cell before anything runs.

    Parameters
    ----------
    notebook : int, str or path
        Number (``10``), stem (``"10_wang2023cja_turntable"``) or source path.
    name : str, optional
        Run folder name (default: ``NN_<parameters>``).
    parameters : dict, optional
        Values for the parameters cell, e.g. ``{"gyro_grade": "industrial"}``.
    size : {"ci", "full"}
        Run size (``$MTCAL_SIZE`` for the kernel; a ``SIZE`` parameter wins).
    runs_dir : path
        Parent folder of the runs (default ``runs`` under the current directory).
    overwrite : bool
        Replace an existing run folder of the same name (else ValueError).
    progress_bar : bool
        Print a line per executed cell on stderr while the notebook runs (``NN_x: cell 12/40
        [01:23]``; papermill's progress as lines, also when stderr is not a terminal). The
        notebook runs in its own process through :func:`mtcal.runs.executor.execute_jobs`, the
        executor of ``make reproduce``; its outputs do not depend on this.

    Raises
    ------
    ValueError
        Unknown parameter name, value of the wrong type, bad size or name, existing run folder.
    NotebookRunError
        A cell failed; the partial notebook is in the run folder and ``params.json`` says ``failed``.
    """
    if size not in ("ci", "full"):
        raise ValueError(f"size must be 'ci' or 'full', got {size!r}")
    source = resolve_notebook(notebook, notebooks_dir)
    valid = notebook_parameters(source)
    params = check_parameters(dict(parameters or {}), valid, notebook=source.stem)
    check_scenario(source.stem, params)
    name = name or _run_name(source.stem, params, size)
    if not isinstance(name, str) or not _NAME_RE.match(name) or name in (".", ".."):
        raise ValueError(f"name must be a plain folder name (letters, digits, _ . = + , -), got {name!r}")
    folder = Path(runs_dir) / name
    root = repo_root()
    if root is not None:
        committed = [root / "data", root / "figures", root / "notebooks"]
        if any(folder.resolve() == c or c in folder.resolve().parents for c in committed):
            raise ValueError(f"runs_dir must not be inside the committed data/, figures/ or notebooks/, got {runs_dir}")
    if folder.exists():
        if not overwrite:
            raise ValueError(f"run folder {folder} exists; choose another name or overwrite it (--force)")
        shutil.rmtree(folder)
    try:
        folder.mkdir(parents=True)
    except OSError as exc:
        raise ValueError(f"runs_dir {runs_dir}: cannot make the run folder ({exc.strerror}: {exc.filename})") from None
    record = {"notebook": source.stem, "size": size, "parameters": params,
              "defaults": {k: v["default"] for k, v in valid.items()}, "numerics_env": numerics_env(),
              "status": "running"}
    params_path = folder / "params.json"
    params_path.write_text(json.dumps(record, indent=1, sort_keys=True) + "\n", encoding="utf-8")
    output = folder / f"{source.stem}.ipynb"
    env = {"MTCAL_SIZE": size, "MTCAL_OUTPUT_DIR": str(folder.resolve())}
    # the same executor as `make reproduce`: the notebook in its own process, cwd and environment
    from mtcal.runs.executor import NotebookJob, execute_jobs

    result = execute_jobs([NotebookJob(source, output, params, env, progress=bool(progress_bar))], n_jobs=1)[0]
    if not result.ok:
        record["status"] = "failed"
        params_path.write_text(json.dumps(record, indent=1, sort_keys=True) + "\n", encoding="utf-8")
        raise NotebookRunError(result.error, output)
    record["status"] = "completed"
    params_path.write_text(json.dumps(record, indent=1, sort_keys=True) + "\n", encoding="utf-8")
    return RunResult(folder, output, params, size, _claims_report(folder))


def _claims_report(folder: Path) -> str:
    lines = []
    for path in sorted((Path(folder) / "data").glob("*_comparison.csv")):
        table = pd.read_csv(path, dtype=str, keep_default_na=False)
        if "holds" not in table:
            continue
        table["holds"] = table["holds"].map({"True": True, "False": False}).astype(object)
        table.loc[table["holds"].isna(), "holds"] = None
        lines.append(f"{path.stem}: {check_claims(table, enforce=False)}")
    return "\n".join(lines) if lines else "no comparison table written"
