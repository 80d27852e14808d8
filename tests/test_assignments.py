"""The course: nbgrader source notebooks, nbgrader's student release, the course plan, the full
grading cycle (and the feedback on typical wrong answers), and the lessons copied out of cshape
by ``cshape lessons``."""

from __future__ import annotations

import ast
import html
import json
import re
import shutil
import sys

import nbformat
import pytest

from cshape.cli import main
from cshape.course import assignments as asg
from cshape.course.lessons import stderr_outputs

NB_DIR = asg.lessons_dir()
LESSONS = sorted(NB_DIR.glob(asg.PATTERN))
GRADED = [p for p in LESSONS if asg.is_graded(p)]
ANSWERS = sorted((NB_DIR / asg.ANSWERS).glob("*.md"))
CAPSTONE = NB_DIR / "11_capstone.ipynb"


def _nbgrader_cells(path):
    nb = nbformat.read(path, as_version=4)
    return nb, [(k, c, c.metadata["nbgrader"]) for k, c in enumerate(nb.cells)
                if "nbgrader" in c.metadata]


@pytest.mark.parametrize("stem", ["01_fem", "02_shape", "03_dft", "04_mds", "05_noise"])
def test_lessons_1_to_5_have_a_graded_exercise_with_hidden_tests(stem):
    (path,) = [p for p in LESSONS if p.name.startswith(stem)]
    _, cells = _nbgrader_cells(path)
    solutions = [c for _, c, m in cells if m["solution"]]
    tests = [(c, m) for _, c, m in cells if m["grade"] and not m["solution"]]
    assert solutions and tests, f"{path.name}: no nbgrader solution and test cells"
    assert any("### BEGIN HIDDEN TESTS" in c.source for c, _ in tests), path.name
    assert any("hint" in c.source for c, _ in tests), f"{path.name}: visible checks give hints"


@pytest.mark.parametrize("path", GRADED, ids=lambda p: p.stem)
def test_graded_cells_carry_valid_nbgrader_metadata(path):
    """What nbgrader needs: markers only in cells of the right kind, unique stable grade_ids,
    points on test cells, test cells locked."""
    nb, cells = _nbgrader_cells(path)
    ids = [m["grade_id"] for _, _, m in cells]
    assert len(ids) == len(set(ids)), f"{path.name}: duplicate grade_id in {ids}"
    for k, _, m in cells:
        assert m["schema_version"] == 3 and m["grade_id"].isidentifier(), (path.name, k)
        if m["grade"]:
            assert m.get("points", 0) > 0, f"{path.name} cell {k}: a graded cell needs points"
        if m["grade"] and not m["solution"]:
            assert m["locked"], f"{path.name} cell {k}: autograder tests are locked"
    for k, c in enumerate(nb.cells):
        m = c.metadata.get("nbgrader", {})
        if "### BEGIN SOLUTION" in c.source:
            assert m.get("solution"), f"{path.name} cell {k}: solution region, no solution cell"
        if "### BEGIN HIDDEN TESTS" in c.source:
            assert m.get("grade") and not m.get("solution"), (
                f"{path.name} cell {k}: hidden tests belong in an autograder-test cell")


def test_course_plan_puts_every_lesson_in_one_assignment():
    """At least four weekly assignments and the capstone, every lesson in exactly one, every
    assignment with a graded lesson."""
    assert len(asg.ASSIGNMENTS) >= 5 and list(asg.ASSIGNMENTS)[-1] == "capstone"
    numbers = [nn for nns in asg.ASSIGNMENTS.values() for nn in nns]
    assert len(numbers) == len(set(numbers)), asg.ASSIGNMENTS
    groups = asg.plan(LESSONS)
    assert sorted(p for paths in groups.values() for p in paths) == LESSONS
    assert list(groups) == list(asg.ASSIGNMENTS)  # no assignment without a lesson
    assert groups["capstone"] == [CAPSTONE]
    for name, paths in groups.items():
        assert any(asg.is_graded(p) for p in paths), f"{name}: no graded lesson"
        assert all(p.name[:2] in asg.ASSIGNMENTS[name] for p in paths)


