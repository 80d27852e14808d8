"""Reading mesh files (cshape.readers): formats, byte orders, gzip, oddities that still load,
repairs reported with the file's name, and hostile files that must never crash or exhaust
the Python process (the native reader, PyMeshLab, allocates what a file *declares*, so
hostile and fuzzed files are loaded in a memory-limited subprocess here).

The errors of malformed files (one ValueError naming the file each) are the readers' table
in test_validation.py; the files themselves are built by meshfiles.py."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from meshfiles import (
    FULL_PLY,
    MALFORMED,
    OFF_TET,
    TET_F,
    TET_V,
    TET_WITH_JUNK,
    mutants,
    ply_be_double,
    ply_binary,
    ply_with_extra_list,
)

import cshape


def test_valid_binary_ply_reads_in_both_byte_orders(tmp_path):
    for endian in "<>":
        p = tmp_path / f"tet{'le' if endian == '<' else 'be'}.ply"
        p.write_bytes(ply_binary(endian=endian))
        m = cshape.load_mesh(p)
        assert (m.n_vertices, m.n_faces) == (4, 4) and m.is_closed


@pytest.mark.slow  # a subprocess
def test_hostile_files_do_not_kill_or_exhaust_the_interpreter(tmp_path):
    """Load every malformed file in a child process limited to 3 GB of address space.

    Without the pre-checks PyMeshLab would allocate the declared counts (10^12 vertices)
    before reading; here the child must survive every file and report a ValueError.
    """
    names = []
    for name, content, _ in MALFORMED:
        (tmp_path / name).write_bytes(content)
        names.append(str(tmp_path / name))
    code = textwrap.dedent(
        """
        import json, resource, sys, warnings
        resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))
        warnings.simplefilter("ignore")
        import cshape
        out = {}
        for path in json.loads(sys.argv[1]):
            try:
                cshape.load_mesh(path)
                out[path] = "loaded"
            except Exception as exc:
                out[path] = type(exc).__name__
        print(json.dumps(out))
        """
    )
    res = subprocess.run([sys.executable, "-c", code, json.dumps(names)], capture_output=True,
                         text=True, timeout=240)
    assert res.returncode == 0, f"the interpreter died (rc={res.returncode}): {res.stderr[-2000:]}"
    outcome = json.loads(res.stdout.strip().splitlines()[-1])
    assert outcome == {n: "ValueError" for n in names}


def test_unreadable_file_permissions(tmp_path):
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        pytest.skip("running as root: chmod 000 does not stop root from reading the file")
    p = tmp_path / "locked.off"
    p.write_text(OFF_TET)
    p.chmod(0)
    try:
        with pytest.raises((PermissionError, ValueError), match="locked.off"):
            cshape.load_mesh(p)
    finally:
        p.chmod(0o644)


def test_read_error_during_the_scan_names_the_file(tmp_path, monkeypatch):
    """The unreadable-file case simulated for any user (root included): open() fails."""
    import cshape._prescan as prescan
    import cshape.readers as readers

    p = tmp_path / "locked.obj"
    p.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")

    def denied(path, *args, **kwargs):
        raise PermissionError(13, "Permission denied", str(path))

    monkeypatch.setattr(readers, "open", denied, raising=False)
    monkeypatch.setattr(prescan, "open", denied, raising=False)
    monkeypatch.setattr(Path, "read_bytes", denied)
    with pytest.raises(PermissionError, match="locked.obj"):
        cshape.load_mesh(p)


def test_non_utf8_comment_in_off_is_accepted(tmp_path):
    p = tmp_path / "latin1.off"
    p.write_bytes(OFF_TET.replace("OFF\n", "OFF\n# auteur: Jos\xe9 \xa9 2024\n").encode("latin-1"))
    m = cshape.load_mesh(p)
    assert (m.n_vertices, m.n_faces) == (4, 4)


@pytest.mark.parametrize(
    "name, content",
    [
        ("crlf.off", OFF_TET.replace("\n", "\r\n").encode()),
        ("bom.off", b"\xef\xbb\xbf" + OFF_TET.encode()),
        ("UPPER.OFF", OFF_TET.encode()),
        ("trailing_nuls.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n\x00\x00\x00"),
        ("continued_lines.obj", b"v 0 0 0\nv 1 0 \\\n0\nv 0 1 0\nf 1 \\\n 2 3\n"),
        ("uppercase_V_ignored.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nV 5 5 5\nf 1 2 3\n"),
    ],
)
def test_harmless_oddities_still_load(tmp_path, name, content):
    p = tmp_path / name
    p.write_bytes(content)
    m = cshape.load_mesh(p)
    assert m.n_faces >= 1 and np.isfinite(m.vertices).all()


@pytest.mark.parametrize("ext", sorted(TET_WITH_JUNK))
def test_loaded_files_are_repaired_with_a_warning_naming_the_file(tmp_path, ext):
    """README: faces repeating a vertex, duplicate faces and unreferenced vertices are
    repaired with a warning.  (PyMeshLab drops collapsed faces itself; that used to be
    reported as a corrupt file.)"""
    p = tmp_path / f"messy.{ext}"
    p.write_text(TET_WITH_JUNK[ext])
    with pytest.warns(cshape.CShapeWarning, match=rf"messy\.{ext}: repaired mesh") as rec:
        m = cshape.load_mesh(p)
    msg = " ".join(str(w.message) for w in rec)
    for what in ("duplicate faces", "faces with a repeated vertex", "unreferenced vertices"):
        assert what in msg
    assert (m.n_vertices, m.n_faces) == (4, 4) and m.is_closed


def test_big_endian_double_ply_is_read_exactly(tmp_path):
    """PyMeshLab turns big-endian double coordinates into finite garbage without an error;
    cshape reads such files itself."""
    rng = np.random.default_rng(3)
    V = TET_V + rng.normal(scale=0.1, size=TET_V.shape)
    p = tmp_path / "be_double.ply"
    p.write_bytes(ply_be_double(V))
    m = cshape.load_mesh(p)
    np.testing.assert_array_equal(m.vertices, V)  # exactly: doubles, no float32 rounding
    np.testing.assert_array_equal(m.faces, TET_F)


@pytest.mark.parametrize("n, fmt", [(128, "binary_little_endian"), (255, "ascii")])
def test_lists_PyMeshLab_handles_still_load(tmp_path, n, fmt):
    """512 bytes is the binary limit; ASCII lists of any length are read safely."""
    p = tmp_path / "extra.ply"
    p.write_bytes(ply_with_extra_list(n, fmt))
    assert cshape.load_mesh(p).n_faces == 4


def test_failed_load_restores_the_working_folder(tmp_path, monkeypatch):
    """PyMeshLab changes into the file's folder and stayed there when a load failed."""
    sub = tmp_path / "meshes"
    sub.mkdir()
    (sub / "bad.ply").write_bytes(FULL_PLY[:-20])
    (sub / "good.off").write_text(OFF_TET)
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ValueError, match="bad.ply"):
        cshape.load_mesh("meshes/bad.ply")
    assert Path.cwd() == tmp_path
    assert cshape.load_mesh("meshes/good.off").n_faces == 4  # relative paths still work


