"""Every notebook runs top to bottom on a fresh kernel (small sizes).  A cell error fails the
test.  Where nbgrader is installed, its autograde of the instructor's solutions is that run,
with the same checks, for every lesson of the course plan, and the untouched student release
runs up to its first exercise stub (tests/test_assignments.py); here run the lessons outside
the plan, and every lesson where nbgrader is missing."""

from __future__ import annotations

import importlib.util
import os
import sys

import nbformat
import pytest

from cshape.cli import main
from cshape.course.lessons import (
    default_notebook_dir,
    find_notebooks,
    offline_mathjax,
    run_notebook,
    run_notebooks,
)

NB_DIR = default_notebook_dir()
NOTEBOOKS = find_notebooks(NB_DIR)
STUDENT = find_notebooks(NB_DIR / "student") if (NB_DIR / "student").is_dir() else []


def test_notebooks_are_there_numbered_and_stored_without_outputs():
    assert len(NOTEBOOKS) >= 6, [p.name for p in NOTEBOOKS]
    for path in NOTEBOOKS + STUDENT:
        nb = nbformat.read(path, as_version=4)
        nbformat.validate(nb)
        assert nb.metadata["kernelspec"]["name"] == "python3", path.name
        for k, cell in enumerate(nb.cells):
            if cell.cell_type == "code":
                assert cell.outputs == [] and cell.execution_count is None, (
                    f"{path.name} cell {k} has outputs; notebooks are committed without them")


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebook_is_a_lesson(path):
    nb = nbformat.read(path, as_version=4)
    md = [c.source for c in nb.cells if c.cell_type == "markdown"]
    assert "Learning goals" in md[0], f"{path.name} must open with its learning goals"
    assert "Eq." in md[0] or "Section" in md[0], f"{path.name}: name the paper's equations"
    assert md[-1].lstrip().startswith("## Exercises"), f"{path.name} must end with exercises"
    code = "\n".join(c.source for c in nb.cells if c.cell_type == "code")
    # the one size switch: `from cshape.course.teaching import SMALL, size` (CSHAPE_SMALL=1)
    assert "from cshape.course.teaching import SMALL" in code or "CSHAPE_SMALL" in code, (
        f"{path.name} must honour the small-size switch")


@pytest.fixture(scope="module")
def kernel_env(tmp_path_factory):
    """The kernels' cshape cache lives in a temporary folder, not in the user's cache."""
    return {"CSHAPE_CACHE": str(tmp_path_factory.mktemp("cshape-cache"))}


def _graded_by_nbgrader(path):
    """Whether the nbgrader cycle of tests/test_assignments.py runs this lesson."""
    from cshape.course import assignments as asg

    if importlib.util.find_spec("nbgrader") is None:
        return False
    return any(path.name[:2] in numbers for numbers in asg.ASSIGNMENTS.values())


@pytest.mark.slow
@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebook_runs(path, kernel_env, tmp_path):
    if _graded_by_nbgrader(path):
        pytest.skip("nbgrader's autograde of the instructor's solutions runs this lesson, with "
                    "these checks (tests/test_assignments.py)")
    tmp = tmp_path / "tmp"  # the kernel's temporary folder, to see what it leaves behind
    tmp.mkdir()
    res = run_notebook(path, small=True, html=False, timeout=600,
                       env={**kernel_env, "TMPDIR": str(tmp)})
    assert res.ok, f"{path.name} failed after {res.seconds:.1f} s: {res.error}"
    # no warning boxes in a lesson, unless a cell tagged expect-stderr is about that warning
    assert res.stderr == [], f"{path.name} has stderr outputs: {res.stderr}"
    left = sorted(p.name for p in tmp.iterdir() if p.name.startswith("cshape"))
    assert left == [], f"{path.name} leaves temporary folders behind: {left}"


def _tiny(folder, source):
    nb = nbformat.v4.new_notebook()
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                 "language": "python"}
    cell = nbformat.v4.new_code_cell(source)
    cell["id"] = "c0"
    nb.cells.append(cell)
    folder.mkdir(parents=True, exist_ok=True)
    nbformat.write(nb, folder / "01_tiny.ipynb")
    return folder / "01_tiny.ipynb"


