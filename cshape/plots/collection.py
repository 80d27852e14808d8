"""Pictures of a collection: MDS scatter plots (Fig. 4-5) and distance-matrix images
(Fig. 3, 6), with short readable labels.
"""

from __future__ import annotations

import numpy as np

from .._checks import check_labels, check_square
from ..compare import scale_255

# --------------------------------------------------------------------------- plots
#: An MDS plot names its points up to this many shapes; beyond, only the class legend.
MDS_MAX_NAMES = 40
#: A distance matrix gets one tick per shape up to this many shapes; beyond, one per class.
MATRIX_MAX_NAMES = 40
#: A legend lists up to this many classes; beyond, colours repeat and no legend is drawn.
MAX_LEGEND_CLASSES = 20
#: Longest point or tick label, in characters; longer names are cut in the middle.
LABEL_WIDTH = 16


def short_label(name, width=LABEL_WIDTH) -> str:
    """A name short enough for a plot: the part after the last ``/``, cut in the middle.

    >>> short_label("animals/spot_low_resolution", 12)
    'spot_…lution'
    """
    text = str(name).replace("\\", "/").rstrip("/")
    return _cut_middle(text.rsplit("/", 1)[-1] or str(name), width)


def _cut_middle(text, width):
    """``text`` cut to ``width`` characters in the middle (an ellipsis marks the cut)."""
    if len(text) <= width:
        return text
    head = (width - 1) // 2
    return text[:head] + "\u2026" + text[len(text) - (width - 1 - head):]


def short_labels(names, width=LABEL_WIDTH) -> list:
    """:func:`short_label` of every name, kept distinct where the names are.

    Names whose short labels would coincide (``a/spot`` and ``b/spot`` both give ``spot``)
    keep their parent folder (``a/spot``, ``b/spot``), cut in the middle to ``width``; if
    they still coincide, each gets its position in ``names`` as a suffix (``spot#3``).

    >>> short_labels(["a/spot", "b/spot", "c/bob"])
    ['a/spot', 'b/spot', 'bob']
    """
    names = [str(n) for n in names]
    out = [short_label(n, width) for n in names]

    def clashes(labels):
        seen = {}
        for i, (lab, name) in enumerate(zip(labels, names, strict=True)):
            seen.setdefault(lab, {}).setdefault(name, []).append(i)
        return [i for group in seen.values() if len(group) > 1
                for idx in group.values() for i in idx]

    for i in clashes(out):
        parts = names[i].replace("\\", "/").rstrip("/").split("/")
        out[i] = _cut_middle("/".join(parts[-2:]), width)
    for i in clashes(out):
        suffix = f"#{i}"
        out[i] = _cut_middle(out[i], max(width - len(suffix), 2)) + suffix
    return out


def _figure_and_ax(ax, figsize):
    if ax is not None:
        return ax.figure, ax
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, layout="constrained")
    return fig, fig.add_subplot()


def _class_colours(labels, p):
    """(colour of each point, [(class, colour)] in first-seen order)."""
    import matplotlib as mpl

    codes = check_labels(labels, p)
    first = {}
    for i, c in enumerate(codes):
        first.setdefault(c, i)
    cmap = mpl.colormaps["tab10" if len(first) <= 10 else "tab20"]
    lab = list(labels)
    return ([cmap(c % cmap.N) for c in codes],
            [(str(lab[i]), cmap(c % cmap.N)) for c, i in first.items()])


def _square_limits(ax, Y, margin=0.08):
    """Equal x and y ranges around the points and a square box: the panel stays square
    and one unit is as long on both axes, whatever the spread of the embedding."""
    lo, hi = Y.min(axis=0), Y.max(axis=0)
    centre = (lo + hi) / 2
    half = max(float((hi - lo).max()) / 2, 1e-12 * max(1.0, float(np.abs(Y).max())))
    half *= 1 + 2 * margin
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_aspect("equal", adjustable="box")
    return 2 * half


def _side_points(ax) -> float:
    """The shorter side of ``ax`` in points (after a layout pass, if the figure has a
    layout engine; a fixed layout, as the M-sweep widget's, needs none)."""
    fig = ax.figure
    if fig.get_layout_engine() is not None:
        fig.draw_without_rendering()  # the axes get their final size
    box = ax.get_window_extent()
    return 72.0 * min(box.width, box.height) / fig.dpi


