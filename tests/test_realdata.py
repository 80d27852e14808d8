"""Real meshes from ../shared/meshes (odedstein/meshes, public domain / CC BY): every file
loads and gives a finite spectrum.  Skipped when the folder is absent."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import cshape

pytestmark = pytest.mark.realdata

ALL = [
    "cube/cube.obj", "cube/cube_no_bottom.obj", "fish/fish.obj", "fish/fish_control_mesh.obj",
    "fish/fish_low_resolution.obj", "goathead/goathead.obj", "penguin/penguin.obj",
    "penguin/penguin_control_mesh.obj", "penguin/penguin_hr.obj", "plane/plane_holes.obj",
    "sphere/sphere.obj", "spot/spot.obj", "spot/spot_control_mesh.obj",
    "spot/spot_low_resolution.obj", "sword/sword-quad-dominant.obj", "sword/sword.obj",
    "torus/torus.obj", "wingnut/wingnut.obj",
]


@pytest.mark.slow
@pytest.mark.parametrize("rel", ALL)
def test_every_real_mesh_loads_and_has_a_finite_spectrum(shared_meshes, rel):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cshape.CShapeWarning)  # e.g. mollified slivers
        mesh = cshape.load_mesh(shared_meshes / rel)
        lam = cshape.shape_dna(mesh, N=min(30, mesh.n_vertices))
    assert np.all(np.isfinite(lam))
    assert lam[0] == pytest.approx(0, abs=1e-8) and np.all(np.diff(lam) >= -1e-9)
    S = cshape.compact_shape_dna(lam, M=4, N=len(lam), area=mesh.area)
    assert np.all(np.isfinite(S))


def test_obj_with_uvs_keeps_one_vertex_per_position(shared_meshes):
    # spot.obj has texture coordinates; splitting at seams would cut the surface open
    mesh = cshape.load_mesh(shared_meshes / "spot" / "spot.obj")
    n_v = sum(1 for line in open(shared_meshes / "spot" / "spot.obj") if line.startswith("v "))
    assert mesh.n_vertices == n_v == 11533
    assert mesh.is_closed and mesh.genus == 0


def test_quad_dominant_file_is_triangulated(shared_meshes):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cshape.CShapeWarning)
        quad = cshape.load_mesh(shared_meshes / "sword" / "sword-quad-dominant.obj")
    tri = cshape.load_mesh(shared_meshes / "sword" / "sword.obj")
    assert quad.n_vertices == tri.n_vertices and quad.n_faces == tri.n_faces
    assert quad.area == pytest.approx(tri.area, rel=1e-3)


def test_same_shape_at_two_resolutions_has_close_normalised_spectra(shared_meshes):
    hi = cshape.load_mesh(shared_meshes / "spot" / "spot.obj")
    lo = cshape.load_mesh(shared_meshes / "spot" / "spot_low_resolution.obj")
    a = cshape.normalize(cshape.shape_dna(hi, N=11), hi.area)
    b = cshape.normalize(cshape.shape_dna(lo, N=11), lo.area)
    np.testing.assert_allclose(b[1:], a[1:], rtol=0.05)


def test_open_cube_neumann_and_dirichlet(shared_meshes):
    mesh = cshape.load_mesh(shared_meshes / "cube" / "cube_no_bottom.obj")
    assert len(mesh.boundary_edges) == 8
    lam_n = cshape.shape_dna(mesh, N=5)
    lam_d = cshape.shape_dna(mesh, N=5, bc="dirichlet")
    assert lam_n[0] == pytest.approx(0, abs=1e-10)
    assert lam_d[0] > 0  # no constant mode with the boundary held at 0
    assert np.all(lam_d >= lam_n - 1e-9)  # Dirichlet eigenvalues dominate Neumann ones


@pytest.mark.slow
def test_extrapolated_upper_spectra_of_two_resolutions_agree(shared_meshes):
    # issue 42's goal: at i = 80-99 the log-Weyl ratios of the same object at two
    # resolutions differ by at most a third of linear FEM's difference
    hi = cshape.load_mesh(shared_meshes / "spot" / "spot.obj")
    lo = cshape.load_mesh(shared_meshes / "spot" / "spot_low_resolution.obj")

    def upper(mesh, refine):
        lam = cshape.shape_dna(mesh, N=100, refine=refine)
        i = np.arange(80, 100)
        return np.log(lam[i] * mesh.area / (4 * np.pi * i))

    linear = np.abs(upper(hi, "none") - upper(lo, "none")).mean()
    extrapolated = np.abs(upper(hi, "extrapolate") - upper(lo, "extrapolate")).mean()
    assert extrapolated < linear / 3  # measured: 0.0027 against 0.092
