"""Mesh files built in code for the reader tests (test_validation.py, test_readers.py):
binary and ASCII PLY / STL writers with optionally lying headers, the table of malformed
files every one of which must raise a ValueError naming the file, and random byte-level
mutants of valid files.  Nothing is built at import time beyond small byte strings."""

from __future__ import annotations

import io
import struct
import zipfile

import numpy as np

TET_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
TET_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
OFF_TET = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"
PNG_HEAD = b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR" + bytes(range(256)) * 2


def ply_binary(V=TET_V, F=TET_F, *, nv=None, nf=None, endian="<", count_type="B"):
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


def zip_bytes():
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", compression=zipfile.ZIP_DEFLATED) as zf:
        zf.writestr("mesh.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    return buf.getvalue()


def binary_stl(V, F, nan_at=None):
    tris = np.asarray(V, np.float32)[F].copy()
    if nan_at is not None:
        tris[nan_at] = np.nan
    recs = b"".join(struct.pack("<12fH", 0, 0, 0, *t.reshape(-1), 0) for t in tris)
    return b"\0" * 80 + struct.pack("<I", len(F)) + recs


def ascii_stl(V, F, replace=None):
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
def ply_with_extra_list(n, fmt="binary_little_endian"):
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


FULL_PLY = ply_binary()
HEADER_END = FULL_PLY.index(b"end_header\n") + len(b"end_header\n")
F_OOR = TET_F.copy()
F_OOR[3, 2] = 99
F_NEG = TET_F.copy()
F_NEG[3, 2] = -5
V_NAN = TET_V.copy()
V_NAN[3, 2] = np.nan
V_INF = TET_V.copy()
V_INF[1, 0] = np.inf

#: (file name, content, expected message): every one must raise ValueError naming the file.
MALFORMED = [
    # binary PLY
    ("trunc_in_vertices.ply", FULL_PLY[: HEADER_END + 20], "need at least 52 bytes.*truncated"),
    ("trunc_in_faces.ply", FULL_PLY[:-20], "records end early: the file is truncated"),
    ("oor_index.ply", ply_binary(F=F_OOR), "Bad vertex index in face 3: 99, .* 4 vertices"),
    ("negative_index.ply", ply_binary(F=F_NEG), "Bad vertex index in face 3: -5"),
    ("nan_vertex.ply", ply_binary(V=V_NAN), "declares 4 vertices but 3 could be read"),
    ("inf_vertex.ply", ply_binary(V=V_INF), "declares 4 vertices but 3 could be read"),
    ("oor_big_endian.ply", ply_binary(F=F_OOR, endian=">"), "Bad vertex index"),
    # an out-of-range index in a polygon made PyMeshLab segfault (the Python process died)
    ("oor_in_quad.ply", ply_binary(F=[[0, 2, 1, 3], [0, 1, 3, 99]]), "face 1: 99"),
    ("oor_in_quad_ascii.ply", (PLY_ASCII_HEAD.format(nf=2) + "4 0 2 1 3\n5 0 1 3 2 -5\n").encode(),
     "face 1: -5"),
    # a binary list over 512 bytes outside the face indices aborted it (buffer overflow)
    ("long_list_extra_element.ply", ply_with_extra_list(129), "list property 'bar' of 516 bytes"),
    ("renamed_face_element.ply", FULL_PLY.replace(b"element face", b"element f\x8dce"),
     "4 vertices but no triangles"),
    ("list_runs_past_eof.ply", FULL_PLY.replace(struct.pack("<B3i", 3, 0, 2, 1),
                                             struct.pack("<B3i", 255, 0, 2, 1)),
     "records end early"),
    ("huge_counts.ply", ply_binary(nv=10**12, nf=10**12), "declares 1000000000000 vertex"),
    ("int32_overflow.ply", ply_binary(nv=2**31 + 10), "need at least"),
    ("huge_faces_ascii.ply", b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
     b"property float y\nproperty float z\nelement face 300000000\n"
     b"property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
     "300000000 face records"),
    ("negative_count.ply", ply_binary(nv=-4), "negative count -4"),
    ("word_count.ply", FULL_PLY.replace(b"element vertex 4", b"element vertex four"),
     "integer count"),
    ("no_xyz.ply", FULL_PLY.replace(b"property float x\nproperty float y\nproperty float z",
                                 b"property float a\nproperty float b\nproperty float c"),
     "No vertex field found"),
    ("unknown_format.ply", FULL_PLY.replace(b"binary_little_endian", b"binary_middle_endian"),
     "Format not found"),
    # counts far beyond the file in the text formats
    ("huge_counts.off", b"OFF\n1000000000000 1000000000000 0\n0 0 0\n", "truncated"),
    # NaN vertices in STL: PyMeshLab alone silently drops their triangles
    ("nan_vertex_ascii.stl", ascii_stl(TET_V, TET_F, ("vertex 0.0 0.0 1.0",
                                                      "vertex nan 0.0 1.0")).encode(),
     "line .*NaN or infinite"),
    ("nan_vertex_binary.stl", binary_stl(TET_V, TET_F, nan_at=(2, 1)),
     "declares 4 triangles.*only 3"),
    # non-mesh content behind a mesh extension
    *[(f"png_image.{ext}", PNG_HEAD, why) for ext, why in [
        ("obj", "not an OBJ triangle mesh"), ("off", "expected the OFF header"),
        ("ply", "'ply' magic line"), ("stl", "binary STL header declares")]],
    *[(f"zip_archive.{ext}", zip_bytes(), why) for ext, why in [
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


def ply_be_double(V=TET_V, F=TET_F, *, counts=None, nv=None):
    head = (f"ply\nformat binary_big_endian 1.0\nelement vertex {len(V) if nv is None else nv}\n"
            "property double x\nproperty double y\nproperty double z\nproperty uchar red\n"
            f"element face {len(F)}\nproperty list uchar int vertex_indices\nend_header\n")
    body = b"".join(struct.pack(">3dB", *v, 7) for v in V)
    counts = [len(f) for f in F] if counts is None else counts
    body += b"".join(struct.pack(f">B{len(f)}i", c, *f) for c, f in zip(counts, F, strict=True))
    return head.encode() + body


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


def mutants(seed, n):
    """``n`` valid mesh files (every format), each corrupted by 1-5 random byte edits."""
    rng = np.random.default_rng(seed)
    import cshape

    s = cshape.shapes.icosphere(1)
    V, F = s.vertices, s.faces
    off = (f"OFF\n{len(V)} {len(F)} 0\n" + "".join(f"{x!r} {y!r} {z!r}\n" for x, y, z in V.tolist())
           + "".join(f"3 {a} {b} {c}\n" for a, b, c in F)).encode()
    obj = ("".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in V.tolist())
           + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in F)).encode()
    quads = np.c_[F[0::2], F[1::2, :1]]  # 4-gons, to reach the polygon code paths
    seeds = [("off", off), ("obj", obj), ("ply", ply_binary(V, F)),
             ("ply", ply_binary(V, quads)), ("ply", ply_be_double(V, F)),
             ("ply", ply_with_extra_list(100)), ("stl", binary_stl(V, F)),
             ("stl", ascii_stl(V, F).encode())]
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
