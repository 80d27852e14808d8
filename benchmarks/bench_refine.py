"""Benchmark: resolution-free spectra: mixed mass, Richardson extrapolation and P2 elements.

Run from the repository root::

    .venv/bin/python benchmarks/bench_refine.py                  # accuracy + costs
    .venv/bin/python benchmarks/bench_refine.py --no-costs       # accuracy only
    .venv/bin/python benchmarks/bench_refine.py --sizes 1k,10k   # costs without 100K

Five spectra of a mesh, ``N = 100``:

* **linear**: ``shape_dna(mesh, N)``, linear FEM (Eq. 4-7) with the consistent mass matrix,
  cshape's default;
* **lumped**: ``shape_dna(mesh, N, mass='lumped')``, the lumped (diagonal) mass matrix;
* **mixed**: ``shape_dna(mesh, N, mass='mixed')``, the average of the two mass matrices;
* **extrapolated**: ``shape_dna(mesh, N, refine='extrapolate')``: Richardson
  ``(4 lam_fine - lam) / 3`` over one midpoint subdivision (flat triangles kept);
* **P2**: quadratic Lagrange elements on the same flat triangles (a prototype defined here,
  not part of cshape): Eq. (4)-(5) with the six P2 basis functions per triangle, integrated
  exactly (6-point degree-4 rule); nodes at vertices and flat edge midpoints.

The extrapolated and P2 spectra converge to the spectrum of the *polyhedral* surface (the flat
triangles); on a curved surface that differs from the smooth one by ``O(h^2)`` in the metric.

Accuracy: the largest relative error of ``lam_1 .. lam_99`` on unit icospheres against
``l(l+1)``; flat unit square and unit disk, Dirichlet and Neumann, against their exact
eigenvalues (the disk's polygon is not the disk: ``O(h^2)`` in area); a torus of revolution
against the extrapolated spectrum of a much finer mesh; the convergence order fitted over
three refinements of the square and of the equilateral triangle; same-object pairs at two
resolutions of ``../shared/meshes`` (``$CSHAPE_SHARED_MESHES``; skipped when missing): mean
``|difference|`` of the log-Weyl ratios ``log(lam_i area / (4 pi i))`` for ``i = 1-17`` and
``i = 80-99``.

Weight study (known answers only): ``B = (1 - w) B_consistent + w B_lumped`` for ``w`` from
0.3 to 0.7 (``w = 1/2`` is ``mass='mixed'``), the largest relative error on the sphere, the
square, the disk and the equilateral triangle, and the best ``w`` of each on a fine grid.

``--candidates``: the first tier of the exploration default's candidates
(:data:`cshape.reproduce.scores.CANDIDATES`) on the suite's development instances, with linear
and with extrapolated spectra (``results/refine_candidates.md``).

Costs: time and peak resident memory of each spectrum of tori of about 1K, 10K and 100K
vertices, each in a fresh child process.  Results: ``benchmarks/results/refine.md``.
Nothing here asserts a number.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import scipy.sparse as sp
from scipy.special import jn_zeros, jnp_zeros

import cshape
from cshape import shapes
from cshape.mesh import as_mesh, repair_mesh
from cshape.spectrum import solve_eigenproblem

sys.path.insert(0, str(Path(__file__).parent))
from _common import machine_summary, proc_status_kib, processor, run_child  # noqa: E402

N = 100
HERE = Path(__file__).parent
SHARED = Path(os.environ.get("CSHAPE_SHARED_MESHES",
                             HERE.resolve().parents[1] / "shared" / "meshes"))
PAIRS = [("spot", "spot/spot.obj", "spot/spot_low_resolution.obj"),
         ("fish", "fish/fish.obj", "fish/fish_low_resolution.obj"),
         ("penguin", "penguin/penguin_hr.obj", "penguin/penguin.obj")]
SIZES = {"1k": (40, 25), "10k": (160, 63), "100k": (500, 200)}  # torus grids

# --------------------------------------------------------------------------- P2 prototype
_A, _B = 0.445948490915965, 0.091576213509771
_QP = np.array([[_A, _A], [1 - 2 * _A, _A], [_A, 1 - 2 * _A],
                [_B, _B], [1 - 2 * _B, _B], [_B, 1 - 2 * _B]])
_QW = np.array([0.223381589678011] * 3 + [0.109951743655322] * 3)


def _p2_reference():
    """Values (q, 6) and reference gradients (q, 6, 2) of the P2 basis at the quadrature points.

    Local nodes: vertices 0, 1, 2, then the midpoints of (0, 1), (1, 2), (2, 0).
    """
    s, t = _QP[:, 0], _QP[:, 1]
    L = np.stack([1 - s - t, s, t], 1)  # barycentric coordinates
    dL = np.array([[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]])
    phi = np.concatenate([L * (2 * L - 1), 4 * np.stack([L[:, 0] * L[:, 1], L[:, 1] * L[:, 2],
                                                          L[:, 2] * L[:, 0]], 1)], 1)
    grad = np.zeros((len(s), 6, 2))
    for a in range(3):
        grad[:, a] = (4 * L[:, a] - 1)[:, None] * dL[a]
    for k, (a, b) in enumerate(((0, 1), (1, 2), (2, 0))):
        grad[:, 3 + k] = 4 * (L[:, a, None] * dL[b] + L[:, b, None] * dL[a])
    return phi, grad


def p2_matrices(mesh, bc="neumann"):
    """Stiffness ``A`` (negative semidefinite) and mass ``B`` of P2 elements on flat triangles."""
    mesh = repair_mesh(as_mesh(mesh), warn=False)
    V, F = mesh.vertices, mesh.faces
    n, m = len(V), len(F)
    edges, h2e, _ = mesh._edge_data
    nodes = np.column_stack([F, n + h2e.reshape(3, m).T])
    e1, e2 = V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]
    G = np.stack([np.stack([(e1 * e1).sum(1), (e1 * e2).sum(1)], 1),
                  np.stack([(e1 * e2).sum(1), (e2 * e2).sum(1)], 1)], 1)  # metric (m, 2, 2)
    det = G[:, 0, 0] * G[:, 1, 1] - G[:, 0, 1] ** 2
    area = 0.5 * np.sqrt(det)
    Ginv = np.stack([np.stack([G[:, 1, 1], -G[:, 0, 1]], 1),
                     np.stack([-G[:, 0, 1], G[:, 0, 0]], 1)], 1) / det[:, None, None]
    phi, grad = _p2_reference()
    Kloc = np.einsum("q,qia,tab,qjb->tij", _QW, grad, Ginv, grad) * area[:, None, None]
    Mref = np.einsum("q,qi,qj->ij", _QW, phi, phi)
    Mloc = area[:, None, None] * Mref[None]
    rows = np.repeat(nodes, 6, axis=1).ravel()
    cols = np.tile(nodes, (1, 6)).ravel()
    k = n + len(edges)
    K = sp.csr_matrix((Kloc.ravel(), (rows, cols)), shape=(k, k))
    B = sp.csr_matrix((Mloc.ravel(), (rows, cols)), shape=(k, k))
    if bc == "dirichlet":
        fixed_e = np.flatnonzero(mesh.edge_face_counts != 2)
        fixed = np.union1d(np.union1d(mesh.boundary_vertices, mesh.nonmanifold_vertices),
                           n + fixed_e)
        free = np.setdiff1d(np.arange(k), fixed)
        K, B = K[free][:, free].tocsr(), B[free][:, free].tocsr()
    return -K, B


def spectrum(mesh, method, bc="neumann", n=N):
    """The ``n`` smallest eigenvalues by ``method`` (one of :data:`METHODS`)."""
    if method == "p2":
        A, B = p2_matrices(mesh, bc)
        return solve_eigenproblem(A, B, n, return_vectors=False)
    refine = "extrapolate" if method == "extrapolated" else "none"
    mass = method if method in ("lumped", "mixed") else "consistent"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return cshape.shape_dna(mesh, n, bc=bc, mass=mass, refine=refine)


METHODS = ("linear", "lumped", "mixed", "extrapolated", "p2")


def weighted_spectrum(mesh, w, bc="neumann", n=N):
    """Eigenvalues with ``B = (1 - w) B_consistent + w B_lumped`` (``w = 1/2``: mixed)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        A, Bc = cshape.fem_matrices(mesh, bc=bc)
        _, Bl = cshape.fem_matrices(mesh, bc=bc, mass="lumped")
    return solve_eigenproblem(A, (1 - w) * Bc + w * Bl, n, return_vectors=False)


