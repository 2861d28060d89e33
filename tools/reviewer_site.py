"""Build the reviewer's site: every paper artifact with its verdict, our figure and the paper's table layout.

Usage (from the repository root; ``make report``, last step of ``make reproduce``)::

    python tools/reviewer_site.py [--verdicts data/verdicts.csv] [--out build/report] [--src build/site-src]

Sphinx + MyST-NB with sphinx-book-theme. The sources are ``docs/`` (``conf.py``, ``_static/`` and the
hand-written MyST pages ``docs/*.md``); this script stages them in ``--src`` together with the executed
notebooks (``notebooks/NN_*.ipynb``, rendered as they are: execution off), the figures, the data files and
the pages it generates from data, then runs ``sphinx-build`` into ``--out`` (``index.html``). Nothing of
the build is committed; everything it reads is:

* ``data/verdicts.csv`` — one row per catalogue artifact: ``artifact_id, paper, paper_item, verdict,
  numbers_compared, numbers_inside, claims_holding, claims_failing, cause, notebook_section``, verdict one
  of :data:`VERDICTS`. Required: a missing file, a missing column, an unknown verdict, a catalogue
  artifact without its row or a row without its artifact stops the build with ``site: error: …``;
* ``docs/artifacts.md`` (the catalogue: file, paper item, notebook § section, producing function);
* ``data/*_comparison.csv`` (every printed number beside ours: band, inside or not, role, claim) and the
  paper's own tables ``mtcal/reporting/paper_data/*.csv`` (their layout: a comparison row's ``ref``
  ``<table>:<row>:<column>`` places our number beside the printed one);
* ``data/fidelity_scores.csv`` (held-out coverage and sharpness, put in words) and ``docs/errata.md``.

Pages: ``index`` (a scoreboard per paper), one page per paper with its figures and tables in the paper's
order (:func:`paper_order`) followed by our additions, one page per other notebook (constrained
calibration, filter bake-off, conventions, real data …), ``other`` (files made outside the notebooks),
``api`` (every producing function: docstring and highlighted source), the rendered notebooks and the
hand-written docs. The page is self-contained: no CDN, no web font, no MathJax (the notebooks carry no
LaTeX), so ``build/report/index.html`` opens from ``file://`` offline.
"""

from __future__ import annotations

import argparse
import csv
import filecmp
import html
import json
import re
import shutil
import sys
import time
import warnings
from collections import Counter, OrderedDict
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: paper keys in the order of the front page (a key is shown once data/verdicts.csv has its rows)
KEYS = ("wang2023cja", "tan2022", "wang2022sensors", "broad2021")
VERDICTS = ("reproduced", "partly reproduced", "not reproduced", "not comparable")
VERDICT_COLUMNS = ("artifact_id", "paper", "paper_item", "verdict", "numbers_compared", "numbers_inside",
                   "claims_holding", "claims_failing", "cause", "notebook_section")
FILE_RE = re.compile(r"^`(?P<file>(?:figures|data)/(?P<id>[A-Za-z0-9_]+)\.(?P<ext>png|csv))`$")
WHERE_RE = re.compile(r"^`(?P<notebook>\d\d_[A-Za-z0-9_]+)`\s*§\s*(?P<section>.*)$")
ITEM_RE = re.compile(r"^(?P<key>[a-z0-9]+)_(?P<kind>fig|table)(?P<num>\d+)$")
ROLE_WORDS = {"heldout": "held out", "train": "training", "finding": "our finding", "erratum": "erratum",
              "consistency": "consistency"}
KIND_WORDS = {"claim": "paper claim", "consistency": "consistency check", "": "our check"}
PAPER_DATA = ROOT / "mtcal" / "reporting" / "paper_data"
#: the catalogue id of data/verdicts.csv itself (catalogued once committed): it gives the badges, carries none
SELF = "verdicts"


class SiteError(Exception):
    """An input the site cannot be built from (printed as one ``site: error:`` line, exit 2)."""


@dataclass
class Artifact:
    """One catalogue artifact: its files, where it is shown and how it is produced."""

    id: str
    paper_item: str
    notebook: str
    section: str
    where: str
    producer: str
    files: list = field(default_factory=list)


# ---------------------------------------------------------------------------------------------- inputs

def read_catalogue(path: Path) -> "OrderedDict[str, Artifact]":
    """Every artifact of ``docs/artifacts.md`` (file rows grouped by id), in catalogue order.

    >>> cat = read_catalogue(ROOT / "docs" / "artifacts.md")
    >>> a = cat["wang2023cja_fig07"]
    >>> a.paper_item, a.notebook, a.files, a.producer
    ('wang2023cja Fig. 7', '10_wang2023cja_turntable', ['figures/wang2023cja_fig07.png'], 'mtcal.studies.wang2023cja.plots.fig07')
    """
    out: OrderedDict[str, Artifact] = OrderedDict()
    for line in path.read_text(encoding="utf-8").splitlines():
        line = line.strip()
        if not (line.startswith("|") and line.endswith("|")):
            continue
        cells = [c.strip().replace("\\|", "|") for c in re.split(r"(?<!\\)\|", line[1:-1])]
        m = FILE_RE.match(cells[0]) if len(cells) == 4 else None
        if not m:
            continue
        w = WHERE_RE.match(cells[2])
        art = out.setdefault(m["id"], Artifact(m["id"], cells[1], w["notebook"] if w else "",
                                               w["section"].strip() if w else "", cells[2].replace("`", ""),
                                               cells[3].strip("`")))
        art.files.append(m["file"])
    return out


