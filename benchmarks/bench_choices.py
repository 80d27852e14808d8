"""Benchmark: small implementation choices of the mesh stage and the eigensolver, each against
the plain alternative it replaced.

Run from the repository root::

    .venv/bin/python benchmarks/bench_choices.py --out benchmarks/results/choices.md

* **edge keys** (``Mesh._edge_data``): the unique edges of an icosphere as one sort of the
  ``3m`` integers ``lo * n + hi``, against ``np.unique`` over the rows of sorted vertex pairs
  (a sort of a structured type);
* **distinct rows** (``mesh._all_rows_distinct``, the test of :func:`cshape.repair_mesh` for
  duplicate vertices): one sort of a 64-bit hash per row, against ``np.unique(V, axis=0)``;
* **first touch** (the Lanczos basis allocated beside the factorisation,
  ``cshape._eigensolver.shift``): the seconds of writing a freshly allocated array of the size
  of the basis of a 163,842-vertex solve (``300`` columns, 393 MB) the first time (page
  faults) and a second time.

Minimum over ``--repeats`` runs, one process; the processor is named in the output.
Nothing here asserts a number.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import machine_summary, processor  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"


def _best(fn, repeats):
    best = np.inf
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def edge_keys(mesh, repeats):
    """Seconds of the integer-key sort and of ``np.unique`` over rows, and whether they agree."""
    F = mesh.faces
    n = mesh.n_vertices
    half = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    lo, hi = half.min(axis=1), half.max(axis=1)

    def by_key():
        return np.unique(lo * n + hi)

    def by_rows():
        return np.unique(np.stack([lo, hi], axis=1), axis=0)

    keys, rows = by_key(), by_rows()
    agree = bool(np.array_equal(np.stack([keys // n, keys % n], axis=1), rows))
    return _best(by_key, repeats), _best(by_rows, repeats), agree


def distinct_rows(mesh, repeats):
    """Seconds of the hash test and of ``np.unique(V, axis=0)`` on the vertices."""
    from cshape.mesh import _all_rows_distinct

    V = mesh.vertices
    agree = _all_rows_distinct(V) == (len(np.unique(V, axis=0)) == len(V))
    return (_best(lambda: _all_rows_distinct(V), repeats),
            _best(lambda: np.unique(V, axis=0), repeats), bool(agree))


def first_touch(rows=163_842, cols=300, repeats=3):
    """Seconds of the first and of a second write of a fresh ``rows x cols`` float array."""
    first, second = np.inf, np.inf
    for _ in range(repeats):
        a = np.empty((rows, cols))
        t = time.perf_counter()
        a.fill(0.0)
        first = min(first, time.perf_counter() - t)
        t = time.perf_counter()
        a.fill(1.0)
        second = min(second, time.perf_counter() - t)
        del a
    return first, second, rows * cols * 8


def main(argv=None):
    from cshape import shapes

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--level", type=int, default=6,
                        help="icosphere subdivisions (6: 40,962 vertices)")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--basis-rows", type=int, default=163_842,
                        help="rows of the 300-column basis written (default: a 164K solve's)")
    parser.add_argument("--out", type=Path, default=None,
                        help="write the Markdown table here (default: print only)")
    args = parser.parse_args(argv)
    mesh = shapes.icosphere(args.level)
    ek = edge_keys(mesh, args.repeats)
    dr = distinct_rows(mesh, args.repeats)
    ft = first_touch(rows=args.basis_rows, repeats=min(args.repeats, 3))
    lines = [
        "# Small choices of the mesh stage and the eigensolver", "",
        f"`benchmarks/bench_choices.py --level {args.level} --repeats {args.repeats}`; "
        f"{machine_summary()}.", "", f"Processor: {processor()}.", "",
        "| choice | what it replaced | mesh / array | chosen s | replaced s | ratio "
        "| same result |",
        "|---|---|---|---:|---:|---:|---|",
        f"| edge keys: one sort of `lo * n + hi` | `np.unique` over rows of pairs | "
        f"icosphere, {mesh.n_faces:,} triangles | {ek[0]:.4f} | {ek[1]:.4f} | "
        f"{ek[1] / ek[0]:.1f}x | {ek[2]} |",
        f"| distinct vertices: a 64-bit hash per row, one sort | `np.unique(V, axis=0)` | "
        f"icosphere, {mesh.n_vertices:,} vertices | {dr[0]:.4f} | {dr[1]:.4f} | "
        f"{dr[1] / dr[0]:.1f}x | {dr[2]} |",
        f"| the basis written once beside the factorisation | its first write in the solve | "
        f"{ft[2] / 1e6:.0f} MB ({args.basis_rows:,} x 300) | {ft[1]:.3f} (a second write) | "
        f"{ft[0]:.3f} "
        f"(first write: page faults) | {ft[0] / ft[1]:.1f}x | - |",
    ]
    text = "\n".join(lines) + "\n"
    print(text)
    if args.out is not None:
        out = args.out if args.out.is_absolute() else Path.cwd() / args.out
        out.write_text(text)
        print(f"wrote {out}")


if __name__ == "__main__":
    main()
