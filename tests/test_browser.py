"""End to end in a real browser: JupyterLab on loopback, lesson 07's M-sweep widget in headless
Chromium (Debian's package, driven by Playwright), run all cells, move the M slider, check that
the plot and the statistics change, keep a screenshot in ``test-artifacts/``; lesson 02's
eigenfunction explorer there too; exported pages and every 3-D view offline.

Needs ``/usr/bin/chromium`` (``tools/ensure_browser.sh`` installs it) and the ``playwright``
Python package (test dependency group); the browser itself is never downloaded.  Skipped with
a reason when either is missing.
"""

from __future__ import annotations

import os
import secrets
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import nbformat
import numpy as np
import pytest

pytestmark = pytest.mark.browser

CHROMIUM = Path("/usr/bin/chromium")
REPO = Path(__file__).resolve().parents[1]
ARTIFACTS = REPO / "test-artifacts"
#: The JupyterLab test's notebook: lesson 02's eigenfunction explorer and lesson 07's M-sweep
#: widget, each made by its lesson's own lines (``(lesson, cell)``, checked below against the
#: lessons' sources), without the rest of the lessons (the lessons themselves run in nbgrader's
#: autograde, tests/test_assignments.py).
NOTEBOOK = "widgets.ipynb"
LAB_CELLS = [
    ("02_shape_dna_weyl.py",
     "import cshape\n"
     "from cshape import plots, shapes\n"
     "from cshape.course.teaching import SMALL, size  # CSHAPE_SMALL=1: small meshes and N\n"
     "from cshape.course.teaching import real_mesh  # Spot the cow, shipped with cshape\n"
     "N = size(50, 100)\n"
     "real, real_name = real_mesh()\n"
     "basis = cshape.eigenbasis(real, N)  # the eigenpairs, with B, the area and the mesh"),
    ("02_shape_dna_weyl.py",
     'plots.eigenfunction_explorer(real, 21, basis=basis, vertical_axis="y")'),
    ("07_m_sweep.py",
     "from cshape import batch\n"
     "from cshape.course.teaching import SMALL, size  # CSHAPE_SMALL=1: small meshes and N\n"
     "from cshape.course.teaching import demo_collection\n"
     "from cshape.plots import widgets\n"
     "N = size(40, 100)\n"
     "table = batch.describe(demo_collection(), N=N, progress=not SMALL)"),
    ("07_m_sweep.py",
     'no_spheres = table.select([i for i, lab in enumerate(table.labels) if lab != "sphere"])\n'
     'w = widgets.m_sweep_widget({"all shapes": table, "without spheres": no_spheres}, M=8, '
     "N=N)\nw"),
]
FLAGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
]


def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _wait_for_server(url, proc, timeout=90.0):
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout:
        if proc.poll() is not None:
            raise RuntimeError(f"JupyterLab exited with code {proc.returncode}")
        try:
            with urllib.request.urlopen(url, timeout=2) as r:  # loopback only
                if r.status == 200:
                    return
        except OSError:
            time.sleep(0.5)
    raise TimeoutError(f"JupyterLab did not answer at {url} within {timeout:.0f} s")


