"""Files the package writes: one cache folder and one atomic write.

* :func:`cache_root` - the folder shared by every cache of cshape (generated meshes,
  eigenvalues, downloads): ``path`` if given, else ``$CSHAPE_CACHE``, else the user cache folder;
* :func:`make_folder` - create a folder, or raise an ``OSError`` that names it and the fix;
* :func:`atomic_write` - write through a temporary file in the same folder and ``os.replace``
  it into place, with the user's umask permissions; nothing half-written is ever left behind.
"""

from __future__ import annotations

import errno
import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import IO, Any


def cache_root(path: str | os.PathLike | None = None) -> Path:
    """Return the cache folder: ``path``, else ``$CSHAPE_CACHE``, else the user cache folder.

    The user cache folder is ``platformdirs.user_cache_dir('cshape', appauthor=False)`` when
    platformdirs is installed, else ``$XDG_CACHE_HOME/cshape`` or ``~/.cache/cshape``.
    Not created here.
    """
    if path is not None:
        return Path(path).expanduser()
    env = os.environ.get("CSHAPE_CACHE")
    if env:
        return Path(env).expanduser()
    try:
        import platformdirs

        return Path(platformdirs.user_cache_dir("cshape", appauthor=False))
    except ImportError:  # pragma: no cover - platformdirs comes with pooch
        base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
        return Path(base) / "cshape"


def umask() -> int:
    """Return the process's umask (read without changing it for longer than one call)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def make_folder(folder: Path, *, what: str = "folder",
                hint: str = "pass cache_dir= or set CSHAPE_CACHE to a writable folder") -> None:
    """Create ``folder`` (and its parents), or raise an ``OSError`` naming it.

    The error names the folder as ``what`` (e.g. ``'cache folder'``) and gives ``hint``.
    """
    folder = Path(folder)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        blocker = next((q for q in [folder, *folder.parents] if q.exists()), None)
        why = (
            f"{str(blocker)!r} is a file, not a folder"
            if blocker is not None and not blocker.is_dir()
            else exc.strerror or str(exc)
        )
        raise type(exc)(exc.errno, f"cannot create the {what} {str(folder)!r}: {why}; {hint}") \
            from None


def atomic_write(path: str | os.PathLike, write: Callable[[IO[Any]], object], *,
                 binary: bool = True, what: str = "file",
                 hint: str = "choose another folder") -> Path:
    """Write ``path`` through ``write(file)`` atomically, with the usual permissions.

    The data go to a temporary file in the same folder, which is flushed, given the
    permissions ``0o666 & ~umask`` (``mkstemp`` makes 0600) and moved into place with
    ``os.replace``.  On any failure (disk full, read-only folder, interrupt) the temporary
    file is removed and ``path`` is left as it was.

    Parameters
    ----------
    path : path-like
        The file to write; its folder must exist.
    write : callable
        Called once with the open file object (text files: UTF-8, ``newline=''``).
    binary : bool, default=True
        Open the file in binary mode.
    what : str, default='file'
        What the file is, for messages (``'cache file'``: its folder is the cache folder).
    hint : str
        What the user can do, appended to an ``OSError`` about the folder or a full disk.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    path = Path(path)
    try:
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    except OSError as exc:
        raise type(exc)(
            exc.errno,
            f"cannot write to the {what.replace('file', 'folder')} {str(path.parent)!r} "
            f"({exc.strerror}); {hint}",
        ) from None
    try:
        kw: dict[str, Any] = {} if binary else {"newline": "", "encoding": "utf-8"}
        with os.fdopen(fd, "wb" if binary else "w", **kw) as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, 0o666 & ~umask())
        os.replace(tmp, path)
    except BaseException as exc:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        if isinstance(exc, OSError) and exc.errno in (errno.ENOSPC, errno.EDQUOT):
            raise OSError(
                exc.errno,
                f"no space left to write the {what} {str(path)!r} ({exc.strerror}); "
                "nothing was written. "
                f"Free disk space, or {hint}",
            ) from None
        raise
    return path
