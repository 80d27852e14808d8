"""The benchmark suite (identities, resolutions) and the exploration default it chose.

The default descriptor is one constant, :data:`cshape.DEFAULT` (a :class:`cshape.Descriptor`);
every surface that compares shapes with no descriptor given must read it (the tests change
the constant and check that each surface follows), and the paper's cShape-DNA stays one
option away (``cshape.PAPER``, ``--kind cshape``).
"""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

import cshape
from cshape import PAPER, Descriptor, compare, shapes
from cshape.batch import DescriptorTable
from cshape.batch.table import collection_distances
from cshape.cli import main as cli_main
from cshape.compare import retrieval_scores
from cshape.descriptors import recipe
from cshape.index import DescriptorIndex
from cshape.reproduce.scores import candidates, choose_default, default_row, suite_scores

N = 30


@pytest.fixture(scope="module")
def table():
    """Ellipsoids of three shapes, each at two resolutions and two scales: 12 rows."""
    names, lams, areas, labels = [], [], [], []
    for k, (a, b) in enumerate([(1.0, 1.0), (2.0, 1.0), (3.0, 2.0)]):
        for sub in (3, 4):
            base = shapes.icosphere(sub)
            for s in (1.0, 2.0):
                V = s * base.vertices * np.array([a, b, 1.0])
                lam = cshape.shape_dna((V, base.faces), N=N)
                names.append(f"e{k}-{sub}-{s:g}")
                lams.append(lam)
                areas.append(cshape.Mesh(V, base.faces).area)
                labels.append(f"e{k}")
    return DescriptorTable(names, np.array(lams), areas, labels)


#: The replacement default of :func:`other_default`, at the table's N.
OTHER = Descriptor("cshape", N=N, M=3, transform="log-weyl-dct", normalization="fiedler")


def fresh(t: DescriptorTable) -> DescriptorTable:
    """The same spectra in a table made now: it compares the current constant (a table
    keeps the descriptor of the time it was made, saved with it)."""
    return DescriptorTable(t.names, t.lam, t.areas, t.labels, components=t.components)


@pytest.fixture
def other_default(monkeypatch):
    """Replace the exploration default by a log-Weyl DCT cShape-DNA with M=3: a surface that
    copied the constant instead of reading it would not follow."""
    monkeypatch.setattr(recipe, "DEFAULT", OTHER.replace(N=100))
    return OTHER


# ---------------------------------------------------------------------- the constant
def test_default_is_one_constant_and_compact_shape_dna_keeps_the_papers_form():
    assert cshape.DEFAULT == Descriptor("two-scale", N=100, M=4)
    assert cshape.PAPER == Descriptor("cshape", N=100, M=16)
    for gone in ("DEFAULT_DESCRIPTOR", "PAPER_DESCRIPTOR", "default_descriptor",
                 "descriptor_label", "descriptor_size", "descriptor_matrix", "descriptor_rows",
                 "row_problems"):
        assert not hasattr(compare, gone), gone
    # compact_shape_dna's defaults are the paper's descriptor (Eq. 8-10; its bits are checked
    # against the equations in test_descriptors.py), not the exploration default
    import inspect

    sig = inspect.signature(cshape.compact_shape_dna).parameters
    paper = cshape.PAPER
    assert [sig[k].default for k in ("M", "N", "transform", "normalization")] == [
        paper.M, paper.N, paper.transform, paper.normalization] == [16, 100, "weyl", "area"]
    assert cshape.DEFAULT != paper


def test_default_lowers_M_to_what_N_allows(table):
    d = cshape.DEFAULT.for_N(N)
    assert d.N == N and d.M <= cshape.DEFAULT.M
    X = d.matrix(table.lam, table.areas)  # computable from N eigenvalues
    assert X.shape == (len(table), d.size)
    assert cshape.DEFAULT.for_N(1000).M == cshape.DEFAULT.M
    with pytest.raises(ValueError, match="N must be an integer >= 1"):
        cshape.DEFAULT.for_N(0)