@pytest.fixture(scope="module")
def jupyterlab_server(tmp_path_factory):
    """A JupyterLab server on 127.0.0.1 with a random port and token, serving the notebook of
    :data:`LAB_CELLS`; the kernels see CSHAPE_SMALL=1.  Started once for
    the module (its start-up is most of a test's time); each test gets its own workspace
    and browser profile through :func:`jupyterlab`."""
    pytest.importorskip("jupyterlab", reason="jupyterlab is not installed")
    tmp_path = tmp_path_factory.mktemp("jupyterlab")
    root = tmp_path / "root"
    root.mkdir()
    nb = nbformat.v4.new_notebook()
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                 "language": "python"}
    nb.cells = [nbformat.v4.new_code_cell(c) for _lesson, c in LAB_CELLS]
    nbformat.write(nb, root / NOTEBOOK)
    # no "get notified about Jupyter news?" toast over the plot
    notif = tmp_path / "settings" / "@jupyterlab" / "apputils-extension"
    notif.mkdir(parents=True)
    (notif / "notification.jupyterlab-settings").write_text('{"fetchNews": "false"}')
    port, token = _free_port(), secrets.token_hex(16)
    env = dict(os.environ, CSHAPE_SMALL="1", CSHAPE_CACHE=str(tmp_path / "cshape-cache"),
               JUPYTER_CONFIG_DIR=str(tmp_path / "config"),
               JUPYTER_DATA_DIR=str(tmp_path / "data"),
               JUPYTER_RUNTIME_DIR=str(tmp_path / "runtime"),
               JUPYTERLAB_SETTINGS_DIR=str(tmp_path / "settings"),
               JUPYTERLAB_WORKSPACES_DIR=str(tmp_path / "workspaces"))
    cmd = [sys.executable, "-m", "jupyterlab", "--no-browser",
           "--ServerApp.ip=127.0.0.1", f"--ServerApp.port={port}",
           "--ServerApp.port_retries=0", f"--IdentityProvider.token={token}",
           f"--ServerApp.root_dir={root}", "--LabApp.news_url=None",
           "--LabApp.extension_manager=readonly", "--ServerApp.terminals_enabled=False",
           "--LabApp.expose_app_in_browser=True"]
    if hasattr(os, "geteuid") and os.geteuid() == 0:  # CI machines run as root
        cmd.append("--allow-root")
    log = open(tmp_path / "jupyterlab.log", "w")  # noqa: SIM115 - closed below
    proc = subprocess.Popen(cmd, env=env, stdout=log, stderr=subprocess.STDOUT, cwd=root)
    try:
        try:
            _wait_for_server(f"http://127.0.0.1:{port}/api/status?token={token}", proc)
        except (RuntimeError, TimeoutError) as exc:
            log.flush()
            tail = (tmp_path / "jupyterlab.log").read_text()[-3000:]
            raise RuntimeError(f"{exc}; JupyterLab's log ends with:\n{tail}") from None
        yield f"http://127.0.0.1:{port}", token
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait(timeout=10)
        log.close()


def _api(base, token, path, method="GET"):
    """A call of the Jupyter server's REST API on loopback; the decoded JSON, or None."""
    import json

    req = urllib.request.Request(f"{base}/api/{path}?token={token}", method=method)
    with urllib.request.urlopen(req, timeout=30) as r:  # loopback only
        body = r.read()
    return json.loads(body) if body else None


@pytest.fixture
def jupyterlab(jupyterlab_server, tmp_path, request):
    """The module's JupyterLab server for one test: ``(base, token, tmp, workspace)``, with a
    workspace of the test's own (no layout restored from another test) and ``tmp`` for its
    browser profile; the kernels the test started are shut down after it."""
    base, token = jupyterlab_server
    before = {s["id"] for s in _api(base, token, "sessions")}
    yield base, token, tmp_path, request.node.name.replace("[", "-").rstrip("]")
    for session in _api(base, token, "sessions"):
        if session["id"] not in before:
            _api(base, token, f"sessions/{session['id']}", method="DELETE")


def _start_kernel(page, timeout=90.0):
    """Accept JupyterLab's "Select Kernel" dialog if it comes up, then wait for an idle kernel."""
    accept = page.locator(".jp-Dialog .jp-mod-accept")
    idle = page.locator(".jp-Notebook-ExecutionIndicator[data-status='idle']")
    # the indicator can say idle before the session has a kernel: ask the session itself
    connected = """() => { const w = window.jupyterapp.shell.currentWidget;
        const k = w && w.sessionContext && w.sessionContext.session
                  && w.sessionContext.session.kernel;
        return !!k && k.status === 'idle' && k.connectionStatus === 'connected'; }"""
    t0 = time.monotonic()
    quiet_since = None
    while time.monotonic() - t0 < timeout:
        if accept.count() and accept.first.is_visible():
            accept.first.click()
            quiet_since = None
        elif idle.count() and page.evaluate(connected):
            # idle and no dialog for a second: the kernel is up
            quiet_since = quiet_since or time.monotonic()
            if time.monotonic() - quiet_since > 1.0:
                return
        time.sleep(0.2)
    raise TimeoutError(f"the notebook's kernel was not idle within {timeout:.0f} s")


def _playwright():
    """Playwright's sync API for Debian's Chromium; without the browser the test skips (and
    fails under CI, where make test installs it as root)."""
    if not CHROMIUM.exists():
        msg = f"{CHROMIUM} not found: install Debian's chromium (tools/ensure_browser.sh)"
        if os.environ.get("CI"):
            pytest.fail(msg + "; CI must run the browser test, and make test installs it as root")
        pytest.skip(msg)
    return pytest.importorskip(
        "playwright.sync_api", reason="the playwright Python package is not installed")


def _lab_context(p, tmp):
    """A headless Chromium with its own profile in ``tmp``, sized for JupyterLab."""
    return p.chromium.launch_persistent_context(
        str(tmp / "chromium-profile"), executable_path=str(CHROMIUM), headless=True,
        args=FLAGS, viewport={"width": 1400, "height": 1000},
    )


