"""Thread policy of the eigensolver and its products over fixed row ranges.

How many threads a solve may use (:func:`solver_threads`), whether they help at each step
(:class:`ThreadChooser`, by timing the steps' block solves and products), BLAS limited to one thread
(:func:`one_blas_thread`), and :class:`RowSplit`, the tall products of the block Lanczos
iteration computed over fixed row ranges whose partial results are added in a fixed
order: the eigenvalues are the same bits with any number of threads.
"""

from __future__ import annotations

import contextlib
import functools
import multiprocessing
import os
import threading

import numpy as np

from .._checks import check_int

#: Problems with at least this many unknowns split their tall products into
#: :data:`ROW_PARTS` fixed row ranges, which threads may compute at once.
THREADS_MIN_UNKNOWNS = 50_000

#: Row ranges of a split product (fixed, so the result never depends on the threads).
ROW_PARTS = 4

#: Below this many rows the products of the Lanczos recurrence with its two newest blocks
#: are computed in the row-major order of the block they update (:meth:`RowSplit.sub_times`).
SMALL_PRODUCT_ROWS = 8_000


@functools.cache
def _blas_controller():
    """Return threadpoolctl's view of the BLAS libraries loaded now, or None.

    Cached: building it scans every shared library of the process.  None if threadpoolctl is
    missing.
    """
    try:
        from threadpoolctl import ThreadpoolController
    except ImportError:  # pragma: no cover - threadpoolctl is a dependency
        return None
    return ThreadpoolController()


def one_blas_thread():
    """Context limiting BLAS to one thread (threadpoolctl), a no-op if it is missing.

    The products of the block Lanczos iteration are tall and skinny (``n x b``), hence
    memory bound: extra BLAS threads add little, and spinning BLAS worker threads slow
    them down as soon as another process uses the cores.  The BLAS libraries are those
    loaded when this was first called (NumPy's and SciPy's; CHOLMOD's BLAS is
    single-threaded).
    """
    controller = _blas_controller()
    if controller is None:  # pragma: no cover
        return contextlib.nullcontext()
    return controller.limit(limits=1, user_api="blas")


def solver_threads(n: int) -> int:
    """Return the most threads a solve of ``n`` unknowns may use (the policy).

    * ``CSHAPE_THREADS`` (environment), a positive integer, decides if set;
    * else 1 below :data:`THREADS_MIN_UNKNOWNS` unknowns, in a child process (a process
      pool's or a Dask worker: batch runs already use one process per core), and off the
      main thread (e.g. a threads-only Dask cluster);
    * else the CPUs this process may use, at most :data:`ROW_PARTS`.

    The load average does not enter: it lags by a minute and counts the threads of other
    libraries as well (a BLAS pool that has just spun).  Whether the threads help *now*
    is measured during the solve instead (:class:`ThreadChooser`), and the eigenvalues do
    not depend on it: the products are split into the same :data:`ROW_PARTS` row ranges,
    added in the same order, and the block solves into the same two halves, with any
    number of threads (one included).

    Parameters
    ----------
    n : int
        Number of unknowns.

    Returns
    -------
    int
        At least 1.
    """
    n = check_int("n", n, min=0)
    env = os.environ.get("CSHAPE_THREADS", "").strip()
    if env:
        if not env.isdigit() or int(env) < 1:
            raise ValueError(f"CSHAPE_THREADS must be a positive integer, got {env!r}")
        return int(env)
    if n < THREADS_MIN_UNKNOWNS:
        return 1
    if multiprocessing.parent_process() is not None \
            or threading.current_thread() is not threading.main_thread():
        return 1
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        cores = os.cpu_count() or 1
    return int(max(1, min(cores, ROW_PARTS)))


class ThreadChooser:
    """Threads of a job done at each Lanczos step, chosen by timing it on ``threads`` and on 1.

    On a machine whose other cores are busy (other processes, other virtual machines on
    the same host) a second thread gains nothing and its synchronisation costs time; on
    a quiet one it speeds the solves and the products up, by how much depends on the
    processor and its memory.  Which holds is measured in the solve itself, at no cost
    for a calibration: steps ``1 .. PROBE_STEPS`` alternate ``threads`` and one thread,
    each timing a job that costs the same at every step (:meth:`record`): the eigensolver
    keeps one chooser for the block solve (its halves at once, or the block in one solve)
    and one for the first orthogonalisation pass against the two newest blocks (the
    products over the rows); the setting of the fastest such time (``threads`` only if
    faster by the factor :data:`GAIN`) is kept until the next probe, every
    :data:`REPROBE_EVERY` steps.  The choice changes the timing only: the results are
    the same bits with any number of threads.

    Parameters
    ----------
    threads : int
        The most threads (:func:`solver_threads`); 1 never probes.
    """

    PROBE_STEPS = 4
    REPROBE_EVERY = 32
    GAIN = 0.95

    def __init__(self, threads):
        self.max = max(1, int(threads))
        self.current = self.max
        self.steps = 0
        self.samples = {}
        self.history = []  # (step, threads, solve seconds), for benchmarks

    def start_step(self):
        """Return the threads of the next step."""
        phase = self.steps % self.REPROBE_EVERY
        self.steps += 1
        if self.max == 1:
            return 1
        if 1 <= phase <= self.PROBE_STEPS:
            self.current = self.max if phase % 2 else 1
        elif phase == self.PROBE_STEPS + 1 and self.samples:
            fast = min(self.samples.get(self.max, [np.inf]))
            slow = min(self.samples.get(1, [np.inf]))
            self.current = self.max if fast <= self.GAIN * slow else 1
            self.samples = {}
        return self.current

    def record(self, seconds):
        """Record the time of the timed job of the step just started."""
        self.history.append((self.steps - 1, self.current, seconds))
        if 1 <= (self.steps - 1) % self.REPROBE_EVERY <= self.PROBE_STEPS:
            self.samples.setdefault(self.current, []).append(seconds)


