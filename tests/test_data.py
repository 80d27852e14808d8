"""Tests of cshape.data: manifest schema, generated collections and their cache, local,
package and download collections (never downloading), benchmark layouts, archives, CLI."""

from __future__ import annotations

import copy
import functools
import hashlib
import io
import os
import subprocess
import sys
import tarfile
import textwrap
import zipfile
from pathlib import Path

import numpy as np
import pytest
import yaml

import cshape.data as data
from cshape import CShapeWarning, shapes
from cshape.cli import main
from cshape.data import bodies, quality
from cshape.data import variants as v

REPO = Path(__file__).resolve().parents[1]


@pytest.fixture(autouse=True)
def _isolated_cache(tmp_path, monkeypatch):
    """Every test gets an empty cache; nothing touches ~/.cache."""
    monkeypatch.setenv("CSHAPE_CACHE", str(tmp_path / "cache"))
    monkeypatch.delenv("CSHAPE_MANIFEST", raising=False)


@pytest.fixture(scope="module")
def shipped():
    with open(REPO / "data_manifest.yaml", encoding="utf-8") as fh:
        return yaml.safe_load(fh)


@pytest.fixture(scope="module")
def built_paper(tmp_path_factory):
    """paper-models built once for the module (about 5 s)."""
    cache = tmp_path_factory.mktemp("paper-cache")
    return cache, data.load_collection("paper-models", cache_dir=cache, progress=False)


def _write_manifest(tmp_path, collections, name="m.yaml"):
    p = tmp_path / name
    p.write_text(yaml.safe_dump({"version": 1, "collections": collections}), encoding="utf-8")
    return p


TINY = {
    "name": "tiny",
    "kind": "generated",
    "description": "test",
    "license": "BSD-3-Clause",
    "citation": "none",
    "items": [
        {"name": "s", "label": "sphere", "recipe": "sphere", "params": {"subdivisions": 2}},
        {"name": "n", "label": "sphere", "recipe": "noise", "base": "tiny/s", "seed": 3,
         "params": {"amplitude": 1.0}},
    ],
}


def _write_obj(path, mesh):
    path.parent.mkdir(parents=True, exist_ok=True)
    lines = [f"v {x:.17g} {y:.17g} {z:.17g}" for x, y, z in mesh.vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in mesh.faces]
    path.write_text("\n".join(lines) + "\n")


def _write_off(path, mesh):
    path.parent.mkdir(parents=True, exist_ok=True)
    lines = ["OFF", f"{mesh.n_vertices} {mesh.n_faces} 0"]
    lines += [f"{x:.17g} {y:.17g} {z:.17g}" for x, y, z in mesh.vertices]
    lines += [f"3 {a} {b} {c}" for a, b, c in mesh.faces]
    path.write_text("\n".join(lines) + "\n")


def _write_ply(path, mesh):
    path.parent.mkdir(parents=True, exist_ok=True)
    head = ["ply", "format ascii 1.0", f"element vertex {mesh.n_vertices}", "property float x",
            "property float y", "property float z", f"element face {mesh.n_faces}",
            "property list uchar int vertex_indices", "end_header"]
    lines = head + [f"{x:.9g} {y:.9g} {z:.9g}" for x, y, z in mesh.vertices]
    lines += [f"3 {a} {b} {c}" for a, b, c in mesh.faces]
    path.write_text("\n".join(lines) + "\n")


# ====================================================================== manifest
def test_shipped_manifest_validates(shipped):
    entries = data.manifest.validate_manifest(copy.deepcopy(shipped))
    assert set(e["kind"] for e in entries.values()) == set(data.manifest.KINDS)
    names = data.list_collections()
    for name in ["paper-models", "articulated", "noisy", "pymeshlab-samples",
                 "odedstein-meshes", "shared-meshes", "mcgill-3dsb", "tosca",
                 "shrec07-watertight"]:
        assert name in names
    assert data.info("tosca")["layout"] == "tosca"


