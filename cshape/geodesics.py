"""Geodesic distances on a triangle mesh by the heat method, and the errors of a vertex map.

==========================  =================================================================
function                    what it does
==========================  =================================================================
:func:`geodesic_distance`   geodesic distance from a set of vertices to every vertex (Crane,
                            Weischedel and Wardetzky 2013)
:class:`HeatGeodesics`      the same, factorised once for many sources
:func:`geodesic_errors`     geodesic distance between a map's images and the true ones
:func:`face_gradients`      the per-triangle gradient operator ``G`` (``A = -G^T |t| G``)
==========================  =================================================================

A mesh of several pieces: a vertex that no path on the surface joins to the sources is at
distance ``inf`` (the distance between two points of different pieces is infinite), and so is
the error of a map that sends a vertex onto another piece than its true image.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import ArrayLike, NDArray

from ._checks import check_real, check_vertex_indices
from .fem import fem_matrices
from .mesh import Mesh, MeshLike, as_mesh, repair_mesh

__all__ = [
    "HeatGeodesics",
    "geodesic_distance",
    "geodesic_errors",
]


def _check_mesh(name: str, mesh: MeshLike) -> Mesh:
    """Return a mesh that the FEM stage will not renumber (no repair needed), or raise."""
    try:
        m = as_mesh(mesh)
    except TypeError as exc:
        raise TypeError(f"{name}: {exc}") from None
    fixed = repair_mesh(m, warn=False)
    if fixed.n_vertices != m.n_vertices:
        raise ValueError(
            f"{name} has {m.n_vertices - fixed.n_vertices} duplicate or unreferenced vertices, "
            "so its functions would not have one value per vertex; call "
            f"cshape.repair_mesh({name}) first and use the repaired mesh"
        )
    return m


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
        The surface.

    Returns
    -------
    G : scipy.sparse.csr_matrix, shape (3 F, n)
        ``(G f)[3 t + c]`` is component ``c`` of the gradient of ``f`` on triangle ``t``.
    areas : ndarray, shape (F,)
        Triangle areas ``|t|``.
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
    On a mesh of several pieces (:attr:`cshape.Mesh.component_labels`), the vertices of the
    pieces that hold no source are at distance ``inf``.

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        Without duplicate or unreferenced vertices (:func:`cshape.repair_mesh`).
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
        self._pieces = self.mesh.component_labels
        # -A is singular (constants on each piece): a tiny mass shift fixes the constants
        # without moving the gradient; the distances are shifted to 0 at the sources
        shift = 1e-10 * self._K.diagonal().mean() / B.diagonal().mean()
        self._poisson = spla.splu((self._K + shift * B).tocsc())

    def distances(self, sources: ArrayLike) -> NDArray[np.float64]:
        """One distance field per source vertex.

        Parameters
        ----------
        sources : array_like of int, shape (s,)
            Vertex indices, one distance field each.

        Returns
        -------
        ndarray, shape (n, s)
            Column ``j``: the geodesic distance from ``sources[j]`` to every vertex; ``inf``
            on the pieces of the mesh other than the one of ``sources[j]``.
        """
        n = self.mesh.n_vertices
        src = check_vertex_indices("sources", sources, n)
        rhs = np.zeros((n, len(src)))
        rhs[src, np.arange(len(src))] = 1.0
        b = self._divergence(self._heat.solve(self._B @ rhs))
        phi = self._poisson.solve(b)
        phi -= phi[src, np.arange(len(src))]
        phi = np.maximum(phi, 0.0)
        phi[self._pieces[:, None] != self._pieces[src][None, :]] = np.inf
        return phi

    def distance(self, sources: ArrayLike) -> NDArray[np.float64]:
        """Geodesic distance to the nearest of a set of vertices.

        Parameters
        ----------
        sources : int or array_like of int, shape (s,)
            Vertex indices; the distance is to the nearest of them.

        Returns
        -------
        ndarray, shape (n,)
            0 at the sources; ``inf`` on the pieces of the mesh that hold no source.
        """
        n = self.mesh.n_vertices
        src = check_vertex_indices("sources", sources, n)
        if src.size == 0:
            raise ValueError("sources is empty; pass at least one vertex index")
        src = np.unique(src)
        if len(src) == 1:
            return self.distances(src)[:, 0]
        # several sources: the Poisson problem with phi = 0 at every source (Dirichlet),
        # so that no source is left at the error of another one; on the pieces that hold a
        # source only (elsewhere -A has no Dirichlet vertex and is singular)
        rhs = np.zeros((n, 1))
        rhs[src, 0] = 1.0
        b = self._divergence(self._heat.solve(self._B @ rhs))[:, 0]
        reached = np.isin(self._pieces, self._pieces[src])
        free = np.flatnonzero(reached)
        free = np.setdiff1d(free, src)
        phi = np.full(n, np.inf)
        phi[src] = 0.0
        if len(free):
            phi[free] = np.maximum(spla.spsolve(self._K[free][:, free].tocsc(), b[free]), 0.0)
        return phi

    def _divergence(self, u):
        """``G^T diag(|t|) X`` of the normalised field ``X = -grad u / |grad u|``."""
        nF = len(self.areas)
        g = (self.G @ u).reshape(nF, 3, -1)
        norm = np.linalg.norm(g, axis=1, keepdims=True)
        X = -g / np.where(norm > 0, norm, 1.0)
        return self.G.T @ (X * self.areas[:, None, None]).reshape(3 * nF, -1)


def geodesic_distance(mesh: MeshLike, sources: ArrayLike, *, m: float = 1.0
                      ) -> NDArray[np.float64]:
    """Geodesic distance from a set of vertices to every vertex, by the heat method.

    The one-call form of :class:`HeatGeodesics` (Crane et al. 2013): use the class to reuse
    its factorisations for many sources.

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        The surface, without duplicate or unreferenced vertices (:func:`cshape.repair_mesh`).
    sources : int or array_like of int, shape (s,)
        Vertex indices; the distance is to the nearest of them.
    m : float, default=1.0
        Heat time ``t = m h^2`` (``h`` the mean edge length).

    Returns
    -------
    ndarray, shape (n,)
        In the mesh's length units; 0 at the sources, ``inf`` on the pieces of the mesh that
        hold no source (no path on the surface reaches them).

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
        For each target vertex, a source vertex (:func:`cshape.point_map`).
    truth : array_like of int, shape (n_T,), optional
        The true map; default the identity (shapes that share their vertices).
    vertices : array_like of int, shape (s,), optional
        The target vertices to evaluate (one heat solve each); default all.
    geodesics : HeatGeodesics, optional
        Of ``mesh``, to reuse its factorisations.

    Returns
    -------
    ndarray, shape (s,)
        ``inf`` where the image lies on another piece of the mesh than the true vertex (no
        path joins them), so that a mean over such a map is ``inf``, not a finite number.
    """
    if geodesics is not None and not isinstance(geodesics, HeatGeodesics):
        raise TypeError("geodesics must be a cshape.geodesics.HeatGeodesics of mesh, got "
                        f"{type(geodesics).__name__}")
    geo = geodesics if geodesics is not None else HeatGeodesics(mesh)
    n = geo.mesh.n_vertices
    if geodesics is not None:
        other = as_mesh(mesh)
        if other.n_vertices != n:
            raise ValueError(f"geodesics is of a mesh of {n} vertices but mesh has "
                             f"{other.n_vertices}; pass cshape.geodesics.HeatGeodesics(mesh)")
    p2p = check_vertex_indices("p2p", p2p, n)
    truth = np.arange(len(p2p)) if truth is None else check_vertex_indices("truth", truth, n)
    if len(truth) != len(p2p):
        raise ValueError(f"truth has {len(truth)} entries and p2p {len(p2p)}; both have one "
                         "source vertex per target vertex")
    v = (np.arange(len(p2p)) if vertices is None
         else check_vertex_indices("vertices", vertices, len(p2p)))
    out = np.empty(len(v))
    for s in range(0, len(v), 64):
        block = v[s:s + 64]
        D = geo.distances(truth[block])
        out[s:s + 64] = D[p2p[block], np.arange(len(block))]
    return out
