"""Static type check of the core: mypy over the modules listed in pyproject's [tool.mypy]
(mesh, readers, fem, spectrum, descriptors, compare, index, signatures, shapes, _checks)."""

from __future__ import annotations

import subprocess
import sys

import pytest
from conftest import REPO


@pytest.mark.slow
def test_the_core_type_checks():
    pytest.importorskip("mypy", reason="mypy comes with the test dependency group")
    res = subprocess.run([sys.executable, "-m", "mypy", "--no-incremental",
                          "--cache-dir", "/dev/null"], cwd=REPO, capture_output=True, text=True,
                         timeout=600)
    assert res.returncode == 0, res.stdout[-4000:] + res.stderr[-2000:]
    assert "Success: no issues found" in res.stdout
