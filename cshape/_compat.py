"""Old module names, kept importable: ``cshape.viewer`` is now ``cshape.plots.viewer``, ...

A meta-path finder maps each old name to its new module (the same module object, so
``cshape.viewer.view_mesh is cshape.plots.viewer.view_mesh``) and warns once with a
``DeprecationWarning`` that names the new place.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys
import warnings

#: old module name -> new module name
MOVED = {
    "cshape.viewer": "cshape.plots.viewer",
    "cshape.widgets": "cshape.plots.widgets",
    "cshape.variants": "cshape.data.variants",
    "cshape.creatures": "cshape.data.creatures",
    "cshape.notebooks_run": "cshape.course.lessons",
    "cshape.assignments": "cshape.course.assignments",
    "cshape.teaching": "cshape.course.teaching",
    "cshape.commands": "cshape.cli.explore",
}


class _Alias(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    def find_spec(self, fullname, path=None, target=None):
        if fullname not in MOVED:
            return None
        return importlib.machinery.ModuleSpec(fullname, self)

    def create_module(self, spec):
        new = MOVED[spec.name]
        warnings.warn(f"{spec.name} moved to {new}; import that instead", DeprecationWarning,
                      stacklevel=2)
        return importlib.import_module(new)

    def exec_module(self, module):
        pass


def install() -> None:
    """Add the alias finder to ``sys.meta_path`` once."""
    if not any(isinstance(f, _Alias) for f in sys.meta_path):
        sys.meta_path.insert(0, _Alias())
