"""FEM matrices: hand-computed entries, Eq. (4)-(7) structure, Dirichlet, degenerate triangles."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

import cshape
from cshape import Mesh, fem_matrices, shapes


def test_single_right_triangle_by_hand():
    # angles: 90 deg at v0 (cot 0), 45 deg at v1 and v2 (cot 1); area 1/2
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0.0]])
    F = np.array([[0, 1, 2]])
    A, B = fem_matrices((V, F))
    A_expected = np.array([[-1.0, 0.5, 0.5], [0.5, -0.5, 0.0], [0.5, 0.0, -0.5]])
    B_expected = np.array([[2, 1, 1], [1, 2, 1], [1, 1, 2]]) / 24.0
    np.testing.assert_allclose(A.toarray(), A_expected, atol=1e-15)
    np.testing.assert_allclose(B.toarray(), B_expected, atol=1e-15)
    _, Bl = fem_matrices((V, F), mass="lumped")
    np.testing.assert_allclose(Bl.toarray(), np.eye(3) / 6.0)


def test_nonmanifold_edge_shared_by_three_triangles_eq6_eq7():
    # edge (0, 1) is shared by three triangles; the angle opposite it is the same
    # in each, cot = 0.75, and each triangle has area 1/2.
    V = np.array([[0, 0, 0], [1, 0, 0], [0.5, 1, 0], [0.5, -1, 0], [0.5, 0, 1.0]])
    F = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    A, B = fem_matrices((V, F))
    assert A[0, 1] == pytest.approx(3 * 0.75 / 2)  # Eq. (6): sum over chi(01) of cot/2
    assert B[0, 1] == pytest.approx(3 * 0.5 / 12)  # Eq. (7): sum over T(01) of |t|/12
    assert B[0, 0] == pytest.approx(3 * 0.5 / 6)
    np.testing.assert_allclose(np.asarray(A.sum(axis=1)).ravel(), 0, atol=1e-14)
    # Dirichlet drops the two non-manifold vertices and the three boundary ones: nothing left
    with pytest.raises(ValueError, match="no unknowns"):
        fem_matrices((V, F), bc="dirichlet")


@pytest.mark.parametrize(
    "mesh",
    [shapes.icosphere(2), shapes.square(6), shapes.torus(12, 8), shapes.hemisphere(5)],
    ids=["sphere", "square", "torus", "hemisphere"],
)
def test_structure(mesh):
    A, B = fem_matrices(mesh)
    assert sp.issparse(A) and sp.issparse(B)
    assert abs(A - A.T).max() < 1e-12
    assert abs(B - B.T).max() < 1e-15
    np.testing.assert_allclose(np.asarray(A.sum(axis=1)).ravel(), 0, atol=1e-10)
    assert B.sum() == pytest.approx(mesh.area, rel=1e-12)
    # A negative semidefinite, B positive definite
    assert np.linalg.eigvalsh(A.toarray()).max() < 1e-10
    assert np.linalg.eigvalsh(B.toarray()).min() > 0
    # a constant function has zero energy: A 1 = 0
    assert np.abs(A @ np.ones(mesh.n_vertices)).max() < 1e-10


def test_dirichlet_keeps_inner_vertices():
    sq = shapes.square(6)
    A, B = fem_matrices(sq, bc="dirichlet")
    assert A.shape == (25, 25)  # (6-1)^2 inner vertices
    Afull, Bfull = fem_matrices(sq)
    inner = np.setdiff1d(np.arange(sq.n_vertices), sq.boundary_vertices)
    np.testing.assert_allclose(A.toarray(), Afull[inner][:, inner].toarray())
    np.testing.assert_allclose(B.toarray(), Bfull[inner][:, inner].toarray())


def test_closed_mesh_dirichlet_equals_neumann():
    m = shapes.icosphere(1)
    A1, B1 = fem_matrices(m)
    A2, B2 = fem_matrices(m, bc="dirichlet")
    assert abs(A1 - A2).max() == 0 and abs(B1 - B2).max() == 0


def test_bad_options():
    m = shapes.icosphere(0)
    with pytest.raises(ValueError, match=r"bc must be one of \{'neumann', 'dirichlet'\}"):
        fem_matrices(m, bc="robin")
    with pytest.raises(ValueError, match="mass must be one of"):
        fem_matrices(m, mass="diagonal")


def _sphere_with_zero_area_cap(subdiv=3):
    """Icosphere with one zero-area triangle: an edge (a, b) gets its exact midpoint m on one
    side (two triangles) and a flat cap triangle (a, b, m) towards the other side."""
    s = shapes.icosphere(subdiv)
    V, F = s.vertices.copy(), s.faces.copy()
    a, b, c = F[0]
    m = len(V)
    V = np.vstack([V, 0.5 * (V[a] + V[b])])
    F = np.vstack([F[1:], [[a, m, c], [m, b, c], [b, a, m]]])
    return s, Mesh(V, F)


def test_zero_area_triangle_is_mollified_with_warning():
    s, bad = _sphere_with_zero_area_cap()
    assert bad.is_closed and bad.face_areas.min() < 1e-15
    with pytest.warns(cshape.CShapeWarning, match="mollified"):
        A, B = fem_matrices(bad)
    assert np.all(np.isfinite(A.data)) and np.all(np.isfinite(B.data))
    with pytest.warns(cshape.CShapeWarning):
        lam = cshape.shape_dna(bad, N=20)
    ref = cshape.shape_dna(s, N=20)
    assert np.all(np.isfinite(lam))
    # the cap only constrains the midpoint to follow the edge: the spectrum barely moves
    np.testing.assert_allclose(lam[1:], ref[1:], rtol=2e-3)


def test_good_mesh_is_not_mollified():
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error", cshape.CShapeWarning)
        fem_matrices(shapes.icosphere(3))


def _reference_assembly(V, F):
    """Eq. (4)-(5) triangle by triangle, entry by entry (the textbook loop), dense."""
    n = len(V)
    A, B = np.zeros((n, n)), np.zeros((n, n))
    for t in F:
        p = V[t]
        area = 0.5 * np.linalg.norm(np.cross(p[1] - p[0], p[2] - p[0]))
        for c in range(3):
            i, j, k = t[c], t[(c + 1) % 3], t[(c + 2) % 3]  # angle at i, opposite edge (j, k)
            u, v = V[j] - V[i], V[k] - V[i]
            w = 0.5 * np.dot(u, v) / np.linalg.norm(np.cross(u, v))
            A[j, k] += w
            A[k, j] += w
            A[j, j] -= w
            A[k, k] -= w
            B[j, k] += area / 12
            B[k, j] += area / 12
            B[i, i] += area / 6
    return A, B


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_assembly_equals_the_textbook_loop_on_open_and_nonmanifold_meshes(seed):
    # random triangles over few vertices: boundary edges, edges in 3-5 triangles, bow-ties,
    # several components; the sort-free CSR fill must give the loop's matrices
    rng = np.random.default_rng(seed)
    V = rng.standard_normal((12, 3))
    F = np.array([f for f in rng.integers(0, 12, (40, 3)) if len(set(f)) == 3])
    F = F[np.unique(np.sort(F, axis=1), axis=0, return_index=True)[1]]
    A, B = fem_matrices((V, F))
    A_ref, B_ref = _reference_assembly(V, F)
    scale = np.abs(A_ref).max()
    np.testing.assert_allclose(A.toarray(), A_ref, atol=1e-12 * scale)
    np.testing.assert_allclose(B.toarray(), B_ref, atol=1e-14)
    assert A.has_sorted_indices and B.has_sorted_indices
    assert A.nnz == B.nnz == len(V) + 2 * len(cshape.Mesh(V, F).edges)


def test_assembly_of_an_unrepaired_mesh_with_a_collapsed_face():
    # _assemble() skips repair: a face (0, 0, 5) and a duplicate face keep the
    # old COO-sum result (A: zero row sums; B: the collapsed face's |t| = 0 after
    # mollification is tiny, the duplicate counts twice)
    m = shapes.icosphere(1)
    F = np.vstack([m.faces, m.faces[:2], [[0, 0, 5]]])
    with pytest.warns(cshape.CShapeWarning, match="mollified"):
        pass_mesh = cshape.Mesh(m.vertices, F)
        A, B, eps, nbad = cshape.fem._assemble(pass_mesh)
        cshape.fem._problem(pass_mesh, repair=False)
    assert eps > 0 and nbad == 1
    np.testing.assert_allclose(np.asarray(A.sum(axis=1)).ravel(), 0, atol=1e-9 * abs(A).max())
    assert B.sum() == pytest.approx(cshape.fem._heron(
        cshape.fem._edge_lengths(pass_mesh) + eps).sum(), rel=1e-12)
    assert (np.diff(A.indptr) > 0).all() and A.has_sorted_indices


def test_fem_matrices_is_the_one_public_way_to_get_A_and_B():
    assert cshape.fem.__all__ == ["fem_matrices"]
    assert cshape.fem_matrices is cshape.fem.fem_matrices
    for old in ("fem", "assemble", "FEM"):
        assert not hasattr(cshape.fem, old), old
