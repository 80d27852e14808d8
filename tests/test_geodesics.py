"""Geodesics by the heat method: exact distances on the sphere and the plane, the errors of a
map, meshes of two pieces (``inf`` where no path reaches) and the argument checks."""

from __future__ import annotations

import numpy as np
import pytest

import cshape
from cshape import shapes


@pytest.fixture(scope="module")
def ellipsoid():
    m = shapes.icosphere(3)
    return cshape.Mesh(m.vertices * [1.0, 0.7, 0.5], m.faces)


@pytest.fixture(scope="module")
def two_spheres():
    """Two unit spheres 3 apart: one mesh, two pieces (vertices 0..n-1 and n..2n-1)."""
    m = shapes.icosphere(3)
    n = m.n_vertices
    V = np.vstack([m.vertices, m.vertices + [3.0, 0.0, 0.0]])
    return cshape.Mesh(V, np.vstack([m.faces, m.faces + n])), m


def _sphere_error(subdivisions):
    m = shapes.icosphere(subdivisions)
    X = m.vertices / np.linalg.norm(m.vertices, axis=1, keepdims=True)
    exact = np.arccos(np.clip(X @ X[0], -1.0, 1.0))
    d = cshape.geodesic_distance(m, 0)
    assert d[0] == 0.0 and (d >= 0).all()
    return np.abs(d - exact).mean() / np.pi


def test_geodesic_distance_on_the_unit_sphere_is_the_great_circle_distance():
    e3, e4 = _sphere_error(3), _sphere_error(4)
    assert e4 < 0.03
    assert e4 < e3  # converges as the mesh is refined


def test_geodesic_distance_on_a_plane_is_the_euclidean_distance():
    m = shapes.square(40)
    V = m.vertices
    c = int(np.argmin(np.linalg.norm(V[:, :2] - 0.5, axis=1)))
    exact = np.linalg.norm(V - V[c], axis=1)
    d = cshape.geodesic_distance(m, c)
    inside = exact < 0.35  # away from the boundary
    assert np.abs(d - exact)[inside].max() < 0.02
    assert np.abs(d - exact)[inside].mean() < 0.01


def test_heat_geodesics_distances_are_symmetric_and_the_set_distance_is_their_minimum(ellipsoid):
    geo = cshape.geodesics.HeatGeodesics(ellipsoid)
    src = np.array([0, 100, 400])
    D = geo.distances(src)
    assert D.shape == (ellipsoid.n_vertices, 3)
    # d(a, b) ~ d(b, a): the method is not symmetric exactly, to within its error
    scale = np.sqrt(ellipsoid.area)
    assert abs(D[100, 0] - D[0, 1]) < 0.05 * scale
    d = geo.distance(src)
    assert np.all(d[src] == 0)
    assert np.abs(d - D.min(axis=1)).mean() < 0.02 * scale
    assert np.abs(d - D.min(axis=1)).max() < 0.1 * scale


def test_geodesic_errors_are_zero_for_the_truth_and_the_distance_otherwise(ellipsoid):
    n = ellipsoid.n_vertices
    v = np.arange(0, n, 50)
    assert np.all(cshape.geodesics.geodesic_errors(ellipsoid, np.arange(n), vertices=v) == 0)
    wrong = np.full(n, 7)
    geo = cshape.geodesics.HeatGeodesics(ellipsoid)
    err = cshape.geodesics.geodesic_errors(ellipsoid, wrong, vertices=v, geodesics=geo)
    np.testing.assert_allclose(err, geo.distances(v)[7, :], rtol=1e-12)


def test_geodesics_reject_bad_sources(ellipsoid):
    with pytest.raises(ValueError, match=r"sources holds vertex index -1"):
        cshape.geodesic_distance(ellipsoid, -1)
    with pytest.raises(TypeError, match="sources must be an integer array"):
        cshape.geodesic_distance(ellipsoid, 0.5)
    with pytest.raises(ValueError, match="sources is empty"):
        cshape.geodesic_distance(ellipsoid, np.array([], dtype=int))
    with pytest.raises(ValueError, match="m must be"):
        cshape.geodesics.HeatGeodesics(ellipsoid, m=0.0)


def test_vertices_that_no_path_reaches_are_at_infinite_distance(two_spheres):
    both, one = two_spheres
    n = one.n_vertices
    alone = cshape.geodesic_distance(one, 0)
    d = cshape.geodesic_distance(both, 0)
    assert np.isinf(d[n:]).all()
    np.testing.assert_allclose(d[:n], alone, atol=1e-8 * np.pi)
    # a set of sources on one piece (the Dirichlet problem of that piece alone)
    d = cshape.geodesic_distance(both, [0, 5])
    assert np.isinf(d[n:]).all() and np.isfinite(d[:n]).all()
    np.testing.assert_allclose(d[:n], cshape.geodesic_distance(one, [0, 5]), atol=1e-10)
    # sources on both pieces reach every vertex; each piece has its own distance
    d = cshape.geodesic_distance(both, [0, n])
    assert np.isfinite(d).all()
    np.testing.assert_allclose(d[n:], d[:n], atol=1e-8)


def test_heat_geodesics_gives_each_source_its_own_piece(two_spheres):
    both, one = two_spheres
    n = one.n_vertices
    D = cshape.geodesics.HeatGeodesics(both).distances([3, n + 3])
    assert np.isinf(D[n:, 0]).all() and np.isinf(D[:n, 1]).all()
    assert np.isfinite(D[:n, 0]).all() and np.isfinite(D[n:, 1]).all()
    np.testing.assert_allclose(D[:n, 0], D[n:, 1], atol=1e-8)


def test_geodesic_errors_are_infinite_for_an_image_on_another_piece(two_spheres):
    both, one = two_spheres
    n = one.n_vertices
    swap = np.concatenate([np.arange(n, 2 * n), np.arange(n)])  # each piece onto the other
    v = np.array([0, 1, n, n + 1])
    err = cshape.geodesics.geodesic_errors(both, swap, vertices=v)
    assert np.isinf(err).all()
    assert np.all(cshape.geodesics.geodesic_errors(both, np.arange(2 * n), vertices=v) == 0)
    one_off = np.arange(2 * n)
    one_off[0] = 7  # on the same piece: a finite error
    assert np.isfinite(cshape.geodesics.geodesic_errors(both, one_off, vertices=v)).all()


def test_geodesic_errors_reject_geodesics_of_another_mesh(ellipsoid):
    geo = cshape.geodesics.HeatGeodesics(shapes.icosphere(2))
    n = ellipsoid.n_vertices
    with pytest.raises(ValueError, match=r"geodesics is of a mesh of 162 vertices but mesh has"):
        cshape.geodesics.geodesic_errors(ellipsoid, np.arange(n), geodesics=geo)
    with pytest.raises(TypeError, match="geodesics must be a cshape.geodesics.HeatGeodesics"):
        cshape.geodesics.geodesic_errors(ellipsoid, np.arange(n), geodesics="heat")
    with pytest.raises(ValueError, match="truth has 3 entries and p2p"):
        cshape.geodesics.geodesic_errors(ellipsoid, np.arange(n), [0, 1, 2])
