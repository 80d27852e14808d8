"""Figures that hold on any collection: square panels, bounded and non-overlapping labels,
class legends and ticks, from 3 to 1000 shapes with long names (no eigensolve: synthetic
spectra)."""

from __future__ import annotations

import numpy as np
import pytest

from cshape import Descriptor, plots
from cshape.batch import DescriptorTable
from cshape.plots.collection import (
    LEGEND_COLUMNS,
    MAX_LEGEND_CLASSES,
    plot_distance_matrix,
    plot_mds,
)
from cshape.plots.layout import LABEL_WIDTH, MDS_MAX_NAMES, short_label, short_labels
from cshape.reproduce.figures import _mds_figure, fig1_selection


def synthetic_table(p, n_classes, N=30, seed=0):
    """p shapes in n_classes contiguous classes with long names; Weyl-like spectra."""
    rng = np.random.default_rng(seed)
    labels = [f"class_with_a_rather_long_name_{k % n_classes:03d}" for k in range(p)]
    labels.sort()
    names = [f"animals/{lab}/specimen_low_resolution_{i:04d}" for i, lab in enumerate(labels)]
    base = {lab: 1 + 0.3 * rng.random(N) for lab in set(labels)}
    i = np.arange(N)
    lam = np.array([4 * np.pi * i * np.sort(base[lab] * (1 + 0.01 * rng.random(N)))
                    for lab in labels])
    return DescriptorTable(names, lam, np.ones(p), labels)


def drawn(fig):
    fig.draw_without_rendering()
    return fig


def assert_square(ax, tol=0.02):
    box = ax.get_window_extent()
    assert box.width == pytest.approx(box.height, rel=tol), (box.width, box.height)
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    assert abs(x1 - x0) == pytest.approx(abs(y1 - y0), rel=1e-9)  # one unit, both axes


def assert_no_overlap(artists):
    boxes = [a.get_window_extent() for a in artists if a.get_visible() and a.get_text()]
    for k, a in enumerate(boxes):
        for b in boxes[k + 1:]:
            assert not a.overlaps(b), (a, b)


def test_short_labels_keep_different_names_apart():
    assert short_labels(["a/spot", "b/spot", "c/bob"]) == ["a/spot", "b/spot", "bob"]
    assert short_labels(["a\\cow", "b\\cow"]) == ["a/cow", "b/cow"]  # Windows separators
    # the parent folders cut to the width, still distinct
    assert short_labels(["m/long_folder_name_a/cow", "m/long_folder_name_b/cow"], 12) == [
        "long_\u2026_a/cow", "long_\u2026_b/cow"]
    # same parent and name once cut: the position tells them apart, within the width
    names = [f"{d}/animals/spot_low_resolution_version_one" for d in "xy"]
    labels = short_labels(names, 16)
    assert labels == ["animal\u2026ion_one#0", "animal\u2026ion_one#1"]
    assert all(len(lab) <= 16 for lab in labels)
    # equal names label equally; distinct short names are left as short_label makes them
    assert short_labels(["spot", "spot", "x/bob"]) == ["spot", "spot", "bob"]
    assert short_labels([]) == []


def test_short_label():
    assert short_label("animals/spot_low_resolution", 12) == "spot_\u2026lution"
    assert short_label("spot") == "spot"
    assert len(short_label("x" * 200)) == LABEL_WIDTH


@pytest.mark.parametrize("p, n_classes", [(3, 3), (12, 3), (40, 8), (1000, 40), (1000, 300)])
def test_mds_panel_square_bounded_labels(p, n_classes):
    table = synthetic_table(p, n_classes)
    Y = np.random.default_rng(1).normal(size=(p, 2)) * [10.0, 0.1]  # a thin cloud
    fig = drawn(plot_mds(Y, names=table.names, labels=table.labels, title="MDS"))
    ax = fig.axes[0]
    assert_square(ax)
    count = f"{n_classes} classes"
    texts = [t for t in ax.texts if t.get_text() != count]
    assert_no_overlap(texts)
    if p > MDS_MAX_NAMES:  # no shape names: class names at their classes
        assert texts and len(texts) <= n_classes
        assert {t.get_text() for t in texts} <= {short_label(x) for x in table.labels}
    else:
        assert texts and len(texts) <= p and all(len(t.get_text()) <= LABEL_WIDTH for t in texts)
        assert {t.get_text() for t in texts} <= set(short_labels(table.names))
    legend = ax.get_legend()
    if n_classes <= MAX_LEGEND_CLASSES * LEGEND_COLUMNS:
        assert len(legend.get_texts()) == n_classes
        assert legend._ncols == (1 if n_classes <= MAX_LEGEND_CLASSES else 2)
        box, page = legend.get_window_extent(), fig.bbox
        assert page.x0 <= box.x0 and box.x1 <= page.x1 + 1  # within the figure
        assert page.y0 <= box.y0 and box.y1 <= page.y1 + 1
    else:  # too many to list: the panel says how many
        assert legend is None
        assert [t.get_text() for t in ax.texts].count(count) == 1


