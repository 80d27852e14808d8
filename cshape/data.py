"""Shape collections: the data manifest, generated and cached shapes, packaged, local and
downloadable meshes, and loaders for the classic benchmarks' folder layouts.

Every collection is an entry of ``data_manifest.yaml`` (shipped inside the package, or the file
named by ``CSHAPE_MANIFEST``), of one of four kinds:

==========  ===================================================================================
generated   built by a recipe of :mod:`cshape.variants` (PyMeshLab), seeded, cached on disk
package     meshes shipped inside an installed Python package (PyMeshLab's samples)
download    public files fetched *only on request* (:func:`fetch`, ``cshape data build NAME``)
            into the cache and checked against their sha256; benchmarks whose terms forbid
            redistribution (McGill, TOSCA, SHREC'07) are fetched by hand and read by a layout
            loader (:func:`read_mcgill`, :func:`read_tosca`, :func:`read_shrec07`)
local       any folder of meshes, class labels from sub-folder names or a CSV
            (:func:`load_folder`)
==========  ===================================================================================

One call gets a shape or a whole collection, offline and reproducibly::

    import cshape.data
    cshape.data.list_collections()              # ['paper-models', 'articulated', ...]
    S1 = cshape.data.load("paper-models", "S1")  # a cshape.Mesh
    poses = cshape.data.load_collection("articulated")
    poses.names, poses.labels, poses[0].mesh

Cache
-----
Generated meshes live in ``<cache>/generated/<collection>/<item>-<key>.npz`` (arrays
``vertices``, ``faces`` and the recipe as JSON; read with ``allow_pickle=False``), where
``<cache>`` is ``cache_dir=`` if given, else ``$CSHAPE_CACHE``, else the user cache folder
(``~/.cache/cshape`` on Linux) and ``<key>`` hashes the recipe, its parameters, the seed, the
base item's key, :data:`RECIPES_VERSION` and the PyMeshLab version.  Files are written to a
temporary name and moved into place (``os.replace``), so an interrupted build never leaves a
partial file; a cache folder that cannot be written (a file in its place, a full disk) gives an
``OSError`` naming it.  Downloads go to ``<cache>/downloads/<collection>/``; a downloaded file is
checked against the manifest's size and sha256 before each read, so a corrupt or replaced file
is an error, never a silently different mesh.
"""

from __future__ import annotations

import contextlib
import copy
import csv
import errno
import hashlib
import inspect
import json
import os
import re
import shutil
import tarfile
import tempfile
import warnings
import zipfile
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path, PurePosixPath

import numpy as np

from .mesh import Mesh
from .readers import MESH_SUFFIXES, load_mesh, split_mesh_name

__all__ = [
    "KINDS",
    "LAYOUTS",
    "MANIFEST_SCHEMA",
    "RECIPES",
    "RECIPES_VERSION",
    "Collection",
    "Item",
    "build",
    "cache_dir",
    "collection_path",
    "extract_archive",
    "fetch",
    "info",
    "list_collections",
    "load",
    "load_collection",
    "load_creatures",
    "load_folder",
    "load_manifest",
    "read_mcgill",
    "read_shrec07",
    "read_tosca",
    "read_vert_tri",
    "validate_manifest",
]

KINDS = ("generated", "package", "download", "local")
LAYOUTS = ("mcgill", "tosca", "shrec07")

#: Bumped whenever a recipe's output changes, so stale cache files are not reused.
RECIPES_VERSION = 1

#: The manifest shipped inside the package.  In a source checkout ``cshape/data_manifest.yaml``
#: is a symbolic link to the top-level ``data_manifest.yaml`` (the one file to edit); the
#: wheel stores the file itself (``[tool.setuptools.package-data]`` in pyproject.toml).
_DEFAULT_MANIFEST = Path(__file__).resolve().parent / "data_manifest.yaml"


# ====================================================================== records
@dataclass(eq=False)
class Item:
    """One mesh of a collection: its name, class label and (lazily loaded) mesh.

    Attributes
    ----------
    name : str
        Unique within the collection.
    label : str
        Class label (for classification and MDS colouring).
    collection : str
        Name of the collection.
    meta : dict
        The manifest entry of the item (recipe, params, seed, file, license, ...).
    mesh : Mesh
        Loaded on first access and kept.
    path : Path or None
        The file it is read from (a generated item's cache file).
    """

    name: str
    label: str
    collection: str = ""
    meta: dict = field(default_factory=dict, repr=False)
    _load: Callable[[], Mesh] | None = field(default=None, repr=False)

    @property
    def path(self) -> Path | None:
        """The file the mesh is read from (for generated items, its cache file)."""
        return getattr(self._load, "path", None)

    @cached_property
    def mesh(self) -> Mesh:
        """The item's mesh, loaded (or read from the cache) on first access."""
        if self._load is None:  # pragma: no cover - every constructor passes a loader
            raise ValueError(f"item {self.name!r} has no loader")
        return self._load()


