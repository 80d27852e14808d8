"""Per-mesh spectra and global features of the real collections (cached), for
``bench_real_collections.py``.

For one mesh file this computes, once, and stores in ``<cache>/<collection>/<stem>.npz``:

* ``lam``, ``area``: cshape's 100 smallest eigenvalues (linear FEM, consistent mass,
  Neumann; :func:`cshape.spectrum.eigenpairs`) and the surface area;
* ``hks_q``: area-weighted quantiles (5 %, 15 %, ..., 95 %) of ``log HKS`` of the shape
  scaled to unit area, at ``HKS_T`` (unit-area times), shape ``(len(HKS_T), 10)``;
* ``wks_q``: the same quantiles of the WKS (trace-normalised) at the unit-area energies
  ``WKS_E``, shape ``(len(WKS_E), 10)``;
* ``d2``: the D2 shape distribution (Osada et al. 2002): histogram of the distances between
  ``D2_PAIRS`` pairs of area-uniform random surface points, in units of ``sqrt(area)``,
  ``D2_BINS`` bins over ``[0, D2_MAX]`` (fixed seed);
* ``lam_idl``: the 100 smallest eigenvalues of the intrinsic Delaunay Laplacian
  (``robust_laplacian.mesh_laplacian``, Sharp and Crane 2020; lumped mass), of the mesh
  scaled to unit area (so ``lam_idl`` is area-normalised), shift-invert ARPACK, ``tol=0``;
* ``lam_arpack``: cshape's matrices solved by plain ``scipy.sparse.linalg.eigsh`` (default
  ``tol=0``, shift-invert ``sigma = -0.01`` of the unit-area problem, raw units), for the
  zero-mode round-off;
* ``lam_lapy``: LaPy's ``Solver(TriaMesh).eigs(k=100)`` where LaPy is installed (raw units).
"""

from __future__ import annotations

import numpy as np

HKS_T = np.geomspace(2e-3, 0.5, 8)        # unit-area times
WKS_E = np.linspace(np.log(20.0), np.log(900.0), 8)  # unit-area log energies
WKS_SIGMA = 7 * (np.log(1250.0) - np.log(12.0)) / 100  # Aubry et al.'s width for this range
QUANTILES = np.linspace(0.05, 0.95, 10)
D2_PAIRS = 200_000
D2_BINS = 64
D2_MAX = 2.0
N = 100


def _wquantiles(values, weights, q):
    """Weighted quantiles of each column of ``values`` (n, T): shape (T, len(q))."""
    out = np.empty((values.shape[1], len(q)))
    for j in range(values.shape[1]):
        order = np.argsort(values[:, j])
        cw = np.cumsum(weights[order])
        cw /= cw[-1]
        out[j] = np.interp(q, cw, values[order, j])
    return out


def _vertex_areas(V, F):
    a = 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
    w = np.zeros(len(V))
    for c in range(3):
        np.add.at(w, F[:, c], a / 3)
    return a, w


def _d2(V, F, face_areas, seed=0):
    rng = np.random.default_rng(seed)
    p = face_areas / face_areas.sum()
    def sample(n):
        f = rng.choice(len(F), size=n, p=p)
        u, v = rng.random(n), rng.random(n)
        flip = u + v > 1
        u[flip], v[flip] = 1 - u[flip], 1 - v[flip]
        A, B, C = V[F[f, 0]], V[F[f, 1]], V[F[f, 2]]
        return A + u[:, None] * (B - A) + v[:, None] * (C - A)
    d = np.linalg.norm(sample(D2_PAIRS) - sample(D2_PAIRS), axis=1) / np.sqrt(face_areas.sum())
    h, _ = np.histogram(d, bins=D2_BINS, range=(0, D2_MAX))
    return h / D2_PAIRS


def _eigsh(L, Mm, sigma):
    from scipy.sparse.linalg import eigsh
    lam = eigsh(L.tocsc(), k=N, M=Mm.tocsc(), sigma=sigma, which="LM", tol=0,
                return_eigenvectors=False)
    return np.sort(lam)


