"""Stage 2 of the pipeline: linear finite elements, the matrices ``A`` and ``B`` of Eq. (3)-(7).

Sign convention (the paper's)
-----------------------------
``A`` is the cotangent *stiffness* matrix with the paper's sign: off-diagonal entries
``+(cot alpha + cot beta)/2`` and a diagonal that makes every row sum to zero, so ``A`` is
symmetric **negative** semidefinite and the generalised eigenproblem reads

    A f = -lam B f,        lam >= 0.                                   (Eq. 3)

``B`` is the consistent mass matrix (or, optionally, the lumped one, or their average, the
mixed one), symmetric positive definite, whose entries add up to the surface area.

A note on the paper's printed Eq. (5) and (7): the diagonal of the consistent mass matrix
is ``+sum_t |t| / 6`` over the triangles ``t`` at vertex ``i`` (which equals
``+sum_k b_ik``); the minus signs printed there are a typo, since ``B`` must be positive
definite.  cshape implements the standard linear-FEM mass matrix.
"""

from __future__ import annotations

import warnings

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from ._checks import check_bool, check_choice
from .mesh import CShapeWarning, Mesh, MeshLike, as_mesh, repair_mesh

__all__ = ["fem_matrices"]

BOUNDARY_CONDITIONS = ("neumann", "dirichlet")
MASS_TYPES = ("consistent", "lumped", "mixed")

#: Relative size (times the mean edge length) below which a triangle's triangle-inequality
#: margin counts as degenerate and intrinsic mollification switches on.
MOLLIFY_DELTA = 1e-6

#: A mesh whose area is below this fraction of ``n_faces * mean_edge**2`` has zero area (all
#: triangles degenerate): it is refused rather than mollified into an invented surface.
ZERO_AREA_RTOL = 1e-10


class _FEMProblem:
    """Assembled FEM matrices of a mesh, with the bookkeeping of the unknowns.

    Private: the public way to get ``A`` and ``B`` is :func:`fem_matrices`.

    Attributes
    ----------
    A : scipy.sparse.csr_matrix, shape (k, k)
        Stiffness matrix, negative semidefinite (Eq. 4 / 6).
    B : scipy.sparse.csr_matrix, shape (k, k)
        Mass matrix, positive definite (Eq. 5 / 7, lumped or mixed).
    free : ndarray of int, shape (k,)
        Mesh vertex index of each unknown (all vertices for Neumann; the inner manifold
        vertices for Dirichlet).
    n_vertices : int
        Number of mesh vertices ``n``.
    area : float
        Surface area of the mesh.
    bc : {'neumann', 'dirichlet'}
    mollified : float
        The intrinsic-mollification length added to every edge (0 unless the mesh has
        zero-area triangles).
    B_vertices : scipy.sparse.csr_matrix, shape (n, n)
        The mass matrix over all mesh vertices (``B`` itself for Neumann): the inner
        product of functions on the vertices.
    """

    def __init__(self, A: sp.csr_matrix, B: sp.csr_matrix, free: NDArray[np.int64],
                 n_vertices: int, area: float, bc: str, mollified: float,
                 B_vertices: sp.csr_matrix | None = None) -> None:
        self.A = A
        self.B = B
        self.B_vertices = B if B_vertices is None else B_vertices
        self.free = free
        self.n_vertices = n_vertices
        self.area = area
        self.bc = bc
        self.mollified = mollified

    @property
    def n_unknowns(self) -> int:
        """Number of unknowns ``k`` (rows of A and B)."""
        return int(self.A.shape[0])

    def to_vertices(self, f: NDArray[np.float64]) -> NDArray[np.float64]:
        """Extend functions on the unknowns, (k,) or (k, p), to all n vertices (0 elsewhere)."""
        f = np.asarray(f)
        out = np.zeros((self.n_vertices,) + f.shape[1:], dtype=f.dtype)
        out[self.free] = f
        return out


