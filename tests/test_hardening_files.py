"""Hardening: malformed and hostile mesh files beyond those of test_mesh.py.

Every bad file must give a ``ValueError`` (or ``FileNotFoundError``) naming the file, and
never crash or exhaust the Python process: the native reader (PyMeshLab) allocates what a
file *declares*, so loads of hostile files also run in a memory-limited subprocess here.
"""

from __future__ import annotations

import io
import json
import os
import struct
import subprocess
import sys
import textwrap
import zipfile
from pathlib import Path

import numpy as np
import pytest

import cshape

TET_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
TET_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
OFF_TET = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"
PNG_HEAD = b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR" + bytes(range(256)) * 2


def _ply_binary(V=TET_V, F=TET_F, *, nv=None, nf=None, endian="<", count_type="B"):
    """A binary PLY (float32 x y z; uchar-int face lists), with optionally lying counts."""
    fmt = "binary_little_endian" if endian == "<" else "binary_big_endian"
    nv = len(V) if nv is None else nv
    nf = len(F) if nf is None else nf
    head = (
        f"ply\nformat {fmt} 1.0\nelement vertex {nv}\nproperty float x\nproperty float y\n"
        f"property float z\nelement face {nf}\nproperty list uchar int vertex_indices\n"
        "end_header\n"
    ).encode()
    body = b"".join(struct.pack(endian + "3f", *v) for v in np.asarray(V, np.float32))
    body += b"".join(struct.pack(f"{endian}{count_type}{len(f)}i", len(f), *f) for f in F)
    return head + body


