"""What a mesh file declares, checked before PyMeshLab reads it (used by :func:`cshape.load_mesh`).

PyMeshLab silently drops faces with out-of-range indices and vertices with NaN coordinates,
allocates declared counts before reading them, misreads big-endian double PLY files, and
crashes on some malformed records.  :func:`prescan` reads what an OBJ, OFF, PLY or STL file
declares (counts, indices, coordinates), so that such a file gives a clear error naming it
instead of a quietly different mesh or a crash; :func:`check_against_expected` compares what
PyMeshLab read with that declaration.  Every error is a ``ValueError`` from :func:`bad_file`.

Plain OFF and OBJ layouts are checked vectorised (:func:`_fast_off`, :func:`_fast_obj`); any
other layout line by line, which also names the line of a problem.
"""

from __future__ import annotations

import re
import warnings
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from collections.abc import Iterable, Iterator, Sequence
    from pathlib import Path

    from numpy.typing import ArrayLike


class Expected:
    """What a file declares: vertex count, minimum triangle count, collapsed faces.

    The minimum triangle count is taken after triangulating polygons and leaving out the faces
    that repeat a vertex, which the reader drops; the last field is how many such collapsed
    faces were seen (None when the scan does not read the faces).
    """

    def __init__(self, n_vertices: int | None = None, min_faces: int | None = None,
                 exact_vertices: bool = True, collapsed: int | None = 0,
                 faces_read: bool = True) -> None:
        self.n_vertices = n_vertices
        self.min_faces = min_faces
        self.exact_vertices = exact_vertices
        self.collapsed = collapsed
        self.faces_read = faces_read
        # (V, F) read by cshape itself, where PyMeshLab misreads the file
        self.arrays: tuple[np.ndarray, np.ndarray] | None = None


def bad_file(p: Path, what: str) -> ValueError:
    """Return the error of a file that cannot be read as a mesh, naming the file."""
    return ValueError(f"cannot read mesh {str(p)!r}: {what}")


def prescan(p: Path, ext: str) -> Expected | None:
    """Return what the file declares (vertex count, minimum triangle count), or None."""
    try:
        fast = _fast_obj(p) if ext == "obj" else _fast_off(p) if ext == "off" else None
        if fast is not None:
            return fast
        if ext == "obj":
            nv, ntri, max_idx, nrec, collapsed = _scan_obj(p)
            if nv == 0 or nrec == 0:
                raise bad_file(
                    p, f"found {nv} vertex ('v x y z') and {nrec} face ('f i j k') records: "
                    "it is not an OBJ triangle mesh"
                )
            if max_idx > nv:
                raise bad_file(
                    p, f"a face references vertex {max_idx} but the file has only "
                    f"{nv} vertices; the file is truncated or its faces are wrong"
                )
            return Expected(nv, ntri, collapsed=collapsed)
        if ext == "off":
            return _scan_off(p)
        if ext == "ply":
            return _scan_ply_header(p)
        if ext == "stl":
            return _scan_stl(p)
    except UnicodeDecodeError:
        raise bad_file(p, "it is not a text file, as this format requires") from None
    return None


def check_against_expected(p: Path, expected: Expected | None, nv: int, nf: int
                           ) -> list[str]:
    """Raise if the reader silently lost vertices or faces; return notes on dropped faces."""
    if expected is None:
        return []
    if expected.n_vertices is not None and nv != expected.n_vertices:
        raise bad_file(
            p, f"the file declares {expected.n_vertices} vertices but {nv} could be read "
            "(NaN coordinates or corrupt vertex records?)"
        )
    if expected.min_faces is not None and nf < expected.min_faces and not expected.faces_read:
        # PLY: only the header was read; out-of-range indices make the reader fail, so the
        # faces it drops silently are those that repeat a vertex or have fewer than three
        return [
            f"removed {expected.min_faces - nf} faces with a repeated vertex (or fewer than "
            f"3), of the {expected.min_faces} the file declares"
        ]
    if expected.min_faces is not None and nf < expected.min_faces:
        raise bad_file(
            p, f"the file declares {expected.min_faces} triangles (after triangulating "
            f"polygons) but only {nf} could be read: some faces reference missing vertices "
            "or are corrupt"
        )
    if expected.collapsed:
        return [f"removed {expected.collapsed} faces with a repeated vertex"]
    return []


