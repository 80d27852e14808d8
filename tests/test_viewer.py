"""The interactive 3-D views (cshape.plots.viewer, re-exported by cshape.plots): the pure functions
behind them (symmetric colour limits, per-mode data, plotly arrays) and their validation."""

from __future__ import annotations

import numpy as np
import pytest

import cshape
from cshape import plots, shapes
from cshape.plots.viewer import mesh3d_arrays, mode_data, symmetric_limits

go = pytest.importorskip("plotly.graph_objects")


@pytest.fixture(scope="module")
def sphere():
    return shapes.icosphere(2)


@pytest.fixture(scope="module")
def basis(sphere):
    return cshape.eigenbasis(sphere, 12)


@pytest.fixture(scope="module")
def pairs(basis):
    return basis.lam, basis.phi


# ------------------------------------------------------------------------------ pure parts
def test_symmetric_limits_cover_values_and_are_centred_on_zero():
    assert symmetric_limits([-0.2, 0.5, 0.1]) == 0.5
    assert symmetric_limits([-3.0, 1.0]) == 3.0
    assert symmetric_limits(np.zeros(4)) == 1.0  # never an empty range
    cols = symmetric_limits(np.array([[1.0, -4.0, 0.0], [-2.0, 3.0, 0.0]]))
    np.testing.assert_array_equal(cols, [2.0, 4.0, 1.0])


@pytest.mark.parametrize("bad, match", [
    (np.array([]), "shape"), (np.ones((2, 2, 2)), "shape"), ([0.0, np.nan], "NaN"),
])
def test_symmetric_limits_rejects_bad_values(bad, match):
    with pytest.raises(ValueError, match=match):
        symmetric_limits(bad)


def test_mode_data_per_mode(pairs):
    lam, phi = pairs
    modes = mode_data(lam, phi)
    assert [m["i"] for m in modes] == list(range(12))
    for m in modes:
        i = m["i"]
        assert m["cmin"] == -m["cmax"] and m["cmax"] == pytest.approx(np.abs(phi[:, i]).max())
        assert np.all(m["values"] >= m["cmin"]) and np.all(m["values"] <= m["cmax"])
        np.testing.assert_allclose(m["values"], phi[:, i], rtol=1e-6, atol=1e-7)
        assert m["lam"] == lam[i] and f"{lam[i]:.5g}" in m["title"] and f">{i}<" in m["title"]
    # the sphere's first non-constant eigenvalue 2 repeats 3 times (l = 1)
    assert [m["i"] for m in mode_data(lam, phi, [3, 1])] == [3, 1]


@pytest.mark.parametrize("indices, exc, match", [
    ([12], ValueError, r"indices must be an integer in \[0, 11\], got 12"),
    ([-1], ValueError, r"indices must be an integer in \[0, 11\], got -1"),
    ([True], TypeError, "indices must be an integer, got bool True"),
    ([1.5], TypeError, "indices must be an integer, got float 1.5"),
])
def test_mode_data_rejects_bad_indices(pairs, indices, exc, match):
    with pytest.raises(exc, match=match):
        mode_data(*pairs, indices)


def test_mode_data_rejects_mismatched_shapes(pairs):
    lam, phi = pairs
    with pytest.raises(ValueError, match="phi must have shape"):
        mode_data(lam[:5], phi)


def test_mesh3d_arrays(sphere):
    a = mesh3d_arrays(sphere)
    np.testing.assert_allclose(np.c_[a["x"], a["y"], a["z"]], sphere.vertices, rtol=1e-6)
    np.testing.assert_array_equal(np.c_[a["i"], a["j"], a["k"]], sphere.faces)
    # plain (vertices, faces) works the same
    b = mesh3d_arrays((sphere.vertices, sphere.faces))
    assert all(np.array_equal(a[k], b[k]) for k in "xyzijk")


# ------------------------------------------------------------------------------ figures
def test_explorer_has_one_frame_per_mode_and_a_slider(sphere, pairs, basis):
    fig = plots.eigenfunction_explorer(sphere, 12, start=3)
    assert isinstance(fig, go.Figure)
    assert len(fig.frames) == 12 and [f.name for f in fig.frames] == [str(i) for i in range(12)]
    (slider,) = fig.layout.sliders
    assert slider.active == 3 and [s.label for s in slider.steps] == [str(i) for i in range(12)]
    assert [list(s.args[0]) for s in slider.steps] == [[str(i)] for i in range(12)]
    lam, phi = pairs
    for i, fr in enumerate(fig.frames):
        (tr,) = fr.data
        assert tr.cmin == -tr.cmax  # symmetric about 0
        # the same eigenfunction up to sign (a repeated eigenvalue would allow any rotation,
        # but the solver is deterministic: same mesh, same basis)
        np.testing.assert_allclose(np.abs(tr.intensity), np.abs(phi[:, i]), atol=1e-5)
        assert f"{lam[i]:.5g}" in fr.layout.title.text
    (trace,) = fig.data
    np.testing.assert_array_equal(trace.intensity, fig.frames[3].data[0].intensity)
    assert fig.layout.title.text == fig.frames[3].layout.title.text
    # a given basis is used as it is
    fig2 = plots.eigenfunction_explorer(sphere, 5, basis=basis)
    np.testing.assert_array_equal(fig2.frames[4].data[0].intensity, phi[:, 4].astype(np.float32))


