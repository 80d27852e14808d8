"""Draw the house from the imports: cshape's modules, their layers, and the edges between them.

    python tools/import_graph.py            # layers and the imports between them, as text
    python tools/import_graph.py --modules  # every module-to-module import

Every ``import`` and ``from ... import`` of the package is read with :mod:`ast` (the ones inside
functions too), so the graph is what the code can import, not only what it imports at start.
:func:`violations` lists what breaks the architecture; ``tests/test_architecture.py`` asserts
it is empty.
"""

from __future__ import annotations

import argparse
import ast
from collections import defaultdict
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "cshape"

#: The package's entry points, which may serve layers: ``cshape`` (lazily, on first use) and
#: ``python -m cshape`` (the command line).
ENTRY_POINTS = ("cshape", "cshape.__main__")

#: The layers on top of the core (subpackages), and the applications.
LAYERS = ("plots", "data", "course", "cli")
APPLICATIONS = ("batch", "reproduce")


def module_name(path: Path) -> str:
    rel = path.relative_to(PACKAGE.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def group(module: str) -> str:
    """'core', or the layer / application a module belongs to."""
    parts = module.split(".")
    if len(parts) > 1 and parts[1] in LAYERS + APPLICATIONS:
        return parts[1]
    return "core"


def imports(path: Path) -> list[tuple[str, list[str], int]]:
    """(imported module, imported names, line) for every import of ``path`` into cshape."""
    mod = module_name(path)
    is_pkg = path.name == "__init__.py"
    out = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out += [(a.name, [], node.lineno) for a in node.names if a.name.startswith("cshape")]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = mod.split(".")
                base = base if is_pkg else base[:-1]
                base = base[: len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if not target.startswith("cshape"):
                continue
            names = [a.name for a in node.names]
            # `from cshape import data` imports the module cshape.data
            where = [(n, PACKAGE.parent / (target + "." + n).replace(".", "/")) for n in names]
            subs = [n for n, w in where if w.is_dir() or w.with_suffix(".py").is_file()]
            if subs:
                out += [(target + "." + n, [], node.lineno) for n in subs]
            rest = [n for n in names if n not in subs]
            if rest:
                out.append((target, rest, node.lineno))
    return out


def graph() -> dict[str, list[tuple[str, list[str], int]]]:
    return {module_name(p): imports(p) for p in sorted(PACKAGE.rglob("*.py"))}


def _resolve(target: str, modules: set[str]) -> str:
    while target not in modules and "." in target:
        target = target.rsplit(".", 1)[0]
    return target


def cycles(g) -> list[list[str]]:
    """Import circles between modules (a package's ``__init__`` re-exporting its own modules
    is not counted as a circle with them)."""
    mods = set(g)
    edges = defaultdict(set)
    for m, imps in g.items():
        for t, _names, _line in imps:
            t = _resolve(t, mods)
            if t != m and not m.startswith(t + ".") and not t.startswith(m + "."):
                edges[m].add(t)
    found, state, stack = [], {}, []

    def visit(m):
        state[m] = 1
        stack.append(m)
        for t in sorted(edges[m]):
            if state.get(t) == 1:
                found.append(stack[stack.index(t):] + [t])
            elif t not in state:
                visit(t)
        stack.pop()
        state[m] = 2

    for m in sorted(mods):
        if m not in state:
            visit(m)
    return found


def violations(g=None) -> list[str]:
    """What breaks the house rules: the core importing a layer or application, a module
    importing another group's private name or private module, and import circles."""
    g = graph() if g is None else g
    out = []
    for m, imps in g.items():
        src = group(m)
        for t, names, line in imps:
            dst = group(t)
            if src == "core" and dst != "core" and m not in ENTRY_POINTS:
                out.append(f"{m}:{line} the core imports the {dst} layer ({t})")
            if dst != src and dst != "core":
                private = [n for n in names if n.startswith("_")]
                private_mod = [p for p in t.split(".")[2:] if p.startswith("_")]
                if private or private_mod:
                    out.append(f"{m}:{line} imports a private name of {dst}: {t} {private}")
    for c in cycles(g):
        out.append("import circle: " + " -> ".join(c))
    return out


def layer_edges(g=None) -> dict[tuple[str, str], int]:
    g = graph() if g is None else g
    count = defaultdict(int)
    for m, imps in g.items():
        for t, _n, _l in imps:
            a, b = group(m), group(t)
            if a != b and m not in ENTRY_POINTS:
                count[(a, b)] += 1
    return dict(count)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--modules", action="store_true", help="list every module-to-module import")
    args = ap.parse_args(argv)
    g = graph()
    if args.modules:
        for m, imps in g.items():
            for t in sorted({_resolve(t, set(g)) for t, _n, _l in imps}):
                print(f"{m} -> {t}")
        return 0
    order = ["cli", "course", "plots", "data", "reproduce", "batch", "core"]
    print("groups (top to bottom) and the imports between them:")
    for a in order:
        outs = [f"{b} ({n})" for (x, b), n in sorted(layer_edges(g).items()) if x == a]
        print(f"  {a:<10} -> {', '.join(outs) if outs else 'nothing in cshape'}")
    v = violations(g)
    print(f"violations: {len(v)}")
    for line in v:
        print("  " + line)
    return 1 if v else 0


if __name__ == "__main__":
    raise SystemExit(main())