@dataclass(eq=False)
class Collection:
    """A named list of :class:`Item`, indexable by position or item name.

    Attributes
    ----------
    name : str
    items : list of Item
    info : dict
        The manifest entry (description, license, citation, ...).
    """

    name: str
    items: list
    info: dict = field(default_factory=dict, repr=False)

    def __len__(self) -> int:
        return len(self.items)

    def __iter__(self):
        return iter(self.items)

    def __getitem__(self, key) -> Item:
        if isinstance(key, str):
            for it in self.items:
                if it.name == key:
                    return it
            raise KeyError(
                f"collection {self.name!r} has no item {key!r}; items are {self.names[:20]}"
            )
        return self.items[key]

    @property
    def names(self) -> list[str]:
        """Item names, in order."""
        return [it.name for it in self.items]

    @property
    def labels(self) -> list[str]:
        """Class labels, in order."""
        return [it.label for it in self.items]

    @property
    def meshes(self) -> list[Mesh]:
        """All meshes (loads those not loaded yet)."""
        return [it.mesh for it in self.items]

    def __repr__(self) -> str:
        classes = sorted(set(self.labels))
        return f"Collection({self.name!r}, {len(self)} items, {len(classes)} classes)"


# ====================================================================== recipes
def _recipes() -> dict:
    from . import variants as v
    from .creatures import creature

    return {
        # name: (function, takes a base mesh, takes a seed)
        "sphere": (v.sphere, False, False),
        "torus": (v.torus, False, False),
        "cube": (v.cube, False, False),
        "eight": (v.eight, False, False),
        "figure": (v.articulated_figure, False, True),
        "remesh": (v.remesh, True, False),
        "subdivide": (v.subdivide, True, False),
        "noise": (v.add_normal_noise, True, True),
        "creature": (creature, False, True),
    }


#: Recipe names a ``generated`` item may use, with the :mod:`cshape.variants` function each
#: calls (``base`` items pass the base mesh first; ``seed`` is passed as ``random_state``).
RECIPES = {
    "sphere": "cshape.variants.sphere",
    "torus": "cshape.variants.torus",
    "cube": "cshape.variants.cube",
    "eight": "cshape.variants.eight",
    "figure": "cshape.variants.articulated_figure (seed -> random_state)",
    "remesh": "cshape.variants.remesh (base mesh)",
    "subdivide": "cshape.variants.subdivide (base mesh)",
    "noise": "cshape.variants.add_normal_noise (base mesh, seed -> random_state)",
    "creature": "cshape.creatures.creature (seed -> random_state)",
}

#: Fields of a generated collection's ``generate`` mapping: the arguments of
#: :func:`cshape.creatures.creature_items`, which lists the items in place of ``items``.
GENERATE_FIELDS = ("seed", "members", "kinds", "params")


# ====================================================================== manifest schema
_STR, _INT, _DICT, _LIST = "str", "int", "dict", "list"

#: The manifest schema: fields every collection needs, and per kind the required and optional
#: collection fields and item fields (``type`` names: str, int, dict, list, "int|null", ...).
MANIFEST_SCHEMA = {
    "top": {"required": {"version": _INT, "collections": _LIST}},
    "collection": {
        "required": {
            "name": _STR, "kind": _STR, "description": _STR, "license": _STR, "citation": _STR,
        },
    },
    "kinds": {
        "generated": {
            "required": {},
            "optional": {"items": _LIST, "generate": _DICT},
            "item_required": {"name": _STR, "label": _STR, "recipe": _STR},
            "item_optional": {"params": _DICT, "seed": _INT, "base": _STR, "description": _STR},
        },
        "package": {
            "required": {"package": _STR, "path": _STR, "items": _LIST},
            "optional": {},
            "item_required": {"name": _STR, "label": _STR, "file": _STR},
            "item_optional": {"description": _STR},
        },
        "download": {
            "required": {"page": _STR, "format": _STR},
            "optional": {"items": _LIST, "layout": _STR, "path_env": _STR},
            "item_required": {
                "name": _STR, "label": _STR, "file": _STR, "url": _STR, "sha256": _STR,
                "size": _INT,
            },
            "item_optional": {"license": _STR, "author": _STR, "citation": _STR},
        },
        "local": {
            "required": {"path": _STR, "labels": _STR},
            "optional": {"path_env": _STR, "items": _LIST},
            "item_required": {"name": _STR, "label": _STR, "file": _STR},
            "item_optional": {},
        },
    },
}

