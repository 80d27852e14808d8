"""The creature benchmark (cshape.data.creatures) and its manifest collections: deterministic,
sized, cached, varied within a class, and hard enough that retrieval does not saturate."""

from __future__ import annotations

import copy

import numpy as np
import pytest

import cshape
import cshape.data as data
from cshape.compare import retrieval_scores
from cshape.data import bodies
from cshape.data import creatures as cr
from cshape.data import variants as v

#: Small and fast: coarse grid, few vertices (the meshes are still closed).
FAST = {"vertices": [300, 400], "voxelsize": 0.035}


@pytest.fixture(autouse=True)
def _isolated_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("CSHAPE_CACHE", str(tmp_path / "cache"))
    monkeypatch.delenv("CSHAPE_MANIFEST", raising=False)


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    """creatures-small (12 classes x 3, as shipped) built once, and its Shape-DNA N=100."""
    cache = tmp_path_factory.mktemp("creatures-cache")
    coll = data.load_collection("creatures-small", cache_dir=cache, progress=False)
    table = cshape.describe(coll, N=100, cache_dir=cache / "eig", progress=False, n_jobs=1)
    return cache, coll, table


# ---------------------------------------------------------------------- capsules
def _bones(caps):
    return np.array([np.linalg.norm(np.subtract(c.b, c.a)) for c in caps])


def test_capsules_are_seeded_and_vary_within_a_class():
    a = cr.creature_capsules("human", 3)
    assert a == cr.creature_capsules("human", 3)
    b = cr.creature_capsules("human", 4)
    assert len(a) == len(b)  # same skeleton ...
    assert not np.allclose(_bones(a), _bones(b))  # ... other proportions
    assert not np.allclose([c.radius for c in a], [c.radius for c in b])


def test_variation_zero_keeps_the_proportions_and_changes_the_pose():
    a = cr.creature_capsules("spider", 1, variation=0)
    b = cr.creature_capsules("spider", 2, variation=0)
    np.testing.assert_allclose(_bones(a), _bones(b))
    np.testing.assert_allclose([c.radius for c in a], [c.radius for c in b])
    assert not np.allclose([c.b for c in a], [c.b for c in b])  # joint angles differ


def test_proportions_stay_in_the_documented_range():
    # the human's torso is the first capsule: 0.55 times the body's length factor
    lengths = [_bones(cr.creature_capsules("human", s))[0] / 0.55 for s in range(40)]
    assert 1 / 1.35 <= min(lengths) and max(lengths) <= 1.35
    assert max(lengths) / min(lengths) > 1.3  # the range is used


@pytest.mark.parametrize("kind", cr.CREATURE_KINDS)
def test_every_class_gives_a_connected_closed_mesh(kind):
    m = cr.creature(kind, 0, **{**FAST, "vertices": tuple(FAST["vertices"])})
    assert m.is_closed and m.n_components == 1
    assert 150 < m.n_vertices < 700


def test_creature_is_deterministic_and_seeded():
    a = cr.creature("snake", 5, vertices=300, voxelsize=0.04)
    b = cr.creature("snake", 5, vertices=300, voxelsize=0.04)
    c = cr.creature("snake", 6, vertices=300, voxelsize=0.04)
    np.testing.assert_array_equal(a.vertices, b.vertices)
    np.testing.assert_array_equal(a.faces, b.faces)
    assert a.n_vertices != c.n_vertices or not np.allclose(a.vertices, c.vertices)


def test_noise_zero_is_the_clean_remesh():
    clean = cr.creature("snake", 2, vertices=300, voxelsize=0.04, noise=0)
    noisy = cr.creature("snake", 2, vertices=300, voxelsize=0.04, noise=1.0)
    np.testing.assert_array_equal(clean.faces, noisy.faces)  # same remesh, moved vertices
    d = np.linalg.norm(noisy.vertices - clean.vertices, axis=1)
    assert 0 < d.max() <= 1.0 * clean.mean_edge_length


def test_capsules_expression_cutoff_keeps_the_surface():
    caps = cr.creature_capsules("starfish", 0)
    pts = np.array([c.a for c in caps] + [c.b for c in caps])
    box = (*(pts.min(0) - 0.3), *(pts.max(0) + 0.3))
    full = v.marching_cubes(bodies.capsules_expression(caps), box, 0.04)
    cut = v.marching_cubes(bodies.capsules_expression(caps, cutoff=0.12), box, 0.04)
    np.testing.assert_allclose(cut.vertices, full.vertices, atol=1e-9)
    np.testing.assert_array_equal(cut.faces, full.faces)
    with pytest.raises(ValueError, match="cutoff must be a positive finite number"):
        bodies.capsules_expression(caps, cutoff=0)


