"""Benchmark: how close is ``cshape.shape_dna`` to the floor of its method, and where the rest goes.

Run from the repository root::

    .venv/bin/python benchmarks/bench_floor.py --quick          # 40K-vertex icosphere, < 2 min
    .venv/bin/python benchmarks/bench_floor.py                  # 10K, 164K spheres, 655K torus
    .venv/bin/python benchmarks/bench_floor.py --mesh ico7 --block-sizes 8,16

The eigensolve of ``cshape/spectrum.py`` (block shift-invert Lanczos) cannot cost less than
one sparse Cholesky factorisation of ``S = K - sigma B`` plus the triangular solves with
``S`` that build its Krylov space.  For each mesh this measures, in one run:

* ``total``: ``cshape.shape_dna(mesh, N)``, everything a user pays (best of ``--repeats``);
* the stages, each timed on its own: repair checks and FEM assembly (``spectrum._prepare``),
  the connected-components check, the factorisation as the solver does it
  (``_shift.CholeskyOperator``), the bare factorisation of the backend in use
  (``cshape._eigensolver.cholmod.factorize``) and cholespy's (LaPy's) on ready arrays, and the
  block Lanczos iteration ``_lanczos.block_lanczos`` with its solves counted and timed;
* ``floor (method)``: bare factorisation + as many multi-right-hand-side solves (blocks of
  ``b`` columns) as the Lanczos iteration used; ``floor (ideal)``: bare factorisation +
  ``N`` solve columns in blocks of ``b`` (no Krylov method finds N eigenpairs with fewer);
* the cost per column of a CHOLMOD solve with 1, 8, 16 and 32 right-hand sides;
* a ``cProfile`` of ``shape_dna`` grouped into FEM, factorisation, solves, sparse
  products with ``B``, dense orthogonalisation (the self time of the Lanczos loop),
  Cholesky-QR, Rayleigh-Ritz and the rest;
* ``_lanczos.block_lanczos`` with other block sizes (``--block-sizes``) on the same factorisation:
  time, solve columns, and the largest relative eigenvalue difference from block size 8
  (must be at most 1e-8 to count).

The private functions of ``cshape.spectrum`` are called, never changed.  BLAS runs with
``--threads`` threads (default 1, as the Lanczos loop does).  Results go to
``benchmarks/results/floor.{csv,md}`` (``floor_quick.*`` with ``--quick``).  Nothing here
asserts a time.
"""

from __future__ import annotations

import argparse
import cProfile
import csv
import pstats
import sys
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import load_average, max_relative_difference  # noqa: E402
from _common import machine_summary as _machine_summary


def machine_summary():
    """One line: date, machine, memory, library versions and the load average."""
    return _machine_summary(libs=('scipy',))

RESULTS = Path(__file__).resolve().parent / "results"
#: Mesh label -> (constructor name, arguments).
MESHES = {
    "ico5": ("icosphere", (5,)),
    "ico6": ("icosphere", (6,)),
    "ico7": ("icosphere", (7,)),
    "torus640k": ("torus", (1280, 512)),
    "tiny": ("icosphere", (4,)),
}


def make_mesh(label):
    """The benchmark mesh called ``label`` (a key of :data:`MESHES`)."""
    from cshape import shapes

    name, args = MESHES[label]
    if name == "torus":
        return shapes.torus(*args, R=1.0, r=0.4)
    return getattr(shapes, name)(*args)


def _best(fn, repeats):
    best, out = np.inf, None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


class CountingSolve:
    """Wraps ``X -> S^{-1} X``, counting calls and columns and timing them."""

    def __init__(self, solve):
        self.solve = solve
        self.calls = 0
        self.columns = 0
        self.seconds = 0.0

    def __call__(self, X):
        t0 = time.perf_counter()
        out = self.solve(X)
        self.seconds += time.perf_counter() - t0
        self.calls += 1
        self.columns += X.shape[1] if X.ndim == 2 else 1
        return out


