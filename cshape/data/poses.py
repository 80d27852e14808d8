"""Poses that keep the template's vertices: articulated figures deformed by a skeleton.

:func:`cshape.data.bodies.articulated_figure` meshes every pose anew (marching cubes and
remeshing), so two poses share no vertex and a point-to-point map between them has no
ground truth.  Here a figure is meshed **once**, in a rest pose (the *template*), and every
pose moves the template's vertices by **linear blend skinning**: each bone turns about its
joint, each vertex follows the bones near it,

``x' = sum_b w_b(x) G_b x``, ``G_b = G_parent(b) T(j_b) R_b T(-j_b)``,

where ``j_b`` is the bone's joint in the rest pose, ``R_b`` its rotation and ``w_b(x)``
smooth weights that sum to 1 (``(1 - s^2)^2`` for ``s = (d_b(x) - d_min(x)) / h < 1``,
else 0; ``d_b`` the distance to the bone's capsules).  The faces stay the same, so **the
ground-truth map between two poses is the identity** on vertex indices.  Rigid parts keep
their metric exactly; joints bend with the stretching and compression of real skin
(near-isometric, as real poses are).

:func:`mirror_map` gives the template's left-right symmetry (a second map that intrinsic
signatures cannot tell from the identity).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np

from .._checks import check_bool, check_choice, check_int, check_real
from ..mesh import Mesh, as_mesh
from .bodies import Capsule, capsules_surface
from .variants import remesh

if TYPE_CHECKING:
    from collections.abc import Sequence

    from numpy.typing import ArrayLike

    from ..mesh import MeshLike

__all__ = [
    "mirror_map",
    "pose",
    "posed_figure",
]

#: The classes of :func:`posed_figure`.
POSED_KINDS = ("human", "quadruped")

#: Width ``h`` of the blend between two bones (units of the figure, about 1.7 long).
BLEND_WIDTH = 0.06


@dataclass(frozen=True)
class _Joint:
    """One degree of freedom: a rotation about ``axis`` (rest frame) by an angle in range."""

    axis: tuple
    lo: float
    hi: float


@dataclass(frozen=True)
class _Bone:
    name: str
    parent: int  # index of the parent bone, -1 for the root
    joint: tuple  # rest-pose position of the joint the bone turns about
    capsules: tuple  # its Capsules in the rest pose
    dofs: tuple = field(default_factory=tuple)  # _Joint rotations, applied in order


def _unit(v: ArrayLike) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def _human() -> list[_Bone]:
    bones = [_Bone("torso", -1, (0, 0, 0), (Capsule((0, 0, 0), (0, 0, 0.55), 0.16),))]
    bones.append(_Bone(
        "head", 0, (0, 0, 0.55),
        (Capsule((0, 0, 0.55), (0, 0, 0.72), 0.06), Capsule((0, 0, 0.78), (0, 0, 0.86), 0.13)),
        (_Joint((1, 0, 0), -20, 20), _Joint((0, 1, 0), -15, 15)),
    ))
    for s in (-1, 1):
        sh = np.array([0.2 * s, 0.0, 0.5])
        arm = _unit([s * np.sin(np.radians(50)), 0, -np.cos(np.radians(50))])
        el = sh + 0.3 * arm
        hand = el + 0.28 * arm
        bend = tuple(_unit(np.cross(arm, [0, 1, 0])))  # flexes the forearm forward
        up = len(bones)
        bones.append(_Bone(
            f"upper_arm_{s}", 0, tuple(sh), (Capsule(tuple(sh), tuple(el), 0.055),),
            (_Joint((0, 1, 0), -25 * s, 35 * s), _Joint((1, 0, 0), -35, 35)),
        ))
        bones.append(_Bone(f"forearm_{s}", up, tuple(el), (Capsule(tuple(el), tuple(hand), 0.055),),
                           (_Joint(bend, 0, 100),)))
        hip = np.array([0.09 * s, 0.0, 0.0])
        leg = _unit([s * np.sin(np.radians(12)), 0, -np.cos(np.radians(12))])
        knee = hip + 0.4 * leg
        foot = knee + 0.4 * leg
        th = len(bones)
        bones.append(_Bone(
            f"thigh_{s}", 0, tuple(hip), (Capsule(tuple(hip), tuple(knee), 0.07),),
            (_Joint((1, 0, 0), -35, 35), _Joint((0, 1, 0), -5 * s, 12 * s)),
        ))
        bones.append(_Bone(f"shin_{s}", th, tuple(knee), (Capsule(tuple(knee), tuple(foot), 0.07),),
                           (_Joint((1, 0, 0), -80, 0),)))
    return bones


def _quadruped() -> list[_Bone]:
    bones = [_Bone("body", -1, (0, 0, 0), (Capsule((-0.45, 0, 0), (0.45, 0, 0), 0.17),))]
    neck_dir = _unit([np.cos(np.radians(45)), 0, np.sin(np.radians(45))])
    n0 = np.array([0.45, 0.0, 0.05])
    n1 = n0 + 0.3 * neck_dir
    head_end = n1 + 0.22 * _unit([1, 0, -0.2])
    bones.append(_Bone(
        "neck", 0, tuple(n0),
        (Capsule(tuple(n0), tuple(n1), 0.08), Capsule(tuple(n1), tuple(head_end), 0.09)),
        (_Joint((0, 1, 0), -25, 25), _Joint((0, 0, 1), -30, 30)),
    ))
    for sx in (-1, 1):
        for sy in (-1, 1):
            hip = np.array([0.34 * sx, 0.09 * sy, -0.05])
            knee = hip + [0, 0, -0.28]
            foot = knee + [0, 0, -0.26]
            up = len(bones)
            bones.append(_Bone(
                f"leg_{sx}_{sy}", 0, tuple(hip), (Capsule(tuple(hip), tuple(knee), 0.055),),
                (_Joint((0, 1, 0), -30, 30), _Joint((1, 0, 0), -10 * sy, 5 * sy)),
            ))
            bones.append(_Bone(
                f"lower_leg_{sx}_{sy}", up, tuple(knee),
                (Capsule(tuple(knee), tuple(foot), 0.055),),
                (_Joint((0, 1, 0), 0, 60 * sx),),
            ))
    t0 = np.array([-0.45, 0.0, 0.05])
    bones.append(_Bone(
        "tail", 0, tuple(t0), (Capsule(tuple(t0), tuple(t0 + [-0.32, 0, 0]), 0.045),),
        (_Joint((0, 0, 1), -35, 35), _Joint((0, 1, 0), -35, 35)),
    ))
    return bones


_SKELETONS = {"human": _human, "quadruped": _quadruped}
#: The mirror of each class: the coordinate that flips between left and right.
_MIRROR_AXIS = {"human": 0, "quadruped": 1}


def _skeleton(kind: str) -> list[_Bone]:
    return _SKELETONS[check_choice("kind", kind, POSED_KINDS)]()


@lru_cache(maxsize=8)
def _template(kind: str, voxelsize: float, target_vertices: int) -> Mesh:
    mesh = capsules_surface([c for b in _skeleton(kind) for c in b.capsules], voxelsize)
    return remesh(mesh, target_vertices=target_vertices)


def pose_template(kind: str = "human", *, voxelsize: float = 0.02, target_vertices: int = 3000
                  ) -> Mesh:
    """The template of a class: the rest pose, meshed once (marching cubes and remeshing).

    Parameters
    ----------
    kind : {'human', 'quadruped'}, default='human'
    voxelsize : float, default=0.02
        Marching-cubes voxel (keep it below half the thinnest radius, 0.045).
    target_vertices : int, default=3000
        Approximate vertex count after isotropic remeshing.

    Returns
    -------
    Mesh
        Closed and connected; cached, so every pose of a class starts from the same one.
    """
    kind = check_choice("kind", kind, POSED_KINDS)
    voxelsize = check_real("voxelsize", voxelsize, positive=True)
    target_vertices = check_int("target_vertices", target_vertices, min=100)
    return _template(kind, voxelsize, target_vertices)


def _segment_distance(x: np.ndarray, a: ArrayLike, b: ArrayLike) -> np.ndarray:
    """Distances from points ``x`` (n, 3) to the segment ``a b``."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    d = b - a
    L2 = float(d @ d)
    s = np.clip((x - a) @ d / L2, 0.0, 1.0) if L2 > 0 else np.zeros(len(x))
    return np.linalg.norm(x - (a + s[:, None] * d), axis=1)


