"""Pictures of a collection: MDS scatter plots (Fig. 4-5) and distance-matrix images
(Fig. 3, 6), with short readable labels, and the pure functions behind them.

* :func:`plot_mds` - the MDS scatter plot: square, one colour and marker per class, names
  where they fit, outliers (:func:`cshape.compare.mds_outliers`) marked at the border
  (:func:`cshape.plots.layout.border_points`) so that the rest is drawn at a scale where it
  separates;
* :func:`plot_distance_matrix`, :func:`matrix_ticks` - the matrix image and its ticks.

Where the points and their names go (short labels, outliers at the border, names that do not
overlap) is :mod:`cshape.plots.layout`'s.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._checks import (
    check_bool,
    check_entries,
    check_flag_or_choice,
    check_int,
    check_labels,
    check_points,
    check_real,
    check_square,
)
from ..compare import scale_255
from .layout import (
    MDS_MAX_NAMES,
    _axes_points,
    _set_square,
    _spread_out,
    annotate_points,
    class_medians,
    mds_layout,
    named_points,
    short_label,
    short_labels,
)

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.colors import Colormap
    from matplotlib.figure import Figure, SubFigure
    from matplotlib.typing import ColorType

# --------------------------------------------------------------------------- plots
#: A distance matrix gets one tick per shape up to this many shapes (in a smaller font when
#: needed, down to :data:`MIN_TICK_POINTS`); beyond, one per class, or every k-th name for
#: one class.
MATRIX_MAX_NAMES = 100
#: The smallest font of a matrix's names, in points.
MIN_TICK_POINTS = 4.5
#: A legend lists up to this many classes in one column; beyond, a figure of its own gets a
#: legend in columns below the panel (up to :data:`LEGEND_COLUMNS` columns).
MAX_LEGEND_CLASSES = 20
#: Most columns of a legend below an MDS panel: up to ``MAX_LEGEND_CLASSES * LEGEND_COLUMNS``
#: classes are listed; beyond, the panel says how many classes there are.
LEGEND_COLUMNS = 4
#: Marker shapes of the classes: classes 0-19 are circles in 20 colours, 20-39 squares, ...
CLASS_MARKERS = "os^Dv<>pP*Xh"


def _figure_and_ax(ax: Axes | None, figsize: tuple[float, float]
                   ) -> tuple[Figure | SubFigure, Axes]:
    if ax is not None:
        return ax.figure, ax
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, layout="constrained")
    return fig, fig.add_subplot()


def _class_colours(labels: Iterable[Any], p: int
                   ) -> tuple[list[ColorType], list[tuple[str, ColorType]]]:
    """(colour of each point, [(class, colour)] in first-seen order)."""
    codes, styles = class_styles(labels, p)
    return [styles[c][1] for c in codes], [(lab, col) for lab, col, _ in styles]


def class_styles(labels: Iterable[Any], p: int | None = None
                 ) -> tuple[NDArray[np.int64], list[tuple[str, ColorType, str]]]:
    """A colour and a marker per class, distinct for up to ``20 * len(CLASS_MARKERS)`` classes.

    Up to 10 classes: ``tab10`` circles; up to 20: ``tab20`` circles; beyond, class ``c``
    gets colour ``c % 20`` of ``tab20`` and marker ``CLASS_MARKERS[c // 20]``.

    Parameters
    ----------
    labels : sequence, length p
    p : int, optional
        Expected length (checked).

    Returns
    -------
    codes : ndarray of int, shape (p,)
        Class number of each point, in first-seen order.
    styles : list of (str, colour, str)
        ``(class label, RGBA colour, marker)`` of each class, in first-seen order.
    """
    import matplotlib as mpl

    lab = list(labels)
    codes = check_labels(lab, len(lab) if p is None else p)
    first: dict[int, int] = {}
    for i, c in enumerate(codes):
        first.setdefault(int(c), i)
    cmap = mpl.colormaps["tab10" if len(first) <= 10 else "tab20"]
    return codes, [(str(lab[i]), cmap(c % cmap.N),
                    CLASS_MARKERS[(c // cmap.N) % len(CLASS_MARKERS)])
                   for c, i in first.items()]


# --------------------------------------------------------------------------- outliers


# --------------------------------------------------------------------------- labels


def plot_mds(Y: ArrayLike, names: Sequence[Any] | None = None,
             labels: Sequence[Any] | None = None, *, ax: Axes | None = None,
             title: str | None = None, figsize: tuple[float, float] = (5.0, 4.5),
             max_names: int = MDS_MAX_NAMES, legend: bool | str = True,
             outliers: str | ArrayLike | None = "auto") -> Figure | SubFigure:
    """Scatter plot of a 2-D MDS embedding, square, coloured by class (Fig. 4-5).

    Readable from 3 to thousands of shapes with any names, and with outliers:

    * the panel is square with equal units on both axes;
    * outliers (:func:`cshape.compare.mds_outliers`: a point whose median distance to the
      others is :data:`cshape.compare.OUTLIER_FACTOR` times the typical one, such as a
      coarse control cage among fine meshes) are drawn as arrow heads on the border, in
      their direction, with their name and how many times farther than typical they lie;
      the other points fill the panel at their own scale, where they separate;
    * points are named (the part after the last ``/``, at most :data:`LABEL_WIDTH`
      characters) up to ``max_names`` shapes, where a name covers no other; beyond, each
      class's name is written at the median of its points;
    * classes get a colour and a marker each (:func:`class_styles`), listed in a legend
      outside the panel: one column up to :data:`MAX_LEGEND_CLASSES` classes, in columns
      below the panel up to ``LEGEND_COLUMNS`` times as many; beyond, the panel states
      the number of classes.

    Parameters
    ----------
    Y : array_like, shape (p, 2)
        From :func:`mds_embedding`.
    names : sequence of str, length p, optional
        Shape names, written beside the points (up to ``max_names`` shapes).
    labels : sequence, length p, optional
        Classes; points of one class share a colour and a marker.
    ax : matplotlib Axes, optional
        Draw here; by default a new Figure is made (not registered with pyplot).
    title : str, optional
        Title of the axes.
    figsize : (float, float), default=(5.0, 4.5)
        Made taller for a legend in columns.
    max_names : int, default=MDS_MAX_NAMES
        Write no shape name when there are more shapes (class names instead).
    legend : bool or 'outside', default=True
        Draw the class legend: outside the panel on a figure of its own or with
        ``'outside'``; inside (where it covers the fewest points, up to
        :data:`MAX_LEGEND_CLASSES` classes) when ``ax`` is given.  A figure of several
        panels reads best with ``legend=False`` and one ``fig.legend``.
    outliers : 'auto', None or array_like of bool, default='auto'
        Which points to draw on the border (see :func:`cshape.plots.layout.mds_layout`);
        None draws every point where it is, at the scale of them all.

    Returns
    -------
    matplotlib.figure.Figure
        The new figure, or the figure (or subfigure) holding ``ax``.
    """
    Y = check_points(Y, d=2, min_points=1, fix="use mds_embedding(D)")
    p = len(Y)
    if names is not None:
        check_entries("names", names, p)
    if labels is not None:
        check_entries("labels", labels, p)
    max_names = check_int("max_names", max_names, min=0)
    legend = check_flag_or_choice("legend", legend, ("outside",))
    lay = mds_layout(Y, outliers)
    own = ax is None
    size = 25.0 if p <= 100 else max(4.0, 2500.0 / p)
    styles: list[tuple[str, ColorType, str]]
    if labels is not None:
        codes, styles = class_styles(labels, p)
    else:
        codes, styles = np.zeros(p, dtype=np.int64), [("", "C0", "o")]
    plan = _mds_legend_plan(len(styles) if labels is not None else 0, labels is not None,
                            legend, own, bool(lay["outliers"].any()))
    if own and plan.listed and plan.columns > 1:  # the legend goes below: a taller figure
        figsize = (max(figsize[0], 1.9 * plan.columns), figsize[1] + 0.21 * plan.rows + 0.5)
    fig, ax = _figure_and_ax(ax, figsize)
    _draw_mds_points(ax, lay, codes, styles, size, labels is not None)
    _set_square(ax, lay["centre"], lay["half"])
    _draw_mds_legend(ax, plan, own=own, outside=own or legend == "outside",
                     markerscale=max(1.0, (25.0 / size) ** 0.5))
    _style_mds_axes(ax, title)
    # texts last (they take the final layout): outliers first, then names or classes
    texts, where = _mds_texts(Y, lay, names, labels, plan.n_classes, max_names)
    if texts:
        # names keep off every point; class names, written over their classes, cannot
        by_class = labels is not None and plan.n_classes > 1 and p > max_names
        annotate_points(ax, np.array(where), texts,
                        points=np.empty((0, 2)) if by_class else lay["P"],
                        required=int(lay["outliers"].sum()))
    return fig


class _MdsLegend(NamedTuple):
    """How :func:`plot_mds` lists the classes: in ``columns`` columns of ``rows`` rows
    (``listed``), or not at all (then, with ``labels``, the panel states their number)."""

    legend: bool | str
    has_labels: bool
    n_classes: int
    columns: int
    rows: int
    listed: bool
    any_outlier: bool


def _mds_legend_plan(n_classes: int, has_labels: bool, legend: bool | str, own: bool,
                     any_outlier: bool) -> _MdsLegend:
    """The legend of :func:`plot_mds`: one column up to :data:`MAX_LEGEND_CLASSES` classes,
    below the panel of a figure of its own in up to :data:`LEGEND_COLUMNS` columns."""
    columns = 1 if n_classes <= MAX_LEGEND_CLASSES else -(-n_classes // MAX_LEGEND_CLASSES)
    listed = bool(legend) and has_labels and columns <= LEGEND_COLUMNS
    rows = 0
    if own and listed and columns > 1:
        columns = min(LEGEND_COLUMNS, max(columns, 2))
        rows = -(-(n_classes + any_outlier) // columns)
    return _MdsLegend(legend, has_labels, n_classes, columns, rows, listed, any_outlier)


def _draw_mds_points(ax: Axes, lay: dict[str, Any], codes: NDArray[np.int64],
                     styles: list[tuple[str, ColorType, str]], size: float,
                     named_classes: bool) -> None:
    """The points of :func:`plot_mds`: inliers class by class, outliers as arrow heads on
    the border (and an empty marker for the legend's outlier entry)."""
    out, P = lay["outliers"], lay["P"]
    for c, (lab, col, marker) in enumerate(styles):
        sel = (codes == c) & ~out
        ax.scatter(P[sel, 0], P[sel, 1], color=col, marker=marker, s=size, linewidths=0,
                   label=short_label(lab) if named_classes else None)
    if not out.any():
        return
    from matplotlib.markers import MarkerStyle
    from matplotlib.transforms import Affine2D

    for i in np.flatnonzero(out):
        m = MarkerStyle(">", transform=Affine2D().rotate_deg(lay["angle"][i]))
        ax.scatter([P[i, 0]], [P[i, 1]], color=styles[codes[i]][1], marker=m,
                   s=max(size, 25.0) * 2.2, edgecolors="black", linewidths=0.6,
                   zorder=3)
    ax.scatter([], [], marker=">", color="white", edgecolors="black", linewidths=0.6,
               label="outlier, on the border (\u00d7k typical distance)")


def _draw_mds_legend(ax: Axes, plan: _MdsLegend, *, own: bool, outside: bool,
                     markerscale: float) -> None:
    """The class legend of :func:`plot_mds` (beside, below or inside the panel), or the
    number of classes when they are too many to list."""
    scale = {"markerscale": markerscale}  # legend markers stay visible
    if plan.listed and outside and (plan.columns == 1 or not own):
        ax.legend(fontsize="small" if plan.columns == 1 else "x-small", loc="upper left",
                  bbox_to_anchor=(1.02, 1.0), ncol=plan.columns, borderaxespad=0.0,
                  frameon=False, **scale)
    elif plan.listed and own:
        ax.legend(fontsize="x-small", loc="upper center", bbox_to_anchor=(0.5, -0.1),
                  ncol=plan.columns, borderaxespad=0.0, frameon=False, columnspacing=1.0,
                  handletextpad=0.3, **scale)
    elif plan.legend and plan.has_labels and plan.n_classes <= MAX_LEGEND_CLASSES:
        ax.legend(fontsize="x-small", loc="best", framealpha=0.7, **scale)  # in a panel
    elif plan.any_outlier and plan.legend:
        ax.legend(handles=ax.get_legend_handles_labels()[0][-1:], fontsize="x-small",
                  loc="best", framealpha=0.7)
    if plan.has_labels and plan.legend and not plan.listed:
        ax.text(0.01, 0.01, f"{plan.n_classes} classes", transform=ax.transAxes,
                fontsize="x-small", color="0.35", ha="left", va="bottom")


def _style_mds_axes(ax: Axes, title: str | None) -> None:
    """Axis names, a few ticks in small print, and the title of an MDS panel."""
    ax.set_xlabel("MDS 1", fontsize="small")
    ax.set_ylabel("MDS 2", fontsize="small")
    ax.locator_params(nbins=4)
    ax.ticklabel_format(style="sci", scilimits=(-3, 3))
    ax.tick_params(labelsize="x-small")
    if title:
        ax.set_title(title, fontsize="medium")


def _mds_texts(Y: NDArray[np.float64], lay: dict[str, Any], names: Sequence[str] | None,
               labels: Sequence[Any] | None, n_classes: int, max_names: int
               ) -> tuple[list[str], list[Any]]:
    """The texts of :func:`plot_mds` and where they go: each outlier's name and ratio,
    then the shape names (up to ``max_names`` shapes) or each class's name at its median."""
    out, P = lay["outliers"], lay["P"]
    p = len(Y)
    texts: list[str] = []
    where: list[Any] = []
    one_class = labels is None or n_classes <= 1
    if names is None:
        order = np.flatnonzero(out)
    elif p <= max_names or one_class:
        order = named_points(P, out, max_names)
    else:  # many shapes of several classes: outliers by name, the classes at their medians
        order = np.flatnonzero(out)
    tags = short_labels(names) if names is not None else [f"#{i}" for i in range(p)]
    for i in order:
        texts.append(f"{tags[i]} \u00d7{lay['ratio'][i]:.0f}" if out[i] else tags[i])
        where.append(P[i])
    if labels is not None and n_classes > 1 and p > max_names:
        for lab, xy in class_medians(Y[~out], [labels[int(i)] for i in np.flatnonzero(~out)]):
            texts.append(short_label(lab))
            where.append(xy)
    return texts, where


def _runs(labels: Sequence[str]) -> list[tuple[int, int, str]]:
    """Contiguous runs of equal labels: [(start, stop, label)]."""
    out: list[list[Any]] = []
    for i, lab in enumerate(labels):
        if out and out[-1][2] == lab:
            out[-1][1] = i + 1
        else:
            out.append([i, i + 1, lab])
    return [(a, b, lab) for a, b, lab in out]


def matrix_ticks(ax: Axes, p: int, names: Sequence[str] | None = None,
                 labels: Sequence[Any] | None = None, *, max_names: int = MATRIX_MAX_NAMES,
                 fontsize: str | float = "x-small", safety: float = 1.5,
                 side_pt: float | None = None) -> float:
    """Set the ticks of a (p, p) matrix image, so that they never write over each other.

    One tick per shape (short names) when there are at most ``max_names`` shapes and their
    labels fit the axes' height (in a font down to :data:`MIN_TICK_POINTS`); else one per
    class, at the middle of each run of a class,
    as many as fit (the axes' size after a layout pass without ticks, ``safety`` times
    smaller for the room the tick labels take), with thin white lines at the class
    boundaries; with one class, every k-th name.

    Parameters
    ----------
    ax : matplotlib Axes
        The axes showing the matrix.
    p : int
        Rows (and columns) of the matrix.
    names : sequence of str, length p, optional
        Shape names (shortened with :func:`short_labels`).
    labels : sequence, length p, optional
        Class of each row.
    max_names : int, default=MATRIX_MAX_NAMES (100)
        Most shapes that get a tick each.
    fontsize : str or float, default='x-small'
        Matplotlib font size of the ticks (made smaller, down to
        :data:`MIN_TICK_POINTS`, to fit).
    safety : float, default=1.5
        Factor by which the room the tick labels take is estimated larger.
    side_pt : float, optional
        The axes' shorter side in points; measured (a layout pass) when not given.  Pass
        the value returned for one panel to give panels of one size the same ticks.

    Returns
    -------
    float
        The side used.
    """
    from matplotlib.font_manager import FontProperties

    ax.set_xticks([])
    ax.set_yticks([])
    if side_pt is None:
        side_pt = min(_axes_points(ax))
    size = FontProperties(size=fontsize).get_size_in_points()
    n_fit = max(1, int(side_pt / safety / (1.2 * size)))
    runs = _runs([str(x) for x in labels]) if labels is not None and len(labels) == p else []
    # a name per row, in a smaller font if that fits (names take less room than classes)
    small = min(size, side_pt / 1.3 / (1.2 * p))
    if names is not None and len(names) == p and p <= max_names and small >= MIN_TICK_POINTS:
        where, text, fontsize = list(range(p)), short_labels(names), small
    elif len(runs) > 1:
        mids = np.array([[(a + b - 1) / 2, 0.0] for a, b, _ in runs])
        keep = _spread_out(mids, p / n_fit)
        where, text = [mids[k, 0] for k in keep], [short_label(runs[k][2]) for k in keep]
    elif names is not None and len(names) == p:  # one class: every k-th name
        step = -(-p // max(1, int(side_pt / 1.3 / (1.2 * MIN_TICK_POINTS))))
        where = list(range(0, p, step))
        text, fontsize = [short_labels(names)[i] for i in where], MIN_TICK_POINTS
    else:
        return side_pt
    ax.set_xticks(where, text, rotation=90, fontsize=fontsize)
    ax.set_yticks(where, text, fontsize=fontsize)
    if 1 < len(runs) <= 100:  # beyond, the lines would hide the matrix
        for a, _, _ in runs[1:]:
            ax.axhline(a - 0.5, color="white", lw=0.6)
            ax.axvline(a - 0.5, color="white", lw=0.6)
    return side_pt


def plot_distance_matrix(D: ArrayLike, *, scale: bool = True, ax: Axes | None = None,
                         title: str | None = None, names: Sequence[str] | None = None,
                         labels: Sequence[Any] | None = None, cmap: str | Colormap = "jet",
                         vmax: float | None = None, colorbar: bool = True,
                         figsize: tuple[float, float] = (5.0, 4.5)) -> Figure | SubFigure:
    """Image of a distance matrix, as in Fig. 3 and 6 (blue: similar, red: dissimilar).

    Parameters
    ----------
    D : array_like, shape (p, p)
        Distances, or a difference matrix from :func:`difference_matrix` (then pass
        ``scale=False``).
    scale : bool, default=True
        Show :func:`scale_255` of ``D`` on a fixed ``[0, 255]`` colour range.
    ax : matplotlib Axes, optional
        Draw here; by default a new Figure is made (not registered with pyplot).
    title : str, optional
        Title of the axes.
    names : sequence of str, optional
        Tick labels, one per shape (shortened), drawn for at most
        :data:`MATRIX_MAX_NAMES` shapes.
    labels : sequence, optional
        Classes of the rows: beyond :data:`MATRIX_MAX_NAMES` shapes (or without
        ``names``) one tick per class, and lines between classes (see
        :func:`matrix_ticks`).
    cmap : str, default='jet'
        The paper's colours.
    vmax : float, optional
        Top of the colour range; default 255 when scaled, else ``D.max()``.
    colorbar : bool, default=True
        Draw a colour bar.
    figsize : (float, float), default=(5.0, 4.5)
        Size of a new figure, in inches.

    Returns
    -------
    matplotlib.figure.Figure
        The new figure, or the figure (or subfigure) holding ``ax``.
    """
    A = check_square(D, "D")
    scale, colorbar = check_bool("scale", scale), check_bool("colorbar", colorbar)
    for arg, value in (("names", names), ("labels", labels)):
        if value is not None:
            check_entries(arg, value, len(A), of="D", unit="rows")
    img = scale_255(A) if scale else A
    if vmax is None:
        vmax = 255.0 if scale else (float(img.max()) or 1.0)
    vmax = check_real("vmax", vmax, positive=True)
    fig, ax = _figure_and_ax(ax, figsize)
    im = ax.imshow(img, cmap=cmap, vmin=0.0, vmax=vmax, interpolation="nearest")
    matrix_ticks(ax, len(A), names, labels)
    if colorbar:
        fig.colorbar(im, ax=ax, shrink=0.8)
    if title:
        ax.set_title(title, fontsize="medium")
    return fig
