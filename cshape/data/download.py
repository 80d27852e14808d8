"""Downloads, only on request: fetching pinned files (:func:`fetch`), unpacking archives
safely (:func:`extract_archive`) and building a collection's folder (:func:`build`).
"""

from __future__ import annotations

import errno
import os
import re
import shutil
import tarfile
import tempfile
import zipfile
from pathlib import Path, PurePosixPath
from typing import TYPE_CHECKING, Any

from .folders import _manual_message
from .manifest import _entry, _find_item, load_manifest
from .paths import _removing_new_folders, collection_path

if TYPE_CHECKING:
    import os
    from collections.abc import Iterable

    #: a path; a manifest: its path, or the parsed manifest
    _StrPath = str | os.PathLike[str]
    _Manifest = str | os.PathLike[str] | dict[str, Any]


# ====================================================================== downloads
def extract_archive(archive: _StrPath, target: _StrPath) -> Path:
    """Unpack a .zip or .tar(.gz/.bz2/.xz) archive into ``target``, refusing to escape it.

    Members with absolute paths, ``..`` components, or (for tar) links and device files are
    rejected before anything is written; the archive is unpacked into a temporary folder
    beside ``target`` and moved into place, so a failure leaves ``target`` as it was.

    Parameters
    ----------
    archive : str or os.PathLike
        The ``.zip``, ``.tar``, ``.tar.gz``, ``.tar.bz2`` or ``.tar.xz`` file.
    target : str or os.PathLike
        The folder to unpack into; its parent is created if needed.

    Returns
    -------
    Path
        ``target``.

    Raises
    ------
    ValueError
        If a member would land outside ``target`` or the file is not a known archive.
    OSError
        If the unpacked members would not fit on the disk (checked before writing).
    """
    archive, target = Path(archive), Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(dir=target.parent, prefix=f".{target.name}.extract."))
    try:
        if zipfile.is_zipfile(archive):
            with zipfile.ZipFile(archive) as zf:
                for n in zf.namelist():
                    _check_member(n, archive)
                _check_space(sum(i.file_size for i in zf.infolist()), tmp, archive)
                zf.extractall(tmp)
        elif tarfile.is_tarfile(archive):
            with tarfile.open(archive) as tf:
                members = tf.getmembers()
                for m in members:
                    _check_member(m.name, archive)
                    if not (m.isfile() or m.isdir()):
                        raise ValueError(
                            f"archive {archive.name!r}: member {m.name!r} is a link or special "
                            "file; refusing to extract it"
                        )
                _check_space(sum(m.size for m in members), tmp, archive)
                if hasattr(tarfile, "data_filter"):  # Python >= 3.11.4: also drops setuid
                    tf.extractall(tmp, members=members, filter="data")  # bits, owners, ...
                else:  # pragma: no cover
                    tf.extractall(tmp, members=members)
        else:
            raise ValueError(f"{archive.name!r} is not a .zip or .tar archive")
        target.mkdir(parents=True, exist_ok=True)
        for child in tmp.iterdir():
            dest = target / child.name
            if dest.is_symlink() or dest.is_file():
                dest.unlink()  # a link is replaced, never followed
            elif dest.exists():
                shutil.rmtree(dest)
            os.replace(child, dest)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return target


def _check_space(total: int, folder: Path, archive: Path) -> None:
    """Refuse to start unpacking what the disk cannot hold (or a zip bomb)."""
    free = shutil.disk_usage(folder).free
    if total > free:
        raise OSError(
            errno.ENOSPC,
            f"archive {archive.name!r} unpacks to {total / 1e6:.1f} MB but only "
            f"{free / 1e6:.1f} MB are free in {str(folder.parent)!r}; free disk space or "
            "unpack it elsewhere (cache_dir= / CSHAPE_CACHE)",
        )


def _check_member(name: str, archive: Path) -> None:
    p = PurePosixPath(name.replace("\\", "/"))
    if p.is_absolute() or ".." in p.parts or re.match(r"^[A-Za-z]:", name):
        raise ValueError(
            f"archive {archive.name!r}: member {name!r} would be written outside the target "
            "folder; refusing to extract"
        )


