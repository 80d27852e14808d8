"""A generated retrieval benchmark that does not saturate: twelve classes of creatures.

The generated collections ``paper-models`` and ``articulated`` are too easy for retrieval:
their classes differ in topology and every pose of a class has the same bone lengths, so
every descriptor finds the right class every time (nearest neighbour = first tier = 1).
:func:`creature` draws a member of a class with the variation a real benchmark has
(McGill, SHREC'07):

* **proportions**: every limb group (arms, legs, tentacles, ...) gets its own length factor
  and thickness factor, log-uniform in ``[1/(1+v_l), 1+v_l]`` and ``[1/(1+v_t), 1+v_t]``
  (``v_l = 0.35``, ``v_t = 0.25`` times ``variation``), and the body its own;
* **pose**: joint angles uniform in ranges chosen per class (near-isometric changes);
* **resolution**: the remeshed vertex count is uniform in ``vertices`` (default 1500 to
  4000), the marching-cubes voxel follows the thinnest limb;
* **noise**: every vertex moves along its normal by a uniform amount in ``[-a L, a L]``
  (``L`` the mean edge length) with ``a`` uniform in ``[0, noise]`` (default 0.3).

A creature is a union of capsules (:class:`cshape.data.bodies.Capsule`) meshed by PyMeshLab's
marching cubes, isotropically remeshed and made noisy, all from one ``random_state``: the
same seed gives the same mesh.  :func:`creature_items` lists the members of a benchmark
instance for a collection seed; ``data_manifest.yaml`` has a development instance
(``creatures-dev``, seed 0: choose and tune anything on it), a held-out instance
(``creatures``, seed 1: report numbers on it) and a small one for tests and lessons
(``creatures-small``).
"""

from __future__ import annotations

import numbers
from typing import TYPE_CHECKING, Any

import numpy as np

from .._checks import check_choice, check_real
from ..mesh import Mesh, largest_component
from .bodies import Capsule, _bend, _dir, _limb, _rot_z, capsules_surface
from .variants import _check_int, add_normal_noise, remesh

if TYPE_CHECKING:
    from collections.abc import Iterable

__all__ = [
    "creature",
]

#: The classes of :func:`creature`, in the order of the benchmark's items.
CREATURE_KINDS = (
    "human", "centaur", "teddy", "quadruped", "bird", "spider", "ant", "crab", "octopus",
    "starfish", "hand", "snake",
)

#: Base amplitudes of the proportion variation (log-uniform factors in [1/(1+v), 1+v]).
LENGTH_SPREAD, THICKNESS_SPREAD = 0.35, 0.25


class _Draw:
    """The random draws of one member: factors, angles and jitters from one generator."""

    def __init__(self, rng: np.random.Generator, variation: float) -> None:
        self.rng = rng
        self.variation = variation

    def u(self, lo: float, hi: float) -> float:
        return float(self.rng.uniform(lo, hi))

    def factor(self, spread: float) -> float:
        """Log-uniform factor in ``[1/(1+s), 1+s]`` with ``s = spread * variation``."""
        s = np.log1p(spread * self.variation)
        return float(np.exp(self.rng.uniform(-s, s)))

    def group(self) -> tuple[float, float]:
        """(length factor, thickness factor) of one limb group."""
        return self.factor(LENGTH_SPREAD), self.factor(THICKNESS_SPREAD)

    def jitter(self) -> float:
        """A small per-limb length jitter (+-10 % at variation 1)."""
        return self.factor(0.1)


def creature_capsules(kind: str, random_state: int | np.random.Generator | None = None, *,
                      variation: float = 1.0) -> list[Capsule]:
    """The capsules of one member of a creature class.

    Parameters
    ----------
    kind : str
        One of :data:`CREATURE_KINDS`.
    random_state : int, numpy.random.Generator or None
        Seed of the proportions and the pose.
    variation : float, default=1.0
        Scales the amplitude of the proportion variation (0: every member has the class's
        mean proportions, only the pose changes).

    Returns
    -------
    list of Capsule
        Connected (every limb starts inside the body), about 1 to 2 units across.
    """
    kind = check_choice("kind", kind, CREATURE_KINDS)
    variation = check_real("variation", variation, min=0)
    d = _Draw(np.random.default_rng(random_state), variation)
    return _BUILDERS[kind](d)