_TYPES = {_STR: str, _INT: int, _DICT: dict, _LIST: list}


def _check_fields(obj, required, optional, where):
    if not isinstance(obj, dict):
        raise ValueError(f"{where}: expected a mapping of fields, got {type(obj).__name__}")
    for key, typ in required.items():
        if key not in obj or obj[key] is None:
            raise ValueError(f"{where}: missing required field {key!r} ({typ})")
    allowed = {**required, **optional}
    for key, value in obj.items():
        if key not in allowed:
            raise ValueError(
                f"{where}: unknown field {key!r}; allowed fields are {sorted(allowed)}"
            )
        typ = allowed[key]
        ok = isinstance(value, _TYPES[typ]) and not isinstance(value, bool)
        if not ok and not (value is None and key in optional):
            raise ValueError(
                f"{where}: field {key!r} must be a {typ}, got {type(value).__name__} {value!r}"
            )


def validate_manifest(doc, *, source="data_manifest.yaml") -> dict:
    """Check a parsed manifest against :data:`MANIFEST_SCHEMA`; return it keyed by name.

    Besides the fields and their types, checks that names are unique, kinds and layouts
    known, recipes and their parameter names exist in :mod:`cshape.variants`, ``base``
    references name an *earlier* generated item, and sha256 / url / size look right.

    Parameters
    ----------
    doc : dict
        As returned by ``yaml.safe_load``.
    source : str
        Shown in error messages.

    Returns
    -------
    dict
        ``{collection name: entry}``, in manifest order.

    Raises
    ------
    ValueError
        Naming the collection (and item) and the field at fault.
    """
    _check_fields(doc, MANIFEST_SCHEMA["top"]["required"], {}, source)
    recipes = _recipes()
    out: dict = {}
    for i, entry in enumerate(doc["collections"]):
        name = entry.get("name") if isinstance(entry, dict) else None
        where = f"{source}: collection {name!r} (entry {i})" if name else f"{source}: entry {i}"
        if not isinstance(entry, dict):
            raise ValueError(f"{where}: expected a mapping of fields")
        kind = entry.get("kind")
        if kind is not None and kind not in KINDS:
            raise ValueError(f"{where}: unknown kind {kind!r}; kind must be one of {KINDS}")
        base_required = MANIFEST_SCHEMA["collection"]["required"]
        spec = MANIFEST_SCHEMA["kinds"].get(kind, {"required": {}, "optional": {}})
        _check_fields(
            entry, {**base_required, **spec["required"]}, spec["optional"], where
        )
        if name in out:
            raise ValueError(f"{where}: duplicate collection name {name!r}")
        if not re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9_.-]*", name):
            raise ValueError(
                f"{where}: name must be letters, digits, '-', '_' or '.', got {name!r}"
            )
        if kind == "download":
            if ("items" in entry) == ("layout" in entry):
                raise ValueError(
                    f"{where}: a download collection needs either 'items' (files with url, "
                    "sha256, size) or 'layout' (a benchmark fetched by hand), not both or none"
                )
            if "layout" in entry and entry["layout"] not in LAYOUTS:
                raise ValueError(
                    f"{where}: unknown layout {entry['layout']!r}; layout must be one of {LAYOUTS}"
                )
        if kind == "generated":
            if ("items" in entry) == ("generate" in entry):
                raise ValueError(
                    f"{where}: a generated collection needs either 'items' (one recipe per "
                    "item) or 'generate' (a creature benchmark: seed, members, kinds, "
                    "params), not both or none"
                )
            if "generate" in entry:
                entry["items"] = _generate_items(entry["generate"], where)
        if kind == "package":
            rel = PurePosixPath(entry["path"])
            if rel.is_absolute() or ".." in rel.parts:
                raise ValueError(
                    f"{where}: field 'path' must be a folder inside package "
                    f"{entry['package']!r}, got {entry['path']!r}"
                )
        if kind == "local" and entry["labels"] != "subfolder" and not entry["labels"].endswith(
            ".csv"
        ):
            raise ValueError(
                f"{where}: field 'labels' must be 'subfolder' or the name of a CSV file, "
                f"got {entry['labels']!r}"
            )
        seen = set()
        for j, item in enumerate(entry.get("items") or []):
            iname = item.get("name") if isinstance(item, dict) else None
            iwhere = f"{where}, item {iname!r}" if iname else f"{where}, item {j}"
            _check_fields(item, spec["item_required"], spec["item_optional"], iwhere)
            if iname in seen:
                raise ValueError(f"{iwhere}: duplicate item name {iname!r}")
            if not re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9_.-]*", iname):
                # names become cache file names: no '/', '..' or hidden files
                raise ValueError(
                    f"{iwhere}: item name must be letters, digits, '-', '_' or '.' (starting "
                    f"with a letter or digit), got {iname!r}"
                )
            seen.add(iname)
            if kind == "generated":
                _check_recipe(item, recipes, out, entry, iwhere)
            if kind == "download":
                if not re.fullmatch(r"[0-9a-f]{64}", item["sha256"]):
                    raise ValueError(
                        f"{iwhere}: field 'sha256' must be 64 lowercase hex digits, "
                        f"got {item['sha256']!r}"
                    )
                if not item["url"].startswith("https://"):
                    raise ValueError(f"{iwhere}: field 'url' must be an https URL")
                if item["size"] <= 0:
                    raise ValueError(f"{iwhere}: field 'size' must be a positive byte count")
            if "file" in item:
                p = PurePosixPath(item["file"])
                if p.is_absolute() or ".." in p.parts:
                    raise ValueError(
                        f"{iwhere}: field 'file' must be a relative path inside the "
                        f"collection, got {item['file']!r}"
                    )
        out[name] = entry
    return out


