"""Benchmark: what point signatures (HKS, WKS, SI-HKS) are good for, and what they cost.

Run from the repository root::

    .venv/bin/python benchmarks/bench_signatures.py correspondence          # 2 classes x 5 poses
    .venv/bin/python benchmarks/bench_signatures.py retrieval --collection identities
    .venv/bin/python benchmarks/bench_signatures.py speed                   # 100K-vertex torus
    .venv/bin/python benchmarks/bench_signatures.py correspondence --quick  # 2 x 2 poses

The claims of the signatures guide (``docs/guides/signatures.md``), one part each; every part
writes its own section of the one result file ``benchmarks/results/signatures.md`` (a part run
again replaces its section; ``--quick`` writes ``signatures_quick.md``):

1. **correspondence**: point correspondence across poses.  The shapes are
   :func:`cshape.data.poses.posed_figure`: a template (rest pose, ~2800 vertices) whose
   vertices are moved by a skeleton, so that the ground-truth map from the rest pose to every
   pose is the identity (the manifest's ``poses`` collection).  For every pose, each vertex
   ``i`` of the rest pose is matched to the vertex of the pose whose descriptor is nearest
   (:func:`cshape.signatures.match_points`), and the error is the geodesic distance on the pose
   between the match and vertex ``i`` (shortest paths along the edges, which overestimate the
   geodesic by a few per cent), over the pose's geodesic diameter; a match is correct within
   5 % of it.  Descriptors from ``N = 100`` eigenpairs of each shape: ``HKS`` (Sun et al.'s
   scaled HKS, ``scale='trace'``, at the 100 default times of the rest pose, the same times on
   both shapes), ``WKS`` (Aubry et al.'s, the 100 default energies of the rest pose),
   ``SI-HKS`` (the 6 lowest frequencies), and two baselines: ``xyz, rigid oracle``
   (coordinates after the best rigid alignment given the true map, Procrustes: the most any
   rigid alignment could do) and ``xyz, ICP`` (iterative closest point from the centred
   shapes).  The left-right mirror of a figure is an intrinsic symmetry, so the table gives
   the accuracy exact and "up to the mirror", and for mutual nearest neighbours only.
2. **retrieval**: shape retrieval with one vector per shape pooled from the signatures,
   against the log spectrum.  From ``N = 100`` eigenpairs of each shape, area-normalised:
   ``log spectrum`` (the log-Weyl ratio ``log(lam_i area / (4 pi i))``, ``i = 1..99``);
   ``HKS quantiles`` (``log HKS`` at 16 fixed unit-area times log-spaced over
   ``[4 ln 10 / (4 pi 99), 4 ln 10 / (4 pi)]``, Sun et al.'s range for Weyl's
   ``lam_i area ~ 4 pi i``, and at each time the area-weighted quantiles 0.1, 0.25, 0.5,
   0.75, 0.9 over the vertices: 80 values); ``WKS quantiles`` (the same with ``log WKS`` at 16
   fixed log-energies over Aubry et al.'s range, ``sigma = 7`` steps of a 100-energy grid).
   Euclidean distances, scored with :func:`cshape.retrieval_scores` (nearest neighbour,
   first and second tier, mean average precision).  The choices were made before the run and
   not tuned.
3. **speed**: the signatures of a large mesh (a torus of ``--vertices`` vertices, 100,000 by
   default): :func:`cshape.eigenbasis` with ``N = 100`` once, then the seconds of
   :func:`cshape.hks` and :func:`cshape.wks` at ``--scales`` (100) times or energies,
   :func:`cshape.signatures.si_hks` (its 321 log-times), :func:`cshape.signatures.heat_kernel`
   from one vertex and :func:`cshape.signatures.match_points` of 1000 vertices against all (brute
   force: ``n_a n_b k`` operations), each beside the eigensolve, as a fraction of it.  The
   eigenpairs against LaPy's are ``bench_sweep.py --eigenpairs``.

Every section names the machine and the processor.  Nothing here asserts a number.
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
from cshape import shapes
from cshape import signatures as sg
from cshape.compare import retrieval_scores
from cshape.data import poses
from cshape.descriptors import log_weyl_ratio

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import load_average, machine_summary, write_section  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
TITLE = "Point signatures: correspondence, retrieval, speed"


# ============================================================================ correspondence
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
        "SI-HKS": (sg.si_hks(ba), sg.si_hks(bb)),
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
            match = sg.match_points(a, b)
            err, err_m = D[ident, match], D[mirror, match]
            best = np.minimum(err, err_m)
            # mutual nearest neighbours only: fewer matches, how many of them right
            kept = sg.match_points(a, b, mutual=True) >= 0
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


def correspondence_lines(rows, header, footer):
    """The correspondence section's Markdown lines."""
    lines = [
        "## Correspondence: point correspondence across poses", "", header, "",
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
    return lines + ["", footer, ""]



# ============================================================================ retrieval
QUANTILES = (0.1, 0.25, 0.5, 0.75, 0.9)
N_SCALES = 16
WEYL = 4.0 * np.pi


def fixed_scales(N=100, n_scales=N_SCALES):
    """The unit-area times and (energies, sigma) every shape is sampled at."""
    t = np.geomspace(sg.T_FACTOR / (WEYL * (N - 1)), sg.T_FACTOR / WEYL, n_scales)
    e1, eN = np.log(WEYL), np.log(WEYL * (N - 1))
    sigma = sg.WKS_WIDTH * (eN - e1) / 100
    return t, np.linspace(e1 + 2 * sigma, eN - 2 * sigma, n_scales), sigma


def weighted_quantiles(X, w, qs=QUANTILES):
    """Column-wise quantiles of ``X`` (n, k) with vertex weights ``w`` (n,): (len(qs), k).

    Each sorted value sits at the middle of its weight's share of the cumulative weight;
    quantiles interpolate linearly between them (and clip at the ends).
    """
    out = np.empty((len(qs), X.shape[1]))
    for j in range(X.shape[1]):
        order = np.argsort(X[:, j])
        cw = np.cumsum(w[order])
        cw = (cw - 0.5 * w[order]) / cw[-1]
        out[:, j] = np.interp(qs, cw, X[order, j])
    return out


def shape_descriptors(mesh, N=100):
    """The three global descriptors of one mesh, by name."""
    mesh = cshape.repair_mesh(mesh, warn=False)
    basis = cshape.eigenbasis(mesh, N)
    w = np.asarray(basis.B.sum(axis=1)).ravel()  # vertex areas (lumped mass)
    t, e, sigma = fixed_scales(N)
    h = np.log(cshape.hks(basis, t, normalization="area"))
    k = np.log(np.maximum(cshape.wks(basis, e, sigma, normalization="area"), 1e-300))
    return {
        "log spectrum": log_weyl_ratio(cshape.normalize(basis.lam, area=basis.area)),
        "HKS quantiles": weighted_quantiles(h, w).ravel(),
        "WKS quantiles": weighted_quantiles(k, w).ravel(),
    }


def score(descs, labels):
    """Retrieval scores of each pooled descriptor (Euclidean distances)."""
    rows = []
    for name in descs[0]:
        X = np.array([d[name] for d in descs])
        D = np.linalg.norm(X[:, None, :] - X[None, :, :], axis=2)
        rows.append({"descriptor": name, "values": X.shape[1], **retrieval_scores(D, labels)})
    return rows


def retrieval_lines(rows, name, n, classes, header, footer):
    """The Markdown lines of the retrieval section of collection ``name``."""
    lines = [f"## Retrieval: pooled signatures on `{name}` ({n} shapes, {classes} classes)", "",
             header, "",
             "| descriptor | values | NN | FT | ST | mAP |", "|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['descriptor']} | {r['values']} | {r['nn']:.3f} | {r['ft']:.3f} | "
                     f"{r['st']:.3f} | {r['map']:.3f} |")
    return lines + ["", footer, ""]



# ============================================================================ speed
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
    s, r["si_hks"] = _timed(sg.si_hks, basis)
    _, r["heat_kernel"] = _timed(sg.heat_kernel, basis, float(sg.hks_times(basis)[50]), 0)
    rng = np.random.default_rng(seed)
    sub = rng.choice(mesh.n_vertices, size=min(n_match, mesh.n_vertices), replace=False)
    logh = np.log(h)
    match, r["match_points"] = _timed(sg.match_points, logh[sub], logh)
    r["hks_shape"], r["wks_shape"], r["si_hks_shape"] = h.shape, w.shape, s.shape
    r["si_hks_times"] = len(sg.si_hks_tau())
    r["n_match"] = len(sub)
    # a vertex's own signature is in the set: the match is at distance ~0 (the vertex or one
    # with the same signature: the torus is a surface of revolution)
    r["match_dist"] = float(np.linalg.norm(logh[match] - logh[sub], axis=1).max())
    return r




def speed_lines(sig, header, footer):
    """The speed section's Markdown lines: each signature's seconds beside the eigensolve."""
    lines = [
        f"## Speed: signatures of a {sig['n']:,}-vertex torus from N = {sig['N']} eigenpairs",
        "", header, "",
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
    return lines + [
        "", f"Largest distance from a matched vertex's log HKS to its match's (its own "
        f"signature is in the set): {sig['match_dist']:.1e}.", "", footer, ""]


# ============================================================================ the command
def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parts = parser.add_subparsers(dest="part", required=True)
    p = parts.add_parser("correspondence", help="point correspondence across poses")
    p.add_argument("--poses", type=int, default=5, help="poses per class (default 5)")
    p.add_argument("--quick", action="store_true", help="2 poses per class")
    p = parts.add_parser("retrieval", help="retrieval with pooled signatures")
    p.add_argument("--collection", default="creatures")
    p.add_argument("-N", type=int, default=100)
    p.add_argument("--quick", action="store_true", help="write signatures_quick.md")
    p = parts.add_parser("speed", help="signatures of a large mesh beside its eigensolve")
    p.add_argument("--vertices", type=int, default=100_000,
                   help="vertices of the torus (default 100000)")
    p.add_argument("--scales", type=int, default=100, help="times / energies (100)")
    p.add_argument("-N", type=int, default=100, help="eigenpairs (default 100)")
    p.add_argument("--quick", action="store_true", help="a 20K-vertex torus")
    parser.add_argument("--out", default=None,
                        help="the result file (default benchmarks/results/signatures.md; "
                             "--quick: signatures_quick.md)")
    args = parser.parse_args(argv)
    out = Path(args.out) if args.out else RESULTS / (
        "signatures_quick.md" if args.quick else "signatures.md")
    header = machine_summary()
    print(header, flush=True)

    def footer():
        return f"At the end: load average {' '.join(f'{x:.2f}' for x in load_average())}."

    if args.part == "correspondence":
        rows = []
        for kind in poses.POSED_KINDS:
            rows += evaluate(kind, range(2 if args.quick else args.poses))
        lines, key = correspondence_lines(rows, header, footer()), "correspondence"
    elif args.part == "retrieval":
        from cshape import data

        t0 = time.perf_counter()
        coll = data.load_collection(args.collection)
        print(f"loaded {len(coll)} meshes in {time.perf_counter() - t0:.0f} s", flush=True)
        t0 = time.perf_counter()
        descs = [shape_descriptors(m, args.N) for m in coll.meshes]
        print(f"descriptors in {time.perf_counter() - t0:.0f} s", flush=True)
        rows = score(descs, list(coll.labels))
        lines = retrieval_lines(rows, args.collection, len(coll), len(set(coll.labels)),
                                header, footer())
        key = f"retrieval {args.collection}"
    else:
        n = 20_000 if args.quick else args.vertices
        sig = time_signatures(torus_mesh(n), args.N, args.scales)
        lines, key = speed_lines(sig, header, footer()), "speed"
    write_section(out, key, lines, TITLE)
    print("\n".join(lines))
    print(f"results: {out}, section {key!r}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
