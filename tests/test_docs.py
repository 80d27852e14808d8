"""The documentation site: built with warnings as errors, every internal link resolves, every
public name has its page, nothing is loaded from the network, and in headless Chromium the
home page, a lesson (equations and a 3-D viewer) and the API page of ``shape_dna`` render
offline.  Screenshots go to ``test-artifacts/``.

The build renders lesson 02 executed (at small size, here, into a temporary folder) and the
other lessons from their sources without outputs: the site's build never executes a notebook.
"""

from __future__ import annotations

import functools
import importlib
import os
import re
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest
from conftest import REPO

pytestmark = [pytest.mark.slow, pytest.mark.docs]

DOCS = REPO / "docs"
ARTIFACTS = REPO / "test-artifacts"
LESSON = "02_shape_dna_weyl"


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """Lesson 02 executed at small size, then ``sphinx -W -b html docs OUT``; returns OUT."""
    pytest.importorskip("sphinx", reason="the docs dependency group is not installed")
    pytest.importorskip("myst_nb", reason="the docs dependency group is not installed")
    from cshape.course.lessons import default_notebook_dir, run_notebook

    tmp = tmp_path_factory.mktemp("docs")
    executed = tmp / "executed"
    res = run_notebook(default_notebook_dir() / f"{LESSON}.ipynb", executed, small=True,
                       html=False, timeout=600, env={"CSHAPE_CACHE": str(tmp / "cache")})
    assert res.ok, res.error
    out = tmp / "html"
    env = dict(os.environ, CSHAPE_DOCS_NOTEBOOKS=str(executed))
    r = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
         "-d", str(tmp / "doctrees"), str(DOCS), str(out)],
        cwd=REPO, env=env, capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, f"sphinx -W failed:\n{r.stdout[-3000:]}\n{r.stderr[-6000:]}"
    assert "WARNING" not in r.stderr, r.stderr[-6000:]
    return out


class _Refs(HTMLParser):
    """Every href/src of a page, and every id (anchor) it defines."""

    def __init__(self):
        super().__init__()
        self.refs, self.ids = [], set()

    def handle_starttag(self, tag, attrs):
        for name, value in attrs:
            if name in ("href", "src") and value:
                self.refs.append((tag, name, value))
            elif name in ("id", "name") and value:
                self.ids.add(value)


def _parse(path: Path) -> _Refs:
    p = _Refs()
    p.feed(path.read_text(encoding="utf-8", errors="replace"))
    return p


@pytest.fixture(scope="module")
def parsed(site):
    """Every page of the site (not the theme's templates that Sphinx copies into _static/ as
    they are), parsed: page -> :class:`_Refs`."""
    pages = sorted(p for p in site.rglob("*.html") if "_static" not in p.relative_to(site).parts)
    return {p: _parse(p) for p in pages}


def test_internal_links_resolve(site, parsed):
    assert len(parsed) > 50, len(parsed)
    broken = []

    @functools.cache  # every page links the same sidebar: resolve each address once
    def resolve(folder, path):
        target = (folder / path).resolve()
        return target, target.exists()

    for page, refs in parsed.items():
        for _tag, _attr, value in refs.refs:
            url = urlsplit(value)
            if url.scheme or value.startswith(("//", "mailto:", "javascript:")):
                continue
            target, exists = (page, True) if not url.path else resolve(page.parent,
                                                                       unquote(url.path))
            if not exists:
                broken.append(f"{page.relative_to(site)}: {value}")
            elif url.fragment and target.suffix == ".html":
                ids = parsed[target].ids if target in parsed else _parse(target).ids
                if unquote(url.fragment) not in ids:
                    broken.append(f"{page.relative_to(site)}: {value} (no such anchor)")
    assert broken == [], "\n".join(broken[:40])


def test_nothing_is_loaded_from_the_network(site, parsed):
    """Scripts, styles, images and frames are all local (links to other sites may stay)."""
    remote = []
    for page, refs in parsed.items():
        for tag, attr, value in refs.refs:
            loads = attr == "src" or (tag == "link" and attr == "href")
            if loads and re.match(r"(https?:)?//", value):
                remote.append(f"{page.relative_to(site)}: <{tag} {attr}={value}>")
    assert remote == [], "\n".join(remote[:20])
    assert (site / "_static" / "mathjax" / "MathJax.js").is_file()


