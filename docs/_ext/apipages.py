"""The API reference's pages, written from the package's ``__all__`` lists at build time.

One section per public module (the core ``cshape`` and the layers); each public function and
class gets its own page (autosummary), each public constant is described on its section's
page.  The lists come from ``__all__``, so a name another developer adds appears by itself;
an object exported twice (``cshape.describe`` is ``cshape.batch.describe``) is documented
once, where its layer puts it, and listed as a link in the other section.
"""

from __future__ import annotations

import importlib
import inspect
from dataclasses import dataclass, field
from pathlib import Path

#: (module, title, what it is); the order of the API index.
SECTIONS = [
    ("cshape", "Core: the method", "The pipeline, one module per stage: mesh and file "
     "reading, FEM matrices (Eq. 4-7), eigenvalues (Eq. 3), descriptors (Eq. 8-10), "
     "distances, retrieval and the nearest-neighbour index, per-point signatures."),
    ("cshape.mesh", "Core: meshes", "The mesh container, repair, pieces, and the mesh "
     "objects of other libraries."),
    ("cshape.spectrum", "Core: the spectrum", "Eigenvalues and eigenpairs of "
     "``A f = -lam B f`` (Eq. 3)."),
    ("cshape.descriptors", "Core: descriptors", "The paper's formulas (Eq. 8-10) and their "
     "variants, and the descriptor recipe."),
    ("cshape.compare", "Core: distances and retrieval", "Distance matrices, the [0, 255] "
     "scale, retrieval scores, nearest neighbours, MDS."),
    ("cshape.signatures", "Core: per-point signatures", "Heat and wave kernel signatures "
     "of an eigenbasis, and matching points by them."),
    ("cshape.maps", "Core: maps between shapes", "Functional maps, ZoomOut, and point maps."),
    ("cshape.geodesics", "Core: geodesics", "Geodesic distances by the heat method, and "
     "the geodesic error of a map."),
    ("cshape.shapes", "Analytic test shapes", "Meshes built in code, with known spectra."),
    ("cshape.batch", "Batch runs", "Describe a whole collection into a table: cached, "
     "resumable, in local processes or on a Dask cluster."),
    ("cshape.data", "Data: collections and the manifest", "The data manifest, "
     "generated and downloaded collections, folders of your own meshes."),
    ("cshape.data.variants", "Data: PyMeshLab variants", "Marching cubes, remeshing, "
     "subdivision, noise along normals (Section 3.3)."),
    ("cshape.data.bodies", "Data: articulated bodies", "Figures made of capsules, meshed in "
     "any pose (the isometry test's shapes)."),
    ("cshape.data.quality", "Data: mesh quality", "Triangle angles and the quality summary "
     "of a mesh (Section 3)."),
    ("cshape.data.poses", "Data: posed figures", "Articulated figures in poses, with the "
     "true vertex map between them (for maps)."),
    ("cshape.data.creatures", "Data: creatures", "The creature benchmark's shapes, made in "
     "code."),
    ("cshape.data.suite", "Data: the generated suite", "Bodies in poses made in code, the "
     "identity benchmark's members (the capstone's collection)."),
    ("cshape.plots", "Plots: figures and the 3-D viewer", "The lessons' matplotlib figures "
     "and the plotly 3-D views (extra ``cshape[plots]``)."),
    ("cshape.plots.widgets", "Plots: widgets", "The M-sweep widget over pure functions."),
    ("cshape.reproduce", "Reproduce the paper", "Section 3's experiments and the retrieval "
     "tables, as a report."),
    ("cshape.course.lessons", "Course: running the lessons", "Execute the walkthrough "
     "notebooks into executed notebooks and offline HTML."),
    ("cshape.course.assignments", "Course: nbgrader assignments", "The student release "
     "and a course folder."),
    ("cshape.course.teaching", "Course: teaching helpers", "What the lessons import."),
]


#: The layers on top of the core: a name they define is documented in their section.
LAYERS = ("cshape.batch", "cshape.data", "cshape.plots", "cshape.course", "cshape.reproduce",
          "cshape.cli")


@dataclass
class Section:
    module: str
    title: str
    blurb: str
    pages: list = field(default_factory=list)      # names documented here, one page each
    constants: list = field(default_factory=list)  # names described on the section page
    links: list = field(default_factory=list)      # (name, where it is documented)
    modules: list = field(default_factory=list)    # public submodules listed in __all__


def _kind(obj) -> str:
    if inspect.ismodule(obj):
        return "module"
    if inspect.isclass(obj) or inspect.isfunction(obj) or inspect.isbuiltin(obj):
        return "page"
    return "constant"