def annotate_points(ax, Y, texts, *, fontsize="x-small", offset=3.0, safety=1.15):
    """Write ``texts[i]`` beside point ``Y[i]`` where it covers no text already written.

    Greedy, in order: a text's box is estimated from its length, the font size and the
    axes' size after a layout pass (``safety`` times larger), and skipped when it would
    overlap a box kept before.  The texts take no part in the layout, so call this last,
    after the axis limits, legends and colour bars are set.

    Returns
    -------
    list of int
        The indices of the points that got their text.
    """
    from matplotlib.font_manager import FontProperties

    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    per_pt = max(x1 - x0, y1 - y0) / max(_side_points(ax), 1.0) * safety
    size = FontProperties(size=fontsize).get_size_in_points()
    boxes, kept = [], []
    for i, text in enumerate(texts):
        w, h = 0.62 * size * len(text) * per_pt, 1.25 * size * per_pt
        d = offset * per_pt
        # right of and above the point, or left / below where the axes end
        right = Y[i, 0] + d + w <= max(x0, x1)
        up = Y[i, 1] + d + h <= max(y0, y1)
        bx = Y[i, 0] + d if right else Y[i, 0] - d - w
        by = Y[i, 1] + d if up else Y[i, 1] - d - h
        box = (bx, by, bx + w, by + h)
        if any(box[0] < b[2] and b[0] < box[2] and box[1] < b[3] and b[1] < box[3]
               for b in boxes):
            continue
        boxes.append(box)
        kept.append(i)
        t = ax.annotate(text, tuple(Y[i]), xytext=(offset if right else -offset,
                                                   offset if up else -offset),
                        textcoords="offset points", fontsize=fontsize,
                        ha="left" if right else "right", va="bottom" if up else "top",
                        annotation_clip=True)
        t.set_in_layout(False)
        t.set_clip_on(True)
    return kept


def _spread_out(points, min_gap):
    """Indices of points kept so that no two are closer than ``min_gap`` (greedy, in
    order): the points whose labels can be written without writing over each other."""
    kept = []
    for i, x in enumerate(points):
        if all(np.linalg.norm(x - points[j]) >= min_gap for j in kept):
            kept.append(i)
    return kept