def test_every_public_name_has_its_page(site):
    sys.path.insert(0, str(DOCS / "_ext"))
    try:
        import apipages
    finally:
        sys.path.remove(str(DOCS / "_ext"))
    pages = apipages.write(DOCS / "api")
    expected = set()
    for module, *_ in apipages.SECTIONS:
        mod = importlib.import_module(module)
        expected |= {f"{module}.{n}" for n in mod.__all__}
    assert set(pages) == expected
    missing = [f"{name} -> {page}" for name, page in pages.items()
               if not (site / page).is_file()]
    assert missing == [], missing
    # one page per function and class of the core, under its public name
    import cshape

    for name in cshape.__all__:
        obj = getattr(cshape, name)
        if callable(obj) and getattr(obj, "__module__", "").startswith("cshape"):
            assert pages[f"cshape.{name}"].startswith("api/generated/"), name
    assert (site / "api" / "generated" / "cshape.shape_dna.html").is_file()


def test_lessons_are_rendered_with_their_outputs(site):
    page = (site / "lessons" / f"{LESSON}.html").read_text(encoding="utf-8")
    assert "Learning goals" in page
    assert "plotly" in page.lower() and "Plotly.newPlot" in page  # the 3-D viewer, embedded
    assert '<img alt="_images/' in page or "<img" in page  # matplotlib figures
    assert "cdnjs.cloudflare.com/ajax/libs/mathjax" not in page
    assert "shared meshes not available" not in page
    for other in sorted((REPO / "notebooks").glob("[0-9][0-9]_*.ipynb")):
        assert (site / "lessons" / f"{other.stem}.html").is_file(), other.name


# ----------------------------------------------------------------------------- in a browser
@pytest.mark.browser
def test_site_in_chromium_offline(site):
    """Home page, lesson 02 and the API page of shape_dna in headless Chromium, with every
    request that is not for a local file blocked and recorded: no request is made, the
    equations are typeset (no raw TeX left), the lesson's 3-D viewer draws."""
    from test_browser import CHROMIUM, FLAGS, _drawn, _not_blank, _playwright

    sync_api = _playwright()
    ARTIFACTS.mkdir(exist_ok=True)
    asked = []

    def offline(route):
        if route.request.url.startswith(("file:", "data:", "blob:")):
            route.continue_()
        else:
            asked.append(route.request.url)
            route.abort("internetdisconnected")

    typeset = ("() => window.MathJax && MathJax.Hub && MathJax.Hub.queue.pending === 0"
               " && document.querySelectorAll('.MathJax, .MathJax_Display').length > 0")
    with sync_api.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=str(CHROMIUM), headless=True, args=FLAGS)
        try:
            page = browser.new_page(viewport={"width": 1300, "height": 950})
            page.route("**/*", offline)

            page.goto((site / "index.html").as_uri(), timeout=60_000)
            page.wait_for_function(typeset, timeout=60_000)
            assert "cshape" in page.title()
            assert page.locator("nav").count() > 0
            home = page.inner_text("body")
            assert "Shape-DNA" in home and "$N$" not in home
            page.screenshot(path=str(ARTIFACTS / "docs_home.png"))

            page.goto((site / "lessons" / f"{LESSON}.html").as_uri(), timeout=60_000)
            page.wait_for_function(typeset, timeout=90_000)
            text = page.inner_text("article")
            assert "$$" not in text and "\\lambda" not in text and "\\frac" not in text
            assert page.locator(".MathJax .merror, .MathJax_Display .merror").count() == 0
            assert page.locator(".MathJax_Display").count() >= 1
            canvas = page.locator(".js-plotly-plot .gl-container canvas").first
            canvas.wait_for(timeout=60_000)
            canvas.scroll_into_view_if_needed()
            px = _drawn(canvas)
            assert _not_blank(px), "the 3-D viewer is blank"
            title = page.locator(".js-plotly-plot .gtitle").first.text_content()
            assert "λ" in title and "φ" in title, title
            page.screenshot(path=str(ARTIFACTS / "docs_lesson_02_viewer.png"))
            page.evaluate("window.scrollTo(0, 0)")
            page.screenshot(path=str(ARTIFACTS / "docs_lesson_02.png"))

            page.goto((site / "api" / "generated" / "cshape.shape_dna.html").as_uri(),
                      timeout=60_000)
            page.wait_for_selector("dl.py.function", timeout=30_000)
            api = page.inner_text("article")
            assert "shape_dna" in api and "Parameters" in api and "Returns" in api
            page.screenshot(path=str(ARTIFACTS / "docs_api_shape_dna.png"))
        finally:
            browser.close()
    assert asked == [], f"requests left the machine: {asked[:10]}"
