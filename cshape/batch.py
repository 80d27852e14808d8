"""Batch runs: eigenvalues and descriptors of a whole collection, cached, resumable, parallel.

:func:`describe` computes the Shape-DNA (the ``N`` smallest eigenvalues, Section 2.1) of
every mesh of a collection and returns a :class:`DescriptorTable`, from which every
descriptor of :func:`cshape.compare.descriptor_matrix` (normalised / truncated Shape-DNA,
cShape-DNA for any ``M``, F1) is derived without another eigensolve.

The cache
---------
Each mesh's eigenvalues are stored in ``cache_dir`` as one ``<key>.npz`` file (NumPy
arrays only, read with ``allow_pickle=False``), where ``key`` is the SHA-256 of the mesh
content (vertex and face bytes) and of the parameters that change the eigenvalues
(``bc``, ``mass``, :data:`CACHE_VERSION`).  ``N`` is not part of the key: an entry with at
least ``N`` eigenvalues serves any smaller ``N`` (the first ``N`` values), and any ``M``.
Entries are written atomically (temporary file in the same folder, then ``os.replace``) by
the calling process only, as each result arrives, so an interrupted run (Ctrl-C, a killed
process or worker) leaves only complete entries and the next run resumes where it stopped.
An unreadable entry is reported, recomputed and overwritten.  Leftover ``.*.tmp`` files of
a killed run are ignored and safe to delete.

Meshes given as file paths are also remembered by file: ``cache_dir/files/<h>.key`` holds
the content key of the file whose resolved path, size and modification time (ns) hash to
``h`` (with ``bc``, ``mass`` and :data:`CACHE_VERSION`).  A second run over unchanged files
finds their eigenvalues without reading the meshes; a changed file has a new ``h`` and is
read (and its content key looked up) again.
"""

from __future__ import annotations

import contextlib
import csv
import hashlib
import json
import numbers
import os
import tempfile
import threading
import time
import warnings
import zipfile
from collections import Counter, deque
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from ._checks import check_choice
from .compare import descriptor_matrix, distance_matrix
from .descriptors import TRANSFORMS
from .mesh import CShapeWarning, Mesh, as_mesh, repair_mesh
from .readers import load_mesh
from .spectrum import shape_dna

__all__ = ["CACHE_VERSION", "DescriptorTable", "default_cache_dir", "describe", "mesh_key"]

#: Bump when the FEM or the eigensolver changes its results: old cache entries are ignored.
CACHE_VERSION = 1

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
        kind : {'shape_dna', 'truncated', 'cshape', 'cshape_complex', 'f1', 'truncated_log'}
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
        return self.descriptors("shape_dna")

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
            _atomic_write(path, write, binary=True)
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
            _atomic_write(path, write, binary=False)
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


def _atomic_write(path: Path, write, *, binary: bool):
    """Write via a temporary file in the same folder and ``os.replace`` it into place."""
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        mode = "wb" if binary else "w"
        kw = {} if binary else {"newline": "", "encoding": "utf-8"}
        with os.fdopen(fd, mode, **kw) as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


# =========================================================================== cache
def default_cache_dir() -> Path:
    """``<cache>/eigenvalues``, with ``<cache>`` the cache folder shared by cshape.

    ``<cache>`` is ``$CSHAPE_CACHE``, else ``platformdirs.user_cache_dir('cshape')`` when
    platformdirs is installed, else ``$XDG_CACHE_HOME/cshape`` or ``~/.cache/cshape`` (the
    same folder as :func:`cshape.data.cache_dir`).  Not created here.
    """
    env = os.environ.get("CSHAPE_CACHE")
    if env:
        return Path(env).expanduser() / "eigenvalues"
    try:
        import platformdirs

        base = Path(platformdirs.user_cache_dir("cshape"))
    except ImportError:
        xdg = os.environ.get("XDG_CACHE_HOME")
        base = (Path(xdg) if xdg else Path.home() / ".cache") / "cshape"
    return base / "eigenvalues"


