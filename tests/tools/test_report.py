"""The reproduction report (tools/report/build.py): complete, no broken link or image, opens in chromium."""

import importlib.util
import re
import shutil
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[2]
SPEC = importlib.util.spec_from_file_location("report_build", ROOT / "tools" / "report" / "build.py")
build = importlib.util.module_from_spec(SPEC)
SPEC.loader.exec_module(build)
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
CHROMEDRIVER = shutil.which("chromedriver")


class _Links(HTMLParser):
    def __init__(self):
        super().__init__()
        self.ids, self.hrefs, self.imgs = set(), [], []

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if attrs.get("id"):
            self.ids.add(attrs["id"])
        if tag == "a" and attrs.get("href"):
            self.hrefs.append(attrs["href"])
        if tag == "img":
            self.imgs.append(attrs.get("src", ""))


def _parse(path: Path) -> _Links:
    p = _Links()
    p.feed(path.read_text(encoding="utf-8"))
    return p


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("report")
    return build.build_report(ROOT, out)


def test_every_catalogue_artifact_number_and_claim_is_shown(report):
    out = report["out"]
    catalogue = build.read_catalogue(ROOT / "docs" / "artifacts.md")
    assert catalogue and set(report["artifacts"]) == {r["id"] for r in catalogue}
    pages = {p: _parse(out / p) for p in report["pages"]}
    shown = {i.removeprefix("art-") for p in pages.values() for i in p.ids if i.startswith("art-")}
    assert shown == {r["id"] for r in catalogue}
    for key in ("wang2023cja", "tan2022", "wang2022sensors", "extras"):
        assert f"{key}.html" in report["pages"]
    n_rows = sum(len(pd.read_csv(p, dtype=str)) for p in (ROOT / "data").glob("*_comparison.csv"))
    text = "".join((out / p).read_text(encoding="utf-8") for p in ("wang2023cja.html", "tan2022.html",
                                                                  "wang2022sensors.html", "extras.html"))
    assert len(re.findall(r'<tr class="(?:pass|fail|na)"><td>', text)) >= n_rows  # numbers (+ claims)
    assert 'class="role role-' in text and "Errata" in text and "Fig. 7" in text
    figures = {f.name for f in (ROOT / "figures").glob("*.png")}
    assert figures <= {f.name for f in (out / "figures").glob("*.png")}
    if (ROOT / "data" / "fidelity_scores.csv").is_file():
        assert 'id="fidelity"' in (out / "index.html").read_text(encoding="utf-8")


def test_no_broken_link_image_or_anchor(report):
    out = report["out"]
    parsed = {}
    for page in report["pages"]:
        path = out / page
        links = parsed.setdefault(path, _parse(path))
        for src in links.imgs:
            if src.startswith("data:"):
                continue
            assert (path.parent / unquote(src)).is_file(), f"{page}: image {src}"
        for href in links.hrefs:
            parts = urlsplit(href)
            if parts.scheme in ("http", "https", "mailto"):
                continue
            target = (path.parent / unquote(parts.path)).resolve() if parts.path else path
            assert target.is_file(), f"{page}: link {href}"
            if parts.fragment and target.suffix == ".html":
                ids = parsed.setdefault(target, _parse(target)).ids
                assert parts.fragment in ids or unquote(parts.fragment) in ids, f"{page}: anchor {href}"


def test_artifacts_link_their_notebook_section_and_producer(report):
    text = (report["out"] / "wang2023cja.html").read_text(encoding="utf-8")
    section = text[text.index('id="art-wang2023cja_fig07"'):]
    section = section[:section.index("</section>")]
    assert 'href="notebooks/10_wang2023cja_turntable.html#wang2023cja_fig07' in section
    assert 'href="functions.html#mtcal.studies.wang2023cja.plots.fig07"' in section
    assert '<img src="figures/wang2023cja_fig07.png"' in section


def test_paper_of_and_verdicts():
    assert build.paper_of("wang2022sensors_fig06") == "wang2022sensors" and build.paper_of("x") == "extras"
    assert build._verdict({"holds": "False"}) == ("fail", "check fails")
    assert build._verdict({"holds": "False", "kind": "claim"}) == ("fail", "claim fails")
    assert build._verdict({"holds": "True", "kind": "consistency"}) == ("pass", "consistency holds")
    assert build._verdict({"holds": "", "paper_in_band": "True"}) == ("pass", "in band")
    assert build._verdict({}) == ("na", "—")


@pytest.mark.skipif(CHROMIUM is None or CHROMEDRIVER is None,
                    reason="Debian chromium/chromium-driver not installed (.ci/run installs them: "
                           "apt-get install -y chromium chromium-driver)")
def test_report_in_headless_chromium(report):
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    from selenium.webdriver.support.ui import WebDriverWait

    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                 "--disable-background-networking", "--disable-extensions", "--no-first-run",
                 "--window-size=1400,1000", "--allow-file-access-from-files"):
        options.add_argument(flag)
    driver = webdriver.Chrome(options=options, service=Service(CHROMEDRIVER))
    try:
        seen = set()
        for page in report["pages"]:
            driver.get((report["out"] / page).as_uri())
            WebDriverWait(driver, 60).until(lambda d: d.execute_script("return document.readyState") == "complete",
                                            message=f"{page} did not finish loading")
            assert "mtcal reproduction report" in driver.title, page
            broken = driver.execute_script(
                "return Array.from(document.images).filter(i => !(i.complete && i.naturalWidth > 0))"
                ".map(i => i.getAttribute('src'))")
            assert broken == [], f"{page}: broken images {broken}"
            seen.update(driver.execute_script(
                "return Array.from(document.querySelectorAll('section.artifact[id^=\"art-\"]')).map(s => s.id)"))
        catalogue = {r["id"] for r in build.read_catalogue(ROOT / "docs" / "artifacts.md")}
        assert {s.removeprefix("art-") for s in seen} == catalogue
        # a section link lands on its heading in the executed notebook
        driver.get((report["out"] / "wang2023cja.html").as_uri())
        link = driver.execute_script("return document.querySelector('#art-wang2023cja_fig07 a').href")
        driver.get(link)
        assert driver.execute_script("return document.querySelector(':target') !== null")
        driver.get((report["out"] / "index.html").as_uri())
        shot = ROOT / "build" / "report_index.png"
        shot.parent.mkdir(exist_ok=True)
        assert driver.save_screenshot(str(shot)) and shot.stat().st_size > 10_000
    finally:
        driver.quit()
