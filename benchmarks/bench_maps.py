"""Benchmark: vertex maps between poses by nearest signature, functional maps and ZoomOut.

Run from the repository root::

    .venv/bin/python benchmarks/bench_maps.py            # generated poses + TOSCA wolf, centaur
    .venv/bin/python benchmarks/bench_maps.py --quick    # generated poses only

Pairs whose true map is the identity (the same vertices and faces, moved):

* generated: the rest pose of :func:`cshape.data.poses.posed_figure` to its poses 0 and 1
  (human and quadruped);
* TOSCA (``../shared/realdev/tosca-dev``, read in place, skipped when missing): pose 0 of a
  character to another pose of the same character with the same number of vertices.

For each pair, with ``N = 100`` eigenpairs of each shape and the WKS of :func:`cshape.point_map`
(100 energies of the source, every 5th kept, shapes scaled to unit area):

* ``nearest WKS``: :func:`cshape.match_points` on the 100 WKS values;
* ``FM k0=30``: :func:`cshape.functional_map` (size 30) and :func:`cshape.map_to_pointwise`,
  with and without the orientation term;
* ``FM + ZoomOut``: the same, then :func:`cshape.zoomout` to size 100 (3000 samples per shape,
  as :func:`cshape.point_map` does).

Measures: the share of target vertices whose match lies within 5 % of the source's
bounding-box diagonal of the true vertex (Euclidean, on the source), the mean geodesic error
over 200 target vertices (:func:`cshape.geodesic_errors`, heat method) divided by
``sqrt(area)``, and the seconds of the mapping step (the eigenpairs, common to all methods,
are timed apart).  Results go to ``benchmarks/results/maps[_quick].md``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

import cshape
from cshape import signatures as sg
from cshape.data import poses

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import cpu_summary, load_average  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
TOSCA = Path(__file__).resolve().parents[2] / "shared" / "realdev" / "tosca-dev"
if not TOSCA.exists():
    TOSCA = Path("/work/shared/realdev/tosca-dev")

N, K0, N_ENERGIES, STRIDE, SAMPLE, N_EVAL = 100, 30, 100, 5, 3000, 200
THRESHOLD = 0.05
METHODS = ("nearest WKS", "FM k0=30, no orientation", "FM k0=30, orientation",
           "FM + ZoomOut, no orientation", "FM + ZoomOut, orientation")


def generated_pairs():
    for kind in ("human", "quadruped"):
        rest = poses.posed_figure(kind, rest=True)
        for seed in (0, 1):
            yield f"{kind} rest -> pose {seed}", rest, poses.posed_figure(kind, seed)


def _same_faces(a, b, share=0.8):
    """Most triangles in common (each face's vertices sorted): the poses of a TOSCA character
    share their vertex numbering and 83-99 % of their faces (sorted)."""
    fa, fb = np.sort(a.faces, axis=1), np.sort(b.faces, axis=1)
    return fa.shape == fb.shape and (fa == fb).all(axis=1).mean() >= share


def tosca_pairs(characters=("cat", "dog", "wolf", "centaur")):
    if not TOSCA.exists():
        return
    for c in characters:
        first = cshape.load_mesh(TOSCA / f"{c}0.off.gz")
        for i in range(1, 12):
            path = TOSCA / f"{c}{i}.off.gz"
            if path.exists():
                other = cshape.load_mesh(path)
                if other.n_vertices == first.n_vertices and _same_faces(other, first):
                    yield f"TOSCA {c}0 -> {c}{i}", first, other
                    break


def measure(S, T, *, n=N, k0=K0):
    """Every method on one pair: ``{method: (share within 5 %, geodesic error, seconds)}``."""
    t = time.perf_counter()
    lS, pS = cshape.eigenpairs(S, n)
    lT, pT = cshape.eigenpairs(T, n)
    eig_s = time.perf_counter() - t
    _, BS = cshape.fem_matrices(S)
    _, BT = cshape.fem_matrices(T)
    e, sigma = sg.wks_energies(lS, N_ENERGIES, area=S.area)
    dS = cshape.wks(lS, pS, e, sigma, area=S.area)
    dT = cshape.wks(lT, pT, e, sigma, area=T.area)
    diag = np.linalg.norm(S.vertices.max(0) - S.vertices.min(0))
    geo = cshape.HeatGeodesics(S)
    ev = np.linspace(0, T.n_vertices - 1, N_EVAL).astype(int)
    out = {}

    def score(name, p, seconds):
        within = np.linalg.norm(S.vertices[p] - S.vertices, axis=1) <= THRESHOLD * diag
        err = cshape.geodesic_errors(S, p, vertices=ev, geodesics=geo).mean()
        out[name] = (float(within.mean()), float(err / np.sqrt(S.area)), seconds)

    t = time.perf_counter()
    p = cshape.match_points(dT, dS)
    score("nearest WKS", p, time.perf_counter() - t)
    for orient in (False, True):
        label = "orientation" if orient else "no orientation"
        t = time.perf_counter()
        C = cshape.functional_map(lS[:k0], pS[:, :k0], BS, lT[:k0], pT[:, :k0], BT,
                                  dS[:, ::STRIDE], dT[:, ::STRIDE], source=S, target=T,
                                  orientation_weight=0.1 if orient else 0.0)
        fm_s = time.perf_counter() - t
        score(f"FM k0={k0}, {label}", cshape.map_to_pointwise(C, pS, pT),
              time.perf_counter() - t)
        t = time.perf_counter()
        Z = cshape.zoomout(C, pS, pT, BT, n, sample=SAMPLE)
        score(f"FM + ZoomOut, {label}", cshape.map_to_pointwise(Z, pS, pT),
              fm_s + time.perf_counter() - t)
    return out, eig_s


def write_results(rows, name, command=""):
    RESULTS.mkdir(exist_ok=True)
    lines = ["# Vertex maps between poses: nearest signature, functional maps, ZoomOut",
             "",
             f"Processor: {cpu_summary()}; load average {load_average()[0]:.1f}.",
             f"`N = {N}` eigenpairs per shape, `k0 = {K0}`, ZoomOut to {N} with {SAMPLE} "
             f"samples; within 5 %: share of target vertices matched within 5 % of the "
             f"bounding-box diagonal of the true vertex; geodesic error: mean over {N_EVAL} "
             "vertices / sqrt(area); seconds: the mapping step (eigenpairs apart).",
             f"Command: `python benchmarks/bench_maps.py{' ' + command if command else ''}`.",
             "",
             "| pair | vertices | eigenpairs (s) | method | within 5 % | geodesic error | s |",
             "|---|---|---|---|---|---|---|"]
    for pair, nv, eig_s, res in rows:
        for m in METHODS:
            w, g, s = res[m]
            lines.append(f"| {pair} | {nv} | {eig_s:.1f} | {m} | {w:.3f} | {g:.4f} | {s:.2f} |")
    lines += ["", "Mean over the pairs:", "", "| method | within 5 % | geodesic error |",
              "|---|---|---|"]
    for m in METHODS:
        w = np.mean([r[3][m][0] for r in rows])
        g = np.mean([r[3][m][1] for r in rows])
        lines.append(f"| {m} | {w:.3f} | {g:.4f} |")
    (RESULTS / f"{name}.md").write_text("\n".join(lines) + "\n")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="generated poses only")
    ap.add_argument("--characters", default="wolf,centaur",
                    help="TOSCA characters, comma-separated (default: wolf,centaur; cat and "
                         "dog have 25-28K vertices)")
    ap.add_argument("--tosca-only", action="store_true", help="the TOSCA pairs only")
    args = ap.parse_args(argv)
    pairs = [] if args.tosca_only else list(generated_pairs())
    if not args.quick:
        pairs += list(tosca_pairs(tuple(args.characters.split(","))))
    rows = []
    for label, S, T in pairs:
        res, eig_s = measure(S, T)
        rows.append((label, S.n_vertices, eig_s, res))
        print(label, {m: tuple(round(x, 3) for x in v) for m, v in res.items()}, flush=True)
    command = " ".join(sys.argv[1:] if argv is None else argv)
    name = "maps_quick" if args.quick else "maps_tosca" if args.tosca_only else "maps"
    print(write_results(rows, name, command))


if __name__ == "__main__":
    main()
