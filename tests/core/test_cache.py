"""mtcal.core.cache: keyed by parameters, seed and code; stale entries recomputed, never reused."""

import dataclasses

import numpy as np
import pytest

from mtcal.core import cache


@dataclasses.dataclass(frozen=True)
class Setup:
    gain: float
    axis: np.ndarray


CALLS = []


@cache.cached
def monte_carlo(setup: Setup, trials: int, seed: int) -> dict:
    CALLS.append((trials, seed))
    rng = np.random.default_rng(seed)
    return {"x": setup.gain * rng.standard_normal(trials) + setup.axis.sum()}


@pytest.fixture
def store(tmp_path, monkeypatch):
    monkeypatch.setenv("MTCAL_CACHE_DIR", str(tmp_path / "cache"))
    CALLS.clear()
    cache.STATS.clear()
    return tmp_path / "cache"


def test_off_without_the_environment_variable(monkeypatch):
    monkeypatch.delenv("MTCAL_CACHE_DIR", raising=False)
    CALLS.clear()
    monte_carlo(Setup(1.0, np.zeros(3)), 4, 1)
    monte_carlo(Setup(1.0, np.zeros(3)), 4, 1)
    assert CALLS == [(4, 1), (4, 1)] and cache.cache_dir() is None


def test_hit_is_identical_and_keyed_by_parameters_and_seed(store):
    s = Setup(2.0, np.array([0.1, 0.2, 0.3]))
    first = monte_carlo(s, 5, seed=7)
    again = monte_carlo(Setup(2.0, np.array([0.1, 0.2, 0.3])), trials=5, seed=7)
    assert CALLS == [(5, 7)] and again["x"].tobytes() == first["x"].tobytes()
    monte_carlo(s, 5, 8)  # another seed
    monte_carlo(Setup(2.0, np.array([0.1, 0.2, 0.4])), 5, 7)  # another array value
    monte_carlo(s, 6, 7)  # another trial count
    assert len(CALLS) == 4 and cache.STATS["hit"] == 1 and cache.STATS["miss"] == 4
    entries = list(store.glob("*monte_carlo/*/*.pkl"))
    assert len(entries) == 4 and all(p.parent.parent.name.endswith("test_cache.monte_carlo") for p in entries)


def test_changed_code_hash_recomputes_and_deletes_the_stale_entry(store, monkeypatch):
    s = Setup(1.0, np.zeros(3))
    monte_carlo(s, 3, 1)
    old = list(store.rglob("*.pkl"))
    monkeypatch.setattr(cache, "code_hash", lambda func: "f" * 64)  # the producing code changed
    monte_carlo(s, 3, 1)
    assert CALLS == [(3, 1), (3, 1)] and cache.STATS["stale"] == 1
    assert not old[0].exists() and [p.name for p in store.rglob("*.pkl")] == ["f" * 32 + ".pkl"]
    monte_carlo(s, 3, 1)
    assert len(CALLS) == 2 and cache.STATS["hit"] == 1


def test_code_hash_follows_the_imported_mtcal_modules(tmp_path, monkeypatch):
    pkg = tmp_path / "mtcal"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "sub" / "__init__.py").write_text("")
    (pkg / "sub" / "a.py").write_text("from .b import f\n")
    (pkg / "sub" / "b.py").write_text("def f():\n    return 1\n")
    (pkg / "other.py").write_text("x = 1\n")
    monkeypatch.setattr(cache, "_PACKAGE_ROOT", pkg)
    cache._closure_hash.cache_clear()
    cache._data_hash.cache_clear()
    before = cache._closure_hash("mtcal.sub.a")
    (pkg / "other.py").write_text("x = 2\n")  # not imported by a: same hash
    cache._closure_hash.cache_clear()
    assert cache._closure_hash("mtcal.sub.a") == before
    (pkg / "sub" / "b.py").write_text("def f():\n    return 2\n")  # imported by a: new hash
    cache._closure_hash.cache_clear()
    assert cache._closure_hash("mtcal.sub.a") != before
    (pkg / "table.csv").write_text("paper,1\n")  # a data file (paper numbers): new hash
    cache._closure_hash.cache_clear()
    cache._data_hash.cache_clear()
    changed = cache._closure_hash("mtcal.sub.a")
    cache._closure_hash.cache_clear()
    cache._data_hash.cache_clear()
    assert changed != before


def test_code_hash_of_a_study_entry_point_is_stable():
    from mtcal.studies.wang2023cja import runs

    assert cache.code_hash(runs.turntable_runs) == cache.code_hash(runs.turntable_runs)
    assert cache.code_hash(runs.turntable_runs) != cache.code_hash(monte_carlo)


def test_generator_argument_and_unpicklable_result_are_computed_not_cached(store):
    calls = []

    @cache.cached
    def draw(rng):
        calls.append(1)
        return rng.standard_normal()

    @cache.cached
    def make(seed: int):
        calls.append(2)
        return lambda: seed

    draw(np.random.default_rng(1))
    draw(np.random.default_rng(1))
    make(1)
    make(1)
    assert calls == [1, 1, 2, 2] and cache.STATS["uncacheable"] == 2
    assert not list(store.rglob("*.pkl"))


def test_parameters_hash_binds_defaults_and_rejects_bad_calls():
    def f(a, b=2):
        return a

    assert cache.parameters_hash(f, (1,), {}) == cache.parameters_hash(f, (), {"a": 1, "b": 2})
    with pytest.raises(TypeError, match="missing a required argument: 'a'"):
        cache.parameters_hash(f, (), {})


def test_another_numerics_environment_is_another_entry_not_a_stale_one(store, monkeypatch):
    s = Setup(1.0, np.zeros(3))
    monkeypatch.setenv("OPENBLAS_CORETYPE", "Nehalem")
    monte_carlo(s, 3, 1)
    monkeypatch.setenv("OPENBLAS_CORETYPE", "Haswell")
    monte_carlo(s, 3, 1)
    assert len(CALLS) == 2 and cache.STATS["stale"] == 0 and len(list(store.rglob("*.pkl"))) == 2
    monkeypatch.setenv("OPENBLAS_CORETYPE", "Nehalem")
    monte_carlo(s, 3, 1)
    assert len(CALLS) == 2 and cache.STATS["hit"] == 1


def test_papers_numbers_from_mtcal_paper_dir_are_an_input(store, monkeypatch, tmp_path):
    """The leak test points MTCAL_PAPER_DIR at perturbed copies: never served a result of other numbers."""
    papers = tmp_path / "papers"
    papers.mkdir()
    (papers / "x.csv").write_text("value\n1.0\n")
    monkeypatch.setenv("MTCAL_PAPER_DIR", str(papers))
    s = Setup(1.0, np.zeros(3))
    monte_carlo(s, 3, 1)
    (papers / "x.csv").write_text("value\n1000.0\n")  # perturbed held-out number, same folder
    monte_carlo(s, 3, 1)
    assert len(CALLS) == 2 and cache.STATS["hit"] == 0