def test_articulated_manifest_has_classes_and_poses():
    coll = data.info("articulated")
    labels = [it["label"] for it in coll["items"]]
    counts = {lab: labels.count(lab) for lab in set(labels)}
    assert len(counts) >= 3 and min(counts.values()) >= 5


def test_noisy_manifest_uses_the_papers_levels():
    levels = {it["params"]["amplitude"] for it in data.info("noisy")["items"]}
    assert set(v.NOISE_LEVELS) <= levels


def _bad(shipped, mutate):
    doc = copy.deepcopy(shipped)
    mutate(doc)
    return doc


@pytest.mark.parametrize(
    "mutate, match",
    [
        (lambda d: d["collections"][0].pop("license"),
         r"collection 'paper-models' \(entry 0\): missing required field 'license'"),
        (lambda d: d["collections"][1].update(kind="zip"),
         r"collection 'articulated' \(entry 1\): unknown kind 'zip'"),
        (lambda d: d["collections"][0]["items"][0].update(recipe="blob"),
         r"item 'S1': unknown recipe 'blob'"),
        (lambda d: d["collections"][0]["items"][0]["params"].update(subdivs=3),
         r"item 'S1': recipe 'sphere' has no parameter 'subdivs'"),
        (lambda d: d["collections"][0]["items"][7].update(base="paper-models/ZZ"),
         r"item 'CS': field 'base' must name an earlier generated item"),
        (lambda d: d["collections"][0]["items"][1].update(name="S1"),
         r"duplicate item name 'S1'"),
        (lambda d: d["collections"][4]["items"][0].update(sha256="abc"),
         r"collection 'odedstein-meshes'.*item 'cube': field 'sha256' must be 64"),
        (lambda d: d["collections"][4]["items"][0].pop("url"),
         r"item 'cube': missing required field 'url'"),
        (lambda d: d["collections"][0].update(colour="red"),
         r"collection 'paper-models'.*unknown field 'colour'"),
        (lambda d: d["collections"][5].update(labels="folders"),
         r"collection 'shared-meshes'.*'labels' must be 'subfolder' or the name of a CSV"),
        (lambda d: d["collections"][6].update(layout="princeton"),
         r"collection 'mcgill-3dsb'.*unknown layout 'princeton'"),
        (lambda d: d["collections"][2].update(name="paper-models"),
         r"duplicate collection name 'paper-models'"),
        (lambda d: d["collections"][3]["items"][0].update(file="../../etc/passwd"),
         r"item 'bunny': field 'file' must be a relative path inside"),
        (lambda d: d["collections"][0].update(description=3),
         r"field 'description' must be a str"),
        (lambda d: d.pop("version"), r"missing required field 'version'"),
        (lambda d: d["collections"][0].update(items=None),
         r"collection 'paper-models' \(entry 0\): a generated collection needs either 'items'"),
    ],
)
def test_bad_manifest_errors(shipped, mutate, match):
    with pytest.raises(ValueError, match=match):
        data.manifest.validate_manifest(_bad(shipped, mutate))


def test_bad_manifest_file_errors(tmp_path):
    p = tmp_path / "bad.yaml"
    p.write_text("collections: [unclosed\n")
    with pytest.raises(ValueError, match="not valid YAML"):
        data.manifest.load_manifest(p)
    with pytest.raises(FileNotFoundError, match="no data manifest"):
        data.manifest.load_manifest(tmp_path / "missing.yaml")


