"""Built-in analytic shapes, made with NumPy alone (no file, no download).

They are the known-answer cases of the test suite and the demo:

=================  ===========================================  ==============================
shape              exact Laplace-Beltrami spectrum              function
=================  ===========================================  ==============================
unit sphere        l(l+1), multiplicity 2l+1                    :func:`icosphere`
unit square        pi^2 (m^2 + n^2); Neumann m,n >= 0,          :func:`square`
                   Dirichlet m,n >= 1
unit disk          Neumann j'_{m,k}^2, Dirichlet j_{m,k}^2       :func:`disk`
                   (Bessel zeros; multiplicity 2 for m > 0)
unit hemisphere    l(l+1) with l+m even (Neumann) or odd        :func:`hemisphere`
                   (Dirichlet), m = -l..l
=================  ===========================================  ==============================

Each function returns a :class:`cshape.Mesh`.  Resolutions are integers in a range whose
upper bound keeps the mesh within memory, lengths positive finite numbers: a value out of
range is a ``ValueError``, one of the wrong type (a bool, a float resolution, a string) a
``TypeError``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ._checks import check_int, check_real
from ._refine import midpoint_subdivision
from .mesh import Mesh, repair_mesh

__all__ = [
    "icosphere",
    "square",
    "disk",
    "hemisphere",
    "torus",
    "cube",
    "sphere_spectrum",
]


def icosphere(subdivisions: int = 4, radius: float = 1.0) -> Mesh:
    """Icosphere: an icosahedron subdivided ``subdivisions`` times, projected to the sphere.

    Vertex counts ``10 * 4**s + 2``: 642 (s=3), 2562 (4), 10242 (5), 40962 (6), 163842 (7).

    Parameters
    ----------
    subdivisions : int, default=4
        Midpoint subdivisions of the icosahedron, 0 to 8.
    radius : float, default=1.0
        Radius of the sphere, positive.

    Returns
    -------
    Mesh
        A closed genus-0 mesh, centred at the origin, every vertex at distance ``radius``.

    Examples
    --------
    >>> from cshape import shapes
    >>> m = shapes.icosphere(2)
    >>> m.n_vertices, m.n_faces, m.genus
    (162, 320, 0)
    """
    s = check_int("subdivisions", subdivisions, min=0, max=8)
    radius = check_real("radius", radius, positive=True)
    t = (1.0 + 5**0.5) / 2.0
    V = np.array(
        [
            [-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0],
            [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
            [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1],
        ],
        dtype=np.float64,
    )
    F = np.array(
        [
            [0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11],
            [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
            [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
            [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1],
        ],
        dtype=np.int64,
    )
    V /= np.linalg.norm(V, axis=1, keepdims=True)
    for _ in range(s):
        fine = midpoint_subdivision(Mesh(V, F))
        V = fine.vertices / np.linalg.norm(fine.vertices, axis=1, keepdims=True)
        F = fine.faces
    return Mesh(V * radius, F)


def square(n: int = 32, size: float = 1.0) -> Mesh:
    """Flat square ``[0, size]^2`` in the z=0 plane, an ``n x n`` grid of cells.

    Each cell is cut into two triangles along alternating diagonals.  ``(n+1)^2`` vertices.

    Parameters
    ----------
    n : int, default=32
        Cells per side, 1 to 4096.
    size : float, default=1.0
        Side length, positive.

    Returns
    -------
    Mesh
        An open mesh with one boundary loop, normals along +z.
    """
    n = check_int("n", n, min=1, max=4096)
    size = check_real("size", size, positive=True)
    x = np.linspace(0.0, size, n + 1)
    X, Y = np.meshgrid(x, x, indexing="ij")
    V = np.stack([X.ravel(), Y.ravel(), np.zeros(X.size)], 1)
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    a = idx[:-1, :-1].ravel()
    b = idx[1:, :-1].ravel()
    c = idx[1:, 1:].ravel()
    d = idx[:-1, 1:].ravel()
    alt = ((np.add.outer(np.arange(n), np.arange(n))) % 2 == 0).ravel()
    F = np.concatenate(
        [
            np.where(alt[:, None], np.stack([a, b, c], 1), np.stack([a, b, d], 1)),
            np.where(alt[:, None], np.stack([a, c, d], 1), np.stack([b, c, d], 1)),
        ]
    )
    return Mesh(V, F)


def _disk_param(rings: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Concentric-ring triangulation of the unit disk: ring k has 6k vertices.

    Returns (r, theta, F) with polar coordinates of the vertices.
    """
    r = [np.zeros(1)]
    th = [np.zeros(1)]
    start = [0]
    for k in range(1, rings + 1):
        nk = 6 * k
        start.append(start[-1] + len(r[-1]))
        r.append(np.full(nk, k / rings))
        th.append(2 * np.pi * np.arange(nk) / nk)
    faces = []
    for k in range(1, rings + 1):
        inner = np.arange(len(th[k - 1])) + start[k - 1]
        outer = np.arange(len(th[k])) + start[k]
        ti = th[k - 1] if k > 1 else np.zeros(1)
        to = th[k]
        i = o = 0
        ni, no = len(inner), len(outer)
        # stitch the two rings by increasing angle
        while i < ni or o < no:
            a_next = ti[(i + 1) % ni] + (2 * np.pi if i + 1 >= ni else 0.0)
            b_next = to[(o + 1) % no] + (2 * np.pi if o + 1 >= no else 0.0)
            if k == 1 or (o < no and (i >= ni or b_next <= a_next)):
                faces.append([inner[i % ni], outer[o % no], outer[(o + 1) % no]])
                o += 1
            else:
                faces.append([inner[i % ni], outer[o % no], inner[(i + 1) % ni]])
                i += 1
            if k == 1 and o >= no:
                break
    return np.concatenate(r), np.concatenate(th), np.array(faces, dtype=np.int64)


