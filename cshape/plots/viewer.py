"""Interactive 3-D mesh views (plotly): turn a mesh by hand, slide over its eigenfunctions.

* :func:`view_mesh`              - one mesh, optionally coloured by a function on its vertices;
* :func:`view_meshes`            - several meshes side by side (a noisy mesh beside the clean one);
* :func:`eigenfunction_explorer` - a mesh coloured by ``phi_i``, with a slider over ``i`` and
                                   ``lam_i`` in the title (Eq. 3); the eigenpairs are computed once.
* :func:`signature_explorer`     - a mesh coloured by its HKS or WKS (:mod:`cshape.signatures`),
                                   with a slider over the time or the energy.

Two shapes and a point map between them are :func:`cshape.plots.view_map`'s
(:mod:`cshape.plots.maps`).

Every view is framed and lit one way, by :func:`add_mesh_view`: the mesh upright, lit by
:data:`LIGHTING`, seen from above its longest side by a camera that :func:`scene_layout` places
just far enough for the whole mesh to show with a margin, whatever its proportions and the
panel's (:func:`fit_distance`).  The neighbour strip of ``cshape query --plot`` and the maps'
views (:mod:`cshape.plots.maps`) draw their meshes with it too.

All return a :class:`plotly.graph_objects.Figure` and never display it: in a notebook the
figure shows as a cell's last expression.  Drag to rotate, scroll to zoom.

Why plotly: a ``Mesh3d`` figure is rendered by plotly.js in the browser, from JSON alone.  The
slider is plotly's own (``layout.sliders`` stepping through ``frames``), so moving it needs
no kernel: the same figure works in JupyterLab (plotly's lab extension, offline) and in the
HTML that ``cshape notebooks`` exports, where plotly.js is embedded in the page (see
:mod:`cshape.course.lessons`).  Widget libraries (pythreejs, k3d, ipyvolume) need a live
kernel or saved widget state plus their JavaScript from a CDN to show anything in static HTML.

The pure functions behind the figures are tested directly: :func:`symmetric_limits` (colour
range centred on 0, because an eigenfunction's sign is arbitrary), :func:`mode_data` (the
values, colour range and title of each mode) and :func:`mesh3d_arrays` (the arrays plotly
draws).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .._checks import check_choice, check_eigenbasis, check_int, check_real
from ..mesh import as_mesh, repair_mesh

if TYPE_CHECKING:
    from collections.abc import Iterable

    import plotly.graph_objects as go
    from numpy.typing import ArrayLike

    from ..mesh import Mesh, MeshLike
    from ..spectrum import Eigenbasis

#: Diverging colour map (blue < 0 < red) for signed functions, plotly's name.
DIVERGING = "RdBu_r"
#: Sequential colour map for functions of one sign.
SEQUENTIAL = "Viridis"
_UP = {"z": (0, 0, 1), "y": (0, 1, 0), "x": (1, 0, 0)}
_GREY = "rgb(190, 199, 209)"


#: The cyclic permutation of the coordinate columns that brings the vertical axis to z (a
#: rotation, so nothing is mirrored): plotly's turntable rotation keeps z up whatever
#: ``camera.up`` says, so a y-up model is turned rather than the camera.
_TO_Z_UP = {"z": (0, 1, 2), "y": (2, 0, 1), "x": (1, 2, 0)}
#: Direction of the eye: 20 degrees above the horizon, 60 degrees off the longest horizontal
#: axis (a three-quarter view of an animal's flank rather than its rump or a cube's edge).
_EYE_ELEVATION, _EYE_AZIMUTH = 20.0, 60.0
#: plotly.js draws a 3-D scene in perspective with a vertical field of view of 45 degrees.
_TAN_HALF_FOV = float(np.tan(np.radians(22.5)))
#: Part of the half-width and half-height of a view left free around the mesh.
MARGIN = 0.1
#: Width in pixels of a figure that does not set one: the narrowest page a view is fitted for
#: (a notebook cell, an exported lesson, the documentation); wider pages only add room.
PAGE_WIDTH = 760
#: How every mesh of a 3-D view is lit: soft light from the front right, smooth normals, so
#: that the shape shows under the colours.
LIGHTING = dict(ambient=0.5, diffuse=0.75, specular=0.12, roughness=0.7, fresnel=0.1)
_LIGHT_POSITION = dict(x=1e5, y=-1e5, z=1e5)


# ------------------------------------------------------------------------------ pure parts
def symmetric_limits(f: ArrayLike) -> float | np.ndarray:
    """Colour limits ``(-m, m)`` centred on 0 that cover every value of ``f``.

    Parameters
    ----------
    f : array_like, shape (n,) or (n, k)
        Values on the vertices; with two dimensions, one range per column (mode).

    Returns
    -------
    float or ndarray, shape (k,)
        ``m = max |f|`` (per column); 1.0 where ``f`` is identically 0, so that the range
        is never empty.  The colour range is ``[-m, m]``.
    """
    a = np.asarray(f, dtype=np.float64)
    if a.ndim not in (1, 2) or a.shape[0] == 0:
        raise ValueError(f"f must have shape (n,) or (n, k) with n >= 1, got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError("f has NaN or infinite values; pass finite values on the vertices")
    m = np.abs(a).max(axis=0)
    m = np.where(m > 0, m, 1.0)
    return float(m) if a.ndim == 1 else m


def mode_data(lam: ArrayLike, phi: ArrayLike, indices: Iterable[int] | None = None
              ) -> list[dict[str, Any]]:
    """What the eigenfunction explorer shows for each mode ``i``.

    Parameters
    ----------
    lam : array_like, shape (k,)
        Eigenvalues (``cshape.eigenbasis(mesh, N).lam``).
    phi : array_like, shape (n, k)
        Eigenfunctions on the vertices, ``phi[:, i]`` for ``lam[i]``.
    indices : sequence of int, optional
        The modes to show (default: all ``k``).

    Returns
    -------
    list of dict
        One per mode, with ``i`` (int), ``lam`` (float), ``values`` (ndarray, shape (n,),
        float32: the colours), ``cmin`` and ``cmax`` (``-m`` and ``m`` of
        :func:`symmetric_limits`) and ``title`` (str, with ``lam_i``).
    """
    lam = np.asarray(lam, dtype=np.float64).reshape(-1)
    phi = np.asarray(phi, dtype=np.float64)
    if phi.ndim != 2 or phi.shape[1] != len(lam):
        raise ValueError(
            f"phi must have shape (n_vertices, k) with k = len(lam) = {len(lam)}, got "
            f"{phi.shape}; pass the lam, phi of one cshape.eigenbasis(mesh, N)"
        )
    k = len(lam)
    if indices is None:
        indices = range(k)
    out: list[dict[str, Any]] = []
    for i in indices:
        i = check_int("indices", i, min=0, max=k - 1)
        m = symmetric_limits(phi[:, i])
        out.append({
            "i": i, "lam": float(lam[i]), "values": phi[:, i].astype(np.float32),
            "cmin": -m, "cmax": m,
            "title": f"eigenfunction φ<sub>{i}</sub>:  λ<sub>{i}</sub> = {lam[i]:.5g}",
        })
    return out


def mesh3d_arrays(mesh: MeshLike) -> dict[str, np.ndarray]:
    """The arrays of a plotly ``Mesh3d`` trace: coordinates and triangle corners.

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        The mesh to show.

    Returns
    -------
    dict
        ``x, y, z`` (ndarray, shape (n,), float32) and ``i, j, k`` (ndarray, shape (m,),
        int32): the vertex coordinates and the three corners of each face.
    """
    mesh = as_mesh(mesh)
    V = mesh.vertices.astype(np.float32)
    F = mesh.faces.astype(np.int32)
    return {"x": V[:, 0], "y": V[:, 1], "z": V[:, 2], "i": F[:, 0], "j": F[:, 1], "k": F[:, 2]}


def _edge_lines(mesh: Mesh) -> np.ndarray:
    """Unique edges as one polyline with None breaks (a ``Scatter3d`` wireframe)."""
    F = mesh.faces
    e = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    e = np.unique(e, axis=0)
    P = np.full((len(e) * 3, 3), np.nan)
    P[0::3] = mesh.vertices[e[:, 0]]
    P[1::3] = mesh.vertices[e[:, 1]]
    return P


def _scalars(mesh: Mesh, scalars: ArrayLike | None, name: str = "scalars") -> np.ndarray | None:
    if scalars is None:
        return None
    f = np.asarray(scalars, dtype=np.float64).reshape(-1)
    if len(f) != mesh.n_vertices:
        raise ValueError(
            f"{name} has {len(f)} values but the mesh has {mesh.n_vertices} vertices; pass one "
            "value per vertex (e.g. cshape.eigenbasis(mesh, N).phi[:, i] of the same mesh)"
        )
    if not np.all(np.isfinite(f)):
        raise ValueError(f"{name} has NaN or infinite values; pass finite values on the vertices")
    return f


def _check_height(height: float) -> int:
    return int(check_real("height", height, min=100))  # pixels


# ------------------------------------------------------------------------------ figures
def _upright_arrays(mesh: MeshLike, vertical_axis: str) -> dict[str, np.ndarray]:
    kw = mesh3d_arrays(mesh)
    cols = [kw["x"], kw["y"], kw["z"]]
    a, b, c = _TO_Z_UP[vertical_axis]
    return dict(kw, x=cols[a], y=cols[b], z=cols[c])


def _colours(f: np.ndarray | None, *, cmap: str | None, symmetric: bool | None,
             colorbar: dict[str, Any] | None = None) -> dict[str, Any]:
    """``Mesh3d`` colour properties: grey, or ``f`` on the vertices (a colour bar when
    ``colorbar`` is given)."""
    if f is None:
        return dict(color=_GREY)
    if symmetric is None:
        symmetric = f.min() < 0 < f.max()
    if symmetric:
        m = symmetric_limits(f)
        lo, hi = -m, m
    else:
        lo, hi = float(f.min()), float(f.max())
        hi = hi if hi > lo else lo + 1.0
    return dict(intensity=f.astype(np.float32), intensitymode="vertex",
                colorscale=cmap or (DIVERGING if symmetric else SEQUENTIAL), cmin=lo, cmax=hi,
                showscale=colorbar is not None, colorbar=colorbar or {})


#: Pixels of a colour bar beside a view (bar and tick labels) and under a view (horizontal
#: bar), of a slider under a view, and of a title above it.
_COLORBAR_SIDE, _COLORBAR_UNDER, _SLIDER, _TITLE = 90, 56, 100, 40


def _aspect(height: float, *, top: float, bottom: float = 0.0, right: float = 0.0,
            columns: int = 1, spacing: float = 0.0, width: float = PAGE_WIDTH) -> float:
    """Width over height of each of ``columns`` scenes side by side in a figure of ``width``
    x ``height`` pixels, after ``top``, ``bottom`` and ``right`` pixels for titles, colour
    bars and sliders."""
    w = (width - right) * (1.0 - spacing * (columns - 1)) / columns
    return max(w, 50.0) / max(height - top - bottom, 50.0)


def _upright(V: ArrayLike, vertical_axis: str) -> np.ndarray:
    """Vertex coordinates with the vertical axis as z (a rotation: columns permuted cyclically)."""
    return np.asarray(V)[:, list(_TO_Z_UP[vertical_axis])]


def _eye_direction(extent: np.ndarray) -> np.ndarray:
    """Unit vector from the centre towards the eye, for a box of these (upright) extents."""
    el, az = np.radians(_EYE_ELEVATION), np.radians(_EYE_AZIMUTH)
    along, across = -np.cos(el) * np.cos(az), -np.cos(el) * np.sin(az)
    x, y = (along, across) if extent[0] >= extent[1] else (across, along)
    return np.array([x, y, np.sin(el)])


def _box(V: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Centre, extents (never 0: a flat mesh gets a thin box) and longest extent of the
    upright vertices."""
    lo, hi = V.min(axis=0), V.max(axis=0)
    extent = hi - lo
    longest = float(extent.max()) or 1.0
    return (lo + hi) / 2, np.maximum(extent, 1e-3 * longest), longest


