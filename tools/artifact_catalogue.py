"""Generate docs/artifacts.md: every figures/*.png and data/*.csv ↔ paper figure/table ↔ notebook section
↔ producing function, read from the notebook sources (no execution).

Usage: ``python tools/artifact_catalogue.py [--check]`` (``--check``: exit 1 when docs/artifacts.md is
out of date or a committed artifact is missing from the catalogue).

Sources of truth, per notebook ``notebooks/NN_*.py`` (py:percent, read with jupytext):

* section headings ``## <artifact id> — <title>`` (the notebook convention);
* ``save_figure(..., "<id>")`` / ``save_table(..., "<id>")`` calls (literal ids);
* the producing function: the study's producer registered for that ID with
  ``mtcal.core.artifacts.produces`` (``mtcal/studies/<key>/artifacts.py``: the one lookup for every
  study), else the call whose result is saved (``save_table(f(...).table, …)`` included), else the
  first call in the section's code to a function imported from ``mtcal`` (reporting helpers such
  as ``save_table``/``comparison_row`` excluded), else a function defined in the notebook itself
  (reported as notebook code).
"""

from __future__ import annotations

import ast
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
KEYS = ("wang2023cja", "tan2022", "wang2022sensors", "broad2021")
ID_RE = re.compile(r"^(?:(?:%s)_\w+|conventions_\w+)$" % "|".join(KEYS))
HEADING_RE = re.compile(r"^#{2,3}\s+`?([A-Za-z0-9_]*)`?(.*)$")
#: helpers that show or save a result rather than produce it
NOT_PRODUCERS = re.compile(r"^mtcal\.reporting\.(output|compare|paper_numbers)\.|^mtcal\.reporting\.[a-z_]+$")
#: artifacts made outside the notebooks
EXTERNAL = {"data/benchmarks.csv": ("—", "`make bench`", "`benchmarks/run.py`"),
            "data/bench_sweep.csv": ("—", "`make bench`", "`benchmarks/bench_sweep.py`"),
            "data/verdicts.csv": ("— (one verdict per paper figure/table)", "`make reproduce`, after the notebooks",
                                  "`mtcal.reporting.artifact_verdicts.write_verdicts`")}


@dataclass
class Entry:
    artifact: str
    notebook: str
    section: str
    producer: str = ""
    kinds: set = field(default_factory=set)


def paper_artifact(artifact: str) -> str:
    """``wang2023cja_fig07`` → ``wang2023cja Fig. 7``; our additions and summaries described as such.

    >>> paper_artifact("wang2023cja_table06"), paper_artifact("tan2022_extra_threshold_sweep")
    ('wang2023cja Table 6', 'tan2022 (ours: threshold sweep)')
    """
    m = re.match(r"^(%s)_(fig|table)(\d+)$" % "|".join(KEYS), artifact)
    if m:
        return f"{m.group(1)} {'Fig.' if m.group(2) == 'fig' else 'Table'} {int(m.group(3))}"
    m = re.match(r"^(%s)_extra_(\w+)$" % "|".join(KEYS), artifact)
    if m:
        return f"{m.group(1)} (ours: {m.group(2).replace('_', ' ')})"
    if artifact.endswith("_comparison"):
        return "paper vs mtcal table"
    if artifact.startswith("conventions_"):
        return f"conventions/errata (ours: {artifact.removeprefix('conventions_').replace('_', ' ')})"
    return "(ours)"


def _imports(tree: ast.AST) -> dict[str, str]:
    """Local name → dotted mtcal path for every ``import``/``from … import`` of mtcal."""
    names = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.split(".")[0] == "mtcal":
            for a in node.names:
                names[a.asname or a.name] = f"{node.module}.{a.name}"
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name.split(".")[0] == "mtcal":
                    names[a.asname or a.name.split(".")[0]] = a.name if a.asname else a.name.split(".")[0]
    return names


def _dotted(node: ast.AST) -> str | None:
    parts = []
    while isinstance(node, ast.Attribute):
        parts.append(node.attr)
        node = node.value
    if isinstance(node, ast.Name):
        parts.append(node.id)
        return ".".join(reversed(parts))
    return None


def _parse(source: str) -> ast.AST | None:
    lines = [ln for ln in source.splitlines() if not ln.lstrip().startswith(("%", "!"))]
    try:
        return ast.parse("\n".join(lines))
    except SyntaxError:
        return None


def _calls(tree: ast.AST):
    """Calls in source order (outer call before its arguments)."""
    found = [n for n in ast.walk(tree) if isinstance(n, ast.Call)]
    return sorted(found, key=lambda n: (n.lineno, n.col_offset))


def _save_ids(tree: ast.AST) -> list[tuple[str, str]]:
    out = []
    for call in _calls(tree):
        name = _dotted(call.func) or ""
        kind = {"save_figure": "png", "save_table": "csv"}.get(name.rsplit(".", 1)[-1])
        if not kind:
            continue
        arg = call.args[1] if len(call.args) > 1 else next((k.value for k in call.keywords
                                                             if k.arg == "artifact_id"), None)
        if isinstance(arg, ast.Constant) and isinstance(arg.value, str):
            out.append((arg.value, kind))
    return out


