"""The :class:`DescriptorTable`: the eigenvalues of a collection with their names, labels and
areas, every descriptor derived from them, and its file formats (.npz, .csv).
"""

from __future__ import annotations

import csv
import dataclasses
import json
import warnings
import zipfile
from collections import Counter
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any, NamedTuple

import numpy as np

from .._checks import check_path
from .._files import atomic_write
from ..compare import distance_matrix
from ..descriptors import Descriptor, count_zero_modes
from ..descriptors.recipe import check_descriptor
from ..mesh import CShapeWarning
from ..spectrum import SpectrumSettings

if TYPE_CHECKING:
    import os
    from collections.abc import Iterable

    from numpy.typing import ArrayLike

_FORMAT = "cshape-descriptor-table"
#: 1: CSV with a ``# cshape-descriptor-table {json}`` first line; 2: plain CSV (``pandas``
#: reads it with no options) with a ``components`` column, metadata in ``<file>.json``;
#: 3: as 2, without the ``M`` and ``transform`` of versions 1-2 (defaults of a keyword form
#: of :meth:`DescriptorTable.descriptors` that the descriptor now says; read and not used);
#: 4: as 3, with the table's :attr:`~DescriptorTable.descriptor` (its fields).
_FORMAT_VERSION = 4
#: What a table of format 1-3 compares when no descriptor is given: the exploration default
#: of those formats, the area-normalised truncated log spectrum of 17 values.
_DESCRIPTOR_BEFORE_4 = Descriptor("truncated-log", N=100, M=8)
#: The columns before ``lam_0`` of a version-2 CSV.
_CSV_COLUMNS = ("name", "label", "area", "seconds", "cached", "components")