# ---------------------------------------------------------------------- the classes
def _human_upper(d: _Draw, base: tuple[float, float, float], caps: list[Capsule], *,
                 torso_len: float = 0.55, torso_r: float = 0.16) -> float:
    """Torso from ``base`` upwards, neck, head and two arms (human, centaur)."""
    fb, tb = d.group()
    fa, ta = d.group()
    x0, y0, z0 = base
    top = z0 + torso_len * fb
    caps.append(Capsule((x0, y0, z0), (x0, y0, top), torso_r * tb))
    caps.append(Capsule((x0, y0, top), (x0, y0, top + 0.17 * fb), 0.06 * tb))  # neck
    hr = 0.13 * d.factor(0.2)
    caps.append(Capsule((x0, y0, top + 0.17 * fb + hr * 0.6), (x0, y0, top + 0.2 * fb + hr),
                        hr))
    for s in (-1, 1):
        shoulder = (x0 + (torso_r * tb + 0.03) * s, y0, top - 0.05)
        abduct, flex, fwd = d.u(20, 90), d.u(0, 100), d.u(-40, 40)
        upper = np.array([s * np.sin(np.radians(abduct)), 0, -np.cos(np.radians(abduct))])
        upper = _rot_z(upper, s * fwd)
        fore = _bend(upper, flex, np.array([0, 1.0, 0]))
        j = d.jitter()
        caps += _limb(shoulder, [upper, fore], [0.3 * fa * j, 0.28 * fa * j], 0.055 * ta)
    return top


def _human(d: _Draw) -> list[Capsule]:
    caps: list[Capsule] = []
    _human_upper(d, (0, 0, 0), caps)
    fl, tl = d.group()
    for s in (-1, 1):
        hip = (0.09 * s, 0, 0.0)
        spread, swing, knee = d.u(0, 30), d.u(-40, 40), d.u(0, 90)
        thigh = np.array([s * np.sin(np.radians(spread)), 0, -np.cos(np.radians(spread))])
        thigh = _bend(thigh, swing, np.array([0, 1.0, 0]))
        shin = _bend(thigh, knee, np.array([0, -1.0, 0]))
        j = d.jitter()
        caps += _limb(hip, [thigh, shin], [0.4 * fl * j, 0.4 * fl * j], 0.07 * tl)
    return caps


def _four_legs(d: _Draw, caps: list[Capsule], half: float, width: float, z: float, fl: float,
               tl: float, *, upper: float = 0.28, lower: float = 0.26, r: float = 0.055) -> None:
    for sx in (-1, 1):
        for sy in (-1, 1):
            swing, knee, splay = d.u(-35, 35), d.u(0, 70), d.u(-15, 15)
            up = _rot_z(_dir(0, -90 + swing), sy * splay)
            lo = _rot_z(_dir(0, -90 + swing - sx * knee), sy * splay)
            j = d.jitter()
            caps += _limb((half * sx, width * sy, z), [up, lo], [upper * fl * j, lower * fl * j],
                          r * tl)


def _tail(d: _Draw, start: tuple[float, float, float], azimuths: tuple[float, float],
          elevations: tuple[float, float], length: float, radius: float) -> list[Capsule]:
    """A one-capsule tail: direction, length and thickness of its own."""
    return _limb(start, [_dir(d.u(*azimuths), d.u(*elevations))],
                 [length * d.factor(LENGTH_SPREAD)], radius * d.factor(THICKNESS_SPREAD))


def _quadruped(d: _Draw) -> list[Capsule]:
    fb, tb = d.group()
    fl, tl = d.group()
    half = 0.45 * fb
    caps = [Capsule((-half, 0, 0), (half, 0, 0), 0.17 * tb)]
    fn, tn = d.group()
    neck = _limb((half, 0, 0.05), [_dir(d.u(-20, 20), d.u(15, 75))], [0.3 * fn], 0.08 * tn)
    head = _limb(neck[-1].b, [_dir(d.u(-30, 30), d.u(-45, 10))], [0.22 * d.factor(0.2)],
                 0.09 * tn)
    caps += neck + head
    _four_legs(d, caps, 0.75 * half, 0.09 * tb, -0.05, fl, tl)
    caps += _tail(d, (-half, 0, 0.05), (140, 220), (-45, 45), 0.32, 0.045)
    return caps


