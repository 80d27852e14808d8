"""The data manifest: its records (:class:`Item`, :class:`Collection`), the recipes that
generate shapes, the schema and :func:`validate_manifest`, and look-ups by name.
"""

from __future__ import annotations

import copy
import inspect
import os
import re
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path, PurePosixPath
from typing import Any, TypeAlias

from ..mesh import Mesh

#: A collection's manifest entry, and the validated manifest: ``{collection name: entry}``.
Entry: TypeAlias = dict[str, Any]
Entries: TypeAlias = dict[str, Entry]
#: Where a manifest comes from: a YAML file, an already parsed manifest, or None (the default).
ManifestSource: TypeAlias = "str | os.PathLike[str] | dict[str, Any] | None"
#: A recipe: ``(function, takes a base mesh, takes a seed)``.
Recipe: TypeAlias = tuple[Callable[..., Mesh], bool, bool]

KINDS = ("generated", "package", "download", "local")
LAYOUTS = ("mcgill", "tosca", "shrec07")

#: Bumped whenever a recipe's output changes, so stale cache files are not reused.
RECIPES_VERSION = 3

#: The manifest shipped inside the package.  In a source checkout ``cshape/data/data_manifest.yaml``
#: is a symbolic link to the top-level ``data_manifest.yaml`` (the one file to edit); the
#: wheel stores the file itself (``[tool.setuptools.package-data]`` in pyproject.toml).
_DEFAULT_MANIFEST = Path(__file__).resolve().parent / "data_manifest.yaml"

#: The validated manifests read from files: ``{resolved path: (text, entries)}``.  A file is
#: parsed and checked again when its text changes; each call gets its own copy.
_READ: dict[str, tuple[str, Entries]] = {}


