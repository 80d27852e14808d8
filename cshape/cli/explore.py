"""The commands of the command line on meshes and collections: ``cshape describe``,
``cshape info``, ``cshape query`` and ``cshape data``.

* ``cshape describe PATH... [--out table.csv|table.npz]`` - Shape-DNA / cShape-DNA of every
  mesh under the paths (files, folders searched recursively, globs; class labels from
  sub-folders), through :func:`cshape.describe` (cached, parallel, Dask) into a
  :class:`cshape.DescriptorTable`;
* ``cshape info MESH`` - size, area, topology, triangle quality and what the repair would
  change, from :mod:`cshape.mesh` (:class:`cshape.Mesh`, :func:`cshape.repair_mesh`) and
  :func:`cshape.data.quality.mesh_quality`;
* ``cshape query TABLE MESH_OR_NAME -k 5`` - the nearest shapes of a table, with their
  distances (:class:`cshape.DescriptorIndex`); with ``--plot FILE --meshes PATH`` also the
  query and its neighbours as thumbnails (:func:`cshape.plots.overview.plot_neighbour_strip`,
  .png/.svg/.pdf, or :func:`~cshape.plots.overview.neighbour_strip_plotly`, .html);
* ``cshape data {list, build NAME, path NAME}`` - the shape collections of
  :mod:`cshape.data`.

Only argument handling and printing live here; the work is done by the pipeline's
functions.  Expected failures raise :class:`cshape.cli.output.CommandError` (or the pipeline's
``ValueError`` / ``OSError``), which :func:`cshape.cli.registry` prints on one line with exit
status 2.
"""

from __future__ import annotations

import contextlib
import dataclasses
import glob
import json
import os
import sys
import time
import warnings
from collections import Counter
from pathlib import Path
from typing import TYPE_CHECKING, Any, TextIO

from .output import CommandError, print_warnings

if TYPE_CHECKING:
    import argparse
    from collections.abc import Iterator, Sequence

    import numpy as np

    from ..batch import DescriptorTable
    from ..descriptors import Descriptor

    _SubParsers = argparse._SubParsersAction[Any]  # of the command line's parser class

# ============================================================================ inputs
def _mesh_suffixes() -> tuple[str, ...]:
    from ..readers import MESH_SUFFIXES

    return tuple(MESH_SUFFIXES)


def _is_mesh_name(path: Path) -> bool:
    """True for a file name ending in a mesh suffix (also under ``.gz``)."""
    from ..readers import split_mesh_name

    return split_mesh_name(path)[1] in _mesh_suffixes()


def _stem(path: Path) -> str:
    from ..readers import split_mesh_name

    return split_mesh_name(path)[0]


