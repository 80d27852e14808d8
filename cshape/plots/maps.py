"""Pictures of maps between shapes (:mod:`cshape.maps`): colours carried across, the matrix C.

* :func:`map_colours`         - the colours of a map: a field on the source and its pull-back
                                ``values[p2p]`` on the target, on one colour range;
* :func:`plot_map`            - the source and the target side by side (matplotlib), the target
                                coloured through the map, matched landmarks as marked points of
                                one colour per pair;
* :func:`plot_functional_map` - the functional map ``C`` (``N_T x N_S``) as an image on a
                                diverging colour map centred on 0;
* :func:`diagonal_share`      - the share of ``C``'s energy near its diagonal (near 1 for
                                near-isometric shapes, whose eigenfunctions correspond in order);
* :func:`view_map`            - the interactive 3-D counterpart of :func:`plot_map` (plotly,
                                offline in exported HTML like :mod:`cshape.plots.viewer`).

The convention is :func:`cshape.point_map`'s: ``p2p[y]`` is the source vertex matched to the
target vertex ``y``, so a field ``f`` on the source reads ``f[p2p]`` on the target (the
pull-back), and a wrong match shows as a colour out of place.  Landmarks are pairs
``(source vertex, target vertex)``, shape ``(L, 2)``, as the ``landmarks=`` of
:func:`cshape.point_map`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._checks import check_choice, check_int, check_landmarks, check_real
from ..mesh import Mesh, MeshLike, as_mesh
from .figures import _axes, new_figure, plot_mesh
from .viewer import _upright, view_meshes

if TYPE_CHECKING:
    import plotly.graph_objects as go
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: Colour map of the carried field (a smooth ramp whose colours are all told apart).
FIELD_CMAP = "turbo"
#: Qualitative colour map of the landmark pairs (pair ``j`` gets colour ``j mod 10``).
LANDMARK_CMAP = "tab10"
#: Diverging colour map of ``C`` (blue < 0 < red; the sign of an eigenfunction is arbitrary).
MAP_CMAP = "RdBu_r"
_VERTICAL = ("z", "y", "x")


# ------------------------------------------------------------------------------ checks
def _mesh(name: str, mesh: Any) -> Mesh:
    try:
        return as_mesh(mesh)
    except (TypeError, ValueError) as err:
        raise type(err)(f"{name}: {err}") from None


def _p2p(p2p: object, n_source: int, n_target: int, unmatched: bool = False
         ) -> NDArray[np.int64]:
    """``p2p`` checked: one source vertex per target vertex (or -1 where ``unmatched``)."""
    p = np.asarray(p2p)
    if p.ndim != 1 or p.dtype.kind not in "iu":
        raise TypeError(f"p2p must be a 1-D integer array (a source vertex per target vertex, "
                        f"cshape.point_map(source, target)), got {p.dtype} of shape {p.shape}")
    if len(p) != n_target:
        raise ValueError(f"p2p has {len(p)} entries but the target has {n_target} vertices; "
                         "pass cshape.point_map(source, target), source first")
    low = -1 if unmatched else 0
    if p.size and (p.min() < low or p.max() >= n_source):
        bad = int(p.min() if p.min() < low else p.max())
        raise ValueError(f"p2p holds {bad}, outside [{low}, {n_source - 1}] (the source's "
                         f"vertices{', -1 for unmatched' if unmatched else ''}); pass "
                         "cshape.point_map(source, target), source first")
    return p.astype(np.int64)


def _values(values: ArrayLike | None, source: Mesh) -> NDArray[np.float64]:
    if values is None:
        # the position along the source's longest axis: a ramp from one end to the other
        X = source.vertices - source.vertices.mean(axis=0)
        axis = np.linalg.svd(X, full_matrices=False)[2][0]
        return X @ axis
    try:
        f = np.asarray(values, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"values must be an array of numbers, one per source vertex, got "
                        f"{type(values).__name__}") from None
    if f.ndim != 1 or len(f) != source.n_vertices:
        raise ValueError(f"values has shape {f.shape} but the source has {source.n_vertices} "
                         "vertices; pass one value per source vertex")
    if not np.all(np.isfinite(f)):
        raise ValueError("values holds NaN or inf; pass finite values on the source")
    return f


def _cmap(cmap: object) -> str:
    import matplotlib as mpl

    if not isinstance(cmap, str):
        raise TypeError(f"cmap must be a matplotlib colour map name such as 'turbo', got "
                        f"{type(cmap).__name__}")
    if cmap not in mpl.colormaps:
        raise ValueError(f"cmap must be a matplotlib colour map name such as 'turbo' or "
                         f"'RdBu_r' (see matplotlib.colormaps), got {cmap!r}")
    return cmap


def _titles(titles: Any) -> tuple[str, str]:
    if isinstance(titles, str) or not hasattr(titles, "__len__") or len(titles) != 2:
        raise TypeError(f"titles must be two strings (source, target), got {titles!r}")
    return str(titles[0]), str(titles[1])


# ------------------------------------------------------------------------------ pure parts
def map_colours(source: MeshLike, target: MeshLike, p2p: ArrayLike,
                values: ArrayLike | None = None
                ) -> tuple[NDArray[np.float64], NDArray[np.float64], tuple[float, float]]:
    """The field drawn on the source, its pull-back on the target and their common range.

    Parameters
    ----------
    source, target : Mesh or (vertices, faces)
        The two shapes.
    p2p : array_like of int, shape (n_T,)
        For each target vertex a source vertex (:func:`cshape.point_map`).
    values : array_like, shape (n_S,), optional
        The field on the source; default the position along the source's longest axis
        (its first principal direction), a ramp from one end to the other.

    Returns
    -------
    f_source : ndarray, shape (n_S,)
        The field on the source.
    f_target : ndarray, shape (n_T,)
        ``f_source[p2p]``: a target vertex takes the value of its match.
    limits : (float, float)
        The range of ``f_source``, the colour range of both shapes.
    """
    S, T = _mesh("source", source), _mesh("target", target)
    p = _p2p(p2p, S.n_vertices, T.n_vertices)
    f = _values(values, S)
    lo, hi = float(f.min()), float(f.max())
    if hi <= lo:
        hi = lo + 1.0
    return f, f[p], (lo, hi)


def diagonal_share(C: ArrayLike, band: int = 0) -> float:
    """The share of the squared entries of ``C`` within ``band`` of its diagonal.

    ``sum_{|i - j| <= band} C_ij^2 / sum_ij C_ij^2``.  Between near-isometric shapes the
    eigenfunctions correspond in order, up to sign and within groups of nearly equal
    eigenvalues, so ``C`` is nearly diagonal (a near-diagonal band); between different shapes,
    or for a map that is wrong, the energy spreads.

    Parameters
    ----------
    C : array_like, shape (N_T, N_S)
        A functional map (:func:`cshape.maps.functional_map`).
    band : int, default=0
        Half-width of the band (0: the diagonal only).

    Returns
    -------
    float
        In [0, 1].
    """
    C = _check_map(C)
    band = check_int("band", band, min=0)
    i, j = np.indices(C.shape)
    total = float(np.square(C).sum())
    if total == 0:
        raise ValueError("C is all zeros; pass a functional map (cshape.maps.functional_map)")
    return float(np.square(C[np.abs(i - j) <= band]).sum() / total)


def _check_map(C: ArrayLike) -> NDArray[np.float64]:
    try:
        C = np.asarray(C, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"C must be a 2-D array of numbers (N_T x N_S), got "
                        f"{type(C).__name__}") from None
    if C.ndim != 2 or 0 in C.shape:
        raise ValueError(f"C must be a non-empty 2-D array (N_T x N_S), got shape {C.shape}")
    if not np.all(np.isfinite(C)):
        raise ValueError("C holds NaN or inf; pass a finite functional map")
    return C


# ------------------------------------------------------------------------------ figures
def plot_map(source: MeshLike, target: MeshLike, p2p: ArrayLike, *,
             values: ArrayLike | None = None, landmarks: ArrayLike | None = None,
             titles: tuple[str, str] = ("source", "target"), cmap: str = FIELD_CMAP,
             elev: float = 20.0, azim: float = -60.0, vertical_axis: str = "z",
             marker_size: float = 40.0, figsize: tuple[float, float] = (8.0, 4.0)) -> Figure:
    """The source and the target side by side, a field on the source carried to the target.

    The source is coloured by ``values``, the target by ``values[p2p]`` (each target vertex
    takes the colour of its match), both on the source's colour range, so a wrong match is a
    colour out of place.  Landmark pairs are drawn on both shapes as marked points, pair ``j``
    in the ``j``-th colour of ``'tab10'`` on both.

    Parameters
    ----------
    source, target : Mesh or (vertices, faces)
        The two shapes, the source on the left.
    p2p : array_like of int, shape (n_T,)
        For each target vertex a source vertex (:func:`cshape.point_map`).
    values : array_like, shape (n_S,), optional
        The field on the source; default the position along its longest axis (a ramp).
        The x coordinate shows a left-right mirror: ``values=source.vertices[:, 0]``.
    landmarks : array_like of int, shape (L, 2), optional
        Corresponding vertices ``(source vertex, target vertex)``.
    titles : (str, str), default=('source', 'target')
        Titles of the two axes.
    cmap : str, default='turbo'
        A matplotlib colour map.
    elev, azim : float
        View angles in degrees, the same for both shapes.
    vertical_axis : {'z', 'y', 'x'}, default='z'
    marker_size : float, default=40.0
        Area of the landmark markers in points^2.
    figsize : (float, float), default=(8.0, 4.0)
        Size of a new figure, in inches.

    Returns
    -------
    matplotlib.figure.Figure
        Two 3-D axes (source, target); the meshes are their first collection, the landmarks
        (when given) their second.
    """
    import matplotlib as mpl

    S, T = _mesh("source", source), _mesh("target", target)
    fS, fT, limits = map_colours(S, T, p2p, values)
    lm = check_landmarks(landmarks, S.n_vertices, T.n_vertices)
    ts = _titles(titles)
    cmap = _cmap(cmap)
    vertical_axis = check_choice("vertical_axis", vertical_axis, _VERTICAL)
    elev = check_real("elev", elev)
    azim = check_real("azim", azim)
    marker_size = check_real("marker_size", marker_size, min=0)
    fig = new_figure(figsize)
    axes = fig.subplots(1, 2, subplot_kw=dict(projection="3d"))
    for ax, mesh, f, title in zip(axes, (S, T), (fS, fT), ts, strict=True):
        plot_mesh(mesh, f, ax=ax, cmap=cmap, elev=elev, azim=azim, edges=False,
                  symmetric=False, limits=limits, title=title, vertical_axis=vertical_axis)
    if lm is not None:
        colours = mpl.colormaps[LANDMARK_CMAP](np.arange(len(lm)) % 10)
        for ax, mesh, col in zip(axes, (S, T), (0, 1), strict=True):
            P = mesh.vertices[lm[:, col]]
            ax.scatter(P[:, 0], P[:, 1], P[:, 2], c=colours, s=marker_size, marker="o",
                       edgecolors="black", linewidths=0.8, depthshade=False)
    sm = mpl.cm.ScalarMappable(norm=mpl.colors.Normalize(*limits), cmap=cmap)
    fig.colorbar(sm, ax=list(axes), shrink=0.6, label="value on the source")
    return fig


def plot_functional_map(C: ArrayLike, *, ax: Axes | None = None, cmap: str = MAP_CMAP,
                        title: str | None = "functional map C", colorbar: bool = True,
                        figsize: tuple[float, float] = (4.4, 4.0)) -> Figure:
    """Draw the functional map ``C`` as an image.

    Row ``i`` is a target basis function, column ``j`` a source basis function.

    The colour range is centred on 0 (``[-max|C|, max|C|]``): between near-isometric shapes
    the image is a near-diagonal band of values near ``+-1`` (:func:`diagonal_share`).

    Parameters
    ----------
    C : array_like, shape (N_T, N_S)
        From :func:`cshape.maps.functional_map`, :func:`cshape.maps.zoomout` or
        ``cshape.point_map(..., return_map=True)``.
    ax : matplotlib.axes.Axes, optional
        Draw here; by default a new Figure is made.
    cmap : str, default='RdBu_r'
        A matplotlib colour map (a diverging one: the sign matters).
    title : str or None, default='functional map C'
        Title of the axes.
    colorbar : bool, default=True
        Draw a colour bar.
    figsize : (float, float), default=(4.4, 4.0)
        Size of a new figure, in inches.

    Returns
    -------
    matplotlib.figure.Figure
        The image is the axes' first image, with ``C`` as its array.
    """
    C = _check_map(C)
    cmap = _cmap(cmap)
    fig, ax = _axes(ax, figsize)
    m = float(np.abs(C).max()) or 1.0
    im = ax.imshow(C, cmap=cmap, vmin=-m, vmax=m, interpolation="nearest", origin="upper")
    from matplotlib.ticker import MaxNLocator

    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.yaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_xlabel("source eigenfunction j")
    ax.set_ylabel("target eigenfunction i")
    if title:
        ax.set_title(title, fontsize="medium")
    if colorbar:
        fig.colorbar(im, ax=ax, shrink=0.8, label="C[i, j]")
    return fig


def view_map(source: MeshLike, target: MeshLike, p2p: ArrayLike, *,
             values: ArrayLike | None = None, landmarks: ArrayLike | None = None,
             titles: tuple[str, str] = ("source", "target"), cmap: str = "Turbo",
             vertical_axis: str = "z", marker_size: int = 6, height: int = 420) -> go.Figure:
    """The interactive 3-D counterpart of :func:`plot_map`: two rotatable shapes (plotly).

    The source coloured by ``values``, the target by the same colours carried through the
    map (one colour range: matched points share a colour, a wrong match shows as a colour
    out of place), with the landmark pairs as markers of one colour per pair.  Any point
    map: :func:`cshape.point_map`'s, or the nearest signatures of
    :func:`cshape.signatures.match_points` (``match_points(sig_target, sig_source)``, target
    first).  Offline: the figure is JSON drawn by plotly.js, which the exported lesson pages
    embed.

    Parameters
    ----------
    source, target : Mesh or (vertices, faces)
        The two shapes, the source on the left.
    p2p : array_like of int, shape (n_T,)
        For each target vertex a source vertex (:func:`cshape.point_map`), or -1 where it
        has none (``match_points(..., mutual=True)``): such vertices take the mean colour,
        and the target's title says how many there are.
    values : array_like, shape (n_S,), optional
        See :func:`plot_map`.
    landmarks : array_like of int, shape (L, 2), optional
        Corresponding vertices ``(source vertex, target vertex)``.
    titles : (str, str), default=('source', 'target')
        Titles of the two views.
    cmap : str, default='Turbo'
        A plotly colour scale.
    vertical_axis : {'z', 'y', 'x'}, default='z'
    marker_size : int, default=6
        Landmark marker diameter in pixels.
    height : int, default=420
        Height of the figure, in pixels.

    Returns
    -------
    plotly.graph_objects.Figure
        Never displayed here; the landmark traces are named ``'landmarks'``.
    """
    import plotly.graph_objects as go

    S, T = _mesh("source", source), _mesh("target", target)
    p = _p2p(p2p, S.n_vertices, T.n_vertices, unmatched=True)
    fS = _values(values, S)
    lm = check_landmarks(landmarks, S.n_vertices, T.n_vertices)
    ta, tb = _titles(titles)
    marker_size = check_int("marker_size", marker_size, min=1)
    vertical_axis = check_choice("vertical_axis", vertical_axis, _VERTICAL)
    # unmatched vertices cannot be drawn without a colour: the mean one, counted in the title
    fT = np.where(p >= 0, fS[np.maximum(p, 0)], fS.mean())
    unmatched = int((p < 0).sum())
    if unmatched:
        tb = f"{tb} ({unmatched} unmatched)"
    fig = view_meshes({ta: S, tb: T}, {ta: fS, tb: fT}, cmap=cmap, symmetric=False,
                      edges=False, vertical_axis=vertical_axis, height=height)
    # one colour range for both panels: the same value, the same colour
    lo, hi = float(fS.min()), float(fS.max())
    fig.update_traces(cmin=lo, cmax=hi, showscale=False, selector=dict(type="mesh3d"))
    if lm is not None:
        import matplotlib as mpl

        rgb = mpl.colormaps[LANDMARK_CMAP](np.arange(len(lm)) % 10)[:, :3]
        colours = [f"rgb({r:.0f}, {g:.0f}, {b:.0f})" for r, g, b in 255 * rgb]
        for c, (mesh, scene) in enumerate(((S, "scene"), (T, "scene2"))):
            P = _upright(mesh.vertices[lm[:, c]], vertical_axis)
            fig.add_trace(go.Scatter3d(
                x=P[:, 0], y=P[:, 1], z=P[:, 2], mode="markers", name="landmarks",
                marker=dict(size=marker_size, color=colours, line=dict(color="black", width=1)),
                text=[f"landmark {j}" for j in range(len(lm))], hoverinfo="text",
                showlegend=False, scene=scene))
    return fig
