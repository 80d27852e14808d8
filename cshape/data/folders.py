"""Meshes in folders: any folder of meshes (:func:`load_folder`) and the folder layouts of
the classic benchmarks (McGill, TOSCA, SHREC'07).
"""

from __future__ import annotations

import csv
import re
from pathlib import Path, PurePosixPath
from typing import TYPE_CHECKING, Any

from ..readers import MESH_SUFFIXES, split_mesh_name
from .files import _file_loader
from .manifest import Collection, Item

if TYPE_CHECKING:
    import os


# ====================================================================== local folders
def _mesh_files(folder: Path) -> list[Path]:
    """Mesh files under ``folder`` (also ``.gz``-compressed ones), sorted; hidden skipped."""
    return sorted(
        p for p in folder.rglob("*")
        if p.is_file() and _suffix(p) in MESH_SUFFIXES + (".vert",)
        and not any(part.startswith(".") for part in p.relative_to(folder).parts)
    )


def _suffix(p: str | os.PathLike[str]) -> str:
    """The format suffix of a mesh file, looking through ``.gz`` (``a.off.gz`` -> ``.off``)."""
    return split_mesh_name(p)[1]


def _stem(p: str | os.PathLike[str]) -> str:
    """The name of a mesh file without ``.gz`` and its format suffix."""
    return split_mesh_name(p)[0]


def _item_names(rels: list[PurePosixPath]) -> list[str]:
    stems = [_stem(r) for r in rels]
    unique = len(set(stems)) == len(stems)
    return stems if unique else [str(r.parent / _stem(r)) for r in rels]


def load_folder(folder: str | os.PathLike[str], labels: str | os.PathLike[str] = "subfolder", *,
                name: str | None = None) -> Collection:
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


def read_mcgill(folder: str | os.PathLike[str]) -> Collection:
    """Read the McGill 3D Shape Benchmark as unpacked from its per-class archives.

    Layout: one folder per class (``ants/``, ``crabs/``, ``teddy-bears/``, ...), possibly
    under ``articulated/`` and ``nonarticulated/`` group folders, with the meshes (``.ply``;
    ``.off`` and ``.obj`` also read) at any depth below, e.g. ``ants/Ply/b1.ply``.  The label
    is the class folder's name; medial-surface files (``.im``) are ignored.

    Parameters
    ----------
    folder : str or os.PathLike
        The unpacked benchmark.

    Returns
    -------
    Collection
        Named ``mcgill-3dsb``; every mesh found, labelled by its class folder, loaded on
        first access.
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




def read_tosca(folder: str | os.PathLike[str]) -> Collection:
    """Read TOSCA (high-resolution) as unpacked from ``toscahires-asci.zip``.

    Layout: ``cat0.vert`` + ``cat0.tri``, ``centaur1.vert`` + ..., at any depth (``.off``
    copies are read too when there is no ``.vert``).  Label: the name without its trailing
    pose number (``cat``, ``centaur``, ``david``, ``dog``, ``gorilla``, ``horse``,
    ``michael``, ``victoria``, ``wolf``).

    Parameters
    ----------
    folder : str or os.PathLike
        The unpacked archive.

    Returns
    -------
    Collection
        Named ``tosca``; the meshes found, labelled by class, loaded on first access.
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


def read_shrec07(folder: str | os.PathLike[str]) -> Collection:
    """Read the SHREC'07 watertight track: ``1.off`` ... ``400.off`` at any depth.

    Model ``n`` belongs to class ``SHREC07_CLASSES[(n - 1) // 20]``; files not named by a
    number from 1 to 400 are ignored.

    Parameters
    ----------
    folder : str or os.PathLike
        The unpacked track.

    Returns
    -------
    Collection
        The models found, in number order, labelled by class, loaded on first access.
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


def _natural_key(s: str) -> list[int | str]:
    return [int(t) if t.isdigit() else t for t in re.split(r"(\d+)", s)]


_LAYOUT_READERS = {"mcgill": read_mcgill, "tosca": read_tosca, "shrec07": read_shrec07}


def _manual_message(entry: dict[str, Any], folder: str | os.PathLike[str]) -> str:
    env = entry.get("path_env")
    return (
        f"collection {entry['name']!r} is not on this machine: its terms ({entry['license']}) "
        f"mean cshape does not download it.  Get it from {entry['page']} ({entry['format']}), "
        f"then unpack it into {str(folder)!r}"
        + (f" or set {env} to its folder" if env else "")
        + f", or run `cshape data build {entry['name']} --archive FILE`."
    )
