"""Mesh objects of other libraries, read by their attributes (never by importing them).

:func:`cshape.mesh.as_mesh` takes, besides a :class:`~cshape.mesh.Mesh` and a
``(vertices, faces)`` pair, the mesh objects of the libraries people load meshes with:

==========  ============================  ===============================================
library     object                        read as
==========  ============================  ===============================================
trimesh     ``Trimesh``                   ``.vertices``, ``.faces``
PyVista     ``PolyData``                  ``.points``, ``.faces`` (flat VTK cells
                                          ``[3, i, j, k, 3, ...]``: triangles only)
meshio      ``Mesh``                      ``.points``, ``.cells_dict['triangle']``
Open3D      ``geometry.TriangleMesh``     ``np.asarray(.vertices)``, ``np.asarray(.triangles)``
PyMeshLab   ``Mesh``, ``MeshSet``         ``.vertex_matrix()``, ``.face_matrix()`` (of
                                          ``.current_mesh()`` for a ``MeshSet``)
==========  ============================  ===============================================

:func:`foreign_arrays` recognises an object by these attributes alone, so an object of
another library with the same layout is read the same way, and none of these libraries is
needed to use cshape.
"""

from __future__ import annotations

from typing import Any

import numpy as np

#: What a mesh argument may be, for error messages.
ACCEPTED = (
    "a cshape.Mesh, a (vertices, faces) pair of arrays, or a mesh object of trimesh "
    "(.vertices, .faces), PyVista (PolyData), meshio (.points, .cells_dict['triangle']), "
    "Open3D (TriangleMesh) or PyMeshLab (Mesh, MeshSet)"
)

#: meshio's cell types of surfaces other than plain triangles.
_MESHIO_POLYGONS = ("quad", "polygon", "triangle6", "triangle7", "quad8", "quad9")


def _kind(obj: object) -> str | None:
    """Name the library layout of ``obj`` (None when it has none of them)."""
    has = lambda name: hasattr(obj, name)  # noqa: E731
    if has("vertex_matrix") and has("face_matrix"):
        return "pymeshlab"
    if has("current_mesh") and callable(obj.current_mesh):  # type: ignore[attr-defined]
        return "meshset"
    # trimesh's Trimesh has .faces and also .triangles (the corners' coordinates), so the
    # .faces layout is recognised first; Open3D's TriangleMesh has .triangles and no .faces
    if has("vertices") and has("faces"):
        return "trimesh"
    if has("vertices") and has("triangles"):
        return "open3d"
    if has("points") and has("cells_dict"):
        return "meshio"
    if has("points") and has("faces"):
        return "pyvista"
    return None


def looks_like_mesh(obj: object) -> bool:
    """Whether ``obj`` has the attribute layout of one of the libraries' mesh objects."""
    try:
        return _kind(obj) is not None
    except Exception:  # noqa: BLE001 - a property that fails is not a mesh's layout
        return False


def _name(obj: object) -> str:
    t = type(obj)
    module = t.__module__.split(".")[0]
    return t.__name__ if module == "builtins" else f"{module}.{t.__name__}"


def _pyvista_faces(cells: Any, what: str) -> np.ndarray:
    flat = np.asarray(cells).ravel()
    if flat.size == 0:
        raise ValueError(f"{what} has no faces; a mesh needs at least one triangle")
    if flat.size % 4 == 0:
        rows = flat.reshape(-1, 4)
        if np.all(rows[:, 0] == 3):
            return rows[:, 1:]
    raise ValueError(
        f"{what} has faces that are not all triangles (its flat VTK cell array does not "
        "read as [3, i, j, k, 3, ...]); triangulate it first: mesh.triangulate()"
    )


def _meshio_faces(cells: Any, what: str) -> np.ndarray:
    cells = dict(cells)
    polygons = [k for k in cells if k in _MESHIO_POLYGONS]
    if polygons:
        raise ValueError(
            f"{what} has {', '.join(polygons)} cells besides triangles; cshape needs a "
            "triangle mesh: triangulate it first (cshape.load_mesh(path) reads and "
            "triangulates a file)"
        )
    if "triangle" not in cells:
        raise ValueError(
            f"{what} has no 'triangle' cells (its cells: {sorted(cells) or 'none'}); "
            "cshape needs a triangle surface mesh"
        )
    return np.asarray(cells["triangle"])


def foreign_arrays(obj: object) -> tuple[np.ndarray, np.ndarray] | None:
    """``(vertices, faces)`` of another library's mesh object, or None for anything else.

    The arrays are not validated yet (the :class:`~cshape.mesh.Mesh` constructor does that).

    Raises
    ------
    ValueError
        If ``obj`` has a library's layout but holds no triangle mesh (polygons, no
        triangles, an empty ``MeshSet``).
    """
    try:
        kind = _kind(obj)
    except Exception:  # noqa: BLE001 - a property that fails is not a mesh's layout
        return None
    what = f"the {_name(obj)} mesh"
    o: Any = obj
    if kind == "meshset":
        try:
            o = o.current_mesh()
        except Exception as exc:  # noqa: BLE001 - PyMeshLab raises its own error type
            raise ValueError(
                f"{what} has no current mesh ({exc}); load one first: ms.load_new_mesh(path)"
            ) from None
        kind = "pymeshlab"
    if kind == "pymeshlab":
        return np.asarray(o.vertex_matrix()), np.asarray(o.face_matrix())
    if kind == "open3d":
        return np.asarray(o.vertices), np.asarray(o.triangles)
    if kind == "trimesh":
        return np.asarray(o.vertices), np.asarray(o.faces)
    if kind == "meshio":
        return np.asarray(o.points), _meshio_faces(o.cells_dict, what)
    if kind == "pyvista":
        return np.asarray(o.points), _pyvista_faces(o.faces, what)
    return None
