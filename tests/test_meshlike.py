"""Mesh objects of trimesh, PyVista, meshio, Open3D and PyMeshLab, taken wherever a mesh is.

Each library's own mesh object is tested: trimesh and meshio are in the test dependencies,
PyMeshLab is a dependency of cshape, and PyVista and Open3D are tested where they are
installed (their tests skip with the reason otherwise).  A few look-alike classes remain for
the refusals of malformed layouts that the libraries themselves would not build.
"""

from __future__ import annotations

import numpy as np
import pytest

import cshape
from cshape import Mesh, shapes

TET_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
TET_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def _trimesh(V, F):
    trimesh = pytest.importorskip("trimesh")
    return trimesh.Trimesh(vertices=V, faces=F, process=False)


def _pyvista(V, F):
    pv = pytest.importorskip("pyvista")
    return pv.PolyData(np.asarray(V, float), np.column_stack([np.full(len(F), 3), F]).ravel())


def _meshio(V, F):
    meshio = pytest.importorskip("meshio")
    return meshio.Mesh(V, [("triangle", F), ("vertex", np.arange(len(V))[:, None])])


def _open3d(V, F):
    o3d = pytest.importorskip("open3d")
    return o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(np.asarray(V, float)),
                                     o3d.utility.Vector3iVector(np.asarray(F, np.int32)))


def _pymeshlab_mesh(V, F):
    pymeshlab = pytest.importorskip("pymeshlab")
    return pymeshlab.Mesh(vertex_matrix=np.asarray(V, float),
                          face_matrix=np.asarray(F, np.int32))


def _pymeshlab_meshset(V, F):
    pymeshlab = pytest.importorskip("pymeshlab")
    ms = pymeshlab.MeshSet()
    ms.add_mesh(_pymeshlab_mesh(V, F))
    return ms


LIBRARIES = {
    "trimesh": _trimesh,
    "pyvista": _pyvista,
    "meshio": _meshio,
    "open3d": _open3d,
    "pymeshlab-mesh": _pymeshlab_mesh,
    "pymeshlab-meshset": _pymeshlab_meshset,
}


@pytest.mark.parametrize("lib", sorted(LIBRARIES))
def test_as_mesh_reads_each_librarys_mesh(lib):
    m = cshape.mesh.as_mesh(LIBRARIES[lib](TET_V, TET_F))
    assert isinstance(m, Mesh)
    np.testing.assert_array_equal(m.vertices, TET_V)
    np.testing.assert_array_equal(m.faces, TET_F)


@pytest.mark.parametrize("lib", sorted(LIBRARIES))
def test_every_stage_takes_a_librarys_mesh(lib):
    """shape_dna, eigenbasis and describe give the numbers of the (V, F) pair; a formula
    refuses the library's mesh as it refuses ours (it takes eigenvalues)."""
    s = shapes.icosphere(1)
    obj = LIBRARIES[lib](s.vertices, s.faces)
    ref = cshape.shape_dna((s.vertices, s.faces), N=5)
    np.testing.assert_array_equal(cshape.shape_dna(obj, N=5), ref)
    np.testing.assert_array_equal(cshape.eigenbasis(obj, N=5).lam,
                                  cshape.eigenbasis(s, N=5).lam)
    with pytest.raises(TypeError, match="takes eigenvalues, not a mesh"):
        cshape.compact_shape_dna(obj, M=1, N=5)
    tables = [cshape.describe([m], N=5, cache_dir=False, progress=False)
              for m in (obj, s)]
    np.testing.assert_array_equal(tables[0].lam, tables[1].lam)


def test_trimesh_is_read_by_its_faces_not_its_triangles_corners():
    """A ``trimesh.Trimesh`` also has ``.triangles``, the corners' coordinates (m, 3, 3):
    it is read by ``.faces``, as trimesh's users expect, with no conversion."""
    trimesh = pytest.importorskip("trimesh")
    sphere = trimesh.creation.icosphere(3)
    assert hasattr(sphere, "triangles")
    s = cshape.Mesh(sphere.vertices, sphere.faces)
    np.testing.assert_array_equal(cshape.shape_dna(sphere, N=8), cshape.shape_dna(s, N=8))


def test_a_real_empty_pymeshlab_meshset_is_refused():
    pymeshlab = pytest.importorskip("pymeshlab")
    with pytest.raises(ValueError, match=r"the pymeshlab.MeshSet mesh has no current mesh .*"
                                         r"load one first: ms.load_new_mesh\(path\)"):
        cshape.mesh.as_mesh(pymeshlab.MeshSet())


def test_real_polygon_meshes_are_refused_by_name():
    """Quads in PyVista and meshio are named, with the fix (triangulate)."""
    meshio = pytest.importorskip("meshio")
    m = meshio.Mesh(TET_V, [("triangle", TET_F), ("quad", np.array([[0, 1, 2, 3]]))])
    with pytest.raises(ValueError, match="the meshio.Mesh mesh has quad cells besides triangles; "
                                         "cshape needs a triangle mesh: triangulate it first"):
        cshape.mesh.as_mesh(m)
    pv = pytest.importorskip("pyvista")
    quad = pv.PolyData(TET_V, np.array([4, 0, 1, 2, 3]))
    with pytest.raises(ValueError, match=r"faces that are not all triangles .* triangulate it "
                                         r"first: mesh.triangulate\(\)"):
        cshape.mesh.as_mesh(quad)


# look-alike layouts that the libraries would not build: the refusals of malformed objects
class Vector:  # open3d.utility.Vector3dVector / Vector3iVector: np.asarray works
    def __init__(self, a):
        self._a = np.asarray(a)

    def __array__(self, dtype=None, copy=None):
        return self._a if dtype is None else self._a.astype(dtype)


class TriangleMesh:  # open3d.geometry.TriangleMesh's layout: .vertices, .triangles (vectors)
    def __init__(self, V, F):
        self.vertices, self.triangles = Vector(V), Vector(F)


class Trimesh:  # trimesh.Trimesh's layout: .vertices (n, 3), .faces (m, 3)
    def __init__(self, V, F):
        self.vertices, self.faces = V, F


class MeshioMesh:  # meshio.Mesh's layout: .points, .cells_dict
    def __init__(self, V, F, **more):
        self.points = V
        self.cells_dict = {"triangle": F, **more}


class MeshSet:  # pymeshlab.MeshSet's layout: current_mesh()
    def __init__(self, mesh=None):
        self._m = mesh

    def current_mesh(self):
        if self._m is None:
            raise RuntimeError("no mesh loaded")  # pymeshlab raises its own error type
        return self._m


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
        cshape.mesh.as_mesh(obj)


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
        cshape.mesh.as_mesh(obj)
    with pytest.raises(TypeError, match="expected a mesh"):
        cshape.shape_dna(obj, N=3) if name != "numpy.ndarray" else cshape.eigenbasis(obj, N=3)