def mesh_key(mesh, bc="neumann", mass="consistent") -> str:
    """Cache key: SHA-256 (hex) of the mesh content and the eigenvalue parameters.

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
    bc, mass : str
        See :func:`cshape.shape_dna`.

    Returns
    -------
    str
        64 hexadecimal digits; equal for meshes with identical vertex and face arrays.
    """
    mesh = as_mesh(mesh)
    V = np.ascontiguousarray(mesh.vertices, dtype="<f8")
    F = np.ascontiguousarray(mesh.faces, dtype="<i8")
    h = hashlib.sha256()
    h.update(f"cshape-lam-v{CACHE_VERSION}|bc={bc}|mass={mass}|".encode())
    h.update(f"{V.shape}|{F.shape}|".encode())
    h.update(V.tobytes())
    h.update(F.tobytes())
    return h.hexdigest()


def _entry_path(cache_dir, key) -> Path:
    return Path(cache_dir) / f"{key}.npz"


def _read_entry(cache_dir, key, N):
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
    return {"lam": lam[:N], "area": area, "seconds": seconds, "key": key, "cached": True}


def _file_alias(cache_dir, path, bc, mass) -> Path | None:
    """``cache_dir/files/<h>.key`` for a mesh file (see the module notes), None if unreadable."""
    try:
        p = Path(path).resolve()
        st = p.stat()
    except OSError:
        return None
    h = hashlib.sha256(
        f"cshape-file-v{CACHE_VERSION}|bc={bc}|mass={mass}|{p}|{st.st_size}|"
        f"{st.st_mtime_ns}".encode()).hexdigest()
    return Path(cache_dir) / "files" / f"{h}.key"


def _read_alias(alias) -> str | None:
    """The content key an alias file names, or None (missing or not a key)."""
    try:
        key = alias.read_text(encoding="ascii").strip()
    except (OSError, UnicodeError):
        return None
    return key if len(key) == 64 and all(c in "0123456789abcdef" for c in key) else None


def _write_entry(cache_dir, result):
    path = _entry_path(cache_dir, result["key"])

    def write(f):
        np.savez(f, lam=result["lam"], area=np.float64(result["area"]),
                 seconds=np.float64(result["seconds"]), key=np.array(result["key"]),
                 n_vertices=np.int64(result["n_vertices"]),
                 n_faces=np.int64(result["n_faces"]),
                 params=np.array(json.dumps(result["params"])))

    _atomic_write(path, write, binary=True)


# =========================================================================== the work
def _load_source(source) -> Mesh:
    if isinstance(source, (str, os.PathLike)):
        return load_mesh(source)
    return as_mesh(source)


def _work(task):
    """Eigenvalues of one mesh; runs in the caller, a worker process or a Dask worker.

    Never raises: errors come back as ``{'ok': False, 'error': message}``.  Warnings are
    recorded (and returned, to be re-issued with the mesh name) when this runs in a main
    thread; in other threads they are left alone (``catch_warnings`` is not thread-safe).
    """
    capture = threading.current_thread() is threading.main_thread()
    if capture:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            out = _work_inner(task)
        out["warnings"] = [str(w.message) for w in caught]
    else:
        out = _work_inner(task)
        out["warnings"] = []
    return out


def _work_inner(task):
    index, source, N, bc, mass, cache_dir, key = task
    t0 = time.perf_counter()
    try:
        mesh = _load_source(source)
        if key is None:
            key = mesh_key(mesh, bc, mass)
            if cache_dir is not None:
                hit = _read_entry(cache_dir, key, N)
                if hit is not None:
                    hit.update(index=index, ok=True)
                    return hit
        fixed = repair_mesh(mesh)
        lam = shape_dna(fixed, N=N, bc=bc, mass=mass)
        return {"index": index, "ok": True, "lam": lam, "area": float(fixed.area),
                "key": key, "seconds": time.perf_counter() - t0, "cached": False,
                "n_vertices": mesh.n_vertices, "n_faces": mesh.n_faces,
                "params": {"N": N, "bc": bc, "mass": mass, "cache_version": CACHE_VERSION}}
    except Exception as exc:  # noqa: BLE001 - reported and skipped by describe
        msg = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
        return {"index": index, "ok": False, "error": f"{type(exc).__name__}: {msg}"}


_THREAD_LIMITS = None


def _blas_limit(blas_threads):
    """Context manager limiting BLAS / OpenMP threads (a no-op for None)."""
    import contextlib

    if blas_threads is None:
        return contextlib.nullcontext()
    from threadpoolctl import threadpool_limits

    return threadpool_limits(limits=blas_threads)


