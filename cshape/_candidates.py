"""Initial functional maps that survive a change of body shape, and the check that picks one.

The internals of :func:`cshape.point_map` when no landmarks are given (the rationale and the
measurements: ``docs/guides/maps.md``, ``benchmarks/results/maps_people.md``).

Between two people, the first few eigenfunctions still correspond one to one, up to their
signs (and the order of two whose eigenvalues are close): the true ``C`` is close to a signed
permutation in its first ``SIGN_SIZE`` rows and columns, while the descriptors (WKS) of the
two bodies no longer agree.  So every sign pattern is a candidate (``2^(SIGN_SIZE - 1)``; the
constant eigenfunction's sign is known), and those that swap two neighbours of close
eigenvalues (:func:`_swaps`), each one upsampled by a sampled ZoomOut to ``SIGN_ZOOM``
eigenfunctions.  The candidates whose sampled vertex maps fit their ``C`` best (the smallest
spectral residual ``|Phi_T[y] - C Phi_S[p[y]]|``) are kept, two that differ.  The first
eigenfunctions of a body are often all symmetric left to right: a pattern then fits the map
and its mirror image alike, and ZoomOut ends on either.  :func:`cshape.point_map` therefore
also starts from each pattern's oriented map (the pattern's eigenfunctions as descriptors,
with the orientation term), which settles left and right.

ZoomOut may end with a limb reflected about its own axis while the extremities (hands, feet,
head) still land on the right limb.  So each candidate also gives landmarks: the target's
``EXTREMITIES`` farthest points (:func:`extremities`) and their images, from which the
landmark route of :func:`cshape.point_map` computes one more candidate.

A map that turns a body about its long axis (front to back and left to right) keeps the
orientation, fits the first eigenfunctions and agrees with the descriptors about as well as
the true map: a body looks nearly alike in front and behind to every intrinsic measure.  In
space it does not: the toes, the face and the chest point the other way.  Of the candidates
that fit and keep the orientation, :func:`pick_extrinsic` keeps the one whose images are
carried onto the target best by a rotation, a scale and a smooth bending
(:func:`extrinsic_residual`).

Between bodies of different build, ZoomOut may also end on a map that sends the front of the
body to its back: it keeps every part in place (the error is about the body's thickness) but
reverses the orientation, and the oriented map of its pattern need not repair it.  Placed in
space, such a map carries the source over the target (:func:`extrinsic_residual`'s rotation
and smooth bending); each target vertex then takes the source vertex nearest in position and
normal, and the normals put it on the right side (:func:`turned_in_space`).  Fitted in space,
that map's extrinsic misfit is small by construction: :func:`pick_extrinsic` lets it compete
only if no other candidate beats it on all three intrinsic criteria.

None of these criteria can tell two maps apart on a shape with a symmetry that keeps the
orientation (a half turn of a shape symmetric in space too): every criterion of its two maps
agrees within noise. :func:`rival` finds such a map, and :func:`settling_vertices` the target
vertices where landmarks would decide.
"""

from __future__ import annotations

import itertools
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from ._nearest import nearest_rows
from .mesh import Mesh

