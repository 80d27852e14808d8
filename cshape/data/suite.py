"""The benchmark suite: three generated retrieval benchmarks that ask different questions.

=============  ==================  =====================================================
benchmark      classes             what a class holds
=============  ==================  =====================================================
creatures      12 kinds of animal  members of a kind with their own proportions, pose,
               (category level)    resolution and noise (:mod:`cshape.data.creatures`)
identities     12 identities       one body (a human or a quadruped with its own limb
               (instance level)    lengths and thicknesses) in 8 poses at 2 resolutions
resolutions    24 shapes           one surface meshed three ways: isotropic remeshes to
               (same shape)        about 1000 and 2500 vertices, a quadric decimation
=============  ==================  =====================================================

Every benchmark has a **development** instance (collection seed 0, ``<name>-dev`` in
``data_manifest.yaml``: choose and tune on it) and a **held-out** one (seed 1, ``<name>``:
report on it); the two share no member.  :data:`SUITE` lists them.

Identities (:func:`identity_pose`) reuse the skeletons of :mod:`cshape.data.poses`: an
identity rescales every limb group of the skeleton (length and thickness factors, log-uniform
in ``[1/(1+v_l), 1+v_l]`` and ``[1/(1+v_t), 1+v_t]``), is meshed once per resolution (marching
cubes, isotropic remeshing) and posed by linear blend skinning, so its poses are
near-isometric and its two resolutions are the same surface.  Distinct identities of one kind
differ only in proportions: the question real collections of people or animals ask (TOSCA,
FAUST), harder than telling a spider from a snake.

Resolutions (:func:`resolution_shape`) draw a creature (:func:`cshape.data.creatures.
creature_capsules`), mesh it once on a fine marching-cubes grid and remesh it three ways:
the question "is this the same object at another resolution?" of a real folder of meshes.
"""

from __future__ import annotations

import numbers
from functools import lru_cache
from typing import TYPE_CHECKING, Any

import numpy as np

from .._checks import check_choice, check_real
from ..mesh import Mesh, largest_component
from .bodies import Capsule, capsules_surface
from .creatures import CREATURE_KINDS, creature_capsules, creature_items
from .poses import POSED_KINDS, _blend_weights, _bone_transforms, _skeleton
from .variants import (
    _check_int,
    _from_meshset,
    _meshset,
    add_normal_noise,
    remesh,
)

__all__ = [
    "identity_pose",
]

if TYPE_CHECKING:
    from collections.abc import Iterable

    from numpy.typing import ArrayLike

    from .poses import _Bone

    #: how a bone's points map into an identity: (joint, length factor, thickness factor,
    #: the trunk's unit axis or None)
    _Scale = tuple[np.ndarray, float, float, np.ndarray | None]

#: The suite: benchmark name -> (development collection, held-out collection).
SUITE = {
    "creatures": ("creatures-dev", "creatures"),
    "identities": ("identities-dev", "identities"),
    "resolutions": ("resolutions-dev", "resolutions"),
}

#: What each benchmark asks (for tables and reports).
BENCHMARKS = {
    "creatures": "category level: 12 kinds x 10 members (proportions, pose, resolution, noise)",
    "identities": "instance level: 12 identities (6 humans, 6 quadrupeds) x 8 poses x 2 "
                  "resolutions",
    "resolutions": "same shape: 24 creatures x 3 meshings (remesh ~1000 / ~2500 vertices, "
                   "quadric decimation ~1800)",
}

#: The classes of :func:`identity_pose` (the skeletons of :mod:`cshape.data.poses`).
IDENTITY_KINDS = POSED_KINDS

#: Amplitudes of an identity's proportions (log-uniform factors in [1/(1+v), 1+v]).
IDENTITY_LENGTH_SPREAD, IDENTITY_THICKNESS_SPREAD = 0.3, 0.25

#: The limb group of each bone (bones of one group share their factors, so an identity is
#: left-right symmetric).
_GROUPS = {
    "torso": "trunk", "body": "trunk", "head": "head", "neck": "head", "tail": "tail",
    "upper_arm": "arms", "forearm": "arms", "thigh": "legs", "shin": "legs",
    "leg": "legs", "lower_leg": "legs",
}