def collect_mesh_files(paths: Sequence[str | os.PathLike[str]] | None
                       ) -> list[tuple[str, str, Path]]:
    """The meshes named by command-line paths, as ``(name, label, path)`` records.

    Parameters
    ----------
    paths : sequence of str
        Each a mesh file (read whatever its suffix), a folder (searched recursively for
        mesh files by :func:`cshape.data.load_folder`; hidden files skipped) or a glob
        pattern (``*``, ``?``, ``[...]``; ``**`` crosses folders) whose matching mesh files
        and folders are taken.

    Returns
    -------
    list of (str, str, Path)
        In the order of ``paths`` (a folder's files sorted), each file once.  ``name`` is the
        file stem; where stems repeat, the path relative to the folder it was found in, else
        to the folder all the files of that stem are in (without the suffix, unless only the
        suffix differs); ``label`` is the first sub-folder below the folder given and, for a
        file or glob match, the name of the folder holding the file.  Files directly in a
        folder given are labelled by that folder's name when several folders or files are
        given (``cats/ dogs/``), and are in no class (``''``) when that folder is the only
        path: one flat folder has no classes.

    Raises
    ------
    FileNotFoundError
        If a path is neither a file, a folder, nor a pattern matching anything.
    ValueError
        If a folder or a pattern holds no mesh file, or no path was given.
    """
    from ..data import load_folder

    found: list[tuple[Path, str, Path]] = []  # (file, label, base for relative names)
    flat: list[int] = []  # rows of files directly in a folder given (labelled at the end)
    sources: list[Path] = []  # the folders and files given (or matched by a pattern)

    def add_folder(folder: Path) -> None:
        top = folder.resolve()
        sources.append(top)
        for item in load_folder(folder):
            assert item.path is not None  # the items of a folder are its files
            path = Path(item.path)
            if path.resolve().parent == top:
                flat.append(len(found))
                found.append((path, top.name, folder))
            else:
                found.append((path, item.label, folder))

    def add_file(path: Path) -> None:
        sources.append(path.resolve())
        found.append((path, path.resolve().parent.name, path.parent))

    if not paths:
        raise ValueError("no mesh path given; pass mesh files, folders or glob patterns")
    for arg in paths:
        p = Path(arg).expanduser()
        if p.is_dir():
            add_folder(p)
        elif p.is_file():
            add_file(p)
        elif glob.has_magic(str(arg)):
            matches = sorted(glob.glob(os.path.expanduser(str(arg)), recursive=True))
            n_before = len(found)
            for m in map(Path, matches):
                if m.is_dir():
                    add_folder(m)
                elif m.is_file() and _is_mesh_name(m):
                    add_file(m)
            if len(found) == n_before:
                raise ValueError(
                    f"pattern {arg!r} matches no mesh file ({', '.join(_mesh_suffixes())}); "
                    "quote it if your shell expanded it, or check the path"
                )
        else:
            raise FileNotFoundError(f"no file or folder {str(arg)!r}")
    if len(set(sources)) == 1:  # one folder alone: its own files are in no class
        for r in flat:
            found[r] = (found[r][0], "", found[r][2])
    # each file once, first occurrence kept
    seen, unique = set(), []
    for rec in found:
        key = rec[0].resolve()
        if key not in seen:
            seen.add(key)
            unique.append(rec)
    names = [_stem(f) for f, _, _ in unique]
    repeated = {n for n, c in Counter(names).items() if c > 1}
    if repeated:
        for i, (f, _, base) in enumerate(unique):
            if names[i] in repeated:
                rel = f.relative_to(base) if f.is_relative_to(base) else f
                names[i] = str(rel.parent / _stem(rel)) if rel.parent != Path() else _stem(rel)
        for name in {n for n, c in Counter(names).items() if c > 1}:
            # still equal: the path below the folder all the files of that name are in
            clash = [i for i in range(len(unique)) if names[i] == name]
            files = [unique[i][0].resolve() for i in clash]
            common = Path(os.path.commonpath(files))
            rels = [f.relative_to(common) for f in files]
            new = [str(r.parent / _stem(r)) for r in rels]
            if len(set(new)) < len(new):  # x.off and x.ply: the suffix too
                new = [str(r) for r in rels]
            for i, n in zip(clash, new, strict=True):
                names[i] = n
    return [(n, lab, f) for n, (f, lab, _) in zip(names, unique, strict=True)]


def _progress(args: argparse.Namespace) -> bool:
    return not args.quiet and sys.stderr.isatty()


def _transforms() -> tuple[str, ...]:
    from ..descriptors.formulas import TRANSFORMS

    return TRANSFORMS


def _mass_types() -> tuple[str, ...]:
    from ..fem import MASS_TYPES

    return MASS_TYPES


def _refinements() -> tuple[str, ...]:
    from ..spectrum import REFINEMENTS

    return REFINEMENTS