def test_a_manifest_file_is_read_again_when_it_changes(tmp_path):
    """A file read before gives its entries again, each call its own copy; a file rewritten in
    place (the same size, at once) is read and checked again."""
    p = tmp_path / "m.yaml"
    entry = ("version: 1\ncollections:\n- name: {name}\n  kind: generated\n  description: d\n"
             "  license: BSD-3-Clause\n  citation: none\n  items:\n  - {{name: s, label: sphere, "
             "recipe: sphere, params: {{subdivisions: 1}}}}\n")
    p.write_text(entry.format(name="aaaa"))
    first = data.manifest.load_manifest(p)
    first["aaaa"]["description"] = "changed by the caller"
    assert data.manifest.load_manifest(p)["aaaa"]["description"] == "d"
    p.write_text(entry.format(name="bbbb"))
    assert list(data.manifest.load_manifest(p)) == ["bbbb"]
    p.write_text(entry.format(name="cccc") + "  bad_field: 1\n")
    with pytest.raises(ValueError, match="bad_field"):
        data.manifest.load_manifest(p)


def test_unknown_collection_and_item():
    with pytest.raises(ValueError, match="unknown collection 'nope'; known collections"):
        data.load_collection("nope")
    with pytest.raises(ValueError, match="has no item 'S9'"):
        data.load("paper-models", "S9")


# ====================================================================== generated
@pytest.mark.slow
def test_paper_models_properties(built_paper):
    _, coll = built_paper
    m = {it.name: it.mesh for it in coll}
    assert [m[k].n_vertices for k in ("S1", "S2", "S3")] == [2562, 10242, 40962]
    for k, genus in {"S1": 0, "S2": 0, "S3": 0, "C": 0, "T": 1, "E": 2, "CM": 0, "CS": 0,
                     "D1": 0, "D2": 0}.items():
        assert m[k].is_closed and m[k].genus == genus, k
    assert m["C"].n_vertices == 6146
    # the unit cube of cshape.shapes, centred at the origin like the spheres and the torus
    np.testing.assert_allclose(m["C"].vertices.min(axis=0), -0.5)
    np.testing.assert_allclose(m["C"].vertices.max(axis=0), 0.5)
    assert m["C"].area == pytest.approx(6.0)
    np.testing.assert_array_equal(m["S1"].vertices, shapes.icosphere(4).vertices)
    assert 3.5 < m["D2"].n_vertices / m["D1"].n_vertices < 4.5
    qm, qs = quality.mesh_quality(m["CM"]), quality.mesh_quality(m["CS"])
    assert qm["min_angle"] < qs["min_angle"] and qm["mean_min_angle"] < qs["mean_min_angle"]
    assert coll["CM"].label == coll["CS"].label
    assert coll.labels.count("sphere") == 3


@pytest.mark.slow
def test_noisy_item_is_bounded_by_lam_L(built_paper):
    cache, coll = built_paper
    E = coll["E"].mesh
    noisy = data.load("noisy", "E-noise-2", cache_dir=cache)
    np.testing.assert_array_equal(noisy.faces, E.faces)
    d = np.linalg.norm(noisy.vertices - E.vertices, axis=1)
    assert d.max() <= 2.0 * E.mean_edge_length and d.max() > 1.5 * E.mean_edge_length
    np.testing.assert_array_equal(data.load("noisy", "E-noise-0", cache_dir=cache).vertices,
                                  E.vertices)


@pytest.mark.slow
@pytest.mark.parametrize("kind", bodies.ARTICULATED_KINDS)
def test_articulated_item_builds(kind):
    m = data.load("articulated", f"{kind}-0")
    assert m.is_closed and m.genus == 0 and 2000 < m.n_vertices < 4000


@pytest.fixture
def sphere_builds(monkeypatch):
    """The calls of ``shapes.icosphere`` (the TINY manifest's recipe), one entry per build."""
    calls = []
    real = shapes.icosphere

    @functools.wraps(real)
    def counting_sphere(*args, **kwargs):
        calls.append(1)
        return real(*args, **kwargs)

    monkeypatch.setattr(shapes, "icosphere", counting_sphere)
    return calls


