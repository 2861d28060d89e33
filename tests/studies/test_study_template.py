"""docs/study_template.md, checked on the source: random numbers only through the keyed streams of
``mtcal.core.rng`` (no ``default_rng(…)``, ``SeedSequence(…)``, ``.spawn(…)``, no bit generator or
legacy global draw), docstrings and doctest examples included."""

import re
from pathlib import Path

import pytest

STUDIES = Path(__file__).resolve().parents[2] / "mtcal" / "studies"
#: direct numpy seeding or drawing, anywhere in a study's source text (code, comments, docstrings)
FORBIDDEN = re.compile(r"\bdefault_rng\(|\bSeedSequence\(|\.spawn\(|\b(?:PCG64|PCG64DXSM|Philox|MT19937|SFC64|"
                       r"RandomState)\(|\bnp\.random\.(?!Generator\b)[a-z_]+\(")
MODULES = sorted(STUDIES.rglob("*.py"))


def test_every_study_is_checked():
    assert {p.parent.name for p in MODULES} >= {"wang2023cja", "tan2022", "wang2022sensors", "broad2021"}


def test_the_pattern_catches_each_form():
    for bad in ("np.random.default_rng(seed)", "np.random.SeedSequence([s, 1])", "rng.spawn(3)",
                "np.random.Generator(np.random.PCG64(k))", "np.random.normal(0, 1)", ">>> rng = default_rng(0)"):
        assert FORBIDDEN.search(bad), bad
    for fine in ("stream_rng(seed, STREAM_FIG06)", "child_rngs(rng, 3)", "rng: np.random.Generator",
                 "a SeedSequence (mtcal.core.rng)", "spawn_philox_key(rng)"):
        assert not FORBIDDEN.search(fine), fine


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(STUDIES)))
def test_study_draws_only_from_keyed_streams(path):
    found = [f"{path.name}:{i}: {line.strip()}" for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
             if FORBIDDEN.search(line)]
    assert not found, "use mtcal.core.rng (stream_rng / trial_rng / child_rngs / rng_copy):\n" + "\n".join(found)


def _artifact_functions():
    """Every public function of a study package whose annotated return is an ``Artifact``."""
    import importlib
    import inspect

    found = []
    for key in sorted(p.name for p in STUDIES.iterdir() if (p / "__init__.py").is_file()):
        pkg = importlib.import_module(f"mtcal.studies.{key}")
        for name in pkg.__all__:
            fn = inspect.unwrap(getattr(pkg, name))
            if inspect.isfunction(fn) and str(inspect.signature(fn).return_annotation).endswith("Artifact"):
                found.append((key, name, getattr(pkg, name)))
    return found


def test_every_artifact_of_a_study_comes_from_a_producer():
    """One Artifact idiom: a study function that returns an Artifact is declared with ``@produces``
    (its ID on the function, stamped on what it returns), in every study."""
    found = _artifact_functions()
    assert {key for key, _, _ in found} >= {"wang2023cja", "tan2022", "wang2022sensors", "broad2021"}
    bare = [f"{key}.{name}" for key, name, fn in found if not getattr(fn, "artifact_id", "").startswith(key + "_")]
    assert not bare, "declare with @produces(artifact_id, kind, paper_item): " + ", ".join(bare)


def test_the_producer_check_catches_an_undeclared_artifact():
    from mtcal.core.artifacts import Artifact, produces

    def bare() -> Artifact:
        return Artifact(None, [], {}, [])

    assert not hasattr(bare, "artifact_id")
    assert produces("demo_fig01", "figure", "Fig. 1")(bare).artifact_id == "demo_fig01"


#: public callables that take the rate because they hold it: the sensor specs and their builders own ``fs_hz``
#: (docs/study_template.md, Time base: "the sample rate is owned by the sensor spec")
_RATE_OWNERS = re.compile(r"\.(ImuSpec|imu_from_grade|AhrsImu\.resolve|sensor_spec|SensorGrade\.sensor_spec)$")


def _rate_taking_functions():
    """``(dotted name, function)`` of every public function or method of mtcal (outside the CLI, whose options
    are the user's words) with a parameter ``fs_hz``."""
    import importlib
    import inspect
    import pkgutil

    import mtcal

    seen, out = set(), []
    for info in pkgutil.walk_packages(mtcal.__path__, "mtcal."):
        if info.name.startswith(("mtcal.cli", "mtcal.runs")) or info.name.rsplit(".", 1)[-1].startswith("_"):
            continue
        module = importlib.import_module(info.name)
        for name in getattr(module, "__all__", ()):
            obj = getattr(module, name, None)
            # functions and the public methods of classes; a class's own fields (a spec, a trial record) hold the rate
            members = [(name, obj)] if inspect.isfunction(obj) else (
                [(f"{name}.{k}", getattr(v, "__func__", v)) for k, v in vars(obj).items()
                 if not k.startswith("_") and (inspect.isfunction(v) or isinstance(v, (classmethod, staticmethod)))]
                if inspect.isclass(obj) else [])
            for label, fn in members:
                if id(fn) in seen:
                    continue
                seen.add(id(fn))
                try:
                    params = inspect.signature(fn).parameters
                except (TypeError, ValueError):
                    continue
                if "fs_hz" in params:
                    out.append((f"{fn.__module__}.{label}", fn))
    return out


def test_a_function_that_makes_samples_from_a_rate_says_why():
    """Time base: a public function that takes (or makes) sample arrays takes ``dt_s``; an exception says why in
    its docstring, saying the rate is taken "not ``dt_s``" and why."""
    found = _rate_taking_functions()
    assert len(found) >= 10
    silent = [name for name, fn in found if not _RATE_OWNERS.search(name)
              and "not ``dt_s``" not in " ".join((fn.__doc__ or "").split())]
    assert not silent, "take dt_s, or say why the rate (\"… not ``dt_s``: …\"): " + ", ".join(silent)