#: The meshings of :func:`resolution_shape`: level -> (method, vertex count).
RESOLUTION_LEVELS = {
    "coarse": ("remesh", 1000),
    "fine": ("remesh", 2500),
    "decimated": ("decimate", 1800),
}


def _group(bone_name: str) -> str:
    return _GROUPS[bone_name.rstrip("-0123456789_")]  # 'leg_-1_1' -> 'leg'


# ---------------------------------------------------------------------- identities
def _map_point(bone: _Bone, scale: _Scale, x: ArrayLike) -> np.ndarray:
    """The rest-pose point ``x`` of ``bone`` in the identity: ``(J, L, T, axis)`` of
    ``scale``; along the bone's axis by ``L``, across it by ``T`` (the trunk) or by ``L``."""
    J, L, T, axis = scale
    v = np.asarray(x, float) - np.asarray(bone.joint, float)
    if axis is None:
        return J + L * v
    along = (v @ axis) * axis
    return J + L * along + T * (v - along)


def identity_bones(kind: str = "human", random_state: int | np.random.Generator | None = 0, *,
                   variation: float = 1.0) -> list[_Bone]:
    """The skeleton of an identity: the class's bones with its own proportions.

    Every limb group (trunk, head, arms, legs, tail) gets a length factor ``L`` and a
    thickness factor ``T`` (log-uniform, :data:`IDENTITY_LENGTH_SPREAD` and
    :data:`IDENTITY_THICKNESS_SPREAD` times ``variation``).  A bone's capsules scale about its
    joint by ``L`` (the trunk: ``L`` along its axis, ``T`` across, so limbs stay attached)
    and their radii by ``T``; a child's joint follows its parent's scaling.

    Returns
    -------
    list of the ``_Bone`` records of :mod:`cshape.data.poses`, same order and joints' axes.
    """
    from dataclasses import replace

    kind = check_choice("kind", kind, IDENTITY_KINDS)
    variation = check_real("variation", variation, min=0)
    rng = np.random.default_rng(random_state)
    bones = _skeleton(kind)
    factors: dict[str, tuple[float, float]] = {}
    for g in dict.fromkeys(_group(b.name) for b in bones):
        sl = np.log1p(IDENTITY_LENGTH_SPREAD * variation)
        st = np.log1p(IDENTITY_THICKNESS_SPREAD * variation)
        factors[g] = (float(np.exp(rng.uniform(-sl, sl))), float(np.exp(rng.uniform(-st, st))))
    scales: list[_Scale] = []
    out: list[_Bone] = []
    for b in bones:
        L, T = factors[_group(b.name)]
        if b.parent < 0:
            c = b.capsules[0]
            axis = np.asarray(c.b, float) - np.asarray(c.a, float)
            J = np.asarray(b.joint, float)
            scale = (J, L, T, axis / np.linalg.norm(axis))
        else:
            J = _map_point(bones[b.parent], scales[b.parent], b.joint)
            scale = (J, L, T, None)
        scales.append(scale)
        caps = tuple(Capsule(tuple(_map_point(b, scale, c.a)), tuple(_map_point(b, scale, c.b)),
                             c.radius * T) for c in b.capsules)
        out.append(replace(b, joint=tuple(J), capsules=caps))
    return out


@lru_cache(maxsize=64)
def _identity_surface(kind: str, seed: int, variation: float, voxelsize: float) -> Mesh:
    caps = [c for b in identity_bones(kind, seed, variation=variation) for c in b.capsules]
    return capsules_surface(caps, voxelsize)


@lru_cache(maxsize=64)
def _identity_template(kind: str, seed: int, variation: float, voxelsize: float, vertices: int
                       ) -> Mesh:
    mesh = remesh(_identity_surface(kind, seed, variation, voxelsize), target_vertices=vertices)
    return largest_component(mesh) if mesh.n_components > 1 else mesh