@pytest.mark.parametrize("kind", ["octopus", "crab", "human"])
def test_capsules_expression_tree_gives_the_bits_of_one_capsule_at_a_time(kind):
    """With a cutoff, the capsules are tested in a tree of boxes; the marching cubes are those
    of the capsules tested one by one (written out here), to the last bit: creatures and
    figures are the same meshes as before the tree."""
    caps = cr.creature_capsules(kind, 3)
    cutoff, voxel = 0.12, 0.04
    flat = []
    for c in caps:
        a, b = np.asarray(c.a, dtype=float), np.asarray(c.b, dtype=float)
        lo, hi = np.minimum(a, b) - c.radius - cutoff, np.maximum(a, b) + c.radius + cutoff
        inside = "&&".join(f"({x}>{p:.9g})&&({x}<{q:.9g})"
                           for x, p, q in zip("xyz", lo, hi, strict=True))
        flat.append(f"(({inside})?({c.expression()}):{cutoff:.9g})")
    one_by_one = flat[0]
    for e in flat[1:]:
        one_by_one = f"min({one_by_one},{e})"
    tree = bodies.capsules_expression(caps, cutoff=cutoff)
    assert tree.count("?") > len(caps)  # the groups' boxes are tested too
    pts = np.array([c.a for c in caps] + [c.b for c in caps])
    box = (*(pts.min(0) - 0.3), *(pts.max(0) + 0.3))
    ref = v.marching_cubes(one_by_one, box, voxel)
    got = v.marching_cubes(tree, box, voxel)
    np.testing.assert_array_equal(got.vertices, ref.vertices)
    np.testing.assert_array_equal(got.faces, ref.faces)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: cr.creature_capsules("dragon", 0), r"kind must be one of \{'human'"),
        (lambda: cr.creature_capsules("human", 0, variation=-1), "variation must be"),
        (lambda: cr.creature("human", 0, noise=-0.1), "noise must be a finite number >= 0"),
        (lambda: cr.creature("human", 0, vertices=(4000, 1500)), "vertices must be an integer"),
        (lambda: cr.creature_items(seed=-1), "seed must be an integer"),
        (lambda: cr.creature_items(members=0), "members must be an integer"),
        (lambda: cr.creature_items(kinds=["human", "elf"]), r"kinds must be one of"),
    ],
)
def test_bad_arguments_are_named(call, match):
    with pytest.raises(ValueError, match=match):
        call()


# ---------------------------------------------------------------------- items and manifest
def test_items_of_two_seeds_share_no_member_and_grow_by_prefix():
    dev, held = cr.creature_items(0, 10), cr.creature_items(1, 10)
    assert len(dev) == len(held) == 10 * len(cr.CREATURE_KINDS)
    assert not {it["seed"] for it in dev} & {it["seed"] for it in held}
    assert len({it["seed"] for it in dev}) == len(dev)
    assert [it["name"] for it in dev] == [it["name"] for it in held]
    three = cr.creature_items(0, 3)
    assert all(it in dev for it in three)  # a smaller instance is part of the larger one
    assert dev[0] == {"name": "human-00", "label": "human", "recipe": "creature",
                      "seed": 0, "params": {"kind": "human"}}


def test_manifest_has_dev_heldout_and_small_instances():
    held, dev, small = (data.info(n) for n in ("creatures", "creatures-dev", "creatures-small"))
    assert held["generate"]["seed"] != dev["generate"]["seed"]
    for e, members in ((held, 10), (dev, 10), (small, 3)):
        labels = [it["label"] for it in e["items"]]
        assert sorted(set(labels)) == sorted(cr.CREATURE_KINDS)
        assert all(labels.count(k) == members for k in set(labels))
    said = " ".join(held["description"].split()).lower()
    for word in ("proportions", "pose", "resolution", "noise", "held-out"):  # what it varies
        assert word in said


@pytest.mark.parametrize(
    "mutate, match",
    [
        (lambda e: e.update(items=[]), "either 'items'.*or 'generate'"),
        (lambda e: e["generate"].update(colour=1), r"'generate' has unknown key\(s\) \['colour'\]"),
        (lambda e: e["generate"].update(members=0), "'generate': members must be"),
        (lambda e: e["generate"].update(params={"wings": 2}),
         "recipe 'creature' has no parameter 'wings'"),
    ],
)
def test_generate_field_is_validated(mutate, match):
    e = {"name": "c", "kind": "generated", "description": "d", "license": "l",
         "citation": "c", "generate": {"seed": 0, "members": 1}}
    mutate(e)
    with pytest.raises(ValueError, match=match):
        data.manifest.validate_manifest(copy.deepcopy({"version": 1, "collections": [e]}))


