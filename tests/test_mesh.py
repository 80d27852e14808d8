"""Mesh container: validation errors, topology, repair, loading."""

from __future__ import annotations

import numpy as np
import pytest

import cshape
from cshape import Mesh, shapes

TET_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
TET_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def test_tetrahedron_basic_facts():
    m = Mesh(TET_V, TET_F)
    assert (m.n_vertices, m.n_faces) == (4, 4)
    # three right triangles of area 1/2 and one equilateral of side sqrt(2)
    assert m.area == pytest.approx(1.5 + np.sqrt(3) / 4 * 2)
    assert m.is_closed and m.genus == 0 and m.n_components == 1
    assert m.euler_characteristic == 2
    assert len(m.edges) == 6 and len(m.boundary_edges) == 0


@pytest.mark.parametrize(
    "vertices, faces, exc, match",
    [
        (np.zeros((4, 2)), TET_F, ValueError, r"vertices must have shape \(n, 3\)"),
        (np.zeros((0, 3)), TET_F, ValueError, "vertices is empty"),
        (np.where(np.eye(4, 3) > 0, np.nan, 0.0), TET_F, ValueError, "NaN or infinite"),
        (np.full((4, 3), np.inf), TET_F, ValueError, "NaN or infinite"),
        (TET_V, TET_F[:, :2], ValueError, r"faces must have shape \(m, 3\)"),
        (TET_V, np.zeros((0, 3), int), ValueError, "faces is empty"),
        (TET_V, TET_F + 1, ValueError, r"outside \[0, 3\]"),
        (TET_V, TET_F - 1, ValueError, r"outside \[0, 3\]"),
        (TET_V, TET_F + 0.5, TypeError, "integer"),
        (TET_V, np.array([["a", "b", "c"]]), TypeError, "integer array"),
        ("abc", TET_F, TypeError, "vertices must be a real array"),
    ],
)
def test_mesh_validation_errors(vertices, faces, exc, match):
    with pytest.raises(exc, match=match):
        Mesh(vertices, faces)


def test_as_mesh_accepts_pairs_and_rejects_paths():
    assert cshape.mesh.as_mesh((TET_V, TET_F)).n_faces == 4
    with pytest.raises(TypeError, match="load_mesh"):
        cshape.mesh.as_mesh("bunny.obj")
    with pytest.raises(TypeError, match=r"expected a mesh: a cshape.Mesh, .*; got int$"):
        cshape.mesh.as_mesh(42)


def test_boundary_and_nonmanifold_topology():
    sq = shapes.square(4)
    assert not sq.is_closed and sq.genus is None
    assert len(sq.boundary_edges) == 16
    assert len(sq.boundary_vertices) == 16
    # three triangles sharing the edge (0, 1): a non-manifold "book" of pages
    V = np.array([[0, 0, 0], [1, 0, 0], [0.5, 1, 0], [0.5, -1, 0], [0.5, 0, 1.0]])
    F = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    m = Mesh(V, F)
    assert m.nonmanifold_edges.tolist() == [[0, 1]]
    assert set(m.nonmanifold_vertices.tolist()) == {0, 1}


def test_bowtie_vertex_is_nonmanifold():
    # two triangles touching at vertex 0 only
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [-1, 0, 0], [-1, -1, 0.0]])
    F = np.array([[0, 1, 2], [0, 3, 4]])
    m = Mesh(V, F)
    assert m.nonmanifold_vertices.tolist() == [0]
    assert len(m.nonmanifold_edges) == 0
    assert m.n_components == 1


def test_components_and_largest_component():
    a = shapes.icosphere(1)
    b = shapes.icosphere(1, radius=2.0)
    V = np.vstack([a.vertices, b.vertices + 10])
    F = np.vstack([a.faces, b.faces + a.n_vertices])
    m = Mesh(V, F)
    assert m.n_components == 2 and m.genus is None
    big = cshape.largest_component(m)
    assert big.n_vertices == b.n_vertices
    assert big.area == pytest.approx(b.area)


def test_repair_welds_drops_and_reindexes():
    # two triangles of a square stored as soup (6 vertices), plus junk
    V = np.array(
        [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 0, 0], [1, 1, 0], [0, 1, 0], [5, 5, 5.0]]
    )
    F = np.array([[0, 1, 2], [3, 4, 5], [0, 0, 1], [2, 1, 0]])
    with pytest.warns(cshape.CShapeWarning, match="welded 2 duplicate vertices") as rec:
        r = cshape.repair_mesh((V, F))
    msg = str(rec[0].message)
    assert "removed 1 faces with a repeated vertex" in msg
    assert "removed 1 duplicate faces" in msg
    assert "removed 1 unreferenced vertices" in msg
    assert r.n_vertices == 4 and r.n_faces == 2
    assert r.area == pytest.approx(1.0)
    assert len(r.boundary_edges) == 4  # a connected square, not two loose triangles