def _init_worker(blas_threads):
    """Worker-process initialiser: limit BLAS threads for the life of the process."""
    global _THREAD_LIMITS
    if blas_threads is not None:
        from threadpoolctl import threadpool_limits

        _THREAD_LIMITS = threadpool_limits(limits=blas_threads)


# =========================================================================== records
class _Failed:
    """Stands for a mesh whose record could not produce it; describe reports the message."""

    def __init__(self, message):
        self.message = message


def _has_attr(cls, obj, name) -> bool:
    """``hasattr`` without running a property (which may load a mesh)."""
    import inspect

    try:
        inspect.getattr_static(obj, name)
        return True
    except AttributeError:
        return False


def _records(collection):
    """[(name, label, source)] from the accepted collection forms (see :func:`describe`)."""
    if isinstance(collection, (str, os.PathLike, Mesh)):
        raise TypeError(
            "collection must be an iterable of meshes, paths or records, got a single "
            f"{type(collection).__name__}; wrap it in a list"
        )
    items = list(collection.items()) if isinstance(collection, Mapping) else list(collection)
    out = []
    path_rows = []
    for i, item in enumerate(items):
        if isinstance(item, (str, os.PathLike)):
            path_rows.append(len(out))
            out.append([Path(item).stem, "", Path(item)])
        elif isinstance(item, Mesh):
            out.append([f"mesh{i}", "", item])
        elif isinstance(item, (tuple, list)) and len(item) in (2, 3) and isinstance(item[0], str):
            name, label, src = (item[0], "", item[1]) if len(item) == 2 else item
            out.append([name, label, src])
        elif isinstance(item, (tuple, list)) and len(item) == 2 and np.ndim(item[0]) == 2:
            out.append([f"mesh{i}", "", item])
        elif _has_attr(type(item), item, "mesh") or _has_attr(type(item), item, "path"):
            try:  # one access: a record may load its mesh lazily (and fail doing so)
                src = getattr(item, "mesh", None)
            except Exception as exc:  # noqa: BLE001 - reported as this mesh's failure
                src = _Failed(f"{type(exc).__name__}: {exc}")
            if src is None:
                src = item.path
            out.append([getattr(item, "name", None) or f"mesh{i}",
                        getattr(item, "label", "") or "", src])
        else:
            raise TypeError(
                f"collection item {i} is a {type(item).__name__}; expected a path, a Mesh, "
                "a (vertices, faces) pair, a (name, mesh) or (name, label, mesh) tuple, or "
                "a record with .name, .label and .mesh (or .path)"
            )
    # paths given bare: the file stem, or the whole path where stems collide
    stems = Counter(out[r][0] for r in path_rows)
    for r in path_rows:
        if stems[out[r][0]] > 1:
            out[r][0] = str(out[r][2])
    names = [str(r[0]) for r in out]
    if len(set(names)) != len(names):
        dup = sorted(n for n, c in Counter(names).items() if c > 1)
        raise ValueError(
            f"collection has repeated names {dup[:5]}; give each mesh a unique name, e.g. "
            "as (name, mesh) pairs"
        )
    return [(str(n), str(lab), src) for n, lab, src in out]


