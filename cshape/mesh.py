"""Stage 1 of the pipeline: triangle meshes (container, validation, topology, repair).

A :class:`Mesh` is a thin, validated pair of plain arrays

* ``vertices`` : (n, 3) float64, positions in R^3,
* ``faces``    : (m, 3) int64, zero-based vertex indices of each triangle,

plus the topological facts the FEM stage needs (boundary and non-manifold edges,
connected components).  Every public function of cshape also accepts the pair
``(vertices, faces)``, or a mesh object of trimesh, PyVista, meshio, Open3D or PyMeshLab, in
place of a :class:`Mesh` (see :func:`as_mesh`).

Reading files (:func:`cshape.load_mesh` and its format checks) lives in :mod:`cshape.readers`,
the next module of the pipeline: it imports this one, never the reverse.
"""

from __future__ import annotations

import os
import warnings
from functools import cached_property
from typing import Any, TypeAlias

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike, NDArray
from scipy.sparse.csgraph import connected_components

from ._checks import check_bool, check_real
from ._meshlike import ACCEPTED, foreign_arrays, looks_like_mesh

__all__ = [
    "CShapeWarning",
    "Mesh",
    "MeshLike",
    "as_mesh",
    "repair_mesh",
    "largest_component",
]


class CShapeWarning(UserWarning):
    """Warning issued by cshape when it repairs or interprets an imperfect input."""


