"""``mass='mixed'``: the average of the consistent and the lumped mass matrices.

The matrix itself (the average, the consistent pattern, its row sums), the order of the
three spectra, known answers (unit sphere, rectangle, disk with both boundary conditions,
equilateral triangle), the convergence orders, the paper's default left bit for bit, the
errors, and the option along the batch layer, the table and the command line.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import equilateral, equilateral_dirichlet
from scipy.special import jn_zeros, jnp_zeros

import cshape
from cshape import shapes
from cshape.batch import DescriptorTable, describe
from cshape.batch.cache import mesh_key
from cshape.cli import main as cli_main
from cshape.mesh import Mesh
from cshape.spectrum import SpectrumSettings, solve_eigenproblem

MASSES = ("consistent", "lumped", "mixed")


def rel_err(lam, ref):
    pos = ref > 0
    return np.abs(lam[pos] / ref[pos] - 1)


def worst(mesh, n, ref, bc="neumann"):
    """Largest relative error of each mass's first ``n`` eigenvalues, as a dict."""
    return {m: rel_err(cshape.shape_dna(mesh, n, bc=bc, mass=m), ref).max() for m in MASSES}


def rectangle(g, a=2.0):
    """The rectangle ``[0, a] x [0, 1]`` as the unit square's grid stretched along x."""
    sq = shapes.square(g)
    return Mesh(sq.vertices * [a, 1.0, 1.0], sq.faces)


def rectangle_spectrum(n, bc, a=2.0):
    """``pi^2 (j^2 / a^2 + k^2)``, ``j, k >= 1`` (Dirichlet) or ``>= 0`` (Neumann)."""
    k = np.arange(1 if bc == "dirichlet" else 0, 40)
    return np.sort(np.add.outer((k / a) ** 2, k**2).ravel())[:n] * np.pi**2


def disk_spectrum(n, bc):
    """Squares of the Bessel zeros ``j_{m,k}`` (Dirichlet) or ``j'_{m,k}`` (Neumann)."""
    vals = []
    for order in range(20):
        z = jn_zeros(order, 10) if bc == "dirichlet" else jnp_zeros(order, 10)
        if bc == "neumann" and order == 0:
            z = np.concatenate([[0.0], z])
        vals += list(z**2) * (1 if order == 0 else 2)
    return np.sort(vals)[:n]


# ----------------------------------------------------------------------------- the matrix
@pytest.mark.parametrize("mesh, bc", [(shapes.icosphere(2), "neumann"),
                                      (shapes.disk(4), "neumann"),
                                      (shapes.disk(4), "dirichlet")])
def test_mixed_is_the_average_on_the_consistent_pattern(mesh, bc):
    Ac, Bc = cshape.fem_matrices(mesh, bc=bc)
    Al, Bl = cshape.fem_matrices(mesh, bc=bc, mass="lumped")
    Am, Bm = cshape.fem_matrices(mesh, bc=bc, mass="mixed")
    assert (Am != Ac).nnz == 0 and (Al != Ac).nnz == 0  # A does not depend on the mass
    np.testing.assert_allclose(Bm.toarray(), 0.5 * (Bc + Bl).toarray(), rtol=1e-15, atol=0)
    np.testing.assert_array_equal(Bm.indptr, Bc.indptr)  # the same sparsity
    np.testing.assert_array_equal(Bm.indices, Bc.indices)
    assert (Bm != Bm.T).nnz == 0
    assert np.all(np.linalg.eigvalsh(Bm.toarray()) > 0)
    if bc == "neumann":
        # every row sums to the lumped diagonal, and the whole to the area
        np.testing.assert_allclose(np.asarray(Bm.sum(axis=1)).ravel(), Bl.diagonal(),
                                   rtol=1e-12)
        assert np.isclose(Bm.sum(), mesh.area, rtol=1e-12)
        # on a triangle: |t|/24 off the diagonal, |t|/4 on it
        tri = Mesh(mesh.vertices[mesh.faces[0]], [[0, 1, 2]])
        _, Bt = cshape.fem_matrices(tri, mass="mixed")
        np.testing.assert_allclose(Bt.toarray(), tri.area / 24 * (np.ones((3, 3)) + 5 * np.eye(3)),
                                   rtol=1e-12)


