"""Retrieval of the compact descriptors at equal size: the paper's cShape-DNA against the
log-Weyl transforms (DFT and DCT), truncated Shape-DNA, truncated log spectrum and F1.

Usage::

    .venv/bin/python benchmarks/bench_descriptors.py                      # creatures-dev
    .venv/bin/python benchmarks/bench_descriptors.py --collection creatures   # held out
    .venv/bin/python benchmarks/bench_descriptors.py --collection articulated --jobs 2

For every size ``2M+1`` (``M = 1..16``; 17 and 33 numbers are ``M = 8`` and ``16``) it
scores, with :func:`cshape.compare.retrieval_scores` (nearest neighbour, first and second
tier, mean average precision), these descriptors of ``2M+1`` numbers computed from the same
``N`` eigenvalues (default ``N = 100``, the paper's):

* ``cShape-DNA (paper)``: ``compact_shape_dna(..., transform='weyl')``, Eq. (8)-(10);
* ``log-Weyl DFT``: ``transform='log-weyl'``;
* ``log-Weyl DCT``: ``transform='log-weyl-dct'``;
* ``truncated Shape-DNA``: ``lam_0^norm .. lam_{2M}^norm`` (the paper's Fig. 5);
* ``truncated log spectrum``: ``r_1 .. r_{2M+1}`` (kind ``'truncated-log'``);
* ``F1``: ``lam_1 / lam_i`` for ``i = 2 .. 2M+2`` (F1 of ``2M+3`` eigenvalues);

and, as a reference, Shape-DNA with all ``N`` values.  The one result file is
``benchmarks/results/descriptors.md``, a section per collection (a run replaces its
collection's section): the table at 17 and 33 numbers, the best descriptor at every size, the
DCT against the DFT paired over the queries, the length ``N`` at equal size, and every
descriptor at every size with every measure.

Research hygiene: choose on the development collection (``creatures-dev``), report on the
held-out one (``creatures``, other random members of the same classes); the script prints
which one it ran on.  Eigenvalues are cached (``cshape.describe``), so a second run is fast.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import machine_summary, write_section  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
TITLE = "Compact descriptors at equal size"

#: (row title, kind of cshape.Descriptor, transform); every row has 2M+1 numbers.
ROWS = (
    ("cShape-DNA (paper)", "cshape", "weyl"),
    ("log-Weyl DFT", "cshape", "log-weyl"),
    ("log-Weyl DCT", "cshape", "log-weyl-dct"),
    ("truncated Shape-DNA", "truncated", "weyl"),
    ("truncated log spectrum", "truncated-log", "weyl"),
    ("F1", "f1", "weyl"),
)
MEASURES = ("nn", "ft", "st", "map")


def descriptors(table, title, M, N):
    """The descriptor matrix (p, 2M+1) of row ``title`` of :data:`ROWS`."""
    from cshape import Descriptor

    kind, transform = {t: (k, tr) for t, k, tr in ROWS}[title]
    if kind == "f1":  # lam_1 / lam_2 .. lam_1 / lam_{2M+2}
        return table.descriptors(Descriptor("f1", N=2 * M + 3))
    return table.descriptors(Descriptor(kind, N=N, M=M, transform=transform))


def connected_only(table):
    """The table without shapes whose ``lam_1`` is zero (several components), and their names.

    Such a spectrum has one zero eigenvalue per component; the log-Weyl ratio has no
    logarithm for it (``cshape.descriptors.log_weyl_ratio`` refuses it), and the paper's descriptors
    would compare it with a shifted index.  It is left out of *every* row, so all rows
    score the same shapes.
    """
    lam1 = table.lam[:, 1]
    ok = lam1 > 1e-8 * table.lam.max(axis=1)
    return table.select(ok), [n for n, k in zip(table.names, ok, strict=True) if not k]


def score_table(table, Ms, N):
    """Retrieval scores of every row of :data:`ROWS` at every ``M``, and the N reference.

    Returns
    -------
    list of dict
        ``descriptor``, ``M``, ``size`` and the :data:`MEASURES`.
    """
    from cshape import Descriptor
    from cshape.compare import distance_matrix, retrieval_scores

    out = []
    ref = retrieval_scores(table.distance_matrix(Descriptor("shape-dna", N=N)), table.labels)
    out.append({"descriptor": f"Shape-DNA N={N}", "M": "", "size": N,
                **{k: ref[k] for k in MEASURES}})
    for M in Ms:
        for title, _, _ in ROWS:
            X = descriptors(table, title, M, N)
            assert X.shape[1] == 2 * M + 1, (title, X.shape)
            s = retrieval_scores(distance_matrix(X), table.labels)
            out.append({"descriptor": title, "M": M, "size": 2 * M + 1,
                        **{k: s[k] for k in MEASURES}})
    return out


def winners(rows, measure="ft", tol=1e-12):
    """``{size: (best descriptors joined by ' = ', score)}`` over the equal-size rows."""
    top = {}
    for r in rows:
        if r["M"] != "":
            top[r["size"]] = max(top.get(r["size"], -1.0), r[measure])
    best = {}
    for r in rows:
        if r["M"] != "" and r[measure] >= top[r["size"]] - tol:
            names, _ = best.get(r["size"], ([], None))
            best[r["size"]] = (names + [r["descriptor"]], top[r["size"]])
    return {k: (" = ".join(v[0]), v[1]) for k, v in best.items()}


def paired(table, M, N, a="log-weyl-dct", b="log-weyl", measures=("ft", "map")):
    """Mean and standard error over queries of ``score(a) - score(b)``, per measure.

    Both transforms rank the same queries, so the per-query differences are paired; the
    standard error is ``std(diff, ddof=1) / sqrt(q)`` over the ``q`` scored queries.
    """
    from cshape import Descriptor
    from cshape.compare import retrieval_per_query

    pa = retrieval_per_query(table.distance_matrix(Descriptor("cshape", N=N, M=M, transform=a)),
                             table.labels)
    pb = retrieval_per_query(table.distance_matrix(Descriptor("cshape", N=N, M=M, transform=b)),
                             table.labels)
    out = {}
    for k in measures:
        d = pa[k] - pb[k]
        d = d[~np.isnan(d)]
        out[k] = (float(d.mean()), float(d.std(ddof=1) / np.sqrt(len(d))))
    return out


def n_sweep(table, Ms=(8, 16), Ns=(40, 50, 67, 100)):
    """First tier and mAP of the three transforms at sizes ``2M+1`` for several ``N``.

    ``N = 2M+2`` is included: there every log-Weyl coefficient is kept, so both log-Weyl
    transforms have the distances of the truncated log spectrum (an orthogonal DCT, a
    scaled unitary DFT).  Returns a list of dicts ``M, N, transform, ft, map``.
    """
    from cshape import Descriptor
    from cshape.compare import retrieval_scores

    out = []
    for M in Ms:
        for N in sorted({2 * M + 2, *[n for n in Ns if 2 * M + 2 <= n <= table.N]}):
            for tr in ("weyl", "log-weyl", "log-weyl-dct"):
                d = Descriptor("cshape", N=N, M=M, transform=tr)
                s = retrieval_scores(table.distance_matrix(d), table.labels)
                out.append({"M": M, "N": N, "transform": tr, "ft": s["ft"], "map": s["map"]})
    return out


def markdown(rows, name, n_shapes, n_classes, N, header, pairs=None, sweep=None):
    """The section of a collection: the table at 17 and 33 numbers, the winner at every size,
    the paired DCT - DFT differences, the N sweep and every row at every size."""
    lines = [f"## Compact descriptors on `{name}` ({n_shapes} shapes, {n_classes} classes, "
             f"N = {N})", "", header, "",
             "| descriptor | size | nearest neighbour | first tier | second tier | mAP |",
             "|---|---|---|---|---|---|"]
    for r in rows:
        if r["M"] == "" or r["size"] in (17, 33):
            lines.append(f"| {r['descriptor']} | {r['size']} | {r['nn']:.3f} | {r['ft']:.3f} "
                         f"| {r['st']:.3f} | {r['map']:.3f} |")
    lines += ["", "Best first tier at every size (ties joined by '='):", "",
              "| size | best | first tier | paper's cShape-DNA | log-Weyl DFT | log-Weyl DCT |",
              "|---|---|---|---|---|---|"]
    by = {(r["descriptor"], r["size"]): r for r in rows}
    for size, (title, score) in sorted(winners(rows).items()):
        lines.append(f"| {size} | {title} | {score:.3f} | "
                     f"{by[('cShape-DNA (paper)', size)]['ft']:.3f} | "
                     f"{by[('log-Weyl DFT', size)]['ft']:.3f} | "
                     f"{by[('log-Weyl DCT', size)]['ft']:.3f} |")
    if pairs:
        lines += ["", f"log-Weyl DCT minus log-Weyl DFT, paired over the queries (N = {N}; "
                  "mean +- standard error):", "",
                  "| size | first tier | mAP |", "|---|---|---|"]
        for size, d in sorted(pairs.items()):
            lines.append(f"| {size} | {d['ft'][0]:+.3f} +- {d['ft'][1]:.3f} "
                         f"| {d['map'][0]:+.3f} +- {d['map'][1]:.3f} |")
    if sweep:
        lines += ["", "The Shape-DNA length N at equal size (first tier / mAP); N = 2M+2 keeps "
                  "every log-Weyl coefficient (= truncated log spectrum):", "",
                  "| size | N | paper (weyl) | log-Weyl DFT | log-Weyl DCT |",
                  "|---|---|---|---|---|"]
        cell = {(r["M"], r["N"], r["transform"]): r for r in sweep}
        for M, n in dict.fromkeys((r["M"], r["N"]) for r in sweep):
            vals = [cell[(M, n, tr)] for tr in ("weyl", "log-weyl", "log-weyl-dct")]
            lines.append(f"| {2 * M + 1} | {n} | "
                         + " | ".join(f"{v['ft']:.3f} / {v['map']:.3f}" for v in vals) + " |")
    return "\n".join(lines + every_size_lines(rows)) + "\n"


def every_size_lines(rows):
    """Every descriptor at every size, every measure (the table's raw rows)."""
    lines = ["", "Every descriptor at every size:", "",
             "| descriptor | M | size | " + " | ".join(MEASURES) + " |",
             "|---|---|---|" + "---|" * len(MEASURES)]
    for r in rows:
        lines.append(f"| {r['descriptor']} | {r['M']} | {r['size']} | "
                     + " | ".join(f"{float(r[k]):.4f}" for k in MEASURES) + " |")
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--collection", default="creatures-dev",
                    help="a collection of cshape.data (default: creatures-dev)")
    ap.add_argument("-N", type=int, default=100, help="eigenvalues per shape (default 100)")
    ap.add_argument("--max-M", type=int, default=16, help="sizes 2M+1 for M = 1..max-M")
    ap.add_argument("--jobs", type=int, default=1, help="worker processes of describe")
    ap.add_argument("--out", default=None,
                    help="the result file (default benchmarks/results/descriptors.md)")
    args = ap.parse_args(argv)

    import cshape.data
    from cshape import describe

    coll = cshape.data.load_collection(args.collection)
    table = describe(coll, N=args.N, n_jobs=args.jobs, progress=False)
    if table.failures:
        print(f"{len(table.failures)} meshes failed: {table.failures[:3]}", file=sys.stderr)
    table, dropped = connected_only(table)
    if dropped:
        print(f"left out of every row (several zero eigenvalues: a mesh of several "
              f"components): {', '.join(dropped)}", file=sys.stderr)
    Ms = range(1, args.max_M + 1)
    rows = score_table(table, Ms, args.N)
    out = Path(args.out) if args.out else RESULTS / "descriptors.md"
    cmd = " ".join(["benchmarks/bench_descriptors.py", *(argv or sys.argv[1:])])
    header = f"`{cmd}`; {machine_summary()}"
    if dropped:
        header += (f"\n\nLeft out (several components, lam_1 = 0): {', '.join(dropped)}; "
                   f"{len(table)} shapes scored.")
    pairs = {2 * M + 1: paired(table, M, args.N) for M in Ms}
    sweep = n_sweep(table, Ms=[m for m in (8, 16) if m <= args.max_M])
    md = markdown(rows, args.collection, len(table), len(set(table.labels)), args.N, header,
                  pairs, sweep)
    write_section(out, args.collection, md.rstrip("\n").split("\n") + [""], TITLE)
    print(md)
    print(f"results: {out}, section {args.collection!r}")


if __name__ == "__main__":
    main()