def test_lab_notebook_makes_the_widgets_as_their_lessons_do():
    """Every line of the JupyterLab test's notebook is a line of its lesson's source."""
    for lesson, cell in LAB_CELLS:
        lines = {ln.strip() for ln in (REPO / "notebooks" / lesson).read_text().splitlines()}
        missing = [ln for ln in cell.splitlines() if ln.strip() not in lines]
        assert missing == [], f"not in {lesson}: {missing}"


def _run_all(page, notebook):
    """Open ``notebook`` in the page's JupyterLab, wait for its kernel, then Run > Run All
    Cells (the menu's command)."""
    page.evaluate("p => window.jupyterapp.commands.execute('docmanager:open', {path: p})",
                  notebook)
    page.wait_for_function(
        "p => { const w = window.jupyterapp.shell.currentWidget;"
        " return !!w && !!w.context && w.context.path === p; }", arg=notebook, timeout=90_000)
    _start_kernel(page)
    # (not awaiting the command's promise: it settles only when every cell has run)
    page.evaluate("() => { window.jupyterapp.commands.execute('notebook:run-all-cells'); }")


def _failed(page, what, png):
    page.screenshot(path=str(ARTIFACTS / png))
    errors = page.locator(".jp-OutputArea-output[data-mime-type*='stderr']")
    return AssertionError(
        f"{what} did not appear; stderr outputs: "
        f"{[errors.nth(i).inner_text()[:500] for i in range(errors.count())]}")


