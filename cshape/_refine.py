"""Richardson extrapolation of linear-FEM eigenvalues over one midpoint subdivision.

Private: the public way in is ``cshape.shape_dna(mesh, N, refine='extrapolate')``.

Linear finite elements overestimate each eigenvalue by ``C_i h^2`` (``h`` the edge length,
``C_i`` growing like ``lam_i^2``).  Splitting every triangle into four at its edge midpoints
halves ``h`` and keeps every triangle flat, so the linear functions of the mesh are linear
functions of the subdivided mesh: the subdivided problem is a Galerkin refinement of the same
polyhedral surface, and by the min-max principle ``lam_fine[i] <= lam[i]`` for every ``i``
(consistent mass).  Eliminating the ``h^2`` term,

    lam_extrapolated = (4 lam_fine - lam) / 3,

leaves an ``O(h^4)`` error against the polyhedral surface's spectrum, provided that ``C_i``
is the same at both resolutions: exactly so where the subdivision repeats the mesh's pattern
at half the size; elsewhere ``C_i`` changes a little with the pattern and a smaller ``h^2``
term remains.  Eigenvalues are paired
by their index in the ascending lists: each solve returns the N smallest eigenvalues with
their multiplicities, and the min-max principle orders both lists the same way, so a cluster
of (nearly) repeated eigenvalues cut by the N-th pairs its members in order, whatever
follows.  The derivation, what it converges to and the measured orders: the guide
"Spectra that do not depend on the mesh's resolution" (``docs/guides/resolution-free-spectra.md``);
figures: ``benchmarks/results/refine.md``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from .mesh import Mesh


def midpoint_subdivision(mesh: Mesh) -> Mesh:
    """Split every triangle into four at its edge midpoints (flat triangles kept).

    The one midpoint subdivision of the package: :func:`cshape.shapes.icosphere` refines
    with it too (projecting the new vertices onto the sphere).

    Parameters
    ----------
    mesh : Mesh
        A repaired mesh (no repeated index in a face).

    Returns
    -------
    Mesh
        ``n + e`` vertices (``e`` unique edges, ascending; vertex ``n + k`` is the midpoint
        of ``mesh.edges[k]``) and ``4 m`` faces, oriented as their parents: the corner
        triangles of every face at its corners ``f0``, ``f1``, ``f2`` (in that order, each
        starting at its corner), then every middle triangle.  Boundary edges stay boundary,
        non-manifold edges stay non-manifold, pieces stay pieces.
    """
    V, F = mesh.vertices, mesh.faces
    n, m = len(V), len(F)
    edges, half_to_edge, _ = mesh._edge_data
    mid = n + half_to_edge.reshape(3, m)  # midpoints of (f0, f1), (f1, f2), (f2, f0)
    m01, m12, m20 = mid[0], mid[1], mid[2]
    f0, f1, f2 = F[:, 0], F[:, 1], F[:, 2]
    faces = np.concatenate([
        np.stack([f0, m01, m20], axis=1),
        np.stack([f1, m12, m01], axis=1),
        np.stack([f2, m20, m12], axis=1),
        np.stack([m01, m12, m20], axis=1),
    ])
    vertices = np.concatenate([V, 0.5 * (V[edges[:, 0]] + V[edges[:, 1]])])
    return Mesh(vertices, faces)


def extrapolate(lam: NDArray[np.float64], lam_fine: NDArray[np.float64]
                ) -> NDArray[np.float64]:
    """Richardson's ``(4 lam_fine - lam) / 3`` for an ``O(h^2)`` error, index by index.

    Parameters
    ----------
    lam, lam_fine : ndarray, shape (N,)
        Ascending eigenvalues of a mesh and of its midpoint subdivision.

    Returns
    -------
    ndarray, shape (N,)
        The extrapolated eigenvalues, ascending; zero eigenvalues stay exactly 0 and none
        is negative.
    """
    out = (4.0 * lam_fine - lam) / 3.0
    out[(lam == 0.0) & (lam_fine == 0.0)] = 0.0
    # a crossing of two close eigenvalues between the resolutions may swap neighbours
    return np.sort(np.maximum(out, 0.0))