def features(path, lapy=True):
    import cshape
    from cshape.fem import fem_matrices

    mesh = cshape.load_mesh(path)
    V = np.asarray(mesh.vertices, dtype=np.float64)
    F = np.asarray(mesh.faces, dtype=np.int64)
    fa, va = _vertex_areas(V, F)
    area = float(fa.sum())
    lam, phi = cshape.spectrum.eigenpairs(mesh, N=N)
    if phi.shape[0] != len(V):  # pragma: no cover - load_mesh repaired already
        raise RuntimeError(f"{path}: {phi.shape[0]} eigenfunction rows, {len(V)} vertices")
    out = {"lam": lam, "area": area, "n_vertices": len(V), "n_faces": len(F)}
    # signatures of the unit-area shape: lam * area, phi^2 * area (phi is B-orthonormal)
    ln, ph2 = lam * area, phi**2 * area
    H = ph2 @ np.exp(-np.outer(ln, HKS_T))
    out["hks_q"] = _wquantiles(np.log(np.maximum(H, 1e-300)), va, QUANTILES)
    keep = ln > 1e-8 * ln.max()
    G = np.exp(-np.square(WKS_E[None, :] - np.log(ln[keep])[:, None]) / (2 * WKS_SIGMA**2))
    W = (ph2[:, keep] @ G) / G.sum(axis=0)
    out["wks_q"] = _wquantiles(np.log(np.maximum(W, 1e-300)), va, QUANTILES)
    out["d2"] = _d2(V, F, fa)
    # intrinsic Delaunay Laplacian of the unit-area mesh
    import robust_laplacian
    Ls, Ms = robust_laplacian.mesh_laplacian(V / np.sqrt(area), F)
    out["lam_idl"] = _eigsh(Ls, Ms, -0.01)
    # cshape's own matrices, plain ARPACK (default tol=0), raw units
    A, B = fem_matrices(mesh)[:2]
    out["lam_arpack"] = _eigsh(-A if A.diagonal().max() <= 0 else A, B, -0.01 / area)
    if lapy:
        try:
            from lapy import Solver, TriaMesh
            ev, _ = Solver(TriaMesh(V, F)).eigs(k=N)
            out["lam_lapy"] = np.sort(ev)
        except ImportError:
            pass
    return out


def mesh_signatures(mesh):
    """lam (N,), and hks_q, wks_q, d2, lam_idl of one mesh (see the module notes)."""
    import robust_laplacian

    import cshape

    V = np.asarray(mesh.vertices, dtype=np.float64)
    F = np.asarray(mesh.faces, dtype=np.int64)
    fa, va = _vertex_areas(V, F)
    area = float(fa.sum())
    lam, phi = cshape.spectrum.eigenpairs(mesh, N=N)
    if phi.shape[0] != len(V):
        raise RuntimeError(f"{phi.shape[0]} eigenfunction rows but {len(V)} vertices "
                           "(the mesh was repaired): load it with cshape.load_mesh first")
    ln, ph2 = lam * area, phi**2 * area  # the unit-area shape (phi is B-orthonormal)
    H = ph2 @ np.exp(-np.outer(ln, HKS_T))
    keep = ln > 1e-8 * ln.max()
    G = np.exp(-np.square(WKS_E[None, :] - np.log(ln[keep])[:, None]) / (2 * WKS_SIGMA**2))
    W = (ph2[:, keep] @ G) / G.sum(axis=0)
    Ls, Ms = robust_laplacian.mesh_laplacian(V / np.sqrt(area), F)
    return {"lam": lam, "area": area, "n_vertices": len(V), "n_faces": len(F),
            "hks_q": _wquantiles(np.log(np.maximum(H, 1e-300)), va, QUANTILES),
            "wks_q": _wquantiles(np.log(np.maximum(W, 1e-300)), va, QUANTILES),
            "d2": _d2(V, F, fa), "lam_idl": _eigsh(Ls, Ms, -0.01)}


def suite_features(bench, dst):
    """The signatures of every mesh of the suite benchmark ``bench``'s development instance."""
    import cshape.data
    from cshape.data.suite import SUITE

    coll = cshape.data.load_collection(SUITE[bench][0], progress=False)
    acc = {k: [] for k in ("hks_q", "wks_q", "d2", "lam_idl", "lam")}
    for mesh in coll.meshes:
        f = mesh_signatures(mesh)
        for k in acc:
            acc[k].append(f[k])
    np.savez(dst, names=np.array(coll.names, dtype=str),
             labels=np.array(coll.labels, dtype=str), **{k: np.array(v) for k, v in acc.items()})


def main(argv=None):
    import argparse
    import sys
    import time
    from pathlib import Path

    ap = argparse.ArgumentParser()
    ap.add_argument("folder")
    ap.add_argument("cache")
    ap.add_argument("--no-lapy", action="store_true")
    args = ap.parse_args(argv)
    folder = Path(args.folder)
    cache = Path(args.cache) / folder.name
    cache.mkdir(parents=True, exist_ok=True)
    files = sorted(folder.glob("*.off.gz"), key=lambda p: p.stat().st_size)
    for f in files:
        dst = cache / (f.name[: -len(".off.gz")] + ".npz")
        if dst.exists():
            continue
        t0 = time.perf_counter()
        out = features(f, lapy=not args.no_lapy)
        np.savez(dst.with_suffix(".tmp.npz"), **out)
        dst.with_suffix(".tmp.npz").rename(dst)
        print(f"{folder.name}/{f.name}: {out['n_vertices']} vertices, "
              f"{time.perf_counter() - t0:.1f} s", file=sys.stderr, flush=True)


if __name__ == "__main__":
    main()
