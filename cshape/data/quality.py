"""Measures of a mesh's triangles: their angles and the quality summary of Section 3.

A marching-cubes mesh has needle and zero-area triangles; its remesh does not
(:mod:`cshape.data.variants`).  :func:`mesh_quality` says how much (minimum angle, aspect
ratio), :func:`triangle_angles` gives every angle.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..mesh import MeshLike, as_mesh

__all__ = [
    "mesh_quality",
    "triangle_angles",
]


def triangle_angles(mesh: MeshLike) -> NDArray[np.float64]:
    """Interior angles of every triangle in degrees, shape (m, 3), angle ``k`` at corner ``k``.

    A zero-area triangle has angles 0, 0, 180 (or 0 where two vertices coincide).

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        The mesh.

    Returns
    -------
    ndarray, shape (m, 3)
        Angle ``k`` of each triangle at its corner ``k``, in degrees.
    """
    mesh = as_mesh(mesh)
    V, F = mesh.vertices, mesh.faces
    out = np.empty(F.shape, dtype=np.float64)
    for k in range(3):
        u = V[F[:, (k + 1) % 3]] - V[F[:, k]]
        w = V[F[:, (k + 2) % 3]] - V[F[:, k]]
        nu, nw = np.linalg.norm(u, axis=1), np.linalg.norm(w, axis=1)
        cos = np.einsum("ij,ij->i", u, w) / np.maximum(nu * nw, np.finfo(float).tiny)
        sin = np.linalg.norm(np.cross(u, w), axis=1) / np.maximum(nu * nw, np.finfo(float).tiny)
        out[:, k] = np.degrees(np.arctan2(sin, cos))
    return out


def mesh_quality(mesh: MeshLike) -> dict[str, float]:
    """Triangle-quality figures of a mesh (e.g. the paper's "CM" versus "CS").

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        The mesh to measure.

    Returns
    -------
    dict
        ``min_angle``, ``mean_min_angle``, ``max_angle`` (degrees); ``pct_below_10`` (share of
        triangles with an angle under 10 degrees, in percent); ``aspect_max``,
        ``aspect_mean`` (aspect ratio ``R / (2 r)``, circumradius over twice the inradius:
        1 for an equilateral triangle, ``inf`` for a degenerate one); ``n_degenerate``
        (triangles of area below ``1e-12`` times the mean); ``n_vertices``, ``n_faces``,
        ``mean_edge_length``.

    Examples
    --------
    >>> from cshape import shapes
    >>> from cshape.data import quality
    >>> q = quality.mesh_quality(shapes.icosphere(2))
    >>> round(q["aspect_max"], 2) < 1.3
    True
    """
    mesh = as_mesh(mesh)
    ang = triangle_angles(mesh)
    V, F = mesh.vertices, mesh.faces
    e = np.stack([np.linalg.norm(V[F[:, (k + 1) % 3]] - V[F[:, k]], axis=1) for k in range(3)], 1)
    A = mesh.face_areas
    s = e.sum(1) / 2
    with np.errstate(divide="ignore", invalid="ignore"):
        aspect = np.where(A > 0, e.prod(1) * s / (8 * A**2), np.inf)
    min_ang = ang.min(1)
    return {
        "n_vertices": mesh.n_vertices,
        "n_faces": mesh.n_faces,
        "mean_edge_length": mesh.mean_edge_length,
        "min_angle": float(min_ang.min()),
        "mean_min_angle": float(min_ang.mean()),
        "max_angle": float(ang.max()),
        "pct_below_10": float(100 * np.mean(min_ang < 10)),
        "aspect_max": float(aspect.max()),
        "aspect_mean": float(np.mean(aspect[np.isfinite(aspect)])) if np.isfinite(aspect).any()
        else float("inf"),
        "n_degenerate": int(np.sum(A < 1e-12 * A.mean())),
    }