# =========================================================================== describe
def describe(collection, N=100, M=16, *, bc="neumann", mass="consistent", cache_dir=None,
             n_jobs=1, client=None, blas_threads=1, progress=True,
             on_error="warn", transform="weyl") -> DescriptorTable:
    """Eigenvalues and descriptors of every mesh of a collection: cached, resumable, parallel.

    Parameters
    ----------
    collection : iterable
        The meshes, each given as one of

        * a path (``str`` or ``os.PathLike``) of a mesh file, read by
          :func:`cshape.load_mesh` in the worker; named by its file stem (by the whole path
          when stems collide);
        * a :class:`cshape.Mesh` or a ``(vertices, faces)`` pair, named ``mesh<i>``;
        * a ``(name, mesh)`` or ``(name, label, mesh)`` tuple, ``mesh`` as above;
        * a record with attributes ``name``, ``label`` (optional) and ``mesh`` (or
          ``path``), e.g. the records of a cshape data collection;

        or a mapping ``{name: mesh}``.  Names must be unique.
    N : int, default=100
        Number of eigenvalues per shape (Shape-DNA length).
    M : int, default=16
        Default cShape-DNA half-width of the returned table (any ``M <= (N-1)//2`` can be
        asked of it later without recomputing; ``M <= (N-2)//2`` for the log-Weyl
        transforms).
    bc : {'neumann', 'dirichlet'}, default='neumann'
    mass : {'consistent', 'lumped'}, default='consistent'
    cache_dir : str, os.PathLike, None or False, default=None
        Folder of the eigenvalue cache (see the module notes); ``None`` uses
        :func:`default_cache_dir`, ``False`` disables caching.
    n_jobs : int, default=1
        Local worker processes (``-1``: all cores).  ``1`` computes in this process.
        Each worker process uses one BLAS thread.  The workers (joblib's loky pool) do
        not re-run the calling script, so a plain script without an
        ``if __name__ == '__main__':`` guard works.
    client : dask.distributed.Client or str, optional
        Run on a Dask cluster: a client, or a scheduler address such as
        ``'tcp://10.0.0.5:8786'`` (a client is opened and closed for the run).  The workers
        need cshape installed; the cache is read and written by this process only, so it
        need not be on a shared file system (workers given *paths* must be able to read
        them).  Takes precedence over ``n_jobs``.  On its first task each worker process
        undoes its nanny's ``MALLOC_TRIM_THRESHOLD_``, which made eigensolves about 1.35x
        slower (glibc's allocator thresholds set back to a plain process's), and while
        describe runs, each worker's statistical profiler and 20 ms event-loop tick are
        paused (they took the GIL from the eigensolves: about 10 % of their time) and
        restarted at the end; clusters need no other setup.
    blas_threads : int or None, default=1
        BLAS / OpenMP threads for each eigensolve, in this process (``n_jobs=1``) and in
        every local worker process; ``None`` leaves the library default.  One thread is
        the right choice for many small and medium meshes: on a busy 2-core machine two
        OpenBLAS threads made the dense eigensolve of 1000-vertex meshes about 100 times
        slower.  Dask workers started by a nanny already use one thread.
    progress : bool, default=True
        Show a tqdm progress bar.
    on_error : {'warn', 'raise'}, default='warn'
        ``'warn'``: a mesh that fails (unreadable file, too few vertices for ``N``, ...) is
        skipped, listed in ``table.failures`` and reported in one warning at the end.
        ``'raise'``: stop at the first failure with a ``RuntimeError``.
    transform : {'weyl', 'log-weyl', 'log-weyl-dct'}, default='weyl'
        Default cShape-DNA transform of the returned table (see
        :func:`cshape.compact_shape_dna`); like ``M`` it does not change the eigenvalues or
        the cache, and any transform can be asked of the table later.

    Returns
    -------
    DescriptorTable
        The successful meshes in the order of ``collection``: ``names``, ``labels``,
        ``lam`` (p, N), ``areas`` (p,), ``seconds``, ``cached`` and ``failures``;
        descriptors through :meth:`DescriptorTable.descriptors`.

    Warns
    -----
    CShapeWarning
        For failed meshes, corrupt cache entries (recomputed), and the warnings of the
        mesh stage (repairs, several components) prefixed by the mesh name.

    Examples
    --------
    >>> from cshape import shapes
    >>> from cshape.batch import describe
    >>> meshes = [("s1", "sphere", shapes.icosphere(2)), ("s2", "sphere", shapes.icosphere(3)),
    ...           ("t1", "torus", shapes.torus(24, 12))]
    >>> table = describe(meshes, N=30, M=4, cache_dir=False, progress=False)
    >>> table
    DescriptorTable(3 shapes, N=30, M=4, 2 classes)
    >>> table.cshape.shape, table.distance_matrix("shape_dna").shape
    ((3, 9), (3, 3))

    Notes
    -----
    If a local worker process dies (killed, out of memory), the meshes it had not finished
    are reported as failures; the finished ones are already cached, so calling
    ``describe`` again computes only what is missing.
    """
    N = _check_pos_int(N, "N")
    M = _check_pos_int(M, "M", lo=0)
    transform = check_choice("transform", transform, TRANSFORMS)
    if 2 * M + 1 > N:
        raise ValueError(f"M={M} needs 2M+1 = {2 * M + 1} <= N = {N}; use M <= {(N - 1) // 2}")
    if transform != "weyl" and 2 * M + 1 > N - 1:
        raise ValueError(f"M={M} with transform={transform!r} needs 2M+1 = {2 * M + 1} <= N-1 "
                         f"= {N - 1} (lam_0 has no logarithm); use M <= {(N - 2) // 2}")
    bc = check_choice("bc", bc, ("neumann", "dirichlet"))
    mass = check_choice("mass", mass, ("consistent", "lumped"))
    n_jobs = _check_n_jobs(n_jobs)
    if blas_threads is not None:
        blas_threads = _check_pos_int(blas_threads, "blas_threads")
    on_error = check_choice("on_error", on_error, ("warn", "raise"))
    if cache_dir is False:
        cache = None
    else:
        cache = Path(default_cache_dir() if cache_dir is None else cache_dir)
        cache.mkdir(parents=True, exist_ok=True)
    records = _records(collection)
    p = len(records)
    results = [None] * p
    failures = {}

    from tqdm.auto import tqdm

    bar = tqdm(total=p, desc="describe", unit="mesh", disable=not progress)
    aliases = {}  # row -> alias file of a mesh given by path (see the module notes)

    def finish(i, res):
        name = records[i][0]
        for msg in res.get("warnings", ()):
            warnings.warn(f"{name}: {msg}", CShapeWarning, stacklevel=3)
        if res["ok"]:
            if cache is not None and not res["cached"]:
                try:
                    _write_entry(cache, res)
                except OSError as exc:  # a full or read-only disk must not lose the result
                    warnings.warn(f"{name}: could not write its cache entry ({exc}); the "
                                  "result is kept but will be recomputed next time",
                                  CShapeWarning, stacklevel=3)
            alias = aliases.get(i)
            if alias is not None and _read_alias(alias) != res["key"]:
                try:
                    alias.parent.mkdir(exist_ok=True)
                    _atomic_write(alias, lambda f: f.write(res["key"]), binary=False)
                except OSError:
                    pass  # only the shortcut is lost: the file is read again next time
            results[i] = res
        else:
            if on_error == "raise":
                raise RuntimeError(f"describe: mesh {name!r} failed: {res['error']}")
            failures[i] = res["error"]
        bar.update(1)

    try:
        # meshes in memory, and files seen before unchanged: look them up in the cache here,
        # before any task is sent
        tasks = []
        for i, (_name, _label, src) in enumerate(records):
            key = None
            if isinstance(src, _Failed):
                finish(i, {"ok": False, "error": src.message})
                continue
            if isinstance(src, (str, os.PathLike)) and cache is not None:
                alias = aliases[i] = _file_alias(cache, src, bc, mass)
                known = None if alias is None else _read_alias(alias)
                hit = None if known is None else _read_entry(cache, known, N)
                if hit is not None:
                    finish(i, {**hit, "ok": True})
                    continue
            if not isinstance(src, (str, os.PathLike)):
                try:
                    key = mesh_key(src, bc, mass)
                except (TypeError, ValueError) as exc:
                    finish(i, {"ok": False, "error": f"{type(exc).__name__}: {exc}"})
                    continue
                hit = None if cache is None else _read_entry(cache, key, N)
                if hit is not None:
                    finish(i, {**hit, "ok": True})
                    continue
            tasks.append((i, src, N, bc, mass, None if cache is None else str(cache), key))

        if client is not None:
            _run_dask(tasks, client, finish)
        elif n_jobs == 1 or len(tasks) <= 1:
            with _blas_limit(blas_threads):
                for t in tasks:
                    finish(t[0], _work(t))
        else:
            _run_processes(tasks, n_jobs, finish, failures, blas_threads)
    finally:
        bar.close()

    ok = [i for i in range(p) if results[i] is not None]
    fail_list = [(records[i][0], failures[i]) for i in sorted(failures)]
    if fail_list:
        shown = "; ".join(f"{n} ({m})" for n, m in fail_list[:5])
        more = f"; and {len(fail_list) - 5} more" if len(fail_list) > 5 else ""
        warnings.warn(
            f"describe: {len(fail_list)} of {p} meshes failed and were skipped "
            f"(see table.failures): {shown}{more}", CShapeWarning, stacklevel=2)
    return DescriptorTable(
        [records[i][0] for i in ok],
        np.array([results[i]["lam"][:N] for i in ok]).reshape(len(ok), N),
        [results[i]["area"] for i in ok],
        [records[i][1] for i in ok], M=M, bc=bc, mass=mass,
        seconds=[results[i]["seconds"] for i in ok],
        cached=[results[i]["cached"] for i in ok], failures=fail_list, transform=transform)


