"""Benchmark: vertex maps between poses by nearest signature, functional maps and ZoomOut.

Run from the repository root::

    .venv/bin/python benchmarks/bench_maps.py --quick     # generated poses (maps_quick.md)
    .venv/bin/python benchmarks/bench_maps.py             # every TOSCA pose pair (maps_tosca.md)
    .venv/bin/python benchmarks/bench_maps.py --timing    # 16K, 46K, 63K vertices (maps_timing.md)
    .venv/bin/python benchmarks/bench_maps.py --calibrate # orientation weight, generated poses
    .venv/bin/python benchmarks/bench_maps.py --people current # point_map on FAUST remeshed
                            # pairs, registrations and TOSCA poses (maps_people.md); a subset:
                            # --groups remeshed-different --pairs 006->049,010->006 --limit 5
                            # (groups: remeshed-different, remeshed-same, registrations,
                            # tosca, tosca-remeshed: cat and centaur poses remeshed each on
                            # its own, dense: 54K-vertex remeshed registrations)
    .venv/bin/python benchmarks/bench_maps.py --diagnose 006->049  # the search's candidates
    .venv/bin/python benchmarks/bench_maps.py --people-landmarks   # failed pairs + landmarks
    .venv/bin/python benchmarks/bench_maps.py --people-pictures  # a failed and a repaired map

Pairs whose true map is the identity (the same vertices, moved):

* generated: the rest pose of :func:`cshape.data.poses.posed_figure` to its poses 0, 1, 2
  (human and quadruped);
* TOSCA (``../shared/realdev/tosca-dev``, read in place, skipped when missing): pose 0 of a
  character to each other pose with the same number of vertices whose edges keep their
  length under the identity (median relative change of pose 0's edge lengths below
  ``IDENTITY_STRETCH``; a renumbered pose would change them by order 1).  The poses share
  83-99 % of their triangles only (some quads are split along the other diagonal), so the
  check is on vertex positions, not on faces.

For each pair, with ``N = 100`` eigenpairs of each shape and the WKS of :func:`cshape.point_map`
(100 energies of the source, every 5th kept, shapes scaled to unit area):

* ``nearest WKS``: :func:`cshape.signatures.match_points` on the 100 WKS values;
* ``FM N0=30``: :func:`cshape.maps.functional_map` (size 30) and
  :func:`cshape.maps.map_to_pointwise`,
  with and without the orientation term (weight ``cshape.maps.ORIENTATION_WEIGHT``);
* ``FM + ZoomOut``: the same, then :func:`cshape.maps.zoomout` to size 100 (3000 samples per shape,
  as :func:`cshape.point_map` does).

Measures, on ``N_ROWS = 2000`` target vertices spread over the vertex numbers (the vertex map
of the others is not computed; ZoomOut runs as in :func:`cshape.point_map`): the share whose
match lies within 5 % of the source's bounding-box diagonal of the true vertex (Euclidean, on
the source); on 200 of them, the share within 5 % of the geodesic diameter and the mean
geodesic error divided by ``sqrt(area)`` (heat method, :class:`cshape.geodesics.HeatGeodesics`; the
diameter is the largest distance found from the 200 vertices and a second sweep, a lower
bound); seconds of the
mapping step (for the 2000 vertices) and of the whole pair (eigenpairs and descriptors
included); the full-size time of :func:`cshape.point_map` is ``--timing``'s.
"""

from __future__ import annotations

import argparse
import os
import re
import sys
import time
from pathlib import Path

import numpy as np

import cshape
from cshape import maps
from cshape import signatures as sg
from cshape.data import poses

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import cpu_summary, load_average  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
TOSCA = Path(__file__).resolve().parents[2] / "shared" / "realdev" / "tosca-dev"
if not TOSCA.exists():
    TOSCA = Path("/work/shared/realdev/tosca-dev")

N, K0, N_ENERGIES, STRIDE, SAMPLE, N_EVAL = 100, 30, 100, 5, 3000, 200
#: Target vertices evaluated per pair (spread over the vertex numbers; all if fewer).
N_ROWS = 2000
THRESHOLD = 0.05
#: Median relative change of pose 0's edge lengths under the identity, at most.
IDENTITY_STRETCH = 0.02
METHODS = ("nearest WKS", "FM N0=30, no orientation", "FM N0=30, orientation",
           "FM + ZoomOut, no orientation", "FM + ZoomOut, orientation")
GOAL = 0.80


# ---------------------------------------------------------------------- pairs
def generated_pairs(seeds=(0, 1, 2)):
    for kind in ("human", "quadruped"):
        rest = poses.posed_figure(kind, rest=True)
        for seed in seeds:
            yield f"{kind} rest -> pose {seed}", rest, poses.posed_figure(kind, seed), None


def _edges(faces):
    e = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    return np.unique(e, axis=0)


def identity_check(a, b):
    """``(share of sorted faces in common, median relative edge-length change)`` of b
    against a under the identity vertex map (edges of a)."""
    sa = {tuple(f) for f in np.sort(a.faces, axis=1)}
    sb = {tuple(f) for f in np.sort(b.faces, axis=1)}
    e = _edges(a.faces)
    la = np.linalg.norm(a.vertices[e[:, 0]] - a.vertices[e[:, 1]], axis=1)
    lb = np.linalg.norm(b.vertices[e[:, 0]] - b.vertices[e[:, 1]], axis=1)
    return len(sa & sb) / len(sa), float(np.median(np.abs(lb / la - 1.0)))


def tosca_characters():
    names = {}
    for path in TOSCA.glob("*.off.gz"):
        m = re.fullmatch(r"([a-z]+)(\d+)\.off\.gz", path.name)
        if m:
            names.setdefault(m[1], []).append(int(m[2]))
    return {c: sorted(v) for c, v in sorted(names.items())}


def tosca_pairs(characters=None, checks=None):
    """Pose 0 of each character against each of its other poses that pass the identity
    check (``checks`` collects ``(pair, vertices, face share, stretch, used)``)."""
    if not TOSCA.exists():
        return
    chars = tosca_characters()
    for c in characters or chars:
        first = cshape.load_mesh(TOSCA / f"{c}{chars[c][0]}.off.gz")
        for i in chars[c][1:]:
            other = cshape.load_mesh(TOSCA / f"{c}{i}.off.gz")
            label = f"{c}{chars[c][0]} -> {c}{i}"
            if other.n_vertices != first.n_vertices:
                if checks is not None:
                    checks.append((label, other.n_vertices, float("nan"), float("nan"), False))
                continue
            share, stretch = identity_check(first, other)
            ok = stretch <= IDENTITY_STRETCH
            if checks is not None:
                checks.append((label, first.n_vertices, share, stretch, ok))
            if ok:
                yield label, first, other, None


def midpoint_subdivide(mesh):
    """Split every edge at its midpoint (4 triangles per triangle); new vertex ``V + e``
    for edge ``e`` of ``_edges(faces)``.  Returns the mesh and its sorted edges."""
    V, F = mesh.vertices, mesh.faces
    e = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    uniq, inv = np.unique(e, axis=0, return_inverse=True)
    inv = inv.reshape(3, -1).T + len(V)
    a, b, c = F.T
    ab, bc, ca = inv.T
    F2 = np.concatenate([np.stack([a, ab, ca], 1), np.stack([b, bc, ab], 1),
                         np.stack([c, ca, bc], 1), np.stack([ab, bc, ca], 1)])
    mids = 0.5 * (V[uniq[:, 0]] + V[uniq[:, 1]])
    return cshape.Mesh(np.vstack([V, mids]), F2), uniq


def subdivided_pair(character="centaur", pose=1):
    """Pose 0 and ``pose`` of a TOSCA character, each midpoint-subdivided on its own faces.

    True map: the identity on the original vertices, and edge midpoint to the midpoint of
    the same edge where both poses have that edge; -1 (not evaluated) elsewhere."""
    S, eS = midpoint_subdivide(cshape.load_mesh(TOSCA / f"{character}0.off.gz"))
    T, eT = midpoint_subdivide(cshape.load_mesh(TOSCA / f"{character}{pose}.off.gz"))
    n = S.n_vertices - len(eS)
    index = {tuple(e): n + j for j, e in enumerate(eS)}
    truth = np.concatenate([np.arange(n), [index.get(tuple(e), -1) for e in eT]])
    return f"{character}0 -> {character}{pose}, midpoint-subdivided", S, T, truth


