"""Point signatures (HKS, WKS, SI-HKS, heat kernel and trace) and point matching.

Known answers (the sphere), properties (invariances, scale, refinement, integrals) and one
``pytest.raises`` per bad argument.  Meshes are built in code; eigenpairs are computed once
per module.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

import cshape
from cshape import shapes
from cshape import signatures as sg
from cshape.signatures import heat_kernel, heat_trace, match_points, si_hks

N = 100  # l = 0..9 on the sphere: whole multiplets (2l + 1 copies each)


def _ellipsoid(level):
    """An ellipsoid with three different axes (no repeated eigenvalues), icosphere levels
    share their first vertices: level s has the 10 * 4**(s-1) + 2 vertices of level s-1 first."""
    m = shapes.icosphere(level)
    return cshape.Mesh(m.vertices * [1.0, 0.7, 0.5], m.faces)


def _basis(lam, phi, **kw):
    """An Eigenbasis of hand-made pairs (identity mass: the formulas do not use B)."""
    phi = np.asarray(phi, dtype=float)
    return cshape.Eigenbasis(lam, phi, sp.identity(len(phi), format="csr"), **kw)


@pytest.fixture(scope="module")
def sphere():
    m = shapes.icosphere(4)
    return m, cshape.eigenbasis(m, N)


@pytest.fixture(scope="module")
def ellipsoid():
    m = _ellipsoid(3)
    return m, cshape.eigenbasis(m, 40)


# ---------------------------------------------------------------------- known answers
def test_sphere_hks_is_constant_and_equals_trace_over_area(sphere):
    m, b = sphere
    t = sg.hks_times(b)
    h = cshape.hks(b, t)
    assert h.shape == (m.n_vertices, 100)
    # addition theorem: sum_m Y_lm(x)^2 = (2l + 1) / (4 pi) at every point of the unit sphere
    assert (np.ptp(h, axis=0) / h.mean(axis=0)).max() < 1e-2
    Z = heat_trace(b, t)
    np.testing.assert_allclose(h, np.broadcast_to(Z / m.area, h.shape), rtol=1e-2)
    # and the discrete error shrinks with the mesh (O(h^2): about 4x per level)
    m3 = shapes.icosphere(3)
    b3 = cshape.eigenbasis(m3, N)
    Z3 = heat_trace(b3, t)
    err3 = np.abs(cshape.hks(b3, t) / (Z3 / m3.area) - 1).max()
    err4 = np.abs(h / (Z / m.area) - 1).max()
    assert err4 < err3 / 3


def test_sphere_heat_trace_known_values():
    # exact sphere spectrum l(l+1) with multiplicity 2l+1
    b = _basis(shapes.sphere_spectrum(N), np.eye(N), area=2.0)
    t = np.array([0.05, 0.5, 2.0])
    expected = [sum((2 * l + 1) * np.exp(-l * (l + 1) * ti) for l in range(10)) for ti in t]
    np.testing.assert_allclose(heat_trace(b, t), expected, rtol=1e-13)
    # unit-area scaling: the trace at time t of lam * area
    np.testing.assert_allclose(heat_trace(b, t / 2.0, normalization="area"), expected,
                               rtol=1e-13)


def test_hks_integrates_to_heat_trace_with_lumped_mass():
    # int k_t(x, x) dx = sum_i exp(-lam_i t) int phi_i^2 = Z(t); exact when the integral
    # of phi_i^2 is 1^T B phi_i^2, i.e. for the lumped (diagonal) mass matrix
    m = _ellipsoid(3)
    b = cshape.eigenbasis(m, 30, mass="lumped")
    B = b.B
    t = sg.hks_times(b, 10)
    np.testing.assert_allclose((B @ cshape.hks(b, t)).sum(axis=0),
                               heat_trace(b, t), rtol=1e-10)
    ht = cshape.hks(b, t, scale="trace")
    np.testing.assert_allclose((B @ ht).sum(axis=0), 1.0, rtol=1e-10)
    w = cshape.wks(b, n_energies=30)
    np.testing.assert_allclose((B @ w).sum(axis=0), 1.0, rtol=1e-10)


def test_hks_times_are_sun_et_al_defaults():
    lam = np.array([0.0, 2.0, 6.0, 12.0])
    t = sg.hks_times(_basis(lam, np.eye(4)), 5)
    assert t[0] == pytest.approx(4 * np.log(10) / 12.0)
    assert t[-1] == pytest.approx(4 * np.log(10) / 2.0)
    np.testing.assert_allclose(np.diff(np.log(t)), np.log(6.0) / 4)


def test_wks_energies_are_aubry_et_al_defaults():
    lam = np.array([0.0, 1.0, 3.0, np.e**4])
    e, sigma = sg.wks_energies(_basis(lam, np.eye(4)), 40)
    assert sigma == pytest.approx(7 * 4.0 / 40)
    assert e[0] == pytest.approx(1.4) and e[-1] == pytest.approx(2.6)  # 2 sigma from the ends
    assert len(e) == 40 and (np.diff(e) > 0).all()


def test_wks_by_hand():
    # two vertices, eigenpairs lam = (0, 1, e): WKS at e = 0.5 with sigma = 1
    lam = np.array([0.0, 1.0, np.e])
    phi = np.array([[1.0, 2.0, 3.0], [1.0, -1.0, 0.5]])
    g = np.exp(-np.array([0.5, 0.5]) ** 2 / 2)  # log 1 = 0, log e = 1: both 0.5 away
    expected = np.array([(4 * g[0] + 9 * g[1]), (1 * g[0] + 0.25 * g[1])]) / g.sum()
    b = _basis(lam, phi)
    np.testing.assert_allclose(cshape.wks(b, 0.5, 1.0)[:, 0], expected)
    np.testing.assert_allclose(cshape.wks(b, [0.5], 1.0, scale="none")[:, 0],
                               expected * g.sum())


def test_hks_by_hand():
    lam = np.array([0.0, 1.0, 2.0])
    phi = np.array([[1.0, 2.0, 3.0], [1.0, -1.0, 0.5]])
    t = np.array([0.5, 1.0])
    E = np.exp(-np.outer(lam, t))
    b = _basis(lam, phi)
    np.testing.assert_allclose(cshape.hks(b, t), (phi**2) @ E)
    np.testing.assert_allclose(cshape.hks(b, t, scale="trace"),
                               (phi**2) @ E / E.sum(axis=0))
    # the shape scaled to unit area: lam * area, phi * sqrt(area) (here area = B.sum() = 2)
    np.testing.assert_allclose(cshape.hks(b, t, normalization="area"),
                               2 * (phi**2) @ np.exp(-np.outer(2 * lam, t)))


def test_hks_agrees_with_lapy(ellipsoid):
    # the peer's heat kernel diagonal (lapy.heat.diagonal) from the peer's own eigenpairs
    lapy = pytest.importorskip("lapy")
    from lapy import heat

    m, b = ellipsoid
    ev, ef = lapy.Solver(lapy.TriaMesh(m.vertices, m.faces)).eigs(k=40)
    t = sg.hks_times(b, 10)
    ref = heat.diagonal(t[None, :], np.arange(m.n_vertices), ef, ev[:, None], 40)
    np.testing.assert_allclose(cshape.hks(b, t), ref, rtol=1e-8)


# ---------------------------------------------------------------------- heat kernel
def test_heat_kernel_symmetric_conserves_heat_and_diagonal_is_hks(ellipsoid):
    m, b = ellipsoid
    B = cshape.fem_matrices(m)[1]
    src = np.array([0, 7, 300])
    t = 0.05
    k = heat_kernel(b, t, src)
    assert k.shape == (m.n_vertices, 3)
    np.testing.assert_allclose(k[src], k[src].T, rtol=1e-12)
    np.testing.assert_allclose((B @ k).sum(axis=0), 1.0, rtol=1e-10)  # phi_i, i > 0, B-orth to 1
    np.testing.assert_allclose(k[src, [0, 1, 2]], cshape.hks(b, t)[src, 0])
    np.testing.assert_allclose(heat_kernel(b, t, 7), k[:, 1])
    # as t grows the heat spreads out to the uniform 1 / area
    k_late = heat_kernel(b, 50.0, 0)
    np.testing.assert_allclose(k_late, 1 / m.area, rtol=1e-6)


# ---------------------------------------------------------------------- invariances
def _random_rotation(rng):
    Q, R = np.linalg.qr(rng.standard_normal((3, 3)))
    Q = Q * np.sign(np.diag(R))
    return Q if np.linalg.det(Q) > 0 else -Q


def test_invariant_to_rigid_motion_and_vertex_order(ellipsoid):
    m, b = ellipsoid
    rng = np.random.default_rng(0)
    perm = rng.permutation(m.n_vertices)
    inv = np.argsort(perm)
    V = m.vertices[perm] @ _random_rotation(rng).T + [3.0, -1.0, 0.5]
    moved = cshape.Mesh(V, inv[m.faces])
    b2 = cshape.eigenbasis(moved, 40)
    t = sg.hks_times(b, 20)
    np.testing.assert_allclose(cshape.hks(b2, t), cshape.hks(b, t)[perm], rtol=1e-6)
    e, s = sg.wks_energies(b, 30)
    np.testing.assert_allclose(cshape.wks(b2, e, s), cshape.wks(b, e, s)[perm], rtol=1e-6)
    np.testing.assert_allclose(si_hks(b2), si_hks(b)[perm],
                               rtol=1e-6, atol=1e-9)
    # and the correspondence is found back from the signatures, up to the ellipsoid's
    # symmetries (sign flips of x, y, z: up to 8 vertices with the same HKS)
    match = match_points(cshape.hks(b, t), cshape.hks(b2, t))
    found = np.abs(m.vertices[perm[match]])
    assert np.mean(np.abs(found - np.abs(m.vertices)).max(axis=1) < 1e-9) > 0.99


def test_scale_hks_at_scaled_times_and_invariant_forms(ellipsoid):
    m, b = ellipsoid
    s = 3.0
    big = cshape.Mesh(m.vertices * s, m.faces)
    b2 = cshape.eigenbasis(big, 40)
    t = sg.hks_times(b, 30)
    # HKS_s(x, s^2 t) = HKS(x, t) / s^2
    np.testing.assert_allclose(cshape.hks(b2, s**2 * t) * s**2, cshape.hks(b, t), rtol=1e-8)
    # default times follow the spectrum: same relation
    np.testing.assert_allclose(sg.hks_times(b2, 30), s**2 * t, rtol=1e-8)
    # unit-area normalisation, SI-HKS and the area-normalised WKS: invariant
    np.testing.assert_allclose(cshape.hks(b2, normalization="area"),
                               cshape.hks(b, normalization="area"), rtol=1e-8)
    np.testing.assert_allclose(cshape.wks(b2, normalization="area"),
                               cshape.wks(b, normalization="area"), rtol=1e-8)
    np.testing.assert_allclose(sg.hks_times(b2, 30, normalization="area"),
                               sg.hks_times(b, 30, normalization="area"), rtol=1e-8)
    si, si2 = si_hks(b), si_hks(b2)
    assert si.shape == (m.n_vertices, 6)
    np.testing.assert_allclose(si2, si, rtol=1e-4, atol=1e-4 * np.abs(si).max())
    # while the plain HKS at the same times is not
    assert np.abs(cshape.hks(b2, t) / cshape.hks(b, t) - 1).max() > 0.5


def test_si_hks_is_not_trivially_constant(ellipsoid):
    m, b = ellipsoid
    si = si_hks(b)
    # poles of the long axis and the short axis differ
    ends = [int(np.argmax(m.vertices[:, 0])), int(np.argmax(m.vertices[:, 2]))]
    assert np.abs(si[ends[0]] - si[ends[1]]).max() > 1e-2 * np.abs(si).max()


def test_stable_under_refinement():
    # level s+1 keeps the vertices of level s first: compare the signatures there
    meshes = [_ellipsoid(s) for s in (3, 4, 5)]
    bases = [cshape.eigenbasis(m, 30) for m in meshes]
    n3 = meshes[0].n_vertices
    t = sg.hks_times(bases[-1], 20)
    e, sigma = sg.wks_energies(bases[-1], 30)
    h = [cshape.hks(b, t)[:n3] for b in bases]
    w = [cshape.wks(b, e, sigma)[:n3] for b in bases]
    assert np.abs(h[0] / h[2] - 1).max() < 1e-2
    assert np.abs(w[0] / w[2] - 1).max() < 0.15
    # converging: the middle level is closer to the finest than the coarsest is
    for sig in (h, w):
        assert np.abs(sig[1] / sig[2] - 1).max() < 0.5 * np.abs(sig[0] / sig[2] - 1).max()


# ---------------------------------------------------------------------- matching
def test_match_points_identity_permutation_and_mutual():
    rng = np.random.default_rng(3)
    for k in (3, 20):  # the k-d tree path and the dense path
        X = rng.standard_normal((500, k))
        perm = rng.permutation(500)
        np.testing.assert_array_equal(match_points(X, X), np.arange(500))
        # row i of X is row inv[i] of X[perm]
        np.testing.assert_array_equal(match_points(X, X[perm]), np.argsort(perm))
    a = np.array([[0.0], [0.1], [5.0]])
    b = np.array([[0.05], [4.0]])
    np.testing.assert_array_equal(match_points(a, b), [0, 0, 1])
    # 0.1 and 0.0 are both nearest 0.05, whose nearest is 0.0 (0.05 away from both: ties
    # go to the first); 5.0 -> 4.0 -> 5.0 is mutual
    np.testing.assert_array_equal(match_points(a, b, mutual=True), [0, -1, 1])
    np.testing.assert_array_equal(match_points(a[:, 0], b[:, 0]), [0, 0, 1])


# ---------------------------------------------------------------------- bad arguments
LAM = np.array([0.0, 1.0, 2.0])
PHI = np.ones((4, 3))
BASIS = _basis(LAM, PHI)


@pytest.mark.parametrize(
    "call, exc, match",
    [
        (lambda: cshape.hks((LAM, PHI)), TypeError, "basis must be a cshape.Eigenbasis, got tuple"),
        (lambda: cshape.hks(BASIS, [1.0, -2.0]), ValueError, "t must be positive finite"),
        (lambda: cshape.hks(BASIS, [[1.0]]), ValueError, "t must be a number or a 1-D"),
        (lambda: cshape.hks(BASIS, []), ValueError, "t is empty"),
        (lambda: cshape.hks(BASIS, n_times=0), ValueError,
         r"n_times must be an integer >= 1, got 0"),
        (lambda: cshape.hks(BASIS, n_times=2.5), TypeError,
         "n_times must be an integer, got float 2.5"),
        (lambda: cshape.hks(BASIS, normalization="trace"), ValueError,
         r"normalization must be one of \{'none', 'area'\}"),
        (lambda: cshape.hks(BASIS, scale="area"), ValueError,
         r"scale must be one of \{'none', 'trace'\}"),
        (lambda: cshape.hks(_basis(np.zeros(3), PHI)), ValueError, "no non-zero eigenvalue"),
        (lambda: cshape.wks(BASIS, [0.0, 1.0]), ValueError, "sigma is required"),
        (lambda: cshape.wks(BASIS, sigma=0.0), ValueError, "sigma must be a positive finite"),
        (lambda: cshape.wks(BASIS, [50.0], sigma=0.01), ValueError, "too far from every"),
        (lambda: cshape.wks(BASIS, [np.inf], 1.0), ValueError, "energies must be finite"),
        (lambda: cshape.wks(BASIS, n_energies=-1), ValueError,
         "n_energies must be an integer >= 1, got -1"),
        (lambda: cshape.wks(_basis([0.0, 1.0, 1.0], PHI)), ValueError, "two distinct non-zero"),
        (lambda: cshape.wks(BASIS, n_energies=20), ValueError,
         "n_energies must be at least 29 for the default width"),
        (lambda: si_hks(BASIS, [0.0, 1.0, 3.0]), ValueError, "tau must be evenly"),
        (lambda: si_hks(BASIS, [0.0, 1.0]), ValueError, "at least 3 log-times"),
        (lambda: si_hks(BASIS, np.arange(-1, 1, 0.125)), ValueError,
         "tau does not cover"),
        (lambda: si_hks(BASIS, n_freqs=400), ValueError, "n_freqs=400 is more than"),
        (lambda: si_hks(BASIS, base=1.0), ValueError, "base must differ from 1"),
        (lambda: si_hks(_basis(LAM, np.vstack([PHI, np.zeros(3)]))), ValueError,
         "HKS vanishes at some vertices"),
        (lambda: heat_kernel(BASIS, 1.0, 1.5), TypeError, "sources must be a vertex"),
        (lambda: heat_kernel(BASIS, 1.0, [0, 4]), ValueError,
         r"sources holds vertex index 4, outside \[0, 3\]"),
        (lambda: heat_kernel(BASIS, [1.0, 2.0], 0), ValueError, "t must be one time"),
        (lambda: heat_trace(BASIS, 0.0), ValueError, "t must be positive finite"),
        (lambda: heat_trace(LAM, 1.0), TypeError, "basis must be a cshape.Eigenbasis"),
        (lambda: sg.hks_times(BASIS, normalization="unit"), ValueError,
         r"normalization must be one of"),
        (lambda: match_points(PHI, PHI[:, :2]), ValueError, "sig_a has 3 scales and"),
        (lambda: match_points(PHI, PHI, mutual=1), TypeError,
         "mutual must be True or False, got int 1"),
        (lambda: match_points(PHI * np.nan, PHI), ValueError, "sig_a contains NaN"),
        (lambda: match_points(PHI, np.ones((0, 3))), ValueError,
         r"sig_b must have shape \(n, n_scales\)"),
    ],
)
def test_bad_arguments(call, exc, match):
    with pytest.raises(exc, match=match):
        call()