def registered_producers() -> dict[str, str]:
    """Artifact ID → `` `mtcal.studies.<key>.<name>` `` of every producer a study registers with
    ``mtcal.core.artifacts.produces`` in its ``artifacts`` module (the package's public name when it
    re-exports the producer)."""
    import importlib

    out: dict[str, str] = {}
    for key in KEYS:
        try:
            module = importlib.import_module(f"mtcal.studies.{key}.artifacts")
        except ModuleNotFoundError:
            continue
        package = importlib.import_module(f"mtcal.studies.{key}")
        for name, fn in vars(module).items():
            ident = getattr(fn, "artifact_id", None)
            if name.startswith("_") or not callable(fn) or not isinstance(ident, str):
                continue
            public = f"{package.__name__}.{name}" if getattr(package, name, None) is fn else f"{module.__name__}.{name}"
            if ident.endswith("_" + name):     # the producer named after the ID (``fig12``) is the file's, over a
                out[ident] = f"`{public}`"     # part of its claims declared with the same ID (``threshold_check``)
            else:
                out.setdefault(ident, f"`{public}`")
    return out


def _function_of(node: ast.AST, imports: dict[str, str], local_defs: set[str]) -> str:
    """`mtcal.x.f` for a call of an mtcal function (or a field of its result: ``f(...).table``), notebook
    code for a local one, else ""."""
    while isinstance(node, (ast.Attribute, ast.Subscript)) and isinstance(node.value, (ast.Call, ast.Attribute,
                                                                                        ast.Subscript)):
        node = node.value
    if not isinstance(node, ast.Call):
        return ""
    name = _dotted(node.func)
    if not name:
        return ""
    root, _, rest = name.partition(".")
    if root in imports:
        full = imports[root] + (f".{rest}" if rest else "")
        return "" if NOT_PRODUCERS.search(full) else f"`{full}`"
    if name in local_defs:
        return f"notebook code (`{name}`)"
    return ""


def _producer(trees: list[ast.AST], imports: dict[str, str], local_defs: set[str], artifact: str) -> str:
    """The function whose result is saved as ``artifact`` (the save call's first argument, or the call
    assigned to that variable), else the first mtcal call of the section."""
    assigned: dict[str, ast.AST] = {}
    for tree in trees:
        for node in ast.walk(tree):
            if isinstance(node, ast.Assign) and len(node.targets) == 1:
                target = node.targets[0]
                names = [target] if isinstance(target, ast.Name) else list(getattr(target, "elts", []))
                for t in names:
                    if isinstance(t, ast.Name):
                        assigned[t.id] = node.value
        for call in _calls(tree):
            if (_dotted(call.func) or "").rsplit(".", 1)[-1] not in ("save_figure", "save_table"):
                continue
            ids = [a for a, _ in _save_ids(ast.Expression(body=call))]
            if ids != [artifact] or not call.args:
                continue
            arg = call.args[0]
            found = _function_of(arg, imports, local_defs) or (
                _function_of(assigned.get(arg.id), imports, local_defs) if isinstance(arg, ast.Name) else "")
            if found:
                return found
    first = ""
    for tree in trees:
        for call in _calls(tree):
            found = _function_of(call, imports, local_defs)
            if found.startswith("`"):
                return found
            first = first or found
    return first


def catalogue(notebooks_dir: Path = ROOT / "notebooks") -> list[Entry]:
    """Entries for every artifact named by a section heading or a literal save call, in notebook order."""
    import jupytext

    entries: dict[str, Entry] = {}
    registered = registered_producers()
    for src in sorted(notebooks_dir.glob("[0-9][0-9]_*.py")):
        nb = jupytext.read(src, fmt="py:percent")
        trees = [(_parse(c.source) if c.cell_type == "code" else None) for c in nb.cells]
        all_code = "\n".join(c.source for c in nb.cells if c.cell_type == "code")
        module = _parse(all_code) or ast.parse("")
        imports = _imports(module)
        local_defs = {n.name for n in ast.walk(module) if isinstance(n, ast.FunctionDef)}
        # sections: (heading id or None, heading text, [code trees])
        sections, current = [], [None, "(top)", []]
        for cell, tree in zip(nb.cells, trees):
            if cell.cell_type == "markdown":
                for line in cell.source.splitlines():
                    m = HEADING_RE.match(line.strip())
                    if m and line.startswith("##") and not line.startswith("####"):
                        sections.append(current)
                        ident = m.group(1) if ID_RE.match(m.group(1)) else None
                        current = [ident, line.lstrip("# ").strip(), []]
            elif tree is not None:
                current[2].append(tree)
        sections.append(current)
        comparison = f"{src.stem[3:]}_comparison"  # the convention data/<key>_<topic>_comparison.csv
        for ident, heading, code in sections:
            saves = [s for tree in code for s in _save_ids(tree)]
            named = [ident] if ident else []
            for tree in code:
                for node in ast.walk(tree):
                    if isinstance(node, ast.Constant) and node.value in (comparison, f"{comparison}.csv"):
                        saves.append((comparison, "csv"))
            for artifact in dict.fromkeys(named + [a for a, _ in saves]):
                entry = entries.get(artifact)
                if entry is None:
                    producer = ("`mtcal.reporting.compare.comparison_table`" if artifact.endswith("_comparison")
                                else registered.get(artifact) or _producer(code, imports, local_defs, artifact))
                    entry = entries[artifact] = Entry(artifact, src.stem, heading, producer)
                entry.kinds |= {k for a, k in saves if a == artifact}
        if comparison not in entries:
            ident, heading, code = sections[-1]
            entries[comparison] = Entry(comparison, src.stem, heading, "`mtcal.reporting.compare.comparison_table`")
    return list(entries.values())


