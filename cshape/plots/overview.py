"""Pictures for exploring one's own collection: which shapes lie near which.

The distances they draw come from :func:`cshape.batch.table.collection_distances` (the rows that
cannot be described left out and named), the neighbours and outliers from
:func:`cshape.compare.nearest_neighbours` and :func:`cshape.compare.mds_outliers`.

* :func:`interactive_mds`      - the MDS as a plotly figure: each shape's name, class and
  nearest neighbours on hover, outliers on the border, at any size;
* :func:`plot_neighbour_strip`, :func:`neighbour_strip_plotly` - a query and its nearest
  shapes as rendered thumbnails with their distances (matplotlib, plotly);
* :func:`plot_overview`, :func:`overview_html` - the overview of a described folder: MDS,
  distance matrix and a table of the classes (:func:`class_summary`);
* :func:`figure_html`, :func:`save_figure` - offline HTML (plotly.js embedded, no network)
  and atomic writes of any of these figures.

Every figure names the descriptor it compared (its :attr:`cshape.Descriptor.label`).  The
pure functions behind the pictures (:func:`class_summary`, :func:`thumbnail_mesh`,
:func:`~cshape.plots.layout.mds_layout`) are tested directly.
"""

from __future__ import annotations

import html
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .._checks import check_entries, check_int, check_labels, check_points, check_square
from .._files import atomic_write
from ..compare import nearest_neighbours
from ..mesh import as_mesh
from .collection import MATRIX_MAX_NAMES, class_styles, plot_distance_matrix, plot_mds
from .layout import mds_layout, named_points, short_label, short_labels

if TYPE_CHECKING:
    from collections.abc import Sequence

    import plotly.graph_objects as go
    from matplotlib.figure import Figure
    from numpy.typing import ArrayLike

    from ..descriptors import Descriptor
    from ..mesh import MeshLike

    #: a distance matrix, shape (p, p)
    _Matrix = np.ndarray | Sequence[Sequence[float]]

#: Most triangles of a thumbnail drawn by matplotlib (:func:`thumbnail_mesh`).
THUMBNAIL_FACES = 6000
#: Most triangles of a mesh drawn in an HTML strip (WebGL draws more, the file grows).
HTML_THUMBNAIL_FACES = 20000
#: Beyond this many shapes the HTML overview shows the class-by-class matrix of median
#: distances instead of the shape-by-shape matrix (which would make a file of p^2 numbers).
HTML_MATRIX_MAX = 800
#: The static overview's class table lists at most this many classes (the largest first).
OVERVIEW_TABLE_ROWS = 20
#: plotly marker symbols of matplotlib's class markers.
_PLOTLY_SYMBOLS = {"o": "circle", "s": "square", "^": "triangle-up", "D": "diamond",
                   "v": "triangle-down", "<": "triangle-left", ">": "triangle-right",
                   "p": "pentagon", "P": "cross", "*": "star", "X": "x", "h": "hexagon"}


# =========================================================================== classes
def class_summary(D: ArrayLike, labels: Sequence[object]) -> list[dict[str, Any]]:
    """Summarise every class: its size, spread, nearest other class and neighbours.

    The neighbours: how often the nearest neighbour of a shape of the class is of the class.

    Parameters
    ----------
    D : array_like, shape (p, p)
        Distances between the shapes.
    labels : sequence, length p
        Class of each shape.

    Returns
    -------
    list of dict, one per class in first-seen order
        ``label``; ``n`` (shapes); ``within`` (median distance between two shapes of the
        class, NaN for a class of one); ``nearest`` (the class of the nearest shape of
        another class, ``''`` when there is one class) and ``gap`` (that distance);
        ``nn_same`` (fraction of the class's shapes whose nearest other shape is of the
        class, NaN for a class of one).
    """
    A = check_square(D, "D")
    codes = check_labels(labels, len(A))
    lab = [str(x) for x in labels]
    first: dict[int, int] = {}
    for i, c in enumerate(codes):
        first.setdefault(int(c), i)
    B = A.copy()
    np.fill_diagonal(B, np.inf)
    nn = np.argmin(B, axis=1) if len(A) > 1 else np.zeros(len(A), dtype=np.int64)
    out = []
    for c, i0 in first.items():
        inside = codes == c
        n = int(inside.sum())
        sub = A[np.ix_(inside, inside)][np.triu_indices(n, 1)]
        other = B[np.ix_(inside, ~inside)]
        if other.size:
            a, b = np.unravel_index(np.argmin(other), other.shape)
            nearest, gap = lab[np.flatnonzero(~inside)[b]], float(other[a, b])
        else:
            nearest, gap = "", float("nan")
        out.append({
            "label": lab[i0], "n": n,
            "within": float(np.median(sub)) if sub.size else float("nan"),
            "nearest": nearest, "gap": gap,
            "nn_same": float(np.mean(codes[nn[inside]] == c)) if n > 1 else float("nan"),
        })
    return out


