"""The examples in the core's docstrings run, and print what they say (the fast tier).

The core is every module that tools/import_graph.py counts as core: ``cshape/*.py`` and the
core's subpackages, not the layers that need optional extras.  ``python -m cshape`` (the
command line) is an entry point, not a module with examples.
"""

from __future__ import annotations

import doctest
import importlib
import importlib.util

import pytest
from conftest import REPO

#: Modules that are not imported to look for examples: running them is what they do.
_ENTRY_POINTS = {"cshape.__main__"}

_FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE


def core_modules() -> list[str]:
    """The names of the core's modules (read from the files: no layer is imported)."""
    spec = importlib.util.spec_from_file_location("import_graph",
                                                  REPO / "tools" / "import_graph.py")
    ig = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ig)
    names = [ig.module_name(p) for p in sorted(ig.PACKAGE.rglob("*.py"))]
    return sorted(n for n in names if n not in _ENTRY_POINTS and ig.group(n) == "core")


def _examples(module: str) -> list[doctest.DocTest]:
    mod = importlib.import_module(module)
    finder = doctest.DocTestFinder(exclude_empty=True)
    return [t for t in finder.find(mod, module) if t.examples]


CORE = core_modules()
#: The core modules with examples, and how many each has.
EXAMPLES = {m: sum(len(t.examples) for t in _examples(m)) for m in CORE}

#: Examples known to print something else than they say, with the reason; each is a strict
#: xfail, so the entry must go once the docstring is fixed.
_STALE: dict[str, str] = {}


def test_the_core_is_found_and_the_layers_are_not():
    assert {"cshape", "cshape.mesh", "cshape.readers", "cshape.fem", "cshape.spectrum"} <= set(CORE)
    assert not [m for m in CORE if m.split(".")[1:2] in (
        ["plots"], ["data"], ["course"], ["cli"], ["batch"], ["reproduce"])]


def test_the_core_has_examples():
    """A floor, so that a finder that finds nothing cannot pass for a clean run."""
    assert sum(EXAMPLES.values()) >= 40, EXAMPLES
    gone = set(_STALE) - set(CORE)
    assert not gone, f"_STALE names modules that are gone: {sorted(gone)}; remove them"


@pytest.mark.parametrize("module", [
    pytest.param(m, marks=pytest.mark.xfail(reason=_STALE[m], strict=True)) if m in _STALE
    else m for m in CORE if EXAMPLES[m]])
def test_docstring_examples_run(module):
    failures: list[str] = []
    runner = doctest.DocTestRunner(optionflags=_FLAGS)
    for t in _examples(module):
        runner.run(t, out=failures.append)
    assert runner.failures == 0, "\n".join(failures)