# ====================================================================== records
@dataclass(eq=False)
class Item:
    """One mesh of a collection: its name, class label and (lazily loaded) mesh.

    Parameters
    ----------
    name : str
        Unique within the collection.
    label : str
        Class label (for classification and MDS colouring).
    collection : str, default=''
        Name of the collection.
    meta : dict, optional
        The manifest entry of the item (recipe, params, seed, file, license, ...).
    _load : callable, optional
        Returns the mesh; called on the first access to :attr:`mesh`.  The collection
        readers set it.

    Attributes
    ----------
    mesh : Mesh
        Loaded on first access and kept.
    path : Path or None
        The file it is read from (a generated item's cache file).
    """

    name: str
    label: str
    collection: str = ""
    meta: dict[str, Any] = field(default_factory=dict, repr=False)
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

    Parameters
    ----------
    name : str
        Name of the collection.
    items : list of Item
        Its meshes, in order.
    info : dict, optional
        The manifest entry (description, license, citation, ...).
    """

    name: str
    items: list[Item]
    info: dict[str, Any] = field(default_factory=dict, repr=False)

    def __len__(self) -> int:
        return len(self.items)

    def __iter__(self) -> Iterator[Item]:
        return iter(self.items)

    def __getitem__(self, key: int | str) -> Item:
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
def _recipes() -> dict[str, Recipe]:
    from .. import shapes
    from . import variants as v
    from .bodies import articulated_figure
    from .creatures import creature
    from .poses import pose, pose_template
    from .suite import identity_pose, resolution_shape

    return {
        # name: (function, takes a base mesh, takes a seed)
        "sphere": (shapes.icosphere, False, False),
        "torus": (shapes.torus, False, False),
        "cube": (_centred_cube, False, False),
        "eight": (v.eight, False, False),
        "figure": (articulated_figure, False, True),
        "remesh": (v.remesh, True, False),
        "subdivide": (v.subdivide, True, False),
        "noise": (v.add_normal_noise, True, True),
        "creature": (creature, False, True),
        "pose-template": (pose_template, False, False),
        "pose": (pose, True, True),
        "identity": (identity_pose, False, True),
        "resolution": (resolution_shape, False, True),
    }


def _centred_cube(n: int = 16, size: float = 1.0) -> Mesh:
    """Return :func:`cshape.shapes.cube` moved to be centred at the origin, as the paper models."""
    from .. import shapes

    mesh = shapes.cube(n, size)
    V = mesh.vertices
    return Mesh(V - 0.5 * (V.min(axis=0) + V.max(axis=0)), mesh.faces)


#: Recipe names a ``generated`` item may use, with the function each calls (``base`` items
#: pass the base mesh first; ``seed`` is passed as ``random_state``).
RECIPES = {
    "sphere": "cshape.shapes.icosphere",
    "torus": "cshape.shapes.torus",
    "cube": "cshape.shapes.cube, centred at the origin",
    "eight": "cshape.data.variants.eight",
    "figure": "cshape.data.bodies.articulated_figure (seed -> random_state)",
    "remesh": "cshape.data.variants.remesh (base mesh)",
    "subdivide": "cshape.data.variants.subdivide (base mesh)",
    "noise": "cshape.data.variants.add_normal_noise (base mesh, seed -> random_state)",
    "creature": "cshape.data.creatures.creature (seed -> random_state)",
    "pose-template": "cshape.data.poses.pose_template",
    "pose": "cshape.data.poses.pose (base: the template, seed -> random_state)",
    "identity": "cshape.data.suite.identity_pose (seed -> random_state: the identity)",
    "resolution": "cshape.data.suite.resolution_shape (seed -> random_state: the creature)",
}

#: Fields of a generated collection's ``generate`` mapping, per ``benchmark`` (default
#: 'creatures'): the arguments of the function that lists the items in place of ``items``
#: (:func:`cshape.data.creatures.creature_items`, :func:`cshape.data.suite.identity_items`,
#: :func:`cshape.data.suite.resolution_items`).
GENERATE_BENCHMARKS = {
    "creatures": ("seed", "members", "kinds", "params"),
    "identities": ("seed", "identities", "poses", "resolutions", "kinds", "params"),
    "resolutions": ("seed", "members", "kinds", "levels", "params"),
}
GENERATE_FIELDS = ("benchmark", *dict.fromkeys(
    f for fields in GENERATE_BENCHMARKS.values() for f in fields))


# ====================================================================== manifest schema
_STR, _INT, _DICT, _LIST = "str", "int", "dict", "list"

#: The manifest schema: fields every collection needs, and per kind the required and optional
#: collection fields and item fields (``type`` names: str, int, dict, list, "int|null", ...).
MANIFEST_SCHEMA: dict[str, Any] = {
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


def _check_fields(obj: Any, required: Mapping[str, str], optional: Mapping[str, str],
                  where: str) -> None:
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


def validate_manifest(doc: dict[str, Any], *, source: str = "data_manifest.yaml") -> Entries:
    """Check a parsed manifest against :data:`MANIFEST_SCHEMA`; return it keyed by name.

    Besides the fields and their types, checks that names are unique, kinds and layouts
    known, recipes and their parameter names exist (:data:`RECIPES`), ``base``
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
    out: Entries = {}
    for i, entry in enumerate(doc["collections"]):
        name = entry.get("name") if isinstance(entry, dict) else None
        where = f"{source}: collection {name!r} (entry {i})" if name else f"{source}: entry {i}"
        if not isinstance(entry, dict):
            raise ValueError(f"{where}: expected a mapping of fields")
        spec = _check_collection(entry, out, where)
        seen: set[str] = set()
        for j, item in enumerate(entry.get("items") or []):
            _check_item(item, j, entry, spec, recipes, out, seen, where)
        out[entry["name"]] = entry
    return out


#: What a collection's name and its items' names may be (they become folder and cache file
#: names: no '/', '..' or hidden files).
_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]*")


def _check_collection(entry: Entry, done: Entries, where: str) -> dict[str, Any]:
    """Check a collection's fields, name and the rules of its kind (a ``generate``
    mapping becomes its ``items``); return the schema of its kind."""
    kind = entry.get("kind")
    if kind is not None and kind not in KINDS:
        raise ValueError(f"{where}: unknown kind {kind!r}; kind must be one of {KINDS}")
    base_required = MANIFEST_SCHEMA["collection"]["required"]
    spec: dict[str, Any] = MANIFEST_SCHEMA["kinds"].get(kind, {"required": {}, "optional": {}})
    _check_fields(entry, {**base_required, **spec["required"]}, spec["optional"], where)
    name: str = entry["name"]
    if name in done:
        raise ValueError(f"{where}: duplicate collection name {name!r}")
    if not _NAME.fullmatch(name):
        raise ValueError(
            f"{where}: name must be letters, digits, '-', '_' or '.', got {name!r}"
        )
    _KIND_RULES[entry["kind"]](entry, where)
    return spec


