"""The work of one mesh in a batch run: read, repair, eigensolve (in any process)."""

from __future__ import annotations

import contextlib
import os
import threading
import time
import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from ..mesh import Mesh, as_mesh, repair_mesh
from ..readers import load_mesh
from ..spectrum import SpectrumSettings, shape_dna
from .cache import CACHE_VERSION, _read_entry, mesh_key

if TYPE_CHECKING:
    from ..mesh import MeshLike


@dataclass(frozen=True)
class Task:
    """One eigensolve of a batch run, as sent to a worker (the caller's process, a worker
    process or a Dask worker).

    Attributes
    ----------
    index : int
        Row of the mesh in the collection.
    source : Mesh, (vertices, faces) or path
        The mesh, or the file to read it from.
    settings : SpectrumSettings
        How the eigenvalues are computed (checked once, by :func:`cshape.describe`).
    cache_dir : str or None
        The cache folder, or None when caching is off.
    key : str or None
        The mesh's content key; None when the worker computes it from the file.
    """

    index: int
    source: Any
    settings: SpectrumSettings
    cache_dir: str | None
    key: str | None


#: What a worker sends back: ``{'index', 'ok', 'lam', 'area', ...}`` or ``{'ok': False,
#: 'error'}``.
Result = dict[str, Any]


def load_source(source: str | os.PathLike[str] | MeshLike) -> Mesh:
    if isinstance(source, (str, os.PathLike)):
        return load_mesh(source)
    return as_mesh(source)


def _work(task: Task) -> Result:
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


def _work_inner(task: Task) -> Result:
    index, settings, key = task.index, task.settings, task.key
    t0 = time.perf_counter()
    try:
        mesh = load_source(task.source)
        if key is None:
            key = mesh_key(mesh, settings)
            if task.cache_dir is not None:
                hit = _read_entry(task.cache_dir, key, settings.N)
                if hit is not None:
                    hit.update(index=index, ok=True)
                    return hit
        fixed = repair_mesh(mesh)
        lam = shape_dna(fixed, **settings.as_kwargs())
        return {"index": index, "ok": True, "lam": lam, "area": float(fixed.area),
                "components": int(fixed.n_components),
                "key": key, "seconds": time.perf_counter() - t0, "cached": False,
                "n_vertices": mesh.n_vertices, "n_faces": mesh.n_faces,
                "params": {**settings.as_kwargs(), "cache_version": CACHE_VERSION}}
    except Exception as exc:  # noqa: BLE001 - reported and skipped by describe
        msg = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
        return {"index": index, "ok": False, "error": f"{type(exc).__name__}: {msg}"}


_THREAD_LIMITS: Any = None


def _blas_limit(blas_threads: int | None) -> contextlib.AbstractContextManager[Any]:
    """Context manager limiting BLAS / OpenMP threads (a no-op for None)."""

    if blas_threads is None:
        return contextlib.nullcontext()
    from threadpoolctl import threadpool_limits

    return threadpool_limits(limits=blas_threads)


def _init_worker(blas_threads: int | None) -> None:
    """Worker-process initialiser: limit BLAS threads for the life of the process."""
    global _THREAD_LIMITS
    if blas_threads is not None:
        from threadpoolctl import threadpool_limits

        _THREAD_LIMITS = threadpool_limits(limits=blas_threads)