@pytest.mark.slow  # a subprocess
def test_fuzzed_files_never_crash_the_interpreter(tmp_path):
    """600 corrupted files loaded in one memory-limited child process: each one loads or
    raises ValueError.  (Found this way: PyMeshLab segfaults on an out-of-range index in a
    polygon and aborts on a long binary list; both are now refused before it reads.)"""
    for name, content in mutants(seed=20261122, n=600):
        (tmp_path / name).write_bytes(content)
    code = textwrap.dedent(
        """
        import collections, json, resource, sys, warnings
        from pathlib import Path
        resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))
        warnings.simplefilter("ignore")
        import cshape
        out = collections.Counter()
        for p in sorted(Path(sys.argv[1]).iterdir()):
            try:
                cshape.load_mesh(p)
                out["loaded"] += 1
            except ValueError:
                out["ValueError"] += 1
            except Exception as exc:
                out[f"{p.name}: {type(exc).__name__}: {exc}"] += 1
        print(json.dumps(out))
        """
    )
    res = subprocess.run([sys.executable, "-c", code, str(tmp_path)], capture_output=True,
                         text=True, timeout=300)
    assert res.returncode == 0, f"the interpreter died (rc={res.returncode}): {res.stderr[-2000:]}"
    outcome = json.loads(res.stdout.strip().splitlines()[-1])
    assert set(outcome) <= {"loaded", "ValueError"}, outcome
    assert sum(outcome.values()) == 600 and outcome["ValueError"] > 300