# ---------------------------------------------------------------------- accuracy
def measure(S, T, truth=None, *, n=N, k0=K0, orientation_weight=None):
    """Every method on one pair.

    Returns ``({method: (within 5 % diag, within 5 % geodesic diameter, geodesic error /
    sqrt(area), mapping seconds)}, seconds of eigenpairs + descriptors)``."""
    wo = maps.ORIENTATION_WEIGHT if orientation_weight is None else orientation_weight
    t = time.perf_counter()
    bS, bT = cshape.eigenbasis(S, n), cshape.eigenbasis(T, n)
    e, sigma = sg.wks_energies(bS, N_ENERGIES, normalization="area")
    dS = cshape.wks(bS, e, sigma, normalization="area")
    dT = cshape.wks(bT, e, sigma, normalization="area")
    common_s = time.perf_counter() - t

    truth = np.arange(T.n_vertices) if truth is None else np.asarray(truth)
    known = np.flatnonzero(truth >= 0)
    # the evaluated target vertices: N_ROWS spread over the mesh (every one if fewer), and
    # N_EVAL of them for the geodesic measures
    rows = known[np.unique(np.linspace(0, len(known) - 1, min(N_ROWS, len(known))).astype(int))]
    at = np.unique(np.linspace(0, len(rows) - 1, N_EVAL).astype(int))
    diag = np.linalg.norm(S.vertices.max(0) - S.vertices.min(0))
    geo = cshape.geodesics.HeatGeodesics(S)
    D = geo.distances(truth[rows[at]])  # (n_S, N_EVAL): distance to the true images
    far = int(np.argmax(D.max(axis=1)))
    diameter = max(float(D.max()), float(geo.distances([far]).max()))
    sqrt_area = np.sqrt(S.area)
    out = {}

    def score(name, p, seconds):
        """``p``: the source vertex of each evaluated target vertex (``rows``)."""
        within = np.linalg.norm(S.vertices[p] - S.vertices[truth[rows]], axis=1)
        err = D[p[at], np.arange(len(at))]
        out[name] = (float((within <= THRESHOLD * diag).mean()),
                     float((err <= THRESHOLD * diameter).mean()),
                     float(err.mean() / sqrt_area), seconds)

    t = time.perf_counter()
    p = cshape.signatures.match_points(dT[rows], dS)
    score("nearest WKS", p, time.perf_counter() - t)
    for orient in (False, True):
        label = "orientation" if orient else "no orientation"
        t = time.perf_counter()
        C = cshape.maps.functional_map(bS.truncate(k0), bT.truncate(k0),
                                  dS[:, ::STRIDE], dT[:, ::STRIDE],
                                  orientation_weight=wo if orient else 0.0)
        fm_s = time.perf_counter() - t
        score(f"FM N0={k0}, {label}", cshape.maps.map_to_pointwise(C, bS, bT, vertices=rows),
              time.perf_counter() - t)
        t = time.perf_counter()
        Z = cshape.maps.zoomout(C, bS, bT, n, sample=SAMPLE)
        score(f"FM + ZoomOut, {label}", cshape.maps.map_to_pointwise(Z, bS, bT, vertices=rows),
              fm_s + time.perf_counter() - t)
    return out, common_s


def _header(title, command):
    return [f"# {title}", "",
            f"Processor: {cpu_summary()} ({os.cpu_count()} cores, shared).",
            f"Command: `python benchmarks/bench_maps.py{' ' + command if command else ''}`.",
            ""]


def write_accuracy(rows, name, command, checks=None, total=None, note=""):
    RESULTS.mkdir(exist_ok=True)
    la = load_average()
    lines = _header("Vertex maps between poses: nearest signature, functional maps, ZoomOut",
                    command)
    lines += [
        f"`N = {N}` eigenpairs per shape, `N0 = {K0}`, ZoomOut to {N} with {SAMPLE} samples, "
        f"orientation weight {maps.ORIENTATION_WEIGHT:g} (the operators of shapes scaled to "
        "unit area), chosen on the generated poses (`maps_orientation_weight.md`): the TOSCA "
        "poses are held out.",
        f"*diag 5 %*: share of {N_ROWS} target vertices (spread over the vertex numbers; all "
        "if fewer) matched within 5 % of the bounding-box "
        "diagonal of the true vertex; *geo 5 %*: share of "
        f"{N_EVAL} of them within 5 % of the geodesic diameter; *geo err*: their "
        "mean geodesic error / sqrt(area) (ZoomOut's published 15.8e-3 on FAUST+SCAPE is "
        "0.0158); *map s*: the mapping step (ZoomOut in full, the vertex map of the "
        f"{N_ROWS} vertices); *pair s*: eigenpairs, descriptors and the mapping step "
        "(full-size `point_map` times: `maps_timing.md`).",
        f"Load average at the end: {la[0]:.1f} / {la[1]:.1f} / {la[2]:.1f} (1 / 5 / 15 min).",
        ""]
    if note:
        lines += [note, ""]
    if total is not None and len(rows) < total:
        lines += [f"**{len(rows)} of {total} pairs measured so far.**", ""]
    lines += ["Mean over the pairs, and the pairs below the goal (>= 0.80 within 5 % of the "
              "diagonal):", "",
              "| method | diag 5 % | geo 5 % | geo err | min diag 5 % | pairs < 0.80 | "
              "map s (median) | pair s (median) |",
              "|---|---|---|---|---|---|---|---|"]
    for m in METHODS:
        r = np.array([row[4][m] for row in rows])
        pair_s = np.array([row[4][m][3] + row[3] for row in rows])
        lines.append(f"| {m} | {r[:, 0].mean():.3f} | {r[:, 1].mean():.3f} | "
                     f"{r[:, 2].mean():.4f} | {r[:, 0].min():.3f} | {(r[:, 0] < GOAL).sum()} "
                     f"of {len(r)} | {np.median(r[:, 3]):.1f} | {np.median(pair_s):.1f} |")
    best = METHODS[-1]
    below = [f"{row[1]} ({row[4][best][0]:.3f})" for row in rows if row[4][best][0] < GOAL]
    lines += ["", f"Where {best} loses (below {GOAL:.2f} within 5 % of the diagonal): "
              + (", ".join(below) if below else "no pair") + "."]
    sets = sorted({row[0] for row in rows}, key=[row[0] for row in rows].index)
    if len(sets) > 1:
        lines += ["", "Mean per set (character or figure):", "",
                  "| set | pairs | vertices | method | diag 5 % | geo 5 % | geo err | "
                  "pair s (median) |", "|---|---|---|---|---|---|---|---|"]
        for s in sets:
            sub = [row for row in rows if row[0] == s]
            for m in METHODS:
                r = np.array([row[4][m] for row in sub])
                ps = np.median([row[4][m][3] + row[3] for row in sub])
                lines.append(f"| {s} | {len(sub)} | {sub[0][2]} | {m} | {r[:, 0].mean():.3f} | "
                             f"{r[:, 1].mean():.3f} | {r[:, 2].mean():.4f} | {ps:.1f} |")
    lines += ["", "Every pair:", "",
              "| pair | vertices | method | diag 5 % | geo 5 % | geo err | map s | pair s |",
              "|---|---|---|---|---|---|---|---|"]
    for _set, pair, nv, common_s, res in rows:
        for m in METHODS:
            w, g, err, s = res[m]
            lines.append(f"| {pair} | {nv} | {m} | {w:.3f} | {g:.3f} | {err:.4f} | {s:.1f} | "
                         f"{s + common_s:.1f} |")
    if checks:
        lines += ["", f"Pose pairs and the identity check (used when the median relative "
                  f"change of pose 0's edge lengths under the identity is at most "
                  f"{IDENTITY_STRETCH}; measured pairs are in the tables above):", "",
                  "| pair | vertices | sorted faces in common | median edge change | "
                  "identity holds |",
                  "|---|---|---|---|---|"]
        for label, nv, share, stretch, ok in checks:
            lines.append(f"| {label} | {nv} | {share:.3f} | {stretch:.4f} | "
                         f"{'yes' if ok else 'no'} |")
    (RESULTS / f"{name}.md").write_text("\n".join(lines) + "\n")
    return "\n".join(lines)


