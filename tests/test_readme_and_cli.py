"""The README's Python snippets run, and the demo main job works."""

from __future__ import annotations

import re
import subprocess
import sys

import pytest
from conftest import REPO


def test_readme_python_snippets_run():
    text = (REPO / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert blocks, "README has no python snippet"
    for code in blocks:
        exec(compile(code, "README.md", "exec"), {})


@pytest.mark.slow
def test_demo_command_prints_descriptors():
    out = subprocess.run(
        [sys.executable, "-m", "cshape", "demo", "-N", "20", "-M", "2"],
        capture_output=True, text=True, timeout=300, check=True,
    ).stdout
    assert "unit sphere" in out and "cShape-DNA" in out


@pytest.mark.slow
def test_cli_reports_bad_arguments_cleanly():
    res = subprocess.run(
        [sys.executable, "-m", "cshape", "demo", "-N", "20", "-M", "10"],
        capture_output=True, text=True, timeout=300,
    )
    assert res.returncode == 2
    assert "use M <= 9" in res.stderr and "Traceback" not in res.stderr


def _bash_block(text, heading):
    section = text.split(f"## {heading}\n", 1)[1].split("\n## ", 1)[0]
    block = re.search(r"```bash\n(.*?)```", section, flags=re.S).group(1)
    return [line.split("#", 1)[0].strip() for line in block.splitlines()
            if line.split("#", 1)[0].strip()]


@pytest.mark.slow
def test_readme_own_meshes_commands_run_on_a_folder(tmp_path):
    """The README's command-line example, line by line, on a folder of two classes."""
    from conftest import cli, write_off

    from cshape import shapes
    from cshape.course.teaching import real_mesh

    cow, _ = real_mesh(small=True)
    write_off(tmp_path / "meshes" / "cows" / "cow.off", cow)
    write_off(tmp_path / "meshes" / "cows" / "calf.off", (0.5 * cow.vertices, cow.faces))
    write_off(tmp_path / "meshes" / "balls" / "ball.off", shapes.icosphere(3))
    write_off(tmp_path / "meshes" / "balls" / "pebble.off", shapes.icosphere(2))
    lines = _bash_block((REPO / "README.md").read_text(), "Your own meshes")
    assert [ln.split()[1] for ln in lines] == ["info", "describe", "query", "query",
                                               "overview"]
    outs = []
    for line in lines:  # `cshape ARGS` runs cshape.cli.main(ARGS)
        res = cli(*line.split()[1:], cache=tmp_path / "cache", cwd=tmp_path)
        assert res.returncode == 0, (line, res.stderr)
        outs.append(res.stdout)
    assert outs[0].count("\nfile ") + outs[0].startswith("file ") == 4  # info: four files
    assert (tmp_path / "table.csv").is_file()
    first = outs[2].split("calf")[0]  # query: cow's nearest shape is its own class's calf
    assert "ball" not in first and "pebble" not in first, outs[2]
    assert (tmp_path / "cow.html").is_file() and (tmp_path / "overview.html").is_file()
    assert outs[4] == "" or "overview.html" in outs[4]


def test_readme_teaching_commands_are_the_course_folders():
    """The README's teaching example uses the commands the course README and the teaching
    guide explain, in the same order."""
    from cshape.course.assignments import INSTRUCTORS_README

    lines = _bash_block((REPO / "README.md").read_text(), "Teaching")
    nbgrader = [ln for ln in lines if ln.startswith("nbgrader ")]
    assert nbgrader == ["nbgrader generate_assignment week1", "nbgrader autograde week1",
                        "nbgrader generate_feedback week1"]
    for doc in (INSTRUCTORS_README, REPO / "docs" / "guides" / "teaching.md"):
        text = doc.read_text()
        where = [text.index(cmd) for cmd in nbgrader]
        assert where == sorted(where), doc
        assert "submitted/<student>/week1/" in text
    assert lines[0] == "cshape lessons mycourse && cd mycourse"
