"""Stage 3 of the pipeline: the eigensolve ``A f = -lam B f`` (Eq. 3) for the N smallest lam.

With ``K = -A`` (positive semidefinite) the problem is ``K f = lam B f``.  Small problems
(at most :data:`DENSE_LIMIT` unknowns, or ``N`` above a third of them) are solved densely
with LAPACK.  Larger ones use a **block shift-invert Lanczos** method written here on top
of one sparse Cholesky factorisation:

1. Factorise ``S = K - sigma B`` once (CHOLMOD, supernodal ``L L^T``: the build in the
   ``cvxopt`` wheel with an optimised BLAS, else the ``cholespy`` wheel, else SciPy's
   SuperLU; see :mod:`cshape._cholmod`) with a shift ``sigma < 0`` below the whole
   spectrum, so ``S`` is positive definite.  Default ``sigma = -0.01 * 4 pi N / area``:
   one hundredth of Weyl's estimate ``lam_N ~ 4 pi N / area`` (-1 for the unit sphere and N = 100).
2. The operator ``OP = S^{-1} B`` is self-adjoint in the B-inner product and has the
   eigenvalues ``theta = 1 / (lam - sigma)``: the N smallest ``lam`` are its N largest
   ``theta``.  A block Krylov space of ``OP`` is grown from a fixed random block of
   ``b = BLOCK_SIZE = 8`` vectors.  Each step applies ``S^{-1}`` to ``b`` right-hand sides at
   once (one multi-right-hand-side CHOLMOD solve) and B-orthonormalises the new block with
   dense matrix products: classical Gram-Schmidt twice against the two newest blocks (the
   block Lanczos recurrence), Cholesky-QR inside the block, and *partial
   re-orthogonalisation* against the older blocks.  In exact arithmetic the recurrence
   alone keeps the basis orthogonal; in floating point orthogonality is lost gradually
   along the converged Ritz vectors.  The pass over the older blocks therefore runs only
   every one to few steps: its coefficients measure the loss accumulated since the previous
   pass, and the interval adapts to keep it below 1e-8 (a pass at every step once it is
   exceeded), under ``sqrt(eps) ~ 1.5e-8`` (semi-orthogonality, which keeps the Ritz values
   accurate to rounding; Simon 1984).  With the shift inside the spectrum (below) the bound
   is 3e-8, a measured choice a little above it (:data:`_OMEGA_MAX_INSIDE`): the same
   eigenvalues within 1e-10 relative of a tight reference on 15 meshes for N = 20 to 300,
   for up to a fifth fewer passes.
   **Shift inside the spectrum** (at most :data:`INSIDE_LIMIT` unknowns, the default
   shift): ``sigma = 0.65 * 4 pi N / area`` instead, near the middle of the wanted
   eigenvalues, and ``S`` is factorised as ``L D L^T`` (CHOLMOD, simplicial, no
   pivoting).  By Sylvester's law of inertia the number ``p`` of negative entries of
   ``D`` is exactly the number of eigenvalues below ``sigma``; they become the negative
   ``theta``, and the wanted pairs are all ``p`` of them and the ``N - p`` largest positive
   ones.  Both ends of the wanted part now lie about N/2 eigenvalues from the shift, and
   the Krylov space that resolves them is a third smaller (about ``1.5 N + 75`` instead of
   ``2.4 N + 75`` dimensions for N = 100): a third fewer solves, about half the
   orthogonalisation.  The factorisation does not pivot, so its accuracy is checked (the
   backward error of a solve; another shift otherwise), the smallest eigenvalues, farthest
   from the shift, get a tighter residual tolerance and a last Rayleigh-Ritz step with a
   refined solve (:func:`_solve_inside`; with or without eigenvectors: both give the
   same eigenvalues).  Measured against a tight reference on 15 meshes for N = 20 to
   300: within 6e-11 relative up to N = 200, 2.1e-10 at N = 300.
3. The projection of ``OP`` onto the basis is block tridiagonal (bandwidth ``b``); its
   top eigenpairs (Rayleigh-Ritz, LAPACK's divide and conquer) give Ritz values ``theta_i``
   and, from the Lanczos relation, the residual norms ``||OP x_i - theta_i x_i||_B`` at no
   cost.  The iteration stops when all N wanted pairs have a residual at most
   ``RESIDUAL_TOL * theta_i`` (1e-6).  The projected problem is solved only where the
   pairs may have converged (first at a Krylov dimension of about ``2.3 N + 70``, from
   measurements, then where the missing ones are predicted to have converged; about two
   times per solve).  Ritz values of a self-adjoint operator are accurate
   to the *square* of the residual over the spectral gap, so the eigenvalues agree with
   ARPACK's full-accuracy ones to about 1e-12 relative.  Eigenvectors, when asked for,
   are made B-orthonormal to rounding by Loewdin's symmetric orthonormalisation.

Why it is faster than ARPACK's implicitly restarted Lanczos (``scipy.sparse.linalg.eigsh``
in shift-invert mode, as used by LaPy): for N = 100 both need about 3.5 N solves, but
here they come in blocks, and ARPACK's vector-at-a-time re-orthogonalisation against its
whole basis plus its restarts, which dominate on large meshes, become a few memory-bound
matrix products over a basis that is re-orthogonalised only when needed.  See
``benchmarks/bench_spectrum.py``, ``benchmarks/README.md`` and ``benchmarks/SCALE.md``
("The eigensolver") for measurements.

Threads.  The factorisation runs on one core.  The solves are bound by reading the factor:
with two threads on a big mesh (``THREADS_MIN_UNKNOWNS``) the block grows to
``BLOCK_SIZE_THREADED = 16`` vectors whose solve runs as two halves of 8 at once, each
reading the factor once for 8 vectors (the columns' solves are independent).  The products
of the Lanczos loop over the basis (``n`` rows) are split, for
``n >= THREADS_MIN_UNKNOWNS``, into ``ROW_PARTS`` fixed row ranges that threads may compute
at once, each with one BLAS thread; the partial sums are added in a fixed order, so with a
given block size the eigenvalues are the same bits with any number of threads (one thread
and two differ by the block size: by rounding, about 1e-12 relative).  How many is decided
by :func:`solver_threads`: the environment variable ``CSHAPE_THREADS`` if set, else one in
worker processes (``describe(n_jobs=...)``, Dask) and for small meshes, else the cores that
look free by the load average.

Completeness.  Below an inside shift the count is exact: the iteration stops only when all
``p`` negative Ritz values (the inertia) have converged.  Above it, as with a shift below
the spectrum, a Krylov method cannot see a copy of an eigenvalue that its start vectors
miss.  A block of ``b`` random vectors resolves multiplicities up to ``b``; the symmetry of
a connected surface in space gives at most 5 (the icosahedral group), e.g. an icosphere
splits the ``2l + 1`` copies of the sphere's ``l(l+1)`` into groups of at most 5.  Larger
multiplicities come from identical connected components, so a mesh with several
components is solved one component at a time and the spectra are merged.  If the Krylov
space becomes invariant (a breakdown), it is continued with fresh random vectors and the
convergence test waits until they have been developed as far as the first ones.  The
solver is checked against dense LAPACK, ARPACK with ``tol=0`` and the exact sphere
multiplicities in ``tests/test_spectrum_solver.py``.  If the block method does not
converge within its dimension budget (``max(6 N, N + 40 b)``) it falls back to ARPACK with
``tol=0`` on the same factorisation.  Both paths are deterministic (fixed seeds).
"""

from __future__ import annotations

import contextlib
import functools
import mmap
import multiprocessing
import os
import threading
import warnings
from typing import Literal, overload

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph
import scipy.sparse.linalg as spla
from numpy.typing import NDArray

from . import _cholmod
from ._checks import check_bool, check_int, check_real
from .fem import fem
from .mesh import CShapeWarning, MeshLike, as_mesh, repair_mesh

__all__ = ["eigenpairs", "estimate_seconds", "shape_dna", "solve_eigenproblem",
           "solver_threads"]