def _generate_items(spec, where) -> list:
    """The items of a ``generate`` mapping (:func:`cshape.creatures.creature_items`)."""
    from .creatures import creature_items

    bad = sorted(set(spec) - set(GENERATE_FIELDS))
    if bad:
        raise ValueError(
            f"{where}: field 'generate' has unknown key(s) {bad}; its keys are "
            f"{list(GENERATE_FIELDS)}"
        )
    try:
        return creature_items(**spec)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{where}: field 'generate': {exc}") from None


def _check_recipe(item, recipes, done, entry, where):
    recipe = item["recipe"]
    if recipe not in recipes:
        raise ValueError(
            f"{where}: unknown recipe {recipe!r}; recipe must be one of {sorted(recipes)}"
        )
    fn, takes_base, takes_seed = recipes[recipe]
    sig = inspect.signature(fn)
    names = list(sig.parameters)
    allowed = set(names[1:] if takes_base else names) - {"random_state"}
    for key in item.get("params") or {}:
        if key not in allowed:
            raise ValueError(
                f"{where}: recipe {recipe!r} has no parameter {key!r}; "
                f"its parameters are {sorted(allowed)}"
            )
    if takes_base != ("base" in item):
        need = "needs a 'base' (collection/item)" if takes_base else "takes no 'base'"
        raise ValueError(f"{where}: recipe {recipe!r} {need}")
    if "seed" in item and not takes_seed:
        raise ValueError(f"{where}: recipe {recipe!r} is deterministic and takes no 'seed'")
    if takes_base:
        coll, _, iname = item["base"].partition("/")
        pool = {it["name"] for it in entry["items"][: entry["items"].index(item)]}
        known = pool if coll == entry["name"] else (
            {it["name"] for it in done[coll]["items"]}
            if coll in done and done[coll]["kind"] == "generated" else None
        )
        if known is None or iname not in known:
            raise ValueError(
                f"{where}: field 'base' must name an earlier generated item as "
                f"'collection/item', got {item['base']!r}"
            )


def load_manifest(path=None) -> dict:
    """Read and validate a manifest; return ``{collection name: entry}``.

    Parameters
    ----------
    path : str, os.PathLike or dict, optional
        The YAML file; default ``$CSHAPE_MANIFEST`` or the ``data_manifest.yaml`` shipped
        inside the package.  A dict is taken as an already parsed manifest.
        The file's folder is recorded (key ``_root`` of each entry) to resolve relative
        ``local`` paths.
    """
    if isinstance(path, dict):
        if "collections" in path:
            # a copy: the entries get a '_root' key, which must not change the caller's dict
            doc = copy.deepcopy(path)
            return _with_root(validate_manifest(doc, source="manifest"), Path.cwd())
        return path  # already validated
    import yaml

    p = Path(path or os.environ.get("CSHAPE_MANIFEST") or _DEFAULT_MANIFEST)
    if not p.is_file():
        raise FileNotFoundError(
            f"no data manifest at {str(p)!r}; pass manifest=PATH or set CSHAPE_MANIFEST"
        )
    with open(p, encoding="utf-8") as fh:
        try:
            doc = yaml.safe_load(fh)
        except yaml.YAMLError as exc:
            raise ValueError(f"{p.name}: not valid YAML ({exc})") from None
    return _with_root(validate_manifest(doc, source=p.name), p.resolve().parent)


def _with_root(entries, root):
    for e in entries.values():
        e.setdefault("_root", str(root))
    return entries


def _entry(name, manifest) -> dict:
    entries = load_manifest(manifest)
    if name not in entries:
        raise ValueError(
            f"unknown collection {name!r}; known collections are {list(entries)} "
            "(see `cshape data list`)"
        )
    return entries[name]


