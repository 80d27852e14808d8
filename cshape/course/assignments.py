"""The course: nbgrader makes the student versions of the lessons; the lessons ship with cshape.

The lessons ``NN_topic.ipynb`` are the solutions.  Their graded exercises are real nbgrader
source cells (cell metadata ``nbgrader``: solution cells, autograder-test cells with points,
read-only cells, stable ``grade_id`` s) with nbgrader's text markers inside::

    def mass_matrix(V, F):            # solution cell
        ### BEGIN SOLUTION
        ...
        ### END SOLUTION

    check_close(...)                  # autograder-test cell, 1 point, locked
    ### BEGIN HIDDEN TESTS
    ...                               # run by the autograder, not shown to students
    ### END HIDDEN TESTS

The course plan :data:`ASSIGNMENTS` groups the lessons into nbgrader assignments, one per
week of a four-week module plus the capstone; every function here, the command line and the
instructors' README follow it.

nbgrader itself (the optional ``course`` extra: ``pip install "cshape[course]"``) makes the
student release; this module only lays out a course folder and calls it:

* :func:`write_course` writes an nbgrader course: ``nbgrader_config.py`` and
  ``source/<assignment>/`` with the lessons of each assignment of the plan;
* :func:`generate` runs ``nbgrader generate_assignment`` in a throwaway course and writes
  the release into ``notebooks/student/`` (``cshape assignments``, ``make assignments``);
  ``check=True`` reports what is out of date instead (the test suite does this);
* :func:`copy_lessons` copies the lessons, their student versions, a ready nbgrader
  course and, for instructors only, the answer keys ``answers/NN_topic.md`` into a folder,
  from an installed package as from a checkout (``cshape lessons``).
"""

from __future__ import annotations

import importlib.util
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

from .._files import atomic_write, umask

if TYPE_CHECKING:
    from collections.abc import Iterable

__all__ = [
    "ASSIGNMENTS",
    "copy_lessons",
    "generate",
    "plan",
    "write_course",
]

#: Notebooks are named ``NN_topic.ipynb``.
PATTERN = "[0-9][0-9]_*.ipynb"
#: The README of a course folder: what is in it and the nbgrader cycle, for instructors.
INSTRUCTORS_README = Path(__file__).with_name("instructors.md")
#: The course plan: nbgrader assignment -> the numbers ``NN`` of the lessons it holds, in the
#: order of a four-week module (the instructors' README gives the same weeks).
ASSIGNMENTS: dict[str, tuple[str, ...]] = {
    "week1": ("01", "02", "03"),      # the FEM matrices, the spectrum and Weyl, the DFT crop
    "week2": ("04", "05", "07"),      # distances, MDS and retrieval; noise; the M-sweep
    "week3": ("06", "08"),            # your own collection; beyond the paper
    "week4": ("09", "10"),            # signatures and correspondence; functional maps
    "capstone": ("11",),              # the whole pipeline, chosen on dev, reported on test
}
#: The instructors' answer keys of the open exercises, ``answers/NN_topic.md`` beside the
#: lessons: copied into a course folder's ``answers/``, never into a student release.
ANSWERS = "answers"
#: ``nbgrader_config.py`` of the course folders written here.
NBGRADER_CONFIG = """\
# nbgrader configuration of a cshape course (written by `cshape lessons`).
c = get_config()  # noqa: F821
c.CourseDirectory.course_id = "cshape"
# the lessons compute spectra: allow a cell up to 20 minutes (nbgrader's default is 30 s)
c.Execute.timeout = 1200
# cshape's grading options (cshape.course.grading): no "checksum has changed" warning for
# the hidden tests that the release left out, and feedback pages whose equations are
# typeset by the MathJax copy in this folder (mathjax/), with no network
from cshape.course.grading import configure  # noqa: E402

configure(c)
"""


def lessons_dir() -> Path:
    """The folder of the lessons ``NN_*.ipynb`` (with ``student/`` and ``README.md``).

    In an installed package that is the package data ``cshape/lessons``; in a source
    checkout (an editable install) it is the checkout's ``notebooks/``.
    """
    package = Path(__file__).resolve().parents[1]  # cshape/
    for folder in (package / "lessons", package.parent / "notebooks"):
        if any(folder.glob(PATTERN)):
            return folder
    raise FileNotFoundError(
        f"no lessons found in {str(package / 'lessons')!r}: reinstall cshape (pip install "
        "--force-reinstall cshape), or run from the repository's checkout"
    )


def is_graded(nb: Any) -> bool:
    """Whether a notebook (``nbformat`` node or path) has nbgrader cells."""
    if not hasattr(nb, "cells"):
        import nbformat

        nb = nbformat.read(nb, as_version=4)
    return any("nbgrader" in c.get("metadata", {}) for c in nb.cells)


