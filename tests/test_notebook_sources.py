"""One source per lesson: ``notebooks/NN_topic.py`` (jupytext percent format) and the generated
``NN_topic.ipynb`` must agree (cell types, sources, cell metadata, notebook metadata)."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import nbformat
import pytest

pytest.importorskip("jupytext", reason="jupytext is in the test dependency group")

ROOT = Path(__file__).resolve().parent.parent
_spec = importlib.util.spec_from_file_location("sync_notebooks",
                                               ROOT / "tools" / "sync_notebooks.py")
sync_notebooks = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(sync_notebooks)

LESSON = '''\
# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Title
#
# Learning goals

# %% nbgrader={"grade": false, "grade_id": "f", "locked": false, "solution": true}
def f(x):
    ### BEGIN SOLUTION
    return x * x
    ### END SOLUTION


# %%
print(f(3))
'''


def test_every_lesson_has_one_source_and_agrees_with_it():
    problems = sync_notebooks.out_of_sync()
    assert problems == [], "\n".join(
        problems + ["edit notebooks/NN_*.py, then run `python tools/sync_notebooks.py`"])
    assert len(list(sync_notebooks.NOTEBOOKS.glob(sync_notebooks.PATTERN))) >= 7


def test_sync_writes_the_notebook_and_the_check_catches_every_kind_of_drift(tmp_path):
    (tmp_path / "01_t.py").write_text(LESSON)
    assert sync_notebooks.out_of_sync(tmp_path) == [
        "01_t.py has no notebook 01_t.ipynb (run the sync)"]
    assert sync_notebooks.sync(tmp_path) == [tmp_path / "01_t.ipynb"]
    assert sync_notebooks.sync(tmp_path) == []  # deterministic: nothing to rewrite
    nb = nbformat.read(tmp_path / "01_t.ipynb", as_version=4)
    assert [c.id for c in nb.cells] == ["01-00", "01-01", "01-02"]
    assert nb.cells[1].metadata["nbgrader"]["grade_id"] == "f"  # cell metadata carried over
    assert "### BEGIN SOLUTION" in nb.cells[1].source and "jupytext" not in nb.metadata
    assert sync_notebooks.out_of_sync(tmp_path) == []

    good = (tmp_path / "01_t.ipynb").read_text()
    edits = {
        "cell 2 source differs": lambda d: d["cells"][2].update(source="print(f(4))"),
        "cell 1 metadata differs": lambda d: d["cells"][1]["metadata"]["nbgrader"].update(
            grade_id="g"),
        "2 cells in the .ipynb, 3 in the .py": lambda d: d["cells"].pop(),
        "notebook metadata differs": lambda d: d["metadata"].pop("kernelspec"),
    }
    for message, edit in edits.items():
        data = json.loads(good)
        edit(data)
        (tmp_path / "01_t.ipynb").write_text(json.dumps(data))
        problems = sync_notebooks.out_of_sync(tmp_path)
        assert len(problems) == 1 and message in problems[0], (message, problems)
    # ids, outputs and execution counts are not compared (JupyterLab may rewrite them)
    data = json.loads(good)
    data["cells"][2].update(id="xyz", execution_count=3,
                            outputs=[{"output_type": "stream", "name": "stdout", "text": "9\n"}])
    (tmp_path / "01_t.ipynb").write_text(json.dumps(data))
    assert sync_notebooks.out_of_sync(tmp_path) == []
    (tmp_path / "01_t.py").unlink()
    assert sync_notebooks.out_of_sync(tmp_path) == [
        "01_t.ipynb has no source 01_t.py (jupytext --to py:percent it)"]


def test_check_command_exit_status(tmp_path, capsys):
    (tmp_path / "02_t.py").write_text(LESSON)
    assert sync_notebooks.main(["--check", "--folder", str(tmp_path)]) == 1
    assert sync_notebooks.main(["--folder", str(tmp_path)]) == 0
    assert sync_notebooks.main(["--check", "--folder", str(tmp_path)]) == 0
    assert "agree" in capsys.readouterr().out


def test_jupyterlab_of_the_venv_lists_each_lesson_once():
    """`make setup` gives the venv's Jupyter server a config that hides the lesson sources
    NN_topic.py (the .ipynb is the one a student opens), and nothing else of jupyter's."""
    import fnmatch

    config = ROOT / "tools" / "jupyter_server_config.json"
    globs = json.loads(config.read_text())["ContentsManager"]["hide_globs"]
    assert {"__pycache__", "*.pyc", "*.pyo", ".DS_Store", "*~"} <= set(globs)
    names = [p.name for p in (ROOT / "notebooks").iterdir()]
    hidden = {n for n in names if any(fnmatch.fnmatch(n, g) for g in globs)}
    assert hidden == {n for n in names if n.endswith(".py") and n[:2].isdigit()}
    assert not any(n.endswith(".ipynb") for n in hidden) and "README.md" not in hidden
    make = (ROOT / "Makefile").read_text()
    assert ("cp tools/jupyter_server_config.json "
            "$(VENV)/etc/jupyter/jupyter_server_config.json") in make
