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
* ``truncated log spectrum``: ``r_1 .. r_{2M+1}`` (kind ``'truncated_log'``);
* ``F1``: ``lam_1 / lam_i`` for ``i = 2 .. 2M+2`` (F1 of ``2M+3`` eigenvalues);

and, as a reference, Shape-DNA with all ``N`` values.  It writes
``benchmarks/results/descriptors_<collection>.md`` (the table at 17 and 33 numbers, and the
best descriptor at every size) and ``.csv`` (every size and measure).

Research hygiene: choose on the development collection (``creatures-dev``), report on the
held-out one (``creatures``, other random members of the same classes); the script prints
which one it ran on.  Eigenvalues are cached (``cshape.describe``), so a second run is fast.
"""

from __future__ import annotations

import argparse
import csv
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import machine_summary  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"

#: (row title, descriptor_matrix kind, transform); every row has 2M+1 numbers.
ROWS = (
    ("cShape-DNA (paper)", "cshape", "weyl"),
    ("log-Weyl DFT", "cshape", "log-weyl"),
    ("log-Weyl DCT", "cshape", "log-weyl-dct"),
    ("truncated Shape-DNA", "truncated", "weyl"),
    ("truncated log spectrum", "truncated_log", "weyl"),
    ("F1", "f1", "weyl"),
)
MEASURES = ("nn", "ft", "st", "map")


def descriptors(table, title, M, N):
    """The descriptor matrix (p, 2M+1) of row ``title`` of :data:`ROWS`."""
    kind, transform = {t: (k, tr) for t, k, tr in ROWS}[title]
    if kind == "f1":
        return table.descriptors("f1", N=2 * M + 3)  # lam_1 / lam_2 .. lam_1 / lam_{2M+2}
    return table.descriptors(kind, M=M, N=N, transform=transform)


def score_table(table, Ms, N):
    """Retrieval scores of every row of :data:`ROWS` at every ``M``, and the N reference.

    Returns
    -------
    list of dict
        ``descriptor``, ``M``, ``size`` and the :data:`MEASURES`.
    """
    from cshape.compare import distance_matrix, retrieval_scores

    out = []
    ref = retrieval_scores(table.distance_matrix("shape_dna", N=N), table.labels)
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


def markdown(rows, name, n_shapes, n_classes, N, header):
    """The results page: the table at 17 and 33 numbers and the winner at every size."""
    lines = [f"# Compact descriptors on `{name}` ({n_shapes} shapes, {n_classes} classes, "
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
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--collection", default="creatures-dev",
                    help="a collection of cshape.data (default: creatures-dev)")
    ap.add_argument("-N", type=int, default=100, help="eigenvalues per shape (default 100)")
    ap.add_argument("--max-M", type=int, default=16, help="sizes 2M+1 for M = 1..max-M")
    ap.add_argument("--jobs", type=int, default=1, help="worker processes of describe")
    ap.add_argument("--out", default=None, help="file stem in benchmarks/results")
    args = ap.parse_args(argv)

    import cshape.data
    from cshape import describe

    coll = cshape.data.load_collection(args.collection)
    table = describe(coll, N=args.N, n_jobs=args.jobs, progress=False)
    if table.failures:
        print(f"{len(table.failures)} meshes failed: {table.failures[:3]}", file=sys.stderr)
    Ms = range(1, args.max_M + 1)
    rows = score_table(table, Ms, args.N)
    stem = args.out or f"descriptors_{args.collection}"
    RESULTS.mkdir(exist_ok=True)
    with open(RESULTS / f"{stem}.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["descriptor", "M", "size", *MEASURES])
        w.writeheader()
        w.writerows(rows)
    cmd = " ".join(["benchmarks/bench_descriptors.py", *(argv or sys.argv[1:])])
    header = f"`{cmd}`; {machine_summary()}"
    md = markdown(rows, args.collection, len(table), len(set(table.labels)), args.N, header)
    (RESULTS / f"{stem}.md").write_text(md)
    print(md)


if __name__ == "__main__":
    main()
