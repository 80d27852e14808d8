"""Dask plumbing of :func:`cshape.batch.describe`: the worker task, allocator tuning and the
workers' samplers paused during a run.
"""

from __future__ import annotations

import contextlib
import os
from collections import deque
from typing import TYPE_CHECKING, Any

from .work import _work

if TYPE_CHECKING:
    from collections.abc import Callable, Iterable

    from .work import Result, Task

_MMAP_THRESHOLD = 32 * 2**20
_WORKER_READY = False


def _malloc_as_a_plain_process() -> bool:
    """Undo the Dask nanny's ``MALLOC_TRIM_THRESHOLD_`` for this worker process (glibc only).

    The nanny starts workers with ``MALLOC_TRIM_THRESHOLD_=65536`` (its
    ``distributed.nanny.pre-spawn-environ``), to hand freed memory back to the system
    promptly.  Setting any such variable also freezes glibc's adaptive mmap threshold at
    128 KiB: every temporary array above it (an eigensolve makes thousands, 0.1-10 MB each)
    is then mapped fresh and page-faulted in again, which slows the eigensolves of
    ``describe`` in Dask workers (``benchmarks/SCALE.md``, "Operations notes").  Here the
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


def _dask_work(task: Task) -> Result:
    """:func:`_work` in a Dask worker; its first call sets the worker process up.

    A worker process started by a nanny runs with one BLAS / OpenMP thread already (the
    nanny's ``distributed.nanny.pre-spawn-environ`` sets ``OMP_NUM_THREADS=1`` and friends)
    and with ``MALLOC_TRIM_THRESHOLD_=65536``, which slows eigensolves down: on its first
    task each such process sets glibc's thresholds back to a plain process's
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
#: dozens of times a second (figures: ``benchmarks/SCALE.md``, "Many meshes").
_SAMPLERS = ("profile", "profile-cycle", "tick")


def _pause_samplers(dask_worker: Any) -> list[str]:
    """Stop the worker's :data:`_SAMPLERS` (run on its event loop by ``client.run``)."""
    paused: list[str] = []
    for name in _SAMPLERS:
        pc = dask_worker.periodic_callbacks.get(name)
        if pc is not None and pc.is_running():
            pc.stop()
            paused.append(name)
    dask_worker._cshape_paused = paused
    return paused


def _resume_samplers(dask_worker: Any) -> list[str]:
    """Restart what :func:`_pause_samplers` stopped on this worker."""
    resumed: list[str] = []
    for name in getattr(dask_worker, "_cshape_paused", ()):
        pc = dask_worker.periodic_callbacks.get(name)
        if pc is not None and not pc.is_running():
            pc.start()
            resumed.append(name)
    dask_worker._cshape_paused = []
    return resumed


def _run_dask(tasks: Iterable[Task], client: Any, finish: Callable[[int, Result], None]
              ) -> None:
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
        index: dict[Any, int] = {}  # future's key -> row

        def submit() -> None:
            t = todo.popleft()
            fut = client.submit(_dask_work, t, pure=False)
            index[fut.key] = t.index
            ac.add(fut)

        while todo and in_flight < window:
            submit()
            in_flight += 1
        for fut in ac:
            try:
                res: Result = fut.result()
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
