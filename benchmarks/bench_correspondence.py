"""Benchmark: point correspondence across poses with HKS, WKS, SI-HKS and raw coordinates.

Run from the repository root::

    .venv/bin/python benchmarks/bench_correspondence.py            # 2 classes x 5 poses
    .venv/bin/python benchmarks/bench_correspondence.py --quick    # 2 classes x 2 poses

The shapes are :func:`cshape.data.poses.posed_figure`: a template (rest pose, ~2800 vertices)
whose vertices are moved by a skeleton, so that the ground-truth map from the rest pose to
every pose is the identity.  They are the items of the manifest's ``poses`` collection
(``cshape.data.load_collection("poses")``: rest pose and poses 0-4 of each class).

For every pose, each vertex ``i`` of the rest pose is matched to the vertex of the pose
whose descriptor is nearest (:func:`cshape.signatures.match_points`), and the
error is the geodesic distance on the pose between the match and vertex ``i`` (shortest
paths along the edges, which overestimate the geodesic by a few per cent), over the pose's
geodesic diameter.  A match counts as correct when the error is at most 5 % of it.

Descriptors, all from ``N = 100`` eigenpairs of each shape:

* ``HKS``: Sun et al.'s scaled HKS (``normalization='trace'``) at the 100 default times of the
  rest pose, the same times on both shapes;
* ``WKS``: Aubry et al.'s WKS at the 100 default energies of the rest pose;
* ``SI-HKS``: the 6 lowest frequencies (default grid);
* ``xyz, rigid oracle``: coordinates after the best rigid alignment given the true map
  (Procrustes): the most any rigid alignment could do, a baseline that knows the answer;
* ``xyz, ICP``: coordinates after iterative closest point from the centred shapes (a rigid
  alignment without the answer).

The left-right mirror of a figure is an intrinsic symmetry: HKS, WKS and SI-HKS cannot tell
a left hand from a right one.  The table gives the accuracy both ways: exact, and "up to the
mirror" (a match at the mirror image of the right vertex counts, as symmetric-shape
benchmarks usually report), and for mutual nearest neighbours only (``mutual=True``): the
share of vertices kept and the exact accuracy among them.  Results go to
``benchmarks/results/correspondence[_quick].md``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp
from scipy.sparse import csgraph
from scipy.spatial import cKDTree

import cshape
from cshape import signatures as sg
from cshape.data import poses

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import load_average, machine_summary  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"

#: A match is correct within this fraction of the geodesic diameter.
THRESHOLD = 0.05

DESCRIPTORS = ("HKS", "WKS", "SI-HKS", "xyz, rigid oracle", "xyz, ICP")


def edge_graph(mesh):
    """The mesh's edges as a symmetric sparse matrix of their lengths."""
    E = mesh.edges
    w = np.linalg.norm(mesh.vertices[E[:, 0]] - mesh.vertices[E[:, 1]], axis=1)
    n = mesh.n_vertices
    G = sp.coo_matrix((w, (E[:, 0], E[:, 1])), shape=(n, n))
    return (G + G.T).tocsr()


def geodesic_distances(mesh):
    """All-pairs shortest edge-path distances on ``mesh``, shape (n, n)."""
    return csgraph.dijkstra(edge_graph(mesh), directed=False)


def procrustes(X, Y):
    """The rotation ``R`` and shift ``t`` minimising ``|X R^T + t - Y|`` (Kabsch)."""
    mx, my = X.mean(0), Y.mean(0)
    U, _, Vt = np.linalg.svd((X - mx).T @ (Y - my))
    d = np.sign(np.linalg.det(U @ Vt))
    R = (U @ np.diag([1, 1, d]) @ Vt).T
    return R, my - mx @ R.T


def icp(X, Y, iterations=50):
    """``X`` rigidly aligned to ``Y`` by iterative closest point from the centred shapes."""
    Z = X - X.mean(0) + Y.mean(0)
    tree = cKDTree(Y)
    for _ in range(iterations):
        nn = tree.query(Z)[1]
        R, t = procrustes(Z, Y[nn])
        Z = Z @ R.T + t
    return Z


def descriptors(rest, pose, N=100, n_scales=100):
    """Per-vertex descriptors of the rest pose and the pose, by name: (a, b) pairs."""
    ba, bb = cshape.eigenbasis(rest, N), cshape.eigenbasis(pose, N)
    t = sg.hks_times(ba, n_scales)
    e, sigma = sg.wks_energies(ba, n_scales)
    R, tr = procrustes(rest.vertices, pose.vertices)
    return {
        "HKS": (cshape.hks(ba, t, scale="trace"), cshape.hks(bb, t, scale="trace")),
        "WKS": (cshape.wks(ba, e, sigma), cshape.wks(bb, e, sigma)),
        "SI-HKS": (cshape.signatures.si_hks(ba), cshape.signatures.si_hks(bb)),
        "xyz, rigid oracle": (rest.vertices @ R.T + tr, pose.vertices),
        "xyz, ICP": (icp(rest.vertices, pose.vertices), pose.vertices),
    }