def test_widgets_in_jupyterlab(jupyterlab):
    """In JupyterLab, as a student has them: Run All Cells of a notebook of lesson 02's and
    lesson 07's lines.  The M-sweep widget appears, and moving its M slider one step changes
    the statistics and the plot; lesson 02's eigenfunction explorer (plotly, rendered by the
    lab extension) is there too, and moving its slider to phi_10 re-renders the 3-D
    canvas."""
    sync_api = _playwright()
    base, token, tmp, workspace = jupyterlab
    ARTIFACTS.mkdir(exist_ok=True)
    with sync_api.sync_playwright() as p:
        ctx = _lab_context(p, tmp)
        try:
            page = ctx.new_page()
            page.goto(f"{base}/lab/workspaces/{workspace}?token={token}", timeout=90_000)
            page.wait_for_function("() => window.jupyterapp !== undefined", timeout=90_000)
            page.evaluate("() => window.jupyterapp.restored.then(() => true)")
            _run_all(page, NOTEBOOK)

            # ---- the M-sweep widget (made by the last cell: every cell has run)
            stats = page.locator(".cshape-msweep-stats")
            try:
                stats.wait_for(timeout=240_000)
            except sync_api.TimeoutError:
                raise _failed(page, "the M-sweep widget", "m_sweep_browser_failed.png") from None
            plot = page.locator("img.cshape-msweep-plot")
            plot.wait_for(timeout=60_000)
            plot.scroll_into_view_if_needed()
            text0 = stats.inner_text()
            src0 = plot.get_attribute("src")
            png0 = plot.screenshot()
            assert "M = 8" in text0, text0
            # move the M slider one step down: focus its handle, press the left arrow
            slider = page.locator(".cshape-msweep .widget-slider").filter(
                has=page.locator("label", has_text="M"))
            handle = slider.locator(".noUi-handle").first
            handle.focus()
            handle.press("ArrowLeft")
            t0 = time.monotonic()
            while "M = 7" not in stats.inner_text() and time.monotonic() - t0 < 60:
                time.sleep(0.25)
            text1 = stats.inner_text()
            t0 = time.monotonic()
            while plot.get_attribute("src") == src0 and time.monotonic() - t0 < 30:
                time.sleep(0.25)
            page.screenshot(path=str(ARTIFACTS / "m_sweep_browser.png"), full_page=False)
            plot.screenshot(path=str(ARTIFACTS / "m_sweep_plot.png"))
            assert text1 != text0 and "M = 7:" in text1, (text0, text1)
            assert plot.get_attribute("src") != src0
            assert plot.screenshot() != png0, "the plot image did not change"

            # ---- the eigenfunction explorer, above it
            # the first plotly figure with a slider: the explorer of the real mesh
            plot = page.locator(".js-plotly-plot").filter(
                has=page.locator(".slider-rail-rect")).first
            try:
                plot.wait_for(timeout=60_000)
            except sync_api.TimeoutError:
                raise _failed(page, "the eigenfunction explorer",
                              "explorer_browser_failed.png") from None
            plot.scroll_into_view_if_needed()
            canvas = plot.locator(".gl-container canvas").first
            canvas.wait_for(timeout=60_000)
            px0 = _drawn(canvas)
            title = plot.locator(".gtitle")
            title0 = title.text_content()
            box = plot.locator(".slider-rail-rect").bounding_box()
            assert "λ" in title0 and "φ" in title0, title0
            # the slider has 21 steps (phi_0..phi_20): step 10 is in the middle of the rail
            page.mouse.click(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
            page.wait_for_function(
                "([el, t]) => el.textContent !== t", arg=[title.element_handle(), title0],
                timeout=30_000)
            title1 = title.text_content()
            png1 = _eventually(canvas.screenshot,  # the new eigenfunction drawn
                               lambda png: _changed(px0, _canvas_pixels(png)) > 0.01)
            page.screenshot(path=str(ARTIFACTS / "explorer_browser.png"))
            canvas.screenshot(path=str(ARTIFACTS / "explorer_canvas.png"))
        finally:
            ctx.close()
    assert "φ10" in title1.replace("\u200b", "").replace(" ", ""), (title0, title1)
    px1 = _canvas_pixels(png1)
    assert _not_blank(px0) and _not_blank(px1), "the 3-D canvas is blank"
    assert _changed(px0, px1) > 0.01, "the canvas did not change"


def test_ensure_browser_is_idempotent():
    """With the browser installed, tools/ensure_browser.sh changes nothing and exits 0."""
    if not (CHROMIUM.exists() and Path("/usr/bin/chromedriver").exists()):
        pytest.skip("chromium / chromedriver not installed; the script would install them")
    res = subprocess.run(["bash", str(REPO / "tools" / "ensure_browser.sh")],
                         capture_output=True, text=True, timeout=60)
    assert res.returncode == 0 and "present" in res.stdout, res.stdout + res.stderr


# ------------------------------------------------------------------------------ offline HTML
def _canvas_pixels(png: bytes):
    """RGB pixels of a screenshot, shape (h, w, 3)."""
    import io

    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(np.int16)


def _not_blank(px) -> bool:
    """More than 2 % of the pixels differ from the corner colour (the background)."""
    return float(np.mean(np.abs(px - px[0, 0]).sum(axis=2) > 30)) > 0.02


def _eventually(shot, ok, timeout=30.0, every=0.2):
    """``shot()`` again and again until ``ok(result)`` holds or ``timeout`` seconds have passed;
    the last result.  WebGL draws in the frames after the page has its canvas, later on a
    loaded machine: wait for what the test asserts, not for a fixed time."""
    t0 = time.monotonic()
    while True:
        out = shot()
        if ok(out) or time.monotonic() - t0 > timeout:
            return out
        time.sleep(every)


def _drawn(canvas, timeout=30.0):
    """The pixels of a WebGL canvas once it is not blank (or after ``timeout`` seconds)."""
    return _eventually(lambda: _canvas_pixels(canvas.screenshot()), _not_blank, timeout)


def _changed(px0, px1) -> float:
    """Fraction of pixels that differ, over the common part of two screenshots (a re-layout
    may change a canvas's size by a scrollbar's width)."""
    h, w = min(px0.shape[0], px1.shape[0]), min(px0.shape[1], px1.shape[1])
    return float(np.mean(np.abs(px1[:h, :w] - px0[:h, :w]).sum(axis=2) > 30))


def test_exported_html_renders_math_and_3d_offline(tmp_path):
    """An exported page (the markdown of every lesson, and an eigenfunction explorer) opens in
    Chromium with every non-file request blocked: MathJax typesets the equations from the copy
    next to the page (no raw $$ left), plotly draws the mesh, and its slider re-renders it."""
    if not CHROMIUM.exists():
        pytest.skip(f"{CHROMIUM} not found: install Debian's chromium (tools/ensure_browser.sh)")
    sync_api = pytest.importorskip(
        "playwright.sync_api", reason="the playwright Python package is not installed")
    pytest.importorskip("jupyter_server_mathjax", reason="jupyter-server-mathjax not installed")
    import nbformat

    from cshape.course.lessons import find_notebooks, run_notebook

    nb = nbformat.v4.new_notebook()
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                 "language": "python"}
    for path in find_notebooks():
        nb.cells += [c for c in nbformat.read(path, as_version=4).cells
                     if c.cell_type == "markdown" and "$" in c.source]
    n_math = len(nb.cells)
    nb.cells.append(nbformat.v4.new_code_cell(
        "from cshape import plots, shapes\nplots.eigenfunction_explorer(shapes.icosphere(2), 12)"))
    for k, c in enumerate(nb.cells):
        c["id"] = f"c{k}"
    src = tmp_path / "src"
    src.mkdir()
    nbformat.write(nb, src / "01_offline.ipynb")
    res = run_notebook(src / "01_offline.ipynb", tmp_path / "out", timeout=300)
    assert res.ok, res.error
    assert (tmp_path / "out" / "mathjax" / "MathJax.js").is_file()
    ARTIFACTS.mkdir(exist_ok=True)
    with sync_api.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=str(CHROMIUM), headless=True, args=FLAGS)
        try:
            page = browser.new_page(viewport={"width": 1200, "height": 900})
            asked = []

            def offline(route):
                if route.request.url.startswith("file:"):
                    route.continue_()
                else:
                    asked.append(route.request.url)
                    route.abort("internetdisconnected")

            page.route("**/*", offline)
            page.goto(res.html.as_uri(), timeout=60_000)
            page.wait_for_function(
                "() => window.MathJax && MathJax.Hub && MathJax.Hub.queue.pending === 0"
                " && document.querySelectorAll('.MathJax_Display').length > 0", timeout=90_000)
            text = page.inner_text("body")
            assert "$$" not in text, text[text.index("$$") - 200:text.index("$$") + 200]
            assert "\\lambda" not in text and "\\frac" not in text
            assert page.locator(".MathJax").count() >= n_math  # typeset, inline or display
            assert page.locator(".MathJax .merror").count() == 0  # no TeX errors
            # the only request for the network is nbconvert's require.js (for widget pages)
            assert all("require" in u for u in asked), asked
            canvas = page.locator(".js-plotly-plot .gl-container canvas").first
            canvas.scroll_into_view_if_needed()
            px0 = _drawn(canvas)
            title0 = page.locator(".js-plotly-plot .gtitle").text_content()
            rail = page.locator(".js-plotly-plot .slider-rail-rect").first
            box = rail.bounding_box()
            page.mouse.click(box["x"] + box["width"] * 10 / 11, box["y"] + box["height"] / 2)
            page.wait_for_function(
                "t => document.querySelector('.js-plotly-plot .gtitle').textContent !== t",
                arg=title0, timeout=30_000)
            png1 = _eventually(canvas.screenshot,  # the 10th eigenfunction drawn
                               lambda png: _changed(px0, _canvas_pixels(png)) > 0.01)
            page.screenshot(path=str(ARTIFACTS / "offline_html.png"))
            px1 = _canvas_pixels(png1)
            title1 = page.locator(".js-plotly-plot .gtitle").text_content()
        finally:
            browser.close()
    assert "φ" in title0 and "λ" in title0 and title1 != title0
    assert "10" in title1, title1  # the 10th eigenfunction
    assert _not_blank(px0) and _not_blank(px1)
    assert _changed(px0, px1) > 0.01, "the canvas did not change"