def needs_verdict(artifact: "Artifact") -> bool:
    """A catalogue entry that carries a verdict: a paper figure/table or one of our additions
    (:func:`mtcal.reporting.artifact_verdicts.has_verdict`, the rule that writes ``data/verdicts.csv``);
    the bookkeeping files (comparison tables, fidelity records and scores, benchmarks) carry none."""
    from mtcal.reporting.artifact_verdicts import has_verdict

    return has_verdict(artifact.paper_item)


def read_verdicts(path: Path, catalogue: dict) -> "OrderedDict[str, dict]":
    """``data/verdicts.csv`` checked against the catalogue: ``{artifact_id: row}``.

    Every catalogue entry that :func:`needs_verdict` has exactly one row; no row names another id.

    Raises
    ------
    SiteError
        The file is missing, a column is missing, a verdict is not one of :data:`VERDICTS`, a count is not a
        whole number, or the rows and the catalogue artifacts differ (each one named).
    """
    if not path.is_file():
        raise SiteError(f"{path}: no such file: the verdicts table (one row per catalogue artifact, "
                        f"written by make reproduce) is needed; --verdicts PATH names another file")
    with path.open(encoding="utf-8", newline="") as fh:
        reader = csv.DictReader(fh)
        missing = [c for c in VERDICT_COLUMNS if c not in (reader.fieldnames or [])]
        if missing:
            raise SiteError(f"{path}: missing column(s) {', '.join(missing)} (expected {', '.join(VERDICT_COLUMNS)})")
        rows = list(reader)
    out: OrderedDict[str, dict] = OrderedDict()
    for i, row in enumerate(rows, start=2):
        aid = row["artifact_id"]
        if row["verdict"] not in VERDICTS:
            raise SiteError(f"{path}:{i}: verdict {row['verdict']!r} of {aid} is not one of {', '.join(VERDICTS)}")
        for col in ("numbers_compared", "numbers_inside", "claims_holding", "claims_failing"):
            if not re.fullmatch(r"\d+", row[col].strip()):
                raise SiteError(f"{path}:{i}: {col} of {aid} is {row[col]!r}, not a whole number")
        if aid == SELF and aid not in catalogue:
            continue
        if aid in out:
            raise SiteError(f"{path}:{i}: {aid} has a second row")
        out[aid] = row
    unknown = [a for a in out if a not in catalogue]
    absent = [a for a, art in catalogue.items() if a not in out and a != SELF
              and (art is None or needs_verdict(art))]
    if unknown or absent:
        raise SiteError(f"{path}: rows and catalogue (docs/artifacts.md) differ: "
                        + "; ".join(p for p in (f"no verdict for {', '.join(absent)}" if absent else "",
                                                f"not in the catalogue: {', '.join(unknown)}" if unknown else "")
                                    if p))
    return out


def read_comparisons(data: Path) -> list[dict]:
    """Every row of ``data/*_comparison.csv`` as strings, with the table it comes from."""
    rows = []
    for path in sorted(data.glob("*_comparison.csv")):
        with path.open(encoding="utf-8", newline="") as fh:
            for rec in csv.DictReader(fh):
                rec["table"] = path.stem
                rows.append(rec)
    return rows


def read_fidelity(path: Path, role: str = "heldout") -> dict[tuple[str, str], dict]:
    """``{(scope, baseline): row}`` of the ``role`` rows of ``data/fidelity_scores.csv`` (empty when absent)."""
    if not path.is_file():
        return {}
    with path.open(encoding="utf-8", newline="") as fh:
        return {(r["scope"], r["baseline"]): r for r in csv.DictReader(fh) if r.get("role", "heldout") == role}


def errata_sections(path: Path) -> dict[str, tuple[str, int]]:
    """``{key: (citation, number of errata)}`` from the ``## <key> — <citation>`` sections of ``docs/errata.md``."""
    out, key = {}, None
    for line in path.read_text(encoding="utf-8").splitlines() if path.is_file() else []:
        m = re.match(r"^##\s+(\S+)\s+—\s+(.*)$", line)
        if m:
            key = m.group(1)
            out[key] = (m.group(2).strip(), 0)
        elif key and re.match(r"^\|\s*[^|#\s-][^|]*\|", line):
            out[key] = (out[key][0], out[key][1] + 1)
    return out


# ------------------------------------------------------------------------------------------ ordering

def paper_key(artifact_id: str) -> str:
    """The paper an artifact id belongs to, else ``""``.

    >>> paper_key("wang2022sensors_fig06"), paper_key("tan2022_extra_roll_error"), paper_key("conventions_allan")
    ('wang2022sensors', 'tan2022', '')
    """
    return next((k for k in sorted(KEYS, key=len, reverse=True) if artifact_id.startswith(k + "_")), "")


