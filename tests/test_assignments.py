"""The course: nbgrader source notebooks, nbgrader's student release, the full grading cycle,
and the lessons copied out of cshape by ``cshape lessons``."""

from __future__ import annotations

import json
import shutil
import zipfile

import nbformat
import pytest

from cshape.cli import main
from cshape.course import assignments as asg

NB_DIR = asg.lessons_dir()
LESSONS = sorted(NB_DIR.glob(asg.PATTERN))
GRADED = [p for p in LESSONS if asg.is_graded(p)]


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


@pytest.mark.slow
def test_nbgrader_course_full_cycle(tmp_path):
    """Release, autograde two submissions, feedback: the instructor's solutions get full marks,
    the untouched student release gets less and does not crash the grader."""
    pytest.importorskip("nbgrader", reason="the course extra: pip install 'cshape[course]'")
    from nbgrader.api import Gradebook

    course = asg.write_course(tmp_path / "course", GRADED)
    asg.run_nbgrader("generate_assignment", asg.ASSIGNMENT, "--force", cwd=course)
    release = course / "release" / asg.ASSIGNMENT
    assert sorted(p.name for p in release.glob("*.ipynb")) == [p.name for p in GRADED]
    submissions = {"instructor": course / "source" / asg.ASSIGNMENT, "untouched": release}
    for student, folder in submissions.items():
        shutil.copytree(folder, course / "submitted" / student / asg.ASSIGNMENT)
    env = {"CSHAPE_SMALL": "1", "CSHAPE_CACHE": str(tmp_path / "cache")}
    log = asg.run_nbgrader("autograde", asg.ASSIGNMENT, "--force", cwd=course, env=env)
    # neither the solutions nor the untouched release changed a locked cell
    assert "has changed!" not in log, [ln for ln in log.splitlines() if "changed!" in ln]
    asg.run_nbgrader("generate_feedback", asg.ASSIGNMENT, "--force", cwd=course)

    with Gradebook(f"sqlite:///{course / 'gradebook.db'}") as gb:
        scores = {}
        for student in submissions:
            sub = gb.find_submission(asg.ASSIGNMENT, student)
            scores[student] = (sub.score, sub.max_score)
            per_nb = {nb.name: (nb.score, nb.max_score) for nb in sub.notebooks}
            assert sorted(per_nb) == [p.stem for p in GRADED], student
            if student == "instructor":
                assert all(s == m > 0 for s, m in per_nb.values()), per_nb
        max_score = scores["instructor"][1]
        assert max_score >= 2 * len(GRADED)
        assert scores["instructor"][0] == max_score, scores
        assert scores["untouched"][0] < max_score, scores
    for student in submissions:
        for path in GRADED:
            page = course / "feedback" / student / asg.ASSIGNMENT / f"{path.stem}.html"
            assert page.is_file() and page.stat().st_size > 1000, page
            # equations typeset offline, by the course folder's MathJax copy
            text = page.read_text()
            assert "cdnjs.cloudflare.com/ajax/libs/mathjax" not in text
            assert '<script src="../../../mathjax/MathJax.js?config=' in text
    assert (course / "mathjax" / "MathJax.js").is_file()
    # the solutions ran without an error anywhere, graded or not
    for path in GRADED:
        done = nbformat.read(course / "autograded" / "instructor" / asg.ASSIGNMENT / path.name,
                             as_version=4)
        errors = [(k, o.get("ename")) for k, c in enumerate(done.cells)
                  for o in c.get("outputs", []) if o.output_type == "error"]
        assert errors == [], f"{path.name}: errors in the instructor's run: {errors}"
    # the hidden tests ran in the autograder (they are in the graded copy, not in the release)
    graded = (course / "autograded" / "untouched" / asg.ASSIGNMENT / GRADED[0].name).read_text()
    assert "### BEGIN HIDDEN TESTS" in graded
    assert "### BEGIN HIDDEN TESTS" not in (release / GRADED[0].name).read_text()