def fit_distance(points: ArrayLike, direction: ArrayLike, aspect: float = 1.0,
                 margin: float = MARGIN) -> float:
    """Distance of the eye from the centre at which every point is in the picture.

    The picture is plotly's perspective view (vertical field of view 45 degrees) from
    ``distance * direction`` towards the origin, with z up.

    Parameters
    ----------
    points : array_like, shape (n, 3)
        In scene units, centred on the origin.
    direction : array_like, shape (3,)
        Unit vector from the origin towards the eye, not vertical.
    aspect : float, default=1.0
        Width over height of the picture.
    margin : float, default=MARGIN
        Part of the half-width and half-height left free around the points.

    Returns
    -------
    float
        The smallest distance at which each point's projection lies within ``1 - margin``
        of the picture's half-width and half-height.
    """
    P = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    e = np.asarray(direction, dtype=np.float64)
    right = np.cross(-e, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, -e)
    t = (1.0 - margin) * _TAN_HALF_FOV
    depth = P @ e  # towards the eye
    need = np.maximum(np.abs(P @ right) / (aspect * t), np.abs(P @ up) / t) + depth
    return float(need.max()) if len(P) else 1.0


def scene_layout(vertices: ArrayLike, vertical_axis: str = "z", *, aspect: float = 1.0,
                 margin: float = MARGIN) -> dict[str, Any]:
    """How a 3-D view of a mesh is framed: the layout of its plotly scene.

    Every 3-D view of cshape is framed here (and lit by :data:`LIGHTING`, see
    :func:`add_mesh_view`): the mesh upright, its proportions kept, seen from 20 degrees
    above the horizon and 60 degrees off its longest horizontal axis, from just far enough
    that the whole mesh is in the picture with ``margin`` to spare (:func:`fit_distance`).

    Parameters
    ----------
    vertices : array_like, shape (n, 3)
        The mesh's vertices, in the figure's (upright) coordinates.
    vertical_axis : {'z', 'y', 'x'}, default='z'
        The axis of ``vertices`` that points up.
    aspect : float, default=1.0
        Width over height of the scene in pixels.
    margin : float, default=MARGIN
        Part of the view's half-width and half-height left free around the mesh.

    Returns
    -------
    dict
        ``scene`` layout: axis ranges of the mesh's box (axes hidden), ``aspectmode``
        ``'manual'`` with the box's proportions, ``camera`` (``eye`` as
        :func:`default_eye`, ``up`` z, ``center`` the box's centre), turntable rotation.
    """
    vertical_axis = check_choice("vertical_axis", vertical_axis, tuple(_UP))
    aspect = check_real("aspect", aspect, min=0.05)
    margin = check_real("margin", margin, min=0.0)
    if margin >= 0.9:
        raise ValueError(f"margin must be below 0.9 (a part of the half-width), got {margin}")
    V = _upright(np.asarray(vertices, dtype=np.float64).reshape(-1, 3), vertical_axis)
    centre, extent, longest = _box(V)
    e = _eye_direction(extent)
    d = fit_distance((V - centre) / longest, e, aspect, margin)
    eye = d * e
    axes = {f"{c}axis": dict(visible=False, showbackground=False, showspikes=False,
                             range=[float(centre[k] - extent[k] / 2),
                                    float(centre[k] + extent[k] / 2)])
            for k, c in enumerate("xyz")}
    return dict(aspectmode="manual",
                aspectratio=dict(zip("xyz", (float(x) for x in extent / longest), strict=True)),
                camera=dict(up=dict(x=0, y=0, z=1), center=dict(x=0, y=0, z=0),
                            eye=dict(zip("xyz", (float(x) for x in eye), strict=True)),
                            projection=dict(type="perspective")),
                dragmode="turntable", **axes)


