"""The lint of the repository: ruff with pyproject's rules, the numpy docstring convention on
the core modules (cshape/*.py) included, so that ``make lint`` stays clean."""

from __future__ import annotations

import subprocess
import sys

import pytest
from conftest import REPO


def test_the_repository_passes_ruff():
    pytest.importorskip("ruff", reason="ruff comes with the test dependency group")
    res = subprocess.run([sys.executable, "-m", "ruff", "check", "--no-cache", "."], cwd=REPO,
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stdout[-4000:] + res.stderr[-2000:]


def test_the_docstring_rules_reach_the_core_and_only_the_core(tmp_path):
    """A docstring that breaks the numpy convention is reported in a core module and not in
    a layer subpackage or a test (checked on copies, so the repository is not touched)."""
    pytest.importorskip("ruff", reason="ruff comes with the test dependency group")
    bad = 'def f():\n    """Returns one\n    and more."""\n    return 1\n'
    found = {}
    for rel in ("cshape/zz_core.py", "cshape/plots/zz_layer.py", "tests/zz_test.py"):
        res = subprocess.run([sys.executable, "-m", "ruff", "check", "--no-cache",
                              "--stdin-filename", rel, "-"], cwd=REPO, input=bad,
                             capture_output=True, text=True, timeout=120)
        found[rel] = {c for c in ("D205", "D209", "D401") if c in res.stdout}
    assert found == {"cshape/zz_core.py": {"D205", "D209", "D401"},
                     "cshape/plots/zz_layer.py": set(), "tests/zz_test.py": set()}
