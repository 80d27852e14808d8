"""Benchmark: ``cshape.shape_dna(mesh, N=100)`` against LaPy on icospheres, in the same run.

Run from the repository root::

    .venv/bin/python benchmarks/bench_spectrum.py                 # 10k, 40k, 160k vertices
    .venv/bin/python benchmarks/bench_spectrum.py --sizes 10k,40k --repeats 5
    .venv/bin/python benchmarks/bench_spectrum.py --quick         # 10k, 40k, best of 2

For each sphere (``cshape.shapes.icosphere``: 10242, 40962, 163842 vertices) it times

* cshape: ``cshape.shape_dna((vertices, faces), N)`` (validation, repair, topology, FEM
  assembly and eigensolve, everything a user pays for: the plain arrays are passed so that
  no run reuses the topology cached on a ``Mesh`` by the one before), and
* LaPy as its users run it: ``lapy.Solver(TriaMesh(v, f)).eigs(k=N)`` at its defaults
  (LaPy 1.7.0: ``use_cholmod=False``, SuperLU; all BLAS threads), and its fastest setting
  ``use_cholmod=True`` (CHOLMOD through ``cholespy``), all BLAS threads; ``--lapy-one-thread``
  adds ``use_cholmod=True`` with BLAS held to one thread (the settings of
  ``bench_sweep.LAPY_SETTINGS``).  The ratio is against LaPy's defaults, with the one
  against ``use_cholmod=True`` beside it.

Each timing is the best of ``--repeats`` runs, the runs of the two libraries interleaved so
that both see the same machine load.  It then checks that both give the same eigenvalues
(relative difference at most ``--rtol``, 1e-8 by default; a zero eigenvalue is compared on
the scale of the largest one) and prints a table with the ratio LaPy time / cshape time.
A second table compares what comes before the eigensolve: cshape's preparation inside
``shape_dna`` (``spectrum._prepare``), ``cshape.fem_matrices`` called alone, and LaPy's
``TriaMesh`` + ``Solver`` assembly, with the threads ``spectrum.solver_threads`` gives the
Lanczos products at that size and load (``CSHAPE_THREADS`` overrides it).
The exit status is 1 if an accuracy check fails, 2 if LaPy is not installed (it is in the
``bench`` dependency group: ``pip install --group bench``).  Nothing here asserts a time.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

import cshape
from cshape import shapes, spectrum
from cshape._eigensolver.threads import solver_threads

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import load_average, processor, relative_difference  # noqa: E402
from _common import machine_summary as _machine_summary
from bench_sweep import lapy_label, lapy_setup  # noqa: E402


def machine_summary():
    """One line: date, machine, memory, library versions and the load average."""
    return _machine_summary(libs=('scipy', 'lapy'))

#: Accepted size labels and the icosphere subdivision level that gives them.
SIZES = {"10k": 5, "40k": 6, "160k": 7}


def _parse_sizes(text):
    labels = [t.strip().lower() for t in text.split(",") if t.strip()]
    bad = [t for t in labels if t not in SIZES]
    if bad or not labels:
        raise argparse.ArgumentTypeError(
            f"--sizes must be a comma-separated subset of {','.join(SIZES)}, got {text!r}"
        )
    return labels


def run_cshape(mesh, N):
    """Eigenvalues and seconds of ``cshape.shape_dna((vertices, faces), N)``.

    The plain arrays are passed, so every run validates the input and builds its topology
    anew, as LaPy's runs build their ``TriaMesh`` (a ``Mesh`` object would keep its cached
    edges from one run to the next).
    """
    t = time.perf_counter()
    lam = cshape.shape_dna((mesh.vertices, mesh.faces), N=N)
    return lam, time.perf_counter() - t


def run_overheads(mesh, N):
    """Seconds of what comes before the eigensolve, for cshape and for LaPy.

    Returns
    -------
    dict
        ``prepare``: cshape's validation, repair, topology, assembly and component check as
        ``shape_dna`` runs them (``spectrum._prepare``); ``fem_matrices``: the public
        ``cshape.fem_matrices`` called alone; ``lapy_assembly``: ``TriaMesh`` plus LaPy's
        ``Solver`` constructor (its FEM assembly).
    """
    from lapy import Solver, TriaMesh

    VF = (mesh.vertices, mesh.faces)
    out = {}
    t = time.perf_counter()
    spectrum._prepare(VF, N, "neumann", "consistent")
    out["prepare"] = time.perf_counter() - t
    t = time.perf_counter()
    cshape.fem_matrices(VF)
    out["fem_matrices"] = time.perf_counter() - t
    t = time.perf_counter()
    Solver(TriaMesh(mesh.vertices, mesh.faces))
    out["lapy_assembly"] = time.perf_counter() - t
    return out


def run_lapy(mesh, N, setting="default"):
    """Eigenvalues and seconds of one LaPy setting (assembly included; see
    ``bench_sweep.LAPY_SETTINGS``)."""
    from lapy import Solver, TriaMesh

    kwargs, limit = lapy_setup(setting)
    with limit:
        t = time.perf_counter()
        solver = Solver(TriaMesh(mesh.vertices, mesh.faces), **kwargs)
        lam, _ = solver.eigs(k=N)
        return np.sort(lam), time.perf_counter() - t


def missed_copies(lam):
    """Whether ``lam`` (unit sphere) is off the exact spectrum by more than 5 % anywhere.

    The discretisation error of these spheres is below 1 %; a solver that misses one copy of
    a repeated eigenvalue ``l(l+1)`` shifts every later value to the next cluster (>= 10 %).
    """
    ex = shapes.sphere_spectrum(len(lam))
    return bool(np.any(np.abs(lam[1:] - ex[1:]) / ex[1:] > 0.05))


def bench_size(label, N, repeats, lapy=("default", "cholespy")):
    """Time both solvers (LaPy in each of its settings ``lapy``); check every run of each
    against the exact sphere spectrum, and cshape's eigenvalues against those of a LaPy run
    that found every copy."""
    mesh = shapes.icosphere(SIZES[label])
    t_cs, t_lapy = [], {s: [] for s in lapy}
    runs_cs, runs_lapy = [], []
    over = []
    for _ in range(repeats):
        over.append(run_overheads(mesh, N))
        lam, t = run_cshape(mesh, N)
        runs_cs.append(lam)
        t_cs.append(t)
        for setting in lapy:
            lam, t = run_lapy(mesh, N, setting)
            runs_lapy.append(lam)
            t_lapy[setting].append(t)
    best_lapy = {k: min(v) for k, v in t_lapy.items()}
    cs_missed = sum(missed_copies(lam) for lam in runs_cs)
    lapy_missed = sum(missed_copies(lam) for lam in runs_lapy)
    cs_spread = max(float(relative_difference(lam, runs_cs[0]).max()) for lam in runs_cs)
    good_lapy = [lam for lam in runs_lapy if not missed_copies(lam)] or runs_lapy
    # against the LaPy run that agrees best: ARPACK draws a new random start vector per
    # call and can take a copy from the neighbouring cluster of a multiplet that the
    # icosphere splits (l=4: 4+5 copies, ~6e-4 apart), which missed_copies cannot see
    rel = max(min(float(relative_difference(lam, ref).max()) for ref in good_lapy)
              for lam in runs_cs)
    return {
        "label": label,
        "n": mesh.n_vertices,
        "threads": solver_threads(mesh.n_vertices),
        **{k: min(o[k] for o in over) for k in over[0]},
        "cshape": min(t_cs),
        "lapy": best_lapy[lapy[0]],
        "lapy_settings": best_lapy,
        "maxrel": rel,
        "cshape_missed": cs_missed,
        "cshape_runs": len(runs_cs),
        "cshape_spread": cs_spread,
        "lapy_missed": lapy_missed,
        "lapy_runs": len(runs_lapy),
    }


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=_parse_sizes, default=list(SIZES),
                        help="comma-separated subset of 10k,40k,160k (default: all)")
    parser.add_argument("--repeats", type=int, default=3, help="runs per timing (best counts)")
    parser.add_argument("-N", type=int, default=100, help="number of eigenvalues (default 100)")
    parser.add_argument("--quick", action="store_true",
                        help="10k and 40k only, best of 2 (a few minutes)")
    parser.add_argument("--rtol", type=float, default=1e-8,
                        help="largest accepted relative eigenvalue difference (default 1e-8)")
    parser.add_argument("--lapy-one-thread", action="store_true",
                        help="also time LaPy use_cholmod=True with BLAS held to one thread")
    args = parser.parse_args(argv)
    try:
        import lapy  # noqa: F401
    except ImportError:
        print("LaPy is not installed: .venv/bin/pip install --group bench  (or pip install lapy)")
        return 2

    if args.quick:
        args.sizes, args.repeats = ["10k", "40k"], min(args.repeats, 2)
    lapy = ("default", "cholespy") + (("cholespy-1t",) if args.lapy_one_thread else ())
    print(machine_summary())
    print(f"Processor: {processor()}")
    print(f"N={args.N}, best of {args.repeats} runs each, runs interleaved; cshape at its "
          "defaults; LaPy:")
    for s in lapy:
        print(f"  {s}: {lapy_label(s)}")
    print()
    header = (f"{'size':>5} {'vertices':>9} {'cshape [s]':>11} {'LaPy [s]':>9} "
              f"{'LaPy/cshape':>12} {'max rel diff':>13}  check   "
              + " / ".join(lapy) + " [s] (LaPy / cshape)")
    print(header)
    print("-" * len(header))
    failed = False
    notes = []
    rows = []
    for label in args.sizes:
        r = bench_size(label, args.N, args.repeats, lapy)
        rows.append(r)
        ok = r["maxrel"] <= args.rtol and r["cshape_missed"] == 0 and r["cshape_spread"] == 0
        failed |= not ok
        print(f"{r['label']:>5} {r['n']:>9d} {r['cshape']:>11.2f} {r['lapy']:>9.2f} "
              f"{r['lapy'] / r['cshape']:>12.2f} {r['maxrel']:>13.1e}  {'ok' if ok else 'FAIL':<6}"
              "  " + " / ".join(f"{r['lapy_settings'][s]:.2f}" for s in lapy) + " ("
              + " / ".join(f"{r['lapy_settings'][s] / r['cshape']:.2f}" for s in lapy) + ")",
              flush=True)
        if r["cshape_missed"] or r["cshape_spread"]:
            notes.append(f"{label}: cshape missed a copy of a repeated eigenvalue in "
                         f"{r['cshape_missed']} of {r['cshape_runs']} runs; its runs differ "
                         f"by up to {r['cshape_spread']:.1e} (it must be deterministic)")
        if r["lapy_missed"]:
            notes.append(f"{label}: LaPy (ARPACK, random start vector) missed a copy of a "
                         f"repeated eigenvalue in {r['lapy_missed']} of {r['lapy_runs']} runs; "
                         "cshape was compared with a LaPy run that found them all")
    print("\nBefore the eigensolve (best of the same runs): cshape's validation, repair, "
          "topology and assembly\ninside shape_dna, fem_matrices called alone, LaPy's "
          "TriaMesh + Solver() assembly\n")
    head2 = (f"{'size':>5} {'prepare [s]':>12} {'fem_matrices [s]':>17} {'LaPy assembly [s]':>18}"
             f" {'LaPy/prepare':>13}  threads")
    print(head2)
    print("-" * len(head2))
    for r in rows:
        print(f"{r['label']:>5} {r['prepare']:>12.3f} {r['fem_matrices']:>17.3f} "
              f"{r['lapy_assembly']:>18.3f} {r['lapy_assembly'] / r['prepare']:>13.2f}  "
              f"{r['threads']}")
    print(f"\nat the end: load average {' '.join(f'{x:.2f}' for x in load_average())}")
    for note in notes:
        print("note:", note)
    if failed:
        print(f"\nFAIL: cshape's eigenvalues are wrong, not deterministic, or differ from "
              f"LaPy's by more than rtol={args.rtol:g}")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