#: Eigenfunctions whose signs are enumerated (the constant one included).
SIGN_SIZE = 6
#: Eigenfunctions of the target that span the smooth bending :func:`extrinsic_residual`
#: forgives.
EXTRINSIC_BASIS = 20
#: Neighbouring eigenfunctions whose eigenvalues are within this ratio on either shape are
#: also tried in swapped order (:func:`sign_candidates`).
SWAP_RATIO = 1.3
#: Size to which each sign pattern is upsampled before the candidates are compared.
SIGN_ZOOM = 20
#: Vertices per shape in that upsampling.
SIGN_SAMPLE = 1000
#: At this size of the upsampling only the ``SIGN_PRUNE_KEEP`` patterns of the smallest
#: residual go on (the two kept in the end rank well among them from about this size on).
SIGN_PRUNE_SIZE = 12
SIGN_PRUNE_KEEP = 24
#: Vertices per shape in the upsampling of every candidate to ``COMPARE_SIZE`` (at most the
#: ``sample`` of :func:`cshape.point_map`).
COMPARE_SAMPLE = 1500
#: Candidates of the sign patterns refined in full (those of the smallest residual that differ).
SIGN_KEEP = 2
#: A candidate that keeps the orientation on at most this share of the area is a mirror image
#: (:func:`cshape.point_map` also tries it turned in space, :func:`turned_in_space`).
MIRROR_SHARE = 0.5
#: Weight of the normals in :func:`turned_in_space` (per unit of normal, in ``sqrt(area)``).
NORMAL_WEIGHT = 0.1
#: Eigenfunctions of the target that span the smooth bending :func:`turned_in_space` undoes
#: (fewer than ``EXTRINSIC_BASIS``: front and back of a limb must not be bent into each other).
TURN_BASIS = 10
#: Size to which every candidate is upsampled (ZoomOut) before they are compared; the one
#: kept goes on to the final size.
COMPARE_SIZE = 50
#: A candidate is compared by its orientation only if its residual is at most this factor
#: times the smallest residual of the candidates (a map that fits its ``C`` worse is wrong).
RESIDUAL_SLACK = 1.2
#: A map from extremities whose orientation share is at most this below the kept start's
#: competes with it on the descriptors (:func:`descriptor_error`).
ORIENTATION_SLACK = 0.1
#: Two candidate maps that differ are within noise of each other, and :func:`cshape.point_map`
#: warns, if their residuals differ by at most this share, their orientation shares by at
#: most ``TIE_ORIENTATION`` and their descriptor errors by at most ``TIE_DESCRIPTORS``.
TIE_RESIDUAL = 0.05
TIE_ORIENTATION = 0.03
TIE_DESCRIPTORS = 0.03
#: ... and their extrinsic misfits (:func:`extrinsic_residual`) by at most this share.
TIE_EXTRINSIC = 0.05
#: Two maps differ if their images of the target lie on average this far apart (in units of
#: the square root of the source's area).
TIE_DISTANCE = 0.1
#: Landmarks taken from each candidate (the target's extremities and their images).
EXTREMITIES = 5
#: Eigenfunctions of the embedding in which the extremities are farthest points.
EXTREMITY_BASIS = 20


def _fit(phiT, phiS_mapped, w, B):
    """Fit ``C`` to a vertex map (on all vertices, or by least squares on samples).

    ``C = Phi_T^T B Phi_S[p]`` (all vertices), or the mass-weighted least squares fit
    ``min_C sum_y w_y |Phi_T[y] C - ...|`` on samples: ``(Phi_T^T W Phi_T)^-1 Phi_T^T W
    Phi_S[p]`` (the transpose of the map written row-wise).
    """
    if B is not None:
        return phiT.T @ (B @ phiS_mapped)
    Wp = phiT * w[:, None]
    return np.linalg.solve(phiT.T @ Wp, Wp.T @ phiS_mapped)


def _zoom(C, subS, subT, w, k):
    """Upsample ``C`` to size ``k`` by ZoomOut on samples (mass-weighted least squares)."""
    kc = C.shape[0]
    while True:
        p = nearest_rows(np.ascontiguousarray(subT[:, :kc]), subS[:, :kc] @ C.T, single=True)
        if kc >= k:
            return C, p
        kc += 1
        C = _fit(subT[:, :kc], subS[p, :kc], w, None)