# ------------------------------------------------------------------------------ own collection
def _offline_page(browser, asked, viewport=(1200, 900)):
    """A page that may load file: URLs only; any other request is recorded and refused."""
    page = browser.new_page(viewport={"width": viewport[0], "height": viewport[1]})

    def offline(route):
        if route.request.url.startswith("file:"):
            route.continue_()
        else:
            asked.append(route.request.url)
            route.abort("internetdisconnected")

    page.route("**/*", offline)
    return page


def _hover_text(page, point):
    """Move the mouse onto an SVG point of a plotly figure; the hover label's text."""
    point.scroll_into_view_if_needed()
    box = point.bounding_box()
    page.mouse.move(0, 0)
    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    label = page.locator(".hoverlayer .hovertext").first
    label.wait_for(timeout=10_000)
    return label.text_content()


@pytest.mark.slow
def test_collection_pictures_in_chromium_offline(tmp_path):
    """`cshape overview` and `cshape query --plot` pages open in Chromium with the network
    blocked: the MDS draws every shape, hovering a point shows its name, class and nearest
    shapes (those of the distance matrix), the outlier's arrow says it is one, the strip's
    meshes render with their distances, and no request leaves the page."""
    sync_api = _playwright()
    from conftest import write_off

    from cshape import PAPER, shapes
    from cshape.batch import DescriptorTable
    from cshape.batch.table import collection_distances
    from cshape.cli import main
    from cshape.compare import nearest_neighbours

    # a collection of 12 spectra in 3 classes, and one far away (a coarse control cage)
    rng = np.random.default_rng(0)
    i = np.arange(30)
    labels = [f"class{k % 3}" for k in range(12)] + ["class0"]
    lam = np.array([4 * np.pi * i * (1 + 0.3 * int(lab[-1]) + 0.2 * rng.random(30))
                    for lab in labels])
    lam[-1] *= 300.0
    names = [f"shape{k}" for k in range(12)] + ["cage"]
    table = DescriptorTable(names, lam, np.ones(13), labels)
    table.save(tmp_path / "t.csv")
    # the paper's cShape-DNA: lam_99 x 300 makes the cage an outlier under it
    assert main(["overview", str(tmp_path / "t.csv"), "--out", str(tmp_path / "o.html"),
                 "--kind", "cshape"]) == 0
    c = collection_distances(table, PAPER.for_N(30))  # what --kind cshape compares
    ind, _ = nearest_neighbours(c.D, 3)
    expected = {n: [c.names[j] for j in ind[k]] for k, n in enumerate(c.names)}
    # four meshes in two classes, described, and the strip of one query
    meshes = tmp_path / "meshes"
    ico = shapes.icosphere(2)
    write_off(meshes / "round" / "small.off", ico)
    write_off(meshes / "round" / "big.off", (2.0 * ico.vertices, ico.faces))
    write_off(meshes / "ring" / "thin.off", shapes.torus(24, 12, r=0.3))
    write_off(meshes / "ring" / "fat.off", shapes.torus(24, 12, r=0.45))
    assert main(["describe", str(meshes), "--out", str(tmp_path / "m.csv"), "-N", "20",
                 "--no-cache", "-q"]) == 0
    assert main(["query", str(tmp_path / "m.csv"), "small", "-k", "2", "--plot",
                 str(tmp_path / "strip.html"), "--meshes", str(meshes)]) == 0
    ARTIFACTS.mkdir(exist_ok=True)
    asked = []
    with sync_api.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=str(CHROMIUM), headless=True, args=FLAGS)
        try:
            page = _offline_page(browser, asked)
            page.goto((tmp_path / "o.html").as_uri(), timeout=60_000)
            mds = page.locator(".js-plotly-plot").first
            mds.locator(".scatterlayer .point").first.wait_for(timeout=60_000)
            assert mds.locator(".scatterlayer .point").count() == 13
            title = mds.locator(".gtitle").text_content()
            hovers = {}
            for k in range(mds.locator(".scatterlayer .point").count()):
                text = _hover_text(page, mds.locator(".scatterlayer .point").nth(k))
                hovers[text.split("class: ")[0]] = text  # the name comes first
            page.screenshot(path=str(ARTIFACTS / "overview_html.png"), full_page=True)
            n_matrix = page.locator(".js-plotly-plot .heatmaplayer").count()
            strip = _offline_page(browser, asked, viewport=(1000, 450))
            strip.goto((tmp_path / "strip.html").as_uri(), timeout=60_000)
            canvas = strip.locator(".js-plotly-plot .gl-container canvas").first
            canvas.wait_for(timeout=60_000)
            drawn = _drawn(canvas)
            heads = strip.locator(".js-plotly-plot .annotation-text").all_text_contents()
            png = strip.locator(".js-plotly-plot").first.screenshot()
            strip.screenshot(path=str(ARTIFACTS / "neighbour_strip_html.png"))
        finally:
            browser.close()
    assert asked == []  # plotly.js is in the page; nothing was asked of the network
    assert "MDS of 13 shapes by paper's cShape-DNA (M=14 of N=30, 29 values)" in title
    assert n_matrix == 1
    assert len(hovers) >= 10  # (points drawn on top of each other share one label)
    assert set(hovers) <= set(names)
    for name, text in hovers.items():
        assert f"class: {labels[names.index(name)]}" in text
        near = text.split("nearest: ")[1].split("outlier")[0]
        assert [x.split(" (")[0] for x in near.split(", ")] == expected[name], text
    assert "outlier" in hovers["cage"] and "drawn at the border" in hovers["cage"]
    assert heads[0].startswith("query") and "small" in heads[0]
    assert all("d = " in h for h in heads[1:]) and len(heads) == 3
    assert _not_blank(drawn) and _not_blank(_canvas_pixels(png))


