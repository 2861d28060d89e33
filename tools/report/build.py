"""Build the reproduction report: static HTML under ``build/report/`` (``make report``, part of ``make reproduce``).

Usage (from the repository root)::

    python tools/report/build.py [--out build/report]

Tools: **nbconvert** renders each executed notebook (``notebooks/NN_*.ipynb``) to HTML with
its headings as anchors (so an artifact links to its notebook section) and **Jinja2**
renders the pages from ``tools/report/templates/``. Nothing is fetched from the network
(no CDN scripts: nbconvert's ``basic`` template inside our own page), so the report opens
from disk in any browser. Inputs, all committed: ``docs/artifacts.md`` (the catalogue: every
figure/table, its paper item, notebook section, producing function), ``data/*_comparison.csv``
(every printed number beside ours, band, verdict, role, kind, prior band when present),
``figures/*.png``, ``data/*.csv``, ``docs/errata.md`` and ``data/fidelity_scores.csv`` (when
present).

Pages: ``index.html`` (the three papers and the extras, overall counts, fidelity scores),
``<key>.html`` per paper (fidelity, numbers, claims, errata, every artifact),
``extras.html`` (conventions, benchmarks, anything not of one paper), ``functions.html``
(every producing function: signature, docstring, source) and ``notebooks/<stem>.html``.
"""

from __future__ import annotations

import argparse
import importlib
import inspect
import re
import shutil
import sys
from collections import OrderedDict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TEMPLATES = Path(__file__).resolve().parent / "templates"
KEYS = ("wang2023cja", "tan2022", "wang2022sensors")
FILE_RE = re.compile(r"^`(?P<file>(?:figures|data)/(?P<id>[A-Za-z0-9_]+)\.(?P<ext>png|csv))`$")
WHERE_RE = re.compile(r"^`(?P<notebook>\d\d_[A-Za-z0-9_]+)`\s*§\s*(?P<section>.*)$")
#: Shown per comparison row; ``mc_draws``/``prior_draws`` are the Monte Carlo draws behind each band (a "95 % band"
#: rests on >= 1000, a range prints its count in the band text; mtcal.reporting.compare.check_bands).
COMPARISON_COLUMNS = ["artifact", "quantity", "paper", "mtcal", "mc_band", "mc_draws", "paper_in_band", "prior_band",
                      "prior_draws", "prior_in_band", "claim", "holds", "kind", "role", "source"]
MAX_TABLE_ROWS = 40


def paper_of(artifact_id: str) -> str:
    """The paper key an artifact or comparison table belongs to, else ``"extras"``.

    >>> paper_of("wang2023cja_fig07"), paper_of("wang2022sensors_table05"), paper_of("conventions_allan")
    ('wang2023cja', 'wang2022sensors', 'extras')
    """
    for key in sorted(KEYS, key=len, reverse=True):
        if artifact_id == key or artifact_id.startswith(key + "_"):
            return key
    return "extras"


def read_catalogue(path: Path) -> list[dict]:
    """Every file row of ``docs/artifacts.md`` (notebook-made and external)."""
    rows = []
    for line in path.read_text(encoding="utf-8").splitlines():
        line = line.strip()
        if not (line.startswith("|") and line.endswith("|")):
            continue
        cells = [c.strip().replace("\\|", "|") for c in re.split(r"(?<!\\)\|", line[1:-1])]
        m = FILE_RE.match(cells[0]) if len(cells) == 4 else None
        if not m:
            continue
        where = cells[2]
        w = WHERE_RE.match(where)
        rows.append({"id": m["id"], "file": m["file"], "ext": m["ext"], "paper_item": cells[1],
                     "notebook": w["notebook"] if w else "", "section": w["section"].strip() if w else "",
                     "where": where.replace("`", ""), "producer": cells[3].strip("`")})
    return rows


