"""Hardening: untrusted data and interrupted or concurrent runs.

* YAML manifests are read with a safe loader: Python tags raise, never execute;
* no pickle anywhere: caches and saved tables are plain arrays, and a crafted file holding
  a pickled object is refused (or rebuilt) without running it;
* downloads are checked against their sha256 before use (no network: pooch's transport is
  replaced by a local fake);
* archive extraction cannot write outside its target (``..``, absolute paths, links);
* the data cache survives killed and concurrent builds, and a cache folder that cannot be
  written or a full disk gives a clear error with nothing half-written.
"""

from __future__ import annotations

import errno
import hashlib
import io
import json
import os
import re
import signal
import socket
import stat
import subprocess
import sys
import tarfile
import textwrap
import zipfile
from pathlib import Path

import numpy as np
import pytest
import yaml

import cshape
import cshape.data as data
from cshape import shapes

PACKAGE = Path(cshape.__file__).resolve().parent

TINY = {
    "name": "tiny",
    "kind": "generated",
    "description": "test",
    "license": "BSD-3-Clause",
    "citation": "none",
    "items": [{"name": "s", "label": "sphere", "recipe": "sphere", "params": {"subdivisions": 2}}],
}


@pytest.fixture(autouse=True)
def _isolated(tmp_path, monkeypatch):
    """An empty cache per test, and no network: any socket connection fails the test."""
    monkeypatch.setenv("CSHAPE_CACHE", str(tmp_path / "cache"))
    monkeypatch.delenv("CSHAPE_MANIFEST", raising=False)

    def no_network(*args, **kwargs):
        raise AssertionError("a test tried to open a network connection")

    monkeypatch.setattr(socket.socket, "connect", no_network)


def _manifest(tmp_path, collections, name="m.yaml"):
    p = tmp_path / name
    p.write_text(yaml.safe_dump({"version": 1, "collections": collections}), encoding="utf-8")
    return p


class _Payload:
    """Unpickling this creates ``marker`` (an ``open(marker, 'w')`` call): proof of execution."""

    def __init__(self, marker):
        self.marker = str(marker)

    def __reduce__(self):
        return (open, (self.marker, "w"))


def _pickled_npz(path, marker, **extra):
    """An .npz whose ``vertices`` is an object array: loading it with pickle runs _Payload."""
    arr = np.empty(1, dtype=object)
    arr[0] = _Payload(marker)
    np.savez(path, vertices=arr, faces=np.zeros((1, 3), np.int64), **extra)


def _package_sources():
    return sorted(PACKAGE.rglob("*.py"))


# ====================================================================== YAML
@pytest.mark.parametrize(
    "tag",
    [
        "!!python/object/apply:builtins.open ['{marker}', 'w']",
        "!!python/object/new:builtins.open ['{marker}', 'w']",
        "!!python/name:builtins.open",
        "!!python/object:cshape.data.manifest.Item {{name: x}}",
    ],
)
def test_manifest_with_python_tags_raises_and_runs_nothing(tmp_path, monkeypatch, tag):
    marker = tmp_path / "EXECUTED"
    p = tmp_path / "evil.yaml"
    p.write_text(f"version: 1\ncollections:\n  - {tag.format(marker=marker)}\n")
    with pytest.raises(ValueError, match=r"evil\.yaml: not valid YAML"):
        data.manifest.load_manifest(p)
    monkeypatch.setenv("CSHAPE_MANIFEST", str(p))
    with pytest.raises(ValueError, match="not valid YAML"):
        data.list_collections()
    assert not marker.exists()


def test_package_reads_yaml_only_with_the_safe_loader():
    """yaml.safe_load, or yaml.load with libyaml's safe loader or PyYAML's own safe loader on
    the same line; nothing else."""
    unsafe = re.compile(r"yaml\.(load|full_load|unsafe_load|load_all)\s*\(|Loader\s*=")
    safe = re.compile(r'yaml\.load\([^()]*, Loader=getattr\(yaml, "CSafeLoader", '
                      r"yaml\.SafeLoader\)\)")
    hits = [f"{p.name}:{i}" for p in _package_sources()
            for i, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1)
            if unsafe.search(safe.sub("", line))]
    assert hits == []