class CountingProducts:
    """Counts the products ``B @ X`` of the Lanczos loop (``_threads.RowSplit.bmul``).

    Each Lanczos step multiplies by ``B`` once in its Cholesky-QR and once more when it runs
    the full re-orthogonalisation pass against the older blocks, so the number of passes is
    ``products - steps - 1`` (one product for the start block).  Use as a context manager.
    """

    def __init__(self):
        self.products = 0

    def __enter__(self):
        from cshape._eigensolver import threads as _threads

        self._orig = _threads.RowSplit.bmul
        counter = self

        def bmul(split, X):
            counter.products += 1
            return counter._orig(split, X)

        _threads.RowSplit.bmul = bmul
        return self

    def __exit__(self, *exc):
        from cshape._eigensolver import threads as _threads

        _threads.RowSplit.bmul = self._orig


# ----------------------------------------------------------------------------- analysis
def stages(mesh, N=100, repeats=1, block_sizes=(8,)):
    """Stage times, solve counts, floors and block-size variants for one mesh.

    Parameters
    ----------
    mesh : cshape.Mesh
        A connected mesh with more than ``spectrum.DENSE_LIMIT`` vertices.
    N : int, default=100
    repeats : int, default=1
        Timings are the best of this many runs.
    block_sizes : sequence of int, default=(8,)
        Block sizes of ``_lanczos.block_lanczos`` to try besides the default.

    Returns
    -------
    dict
        Times in seconds (``total``, ``prepare``, ``components``, ``factor_solver``,
        ``factor_bare`` (the backend of ``cshape._eigensolver.cholmod``, ``backend``),
        ``factor_cholespy``,
        ``lanczos``, ``lanczos_solves``, ``floor_method``, ``floor_ideal``,
        ``solve_per_column`` (dict: right-hand sides -> seconds per column)), counts
        (``solve_calls``, ``solve_columns``, ``block_size``, ``n``) and ``variants`` (list of
        dicts: ``block_size``, ``seconds``, ``columns``, ``maxrel``).
    """
    import cholespy
    import scipy.sparse.csgraph as csgraph

    import cshape
    from cshape import spectrum
    from cshape._eigensolver import cholmod as _cholmod
    from cshape._eigensolver import lanczos as _lanczos
    from cshape._eigensolver import shift as _shift
    from cshape._eigensolver import threads as _threads

    cshape.shape_dna(make_mesh("tiny"), N=min(N, 100))  # warm-up: imports, first calls
    b0 = spectrum.BLOCK_SIZE
    threads = spectrum.solver_threads(int(mesh.n_vertices))  # the policy, as shape_dna uses it
    out = {"n": int(mesh.n_vertices), "N": N, "block_size": b0, "threads": threads}
    out["total"], lam_ref = _best(lambda: cshape.shape_dna(mesh, N=N), repeats)
    out["prepare"], (_, problem) = _best(
        lambda: spectrum._prepare(mesh, N, "neumann", "consistent"), repeats)
    K = (-sp.csr_matrix(problem.A)).tocsr()
    B = sp.csr_matrix(problem.B)
    out["components"], _ = _best(
        lambda: csgraph.connected_components(B, directed=False), repeats)
    sigma = _shift.default_sigma(B, N)
    S = K - sigma * B
    out["factor_solver"], op = _best(lambda: _shift.CholeskyOperator(S), repeats)
    Sc = sp.csr_matrix(S)
    Sc.sum_duplicates()
    ip, ix, dx = Sc.indptr.astype(np.int32), Sc.indices.astype(np.int32), Sc.data.copy()
    n = S.shape[0]
    out["backend"] = _cholmod.backend()
    out["factor_bare"], fac = _best(lambda: _cholmod.factorize(Sc), repeats)
    # LaPy's factorisation (cholespy, reference BLAS), for comparison
    out["factor_cholespy"], _ = _best(
        lambda: cholespy.CholeskySolverD(n, ip, ix, dx, cholespy.MatrixType.CSR), repeats)

    def solve_cols(m, reps):
        X = np.asarray(np.random.default_rng(1).standard_normal((n, m)), order=fac.rhs_order)
        t0 = time.perf_counter()
        for _ in range(reps):
            fac.solve(X if m > 1 else X[:, 0].copy())
        return (time.perf_counter() - t0) / (reps * m)

    reps = max(2, int(2e6 // n))
    out["solve_per_column"] = {m: min(solve_cols(m, reps) for _ in range(repeats))
                               for m in (1, 8, 16, 32)}

    with _threads.one_blas_thread():
        variants = []
        for b in [b0] + [int(x) for x in block_sizes if int(x) != b0]:
            runs = []
            for _ in range(repeats):
                counter = CountingSolve(op.matmat)
                Bc = CountingProducts()
                t0 = time.perf_counter()
                try:
                    with Bc:
                        lam, _ = _lanczos.block_lanczos(K, B, N, counter, sigma, block_size=b,
                                                        return_vectors=False, threads=threads,
                                                        rhs_order=op.rhs_order)
                except _lanczos.NoConvergence as exc:
                    runs.append({"block_size": b, "seconds": float("nan"),
                                 "columns": counter.columns, "calls": counter.calls,
                                 "full_passes": -1, "maxrel": float("nan"),
                                 "solve_seconds": counter.seconds, "note": str(exc)})
                    break
                sec = time.perf_counter() - t0
                lam = np.sort(lam)
                lam[np.abs(lam) < 1e-10 * np.abs(lam).max()] = 0.0
                maxrel = max_relative_difference(np.maximum(lam, 0), lam_ref)
                runs.append({"block_size": b, "seconds": sec, "columns": counter.columns,
                             "calls": counter.calls, "solve_seconds": counter.seconds,
                             "full_passes": Bc.products - counter.calls - 1,
                             "maxrel": maxrel,
                             "note": "" if maxrel <= 1e-8 else "WRONG eigenvalues"})
            variants.append(min(runs, key=lambda v: (np.isnan(v["seconds"]), v["seconds"])))
    base = variants[0]
    out["lanczos"] = base["seconds"]
    out["lanczos_solves"] = base["solve_seconds"]
    out["solve_calls"] = base["calls"]
    out["solve_columns"] = base["columns"]
    out["full_passes"] = base["full_passes"]
    per_b = out["solve_per_column"][8] if b0 == 8 else out["solve_per_column"][1]
    out["floor_method"] = out["factor_bare"] + base["columns"] * per_b
    out["floor_ideal"] = out["factor_bare"] + N * per_b
    out["variants"] = variants
    return out


#: The functions of the block Lanczos iteration outside its solves and Cholesky-QR.
_LANCZOS_LOOP = ("block_lanczos", "__init__", "run", "step", "_orthogonalize",
                 "rayleigh_ritz", "refine_smallest", "ritz_vectors")

#: Profile groups: (label, predicate on (file, function name)).
GROUPS = [
    ("FEM assembly, repair and checks",
     lambda f, fn: "cshape/fem.py" in f or "cshape/mesh.py" in f),
    ("factorisation (CHOLMOD)", lambda f, fn: fn == "factorize" and "_eigensolver/cholmod.py" in f),
    ("triangular solves (CHOLMOD)",
     lambda f, fn: fn in ("solve", "solve_split") and "_eigensolver/cholmod.py" in f),
    ("Cholesky-QR (b_orthonormalize)", lambda f, fn: fn == "b_orthonormalize"),
    ("dense orthogonalisation (Lanczos loop)",
     lambda f, fn: "_eigensolver/lanczos.py" in f and fn in _LANCZOS_LOOP),
    ("Rayleigh-Ritz (LAPACK eigh or eig_banded)",
     lambda f, fn: fn in ("eig_banded", "eigh")),
    ("sparse products (B @ X, K - sigma B)",
     lambda f, fn: "scipy/sparse" in f and "csgraph" not in f),
    ("connected components", lambda f, fn: "connected_components" in fn),
]


def profile(mesh, N=100):
    """cProfile of ``cshape.shape_dna(mesh, N)``.

    Returns
    -------
    groups : list of (str, float)
        Inclusive seconds per group of :data:`GROUPS` (a call counted in the first group
        that claims it or one of its callers), then 'other' and 'total'.
    top : list of (str, float, float, int)
        ``(function, tottime, cumtime, calls)`` of the 15 largest self times.
    """
    import cshape

    pr = cProfile.Profile()
    pr.enable()
    cshape.shape_dna(mesh, N=N)
    pr.disable()
    st = pstats.Stats(pr)
    stats = st.stats  # {(file, line, fn): (cc, nc, tt, ct, callers)}
    total = sum(v[2] for v in stats.values())

    def group_of(key, seen=()):
        f, _, fn = key
        for label, pred in GROUPS:
            if pred(f, fn):
                return label
        return None

    # self time of every function, attributed to the nearest grouped caller chain
    memo = {}

    fem_label, sparse_label = GROUPS[0][0], GROUPS[6][0]

    def owner(key, depth=0):
        if key in memo:
            return memo[key]
        g = group_of(key)
        if g in (None, sparse_label) and depth < 40:
            callers = stats[key][4]
            if callers:
                # the caller with the largest cumulative share decides; sparse work done
                # for the FEM assembly (COO -> CSR) counts as FEM
                parent = max(callers, key=lambda c: callers[c][3])
                if parent in stats and parent != key:
                    up = owner(parent, depth + 1)
                    if g is None or up == fem_label:
                        g = up
        memo[key] = g
        return g

    sums = {label: 0.0 for label, _ in GROUPS}
    other = 0.0
    for key, v in stats.items():
        g = owner(key)
        if g is None:
            other += v[2]
        else:
            sums[g] += v[2]
    groups = [(label, sums[label]) for label, _ in GROUPS] + [("other", other), ("total", total)]
    top = sorted(stats.items(), key=lambda kv: -kv[1][2])[:15]
    top = [(f"{Path(k[0]).name}:{k[1]}({k[2]})", v[2], v[3], v[1]) for k, v in top]
    return groups, top


# ----------------------------------------------------------------------------- main
def report(label, r, groups, top):
    """Lines of text for one mesh."""
    b = r["block_size"]
    per = r["solve_per_column"]
    lines = [
        f"## {label}: {r['n']:,} vertices, N = {r['N']}", "",
        "| stage | seconds | share of total |", "|---|---|---|",
    ]
    rest = r["total"] - r["prepare"] - r["components"] - r["factor_solver"] - r["lanczos"]
    for name, key in (("shape_dna total", "total"), ("repair checks + FEM assembly", "prepare"),
                      ("connected components", "components"),
                      ("factorisation as the solver does it", "factor_solver"),
                      (f"  of which bare {r['backend']} factorisation", "factor_bare"),
                      ("  (cholespy's, as LaPy uses it, for comparison)", "factor_cholespy"),
                      (f"block Lanczos (b = {b}, {r['threads']} thread(s) for its products)",
                       "lanczos"),
                      (f"  of which {r['solve_calls']} solves, {r['solve_columns']} columns",
                       "lanczos_solves")):
        lines.append(f"| {name} | {r[key]:.2f} | {100 * r[key] / r['total']:.0f} % |")
    lines.append(f"| rest (eigenvalue clean-up, conversions) | {rest:.2f} | "
                 f"{100 * rest / r['total']:.0f} % |")
    lines += [
        "",
        f"- floor of the method (bare factorisation + {r['solve_columns']} solve columns in "
        f"blocks of {b}): **{r['floor_method']:.2f} s**; shape_dna is "
        f"**{r['total'] / r['floor_method']:.2f}x** the floor",
        f"- ideal floor (factorisation + N = {r['N']} columns): {r['floor_ideal']:.2f} s; "
        f"shape_dna is {r['total'] / r['floor_ideal']:.2f}x it",
        f"- Lanczos overhead beyond its solves: {r['lanczos'] - r['lanczos_solves']:.2f} s "
        f"({100 * (r['lanczos'] - r['lanczos_solves']) / r['total']:.0f} % of total); "
        f"{r['full_passes']} full re-orthogonalisation passes over the basis in "
        f"{r['solve_calls']} steps (each reads the n x m basis twice)",
        f"- CHOLMOD ({r['backend']}) solve cost per column: " + ", ".join(
            f"{m} rhs {1e3 * per[m]:.2f} ms" for m in sorted(per)),
        "",
        "Block sizes (same factorisation; max rel diff against shape_dna's eigenvalues):", "",
        "| block size | Lanczos [s] | solve columns | solve time [s] | full passes | "
        "max rel diff | note |",
        "|---|---|---|---|---|---|---|",
    ]
    for v in r["variants"]:
        lines.append(f"| {v['block_size']} | {v['seconds']:.2f} | {v['columns']} | "
                     f"{v['solve_seconds']:.2f} | {v['full_passes']} | {v['maxrel']:.1e} | "
                     f"{v['note']} |")
    g = dict(groups)
    floor_prof = g["factorisation (CHOLMOD)"] + g["triangular solves (CHOLMOD)"]
    lines += ["", "Profile of shape_dna (cProfile, one run, self time grouped by stage; the "
              "share is immune to load changes between the separately timed stages above):",
              "", "| group | seconds | share |", "|---|---|---|"]
    lines += [f"| {name} | {sec:.2f} | {100 * sec / g['total']:.0f} % |" for name, sec in groups]
    lines += ["", f"- in the profiled run, factorisation + solves = {floor_prof:.2f} s of "
              f"{g['total']:.2f} s: shape_dna is **{g['total'] / floor_prof:.2f}x** its floor"]
    lines += ["", "Largest self times:", "", "| function | self [s] | cumulative [s] | calls |",
              "|---|---|---|---|"]
    lines += [f"| `{f}` | {t:.2f} | {c:.2f} | {n} |" for f, t, c, n in top[:10]]
    return lines


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="40K-vertex icosphere (< 2 min)")
    parser.add_argument("--mesh", default=None,
                        help=f"comma-separated subset of {','.join(MESHES)} "
                             "(default ico5,ico7,torus640k; ico6 with --quick)")
    parser.add_argument("-N", type=int, default=100)
    parser.add_argument("--repeats", type=int, default=None,
                        help="timings are the best of this many runs (default 2, 1 quick)")
    parser.add_argument("--block-sizes", default="6,12,16",
                        help="other Lanczos block sizes to try (default 6,12,16; at least 6)")
    parser.add_argument("--threads", type=int, default=1,
                        help="BLAS threads (default 1; 0: library default)")
    args = parser.parse_args(argv)
    labels = (args.mesh.split(",") if args.mesh else
              ["ico6"] if args.quick else ["ico5", "ico7", "torus640k"])
    bad = [m for m in labels if m not in MESHES]
    if bad:
        parser.error(f"--mesh must be a subset of {','.join(MESHES)}, got {bad}")
    repeats = args.repeats or (1 if args.quick else 2)
    block_sizes = [int(x) for x in args.block_sizes.split(",") if x.strip()]
    from cshape import spectrum

    if any(b < spectrum.MIN_BLOCK_SIZE for b in block_sizes):
        parser.error(f"--block-sizes must be at least {spectrum.MIN_BLOCK_SIZE} (smaller blocks "
                     "miss copies of the icosphere's 5-fold eigenvalues and are refused)")
    from threadpoolctl import threadpool_limits

    summary = machine_summary()
    print(summary)
    md = ["# The floor of the eigensolve", "", summary, ""]
    rows = []
    with threadpool_limits(limits=args.threads or None):
        for label in labels:
            mesh = make_mesh(label)
            r = stages(mesh, N=args.N, repeats=repeats, block_sizes=block_sizes)
            groups, top = profile(mesh, N=args.N)
            lines = report(label, r, groups, top)
            print("\n".join(lines), flush=True)
            md += lines + [""]
            rows.append({"mesh": label, **{k: v for k, v in r.items()
                                           if k not in ("variants", "solve_per_column")},
                         "load1": load_average()[0]})
    summary_end = machine_summary()
    print(f"\nat the end: {summary_end}")
    md += [f"At the end: {summary_end}"]
    RESULTS.mkdir(parents=True, exist_ok=True)
    stem = "floor_quick" if args.quick else "floor"
    with open(RESULTS / f"{stem}.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    (RESULTS / f"{stem}.md").write_text("\n".join(md) + "\n")
    print(f"results: {RESULTS / stem}.{{csv,md}}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
