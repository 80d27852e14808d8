"""Collections on disk: the cache of generated meshes, collection folders, and loading a
collection or one shape by name (:func:`load_collection`, :func:`load`).
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import json
import os
import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from .._checks import check_int
from .._files import atomic_write, make_folder
from ..mesh import Mesh
from .download import extract_archive, fetch
from .files import _file_loader, _FileLoader, _read_npz, _VerifiedLoader
from .folders import _LAYOUT_READERS, _manual_message, load_folder
from .manifest import RECIPES_VERSION, Collection, Item, _entry, _find_item, _recipes, load_manifest
from .paths import _cache_root, _removing_new_folders, collection_path

if TYPE_CHECKING:
    from collections.abc import Iterable, Iterator

    #: a path; a manifest: its path, or the parsed manifest; the entries of a manifest
    _StrPath = str | os.PathLike[str]
    _Manifest = str | os.PathLike[str] | dict[str, Any]
    _Entries = dict[str, dict[str, Any]]

# ====================================================================== cache


def _pymeshlab_version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("pymeshlab")
    except PackageNotFoundError:  # pragma: no cover
        return "unknown"


def _recipe_record(entries: _Entries, coll: str, item: dict[str, Any]) -> dict[str, Any]:
    rec = {
        "recipe": item["recipe"],
        "params": item.get("params") or {},
        "seed": item.get("seed"),
        "recipes_version": RECIPES_VERSION,
        "pymeshlab": _pymeshlab_version(),
    }
    if "base" in item:
        bcoll, _, bname = item["base"].partition("/")
        bitem = _find_item(entries[bcoll], bname)
        rec["base"] = {"item": item["base"], "key": _key(_recipe_record(entries, bcoll, bitem))}
    return rec


def _key(record: dict[str, Any]) -> str:
    blob = json.dumps(record, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(blob.encode()).hexdigest()[:16]


def _atomic_save_npz(path: Path, **arrays: Any) -> None:
    """Write ``arrays`` to ``path`` as .npz atomically (see :func:`cshape._files.atomic_write`)."""
    hint = "pass cache_dir= or set CSHAPE_CACHE to a writable folder"
    make_folder(path.parent, what="cache folder", hint=hint)
    atomic_write(path, lambda fh: np.savez(fh, **arrays), what="cache file", hint=hint)


def _cache_file(entries: _Entries, coll: str, item: dict[str, Any], root: Path) -> Path:
    key = _key(_recipe_record(entries, coll, item))
    return root / "generated" / coll / f"{item['name']}-{key}.npz"


def _generated_mesh(entries: _Entries, coll: str, item: dict[str, Any], root: Path
                    ) -> tuple[Mesh, bool]:
    """Return (mesh, built) for a generated item, from the cache or by building it.

    Processes that ask for the same missing item at once build it once: the others wait
    for the first one's file (a lock beside it, where the system has ``fcntl``)."""
    path = _cache_file(entries, coll, item, root)
    record = _recipe_record(entries, coll, item)
    existed = path.is_file()
    mesh = _read_cached(path, record)
    if mesh is None:
        with _build_lock(path):
            # built by another process meanwhile (an unreadable file is rebuilt at once)
            mesh = None if existed else _read_cached(path, record)
            if mesh is None:
                return _build_item(entries, coll, item, root, path, record), True
    return mesh, False


def _read_cached(path: Path, record: dict[str, Any]) -> Mesh | None:
    """The cached mesh at ``path``; None if there is none, or (with a warning) an
    unreadable one, which is then rebuilt."""
    if not path.is_file():
        return None
    try:
        return _read_npz(path, record)
    except (OSError, ValueError, KeyError) as exc:
        warnings.warn(f"rebuilding unreadable cache file {path} ({exc})", stacklevel=4)
        return None


@contextlib.contextmanager
def _build_lock(path: Path) -> Iterator[None]:
    """Hold ``.<name>.lock`` beside ``path`` exclusively (none without ``fcntl``).

    A process killed while it holds the lock leaves the empty file; the system has
    released the lock, and the next build takes it and removes the file."""
    try:
        import fcntl
    except ImportError:  # Windows: two processes may build the same item; both write atomically
        yield
        return
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fh = open(path.with_name(f".{path.name}.lock"), "a")  # noqa: SIM115
    except OSError:  # a read-only cache: the build's own write says what is wrong
        yield
        return
    with fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            # gone once the item is built: a process still waiting holds it open and then
            # finds the cache file; a later one finds the file first
            with contextlib.suppress(OSError):
                os.unlink(fh.name)
            fcntl.flock(fh, fcntl.LOCK_UN)


