"""Course-assignment versions of the notebooks, generated from the solution notebooks.

The notebooks in ``notebooks/`` are the tested source: they contain the solutions, marked the
way nbgrader marks them::

    def mass_matrix(V, F):
        ### BEGIN SOLUTION
        ...                      # the solution, run by the test suite
        ### END SOLUTION

    ### BEGIN HIDDEN TESTS
    check_close(...)             # extra checks the student does not see
    ### END HIDDEN TESTS

:func:`student_notebook` turns one notebook into the student version:

* code between ``### BEGIN SOLUTION`` and ``### END SOLUTION`` becomes
  ``raise NotImplementedError("...")`` at the marker's indentation;
* in markdown cells the region becomes *"YOUR ANSWER HERE"*;
* hidden-test regions are removed, and a cell left empty (or tagged ``hidden-tests``) is
  dropped;
* outputs and execution counts are cleared and a note at the top says the file is generated.

:func:`generate` writes the student versions of every notebook that has solution markers into
``notebooks/student/`` (committed, so that instructors and students can open them directly);
``check=True`` reports generated files that are out of date instead of writing (the test suite
does this).  Never edit the generated files by hand: edit the solution notebook and run
``python -m cshape assignments``.
"""

from __future__ import annotations

import copy
import re
from pathlib import Path

__all__ = [
    "BEGIN_SOLUTION",
    "END_SOLUTION",
    "BEGIN_HIDDEN",
    "END_HIDDEN",
    "STUB_MESSAGE",
    "add_assignments",
    "generate",
    "has_markers",
    "strip_regions",
    "student_notebook",
]

BEGIN_SOLUTION = "### BEGIN SOLUTION"
END_SOLUTION = "### END SOLUTION"
BEGIN_HIDDEN = "### BEGIN HIDDEN TESTS"
END_HIDDEN = "### END HIDDEN TESTS"
#: Cells with this tag are removed from the student version as a whole.
HIDDEN_TAG = "hidden-tests"
STUB_MESSAGE = "Exercise: replace this line with your solution"
MARKDOWN_ANSWER = "_YOUR ANSWER HERE_"

_NOTE = (
    "> **Student version**, generated from `../{source}` by `python -m cshape assignments`: "
    "do not edit it by hand. Fill in every cell that raises `NotImplementedError`, then run "
    "the check cell below it: it tells you what is wrong."
)


def _marker_re(marker):
    return re.compile(r"^([ \t]*)" + re.escape(marker) + r"[ \t]*$")


_RE = {m: _marker_re(m) for m in (BEGIN_SOLUTION, END_SOLUTION, BEGIN_HIDDEN, END_HIDDEN)}


def strip_regions(source, begin, end, replacement=None, *, where="cell"):
    """Replace every ``begin`` ... ``end`` region (marker lines included) of a cell's source.

    Parameters
    ----------
    source : str
        The cell source.
    begin, end : str
        Marker lines, e.g. :data:`BEGIN_SOLUTION` and :data:`END_SOLUTION`; each must stand
        alone on its line (indentation allowed).
    replacement : callable or None
        ``replacement(indent) -> str`` gives the line(s) put in place of each region; None
        removes the region.
    where : str
        Named in error messages (e.g. ``"01_fem_assembly.ipynb, cell 8"``).

    Returns
    -------
    str

    Raises
    ------
    ValueError
        For an unbalanced or nested pair of markers, naming ``where`` and the line.
    """
    out, inside, indent = [], False, ""
    b_re, e_re = _RE.get(begin, _marker_re(begin)), _RE.get(end, _marker_re(end))
    lines = source.split("\n")
    for k, line in enumerate(lines, start=1):
        mb, me = b_re.match(line), e_re.match(line)
        if mb:
            if inside:
                raise ValueError(f"{where}, line {k}: {begin!r} inside another {begin!r} region; "
                                 f"close the first with {end!r}")
            inside, indent = True, mb.group(1)
            continue
        if me:
            if not inside:
                raise ValueError(f"{where}, line {k}: {end!r} without a {begin!r} before it")
            inside = False
            if replacement is not None:
                out.append(replacement(indent))
            continue
        if not inside:
            out.append(line)
    if inside:
        raise ValueError(f"{where}: {begin!r} is never closed; add a {end!r} line")
    return "\n".join(out)


def has_markers(nb) -> bool:
    """Whether a notebook has any solution or hidden-test markers (or hidden-test tags)."""
    for cell in nb.cells:
        if HIDDEN_TAG in cell.get("metadata", {}).get("tags", []):
            return True
        if BEGIN_SOLUTION in cell.source or BEGIN_HIDDEN in cell.source:
            return True
    return False


def _is_empty(source) -> bool:
    return all(not ln.strip() or ln.strip().startswith("#") for ln in source.split("\n"))