def default_eye(vertices: ArrayLike, vertical_axis: str = "z", *, aspect: float = 1.0
                ) -> dict[str, float]:
    """The camera's eye of the 3-D views (:func:`scene_layout`).

    Parameters
    ----------
    vertices : array_like, shape (n, 3)
        The mesh's vertices, in the figure's (upright) coordinates.
    vertical_axis : {'z', 'y', 'x'}, default='z'
        The axis of ``vertices`` that points up.
    aspect : float, default=1.0
        Width over height of the scene in pixels.

    Returns
    -------
    dict
        ``x, y, z`` of plotly's ``scene.camera.eye`` in the figure's (upright) coordinates:
        20 degrees above the horizon, 60 degrees off the mesh's longest horizontal axis,
        from its negative side, at the distance of :func:`fit_distance`.
    """
    return dict(scene_layout(vertices, vertical_axis, aspect=aspect)["camera"]["eye"])


def add_mesh_view(fig: go.Figure, mesh: MeshLike, *, scene: str = "scene",
                  vertical_axis: str = "z", aspect: float = 1.0, **style: Any) -> None:
    """Draw a mesh, lit and framed, into a scene of a plotly figure.

    This is the one way cshape makes a 3-D view.

    Parameters
    ----------
    fig : plotly.graph_objects.Figure
        With a 3-D scene named ``scene`` (``make_subplots`` with ``{"type": "scene"}`` specs
        names them ``'scene'``, ``'scene2'``, ...).
    mesh : Mesh or (vertices, faces)
        The mesh to show.
    scene : str, default='scene'
        Name of the scene to draw into.
    vertical_axis : {'z', 'y', 'x'}, default='z'
        The mesh's axis that points up; the trace's coordinates are the mesh's with this
        axis as z (its columns permuted cyclically).
    aspect : float, default=1.0
        Width over height of the scene in pixels (:func:`scene_layout`).
    **style
        Further ``Mesh3d`` properties: ``color``, or ``intensity`` with its ``colorscale``,
        ``cmin``, ``cmax``, ``colorbar``; ``hovertext``, ``name``.

    Returns
    -------
    None
        The trace is appended to ``fig.data``, the scene's layout is set.
    """
    import plotly.graph_objects as go

    kw = _upright_arrays(mesh, vertical_axis)
    trace = dict(flatshading=False, hoverinfo="skip", lighting=LIGHTING,
                 lightposition=_LIGHT_POSITION, showscale=False)
    trace.update(style)
    fig.add_trace(go.Mesh3d(**kw, scene=scene, **trace))
    fig.update_layout({scene: scene_layout(np.c_[kw["x"], kw["y"], kw["z"]], "z",
                                           aspect=aspect)})