def test_kernel_is_this_interpreter_and_cli_writes_html(tmp_path, capsys):
    src = tmp_path / "src"
    _tiny(src, "import os, sys\nprint(sys.executable)\nprint(os.environ.get('CSHAPE_SMALL'))"
               "\nprint(os.environ.get('PLOTLY_RENDERER'))")
    out = tmp_path / "out"
    assert main(["notebooks", "--small", "--src", str(src), "--out", str(out)]) == 0
    nb = nbformat.read(out / "01_tiny.ipynb", as_version=4)
    printed = nb.cells[0].outputs[0]["text"].split()
    # plotly figures: lab extension mime type + embedded plotly.js for the HTML page
    assert printed == [sys.executable, "1", "plotly_mimetype+notebook"]
    page = (out / "01_tiny.html").read_text()
    assert len(page) > 1000
    if importlib.util.find_spec("jupyter_server_mathjax"):  # the notebooks extra
        # MathJax from the copy next to the page, not from a CDN (offline exam rooms)
        assert '<script src="mathjax/MathJax.js?config=' in page
        assert "cdnjs.cloudflare.com/ajax/libs/mathjax" not in page
        assert (out / "mathjax" / "MathJax.js").is_file()
        assert (out / "mathjax" / "config" / "local" / "cshape.js").is_file()
        local = out / "mathjax" / "config" / "local" / "cshape.js"
        stamp = local.stat().st_mtime_ns
        url = offline_mathjax(out)  # a second call copies nothing again ...
        assert local.stat().st_mtime_ns == stamp
        assert f'<script src="{url}"' in page  # ... and gives the URL the page loads
    assert "01_tiny.html" in (out / "index.html").read_text()
    assert "01_tiny.ipynb: ok" in capsys.readouterr().out


def test_stderr_outputs_are_reported_unless_expected(tmp_path):
    src = "import sys, warnings\nprint('fine')\nwarnings.warn('a box in the lesson')"
    path = _tiny(tmp_path, src)
    res = run_notebook(path, html=False)
    assert res.ok and len(res.stderr) == 1 and "a box in the lesson" in res.stderr[0], res.stderr
    assert res.stderr[0].startswith("cell 0: ")
    nb = nbformat.read(path, as_version=4)
    nb.cells[0].metadata["tags"] = ["expect-stderr"]
    nbformat.write(nb, path)
    assert run_notebook(path, html=False).stderr == []


@pytest.mark.slow
def test_failing_cell_is_reported(tmp_path):
    path = _tiny(tmp_path, "raise RuntimeError('boom')")
    res = run_notebook(path, html=False)
    assert not res.ok and "RuntimeError: boom" in res.error
    assert main(["notebooks", "--src", str(tmp_path), "--out", str(tmp_path / "o"),
                 "--no-html"]) == 1


def test_unknown_notebook_name():
    with pytest.raises(ValueError, match="no notebook '99'"):
        find_notebooks(NB_DIR, ["99"])


def test_real_mesh_is_shipped_spot_without_the_shared_folder(tmp_path, monkeypatch, capsys):
    """Lessons 02-03 read Spot from the package: no shared folder, no message about one."""
    from cshape.course.teaching import real_mesh

    monkeypatch.setenv("CSHAPE_SHARED_MESHES", str(tmp_path / "no-such-folder"))
    small, credit = real_mesh(small=True)
    assert (small.n_vertices, small.n_faces) == (829, 1654)
    assert "Spot" in credit and "public domain" in credit
    full, _ = real_mesh(small=False)  # one Loop subdivision: V + E vertices, 4x the faces
    assert full.n_faces == 4 * small.n_faces
    assert full.n_vertices == small.n_vertices + small.n_faces * 3 // 2
    assert abs(full.area - small.area) < 0.05 * small.area  # the same shape, smoothed
    assert "shared" not in capsys.readouterr().out


def test_size_switch_follows_cshape_small(monkeypatch):
    """`size(small, full)` of the lessons picks by SMALL, which is CSHAPE_SMALL=1 at import."""
    import subprocess

    import cshape.course.teaching as teaching

    monkeypatch.setattr(teaching, "SMALL", True)
    assert teaching.size(50, 100) == 50 and teaching.size("a", "b") == "a"
    monkeypatch.setattr(teaching, "SMALL", False)
    assert teaching.size(50, 100) == 100
    code = "from cshape.course.teaching import SMALL, size; print(SMALL, size(50, 100))"
    for value, want in (("1", "True 50"), ("0", "False 100"), ("", "False 100")):
        env = dict(os.environ, CSHAPE_SMALL=value)
        out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                             text=True, timeout=120, check=True).stdout.strip()
        assert out == want, (value, out)