def _parse_floats(p: Path, tokens: Sequence[bytes | str], lineno: int, kind: str) -> None:
    try:
        xyz = [float(t) for t in tokens[:3]]
    except ValueError:
        raise bad_file(
            p, f"line {lineno}: {kind} coordinates {tokens[:3]} are not numbers"
        ) from None
    if len(xyz) < 3:
        raise bad_file(p, f"line {lineno}: a vertex needs 3 coordinates, got {len(xyz)}")
    if not all(np.isfinite(xyz)):
        raise bad_file(
            p, f"line {lineno}: vertex coordinates {xyz} are NaN or infinite; fix or remove them"
        )


def _obj_records(fh: Iterable[bytes]) -> Iterator[tuple[int, bytes]]:
    """``(line number, record)`` of an OBJ file, joining lines continued by a backslash."""
    pending, start = b"", 0
    for lineno, raw in enumerate(fh, 1):
        line = raw.rstrip(b"\r\n")
        if not pending:
            start = lineno
        if line.endswith(b"\\"):
            pending += line[:-1] + b" "
            continue
        yield start, pending + line
        pending = b""
    if pending:
        yield start, pending


def _scan_obj(p: Path) -> tuple[int, int, int, int, int]:
    """Check the records PyMeshLab's OBJ reader will use.

    The checks mirror that reader: it skips indented ``v`` lines but reads indented ``f``
    lines, and returns (memory-unsafe) faces with out-of-range indices, so every face index
    is checked here against the vertices it will read.
    """
    nv = ntri = max_idx = nrec = collapsed = 0
    with open(p, "rb") as fh:
        for lineno, raw in _obj_records(fh):
            rec = raw.lstrip()
            if rec[:2] in (b"v ", b"v\t"):
                if len(rec) != len(raw):
                    raise bad_file(
                        p, f"line {lineno}: the vertex record is indented; PyMeshLab's OBJ "
                        "reader skips indented 'v' lines, so the faces would point at the "
                        "wrong vertices: remove the leading whitespace"
                    )
                _parse_floats(p, rec.split()[1:], lineno, "vertex")
                nv += 1
            elif rec[:2] in (b"f ", b"f\t"):
                toks = rec.split()[1:]
                if len(toks) < 3:
                    raise bad_file(p, f"line {lineno}: a face needs at least 3 vertices")
                nrec += 1
                corners = set()
                for t in toks:
                    try:
                        idx = int(t.split(b"/")[0])
                    except ValueError:
                        raise bad_file(
                            p, f"line {lineno}: face index {t.decode(errors='replace')!r} "
                            "is not an integer"
                        ) from None
                    if idx == 0 or idx < -nv:
                        raise bad_file(
                            p, f"line {lineno}: face index {idx} is invalid (OBJ indices start "
                            f"at 1; negative ones count back from the {nv} vertices read so far)"
                        )
                    max_idx = max(max_idx, idx)
                    corners.add(idx if idx > 0 else nv + idx + 1)
                ntri += max(len(corners) - 2, 0)
                collapsed += len(corners) < 3
    return nv, ntri, max_idx, nrec, collapsed