#: Problems with at most this many unknowns are solved densely (N = 100, one thread: dense
#: LAPACK and the sparse path take the same time at 642 unknowns, dense 2.2x longer at 829).
DENSE_LIMIT = 700

#: Problems with at most this many unknowns put the shift inside the spectrum
#: (:func:`_solve_inside`).  Its factorisation is simplicial (CHOLMOD has no supernodal
#: ``L D L^T``) and grows faster with the size than the supernodal ``L L^T`` of the shift
#: below: CPU time of the shift below over the inside shift (one thread, N = 100), 1.2-1.6
#: at 1K-3K unknowns, 1.1-1.4 at 8K-13K (real meshes, icosphere, torus), 1.15-1.19 on the
#: 22K real meshes but 0.89 on a 22K torus and 0.92 at 30K; at 41K 0.6, at 163,842
#: unknowns the factorisation alone takes 4.7 s against 0.44 s.
INSIDE_LIMIT = 25_000

#: Fewer wanted eigenvalues keep the shift below the spectrum: the Krylov spaces of both
#: shifts have about 90 dimensions for N < 10 (measured: ``2.4 N + 75`` and ``1.5 N + 80``).
INSIDE_MIN_N = 10

#: Inside shifts tried in turn, as fractions of Weyl's estimate ``4 pi N / area`` of
#: ``lam_N`` (fewest Krylov dimensions at 0.6-0.7 on five meshes, N = 20, 50, 100, 200).
INSIDE_SHIFTS = (0.65, 0.6, 0.7)

#: Largest componentwise backward error of the indefinite factorisation's solve for which
#: an inside shift is used (:func:`_backward_error`).  Measured: eigenvalues within 6e-11
#: of a tight reference up to 5e-11 (with the refined smallest eigenvalues and their
#: tighter tolerance), 2e-9 without those at 1e-11.
INSIDE_BACKWARD_MAX = 1e-10

#: An eigensolve estimated (:func:`estimate_seconds`) to take longer warns before it starts.
LONG_SOLVE_SECONDS = 60.0

#: Block size ``b`` of the block Lanczos method (number of simultaneous right-hand sides).
BLOCK_SIZE = 8

#: Block size with two or more threads at :data:`THREADS_MIN_UNKNOWNS` unknowns or more:
#: the solves of a block of 16 run as two halves of 8 at once.  At 163,842 unknowns it
#: needs about 70 more Krylov dimensions than 8, but each solve reads the factor once for
#: 16 vectors: 5.7-6.6 s against 6.1-7.1 s on 2 threads (and 12 % slower than 8 on one
#: thread, where it is not used).  The eigenvalues then differ from the one-thread ones
#: by rounding (another Krylov space), about 1e-12 relative.
BLOCK_SIZE_THREADED = 16

#: Smallest block size accepted: a block Krylov method resolves at most ``b`` copies of an
#: exactly repeated eigenvalue, and a connected surface's symmetry group can make up to 5
#: (icosahedral symmetry; with ``b = 4`` the 10K icosphere came out wrong by 22 %).
MIN_BLOCK_SIZE = 6

#: A Ritz pair ``(theta, x)`` of ``OP`` counts as converged when
#: ``||OP x - theta x||_B <= RESIDUAL_TOL * theta``.
RESIDUAL_TOL = 1e-6

#: Largest loss of B-orthogonality (``|V_i^T B q|`` for a new Lanczos vector ``q`` against
#: the older basis) tolerated between two full re-orthogonalisation passes, with the shift
#: below the spectrum (:data:`_OMEGA_MAX_INSIDE` with the shift inside it).
_OMEGA_MAX = 1e-8
# (1e-9 instead: 22 % more full passes on 15 meshes for the same eigenvalues.
# 1e-7 here put one eigenvalue of penguin.obj, N = 200, 1.7e-9 off, against 3e-15 at 1e-8.)

#: The same bound with the shift inside the spectrum, a little above ``sqrt(eps)``.
#: Measured on 15 meshes (the 12 real ones of ``../shared/meshes`` above 700 vertices,
#: icospheres of 2.5K and 10K, a 1K torus) against the shift below run at 1e-9 to a
#: residual of 1e-10, N = 20, 50, 100, 150, 200, 300: within 5.9e-11 up to N = 200 and
#: 2.1e-10 at N = 300 (penguin.obj; the same at 1e-8).  The pairs far from the shift get
#: tightened tolerances, the smallest a refined Rayleigh-Ritz step.  Full passes
#: for N = 100: fish.obj 25 -> 20, wingnut 18 -> 15, penguin 19 -> 17, sword 24 -> 22 (a
#: shift close to an eigenvalue loses orthogonality fastest).  Higher bounds save more
#: (1e-7: fish 16 passes) but come near a cliff: on the 1K torus the error was 2e-10 at
#: 6e-8 (N = 300) and 8.4e-9 at 2e-7 (N = 200), against 1e-12 at 3e-8.
_OMEGA_MAX_INSIDE = 3e-8


@functools.cache
def _blas_controller():
    """threadpoolctl's view of the BLAS libraries loaded now (cached: building it scans
    every shared library of the process, 1.4 ms, as long as a 1000-vertex eigensolve's
    factorisation); None if threadpoolctl is missing."""
    try:
        from threadpoolctl import ThreadpoolController
    except ImportError:  # pragma: no cover - threadpoolctl is a dependency
        return None
    return ThreadpoolController()


def _one_blas_thread():
    """Context limiting BLAS to one thread (threadpoolctl), a no-op if it is missing.

    The products of the block Lanczos loop are tall and skinny (``n x b`` with ``b = 8``),
    hence memory bound: extra BLAS threads add little, and OpenBLAS's spinning worker
    threads slow them down severalfold as soon as another process uses the cores.
    The BLAS libraries are those loaded when this was first called (NumPy's and SciPy's,
    loaded with this module; CHOLMOD's BLAS is single-threaded).
    """
    controller = _blas_controller()
    if controller is None:  # pragma: no cover
        return contextlib.nullcontext()
    return controller.limit(limits=1, user_api="blas")


def _check_N(N: object, n_unknowns: int, bc: str) -> int:
    N = check_int("N", N, min=1)
    if N > n_unknowns:
        raise ValueError(
            f"N={N} eigenvalues requested but the {bc} problem has only {n_unknowns} unknowns "
            f"(mesh vertices{' not on the boundary' if bc == 'dirichlet' else ''}); use "
            f"N <= {n_unknowns} or a finer mesh (e.g. cshape.variants.subdivide(mesh) or "
            "cshape.variants.remesh(mesh))"
        )
    return N


class _CholeskyOperator(spla.LinearOperator):
    """``x -> (K - sigma B)^{-1} x`` with a sparse Cholesky factor (vectors or blocks).

    The factorisation is CHOLMOD's, through the fastest backend that works here
    (:mod:`cshape._cholmod`; ``CSHAPE_CHOLESKY`` chooses one).  ``rhs_order`` is the memory
    order of a block of right-hand sides that the backend takes without a copy.
    """

    def __init__(self, M):
        n = M.shape[0]
        super().__init__(dtype=np.float64, shape=(n, n))
        self._factor = _cholmod.factorize(M)
        self.rhs_order = self._factor.rhs_order

    def _matvec(self, x):
        return self._factor.solve(np.asarray(x, dtype=np.float64).reshape(-1))

    def _matmat(self, X):
        return self._factor.solve(X)

    def solve_split(self, X, parts=2):
        """``S^{-1} X`` with the columns in ``parts`` groups at once (the same bits)."""
        return self._factor.solve_split(X, parts)


class _NoConvergence(RuntimeError):
    """The block Lanczos method did not converge within its dimension budget."""


def _default_sigma(B, N):
    """A shift below the spectrum on the scale of ``lam_N`` (Weyl: lam_k ~ 4 pi k / area).

    ``sigma = -0.01 * 4 pi N / area`` (-1 for the unit sphere and N = 100): far enough
    below 0 to keep ``OP = S^{-1} B`` well scaled, close enough not to slow convergence.
    """
    area = float(B.sum())
    if not np.isfinite(area) or area <= 0:
        return -1e-2
    return -0.01 * 4.0 * np.pi * max(N, 1) / area