def test_repair_returns_same_object_when_clean():
    m = shapes.icosphere(1)
    assert cshape.repair_mesh(m) is m


def test_repair_rejects_all_degenerate():
    with pytest.raises(ValueError, match="no valid triangle"):
        cshape.repair_mesh((TET_V, np.array([[0, 0, 1], [2, 2, 2]])))


def _write_off(path, V, F):
    lines = ["OFF", f"{len(V)} {len(F)} 0"]
    lines += [" ".join(map(str, v)) for v in V]
    lines += ["3 " + " ".join(map(str, f)) for f in F]
    path.write_text("\n".join(lines) + "\n")


def test_load_mesh_lives_in_readers():
    """File reading is cshape.readers' (it imports cshape.mesh, never the reverse)."""
    import cshape.mesh
    import cshape.readers

    assert cshape.load_mesh is cshape.readers.load_mesh
    assert not hasattr(cshape.mesh, "load_mesh")


def test_load_off_roundtrip(tmp_path):
    p = tmp_path / "tet.off"
    _write_off(p, TET_V, TET_F)
    m = cshape.load_mesh(p)
    assert m.n_vertices == 4 and m.n_faces == 4
    assert m.area == pytest.approx(Mesh(TET_V, TET_F).area)


def test_load_obj_quads_are_triangulated_and_uv_seams_kept(tmp_path):
    # a unit square of two quads, with texture coordinates that differ per face corner
    p = tmp_path / "quads.obj"
    p.write_text(
        "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\n"
        "vt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\nvt 0.5 0.5\nvt 0.2 0.2\n"
        "f 1/1 2/2 5/4 4/3\nf 2/5 3/6 6/4 5/3\n"
    )
    m = cshape.load_mesh(p)
    assert m.n_vertices == 6  # not split at the UV seam along x = 1
    assert m.n_faces == 4
    assert m.area == pytest.approx(2.0)
    assert len(m.boundary_edges) == 6


def test_load_stl_soup_is_welded(tmp_path):
    p = tmp_path / "tet.stl"
    tris = TET_V[TET_F]
    lines = ["solid t"]
    for t in tris:
        lines += ["facet normal 0 0 0", "outer loop"]
        lines += [f"vertex {x} {y} {z}" for x, y, z in t]
        lines += ["endloop", "endfacet"]
    lines.append("endsolid t")
    p.write_text("\n".join(lines) + "\n")
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cshape.CShapeWarning)
        m = cshape.load_mesh(p)
    assert m.n_vertices == 4 and m.n_faces == 4 and m.is_closed


def test_load_errors_name_the_file(tmp_path):
    with pytest.raises(FileNotFoundError, match="no mesh file"):
        cshape.load_mesh(tmp_path / "missing.off")
    empty = tmp_path / "empty.off"
    empty.write_text("")
    with pytest.raises(ValueError, match="empty.off.*empty"):
        cshape.load_mesh(empty)
    garbage = tmp_path / "garbage.ply"
    garbage.write_bytes(b"\x00\x01binary garbage\xff" * 20)
    with pytest.raises(ValueError, match="garbage.ply"):
        cshape.load_mesh(garbage)
    unknown = tmp_path / "mesh.xyz123"
    unknown.write_text("hello")
    with pytest.raises(ValueError, match="xyz123"):
        cshape.load_mesh(unknown)
    with pytest.raises(ValueError, match="is a folder"):
        cshape.load_mesh(tmp_path)


OFF_TET = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"
PLY_HEAD = (
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
)