def test_plan_names_a_lesson_outside_it(tmp_path):
    with pytest.raises(ValueError, match=r"'12_extra.ipynb' is in no assignment.*ASSIGNMENTS"):
        asg.plan([tmp_path / "01_a.ipynb", tmp_path / "12_extra.ipynb"])
    assert asg.plan([tmp_path / "03_b.ipynb", tmp_path / "01_a.ipynb"]) == {
        "week1": [tmp_path / "01_a.ipynb", tmp_path / "03_b.ipynb"]}


def test_capstone_is_graded_beyond_the_walkthroughs():
    """The capstone: at least 10 auto-graded points in several graded cells, hidden tests,
    and a written answer graded by hand."""
    _, cells = _nbgrader_cells(CAPSTONE)
    auto = [m for _, c, m in cells if m["grade"] and not m["solution"]]
    manual = [(c, m) for _, c, m in cells if m["grade"] and m["solution"]]
    assert sum(m["points"] for m in auto) >= 10 and len(auto) >= 4, auto
    assert any(c.cell_type == "markdown" for c, _ in manual), "a written answer graded by hand"
    tests = [c.source for _, c, m in cells if m["grade"] and not m["solution"]]
    assert sum("### BEGIN HIDDEN TESTS" in t for t in tests) >= 4


@pytest.fixture(scope="module")
def released():
    """nbgrader's release of the committed lessons (one nbgrader run for the module)."""
    pytest.importorskip("nbgrader", reason="the course extra: pip install 'cshape[course]'")
    return asg.release_notebooks()


@pytest.mark.slow
def test_committed_student_notebooks_are_nbgraders_release(released):
    assert sorted(released) == [p.name for p in GRADED]
    stale = asg.update_folder(released, NB_DIR / "student", check=True)
    assert stale == [], (
        f"student notebooks out of date: {[p.name for p in stale]}; run `make assignments` "
        "and commit notebooks/student/"
    )
    for path in GRADED:
        student = (NB_DIR / "student" / path.name).read_text()
        assert "### BEGIN SOLUTION" not in student and "### BEGIN HIDDEN TESTS" not in student
        assert "raise NotImplementedError()" in student


def test_update_folder_writes_checks_and_removes_stale(tmp_path):
    dest = tmp_path / "student"
    want = {"01_a.ipynb": "A\n", "02_b.ipynb": "B\n"}
    assert asg.update_folder(want, dest, check=True) == [dest / "01_a.ipynb", dest / "02_b.ipynb"]
    assert not dest.exists()  # check writes nothing
    assert asg.update_folder(want, dest) == [dest / "01_a.ipynb", dest / "02_b.ipynb"]
    assert asg.update_folder(want, dest, check=True) == []
    assert asg.update_folder(want, dest) == []  # nothing changed, nothing written
    (dest / "01_a.ipynb").write_text("A\n ")  # a hand edit
    (dest / "03_c.ipynb").write_text("C\n")  # its lesson is gone
    assert asg.update_folder(want, dest, check=True) == [dest / "01_a.ipynb", dest / "03_c.ipynb"]
    assert asg.update_folder(want, dest) == [dest / "01_a.ipynb"]
    assert sorted(p.name for p in dest.iterdir()) == ["01_a.ipynb", "02_b.ipynb"]
    assert (dest / "01_a.ipynb").read_text() == "A\n"