def identity_pose(kind: str = "human", random_state: int = 0, *, pose: int = 0,
                  vertices: int = 1200, variation: float = 1.0, noise: float = 0.3,
                  voxelsize: float = 0.015) -> Mesh:
    """One pose of one identity at one resolution.

    Parameters
    ----------
    kind : {'human', 'quadruped'}, default='human'
    random_state : int, default=0
        Seed of the identity (its proportions, :func:`identity_bones`).
    pose : int, default=0
        Seed of the joint angles (with the identity's seed), each uniform in the range of
        :mod:`cshape.data.poses`; the same ``pose`` gives the same angles at every resolution.
    vertices : int, default=1200
        Vertex count of the template's isotropic remeshing (its resolution).
    variation : float, default=1.0
        Scales the proportion spread (0: every identity is the class's mean body).
    noise : float, default=0.3
        Largest normal noise amplitude in mean edge lengths, as for the creatures: each
        pose at each resolution draws an amplitude ``a`` uniformly in ``[0, noise]`` and
        moves each vertex along its normal by ``[-a L, a L]`` (a scan's noise).
    voxelsize : float, default=0.015
        Marching-cubes voxel of the template (below half the thinnest radius).

    Returns
    -------
    Mesh
        Closed and connected; every pose of an identity at one resolution has the template's
        faces.
    """
    kind = check_choice("kind", kind, IDENTITY_KINDS)
    seed = _check_int("random_state", random_state, 0)
    pose = _check_int("pose", pose, 0)
    vertices = _check_int("vertices", vertices, 100, 1_000_000)
    template = _identity_template(kind, seed, float(variation), float(voxelsize), vertices)
    bones = identity_bones(kind, seed, variation=variation)
    rng = np.random.default_rng([seed, pose])
    angles = [[float(rng.uniform(min(d.lo, d.hi), max(d.lo, d.hi))) for d in b.dofs]
              for b in bones]
    V = template.vertices
    W = _blend_weights(bones, V)
    out = np.zeros_like(V)
    for b, (R, t) in enumerate(_bone_transforms(bones, angles)):
        out += W[:, b:b + 1] * (V @ R.T + t)
    mesh = Mesh(out, template.faces)
    noise = check_real("noise", noise, min=0)
    amp = float(np.random.default_rng([seed, pose, vertices]).uniform(0, noise))
    if amp > 0:
        mesh = add_normal_noise(mesh, amp, np.random.default_rng([seed, pose, vertices, 1]),
                                signed=True)
    return mesh


def identity_items(seed: int = 1, identities: int = 6, poses: int = 8,
                   resolutions: Iterable[int] = (1200, 2800),
                   kinds: Iterable[str] = IDENTITY_KINDS, params: dict[str, Any] | None = None
                   ) -> list[dict[str, Any]]:
    """The items of an identity benchmark instance, as ``data_manifest.yaml`` items.

    Identity ``k`` of the kind at position ``c`` of :data:`IDENTITY_KINDS` gets the seed
    ``1_000_000 * seed + 1000 * c + k`` (two instances share no identity); its items are
    ``<kind>-<k>-p<pose>-v<vertices>``, labelled ``<kind>-<k>``.

    Parameters
    ----------
    seed : int, default=1
        Instance seed.
    identities : int, default=6
        Identities (classes) per kind, 1 to 999.
    poses : int, default=8
        Poses of each identity, 1 to 999.
    resolutions : iterable of int, default=(1200, 2800)
        Approximate vertex counts; every pose is meshed at each (at least 100).
    kinds : iterable of str, default=('human', 'quadruped')
        Kinds of :data:`IDENTITY_KINDS`.
    params : dict, optional
        Further recipe parameters of every item (merged into its ``params``).

    Returns
    -------
    list of dict
        One manifest item per identity, pose and resolution (``name``, ``label``,
        ``recipe``, ``seed``, ``params``).
    """
    seed = _check_int("seed", seed, 0, 2000)
    identities = _check_int("identities", identities, 1, 999)
    poses = _check_int("poses", poses, 1, 999)
    res = [_check_int("resolutions", int(r) if isinstance(r, numbers.Integral) else r, 100)
           for r in resolutions]
    out: list[dict[str, Any]] = []
    for kind in kinds:
        ci = IDENTITY_KINDS.index(check_choice("kinds", kind, IDENTITY_KINDS))
        for k in range(identities):
            label = f"{kind}-{k:02d}"
            for p in range(poses):
                for v in res:
                    out.append({"name": f"{label}-p{p}-v{v}", "label": label,
                                "recipe": "identity",
                                "seed": 1_000_000 * seed + 1000 * ci + k,
                                "params": {"kind": kind, "pose": p, "vertices": v,
                                           **(params or {})}})
    return out


