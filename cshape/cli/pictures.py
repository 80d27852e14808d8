"""The command line's overview of a described collection: ``cshape overview``.

``cshape overview TABLE --out overview.html [--out overview.png]`` draws the MDS (outliers on
the border, names and neighbours on hover), the distance matrix by class and a table of the
classes (:func:`cshape.plots.overview.overview_html`,
:func:`~cshape.plots.overview.plot_overview`).  The neighbour strip of ``cshape query ...
--plot FILE`` lives with the query in :mod:`cshape.cli.explore`.

Files are checked before any work (suffix, folder) and written atomically, after every
figure is made: a failure leaves no half-written file.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .explore import (
    HTML_SUFFIXES,
    add_descriptor_options,
    check_figure_path,
    chosen_descriptor,
    spectra_words,
)
from .output import CommandError, print_warnings

if TYPE_CHECKING:
    import argparse

    from matplotlib.figure import Figure

    _SubParsers = argparse._SubParsersAction[Any]  # of the command line's parser class

# ============================================================================ overview
def _cmd_overview(args: argparse.Namespace) -> int:
    from ..batch import DescriptorTable
    from ..batch.table import collection_distances
    from ..compare import mds_embedding
    from ..plots.layout import mds_layout
    from ..plots.overview import collection_title, overview_html, plot_overview, save_figure

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
        c = collection_distances(table, descriptor=chosen_descriptor(args, table))
        Y = mds_embedding(c.D, random_state=args.seed)
    print_warnings(caught, "overview", args.verbose)
    name = f"{Path(args.table).name} ({spectra_words(table)})"
    made: list[str | Figure] = []  # every figure first, then the files: nothing half-written
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
        msg = (f"cshape overview: {collection_title(len(c.names), len(set(c.labels)))}, "
               f"compared by {c.descriptor.label} ({spectra_words(table)})")
        if c.left_out:
            msg += f"; {len(c.left_out)} left out"
        if far:
            msg += (f"; {len(far)} outlier{'s' if len(far) > 1 else ''} on the border: "
                    + ", ".join(far[:5]) + (" ..." if len(far) > 5 else ""))
        print(msg + "; wrote " + ", ".join(str(o) for o in outs), file=sys.stderr)
    return 0


def add_overview(sub: _SubParsers) -> None:
    p = sub.add_parser(
        "overview",
        help="pictures of a described collection: MDS, distance matrix and classes",
        description="Draw the overview of a table written by `cshape describe --out`: an MDS "
        "picture (outliers marked on the border, the rest at its own scale; in HTML each "
        "shape's name, class and nearest neighbours on hover), the distance matrix ordered "
        "by class and, for two or more classes, a table of them (size, spread, nearest other "
        "class, how often a shape's nearest neighbour is of its class).  The HTML page works "
        "offline.  Shapes that the descriptor cannot describe are left out and named.",
        epilog="example: cshape overview table.csv --out overview.html --out overview.png",
    )
    p.add_argument("table", metavar="TABLE", help="descriptor table (.csv or .npz)")
    p.add_argument("--out", metavar="FILE", action="append", required=True,
                   help="write FILE: .html (interactive, offline) or .png/.svg/.pdf; repeat "
                   "for several")
    add_descriptor_options(p)
    p.add_argument("-k", type=int, default=3,
                   help="nearest neighbours listed on hover (default 3)")
    p.add_argument("--seed", type=int, default=0, help="seed of the MDS (default 0)")
    p.add_argument("-q", "--quiet", action="store_true", help="no summary line")
    p.add_argument("-v", "--verbose", action="store_true", help="list every warning")
    p.set_defaults(func=_cmd_overview)