@pytest.mark.slow
def test_generate_releases_only_graded_lessons(tmp_path):
    pytest.importorskip("nbgrader", reason="the course extra: pip install 'cshape[course]'")
    src = tmp_path / "nb"
    src.mkdir()
    shutil.copyfile(NB_DIR / "03_dft_compression.ipynb", src / "03_dft_compression.ipynb")
    nb = nbformat.v4.new_notebook()
    nb.cells.append(nbformat.v4.new_code_cell("1 + 1"))
    nbformat.write(nb, src / "09_plain.ipynb")  # no nbgrader cells: no student version
    dest = src / "student"
    assert asg.generate(src) == [dest / "03_dft_compression.ipynb"]
    assert sorted(p.name for p in dest.iterdir()) == ["03_dft_compression.ipynb"]
    assert ((dest / "03_dft_compression.ipynb").read_text()
            == (NB_DIR / "student" / "03_dft_compression.ipynb").read_text())


@pytest.mark.slow
def test_nbgrader_refuses_markers_outside_nbgrader_cells(tmp_path):
    """The failure of issue 12 stays caught: a solution region without metadata."""
    pytest.importorskip("nbgrader", reason="the course extra: pip install 'cshape[course]'")
    nb = nbformat.read(NB_DIR / "03_dft_compression.ipynb", as_version=4)
    for c in nb.cells:
        if "### BEGIN SOLUTION" in c.source:
            del c.metadata["nbgrader"]
            break
    src = tmp_path / "nb"
    src.mkdir()
    nbformat.write(nb, src / "03_dft_compression.ipynb")
    why = "generate_assignment.*failed.*Solution region detected in a non-solution cell"
    with pytest.raises(RuntimeError, match=why):
        asg.generate(src, check=True)


def test_generate_names_a_missing_folder(tmp_path):
    with pytest.raises(FileNotFoundError, match="does not exist"):
        asg.generate(tmp_path / "nope")


def test_cli_check(tmp_path, capsys):
    nb = nbformat.v4.new_notebook()
    nb.cells.append(nbformat.v4.new_code_cell("1 + 1"))
    nbformat.write(nb, tmp_path / "01_plain.ipynb")
    assert main(["assignments", "--check", "--src", str(tmp_path)]) == 0
    assert "up to date" in capsys.readouterr().out
    (tmp_path / "student").mkdir()
    (tmp_path / "student" / "01_plain.ipynb").write_text("{}")  # stale: nothing to grade
    assert main(["assignments", "--check", "--src", str(tmp_path)]) == 1
    assert "out of date" in capsys.readouterr().out
    assert main(["assignments", "--src", str(tmp_path / "nope")]) == 2
    assert "does not exist" in capsys.readouterr().err


def _hint(path, grade_id, word):
    """The hint of a test cell: the string literal of its source that holds ``word``."""
    nb = nbformat.read(path, as_version=4)
    (cell,) = [c for c in nb.cells if c.metadata.get("nbgrader", {}).get("grade_id") == grade_id]
    texts = [n.value for n in ast.walk(ast.parse(cell.source))
             if isinstance(n, ast.Constant) and isinstance(n.value, str) and word in n.value]
    assert texts, f"{path.name}: the test cell {grade_id} has no hint naming {word!r}"
    return texts[0]


def _page_text(page):
    """The text of an HTML page, tags removed and entities decoded."""
    return html.unescape(re.sub(r"<[^>]+>", "", page.read_text(encoding="utf-8")))


def _typical_wrong_capstone(release, source):
    """The capstone's release filled with the instructor's answers, except two typical
    mistakes: the lumped mass in ``spectra`` and a prediction of one over the classes."""
    nb = nbformat.read(release, as_version=4)
    solutions = {c.metadata["nbgrader"]["grade_id"]: c.source
                 for c in nbformat.read(source, as_version=4).cells
                 if c.metadata.get("nbgrader", {}).get("solution")}
    for c in nb.cells:
        gid = c.metadata.get("nbgrader", {}).get("grade_id")
        if gid in solutions and c.cell_type == "code":
            c.source = "\n".join(ln for ln in solutions[gid].splitlines()
                                  if not re.match(r"\s*### (BEGIN|END) SOLUTION", ln))
        if gid == "spectra":
            c.source = c.source.replace("cshape.shape_dna(m, N)",
                                        "cshape.shape_dna(m, N, mass='lumped')")
            assert "mass='lumped'" in c.source
        if gid == "prediction":
            c.source = "prediction = 1 / len(set(dev_labels))  # one class in so many"
    return nb


