"""The public surface stays small: the names of every ``__all__`` of the package, counted.

A public name is a promise to keep; the top level holds the entry points a user needs and
every other public name lives in its stage's module or layer.  Raising a limit here is a
decision to write down, not a number to bump.
"""

from __future__ import annotations

import ast
import importlib
from pathlib import Path

import cshape

PACKAGE = Path(cshape.__file__).parent
TOP_LEVEL_LIMIT = 30
ALL_LIMIT = 130


def _all_lists():
    out = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        for node in ast.parse(path.read_text(encoding="utf-8")).body:
            if isinstance(node, ast.Assign) and any(getattr(t, "id", None) == "__all__"
                                                    for t in node.targets):
                module = ".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts)
                out[module.removesuffix(".__init__")] = ast.literal_eval(node.value)
    return out


def test_the_top_level_holds_at_most_thirty_entry_points():
    assert len(cshape.__all__) <= TOP_LEVEL_LIMIT, sorted(cshape.__all__)
    assert len(set(cshape.__all__)) == len(cshape.__all__)
    for name in cshape.__all__:
        assert getattr(cshape, name) is not None


def test_the_package_has_at_most_130_public_names():
    lists = _all_lists()
    names = {n for names in lists.values() for n in names}
    assert len(names) <= ALL_LIMIT, (len(names), {m: len(v) for m, v in lists.items()})


def test_private_modules_declare_no_public_names():
    private = [m for m in _all_lists() if any(p.startswith("_") for p in m.split(".")[1:])]
    assert private == []


def test_every_listed_name_exists_and_is_not_private():
    for module, names in _all_lists().items():
        if module.startswith("cshape.course") and not _has("nbgrader") and "grading" in module:
            continue
        mod = importlib.import_module(module)
        for name in names:
            assert not name.startswith("_"), (module, name)
            assert hasattr(mod, name), (module, name)


def test_one_public_way_to_the_eigenpairs():
    """``eigenbasis`` gives the eigenpairs; no second public function computes them."""
    import cshape.spectrum

    assert "eigenpairs" not in cshape.__all__ and not hasattr(cshape, "eigenpairs")
    assert "eigenpairs" not in cshape.spectrum.__all__
    b = cshape.eigenbasis(cshape.shapes.icosphere(1), N=4)
    assert b.lam.shape == (4,) and b.phi.shape == (42, 4)


def _has(module):
    try:
        importlib.import_module(module)
    except ImportError:
        return False
    return True
