"""The figures of the ``cshape reproduce`` report.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..compare import mds_embedding
from ..plots.collection import MAX_LEGEND_CLASSES, plot_mds
from ..plots.layout import MDS_MAX_NAMES, annotate_points, short_labels
from .experiments import FIG1_MAX_SHAPES

if TYPE_CHECKING:
    from collections.abc import Sequence

    from matplotlib.figure import Figure

    from ..batch import DescriptorTable
    from ..descriptors import Descriptor


# --------------------------------------------------------------------------- figures
def _grid(n: int, size: float = 3.2, cols: int = 3) -> tuple[Figure, np.ndarray]:
    from matplotlib.figure import Figure

    rows = (n + cols - 1) // cols
    fig = Figure(figsize=(size * cols, size * rows), layout="constrained")
    axs = np.atleast_1d(fig.subplots(rows, cols)).ravel()
    for ax in axs[n:]:
        ax.set_visible(False)
    return fig, axs


def _drop_overlapping_texts(fig: Figure) -> int:
    """Draw ``fig`` once and remove each annotation that overlaps one kept before it in
    its axes, by their drawn extents.

    :func:`cshape.plots.layout.annotate_points` places texts from estimated sizes after a layout
    pass; if the final layout still moves the axes (seen once in a long test run: two
    names of an MDS panel overlapping), this keeps the promise that names cover no other
    name.  The texts take no part in the layout, so a later draw keeps their places.

    Returns
    -------
    int
        The number of texts removed.
    """
    fig.draw_without_rendering()
    removed = 0
    for ax in fig.axes:
        kept: list[Any] = []
        for t in list(ax.texts):
            if not (t.get_visible() and t.get_text()):
                continue
            box = t.get_window_extent()
            if any(box.overlaps(b) for b in kept):
                t.remove()
                removed += 1
            else:
                kept.append(box)
    return removed


def _mds_figure(table: DescriptorTable,
                panels: Sequence[tuple[str, Descriptor]], random_state: int | None
                ) -> Figure:
    """MDS panels (Fig. 4-5): square, names up to MDS_MAX_NAMES shapes, one class legend."""
    fig, axs = _grid(len(panels))
    Ys = []
    for ax, (title, d) in zip(axs, panels, strict=False):
        Ys.append(mds_embedding(table.distance_matrix(d), random_state=random_state))
        plot_mds(Ys[-1], labels=table.labels, ax=ax, title=title, legend=False)
    handles, labels = axs[0].get_legend_handles_labels()
    if handles and len(handles) <= MAX_LEGEND_CLASSES:
        fig.legend(handles, labels, loc="outside right upper", fontsize="small", frameon=False)
    elif handles:
        fig.suptitle(f"{len(handles)} classes (colours repeat)", fontsize="small")
    if len(table) <= MDS_MAX_NAMES:  # names last: they are placed in the final layout
        short = short_labels(table.names)
        for k, (ax, Y) in enumerate(zip(axs, Ys, strict=False)):
            annotate_points(ax, Y, short, layout=k == 0)  # one layout pass for the figure
        _drop_overlapping_texts(fig)  # in the final layout, by the drawn extents
    return fig


def fig1_selection(table: DescriptorTable, max_shapes: int = FIG1_MAX_SHAPES
                   ) -> tuple[list[str], str]:
    """The shapes of Fig. 1, and a sentence for the report when they are a sample.

    One shape per class, the first of each class in the table; with more than
    ``max_shapes`` classes, the classes are taken evenly spread over their order.  Without
    class labels (or one class), the first ``max_shapes`` shapes.

    Parameters
    ----------
    table : DescriptorTable
        The collection.
    max_shapes : int, default=8
        Most shapes drawn.

    Returns
    -------
    names : list of str
        The shapes drawn.
    note : str
        Empty when every shape is drawn.
    """
    p = len(table)
    classes = list(dict.fromkeys(table.labels))
    if all(table.labels) and len(classes) > 1:
        rows = [table.labels.index(c) for c in classes]
        if len(rows) > max_shapes:
            pick = np.unique(np.linspace(0, len(rows) - 1, max_shapes).round().astype(int))
            rows = [rows[k] for k in pick]
        how = (f"one shape of each of the {len(classes)} classes" if len(rows) == len(classes)
               else f"one shape of each of {len(rows)} of the {len(classes)} classes (evenly "
               "spread over the classes)")
    else:
        rows = list(range(min(max_shapes, p)))
        how = f"the first {len(rows)} shapes"
    names = [table.names[i] for i in rows]
    note = "" if len(rows) == p else (
        f"Fig. 1 samples: it shows {how}, {len(rows)} of the {p} shapes ("
        + ", ".join(names) + ").")
    return names, note


def _noise_change_figure(noise: dict[float, dict[str, Any]], levels: Sequence[float]
                         ) -> Figure:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10, 3.6), layout="constrained")
    axs = fig.subplots(1, 2)
    for ax, kind, title in ((axs[0], "shape-dna", "(a) Shape-DNA"),
                            (axs[1], "cshape", "(b) cShape-DNA")):
        top = max(float(noise[lv]["change_" + kind].max()) for lv in levels) or 1.0
        for lv in levels:
            ax.plot(noise[lv]["change_" + kind] / top, ".-", ms=3, lw=0.8,
                    label=f"amplitude={lv:g}")
        ax.set(xlabel="model", ylabel="||noisy - clean|| / max", title=title)
        ax.legend(fontsize="small")
    return fig
