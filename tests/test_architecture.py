"""The package's architecture, checked: the house drawn from the imports (tools/import_graph.py),
a light ``import cshape``, one line naming the extra when a layer's dependency is missing, the
command line's one static registry, and the public names that issues fixed."""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import pkgutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]


def _import_graph():
    path = REPO / "tools" / "import_graph.py"
    spec = importlib.util.spec_from_file_location("import_graph", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_the_core_imports_no_layer_and_there_are_no_circles():
    ig = _import_graph()
    assert ig.violations() == []
    edges = ig.layer_edges()
    assert not any(a == "core" for a, _b in edges), edges
    # the applications and layers do use the core
    for group in ("batch", "reproduce", "plots", "data", "cli"):
        assert edges.get((group, "core"), 0) > 0


def test_import_graph_finds_what_breaks_the_rules():
    """The checker is not vacuous: a core module importing a layer, a private name across
    layers, and a circle are each reported."""
    ig = _import_graph()
    g = {
        "cshape.fem": [("cshape.plots.figures", ["plot_mesh"], 3)],
        "cshape.plots.figures": [("cshape.data.store", ["_cache_file"], 5)],
        "cshape.data.store": [("cshape.fem", ["fem"], 7)],
    }
    v = ig.violations(g)
    assert any("the core imports the plots layer" in s for s in v)
    assert any("private name of data" in s for s in v)
    assert any(s.startswith("import circle") for s in v)


def test_import_cshape_is_light():
    code = ("import sys, cshape; heavy = ('matplotlib', 'plotly', 'ipywidgets', 'sklearn', "
            "'pymeshlab', 'yaml', 'nbformat', 'dask', 'pooch', 'jupyterlab', 'tqdm'); "
            "print(sorted({m.split('.')[0] for m in sys.modules} & set(heavy)))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "[]", r.stdout
    # the layers are served on first use
    import cshape

    assert cshape.describe is importlib.import_module("cshape.batch").describe
    assert cshape.DescriptorTable is importlib.import_module("cshape.batch").DescriptorTable
    assert cshape.data is importlib.import_module("cshape.data")
    with pytest.raises(AttributeError, match="no attribute 'no_such_name'"):
        cshape.no_such_name  # noqa: B018


class _Missing(importlib.abc.MetaPathFinder):
    """Makes the named top-level packages unimportable, as when an extra is not installed."""

    def __init__(self, names):
        self.names = set(names)

    def find_spec(self, fullname, path=None, target=None):
        if fullname.split(".")[0] in self.names:
            raise ModuleNotFoundError(f"No module named {fullname!r}", name=fullname)
        return None


@pytest.mark.parametrize("layer, missing, extra", [
    ("cshape.plots", "matplotlib", "plots"),
    ("cshape.plots", "plotly", "plots"),
])
def test_a_layer_without_its_extra_names_the_extra(layer, missing, extra, monkeypatch):
    saved = {m: sys.modules.pop(m) for m in list(sys.modules)
             if m == layer or m.startswith(layer + ".") or m.split(".")[0] == missing}
    blocker = _Missing([missing])
    sys.meta_path.insert(0, blocker)
    try:
        with pytest.raises(ImportError) as info:
            importlib.import_module(layer)
        msg = str(info.value)
        assert "\n" not in msg
        assert f"pip install 'cshape[{extra}]'" in msg and missing in msg
    finally:
        sys.meta_path.remove(blocker)
        for m in [m for m in sys.modules if m == layer or m.startswith(layer + ".")]:
            del sys.modules[m]
        sys.modules.update(saved)


def test_the_command_line_has_one_static_registry():
    from cshape.cli.registry import SUBCOMMANDS, build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    names = list(sub.choices)
    for cmd in ("demo", "reproduce", "describe", "info", "query", "data", "notebooks",
                "assignments", "lessons"):
        assert cmd in names
    # every registered function adds at least one command, and nothing else adds any
    assert len(SUBCOMMANDS) <= len(names)
    import cshape.cli.registry as main_mod

    src = Path(main_mod.__file__).read_text()
    assert "__import__" not in src and "importlib" not in src


@pytest.mark.parametrize("old", ["cshape.viewer", "cshape.widgets", "cshape.creatures",
                                 "cshape.teaching", "cshape.notebooks_run",
                                 "cshape.assignments", "cshape.commands"])
def test_no_alias_machinery_for_module_names_no_issue_fixed(old):
    # the package was never released: the layers' modules have one name each
    sys.modules.pop(old, None)
    with pytest.raises(ModuleNotFoundError, match=old.replace(".", r"\.")):
        importlib.import_module(old)


def test_the_descriptor_stage_is_one_package_of_formulas_and_the_recipe():
    """``cshape.descriptors`` is one package, the formulas (``formulas``) and the recipe
    (``recipe``), both of the core; no module of a confusable name stands beside it."""
    import cshape

    assert not (REPO / "cshape" / "descriptor.py").exists()
    assert not (REPO / "cshape" / "descriptors.py").exists()
    assert cshape.descriptors.__file__.endswith("__init__.py")
    assert {m.name for m in pkgutil.iter_modules(cshape.descriptors.__path__)} == {
        "formulas", "recipe"}
    ig = _import_graph()
    assert ig.group("cshape.descriptors.recipe") == "core"
    assert ig.group("cshape.descriptors.formulas") == "core"


def test_public_names_that_issues_fixed_still_work():
    import cshape
    from cshape import plots
    from cshape.batch import DescriptorTable, describe

    assert cshape.describe is describe and cshape.DescriptorTable is DescriptorTable
    for name in ("plot_mds", "plot_weyl", "view_mesh", "plot_m_sweep", "plot_distance_matrix"):
        assert callable(getattr(plots, name))
    assert callable(cshape.data.load_collection) and callable(cshape.data.load_folder)
    assert callable(importlib.import_module("cshape.data.variants").marching_cubes)