# ============================================================================ describe
def _cmd_describe(args: argparse.Namespace) -> int:
    from ..batch import describe
    from ..batch.run import LONG_RUN_PREFIX

    out = Path(args.out) if args.out else None
    if out is not None and out.suffix.lower() not in (".csv", ".npz"):
        raise ValueError(f"--out must end in .csv or .npz (the DescriptorTable formats), "
                         f"got {args.out!r}")
    if out is not None and out.is_dir():
        raise ValueError(f"--out {args.out!r} is a folder; give a file name such as "
                         f"{str(out / 'table.csv')!r}")
    if out is not None:
        check_out(out)  # before the eigensolves, not after
    if args.dask:
        try:
            import distributed  # noqa: F401
        except ImportError:
            raise ImportError("--dask needs dask.distributed; install it with "
                              "`pip install cshape[distributed]`") from None
    records = collect_mesh_files(args.paths)
    t0 = time.perf_counter()
    with _warnings_now((LONG_RUN_PREFIX,), "describe") as caught:
        table = describe(
            records, N=args.N, bc=args.bc, n_jobs=args.jobs, client=args.dask,
            cache_dir=False if args.no_cache else args.cache_dir, progress=_progress(args),
            on_error="warn", refine=args.refine, mass=args.mass,
        )
    seconds = time.perf_counter() - t0
    # describe's own summary of the failures is replaced by the list below; each mesh's
    # estimate of a long eigensolve was announced before the run, in one line
    announced = any(str(w.message).startswith(LONG_RUN_PREFIX) for w in caught)
    caught = [w for w in caught
              if not (announced and "the eigensolve will take about" in str(w.message))]
    print_warnings(caught, "describe", args.verbose, skip=("describe: ", LONG_RUN_PREFIX))
    for name, msg in table.failures:
        print(f"cshape describe: failed: {name}: {' '.join(msg.split())}", file=sys.stderr)
    n_fail, p = len(table.failures), len(records)
    if n_fail and (args.strict or len(table) == 0):
        what = "the table was not written" if out is not None else "nothing was printed"
        hint = ("; fix or remove them, or leave out --strict to keep the others"
                if len(table) else "")
        raise CommandError(f"{n_fail} of {p} meshes failed (listed above); {what}{hint}")
    n_cached = int(table.cached.sum())
    if out is not None:
        table.save(out)
        where = f"; wrote {out}" + (f" (metadata in {out}.json)" if out.suffix.lower() == ".csv"
                                    else "")
    else:
        where = ""
        _print_table(table)
    if not args.quiet:
        pieces = [(n, int(c)) for n, c in zip(table.names, _pieces(table), strict=True)
                  if c > 1]
        several = ""
        if pieces:
            listed = ", ".join(f"{n} ({c})" for n, c in pieces[:5])
            more = f" and {len(pieces) - 5} more" if len(pieces) > 5 else ""
            several = (f"; {len(pieces)} with several components: {listed}{more} (their "
                       "zero modes are dropped by the log descriptors)")
        # every mesh tried is counted once: described (some from the cache) or failed
        counts = (f"{len(table)} of {p} meshes described ({n_cached} from the cache), "
                  f"{n_fail} failed," if n_fail else
                  f"{len(table)} meshes ({n_cached} from the cache)")
        print(f"cshape describe: {counts} in {seconds:.1f} s, "
              f"N={table.N}, {spectra_words(table)}{several}{where}; `cshape query` compares the "
              f"{_table_label(table)} (--kind cshape: the paper's)", file=sys.stderr)
    return 0


@contextlib.contextmanager
def _warnings_now(prefixes: tuple[str, ...], command: str
                  ) -> Iterator[list[warnings.WarningMessage]]:
    """Record warnings (as ``catch_warnings(record=True)``), and print at once those whose
    message starts with one of ``prefixes`` (e.g. a long run ahead)."""
    caught: list[warnings.WarningMessage] = []
    with warnings.catch_warnings():
        warnings.simplefilter("always")

        def show(message: Warning | str, category: type[Warning], filename: str, lineno: int,
                 file: TextIO | None = None, line: str | None = None) -> None:
            text = " ".join(str(message).split())
            if text.startswith(prefixes):
                print(f"cshape {command}: warning: {text}", file=sys.stderr, flush=True)
            caught.append(warnings.WarningMessage(message, category, filename, lineno,
                                                  file, line))

        warnings.showwarning = show
        yield caught


def check_out(path: str | os.PathLike[str]) -> None:
    """An ``--out`` file's folder must exist: else a ``FileNotFoundError`` naming it."""
    from ..batch.table import check_out_folder

    check_out_folder(path)


def _pieces(table: DescriptorTable) -> list[int]:
    """Connected components of each shape: stored, else (old tables) its zero modes."""
    return [int(c) if c >= 0 else int(z)
            for c, z in zip(table.components, table.zero_modes, strict=True)]


def _print_table(table: DescriptorTable, width: int = 4) -> None:
    """One line per shape on stdout: name, label, area, components and the first values of
    the default descriptor (:data:`cshape.DEFAULT`, the one `cshape query`
    compares; '-' for a shape it cannot describe)."""
    import numpy as np

    S, kept = table.described(warn=False)  # the rows left out are marked below
    if len(S) == 0:
        S = np.zeros((0, 1))
    rows = dict(zip(kept.tolist(), S, strict=True))
    w = max([len(n) for n in table.names] + [4])
    wl = max([len(x) for x in table.labels] + [5])
    print(f"{'name':<{w}}  {'label':<{wl}}  {'area':>10}  pieces  {_table_label(table)} "
          f"({spectra_words(table)}): "
          f"first {min(width, S.shape[1])} values")
    pieces = _pieces(table)
    for i, name in enumerate(table.names):
        vals = (" ".join(f"{x: .4e}" for x in rows[i][:width]) if i in rows
                else "-  (cannot be described: too few non-zero eigenvalues)")
        print(f"{name:<{w}}  {table.labels[i]:<{wl}}  {table.areas[i]:>10.4g}  "
              f"{pieces[i]:>6}  {vals}")