def errata_sections(path: Path) -> dict[str, tuple[str, str]]:
    """``{key: (heading, markdown)}`` from ``docs/errata.md`` (``"intro"`` for the text before the first paper)."""
    text = path.read_text(encoding="utf-8") if path.is_file() else ""
    out, current, lines, heading = {}, "intro", [], ""
    for line in text.splitlines():
        m = re.match(r"^##\s+(\S+)\s+—\s+(.*)$", line)
        if m and m.group(1) in KEYS:
            out[current] = (heading, "\n".join(lines))
            current, heading, lines = m.group(1), m.group(2), []
        elif not line.startswith("# "):
            lines.append(line)
    out[current] = (heading, "\n".join(lines))
    return out


def _markdown(text: str) -> str:
    import mistune

    return mistune.html(text)


def _verdict(row: dict) -> tuple[str, str]:
    """(css class, label) of a comparison row: its claim verdict, else whether the paper is in our band."""
    holds, in_band = str(row.get("holds", "")), str(row.get("paper_in_band", ""))
    what = {"claim": "claim", "consistency": "consistency"}.get(str(row.get("kind", "")), "check")
    if holds == "True":
        return "pass", f"{what} holds"
    if holds == "False":
        return "fail", f"{what} fails"
    if in_band == "True":
        return "pass", "in band"
    if in_band == "False":
        return "fail", "outside band"
    return "na", "—"


def load_comparisons(data: Path) -> list[dict]:
    """Every row of ``data/*_comparison.csv`` (strings), with its table, paper key and verdict."""
    import pandas as pd

    rows = []
    for path in sorted(data.glob("*_comparison.csv")):
        df = pd.read_csv(path, dtype=str, keep_default_na=False)
        for rec in df.to_dict("records"):
            rec = {c: rec.get(c, "") for c in COMPARISON_COLUMNS} | rec
            rec["table"] = path.stem
            rec["key"] = paper_of(rec["artifact"]) if rec["artifact"] else paper_of(path.stem)
            rec["verdict_class"], rec["verdict"] = _verdict(rec)
            rows.append(rec)
    return rows


def _table_html(path: Path) -> tuple[str, int]:
    import pandas as pd

    df = pd.read_csv(path, dtype=str, keep_default_na=False)
    shown = df.head(MAX_TABLE_ROWS)
    return shown.to_html(index=False, classes="data", border=0, escape=True), len(df)


def render_notebooks(notebooks: Path, out: Path) -> dict[str, dict[str, str]]:
    """Executed notebooks → ``out/notebooks/<stem>.html``; returns ``{stem: {heading text: anchor id}}``."""
    import nbformat
    from bs4 import BeautifulSoup
    from nbconvert import HTMLExporter

    exporter = HTMLExporter(template_name="basic")
    anchors = {}
    (out / "notebooks").mkdir(parents=True, exist_ok=True)
    for path in sorted(notebooks.glob("[0-9][0-9]_*.ipynb")):
        nb = nbformat.read(path, as_version=4)
        body, _ = exporter.from_notebook_node(nb)
        soup = BeautifulSoup(body, "html.parser")
        found = {}
        for h in soup.find_all(re.compile(r"^h[1-6]$")):
            if h.get("id"):
                text = h.get_text(" ", strip=True).rstrip("¶").strip()
                found.setdefault(" ".join(text.split()), h["id"])
        anchors[path.stem] = found
        (out / "notebooks" / f"{path.stem}.html").write_text(
            _env().get_template("notebook.html").render(title=path.stem, body=body, root="../",
                                                        css=_pygments_css()), encoding="utf-8")
    return anchors


def _anchor(anchors: dict[str, str], section: str) -> str:
    want = " ".join(section.replace("`", "").split())
    for text, anchor in anchors.items():
        if text == want:
            return anchor
    for text, anchor in anchors.items():
        if text.startswith(want) or want.startswith(text):
            return anchor
    return ""


