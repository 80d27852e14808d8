"""Reading mesh files: :func:`load_mesh` and the checks it runs before PyMeshLab reads a file.

Stage 1 of the pipeline is split in two modules: :mod:`cshape.mesh` holds the :class:`Mesh`
container, its validation and :func:`repair_mesh`; this module turns a file into a
:class:`Mesh`.  PyMeshLab does the parsing; what each file declares (counts, indices,
coordinates of OBJ, OFF, PLY, STL) is checked first by the private :mod:`cshape._prescan`,
because PyMeshLab silently drops NaN vertices and out-of-range faces, allocates declared
counts before reading them, and crashes on some malformed records.
"""

from __future__ import annotations

import errno
import gzip
import os
import tempfile
import warnings
import zlib
from pathlib import Path

import numpy as np

from ._checks import check_bool, check_path
from ._prescan import Expected, bad_file, check_against_expected, prescan
from .mesh import CShapeWarning, Mesh, repair_mesh

__all__ = [
    "load_mesh",
]


#: Mesh file suffixes that folder collections pick up (:func:`cshape.data.load_folder`);
#: each also gzip-compressed (``bunny.off.gz``), which :func:`load_mesh` reads.
MESH_SUFFIXES = (".obj", ".off", ".ply", ".stl")

#: Largest size (bytes) a gzip-compressed mesh may decompress to: a few corrupt or hostile
#: bytes can claim gigabytes ("zip bomb"), so decompression stops there with an error.
#: 4 GiB holds an ASCII mesh of about 40 million triangles.
GZIP_MAX_BYTES = 4 * 2**30


def load_mesh(path: str | os.PathLike[str], *, repair: bool = True) -> Mesh:
    """Read a triangle mesh from any format PyMeshLab reads (OFF, PLY, OBJ, STL, ...).

    Polygons are triangulated.  OBJ texture coordinates and normals are ignored, keeping
    one vertex per position (the surface is not cut at UV seams).  STL triangle soup is
    welded into a connected mesh.  Every format is also read gzip-compressed
    (``bunny.off.gz``, ``scan.ply.gz``, ...).

    Parameters
    ----------
    path : str or os.PathLike
        The mesh file; a name ending in ``.gz`` is decompressed first (the format is the
        suffix before ``.gz``).
    repair : bool, default=True
        Apply :func:`repair_mesh` (weld duplicate vertices, drop collapsed and duplicate
        faces, drop unreferenced vertices), with a warning if anything changed.

    Returns
    -------
    Mesh
        The vertices and triangles of the file (repaired when ``repair`` is true).

    Raises
    ------
    TypeError
        If ``path`` is not a str or os.PathLike, or ``repair`` not a bool.
    FileNotFoundError
        If ``path`` does not exist.
    ValueError
        If the file cannot be read as a mesh (unknown extension, empty, truncated or
        corrupt file, no triangles; corrupt or truncated gzip data, or more than
        :data:`GZIP_MAX_BYTES` once decompressed); the message names the file.

    Notes
    -----
    Before PyMeshLab reads a file, cshape checks what it declares (counts, indices,
    coordinates; OFF, OBJ, PLY, STL): PyMeshLab silently drops NaN vertices and some
    faces, and allocates declared counts before reading them.  Big-endian binary PLY files
    with double coordinates, which PyMeshLab misreads, are read by cshape itself.  A
    ``.gz`` file is decompressed, in bounded chunks, to a temporary file that goes through
    the same checks.
    """
    p = check_path("path", path)
    repair = check_bool("repair", repair)
    if not p.exists():
        raise FileNotFoundError(f"no mesh file at {str(p)!r}")
    if p.is_dir():
        raise ValueError(f"{str(p)!r} is a folder, not a mesh file")
    if p.stat().st_size == 0:
        raise ValueError(f"cannot read mesh {str(p)!r}: the file is empty")
    if p.name.lower().endswith(".gz"):
        with tempfile.TemporaryDirectory(prefix="cshape-gunzip-") as tmp:
            V, F, dropped = _read_arrays(_gunzip(p, Path(tmp)), shown=p)
    else:
        V, F, dropped = _read_arrays(p)
    try:
        mesh = Mesh(V, F)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"cannot read mesh {str(p)!r}: {exc}") from None
    for note in dropped:  # faces the reader left out, which repair_mesh would remove
        warnings.warn(f"{p.name}: repaired mesh: {note}", CShapeWarning, stacklevel=2)
    if repair:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", CShapeWarning)
            mesh = repair_mesh(mesh)
        for w in caught:
            warnings.warn(f"{p.name}: {w.message}", CShapeWarning, stacklevel=2)
    return mesh


def split_mesh_name(path: str | os.PathLike[str]) -> tuple[str, str]:
    """``(stem, format suffix)`` of a mesh file name, looking through ``.gz``.

    ``bunny.off`` and ``bunny.off.gz`` both give ``("bunny", ".off")``; the suffix is
    lower-case (``""`` when there is none).

    Parameters
    ----------
    path : str or os.PathLike
        A mesh file name, with or without folders.

    Returns
    -------
    stem : str
        The name without its format suffix and ``.gz``.
    suffix : str
        The format suffix, lower-case, with its dot (``".off"``), or ``""``.

    Examples
    --------
    >>> from cshape.readers import split_mesh_name
    >>> split_mesh_name("scans/Bunny.OFF.gz")
    ('Bunny', '.off')
    """
    name = check_path("path", path).name
    if name.lower().endswith(".gz"):
        name = name[:-3]
    inner = Path(name)
    return inner.stem, inner.suffix.lower()