# =========================================================================== interactive MDS
def _rgb(colour: Any) -> str:
    r, g, b = (int(round(255 * x)) for x in colour[:3])
    return f"rgb({r},{g},{b})"


def _hover_texts(names: Sequence[object], labels: Sequence[object] | None,
                 D: _Matrix | None, k: int, lay: dict[str, Any]) -> list[str]:
    p = len(names)
    texts: list[str] = []
    ind: Any = None
    dist: Any = None
    if D is not None and p > 1:
        ind, dist = nearest_neighbours(D, k)
    for i in range(p):
        t = f"<b>{html.escape(str(names[i]))}</b>"
        if labels is not None and str(labels[i]):
            t += f"<br>class: {html.escape(str(labels[i]))}"
        if ind is not None:
            near = ", ".join(f"{html.escape(str(names[j]))} ({d:.4g})"
                             for j, d in zip(ind[i], dist[i], strict=True))
            t += f"<br>nearest: {near}"
        if lay["outliers"][i]:
            t += (f"<br>outlier: {lay['ratio'][i]:.0f}\u00d7 the typical distance, drawn at the"
                  " border")
        texts.append(t)
    return texts


def interactive_mds(Y: ArrayLike, names: Any, labels: Sequence[object] | None = None,
                    *, D: _Matrix | None = None, k: int = 3, title: str | None = None,
                    outliers: str | ArrayLike | None = "auto", height: int = 650) -> go.Figure:
    """The MDS of a collection as an interactive plotly figure.

    Hovering a point shows its name, class and its ``k`` nearest shapes with their
    distances (from ``D``, the distances compared, not the MDS coordinates).  Outliers are
    drawn as arrows on the border pointing their way (as in :func:`plot_mds`), so the
    first view shows the rest at its own scale; classes are legend entries (click to hide
    one, double-click to show only it), in the colours and markers of :func:`plot_mds`.
    Any number of shapes: beyond 2000 points WebGL draws them.

    Parameters
    ----------
    Y : array_like, shape (p, 2)
        MDS coordinates (:func:`cshape.mds_embedding`).
    names : sequence of str, length p
        Shape names, shown on hover.
    labels : sequence, length p, optional
        Classes; points of one class share a colour and a marker.
    D : array_like, shape (p, p), optional
        The distances; without it the hover shows no neighbours.
    k : int, default=3
        Nearest neighbours listed on hover.
    title : str, optional
        Say which descriptor was compared (its :attr:`cshape.Descriptor.label`).
    outliers : 'auto', None or array_like of bool, default='auto'
        See :func:`cshape.plots.layout.mds_layout`.
    height : int, default=650
        Pixels.

    Returns
    -------
    plotly.graph_objects.Figure
        Not shown; :func:`figure_html` or :func:`save_figure` write it offline.
    """
    import plotly.graph_objects as go

    Y = check_points(Y, d=2, min_points=1, fix="use mds_embedding(D)")
    p = len(Y)
    check_entries("names", names, p)
    if D is not None and check_square(D, "D").shape[0] != p:
        raise ValueError(f"D has {len(D)} rows but Y has {p} points")
    lay = mds_layout(Y, outliers)
    out, P = lay["outliers"], lay["P"]
    hover = _hover_texts(names, labels, D, k, lay)
    if labels is not None:
        codes, styles = class_styles(labels, p)
    else:
        codes, styles = np.zeros(p, dtype=np.int64), [("shapes", (0.12, 0.47, 0.71), "o")]
    Scatter = go.Scattergl if p > 2000 else go.Scatter
    size = 9 if p <= 200 else 6 if p <= 2000 else 4
    fig = go.Figure()
    for c, (lab, col, marker) in enumerate(styles):
        sel = np.flatnonzero((codes == c) & ~out)
        fig.add_trace(Scatter(
            x=P[sel, 0], y=P[sel, 1], mode="markers",
            name=short_label(lab, 24) if len(styles) > 1 else "shapes",
            legendgroup=str(c), text=[hover[i] for i in sel], hoverinfo="text",
            customdata=[str(names[i]) for i in sel],
            marker={"color": _rgb(col), "symbol": _PLOTLY_SYMBOLS.get(marker, "circle"),
                    "size": size, "line": {"width": 0}}))
    if out.any():
        sel = np.flatnonzero(out)
        tags = short_labels([str(names[i]) for i in range(p)])
        # text inside the panel: to the left of points on the right border, and so on
        pos = []
        for i in sel:
            dx, dy = (P[i] - lay["centre"]) / lay["half"]
            pos.append(("bottom" if dy > 0.5 else "top" if dy < -0.5 else "middle") + " "
                       + ("left" if dx > 0.5 else "right" if dx < -0.5 else "center"))
        fig.add_trace(go.Scatter(
            x=P[sel, 0], y=P[sel, 1], mode="markers+text", name="outliers, at the border",
            text=[f"{tags[i]} \u00d7{lay['ratio'][i]:.0f}" for i in sel], textposition=pos,
            hovertext=[hover[i] for i in sel], hoverinfo="text",
            customdata=[str(names[i]) for i in sel],
            marker={"symbol": "arrow", "angle": [90.0 - lay["angle"][i] for i in sel],
                    "size": 16, "color": [_rgb(styles[codes[i]][1]) for i in sel],
                    "line": {"width": 1, "color": "black"}}))
    named = [i for i in named_points(P, out) if not out[i]]
    if named:  # names on the picture (every one when few, else a spread sample)
        tags = short_labels([str(x) for x in names])
        fig.add_trace(go.Scatter(
            x=P[named, 0], y=P[named, 1], mode="text", text=[tags[i] for i in named],
            textposition="top center", textfont={"size": 10, "color": "#444"},
            hoverinfo="skip", showlegend=False))
    c, h = lay["centre"], lay["half"]
    fig.update_layout(
        title={"text": html.escape(title) if title else None, "x": 0.5},
        height=height, template="plotly_white", hovermode="closest",
        hoverlabel={"align": "left"}, showlegend=len(styles) > 1 or bool(out.any()),
        legend={"title": {"text": "class" if len(styles) > 1 else ""},
                "itemsizing": "constant"},
        xaxis={"range": [c[0] - h, c[0] + h], "title": "MDS 1", "zeroline": False},
        yaxis={"range": [c[1] - h, c[1] + h], "title": "MDS 2", "zeroline": False,
               "scaleanchor": "x", "scaleratio": 1},
        margin={"l": 60, "r": 20, "t": 60, "b": 50})
    return fig