def _releases_stop_at_their_stubs(paths, env):
    """Run each untouched release of ``paths`` the way a student does, cell after cell, until a
    cell raises; return ``{name: (cell number, error name)}`` of the first error of each
    (``None`` when every cell ran).

    The releases take turns in one kernel (``CSHAPE_SMALL=1``), each after ``%reset -f`` in
    its own folder: its names are its own, and the kernel's start and imports are paid once.
    """
    from cshape.course.lessons import _kernel_env, kernel_manager

    km = kernel_manager()
    km.start_kernel(env=_kernel_env(small=True, env=env))  # as run_notebook's kernels
    kc = km.client()
    kc.start_channels()

    def run(code):
        reply = kc.execute_interactive(code, timeout=600, output_hook=lambda msg: None,
                                       store_history=False)
        return None if reply["content"]["status"] == "ok" else reply["content"]["ename"]

    first = {}
    try:
        kc.wait_for_ready(timeout=120)
        for path in paths:
            assert run(f"%reset -f\nimport os\nos.chdir({str(path.parent)!r})") is None
            cells = nbformat.read(path, as_version=4).cells
            first[path.name] = next(((k, e) for k, c in enumerate(cells)
                                     if c.cell_type == "code" and (e := run(c.source))), None)
    finally:
        kc.stop_channels()
        km.shutdown_kernel(now=True)
    return first