def skin_weights(kind: str, vertices: ArrayLike, *, width: float = BLEND_WIDTH) -> np.ndarray:
    """Linear-blend-skinning weights of rest-pose points, shape (n, number of bones).

    ``w_b ~ (1 - s_b^2)^2`` for ``s_b = (d_b - d_min) / width < 1`` and 0 beyond (a smooth
    bump with compact support), with ``d_b`` the distance from the point to the surface of
    bone ``b``'s capsules and ``d_min`` the smallest over the bones; rows sum to 1.  A point
    farther than ``width`` from every other bone's region follows its bone rigidly; near a
    joint it blends the bones that meet there.

    Parameters
    ----------
    kind : {'human', 'quadruped'}
        The class, whose skeleton gives the bones.
    vertices : array_like, shape (n, 3)
        Points of the rest pose.
    width : float, default=BLEND_WIDTH (0.06)
        Width of the blend region, in the template's length units.

    Returns
    -------
    ndarray, shape (n, number of bones)
        The weights ``w_b``; each row sums to 1.
    """
    return _blend_weights(_skeleton(kind), vertices, width)


def _blend_weights(bones: Sequence[_Bone], vertices: ArrayLike, width: float = BLEND_WIDTH
                   ) -> np.ndarray:
    """:func:`skin_weights` for any skeleton (a list of ``_Bone``)."""
    x = np.asarray(vertices, dtype=float)
    D = np.stack([
        np.min([_segment_distance(x, c.a, c.b) - c.radius for c in b.capsules], axis=0)
        for b in bones
    ], axis=1)
    s = (D - D.min(axis=1, keepdims=True)) / width
    W = np.square(np.clip(1.0 - np.square(s), 0.0, None))
    return W / W.sum(axis=1, keepdims=True)