# ------------------------------------------------------------------ gzip-compressed files
@pytest.mark.parametrize("name, binary", [
    ("m.off", False), ("m.obj", False), ("m.ply", False), ("m.ply", True), ("m.stl", False),
    ("m.stl", True), ("M.OFF", False)])
def test_every_format_reads_gzip_compressed(tmp_path, private_tmpdir, name, binary):
    """x.EXT.gz gives exactly the mesh of x.EXT, with the same repair warnings, which name
    the .gz file."""
    import warnings

    from conftest import save_mesh

    mesh = cshape.shapes.torus(12, 6)
    mesh = cshape.Mesh(np.vstack([mesh.vertices, [[9.0, 9, 9]]]), mesh.faces)  # unreferenced
    plain = save_mesh(tmp_path / "plain" / name, mesh, binary=binary)
    packed = save_mesh(tmp_path / "packed" / (name + ".gz"), mesh, binary=binary)
    with warnings.catch_warnings(record=True) as wa:
        warnings.simplefilter("always")
        a = cshape.load_mesh(plain)
    with warnings.catch_warnings(record=True) as wb:
        warnings.simplefilter("always")
        b = cshape.load_mesh(packed)
    np.testing.assert_array_equal(a.vertices, b.vertices)
    np.testing.assert_array_equal(a.faces, b.faces)
    assert b.n_vertices == 72 and b.is_closed
    assert [str(w.message).replace(name, name + ".gz") for w in wa] == [str(w.message) for w in wb]
    assert list(private_tmpdir.iterdir()) == []


def test_gzip_decompression_is_bounded(tmp_path, private_tmpdir, monkeypatch):
    """A small file that decompresses to far more than GZIP_MAX_BYTES (a "zip bomb") is
    refused once the bound is passed, and the partial copy removed."""
    import gzip

    import cshape.readers

    monkeypatch.setattr(cshape.readers, "GZIP_MAX_BYTES", 2**20)
    p = tmp_path / "bomb.off.gz"
    p.write_bytes(gzip.compress(b"OFF\n" + b" " * 2**24))  # 16 MiB of blanks in 16 KiB
    assert p.stat().st_size < 2**15
    with pytest.raises(ValueError, match=r"bomb\.off\.gz.*more than 1048576 bytes"):
        cshape.load_mesh(p)
    assert list(private_tmpdir.iterdir()) == []
    # under the bound the same kind of file is read
    ok = tmp_path / "ok.off.gz"
    ok.write_bytes(gzip.compress(OFF_TET.encode() + b" " * 2**19))
    assert cshape.load_mesh(ok).n_faces == 4


def test_split_mesh_name_looks_through_gzip():
    from cshape.readers import split_mesh_name

    assert split_mesh_name("a/b/bunny.off.gz") == ("bunny", ".off")
    assert split_mesh_name("Scan.PLY.GZ") == ("Scan", ".ply")
    assert split_mesh_name("x.stl") == ("x", ".stl")
    assert split_mesh_name("archive.gz") == ("archive", "")


def test_load_folder_reads_compressed_meshes(tmp_path):
    """Folder collections pick up .off.gz / .ply.gz / ... beside plain files; item names drop
    both suffixes, labels come from the sub-folders as usual."""
    from conftest import save_mesh

    save_mesh(tmp_path / "round" / "s1.off.gz", cshape.shapes.icosphere(1))
    save_mesh(tmp_path / "round" / "s2.ply", cshape.shapes.icosphere(2))
    save_mesh(tmp_path / "ring" / "t1.stl.gz", cshape.shapes.torus(12, 6), binary=True)
    save_mesh(tmp_path / "ring" / "sub" / "s1.obj.gz", cshape.shapes.torus(10, 5))
    (tmp_path / "ring" / "notes.txt.gz").write_bytes(b"")
    c = cshape.data.load_folder(tmp_path)
    got = {(it.name, it.label) for it in c.items}
    # s1 repeats: names become relative paths, without .off.gz / .obj.gz
    assert got == {("round/s1", "round"), ("round/s2", "round"), ("ring/t1", "ring"),
                   ("ring/sub/s1", "ring")}
    sizes = {it.name: it.mesh.n_vertices for it in c.items}
    assert sizes == {"round/s1": 42, "round/s2": 162, "ring/t1": 72, "ring/sub/s1": 50}