def list_collections(manifest=None) -> list[str]:
    """Names of the collections in the manifest, in manifest order.

    Examples
    --------
    >>> import cshape.data
    >>> "paper-models" in cshape.data.list_collections()
    True
    """
    return list(load_manifest(manifest))


def info(name, manifest=None) -> dict:
    """The manifest entry of collection ``name`` (description, kind, license, items, ...)."""
    return {k: v for k, v in _entry(name, manifest).items() if not k.startswith("_")}


# ====================================================================== cache
def cache_dir(path=None) -> Path:
    """The cache folder: ``path``, else ``$CSHAPE_CACHE``, else the user cache folder.

    The user cache folder is ``platformdirs.user_cache_dir('cshape')`` when platformdirs is
    installed, else ``$XDG_CACHE_HOME/cshape`` or ``~/.cache/cshape``.  Not created here.
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


def _pymeshlab_version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("pymeshlab")
    except PackageNotFoundError:  # pragma: no cover
        return "unknown"


def _recipe_record(entries, coll, item) -> dict:
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


def _key(record) -> str:
    blob = json.dumps(record, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(blob.encode()).hexdigest()[:16]


def _find_item(entry, name):
    for it in entry.get("items") or []:
        if it["name"] == name:
            return it
    names = [it["name"] for it in entry.get("items") or []]
    raise ValueError(f"collection {entry['name']!r} has no item {name!r}; items are {names}")


def _make_cache_folder(folder: Path) -> None:
    """Create a cache folder, or raise an OSError that says which folder and what to do."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        blocker = next((q for q in [folder, *folder.parents] if q.exists()), None)
        why = (
            f"{str(blocker)!r} is a file, not a folder"
            if blocker is not None and not blocker.is_dir()
            else exc.strerror or str(exc)
        )
        raise type(exc)(
            exc.errno,
            f"cannot create the cache folder {str(folder)!r}: {why}; pass cache_dir= or set "
            "CSHAPE_CACHE to a writable folder",
        ) from None


def _atomic_save_npz(path: Path, **arrays) -> None:
    """Write ``arrays`` to ``path`` as .npz via a temporary file and ``os.replace``.

    On any failure (disk full, read-only folder, interrupt) the temporary file is removed
    and ``path`` is left as it was; an ``OSError`` names the file and says what to do.
    """
    _make_cache_folder(path.parent)
    try:
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    except OSError as exc:
        raise type(exc)(
            exc.errno,
            f"cannot write to the cache folder {str(path.parent)!r} ({exc.strerror}); pass "
            "cache_dir= or set CSHAPE_CACHE to a writable folder",
        ) from None
    try:
        with os.fdopen(fd, "wb") as fh:
            np.savez(fh, **arrays)
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600; use the usual permissions
        os.replace(tmp, path)
    except BaseException as exc:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        if isinstance(exc, OSError) and exc.errno in (errno.ENOSPC, errno.EDQUOT):
            raise OSError(
                exc.errno,
                f"no space left to write the cache file {str(path)!r} ({exc.strerror}); "
                "nothing was written. Free disk space, or pass cache_dir= / set CSHAPE_CACHE "
                "to a folder on another disk",
            ) from None
        raise


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _read_npz(path: Path, record=None) -> Mesh:
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


def _cache_file(entries, coll, item, root: Path) -> Path:
    key = _key(_recipe_record(entries, coll, item))
    return root / "generated" / coll / f"{item['name']}-{key}.npz"


def _generated_mesh(entries, coll, item, root: Path) -> tuple[Mesh, bool]:
    """Return (mesh, built) for a generated item, from the cache or by building it."""
    path = _cache_file(entries, coll, item, root)
    record = _recipe_record(entries, coll, item)
    if path.is_file():
        try:
            return _read_npz(path, record), False
        except (OSError, ValueError, KeyError) as exc:
            warnings.warn(f"rebuilding unreadable cache file {path} ({exc})", stacklevel=3)
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
    return mesh, True


# ====================================================================== paths
def _env_path(entry) -> Path | None:
    env = entry.get("path_env")
    if env and os.environ.get(env):
        return Path(os.environ[env]).expanduser()
    return None


def collection_path(name, *, cache_dir=None, manifest=None) -> Path:
    """Where collection ``name`` lives on disk (it may not exist yet).

    generated: ``<cache>/generated/<name>``; download: ``$<path_env>`` if set, else
    ``<cache>/downloads/<name>``; package: the folder inside the installed package;
    local: ``$<path_env>`` if set, else ``path`` relative to the manifest's folder.
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


def _cache_root(path) -> Path:
    return cache_dir(path)


# ====================================================================== loading
def load_collection(
    name, *, cache_dir=None, download=False, progress=None, manifest=None, n_jobs=1
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

    Returns
    -------
    Collection
        ``.names``, ``.labels``, ``.meshes``; items by position or name.  Generated meshes are
        built (or read from the cache) now; files of the other kinds load on first access.
    """
    entries = load_manifest(manifest)
    entry = _entry(name, entries)
    kind = entry["kind"]
    meta = {k: v for k, v in entry.items() if not k.startswith("_")}
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


