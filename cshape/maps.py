"""Stage 7 of the pipeline: maps between shapes (functional maps, ZoomOut) and geodesics.

A *functional map* (Ovsjanikov et al. 2012) carries functions from a source shape ``S`` to a
target shape ``T``.  In the truncated, B-orthonormal eigenbases ``Phi_S`` (``n_S x N_S``)
and ``Phi_T`` (``n_T x N_T``) of :func:`cshape.eigenbasis` it is a small matrix ``C``
(``N_T x N_S``): a function ``f = Phi_S a`` on ``S`` goes to ``Phi_T C a`` on ``T``.  The
functions here take the two :class:`cshape.Eigenbasis` values (``phi``, ``B``, ``lam`` and
the mesh of each shape).  A
vertex map ``p`` (for each target vertex ``y``, a source vertex ``p[y]``; the pyFM
``p2p_21`` convention) and ``C`` determine each other:

``C = Phi_T^T B_T Pi Phi_S``  (``Pi[y, p[y]] = 1``, the pull-back, Eq. 3 of Ovsjanikov et al.)

``p[y] = argmin_x || Phi_T[y] - C Phi_S[x] ||``  (nearest neighbour in spectral space).

==========================  =================================================================
function                    what it does
==========================  =================================================================
:func:`point_map`           the one call: two meshes in, ``p`` (shape ``(n_T,)``) out
:func:`functional_map`      ``C`` from descriptors, Laplacian commutativity, orientation
:func:`zoomout`             spectral upsampling of ``C`` from ``N0`` to ``N`` (Melzi et al. 2019)
:func:`map_to_pointwise`    ``p`` from ``C`` (exact nearest neighbours)
:func:`pointwise_to_map`    ``C`` from ``p``
:func:`transfer_function`   a function on ``S`` carried to ``T`` through ``C``
:func:`geodesic_distance`   heat-method geodesic distance to a set of vertices (Crane et al.
                            2013); :class:`HeatGeodesics` factorises once for many sources
:func:`geodesic_errors`     geodesic distance between a map's images and the true ones
==========================  =================================================================

The energy of :func:`functional_map`, for descriptors ``D_S = Phi_S^T B_S F_S`` (``N_S x d``)
and ``D_T`` projected on the bases, eigenvalues ``lam_S``, ``lam_T``:

``E(C) = w_d ||C D_S - D_T||^2 + w_l sum_ij C_ij^2 (lam_T,i - lam_S,j)^2
+ w_o sum_f ||C O_S,f - O_T,f C||^2``

the descriptor preservation (Eq. 5 of Ovsjanikov et al. 2012), the commutativity with the
Laplace-Beltrami operator (their Eq. 6, diagonal in the eigenbases), and the
orientation-preserving term of Ren, Poulenard, Wonka and Ovsjanikov (2018, Eq. 8):
``O_f g = <n x grad f, grad g>`` is the operator "derivative along the rotated gradient of
the descriptor ``f``", which changes sign under a mirror.  Intrinsic descriptors cannot tell
left from right; this term can, because it uses the surface's orientation (face order).
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import ArrayLike, NDArray

from ._checks import check_bool, check_int, check_landmarks, check_real, check_vertex_indices
from ._eigensolver.threads import one_blas_thread
from .fem import fem_matrices
from .mesh import Mesh, MeshLike, as_mesh, repair_mesh
from .signatures import heat_kernel, wks, wks_energies
from .spectrum import Eigenbasis, eigenbasis

__all__ = [
    "HeatGeodesics",
    "face_gradients",
    "functional_map",
    "geodesic_distance",
    "geodesic_errors",
    "map_to_pointwise",
    "point_map",
    "pointwise_to_map",
    "transfer_function",
    "zoomout",
]

#: Query rows per matrix product of the vertex map (:func:`map_to_pointwise`): a block holds
#: ``NN_BLOCK x n_S`` distances (512 x 60,000 x 8 bytes = 0.25 GB).
NN_BLOCK = 512

#: Threads sharing the blocks of the vertex map (at most the CPUs).
NN_THREADS = 2

#: From this many (query, point) pairs on, the vertex map uses scikit-learn's brute-force
#: search (the full-size map of 10K-vertex meshes and up); below, the blocks above.
NN_SKLEARN_PAIRS = 10**8

#: Default weights of :func:`functional_map` (descriptors, Laplacian, orientation), for
#: descriptors and eigenvalues scaled as described there.
DESCRIPTOR_WEIGHT = 1.0
LAPLACIAN_WEIGHT = 1e-2
ORIENTATION_WEIGHT = 3e-4

#: :func:`point_map` keeps every 5th of its WKS energies (pyFM's ``subsample_step``).
DESCRIPTOR_STRIDE = 5


# ---------------------------------------------------------------------- checks
def _check_mesh(name, mesh) -> Mesh:
    """Return a mesh that the eigensolver will not renumber (no repair needed), or raise."""
    try:
        m = as_mesh(mesh)
    except TypeError as exc:
        raise TypeError(f"{name}: {exc}") from None
    fixed = repair_mesh(m, warn=False)
    if fixed.n_vertices != m.n_vertices:
        raise ValueError(
            f"{name} has {m.n_vertices - fixed.n_vertices} duplicate or unreferenced vertices, "
            "so its eigenfunctions would not have one row per vertex; call "
            f"cshape.repair_mesh({name}) first and map the repaired meshes"
        )
    return m


def _check_eigenbasis(name: str, basis: object) -> Eigenbasis:
    if not isinstance(basis, Eigenbasis):
        raise TypeError(
            f"{name} must be a cshape.Eigenbasis, got {type(basis).__name__}; compute it with "
            f"cshape.eigenbasis(mesh, N) (or build one from arrays: cshape.Eigenbasis(lam, "
            "phi, B))"
        )
    return basis


def _check_array(name, x, n=None) -> np.ndarray:
    """``x`` as a finite real 2-D float array (of ``n`` rows if given), or a clear error."""
    if isinstance(x, (str, bytes)) or np.iscomplexobj(x):
        raise TypeError(f"{name} must be a real 2-D array, got {type(x).__name__}")
    a = np.asarray(x, dtype=np.float64)
    if a.ndim != 2:
        raise ValueError(f"{name} must be a 2-D array, got shape {a.shape}")
    if n is not None and a.shape[0] != n:
        raise ValueError(f"{name} has {a.shape[0]} rows, expected {n} (one per vertex)")
    if not np.isfinite(a).all():
        raise ValueError(f"{name} contains NaN or infinite values")
    return a


def _columns(x):
    """Return a 1-D array as one column, anything else as it is (for :func:`_check_array`)."""
    a = np.asarray(x) if not isinstance(x, (str, bytes)) else x
    return a[:, None] if isinstance(a, np.ndarray) and a.ndim == 1 else a


def _check_C(C, N_target=None, N_source=None) -> np.ndarray:
    C = _check_array("C", C)
    if (N_target is not None and C.shape[0] > N_target) or (
            N_source is not None and C.shape[1] > N_source):
        raise ValueError(f"C has shape {C.shape}, larger than the bases (N_target={N_target}, "
                         f"N_source={N_source}); pass C of shape (N_T, N_S) with N_T, N_S at "
                         "most the basis sizes")
    return C


# ---------------------------------------------------------------------- gradients
def face_gradients(mesh: MeshLike) -> tuple[sp.csr_matrix, NDArray[np.float64],
                                             NDArray[np.float64]]:
    """Assemble the per-triangle gradient operator of piecewise-linear functions.

    On triangle ``t = (i, j, l)`` with unit normal ``n`` and area ``|t|``, the hat function
    of vertex ``i`` has the constant gradient ``grad phi_i = n x e_i / (2 |t|)``, ``e_i`` the
    edge opposite ``i`` (from ``j`` to ``l``).  With it, the stiffness of
    :func:`cshape.fem_matrices` is ``A = -G^T diag(|t|) G`` (each of x, y, z).

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)

    Returns
    -------
    G : scipy.sparse.csr_matrix, shape (3 F, n)
        ``(G f)[3 t + c]`` is component ``c`` of the gradient of ``f`` on triangle ``t``.
    areas : ndarray, shape (F,)
    normals : ndarray, shape (F, 3)
        Unit normals (right-hand rule in the face order).
    """
    m = as_mesh(mesh)
    V, F = m.vertices, m.faces
    cross = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    dbl = np.linalg.norm(cross, axis=1)
    safe = np.where(dbl > 0, dbl, 1.0)
    normals = cross / safe[:, None]
    rows, cols, vals = [], [], []
    nF = len(F)
    for a in range(3):
        j, l = F[:, (a + 1) % 3], F[:, (a + 2) % 3]
        g = np.cross(normals, V[l] - V[j]) / safe[:, None]  # n x e / (2 |t|)
        g[dbl == 0] = 0.0
        for c in range(3):
            rows.append(3 * np.arange(nF) + c)
            cols.append(F[:, a])
            vals.append(g[:, c])
    G = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(3 * nF, m.n_vertices))
    return G, 0.5 * dbl, normals


# ---------------------------------------------------------------------- geodesics
class HeatGeodesics:
    """Geodesic distances by the heat method (Crane, Weischedel and Wardetzky 2013).

    Three steps, each a sparse solve with a matrix factorised once here:

    1. heat flow for a short time ``t``: ``(B - t A) u = B delta_sources`` (one implicit
       Euler step of ``du/dt = Delta u``; ``A`` negative semidefinite, ``B`` the consistent
       mass of :func:`cshape.fem_matrices`);
    2. the unit field ``X = -grad u / |grad u|`` on every triangle (:func:`face_gradients`);
    3. the Poisson problem ``Delta phi = div X``: ``-A phi = G^T diag(|t|) X``, then
       ``phi -= phi[source]`` (one source), or with ``phi = 0`` imposed at every source
       (a set of sources, :meth:`distance`).

    ``t = m h^2`` with ``h`` the mean edge length (Crane et al.'s choice ``m = 1``).  The
    result converges to the geodesic distance as the mesh is refined (error about ``h``).

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
    m : float, default=1.0
        Time factor ``t = m h^2``.
    """

    def __init__(self, mesh: MeshLike, m: float = 1.0) -> None:
        self.mesh = _check_mesh("mesh", mesh)
        self.m = check_real("m", m, positive=True)
        A, B = fem_matrices(self.mesh)
        self.G, self.areas, _ = face_gradients(self.mesh)
        h = self.mesh.mean_edge_length
        t = self.m * h * h
        self._B = B
        self._heat = spla.splu((B - t * A).tocsc())
        self._K = (-A).tocsr()
        # -A is singular (constants): a tiny mass shift fixes the constant without moving
        # the gradient; the distances are shifted to 0 at the sources afterwards
        shift = 1e-10 * self._K.diagonal().mean() / B.diagonal().mean()
        self._poisson = spla.splu((self._K + shift * B).tocsc())

    def distances(self, sources: ArrayLike) -> NDArray[np.float64]:
        """One distance field per source vertex.

        Parameters
        ----------
        sources : array_like of int, shape (s,)

        Returns
        -------
        ndarray, shape (n, s)
            Column ``j``: the geodesic distance from ``sources[j]`` to every vertex.
        """
        n = self.mesh.n_vertices
        src = check_vertex_indices("sources", sources, n)
        rhs = np.zeros((n, len(src)))
        rhs[src, np.arange(len(src))] = 1.0
        return self._solve(self._B @ rhs, [[j] for j in range(len(src))], src)

    def distance(self, sources: ArrayLike) -> NDArray[np.float64]:
        """Compute the geodesic distance to the nearest of a set of vertices, shape (n,)."""
        n = self.mesh.n_vertices
        src = check_vertex_indices("sources", sources, n)
        if src.size == 0:
            raise ValueError("sources is empty; pass at least one vertex index")
        src = np.unique(src)
        rhs = np.zeros((n, 1))
        rhs[src, 0] = 1.0
        if len(src) == 1:
            return self._solve(self._B @ rhs, [[0]], src)[:, 0]
        # several sources: the Poisson problem with phi = 0 at every source (Dirichlet),
        # so that no source is left at the error of another one
        b = self._divergence(self._heat.solve(self._B @ rhs))[:, 0]
        free = np.setdiff1d(np.arange(n), src)
        phi = np.zeros(n)
        phi[free] = spla.spsolve(self._K[free][:, free].tocsc(), b[free])
        return np.maximum(phi, 0.0)

    def _divergence(self, u):
        """``G^T diag(|t|) X`` of the normalised field ``X = -grad u / |grad u|``."""
        nF = len(self.areas)
        g = (self.G @ u).reshape(nF, 3, -1)
        norm = np.linalg.norm(g, axis=1, keepdims=True)
        X = -g / np.where(norm > 0, norm, 1.0)
        return self.G.T @ (X * self.areas[:, None, None]).reshape(3 * nF, -1)

    def _solve(self, rhs, groups, src):
        b = self._divergence(self._heat.solve(rhs))
        phi = self._poisson.solve(b)
        for j, members in enumerate(groups):
            phi[:, j] -= phi[src[members], j].min()
        return np.maximum(phi, 0.0)


def geodesic_distance(mesh: MeshLike, sources: ArrayLike, *, m: float = 1.0
                      ) -> NDArray[np.float64]:
    """Geodesic distance from a set of vertices to every vertex, by the heat method.

    The one-call form of :class:`HeatGeodesics` (Crane et al. 2013): use the class to reuse
    its factorisations for many sources.

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
    sources : int or array_like of int, shape (s,)
        Vertex indices; the distance is to the nearest of them.
    m : float, default=1.0
        Heat time ``t = m h^2`` (``h`` the mean edge length).

    Returns
    -------
    ndarray, shape (n,)
        In the mesh's length units; 0 at the sources.

    Examples
    --------
    >>> import numpy as np, cshape
    >>> sphere = cshape.shapes.icosphere(4)
    >>> d = cshape.geodesic_distance(sphere, 0)
    >>> bool(abs(d.max() - np.pi) < 0.05)   # the antipode of the unit sphere
    True
    """
    return HeatGeodesics(mesh, m=m).distance(sources)


def geodesic_errors(mesh: MeshLike, p2p: ArrayLike, truth: ArrayLike | None = None, *,
                    vertices: ArrayLike | None = None,
                    geodesics: HeatGeodesics | None = None) -> NDArray[np.float64]:
    """Geodesic distance on ``mesh`` between the images of a map and the true images.

    ``err[j] = d(p2p[v_j], truth[v_j])`` for the evaluated target vertices ``v_j``, the
    standard error of a point map (divide by ``sqrt(mesh.area)`` for Kim et al.'s measure,
    or by the geodesic diameter).

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        The source shape (where the images lie).
    p2p : array_like of int, shape (n_T,)
        For each target vertex, a source vertex (:func:`point_map`).
    truth : array_like of int, shape (n_T,), optional
        The true map; default the identity (shapes that share their vertices).
    vertices : array_like of int, shape (s,), optional
        The target vertices to evaluate (one heat solve each); default all.
    geodesics : HeatGeodesics, optional
        Of ``mesh``, to reuse its factorisations.

    Returns
    -------
    ndarray, shape (s,)
    """
    geo = geodesics if geodesics is not None else HeatGeodesics(mesh)
    n = geo.mesh.n_vertices
    p2p = np.asarray(p2p)
    truth = np.arange(len(p2p)) if truth is None else np.asarray(truth)
    p2p = check_vertex_indices("p2p", p2p, n)
    truth = check_vertex_indices("truth", truth, n)
    if len(truth) != len(p2p):
        raise ValueError(f"truth has {len(truth)} entries and p2p {len(p2p)}; both have one "
                         "per target vertex")
    v = np.arange(len(p2p)) if vertices is None else check_vertex_indices("vertices", vertices,
                                                                     len(p2p))
    out = np.empty(len(v))
    for s in range(0, len(v), 64):
        block = v[s:s + 64]
        D = geo.distances(truth[block])
        out[s:s + 64] = D[p2p[block], np.arange(len(block))]
    return out


# ---------------------------------------------------------------------- nearest neighbours
def _nearest_rows(queries, points, block=NN_BLOCK):
    """Index of the nearest row of ``points`` for every row of ``queries``, exactly.

    Up to 3 dimensions a k-d tree.  Above (k-d and ball trees degrade to a scan in 30-100
    dimensions), scikit-learn's brute-force search for big problems (at least
    ``NN_SKLEARN_PAIRS`` query-point pairs: its OpenMP threads cost more than they gain on
    small ones), else blocks of ``|p|^2 - 2 q.p`` (``|q|^2`` does not change the argmin), each
    block one matrix product ``[q, 1] [-2 p, |p|^2]^T`` and its row-wise argmin; the blocks
    are shared among threads with one BLAS thread each, so that no BLAS worker spins.
    """
    if points.shape[1] <= 3:
        from scipy.spatial import cKDTree

        return cKDTree(points).query(queries)[1].astype(np.int64)
    if len(queries) * len(points) >= NN_SKLEARN_PAIRS:
        # the same products, tiled and reduced in compiled code on every core
        from sklearn.neighbors import NearestNeighbors

        nn = NearestNeighbors(n_neighbors=1, algorithm="brute").fit(points)
        return nn.kneighbors(queries, return_distance=False)[:, 0].astype(np.int64)
    P = np.empty((points.shape[1] + 1, len(points)))
    P[:-1] = -2.0 * points.T
    P[-1] = np.einsum("ij,ij->i", points, points)
    Q = np.empty((len(queries), queries.shape[1] + 1))
    Q[:, :-1] = queries
    Q[:, -1] = 1.0
    out = np.empty(len(queries), dtype=np.int64)

    def run(s):
        out[s:s + block] = np.argmin(Q[s:s + block] @ P, axis=1)

    starts = range(0, len(queries), block)
    threads = min(len(starts), NN_THREADS, os.cpu_count() or 1)
    with one_blas_thread():
        if threads > 1:
            with ThreadPoolExecutor(threads) as pool:
                list(pool.map(run, starts))
        else:
            for s in starts:
                run(s)
    return out


def map_to_pointwise(C: ArrayLike, source: Eigenbasis, target: Eigenbasis, *,
                     vertices: ArrayLike | None = None) -> NDArray[np.int64]:
    """Convert a functional map to a vertex map: ``p[y] = argmin_x ||Phi_T[y] - C Phi_S[x]||``.

    Exact nearest neighbours in ``N_T`` dimensions by blocked dense matrix products
    (k-d trees degrade to a scan in 30-100 dimensions).

    Parameters
    ----------
    C : array_like, shape (N_T, N_S)
        At most the sizes of the bases (their first ``N_T``, ``N_S`` eigenfunctions are used).
    source, target : Eigenbasis
        The bases of the two shapes (:func:`cshape.eigenbasis`).
    vertices : array_like of int, shape (s,), optional
        The target vertices to map; default all.

    Returns
    -------
    ndarray of int64, shape (n_T,) or (s,)
        For each target vertex, a source vertex (pyFM's ``p2p_21``).
    """
    source = _check_eigenbasis("source", source)
    target = _check_eigenbasis("target", target)
    C = _check_C(C, target.N, source.N)
    pT = target.phi
    if vertices is not None:
        pT = pT[check_vertex_indices("vertices", vertices, target.n_vertices)]
    kT, kS = C.shape
    return _nearest_rows(np.ascontiguousarray(pT[:, :kT]), source.phi[:, :kS] @ C.T)


def pointwise_to_map(p2p: ArrayLike, source: Eigenbasis, target: Eigenbasis
                     ) -> NDArray[np.float64]:
    """Convert a vertex map to a functional map: ``C = Phi_T^T B_T Pi Phi_S``, (N_T, N_S).

    Parameters
    ----------
    p2p : array_like of int, shape (n_T,)
        For each target vertex, a source vertex.
    source, target : Eigenbasis
        The bases of the two shapes (:func:`cshape.eigenbasis`), of sizes ``N_S`` and
        ``N_T`` (``target.truncate(N)`` for fewer); ``Phi_T^T B_T`` is the projection onto
        the target basis.
    """
    source = _check_eigenbasis("source", source)
    target = _check_eigenbasis("target", target)
    pS, pT = source.phi, target.phi
    p2p = check_vertex_indices("p2p", p2p, len(pS))
    if len(p2p) != len(pT):
        raise ValueError(f"p2p has {len(p2p)} entries but the target {len(pT)} vertices; p2p "
                         "has one source vertex per target vertex")
    return pT.T @ (target.B @ pS[p2p])


def transfer_function(f: ArrayLike, C: ArrayLike, source: Eigenbasis, target: Eigenbasis
                      ) -> NDArray[np.float64]:
    """Carry functions from the source to the target through ``C``.

    ``f_T = Phi_T C Phi_S^T B_S f``: project on the source basis, map the coefficients,
    synthesise on the target (Ovsjanikov et al. 2012, Eq. 1).  Smooth functions survive;
    detail above the ``N_S``-th eigenfunction is lost (use ``f[p2p]`` for that).

    Parameters
    ----------
    f : array_like, shape (n_S,) or (n_S, m)
    C : array_like, shape (N_T, N_S)
        At most the sizes of the bases (their first ``N_T``, ``N_S`` eigenfunctions are used).
    source, target : Eigenbasis
        The bases of the two shapes (:func:`cshape.eigenbasis`).

    Returns
    -------
    ndarray, shape (n_T,) or (n_T, m)
    """
    source = _check_eigenbasis("source", source)
    target = _check_eigenbasis("target", target)
    pS, pT = source.phi, target.phi
    C = _check_C(C, pT.shape[1], pS.shape[1])
    kT, kS = C.shape
    f = np.asarray(f, dtype=np.float64)
    if f.shape[0] != len(pS):
        raise ValueError(f"f has {f.shape[0]} rows but the source has {len(pS)} vertices")
    a = pS[:, :kS].T @ (source.B @ f)
    return pT[:, :kT] @ (C @ a)


# ---------------------------------------------------------------------- functional map
def _orientation_ops(mesh, phi, F):
    """Reduced orientation operators ``Phi^T W_f Phi`` (N x N) for each column ``f`` of F.

    ``W_f[i, j] = int psi_i <n x grad f, grad psi_j>`` (Ren et al. 2018), times
    ``sqrt(area)``: with ``Phi`` B-orthonormal the operators scale as 1 / length, so this
    makes them those of the shape scaled to unit area (the same weight for any unit).
    """
    G, areas, normals = face_gradients(mesh)
    nF, k = len(areas), phi.shape[1]
    gphi = (G @ phi).reshape(nF, 3, k)
    gf = (G @ F).reshape(nF, 3, -1)
    faces = as_mesh(mesh).faces
    # the face average of phi, times |t|: int_t psi_i = |t| / 3
    pface = phi[faces].sum(axis=1) * (areas / 3.0)[:, None]  # (nF, k)
    ops = []
    for d in range(F.shape[1]):
        J = np.cross(normals, gf[:, :, d])  # n x grad f
        nrm = np.linalg.norm(J, axis=1).mean()
        s = np.einsum("fc,fck->fk", J, gphi)
        op = pface.T @ s
        ops.append(op / max(nrm, np.finfo(float).tiny))
    return np.array(ops) * np.sqrt(areas.sum())


def functional_map(source: Eigenbasis, target: Eigenbasis, desc_source: ArrayLike,
                   desc_target: ArrayLike, *,
                   descriptor_weight: float = DESCRIPTOR_WEIGHT,
                   laplacian_weight: float = LAPLACIAN_WEIGHT,
                   orientation_weight: float = ORIENTATION_WEIGHT,
                   maxiter: int = 1000) -> NDArray[np.float64]:
    """Compute the functional map ``C`` (``N_T x N_S``) that best preserves descriptors.

    Minimises (Ovsjanikov et al. 2012, Eq. 5-6; Ren et al. 2018, Eq. 8)

    ``E(C) = w_d ||C D_S - D_T||^2 + w_l sum_ij C_ij^2 (lam_T,i - lam_S,j)^2
    + w_o sum_f ||C O_S,f - O_T,f C||^2``

    with ``D = Phi^T B F`` the descriptors projected on the bases (each descriptor scaled to
    unit B-norm on its shape), eigenvalues divided by the largest source eigenvalue, and
    ``O_f`` the reduced orientation operators of the descriptors (each divided by the mean
    norm of its field, and taken on the shape scaled to unit area, so that ``C`` and the
    weights do not depend on the unit of length).  Without the orientation term (``w_o = 0``)
    every row of ``C`` is an independent ridge regression, solved in closed form:
    ``(D_S D_S^T + w_l/w_d diag((lam_T,i - lam_S)^2)) c_i = D_S D_T[i]``.  With it the rows
    couple; ``E`` stays a convex quadratic, minimised exactly by conjugate gradients on its
    normal equations, started from the closed-form solution.

    Parameters
    ----------
    source, target : Eigenbasis
        The bases of the two shapes (:func:`cshape.eigenbasis`), of sizes ``N_S`` and
        ``N_T`` (``basis.truncate(N)`` for fewer).  The orientation term needs their meshes
        (the faces' orientation).
    desc_source, desc_target : array_like, shape (n_S, d), (n_T, d)
        Corresponding descriptors (e.g. :func:`cshape.wks` at the same energies).
    descriptor_weight, laplacian_weight, orientation_weight : float
        ``w_d``, ``w_l``, ``w_o`` (>= 0).
    maxiter : int, default=1000
        Conjugate-gradient iterations (the orientation term only; 0 leaves it out).

    Returns
    -------
    ndarray, shape (N_T, N_S)

    Raises
    ------
    ValueError
        ``orientation_weight > 0`` with a basis built without its mesh, descriptors of
        different counts or rows, both ``w_d`` and ``w_l`` zero.
    """
    source = _check_eigenbasis("source", source)
    target = _check_eigenbasis("target", target)
    lS, lT = source.lam, target.lam
    pS, pT = source.phi, target.phi
    FS = _check_array("desc_source", _columns(desc_source), len(pS))
    FT = _check_array("desc_target", _columns(desc_target), len(pT))
    if FS.shape[1] != FT.shape[1]:
        raise ValueError(f"desc_source has {FS.shape[1]} descriptors and desc_target "
                         f"{FT.shape[1]}; compute both at the same scales")
    wd = check_real("descriptor_weight", descriptor_weight, min=0)
    wl = check_real("laplacian_weight", laplacian_weight, min=0)
    wo = check_real("orientation_weight", orientation_weight, min=0)
    maxiter = check_int("maxiter", maxiter, min=0)
    if wd == 0 and wl == 0:
        raise ValueError("descriptor_weight and laplacian_weight are both 0; C is then not "
                         "determined; use descriptor_weight > 0")
    if wo > 0 and maxiter > 0:
        for name, b in (("source", source), ("target", target)):
            if b.mesh is None:
                raise ValueError(
                    f"{name} has no mesh, and the orientation term (orientation_weight="
                    f"{wo:g}) needs its faces; compute the basis with cshape.eigenbasis(mesh) "
                    "or pass orientation_weight=0"
                )
    B_source, B_target = source.B, target.B
    nS = np.sqrt(np.einsum("ij,ij->j", FS, B_source @ FS))
    nT = np.sqrt(np.einsum("ij,ij->j", FT, B_target @ FT))
    keep = (nS > 0) & (nT > 0)
    FS, FT = FS[:, keep] / nS[keep], FT[:, keep] / nT[keep]
    DS, DT = pS.T @ (B_source @ FS), pT.T @ (B_target @ FT)
    scale = max(float(np.abs(lS).max()), np.finfo(float).tiny)
    M = np.square(lT[:, None] / scale - lS[None, :] / scale)  # (N_T, N_S)
    # closed form per row: (wd DS DS^T + wl diag(M_i)) c_i = wd DS DT_i
    with one_blas_thread():  # N x N products: spinning BLAS threads only slow them
        return _solve_map(DS, DT, M, wd, wl, wo, maxiter, source.mesh, target.mesh, pS, pT,
                          FS, FT)


def _solve_map(DS, DT, M, wd, wl, wo, maxiter, source, target, pS, pT, FS, FT):
    """Minimise the energy of :func:`functional_map` (its arguments checked)."""
    kT, kS = M.shape
    H = wd * (DS @ DS.T)
    R = wd * (DS @ DT.T)  # (N_S, N_T)
    C = np.empty((kT, kS))
    for i in range(kT):
        C[i] = np.linalg.solve(H + wl * np.diag(M[i]) + 1e-12 * np.eye(kS), R[:, i])
    if wo == 0 or maxiter == 0:
        return C
    OS = _orientation_ops(source, pS, FS)
    OT = _orientation_ops(target, pT, FT)

    OSt, OTt = OS.transpose(0, 2, 1).copy(), OT.transpose(0, 2, 1).copy()

    # E is a convex quadratic in C: its minimiser solves the normal equations H vec(C) = r,
    # solved by conjugate gradients from the closed-form solution without the orientation
    def hess(x):
        X = x.reshape(kT, kS)
        RO = X @ OS - OT @ X  # (f, N_T, N_S): C O_S,f - O_T,f C
        g = X @ H + wl * M * X + 1e-12 * X  # H = wd DS DS^T, symmetric
        g += wo * ((RO @ OSt).sum(axis=0) - (OTt @ RO).sum(axis=0))
        return g.ravel()

    op = spla.LinearOperator((kT * kS, kT * kS), matvec=hess, dtype=np.float64)
    rhs = R.T.ravel()  # wd DT DS^T
    x, _info = spla.cg(op, rhs, x0=C.ravel(), rtol=1e-10, atol=0.0, maxiter=maxiter)
    return x.reshape(kT, kS)


# ---------------------------------------------------------------------- ZoomOut
def zoomout(C: ArrayLike, source: Eigenbasis, target: Eigenbasis, N: int | None = None, *,
            step: int = 1, sample: int | None = None, bijective: bool = False,
            random_state: int = 0) -> NDArray[np.float64]:
    """Spectral upsampling of a functional map (ZoomOut, Melzi et al. 2019, Algorithm 1).

    From ``C`` of size ``N0``, repeat until size ``N``: the vertex map of ``C``
    (:func:`map_to_pointwise`), then ``C`` of size ``+step`` from it
    (``C = Phi_T^T B_T Pi Phi_S``, Eq. 4 of Melzi et al.).  Each step makes the map more
    nearly an isometry between more eigenfunctions; the noise of the first map, in the high
    frequencies, is filtered out.

    With ``sample``, the iterations use that many random vertices of each shape (the
    map of the samples to all source vertices nearest in spectral space is replaced by a
    map to the source samples; ``C`` is fitted by least squares on the target samples,
    weighted by their mass): the cost falls from ``n_T n_S N`` to ``sample^2 N`` per step,
    with the same result to within a few per cent of accuracy (Magnet and Ovsjanikov 2021).

    Parameters
    ----------
    C : array_like, shape (N0, N0)
    source, target : Eigenbasis
        The bases of the two shapes (:func:`cshape.eigenbasis`), of at least ``N`` pairs.
    N : int, optional
        Final size (default: the size of the smaller basis).
    step : int, default=1
        Basis functions added per iteration.
    sample : int, optional
        Vertices per shape used in the iterations (default: all).
    bijective : bool, default=False
        Average ``C`` with the adjoint of the map the other way, ``(Phi_S^T B_S Pi_ST
        Phi_T)^T``, at every step, so the map is pushed towards a bijection.
    random_state : int, default=0
        Seed of the samples.

    Returns
    -------
    ndarray, shape (N, N)
    """
    source = _check_eigenbasis("source", source)
    target = _check_eigenbasis("target", target)
    pS, pT = source.phi, target.phi
    B_source, B_target = source.B, target.B
    C = _check_C(C, pT.shape[1], pS.shape[1])
    kmax = min(pS.shape[1], pT.shape[1])
    k = kmax if N is None else check_int("N", N, min=max(C.shape), max=kmax)
    step = check_int("step", step, min=1)
    bijective = check_bool("bijective", bijective)
    wT = np.asarray(B_target.sum(axis=1)).ravel()
    wS = np.asarray(B_source.sum(axis=1)).ravel()
    if sample is not None:
        sample = check_int("sample", sample, min=1)
        rng = np.random.default_rng(random_state)
        iS = np.sort(rng.choice(len(pS), min(sample, len(pS)), replace=False))
        iT = np.sort(rng.choice(len(pT), min(sample, len(pT)), replace=False))
    else:
        iS, iT = np.arange(len(pS)), np.arange(len(pT))
    subS, subT = pS[iS], pT[iT]
    full = sample is None
    with one_blas_thread():  # small products: spinning BLAS threads only slow them
        kc = C.shape[0]
        while True:
            kT, kS = C.shape
            p = _nearest_rows(np.ascontiguousarray(subT[:, :kT]), subS[:, :kS] @ C.T)
            if kc >= k and kT >= k:
                break
            kc = min(kc + step, k)
            C = _fit(subT[:, :kc], subS[p, :kc], wT[iT], B_target if full else None)
            if bijective:
                q = _nearest_rows(np.ascontiguousarray(subS[:, :kS]), subT[:, :kT] @ C[:kT, :kS])
                C2 = _fit(subS[:, :kc], subT[q, :kc], wS[iS], B_source if full else None)
                C = 0.5 * (C + C2.T)
            if kc >= k:
                break
    return C


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


# ---------------------------------------------------------------------- one call
def _descriptors(source, target, n_descr, landmarks):
    """WKS (and landmark heat kernels) of two bases at the source's energies, unit area."""
    e, sigma = wks_energies(source, n_descr, normalization="area")
    dS = wks(source, e, sigma, normalization="area")[:, ::DESCRIPTOR_STRIDE]
    dT = wks(target, e, sigma, normalization="area")[:, ::DESCRIPTOR_STRIDE]
    if landmarks is not None:
        # heat kernels from the landmarks, at a few times (units of the area)
        for t in (0.002, 0.005, 0.01):
            dS = np.hstack([dS, heat_kernel(source, t, landmarks[:, 0], normalization="area")])
            dT = np.hstack([dT, heat_kernel(target, t, landmarks[:, 1], normalization="area")])
    return dS, dT


def point_map(source: MeshLike, target: MeshLike, *, N: int = 100, N0: int = 30,
              n_descriptors: int = 100, orientation: bool = True,
              zoomout_steps: bool | int = True, landmarks: ArrayLike | None = None,
              bijective: bool = False, sample: int | None = 3000,
              return_map: bool = False, random_state: int = 0
              ) -> NDArray[np.int64] | tuple[NDArray[np.int64], NDArray[np.float64]]:
    """Map the vertices of two meshes in one call, by functional maps and ZoomOut.

    1. the :class:`cshape.Eigenbasis` of each mesh, ``N`` pairs (:func:`cshape.eigenbasis`:
       ``A`` and ``B`` assembled once);
    2. WKS descriptors (:func:`cshape.wks`, the shapes scaled to unit area, ``n_descriptors``
       energies of the source), plus heat kernels from the landmarks when given;
    3. ``C`` of size ``N0`` by :func:`functional_map` (with the orientation term);
    4. :func:`zoomout` to size ``N``;
    5. the vertex map :func:`map_to_pointwise`.

    Parameters
    ----------
    source, target : Mesh or (vertices, faces)
        Consistently oriented triangle meshes without duplicate or unreferenced vertices.
    N : int, default=100
        Final basis size (eigenpairs computed per mesh).
    N0 : int, default=30
        Size of the first functional map.
    n_descriptors : int, default=100
        WKS energies (Aubry et al.'s default grid); every ``DESCRIPTOR_STRIDE``-th is kept
        (20 descriptors, as pyFM).
    orientation : bool, default=True
        Use the orientation-preserving term (Ren et al. 2018): without it a left-right
        symmetric shape may be mapped onto its mirror image.
    zoomout_steps : bool or int, default=True
        ZoomOut from ``N0`` to ``N`` (an int: basis functions added per step; True: 1).
        False: the map of the size-``N0`` ``C``.
    landmarks : array_like of int, shape (L, 2), optional
        Known corresponding vertices ``(source vertex, target vertex)``.
    bijective : bool, default=False
        Bijective ZoomOut (see :func:`zoomout`).
    sample : int or None, default=3000
        Vertices per shape in the ZoomOut iterations (None: all; slower on big meshes).
    return_map : bool, default=False
        Also return ``C`` (``N x N``).
    random_state : int, default=0

    Returns
    -------
    p2p : ndarray of int64, shape (n_target,)
        ``p2p[y]`` is the source vertex matched to target vertex ``y`` (pyFM's ``p2p_21``).
    C : ndarray, shape (N, N)
        Only with ``return_map=True``.

    Examples
    --------
    >>> import numpy as np, cshape
    >>> mesh = cshape.shapes.icosphere(2)
    >>> p = cshape.point_map(mesh, mesh, N=20, N0=10)
    >>> p.shape
    (162,)
    """
    S = _check_mesh("source", source)
    T = _check_mesh("target", target)
    N = check_int("N", N, min=2)
    N0 = check_int("N0", N0, min=2, max=N)
    n_descriptors = check_int("n_descriptors", n_descriptors, min=int(4 * 7) + 1)
    orientation = check_bool("orientation", orientation)
    if isinstance(zoomout_steps, (bool, np.bool_)):
        step = 1 if zoomout_steps else 0
    else:
        step = check_int("zoomout_steps", zoomout_steps, min=1)
    bijective = check_bool("bijective", bijective)
    return_map = check_bool("return_map", return_map)
    lm = check_landmarks(landmarks, S.n_vertices, T.n_vertices)
    if N > min(S.n_vertices, T.n_vertices):
        raise ValueError(f"N={N} is more than the vertices of the smaller mesh "
                         f"({min(S.n_vertices, T.n_vertices)}); use a smaller N")
    bS, bT = eigenbasis(S, N), eigenbasis(T, N)
    dS, dT = _descriptors(bS, bT, n_descriptors, lm)
    C = functional_map(bS.truncate(N0), bT.truncate(N0), dS, dT,
                       orientation_weight=ORIENTATION_WEIGHT if orientation else 0.0)
    if step:
        C = zoomout(C, bS, bT, N, step=step, sample=sample, bijective=bijective,
                    random_state=random_state)
    p2p = map_to_pointwise(C, bS, bT)
    return (p2p, C) if return_map else p2p

