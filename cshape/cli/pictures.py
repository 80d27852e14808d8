"""The command line's pictures of a described collection: ``cshape overview`` and the
neighbour strip of ``cshape query ... --plot FILE``.

* ``cshape overview TABLE --out overview.html [--out overview.png]`` - MDS (outliers on the
  border, names and neighbours on hover), distance matrix by class and a table of the
  classes (:func:`cshape.plots.explore.overview_html`, :func:`~cshape.plots.explore.plot_overview`);
* ``cshape query TABLE NAME --plot strip.png --meshes FOLDER`` - the query and its nearest
  shapes as thumbnails with their distances (.png/.svg/.pdf by matplotlib, .html by plotly).

Files are checked before any work (suffix, folder) and written atomically, after every
figure is made: a failure leaves no half-written file.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

from .output import CommandError, print_warnings

__all__ = ["add_overview", "add_plot_options", "check_figure_path", "write_neighbour_strip"]

#: Figure files: matplotlib's images and plotly's HTML.
IMAGE_SUFFIXES = (".png", ".svg", ".pdf")
HTML_SUFFIXES = (".html", ".htm")


def check_figure_path(path, option: str) -> Path:
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


def _kinds() -> tuple[str, ...]:
    from .explore import _KINDS

    return _KINDS


def _default_kind() -> str:
    """``cshape.compare.DEFAULT_KIND`` when defined, else 'cshape' (as
    :func:`cshape.plots.explore.default_kind`, without importing the plots layer)."""
    from .. import compare

    return str(getattr(compare, "DEFAULT_KIND", "cshape"))


# ============================================================================ query --plot
def add_plot_options(p) -> None:
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


def check_plot_options(args) -> None:
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


def write_neighbour_strip(args, table, hits, query_path, descriptor) -> Path:
    """Draw ``cshape query``'s answer (``hits``: ``[(distance, row)]``) into ``args.plot``.

    ``query_path`` is the mesh file of a query given as a file, else None (the query is the
    table's shape ``args.target``).
    """
    from ..mesh import load_mesh
    from ..plots.explore import (
        guess_vertical_axis,
        neighbour_strip_plotly,
        plot_neighbour_strip,
        save_figure,
    )
    from .explore import collect_mesh_files

    out = check_figure_path(args.plot, "--plot")
    files = {name: path for name, _, path in collect_mesh_files(args.meshes)}
    names = [table.names[i] for _, i in hits]
    if query_path is None:
        names.insert(0, args.target)
        labels = [table.labels[table.index(args.target)]]
    else:
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
    title = (f"nearest to {names[0]} by {descriptor}, among the {len(table)} shapes of "
             f"{Path(args.table).name}")
    if out.suffix.lower() in HTML_SUFFIXES:
        fig = neighbour_strip_plotly(meshes, names, dist, labels=labels, title=title,
                                     vertical_axis=up)
    else:
        fig = plot_neighbour_strip(meshes, names, dist, labels=labels, title=title,
                                   vertical_axis=up)
    return save_figure(fig, out)


# ============================================================================ overview
def _cmd_overview(args) -> int:
    from ..batch import DescriptorTable
    from ..compare import mds_embedding
    from ..plots.collection import mds_layout
    from ..plots.explore import collection_distances, overview_html, plot_overview, save_figure

    outs = [check_figure_path(o, "--out") for o in args.out]
    if len({o.resolve() for o in outs}) < len(outs):
        raise CommandError(f"--out names one file twice: {args.out}")
    if args.k < 1:
        raise CommandError(f"-k must be at least 1, got {args.k}")
    table = DescriptorTable.load(args.table)
    if len(table) < 2:
        raise CommandError(f"table {args.table!r} holds {len(table)} shape(s); an overview "
                           "needs two or more")
    if args.N is not None and args.N > table.N:
        raise CommandError(f"-N {args.N} is more than the table's N = {table.N} eigenvalues; "
                           f"use -N {table.N} or less")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        c = collection_distances(table, args.kind, M=args.M, N=args.N,
                                 transform=args.transform)
        Y = mds_embedding(c.D, random_state=args.seed)
    print_warnings(caught, "overview", args.verbose)
    name = Path(args.table).name
    made = []  # every figure first, then the files: nothing half-written
    for o in outs:
        if o.suffix.lower() in HTML_SUFFIXES:
            made.append(overview_html(c.D, c.names, c.labels, Y=Y, descriptor=c.descriptor,
                                      title=name, left_out=c.left_out, k=args.k))
        else:
            made.append(plot_overview(c.D, c.names, c.labels, Y=Y, descriptor=c.descriptor,
                                      title=name, left_out=c.left_out))
    for o, fig in zip(outs, made, strict=True):
        save_figure(fig, o)
    if not args.quiet:
        lay = mds_layout(Y)
        far = [c.names[i] for i in lay["outliers"].nonzero()[0]]
        n_classes = len(set(c.labels))
        msg = (f"cshape overview: {len(c.names)} shapes, {n_classes} classes, compared by "
               f"{c.descriptor}")
        if c.left_out:
            msg += f"; {len(c.left_out)} left out"
        if far:
            msg += (f"; {len(far)} outlier{'s' if len(far) > 1 else ''} on the border: "
                    + ", ".join(far[:5]) + (" ..." if len(far) > 5 else ""))
        print(msg + "; wrote " + ", ".join(str(o) for o in outs), file=sys.stderr)
    return 0


def add_overview(sub):
    p = sub.add_parser(
        "overview",
        help="pictures of a described collection: MDS, distance matrix and classes",
        description="Draw the overview of a table written by `cshape describe --out`: an MDS "
        "picture (outliers marked on the border, the rest at its own scale; in HTML each "
        "shape's name, class and nearest neighbours on hover), the distance matrix ordered "
        "by class and a table of the classes (size, spread, nearest other class, how often "
        "a shape's nearest neighbour is of its class).  The HTML page works offline.  Shapes "
        "that the descriptor cannot describe are left out and named.",
        epilog="example: cshape overview table.csv --out overview.html --out overview.png",
    )
    p.add_argument("table", metavar="TABLE", help="descriptor table (.csv or .npz)")
    p.add_argument("--out", metavar="FILE", action="append", required=True,
                   help="write FILE: .html (interactive, offline) or .png/.svg/.pdf; repeat "
                   "for several")
    p.add_argument("--kind", default=None, choices=_kinds(),
                   help=f"descriptor compared (default {_default_kind()})")
    p.add_argument("-M", type=int, default=None, help="cShape-DNA M (default: the table's)")
    p.add_argument("-N", type=int, default=None,
                   help="use the first N eigenvalues (default: the table's N)")
    p.add_argument("--transform", default=None, choices=_transforms(),
                   help="cShape-DNA transform (default: the table's)")
    p.add_argument("-k", type=int, default=3,
                   help="nearest neighbours listed on hover (default 3)")
    p.add_argument("--seed", type=int, default=0, help="seed of the MDS (default 0)")
    p.add_argument("-q", "--quiet", action="store_true", help="no summary line")
    p.add_argument("-v", "--verbose", action="store_true", help="list every warning")
    p.set_defaults(func=_cmd_overview)


def _transforms() -> tuple[str, ...]:
    from ..descriptors import TRANSFORMS

    return TRANSFORMS
