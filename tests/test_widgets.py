"""The M sweep: pure functions (Section 3.2, Fig. 6) and the thin ipywidgets shell."""

from __future__ import annotations

import numpy as np
import pytest

import cshape
from cshape import compare, shapes
from cshape.batch import DescriptorTable
from cshape.descriptors import inverse_compact_shape_dna
from cshape.plots import widgets

N = 24


@pytest.fixture(scope="module")
def collection():
    """Six small meshes in three classes, eigenvalues computed once."""
    meshes = {
        "sphere-1": shapes.icosphere(2), "sphere-2": shapes.icosphere(2, radius=1.5),
        "cube-1": shapes.cube(4), "cube-2": shapes.cube(5),
        "torus-1": shapes.torus(16, 8), "torus-2": shapes.torus(20, 10),
    }
    lams = np.vstack([cshape.shape_dna(m, N) for m in meshes.values()])
    areas = np.array([m.area for m in meshes.values()])
    labels = [n.split("-")[0] for n in meshes]
    return DescriptorTable(list(meshes), lams, areas, labels)


def test_sweep_state_matches_the_descriptors(collection):
    t = collection
    st = widgets.sweep_state(t.lam, t.areas, t.labels, M=4, N=N, names=t.names)
    assert st.coefficients.shape == (6, 9) and st.size == 9
    for i in range(6):  # Eq. (8)-(10), row by row
        S = cshape.compact_shape_dna(t.lam[i], M=4, N=N, area=t.areas[i])
        np.testing.assert_allclose(st.coefficients[i], S, rtol=1e-12, atol=1e-9)
    D_ref = compare.distance_matrix(cshape.Descriptor("shape-dna", N=N).matrix(t.lam, t.areas))
    D = compare.distance_matrix(cshape.Descriptor("cshape", N=N, M=4).matrix(t.lam, t.areas))
    np.testing.assert_allclose(st.D_ref, compare.scale_255(D_ref), atol=1e-9)
    np.testing.assert_allclose(st.D, compare.scale_255(D), atol=1e-9)
    mean, std = compare.scaled_difference(D_ref, D)
    assert st.mean == pytest.approx(mean) and st.std == pytest.approx(std)
    np.testing.assert_allclose(st.difference, compare.difference_matrix(D_ref, D), atol=1e-9)
    assert st.mds.shape == (6, 2)
    assert set(st.retrieval) == {"nn", "ft", "nn_ref", "ft_ref"}
    assert "mean" in st.summary() and "std" in st.summary()


def test_reconstruction_is_exact_when_nothing_is_cropped(collection):
    t = collection
    sweep = widgets.MSweep.from_table(t)
    st = sweep.state(11, N=23)  # 2M+1 = N: every frequency kept
    np.testing.assert_allclose(st.reconstruction, st.lam_prime, atol=1e-9)
    assert st.reconstruction_error.max() < 1e-12
    small = sweep.state(1, N=23)
    assert np.all(small.reconstruction_error > st.reconstruction_error)
    rebuilt = inverse_compact_shape_dna(small.coefficients[0], 23, add_weyl=False)
    np.testing.assert_allclose(small.reconstruction[0], rebuilt, atol=1e-9)


def test_difference_shrinks_as_M_grows(collection):
    sweep = widgets.MSweep.from_table(collection)
    means = [sweep.state(M).mean for M in (1, 4, 11)]
    assert means[2] < means[0]


def test_M_independent_stages_are_computed_once(collection, monkeypatch):
    sweep = widgets.MSweep.from_table(collection, mds=False)
    sweep.state(3)
    calls = []
    monkeypatch.setattr(widgets, "normalize", lambda *a, **k: calls.append(1))
    for M in range(0, 12):
        sweep.state(M)  # new M: only the cheap stages, no new normalisation
    assert calls == [] and len(sweep._base) == len(sweep._ref) == 1
    assert sweep.state(5) is sweep.state(5)  # cached


@pytest.mark.parametrize("M, N, match", [
    (12, 24, r"M must be in \[0, 11\] for N = 24"),
    (-1, 24, r"M must be in \[0, 11\]"),
    (2, 25, r"N must be in \[3, 24\]"),
])
def test_sweep_state_rejects_bad_M_and_N(collection, M, N, match):
    with pytest.raises(ValueError, match=match):
        widgets.MSweep.from_table(collection).state(M, N=N)


def test_sweep_validation(collection):
    t = collection
    with pytest.raises(TypeError, match="M must be an integer"):
        widgets.MSweep.from_table(t).state(2.5)
    with pytest.raises(ValueError, match="normalization must be one of"):
        widgets.MSweep.from_table(t, normalization="volume")
    with pytest.raises(ValueError, match="areas has 2 entries but lams has 6 rows"):
        widgets.MSweep(t.lam, [1.0, 2.0])
    with pytest.raises(ValueError, match="at least two shapes"):
        widgets.MSweep(t.lam[:1], t.areas[:1])