# --------------------------------------------------------------------------- known answers
def square_spectrum(n, bc):
    k = np.arange(1 if bc == "dirichlet" else 0, 40)
    return np.sort(np.add.outer(k**2, k**2).ravel())[:n] * np.pi**2


def disk_spectrum(n, bc):
    vals = []
    for order in range(40):
        z = jn_zeros(order, 40) if bc == "dirichlet" else jnp_zeros(order, 40)
        if bc == "neumann" and order == 0:
            z = np.concatenate([[0.0], z])
        vals += list(z**2) * (1 if order == 0 else 2)
    return np.sort(vals)[:n]


def max_rel_error(lam, ref, skip_zero=True):
    i = ref > 0 if skip_zero else slice(None)
    return float(np.max(np.abs(lam[i] / ref[i] - 1)))


def known_answers(quick=False):
    """Rows (case, vertices, error of each method) for the known-answer meshes."""
    rows = []
    for sub in ((3,) if quick else (3, 4)):
        mesh = shapes.icosphere(sub)
        ref = shapes.sphere_spectrum(N)
        rows.append(("unit icosphere, lam_1..lam_99 vs l(l+1)", mesh.n_vertices,
                     [max_rel_error(spectrum(mesh, k), ref) for k in METHODS]))
    n_ref = 20
    for bc in ("dirichlet", "neumann"):
        mesh = shapes.square(16 if quick else 24)
        ref = square_spectrum(N, bc)
        rows.append((f"unit square, {bc}, lam vs pi^2 (j^2 + k^2)", mesh.n_vertices,
                     [max_rel_error(spectrum(mesh, k, bc), ref) for k in METHODS]))
        mesh = shapes.disk(12 if quick else 16)
        ref = disk_spectrum(n_ref, bc)
        rows.append((f"unit disk, {bc}, first {n_ref} vs Bessel zeros^2", mesh.n_vertices,
                     [max_rel_error(spectrum(mesh, k, bc, n_ref), ref) for k in METHODS]))
    big = shapes.torus(96, 48) if quick else shapes.torus(192, 96)
    ref = spectrum(big, "extrapolated")
    mesh = shapes.torus(32, 16)
    rows.append((f"torus R=1, r=0.4, vs extrapolated {big.n_vertices}-vertex mesh",
                 mesh.n_vertices, [max_rel_error(spectrum(mesh, k), ref) for k in METHODS]))
    return rows


