"""Static import graph of ``mtcal/``: no import cycle anywhere and imports only point down the layers.

Every module under ``mtcal/`` is parsed with :mod:`ast` (module-level *and* function-level imports,
relative imports resolved), so a cycle hidden behind a deferred ``import`` inside a function is
found too. An edge ``a → b`` means module ``a`` imports module ``b`` (``from pkg import name``
points at ``pkg.name`` when that is a module, else at ``pkg``'s ``__init__``).

Layers, lowest first (a module may import its own layer and the layers below it)::

    core < methods < filters < systems < reporting < studies < sweep < runs < cli

``reporting`` (the papers' printed numbers, comparison rows with Monte Carlo bands, output
files) imports only ``core`` and is what the studies build their comparison rows from, so it
sits below ``studies``; notebook execution and what-if runs (``runs``) sit above everything
they execute. ``mtcal/__init__.py`` (the face, re-exporting from the layers) and
``mtcal/__main__.py`` (the command) are the top and may import any layer.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
LAYERS = ("core", "methods", "filters", "systems", "reporting", "studies", "sweep", "runs", "cli")


def module_name(path: Path, package_dir: Path) -> str:
    """``<package_dir>/a/b.py`` → ``<package>.a.b``; ``a/__init__.py`` → ``<package>.a``."""
    parts = (package_dir.name, *path.relative_to(package_dir).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def import_graph(package_dir: Path) -> dict[str, set[str]]:
    """``{module: {modules of the same package it imports}}`` for every ``.py`` under ``package_dir``."""
    files = {module_name(p, package_dir): p for p in sorted(package_dir.rglob("*.py"))}
    packages = {m for m, p in files.items() if p.name == "__init__.py"}

    def known(name: str) -> str | None:  # the module itself, else its longest known parent
        while name and name not in files:
            name = name.rpartition(".")[0]
        return name or None

    graph: dict[str, set[str]] = {}
    for mod, path in files.items():
        edges: set[str] = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), filename=str(path))):
            if isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:  # relative: from the module's package, up level - 1
                    base = mod if mod in packages else mod.rpartition(".")[0]
                    for _ in range(node.level - 1):
                        base = base.rpartition(".")[0]
                    base = f"{base}.{node.module}" if node.module else base
                else:
                    base = node.module or ""
                targets = [f"{base}.{a.name}" if f"{base}.{a.name}" in files else base for a in node.names]
            else:
                continue
            edges.update(t for t in map(known, targets) if t is not None and t != mod)
        graph[mod] = edges
    return graph


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One import cycle ``[a, b, …, a]``, or None (iterative depth-first search, sorted order)."""
    state: dict[str, int] = {}  # 1: on the current path, 2: done
    for start in sorted(graph):
        if state.get(start):
            continue
        path, stack = [start], [iter(sorted(graph[start]))]
        state[start] = 1
        while stack:
            nxt = next(stack[-1], None)
            if nxt is None:
                state[path.pop()] = 2
                stack.pop()
            elif state.get(nxt) == 1:
                return path[path.index(nxt):] + [nxt]
            elif not state.get(nxt):
                state[nxt] = 1
                path.append(nxt)
                stack.append(iter(sorted(graph.get(nxt, ()))))
    return None


def layer_violations(graph: dict[str, set[str]], layers: tuple[str, ...] = LAYERS) -> list[str]:
    """Edges from a lower layer to a higher one, as ``"a → b (lower → higher)"`` lines."""
    def layer(mod: str) -> str | None:
        parts = mod.split(".")
        return parts[1] if len(parts) > 1 and parts[1] in layers else None

    out = []
    for mod in sorted(graph):
        src = layer(mod)
        for dst_mod in sorted(graph[mod]):
            dst = layer(dst_mod)
            if src is not None and dst is not None and layers.index(dst) > layers.index(src):
                out.append(f"{mod} → {dst_mod} ({src} → {dst})")
    return out


def test_every_package_is_a_known_layer():
    packages = {p.parent.name for p in (ROOT / "mtcal").glob("*/__init__.py")}
    assert packages <= set(LAYERS), f"packages with no layer: {sorted(packages - set(LAYERS))}"


def test_mtcal_has_no_import_cycle():
    graph = import_graph(ROOT / "mtcal")
    assert len(graph) > 50 and "mtcal.core.rotations" in graph["mtcal.core"]
    cycle = find_cycle(graph)
    assert cycle is None, "import cycle: " + " → ".join(cycle)