def figure_html(fig: go.Figure, *, full_html: bool = True, include_plotlyjs: bool | str = True
                ) -> str:
    """Return a plotly figure as HTML that works offline.

    plotly.js is embedded in the page (no CDN), and no MathJax is asked for.  The page opens
    on the figure as it was made: a figure with frames (an explorer's slider) does not play
    them when the page loads.

    Parameters
    ----------
    fig : plotly.graph_objects.Figure
        The figure.
    full_html : bool, default=True
        A whole page; ``False`` gives a ``<div>`` to put in a page.
    include_plotlyjs : bool or str, default=True
        As for plotly's ``Figure.to_html``: ``True`` embeds plotly.js, ``False`` leaves it
        out (for a page that has it already).

    Returns
    -------
    str
        The HTML.
    """
    text = fig.to_html(full_html=full_html, include_plotlyjs=include_plotlyjs,
                       include_mathjax=False, auto_play=False,
                       config={"displaylogo": False, "responsive": True},
                       default_width="100%", default_height="100vh")
    # a figure without a height fills the window: no page margin, no scroll bar
    return text.replace("<body>", '<body style="margin:0">', 1) if full_html else text


# =========================================================================== thumbnails
def thumbnail_mesh(mesh: MeshLike, max_faces: int = THUMBNAIL_FACES
                   ) -> tuple[np.ndarray, np.ndarray]:
    """A lighter copy of a mesh for a thumbnail: vertex clustering on a grid.

    Vertices in one cell of a regular grid merge into their mean; triangles that lose a
    corner vanish.  The cell shrinks the count below ``max_faces`` (a coarser grid each
    time, starting from about ``sqrt(max_faces)`` cells along the longest side).  Enough
    for a picture, not for computing.

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        The mesh.
    max_faces : int, default=THUMBNAIL_FACES
        Most triangles of the copy.

    Returns
    -------
    V : ndarray, shape (n', 3)
        Vertices of the copy.
    F : ndarray, shape (m', 3)
        ``m' <= max_faces``; the mesh itself when it has no more triangles.
    """
    m = as_mesh(mesh)
    V, F = np.asarray(m.vertices, dtype=np.float64), np.asarray(m.faces, dtype=np.int64)
    if len(F) <= max_faces:
        return V, F
    lo = V.min(axis=0)
    extent = float((V.max(axis=0) - lo).max()) or 1.0
    cells = max(2.0, np.sqrt(max_faces))
    while True:
        key = np.floor((V - lo) / (extent / cells)).astype(np.int64)
        _, inv, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
        inv = inv.reshape(-1)
        W = np.zeros((len(counts), 3))
        np.add.at(W, inv, V)
        W /= counts[:, None]
        G = inv[F]
        G = G[(G[:, 0] != G[:, 1]) & (G[:, 1] != G[:, 2]) & (G[:, 0] != G[:, 2])]
        _, first = np.unique(np.sort(G, axis=1), axis=0, return_index=True)
        G = G[np.sort(first)]
        if len(G) <= max_faces or cells <= 2:
            used, G = np.unique(G, return_inverse=True)
            return W[used], G.reshape(-1, 3)
        cells *= 0.8