def equilateral(subdivisions):
    """The unit equilateral triangle split ``subdivisions`` times at its edge midpoints."""
    from cshape._refine import midpoint_subdivision

    m = cshape.Mesh([[0, 0, 0], [1, 0, 0], [0.5, np.sqrt(3) / 2, 0]], [[0, 1, 2]])
    for _ in range(subdivisions):
        m = midpoint_subdivision(m)
    return m


def equilateral_spectrum(n):
    """Dirichlet eigenvalues of the unit equilateral triangle (Lame)."""
    k = np.arange(1, 30)
    return np.sort((16 * np.pi**2 / 9 * (np.add.outer(k**2, k**2) + np.outer(k, k))).ravel())[:n]


def convergence_orders(quick=False):
    """Fitted order ``p`` of the error ~ h^p of lam_1..lam_10, Dirichlet.

    The square's grids alternate their diagonals, a pattern that midpoint subdivision does
    not repeat at half the size; the equilateral triangle's midpoint subdivisions do.
    """
    out = {}
    cases = (("unit square (alternating diagonals)", [shapes.square(g) for g in (8, 16, 32)],
              (8, 16, 32), square_spectrum(10, "dirichlet")),
             ("equilateral triangle (midpoint subdivisions)", [equilateral(s) for s in (4, 5, 6)],
              (16, 32, 64), equilateral_spectrum(10)))
    for name, meshes, grids, ref in cases:
        for k in METHODS:
            errs = [np.max(np.abs(spectrum(m, k, "dirichlet", 10) / ref - 1)) for m in meshes]
            out[(name, k)] = (grids, errs, -np.polyfit(np.log(grids), np.log(errs), 1)[0])
    return out


