"""Every public docstring passes numpydoc's validation, with the checks the docs build runs.

The public objects are every function and class named in an ``__all__`` of a public module
of cshape (no module path component with a leading underscore), and the public methods,
properties and ``__call__`` that a public class defines itself: what the API pages show
(``docs/_templates/autosummary/class.rst`` documents a class's own members).  The checks and
the excluded names are read from ``docs/conf.py`` (``numpydoc_validation_checks``,
``numpydoc_validation_exclude``), so the docs build and this test use one list.

One test per source file that defines public objects, so a failure names the file to fix and
lists every error in it, one line per error: ``name: CODE message``.
"""

from __future__ import annotations

import ast
import functools
import importlib
import inspect
import pkgutil
import re
from pathlib import Path

import pytest

import cshape

REPO = Path(__file__).resolve().parents[1]
PACKAGE = Path(cshape.__file__).resolve().parent


def _conf_settings() -> tuple[set[str], set[str]]:
    """``numpydoc_validation_checks`` and ``numpydoc_validation_exclude`` of docs/conf.py."""
    tree = ast.parse((REPO / "docs" / "conf.py").read_text(encoding="utf-8"))
    found: dict[str, set[str]] = {}
    for node in tree.body:
        if isinstance(node, ast.Assign) and len(node.targets) == 1 \
                and isinstance(node.targets[0], ast.Name) \
                and node.targets[0].id in ("numpydoc_validation_checks",
                                           "numpydoc_validation_exclude"):
            found[node.targets[0].id] = set(ast.literal_eval(node.value))
    assert "numpydoc_validation_checks" in found, \
        "docs/conf.py sets no literal numpydoc_validation_checks"
    return found["numpydoc_validation_checks"], found.get("numpydoc_validation_exclude", set())


def _public_modules() -> list:
    """cshape and its public submodules (no ``_private`` path component, no ``__main__``)."""
    modules = [cshape]
    for info in pkgutil.walk_packages(cshape.__path__, "cshape."):
        if any(part.startswith("_") for part in info.name.split(".")[1:]):
            continue
        modules.append(importlib.import_module(info.name))
    return modules


def _members(cls: type) -> list[tuple[str, object]]:
    """The public methods, properties and ``__call__`` that ``cls`` defines itself.

    What autodoc's ``:members:`` documents on a class page (members without a docstring
    too: they fail GL08 here, where autodoc would leave them out silently).
    """
    out = []
    for name, value in vars(cls).items():
        if name.startswith("_") and name != "__call__":
            continue
        if isinstance(value, (staticmethod, classmethod)):
            value = value.__func__
        if inspect.isfunction(value) or isinstance(value, (property, functools.cached_property)):
            out.append((name, value))
    return out


def _source(obj: object) -> str:
    """The file defining ``obj``, relative to the repository (``cshape/fem.py``)."""
    try:
        path = Path(inspect.getsourcefile(inspect.unwrap(obj)) or "").resolve()
    except TypeError:
        return "<no source>"
    try:
        return path.relative_to(PACKAGE.parent).as_posix()
    except ValueError:
        return str(path)


def _owner(obj: object, listed: list[str]) -> str:
    """The public name an object is documented under: the listing by the module that
    defines it (the deepest such module), else the first, as docs/_ext/apipages.py does."""
    defined = getattr(obj, "__module__", "") or ""
    fits = [n for n in listed if defined == n.rsplit(".", 1)[0]
            or defined.startswith(n.rsplit(".", 1)[0] + ".")]
    return max(fits, key=lambda n: len(n.rsplit(".", 1)[0])) if fits else listed[0]


def public_objects() -> dict[str, list[tuple[str, object]]]:
    """{source file: [(full public name, object), ...]}, every public object once."""
    listed: dict[int, list[str]] = {}
    objects: dict[int, object] = {}
    for mod in _public_modules():
        for name in getattr(mod, "__all__", []):
            obj = getattr(mod, name)
            if inspect.isclass(obj) or inspect.isfunction(obj):
                # modules have their own sections; constants are described there
                listed.setdefault(id(obj), []).append(f"{mod.__name__}.{name}")
                objects[id(obj)] = obj
    by_file: dict[str, list[tuple[str, object]]] = {}
    for key, obj in objects.items():
        full = _owner(obj, listed[key])
        entries = [(full, obj)]
        if inspect.isclass(obj):
            entries += [(f"{full}.{m}", value) for m, value in _members(obj)]
        by_file.setdefault(_source(obj), []).extend(entries)
    return by_file


PUBLIC = public_objects()


def _errors(entries: list[tuple[str, object]]) -> list[str]:
    validate = pytest.importorskip("numpydoc.validate",
                                   reason="numpydoc (the test and docs groups) is not installed")

    checks, exclude = _conf_settings()
    checks = validate.get_validation_checks(checks)
    excluder = re.compile("|".join(exclude)) if exclude else None
    lines = []
    for full, _ in entries:
        if excluder is not None and excluder.search(full):
            continue
        report = validate.validate(full)
        lines += [f"{full}: {code} {msg}" for code, msg in sorted(report["errors"])
                  if code in checks]
    return lines


# numpydoc reads every attribute of an ipywidgets class; ipywidgets warns of its own
# deprecated class attributes when they are read
@pytest.mark.filterwarnings("ignore:Widget\\..* is deprecated:DeprecationWarning")
@pytest.mark.parametrize("source", sorted(PUBLIC))
def test_public_docstrings_pass_numpydoc_validation(source):
    errors = _errors(PUBLIC[source])
    assert not errors, (f"{len(errors)} numpydoc validation errors in {source} "
                        f"(checks of docs/conf.py):\n" + "\n".join(errors))


def test_the_walk_finds_the_public_surface():
    # the walk sees the core's entry points, a layer's functions and a class's methods, each
    # object once, under the name of the module that defines it
    found = {full: obj for entries in PUBLIC.values() for full, obj in entries}
    objects = [id(o) for o in found.values()]
    assert len(objects) == len(set(objects))
    assert {id(cshape.shape_dna), id(cshape.Mesh), id(cshape.fem_matrices)} <= set(objects)
    assert found["cshape.mesh.Mesh"] is cshape.Mesh
    assert any(n.startswith("cshape.mesh.Mesh.") for n in found)
    assert any(n.startswith("cshape.plots.") for n in found)
    assert not any("._" in n.replace(".__call__", "") for n in found)


def test_the_exclusions_hide_no_public_function_class_or_method():
    # numpydoc_validation_exclude is for what cannot carry a numpydoc docstring (the
    # constants' #: comments), never a way to skip a function, a class or a method
    _, exclude = _conf_settings()
    hidden = [full for entries in PUBLIC.values() for full, _ in entries
              if any(re.search(pattern, full) for pattern in exclude)]
    assert not hidden, f"numpydoc_validation_exclude of docs/conf.py hides {hidden}"
    # and it does exclude the constants it is there for
    assert any(re.search(p, "cshape.data.MESH_SUFFIXES") for p in exclude)


def test_the_checks_are_those_of_the_docs_build():
    pytest.importorskip("numpydoc.validate")
    from numpydoc.validate import ERROR_MSGS, get_validation_checks

    checks, _ = _conf_settings()
    resolved = get_validation_checks(checks)
    # every check but the excluded ones: a missing summary, undocumented parameters and a
    # missing docstring are errors
    assert {"GL08", "SS01", "PR01", "PR02", "RT01"} <= resolved
    assert {"SA01", "EX01", "ES01"}.isdisjoint(resolved)
    assert resolved < set(ERROR_MSGS)