def _centaur(d: _Draw) -> list[Capsule]:
    fb, tb = d.group()
    fl, tl = d.group()
    half = 0.4 * fb
    caps = [Capsule((-half, 0, 0), (half, 0, 0), 0.16 * tb)]
    _four_legs(d, caps, 0.75 * half, 0.09 * tb, -0.05, fl, tl)
    lean = d.u(-20, 30)
    base = (half, 0, 0.05)
    caps += _limb(base, [_dir(0, 90 - lean)], [0.12], 0.12 * tb)
    _human_upper(d, (half + 0.12 * np.sin(np.radians(lean)), 0, 0.1), caps,
                 torso_len=0.38, torso_r=0.12)
    caps += _tail(d, (-half, 0, 0.05), (150, 210), (-50, 30), 0.3, 0.04)
    return caps


def _teddy(d: _Draw) -> list[Capsule]:
    fb, tb = d.group()
    fa, ta = d.group()
    fl, tl = d.group()
    br = 0.26 * tb
    top = 0.3 * fb
    caps = [Capsule((0, 0, 0), (0, 0, top), br)]
    hr = 0.2 * d.factor(THICKNESS_SPREAD)
    hz = top + br + 0.6 * hr
    caps.append(Capsule((0, 0, hz), (0, 0, hz), hr))
    er = 0.07 * d.factor(THICKNESS_SPREAD)
    for s in (-1, 1):
        ear = np.array([0, 0, hz]) + hr * _dir(90 - s * 90, d.u(35, 60))
        caps.append(Capsule(tuple(ear), tuple(ear), er))
    caps.append(Capsule((0, 0, hz - 0.05), (0, hr + 0.06 * d.factor(0.3), hz - 0.07),
                        0.07 * d.factor(0.2)))  # snout
    for s in (-1, 1):
        arm = _dir(90 - s * 90 + d.u(-30, 30), d.u(-60, 20))
        caps += _limb((s * 0.8 * br, 0, top), [arm], [0.28 * fa], 0.085 * ta)
        leg = _dir(90 + s * d.u(5, 40), d.u(-40, 0))
        caps += _limb((s * 0.6 * br, 0, 0.0), [leg], [0.3 * fl], 0.1 * tl)
    return caps


def _bird(d: _Draw) -> list[Capsule]:
    fb, tb = d.group()
    fw, tw = d.group()
    half = 0.25 * fb
    caps = [Capsule((-half, 0, 0), (half, 0, 0.05), 0.13 * tb)]
    neck = _limb((half, 0, 0.05), [_dir(d.u(-20, 20), d.u(30, 80))], [0.18 * d.factor(0.3)],
                 0.06 * tb)
    head = neck[-1].b
    caps += neck + [Capsule(head, head, 0.09 * d.factor(0.2))]
    caps += _limb(head, [_dir(d.u(-20, 20), d.u(-30, 10))], [0.16 * d.factor(0.3)], 0.04)
    for s in (-1, 1):
        flap, fold, sweep = d.u(-30, 60), d.u(0, 60), d.u(-20, 30)
        inner = _rot_z(_dir(90 * s, flap), -s * sweep)
        outer = _bend(inner, fold, np.array([-1.0, 0, -0.3]))
        j = d.jitter()
        caps += _limb((0, 0.08 * s, 0.05), [inner, outer], [0.35 * fw * j, 0.35 * fw * j],
                      0.05 * tw)
        caps += _limb((0.05, 0.06 * s, -0.08), [_dir(d.u(-30, 30), -90 + d.u(-20, 20))],
                      [0.2 * d.factor(0.3)], 0.04)
    caps += _limb((-half, 0, 0), [_dir(180 + d.u(-20, 20), d.u(-30, 30))],
                  [0.25 * d.factor(LENGTH_SPREAD)], 0.05 * d.factor(THICKNESS_SPREAD))
    return caps