# --------------------------------------------------------------------------- weight study
WEIGHTS = (0.3, 0.4, 0.45, 0.5, 0.55, 0.6, 0.7)


def weight_cases(quick=False):
    """(name, mesh, bc, n, exact eigenvalues) of the weight study: known answers only."""
    cases = [("unit icosphere, lam_1..lam_99", shapes.icosphere(3), "neumann", N,
              shapes.sphere_spectrum(N))]
    if not quick:
        cases.append(("unit icosphere, lam_1..lam_99", shapes.icosphere(4), "neumann", N,
                      shapes.sphere_spectrum(N)))
    cases += [("unit square, dirichlet, lam_1..lam_30", shapes.square(32), "dirichlet", 30,
               square_spectrum(30, "dirichlet")),
              ("unit square, neumann, lam_1..lam_30", shapes.square(32), "neumann", 30,
               square_spectrum(30, "neumann")),
              ("unit disk, dirichlet, first 20", shapes.disk(24), "dirichlet", 20,
               disk_spectrum(20, "dirichlet")),
              ("unit disk, neumann, first 20", shapes.disk(24), "neumann", 20,
               disk_spectrum(20, "neumann")),
              ("equilateral triangle, dirichlet, first 10", equilateral(4), "dirichlet", 10,
               equilateral_spectrum(10))]
    return cases


def weight_study(quick=False):
    """Rows (case, vertices, errors at :data:`WEIGHTS`, best w, its error, mixed's error).

    The best ``w`` is the minimiser of the largest relative error over a grid of step 0.01
    (a bounded scalar search would do as well; the grid keeps every solve visible).
    """
    rows = []
    for name, mesh, bc, n, ref in weight_cases(quick):
        errs = [max_rel_error(weighted_spectrum(mesh, w, bc, n), ref) for w in WEIGHTS]
        grid = np.round(np.arange(0.30, 0.701, 0.01), 2)
        fine = [max_rel_error(weighted_spectrum(mesh, w, bc, n), ref) for w in grid]
        k = int(np.argmin(fine))
        mixed = max_rel_error(spectrum(mesh, "mixed", bc, n), ref)
        rows.append((name, mesh.n_vertices, errs, float(grid[k]), fine[k], mixed))
    return rows


# --------------------------------------------------------------------------- real pairs
def log_weyl(lam, area):
    i = np.arange(1, len(lam))
    return np.log(lam[1:] * area / (4 * np.pi * i))


def pairs_table(root=SHARED):
    """Rows (name, vertices a / b, mean |diff| at 1-17 and 80-99 of each method)."""
    if not root.is_dir():
        return []
    rows = []
    for name, a, b in PAIRS:
        ma, mb = (repair_mesh(cshape.load_mesh(root / p), warn=False) for p in (a, b))
        cells = []
        for k in METHODS:
            da, db = log_weyl(spectrum(ma, k), ma.area), log_weyl(spectrum(mb, k), mb.area)
            d = np.abs(da - db)
            cells.append((float(d[0:17].mean()), float(d[79:99].mean())))
        rows.append((name, ma.n_vertices, mb.n_vertices, cells))
    return rows


