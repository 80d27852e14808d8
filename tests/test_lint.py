"""The lint of the repository: ruff with pyproject's rules, the numpy docstring convention on
the core modules (cshape/*.py) included, so that ``make lint`` stays clean.  Without ruff these
tests fail in CI (``CI`` set) and are skipped elsewhere."""

from __future__ import annotations

import subprocess
import sys

import pytest
from conftest import REPO, require_tool

_WHY = "ruff comes with the test dependency group"


def test_the_repository_passes_ruff():
    require_tool("ruff", _WHY)
    res = subprocess.run([sys.executable, "-m", "ruff", "check", "--no-cache", "."], cwd=REPO,
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stdout[-4000:] + res.stderr[-2000:]


def test_the_docstring_rules_reach_the_core_and_only_the_core(tmp_path):
    """A docstring that breaks the numpy convention is reported in a core module and not in
    a layer subpackage or a test (checked on copies, so the repository is not touched)."""
    require_tool("ruff", _WHY)
    bad = 'def f():\n    """Returns one\n    and more."""\n    return 1\n'
    found = {}
    for rel in ("cshape/zz_core.py", "cshape/plots/zz_layer.py", "tests/zz_test.py"):
        res = subprocess.run([sys.executable, "-m", "ruff", "check", "--no-cache",
                              "--stdin-filename", rel, "-"], cwd=REPO, input=bad,
                             capture_output=True, text=True, timeout=120)
        found[rel] = {c for c in ("D205", "D209", "D401") if c in res.stdout}
    assert found == {"cshape/zz_core.py": {"D205", "D209", "D401"},
                     "cshape/plots/zz_layer.py": set(), "tests/zz_test.py": set()}


def test_a_missing_tool_fails_in_ci_and_is_skipped_elsewhere(monkeypatch):
    """The lint and type tests cannot pass silently in CI for want of their tool."""
    for value in ("true", "1", "yes"):
        monkeypatch.setenv("CI", value)
        with pytest.raises(pytest.fail.Exception, match="no_such_tool_0 is not installed"):
            require_tool("no_such_tool_0", "a test")
    for value in ("", "0", "false"):
        monkeypatch.setenv("CI", value)
        with pytest.raises(pytest.skip.Exception, match=r"no_such_tool_0 .*\(a test\)"):
            require_tool("no_such_tool_0", "a test")
    monkeypatch.delenv("CI")
    with pytest.raises(pytest.skip.Exception):
        require_tool("no_such_tool_0", "a test")
    assert require_tool("json", "the standard library").dumps([1]) == "[1]"