def _edge_lengths(mesh: Mesh) -> NDArray[np.float64]:
    """Lengths (m, 3): column c is the length of the edge opposite corner c.

    Read from the mesh's unique edge lengths (computed once for ``mean_edge_length``):
    half-edge blocks ``(f0, f1), (f1, f2), (f2, f0)`` lie opposite corners 2, 0, 1.
    """
    m = mesh.n_faces
    per_half = mesh._edge_lengths[mesh._edge_data[1]].reshape(3, m)
    return np.stack([per_half[1], per_half[2], per_half[0]], axis=1)


def _heron(lengths: np.ndarray) -> np.ndarray:
    """Triangle areas from edge lengths with Kahan's stable form of Heron's formula."""
    l0, l1, l2 = lengths[:, 0], lengths[:, 1], lengths[:, 2]
    a = np.maximum(np.maximum(l0, l1), l2)  # a >= b >= c, without a row-wise sort
    c = np.minimum(np.minimum(l0, l1), l2)
    b = np.maximum(np.minimum(l0, l1), np.minimum(np.maximum(l0, l1), l2))
    prod = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c))
    return 0.25 * np.sqrt(np.maximum(prod, 0.0))


def _edge_csr(edges: np.ndarray, n: int
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """CSR structure of the symmetric matrices on a mesh's edges, for filling A and B.

    Parameters
    ----------
    edges : ndarray of int, shape (e, 2)
        Unique edges ``i < j`` sorted by ``(i, j)`` (:attr:`cshape.Mesh.edges`).
    n : int

    Returns
    -------
    indptr, indices : ndarray
        Sorted CSR pattern of the ``2e + n`` entries (both triangles and the diagonal).
    upper, lower, diag : ndarray of int, shapes (e,), (e,), (n,)
        Position in ``indices`` of entry ``(i, j)`` and ``(j, i)`` of each edge and of
        ``(v, v)``: ``data[upper] = w`` etc. fills a matrix without any sort.
    """
    i, j = edges[:, 0], edges[:, 1]
    n_lower = np.bincount(j, minlength=n)  # entries left of the diagonal in each row
    n_upper = np.bincount(i, minlength=n)
    indptr = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(n_lower + n_upper + 1, out=indptr[1:])
    diag = indptr[:-1] + n_lower
    # upper entries come sorted by (row i, column j): rank within the row from its start
    row_start = np.cumsum(n_upper) - n_upper
    upper = diag[i] + 1 + (np.arange(len(i)) - row_start[i])
    # lower entries (row j, column i): a stable sort by j keeps the columns i ascending
    order = np.argsort(j, kind="stable")
    row_start = np.cumsum(n_lower) - n_lower
    lower = np.empty(len(j), dtype=np.int64)
    lower[order] = indptr[j[order]] + (np.arange(len(j)) - row_start[j[order]])
    indices = np.empty(indptr[-1], dtype=np.int64)
    indices[upper] = j
    indices[lower] = i
    indices[diag] = np.arange(n)
    if indptr[-1] < 2**31:
        indptr, indices = indptr.astype(np.int32), indices.astype(np.int32)
    return indptr, indices, upper, lower, diag


def _mollify(lengths: np.ndarray, mean_edge: float) -> tuple[float, int]:
    """Return the intrinsic mollification eps (Sharp & Crane 2020).

    The smallest eps >= 0 added to every edge length so that each triangle satisfies the
    triangle inequality with margin delta.
    """
    delta = MOLLIFY_DELTA * mean_edge
    l0, l1, l2 = lengths[:, 0], lengths[:, 1], lengths[:, 2]
    margin = np.minimum(np.minimum(l1 + l2 - l0, l2 + l0 - l1), l0 + l1 - l2)
    eps = float(max(0.0, np.max(delta - margin)))
    return eps, int(np.count_nonzero(margin < delta))


#: Largest ratio of the longest to the shortest edge: areas and FEM entries go as length^2
#: and float64 spans about 1e-308 .. 1e308, so beyond this no unit keeps both representable.
MAX_EDGE_RATIO = 1e150


def _check_positive_area(mesh: Mesh) -> None:
    """Raise if the surface has (numerically) zero area, which mollification would invent.

    The message tells the causes apart: coordinates too large for float64 (rescale),
    edge lengths spread too far for float64 or a far-out vertex making needle triangles
    (a misplaced vertex, named), and truly coincident or collinear vertices.
    """
    L = mesh.mean_edge_length
    area = mesh.area
    finite = bool(np.isfinite(area) and np.isfinite(L * L))
    if finite and area > ZERO_AREA_RTOL * mesh.n_faces * L * L:
        return
    lengths = mesh._edge_lengths
    positive = lengths[lengths > 0]
    lo = float(positive.min()) if len(positive) else 0.0
    hi = float(lengths.max())
    ratio = hi / lo if lo > 0 else 0.0
    V = mesh.vertices
    k = int(np.argmax(np.abs(V - np.median(V, axis=0)).max(axis=1)))
    far_out = (f"vertex {k} at {V[k].tolist()} lies farthest from the others and is probably "
               "misplaced: fix or remove it")
    if ratio > MAX_EDGE_RATIO:
        raise ValueError(
            f"the edge lengths range from {lo:.3g} to {hi:.3g}, a ratio beyond "
            f"{MAX_EDGE_RATIO:.0e}: their squares (triangle areas, FEM entries) over- or "
            f"underflow float64 in any unit, so no spectrum can be computed; {far_out}"
        )
    if not finite:
        raise ValueError(
            f"the surface area overflows float64 (area={area:.3g}, mean edge length "
            f"{L:.3g}): the coordinates are too large; rescale the mesh, e.g. "
            f"Mesh(vertices / {L:.0e}, faces) (the area normalisation makes the descriptor "
            "scale invariant)"
        )
    if ratio > 1e6:
        raise ValueError(
            f"the mesh is made of needle triangles: its area {area:.3g} is only "
            f"{area / (mesh.n_faces * L * L):.1e} of (triangles x mean edge length^2), with "
            f"edge lengths from {lo:.3g} to {hi:.3g}, too thin for a stable spectrum; "
            f"{far_out}"
        )
    raise ValueError(
        f"the mesh has zero surface area (area={area:.3g}, {mesh.n_faces} triangles, "
        f"mean edge length {L:.3g}): its vertices are coincident or collinear (or too "
        "close together for float64), so it has no Laplace-Beltrami spectrum; check the "
        "vertex coordinates (all zero? one axis only?)"
    )


def _assemble(mesh: MeshLike, mass: str = "consistent"
             ) -> tuple[sp.csr_matrix, sp.csr_matrix, float, int]:
    """Assemble the full (Neumann) matrices ``A`` and ``B`` over all vertices.

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
    mass : {'consistent', 'lumped', 'mixed'}, default='consistent'

    Raises
    ------
    ValueError
        If the mesh has zero total area (all vertices coincident or collinear).

    Returns
    -------
    A : scipy.sparse.csr_matrix, shape (n, n)
        Eq. (4) for closed meshes, Eq. (6) with boundary or non-manifold edges.
    B : scipy.sparse.csr_matrix, shape (n, n)
        Eq. (5) / (7), the row-sum lumped diagonal ``sum_t |t| / 3``, or their average.
    eps : float
        The mollification length added to all edges (0 for meshes without degenerate triangles).
    n_degenerate : int
        Number of triangles whose triangle-inequality margin was below the threshold.
    """
    mesh = as_mesh(mesh)
    mass = check_choice("mass", mass, MASS_TYPES)
    _check_positive_area(mesh)
    F = mesh.faces
    n = mesh.n_vertices
    # lengths in units of the mean edge: Heron's product of four lengths and the squares
    # below stay finite for any coordinate scale; cotangents do not depend on the unit
    unit = mesh.mean_edge_length
    L = _edge_lengths(mesh) / unit
    eps, n_degenerate = _mollify(L, 1.0)
    if eps > 0:
        L = L + eps
    area_u = _heron(L)  # (m,), in units of unit**2
    sq = L * L
    # cot of the angle at corner c: (l_a^2 + l_b^2 - l_c^2) / (4 |t|)
    cot = (sq.sum(axis=1, keepdims=True) - 2.0 * sq) / (4.0 * area_u[:, None])
    eps *= unit
    area = area_u * unit * unit
    if not np.all(np.isfinite(area)):
        raise ValueError(
            f"the triangle areas overflow (mean edge length {unit:.3g}): the coordinates are "
            "too large for float64; rescale the mesh (the area normalisation makes the "
            "descriptor scale invariant)"
        )
    # Sum per unique edge over its triangles (half-edge blocks (f0, f1), (f1, f2), (f2, f0)
    # lie opposite corners 2, 0, 1), then fill a CSR pattern built without sorting.
    edges, half_to_edge, _ = mesh._edge_data
    ne = len(edges)
    w = 0.5 * np.concatenate([cot[:, 2], cot[:, 0], cot[:, 1]])
    a3 = np.concatenate([area, area, area])
    w_edge = np.bincount(half_to_edge, weights=w, minlength=ne)
    loop = edges[:, 0] == edges[:, 1]  # only in unrepaired meshes (a repeated index)
    if loop.any():
        b_loop = np.bincount(edges[loop, 0], weights=np.bincount(
            half_to_edge, weights=a3, minlength=ne)[loop] / 6.0, minlength=n)
        edges, w_edge = edges[~loop], w_edge[~loop]
        half_to_edge = np.cumsum(~loop)[half_to_edge] - 1
        keep_half = ~loop[mesh._edge_data[1]]
    indptr, indices, upper, lower, diag = _edge_csr(edges, n)
    # Eq. (4)/(6): off-diagonal sum of cot/2 over the opposite angles; zero row sums.
    data = np.empty(len(indices))
    data[upper] = w_edge
    data[lower] = w_edge
    data[diag] = -(np.bincount(edges[:, 0], weights=w_edge, minlength=n)
                   + np.bincount(edges[:, 1], weights=w_edge, minlength=n))
    A = sp.csr_matrix((data, indices, indptr), shape=(n, n))
    if mass != "lumped":
        # Eq. (5)/(7): off-diagonal sum |t|/12 over the triangles at the edge; diagonal
        # sum |t|/6 over the triangles at the vertex.  Mixed: the average of that and the
        # lumped diagonal sum |t|/3, i.e. |t|/24 off the diagonal and |t|/4 on it.
        if loop.any():
            b_edge = np.bincount(half_to_edge[keep_half], weights=a3[keep_half] / 12.0,
                                 minlength=len(edges))
        else:
            b_edge = np.bincount(half_to_edge, weights=a3 / 12.0, minlength=len(edges))
        data = np.empty(len(indices))
        data[upper] = b_edge
        data[lower] = b_edge
        data[diag] = np.bincount(F.reshape(-1), weights=np.repeat(area / 6.0, 3), minlength=n)
        if loop.any():
            data[diag] += b_loop
        if mass == "mixed":
            lumped = np.bincount(F.reshape(-1), weights=np.repeat(area / 3.0, 3), minlength=n)
            data = 0.5 * data
            data[diag] += 0.5 * lumped
        B = sp.csr_matrix((data, indices.copy(), indptr.copy()), shape=(n, n))
    else:
        d = np.bincount(F.reshape(-1), weights=np.repeat(area / 3.0, 3), minlength=n)
        B = sp.diags(d).tocsr()
    return A, B, eps, n_degenerate


def _problem(mesh: MeshLike, bc: str = "neumann", mass: str = "consistent", *,
             repair: bool = True) -> _FEMProblem:
    """Assemble the FEM problem of a mesh, returning a :class:`_FEMProblem` with its bookkeeping.

    See :func:`fem_matrices` for the parameters and errors; ``repair=False`` skips
    :func:`cshape.repair_mesh` (for a mesh that was repaired already).
    """
    bc = check_choice("bc", bc, BOUNDARY_CONDITIONS)
    mass = check_choice("mass", mass, MASS_TYPES)
    repair = check_bool("repair", repair)
    mesh = as_mesh(mesh)
    if repair:
        mesh = repair_mesh(mesh)
    A, B, eps, nbad = _assemble(mesh, mass=mass)
    if eps > 0:
        warnings.warn(
            f"mesh has {nbad} degenerate (near zero-area) triangles: edge lengths were "
            f"mollified by {eps:.3g} (intrinsic mollification, Sharp & Crane 2020) so that all "
            "cotangents are finite",
            CShapeWarning,
            stacklevel=3,
        )
    n = mesh.n_vertices
    B_vertices = B
    if bc == "dirichlet":
        fixed = np.union1d(mesh.boundary_vertices, mesh.nonmanifold_vertices)
        free = np.setdiff1d(np.arange(n), fixed)
        if len(free) == 0:
            raise ValueError(
                "bc='dirichlet' leaves no unknowns: every vertex is a boundary or non-manifold "
                "vertex; use bc='neumann' or a finer mesh"
            )
        A = A[free][:, free].tocsr()
        B = B[free][:, free].tocsr()
    else:
        free = np.arange(n)
    return _FEMProblem(A, B, free, n, mesh.area, bc, eps, B_vertices)


def fem_matrices(mesh: MeshLike, bc: str = "neumann", mass: str = "consistent"
                 ) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """Stiffness ``A`` and mass ``B`` of the linear FEM discretisation, Eq. (4)-(7).

    The Laplace-Beltrami eigenproblem ``Delta f = -lam f`` (Eq. 2) becomes the
    generalised matrix eigenproblem ``A f = -lam B f`` (Eq. 3).  **Sign convention:**
    ``A`` has off-diagonal entries ``+(cot alpha_ij + cot beta_ij) / 2`` and rows summing
    to zero, so it is negative semidefinite; ``B`` is positive definite.

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        The surface.  It is repaired first with :func:`cshape.repair_mesh` (warning if
        anything changed).
    bc : {'neumann', 'dirichlet'}, default='neumann'
        Boundary condition on boundary and non-manifold vertices.  ``'neumann'`` keeps
        every vertex as an unknown: Eq. (4)-(5) on a closed mesh and Eq. (6)-(7) where an
        edge has one triangle (boundary) or three and more (non-manifold).  ``'dirichlet'``
        fixes the function to zero on the boundary and non-manifold vertices, keeping
        only the inner manifold vertices ``V_I`` (Section 2.2).
    mass : {'consistent', 'lumped', 'mixed'}, default='consistent'
        Consistent mass matrix of Eq. (5) / (7) (the paper's), the lumped diagonal
        ``sum_t |t|/3``, or ``'mixed'``: their average ``(B_consistent + B_lumped) / 2``,
        with the sparsity of the consistent one.  Linear FEM with the consistent mass
        overestimates the eigenvalues by a leading term that grows like ``h^2 lam^2``
        (``h`` the edge length); with the lumped mass that term has the opposite sign, and
        their average cancels most of it (see the resolution guide).

    Returns
    -------
    A : scipy.sparse.csr_matrix, shape (k, k)
        Symmetric negative semidefinite stiffness; ``k = n`` for Neumann, ``|V_I|``
        for Dirichlet (in increasing vertex order).
    B : scipy.sparse.csr_matrix, shape (k, k)
        Symmetric positive definite mass; its entries sum to the surface area (Neumann).

    Raises
    ------
    TypeError
        If ``bc`` or ``mass`` is not a string, or ``mesh`` is not a mesh.
    ValueError
        If ``bc`` or ``mass`` is unknown, the mesh has zero total area (every triangle
        degenerate: vertices coincident or collinear), or ``bc='dirichlet'`` leaves no
        unknowns.

    Notes
    -----
    Triangles of zero area (e.g. from marching cubes) have infinite cotangents.  When the
    mesh has any, all edge lengths are increased by the smallest ``eps`` that gives every
    triangle a positive area (intrinsic mollification, Sharp & Crane 2020), with a
    :class:`cshape.CShapeWarning`; ``eps`` is at most ``1e-6`` times the mean edge
    length, so the spectrum is unchanged to that relative order.  Meshes without
    degenerate triangles are assembled exactly as Eq. (4)-(7).

    Examples
    --------
    >>> import numpy as np, cshape
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
    >>> F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    >>> A, B = cshape.fem_matrices((V, F))
    >>> bool(abs(A.sum()) < 1e-12), bool(np.isclose(B.sum(), cshape.Mesh(V, F).area))
    (True, True)
    """
    f = _problem(mesh, bc=bc, mass=mass)
    return f.A, f.B