def _check_download(entry: Entry, where: str) -> None:
    if ("items" in entry) == ("layout" in entry):
        raise ValueError(
            f"{where}: a download collection needs either 'items' (files with url, "
            "sha256, size) or 'layout' (a benchmark fetched by hand), not both or none"
        )
    if "layout" in entry and entry["layout"] not in LAYOUTS:
        raise ValueError(
            f"{where}: unknown layout {entry['layout']!r}; layout must be one of {LAYOUTS}"
        )


def _check_generated(entry: Entry, where: str) -> None:
    if (entry.get("items") is None) == (entry.get("generate") is None):
        raise ValueError(
            f"{where}: a generated collection needs either 'items' (one recipe per "
            "item) or 'generate' (a generated benchmark: benchmark, seed, members, kinds, "
            "params), not both or none"
        )
    if entry.get("generate") is not None:
        entry["items"] = _generate_items(entry["generate"], where)


def _check_package(entry: Entry, where: str) -> None:
    rel = PurePosixPath(entry["path"])
    if rel.is_absolute() or ".." in rel.parts:
        raise ValueError(
            f"{where}: field 'path' must be a folder inside package "
            f"{entry['package']!r}, got {entry['path']!r}"
        )


def _check_local(entry: Entry, where: str) -> None:
    if entry["labels"] != "subfolder" and not entry["labels"].endswith(".csv"):
        raise ValueError(
            f"{where}: field 'labels' must be 'subfolder' or the name of a CSV file, "
            f"got {entry['labels']!r}"
        )


#: The rules of each kind beyond its fields (:func:`validate_manifest`).
_KIND_RULES: dict[str, Callable[[Entry, str], None]] = {
    "generated": _check_generated,
    "package": _check_package,
    "download": _check_download,
    "local": _check_local,
}


def _check_item(item: Any, j: int, entry: Entry, spec: dict[str, Any],
                recipes: dict[str, Recipe], done: Entries, seen: set[str], where: str) -> None:
    """Check item ``j`` of a collection: its fields, a unique name, and its recipe, file
    and checksum as its kind needs (``seen``: the item names before it, gets its name)."""
    given = item.get("name") if isinstance(item, dict) else None
    iwhere = f"{where}, item {given!r}" if given else f"{where}, item {j}"
    _check_fields(item, spec["item_required"], spec["item_optional"], iwhere)
    iname: str = item["name"]
    if iname in seen:
        raise ValueError(f"{iwhere}: duplicate item name {iname!r}")
    if not _NAME.fullmatch(iname):
        raise ValueError(
            f"{iwhere}: item name must be letters, digits, '-', '_' or '.' (starting "
            f"with a letter or digit), got {iname!r}"
        )
    seen.add(iname)
    if entry["kind"] == "generated":
        _check_recipe(item, recipes, done, entry, iwhere)
    if entry["kind"] == "download":
        _check_download_item(item, iwhere)
    if "file" in item:
        p = PurePosixPath(item["file"])
        if p.is_absolute() or ".." in p.parts:
            raise ValueError(
                f"{iwhere}: field 'file' must be a relative path inside the "
                f"collection, got {item['file']!r}"
            )


def _check_download_item(item: dict[str, Any], where: str) -> None:
    """A downloaded file's checksum, address and size."""
    if not re.fullmatch(r"[0-9a-f]{64}", item["sha256"]):
        raise ValueError(
            f"{where}: field 'sha256' must be 64 lowercase hex digits, "
            f"got {item['sha256']!r}"
        )
    if not item["url"].startswith("https://"):
        raise ValueError(f"{where}: field 'url' must be an https URL")
    if item["size"] <= 0:
        raise ValueError(f"{where}: field 'size' must be a positive byte count")


