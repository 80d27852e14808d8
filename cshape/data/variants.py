"""Shape variants made with PyMeshLab: marching cubes, remeshing, subdivision, noise.

The paper's experiments (Section 3) compare a shape with versions of itself:

* the same surface at several resolutions (spheres S1-S3, :func:`cshape.shapes.icosphere`;
  D1 / D2, :func:`subdivide`);
* a marching-cubes mesh with needle and zero-area triangles ("CM", :func:`marching_cubes`)
  and its quality-improved remesh ("CS", :func:`remesh`);
  :func:`cshape.data.quality.mesh_quality` measures the difference (minimum angle, aspect
  ratio);
* near-isometric poses of an articulated figure
  (:func:`cshape.data.bodies.articulated_figure`);
* noisy copies, each vertex moved along its outward normal by a uniform random amount of at
  most ``amplitude * L`` (Section 3.3, :func:`add_normal_noise`).

Every function returns a :class:`cshape.Mesh` and accepts a ``Mesh`` or a ``(vertices,
faces)`` pair.  Everything is deterministic: PyMeshLab's filters used here are, and the
random choices take a ``random_state``.  The primitive shapes (sphere, torus, cube, ...) are
:mod:`cshape.shapes`'.  Cached, named collections of these shapes are in :mod:`cshape.data`.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._checks import check_bool, check_choice, check_int, check_real
from ..mesh import CShapeWarning, Mesh, MeshLike, as_mesh, repair_mesh

__all__ = [
    "add_normal_noise",
    "marching_cubes",
    "remesh",
    "subdivide",
    "vertex_normals",
]

#: The noise levels ``amplitude`` of Section 3.3 (maximum displacement ``amplitude * L``).
NOISE_LEVELS = (0.5, 1.0, 2.0, 4.0, 10.0)

#: Largest mesh :func:`remesh` and :func:`subdivide` may produce (triangles): PyMeshLab
#: allocates it natively, and a mistyped parameter would otherwise exhaust the memory.
MAX_OUTPUT_FACES = 20_000_000


# ---------------------------------------------------------------------- PyMeshLab glue
def _meshset(mesh: MeshLike | None = None) -> Any:
    import pymeshlab

    ms = pymeshlab.MeshSet()
    if mesh is not None:
        m = as_mesh(mesh)
        ms.add_mesh(pymeshlab.Mesh(vertex_matrix=m.vertices, face_matrix=m.faces))
    return ms


def _from_meshset(ms: Any, *, what: str) -> Mesh:
    m = ms.current_mesh()
    if m.face_number() == 0:
        raise ValueError(f"{what} produced no triangles; check its parameters")
    V = np.array(m.vertex_matrix(), dtype=np.float64)
    F = np.array(m.face_matrix(), dtype=np.int64)
    return repair_mesh(Mesh(V, F), warn=False)


def _check_int(name: str, value: object, lo: int, hi: int | None = None) -> int:
    return check_int(name, value, min=lo, max=hi)


def _check_pos(name: str, value: object) -> float:
    return check_real(name, value, positive=True)


# ---------------------------------------------------------------------- the genus-2 eight
def _smooth_min(a: str, b: str, k: float) -> str:
    # polynomial smooth minimum: min(a, b) - h^2 k / 4, h = max(k - |a - b|, 0) / k
    h = f"(max({k}-abs(({a})-({b})),0)/{k})"
    return f"(min({a},{b})-{h}*{h}*{k}/4)"


def eight(voxelsize: float = 0.02, target_vertices: int | None = 4000, *, R: float = 0.6,
          r: float = 0.22, separation: float = 1.1) -> Mesh:
    """A genus-2 "eight": two tori blended into one (the paper's "E"), remeshed.

    The implicit surface ``smin(torus(x + s/2), torus(x - s/2)) = 0`` (a smooth union of two
    tori whose centres are ``separation`` apart) is meshed by marching cubes
    (:func:`marching_cubes`) and remeshed isotropically (:func:`remesh`).

    Parameters
    ----------
    voxelsize : float, default=0.02
        Marching-cubes voxel size.
    target_vertices : int or None, default=4000
        Approximate vertex count after remeshing; ``None`` returns the raw marching-cubes mesh.
    R, r : float, default=0.6, 0.22
        Major and tube radius of each torus.
    separation : float, default=1.1
        Distance between the torus centres; must be below ``2 * (R + r)`` so they merge and
        above ``2 * (R - r)`` so the two holes stay open.

    Returns
    -------
    Mesh
        Closed, connected, genus 2.
    """
    R, r, separation = _check_pos("R", R), _check_pos("r", r), _check_pos("separation", separation)
    if not 2 * (R - r) < separation < 2 * (R + r):
        raise ValueError(
            f"separation must lie in (2(R - r), 2(R + r)) = ({2 * (R - r):g}, {2 * (R + r):g}) "
            f"for a genus-2 eight, got {separation}"
        )
    a = separation / 2
    t1 = f"sqrt((sqrt((x+{a})^2+y^2)-{R})^2+z^2)-{r}"
    t2 = f"sqrt((sqrt((x-{a})^2+y^2)-{R})^2+z^2)-{r}"
    m = 4 * voxelsize + 0.05  # PyMeshLab's grid may stop ~2 voxels short of the max corner
    bx, by, bz = a + R + r + m, R + r + m, r + m
    mesh = marching_cubes(_smooth_min(t1, t2, 0.1), (-bx, -by, -bz, bx, by, bz), voxelsize)
    if target_vertices is None:
        return mesh
    return remesh(mesh, target_vertices=target_vertices)


# ---------------------------------------------------------------------- marching cubes
def marching_cubes(expr: str, bbox: Sequence[float], voxelsize: float = 0.02) -> Mesh:
    """Mesh the zero level set of an implicit function with PyMeshLab's marching cubes.

    Wraps ``create_implicit_surface``.  Its output is a typical marching-cubes mesh: closed
    where the surface stays inside the box, with needle triangles and some triangles of
    (numerically) zero area -- the paper's low-quality "CM".  The FEM stage handles the
    zero-area ones (intrinsic mollification, with a :class:`cshape.CShapeWarning`).

    Parameters
    ----------
    expr : str
        The implicit function of ``x, y, z`` in muparser syntax (``sqrt``, ``min``, ``max``,
        ``abs``, ``^``, ...), negative inside.
    bbox : sequence of 6 floats
        ``(xmin, ymin, zmin, xmax, ymax, zmax)``, the sampled box.  Keep the surface a few
        voxels inside it: PyMeshLab's grid can stop up to about two voxels short of the max
        corner, and a surface reaching past the grid comes out cut open (with a warning).
    voxelsize : float, default=0.02
        Edge of the sampling voxels; the edge length of the output is about this.

    Returns
    -------
    Mesh
        With duplicate vertices welded and collapsed faces removed (zero-area faces with three
        distinct vertices are kept).

    Raises
    ------
    ValueError
        If ``expr`` does not parse, ``bbox`` or ``voxelsize`` is invalid (too many voxels),
        or the level set has no triangle in the box.
    """
    if not isinstance(expr, str) or not expr.strip():
        raise TypeError(f"expr must be a non-empty muparser expression string, got {expr!r}")
    try:
        box = np.asarray(bbox, dtype=np.float64).reshape(6)
    except (TypeError, ValueError):
        raise ValueError(
            f"bbox must be 6 numbers (xmin, ymin, zmin, xmax, ymax, zmax), got {bbox!r}"
        ) from None
    if not np.all(box[3:] > box[:3]):
        raise ValueError(f"bbox must have max > min on every axis, got {box.tolist()}")
    voxelsize = _check_pos("voxelsize", voxelsize)
    n_vox = np.prod(np.ceil((box[3:] - box[:3]) / voxelsize))
    if n_vox > 2e8:
        raise ValueError(
            f"voxelsize={voxelsize} samples {n_vox:.3g} voxels in this bbox; use a larger voxelsize"
        )
    import pymeshlab

    ms = _meshset()
    try:
        ms.create_implicit_surface(
            expr=expr, voxelsize=voxelsize,
            minx=box[0], miny=box[1], minz=box[2], maxx=box[3], maxy=box[4], maxz=box[5],
        )
    except pymeshlab.PyMeshLabException as exc:
        details = str(exc).split("Details:", 1)[-1].strip().splitlines()[0]
        raise ValueError(
            f"expr {expr[:80]!r} is not a valid muparser expression of x, y, z ({details})"
        ) from None
    mesh = _from_meshset(ms, what=f"marching cubes of {expr[:60]!r}")
    if len(mesh.boundary_edges):
        warnings.warn(
            f"marching cubes: the surface is cut open by the sampling box "
            f"({len(mesh.boundary_edges)} boundary edges); enlarge bbox by a few voxels",
            CShapeWarning,
            stacklevel=2,
        )
    return mesh


# ---------------------------------------------------------------------- remeshing
def remesh(
    mesh: MeshLike, target_length: float | None = None, *, target_vertices: int | None = None,
    iterations: int = 10, feature_angle: float = 90.0
) -> Mesh:
    """Isotropic explicit remeshing (PyMeshLab ``meshing_isotropic_explicit_remeshing``).

    Splits, collapses and flips edges and smooths tangentially towards a uniform edge
    length, reprojecting onto the input: the quality-improvement step turning "CM" into "CS".

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        The mesh to remesh.
    target_length : float, optional
        Target edge length in the mesh's units.
    target_vertices : int, optional
        Alternatively, an approximate vertex count; the target edge length is then
        ``sqrt(area / (0.866 * target_vertices))`` (equilateral triangles, two per vertex).
        Give exactly one of the two.
    iterations : int, default=10
        Remeshing iterations, 1 to 1000.
    feature_angle : float, default=90.0
        Edges whose dihedral angle exceeds this many degrees are kept as sharp features.
        The default 90 smooths the creases a union of capsules leaves (PyMeshLab's own
        default, 30, keeps them and with them slivers of about 3 degrees).

    Returns
    -------
    Mesh
        The remeshed surface.
    """
    mesh = as_mesh(mesh)
    if (target_length is None) == (target_vertices is None):
        raise ValueError(
            "give exactly one of target_length (an edge length) or target_vertices (a count), "
            f"got target_length={target_length!r}, target_vertices={target_vertices!r}"
        )
    if target_vertices is not None:
        target_vertices = _check_int("target_vertices", target_vertices, 4)
        target_length = float(np.sqrt(mesh.area / (0.866 * target_vertices)))
    target_length = _check_pos("target_length", target_length)
    expected_faces = 2.0 * mesh.area / (0.866 * target_length**2)
    if expected_faces > MAX_OUTPUT_FACES:
        shortest = float(np.sqrt(2.0 * mesh.area / (0.866 * MAX_OUTPUT_FACES)))
        raise ValueError(
            f"target_length={target_length:.3g} would make about {expected_faces:.3g} triangles "
            f"on this surface of area {mesh.area:.3g} (more than {MAX_OUTPUT_FACES:.0e}); use "
            f"target_length >= {shortest:.3g} (in the mesh's units)"
        )
    iterations = _check_int("iterations", iterations, 1, 1000)
    feature_angle = _check_pos("feature_angle", feature_angle)
    import pymeshlab

    ms = _meshset(mesh)
    # Every parameter is given, those we do not choose at PyMeshLab's documented defaults:
    # a parameter left out takes its default from the filter plugin, which (PyMeshLab
    # 2025.7) reads it from a member that is uninitialised in a new process and holds the
    # previous call's value afterwards (valgrind: "uninitialised value ... created by
    # qt_plugin_instance").  Left out, the same input gave a closed 418-vertex mesh in
    # most processes and an open 263-vertex one in some, depending on what the process had
    # done before.
    ms.meshing_isotropic_explicit_remeshing(
        iterations=iterations,
        adaptive=False,
        selectedonly=False,
        targetlen=pymeshlab.PureValue(target_length),
        featuredeg=feature_angle,
        checksurfdist=True,
        maxsurfdist=pymeshlab.PercentageValue(1.0),
        splitflag=True,
        collapseflag=True,
        swapflag=True,
        smoothflag=True,
        reprojectflag=True,
    )
    return _from_meshset(ms, what="isotropic remeshing")


def subdivide(mesh: MeshLike, iterations: int = 1, method: str = "loop") -> Mesh:
    """Refine a mesh by splitting every edge (about 4x the vertices per iteration).

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        The mesh to refine.
    iterations : int, default=1
        Subdivision steps, 0 to 8 (at most 20 million triangles in the result).
    method : {'loop', 'midpoint'}, default='loop'
        ``'loop'`` (smooths; the paper's D1 -> D2 refinement) or ``'midpoint'`` (keeps every
        face flat).

    Returns
    -------
    Mesh
        ``V + E`` vertices after one iteration (``E`` the number of edges, ``~3V``).
    """
    mesh = as_mesh(mesh)
    iterations = _check_int("iterations", iterations, 0, 8)
    if mesh.n_faces * 4**iterations > MAX_OUTPUT_FACES:
        most = int(np.floor(np.log(MAX_OUTPUT_FACES / mesh.n_faces) / np.log(4)))
        raise ValueError(
            f"iterations={iterations} would make {mesh.n_faces * 4**iterations:.3g} triangles "
            f"from {mesh.n_faces} (more than {MAX_OUTPUT_FACES:.0e}); use iterations <= "
            f"{max(most, 0)}"
        )
    method = check_choice("method", method, ("loop", "midpoint"))
    if iterations == 0:
        return mesh
    if len(mesh.nonmanifold_edges):
        # PyMeshLab's subdivision filters refuse these with an opaque PyMeshLabException
        raise ValueError(
            f"subdivide needs edge-manifold input, but the mesh has "
            f"{len(mesh.nonmanifold_edges)} edges shared by three or more triangles; split "
            "them first (or refine with remesh, which accepts them)"
        )
    import pymeshlab

    ms = _meshset(mesh)
    zero = pymeshlab.PercentageValue(0.0)  # split every edge, however short
    # every parameter given (see remesh: one left out may take an earlier call's value)
    if method == "loop":
        ms.meshing_surface_subdivision_loop(loopweight="Loop", iterations=iterations,
                                            threshold=zero, selected=False)
    else:
        ms.meshing_surface_subdivision_midpoint(iterations=iterations, threshold=zero,
                                                selected=False)
    return _from_meshset(ms, what=f"{method} subdivision")


# ---------------------------------------------------------------------- noise (Section 3.3)
def vertex_normals(mesh: MeshLike) -> NDArray[np.float64]:
    """Outward unit vertex normals, shape (n, 3): area-weighted means of the face normals.

    The faces' orientation is taken as given; for a closed mesh with negative signed volume
    (faces ordered clockwise seen from outside) the normals are flipped so they point
    outward.  A vertex in no triangle (or whose face normals cancel) gets the zero vector.

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        The mesh.

    Returns
    -------
    ndarray, shape (n, 3)
        The unit normal of each vertex (or zero).
    """
    mesh = as_mesh(mesh)
    V, F = mesh.vertices, mesh.faces
    fn = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])  # 2 * area * unit normal
    N = np.zeros_like(V)
    for k in range(3):
        np.add.at(N, F[:, k], fn)
    if mesh.is_closed:
        volume = np.einsum("ij,ij->i", V[F[:, 0]], np.cross(V[F[:, 1]], V[F[:, 2]])).sum() / 6
        if volume < 0:
            N = -N
    norm = np.linalg.norm(N, axis=1, keepdims=True)
    return np.divide(N, norm, out=np.zeros_like(N), where=norm > 0)


def add_normal_noise(mesh: MeshLike, amplitude: float = 1.0,
                     random_state: int | np.random.Generator | None = None, *,
                     signed: bool = False, length: float | None = None) -> Mesh:
    """Section 3.3's noise: move every vertex along its outward normal by up to ``amplitude * L``.

    Vertex ``i`` moves to ``v_i + d_i n_i`` with ``n_i`` its outward unit normal
    (:func:`vertex_normals`) and ``d_i`` drawn independently and uniformly from
    ``[0, amplitude * L]``, where ``L`` is the mean edge length of the *original* mesh.  The
    paper says "a random noise up to a maximum distance of lambda x L along the outward normal
    direction"; its lambda is ``amplitude`` here (``lam`` names eigenvalues only).  cshape reads
    this as a magnitude in ``[0, amplitude L]`` along the outward normal (``signed=False``, the
    default).  ``signed=True`` draws from ``[-amplitude L, amplitude L]`` instead.

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        The mesh to displace.
    amplitude : float, default=1.0
        The paper's noise level ``>= 0``: the largest displacement as a fraction of the mean
        edge length ``L``; the paper uses 0.5, 1, 2, 4 and 10 (:data:`NOISE_LEVELS`).
    random_state : int, numpy.random.Generator or None
        Seed; the same seed gives the same noisy mesh.
    signed : bool, default=False
        Draw from ``[-amplitude L, amplitude L]`` (in and out) instead of ``[0, amplitude L]``
        (out only).
    length : float, optional
        Use this ``L`` instead of the mesh's mean edge length.

    Returns
    -------
    Mesh
        Same faces, displaced vertices.

    Raises
    ------
    TypeError
        ``amplitude`` is not a real number.
    ValueError
        ``amplitude`` is negative, NaN or infinite.
    """
    mesh = as_mesh(mesh)
    amplitude = check_real("amplitude", amplitude, min=0.0)
    signed = check_bool("signed", signed)
    L = mesh.mean_edge_length if length is None else _check_pos("length", length)
    rng = np.random.default_rng(random_state)
    lo = -amplitude * L if signed else 0.0
    d = rng.uniform(lo, amplitude * L, size=mesh.n_vertices)
    V = mesh.vertices + d[:, None] * vertex_normals(mesh)
    return Mesh(V, mesh.faces)