def paper_order(ids: list[str]) -> list[str]:
    """The paper's figures and tables in the paper's order.

    Each paper numbers its figures and its tables in the order they appear, so each kind is sorted by its
    number; the two sequences are merged by where the notebooks show them (``ids`` in catalogue order, the
    notebooks follow the paper), taking the next table or the next figure, whichever comes first there.

    >>> paper_order(["x_table01", "x_fig06", "x_table02", "x_fig12", "x_table04", "x_fig09", "x_fig11", "x_table05"])
    ['x_table01', 'x_fig06', 'x_table02', 'x_table04', 'x_fig09', 'x_fig11', 'x_fig12', 'x_table05']
    """
    position = {a: i for i, a in enumerate(ids)}
    kinds = {"table": [], "fig": []}
    for a in ids:
        m = ITEM_RE.match(a)
        if m:
            kinds[m["kind"]].append((int(m["num"]), a))
    tables, figs = (sorted(kinds[k]) for k in ("table", "fig"))
    out = []
    while tables or figs:
        take = tables if not figs or (tables and position[tables[0][1]] < position[figs[0][1]]) else figs
        out.append(take.pop(0)[1])
    return out


# ------------------------------------------------------------------------------------- page fragments

def esc(text) -> str:
    return html.escape(str(text), quote=True)


def badge(verdict: str, artifact_id: str = "") -> str:
    """The verdict badge (inline HTML); ``data-artifact`` marks the one badge of an artifact's section."""
    data = f' data-artifact="{esc(artifact_id)}"' if artifact_id else ""
    return f'<span class="verdict verdict-{verdict.replace(" ", "-")}"{data}>{esc(verdict)}</span>'


def md_cell(text) -> str:
    """Text for a MyST pipe-table cell."""
    return str(text).replace("|", "\\|").replace("\n", " ")


def slugify(text: str) -> str:
    """The anchor MyST gives a heading (``myst_heading_anchors``: mdit-py-plugins' GitHub-style slug of its text).

    >>> slugify("`wang2023cja_fig07` — roll and yaw errors (paper Fig 7)")
    'wang2023cja_fig07--roll-and-yaw-errors-paper-fig-7'
    """
    from mdit_py_plugins.anchors.index import slugify as github_slug

    return github_slug(text.replace("`", "").strip())


def notebook_headings(path: Path) -> list[str]:
    """The text of every markdown heading of an executed notebook, in order."""
    nb = json.loads(path.read_text(encoding="utf-8"))
    found = []
    for cell in nb.get("cells", []):
        if cell.get("cell_type") != "markdown":
            continue
        source = "".join(cell.get("source", []))
        found += [m.group(1).strip() for m in re.finditer(r"^#{1,6}\s+(.+?)\s*#*\s*$", source, re.M)]
    return found


def section_anchor(headings: list[str], section: str) -> str:
    """The slug of the notebook heading the catalogue's section names ('' when none matches)."""
    want = " ".join(section.replace("`", "").split())
    texts = [(" ".join(h.replace("`", "").split()), h) for h in headings]
    for text, h in texts:
        if text == want:
            return slugify(h)
    for text, h in texts:
        if text.startswith(want) or want.startswith(text):
            return slugify(h)
    return ""


def fmt_band(row: dict) -> str:
    band = row.get("mc_band", "")
    return band if band else "—"


def in_band_class(row: dict) -> str:
    return {"True": "inside", "False": "outside"}.get(row.get("paper_in_band", ""), "nocompare")


def role_tag(row: dict) -> str:
    role = row.get("role", "")
    return f'<span class="role role-{esc(role)}">{esc(ROLE_WORDS.get(role, role))}</span>' if role else ""


def _cell(value: str, row: dict | None) -> str:
    if row is None:
        return f"<td>{esc(value)}</td>"
    where = {"inside": "inside our band", "outside": "outside our band"}.get(in_band_class(row), "")
    title = esc(f"{row.get('quantity', '')}: paper {value}, ours {row.get('mtcal', '')} {fmt_band(row)} {where}")
    compared = row.get("paper", "")
    same = _number(compared) is not None and _number(compared) == _number(value)
    shown = "" if same or not compared else f'<span class="compared">compared: {esc(compared)}</span>'
    return (f'<td class="cmp {in_band_class(row)}" title="{title}"><span class="paper-value">{esc(value)}</span>'
            f'{shown}<span class="ours">ours {esc(row.get("mtcal", ""))}</span>'
            f'<span class="band">{esc(fmt_band(row))}</span>{role_tag(row)}</td>')


def _number(text) -> float | None:
    try:
        return float(str(text).replace("−", "-"))
    except ValueError:
        return None


def _header(column: str) -> str:
    label = column.replace("_deg", " (°)").replace("_", " ")
    return f"<th>{esc(label)}</th>"


