"""Student versions of the notebooks: solutions -> stubs, hidden tests removed, kept in sync."""

from __future__ import annotations

import nbformat
import pytest

from cshape import assignments as asg
from cshape.cli import main
from cshape.notebooks_run import default_notebook_dir

SOLUTION_CELL = '''\
def f(x):
    """Square it."""
    ### BEGIN SOLUTION
    y = x * x
    return y
    ### END SOLUTION


print(f(3))'''


def _nb(*cells):
    nb = nbformat.v4.new_notebook()
    for k, (kind, src, *tags) in enumerate(cells):
        cell = (nbformat.v4.new_code_cell if kind == "code" else nbformat.v4.new_markdown_cell)(src)
        cell["id"] = f"c{k}"
        if tags:
            cell.metadata["tags"] = list(tags)
        if kind == "code":
            cell.outputs = [nbformat.v4.new_output("stream", text="9\n")]
            cell.execution_count = 1
        nb.cells.append(cell)
    return nb


def test_solution_becomes_a_stub_at_its_indentation():
    out = asg.strip_regions(SOLUTION_CELL, asg.BEGIN_SOLUTION, asg.END_SOLUTION,
                            replacement=lambda ind: f'{ind}raise NotImplementedError("x")')
    assert "x * x" not in out and "BEGIN" not in out
    assert '\n    raise NotImplementedError("x")\n' in out
    assert out.endswith("print(f(3))")
    ns = {}
    exec(out.replace("print(f(3))", ""), ns)
    with pytest.raises(NotImplementedError):
        ns["f"](2)


@pytest.mark.parametrize("source, match", [
    ("a\n### BEGIN SOLUTION\nb", "never closed"),
    ("a\n### END SOLUTION\nb", "line 2: '### END SOLUTION' without"),
    ("### BEGIN SOLUTION\n### BEGIN SOLUTION\n### END SOLUTION", "inside another"),
])
def test_unbalanced_markers_are_errors(source, match):
    with pytest.raises(ValueError, match=match):
        asg.strip_regions(source, asg.BEGIN_SOLUTION, asg.END_SOLUTION, where="nb.ipynb, cell 3")


def test_student_notebook():
    nb = _nb(
        ("markdown", "# Title\n\nLearning goals"),
        ("code", SOLUTION_CELL),
        ("code", "check(f)\n### BEGIN HIDDEN TESTS\nassert f(4) == 16\n### END HIDDEN TESTS"),
        ("code", "### BEGIN HIDDEN TESTS\nassert f(5) == 25\n### END HIDDEN TESTS"),
        ("code", "secret = 1", "hidden-tests"),
        ("markdown", "Why?\n### BEGIN SOLUTION\nBecause.\n### END SOLUTION"),
    )
    before = nbformat.writes(nb)
    st = asg.student_notebook(nb, source_name="01_x.ipynb")
    assert nbformat.writes(nb) == before  # the solution notebook is unchanged
    nbformat.validate(st)
    srcs = [c.source for c in st.cells]
    assert srcs[0].startswith("# Title")
    assert "Student version" in srcs[1] and "01_x.ipynb" in srcs[1]
    assert "NotImplementedError" in srcs[2] and "x * x" not in srcs[2]
    assert srcs[3] == "check(f)"  # hidden region removed, visible check kept
    assert not any("f(5)" in s or "secret" in s for s in srcs)  # hidden-only and tagged cells
    assert asg.MARKDOWN_ANSWER in srcs[-1] and "Because" not in srcs[-1]
    assert all(c.outputs == [] and c.execution_count is None
               for c in st.cells if c.cell_type == "code")
    assert asg.has_markers(nb) and not asg.has_markers(st)


def test_generate_check_and_stale(tmp_path):
    src = tmp_path / "nb"
    src.mkdir()
    nbformat.write(_nb(("markdown", "# A"), ("code", SOLUTION_CELL)), src / "01_a.ipynb")
    nbformat.write(_nb(("markdown", "# B"), ("code", "1 + 1")), src / "02_b.ipynb")
    dest = src / "student"
    assert asg.generate(src, check=True) == [dest / "01_a.ipynb"]
    assert asg.generate(src) == [dest / "01_a.ipynb"]  # only notebooks with markers
    assert asg.generate(src, check=True) == []
    assert asg.generate(src) == []  # nothing changed, nothing written
    (dest / "01_a.ipynb").write_text((dest / "01_a.ipynb").read_text() + " ")  # hand edit
    assert asg.generate(src, check=True) == [dest / "01_a.ipynb"]
    (src / "01_a.ipynb").unlink()  # source gone: the student version is stale
    assert asg.generate(src, check=True) == [dest / "01_a.ipynb"]
    asg.generate(src)
    assert not (dest / "01_a.ipynb").exists()


def test_generate_names_a_missing_folder(tmp_path):
    with pytest.raises(FileNotFoundError, match="does not exist"):
        asg.generate(tmp_path / "nope")


def test_committed_student_notebooks_are_up_to_date():
    stale = asg.generate(check=True)
    assert stale == [], (
        f"generated student notebooks out of date: {[p.name for p in stale]}; run "
        "`python -m cshape assignments` and commit notebooks/student/"
    )


def test_notebooks_1_and_3_have_graded_exercises():
    folder = default_notebook_dir()
    for name in ("01_fem_assembly.ipynb", "03_dft_compression.ipynb"):
        nb = nbformat.read(folder / name, as_version=4)
        text = "\n".join(c.source for c in nb.cells)
        assert text.count(asg.BEGIN_SOLUTION) >= 1 and asg.BEGIN_HIDDEN in text, name
        assert (folder / "student" / name).is_file()


def test_cli_check(capsys):
    assert main(["assignments", "--check"]) == 0
    assert "up to date" in capsys.readouterr().out