def _build_one(task) -> None:
    entries, coll, item, root = task
    _generated_mesh(entries, coll, item, Path(root))


def _build_in_processes(entries, name, root, n_jobs, progress) -> None:
    """Build the missing items of a generated collection (those without a base) in
    ``n_jobs`` processes; each writes its cache file atomically, as a serial build does."""
    if isinstance(n_jobs, bool) or not isinstance(n_jobs, int) or n_jobs < 1:
        raise ValueError(f"n_jobs must be an integer >= 1 (worker processes), got {n_jobs!r}")
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


def load(name, item, *, cache_dir=None, download=False, manifest=None) -> Mesh:
    """One mesh of a collection, e.g. ``load("paper-models", "CM")``.

    Parameters
    ----------
    name : str
        The collection.
    item : str
        The item's name (``load_collection(name).names``).
    cache_dir, download, manifest
        As for :func:`load_collection`.

    Returns
    -------
    Mesh
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


def load_creatures(seed=1, members=10, kinds=None, *, cache_dir=None, progress=None,
                   n_jobs=1, **params) -> Collection:
    """An instance of the creature benchmark (:mod:`cshape.creatures`) for any seed.

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
        Classes (default all of :data:`cshape.creatures.CREATURE_KINDS`).
    cache_dir, progress, n_jobs
        As for :func:`load_collection`.
    **params
        Passed to :func:`cshape.creatures.creature` for every item (``variation``,
        ``vertices``, ``noise``, ``voxelsize``).

    Returns
    -------
    Collection
        Named ``creatures-seed<seed>``; items ``<kind>-<k>``, labels the class.

    Examples
    --------
    >>> import cshape.data
    >>> small = cshape.data.load_creatures(0, members=2, kinds=["snake", "teddy"],
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
        "citation": "cshape.creatures.creature, built with PyMeshLab",
    }]}
    return load_collection(name, cache_dir=cache_dir, progress=progress, manifest=doc,
                           n_jobs=n_jobs)


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


class _NoBar:
    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    def update(self, n=1):
        pass


def _progress(total, desc, progress):
    if progress is False:
        return _NoBar()
    try:
        from tqdm.auto import tqdm
    except ImportError:  # pragma: no cover - tqdm is a dependency
        return _NoBar()
    return tqdm(total=total, desc=desc, unit="mesh", delay=0.5, disable=None if progress is None
                else not progress, leave=False)


# ====================================================================== local folders
def _mesh_files(folder: Path) -> list[Path]:
    """Mesh files under ``folder`` (also ``.gz``-compressed ones), sorted; hidden skipped."""
    return sorted(
        p for p in folder.rglob("*")
        if p.is_file() and _suffix(p) in MESH_SUFFIXES + (".vert",)
        and not any(part.startswith(".") for part in p.relative_to(folder).parts)
    )


def _suffix(p) -> str:
    """The format suffix of a mesh file, looking through ``.gz`` (``a.off.gz`` -> ``.off``)."""
    return split_mesh_name(p)[1]


def _stem(p) -> str:
    """The name of a mesh file without ``.gz`` and its format suffix."""
    return split_mesh_name(p)[0]


def _item_names(rels: list[PurePosixPath]) -> list[str]:
    stems = [_stem(r) for r in rels]
    unique = len(set(stems)) == len(stems)
    return stems if unique else [str(r.parent / _stem(r)) for r in rels]