def add_describe(sub: _SubParsers) -> None:
    p = sub.add_parser(
        "describe",
        help="Shape-DNA and cShape-DNA of mesh files and folders, into a descriptor table",
        description="Compute the Shape-DNA (N smallest Laplace-Beltrami eigenvalues) of every "
        "mesh under PATH (mesh files, folders searched recursively, glob patterns; class "
        "labels from sub-folder names) and write a descriptor table, from which every "
        "descriptor (cShape-DNA for any M and transform, Shape-DNA, F1) is derived: "
        "`cshape query` and `cshape overview` choose it (--kind, -M, --transform).  "
        "Eigenvalues are cached: a second run over the same meshes reads them back.",
        epilog="example: cshape describe meshes/ --out table.csv",
    )
    p.add_argument("paths", nargs="+", metavar="PATH", help="mesh files, folders or globs")
    p.add_argument("-N", type=int, default=100, help="Shape-DNA length N (default 100)")
    p.add_argument("--bc", default="neumann", choices=("neumann", "dirichlet"),
                   help="boundary condition on open surfaces (default neumann)")
    p.add_argument("--mass", default="consistent", choices=_mass_types(),
                   help="mass matrix B: 'consistent' (Eq. 5, the paper, default), 'lumped', or "
                   "'mixed', their average: eigenvalues that depend far less on the mesh "
                   "resolution, at the cost of a plain solve (see cshape.fem_matrices)")
    p.add_argument("--refine", default="none", choices=_refinements(),
                   help="'none': linear FEM (the paper, default); 'extrapolate': Richardson "
                   "extrapolation over one midpoint subdivision, eigenvalues that depend far "
                   "less on the mesh resolution, at several times the cost (see cshape.shape_dna)")
    p.add_argument("--jobs", type=int, default=1,
                   help="local worker processes (default 1; -1: all cores)")
    p.add_argument("--dask", metavar="ADDRESS", default=None,
                   help="run on a Dask cluster, e.g. tcp://10.0.0.5:8786")
    p.add_argument("--out", metavar="TABLE", default=None,
                   help="write the table to TABLE (.csv or .npz); default: print a summary")
    p.add_argument("--cache-dir", default=None,
                   help="eigenvalue cache (default: $CSHAPE_CACHE/eigenvalues or "
                   "~/.cache/cshape/eigenvalues)")
    p.add_argument("--no-cache", action="store_true", help="neither read nor write the cache")
    p.add_argument("--strict", action="store_true",
                   help="write nothing and exit 2 when any mesh fails (default: the meshes "
                   "that fail are listed and left out, the others are written)")
    p.add_argument("-q", "--quiet", action="store_true",
                   help="no progress bar and no summary line")
    p.add_argument("-v", "--verbose", action="store_true", help="list every warning")
    p.set_defaults(func=_cmd_describe)


