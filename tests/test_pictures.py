"""Pictures of one's own collection (issue 19, part 3): the pure functions behind them with
known answers (outliers, layout, neighbour lists, class table, thumbnails), the figure
functions (they return figures, never show), the files (atomic, offline HTML) and the
command line (`cshape overview`, `cshape query --plot`), in-process; one subprocess run
each in the slow tier.  The real browser checks are in test_browser.py."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest
from conftest import write_off

import cshape
from cshape import Descriptor, shapes
from cshape.batch import DescriptorTable
from cshape.batch.table import collection_distances
from cshape.cli import main
from cshape.compare import distance_matrix, mds_outliers, median_distances, nearest_neighbours
from cshape.descriptors import recipe
from cshape.mesh import CShapeWarning
from cshape.plots.collection import class_styles, plot_mds
from cshape.plots.layout import border_points, mds_layout, spread_on_border
from cshape.plots.overview import (
    class_summary,
    colour_limit,
    interactive_mds,
    neighbour_strip_plotly,
    overview_html,
    plot_neighbour_strip,
    plot_overview,
    save_figure,
    thumbnail_mesh,
)


def blob_with_outlier(p=30, seed=0):
    """A 2-D Gaussian blob of p-1 points and one point 1000 units away."""
    Y = np.random.default_rng(seed).normal(size=(p, 2))
    Y[-1] = [1000.0, 0.0]
    return Y


def spectra_table(p=8, n_classes=2, N=30, seed=0, **kw):
    """A DescriptorTable of Weyl-like spectra (no eigensolve), classes c0, c1, ..."""
    rng = np.random.default_rng(seed)
    labels = [f"c{k % n_classes}" for k in range(p)]
    i = np.arange(N)
    lam = np.array([4 * np.pi * i * (1 + 0.2 * int(lab[1:]) + 0.01 * rng.random(N))
                     for lab in labels])
    return DescriptorTable([f"shape{k}" for k in range(p)], lam, np.ones(p), labels, **kw)


#: The descriptors of the pictures' tests: spectra_table's N = 30, M = 4.
LOG9 = Descriptor("truncated-log", N=30, M=4)
SD30 = Descriptor("shape-dna", N=30)


# ------------------------------------------------------------------------------ outliers
def test_median_distances_known_values_and_reference_subset():
    x = np.array([[0.0, 0], [1, 0], [3, 0]])
    assert median_distances(x).tolist() == [2.0, 1.5, 2.5]  # medians of [1,3], [1,2], [3,2]
    Y = np.arange(10.0)[:, None] * [1.0, 0.0]
    # against rows 0, 4.5->4 (rounded: 0, 4, 9 -> evenly spaced), never against itself
    ref = median_distances(Y, reference=3)
    assert ref[0] == np.median([4.0, 9.0]) and ref[4] == np.median([4.0, 5.0])
    assert median_distances(np.zeros((1, 2))).tolist() == [0.0]


def test_mds_outliers_flags_the_far_point_only():
    Y = blob_with_outlier()
    out = mds_outliers(Y)
    assert out.tolist() == [False] * 29 + [True]
    # a Gaussian cloud, round or thin, has none; nor has a set of mostly equal points
    rng = np.random.default_rng(3)
    assert not mds_outliers(rng.normal(size=(2000, 2))).any()
    assert not mds_outliers(rng.normal(size=(2000, 2)) * [10.0, 0.1]).any()
    assert not mds_outliers(np.r_[np.zeros((5, 2)), [[1.0, 1.0]]]).any()
    assert not mds_outliers(np.array([[0.0, 0.0], [1e6, 0.0]])).any()  # fewer than 3
    # the factor is the threshold: the point at 1000 is ~800 times the typical distance
    assert not mds_outliers(Y, factor=5000.0).any()


def test_mds_outliers_rejects_a_factor_of_one():
    with pytest.raises(ValueError, match=r"factor must be a finite number > 1, got 1\.0"):
        mds_outliers(blob_with_outlier(), factor=1.0)


def test_border_points_known_answer():
    P, angle = border_points([[10.0, 5.0], [0.0, -3.0], [0.1, 0.0]], [True, True, False],
                             [0.0, 0.0], 1.0)
    assert P.tolist() == [[1.0, 0.5], [0.0, -1.0]]
    assert angle.round(2).tolist() == [26.57, -90.0]


def test_spread_on_border_keeps_points_on_the_border_apart_and_in_order():
    P = np.array([[1.0, 0.0], [1.0, 0.01], [1.0, 0.02], [-1.0, 0.5]])
    Q = spread_on_border(P, [0.0, 0.0], 1.0, 0.2)
    assert np.allclose(np.abs(Q).max(axis=1), 1.0)  # on the border
    assert np.all(np.diff(Q[:3, 1]) >= 0.2 - 1e-9)  # apart, in their order
    assert np.allclose(Q[:3, 1].mean(), 0.01)  # spread around where they were
    assert np.allclose(Q[3], P[3])  # alone on its side: not moved
    assert spread_on_border(P[:1], [0, 0], 1.0, 0.2).tolist() == [[1.0, 0.0]]


def test_mds_layout_scales_to_the_inliers():
    Y = blob_with_outlier()
    lay = mds_layout(Y)
    inl = ~lay["outliers"]
    assert lay["outliers"].sum() == 1
    assert np.array_equal(lay["P"][inl], Y[inl])  # inliers where they are
    c, h = lay["centre"], lay["half"]
    extent = (Y[inl].max(axis=0) - Y[inl].min(axis=0)).max()
    assert extent / 2 < h < extent  # the panel fits the inliers, not the outlier
    assert np.all(np.abs(lay["P"] - c) <= h)  # the outlier is drawn inside the panel
    assert np.abs(lay["P"][-1] - c).max() > 0.9 * h  # ... on its border
    assert lay["P"][-1, 0] > c[0]  # ... on its side
    assert lay["ratio"][-1] > 100
    none = mds_layout(Y, outliers=None)
    assert not none["outliers"].any() and none["half"] > 500


def test_class_styles_are_distinct_beyond_twenty_classes():
    labels = [f"k{i}" for i in range(45)]
    codes, styles = class_styles(labels)
    assert codes.tolist() == list(range(45))
    assert len({(tuple(c), m) for _, c, m in styles}) == 45
    assert [m for _, _, m in styles[:3]] == ["o", "o", "o"] and styles[20][2] == "s"


# ------------------------------------------------------------------------------ neighbours
def test_nearest_neighbours_known_answer_self_left_out_ties_by_row():
    D = np.array([[0, 1, 3, 0], [1, 0, 1, 1], [3, 1, 0, 3], [0, 1, 3, 0]], dtype=float)
    ind, dist = nearest_neighbours(D, k=2)
    assert ind.tolist() == [[3, 1], [0, 2], [1, 0], [0, 1]]  # row 3 duplicates row 0
    assert dist.tolist() == [[0, 1], [1, 1], [1, 3], [0, 1]]
    ind, dist = nearest_neighbours(D, k=10)  # at most p - 1
    assert ind.shape == (4, 3)


def test_nearest_neighbours_rejects_k_zero():
    with pytest.raises(ValueError, match="k must be an integer >= 1"):
        nearest_neighbours(np.zeros((2, 2)), k=0)


def test_class_summary_known_answer():
    # a, a, b, b, c: a's two shapes 1 apart, b's 2; a0 is 3 from b0, b1 is 1.5 from c
    D = np.array([[0, 1, 3, 4, 9],
                  [1, 0, 5, 6, 9],
                  [3, 5, 0, 2, 9],
                  [4, 6, 2, 0, 1.5],
                  [9, 9, 9, 1.5, 0]])
    rows = {r["label"]: r for r in class_summary(D, list("aabbc"))}
    assert list(rows) == ["a", "b", "c"]
    assert (rows["a"]["n"], rows["a"]["within"], rows["a"]["nearest"], rows["a"]["gap"]) == (
        2, 1.0, "b", 3.0)
    assert rows["a"]["nn_same"] == 1.0
    assert (rows["b"]["within"], rows["b"]["nearest"], rows["b"]["gap"]) == (2.0, "c", 1.5)
    assert rows["b"]["nn_same"] == 0.5  # b0's nearest is b1; b1's is c
    assert np.isnan(rows["c"]["within"]) and np.isnan(rows["c"]["nn_same"])
    assert (rows["c"]["nearest"], rows["c"]["gap"]) == ("b", 1.5)


def test_colour_limit_leaves_the_outliers_out():
    D = distance_matrix(blob_with_outlier(10))
    out = [False] * 9 + [True]
    assert colour_limit(D, out) == D[:9, :9].max() < 100 < D.max()
    assert colour_limit(D, [False] * 10) == D.max()


# ------------------------------------------------------------------------------ descriptors
def test_collection_distances_of_a_table():
    table = spectra_table()
    c = collection_distances(table, LOG9)
    # the truncated log-Weyl ratios r_1 .. r_9 are at the distances of the truncated log
    # spectrum log(lam_i * area), i = 1 .. 9 (the Weyl term 4 pi i cancels in a difference)
    logs = np.log(table.lam[:, 1:10] * np.asarray(table.areas)[:, None])
    expected = np.linalg.norm(logs[:, None, :] - logs[None, :, :], axis=-1)
    np.testing.assert_allclose(c.D, expected, rtol=1e-10, atol=1e-12)
    assert c.rows.tolist() == list(range(8)) and c.left_out == [] and c.names == table.names
    assert c.descriptor == LOG9 and c.descriptor.label == "truncated log spectrum (9 values)"


def test_collection_distances_leaves_out_what_cannot_be_described():
    """A row without a positive area is left out and named."""
    t = spectra_table(p=5)
    areas = t.areas.copy()
    areas[2] = 0.0
    table = DescriptorTable(t.names, t.lam, areas, t.labels)
    with pytest.warns(CShapeWarning, match=r"Shape-DNA \(30 values\) cannot describe 1 of 5 "
                                           r"shapes, left out: shape2"):
        c = collection_distances(table, SD30)
    assert c.rows.tolist() == [0, 1, 3, 4] and [n for n, _ in c.left_out] == ["shape2"]
    assert c.names == ["shape0", "shape1", "shape3", "shape4"]
    assert np.allclose(c.D, distance_matrix(t.lam[[0, 1, 3, 4]]))


def test_collection_distances_with_meshes_of_several_pieces():
    """Zero eigenvalues (pieces) are dropped: two pieces are described; a mesh of so many
    pieces that too few non-zero eigenvalues remain is left out, named in the warning."""
    t = spectra_table(p=5)
    lam = t.lam.copy()
    lam[1, 1] = 0.0  # two pieces
    lam[3, :25] = 0.0  # 25 pieces: 5 non-zero eigenvalues, truncated-log M=4 needs 10
    table = DescriptorTable(t.names, lam, t.areas, t.labels)
    with pytest.warns(CShapeWarning, match=r"cannot describe 1 of 5 shapes, left out: shape3"):
        c = collection_distances(table, LOG9)
    assert c.rows.tolist() == [0, 1, 2, 4] and [n for n, _ in c.left_out] == ["shape3"]
    assert np.allclose(c.D, distance_matrix(table.select([0, 1, 2, 4]).descriptors(LOG9)))


def test_collection_distances_errors():
    table = spectra_table(p=3)
    with pytest.raises(TypeError, match=r"descriptor must be a cshape.Descriptor .* got str"):
        collection_distances(table, "nope")
    with pytest.raises(ValueError, match=r"lams\[0\] has shape \(30,\) but kind='cshape' needs "
                                         r"at least 100 eigenvalues"):
        collection_distances(table, cshape.PAPER)
    with pytest.raises(ValueError, match=r"only 0 of the 3 shapes can be described"), \
            pytest.warns(CShapeWarning):
        collection_distances(DescriptorTable(table.names, table.lam, np.zeros(3)), SD30)


# ------------------------------------------------------------------------------ thumbnails
def test_thumbnail_mesh_fewer_faces_same_extent():
    mesh = shapes.icosphere(5)  # 20480 triangles
    V, F = thumbnail_mesh(mesh, max_faces=2000)
    assert 200 < len(F) <= 2000 and F.max() < len(V) and F.min() >= 0
    assert np.all(F[:, 0] != F[:, 1]) and np.all(F[:, 1] != F[:, 2])
    ext0 = mesh.vertices.max(axis=0) - mesh.vertices.min(axis=0)
    assert np.allclose(V.max(axis=0) - V.min(axis=0), ext0, rtol=0.1)
    small = shapes.icosphere(1)
    V1, F1 = thumbnail_mesh(small, max_faces=2000)
    assert np.array_equal(V1, small.vertices) and np.array_equal(F1, small.faces)


# ------------------------------------------------------------------------------ figures
def test_plot_mds_marks_the_outlier_and_names_it():
    Y = blob_with_outlier(12)
    names = [f"s{i}" for i in range(11)] + ["cage"]
    fig = plot_mds(Y, names, ["a"] * 6 + ["b"] * 6)
    fig.draw_without_rendering()
    ax = fig.axes[0]
    x0, x1 = ax.get_xlim()
    assert x1 - x0 < 20  # the scale of the blob, not of the point 1000 away
    assert any(t.get_text().startswith("cage \u00d7") for t in ax.texts)
    assert any(t.get_text().startswith("outlier, on the border")
               for t in ax.get_legend().get_texts())


def test_interactive_mds_hover_has_name_class_and_neighbours():
    Y = blob_with_outlier(12)
    names = [f"s{i}" for i in range(11)] + ["cage"]
    labels = ["a"] * 6 + ["b"] * 6
    D = distance_matrix(Y)
    fig = interactive_mds(Y, names, labels, D=D, k=2, title="by cShape-DNA M=16")
    assert fig.layout.title.text == "by cShape-DNA M=16"
    ind, _ = nearest_neighbours(D, 2)
    hover = {}
    names_on_picture = [tr for tr in fig.data if tr.mode == "text"]
    assert len(names_on_picture) == 1 and set(names_on_picture[0].text) == set(names[:-1])
    for tr in fig.data:
        if tr.mode == "text":
            continue
        for name, text in zip(tr.customdata, tr.hovertext or tr.text, strict=True):
            hover[name] = text
    assert sorted(hover) == sorted(names)
    for i, n in enumerate(names):
        assert f"<b>{n}</b>" in hover[n] and f"class: {labels[i]}" in hover[n]
        near = hover[n].split("nearest: ")[1]
        assert [names[j] for j in ind[i]] == [x.split(" (")[0] for x in near.split("<br>")[0]
                                              .split(", ")]
    arrows = [tr for tr in fig.data if tr.marker.symbol == "arrow"]
    assert len(arrows) == 1 and list(arrows[0].customdata) == ["cage"]
    assert "outlier" in hover["cage"]
    assert fig.layout.xaxis.range[1] - fig.layout.xaxis.range[0] < 20


def test_neighbour_strips_return_figures():
    meshes = [shapes.icosphere(2), shapes.torus(16, 8), shapes.cube(4)]
    fig = plot_neighbour_strip(meshes, ["q", "n1", "n2"], [0.5, 1.25], labels=list("abc"),
                               title="nearest to q by F1 N=20 (18 values)")
    assert len(fig.axes) == 3 and fig._suptitle.get_text().startswith("nearest to q by F1")
    assert [ax.get_title().split("\n")[0] for ax in fig.axes] == [
        "query", "1. d = 0.5", "2. d = 1.25"]
    pfig = neighbour_strip_plotly(meshes, ["q", "n1", "n2"], [0.5, 1.25], vertical_axis="y")
    assert len(pfig.data) == 3 and pfig.layout.scene2.camera.up.z == 1
    # y up: the trace's coordinates are the mesh's (z, x, y), drawn upright
    V = shapes.torus(16, 8).vertices
    tr = pfig.data[1]
    np.testing.assert_allclose(np.c_[tr.x, tr.y, tr.z], V[:, [2, 0, 1]], rtol=1e-6)
    assert pfig.layout.height is None  # the page gives it its size
    with pytest.raises(ValueError, match=r"distances has 1 entries but the strip has 2 neighbours"):
        plot_neighbour_strip(meshes, ["q", "n1", "n2"], [0.5])
    # a shape of no class ('', e.g. from a flat folder) shows no [class] line
    fig = plot_neighbour_strip(meshes, ["q", "n1", "n2"], [0.5, 1.25], labels=["", "", "x"])
    assert [ax.get_title().split("\n")[1:] for ax in fig.axes] == [["q"], ["n1"], ["n2", "[x]"]]
    pfig = neighbour_strip_plotly(meshes, ["q", "n1", "n2"], [0.5, 1.25], labels=["", "", "x"])
    titles = [a.text for a in pfig.layout.annotations]
    assert "[" not in titles[0] + titles[1] and titles[2].endswith("<br>[x]")


@pytest.mark.parametrize("n, grid", [(1, (1, 1)), (2, (1, 2)), (4, (2, 2)), (6, (2, 3)),
                                     (11, (3, 4))])
def test_strip_grid_keeps_panels_near_square(n, grid):
    from cshape.plots.overview import strip_grid

    assert strip_grid(n) == grid
    rows, cols = grid
    assert rows * cols >= n > (rows - 1) * cols


def test_overview_png_and_html_name_the_descriptor_and_left_out():
    table = spectra_table(p=10, n_classes=3)
    c = collection_distances(table, SD30)
    fig = plot_overview(c.D, c.names, c.labels, descriptor=c.descriptor, title="t.csv",
                        left_out=[("broken", "two pieces")])
    sup = fig._suptitle.get_text()
    assert "10 shapes in 3 classes, compared by Shape-DNA (30 values)" in sup and "broken" in sup
    page = overview_html(c.D, c.names, c.labels, descriptor=c.descriptor,
                         left_out=[("broken", "two pieces")])
    assert "Shape-DNA (30 values)" in page and "broken: two pieces" in page
    assert page.count("<tr>") == 1 + 3  # header and one row per class
    assert '<script src="http' not in page and "cdn.plot.ly/plotly" not in page


def test_save_figure_is_atomic_and_checks_the_suffix(tmp_path):
    fig = plot_mds(np.random.default_rng(0).normal(size=(5, 2)))
    out = save_figure(fig, tmp_path / "m.png")
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert oct(out.stat().st_mode & 0o777) == oct(0o666 & ~_umask())

    def broken(f, **kw):
        f.write(b"half")
        raise RuntimeError("disk on fire")

    fig.savefig = broken
    with pytest.raises(RuntimeError, match="disk on fire"):
        save_figure(fig, tmp_path / "half.png")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.png"]  # nothing half-written
    with pytest.raises(ValueError, match="a matplotlib figure is written as .png"):
        save_figure(plot_mds(np.zeros((3, 2))), tmp_path / "m.html")


def _umask():
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


# ------------------------------------------------------------------------------ command line
@pytest.fixture(scope="module")
def described(tmp_path_factory):
    """Four small meshes in two classes, described into t.csv (N=20)."""
    root = tmp_path_factory.mktemp("own")
    ico = shapes.icosphere(2)
    write_off(root / "meshes" / "round" / "small.off", ico)
    write_off(root / "meshes" / "round" / "big.off", (2.0 * ico.vertices, ico.faces))
    write_off(root / "meshes" / "ring" / "thin.off", shapes.torus(24, 12, r=0.3))
    write_off(root / "meshes" / "ring" / "fat.off", shapes.torus(24, 12, r=0.45))
    table = root / "t.csv"
    assert main(["describe", str(root / "meshes"), "--out", str(table), "-N", "20",
                 "--no-cache", "-q"]) == 0
    return root


def test_cli_overview_writes_html_and_png(described, tmp_path, capsys):
    html, png = tmp_path / "o.html", tmp_path / "o.png"
    rc = main(["overview", str(described / "t.csv"), "--out", str(html), "--out", str(png),
               "--kind", "truncated-log", "-M", "4"])
    err = capsys.readouterr().err
    assert rc == 0, err
    assert "4 shapes in 2 classes, compared by truncated log spectrum (9 values)" in err
    page = html.read_text()
    assert all(n in page for n in ("small", "big", "thin", "fat"))
    assert png.read_bytes()[:4] == b"\x89PNG"


@pytest.mark.parametrize("args, match", [
    (["--out", "{tmp}/o.txt"], "the file name must end in .html"),
    (["--out", "{tmp}/missing/o.html"], "the folder"),
    (["--out", "{tmp}"], "is a folder"),
    (["--out", "{tmp}/o.html", "--kind", "f1", "-N", "500"], "-N 500 is more than"),
    (["--out", "{tmp}/o.html", "-k", "0"], "-k must be at least 1"),
])
def test_cli_overview_bad_input_one_line_exit_2_no_file(described, tmp_path, capsys, args,
                                                        match):
    rc = main(["overview", str(described / "t.csv")] + [a.format(tmp=tmp_path) for a in args])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and err[0].startswith("cshape overview: error: ")
    assert match in err[0]
    assert list(tmp_path.iterdir()) == []


def test_cli_query_plot_png_and_html(described, tmp_path, capsys):
    for suffix in (".png", ".html"):
        out = tmp_path / f"strip{suffix}"
        rc = main(["query", str(described / "t.csv"), "small", "-k", "2", "--plot", str(out),
                   "--meshes", str(described / "meshes")])
        cap = capsys.readouterr()
        assert rc == 0, cap.err
        assert f"wrote {out}" in cap.err and "nearest to 'small'" in cap.out
        assert out.stat().st_size > 1000
    assert "big" in (tmp_path / "strip.html").read_text()
    # a mesh file as the query: drawn first, under its file name
    out = tmp_path / "file.png"
    rc = main(["query", str(described / "t.csv"), str(described / "meshes" / "ring" / "fat.off"),
               "-k", "1", "--plot", str(out), "--meshes", str(described / "meshes")])
    assert rc == 0, capsys.readouterr().err
    assert out.read_bytes()[:4] == b"\x89PNG"


@pytest.mark.parametrize("extra, match", [
    ([], "pass --meshes"),
    (["--meshes", "{meshes}/ring"], "--meshes holds no mesh named"),
])
def test_cli_query_plot_errors(described, tmp_path, capsys, extra, match):
    out = tmp_path / "s.png"
    rc = main(["query", str(described / "t.csv"), "small", "-k", "2", "--plot", str(out)]
              + [a.format(meshes=described / "meshes") for a in extra])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and match in err[0], err
    assert not out.exists()


@pytest.mark.slow
def test_cli_overview_and_query_plot_as_subprocesses(described, tmp_path):
    def run(*args):
        return subprocess.run([sys.executable, "-m", "cshape", *map(str, args)],
                              capture_output=True, text=True, timeout=600)

    res = run("overview", described / "t.csv", "--out", tmp_path / "o.html")
    assert res.returncode == 0 and (tmp_path / "o.html").is_file(), res.stderr
    res = run("query", described / "t.csv", "fat", "-k", "1", "--plot", tmp_path / "q.png",
              "--meshes", described / "meshes")
    assert res.returncode == 0 and (tmp_path / "q.png").is_file(), res.stderr
    res = run("overview", described / "t.csv", "--out", tmp_path / "o.doc")
    assert res.returncode == 2 and "Traceback" not in res.stderr
    assert len(res.stderr.strip().splitlines()) == 1


def test_the_default_descriptor_follows_the_constant(monkeypatch, described, tmp_path, capsys):
    """Without a descriptor the pictures compare cshape.DEFAULT (at the table's N), and say
    so."""
    saved = DescriptorTable.load(described / "t.csv").descriptor  # saved with the table
    monkeypatch.setattr(recipe, "DEFAULT", Descriptor("shape-dna", M=8))
    assert collection_distances(spectra_table()).descriptor == SD30.replace(M=8)
    table = DescriptorTable.load(described / "t.csv")
    DescriptorTable(table.names, table.lam, table.areas, table.labels).save(tmp_path / "n.csv")
    rc = main(["overview", str(tmp_path / "n.csv"), "--out", str(tmp_path / "o.html")])
    assert rc == 0 and "compared by Shape-DNA (20 values)" in capsys.readouterr().err
    # a table saved before keeps comparing what it compared then
    rc = main(["overview", str(described / "t.csv"), "--out", str(tmp_path / "o.html")])
    assert rc == 0 and f"compared by {saved.label}" in capsys.readouterr().err
    assert saved.kind != "shape-dna"


def test_guess_vertical_axis_by_format():
    from cshape.plots.overview import guess_vertical_axis

    assert [guess_vertical_axis(f) for f in ("a/spot.obj", "b.OBJ.gz", "c.ply", "d.off",
                                             "e.stl", "f.glb")] == ["y", "y", "z", "z", "z", "y"]


# ------------------------------------------------------------------------------ flat folders
def _flat_table(p, seed=0, long_names=False):
    """p shapes of one class (a flat folder), spectra spread in two directions."""
    rng = np.random.default_rng(seed)
    i = np.arange(30)
    lam = np.array([4 * np.pi * np.maximum(i + 3 * rng.random() * np.sin(i / 4 + 6 * rng.random()),
                                           0) for _ in range(p)])
    lam[:, 0] = 0.0
    lam[-1] *= 300.0  # a far one (a coarse control cage): an outlier
    stem = "fish_control_mesh_" if long_names else "m"
    return DescriptorTable([f"{stem}{k}" for k in range(p)], lam, np.ones(p), ["flat"] * p)


def _text_boxes(fig):
    """Display boxes of the figure's visible texts written on its axes (names)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    r = FigureCanvasAgg(fig).get_renderer()
    fig.draw(r)
    return [(t.get_text(), t.get_window_extent(r)) for ax in fig.axes for t in ax.texts
            if t.get_text() and t.get_visible()]


@pytest.mark.parametrize("p, long_names", [(12, True), (64, False)])
def test_overview_of_a_flat_folder_reads(p, long_names):
    """One class: the title counts shapes only, no class table, no class legend; the MDS
    names every shape when few, else the outlier and a sample; every name is whole, inside
    the figure and its axes, over no other name and no point; the matrix names its rows."""
    from cshape.plots.layout import LABEL_WIDTH, MDS_SAMPLE_NAMES

    table = _flat_table(p, long_names=long_names)
    c = collection_distances(table, Descriptor("shape-dna", N=30))
    fig = plot_overview(c.D, c.names, c.labels, descriptor=c.descriptor, title="flat.csv")
    sup = fig._suptitle.get_text()
    assert sup == f"flat.csv: {p} shapes, compared by Shape-DNA (30 values)"
    mds, matrix = fig.axes[0], fig.axes[1]
    assert not any(ax.tables for ax in fig.axes)  # no class table
    boxes = _text_boxes(fig)
    names = [t for t, _ in boxes]
    far = c.names[-1]
    assert any(t.startswith(far + " \u00d7") for t in names)  # the outlier, whole
    inner = [t for t in names if "\u00d7" not in t]
    if p <= 40:
        assert len(inner) >= 2 * (p - 1) // 3  # (a name with no free place is left out)
    else:
        assert 8 <= len(inner) <= MDS_SAMPLE_NAMES
    assert all(t in c.names for t in inner)  # whole names (all shorter than LABEL_WIDTH)
    assert max(len(n) for n in c.names) <= LABEL_WIDTH
    page, panel = fig.bbox, mds.get_window_extent()
    for _, b in boxes:
        assert page.x0 <= b.x0 and b.x1 <= page.x1 and page.y0 <= b.y0 and b.y1 <= page.y1
        assert panel.x0 <= b.x0 and b.x1 <= panel.x1 and panel.y0 <= b.y0 and b.y1 <= panel.y1
    for k, (_, a) in enumerate(boxes):
        for _, b in boxes[k + 1:]:
            assert not a.overlaps(b)
    # no name over a point (its own point is beside it)
    pts = np.vstack([col.get_offsets() for col in mds.collections if len(col.get_offsets())])
    xy = mds.transData.transform(pts)
    for text, b in boxes:
        inside = (xy[:, 0] > b.x0 + 1) & (xy[:, 0] < b.x1 - 1) & (xy[:, 1] > b.y0 + 1) \
            & (xy[:, 1] < b.y1 - 1)
        assert not inside.any(), text
    ticks = [t.get_text() for t in matrix.get_yticklabels()]
    assert ticks == sorted(ticks, key=c.names.index) and len(ticks) == p


def test_overview_html_of_a_flat_folder_has_no_class_table():
    table = _flat_table(12)
    c = collection_distances(table, Descriptor("shape-dna", N=30))
    page = overview_html(c.D, c.names, c.labels, descriptor=c.descriptor, title="flat.csv")
    assert "<h1>flat.csv: 12 shapes</h1>" in page
    assert "<h2>Classes</h2>" not in page and "<th>class</th>" not in page


def test_collection_title_counts_in_english():
    from cshape.plots.overview import collection_title

    assert collection_title(64, 1) == "64 shapes"
    assert collection_title(1, 1) == "1 shape"
    assert collection_title(200, 10) == "200 shapes in 10 classes"
