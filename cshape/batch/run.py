"""Batch runs: :func:`describe` computes the Shape-DNA of every mesh of a collection (cached,
resumable, in worker processes or on a Dask cluster) into a :class:`DescriptorTable`.
"""

from __future__ import annotations

import os
import warnings
from collections import Counter, deque
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from .._checks import (
    check_bool,
    check_choice,
    check_int,
    check_n_jobs,
    check_path,
)
from .._files import atomic_write
from ..mesh import CShapeWarning, Mesh, as_mesh, is_mesh_like
from ..spectrum import (
    SpectrumSettings,
    components_message,
    estimate_seconds,
    long_solve_message,
)
from ._dask import _run_dask
from .cache import _file_alias, _read_alias, _read_entry, _write_entry, default_cache_dir, mesh_key
from .table import DescriptorTable
from .work import Task, _blas_limit, _init_worker, _work

if TYPE_CHECKING:
    from collections.abc import Callable, Sequence

    from .work import Result


# =========================================================================== records
class _Failed:
    """Stands for a mesh whose record could not produce it; describe reports the message."""

    def __init__(self, message: str) -> None:
        self.message = message


def _has_attr(cls: type, obj: object, name: str) -> bool:
    """``hasattr`` without running a property (which may load a mesh)."""
    import inspect

    try:
        inspect.getattr_static(obj, name)
        return True
    except AttributeError:
        return False