# ====================================================================== no pickle
def test_package_never_unpickles():
    bad = re.compile(r"\bimport (c?pickle|dill|cloudpickle|joblib|shelve)\b|pickle\.loads?\("
                     r"|allow_pickle\s*=\s*True|read_pickle|to_pickle|marshal\.loads?\(")
    hits, loads = [], []
    for p in _package_sources():
        for i, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1):
            if bad.search(line):
                hits.append(f"{p.name}:{i}: {line.strip()}")
            if "np.load(" in line:
                loads.append((f"{p.name}:{i}", "allow_pickle=False" in line))
    assert hits == []
    assert loads and all(ok for _, ok in loads), loads  # every np.load refuses pickles


def test_pickled_generated_cache_file_is_rebuilt_not_executed(tmp_path):
    marker = tmp_path / "EXECUTED"
    man = data.manifest.load_manifest(_manifest(tmp_path, [TINY]))
    path = data.store._cache_file(man, "tiny", man["tiny"]["items"][0], tmp_path / "cache")
    path.parent.mkdir(parents=True)
    _pickled_npz(path, marker)
    with pytest.warns(UserWarning, match="rebuilding unreadable cache file.*Object arrays"):
        m = data.load("tiny", "s", manifest=man)
    assert m.n_vertices == 162 and not marker.exists()
    with np.load(path, allow_pickle=False) as z:  # overwritten with plain arrays
        assert z["vertices"].dtype == np.float64


def test_pickled_npz_read_directly_is_a_clear_error(tmp_path):
    marker = tmp_path / "EXECUTED"
    p = tmp_path / "item.npz"
    _pickled_npz(p, marker)
    with pytest.raises(ValueError, match=r"cannot read cached mesh .*item\.npz.*Object arrays"):
        data.files._FileLoader(p)()
    assert not marker.exists()


def test_pickled_eigenvalue_cache_entry_is_recomputed_not_executed(tmp_path):
    from cshape.batch import describe
    from cshape.batch.cache import mesh_key

    marker = tmp_path / "EXECUTED"
    mesh = shapes.icosphere(1)
    cache = tmp_path / "eig"
    cache.mkdir()
    arr = np.empty(1, dtype=object)
    arr[0] = _Payload(marker)
    key = mesh_key(mesh)
    np.savez(cache / f"{key}.npz", lam=arr, area=np.float64(1.0), seconds=np.float64(0.0),
             key=np.array(key))
    with pytest.warns(cshape.CShapeWarning, match="corrupt cache entry"):
        table = describe([("ball", mesh)], N=6, cache_dir=cache, progress=False)
    assert not marker.exists()
    np.testing.assert_allclose(table.lam[0], cshape.shape_dna(mesh, N=6), atol=1e-12)


def test_pickled_descriptor_table_is_refused_not_executed(tmp_path):
    from cshape.batch import DescriptorTable

    marker = tmp_path / "EXECUTED"
    p = tmp_path / "table.npz"
    names = np.empty(1, dtype=object)
    names[0] = _Payload(marker)
    meta = {"format": "cshape-descriptor-table", "format_version": 1, "N": 3, "M": 1,
            "bc": "neumann", "mass": "consistent", "failures": []}
    np.savez(p, names=names, labels=np.array(["a"]), lam=np.zeros((1, 3)), areas=np.ones(1),
             seconds=np.zeros(1), cached=np.zeros(1, bool), meta=np.array(json.dumps(meta)))
    with pytest.raises(ValueError, match="allow_pickle"):
        DescriptorTable.load(p)
    assert not marker.exists()