def test_clamp_M():
    assert widgets.clamp_M(16, 100) == 16
    assert widgets.clamp_M(60, 100) == 49
    assert widgets.clamp_M(5, 10) == 4
    assert widgets.clamp_M(-3, 10) == 0


def test_widget_updates_on_slider_and_clamps(collection, monkeypatch):
    import IPython.display

    def no_display(*a, **k):
        raise AssertionError("the widget factory must not display anything")

    monkeypatch.setattr(IPython.display, "display", no_display)
    w = widgets.m_sweep_widget(collection, M=8, dpi=40, figsize=(8, 5))
    assert w.state.M == 8 and w.controls["M"].max == (N - 1) // 2
    png0, stats0 = w.image.value, w.stats.value
    assert png0[:8] == b"\x89PNG\r\n\x1a\n"
    w.controls["M"].value = 2
    assert w.state.M == 2
    assert w.image.value != png0 and w.stats.value != stats0
    assert "M = 2" in w.stats.value
    w.controls["N"].value = 5  # M clamped to (N-1)//2 = 2, slider max follows
    assert w.controls["M"].max == 2 and w.state.N == 5 and w.state.M <= 2
    w.controls["normalization"].value = "weyl"
    assert w.state.normalization == "weyl"
    w.controls["shape"].value = 3
    assert w.state.M <= 2


def test_widget_with_several_collections(collection):
    t = collection
    w = widgets.m_sweep_widget({"all": t, "two classes": t.select(range(4))}, M=20, dpi=30,
                               figsize=(6, 4))
    assert w.state.M == (N - 1) // 2  # clamped at construction
    w.controls["collection"].value = "two classes"
    assert len(w.state.names) == 4 and len(w.controls["shape"].options) == 4


def test_widget_rejects_other_data():
    with pytest.raises(TypeError, match="DescriptorTable"):
        widgets.m_sweep_widget(np.ones((3, 10)))


def test_plot_m_sweep_returns_a_figure(collection):
    from matplotlib.figure import Figure

    from cshape import plots

    st = widgets.MSweep.from_table(collection).state(3)
    fig = plots.plot_m_sweep(st, shape=2, figsize=(6, 4))
    assert isinstance(fig, Figure) and len(fig.axes) >= 6
    with pytest.raises(ValueError, match=r"shape must be an integer in \[0, 5\], got 6"):
        plots.plot_m_sweep(st, shape=6)
    with pytest.raises(TypeError, match="shape must be an integer, got float 1.0"):
        plots.plot_m_sweep(st, shape=1.0)


# ------------------------------------------------------------------------------ plots
def test_plots_return_figures_without_pyplot():
    import matplotlib.pyplot as plt
    from matplotlib.figure import Figure

    from cshape import plots

    mesh = shapes.icosphere(1)
    lam, phi = cshape.spectrum.eigenpairs(mesh, 12)
    before = plt.get_fignums()
    figs = [
        plots.plot_mesh(mesh, phi[:, 1], colorbar=True),
        plots.plot_mesh(mesh, vertical_axis="y"),
        plots.plot_eigenfunctions(mesh, phi, [1, 2], lam),
        plots.plot_weyl({"s": lam}, {"s": mesh.area}),
        plots.plot_shape_dna_stages(lam, mesh.area),
        plots.plot_dft(lam, mesh.area, 2),
        plots.plot_reconstruction_error([1, 2], [0.5, 0.1]),
        plots.plot_convergence([0.2, 0.1], [[1e-2, 2.5e-3]]),
        plots.plot_cshape_dna({"s": cshape.compact_shape_dna(lam, N=12, M=2, area=mesh.area)}),
        plots.plot_matrices([np.eye(3), np.ones((3, 3))], ["a", "b"]),
    ]
    assert all(isinstance(f, Figure) for f in figs)
    assert plt.get_fignums() == before  # nothing registered with pyplot, nothing shown


def test_plot_validation():
    from cshape import plots

    mesh = shapes.icosphere(1)
    with pytest.raises(ValueError, match="f has 3 values but the mesh has 42 vertices"):
        plots.plot_mesh(mesh, np.ones(3))
    with pytest.raises(ValueError, match=r"phi must have shape \(n_vertices, k\)"):
        plots.plot_eigenfunctions(mesh, np.ones((5, 2)))
    with pytest.raises(ValueError, match="areas has no entry"):
        plots.plot_weyl({"s": np.arange(5.0)}, {})
    with pytest.raises(TypeError, match="spectra must be a dict"):
        plots.plot_weyl([np.arange(5.0)], {})