# ------------------------------------------------------------------------------ framing
#: JavaScript: the pixel rectangle (left, top, width, height), in the window, of every 3-D
#: scene of the plotly figures inside the elements that ``selector`` picks, from plotly's own
#: layout (the plot area less the margins, times the domain).
_SCENE_RECTS = """selector => Array.from(document.querySelectorAll(selector))
    .flatMap(el => Array.from(el.querySelectorAll('.js-plotly-plot'))).flatMap(gd => {
    const L = gd._fullLayout, s = L._size, box = gd.getBoundingClientRect();
    return (L._subplots.gl3d || []).map(id => {
        const d = L[id].domain;
        return [box.left + s.l + d.x[0] * s.w, box.top + s.t + (1 - d.y[1]) * s.h,
                (d.x[1] - d.x[0]) * s.w, (d.y[1] - d.y[0]) * s.h]; }); })"""


#: JavaScript: every plotly figure of the page is laid out at its element's width (after a
#: load or a resize of the window).
_LAID_OUT = """() => Array.from(document.querySelectorAll('.js-plotly-plot')).every(gd =>
    gd._fullLayout && Math.abs(gd._fullLayout.width - gd.getBoundingClientRect().width) < 1.5)"""
#: JavaScript: a promise that settles after the browser has drawn two more frames.
_FRAMES = "() => new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))"