def _zoom_all(starts, subS, subT, w, k, threads=1, prune=None):
    """:func:`_zoom` of every map in ``starts``, each ZoomOut followed once.

    A ZoomOut step depends only on the vertex map of the step before, so two starts whose
    vertex maps meet go on alike from there: only the first of them is followed, the others
    give ``(None, None)``.  The starts of one step are shared among ``threads`` threads (the
    same result).  ``prune=(size, keep)``: at that size only the ``keep`` maps of the
    smallest :func:`residual` go on; the others give ``(None, None)``.
    """
    out, live = [None] * len(starts), dict(enumerate(starts))
    kc = min(C.shape[0] for C in starts)

    def nearest(item):
        i, C = item
        return i, nearest_rows(np.ascontiguousarray(subT[:, :kc]), subS[:, :kc] @ C.T,
                               single=True)

    def fit(item):
        return _fit(subT[:, :kc + 1], subS[item[1], :kc + 1], w, None)

    with ThreadPoolExecutor(threads) as pool:
        while live:
            seen, going = set(), {}
            for i, p in pool.map(nearest, live.items()):  # in the order of the starts
                key = p.tobytes()
                if key in seen:
                    out[i] = (None, None)
                elif kc >= k:
                    seen.add(key)
                    out[i] = (live[i], p)
                else:
                    seen.add(key)
                    going[i] = p
            if prune is not None and kc == prune[0] and len(going) > prune[1]:
                r = {i: residual(live[i], subS, subT, p) for i, p in going.items()}
                best = set(sorted(going, key=lambda i: (r[i], i))[:prune[1]])
                for i in going:
                    if i not in best:
                        out[i] = (None, None)
                going = {i: p for i, p in going.items() if i in best}
            live = dict(zip(going, pool.map(fit, going.items()), strict=True))
            kc += 1
    return out


def residual(C, phiS, phiT, p):
    """Mean spectral residual ``|Phi_T[y] - C Phi_S[p[y]]|`` of a map and its ``C``."""
    k = C.shape[0]
    return float(np.linalg.norm(phiT[:, :k] - phiS[p, :k] @ C.T, axis=1).mean())


def _swaps(lamS, lamT, m):
    """Return the eigenfunction pairs ``(i, i + 1)`` whose order may differ between the shapes.

    Those with ``1 <= i < m - 1`` whose eigenvalues lie within ``SWAP_RATIO`` of each other
    on either shape.
    """
    if lamS is None or lamT is None:
        return []
    out = []
    for i in range(1, m - 1):
        ratios = [lam[i + 1] / lam[i] for lam in (lamS, lamT) if lam[i] > 0]
        if ratios and min(ratios) < SWAP_RATIO:
            out.append(i)
    return out


def sign_candidates(phiS, phiT, wT, rng, lamS=None, lamT=None, threads=1):
    """Return the ``SIGN_KEEP`` sign patterns of the smallest residual, upsampled, that differ.

    A pattern is a signed permutation ``P`` of the first ``SIGN_SIZE`` eigenfunctions (the
    constant one first, its sign known): the diagonal ones, and, with the eigenvalues
    ``lamS``, ``lamT``, those that swap two neighbours of close eigenvalues (:func:`_swaps`).
    A list of ``(P, C)``: the pattern, ``P[i, j] = +-1`` if the target's eigenfunction ``i``
    is the source's ``j``, and its ``C`` upsampled to size ``SIGN_ZOOM`` (at most the bases'
    sizes).
    """
    k = min(SIGN_ZOOM, phiS.shape[1], phiT.shape[1])
    iS = np.sort(rng.choice(len(phiS), min(SIGN_SAMPLE, len(phiS)), replace=False))
    iT = np.sort(rng.choice(len(phiT), min(SIGN_SAMPLE, len(phiT)), replace=False))
    subS, subT, w = phiS[iS], phiT[iT], wT[iT]
    s0 = np.sign(phiS[:, 0].sum() * phiT[:, 0].sum()) or 1.0
    m = min(SIGN_SIZE, k)
    orders = [np.arange(m)]
    for i in _swaps(lamS, lamT, m):
        o = np.arange(m)
        o[[i, i + 1]] = o[[i + 1, i]]
        orders.append(o)
    patterns = []
    for order in orders:
        for signs in itertools.product((1.0, -1.0), repeat=m - 1):
            P = np.zeros((m, m))
            P[np.arange(m), order] = [s0, *signs]
            patterns.append(P)
    found = [(residual(C, subS, subT, p), C, p, P)
             for P, (C, p) in zip(patterns, _zoom_all(patterns, subS, subT, w, k, threads,
                                                      (SIGN_PRUNE_SIZE, SIGN_PRUNE_KEEP)),
                                  strict=True) if C is not None]
    found.sort(key=lambda f: f[0])
    kept = [found[0]]
    for f in found[1:]:
        if len(kept) == SIGN_KEEP:
            break
        if all(np.mean(f[2] == g[2]) < 0.5 for g in kept):
            kept.append(f)
    return [(P, C) for _r, C, _p, P in kept]