# --------------------------------------------------------------------------- candidates
def candidate_scores(N=N):
    """{refine: suite_scores rows} of the default's candidates on the suite's dev instances."""
    import cshape.data
    from cshape.data.suite import SUITE
    from cshape.reproduce.scores import suite_scores

    out = {}
    for refine in ("none", "extrapolate"):
        tables = {}
        for bench, (dev, _held_out) in SUITE.items():
            coll = cshape.data.load_collection(dev, progress=False)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                tables[bench] = cshape.describe(coll, N=N, progress=False, refine=refine)
        out[refine] = suite_scores(tables)
    return out


def candidates_report(scores):
    """Markdown: first tier of every candidate with linear and extrapolated spectra."""
    from cshape.reproduce.scores import choose_default

    lin = {r["title"]: r for r in scores["none"]}
    ext = {r["title"]: r for r in scores["extrapolate"]}
    benches = list(next(iter(lin.values()))["scores"])
    lines = ["# The exploration default's candidates with extrapolated spectra", "",
             f"`benchmarks/bench_refine.py --candidates`; {machine_summary()}", "",
             "First tier on the **development** instances of the suite "
             "(`cshape.data.suite.SUITE`), N = 100, with linear FEM spectra (lin) and "
             "`refine='extrapolate'` (ex).  Development numbers only: nothing here is "
             "held out.", "",
             "| candidate | " + " | ".join(f"{b} lin | ex" for b in benches)
             + " | worst lin | worst ex |",
             "|---|" + "---|---|" * len(benches) + "---|---|"]
    for title, r in lin.items():
        e = ext.get(title)
        if e is None:
            continue
        cells = " | ".join(f"{r['scores'][b]['ft']:.3f} | {e['scores'][b]['ft']:.3f}"
                           for b in benches)
        lines.append(f"| {title} | {cells} | {r['worst']:.3f} | {e['worst']:.3f} |")
    lines += ["", f"Highest worst first tier: linear {choose_default(scores['none'])['title']}, "
              f"extrapolated {choose_default(scores['extrapolate'])['title']}."]
    return "\n".join(lines) + "\n"


# --------------------------------------------------------------------------- costs
def child(size, method):
    """Time and peak memory of one spectrum of a torus, in this (fresh) process."""
    mesh = shapes.torus(*SIZES[size])
    spectrum(shapes.icosphere(1), method, n=10)  # imports and first calls
    base = proc_status_kib("VmHWM")
    t0, c0 = time.perf_counter(), time.process_time()
    spectrum(mesh, method)
    dt, cpu = time.perf_counter() - t0, time.process_time() - c0
    peak = proc_status_kib("VmHWM")
    return {"size": size, "method": method, "n": mesh.n_vertices, "seconds": dt, "cpu": cpu,
            "peak_mib": peak / 1024, "extra_mib": (peak - base) / 1024}


def costs(sizes, methods):
    out = []
    for size in sizes:
        for k in methods:
            if k == "p2" and size == "100k":
                continue  # the prototype's dense local assembly is not the point at 100K
            out.append(run_child(__file__, ["--child", size, k], threads=1, timeout=1800))
    return out