def _nbgrader_env() -> dict[str, str]:
    """Environment for nbgrader: this interpreter's scripts first (nbgrader calls
    ``alembic``), so its kernels are this interpreter's too."""
    env = dict(os.environ)
    env["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), env.get("PATH", "")])
    return env


def run_nbgrader(*args: str, cwd: str | os.PathLike[str], env: dict[str, str] | None = None,
                 timeout: float = 3600) -> str:
    """Run ``python -m nbgrader ARGS`` in the course folder ``cwd``; return its log.

    Parameters
    ----------
    *args : str
        The nbgrader command, e.g. ``"generate_assignment", "lessons", "--force"``.
    cwd : str or os.PathLike
        The course folder (holding ``nbgrader_config.py``).
    env : dict, optional
        Extra environment variables (they reach the kernels, e.g. ``CSHAPE_SMALL``).
    timeout : float, default=3600
        Seconds for the whole command.

    Raises
    ------
    ImportError
        When nbgrader is not installed (``pip install "cshape[course]"``).
    RuntimeError
        When nbgrader fails; the message ends with nbgrader's error line.
    """
    if importlib.util.find_spec("nbgrader") is None:  # without importing it (seconds)
        raise ImportError(
            'nbgrader is not installed; it makes the student versions: pip install "cshape[course]"'
        )
    full_env = _nbgrader_env()
    full_env.update(env or {})
    r = subprocess.run([sys.executable, "-m", "nbgrader", *args], cwd=str(cwd), env=full_env,
                       capture_output=True, text=True, timeout=timeout)
    log = r.stdout + r.stderr
    if r.returncode != 0 or "[ERROR]" in log or "| ERROR]" in log:
        lines = log.strip().splitlines()
        errors = [ln.strip() for ln in lines if re.match(r"\s*\w+(Error|Exception): ", ln)]
        why = errors[-1] if errors else " / ".join(ln.strip() for ln in lines[-5:])
        raise RuntimeError(f"nbgrader {' '.join(args)} failed in {str(cwd)!r}: {why}")
    return log


def plan(lessons: Iterable[str | os.PathLike[str]]) -> dict[str, list[Path]]:
    """Group lesson files by the assignment of :data:`ASSIGNMENTS` that holds them.

    Parameters
    ----------
    lessons : iterable of path
        Notebooks named ``NN_topic.ipynb``.

    Returns
    -------
    dict
        Assignment name -> its lessons, sorted, in the plan's order; assignments without any
        of ``lessons`` are left out.

    Raises
    ------
    ValueError
        If a lesson's number is in no assignment of the plan.
    """
    number = {nn: name for name, nns in ASSIGNMENTS.items() for nn in nns}
    out: dict[str, list[Path]] = {name: [] for name in ASSIGNMENTS}
    for path in sorted(Path(p) for p in lessons):
        nn = path.name[:2]
        if nn not in number:
            raise ValueError(
                f"lesson {path.name!r} is in no assignment of the course plan "
                f"{ {k: list(v) for k, v in ASSIGNMENTS.items()} }: add its number {nn!r} to "
                "cshape.course.assignments.ASSIGNMENTS"
            )
        out[number[nn]].append(path)
    return {name: paths for name, paths in out.items() if paths}


def write_course(dest: str | os.PathLike[str], lessons: Iterable[str | os.PathLike[str]]
                 ) -> dict[str, list[Path]]:
    """Lay out an nbgrader course folder: ``nbgrader_config.py`` and ``source/<assignment>/``.

    Each lesson goes into the assignment of the course plan :data:`ASSIGNMENTS` that holds
    its number.

    Parameters
    ----------
    dest : str or os.PathLike
        The course folder (created; existing files of the same names are replaced).
    lessons : iterable of path
        The solution notebooks to put in the course.

    Returns
    -------
    dict
        Assignment name -> the lessons in its source folder (:func:`plan`).

    Raises
    ------
    ValueError
        See :func:`plan`.
    """
    dest = Path(dest)
    groups = plan(lessons)
    dest.mkdir(parents=True, exist_ok=True)
    atomic_write(dest / "nbgrader_config.py", lambda f: f.write(NBGRADER_CONFIG),
                 binary=False)
    for assignment, paths in groups.items():
        source = dest / "source" / assignment
        source.mkdir(parents=True, exist_ok=True)
        for path in paths:
            shutil.copyfile(path, source / path.name)
    return groups


def _render(path: str | os.PathLike[str]) -> str:
    import nbformat

    text = nbformat.writes(nbformat.read(path, as_version=4))
    return text if text.endswith("\n") else text + "\n"


def release_notebooks(src: str | os.PathLike[str] | None = None) -> dict[str, str]:
    """nbgrader's student release of the graded lessons in ``src``: file name -> notebook text.

    Runs ``nbgrader generate_assignment --no-db`` once, for every assignment of the course
    plan, in a throwaway course folder.
    ``src`` defaults to :func:`lessons_dir`; lessons without nbgrader cells are left out.

    Raises
    ------
    FileNotFoundError
        If ``src`` does not exist.
    ImportError, RuntimeError
        See :func:`run_nbgrader`.
    """
    src = lessons_dir() if src is None else Path(src)
    if not src.is_dir():
        raise FileNotFoundError(f"src folder {str(src)!r} does not exist; pass the notebooks/ "
                                "folder of the repository")
    graded = [p for p in sorted(src.glob(PATTERN)) if is_graded(p)]
    if not graded:
        return {}
    with tempfile.TemporaryDirectory(prefix="cshape-course-") as tmp:
        groups = write_course(tmp, graded)
        run_nbgrader("generate_assignment", "*", "--force", "--no-db", cwd=tmp)
        return {p.name: _render(Path(tmp) / "release" / assignment / p.name)
                for assignment, paths in groups.items() for p in paths}


def update_folder(wanted: dict[str, str], dest: str | os.PathLike[str], *, check: bool = False
                  ) -> list[Path]:
    """Make the ``NN_*.ipynb`` files of ``dest`` exactly ``wanted`` (file name -> text).

    Writes the files that are missing or differ and deletes the other ``NN_*.ipynb``; with
    ``check`` writes nothing and returns those files instead.  Returns the paths written
    (or, with ``check``, out of date), sorted; stale ones last.
    """
    dest = Path(dest)
    wanted = {dest / name: text for name, text in wanted.items()}
    existing = set(dest.glob(PATTERN)) if dest.is_dir() else set()
    changed = [p for p, text in wanted.items()
               if not p.is_file() or p.read_text(encoding="utf-8") != text]
    stale = sorted(existing - set(wanted))
    if check:
        return sorted(changed) + stale
    dest.mkdir(parents=True, exist_ok=True)
    for p in changed:
        def write(f: IO[Any], text: str = wanted[p]) -> None:
            f.write(text)

        atomic_write(p, write, binary=False)
    for p in stale:
        p.unlink()
    return sorted(changed)


def generate(src: str | os.PathLike[str] | None = None, dest: str | os.PathLike[str] | None = None,
             *, check: bool = False) -> list[Path]:
    """Make the student versions of the graded lessons with nbgrader, into ``dest``.

    Parameters
    ----------
    src : str or os.PathLike, optional
        Folder of the solution notebooks ``NN_*.ipynb`` (default :func:`lessons_dir`).
    dest : str or os.PathLike, optional
        Output folder (default ``<src>/student``).  Student versions whose lesson has no
        graded cells any more, or is gone, are deleted (not with ``check``).
    check : bool, default=False
        Write nothing; return the student versions that are missing, different from
        nbgrader's release, or stale.

    Returns
    -------
    list of pathlib.Path
        Files written (or, with ``check``, out of date).

    Raises
    ------
    FileNotFoundError, ImportError, RuntimeError
        See :func:`release_notebooks`.
    """
    src = lessons_dir() if src is None else Path(src)
    wanted = release_notebooks(src)
    return update_folder(wanted, src / "student" if dest is None else dest, check=check)


def copy_lessons(dest: str | os.PathLike[str], *, src: str | os.PathLike[str] | None = None
                 ) -> list[Path]:
    """Copy the lessons, their student versions, an nbgrader course and the answer keys.

    ``dest`` gets ``README.md`` (for instructors: the folder, the course plan, the lessons
    and the nbgrader cycle, from :data:`INSTRUCTORS_README`), the lessons ``NN_*.ipynb``
    (they run there: they need only an installed cshape), ``student/NN_*.ipynb``, the
    answer keys of the open exercises ``answers/*.md`` (for instructors: no nbgrader command
    releases them) and, for ``nbgrader``, ``nbgrader_config.py`` with the lessons in
    ``source/<assignment>/``, one folder per assignment of :data:`ASSIGNMENTS`.  Everything is
    written to a temporary folder beside ``dest`` first and moved into place at the end, so
    a failure leaves no half-written folder.

    Parameters
    ----------
    dest : str or os.PathLike
        A folder that does not exist yet, or an empty one.
    src : str or os.PathLike, optional
        Folder of the lessons (default :func:`lessons_dir`).

    Returns
    -------
    list of pathlib.Path
        The files written, relative to ``dest``.

    Raises
    ------
    FileExistsError
        If ``dest`` exists and is not an empty folder.
    """
    dest = Path(dest)
    if dest.exists() and (not dest.is_dir() or any(dest.iterdir())):
        raise FileExistsError(f"dest {str(dest)!r} already exists and is not an empty folder; "
                              "choose a new folder")
    src = lessons_dir() if src is None else Path(src)
    lessons = sorted(src.glob(PATTERN))
    dest.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{dest.name}-", dir=dest.parent))
    try:
        for path in lessons:
            shutil.copyfile(path, tmp / path.name)
        shutil.copyfile(INSTRUCTORS_README, tmp / "README.md")
        student = sorted((src / "student").glob(PATTERN))
        if student:
            (tmp / "student").mkdir()
            for path in student:
                shutil.copyfile(path, tmp / "student" / path.name)
        answers = sorted((src / ANSWERS).glob("*.md"))
        if answers:
            (tmp / ANSWERS).mkdir()
            for path in answers:
                shutil.copyfile(path, tmp / ANSWERS / path.name)
        write_course(tmp, lessons)
        if dest.exists():
            dest.rmdir()
        os.chmod(tmp, 0o777 & ~umask())  # mkdtemp makes 0700
        tmp.rename(dest)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return sorted(p.relative_to(dest) for p in dest.rglob("*") if p.is_file())