def _vertex_normals(mesh):
    """Return unit vertex normals (the area-weighted sum of the faces' normals)."""
    V, F = mesh.vertices, mesh.faces
    fn = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    vn = np.zeros_like(V)
    for j in range(3):
        np.add.at(vn, F[:, j], fn)
    return vn / np.maximum(np.linalg.norm(vn, axis=1), np.finfo(float).tiny)[:, None]


def turned_in_space(source: Mesh, target: Mesh, BT, p2p, phiT=None) -> np.ndarray:
    """Return a mirror-image map turned the right way round in space.

    The rotation, scale and translation of least mass-weighted squares that carry the images
    ``V_S[p]`` onto ``V_T`` (as in :func:`extrinsic_residual`) place the source over the
    target; with ``phiT`` (the target's eigenfunctions) the target is also unbent by the
    misfit's projection on its first ``TURN_BASIS`` eigenfunctions.  Each target vertex then
    takes the source vertex nearest to it in position and normal (``NORMAL_WEIGHT`` times
    ``sqrt(area)`` per unit of normal).  A map that sends the front of a body to its back
    places the source well but its normals the wrong way: the nearest vertex whose normal
    agrees is on the right side.  Returns a vertex map, shape ``(n_T,)``.
    """
    from scipy.spatial import cKDTree

    w = np.asarray(BT.sum(axis=1)).ravel()
    w = w / w.sum()
    a, b = source.vertices[p2p], target.vertices
    ca, cb = w @ a, w @ b
    U, _s, Vt = np.linalg.svd(((a - ca) * w[:, None]).T @ (b - cb))
    D = np.array([1.0, 1.0, np.sign(np.linalg.det(U @ Vt)) or 1.0])
    R = (U * D) @ Vt
    scale = np.sqrt(target.area / source.area)
    h = NORMAL_WEIGHT * np.sqrt(target.area)
    emb_S = np.hstack([scale * (source.vertices - ca) @ R + cb,
                       h * (_vertex_normals(source) @ R)])
    bt = b
    if phiT is not None:
        r = b - (scale * (a - ca) @ R + cb)
        P = phiT[:, :TURN_BASIS]
        bt = b - P @ (P.T @ (BT @ r))
    emb_T = np.hstack([bt, h * _vertex_normals(target)])
    return cKDTree(emb_S).query(emb_T)[1].astype(np.int64)


def orientation_share(source: Mesh, target: Mesh, p2p: np.ndarray) -> float:
    """Share of the target's area whose image keeps the orientation of the surface.

    Each target triangle ``(a, b, c)`` goes to the source triangle ``(p[a], p[b], p[c])``; it
    keeps the orientation if that triangle's normal points to the same side as the source's
    vertex normals there.  About 1 for a correct map, 0 for a mirror image; degenerate images
    (two corners on one vertex) do not count.
    """
    V, G = source.vertices, source.faces
    fn = np.cross(V[G[:, 1]] - V[G[:, 0]], V[G[:, 2]] - V[G[:, 0]])
    vn = np.zeros_like(V)
    for j in range(3):
        np.add.at(vn, G[:, j], fn)
    F = target.faces
    a, b, c = p2p[F[:, 0]], p2p[F[:, 1]], p2p[F[:, 2]]
    d = np.einsum("ij,ij->i", np.cross(V[b] - V[a], V[c] - V[a]), vn[a] + vn[b] + vn[c])
    W = target.vertices
    area = np.linalg.norm(np.cross(W[F[:, 1]] - W[F[:, 0]], W[F[:, 2]] - W[F[:, 0]]), axis=1)
    counted = area * (d != 0)
    total = counted.sum()
    return float((counted * (d > 0)).sum() / total) if total > 0 else 0.5