# ---------------------------------------------------------------------- orientation weight
#: Orientation weights tried on the generated poses (the operators of unit-area shapes).
WEIGHTS = (0.0, 1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2, 1e-1)


def calibrate(seeds=(0, 1, 2)):
    """FM (size 30) and FM + ZoomOut within 5 % of the diagonal, per generated pair and
    orientation weight: ``{(pair, weight): (fm, zoomout)}``."""
    out = {}
    for kind in ("human", "quadruped"):
        rest = poses.posed_figure(kind, rest=True)
        bS = cshape.eigenbasis(rest, N)
        diag = np.linalg.norm(rest.vertices.max(0) - rest.vertices.min(0))
        e, sigma = sg.wks_energies(bS, N_ENERGIES, normalization="area")
        dS = cshape.wks(bS, e, sigma, normalization="area")[:, ::STRIDE]
        for seed in seeds:
            T = poses.posed_figure(kind, seed)
            bT = cshape.eigenbasis(T, N)
            dT = cshape.wks(bT, e, sigma, normalization="area")[:, ::STRIDE]

            def within(p, rest=rest, diag=diag):
                return float((np.linalg.norm(rest.vertices[p] - rest.vertices, axis=1)
                              <= THRESHOLD * diag).mean())

            for w in WEIGHTS:
                C = cshape.maps.functional_map(bS.truncate(K0), bT.truncate(K0), dS, dT,
                                          orientation_weight=w)
                Z = cshape.maps.zoomout(C, bS, bT, N, sample=SAMPLE)
                out[f"{kind} rest -> pose {seed}", w] = (
                    within(cshape.maps.map_to_pointwise(C, bS, bT)),
                    within(cshape.maps.map_to_pointwise(Z, bS, bT)))
                print(kind, seed, w, out[f"{kind} rest -> pose {seed}", w], flush=True)
    return out


def write_calibration(out, command):
    pairs = sorted({p for p, _w in out}, key=[p for p, _w in out].index)
    lines = _header("The orientation weight of the functional map, chosen on the generated "
                    "poses", command)
    lines += ["Share of target vertices within 5 % of the bounding-box diagonal of the true "
              f"vertex, FM + ZoomOut (FM of size {K0} in brackets), per orientation weight "
              "`w_o` (operators of the shapes scaled to unit area, `cshape.maps.functional_map`). "
              "The weight of `cshape.maps.ORIENTATION_WEIGHT` is the best mean of this set; "
              "the real TOSCA poses (`maps_tosca.md`) are held out.", "",
              "| pair | " + " | ".join(f"{w:g}" for w in WEIGHTS) + " |",
              "|---|" + "---|" * len(WEIGHTS)]
    for p in pairs:
        lines.append(f"| {p} | " + " | ".join(f"{out[p, w][1]:.3f} ({out[p, w][0]:.3f})"
                                               for w in WEIGHTS) + " |")
    means = [np.mean([out[p, w][1] for p in pairs]) for w in WEIGHTS]
    lines.append("| **mean** | " + " | ".join(f"**{m:.3f}**" for m in means) + " |")
    best = WEIGHTS[int(np.argmax(means))]
    lines += ["", f"Best mean: `w_o = {best:g}`."]
    lose = [p for p in pairs if max(out[p, w][1] for w in WEIGHTS[1:]) < out[p, 0.0][1]]
    if lose:
        lines += ["", "Where the orientation term loses (FM + ZoomOut without it is better at "
                  "every weight tried): " + ", ".join(
                      f"{p} ({out[p, 0.0][1]:.3f} without, "
                      f"{max(out[p, w][1] for w in WEIGHTS[1:]):.3f} at best with)"
                      for p in lose) + "."]
    lines.append("")
    (RESULTS / "maps_orientation_weight.md").write_text("\n".join(lines) + "\n")
    return "\n".join(lines)


# ---------------------------------------------------------------------- timing
def _blocked_nearest(queries, points, block=1024):
    """Exact nearest rows by blocked numpy products (the former implementation)."""
    pp = np.einsum("ij,ij->i", points, points)
    out = np.empty(len(queries), dtype=np.int64)
    pT = np.ascontiguousarray(points.T)
    for s in range(0, len(queries), block):
        Q = queries[s:s + block] @ pT
        Q *= -2.0
        Q += pp
        out[s:s + block] = np.argmin(Q, axis=1)
    return out


def _nn_methods(big, k):
    from scipy.spatial import cKDTree
    from sklearn.neighbors import NearestNeighbors

    from cshape import _nearest

    def sk(algorithm):
        return lambda q, p: NearestNeighbors(n_neighbors=1, algorithm=algorithm).fit(
            p).kneighbors(q, return_distance=False)[:, 0]

    out = {"numpy blocked products (1024 rows, BLAS threads)": (_blocked_nearest, 3),
           "cshape.maps.map_to_pointwise (fused products, 2 threads x 1 BLAS thread)": (
               _nearest.nearest_rows, 3),
           "scikit-learn brute": (sk("brute"), 3),
           "scipy cKDTree (2 workers)": (lambda q, p: cKDTree(p).query(q, workers=-1)[1],
                                         1 if big else 3),
           "scikit-learn kd_tree": (sk("kd_tree"), 1 if big else 3)}
    if not big:
        out["scikit-learn ball_tree"] = (sk("ball_tree"), 1)
    if big and k > 30:  # the trees: at 16K vertices already slower than a scan at k = 100
        out = {name: v for name, v in out.items() if "tree" not in name.lower()}
    return out


def _median_time(f, repeats, cpu=None):
    """Median wall seconds of ``repeats`` calls, every one, and the last result; the CPU
    seconds of this process (all its threads) go to the list ``cpu`` if given."""
    times, result = [], None
    for _ in range(repeats):
        t, c = time.perf_counter(), time.process_time()
        result = f()
        times.append(time.perf_counter() - t)
        if cpu is not None:
            cpu.append(time.process_time() - c)
    return float(np.median(times)), times, result


def point_map_times(repeats=3):
    """Wall and CPU seconds of ``point_map`` on the 63K-vertex pair alone (no stages)."""
    label, S, T, _truth = subdivided_pair("centaur", 1)
    la0, cpu = load_average()[0], []
    tot, tot_all, _p = _median_time(lambda: cshape.point_map(S, T), repeats, cpu)
    return label, S.n_vertices, tot, tot_all, cpu, la0, load_average()[0]


def append_point_map_times(row, command):
    label, nv, tot, tot_all, cpu, la0, la1 = row
    lines = ["", f"Re-measured with no other benchmark of this repository running "
             f"(`python benchmarks/bench_maps.py {command}`); CPU: seconds of this process, "
             "all its threads (on 2 free cores the wall time is about half the CPU time "
             "where both threads work):", "",
             "| pair | vertices | point_map s (median) | runs (s) | CPU s per run | "
             "load before / after |", "|---|---|---|---|---|---|",
             f"| {label} | {nv} | {tot:.1f} | {', '.join(f'{t:.1f}' for t in tot_all)} | "
             f"{', '.join(f'{c:.1f}' for c in cpu)} | {la0:.1f} / {la1:.1f} |"]
    with open(RESULTS / "maps_timing.md", "a") as fh:
        fh.write("\n".join(lines) + "\n")
    return "\n".join(lines)