# ------------------------------------------------------------------ the transform toggle
@pytest.mark.parametrize("transform", ["weyl", "log-weyl", "log-weyl-dct"])
def test_sweep_state_for_every_transform_matches_the_descriptors(collection, transform):
    t = collection
    sweep = widgets.MSweep.from_table(t, mds=False)
    st = sweep.state(4, N=N, transform=transform)
    assert st.transform == transform and st.coefficients.shape == (6, 9)
    L = N if transform == "weyl" else N - 1
    assert st.lam_prime.shape == st.reconstruction.shape == st.spectra.shape == (6, L)
    for i in range(6):
        S = cshape.compact_shape_dna(t.lam[i], M=4, N=N, area=t.areas[i], transform=transform)
        np.testing.assert_allclose(st.coefficients[i], S, rtol=1e-12, atol=1e-12)
        rec = inverse_compact_shape_dna(S, N, add_weyl=False, transform=transform)
        np.testing.assert_allclose(st.reconstruction[i], rec, atol=1e-12)
    X = cshape.Descriptor("cshape", N=N, M=4, transform=transform).matrix(t.lam, t.areas)
    np.testing.assert_allclose(st.D, compare.scale_255(compare.distance_matrix(X)), atol=1e-9)
    # the Shape-DNA reference does not depend on the transform, and is computed once
    np.testing.assert_array_equal(st.D_ref, sweep.state(4, N=N, transform="weyl").D_ref)
    assert len(sweep._ref) == 1
    if transform != "weyl":
        assert "(" + transform + ")" in st.summary()
        full = sweep.state(widgets.max_M(N, transform), N=N, transform=transform)  # 2M+1 = N-1
        np.testing.assert_allclose(full.reconstruction, full.lam_prime, atol=1e-12)


def test_max_M_and_clamp_for_the_transforms():
    assert widgets.max_M(24) == 11 and widgets.max_M(24, "log-weyl") == 11
    assert widgets.max_M(25) == 12 and widgets.max_M(25, "log-weyl-dct") == 11
    assert widgets.clamp_M(20, 25, "log-weyl") == 11 and widgets.clamp_M(20, 25) == 12
    with pytest.raises(ValueError, match="transform must be one of"):
        widgets.max_M(25, "dft")


def test_sweep_rejects_M_beyond_the_log_weyl_bound(collection):
    sweep = widgets.MSweep.from_table(collection.select(range(4)), mds=False)
    sweep.state(11, N=23)  # fine for the paper's transform
    with pytest.raises(ValueError, match=r"M must be in \[0, 10\] for N = 23 \(2M\+1 <= N-1\)"):
        sweep.state(11, N=23, transform="log-weyl")
    with pytest.raises(ValueError, match="transform must be one of"):
        widgets.MSweep.from_table(collection, transform="log")


def test_widget_transform_toggle_clamps_M(collection):
    sweep = widgets.MSweep.from_table(collection.select(range(4)), mds=False)
    w = widgets.m_sweep_widget(sweep, M=11, N=23, dpi=30, figsize=(6, 4))
    assert w.state.M == 11 and w.state.transform == "weyl"
    png = w.image.value
    w.controls["transform"].value = "log-weyl-dct"  # M = 11 needs 2M+1 = 23 > N-1 = 22
    assert w.state.transform == "log-weyl-dct" and w.state.M == 10
    assert w.controls["M"].max == 10 and w.image.value != png
    assert "(log-weyl-dct)" in w.stats.value
    w.controls["transform"].value = "log-weyl"
    assert w.state.transform == "log-weyl" and w.state.M == 10
    w.controls["transform"].value = "weyl"
    assert w.controls["M"].max == 11 and w.state.transform == "weyl"


def test_widget_shows_its_picture_where_no_kernel_runs(collection):
    """The widget's display data carry, besides the live view, its current picture and
    statistics as HTML: what an exported page shows when no widget state was saved."""
    import base64

    pytest.importorskip("ipywidgets")
    w = widgets.m_sweep_widget(collection, M=3, dpi=40, figsize=(8, 5))
    data = w._repr_mimebundle_()
    assert "application/vnd.jupyter.widget-view+json" in data
    page = data["text/html"]
    assert w.state.summary() in page.replace("&#x27;", "'").replace("&quot;", '"')
    png = base64.b64decode(page.split("base64,")[1].split('"')[0])
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and png == bytes(w.image.value)
    w.controls["M"].value = 1
    assert "M = 1" in w._repr_mimebundle_()["text/html"]
