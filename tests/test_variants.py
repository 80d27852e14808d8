"""Tests of cshape.data.variants: marching cubes, remeshing, subdivision, noise, quality."""

from __future__ import annotations

import numpy as np
import pytest

from cshape import CShapeWarning, Mesh, shapes
from cshape.data import bodies, quality
from cshape.data import variants as v


def test_eight_is_genus_two():
    m = v.eight(voxelsize=0.04, target_vertices=1500)
    assert m.is_closed and m.n_components == 1 and m.genus == 2
    assert 1000 < m.n_vertices < 2200


def test_eight_separation_error():
    with pytest.raises(ValueError, match="separation must lie in"):
        v.eight(separation=3.0)


# ---------------------------------------------------------------------- marching cubes
def test_marching_cubes_warns_when_the_box_cuts_the_surface():
    with pytest.warns(CShapeWarning, match="enlarge bbox"):
        m = v.marching_cubes("x^2+y^2+z^2-0.25", (-0.3, -1, -1, 0.3, 1, 1), voxelsize=0.05)
    assert not m.is_closed


def test_marching_cubes_sphere():
    m = v.marching_cubes("x^2+y^2+z^2-0.25", (-1, -1, -1, 1, 1, 1), voxelsize=0.05)
    assert m.is_closed and m.genus == 0
    r = np.linalg.norm(m.vertices, axis=1)
    assert np.all(np.abs(r - 0.5) < 0.05)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"expr": ""}, "expr must be a non-empty"),
        ({"bbox": (0, 0, 0, 1, 1)}, "bbox must be 6 numbers"),
        ({"bbox": (1, -1, -1, -1, 1, 1)}, "max > min"),
        ({"voxelsize": 0.0}, "voxelsize must be a positive"),
        ({"voxelsize": 1e-4}, "use a larger voxelsize"),
    ],
)
def test_marching_cubes_errors(kwargs, match):
    args = {"expr": "x^2+y^2+z^2-0.25", "bbox": (-1, -1, -1, 1, 1, 1), "voxelsize": 0.1}
    args.update(kwargs)
    with pytest.raises((ValueError, TypeError), match=match):
        v.marching_cubes(**args)


def test_cm_has_worse_quality_than_cs():
    """The paper's CM (marching cubes) versus CS (its quality-improved remesh)."""
    cm = bodies.articulated_figure("quadruped", 0, voxelsize=0.03, target_vertices=None)
    cs = v.remesh(cm, target_vertices=2000)
    qm, qs = quality.mesh_quality(cm), quality.mesh_quality(cs)
    assert cm.is_closed and cs.is_closed and cm.genus == cs.genus == 0
    assert qm["min_angle"] < 2.0 < 10.0 < qs["min_angle"]
    assert qm["mean_min_angle"] < qs["mean_min_angle"]
    assert qm["pct_below_10"] > 10 * max(qs["pct_below_10"], 0.1)
    assert qm["aspect_max"] > qs["aspect_max"]
    assert cs.area == pytest.approx(cm.area, rel=0.02)  # same shape


# ---------------------------------------------------------------------- remesh, subdivide
def test_remesh_vertex_target():
    m = v.remesh(shapes.icosphere(4), target_vertices=800)
    assert 600 < m.n_vertices < 1000 and m.is_closed


def test_remesh_needs_exactly_one_target():
    with pytest.raises(ValueError, match="exactly one of target_length"):
        v.remesh(shapes.icosphere(2))
    with pytest.raises(ValueError, match="exactly one of target_length"):
        v.remesh(shapes.icosphere(2), 0.1, target_vertices=100)


@pytest.mark.parametrize("method", ["loop", "midpoint"])
def test_subdivide_quadruples(method):
    m = shapes.icosphere(2)
    d = v.subdivide(m, 1, method=method)
    assert d.n_vertices == m.n_vertices + len(m.edges)  # V + E, about 4x
    assert d.n_faces == 4 * m.n_faces and d.is_closed and d.genus == 0