def test_generated_cache_hit_does_not_rebuild(tmp_path, sphere_builds):
    man = _write_manifest(tmp_path, [TINY])
    calls = sphere_builds
    c1 = data.load_collection("tiny", manifest=man, progress=False)
    assert calls == [1]  # built once, reused as the noise recipe's base
    files = sorted((tmp_path / "cache" / "generated" / "tiny").iterdir())
    assert [f.suffix for f in files] == [".npz", ".npz"]
    mtimes = [f.stat().st_mtime_ns for f in files]
    c2 = data.load_collection("tiny", manifest=man, progress=False)
    assert calls == [1]
    assert [f.stat().st_mtime_ns for f in files] == mtimes
    np.testing.assert_array_equal(c1["n"].mesh.vertices, c2["n"].mesh.vertices)
    assert c1.names == ["s", "n"] and c1.labels == ["sphere", "sphere"]
    assert c1["s"].path in files and c1["s"].path.suffix == ".npz"
    with np.load(files[0], allow_pickle=False) as z:
        assert set(z.files) == {"vertices", "faces", "recipe"}


def test_lazy_generated_collection_builds_only_what_is_used(tmp_path, sphere_builds):
    man = _write_manifest(tmp_path, [TINY])
    calls = sphere_builds
    lazy = data.load_collection("tiny", manifest=man, lazy=True)
    assert calls == [] and lazy.names == ["s", "n"] and lazy.labels == ["sphere", "sphere"]
    assert not (tmp_path / "cache" / "generated" / "tiny").exists()  # nothing built yet
    mesh = lazy["s"].mesh
    assert calls == [1] and mesh.n_vertices > 0
    assert len(list((tmp_path / "cache" / "generated" / "tiny").iterdir())) == 1
    built = data.load_collection("tiny", manifest=man, progress=False)  # the rest, then cached
    np.testing.assert_array_equal(built["s"].mesh.vertices, mesh.vertices)
    np.testing.assert_array_equal(lazy["n"].mesh.vertices, built["n"].mesh.vertices)
    assert calls == [1]


def _build_flag(args):
    """In a worker process: (built, vertices) of one generated item of the manifest."""
    from cshape.data import manifest as manifest_module
    from cshape.data import store

    man, root, coll, name = args
    entries = manifest_module.load_manifest(man)
    item = next(it for it in entries[coll]["items"] if it["name"] == name)
    mesh, built = store._generated_mesh(entries, coll, item, Path(root))
    return built, mesh.vertices


@pytest.mark.skipif(sys.platform == "win32", reason="the build lock needs fcntl")
def test_processes_asking_for_one_missing_item_build_it_once(tmp_path):
    slow = {"name": "slow", "kind": "generated", "description": "test",
            "license": "BSD-3-Clause", "citation": "none",
            "items": [{"name": "c", "label": "snake", "recipe": "creature", "seed": 5,
                       "params": {"kind": "snake", "vertices": 600, "voxelsize": 0.03}}]}
    man = _write_manifest(tmp_path, [slow])
    from concurrent.futures import ProcessPoolExecutor

    args = (str(man), str(tmp_path / "cache"), "slow", "c")
    with ProcessPoolExecutor(max_workers=3) as ex:
        out = list(ex.map(_build_flag, [args] * 3))
    assert sorted(b for b, _ in out) == [False, False, True]  # one built, two read its file
    for _, verts in out[1:]:
        np.testing.assert_array_equal(verts, out[0][1])
    assert [f.suffix for f in (tmp_path / "cache" / "generated" / "slow").iterdir()] == [".npz"]