# ============================================================================ info
def mesh_report(path: str | os.PathLike[str]) -> dict[str, Any]:
    """Size, area, topology, triangle quality and repairs of a mesh file (``cshape info``).

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    dict
        ``file``; ``vertices``, ``faces`` (as read, before any repair); ``reader`` (notes of
        the reader: faces it dropped); ``repair`` (what :func:`cshape.repair_mesh` changes,
        empty when nothing); after the repair (the mesh every cshape computation uses):
        ``repaired_vertices``, ``repaired_faces``, ``area``, ``components``,
        ``boundary_edges``, ``boundary_loops``, ``nonmanifold_edges``,
        ``nonmanifold_vertices``, ``euler_characteristic``, ``closed``, ``genus`` (of a
        connected manifold surface, closed or with ``b`` boundary loops: ``chi = 2 - 2 genus
        - b``; None otherwise) and ``genus_note`` (open surface, or why there is none),
        ``bbox`` (extent along x, y, z),
        ``mean_edge_length``, ``min_angle`` and ``mean_min_angle`` (degrees),
        ``pct_below_10`` (share of triangles with an angle under 10 degrees, percent),
        ``degenerate_faces``.
    """
    from ..data.quality import mesh_quality
    from ..mesh import CShapeWarning, repair_mesh
    from ..readers import load_mesh

    path = Path(path)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", CShapeWarning)
        raw = load_mesh(path, repair=False)
    reader = [str(w.message) for w in caught if issubclass(w.category, CShapeWarning)]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", CShapeWarning)
        mesh = repair_mesh(raw)
    repair = []
    for w in caught:
        msg = str(w.message)
        msg = msg.split("repaired mesh: ", 1)[-1]
        repair += [x.strip() for x in msg.split(";") if x.strip()]
    q = mesh_quality(mesh)
    genus, note = mesh.genus, ""
    loops = mesh.n_boundary_loops
    manifold = not len(mesh.nonmanifold_edges) and not len(mesh.nonmanifold_vertices)
    if genus is None and manifold and mesh.n_components == 1 and loops:
        # Euler's formula for a connected, orientable surface with b boundary loops:
        # chi = 2 - 2 g - b
        genus = (2 - mesh.euler_characteristic - loops) // 2
        note = f"open surface, {loops} boundary loop{'s' if loops > 1 else ''}"
    elif genus is None:
        note = ("non-manifold surface" if not manifold
                else f"{mesh.n_components} components")
    ext = mesh.vertices.max(axis=0) - mesh.vertices.min(axis=0)
    return {
        "file": str(path),
        "vertices": raw.n_vertices,
        "faces": raw.n_faces,
        "reader": reader,
        "repair": repair,
        "repaired_vertices": mesh.n_vertices,
        "repaired_faces": mesh.n_faces,
        "area": mesh.area,
        "components": mesh.n_components,
        "boundary_edges": int(len(mesh.boundary_edges)),
        "boundary_loops": loops,
        "nonmanifold_edges": int(len(mesh.nonmanifold_edges)),
        "nonmanifold_vertices": int(len(mesh.nonmanifold_vertices)),
        "euler_characteristic": mesh.euler_characteristic,
        "closed": mesh.is_closed,
        "genus": genus,
        "genus_note": note,
        "bbox": [float(x) for x in ext],
        "mean_edge_length": mesh.mean_edge_length,
        "min_angle": q["min_angle"],
        "mean_min_angle": q["mean_min_angle"],
        "pct_below_10": q["pct_below_10"],
        "degenerate_faces": q["n_degenerate"],
    }


def _cmd_info(args: argparse.Namespace) -> int:
    # a folder or a pattern stands for its mesh files, as in describe
    paths = [f for arg in args.meshes
             for f in ([rec[2] for rec in collect_mesh_files([arg])]
                       if Path(arg).expanduser().is_dir() or glob.has_magic(arg)
                       else [Path(arg)])]
    for k, path in enumerate(paths):
        r = mesh_report(path)
        if args.json:
            print(json.dumps(r))
            continue
        if k:
            print()
        repair = "; ".join(r["repair"]) if r["repair"] else "nothing to change"
        rows = [
            ("file", r["file"]),
            ("vertices", r["vertices"]),
            ("faces", r["faces"]),
        ]
        rows += [("reader", note) for note in r["reader"]]
        rows += [("repair", repair)]
        if r["repair"]:
            rows += [("after repair", f"{r['repaired_vertices']} vertices, "
                                      f"{r['repaired_faces']} faces")]
        g = "-" if r["genus"] is None else r["genus"]
        g = f"{g} ({r['genus_note']})" if r["genus_note"] else g
        bbox = " x ".join(f"{x:.4g}" for x in r["bbox"])
        rows += [
            ("area", f"{r['area']:.6g}"),
            ("bounding box", bbox),
            ("mean edge length", f"{r['mean_edge_length']:.4g}"),
            ("components", r["components"]),
            ("boundary edges", f"{r['boundary_edges']} in {r['boundary_loops']} loop"
                               f"{'' if r['boundary_loops'] == 1 else 's'}"),
            ("non-manifold edges", r["nonmanifold_edges"]),
            ("non-manifold vertices", r["nonmanifold_vertices"]),
            ("Euler characteristic", r["euler_characteristic"]),
            ("genus", g),
            ("minimum angle", f"{r['min_angle']:.3g} deg (mean of the triangles' smallest "
                              f"{r['mean_min_angle']:.3g}; {r['pct_below_10']:.1f} % of "
                              "triangles have an angle below 10 deg)"),
            ("zero-area faces", r["degenerate_faces"]),
        ]
        w = max(len(a) for a, _ in rows)
        for a, b in rows:
            print(f"{a:<{w}}  {b}")
    return 0


def add_info(sub: _SubParsers) -> None:
    p = sub.add_parser(
        "info",
        help="size, area, topology, minimum angle and needed repairs of mesh files",
        description="Read a mesh file and print its vertices and faces, what the repair "
        "(cshape.repair_mesh, applied by every cshape computation) would change, then the "
        "repaired mesh's area, components, boundary and non-manifold edges, Euler "
        "characteristic, genus and minimum triangle angle.",
    )
    p.add_argument("meshes", nargs="+", metavar="MESH",
                   help="mesh files, folders (their mesh files, as describe finds them) or "
                   "glob patterns")
    p.add_argument("--json", action="store_true", help="one JSON object per mesh")
    p.set_defaults(func=_cmd_info)


