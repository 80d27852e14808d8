"""The shift of the sparse eigensolver: where it lies, how ``K - sigma B`` is factorised.

Two shifts, tried in this order by :mod:`cshape.spectrum` for one connected component:

* :func:`solve_inside`, the shift inside the wanted part of the spectrum (meshes of at
  most :data:`INSIDE_LIMIT` unknowns): ``K - sigma B`` is indefinite and factorised as
  ``L D L^T``; its inertia (Sylvester's law) counts the eigenvalues below the shift.
  None where it does not apply.
* :func:`solve_below`, the shift below the whole spectrum: ``K - sigma B`` is positive
  definite (Cholesky ``L L^T``), with a block size set by the size, and ARPACK with
  ``tol=0`` on the same factorisation if the block Lanczos method does not converge.

Both hand their solve to :func:`cshape._eigensolver.lanczos.block_lanczos`; the factorisations are
:mod:`cshape._eigensolver.cholmod`'s.
"""

from __future__ import annotations

import functools
import time

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from . import cholmod as _cholmod
from . import lanczos as _lanczos
from . import threads as _threads

#: Problems with at most this many unknowns put the shift inside the spectrum
#: (:func:`solve_inside`).  Its factorisation is simplicial (CHOLMOD has no supernodal
#: ``L D L^T``) and grows faster with the size than the supernodal ``L L^T`` of the
#: shift below; above this size the shift below is faster.
INSIDE_LIMIT = 25_000

#: Fewer wanted eigenvalues keep the shift below the spectrum: there the Krylov spaces of
#: both shifts have about the same dimension.
INSIDE_MIN_N = 10

#: Inside shifts tried in turn, as fractions of Weyl's estimate ``4 pi N / area`` of
#: ``lam_N``.
INSIDE_SHIFTS = (0.65, 0.6, 0.7)

#: Largest componentwise backward error of the indefinite factorisation's solve for which
#: an inside shift is used (:func:`backward_error`).
INSIDE_BACKWARD_MAX = 1e-10


