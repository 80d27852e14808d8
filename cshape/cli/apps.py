"""``cshape demo`` and ``cshape reproduce``: the applications on the command line."""

from __future__ import annotations

import contextlib
import shutil
import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .output import print_warnings

if TYPE_CHECKING:
    import argparse
    import os
    from collections.abc import Iterator

    from ..data import Collection

    _SubParsers = argparse._SubParsersAction[Any]  # of the command line's parser class


def _demo(args: argparse.Namespace) -> int:
    import numpy as np

    from .. import compact_shape_dna, normalize, shape_dna, shapes

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


def add_demo(sub: _SubParsers) -> None:
    p = sub.add_parser("demo", help="print Shape-DNA and cShape-DNA of a few built-in shapes")
    p.add_argument("-N", type=int, default=100, help="number of eigenvalues (default 100)")
    p.add_argument("-M", type=int, default=4, help="crop half-width M (default 4)")
    p.set_defaults(func=_demo)


#: The default shapes of ``cshape reproduce``: the paper's models and poses for Section 3,
#: and the held-out instance of the creature benchmark for the retrieval tables.
REPRODUCE_COLLECTIONS = "paper-models,articulated"
REPRODUCE_BENCHMARK = "creatures"


def _load_named(spec: str, what: str, n_jobs: int = 1) -> Collection:
    """A manifest collection by name, or a folder of meshes (labels from sub-folders)."""
    from .. import data

    if spec in data.list_collections():
        return data.load_collection(spec, progress=True, n_jobs=n_jobs)
    if Path(spec).expanduser().is_dir():
        return data.load_folder(spec)
    raise ValueError(
        f"{what} {spec!r} is neither a collection of the data manifest (see `cshape data "
        "list`) nor a folder of meshes"
    )


@contextlib.contextmanager
def _new_folder(path: str | os.PathLike[str]) -> Iterator[None]:
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


def _reproduce(args: argparse.Namespace) -> int:
    from .. import data
    from ..reproduce import reproduce

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
    suite, which = None, args.suite
    if which is None:  # default: the held-out suite, unless the shapes were chosen
        which = "none" if args.folder or args.collections is not None else "held-out"
    if which != "none":
        from ..data.suite import SUITE

        pick = 0 if which == "dev" else 1
        suite = {b: _load_named(names[pick], "--suite", args.jobs) for b, names in SUITE.items()}
    levels = tuple(float(x) for x in args.noise.split(",") if x) if args.noise else ()
    quality = ("CM", "CS") if {"CM", "CS"} <= {r.name for r in records} else None
    with warnings.catch_warnings(record=True) as caught, _new_folder(args.out):
        warnings.simplefilter("always")
        res = reproduce(
            records, args.out, N=args.N, M=args.M, noise_levels=levels, quality=quality,
            n_jobs=args.jobs, progress=True, benchmark=benchmark, suite=suite,
        )
    print_warnings(caught, "reproduce", args.verbose)
    b, sizes = res["benchmark"], res.get("sizes") or {}
    scored = (f", {sizes['n_queries']} queries scored" if "n_queries" in sizes
              and sizes["n_queries"] != b["n_shapes"] else
              (f", {sizes['n_queries']} queries" if "n_queries" in sizes else ""))
    print(f"report written to {args.out}/report.md ({res['n_shapes']} shapes; retrieval on "
          f"{b['name']}, {b['n_shapes']} shapes{scored})")
    for line in res["verdict"]:
        print(line)
    if res.get("suite"):
        d = res["suite"]["default"]
        names = ", ".join(res["suite"]["benchmarks"])
        print(f"suite ({which} instances: {names}): every descriptor in report.md"
              + (f"; the default, {d['label']}: worst first tier {d['worst']:.3f}, mean "
                 f"{d['mean']:.3f}" if d else ""))
    return 0


def add_reproduce(sub: _SubParsers) -> None:
    p = sub.add_parser(
        "reproduce",
        help="run the paper's Section 3 experiments and write a report folder",
        description="Run the paper's Section 3 (distance matrices, M sweep, noise, mesh "
        "quality, size and time) on shape collections, the retrieval tables (every "
        "descriptor; every size M = 16 .. 1 with a verdict) on a labelled benchmark, every "
        "descriptor on every benchmark of the suite (creatures, identities, resolutions), and "
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
    p.add_argument("--suite", default=None, choices=("held-out", "dev", "none"),
                   help="the benchmark suite (creatures, identities, resolutions) scored for "
                   "every descriptor: its held-out instances (default), the development "
                   "ones, or none (the default when --collections or --folder is given)")
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
