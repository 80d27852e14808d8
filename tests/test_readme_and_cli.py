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