@pytest.mark.parametrize("mesh, bc", [(shapes.icosphere(2), "neumann"),
                                      (shapes.torus(16, 8), "neumann"),
                                      (shapes.disk(6), "dirichlet")])
def test_lumped_mixed_consistent_in_order_for_every_index(mesh, bc):
    # B_lumped - B_consistent is |t|/12 times a graph Laplacian on each triangle (positive
    # semidefinite), so B_lumped >= B_mixed >= B_consistent and by min-max every
    # eigenvalue comes in the order lumped <= mixed <= consistent
    lam = {m: cshape.shape_dna(mesh, 30, bc=bc, mass=m) for m in MASSES}
    tol = 1e-9 * lam["consistent"][-1]
    assert np.all(lam["lumped"] <= lam["mixed"] + tol)
    assert np.all(lam["mixed"] <= lam["consistent"] + tol)
    assert np.all(lam["lumped"][1:] < lam["consistent"][1:])


# ----------------------------------------------------------------------------- known answers
def test_sphere_consistent_above_lumped_below_mixed_between():
    mesh = shapes.icosphere(3)
    assert mesh.n_vertices == 642
    ref = shapes.sphere_spectrum(100)
    err = {m: cshape.shape_dna(mesh, 100, mass=m)[1:] / ref[1:] - 1 for m in MASSES}
    assert err["consistent"].min() > 0  # every one too high
    assert err["lumped"].max() < 0  # every one too low
    e = {m: np.abs(v).max() for m, v in err.items()}
    assert e["mixed"] < 0.015  # measured 1.24 %
    assert e["mixed"] < e["consistent"] / 5 and e["mixed"] < e["lumped"] / 5


def test_sphere_2562_and_its_multiplicities():
    mesh = shapes.icosphere(4)
    ref = shapes.sphere_spectrum(100)
    lam = cshape.shape_dna(mesh, 100, mass="mixed")
    assert lam[0] == 0.0 or abs(lam[0]) < 1e-10
    assert rel_err(lam, ref).max() < 0.005  # measured 0.34 %
    for ell in range(1, 10):  # 2l+1 copies of l(l+1), none missing, none extra
        near = np.abs(lam / (ell * (ell + 1)) - 1) < 0.01
        assert near.sum() == 2 * ell + 1, ell


@pytest.mark.parametrize("bc, bound", [("dirichlet", 0.03), ("neumann", 0.01)])
def test_rectangle(bc, bound):
    mesh = rectangle(16)
    e = worst(mesh, 10, rectangle_spectrum(10, bc), bc)
    assert e["mixed"] < bound  # measured 2.3 % and 0.78 %
    assert e["mixed"] < min(e["consistent"], e["lumped"]) / 3


@pytest.mark.parametrize("bc", ["dirichlet", "neumann"])
def test_disk_bessel_zeros(bc):
    mesh = shapes.disk(12)
    e = worst(mesh, 20, disk_spectrum(20, bc), bc)
    assert e["mixed"] < 0.015  # measured 1.2 % and 0.49 %
    assert e["mixed"] < min(e["consistent"], e["lumped"]) / 3


def slope(sizes, errors):
    return -np.polyfit(np.log(sizes), np.log(errors), 1)[0]


