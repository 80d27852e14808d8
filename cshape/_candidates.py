"""Initial functional maps that survive a change of body shape, and the check that picks one.

The internals of :func:`cshape.point_map` when no landmarks are given (the rationale and the
measurements: ``docs/guides/maps.md``, ``benchmarks/results/maps_people.md``).

Between two people, the first few eigenfunctions still correspond one to one, up to their
signs: the true ``C`` is close to ``diag(+-1)`` in its first ``SIGN_SIZE`` rows and columns,
while the descriptors (WKS) of the two bodies no longer agree.  So every sign pattern is a
candidate (``2^(SIGN_SIZE - 1)``; the constant eigenfunction's sign is known), each one
upsampled by a sampled ZoomOut to ``SIGN_ZOOM`` eigenfunctions.  The candidates whose sampled
vertex maps fit their ``C`` best (the smallest spectral residual ``|Phi_T[y] - C Phi_S[p[y]]|``)
are kept, two that differ.  A left-right symmetric body has two such fits, the map and its
mirror; no intrinsic energy tells them apart, the orientation of the surface does
(:func:`orientation_share`).

ZoomOut may end with a limb reflected about its own axis while the extremities (hands, feet,
head) still land on the right limb.  So each candidate also gives landmarks: the target's
``EXTREMITIES`` farthest points (:func:`extremities`) and their images, from which the
landmark route of :func:`cshape.point_map` computes one more candidate.  Those maps are all
oriented; a map that turns the body about its vertical axis (front to back and left to right)
is oriented too, and fits the first eigenfunctions as well.  What tells it apart is the
descriptors: the back does not look like the front (:func:`descriptor_error`).  The
descriptors' map is fitted to the descriptors: they judge only the maps from extremities
against the start kept (:func:`pick`).

None of these criteria can tell two maps apart on a shape with a symmetry that keeps the
orientation (a half turn): every criterion of its two maps agrees within noise.
:func:`rival` finds such a map, and :func:`settling_vertices` the target vertices where
landmarks would decide.
"""

from __future__ import annotations

import itertools

import numpy as np

from ._nearest import nearest_rows
from .mesh import Mesh

#: Eigenfunctions whose signs are enumerated (the constant one included).
SIGN_SIZE = 6
#: Size to which each sign pattern is upsampled before the candidates are compared.
SIGN_ZOOM = 20
#: Vertices per shape in that upsampling.
SIGN_SAMPLE = 1000
#: Candidates of the sign patterns refined in full (those of the smallest residual that differ).
SIGN_KEEP = 2
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
        p = nearest_rows(np.ascontiguousarray(subT[:, :kc]), subS[:, :kc] @ C.T)
        if kc >= k:
            return C, p
        kc += 1
        C = _fit(subT[:, :kc], subS[p, :kc], w, None)


def residual(C, phiS, phiT, p):
    """Mean spectral residual ``|Phi_T[y] - C Phi_S[p[y]]|`` of a map and its ``C``."""
    k = C.shape[0]
    return float(np.linalg.norm(phiT[:, :k] - phiS[p, :k] @ C.T, axis=1).mean())


def sign_candidates(phiS, phiT, wT, rng):
    """Return the ``SIGN_KEEP`` sign patterns of the smallest residual, upsampled, that differ.

    A list of ``C`` of size ``SIGN_ZOOM`` (at most the bases' sizes).
    """
    k = min(SIGN_ZOOM, phiS.shape[1], phiT.shape[1])
    iS = np.sort(rng.choice(len(phiS), min(SIGN_SAMPLE, len(phiS)), replace=False))
    iT = np.sort(rng.choice(len(phiT), min(SIGN_SAMPLE, len(phiT)), replace=False))
    subS, subT, w = phiS[iS], phiT[iT], wT[iT]
    s0 = np.sign(phiS[:, 0].sum() * phiT[:, 0].sum()) or 1.0
    m = min(SIGN_SIZE, k)
    found = []
    for signs in itertools.product((1.0, -1.0), repeat=m - 1):
        C, p = _zoom(np.diag([s0, *signs]), subS, subT, w, k)
        found.append((residual(C, subS, subT, p), C, p))
    found.sort(key=lambda f: f[0])
    kept = [found[0]]
    for f in found[1:]:
        if len(kept) == SIGN_KEEP:
            break
        if all(np.mean(f[2] == g[2]) < 0.5 for g in kept):
            kept.append(f)
    return [C for _r, C, _p in kept]


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

    ``scores`` as for :func:`pick`; ``distances[i]``: the mean distance between the images of
    candidate ``i`` and of the kept one (over the square root of the source's area).  Of the
    candidates within ``TIE_RESIDUAL``, ``TIE_ORIENTATION`` and ``TIE_DESCRIPTORS`` of the
    kept one and farther than ``TIE_DISTANCE`` from it, the one of the smallest residual.
    ``floor``: a difference of residuals this small is round-off (exact maps of a symmetric
    shape have residuals of round-off size).
    """
    r, o, d = scores[keep]
    tied = [i for i, (ri, oi, di) in enumerate(scores)
            if i != keep and distances[i] > TIE_DISTANCE
            and abs(ri - r) <= TIE_RESIDUAL * max(r, ri) + floor
            and abs(oi - o) <= TIE_ORIENTATION
            and abs(di - d) <= TIE_DESCRIPTORS * max(d, di) + 1e-9]
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