def _zip_bytes():
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", compression=zipfile.ZIP_DEFLATED) as zf:
        zf.writestr("mesh.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    return buf.getvalue()


def _binary_stl(V, F, nan_at=None):
    tris = np.asarray(V, np.float32)[F].copy()
    if nan_at is not None:
        tris[nan_at] = np.nan
    recs = b"".join(struct.pack("<12fH", 0, 0, 0, *t.reshape(-1), 0) for t in tris)
    return b"\0" * 80 + struct.pack("<I", len(F)) + recs


def _ascii_stl(V, F, replace=None):
    out = ["solid t"]
    for t in np.asarray(V)[F]:
        out += ["facet normal 0 0 0", "outer loop"]
        out += [f"vertex {x} {y} {z}" for x, y, z in t]
        out += ["endloop", "endfacet"]
    text = "\n".join(out + ["endsolid t"]) + "\n"
    return text.replace(*replace, 1) if replace else text


PLY_ASCII_HEAD = (
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
    "property float z\nelement face {nf}\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
)
def _ply_with_extra_list(n, fmt="binary_little_endian"):
    """The tetrahedron plus an element 'foo' holding one list of ``n`` ints."""
    head = (f"ply\nformat {fmt} 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
            "property float z\nelement face 4\nproperty list uchar int vertex_indices\n"
            "element foo 1\nproperty list uchar int bar\nend_header\n")
    if fmt == "ascii":
        body = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n" + "".join(f"3 {a} {b} {c}\n" for a, b, c in TET_F)
        return (head + body + f"{n} " + " ".join(["0"] * n) + "\n").encode()
    body = b"".join(struct.pack("<3f", *v) for v in TET_V)
    body += b"".join(struct.pack("<B3i", 3, *f) for f in TET_F)
    return head.encode() + body + struct.pack(f"<B{n}i", n, *([0] * n))


_FULL = _ply_binary()
_HEADER_END = _FULL.index(b"end_header\n") + len(b"end_header\n")
_F_OOR = TET_F.copy()
_F_OOR[3, 2] = 99
_F_NEG = TET_F.copy()
_F_NEG[3, 2] = -5
_V_NAN = TET_V.copy()
_V_NAN[3, 2] = np.nan
_V_INF = TET_V.copy()
_V_INF[1, 0] = np.inf

#: (file name, content, expected message): every one must raise ValueError naming the file.
MALFORMED = [
    # binary PLY
    ("trunc_in_vertices.ply", _FULL[: _HEADER_END + 20], "need at least 52 bytes.*truncated"),
    ("trunc_in_faces.ply", _FULL[:-20], "records end early: the file is truncated"),
    ("oor_index.ply", _ply_binary(F=_F_OOR), "Bad vertex index in face 3: 99, .* 4 vertices"),
    ("negative_index.ply", _ply_binary(F=_F_NEG), "Bad vertex index in face 3: -5"),
    ("nan_vertex.ply", _ply_binary(V=_V_NAN), "declares 4 vertices but 3 could be read"),
    ("inf_vertex.ply", _ply_binary(V=_V_INF), "declares 4 vertices but 3 could be read"),
    ("oor_big_endian.ply", _ply_binary(F=_F_OOR, endian=">"), "Bad vertex index"),
    # an out-of-range index in a polygon made PyMeshLab segfault (the Python process died)
    ("oor_in_quad.ply", _ply_binary(F=[[0, 2, 1, 3], [0, 1, 3, 99]]), "face 1: 99"),
    ("oor_in_quad_ascii.ply", (PLY_ASCII_HEAD.format(nf=2) + "4 0 2 1 3\n5 0 1 3 2 -5\n").encode(),
     "face 1: -5"),
    # a binary list over 512 bytes outside the face indices aborted it (buffer overflow)
    ("long_list_extra_element.ply", _ply_with_extra_list(129), "list property 'bar' of 516 bytes"),
    ("renamed_face_element.ply", _FULL.replace(b"element face", b"element f\x8dce"),
     "4 vertices but no triangles"),
    ("list_runs_past_eof.ply", _FULL.replace(struct.pack("<B3i", 3, 0, 2, 1),
                                             struct.pack("<B3i", 255, 0, 2, 1)),
     "records end early"),
    ("huge_counts.ply", _ply_binary(nv=10**12, nf=10**12), "declares 1000000000000 vertex"),
    ("int32_overflow.ply", _ply_binary(nv=2**31 + 10), "need at least"),
    ("huge_faces_ascii.ply", b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
     b"property float y\nproperty float z\nelement face 300000000\n"
     b"property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
     "300000000 face records"),
    ("negative_count.ply", _ply_binary(nv=-4), "negative count -4"),
    ("word_count.ply", _FULL.replace(b"element vertex 4", b"element vertex four"),
     "integer count"),
    ("no_xyz.ply", _FULL.replace(b"property float x\nproperty float y\nproperty float z",
                                 b"property float a\nproperty float b\nproperty float c"),
     "No vertex field found"),
    ("unknown_format.ply", _FULL.replace(b"binary_little_endian", b"binary_middle_endian"),
     "Format not found"),
    # counts far beyond the file in the text formats
    ("huge_counts.off", b"OFF\n1000000000000 1000000000000 0\n0 0 0\n", "truncated"),
    # NaN vertices in STL: PyMeshLab alone silently drops their triangles
    ("nan_vertex_ascii.stl", _ascii_stl(TET_V, TET_F, ("vertex 0.0 0.0 1.0",
                                                      "vertex nan 0.0 1.0")).encode(),
     "line .*NaN or infinite"),
    ("nan_vertex_binary.stl", _binary_stl(TET_V, TET_F, nan_at=(2, 1)),
     "declares 4 triangles.*only 3"),
    # non-mesh content behind a mesh extension
    *[(f"png_image.{ext}", PNG_HEAD, why) for ext, why in [
        ("obj", "not an OBJ triangle mesh"), ("off", "expected the OFF header"),
        ("ply", "'ply' magic line"), ("stl", "binary STL header declares")]],
    *[(f"zip_archive.{ext}", _zip_bytes(), why) for ext, why in [
        ("obj", "not an OBJ triangle mesh"), ("off", "expected the OFF header"),
        ("ply", "'ply' magic line"), ("stl", "binary STL header declares")]],
    # binary junk inside a text format
    ("junk_coordinate.off", OFF_TET.encode().replace(b"0 0 1\n", b"0 0 \xff\xfe\n"),
     "line 6: vertex coordinates .* are not numbers"),
    ("huge_index.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n",
     "references vertex 99999999999999999999"),
    # PyMeshLab's OBJ reader skips indented 'v' lines but not 'f' lines, and hands back faces
    # with out-of-range indices (heap corruption, "munmap_chunk(): invalid pointer", seen)
    ("indented_vertex.obj", b"  v 0 0 0\n v 1 0 0\nv 0 1 0\nv 0 0 1\n f 1 3 2\nf 1 2 4\n",
     "line 1: the vertex record is indented"),
    ("indented_face_oor.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\n\tf 1 2 9\n", "vertex 9"),
    ("face_comment.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3 # c\n",
     "line 5: face index '#' is not an integer"),
]


@pytest.mark.parametrize("name, content, match", MALFORMED, ids=[m[0] for m in MALFORMED])
def test_malformed_file_gives_clear_error(tmp_path, name, content, match):
    p = tmp_path / name
    p.write_bytes(content)
    with pytest.raises(ValueError, match=match) as info:
        cshape.load_mesh(p)
    assert name in str(info.value)  # the message names the file


def test_valid_binary_ply_reads_in_both_byte_orders(tmp_path):
    for endian in "<>":
        p = tmp_path / f"tet{'le' if endian == '<' else 'be'}.ply"
        p.write_bytes(_ply_binary(endian=endian))
        m = cshape.load_mesh(p)
        assert (m.n_vertices, m.n_faces) == (4, 4) and m.is_closed


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


def test_directory_named_like_a_mesh(tmp_path):
    d = tmp_path / "x.obj"
    d.mkdir()
    with pytest.raises(ValueError, match=r"x\.obj.*is a folder, not a mesh file"):
        cshape.load_mesh(d)


def test_fifo_named_like_a_mesh_does_not_hang(tmp_path):
    if not hasattr(os, "mkfifo"):
        pytest.skip("no named pipes on this platform")
    p = tmp_path / "pipe.off"
    os.mkfifo(p)  # opening it for reading would block forever without a writer
    with pytest.raises(ValueError, match=r"pipe\.off.*empty"):
        cshape.load_mesh(p)


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
    import cshape.readers as readers

    p = tmp_path / "locked.obj"
    p.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")

    def denied(path, *args, **kwargs):
        raise PermissionError(13, "Permission denied", str(path))

    monkeypatch.setattr(readers, "open", denied, raising=False)
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


def test_point_cloud_ply_is_refused(tmp_path):
    p = tmp_path / "cloud.ply"
    p.write_bytes(b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                  b"property float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n")
    with pytest.raises(ValueError, match=r"cloud\.ply.*no triangles"):
        cshape.load_mesh(p)


TET_WITH_JUNK = {
    # 4 tetrahedron faces + a reversed duplicate + a collapsed face; vertex 4 unreferenced
    "off": "OFF\n5 6 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n9 9 9\n"
           "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n3 3 2 1\n3 0 0 1\n",
    "obj": "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 9 9 9\n"
           "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\nf 4 3 2\nf 1 1 2\n",
    "ply": "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
           "property float z\nelement face 6\nproperty list uchar int vertex_indices\n"
           "end_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n9 9 9\n"
           "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n3 3 2 1\n3 0 0 1\n",
}


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


@pytest.mark.parametrize(
    "vert, tri, match",
    [
        ("0 0 0\n1 0 0\n0 1 0\n", "1 2 3.5\n", "non-integer floats"),
        ("0 0 0\n1 0 0\n0 1 0\n", "1 2 nan\n", "non-integer floats"),
        ("0 0 0\n1 0 0\n0 1 0\n", "1 2 4\n", r"outside \[0, 2\]"),
        ("0 0 0\n1 0\n0 1 0\n", "1 2 3\n", "cannot read TOSCA mesh"),
        ("0 0 0\n1 0 0\n0 1 nan\n", "1 2 3\n", "NaN or infinite"),
        ("0 0\n1 0\n0 1\n", "1 2 3\n", r"vertices must have shape \(n, 3\)"),
    ],
    ids=["fractional", "nan_index", "out_of_range", "ragged", "nan_vertex", "2d"],
)
def test_bad_tosca_vert_tri_files(tmp_path, vert, tri, match):
    from cshape.data import read_vert_tri

    (tmp_path / "cat0.vert").write_text(vert)
    (tmp_path / "cat0.tri").write_text(tri)
    with pytest.raises(ValueError, match=match) as info:
        read_vert_tri(tmp_path / "cat0.vert")
    assert "cat0" in str(info.value)


def _ply_be_double(V=TET_V, F=TET_F, *, counts=None, nv=None):
    head = (f"ply\nformat binary_big_endian 1.0\nelement vertex {len(V) if nv is None else nv}\n"
            "property double x\nproperty double y\nproperty double z\nproperty uchar red\n"
            f"element face {len(F)}\nproperty list uchar int vertex_indices\nend_header\n")
    body = b"".join(struct.pack(">3dB", *v, 7) for v in V)
    counts = [len(f) for f in F] if counts is None else counts
    body += b"".join(struct.pack(f">B{len(f)}i", c, *f) for c, f in zip(counts, F, strict=True))
    return head.encode() + body


def test_big_endian_double_ply_is_read_exactly(tmp_path):
    """PyMeshLab turns big-endian double coordinates into finite garbage without an error;
    cshape reads such files itself."""
    rng = np.random.default_rng(3)
    V = TET_V + rng.normal(scale=0.1, size=TET_V.shape)
    p = tmp_path / "be_double.ply"
    p.write_bytes(_ply_be_double(V))
    m = cshape.load_mesh(p)
    np.testing.assert_array_equal(m.vertices, V)  # exactly: doubles, no float32 rounding
    np.testing.assert_array_equal(m.faces, TET_F)


@pytest.mark.parametrize(
    "content, match",
    [
        (_ply_be_double(F=[[0, 2, 1, 3], [0, 1, 3], [0, 3, 2], [1, 2, 3]]),
         "big-endian PLY with double coordinates and faces that are not all triangles"),
        (_ply_be_double(F=_F_OOR), "references vertex 99 but the file has only 4"),
        (_ply_be_double(nv=5)[:-40], "declares 5 vertex, 4 face records"),
    ],
    ids=["quads", "out_of_range", "truncated"],
)
def test_big_endian_double_ply_errors(tmp_path, content, match):
    p = tmp_path / "be_double.ply"
    p.write_bytes(content)
    with pytest.raises(ValueError, match=match) as info:
        cshape.load_mesh(p)
    assert "be_double.ply" in str(info.value)


@pytest.mark.parametrize("n, fmt", [(128, "binary_little_endian"), (255, "ascii")])
def test_lists_PyMeshLab_handles_still_load(tmp_path, n, fmt):
    """512 bytes is the binary limit; ASCII lists of any length are read safely."""
    p = tmp_path / "extra.ply"
    p.write_bytes(_ply_with_extra_list(n, fmt))
    assert cshape.load_mesh(p).n_faces == 4


def test_failed_load_restores_the_working_folder(tmp_path, monkeypatch):
    """PyMeshLab changes into the file's folder and stayed there when a load failed."""
    sub = tmp_path / "meshes"
    sub.mkdir()
    (sub / "bad.ply").write_bytes(_FULL[:-20])
    (sub / "good.off").write_text(OFF_TET)
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ValueError, match="bad.ply"):
        cshape.load_mesh("meshes/bad.ply")
    assert Path.cwd() == tmp_path
    assert cshape.load_mesh("meshes/good.off").n_faces == 4  # relative paths still work


