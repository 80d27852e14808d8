"""Articulated bodies made of capsules: the figures whose poses the paper's isometry test bends.

A body is an implicit union of capsules (:class:`Capsule`, :func:`capsules_expression`)
whose joint angles change from pose to pose; :func:`articulated_figure` meshes one pose by
marching cubes and remeshes it (:mod:`cshape.data.variants`).  The creatures
(:mod:`cshape.data.creatures`), the posed figures with their true maps
(:mod:`cshape.data.poses`) and the suite's identities (:mod:`cshape.data.suite`) are built
from the same capsules.  Everything is deterministic: the random choices take a
``random_state``.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .._checks import check_choice
from ..mesh import Mesh
from .variants import _check_pos, marching_cubes, remesh

__all__ = [
    "articulated_figure",
]

#: The classes of :func:`articulated_figure`.
ARTICULATED_KINDS = ("human", "quadruped", "spider", "snake")


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
        figure of many capsules evaluates far fewer distances.  Use a few voxels.  The grown
        boxes are grouped in a tree of boxes (halves along the longest axis of their
        centres): a point outside a group's box gets ``cutoff`` at once, the value each
        capsule of the group would give it there, so the function's values are those of the
        capsules tested one by one, to the last bit.

    Returns
    -------
    str
        The function in muparser syntax, negative inside the union.
    """
    capsules = list(capsules)
    if not capsules:
        raise ValueError("capsules is empty: a figure needs at least one capsule")
    if cutoff is None:
        return _minimum([c.expression() for c in capsules])
    cutoff = _check_pos("cutoff", cutoff)
    leaves = []
    for c in capsules:
        a, b = np.asarray(c.a, dtype=float), np.asarray(c.b, dtype=float)
        lo = _as_written(np.minimum(a, b) - c.radius - cutoff)
        hi = _as_written(np.maximum(a, b) + c.radius + cutoff)
        leaves.append((f"(({_inside(lo, hi)})?({c.expression()}):{cutoff:.9g})", lo, hi,
                       (a + b) / 2))
    return _box_tree(leaves, cutoff)[0]


def _minimum(exprs: Sequence[str]) -> str:
    """muparser: the minimum of ``exprs``, as nested ``min(a,b)`` from the first on."""
    expr = exprs[0]
    for e in exprs[1:]:
        expr = f"min({expr},{e})"
    return expr


def _as_written(values: np.ndarray) -> np.ndarray:
    """The numbers as an expression writes them (9 significant digits) and muparser reads
    them: a box around boxes, made of these, holds them exactly."""
    return np.array([float(f"{v:.9g}") for v in values])


def _inside(lo: np.ndarray, hi: np.ndarray) -> str:
    """muparser: the point ``(x, y, z)`` is strictly inside the box ``[lo, hi]``."""
    return "&&".join(f"({v}>{p:.9g})&&({v}<{q:.9g})"
                     for v, p, q in zip("xyz", lo, hi, strict=True))


def _box_tree(leaves: list, cutoff: float) -> tuple[str, np.ndarray, np.ndarray]:
    """The minimum of the ``leaves`` (``(expression, lo, hi, centre)``, each ``cutoff``
    outside its box ``[lo, hi]``), split in halves along the longest axis of their centres,
    each half tested against its box first; returns ``(expression, lo, hi)``."""
    lo = np.min([leaf[1] for leaf in leaves], axis=0)
    hi = np.max([leaf[2] for leaf in leaves], axis=0)
    if len(leaves) <= 2:
        return _minimum([leaf[0] for leaf in leaves]), lo, hi
    centres = np.array([leaf[3] for leaf in leaves])
    order = np.argsort(centres[:, int(np.argmax(np.ptp(centres, axis=0)))], kind="stable")
    half = len(leaves) // 2
    left = _box_tree([leaves[k] for k in order[:half]], cutoff)
    right = _box_tree([leaves[k] for k in order[half:]], cutoff)
    both = _minimum([left[0], right[0]])
    return f"(({_inside(lo, hi)})?({both}):{cutoff:.9g})", lo, hi


def capsules_surface(capsules: Sequence[Capsule], voxelsize: float) -> Mesh:
    """The surface of a union of capsules: marching cubes of :func:`capsules_expression`.

    The sampled box holds every capsule with a margin of a few voxels (PyMeshLab's grid may
    stop short of the max corner), and each capsule's distance is evaluated only within three
    voxels of it (``cutoff``), which gives the mesh of the whole union, bit for bit.

    Parameters
    ----------
    capsules : sequence of Capsule
        The capsules of the union.
    voxelsize : float
        Marching-cubes voxel size; keep it below half the thinnest radius.

    Returns
    -------
    Mesh
        The raw marching-cubes mesh (see :func:`cshape.data.variants.marching_cubes`).
    """
    pts = np.array([c.a for c in capsules] + [c.b for c in capsules], dtype=float)
    margin = max(c.radius for c in capsules) + 4 * voxelsize + 0.05
    box = (*(pts.min(0) - margin), *(pts.max(0) + margin))
    return marching_cubes(capsules_expression(capsules, cutoff=3 * voxelsize), box, voxelsize)


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
    mesh = capsules_surface(figure_capsules(kind, random_state), voxelsize)
    if target_vertices is None:
        return mesh
    return remesh(mesh, target_vertices=target_vertices)