def collection_records(collection: Any) -> list[tuple[str, str, Any]]:
    """[(name, label, source)] from the accepted collection forms (see :func:`describe`)."""
    if isinstance(collection, (str, os.PathLike, Mesh)):
        raise TypeError(
            "collection must be an iterable of meshes, paths or records, got a single "
            f"{type(collection).__name__}; wrap it in a list"
        )
    items: list[Any] = (list(collection.items()) if isinstance(collection, Mapping)
                        else list(collection))
    out: list[list[Any]] = []
    path_rows: list[int] = []
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
        elif not isinstance(item, (tuple, list)) and is_mesh_like(item):
            out.append([f"mesh{i}", "", as_mesh(item)])
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
def describe(collection: Any, N: int = 100, *, bc: str = "neumann",
             mass: str = "consistent", cache_dir: str | os.PathLike[str] | bool | None = None,
             n_jobs: int | None = 1, client: Any = None, blas_threads: int | None = 1,
             progress: bool = True, on_error: str = "warn",
             refine: str = "none") -> DescriptorTable:
    """Compute the eigenvalues of every mesh of a collection: cached, resumable, parallel.

    Parameters
    ----------
    collection : iterable
        The meshes, each given as one of

        * a path (``str`` or ``os.PathLike``) of a mesh file, read by
          :func:`cshape.load_mesh` in the worker; named by its file stem (by the whole path
          when stems collide);
        * a :class:`cshape.Mesh`, a ``(vertices, faces)`` pair or a mesh object of another
          library (read by :func:`cshape.mesh.as_mesh`), named ``mesh<i>``;
        * a ``(name, mesh)`` or ``(name, label, mesh)`` tuple, ``mesh`` as above;
        * a record with attributes ``name``, ``label`` (optional) and ``mesh`` (or
          ``path``), e.g. the records of a cshape data collection;

        or a mapping ``{name: mesh}``.  Names must be unique.
    N : int, default=100
        Number of eigenvalues per shape (Shape-DNA length).  Every descriptor of at most
        ``N`` eigenvalues (any ``M``, any transform) is derived from the table later,
        without another eigensolve.
    bc : {'neumann', 'dirichlet'}, default='neumann'
        Boundary condition on the meshes' boundaries (see :func:`cshape.shape_dna`).
    mass : {'consistent', 'lumped', 'mixed'}, default='consistent'
        Mass matrix ``B`` (see :func:`cshape.fem_matrices`).
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
        them).  Takes precedence over ``n_jobs``.  Clusters need no setup: describe tunes
        each worker for the eigensolves while it runs and restores it afterwards (what it
        changes, and why, is in ``benchmarks/SCALE.md``, "Dask workers").
    blas_threads : int or None, default=1
        BLAS / OpenMP threads for each eigensolve, in this process (``n_jobs=1``) and in
        every local worker process; ``None`` leaves the library default.  One thread is
        the right choice for many small and medium meshes (measurements in
        ``benchmarks/SCALE.md``).  Dask workers started by a nanny already use one thread.
    progress : bool, default=True
        Show a tqdm progress bar.
    on_error : {'warn', 'raise'}, default='warn'
        ``'warn'``: a mesh that fails (unreadable file, too few vertices for ``N``, ...) is
        skipped, listed in ``table.failures`` and reported in one warning at the end.
        ``'raise'``: stop at the first failure with a ``RuntimeError``.
    refine : {'none', 'extrapolate'}, default='none'
        How the eigenvalues are computed (see :func:`cshape.shape_dna`); recorded in the
        table, and cached apart from the other kinds.

    Returns
    -------
    DescriptorTable
        The successful meshes in the order of ``collection``: ``names``, ``labels``,
        ``lam`` (p, N), ``areas`` (p,), ``seconds``, ``cached`` and ``failures``;
        descriptors through :meth:`DescriptorTable.descriptors`.

    Raises
    ------
    TypeError
        An argument of the wrong type (``N=2.5``, ``progress=1``,
        ``cache_dir=3``), with the message every other function gives for it.
    ValueError
        An argument out of range (``N=0``, an unknown ``bc``, ``mass`` or ``on_error``,
        ``n_jobs=0``), before any mesh is read.
    RuntimeError
        With ``on_error='raise'``, the first mesh that fails.

    Warns
    -----
    CShapeWarning
        For failed meshes, corrupt cache entries (recomputed), and the warnings of the
        mesh stage (repairs, several components) prefixed by the mesh name.

    Notes
    -----
    If a local worker process dies (killed, out of memory), the meshes it had not finished
    are reported as failures; the finished ones are already cached, so calling
    ``describe`` again computes only what is missing.

    Examples
    --------
    >>> from cshape import shapes
    >>> from cshape.batch import describe
    >>> meshes = [("s1", "sphere", shapes.icosphere(2)), ("s2", "sphere", shapes.icosphere(3)),
    ...           ("t1", "torus", shapes.torus(24, 12))]
    >>> table = describe(meshes, N=30, cache_dir=False, progress=False)
    >>> table
    DescriptorTable(3 shapes, N=30, mass='consistent', 2 classes)
    >>> from cshape import Descriptor
    >>> table.descriptors(Descriptor("cshape", N=30, M=4)).shape
    (3, 9)
    >>> table.distance_matrix(Descriptor("shape-dna", N=30)).shape
    (3, 3)
    """
    settings = SpectrumSettings(N, bc, mass, refine)  # checked here, once
    n_jobs = check_n_jobs(n_jobs)
    n_jobs = 1 if n_jobs is None else (os.cpu_count() or 1) if n_jobs == -1 else n_jobs
    if blas_threads is not None:
        blas_threads = check_int("blas_threads", blas_threads, min=1)
    progress = check_bool("progress", progress)
    on_error = check_choice("on_error", on_error, ("warn", "raise"))
    cache = _cache_folder(cache_dir)
    from tqdm.auto import tqdm

    run = _Run(collection_records(collection), settings, cache, on_error)
    run.bar = tqdm(total=len(run.records), desc="describe", unit="mesh",
                   disable=not progress)
    try:
        tasks = run.tasks()  # what the cache does not hold
        _warn_long_run(tasks, run.records, settings)
        if client is not None:
            _run_dask(tasks, client, run.finish)
        elif n_jobs == 1 or len(tasks) <= 1:
            with _blas_limit(blas_threads):
                for t in tasks:
                    run.finish(t.index, _work(t))
        else:
            _run_processes(tasks, n_jobs, run.finish, run.failures, blas_threads)
    finally:
        run.bar.close()
    return run.table()


def _cache_folder(cache_dir: str | os.PathLike[str] | bool | None) -> Path | None:
    """The cache folder of ``cache_dir`` (created), or None when caching is off."""
    if cache_dir is False:
        return None
    cache = default_cache_dir() if cache_dir is None else check_path("cache_dir", cache_dir)
    cache.mkdir(parents=True, exist_ok=True)
    return cache