# ============================================================================ query
_KINDS = ("cshape", "shape-dna", "truncated", "truncated-log", "two-scale", "f1")


def _default_label(N: int = 100) -> str:
    """The exploration default (cshape.DEFAULT, for N eigenvalues) in words."""
    return _descriptor_default(N).label


def _descriptor_default(N: int) -> Descriptor:
    """The exploration default for spectra of ``N`` eigenvalues (read when called)."""
    from ..descriptors import recipe

    return recipe.DEFAULT.for_N(N)


def spectra_words(table: DescriptorTable) -> str:
    """Which spectra the table holds, in words: its mass matrix, and its refinement if any."""
    ref = "" if table.refine == "none" else f", refine={table.refine!r}"
    return f"mass={table.mass!r}{ref}"


def _table_label(table: DescriptorTable) -> str:
    """What the table compares when no descriptor is asked for, in words."""
    if table.descriptor is not None:
        return table.descriptor.label
    return f"no row of {_default_label()} fits N = {table.N}"


def chosen_descriptor(args: argparse.Namespace, table: DescriptorTable) -> Descriptor:
    """The :class:`cshape.Descriptor` of ``--kind``, ``-M``, ``-N`` and ``--transform``.

    Without ``--kind``: :data:`cshape.DEFAULT` at ``-N`` (default: the table's ``N``), with
    ``-M`` and ``--transform`` where given.  With it: that kind at ``-N``, with ``-M``
    (default: the paper's 16, lowered to what ``N`` allows) and ``--transform`` (default:
    the paper's 'weyl').
    """
    from ..descriptors import Descriptor

    N = table.N if args.N is None else args.N
    given = {k: v for k, v in (("M", args.M), ("transform", args.transform)) if v is not None}
    if args.kind is None:  # what the table compares (saved with it), at -N
        own = table.descriptor or _descriptor_default(N)
        d = own if N == own.N else own.for_N(N)
        return d.replace(**given)
    if args.M is not None:
        return Descriptor(args.kind, N=N, **given)
    return Descriptor(args.kind, **given).for_N(N)


def _query_target(args: argparse.Namespace, table: DescriptorTable
                  ) -> tuple[np.ndarray, float, int | None, str, int]:
    """The query's eigenvalues, area, table row to exclude (None for a file), name in the
    header and component count: a shape of the table, or a mesh file described now."""
    from ..batch import describe

    target = args.target
    if target in table.names:
        row = table.index(target)
        return (table.lam[row], table.areas[row], row, f"{target!r}",
                int(table.zero_modes[row]))
    if Path(target).is_file():
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            one = describe([(_stem(Path(target)), "", Path(target))],
                           **table.settings.as_kwargs(),
                           cache_dir=False if args.no_cache else args.cache_dir,
                           progress=False, on_error="warn")
        print_warnings(caught, "query", False, skip=("describe: ",))
        if one.failures:
            raise ValueError(f"cannot describe {target!r}: {one.failures[0][1]}")
        return one.lam[0], one.areas[0], None, repr(target), int(one.zero_modes[0])
    close = [n for n in table.names if target.lower() in n.lower()][:5]
    hint = f"; names containing it: {close}" if close else ""
    raise ValueError(f"{target!r} is neither a shape of the table ({len(table)} shapes)"
                     f" nor a mesh file{hint}")