def _times(V, C):
    """``V @ C`` for a column-major basis ``V`` (k, m) and a small ``C`` (m, b).

    Computed as ``(C.T @ V.T).T``: the same product, but OpenBLAS streams the basis about
    1.7x faster in this orientation (measured: 57 vs 102 ms for k = 163842, m = 300, b = 8).
    """
    return (C.T @ V.T).T


#: Problems with at least this many unknowns split their tall products into
#: :data:`ROW_PARTS` fixed row ranges, which threads may compute at once.
THREADS_MIN_UNKNOWNS = 50_000

#: Row ranges of a split product (fixed, so the result never depends on the threads).
ROW_PARTS = 4

#: Below this many rows the products of the Lanczos recurrence with its two newest blocks
#: are computed in the row-major order of the block they update (:meth:`_RowSplit.sub_times`).
SMALL_PRODUCT_ROWS = 8_000


def solver_threads(n: int) -> int:
    """Threads for the Lanczos products of a problem with ``n`` unknowns (the policy).

    * ``CSHAPE_THREADS`` (environment), a positive integer, decides if set;
    * else 1 below :data:`THREADS_MIN_UNKNOWNS` unknowns, in a child process (a process
      pool's or a Dask worker: batch runs already use one process per core), and off the
      main thread (e.g. a threads-only Dask cluster);
    * else as many as the cores that look free, at most :data:`ROW_PARTS`: the CPU count
      this process may use minus the 1-minute load average, plus one for this process
      (on a shared machine extra threads only wait for cores and slow the solve down).

    The products are split into the same
    :data:`ROW_PARTS` row ranges, added in the same order, whatever their number; from
    two threads on the block size is :data:`BLOCK_SIZE_THREADED` (its solves in two
    halves at once), which changes the eigenvalues by rounding (about 1e-12 relative).
    The CHOLMOD factorisation runs on one core in any case.

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
    try:
        load = os.getloadavg()[0]
    except OSError:  # pragma: no cover
        load = float(cores)
    return int(max(1, min(cores, ROW_PARTS, np.floor(cores - load + 1.5))))


class _RowSplit:
    """Products over the rows of tall (n, .) arrays, in fixed row ranges, maybe threaded.

    Reductions over the rows (``X.T @ Y``) add the ranges' partial products in range
    order and row-wise products are computed range by range, so every result is the same
    bit for bit with any number of threads.  NumPy's BLAS calls release the GIL: with
    ``threads > 1`` the ranges run at once (BLAS itself on one thread each).
    """

    def __init__(self, n, B, threads=1, rhs_order="C"):
        self.rhs_order = rhs_order  # memory order of the B-images handed to the solver
        parts = ROW_PARTS if n >= THREADS_MIN_UNKNOWNS else 1
        edges = np.linspace(0, n, parts + 1).astype(int)
        self.ranges = list(zip(edges[:-1], edges[1:], strict=True))
        # row ranges of B in CSC: the same sums in the same order (same bits) as CSR, but
        # faster for blocks of vectors (163,842 unknowns, 16 columns, two threads: 5.2-6.5
        # ms against 7.0-7.8 ms)
        self.B_rows = [B[a:b].tocsc() for a, b in self.ranges] if parts > 1 else [B]
        self.single = parts == 1  # one range: the plain products, without dispatch
        self.pool = None
        if threads > 1 and parts > 1:
            from concurrent.futures import ThreadPoolExecutor

            self.pool = ThreadPoolExecutor(min(threads, parts))

    def close(self):
        if self.pool is not None:
            self.pool.shutdown()

    def _map(self, fn):
        if self.pool is None:
            return [fn(i, a, b) for i, (a, b) in enumerate(self.ranges)]
        futures = [self.pool.submit(fn, i, a, b) for i, (a, b) in enumerate(self.ranges)]
        return [f.result() for f in futures]

    def tdot(self, X, Y):
        """``X.T @ Y`` for X (n, p), Y (n, q).

        Computed as ``(Y.T @ X).T``: the same product, but OpenBLAS streams a column-major
        basis ``X`` faster in this orientation (measured at 10,786 unknowns, p = 230,
        q = 8: 1.9 ms against 3.4 ms).
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
        subtraction runs along memory, 2x faster at 3,047 rows than the column-major
        product of :func:`_times` (24 against 45 microseconds; the same at 10,786 rows).
        """
        if self.single:
            if V.shape[1] <= 16 and V.shape[0] < SMALL_PRODUCT_ROWS and W.flags.c_contiguous:
                W -= V @ C
            else:
                W -= _times(V, C)
            return

        def f(i, a, b):
            W[a:b] -= _times(V[a:b], C)
        self._map(f)

    def times(self, X, C, order="C"):
        """``X @ C`` as a new (n, q) array in the given memory order."""
        if self.single:
            return _times(X, C) if order == "F" else np.ascontiguousarray(X @ C)
        out = np.empty((X.shape[0], C.shape[1]), order=order)

        def f(i, a, b):
            out[a:b] = _times(X[a:b], C) if order == "F" else X[a:b] @ C
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


def _empty_basis(n, m, touch=0):
    """A column-major (n, m) float64 array, on huge pages where possible, its first
    ``touch`` columns zero (the rest uninitialised).

    The Lanczos basis is the largest array of the solve (482 MB for n = 163842, m = 368)
    and is streamed through at every re-orthogonalisation: on Linux it is mapped with
    ``MADV_HUGEPAGE``, which halves the time of its first touch and speeds up the
    streaming products by about 10 % (fewer page faults and TLB misses).  The columns
    the solve will surely use are touched here, in one sweep: at 163,842 unknowns on
    this project's virtual machine, writing the same 448 columns block by block during
    the iteration took 0.4-0.8 s of page faults, zeroing them at once 0.07 s.
    """
    nbytes = 8 * n * m
    V = None
    if nbytes >= 2**26 and hasattr(mmap, "MADV_HUGEPAGE"):
        try:
            buf = mmap.mmap(-1, nbytes, flags=mmap.MAP_PRIVATE | mmap.MAP_ANONYMOUS)
            buf.madvise(mmap.MADV_HUGEPAGE)
            V = np.frombuffer(buf, dtype=np.float64).reshape(m, n).T
        except (OSError, ValueError, AttributeError):  # pragma: no cover - no THP
            pass
    if V is None:
        V = np.empty((n, m), order="F")
    if touch:
        V[:, :touch] = 0.0
    return V


def _upper_cholesky(G):
    """``R`` upper triangular with ``R.T @ R = G`` (LAPACK potrf; a tenth of the time of
    ``scipy.linalg.cholesky`` on the b x b blocks of the Lanczos loop)."""
    if not np.isfinite(G).all():
        raise la.LinAlgError("non-finite entries in a Gram matrix")
    R, info = la.lapack.dpotrf(G, lower=0, clean=1)
    if info != 0:
        raise la.LinAlgError(f"Gram matrix not positive definite (potrf info {info})")
    return R


def _triangular_inverse(R):
    """The inverse of an invertible upper triangular matrix (LAPACK ``trtri``)."""
    Rinv, info = la.lapack.dtrtri(R, lower=0)
    if info != 0:  # pragma: no cover - R comes from a successful, well-conditioned Cholesky
        raise la.LinAlgError(f"singular triangular factor (trtri info {info})")
    return Rinv


def _b_orthonormalize(W, B, scale, split=None):
    """B-orthonormalise the columns of ``W`` (Cholesky-QR, repeated if ill-conditioned).

    Parameters
    ----------
    W : ndarray, shape (k, b)
    B : sparse matrix, shape (k, k)
    scale : float
        B-norm of the vectors ``W`` was computed from; directions of ``W`` shorter than
        ``1e-12 * scale`` count as numerically zero (rank deficiency).

    Returns
    -------
    Q, BQ : ndarray, shape (k, r)
        ``Q.T @ B @ Q = I`` and ``BQ = B @ Q``.
    R : ndarray, shape (r, b)
        ``W = Q R`` up to the dropped directions; ``r < b`` if ``W`` is rank deficient.
    """
    if split is None:
        split = _RowSplit(W.shape[0], B)
    BW = split.bmul(W)
    G = split.tdot(W, BW)
    G = 0.5 * (G + G.T)
    try:
        R = _upper_cholesky(G)
        diag = np.abs(np.diag(R))
        # 1-norm condition number estimate of the triangular factor (LAPACK trcon): a
        # fraction of the cost of the exact 2-norm one (an SVD), and within a factor
        # b of it
        rcond, info = la.lapack.dtrcon(R, norm="1", uplo="U")
        cond = 1.0 / rcond if info == 0 and rcond > 0 else np.inf
        if diag.min() <= 1e-12 * max(scale, diag.max()) or cond > 1e6:
            raise la.LinAlgError("ill-conditioned block")
    except la.LinAlgError:
        # rank revealing: keep the directions of W that are not numerically zero
        D, U = la.eigh(G)
        keep = D > (1e-12 * max(scale, np.sqrt(max(D.max(), 0.0)))) ** 2
        U, D = U[:, keep], D[keep]
        T = U / np.sqrt(D)
        Q, BQ = W @ T, BW @ T
        R = np.sqrt(D)[:, None] * U.T
        if Q.shape[1] == 0:
            return Q, BQ, R
        Q, BQ, R2 = _b_orthonormalize(Q, B, 1.0, split)
        return Q, BQ, R2 @ R
    Rinv = _triangular_inverse(R)
    # Q column-major (it is copied into the column-major basis as one contiguous block),
    # BQ in the order the solver takes without a copy (the next block of right-hand sides)
    Q, BQ = split.times(W, Rinv, "F"), split.times(BW, Rinv, split.rhs_order)
    if cond > 1e2:  # Cholesky-QR loses eps * cond^2 of orthogonality: repeat
        G = split.tdot(Q, BQ)
        R2 = _upper_cholesky(0.5 * (G + G.T))  # G ~ I: well conditioned
        R2inv = _triangular_inverse(R2)
        Q, BQ, R = (split.times(Q, R2inv, "F"), split.times(BQ, R2inv, split.rhs_order),
                    R2 @ R)
    return Q, BQ, R


def _complete_block(rng, Q, BQ, R, b, V, B):
    """Fill a rank-deficient block ``Q`` (r < b columns) with random directions.

    The new columns are B-orthonormal to ``V`` and ``Q``; ``R`` gets zero rows for them,
    so the Lanczos relation stays exact (the Krylov space had become invariant there).
    """
    r = Q.shape[1]
    for _ in range(3):
        Z = rng.standard_normal((V.shape[0], b - r))
        for _ in range(2):
            Z -= V @ (V.T @ (B @ Z))
            Z -= Q @ (BQ.T @ Z)
        Qz, BQz, _ = _b_orthonormalize(Z, B, float(np.sqrt(np.abs(Z.T @ (B @ Z)).max())))
        if Qz.shape[1] == b - r:
            return (np.hstack([Q, Qz]), np.hstack([BQ, BQz]),
                    np.vstack([R, np.zeros((b - r, b))]))
    raise _NoConvergence("could not extend the Krylov basis")


def _block_lanczos(
    K, B, N, solve, sigma, *, block_size=BLOCK_SIZE, max_dim=None, tol=RESIDUAL_TOL, seed=0,
    return_vectors=True, threads=1, rhs_order="C", negatives=None, refine=None,
):
    """The ``N`` smallest eigenpairs of ``K f = lam B f`` by block shift-invert Lanczos.

    Parameters
    ----------
    K, B : scipy.sparse.csr_matrix, shape (k, k)
        Stiffness (positive semidefinite) and mass (positive definite).
    N : int
        Number of wanted eigenpairs.
    solve : callable
        ``X -> (K - sigma B)^{-1} X`` for ``X`` of shape (k, b).
    sigma : float
        The shift, below the smallest eigenvalue.
    block_size : int, default=BLOCK_SIZE
    max_dim : int, optional
        Largest Krylov dimension before giving up (default ``max(6 N, N + 40 b)``, at
        most ``k``).
    tol : float, default=RESIDUAL_TOL
        Convergence: ``||OP x - theta x||_B <= tol * theta`` for each wanted pair.
    seed : int, default=0
        Seed of the random start block.
    return_vectors : bool, default=True
    threads : int, default=1
        Threads for the products over the basis (:func:`solver_threads`); the result is
        the same with any number.
    rhs_order : {'C', 'F'}, default='C'
        Memory order of the blocks passed to ``solve`` (the one it takes without a copy).
    negatives : int, optional
        The shift lies inside the spectrum with exactly this many eigenvalues below it
        (the inertia of ``K - sigma B``), ``0 <= negatives <= N``: the wanted pairs are
        all the negative ``theta`` and the ``N - negatives`` largest positive ones.
        Default: ``sigma`` lies below the spectrum (the N largest ``theta``).
    refine : callable, optional
        With ``negatives``: an accurate ``X -> (K - sigma B)^{-1} X`` (e.g. ``solve`` with
        a step of iterative refinement), used once at the end for the ``2 b`` smallest
        eigenvalues, whose relative accuracy an inside shift reduces.

    Returns
    -------
    lam : ndarray, shape (N,)
        Ascending eigenvalues.
    phi : ndarray, shape (k, N) or None
        B-orthonormal eigenvectors (None unless ``return_vectors``).

    Raises
    ------
    _NoConvergence
        If the wanted pairs have not converged within ``max_dim``.
    """
    n = K.shape[0]
    b = int(block_size)
    if b < MIN_BLOCK_SIZE:
        raise ValueError(
            f"block_size must be at least {MIN_BLOCK_SIZE} (the largest multiplicity a connected "
            f"surface's symmetry can give is 5), got {block_size}"
        )
    if max_dim is None:
        max_dim = max(6 * N, N + 40 * b)
    nblocks = max(1, min(max_dim, n - b) // b)
    if nblocks * b < N:
        raise _NoConvergence("Krylov dimension budget below N")
    cap = (nblocks + 1) * b
    # The basis only; the B-images of the two newest blocks are kept aside (BVprev, BVcur)
    # and B @ W is recomputed (sparse, cheap) where an inner product with older blocks is
    # needed: half the memory traffic of storing B @ V.
    V = _empty_basis(n, cap, touch=min(cap, _first_check(N, b, n, negatives is not None) + 2 * b))
    # Block tridiagonal projection of OP, in LAPACK upper banded storage (bandwidth b).
    band = np.zeros((b + 1, cap))
    split = _RowSplit(n, B, threads, rhs_order)
    try:
        return _lanczos_loop(K, B, N, solve, sigma, b, nblocks, cap, V, band, split, tol,
                             seed, return_vectors, negatives, refine)
    finally:
        split.close()


def _band_to_dense(band, m):
    """The symmetric (m, m) matrix whose upper triangle ``band[:, :m]`` stores (LAPACK)."""
    b = band.shape[0] - 1
    T = np.zeros((m, m))
    for d in range(min(b, m - 1) + 1):  # d-th superdiagonal: band[b - d, d:m]
        i = np.arange(m - d)
        T[i, i + d] = T[i + d, i] = band[b - d, d:m]
    return T


def _first_check(N, b=8, n=None, inside=False):
    """Krylov dimension of the first Rayleigh-Ritz step of :func:`_lanczos_loop`.

    The projected problem is solved only when the wanted pairs may have converged: one
    such solve (LAPACK, about 10 ms at a dimension of 320) costs as
    much as several Lanczos steps on a mesh of a few thousand vertices.  Measured on ten
    real meshes of 2K-22K vertices and icospheres (block size 8), all ``N`` pairs
    converged at a Krylov dimension between ``2.4 N + 40`` and ``2.4 N + 112`` for
    N = 20 .. 200 (``m ~ 3.2 N`` for N = 100).  The first look is a little before the
    middle of that range, or at its middle for problems of fewer than 10,000 unknowns
    ``n``, where a Lanczos step costs less than a tenth of a Rayleigh-Ritz step (1.23
    instead of 2.0 looks on average, 5 more Krylov dimensions).

    With the shift inside the spectrum (``inside``, :data:`INSIDE_SHIFTS`) the pairs
    converged at a median of 96, 152, 224 and 376 Krylov dimensions for N = 20, 50, 100,
    200 (15 meshes, within -16 and +48 of it): the first look is at about the median,
    ``1.5 N + 80`` (``1.5 N + 66`` from 10,000 unknowns).
    """
    if inside:
        return max(N, int(1.5 * N + (80 if n is not None and n < 10_000 else 66)
                          + 9 * (b - 8)))
    factor = 1.0 if n is not None and n < 10_000 else 0.95
    return max(N, int(factor * (2.4 * N + 75 + 9 * (b - 8))))


#: From this many unknowns a Rayleigh-Ritz step (10-20 ms) costs a fraction of a
#: Lanczos step (0.1-0.3 s at 163,842 unknowns): after the first look, look at every step.
CHECK_EVERY_STEP_UNKNOWNS = 50_000


def _next_check(m, missing, b, inside=False, n=None):
    """Krylov dimension of the next Rayleigh-Ritz step, ``missing`` pairs short at ``m``.

    Near the end, about one pair converges per 2.5 Krylov dimensions (measured as in
    :func:`_first_check`), or per 1.2 with the shift inside the spectrum (``inside``;
    the last 7-16 pairs of five real meshes took 8-16 dimensions): look again when all
    missing ones may have converged.  Problems of ``n >=``
    :data:`CHECK_EVERY_STEP_UNKNOWNS` unknowns look at the next step (at 163,842
    unknowns and blocks of 16 the schedule above looked at 416 and 448 dimensions, the
    pairs had converged at 432).
    """
    if n is not None and n >= CHECK_EVERY_STEP_UNKNOWNS:
        return m + b
    per_pair = (6, 5) if inside else (5, 2)  # dimensions per pair, as a fraction
    return m + b * max(1, -(-per_pair[0] * missing // (per_pair[1] * b)))


def _pair_tolerance(B, N, sigma, negatives):
    """Factors of the residual tolerance, ``theta -> f(theta)`` (1, or an array in (0, 1]).

    A Ritz value with relative residual ``r`` is accurate to about ``r**2 / gap`` in
    ``theta``, so ``lam = sigma + 1/theta`` is accurate to about ``r**2 (lam - sigma)**2 / s``
    with ``s`` the spacing of the eigenvalues (Weyl: ``4 pi / area``).  With the shift
    below the spectrum the largest relative bound is the one of ``lam_N``, about
    ``r**2 N``.  With the shift inside, the smallest eigenvalues lie far from it relative
    to their size: their tolerance is multiplied by
    ``sqrt(N s max(lam, s)) / |lam - sigma|`` (at most 1), which keeps every eigenvalue's
    bound at most ``r**2 N``.
    """
    if not negatives:
        return lambda theta: 1.0
    area = float(B.sum())
    s = 4.0 * np.pi / area if np.isfinite(area) and area > 0 else 0.0

    def factor(theta):
        lam = sigma + 1.0 / theta
        return np.minimum(1.0, np.sqrt(N * s * np.maximum(s, lam)) * np.abs(theta))
    return factor


def _next_skip(skip, omega, bound=_OMEGA_MAX):
    """Local-only Lanczos steps before the next full re-orthogonalisation pass.

    ``omega`` is the loss of orthogonality the last pass measured after ``skip`` such
    steps.  Above ``bound`` the passes run at every step until it is back under it: the
    loss spreads from the blocks that carry it to every new one (with one step fewer at a
    time instead, it grew to 2e-5 on a 10K-vertex icosphere).  Far below it (1e-3 of it;
    the loss grows by about 100-700x a step) one more step is allowed, at most 4.
    """
    if omega > bound:
        return 0
    if omega < 1e-3 * bound:
        return min(skip + 1, 4)
    return skip


def _lanczos_loop(K, B, N, solve, sigma, b, nblocks, cap, V, band, split, tol, seed,
                  return_vectors, negatives=None, refine=None):
    """The iteration of :func:`_block_lanczos` (its arguments, checked and allocated)."""
    n = K.shape[0]
    rng = np.random.default_rng(seed)
    Q, BQ, _ = _b_orthonormalize(rng.standard_normal((n, b)), B, 1.0, split)
    if Q.shape[1] < b:  # pragma: no cover - a random block is full rank
        raise _NoConvergence("random start block is rank deficient")
    V[:, :b] = Q
    BVprev, BVcur = None, BQ
    theta = Y = None
    # Partial re-orthogonalisation: the Lanczos recurrence only needs the two newest blocks;
    # orthogonality to the older ones is lost gradually (rounding errors, amplified along
    # converged Ritz vectors, about 100x per step here).  The pass over the older blocks
    # runs after every ``skip`` local-only steps; its coefficients measure the loss
    # ``omega`` accumulated since the last pass, and ``skip`` adapts so that omega stays
    # below _OMEGA_MAX, or _OMEGA_MAX_INSIDE with the shift inside the spectrum (near
    # sqrt(eps): semi-orthogonality keeps the Ritz values accurate to rounding, Simon 1984;
    # see those constants for the measured choices).
    skip, since = 0, 0
    omega_max = _OMEGA_MAX if negatives is None else _OMEGA_MAX_INSIDE
    next_check = _first_check(N, b, n, inside=negatives is not None)
    pair_tol = _pair_tolerance(B, N, sigma, negatives)
    segment = 0  # start of the current Krylov sequence (0, or the last breakdown)
    urows, ucols = np.triu_indices(b)  # the entries (r, c), r <= c, of a b x b block
    R = None
    for j in range(nblocks):
        m0, m = j * b, (j + 1) * b
        lo = max(0, m0 - b)
        W = solve(BVcur)
        # first pass (classical Gram-Schmidt) against the two newest blocks; the coupling
        # to the previous block is known (R_j^T, by symmetry)
        A = split.tdot(BVcur, W)
        if R is not None:
            split.sub_times(W, V[:, lo:m], np.vstack([R.T, A]))
        else:
            split.sub_times(W, V[:, m0:m], A)
        scale = max(float(np.abs(A).max()), float(np.abs(R).max()) if R is not None else 0.0)
        omega = None
        if lo > 0 and since >= skip:
            # second pass against the whole basis: re-orthogonalisation, whose coefficients
            # on the older blocks measure the loss of orthogonality since the last one
            C = split.tdot(V[:, :m], split.bmul(W))
            split.sub_times(W, V[:, :m], C)
            omega = float(np.abs(C[:lo]).max())
            A += C[m0:m]
            since = 0
        else:
            # second pass against the two newest blocks (classical Gram-Schmidt twice)
            since += 1
            C2 = split.tdot(BVcur, W)
            if BVprev is not None:
                C2p = split.tdot(BVprev, W)
                split.sub_times(W, V[:, lo:m], np.vstack([C2p, C2]))
            else:
                split.sub_times(W, V[:, m0:m], C2)
            A += C2
        Q, BQ, R = _b_orthonormalize(W, B, scale, split)
        due = m >= next_check or j == nblocks - 1
        if Q.shape[1] < b:  # Krylov space (nearly) invariant: continue with random vectors
            Q, BQ, R = _complete_block(rng, Q, BQ, R, b, V[:, :m], B)
            skip, since = 0, 0
            # The Ritz pairs of an invariant subspace are exact but may lack copies of
            # eigenvalues repeated more than b times: let the new directions grow as far
            # as the previous ones did before judging convergence again.
            due = due and segment > 0  # never right at the first breakdown
            next_check = max(next_check, 2 * m - segment)
            segment = m
        elif omega is not None:  # adapt the re-orthogonalisation interval
            omega /= max(float(np.abs(np.diag(R)).min()), 1e-300)
            skip = _next_skip(skip, omega, omega_max)
        split.copy_into(V[:, m : m + b], Q)
        BVprev, BVcur = BVcur, BQ
        # diagonal block (symmetrised) and sub-diagonal block R into the band
        A = 0.5 * (A + A.T)
        band[b - ucols + urows, m0 + ucols] = A[urows, ucols]
        # R (upper triangular) couples block j+1 to block j: T[m + r, m0 + c] = R[r, c]
        # for r <= c, kept in the upper storage as band[c - r, m + r] = T[m0 + c, m + r].
        band[ucols - urows, m + urows] = R[urows, ucols]
        if not due:
            continue
        # All eigenpairs of the dense T by divide and conquer (LAPACK syevd), the N largest
        # kept: 10-11 ms at m = 320 on real meshes against 17-20 ms for the N wanted ones
        # from the banded solver (sbevx, slow on T's clusters of close eigenvalues).
        # (T is finite: its entries come from products checked by la.cholesky.)
        theta, Y = la.eigh(_band_to_dense(band, m), driver="evd", check_finite=False)
        if negatives is None:  # the N largest theta
            wanted = np.arange(m - 1, m - 1 - N, -1)
            signs_ok = m >= N and theta[m - N] > 0
        else:  # every negative theta (their number is known) and the N - p largest
            p = negatives
            wanted = np.r_[np.arange(p), np.arange(m - (N - p), m)]
            # Cauchy interlacing: at most p Ritz values are negative
            signs_ok = m >= N and (p == 0 or theta[p - 1] < 0) and \
                (p == N or theta[m - (N - p)] > 0)
        theta, Y = theta[wanted], Y[:, wanted]
        res = np.linalg.norm(R @ Y[m0:m], axis=0)
        nconv = int(np.sum(res <= tol * np.abs(theta) * pair_tol(theta)))
        if nconv == N and signs_ok:
            break
        next_check = max(next_check, _next_check(m, N - nconv, b, negatives is not None, n))
    else:
        raise _NoConvergence(f"no convergence within a Krylov dimension of {nblocks * b}")
    # the 2 b smallest eigenvalues below an inside shift: theta[:p] is ascending, lam_0 is
    # theta[p - 1]
    smallest = slice(negatives - min(2 * b, negatives), negatives) if negatives else None
    if negatives and refine is not None:
        # The smallest eigenvalues lie farthest below an inside shift: lam = sigma + 1/theta
        # turns a relative error of theta into one about sigma/lam times larger.  Their
        # block of Ritz vectors gets a Rayleigh-Ritz step with the solve made accurate by
        # refinement (errors of the Ritz vectors enter it squared), with or without
        # eigenvectors, so that both give the same eigenvalues.  (The Rayleigh quotients
        # x^T K x of the orthonormalised vectors, once used for eigenpairs, weigh
        # the vectors' errors by the large eigenvalues: 5.8e-10 off on the swords at
        # N = 15, against 3.3e-12 here.)
        X = split.times(V[:, :m], np.ascontiguousarray(Y[:, smallest]), "F")
        BX = np.asfortranarray(B @ X)
        # The Lanczos relation gives OP X = X diag(theta) + V_{m+1} R Y_m up to the
        # coefficients dropped at the re-orthogonalisation passes (the loss of
        # orthogonality): a first guess of S^{-1} B X, measured within 2e-12 to 9e-7 of it
        # on 14 meshes, that one step of refinement makes as accurate as two steps from a
        # plain solve (to 1e-14), one solve fewer.
        Z0 = X * theta[smallest] + _times(V[:, m:m + b], R @ Y[m0:m, smallest])
        G = BX.T @ refine(BX, Z0)
        M = X.T @ BX
        G, M = 0.5 * (G + G.T), 0.5 * (M + M.T)
        theta[smallest] = la.eigh(G, M, eigvals_only=True)
        if return_vectors:  # the Ritz vectors of this step; their values stay those of
            # the call above without vectors (LAPACK's two drivers may differ in the last
            # bit, and shape_dna makes that call only)
            Y = Y.copy()
            Y[:, smallest] = Y[:, smallest] @ la.eigh(G, M)[1]
    lam = sigma + 1.0 / theta
    if not return_vectors:
        return lam, None
    # Ritz vectors, made B-orthonormal to rounding (the basis is only semi-orthogonal) by
    # Loewdin's symmetric orthonormalisation X G^(-1/2), G = X^T B X = I + O(1e-8): it
    # changes each vector least.  The eigenvalues stay those computed without vectors (the
    # same bits).  A Rayleigh-Ritz step with the pencil (K, B) instead cost 3-8 % more of
    # the whole solve (K X, a second Gram matrix, a generalised eigenproblem) for the same
    # accuracy.
    # The products over the n rows run on the row ranges of ``split`` (threaded on big
    # meshes, the same bits with any number of threads): at 163,842 unknowns V @ Y alone
    # is 11 GFlop.
    X = split.times(V[:, :m], np.ascontiguousarray(Y), "C")
    G = split.tdot(X, split.bmul(X))
    D, U = la.eigh(0.5 * (G + G.T))
    if not D.min() > 0.5:  # pragma: no cover - semi-orthogonality keeps G within 1e-7 of I
        raise _NoConvergence("the Ritz vectors are not numerically independent")
    X = split.times(X, (U / np.sqrt(D)) @ U.T, "C")
    return lam, X


def _arpack(K, B, N, op, sigma, return_vectors):
    """The former path: ARPACK shift-invert Lanczos with ``tol=0`` (fallback)."""
    k = K.shape[0]
    v0 = np.random.default_rng(0).standard_normal(k)
    ncv = min(k, max(2 * N + 1, 20))
    res = spla.eigsh(
        K, k=N, M=B, sigma=sigma, which="LM", OPinv=op, v0=v0, ncv=ncv, tol=0,
        return_eigenvectors=return_vectors,
    )
    if return_vectors:
        return res
    return res, None


def _same_pattern(K, B):
    """Whether two CSR matrices store the same (canonical) pattern of entries."""
    return (K.has_canonical_format and B.has_canonical_format and K.nnz == B.nnz
            and np.array_equal(K.indptr, B.indptr) and np.array_equal(K.indices, B.indices))


def _solve_sparse(K, B, N, sigma, return_vectors):
    """Sparse path of :func:`solve_eigenproblem`, one connected component at a time.

    The problem of a mesh with several connected components is block diagonal.  Each
    block is solved on its own (dense if small) and the N smallest eigenvalues of the
    union are kept: identical components would otherwise make every eigenvalue exactly
    repeated once per component, beyond what the block size of the Krylov method can
    resolve.
    """
    k = K.shape[0]
    same = _same_pattern(K, B)
    if same and bool((B.data > 0).all()):
        pattern = B  # a consistent mass matrix: positive on every edge of the mesh
    else:
        pattern = (K != 0) + (B != 0)  # explicit zeros are no edges
    ncomp, labels = csgraph.connected_components(pattern, directed=False)
    if ncomp > 1:
        # permute once so that every component is a contiguous diagonal block
        perm = np.argsort(labels, kind="stable")
        bounds = np.concatenate([[0], np.cumsum(np.bincount(labels, minlength=ncomp))])
        Kp = K[perm][:, perm].tocsr()
        Bp = B[perm][:, perm].tocsr()
        lams, vecs = [], []
        for c in range(ncomp):
            lo, hi = int(bounds[c]), int(bounds[c + 1])
            idx = perm[lo:hi]
            Kc = Kp[lo:hi, lo:hi]
            Bc = Bp[lo:hi, lo:hi]
            Nc = min(N, len(idx))
            if len(idx) <= DENSE_LIMIT or 3 * Nc >= len(idx):
                out = la.eigh(Kc.toarray(), Bc.toarray(), subset_by_index=[0, Nc - 1],
                              eigvals_only=not return_vectors)
                lc, pc = out if return_vectors else (out, None)
            else:
                lc, pc = _solve_sparse(Kc, Bc, Nc, sigma, return_vectors)
            lams.append(lc)
            if return_vectors:
                full = np.zeros((k, Nc))
                full[idx] = pc
                vecs.append(full)
        lam = np.concatenate(lams)
        order = np.argsort(lam, kind="stable")[:N]
        return lam[order], (np.hstack(vecs)[:, order] if return_vectors else None)
    if sigma is None and k <= INSIDE_LIMIT and N >= INSIDE_MIN_N:
        out = _solve_inside(K, B, N, same, return_vectors)
        if out is not None:
            return out
    if sigma is None:
        sigma = _default_sigma(B, N)
    op = _CholeskyOperator(_shifted(K, B, sigma, same))
    threads = solver_threads(k)
    solve, b = op.matmat, BLOCK_SIZE
    if threads >= 2 and k >= THREADS_MIN_UNKNOWNS:
        # two threads: blocks of 16 whose solves run as two halves at once
        solve, b = functools.partial(op.solve_split, parts=2), BLOCK_SIZE_THREADED
    try:
        with _one_blas_thread():
            lam, phi = _block_lanczos(K, B, N, solve, sigma, return_vectors=return_vectors,
                                      threads=threads, rhs_order=op.rhs_order, block_size=b)
    except (_NoConvergence, la.LinAlgError):
        lam, phi = _arpack(K, B, N, op, sigma, return_vectors)
    order = np.argsort(lam, kind="stable")
    return lam[order], (phi[:, order] if phi is not None else None)


def _shifted(K, B, sigma, same):
    """``K - sigma B`` (on the shared pattern of two canonical CSR matrices if ``same``)."""
    if same:
        return sp.csr_matrix((K.data - sigma * B.data, K.indices, K.indptr), shape=K.shape)
    return (K - sigma * B).tocsr()


def _backward_error(S, factor):
    """Componentwise relative backward error of ``factor`` on two fixed random right-hand sides.

    ``max_i |S y - x|_i / (|S| |y| + |x|)_i`` for ``y = factor.solve(x)``: about 1e-16 for
    a Cholesky factor; larger for ``L D L^T`` without pivoting when the elimination meets
    a nearly singular leading block (element growth).
    """
    X = np.asfortranarray(np.random.default_rng(1).standard_normal((S.shape[0], 2)))
    Y = factor.solve(X)
    denom = abs(S) @ np.abs(Y) + np.abs(X)
    return float((np.abs(S @ Y - X) / denom).max())


def _refined_solve(S, factor, X, Z=None):
    """``S^{-1} X`` by one step of iterative refinement from ``Z`` (default: ``factor``'s solve)."""
    if Z is None:
        Z = factor.solve(X)
    return Z + factor.solve(np.asfortranarray(X - S @ Z))


def _solve_inside(K, B, N, same, return_vectors):
    """Block Lanczos with the shift inside the spectrum, or None where it does not apply.

    ``sigma = c * 4 pi N / area`` (Weyl's estimate of ``lam_k`` for ``k = c N``; ``c`` from
    :data:`INSIDE_SHIFTS`).  ``K - sigma B`` is indefinite: it is factorised as
    ``L D L^T`` (CHOLMOD, simplicial, no pivoting), and the number ``p`` of negative
    entries of ``D`` is, by Sylvester's law of inertia, exactly the number of eigenvalues
    below ``sigma``.  ``OP = (K - sigma B)^{-1} B`` maps them to negative
    ``theta = 1 / (lam - sigma)``: the wanted pairs are all ``p`` negative ``theta`` and
    the ``N - p`` largest positive ones.  Both ends of the wanted part of the spectrum now
    lie about N/2 eigenvalues from the shift instead of N, and the Krylov space that
    resolves them is a third smaller (measured: about ``1.6 N + 65`` dimensions against
    ``2.4 N + 75``): a third fewer solves and about half the orthogonalisation.  The
    count ``p`` makes the negative side exact: the iteration stops only when ``p``
    negative Ritz values have converged, so no copy of an eigenvalue below the shift can
    be missed.

    Accuracy.  ``lam = sigma + 1/theta`` turns a relative error of ``theta`` into one about
    ``sigma / lam`` times larger for the smallest eigenvalues, and the factorisation does
    not pivot (element growth at a nearly singular leading block; plain, the eigenvalues
    were off by up to 7e-9 relative, measured).  Three measures: a shift is used only if
    the backward error of a solve is at most :data:`INSIDE_BACKWARD_MAX` (else the next
    of :data:`INSIDE_SHIFTS`); the residual tolerance of the pairs far below the shift is
    tightened (:func:`_pair_tolerance`); the ``2 b`` smallest eigenvalues get a last
    Rayleigh-Ritz step with a refined solve (:func:`_refined_solve`).  Measured against
    the shift below run to a 1e-10 residual on 15 meshes, N = 20, 50, 100, 200: within
    4e-12 relative.

    Returns None (the caller takes the shift below the spectrum) if the backend has no
    indefinite factorisation, if ``N`` or more eigenvalues lie below the first shift, if
    no shift passes the backward-error test, or if the iteration does not converge.
    """
    area = float(B.sum())
    if not np.isfinite(area) or area <= 0:
        return None
    for c in INSIDE_SHIFTS:
        sigma = c * 4.0 * np.pi * N / area
        S = _shifted(K, B, sigma, same)
        try:
            factor = _cholmod.factorize(S, indefinite=True)
        except la.LinAlgError:  # a zero pivot
            continue
        except (ValueError, OSError):  # no indefinite factorisation here
            return None
        if factor.inertia >= N:  # Weyl's estimate far off (e.g. a long thin strip)
            return None
        if _backward_error(S, factor) <= INSIDE_BACKWARD_MAX:
            break
    else:
        return None
    try:
        with _one_blas_thread():
            lam, phi = _block_lanczos(K, B, N, factor.solve, sigma,
                                      return_vectors=return_vectors, threads=1,
                                      rhs_order=factor.rhs_order, negatives=factor.inertia,
                                      refine=functools.partial(_refined_solve, S, factor))
    except (_NoConvergence, la.LinAlgError):
        return None
    order = np.argsort(lam, kind="stable")
    return lam[order], (phi[:, order] if phi is not None else None)


@overload
def solve_eigenproblem(A: sp.spmatrix, B: sp.spmatrix, N: int, *,
                       return_vectors: Literal[True] = ..., sigma: float | None = ...
                       ) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
@overload
def solve_eigenproblem(A: sp.spmatrix, B: sp.spmatrix, N: int, *,
                       return_vectors: Literal[False], sigma: float | None = ...
                       ) -> NDArray[np.float64]: ...
def solve_eigenproblem(A: sp.spmatrix, B: sp.spmatrix, N: int, *, return_vectors: bool = True,
                       sigma: float | None = None
                       ) -> NDArray[np.float64] | tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The ``N`` smallest eigenpairs of ``A f = -lam B f`` (Eq. 3).

    Parameters
    ----------
    A : scipy.sparse matrix, shape (k, k)
        Stiffness, negative semidefinite (paper's sign).
    B : scipy.sparse matrix, shape (k, k)
        Mass, positive definite.
    N : int
        Number of eigenpairs, ``1 <= N <= k``.
    return_vectors : bool, default=True
    sigma : float, optional
        Shift for shift-invert (must be below the smallest eigenvalue, i.e. negative).
        Default: ``-0.01 * 4 pi N / area`` with ``area = B.sum()``, one hundredth of
        Weyl's estimate of ``lam_N`` below zero.

    Returns
    -------
    lam : ndarray, shape (N,)
        Ascending eigenvalues; round-off below ``1e-10`` times the largest (zero
        eigenvalues) is set to 0 and tiny negative values are clipped to 0.
    phi : ndarray, shape (k, N)
        B-orthonormal eigenvectors (``phi.T @ B @ phi = I``), only if ``return_vectors``.

    Notes
    -----
    ``k <= DENSE_LIMIT`` or ``3 N >= k``: dense LAPACK (``scipy.linalg.eigh``).
    Otherwise each connected component of the matrix graph is solved on its own (dense
    if small) by block shift-invert Lanczos on one sparse Cholesky factorisation (see the
    module docstring), falling back to ARPACK (``eigsh``, ``tol=0``) if it does not
    converge.  The result is deterministic: fixed random seeds.
    """
    return_vectors = check_bool("return_vectors", return_vectors)
    if sigma is not None:
        sigma = check_real("sigma", sigma)
    K = (-sp.csr_matrix(A)).tocsr()
    B = sp.csr_matrix(B)
    k = K.shape[0]
    N = _check_N(N, k, "")
    if k <= DENSE_LIMIT or 3 * N >= k:  # a Krylov space would need about 3 N dimensions
        # one BLAS thread: at this size threading gains little, and on a busy machine
        # OpenBLAS's spinning threads made a 1141-unknown solve 20x slower (4.1 s vs 0.18 s)
        with _one_blas_thread():
            if return_vectors:
                lam, phi = la.eigh(K.toarray(), B.toarray(), subset_by_index=[0, N - 1])
            else:
                lam = la.eigh(
                    K.toarray(), B.toarray(), subset_by_index=[0, N - 1], eigvals_only=True
                )
                phi = None
    else:
        lam, phi = _solve_sparse(K, B, N, sigma, return_vectors)
    lam = np.asarray(lam, dtype=np.float64)
    # round-off of zero eigenvalues -> 0, relative to the scale of the spectrum (the
    # largest eigenvalue, or Weyl's 4 pi / area for lam_1 when N is tiny), so that meshes
    # in any unit keep their small eigenvalues
    area = float(B.sum())
    scale = max(float(np.abs(lam).max()), 4.0 * np.pi / area if area > 0 else 0.0)
    lam[np.abs(lam) < 1e-10 * scale] = 0.0
    lam = np.maximum(lam, 0.0)
    if return_vectors:
        return lam, phi  # type: ignore[return-value]  # phi is set when return_vectors
    return lam


def eigenpairs(mesh: MeshLike, N: int = 100, bc: str = "neumann", mass: str = "consistent"
               ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The ``N`` smallest Laplace-Beltrami eigenvalues and B-orthonormal eigenfunctions.

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
    N : int, default=100
        Number of eigenpairs (lam_0 included).
    bc : {'neumann', 'dirichlet'}, default='neumann'
        See :func:`cshape.fem_matrices`.
    mass : {'consistent', 'lumped'}, default='consistent'

    Returns
    -------
    lam : ndarray, shape (N,)
        Ascending eigenvalues of ``A f = -lam B f`` (Eq. 3): those of :func:`shape_dna`
        for the same arguments (the same bits from the block Lanczos solver; on the
        dense path of small problems, LAPACK with and without vectors, to rounding).
    phi : ndarray, shape (n, N)
        Eigenfunctions on the mesh vertices, ``phi[:, i]`` for ``lam[i]``; B-orthonormal
        over the unknowns; zero on fixed vertices for ``bc='dirichlet'``.  If the mesh
        was repaired (duplicate or unreferenced vertices), ``n`` is the vertex count of
        the repaired mesh.

    Raises
    ------
    TypeError
        ``N`` not an integer (bools are refused), ``bc`` or ``mass`` not a string, ``mesh``
        not a mesh.
    ValueError
        ``N < 1`` or more than the unknowns, an unknown ``bc`` or ``mass``, an invalid or
        zero-area mesh.
    """
    problem = _prepare(mesh, N, bc, mass)
    lam, phi = solve_eigenproblem(problem.A, problem.B, N, return_vectors=True)
    return lam, problem.to_vertices(phi)


def shape_dna(mesh: MeshLike, N: int = 100, bc: str = "neumann", mass: str = "consistent"
              ) -> NDArray[np.float64]:
    """Shape-DNA: the ``N`` smallest Laplace-Beltrami eigenvalues of a mesh (Section 2.1).

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        A triangle mesh; repaired with a warning if it has duplicate or unreferenced
        vertices or collapsed faces.
    N : int, default=100
        Number of eigenvalues, lam_0 included.  Must not exceed the number of unknowns.
    bc : {'neumann', 'dirichlet'}, default='neumann'
    mass : {'consistent', 'lumped'}, default='consistent'

    Returns
    -------
    lam : ndarray, shape (N,)
        Ascending eigenvalues; ``lam[0] == 0`` for a closed (or Neumann) mesh.  A mesh
        with ``c`` connected components has ``c`` zero eigenvalues (a warning says so).

    Raises
    ------
    TypeError, ValueError
        As :func:`eigenpairs`.

    Notes
    -----
    Meshes of 50,000 vertices and more may use several threads for the products of the
    eigensolver when cores are free (never in batch workers); the environment variable
    ``CSHAPE_THREADS`` sets the number.  The eigenvalues are the same bits with any number
    of threads from two on, and agree with the one-thread ones to rounding (about 1e-12
    relative; :func:`solver_threads`).

    Examples
    --------
    >>> import cshape
    >>> lam = cshape.shape_dna(cshape.shapes.icosphere(3), N=4)
    >>> lam.round(2)  # the unit sphere: 0, then 2 (three times)
    array([0.  , 2.01, 2.01, 2.01])
    """
    problem = _prepare(mesh, N, bc, mass)
    return solve_eigenproblem(problem.A, problem.B, N, return_vectors=False)


def estimate_seconds(n: int, N: int) -> float:
    """A rough wall time of the eigensolve of ``N`` eigenvalues with ``n`` unknowns, in s.

    ``1e-9 n^3`` for the dense path (``n <= DENSE_LIMIT`` or ``3 N >= n``), else
    ``1e-8 n N^2`` (the Lanczos basis of about ``3 N`` vectors of length ``n``, kept
    orthogonal), plus ``2e-5 n`` (FEM, factorisation), fitted on one core of a 2-core
    machine (the fit: ``benchmarks/SCALE.md``, "The eigensolver").  The estimate is for
    warnings, not for planning to the minute.
    """
    n, N = float(check_int("n", n, min=0)), float(check_int("N", N, min=1))
    if n <= DENSE_LIMIT or 3 * N >= n:
        return 1e-9 * n**3 + 2e-5 * n
    return 1e-8 * n * N**2 + 2e-5 * n


def _duration(seconds) -> str:
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def long_solve_message(n: int, N: int) -> str | None:
    """The warning of an eigensolve estimated to take long, or None (see
    :func:`estimate_seconds` and ``LONG_SOLVE_SECONDS``)."""
    t = estimate_seconds(n, N)
    if t < LONG_SOLVE_SECONDS:
        return None
    faster = next((m for m in (400, 200, 100, 50) if m < N
                   and estimate_seconds(n, m) < LONG_SOLVE_SECONDS), None)
    hint = (f"; N={faster} would take about {_duration(estimate_seconds(n, faster))}"
            if faster else "")
    return (f"N={int(N)} eigenvalues of a mesh of {int(n)} vertices: the eigensolve will "
            f"take about {_duration(t)} on one core (a rough estimate, 1e-8 n N^2 s){hint}")


def components_message(ncomp: int) -> str:
    """The warning about a mesh of ``ncomp`` connected components (also shown by a batch
    run whose eigenvalues come from the cache)."""
    return (f"mesh has {ncomp} connected components: its spectrum is the union of theirs, "
            f"with {ncomp} zero eigenvalues under Neumann conditions; the log-Weyl, "
            "truncated log and F1 descriptors drop them (cshape.nonzero_eigenvalues); use "
            "cshape.largest_component(mesh) to describe one piece")


def _prepare(mesh, N, bc, mass):
    # repair first, so that the components counted are those of the mesh that is solved
    # (a welded STL triangle soup is one piece, not one per triangle)
    mesh = repair_mesh(as_mesh(mesh))
    problem = fem(mesh, bc=bc, mass=mass, repair=False)
    _check_N(N, problem.n_unknowns, problem.bc)
    if problem.bc == "neumann" and problem.B.nnz > problem.n_unknowns:
        # consistent mass: positive on every edge, so its graph is the mesh's (cheaper
        # than building the vertex graph again)
        ncomp = csgraph.connected_components(problem.B, directed=False)[0]
    else:
        ncomp = mesh.n_components
    if ncomp > 1:
        warnings.warn(components_message(ncomp), CShapeWarning, stacklevel=3)
    long = long_solve_message(problem.n_unknowns, N)
    if long:
        warnings.warn(long, CShapeWarning, stacklevel=3)
    return problem
