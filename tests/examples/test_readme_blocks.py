"""Every command block of README.md runs in ``make test`` (issue #36), at a small size.

* the command-line block (``mtcal rests walk.csv …``): :mod:`tests.examples.test_readme`;
* the what-if block (``mtcal run`` / ``mtcal compare``): every line as written, in order, in a stand-in
  checkout whose notebooks 10 and 20 are tiny notebooks with the same parameter names (a real CI-size
  run of notebook 10 takes minutes); the real notebooks are checked for every ``-p`` name and type,
  and ``mtcal run 10 --list`` runs on the real notebook 10;
* the sweep block: every line as written on small copies of the shipped specs (2 trials), ``SPEC.toml``
  a small spec and ``tcp://scheduler:8786`` the address of a local Dask scheduler on tcp;
* the ``make`` blocks (``make reproduce``, ``make test``, ``make artifact``, ``make report``) and
  ``.ci/run`` are inherently long (minutes to an hour, and ``make test`` would run itself): each target
  is checked to be well-formed with ``make -n`` (prints the recipe, runs nothing), ``.ci/run`` with
  ``bash -n``. ``make reproduce`` itself is the integrator's and CI's full run.

A block the tests do not know fails :func:`test_every_readme_command_is_covered`.
"""

import os
import re
import shlex
import shutil
import subprocess
from pathlib import Path

import pandas as pd
import pytest

from mtcal import cli
from tests.examples.test_readme import readme_cli_block

ROOT = Path(__file__).resolve().parents[2]
README = ROOT / "README.md"


def readme_blocks() -> list[list[str]]:
    """Every ``sh`` block of the README as its command lines (comments dropped, ``&&`` split)."""
    blocks = re.findall(r"```sh\n(.*?)```", README.read_text(encoding="utf-8"), flags=re.S)
    out = []
    for block in blocks:
        lines = []
        for line in block.splitlines():
            code = line.split("  #")[0].strip()
            lines += [part.strip() for part in code.split("&&") if part.strip()]
        out.append(lines)
    return out


def _block(first: str) -> list[str]:
    return next(b for b in readme_blocks() if b and b[0].startswith(first))


def _kind(line: str) -> str:
    if line.startswith("make ") or line == ".ci/run":
        return "make"
    if line.startswith(("mtcal run ", "mtcal compare ")):
        return "what-if"
    if line.startswith("mtcal sweep"):
        return "sweep"
    if line in readme_cli_block():
        return "cli"
    return "unknown"


def test_every_readme_command_is_covered():
    lines = [ln for block in readme_blocks() for ln in block]
    assert len(lines) >= 20
    assert [ln for ln in lines if _kind(ln) == "unknown"] == []
    assert {_kind(ln) for ln in lines} == {"make", "what-if", "sweep", "cli"}


# -- make blocks: well-formed (make -n), never run here --------------------------------------------