def _cmd_query(args: argparse.Namespace) -> int:
    from ..batch import DescriptorTable
    from ..index import DescriptorIndex

    table = DescriptorTable.load(args.table)
    if len(table) == 0:
        raise ValueError(f"table {args.table!r} holds no shape")
    if args.N is not None and args.N > table.N:
        raise ValueError(f"-N {args.N} is more than the table's N = {table.N} eigenvalues; "
                         f"use -N {table.N} or less")
    if args.k < 1:
        raise ValueError(f"-k must be at least 1, got {args.k}")
    check_plot_options(args)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        index = DescriptorIndex.from_table(table, descriptor=chosen_descriptor(args, table))
    print_warnings(caught, "query", False)
    desc = index.descriptor_
    assert desc is not None  # from_table gives the index its descriptor
    by = (f"--kind {args.kind}" if args.kind
          else f"the default descriptor ({desc.label})")
    target = args.target
    lam, area, exclude, what, pieces = _query_target(args, table)
    rows = index.rows_  # the table rows the kind describes
    if exclude is not None and exclude not in rows:
        raise ValueError(f"{by} cannot describe {target!r} (the warning above "
                         "says why); choose another --kind, or a smaller -M")
    available = len(rows) - (exclude is not None and exclude in rows)
    if available == 0:
        which = f" that {by} describes" if len(rows) < len(table) else ""
        raise ValueError(f"table {args.table!r} holds no other shape{which} than {target!r}")
    k = min(args.k, available)
    dist, ind = index.query_spectra(lam, area, k=min(k + 1, len(rows)), zero_modes=[pieces],
                                    names=[target])
    hits = [(float(d), int(rows[i])) for d, i in zip(dist[0], ind[0], strict=True)
            if rows[i] != exclude]
    hits = hits[:k]
    if k < args.k:
        print(f"cshape query: only {k} other shapes in the table"
              f"{' that ' + by + ' describes' if len(rows) < len(table) else ''}",
              file=sys.stderr)
    if args.plot is not None:
        wrote = write_neighbour_strip(args, table, hits, None if exclude is not None else target,
                                      desc.label)
        print(f"cshape query: wrote {wrote}", file=sys.stderr)
    if args.json:
        print(json.dumps({"query": target, **dataclasses.asdict(desc), "descriptor": desc.label,
                          "mass": table.mass, "refine": table.refine,
                          "neighbours": [{"rank": j + 1, "name": table.names[i],
                                          "label": table.labels[i], "distance": d}
                                         for j, (d, i) in enumerate(hits)]}))
        return 0
    among = (f"the {len(table)} shapes" if len(rows) == len(table)
             else f"the {len(rows)} of {len(table)} shapes it describes")
    print(f"nearest to {what} by the {desc.label} ({spectra_words(table)}), Euclidean distance, "
          f"among {among} of "
          f"{args.table}:")
    w = max([len(table.names[i]) for _, i in hits] + [4])
    print(f"{'rank':>4}  {'distance':>11}  {'name':<{w}}  label")
    for j, (d, i) in enumerate(hits, 1):
        print(f"{j:>4}  {d:>11.5g}  {table.names[i]:<{w}}  {table.labels[i]}")
    return 0


def add_descriptor_options(p: argparse.ArgumentParser) -> None:
    """``--kind``, ``-M``, ``-N`` and ``--transform``: which descriptor a command compares
    (``cshape query`` and ``cshape overview``)."""
    p.add_argument("--kind", default=None, choices=_KINDS, type=str.lower,
                   help="descriptor compared (default: the one saved with the table, "
                   f"for a new table {_default_label()}; 'cshape' is the paper's cShape-DNA)")
    p.add_argument("-M", type=int, default=None,
                   help="crop half-width, 2M+1 values (default: the default descriptor's, or "
                   "with --kind the paper's 16, lowered to what N allows)")
    p.add_argument("-N", type=int, default=None,
                   help="use the first N eigenvalues (default: the table's N)")
    p.add_argument("--transform", default=None, choices=_transforms(),
                   help="cShape-DNA transform (default: the paper's 'weyl')")


def add_query(sub: _SubParsers) -> None:
    p = sub.add_parser(
        "query",
        help="the nearest shapes of a descriptor table to a mesh file or a shape of the table",
        description="Load a table written by `cshape describe --out` and list the k shapes "
        "nearest to MESH_OR_NAME (a shape of the table, or a mesh file, described with the "
        "table's N, boundary condition and mass matrix), with their distances.",
        epilog="example: cshape query table.csv spot -k 5 --plot spot.png --meshes meshes/",
    )
    p.add_argument("table", metavar="TABLE", help="descriptor table (.csv or .npz)")
    p.add_argument("target", metavar="MESH_OR_NAME", help="a shape name of TABLE or a mesh file")
    p.add_argument("-k", type=int, default=5, help="number of neighbours (default 5)")
    add_descriptor_options(p)
    p.add_argument("--cache-dir", default=None, help="eigenvalue cache for a mesh file query")
    p.add_argument("--no-cache", action="store_true", help="do not use the eigenvalue cache")
    p.add_argument("--json", action="store_true", help="print the neighbours as JSON")
    add_plot_options(p)
    p.set_defaults(func=_cmd_query)


# ============================================================================ query --plot
#: Figure files: matplotlib's images and plotly's HTML.
IMAGE_SUFFIXES = (".png", ".svg", ".pdf")
HTML_SUFFIXES = (".html", ".htm")