# ---------------------------------------------------------------------- every surface
def test_table_descriptors_and_distances_default_to_the_constant(table, other_default):
    table = fresh(table)
    X = table.descriptors()
    np.testing.assert_array_equal(X, other_default.matrix(table.lam, table.areas))
    assert X.shape == (len(table), 7)
    np.testing.assert_array_equal(table.distance_matrix(), compare.distance_matrix(X))
    assert table.described()[1].tolist() == list(range(len(table)))
    # the paper's descriptor is one value away
    np.testing.assert_array_equal(
        table.descriptors(PAPER.for_N(N)),
        Descriptor("cshape", N=N, M=14, transform="weyl", normalization="area").matrix(
            table.lam, table.areas))


def test_table_default_is_the_shipped_constant(table):
    np.testing.assert_array_equal(
        table.descriptors(), Descriptor("two-scale", N=N, M=4).matrix(table.lam, table.areas))


def test_index_defaults_to_the_constant(table, other_default):
    table = fresh(table)
    index = DescriptorIndex.from_table(table)
    assert index.descriptor_ == other_default
    paper = DescriptorIndex.from_table(table, PAPER.replace(N=N, M=4))
    assert paper.descriptor_.label.startswith("paper's cShape-DNA")


def test_query_header_says_what_it_compared(table, tmp_path, capsys):
    path = table.save(tmp_path / "t.npz")
    assert cli_main(["query", str(path), "e1-3-1", "-k", "3"]) == 0
    out = capsys.readouterr().out.splitlines()
    label = cshape.DEFAULT.for_N(N).label
    assert out[0].startswith("nearest to 'e1-3-1' by the " + label)
    # the same shape at another scale and resolution is nearest (distance ~0 for the scale)
    ranked = [line.split() for line in out[2:]]
    assert ranked[0][2] == "e1-3-2" and float(ranked[0][1]) < 1e-8
    assert {r[3] for r in ranked[:3]} == {"e1"}
    assert cli_main(["query", str(path), "e1-3-1", "--kind", "cshape", "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    assert got["kind"] == "cshape" and got["descriptor"].startswith("paper's cShape-DNA")
    # --kind cshape: the paper's, its M lowered to what the table's N allows
    assert (got["N"], got["M"], got["transform"]) == (N, 14, "weyl")


def test_query_follows_the_constant(table, tmp_path, capsys, other_default):
    table = fresh(table)
    path = table.save(tmp_path / "t.npz")
    assert cli_main(["query", str(path), "e0-3-1", "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    assert Descriptor(got["kind"], N=got["N"], M=got["M"], transform=got["transform"],
                      normalization=got["normalization"]) == other_default


def test_a_saved_table_is_queried_by_what_it_was_saved_with(table, tmp_path, capsys,
                                                           monkeypatch):
    path = table.save(tmp_path / "t.npz")  # under the shipped constant
    monkeypatch.setattr(recipe, "DEFAULT", OTHER.replace(N=100))
    assert cli_main(["query", str(path), "e0-3-1", "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    assert Descriptor(got["kind"], N=got["N"], M=got["M"], transform=got["transform"],
                      normalization=got["normalization"]) == table.descriptor != OTHER


def test_describe_summary_shows_the_default(table, capsys, other_default):
    table = fresh(table)
    from cshape.cli.explore import _print_table

    _print_table(table)
    head = capsys.readouterr().out.splitlines()[0]
    assert other_default.label in head


def test_collection_distances_default_to_the_constant(table, other_default):
    """The MDS and overview of one's own collection (cshape.plots, `cshape overview`)."""
    table = fresh(table)
    c = collection_distances(table)
    np.testing.assert_allclose(c.D, table.distance_matrix())
    assert c.descriptor == other_default
    paper = collection_distances(table, PAPER.for_N(N))
    np.testing.assert_allclose(paper.D, table.distance_matrix(PAPER.for_N(N)))


def test_lesson_06_uses_the_default_and_the_paper_beside_it():
    from pathlib import Path

    src = (Path(__file__).resolve().parents[1] / "notebooks" / "06_own_collection.py").read_text()
    assert "DescriptorIndex.from_table(table)" in src  # no descriptor: the default
    assert re.search(r"paper = cshape\.PAPER\.replace\(", src)  # the paper's, one value away
    assert "from_table(table, paper)" in src
    assert "table.distance_matrix(descriptor)" in src and "descriptor.label" in src


# ---------------------------------------------------------------------- choosing
def _row(title, fts):
    return {"title": title, "size": 17, "scores": {b: {"ft": v} for b, v in fts.items()},
            "worst": min(fts.values()), "mean": float(np.mean(list(fts.values())))}


def test_choice_is_by_the_worst_benchmark_not_the_mean():
    rows = [_row("strong on two", {"a": 1.0, "b": 1.0, "c": 0.4}),  # mean 0.8
            _row("even", {"a": 0.7, "b": 0.7, "c": 0.7})]  # mean 0.7
    assert choose_default(rows)["title"] == "even"
    with pytest.raises(ValueError, match="rows is empty"):
        choose_default([])


def test_candidates_cover_every_family_and_fit_N():
    cands = candidates(100)
    fams = {c["family"] for c in cands}
    assert fams == {"Shape-DNA", "cShape-DNA (paper)", "log-Weyl DFT", "log-Weyl DCT",
                    "truncated Shape-DNA", "truncated log spectrum", "F1",
                    "truncated log spectrum, Weyl-normalised",
                    "truncated log spectrum, lam_1-normalised", "two-scale log spectrum"}
    assert all(c["size"] == Descriptor(c["kind"], N=c["N"], M=c["M"]).size
               for c in cands if c["M"] is not None)
    assert default_row(cands) is not None  # the exploration default is a candidate
    small = candidates(20)
    assert all(c["size"] <= 20 for c in small if c["kind"] != "two-scale")
    assert len(small) < len(cands)


def test_suite_scores_on_a_tiny_suite_are_sane(table):
    """Two 'benchmarks' of the ellipsoid table (shape classes; resolution pairs)."""
    by_res = DescriptorTable(table.names, table.lam, table.areas,
                             [n.rsplit("-", 1)[0] for n in table.names])
    rows = suite_scores({"shapes": table, "scales": by_res})
    assert rows and all(set(r["scores"]) == {"shapes", "scales"} for r in rows)
    for r in rows:
        fts = [s["ft"] for s in r["scores"].values()]
        assert r["worst"] == min(fts) and 0 <= r["worst"] <= r["mean"] <= 1
    sd = next(r for r in rows if r["kind"] == "shape-dna")
    # the same mesh at twice the size has the same normalised spectrum: its partner is first
    assert sd["scores"]["scales"]["nn"] == 1.0
    ref = retrieval_scores(table.distance_matrix(Descriptor("shape-dna", N=N)), table.labels)
    assert sd["scores"]["shapes"]["ft"] == pytest.approx(ref["ft"])
    assert choose_default(rows)["worst"] == max(r["worst"] for r in rows)


def test_default_row_finds_the_constant(other_default):
    rows = [{"title": t, "kind": k, "M": m, "transform": tr, "normalization": nm}
            for t, k, m, tr, nm in [
                ("paper 7", "cshape", 3, "weyl", "fiedler"),
                ("dct 5", "cshape", 2, "log-weyl-dct", "fiedler"),
                ("dct 7 area", "cshape", 3, "log-weyl-dct", "area"),
                ("dct 7", "cshape", 3, "log-weyl-dct", "fiedler"),
                ("log 7", "truncated-log", 3, "weyl", "fiedler")]]
    assert default_row(rows)["title"] == "dct 7"
    assert default_row(rows[:2]) is None


# ---------------------------------------------------------------------- the benchmarks
def test_suite_collections_are_in_the_manifest_dev_and_held_out():
    from cshape.data.suite import SUITE

    for dev, held in SUITE.values():
        a, b = cshape.data.info(dev), cshape.data.info(held)
        assert [it["name"] for it in a["items"]] == [it["name"] for it in b["items"]]
        assert not {it["seed"] for it in a["items"]} & {it["seed"] for it in b["items"]}
        assert "HELD-OUT" in b["description"] and "Development" in a["description"]
    ident = cshape.data.info("identities")["items"]
    labels = {it["label"] for it in ident}
    assert len(labels) == 12 and len(ident) == 12 * 8 * 2  # 8 poses x 2 resolutions
    res = cshape.data.info("resolutions")["items"]
    assert len({it["label"] for it in res}) == 24 and len(res) == 72


def test_generate_rejects_an_unknown_benchmark(tmp_path):
    import yaml

    from cshape.data.manifest import validate_manifest

    doc = {"version": 1, "collections": [{
        "name": "x", "kind": "generated", "description": "d", "license": "l",
        "citation": "c", "generate": {"benchmark": "faces", "seed": 0}}]}
    with pytest.raises(ValueError, match="benchmark must be one of"):
        validate_manifest(yaml.safe_load(yaml.safe_dump(doc)))
    doc["collections"][0]["generate"] = {"benchmark": "identities", "members": 2}
    with pytest.raises(ValueError, match=r"unknown key\(s\) \['members'\]"):
        validate_manifest(doc)


def test_identity_items_and_resolution_items():
    from cshape.data.suite import identity_items, resolution_items

    items = identity_items(0, identities=2, poses=3, resolutions=(300, 600))
    assert len(items) == 2 * 2 * 3 * 2
    assert items[0] == {"name": "human-00-p0-v300", "label": "human-00", "recipe": "identity",
                        "seed": 0, "params": {"kind": "human", "pose": 0, "vertices": 300}}
    assert {it["label"] for it in items} == {"human-00", "human-01", "quadruped-00",
                                             "quadruped-01"}
    res = resolution_items(0, members=1, kinds=["snake"])
    assert [it["name"] for it in res] == ["snake-00-coarse", "snake-00-fine",
                                          "snake-00-decimated"]
    assert len({it["seed"] for it in res}) == 1 and {it["label"] for it in res} == {"snake-00"}
    with pytest.raises(ValueError, match="levels must be one of"):
        resolution_items(0, levels=["huge"])


def test_identities_differ_in_proportions_and_keep_bone_directions():
    from cshape.data.suite import identity_bones

    a, b = identity_bones("human", 0), identity_bones("human", 1)
    ra = [c.radius for bone in a for c in bone.capsules]
    rb = [c.radius for bone in b for c in bone.capsules]
    assert not np.allclose(ra, rb)
    left = {bone.name: bone for bone in a}
    # left and right limbs of one identity share their factors (a symmetric body)
    assert left["forearm_-1"].capsules[0].radius == left["forearm_1"].capsules[0].radius
    # a child's joint is its parent's capsule end: limbs stay attached
    np.testing.assert_allclose(left["forearm_-1"].joint, left["upper_arm_-1"].capsules[0].b)
    with pytest.raises(ValueError, match="kind must be one of"):
        identity_bones("dragon", 0)


@pytest.mark.slow
def test_identity_poses_share_the_template_and_resolutions_differ():
    pytest.importorskip("pymeshlab")
    from cshape.data.suite import identity_pose

    a = identity_pose("quadruped", 3, pose=1, vertices=400, voxelsize=0.02)
    b = identity_pose("quadruped", 3, pose=2, vertices=400, voxelsize=0.02)
    c = identity_pose("quadruped", 3, pose=1, vertices=900, voxelsize=0.02)
    other = identity_pose("quadruped", 4, pose=1, vertices=400, voxelsize=0.02)
    np.testing.assert_array_equal(a.faces, b.faces)  # one template per identity
    assert np.abs(a.vertices - b.vertices).max() > 0.05  # another pose
    assert a.area == pytest.approx(b.area, rel=0.06)  # near-isometric
    # the same surface: a coarse remesh cuts corners (about 4 % of the area at 400 vertices)
    assert c.n_vertices > 1.8 * a.n_vertices and c.area == pytest.approx(a.area, rel=0.06)
    assert a.n_components == 1 and a.is_closed
    # retrieval: the other resolution of the same pose is nearer than another identity
    lams = [cshape.shape_dna(m, N=20) for m in (a, c, other)]
    D = compare.distance_matrix(Descriptor("truncated-log", N=20, M=8).matrix(
        lams, [m.area for m in (a, c, other)]))
    assert D[0, 1] < D[0, 2]


@pytest.mark.slow
def test_resolution_shape_is_one_surface_meshed_three_ways():
    pytest.importorskip("pymeshlab")
    from cshape.data.suite import resolution_shape

    meshes = [resolution_shape("snake", 5, level=lv) for lv in ("coarse", "fine", "decimated")]
    n = [m.n_vertices for m in meshes]
    assert n[0] < n[2] < n[1]
    areas = [m.area for m in meshes]
    assert max(areas) / min(areas) < 1.03
    assert all(m.n_components == 1 for m in meshes)


@pytest.mark.slow
def test_reproduce_reports_the_suite_with_the_default_marked(tmp_path, monkeypatch):
    from cshape.reproduce import reproduce

    # a size the N = 30 candidates have
    monkeypatch.setattr(recipe, "DEFAULT", cshape.DEFAULT.replace(M=8))
    recs = []
    for k, (a, b) in enumerate([(1.0, 1.0), (2.0, 1.0), (3.0, 2.0)]):
        for sub in (2, 3):
            m = shapes.icosphere(sub)
            recs.append((f"e{k}-{sub}", f"e{k}", (m.vertices * [a, b, 1.0], m.faces)))
    by_res = [(n, n.rsplit("-", 1)[1], mesh) for n, _, mesh in recs]
    res = reproduce(recs, tmp_path / "rep", N=30, M=4, Ms=(2,), noise_levels=(),
                    cache_dir=tmp_path / "cache", progress=False,
                    suite={"shapes": recs, "resolution": by_res})
    st = res["suite"]
    assert st["benchmarks"] == {"shapes": {"n_shapes": 6, "n_classes": 3},
                                "resolution": {"n_shapes": 6, "n_classes": 2}}
    assert st["default"]["kind"] == cshape.DEFAULT.kind and st["default"]["M"] == 8
    rep = (tmp_path / "rep" / "report.md").read_text()
    assert "## The benchmark suite" in rep
    assert f"| **{st['default']['title']}** |" in rep
    assert "| Shape-DNA 30 | 30 |" in rep


def test_bench_suite_script_chooses_on_dev_and_reports_held_out(table, tmp_path, monkeypatch):
    """benchmarks/bench_suite.py on two tiny 'benchmarks' (the script's core cannot rot)."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "benchmarks" / "bench_suite.py"
    spec = importlib.util.spec_from_file_location("bench_suite", path)
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    by_res = DescriptorTable(table.names, table.lam, table.areas,
                             [n.rsplit("-", 1)[0] for n in table.names])
    held = table.select(list(range(0, len(table), 2)) + list(range(1, len(table), 2)))
    fake = {"dev": {"creatures": table, "identities": by_res, "resolutions": table},
            "held-out": {"creatures": held, "identities": by_res, "resolutions": held}}
    monkeypatch.setattr(bench, "tables", lambda inst, N, jobs: fake[inst])
    monkeypatch.setattr(bench, "RESULTS", tmp_path)
    rc = bench.main(["-N", str(N)])
    md = (tmp_path / "suite.md").read_text()
    rows = suite_scores(fake["dev"])
    chosen = choose_default(rows)
    assert f"**Best worst case: {chosen['title']}**" in md
    assert f"| **{chosen['title']}** |" in md
    assert "### Held-out instances (reported, not chosen on): first tier" in md
    assert rc == 0 and "`cshape.DEFAULT` = `Descriptor(kind='two-scale'" in md
    lines = (tmp_path / "suite.csv").read_text().splitlines()
    assert len(lines) == 1 + 2 * 3 * len(rows)  # header, instance x benchmark x descriptor