# ---------------------------------------------------------------------- resolutions
@lru_cache(maxsize=16)
def _fine_surface(kind: str, seed: int, voxelsize: float) -> Mesh:
    caps = creature_capsules(kind, seed)
    rmin = min(c.radius for c in caps)
    return capsules_surface(caps, min(voxelsize, rmin / 2.2))


def _decimate(mesh: Mesh, vertices: int) -> Mesh:
    ms = _meshset(mesh)
    # every parameter given, the others at PyMeshLab's defaults (see variants.remesh: one
    # left out may take an earlier call's value)
    ms.meshing_decimation_quadric_edge_collapse(
        targetfacenum=int(2 * vertices), targetperc=0.0, qualitythr=0.3,
        preserveboundary=False, boundaryweight=1.0, preservenormal=True,
        preservetopology=False, optimalplacement=True, planarquadric=False,
        planarweight=0.001, qualityweight=False, autoclean=True, selected=False)
    return _from_meshset(ms, what="quadric decimation")


def resolution_shape(kind: str = "human", random_state: int = 0, *, level: str = "coarse",
                     voxelsize: float = 0.025) -> Mesh:
    """One creature (:func:`cshape.data.creatures.creature_capsules`) in one meshing.

    Parameters
    ----------
    kind : str, default='human'
        A class of :data:`cshape.data.creatures.CREATURE_KINDS`.
    random_state : int, default=0
        Seed of the creature (proportions and pose); every level meshes the same surface.
    level : {'coarse', 'fine', 'decimated'}, default='coarse'
        See :data:`RESOLUTION_LEVELS`: isotropic remeshing to about 1000 or 2500 vertices, or
        quadric edge-collapse decimation to about 1800 (irregular triangles) of the
        marching-cubes surface (voxel ``min(voxelsize, thinnest radius / 2.2)``).
    voxelsize : float, default=0.025
        Largest marching-cubes voxel, in the creature's length units.

    Returns
    -------
    Mesh
        Closed and connected (the largest component).
    """
    kind = check_choice("kind", kind, CREATURE_KINDS)
    seed = _check_int("random_state", random_state, 0)
    level = check_choice("level", level, tuple(RESOLUTION_LEVELS))
    fine = _fine_surface(kind, seed, float(voxelsize))
    method, n = RESOLUTION_LEVELS[level]
    mesh = remesh(fine, target_vertices=n) if method == "remesh" else _decimate(fine, n)
    return largest_component(mesh) if mesh.n_components > 1 else mesh


def resolution_items(seed: int = 1, members: int = 2, kinds: Iterable[str] | None = None,
                     levels: Iterable[str] = tuple(RESOLUTION_LEVELS),
                     params: dict[str, Any] | None = None) -> list[dict[str, Any]]:
    """Return the items of a resolution benchmark instance, as ``data_manifest.yaml`` items.

    ``members`` creatures of every kind, each a class ``<kind>-<k>``, in every meshing of
    ``levels`` (``<kind>-<k>-<level>``).  Creature seeds are those of
    :func:`cshape.data.creatures.creature_items` plus 500, so no shape is also a member of
    a creature benchmark instance.

    Parameters
    ----------
    seed : int, default=1
        Instance seed.
    members : int, default=2
        Creatures (classes) per kind.
    kinds : iterable of str, optional
        Kinds of :data:`cshape.data.creatures.CREATURE_KINDS` (default all).
    levels : iterable of str, default=('coarse', 'fine', 'decimated')
        Meshings of :data:`RESOLUTION_LEVELS`.
    params : dict, optional
        Further recipe parameters of every item (merged into its ``params``).

    Returns
    -------
    list of dict
        One manifest item per creature and level (``name``, ``label``, ``recipe``,
        ``seed``, ``params``).
    """
    levels = [check_choice("levels", lv, tuple(RESOLUTION_LEVELS)) for lv in levels]
    out: list[dict[str, Any]] = []
    for it in creature_items(seed=seed, members=members, kinds=kinds):
        for level in levels:
            out.append({"name": f"{it['name']}-{level}",
                        "label": it["name"], "recipe": "resolution", "seed": it["seed"] + 500,
                        "params": {"kind": it["label"], "level": level, **(params or {})}})
    return out