def test_mtcal_imports_only_point_down_the_layers():
    violations = layer_violations(import_graph(ROOT / "mtcal"))
    assert not violations, "imports pointing up a layer:\n" + "\n".join(violations)


def test_package_inits_import_names_explicitly():
    """No ``from .x import *`` and no ``sys.modules`` rebinding: every re-exported name is listed."""
    for path in sorted((ROOT / "mtcal").rglob("__init__.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        stars = [n.lineno for n in ast.walk(tree)
                 if isinstance(n, ast.ImportFrom) and any(a.name == "*" for a in n.names)]
        assert not stars, f"{path.relative_to(ROOT)}: star import at lines {stars}"
        assert "sys.modules" not in path.read_text(encoding="utf-8"), f"{path.relative_to(ROOT)} rebinds sys.modules"


def test_no_private_name_is_imported_from_another_module():
    """``from mtcal.a import _b`` only for a private *module* of the importer's own package."""
    graph_files = {module_name(p, ROOT / "mtcal"): p for p in (ROOT / "mtcal").rglob("*.py")}
    bad = []
    for mod, path in sorted(graph_files.items()):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.ImportFrom) or node.level or not (node.module or "").startswith("mtcal"):
                continue
            for alias in node.names:
                target = f"{node.module}.{alias.name}"
                own_private_module = target in graph_files and node.module == mod.rpartition(".")[0]
                if alias.name.startswith("_") and not own_private_module:
                    bad.append(f"{mod}:{node.lineno} imports {target}")
    assert not bad, "private names imported across modules:\n" + "\n".join(bad)


# ------------------------------------------------------------------ the checker on a tiny fake package
def _package(tmp_path: Path, files: dict[str, str]) -> Path:
    root = tmp_path / "mtcal"
    for rel, text in files.items():
        path = root / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    return root


def test_checker_finds_a_cycle_through_a_function_level_import(tmp_path):
    root = _package(tmp_path, {
        "__init__.py": "",
        "core/__init__.py": "from . import a, b\n",
        "core/a.py": "from mtcal.core.b import g\n",
        "core/b.py": "def g():\n    from .a import f\n    return f\n",
        "core/c.py": "import mtcal.core.a\n",
    })
    graph = import_graph(root)
    assert graph["mtcal.core"] == {"mtcal.core.a", "mtcal.core.b"}
    assert graph["mtcal.core.b"] == {"mtcal.core.a"} and graph["mtcal.core.c"] == {"mtcal.core.a"}
    assert find_cycle(graph) == ["mtcal.core.a", "mtcal.core.b", "mtcal.core.a"]
    with pytest.raises(AssertionError, match="import cycle: mtcal.core.a → mtcal.core.b → mtcal.core.a"):
        assert find_cycle(graph) is None, "import cycle: " + " → ".join(find_cycle(graph))


def test_checker_finds_a_cycle_through_a_package_init(tmp_path):
    # a module importing a name from its own package's __init__, which imports the module back
    root = _package(tmp_path, {"__init__.py": "", "core/__init__.py": "from .a import f\n",
                               "core/a.py": "from mtcal.core import g\nf = 1\n"})
    assert find_cycle(import_graph(root)) == ["mtcal.core", "mtcal.core.a", "mtcal.core"]


def test_checker_passes_an_acyclic_package_and_flags_an_upward_import(tmp_path):
    root = _package(tmp_path, {
        "__init__.py": "from mtcal import cli\n",
        "core/__init__.py": "", "core/x.py": "import numpy\nfrom ..core import y\n", "core/y.py": "",
        "methods/__init__.py": "", "methods/m.py": "from mtcal.core import x\n",
        "cli/__init__.py": "", "cli/main.py": "from mtcal.methods.m import *\n",
    })
    graph = import_graph(root)
    assert find_cycle(graph) is None
    assert layer_violations(graph) == []
    (root / "core/y.py").write_text("def late():\n    from mtcal.methods import m\n")
    assert layer_violations(import_graph(root)) == ["mtcal.core.y → mtcal.methods.m (core → methods)"]
    assert find_cycle(import_graph(root)) == ["mtcal.methods.m", "mtcal.core.x", "mtcal.core.y", "mtcal.methods.m"]