def test_explorer_repairs_the_mesh_once(sphere):
    V = np.vstack([sphere.vertices, sphere.vertices[:1]])  # a duplicate of vertex 0
    F = sphere.faces.copy()
    F[F == 0] = len(V) - 1
    F[0, 0] = 0
    with pytest.warns(cshape.CShapeWarning, match="welded 1 duplicate"):
        fig = plots.eigenfunction_explorer((V, F), 4)
    assert len(fig.data[0].x) == sphere.n_vertices == len(fig.frames[1].data[0].intensity)


@pytest.mark.parametrize("kwargs, exc, match", [
    (dict(N=0), ValueError, "N must be an integer >= 1, got 0"),
    (dict(N=2.5), TypeError, "N must be an integer, got float 2.5"),
    (dict(N=True), TypeError, "N must be an integer, got bool True"),
    (dict(N=4, start=4), ValueError, r"start must be an integer in \[0, 3\], got 4"),
    (dict(N=4, vertical_axis="up"), ValueError, "vertical_axis must be one of"),
    (dict(N=4, height=10), ValueError, "height must be a finite number >= 100, got 10"),
    (dict(N=4, height="tall"), TypeError, "height must be a real number, got str"),
    (dict(N=20, basis=cshape.Eigenbasis(np.zeros(5), np.zeros((162, 5)), np.eye(162))),
     ValueError, "basis has 5 eigenpairs on 162 vertices.*N >= 20"),
    (dict(N=4, basis=(np.zeros(5), np.zeros((162, 5)))), TypeError,
     "basis must be a cshape.Eigenbasis, got tuple"),
])
def test_explorer_rejects_bad_arguments(sphere, kwargs, exc, match):
    with pytest.raises(exc, match=match):
        plots.eigenfunction_explorer(sphere, **kwargs)


def test_view_mesh_colours_and_grey(sphere):
    f = sphere.vertices[:, 2] - 0.1
    fig = plots.view_mesh(sphere, f)
    (tr, *_) = fig.data
    assert tr.cmin == -tr.cmax == -np.abs(f).max()
    assert tr.colorscale[0][1] != tr.colorscale[-1][1]
    pos = plots.view_mesh(sphere, f - f.min())  # one sign: the range is the data's
    assert pos.data[0].cmin == pytest.approx(0.0, abs=1e-6)
    grey = plots.view_mesh(sphere, edges=True)
    assert grey.data[0].intensity is None and grey.data[1].mode == "lines"
    assert len(plots.view_mesh(sphere, edges=False).data) == 1


def test_view_meshes_side_by_side(sphere):
    cube = shapes.cube(3)
    fig = plots.view_meshes({"clean": sphere, "cube": cube}, {"cube": cube.vertices[:, 0]},
                            edges=False)
    assert [t.scene for t in fig.data] == ["scene", "scene2"]
    assert fig.data[0].intensity is None and fig.data[1].intensity is not None
    assert [a.text for a in fig.layout.annotations] == ["clean", "cube"]


@pytest.mark.parametrize("call, match", [
    (lambda m: plots.view_mesh(m, np.ones(3)), r"scalars\[''\] has 3 values"),
    (lambda m: plots.view_mesh(m, np.full(m.n_vertices, np.inf)), "NaN or infinite"),
    (lambda m: plots.view_meshes([m]), "meshes must be a non-empty dict"),
    (lambda m: plots.view_meshes({}), "meshes must be a non-empty dict"),
    (lambda m: plots.view_meshes({"a": m}, {"b": np.ones(3)}), r"keys \['b'\]"),
])
def test_view_rejects_bad_arguments(sphere, call, match):
    with pytest.raises((ValueError, TypeError), match=match):
        call(sphere)