# ====================================================================== downloads
def _download_manifest(tmp_path, payload: bytes):
    item = {"name": "tet", "label": "tet", "file": "tet.off",
            "url": "https://example.invalid/meshes/tet.off",
            "sha256": hashlib.sha256(payload).hexdigest(), "size": len(payload)}
    entry = {"name": "dl", "kind": "download", "description": "test", "license": "CC0",
             "citation": "none", "page": "https://example.invalid", "format": "OFF",
             "items": [item]}
    return _manifest(tmp_path, [entry], "dl.yaml")


TET_OFF = b"OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"


@pytest.fixture
def fake_transport(monkeypatch):
    """Replace pooch's downloaders by one serving ``served['bytes']``; counts the calls."""
    pytest.importorskip("pooch")
    import pooch.core

    served = {"bytes": TET_OFF, "calls": 0}

    def choose(url, progressbar=False):
        def download(url, output_file, pooch_obj, check_only=False):
            served["calls"] += 1
            Path(output_file).write_bytes(served["bytes"])

        return download

    monkeypatch.setattr(pooch.core, "choose_downloader", choose)
    return served


def test_download_with_the_right_checksum_is_used(tmp_path, fake_transport):
    man = _download_manifest(tmp_path, TET_OFF)
    m = data.load("dl", "tet", download=True, manifest=man)
    assert m.n_faces == 4 and fake_transport["calls"] == 1
    assert data.load("dl", "tet", manifest=man).n_faces == 4  # from the cache, verified
    assert fake_transport["calls"] == 1


def test_download_with_a_wrong_checksum_is_refused_and_not_kept(tmp_path, fake_transport):
    man = _download_manifest(tmp_path, TET_OFF)
    fake_transport["bytes"] = TET_OFF.replace(b"0 0 1\n", b"0 0 9\n")  # a tampered mirror
    with pytest.raises(ValueError, match=r"(?i)hash.*does not match"):
        data.load("dl", "tet", download=True, manifest=man)
    folder = data.paths.collection_path("dl", manifest=man)
    assert not folder.exists() or [p.name for p in folder.rglob("*")
                                   if p.is_file()] == []  # no file, no temporary
    with pytest.raises(FileNotFoundError, match="not downloaded yet"):
        data.load("dl", "tet", manifest=man)


@pytest.mark.parametrize("tamper", ["same_size", "other_size"])
def test_cached_download_is_verified_before_each_read(tmp_path, fake_transport, tamper):
    man = _download_manifest(tmp_path, TET_OFF)
    data.fetch("dl", manifest=man, progress=False)
    f = data.paths.collection_path("dl", manifest=man) / "tet.off"
    good = f.read_bytes()
    f.write_bytes(good.replace(b"0 0 1\n", b"0 0 2\n") if tamper == "same_size"
                  else good + b"# appended\n")
    why = "sha256 differs" if tamper == "same_size" else "size is"
    with pytest.raises(ValueError, match=rf"tet\.off.*fails its check: its {why}.*cshape data "
                                         r"build dl"):
        data.load("dl", "tet", manifest=man)
    with pytest.raises(ValueError, match="fails its check"):
        data.load_collection("dl", manifest=man)["tet"].mesh  # noqa: B018
    # fetching again repairs it (pooch sees the wrong hash and downloads anew)
    data.fetch("dl", manifest=man, progress=False)
    assert data.load("dl", "tet", manifest=man).n_faces == 4


def test_download_urls_must_be_https(tmp_path):
    man = yaml.safe_load(_download_manifest(tmp_path, TET_OFF).read_text())
    for url in ["http://example.invalid/tet.off", "file:///etc/passwd", "ftp://x/tet.off"]:
        man["collections"][0]["items"][0]["url"] = url
        with pytest.raises(ValueError, match="field 'url' must be an https URL"):
            data.manifest.validate_manifest(man)