# --------------------------------------------------------------------------- report
def report(known, orders, pairs, cost_rows, weights=()):
    pct = lambda x: f"{100 * x:.3g} %"  # noqa: E731
    lines = ["# Resolution-free spectra: mass matrices, Richardson extrapolation, P2", "",
             f"`benchmarks/bench_refine.py`; {machine_summary()}", "",
             f"Processor: {processor()}", "",
             "## Known answers (largest relative error)", "",
             "linear: consistent mass (Eq. 5); lumped; mixed: their average; extrapolated: "
             "`refine='extrapolate'` (consistent mass); P2: quadratic elements.", "",
             "| mesh | vertices | linear | lumped | mixed | extrapolated | P2 |",
             "|---|---|---|---|---|---|---|"]
    for case, nv, errs in known:
        lines.append(f"| {case} | {nv} | " + " | ".join(pct(e) for e in errs) + " |")
    lines += ["", "## Convergence order, Dirichlet, lam_1 .. lam_10", "",
              "| domain | method | 1/h | largest relative errors | fitted order p "
              "(error ~ h^p) |", "|---|---|---|---|---|"]
    for (name, k), (grids, errs, p) in orders.items():
        lines.append(f"| {name} | {k} | {', '.join(map(str, grids))} | "
                     f"{', '.join(f'{e:.2e}' for e in errs)} | {p:.2f} |")
    if weights:
        lines += ["", "## The weight of the mixed mass matrix (known answers only)", "",
                  "Largest relative error with `B = (1 - w) B_consistent + w B_lumped`; "
                  "`w = 0.5` is `mass='mixed'`; best w on a grid of step 0.01.", "",
                  "| mesh | vertices | " + " | ".join(f"w={w:g}" for w in WEIGHTS)
                  + " | best w | its error | mixed |",
                  "|---|---|" + "---|" * len(WEIGHTS) + "---|---|---|"]
        for case, nv, errs, best, best_err, mixed in weights:
            lines.append(f"| {case} | {nv} | " + " | ".join(pct(e) for e in errs)
                         + f" | {best:.2f} | {pct(best_err)} | {pct(mixed)} |")
    if pairs:
        lines += ["", "## Same object at two resolutions (`../shared/meshes`)", "",
                  "Mean |difference| of `log(lam_i area / (4 pi i))` between the two meshes.", "",
                  "| pair (vertices) | i=1-17 " + " | ".join(METHODS) + " | i=80-99 "
                  + " | ".join(METHODS) + " |", "|---|" + "---|" * (2 * len(METHODS))]
        for name, na, nb, cells in pairs:
            lo = " | ".join(f"{c[0]:.4f}" for c in cells)
            hi = " | ".join(f"{c[1]:.4f}" for c in cells)
            lines.append(f"| {name} {na} / {nb} | {lo} | {hi} |")
    if cost_rows:
        lines += ["", "## Costs (tori, N = 100, one BLAS thread, each in a fresh process)", "",
                  "CPU seconds of the process (all its threads) and wall seconds; the ratio is "
                  "of CPU seconds, which a busy shared machine disturbs less than wall time.",
                  "", "| vertices | method | CPU s | x linear | wall s | peak RSS MiB | MiB "
                  "added by the solve |", "|---|---|---|---|---|---|---|"]
        base = {r["size"]: r["cpu"] for r in cost_rows
                if "error" not in r and r["method"] == "linear"}
        for r in cost_rows:
            if "error" in r:
                lines.append(f"| ? | ? | {r['error']} | | | | |")
                continue
            ratio = r["cpu"] / base[r["size"]] if r["size"] in base else float("nan")
            lines.append(f"| {r['n']} | {r['method']} | {r['cpu']:.2f} | {ratio:.2f} | "
                         f"{r['seconds']:.2f} | {r['peak_mib']:.0f} | {r['extra_mib']:.0f} |")
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--child", nargs=2, metavar=("SIZE", "METHOD"), help=argparse.SUPPRESS)
    ap.add_argument("--sizes", default="1k,10k,100k")
    ap.add_argument("--methods", default=",".join(METHODS))
    ap.add_argument("--no-costs", action="store_true")
    ap.add_argument("--quick", action="store_true", help="smaller meshes (smoke test)")
    ap.add_argument("--candidates", action="store_true",
                    help="only: the exploration default's candidates on the suite's dev "
                    "instances, linear and extrapolated (results/refine_candidates.md)")
    ap.add_argument("--out", default=str(HERE / "results" / "refine.md"))
    args = ap.parse_args(argv)
    if args.child:
        print(json.dumps(child(*args.child)))
        return 0
    if args.candidates:
        text = candidates_report(candidate_scores())
        (HERE / "results" / "refine_candidates.md").write_text(text)
        print(text)
        return 0
    known = known_answers(args.quick)
    orders = convergence_orders(args.quick)
    weights = weight_study(args.quick)
    pairs = [] if args.quick else pairs_table()
    cost_rows = [] if args.no_costs else costs(args.sizes.split(","), args.methods.split(","))
    text = report(known, orders, pairs, cost_rows, weights)
    Path(args.out).write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