@pytest.mark.slow
def test_nbgrader_course_full_cycle(tmp_path):
    """The whole course, as an instructor runs it: ``generate_assignment`` and ``autograde``
    of every assignment of the plan in one course folder.  The instructor's solutions get full
    marks on every auto-graded cell and run without an error or a warning box anywhere, and a
    student who runs an untouched release meets the first exercise's stub before any other
    error.  The capstone's cycle goes on to the feedback (``generate_feedback`` is the same
    command for every assignment): typical wrong answers get feedback that names the mistake
    (the hint of the lesson's own test cell), with the equations typeset offline.  (How
    nbgrader grades an untouched release and an edited locked cell:
    ``test_nbgrader_grades_a_small_assignment``.)"""
    pytest.importorskip("nbgrader", reason="the course extra: pip install 'cshape[course]'")
    from nbgrader.api import Gradebook

    course = tmp_path / "course"
    groups = asg.write_course(course, GRADED)
    assert list(groups) == list(asg.ASSIGNMENTS)
    asg.run_nbgrader("generate_assignment", "*", "--force", cwd=course)
    for name, paths in groups.items():
        release = course / "release" / name
        assert sorted(p.name for p in release.iterdir()) == [p.name for p in paths], name
        shutil.copytree(course / "source" / name, course / "submitted" / "instructor" / name)
    typical = course / "submitted" / "typical" / "capstone"
    typical.mkdir(parents=True)
    nbformat.write(_typical_wrong_capstone(course / "release" / "capstone" / CAPSTONE.name,
                                           CAPSTONE), typical / CAPSTONE.name)
    # the kernels' temporary folder, to see what they leave behind: this autograde is also
    # the lessons' run (tests/test_notebooks.py), in the environment an instructor grades in,
    # with one cache, as one instructor's machine has it
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    env = {"CSHAPE_CACHE": str(tmp_path / "cache"), "TMPDIR": str(tmp)}
    log = asg.run_nbgrader("autograde", "*", "--force", cwd=course,
                           env={"CSHAPE_SMALL": "1", **env})
    left = sorted(p.name for p in tmp.iterdir() if p.name.startswith("cshape"))
    assert left == [], f"the lessons leave temporary folders behind: {left}"
    # the solutions changed no locked cell
    assert "has changed!" not in log, [ln for ln in log.splitlines() if "changed!" in ln]
    asg.run_nbgrader("generate_feedback", "capstone", "--force", cwd=course)

    manual = {m["grade_id"] for p in GRADED for _, _, m in _nbgrader_cells(p)[1]
              if m["grade"] and m["solution"]}
    with Gradebook(f"sqlite:///{course / 'gradebook.db'}") as gb:
        for name, paths in groups.items():
            sub = gb.find_submission(name, "instructor")
            assert sorted(nb.name for nb in sub.notebooks) == [p.stem for p in paths]
            grades = [g for nb in sub.notebooks for g in nb.grades if g.name not in manual]
            wrong = [(g.notebook.name, g.name, g.auto_score, g.max_score)
                     for g in grades if g.auto_score != g.max_score]
            assert wrong == [], f"{name}: the solutions lose points: {wrong}"
            assert sum(g.max_score for g in grades) >= 2 * len(paths), name
            # the written answers wait for the grader
            waiting = [g for nb in sub.notebooks for g in nb.grades if g.name in manual]
            assert all(g.needs_manual_grade for g in waiting), name
        typical_grades = {g.name: g for nb in gb.find_submission("capstone", "typical").notebooks
                          for g in nb.grades}
        assert typical_grades["test_spectra"].auto_score == 0
        assert typical_grades["test_prediction"].auto_score == 0
        assert typical_grades["test_descriptors"].auto_score == typical_grades[
            "test_descriptors"].max_score  # the other answers are right
    for student in ("instructor", "typical"):
        page = course / "feedback" / student / "capstone" / f"{CAPSTONE.stem}.html"
        assert page.is_file() and page.stat().st_size > 1000, page
        # equations typeset offline, by the course folder's MathJax copy
        text = page.read_text()
        assert "cdnjs.cloudflare.com/ajax/libs/mathjax" not in text
        assert '<script src="../../../mathjax/MathJax.js?config=' in text
    assert (course / "mathjax" / "MathJax.js").is_file()
    # the feedback on typical wrong answers names each mistake, in the words of the test cell
    feedback = _page_text(course / "feedback" / "typical" / "capstone"
                          / f"{CAPSTONE.stem}.html")
    lumped = _hint(CAPSTONE, "test_spectra", "lumped")
    assert lumped in feedback, lumped
    classes = _hint(CAPSTONE, "test_prediction", "number of classes")
    assert classes.split("{")[0] in feedback, classes  # the text before its first number
    assert "number of classes" in feedback

    releases = []
    for name, paths in groups.items():
        for path in paths:
            # the solutions ran without an error anywhere, graded or not
            graded = course / "autograded" / "instructor" / name / path.name
            done = nbformat.read(graded, as_version=4)
            errors = [(k, o.get("ename")) for k, c in enumerate(done.cells)
                      for o in c.get("outputs", []) if o.output_type == "error"]
            assert errors == [], f"{path.name}: errors in the instructor's run: {errors}"
            # no warning boxes in a lesson, unless a cell tagged expect-stderr is about that
            # warning
            assert stderr_outputs(done) == [], f"{path.name} has stderr outputs"
            # the hidden tests ran in the autograder (they are in the graded copy, not in the
            # release)
            assert "### BEGIN HIDDEN TESTS" in graded.read_text()
            releases.append(course / "release" / name / path.name)
            assert "### BEGIN HIDDEN TESTS" not in releases[-1].read_text()
    # a student who runs the release as given meets the first exercise's stub, raising
    # NotImplementedError where it is first called, before any other error
    first = _releases_stop_at_their_stubs(releases, env)
    other = {name: e for name, e in first.items() if e is None or e[1] != "NotImplementedError"}
    assert other == {}, f"untouched releases that do not stop at a stub (cell, error): {other}"
    # the answer keys are for instructors: nothing of them reaches a release
    released = [p for p in (course / "release").rglob("*") if p.is_file()]
    assert released and all(p.suffix == ".ipynb" for p in released)


