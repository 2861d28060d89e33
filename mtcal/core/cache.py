"""On-disk cache of expensive Monte Carlo results, keyed by parameters, seed and the producing code.

A study marks its expensive, seeded entry points with :func:`cached` (one decorator line).
The cache is **off** unless ``$MTCAL_CACHE_DIR`` names a folder (``make reproduce`` and
``make artifact`` use ``build/cache/``), so library users and unit tests are unaffected.

Key of one call (sha-256):

* **parameters** — every argument bound to the signature (defaults applied) and hashed by
  value: numbers, strings, arrays (dtype, shape, bytes), dataclasses (type and fields),
  dicts, sequences, DataFrames; the seed is one of them; plus the environment: the
  Python/numpy/scipy/numba versions, the pinned numerics variables
  (``mtcal.runs.environment.numerics_env``) as set in this process and, when
  ``$MTCAL_PAPER_DIR`` is set, the contents of that folder (the leak test's perturbed
  papers' numbers are an input, hashed on every call);
* **code** — the source of the function and of every mtcal module its module imports,
  directly or through other mtcal modules (static import closure, function-level imports
  included), and the package's data files (the papers' printed numbers).

Layout: ``<dir>/<function>/<parameters hash>/<code hash>.pkl``. A result stored for the same
parameters under another code hash is **stale**: it is deleted and the result recomputed,
never reused. A call whose arguments include a ``numpy.random.Generator`` (its result depends
on the generator's state and the call advances it) or whose result cannot be pickled is
computed, not cached. Writes are atomic (temporary file + rename), so parallel notebooks can
share one cache. Nothing is printed (notebook outputs do not depend on the cache); counts of
hits, misses and stale entries are in :data:`STATS`.

Why a small keyed store rather than ``joblib.Memory``: joblib keys a call on the function's
own source only, so a change in a method or filter it calls would silently reuse a stale
result; it also hashes arguments by pickling, which is not stable for dataclasses holding
frozen arrays across numpy versions. The store here is ~150 lines with no dependency.

References
----------
Issue #22 (artifact cache; showyourwork's cached intermediate step).

Examples
--------
>>> import os, tempfile
>>> calls = []
>>> @cached
... def mc(trials: int, seed: int) -> float:
...     calls.append(seed)
...     return float(trials * seed)
>>> with tempfile.TemporaryDirectory() as d:
...     os.environ["MTCAL_CACHE_DIR"] = d
...     first, again = mc(3, seed=5), mc(3, 5)
...     del os.environ["MTCAL_CACHE_DIR"]
>>> first, again, calls
(15.0, 15.0, [5])
"""

from __future__ import annotations

import ast
import dataclasses
import enum
import functools
import hashlib
import inspect
import logging
import os
import pickle
import platform
import tempfile
from collections import Counter
from pathlib import Path

import numpy as np

__all__ = ["cached", "cache_dir", "code_hash", "parameters_hash", "STATS", "CACHE_ENV"]

#: environment variable naming the cache folder (unset: caching off)
CACHE_ENV = "MTCAL_CACHE_DIR"
#: counts of ``hit``, ``miss``, ``stale``, ``uncacheable`` calls in this process
STATS: Counter = Counter()
_LOG = logging.getLogger("mtcal.cache")
_PACKAGE_ROOT = Path(__file__).resolve().parents[1]  # .../mtcal
_NUMERICS_VARS = ("OPENBLAS_NUM_THREADS", "OPENBLAS_CORETYPE", "NPY_DISABLE_CPU_FEATURES", "GLIBC_TUNABLES",
                  "NUMBA_CPU_NAME")


class _Uncacheable(Exception):
    """An argument whose value cannot key a cache entry."""


def cache_dir() -> Path | None:
    """The cache folder from ``$MTCAL_CACHE_DIR`` (``None``: caching off)."""
    value = os.environ.get(CACHE_ENV, "").strip()
    return Path(value) if value else None


