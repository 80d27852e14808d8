"""Known answers: linear FEM spectra converge to the exact Laplace-Beltrami spectra at order 2."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from conftest import pairs
from scipy.special import jn_zeros, jnp_zeros

import cshape
from cshape import shapes


def square_exact(K, dirichlet):
    r = range(1, 40) if dirichlet else range(40)
    return np.sort([np.pi**2 * (m * m + n * n) for m in r for n in r])[:K]


def disk_exact(K, dirichlet):
    vals = []
    for m in range(30):
        if dirichlet:
            z = jn_zeros(m, 20)
        else:
            z = np.concatenate([[0.0], jnp_zeros(0, 19)]) if m == 0 else jnp_zeros(m, 20)
        for v in z:
            vals += [v * v] * (1 if m == 0 else 2)  # cos and sin modes for m > 0
    return np.sort(vals)[:K]


def hemisphere_exact(K, dirichlet):
    # spherical harmonics Y_l^m that are even (Neumann) or odd (Dirichlet) about the equator
    vals = [
        ell * (ell + 1)
        for ell in range(40)
        for m in range(-ell, ell + 1)
        if ((ell + m) % 2 == 1) == dirichlet
    ]
    return np.sort(vals)[:K]


def rel_err(lam, exact):
    nz = exact > 0
    assert np.all(np.abs(lam[~nz]) < 1e-8)
    return np.max(np.abs(lam[nz] - exact[nz]) / exact[nz])


def test_sphere_multiplicities_and_order_of_convergence():
    N = 49  # l = 0..6
    exact = shapes.sphere_spectrum(N)
    errs = [rel_err(cshape.shape_dna(shapes.icosphere(s), N=N), exact) for s in (3, 4, 5)]
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    # each subdivision halves h: linear FEM eigenvalues converge as h^2
    assert np.all(orders > 1.9), orders
    assert errs[-1] < 0.01
    lam = cshape.shape_dna(shapes.icosphere(4), N=N)
    assert lam[0] == 0.0
    # multiplicity 2l+1 of l(l+1): the clusters are tight, and separated
    for ell in range(1, 7):
        block = lam[ell * ell : (ell + 1) ** 2]
        assert len(block) == 2 * ell + 1
        assert np.ptp(block) / (ell * (ell + 1)) < 0.01


@pytest.mark.slow
def test_first_100_on_40k_sphere_within_half_percent():
    mesh = shapes.icosphere(6)
    assert mesh.n_vertices == 40962
    lam = cshape.shape_dna(mesh, N=100)
    assert rel_err(lam, shapes.sphere_spectrum(100)) < 0.005


@pytest.mark.parametrize(
    "make, exact",
    [
        (shapes.square, square_exact),
        (shapes.disk, disk_exact),
        (shapes.hemisphere, hemisphere_exact),
    ],
    ids=["square", "disk", "hemisphere"],
)
@pytest.mark.parametrize("bc", ["neumann", "dirichlet"])
def test_flat_and_curved_domains_with_boundary(make, exact, bc):
    K = 30
    e = exact(K, bc == "dirichlet")
    errs = [rel_err(cshape.shape_dna(make(n), N=K, bc=bc), e) for n in (16, 32)]
    assert errs[1] < 0.05  # measured 0.009-0.044 over these cases
    assert np.log2(errs[0] / errs[1]) > 1.9  # order 2


def test_square_low_modes_are_accurate():
    lam = cshape.shape_dna(shapes.square(48), N=6) / np.pi**2
    np.testing.assert_allclose(lam, [0, 1, 1, 2, 4, 4], atol=0.01)
    lam_d = cshape.shape_dna(shapes.square(48), N=3, bc="dirichlet") / np.pi**2
    np.testing.assert_allclose(lam_d, [2, 5, 5], rtol=0.005)


def test_eigenpairs_are_b_orthonormal_and_satisfy_eq3():
    mesh = shapes.hemisphere(8)
    for bc in ("neumann", "dirichlet"):
        lam, phi = pairs(mesh, N=12, bc=bc)
        assert phi.shape == (mesh.n_vertices, 12)
        A, B = cshape.fem_matrices(mesh)  # full Neumann matrices over all vertices
        if bc == "dirichlet":
            assert np.abs(phi[mesh.boundary_vertices]).max() == 0
            inner = np.setdiff1d(np.arange(mesh.n_vertices), mesh.boundary_vertices)
            A, B = A[inner][:, inner], B[inner][:, inner]
            phi = phi[inner]
        np.testing.assert_allclose(phi.T @ (B @ phi), np.eye(12), atol=1e-8)
        # A f = -lam B f (Eq. 3)
        res = A @ phi + (B @ phi) * lam
        assert np.abs(res).max() < 1e-8 * max(1.0, lam.max())


def test_lumped_mass_also_converges():
    lam = cshape.shape_dna(shapes.icosphere(4), N=16, mass="lumped")
    assert rel_err(lam, shapes.sphere_spectrum(16)) < 0.02


def test_multi_component_mesh_has_one_zero_per_component():
    a, b = shapes.icosphere(2), shapes.icosphere(2, radius=2.0)
    V = np.vstack([a.vertices, b.vertices + 5])
    F = np.vstack([a.faces, b.faces + a.n_vertices])
    with pytest.warns(cshape.CShapeWarning, match="2 connected components"):
        lam = cshape.shape_dna((V, F), N=6)
    np.testing.assert_allclose(lam[:2], 0, atol=1e-10)
    assert lam[2] > 0.4  # radius-2 sphere: 2/4 = 0.5 (three times), then radius 1: 2


def test_N_validation():
    m = shapes.icosphere(1)  # 42 vertices
    with pytest.raises(ValueError, match=r"N=50 eigenvalues requested.*only 42 unknowns"):
        cshape.shape_dna(m, N=50)
    with pytest.raises(ValueError, match="N must be an integer >= 1, got 0"):
        cshape.shape_dna(m, N=0)
    with pytest.raises(TypeError, match="N must be an integer"):
        cshape.shape_dna(m, N=2.5)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert len(cshape.shape_dna(m, N=42)) == 42  # every eigenvalue of a tiny mesh


def test_scale_invariance_after_area_normalisation():
    m = shapes.torus(24, 12)
    lam1 = cshape.shape_dna(m, N=20)
    big = cshape.Mesh(m.vertices * 3.7, m.faces)
    lam2 = cshape.shape_dna(big, N=20)
    np.testing.assert_allclose(lam2 * 3.7**2, lam1, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(
        cshape.normalize(lam2, big.area), cshape.normalize(lam1, m.area), rtol=1e-9, atol=1e-9
    )


@pytest.mark.parametrize("fn", [cshape.shape_dna, cshape.eigenbasis])
def test_every_parameter_of_the_spectrum_functions_is_described(fn):
    """The API page lists each parameter with a sentence, bc and mass included."""
    docscrape = pytest.importorskip("numpydoc.docscrape")
    params = {p.name: " ".join(p.desc) for p in docscrape.FunctionDoc(fn)["Parameters"]}
    assert {"mesh", "N", "bc", "mass"} <= set(params)
    for name in ("N", "bc", "mass"):
        assert len(params[name]) > 20, (name, params[name])
    assert "Eq. (5)" in params["mass"] and "fem_matrices" in params["bc"]


def test_spectrum_settings_check_once_and_travel_as_one_value(tmp_path):
    """The settings of a spectrum are one frozen value: checked where they enter, spelt one
    way, carried by describe to its table, which describes one more mesh the same way."""
    import dataclasses

    from cshape.spectrum import SpectrumSettings

    s = SpectrumSettings(12, bc="Neumann", mass="MIXED")
    assert (s.N, s.bc, s.mass, s.refine) == (12, "neumann", "mixed", "none")
    same = SpectrumSettings(12, mass="mixed")
    assert s == same and hash(s) == hash(same)
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.N = 3  # type: ignore[misc]
    for kwargs, exc, match in [
            (dict(N=0), ValueError, "N must be an integer >= 1, got 0"),
            (dict(N=2.0), TypeError, "N must be an integer, got float 2.0"),
            (dict(mass="lump"), ValueError, "mass must be one of"),
            (dict(refine="richardson"), ValueError, "refine must be one of")]:
        with pytest.raises(exc, match=match):
            SpectrumSettings(**kwargs)
    sphere = shapes.icosphere(2)
    np.testing.assert_array_equal(cshape.shape_dna(sphere, **s.as_kwargs()),
                                  cshape.shape_dna(sphere, 12, mass="mixed"))
    table = cshape.describe([("a", "", sphere)], N=12, mass="mixed", cache_dir=False,
                            progress=False)
    assert table.settings == s
    again = cshape.describe([("b", "", shapes.torus(16, 8))], **table.settings.as_kwargs(),
                            cache_dir=False, progress=False)
    assert again.settings == s
    table.save(tmp_path / "t.csv")
    assert cshape.DescriptorTable.load(tmp_path / "t.csv").settings == s
