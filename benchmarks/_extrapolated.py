"""Linear and Richardson-extrapolated spectra of mesh collections (cached), for
``bench_real_collections.py``.

One midpoint subdivision of a mesh (every triangle into four, ``h`` halved) gives a second
linear-FEM spectrum ``lam_fine``; the error of linear elements is ``O(h^2)``, so
``(4 lam_fine - lam_coarse) / 3`` cancels its leading term.  Each collection is stored in
``<cache>/<name>-spectra.npz`` with ``lam`` (linear FEM, the mesh as given), ``lam_fine``
(its subdivision), ``area``, ``names``, ``labels``, ``n_vertices``.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

N = 100


def midpoint_subdivide(V, F):
    """Every triangle into four by its edge midpoints (the surface is unchanged)."""
    V = np.asarray(V, float)
    F = np.asarray(F, np.int64)
    e = np.sort(np.vstack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    uniq, inv = np.unique(e, axis=0, return_inverse=True)
    inv = inv.reshape(-1)
    mid = len(V) + inv.reshape(3, -1).T  # (f, 3): midpoints of edges 01, 12, 20
    V2 = np.vstack([V, 0.5 * (V[uniq[:, 0]] + V[uniq[:, 1]])])
    a, b, c = F[:, 0], F[:, 1], F[:, 2]
    m01, m12, m20 = mid[:, 0], mid[:, 1], mid[:, 2]
    F2 = np.vstack([np.c_[a, m01, m20], np.c_[b, m12, m01], np.c_[c, m20, m12],
                    np.c_[m01, m12, m20]])
    return V2, F2


def _weyl_padded(lam):
    """``N`` values: a spectrum of fewer (a mesh of fewer vertices) extended by Weyl's law
    from its last eigenvalue, ``lam_i = lam_n i / n`` (the product's rule for short rows)."""
    n = len(lam) - 1
    return np.concatenate([lam, lam[-1] * np.arange(n + 1, N) / n])


#: Whether :func:`spectra` solves the midpoint subdivision too (``--no-fine``: not, for the
#: linear and mixed spectra alone).
FINE = True


def spectra(meshes, consistent=True):
    """(lam, lam_mixed, lam_fine, area, n_vertices) of a sequence of cshape meshes: the
    consistent mass (``lam``), the mixed mass (``lam_mixed``) and, where :data:`FINE`, the
    consistent spectrum of the midpoint subdivision; a mesh of fewer than ``N`` vertices gets
    all its eigenvalues, extended by Weyl's law.  ``consistent=False``: no ``lam`` (the
    caller has it)."""
    import cshape

    out = {"lam": [], "lam_mixed": [], "lam_fine": [], "area": [], "n_vertices": []}
    for m in meshes:
        V, F = np.asarray(m.vertices, float), np.asarray(m.faces, np.int64)
        n = min(N, len(V) - 1)
        if consistent:
            out["lam"].append(_weyl_padded(cshape.shape_dna((V, F), N=n)))
        out["lam_mixed"].append(_weyl_padded(cshape.shape_dna((V, F), N=n, mass="mixed")))
        if FINE:
            Vf, Ff = midpoint_subdivide(V, F)
            out["lam_fine"].append(_weyl_padded(cshape.shape_dna((Vf, Ff),
                                                                 N=min(N, len(Vf) - 1))))
        out["area"].append(float(cshape.Mesh(V, F).area))
        out["n_vertices"].append(len(V))
    for k in ("lam_fine",) * (not FINE) + ("lam",) * (not consistent):
        del out[k]
    return {k: np.array(v) for k, v in out.items()}


def real_collection(folder: Path, cache: Path) -> Path:
    import cshape

    dst = cache / f"{folder.name}-spectra.npz"
    if dst.exists():
        return dst
    ref = np.load(folder / "reference-spectra.npz")
    files = [str(f) for f in ref["files"]]
    t0 = time.perf_counter()
    meshes = (cshape.load_mesh(folder / f) for f in files)
    # without the subdivision, the consistent spectra are the collection's reference ones
    out = spectra(meshes, consistent=FINE)
    if not FINE:
        out["lam"] = np.asarray(ref["lam"], float)
    np.savez(dst, names=np.array(files), labels=ref["labels"], **out)
    print(f"{folder.name}: {len(files)} meshes, {time.perf_counter() - t0:.0f} s",
          file=sys.stderr, flush=True)
    return dst


def suite_collection(name: str, cache: Path) -> Path:
    import cshape.data

    dst = cache / f"{name}-spectra.npz"
    if dst.exists():
        return dst
    t0 = time.perf_counter()
    coll = cshape.data.load_collection(name, progress=False)
    out = spectra(coll.meshes)
    np.savez(dst, names=np.array(coll.names, dtype=str),
             labels=np.array(coll.labels, dtype=str), **out)
    print(f"{name}: {len(coll.names)} meshes, {time.perf_counter() - t0:.0f} s",
          file=sys.stderr, flush=True)
    return dst


def folder_collection(folder: Path, cache: Path) -> Path:
    """The meshes of ``../shared/meshes`` (one subfolder per object)."""
    import cshape

    dst = cache / "shared-meshes-spectra.npz"
    if dst.exists():
        return dst
    files = sorted(p for p in folder.rglob("*.obj"))
    names, labels, meshes = [], [], []
    for p in files:
        names.append(p.stem)
        labels.append(p.parent.name)
        meshes.append(cshape.load_mesh(p))
    out = spectra(meshes)
    np.savez(dst, names=np.array(names), labels=np.array(labels), **out)
    return dst


if __name__ == "__main__":
    import argparse

    ap = argparse.ArgumentParser()
    ap.add_argument("--realdev", default="../shared/realdev")
    ap.add_argument("--meshes", default="../shared/meshes")
    ap.add_argument("--cache", default="out/realdev_cache")
    ap.add_argument("--no-fine", action="store_true",
                    help="linear and mixed spectra only, no midpoint subdivision")
    ap.add_argument("what", nargs="*", default=["suite", "real", "meshes"])
    a = ap.parse_args()
    FINE = not a.no_fine
    cache = Path(a.cache)
    cache.mkdir(parents=True, exist_ok=True)
    if "suite" in a.what:
        for n in ("resolutions-dev", "identities-dev", "creatures-dev"):
            suite_collection(n, cache)
    if "meshes" in a.what:
        folder_collection(Path(a.meshes), cache)
    if "real" in a.what:
        for c in ("faust-dev", "tosca-dev", "shrec07-dev"):
            real_collection(Path(a.realdev) / c, cache)