def _build_item(entries: _Entries, coll: str, item: dict[str, Any], root: Path, path: Path,
                record: dict[str, Any]) -> Mesh:
    """Build a generated item by its recipe and write it to its cache file."""
    fn, takes_base, takes_seed = _recipes()[item["recipe"]]
    args, kwargs = [], dict(item.get("params") or {})
    if takes_base:
        bcoll, _, bname = item["base"].partition("/")
        args.append(_generated_mesh(entries, bcoll, _find_item(entries[bcoll], bname), root)[0])
    if takes_seed:
        kwargs["random_state"] = item.get("seed")
    mesh = fn(*args, **kwargs)
    _atomic_save_npz(
        path, vertices=mesh.vertices, faces=mesh.faces, recipe=np.array(json.dumps(record))
    )
    return mesh


def _generated_item(entries: _Entries, coll: str, item: dict[str, Any], root: Path) -> Mesh:
    """The mesh of a generated item, read from the cache or built (a lazy item's loader)."""
    return _generated_mesh(entries, coll, item, root)[0]


# ====================================================================== loading
def load_collection(
    name: str, *, cache_dir: _StrPath | None = None, download: bool = False,
    progress: bool | None = None, manifest: _Manifest | None = None, n_jobs: int = 1,
    lazy: bool = False
) -> Collection:
    """Load a collection: its meshes with names and class labels.

    Parameters
    ----------
    name : str
        A collection of the manifest (:func:`list_collections`).
    cache_dir : str or os.PathLike, optional
        Cache folder (default :func:`cache_dir`).
    download : bool, default=False
        For a ``download`` collection whose files are not in the cache yet, fetch them
        (:func:`fetch`).  Without it a missing file is an error saying how to fetch it;
        nothing is ever downloaded unless asked.
    progress : bool or None, default=None
        Progress bar while building generated meshes: ``None`` shows it on a terminal when
        the build takes more than half a second.
    manifest : path or dict, optional
        Another manifest (default :func:`load_manifest`).
    n_jobs : int, default=1
        Worker processes that build the missing generated meshes (joblib's loky pool), each
        from its own seed.  Usually the same bits as built one by one; remeshed meshes can
        differ slightly between processes (isotropic remeshing turns a last-bit difference
        of its input into another edge flip: a few triangles, the same shape), and the
        cache keeps whichever was built first.
    lazy : bool, default=False
        For a generated collection, build (or read from the cache) an item's mesh only when
        its ``mesh`` is first used, one by one, so that a few meshes of a large collection
        cost a few builds.  Ignored by the other kinds, which always load on first access.

    Returns
    -------
    Collection
        ``.names``, ``.labels``, ``.meshes``; items by position or name.  Generated meshes are
        built (or read from the cache) now, unless ``lazy``; files of the other kinds load on
        first access.
    """
    entries = load_manifest(manifest)
    entry = _entry(name, entries)
    kind = entry["kind"]
    meta = {k: v for k, v in entry.items() if not k.startswith("_")}
    if kind == "generated" and lazy:
        root = _cache_root(cache_dir)
        return Collection(name, [
            Item(it["name"], it["label"], name, dict(it),
                 _load=functools.partial(_generated_item, entries, name, it, root))
            for it in entry["items"]], meta)
    if kind == "generated":
        root = _cache_root(cache_dir)
        _build_in_processes(entries, name, root, n_jobs, progress)
        items = []
        with _progress(len(entry["items"]), f"cshape: {name}", progress) as bar:
            for it in entry["items"]:
                mesh, _ = _generated_mesh(entries, name, it, root)
                cached = _cache_file(entries, name, it, root)
                rec = Item(it["name"], it["label"], name, dict(it), _load=_FileLoader(cached))
                rec.__dict__["mesh"] = mesh
                items.append(rec)
                bar.update(1)
        return Collection(name, items, meta)
    folder = collection_path(name, cache_dir=cache_dir, manifest=entries)
    if kind == "download" and "layout" in entry:
        if not folder.is_dir():
            raise FileNotFoundError(_manual_message(entry, folder))
        coll = _LAYOUT_READERS[entry["layout"]](folder)
        return Collection(name, coll.items, meta)
    if kind == "local" and not entry.get("items"):
        coll = load_folder(folder, labels=entry["labels"], name=name)
        return Collection(name, coll.items, meta)
    if kind == "download":
        missing = [it for it in entry["items"] if not (folder / it["file"]).is_file()]
        if missing and not download:
            total = sum(it["size"] for it in missing) / 1e6
            raise FileNotFoundError(
                f"collection {name!r}: {len(missing)} of {len(entry['items'])} files are not "
                f"downloaded yet ({total:.1f} MB) into {str(folder)!r}; run `cshape data "
                f"build {name}` or pass download=True"
            )
        if missing:
            fetch(name, cache_dir=cache_dir, manifest=entries)
    if kind == "package" and not folder.is_dir():
        raise FileNotFoundError(
            f"collection {name!r}: folder {str(folder)!r} is not in the installed "
            f"{entry['package']!r} package (a different version?)"
        )
    items = [
        Item(it["name"], it["label"], name, dict(it), _load=(
            _VerifiedLoader(folder / it["file"], it, name) if kind == "download"
            else _file_loader(folder / it["file"])))
        for it in entry["items"]
    ]
    return Collection(name, items, meta)