@pytest.mark.slow
def test_load_creatures_is_cached_and_reproducible(tmp_path):
    kw = {"members": 2, "kinds": ["snake", "teddy"], **FAST}
    a = data.store.load_creatures(3, cache_dir=tmp_path / "a", progress=False, **kw)
    assert a.names == ["snake-00", "snake-01", "teddy-00", "teddy-01"]
    assert a.labels == ["snake", "snake", "teddy", "teddy"]
    files = sorted((tmp_path / "a").rglob("*.npz"))
    assert len(files) == 4
    mtimes = [f.stat().st_mtime_ns for f in files]
    again = data.store.load_creatures(3, cache_dir=tmp_path / "a", progress=False, **kw)
    assert [f.stat().st_mtime_ns for f in files] == mtimes  # read, not rebuilt
    fresh = data.store.load_creatures(3, cache_dir=tmp_path / "b", progress=False, **kw)
    other = data.store.load_creatures(4, cache_dir=tmp_path / "a", progress=False, **kw)
    for x, y, z in zip(again, fresh, other, strict=True):
        np.testing.assert_array_equal(x.mesh.vertices, y.mesh.vertices)  # same seed
        assert x.mesh.n_vertices != z.mesh.n_vertices or not np.allclose(
            x.mesh.vertices, z.mesh.vertices)  # another seed
    assert len(sorted((tmp_path / "a").rglob("*.npz"))) == 8
    parallel = data.store.load_creatures(3, cache_dir=tmp_path / "c", progress=False, n_jobs=2,
                                         **kw)
    assert parallel.names == fresh.names and parallel.labels == fresh.labels
    for x, y in zip(fresh, parallel, strict=True):  # worker processes build the same shapes
        # Usually bit-equal, but not always: isotropic remeshing is chaotic, and a last-bit
        # difference in its input can flip an edge split or collapse.  The cause was not
        # reproduced outside CI (1 or 2 OpenMP threads, CPU load, allocation history, libc's
        # rand state and the FPU flags all gave the same bits here).  CI runs saw a
        # worker-built snake with 1.9e-6 different coordinates, and once with 530 triangles
        # instead of 526 (then the normal noise, drawn per vertex,
        # is another realisation: 3 % of area and 0.04 of extent between realisations).
        # The shape itself does not change:
        if x.mesh.n_faces == y.mesh.n_faces and np.array_equal(x.mesh.faces, y.mesh.faces):
            np.testing.assert_allclose(x.mesh.vertices, y.mesh.vertices, rtol=0, atol=1e-5)
        assert abs(x.mesh.n_vertices - y.mesh.n_vertices) <= 0.02 * x.mesh.n_vertices
        np.testing.assert_allclose(y.mesh.area, x.mesh.area, rtol=0.08)
        np.testing.assert_allclose(y.mesh.vertices.min(0), x.mesh.vertices.min(0), atol=0.1)
        np.testing.assert_allclose(y.mesh.vertices.max(0), x.mesh.vertices.max(0), atol=0.1)
    with pytest.raises(ValueError, match="n_jobs must be an integer >= 1"):
        data.store.load_creatures(3, cache_dir=tmp_path / "c", n_jobs=0, **kw)


# ---------------------------------------------------------------------- the point of it
@pytest.mark.slow
def test_small_instance_sizes(small):
    _, coll, table = small
    assert len(coll) == 36 and len(set(coll.labels)) == 12
    nv = [it.mesh.n_vertices for it in coll]
    assert 400 < min(nv) and max(nv) < 1300 and max(nv) / min(nv) > 1.4  # resolutions vary
    assert all(it.mesh.is_closed and it.mesh.n_components == 1 for it in coll)
    assert not table.failures and np.all(table.lam[:, 1] > 0)  # one zero eigenvalue each


@pytest.mark.slow
def test_shape_dna_retrieval_does_not_saturate(small):
    from cshape.reproduce.experiments import FAMILIES, experiment_sizes

    _, _, table = small
    s = retrieval_scores(table.distance_matrix(cshape.Descriptor("shape-dna", N=100)), table.labels)
    chance = 2 / 35  # first tier of a random ranking: (class size - 1) / (p - 1)
    assert chance < s["ft"] < 0.9 and s["nn"] < 0.9  # far from perfect
    # ... and the classes are real and the descriptors differ: some descriptor is far above
    # chance, and the six families of equal size spread out (no saturation at 1.0)
    ft = [v["ft"] for v in experiment_sizes(table, Ms=(8,), N=100)["rows"][0]["scores"].values()]
    assert len(ft) == len(FAMILIES)
    assert max(ft) > 4 * chance and max(ft) - min(ft) > 0.1