def test_cache_key_follows_parameters_and_seed(tmp_path):
    t2 = copy.deepcopy(TINY)
    t2["items"][1]["seed"] = 4
    m1 = data.manifest.load_manifest(_write_manifest(tmp_path, [TINY], "a.yaml"))
    m2 = data.manifest.load_manifest(_write_manifest(tmp_path, [t2], "b.yaml"))
    root = tmp_path / "cache"
    f1 = data.store._cache_file(m1, "tiny", m1["tiny"]["items"][1], root)
    f2 = data.store._cache_file(m2, "tiny", m2["tiny"]["items"][1], root)
    assert f1 != f2
    cache_file = data.store._cache_file
    assert cache_file(m1, "tiny", m1["tiny"]["items"][0], root) == cache_file(
        m2, "tiny", m2["tiny"]["items"][0], root)
    a = data.load("tiny", "n", manifest=m1)
    b = data.load("tiny", "n", manifest=m2)
    a2 = data.load("tiny", "n", manifest=m1, cache_dir=tmp_path / "other")  # rebuilt elsewhere
    assert not np.allclose(a.vertices, b.vertices)  # different seed -> different mesh
    np.testing.assert_array_equal(a.vertices, a2.vertices)  # same seed -> same mesh


def test_atomic_write_leaves_no_partial_file(tmp_path, monkeypatch):
    man = _write_manifest(tmp_path, [TINY])

    def broken_savez(fh, **arrays):
        fh.write(b"PK\x03\x04 partial")
        raise OSError("disk full")

    monkeypatch.setattr(data.store.np, "savez", broken_savez)
    with pytest.raises(OSError, match="disk full"):
        data.load("tiny", "s", manifest=man)
    folder = tmp_path / "cache" / "generated" / "tiny"
    assert list(folder.iterdir()) == []  # neither the .npz nor the temporary file


def test_unreadable_cache_file_is_rebuilt(tmp_path):
    man = data.manifest.load_manifest(_write_manifest(tmp_path, [TINY]))
    path = data.store._cache_file(man, "tiny", man["tiny"]["items"][0], tmp_path / "cache")
    path.parent.mkdir(parents=True)
    path.write_bytes(b"garbage")
    with pytest.warns(UserWarning, match="rebuilding unreadable cache file"):
        m = data.load("tiny", "s", manifest=man)
    assert m.n_vertices == 162


def test_cache_dir_resolution(tmp_path, monkeypatch):
    assert data.cache_dir(tmp_path / "x") == tmp_path / "x"
    assert data.cache_dir() == tmp_path / "cache"
    monkeypatch.delenv("CSHAPE_CACHE")
    assert data.cache_dir().name == "cshape"


def test_import_does_not_download_or_build(tmp_path):
    code = "import sys, cshape.data; print('pooch' in sys.modules)"
    env = {**os.environ, "CSHAPE_CACHE": str(tmp_path / "fresh-cache")}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, env=env).stdout.split()
    assert out == ["False"]  # the download library is only imported by fetch()
    assert not (tmp_path / "fresh-cache").exists()  # nothing built or written on import


# ====================================================================== local
@pytest.fixture()
def mesh_folder(tmp_path):
    root = tmp_path / "meshes"
    _write_obj(root / "spheres" / "a.obj", shapes.icosphere(1))
    _write_off(root / "spheres" / "b.off", shapes.icosphere(2))
    _write_obj(root / "tori" / "deep" / "c.obj", shapes.torus(12, 6))
    (root / "tori" / "README.md").write_text("not a mesh")
    (root / ".hidden").mkdir()
    _write_obj(root / ".hidden" / "x.obj", shapes.icosphere(1))
    return root


def test_load_folder_labels_from_subfolders(mesh_folder):
    coll = data.load_folder(mesh_folder)
    assert coll.names == ["a", "b", "c"]
    assert coll.labels == ["spheres", "spheres", "tori"]
    assert coll["c"].mesh.genus == 1 and coll[0].mesh.n_vertices == 42
    assert coll["b"].path == mesh_folder / "spheres" / "b.off"


def test_load_folder_labels_from_csv(mesh_folder):
    csv_text = "file,label\nspheres/a.obj,round\ntori/deep/c.obj,ring\n"
    (mesh_folder / "labels.csv").write_text(csv_text)
    coll = data.load_folder(mesh_folder, labels="labels.csv")
    assert coll.names == ["a", "c"] and coll.labels == ["round", "ring"]