def _build_one(task: tuple[_Entries, str, dict[str, Any], str]) -> None:
    entries, coll, item, root = task
    _generated_mesh(entries, coll, item, Path(root))


def _build_in_processes(entries: _Entries, name: str, root: Path, n_jobs: int,
                        progress: bool | None) -> None:
    """Build the missing items of a generated collection (those without a base) in
    ``n_jobs`` processes; each writes its cache file atomically, as a serial build does."""
    n_jobs = check_int("n_jobs", n_jobs, min=1)  # worker processes
    todo = [it for it in entries[name]["items"]
            if "base" not in it and not _cache_file(entries, name, it, root).is_file()]
    if n_jobs == 1 or len(todo) < 2:
        return
    from joblib.externals.loky import ProcessPoolExecutor

    tasks = [(entries, name, it, str(root)) for it in todo]
    with _progress(len(todo), f"cshape: {name} ({n_jobs} processes)", progress) as bar, \
            ProcessPoolExecutor(max_workers=min(n_jobs, len(todo))) as ex:
        for _ in ex.map(_build_one, tasks):
            bar.update(1)


def load(name: str, item: str, *, cache_dir: _StrPath | None = None, download: bool = False,
         manifest: _Manifest | None = None) -> Mesh:
    """One mesh of a collection, e.g. ``load("paper-models", "CM")``.

    Parameters
    ----------
    name : str
        The collection.
    item : str
        The item's name (``load_collection(name).names``).
    cache_dir : str or os.PathLike, optional
        Cache folder (default :func:`cache_dir`).
    download : bool, default=False
        Fetch a missing file of a ``download`` collection, as for :func:`load_collection`.
    manifest : path or dict, optional
        Another manifest (default :func:`load_manifest`).

    Returns
    -------
    Mesh
        The item's mesh.
    """
    entries = load_manifest(manifest)
    entry = _entry(name, entries)
    if entry["kind"] == "generated":
        return _generated_mesh(entries, name, _find_item(entry, item), _cache_root(cache_dir))[0]
    if entry["kind"] == "download" and "items" in entry:
        it = _find_item(entry, item)
        folder = collection_path(name, cache_dir=cache_dir, manifest=entries)
        if not (folder / it["file"]).is_file():
            if not download:
                raise FileNotFoundError(
                    f"{name}/{item} is not downloaded yet; run `cshape data build {name}` "
                    "or pass download=True"
                )
            fetch(name, items=[item], cache_dir=cache_dir, manifest=entries)
            return _file_loader(folder / it["file"])()  # pooch checked its sha256
        return _VerifiedLoader(folder / it["file"], it, name)()
    return load_collection(name, cache_dir=cache_dir, manifest=entries)[item].mesh