def load_folder(folder, labels="subfolder", *, name=None) -> Collection:
    """Read a folder of meshes as a collection with class labels.

    Parameters
    ----------
    folder : str or os.PathLike
        Searched recursively for ``.obj``, ``.off``, ``.ply``, ``.stl`` files, also
        gzip-compressed (``.off.gz``, ...), and TOSCA ``.vert`` files; hidden files and
        folders are skipped.
    labels : str, default='subfolder'
        ``'subfolder'``: the label of a file is the first sub-folder it is in (files directly
        in ``folder`` get the folder's own name).  Otherwise the name of a CSV file (relative
        to ``folder``, or absolute) with a header and the columns ``file`` (path relative to
        ``folder``) and ``label``, and optionally ``name``; only the files it lists are read.
    name : str, optional
        Collection name (default: the folder's name).

    Returns
    -------
    Collection
        Items named by file stem (by relative path when stems repeat), meshes loaded lazily
        with :func:`cshape.load_mesh`.

    Raises
    ------
    FileNotFoundError
        If the folder, the CSV or a file it lists does not exist.
    ValueError
        If the folder holds no mesh or the CSV lacks a ``file`` or ``label`` column.
    """
    folder = Path(folder).expanduser()
    if not folder.is_dir():
        raise FileNotFoundError(f"no folder {str(folder)!r} to read meshes from")
    cname = name or folder.name
    if labels == "subfolder":
        files = [p for p in _mesh_files(folder) if _suffix(p) != ".vert"]
        if not files:
            raise ValueError(
                f"folder {str(folder)!r} holds no mesh file ({', '.join(MESH_SUFFIXES)}, "
                "each also .gz)"
            )
        rels = [PurePosixPath(p.relative_to(folder).as_posix()) for p in files]
        labs = [r.parts[0] if len(r.parts) > 1 else folder.name for r in rels]
        names = _item_names(rels)
    else:
        csv_path = Path(labels)
        csv_path = csv_path if csv_path.is_absolute() else folder / csv_path
        if not csv_path.is_file():
            raise FileNotFoundError(
                f"labels CSV {str(csv_path)!r} not found; pass labels='subfolder' or a CSV "
                "with columns file,label"
            )
        with open(csv_path, newline="", encoding="utf-8") as fh:
            rows = list(csv.DictReader(fh))
        cols = set(rows[0]) if rows else set()
        if not {"file", "label"} <= cols:
            raise ValueError(
                f"labels CSV {str(csv_path)!r} must have a header with columns 'file' and "
                f"'label' (and optionally 'name'), got {sorted(cols)}"
            )
        files, labs = [], []
        for i, r in enumerate(rows, 2):
            rel = PurePosixPath((r["file"] or "").replace("\\", "/"))
            if not r["file"] or rel.is_absolute() or ".." in rel.parts:
                raise ValueError(
                    f"labels CSV {csv_path.name!r}, line {i}: file {r['file']!r} must be a "
                    f"relative path inside {str(folder)!r}"
                )
            p = folder / r["file"]
            if not p.is_file():
                raise FileNotFoundError(
                    f"labels CSV {csv_path.name!r} lists {r['file']!r}, not found in "
                    f"{str(folder)!r}"
                )
            files.append(p)
            labs.append(r["label"])
        rels = [PurePosixPath(p.relative_to(folder).as_posix()) for p in files]
        names = [r.get("name") or n for r, n in zip(rows, _item_names(rels), strict=True)]
    items = [
        Item(n, lab, cname, {"file": str(r)}, _load=_file_loader(p))
        for n, lab, r, p in zip(names, labs, rels, files, strict=True)
    ]
    return Collection(cname, items, {"name": cname, "kind": "local", "path": str(folder)})


# ====================================================================== benchmark layouts
_MCGILL_GROUPS = {"articulated", "nonarticulated", "non-articulated", "non_articulated"}
_MCGILL_SKIP = {"ply", "off", "obj", "im", "models", "mesh", "meshes"}


def read_mcgill(folder) -> Collection:
    """Read the McGill 3D Shape Benchmark as unpacked from its per-class archives.

    Layout: one folder per class (``ants/``, ``crabs/``, ``teddy-bears/``, ...), possibly
    under ``articulated/`` and ``nonarticulated/`` group folders, with the meshes (``.ply``;
    ``.off`` and ``.obj`` also read) at any depth below, e.g. ``ants/Ply/b1.ply``.  The label
    is the class folder's name; medial-surface files (``.im``) are ignored.
    """
    folder = Path(folder)
    files = [p for p in _mesh_files(folder) if _suffix(p) in (".ply", ".off", ".obj")]
    if not files:
        raise ValueError(f"no McGill .ply meshes under {str(folder)!r} (one folder per class)")
    rels, labs = [], []
    for p in files:
        rel = PurePosixPath(p.relative_to(folder).as_posix())
        parts = [q for q in rel.parts[:-1] if q.lower() not in _MCGILL_GROUPS]
        parts = [q for q in parts if q.lower() not in _MCGILL_SKIP] or [folder.name]
        rels.append(rel)
        labs.append(parts[0])
    names = [f"{lab}/{_stem(r)}" for lab, r in zip(labs, rels, strict=True)]
    if len(set(names)) < len(names):
        names = [str(r.parent / _stem(r)) for r in rels]
    items = [Item(n, lab, "mcgill-3dsb", {"file": str(r)}, _load=_file_loader(p))
             for n, lab, r, p in zip(names, labs, rels, files, strict=True)]
    return Collection("mcgill-3dsb", items, {"layout": "mcgill", "path": str(folder)})


