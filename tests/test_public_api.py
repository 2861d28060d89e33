"""mtcal's public face: the layers in ``__all__`` (systems included, the tooling ``runs``/``cli`` not),
every name resolvable, nothing heavy loaded by ``import mtcal``."""

import subprocess
import sys

import pytest

import mtcal

LIBRARY_LAYERS = ["core", "methods", "filters", "systems", "reporting", "studies", "sweep"]


def test_all_lists_the_library_layers_in_order_and_not_the_tooling():
    layers = [n for n in mtcal.__all__ if n in LIBRARY_LAYERS + ["runs", "cli"]]
    assert layers == LIBRARY_LAYERS
    assert "runs" not in mtcal.__all__ and "cli" not in mtcal.__all__


def test_every_name_of_all_resolves_and_is_listed_by_dir():
    for name in mtcal.__all__:
        assert getattr(mtcal, name) is not None, name
    assert set(mtcal.__all__) <= set(dir(mtcal))


def test_systems_is_the_systems_package_and_its_names_resolve():
    import mtcal.systems as systems

    assert mtcal.systems is systems
    assert callable(mtcal.systems.surface_angle.surface_angle)


def test_runs_and_cli_stay_importable():
    import mtcal.cli
    import mtcal.runs

    assert mtcal.runs.__name__ == "mtcal.runs" and mtcal.cli.__name__ == "mtcal.cli"
    assert callable(mtcal.cli.main)


def test_unknown_attribute_is_an_attribute_error():
    with pytest.raises(AttributeError, match="module 'mtcal' has no attribute 'no_such_name'"):
        getattr(mtcal, "no_such_name")


def test_import_mtcal_loads_no_layer_and_no_heavy_dependency():
    code = ("import sys, mtcal; "
            "print(sorted(m for m in sys.modules if m.split('.')[0] in ('numba', 'scipy', 'pandas') "
            "or m.startswith(('mtcal.systems', 'mtcal.filters', 'mtcal.methods', 'mtcal.runs', 'mtcal.cli'))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
