"""Reading one mesh file of a collection, checked against the manifest when pinned."""

from __future__ import annotations

import hashlib
import json
import zipfile
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..mesh import Mesh
from ..readers import load_mesh

if TYPE_CHECKING:
    import os


def _read_npz(path: Path, record: dict[str, Any] | None = None) -> Mesh:
    """Read a cached mesh (arrays only: pickled objects are refused, never executed).

    With ``record``, the recipe stored in the file must be that record: a file copied or
    written over from another item is not taken for this one.
    """
    try:
        with np.load(path, allow_pickle=False) as z:
            V, F = z["vertices"], z["faces"]
            if record is not None and json.loads(str(z["recipe"])) != record:
                raise ValueError("it holds the mesh of another recipe")
            return Mesh(V, F)
    except (ValueError, KeyError, TypeError, EOFError, zipfile.BadZipFile) as exc:
        raise ValueError(
            f"cannot read cached mesh {str(path)!r}: {exc}; delete the file to rebuild it"
        ) from None


class _FileLoader:
    """Callable reading one mesh file (``.path`` tells which)."""

    def __init__(self, path: Path):
        self.path = Path(path)

    def __call__(self) -> Mesh:
        if self.path.suffix.lower() == ".vert":
            return read_vert_tri(self.path)
        if self.path.suffix.lower() == ".npz":
            return _read_npz(self.path)
        return load_mesh(self.path)


_file_loader = _FileLoader


def _sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _verify_download(path: Path, item: dict, collection: str) -> None:
    """Check a downloaded file against the manifest's size and sha256 before it is read."""
    size = path.stat().st_size
    bad = None
    if size != item["size"]:
        bad = f"its size is {size} bytes, the manifest says {item['size']}"
    elif _sha256(path) != item["sha256"]:
        bad = f"its sha256 differs from the manifest's {item['sha256'][:12]}..."
    if bad:
        raise ValueError(
            f"downloaded file {str(path)!r} of {collection}/{item['name']} fails its check: "
            f"{bad}; it is corrupt or was replaced. Delete it and run `cshape data build "
            f"{collection}` to fetch it again"
        )


class _VerifiedLoader(_FileLoader):
    """A :class:`_FileLoader` for a pinned download: checks size and sha256 first."""

    def __init__(self, path: Path, item: dict, collection: str):
        super().__init__(path)
        self.item = item
        self.collection = collection

    def __call__(self) -> Mesh:
        _verify_download(self.path, self.item, self.collection)
        return super().__call__()


def read_vert_tri(vert_path: str | os.PathLike[str]) -> Mesh:
    """Read a TOSCA mesh: ``NAME.vert`` (x y z per line) and ``NAME.tri`` (1-based triangles).

    Parameters
    ----------
    vert_path : str or os.PathLike
        The ``.vert`` file; the ``.tri`` file of the same name must be beside it.

    Returns
    -------
    Mesh
        The vertices and the triangles, as 0-based indices.

    Raises
    ------
    FileNotFoundError
        If there is no ``.tri`` file beside ``vert_path``.
    ValueError
        If either file cannot be read as numbers, or the triangles are not 1-based indices
        of the vertices.
    """
    vert_path = Path(vert_path)
    tri_path = vert_path.with_suffix(".tri")
    if not tri_path.is_file():
        raise FileNotFoundError(f"{vert_path.name} has no matching {tri_path.name}")
    try:
        V = np.loadtxt(vert_path, dtype=np.float64, ndmin=2)
        F = np.loadtxt(tri_path, dtype=np.float64, ndmin=2)
    except ValueError as exc:
        raise ValueError(f"cannot read TOSCA mesh {str(vert_path)!r}: {exc}") from None
    if F.size and F.min() < 1:
        raise ValueError(f"{tri_path.name}: TOSCA triangles are 1-based, found index {F.min():g}")
    try:
        # as floats: Mesh refuses non-integer indices (a cast would truncate them silently)
        return Mesh(V, F - 1)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"cannot read TOSCA mesh {str(vert_path)!r}: {exc}") from None