@pytest.mark.parametrize(
    "name, content, match",
    [
        ("oor.off", OFF_TET.replace("3 1 2 3\n", "3 1 2 9\n"), "references vertex 9.*only 4"),
        ("trunc_faces.off", OFF_TET.rsplit("3 0 3 2", 1)[0], "declares 4 faces.*truncated"),
        ("trunc_verts.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n", "declares 4 vertices.*truncated"),
        ("nan.off", OFF_TET.replace("0 0 1\n", "0 0 nan\n"), "NaN or infinite"),
        ("words.off", "hello\n", "expected the OFF header"),
        ("oor.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 7\n", "vertex 7.*only 3"),
        ("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", "index 0 is invalid"),
        ("inf.obj", "v 0 0 0\nv 1 0 inf\nv 0 1 0\nf 1 2 3\n", "NaN or infinite"),
        ("text.obj", "this is not a mesh\n", "not an OBJ triangle mesh"),
        ("oor.ply", PLY_HEAD + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 5\n", "Bad vertex index"),
        ("noheader.ply", "ply\nformat ascii 1.0\nelement vertex 3\n", "no end_header"),
        ("short.stl", "x" * 40, "at least 84 bytes"),
        ("trunc.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n", "Malformed"),
    ],
)
def test_malformed_files_give_clear_errors(tmp_path, name, content, match):
    p = tmp_path / name
    p.write_text(content)
    with pytest.raises(ValueError, match=match) as info:
        cshape.load_mesh(p)
    assert name in str(info.value)


def test_binary_stl_truncated(tmp_path):
    import struct

    p = tmp_path / "bin.stl"
    body = b"\0" * 80 + struct.pack("<I", 4) + b"\0" * (50 * 3)  # declares 4, holds 3
    p.write_bytes(body)
    with pytest.raises(ValueError, match="declares 4 triangles"):
        cshape.load_mesh(p)


def test_obj_negative_relative_indices_are_valid(tmp_path):
    p = tmp_path / "rel.obj"
    p.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n")
    m = cshape.load_mesh(p)
    assert m.n_faces == 1 and m.area == pytest.approx(0.5)


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_edge_topology_matches_unique_over_rows(seed):
    # the integer-key sort must give np.unique's edges, counts and half-edge map exactly,
    # also with boundary, non-manifold (3+ triangles) and duplicate faces
    rng = np.random.default_rng(seed)
    n = int(rng.integers(4, 40))
    F = rng.integers(0, n, (int(rng.integers(1, 90)), 3))
    m = Mesh(rng.standard_normal((n, 3)), F)
    half = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    edges, inverse, counts = np.unique(np.sort(half, axis=1), axis=0, return_inverse=True,
                                       return_counts=True)
    np.testing.assert_array_equal(m.edges, edges)
    np.testing.assert_array_equal(m.edge_face_counts, counts)
    np.testing.assert_array_equal(m._edge_data[1], inverse.reshape(-1))
    L = np.linalg.norm(m.vertices[edges[:, 0]] - m.vertices[edges[:, 1]], axis=1)
    assert m.mean_edge_length == pytest.approx(L.mean(), rel=1e-14)


def test_row_distinctness_check_is_exact():
    from cshape.mesh import _all_rows_distinct

    V = shapes.icosphere(4).vertices  # symmetric coordinates: a weak hash would collide
    assert _all_rows_distinct(V)
    W = V.copy()
    W[7] = W[2000]
    assert not _all_rows_distinct(W)
    assert not _all_rows_distinct(np.array([[0.0, 1, 2], [-0.0, 1, 2]]))  # -0.0 == 0.0
    assert _all_rows_distinct(np.array([[0.0, 1, 2], [0.0, 2, 1]]))
    F = np.sort(shapes.icosphere(4).faces, axis=1)
    assert _all_rows_distinct(F)
    assert not _all_rows_distinct(np.vstack([F, F[5:6]]))
    # welding still merges exact duplicates of a big mesh and keeps first occurrences
    m = shapes.icosphere(4)
    n = m.n_vertices
    Vd = np.vstack([m.vertices, m.vertices[m.faces[0]]])  # copies of face 0's corners
    Fd = m.faces.copy()
    Fd[0] = [n, n + 1, n + 2]
    with pytest.warns(cshape.CShapeWarning, match="welded 3 duplicate vertices"):
        r = cshape.repair_mesh(Mesh(Vd, Fd))
    np.testing.assert_array_equal(r.faces, m.faces)
    np.testing.assert_array_equal(r.vertices, m.vertices)


def test_boundary_loops():
    sq = shapes.square(4)
    assert shapes.icosphere(2).n_boundary_loops == 0
    assert sq.n_boundary_loops == 1 and shapes.disk(6).n_boundary_loops == 1
    # two squares side by side, apart: two loops; a hemisphere: one
    V = np.vstack([sq.vertices, sq.vertices + [3.0, 0.0, 0.0]])
    F = np.vstack([sq.faces, sq.faces + sq.n_vertices])
    assert cshape.Mesh(V, F).n_boundary_loops == 2
    assert shapes.hemisphere(8).n_boundary_loops == 1
