"""Figures for the walkthrough notebooks and the M-sweep widget (matplotlib only).

* :func:`plot_mesh`              - a triangle mesh drawn with ``Poly3DCollection``, optionally
                                   coloured by a function on the vertices (an eigenfunction);
* :func:`plot_eigenfunctions`    - a grid of meshes coloured by eigenfunctions;
* :func:`plot_weyl`              - the paper's Fig. 1: raw Shape-DNAs, then area-normalised
                                   ones around the Weyl line ``4 pi i``;
* :func:`plot_shape_dna_stages`  - Fig. 2 (b)-(d): Shape-DNA, normalised, Weyl-subtracted (Eq. 8);
* :func:`plot_dft`               - Fig. 2 (e)-(f): shifted DFT magnitudes (Eq. 9), the cropped
                                   ``2M+1`` coefficients (Eq. 10) and the reconstruction;
* :func:`plot_reconstruction_error` - reconstruction error against ``M``;
* :func:`plot_convergence`       - eigenvalue error against mesh size on a log-log plot;
* :func:`plot_cshape_dna`        - cShape-DNA magnitudes of several models on one plot (Fig. 9);
* :func:`plot_matrices`          - a row of distance / difference images (Fig. 3, 6, 7);
* :func:`plot_m_sweep`           - the panels of the M-sweep widget (Section 3.2, Fig. 6).

The interactive 3-D views (plotly) live in :mod:`cshape.plots.viewer` and are re-exported here:
:func:`view_mesh`, :func:`view_meshes` and :func:`eigenfunction_explorer` (a slider over the
eigenfunctions).  :func:`plot_mesh` and :func:`plot_eigenfunctions` are their static
counterparts, for PDF export and print.

Every function returns a :class:`matplotlib.figure.Figure` made without pyplot (nothing is
registered globally, nothing is shown); in a notebook the figure displays as a cell's last
expression.  Figures never call ``show``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .._checks import check_int
from ..descriptors import inverse_compact_shape_dna, normalize, weyl_subtract
from ..descriptors.formulas import FOUR_PI
from ..mesh import as_mesh

if TYPE_CHECKING:
    from collections.abc import Iterable, Sequence

    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from numpy.typing import ArrayLike

    from ..mesh import MeshLike

    _Size = tuple[float, float]  # a figure's (width, height) in inches


def new_figure(figsize: _Size = (6.0, 4.0), **kwargs: Any) -> Figure:
    """Make a matplotlib Figure not registered with pyplot (so it is garbage collected).

    Parameters
    ----------
    figsize : (float, float), default=(6.0, 4.0)
        Size of the figure, in inches.
    **kwargs
        Passed to :class:`matplotlib.figure.Figure`.

    Returns
    -------
    matplotlib.figure.Figure
        The new figure.
    """
    from matplotlib.figure import Figure

    return Figure(figsize=figsize, layout="constrained", **kwargs)


def _axes(ax: Any, figsize: _Size, projection: str | None = None) -> tuple[Figure, Any]:
    if ax is not None:
        return ax.figure, ax
    fig = new_figure(figsize)
    return fig, fig.add_subplot(projection=projection)


# ------------------------------------------------------------------------------ meshes
#: Zoom of the 3-D axes of :func:`plot_mesh`: matplotlib's default leaves the mesh in the
#: middle third of its panel, this one lets it fill the panel in any direction of view.
_ZOOM = 1.3


def plot_mesh(mesh: MeshLike, f: ArrayLike | None = None, *, ax: Any = None, cmap: str = "RdBu_r",
              elev: float = 20.0, azim: float = -60.0, edges: bool | None = None,
              shade: bool = True, symmetric: bool | None = None, colorbar: bool = False,
              title: str | None = None, figsize: _Size = (4.0, 4.0),
              vertical_axis: str = "z", limits: tuple[float, float] | None = None) -> Figure:
    """Draw a triangle mesh in 3-D, optionally coloured by a function on its vertices.

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        The mesh to draw.
    f : array_like, shape (n,), optional
        Values on the vertices (an eigenfunction ``phi[:, i]``, a displacement, ...); each
        triangle is coloured by the mean of its three values.  Without ``f`` the mesh is
        drawn in a uniform grey.
    ax : mpl_toolkits.mplot3d.Axes3D, optional
        Draw here; by default a new Figure is made.
    cmap : str, default='RdBu_r'
        Matplotlib colour map.
    elev, azim : float
        View angles in degrees.
    edges : bool, optional
        Draw the triangle edges; default: only for meshes with at most 2000 triangles.
    shade : bool, default=True
        Darken triangles facing away from the light (Lambert shading), which shows the
        shape; the colours of ``f`` keep their hue.
    symmetric : bool, optional
        Centre the colour range on 0 (right for eigenfunctions, whose sign is arbitrary);
        default: True when ``f`` takes both signs.
    colorbar : bool, default=False
        Draw a colour bar.
    title : str, optional
        Title of the axes.
    figsize : (float, float), default=(4.0, 4.0)
        Size of a new figure, in inches.
    vertical_axis : {'z', 'y', 'x'}, default='z'
        The axis drawn upwards (``'y'`` for the many models stored y-up, e.g. Spot).
    limits : (float, float), optional
        The values drawn at the two ends of the colour map (several meshes on one colour
        scale); default: the range of ``f`` (centred on 0 when ``symmetric``).

    Returns
    -------
    matplotlib.figure.Figure
        The new figure, or the figure (or subfigure) holding ``ax``.
    """
    import matplotlib as mpl
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    mesh = as_mesh(mesh)
    V, F = mesh.vertices, mesh.faces
    if f is not None:
        f = np.asarray(f, dtype=np.float64).reshape(-1)
        if len(f) != mesh.n_vertices:
            raise ValueError(
                f"f has {len(f)} values but the mesh has {mesh.n_vertices} vertices; pass one "
                "value per vertex (e.g. cshape.eigenbasis(mesh, N).phi[:, i] of the same mesh)"
            )
    fig, ax = _axes(ax, figsize, projection="3d")
    tris = V[F]
    if f is None:
        rgba = np.tile(np.array([0.75, 0.78, 0.82, 1.0]), (len(F), 1))
        norm = None
    else:
        vals = f[F].mean(axis=1)
        if limits is not None:
            lo, hi = (float(x) for x in limits)
        else:
            lo, hi = float(f.min()), float(f.max())
            if symmetric is None:
                symmetric = lo < 0 < hi
            if symmetric:
                m = max(abs(lo), abs(hi)) or 1.0
                lo, hi = -m, m
        if hi <= lo:
            hi = lo + 1.0
        norm = mpl.colors.Normalize(lo, hi)
        rgba = mpl.colormaps[cmap](norm(vals))
    if shade:
        n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
        n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
        light = np.array([0.4, -0.5, 0.77])
        light /= np.linalg.norm(light)
        k = 0.55 + 0.45 * np.abs(n @ light)
        rgba = rgba.copy()
        rgba[:, :3] *= k[:, None]
    if edges is None:
        edges = len(F) <= 2000
    coll = Poly3DCollection(tris, facecolors=rgba, edgecolors=(0, 0, 0, 0.25) if edges else "none",
                            linewidths=0.3 if edges else 0.0)
    ax.add_collection3d(coll)
    # a cube around the mesh (equal scales: nothing is stretched), seen from close up: the
    # bounding cube's corners may leave the picture, the mesh does not
    lo3, hi3 = V.min(axis=0), V.max(axis=0)
    ctr, half = (lo3 + hi3) / 2, max(float((hi3 - lo3).max()) / 2, 1e-12)
    ax.set_xlim(ctr[0] - half, ctr[0] + half)
    ax.set_ylim(ctr[1] - half, ctr[1] + half)
    ax.set_zlim(ctr[2] - half, ctr[2] + half)
    ax.set_box_aspect((1, 1, 1), zoom=_ZOOM)
    ax.view_init(elev=elev, azim=azim, vertical_axis=vertical_axis)
    ax.set_axis_off()
    if title:
        ax.set_title(title, fontsize="medium")
    if colorbar and norm is not None:
        sm = mpl.cm.ScalarMappable(norm=norm, cmap=cmap)
        fig.colorbar(sm, ax=ax, shrink=0.6)
    return fig


def plot_eigenfunctions(mesh: MeshLike, phi: ArrayLike, indices: Iterable[int] | None = None,
                        lam: np.ndarray | Sequence[float] | None = None, *, ncols: int = 4,
                        cmap: str = "RdBu_r", elev: float = 20.0, azim: float = -60.0,
                        size: float = 2.6, vertical_axis: str = "z") -> Figure:
    """A grid of copies of the mesh, each coloured by one eigenfunction.

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        The mesh to draw.
    phi : array_like, shape (n, k)
        Eigenfunctions on the vertices (``cshape.eigenbasis(mesh, N).phi``).
    indices : sequence of int, optional
        Which columns to show (default: the first ``min(k, 8)``).
    lam : array_like, shape (k,), optional
        Eigenvalues, written in the titles.
    ncols : int, default=4
        Copies per row.
    cmap : str, default='RdBu_r'
        Matplotlib colour map.
    elev, azim : float
        View angles in degrees.
    size : float, default=2.6
        Size of one panel in inches.
    vertical_axis : {'z', 'y', 'x'}, default='z'

    Returns
    -------
    matplotlib.figure.Figure
        A new figure (not registered with pyplot).
    """
    mesh = as_mesh(mesh)
    phi = np.asarray(phi, dtype=np.float64)
    if phi.ndim != 2 or phi.shape[0] != mesh.n_vertices:
        raise ValueError(
            f"phi must have shape (n_vertices, k) = ({mesh.n_vertices}, k), got {phi.shape}; "
            "use the phi of cshape.eigenbasis(mesh, N) for this mesh"
        )
    if indices is None:
        indices = range(min(phi.shape[1], 8))
    indices = [int(i) for i in indices]
    ncols = max(1, min(int(ncols), len(indices)))
    nrows = -(-len(indices) // ncols)
    fig = new_figure((size * ncols, size * nrows))
    for k, i in enumerate(indices):
        ax = fig.add_subplot(nrows, ncols, k + 1, projection="3d")
        title = f"phi_{i}" + (f", lam = {float(lam[i]):.3g}" if lam is not None else "")
        plot_mesh(mesh, phi[:, i], ax=ax, cmap=cmap, elev=elev, azim=azim, title=title,
                  edges=False, vertical_axis=vertical_axis)
    return fig


# ------------------------------------------------------------------------------ spectra
def _spectra(spectra: dict[str, ArrayLike]) -> list[tuple[str, np.ndarray]]:
    if isinstance(spectra, dict):
        items = list(spectra.items())
    else:
        raise TypeError(
            "spectra must be a dict {name: lam} of 1-D eigenvalue arrays, got "
            f"{type(spectra).__name__}"
        )
    if not items:
        raise ValueError("spectra is empty; pass at least one {name: lam}")
    return [(str(k), np.asarray(v, dtype=np.float64).reshape(-1)) for k, v in items]


def plot_weyl(spectra: dict[str, ArrayLike], areas: dict[str, float], *,
              figsize: _Size = (10.0, 4.0)) -> Figure:
    """The paper's Fig. 1: raw Shape-DNAs (a), then multiplied by the area (b).

    Parameters
    ----------
    spectra : dict of str to array_like, shape (N,)
        Shape-DNA of each model (``cshape.shape_dna``).
    areas : dict of str to float
        Surface area of each model (same keys).
    figsize : (float, float)
        Size of a new figure, in inches.

    Returns
    -------
    matplotlib.figure.Figure
        Left: ``lam_i`` against ``i``, each model along its own line.  Right: ``area * lam_i``,
        all models around the common Weyl line ``4 pi i`` (dashed).
    """
    from .layout import LABEL_WIDTH, short_label

    items = _spectra(spectra)
    missing = [k for k, _ in items if k not in areas]
    if missing:
        raise ValueError(f"areas has no entry for {missing}; pass one area per spectrum")
    fig = new_figure(figsize)
    ax1, ax2 = fig.subplots(1, 2)
    nmax = 0
    for name, lam in items:
        i = np.arange(len(lam))
        nmax = max(nmax, len(lam))
        label = short_label(name, 2 * LABEL_WIDTH)
        ax1.plot(i, lam, ".", ms=4, label=label)
        ax2.plot(i, normalize(lam, areas[name]), ".", ms=4, label=label)
    x = np.arange(nmax)
    ax2.plot(x, FOUR_PI * x, "k--", lw=1, label="Weyl line 4 pi i")
    ax1.set(xlabel="i", ylabel="lam_i", title="(a) Shape-DNA")
    ax2.set(xlabel="i", ylabel="area x lam_i", title="(b) area-normalised Shape-DNA")
    ax1.legend(fontsize="small")
    ax2.legend(fontsize="small")
    return fig


def plot_shape_dna_stages(lam: ArrayLike, area: float, *, name: str = "",
                          figsize: _Size = (11.0, 3.4)) -> Figure:
    """Fig. 2 (b)-(d): the Shape-DNA, its area normalisation, and Eq. (8)'s subtraction.

    Parameters
    ----------
    lam : array_like, shape (N,)
        Shape-DNA (raw eigenvalues, ascending).
    area : float
        Surface area (the area normalisation).
    name : str, optional
        Model name for the titles.
    figsize : (float, float)
        Size of a new figure, in inches.

    Returns
    -------
    matplotlib.figure.Figure
        A new figure (not registered with pyplot).
    """
    lam = np.asarray(lam, dtype=np.float64)
    lam_norm = normalize(lam, area)
    lam_prime = weyl_subtract(lam_norm)
    i = np.arange(len(lam))
    fig = new_figure(figsize)
    axs = fig.subplots(1, 3)
    axs[0].plot(i, lam, "r.", ms=4)
    axs[0].set(title=f"(b) Shape-DNA {name}".strip(), xlabel="i", ylabel="lam_i")
    axs[1].plot(i, lam_norm, "g.", ms=4, label="area x lam_i")
    axs[1].plot(i, FOUR_PI * i, "k--", lw=1, label="4 pi i")
    axs[1].set(title="(c) normalised", xlabel="i")
    axs[1].legend(fontsize="small")
    axs[2].plot(i, lam_prime, "b.-", ms=4, lw=0.6)
    axs[2].axhline(0, color="k", lw=0.6)
    axs[2].set(title="(d) minus the Weyl line (Eq. 8)", xlabel="i", ylabel="lam'_i")
    return fig


def plot_dft(lam: ArrayLike, area: float, M: int, *, N: int | None = None,
             figsize: _Size = (11.0, 3.4)) -> Figure:
    """Fig. 2 (e)-(f) and the reconstruction: what the ``2M+1`` coefficients keep.

    Parameters
    ----------
    lam : array_like, shape (>= N,)
        Shape-DNA (raw eigenvalues).
    area : float
        Surface area (the area normalisation).
    M : int
        Crop half-width.
    N : int, optional
        Shape-DNA length (default ``len(lam)``).
    figsize : (float, float)
        Size of a new figure, in inches.

    Returns
    -------
    matplotlib.figure.Figure
        Panels: Fig. 2 (e), ``|Lambda^shift|`` over the shifted index with the kept band
        shaded; Fig. 2 (f), the cropped magnitudes over the frequencies ``-M..M``, and the
        normalised Shape-DNA minus the Weyl line with its reconstruction from the ``2M+1``
        values.
    """
    from ..descriptors import compact_shape_dna

    lam = np.asarray(lam, dtype=np.float64)
    N = len(lam) if N is None else int(N)
    lam_prime = weyl_subtract(normalize(lam[:N], area))
    shifted = np.fft.fftshift(np.fft.fft(lam_prime))
    S = compact_shape_dna(lam[:N], M=M, N=N, area=area)
    rec = inverse_compact_shape_dna(S, N, add_weyl=False)
    c = N // 2
    fig = new_figure(figsize)
    axs = fig.subplots(1, 3)
    axs[0].semilogy(np.arange(N), np.abs(shifted) + 1e-300, ".-", ms=3, lw=0.6)
    axs[0].axvspan(c - M - 0.5, c + M + 0.5, color="orange", alpha=0.3, label=f"kept: 2M+1={2*M+1}")
    axs[0].set(title="(e) |DFT| shifted (Eq. 9)", xlabel="shifted index", ylabel="|Lambda|")
    axs[0].legend(fontsize="small")
    k = np.arange(-M, M + 1)
    axs[1].stem(k, np.abs(S), basefmt=" ")
    axs[1].set_yscale("log")
    axs[1].set(title=f"(f) cShape-DNA, M={M} (Eq. 10)", xlabel="frequency k", ylabel="|S_c|")
    i = np.arange(N)
    axs[2].plot(i, lam_prime, "b.", ms=4, label="lam' (Eq. 8)")
    axs[2].plot(i, rec, "r-", lw=1.2, label=f"from 2M+1={2*M+1} values")
    axs[2].set(title="reconstruction", xlabel="i")
    axs[2].legend(fontsize="small")
    return fig


def plot_reconstruction_error(Ms: ArrayLike, errors: ArrayLike, *,
                              labels: Sequence[str] | None = None, N: int | None = None,
                              ax: Axes | None = None, figsize: _Size = (5.0, 3.6)) -> Figure:
    """Reconstruction error against the crop half-width ``M``.

    Parameters
    ----------
    Ms : array_like, shape (k,)
        Crop half-widths ``M``.
    errors : array_like, shape (k,) or (p, k)
        One error curve, or one per model (rows).
    labels : sequence of str, optional
        A legend entry per row of ``errors``.
    N : int, optional
        Shape-DNA length, written in the title.
    ax : Axes, optional
        Draw here; by default a new Figure is made (not registered with pyplot).
    figsize : (float, float)
        Size of a new figure, in inches.

    Returns
    -------
    matplotlib.figure.Figure
        The new figure, or the figure (or subfigure) holding ``ax``.
    """
    Ms = np.asarray(Ms)
    E = np.atleast_2d(np.asarray(errors, dtype=np.float64))
    fig, ax = _axes(ax, figsize)
    for r, row in enumerate(E):
        ax.semilogy(Ms, row, "o-", ms=3, label=None if labels is None else str(labels[r]))
    ax.set(xlabel="M (descriptor size 2M+1)", ylabel="relative error",
           title="reconstruction error" + (f", N={N}" if N else ""))
    if labels is not None:
        ax.legend(fontsize="small")
    return fig


def plot_convergence(h: ArrayLike, errors: ArrayLike, *, labels: Sequence[str] | None = None,
                     order: float = 2, ax: Axes | None = None, figsize: _Size = (5.0, 3.8)
                     ) -> Figure:
    """Log-log plot of errors against the mesh size ``h`` with a reference slope.

    Parameters
    ----------
    h : array_like, shape (k,)
        Mesh sizes (e.g. mean edge lengths).
    errors : array_like, shape (k,) or (p, k)
        Errors (rows: several quantities, e.g. several eigenvalues).
    labels : sequence of str, optional
        A legend entry per row of ``errors``.
    order : float, default=2
        Slope of the dashed reference line ``C h^order``.
    ax : Axes, optional
        Draw here; by default a new Figure is made (not registered with pyplot).
    figsize : (float, float)
        Size of a new figure, in inches.

    Returns
    -------
    matplotlib.figure.Figure
        The new figure, or the figure (or subfigure) holding ``ax``.
    """
    h = np.asarray(h, dtype=np.float64)
    E = np.atleast_2d(np.asarray(errors, dtype=np.float64))
    fig, ax = _axes(ax, figsize)
    for r, row in enumerate(E):
        ax.loglog(h, row, "o-", label=None if labels is None else str(labels[r]))
    ref = E[:, 0].max() * (h / h[0]) ** order
    ax.loglog(h, ref, "k--", lw=1, label=f"slope {order}")
    ax.set(xlabel="mean edge length h", ylabel="error")
    # one plain label per mesh size (a log axis of less than a decade labels its minor
    # ticks, and they run into each other)
    from matplotlib.ticker import NullFormatter, NullLocator

    ax.xaxis.set_minor_locator(NullLocator())
    ax.xaxis.set_minor_formatter(NullFormatter())
    hs = np.unique(h)
    ax.set_xticks(hs, [f"{x:.2g}" for x in hs])
    ax.legend(fontsize="small")
    return fig


def plot_cshape_dna(descriptors: dict[str, ArrayLike], *, ax: Axes | None = None,
                    title: str = "cShape-DNA", figsize: _Size = (6.0, 3.6)) -> Figure:
    """Plot the magnitudes of the cShape-DNAs of several models on one plot (the paper's Fig. 9).

    Parameters
    ----------
    descriptors : dict of str to array_like of complex, shape (2M+1,)
        ``cshape.compact_shape_dna`` of each model.
    ax : Axes, optional
        Draw here; by default a new Figure is made (not registered with pyplot).
    title : str
        Title of the axes.
    figsize : (float, float)
        Size of a new figure, in inches.

    Returns
    -------
    matplotlib.figure.Figure
        The new figure, or the figure (or subfigure) holding ``ax``.
    """
    items = _spectra({k: np.abs(np.asarray(v)) for k, v in descriptors.items()})
    fig, ax = _axes(ax, figsize)
    for name, mag in items:
        M = (len(mag) - 1) // 2
        ax.semilogy(np.arange(-M, M + 1), mag, "o-", ms=3, lw=1, label=name)
    ax.set(xlabel="frequency k", ylabel="|S_c|", title=title)
    ax.legend(fontsize="small")
    return fig


def plot_matrices(matrices: Sequence[ArrayLike], titles: Sequence[str] | None = None, *,
                  scale: bool = False, vmax: float | None = None, cmap: str = "jet",
                  size: float = 3.0, colorbar: bool = True, names: Sequence[str] | None = None,
                  labels: Sequence[str] | None = None) -> Figure:
    """A row of matrix images: scaled distance matrices or difference matrices (Fig. 3, 6, 7).

    Parameters
    ----------
    matrices : sequence of array_like, shape (p, p)
        The matrices, one panel each.
    titles : sequence of str, optional
        A title per panel.
    scale : bool, default=False
        Show ``scale_255`` of each matrix (distance matrices); differences are shown as is.
    vmax : float, optional
        Common top of the colour range (default: 255 when scaled, else the largest value).
    cmap : str, default='jet'
        Matplotlib colour map.
    size : float, default=3.0
        Panel size in inches.
    colorbar : bool, default=True
        Draw a colour bar.
    names, labels : sequence of length p, optional
        Shape names and classes of the rows, for the ticks: one per shape (shortened) up to
        :data:`cshape.compare.MATRIX_MAX_NAMES` shapes, else one per class with lines
        between the classes (:func:`cshape.compare.matrix_ticks`).  No ticks without them.

    Returns
    -------
    matplotlib.figure.Figure
        A new figure (not registered with pyplot).
    """
    from ..compare import scale_255
    from .collection import matrix_ticks, plot_distance_matrix

    mats = [scale_255(m) if scale else np.asarray(m, dtype=np.float64) for m in matrices]
    if not mats:
        raise ValueError("matrices is empty; pass at least one (p, p) matrix")
    if vmax is None:
        vmax = 255.0 if scale else max(float(m.max()) for m in mats) or 1.0
    ticks = names is not None or labels is not None
    fig = new_figure((size * len(mats) + 0.8, size + (0.9 if ticks else 0.0)))
    axs = np.atleast_1d(fig.subplots(1, len(mats)))
    for k, (ax, m) in enumerate(zip(axs, mats, strict=True)):
        plot_distance_matrix(m, scale=False, ax=ax, cmap=cmap, vmax=vmax, colorbar=False,
                             title=None if titles is None else str(titles[k]))
    if colorbar:
        fig.colorbar(axs[-1].images[0], ax=list(axs), shrink=0.8)
    if ticks:  # last, in the final layout; the same ticks on every panel
        side = None
        for ax, m in zip(axs, mats, strict=True):
            side = matrix_ticks(ax, len(m), names, labels, side_pt=side)
    return fig


# ------------------------------------------------------------------------------ M sweep
# state is a widgets.SweepState, typed Any: widgets imports this module (no import circle)
def plot_m_sweep(state: Any, *, shape: int = 0, figsize: _Size = (12.0, 7.0)) -> Figure:
    """The panels of the M-sweep widget for one :class:`cshape.plots.widgets.SweepState`.

    Top row: the cropped DFT coefficients (Eq. 10) of one shape over its full shifted
    spectrum, the reconstruction of its Weyl-subtracted Shape-DNA from them, and the 2-D MDS
    of the cShape-DNAs (Fig. 4).  Bottom row: the scaled Shape-DNA distance matrix
    (Fig. 3a), the scaled cShape-DNA distance matrix (Fig. 6 a-d) and their absolute
    difference with its mean and standard deviation (Fig. 6 e-h).

    Parameters
    ----------
    state : cshape.plots.widgets.SweepState
        From :func:`cshape.plots.widgets.sweep_state`.
    shape : int, default=0
        Row of the shape whose coefficients and reconstruction are drawn.
    figsize : (float, float)
        Size of a new figure, in inches.

    Returns
    -------
    matplotlib.figure.Figure
        A new figure (not registered with pyplot).
    """
    import matplotlib as mpl
    from matplotlib.figure import Figure

    from .layout import MDS_MAX_NAMES, _square_limits, annotate_points, short_labels

    p = len(state.names)
    shape = check_int("shape", shape, min=0, max=p - 1)  # a row of the state
    M, N = state.M, state.N
    # a fixed layout: constrained layout would double the drawing time of every slider move
    fig = Figure(figsize=figsize)
    axs = fig.subplots(2, 3)
    fig.subplots_adjust(left=0.06, right=0.96, bottom=0.07, top=0.95, wspace=0.4, hspace=0.3)
    transform = getattr(state, "transform", "weyl")
    L = state.spectra.shape[1]  # N, or N-1 for the log-Weyl ratio (no lam_0)
    full = np.abs(state.spectra[shape])
    ax = axs[0, 0]
    if transform == "log-weyl-dct":
        ax.semilogy(np.arange(L), full + 1e-300, ".", color="0.6", ms=3, label=f"all {L}")
        k = np.arange(2 * M + 1)
        name = "DCT"
    else:
        ax.semilogy(np.arange(L) - L // 2, full + 1e-300, ".", color="0.6", ms=3,
                    label=f"all {L}")
        k = np.arange(-M, M + 1)
        name = "DFT"
    ax.semilogy(k, np.abs(state.coefficients[shape]) + 1e-300, "o", color="C3", ms=4,
                label=f"kept 2M+1={2 * M + 1}")
    ax.set(title=f"|{name}| of {state.names[shape]}", xlabel="frequency k")
    ax.legend(fontsize="small")
    ax = axs[0, 1]
    i = np.arange(N - L, N)  # the sequence starts at i = 1 for the log-Weyl ratio
    seq = "lam' (Eq. 8)" if transform == "weyl" else "r = log(lam / 4 pi i)"
    ax.plot(i, state.lam_prime[shape], ".", color="C0", ms=3, label=seq)
    ax.plot(i, state.reconstruction[shape], "-", color="C3", lw=1.2, label="reconstruction")
    ax.set(title=f"rel. error {state.reconstruction_error[shape]:.3g}", xlabel="i")
    ax.legend(fontsize="small")
    ax = axs[0, 2]
    codes = {lab: j for j, lab in enumerate(dict.fromkeys(state.labels))}
    cmap = mpl.colormaps["tab10" if len(codes) <= 10 else "tab20"]
    Y = state.mds
    if Y is not None:
        ax.scatter(Y[:, 0], Y[:, 1], c=[cmap(codes[lab] % cmap.N) for lab in state.labels], s=22)
        _square_limits(ax, Y)
        if p <= MDS_MAX_NAMES:
            annotate_points(ax, Y, short_labels(state.names))
    tr = "" if transform == "weyl" else f", {transform}"
    ax.set(title=f"MDS of cShape-DNA (size {2 * M + 1}{tr})")
    for ax, img, title, vmax in (
        (axs[1, 0], state.D_ref, f"Shape-DNA N={N}, scaled", 255.0),
        (axs[1, 1], state.D, f"cShape-DNA M={M}{tr}, scaled", 255.0),
        (axs[1, 2], state.difference, f"|difference|: mean {state.mean:.2f}, std {state.std:.2f}",
         None),
    ):
        im = ax.imshow(img, cmap="jet", vmin=0.0, vmax=vmax or max(float(img.max()), 1.0),
                       interpolation="nearest")
        ax.set_xticks([])
        ax.set_yticks([])
        ax.set_title(title, fontsize="medium")
        fig.colorbar(im, ax=ax, shrink=0.8)
    return fig