def timing(repeats=3):
    """``point_map`` per pair and per stage, and the nearest-neighbour searches."""
    pairs = []
    c = cshape.load_mesh(TOSCA / "centaur0.off.gz"), cshape.load_mesh(TOSCA / "centaur1.off.gz")
    pairs.append(("centaur0 -> centaur1", *c, None))
    v = cshape.load_mesh(TOSCA / "victoria0.off.gz"), cshape.load_mesh(TOSCA / "victoria1.off.gz")
    pairs.append(("victoria0 -> victoria1", *v, None))
    pairs.append(subdivided_pair("centaur", 1))
    stage_rows, nn_rows = [], []
    for label, S, T, truth in pairs:
        la0 = load_average()[0]
        tot, tot_all, p = _median_time(lambda S=S, T=T: cshape.point_map(S, T), repeats)
        truth_ = np.arange(T.n_vertices) if truth is None else truth
        known = truth_ >= 0
        diag = np.linalg.norm(S.vertices.max(0) - S.vertices.min(0))
        within = float((np.linalg.norm(S.vertices[p[known]] - S.vertices[truth_[known]], axis=1)
                        <= THRESHOLD * diag).mean())
        stages = {"A, B and 100 eigenpairs (both)": [], "WKS + functional map (orientation)": [],
                  "ZoomOut 30 -> 100 (3000 samples)": [], "vertex map (n_T x n_S, k = 100)": []}
        for _ in range(1):  # the stages once (point_map itself ``repeats`` times)
            t0 = time.perf_counter()
            bS, bT = cshape.eigenbasis(S, N), cshape.eigenbasis(T, N)
            t1 = time.perf_counter()
            dS, dT = maps._descriptors(bS, bT, N_ENERGIES, None)
            C = cshape.maps.functional_map(bS.truncate(K0), bT.truncate(K0), dS, dT)
            t2 = time.perf_counter()
            Z = cshape.maps.zoomout(C, bS, bT, N, sample=SAMPLE)
            t3 = time.perf_counter()
            cshape.maps.map_to_pointwise(Z, bS, bT)
            t4 = time.perf_counter()
            for key, s in zip(stages, (t1 - t0, t2 - t1, t3 - t2, t4 - t3), strict=True):
                stages[key].append(s)
        la1 = load_average()[0]
        stage_rows.append((label, S.n_vertices, tot, tot_all, within, known.mean(),
                           {k: float(np.median(s)) for k, s in stages.items()}, la0, la1))
        print(stage_rows[-1], flush=True)
        if label.startswith("victoria"):
            continue
        big = S.n_vertices > 30000
        for k in (30, 100):
            Q = np.ascontiguousarray(bT.phi[:, :k])
            P = bS.phi[:, :k] @ Z[:k, :k].T
            ref = _blocked_nearest(Q, P)
            dref = np.linalg.norm(Q - P[ref], axis=1)
            for name, (f, reps) in _nn_methods(big, k).items():
                med, _all, o = _median_time(lambda f=f, Q=Q, P=P: f(Q, P), reps)
                worse = float((np.linalg.norm(Q - P[o], axis=1) > dref * (1 + 1e-9)).mean())
                nn_rows.append((label, S.n_vertices, k, name, med, reps, worse,
                                load_average()[0]))
                print(nn_rows[-1], flush=True)
    return stage_rows, nn_rows


def write_timing(stage_rows, nn_rows, command):
    lines = _header("Time of a vertex map between two poses (`cshape.point_map`)", command)
    lines += [f"`point_map(source, target)` with its defaults (`N = {N}`, `N0 = {K0}`, "
              f"orientation, ZoomOut with {SAMPLE} samples); median of the runs.  Goal: under "
              "60 s per 60K-vertex pair on 2 cores.  The 63K pair is TOSCA centaur0 -> "
              "centaur1 with every edge split at its midpoint on each pose's own faces "
              "(no real pose pair has 60K vertices); its true map is known on the original "
              "vertices and the midpoints of the edges both poses have.", "",
              "| pair | vertices | point_map s (median) | runs (s) | diag 5 % | evaluated | "
              "load before / after |", "|---|---|---|---|---|---|---|"]
    for label, nv, tot, tot_all, within, share, _st, la0, la1 in stage_rows:
        lines.append(f"| {label} | {nv} | {tot:.1f} | {', '.join(f'{t:.1f}' for t in tot_all)}"
                     f" | {within:.3f} | {share:.2f} | {la0:.1f} / {la1:.1f} |")
    lines += ["", "Stages (seconds of one more run, step by step with the public functions):",
              "", "| pair | " + " | ".join(stage_rows[0][6]) + " |",
              "|---|" + "---|" * len(stage_rows[0][6])]
    for row in stage_rows:
        lines.append(f"| {row[0]} | " + " | ".join(f"{s:.1f}" for s in row[6].values()) + " |")
    lines += ["", "Exact nearest neighbours of the vertex map `argmin_x ||Phi_T[y] - C "
              "Phi_S[x]||` (every target vertex, all source vertices; C from ZoomOut), in "
              "k dimensions; *worse*: share of queries whose answer is farther than the "
              "blocked products' (0 = exact):", "",
              "| pair | vertices | k | method | s (median) | runs | worse | load |",
              "|---|---|---|---|---|---|---|---|"]
    for label, nv, k, name, med, reps, worse, la in nn_rows:
        lines.append(f"| {label} | {nv} | {k} | {name} | {med:.2f} | {reps} | {worse:.4f} | "
                     f"{la:.1f} |")
    (RESULTS / "maps_timing.md").write_text("\n".join(lines) + "\n")
    return "\n".join(lines)

# ---------------------------------------------------------------------- people
FAUST = TOSCA.parent / "faust-dev"
#: Target vertices evaluated per pair by the geodesic error (spread over the vertex numbers).
N_EVAL_PEOPLE = 500
#: TOSCA pose pairs measured with ``point_map`` beside the people: one per character, and the
#: cat pairs where it fell below 0.80 within 5 % of the diagonal (``maps_tosca.md``).
TOSCA_POINT_MAP = ("wolf0 -> wolf1", "centaur0 -> centaur1", "dog0 -> dog1",
                   "horse0 -> horse5", "cat0 -> cat1", "cat0 -> cat4", "cat0 -> cat6",
                   "victoria0 -> victoria10")


def faust_pairs():
    """FAUST registrations ``tr_reg_XYZ`` (person ``XYZ // 10``, pose ``XYZ % 10``).

    Different people: for the ``n``-th pair of people ``(a, b)``, ``a < b`` in order, pose
    ``n % 10`` of ``a`` to pose ``(n + 3) % 10`` of ``b`` and pose ``(n + 5) % 10`` of ``b``
    to pose ``(n + 7) % 10`` of ``a`` (20 pairs, every person a source and a target 8 times);
    the same person: pose 1 to pose 6 of each person (5 pairs).  The registrations share one
    connectivity, so the true map is the identity.
    """
    from itertools import combinations

    out = []
    for n, (a, b) in enumerate(combinations(range(5), 2)):
        out.append(("registrations, different people", 10 * a + n % 10, 10 * b + (n + 3) % 10))
        out.append(("registrations, different people", 10 * b + (n + 5) % 10,
                    10 * a + (n + 7) % 10))
    out += [("registrations, same person", 10 * a + 1, 10 * a + 6) for a in range(5)]
    return out


#: Seed of the random pairs of ``faust-dev-remeshed`` (``_remeshed.pairs_different``; this
#: seed gives the 20 pairs of different people first measured there).
REMESHED_SEED = 11
GROUPS = {"remeshed-different": "remeshed, different people",
          "remeshed-same": "remeshed, same person",
          "registrations": "registrations",
          "tosca": "TOSCA poses",
          "tosca-remeshed": "TOSCA poses, remeshed",
          "dense": "dense remeshed, different people"}
#: Characters of ``tosca-remeshed``: each pose remeshed on its own
#: (``_remeshed.tosca_remeshed``), pose 0 against every other pose.
TOSCA_REMESHED = ("cat", "centaur")
#: Pairs of ``dense`` (registrations remeshed on their own to about 55K vertices,
#: ``_remeshed.dense``).
DENSE_PAIRS = ((26, 3), (10, 6))


