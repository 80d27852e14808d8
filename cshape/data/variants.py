"""Shape variants made with PyMeshLab: marching cubes, remeshing, subdivision, noise.

The paper's experiments (Section 3) compare a shape with versions of itself:

* the same surface at several resolutions (spheres S1-S3, :func:`cshape.shapes.icosphere`;
  D1 / D2, :func:`subdivide`);
* a marching-cubes mesh with needle and zero-area triangles ("CM", :func:`marching_cubes`)
  and its quality-improved remesh ("CS", :func:`remesh`); :func:`mesh_quality` measures the
  difference (minimum angle, aspect ratio);
* near-isometric poses of an articulated figure (:func:`articulated_figure`: an implicit union
  of capsules whose joint angles change, meshed by marching cubes and remeshed);
* noisy copies, each vertex moved along its outward normal by a uniform random amount of at
  most ``amplitude * L`` (Section 3.3, :func:`add_normal_noise`).

Every function returns a :class:`cshape.Mesh` and accepts a ``Mesh`` or a ``(vertices,
faces)`` pair.  Everything is deterministic: PyMeshLab's filters used here are, and the
random choices take a ``random_state``.  The primitive shapes (sphere, torus, cube, ...) are
:mod:`cshape.shapes`'.  Cached, named collections of these shapes are in :mod:`cshape.data`.
"""

from __future__ import annotations

import warnings
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._checks import check_bool, check_choice, check_int, check_real
from ..mesh import CShapeWarning, Mesh, MeshLike, as_mesh, repair_mesh

__all__ = [
    "add_normal_noise",
    "articulated_figure",
    "marching_cubes",
    "mesh_quality",
    "remesh",
    "subdivide",
    "triangle_angles",
    "vertex_normals",
]

#: The noise levels ``amplitude`` of Section 3.3 (maximum displacement ``amplitude * L``).
NOISE_LEVELS = (0.5, 1.0, 2.0, 4.0, 10.0)

#: The classes of :func:`articulated_figure`.
ARTICULATED_KINDS = ("human", "quadruped", "spider", "snake")

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


# ---------------------------------------------------------------------- articulated figures
@dataclass(frozen=True)
class Capsule:
    """A capsule: the points within ``radius`` of the segment from ``a`` to ``b``.

    Parameters
    ----------
    a, b : tuple of float
        The segment's end points ``(x, y, z)``.
    radius : float
        Radius around the segment.
    """

    a: tuple
    b: tuple
    radius: float

    def expression(self) -> str:
        """Return the signed distance to the capsule in muparser syntax (negative inside).

        Returns
        -------
        str
            An expression in ``x``, ``y`` and ``z`` for PyMeshLab's implicit surfaces.
        """
        ax, ay, az = (float(c) for c in self.a)
        dx, dy, dz = (float(q) - float(p) for p, q in zip(self.a, self.b, strict=True))
        L2 = dx * dx + dy * dy + dz * dz
        px, py, pz = f"(x-({ax:.9g}))", f"(y-({ay:.9g}))", f"(z-({az:.9g}))"
        if L2 < 1e-18:
            return f"sqrt({px}^2+{py}^2+{pz}^2)-{self.radius:.9g}"
        t = f"min(max(({px}*({dx:.9g})+{py}*({dy:.9g})+{pz}*({dz:.9g}))/{L2:.9g},0),1)"
        return (
            f"sqrt(({px}-{t}*({dx:.9g}))^2+({py}-{t}*({dy:.9g}))^2+({pz}-{t}*({dz:.9g}))^2)"
            f"-{self.radius:.9g}"
        )


def capsules_expression(capsules: Iterable[Capsule], *, cutoff: float | None = None) -> str:
    """Implicit function of the union of capsules: the minimum of their signed distances.

    Parameters
    ----------
    capsules : iterable of Capsule
        The capsules of the union.
    cutoff : float, optional
        If given, each capsule's distance is evaluated only inside its bounding box grown by
        ``cutoff`` (muparser's ``?:`` skips the other branch) and is ``cutoff`` outside it,
        where the true distance is at least ``cutoff``.  The zero level set is the same
        wherever the function is sampled no coarser than ``cutoff``, and marching cubes on a
        figure of many capsules evaluates far fewer distances.  Use a few voxels.

    Returns
    -------
    str
        The function in muparser syntax, negative inside the union.
    """
    capsules = list(capsules)
    if not capsules:
        raise ValueError("capsules is empty: a figure needs at least one capsule")
    if cutoff is not None:
        cutoff = _check_pos("cutoff", cutoff)
    parts = []
    for c in capsules:
        e = c.expression()
        if cutoff is not None:
            a, b = np.asarray(c.a, dtype=float), np.asarray(c.b, dtype=float)
            lo = np.minimum(a, b) - c.radius - cutoff
            hi = np.maximum(a, b) + c.radius + cutoff
            inside = "&&".join(f"({v}>{p:.9g})&&({v}<{q:.9g})"
                               for v, p, q in zip("xyz", lo, hi, strict=True))
            e = f"(({inside})?({e}):{cutoff:.9g})"
        parts.append(e)
    expr = parts[0]
    for e in parts[1:]:
        expr = f"min({expr},{e})"
    return expr