def student_notebook(nb, *, source_name="the solution notebook"):
    """The student version of a solution notebook (a new notebook; ``nb`` is unchanged).

    Parameters
    ----------
    nb : nbformat.NotebookNode
        A version-4 notebook with ``### BEGIN SOLUTION`` / ``### END SOLUTION`` and
        ``### BEGIN HIDDEN TESTS`` / ``### END HIDDEN TESTS`` regions.
    source_name : str
        File name of the solution notebook, written in the generated note.

    Returns
    -------
    nbformat.NotebookNode

    Raises
    ------
    ValueError
        For unbalanced markers, naming the notebook and cell.
    """
    import nbformat

    out = copy.deepcopy(nb)
    cells = []
    for k, cell in enumerate(out.cells):
        where = f"{source_name}, cell {k}"
        if HIDDEN_TAG in cell.get("metadata", {}).get("tags", []):
            continue
        src = strip_regions(cell.source, BEGIN_HIDDEN, END_HIDDEN, where=where)
        if cell.cell_type == "code":
            src = strip_regions(
                src, BEGIN_SOLUTION, END_SOLUTION, where=where,
                replacement=lambda ind: f'{ind}raise NotImplementedError("{STUB_MESSAGE}")',
            )
            if cell.source.strip() and _is_empty(src):
                continue  # the cell held hidden tests only
            cell.outputs = []
            cell.execution_count = None
        else:
            src = strip_regions(src, BEGIN_SOLUTION, END_SOLUTION, where=where,
                                replacement=lambda ind: f"{ind}{MARKDOWN_ANSWER}")
        cell.source = src
        cells.append(cell)
    note = nbformat.v4.new_markdown_cell(_NOTE.format(source=source_name))
    note["id"] = "student-note"
    # after the title cell, so the notebook still opens with its title and learning goals
    out.cells = cells[:1] + [note] + cells[1:]
    return out


def _render(nb) -> str:
    import nbformat

    text = nbformat.writes(nb)
    return text if text.endswith("\n") else text + "\n"


def generate(src=None, dest=None, *, check=False) -> list[Path]:
    """Write the student versions of all notebooks with solution markers.

    Parameters
    ----------
    src : str or os.PathLike, optional
        Folder of the solution notebooks ``NN_*.ipynb`` (default: the checkout's
        ``notebooks/``).
    dest : str or os.PathLike, optional
        Output folder (default ``<src>/student``).  Student versions whose source has lost
        its markers or disappeared are deleted (not with ``check``).
    check : bool, default=False
        Write nothing; return the generated files that are missing, different from what
        would be generated, or stale.

    Returns
    -------
    list of pathlib.Path
        Files written (or, with ``check``, out of date).
    """
    import nbformat

    from .notebooks_run import PATTERN, default_notebook_dir

    src = Path(default_notebook_dir() if src is None else src)
    if not src.is_dir():
        raise FileNotFoundError(f"src folder {str(src)!r} does not exist; pass the notebooks/ "
                                "folder of the repository")
    dest = src / "student" if dest is None else Path(dest)
    wanted = {}
    for path in sorted(src.glob(PATTERN)):
        nb = nbformat.read(path, as_version=4)
        if has_markers(nb):
            wanted[dest / path.name] = _render(student_notebook(nb, source_name=path.name))
    existing = set(dest.glob(PATTERN)) if dest.is_dir() else set()
    changed = [p for p, text in wanted.items()
               if not p.is_file() or p.read_text(encoding="utf-8") != text]
    stale = sorted(existing - set(wanted))
    if check:
        return sorted(changed) + stale
    dest.mkdir(parents=True, exist_ok=True)
    for p in changed:
        p.write_text(wanted[p], encoding="utf-8")
    for p in stale:
        p.unlink()
    return sorted(changed)


def _cmd(args) -> int:
    paths = generate(args.src, args.dest, check=args.check)
    if args.check:
        if paths:
            print("out of date (run `python -m cshape assignments`):")
            for p in paths:
                print("  ", p)
            return 1
        print("student notebooks are up to date")
        return 0
    for p in paths:
        print("wrote", p)
    if not paths:
        print("student notebooks already up to date")
    return 0


def add_assignments(sub) -> None:
    """Register ``cshape assignments`` on the CLI's sub-parsers."""
    p = sub.add_parser(
        "assignments",
        help="generate the student versions of the notebooks (solutions -> stubs, hidden "
             "tests removed) into notebooks/student/",
    )
    p.add_argument("--src", default=None, help="solution notebooks (default: notebooks/)")
    p.add_argument("--dest", default=None, help="output folder (default: <src>/student)")
    p.add_argument("--check", action="store_true",
                   help="write nothing; exit 1 if the generated notebooks are out of date")
    p.set_defaults(func=_cmd)


if __name__ == "__main__":  # pragma: no cover
    import argparse
    import sys

    parser = argparse.ArgumentParser(prog="python -m cshape.assignments")
    add_assignments(parser.add_subparsers(dest="command", required=True))
    a = parser.parse_args(["assignments", *sys.argv[1:]])
    sys.exit(a.func(a))