@pytest.mark.parametrize("bad", ["../escape.off", "/etc/passwd", "a/../../escape.off"])
def test_manifest_file_fields_cannot_point_outside(tmp_path, bad):
    man = yaml.safe_load(_download_manifest(tmp_path, TET_OFF).read_text())
    man["collections"][0]["items"][0]["file"] = bad
    with pytest.raises(ValueError, match="field 'file' must be a relative path inside"):
        data.manifest.validate_manifest(man)


# ====================================================================== archives
def _zip(path, members):
    with zipfile.ZipFile(path, "w") as zf:
        for name, content in members:
            if isinstance(content, zipfile.ZipInfo):
                zf.writestr(content, name)
            else:
                zf.writestr(name, content)
    return path


def _tar(path, members):
    with tarfile.open(path, "w") as tf:
        for m in members:
            if m.isfile():
                tf.addfile(m, io.BytesIO(b"x" * m.size))
            else:
                tf.addfile(m)
    return path


def _tinfo(name, kind=tarfile.REGTYPE, linkname=""):
    info = tarfile.TarInfo(name)
    info.type = kind
    info.linkname = linkname
    info.size = 1 if kind == tarfile.REGTYPE else 0
    return info


def _files_under(folder: Path):
    """Files and links below ``folder`` (extract_archive may create the target's parent)."""
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*")
                  if p.is_file() or p.is_symlink())


@pytest.mark.parametrize("name", ["../evil.txt", "/tmp/evil.txt", "a/../../evil.txt",
                                  "..\\evil.txt", "a\\..\\..\\evil.txt", "C:/evil.txt",
                                  "C:evil.txt"])
def test_zip_members_escaping_the_target_are_refused(tmp_path, name):
    z = _zip(tmp_path / "evil.zip", [("ok.txt", "fine"), (name, "bad")])
    before = _files_under(tmp_path)
    with pytest.raises(ValueError, match="outside the target folder"):
        data.download.extract_archive(z, tmp_path / "out" / "target")
    assert _files_under(tmp_path) == before  # nothing written anywhere, target not created


@pytest.mark.parametrize(
    "member, match",
    [
        (_tinfo("../evil.txt"), "outside the target folder"),
        (_tinfo("/tmp/evil.txt"), "outside the target folder"),
        (_tinfo("sub/../../evil.txt"), "outside the target folder"),
        (_tinfo("link", tarfile.SYMTYPE, "../../etc"), "link or special file"),
        (_tinfo("inside_link", tarfile.SYMTYPE, "ok.txt"), "link or special file"),
        (_tinfo("hard", tarfile.LNKTYPE, "/etc/passwd"), "link or special file"),
        (_tinfo("fifo", tarfile.FIFOTYPE), "link or special file"),
        (_tinfo("dev", tarfile.CHRTYPE), "link or special file"),
        (_tinfo("blk", tarfile.BLKTYPE), "link or special file"),
    ],
    ids=["dotdot", "absolute", "nested_dotdot", "symlink_out", "symlink_in", "hardlink",
         "fifo", "chardev", "blockdev"],
)
def test_tar_members_escaping_or_special_are_refused(tmp_path, member, match):
    t = _tar(tmp_path / "evil.tar", [_tinfo("ok.txt"), member])
    before = _files_under(tmp_path)
    with pytest.raises(ValueError, match=match):
        data.download.extract_archive(t, tmp_path / "out" / "target")
    assert _files_under(tmp_path) == before


def test_zip_symlink_entry_is_written_as_a_plain_file(tmp_path):
    info = zipfile.ZipInfo("link")
    info.external_attr = (stat.S_IFLNK | 0o777) << 16  # a Unix symlink entry
    z = _zip(tmp_path / "link.zip", [("/etc/passwd", info)])
    out = data.download.extract_archive(z, tmp_path / "target")
    assert not (out / "link").is_symlink()
    assert (out / "link").read_text() == "/etc/passwd"  # the link text, as data