def people_pairs(groups=tuple(GROUPS), only=(), limit=0):
    """``(group, label, loader)`` of the pairs measured by ``--people``.

    ``loader()`` returns ``(source, target, truth)`` (``truth``: the true source vertex of
    each target vertex).  ``only``: labels to keep (e.g. ``006->049``); ``limit``: at most
    this many pairs per group."""
    import _remeshed as rm

    def remeshed(a, b):
        return lambda: (rm.remeshed(a), rm.remeshed(b), rm.true_map(a, b))

    def registration(a, b):
        return lambda: (rm.registration(a), rm.registration(b),
                        np.arange(rm.registration(b).n_vertices))

    out = []
    if "remeshed-different" in groups and rm.REMESHED.exists():
        out += [(GROUPS["remeshed-different"], f"{a:03d}->{b:03d}", remeshed(a, b))
                for a, b in rm.pairs_different(20, REMESHED_SEED)]
    if "remeshed-same" in groups and rm.REMESHED.exists():
        out += [(GROUPS["remeshed-same"], f"{a:03d}->{b:03d}", remeshed(a, b))
                for a, b in rm.pairs_same(10, REMESHED_SEED)]
    if "registrations" in groups and FAUST.exists():
        out += [(g, f"{a:03d}->{b:03d}", registration(a, b)) for g, a, b in faust_pairs()]
    if "tosca" in groups and TOSCA.exists():
        chars = tuple(sorted({re.split(r"[0-9]", p)[0] for p in TOSCA_POINT_MAP}))
        wanted = {lab.replace(" -> ", "->") for lab in TOSCA_POINT_MAP}
        tosca = [(lab.replace(" -> ", "->"), S, T) for lab, S, T, _t in tosca_pairs(chars)]
        out += [(GROUPS["tosca"], lab, (lambda S=S, T=T: (S, T, np.arange(T.n_vertices))))
                for lab, S, T in tosca if lab in wanted]
    if "tosca-remeshed" in groups and TOSCA.exists():
        for lab, _S, _T, _t in tosca_pairs(TOSCA_REMESHED):  # the poses that share vertices
            a, b = lab.split(" -> ")
            out.append((GROUPS["tosca-remeshed"], f"{a}->{b}", (
                lambda a=a, b=b: (rm.tosca_remeshed(a)[0], rm.tosca_remeshed(b)[0],
                                  rm.tosca_true_map(a, b)))))
    if "dense" in groups and FAUST.exists():
        out += [(GROUPS["dense"], f"{a:03d}->{b:03d}",
                 (lambda a=a, b=b: (rm.dense(a)[0], rm.dense(b)[0], rm.dense_true_map(a, b))))
                for a, b in DENSE_PAIRS]
    if only:
        out = [p for p in out if p[1] in only]
    if limit:
        count = {}
        out = [p for p in out if count.setdefault(p[0], [0]).__setitem__(0, count[p[0]][0] + 1)
               or count[p[0]][0] <= limit]
    return out


def measure_point_map(S, T, truth):
    """``cshape.point_map(S, T)`` with its defaults, timed, and its errors as the literature
    measures them.

    Returns ``(mean geodesic error / sqrt(area of S), share of them at most 0.05, seconds,
    1-minute load at the start, 1 if point_map warned that two maps tie else 0, processor
    seconds of this process, all its threads)`` over
    ``N_EVAL_PEOPLE`` target vertices spread over the vertex numbers (heat method on the
    source)."""
    import warnings

    import _remeshed as rm

    la = load_average()[0]
    t, cpu = time.perf_counter(), time.process_time()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", cshape.CShapeWarning)
        p = cshape.point_map(S, T)
    seconds, cpu = time.perf_counter() - t, time.process_time() - cpu
    warned = any("cannot tell two candidate maps apart" in str(w.message) for w in caught)
    err = rm.errors(S, p, truth, vertices=rm.rows(T.n_vertices, N_EVAL_PEOPLE))
    return (float(err.mean()), float((err <= THRESHOLD).mean()), seconds, la, float(warned),
            cpu)


HEADER = "group,pair,vertices,geo_err,within5,seconds,load,warned,cpu_seconds"


def people(label, groups=tuple(GROUPS), only=(), limit=0):
    """Measure the pairs of :func:`people_pairs` into ``maps_people_<label>.csv`` (the rows of
    pairs measured again are replaced; the others kept)."""
    RESULTS.mkdir(exist_ok=True)
    path = RESULTS / f"maps_people_{label}.csv"
    rows = {k: v for k, v in _read_people(label).items()}
    for group, pair, load in people_pairs(groups, only, limit):
        S, T, truth = load()
        r = measure_point_map(S, T, truth)
        rows[(group, pair)] = (T.n_vertices, *r)
        print(group, pair, T.n_vertices, " ".join(f"{x:.4f}" for x in r), flush=True)
        lines = [HEADER]
        lines += [f"{g},{p},{v[0]}," + ",".join(f"{x:.4f}" for x in v[1:])
                  for (g, p), v in rows.items()]
        path.write_text("\n".join(lines) + "\n")
    return path


def _read_people(label):
    path = RESULTS / f"maps_people_{label}.csv"
    if not path.exists():
        return {}
    lines = path.read_text().splitlines()
    if not lines or not HEADER.startswith(lines[0]):
        return {}
    out = {}
    for line in lines[1:]:
        r = line.split(",")
        i = next(j for j, x in enumerate(r) if "->" in x)  # the group's name has commas
        values = [float(x) for x in r[i + 2:]]
        values += [np.nan] * (6 - len(values))  # "warned", "cpu" not recorded in older rows
        out[(",".join(r[:i]), r[i])] = (int(r[i + 1]), *values)
    return out


def summary(errs, pairs):
    """Mean, median, worst (and its pair), and the counts over 0.05 and over 0.1 of per-pair
    errors."""
    e = np.asarray(errs)
    return (f"**{e.mean():.4f}** | {np.median(e):.4f} | {e.max():.4f} ({pairs[e.argmax()]}) | "
            f"{int((e > 0.05).sum())} | {int((e > 0.1).sum())}")


#: The results kept carry this label; another label (a branch's version, run with its
#: checkout first on ``PYTHONPATH``) is shown beside them.
CURRENT = "current"

#: How ``maps_people.md`` was measured.
PEOPLE_NOTE = (
    "*current*: this version of `point_map` (the nearest rows of the search and of the "
    "ZoomOut iterations in single precision, and the sign patterns beyond the 24 of the "
    "smallest residual stopped at size 12: `_candidates.SIGN_PRUNE_SIZE`, "
    "`SIGN_PRUNE_KEEP`).  Every timing here is under the load of other work on the two "
    "cores (the *load* columns: 1-minute load average at the start of the pair; a load of "
    "3-6 means that this process had about one core or less), so *s* is not a quiet time; "
    "*cpu s* (processor seconds of the process, all its threads) varies less.  Where the "
    "time goes: `maps_stages.md`.  *TOSCA poses, remeshed*: pose 0 of cat and of centaur "
    "to each of their other poses, each pose remeshed on its own; it was not used to choose "
    "anything (held out from the tuning, though not from the developers' eyes).")


def _labels(kind):
    """The labels of the ``maps_<kind>_<label>.csv`` files in ``results/``: the kept
    results' (:data:`CURRENT`) first."""
    found = [p.stem.removeprefix(f"maps_{kind}_") for p in RESULTS.glob(f"maps_{kind}_*.csv")]
    return sorted(found, key=lambda lab: (lab != CURRENT, lab))