def test_subdivide_bad_method():
    with pytest.raises(ValueError, match="method must be one of"):
        v.subdivide(shapes.icosphere(1), 1, method="sqrt3")


# ---------------------------------------------------------------------- articulated figures
@pytest.mark.parametrize("kind", bodies.ARTICULATED_KINDS)
def test_articulated_figure_is_closed_genus0(kind):
    m = bodies.articulated_figure(kind, 1, voxelsize=0.03, target_vertices=1200)
    assert m.is_closed and m.n_components == 1 and m.genus == 0
    assert 900 < m.n_vertices < 1600


@pytest.mark.slow
def test_articulated_poses_near_isometric_and_seeded():
    a = bodies.articulated_figure("human", 0, voxelsize=0.03, target_vertices=1000)
    b = bodies.articulated_figure("human", 3, voxelsize=0.03, target_vertices=1000)
    a2 = bodies.articulated_figure("human", 0, voxelsize=0.03, target_vertices=1000)
    np.testing.assert_array_equal(a.vertices, a2.vertices)  # same seed, same mesh
    np.testing.assert_array_equal(a.faces, a2.faces)
    assert a.n_vertices != b.n_vertices or not np.allclose(a.vertices, b.vertices)
    assert b.area == pytest.approx(a.area, rel=0.03)  # bone lengths fixed: same area


@pytest.mark.parametrize("kind", ["spider", "snake"])
def test_articulated_figure_is_the_marching_cubes_of_the_whole_union(kind):
    """The figure evaluates each capsule only near it (a cutoff of three voxels), and gets
    the marching-cubes mesh of the full union of capsules, bit for bit."""
    caps, vs = bodies.figure_capsules(kind, 2), 0.04
    got = bodies.articulated_figure(kind, 2, voxelsize=vs, target_vertices=None)
    pts = np.array([c.a for c in caps] + [c.b for c in caps])
    margin = max(c.radius for c in caps) + 4 * vs + 0.05
    full = v.marching_cubes(bodies.capsules_expression(caps),
                            (*(pts.min(0) - margin), *(pts.max(0) + margin)), vs)
    np.testing.assert_array_equal(got.vertices, full.vertices)
    np.testing.assert_array_equal(got.faces, full.faces)


def test_figure_capsules_bone_lengths_fixed():
    for kind in bodies.ARTICULATED_KINDS:
        lengths = [
            [np.linalg.norm(np.subtract(c.b, c.a)) for c in bodies.figure_capsules(kind, s)]
            for s in range(3)
        ]
        np.testing.assert_allclose(lengths[0], lengths[1])
        np.testing.assert_allclose(lengths[0], lengths[2])


def test_figure_unknown_kind():
    with pytest.raises(ValueError, match="kind must be one of"):
        bodies.figure_capsules("dragon")


# ---------------------------------------------------------------------- noise (Section 3.3)
def test_noise_levels_are_the_papers():
    assert v.NOISE_LEVELS == (0.5, 1.0, 2.0, 4.0, 10.0)


@pytest.mark.parametrize("amplitude", v.NOISE_LEVELS)
def test_noise_bounded_and_along_outward_normals(amplitude):
    m = shapes.icosphere(3)
    L = m.mean_edge_length
    noisy = v.add_normal_noise(m, amplitude, random_state=1)
    d = noisy.vertices - m.vertices
    n = v.vertex_normals(m)
    along = np.einsum("ij,ij->i", d, n)
    assert np.all(along >= 0) and np.all(along <= amplitude * L)
    np.testing.assert_allclose(np.cross(d, n), 0, atol=1e-12)  # only along the normal
    assert along.max() > 0.8 * amplitude * L  # uses the range
    np.testing.assert_array_equal(noisy.faces, m.faces)


def test_noise_seeded():
    m = shapes.icosphere(2)
    a = v.add_normal_noise(m, 1.0, random_state=5)
    b = v.add_normal_noise(m, 1.0, random_state=5)
    c = v.add_normal_noise(m, 1.0, random_state=6)
    np.testing.assert_array_equal(a.vertices, b.vertices)
    assert not np.allclose(a.vertices, c.vertices)