def _dir(azimuth: float, elevation: float) -> np.ndarray:
    """Unit vector from azimuth (about z, from +x) and elevation (from the xy-plane), degrees."""
    az, el = np.radians(azimuth), np.radians(elevation)
    return np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])


def _limb(start: ArrayLike, dirs: Sequence[ArrayLike], lengths: Sequence[float], radius: float
          ) -> list[Capsule]:
    out, p = [], np.asarray(start, dtype=float)
    for d, length in zip(dirs, lengths, strict=True):
        q = p + length * np.asarray(d)
        out.append(Capsule(tuple(p), tuple(q), radius))
        p = q
    return out


def figure_capsules(kind: str, random_state: int | np.random.Generator | None = None
                    ) -> list[Capsule]:
    """The capsules of an articulated figure in a pose drawn from ``random_state``.

    Every class has fixed bone lengths and radii; a pose only changes joint angles, drawn
    uniformly from ranges chosen so limbs never touch each other or the body.  Different
    poses of one class are therefore near-isometric (exactly so away from the joints).

    Parameters
    ----------
    kind : {'human', 'quadruped', 'spider', 'snake'}
    random_state : int, numpy.random.Generator or None
        Seed of the pose.  ``None`` gives a fresh, unseeded pose.

    Returns
    -------
    list of Capsule
        The figure's capsules, the union of which is its body.
    """
    kind = check_choice("kind", kind, ARTICULATED_KINDS)
    rng = np.random.default_rng(random_state)
    u = rng.uniform
    caps: list[Capsule] = []
    if kind == "human":
        caps.append(Capsule((0, 0, 0), (0, 0, 0.55), 0.16))  # torso
        caps.append(Capsule((0, 0, 0.78), (0, 0, 0.86), 0.13))  # head
        caps.append(Capsule((0, 0, 0.55), (0, 0, 0.72), 0.06))  # neck
        for s in (-1, 1):
            shoulder = (0.2 * s, 0, 0.5)
            abduct, flex, fwd = u(25, 85), u(0, 80), u(-30, 30)
            upper = np.array([s * np.sin(np.radians(abduct)), 0, -np.cos(np.radians(abduct))])
            upper = _rot_z(upper, s * fwd)
            fore = _bend(upper, flex, np.array([0, 1.0, 0]))
            caps += _limb(shoulder, [upper, fore], [0.3, 0.28], 0.055)
            hip = (0.09 * s, 0, 0.0)
            spread, swing, knee = u(5, 25), u(-30, 30), u(0, 70)
            thigh = np.array([s * np.sin(np.radians(spread)), 0, -np.cos(np.radians(spread))])
            thigh = _bend(thigh, swing, np.array([0, 1.0, 0]))
            shin = _bend(thigh, knee, np.array([0, -1.0, 0]))
            caps += _limb(hip, [thigh, shin], [0.4, 0.4], 0.07)
    elif kind == "quadruped":
        caps.append(Capsule((-0.45, 0, 0), (0.45, 0, 0), 0.17))  # body
        neck_el = u(20, 70)
        neck = _limb((0.45, 0, 0.05), [_dir(0, neck_el)], [0.3], 0.08)
        head_el = u(-40, 10)
        head = _limb(neck[-1].b, [_dir(0, head_el)], [0.22], 0.09)
        caps += neck + head
        for sx in (-1, 1):
            for sy in (-1, 1):
                swing, knee = u(-30, 30), u(0, 60)
                upper = _dir(0, -90 + swing)
                lower = _dir(0, -90 + swing - sx * knee)
                caps += _limb((0.34 * sx, 0.09 * sy, -0.05), [upper, lower], [0.28, 0.26], 0.055)
        tail_az, tail_el = u(150, 210), u(-40, 40)
        caps += _limb((-0.45, 0, 0.05), [_dir(tail_az, tail_el)], [0.32], 0.045)
    elif kind == "spider":
        caps.append(Capsule((0, 0, 0), (0, 0, 0.08), 0.22))  # body
        for k in range(6):
            az = 60 * k + u(-12, 12)
            up, down = u(0, 35), u(-75, -25)
            start = 0.18 * _dir(az, 0) + np.array([0, 0, 0.04])
            caps += _limb(start, [_dir(az, up), _dir(az, down)], [0.32, 0.38], 0.05)
    else:  # snake
        p, heading, pitch = np.zeros(3), 0.0, 0.0
        for _ in range(7):
            heading += u(-25, 25)
            pitch = float(np.clip(pitch + u(-12, 12), -20, 20))
            q = p + 0.25 * _dir(heading, pitch)
            caps.append(Capsule(tuple(p), tuple(q), 0.08))
            p = q
    return caps


def _rot_z(v: np.ndarray, deg: float) -> np.ndarray:
    c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]])


def _bend(v: np.ndarray, deg: float, towards: np.ndarray) -> np.ndarray:
    """Rotate unit vector ``v`` by ``deg`` degrees in the plane spanned by ``v`` and ``towards``."""
    w = towards - np.dot(towards, v) * v
    nw = np.linalg.norm(w)
    if nw < 1e-12:
        return v
    w = w / nw
    t = np.radians(deg)
    return np.cos(t) * v + np.sin(t) * w


