"""Imperfect meshes through the whole pipeline (README, "What cshape does with imperfect
meshes"): what is repaired (with a warning), what is interpreted, and what extreme
coordinates do.  The meshes that are refused, and their messages, are the tables of
test_validation.py; the Mesh validators themselves are in test_mesh.py."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from conftest import compact_of, pairs

import cshape
from cshape import CShapeWarning, Mesh, fem_matrices, shapes

TET_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
TET_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


@pytest.fixture(scope="module")
def sphere():
    return shapes.icosphere(2)  # 162 vertices


@pytest.fixture(scope="module")
def sphere_lam(sphere):
    return cshape.shape_dna(sphere, N=12)


def _quiet(fn, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CShapeWarning)
        return fn(*args, **kwargs)


def test_caller_arrays_are_neither_frozen_nor_shared():
    V, F = TET_V.copy(), TET_F.copy()
    m = Mesh(V, F)
    assert V.flags.writeable and F.flags.writeable  # the Mesh must not freeze them
    V[0] = 5.0
    assert m.vertices[0].tolist() == [0, 0, 0]  # nor see later changes
    with pytest.raises(ValueError, match="read-only"):
        m.vertices[0, 0] = 1.0


# ------------------------------------------------------------ degenerate and extreme geometry
def test_mostly_degenerate_but_positive_area_is_mollified_not_refused():
    # a square split into two triangles plus a zero-area sliver along the diagonal's midpoint
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0]])
    F = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4], [0, 4, 2]])
    with pytest.warns(CShapeWarning, match="mollified"):
        A, B = fem_matrices((V, F))
    assert np.isfinite(A.data).all() and np.isfinite(B.data).all()


@pytest.mark.parametrize("scale", [1e-100, 1e-20, 1e-3, 1e3, 1e100])
def test_extreme_coordinate_scales_keep_finite_matrices(sphere, scale):
    m = Mesh(sphere.vertices * scale, sphere.faces)
    assert m.area == pytest.approx(sphere.area * scale**2, rel=1e-12)
    A, B = fem_matrices(m)
    A0, B0 = fem_matrices(sphere)
    # the cotangent matrix does not depend on the unit; the mass matrix scales with area
    np.testing.assert_allclose(A.toarray(), A0.toarray(), rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(B.toarray() / scale**2, B0.toarray(), rtol=1e-10, atol=1e-15)


@pytest.mark.parametrize("scale", [1e-20, 1e-3, 1e3])
def test_descriptor_is_scale_invariant_over_many_orders(sphere, scale):
    ref = compact_of(sphere, M=3, N=9)
    got = compact_of(Mesh(sphere.vertices * scale, sphere.faces), M=3, N=9)
    np.testing.assert_allclose(got, ref, rtol=1e-8, atol=1e-8)


@pytest.mark.parametrize("scale", [1e6, 1e20])
def test_large_unit_mesh_keeps_its_eigenvalues(sphere, sphere_lam, scale):
    """Eigenvalues scale as 1 / length^2: a mesh in um or mm has them far below 1e-10,
    which an absolute zero-clipping threshold used to set to 0."""
    lam = cshape.shape_dna(Mesh(sphere.vertices * scale, sphere.faces), N=12)
    assert lam[0] == 0 and lam[1] > 0
    np.testing.assert_allclose(lam * scale**2, sphere_lam, rtol=1e-8, atol=1e-10)


# ------------------------------------------------------------ repaired, with a warning
def _spectrum(mesh, N=12):
    return cshape.shape_dna(mesh, N=N)


def test_faces_repeating_a_vertex_are_dropped(sphere, sphere_lam):
    F = np.vstack([sphere.faces, [[0, 0, 1], [5, 6, 5], [7, 7, 7]]])
    with pytest.warns(CShapeWarning, match="removed 3 faces with a repeated vertex"):
        lam = _spectrum((sphere.vertices, F))
    np.testing.assert_allclose(lam, sphere_lam, rtol=1e-10, atol=1e-12)


@pytest.mark.parametrize("flip", [False, True], ids=["same_order", "reversed"])
def test_duplicate_faces_are_dropped(sphere, sphere_lam, flip):
    dup = sphere.faces[:10, ::-1] if flip else np.roll(sphere.faces[:10], 1, axis=1)
    F = np.vstack([sphere.faces, dup])
    with pytest.warns(CShapeWarning, match="removed 10 duplicate faces"):
        lam = _spectrum((sphere.vertices, F))
    np.testing.assert_allclose(lam, sphere_lam, rtol=1e-10, atol=1e-12)


def _soup(mesh):
    V = mesh.vertices[mesh.faces.reshape(-1)]  # 3 vertices per face, as in STL
    return V, np.arange(len(V)).reshape(-1, 3)


def test_triangle_soup_is_welded(sphere, sphere_lam):
    V, F = _soup(sphere)
    with pytest.warns(CShapeWarning, match=f"welded {len(V) - sphere.n_vertices} duplicate"):
        lam = _spectrum((V, F))
    np.testing.assert_allclose(lam, sphere_lam, rtol=1e-10, atol=1e-12)


def test_triangle_soup_gives_no_false_components_warning(sphere):
    """Components are counted after the repair (the soup welds into one piece)."""
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always", CShapeWarning)
        cshape.shape_dna(_soup(sphere), N=4)
    assert not [w for w in rec if "connected components" in str(w.message)]


def test_nearly_coincident_vertices_need_merge_tol(sphere):
    V = sphere.vertices[sphere.faces.reshape(-1)]
    V = V + np.random.default_rng(0).normal(scale=1e-12, size=V.shape)
    F = np.arange(len(V)).reshape(-1, 3)
    exact = _quiet(cshape.repair_mesh, (V, F))
    assert exact.n_vertices == len(V)  # merge_tol=0 welds only identical positions
    assert exact.n_components == sphere.n_faces  # ... so the soup stays loose triangles
    with pytest.warns(CShapeWarning, match="welded"):
        welded = cshape.repair_mesh((V, F), merge_tol=1e-9)
    assert welded.n_vertices == sphere.n_vertices and welded.is_closed


def test_unreferenced_vertices_are_dropped(sphere, sphere_lam):
    V = np.vstack([[[9.0, 9.0, 9.0]], sphere.vertices, [[7.0, 7.0, 7.0]]])
    F = sphere.faces + 1
    with pytest.warns(CShapeWarning, match="removed 2 unreferenced vertices"):
        lam, phi = pairs((V, F), N=12)
    np.testing.assert_allclose(lam, sphere_lam, rtol=1e-10, atol=1e-12)
    assert phi.shape == (sphere.n_vertices, 12)  # documented: rows of the repaired mesh


def test_clean_mesh_passes_without_any_warning(sphere):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        compact_of(sphere, M=2, N=9)


# ------------------------------------------------------------ interpreted, documented
def test_several_components_warn_and_give_one_zero_each():
    a = shapes.icosphere(1)
    parts = [a.vertices, a.vertices * 2 + 5, a.vertices * 0.5 - 5]
    V = np.vstack(parts)
    F = np.vstack([a.faces + k * a.n_vertices for k in range(3)])
    with pytest.warns(CShapeWarning, match="3 connected components.*largest_component"):
        lam = cshape.shape_dna((V, F), N=6)
    np.testing.assert_allclose(lam[:3], 0, atol=1e-12)
    assert lam[3] > 0.1
    with warnings.catch_warnings():
        warnings.simplefilter("error", CShapeWarning)
        big = cshape.largest_component((V, F))
        lam_big = cshape.shape_dna(big, N=4)
    assert big.area == pytest.approx(4 * a.area)
    np.testing.assert_allclose(lam_big, cshape.shape_dna(a, N=4) / 4, rtol=1e-10, atol=1e-12)


def _book(pages=3):
    """`pages` square sheets glued along one edge (x axis): a non-manifold edge fan."""
    n = 4
    Vs, Fs = [], []
    base = shapes.square(n)  # in the z=0 plane, [0,1]^2; edge y=0 shared
    shared = np.flatnonzero(np.isclose(base.vertices[:, 1], 0))
    for k in range(pages):
        ang = 2 * np.pi * k / pages
        V = base.vertices.copy()
        y = V[:, 1].copy()
        V[:, 1], V[:, 2] = y * np.cos(ang), y * np.sin(ang)
        Vs.append(V)
        Fs.append(base.faces + k * base.n_vertices)
    V, F = np.vstack(Vs), np.vstack(Fs)
    # glue: the shared edge's vertices of every page map to page 0's
    remap = np.arange(len(V))
    for k in range(1, pages):
        remap[shared + k * base.n_vertices] = shared
    return cshape.repair_mesh(Mesh(V, remap[F]), warn=False)


def test_nonmanifold_edges_are_assembled_and_solved():
    book = _book(3)
    assert len(book.nonmanifold_edges) == 4 and book.n_components == 1
    with warnings.catch_warnings():
        warnings.simplefilter("error", CShapeWarning)  # no repair needed, no warning
        lam = cshape.shape_dna(book, N=8)
    assert np.isfinite(lam).all() and np.all(np.diff(lam) >= 0)
    assert lam[0] == 0 and lam[1] > 0  # connected through the spine: one zero
    # Dirichlet drops the spine and the boundary: each page's inner vertices decouple
    lam_d = cshape.shape_dna(book, N=6, bc="dirichlet")
    page_d = cshape.shape_dna(shapes.square(4), N=2, bc="dirichlet")
    np.testing.assert_allclose(lam_d[:3], page_d[0], rtol=1e-10)  # three equal pages


def test_bowtie_vertex_joins_two_spheres():
    a = shapes.icosphere(1)
    top = int(np.argmax(a.vertices[:, 2]))
    b_V = a.vertices.copy()
    b_V[:, 2] = -b_V[:, 2] + 2 * a.vertices[top, 2]  # mirror: b's bottom touches a's top
    V = np.vstack([a.vertices, b_V])
    F2 = a.faces[:, ::-1] + a.n_vertices
    F2[F2 == top + a.n_vertices] = top  # share the touching vertex
    F = np.vstack([a.faces, F2])
    m = _quiet(cshape.repair_mesh, (V, F))
    assert m.nonmanifold_vertices.tolist() == [top] and len(m.nonmanifold_edges) == 0
    assert m.n_components == 1 and m.genus is None
    lam = cshape.shape_dna(m, N=6)
    assert lam[0] == 0 and lam[1] > 0 and np.isfinite(lam).all()
    # Dirichlet fixes the bowtie vertex: the two spheres each lose one vertex and decouple
    lam_d = cshape.shape_dna(m, N=4, bc="dirichlet")
    assert lam_d[1] == pytest.approx(lam_d[0], rel=1e-8)


def test_inconsistent_orientation_does_not_change_the_spectrum():
    m = shapes.torus(16, 8)
    rng = np.random.default_rng(1)
    F = m.faces.copy()
    flip = rng.random(len(F)) < 0.5
    F[flip] = F[flip][:, ::-1]
    A0, B0 = fem_matrices(m)
    A1, B1 = fem_matrices((m.vertices, F))
    assert abs(A1 - A0).max() < 1e-14 and abs(B1 - B0).max() < 1e-15
    np.testing.assert_allclose(cshape.shape_dna((m.vertices, F), N=10),
                               cshape.shape_dna(m, N=10), rtol=1e-10, atol=1e-12)


def test_single_triangle():
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0.0]])
    lam = cshape.shape_dna((V, [[0, 1, 2]]), N=3)
    assert lam[0] == 0 and np.all(lam[1:] > 0)


def test_merge_tol_welds_close_pairs_on_both_sides_of_any_grid_cell():
    """A square as two loose triangles whose copies of the shared corners are 0.61 tol
    apart, across a cell boundary of a grid of size tol (1 / tol = 707.1 cells, the copy at
    706.49): the soup must still weld into one connected square."""
    h = 1e-3 * np.sqrt(2)  # merge_tol x the bounding-box diagonal
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0],  # triangle 1
                  [1 - 0.61 * h, 0, 0], [1, 1, 0], [0, 1 - 0.61 * h, 0]])  # triangle 2
    F = np.array([[0, 1, 2], [3, 4, 5]])
    with pytest.warns(CShapeWarning, match="welded 2 duplicate vertices"):
        m = cshape.repair_mesh((V, F), merge_tol=1e-3)
    assert m.n_vertices == 4 and m.n_components == 1 and len(m.boundary_edges) == 4
    # beyond the tolerance nothing is welded
    far = cshape.repair_mesh((V, F), merge_tol=0.5e-3)
    assert far.n_vertices == 6 and far.n_components == 2


@pytest.mark.parametrize("method", ["loop", "midpoint"])
def test_subdivide_refuses_nonmanifold_edges_clearly(method):
    from cshape.data import variants

    with pytest.raises(ValueError, match="subdivide needs edge-manifold input.*4 edges shared"):
        variants.subdivide(_book(3), 1, method)


@pytest.mark.parametrize("op", ["remesh", "subdivide", "noise"])
def test_variants_accept_boundaries_and_bowties(op):
    """PyMeshLab filters on open, bow-tie and single-triangle meshes: a mesh, no crash."""
    from cshape.data import variants

    a = shapes.icosphere(1)
    top = int(np.argmax(a.vertices[:, 2]))
    bV = a.vertices * [1, 1, -1] + [0, 0, 2 * a.vertices[top, 2]]
    F2 = a.faces[:, ::-1] + a.n_vertices
    F2[F2 == top + a.n_vertices] = top
    bowtie = cshape.repair_mesh((np.vstack([a.vertices, bV]), np.vstack([a.faces, F2])),
                                warn=False)
    tri = Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    run = {"remesh": lambda m: variants.remesh(m, target_length=0.3),
           "subdivide": lambda m: variants.subdivide(m, 1),
           "noise": lambda m: variants.add_normal_noise(m, 1.0, random_state=0)}[op]
    for m in (shapes.square(3), bowtie, tri):
        out = run(m)
        assert isinstance(out, Mesh) and np.isfinite(out.vertices).all()