def guess_vertical_axis(path: str | os.PathLike[str]) -> str:
    """Guess the up axis of a mesh file from its format's habit.

    ``'y'`` for OBJ, glTF and COLLADA (modelling tools), ``'z'`` for the rest (scanners
    and CAD: PLY, STL, OFF, ...).

    Parameters
    ----------
    path : str or os.PathLike
        The mesh file (only its name is read).

    Returns
    -------
    {'y', 'z'}
        The axis to draw upwards.
    """
    from ..readers import split_mesh_name

    suffix = split_mesh_name(Path(path))[1].lower()
    return "y" if suffix in (".obj", ".gltf", ".glb", ".dae") else "z"


def _axes_list(vertical_axis: str | Sequence[str], n: int) -> list[str]:
    if isinstance(vertical_axis, str):
        return [vertical_axis] * n
    return check_entries("vertical_axis", vertical_axis, n, of="the strip", unit="meshes")


def _strip_texts(names: Sequence[object], distances: ArrayLike,
                 labels: Sequence[object] | None, n: int) -> tuple[list[str], np.ndarray]:
    check_entries("names", names, n, of="the strip", unit="meshes (the query first)")
    d = np.asarray(distances, dtype=np.float64).reshape(-1)
    check_entries("distances", d, n - 1, of="the strip",
                  unit="neighbours (one per mesh after the query)")
    if labels is not None:
        check_entries("labels", labels, n, of="the strip", unit="meshes")
    heads = ["query"] + [f"{j}. d = {d[j - 1]:.4g}" for j in range(1, n)]
    return heads, d


