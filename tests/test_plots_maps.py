"""Pictures of maps between shapes (cshape.plots.maps): the colours a map carries, the landmark
markers, the image of C, the offline 3-D view, and the errors of every argument."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import re  # noqa: E402

import matplotlib as mpl  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import cshape  # noqa: E402
from cshape import plots, shapes  # noqa: E402
from cshape.data import poses  # noqa: E402

TINY = {"voxelsize": 0.04, "target_vertices": 400}


@pytest.fixture(scope="module")
def pair():
    """The rest pose and pose 1 of the human (same vertices: the true map is the identity)."""
    return poses.posed_figure("human", rest=True, **TINY), poses.posed_figure("human", 1, **TINY)


@pytest.fixture(scope="module")
def sphere():
    return shapes.icosphere(1)


def rgb_direction(rgba):
    """Colours up to the shading factor (plot_mesh multiplies r, g, b by one factor)."""
    rgb = np.asarray(rgba)[:, :3]
    return rgb / rgb.sum(axis=1, keepdims=True)


# ------------------------------------------------------------------------------ map_colours
def test_map_colours_pull_back_and_one_range(sphere):
    n = sphere.n_vertices
    f = np.linspace(-1.0, 2.0, n)
    p = np.random.default_rng(0).integers(0, n, n)
    fS, fT, limits = plots.maps.map_colours(sphere, sphere, p, f)
    np.testing.assert_array_equal(fS, f)
    np.testing.assert_array_equal(fT, f[p])
    assert limits == (-1.0, 2.0)


def test_map_colours_default_is_a_ramp_along_the_longest_axis():
    # an ellipsoid 4 x 1 x 1: the ramp runs along x, so it is a linear function of x
    ball = shapes.icosphere(2)
    mesh = cshape.Mesh(ball.vertices * [4.0, 1.0, 1.0], ball.faces)
    fS, fT, (lo, hi) = plots.maps.map_colours(mesh, mesh, np.arange(mesh.n_vertices))
    x = mesh.vertices[:, 0] - mesh.vertices[:, 0].mean()
    assert abs(np.corrcoef(fS, x)[0, 1]) == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_array_equal(fS, fT)
    assert hi - lo == pytest.approx(np.ptp(mesh.vertices[:, 0]))


# ------------------------------------------------------------------------------ plot_map
def test_plot_map_identity_gives_the_same_colours(sphere):
    n = sphere.n_vertices
    fig = plots.plot_map(sphere, sphere, np.arange(n), values=sphere.vertices[:, 2])
    fig.draw_without_rendering()
    a, b = (ax for ax in fig.axes if ax.name == "3d")
    ca, cb = a.collections[0].get_facecolor(), b.collections[0].get_facecolor()
    assert ca.shape == (sphere.n_faces, 4)
    np.testing.assert_allclose(ca, cb)
    assert [a.get_title(), b.get_title()] == ["source", "target"]


def test_plot_map_carries_colours_through_the_map(sphere):
    n = sphere.n_vertices
    f = sphere.vertices[:, 2]
    top = int(np.argmax(f))
    fig = plots.plot_map(sphere, sphere, np.full(n, top), values=f, cmap="viridis")
    fig.draw_without_rendering()
    a, b = (ax for ax in fig.axes if ax.name == "3d")
    # every target vertex matched to the top: every target face has the top's colour, the
    # top of the source's range (one colour range for both), only shaded
    want = mpl.colormaps["viridis"](1.0)
    got = rgb_direction(b.collections[0].get_facecolor())
    np.testing.assert_allclose(got, np.tile(rgb_direction([want]), (sphere.n_faces, 1)), atol=1e-12)
    # the source keeps its own range: its faces are not all one colour
    assert np.ptp(rgb_direction(a.collections[0].get_facecolor()), axis=0).max() > 0.1
    cbar = [ax for ax in fig.axes if ax.name != "3d"]
    assert len(cbar) == 1 and cbar[0].get_ylim() == pytest.approx((f.min(), f.max()))


def test_plot_map_landmarks_share_a_colour_per_pair(pair):
    rest, pose = pair
    lm = np.array([[0, 5], [10, 10], [20, 3]])
    fig = plots.plot_map(rest, pose, np.arange(pose.n_vertices), landmarks=lm)
    fig.draw_without_rendering()
    a, b = (ax for ax in fig.axes if ax.name == "3d")
    assert len(a.collections) == len(b.collections) == 2
    ma, mb = a.collections[1], b.collections[1]
    # pair j in the j-th colour of tab10 on both shapes (drawn in depth order)
    want = mpl.colormaps["tab10"](np.arange(3))
    rows = sorted(map(tuple, want))
    assert sorted(map(tuple, ma.get_facecolor())) == sorted(map(tuple, mb.get_facecolor())) == rows
    # the markers sit on the landmark vertices of each shape
    np.testing.assert_allclose(np.column_stack(ma._offsets3d), rest.vertices[lm[:, 0]])
    np.testing.assert_allclose(np.column_stack(mb._offsets3d), pose.vertices[lm[:, 1]])


def test_plot_map_without_landmarks_has_only_the_meshes(pair):
    rest, pose = pair
    fig = plots.plot_map(rest, pose, np.arange(pose.n_vertices), titles=("rest", "pose 1"))
    a, b = (ax for ax in fig.axes if ax.name == "3d")
    assert len(a.collections) == len(b.collections) == 1
    assert b.get_title() == "pose 1"


# ------------------------------------------------------------------------------ C
def test_plot_functional_map_draws_C_on_a_symmetric_range():
    C = np.array([[1.0, 0.2, 0.0], [-0.1, -0.9, 0.3]])
    fig = plots.plot_functional_map(C)
    ax = fig.axes[0]
    im = ax.images[0]
    np.testing.assert_array_equal(im.get_array(), C)
    assert im.get_clim() == (-1.0, 1.0)
    assert im.get_cmap().name == "RdBu_r"
    assert ax.get_title() == "functional map C"
    assert len(fig.axes) == 2  # the colour bar
    fig2 = plots.plot_functional_map(C, title=None, colorbar=False, cmap="PuOr")
    assert len(fig2.axes) == 1 and fig2.axes[0].get_title() == ""


def test_diagonal_share_known_values():
    assert plots.diagonal_share(np.eye(4)) == 1.0
    assert plots.diagonal_share([[1.0, 2.0], [0.0, 1.0]]) == pytest.approx(2 / 6)
    assert plots.diagonal_share([[1.0, 2.0], [0.0, 1.0]], band=1) == 1.0
    assert plots.diagonal_share(np.fliplr(np.eye(4))) == 0.0


def test_functional_map_of_near_isometric_poses_is_near_diagonal(pair):
    rest, pose = pair
    b_s, b_t = cshape.eigenbasis(rest, 20), cshape.eigenbasis(pose, 20)
    true = cshape.maps.pointwise_to_map(np.arange(pose.n_vertices), b_s, b_t)
    shuffled = cshape.maps.pointwise_to_map(np.random.default_rng(0).permutation(rest.n_vertices),
                                       b_s, b_t)
    assert plots.diagonal_share(true, band=1) > 0.95  # measured 0.99
    assert plots.diagonal_share(shuffled, band=1) < 0.7  # measured 0.58 (C[0, 0] = 1 stays)


# ------------------------------------------------------------------------------ view_map
def test_view_map_offline_with_landmarks(pair):
    rest, pose = pair
    p = np.arange(pose.n_vertices)[::-1].copy() % rest.n_vertices
    lm = np.array([[1, 2], [30, 40]])
    f = rest.vertices[:, 0]
    fig = plots.view_map(rest, pose, p, values=f, landmarks=lm, titles=("rest", "pose"))
    meshes = [t for t in fig.data if t.type == "mesh3d"]
    marks = [t for t in fig.data if t.name == "landmarks"]
    assert len(meshes) == 2 and len(marks) == 2
    np.testing.assert_allclose(meshes[1].intensity, f[p].astype(np.float32))
    assert meshes[0].cmin == meshes[1].cmin == pytest.approx(f.min())
    assert marks[0].marker.color == marks[1].marker.color and len(marks[0].marker.color) == 2
    assert (marks[0].scene, marks[1].scene) == ("scene", "scene2")
    np.testing.assert_allclose(np.column_stack([marks[1].x, marks[1].y, marks[1].z]),
                               pose.vertices[lm[:, 1]])
    page = fig.to_html(include_plotlyjs=True, full_html=True)
    # plotly.js is in the page (its topojson default URL is never fetched for a 3-D scene)
    assert '<script src="http' not in page and "cdn.plot.ly/plotly" not in page
    assert "Plotly.newPlot" in page and len(page) > 1_000_000


def test_view_map_y_up_turns_the_markers_with_the_mesh(pair):
    rest, pose = pair
    lm = np.array([[3, 3]])
    fig = plots.view_map(rest, pose, np.arange(pose.n_vertices), landmarks=lm,
                         vertical_axis="y")
    mark = [t for t in fig.data if t.name == "landmarks"][0]
    x, y, z = rest.vertices[3]
    assert (mark.x[0], mark.y[0], mark.z[0]) == pytest.approx((z, x, y))


# ------------------------------------------------------------------------------ errors
@pytest.mark.parametrize("kwargs, err, match", [
    (dict(p2p=np.zeros(3, dtype=int)), ValueError, "p2p has 3 entries but the target has"),
    (dict(p2p="x"), TypeError, "p2p must be a 1-D integer array"),
    (dict(p2p=np.zeros(42)), TypeError, "p2p must be a 1-D integer array"),
    (dict(p2p=np.full(42, 42)), ValueError, r"p2p holds 42, outside \[0, 41\]"),
    (dict(p2p=np.full(42, -1)), ValueError, r"p2p holds -1, outside"),
    (dict(values=np.zeros(5)), ValueError, "values has shape \\(5,\\) but the source has 42"),
    (dict(values=np.full(42, np.nan)), ValueError, "values holds NaN"),
    (dict(values="abc"), TypeError, "values must be an array of numbers"),
    (dict(landmarks=[1, 2]), ValueError, r"landmarks must have shape \(L, 2\).*got shape \(2,\)"),
    (dict(landmarks=np.zeros((0, 2), int)), ValueError, "landmarks must have shape"),
    (dict(landmarks=[[0.5, 1.0]]), TypeError, "landmarks must be integer vertex indices"),
    (dict(landmarks=[[42, 0]]), ValueError, r"landmarks\[:, 0\] holds vertex index 42, outside"),
    (dict(landmarks=[[0, -1]]), ValueError, r"landmarks\[:, 1\] holds vertex index -1, outside"),
    (dict(titles="ab"), TypeError, "titles must be two strings"),
    (dict(cmap="no-such-map"), ValueError, "cmap must be a matplotlib colour map"),
    (dict(cmap=3), TypeError, "cmap must be a matplotlib colour map"),
    (dict(vertical_axis="w"), ValueError, "vertical_axis must be one of"),
    (dict(marker_size=-1.0), ValueError, "marker_size must be"),
    (dict(source="mesh"), TypeError, "source"),
])
def test_plot_map_errors(sphere, kwargs, err, match):
    args = dict(source=sphere, target=sphere, p2p=np.arange(sphere.n_vertices))
    args.update(kwargs)
    with pytest.raises(err, match=match):
        plots.plot_map(args.pop("source"), args.pop("target"), args.pop("p2p"), **args)


@pytest.mark.parametrize("kwargs, err, match", [
    (dict(landmarks=[[0, 99]]), ValueError, r"landmarks\[:, 1\] holds vertex index 99, outside"),
    (dict(marker_size=2.5), TypeError, "marker_size must be an integer"),
    (dict(vertical_axis=1), TypeError, "vertical_axis must be one of"),
    (dict(p2p=np.arange(5)), ValueError, "p2p has 5 entries"),
])
def test_view_map_errors(sphere, kwargs, err, match):
    args = dict(p2p=np.arange(sphere.n_vertices))
    args.update(kwargs)
    with pytest.raises(err, match=match):
        plots.view_map(sphere, sphere, args.pop("p2p"), **args)


@pytest.mark.parametrize("C, kwargs, err, match", [
    (np.zeros(3), {}, ValueError, r"C must be a non-empty 2-D array .* got shape \(3,\)"),
    (np.zeros((0, 2)), {}, ValueError, "C must be a non-empty 2-D array"),
    ([[1.0, np.inf]], {}, ValueError, "C holds NaN or inf"),
    ("C", {}, TypeError, "C must be a 2-D array of numbers"),
    ([[1.0, 0.0]], {"cmap": "nope"}, ValueError, "cmap must be a matplotlib colour map"),
])
def test_plot_functional_map_errors(C, kwargs, err, match):
    with pytest.raises(err, match=match):
        plots.plot_functional_map(C, **kwargs)


def test_diagonal_share_errors():
    with pytest.raises(ValueError, match="band must be an integer >= 0"):
        plots.diagonal_share(np.eye(2), band=-1)
    with pytest.raises(TypeError, match="band must be an integer"):
        plots.diagonal_share(np.eye(2), band=1.5)
    with pytest.raises(ValueError, match="C is all zeros"):
        plots.diagonal_share(np.zeros((2, 2)))


@pytest.mark.parametrize("bad", [[[0.5, 1.0]], [1, 2], np.zeros((0, 2), int)])
def test_landmark_errors_are_point_maps(sphere, bad):
    """The same bad landmarks get the same error from the pictures as from cshape.point_map."""
    with pytest.raises((TypeError, ValueError)) as want:
        cshape.point_map(sphere, sphere, N=10, N0=5, landmarks=bad)
    with pytest.raises(want.type, match=re.escape(str(want.value))):
        plots.plot_map(sphere, sphere, np.arange(sphere.n_vertices), landmarks=bad)


def test_the_maps_guide_example_runs():
    """The Python block of docs/guides/maps.md runs as written (small meshes); its map is good."""
    from pathlib import Path

    text = (Path(__file__).resolve().parent.parent / "docs" / "guides" / "maps.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    # the first block is the runnable example; the others are patterns on the user's meshes
    # (names such as source, target), which must at least be valid Python
    for block in blocks[1:]:
        compile(block, "docs/guides/maps.md", "exec")
    env: dict = {}
    exec(compile(blocks[0], "docs/guides/maps.md", "exec"), env)
    assert env["p"].shape == (env["pose"].n_vertices,) and env["C"].shape == (40, 40)
    assert env["err"].mean() / np.sqrt(env["rest"].area) < 0.1
    assert len(env["fig"].axes) == 3
    assert env["fig_C"].axes[0].images[0].get_array().shape == (40, 40)
