"""Where the points and names of a collection picture go: short labels, outliers at the
border, labels that do not overlap.

The pure layout behind :mod:`cshape.plots.collection`'s pictures (and the overview's):

* :func:`short_label`, :func:`short_labels` - names cut in the middle to a readable width;
* :func:`mds_layout`, :func:`border_points`, :func:`spread_on_border` - the square frame of
  an MDS picture, with outliers (:func:`cshape.compare.mds_outliers`) drawn at its border so
  that the rest is drawn at a scale where it separates;
* :func:`named_points`, :func:`annotate_points` - which points get a name, and where the
  names go without overlapping.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._checks import (
    check_choice,
    check_entries,
    check_labels,
    check_points,
    check_real,
)
from ..compare import mds_outliers, median_distances

if TYPE_CHECKING:
    from matplotlib.axes import Axes

#: An MDS plot names its points up to this many shapes; beyond, only the class legend.
MDS_MAX_NAMES = 40

#: Longest point or tick label, in characters; longer names are cut in the middle.
LABEL_WIDTH = 20

#: Beyond :data:`MDS_MAX_NAMES` shapes, an MDS picture of one class names this many, spread
#: over the picture (:func:`named_points`), besides the outliers.
MDS_SAMPLE_NAMES = 16

#: Room kept between two point labels, in points, so that a layout that moves the axes by
#: a fraction of a pixel cannot make them touch.
GAP_POINTS = 1.5

def short_label(name: object, width: int = LABEL_WIDTH) -> str:
    """Shorten a name for a plot: the part after the last ``/``, cut in the middle.

    Parameters
    ----------
    name : object
        A shape's name (a path-like name is cut after its last ``/``).
    width : int, default=LABEL_WIDTH (20)
        Most characters of the label.

    Returns
    -------
    str
        The label; an ellipsis marks a cut.

    Examples
    --------
    >>> short_label("animals/spot_low_resolution", 12)
    'spot_…lution'
    """
    text = str(name).replace("\\", "/").rstrip("/")
    return _cut_middle(text.rsplit("/", 1)[-1] or str(name), width)

def _cut_middle(text: str, width: int) -> str:
    """``text`` cut to ``width`` characters in the middle (an ellipsis marks the cut)."""
    if len(text) <= width:
        return text
    head = (width - 1) // 2
    return text[:head] + "\u2026" + text[len(text) - (width - 1 - head):]

def short_labels(names: Iterable[object], width: int = LABEL_WIDTH) -> list[str]:
    """Shorten every name with :func:`short_label`, keeping distinct names distinct.

    Names whose short labels would coincide (``a/spot`` and ``b/spot`` both give ``spot``)
    keep their parent folder (``a/spot``, ``b/spot``), cut in the middle to ``width``; if
    they still coincide, each gets its position in ``names`` as a suffix (``spot#3``).

    Parameters
    ----------
    names : iterable of object
        The shapes' names.
    width : int, default=LABEL_WIDTH (20)
        Most characters of a label.

    Returns
    -------
    list of str
        One label per name, in order.

    Examples
    --------
    >>> short_labels(["a/spot", "b/spot", "c/bob"])
    ['a/spot', 'b/spot', 'bob']
    """
    full = [str(n) for n in names]
    out = [short_label(n, width) for n in full]

    def clashes(labels: list[str]) -> list[int]:
        seen: dict[str, dict[str, list[int]]] = {}
        for i, (lab, name) in enumerate(zip(labels, full, strict=True)):
            seen.setdefault(lab, {}).setdefault(name, []).append(i)
        return [i for group in seen.values() if len(group) > 1
                for idx in group.values() for i in idx]

    for i in clashes(out):
        parts = full[i].replace("\\", "/").rstrip("/").split("/")
        out[i] = _cut_middle("/".join(parts[-2:]), width)
    for i in clashes(out):
        suffix = f"#{i}"
        out[i] = _cut_middle(out[i], max(width - len(suffix), 2)) + suffix
    return out

def square_limits(Y: ArrayLike, margin: float = 0.08) -> tuple[NDArray[np.float64], float]:
    """The square drawn around points: ``(centre, half)``, the box being
    ``centre +- half`` on both axes.

    ``half`` is half the larger extent of the points, times ``1 + 2 * margin`` (never 0).

    >>> square_limits(np.array([[0.0, 0.0], [4.0, 2.0]]), margin=0.0)
    (array([2., 1.]), 2.0)
    """
    Y = check_points(Y, min_points=1)
    margin = check_real("margin", margin, min=0)
    lo, hi = Y.min(axis=0), Y.max(axis=0)
    centre = (lo + hi) / 2
    half = max(float((hi - lo).max()) / 2, 1e-12 * max(1.0, float(np.abs(Y).max())))
    return centre, half * (1 + 2 * margin)

def _square_limits(ax: Axes, Y: ArrayLike, margin: float = 0.08) -> float:
    """Equal x and y ranges around the points and a square box: the panel stays square
    and one unit is as long on both axes, whatever the spread of the embedding."""
    centre, half = square_limits(Y, margin)
    _set_square(ax, centre, half)
    return 2 * half

def _set_square(ax: Axes, centre: NDArray[np.float64], half: float) -> None:
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_aspect("equal", adjustable="box")

def outlier_ratios(Y: ArrayLike) -> NDArray[np.float64]:
    """Each point's median distance to the others over the median of those: how many
    times farther than typical a point lies (compared with ``factor`` by
    :func:`cshape.compare.mds_outliers`)."""
    m = median_distances(Y)
    typical = float(np.median(m)) if len(m) else 0.0
    return m / typical if typical > 0 else np.ones_like(m)

def border_points(Y: ArrayLike, outliers: ArrayLike, centre: ArrayLike, half: float
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Where outliers are drawn: on the border of the square ``centre +- half``, in their
    direction from the centre.

    Parameters
    ----------
    Y : array_like, shape (p, 2)
    outliers : array_like of bool, shape (p,)
    centre : array_like, shape (2,)
    half : float
        Half the side of the square on whose border the outliers are drawn.

    Returns
    -------
    P : ndarray, shape (q, 2)
        The border positions of the ``q`` outliers, in the order of ``Y``.
    angle : ndarray, shape (q,)
        Their direction from the centre, degrees counter-clockwise from +x.

    >>> P, angle = border_points([[10.0, 5.0], [0.0, 0.0]], [True, False], [0.0, 0.0], 1.0)
    >>> P.tolist(), angle.round(2).tolist()
    ([[1.0, 0.5]], [26.57])
    """
    Y = np.asarray(Y, dtype=np.float64)
    out = np.asarray(outliers, dtype=bool)
    c = np.asarray(centre, dtype=np.float64)
    d = Y[out] - c
    reach = np.abs(d).max(axis=1)
    t = np.divide(float(half), reach, out=np.zeros_like(reach), where=reach > 0)
    return c + d * t[:, None], np.degrees(np.arctan2(d[:, 1], d[:, 0]))

def spread_on_border(P: ArrayLike, centre: ArrayLike, half: float, gap: float
                     ) -> NDArray[np.float64]:
    """Points on the border of the square ``centre +- half`` moved along it, in order,
    until neighbours are at least ``gap`` apart (measured along the border).

    Parameters
    ----------
    P : array_like, shape (q, 2)
        Points on the border (from :func:`border_points`).
    centre : array_like, shape (2,)
    half : float
    gap : float
        At most ``8 * half / q`` is used, so that the points fit.

    Returns
    -------
    ndarray, shape (q, 2)
        In the order of ``P``.

    >>> spread_on_border([[1.0, 0.0], [1.0, 0.1]], [0.0, 0.0], 1.0, 0.5).round(3).tolist()
    [[1.0, -0.2], [1.0, 0.3]]
    """
    P = np.asarray(P, dtype=np.float64).reshape(-1, 2)
    q, h = len(P), float(half)
    if q < 2 or h <= 0:
        return P.copy()
    gap = min(float(gap), 8 * h / q)
    x, y = (P - np.asarray(centre, dtype=np.float64)).T / h
    # position along the border, counter-clockwise from the bottom-left corner, in [0, 8)
    t = np.where(np.isclose(y, -1) & (x < 1), 1 + x,
        np.where(np.isclose(x, 1) & (y < 1), 3 + y,
        np.where(np.isclose(y, 1) & (x > -1), 5 - x, (7 - y) % 8)))
    order = np.argsort(t, kind="stable")
    u = t[order].copy()
    g = gap / h
    for _ in range(50):  # push apart, pairwise, until no pair is closer than the gap
        moved = False
        for j in range(1, q):
            short = g - (u[j] - u[j - 1])
            if short > 1e-12:
                u[j - 1] -= short / 2
                u[j] += short / 2
                moved = True
        if not moved:
            break
    u %= 8
    out = np.empty_like(P)
    for k, v in zip(order, u, strict=True):
        if v < 2:
            xy = (v - 1, -1.0)
        elif v < 4:
            xy = (1.0, v - 3)
        elif v < 6:
            xy = (5 - v, 1.0)
        else:
            xy = (-1.0, 7 - v)
        out[k] = np.asarray(centre, dtype=np.float64) + h * np.array(xy)
    return out

def named_points(P: ArrayLike, outliers: ArrayLike, max_names: int = MDS_MAX_NAMES,
                 sample: int = MDS_SAMPLE_NAMES) -> NDArray[np.int64]:
    """The points of an MDS picture that get their name written: every point up to
    ``max_names``; beyond, the outliers and ``sample`` others spread over the picture.

    The sample is drawn by farthest-point order from the point nearest the centre (each
    next point the farthest from those taken), so the names cover the picture's extremes
    and its middle.

    Parameters
    ----------
    P : array_like, shape (p, 2)
        The drawn positions (:func:`mds_layout`'s ``P``).
    outliers : array_like of bool, shape (p,)
    max_names : int, default=MDS_MAX_NAMES
    sample : int, default=MDS_SAMPLE_NAMES

    Returns
    -------
    ndarray of int
        Outliers first, then the others, in the order their names should be placed.

    >>> named_points([[0, 0], [1, 0], [5, 0]], [False, False, True]).tolist()
    [2, 0, 1]
    >>> named_points([[0, 0], [1, 0], [9, 0], [4, 0], [5, 0]], [False] * 5, max_names=2,
    ...              sample=2).tolist()
    [3, 2]
    """
    P = np.asarray(P, dtype=np.float64)
    out = np.asarray(outliers, dtype=bool)
    inner = np.flatnonzero(~out)
    if len(P) <= max_names or len(inner) <= sample:
        return np.concatenate([np.flatnonzero(out), inner]).astype(np.int64)
    Q = P[inner]
    taken = [int(np.argmin(np.linalg.norm(Q - np.median(Q, axis=0), axis=1)))]
    gap = np.linalg.norm(Q - Q[taken[0]], axis=1)
    while len(taken) < sample:
        j = int(np.argmax(gap))
        taken.append(j)
        gap = np.minimum(gap, np.linalg.norm(Q - Q[j], axis=1))
    return np.concatenate([np.flatnonzero(out), inner[taken]]).astype(np.int64)

def _axes_points(ax: Axes, layout: bool = True) -> tuple[float, float]:
    """The width and height of ``ax`` in points, at least 1 (after a layout pass, if
    ``layout`` and the figure has a layout engine; a fixed layout, as the M-sweep widget's,
    needs none)."""
    fig: Any = ax.figure
    while getattr(fig, "figure", fig) is not fig:  # the root figure of a subfigure
        fig = fig.figure
    if layout and fig.get_layout_engine() is not None:
        fig.draw_without_rendering()  # the axes get their final size
    box = ax.get_window_extent()
    return max(72.0 * box.width / fig.dpi, 1.0), max(72.0 * box.height / fig.dpi, 1.0)

def _overlap(a: tuple[float, float, float, float], b: tuple[float, float, float, float],
             gx: float = 0.0, gy: float = 0.0) -> bool:
    """Whether boxes ``(x0, y0, x1, y1)`` come closer than ``gx`` across and ``gy`` up."""
    return a[0] - gx < b[2] and b[0] < a[2] + gx and a[1] - gy < b[3] and b[1] < a[3] + gy

def annotate_points(ax: Axes, Y: ArrayLike, texts: Sequence[str], *,
                    fontsize: str | float = "x-small", offset: float = 3.0,
                    safety: float = 1.15, points: ArrayLike | None = None,
                    required: int = 0, layout: bool = True) -> list[int]:
    """Write ``texts[i]`` beside point ``Y[i]``, inside the axes, covering no text or point.

    Greedy, in order: a text's box is estimated from its length, the font size and the
    axes' size after a layout pass (``safety`` times larger) and tried above right, above
    left, below right and below left of its point; the text is left out when each would
    leave the axes or overlap a box kept before or a point's marker.  The texts take no
    part in the layout, so call this last, after the axis limits, legends and colour bars
    are set.

    Parameters
    ----------
    ax : matplotlib Axes
        The axes the points are drawn on.
    Y : array_like, shape (p, 2)
        The points to name, in data coordinates.
    texts : sequence of str, length p
        One text per point.
    fontsize : str or float, default='x-small'
        Matplotlib font size.
    offset : float, default=3.0
        Distance of a text from its point, in points.
    safety : float, default=1.15
        Factor by which the estimated text boxes are enlarged.
    points : array_like, shape (q, 2), optional
        Every point drawn, which no text may cover (default: ``Y``).
    required : int, default=0
        The first ``required`` texts (an outlier's name) are written in any case: over a
        point, or even over a text, where no free place is found inside the axes.
    layout : bool, default=True
        Run the figure's layout first, so that the axes have their final size.  Pass False
        for the second and later axes of a figure annotated in turn, with nothing else
        added in between: the texts take no part in the layout, so it has not changed.

    Returns
    -------
    list of int
        The indices of the points that got their text.
    """
    from matplotlib.font_manager import FontProperties

    Y = np.asarray(Y, dtype=np.float64)
    x0, x1 = (float(v) for v in ax.get_xlim())
    y0, y1 = (float(v) for v in ax.get_ylim())
    width, height = _axes_points(ax, layout)
    ux, uy = abs(x1 - x0) / width, abs(y1 - y0) / height  # data units per point
    size = FontProperties(size=fontsize).get_size_in_points()
    dx, dy = offset * ux, offset * uy  # the true offsets: larger ones would hide overlaps
    gx, gy = GAP_POINTS * ux, GAP_POINTS * uy  # room kept between two boxes
    rx, ry = 2.5 * safety * ux, 2.5 * safety * uy  # half the side of a marker, with room
    lo_x, hi_x, lo_y, hi_y = min(x0, x1), max(x0, x1), min(y0, y1), max(y0, y1)
    P = Y if points is None else np.asarray(points, dtype=np.float64).reshape(-1, 2)
    obstacles = [(float(x) - rx, float(y) - ry, float(x) + rx, float(y) + ry) for x, y in P]
    boxes: list[tuple[float, float, float, float]] = []
    kept: list[int] = []

    def free(box: tuple[float, float, float, float], own: tuple[float, float],
             level: int) -> bool:
        """Level 0: inside the axes, over no text and no point; 1: over no text; 2: inside."""
        inside = lo_x <= box[0] and box[2] <= hi_x and lo_y <= box[1] and box[3] <= hi_y
        # a point's own marker is no obstacle to its name
        near = [b for b in obstacles if not (b[0] < own[0] < b[2] and b[1] < own[1] < b[3])]
        hit_text = any(_overlap(box, b, gx, gy) for b in boxes)
        hit_point = any(_overlap(box, b) for b in near)
        return inside and (level == 2 or not hit_text) and (level >= 1 or not hit_point)

    # (horizontal, vertical) side of the point: +1 right / above, -1 left / below, 0 centred
    sides = ((1, 1), (-1, 1), (1, -1), (-1, -1), (0, 1), (0, -1))
    for i, text in enumerate(texts):
        w, h = 0.7 * safety * size * len(text) * ux, 1.35 * safety * size * uy
        placed = None
        for level in range(3 if i < required else 1):
            for sx, sy in sides:
                bx = Y[i, 0] + dx if sx > 0 else Y[i, 0] - dx - w if sx < 0 else Y[i, 0] - w / 2
                by = Y[i, 1] + dy if sy > 0 else Y[i, 1] - dy - h
                box = (bx, by, bx + w, by + h)
                if free(box, (Y[i, 0], Y[i, 1]), level):
                    placed = (sx, sy)
                    break
            if placed:
                break
        if placed is None:
            continue
        sx, sy = placed
        boxes.append(box)
        kept.append(i)
        t = ax.annotate(text, tuple(Y[i]), xytext=(offset * sx, offset * sy),
                        textcoords="offset points", fontsize=fontsize,
                        ha={1: "left", -1: "right", 0: "center"}[sx],
                        va="bottom" if sy > 0 else "top", annotation_clip=True)
        t.set_in_layout(False)
    return kept

def _spread_out(points: NDArray[np.float64], min_gap: float) -> list[int]:
    """Indices of points kept so that no two are closer than ``min_gap`` (greedy, in
    order): the points whose labels can be written without writing over each other."""
    kept: list[int] = []
    for i, x in enumerate(points):
        if all(np.linalg.norm(x - points[j]) >= min_gap for j in kept):
            kept.append(i)
    return kept

def _outlier_mask(Y: NDArray[np.float64], outliers: str | ArrayLike | None) -> NDArray[np.bool_]:
    if outliers is None or outliers is False:
        return np.zeros(len(Y), dtype=bool)
    if isinstance(outliers, str):
        check_choice("outliers", outliers, ("auto",))
        return mds_outliers(Y)
    mask = np.asarray(outliers, dtype=bool).reshape(-1)
    check_entries("outliers", mask, len(Y))
    return mask

def mds_layout(Y: ArrayLike, outliers: str | ArrayLike | None = "auto", *,
               margin: float = 0.08) -> dict[str, Any]:
    """Where :func:`plot_mds` draws each point: the inliers where they are, the outliers on
    the border of a square fitted to the inliers.

    Parameters
    ----------
    Y : array_like, shape (p, 2)
    outliers : 'auto', None or array_like of bool, default='auto'
        'auto': :func:`cshape.compare.mds_outliers`; None: no outliers (every point where it is).
    margin : float, default=0.08
        Room around the inliers, as a fraction of their extent on each side.

    Returns
    -------
    dict
        ``outliers`` (bool, (p,)), ``P`` ((p, 2): drawn positions), ``angle`` ((p,):
        outward direction of each outlier in degrees, NaN for inliers), ``centre`` and
        ``half`` (the panel is ``centre +- half``), ``ratio`` ((p,): median distance over
        the typical one, see :func:`outlier_ratios`; NaN unless there are outliers).
    """
    Y = check_points(Y, d=2, min_points=1)
    margin = check_real("margin", margin, min=0)
    out = _outlier_mask(Y, outliers)
    if out.all():
        out = np.zeros(len(Y), dtype=bool)
    P = Y.copy()
    angle = np.full(len(Y), np.nan)
    ratio = np.full(len(Y), np.nan)
    if out.any():
        # the outliers sit in a band beyond the inliers: the panel is a little larger
        centre, half = square_limits(Y[~out], margin + 0.05)
        P[out], angle[out] = border_points(Y, out, centre, half)
        P[out] = spread_on_border(P[out], centre, half, 0.14 * half)
        half *= 1 + 2 * 0.04
        ratio = outlier_ratios(Y)
    else:
        centre, half = square_limits(Y, margin)
    return {"outliers": out, "P": P, "angle": angle, "centre": centre, "half": half,
            "ratio": ratio}

def class_medians(Y: ArrayLike, labels: Sequence[Any]) -> list[tuple[str, NDArray[np.float64]]]:
    """The coordinate-wise median of each class's points: ``[(label, (x, y))]`` in
    first-seen order (where :func:`plot_mds` writes class names)."""
    Y = np.asarray(Y, dtype=np.float64)
    codes = check_labels(labels, len(Y))
    lab = [str(x) for x in labels]
    seen: dict[int, int] = {}
    for i, c in enumerate(codes):
        seen.setdefault(int(c), i)
    return [(lab[i], np.median(Y[codes == c], axis=0)) for c, i in seen.items()]
