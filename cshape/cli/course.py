"""``cshape notebooks``, ``cshape assignments`` and ``cshape lessons``: the course's commands.

The course layer (:mod:`cshape.course`) is imported when a command runs, so the command line
works without the ``notebooks`` and ``course`` extras until one of these is called.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import argparse

    _SubParsers = argparse._SubParsersAction[Any]  # of the command line's parser class


def _cmd_notebooks(args: argparse.Namespace) -> int:
    from ..course.lessons import default_notebook_dir, run_notebooks

    src = args.src
    if args.student:
        src = Path(default_notebook_dir() if src is None else src) / "student"
    out = args.out or ("out/notebooks/student" if args.student else "out/notebooks")
    results = run_notebooks(src, out, names=args.names or None, small=args.small,
                            timeout=args.timeout, html=not args.no_html,
                            stop_at_stub=args.student, n_jobs=args.jobs)
    return 0 if all(r.ok for r in results) else 1


def add_notebooks(sub: _SubParsers) -> None:
    """Register ``cshape notebooks``."""
    p = sub.add_parser(
        "notebooks",
        help="execute the walkthrough notebooks into an output folder (executed .ipynb + HTML)",
    )
    p.add_argument("names", nargs="*", help="notebooks to run, e.g. 01 03 (default: all)")
    p.add_argument("--src", default=None, help="notebook folder (default: the checkout's)")
    p.add_argument("--out", default=None, help="output folder (default: out/notebooks)")
    p.add_argument("--small", action="store_true",
                   help="small meshes and N (sets CSHAPE_SMALL=1 in the kernels)")
    p.add_argument("--student", action="store_true",
                   help="run notebooks/student/ instead, each up to its first exercise stub")
    p.add_argument("--no-html", action="store_true", help="write the executed .ipynb only")
    p.add_argument("--timeout", type=int, default=1200, help="seconds per cell (default 1200)")
    p.add_argument("--jobs", type=int, default=min(2, os.cpu_count() or 1),
                   help="lessons run at once, each on its own kernel (default: 2, or 1 on a "
                        "machine of one core)")
    p.set_defaults(func=_cmd_notebooks)


def _cmd_assignments(args: argparse.Namespace) -> int:
    from ..course.assignments import generate

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


def _installed(module: str) -> bool:
    import importlib.util

    return importlib.util.find_spec(module) is not None


def _cmd_lessons(args: argparse.Namespace) -> int:
    from ..course.assignments import ANSWERS, ASSIGNMENTS, copy_lessons

    if not _installed("nbformat"):
        raise ImportError('cshape lessons reads the notebooks with nbformat, which is not '
                          'installed: pip install "cshape[notebooks]" (or "cshape[course]" '
                          "to grade them with nbgrader too)")
    files = copy_lessons(args.dir)
    lessons = [f for f in files if f.parent == Path(".") and f.suffix == ".ipynb"]
    made = [name for name in ASSIGNMENTS
            if any(f.parts[:2] == ("source", name) for f in files)]
    keys = sum(f.parts[0] == ANSWERS for f in files)
    print(f"{len(lessons)} lessons, {sum(f.parts[0] == 'student' for f in files)} student "
          f"versions and an nbgrader course of {len(made)} assignments in {args.dir}:")
    for name in made:
        print(f"  source/{name}/: " + ", ".join(
            f.stem for f in files if f.parts[:2] == ("source", name)))
    if keys:
        print(f"answer keys for instructors (never released to students): {ANSWERS}/")
    lab = "" if _installed("jupyterlab") else ' (needs pip install "cshape[notebooks]")'
    print(f"open them: jupyter lab {args.dir}{lab}")
    print(f"{Path(args.dir) / 'README.md'} gives the course plan and walks the grading cycle: "
          "release, collect, autograde, feedback")
    first = made[0] if made else "week1"
    if _installed("nbgrader"):
        print(f"release the first week: cd {args.dir} && nbgrader generate_assignment {first}")
    else:
        print('release and grade them with nbgrader, which is not installed: pip install '
              f'"cshape[course]", then cd {args.dir} && nbgrader generate_assignment {first}')
    return 0


def add_assignments(sub: _SubParsers) -> None:
    """Register ``cshape assignments`` and ``cshape lessons`` on the CLI's sub-parsers."""
    p = sub.add_parser(
        "assignments",
        help="make the student versions of the graded lessons with nbgrader "
             "(into notebooks/student/)",
    )
    p.add_argument("--src", default=None, help="solution notebooks (default: the lessons)")
    p.add_argument("--dest", default=None, help="output folder (default: <src>/student)")
    p.add_argument("--check", action="store_true",
                   help="write nothing; exit 1 if the student notebooks are out of date")
    p.set_defaults(func=_cmd_assignments)
    q = sub.add_parser(
        "lessons",
        help="copy the lessons, their student versions, an nbgrader course (one assignment "
             "per week and the capstone) and the instructors' answer keys into DIR",
    )
    q.add_argument("dir", help="a new (or empty) folder")
    q.set_defaults(func=_cmd_lessons)