class Mesh:
    """A triangle mesh: vertex positions and triangles, validated on construction.

    Parameters
    ----------
    vertices : array_like, shape (n, 3)
        Vertex coordinates. Must be finite real numbers.
    faces : array_like, shape (m, 3)
        Zero-based vertex indices of each triangle; integers in ``[0, n)``.

    Raises
    ------
    TypeError
        If ``vertices`` is not a real array (complex, strings, ragged rows) or ``faces``
        not an integer array (bool, object, fractional floats).
    ValueError
        If an array has the wrong shape, a coordinate is NaN or infinite, or a face
        index is negative or out of range.  The message names the argument, the bad
        value and how to fix it.

    Notes
    -----
    The constructor only validates; it does not repair.  Degenerate faces, duplicate
    or unreferenced vertices are handled by :func:`repair_mesh` (which
    :func:`load_mesh` and the FEM stage call for you, with a warning).

    Examples
    --------
    >>> import numpy as np, cshape
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
    >>> F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    >>> m = cshape.Mesh(V, F)
    >>> m.n_vertices, m.n_faces, m.is_closed
    (4, 4, True)
    """

    vertices: NDArray[np.float64]
    faces: NDArray[np.int64]

    def __init__(self, vertices: ArrayLike, faces: ArrayLike) -> None:
        self.vertices = _check_vertices(vertices)
        self.faces = _check_faces(faces, len(self.vertices))
        self.vertices.setflags(write=False)
        self.faces.setflags(write=False)
        # set by repair_mesh on what it returns (merge_tol=0): then there is nothing to repair
        self._repaired = False

    # ------------------------------------------------------------------ sizes
    @property
    def n_vertices(self) -> int:
        """Number of vertices ``n``."""
        return int(self.vertices.shape[0])

    @property
    def n_faces(self) -> int:
        """Number of triangles ``m``."""
        return int(self.faces.shape[0])

    def __repr__(self) -> str:
        """Return the counts, area, components and defect edges of the mesh, on one line."""
        return (
            f"Mesh(n_vertices={self.n_vertices}, n_faces={self.n_faces}, "
            f"area={self.area:.6g}, components={self.n_components}, "
            f"boundary_edges={len(self.boundary_edges)}, "
            f"nonmanifold_edges={len(self.nonmanifold_edges)})"
        )

    # --------------------------------------------------------------- geometry
    @cached_property
    def face_areas(self) -> np.ndarray:
        """Area ``|t|`` of each triangle, shape (m,)."""
        p = self.vertices[self.faces]  # (m, 3, 3): one gather
        u = p[:, 1] - p[:, 0]
        v = p[:, 2] - p[:, 0]
        cross = np.empty_like(u)
        cross[:, 0] = u[:, 1] * v[:, 2] - u[:, 2] * v[:, 1]
        cross[:, 1] = u[:, 2] * v[:, 0] - u[:, 0] * v[:, 2]
        cross[:, 2] = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
        return 0.5 * _row_norms(cross)

    @cached_property
    def area(self) -> float:
        """Surface area, the sum of the triangle areas (used by the area normalisation)."""
        return float(self.face_areas.sum())

    @cached_property
    def mean_edge_length(self) -> float:
        """Mean length ``L`` of the (unique) edges."""
        if len(self.edges) == 0:  # pragma: no cover - a mesh has at least one triangle
            return 0.0
        return float(self._edge_lengths.mean())

    @cached_property
    def _edge_lengths(self) -> np.ndarray:
        """Length of each edge of :attr:`edges`, shape (e,) (shared with the FEM stage)."""
        e = self.edges
        return _row_norms(self.vertices[e[:, 0]] - self.vertices[e[:, 1]])

    # --------------------------------------------------------------- topology
    @cached_property
    def _edge_data(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Unique edges, the edge of each half-edge, and triangles per edge.

        Half-edges ``(f0, f1), (f1, f2), (f2, f0)`` of all faces, in that order, are keyed
        by the integer ``lo * n + hi`` of their sorted ends: one sort of 3m integers.
        """
        f = self.faces
        n = self.n_vertices
        a = np.concatenate([f[:, 0], f[:, 1], f[:, 2]])
        b = np.concatenate([f[:, 1], f[:, 2], f[:, 0]])
        key = np.minimum(a, b) * n + np.maximum(a, b)  # n**2 < 2**63 for n < 3e9
        order = np.argsort(key)  # the order among equal keys does not matter below
        skey = key[order]
        first = np.empty(len(skey), dtype=bool)
        first[:1] = True
        np.not_equal(skey[1:], skey[:-1], out=first[1:])
        ukey = skey[first]
        edges = np.stack([ukey // n, ukey % n], axis=1)
        inverse = np.empty(len(skey), dtype=np.int64)
        inverse[order] = np.cumsum(first) - 1
        counts = np.diff(np.append(np.flatnonzero(first), len(skey)))
        return edges, inverse, counts

    @property
    def edges(self) -> np.ndarray:
        """Unique undirected edges, shape (e, 2), each row sorted ascending."""
        return self._edge_data[0]

    @property
    def edge_face_counts(self) -> np.ndarray:
        """Number of triangles containing each edge of :attr:`edges`, shape (e,)."""
        return self._edge_data[2]

    @property
    def boundary_edges(self) -> np.ndarray:
        """Edges contained in exactly one triangle, shape (b, 2)."""
        return self.edges[self.edge_face_counts == 1]

    @property
    def nonmanifold_edges(self) -> np.ndarray:
        """Edges shared by three or more triangles, shape (k, 2)."""
        return self.edges[self.edge_face_counts > 2]

    @cached_property
    def boundary_vertices(self) -> np.ndarray:
        """Sorted indices of vertices on a boundary edge."""
        return np.unique(self.boundary_edges)

    @cached_property
    def n_boundary_loops(self) -> int:
        """Number of boundary loops: connected pieces of the boundary edges (0 if closed)."""
        b = self.boundary_edges
        if len(b) == 0:
            return 0
        n = self.n_vertices
        g = sp.coo_matrix((np.ones(len(b)), (b[:, 0], b[:, 1])), shape=(n, n))
        _, lab = connected_components(g, directed=False)
        return int(len(np.unique(lab[self.boundary_vertices])))

    @cached_property
    def nonmanifold_vertices(self) -> np.ndarray:
        """Sorted indices of non-manifold vertices.

        A vertex is non-manifold if it lies on a non-manifold edge, or if the triangles
        around it form more than one fan (a "bow-tie" vertex where two sheets touch).
        """
        on_edge = np.unique(self.nonmanifold_edges)
        return np.union1d(on_edge, self._bowtie_vertices)

    @cached_property
    def _bowtie_vertices(self) -> np.ndarray:
        f = self.faces
        m = len(f)
        if m == 0:
            return np.zeros(0, dtype=np.int64)
        # corners (face, local index) -> vertex; two corners at the same vertex are in one
        # fan when their triangles share an edge through that vertex.
        corner_v = f.reshape(-1)
        corner_id = np.arange(3 * m)
        nxt = np.roll(f, -1, axis=1).reshape(-1)
        prv = np.roll(f, 1, axis=1).reshape(-1)
        # key (v, w) for each of the two edges at the corner
        keys = np.concatenate([np.stack([corner_v, nxt], 1), np.stack([corner_v, prv], 1)])
        ids = np.concatenate([corner_id, corner_id])
        _, kinv = np.unique(keys, axis=0, return_inverse=True)
        kinv = kinv.reshape(-1)
        nk = kinv.max() + 1
        g = sp.coo_matrix((np.ones(len(ids)), (ids, kinv + 3 * m)), shape=(3 * m + nk, 3 * m + nk))
        _, lab = connected_components(g, directed=False)
        fans = np.unique(np.stack([corner_v, lab[: 3 * m]], 1), axis=0)
        nfans = np.bincount(fans[:, 0], minlength=self.n_vertices)
        return np.flatnonzero(nfans > 1)

    @cached_property
    def component_labels(self) -> np.ndarray:
        """Connected-component label of each vertex, shape (n,); isolated vertices get their own."""
        n = self.n_vertices
        f = self.faces
        rows = np.concatenate([f[:, 0], f[:, 1], f[:, 2]])
        cols = np.concatenate([f[:, 1], f[:, 2], f[:, 0]])
        g = sp.coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n))
        _, lab = connected_components(g, directed=False)
        return lab

    @property
    def n_components(self) -> int:
        """Number of connected components of the referenced vertices (edge-connected)."""
        used = np.zeros(self.n_vertices, bool)
        used[self.faces.reshape(-1)] = True
        return int(len(np.unique(self.component_labels[used])))

    @property
    def unreferenced_vertices(self) -> np.ndarray:
        """Indices of vertices used by no triangle."""
        used = np.zeros(self.n_vertices, bool)
        used[self.faces.reshape(-1)] = True
        return np.flatnonzero(~used)

    @property
    def is_closed(self) -> bool:
        """True when every edge has exactly two triangles (no boundary, no non-manifold edge)."""
        return bool(self.n_faces > 0 and np.all(self.edge_face_counts == 2))

    @property
    def euler_characteristic(self) -> int:
        """``V - E + F`` over the referenced vertices."""
        nv = self.n_vertices - len(self.unreferenced_vertices)
        return int(nv - len(self.edges) + self.n_faces)

    @property
    def genus(self) -> int | None:
        """Genus of a closed, connected, manifold mesh; ``None`` otherwise."""
        if not self.is_closed or self.n_components != 1 or len(self.nonmanifold_vertices):
            return None
        return int((2 - self.euler_characteristic) // 2)


def _row_norms(x: np.ndarray) -> np.ndarray:
    """Return the Euclidean norms of the rows of an (k, 3) array, without squaring's overflow.

    Nor its underflow: meshes in units of 1e-100 or 1e100 keep finite, non-zero lengths and
    areas.
    """
    sq = np.einsum("ij,ij->i", x, x)
    out = np.sqrt(sq)
    # squares within (1e-290, 1e290) neither overflow nor lose digits to underflow (a
    # component too small to square exactly is below eps of the largest one); the rest,
    # zero rows included, take the slower hypot
    bad = ~((sq > 1e-290) & (sq < 1e290))
    if bad.any():
        y = x[bad]
        out[bad] = np.hypot(np.hypot(y[:, 0], y[:, 1]), y[:, 2])
    return out


#: A mesh argument: a :class:`Mesh`, a ``(vertices, faces)`` pair of arrays, or a mesh object
#: of trimesh, PyVista, meshio, Open3D or PyMeshLab (read by :func:`as_mesh`; typed ``Any``).
MeshLike: TypeAlias = Mesh | tuple[ArrayLike, ArrayLike] | Any


# ---------------------------------------------------------------------- validation
def _check_vertices(vertices: Any) -> NDArray[np.float64]:
    try:
        is_complex = np.iscomplexobj(vertices)
        # a copy: the Mesh freezes its arrays, which must not freeze the caller's
        v = (np.empty((0, 3)) if is_complex
             else np.array(vertices, dtype=np.float64, copy=True))
    except (TypeError, ValueError) as exc:
        raise TypeError(
            "vertices must be a real array of shape (n, 3); "
            f"could not convert it to float64 ({exc})"
        ) from None
    if is_complex:
        raise TypeError(
            "vertices must be real coordinates, got a complex array; pass vertices.real if "
            "the imaginary parts are zero"
        )
    if v.ndim != 2 or v.shape[1] != 3:
        raise ValueError(
            f"vertices must have shape (n, 3), got {v.shape}; pass one row of x, y, z per vertex"
        )
    if v.shape[0] == 0:
        raise ValueError("vertices is empty: a mesh needs at least 3 vertices")
    bad = ~np.isfinite(v).all(axis=1)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(
            f"vertices contain NaN or infinite coordinates ({int(bad.sum())} vertices, first at "
            f"index {i}: {v[i].tolist()}); remove or fix those vertices before building the mesh"
        )
    return np.ascontiguousarray(v)


def _check_faces(faces: Any, n_vertices: int) -> NDArray[np.int64]:
    try:
        f0 = np.asarray(faces)
    except (TypeError, ValueError):
        raise TypeError(
            "faces must be an integer array of shape (m, 3); got a ragged sequence (rows of "
            "different lengths?); triangulate polygons first"
        ) from None
    if f0.dtype.kind == "f":
        if f0.size and not np.all(np.isfinite(f0) & (f0 == np.round(f0))):
            raise TypeError("faces must hold integer vertex indices; got non-integer floats")
    elif f0.dtype.kind not in "iu" and f0.size:
        raise TypeError(f"faces must be an integer array of shape (m, 3), got dtype {f0.dtype}")
    if f0.size and f0.dtype.kind in "fu" and (
        float(f0.max()) >= n_vertices or float(f0.min()) < 0
    ):
        # check before the cast to int64, which would wrap huge indices
        bad = (f0.max() if float(f0.max()) >= n_vertices else f0.min()).item()
        raise ValueError(
            f"faces reference vertex index {bad!r}, outside [0, {n_vertices - 1}]; "
            "indices are zero-based and must be smaller than the number of vertices"
        )
    f = np.array(f0, dtype=np.int64, copy=True) if f0.size else np.zeros((0, 3), np.int64)
    if f.ndim != 2 or f.shape[1] != 3:
        raise ValueError(
            f"faces must have shape (m, 3) (triangles), got {f0.shape}; triangulate polygons "
            "first, e.g. with cshape.load_mesh which does it for you"
        )
    if f.shape[0] == 0:
        raise ValueError("faces is empty: a mesh needs at least one triangle")
    lo, hi = int(f.min()), int(f.max())
    if lo < 0 or hi >= n_vertices:
        bad = int(np.flatnonzero(((f < 0) | (f >= n_vertices)).any(axis=1))[0])
        raise ValueError(
            f"faces reference vertex indices outside [0, {n_vertices - 1}] (face {bad} is "
            f"{f[bad].tolist()}); indices are zero-based and must be smaller than the number "
            "of vertices"
        )
    return np.ascontiguousarray(f)


def as_mesh(mesh_or_vf: MeshLike) -> Mesh:
    """Return a :class:`Mesh` from any accepted mesh argument: the one entry point.

    Parameters
    ----------
    mesh_or_vf : Mesh, tuple of (array_like (n, 3), array_like (m, 3)), or a mesh object
        A mesh object of trimesh (``Trimesh``), PyVista (``PolyData`` of triangles), meshio
        (``Mesh`` with ``'triangle'`` cells), Open3D (``TriangleMesh``) or PyMeshLab
        (``Mesh``, or the current mesh of a ``MeshSet``) is read by its attributes, without
        importing its library (see :mod:`cshape._meshlike`); its arrays are copied.

    Returns
    -------
    Mesh
        ``mesh_or_vf`` itself when it is a :class:`Mesh`.

    Raises
    ------
    TypeError
        If the argument is none of these (a path, an array, ...).
    ValueError
        If a library's mesh object holds polygons or no triangles, or its arrays are not a
        valid mesh (see :class:`Mesh`).

    Examples
    --------
    >>> import numpy as np, cshape
    >>> class PolyData:  # PyVista's layout: points and a flat VTK cell array
    ...     points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
    ...     faces = np.array([3, 0, 2, 1, 3, 0, 1, 3, 3, 0, 3, 2, 3, 1, 2, 3])
    >>> cshape.mesh.as_mesh(PolyData()).n_faces
    4
    """
    if isinstance(mesh_or_vf, Mesh):
        return mesh_or_vf
    if isinstance(mesh_or_vf, (tuple, list)) and len(mesh_or_vf) == 2:
        return Mesh(*mesh_or_vf)
    if isinstance(mesh_or_vf, (str, os.PathLike)):
        raise TypeError(
            f"got a path ({mesh_or_vf!r}) where a mesh was expected; load it first with "
            "cshape.load_mesh(path)"
        )
    arrays = foreign_arrays(mesh_or_vf)
    if arrays is not None:
        return Mesh(*arrays)
    t = type(mesh_or_vf)
    name = t.__name__ if t.__module__ == "builtins" else f"{t.__module__}.{t.__name__}"
    raise TypeError(f"expected a mesh: {ACCEPTED}; got {name}")


def is_mesh_like(obj: object) -> bool:
    """Whether ``obj`` is a mesh argument that :func:`as_mesh` reads (not checked further).

    True for a :class:`Mesh`, a pair whose first entry is 2-D (vertices), and a mesh object
    of the libraries :func:`as_mesh` names.
    """
    return (isinstance(obj, Mesh)
            or (isinstance(obj, (tuple, list)) and len(obj) == 2 and np.ndim(obj[0]) == 2)
            or looks_like_mesh(obj))


# ---------------------------------------------------------------------- repair
def repair_mesh(mesh: MeshLike, *, merge_tol: float = 0.0, warn: bool = True) -> Mesh:
    """Return a cleaned copy of a mesh; what changed is reported in one warning.

    The repairs, in order:

    1. vertices at identical positions (or, with ``merge_tol > 0``, chained by distances of
       at most ``merge_tol`` times the bounding-box diagonal) are welded into one, at the
       position of the first, as in STL triangle soup;
    2. faces that repeat a vertex index (collapsed to a segment or point) are removed;
    3. duplicate faces (the same three vertices, in any order) are reduced to one;
    4. unreferenced vertices are removed and the faces re-indexed.

    Geometrically degenerate faces with three distinct vertices (zero area, as left by
    marching cubes) are *kept*: the FEM stage handles them (see
    :func:`cshape.fem.fem_matrices`), because removing them would cut the surface.

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        The mesh to repair.
    merge_tol : float, default=0.0
        Relative welding tolerance; 0 welds only exactly coincident vertices.
    warn : bool, default=True
        Issue a :class:`CShapeWarning` describing the repairs, if any.

    Returns
    -------
    Mesh
        The repaired mesh (the input itself when nothing needed repair).  The result is
        marked as repaired, so that repairing it again (``merge_tol=0``) returns it at once:
        a mesh read, repaired and solved is repaired once.

    Raises
    ------
    TypeError
        ``merge_tol`` not a real number, ``warn`` not a bool, ``mesh`` not a mesh.
    ValueError
        ``merge_tol`` negative or not finite; no triangle left after the repair.
    """
    merge_tol = check_real("merge_tol", merge_tol, min=0)
    warn = check_bool("warn", warn)
    mesh = as_mesh(mesh)
    if merge_tol == 0 and getattr(mesh, "_repaired", False):
        return mesh
    V = mesh.vertices
    F = mesh.faces
    notes = []
    # 1. weld coincident vertices
    if merge_tol > 0:
        # clusters of vertices chained by distances <= tol (a grid snap would miss close
        # pairs on either side of a cell boundary)
        from scipy.spatial import cKDTree

        diag = float(_row_norms((V.max(0) - V.min(0))[None])[0]) or 1.0
        pairs = cKDTree(V).query_pairs(merge_tol * diag, output_type="ndarray")
        n = len(V)
        g = sp.coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
        _, key = connected_components(g, directed=False)
        _, first, inv = np.unique(key, return_index=True, return_inverse=True)
    elif _all_rows_distinct(V):  # the common case: no np.unique over rows
        first = inv = np.arange(len(V))
    else:
        _, first, inv = np.unique(V, axis=0, return_index=True, return_inverse=True)
    inv = inv.reshape(-1)
    if len(first) < len(V):
        notes.append(f"welded {len(V) - len(first)} duplicate vertices")
        # keep the vertex order of first occurrence
        order = np.argsort(first)
        rank = np.empty_like(order)
        rank[order] = np.arange(len(order))
        V = V[first[order]]
        F = rank[inv][F]
    # 2. faces with a repeated index
    degenerate = (F[:, 0] == F[:, 1]) | (F[:, 1] == F[:, 2]) | (F[:, 2] == F[:, 0])
    if degenerate.any():
        notes.append(f"removed {int(degenerate.sum())} faces with a repeated vertex")
        F = F[~degenerate]
    # 3. duplicate faces
    if len(F) and not _all_rows_distinct(np.sort(F, axis=1)):
        _, keep = np.unique(np.sort(F, axis=1), axis=0, return_index=True)
        if len(keep) < len(F):
            notes.append(f"removed {len(F) - len(keep)} duplicate faces")
            F = F[np.sort(keep)]
    if len(F) == 0:
        raise ValueError(
            "the mesh has no valid triangle left after removing degenerate faces; "
            "check that the faces reference three distinct vertices"
        )
    # 4. unreferenced vertices
    used = np.zeros(len(V), bool)
    used[F.reshape(-1)] = True
    if not used.all():
        notes.append(f"removed {int((~used).sum())} unreferenced vertices")
        new = np.cumsum(used) - 1
        V = V[used]
        F = new[F]
    if not notes:
        mesh._repaired = True
        return mesh
    if warn:
        warnings.warn("repaired mesh: " + "; ".join(notes), CShapeWarning, stacklevel=2)
    out = Mesh(V, F)
    out._repaired = True  # welding, then dropping faces and vertices: nothing left to repair
    return out


def _mix64(z: np.ndarray) -> np.ndarray:
    """SplitMix64's finaliser: a bijection of uint64 that scatters every input bit."""
    with np.errstate(over="ignore"):
        z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
        z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return z ^ (z >> np.uint64(31))


def _all_rows_distinct(X: np.ndarray) -> bool:
    """Whether no two rows of an (k, 3) array are equal: one sort of a 64-bit row hash.

    Equal rows have equal hashes, so distinct hashes prove distinct rows; only if two
    hashes collide are the rows compared exactly (a lexicographic sort).  Floats get
    ``+ 0.0`` first so that ``-0.0`` and ``0.0`` (equal values) hash alike.
    """
    if len(X) < 2:
        return True
    if X.dtype.kind == "f":
        bits = np.ascontiguousarray(X + 0.0).view(np.uint64)
    else:
        bits = np.ascontiguousarray(X, dtype=np.int64).view(np.uint64)
    h = _mix64(_mix64(_mix64(bits[:, 0]) ^ bits[:, 1]) ^ bits[:, 2])
    h.sort()
    if not (h[1:] == h[:-1]).any():
        return True
    order = np.lexsort(X.T[::-1])
    Xs = X[order]
    return bool(np.any(Xs[1:] != Xs[:-1], axis=1).all())


def largest_component(mesh: MeshLike) -> Mesh:
    """Return the connected component with the largest surface area.

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        The mesh, of one component or more.

    Returns
    -------
    Mesh
        The component, with unreferenced vertices removed.
    """
    mesh = as_mesh(mesh)
    lab = mesh.component_labels[mesh.faces[:, 0]]
    per = np.bincount(lab, weights=mesh.face_areas)
    keep = lab == int(np.argmax(per))
    return repair_mesh(Mesh(mesh.vertices, mesh.faces[keep]), warn=False)