def paper_layout_tables(rows: list[dict]) -> tuple[list[str], list[dict]]:
    """The paper's own tables that ``rows`` point into (``ref`` ``<table>:<row>:<column>``), each printed number
    with ours beside it; returns (HTML tables, rows not placed in a paper table)."""
    placed: dict[str, dict[tuple[int, str], dict]] = OrderedDict()
    rest = []
    for r in rows:
        parts = r.get("ref", "").split(":")
        table = parts[0] if len(parts) == 3 else ""
        if table and (PAPER_DATA / f"{table}.csv").is_file() and parts[1].isdigit() and not table.endswith(
                ("_claims", "_params")):
            placed.setdefault(table, {})[(int(parts[1]), parts[2])] = r
        else:
            rest.append(r)
    out = []
    for table, cells in placed.items():
        with (PAPER_DATA / f"{table}.csv").open(encoding="utf-8", newline="") as fh:
            reader = csv.DictReader(fh)
            columns, body = reader.fieldnames or [], list(reader)
        if not all(col in columns and 1 <= i <= len(body) for i, col in cells):
            rest.extend(cells.values())  # a reference that does not fit the printed table: listed, not placed
            continue
        lines = [f'<div class="table-scroll"><table class="paper-layout" data-paper-table="{esc(table)}">',
                 f"<caption>The paper's table as printed ({esc(table)}). Below each compared number: the value "
                 f"compared when it is not the printed one (e.g. the error against the reference), ours, our 95 % "
                 f"band and the number's role; green: inside our band, red: outside</caption>",
                 "<thead><tr>" + "".join(_header(c) for c in columns) + "</tr></thead><tbody>"]
        for i, rec in enumerate(body, start=1):
            lines.append("<tr>" + "".join(_cell(rec[c], cells.get((i, c))) for c in columns) + "</tr>")
        lines.append("</tbody></table></div>")
        out.append("\n".join(lines))
    return out, rest


def other_numbers_table(rows: list[dict]) -> str:
    """Comparison rows not placed in a paper table: quantity, paper, ours, band, inside, role, claim."""
    if not rows:
        return ""
    lines = ['<div class="table-scroll"><table class="numbers">',
             "<thead><tr><th>quantity</th><th>paper</th><th>ours</th><th>our 95 % band</th><th>paper inside</th>"
             "<th>role</th><th>claim or check</th></tr></thead><tbody>"]
    for r in rows:
        holds = {"True": '<span class="holds yes">holds</span>',
                 "False": '<span class="holds no">fails</span>'}.get(r.get("holds", ""), "")
        inside = {"inside": "inside", "outside": "outside"}.get(in_band_class(r), "—")
        lines.append(f'<tr><td>{esc(r.get("quantity", ""))}</td><td>{esc(r.get("paper", ""))}</td>'
                     f'<td>{esc(r.get("mtcal", ""))}</td><td>{esc(fmt_band(r))}</td>'
                     f'<td class="cmp {in_band_class(r)}">{inside}</td><td>{role_tag(r)}</td>'
                     f'<td>{holds} {esc(r.get("claim", ""))}</td></tr>')
    lines.append("</tbody></table></div>")
    return "\n".join(lines)


def claims_list(rows: list[dict]) -> list[str]:
    """Each distinct claim of ``rows`` once: holds / fails, on how many numbers, its kind (MyST list items)."""
    seen: OrderedDict[str, list[dict]] = OrderedDict()
    for r in rows:
        if r.get("claim"):
            seen.setdefault(r["claim"], []).append(r)
    out = []
    for claim, rs in seen.items():
        holds = [r.get("holds") == "True" for r in rs if r.get("holds") in ("True", "False")]
        if not holds:
            continue
        state = "holds" if all(holds) else "fails"
        count = f" ({sum(holds)} of {len(holds)} numbers)" if len(holds) > 1 else ""
        kind = KIND_WORDS.get(rs[0].get("kind", ""), rs[0].get("kind", ""))
        out.append(f'- <span class="holds {"yes" if state == "holds" else "no"}">{state}</span>{count} '
                   f"*{md_escape(kind)}*: {md_escape(claim)}")
    return out


def md_escape(text: str) -> str:
    """Plain text inside MyST (no markup, no roles, no HTML)."""
    return re.sub(r"([\\`*_\[\]{}<>#|$])", r"\\\1", str(text))


# ------------------------------------------------------------------------------------------- pages