def plot_neighbour_strip(meshes: Sequence[MeshLike], names: Sequence[object],
                         distances: ArrayLike, *, labels: Sequence[object] | None = None,
                         title: str | None = None, vertical_axis: str | Sequence[str] = "z",
                         max_faces: int = THUMBNAIL_FACES, ncols: int = 6, size: float = 2.3
                         ) -> Figure:
    """A query and its nearest shapes, rendered side by side with their distances.

    Parameters
    ----------
    meshes : sequence of Mesh or (vertices, faces)
        The query first, then its neighbours, nearest first.
    names : sequence of str
        One per mesh.
    distances : array_like, shape (len(meshes) - 1,)
        Distance of each neighbour to the query.
    labels : sequence of str, optional
        Class of each mesh, written under its name.
    title : str, optional
        Say which descriptor was compared (its :attr:`cshape.Descriptor.label`).
    vertical_axis : {'z', 'y', 'x'} or sequence of them, default='z'
        The axis drawn upwards, for all meshes or each (see :func:`guess_vertical_axis`).
    max_faces : int, default=THUMBNAIL_FACES
        Meshes with more triangles are drawn from :func:`thumbnail_mesh`.
    ncols : int, default=6
        Thumbnails per row.
    size : float, default=2.3
        Inches per thumbnail.

    Returns
    -------
    matplotlib.figure.Figure
        A new figure (not registered with pyplot).
    """
    from matplotlib.figure import Figure

    from .figures import plot_mesh

    n = len(meshes)
    heads, _ = _strip_texts(names, distances, labels, n)
    axes = _axes_list(vertical_axis, n)
    cols = min(ncols, n)
    rows = -(-n // cols)
    head = 0.35 if title else 0.0  # inches above the panels
    height = size * rows * 1.15 + head
    fig = Figure(figsize=(size * cols, height))
    # a fixed layout: 3-D panels' titles are not seen by the layout engines
    fig.subplots_adjust(left=0.0, right=1.0, bottom=0.0, top=1.0 - head / height,
                        wspace=0.02, hspace=0.12)
    for j in range(n):
        ax = fig.add_subplot(rows, cols, j + 1, projection="3d")
        plot_mesh(thumbnail_mesh(meshes[j], max_faces), ax=ax, edges=False,
                  vertical_axis=axes[j], elev=18.0, azim=-60.0)
        ax.set_box_aspect((1, 1, 1), zoom=1.3)
        text = f"{heads[j]}\n{short_label(names[j], 22)}"
        if labels is not None and str(labels[j]):  # '' is no class: nothing to show
            text += f"\n[{short_label(labels[j], 22)}]"
        ax.set_title(text, fontsize="small", color="C3" if j == 0 else "black",
                     fontweight="bold" if j == 0 else "normal", y=0.93)
    if title:
        fig.suptitle(title, fontsize="medium", y=1.0 - 0.08 / height, va="top")
    return fig


#: The window a full-page strip is fitted for (pixels): a landscape window, 4:3 at its
#: narrowest; wider windows only add room.
_WINDOW = (1200, 900)
#: Pixels of the strip's title and of each row's panel titles (three lines).
_STRIP_TITLE, _PANEL_TITLE = 50, 62
#: The lowest window whose rows leave their titles room (pixels).
_LOWEST_WINDOW = 640


def strip_grid(n: int, window: tuple[float, float] = _WINDOW) -> tuple[int, int]:
    """Rows and columns of ``n`` views on a page: the panels as near square as the window
    allows, with fewer than a row of empty cells.

    >>> strip_grid(6), strip_grid(2), strip_grid(11)
    ((2, 3), (1, 2), (3, 4))
    """
    n = check_int("n", n, min=1)
    w, h = window

    def badness(rows: int) -> float:
        cols = -(-n // rows)
        return abs(np.log((w / cols) / (h / rows)))

    rows = min(range(1, n + 1), key=badness)
    return rows, -(-n // rows)


def neighbour_strip_plotly(meshes: Sequence[MeshLike], names: Sequence[object],
                           distances: ArrayLike, *, labels: Sequence[object] | None = None,
                           title: str | None = None, vertical_axis: str | Sequence[str] = "z",
                           max_faces: int = HTML_THUMBNAIL_FACES) -> go.Figure:
    """Show a query and its nearest shapes as an interactive plotly figure that fills its page.

    :func:`plot_neighbour_strip` in plotly: the views on a grid (:func:`strip_grid`), each
    lit and framed by :func:`cshape.plots.viewer.add_mesh_view`, each turning and zooming
    on its own; hover shows a mesh's name.

    Parameters
    ----------
    meshes : sequence of Mesh or (vertices, faces)
        The query first, then its neighbours, nearest first.
    names : sequence of str
        One per mesh.
    distances : array_like, shape (len(meshes) - 1,)
        Distance of each neighbour to the query.
    labels : sequence of str, optional
        Class of each mesh, written under its name.
    title : str, optional
        Say which descriptor was compared (its :attr:`cshape.Descriptor.label`).
    vertical_axis : {'z', 'y', 'x'} or sequence of them, default='z'
        The axis drawn upwards, for all meshes or each (see :func:`guess_vertical_axis`).
    max_faces : int, default=HTML_THUMBNAIL_FACES
        Meshes with more triangles are drawn from :func:`thumbnail_mesh`.

    Returns
    -------
    plotly.graph_objects.Figure
        Without a size (:func:`figure_html` gives it the window); not shown.
    """
    from plotly.subplots import make_subplots

    from .viewer import add_mesh_view

    n = len(meshes)
    heads, _ = _strip_texts(names, distances, labels, n)
    axes = _axes_list(vertical_axis, n)
    titles = [f"{h}<br>{html.escape(str(nm))}"
              + (f"<br>[{html.escape(str(labels[j]))}]"
                 if labels is not None and str(labels[j]) else "")
              for j, (h, nm) in enumerate(zip(heads, names, strict=True))]
    rows, cols = strip_grid(n)
    w, h = _WINDOW
    vspace = (_PANEL_TITLE / (_LOWEST_WINDOW - _STRIP_TITLE - _PANEL_TITLE) if rows > 1
              else 0.0)
    fig = make_subplots(rows=rows, cols=cols, specs=[[{"type": "scene"}] * cols] * rows,
                        subplot_titles=titles, horizontal_spacing=0.01, vertical_spacing=vspace)
    panel_h = (h - _STRIP_TITLE - _PANEL_TITLE) * (1 - vspace * (rows - 1)) / rows
    aspect = (w * (1 - 0.01 * (cols - 1)) / cols) / panel_h
    for j in range(n):
        scene = "scene" if j == 0 else f"scene{j + 1}"
        add_mesh_view(fig, thumbnail_mesh(meshes[j], max_faces), scene=scene,
                      vertical_axis=axes[j], aspect=aspect,
                      color="rgb(214, 96, 77)" if j == 0 else "rgb(185, 192, 205)",
                      hoverinfo="text", hovertext=html.escape(str(names[j])),
                      name=str(names[j]))
    fig.update_layout(title={"text": html.escape(title) if title else None, "x": 0.5},
                      showlegend=False,
                      margin={"l": 5, "r": 5, "t": _STRIP_TITLE + _PANEL_TITLE, "b": 5})
    for a in fig.layout.annotations:
        a.font.size = 12
    return fig


# =========================================================================== overview
def colour_limit(D: ArrayLike, outliers: ArrayLike | None) -> float:
    """Return the top of a distance matrix's colour range, outliers left out.

    The largest distance between two shapes that are not outliers (their rows would
    otherwise take the whole range, leaving the rest one colour), or the largest distance
    when there is no outlier.

    Parameters
    ----------
    D : array_like, shape (p, p)
        Distances between the shapes.
    outliers : array_like of bool, shape (p,), or None
        Which shapes are outliers; ``None``: none.

    Returns
    -------
    float
        The top of the colour range.

    Examples
    --------
    >>> colour_limit([[0, 1, 9], [1, 0, 9], [9, 9, 0]], [False, False, True])
    1.0
    """
    A = check_square(D, "D")
    keep = ~np.asarray(outliers, dtype=bool)
    inner = A[np.ix_(keep, keep)] if keep.sum() > 1 else A
    return float(inner.max()) or float(A.max()) or 1.0


def _class_order(labels: Sequence[object]) -> np.ndarray:
    """Rows ordered by class (first-seen order of the classes), stable within a class."""
    codes = check_labels(labels, len(labels))
    return np.argsort(codes, kind="stable")


def _fmt(x: float | None, spec: str = ".4g") -> str:
    return "-" if x is None or (isinstance(x, float) and np.isnan(x)) else format(x, spec)


def collection_title(p: int, n_classes: int) -> str:
    """How many shapes and classes, in words: ``'64 shapes'`` for a flat folder (one
    class), ``'200 shapes in 10 classes'``.

    >>> collection_title(64, 1), collection_title(2, 2), collection_title(1, 1)
    ('64 shapes', '2 shapes in 2 classes', '1 shape')
    """
    shapes = f"{p} shape{'s' if p != 1 else ''}"
    return shapes if n_classes <= 1 else f"{shapes} in {n_classes} classes"


def _overview_inputs(D: ArrayLike, names: Sequence[object], labels: Sequence[object],
                     Y: ArrayLike | None, random_state: int | None
                     ) -> tuple[np.ndarray, list[Any], ArrayLike]:
    """The checked distance matrix, the labels as text and the MDS coordinates (computed when
    ``Y`` is None) of :func:`plot_overview` and :func:`overview_html`."""
    from ..compare import mds_embedding

    A = check_square(D, "D")
    p = len(A)
    check_entries("names", names, p, of="D", unit="rows")
    labels = [str(x) for x in check_entries("labels", labels, p, of="D", unit="rows")]
    if Y is None:
        Y = mds_embedding(A, random_state=random_state)
    return A, labels, Y


def _compared(descriptor: Descriptor | None) -> str:
    """What was compared, in words: the descriptor's label."""
    from ..descriptors import Descriptor

    if descriptor is None:
        return "the descriptors"
    if not isinstance(descriptor, Descriptor):
        raise TypeError("descriptor must be a cshape.Descriptor (its label goes in the title), "
                        f"got {type(descriptor).__name__}")
    return descriptor.label


def plot_overview(D: ArrayLike, names: Sequence[object], labels: Sequence[object], *,
                  Y: ArrayLike | None = None, descriptor: Descriptor | None = None,
                  title: str | None = None, left_out: Sequence[tuple[str, str]] = (),
                  random_state: int | None = 0, table_rows: int = OVERVIEW_TABLE_ROWS
                  ) -> Figure:
    """The overview of a described collection on one page: MDS, distance matrix, classes.

    Parameters
    ----------
    D : array_like, shape (p, p)
        Distances (:func:`cshape.batch.table.collection_distances`).
    names, labels : sequence of str, length p
        Name and class of each shape.
    Y : array_like, shape (p, 2), optional
        MDS coordinates; computed from ``D`` when not given.
    descriptor : Descriptor, optional
        What was compared; its :attr:`~cshape.Descriptor.label` goes in the title.
    title : str, optional
        First line of the title (e.g. the table's file name).
    left_out : sequence of (str, str)
        Shapes that could not be described, named under the title.
    random_state : int, default=0
        Of :func:`cshape.mds_embedding`.
    table_rows : int, default=OVERVIEW_TABLE_ROWS
        Classes listed (the largest first), the rest counted.

    Returns
    -------
    matplotlib.figure.Figure
        A new figure (not registered with pyplot).
    """
    from matplotlib.figure import Figure

    A, labels, Y = _overview_inputs(D, names, labels, Y, random_state)
    what = _compared(descriptor)
    p = len(A)
    rows = sorted(class_summary(A, labels), key=lambda r: (-r["n"], r["label"]))
    n_classes = len(rows)
    shown = rows[:table_rows] if n_classes > 1 else []  # one class: nothing to tabulate
    # many shapes (the matrix names them up to MATRIX_MAX_NAMES): a larger figure
    wide, high = (12.0, 5.2) if p <= 40 else (15.0, 8.0)
    table_h = 0.22 * (len(shown) + 2) + 0.3 if shown else 0.0
    fig = Figure(figsize=(wide, high + table_h), layout="constrained")
    if shown:
        top, bottom = fig.subfigures(2, 1,  # type: ignore[misc]  # two: an array of them
                                     height_ratios=[high, table_h])
    else:
        top, bottom = fig, None
    ax1, ax2 = top.subplots(1, 2)
    order = _class_order(labels)
    out = mds_layout(Y)["outliers"]
    vmax = colour_limit(A, out)
    plot_distance_matrix(A[np.ix_(order, order)], ax=ax2, names=[names[i] for i in order],
                         labels=[labels[i] for i in order], scale=False, vmax=vmax,
                         title=("distances, by class" if n_classes > 1 else "distances") + (
                             " (colours saturate at the outliers)" if out.any() else ""))
    head = f"{title}: " if title else ""
    sup = f"{head}{collection_title(p, n_classes)}, compared by {what}"
    if left_out:
        sup += (f"\nleft out ({len(left_out)}, cannot be described): "
                + ", ".join(n for n, _ in left_out[:8]) + (" ..." if len(left_out) > 8 else ""))
    fig.suptitle(sup, fontsize="medium")
    if bottom is not None:
        ax3 = bottom.subplots()
        ax3.set_axis_off()
        cells = [[short_label(r["label"], 24), str(r["n"]), _fmt(r["within"]),
                  short_label(r["nearest"], 24) or "-", _fmt(r["gap"]),
                  _fmt(100 * r["nn_same"], ".0f")] for r in shown]
        if len(rows) > len(shown):
            rest = rows[len(shown):]
            cells.append([f"... {len(rest)} more classes", str(sum(r["n"] for r in rest)),
                          "", "", "", ""])
        tab = ax3.table(cellText=cells, loc="upper center", cellLoc="left",
                        colLabels=["class", "shapes", "median distance within",
                                   "nearest other class", "its distance",
                                   "nearest neighbour in class (%)"])
        tab.auto_set_font_size(False)
        tab.set_fontsize(8)
        tab.auto_set_column_width(list(range(6)))
    # the MDS last: its names are placed in the final layout
    plot_mds(Y, names, labels if n_classes > 1 else None, ax=ax1, legend="outside",
             title="MDS (Euclidean distances of the descriptors)")
    return fig


def _matrix_figure(A: np.ndarray, names: Sequence[object], labels: Sequence[str],
                   descriptor: str, vmax: float | None = None) -> go.Figure:
    import plotly.graph_objects as go

    p = len(A)
    order = _class_order(labels)
    if p <= HTML_MATRIX_MAX:
        z = A[np.ix_(order, order)]
        ticks = [str(names[i]) for i in order]
        hover = "%{y}<br>%{x}<br>distance %{z:.4g}<extra></extra>"
        what = "distance between every two shapes, ordered by class"
    else:  # one cell per pair of classes: the median distance
        codes = check_labels(labels, p)
        first: dict[int, int] = {}
        for i, c in enumerate(codes):
            first.setdefault(int(c), i)
        ticks = [str(labels[i]) for i in first.values()]
        cls = list(first)
        z = np.array([[np.median(A[np.ix_(codes == a, codes == b)]) for b in cls]
                      for a in cls])
        hover = "%{y}<br>%{x}<br>median distance %{z:.4g}<extra></extra>"
        what = (f"median distance between every two classes ({p} shapes are more than "
                f"{HTML_MATRIX_MAX}, the shape-by-shape matrix would be too large)")
    font = 11 if len(ticks) <= 40 else 8
    fig = go.Figure(go.Heatmap(z=z, x=ticks, y=ticks, colorscale="Jet", hovertemplate=hover,
                               zmin=0.0, zmax=vmax,
                               colorbar={"title": {"text": "distance"}}))
    fig.update_layout(title={"text": html.escape(f"{what}; {descriptor}"), "x": 0.5},
                      height=700, template="plotly_white",
                      xaxis={"showticklabels": len(ticks) <= MATRIX_MAX_NAMES,
                             "constrain": "domain", "tickfont": {"size": font},
                             "dtick": 1, "automargin": True},
                      yaxis={"autorange": "reversed", "scaleanchor": "x", "dtick": 1,
                             "showticklabels": len(ticks) <= MATRIX_MAX_NAMES,
                             "tickfont": {"size": font}, "automargin": True},
                      margin={"l": 60, "r": 20, "t": 60, "b": 40})
    return fig


_STYLE = """body{font-family:system-ui,sans-serif;margin:1.5em auto;max-width:1100px;color:#222}
h1{font-size:1.4em}h2{font-size:1.15em;margin-top:1.6em}
table{border-collapse:collapse;font-size:.9em}td,th{padding:.25em .7em;border-bottom:1px solid #ddd}
th{text-align:left;background:#f4f4f4}td.n{text-align:right}.note{color:#555}"""


def overview_html(D: ArrayLike, names: Sequence[object], labels: Sequence[object], *,
                  Y: ArrayLike | None = None, descriptor: Descriptor | None = None,
                  title: str | None = None, left_out: Sequence[tuple[str, str]] = (),
                  k: int = 3, random_state: int | None = 0) -> str:
    """The overview of a described collection as one offline HTML page.

    An interactive MDS (:func:`interactive_mds`: names, classes and nearest neighbours on
    hover), the distance matrix (hover: the two shapes and their distance; beyond
    :data:`HTML_MATRIX_MAX` shapes the class-by-class medians) and a table of the classes
    (:func:`class_summary`).  plotly.js is embedded once; the page asks the network for
    nothing.

    Parameters
    ----------
    D : array_like, shape (p, p)
        Distances (:func:`cshape.batch.collection_distances`).
    names, labels : sequence of str, length p
        Name and class of each shape.
    Y : array_like, shape (p, 2), optional
        MDS coordinates; computed from ``D`` when not given.
    descriptor : Descriptor, optional
        What was compared; its :attr:`~cshape.Descriptor.label` goes in the title.
    title : str, optional
        First line of the title (e.g. the table's file name).
    left_out : sequence of (str, str)
        Shapes that could not be described, named under the title.
    k : int, default=3
        Nearest neighbours listed on hover.
    random_state : int, default=0
        Of :func:`cshape.mds_embedding`.

    Returns
    -------
    str
        The whole HTML page.
    """
    A, labels, Y = _overview_inputs(D, names, labels, Y, random_state)
    what = _compared(descriptor)
    p = len(A)
    rows = class_summary(A, labels)
    head = f"{title}: " if title else ""
    mds = interactive_mds(Y, names, labels, D=A, k=k, outliers="auto",
                          title=f"MDS of {p} shapes by {what}")
    n_out = int(mds_layout(Y)["outliers"].sum())
    parts = [
        "<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
        f"<title>{html.escape(head + 'overview')}</title><style>{_STYLE}</style></head><body>",
        f"<h1>{html.escape(head)}{collection_title(p, len(rows))}</h1>",
        f"<p>Compared by <b>{html.escape(what)}</b>, Euclidean distance. "
        "Hover a point for its name, class and nearest shapes.</p>",
    ]
    if left_out:
        items = "".join(f"<li>{html.escape(n)}: {html.escape(w)}</li>" for n, w in left_out)
        parts.append(f"<p class='note'>Left out ({len(left_out)}: they cannot be described by "
                     f"{html.escape(what)}):</p><ul class='note'>{items}</ul>")
    parts += ["<h2>MDS</h2>"]
    if n_out:
        parts.append(f"<p class='note'>{n_out} outlier{'s' if n_out > 1 else ''} (median "
                     "distance more than 5\u00d7 the typical one) drawn as arrows on the "
                     "border, pointing their way; the rest is drawn at its own scale.</p>")
    parts += [figure_html(mds, full_html=False, include_plotlyjs=True),
              "<h2>Distance matrix</h2>",
              figure_html(_matrix_figure(A, names, labels, what,
                                         colour_limit(A, mds_layout(Y)["outliers"])),
                          full_html=False,
                          include_plotlyjs=False),
              ]
    if len(rows) > 1:  # one class: nothing to tabulate
        parts += ["<h2>Classes</h2>",
                  "<table><tr><th>class</th><th>shapes</th><th>median distance within</th>"
                  "<th>nearest other class</th><th>its distance</th>"
                  "<th>nearest neighbour in class (%)</th></tr>"]
    for r in sorted(rows, key=lambda r: (-r["n"], r["label"])) if len(rows) > 1 else []:
        parts.append(
            f"<tr><td>{html.escape(r['label'])}</td><td class='n'>{r['n']}</td>"
            f"<td class='n'>{_fmt(r['within'])}</td><td>{html.escape(r['nearest']) or '-'}</td>"
            f"<td class='n'>{_fmt(r['gap'])}</td>"
            f"<td class='n'>{_fmt(100 * r['nn_same'], '.0f')}</td></tr>")
    parts += ["</table>" if len(rows) > 1 else "", "</body></html>"]
    return "\n".join(parts)


# =========================================================================== files
#: File types :func:`save_figure` writes: matplotlib figures and plotly figures.
IMAGE_SUFFIXES = (".png", ".svg", ".pdf")
HTML_SUFFIXES = (".html", ".htm")


def save_figure(fig: Figure | go.Figure | str, path: str | os.PathLike[str], *, dpi: float = 150
                ) -> Path:
    """Write a figure atomically (never a half-written file).

    A matplotlib figure as ``.png``, ``.svg`` or ``.pdf``; a plotly figure or an HTML
    string as ``.html`` (offline, plotly.js embedded).

    Parameters
    ----------
    fig : matplotlib.figure.Figure, plotly.graph_objects.Figure or str
        The figure, or a page of HTML.
    path : str or os.PathLike
        The file to write; its suffix chooses the format.
    dpi : float, default=150
        Dots per inch of a matplotlib figure.

    Returns
    -------
    pathlib.Path
        The file written.
    """
    path = Path(os.fspath(path))
    suffix = path.suffix.lower()
    if isinstance(fig, str) or hasattr(fig, "to_html"):
        if suffix not in HTML_SUFFIXES:
            raise ValueError(f"an interactive figure is written as .html, got {str(path)!r}")
        text = fig if isinstance(fig, str) else figure_html(fig)
        return atomic_write(path, lambda f: f.write(text), binary=False)
    if suffix not in IMAGE_SUFFIXES:
        raise ValueError(f"a matplotlib figure is written as {', '.join(IMAGE_SUFFIXES)}, "
                         f"got {str(path)!r}")
    return atomic_write(path, lambda f: fig.savefig(f, format=suffix[1:], dpi=dpi))