def test_convergence_orders():
    # the equilateral triangle's midpoint subdivisions repeat one pattern at half the size:
    # consistent and lumped converge as h^2, and their average cancels the h^2 term
    ref = equilateral_dirichlet(6)
    h = [2.0**-s for s in (3, 4, 5)]
    errs = {m: [] for m in MASSES}
    for s in (3, 4, 5):
        for m, e in worst(equilateral(s), 6, ref, "dirichlet").items():
            errs[m].append(e)
    assert 1.8 < -slope(h, errs["consistent"]) < 2.2
    assert 1.8 < -slope(h, errs["lumped"]) < 2.2
    assert 3.5 < -slope(h, errs["mixed"]) < 4.5
    # the sphere: the polyhedron differs from the sphere by O(h^2) in its metric, so every
    # mass converges as h^2; mixed with a constant several times smaller
    ref = shapes.sphere_spectrum(10)
    sph = {m: [] for m in MASSES}
    for sub in (2, 3, 4):
        for m, e in worst(shapes.icosphere(sub), 10, ref).items():
            sph[m].append(e)
    h = [2.0**-s for s in (2, 3, 4)]
    for m in MASSES:
        assert 1.8 < -slope(h, sph[m]) < 2.2, m
    assert np.all(np.array(sph["mixed"]) < np.array(sph["consistent"]) / 5)


# ----------------------------------------------------------------------------- the default
def test_default_is_eq5_bit_for_bit():
    mesh = shapes.torus(24, 12)
    A, B = cshape.fem_matrices(mesh)
    A2, B2 = cshape.fem_matrices(mesh, mass="consistent")
    assert (A != A2).nnz == 0 and (B != B2).nnz == 0
    # Eq. (5): |t|/12 off the diagonal of each triangle, |t|/6 on it
    V, F = mesh.vertices, mesh.faces
    t = 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
    ref = np.zeros((mesh.n_vertices,) * 2)
    for (i, j, k), a in zip(F, t, strict=True):
        for p in (i, j, k):
            for q in (i, j, k):
                ref[p, q] += a / 6 if p == q else a / 12
    np.testing.assert_allclose(B.toarray(), ref, rtol=1e-12, atol=0)
    plain = solve_eigenproblem(A, B, 30, return_vectors=False)
    np.testing.assert_array_equal(cshape.shape_dna(mesh, 30), plain)
    np.testing.assert_array_equal(cshape.eigenbasis(mesh, 8).lam,
                                  cshape.eigenbasis(mesh, 8, mass="consistent").lam)
    assert cshape.eigenbasis(mesh, 8).mass == "consistent"
    assert mesh_key(mesh) == mesh_key(mesh, SpectrumSettings(mass="consistent")) != mesh_key(
        mesh, SpectrumSettings(mass="mixed"))


# ----------------------------------------------------------------------------- errors
@pytest.mark.parametrize("bad, err", [("mixd", ValueError), ("mixed ", ValueError),
                                      (0.5, TypeError), (None, TypeError)])
def test_bad_mass_named_everywhere(bad, err):
    mesh = shapes.icosphere(1)
    match = r"mass must be one of \{'consistent', 'lumped', 'mixed'\}, got "
    with pytest.raises(err, match=match):
        cshape.fem_matrices(mesh, mass=bad)
    with pytest.raises(err, match=match):
        cshape.shape_dna(mesh, 5, mass=bad)
    with pytest.raises(err, match=match):
        cshape.eigenbasis(mesh, 5, mass=bad)
    with pytest.raises(err, match=match):
        describe([mesh], N=5, mass=bad, cache_dir=False, progress=False)
    with pytest.raises(err, match=match):
        DescriptorTable(["a"], [[0.0, 1.0, 2.0]], [1.0], mass=bad)


def test_mass_is_case_insensitive_like_every_option():
    mesh = shapes.icosphere(1)
    np.testing.assert_array_equal(cshape.shape_dna(mesh, 5, mass="Mixed"),
                                  cshape.shape_dna(mesh, 5, mass="mixed"))
    assert cshape.eigenbasis(mesh, 5, mass="MIXED").mass == "mixed"


