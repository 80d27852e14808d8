"""The executed lessons' HTML pages as a newcomer opens them after `make demo`: no script from
a network host, and a progress bar that shows where it ended."""

from __future__ import annotations

import importlib.util
import re

import nbformat
import pytest

from cshape.course.lessons import run_notebook

CELLS = [
    "import time\nfrom tqdm.auto import tqdm\n"
    "for i in tqdm(range(5), desc='shapes'):\n    time.sleep(0.01)\nprint('done')",
    "import ipywidgets\nipywidgets.IntSlider(3)",
]
if importlib.util.find_spec("plotly") is not None:
    CELLS.append("import plotly.graph_objects as go\ngo.Figure(go.Scatter(x=[0, 1], y=[1, 0]))")


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    """A lesson with a progress bar, a widget and (with plotly) a figure, executed to HTML."""
    folder = tmp_path_factory.mktemp("lesson")
    nb = nbformat.v4.new_notebook()
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                 "language": "python"}
    nb.cells = [nbformat.v4.new_code_cell(src) for src in CELLS]
    nbformat.write(nb, folder / "01_page.ipynb")
    res = run_notebook(folder / "01_page.ipynb", folder / "out")
    assert res.ok, res.error
    return res


@pytest.mark.slow
def test_a_lesson_page_loads_no_script_from_a_network_host(page):
    text = page.html.read_text(encoding="utf-8")
    sources = re.findall(r"<script[^>]*\ssrc=\"([^\"]*)\"", text)
    assert sources and all(not re.match(r"(https?:)?//", s) for s in sources), sources
    assert "require.min.js" not in text and "unpkg.com" not in text
    # the widget shows its static copy, with no widget state for a network renderer
    assert "widgets" not in nbformat.read(page.ipynb, as_version=4).metadata


@pytest.mark.slow
def test_a_progress_bar_shows_its_final_state(page):
    nb = nbformat.read(page.ipynb, as_version=4)
    bars = [o["data"]["text/plain"] for o in nb.cells[0].outputs
            if "application/vnd.jupyter.widget-view+json" in o.get("data", {})]
    assert len(bars) == 1 and bars[0].startswith("shapes: 100%|"), bars
    assert "| 5/5 [" in bars[0], bars
    text = page.html.read_text(encoding="utf-8")
    assert "shapes: 100%|" in text and "shapes:   0%|" not in text
