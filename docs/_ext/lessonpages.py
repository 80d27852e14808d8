"""The lessons as pages of the site, from executed notebooks; MathJax copied into the site.

``collect`` copies each lesson ``notebooks/NN_topic.ipynb`` into ``docs/lessons/`` for
myst-nb: its executed copy from ``out/notebooks/`` (or ``CSHAPE_DOCS_NOTEBOOKS``) when that
copy has the same cells as the source, else the source itself (rendered without outputs).
Nothing is executed during the build.  Plotly's figures keep plotly.js embedded; the MathJax
3 script that plotly's notebook renderer adds from a CDN is removed (the site has its own).

``python docs/_ext/lessonpages.py stale`` prints the lessons whose executed copy is missing or
out of date (``make docs`` executes those, at small size, before building).
"""

from __future__ import annotations

import re
import shutil
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
SOURCES = REPO / "notebooks"
EXECUTED = REPO / "out" / "notebooks"
PATTERN = "[0-9][0-9]_*.ipynb"
#: The site's MathJax (2.7, from jupyter-server-mathjax), relative to _static/, and its config.
MATHJAX_URL = "mathjax/MathJax.js?config=TeX-AMS-MML_HTMLorMML-full,Safe,local/cshape"
_CDN_SCRIPT = re.compile(r'<script[^>]*src="https?://[^"]*mathjax[^"]*"[^>]*></script>', re.I)


def _code(nb) -> list[str]:
    return [c.source for c in nb.cells]


def executed_copy(source: Path, folder: Path):
    """The executed notebook of ``source`` in ``folder``, or None when it is missing, has no
    outputs, or its cells differ from the source's (a lesson edited after its run)."""
    import nbformat

    path = folder / source.name
    if not path.is_file():
        return None
    nb = nbformat.read(path, as_version=4)
    ran = any(c.cell_type == "code" and c.get("outputs") for c in nb.cells)
    if not ran or _code(nb) != _code(nbformat.read(source, as_version=4)):
        return None
    return nb


def stale(folder=None) -> list[str]:
    """Lesson numbers (``'02'``) without an up-to-date executed copy in ``folder``."""
    folder = Path(folder) if folder else EXECUTED
    return [p.name[:2] for p in sorted(SOURCES.glob(PATTERN))
            if executed_copy(p, folder) is None]


def _clean(nb) -> None:
    for cell in nb.cells:
        for out in cell.get("outputs", []):
            data = out.get("data", {})
            if "text/html" in data:
                html = data["text/html"]
                html = "".join(html) if isinstance(html, list) else html
                data["text/html"] = _CDN_SCRIPT.sub("", html)


def collect(dest: Path, folder=None) -> dict[str, bool]:
    """Copy every lesson into ``dest``; returns {lesson stem: rendered with outputs}."""
    import nbformat

    folder = Path(folder) if folder else EXECUTED
    dest.mkdir(parents=True, exist_ok=True)
    found = {}
    sources = sorted(SOURCES.glob(PATTERN))
    for old in dest.glob(PATTERN):
        if old.name not in {p.name for p in sources}:
            old.unlink()
    for src in sources:
        nb = executed_copy(src, folder)
        found[src.stem] = nb is not None
        if nb is None:
            nb = nbformat.read(src, as_version=4)
        _clean(nb)
        text = nbformat.writes(nb)
        target = dest / src.name
        if not target.is_file() or target.read_text(encoding="utf-8") != text:
            target.write_text(text, encoding="utf-8")
    return found


def _copy_mathjax(app, exception) -> None:
    if exception is not None or app.builder.format != "html":
        return
    from cshape.course.lessons import offline_mathjax

    static = Path(app.outdir) / "_static"
    if offline_mathjax(static) is None:
        raise RuntimeError("jupyter-server-mathjax is not installed: the site's equations "
                           "need its MathJax copy (pip install --group docs)")


def setup(app):
    app.connect("build-finished", _copy_mathjax)
    return {"parallel_read_safe": True, "parallel_write_safe": True}


if __name__ == "__main__":
    if sys.argv[1:2] == ["stale"]:
        print(" ".join(stale(sys.argv[2] if len(sys.argv) > 2 else None)))
    elif sys.argv[1:2] == ["clean"]:
        shutil.rmtree(REPO / "docs" / "api" / "generated", ignore_errors=True)