# ----------------------------------------------------------------------------- layers
def test_eigenbasis_mixed():
    mesh = shapes.icosphere(2)
    b = cshape.eigenbasis(mesh, 10, mass="mixed")
    assert b.mass == "mixed" and "mass='mixed'" in repr(b)
    np.testing.assert_allclose(b.lam, cshape.shape_dna(mesh, 10, mass="mixed"),
                               rtol=1e-10, atol=1e-12)
    # B-orthonormal in the mixed mass matrix
    np.testing.assert_allclose(b.phi.T @ (b.B @ b.phi), np.eye(10), atol=1e-9)


def test_describe_table_and_files_record_the_mass(tmp_path):
    meshes = [("s", "sphere", shapes.icosphere(2)), ("t", "torus", shapes.torus(16, 8))]
    cache = tmp_path / "cache"
    plain = describe(meshes, N=12, cache_dir=cache, progress=False)
    mixed = describe(meshes, N=12, cache_dir=cache, progress=False, mass="mixed")
    assert plain.mass == "consistent" and mixed.mass == "mixed"
    assert "mass='mixed'" in repr(mixed) and "mass='consistent'" in repr(plain)
    assert not mixed.cached.any()  # cached apart from the consistent spectra
    np.testing.assert_array_equal(mixed.lam[0],
                                  cshape.shape_dna(meshes[0][2], 12, mass="mixed"))
    again = describe(meshes, N=12, cache_dir=cache, progress=False, mass="mixed")
    assert again.cached.all()
    np.testing.assert_array_equal(again.lam, mixed.lam)
    assert mixed.select([1]).mass == "mixed"
    for suffix in ("npz", "csv"):
        back = DescriptorTable.load(mixed.save(tmp_path / f"t.{suffix}"))
        assert back.mass == "mixed" and "mass='mixed'" in repr(back)
        np.testing.assert_array_equal(back.lam, mixed.lam)
    assert json.loads((tmp_path / "t.csv.json").read_text())["mass"] == "mixed"


def test_command_line_describe_and_query_with_the_tables_mass(tmp_path, capsys):
    from conftest import write_off

    write_off(tmp_path / "m" / "ball.off", shapes.icosphere(2))
    write_off(tmp_path / "m" / "ring.off", shapes.torus(16, 8))
    write_off(tmp_path / "q" / "ball2.off", shapes.icosphere(2))
    out = tmp_path / "t.npz"
    capsys.readouterr()
    assert cli_main(["describe", str(tmp_path / "m"), "-N", "12", "--mass", "mixed",
                     "--no-cache", "--out", str(out)]) == 0
    assert "mass='mixed'" in capsys.readouterr().err  # the summary line says so
    table = DescriptorTable.load(out)
    assert table.mass == "mixed"
    np.testing.assert_array_equal(table.lam[table.index("ball")], cshape.shape_dna(
        cshape.load_mesh(tmp_path / "m" / "ball.off"), 12, mass="mixed"))
    # a mesh file is described with the table's mass: its copy in the table is at distance 0
    assert cli_main(["query", str(out), str(tmp_path / "q" / "ball2.off"), "-k", "1",
                     "--no-cache"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert "(mass='mixed')" in lines[0]
    rank, dist, name = lines[2].split()[:3]
    assert name == "ball" and float(dist) == 0.0
    assert cli_main(["query", str(out), "ball", "--json", "-k", "1"]) == 0
    assert json.loads(capsys.readouterr().out)["mass"] == "mixed"
    # without --mass the table holds the paper's consistent spectra
    plain = tmp_path / "p.csv"
    assert cli_main(["describe", str(tmp_path / "m"), "-N", "12", "--no-cache", "-q",
                     "--out", str(plain)]) == 0
    assert DescriptorTable.load(plain).mass == "consistent"
    with pytest.raises(SystemExit) as exc:
        cli_main(["describe", str(tmp_path / "m"), "--mass", "average"])
    assert exc.value.code == 2
    assert "--mass" in capsys.readouterr().err