@pytest.mark.parametrize("line", [ln for b in readme_blocks() for ln in b if _kind(ln) == "make"])
def test_readme_make_line_is_well_formed(line):
    if line == ".ci/run":
        assert os.access(ROOT / ".ci" / "run", os.X_OK)
        assert subprocess.run(["bash", "-n", str(ROOT / ".ci" / "run")]).returncode == 0
        return
    env = {k: v for k, v in os.environ.items() if k not in ("MAKEFLAGS", "MFLAGS", "MAKELEVEL")}
    done = subprocess.run(["make", "-n", *shlex.split(line)[1:]], cwd=ROOT, env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip()   # a recipe, not "Nothing to be done"


# -- the what-if block ---------------------------------------------------------------------------

TINY = '''# %% tags=["parameters"]
SIZE = None  # "ci" or "full"
SEED = 2023  # RNG seed
N_TRIALS = None  # None: the size's default
{name} = {default}  # {help}

# %%
import numpy as np
from mtcal.core import metrics
from mtcal.reporting import compare, output

SIZE = output.run_size(SIZE)
N_TRIALS = N_TRIALS or {{"ci": 8, "full": 40}}[SIZE]
{check}
rng = np.random.default_rng(SEED)
draws = {value} * (1.0 + 0.1 * rng.standard_normal(N_TRIALS))
band = metrics.band_or_range(draws)
row = compare.comparison_row("{key}_t1", "{quantity}", {paper}, band["median"], "{claim}",
                             bool(band["median"] {op} {limit}), band=band)
output.save_table(compare.comparison_table([row]), "{key}_comparison")
'''

NOTEBOOKS = {
    "10_tiny_turntable": dict(name="gyro_grade", default='"wang2023cja"', help="a mtcal.core.sensor_grades name",
                              check="from mtcal.core.sensor_grades import sensor_grade\n"
                                    "noise = sensor_grade(gyro_grade).gyro_noise_density_rad_s_rt_hz",
                              value="noise * 1e4", key="tiny_turntable", quantity="scaled gyro noise",
                              paper=0.02, claim="within 0.03 (<= 0.03)", op="<=", limit=0.03),
    "20_tiny_accelerometer": dict(name="accel_error_g", default="1e-4", help="accelerometer error (g)",
                                  check="", value="accel_error_g * 100.0", key="tiny_accelerometer",
                                  quantity="max error (deg)", paper=0.01, claim="(< 0.05)", op="<", limit=0.05),
}


@pytest.fixture
def stand_in_checkout(tmp_path, monkeypatch):
    """A checkout whose notebooks are 10/20 tiny notebooks and whose committed data/ is their full-size run."""
    from mtcal.runs import compare as runs_compare, notebooks as runs_notebooks
    from mtcal.runs.executor import NotebookJob, execute_jobs

    root = tmp_path / "checkout"
    (root / "notebooks").mkdir(parents=True)
    for stem, fields in NOTEBOOKS.items():
        (root / "notebooks" / f"{stem}.py").write_text(TINY.format(**fields), encoding="utf-8")
    jobs = [NotebookJob(p, p, env={"MTCAL_SIZE": "full", "MTCAL_OUTPUT_DIR": str(root)}, mode="script")
            for p in sorted((root / "notebooks").glob("*.py"))]
    assert all(r.ok for r in execute_jobs(jobs, n_jobs=1))   # the "committed" results (make reproduce)
    monkeypatch.setattr(runs_notebooks, "repo_root", lambda: root)
    monkeypatch.setattr(runs_compare, "repo_root", lambda: root)
    monkeypatch.chdir(root)
    return root


def test_readme_what_if_parameters_exist_in_the_real_notebooks(capsys):
    from mtcal.runs.notebooks import check_parameters, notebook_parameters, parse_parameter, resolve_notebook

    lines = [ln for ln in _block("mtcal run") if ln.startswith("mtcal run ")]
    for line in lines:
        argv = shlex.split(line)[2:]
        source = resolve_notebook(shlex.split(line)[2], ROOT / "notebooks")
        given = dict(parse_parameter(argv[i + 1]) for i, a in enumerate(argv) if a == "-p")
        check_parameters(given, notebook_parameters(source), notebook=source.stem)   # raises on a bad name/type
    assert cli.main(["run", "10", "--list"]) == 0
    assert "gyro_grade" in capsys.readouterr().out


def test_readme_what_if_block_runs_as_written(stand_in_checkout, capsys):
    lines = _block("mtcal run")
    assert len(lines) >= 6 and all(_kind(ln) == "what-if" for ln in lines)
    for line in lines:
        code = cli.main(shlex.split(line)[1:])
        out, err = capsys.readouterr()
        assert code == 0, f"{line}: {err}"
        if line.startswith("mtcal compare"):
            assert "claims that flip" in out and "saved: " in out and "WARNING" not in out + err
        elif "--list" not in line:
            assert re.search(r"\d\d_tiny_\w+: cell 1/\d+", err)   # progress lines
    assert (stand_in_checkout / "runs" / "compare_base_vs_industrial.png").is_file()
    table = pd.read_csv(stand_in_checkout / "runs" / "compare_committed_vs_industrial-full.csv", dtype=str,
                        keep_default_na=False)
    assert (table["comparability"] == "comparable").all() and (table["threshold"] == "<= 0.03").all()


# -- the sweep block -------------------------------------------------------------------------------

def test_readme_sweep_block_runs_as_written(tmp_path, monkeypatch, capsys):
    distributed = pytest.importorskip("distributed")
    lines = _block("mtcal sweep")
    assert any("--scheduler" in ln for ln in lines)
    (tmp_path / "examples" / "sweeps").mkdir(parents=True)
    for spec in sorted((ROOT / "examples" / "sweeps").glob("*.toml")):
        small = re.sub(r"(?m)^(block_)?trials\s*=\s*\d+", lambda m: f"{m.group(1) or ''}trials = 2",
                       spec.read_text(encoding="utf-8"))
        (tmp_path / "examples" / "sweeps" / spec.name).write_text(small, encoding="utf-8")
    spec = (tmp_path / "examples" / "sweeps" / "six_position_count.toml").read_text(encoding="utf-8")
    spec = spec.replace('name = "six_position_count"', 'name = "readme_spec"')
    spec = re.sub(r"(?m)^n_positions = .*$", "n_positions = [4, 6]", spec)
    spec = re.sub(r"(?m)^grade = .*$", 'grade = ["wang2023cja"]', spec)
    (tmp_path / "SPEC.toml").write_text(spec, encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False, protocol="tcp",
                                  host="127.0.0.1", dashboard_address=None) as cluster:
        address = cluster.scheduler_address
        assert address.startswith("tcp://")
        for line in lines:
            argv = shlex.split(line.replace("tcp://scheduler:8786", address))[1:]
            code = cli.main(argv)
            out, err = capsys.readouterr()
            assert code == 0, f"{line}: {err}"
    for name in ("windtunnel_vibration", "six_position_count", "readme_spec"):
        table = pd.read_csv(tmp_path / "runs" / "sweeps" / name / "table.csv")
        assert len(table) and (table["trials"] == 2).all() and table["median"].notna().all()