def disk(rings: int = 24, radius: float = 1.0) -> Mesh:
    """Flat disk in the z=0 plane, centred at the origin, triangulated on concentric rings.

    Ring ``k`` has ``6 k`` vertices: ``1 + 3 rings (rings + 1)`` vertices in all.

    Parameters
    ----------
    rings : int, default=24
        Rings around the centre, 1 to 2048.
    radius : float, default=1.0
        Radius of the disk, positive.

    Returns
    -------
    Mesh
        An open mesh with one boundary loop (the circle), normals along +z.
    """
    rings = check_int("rings", rings, min=1, max=2048)
    radius = check_real("radius", radius, positive=True)
    r, th, F = _disk_param(rings)
    V = np.stack([r * np.cos(th), r * np.sin(th), np.zeros_like(r)], 1) * radius
    return _orient_up(Mesh(V, F))


def hemisphere(rings: int = 24, radius: float = 1.0) -> Mesh:
    """Upper hemisphere ``z >= 0`` of the sphere of the given radius; its boundary is the equator.

    The disk triangulation (:func:`disk`) mapped by polar angle ``phi = r pi / 2``.

    Parameters
    ----------
    rings : int, default=24
        Rings around the pole, 1 to 2048.
    radius : float, default=1.0
        Radius of the sphere, positive.

    Returns
    -------
    Mesh
        An open mesh with one boundary loop (the equator), normals pointing outwards.
    """
    rings = check_int("rings", rings, min=1, max=2048)
    radius = check_real("radius", radius, positive=True)
    r, th, F = _disk_param(rings)
    phi = r * (np.pi / 2)
    V = np.stack([np.sin(phi) * np.cos(th), np.sin(phi) * np.sin(th), np.cos(phi)], 1)
    return _orient_up(Mesh(V * radius, F))


def _orient_up(mesh: Mesh) -> Mesh:
    V, F = mesh.vertices, mesh.faces
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    flip = n[:, 2] < 0
    F = F.copy()
    F[flip] = F[flip][:, ::-1]
    return Mesh(V, F)