def view_meshes(meshes: dict[str, MeshLike], scalars: dict[str, ArrayLike] | None = None, *,
                cmap: str | None = None, symmetric: bool | None = None,
                edges: bool | None = None, vertical_axis: str = "z", title: str | None = None,
                height: int = 420) -> go.Figure:
    """Several meshes side by side, each in its own rotatable 3-D scene.

    Parameters
    ----------
    meshes : dict of str to (Mesh or (vertices, faces))
        Panel title -> mesh, left to right.
    scalars : dict of str to array_like, shape (n,), optional
        Values on the vertices of some of the meshes (same keys); the others are grey.
    cmap : str, optional
        A plotly colour scale; default ``'RdBu_r'`` for values of both signs, else ``'Viridis'``.
    symmetric : bool, optional
        Centre each colour range on 0 (:func:`symmetric_limits`); default: when the values
        take both signs.
    edges : bool, optional
        Draw the triangle edges; default: for meshes of at most 2000 triangles.
    vertical_axis : {'z', 'y', 'x'}, default='z'
        The axis that points up (``'y'`` for the many models stored y-up, e.g. Spot).  The
        view opens upright, the whole mesh in view, from :func:`default_eye`; the figure's
        coordinates are the mesh's with this axis as z (its columns permuted cyclically).
    title : str, optional
        Title of the figure.
    height : int, default=420
        Pixels.

    Returns
    -------
    plotly.graph_objects.Figure
        Drag to rotate, scroll to zoom; never displayed here.
    """
    import plotly.graph_objects as go
    from plotly.subplots import make_subplots

    if not isinstance(meshes, dict) or not meshes:
        raise TypeError(
            "meshes must be a non-empty dict {title: mesh}, got "
            f"{type(meshes).__name__ if not isinstance(meshes, dict) else 'an empty dict'}"
        )
    vertical_axis = check_choice("vertical_axis", vertical_axis, tuple(_UP))
    height = _check_height(height)
    scalars = {} if scalars is None else scalars
    unknown = [k for k in scalars if k not in meshes]
    if unknown:
        raise ValueError(f"scalars has keys {unknown} that are not in meshes {list(meshes)}")
    names = [str(k) for k in meshes]
    n = len(names)
    spacing = 0.02
    top = _TITLE if (title or n > 1) else 10
    coloured = bool(scalars)
    # colour bars: beside a single view, under each of several (their height is known, the
    # page's width is not)
    under = _COLORBAR_UNDER if coloured and n > 1 else 0
    aspect = _aspect(height, top=top, bottom=under, columns=n, spacing=spacing,
                     right=_COLORBAR_SIDE if coloured and n == 1 else 0)
    fig = make_subplots(rows=1, cols=n, specs=[[{"type": "scene"}] * n],
                        subplot_titles=names if n > 1 else None, horizontal_spacing=spacing)
    for c, (key, m) in enumerate(meshes.items()):
        mesh = as_mesh(m)
        f = _scalars(mesh, scalars.get(key), name=f"scalars[{key!r}]")
        scene = "scene" if c == 0 else f"scene{c + 1}"
        domain = fig.layout[scene].domain.x
        colorbar = None
        if f is not None:
            colorbar = dict(thickness=14, len=0.75)
            if n > 1:
                colorbar = dict(thickness=12, orientation="h", x=(domain[0] + domain[1]) / 2,
                                xanchor="center", len=0.8 * (domain[1] - domain[0]),
                                y=0.0, yanchor="bottom", ypad=0)
        add_mesh_view(fig, mesh, scene=scene, vertical_axis=vertical_axis, aspect=aspect,
                      **_colours(f, cmap=cmap, symmetric=symmetric, colorbar=colorbar))
        if under:
            fig.layout[scene].domain.y = (under / (height - top), 1.0)
        if edges if edges is not None else mesh.n_faces <= 2000:
            P = _upright(_edge_lines(mesh), vertical_axis)
            fig.add_trace(go.Scatter3d(x=P[:, 0], y=P[:, 1], z=P[:, 2], mode="lines",
                                       line=dict(color="rgba(0,0,0,0.6)", width=2),
                                       hoverinfo="skip", showlegend=False, scene=scene))
    fig.update_layout(height=height, margin=dict(l=0, r=0, t=top, b=0),
                      title=dict(text=title) if title else None, showlegend=False)
    return fig