def plot_mds(Y, names=None, labels=None, *, ax=None, title=None, figsize=(5.0, 4.5),
             max_names=MDS_MAX_NAMES, legend=True):
    """Scatter plot of a 2-D MDS embedding, square, coloured by class (Fig. 4-5).

    Readable from 3 to thousands of shapes with any names: the panel is square with equal
    units on both axes; points are named (the part after the last ``/``, at most
    :data:`LABEL_WIDTH` characters) only up to ``max_names`` shapes, and only where a name
    does not cover another; classes are told apart by colour, listed in a legend outside
    the panel up to :data:`MAX_LEGEND_CLASSES` classes.

    Parameters
    ----------
    Y : array_like, shape (p, 2)
        From :func:`mds_embedding`.
    names : sequence of str, length p, optional
        Shape names, written beside the points (up to ``max_names`` shapes).
    labels : sequence, length p, optional
        Classes; points of one class share a colour.
    ax : matplotlib Axes, optional
        Draw here; by default a new Figure is made (not registered with pyplot).
    title : str, optional
    figsize : (float, float), default=(5.0, 4.5)
    max_names : int, default=MDS_MAX_NAMES
        Write no name when there are more shapes.
    legend : bool, default=True
        Draw the class legend: outside the panel, on the right, on a figure of its own;
        inside (where it covers the fewest points) when ``ax`` is given.  A figure of
        several panels reads best with ``legend=False`` and one ``fig.legend``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    Y = np.asarray(Y, dtype=np.float64)
    if Y.ndim != 2 or Y.shape[1] != 2:
        raise ValueError(f"Y must have shape (p, 2), got {Y.shape}; use mds_embedding(D)")
    p = len(Y)
    if names is not None and len(names) != p:
        raise ValueError(f"names has {len(names)} entries but Y has {p} points")
    own = ax is None
    fig, ax = _figure_and_ax(ax, figsize)
    size = 25.0 if p <= 100 else max(4.0, 2500.0 / p)
    if labels is not None:
        colours, classes = _class_colours(labels, p)
        ax.scatter(Y[:, 0], Y[:, 1], c=colours, s=size, linewidths=0)
        for lab, col in classes:
            ax.scatter([], [], color=col, label=short_label(lab))
        if legend and len(classes) <= MAX_LEGEND_CLASSES and own:
            ax.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.02, 1.0),
                      borderaxespad=0.0, frameon=False)
        elif legend and len(classes) <= MAX_LEGEND_CLASSES:  # a panel of a larger figure
            ax.legend(fontsize="x-small", loc="best", framealpha=0.7)
    else:
        ax.scatter(Y[:, 0], Y[:, 1], s=size, linewidths=0)
    _square_limits(ax, Y)
    if names is not None and p <= max_names:
        annotate_points(ax, Y, short_labels(names))
    ax.set_xlabel("MDS 1", fontsize="small")
    ax.set_ylabel("MDS 2", fontsize="small")
    ax.locator_params(nbins=4)
    ax.ticklabel_format(style="sci", scilimits=(-3, 3))
    ax.tick_params(labelsize="x-small")
    if title:
        ax.set_title(title, fontsize="medium")
    return fig


def _runs(labels):
    """Contiguous runs of equal labels: [(start, stop, label)]."""
    out = []
    for i, lab in enumerate(labels):
        if out and out[-1][2] == lab:
            out[-1][1] = i + 1
        else:
            out.append([i, i + 1, lab])
    return [tuple(r) for r in out]


def matrix_ticks(ax, p, names=None, labels=None, *, max_names=MATRIX_MAX_NAMES,
                 fontsize="x-small", safety=1.5, side_pt=None):
    """Ticks of a (p, p) matrix image that never write over each other.

    One tick per shape (short names) when there are at most ``max_names`` shapes and their
    labels fit the axes' height; else one per class, at the middle of each run of a class,
    as many as fit (the axes' size after a layout pass without ticks, ``safety`` times
    smaller for the room the tick labels take), with thin white lines at the class
    boundaries.

    Parameters
    ----------
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
        side_pt = _side_points(ax)
    size = FontProperties(size=fontsize).get_size_in_points()
    n_fit = max(1, int(side_pt / safety / (1.2 * size)))
    runs = _runs([str(x) for x in labels]) if labels is not None and len(labels) == p else []
    if names is not None and len(names) == p and p <= min(max_names, n_fit):
        where, text = list(range(p)), short_labels(names)
    elif len(runs) > 1:
        mids = np.array([[(a + b - 1) / 2, 0.0] for a, b, _ in runs])
        keep = _spread_out(mids, p / n_fit)
        where, text = [mids[k, 0] for k in keep], [short_label(runs[k][2]) for k in keep]
    else:
        return side_pt
    ax.set_xticks(where, text, rotation=90, fontsize=fontsize)
    ax.set_yticks(where, text, fontsize=fontsize)
    if 1 < len(runs) <= 100:  # beyond, the lines would hide the matrix
        for a, _, _ in runs[1:]:
            ax.axhline(a - 0.5, color="white", lw=0.6)
            ax.axvline(a - 0.5, color="white", lw=0.6)
    return side_pt


def plot_distance_matrix(D, *, scale=True, ax=None, title=None, names=None, labels=None,
                         cmap="jet", vmax=None, colorbar=True, figsize=(5.0, 4.5)):
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
    figsize : (float, float), default=(5.0, 4.5)

    Returns
    -------
    matplotlib.figure.Figure
    """
    A = check_square(D, "D")
    img = scale_255(A) if scale else A
    if vmax is None:
        vmax = 255.0 if scale else (float(img.max()) or 1.0)
    fig, ax = _figure_and_ax(ax, figsize)
    im = ax.imshow(img, cmap=cmap, vmin=0.0, vmax=vmax, interpolation="nearest")
    matrix_ticks(ax, len(A), names, labels)
    if colorbar:
        fig.colorbar(im, ax=ax, shrink=0.8)
    if title:
        ax.set_title(title, fontsize="medium")
    return fig
