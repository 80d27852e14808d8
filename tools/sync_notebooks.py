"""Write each lesson ``notebooks/NN_topic.ipynb`` from its source ``notebooks/NN_topic.py``.

The ``.py`` files (jupytext percent format, ``# %%`` cells) are the one source of the lessons:
edit them, then run::

    python tools/sync_notebooks.py            # or: make notebooks
    python tools/sync_notebooks.py --check    # exit 1 and name the pairs that are out of sync

The ``.ipynb`` is generated: same cells, sources and cell metadata (nbgrader's included), the
notebook metadata of the ``.py`` header (kernelspec), stable cell ids ``NN-kk``, no outputs.
The check compares cell types, sources and metadata, not ids or timestamps, so a pair saved
together by JupyterLab's jupytext extension (``notebooks/jupytext.toml`` pairs them) is in
sync too.  A ``.ipynb`` without its ``.py`` (or the reverse) is reported.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import jupytext
import nbformat

NOTEBOOKS = Path(__file__).resolve().parent.parent / "notebooks"
#: Lesson sources are named ``NN_topic.py``.
PATTERN = "[0-9][0-9]_*.py"


def notebook_from_source(py) -> nbformat.NotebookNode:
    """The notebook of a percent-format lesson source: stable ids, no outputs, no jupytext keys."""
    py = Path(py)
    nb = jupytext.read(py, fmt="py:percent")
    nb.metadata.pop("jupytext", None)
    nb.nbformat, nb.nbformat_minor = 4, 5
    for k, cell in enumerate(nb.cells):
        cell["id"] = f"{py.stem[:2]}-{k:02d}"
        if cell.cell_type == "code":
            cell.outputs, cell.execution_count = [], None
    nbformat.validate(nb)
    return nb


def render(py) -> str:
    """The ``.ipynb`` text written for the lesson source ``py``."""
    text = nbformat.writes(notebook_from_source(py))
    return text if text.endswith("\n") else text + "\n"


def _content(nb):
    meta = {k: v for k, v in nb.metadata.items() if k != "jupytext"}
    cells = [(c.cell_type, c.source, dict(c.get("metadata", {}))) for c in nb.cells]
    return meta, cells


def out_of_sync(folder=NOTEBOOKS) -> list[str]:
    """Problems with the lesson pairs in ``folder``, one line each (empty when all agree).

    A pair agrees when the notebook metadata and every cell's type, source and metadata are
    equal; outputs, execution counts and cell ids are not compared.
    """
    folder = Path(folder)
    problems = []
    sources = {p.stem: p for p in folder.glob(PATTERN)}
    notebooks = {p.stem: p for p in folder.glob(PATTERN.replace(".py", ".ipynb"))}
    for stem in sorted(notebooks.keys() - sources.keys()):
        problems.append(f"{stem}.ipynb has no source {stem}.py (jupytext --to py:percent it)")
    for stem in sorted(sources.keys() - notebooks.keys()):
        problems.append(f"{stem}.py has no notebook {stem}.ipynb (run the sync)")
    for stem in sorted(sources.keys() & notebooks.keys()):
        want = _content(notebook_from_source(sources[stem]))
        have = _content(nbformat.read(notebooks[stem], as_version=4))
        if want[0] != have[0]:
            problems.append(f"{stem}: notebook metadata differs ({have[0]} != {want[0]})")
        elif len(want[1]) != len(have[1]):
            problems.append(
                f"{stem}: {len(have[1])} cells in the .ipynb, {len(want[1])} in the .py")
        else:
            for k, (w, h) in enumerate(zip(want[1], have[1], strict=True)):
                if w != h:
                    what = ("type" if w[0] != h[0] else "source" if w[1] != h[1] else "metadata")
                    problems.append(f"{stem}: cell {k} {what} differs")
                    break
    return problems


def sync(folder=NOTEBOOKS) -> list[Path]:
    """Rewrite every ``NN_*.ipynb`` whose text differs from its ``.py``; return those written."""
    written = []
    for py in sorted(Path(folder).glob(PATTERN)):
        ipynb, text = py.with_suffix(".ipynb"), render(py)
        if not ipynb.is_file() or ipynb.read_text(encoding="utf-8") != text:
            ipynb.write_text(text, encoding="utf-8")
            written.append(ipynb)
    return written


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--check", action="store_true",
                        help="write nothing; exit 1 naming the pairs that are out of sync")
    parser.add_argument("--folder", default=str(NOTEBOOKS), help="default: notebooks/")
    args = parser.parse_args(argv)
    if args.check:
        problems = out_of_sync(args.folder)
        for line in problems:
            print(line)
        print("out of sync: edit the .py and run `python tools/sync_notebooks.py`" if problems
              else "lesson notebooks agree with their .py sources")
        return 1 if problems else 0
    for path in sync(args.folder):
        print("wrote", path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