def fetch(name: str, *, items: Iterable[str] | None = None, cache_dir: _StrPath | None = None,
          progress: bool = True, manifest: _Manifest | None = None) -> list[Path]:
    """Download the files of a ``download`` collection into the cache (only when called).

    Uses pooch: each file is downloaded to a temporary name, checked against the manifest's
    sha256 and moved into place; files already present with the right hash are not fetched
    again.

    Parameters
    ----------
    name : str
        A ``download`` collection with pinned ``items``.
    items : list of str, optional
        Only these items (default: all).
    cache_dir : str or os.PathLike, optional
        Cache folder (default :func:`cache_dir`).
    progress : bool, default=True
        Show pooch's progress bar per file.
    manifest : path or dict, optional
        Another manifest (default :func:`load_manifest`).

    Returns
    -------
    list of Path
        The local files.

    Raises
    ------
    ImportError
        If pooch is not installed (``pip install cshape[download]``).
    ValueError
        If the collection is not downloadable (a benchmark fetched by hand, or another
        kind), or a downloaded file differs from the manifest's sha256.
    ConnectionError
        If the server cannot be reached (offline, refused, name not resolved, timeout).
    OSError
        If the server answers with an HTTP error, or the file cannot be written.

    Notes
    -----
    A failed download keeps the files fetched and checked before it, removes its temporary
    file and the folders it created and left empty; the message names the item, the URL
    and the cause on one line.
    """
    entries = load_manifest(manifest)
    entry = _entry(name, entries)
    if entry["kind"] != "download":
        raise ValueError(
            f"collection {name!r} is of kind {entry['kind']!r}; only 'download' collections "
            "are fetched (generated ones are built: `cshape data build`)"
        )
    folder = collection_path(name, cache_dir=cache_dir, manifest=entries)
    if "layout" in entry:
        raise ValueError(_manual_message(entry, folder))
    try:
        import pooch
    except ImportError:
        raise ImportError(
            "downloading needs pooch; install it with `pip install cshape[download]`"
        ) from None
    wanted = entry["items"] if items is None else [_find_item(entry, i) for i in items]
    out = []
    logger = pooch.get_logger()
    level = logger.level
    logger.setLevel("WARNING")  # the progress bar says what is downloaded
    try:
        with _removing_new_folders(folder):
            for it in wanted:
                dest = folder / it["file"]
                try:
                    got = pooch.retrieve(
                        url=it["url"], known_hash=f"sha256:{it['sha256']}", fname=dest.name,
                        path=dest.parent, progressbar=progress,
                    )
                except Exception as exc:  # noqa: BLE001 - requests', pooch's and OS errors
                    raise _download_error(exc, name, it) from None
                out.append(Path(got))
    finally:
        logger.setLevel(level)
    return out


def _download_error(exc: BaseException, collection: str, item: dict[str, Any]) -> Exception:
    """One clear error for a failed download: ConnectionError, ValueError or OSError."""
    text = " ".join(str(exc).split())
    where = f"cannot download {collection}/{item['name']} from {item['url']}"
    again = f"run `cshape data build {collection}` again"
    reason = re.search(r"\[Errno -?\d+\] ([^'\")\]]+)", text)
    name = type(exc).__name__
    module = type(exc).__module__.split(".")[0]
    if "hash" in text.lower() and isinstance(exc, ValueError):
        return ValueError(
            f"{where}: the file received differs from the manifest's sha256 (the file on the "
            f"server changed, or the download was altered); nothing was kept. {text}"
        )
    if module in ("requests", "urllib3", "socket", "ssl") or isinstance(exc, OSError):
        status = getattr(getattr(exc, "response", None), "status_code", None)
        if status is not None:
            why = f"the server answered HTTP {status}"
        elif reason:
            why = f"{reason.group(1).strip()} ({name})"
        else:
            why = f"{name}: {text[:200]}"
        cls = ConnectionError if status is None else OSError
        return cls(f"{where}: {why}; check the network connection (or proxy) and {again}")
    return OSError(f"{where}: {name}: {text[:300]}; {again}")