def _feed(h, obj, depth: int = 0) -> None:
    """Hash ``obj`` by value into ``h`` (type-tagged, order-stable)."""
    if depth > 50:
        raise _Uncacheable("nesting too deep")
    if obj is None or isinstance(obj, (bool, int, float, complex, str, bytes)):
        h.update(f"{type(obj).__name__}:{obj!r};".encode())
    elif isinstance(obj, np.random.Generator) or isinstance(obj, np.random.RandomState):
        raise _Uncacheable("a random generator argument (the result depends on, and advances, its state)")
    elif isinstance(obj, np.ndarray):
        if obj.dtype == object:
            h.update(b"objarray;")
            _feed(h, obj.tolist(), depth + 1)
        else:
            h.update(f"nd:{obj.dtype.str}:{obj.shape};".encode())
            h.update(np.ascontiguousarray(obj).tobytes())
    elif isinstance(obj, np.generic):
        _feed(h, obj.item(), depth + 1)
    elif isinstance(obj, enum.Enum):
        h.update(f"enum:{type(obj).__qualname__}.{obj.name};".encode())
    elif isinstance(obj, Path):
        h.update(f"path:{obj};".encode())
    elif dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        h.update(f"dc:{type(obj).__module__}.{type(obj).__qualname__}(".encode())
        for f in dataclasses.fields(obj):
            h.update(f"{f.name}=".encode())
            _feed(h, getattr(obj, f.name), depth + 1)
        h.update(b")")
    elif isinstance(obj, dict):
        h.update(b"dict{")
        for key in sorted(obj, key=repr):
            _feed(h, key, depth + 1)
            _feed(h, obj[key], depth + 1)
        h.update(b"}")
    elif isinstance(obj, (list, tuple, range)):
        h.update(f"{type(obj).__name__}[".encode())
        for item in obj:
            _feed(h, item, depth + 1)
        h.update(b"]")
    elif isinstance(obj, (set, frozenset)):
        h.update(b"set{")
        for item in sorted(obj, key=repr):
            _feed(h, item, depth + 1)
        h.update(b"}")
    elif type(obj).__module__.startswith("pandas") and hasattr(obj, "to_numpy"):
        h.update(f"pd:{type(obj).__name__}:".encode())
        _feed(h, [str(c) for c in getattr(obj, "columns", [])], depth + 1)
        _feed(h, [str(i) for i in obj.index], depth + 1)
        _feed(h, obj.to_numpy(), depth + 1)
    elif callable(obj) and hasattr(obj, "__qualname__"):
        h.update(f"fn:{getattr(obj, '__module__', '')}.{obj.__qualname__};".encode())
    elif hasattr(obj, "__dict__"):
        h.update(f"obj:{type(obj).__module__}.{type(obj).__qualname__}".encode())
        _feed(h, vars(obj), depth + 1)
    else:
        raise _Uncacheable(f"an argument of type {type(obj).__name__}")


def parameters_hash(func, args: tuple, kwargs: dict) -> str:
    """sha-256 of a call's arguments bound to ``func``'s signature (defaults applied).

    >>> def f(a, b=2): ...
    >>> parameters_hash(f, (1,), {}) == parameters_hash(f, (), {"a": 1, "b": 2})
    True
    >>> parameters_hash(f, (1,), {}) == parameters_hash(f, (1, 3), {})
    False
    """
    bound = inspect.signature(func).bind(*args, **kwargs)
    bound.apply_defaults()
    h = hashlib.sha256()
    _feed(h, dict(bound.arguments))
    h.update(_environment_key().encode())
    return h.hexdigest()


def _environment_key() -> str:
    """Library versions and the pinned numerics environment: another environment is another entry
    (kept beside this one), not a stale one."""
    import scipy

    try:
        import numba
        numba_version = numba.__version__
    except ImportError:  # pragma: no cover - numba is a dependency
        numba_version = "-"
    # papers' numbers read from $MTCAL_PAPER_DIR (e.g. the leak test's perturbed copy) are an input:
    # hashed on every call, so other contents are another entry
    paper_dir = os.environ.get("MTCAL_PAPER_DIR")
    paper = _folder_hash(Path(paper_dir)) if paper_dir and Path(paper_dir).is_dir() else "package"
    return (f"{platform.python_version()} numpy {np.__version__} scipy {scipy.__version__} numba {numba_version} "
            + repr([(k, os.environ.get(k)) for k in _NUMERICS_VARS]) + f" papers {paper}")


