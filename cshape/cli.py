"""Command line: ``cshape demo``, ``cshape reproduce`` and the sub-commands other modules
register (:mod:`cshape.commands`: ``describe``, ``info``, ``query``, ``data``; ...).

Sub-commands are small functions ``add_<name>(subparsers)`` that define their parser and
set ``func``; :func:`main` wires them up.  Heavy imports happen inside the commands.

The one error path: every expected failure (bad input, a missing or unreadable file, an
offline or failed download, a missing optional dependency) ends in one line on stderr,
``cshape <command>: error: <message>``, and exit status 2, without a traceback; Ctrl-C ends
in ``cshape <command>: interrupted`` and exit status 130.  Anything else is a bug and keeps
its traceback.
"""

from __future__ import annotations

import argparse
import contextlib
import shutil
import sys
import warnings
from pathlib import Path

__all__ = ["EXPECTED_ERRORS", "CommandError", "main", "one_line", "print_warnings"]


def _demo(args) -> int:
    import numpy as np

    from . import compact_shape_dna, normalize, shape_dna, shapes

    np.set_printoptions(precision=3, suppress=True, linewidth=100)
    cases = {
        "unit sphere (icosphere, 2562 vertices)": shapes.icosphere(4),
        "cube (surface, 1538 vertices)": shapes.cube(16),
        "torus R=1, r=0.4 (2048 vertices)": shapes.torus(64, 32),
    }
    N, M = args.N, args.M
    for name, mesh in cases.items():
        lam = shape_dna(mesh, N=N)
        S = compact_shape_dna(lam, M=M, N=N, area=mesh.area)
        print(f"== {name}: area {mesh.area:.4f}")
        print(f"Shape-DNA, first 10 of N={N}:           ", lam[:10])
        print("area-normalised, first 10:              ", normalize(lam, mesh.area)[:10])
        print(f"cShape-DNA |Lambda_k|, k=-{M}..{M} (2M+1={2 * M + 1}):", np.abs(S))
    print("\nThe exact unit-sphere spectrum is 0, 2 (x3), 6 (x5), 12 (x7), ...")
    return 0


def add_demo(sub):
    p = sub.add_parser("demo", help="print Shape-DNA and cShape-DNA of a few built-in shapes")
    p.add_argument("-N", type=int, default=100, help="number of eigenvalues (default 100)")
    p.add_argument("-M", type=int, default=4, help="crop half-width M (default 4)")
    p.set_defaults(func=_demo)


#: The default shapes of ``cshape reproduce``: the paper's models and poses for Section 3,
#: and the held-out instance of the creature benchmark for the retrieval tables.
REPRODUCE_COLLECTIONS = "paper-models,articulated"
REPRODUCE_BENCHMARK = "creatures"


def _load_named(spec, what, n_jobs=1):
    """A manifest collection by name, or a folder of meshes (labels from sub-folders)."""
    from . import data

    if spec in data.list_collections():
        return data.load_collection(spec, progress=True, n_jobs=n_jobs)
    if Path(spec).expanduser().is_dir():
        return data.load_folder(spec)
    raise ValueError(
        f"{what} {spec!r} is neither a collection of the data manifest (see `cshape data "
        "list`) nor a folder of meshes"
    )


@contextlib.contextmanager
def _new_folder(path):
    """Remove ``path`` again (with what was written into it) if it is new and the block
    fails: a failed or interrupted command leaves no half-written report folder.  The
    folders above it that the block created and left empty go too."""
    path = Path(path)
    new = [q for q in [path, *path.parents] if not q.exists()]
    try:
        yield
    except BaseException:
        if new:
            shutil.rmtree(new[0], ignore_errors=True)
            for q in new[1:]:
                try:
                    q.rmdir()
                except OSError:
                    break
        raise


def _reproduce(args) -> int:
    from . import data
    from .reproduce import reproduce

    records = []
    if args.folder:
        records.extend(data.load_folder(args.folder).items)
    collections = args.collections if args.collections is not None else REPRODUCE_COLLECTIONS
    for name in [c for c in collections.split(",") if c] if not args.folder else []:
        records.extend(_load_named(name, "--collections", args.jobs).items)
    if args.limit:
        records = records[: args.limit]
    bench = args.benchmark
    if bench is None:  # default: the creatures, unless the shapes were chosen
        bench = "same" if args.folder or args.collections is not None else REPRODUCE_BENCHMARK
    benchmark = (None if bench.lower() == "same"
                 else _load_named(bench, "--benchmark", args.jobs))
    levels = tuple(float(x) for x in args.noise.split(",") if x) if args.noise else ()
    quality = ("CM", "CS") if {"CM", "CS"} <= {r.name for r in records} else None
    with warnings.catch_warnings(record=True) as caught, _new_folder(args.out):
        warnings.simplefilter("always")
        res = reproduce(
            records, args.out, N=args.N, M=args.M, noise_levels=levels, quality=quality,
            n_jobs=args.jobs, progress=True, benchmark=benchmark,
        )
    print_warnings(caught, "reproduce", args.verbose)
    print(f"report written to {args.out}/report.md ({res['n_shapes']} shapes; retrieval on "
          f"{res['benchmark']['name']}, {res['benchmark']['n_shapes']} shapes)")
    for line in res["verdict"]:
        print(line)
    return 0