def collect() -> list[Section]:
    """Every section with its names, each object documented once."""
    sections = [Section(*s) for s in SECTIONS]
    # an object listed by several modules is documented by the one that defines it (the
    # longest section name that its __module__ starts with), else by the first listing it
    listed: dict[int, list[str]] = {}
    objects: dict[int, object] = {}
    for sec in sections:
        mod = importlib.import_module(sec.module)
        for name in getattr(mod, "__all__", []):
            obj = getattr(mod, name)
            if _kind(obj) == "page":
                listed.setdefault(id(obj), []).append(f"{sec.module}.{name}")
                objects[id(obj)] = obj
    # an entry point of the core that the top level exports (cshape.shape_dna) is documented
    # there, under the name users write; its stage module's section links to it
    owner: dict[int, str] = {}
    for key, names in listed.items():
        defined = getattr(objects[key], "__module__", "") or ""
        top = [n for n in names if n.rsplit(".", 1)[0] == "cshape"]
        if top and not defined.startswith(LAYERS):
            owner[key] = top[0]
            continue
        fits = [n for n in names if defined == n.rsplit(".", 1)[0]
                or defined.startswith(n.rsplit(".", 1)[0] + ".")]
        owner[key] = max(fits, key=lambda n: len(n.rsplit(".", 1)[0])) if fits else names[0]
    for sec in sections:
        mod = importlib.import_module(sec.module)
        for name in getattr(mod, "__all__", []):
            obj = getattr(mod, name)
            kind = _kind(obj)
            full = f"{sec.module}.{name}"
            if kind == "module":
                sec.modules.append((name, obj.__name__))
            elif kind == "constant":
                sec.constants.append(name)
            elif owner.get(id(obj)) == full:
                sec.pages.append(name)
            else:
                sec.links.append((name, owner[id(obj)]))
    return sections


def _page_name(module: str) -> str:
    return module.replace(".", "-")


def write(out: Path) -> dict[str, str]:
    """Write ``out/<section>.rst`` for every section; returns {public name: page path}."""
    out.mkdir(parents=True, exist_ok=True)
    pages: dict[str, str] = {}
    sections = collect()
    section_page = {s.module: _page_name(s.module) for s in sections}
    for sec in sections:
        lines = [sec.title, "=" * len(sec.title), "", f".. module:: {sec.module}", "",
                 sec.blurb, ""]
        if sec.pages:
            lines += [f".. currentmodule:: {sec.module}", "", ".. autosummary::",
                      "   :toctree: generated/", "   :nosignatures:", ""]
            lines += [f"   {n}" for n in sorted(sec.pages, key=str.lower)]
            lines.append("")
            for n in sec.pages:
                pages[f"{sec.module}.{n}"] = f"api/generated/{sec.module}.{n}.html"
        if sec.links:
            lines += ["Also here", "---------", ""]
            for n, where in sorted(sec.links):
                lines.append(f"* ``{sec.module}.{n}`` is :obj:`{where}`.")
                pages[f"{sec.module}.{n}"] = f"api/generated/{where}.html"
            lines.append("")
        if sec.modules:
            lines += ["Submodules", "----------", ""]
            for n, real in sec.modules:
                target = section_page.get(real)
                lines.append(f"* ``{sec.module}.{n}``: :doc:`{target}`" if target
                             else f"* ``{sec.module}.{n}`` (``{real}``)")
                pages[f"{sec.module}.{n}"] = f"api/{target}.html" if target else ""
            lines.append("")
        if sec.constants:
            lines += ["Constants", "---------", ""]
            for n in sec.constants:
                lines += [f".. autodata:: {sec.module}.{n}", "   :no-value:", ""]
                pages[f"{sec.module}.{n}"] = f"api/{section_page[sec.module]}.html"
        _write_if_changed(out / f"{section_page[sec.module]}.rst", "\n".join(lines))
    index = ["API reference", "=============", "",
             "Every public function and class of cshape has a page; the sections follow the "
             "package: the core (the method, one module per stage, in pipeline order), then "
             "the layers on top.  Arrays are NumPy arrays, matrices SciPy sparse matrices; "
             "every function that takes a mesh also takes a pair ``(vertices, faces)``.", "",
             ".. toctree::", "   :maxdepth: 1", ""]
    index += [f"   {section_page[s.module]}" for s in sections]
    index += ["   cli"]
    write_cli(out)
    _write_if_changed(out / "index.rst", "\n".join(index) + "\n")
    _remove_stale(out, {section_page[s.module] for s in sections} | {"index", "cli"},
                  {f"{s.module}.{n}" for s in sections for n in s.pages})
    return pages


def _remove_stale(out: Path, sections: set[str], generated: set[str]) -> None:
    """Remove the pages of names and modules that are no longer public: autosummary would
    try to import them, and the build would fail on a name that moved."""
    for f in out.glob("*.rst"):
        if f.stem not in sections:
            f.unlink()
    for f in (out / "generated").glob("*.rst"):
        if f.stem not in generated:
            f.unlink()


def write_cli(out: Path) -> None:
    """``out/cli.rst``: the help of ``cshape`` and of every subcommand, from the parser itself."""
    import argparse
    import os

    from cshape.cli.registry import build_parser

    columns = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = "96"  # argparse wraps to the terminal: the same page everywhere
    try:
        parser = build_parser()
        text = _cli_text(parser, argparse)
    finally:
        if columns is None:
            os.environ.pop("COLUMNS", None)
        else:
            os.environ["COLUMNS"] = columns
    _write_if_changed(out / "cli.rst", text)


def _cli_text(parser, argparse) -> str:
    parser.prog = "cshape"
    lines = ["Command line", "============", "",
             "The ``cshape`` command (also ``python -m cshape``): its help and the help of every "
             "subcommand, as the installed version prints them.  Every expected failure ends in "
             "one line on stderr, ``cshape <command>: error: ...``, and exit status 2.", "",
             ".. code-block:: text", ""]
    lines += ["   " + ln for ln in parser.format_help().splitlines()] + [""]
    subs = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    for name, sub in (subs[0].choices.items() if subs else []):
        lines += [f"cshape {name}", "-" * len(f"cshape {name}"), "", ".. code-block:: text", ""]
        lines += ["   " + ln for ln in sub.format_help().splitlines()] + [""]
    return "\n".join(lines)


def _write_if_changed(path: Path, text: str) -> None:
    if not path.is_file() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")
