"""The Eigenbasis value: the same pairs as eigenpairs, bit for bit; its fields; its checks."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import scipy.sparse as sp

import cshape
from cshape import shapes
from cshape.spectrum import solve_eigenproblem


def _cases():
    # dense LAPACK (642 unknowns), block Lanczos (800 unknowns, 60 pairs), Dirichlet
    return [(shapes.icosphere(3), 20, "neumann", "consistent"),
            (shapes.torus(40, 20), 60, "neumann", "consistent"),
            (shapes.torus(40, 20), 30, "neumann", "lumped"),
            (shapes.hemisphere(12), 10, "dirichlet", "consistent")]


@pytest.mark.parametrize("mesh, N, bc, mass", _cases())
def test_eigenbasis_holds_the_bits_of_the_fem_route(mesh, N, bc, mass):
    basis = cshape.eigenbasis(mesh, N, bc=bc, mass=mass)
    # the route of fem_matrices and solve_eigenproblem (the matrices assembled separately)
    A, B = cshape.fem_matrices(mesh, bc=bc, mass=mass)
    lam2, phi2 = solve_eigenproblem(A, B, N)
    assert np.array_equal(basis.lam, lam2)
    if bc == "neumann":
        assert np.array_equal(basis.phi, phi2)
        assert (basis.B != B).nnz == 0
    assert basis.area == mesh.area and basis.mesh is mesh
    assert (basis.N, basis.n_vertices, basis.bc, basis.mass) == (N, mesh.n_vertices, bc, mass)
    # B is the mass over all vertices, so phi is B-orthonormal for both conditions
    np.testing.assert_allclose(basis.phi.T @ (basis.B @ basis.phi), np.eye(N), atol=1e-10)


def test_sphere_multiplets_come_whole():
    # l(l+1) with 2l + 1 copies: 49 = 7^2 pairs end with the whole l = 6 multiplet
    basis = cshape.eigenbasis(shapes.icosphere(4), 49)
    for l in range(7):
        block = basis.lam[l * l:(l + 1) ** 2]
        assert len(block) == 2 * l + 1
        assert abs(block.mean() - l * (l + 1)) < 0.03 * max(l * (l + 1), 1)
        # tight clusters, far apart: every copy of l(l+1) is in its block
        assert np.ptp(block) <= 0.01 * max(block.mean(), 1.0)
        if l < 6:
            assert basis.lam[(l + 1) ** 2] - block.max() > 0.5 * (2 * l + 2)
    # the multiplet's eigenfunctions are a B-orthonormal basis of its space
    P = basis.phi[:, 36:49]
    np.testing.assert_allclose(P.T @ (basis.B @ P), np.eye(13), atol=1e-10)


def test_eigenbasis_of_a_mesh_needing_repair_keeps_the_repaired_mesh():
    m = shapes.icosphere(2)
    V = np.vstack([m.vertices, [[5.0, 5.0, 5.0]]])  # one unreferenced vertex
    with pytest.warns(cshape.CShapeWarning, match="removed 1 unreferenced"):
        basis = cshape.eigenbasis((V, m.faces), 8)
    assert basis.mesh.n_vertices == m.n_vertices == basis.phi.shape[0]


def test_eigenbasis_is_frozen_and_its_arrays_read_only():
    basis = cshape.eigenbasis(shapes.icosphere(2), 6)
    with pytest.raises(dataclasses.FrozenInstanceError):
        basis.lam = np.zeros(6)  # type: ignore[misc]
    with pytest.raises(ValueError, match="read-only"):
        basis.phi[0, 0] = 1.0
    # eigenpairs still hands out arrays of its own
    lam, phi = cshape.spectrum.eigenpairs(shapes.icosphere(2), 6)
    phi[0, 0] = 1.0


def test_repr_is_one_line_without_arrays():
    basis = cshape.eigenbasis(shapes.icosphere(3), 16)
    assert repr(basis) == ("Eigenbasis(N=16, n_vertices=642, bc='neumann', mass='consistent', "
                           "area=12.5, lam=[0 .. 12.2])")


def test_truncate_keeps_the_first_pairs_as_views():
    basis = cshape.eigenbasis(shapes.icosphere(3), 16)
    b4 = basis.truncate(4)
    assert b4.N == 4 and np.shares_memory(b4.phi, basis.phi)
    assert np.array_equal(b4.phi, basis.phi[:, :4]) and b4.B is basis.B
    assert (b4.area, b4.mesh, b4.bc) == (basis.area, basis.mesh, basis.bc)
    with pytest.raises(ValueError, match=r"N must be an integer in \[1, 16\], got 17"):
        basis.truncate(17)


def test_constructor_from_plain_arrays():
    lam = np.array([0.0, 1.0, 2.0])
    phi = np.ones((4, 3))
    b = cshape.Eigenbasis(lam, phi, np.eye(4))
    assert sp.issparse(b.B) and b.area == 4.0 and b.mesh is None
    assert cshape.Eigenbasis(lam, phi, np.eye(4), 2.5).area == 2.5
    # round-off below zero is clipped; the caller's arrays stay writable
    b = cshape.Eigenbasis(np.array([-1e-14, 1.0, 2.0]), phi, np.eye(4))
    assert b.lam[0] == 0.0 and phi.flags.writeable


LAM = np.array([0.0, 1.0, 2.0])
PHI = np.ones((4, 3))
B4 = np.eye(4)


@pytest.mark.parametrize("kwargs, exc, match", [
    (dict(lam=LAM + 1j), TypeError, "lam must be real"),
    (dict(lam=LAM[None]), ValueError, "lam must be 1-D"),
    (dict(lam=[0.0, -1.0, 2.0]), ValueError, "lam must be eigenvalues >= 0"),
    (dict(lam=[0.0, np.nan, 2.0]), ValueError, "lam contains NaN"),
    (dict(phi="phi"), TypeError, "phi must be a real array, got str"),
    (dict(phi=PHI[:, 0]), ValueError, r"phi must have shape \(n, N\) = \(n, 3\)"),
    (dict(phi=PHI[:, :2]), ValueError, r"got shape \(4, 2\)"),
    (dict(phi=PHI * np.nan), ValueError, "phi contains NaN"),
    (dict(B=np.eye(3)), ValueError, r"B must be the mass matrix of shape \(n, n\) = \(4, 4\)"),
    (dict(B="B"), TypeError, "B must be a real array"),
    (dict(B=0 * B4), ValueError, "B sums to 0"),
    (dict(area=-1.0), ValueError, "area must be a positive finite"),
    (dict(area="1"), TypeError, "area must be a real number, got str '1'"),
    (dict(mesh=(np.eye(3), [[0, 1, 2]])), TypeError, "mesh must be a cshape.Mesh or None"),
    (dict(mesh=shapes.icosphere(1)), ValueError, "mesh has 42 vertices but phi has 4 rows"),
    (dict(bc="robin"), ValueError, "bc must be one of"),
    (dict(mass=1), TypeError, "mass must be"),
])
def test_constructor_errors(kwargs, exc, match):
    args = dict(lam=LAM, phi=PHI, B=B4) | kwargs
    with pytest.raises(exc, match=match):
        cshape.Eigenbasis(**args)


def test_point_map_is_the_pipeline_on_the_fem_route():
    """point_map's result equals the same steps on pairs of fem_matrices + solve_eigenproblem."""
    from cshape import maps
    from cshape.data import poses

    S = poses.posed_figure("quadruped", rest=True, voxelsize=0.04, target_vertices=500)
    T = poses.posed_figure("quadruped", 0, voxelsize=0.04, target_vertices=500)
    N, N0 = 40, 15
    p, C = cshape.point_map(S, T, N=N, N0=N0, return_map=True)
    bases = []
    for m in (S, T):
        A, B = cshape.fem_matrices(m)
        lam, phi = solve_eigenproblem(A, B, N)
        bases.append(cshape.Eigenbasis(lam, phi, B, m.area, mesh=m))
    bS, bT = bases
    dS, dT = maps._descriptors(bS, bT, 100, None)
    C2 = cshape.maps.functional_map(bS.truncate(N0), bT.truncate(N0), dS, dT)
    C2 = cshape.maps.zoomout(C2, bS, bT, N, sample=3000)
    assert np.array_equal(C, C2)
    assert np.array_equal(p, cshape.maps.map_to_pointwise(C2, bS, bT))


