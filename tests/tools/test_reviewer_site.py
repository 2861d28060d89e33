"""The reviewer's site (tools/reviewer_site.py, Sphinx + MyST-NB): its inputs checked, every page opened in
headless Debian chromium (selenium): no console error, no broken link, anchor or image, nothing from the web,
no horizontal page overflow at 1280×800, every catalogue artifact once with its verdict badge, search works."""

import csv
import re
from collections import Counter
import doctest
import importlib.util
import shutil
import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest

ROOT = Path(__file__).resolve().parents[2]
SPEC = importlib.util.spec_from_file_location("reviewer_site", ROOT / "tools" / "reviewer_site.py")
site = importlib.util.module_from_spec(SPEC)
sys.modules["reviewer_site"] = site
SPEC.loader.exec_module(site)
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
CHROMEDRIVER = shutil.which("chromedriver")
CATALOGUE = site.read_catalogue(ROOT / "docs" / "artifacts.md")
CATALOGUE.pop(site.SELF, None)  # data/verdicts.csv itself: the source of the badges
#: the catalogue entries that carry a verdict (paper figures/tables and our additions; not bookkeeping files)
WITH_VERDICT = [a for a, art in CATALOGUE.items() if site.needs_verdict(art)]
COMMITTED_VERDICTS = ROOT / "data" / "verdicts.csv"


def write_verdicts(path: Path, ids, verdicts=site.VERDICTS, drop=(), extra=(), columns=site.VERDICT_COLUMNS):
    """A verdicts table for ``ids``: verdicts in turn (test data for the site's machinery, not results)."""
    with path.open("w", encoding="utf-8", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(columns), extrasaction="ignore")
        w.writeheader()
        for i, aid in enumerate([a for a in ids if a not in drop] + list(extra)):
            w.writerow({"artifact_id": aid, "paper": site.paper_key(aid), "paper_item": "",
                        "verdict": verdicts[i % len(verdicts)], "numbers_compared": "3", "numbers_inside": "2",
                        "claims_holding": "1", "claims_failing": "0", "cause": f"test row {i}",
                        "notebook_section": ""})
    return path


def test_doctests():
    assert doctest.testmod(site, optionflags=doctest.ELLIPSIS).failed == 0


def test_verdicts_are_checked_against_the_catalogue(tmp_path):
    ids = list(WITH_VERDICT)
    assert len(site.read_verdicts(write_verdicts(tmp_path / "ok.csv", ids), CATALOGUE)) == len(ids)
    assert "wang2023cja_turntable_comparison" in CATALOGUE and "wang2023cja_turntable_comparison" not in ids
    with pytest.raises(site.SiteError, match=r"no such file.*--verdicts PATH"):
        site.read_verdicts(tmp_path / "absent.csv", CATALOGUE)
    with pytest.raises(site.SiteError, match=r"missing column\(s\) cause"):
        site.read_verdicts(write_verdicts(tmp_path / "c.csv", ids, columns=[c for c in site.VERDICT_COLUMNS
                                                                            if c != "cause"]), CATALOGUE)
    with pytest.raises(site.SiteError, match=r"verdict 'mostly' of .* is not one of reproduced"):
        site.read_verdicts(write_verdicts(tmp_path / "v.csv", ids, verdicts=("mostly",)), CATALOGUE)
    with pytest.raises(site.SiteError, match=rf"no verdict for {ids[3]}$"):
        site.read_verdicts(write_verdicts(tmp_path / "d.csv", ids, drop=(ids[3],)), CATALOGUE)
    with pytest.raises(site.SiteError, match=r"not in the catalogue: wang2023cja_fig99"):
        site.read_verdicts(write_verdicts(tmp_path / "e.csv", ids, extra=("wang2023cja_fig99",)), CATALOGUE)
    with_self = dict(CATALOGUE, verdicts=None)  # the verdicts table catalogued: no row needed, one allowed
    assert len(site.read_verdicts(write_verdicts(tmp_path / "s.csv", ids), with_self)) == len(ids)
    assert len(site.read_verdicts(write_verdicts(tmp_path / "t.csv", ids, extra=("verdicts",)), CATALOGUE)) == len(ids)
    with pytest.raises(site.SiteError, match=rf"{ids[0]} has a second row"):
        site.read_verdicts(write_verdicts(tmp_path / "f.csv", ids, extra=(ids[0],)), CATALOGUE)


