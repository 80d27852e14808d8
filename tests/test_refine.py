"""``refine='extrapolate'``: Richardson extrapolation over one midpoint subdivision.

Known answers (sphere, flat square and disk with both boundary conditions, equilateral
triangle, torus), the convergence orders, repeated eigenvalues, mesh pieces, the default
left bit for bit, and the option along the batch layer, the table and the command line.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import equilateral, equilateral_dirichlet
from scipy.special import jn_zeros, jnp_zeros

import cshape
from cshape import _refine, shapes
from cshape.batch import DescriptorTable, describe
from cshape.batch.cache import mesh_key
from cshape.batch.work import Task
from cshape.cli import main as cli_main
from cshape.mesh import Mesh
from cshape.spectrum import SpectrumSettings, solve_eigenproblem

EX = "extrapolate"


def rel_err(lam, ref):
    pos = ref > 0
    return np.abs(lam[pos] / ref[pos] - 1)


def square_spectrum(n, bc):
    k = np.arange(1 if bc == "dirichlet" else 0, 30)
    return np.sort(np.add.outer(k**2, k**2).ravel())[:n] * np.pi**2


# ----------------------------------------------------------------------------- known answers
@pytest.mark.parametrize("mass", ["consistent", "lumped"])
def test_sphere_642_every_eigenvalue_within_one_percent(mass):
    mesh = shapes.icosphere(3)
    assert mesh.n_vertices == 642
    ref = shapes.sphere_spectrum(100)
    lam = cshape.shape_dna(mesh, 100, mass=mass, refine=EX)
    assert lam[0] == 0.0
    assert rel_err(lam, ref).max() < 0.01
    assert rel_err(cshape.shape_dna(mesh, 100, mass=mass), ref).max() > 0.1  # 14.7 %, 12.6 %


def test_sphere_clusters_found_whole_and_a_cut_cluster_pairs_in_order():
    mesh = shapes.icosphere(3)
    lam = cshape.shape_dna(mesh, 100, refine=EX)
    for ell in range(1, 10):  # 2l+1 copies of l(l+1), none missing, none extra
        near = np.abs(lam / (ell * (ell + 1)) - 1) < 0.02
        assert near.sum() == 2 * ell + 1, ell
    # N = 12 cuts the cluster l = 3 (indices 9..15): its first members are those of N = 16
    np.testing.assert_allclose(cshape.shape_dna(mesh, 12, refine=EX),
                               cshape.shape_dna(mesh, 16, refine=EX)[:12], rtol=1e-9)


def test_subdivision_lowers_every_eigenvalue_min_max():
    # the linear functions of a mesh are linear on its midpoint subdivision (nested spaces)
    for mesh, bc in ((shapes.icosphere(2), "neumann"), (shapes.disk(6), "dirichlet")):
        fine = _refine.midpoint_subdivision(mesh)
        assert fine.n_faces == 4 * mesh.n_faces
        assert fine.n_vertices == mesh.n_vertices + len(mesh.edges)
        assert np.isclose(fine.area, mesh.area, rtol=1e-12)
        a = cshape.shape_dna(mesh, 30, bc=bc)
        b = cshape.shape_dna(fine, 30, bc=bc)
        assert np.all(b <= a * (1 + 1e-10))


def test_midpoint_subdivision_children_and_the_icosphere():
    """Each face's four children: its corners' triangles (starting at the corner) and the
    middle one; the icosphere is this subdivision, its new vertices pushed to the sphere."""
    mesh = shapes.icosphere(1)
    fine = _refine.midpoint_subdivision(mesh)
    m, n = mesh.n_faces, mesh.n_vertices
    F, G = mesh.faces, fine.faces
    np.testing.assert_array_equal(G[:m, 0], F[:, 0])
    np.testing.assert_array_equal(G[m:2 * m, 0], F[:, 1])
    np.testing.assert_array_equal(G[2 * m:3 * m, 0], F[:, 2])
    assert (G[3 * m:] >= n).all()  # the middle triangles have only new vertices
    mids = fine.vertices[n:]
    np.testing.assert_allclose(mids, 0.5 * mesh.vertices[mesh.edges].sum(axis=1), rtol=0, atol=0)
    # every child keeps its parent's orientation: normals agree
    def normals(mm):
        v = mm.vertices[mm.faces]
        return np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    parent = np.tile(normals(mesh), (4, 1))
    assert (np.einsum("ij,ij->i", normals(fine), parent) > 0).all()
    ico = shapes.icosphere(2)
    np.testing.assert_array_equal(ico.faces, fine.faces)
    np.testing.assert_array_equal(
        ico.vertices, fine.vertices / np.linalg.norm(fine.vertices, axis=1, keepdims=True))


@pytest.mark.parametrize("bc", ["dirichlet", "neumann"])
def test_flat_square(bc):
    mesh = shapes.square(16)
    ref = square_spectrum(40, bc)
    lin = rel_err(cshape.shape_dna(mesh, 40, bc=bc), ref).max()
    ext = rel_err(cshape.shape_dna(mesh, 40, bc=bc, refine=EX), ref).max()
    assert ext < 0.01 and ext < lin / 10


@pytest.mark.parametrize("bc", ["dirichlet", "neumann"])
def test_flat_disk(bc):
    vals = []
    for order in range(12):
        z = jn_zeros(order, 8) if bc == "dirichlet" else jnp_zeros(order, 8)
        if bc == "neumann" and order == 0:
            z = np.concatenate([[0.0], z])
        vals += list(z**2) * (1 if order == 0 else 2)
    ref = np.sort(vals)[:20]
    mesh = shapes.disk(12)
    lin = rel_err(cshape.shape_dna(mesh, 20, bc=bc), ref).max()
    ext = rel_err(cshape.shape_dna(mesh, 20, bc=bc, refine=EX), ref).max()
    # the polygon is not the disk: a geometric error O(h^2) that does not grow with lam
    assert ext < 0.003 and ext < lin / 10


def test_torus_against_a_much_finer_mesh():
    ref = cshape.shape_dna(shapes.torus(96, 48), 40, refine=EX)
    mesh = shapes.torus(32, 16)
    lin = rel_err(cshape.shape_dna(mesh, 40), ref).max()
    ext = rel_err(cshape.shape_dna(mesh, 40, refine=EX), ref).max()
    assert ext < 0.03 and ext < lin / 5  # measured: 2.3 %


def slope(sizes, errors):
    return -np.polyfit(np.log(sizes), np.log(errors), 1)[0]


def test_convergence_orders_two_and_four():
    # the equilateral triangle: midpoint subdivision keeps its pattern, so the h^2 term of
    # the error is the same at both resolutions and extrapolation removes it
    ref = equilateral_dirichlet(6)
    h, lin, ext = [], [], []
    for s in (3, 4, 5):
        mesh = equilateral(s)
        h.append(2.0**-s)
        lin.append(rel_err(cshape.shape_dna(mesh, 6, bc="dirichlet"), ref).max())
        ext.append(rel_err(cshape.shape_dna(mesh, 6, bc="dirichlet", refine=EX), ref).max())
    assert 1.8 < -slope(h, lin) < 2.2
    assert 3.5 < -slope(h, ext) < 4.5


# ----------------------------------------------------------------------------- the default
def test_default_is_the_linear_fem_bit_for_bit():
    mesh = shapes.torus(24, 12)
    A, B = cshape.fem_matrices(mesh)
    plain = solve_eigenproblem(A, B, 30, return_vectors=False)
    np.testing.assert_array_equal(cshape.shape_dna(mesh, 30), plain)
    np.testing.assert_array_equal(cshape.shape_dna(mesh, 30, refine="none"), plain)
    assert mesh_key(mesh) == mesh_key(mesh, SpectrumSettings(refine="none")) != mesh_key(
        mesh, SpectrumSettings(refine=EX))


def test_pieces_keep_their_zero_modes():
    a, b = shapes.icosphere(1), shapes.icosphere(1)
    two = Mesh(np.vstack([a.vertices, b.vertices + 3.0]),
               np.vstack([a.faces, b.faces + a.n_vertices]))
    with pytest.warns(cshape.CShapeWarning, match="2 connected components"):
        lam = cshape.shape_dna(two, 10, refine=EX)
    assert (lam[:2] == 0).all() and (lam[2:] > 0).all()
    # the union of the pieces' spectra: 2 twice, once per piece and axis
    one = cshape.shape_dna(a, 5, refine=EX)
    np.testing.assert_allclose(lam[2:8], np.repeat(one[1:4], 2), rtol=1e-8)


@pytest.mark.parametrize("bad, err, match", [
    ("richardson", ValueError, "refine"), ("Extrapolate ", ValueError, "refine"),
    (True, TypeError, "refine"), (None, TypeError, "refine")])
def test_bad_refine_named_everywhere(bad, err, match):
    mesh = shapes.icosphere(1)
    with pytest.raises(err, match=match):
        cshape.shape_dna(mesh, 5, refine=bad)
    with pytest.raises(err, match=match):
        describe([mesh], N=5, refine=bad, cache_dir=False, progress=False)
    with pytest.raises(err, match=match):
        DescriptorTable(["a"], [[0.0, 1.0, 2.0]], [1.0], refine=bad)


def test_a_long_solve_of_the_subdivided_mesh_warns(monkeypatch):
    from cshape import spectrum

    # estimates: 0.0075 s for the 162 vertices, 0.28 s for the 642 of the subdivision
    monkeypatch.setattr(spectrum, "LONG_SOLVE_SECONDS", 0.1)
    mesh = shapes.icosphere(2)
    with pytest.warns(cshape.CShapeWarning, match="solves its midpoint subdivision too: "
                      "N=20 eigenvalues of a mesh of 642 vertices"):
        cshape.shape_dna(mesh, 20, refine=EX)


def test_too_few_unknowns_for_N_is_the_coarse_meshs_error():
    with pytest.raises(ValueError, match="N=50 eigenvalues requested"):
        cshape.shape_dna(shapes.icosphere(1), 50, refine=EX)


# ----------------------------------------------------------------------------- layers
def test_describe_table_and_files_record_the_kind(tmp_path):
    meshes = [("s", "sphere", shapes.icosphere(2)), ("t", "torus", shapes.torus(16, 8))]
    cache = tmp_path / "cache"
    plain = describe(meshes, N=12, cache_dir=cache, progress=False)
    ext = describe(meshes, N=12, cache_dir=cache, progress=False, refine=EX)
    assert plain.refine == "none" and ext.refine == EX and "refine='extrapolate'" in repr(ext)
    assert not ext.cached.any()  # cached apart from the linear spectra
    np.testing.assert_array_equal(ext.lam[0], cshape.shape_dna(meshes[0][2], 12, refine=EX))
    again = describe(meshes, N=12, cache_dir=cache, progress=False, refine=EX)
    assert again.cached.all()
    np.testing.assert_array_equal(again.lam, ext.lam)
    assert ext.select([1]).refine == EX
    for suffix in ("npz", "csv"):
        back = DescriptorTable.load(ext.save(tmp_path / f"t.{suffix}"))
        assert back.refine == EX
        np.testing.assert_array_equal(back.lam, ext.lam)
    # a table written before the option existed holds linear FEM spectra
    side = tmp_path / "t.csv.json"
    meta = json.loads(side.read_text())
    del meta["refine"]
    side.write_text(json.dumps(meta))
    assert DescriptorTable.load(tmp_path / "t.csv").refine == "none"


def test_command_line_describe_refine(tmp_path, capsys):
    from conftest import write_off

    write_off(tmp_path / "m" / "ball.off", shapes.icosphere(2))
    out = tmp_path / "t.npz"
    assert cli_main(["describe", str(tmp_path / "m"), "-N", "12", "--refine", EX,
                     "--no-cache", "-q", "--out", str(out)]) == 0
    table = DescriptorTable.load(out)
    assert table.refine == EX
    np.testing.assert_array_equal(table.lam[0], cshape.shape_dna(
        cshape.load_mesh(tmp_path / "m" / "ball.off"), 12, refine=EX))
    with pytest.raises(SystemExit) as exc:
        cli_main(["describe", str(tmp_path / "m"), "--refine", "p2"])
    assert exc.value.code == 2
    assert "--refine" in capsys.readouterr().err


def test_describe_counts_the_subdivisions_in_its_estimate(monkeypatch):
    import cshape.batch.run as run

    monkeypatch.setattr(run, "estimate_seconds", lambda n, N: n / 2.0)  # linear in n
    monkeypatch.setattr(run, "_ESTIMATE_MIN_N", 5)
    mesh = shapes.icosphere(2)  # 162 vertices: 81 s, 405 s with the 648 of a subdivision
    with pytest.warns(cshape.CShapeWarning, match=r"long run ahead: 1 eigensolve of N=6 \(and "
                      r"of their midpoint subdivisions\), about 7 min in all"):
        run._warn_long_run([Task(0, mesh, SpectrumSettings(6, refine=EX), None, None)],
                           [("ball", "", mesh)], SpectrumSettings(6, refine=EX))