def _small_assignment(path):
    """A graded notebook of four cells, in the lessons' nbgrader layout: a locked set-up
    cell, an exercise, its test cell with a hidden test, and a plain cell."""
    def cell(source, grade_id, *, solution=False, grade=False, locked=False, points=None):
        c = nbformat.v4.new_code_cell(source)
        c.metadata["nbgrader"] = {"grade": grade, "grade_id": grade_id, "locked": locked,
                                  "schema_version": 3, "solution": solution, "task": False}
        if points is not None:
            c.metadata["nbgrader"]["points"] = points
        return c

    nb = nbformat.v4.new_notebook()
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                 "language": "python"}
    nb.cells = [
        cell("scale = 2", "setup", locked=True),
        cell("def double(x):\n    ### BEGIN SOLUTION\n    return scale * x\n"
             "    ### END SOLUTION", "double", solution=True),
        cell('assert double(1) == 2, "double(1) should be 2"\n### BEGIN HIDDEN TESTS\n'
             'assert double(3) == 6, "double(3) should be 6"\n### END HIDDEN TESTS',
             "test_double", grade=True, locked=True, points=2),
        nbformat.v4.new_code_cell('print("after the exercise")'),
    ]
    path.parent.mkdir(parents=True, exist_ok=True)
    nbformat.write(nb, path)
    return path


@pytest.mark.slow
def test_nbgrader_grades_a_small_assignment(tmp_path):
    """With the course's configuration: the solutions get full marks, the untouched release
    gets less (its stub raises) and the grader goes on to the last cell; the hidden tests the
    release left out are no change, and a student's edit of a locked cell is (nbgrader's
    warning, and the cell is graded as released)."""
    pytest.importorskip("nbgrader", reason="the course extra: pip install 'cshape[course]'")
    from nbgrader.api import Gradebook

    lesson = _small_assignment(tmp_path / "nb" / "01_small.ipynb")
    course = tmp_path / "course"
    (assignment,) = asg.write_course(course, [lesson])
    asg.run_nbgrader("generate_assignment", assignment, "--force", cwd=course)
    release = course / "release" / assignment / lesson.name
    assert "raise NotImplementedError()" in release.read_text()
    assert "### BEGIN HIDDEN TESTS" not in release.read_text()
    nb = nbformat.read(release, as_version=4)
    k = next(k for k, c in enumerate(nb.cells) if c.metadata["nbgrader"].get("grade"))
    nb.cells[k].source = "assert True  # edited\n" + nb.cells[k].source
    for student, book in (("instructor", nbformat.read(lesson, as_version=4)),
                          ("untouched", nbformat.read(release, as_version=4)),
                          ("edited", nb)):
        folder = course / "submitted" / student / assignment
        folder.mkdir(parents=True)
        nbformat.write(book, folder / lesson.name)
    log = asg.run_nbgrader("autograde", assignment, "--force", cwd=course)
    changed = [ln for ln in log.splitlines() if "has changed!" in ln]
    assert len(changed) == 1 and "'checksum' for cell test_double has changed" in changed[0]
    graded = nbformat.read(course / "autograded" / "edited" / assignment / lesson.name,
                           as_version=4)
    assert "# edited" not in graded.cells[k].source
    untouched = nbformat.read(course / "autograded" / "untouched" / assignment / lesson.name,
                              as_version=4)
    assert [o["text"] for o in untouched.cells[-1].outputs] == ["after the exercise\n"]
    with Gradebook(f"sqlite:///{course / 'gradebook.db'}") as gb:
        score = {s: gb.find_submission(assignment, s).score
                 for s in ("instructor", "untouched", "edited")}
    assert score == {"instructor": 2, "untouched": 0, "edited": 0}, score


def test_run_nbgrader_without_nbgrader_says_how_to_install_it(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "nbgrader", None)  # as if it were not installed
    with pytest.raises(ImportError, match=r"nbgrader is not installed.*cshape\[course\]"):
        asg.run_nbgrader("generate_assignment", "week1", cwd=tmp_path)