def _read_arrays(p: Path, shown: Path | None = None) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """``(V, F, notes)`` of the (uncompressed) file ``p``: pre-scan, then PyMeshLab.

    ``shown`` is the path the user gave (the ``.gz`` file ``p`` was decompressed from);
    error messages name it instead of the temporary file.
    """
    ext = p.suffix.lower().lstrip(".")
    try:
        expected = prescan(p, ext)
        if expected is not None and expected.arrays is not None:
            return (*expected.arrays, [])  # a file PyMeshLab misreads, read by cshape
        return _load_with_pymeshlab(p, ext, expected)
    except ValueError as exc:
        if shown is None:
            raise
        msg = str(exc).replace(repr(str(p)), repr(str(shown))).replace(str(p), str(shown))
        raise ValueError(msg) from None


def _gunzip(src: Path, folder: Path) -> Path:
    """Decompress ``src`` (``NAME.EXT.gz``) to ``folder / NAME.EXT``; return the new file.

    Reads in chunks of 1 MiB, stopping with an error beyond :data:`GZIP_MAX_BYTES`.
    """
    if not split_mesh_name(src)[1]:
        raise bad_file(
            src, "a compressed mesh must name its format before '.gz' (e.g. bunny.off.gz, "
            "scan.ply.gz); rename the file"
        )
    dst = folder / src.name[:-3]
    total = 0
    try:
        with gzip.open(src, "rb") as fin, open(dst, "wb") as fout:
            while chunk := fin.read(2**20):
                total += len(chunk)
                if total > GZIP_MAX_BYTES:
                    raise bad_file(
                        src, f"it decompresses to more than {GZIP_MAX_BYTES} bytes "
                        "(cshape.readers.GZIP_MAX_BYTES), too large for a mesh or a "
                        "corrupt file; decompress it yourself (gunzip) if it is genuine"
                    )
                fout.write(chunk)
    except (gzip.BadGzipFile, EOFError, zlib.error) as exc:
        raise bad_file(
            src, f"its gzip data is corrupt or truncated ({exc}); download it again, or drop "
            "the '.gz' from its name if it is not compressed"
        ) from None
    except OSError as exc:
        if exc.errno != errno.ENOSPC:
            raise
        raise bad_file(
            src, f"no space left to decompress it in {str(folder.parent)!r}; free some, "
            "or set TMPDIR to a folder with room"
        ) from None
    if total == 0:
        raise bad_file(src, "it decompresses to an empty file")
    return dst


def _load_with_pymeshlab(p: Path, ext: str, expected: Expected | None
                         ) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """``(V, F, notes)`` read by PyMeshLab and checked against what the file declares."""
    import pymeshlab

    ms = pymeshlab.MeshSet()
    try:
        cwd = os.getcwd()
    except OSError:  # the working folder was deleted: nothing to restore
        cwd = None
    try:
        # an absolute path; and the working folder is restored below, because PyMeshLab
        # changes into the file's folder and stays there when the load fails
        ms.load_new_mesh(str(p.resolve()))
    except pymeshlab.PyMeshLabException as exc:
        text = str(exc).strip()
        details = text.split("Error details:", 1)[-1].strip() if "Error details:" in text else ""
        msg = details or (text.splitlines()[0] if text else type(exc).__name__)
        if "Unknown format" in str(exc) or "unknown format" in str(exc).lower():
            raise ValueError(
                f"cannot read mesh {str(p)!r}: the extension '.{ext}' is not a mesh format "
                "PyMeshLab reads (use OFF, PLY, OBJ, STL, ...)"
            ) from None
        raise ValueError(
            f"cannot read mesh {str(p)!r}: PyMeshLab reports {msg!r}; the file is probably "
            "truncated, corrupt or not a mesh of that format"
        ) from None
    except (MemoryError, ValueError, RuntimeError, OverflowError) as exc:
        # C++ exceptions of the reader (std::bad_alloc, std::length_error, ...)
        raise ValueError(
            f"cannot read mesh {str(p)!r}: PyMeshLab failed with {type(exc).__name__} "
            f"({str(exc)[:200]!r}); the file is probably corrupt (declared counts too large?)"
        ) from None
    finally:
        if cwd is not None and os.getcwd() != cwd:
            os.chdir(cwd)
    m = ms.current_mesh()
    if m.face_number() == 0:
        raise ValueError(
            f"cannot read mesh {str(p)!r}: it has {m.vertex_number()} vertices but no triangles "
            "(a point cloud?); cshape needs a triangle surface mesh"
        )
    V = np.array(m.vertex_matrix(), dtype=np.float64)
    F = np.array(m.face_matrix(), dtype=np.int64)
    return V, F, check_against_expected(p, expected, len(V), len(F))