def test_existing_symlink_in_the_target_is_not_followed(tmp_path):
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "precious.txt").write_text("keep")
    target = tmp_path / "target"
    target.mkdir()
    (target / "sub").symlink_to(outside, target_is_directory=True)
    z = _zip(tmp_path / "a.zip", [("sub/new.txt", "data")])
    data.download.extract_archive(z, target)  # the link is replaced by the archive's folder
    assert not (target / "sub").is_symlink() and (target / "sub" / "new.txt").is_file()
    assert _files_under(outside) == ["precious.txt"]
    assert (outside / "precious.txt").read_text() == "keep"
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".target.extract.")]


def test_not_an_archive(tmp_path):
    p = tmp_path / "model.zip"
    p.write_bytes(b"\x89PNG\r\n\x1a\n" + b"\0" * 100)
    with pytest.raises(ValueError, match=r"model\.zip.*not a \.zip or \.tar archive"):
        data.download.extract_archive(p, tmp_path / "target")


def test_build_with_an_escaping_archive_writes_nothing(tmp_path):
    z = _zip(tmp_path / "shrec.zip", [("watertight/1.off", "OFF\n"), ("../../evil.off", "x")])
    with pytest.raises(ValueError, match="outside the target folder"):
        data.build("shrec07-watertight", archive=z)
    downloads = tmp_path / "cache" / "downloads"
    assert not downloads.exists() or _files_under(downloads) == []
    assert not list(tmp_path.rglob("evil.off"))