def _radial_legs(d: _Draw, caps: list[Capsule], n: int, r_attach: float, z: float,
                 lengths: tuple[float, float], radius: float, *,
                 up: tuple[float, float] = (0, 40), down: tuple[float, float] = (-80, -25),
                 az0: float = 0.0, az_jit: float = 10.0) -> None:
    fl, tl = d.group()
    for k in range(n):
        az = az0 + 360.0 * k / n + d.u(-az_jit, az_jit)
        j = d.jitter()
        start = r_attach * _dir(az, 0) + np.array([0, 0, z])
        caps += _limb(start, [_dir(az, d.u(*up)), _dir(az, d.u(*down))],
                      [lengths[0] * fl * j, lengths[1] * fl * j], radius * tl)


def _spider(d: _Draw) -> list[Capsule]:
    fb, tb = d.group()
    caps = [Capsule((0, 0, 0), (0, 0, 0.08), 0.2 * tb),
            Capsule((-0.15 * fb, 0, 0.04), (-0.35 * fb, 0, 0.08), 0.17 * tb)]  # abdomen
    _radial_legs(d, caps, 8, 0.16 * tb, 0.04, (0.32, 0.38), 0.045, az0=22.5)
    return caps


def _ant(d: _Draw) -> list[Capsule]:
    fb, tb = d.group()
    rt, rh, ra = 0.085 * tb, 0.1 * tb, 0.14 * tb
    t1 = 0.18 * fb  # thorax from x = 0 to t1; head and abdomen overlap its ends
    head = (t1 + 0.8 * (rt + rh), 0, 0.05)
    caps = [Capsule(head, head, rh),
            Capsule((0, 0, 0), (t1, 0, 0.02), rt),
            Capsule((-0.8 * (rt + ra), 0, 0.02), (-0.8 * (rt + ra) - 0.28 * fb, 0, 0.08), ra)]
    fl, tl = d.group()
    for k, x in enumerate((0.9, 0.5, 0.1)):
        for s in (-1, 1):
            az = s * (60 - 40 * k + d.u(-10, 10))
            j = d.jitter()
            caps += _limb((x * t1, 0.05 * s, 0.0), [_dir(az, d.u(10, 45)), _dir(az, d.u(-80, -30))],
                          [0.25 * fl * j, 0.3 * fl * j], 0.04 * tl)
    for s in (-1, 1):
        caps += _limb(head, [_dir(s * d.u(15, 45), d.u(20, 60))], [0.2 * d.factor(0.3)], 0.04)
    return caps


def _crab(d: _Draw) -> list[Capsule]:
    fb, tb = d.group()
    w = 0.22 * fb
    caps = [Capsule((0.03, -w, 0), (0.03, w, 0), 0.13 * tb),
            Capsule((-0.07, -0.8 * w, 0), (-0.07, 0.8 * w, 0), 0.12 * tb)]
    fl, tl = d.group()
    for s in (-1, 1):
        for k in range(4):
            az = s * (60 + 25 * k + d.u(-8, 8))
            j = d.jitter()
            caps += _limb((-0.04 * k, s * w * 0.9, 0), [_dir(az, d.u(10, 40)),
                                                       _dir(az, d.u(-75, -30))],
                          [0.22 * fl * j, 0.25 * fl * j], 0.04 * tl)
    fc, tc = d.group()
    for s in (-1, 1):
        arm = _limb((0.1, s * w * 0.7, 0), [_dir(s * d.u(20, 50), d.u(-10, 30)),
                                              _dir(s * d.u(-20, 20), d.u(-10, 20))],
                    [0.18 * fc, 0.15 * fc], 0.05 * tc)
        tip = arm[-1].b
        opening = d.u(10, 40)
        for t in (-1, 1):
            caps += _limb(tip, [_dir(s * (t * opening / 2) + d.u(-10, 10), 0)], [0.14 * fc],
                          0.045 * tc)
        caps += arm + [Capsule(tip, tip, 0.075 * tc)]
    return caps