def times(V, C):
    """``V @ C`` for a column-major basis ``V`` (k, m) and a small ``C`` (m, b).

    Computed as ``(C.T @ V.T).T``: the same product, but OpenBLAS streams the basis
    faster in this orientation.
    """
    return (C.T @ V.T).T


class RowSplit:
    """Products over the rows of tall (n, .) arrays, in fixed row ranges, maybe threaded.

    Reductions over the rows (``X.T @ Y``) add the ranges' partial products in range
    order and row-wise products are computed range by range, so every result is the same
    bit for bit with any number of threads.  NumPy's BLAS calls release the GIL: with
    ``threads > 1`` the ranges run at once (BLAS itself on one thread each).

    Parameters
    ----------
    n : int
        Number of rows (unknowns); from :data:`THREADS_MIN_UNKNOWNS` on the rows are
        split into :data:`ROW_PARTS` ranges.
    B : scipy.sparse matrix, shape (n, n)
        The mass matrix, for :meth:`bmul`.
    threads : int, default=1
        The most threads; :attr:`threads` may lower it between products.
    rhs_order : {'C', 'F'}, default='C'
        Memory order of the B-images handed to the solver.
    """

    def __init__(self, n, B, threads=1, rhs_order="C"):
        self.rhs_order = rhs_order
        parts = ROW_PARTS if n >= THREADS_MIN_UNKNOWNS else 1
        edges = np.linspace(0, n, parts + 1).astype(int)
        self.ranges = list(zip(edges[:-1], edges[1:], strict=True))
        # row ranges of B in CSC: the same sums in the same order (same bits) as CSR, but
        # faster for blocks of vectors
        self.B_rows = [B[a:b].tocsc() for a, b in self.ranges] if parts > 1 else [B]
        self.single = parts == 1  # one range: the plain products, without dispatch
        self.pool = None
        #: Threads of the next products (at most ``threads``; 1: in the calling thread).
        self.threads = threads
        if threads > 1 and parts > 1:
            from concurrent.futures import ThreadPoolExecutor

            self.pool = ThreadPoolExecutor(min(threads, parts))

    def close(self):
        """Shut the thread pool down (if any)."""
        if self.pool is not None:
            self.pool.shutdown()

    def _map(self, fn):
        if self.pool is None or self.threads < 2:
            return [fn(i, a, b) for i, (a, b) in enumerate(self.ranges)]
        futures = [self.pool.submit(fn, i, a, b) for i, (a, b) in enumerate(self.ranges)]
        return [f.result() for f in futures]

    def tdot(self, X, Y):
        """``X.T @ Y`` for X (n, p), Y (n, q).

        Computed as ``(Y.T @ X).T``: the same product, but OpenBLAS streams a column-major
        basis ``X`` faster in this orientation.
        """
        if self.single:
            return (Y.T @ X).T
        parts = self._map(lambda i, a, b: (Y[a:b].T @ X[a:b]).T)
        out = parts[0]
        for part in parts[1:]:
            out = out + part
        return out

    def sub_times(self, W, V, C):
        """``W -= V @ C`` in place, for W (n, q), V (n, p) column-major, C (p, q).

        A product with the two newest blocks (``p <= 16``) of fewer than
        :data:`SMALL_PRODUCT_ROWS` rows is computed in W's row-major order: then the
        subtraction runs along memory, faster than the column-major product of
        :func:`times`.
        """
        if self.single:
            if V.shape[1] <= 16 and V.shape[0] < SMALL_PRODUCT_ROWS and W.flags.c_contiguous:
                W -= V @ C
            else:
                W -= times(V, C)
            return

        def f(i, a, b):
            W[a:b] -= times(V[a:b], C)
        self._map(f)

    def times(self, X, C, order="C"):
        """``X @ C`` as a new (n, q) array in the given memory order."""
        if self.single:
            return times(X, C) if order == "F" else np.ascontiguousarray(X @ C)
        out = np.empty((X.shape[0], C.shape[1]), order=order)

        def f(i, a, b):
            out[a:b] = times(X[a:b], C) if order == "F" else X[a:b] @ C
        self._map(f)
        return out

    def bmul(self, X):
        """``B @ X`` (the rows of a sparse product are independent: same bits)."""
        if self.single:
            return self.B_rows[0] @ X
        out = np.empty((X.shape[0], X.shape[1]))

        def f(i, a, b):
            out[a:b] = self.B_rows[i] @ X
        self._map(f)
        return out

    def copy_into(self, dst, src):
        """``dst[:] = src`` range by range."""
        if self.single:
            dst[...] = src
            return

        def f(i, a, b):
            dst[a:b] = src[a:b]
        self._map(f)