def _border_hits(px, rect, band=2):
    """Pixels of the band just inside a scene's rectangle that are not the page's white: a mesh
    drawn there is cut by the frame."""
    x0, y0, w, h = (int(round(v)) for v in rect)
    x1, y1 = x0 + w, y0 + h
    x0, y0 = x0 + 1, y0 + 1  # the rectangle's own edge may be anti-aliased
    x1, y1 = x1 - 1, y1 - 1
    edge = np.concatenate([px[y0:y0 + band, x0:x1].reshape(-1, 3),
                           px[y1 - band:y1, x0:x1].reshape(-1, 3),
                           px[y0:y1, x0:x0 + band].reshape(-1, 3),
                           px[y0:y1, x1 - band:x1].reshape(-1, 3)])
    inside = px[y0:y1, x0:x1].reshape(-1, 3)
    not_white = lambda a: (np.abs(a - 255).sum(axis=1) > 40)  # noqa: E731
    return int(not_white(edge).sum()), float(not_white(inside).mean())


def _framing_views(tmp_path):
    """Every kind of 3-D view the lessons and the command line make, with the lessons' sizes:
    ``[(page, viewport sizes, views)]``.  The lessons' figures share one page, as in a
    notebook (``figure_html(fig, full_html=False)``, plotly.js with the first, each in an element
    ``data-view=NAME``); ``cshape query --plot`` writes a page of its own."""
    from conftest import write_off

    from cshape import eigenbasis, plots, shapes, wks
    from cshape import signatures as sg
    from cshape.cli import main
    from cshape.data import poses
    from cshape.plots.overview import figure_html
    from cshape.signatures import heat_kernel, match_points

    rest = poses.posed_figure("human", rest=True, voxelsize=0.03, target_vertices=800)
    pose = poses.posed_figure("human", 1, voxelsize=0.03, target_vertices=800)
    basis, basis_p = eigenbasis(rest, N=40), eigenbasis(pose, N=40)
    tk = sg.hks_times(basis)
    hand = int(np.argmax(rest.vertices[:, 0]))
    heat = {f"t = {tk[k]:.3g}": heat_kernel(basis, float(tk[k]), hand) for k in (60, 80, 95)}
    long_box = (shapes.cube(4).vertices * [4.0, 1.0, 0.6], shapes.cube(4).faces)  # y up
    ball = shapes.icosphere(2)
    a, b = wks(basis), wks(basis_p)
    figs = {
        "view_mesh": plots.view_mesh(rest),
        "view_mesh_y_up_long": plots.view_mesh(long_box, vertical_axis="y"),
        "lesson01_hat": plots.view_mesh(ball, ball.vertices[:, 0], cmap="Reds", edges=True,
                                        height=380, title="the hat function"),
        "lesson05_noise": plots.view_meshes({"clean": shapes.torus(32, 16),
                                             "noisy": shapes.torus(32, 16)}, height=380),
        "lesson09_heat": plots.view_meshes({k: rest for k in heat}, heat, cmap="Viridis",
                                           symmetric=False, height=360),
        "eigenfunction_explorer": plots.eigenfunction_explorer(rest, 12, basis=basis),
        "signature_explorer": plots.signature_explorer(rest, "wks", basis=basis,
                                                       n_scales=12),
        "correspondence": plots.view_map(rest, pose, match_points(b, a),
                                         titles=("rest", "pose"), height=380),
        "view_map": plots.view_map(rest, pose, np.arange(pose.n_vertices), height=380,
                                   landmarks=np.array([[hand, hand], [0, 0]])),
    }
    lessons = tmp_path / "lessons.html"  # plotly.js once, with the first figure
    lessons.write_text('<html><head><meta charset="utf-8"></head><body style="margin:0">' + "".join(
        f'<div data-view="{name}">'
        f"{figure_html(fig, full_html=False, include_plotlyjs=k == 0)}</div>"
        for k, (name, fig) in enumerate(figs.items())) + "</body></html>")
    # the command line: cshape query ... --plot view.html, on a folder of meshes
    meshes = tmp_path / "meshes"
    write_off(meshes / "rest.off", rest)
    write_off(meshes / "pose.off", pose)
    write_off(meshes / "long.off", long_box)
    write_off(meshes / "ball.off", ball)
    write_off(meshes / "ring.off", shapes.torus(24, 12))
    assert main(["describe", str(meshes), "--out", str(tmp_path / "m.csv"), "-N", "20",
                 "--no-cache", "-q"]) == 0
    assert main(["query", str(tmp_path / "m.csv"), "rest", "-k", "4", "--plot",
                 str(tmp_path / "query.html"), "--meshes", str(meshes)]) == 0
    return [(lessons, [(760, 700), (1200, 800)], list(figs)),
            (tmp_path / "query.html", [(1200, 900), (1280, 720), (1000, 800)], [None])]


