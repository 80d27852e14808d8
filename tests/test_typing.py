"""Static type check of the package: mypy over every module of ``cshape`` (pyproject's
[tool.mypy]: ``files = ["cshape"]``, untyped functions refused outside the overrides that
name a module), and the public names that carry a hint (tools/typed_fraction.py).  Without
mypy the check fails in CI (``CI`` set) and is skipped elsewhere."""

from __future__ import annotations

import importlib.util
import subprocess
import sys

import pytest
from conftest import REPO, require_tool


def _typed_fraction():
    spec = importlib.util.spec_from_file_location("typed_fraction",
                                                  REPO / "tools" / "typed_fraction.py")
    tf = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tf)
    return tf


def _mypy_config() -> dict:
    tomllib = pytest.importorskip("tomllib", reason="tomllib comes with Python 3.11")
    return tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["mypy"]


@pytest.mark.slow
def test_the_package_type_checks():
    require_tool("mypy", "mypy comes with the test dependency group")
    res = subprocess.run([sys.executable, "-m", "mypy", "--no-incremental",
                          "--cache-dir", "/dev/null"], cwd=REPO, capture_output=True, text=True,
                         timeout=600)
    assert res.returncode == 0, res.stdout[-4000:] + res.stderr[-2000:]
    assert "Success: no issues found" in res.stdout
    # every module of the package was checked (the core, its private modules, the layers)
    n_modules = len(list((REPO / "cshape").rglob("*.py")))
    assert f"in {n_modules} source files" in res.stdout, res.stdout[-500:]


def test_mypy_checks_every_module_and_refuses_untyped_functions():
    """The check covers the whole package, and an untyped function is an error wherever no
    override names its module (py.typed promises hints for all of cshape)."""
    cfg = _mypy_config()
    assert cfg["files"] == ["cshape"]
    assert cfg["disallow_untyped_defs"] is True
    for o in cfg.get("overrides", []):
        if o.get("disallow_untyped_defs") is False or o.get("ignore_errors"):
            modules = o["module"] if isinstance(o["module"], list) else [o["module"]]
            assert all(m.startswith("cshape.") and "*" not in m for m in modules), modules


def _untyped_modules() -> set[str]:
    """The cshape modules an override lets define untyped functions, as 'plots/collection'."""
    out = set()
    for o in _mypy_config().get("overrides", []):
        if o.get("disallow_untyped_defs") is False or o.get("ignore_errors"):
            modules = o["module"] if isinstance(o["module"], list) else [o["module"]]
            out |= {m.removeprefix("cshape.").replace(".", "/") for m in modules}
    return out


def test_every_public_parameter_of_the_core_is_typed():
    """tools/typed_fraction.py counts the parameters and returns of the public functions and
    classes of the core stages; all of them carry a type hint (the mypy check above only
    checks the hints that exist where an override allows untyped functions)."""
    tf = _typed_fraction()
    missing: list[str] = []
    for module in tf.CORE:
        tf.count(module, None, missing)
    assert missing == [], f"public names of the core without a type hint: {missing}"


def test_every_public_parameter_of_the_layers_is_typed():
    """The same count over the layer subpackages (plots, data, course, cli, batch,
    reproduce), but for the modules an override of [tool.mypy] still exempts."""
    tf = _typed_fraction()
    exempt = _untyped_modules()
    missing: list[str] = []
    checked = 0
    for layer in tf.LAYERS:
        for module in tf.layer_modules(layer, None):
            if module not in exempt:
                tf.count(module, None, missing)
                checked += 1
    assert checked >= 30  # the layers' modules were found
    assert missing == [], f"public names of the layers without a type hint: {missing}"
