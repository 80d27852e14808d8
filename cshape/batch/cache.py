"""The eigenvalue cache: one ``<key>.npz`` per mesh content and parameters, and file aliases.
"""

from __future__ import annotations

import hashlib
import json
import warnings
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

import numpy as np

from .._files import atomic_write, cache_root
from ..mesh import CShapeWarning, as_mesh
from ..spectrum import SpectrumSettings

_DEFAULT_SETTINGS = SpectrumSettings()

if TYPE_CHECKING:
    import os

    from ..mesh import MeshLike


# =========================================================================== cache
def default_cache_dir() -> Path:
    """``<cache>/eigenvalues``, with ``<cache>`` the cache folder shared by cshape.

    ``<cache>`` is ``$CSHAPE_CACHE``, else ``platformdirs.user_cache_dir('cshape')`` when
    platformdirs is installed, else ``$XDG_CACHE_HOME/cshape`` or ``~/.cache/cshape`` (the
    same folder as :func:`cshape.data.cache_dir`).  Not created here.
    """
    return cache_root() / "eigenvalues"


def mesh_key(mesh: MeshLike, settings: SpectrumSettings = _DEFAULT_SETTINGS) -> str:
    """Cache key: SHA-256 (hex) of the mesh content and the eigenvalue settings.

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
    settings : SpectrumSettings, default=SpectrumSettings()
        Its ``bc``, ``mass`` and ``refine`` are part of the key; ``N`` is not (an entry
        serves every ``N`` up to the number it holds).

    Returns
    -------
    str
        64 hexadecimal digits; equal for meshes with identical vertex and face arrays.
    """
    mesh = as_mesh(mesh)
    V = np.ascontiguousarray(mesh.vertices, dtype="<f8")
    F = np.ascontiguousarray(mesh.faces, dtype="<i8")
    h = hashlib.sha256()
    h.update(f"cshape-lam-v{CACHE_VERSION}|{_settings_tag(settings)}".encode())
    h.update(f"{V.shape}|{F.shape}|".encode())
    h.update(V.tobytes())
    h.update(F.tobytes())
    return h.hexdigest()


def _settings_tag(settings: SpectrumSettings) -> str:
    """The part of a key that names the settings: ``bc``, ``mass`` and ``refine`` (``refine``
    only when not ``'none'``: the keys of plain linear FEM are those written before the
    option existed)."""
    refine = "" if settings.refine == "none" else f"refine={settings.refine}|"
    return f"bc={settings.bc}|mass={settings.mass}|{refine}"


def _entry_path(cache_dir: str | os.PathLike[str], key: str) -> Path:
    return Path(cache_dir) / f"{key}.npz"


def _read_entry(cache_dir: str | os.PathLike[str], key: str, N: int) -> dict[str, Any] | None:
    """The cached result with >= N eigenvalues, or None (missing, too short or corrupt)."""
    path = _entry_path(cache_dir, key)
    if not path.exists():
        return None
    try:
        with np.load(path, allow_pickle=False) as z:
            lam = np.asarray(z["lam"], dtype=np.float64)
            area = float(z["area"])
            seconds = float(z["seconds"])
            stored_key = str(z["key"])
            components = int(z["components"])
        if stored_key != key or lam.ndim != 1 or not np.all(np.isfinite(lam)):
            raise ValueError("inconsistent content")
        if not (np.isfinite(area) and area > 0):
            raise ValueError("bad area")
    except Exception as exc:  # noqa: BLE001 - any unreadable entry is recomputed
        warnings.warn(
            f"corrupt cache entry {str(path)!r} ({type(exc).__name__}: {exc}); recomputing it",
            CShapeWarning, stacklevel=2)
        return None
    if len(lam) < N:
        return None
    return {"lam": lam[:N], "area": area, "seconds": seconds, "key": key, "cached": True,
            "components": components}


def _file_alias(cache_dir: str | os.PathLike[str], path: str | os.PathLike[str],
                settings: SpectrumSettings) -> Path | None:
    """``cache_dir/files/<h>.key`` for a mesh file (see the module notes), None if unreadable."""
    try:
        p = Path(path).resolve()
        st = p.stat()
    except OSError:
        return None
    h = hashlib.sha256(
        f"cshape-file-v{CACHE_VERSION}|{_settings_tag(settings)}{p}|"
        f"{st.st_size}|"
        f"{st.st_mtime_ns}".encode()).hexdigest()
    return Path(cache_dir) / "files" / f"{h}.key"


def _read_alias(alias: Path) -> str | None:
    """The content key an alias file names, or None (missing or not a key)."""
    try:
        key = alias.read_text(encoding="ascii").strip()
    except (OSError, UnicodeError):
        return None
    return key if len(key) == 64 and all(c in "0123456789abcdef" for c in key) else None


def _write_entry(cache_dir: str | os.PathLike[str], result: dict[str, Any]) -> None:
    path = _entry_path(cache_dir, result["key"])

    def write(f: IO[Any]) -> None:
        np.savez(f, lam=result["lam"], area=np.float64(result["area"]),
                 seconds=np.float64(result["seconds"]), key=np.array(result["key"]),
                 n_vertices=np.int64(result["n_vertices"]),
                 n_faces=np.int64(result["n_faces"]),
                 components=np.int64(result["components"]),
                 params=np.array(json.dumps(result["params"])))

    atomic_write(path, write, binary=True)


CACHE_VERSION = 1