def write_people(command, labels=None, note=""):
    """``maps_people.md``: the per-pair tables of ``maps_people_<label>.csv`` (default: every
    label there is) side by side, and each group's summary."""
    got = {lab: _read_people(lab) for lab in (labels or _labels("people"))}
    got = {lab: rows for lab, rows in got.items() if rows}
    keys = list(dict.fromkeys(k for rows in got.values() for k in rows))
    order = list(GROUPS.values())
    groups = sorted(dict.fromkeys(k[0] for k in keys),
                    key=lambda g: next((i for i, o in enumerate(order) if g.startswith(o)), 9))
    lines = _header("Vertex maps between different people and between poses "
                    "(`cshape.point_map`)", command)
    lines += [
        "`cshape.point_map(source, target)` with its defaults.  *remeshed*: "
        "`../shared/realdev/faust-dev-remeshed` (FAUST people 0-4, each mesh remeshed on its "
        "own, 4-6K vertices, as the published FAUST_r benchmark), 20 random pairs of different "
        f"people and 10 of one person (seed {REMESHED_SEED}), the true map from `truth.npz`; "
        "*registrations*: `faust-dev` (6,890 vertices, one connectivity: the true map is the "
        "identity), pairs `faust_pairs()`; *TOSCA poses*: `tosca-dev`, pose 0 to another pose "
        "(the identity checked as in `maps_tosca.md`); *TOSCA poses, remeshed*: the poses "
        "of cat and centaur that pass that check, each remeshed on its own to about 5,000 "
        "vertices as faust-dev-remeshed (`_remeshed.tosca_remeshed`, built at benchmark time "
        "into a cache in the temporary folder), the truth carried by each remeshed vertex's "
        "nearest vertex of the published pose, pose 0 to each other pose.  "
        f"*err*: mean geodesic error over sqrt(area) of {N_EVAL_PEOPLE} target vertices "
        "(spread over the vertex numbers; heat method on the source), as the literature "
        "measures it; *5 %*: share of them with an error at most 0.05; *s*: seconds of the "
        "whole `point_map` call (eigenpairs included) on the shared machine (its load "
        "average in the csv files); *warned*: whether "
        "`point_map` warned that two candidate maps tie (`-`: not recorded).  These are "
        "development sets: the search was chosen on faust-dev, and its failures were diagnosed "
        "on faust-dev-remeshed; held-out figures are not these.", "",
        "Labels: " + "; ".join(f"*{lab}*" for lab in got) + ".", *([note] if note else []),
        ""]
    for group in groups:
        sub = [k for k in keys if k[0] == group]
        lines += [f"## {group}", "", "| pair | vertices | " + " | ".join(
            f"{lab} err | {lab} 5 % | {lab} s | {lab} cpu s | {lab} load | {lab} warned"
            for lab in got) + " |",
            "|---|---|" + "---|---|---|---|---|---|" * len(got)]
        for k in sub:
            nv = next(rows[k][0] for rows in got.values() if k in rows)
            cells = [" | ".join(["-"] * 6) if (r := rows.get(k)) is None else
                     f"{r[1]:.4f} | {'-' if np.isnan(r[2]) else f'{r[2]:.3f}'} | {r[3]:.1f} | "
                     + ("-" if np.isnan(r[6]) else f"{r[6]:.1f}") + f" | {r[4]:.1f} | "
                     + ("-" if np.isnan(r[5]) else "yes" if r[5] else "no")
                     for rows in got.values()]
            lines.append(f"| {k[1]} | {nv} | " + " | ".join(cells) + " |")
        lines += ["", "| label | pairs | mean err | median | worst | over 0.05 | over 0.1 | "
                  "5 % (mean) | s (median, max) | cpu s (median) |",
                  "|---|---|---|---|---|---|---|---|---|---|"]
        for lab, rows in got.items():
            r = np.array([rows[k][1:] for k in sub if k in rows])
            if len(r):
                names = [k[1] for k in sub if k in rows]
                share = "-" if np.isnan(r[:, 1]).any() else f"{r[:, 1].mean():.3f}"
                lines.append(f"| {lab} | {len(r)} | {summary(r[:, 0], names)} | {share} "
                             f"| {np.median(r[:, 2]):.1f}, {r[:, 2].max():.1f} | "
                             + ("-" if np.isnan(r[:, 5]).all()
                                else f"{np.nanmedian(r[:, 5]):.1f}") + " |")
        lines.append("")
    (RESULTS / "maps_people.md").write_text("\n".join(lines) + "\n")
    return "\n".join(lines)


#: The pairs whose time :func:`stages` and :func:`wall` measure: one of registrations, two
#: remeshed each on its own.
TIMED_PAIRS = ("000->013", "010->006", "006->049")
#: Stages of :func:`stages`, in the order of ``point_map``.
STAGES = ("eigenbases (2 x 100)", "descriptors and first map", "sign patterns (6 -> 20)",
          "candidates' ZoomOuts to 50", "candidates' vertex maps (full size, k=50)",
          "candidates' other (oriented and landmark maps, scores, turning)",
          "final ZoomOut to 100", "final vertex map (k=100)")


def stage_seconds(S, T):
    """Processor seconds of each stage of ``cshape.point_map(S, T)`` (:data:`STAGES`), with
    one thread everywhere (so that the seconds of a stage are its own), and the total.

    The stages are found by wrapping the functions ``point_map`` calls (the ZoomOut and the
    vertex map by their size: below ``N`` inside the search, ``N`` at the end)."""
    from cshape import _candidates, _nearest

    clock, spent = time.process_time, dict.fromkeys(STAGES, 0.0)
    saved, inside = [], [False]

    def wrap(mod, name, stage, search=False):
        f = getattr(mod, name, None)
        if f is None:
            return

        def g(*a, **k):
            label = stage(a, k)
            inside[0] |= search
            t = clock()
            try:
                return f(*a, **k)
            finally:
                spent[label] += clock() - t
                inside[0] &= not search
        saved.append((mod, name, f))
        setattr(mod, name, g)
    zoom_name = "_zoomout" if hasattr(maps, "_zoomout") else "zoomout"
    map_name = "_pointwise" if hasattr(maps, "_pointwise") else "map_to_pointwise"
    threads = (maps.SEARCH_THREADS, _nearest.NN_THREADS)
    maps.SEARCH_THREADS = _nearest.NN_THREADS = 1
    wrap(maps, "eigenbasis", lambda a, k: STAGES[0])
    wrap(_candidates, "sign_candidates", lambda a, k: STAGES[2])
    wrap(maps, zoom_name, lambda a, k: STAGES[3] if inside[0] else STAGES[6])
    wrap(maps, map_name, lambda a, k: STAGES[4] if inside[0] else STAGES[7])
    wrap(maps, "_candidates_of", lambda a, k: STAGES[5], search=True)
    try:
        t = clock()
        cshape.point_map(S, T)
        total = clock() - t
    finally:
        for mod, name, f in reversed(saved):
            setattr(mod, name, f)
        maps.SEARCH_THREADS, _nearest.NN_THREADS = threads
    # _candidates_of holds the sign patterns and the candidates' ZoomOuts and maps
    spent[STAGES[5]] -= spent[STAGES[2]] + spent[STAGES[3]] + spent[STAGES[4]]
    spent[STAGES[1]] = total - sum(v for s, v in spent.items() if s != STAGES[1])
    return spent, total


def stages(label, pairs=TIMED_PAIRS):
    """:func:`stage_seconds` of registration and remeshed pairs, into
    ``maps_stages_<label>.csv``; ``maps_stages.md`` shows every label."""
    group_of = {p[1]: p for p in people_pairs(("remeshed-different", "registrations"))}
    RESULTS.mkdir(exist_ok=True)
    path = RESULTS / f"maps_stages_{label}.csv"
    lines = ["group,pair,vertices,load," + ",".join(f'"{s}"' for s in STAGES) + ",total"]
    for pair in pairs:
        group, _lab, load = group_of[pair]
        S, T, _truth = load()
        la = load_average()[0]
        spent, total = stage_seconds(S, T)
        lines.append(f'"{group}",{pair},{T.n_vertices},{la:.2f},'
                     + ",".join(f"{v:.2f}" for v in spent.values()) + f",{total:.2f}")
        print(lines[-1], flush=True)
        path.write_text("\n".join(lines) + "\n")
    return path