def test_noise_outward_even_for_inward_oriented_faces():
    m = shapes.icosphere(2)
    flipped = Mesh(m.vertices, m.faces[:, ::-1])
    noisy = v.add_normal_noise(flipped, 2.0, random_state=0)
    assert np.all(np.linalg.norm(noisy.vertices, axis=1) >= 1 - 1e-12)


def test_noise_signed_and_zero():
    m = shapes.icosphere(2)
    np.testing.assert_array_equal(v.add_normal_noise(m, 0.0, 0).vertices, m.vertices)
    s = v.add_normal_noise(m, 1.0, 0, signed=True)
    r = np.linalg.norm(s.vertices, axis=1)
    assert r.min() < 1 < r.max()
    with pytest.raises(ValueError, match="amplitude must be a finite number >= 0"):
        v.add_normal_noise(m, -1.0)


def test_vertex_normals_of_sphere_are_radial():
    m = shapes.icosphere(3)
    n = v.vertex_normals(m)
    np.testing.assert_allclose(np.einsum("ij,ij->i", n, m.vertices), 1.0, atol=2e-3)


# ---------------------------------------------------------------------- quality
def test_triangle_angles_sum_to_180():
    ang = quality.triangle_angles(shapes.icosphere(2))
    np.testing.assert_allclose(ang.sum(axis=1), 180.0)


def test_quality_of_equilateral_and_degenerate():
    V = np.array([[0, 0, 0], [1, 0, 0], [0.5, np.sqrt(3) / 2, 0], [2, 0, 0.0]])
    q = quality.mesh_quality(Mesh(V[:3], [[0, 1, 2]]))
    assert q["min_angle"] == pytest.approx(60) and q["aspect_max"] == pytest.approx(1)
    q = quality.mesh_quality(Mesh(V, [[0, 1, 2], [0, 1, 3]]))  # second triangle is flat
    assert q["min_angle"] == pytest.approx(0, abs=1e-9)
    assert q["n_degenerate"] == 1 and q["aspect_max"] == np.inf
    assert np.isfinite(q["aspect_mean"])


def test_remesh_does_not_depend_on_earlier_pymeshlab_calls():
    """``remesh`` passes every parameter of PyMeshLab's filter: one left out takes the value
    of the previous call in the process (uninitialised in a new one), which made creatures
    open or of other sizes depending on what the process had run before."""
    import pymeshlab

    src = shapes.icosphere(3)
    before = v.remesh(src, 0.15)
    ms = v._meshset(src)  # another user of the filter in this process, with other flags
    ms.meshing_isotropic_explicit_remeshing(
        iterations=2, adaptive=True, swapflag=False, smoothflag=False, reprojectflag=False,
        checksurfdist=False, targetlen=pymeshlab.PureValue(0.3))
    after = v.remesh(src, 0.15)
    np.testing.assert_array_equal(before.faces, after.faces)
    np.testing.assert_array_equal(before.vertices, after.vertices)
    assert after.is_closed and after.n_components == 1


def test_signatures_and_descriptors_share_one_zero_tolerance():
    import cshape.signatures as s
    from cshape.descriptors import count_zero_modes
    from cshape.descriptors.formulas import ZERO_RTOL

    assert s.ZERO_RTOL is ZERO_RTOL
    lam = np.array([0.5 * ZERO_RTOL, 1.0, 2.0, 3.0])
    assert count_zero_modes(lam) == 1
    assert s._nonzero(lam).tolist() == [False, True, True, True]


def test_add_normal_noise_takes_amplitude_and_lam_is_gone():
    m = shapes.icosphere(1)
    a = v.add_normal_noise(m, amplitude=2.0, random_state=3)
    b = v.add_normal_noise(m, 2.0, 3)
    np.testing.assert_array_equal(a.vertices, b.vertices)
    with pytest.raises(TypeError, match="lam"):
        v.add_normal_noise(m, lam=2.0)
    with pytest.raises(TypeError, match="signed must be True or False"):
        v.add_normal_noise(m, 1.0, signed="yes")
