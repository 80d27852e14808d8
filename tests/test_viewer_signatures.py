"""The signature explorer and the correspondence view (cshape.plots.viewer): their pure parts
(per-scale colour data, colours carried through a point map) and the figures."""

from __future__ import annotations

import numpy as np
import pytest

import cshape
from cshape import shapes
from cshape import signatures as sg

go = pytest.importorskip("plotly.graph_objects")

from cshape import plots  # noqa: E402
from cshape.plots.viewer import scale_data  # noqa: E402


@pytest.fixture(scope="module")
def ellipsoid():
    m = shapes.icosphere(3)
    return cshape.Mesh(m.vertices * [1.0, 0.7, 0.5], m.faces)


@pytest.fixture(scope="module")
def basis(ellipsoid):
    return cshape.eigenbasis(ellipsoid, 40)


def test_scale_data_per_column_log_range_and_titles():
    sig = np.array([[1.0, 10.0], [100.0, 10.0], [10.0, 10.0]])
    d = scale_data(sig, [0.5, 2.0])
    assert [x["j"] for x in d] == [0, 1]
    np.testing.assert_allclose(d[0]["values"], [0.0, 2.0, 1.0])
    assert (d[0]["cmin"], d[0]["cmax"]) == (0.0, 2.0)
    assert (d[1]["cmin"], d[1]["cmax"]) == (1.0, 2.0)  # a constant column: a non-empty range
    assert "HKS at t = 0.5" in d[0]["title"] and "log" in d[0]["title"]
    w = scale_data(sig, [1.0, 3.0], signature="wks", log=False)
    np.testing.assert_allclose(w[0]["values"], sig[:, 0])
    assert w[1]["title"] == "WKS at e = 3"


@pytest.mark.parametrize("kwargs, exc, match", [
    ({"sig": np.ones((3, 2)), "scales": [1.0]}, ValueError, r"k = len\(scales\) = 1"),
    ({"sig": -np.ones((3, 1)), "scales": [1.0]}, ValueError, "log=True needs values > 0"),
    ({"sig": np.ones((3, 1)), "scales": [1.0], "signature": "gps"}, ValueError,
     r"signature must be one of \{'hks', 'wks'\}"),
    ({"sig": np.ones((3, 1)), "scales": [1.0], "log": 1}, TypeError, "log must be True or False"),
])
def test_scale_data_rejects_bad_arguments(kwargs, exc, match):
    with pytest.raises(exc, match=match):
        scale_data(**kwargs)


def test_signature_explorer_frames_are_the_hks_at_spread_times(ellipsoid, basis):
    fig = plots.signature_explorer(ellipsoid, basis=basis, n_scales=5)
    assert len(fig.frames) == 5 and len(fig.layout.sliders[0].steps) == 5
    t = sg.hks_times(basis)
    h = sg.hks(basis, t)
    cols = [0, 25, 50, 74, 99]  # 5 of the 100 default times, evenly spread
    for frame, c in zip(fig.frames, cols, strict=True):
        np.testing.assert_allclose(frame.data[0].intensity, np.log10(h[:, c]), rtol=1e-5)
        assert f"{t[c]:.4g}" in frame.layout.title.text
    assert fig.layout.sliders[0].active == 2  # the middle step first
    np.testing.assert_allclose(fig.data[0].intensity, fig.frames[2].data[0].intensity)
    # WKS: Aubry's energies; computed here when no basis is given
    fig_w = plots.signature_explorer(ellipsoid, "wks", N=40, n_scales=3, log=False, start=0)
    e, sigma = sg.wks_energies(basis)
    np.testing.assert_allclose(fig_w.frames[0].data[0].intensity,
                               sg.wks(basis, e[:1], sigma)[:, 0], rtol=1e-4)
    assert fig_w.layout.sliders[0].currentvalue.prefix == "e = "


@pytest.mark.parametrize("kwargs, exc, match", [
    ({"signature": "si-hks"}, ValueError, r"signature must be one of \{'hks', 'wks'\}"),
    ({"n_scales": 0}, ValueError, r"n_scales must be an integer in \[1, 100\], got 0"),
    ({"n_scales": 2.0}, TypeError, "n_scales must be an integer, got float"),
    ({"start": 7, "n_scales": 5}, ValueError, r"start must be an integer in \[0, 4\]"),
    ({"basis": cshape.Eigenbasis(np.ones(3), np.ones((5, 3)), np.eye(5))}, ValueError,
     "basis has 3 eigenpairs on 5 vertices, but the"),
    ({"basis": (np.ones(3), np.ones((5, 3)))}, TypeError, "basis must be a cshape.Eigenbasis"),
])
def test_signature_explorer_rejects_bad_arguments(ellipsoid, basis, kwargs, exc, match):
    kwargs = {"basis": basis, **kwargs}
    with pytest.raises(exc, match=match):
        plots.signature_explorer(ellipsoid, **kwargs)


def test_view_map_of_signature_matches_identity_gives_the_same_colours(ellipsoid):
    """A map by nearest signatures (with unmatched vertices) is viewed like any point map."""
    n = ellipsoid.n_vertices
    moved = cshape.Mesh(ellipsoid.vertices + [3.0, 0, 0], ellipsoid.faces)
    fig = plots.view_map(ellipsoid, moved, np.arange(n), titles=("rest", "pose"))
    a, b = [tr for tr in fig.data if tr.type == "mesh3d"]
    np.testing.assert_allclose(a.intensity, b.intensity)
    assert (a.cmin, a.cmax) == (b.cmin, b.cmax)  # one colour range: same value, same colour
    # the default colours: position along the longest axis (x for this ellipsoid)
    assert abs(np.corrcoef(a.intensity, ellipsoid.vertices[:, 0])[0, 1]) > 0.99
    rev = np.arange(n)[::-1].copy()
    rev[:4] = -1  # match_points(..., mutual=True): not matched
    fig2 = plots.view_map(ellipsoid, moved, rev)
    assert "4 unmatched" in fig2.layout.annotations[1].text
    b2 = [tr for tr in fig2.data if tr.type == "mesh3d"][1]
    np.testing.assert_allclose(b2.intensity[4:], np.asarray(a.intensity)[rev[4:]])
    np.testing.assert_allclose(b2.intensity[:4], np.mean(a.intensity), atol=1e-12)
    with pytest.raises(ValueError, match="p2p has 3 entries but the target has"):
        plots.view_map(ellipsoid, moved, [0, 1, 2])
    with pytest.raises(ValueError, match=r"p2p holds -2, outside \[-1, "):
        plots.view_map(ellipsoid, moved, np.full(n, -2))