class Site:
    """Everything read once; the pages are methods writing MyST text."""

    def __init__(self, root: Path, verdicts_path: Path):
        self.root = Path(root)
        self.catalogue = read_catalogue(self.root / "docs" / "artifacts.md")
        self.catalogue.pop(SELF, None)  # data/verdicts.csv is the source of every badge, not an artifact with one
        self.verdicts = read_verdicts(Path(verdicts_path), self.catalogue)
        self.comparisons = read_comparisons(self.root / "data")
        self.fidelity = read_fidelity(self.root / "data" / "fidelity_scores.csv")
        self.fidelity_tuned = read_fidelity(self.root / "data" / "fidelity_scores.csv", role="tuned")
        self.fidelity_cv = read_fidelity(self.root / "data" / "fidelity_scores.csv", role="cv-heldout")
        self.errata = errata_sections(self.root / "docs" / "errata.md")
        self.headings = {p.stem: notebook_headings(p) for p in sorted((self.root / "notebooks").glob("[0-9][0-9]_*.ipynb"))}
        self.rows_of: dict[str, list[dict]] = {}
        for r in self.comparisons:
            self.rows_of.setdefault(r.get("artifact", ""), []).append(r)
        self.pages = self._assign_pages()

    # which page shows which artifact ----------------------------------------------------------
    def notebook_title(self, stem: str) -> str:
        heads = self.headings.get(stem, [])
        return heads[0].replace("`", "") if heads else stem

    def _assign_pages(self) -> "OrderedDict[str, dict]":
        """``{page name: {title, key, artifacts}}``: a page per paper (the notebooks that show its figures or
        tables), one per other notebook, and ``other`` for files made outside the notebooks."""
        paper_notebooks: dict[str, str] = {}
        for a in self.catalogue.values():
            m = ITEM_RE.match(a.id)
            if m and a.notebook and m["key"] in KEYS:
                paper_notebooks.setdefault(a.notebook, m["key"])
        pages: OrderedDict[str, dict] = OrderedDict()
        for key in KEYS:
            if key in paper_notebooks.values():
                pages[f"papers/{key}"] = {"title": key, "key": key, "artifacts": []}
        for a in self.catalogue.values():
            key = paper_notebooks.get(a.notebook)
            if key:
                name = f"papers/{key}"
            elif a.notebook:
                name = f"extras/{a.notebook}"
                pages.setdefault(name, {"title": f"Artifacts of {self.notebook_title(a.notebook)}", "key": "",
                                       "artifacts": []})
            else:
                name = "extras/other"
                pages.setdefault(name, {"title": "Files made outside the notebooks", "key": "", "artifacts": []})
            pages[name]["artifacts"].append(a.id)
        for name, page in pages.items():
            if page["key"]:
                items = paper_order([a for a in page["artifacts"] if ITEM_RE.match(a)])
                page["items"] = items
                page["additions"] = [a for a in page["artifacts"] if a not in items]
            else:
                page["items"], page["additions"] = [], page["artifacts"]
        # "other" last
        if "extras/other" in pages:
            pages.move_to_end("extras/other")
        return pages

    # numbers in words ---------------------------------------------------------------------------
    def counts(self, ids) -> Counter:
        return Counter(self.verdicts[a]["verdict"] for a in ids if a in self.verdicts)

    def fidelity_words(self, scope: str) -> str:
        """Held-out coverage and sharpness of ``scope`` (a paper key or ``overall``) in one paragraph."""
        fit, prior = self.fidelity.get((scope, "fitted")), self.fidelity.get((scope, "prior"))
        if not fit or int(fit["n"] or 0) == 0:
            return ("No held-out printed number with a 95 % band: every number of this paper was used to "
                    "set the simulation up (training) or is compared without a band.")
        n, inside = int(fit["n"]), int(fit["inside"])
        text = (f"**{inside} of {n}** held-out printed numbers lie inside our 95 % bands "
                f"(coverage {float(fit['coverage']):.0%}, 95 % interval {float(fit['coverage_low']):.0%}–"
                f"{float(fit['coverage_high']):.0%}); calibrated bands would hold about {round(0.95 * n)}. ")
        if fit.get("median_rel_width"):
            text += (f"Sharpness: the median band is {float(fit['median_rel_width']):.1f}× as wide as the printed "
                     f"value; {fit['within_25pct']} of {n} printed values lie within 25 % of our median. ")
        if prior and prior.get("median_rel_width"):
            text += (f"Before fitting (prior predictive) the bands hold {prior['inside']} of {prior['n']} but are "
                     f"{float(prior['median_rel_width']):.1f}× as wide. ")
        tuned = self.fidelity_tuned.get((scope, "fitted"))
        if tuned and int(tuned["n"] or 0):
            text += (f"In-sample (numbers a mechanism or setting was chosen against, not predictions): "
                     f"{tuned['inside']} of {tuned['n']} inside. ")
        cv = {b: self.fidelity_cv.get((scope, b)) for b in ("fitted", "no-physics", "prior")}
        if cv["fitted"] and int(cv["fitted"]["n"] or 0):
            f = cv["fitted"]
            others = "; ".join(f"{b} {r['inside']} of {r['n']}, {float(r['mean_rel_interval_score']):.1f}"
                               for b, r in cv.items() if b != "fitted" and r)
            text += (f"Leave-one-table-out cross-validation (each table predicted by a fit to the others, blind by "
                     f"construction): {f['inside']} of {f['n']} inside, mean interval score/|paper| "
                     f"{float(f['mean_rel_interval_score']):.1f} (lower is better; baselines on the same numbers: "
                     f"{others}).")
        return text.strip()

    def claims_words(self, ids) -> tuple[int, int]:
        rows = [self.verdicts[a] for a in ids if a in self.verdicts]
        return sum(int(r["claims_holding"]) for r in rows), sum(int(r["claims_failing"]) for r in rows)

    # page writers -------------------------------------------------------------------------------
    def paper_groups(self) -> "OrderedDict[str, list[str]]":
        """``{paper: [artifact ids]}`` by the verdicts' ``paper`` column (the papers of :data:`KEYS` first)."""
        groups: OrderedDict[str, list[str]] = OrderedDict((k, []) for k in KEYS)
        for aid, row in self.verdicts.items():
            if row["paper"]:
                groups.setdefault(row["paper"], []).append(aid)
        return OrderedDict((k, ids) for k, ids in groups.items() if ids)

    def page_of(self, key: str, ids: list[str]) -> str:
        """The paper's page, else the page showing most of its artifacts (a real-data study's notebook page)."""
        if f"papers/{key}" in self.pages:
            return f"papers/{key}"
        where = Counter(n for n, p in self.pages.items() for a in p["artifacts"] if a in set(ids))
        return where.most_common(1)[0][0]

    def scoreboard(self) -> str:
        """The front page's table: per paper, artifacts by verdict, held-out numbers inside, claims, errata."""
        head = ("<tr><th>paper (artifacts)</th>" + "".join(f"<th>{badge(v)}</th>" for v in VERDICTS)
                + "<th>held-out inside</th><th>claims hold</th><th>claims fail</th><th>errata</th></tr>")
        body = []
        for key, ids in self.paper_groups().items():
            name = self.page_of(key, ids)
            c, (hold, fail) = self.counts(ids), self.claims_words(ids)
            fit = self.fidelity.get((key, "fitted"))
            held = f"{fit['inside']} of {fit['n']}" if fit and int(fit["n"] or 0) else "none held out"
            n_err = self.errata.get(key, ("", 0))[1]
            err = (f'<a href="errata.html#{slugify(key + " — " + self.errata[key][0])}">{n_err}</a>'
                   if n_err else "0")
            body.append(f'<tr><td><a href="{name}.html">{esc(key)}</a> ({len(ids)})</td>'
                        + "".join(f"<td>{c[v]}</td>" for v in VERDICTS)
                        + f"<td>{held}</td><td>{hold}</td><td>{fail}</td><td>{err}</td></tr>")
        return ('<div class="table-scroll"><table class="scoreboard"><thead>' + head + "</thead><tbody>"
                + "".join(body) + "</tbody></table></div>")

    def index_page(self) -> str:
        lines = ["# mtcal: what the papers' artifacts reproduce", "",
                 "Every table and figure of the papers, regenerated from simulated data (and, for `broad2021`, "
                 "real recordings), with the paper's printed numbers beside ours and our 95 % Monte Carlo bands. "
                 "Each artifact carries a verdict from `data/verdicts.csv`: "
                 + ", ".join(badge(v) for v in VERDICTS) + ". The paper pages follow each paper's own order; "
                 "a verdict's cause is computed in the notebook section linked beside it.", "",
                 "```{raw} html", self.scoreboard(), "```", ""]
        lines += [""]
        for key, ids in self.paper_groups().items():
            name = self.page_of(key, ids)
            c, (hold, fail) = self.counts(ids), self.claims_words(ids)
            citation = self.errata.get(key, ("", 0))[0]
            items = paper_order([a for a in ids if ITEM_RE.match(a)])
            ci = self.counts(items)
            lines += [f"## [{key}]({name}.md)", ""] + ([f"*{md_escape(citation)}*", ""] if citation else []) + [
                      f"Of the paper's {len(items)} figures and tables: "
                      + ", ".join(f"{ci[v]} {v}" for v in VERDICTS) + f"; with our {len(ids) - len(items)} "
                      f"additions, {len(ids)} artifacts. Claims: {hold} holding, {fail} failing.", "",
                      self.fidelity_words(key), ""]
        lines += ["## Everything else", "",
                  "| page | artifacts | " + " | ".join(badge(v) for v in VERDICTS) + " |",
                  "|---|---|" + "---|" * len(VERDICTS)]
        for name, page in self.pages.items():
            if not page["key"]:
                c = self.counts(page["artifacts"])
                lines.append(f"| [{md_cell(page['title'])}]({name}.md) | {len(page['artifacts'])} | "
                             + " | ".join(str(c[v]) for v in VERDICTS) + " |")
        if self.fidelity:
            lines += ["", "**All papers together.** " + self.fidelity_words("overall")]
        lines += ["", "```{toctree}", ":caption: Papers", ":maxdepth: 1", ""]
        lines += [f"{n}" for n, p in self.pages.items() if p["key"]]
        lines += ["```", "", "```{toctree}", ":caption: Beyond the papers", ":maxdepth: 1", ""]
        lines += [f"{n}" for n, p in self.pages.items() if not p["key"]]
        lines += ["```", "", "```{toctree}", ":caption: Notebooks", ":maxdepth: 1", ""]
        lines += [f"notebooks/{s}" for s in self.headings]
        lines += ["```", "", "```{toctree}", ":caption: Reference", ":maxdepth: 1", "", "errata", "artifacts",
                  "conventions", "deviations", "study_template", "api", "```", ""]
        return "\n".join(lines)

    def artifact_section(self, aid: str, level: str = "##") -> list[str]:
        a = self.catalogue[aid]
        v = self.verdicts.get(aid, {"verdict": "", "cause": "", "numbers_compared": "0", "numbers_inside": "0",
                                    "claims_holding": "0", "claims_failing": "0"})
        title = re.sub(rf"^{re.escape(aid)}\s*(\(beyond the paper\))?\s*[—-]?\s*", "", a.section.replace("`", ""))
        m = ITEM_RE.match(aid)
        item = (f"{'Fig.' if m['kind'] == 'fig' else 'Table'} {int(m['num'])}" if m else aid)
        heading = f"{item} — {title}" if title and title != aid else item
        lines = [f"(art-{aid})=", f"{level} {md_escape(heading)}", "",
                 f"{badge(v['verdict'], aid)} {md_escape(v['cause'])}" if v["verdict"] else
                 "Bookkeeping file (the rows behind the verdicts; it carries no verdict of its own).", ""]
        facts = [f"`{aid}`"]
        if int(v["numbers_compared"]):
            facts.append(f"{v['numbers_inside']} of {v['numbers_compared']} printed numbers inside our band")
        if int(v["claims_holding"]) or int(v["claims_failing"]):
            facts.append(f"claims: {v['claims_holding']} holding, {v['claims_failing']} failing")
        lines += [" · ".join(facts), ""]
        for f in a.files:
            if f.endswith(".png"):
                lines += ["```{image} ../" + f, f":alt: {aid}: our figure", ":width: 100%", "```", ""]
        rows = self.rows_of.get(aid, [])
        tables, rest = paper_layout_tables(rows)
        for t in tables:
            lines += ["```{raw} html", t, "```", ""]
        if rest:
            lines += ["```{raw} html", other_numbers_table(rest), "```", ""]
        claims = claims_list(rows)
        if claims:
            lines += ["Claims and checks it carries:", ""] + claims + [""]
        links = []
        if a.notebook in self.headings:
            anchor = section_anchor(self.headings[a.notebook], a.section)
            links.append(f"[notebook § {md_escape(a.section.replace('`', '')[:80])}]"
                         f"(../notebooks/{a.notebook}.ipynb{'#' + anchor if anchor else ''})")
        elif a.where:
            links.append(f"made by {md_escape(a.where)}")
        if re.fullmatch(r"mtcal(\.\w+)+", a.producer):
            links.append(f"produced by {{ref}}`{a.producer} <src-{a.producer}>`")
        elif a.producer and a.producer != "—":
            links.append(f"produced by {md_escape(a.producer.replace('`', ''))}")
        for f in a.files:
            if f.endswith(".csv"):
                links.append(f"{{download}}`{f} <../{f}>`")
        lines += [" · ".join(links), ""]
        if a.notebook:
            lines += [f"Rebuild: `make artifact ID={aid}`", ""]
        return lines

    def paper_page(self, name: str) -> str:
        page = self.pages[name]
        key = page["key"]
        citation = self.errata.get(key, ("", 0))[0]
        c = self.counts(page["artifacts"])
        lines = [f"# {key}", ""] + ([f"*{md_escape(citation)}*", ""] if citation else []) + [
                 " · ".join(f"{badge(v)} {c[v]}" for v in VERDICTS), "", self.fidelity_words(key), ""]
        if self.errata.get(key, ("", 0))[1]:
            lines += [f"Errata of this paper: [{self.errata[key][1]} listed](../errata.md#"
                      f"{slugify(key + ' — ' + citation)}).", ""]
        lines += ["The paper's figures and tables in the paper's order, then our additions. Each printed number "
                  "stands beside ours with our 95 % band; the role says whether it was used to set the "
                  "simulation up (training), predicted blind (held out), or is our own finding.", ""]
        for aid in page["items"]:
            lines += self.artifact_section(aid)
        if page["additions"]:
            lines += ["## Beyond the paper", "",
                      "Our additions in the same notebooks: error models, sensitivity, the comparison tables and "
                      "the held-out score records.", ""]
            for aid in page["additions"]:
                lines += self.artifact_section(aid, "###")
        return "\n".join(lines)

    def extra_page(self, name: str) -> str:
        page = self.pages[name]
        c = self.counts(page["artifacts"])
        stem = name.split("/", 1)[1]
        lines = [f"# {md_escape(page['title'])}", "", " · ".join(f"{badge(v)} {c[v]}" for v in VERDICTS), ""]
        if stem in self.headings:
            lines += [f"The rendered notebook: [{stem}](../notebooks/{stem}.ipynb).", ""]
        for aid in page["artifacts"]:
            lines += self.artifact_section(aid)
        return "\n".join(lines)

    def producers(self) -> "OrderedDict[str, tuple[str, str]]":
        """``{dotted name: (defining source file, function name)}`` of every mtcal producing function."""
        import importlib
        import inspect

        out: OrderedDict[str, tuple[str, str]] = OrderedDict()
        for a in self.catalogue.values():
            if not re.fullmatch(r"mtcal(\.\w+)+", a.producer) or a.producer in out:
                continue
            module, _, name = a.producer.rpartition(".")
            try:
                obj = inspect.unwrap(getattr(importlib.import_module(module), name))
                out[a.producer] = (inspect.getsourcefile(obj), obj.__name__)
            except (ImportError, AttributeError, TypeError) as exc:
                raise SiteError(f"docs/artifacts.md names {a.producer} for {a.id}, which is not an importable "
                                f"function ({type(exc).__name__}: {exc}); run python tools/artifact_catalogue.py")
        return out

    def api_page(self, src: Path) -> str:
        import os

        lines = ["# Producing functions", "",
                 "The source of every library function that produces a catalogue artifact (its docstring "
                 "cites the paper's equations), grouped by the file that defines it.", ""]
        by_file: OrderedDict[str, list[tuple[str, str]]] = OrderedDict()
        for dotted, (path, name) in self.producers().items():
            by_file.setdefault(path, []).append((dotted, name))
        for path, funcs in sorted(by_file.items()):
            rel = Path(path).resolve().relative_to(self.root) if Path(path).resolve().is_relative_to(self.root) else path
            lines += [f"## `{rel}`", ""]
            for dotted, name in funcs:
                lines += [f"(src-{dotted})=", f"### `{dotted}`", "",
                          f"```{{literalinclude}} {os.path.relpath(path, src)}", f":pyobject: {name}",
                          ":language: python", "```", ""]
        return "\n".join(lines)

    def stage(self, src: Path) -> list[str]:
        """Write the site sources into ``src`` (unchanged files keep their time: incremental builds)."""
        src.mkdir(parents=True, exist_ok=True)
        wanted: set[Path] = set()

        def put(rel: str, text: str | None = None, copy_from: Path | None = None):
            path = src / rel
            wanted.add(path)
            path.parent.mkdir(parents=True, exist_ok=True)
            if copy_from is not None:
                if not path.is_file() or not filecmp.cmp(copy_from, path, shallow=False):
                    shutil.copy2(copy_from, path)
            elif not path.is_file() or path.read_text(encoding="utf-8") != text:
                path.write_text(text, encoding="utf-8")

        docs = self.root / "docs"
        for p in sorted(docs.rglob("*")):
            if p.is_file() and "__pycache__" not in p.parts:
                put(str(p.relative_to(docs)), copy_from=p)
        for stem in self.headings:
            put(f"notebooks/{stem}.ipynb", copy_from=self.root / "notebooks" / f"{stem}.ipynb")
        for a in self.catalogue.values():
            for f in a.files:
                if (self.root / f).is_file():
                    put(f, copy_from=self.root / f)
                else:
                    raise SiteError(f"{f}: catalogued in docs/artifacts.md but not in the repository "
                                    f"(run make reproduce)")
        put("index.md", self.index_page())
        put("api.md", self.api_page(src))
        for name, page in self.pages.items():
            put(f"{name}.md", self.paper_page(name) if page["key"] else self.extra_page(name))
        for p in sorted(src.rglob("*"), reverse=True):  # pages and files no longer made
            if p.is_file() and p not in wanted:
                p.unlink()
        return sorted(str(p.relative_to(src)) for p in wanted)


