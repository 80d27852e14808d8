"""Count the public parameters of the core modules, and of each layer subpackage, that carry
a type hint.

    python tools/typed_fraction.py [REV]

Public: module-level functions and classes not starting with '_', and the public methods
(plus ``__init__``) of public classes; ``self``/``cls`` are not counted; ``*args`` and
``**kwargs`` are; ``typing.overload`` stubs are not (their implementation is).  With REV,
the modules are read from that git revision.  The first table lists the core modules, the
second sums the modules of each layer subpackage (``cshape/<layer>/*.py``, private modules
included).
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

CORE = ["mesh", "readers", "fem", "spectrum", "descriptors", "compare", "index", "signatures",
        "shapes", "maps", "geodesics"]
# the layer subpackages: figures and viewer, data, course, command line, batch runs, reproduce
LAYERS = ["plots", "data", "course", "cli", "batch", "reproduce"]
ROOT = Path(__file__).resolve().parents[1]


def layer_modules(layer: str, rev: str | None) -> list[str]:
    """The modules of ``cshape/<layer>/`` as ``'<layer>/<name>'`` (read from ``rev`` if given)."""
    if rev is None:
        names = [p.name for p in (ROOT / "cshape" / layer).glob("*.py")]
    else:
        out = subprocess.run(["git", "-C", str(ROOT), "ls-tree", "--name-only",
                              f"{rev}:cshape/{layer}"],
                             check=True, capture_output=True, text=True).stdout
        names = [n for n in out.split() if n.endswith(".py")]
    return sorted(f"{layer}/{n[:-3]}" for n in names)


def source(module: str, rev: str | None) -> str:
    """The text of ``cshape/<module>.py``, or of every module of the package
    ``cshape/<module>/`` (a stage in several modules, such as ``descriptors``)."""
    if rev is None:
        path = ROOT / "cshape" / f"{module}.py"
        if path.is_file():
            return path.read_text()
        return "\n".join(p.read_text() for p in sorted((ROOT / "cshape" / module).glob("*.py"))
                         if p.name != "__init__.py")

    def show(path: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run(["git", "-C", str(ROOT), "show", f"{rev}:{path}"],
                              capture_output=True, text=True)

    one = show(f"cshape/{module}.py")
    if one.returncode == 0:
        return one.stdout
    out = subprocess.run(["git", "-C", str(ROOT), "ls-tree", "--name-only",
                          f"{rev}:cshape/{module}"], check=True, capture_output=True,
                         text=True).stdout
    return "\n".join(show(f"cshape/{module}/{n}").stdout for n in sorted(out.split())
                     if n.endswith(".py") and n != "__init__.py")


def params(fn: ast.FunctionDef | ast.AsyncFunctionDef, method: bool):
    a = fn.args
    every = a.posonlyargs + a.args + a.kwonlyargs
    if method and every and every[0].arg in ("self", "cls"):
        every = every[1:]
    every += [x for x in (a.vararg, a.kwarg) if x is not None]
    return every


def count(module: str, rev: str | None, missing: list[str] | None = None
          ) -> tuple[int, int, int, int]:
    """(parameters, typed, returns, typed) of the public names of ``cshape/<module>.py``;
    the untyped ones are appended to ``missing`` as ``module.function(parameter)``."""
    tree = ast.parse(source(module, rev))
    n = typed = n_ret = typed_ret = 0

    def visit(fn, method):
        nonlocal n, typed, n_ret, typed_ret
        if any(ast.unparse(d).endswith("overload") for d in fn.decorator_list):
            return  # typing.overload stubs: the implementation is counted
        ps = params(fn, method)
        n += len(ps)
        typed += sum(p.annotation is not None for p in ps)
        if missing is not None:
            missing.extend(f"{module}.{fn.name}({p.arg})" for p in ps if p.annotation is None)
        if fn.name != "__init__":
            n_ret += 1
            typed_ret += fn.returns is not None
            if missing is not None and fn.returns is None:
                missing.append(f"{module}.{fn.name} -> ?")

    for node in tree.body:
        public = not node.name.startswith("_") if hasattr(node, "name") else False
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and public:
            visit(node, False)
        elif isinstance(node, ast.ClassDef) and not node.name.startswith("_"):
            for sub in node.body:
                if isinstance(sub, (ast.FunctionDef, ast.AsyncFunctionDef)) and (
                        not sub.name.startswith("_") or sub.name == "__init__"):
                    visit(sub, True)
    return n, typed, n_ret, typed_ret


def main(argv: list[str]) -> int:
    rev = argv[0] if argv else None
    tot = [0, 0, 0, 0]
    print(f"{'module':<12} {'params':>7} {'typed':>6} {'returns':>8} {'typed':>6}")
    for m in CORE:
        c = count(m, rev)
        tot = [a + b for a, b in zip(tot, c, strict=True)]
        print(f"{m:<12} {c[0]:>7} {c[1]:>6} {c[2]:>8} {c[3]:>6}")
    print(f"{'total':<12} {tot[0]:>7} {tot[1]:>6} {tot[2]:>8} {tot[3]:>6}")
    print(f"typed parameters: {tot[1]}/{tot[0]} = {100 * tot[1] / max(tot[0], 1):.1f} %; "
          f"typed returns: {tot[3]}/{tot[2]} = {100 * tot[3] / max(tot[2], 1):.1f} %")
    print()
    tot = [0, 0, 0, 0]
    print(f"{'layer':<12} {'params':>7} {'typed':>6} {'returns':>8} {'typed':>6}")
    for layer in LAYERS:
        c = [0, 0, 0, 0]
        for m in layer_modules(layer, rev):
            c = [a + b for a, b in zip(c, count(m, rev), strict=True)]
        tot = [a + b for a, b in zip(tot, c, strict=True)]
        print(f"{layer:<12} {c[0]:>7} {c[1]:>6} {c[2]:>8} {c[3]:>6}")
    print(f"{'total':<12} {tot[0]:>7} {tot[1]:>6} {tot[2]:>8} {tot[3]:>6}")
    print(f"typed parameters: {tot[1]}/{tot[0]} = {100 * tot[1] / max(tot[0], 1):.1f} %; "
          f"typed returns: {tot[3]}/{tot[2]} = {100 * tot[3] / max(tot[2], 1):.1f} %")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