def _octopus(d: _Draw) -> list[Capsule]:
    fb, tb = d.group()
    fl, tl = d.group()
    caps = [Capsule((0, 0, 0.08), (d.u(-0.1, 0.1), 0, 0.08 + 0.32 * fb), 0.2 * tb)]
    for k in range(8):
        az = 45.0 * k + d.u(-10, 10)
        p = 0.14 * tb * _dir(az, 0)
        heading, el = az, d.u(-40, 0)
        segs, radii = [], (0.07, 0.055, 0.045)
        j = d.jitter()
        dirs = []
        for _ in range(3):
            dirs.append(_dir(heading, el))
            heading += d.u(-35, 35)
            el = float(np.clip(el + d.u(-35, 35), -80, 40))
        for dd, rr in zip(dirs, radii, strict=True):
            segs += _limb(p, [dd], [0.2 * fl * j], rr * tl)
            p = segs[-1].b
        caps += segs
    return caps


def _starfish(d: _Draw) -> list[Capsule]:
    fb, tb = d.group()
    fl, tl = d.group()
    caps = [Capsule((0, 0, -0.02), (0, 0, 0.02), 0.15 * tb)]
    for k in range(5):
        az = 72.0 * k + d.u(-12, 12)
        p = np.zeros(3)
        heading, el = az, d.u(-15, 15)
        j = d.jitter()
        for rr in (0.1, 0.08, 0.06):
            seg = _limb(p, [_dir(heading, el)], [0.2 * fl * j], rr * tl)
            caps += seg
            p = np.asarray(seg[-1].b)
            heading += d.u(-25, 25)
            el = float(np.clip(el + d.u(-25, 25), -40, 40))
    return caps


def _hand(d: _Draw) -> list[Capsule]:
    fb, tb = d.group()
    fl, tl = d.group()
    h = 0.4 * fb
    caps = [Capsule((x, 0, 0), (x, 0, h), 0.075 * tb) for x in (-0.1, 0.0, 0.1)]
    caps.append(Capsule((0, 0, -0.08), (0, 0, -0.25 * fb), 0.09 * tb))  # wrist
    for k, (x, length) in enumerate(((-0.13, 0.75), (-0.045, 0.95), (0.045, 1.0),
                                     (0.13, 0.85))):
        spread = (k - 1.5) * d.u(0, 8)
        curl = [d.u(0, 60) for _ in range(3)]
        direc = np.array([np.sin(np.radians(spread)), 0, np.cos(np.radians(spread))])
        dirs = []
        for c in curl:
            direc = _bend(direc, c, np.array([0, 1.0, 0]))
            dirs.append(direc)
        j = d.jitter()
        seg = [0.17 * length * fl * j, 0.12 * length * fl * j, 0.09 * length * fl * j]
        caps += _limb((x, 0, h), dirs, seg, 0.045 * tl)
    th = _bend(np.array([-1.0, 0, 0.3]) / np.hypot(1, 0.3), d.u(0, 50), np.array([0, 1.0, 0]))
    th2 = _bend(th, d.u(0, 50), np.array([0, 1.0, 0]))
    caps += _limb((-0.12, 0, 0.12 * fb), [th, th2], [0.16 * fl, 0.13 * fl], 0.05 * tl)
    return caps


def _snake(d: _Draw) -> list[Capsule]:
    fb, tb = d.group()
    p, heading, pitch = np.zeros(3), 0.0, 0.0
    caps = []
    n = 9
    for i in range(n):
        heading += d.u(-35, 35)
        pitch = float(np.clip(pitch + d.u(-15, 15), -25, 25))
        r = 0.08 * tb * (1.0 - 0.45 * max(0, i - n + 4) / 4)  # tapering tail
        q = p + 0.24 * fb * _dir(heading, pitch)
        caps.append(Capsule(tuple(p), tuple(q), r))
        p = q
    caps.append(Capsule(caps[0].a, caps[0].a, 0.1 * tb * d.factor(0.2)))  # head
    return caps


_BUILDERS = {
    "human": _human, "centaur": _centaur, "teddy": _teddy, "quadruped": _quadruped,
    "bird": _bird, "spider": _spider, "ant": _ant, "crab": _crab, "octopus": _octopus,
    "starfish": _starfish, "hand": _hand, "snake": _snake,
}