@pytest.mark.slow
def test_autograde_warns_of_an_edited_locked_cell_only(tmp_path):
    """The hidden tests the release left out are no change; a student's edit of a locked
    cell still is (nbgrader's warning, and the cell is graded as released)."""
    pytest.importorskip("nbgrader", reason="the course extra: pip install 'cshape[course]'")
    lesson = GRADED[0]
    course = asg.write_course(tmp_path / "course", [lesson])
    asg.run_nbgrader("generate_assignment", asg.ASSIGNMENT, "--force", cwd=course)
    release = course / "release" / asg.ASSIGNMENT / lesson.name
    nb = nbformat.read(release, as_version=4)
    k, cell = next((k, c) for k, c in enumerate(nb.cells)
                   if c.metadata.get("nbgrader", {}).get("grade"))
    cell.source = "assert True  # edited\n" + cell.source
    for student, book in (("untouched", nbformat.read(release, as_version=4)), ("edited", nb)):
        folder = course / "submitted" / student / asg.ASSIGNMENT
        folder.mkdir(parents=True)
        nbformat.write(book, folder / lesson.name)
    log = asg.run_nbgrader("autograde", asg.ASSIGNMENT, "--force", cwd=course,
                           env={"CSHAPE_SMALL": "1", "CSHAPE_CACHE": str(tmp_path / "cache")})
    changed = [ln for ln in log.splitlines() if "has changed!" in ln]
    grade_id = cell.metadata["nbgrader"]["grade_id"]
    assert len(changed) == 1 and f"'checksum' for cell {grade_id} has changed" in changed[0]
    graded = nbformat.read(course / "autograded" / "edited" / asg.ASSIGNMENT / lesson.name,
                           as_version=4)
    assert "# edited" not in graded.cells[k].source


def test_copy_lessons_and_refuse_a_used_folder(tmp_path, capsys):
    dest = tmp_path / "course"
    assert main(["lessons", str(dest)]) == 0
    names = {p.name for p in dest.glob(asg.PATTERN)}
    assert names == {p.name for p in LESSONS}
    assert {p.name for p in (dest / "student").glob(asg.PATTERN)} == {p.name for p in GRADED}
    assert {p.name for p in (dest / "source" / asg.ASSIGNMENT).iterdir()} == {
        p.name for p in GRADED}
    assert "course_id" in (dest / "nbgrader_config.py").read_text()
    # the README speaks to instructors, of this folder and the nbgrader cycle, not of the
    # repository's tools
    readme = (dest / "README.md").read_text()
    for step in ("nbgrader generate_assignment lessons", "submitted/<student>/lessons/",
                 "nbgrader autograde lessons", "nbgrader generate_feedback lessons",
                 "nbgrader collect lessons", "nbgrader export"):
        assert step in readme, step
    for developers in ("make notebooks", "sync_notebooks", "commit the .py", "_topic.py"):
        assert developers not in readme, developers
    for p in LESSONS:
        assert json.loads((dest / p.name).read_text()) == json.loads(p.read_text())
    assert "lessons" in capsys.readouterr().out
    # a folder in use: one line, exit 2, nothing written
    before = sorted(dest.rglob("*"))
    assert main(["lessons", str(dest)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "not an empty folder" in err
    assert sorted(dest.rglob("*")) == before
    assert [p.name for p in tmp_path.iterdir()] == ["course"]  # no temporary folder left


@pytest.mark.slow
def test_lessons_from_an_installed_wheel_run_there(installed_wheel_env):
    """`pip install cshape`, no clone: `cshape lessons DIR` copies the lessons out of the
    package, and a lesson and its student version run in DIR with the installed cshape."""
    from conftest import REPO

    env = installed_wheel_env
    with zipfile.ZipFile(env.wheel) as zf:
        names = set(zf.namelist())
    packages = {f"{p.parent.relative_to(REPO).as_posix()}/__init__.py"
                for p in (REPO / "cshape").rglob("__init__.py")}
    assert packages <= names, f"add to [tool.setuptools] packages: {sorted(packages - names)}"
    dest = env.workdir / "my-course"
    r = env.run("cshape", "lessons", dest)
    assert r.returncode == 0, r.stderr
    assert sorted(p.name for p in dest.glob(asg.PATTERN)) == [p.name for p in LESSONS]
    assert sorted(p.name for p in (dest / "student").glob(asg.PATTERN)) == [
        p.name for p in GRADED]
    assert (dest / "nbgrader_config.py").is_file()
    assert "nbgrader autograde lessons" in (dest / "README.md").read_text()
    for extra in ([], ["--student"]):
        out = env.workdir / f"executed{'-'.join(extra)}"
        r = env.run("cshape", "notebooks", "01", "--small", "--no-html", "--src", dest,
                    "--out", out, *extra)
        assert r.returncode == 0, r.stdout + r.stderr
        assert "01_fem_assembly.ipynb: ok" in r.stdout, r.stdout
        executed = nbformat.read(out / "01_fem_assembly.ipynb", as_version=4)
        printed = "".join(o.get("text", "") for o in executed.cells[1].outputs)
        assert printed.startswith("cshape ") and "(small sizes)" in printed, printed


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