# ====================================================================== interrupted writes
def _run_child(code, tmp_path, *args, timeout=120):
    env = {**os.environ, "CSHAPE_CACHE": str(tmp_path / "cache")}
    return subprocess.Popen([sys.executable, "-c", textwrap.dedent(code), *map(str, args)],
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _cache_folder(tmp_path):
    return tmp_path / "cache" / "generated" / "tiny"


def test_build_killed_mid_write_leaves_no_cache_entry(tmp_path):
    man = _manifest(tmp_path, [TINY])
    code = """
        import os, signal, sys
        import numpy as np
        import cshape.data as data

        def dying_savez(fh, **arrays):
            fh.write(b"PK\\x03\\x04 half an npz")
            fh.flush()
            os.kill(os.getpid(), signal.SIGKILL)  # killed in the middle of the write

        data.store.np.savez = dying_savez
        data.load("tiny", "s", manifest=sys.argv[1])
    """
    child = _run_child(code, tmp_path, man)
    child.communicate(timeout=120)
    assert child.returncode == -signal.SIGKILL
    folder = _cache_folder(tmp_path)
    assert not list(folder.glob("*.npz"))  # no final entry, only a hidden temporary
    # a hidden temporary, and the build's lock file (the system released the lock)
    assert all(p.name.startswith(".") and p.name.endswith((".tmp", ".npz.lock"))
               for p in folder.iterdir())
    m = data.load("tiny", "s", manifest=man)  # the next run builds it cleanly
    assert m.n_vertices == 162 and len(list(folder.glob("*.npz"))) == 1
    assert not list(folder.glob(".*.lock"))  # and takes the lock file away


def test_interrupt_mid_write_removes_the_temporary(tmp_path, monkeypatch):
    man = _manifest(tmp_path, [TINY])

    def interrupted(fh, **arrays):
        fh.write(b"PK\x03\x04 partial")
        raise KeyboardInterrupt

    monkeypatch.setattr(data.store.np, "savez", interrupted)
    with pytest.raises(KeyboardInterrupt):
        data.load("tiny", "s", manifest=man)
    assert list(_cache_folder(tmp_path).iterdir()) == []


@pytest.mark.slow
def test_two_processes_building_the_same_item_do_not_corrupt_it(tmp_path):
    man = _manifest(tmp_path, [TINY])
    start = tmp_path / "go"
    code = """
        import hashlib, os, sys, time
        from pathlib import Path
        import cshape.data as data

        real = data.store.np.savez

        def slow_savez(fh, **arrays):  # both writers are inside the write at once
            real(fh, **arrays)
            time.sleep(0.5)

        data.store.np.savez = slow_savez
        while not Path(sys.argv[2]).exists():
            time.sleep(0.01)
        m = data.load("tiny", "s", manifest=sys.argv[1])
        print(hashlib.sha256(m.vertices.tobytes() + m.faces.tobytes()).hexdigest())
    """
    children = [_run_child(code, tmp_path, man, start) for _ in range(2)]
    start.touch()
    outs = [c.communicate(timeout=120) for c in children]
    assert [c.returncode for c in children] == [0, 0], [o[1][-1500:] for o in outs]
    digests = {o[0].split()[-1] for o in outs}
    assert len(digests) == 1
    files = list(_cache_folder(tmp_path).iterdir())
    assert [f.suffix for f in files] == [".npz"]  # one entry, no temporaries left
    m = data.load("tiny", "s", manifest=man)
    assert hashlib.sha256(m.vertices.tobytes() + m.faces.tobytes()).hexdigest() in digests


# ====================================================================== unwritable cache
def test_cache_dir_under_a_regular_file_is_a_clear_error(tmp_path):
    man = _manifest(tmp_path, [TINY])
    blocker = tmp_path / "not_a_folder"
    blocker.write_text("I am a file")
    with pytest.raises(OSError, match=r"cannot create the cache folder .*not_a_folder.* is a "
                                      r"file, not a folder.*CSHAPE_CACHE"):
        data.load("tiny", "s", manifest=man, cache_dir=blocker / "cache")
    with pytest.raises(OSError, match="is a file, not a folder"):
        data.load("tiny", "s", manifest=man, cache_dir=blocker)
    assert blocker.read_text() == "I am a file"


def test_read_only_cache_dir_is_a_clear_error(tmp_path):
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        pytest.skip("running as root: a read-only folder does not stop root from writing "
                    "(the case is covered by test_cache_dir_under_a_regular_file_...)")
    man = _manifest(tmp_path, [TINY])
    folder = _cache_folder(tmp_path)
    folder.mkdir(parents=True)
    folder.chmod(0o555)
    try:
        with pytest.raises(OSError, match=r"cannot write to the cache folder .*CSHAPE_CACHE"):
            data.load("tiny", "s", manifest=man)
    finally:
        folder.chmod(0o755)


@pytest.mark.parametrize("where", ["write", "replace"])
def test_full_disk_is_a_clear_error_and_leaves_nothing(tmp_path, monkeypatch, where):
    man = _manifest(tmp_path, [TINY])
    enospc = OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    if where == "write":
        def full(fh, **arrays):
            fh.write(b"PK\x03\x04 the first few bytes")
            raise enospc

        monkeypatch.setattr(data.store.np, "savez", full)
    else:
        def full(src, dst):
            raise enospc

        monkeypatch.setattr(os, "replace", full)
    with pytest.raises(OSError, match=r"no space left to write the cache file .*s-\w+\.npz.*"
                                      r"nothing was written.*CSHAPE_CACHE") as info:
        data.load("tiny", "s", manifest=man)
    assert info.value.errno == errno.ENOSPC
    assert list(_cache_folder(tmp_path).iterdir()) == []


def test_descriptor_table_save_on_a_full_disk_leaves_nothing(tmp_path, monkeypatch):
    from cshape.batch import describe

    table = describe([("ball", shapes.icosphere(1))], N=5, cache_dir=False,
                     progress=False)
    monkeypatch.setattr(os, "replace", lambda *a: (_ for _ in ()).throw(
        OSError(errno.ENOSPC, "No space left on device")))
    for name in ("t.npz", "t.csv"):
        with pytest.raises(OSError, match="No space left"):
            table.save(tmp_path / "tables" / name)
    assert list((tmp_path / "tables").iterdir()) == []


# ====================================================================== local folders
@pytest.mark.parametrize("bad", ["../outside.off", "/etc/passwd", "a/../../outside.off",
                                 "..\\outside.off", ""])
def test_labels_csv_cannot_point_outside_its_folder(tmp_path, bad):
    folder = tmp_path / "meshes"
    folder.mkdir()
    (folder / "ok.off").write_bytes(TET_OFF)
    (tmp_path / "outside.off").write_bytes(TET_OFF)
    (folder / "labels.csv").write_text(f"file,label\nok.off,tet\n{bad},x\n")
    with pytest.raises(ValueError, match=r"labels CSV 'labels.csv', line 3: file .* must be a "
                                         "relative path inside"):
        data.load_folder(folder, labels="labels.csv")


@pytest.mark.parametrize("name", ["../../../escaped", "/tmp/abs", "sub/dir", ".hidden", "..",
                                  "a\\..\\b", ""])
def test_generated_item_names_cannot_escape_the_cache(tmp_path, name):
    """Item names become cache file names (<cache>/generated/<coll>/<item>-<key>.npz)."""
    entry = {**TINY, "items": [{**TINY["items"][0], "name": name}]}
    with pytest.raises(ValueError, match="item name must be letters, digits|missing required"):
        data.manifest.load_manifest(_manifest(tmp_path, [entry]))
    assert not list(tmp_path.rglob("*.npz"))


def test_tar_extraction_drops_setuid_and_world_writable_bits(tmp_path):
    info = _tinfo("run.sh")
    info.mode = 0o6777  # setuid, setgid, writable by everyone
    out = data.download.extract_archive(_tar(tmp_path / "suid.tar", [info]), tmp_path / "target")
    mode = (out / "run.sh").stat().st_mode
    assert not mode & (stat.S_ISUID | stat.S_ISGID | stat.S_IWOTH)


def test_archive_larger_than_the_free_space_is_refused_before_writing(tmp_path, monkeypatch):
    import shutil
    from collections import namedtuple

    z = _zip(tmp_path / "big.zip", [("a.off", "x" * 5000), ("b.off", "y" * 5000)])
    usage = namedtuple("usage", "total used free")
    monkeypatch.setattr(shutil, "disk_usage", lambda path: usage(10**6, 10**6 - 4000, 4000))
    with pytest.raises(OSError, match=r"big\.zip' unpacks to 0\.0 MB but only 0\.0 MB are "
                                      r"free .*free disk space") as info:
        data.download.extract_archive(z, tmp_path / "target")
    assert info.value.errno == errno.ENOSPC
    assert _files_under(tmp_path) == ["big.zip"]


def test_cache_file_of_another_recipe_is_not_taken_for_this_item(tmp_path):
    """A cache file copied over (or written) from another item is detected and rebuilt."""
    other = {**TINY["items"][0], "name": "t", "params": {"subdivisions": 1}}
    man = data.manifest.load_manifest(
        _manifest(tmp_path, [{**TINY, "items": [TINY["items"][0], other]}]))
    data.load_collection("tiny", manifest=man, progress=False)
    root = tmp_path / "cache"
    s_path = data.store._cache_file(man, "tiny", man["tiny"]["items"][0], root)
    t_path = data.store._cache_file(man, "tiny", man["tiny"]["items"][1], root)
    s_path.write_bytes(t_path.read_bytes())  # 's' now holds the 42-vertex sphere of 't'
    with pytest.warns(UserWarning, match="rebuilding .* another recipe"):
        m = data.load("tiny", "s", manifest=man)
    assert m.n_vertices == 162
    assert data.load("tiny", "s", manifest=man).n_vertices == 162  # repaired on disk


@pytest.mark.parametrize("bad", ["../../etc", "/etc", "meshes/../../.."])
def test_package_collection_path_stays_inside_the_package(tmp_path, bad):
    entry = {"name": "pkg", "kind": "package", "description": "t", "license": "x",
             "citation": "n", "package": "pymeshlab", "path": bad,
             "items": [{"name": "a", "label": "a", "file": "a.ply"}]}
    with pytest.raises(ValueError, match="field 'path' must be a folder inside package"):
        data.manifest.load_manifest(_manifest(tmp_path, [entry]))