class _Run:
    """The state of one :func:`describe` call: the records, their results and failures.

    :meth:`tasks` looks each mesh up in the cache (finishing the hits) and returns the
    eigensolves left to do; :meth:`finish` takes a result as it comes back (from this
    process, a worker process or a Dask worker); :meth:`table` makes the
    :class:`DescriptorTable` of the successful meshes.
    """

    def __init__(self, records: list[tuple[str, str, Any]], settings: SpectrumSettings,
                 cache: Path | None, on_error: str) -> None:
        self.records, self.settings = records, settings
        self.cache, self.on_error = cache, on_error
        self.results: list[Any] = [None] * len(records)  # a Result once row i is done
        self.failures: dict[int, str] = {}
        # row -> alias file of a mesh given by path (see the module notes)
        self.aliases: dict[int, Path | None] = {}
        self.bar: Any = None

    # ------------------------------------------------------------------ before the work
    def tasks(self) -> list[Task]:
        """Meshes in memory, and files seen before unchanged: looked up in the cache here,
        before any task is sent; the tasks of the others."""
        tasks: list[Task] = []
        for i, (_name, _label, src) in enumerate(self.records):
            key = self._lookup(i, src)
            if key is not False:
                tasks.append(Task(i, src, self.settings,
                                  None if self.cache is None else str(self.cache), key))
        return tasks

    def _lookup(self, i: int, src: Any) -> str | None | Literal[False]:
        """False when row ``i`` is finished (a cache hit or a failure), else its cache key
        (None for a mesh given by path: the worker reads the file and computes it)."""
        cache, N = self.cache, self.settings.N
        if isinstance(src, _Failed):
            self.finish(i, {"ok": False, "error": src.message})
            return False
        if isinstance(src, (str, os.PathLike)):
            if cache is not None:
                alias = self.aliases[i] = _file_alias(cache, src, self.settings)
                known = None if alias is None else _read_alias(alias)
                hit = None if known is None else _read_entry(cache, known, N)
                if hit is not None:
                    self.finish(i, {**hit, "ok": True})
                    return False
            return None
        try:
            key = mesh_key(src, self.settings)
        except (TypeError, ValueError) as exc:
            self.finish(i, {"ok": False, "error": f"{type(exc).__name__}: {exc}"})
            return False
        hit = None if cache is None else _read_entry(cache, key, N)
        if hit is not None:
            self.finish(i, {**hit, "ok": True})
            return False
        return key

    # ------------------------------------------------------------------ as results come
    def finish(self, i: int, res: Result) -> None:
        """Take the result of row ``i``: warn, cache, keep (or record the failure)."""
        name = self.records[i][0]
        for msg in res.get("warnings", ()):
            warnings.warn(f"{name}: {msg}", CShapeWarning, stacklevel=3)
        if res["ok"]:
            if res["cached"]:
                self._warn_pieces_again(name, res)
            else:
                self._write_cache(name, res)
            self._write_alias(i, res)
            self.results[i] = res
        else:
            if self.on_error == "raise":
                raise RuntimeError(f"describe: mesh {name!r} failed: {res['error']}")
            self.failures[i] = res["error"]
        self.bar.update(1)

    def _warn_pieces_again(self, name: str, res: Result) -> None:
        """The warning the eigensolve gave for a mesh of several pieces, again."""
        pieces = res["components"]
        if pieces > 1:
            warnings.warn(f"{name}: {components_message(pieces)}", CShapeWarning,
                          stacklevel=4)

    def _write_cache(self, name: str, res: Result) -> None:
        if self.cache is None:
            return
        try:
            _write_entry(self.cache, res)
        except OSError as exc:  # a full or read-only disk must not lose the result
            warnings.warn(f"{name}: could not write its cache entry ({exc}); the result is "
                          "kept but will be recomputed next time", CShapeWarning, stacklevel=4)

    def _write_alias(self, i: int, res: Result) -> None:
        alias = self.aliases.get(i)
        if alias is not None and _read_alias(alias) != res["key"]:
            try:
                alias.parent.mkdir(exist_ok=True)
                atomic_write(alias, lambda f: f.write(res["key"]), binary=False)
            except OSError:
                pass  # only the shortcut is lost: the file is read again next time

    # ------------------------------------------------------------------ the table
    def table(self) -> DescriptorTable:
        """The successful meshes in the order of the collection; one warning lists the
        failures."""
        records, results, N = self.records, self.results, self.settings.N
        p = len(records)
        ok = [i for i in range(p) if results[i] is not None]
        fail_list = [(records[i][0], self.failures[i]) for i in sorted(self.failures)]
        if fail_list:
            shown = "; ".join(f"{n} ({m})" for n, m in fail_list[:5])
            more = f"; and {len(fail_list) - 5} more" if len(fail_list) > 5 else ""
            warnings.warn(
                f"describe: {len(fail_list)} of {p} meshes failed and were skipped "
                f"(see table.failures): {shown}{more}", CShapeWarning, stacklevel=3)
        return DescriptorTable(
            [records[i][0] for i in ok],
            np.array([results[i]["lam"][:N] for i in ok]).reshape(len(ok), N),
            [results[i]["area"] for i in ok],
            [records[i][1] for i in ok], bc=self.settings.bc, mass=self.settings.mass,
            seconds=[results[i]["seconds"] for i in ok],
            cached=[results[i]["cached"] for i in ok], failures=fail_list,
            refine=self.settings.refine,
            components=[results[i]["components"] for i in ok])