def extremities(phi, lam, k=EXTREMITIES):
    """Return ``k`` extremities of a shape: farthest points in its commute-time embedding.

    The embedding ``Phi[:, i] / sqrt(lam_i)`` (``i = 1 .. EXTREMITY_BASIS - 1``) stretches the
    ends of long parts (hands, feet, head) far from the rest; the first point is the one
    farthest from the embedding's mean, each next one the farthest from those chosen.
    Vertex indices, shape ``(k,)`` (fewer if the shape has fewer vertices).
    """
    m = min(EXTREMITY_BASIS, phi.shape[1])
    lam = np.asarray(lam[1:m], dtype=np.float64)
    X = phi[:, 1:m] / np.sqrt(np.maximum(lam, np.finfo(float).tiny))
    out = [int(np.argmax(np.linalg.norm(X - X.mean(axis=0), axis=1)))]
    d = np.linalg.norm(X - X[out[0]], axis=1)
    while len(out) < min(k, len(phi)):
        out.append(int(np.argmax(d)))
        d = np.minimum(d, np.linalg.norm(X - X[out[-1]], axis=1))
    return np.array(out, dtype=np.int64)


def descriptor_error(dS, dT, wT, p2p):
    """Mean disagreement ``|D_T[y] - D_S[p[y]]|`` of a vertex map's descriptors (mass-weighted).

    Each descriptor is divided by its root mean square on the source first.
    """
    scale = np.sqrt(np.mean(dS * dS, axis=0))
    scale[scale == 0] = 1.0
    e = np.linalg.norm((dT - dS[p2p]) / scale, axis=1)
    return float(e @ wT / wT.sum())


def extrinsic_residual(source: Mesh, target: Mesh, phiT, BT, p2p) -> float:
    """Misfit of the images ``V_S[p]`` to ``V_T`` after a rigid motion and a smooth bending.

    The rotation (determinant +1, so a mirror image is not fitted) and translation of least
    mass-weighted squares (Kabsch), the scale of the areas, then the misfit's projection on
    the target's first ``EXTRINSIC_BASIS`` eigenfunctions (a smooth bending: a change of
    pose or of build) is removed; the median (by area) of the distances that remain, over
    the root mean square of the target about its centre (a median, so that a map right but
    for a limb is not outweighed by one turned as a whole).
    A body looks nearly alike in front and behind to intrinsic measures: a half turn about its
    long axis fits the first eigenfunctions, keeps the orientation and agrees with the
    descriptors about as well as the true map; in space it turns the toes, the face and the
    chest to the back, which no smooth bending undoes.
    """
    w = np.asarray(BT.sum(axis=1)).ravel()
    w = w / w.sum()
    a = source.vertices[p2p]
    b = target.vertices
    a = a - w @ a
    b = b - w @ b
    U, _s, Vt = np.linalg.svd((a * w[:, None]).T @ b)
    D = np.array([1.0, 1.0, np.sign(np.linalg.det(U @ Vt)) or 1.0])
    scale = np.sqrt(target.area / source.area)
    r = b - scale * (a @ (U * D) @ Vt)
    P = phiT[:, :EXTRINSIC_BASIS]
    r = np.linalg.norm(r - P @ (P.T @ (BT @ r)), axis=1)
    size = float(np.sqrt(w @ np.einsum("ij,ij->i", b, b)))
    order = np.argsort(r)
    median = r[order][min(np.searchsorted(np.cumsum(w[order]), 0.5), len(r) - 1)]
    return float(median / size) if size > 0 else 0.0


def pick_extrinsic(scores, turned=()):
    """Return the index of the candidate to keep, by the extrinsic misfit.

    ``scores``: a list of ``(residual, orientation share, descriptor error, extrinsic
    misfit)`` (:func:`extrinsic_residual`).
    Of the candidates that keep the orientation on more than half the area (all, if none
    does), those whose residual is within ``RESIDUAL_SLACK`` of their smallest and whose
    orientation share is at most ``ORIENTATION_SLACK`` below the best of those, the one of
    the smallest :func:`extrinsic_residual` (of the smaller descriptor error on a tie).
    A candidate of ``turned`` (a mirror image turned in space, :func:`turned_in_space`: a
    repair fitted in space, whose extrinsic misfit is small by construction) is one of them
    only if no other is better on all three intrinsic criteria (a smaller residual, a larger
    orientation share and a smaller descriptor error).
    """
    pool = [i for i, s in enumerate(scores) if s[1] > 0.5] or list(range(len(scores)))
    best = min(scores[i][0] for i in pool)
    ok = [i for i in pool if scores[i][0] <= RESIDUAL_SLACK * best]
    top = max(scores[i][1] for i in ok)
    ok = [i for i in ok if scores[i][1] >= top - ORIENTATION_SLACK]
    ok = [i for i in ok if i not in turned or not any(
        scores[j][0] < scores[i][0] and scores[j][1] > scores[i][1]
        and scores[j][2] < scores[i][2] for j in ok if j != i)]
    return min(ok, key=lambda i: (scores[i][3], scores[i][2], i))