def test_index_page_names_each_lesson_by_its_title():
    from cshape.course.lessons import lesson_title

    assert lesson_title(NB_DIR / "02_shape_dna_weyl.ipynb") == "2 · Shape-DNA and the Weyl line"
    titles = [lesson_title(p) for p in NOTEBOOKS]
    assert all(t[0].isdigit() and " · " in t for t in titles), titles


def test_index_page_looks_like_the_site_and_typesets_titles(tmp_path):
    """The first page after `make demo`: the site's top bar and fonts, each lesson's title
    (its TeX for MathJax when the pages have their MathJax copy, else written plainly),
    the paper's sections, time and state."""
    from cshape.course.lessons import RunResult, _index

    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_markdown_cell(
        "# 7 · The parameter $M$, interactively\n\n**Paper:** Gao, Yu and Pang, *A compact "
        "shape descriptor*, CAD 53 (2014); Section 3.2, Fig. 6.\n\nText.")]
    path = tmp_path / "07_m.ipynb"
    nbformat.write(nb, path)
    page = tmp_path / "07_m.html"
    page.write_text("<html></html>")
    ok = RunResult("07_m.ipynb", True, 12.3, ipynb=path, html=page)
    bad = RunResult("08_x.ipynb", False, 1.0, error="ValueError: boom <b>")
    text = _index([ok, bad], tmp_path, small=False).read_text()
    assert "<header><a class='brand' href='index.html'>cshape</a>" in text
    assert "font-family: -apple-system" in text and "Times" not in text
    assert '<a href="07_m.html">7 · The parameter $M$, interactively</a>' in text
    if importlib.util.find_spec("jupyter_server_mathjax"):
        assert '<script src="mathjax/MathJax.js?config=' in text
        assert "inlineMath: [['$','$']]" in text and "processClass: 'title'" in text
    assert "paper: Section 3.2 · <code>07_m.ipynb</code>" in text and "12 s" in text
    assert "ValueError: boom &lt;b&gt;" in text and "badge bad" in text
    # without HTML pages (no MathJax copy) the title is written without TeX
    (tmp_path / "plain").mkdir()
    ok.html = None
    text = _index([ok], tmp_path / "plain", small=True).read_text()
    assert "7 · The parameter <i>M</i>, interactively" in text and "$" not in text
    assert "mathjax" not in text.lower() and "at small size" in text


def test_run_notebooks_says_where_to_look(tmp_path, capsys):
    src = tmp_path / "src"
    _tiny(src, "print(1)")
    run_notebooks(src, tmp_path / "out", html=False)
    last = capsys.readouterr().out.strip().splitlines()[-1]
    assert last == f"open the lessons in a browser: {(tmp_path / 'out' / 'index.html').as_uri()}"


def test_run_notebooks_at_once_keep_their_order(tmp_path, capsys):
    """Two kernels at once: the first notebook ends only when the second has run (so they
    ran at the same time), each runs once, the results come in the notebooks' order, and
    every start and end is said."""
    src = tmp_path / "src"
    marker = tmp_path / "second-ran"
    wait = (f"import os, time\nt = time.monotonic()\nwhile not os.path.exists({str(marker)!r}):\n"
            "    assert time.monotonic() - t < 120, 'the second notebook never ran'\n"
            "    time.sleep(0.05)\nprint('one')")
    for k, code in ((1, wait), (2, f"open({str(marker)!r}, 'w').close()"),
                    (3, "raise ValueError('three')")):
        _tiny(src, code).rename(src / f"0{k}_n.ipynb")
    results = run_notebooks(src, tmp_path / "out", html=False, n_jobs=2)
    assert [r.name for r in results] == ["01_n.ipynb", "02_n.ipynb", "03_n.ipynb"]
    assert [r.ok for r in results] == [True, True, False]
    lines = capsys.readouterr().out.splitlines()
    for name in ("01_n.ipynb", "02_n.ipynb", "03_n.ipynb"):
        assert lines.count(f"running {name} ...") == 1
        assert sum(line.startswith(f"  {name}: ") for line in lines) == 1
    with pytest.raises(ValueError, match="n_jobs"):
        run_notebooks(src, tmp_path / "out", html=False, n_jobs=0)