#: Below this N no eigensolve of a mesh that fits in memory is estimated to take long
#: enough to read the meshes twice for an estimate (see :func:`_warn_long_run`).
_ESTIMATE_MIN_N = 300


def _warn_long_run(tasks: Sequence[Task], records: Sequence[tuple[str, str, Any]],
                   settings: SpectrumSettings) -> None:
    """Warn, before the eigensolves start, when they are estimated to take long.

    Only for ``N >= _ESTIMATE_MIN_N`` (the vertex counts of meshes given by path are read
    for it, from the file).  The estimate is ``cshape.spectrum.estimate_seconds`` summed over the
    meshes not found in the cache.
    """
    N = settings.N
    if N < _ESTIMATE_MIN_N or not tasks:
        return
    refined = settings.refine != "none"
    from ..readers import load_mesh

    sizes: list[tuple[int, str]] = []
    for t in tasks:
        src = t.source
        try:
            mesh = load_mesh(src, repair=False) if isinstance(src, (str, os.PathLike)) \
                else src
            n = mesh.n_vertices if isinstance(mesh, Mesh) else len(mesh[0])
        except Exception:  # noqa: BLE001 - the run itself reports the failure
            continue
        sizes.append((n, records[t.index][0]))
    if not sizes:
        return
    # refine='extrapolate' solves the midpoint subdivision too: about 4n unknowns
    total = sum(estimate_seconds(n, N) + (estimate_seconds(4 * n, N) if refined else 0.0)
                for n, _ in sizes)
    n_big, name = max(sizes)
    one = long_solve_message(n_big, N)
    if one is None and total < 2 * 60.0:
        return
    big = estimate_seconds(n_big, N)
    hint = one.split("; ", 1)[1] if one and "; " in one else ""
    warnings.warn(
        f"{LONG_RUN_PREFIX} {len(sizes)} eigensolve{'s' if len(sizes) > 1 else ''} of "
        f"N={N}{' (and of their midpoint subdivisions)' if refined else ''}, about "
        f"{total / 60:.0f} min in all on one core (a rough estimate, "
        f"1e-8 n N^2 s); the largest, {name} ({n_big} vertices), about "
        f"{big / 60:.0f} min" + (f"; {hint}" if hint else ""),
        CShapeWarning, stacklevel=3)


#: How the warning of :func:`_warn_long_run` starts (the command line shows it at once).
LONG_RUN_PREFIX = "long run ahead:"


def _run_processes(tasks: Sequence[Task], n_jobs: int, finish: Callable[[int, Result], None],
                   failures: dict[int, str], blas_threads: int | None) -> None:
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
        pending: dict[Any, Task] = {}
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
                    finish(t.index, res)
        except BrokenProcessPool:
            lost = list(pending.values()) + list(todo)
            for t in lost:
                failures[t.index] = ("worker process died (killed or crashed) before finishing "
                                  "this mesh; run describe again to resume")
        finally:
            for fut in pending:
                fut.cancel()


#: glibc's ceiling for its adaptive mmap threshold on 64-bit systems (32 MiB): the value a
#: plain process settles at after freeing a few large arrays.