def test_copy_lessons_and_refuse_a_used_folder(tmp_path, capsys):
    dest = tmp_path / "course"
    assert main(["lessons", str(dest)]) == 0
    names = {p.name for p in dest.glob(asg.PATTERN)}
    assert names == {p.name for p in LESSONS}
    assert {p.name for p in (dest / "student").glob(asg.PATTERN)} == {p.name for p in GRADED}
    # the course plan: one source folder per assignment, every lesson in the one that holds it
    assert sorted(p.name for p in (dest / "source").iterdir()) == sorted(asg.ASSIGNMENTS)
    for name, paths in asg.plan(LESSONS).items():
        assert sorted(p.name for p in (dest / "source" / name).iterdir()) == [
            p.name for p in paths], name
    assert "course_id" in (dest / "nbgrader_config.py").read_text()
    # the README speaks to instructors, of this folder, the plan and the nbgrader cycle, not of
    # the repository's tools
    readme = (dest / "README.md").read_text()
    for step in ("nbgrader generate_assignment week1", "submitted/<student>/week1/",
                 "nbgrader autograde week1", "nbgrader generate_feedback week1",
                 "nbgrader collect week1", "nbgrader export", "answers/"):
        assert step in readme, step
    for name, numbers in asg.ASSIGNMENTS.items():
        row = next((ln for ln in readme.splitlines() if ln.startswith(f"| `{name}`")), None)
        assert row is not None, f"the README's plan has no row for {name}"
        assert all(nn in row for nn in numbers), (name, row)
    for p in LESSONS:  # every lesson has its row of objectives, minutes and prerequisites
        assert re.search(rf"^\| {p.name[:2]} ", readme, re.M), p.name
    for developers in ("make notebooks", "sync_notebooks", "commit the .py", "_topic.py"):
        assert developers not in readme, developers
    for p in LESSONS:
        assert json.loads((dest / p.name).read_text()) == json.loads(p.read_text())
    # the answer keys, for instructors only: in answers/, nowhere a student release is made from
    assert [p.name for p in sorted((dest / asg.ANSWERS).iterdir())] == [p.name for p in ANSWERS]
    for p in ANSWERS:
        assert (dest / asg.ANSWERS / p.name).read_text() == p.read_text()
    for folder in (dest / "student", dest / "source"):
        assert [p for p in folder.rglob("*") if p.is_file() and p.suffix != ".ipynb"] == []
    out = capsys.readouterr().out
    assert "lessons" in out and "source/capstone/: 11_capstone" in out and "answers/" in out
    # a folder in use: one line, exit 2, nothing written
    before = sorted(dest.rglob("*"))
    assert main(["lessons", str(dest)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "not an empty folder" in err
    assert sorted(dest.rglob("*")) == before
    assert [p.name for p in tmp_path.iterdir()] == ["course"]  # no temporary folder left


def test_feedback_pages_are_pointed_at_the_course_mathjax(tmp_path):
    """The post-convert hook rewrites nbgrader's network MathJax to the course folder's copy,
    once; other pages are left alone."""
    pytest.importorskip("nbgrader", reason="the course extra: pip install 'cshape[course]'")
    pytest.importorskip("jupyter_server_mathjax", reason="the notebooks extra")
    from cshape.course.grading import CDN_MATHJAX, offline_feedback_math

    page = tmp_path / "feedback" / "ada" / "lessons" / "01_x.html"
    page.parent.mkdir(parents=True)
    page.write_text(f'<script src="{CDN_MATHJAX}"> </script><p>$x$</p>')
    other = page.with_name("02_y.html")
    other.write_text("<p>no math</p>")
    assert offline_feedback_math(root=tmp_path) == [page]
    text = page.read_text()
    assert CDN_MATHJAX not in text
    src = text.split('src="')[1].split("?")[0]
    assert src == "../../../mathjax/MathJax.js" and (page.parent / src).resolve().is_file()
    assert other.read_text() == "<p>no math</p>"
    assert offline_feedback_math(root=tmp_path) == []  # nothing left to rewrite