def test_views_open_upright_with_the_whole_mesh_in_view():
    """The view is turned so that the vertical axis is plotly's z (turntable rotation keeps z
    up), by a rotation (cyclic column permutation, nothing mirrored), and the eye looks from
    20 degrees above, 60 degrees off the longest horizontal axis, from just far enough that
    the mesh fills the picture but for the margin."""
    from cshape.plots.viewer import default_eye

    box = shapes.cube(2)
    V = box.vertices * np.array([1.0, 3.0, 0.5])  # long along y, short along z
    mesh = cshape.Mesh(V, box.faces)
    fig = plots.view_mesh(mesh, vertical_axis="y")
    tr = fig.data[0]
    np.testing.assert_allclose(np.c_[tr.x, tr.y, tr.z], V[:, [2, 0, 1]], rtol=1e-6)
    cam = fig.layout.scene.camera
    assert (cam.up.x, cam.up.y, cam.up.z) == (0, 0, 1)
    eye = np.array([cam.eye.x, cam.eye.y, cam.eye.z])
    assert np.isclose(np.degrees(np.arcsin(eye[2] / np.linalg.norm(eye))), 20.0)
    # upright coordinates (z, x, y): the longest horizontal axis is the second one (old x)
    # against the first (old z, half as long): the eye sits mostly across it, 60 degrees off
    horizontal = np.hypot(eye[0], eye[1])
    assert np.isclose(abs(eye[1]), horizontal * np.cos(np.radians(60)))
    assert np.isclose(abs(eye[0]), horizontal * np.sin(np.radians(60)))
    assert default_eye(V, "y") == {"x": cam.eye.x, "y": cam.eye.y, "z": cam.eye.z}
    # z-up meshes keep their coordinates
    fig = plots.view_mesh(mesh)
    np.testing.assert_allclose(np.c_[fig.data[0].x, fig.data[0].y, fig.data[0].z], V, rtol=1e-6)


def _projected(points, eye, aspect):
    """Picture coordinates in [-1, 1] (x right, y up) of points seen by plotly's perspective
    camera (45 degrees vertical field of view) from ``eye`` towards the origin, z up."""
    f = -eye / np.linalg.norm(eye)
    right = np.cross(f, [0, 0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, f)
    depth = (points - eye) @ f
    t = np.tan(np.radians(22.5))
    return (points @ right) / (depth * t * aspect), (points @ up) / (depth * t)


@pytest.mark.parametrize("aspect", [0.5, 1.0, 2.5])
@pytest.mark.parametrize("scale", [(1.0, 1.0, 1.0), (4.0, 1.0, 0.5), (0.3, 0.4, 5.0)])
def test_scene_layout_fits_the_whole_mesh_with_the_margin(aspect, scale):
    """Every vertex projects inside the picture less the margin, and one touches that line
    (the eye is no further than needed), whatever the mesh's proportions and the scene's."""
    from cshape.plots.viewer import MARGIN, scene_layout

    V = shapes.icosphere(2).vertices * np.array(scale) + [3.0, -2.0, 7.0]
    sc = scene_layout(V, aspect=aspect)
    ranges = np.array([sc[f"{c}axis"]["range"] for c in "xyz"])
    ratio = np.array([sc["aspectratio"][c] for c in "xyz"])
    # plotly's scene units: the axis ranges mapped onto [-ratio/2, ratio/2]
    P = (V - ranges.mean(axis=1)) / np.ptp(ranges, axis=1) * ratio
    eye = np.array([sc["camera"]["eye"][c] for c in "xyz"])
    x, y = _projected(P, eye, aspect)
    reach = np.maximum(np.abs(x), np.abs(y)).max()
    assert np.isclose(reach, 1.0 - MARGIN)
    assert sc["aspectmode"] == "manual" and max(ratio) == 1.0


def test_fit_distance_known_answer():
    """Two points at +-s across the line of sight, eye on that line: d = s / ((1-m) tan 22.5)."""
    from cshape.plots.viewer import fit_distance

    P = np.array([[0.0, 0.3, 0.0], [0.0, -0.3, 0.0]])
    d = fit_distance(P, [1.0, 0.0, 0.0], aspect=1.0, margin=0.1)
    assert np.isclose(d, 0.3 / (0.9 * np.tan(np.radians(22.5))))
    # twice as wide a picture: the width no longer limits, the height (0) does not either
    assert np.isclose(fit_distance(P, [1.0, 0.0, 0.0], aspect=2.0, margin=0.1), d / 2)


def test_every_3d_view_is_lit_alike():
    """One lighting for every mesh trace of every 3-D view."""
    from cshape.plots.viewer import LIGHTING

    m = shapes.icosphere(2)
    basis = cshape.eigenbasis(m, N=6)
    figs = [plots.view_mesh(m), plots.view_meshes({"a": m, "b": m}, {"a": basis.phi[:, 1]}),
            plots.eigenfunction_explorer(m, 6, basis=basis),
            plots.view_map(m, m, np.arange(m.n_vertices))]
    for fig in figs:
        for tr in fig.data:
            if tr.type == "mesh3d":
                assert tr.lighting.to_plotly_json() == LIGHTING
                assert tr.flatshading is False


def test_scene_layout_rejects_bad_arguments():
    from cshape.plots.viewer import scene_layout

    V = shapes.icosphere(1).vertices
    with pytest.raises(ValueError, match="vertical_axis"):
        scene_layout(V, "w")
    with pytest.raises(ValueError, match="aspect"):
        scene_layout(V, aspect=0.0)
    with pytest.raises(ValueError, match="margin"):
        scene_layout(V, margin=0.95)