def test_load_folder_errors(mesh_folder, tmp_path):
    with pytest.raises(FileNotFoundError, match="no folder"):
        data.load_folder(tmp_path / "nowhere")
    (mesh_folder / "bad.csv").write_text("path,class\na.obj,x\n")
    with pytest.raises(ValueError, match="columns 'file' and 'label'"):
        data.load_folder(mesh_folder, labels="bad.csv")
    (mesh_folder / "missing.csv").write_text("file,label\nspheres/zz.obj,x\n")
    with pytest.raises(FileNotFoundError, match="lists 'spheres/zz.obj'"):
        data.load_folder(mesh_folder, labels="missing.csv")
    (tmp_path / "empty").mkdir()
    with pytest.raises(ValueError, match="holds no mesh file"):
        data.load_folder(tmp_path / "empty")


def test_local_collection_from_manifest(mesh_folder, tmp_path, monkeypatch):
    entry = {"name": "mine", "kind": "local", "description": "d", "license": "mine",
             "citation": "none", "path": "meshes", "path_env": "MY_MESHES",
             "labels": "subfolder"}
    man = _write_manifest(tmp_path, [entry])
    coll = data.load_collection("mine", manifest=man)  # path relative to the manifest
    assert coll.labels == ["spheres", "spheres", "tori"] and coll.name == "mine"
    other = tmp_path / "other"
    _write_obj(other / "cubes" / "k.obj", shapes.cube(2))
    monkeypatch.setenv("MY_MESHES", str(other))
    assert data.load_collection("mine", manifest=man).labels == ["cubes"]
    assert data.paths.collection_path("mine", manifest=man) == other


@pytest.mark.realdata
def test_shared_meshes_local_collection(shared_meshes, monkeypatch):
    monkeypatch.setenv("CSHAPE_SHARED_MESHES", str(shared_meshes))
    coll = data.load_collection("shared-meshes")
    assert len(coll) >= 10 and "spot" in coll.labels
    assert coll["torus"].label == "torus" and coll["torus"].mesh.genus == 1


@pytest.mark.realdata
def test_download_manifest_checksums_match_the_shared_copies(shared_meshes):
    for it in data.info("odedstein-meshes")["items"]:
        p = shared_meshes / it["file"]
        assert p.stat().st_size == it["size"], it["name"]
        assert hashlib.sha256(p.read_bytes()).hexdigest() == it["sha256"], it["name"]
        assert it["url"].endswith("/objects/" + it["file"])


# ====================================================================== package, download
def test_package_collection_reads_pymeshlab_samples():
    coll = data.load_collection("pymeshlab-samples")
    assert {"bunny", "cow", "airplane", "bone", "cube"} <= set(coll.names)
    assert coll["cube"].mesh.n_vertices == 8
    with pytest.warns(CShapeWarning, match="bone.ply: repaired mesh"):
        assert coll["bone"].mesh.is_closed
    assert data.paths.collection_path("pymeshlab-samples").is_dir()


def test_download_collection_never_downloads_unasked(monkeypatch):
    import pooch

    monkeypatch.setattr(pooch, "retrieve", lambda *a, **k: pytest.fail("tried to download"))
    with pytest.raises(FileNotFoundError, match="cshape data build odedstein-meshes"):
        data.load_collection("odedstein-meshes")
    with pytest.raises(FileNotFoundError, match="not downloaded yet"):
        data.load("odedstein-meshes", "torus")


def test_fetch_uses_pooch_with_sha256(tmp_path, monkeypatch):
    import pooch

    calls = []

    def fake_retrieve(url, known_hash, fname, path, progressbar):
        calls.append((url, known_hash))
        Path(path).mkdir(parents=True, exist_ok=True)
        _write_obj(Path(path) / fname, shapes.torus(12, 6))
        return str(Path(path) / fname)

    monkeypatch.setattr(pooch, "retrieve", fake_retrieve)
    m = data.load("odedstein-meshes", "torus", download=True)
    assert m.genus == 1
    (url, known), = calls
    item = data.manifest._find_item(data.info("odedstein-meshes"), "torus")
    assert url == item["url"] and known == "sha256:" + item["sha256"]
    dest = tmp_path / "cache" / "downloads" / "odedstein-meshes" / "torus" / "torus.obj"
    assert dest.is_file()
    with pytest.raises(ValueError, match="only 'download' collections"):
        data.fetch("paper-models")


