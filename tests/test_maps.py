"""Stage 7, maps between shapes: heat-method geodesics against exact distances (sphere, plane),
functional maps and ZoomOut recovering known vertex maps, and the argument checks."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.distance import cdist

import cshape
from cshape import _candidates, _nearest, shapes
from cshape.signatures import wks_energies

K, K0 = 60, 20


def _blob(subdivisions=3):
    """An icosphere stretched to axes 1, 0.7, 0.5 with two bumps: no symmetry left."""
    m = shapes.icosphere(subdivisions)
    U = m.vertices
    V = U * [1.0, 0.7, 0.5]
    for c, a in (([0.6, 0.5, 0.3], 0.35), ([-0.5, -0.2, 0.4], 0.2)):
        c = np.array(c) / np.linalg.norm(c)
        V = V + a * np.exp(-np.sum((U - c) ** 2, axis=1) / 0.08)[:, None] * U
    return cshape.Mesh(V, m.faces)


def _rotation(ax, ay, az):
    cx, sx, cy, sy, cz, sz = np.cos(ax), np.sin(ax), np.cos(ay), np.sin(ay), np.cos(az), np.sin(az)
    Rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    Ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    Rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return Rz @ Ry @ Rx


@pytest.fixture(scope="module")
def blob():
    return _blob()


@pytest.fixture(scope="module")
def shuffled(blob):
    """The blob with its vertices permuted (faces re-indexed), rotated and moved: target
    vertex ``y`` is source vertex ``perm[y]``."""
    rng = np.random.default_rng(1)
    perm = rng.permutation(blob.n_vertices)
    inv = np.argsort(perm)
    R = _rotation(0.5, -0.9, 1.2)
    return cshape.Mesh(blob.vertices[perm] @ R.T + [1.0, 2.0, 3.0], inv[blob.faces]), perm


@pytest.fixture(scope="module")
def basis(blob):
    lam, phi = cshape.eigenpairs(blob, K)
    _, B = cshape.fem_matrices(blob)
    return lam, phi, B


# ---------------------------------------------------------------------- maps
def test_functional_map_of_identical_bases_is_the_identity(blob, basis):
    lam, phi, B = basis
    wks = cshape.wks(lam, phi, n_energies=100, area=blob.area)[:, ::5]
    for kw in ({"orientation_weight": 0.0}, {"source": blob, "target": blob}):
        C = cshape.functional_map(lam[:K0], phi[:, :K0], B, lam[:K0], phi[:, :K0], B, wks, wks,
                                  **kw)
        assert C.shape == (K0, K0)
        np.testing.assert_allclose(np.abs(np.diag(C)), 1.0, atol=1e-3)
        assert np.abs(C - np.diag(np.diag(C))).max() < 1e-3
        p = cshape.map_to_pointwise(C, phi[:, :K0], phi[:, :K0])
        assert (p == np.arange(blob.n_vertices)).mean() > 0.99


def test_point_map_of_a_mesh_to_itself_is_the_identity(blob):
    p = cshape.point_map(blob, blob, k=K, k0=K0)
    assert p.shape == (blob.n_vertices,) and p.dtype == np.int64
    assert (p == np.arange(blob.n_vertices)).mean() > 0.95


@pytest.mark.parametrize("options", [{}, {"orientation": False}, {"zoomout_steps": False},
                                     {"bijective": True}])
def test_point_map_recovers_a_permutation_and_a_rigid_motion(blob, shuffled, options):
    target, perm = shuffled
    p, C = cshape.point_map(blob, target, k=K, k0=K0, return_map=True, **options)
    assert p.shape == (target.n_vertices,)
    assert C.shape == ((K, K) if options.get("zoomout_steps", True) else (K0, K0))
    assert (p == perm).mean() > 0.9


def test_pointwise_to_map_and_back(blob, shuffled, basis):
    target, perm = shuffled
    _, phiS, _ = basis
    _, phiT = cshape.eigenpairs(target, K)
    _, BT = cshape.fem_matrices(target)
    C = cshape.pointwise_to_map(perm, phiS, phiT, BT)
    # the exact map is an isometry: C is orthogonal (up to the truncation), |C_ii| ~ 1
    assert np.abs(C[:K0, :K0].T @ C[:K0, :K0] - np.eye(K0)).max() < 0.05
    p = cshape.map_to_pointwise(C, phiS, phiT)
    assert (p == perm).mean() > 0.95


def test_zoomout_keeps_a_good_map_and_grows_it(blob, basis):
    _, phi, B = basis
    C = cshape.zoomout(np.eye(K0), phi, phi, B, K)
    assert C.shape == (K, K)
    np.testing.assert_allclose(C, np.eye(K), atol=1e-8)


def test_transfer_function_carries_smooth_functions(blob, shuffled, basis):
    target, perm = shuffled
    _, phiS, BS = basis
    _, phiT = cshape.eigenpairs(target, K)
    _, BT = cshape.fem_matrices(target)
    f = blob.vertices[:, 0] + 0.5 * blob.vertices[:, 1] ** 2  # smooth on the source
    C = cshape.pointwise_to_map(perm, phiS, phiT, BT)
    g = cshape.transfer_function(f, C, phiS, phiT, BS)
    assert g.shape == (target.n_vertices,)
    rel = np.linalg.norm(g - f[perm]) / np.linalg.norm(f)
    assert rel < 0.05
    # and back: the inverse map's C carries g to f
    Cinv = cshape.pointwise_to_map(np.argsort(perm), phiT, phiS, BS)
    back = cshape.transfer_function(g, Cinv, phiT, phiS, BT)
    assert np.linalg.norm(back - f) / np.linalg.norm(f) < 0.05
    # several functions at once
    F = np.column_stack([f, 2 * f])
    np.testing.assert_allclose(cshape.transfer_function(F, C, phiS, phiT, BS)[:, 1], 2 * g)


# ---------------------------------------------------------------------- checks
def test_point_map_rejects_what_is_not_a_mesh(blob):
    with pytest.raises(TypeError, match="source"):
        cshape.point_map("bunny.obj", blob)


def test_point_map_rejects_a_mesh_with_unreferenced_vertices(blob):
    V = np.vstack([blob.vertices, [[5.0, 5.0, 5.0]]])
    with pytest.raises(ValueError, match=r"target has 1 duplicate or unreferenced.*repair_mesh"):
        cshape.point_map(blob, (V, blob.faces))


def test_point_map_rejects_bad_sizes(blob):
    with pytest.raises(ValueError, match="k must be an integer >= 2, got 1"):
        cshape.point_map(blob, blob, k=1)
    with pytest.raises(TypeError, match="k must be an integer, got float"):
        cshape.point_map(blob, blob, k=20.0)
    with pytest.raises(ValueError, match=r"k0 must be an integer in \[2, 20\], got 30"):
        cshape.point_map(blob, blob, k=20, k0=30)
    with pytest.raises(ValueError, match="k=5000 is more than the vertices"):
        cshape.point_map(blob, blob, k=5000)


def test_point_map_rejects_bad_landmarks(blob):
    with pytest.raises(ValueError, match=r"landmarks must have shape \(L, 2\)"):
        cshape.point_map(blob, blob, landmarks=[1, 2, 3])
    with pytest.raises(ValueError, match=r"landmarks\[:, 1\] holds vertex index 9999"):
        cshape.point_map(blob, blob, landmarks=[[0, 9999]])
    with pytest.raises(TypeError, match="landmarks must be integer vertex indices"):
        cshape.point_map(blob, blob, landmarks=[[0.5, 1.0]])


def test_maps_reject_a_C_larger_than_the_bases(basis):
    _, phi, B = basis
    with pytest.raises(ValueError, match=r"C has shape \(70, 70\), larger than the bases"):
        cshape.map_to_pointwise(np.eye(70), phi, phi)
    with pytest.raises(ValueError, match="C must have shape"):
        cshape.transfer_function(phi[:, 0], np.ones(5), phi, phi, B)
    with pytest.raises(ValueError, match=r"k must be an integer in \[20, 60\], got 10"):
        cshape.zoomout(np.eye(K0), phi, phi, B, 10)


def test_functional_map_rejects_mismatched_descriptors(basis):
    lam, phi, B = basis
    with pytest.raises(ValueError, match="desc_source has 3 descriptors and desc_target 4"):
        cshape.functional_map(lam, phi, B, lam, phi, B, phi[:, :3], phi[:, :4])
    with pytest.raises(ValueError, match="lam_source has 5 eigenvalues but phi_source has 60 "
                       "columns"):
        cshape.functional_map(lam[:5], phi, B, lam, phi, B, phi[:, :3], phi[:, :3])


def test_maps_name_the_argument_whose_shape_does_not_fit(blob, basis):
    """Arrays of mismatched shapes: the argument, its shape and the fix, never numpy's
    reshape or matmul error."""
    lam, phi, B = basis
    n = len(phi)
    d = phi[:, :3]
    with pytest.raises(ValueError, match=rf"desc_source has shape \(15,\) but phi_source has "
                       rf"{n} rows.*one row per vertex"):
        cshape.functional_map(lam, phi, B, lam, phi, B, np.ones(15), d)
    with pytest.raises(ValueError, match=rf"desc_target has shape \(5, 3\) but phi_target has {n}"):
        cshape.functional_map(lam, phi, B, lam, phi, B, d, d[:5])
    with pytest.raises(ValueError, match=rf"B_target has shape \(10, 10\) but phi_target has "
                       rf"{n} rows.*mass matrix of the same mesh"):
        cshape.functional_map(lam, phi, B, lam, phi, B[:10, :10], d, d)
    with pytest.raises(ValueError, match=rf"source has 42 vertices but phi_source has {n} rows"):
        cshape.functional_map(lam, phi, B, lam, phi, B, d, d, source=shapes.icosphere(1),
                              target=blob)
    C = np.eye(K0)
    with pytest.raises(ValueError, match=r"B_target has shape \(10, 10\)"):
        cshape.zoomout(C, phi, phi, B[:10, :10])
    with pytest.raises(ValueError, match=r"B_source has shape \(10, 10\)"):
        cshape.zoomout(C, phi, phi, B, bijective=True, B_source=B[:10, :10])
    with pytest.raises(ValueError, match=r"B_target has shape \(10, 10\)"):
        cshape.pointwise_to_map(np.arange(n), phi, phi, B[:10, :10])
    with pytest.raises(ValueError, match=rf"f has shape \(7,\) but phi_source has {n} rows"):
        cshape.transfer_function(np.ones(7), C, phi, phi, B)
    with pytest.raises(ValueError, match=r"f has shape \(\)"):
        cshape.transfer_function(1.0, C, phi, phi, B)
    with pytest.raises(ValueError, match=r"B_source has shape \(10, 10\)"):
        cshape.transfer_function(phi[:, 0], C, phi, phi, B[:10, :10])


def _mirror_symmetric():
    """A shape symmetric under z -> -z only, and the vertex map of that reflection."""
    m = shapes.icosphere(3)
    U = m.vertices
    V = U * [1.0, 0.7, 0.5]
    for c, a in (([1.0, 0.5, 0.0], 0.35), ([-0.5, -0.6, 0.0], 0.2)):
        c = np.array(c) / np.linalg.norm(c)
        V = V + a * np.exp(-np.sum((U - c) ** 2, axis=1) / 0.08)[:, None] * U
    mirror = np.array([np.argmin(np.linalg.norm(U - u * [1, 1, -1], axis=1)) for u in U])
    return cshape.Mesh(V, m.faces), mirror


@pytest.fixture(scope="module")
def symmetric():
    return _mirror_symmetric()


def test_the_orientation_term_tells_a_shape_from_its_mirror_image(symmetric):
    """Intrinsic descriptors cannot tell the identity from the reflection; the orientation
    term of Ren et al. (2018) can."""
    S, mirror = symmetric
    n = S.n_vertices
    assert (mirror != np.arange(n)).mean() > 0.9
    p = cshape.point_map(S, S, k=K, k0=K0)
    assert (p == np.arange(n)).mean() > 0.95
    assert (p == mirror).mean() < 0.1
    q = cshape.point_map(S, S, k=K, k0=K0, orientation=False, initial="descriptors")
    assert (q == mirror).mean() > 0.3  # without it the reflection is as good a match


def test_the_orientation_share_is_one_for_the_identity_and_zero_for_a_mirror(symmetric):
    S, mirror = symmetric
    assert _candidates.orientation_share(S, S, np.arange(S.n_vertices)) == pytest.approx(1.0)
    assert _candidates.orientation_share(S, S, mirror) < 0.05


def test_the_search_keeps_the_oriented_map_among_those_that_fit():
    # residuals within 20 % of the smallest compete on orientation; a worse fit does not
    assert _candidates.pick([(1.0, 0.2), (1.1, 0.9), (1.5, 1.0)]) == 1
    assert _candidates.pick([(1.0, 0.9), (1.1, 0.2)]) == 0
    assert _candidates.pick([(1.0, 0.0), (1.0, 0.0)]) == 0  # without orientation: the best fit


def test_point_map_search_finds_the_map_between_bodies_of_another_shape():
    """A generated figure and a pose of it made stockier (x, y by 1.3, z by 0.9): the
    descriptors no longer agree and their map fails; the sign patterns find it."""
    from cshape.data import poses

    rest = poses.posed_figure("human", rest=True, voxelsize=0.03, target_vertices=800)
    pose = poses.posed_figure("human", 0, voxelsize=0.03, target_vertices=800)
    stocky = cshape.Mesh(pose.vertices * [1.3, 1.3, 0.9], pose.faces)
    geo = cshape.HeatGeodesics(rest)
    v = np.arange(0, rest.n_vertices, 5)
    err = {init: cshape.geodesic_errors(rest, cshape.point_map(rest, stocky, k=50, k0=20,
                                                               initial=init),
                                        vertices=v, geodesics=geo).mean() / np.sqrt(rest.area)
           for init in ("descriptors", "search")}
    assert err["descriptors"] > 0.2
    assert err["search"] < 0.05


def test_landmarks_override_the_search(symmetric):
    S, _mirror = symmetric
    lm = [[0, 0], [100, 100], [400, 400]]
    a = cshape.point_map(S, S, k=K, k0=K0, landmarks=lm)
    b = cshape.point_map(S, S, k=K, k0=K0, landmarks=lm, initial="descriptors")
    np.testing.assert_array_equal(a, b)
    with pytest.raises(ValueError, match="initial"):
        cshape.point_map(S, S, initial="best")


@pytest.mark.parametrize("to_mirror", [False, True])
def test_landmarks_decide_between_a_shape_and_its_mirror_image(symmetric, to_mirror):
    """Without the orientation term, three landmarks on one side (z > 0) choose the map:
    matched to themselves they give the identity, matched to their reflections the
    reflection (which the orientation term would refuse)."""
    S, mirror = symmetric
    V = S.vertices
    up = np.flatnonzero(V[:, 2] > 0.25)
    top = up[[np.argmin(V[up, 0]), np.argmax(V[up, 0]), np.argmax(V[up, 1])]]
    assert len(set(top)) == 3
    truth = mirror if to_mirror else np.arange(S.n_vertices)
    landmarks = np.column_stack([truth[top], top])  # (source vertex, target vertex)
    p = cshape.point_map(S, S, k=K, k0=K0, orientation=False, landmarks=landmarks)
    assert (p == truth).mean() > 0.9
    assert (p[top] == truth[top]).all()  # the landmarks themselves are matched exactly


def test_functional_map_does_not_depend_on_the_unit_of_length(blob, shuffled):
    """Descriptors scaled to unit B-norm, eigenvalues to the largest, orientation operators
    to the unit-area shape: the same C for meshes in millimetres and in metres."""
    target, _ = shuffled
    out = []
    for s in (1.0, 1000.0):
        S, T = cshape.Mesh(s * blob.vertices, blob.faces), cshape.Mesh(s * target.vertices,
                                                                        target.faces)
        (lS, pS), (lT, pT) = cshape.eigenpairs(S, K0), cshape.eigenpairs(T, K0)
        BS, BT = cshape.fem_matrices(S)[1], cshape.fem_matrices(T)[1]
        e, sigma = wks_energies(lS, 100, area=S.area)
        dS = cshape.wks(lS, pS, e, sigma, area=S.area)[:, ::5]
        dT = cshape.wks(lT, pT, e, sigma, area=T.area)[:, ::5]
        out.append(cshape.functional_map(lS, pS, BS, lT, pT, BT, dS, dT, source=S, target=T))
    # eigenvectors scale by 1/s (B-orthonormal), signs alike: C is the same
    np.testing.assert_allclose(out[1], out[0], atol=1e-6)


@pytest.mark.parametrize("big", [False, True])
def test_map_to_pointwise_is_the_exact_nearest_neighbour(monkeypatch, big):
    """Blocks, threads, scikit-learn's search (big problems) and the 3-d k-d tree path give
    the argmin of the full distances."""
    if big:
        monkeypatch.setattr(_nearest, "NN_SKLEARN_PAIRS", 1)
    rng = np.random.default_rng(3)
    for n_t, n_s, k in ((1500, 1200, 40), (300, 250, 3)):
        phiT, phiS = rng.standard_normal((n_t, k)), rng.standard_normal((n_s, k))
        C = rng.standard_normal((k, k))
        p = cshape.map_to_pointwise(C, phiS, phiT)
        full = cdist(phiT, phiS @ C.T, "sqeuclidean")  # differences, not products
        np.testing.assert_array_equal(p, np.argmin(full, axis=1))


def test_pointwise_to_map_of_the_identity_is_the_identity_matrix(basis):
    _, phi, B = basis
    n = phi.shape[0]
    np.testing.assert_allclose(cshape.pointwise_to_map(np.arange(n), phi, phi, B), np.eye(K),
                               atol=1e-10)


def test_bijective_zoomout_needs_the_source_mass_and_keeps_a_good_map(basis):
    _, phi, B = basis
    with pytest.raises(ValueError, match="bijective=True needs B_source"):
        cshape.zoomout(np.eye(K0), phi, phi, B, K, bijective=True)
    C = cshape.zoomout(np.eye(K0), phi, phi, B, K, bijective=True, B_source=B)
    np.testing.assert_allclose(C, np.eye(K), atol=1e-8)
