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


def test_every_public_parameter_of_the_core_is_typed():
    """tools/typed_fraction.py counts the parameters and returns of the public functions and
    classes of the core stages; all of them carry a type hint (the mypy check above only
    checks the hints that exist)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("typed_fraction",
                                                  REPO / "tools" / "typed_fraction.py")
    tf = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tf)
    missing: list[str] = []
    for module in tf.CORE:
        tf.count(module, None, missing)
    assert missing == [], f"public names of the core without a type hint: {missing}"
