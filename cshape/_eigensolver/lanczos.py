"""Block shift-invert Lanczos: the N smallest eigenpairs of ``K f = lam B f`` from one solve.

:func:`block_lanczos` takes a solve ``X -> (K - sigma B)^{-1} X`` (a factorisation made
by :mod:`cshape._eigensolver.shift`) and runs :class:`BlockLanczos`, the iteration's state with one
method per stage: a Lanczos step (:meth:`~BlockLanczos.step`), the Rayleigh-Ritz test of
convergence (:meth:`~BlockLanczos.rayleigh_ritz`), the refined smallest eigenvalues below
an inside shift (:meth:`~BlockLanczos.refine_smallest`) and the B-orthonormal Ritz
vectors (:meth:`~BlockLanczos.ritz_vectors`).  The derivation: docs/guides/eigensolver.md.
"""

from __future__ import annotations

import mmap
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp

from . import threads as _threads
from .threads import RowSplit, ThreadChooser, times

#: Block size ``b`` (number of simultaneous right-hand sides).
BLOCK_SIZE = 8

#: Block size of a big mesh (``THREADS_MIN_UNKNOWNS`` to :data:`BIG_BLOCK_MAX_UNKNOWNS`
#: unknowns, shift below the spectrum): its solves run as two halves of
#: :data:`BLOCK_SIZE`, at once when two threads help, each reading the factor once.
BLOCK_SIZE_THREADED = 16

#: From this many unknowns the block size is :data:`BLOCK_SIZE` again, blocks of
#: :data:`BLOCK_SIZE_THREADED` no longer paying for the larger Krylov space they build
#: (``benchmarks/SCALE.md``, "Threads").
BIG_BLOCK_MAX_UNKNOWNS = 800_000


def block_size(n):
    """Return the block size of a problem of ``n`` unknowns with the shift below the spectrum.

    :data:`BLOCK_SIZE_THREADED` from ``THREADS_MIN_UNKNOWNS`` to
    :data:`BIG_BLOCK_MAX_UNKNOWNS` unknowns, else :data:`BLOCK_SIZE`.  It depends on the
    size only, never on the threads: the eigenvalues are the same bits with any number.
    """
    if _threads.THREADS_MIN_UNKNOWNS <= n < BIG_BLOCK_MAX_UNKNOWNS:
        return BLOCK_SIZE_THREADED
    return BLOCK_SIZE


#: Smallest block size accepted: a block Krylov method resolves at most ``b`` copies of an
#: exactly repeated eigenvalue, and a connected surface's symmetry group can make up to 5
#: (icosahedral symmetry).
MIN_BLOCK_SIZE = 6

#: A Ritz pair ``(theta, x)`` of ``OP`` counts as converged when
#: ``||OP x - theta x||_B <= RESIDUAL_TOL * theta``.
RESIDUAL_TOL = 1e-6

#: Largest loss of B-orthogonality (``|V_i^T B q|`` for a new Lanczos vector ``q`` against
#: the older basis) tolerated between two full re-orthogonalisation passes with the shift
#: below the spectrum: under ``sqrt(eps)``, semi-orthogonality (Simon 1984).
OMEGA_MAX = 1e-8

#: The same bound with the shift inside the spectrum, a little above ``sqrt(eps)``
#: (there the pairs far from the shift get tightened tolerances and the smallest a
#: refined Rayleigh-Ritz step).
OMEGA_MAX_INSIDE = 3e-8

#: From this many unknowns a Rayleigh-Ritz step costs a fraction of a Lanczos step:
#: after the first look, look at every step.
CHECK_EVERY_STEP_UNKNOWNS = 50_000


class NoConvergence(RuntimeError):
    """The block Lanczos method did not converge within its dimension budget."""