def read_vert_tri(vert_path) -> Mesh:
    """Read a TOSCA mesh: ``NAME.vert`` (x y z per line) and ``NAME.tri`` (1-based triangles)."""
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


def read_tosca(folder) -> Collection:
    """Read TOSCA (high-resolution) as unpacked from ``toscahires-asci.zip``.

    Layout: ``cat0.vert`` + ``cat0.tri``, ``centaur1.vert`` + ..., at any depth (``.off``
    copies are read too when there is no ``.vert``).  Label: the name without its trailing
    pose number (``cat``, ``centaur``, ``david``, ``dog``, ``gorilla``, ``horse``,
    ``michael``, ``victoria``, ``wolf``).
    """
    folder = Path(folder)
    files = _mesh_files(folder)
    verts = {p.stem: p for p in files if p.suffix.lower() == ".vert"}
    offs = {_stem(p): p for p in files if _suffix(p) == ".off" and _stem(p) not in verts}
    chosen = {**offs, **verts}
    if not chosen:
        raise ValueError(f"no TOSCA .vert/.tri (or .off) meshes under {str(folder)!r}")
    items = []
    for stem in sorted(chosen, key=_natural_key):
        label = re.sub(r"\d+$", "", stem) or stem
        p = chosen[stem]
        items.append(Item(stem, label, "tosca", {"file": p.name}, _load=_file_loader(p)))
    return Collection("tosca", items, {"layout": "tosca", "path": str(folder)})


#: SHREC'07 watertight classes, in order: models 20k+1 ... 20k+20 belong to class k.
SHREC07_CLASSES = (
    "human", "cup", "glasses", "airplane", "ant", "chair", "octopus", "table", "teddy", "hand",
    "plier", "fish", "bird", "spring", "armadillo", "bust", "mech", "bearing", "vase", "fourleg",
)


def read_shrec07(folder) -> Collection:
    """Read the SHREC'07 watertight track: ``1.off`` ... ``400.off`` at any depth.

    Model ``n`` belongs to class ``SHREC07_CLASSES[(n - 1) // 20]``; files not named by a
    number from 1 to 400 are ignored.
    """
    folder = Path(folder)
    found = {}
    for p in _mesh_files(folder):
        if _suffix(p) == ".off" and _stem(p).isdigit() and 1 <= int(_stem(p)) <= 400:
            found[int(_stem(p))] = p
    if not found:
        raise ValueError(f"no SHREC'07 meshes 1.off ... 400.off under {str(folder)!r}")
    items = [
        Item(str(n), SHREC07_CLASSES[(n - 1) // 20], "shrec07-watertight",
             {"file": found[n].name}, _load=_file_loader(found[n]))
        for n in sorted(found)
    ]
    return Collection("shrec07-watertight", items, {"layout": "shrec07", "path": str(folder)})


def _natural_key(s):
    return [int(t) if t.isdigit() else t for t in re.split(r"(\d+)", s)]


_LAYOUT_READERS = {"mcgill": read_mcgill, "tosca": read_tosca, "shrec07": read_shrec07}


def _manual_message(entry, folder) -> str:
    env = entry.get("path_env")
    return (
        f"collection {entry['name']!r} is not on this machine: its terms ({entry['license']}) "
        f"mean cshape does not download it.  Get it from {entry['page']} ({entry['format']}), "
        f"then unpack it into {str(folder)!r}"
        + (f" or set {env} to its folder" if env else "")
        + f", or run `cshape data build {entry['name']} --archive FILE`."
    )


# ====================================================================== downloads
def extract_archive(archive, target) -> Path:
    """Unpack a .zip or .tar(.gz/.bz2/.xz) archive into ``target``, refusing to escape it.

    Members with absolute paths, ``..`` components, or (for tar) links and device files are
    rejected before anything is written; the archive is unpacked into a temporary folder
    beside ``target`` and moved into place, so a failure leaves ``target`` as it was.

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


def fetch(name, *, items=None, cache_dir=None, progress=True, manifest=None) -> list[Path]:
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
    cache_dir : optional
        Cache folder (default :func:`cache_dir`).
    progress : bool, default=True
        pooch's progress bar per file.

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


def _download_error(exc, collection, item) -> Exception:
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


@contextlib.contextmanager
def _removing_new_folders(folder):
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


def build(name, *, cache_dir=None, progress=None, archive=None, manifest=None) -> Path:
    """Make a collection available offline and return its folder.

    generated: build every missing item into the cache; download (pinned files): fetch them;
    download (benchmark): unpack ``archive`` (a file you downloaded by hand) into place with
    :func:`extract_archive`, then check it reads; package / local: check every file reads.
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