def torus(n_major: int = 64, n_minor: int = 32, R: float = 1.0, r: float = 0.4) -> Mesh:
    """Build a torus of revolution with major radius ``R`` and tube radius ``r`` (genus 1).

    The axis is z; ``n_major * n_minor`` vertices.

    Parameters
    ----------
    n_major : int, default=64
        Vertices around the axis, 3 to 8192.
    n_minor : int, default=32
        Vertices around the tube, 3 to 8192.
    R : float, default=1.0
        Distance from the axis to the centre of the tube.
    r : float, default=0.4
        Radius of the tube, ``0 < r < R``.

    Returns
    -------
    Mesh
        A closed genus-1 mesh, centred at the origin.

    Examples
    --------
    >>> from cshape import shapes
    >>> t = shapes.torus(16, 8)
    >>> t.n_vertices, t.genus
    (128, 1)
    """
    n_major = check_int("n_major", n_major, min=3, max=8192)
    n_minor = check_int("n_minor", n_minor, min=3, max=8192)
    R, r = check_real("R", R, positive=True), check_real("r", r, positive=True)
    if not 0 < r < R:
        raise ValueError(f"torus needs 0 < r < R, got R={R}, r={r}")
    u = 2 * np.pi * np.arange(n_major) / n_major
    v = 2 * np.pi * np.arange(n_minor) / n_minor
    U, W = np.meshgrid(u, v, indexing="ij")
    V = np.stack(
        [(R + r * np.cos(W)) * np.cos(U), (R + r * np.cos(W)) * np.sin(U), r * np.sin(W)], -1
    ).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(n_major), np.arange(n_minor), indexing="ij")
    a = (i * n_minor + j).ravel()
    b = (((i + 1) % n_major) * n_minor + j).ravel()
    c = (((i + 1) % n_major) * n_minor + (j + 1) % n_minor).ravel()
    d = (i * n_minor + (j + 1) % n_minor).ravel()
    F = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    return Mesh(V, F)


def cube(n: int = 16, size: float = 1.0) -> Mesh:
    """Surface of the cube ``[0, size]^3``, each face an ``n x n`` grid (closed, welded).

    ``6 n^2 + 2`` vertices; the grid's diagonals alternate, as in :func:`square`.

    Parameters
    ----------
    n : int, default=16
        Cells per side of each face, 1 to 1024.
    size : float, default=1.0
        Edge length of the cube, positive.

    Returns
    -------
    Mesh
        A closed genus-0 mesh with one corner at the origin.

    Examples
    --------
    >>> from cshape import shapes
    >>> c = shapes.cube(2, size=3.0)
    >>> c.n_vertices, c.area
    (26, 54.0)
    >>> c.vertices.min(axis=0), c.vertices.max(axis=0)
    (array([0., 0., 0.]), array([3., 3., 3.]))
    """
    n = check_int("n", n, min=1, max=1024)
    size = check_real("size", size, positive=True)
    sq = square(n, size)
    V0, F0 = sq.vertices, sq.faces
    parts_v: list[NDArray[np.float64]] = []
    parts_f: list[NDArray[np.int64]] = []
    s = float(size)
    # six faces as (axes permutation, offset, flip)
    for axis in range(3):
        for side in (0.0, s):
            V = np.zeros_like(V0)
            others = [k for k in range(3) if k != axis]
            V[:, others[0]] = V0[:, 0]
            V[:, others[1]] = V0[:, 1]
            V[:, axis] = side
            F = F0 if (side > 0) == (axis != 1) else F0[:, ::-1]
            parts_f.append(F + sum(len(p) for p in parts_v))
            parts_v.append(V)
    mesh = Mesh(np.vstack(parts_v), np.vstack(parts_f))
    return repair_mesh(mesh, merge_tol=1e-9, warn=False)


def sphere_spectrum(N: int, radius: float = 1.0) -> NDArray[np.float64]:
    """Return the first ``N`` exact sphere eigenvalues: ``l(l+1)/radius^2``, each ``2l+1`` times.

    Parameters
    ----------
    N : int
        How many eigenvalues, 0 or more.
    radius : float, default=1.0
        Radius of the sphere, positive.

    Returns
    -------
    lam : ndarray, shape (N,)
        Ascending eigenvalues of ``Delta f = -lam f`` on the sphere (Eq. 2), in units of
        ``1 / radius^2``.

    Examples
    --------
    >>> from cshape import shapes
    >>> shapes.sphere_spectrum(5)
    array([0., 2., 2., 2., 6.])
    """
    N = check_int("N", N, min=0, max=10**8)
    radius = check_real("radius", radius, positive=True)
    out: list[float] = []
    ell = 0
    while len(out) < N:
        out.extend([ell * (ell + 1) / radius**2] * (2 * ell + 1))
        ell += 1
    return np.array(out[:N], dtype=np.float64)