def _pygments_css() -> str:
    from pygments.formatters import HtmlFormatter

    return HtmlFormatter(style="default").get_style_defs(".highlight")


def _env():
    import jinja2

    return jinja2.Environment(loader=jinja2.FileSystemLoader(TEMPLATES), autoescape=jinja2.select_autoescape(["html"]),
                              undefined=jinja2.StrictUndefined, trim_blocks=True, lstrip_blocks=True,
                              keep_trailing_newline=True)


def describe_function(dotted: str) -> dict | None:
    """Signature, docstring and source of ``mtcal.a.b.fn`` (None when it is not an importable function)."""
    if not re.match(r"^mtcal(\.[A-Za-z_][A-Za-z0-9_]*)+$", dotted):
        return None
    module_name, _, name = dotted.rpartition(".")
    try:
        obj = getattr(importlib.import_module(module_name), name)
        source = inspect.getsource(inspect.unwrap(obj))
        file = Path(inspect.getsourcefile(inspect.unwrap(obj))).resolve()
        try:
            file = file.relative_to(ROOT)
        except ValueError:
            pass
        return {"name": dotted, "signature": f"{name}{inspect.signature(obj)}", "doc": inspect.getdoc(obj) or "",
                "source": source, "file": str(file), "anchor": dotted}
    except Exception:  # noqa: BLE001 - a catalogue entry that is not a function: shown as text
        return None