def build_site(root: Path = ROOT, out: Path | None = None, verdicts: Path | None = None,
               src: Path | None = None, quiet: bool = True) -> dict:
    """Stage the sources and run Sphinx; returns ``{"out", "pages", "artifacts", "seconds"}``.

    Raises
    ------
    SiteError
        Bad inputs (see :func:`read_verdicts`), or Sphinx reported a warning or an error (its log is named).
    """
    from sphinx.cmd.build import build_main

    root = Path(root)
    out = Path(out) if out is not None else root / "build" / "report"
    src = Path(src) if src is not None else root / "build" / "site-src"
    verdicts = Path(verdicts) if verdicts is not None else root / "data" / "verdicts.csv"
    start = time.perf_counter()
    site = Site(root, verdicts)
    site.stage(src)
    if out.exists():  # pages no longer made must go; parsing stays incremental (the doctrees are kept)
        shutil.rmtree(out)
    log = src.parent / f"{src.name}-sphinx.log"
    args = ["-b", "html", "-W", "--keep-going", "-w", str(log), "-d", str(src.parent / f"{src.name}-doctrees"),
            str(src), str(out)] + (["-q"] if quiet else [])
    with warnings.catch_warnings():  # the theme's and MyST's use of APIs Sphinx will remove: not ours to fix
        warnings.simplefilter("ignore", DeprecationWarning)
        warnings.simplefilter("ignore", PendingDeprecationWarning)
        status = build_main(args)
    if status != 0:
        raise SiteError(f"sphinx-build reported warnings or errors: {log}\n{log.read_text(encoding='utf-8')[-3000:]}")
    pages = [n for n in site.pages]
    return {"out": out, "pages": pages, "artifacts": list(site.catalogue), "seconds": time.perf_counter() - start,
            "site": site}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--verdicts", default=str(ROOT / "data" / "verdicts.csv"),
                        help="verdicts table (default data/verdicts.csv)")
    parser.add_argument("--out", default=str(ROOT / "build" / "report"), help="HTML output (default build/report)")
    parser.add_argument("--src", default=str(ROOT / "build" / "site-src"),
                        help="staged Sphinx sources (default build/site-src)")
    args = parser.parse_args(argv)
    try:
        result = build_site(ROOT, Path(args.out), Path(args.verdicts), Path(args.src))
    except SiteError as exc:
        print(f"site: error: {exc}", file=sys.stderr)
        return 2
    c = result["site"].counts(result["artifacts"])
    print(f"site: {len(result['artifacts'])} artifacts (" + ", ".join(f"{c[v]} {v}" for v in VERDICTS)
          + f") on {len(result['pages'])} pages in {result['seconds']:.1f} s → {Path(result['out']) / 'index.html'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