def _ints_or_none(block: bytes, dtype: type = np.int64) -> np.ndarray | None:
    """All whitespace-separated numbers of ``block``, or None if one does not parse."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            return np.fromstring(block, dtype=dtype, sep=" ")
        except (ValueError, DeprecationWarning):
            return None


def _triangle_stats(F: np.ndarray, nv: int) -> tuple[bool, int, int]:
    """``(ok, n_triangles, n_collapsed)`` of (m, 3) zero-based indices."""
    if F.size and (F.min() < 0 or F.max() >= nv):
        return False, 0, 0
    collapsed = int(np.count_nonzero((F[:, 0] == F[:, 1]) | (F[:, 1] == F[:, 2])
                                     | (F[:, 2] == F[:, 0])))
    return True, len(F) - collapsed, collapsed


def _fast_off(p: Path) -> Expected | None:
    """Check an OFF file of the plain layout, vectorised.

    The plain layout: ``OFF``, counts, ``x y z`` lines, ``3 i j k`` lines, no comments.
    None when the file is laid out otherwise or has any problem, which the line-by-line
    :func:`_scan_off` then reports with its line.
    """
    data = p.read_bytes()
    head, _, body = data.partition(b"\n")
    if head.strip() != b"OFF" or b"#" in body:
        return None
    vals = _ints_or_none(body, np.float64)
    if vals is None or len(vals) < 3:
        return None
    nv, nf = vals[0], vals[1]
    if not (nv == int(nv) and nf == int(nf) and nv > 0 and nf > 0):
        return None
    nv, nf = int(nv), int(nf)
    if len(vals) != 3 + 3 * nv + 4 * nf:
        return None  # colours, polygons, extra values: the exact scan decides
    V = vals[3 : 3 + 3 * nv]
    faces = vals[3 + 3 * nv :].reshape(nf, 4)
    if not np.isfinite(V).all() or np.any(faces[:, 0] != 3):
        return None
    F = faces[:, 1:]
    if np.any(F != np.round(F)):
        return None
    ok, ntri, collapsed = _triangle_stats(F.astype(np.int64), nv)
    return Expected(nv, ntri, collapsed=collapsed) if ok else None


_OBJ_INDENTED = re.compile(rb"(?m)^[ \t]+[vf][ \t]")
_OBJ_V = re.compile(rb"(?m)^v[ \t]([^\n]*)")
_OBJ_F = re.compile(rb"(?m)^f[ \t]([^\n]*)")
_OBJ_SLASH = re.compile(rb"/[^\s]*")


def _fast_obj(p: Path) -> Expected | None:
    """Check an OBJ file of triangles with positive indices and ``v x y z`` vertices, vectorised.

    None when the file is laid out otherwise or has any problem, which the line-by-line
    :func:`_scan_obj` then reports with its line.
    """
    data = p.read_bytes()
    if b"\\" in data or _OBJ_INDENTED.search(data):
        return None
    vlines, flines = _OBJ_V.findall(data), _OBJ_F.findall(data)
    nv, nf = len(vlines), len(flines)
    if nv == 0 or nf == 0:
        return None
    V = _ints_or_none(b"\n".join(vlines), np.float64)
    if V is None or len(V) != 3 * nv or not np.isfinite(V).all():
        return None
    F = _ints_or_none(_OBJ_SLASH.sub(b"", b"\n".join(flines)))
    if F is None or len(F) != 3 * nf or F.min() < 1:
        return None  # polygons, relative (negative) or zero indices: the exact scan
    ok, ntri, collapsed = _triangle_stats(F.reshape(nf, 3) - 1, nv)
    return Expected(nv, ntri, collapsed=collapsed) if ok else None


def _next_record(p: Path, lines: Iterator[tuple[int, list[str]]], declared: int, k: int,
                 what: str) -> tuple[int, list[str]]:
    """Return the next ``(line number, tokens)`` of an OFF body, or raise a "truncated" error."""
    try:
        return next(lines)
    except StopIteration:
        raise bad_file(
            p, f"the header declares {declared} {what} but the file ends after {k}: "
            "it is truncated"
        ) from None


def _scan_off(p: Path) -> Expected:
    # latin-1 decodes any byte: numbers are ASCII, comments may be in any 8-bit encoding
    with open(p, encoding="latin-1") as fh:
        tokens_lines = (
            (i, line.split("#", 1)[0].split()) for i, line in enumerate(fh, 1)
        )
        lines = ((i, t) for i, t in tokens_lines if t)
        try:
            i, head = next(lines)
        except StopIteration:
            raise bad_file(p, "the file has no OFF header") from None
        if not head[0].upper().endswith("OFF"):
            raise bad_file(p, f"line {i}: expected the OFF header, got {head[0][:20]!r}")
        counts = head[1:]
        if not counts:
            try:
                i, counts = next(lines)
            except StopIteration:
                raise bad_file(p, "the file ends after the OFF header (no counts)") from None
        try:
            nv, nf = int(counts[0]), int(counts[1])
        except (ValueError, IndexError):
            raise bad_file(p, f"line {i}: expected 'n_vertices n_faces n_edges'") from None
        if nv < 0 or nf < 0:
            raise bad_file(p, f"line {i}: negative counts {nv}, {nf}")
        for k in range(nv):
            i, t = _next_record(p, lines, nv, k, "vertices")
            _parse_floats(p, t, i, "vertex")
        ntri = collapsed = 0
        for k in range(nf):
            i, t = _next_record(p, lines, nf, k, "faces")
            try:
                deg = int(t[0])
                idx = [int(x) for x in t[1 : 1 + deg]]
            except ValueError:
                raise bad_file(p, f"line {i}: face record {t} is not integers") from None
            if deg < 3 or len(idx) < deg:
                raise bad_file(p, f"line {i}: face record {t} is incomplete")
            bad = [x for x in idx if x < 0 or x >= nv]
            if bad:
                raise bad_file(
                    p, f"line {i}: face references vertex {bad[0]} but the file has only {nv} "
                    f"vertices (OFF indices are 0-based, in [0, {nv - 1}])"
                )
            # the reader drops faces that repeat a vertex (collapsed to a segment or point)
            ntri += max(len(set(idx)) - 2, 0)
            collapsed += len(set(idx)) < 3
    return Expected(nv, ntri, collapsed=collapsed)


#: Bytes of each PLY scalar type.
_PLY_SIZES = {
    "char": 1, "int8": 1, "uchar": 1, "uint8": 1, "short": 2, "int16": 2, "ushort": 2,
    "uint16": 2, "int": 4, "int32": 4, "uint": 4, "uint32": 4, "float": 4, "float32": 4,
    "double": 8, "float64": 8,
}


def _scan_ply_header(p: Path) -> Expected:
    """Return the declared counts of a PLY file, checked against its size.

    PyMeshLab allocates the declared number of vertices and faces before reading them, so
    a corrupt count (a few bytes claiming 10^12 vertices) would exhaust the memory; every
    record takes at least one byte (binary: the size of its properties), which bounds the
    counts by the file size.
    """
    nv = nf = None
    fmt = None
    elements: list[Any] = []  # [name, count, min bytes per record in binary, values per record]
    with open(p, "rb") as fh:
        first = fh.readline()
        if first.strip() != b"ply":
            raise bad_file(p, "it does not start with the 'ply' magic line")
        for _ in range(10000):
            line = fh.readline()
            if not line:
                raise bad_file(p, "the PLY header has no end_header line: it is truncated")
            parts = line.decode("latin-1").split()
            if parts[:1] == ["format"] and len(parts) > 1:
                fmt = parts[1]
            elif parts[:1] == ["element"]:
                try:
                    count = int(parts[2])
                except (IndexError, ValueError):
                    raise bad_file(
                        p, f"PLY header line {line.strip()[:60]!r}: expected 'element NAME COUNT' "
                        "with an integer count"
                    ) from None
                if count < 0:
                    raise bad_file(p, f"the PLY header declares a negative count {count}")
                elements.append([parts[1], count, 0, 0, []])
                if parts[1] == "vertex":
                    nv = count
                elif parts[1] == "face":
                    nf = count
            elif parts[:1] == ["property"] and elements:
                el = elements[-1]
                el[3] += 1
                if parts[1:2] == ["list"] and len(parts) > 2:
                    el[2] += _PLY_SIZES.get(parts[2], 1)  # the list length; items may be 0
                    el[4].append((parts[-1], "list", *parts[2:4]))
                elif len(parts) > 1:
                    el[2] += _PLY_SIZES.get(parts[1], 1)
                    el[4].append((parts[-1], parts[1], None, None))
            elif parts[:1] == ["end_header"]:
                break
        header_end = fh.tell()
        body = p.stat().st_size - header_end
    if fmt == "ascii":
        # each value takes at least one character and one separator
        need = sum(2 * count * max(nval, 1) for _, count, _, nval, _ in elements) - 1
    else:
        need = sum(count * max(nbytes, 1) for _, count, nbytes, _, _ in elements)
    if need > body:
        declared = ", ".join(f"{count} {name}" for name, count, *_ in elements)
        raise bad_file(
            p, f"the PLY header declares {declared} records, which need at least {need} bytes, "
            f"but the file has {body} bytes after the header: it is truncated or its counts "
            "are wrong"
        )
    expected = Expected(nv, nf, faces_read=False)
    if fmt == "binary_big_endian":
        expected.arrays = _big_endian_double_ply(p, elements, header_end)
    if expected.arrays is None:
        _check_ply_face_indices(p, fmt, elements, header_end, nv or 0)
    return expected


#: Largest list (in bytes) PyMeshLab's binary PLY reader copies safely, except the face
#: index lists: a longer one (e.g. 129 ints in an extra element) overflows a fixed buffer
#: and aborts the process ("*** buffer overflow detected ***").
PLY_MAX_LIST_BYTES = 512

_PLY_FACE_LISTS = ("vertex_indices", "vertex_index")


def _check_ply_face_indices(p: Path, fmt: str | None, elements: list[Any], header_end: int,
                            nv: int) -> None:
    """Walk the PLY records that could crash PyMeshLab, before it reads the file.

    * every face index must lie in ``[0, nv)``: PyMeshLab reports an out-of-range index
      in a triangle, but *segfaults* on one in a polygon of four or more vertices;
    * (binary) no other list may exceed :data:`PLY_MAX_LIST_BYTES`: PyMeshLab overflows a
      buffer on such a list (in an extra element or property) and aborts.

    Triangle faces take a vectorised path (:func:`_ply_triangle_block`); anything else is
    walked record by record (:func:`_walk_ply_ascii`, :func:`_walk_ply_binary`).
    """
    with open(p, "rb") as fh:
        fh.seek(header_end)
        body = fh.read()
    ascii_ = fmt == "ascii"
    order = ">" if fmt == "binary_big_endian" else "<"
    if ascii_ and _ascii_triangles_ok(p, body, elements, nv):
        return  # ASCII lists cannot overflow the reader; the faces were checked
    data: Any = body.split() if ascii_ else body  # tokens (ascii) or bytes (binary)
    pos = 0  # token index (ascii) or byte offset (binary)

    def has_lists(props: Iterable[Sequence[Any]]) -> bool:
        return any(q[1] == "list" for q in props)

    for e, (name, count, nbytes, _, props) in enumerate(elements):
        if not any(has_lists(el[4]) for el in elements[e:]):
            return  # nothing left that could crash the reader
        if not has_lists(props):
            pos += count * (len(props) if ascii_ else nbytes)
            continue
        if any(q[1] != "list" and q[1] not in _PLY_NUMPY for q in props) or any(
            q[1] == "list" and (q[2] not in _PLY_NUMPY or q[3] not in _PLY_NUMPY) for q in props
        ):
            return  # unknown types: PyMeshLab refuses the file itself
        faces = name == "face"
        if faces and len(props) == 1 and props[0][0] in _PLY_FACE_LISTS:
            end = _ply_triangle_block(p, data, pos, count, props[0], order, nv, ascii_)
            if end is not None:
                pos = end
                continue
        walk = _walk_ply_ascii if ascii_ else _walk_ply_binary
        pos = walk(p, data, pos, name, count, props, order, nv)


def _ply_check_indices(p: Path, idx: ArrayLike, nv: int, k: int | None = None) -> None:
    """Raise if a face index lies outside ``[0, nv)``.

    ``idx`` is one face (face number ``k``) or, with ``k=None``, an (m, 3) block of all the
    faces.
    """
    idx = np.asarray(idx)
    bad = (idx < 0) | (idx >= nv)
    if bad.any():
        if k is None:
            k = int(np.flatnonzero(bad.any(axis=1))[0])
            bad = bad[k]
            idx = idx[k]
        raise bad_file(
            p, f"Bad vertex index in face {k}: {int(idx[bad][0])}, but the file has {nv} "
            f"vertices (PLY indices are 0-based, in [0, {nv - 1}])"
        )


def _ply_ints(p: Path, toks: Sequence[bytes], k: int) -> np.ndarray:
    """Return the ASCII tokens ``toks`` of record ``k`` as int64, or raise naming the record."""
    try:
        return np.array(toks).astype(np.int64)
    except ValueError:
        raise bad_file(p, f"record {k}: {toks[:8]} are not integers") from None


def _ply_truncated(p: Path) -> ValueError:
    """Return the error of a PLY body that ends before its last record."""
    return bad_file(p, "the PLY element records end early: the file is truncated")


def _ply_triangle_block(p: Path, data: Any, pos: int, count: int, prop: Sequence[Any], order: str,
                        nv: int, ascii_: bool) -> int | None:
    """Check a face element of ``count`` triangles at once; return the position after it.

    ``prop`` is the element's one index-list property.  Returns None (nothing checked) when
    some face is not a triangle or the records are short: the caller then walks them one by
    one.
    """
    _, _, c_t, i_t = prop
    if ascii_:
        rec = data[pos : pos + 4 * count]
        if len(rec) == 4 * count and all(t == b"3" for t in rec[::4]):
            _ply_check_indices(p, _ply_ints(p, rec, 0).reshape(count, 4)[:, 1:], nv)
            return pos + 4 * count
        return None
    dt = np.dtype([("n", order + _PLY_NUMPY[c_t]), ("i", order + _PLY_NUMPY[i_t], 3)])
    if len(data) - pos >= count * dt.itemsize:
        rec = np.frombuffer(data, dtype=dt, count=count, offset=pos)
        if np.all(rec["n"] == 3):
            _ply_check_indices(p, rec["i"], nv)
            return pos + count * dt.itemsize
    return None


def _walk_ply_ascii(p: Path, tokens: Sequence[bytes], pos: int, name: str, count: int,
                    props: Sequence[Sequence[Any]], order: str, nv: int) -> int:
    """Check ``count`` ASCII records of element ``name``; return the token index after them.

    ``pos`` is the index of their first token; ``order`` is unused (ASCII has no byte order).
    """
    faces = name == "face"
    for k in range(count):
        for pname, t, _, _ in props:
            if t != "list":
                pos += 1
                continue
            if pos >= len(tokens):
                raise _ply_truncated(p)
            n = int(_ply_ints(p, tokens[pos : pos + 1], k)[0])
            vals = tokens[pos + 1 : pos + 1 + n]
            if n < 0 or len(vals) < n:
                raise _ply_truncated(p)
            if faces and pname in _PLY_FACE_LISTS:
                _ply_check_indices(p, _ply_ints(p, vals, k), nv, k)
            pos += 1 + n
    return pos


def _walk_ply_binary(p: Path, body: bytes, pos: int, name: str, count: int,
                     props: Sequence[Sequence[Any]], order: str, nv: int) -> int:
    """Check ``count`` binary records of element ``name``; return the byte offset after them.

    ``pos`` is the offset of the first record.  Face indices must be in range; other lists
    must not exceed :data:`PLY_MAX_LIST_BYTES`.
    """
    faces = name == "face"
    for k in range(count):
        for pname, t, c_t, i_t in props:
            if t != "list":
                pos += _PLY_SIZES[t]
                continue
            cdt, idt = np.dtype(order + _PLY_NUMPY[c_t]), np.dtype(order + _PLY_NUMPY[i_t])
            if pos + cdt.itemsize > len(body):
                raise _ply_truncated(p)
            n = int(np.frombuffer(body, cdt, 1, pos)[0])
            pos += cdt.itemsize
            if n < 0 or pos + n * idt.itemsize > len(body):
                raise _ply_truncated(p)
            if faces and pname in _PLY_FACE_LISTS:
                _ply_check_indices(p, np.frombuffer(body, idt, n, pos), nv, k)
            elif n * idt.itemsize > PLY_MAX_LIST_BYTES:
                raise bad_file(
                    p, f"record {k} of element {name!r} has a list property {pname!r} of "
                    f"{n * idt.itemsize} bytes; PyMeshLab's PLY reader overflows a buffer "
                    f"on lists over {PLY_MAX_LIST_BYTES} bytes (it would abort Python): "
                    "remove that property or element, or save the file as ASCII PLY"
                )
            pos += n * idt.itemsize
    return pos


def _ascii_triangles_ok(p: Path, body: bytes, elements: list[Any], nv: int) -> bool:
    """Check an ASCII PLY fast, when its faces are one index list of triangles per line.

    The face element comes after elements of scalar properties, one record per line (how
    every writer lays them out).

    Returns True when every face was checked (raising on an out-of-range index), False when
    the file is laid out otherwise: the caller then walks it token by token.
    """
    skip = 0
    for name, count, _, _, props in elements:
        if name == "face":
            break
        if any(q[1] == "list" for q in props):
            return False
        skip += count
    else:
        return True  # no face element
    if len(props) != 1 or props[0][1] != "list" or props[0][0] not in _PLY_FACE_LISTS:
        return False
    pos = 0
    for _ in range(skip):
        pos = body.find(b"\n", pos) + 1
        if pos == 0:
            return False
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:  # parses up to the first token that is not an integer
            vals = np.fromstring(body[pos:], dtype=np.int64, sep=" ")
        except (ValueError, DeprecationWarning):
            end = pos
            for _ in range(count):
                end = body.find(b"\n", end) + 1
                if end == 0:
                    return False
            try:
                vals = np.fromstring(body[pos:end], dtype=np.int64, sep=" ")
            except (ValueError, DeprecationWarning):
                return False
    if len(vals) < 4 * count or np.any(vals[: 4 * count : 4] != 3):
        return False
    idx = vals[: 4 * count].reshape(count, 4)[:, 1:]
    bad = (idx < 0) | (idx >= nv)
    if bad.any():
        k = int(np.flatnonzero(bad.any(axis=1))[0])
        raise bad_file(
            p, f"Bad vertex index in face {k}: {int(idx[k][bad[k]][0])}, but the file has {nv} "
            f"vertices (PLY indices are 0-based, in [0, {nv - 1}])"
        )
    return True


#: NumPy codes of the PLY scalar types.
_PLY_NUMPY = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
    "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
    "float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
}


def _big_endian_double_ply(p: Path, elements: list[Any], header_end: int
                           ) -> tuple[np.ndarray, np.ndarray] | None:
    """``(V, F)`` of a big-endian PLY with double x, y, z, read with NumPy; else None.

    PyMeshLab byte-swaps big-endian doubles wrongly: it returns finite garbage coordinates
    (or drops vertices it reads as NaN) without any error.  cshape therefore reads such
    files itself: a vertex element of scalar properties and a face element of triangles.
    Big-endian files with float coordinates are left to PyMeshLab, which reads them right.
    """
    types = {n: t for name, _, _, _, props in elements if name == "vertex"
             for n, t, _, _ in props}
    if not any(types.get(a) in ("double", "float64") for a in "xyz"):
        return None

    def unsupported(what: str) -> ValueError:
        return bad_file(
            p, f"it is a big-endian PLY with double coordinates and {what}; PyMeshLab "
            "misreads such files and cshape reads only plain triangle meshes of this kind: "
            "save it as little-endian or ASCII PLY"
        )

    offset = header_end
    V = F = None
    for name, count, nbytes, _, props in elements:
        if name == "vertex":
            if not all(a in types for a in "xyz") or any(
                t == "list" or t not in _PLY_NUMPY for _, t, _, _ in props
            ):
                raise unsupported("list or unknown vertex properties")
            dtype = np.dtype([(n, ">" + _PLY_NUMPY[t]) for n, t, _, _ in props])
            rec = np.fromfile(p, dtype=dtype, count=count, offset=offset)
            if len(rec) < count:
                raise bad_file(p, f"the vertex block ends after {len(rec)} of {count} vertices")
            V = np.stack([rec[a].astype(np.float64) for a in "xyz"], axis=1)
            offset += count * dtype.itemsize
        elif name == "face":
            if len(props) != 1 or props[0][1] != "list" or not (
                props[0][2] in _PLY_NUMPY and props[0][3] in _PLY_NUMPY
            ):
                raise unsupported("face properties other than one list of indices")
            _, _, count_t, index_t = props[0]
            dtype = np.dtype(
                [("n", ">" + _PLY_NUMPY[count_t]), ("i", ">" + _PLY_NUMPY[index_t], 3)]
            )
            rec = np.fromfile(p, dtype=dtype, count=count, offset=offset)
            if len(rec) < count or np.any(rec["n"] != 3):
                raise unsupported("faces that are not all triangles (or a truncated face block)")
            F = rec["i"].astype(np.int64)
            break
        elif any(t == "list" for _, t, _, _ in props):
            raise unsupported(f"a list property in element {name!r} before the faces")
        else:
            offset += count * nbytes
    if V is None or F is None:
        raise unsupported("no vertex or face element")
    if F.size and (F.min() < 0 or F.max() >= len(V)):
        raise bad_file(p, f"a face references vertex {int(F.max())} but the file has only "
                        f"{len(V)} vertices")
    return V, F


def _scan_stl(p: Path) -> Expected:
    size = p.stat().st_size
    with open(p, "rb") as fh:
        head = fh.read(84)
    with open(p, "rb") as fh:
        start = fh.read(1024).lower()
    if head[:5].lower() == b"solid" and b"facet" in start:
        return _scan_ascii_stl(p)
    if size < 84:
        raise bad_file(p, f"a binary STL needs at least 84 bytes, the file has {size}")
    n = int.from_bytes(head[80:84], "little")
    if size != 84 + 50 * n:
        raise bad_file(
            p, f"the binary STL header declares {n} triangles ({84 + 50 * n} bytes) but the file "
            f"has {size} bytes: it is truncated or not an STL file"
        )
    return Expected(None, n, exact_vertices=False)


def _scan_ascii_stl(p: Path) -> Expected:
    """Count the facets of an ASCII STL, checking its vertex coordinates.

    PyMeshLab silently drops a triangle with a NaN vertex; broken records are reported by
    PyMeshLab.
    """
    nfacets = 0
    with open(p, "rb") as fh:
        for lineno, raw in enumerate(fh, 1):
            toks = raw.split()
            if not toks:
                continue
            key = toks[0].lower()
            if key == b"facet":
                nfacets += 1
            elif key == b"vertex":
                _parse_floats(p, [t.decode("latin-1") for t in toks[1:]], lineno, "vertex")
    return Expected(None, nfacets, exact_vertices=False)