def test_overlapping_names_are_dropped_by_their_drawn_extents():
    from matplotlib.figure import Figure

    from cshape.reproduce.figures import _drop_overlapping_texts

    fig = Figure(figsize=(3, 3), layout="constrained")
    ax = fig.subplots()
    ax.set(xlim=(0, 1), ylim=(0, 1))
    for x, y, text in ((0.2, 0.5, "first_name"), (0.21, 0.51, "second_name"),
                       (0.2, 0.1, "far_away"), (0.7, 0.9, "")):
        ax.annotate(text, (x, y), fontsize="small")
    assert _drop_overlapping_texts(fig) == 1
    assert [t.get_text() for t in ax.texts] == ["first_name", "far_away", ""]
    assert_no_overlap(drawn(fig).axes[0].texts)


@pytest.mark.slow
@pytest.mark.parametrize("p, n_classes", [(3, 3), (60, 6)])
def test_report_mds_figure_panels_square_with_one_legend(p, n_classes):
    table = synthetic_table(p, n_classes)
    panels = [(f"cShape-DNA M={m}", Descriptor("cshape", N=30, M=m)) for m in (4, 2, 1)]
    panels += [("Shape-DNA", Descriptor("shape-dna", N=30)), ("F1", Descriptor("f1", N=30))]
    fig = drawn(_mds_figure(table, panels, random_state=0))
    shown = [ax for ax in fig.axes if ax.get_visible()]
    assert len(shown) == 5
    for ax in shown:
        assert_square(ax)
        assert_no_overlap(ax.texts)
        assert ax.get_legend() is None
    assert len(fig.legends) == 1 and len(fig.legends[0].get_texts()) == n_classes


@pytest.mark.slow
@pytest.mark.parametrize("p, n_classes", [(3, 3), (30, 3), (1000, 300)])
def test_matrix_figures_square_with_class_ticks(p, n_classes):
    table = synthetic_table(p, n_classes)
    D = table.distance_matrix(Descriptor("cshape", N=30, M=4))
    fig = drawn(plots.plot_matrices([D, D], ["a", "b"], scale=True, names=table.names,
                                    labels=table.labels))
    for ax in fig.axes[:2]:
        assert_square(ax)
        ticks = [t for t in ax.get_yticklabels() if t.get_text()]
        assert ticks
        assert_no_overlap(ticks)
        assert_no_overlap([t for t in ax.get_xticklabels() if t.get_text()])
        if p > 40:  # one tick per class (not per shape), and only class names
            assert len(ticks) <= n_classes
            assert {t.get_text() for t in ticks} <= {short_label(x) for x in table.labels}
    if p == 30:  # 3 classes of 10: a tick in the middle of each class
        ax = drawn(plot_distance_matrix(D, labels=table.labels)).axes[0]
        assert list(ax.get_yticks()) == [4.5, 14.5, 24.5]


def test_fig1_one_shape_per_class_and_says_when_it_samples():
    table = synthetic_table(6, 3)
    names, note = fig1_selection(table)
    assert [table.labels[table.index(n)] for n in names] == sorted(set(table.labels))
    assert "one shape of each of the 3 classes, 3 of the 6 shapes" in note
    many = synthetic_table(40, 20)
    names, note = fig1_selection(many, max_shapes=8)
    assert len({many.labels[many.index(n)] for n in names}) == len(names) == 8
    assert "8 of the 20 classes" in note
    few = DescriptorTable(["a", "b", "c"], np.ones((3, 5)), np.ones(3))
    assert fig1_selection(few) == (["a", "b", "c"], "")
