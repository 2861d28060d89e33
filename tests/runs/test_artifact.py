"""Rebuilding one artifact from the Monte Carlo cache: byte-identical to the notebook's own file."""

import shutil

import pytest

from mtcal import cli
from mtcal.runs import artifact
from mtcal.runs.executor import NotebookJob, execute_jobs
from mtcal.runs.environment import repo_root

ROOT = repo_root()


def test_catalogue_rows_name_notebook_section_and_producer():
    rows = artifact.load_catalogue()
    ids = {r.artifact_id for r in rows}
    assert {"wang2023cja_fig07", "tan2022_fig06", "wang2022sensors_table05"} <= ids
    fig07 = next(r for r in rows if r.artifact_id == "wang2023cja_fig07")
    assert fig07.notebook == "10_wang2023cja_turntable" and fig07.section.startswith("wang2023cja_fig07 — ")
    assert fig07.producer == "mtcal.studies.wang2023cja.plots.fig07" and fig07.paper == "wang2023cja Fig. 7"


def test_truncate_keeps_cells_up_to_the_end_of_the_section(tmp_path):
    src = tmp_path / "01_x.py"
    src.write_text("# %% [markdown]\n# # title\n\n# %%\na = 1\n\n# %% [markdown]\n# ## x_fig01 — first\n\n"
                   "# %%\nb = 2\n\n# %% [markdown]\n# ### detail\n\n# %%\nc = 3\n\n# %% [markdown]\n"
                   "# ## x_fig02 — second\n\n# %%\nd = 4\n", encoding="utf-8")
    out = artifact.truncate_notebook(src, "x_fig01 — first", tmp_path / "cut.py").read_text()
    assert "a = 1" in out and "b = 2" in out and "c = 3" in out and "d = 4" not in out
    with pytest.raises(ValueError, match="has no section headed 'x_fig09'"):
        artifact.truncate_notebook(src, "x_fig09", tmp_path / "cut.py")


def test_unknown_id_and_bad_size_are_rejected(tmp_path):
    with pytest.raises(ValueError, match="unknown artifact 'wang2023cja_fig7'; did you mean wang2023cja_fig07"):
        artifact.rebuild_artifact("wang2023cja_fig7", out_dir=tmp_path)
    with pytest.raises(ValueError, match="size must be 'ci' or 'full', got 'tiny'"):
        artifact.rebuild_artifact("wang2023cja_fig07", size="tiny", out_dir=tmp_path)


def test_cli_reproduce_unknown_id_is_one_line_error(capsys):
    assert cli.main(["reproduce", "nope_fig01"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("mtcal: error: unknown artifact 'nope_fig01'") and err.count("\n") == 1


def test_rebuild_from_cache_is_byte_identical_to_the_notebook_file(tmp_path):
    """CI size: notebook 20 writes its files (and fills the cache); one figure and one table are then
    rebuilt from the cache into another folder and compared byte for byte."""
    cache, full = tmp_path / "cache", tmp_path / "full"
    source = ROOT / "notebooks" / "20_tan2022_accelerometer.py"
    env = {"MTCAL_OUTPUT_DIR": str(full), "MTCAL_SIZE": "ci", "MTCAL_CACHE_DIR": str(cache)}
    result = execute_jobs([NotebookJob(source, tmp_path / "nb.ipynb", env=env)])[0]
    assert result.ok, result.error
    assert list(cache.rglob("*.pkl"))  # the Monte Carlo entry points were cached
    out = tmp_path / "rebuilt"
    for art_id, files in (("tan2022_extra_error_model_accel", ["figures/tan2022_extra_error_model_accel.png",
                                                                 "data/tan2022_extra_error_model_accel.csv"]),
                          ("tan2022_extra_independent_errors", ["figures/tan2022_extra_independent_errors.png",
                                                                  "data/tan2022_extra_independent_errors.csv"])):
        rebuilt = artifact.rebuild_artifact(art_id, size="ci", out_dir=out, cache_dir=cache,
                                            build_dir=tmp_path / "build" / art_id)
        assert {p.relative_to(out).as_posix() for p in rebuilt.files} == set(files)
        assert set(rebuilt.files.values()) == {"new"}
        for f in files:
            assert (out / f).read_bytes() == (full / f).read_bytes(), f
    # the same rebuild into the notebook's folder reports identical files and changes nothing
    again = artifact.rebuild_artifact("tan2022_extra_independent_errors", size="ci", out_dir=full, cache_dir=cache,
                                      build_dir=tmp_path / "build" / "again")
    assert set(again.files.values()) == {"identical"}
    shutil.rmtree(tmp_path / "build")