# ---------------------------------------------------------------------- meshing
def creature(kind: str = "human", random_state: int | np.random.Generator | None = 0, *,
             variation: float = 1.0, vertices: int | tuple[int, int] = (1500, 4000),
             noise: float = 0.3, voxelsize: float | None = None) -> Mesh:
    """One member of a creature class: capsules, marching cubes, remesh, normal noise.

    Parameters
    ----------
    kind : str, default='human'
        One of :data:`CREATURE_KINDS`.
    random_state : int, numpy.random.Generator or None, default=0
        Seed of everything (proportions, pose, resolution, noise); same seed, same mesh.
    variation : float, default=1.0
        Amplitude of the proportion variation (see :func:`creature_capsules`).
    vertices : (int, int) or int, default=(1500, 4000)
        The remeshed vertex count is drawn uniformly from this range (an int fixes it).
    noise : float, default=0.3
        Largest normal noise amplitude in mean edge lengths; each member draws its own
        amplitude ``a`` uniformly in ``[0, noise]`` and moves each vertex by ``[-a L, a L]``.
    voxelsize : float, optional
        Marching-cubes voxel; default: the thinnest capsule radius / 2.2, at most 0.025.

    Returns
    -------
    Mesh
        Closed and connected (the outer surface; a void enclosed where limbs cross is
        dropped).
    """
    lo, hi = ((vertices, vertices) if isinstance(vertices, (int, numbers.Integral))
              else tuple(vertices))
    lo = _check_int("vertices", lo, 100, 1_000_000)
    hi = _check_int("vertices", hi, lo, 1_000_000)
    noise = check_real("noise", noise, min=0)
    rng = np.random.default_rng(random_state)
    caps = creature_capsules(kind, rng, variation=variation)
    rmin = min(c.radius for c in caps)
    vs = min(0.025, rmin / 2.2) if voxelsize is None else float(voxelsize)
    mesh = capsules_surface(caps, vs)
    mesh = remesh(mesh, target_vertices=int(rng.integers(lo, hi + 1)))
    if mesh.n_components > 1:
        # where limbs cross, marching cubes can enclose a small void: an inner shell of a few
        # vertices that would add a zero eigenvalue; the creature is the outer surface
        mesh = largest_component(mesh)
    amp = float(rng.uniform(0, noise))
    if amp > 0:
        mesh = add_normal_noise(mesh, amp, rng, signed=True)
    return mesh


def creature_items(seed: int = 1, members: int = 10, kinds: Iterable[str] | None = None,
                   params: dict[str, Any] | None = None) -> list[dict[str, Any]]:
    """The items of a creature benchmark instance, as ``data_manifest.yaml`` items.

    Member ``k`` of the class at position ``c`` of :data:`CREATURE_KINDS` gets the item seed
    ``1_000_000 * seed + 1000 * c + k``, so two instances (two ``seed``) share no member
    and an instance with more members contains the smaller one.

    Parameters
    ----------
    seed : int, default=1
        Instance seed (the manifest: 0 development, 1 held out).
    members : int, default=10
        Members per class, 1 to 999.
    kinds : sequence of str, optional
        Classes (default :data:`CREATURE_KINDS`).
    params : dict, optional
        Extra parameters of :func:`creature` for every item.

    Returns
    -------
    list of dict
        ``{'name': 'human-00', 'label': 'human', 'recipe': 'creature', 'seed': ...,
        'params': {'kind': 'human', ...}}`` per member, class by class.
    """
    seed = _check_int("seed", seed, 0, 2000)
    members = _check_int("members", members, 1, 999)
    kinds = CREATURE_KINDS if kinds is None else tuple(
        check_choice("kinds", k, CREATURE_KINDS) for k in kinds)
    out: list[dict[str, Any]] = []
    for kind in kinds:
        ci = CREATURE_KINDS.index(kind)
        for k in range(members):
            out.append({"name": f"{kind}-{k:02d}", "label": kind, "recipe": "creature",
                        "seed": 1_000_000 * seed + 1000 * ci + k,
                        "params": {"kind": kind, **(params or {})}})
    return out