def _mutants(seed, n):
    """``n`` valid mesh files (every format), each corrupted by 1-5 random byte edits."""
    rng = np.random.default_rng(seed)
    s = cshape.shapes.icosphere(1)
    V, F = s.vertices, s.faces
    off = (f"OFF\n{len(V)} {len(F)} 0\n" + "".join(f"{x!r} {y!r} {z!r}\n" for x, y, z in V.tolist())
           + "".join(f"3 {a} {b} {c}\n" for a, b, c in F)).encode()
    obj = ("".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in V.tolist())
           + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in F)).encode()
    quads = np.c_[F[0::2], F[1::2, :1]]  # 4-gons, to reach the polygon code paths
    seeds = [("off", off), ("obj", obj), ("ply", _ply_binary(V, F)),
             ("ply", _ply_binary(V, quads)), ("ply", _ply_be_double(V, F)),
             ("ply", _ply_with_extra_list(100)), ("stl", _binary_stl(V, F)),
             ("stl", _ascii_stl(V, F).encode())]
    for i in range(n):
        ext, b = seeds[i % len(seeds)]
        b = bytearray(b)
        for _ in range(rng.integers(1, 6)):
            if not b:
                break
            op, pos = rng.integers(0, 5), int(rng.integers(0, len(b)))
            if op == 0:
                b[pos] = int(rng.integers(0, 256))
            elif op == 1:
                del b[pos : pos + int(rng.integers(1, 50))]
            elif op == 2:
                b[pos:pos] = rng.integers(0, 256, int(rng.integers(1, 20)), np.uint8).tobytes()
            elif op == 3:
                del b[pos:]
            else:  # a digit changed, or turned into a large number
                digits = [j for j, c in enumerate(b) if 48 <= c <= 57]
                if digits:
                    j = digits[int(rng.integers(0, len(digits)))]
                    b[j : j + 1] = b"9999999" if rng.random() < 0.3 else b"7"
        yield f"{i:04d}.{ext}", bytes(b)