def evaluate(kind, seeds, N=100, n_scales=100, template=None):
    """One row per (pose, descriptor): accuracy exact and up to the mirror, mean error.

    ``seeds`` are pose seeds (``None``: the rest pose itself, a check of the plumbing);
    ``template`` holds keyword arguments of :func:`cshape.data.poses.pose_template`.
    """
    template = template or {}
    rest = poses.posed_figure(kind, rest=True, **template)
    mirror = poses.mirror_map(kind, rest)
    ident = np.arange(rest.n_vertices)
    rows = []
    for seed in seeds:
        pose = poses.posed_figure(kind, seed, rest=seed is None, **template)
        t0 = time.perf_counter()
        desc = descriptors(rest, pose, N, n_scales)
        D = geodesic_distances(pose)
        diam = float(D.max())
        for name in DESCRIPTORS:
            a, b = desc[name]
            match = cshape.signatures.match_points(a, b)
            err, err_m = D[ident, match], D[mirror, match]
            best = np.minimum(err, err_m)
            # mutual nearest neighbours only: fewer matches, how many of them right
            kept = cshape.signatures.match_points(a, b, mutual=True) >= 0
            rows.append({
                "kind": kind, "seed": seed, "descriptor": name, "n": rest.n_vertices,
                "acc": float(np.mean(err <= THRESHOLD * diam)),
                "acc_mirror": float(np.mean(best <= THRESHOLD * diam)),
                "mean_err": float(np.mean(err) / diam),
                "mean_err_mirror": float(np.mean(best) / diam),
                "mutual_kept": float(np.mean(kept)),
                "mutual_acc": float(np.mean(err[kept] <= THRESHOLD * diam)),
            })
        print(f"{kind} pose {seed}: {time.perf_counter() - t0:.1f} s", flush=True)
    return rows


def summary(rows):
    """Mean over poses per (class, descriptor) and over everything per descriptor."""
    out = []
    for kind in sorted({r["kind"] for r in rows}) + ["all"]:
        for name in DESCRIPTORS:
            sel = [r for r in rows if r["descriptor"] == name and kind in ("all", r["kind"])]
            out.append({"kind": kind, "descriptor": name, "poses": len(sel),
                        **{k: float(np.mean([r[k] for r in sel]))
                           for k in ("acc", "acc_mirror", "mean_err", "mean_err_mirror",
                                     "mutual_kept", "mutual_acc")}})
    return out


def markdown(rows, header, footer):
    lines = [
        "# Point correspondence across poses (issue 21)", "", header, "",
        "Rest pose to each pose of `cshape.data.poses.posed_figure` (ground truth: the identity); "
        f"a match is correct within {100 * THRESHOLD:.0f} % of the geodesic diameter (edge "
        "paths).  Signatures from N = 100 eigenpairs; the xyz rows are baselines (the oracle "
        "knows the true map for its rigid alignment).", "",
        "| class | descriptor | poses | accuracy | accuracy up to mirror | mean error / diam. "
        "| mean error up to mirror | mutual matches kept | accuracy of mutual |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in summary(rows):
        lines.append(
            f"| {r['kind']} | {r['descriptor']} | {r['poses']} | {100 * r['acc']:.1f} % | "
            f"{100 * r['acc_mirror']:.1f} % | {r['mean_err']:.3f} | {r['mean_err_mirror']:.3f} | "
            f"{100 * r['mutual_kept']:.1f} % | {100 * r['mutual_acc']:.1f} % |"
        )
    lines += ["", footer, ""]
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--poses", type=int, default=5, help="poses per class (default 5)")
    parser.add_argument("--quick", action="store_true", help="2 poses per class")
    args = parser.parse_args(argv)
    n_poses = 2 if args.quick else args.poses
    name = "correspondence_quick" if args.quick else "correspondence"
    header = machine_summary()
    print(header, flush=True)
    rows = []
    for kind in poses.POSED_KINDS:
        rows += evaluate(kind, range(n_poses))
    footer = f"At the end: load average {' '.join(f'{x:.2f}' for x in load_average())}."
    md = markdown(rows, header, footer)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / f"{name}.md").write_text(md)
    print(md)
    return 0


if __name__ == "__main__":
    sys.exit(main())