# =========================================================================== the table
class DescriptorTable:
    """Eigenvalues of a collection of shapes, and every descriptor derived from them.

    Parameters
    ----------
    names : sequence of str, length p
        Unique shape names.
    lam : array_like, shape (p, N)
        Ascending eigenvalues (Shape-DNA) of each shape, ``lam_0`` first.
    areas : array_like, shape (p,)
        Surface areas (for the area normalisation of Section 2.1).
    labels : sequence of str, length p, optional
        Class labels; ``''`` where unknown (the default).
    bc, mass : str
        How the eigenvalues were computed (see :func:`cshape.shape_dna`).
    seconds : array_like, shape (p,), optional
        Wall time of each eigensolve (load + FEM + solve), in seconds; as stored in the
        cache for entries that were not recomputed.
    cached : array_like of bool, shape (p,), optional
        Whether each row came from the cache in the run that made the table.
    failures : list of (str, str)
        ``(name, message)`` of every mesh that was skipped.
    components : array_like of int, shape (p,), optional
        Number of connected components of each (repaired) mesh; ``-1`` where unknown (the
        default; tables written before it was stored).
    refine : {'none', 'extrapolate'}, default='none'
        Which spectra the table holds (see :func:`cshape.shape_dna`): saved with the table;
        files written before it existed load as ``'none'``.
    descriptor : Descriptor, optional
        What the table compares when a method is given no descriptor: default
        :data:`cshape.DEFAULT` at the table's ``N``.  Saved with the table, so that a saved
        table keeps comparing what it compared when it was written; tables of the formats
        before it was saved load with the exploration default of those formats, the
        area-normalised truncated log spectrum of 17 values.

    Attributes
    ----------
    N : int
        Number of eigenvalues per shape (``lam.shape[1]``).
    settings : SpectrumSettings
        How the eigenvalues were computed (``N``, ``bc``, ``mass``, ``refine``).
    zero_modes : ndarray of int, shape (p,)
        Number of zero eigenvalues of each shape: its component count (Neumann), else
        counted from its eigenvalues (:func:`cshape.descriptors.count_zero_modes`).

    Notes
    -----
    **Which descriptor.**  Every method that describes the shapes takes one
    :class:`cshape.Descriptor` (``descriptor=``, e.g. :data:`cshape.PAPER`); without one
    it compares the table's own :attr:`descriptor` (by default the exploration default
    :data:`cshape.DEFAULT` at the table's ``N``, :meth:`cshape.Descriptor.for_N`).

    **Meshes of several pieces.**  The descriptors that need positive eigenvalues
    (``'truncated-log'``, ``'f1'``, the log-Weyl transforms) drop each shape's zero modes
    (see :class:`cshape.Descriptor`).  A shape that still cannot be described (too few
    non-zero eigenvalues) is left out of :meth:`descriptors`, :meth:`distance_matrix` and
    :class:`cshape.DescriptorIndex`, with a warning that names it; :meth:`described`
    gives the rows kept, and ``table.select(table.described(descriptor)[1])`` is the
    table of those rows.

    Examples
    --------
    >>> import numpy as np
    >>> from cshape import PAPER, DescriptorTable
    >>> lam = np.arange(100.0)[None, :] * [[1.0], [1.1]]
    >>> table = DescriptorTable(["a", "b"], lam, [1.0, 1.0])
    >>> table.descriptors().shape, table.descriptors(PAPER).shape
    ((2, 108), (2, 33))
    """

    def __init__(self, names: Iterable[object], lam: ArrayLike, areas: ArrayLike,
                 labels: Iterable[object] | None = None, *, bc: str = "neumann",
                 mass: str = "consistent", seconds: ArrayLike | None = None,
                 cached: ArrayLike | None = None,
                 failures: Iterable[tuple[object, object]] = (),
                 components: ArrayLike | None = None, refine: str = "none",
                 descriptor: Descriptor | None = None) -> None:
        self.names = [str(n) for n in names]
        p = len(self.names)
        lam = np.asarray(lam, dtype=np.float64)
        if lam.ndim != 2 or lam.shape[0] != p:
            raise ValueError(f"lam must have shape ({p}, N) for {p} names, got {lam.shape}")
        self.lam = lam
        self.areas = np.asarray(areas, dtype=np.float64).reshape(-1)
        if len(self.areas) != p:
            raise ValueError(f"areas has {len(self.areas)} entries for {p} names")
        if len(set(self.names)) != p:
            dup = sorted(n for n, c in Counter(self.names).items() if c > 1)
            raise ValueError(f"names must be unique; repeated: {dup[:5]}")
        self.labels = [""] * p if labels is None else ["" if x is None else str(x) for x in labels]
        if len(self.labels) != p:
            raise ValueError(f"labels has {len(self.labels)} entries for {p} names")
        how = SpectrumSettings(max(lam.shape[1], 1), bc, mass, refine)  # checked there
        self.bc, self.mass, self.refine = how.bc, how.mass, how.refine
        self.descriptor: Descriptor | None = _table_descriptor(descriptor, lam.shape[1])
        if self.descriptor is not None and self.descriptor.min_eigenvalues > lam.shape[1]:
            raise ValueError(
                f"descriptor {self.descriptor.label!r} needs {self.descriptor.min_eigenvalues} "
                f"eigenvalues per shape but the table holds N = {lam.shape[1]}; pass "
                "descriptor.for_N(N)")
        self.seconds = (np.full(p, np.nan) if seconds is None
                        else np.asarray(seconds, dtype=np.float64).reshape(-1))
        self.cached = (np.zeros(p, bool) if cached is None
                       else np.asarray(cached, dtype=bool).reshape(-1))
        self.failures = [(str(a), str(b)) for a, b in failures]
        self.components = (np.full(p, -1, dtype=np.int64) if components is None
                           else np.asarray(components, dtype=np.int64).reshape(-1))
        for name, arr in (("seconds", self.seconds), ("cached", self.cached),
                          ("components", self.components)):
            if len(arr) != p:
                raise ValueError(f"{name} has {len(arr)} entries for {p} names")

    # ------------------------------------------------------------------ basics
    @property
    def N(self) -> int:
        """Number of eigenvalues per shape (``lam.shape[1]``)."""
        return int(self.lam.shape[1])

    @property
    def settings(self) -> SpectrumSettings:
        """How the eigenvalues were computed: ``N``, ``bc``, ``mass`` and ``refine``.

        Describe one more mesh the same way with
        ``cshape.describe(meshes, **table.settings.as_kwargs())``.
        """
        return SpectrumSettings(self.N, self.bc, self.mass, self.refine)

    def __len__(self) -> int:
        return len(self.names)

    @property
    def zero_modes(self) -> np.ndarray:
        """Zero eigenvalues per shape, shape (p,).

        The component count where it is known and the boundary condition is Neumann, else
        counted from the eigenvalues (:func:`cshape.descriptors.count_zero_modes`).
        """
        out = self.components.copy()
        for i in np.flatnonzero((out < 0) | (self.bc != "neumann")):
            out[i] = count_zero_modes(self.lam[i])
        return out

    def __repr__(self) -> str:
        nlab = len({x for x in self.labels if x})
        fails = f", {len(self.failures)} failed" if self.failures else ""
        ref = "" if self.refine == "none" else f", refine={self.refine!r}"
        return (f"DescriptorTable({len(self)} shapes, N={self.N}, mass={self.mass!r}{ref}, "
                f"{nlab} classes"
                f"{fails})")

    def index(self, name: object) -> int:
        """Find the row of the shape called ``name``.

        Parameters
        ----------
        name : str
            Shape name (other objects are compared as ``str(name)``).

        Returns
        -------
        int
            Row of the shape in the table.

        Raises
        ------
        KeyError
            If no shape of the table is called ``name``.
        """
        try:
            return self.names.index(str(name))
        except ValueError:
            raise KeyError(f"no shape named {name!r} in the table") from None

    def select(self, rows: Iterable[int | str] | np.ndarray) -> DescriptorTable:
        """Make a table of the given rows, in the order given.

        Parameters
        ----------
        rows : iterable of int or str, or ndarray of bool
            Row indices, shape names, or a boolean mask of shape (p,).

        Returns
        -------
        DescriptorTable
            The selected rows, with this table's ``bc``, ``mass``, ``refine``,
            ``descriptor`` and failures.

        Raises
        ------
        KeyError
            If a name is not in the table.
        """
        rows = list(rows) if not isinstance(rows, np.ndarray) else rows
        if isinstance(rows, np.ndarray) and rows.dtype == bool:
            idx = np.flatnonzero(rows)
        else:
            idx = np.array([self.index(r) if isinstance(r, str) else int(r) for r in rows],
                           dtype=np.int64)
        return DescriptorTable(
            [self.names[i] for i in idx], self.lam[idx], self.areas[idx],
            [self.labels[i] for i in idx], bc=self.bc, mass=self.mass, refine=self.refine,
            descriptor=self.descriptor,
            seconds=self.seconds[idx], cached=self.cached[idx], failures=self.failures,
            components=self.components[idx])

    # ------------------------------------------------------------------ descriptors
    def _warn_left_out(self, d: Descriptor, bad: dict[int, str], stacklevel: int = 3) -> None:
        """A warning that names the rows left out."""
        if bad:
            shown = "; ".join(f"{self.names[i]} ({m})" for i, m in list(bad.items())[:5])
            more = f"; and {len(bad) - 5} more" if len(bad) > 5 else ""
            warnings.warn(
                f"{d.label} cannot describe {len(bad)} of {len(self)} shapes, "
                f"left out: {shown}{more}",
                CShapeWarning, stacklevel=stacklevel)

    def descriptors(self, descriptor: Descriptor | None = None) -> np.ndarray:
        """Descriptor matrix, one row per shape (:meth:`cshape.Descriptor.row` of each).

        Parameters
        ----------
        descriptor : Descriptor, optional
            Which descriptor (e.g. :data:`cshape.PAPER`, the paper's cShape-DNA, or
            ``Descriptor('shape-dna', N=table.N)``).  Default: :data:`cshape.DEFAULT` at the
            table's ``N`` (:meth:`cshape.Descriptor.for_N`).

        Returns
        -------
        ndarray, shape (q, size)
            One row per shape that can be described (``q = p`` unless some are left out,
            with a :class:`cshape.CShapeWarning` naming them; :meth:`described` gives their
            rows).

        Raises
        ------
        TypeError
            ``descriptor`` not a :class:`cshape.Descriptor`.
        ValueError
            The descriptor needs more eigenvalues than the table has (``N``), or it can
            describe none of the shapes.
        """
        d = _chosen(self, descriptor)
        X, _rows = self.described(d, stacklevel=4)
        if len(X) == 0:
            raise ValueError(
                f"{d.label} cannot describe any of the {len(self)} shapes (see the warning); "
                "choose another descriptor or compute more eigenvalues")
        return X

    def described(self, descriptor: Descriptor | None = None, *, warn: bool = True,
                  stacklevel: int = 3) -> tuple[np.ndarray, np.ndarray]:
        """Compute the descriptors and the table rows they belong to, at once.

        Unlike :meth:`descriptors`, no row at all is not an error.

        Parameters
        ----------
        descriptor : Descriptor, optional
            As in :meth:`descriptors`.
        warn : bool, default=True
            Name the rows left out in a :class:`cshape.CShapeWarning`.
        stacklevel : int, default=3
            ``stacklevel`` of that warning (for the methods that call this one).

        Returns
        -------
        X : ndarray, shape (q, size)
            As :meth:`descriptors`.
        rows : ndarray of int, shape (q,)
            The table row of each row of ``X``.
        """
        d = _chosen(self, descriptor)
        X, bad = d._rows(self.lam, self.areas, self.zero_modes)
        if warn:
            self._warn_left_out(d, bad, stacklevel=stacklevel)
        rows = np.setdiff1d(np.arange(len(self)), np.fromiter(bad, dtype=np.int64))
        return X, rows

    def distance_matrix(self, descriptor: Descriptor | None = None) -> np.ndarray:
        """Compute the Euclidean distance matrix of :meth:`descriptors`.

        Parameters
        ----------
        descriptor : Descriptor, optional
            As in :meth:`descriptors` (the same default).

        Returns
        -------
        ndarray, shape (q, q)
            Distances between the rows that :meth:`descriptors` returns.

        Raises
        ------
        TypeError
            ``descriptor`` not a :class:`cshape.Descriptor`.
        ValueError
            As in :meth:`descriptors`.
        """
        return distance_matrix(self.descriptors(descriptor))

    # ------------------------------------------------------------------ persistence
    def _meta(self) -> dict[str, Any]:
        return {"format": _FORMAT, "format_version": _FORMAT_VERSION, "N": self.N,
                "bc": self.bc, "mass": self.mass, "refine": self.refine,
                "descriptor": (None if self.descriptor is None
                               else dataclasses.asdict(self.descriptor)),
                "failures": [list(f) for f in self.failures]}

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Save to ``.npz`` (NumPy arrays only, no pickle) or ``.csv`` (one row per shape).

        The CSV is plain: a header ``name,label,area,seconds,cached,components,lam_0,...,
        lam_{N-1}`` and one row per shape, so that ``pandas.read_csv(path)`` reads it with
        no options; floats are written with 17 significant digits, so both formats
        round-trip exactly.  The metadata (``N``, ``bc``, ``mass``, ``refine``, the failures,
        the format version) go to the sidecar ``<path>.json`` (e.g.
        ``table.csv.json``), written with it; :meth:`load` reads both.

        Parameters
        ----------
        path : str or os.PathLike
            Ending in ``.npz`` or ``.csv``; a missing folder is created (the command
            line's ``--out`` refuses one instead, before any work: a typo in a path
            should not cost a run).

        Returns
        -------
        Path
            The path written (the sidecar of a ``.csv`` is ``<path>.json``).

        Raises
        ------
        ValueError
            If ``path`` does not end in ``.npz`` or ``.csv``.
        """
        path = check_path("path", path)
        suffix = path.suffix.lower()
        if suffix not in (".npz", ".csv"):
            raise ValueError(f"path must end in .npz or .csv, got {str(path)!r}")
        path.parent.mkdir(parents=True, exist_ok=True)
        if suffix == ".npz":
            def write(f: IO[Any]) -> None:
                np.savez(f, names=np.array(self.names, dtype=str),
                         labels=np.array(self.labels, dtype=str), lam=self.lam,
                         areas=self.areas, seconds=self.seconds, cached=self.cached,
                         components=self.components,
                         meta=np.array(json.dumps(self._meta())))
            atomic_write(path, write, binary=True)
        else:
            def write(f: IO[Any]) -> None:
                w = csv.writer(f, lineterminator="\n")
                w.writerow(list(_CSV_COLUMNS) + [f"lam_{i}" for i in range(self.N)])
                for i in range(len(self)):
                    w.writerow([self.names[i], self.labels[i], _fmt(self.areas[i]),
                                _fmt(self.seconds[i]), int(self.cached[i]),
                                int(self.components[i])]
                               + [_fmt(x) for x in self.lam[i]])
            atomic_write(path, write, binary=False)
            atomic_write(sidecar_path(path),
                         lambda f: f.write(json.dumps(self._meta(), indent=1) + "\n"),
                         binary=False)
        return path

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> DescriptorTable:
        """Read a table written by :meth:`save` (``.npz`` or ``.csv``).

        A ``.csv`` is read with its sidecar ``<path>.json``; without the sidecar (a CSV
        copied alone) it loads with the defaults ``bc='neumann'``, ``mass='consistent'`` and
        a warning.  Tables of format versions 1 (the metadata on a first ``#`` line of the
        CSV) and 2 load as well: their eigenvalues, areas, names and labels mean what they
        meant; the ``M`` and ``transform`` they store (the defaults of a keyword form of
        :meth:`descriptors`) are not used: a :class:`cshape.Descriptor` says them.

        Parameters
        ----------
        path : str or os.PathLike
            A ``.npz`` or ``.csv`` file written by :meth:`save`.

        Returns
        -------
        DescriptorTable
            The table as it was saved.

        Raises
        ------
        FileNotFoundError
            If there is no file at ``path``.
        ValueError
            If the file is not a readable cshape descriptor table (wrong format or version,
            truncated, corrupt); the message names the file.
        """
        path = check_path("path", path)
        if not path.is_file():
            raise FileNotFoundError(f"no descriptor table at {str(path)!r}")
        if path.suffix.lower() not in (".npz", ".csv"):
            raise ValueError(f"path must end in .npz or .csv, got {str(path)!r}")
        try:
            return cls._load(path)
        except ValueError as exc:
            if str(path) in str(exc):
                raise
            raise ValueError(
                f"{str(path)!r} is not a readable cshape descriptor table: {exc}"
            ) from None
        except (KeyError, IndexError, TypeError, OSError, EOFError, zipfile.BadZipFile) as exc:
            raise ValueError(
                f"{str(path)!r} is not a readable cshape descriptor table "
                f"({type(exc).__name__}: {exc}); it is truncated or corrupt: write it again "
                "with DescriptorTable.save"
            ) from None

    @classmethod
    def _load(cls, path: Path) -> DescriptorTable:
        if path.suffix.lower() == ".npz":
            with np.load(path, allow_pickle=False) as z:
                meta = json.loads(str(z["meta"]))
                _check_meta(meta, path)
                lam = z["lam"].reshape(-1, int(meta["N"]))
                return cls(z["names"].tolist(), lam, z["areas"], z["labels"].tolist(),
                           bc=meta["bc"], mass=meta["mass"],
                           seconds=z["seconds"], cached=z["cached"],
                           failures=meta["failures"],
                           refine=meta.get("refine", "none"),
                           descriptor=_saved_descriptor(meta, int(meta["N"])),
                           components=z["components"] if "components" in z.files else None)
        with open(path, newline="", encoding="utf-8") as f:
            first = f.readline()
            prefix = f"# {_FORMAT} "
            if first.startswith(prefix):  # version 1: the metadata on the first line
                meta = json.loads(first[len(prefix):])
                _check_meta(meta, path)
                rows = list(csv.reader(f))
                header, body, start = rows[0], rows[1:], 5
            else:
                f.seek(0)
                rows = list(csv.reader(f))
                header, body = rows[0], rows[1:]
                if tuple(header[:len(_CSV_COLUMNS)]) != _CSV_COLUMNS:
                    raise ValueError(
                        f"{str(path)!r} is not a cshape descriptor table CSV (its header "
                        f"should start with {','.join(_CSV_COLUMNS)},lam_0)")
                start = len(_CSV_COLUMNS)
                meta = _read_sidecar(path, len(header) - start)
        N = int(meta["N"])
        if len(header) - start != N:
            raise ValueError(f"{str(path)!r} has {len(header) - start} eigenvalue columns "
                             f"but its metadata say N = {N}")
        lam = np.array([[float(x) for x in r[start:]] for r in body]).reshape(len(body), N)
        return cls([r[0] for r in body], lam, [float(r[2]) for r in body],
                   [r[1] for r in body], bc=meta["bc"], mass=meta["mass"],
                   seconds=[float(r[3]) for r in body], cached=[r[4] == "1" for r in body],
                   failures=meta["failures"], refine=meta.get("refine", "none"),
                   descriptor=_saved_descriptor(meta, N),
                   components=[int(r[5]) for r in body] if start == 6 else None)


class CollectionDistances(NamedTuple):
    """The distances of a described collection under one descriptor.

    Attributes
    ----------
    D : ndarray, shape (q, q)
        Euclidean distances of the descriptors of the rows kept.
    rows : ndarray of int, shape (q,)
        The table rows kept, in order.
    names, labels : list of str, length q
        Their names and classes.
    left_out : list of (str, str)
        ``(name, reason)`` of every row that could not be described.
    descriptor : Descriptor
        The descriptor compared (its :attr:`~cshape.Descriptor.label` says it in words).
    """

    D: np.ndarray
    rows: np.ndarray
    names: list[str]
    labels: list[str]
    left_out: list[tuple[str, str]]
    descriptor: Descriptor


def collection_distances(table: DescriptorTable, descriptor: Descriptor | None = None
                         ) -> CollectionDistances:
    """Distances between the shapes of a described collection, under one descriptor.

    One shape never fails the collection: a row that cannot be described (a mesh of
    several pieces, too few eigenvalues) is left out, and one :class:`cshape.CShapeWarning`
    names every such row.  What the figures of a collection draw (MDS, overview).

    Parameters
    ----------
    table : DescriptorTable
    descriptor : Descriptor, optional
        Default: :data:`cshape.DEFAULT` at the table's ``N``.

    Returns
    -------
    CollectionDistances

    Raises
    ------
    TypeError
        ``descriptor`` not a :class:`cshape.Descriptor`.
    ValueError
        If no shape (or a single one) can be described.
    """
    d = _chosen(table, descriptor)
    X, bad = d._rows(table.lam, table.areas, table.zero_modes)
    table._warn_left_out(d, bad)
    rows = np.setdiff1d(np.arange(len(table)), np.fromiter(bad, dtype=np.int64))
    left_out = [(table.names[i], " ".join(str(why).split())) for i, why in bad.items()]
    p, title = len(table), d.label
    if len(rows) < 2:
        raise ValueError(
            f"only {len(rows)} of the {p} shapes can be described by {title}; a picture "
            "needs two or more: choose another descriptor (descriptor=...)")
    return CollectionDistances(distance_matrix(X), rows, [table.names[i] for i in rows],
                               [table.labels[i] for i in rows], left_out, d)


def sidecar_path(path: str | os.PathLike[str]) -> Path:
    """The metadata file of a CSV table: ``<path>.json`` (``table.csv.json``)."""
    path = Path(path)
    return path.with_name(path.name + ".json")


def _read_sidecar(path: str | os.PathLike[str], N: int) -> dict[str, Any]:
    side = sidecar_path(path)
    if not side.is_file():
        warnings.warn(
            f"{str(path)!r} has no metadata file {str(side)!r} (written with it by "
            "DescriptorTable.save); read with bc='neumann', mass='consistent'",
            CShapeWarning, stacklevel=4)
        return {"format": _FORMAT, "format_version": _FORMAT_VERSION, "N": N,
                "bc": "neumann", "mass": "consistent", "failures": []}
    try:
        meta = json.loads(side.read_text(encoding="utf-8"))
    except (OSError, UnicodeError, json.JSONDecodeError) as exc:
        raise ValueError(f"its metadata file {str(side)!r} is unreadable ({exc}); delete it "
                         "to read the table with the default metadata") from None
    if not isinstance(meta, dict):
        raise ValueError(f"its metadata file {str(side)!r} holds no JSON object")
    _check_meta(meta, side)
    return meta


def check_out_folder(path: str | os.PathLike[str]) -> None:
    """Raise a ``FileNotFoundError`` naming the folder of ``path`` if it does not exist."""
    folder = Path(path).parent
    if not folder.is_dir():
        what = "is a file, not a folder" if folder.exists() else "does not exist"
        raise FileNotFoundError(
            f"cannot write {str(path)!r}: the folder {str(folder)!r} {what}; create it "
            "first or choose another path")


def _fmt(x: float) -> str:
    return repr(float(x))


def _check_meta(meta: dict[str, Any], path: str | os.PathLike[str]) -> None:
    if meta.get("format") != _FORMAT or int(meta.get("format_version", 0)) > _FORMAT_VERSION:
        raise ValueError(
            f"{str(path)!r} is not a cshape descriptor table of a version this cshape reads "
            f"(format {meta.get('format')!r}, version {meta.get('format_version')!r})"
        )


def _saved_descriptor(meta: dict[str, Any], N: int) -> Descriptor | None:
    """The descriptor a saved table compares by default: the one its metadata name (format
    4), else the default of formats 1-3 at the table's ``N``; a sidecar that is missing gives
    :data:`cshape.DEFAULT`."""
    fields = meta.get("descriptor")
    if isinstance(fields, dict):
        try:
            return Descriptor(fields.get("kind", ""), **{k: v for k, v in fields.items()
                                                         if k != "kind"})
        except (TypeError, ValueError) as exc:
            raise ValueError(f"the table's metadata name a descriptor that cshape cannot "
                             f"make ({exc}); delete its 'descriptor' entry to compare with "
                             "cshape.DEFAULT") from None
    if int(meta.get("format_version", _FORMAT_VERSION)) < 4:
        try:
            return _DESCRIPTOR_BEFORE_4.for_N(N)
        except ValueError:  # too few eigenvalues for any row of it
            return None
    return _table_descriptor(None, N)


def _table_descriptor(descriptor: Descriptor | None, N: int) -> Descriptor | None:
    """A table's own descriptor: the one given (checked), else :data:`cshape.DEFAULT` for
    ``N`` eigenvalues, or None when ``N`` is too small for any row of it (a method that
    needs a row then says so)."""
    if descriptor is not None:
        return check_descriptor("descriptor", descriptor, N)
    try:
        return check_descriptor("descriptor", None, N)
    except ValueError:
        return None


def _chosen(table: DescriptorTable, descriptor: Descriptor | None) -> Descriptor:
    """``descriptor`` checked, else the table's own (an error naming N when it has none)."""
    if descriptor is None and table.descriptor is not None:
        return table.descriptor
    return check_descriptor("descriptor", descriptor, table.N)