def rows(root: Path = ROOT) -> list[tuple[str, str, str, str]]:
    """``(file, paper artifact, notebook § section, producer)`` for every catalogued file.

    A heading without a literal save call lists the files of that id that exist in the
    repository (ids built at run time); a literal save lists its file whether or not it
    exists yet.
    """
    out = []
    for e in catalogue(root / "notebooks"):
        kinds = set(e.kinds) | {k for k, folder in (("png", "figures"), ("csv", "data"))
                                if (root / folder / f"{e.artifact}.{k}").is_file()}
        for kind in sorted(kinds, key=lambda k: k != "png"):
            path = f"{'figures' if kind == 'png' else 'data'}/{e.artifact}.{kind}"
            out.append((path, paper_artifact(e.artifact), f"`{e.notebook}` § {e.section}", e.producer or "—"))
    for path, (paper, where, producer) in EXTERNAL.items():
        if (root / path).is_file():
            out.append((path, paper, where, producer))
    # fidelity scores: one records file per study notebook (its score block), aggregated after the notebooks
    for rec in sorted((root / "data").glob("fidelity_records_*.csv")):
        stem = rec.stem.removeprefix("fidelity_records_")
        out.append((f"data/{rec.name}", "— (held-out numbers, bands)", f"`{stem}` § score block",
                    "`mtcal.reporting.fidelity.write_scores`"))
    for rec in sorted((root / "data").glob("fidelity_cv_*.csv")):      # cross-validation records, same scores file
        stem = rec.stem.removeprefix("fidelity_cv_")
        out.append((f"data/{rec.name}", "— (cross-validated numbers, bands of the model and two baselines)",
                    f"`{stem}` § cross-validation", "`mtcal.reporting.fidelity.write_cv_records`"))
    if (root / "data" / "fidelity_scores.csv").is_file():
        out.append(("data/fidelity_scores.csv", "— (fidelity scores)", "`make reproduce`, after the notebooks",
                    "`mtcal.reporting.fidelity.aggregate_scores`"))
    return out


def render(root: Path = ROOT) -> str:
    lines = ["# Artifact catalogue", "",
             "Every file under `figures/` and `data/`, the paper figure or table it reproduces, the notebook",
             "section that shows it and the library function that produces it. Generated from the notebook",
             "sources by `tools/artifact_catalogue.py` (do not edit by hand; `make test` checks it is current",
             "and complete). `<key>_figNN` / `<key>_tableNN` are the paper's own numbering; `<key>_extra_<slug>`",
             "are our additions; `<notebook>_comparison` tables hold every paper-vs-mtcal row (paper value, our",
             "value with its 95 % Monte Carlo band, the claim, whether it holds, role and source).", "",
             "| file | paper | notebook § section | produced by |", "|---|---|---|---|"]
    for path, paper, where, producer in rows(root):
        cell = lambda s: s.replace("|", "\\|")
        lines.append(f"| `{path}` | {cell(paper)} | {cell(where)} | {cell(producer)} |")
    return "\n".join(lines) + "\n"


def problems(root: Path = ROOT) -> list[str]:
    """Committed artifacts missing from the catalogue, catalogued files that do not exist, stale doc."""
    listed = {r[0] for r in rows(root)}
    committed = {f"figures/{p.name}" for p in (root / "figures").glob("*.png")} | \
                {f"data/{p.name}" for p in (root / "data").glob("*.csv")}
    out = [f"{p}: committed but not in the catalogue (no '## <id> —' heading or save call names it)"
           for p in sorted(committed - listed)]
    out += [f"{p}: catalogued but not in the repository (run make reproduce)" for p in sorted(listed - committed)]
    doc = root / "docs" / "artifacts.md"
    if not doc.is_file() or doc.read_text(encoding="utf-8") != render(root):
        out.append("docs/artifacts.md is out of date: run python tools/artifact_catalogue.py")
    return out


def main(argv: list[str]) -> int:
    if "--check" in argv:
        found = problems()
        print("\n".join(found) if found else "artifact catalogue complete and current")
        return 1 if found else 0
    (ROOT / "docs").mkdir(exist_ok=True)
    (ROOT / "docs" / "artifacts.md").write_text(render(), encoding="utf-8")
    print(f"wrote docs/artifacts.md ({len(rows())} files)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