def wall(label, pairs=TIMED_PAIRS, repeats=2):
    """Wall and processor seconds of ``cshape.point_map`` with its defaults (two threads),
    the fastest of ``repeats`` runs per pair, into ``maps_wall_<label>.csv`` (run the labels
    one after the other, so that they meet the same load; :func:`write_stages` shows the
    ratio)."""
    group_of = {p[1]: p for p in people_pairs(("remeshed-different", "registrations"))}
    path = RESULTS / f"maps_wall_{label}.csv"
    lines = ["pair,vertices,load,wall,cpu"]
    for pair in pairs:
        S, T, _truth = group_of[pair][2]()
        cshape.eigenbasis(S, N), cshape.eigenbasis(T, N)  # warm the caches of the imports
        runs = []
        for _ in range(repeats):
            la = load_average()[0]
            t, c = time.perf_counter(), time.process_time()
            cshape.point_map(S, T)
            runs.append((time.perf_counter() - t, time.process_time() - c, la))
        w, c, la = min(runs)
        lines.append(f"{pair},{T.n_vertices},{la:.2f},{w:.2f},{c:.2f}")
        print(lines[-1], flush=True)
        path.write_text("\n".join(lines) + "\n")
    return path


def write_stages(command):
    """``maps_stages.md``: the seconds of each stage, every label side by side."""
    import csv

    lines = _header("Where the time of `cshape.point_map` goes", command) + [
        "Processor seconds of each stage of `cshape.point_map(source, target)` (its "
        "defaults), with one thread everywhere (`SEARCH_THREADS` and the nearest-row "
        "searches' threads set to 1), so that a stage's seconds are its own; on two free "
        "cores the candidates, the sign patterns and the big nearest-row searches are shared "
        "among two threads and the wall time is less (`maps_people.md`).  *load*: the "
        "machine's 1-minute load average at the start (other work shares the two cores, so "
        "even processor seconds grow with it).  *current*: this version; another label is "
        "another version of cshape (its checkout first on `PYTHONPATH`, this script).", ""]
    for label in _labels("stages"):
        rows = list(csv.reader((RESULTS / f"maps_stages_{label}.csv").read_text()
                               .splitlines()))
        head, body = rows[0], rows[1:]
        lines += [f"## {label}", "",
                  "| stage | " + " | ".join(f"{r[1]} ({r[2]} v., load {r[3]})" for r in body)
                  + " |", "|---|" + "---|" * len(body)]
        for j, stage in enumerate(head[4:], start=4):
            lines.append(f"| {stage} | " + " | ".join(r[j] for r in body) + " |")
        lines.append("")
    walls = {label: list(csv.reader((RESULTS / f"maps_wall_{label}.csv").read_text()
                                    .splitlines()))[1:] for label in _labels("wall")}
    if walls:
        labs = list(walls)
        lines += ["## wall time, two threads", "",
                  "`python benchmarks/bench_maps.py --wall LABEL` (each label with its own "
                  "version of cshape, run one after the other): `point_map` with its defaults "
                  "(`SEARCH_THREADS = 2`), the fastest of two runs; *load* at the start of "
                  "that run.", "",
                  "| pair | vertices | " + " | ".join(
                      f"{lab} s | {lab} cpu s | {lab} load" for lab in labs)
                  + (f" | speed-up ({labs[0]} s / {labs[1]} s) | ({labs[0]} cpu s / "
                     f"{labs[1]} cpu s) |" if len(labs) == 2 else " |"),
                  "|---|---|" + "---|---|---|" * len(labs) + ("---|---|" if len(labs) == 2
                                                             else "")]
        for i, r0 in enumerate(walls[labs[0]]):
            rs = [w[i] for w in walls.values() if i < len(w)]
            row = f"| {r0[0]} | {r0[1]} | " + " | ".join(f"{r[3]} | {r[4]} | {r[2]}" for r in rs)
            if len(rs) == 2:
                row += (f" | {float(rs[0][3]) / float(rs[1][3]):.2f} | "
                        f"{float(rs[0][4]) / float(rs[1][4]):.2f}")
            lines.append(row + " |")
        lines.append("")
    (RESULTS / "maps_stages.md").write_text("\n".join(lines) + "\n")
    return "\n".join(lines)


def people_landmarks(pairs=("006->049", "010->006", "006->037"), k=5):
    """Failed remeshed pairs with ``k`` true landmarks: the target's extremities (farthest
    points of its commute-time embedding: hands, feet, head) and their true source vertices,
    as a user would click them.  Written to ``maps_people_landmarks.md``."""
    import _remeshed as rm

    from cshape import _candidates

    lines = _header("Landmarks settle the remeshed pairs that fail (`cshape.point_map`)",
                    "--people-landmarks")
    lines += [f"`point_map(source, target)` without and with {k} true landmarks at the "
              "target's extremities (hands, feet, head), on pairs of `faust-dev-remeshed` "
              "whose search fails; error as in `maps_people.md`.", "",
              "| pair | without: err | 5 % | with landmarks: err | 5 % | s |",
              "|---|---|---|---|---|---|"]
    for label in pairs:
        a, b = (int(x) for x in label.split("->"))
        S, T, truth = rm.remeshed(a), rm.remeshed(b), rm.true_map(a, b)
        v = rm.rows(T.n_vertices, N_EVAL_PEOPLE)
        geo = cshape.geodesics.HeatGeodesics(S)
        bT = cshape.eigenbasis(T, 20)
        y = _candidates.extremities(bT.phi, bT.lam, k)
        out = []
        for lm in (None, np.column_stack([truth[y], y])):
            t = time.perf_counter()
            p = cshape.point_map(S, T, landmarks=lm)
            sec = time.perf_counter() - t
            err = rm.errors(S, p, truth, geo, v)
            out.append((err.mean(), (err <= THRESHOLD).mean(), sec))
        lines.append(f"| {label} | {out[0][0]:.4f} | {out[0][1]:.3f} | {out[1][0]:.4f} | "
                     f"{out[1][1]:.3f} | {out[1][2]:.1f} |")
        print(lines[-1], flush=True)
        (RESULTS / "maps_people_landmarks.md").write_text("\n".join(lines) + "\n")
    return "\n".join(lines)


def people_diagnose(label):
    """Every candidate of the search of ``point_map`` on one ``faust-dev-remeshed`` pair
    (e.g. ``006->049``) or remeshed TOSCA pair (e.g. ``cat0->cat2``): its residual,
    orientation share, descriptor error, extrinsic misfit
    and true error at the compared size (recorded from ``point_map`` itself), and those of
    the true map (its ``C`` at that size, and the vertex map of that ``C``).  Printed, not
    written: a diagnosis."""
    import _remeshed as rm

    from cshape import _candidates as cand
    from cshape import maps as cmaps

    a, b = label.split("->")
    if a.isdigit():
        a, b = int(a), int(b)
        S, T, truth = rm.remeshed(a), rm.remeshed(b), rm.true_map(a, b)
    else:
        S, T = rm.tosca_remeshed(a)[0], rm.tosca_remeshed(b)[0]
        truth = rm.tosca_true_map(a, b)
    geo = cshape.geodesics.HeatGeodesics(S)
    v = rm.rows(T.n_vertices, N_EVAL_PEOPLE)
    seen = {"maps": [], "bases": []}
    pick, to_points, basis = cand.pick_extrinsic, cmaps._pointwise, cmaps.eigenbasis

    def record_pick(scores, *args):
        seen["scores"], seen["keep"] = list(scores), pick(scores, *args)
        return seen["keep"]

    def record_map(*args, **kw):
        q = to_points(*args, **kw)
        if args[1] is not args[2]:  # not the source's map to itself (its mirror symmetry)
            seen["maps"].append(q)
        return q

    def record_basis(*args, **kw):
        seen["bases"].append(basis(*args, **kw))
        return seen["bases"][-1]

    cand.pick_extrinsic, cmaps._pointwise, cmaps.eigenbasis = (record_pick, record_map,
                                                               record_basis)
    threads, cmaps.SEARCH_THREADS = cmaps.SEARCH_THREADS, 1  # the maps in candidate order
    try:
        p = cshape.point_map(S, T)
    finally:
        cand.pick_extrinsic, cmaps._pointwise, cmaps.eigenbasis = pick, to_points, basis
        cmaps.SEARCH_THREADS = threads
    rows = []

    def row(name, sc, q):
        rows.append(f"| {name} | {sc[0]:.4f} | {sc[1]:.3f} | {sc[2]:.4f} | {sc[3]:.4f} | "
                    f"{rm.errors(S, q, truth, geo, v).mean():.4f} |")

    for i, (sc, q) in enumerate(zip(seen["scores"], seen["maps"], strict=False)):
        row(f"candidate {i + 1}" + (" (kept)" if i == seen["keep"] else ""), sc, q)
    bS, bT = seen["bases"]
    m = cand.COMPARE_SIZE
    wT = np.asarray(bT.B.sum(axis=1)).ravel()
    start = cmaps._Start(bS, bT, K0, N_ENERGIES, True)
    Ct = bT.phi[:, :m].T @ (bT.B @ bS.phi[truth, :m])
    for name, q in (("true map (its C at the compared size)", truth),
                    ("vertex map of the true C", to_points(Ct, bS.phi, bT.phi))):
        row(name, (cand.residual(Ct, bS.phi, bT.phi, q), cand.orientation_share(S, T, q),
                   cand.descriptor_error(start.dS, start.dT, wT, q),
                   cand.extrinsic_residual(S, T, bT.phi, bT.B, q)), q)
    row("returned", (float("nan"),) * 4, p)
    lams = (f"eigenvalues 1-5 over the first: source "
            f"{np.round(bS.lam[1:6] / bS.lam[1], 2).tolist()}, target "
            f"{np.round(bT.lam[1:6] / bT.lam[1], 2).tolist()}")
    return "\n".join([f"{label}: {lams}", "",
                      "| candidate | residual | orientation share | descriptor error | "
                      "extrinsic misfit | true error |", "|---|---|---|---|---|---|", *rows])