class CholeskyOperator(spla.LinearOperator):
    """``x -> (K - sigma B)^{-1} x`` with a sparse Cholesky factor (vectors or blocks).

    The factorisation is CHOLMOD's, through the fastest backend that works here
    (:mod:`cshape._eigensolver.cholmod`; ``CSHAPE_CHOLESKY`` chooses one).  ``rhs_order`` is
    the memory order of a block of right-hand sides that the backend takes without a copy.
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

    def solve_split(self, X, parts=2, threads=None):
        """``S^{-1} X`` with the columns in ``parts`` groups, at once with ``threads > 1``.

        The backend keeps the bits the same with any ``threads``: CHOLMOD solves the same
        groups in turn (``threads=1``) or at once (default), the one-thread backends all
        columns in one solve either way.
        """
        return self._factor.solve_split(X, parts, threads)


def default_sigma(B, N):
    """Return a shift below the spectrum on the scale of ``lam_N`` (Weyl: lam_k ~ 4 pi k / area).

    ``sigma = -0.01 * 4 pi N / area`` (-1 for the unit sphere and N = 100): far enough
    below 0 to keep ``OP = S^{-1} B`` well scaled, close enough not to slow convergence.
    """
    area = float(B.sum())
    if not np.isfinite(area) or area <= 0:
        return -1e-2
    return -0.01 * 4.0 * np.pi * max(N, 1) / area


def same_pattern(K, B):
    """Whether two CSR matrices store the same (canonical) pattern of entries."""
    return (K.has_canonical_format and B.has_canonical_format and K.nnz == B.nnz
            and np.array_equal(K.indptr, B.indptr) and np.array_equal(K.indices, B.indices))


def shifted(K, B, sigma, same):
    """``K - sigma B`` (on the shared pattern of two canonical CSR matrices if ``same``)."""
    if same:
        return sp.csr_matrix((K.data - sigma * B.data, K.indices, K.indptr), shape=K.shape)
    return (K - sigma * B).tocsr()


def backward_error(S, factor):
    """Componentwise relative backward error of ``factor`` on two fixed random right-hand sides.

    ``max_i |S y - x|_i / (|S| |y| + |x|)_i`` for ``y = factor.solve(x)``: about 1e-16 for
    a Cholesky factor; larger for ``L D L^T`` without pivoting when the elimination meets
    a nearly singular leading block (element growth).
    """
    X = np.asfortranarray(np.random.default_rng(1).standard_normal((S.shape[0], 2)))
    Y = factor.solve(X)
    denom = abs(S) @ np.abs(Y) + np.abs(X)
    return float((np.abs(S @ Y - X) / denom).max())


def refined_solve(S, factor, X, Z=None):
    """``S^{-1} X`` by one step of iterative refinement from ``Z`` (default: ``factor``'s solve)."""
    if Z is None:
        Z = factor.solve(X)
    return Z + factor.solve(np.asfortranarray(X - S @ Z))


def _ascending(lam, phi):
    order = np.argsort(lam, kind="stable")
    return lam[order], (phi[:, order] if phi is not None else None)


def inside_factor(K, B, N, same):
    """``(sigma, S, factor)`` of the first usable inside shift, or None.

    ``sigma = c * 4 pi N / area`` for ``c`` in :data:`INSIDE_SHIFTS`, ``S = K - sigma B``
    factorised as ``L D L^T`` (CHOLMOD, simplicial, no pivoting; ``factor.inertia`` is the
    number of negative entries of ``D``).  A shift is used if its solve's backward error
    is at most :data:`INSIDE_BACKWARD_MAX`.  None if the backend has no indefinite
    factorisation, if ``N`` or more eigenvalues lie below the first shift (Weyl's
    estimate far off, e.g. a long thin strip), or if no shift passes.
    """
    area = float(B.sum())
    if not np.isfinite(area) or area <= 0:
        return None
    for c in INSIDE_SHIFTS:
        sigma = c * 4.0 * np.pi * N / area
        S = shifted(K, B, sigma, same)
        try:
            factor = _cholmod.factorize(S, indefinite=True)
        except la.LinAlgError:  # a zero pivot
            continue
        except (ValueError, OSError):  # no indefinite factorisation here
            return None
        if factor.inertia >= N:
            return None
        if backward_error(S, factor) <= INSIDE_BACKWARD_MAX:
            return sigma, S, factor
    return None


def solve_inside(K, B, N, same, return_vectors):
    """Block Lanczos with the shift inside the spectrum, or None where it does not apply.

    By Sylvester's law of inertia the number ``p`` of eigenvalues below ``sigma`` is the
    inertia of the factorisation (:func:`inside_factor`).  ``OP = (K - sigma B)^{-1} B``
    maps them to negative ``theta = 1 / (lam - sigma)``: the wanted pairs are all ``p``
    negative ``theta`` and the ``N - p`` largest positive ones, and the iteration stops
    only when ``p`` negative Ritz values have converged, so no copy of an eigenvalue below
    the shift can be missed.  The pairs far below the shift get a tighter residual
    tolerance and the ``2 b`` smallest eigenvalues a last Rayleigh-Ritz step with a
    refined solve (:func:`refined_solve`).

    Returns
    -------
    (lam, phi) or None
        Ascending eigenvalues and eigenvectors (``phi`` None unless ``return_vectors``);
        None (the caller takes the shift below the spectrum) if no inside shift applies
        or the iteration does not converge.
    """
    found = inside_factor(K, B, N, same)
    if found is None:
        return None
    sigma, S, factor = found
    try:
        with _threads.one_blas_thread():
            lam, phi = _lanczos.block_lanczos(
                K, B, N, factor.solve, sigma, return_vectors=return_vectors, threads=1,
                rhs_order=factor.rhs_order, negatives=factor.inertia,
                refine=functools.partial(refined_solve, S, factor))
    except (_lanczos.NoConvergence, la.LinAlgError):
        return None
    return _ascending(lam, phi)


def _basis_beside(k, N, b, threads):
    """Start allocating the Lanczos basis in another thread, if ``threads > 1``; or None.

    The first write to a big array costs page faults; a second core writes it while the
    first one factorises (figures: ``benchmarks/results/choices.md``).  Returns a future of
    the array :func:`~cshape._eigensolver.lanczos.block_lanczos` takes as ``basis``.
    """
    if threads < 2:
        return None
    from concurrent.futures import ThreadPoolExecutor

    _, columns, touched = _lanczos.basis_shape(k, N, b)
    pool = ThreadPoolExecutor(1)
    future = pool.submit(_lanczos.empty_basis, k, columns, touched)
    pool.shutdown(wait=False)  # its thread ends once the basis is written
    return future


def solve_below(K, B, N, sigma, same, return_vectors):
    """Block Lanczos with the shift ``sigma`` below the spectrum (default :func:`default_sigma`).

    ``K - sigma B`` is positive definite: one Cholesky factorisation
    (:class:`CholeskyOperator`).  The block size follows the size
    (:func:`~cshape._eigensolver.lanczos.block_size`); blocks of
    :data:`~cshape._eigensolver.lanczos.BLOCK_SIZE_THREADED` vectors are solved as two halves.  From
    ``THREADS_MIN_UNKNOWNS`` unknowns the halves run at once on two threads (else the whole
    block in one solve) and the products over the basis on several, each where timing
    shows that it helps (two :class:`~cshape._eigensolver.threads.ThreadChooser`, at most
    :func:`~cshape._eigensolver.threads.solver_threads` threads); the eigenvalues are the same bits
    either way.  If the block method does not converge, ARPACK (:func:`arpack`) on the
    same factorisation.  Returns ascending ``(lam, phi)``, ``phi`` None unless
    ``return_vectors``.
    """
    k = K.shape[0]
    if sigma is None:
        sigma = default_sigma(B, N)
    b = _lanczos.block_size(k)
    threads = _threads.solver_threads(k)
    basis = _basis_beside(k, N, b, threads)  # written while the matrix is factorised
    op = CholeskyOperator(shifted(K, B, sigma, same))
    chooser = _threads.ThreadChooser(threads)
    if b == _lanczos.BLOCK_SIZE_THREADED:
        halves = _threads.ThreadChooser(min(threads, 2))  # the solve's own choice

        def solve(X):
            at_once = halves.start_step()
            start = time.perf_counter()
            Z = op.solve_split(X, parts=2, threads=at_once)
            halves.record(time.perf_counter() - start)
            return Z
    else:
        solve = op.matmat
    try:
        with _threads.one_blas_thread():
            lam, phi = _lanczos.block_lanczos(K, B, N, solve, sigma,
                                              return_vectors=return_vectors, threads=chooser,
                                              rhs_order=op.rhs_order, block_size=b,
                                              basis=basis.result() if basis else None)
    except (_lanczos.NoConvergence, la.LinAlgError):
        lam, phi = arpack(K, B, N, op, sigma, return_vectors)
    return _ascending(lam, phi)


def arpack(K, B, N, op, sigma, return_vectors):
    """ARPACK shift-invert Lanczos with ``tol=0`` (the fallback), ``(lam, phi or None)``."""
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