def test_fuzzed_files_never_crash_the_interpreter(tmp_path):
    """600 corrupted files loaded in one memory-limited child process: each one loads or
    raises ValueError.  (Found this way: PyMeshLab segfaults on an out-of-range index in a
    polygon and aborts on a long binary list; both are now refused before it reads.)"""
    for name, content in _mutants(seed=20261122, n=600):
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
@pytest.fixture
def private_tmpdir(tmp_path, monkeypatch):
    """A temporary folder of our own for load_mesh's decompressed copies (to see them go)."""
    import tempfile

    d = tmp_path / "tmpdir"
    d.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(d))
    return d


@pytest.mark.parametrize("name, content, match", MALFORMED, ids=[m[0] for m in MALFORMED])
def test_malformed_file_gives_the_same_error_gzip_compressed(tmp_path, private_tmpdir, name,
                                                            content, match):
    """The pre-scan guards every compressed file as it guards the plain one; the message
    names the .gz file, never the temporary copy, which is removed."""
    import gzip

    p = tmp_path / (name + ".gz")
    p.write_bytes(gzip.compress(content))
    with pytest.raises(ValueError, match=match) as info:
        cshape.load_mesh(p)
    assert repr(str(p)) in str(info.value)
    assert str(private_tmpdir) not in str(info.value)
    assert list(private_tmpdir.iterdir()) == []


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


def test_corrupt_gzip_gives_clear_errors(tmp_path, private_tmpdir):
    import gzip

    data = gzip.compress(OFF_TET.encode())
    cases = {
        "truncated.off.gz": (data[: len(data) // 2], "corrupt or truncated"),
        "crc.off.gz": (data[:-8] + bytes([data[-8] ^ 0xFF]) + data[-7:], "corrupt or truncated"),
        "not_compressed.off.gz": (OFF_TET.encode(), "drop the '.gz'"),
        "empty_inside.off.gz": (gzip.compress(b""), "decompresses to an empty file"),
        "no_format.gz": (data, "must name its format before '.gz'"),
        "unknown_format.docx.gz": (data, r"extension '\.docx' is not a mesh format"),
    }
    for name, (content, match) in cases.items():
        p = tmp_path / name
        p.write_bytes(content)
        with pytest.raises(ValueError, match=match) as info:
            cshape.load_mesh(p)
        assert repr(str(p)) in str(info.value), name
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
