"""Benchmark: point signatures on a large mesh, and eigenpairs against LaPy (issue 21).

Run from the repository root::

    .venv/bin/python benchmarks/bench_signatures.py            # 100K torus, 41K sphere
    .venv/bin/python benchmarks/bench_signatures.py --quick    # 20K torus, 10K sphere

Two parts, in the same run:

1. **Signatures of a large mesh** (a torus of ``--vertices`` vertices, 100,000 by default):
   ``cshape.spectrum.eigenpairs(mesh, N=100)`` once, then the seconds of :func:`cshape.hks` and
   :func:`cshape.wks` at ``--scales`` (100) times or energies, :func:`cshape.signatures.si_hks` (its
   321 log-times), :func:`cshape.signatures.heat_kernel` from one vertex and
:func:`cshape.signatures.match_points`
   of 1000 vertices against all (it is brute force: ``n_a n_b k`` operations).  Each is
   reported beside the eigensolve, as a fraction of it.
2. **Eigenpairs against LaPy** on the icosphere of 40,962 vertices:
   ``cshape.spectrum.eigenpairs((v, f), N=100)`` (eigenfunctions included, plain arrays so that
   every run validates and builds its topology anew) against LaPy as its users run it,
   ``lapy.Solver(TriaMesh(v, f)).eigs(k=100)`` at its defaults (LaPy 1.7.0:
   ``use_cholmod=False``, SuperLU; all BLAS threads), and against its fastest setting
   ``use_cholmod=True`` (cholespy), all BLAS threads (``bench_sweep.LAPY_SETTINGS``);
   runs interleaved, best of ``--repeats``.  Both must agree: the eigenvalues to ``1e-8``
   relative and the HKS computed from either's eigenfunctions (a check that does not
   depend on the basis chosen inside a repeated eigenvalue) to ``1e-6``.

The tables go to ``benchmarks/results/signatures[_quick].md``.  Nothing asserts a time.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

import cshape
from cshape import shapes
from cshape import signatures as sg

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import (  # noqa: E402
    load_average,
    machine_summary,
    max_relative_difference,
    processor,
)
from bench_sweep import lapy_label, lapy_setup  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"


def torus_mesh(n_vertices):
    """A torus (R = 1, r = 0.4) of about ``n_vertices`` vertices, cells near square."""
    n_minor = max(3, int(round(np.sqrt(n_vertices * 0.4))))
    n_major = max(3, int(round(n_vertices / n_minor)))
    return shapes.torus(n_major, n_minor)


def _timed(fn, *args, **kwargs):
    t = time.perf_counter()
    out = fn(*args, **kwargs)
    return out, time.perf_counter() - t


def time_signatures(mesh, N=100, n_scales=100, n_match=1000, seed=0):
    """Seconds of the eigensolve and of each signature on ``mesh``.

    Returns
    -------
    dict
        ``n``, ``N``, ``n_scales`` and the seconds ``eigenpairs`` (:func:`cshape.eigenbasis`),
        ``hks``, ``wks``,
        ``si_hks``, ``heat_kernel``, ``match_points`` (``n_match`` vertices against all),
        with the shapes of the results (``hks_shape`` ...).
    """
    basis, t_eig = _timed(cshape.eigenbasis, mesh, N)
    r = {"n": mesh.n_vertices, "N": N, "n_scales": n_scales, "eigenpairs": t_eig}
    h, r["hks"] = _timed(cshape.hks, basis, n_times=n_scales)
    w, r["wks"] = _timed(cshape.wks, basis, n_energies=n_scales)
    s, r["si_hks"] = _timed(cshape.signatures.si_hks, basis)
    _, r["heat_kernel"] = _timed(sg.heat_kernel, basis, float(sg.hks_times(basis)[50]), 0)
    rng = np.random.default_rng(seed)
    sub = rng.choice(mesh.n_vertices, size=min(n_match, mesh.n_vertices), replace=False)
    logh = np.log(h)
    match, r["match_points"] = _timed(cshape.signatures.match_points, logh[sub], logh)
    r["hks_shape"], r["wks_shape"], r["si_hks_shape"] = h.shape, w.shape, s.shape
    r["si_hks_times"] = len(sg.si_hks_tau())
    r["n_match"] = len(sub)
    # a vertex's own signature is in the set: the match is at distance ~0 (the vertex or one
    # with the same signature: the torus is a surface of revolution)
    r["match_dist"] = float(np.linalg.norm(logh[match] - logh[sub], axis=1).max())
    return r


def run_lapy(mesh, N, setting="default"):
    """(lam, phi) and seconds of one LaPy setting (assembly included; see
    ``bench_sweep.LAPY_SETTINGS``)."""
    from lapy import Solver, TriaMesh

    kwargs, limit = lapy_setup(setting)
    with limit:
        t = time.perf_counter()
        lam, phi = Solver(TriaMesh(mesh.vertices, mesh.faces), **kwargs).eigs(k=N)
        dt = time.perf_counter() - t
    order = np.argsort(lam)
    return lam[order], phi[:, order], dt


LAPY = ("default", "cholespy")


def eigenpairs_vs_lapy(mesh, N=100, repeats=3):
    """Interleaved best-of-``repeats`` timings of cshape's and LaPy's eigenpairs.

    Returns
    -------
    dict
        ``n``, ``N``, ``cshape`` and ``lapy`` seconds (LaPy at its defaults),
        ``lapy_cholespy`` (``use_cholmod=True``), ``ratio`` (LaPy / cshape),
        ``ratio_cholespy``, ``lam_maxrel`` (the
        eigenvalues against the LaPy run that agrees best) and ``hks_maxrel`` (HKS at the
        default times from either's eigenfunctions, same LaPy run).
    """
    VF = (mesh.vertices, mesh.faces)
    t_cs, t_lapy = [], {s: [] for s in LAPY}
    lapy_runs = []
    cs = None
    for _ in range(repeats):
        (lam, phi), t = _timed(cshape.spectrum.eigenpairs, VF, N)
        cs = (lam, phi)
        t_cs.append(t)
        for setting in LAPY:
            lam_l, phi_l, t = run_lapy(mesh, N, setting)
            lapy_runs.append((lam_l, phi_l))
            t_lapy[setting].append(t)
    lam, phi = cs
    # ARPACK's random start can take a copy from a neighbouring cluster of an icosphere
    # multiplet (see bench_spectrum.py): compare with the LaPy run that agrees best
    diffs = [max_relative_difference(lam, ref[0]) for ref in lapy_runs]
    best = int(np.argmin(diffs))
    B = cshape.fem_matrices(VF)[1]  # the same linear FEM mass as LaPy's
    basis = cshape.Eigenbasis(lam, phi, B)
    t = sg.hks_times(basis)
    h_cs = cshape.hks(basis, t)
    h_lapy = cshape.hks(cshape.Eigenbasis(np.maximum(lapy_runs[best][0], 0.0),
                                          lapy_runs[best][1], B), t)
    lapy = {k: min(v) for k, v in t_lapy.items()}
    return {
        "n": mesh.n_vertices, "N": N, "repeats": repeats,
        "cshape": min(t_cs), "lapy": lapy["default"], "lapy_cholespy": lapy["cholespy"],
        "ratio": lapy["default"] / min(t_cs), "ratio_cholespy": lapy["cholespy"] / min(t_cs),
        "lam_maxrel": diffs[best],
        "hks_maxrel": float(np.abs(h_cs / h_lapy - 1).max()),
    }


def markdown(sig, eig, header, footer):
    """The report: the signature timings and the LaPy comparison, as Markdown."""
    lines = [
        "# Point signatures (issue 21)", "", header, "",
        f"## Signatures of a {sig['n']:,}-vertex torus from N = {sig['N']} eigenpairs", "",
        "| step | result shape | seconds | x eigenpairs |", "|---|---|---|---|",
        f"| eigenpairs(N={sig['N']}) | ({sig['n']}, {sig['N']}) | {sig['eigenpairs']:.2f} | 1 |",
    ]
    shapes_ = {"hks": sig["hks_shape"], "wks": sig["wks_shape"], "si_hks": sig["si_hks_shape"],
               "heat_kernel": (sig["n"],), "match_points": (sig["n_match"],)}
    labels = {"hks": f"hks, {sig['n_scales']} times", "wks": f"wks, {sig['n_scales']} energies",
              "si_hks": f"si_hks, {sig['si_hks_times']} log-times, 6 frequencies",
              "heat_kernel": "heat_kernel, one source",
              "match_points": f"match_points, {sig['n_match']} vs {sig['n']:,} (log HKS)"}
    for k, label in labels.items():
        ratio = sig[k] / sig["eigenpairs"]
        lines.append(f"| {label} | {shapes_[k]} | {sig[k]:.2f} | {ratio:.2f} |")
    lines += [
        "", f"Largest distance from a matched vertex's log HKS to its match's (its own "
        f"signature is in the set): {sig['match_dist']:.1e}.", "",
        f"## eigenpairs(N={eig['N']}) against LaPy, {eig['n']:,}-vertex icosphere", "",
        f"Best of {eig['repeats']} interleaved runs; eigenfunctions included in both; cshape "
        f"at its defaults; LaPy: {lapy_label('default')}, and {lapy_label('cholespy')}.  "
        f"Processor: {processor()}.", "",
        "| cshape [s] | LaPy defaults [s] | LaPy / cshape | LaPy use_cholmod=True [s] "
        "| LaPy use_cholmod=True / cshape | max rel. diff. lam | max rel. diff. HKS |",
        "|---|---|---|---|---|---|---|",
        f"| {eig['cshape']:.2f} | {eig['lapy']:.2f} | {eig['ratio']:.2f} | "
        f"{eig['lapy_cholespy']:.2f} | {eig['ratio_cholespy']:.2f} | {eig['lam_maxrel']:.1e} | "
        f"{eig['hks_maxrel']:.1e} |",
        "", footer, "",
    ]
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--vertices", type=int, default=100_000,
                        help="vertices of the torus for the signatures (default 100000)")
    parser.add_argument("--sphere-level", type=int, default=6,
                        help="icosphere level for the LaPy comparison (6: 40962 vertices)")
    parser.add_argument("--scales", type=int, default=100, help="times / energies (100)")
    parser.add_argument("-N", type=int, default=100, help="eigenpairs (default 100)")
    parser.add_argument("--repeats", type=int, default=3, help="runs per LaPy timing")
    parser.add_argument("--quick", action="store_true", help="20K torus, 10K sphere, 2 runs")
    args = parser.parse_args(argv)
    try:
        import lapy  # noqa: F401
    except ImportError:
        print("LaPy is not installed: .venv/bin/pip install --group bench  (or pip install lapy)")
        return 2
    name = "signatures"
    if args.quick:
        args.vertices, args.sphere_level, args.repeats = 20_000, 5, 2
        name = "signatures_quick"
    header = machine_summary(libs=("scipy", "lapy", "cholespy"))
    print(header, flush=True)
    sig = time_signatures(torus_mesh(args.vertices), args.N, args.scales)
    print({k: v for k, v in sig.items()}, flush=True)
    eig = eigenpairs_vs_lapy(shapes.icosphere(args.sphere_level), args.N, args.repeats)
    print(eig, flush=True)
    footer = f"At the end: load average {' '.join(f'{x:.2f}' for x in load_average())}."
    md = markdown(sig, eig, header, footer)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / f"{name}.md").write_text(md)
    print(md)
    ok = eig["lam_maxrel"] <= 1e-8 and eig["hks_maxrel"] <= 1e-6
    if not ok:
        print("FAIL: cshape's and LaPy's eigenpairs disagree")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