def _check_pos_int(value, name, lo=1):
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < lo:
        raise ValueError(f"{name} must be an integer >= {lo}, got {value!r}")
    return int(value)


def _check_n_jobs(n_jobs):
    if n_jobs is None:
        return 1
    if isinstance(n_jobs, bool) or not isinstance(n_jobs, numbers.Integral) or n_jobs == 0 \
            or n_jobs < -1:
        raise ValueError(f"n_jobs must be a positive integer or -1 (all cores), got {n_jobs!r}")
    return (os.cpu_count() or 1) if n_jobs == -1 else int(n_jobs)


def _run_processes(tasks, n_jobs, finish, failures, blas_threads):
    """Run ``tasks`` in ``n_jobs`` local worker processes, calling ``finish`` as they end.

    The pool is joblib's loky executor: its workers start a fresh interpreter that imports
    cshape but not the caller's ``__main__``.  (multiprocessing's 'spawn' and 'forkserver'
    re-run the calling script in every worker, so a script without an
    ``if __name__ == "__main__":`` guard started describe again in each worker, whose death
    failed every mesh; 'fork' is unsafe with the threads of BLAS and PyMeshLab.)  A worker
    that dies (killed, out of memory) breaks the pool: its unfinished meshes are reported as
    failures, and the finished ones are already cached.
    """
    from concurrent.futures import FIRST_COMPLETED, wait

    from joblib.externals.loky import ProcessPoolExecutor
    from joblib.externals.loky.process_executor import BrokenProcessPool

    todo = deque(tasks)
    window = 4 * n_jobs  # tasks in flight: bounded memory for large collections
    with ProcessPoolExecutor(max_workers=min(n_jobs, len(tasks)),
                             initializer=_init_worker, initargs=(blas_threads,)) as ex:
        pending = {}
        try:
            while todo or pending:
                while todo and len(pending) < window:
                    fut = ex.submit(_work, todo[0])  # raises if the pool is broken
                    pending[fut] = todo.popleft()
                done, _ = wait(pending, return_when=FIRST_COMPLETED)
                for fut in done:
                    t = pending[fut]
                    try:
                        res = fut.result()
                    except BrokenProcessPool:
                        raise
                    except Exception as exc:  # noqa: BLE001 - e.g. a task that cannot pickle
                        res = {"ok": False, "error": f"{type(exc).__name__}: {exc}"}
                    del pending[fut]
                    finish(t[0], res)
        except BrokenProcessPool:
            lost = list(pending.values()) + list(todo)
            for t in lost:
                failures[t[0]] = ("worker process died (killed or crashed) before finishing "
                                  "this mesh; run describe again to resume")
        finally:
            for fut in pending:
                fut.cancel()