def test_benchmark_without_files_explains_manual_download(tmp_path):
    with pytest.raises(FileNotFoundError, match=r"does not download it.*Get it from https://www"):
        data.load_collection("mcgill-3dsb")
    with pytest.raises(ValueError, match="CSHAPE_TOSCA"):
        data.fetch("tosca")


# ====================================================================== benchmark layouts
def test_read_mcgill_layout(tmp_path):
    root = tmp_path / "mcgill"
    _write_ply(root / "articulated" / "ants" / "Ply" / "b1.ply", shapes.icosphere(1))
    _write_off(root / "articulated" / "crabs" / "Ply" / "c2.off", shapes.icosphere(1))
    _write_off(root / "nonarticulated" / "cups" / "3.off", shapes.icosphere(1))
    (root / "articulated" / "ants" / "Ply" / "b1.im").write_text("medial surface")
    coll = data.folders.read_mcgill(root)
    assert coll.labels == ["ants", "crabs", "cups"]
    assert coll.names == ["ants/b1", "crabs/c2", "cups/3"]
    assert coll[0].mesh.n_vertices == 42 and coll[1].mesh.is_closed


def test_read_tosca_layout(tmp_path):
    root = tmp_path / "tosca"
    root.mkdir()
    for name, m in [("cat0", shapes.icosphere(1)), ("cat10", shapes.icosphere(1)),
                    ("centaur2", shapes.torus(8, 5))]:
        np.savetxt(root / f"{name}.vert", m.vertices)
        np.savetxt(root / f"{name}.tri", m.faces + 1, fmt="%d")
    _write_off(root / "david0.off", shapes.icosphere(1))
    coll = data.folders.read_tosca(root)
    assert coll.names == ["cat0", "cat10", "centaur2", "david0"]
    assert coll.labels == ["cat", "cat", "centaur", "david"]
    assert coll["centaur2"].mesh.genus == 1
    np.savetxt(root / "bad0.vert", np.zeros((3, 3)))
    np.savetxt(root / "bad0.tri", [[0, 1, 2]], fmt="%d")
    with pytest.raises(ValueError, match="1-based"):
        data.files.read_vert_tri(root / "bad0.vert")


def test_read_shrec07_layout(tmp_path, monkeypatch):
    root = tmp_path / "watertight"
    for n in (1, 20, 21, 400):
        _write_off(root / "off" / f"{n}.off", shapes.icosphere(1))
    _write_off(root / "off" / "401.off", shapes.icosphere(1))
    coll = data.folders.read_shrec07(root)
    assert coll.names == ["1", "20", "21", "400"]
    assert coll.labels == ["human", "human", "cup", "fourleg"]
    monkeypatch.setenv("CSHAPE_SHREC07", str(root))
    assert data.load_collection("shrec07-watertight").labels == coll.labels
    with pytest.raises(ValueError, match="no SHREC'07 meshes"):
        data.folders.read_shrec07(tmp_path / "nothing-here")


# ====================================================================== archives
def test_extract_archive_zip_and_tar(tmp_path):
    z = tmp_path / "a.zip"
    with zipfile.ZipFile(z, "w") as zf:
        zf.writestr("cat0.vert", "0 0 0\n")
        zf.writestr("sub/x.txt", "hi")
    out = data.download.extract_archive(z, tmp_path / "out")
    assert (out / "cat0.vert").is_file() and (out / "sub" / "x.txt").read_text() == "hi"
    t = tmp_path / "b.tar.gz"
    with tarfile.open(t, "w:gz") as tf:
        info = tarfile.TarInfo("y.txt")
        info.size = 2
        tf.addfile(info, io.BytesIO(b"yo"))
    data.download.extract_archive(t, tmp_path / "out")
    assert (tmp_path / "out" / "y.txt").read_text() == "yo"


