"""Where collections live: the cache folder and each collection's folder."""

from __future__ import annotations

import contextlib
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .._files import cache_root
from .manifest import _entry

if TYPE_CHECKING:
    from collections.abc import Iterator


def cache_dir(path: str | os.PathLike[str] | None = None) -> Path:
    """Return the cache folder of the data collections; it is not created here.

    Parameters
    ----------
    path : str or os.PathLike, optional
        The folder to use.  Default: ``$CSHAPE_CACHE``, else the user cache folder
        (``~/.cache/cshape`` on Linux).

    Returns
    -------
    Path
        The cache folder.
    """
    return cache_root(path)


def _env_path(entry: dict[str, Any]) -> Path | None:
    env = entry.get("path_env")
    if env and os.environ.get(env):
        return Path(os.environ[env]).expanduser()
    return None


def collection_path(name: str, *, cache_dir: str | os.PathLike[str] | None = None,
                    manifest: str | os.PathLike[str] | dict[str, Any] | None = None) -> Path:
    """Return where collection ``name`` lives on disk (it may not exist yet).

    generated: ``<cache>/generated/<name>``; download: ``$<path_env>`` if set, else
    ``<cache>/downloads/<name>``; package: the folder inside the installed package;
    local: ``$<path_env>`` if set, else ``path`` relative to the manifest's folder.

    Parameters
    ----------
    name : str
        A collection of the manifest.
    cache_dir : str or os.PathLike, optional
        Cache folder (default :func:`cache_dir`).
    manifest : path or dict, optional
        Another manifest (default :func:`load_manifest`).

    Returns
    -------
    Path
        The collection's folder.
    """
    entry = _entry(name, manifest)
    kind = entry["kind"]
    root = _cache_root(cache_dir)
    if kind == "generated":
        return root / "generated" / name
    if kind == "download":
        return _env_path(entry) or root / "downloads" / name
    if kind == "package":
        import importlib.util

        spec = importlib.util.find_spec(entry["package"])
        if spec is None or not spec.submodule_search_locations:
            raise FileNotFoundError(
                f"collection {name!r} reads package {entry['package']!r}, which is not "
                f"installed; pip install {entry['package']}"
            )
        return Path(list(spec.submodule_search_locations)[0]) / entry["path"]
    env = _env_path(entry)
    if env is not None:
        return env
    p = Path(entry["path"]).expanduser()
    return p if p.is_absolute() else (Path(entry.get("_root", ".")) / p).resolve()


def _cache_root(path: str | os.PathLike[str] | None) -> Path:
    return cache_dir(path)


@contextlib.contextmanager
def _removing_new_folders(folder: str | os.PathLike[str]) -> Iterator[None]:
    """On an error, remove the folders at and below ``folder`` this block created and left
    empty (and the parents of ``folder`` it created), so a failed download or build leaves
    the disk as it found it, apart from complete, checked files."""
    folder = Path(folder)
    parents = [q for q in [folder, *folder.parents] if not q.exists()]
    before = {q for q in folder.rglob("*") if q.is_dir()} if folder.is_dir() else set()
    try:
        yield
    except BaseException:
        new = [q for q in folder.rglob("*") if q.is_dir() and q not in before] \
            if folder.is_dir() else []
        for q in sorted(new, key=lambda q: len(q.parts), reverse=True) + parents:
            try:
                q.rmdir()  # only empty folders go
            except OSError:
                pass
        raise