def view_mesh(mesh: MeshLike, scalars: ArrayLike | None = None, *, cmap: str | None = None,
              symmetric: bool | None = None, edges: bool | None = None,
              vertical_axis: str = "z", title: str | None = None, height: int = 420
              ) -> go.Figure:
    """One mesh in a rotatable, zoomable 3-D view, optionally coloured by values on its vertices.

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        The mesh to show.
    scalars : array_like, shape (n,), optional
        One value per vertex (an eigenfunction ``phi[:, i]``, a displacement, ...),
        interpolated linearly over each triangle (the FEM's hat functions, Eq. 3).
    cmap : str, optional
        A plotly colour scale (see :func:`view_meshes`).
    symmetric : bool, optional
        Centre the colour range on 0 (see :func:`view_meshes`).
    edges : bool, optional
        Draw the triangle edges (see :func:`view_meshes`).
    vertical_axis : {'z', 'y', 'x'}, default='z'
        The axis that points up (see :func:`view_meshes`).
    title : str, optional
        Title of the figure.
    height : int, default=420
        Height of the figure, in pixels.

    Returns
    -------
    plotly.graph_objects.Figure
        Drag to rotate, scroll to zoom; never displayed here.
    """
    return view_meshes({"": mesh}, None if scalars is None else {"": scalars}, cmap=cmap,
                       symmetric=symmetric, edges=edges, vertical_axis=vertical_axis,
                       title=title, height=height)