def add_reproduce(sub):
    p = sub.add_parser(
        "reproduce",
        help="run the paper's Section 3 experiments and write a report folder",
        description="Run the paper's Section 3 (distance matrices, M sweep, noise, mesh "
        "quality, size and time) on shape collections, the retrieval tables (every "
        "descriptor; every size M = 16 .. 1 with a verdict) on a labelled benchmark, and "
        "write report.md, results.json and the figures.",
    )
    p.add_argument("--collections", default=None,
                   help="comma-separated collections of the data manifest for Section 3 "
                   f"(default: {REPRODUCE_COLLECTIONS}, generated offline)")
    p.add_argument("--folder", help="use a folder of meshes instead (labels from sub-folders)")
    p.add_argument("--benchmark", default=None,
                   help="labelled collection (manifest name or folder) for the retrieval "
                   f"tables, or 'same' for the Section 3 shapes (default: {REPRODUCE_BENCHMARK}"
                   ", the held-out creature benchmark; 'same' when --collections or --folder "
                   "is given)")
    p.add_argument("--out", default="out/reproduce", help="report folder (default out/reproduce)")
    p.add_argument("-N", type=int, default=100, help="Shape-DNA length (default 100)")
    p.add_argument("-M", type=int, default=16, help="cShape-DNA half-width (default 16)")
    p.add_argument("--noise", default="0.5,1,2,4,10",
                   help="noise levels of Section 3.3, comma-separated ('' to skip)")
    p.add_argument("--jobs", type=int, default=2,
                   help="local worker processes for eigensolves and generated meshes (default 2)")
    p.add_argument("--limit", type=int, default=0,
                   help="use only the first LIMIT shapes for Section 3 (not the benchmark)")
    p.add_argument("-v", "--verbose", action="store_true", help="list every warning")
    p.set_defaults(func=_reproduce)


class _Parser(argparse.ArgumentParser):
    """An argument parser whose usage errors are one line too (argparse prints the usage
    first); sub-command parsers are of this class as well."""

    def error(self, message):
        print(f"{self.prog}: error: {' '.join(message.split())}; see `{self.prog} --help`",
              file=sys.stderr)
        sys.exit(2)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="cshape", description="Shape-DNA and compact Shape-DNA of triangle meshes"
    )
    sub = parser.add_subparsers(dest="command", required=True)
    add_demo(sub)
    add_reproduce(sub)
    # further sub-commands (data, reproduce, notebooks, ...) register here
    for modname, fname in _EXTRA:
        try:
            mod = __import__(f"cshape.{modname}", fromlist=[fname])
        except ImportError:  # pragma: no cover - module not written yet
            continue
        getattr(mod, fname)(sub)
    return parser


#: (module, function) pairs that add sub-commands; each module imports lazily.
_EXTRA: list[tuple[str, str]] = [
    ("commands", "add_commands"),
    ("notebooks_run", "add_run_notebooks"),
]


class CommandError(Exception):
    """An expected failure of a command; :func:`main` prints its message on one line."""


#: Expected failures: bad values, files (OSError covers FileNotFoundError, PermissionError,
#: a full disk and network errors, requests' and pooch's included), a missing optional
#: dependency, a failed batch run.  KeyError: a name not found (its message is args[0]).
EXPECTED_ERRORS = (CommandError, ValueError, OSError, ImportError, KeyError, RuntimeError)


def one_line(exc: BaseException) -> str:
    """The message of ``exc`` on one line (whitespace runs collapsed), never empty."""
    msg = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
    text = " ".join(str(msg).split())
    return text or type(exc).__name__


#: Warnings listed one by one before a command summarises the rest (``-v``: all).
MAX_WARNINGS = 10


def print_warnings(caught, command, verbose=False, skip=()):
    """Print recorded warnings on stderr, one line each: ``cshape <command>: warning: ...``.

    Repeated messages once; messages starting with a prefix in ``skip`` left out; at most
    :data:`MAX_WARNINGS` unless ``verbose``, then a count of the rest.
    """
    msgs = [" ".join(str(w.message).split()) for w in caught]
    msgs = [m for m in dict.fromkeys(msgs) if not m.startswith(skip)]
    shown = msgs if verbose else msgs[:MAX_WARNINGS]
    for m in shown:
        print(f"cshape {command}: warning: {m}", file=sys.stderr)
    if len(msgs) > len(shown):
        print(f"cshape {command}: {len(msgs) - len(shown)} more warnings (-v lists them all)",
              file=sys.stderr)


def main(argv=None) -> int:
    """Run the ``cshape`` command line; returns the exit status (0, 2 on an expected error)."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except KeyboardInterrupt:
        print(f"cshape {args.command}: interrupted", file=sys.stderr)
        return 130
    except EXPECTED_ERRORS as exc:
        print(f"cshape {args.command}: error: {one_line(exc)}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