def _module_file(name: str) -> Path | None:
    parts = name.split(".")
    if parts[0] != "mtcal":
        return None
    base = _PACKAGE_ROOT.joinpath(*parts[1:])
    for candidate in (base.with_suffix(".py"), base / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


def _imported_modules(name: str, path: Path) -> frozenset[str]:
    """mtcal modules imported by the module ``name`` at ``path`` (any level, relative imports resolved)."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = _imports_of_source(package, path.read_text(encoding="utf-8"))
    return frozenset(m for m in found if m.split(".")[0] == "mtcal" and _module_file(m) is not None)


@functools.lru_cache(maxsize=None)
def _imports_of_source(package: str, source: str) -> frozenset[str]:
    """Module names a source imports (relative ones resolved from ``package``): parsed once per process and
    source text (the closures of one notebook's cached functions share most modules; ~0.25 s each walk)."""
    found = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - node.level + 1]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module or ""
            found.add(module)
            found.update(f"{module}.{a.name}" for a in node.names)  # `from pkg import module`
    return frozenset(found)


@functools.lru_cache(maxsize=None)
def _data_hash() -> str:
    """The package's data files (the papers' printed numbers shipped in ``paper_data/``)."""
    return _folder_hash(_PACKAGE_ROOT)


def _folder_hash(folder: Path) -> str:
    h = hashlib.sha256()
    for path in sorted(p for p in folder.rglob("*") if p.is_file() and p.suffix not in (".py", ".pyc")
                       and "__pycache__" not in p.parts):
        h.update(f"{path.relative_to(folder)}\n".encode())
        h.update(path.read_bytes())
    return h.hexdigest()


@functools.lru_cache(maxsize=None)
def _closure_hash(module: str) -> str:
    seen, todo = set(), [module]
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        seen.add(name)
        parts = name.split(".")  # a module's parent packages run first on import
        todo.extend(".".join(parts[:i]) for i in range(1, len(parts)))
        path = _module_file(name)
        if path is not None:
            todo.extend(_imported_modules(name, path) - seen)
    h = hashlib.sha256()
    h.update(_data_hash().encode())
    for name in sorted(seen):
        path = _module_file(name)
        if path is not None:
            h.update(f"{name}\n".encode())
            h.update(path.read_bytes())
    return h.hexdigest()


def code_hash(func) -> str:
    """sha-256 of the code producing ``func``'s results: the function's source, the sources of the
    mtcal modules its module imports (transitively) and the package's data files.
    """
    func = inspect.unwrap(func)
    h = hashlib.sha256()
    try:
        h.update(inspect.getsource(func).encode())
    except (OSError, TypeError):
        h.update(func.__qualname__.encode())
    h.update(_closure_hash(func.__module__).encode() if func.__module__.startswith("mtcal") else _data_hash().encode())
    return h.hexdigest()


def _store(path: Path, value) -> bool:
    try:
        payload = pickle.dumps(value, protocol=pickle.HIGHEST_PROTOCOL)
    except Exception as exc:  # noqa: BLE001 - an unpicklable result is simply not cached
        _LOG.debug("not caching %s: %s", path, exc)
        return False
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".tmp-", suffix=".pkl")
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(payload)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return True


def cached(func=None, *, name: str | None = None):
    """Decorator: cache ``func``'s results on disk under ``$MTCAL_CACHE_DIR`` (module docstring).

    Parameters
    ----------
    func : callable
        A deterministic function of its arguments (seeded Monte Carlo; no global state).
    name : str, optional
        Folder name of its entries (default ``<module>.<qualname>``).

    Returns
    -------
    callable
        The wrapped function (``__wrapped__`` is the original); with the cache off it just calls it.
    """
    if func is None:
        return functools.partial(cached, name=name)
    label = name or f"{func.__module__}.{func.__qualname__}"

    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        root = cache_dir()
        if root is None:
            return func(*args, **kwargs)
        try:
            params = parameters_hash(func, args, kwargs)
        except (_Uncacheable, TypeError) as exc:
            STATS["uncacheable"] += 1
            _LOG.debug("%s: not cached (%s)", label, exc)
            return func(*args, **kwargs)
        folder = root / label / params[:32]
        path = folder / f"{code_hash(func)[:32]}.pkl"
        if path.is_file():
            try:
                with open(path, "rb") as fh:
                    value = pickle.load(fh)
                STATS["hit"] += 1
                return value
            except Exception as exc:  # noqa: BLE001 - a damaged entry is recomputed
                _LOG.debug("%s: unreadable entry %s (%s), recomputing", label, path, exc)
        stale = [p for p in folder.glob("*.pkl") if p != path] if folder.is_dir() else []
        for old in stale:  # same parameters, other code: never reused
            STATS["stale"] += 1
            _LOG.debug("%s: stale entry %s (code changed), recomputing", label, old.name)
            old.unlink(missing_ok=True)
        STATS["miss"] += 1
        value = func(*args, **kwargs)
        _store(path, value)
        return value

    wrapper.cache_label = label
    return wrapper

