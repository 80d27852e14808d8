"""The :class:`DescriptorTable`: the eigenvalues of a collection with their names, labels and
areas, every descriptor derived from them, and its file formats (.npz, .csv).
"""

from __future__ import annotations

import csv
import json
import zipfile
from collections import Counter
from pathlib import Path

import numpy as np

from .._checks import check_choice
from .._files import atomic_write
from ..compare import descriptor_matrix, distance_matrix
from ..descriptors import TRANSFORMS

_FORMAT = "cshape-descriptor-table"
_FORMAT_VERSION = 1


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
    M : int, default=16
        Default crop half-width of the cShape-DNA for :meth:`descriptors`.
    transform : {'weyl', 'log-weyl', 'log-weyl-dct'}, default='weyl'
        Default transform of the cShape-DNA for :meth:`descriptors` (see
        :func:`cshape.compact_shape_dna`; ``'weyl'`` is the paper's).  Saved with the table;
        files written before it existed load as ``'weyl'``.
    bc, mass : str
        How the eigenvalues were computed (see :func:`cshape.shape_dna`).
    seconds : array_like, shape (p,), optional
        Wall time of each eigensolve (load + FEM + solve), in seconds; as stored in the
        cache for entries that were not recomputed.
    cached : array_like of bool, shape (p,), optional
        Whether each row came from the cache in the run that made the table.
    failures : list of (str, str)
        ``(name, message)`` of every mesh that was skipped.

    Attributes
    ----------
    N : int
        Number of eigenvalues per shape (``lam.shape[1]``).
    """

    def __init__(self, names, lam, areas, labels=None, *, M=16, bc="neumann",
                 mass="consistent", seconds=None, cached=None, failures=(), transform="weyl"):
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
        self.M = int(M)
        self.transform = check_choice("transform", transform, TRANSFORMS)
        self.bc = str(bc)
        self.mass = str(mass)
        self.seconds = (np.full(p, np.nan) if seconds is None
                        else np.asarray(seconds, dtype=np.float64).reshape(-1))
        self.cached = (np.zeros(p, bool) if cached is None
                       else np.asarray(cached, dtype=bool).reshape(-1))
        self.failures = [(str(a), str(b)) for a, b in failures]

    # ------------------------------------------------------------------ basics
    @property
    def N(self) -> int:
        return int(self.lam.shape[1])

    def __len__(self) -> int:
        return len(self.names)

    def __repr__(self) -> str:
        nlab = len({x for x in self.labels if x})
        fails = f", {len(self.failures)} failed" if self.failures else ""
        tr = "" if self.transform == "weyl" else f", transform={self.transform!r}"
        return (f"DescriptorTable({len(self)} shapes, N={self.N}, M={self.M}{tr}, "
                f"{nlab} classes{fails})")

    def index(self, name) -> int:
        """Row of the shape called ``name``."""
        try:
            return self.names.index(str(name))
        except ValueError:
            raise KeyError(f"no shape named {name!r} in the table") from None

    def select(self, rows) -> DescriptorTable:
        """A table with the given rows (indices, names or a boolean mask), in that order."""
        rows = list(rows) if not isinstance(rows, np.ndarray) else rows
        if isinstance(rows, np.ndarray) and rows.dtype == bool:
            idx = np.flatnonzero(rows)
        else:
            idx = np.array([self.index(r) if isinstance(r, str) else int(r) for r in rows],
                           dtype=np.int64)
        return DescriptorTable(
            [self.names[i] for i in idx], self.lam[idx], self.areas[idx],
            [self.labels[i] for i in idx], M=self.M, bc=self.bc, mass=self.mass,
            seconds=self.seconds[idx], cached=self.cached[idx], failures=self.failures,
            transform=self.transform)

    # ------------------------------------------------------------------ descriptors
    def descriptors(self, kind="cshape", M=None, N=None, *, transform=None,
                    **kwargs) -> np.ndarray:
        """Descriptor matrix, one row per shape; see :func:`cshape.compare.descriptor_matrix`.

        Parameters
        ----------
        kind : {'shape-dna', 'truncated', 'cshape', 'cshape-complex', 'f1', 'truncated-log'}
            Default 'cshape'.
        M : int, optional
            Default: the table's ``M``.
        N : int, optional
            Default: the table's ``N``; a smaller ``N`` uses the first ``N`` eigenvalues.
        transform : {'weyl', 'log-weyl', 'log-weyl-dct'}, optional
            Default: the table's ``transform`` (used by the 'cshape' kinds).

        Returns
        -------
        ndarray, shape (p, d)
        """
        return descriptor_matrix(self.lam, self.areas, kind=kind,
                                 M=self.M if M is None else M,
                                 N=self.N if N is None else N,
                                 transform=self.transform if transform is None else transform,
                                 **kwargs)

    def distance_matrix(self, kind="cshape", M=None, N=None, *, transform=None,
                        **kwargs) -> np.ndarray:
        """Euclidean distance matrix (p, p) of :meth:`descriptors`."""
        return distance_matrix(self.descriptors(kind, M=M, N=N, transform=transform, **kwargs))

    @property
    def shape_dna(self) -> np.ndarray:
        """Area-normalised Shape-DNA, shape (p, N)."""
        return self.descriptors("shape-dna")

    @property
    def cshape(self) -> np.ndarray:
        """cShape-DNA with the table's ``M`` and ``transform``, real form, shape (p, 2M+1)."""
        return self.descriptors("cshape")

    @property
    def f1(self) -> np.ndarray:
        """F1 feature, shape (p, N-2)."""
        return self.descriptors("f1")

    # ------------------------------------------------------------------ persistence
    def _meta(self) -> dict:
        return {"format": _FORMAT, "format_version": _FORMAT_VERSION, "N": self.N,
                "M": self.M, "transform": self.transform, "bc": self.bc, "mass": self.mass,
                "failures": [list(f) for f in self.failures]}

    def save(self, path) -> Path:
        """Save to ``.npz`` (NumPy arrays only, no pickle) or ``.csv`` (one row per shape).

        The CSV has a first line ``# cshape-descriptor-table {json}`` with the metadata,
        then a header ``name,label,area,seconds,cached,lam_0,...,lam_{N-1}``; floats are
        written with 17 significant digits, so both formats round-trip exactly.

        Parameters
        ----------
        path : str or os.PathLike
            Ending in ``.npz`` or ``.csv``.

        Returns
        -------
        Path
        """
        path = Path(path)
        suffix = path.suffix.lower()
        if suffix not in (".npz", ".csv"):
            raise ValueError(f"path must end in .npz or .csv, got {str(path)!r}")
        path.parent.mkdir(parents=True, exist_ok=True)
        if suffix == ".npz":
            def write(f):
                np.savez(f, names=np.array(self.names, dtype=str),
                         labels=np.array(self.labels, dtype=str), lam=self.lam,
                         areas=self.areas, seconds=self.seconds, cached=self.cached,
                         meta=np.array(json.dumps(self._meta())))
            atomic_write(path, write, binary=True)
        else:
            def write(f):
                f.write(f"# {_FORMAT} {json.dumps(self._meta())}\n")
                w = csv.writer(f, lineterminator="\n")
                w.writerow(["name", "label", "area", "seconds", "cached"]
                           + [f"lam_{i}" for i in range(self.N)])
                for i in range(len(self)):
                    w.writerow([self.names[i], self.labels[i], _fmt(self.areas[i]),
                                _fmt(self.seconds[i]), int(self.cached[i])]
                               + [_fmt(x) for x in self.lam[i]])
            atomic_write(path, write, binary=False)
        return path

    @classmethod
    def load(cls, path) -> DescriptorTable:
        """Read a table written by :meth:`save` (``.npz`` or ``.csv``).

        Raises
        ------
        FileNotFoundError
            If there is no file at ``path``.
        ValueError
            If the file is not a readable cshape descriptor table (wrong format or version,
            truncated, corrupt); the message names the file.
        """
        path = Path(path)
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
                           M=meta["M"], bc=meta["bc"], mass=meta["mass"],
                           seconds=z["seconds"], cached=z["cached"],
                           failures=meta["failures"],
                           transform=meta.get("transform", "weyl"))
        with open(path, newline="", encoding="utf-8") as f:
            first = f.readline()
            prefix = f"# {_FORMAT} "
            if not first.startswith(prefix):
                raise ValueError(f"{str(path)!r} is not a cshape descriptor table CSV")
            meta = json.loads(first[len(prefix):])
            _check_meta(meta, path)
            rows = list(csv.reader(f))
        body = rows[1:]
        N = int(meta["N"])
        lam = np.array([[float(x) for x in r[5:]] for r in body]).reshape(len(body), N)
        return cls([r[0] for r in body], lam, [float(r[2]) for r in body],
                   [r[1] for r in body], M=meta["M"], bc=meta["bc"], mass=meta["mass"],
                   seconds=[float(r[3]) for r in body], cached=[r[4] == "1" for r in body],
                   failures=meta["failures"], transform=meta.get("transform", "weyl"))


def _fmt(x) -> str:
    return repr(float(x))


def _check_meta(meta, path):
    if meta.get("format") != _FORMAT or int(meta.get("format_version", 0)) > _FORMAT_VERSION:
        raise ValueError(
            f"{str(path)!r} is not a cshape descriptor table of a version this cshape reads "
            f"(format {meta.get('format')!r}, version {meta.get('format_version')!r})"
        )
