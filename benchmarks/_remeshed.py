"""FAUST meshes remeshed each on its own (``faust-dev-remeshed``): loading, the true map, errors.

The true image of remeshed vertex ``j`` of mesh ``b`` on mesh ``a`` is the remeshed vertex of
``a`` nearest to vertex ``truth[b][j]`` of registration ``a`` (all registrations share one
vertex order; ``faust-dev-remeshed/README``).  Errors are measured as the literature does:
the geodesic distance on the source between the image and the true vertex, over the square
root of the source's area.
"""

from __future__ import annotations

import warnings
from functools import cache, lru_cache
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

import cshape

REALDEV = Path(__file__).resolve().parents[2] / "shared" / "realdev"
if not REALDEV.exists():
    REALDEV = Path("/work/shared/realdev")
REMESHED = REALDEV / "faust-dev-remeshed"
REGISTRATIONS = REALDEV / "faust-dev"
THRESHOLD = 0.05


@cache
def _truth():
    return dict(np.load(REMESHED / "truth.npz"))


@lru_cache(maxsize=8)
def remeshed(i):
    with warnings.catch_warnings():  # one file has a duplicate vertex, welded on reading
        warnings.simplefilter("ignore", cshape.CShapeWarning)
        return cshape.load_mesh(REMESHED / f"tr_reg_{i:03d}.off.gz")


@lru_cache(maxsize=8)
def registration(i):
    return cshape.load_mesh(REGISTRATIONS / f"tr_reg_{i:03d}.off.gz")


def true_map(a, b):
    """For each vertex of remeshed ``b`` (the target), its true image on remeshed ``a``."""
    # the truth is per vertex of the file; a repaired mesh may have welded a duplicate
    raw = cshape.load_mesh(REMESHED / f"tr_reg_{b:03d}.off.gz", repair=False).vertices
    rows_of_file = cKDTree(raw).query(remeshed(b).vertices)[1]
    reg = registration(a).vertices[_truth()[f"tr_reg_{b:03d}"][rows_of_file]]
    return cKDTree(remeshed(a).vertices).query(reg)[1].astype(np.int64)


#: Target vertices evaluated per pair (spread over the vertex numbers).
N_EVAL = 300


def rows(n, k=N_EVAL):
    """``k`` target vertices spread over the vertex numbers ``0 .. n-1`` (all if fewer)."""
    return np.unique(np.linspace(0, n - 1, min(k, n)).astype(np.int64))


def errors(S, p, truth, geodesics=None, vertices=None):
    """Geodesic error over sqrt(area) of the target vertices ``vertices`` (default
    :func:`rows`) of a map ``p`` onto ``S``."""
    geo = geodesics or cshape.geodesics.HeatGeodesics(S)
    v = rows(len(p)) if vertices is None else vertices
    return cshape.geodesics.geodesic_errors(S, p, truth, vertices=v,
                                            geodesics=geo) / np.sqrt(S.area)


def pairs_different(n=20, seed=0):
    """``n`` random ordered pairs of meshes of different people (a fixed seed)."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        a, b = (int(x) for x in rng.choice(50, 2, replace=False))
        if a // 10 != b // 10 and (a, b) not in out:
            out.append((a, b))
    return out


def pairs_same(n=10, seed=0):
    """``n`` random ordered pairs of meshes of one person (a fixed seed)."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        a, b = (int(x) for x in rng.choice(50, 2, replace=False))
        if a // 10 == b // 10 and (a, b) not in out:
            out.append((a, b))
    return out


#: Vertices of the dense copies (:func:`dense`), about those of the largest published bodies.
DENSE_VERTICES = 55000


def _remeshed_on_its_own(original, key, vertices):
    """``original`` remeshed on its own to about ``vertices`` vertices (PyMeshLab isotropic
    explicit remeshing, :func:`cshape.data.variants.remesh`, 6 iterations), and for each of
    its vertices the nearest vertex of ``original``.  Cached in the temporary folder as
    ``<key>_<vertices>.npz`` (the remeshing takes a while), never shipped."""
    import tempfile

    from cshape.data import variants

    path = Path(tempfile.gettempdir()) / "cshape-bench" / f"{key}_{vertices}.npz"
    if path.exists():
        z = np.load(path)
        return cshape.Mesh(z["vertices"], z["faces"]), z["truth"]
    orig = original()
    m = variants.remesh(orig, target_vertices=vertices, iterations=6)
    truth = cKDTree(orig.vertices).query(m.vertices)[1].astype(np.int64)
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savez(path, vertices=m.vertices, faces=m.faces, truth=truth)
    return m, truth


def _carried(a, original_a, b):
    """For each vertex of remeshed ``b = (mesh, truth)``, its true image on remeshed ``a``:
    the vertex of ``a`` nearest to the original vertex ``b``'s truth names (the originals of
    ``a`` and ``b`` share one vertex order)."""
    return cKDTree(a[0].vertices).query(original_a.vertices[b[1]])[1].astype(np.int64)


@lru_cache(maxsize=4)
def dense(i, vertices=DENSE_VERTICES):
    """Registration ``i`` remeshed on its own to about ``vertices`` vertices, and its truth.

    As ``faust-dev-remeshed`` but finer (:func:`_remeshed_on_its_own`): the truth of each
    vertex is its nearest vertex of the registration (all registrations share one vertex
    order).
    """
    return _remeshed_on_its_own(lambda: registration(i), f"dense_{i:03d}", vertices)


def dense_true_map(a, b, vertices=DENSE_VERTICES):
    """For each vertex of dense ``b`` (the target), its true image on dense ``a``."""
    return _carried(dense(a, vertices), registration(a), dense(b, vertices))


TOSCA = REALDEV / "tosca-dev"
#: Vertices of each remeshed TOSCA pose (:func:`tosca_remeshed`), about those of
#: ``faust-dev-remeshed``.
TOSCA_VERTICES = 5000


@lru_cache(maxsize=16)
def tosca_original(name):
    """TOSCA mesh ``name`` (e.g. ``cat3``) as published: the poses of a character share one
    vertex order."""
    return cshape.load_mesh(TOSCA / f"{name}.off.gz")


@lru_cache(maxsize=16)
def tosca_remeshed(name, vertices=TOSCA_VERTICES):
    """TOSCA pose ``name`` remeshed on its own to about ``vertices`` vertices, and its truth.

    As ``faust-dev-remeshed`` (:func:`_remeshed_on_its_own`): no two poses share a
    triangulation; the truth of each vertex is its nearest vertex of the published pose (the
    poses of one character share one vertex order).
    """
    return _remeshed_on_its_own(lambda: tosca_original(name), f"tosca_{name}", vertices)


def tosca_true_map(a, b, vertices=TOSCA_VERTICES):
    """For each vertex of remeshed pose ``b`` (the target), its true image on remeshed ``a``
    (poses of one character)."""
    return _carried(tosca_remeshed(a, vertices), tosca_original(a), tosca_remeshed(b, vertices))
