"""Mesh objects of trimesh, PyVista, meshio, Open3D and PyMeshLab, taken wherever a mesh is.

The fake classes below have the attribute layout of each library's mesh object (they test
cshape's duck typing, not the libraries); PyMeshLab, a dependency, is also tested for real.
"""

from __future__ import annotations

import numpy as np
import pytest

import cshape
from cshape import Mesh, shapes

TET_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
TET_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


class Trimesh:  # trimesh.Trimesh: .vertices (n, 3), .faces (m, 3)
    def __init__(self, V, F):
        self.vertices, self.faces = V, F


class PolyData:  # pyvista.PolyData: .points (n, 3), .faces flat [3, i, j, k, 3, ...]
    def __init__(self, V, F):
        self.points = V
        self.faces = np.column_stack([np.full(len(F), 3), F]).ravel()


class MeshioMesh:  # meshio.Mesh: .points, .cells_dict {'triangle': (m, 3), ...}
    def __init__(self, V, F, **more):
        self.points = V
        self.cells_dict = {"triangle": F, **more}


class Vector:  # open3d.utility.Vector3dVector / Vector3iVector: np.asarray works
    def __init__(self, a):
        self._a = np.asarray(a)

    def __array__(self, dtype=None, copy=None):
        return self._a if dtype is None else self._a.astype(dtype)


class TriangleMesh:  # open3d.geometry.TriangleMesh: .vertices, .triangles (vectors)
    def __init__(self, V, F):
        self.vertices, self.triangles = Vector(V), Vector(F)


class MeshLabMesh:  # pymeshlab.Mesh: vertex_matrix(), face_matrix()
    def __init__(self, V, F):
        self._v, self._f = V, F

    def vertex_matrix(self):
        return self._v

    def face_matrix(self):
        return self._f


class MeshSet:  # pymeshlab.MeshSet: current_mesh()
    def __init__(self, mesh=None):
        self._m = mesh

    def current_mesh(self):
        if self._m is None:
            raise RuntimeError("no mesh loaded")  # pymeshlab raises its own error type
        return self._m


LIBRARIES = {
    "trimesh": lambda: Trimesh(TET_V, TET_F),
    "pyvista": lambda: PolyData(TET_V, TET_F),
    "meshio": lambda: MeshioMesh(TET_V, TET_F, vertex=np.arange(4)[:, None]),
    "open3d": lambda: TriangleMesh(TET_V, TET_F),
    "pymeshlab-mesh": lambda: MeshLabMesh(TET_V, TET_F),
    "pymeshlab-meshset": lambda: MeshSet(MeshLabMesh(TET_V, TET_F)),
}


@pytest.mark.parametrize("lib", sorted(LIBRARIES))
def test_as_mesh_reads_each_librarys_layout(lib):
    obj = LIBRARIES[lib]()
    m = cshape.as_mesh(obj)
    assert isinstance(m, Mesh)
    np.testing.assert_array_equal(m.vertices, TET_V)
    np.testing.assert_array_equal(m.faces, TET_F)


@pytest.mark.parametrize("lib", sorted(LIBRARIES))
def test_every_stage_takes_a_librarys_mesh(lib):
    """shape_dna, compact_shape_dna and describe give the numbers of the (V, F) pair."""
    s = shapes.icosphere(1)
    obj = {"trimesh": Trimesh, "pyvista": PolyData, "meshio": MeshioMesh,
           "open3d": TriangleMesh, "pymeshlab-mesh": MeshLabMesh,
           "pymeshlab-meshset": lambda V, F: MeshSet(MeshLabMesh(V, F))}[lib](s.vertices, s.faces)
    ref = cshape.shape_dna((s.vertices, s.faces), N=5)
    np.testing.assert_array_equal(cshape.shape_dna(obj, N=5), ref)
    np.testing.assert_array_equal(cshape.compact_shape_dna(obj, M=1, N=5),
                                  cshape.compact_shape_dna(s, M=1, N=5))
    tables = [cshape.describe([m], N=5, cache_dir=False, progress=False)
              for m in (obj, s)]
    np.testing.assert_array_equal(tables[0].lam, tables[1].lam)


def test_a_real_pymeshlab_meshset_and_mesh():
    pymeshlab = pytest.importorskip("pymeshlab")
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=TET_V, face_matrix=TET_F.astype(np.int32)))
    for obj in (ms, ms.current_mesh()):
        m = cshape.as_mesh(obj)
        np.testing.assert_array_equal(m.vertices, TET_V)
        np.testing.assert_array_equal(m.faces, TET_F)
    with pytest.raises(ValueError, match=r"the pymeshlab.MeshSet mesh has no current mesh .*"
                                         r"load one first: ms.load_new_mesh\(path\)"):
        cshape.as_mesh(pymeshlab.MeshSet())


@pytest.mark.parametrize("obj, match", [
    (MeshSet(), r"MeshSet mesh has no current mesh \(no mesh loaded\); load one first"),
    (type("PolyData", (), {"points": TET_V, "faces": np.array([4, 0, 1, 2, 3])})(),
     r"faces that are not all triangles .* triangulate it first: mesh.triangulate\(\)"),
    (type("PolyData", (), {"points": TET_V, "faces": np.array([], int)})(),
     "has no faces; a mesh needs at least one triangle"),
    (MeshioMesh(TET_V, TET_F, quad=np.array([[0, 1, 2, 3]])),
     "has quad cells besides triangles; cshape needs a triangle mesh: triangulate it first"),
    (type("Mesh", (), {"points": TET_V, "cells_dict": {"line": np.array([[0, 1]])}})(),
     r"has no 'triangle' cells \(its cells: \['line'\]\); cshape needs a triangle surface"),
    (Trimesh(TET_V, TET_F[:, :2]), r"faces must have shape \(m, 3\)"),
    (TriangleMesh(TET_V[:, :2], TET_F), r"vertices must have shape \(n, 3\)"),
])
def test_a_librarys_mesh_that_is_no_triangle_mesh_is_refused_by_name(obj, match):
    with pytest.raises(ValueError, match=match):
        cshape.as_mesh(obj)


@pytest.mark.parametrize("obj, name", [
    (object(), "object"), ({"vertices": TET_V}, "dict"), (np.zeros((4, 3)), "numpy.ndarray"),
    (Vector(TET_V), "test_meshlike.Vector"),
])
def test_anything_else_names_what_was_given_and_what_is_accepted(obj, name):
    with pytest.raises(TypeError, match=(
            r"^expected a mesh: a cshape.Mesh, a \(vertices, faces\) pair of arrays, or a mesh "
            r"object of trimesh \(.vertices, .faces\), PyVista \(PolyData\), meshio "
            r"\(.points, .cells_dict\['triangle'\]\), Open3D \(TriangleMesh\) or PyMeshLab "
            rf"\(Mesh, MeshSet\); got {name}$")):
        cshape.as_mesh(obj)
    with pytest.raises(TypeError, match="expected a mesh"):
        cshape.shape_dna(obj, N=3) if name != "numpy.ndarray" else cshape.eigenpairs(obj, N=3)