def check_figure_path(path: str | os.PathLike[str], option: str) -> Path:
    """The figure file of ``option`` checked before any work: a known suffix, an existing
    folder, not a folder itself."""
    p = Path(path).expanduser()
    if p.is_dir():
        raise CommandError(f"{option} {str(path)!r} is a folder; give a file name such as "
                           f"{str(p / ('overview' + '.html'))!r}")
    if p.suffix.lower() not in IMAGE_SUFFIXES + HTML_SUFFIXES:
        raise CommandError(
            f"{option} {str(path)!r}: the file name must end in .html (interactive, offline) or "
            f"{', '.join(IMAGE_SUFFIXES)} (image)")
    folder = p.parent
    if not folder.is_dir():
        raise CommandError(f"{option} {str(path)!r}: the folder {str(folder)!r} does not "
                           "exist; create it first or write elsewhere")
    return p


def add_plot_options(p: argparse.ArgumentParser) -> None:
    """``--plot``, ``--meshes`` and ``--up`` of ``cshape query``."""
    p.add_argument("--plot", metavar="FILE", default=None,
                   help="draw the query and its neighbours as thumbnails with their distances "
                   "into FILE (.png, .svg, .pdf; .html: interactive, offline); needs --meshes")
    p.add_argument("--meshes", metavar="PATH", nargs="+", default=None,
                   help="with --plot: the mesh files or folders the table was described from "
                   "(as given to cshape describe; the table keeps no file paths)")
    p.add_argument("--up", default="auto", choices=("auto", "x", "y", "z"),
                   help="with --plot: the axis drawn upwards (default auto: y for OBJ, glTF "
                   "and COLLADA files, z for the rest)")


def check_plot_options(args: argparse.Namespace) -> None:
    """Fail before the query's work when ``--plot`` cannot be written."""
    if args.plot is None:
        if args.meshes is not None:
            raise CommandError("--meshes is only used with --plot FILE")
        return
    check_figure_path(args.plot, "--plot")
    if not args.meshes:
        raise CommandError(
            "--plot draws the meshes: pass --meshes with the folders or files given to "
            "cshape describe (the table keeps no file paths)")


def write_neighbour_strip(args: argparse.Namespace, table: DescriptorTable,
                          hits: Sequence[tuple[float, int]],
                          query_path: str | os.PathLike[str] | None, descriptor: str | None
                          ) -> Path:
    """Draw ``cshape query``'s answer (``hits``: ``[(distance, row)]``) into ``args.plot``.

    ``query_path`` is the mesh file of a query given as a file, else None (the query is the
    table's shape ``args.target``).
    """
    from ..plots.overview import (
        guess_vertical_axis,
        neighbour_strip_plotly,
        plot_neighbour_strip,
        save_figure,
    )
    from ..readers import load_mesh

    out = check_figure_path(args.plot, "--plot")
    files = {name: path for name, _, path in collect_mesh_files(args.meshes)}
    names = [table.names[i] for _, i in hits]
    if query_path is None:
        names.insert(0, args.target)
        labels = [table.labels[table.index(args.target)]]
    else:
        names.insert(0, _stem(Path(query_path)))
        labels = ["(mesh file)"]
    labels += [table.labels[i] for _, i in hits]
    missing = [n for n in names[1 if query_path is not None else 0:] if n not in files]
    if missing:
        shown = ", ".join(repr(n) for n in missing[:5]) + (" ..." if len(missing) > 5 else "")
        raise CommandError(
            f"--meshes holds no mesh named {shown} ({len(files)} meshes found there); pass "
            "the folders or files given to cshape describe")
    paths = ([Path(query_path)] if query_path is not None else [])
    paths += [files[n] for n in names[len(paths):]]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the repairs were reported when it was described
        meshes = [load_mesh(p) for p in paths]
    up = ([guess_vertical_axis(p) for p in paths] if args.up == "auto"
          else args.up)
    dist = [d for d, _ in hits]
    title = (f"nearest to {names[0]} by {descriptor} ({spectra_words(table)}), among the "
             f"{len(table)} shapes of "
             f"{Path(args.table).name}")
    if out.suffix.lower() in HTML_SUFFIXES:
        fig = neighbour_strip_plotly(meshes, names, dist, labels=labels, title=title,
                                     vertical_axis=up)
    else:
        fig = plot_neighbour_strip(meshes, names, dist, labels=labels, title=title,
                                   vertical_axis=up)
    return save_figure(fig, out)
