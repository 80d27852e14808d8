"""Sphinx configuration of cshape's documentation site (``make docs`` -> ``out/docs/``).

The site is built offline and renders offline:

* the lessons are the executed notebooks of ``out/notebooks/`` (``python -m cshape notebooks
  --small --out out/notebooks``, or ``make demo``'s full-size run), never executed here; a
  lesson without an executed copy is rendered from its source, without outputs;
  ``CSHAPE_DOCS_NOTEBOOKS`` names another folder of executed notebooks;
* equations are typeset by MathJax 2.7 copied into the site (``_static/mathjax``, from the
  ``jupyter-server-mathjax`` package), plotly.js is embedded in the lesson pages;
* there is no intersphinx: it would download numpy's and scipy's inventories.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
REPO = DOCS.parent
sys.path.insert(0, str(DOCS / "_ext"))
sys.path.insert(0, str(REPO))

import apipages  # noqa: E402
import lessonpages  # noqa: E402

import cshape  # noqa: E402

project = "cshape"
author = "cshape developers"
copyright = "cshape developers, BSD-3-Clause"
version = release = cshape.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_nb",
    "lessonpages",
]

# ---------------------------------------------------------------- pages
root_doc = "index"
exclude_patterns = ["_build", "**.ipynb_checkpoints", "lessons/README.md"]
templates_path = ["_templates"]
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
API_PAGES = apipages.write(DOCS / "api")
LESSONS = lessonpages.collect(DOCS / "lessons", os.environ.get("CSHAPE_DOCS_NOTEBOOKS"))

# ---------------------------------------------------------------- API reference
autosummary_generate = True
autosummary_imported_members = True
autodoc_typehints = "none"  # numpydoc's Parameters say the types
autodoc_default_options = {"members": False}
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
# Every docstring the API pages show is validated (numpydoc's checks, as LaPy's docs do; the
# build runs with -W, so a failing docstring fails it).  "all" followed by codes means every
# check but those codes.  tests/test_docstrings.py reads these two settings from this file
# (keep them literals) and runs the same checks in the fast tier, without Sphinx.
numpydoc_validation_checks = {
    "all",
    "GL01",  # summary on the line of the opening quotes is the house style (ruff's D212)
    "ES01",  # an extended summary only where the summary line needs one
    "SA01",  # See Also only where a related name helps; the API index groups the rest
    "EX01",  # the lessons and guides are the examples; doctests live where they teach
    "RT02",  # a single returned value is named ("lam : ndarray, shape (N,)"), as numpy does
}
# objects that cannot carry a numpydoc docstring of their own (regular expressions on the
# full name); never a public function, class or method (tests/test_docstrings.py checks)
numpydoc_validation_exclude = {
    # module constants (``.. autodata::``, ``cshape.data.MESH_SUFFIXES``): their documentation
    # is a ``#:`` comment, which has no quotes to place (GL02) and no sections, and PAPER
    # and DEFAULT are instances, which would be validated against their class's docstring
    r"^cshape(\.[a-z_][a-z0-9_]*)*\.[A-Z][A-Z0-9_]*$",
    # the type alias of a mesh argument, module data with a #: comment like the constants
    r"^cshape\.mesh\.MeshLike$",
}

# ---------------------------------------------------------------- notebooks and markdown
nb_execution_mode = "off"  # the lessons are executed once, by `cshape notebooks`
nb_output_stderr = "remove"
nb_ipywidgets_js = {}  # widget JavaScript would come from a CDN; widgets need a kernel anyway
nb_merge_streams = True
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
# plotly figures: the embedded HTML (plotly.js in the page), not the JupyterLab mime type;
# widgets: their static copy (text/html), not a view that needs a kernel
nb_mime_priority_overrides = [("html", "application/vnd.plotly.v1+json", None),
                              ("html", "application/vnd.jupyter.widget-view+json", None)]
suppress_warnings = ["mystnb.unknown_mime_type", "myst.header"]

# ---------------------------------------------------------------- math, offline
# MathJax 2: myst marks the page body tex2jax_ignore and every equation with the class
# "math"; MathJax processes those (and notebook outputs) only.  myst's MathJax 3 settings
# are off: they would overwrite these.
mathjax_path = lessonpages.MATHJAX_URL
myst_update_mathjax = False
mathjax2_config = {"tex2jax": {
    "inlineMath": [["\\(", "\\)"]], "displayMath": [["\\[", "\\]"]],
    "processEscapes": True, "ignoreClass": "tex2jax_ignore|mathjax_ignore",
    "processClass": "tex2jax_process|mathjax_process|math|output_area"}}

# ---------------------------------------------------------------- HTML
html_theme = "pydata_sphinx_theme"
html_title = f"cshape {version}"
html_static_path = ["_static"]
html_css_files = ["cshape.css"]
html_last_updated_fmt = None
html_show_sourcelink = False
html_copy_source = False
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "navbar_align": "left",
    "secondary_sidebar_items": ["page-toc"],
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
    "check_switcher": False,
}
html_context = {"default_mode": "light"}