@pytest.mark.slow
def test_every_3d_view_is_framed_in_chromium(tmp_path):
    """Every 3-D view, rendered by plotly.js in Chromium on a white page: no mesh pixel on the
    border of its scene (nothing cut by the frame), and the mesh fills a good part of it.
    Each page opens at its first size and is then resized to the others (the figures follow
    the window, as in a browser a user resizes); each view is scrolled to the top of the
    window and photographed there."""
    sync_api = _playwright()
    out = ARTIFACTS / "framing"
    out.mkdir(parents=True, exist_ok=True)
    problems, seen = [], set()

    def look(page, name, w, h):
        selector = "body" if name is None else f'[data-view="{name}"]'
        name = name or page.url.rsplit("/", 1)[-1].removesuffix(".html")
        png = out / f"{name}_{w}x{h}.png"
        page.evaluate("s => document.querySelector(s).scrollIntoView({block: 'start'})",
                      selector)

        def shot():
            page.screenshot(path=str(png))
            rects = page.evaluate(_SCENE_RECTS, selector)
            px = _canvas_pixels(png.read_bytes())
            assert rects, f"{name}: no 3-D scene"
            found = []
            for k, rect in enumerate(rects):
                x0, y0, rw, rh = rect
                assert x0 >= 0 and y0 >= 0 and x0 + rw <= px.shape[1] and y0 + rh <= px.shape[
                    0], f"{name} at {w}x{h}, scene {k + 1}: {rect} is not inside the window"
                hits, filled = _border_hits(px, rect)
                if hits or filled < 0.03:
                    found.append(f"{name} at {w}x{h}, scene {k + 1}: {hits} mesh "
                                 f"pixels on the border, {filled:.1%} filled")
            return found, px

        # WebGL draws in the frames after the layout, later on a loaded machine: the verdict
        # is that of two screenshots in a row with the same pixels (the drawing has settled)
        # and no problem; a problem that stays for 10 s is reported
        last = []

        def settled(result):
            found, px = result
            same = bool(last) and last[-1].shape == px.shape and np.array_equal(last[-1], px)
            last.append(px)
            return same and not found

        problems.extend(_eventually(shot, settled, timeout=10, every=0.05)[0])
        seen.add(name)

    with sync_api.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=str(CHROMIUM), headless=True, args=FLAGS)
        try:
            for path, sizes, views in _framing_views(tmp_path):
                page = browser.new_page(viewport={"width": sizes[0][0], "height": sizes[0][1]})
                page.goto(path.as_uri(), timeout=60_000)
                page.wait_for_function(  # every figure has its WebGL canvas
                    "() => Array.from(document.querySelectorAll('.js-plotly-plot'))"
                    ".every(gd => gd.querySelector('.gl-container canvas'))", timeout=60_000)
                for k, (w, h) in enumerate(sizes):
                    if k:
                        page.set_viewport_size({"width": w, "height": h})
                    # plotly has laid every figure out at the window's width, then WebGL
                    # draws in the next frames
                    page.wait_for_function(_LAID_OUT, timeout=60_000)
                    page.evaluate(_FRAMES)
                    for name in views:
                        look(page, name, w, h)
                page.close()
        finally:
            browser.close()
    assert len(seen) == 10, seen
    assert not problems, problems