def _basis_of(mesh: Mesh, basis: object, N: int, at_least: int) -> Eigenbasis:
    """``basis`` checked against the (repaired) mesh, or the mesh's basis of ``N`` pairs."""
    from ..spectrum import Eigenbasis, eigenbasis

    if basis is None:
        return eigenbasis(mesh, N)
    basis = check_eigenbasis("basis", basis, Eigenbasis)
    if basis.n_vertices != mesh.n_vertices or basis.N < at_least:
        raise ValueError(
            f"basis has {basis.N} eigenpairs on {basis.n_vertices} vertices, but the (repaired) "
            f"mesh has {mesh.n_vertices} and at least {at_least} pairs are needed; pass "
            f"cshape.eigenbasis(mesh, N) of this mesh with N >= {at_least}"
        )
    return basis


def eigenfunction_explorer(mesh: MeshLike, N: int = 12, *,
                           basis: Eigenbasis | None = None,
                           start: int = 1, cmap: str = DIVERGING, vertical_axis: str = "z",
                           height: int = 520) -> go.Figure:
    """A mesh coloured by its eigenfunction ``phi_i``, with a slider over ``i``.

    The eigenpairs of Eq. (3) are computed once (:func:`cshape.eigenbasis`); every mode's
    colours travel with the figure as one plotly frame, so the slider works without a
    kernel, also in exported HTML.  The colour range of each mode is symmetric about 0
    (:func:`symmetric_limits`): red and blue are the two signs, white the nodal lines.
    Drag to rotate, scroll to zoom.

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        Repaired first (:func:`cshape.repair_mesh`, with its warning) when it needs it.
    N : int, default=12
        Number of eigenpairs ``lam_0 .. lam_{N-1}`` on the slider.
    basis : Eigenbasis, optional
        Already computed ``cshape.eigenbasis(mesh, K)`` with ``K >= N``; skips the
        eigensolve.
    start : int, default=1
        The mode shown first (``phi_0`` is constant under Neumann conditions).
    cmap : str, default='RdBu_r'
        A diverging plotly colour scale.
    vertical_axis : {'z', 'y', 'x'}, default='z'
    height : int, default=520
        Pixels.

    Returns
    -------
    plotly.graph_objects.Figure
        The explorer; never displayed here.
    """
    import plotly.graph_objects as go

    N = check_int("N", N, min=1)
    start = check_int("start", start, min=0, max=N - 1)
    vertical_axis = check_choice("vertical_axis", vertical_axis, tuple(_UP))
    height = _check_height(height)
    mesh = repair_mesh(as_mesh(mesh))
    basis = _basis_of(mesh, basis, N, N)
    modes = mode_data(basis.lam[:N], basis.phi[:, :N])
    first = modes[int(start)]
    fig = go.Figure()
    add_mesh_view(fig, mesh, vertical_axis=vertical_axis,
                  aspect=_aspect(height, top=_TITLE, bottom=_SLIDER, right=_COLORBAR_SIDE),
                  intensity=first["values"], intensitymode="vertex", colorscale=cmap,
                  cmin=first["cmin"], cmax=first["cmax"], showscale=True,
                  colorbar=dict(thickness=14, len=0.75, title=dict(text="φ")))
    frames = [go.Frame(name=str(md["i"]), traces=[0],
                       data=[go.Mesh3d(intensity=md["values"], cmin=md["cmin"],
                                       cmax=md["cmax"])],
                       layout=dict(title=dict(text=md["title"])))
              for md in modes]
    steps = [dict(method="animate", label=str(md["i"]),
                  args=[[str(md["i"])], dict(mode="immediate", frame=dict(duration=0, redraw=True),
                                             transition=dict(duration=0))])
             for md in modes]
    slider = dict(active=int(start), steps=steps, currentvalue=dict(prefix="i = "),
                  pad=dict(t=10, b=10), len=0.9, x=0.05)
    fig.frames = frames
    fig.update_layout(title=dict(text=first["title"]), sliders=[slider], height=height,
                      margin=dict(l=0, r=0, t=_TITLE, b=0))
    return fig