def test_a_mesh_read_and_solved_is_repaired_once(tmp_path, monkeypatch):
    """load_mesh repairs; shape_dna, eigenbasis, point_map and a batch run do not again."""
    import cshape.mesh as mesh_module

    m = shapes.icosphere(2)
    path = tmp_path / "ico.off"
    path.write_text(f"OFF\n{m.n_vertices} {m.n_faces} 0\n"
                    + "".join(f"{x:.17g} {y:.17g} {z:.17g}\n" for x, y, z in m.vertices)
                    + "".join(f"3 {a} {b} {c}\n" for a, b, c in m.faces))
    calls = []
    real = mesh_module._all_rows_distinct

    def counted(X):
        calls.append(len(X))
        return real(X)

    monkeypatch.setattr(mesh_module, "_all_rows_distinct", counted)
    mesh = cshape.load_mesh(path)
    assert calls == [m.n_vertices, m.n_faces]  # one repair: the vertices, then the faces
    cshape.shape_dna(mesh, 8)
    cshape.eigenbasis(mesh, 8)
    cshape.point_map(mesh, mesh, N=10, N0=5)
    assert len(calls) == 2
    calls.clear()
    cshape.describe([str(path)], N=40, progress=False)
    assert len(calls) == 2
    # a mesh built from arrays is repaired by the first stage that needs it, once
    calls.clear()
    fresh = cshape.Mesh(m.vertices, m.faces)
    cshape.eigenbasis(fresh, 8)
    cshape.shape_dna(fresh, 8)
    assert len(calls) == 2