def build_report(root: Path = ROOT, out: Path | None = None) -> dict:
    """Build the report from the committed results of ``root`` into ``out`` (default ``root/build/report``).

    Returns ``{"pages": [...], "artifacts": [...]}``: the pages written and every catalogue ID shown.
    """
    root = Path(root)
    out = Path(out) if out is not None else root / "build" / "report"
    if out.exists():
        shutil.rmtree(out)
    (out / "figures").mkdir(parents=True)
    catalogue = read_catalogue(root / "docs" / "artifacts.md")
    comparisons = load_comparisons(root / "data")
    errata = errata_sections(root / "docs" / "errata.md")
    anchors = render_notebooks(root / "notebooks", out)
    fidelity = None
    fidelity_path = root / "data" / "fidelity_scores.csv"
    if fidelity_path.is_file():
        import pandas as pd

        fidelity = pd.read_csv(fidelity_path, dtype=str, keep_default_na=False)

    functions = OrderedDict()
    artifacts = OrderedDict()  # id → artifact record (files grouped)
    for row in catalogue:
        art = artifacts.setdefault(row["id"], {"id": row["id"], "key": paper_of(row["id"]),
                                               "paper_item": row["paper_item"], "where": row["where"],
                                               "notebook": row["notebook"], "section": row["section"],
                                               "figures": [], "tables": [], "producers": [], "link": "",
                                               "missing": []})
        if row["notebook"] and (root / "notebooks" / f"{row['notebook']}.ipynb").is_file():
            anchor = _anchor(anchors.get(row["notebook"], {}), row["section"])
            art["link"] = f"notebooks/{row['notebook']}.html" + (f"#{anchor}" if anchor else "")
        src = root / row["file"]
        if row["ext"] == "png" and src.is_file():
            shutil.copyfile(src, out / "figures" / src.name)
            art["figures"].append({"src": f"figures/{src.name}", "file": row["file"]})
        elif row["ext"] == "csv" and src.is_file():
            table, n = _table_html(src)
            art["tables"].append({"file": row["file"], "html": table, "n": n, "shown": min(n, MAX_TABLE_ROWS)})
        else:
            art["missing"].append(row["file"])
        producer = row["producer"]
        if producer and producer not in [p["name"] for p in art["producers"]]:
            info = functions.get(producer) or describe_function(producer)
            if info:
                functions[producer] = info
            art["producers"].append({"name": producer, "link": f"functions.html#{producer}" if info else ""})

    for r in comparisons:  # link a row to its artifact's section when the catalogue has it
        r["artifact_link"] = f"#art-{r['artifact']}" if r["artifact"] in artifacts else ""
    groups = [(key, errata.get(key, ("", ""))[0]) for key in KEYS] + [("extras", "conventions, benchmarks and "
                                                                                 "everything not of one paper")]
    env = _env()
    pages = []
    summary = []
    for key, citation in groups:
        rows = [r for r in comparisons if r["key"] == key]
        # the paper's claims (kind "claim") apart from checks true by construction ("consistency") and our findings
        claims = [r for r in rows if r.get("claim") and r.get("kind") == "claim"]
        checks = [r for r in rows if r.get("claim") and r.get("kind") != "claim"]
        heldout = [r for r in rows if r.get("role") == "heldout" and str(r.get("paper_in_band")) in ("True", "False")]
        arts = [a for a in artifacts.values() if a["key"] == key]
        fid = None
        if fidelity is not None and "scope" in fidelity:
            part = fidelity[fidelity["scope"].astype(str).str.contains(key)] if key != "extras" else fidelity.iloc[0:0]
            fid = part.to_html(index=False, classes="data", border=0) if len(part) else None
        err = errata.get(key)
        page = "extras.html" if key == "extras" else f"{key}.html"
        n_pass = sum(r["verdict_class"] == "pass" for r in rows)
        n_fail = sum(r["verdict_class"] == "fail" for r in rows)
        summary.append({"key": key, "citation": citation, "page": page, "n_rows": len(rows), "n_pass": n_pass,
                        "n_fail": n_fail, "n_claims": len(claims),
                        "n_claims_hold": sum(str(r.get("holds")) == "True" for r in claims),
                        "n_checks": len(checks), "n_checks_hold": sum(str(r.get("holds")) == "True" for r in checks),
                        "n_heldout": len(heldout),
                        "n_heldout_in": sum(str(r.get("paper_in_band")) == "True" for r in heldout),
                        "n_artifacts": len(arts)})
        roles = sorted({r.get("role", "") for r in rows if r.get("role")})
        (out / page).write_text(env.get_template("paper.html").render(
            title=key if key != "extras" else "Extras", key=key, citation=citation, rows=rows, claims=claims, checks=checks,
            artifacts=arts, fidelity=fid, errata=_markdown(err[1]) if err and key != "extras" else "",
            errata_intro=_markdown(errata.get("intro", ("", ""))[1]) if key == "extras" else "",
            roles=roles, columns=[c for c in COMPARISON_COLUMNS if any(r.get(c) for r in rows)], root=""),
            encoding="utf-8")
        pages.append(page)
    overall = None
    if fidelity is not None:
        overall = fidelity.to_html(index=False, classes="data", border=0)
    notebooks = sorted(anchors)
    (out / "index.html").write_text(env.get_template("index.html").render(
        title="mtcal reproduction report", summary=summary, notebooks=notebooks, fidelity=overall,
        n_artifacts=len(artifacts), root=""), encoding="utf-8")
    (out / "functions.html").write_text(env.get_template("functions.html").render(
        title="Producing functions", functions=list(functions.values()), root="", css=_pygments_css()),
        encoding="utf-8")
    pages = ["index.html", "functions.html"] + pages + [f"notebooks/{n}.html" for n in notebooks]
    return {"pages": pages, "artifacts": list(artifacts), "out": out}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(ROOT / "build" / "report"), help="output folder (default build/report)")
    args = parser.parse_args(argv)
    try:
        result = build_report(ROOT, Path(args.out))
    except (ImportError, FileNotFoundError, ValueError) as exc:
        print(f"report: error: {type(exc).__name__}: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    print(f"report: {len(result['pages'])} pages, {len(result['artifacts'])} artifacts → "
          f"{Path(result['out']) / 'index.html'}")
    return 0


if __name__ == "__main__":
    sys.path.insert(0, str(ROOT))
    sys.exit(main())