# ------------------------------------------------------------------------------ signatures
#: The signatures :func:`signature_explorer` shows: (function, scale name, scale symbol).
_SIGNATURES = {"hks": ("HKS", "time", "t"), "wks": ("WKS", "log-energy", "e")}


def scale_data(sig: ArrayLike, scales: ArrayLike, *, signature: str = "hks", log: bool = True
               ) -> list[dict[str, Any]]:
    """What the signature explorer shows at each scale (time or energy).

    Parameters
    ----------
    sig : array_like, shape (n, k)
        A signature on the vertices, one column per scale (:func:`cshape.hks`,
        :func:`cshape.wks`).
    scales : array_like, shape (k,)
        The times or log-energies of the columns.
    signature : {'hks', 'wks'}, default='hks'
        For the titles.
    log : bool, default=True
        Colour by ``log10`` of the values: a signature spans orders of magnitude between
        the tips of the limbs and the body at small times.

    Returns
    -------
    list of dict
        One per column, with ``j`` (int), ``scale`` (float), ``values`` (ndarray, shape (n,),
        float32), ``cmin``, ``cmax`` (the range of that column: each scale uses the whole
        colour map) and ``title`` (str).
    """
    from .._checks import check_bool

    signature = check_choice("signature", signature, tuple(_SIGNATURES))
    log = check_bool("log", log)
    a = np.asarray(sig, dtype=np.float64)
    sc = np.asarray(scales, dtype=np.float64).reshape(-1)
    if a.ndim != 2 or a.shape[1] != len(sc) or a.shape[0] == 0:
        raise ValueError(
            f"sig must have shape (n_vertices, k) with k = len(scales) = {len(sc)}, got "
            f"{a.shape}; pass the signature and the times or energies it was computed at"
        )
    if not np.all(np.isfinite(a)) or (log and not np.all(a > 0)):
        raise ValueError(
            "sig has NaN, infinite" + (" or non-positive values (log=True needs values > 0; "
                                       "pass log=False)" if log else " values")
        )
    name, _, sym = _SIGNATURES[signature]
    out = []
    for j in range(a.shape[1]):
        v = np.log10(a[:, j]) if log else a[:, j]
        lo, hi = float(v.min()), float(v.max())
        hi = hi if hi > lo else lo + 1.0
        label = f"log<sub>10</sub> {name}" if log else name
        out.append({"j": j, "scale": float(sc[j]), "values": v.astype(np.float32),
                    "cmin": lo, "cmax": hi, "title": f"{label} at {sym} = {sc[j]:.4g}"})
    return out