def people_pictures():
    """A failed and a repaired map between two generated bodies (no data needed):
    ``maps_people_failed.png`` (``initial='descriptors'``) and ``maps_people_repaired.png``
    (``initial='search'``), the generated human at rest to its pose 0 made stockier."""
    from cshape import plots

    small = {"voxelsize": 0.03, "target_vertices": 800}
    body = poses.posed_figure("human", rest=True, **small)
    stocky = poses.posed_figure("human", 0, **small)
    stocky = cshape.Mesh(stocky.vertices * [1.3, 1.3, 0.9], stocky.faces)
    geo = cshape.geodesics.HeatGeodesics(body)
    out = []
    for initial, name, what in (("descriptors", "failed", "initial='descriptors'"),
                                ("search", "repaired", "initial='search' (default)")):
        p = cshape.point_map(body, stocky, N=50, N0=20, initial=initial)
        err = cshape.geodesics.geodesic_errors(body, p, geodesics=geo).mean() / np.sqrt(body.area)
        fig = plots.plot_map(body, stocky, p, values=body.vertices[:, 0], cmap="coolwarm",
                             titles=("body at rest, coloured by x",
                                     f"a stockier body, {what}: error {err:.3f}"))
        path = RESULTS / f"maps_people_{name}.png"
        fig.savefig(path, dpi=90, bbox_inches="tight")
        out.append(f"{path.name}: {what}, mean geodesic error / sqrt(area) {err:.3f}")
    return "\n".join(out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="the generated poses only")
    ap.add_argument("--timing", action="store_true",
                    help="time point_map at 16K, 46K and 63K vertices (maps_timing.md)")
    ap.add_argument("--timing-63k", action="store_true",
                    help="time point_map on the 63K pair again, appended to maps_timing.md")
    ap.add_argument("--calibrate", action="store_true",
                    help="orientation weights on the generated poses "
                         "(maps_orientation_weight.md)")
    ap.add_argument("--characters", default="",
                    help="TOSCA characters, comma-separated (default: all)")
    ap.add_argument("--max-poses", type=int, default=0,
                    help="at most this many poses per character against its pose 0")
    ap.add_argument("--poses", default="",
                    help="only these pose numbers against pose 0, comma-separated")
    ap.add_argument("--name", default="maps_tosca", help="results file name (no .md)")
    ap.add_argument("--people", metavar="LABEL", default="",
                    help="point_map on FAUST remeshed pairs (different people, one person), "
                         "the registrations and TOSCA pose pairs, saved as "
                         "maps_people_LABEL.csv; maps_people.md shows every label side by "
                         "side (the results kept: 'current')")
    ap.add_argument("--groups", default=",".join(GROUPS),
                    help="with --people: groups of pairs, comma-separated, of "
                         + ", ".join(GROUPS))
    ap.add_argument("--pairs", default="",
                    help="with --people: only these pairs, comma-separated (e.g. 006->049)")
    ap.add_argument("--limit", type=int, default=0,
                    help="with --people: at most this many pairs per group")
    ap.add_argument("--diagnose", metavar="PAIR", default="",
                    help="print every candidate of the search on one faust-dev-remeshed pair "
                         "(e.g. 006->049) or remeshed TOSCA pair (cat0->cat2) and the true "
                         "map's criteria")
    ap.add_argument("--stages", metavar="LABEL", default="",
                    help="processor seconds of each stage of point_map on three pairs, one "
                         "thread (maps_stages_LABEL.csv, maps_stages.md)")
    ap.add_argument("--wall", metavar="LABEL", default="",
                    help="wall and processor seconds of point_map on three pairs, two "
                         "threads (maps_wall_LABEL.csv, shown in maps_stages.md)")
    ap.add_argument("--people-landmarks", action="store_true",
                    help="failed remeshed pairs without and with five true landmarks "
                         "(maps_people_landmarks.md)")
    ap.add_argument("--people-pictures", action="store_true",
                    help="a failed and a repaired map between generated bodies "
                         "(maps_people_failed.png, maps_people_repaired.png)")
    ap.add_argument("--max-vertices", type=int, default=0,
                    help="skip TOSCA characters with more vertices (default: none)")
    args = ap.parse_args(argv)
    command = " ".join(sys.argv[1:] if argv is None else argv)
    if args.calibrate:
        print(write_calibration(calibrate(), command))
        return
    if args.diagnose:
        print(people_diagnose(args.diagnose))
        return
    if args.wall:
        wall(args.wall, tuple(p for p in args.pairs.split(",") if p)
             or TIMED_PAIRS)
        print(write_stages(command))
        return
    if args.stages:
        stages(args.stages, tuple(p for p in args.pairs.split(",") if p)
               or TIMED_PAIRS)
        print(write_stages(command))
        return
    if args.people_landmarks:
        print(people_landmarks())
        return
    if args.people_pictures:
        print(people_pictures())
        return
    if args.people:
        people(args.people, tuple(g for g in args.groups.split(",") if g),
               tuple(p for p in args.pairs.split(",") if p), args.limit)
        print(write_people(command, note=PEOPLE_NOTE))
        return
    if args.timing_63k:
        print(append_point_map_times(point_map_times(), command))
        return
    if args.timing:
        print(write_timing(*timing(), command))
        return
    checks = []
    if args.quick:
        pairs, name = list(generated_pairs()), "maps_quick"
    else:
        chars = tuple(c for c in args.characters.split(",") if c) or None
        pairs, name = list(tosca_pairs(chars, checks)), args.name
        if args.poses:
            wanted = {int(i) for i in args.poses.split(",")}
            pairs = [p for p in pairs if int(re.findall(r"\d+", p[0])[-1]) in wanted]
        if args.max_poses:
            count = {}
            keep = []
            for p in pairs:
                c = re.split(r"[0-9 ]", p[0])[0]
                count[c] = count.get(c, 0) + 1
                if count[c] <= args.max_poses:
                    keep.append(p)
            pairs = keep
        pairs.sort(key=lambda p: p[1].n_vertices)  # the small characters first
        if args.max_vertices:
            pairs = [p for p in pairs if p[1].n_vertices <= args.max_vertices]
    rows = []
    for label, S, T, truth in pairs:
        res, common_s = measure(S, T, truth)
        rows.append((re.split(r"[0-9 ]", label)[0], label, S.n_vertices, common_s, res))
        print(label, {m: tuple(round(x, 3) for x in v) for m, v in res.items()}, flush=True)
        write_accuracy(rows, name, command, checks, total=len(pairs))
    print(write_accuracy(rows, name, command, checks))


if __name__ == "__main__":
    main()