# ----------------------------------------------------------------------------- schedule
def first_check(N, b=8, n=None, inside=False):
    """Krylov dimension of the first Rayleigh-Ritz step.

    The projected problem is solved only where the wanted pairs may have converged: one
    such solve costs as much as several Lanczos steps on a mesh of a few thousand
    vertices.  With the shift below the spectrum all ``N`` pairs converge at a Krylov
    dimension of about ``2.4 N + 75``; the first look is a little before it (at it for
    problems of fewer than 10,000 unknowns ``n``, where a Lanczos step is cheap).  With
    the shift inside the spectrum (``inside``) the first look is at ``1.5 N + 80``
    (``1.5 N + 66`` from 10,000 unknowns).
    """
    if inside:
        return max(N, int(1.5 * N + (80 if n is not None and n < 10_000 else 66)
                          + 9 * (b - 8)))
    factor = 1.0 if n is not None and n < 10_000 else 0.95
    return max(N, int(factor * (2.4 * N + 75 + 9 * (b - 8))))


def next_check(m, missing, b, inside=False, n=None):
    """Krylov dimension of the next Rayleigh-Ritz step, ``missing`` pairs short at ``m``.

    Near the end about one pair converges per 2.5 Krylov dimensions, or per 1.2 with the
    shift inside the spectrum (``inside``): look again when all missing ones may have
    converged.  Problems of ``n >=`` :data:`CHECK_EVERY_STEP_UNKNOWNS` unknowns look at
    the next step.
    """
    if n is not None and n >= CHECK_EVERY_STEP_UNKNOWNS:
        return m + b
    per_pair = (6, 5) if inside else (5, 2)  # dimensions per pair, as a fraction
    return m + b * max(1, -(-per_pair[0] * missing // (per_pair[1] * b)))


def next_skip(skip, omega, bound=OMEGA_MAX):
    """Local-only Lanczos steps before the next full re-orthogonalisation pass.

    ``omega`` is the loss of orthogonality the last pass measured after ``skip`` such
    steps.  Above ``bound`` the passes run at every step until it is back under it (the
    loss spreads from the blocks that carry it to every new one).  Far below it (1e-3 of
    it; the loss grows by a factor of hundreds a step) one more step is allowed, at most 4.
    """
    if omega > bound:
        return 0
    if omega < 1e-3 * bound:
        return min(skip + 1, 4)
    return skip


def pair_tolerance(B, N, sigma, negatives):
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


# ----------------------------------------------------------------------------- blocks
def empty_basis(n, m, touch=0):
    """Allocate a column-major (n, m) float64 array, on huge pages where possible.

    Its first ``touch`` columns are zero (the rest uninitialised).

    The Lanczos basis is the largest array of the solve and is streamed through at every
    re-orthogonalisation: on Linux it is mapped with ``MADV_HUGEPAGE`` (fewer page faults
    and TLB misses).  The columns the solve will surely use are touched here, in one
    sweep, rather than block by block during the iteration.
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


def upper_cholesky(G):
    """Return ``R`` upper triangular with ``R.T @ R = G`` (LAPACK potrf).

    Much cheaper than ``scipy.linalg.cholesky`` on the b x b blocks of the iteration.
    """
    if not np.isfinite(G).all():
        raise la.LinAlgError("non-finite entries in a Gram matrix")
    R, info = la.lapack.dpotrf(G, lower=0, clean=1)
    if info != 0:
        raise la.LinAlgError(f"Gram matrix not positive definite (potrf info {info})")
    return R


def triangular_inverse(R):
    """Invert an invertible upper triangular matrix (LAPACK ``trtri``)."""
    Rinv, info = la.lapack.dtrtri(R, lower=0)
    if info != 0:  # pragma: no cover - R comes from a successful, well-conditioned Cholesky
        raise la.LinAlgError(f"singular triangular factor (trtri info {info})")
    return Rinv


def b_orthonormalize(W, B, scale, split=None):
    """B-orthonormalise the columns of ``W`` (Cholesky-QR, repeated if ill-conditioned).

    Parameters
    ----------
    W : ndarray, shape (k, b)
    B : sparse matrix, shape (k, k)
    scale : float
        B-norm of the vectors ``W`` was computed from; directions of ``W`` shorter than
        ``1e-12 * scale`` count as numerically zero (rank deficiency).
    split : RowSplit, optional
        The products' row ranges (default: one range).

    Returns
    -------
    Q, BQ : ndarray, shape (k, r)
        ``Q.T @ B @ Q = I`` and ``BQ = B @ Q``.
    R : ndarray, shape (r, b)
        ``W = Q R`` up to the dropped directions; ``r < b`` if ``W`` is rank deficient.
    """
    if split is None:
        split = RowSplit(W.shape[0], B)
    BW = split.bmul(W)
    G = split.tdot(W, BW)
    G = 0.5 * (G + G.T)
    try:
        R = upper_cholesky(G)
        diag = np.abs(np.diag(R))
        # 1-norm condition number estimate of the triangular factor (LAPACK trcon): a
        # fraction of the cost of the exact 2-norm one (an SVD), and within a factor
        # b of it
        rcond, info = la.lapack.dtrcon(R, norm="1", uplo="U")
        cond = 1.0 / rcond if info == 0 and rcond > 0 else np.inf
        if diag.min() <= 1e-12 * max(scale, diag.max()) or cond > 1e6:
            raise la.LinAlgError("ill-conditioned block")
    except la.LinAlgError:
        return _rank_revealing(W, BW, G, B, scale, split)
    Rinv = triangular_inverse(R)
    # Q column-major (it is copied into the column-major basis as one contiguous block),
    # BQ in the order the solver takes without a copy (the next block of right-hand sides)
    Q, BQ = split.times(W, Rinv, "F"), split.times(BW, Rinv, split.rhs_order)
    if cond > 1e2:  # Cholesky-QR loses eps * cond^2 of orthogonality: repeat
        G = split.tdot(Q, BQ)
        R2 = upper_cholesky(0.5 * (G + G.T))  # G ~ I: well conditioned
        R2inv = triangular_inverse(R2)
        Q, BQ, R = (split.times(Q, R2inv, "F"), split.times(BQ, R2inv, split.rhs_order),
                    R2 @ R)
    return Q, BQ, R


def _rank_revealing(W, BW, G, B, scale, split):
    """Apply :func:`b_orthonormalize` to a (nearly) rank-deficient ``W``.

    Keep the directions of its Gram matrix ``G`` that are not numerically zero, then
    orthonormalise again.
    """
    D, U = la.eigh(G)
    keep = D > (1e-12 * max(scale, np.sqrt(max(D.max(), 0.0)))) ** 2
    U, D = U[:, keep], D[keep]
    T = U / np.sqrt(D)
    Q, BQ = W @ T, BW @ T
    R = np.sqrt(D)[:, None] * U.T
    if Q.shape[1] == 0:
        return Q, BQ, R
    Q, BQ, R2 = b_orthonormalize(Q, B, 1.0, split)
    return Q, BQ, R2 @ R


def complete_block(rng, Q, BQ, R, b, V, B):
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
        Qz, BQz, _ = b_orthonormalize(Z, B, float(np.sqrt(np.abs(Z.T @ (B @ Z)).max())))
        if Qz.shape[1] == b - r:
            return (np.hstack([Q, Qz]), np.hstack([BQ, BQz]),
                    np.vstack([R, np.zeros((b - r, b))]))
    raise NoConvergence("could not extend the Krylov basis")


def band_to_dense(band, m):
    """Return the symmetric (m, m) matrix whose upper triangle ``band[:, :m]`` stores (LAPACK)."""
    b = band.shape[0] - 1
    T = np.zeros((m, m))
    for d in range(min(b, m - 1) + 1):  # d-th superdiagonal: band[b - d, d:m]
        i = np.arange(m - d)
        T[i, i + d] = T[i + d, i] = band[b - d, d:m]
    return T


# ----------------------------------------------------------------------------- iteration
def basis_shape(n, N, b, max_dim=None, inside=False):
    """Size of the Lanczos basis of :func:`block_lanczos`: ``(blocks, columns, touched)``.

    ``blocks`` is the number of Lanczos steps allowed (from ``max_dim``, see
    :func:`block_lanczos`); the basis has ``columns = (blocks + 1) b`` columns, of which
    the first ``touched`` are surely used (up to the first look at the projected problem).
    """
    if max_dim is None:
        max_dim = max(6 * N, N + 40 * b)
    nblocks = max(1, min(max_dim, n - b) // b)
    cap = (nblocks + 1) * b
    return nblocks, cap, min(cap, first_check(N, b, n, inside) + 2 * b)


def block_lanczos(
    K, B, N, solve, sigma, *, block_size=BLOCK_SIZE, max_dim=None, tol=RESIDUAL_TOL, seed=0,
    return_vectors=True, threads=1, rhs_order="C", negatives=None, refine=None, basis=None,
):
    """Return the ``N`` smallest eigenpairs of ``K f = lam B f`` by block shift-invert Lanczos.

    Parameters
    ----------
    K, B : scipy.sparse.csr_matrix, shape (k, k)
        Stiffness (positive semidefinite) and mass (positive definite).
    N : int
        Number of wanted eigenpairs.
    solve : callable
        ``X -> (K - sigma B)^{-1} X`` for ``X`` of shape (k, b).
    sigma : float
        The shift: below the smallest eigenvalue, or inside the spectrum (``negatives``).
    block_size : int, default=BLOCK_SIZE
        At least :data:`MIN_BLOCK_SIZE`.
    max_dim : int, optional
        Largest Krylov dimension before giving up (default ``max(6 N, N + 40 b)``, at
        most ``k``).
    tol : float, default=RESIDUAL_TOL
        Convergence: ``||OP x - theta x||_B <= tol * theta`` for each wanted pair.
    seed : int, default=0
        Seed of the random start block.
    return_vectors : bool, default=True
    threads : int or ThreadChooser, default=1
        The most threads for the products over the basis
        (:func:`cshape._eigensolver.threads.solver_threads`), or a
        :class:`~cshape._eigensolver.threads.ThreadChooser` that picks them at each step by
        timing the step's first orthogonalisation pass (``solve`` chooses its own threads); the
        result is the same with any number.
    rhs_order : {'C', 'F'}, default='C'
        Memory order of the blocks passed to ``solve`` (the one it takes without a copy).
    negatives : int, optional
        The shift lies inside the spectrum with exactly this many eigenvalues below it
        (the inertia of ``K - sigma B``), ``0 <= negatives <= N``: the wanted pairs are
        all the negative ``theta`` and the ``N - negatives`` largest positive ones.
        Default: ``sigma`` lies below the spectrum (the N largest ``theta``).
    refine : callable, optional
        With ``negatives``: an accurate ``(X, Z0) -> (K - sigma B)^{-1} X`` (one step of
        iterative refinement from the guess ``Z0``), used once at the end for the ``2 b``
        smallest eigenvalues, whose relative accuracy an inside shift reduces.
    basis : ndarray, optional
        The array the basis is built in, column-major, of shape ``(n, columns)``
        (:func:`basis_shape`; allocated and its first ``touched`` columns written
        beforehand, e.g. in another thread during the factorisation); default: allocated
        here by :func:`empty_basis`.

    Returns
    -------
    lam : ndarray, shape (N,)
        Eigenvalues (ascending below the shift, then descending above it).
    phi : ndarray, shape (k, N) or None
        B-orthonormal eigenvectors (None unless ``return_vectors``).

    Raises
    ------
    ValueError
        ``block_size`` below :data:`MIN_BLOCK_SIZE`.
    NoConvergence
        If the wanted pairs have not converged within ``max_dim``.
    """
    b = int(block_size)
    if b < MIN_BLOCK_SIZE:
        raise ValueError(
            f"block_size must be at least {MIN_BLOCK_SIZE} (the largest multiplicity a connected "
            f"surface's symmetry can give is 5), got {block_size}"
        )
    nblocks, cap, touched = basis_shape(K.shape[0], N, b, max_dim, negatives is not None)
    if nblocks * b < N:
        raise NoConvergence("Krylov dimension budget below N")
    if basis is None:
        basis = empty_basis(K.shape[0], cap, touch=touched)
    elif basis.shape != (K.shape[0], cap) or not basis.flags.f_contiguous:
        raise ValueError(f"basis must be a column-major array of shape "
                         f"{(K.shape[0], cap)} (basis_shape), got {basis.shape}")
    chooser = threads if isinstance(threads, ThreadChooser) else None
    split = RowSplit(K.shape[0], B, chooser.max if chooser else int(threads), rhs_order)
    try:
        state = BlockLanczos(B, N, solve, sigma, b, nblocks, split, basis, tol=tol, seed=seed,
                             negatives=negatives, refine=refine, chooser=chooser)
        return state.run(return_vectors)
    finally:
        split.close()


@dataclass(eq=False)
class BlockLanczos:
    """The state of one block shift-invert Lanczos iteration (see :func:`block_lanczos`).

    The fields are the problem and the settings, checked by :func:`block_lanczos`; the
    rest is the state the iteration grows.  The basis ``V`` (column-major,
    ``(nblocks + 1) b`` columns) holds the B-orthonormal blocks; only the B-images of the
    two newest blocks are kept (``BVprev``, ``BVcur``), and ``B @ W`` is recomputed where
    an inner product with older blocks is needed.  The projection ``T`` of
    ``OP = (K - sigma B)^{-1} B`` onto the basis is block tridiagonal, stored in LAPACK
    upper banded form (``band``, bandwidth ``b``).  ``R`` is the newest sub-diagonal
    block; ``skip`` and ``since`` schedule the partial re-orthogonalisation; ``segment``
    is the start of the current Krylov sequence (0, or the last breakdown); ``check`` the
    Krylov dimension of the next Rayleigh-Ritz step; ``theta``, ``Y`` the wanted Ritz
    pairs of the last Rayleigh-Ritz step.
    """

    B: sp.csr_matrix
    N: int
    solve: Callable[[np.ndarray], np.ndarray]
    sigma: float
    b: int
    nblocks: int
    split: RowSplit
    V: np.ndarray
    tol: float = RESIDUAL_TOL
    seed: int = 0
    negatives: int | None = None
    refine: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None
    chooser: ThreadChooser | None = None

    def __post_init__(self):
        n, N, b = self.B.shape[0], self.N, self.b
        self.n, self.inside = n, self.negatives is not None
        self.band = np.zeros((b + 1, self.V.shape[1]))
        self.rng = np.random.default_rng(self.seed)
        self.skip, self.since, self.segment = 0, 0, 0
        self.omega_max = OMEGA_MAX_INSIDE if self.inside else OMEGA_MAX
        self.check = first_check(N, b, n, inside=self.inside)
        self.pair_tol = pair_tolerance(self.B, N, self.sigma, self.negatives)
        self.urows, self.ucols = np.triu_indices(b)  # entries (r, c), r <= c, of a block
        self.R = self.theta = self.Y = None
        Q, BQ, _ = b_orthonormalize(self.rng.standard_normal((n, b)), self.B, 1.0, self.split)
        if Q.shape[1] < b:  # pragma: no cover - a random block is full rank
            raise NoConvergence("random start block is rank deficient")
        self.V[:, :b] = Q
        self.BVprev, self.BVcur = None, BQ

    def run(self, return_vectors):
        """Iterate to convergence; ``(lam, phi)`` as :func:`block_lanczos` returns them."""
        b = self.b
        for j in range(self.nblocks):
            if self.step(j) and self.rayleigh_ritz(j * b, (j + 1) * b):
                break
        else:
            raise NoConvergence(f"no convergence within a Krylov dimension of {self.nblocks * b}")
        m0, m = j * b, (j + 1) * b
        theta, Y = self.theta, self.Y
        if self.negatives and self.refine is not None:
            theta, Y = self.refine_smallest(theta, Y, m0, m, return_vectors)
        lam = self.sigma + 1.0 / theta
        if not return_vectors:
            return lam, None
        return lam, self.ritz_vectors(Y, m)

    def step(self, j):
        """Lanczos step ``j``: block ``j + 1`` of the basis and block row ``j`` of ``T``.

        Returns whether a Rayleigh-Ritz step is due.  A block that comes out rank
        deficient (the Krylov space became invariant, a breakdown) is completed with
        random directions, and the convergence test waits until they have been developed
        as far as the previous ones: the Ritz pairs of an invariant subspace are exact but
        may lack copies of eigenvalues repeated more than ``b`` times.
        """
        b, V, split = self.b, self.V, self.split
        m0, m = j * b, (j + 1) * b
        W, A, scale, omega = self._orthogonalize(m0, m)
        Q, BQ, R = b_orthonormalize(W, self.B, scale, split)
        due = m >= self.check or j == self.nblocks - 1
        if Q.shape[1] < b:  # Krylov space (nearly) invariant: continue with random vectors
            Q, BQ, R = complete_block(self.rng, Q, BQ, R, b, V[:, :m], self.B)
            self.skip, self.since = 0, 0
            due = due and self.segment > 0  # never right at the first breakdown
            self.check = max(self.check, 2 * m - self.segment)
            self.segment = m
        elif omega is not None:  # adapt the re-orthogonalisation interval
            omega /= max(float(np.abs(np.diag(R)).min()), 1e-300)
            self.skip = next_skip(self.skip, omega, self.omega_max)
        split.copy_into(V[:, m : m + b], Q)
        self.BVprev, self.BVcur, self.R = self.BVcur, BQ, R
        # diagonal block (symmetrised) and sub-diagonal block R into the band
        A = 0.5 * (A + A.T)
        urows, ucols = self.urows, self.ucols
        self.band[b - ucols + urows, m0 + ucols] = A[urows, ucols]
        # R (upper triangular) couples block j+1 to block j: T[m + r, m0 + c] = R[r, c]
        # for r <= c, kept in the upper storage as band[c - r, m + r] = T[m0 + c, m + r].
        self.band[ucols - urows, m + urows] = R[urows, ucols]
        return due

    def _orthogonalize(self, m0, m):
        """``W = OP q`` for the newest block, B-orthogonalised against the basis.

        First pass: classical Gram-Schmidt against the two newest blocks (the coupling to
        the previous one is known, ``R^T``, by symmetry).  Second pass: against the whole
        basis when the re-orthogonalisation is due (its coefficients on the older blocks
        measure the loss of orthogonality ``omega`` since the last one), else against the
        two newest blocks again.  Returns ``W``, the diagonal block ``A`` of ``T``, the
        scale of the coefficients and ``omega`` (None without a full pass).
        """
        V, split, R, b = self.V, self.split, self.R, self.b
        lo = max(0, m0 - b)
        W = self.solve(self.BVcur)
        if self.chooser is not None:  # the threads of this step's products
            split.threads = self.chooser.start_step()
            start = time.perf_counter()
        A = split.tdot(self.BVcur, W)
        if R is not None:
            split.sub_times(W, V[:, lo:m], np.vstack([R.T, A]))
        else:
            split.sub_times(W, V[:, m0:m], A)
        if self.chooser is not None:  # the first pass costs the same every step
            self.chooser.record(time.perf_counter() - start)
        scale = max(float(np.abs(A).max()), float(np.abs(R).max()) if R is not None else 0.0)
        omega = None
        if lo > 0 and self.since >= self.skip:
            C = split.tdot(V[:, :m], split.bmul(W))
            split.sub_times(W, V[:, :m], C)
            omega = float(np.abs(C[:lo]).max())
            A += C[m0:m]
            self.since = 0
        else:
            self.since += 1
            C2 = split.tdot(self.BVcur, W)
            if self.BVprev is not None:
                C2p = split.tdot(self.BVprev, W)
                split.sub_times(W, V[:, lo:m], np.vstack([C2p, C2]))
            else:
                split.sub_times(W, V[:, m0:m], C2)
            A += C2
        return W, A, scale, omega

    def rayleigh_ritz(self, m0, m):
        """Ritz pairs of ``T`` (m x m); whether all ``N`` wanted ones have converged.

        All eigenpairs of the dense ``T`` by divide and conquer (LAPACK syevd; faster
        than the banded solver on ``T``'s clusters of close eigenvalues), the wanted ones
        kept in ``theta``, ``Y``.  Their residual norms come from the Lanczos relation,
        ``||R Y[m0:m]||``, at no cost.  Otherwise the next look is scheduled.
        """
        N, negatives = self.N, self.negatives
        # (T is finite: its entries come from products checked by upper_cholesky.)
        theta, Y = la.eigh(band_to_dense(self.band, m), driver="evd", check_finite=False)
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
        self.theta, self.Y = theta, Y
        res = np.linalg.norm(self.R @ Y[m0:m], axis=0)
        nconv = int(np.sum(res <= self.tol * np.abs(theta) * self.pair_tol(theta)))
        if nconv == N and signs_ok:
            return True
        self.check = max(self.check, next_check(m, N - nconv, self.b, self.inside, self.n))
        return False

    def refine_smallest(self, theta, Y, m0, m, return_vectors):
        """Return the ``2 b`` smallest eigenvalues below an inside shift, by refined Rayleigh-Ritz.

        They lie farthest below the shift: ``lam = sigma + 1/theta`` turns a relative
        error of ``theta`` into one about ``sigma/lam`` times larger.  Their block of Ritz
        vectors ``X`` gets a Rayleigh-Ritz step with the solve made accurate by one step
        of refinement (errors of the Ritz vectors enter it squared), with or without
        eigenvectors, so that both give the same eigenvalues.  The Lanczos relation gives
        ``OP X = X diag(theta) + V_{m+1} R Y_m`` up to the coefficients dropped at the
        re-orthogonalisation passes: the refinement starts from it, one solve fewer.
        """
        b, V, B, R = self.b, self.V, self.B, self.R
        p = self.negatives
        smallest = slice(p - min(2 * b, p), p)  # theta[:p] ascending: lam_0 is theta[p - 1]
        X = self.split.times(V[:, :m], np.ascontiguousarray(Y[:, smallest]), "F")
        BX = np.asfortranarray(B @ X)
        Z0 = X * theta[smallest] + times(V[:, m:m + b], R @ Y[m0:m, smallest])
        G = BX.T @ self.refine(BX, Z0)
        MX = X.T @ BX
        G, MX = 0.5 * (G + G.T), 0.5 * (MX + MX.T)
        theta[smallest] = la.eigh(G, MX, eigvals_only=True)
        if return_vectors:  # the Ritz vectors of this step; their values stay those of
            # the call above without vectors (LAPACK's two drivers may differ in the last
            # bit, and shape_dna makes that call only)
            Y = Y.copy()
            Y[:, smallest] = Y[:, smallest] @ la.eigh(G, MX)[1]
        return theta, Y

    def ritz_vectors(self, Y, m):
        """Return the Ritz vectors ``V Y``, made B-orthonormal to rounding.

        The basis is only semi-orthogonal: Loewdin's symmetric orthonormalisation
        ``X G^(-1/2)``, ``G = X^T B X = I + O(1e-8)``, changes each vector least, and the
        eigenvalues stay those computed without vectors (the same bits).  The products
        over the rows run on the row ranges of the split (threaded on big meshes, the
        same bits with any number of threads).
        """
        split = self.split
        X = split.times(self.V[:, :m], np.ascontiguousarray(Y), "C")
        G = split.tdot(X, split.bmul(X))
        D, U = la.eigh(0.5 * (G + G.T))
        if not D.min() > 0.5:  # pragma: no cover - semi-orthogonality keeps G close to I
            raise NoConvergence("the Ritz vectors are not numerically independent")
        return split.times(X, (U / np.sqrt(D)) @ U.T, "C")