@pytest.mark.parametrize("member", ["../evil.txt", "/abs/evil.txt", "a/../../evil.txt"])
def test_extract_archive_refuses_escaping_zip(tmp_path, member):
    z = tmp_path / "evil.zip"
    with zipfile.ZipFile(z, "w") as zf:
        zf.writestr("ok.txt", "fine")
        zf.writestr(member, "bad")
    with pytest.raises(ValueError, match="outside the target folder"):
        data.download.extract_archive(z, tmp_path / "target" / "inner")
    assert not (tmp_path / "evil.txt").exists()
    assert not (tmp_path / "target" / "evil.txt").exists()
    assert not (tmp_path / "target" / "inner").exists()  # nothing written


def test_extract_archive_refuses_tar_links(tmp_path):
    t = tmp_path / "link.tar"
    with tarfile.open(t, "w") as tf:
        info = tarfile.TarInfo("link")
        info.type = tarfile.SYMTYPE
        info.linkname = "/etc/passwd"
        tf.addfile(info)
    with pytest.raises(ValueError, match="link or special file"):
        data.download.extract_archive(t, tmp_path / "target")
    assert not (tmp_path / "target").exists()


def test_build_benchmark_from_archive(tmp_path):
    z = tmp_path / "shrec.zip"
    m = shapes.icosphere(1)
    buf = io.StringIO()
    buf.write(f"OFF\n{m.n_vertices} {m.n_faces} 0\n")
    buf.write("".join(f"{x} {y} {z_}\n" for x, y, z_ in m.vertices))
    buf.write("".join(f"3 {a} {b} {c}\n" for a, b, c in m.faces))
    with zipfile.ZipFile(z, "w") as zf:
        zf.writestr("watertight/41.off", buf.getvalue())
    folder = data.build("shrec07-watertight", archive=z)
    assert folder == tmp_path / "cache" / "downloads" / "shrec07-watertight"
    assert data.load_collection("shrec07-watertight").labels == ["glasses"]


# ====================================================================== command line
def test_cli_list_build_path(tmp_path, capsys):
    man = _write_manifest(tmp_path, [TINY])
    assert main(["data", "list"]) == 0
    out = capsys.readouterr().out
    assert "paper-models" in out and "generated" in out and "shrec07-watertight" in out
    assert main(["data", "build", "tiny", "--manifest", str(man)]) == 0
    assert "tiny: 2 meshes ready" in capsys.readouterr().out
    assert main(["data", "path", "tiny", "--manifest", str(man)]) == 0
    path = Path(capsys.readouterr().out.strip())
    assert path == tmp_path / "cache" / "generated" / "tiny" and len(list(path.iterdir())) == 2
    assert main(["data", "path", "nope"]) == 2
    assert "unknown collection 'nope'" in capsys.readouterr().err


def test_cli_help_mentions_data(capsys):
    with pytest.raises(SystemExit):
        main(["data", "--help"])
    assert "build" in capsys.readouterr().out


@pytest.mark.slow
def test_docs_example_runs(tmp_path):
    """The module docstring's example, on the tiny manifest."""
    man = _write_manifest(tmp_path, [TINY])
    code = textwrap.dedent(
        f"""
        import cshape.data
        assert cshape.data.list_collections({str(man)!r}) == ['tiny']
        m = cshape.data.load('tiny', 's', manifest={str(man)!r})
        c = cshape.data.load_collection('tiny', manifest={str(man)!r})
        print(m.n_vertices, c.names, c.labels, c[0].mesh.n_vertices)
        """
    )
    env = {**os.environ, "CSHAPE_CACHE": str(tmp_path / "c2")}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, env=env).stdout
    assert out.split()[0] == "162"