def test_missing_verdicts_stop_the_build_with_one_line(tmp_path, capsys):
    assert site.main(["--verdicts", str(tmp_path / "verdicts.csv"), "--out", str(tmp_path / "out"),
                      "--src", str(tmp_path / "src")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("site: error: ") and "verdicts.csv: no such file" in err and err.count("\n") == 1
    assert not (tmp_path / "out").exists()


def test_paper_order_and_pages():
    s = site.Site.__new__(site.Site)
    s.catalogue, s.headings = CATALOGUE, {}
    s.verdicts = {a: {"paper": site.paper_key(a)} for a in CATALOGUE}
    pages = s._assign_pages()
    shown = [a for p in pages.values() for a in p["items"] + p["additions"]]
    assert sorted(shown) == sorted(CATALOGUE) and len(shown) == len(set(shown))
    items = pages["papers/wang2023cja"]["items"]
    assert items[:6] == ["wang2023cja_table01", "wang2023cja_table02", "wang2023cja_table03",
                         "wang2023cja_table04", "wang2023cja_table05", "wang2023cja_fig07"]
    assert items[-1] == "wang2023cja_table11"
    assert pages["papers/tan2022"]["items"] == [f"tan2022_fig{n:02d}" for n in (2, 5, 6, 8, 9, 10, 11, 12)]
    assert "extras/40_wang2023cja_constrained_calibration" in pages and "extras/50_filter_bakeoff" in pages


def test_paper_layout_places_ours_beside_each_printed_number():
    rows = [{"artifact": "x", "quantity": "q", "paper": "0.0060", "mtcal": "0.0068", "mc_band": "[-0.02862, 0.04643]",
             "paper_in_band": "True", "role": "train", "ref": "wang2023cja_table01_positions:1:yaw_before_deg"},
            {"artifact": "x", "quantity": "q2", "paper": "8.002", "mtcal": "9", "mc_band": "[8.5, 9.5]",
             "paper_in_band": "False", "role": "heldout", "ref": "wang2023cja_table01_positions:2:yaw_before_deg"},
            {"artifact": "x", "quantity": "other", "paper": "1", "mtcal": "2", "ref": ""}]
    tables, rest = site.paper_layout_tables(rows)
    assert len(tables) == 1 and [r["quantity"] for r in rest] == ["other"]
    t = tables[0]
    assert t.count('class="cmp inside"') == 1 and t.count('class="cmp outside"') == 1
    assert "<span class=\"paper-value\">8.006</span><span class=\"compared\">compared: 0.0060</span>" in t
    assert "<span class=\"paper-value\">-8.002</span>" in t and "ours 9" in t and "held out" in t
    assert t.count("<tr>") == 1 + 6  # header + the six printed positions


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """The site from the committed results; data/verdicts.csv when committed, else a verdicts test table."""
    tmp = tmp_path_factory.mktemp("site")
    verdicts = COMMITTED_VERDICTS if COMMITTED_VERDICTS.is_file() else write_verdicts(tmp / "verdicts.csv", WITH_VERDICT)
    return site.build_site(ROOT, tmp / "out", verdicts, tmp / "src")


def _driver():
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                 "--disable-background-networking", "--disable-extensions", "--no-first-run",
                 "--window-size=1280,800", "--allow-file-access-from-files"):
        options.add_argument(flag)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(options=options, service=Service(CHROMEDRIVER))


class _Page(HTMLParser):
    def __init__(self):
        super().__init__()
        self.ids, self.links, self.resources = set(), [], []

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if attrs.get("id"):
            self.ids.add(attrs["id"])
        if tag == "a" and attrs.get("href"):
            self.links.append(attrs["href"])
        for key in ("src", "href"):
            if tag in ("script", "img", "link", "iframe", "source") and attrs.get(key):
                self.resources.append(attrs[key])


def _parse(path: Path) -> _Page:
    p = _Page()
    p.feed(path.read_text(encoding="utf-8"))
    return p


def test_site_in_headless_chromium(built):
    assert CHROMIUM and CHROMEDRIVER, ("Debian chromium and chromium-driver are needed "
                                       "(.ci/run installs them: apt-get install -y chromium chromium-driver)")
    from selenium.webdriver.support.ui import WebDriverWait

    out = Path(built["out"])
    pages = sorted(p for p in out.rglob("*.html") if "_static" not in p.parts and "_sources" not in p.parts)
    assert {"index.html", "search.html", "api.html", "errata.html", "papers/wang2023cja.html",
            "notebooks/10_wang2023cja_turntable.html"} <= {str(p.relative_to(out)) for p in pages}
    parsed, badges, problems = {}, {}, []
    driver = _driver()
    try:
        for path in pages:
            rel = path.relative_to(out)
            driver.get(path.as_uri())
            WebDriverWait(driver, 60).until(lambda d: d.execute_script("return document.readyState") == "complete",
                                            message=f"{rel} did not finish loading")
            errors = [e["message"] for e in driver.get_log("browser") if e["level"] == "SEVERE"]
            problems += [f"{rel}: console: {m}" for m in errors]
            width = driver.execute_script("return [document.documentElement.scrollWidth, window.innerWidth]")
            if width[0] > width[1]:
                problems.append(f"{rel}: page overflows horizontally ({width[0]} > {width[1]} px)")
            problems += [f"{rel}: broken image {s}" for s in driver.execute_script(
                "return Array.from(document.images).filter(i => !(i.complete && i.naturalWidth > 0))"
                ".map(i => i.getAttribute('src'))")]
            for aid, verdict in driver.execute_script(
                    "return Array.from(document.querySelectorAll('span.verdict[data-artifact]'))"
                    ".map(b => [b.dataset.artifact, b.textContent])"):
                badges.setdefault(aid, []).append((str(rel), verdict))
            page = parsed.setdefault(path, _parse(path))
            problems += [f"{rel}: loads {r} from the web" for r in page.resources
                         if urlsplit(r).scheme in ("http", "https") or r.startswith("//")]
            for href in page.links:
                parts = urlsplit(href)
                if parts.scheme in ("http", "https", "mailto"):
                    continue
                target = (path.parent / unquote(parts.path)).resolve() if parts.path else path
                if not target.is_file():
                    problems.append(f"{rel}: broken link {href}")
                elif parts.fragment and target.suffix == ".html":
                    ids = parsed.setdefault(target, _parse(target)).ids
                    if unquote(parts.fragment) not in ids:
                        problems.append(f"{rel}: broken anchor {href}")
        assert problems == [], "\n".join(problems[:40])
        assert sorted(badges) == sorted(WITH_VERDICT), set(badges) ^ set(WITH_VERDICT)
        twice = {a: b for a, b in badges.items() if len(b) != 1}
        assert not twice, twice
        assert {v for b in badges.values() for _, v in b} <= set(site.VERDICTS)

        # an artifact links to its own section of the rendered notebook
        driver.get((out / "papers" / "wang2023cja.html").as_uri())
        link = driver.execute_script("return Array.from(document.querySelectorAll('a'))"
                                     ".find(a => a.href.includes('10_wang2023cja_turntable.html#wang2023cja-fig07')).href")
        driver.get(link)
        assert driver.execute_script("return document.querySelector(':target') !== null"), link

        # the search page finds the paper's Table 5
        driver.get((out / "search.html").as_uri() + "?q=Table+5")
        WebDriverWait(driver, 60).until(
            lambda d: d.execute_script("return document.querySelectorAll('#search-results li').length") > 0,
            message="the search for 'Table 5' found nothing")
        found = driver.execute_script("return document.querySelector('#search-results').innerText")
        assert "Table 5" in found

        driver.quit()  # the screenshots as a first visit sees the pages (the theme keeps the sidebar's scroll)
        driver = _driver()
        shots = ROOT / "build"
        shots.mkdir(exist_ok=True)
        for name, page in (("site_index.png", out / "index.html"), ("site_wang2023cja.png", out / "papers" / "wang2023cja.html")):
            driver.get(page.as_uri())
            assert driver.save_screenshot(str(shots / name)) and (shots / name).stat().st_size > 10_000
    finally:
        driver.quit()


def test_front_page_counts_come_from_the_verdicts(built):
    s = built["site"]
    board = (Path(built["out"]) / "index.html").read_text(encoding="utf-8")
    for key, ids in s.paper_groups().items():
        assert ids == [a for a, r in s.verdicts.items() if r["paper"] == key]
        counts = Counter(s.verdicts[a]["verdict"] for a in ids)
        row = board[board.index(f'{key}</a> ({len(ids)})'):]
        row = row[:row.index("</tr>")]
        assert [int(c) for c in re.findall(r"<td>(\d+)</td>", row)[:4]] == [counts[v] for v in site.VERDICTS]
    assert "calibrated bands would hold about" in board or not s.fidelity


def test_front_page_states_the_cross_validation_against_both_baselines(built):
    """The leave-one-table-out rows of fidelity_scores.csv are put in words, each baseline beside the model."""
    s = built["site"]
    board = (Path(built["out"]) / "index.html").read_text(encoding="utf-8")
    for scope in {k[0] for k in s.fidelity_cv} & {k[0] for k in s.fidelity}:   # a paper's page, not a fold
        fit = s.fidelity_cv.get((scope, "fitted"))
        if not fit:
            continue
        words = s.fidelity_words(scope)
        assert f"{fit['inside']} of {fit['n']} inside" in words
        for baseline in ("no-physics", "prior"):
            other = s.fidelity_cv.get((scope, baseline))
            if other:
                assert f"{baseline} {other['inside']} of {other['n']}" in words
    if ("wang2023cja", "fitted") in s.fidelity_cv:
        assert "Leave-one-table-out cross-validation" in board