#: glibc's ceiling for its adaptive mmap threshold on 64-bit systems (32 MiB): the value a
#: plain process settles at after freeing a few large arrays.
_MMAP_THRESHOLD = 32 * 2**20
_WORKER_READY = False


def _malloc_as_a_plain_process():
    """Undo the Dask nanny's ``MALLOC_TRIM_THRESHOLD_`` for this worker process (glibc only).

    The nanny starts workers with ``MALLOC_TRIM_THRESHOLD_=65536`` (its
    ``distributed.nanny.pre-spawn-environ``), to hand freed memory back to the system
    promptly.  Setting any such variable also freezes glibc's adaptive mmap threshold at
    128 KiB: every temporary array above it (an eigensolve makes thousands, 0.1-10 MB each)
    is then mapped fresh and page-faulted in again, which made each eigensolve of
    ``describe`` about 1.35x slower in Dask workers than in a local process pool.  Here the
    thresholds are set, through ``mallopt``, to the values glibc adapts to by itself: mmap
    above 32 MiB, trim above 64 MiB.  A worker keeps at most 64 MiB of freed memory.

    Returns
    -------
    bool
        Whether the thresholds were set (False off glibc, or if ``MALLOC_MMAP_THRESHOLD_``
        is set: an explicit choice of the user's, left alone).
    """
    import ctypes
    import sys

    if not sys.platform.startswith("linux") or "MALLOC_MMAP_THRESHOLD_" in os.environ:
        return False
    try:
        libc = ctypes.CDLL("libc.so.6")
        mallopt = libc.mallopt
    except (OSError, AttributeError):  # pragma: no cover - musl and friends
        return False
    m_trim_threshold, m_mmap_threshold = -1, -3  # <malloc.h>
    return bool(mallopt(m_mmap_threshold, _MMAP_THRESHOLD) == 1
                and mallopt(m_trim_threshold, 2 * _MMAP_THRESHOLD) == 1)