def signature_explorer(mesh: MeshLike, signature: str = "hks", *,
                       basis: Eigenbasis | None = None, N: int = 100,
                       n_scales: int = 20, log: bool = True, start: int | None = None,
                       cmap: str = SEQUENTIAL, vertical_axis: str = "z", height: int = 520
                       ) -> go.Figure:
    """A mesh coloured by its heat or wave kernel signature, with a slider over the scale.

    The eigenpairs are computed once, the signature at the default scales of
    :mod:`cshape.signatures` (100 times of Sun et al. for the HKS, 100 energies of Aubry et
    al. for the WKS), and ``n_scales`` of them, evenly spread, go on the slider; every
    scale's colours travel with the figure as a plotly frame, so the slider works without a
    kernel, also in exported HTML.  Each scale is coloured over its own range.

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        Repaired first (:func:`cshape.repair_mesh`) when it needs it.
    signature : {'hks', 'wks'}, default='hks'
    basis : Eigenbasis, optional
        Already computed ``cshape.eigenbasis(mesh, N)``; skips the eigensolve.
    N : int, default=100
        Eigenpairs to compute when ``basis`` is not given.
    n_scales : int, default=20
        Steps of the slider (at most 100).
    log : bool, default=True
        Colour by ``log10`` of the signature (:func:`scale_data`).
    start : int, optional
        The step shown first (default: the middle one).
    cmap : str, default='Viridis'
        Plotly colour scale.
    vertical_axis : {'z', 'y', 'x'}, default='z'
    height : int, default=520
        Height of the figure, in pixels.

    Returns
    -------
    plotly.graph_objects.Figure
        Never displayed here.
    """
    import plotly.graph_objects as go

    from .. import signatures as sg
    from .._checks import check_int
    signature = check_choice("signature", signature, tuple(_SIGNATURES))
    n_scales = check_int("n_scales", n_scales, min=1, max=100)
    vertical_axis = check_choice("vertical_axis", vertical_axis, tuple(_UP))
    height = _check_height(height)
    mesh = repair_mesh(as_mesh(mesh))
    basis = _basis_of(mesh, basis, check_int("N", N, min=2) if basis is None else 2, 2)
    if signature == "hks":
        scales = sg.hks_times(basis)
        sig = sg.hks(basis, scales)
    else:
        scales, sigma = sg.wks_energies(basis)
        sig = sg.wks(basis, scales, sigma)
    cols = np.unique(np.round(np.linspace(0, len(scales) - 1, n_scales)).astype(int))
    steps_data = scale_data(sig[:, cols], scales[cols], signature=signature, log=log)
    start = len(steps_data) // 2 if start is None else check_int(
        "start", start, min=0, max=len(steps_data) - 1)
    first = steps_data[start]
    name, scale_name, sym = _SIGNATURES[signature]
    fig = go.Figure()
    add_mesh_view(fig, mesh, vertical_axis=vertical_axis,
                  aspect=_aspect(height, top=_TITLE, bottom=_SLIDER, right=_COLORBAR_SIDE),
                  intensity=first["values"], intensitymode="vertex", colorscale=cmap,
                  cmin=first["cmin"], cmax=first["cmax"], showscale=True,
                  colorbar=dict(thickness=14, len=0.75,
                                title=dict(text=f"log10 {name}" if log else name)))
    frames = [go.Frame(name=str(d["j"]), traces=[0],
                       data=[go.Mesh3d(intensity=d["values"], cmin=d["cmin"], cmax=d["cmax"])],
                       layout=dict(title=dict(text=d["title"])))
              for d in steps_data]
    steps = [dict(method="animate", label=f"{d['scale']:.3g}",
                  args=[[str(d["j"])], dict(mode="immediate", frame=dict(duration=0, redraw=True),
                                            transition=dict(duration=0))])
             for d in steps_data]
    slider = dict(active=start, steps=steps, currentvalue=dict(prefix=f"{sym} = "),
                  pad=dict(t=10, b=10), len=0.9, x=0.05)
    fig.frames = frames
    fig.update_layout(title=dict(text=first["title"]), sliders=[slider], height=height,
                      margin=dict(l=0, r=0, t=_TITLE, b=0))
    return fig