def _rotation(axis: ArrayLike, deg: float) -> np.ndarray:
    """Rotation matrix about a unit ``axis`` by ``deg`` degrees (Rodrigues)."""
    k = _unit(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    t = np.radians(deg)
    return np.eye(3) + np.sin(t) * K + (1 - np.cos(t)) * (K @ K)


def _bone_transforms(bones: Sequence[_Bone], angles: Sequence[Sequence[float]]
                     ) -> list[tuple[np.ndarray, np.ndarray]]:
    """World transforms (R, t) of every bone, ``x -> R x + t``, from forward kinematics."""
    out: list[tuple[np.ndarray, np.ndarray]] = []
    for b, ang in zip(bones, angles, strict=True):
        R_loc = np.eye(3)
        for dof, a in zip(b.dofs, ang, strict=True):
            R_loc = R_loc @ _rotation(dof.axis, a)
        j = np.asarray(b.joint, float)
        t_loc = j - R_loc @ j  # turn about the joint
        if b.parent < 0:
            out.append((R_loc, t_loc))
        else:
            Rp, tp = out[b.parent]
            out.append((Rp @ R_loc, Rp @ t_loc + tp))
    return out


def pose(template: MeshLike, kind: str = "human",
         random_state: int | np.random.Generator | None = 0) -> Mesh:
    """Move the vertices of a class's template into a pose drawn from ``random_state``.

    Parameters
    ----------
    template : Mesh or (vertices, faces)
        The rest pose of ``kind`` (:func:`pose_template`; the data manifest's ``poses``
        collection passes its cached template item).
    kind : {'human', 'quadruped'}, default='human'
    random_state : int, numpy.random.Generator or None, default=0
        Seed of the joint angles, each uniform in its range (a few tens of degrees; elbows
        and knees up to 100 and 80).

    Returns
    -------
    Mesh
        The template's faces, moved vertices: vertex ``i`` is the same material point in
        every pose (the ground-truth correspondence is the identity).  NumPy only, so the
        same template and seed give the same bits in any process.
    """
    template = as_mesh(template)
    bones = _skeleton(kind)
    rng = np.random.default_rng(random_state)
    angles = [[float(rng.uniform(min(d.lo, d.hi), max(d.lo, d.hi))) for d in b.dofs]
              for b in bones]
    T = _bone_transforms(bones, angles)
    V = template.vertices
    W = skin_weights(kind, V)
    out = np.zeros_like(V)
    for b, (R, t) in enumerate(T):
        out += W[:, b:b + 1] * (V @ R.T + t)
    return Mesh(out, template.faces)


def posed_figure(kind: str = "human", random_state: int | np.random.Generator | None = 0, *,
                 rest: bool = False, voxelsize: float = 0.02, target_vertices: int = 3000
                 ) -> Mesh:
    """Return a pose of a class: :func:`pose` of the class's cached :func:`pose_template`.

    Parameters
    ----------
    kind : {'human', 'quadruped'}, default='human'
        The class.
    random_state : int, numpy.random.Generator or None, default=0
        Seed of the joint angles (see :func:`pose`).
    rest : bool, default=False
        Return the template itself (every angle 0).
    voxelsize : float, default=0.02
        Marching-cubes voxel of the template (:func:`pose_template`).
    target_vertices : int, default=3000
        Approximate vertex count of the template (:func:`pose_template`).

    Returns
    -------
    Mesh
        ``faces`` equal to the template's (the ground-truth correspondence is the identity).
    """
    template = pose_template(kind, voxelsize=voxelsize, target_vertices=target_vertices)
    if check_bool("rest", rest):
        return template
    return pose(template, kind, random_state)


def mirror_map(kind: str, mesh: Mesh) -> np.ndarray:
    """Return the template's left-right mirror as a vertex map.

    ``mirror[i]`` is the vertex nearest to the reflection of vertex ``i`` of the rest pose
    (``x -> -x`` for the human, ``y -> -y`` for the quadruped); the remeshed template is
    symmetric up to about an edge length.

    Parameters
    ----------
    kind : {'human', 'quadruped'}
        The class, which sets the mirror plane.
    mesh : Mesh
        The rest pose (:func:`posed_figure` with ``rest=True``), or a pose with its faces.

    Returns
    -------
    mirror : ndarray of int64, shape (n,)
        The vertex nearest to each vertex's reflection.
    """
    from scipy.spatial import cKDTree

    kind = check_choice("kind", kind, POSED_KINDS)
    V = np.asarray(mesh.vertices, dtype=float)
    R = V.copy()
    R[:, _MIRROR_AXIS[kind]] *= -1
    return cKDTree(V).query(R)[1].astype(np.int64)