def load_creatures(seed: int = 1, members: int = 10, kinds: Iterable[str] | None = None, *,
                   cache_dir: _StrPath | None = None, progress: bool | None = None,
                   n_jobs: int = 1, **params: Any) -> Collection:
    """An instance of the creature benchmark (:mod:`cshape.data.creatures`) for any seed.

    The manifest's ``creatures-dev`` is ``load_creatures(0)``, ``creatures`` (held out) is
    ``load_creatures(1)`` (same meshes, cached in a folder of their own).

    Parameters
    ----------
    seed : int, default=1
        Instance seed: 0 is the development instance (choose and tune on it), 1 the held-out
        one (report on it); any other seed gives a fresh instance.
    members : int, default=10
        Members per class.
    kinds : sequence of str, optional
        Classes (default all of :data:`cshape.data.creatures.CREATURE_KINDS`).
    cache_dir : str or os.PathLike, optional
        Cache folder (default :func:`cache_dir`).
    progress : bool or None, default=None
        Progress bar while building, as for :func:`load_collection`.
    n_jobs : int, default=1
        Worker processes that build the missing meshes, as for :func:`load_collection`.
    **params
        Passed to :func:`cshape.data.creatures.creature` for every item (``variation``,
        ``vertices``, ``noise``, ``voxelsize``).

    Returns
    -------
    Collection
        Named ``creatures-seed<seed>``; items ``<kind>-<k>``, labels the class.

    Examples
    --------
    >>> import cshape.data
    >>> small = cshape.data.store.load_creatures(0, members=2, kinds=["snake", "teddy"],
    ...                                    vertices=[400, 600], voxelsize=0.03)
    >>> small.names
    ['snake-00', 'snake-01', 'teddy-00', 'teddy-01']
    """
    generate = {"seed": seed, "members": members, "params": params}
    if kinds is not None:
        generate["kinds"] = list(kinds)
    name = f"creatures-seed{seed}"
    doc = {"version": 1, "collections": [{
        "name": name, "kind": "generated", "generate": generate,
        "description": f"creature benchmark, seed {seed}, {members} members per class",
        "license": "BSD-3-Clause (generated by cshape; no third-party data)",
        "citation": "cshape.data.creatures.creature, built with PyMeshLab",
    }]}
    return load_collection(name, cache_dir=cache_dir, progress=progress, manifest=doc,
                           n_jobs=n_jobs)


class _NoBar:
    def __enter__(self) -> _NoBar:
        return self

    def __exit__(self, *exc: object) -> Literal[False]:
        return False

    def update(self, n: int = 1) -> None:
        pass


def _progress(total: int, desc: str, progress: bool | None) -> Any:
    if progress is False:
        return _NoBar()
    try:
        from tqdm.auto import tqdm
    except ImportError:  # pragma: no cover - tqdm is a dependency
        return _NoBar()
    return tqdm(total=total, desc=desc, unit="mesh", delay=0.5, disable=None if progress is None
                else not progress, leave=False)


def build(name: str, *, cache_dir: _StrPath | None = None, progress: bool | None = None,
          archive: _StrPath | None = None, manifest: _Manifest | None = None) -> Path:
    """Make a collection available offline and return its folder.

    generated: build every missing item into the cache; download (pinned files): fetch them;
    download (benchmark): unpack ``archive`` (a file you downloaded by hand) into place with
    :func:`extract_archive`, then check it reads; package / local: check every file reads.

    Parameters
    ----------
    name : str
        A collection of the manifest (:func:`list_collections`).
    cache_dir : str or os.PathLike, optional
        Cache folder (default :func:`cache_dir`).
    progress : bool or None, default=None
        Progress bars, as for :func:`load_collection` (downloads show theirs unless
        ``False``).
    archive : str or os.PathLike, optional
        For a ``download`` collection only: the archive to unpack into its folder.
    manifest : path or dict, optional
        Another manifest (default :func:`load_manifest`).

    Returns
    -------
    Path
        The collection's folder (:func:`collection_path`).

    Raises
    ------
    ValueError
        If ``archive`` is given for a collection that is not of kind ``download``.
    """
    entries = load_manifest(manifest)
    entry = _entry(name, entries)
    folder = collection_path(name, cache_dir=cache_dir, manifest=entries)
    if archive is not None and entry["kind"] != "download":
        raise ValueError(f"archive= is only for download collections, not {entry['kind']!r}")
    with _removing_new_folders(folder):
        if archive is not None:
            extract_archive(archive, folder)
        if entry["kind"] == "download" and "items" in entry:
            fetch(name, cache_dir=cache_dir, progress=bool(progress is not False),
                  manifest=entries)
        coll = load_collection(name, cache_dir=cache_dir, progress=progress, manifest=entries)
        if entry["kind"] != "generated":
            for it in coll:
                it.mesh  # noqa: B018 - read every file once, so a broken one shows now
    return folder