def pick(scores, n_starts):
    """Return the index of the candidate to keep.

    ``scores``: a list of ``(residual, orientation share, descriptor error)``, the first
    ``n_starts`` of the starting maps, the others of the maps from their extremities.  Of the
    starting maps whose residual is within ``RESIDUAL_SLACK`` of their smallest, the one that
    keeps the orientation best (of the smaller residual on a tie).  A map from extremities
    whose residual is within ``RESIDUAL_SLACK`` of the smallest of all, and whose orientation
    share is at most ``ORIENTATION_SLACK`` below that one's, replaces it if its descriptors
    agree better.
    """
    best = min(s[0] for s in scores[:n_starts])
    ok = [i for i in range(n_starts) if scores[i][0] <= RESIDUAL_SLACK * best]
    keep = max(ok, key=lambda i: (scores[i][1], -scores[i][0]))
    best = min(s[0] for s in scores)
    rivals = [i for i in range(n_starts, len(scores))
              if scores[i][0] <= RESIDUAL_SLACK * best
              and scores[i][1] >= scores[keep][1] - ORIENTATION_SLACK]
    return min([keep, *rivals], key=lambda i: (scores[i][2], scores[i][0], i))


def rival(scores, distances, keep, floor=0.0):
    """Index of a candidate as good as the one kept, within noise, that differs from it; or None.

    ``scores`` as for :func:`pick` or :func:`pick_extrinsic`; ``distances[i]``: the mean
    distance between the images of candidate ``i`` and of the kept one (over the square root
    of the source's area).  Of the candidates within ``TIE_RESIDUAL``, ``TIE_ORIENTATION``,
    ``TIE_DESCRIPTORS`` (and ``TIE_EXTRINSIC``, with four scores) of the kept one and farther
    than ``TIE_DISTANCE`` from it, the one of the smallest residual.
    ``floor``: a difference of residuals this small is round-off (exact maps of a symmetric
    shape have residuals of round-off size).
    """
    r, o, d = scores[keep][:3]
    e = scores[keep][3] if len(scores[keep]) > 3 else 0.0
    tied = [i for i, (ri, oi, di, *ei) in enumerate(scores)
            if i != keep and distances[i] > TIE_DISTANCE
            and abs(ri - r) <= TIE_RESIDUAL * max(r, ri) + floor
            and abs(oi - o) <= TIE_ORIENTATION
            and abs(di - d) <= TIE_DESCRIPTORS * max(d, di) + 1e-9
            and (not ei or abs(ei[0] - e) <= TIE_EXTRINSIC * max(e, ei[0]) + 1e-6)]
    return min(tied, key=lambda i: (scores[i][0], i)) if tied else None


def settling_vertices(V, p, q, k=3):
    """Return ``k`` target vertices where two vertex maps onto vertices ``V`` disagree most.

    Farthest points (spread apart) among the quarter of the target whose images under ``p``
    and ``q`` lie farthest apart.
    """
    gap = np.linalg.norm(V[p] - V[q], axis=1)
    pool = np.argsort(gap)[::-1][:max(k, len(gap) // 4)]
    out = [int(pool[0])]
    d = np.linalg.norm(V[p[pool]] - V[p[out[0]]], axis=1)
    while len(out) < min(k, len(pool)):
        out.append(int(pool[np.argmax(d)]))
        d = np.minimum(d, np.linalg.norm(V[p[pool]] - V[p[out[-1]]], axis=1))
    return np.array(out, dtype=np.int64)