def articulated_figure(
    kind: str = "human", random_state: int | np.random.Generator | None = 0, *,
    voxelsize: float = 0.02, target_vertices: int | None = 3000
) -> Mesh:
    """A pose of an articulated figure: union of capsules, marching cubes, isotropic remesh.

    Parameters
    ----------
    kind : {'human', 'quadruped', 'spider', 'snake'}, default='human'
        The class (see :func:`figure_capsules`).
    random_state : int, numpy.random.Generator or None, default=0
        Seed of the pose (joint angles); same seed, same mesh.
    voxelsize : float, default=0.02
        Marching-cubes voxel size; keep it below half the thinnest radius (0.045).
    target_vertices : int or None, default=3000
        Approximate vertex count after remeshing; ``None`` returns the raw marching-cubes
        mesh (with its needle and zero-area triangles).

    Returns
    -------
    Mesh
        Closed, connected, genus 0.
    """
    caps = figure_capsules(kind, random_state)
    pts = np.array([c.a for c in caps] + [c.b for c in caps], dtype=float)
    rmax = max(c.radius for c in caps)
    margin = rmax + 4 * voxelsize + 0.05  # PyMeshLab's grid may stop short of the max corner
    lo, hi = pts.min(0) - margin, pts.max(0) + margin
    mesh = marching_cubes(capsules_expression(caps), (*lo, *hi), voxelsize)
    if target_vertices is None:
        return mesh
    return remesh(mesh, target_vertices=target_vertices)


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


# ---------------------------------------------------------------------- mesh quality
def triangle_angles(mesh: MeshLike) -> NDArray[np.float64]:
    """Interior angles of every triangle in degrees, shape (m, 3), angle ``k`` at corner ``k``.

    A zero-area triangle has angles 0, 0, 180 (or 0 where two vertices coincide).

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        The mesh.

    Returns
    -------
    ndarray, shape (m, 3)
        Angle ``k`` of each triangle at its corner ``k``, in degrees.
    """
    mesh = as_mesh(mesh)
    V, F = mesh.vertices, mesh.faces
    out = np.empty(F.shape, dtype=np.float64)
    for k in range(3):
        u = V[F[:, (k + 1) % 3]] - V[F[:, k]]
        w = V[F[:, (k + 2) % 3]] - V[F[:, k]]
        nu, nw = np.linalg.norm(u, axis=1), np.linalg.norm(w, axis=1)
        cos = np.einsum("ij,ij->i", u, w) / np.maximum(nu * nw, np.finfo(float).tiny)
        sin = np.linalg.norm(np.cross(u, w), axis=1) / np.maximum(nu * nw, np.finfo(float).tiny)
        out[:, k] = np.degrees(np.arctan2(sin, cos))
    return out


def mesh_quality(mesh: MeshLike) -> dict[str, float]:
    """Triangle-quality figures of a mesh (e.g. the paper's "CM" versus "CS").

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        The mesh to measure.

    Returns
    -------
    dict
        ``min_angle``, ``mean_min_angle``, ``max_angle`` (degrees); ``pct_below_10`` (share of
        triangles with an angle under 10 degrees, in percent); ``aspect_max``,
        ``aspect_mean`` (aspect ratio ``R / (2 r)``, circumradius over twice the inradius:
        1 for an equilateral triangle, ``inf`` for a degenerate one); ``n_degenerate``
        (triangles of area below ``1e-12`` times the mean); ``n_vertices``, ``n_faces``,
        ``mean_edge_length``.

    Examples
    --------
    >>> from cshape import shapes
    >>> from cshape.data import variants
    >>> q = variants.mesh_quality(shapes.icosphere(2))
    >>> round(q["aspect_max"], 2) < 1.3
    True
    """
    mesh = as_mesh(mesh)
    ang = triangle_angles(mesh)
    V, F = mesh.vertices, mesh.faces
    e = np.stack([np.linalg.norm(V[F[:, (k + 1) % 3]] - V[F[:, k]], axis=1) for k in range(3)], 1)
    A = mesh.face_areas
    s = e.sum(1) / 2
    with np.errstate(divide="ignore", invalid="ignore"):
        aspect = np.where(A > 0, e.prod(1) * s / (8 * A**2), np.inf)
    min_ang = ang.min(1)
    return {
        "n_vertices": mesh.n_vertices,
        "n_faces": mesh.n_faces,
        "mean_edge_length": mesh.mean_edge_length,
        "min_angle": float(min_ang.min()),
        "mean_min_angle": float(min_ang.mean()),
        "max_angle": float(ang.max()),
        "pct_below_10": float(100 * np.mean(min_ang < 10)),
        "aspect_max": float(aspect.max()),
        "aspect_mean": float(np.mean(aspect[np.isfinite(aspect)])) if np.isfinite(aspect).any()
        else float("inf"),
        "n_degenerate": int(np.sum(A < 1e-12 * A.mean())),
    }