def _generate_items(spec: Mapping[str, Any], where: str) -> list[dict[str, Any]]:
    """The items of a ``generate`` mapping (see :data:`GENERATE_BENCHMARKS`)."""
    from .creatures import creature_items
    from .suite import identity_items, resolution_items

    spec = dict(spec)
    benchmark = spec.pop("benchmark", "creatures")
    if benchmark not in GENERATE_BENCHMARKS:
        raise ValueError(
            f"{where}: field 'generate': benchmark must be one of "
            f"{sorted(GENERATE_BENCHMARKS)}, got {benchmark!r}"
        )
    fields = GENERATE_BENCHMARKS[benchmark]
    bad = sorted(set(spec) - set(fields))
    if bad:
        raise ValueError(
            f"{where}: field 'generate' has unknown key(s) {bad}; its keys are "
            f"{['benchmark', *fields]}"
        )
    makers: dict[str, Callable[..., list[dict[str, Any]]]] = {
        "creatures": creature_items, "identities": identity_items,
        "resolutions": resolution_items}
    make = makers[benchmark]
    try:
        return make(**spec)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{where}: field 'generate': {exc}") from None


def _check_recipe(item: dict[str, Any], recipes: dict[str, Recipe], done: Entries,
                  entry: Entry, where: str) -> None:
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


def load_manifest(path: ManifestSource = None) -> Entries:
    """Read and validate a manifest; return ``{collection name: entry}``.

    Parameters
    ----------
    path : str, os.PathLike or dict, optional
        The YAML file; default ``$CSHAPE_MANIFEST`` or the ``data_manifest.yaml`` shipped
        inside the package.  A dict is taken as an already parsed manifest.
        The file's folder is recorded (key ``_root`` of each entry) to resolve relative
        ``local`` paths.  A file read before is parsed and validated again only when its
        text has changed.

    Returns
    -------
    dict of str to dict
        ``{collection name: entry}``, in manifest order.
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
    where, text = p.resolve(), p.read_text(encoding="utf-8")
    known = _READ.get(str(where))
    if known is None or known[0] != text:
        try:  # libyaml's parser where PyYAML has it, else PyYAML's own
            doc = yaml.load(text, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))
        except yaml.YAMLError as exc:
            raise ValueError(f"{p.name}: not valid YAML ({exc})") from None
        known = (text, _with_root(validate_manifest(doc, source=p.name), where.parent))
        _READ[str(where)] = known
    return copy.deepcopy(known[1])


def _with_root(entries: Entries, root: str | os.PathLike[str]) -> Entries:
    for e in entries.values():
        e.setdefault("_root", str(root))
    return entries


def _entry(name: str, manifest: ManifestSource) -> Entry:
    entries = load_manifest(manifest)
    if name not in entries:
        raise ValueError(
            f"unknown collection {name!r}; known collections are {list(entries)} "
            "(see `cshape data list`)"
        )
    return entries[name]


def list_collections(manifest: ManifestSource = None) -> list[str]:
    """Return the names of the collections in the manifest, in manifest order.

    Parameters
    ----------
    manifest : path or dict, optional
        Another manifest (default :func:`load_manifest`).

    Returns
    -------
    list of str
        The collection names.

    Examples
    --------
    >>> import cshape.data
    >>> "paper-models" in cshape.data.list_collections()
    True
    """
    return list(load_manifest(manifest))


def info(name: str, manifest: ManifestSource = None) -> dict[str, Any]:
    """Return the manifest entry of collection ``name`` (description, kind, license, items, ...).

    Parameters
    ----------
    name : str
        A collection of the manifest (:func:`list_collections`).
    manifest : path or dict, optional
        Another manifest (default :func:`load_manifest`).

    Returns
    -------
    dict
        The entry, as :func:`load_manifest` validated it.
    """
    return {k: v for k, v in _entry(name, manifest).items() if not k.startswith("_")}


def _find_item(entry: Entry, name: str) -> dict[str, Any]:
    for it in entry.get("items") or []:
        if it["name"] == name:
            return it
    names = [it["name"] for it in entry.get("items") or []]
    raise ValueError(f"collection {entry['name']!r} has no item {name!r}; items are {names}")