def _dask_work(task):
    """:func:`_work` in a Dask worker; its first call sets the worker process up.

    A worker process started by a nanny runs with one BLAS / OpenMP thread already (the
    nanny's ``distributed.nanny.pre-spawn-environ`` sets ``OMP_NUM_THREADS=1`` and friends)
    and with ``MALLOC_TRIM_THRESHOLD_=65536``, which slows eigensolves down by about 1.35x:
    on its first task each such process sets glibc's thresholds back to a plain process's
    (:func:`_malloc_as_a_plain_process`), whoever started the cluster.  Nothing is changed
    in a process that is not a child process (a threads-only cluster runs tasks in the
    client's own process).  Users who start their own cluster need do nothing; to get the
    same allocator for other Dask work, create the cluster after
    ``dask.config.set({"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None})``
    (no variable: glibc's adaptive thresholds).
    """
    global _WORKER_READY
    if not _WORKER_READY:
        import multiprocessing

        _WORKER_READY = True
        if multiprocessing.parent_process() is not None \
                and "MALLOC_TRIM_THRESHOLD_" in os.environ:
            _malloc_as_a_plain_process()
    return _work(task)


#: Periodic callbacks of a Dask worker's event loop that :func:`_run_dask` pauses: the
#: statistical profiler (a stack sample of the task thread every 10 ms) and the 20 ms tick
#: that watches the event loop.  Both take the GIL from the thread computing an eigensolve
#: dozens of times a second; with them paused, describe's eigensolves in Dask workers took
#: about 10 % less time (50 meshes, 2 workers: 27.4 / 25.5 s vs 30.7 / 28.7 s).
_SAMPLERS = ("profile", "profile-cycle", "tick")


def _pause_samplers(dask_worker):
    """Stop the worker's :data:`_SAMPLERS` (run on its event loop by ``client.run``)."""
    paused = []
    for name in _SAMPLERS:
        pc = dask_worker.periodic_callbacks.get(name)
        if pc is not None and pc.is_running():
            pc.stop()
            paused.append(name)
    dask_worker._cshape_paused = paused
    return paused


def _resume_samplers(dask_worker):
    """Restart what :func:`_pause_samplers` stopped on this worker."""
    resumed = []
    for name in getattr(dask_worker, "_cshape_paused", ()):
        pc = dask_worker.periodic_callbacks.get(name)
        if pc is not None and not pc.is_running():
            pc.start()
            resumed.append(name)
    dask_worker._cshape_paused = []
    return resumed


def _run_dask(tasks, client, finish):
    from distributed import Client, as_completed

    own = None
    if isinstance(client, (str, os.PathLike)):
        own = client = Client(str(client))
    elif not hasattr(client, "submit"):
        raise TypeError(
            f"client must be a dask.distributed.Client or a scheduler address string, "
            f"got {type(client).__name__}"
        )
    paused = False
    try:
        try:  # the workers' profiler and tick take the GIL from the eigensolves: pause them
            client.run(_pause_samplers)
            paused = True
        except Exception:  # noqa: BLE001 - e.g. a cluster that refuses client.run: run anyway
            pass
        todo = deque(tasks)
        nthreads = sum(client.nthreads().values()) or 1
        window = 4 * nthreads
        ac = as_completed()
        in_flight = 0
        index = {}

        def submit():
            t = todo.popleft()
            fut = client.submit(_dask_work, t, pure=False)
            index[fut.key] = t[0]
            ac.add(fut)

        while todo and in_flight < window:
            submit()
            in_flight += 1
        for fut in ac:
            try:
                res = fut.result()
            except Exception as exc:  # noqa: BLE001 - e.g. KilledWorker
                res = {"index": index[fut.key], "ok": False,
                       "error": f"{type(exc).__name__}: {exc}"}
            fut.release()
            finish(res["index"], res)
            if todo:
                submit()
    finally:
        if paused:
            with contextlib.suppress(Exception):  # a worker that died has nothing to resume
                client.run(_resume_samplers)
        if own is not None:
            own.close()
