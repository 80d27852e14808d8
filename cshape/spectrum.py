"""Stage 3 of the pipeline: the eigensolve ``A f = -lam B f`` (Eq. 3) for the N smallest lam.

With ``K = -A`` (positive semidefinite) the problem is ``K f = lam B f``.  Small problems
are solved densely (LAPACK); larger ones by shift-invert Lanczos around a negative shift
``sigma`` with a sparse Cholesky factorisation of ``K - sigma B`` (CHOLMOD through the
``cholespy`` wheel, falling back to SciPy's SuperLU).  The solve is deterministic (fixed
start vector) and runs to machine precision (``tol=0``): a loose tolerance can silently
miss a copy of a repeated eigenvalue on symmetric shapes.
"""

from __future__ import annotations

import warnings

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .fem import fem
from .mesh import CShapeWarning, as_mesh

__all__ = ["eigenpairs", "shape_dna", "solve_eigenproblem"]

#: Problems with at most this many unknowns are solved densely.
DENSE_LIMIT = 1200


def _check_N(N, n_unknowns, bc):
    if isinstance(N, bool) or not isinstance(N, (int, np.integer)):
        raise TypeError(f"N must be an integer, got {type(N).__name__} {N!r}")
    N = int(N)
    if N < 1:
        raise ValueError(f"N must be at least 1 (the number of eigenvalues), got {N}")
    if N > n_unknowns:
        raise ValueError(
            f"N={N} eigenvalues requested but the {bc} problem has only {n_unknowns} unknowns "
            f"(mesh vertices{' not on the boundary' if bc == 'dirichlet' else ''}); use "
            f"N <= {n_unknowns} or a finer mesh (e.g. cshape subdivision/remeshing)"
        )
    return N


class _CholeskyOperator(spla.LinearOperator):
    """``x -> (K - sigma B)^{-1} x`` with a sparse Cholesky factor."""

    def __init__(self, M):
        M = sp.csr_matrix(M)
        n = M.shape[0]
        super().__init__(dtype=np.float64, shape=(n, n))
        self._solver = None
        try:
            import cholespy

            C = M.tocoo()
            self._solver = cholespy.CholeskySolverD(
                n,
                C.row.astype(np.int32),
                C.col.astype(np.int32),
                C.data.astype(np.float64),
                cholespy.MatrixType.COO,
            )
        except ImportError:  # pragma: no cover - cholespy is a core dependency
            self._lu = spla.splu(M.tocsc())

    def _matvec(self, x):
        x = np.ascontiguousarray(x, dtype=np.float64).reshape(-1)
        if self._solver is None:
            return self._lu.solve(x)
        out = np.empty_like(x)
        self._solver.solve(x, out)
        return out

    def _matmat(self, X):
        X = np.ascontiguousarray(X, dtype=np.float64)
        if self._solver is None:
            return self._lu.solve(X)
        out = np.empty_like(X)
        self._solver.solve(X, out)
        return out


def solve_eigenproblem(A, B, N, *, return_vectors=True, sigma=None):
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
        Default: ``-0.01 * trace(K) / trace(B) / k``-scaled, a small negative number on
        the scale of the problem.

    Returns
    -------
    lam : ndarray, shape (N,)
        Ascending eigenvalues (tiny negative round-off clipped to 0).
    phi : ndarray, shape (k, N)
        B-orthonormal eigenvectors (``phi.T @ B @ phi = I``), only if ``return_vectors``.
    """
    K = (-sp.csr_matrix(A)).tocsr()
    B = sp.csr_matrix(B)
    k = K.shape[0]
    N = _check_N(N, k, "")
    if k <= DENSE_LIMIT:
        if return_vectors:
            lam, phi = la.eigh(K.toarray(), B.toarray(), subset_by_index=[0, N - 1])
        else:
            lam = la.eigh(
                K.toarray(), B.toarray(), subset_by_index=[0, N - 1], eigvals_only=True
            )
            phi = None
    else:
        if sigma is None:
            # a shift well below lam_1 on the scale of the mesh: lam_1 ~ 4 pi / area
            area = float(B.sum())
            sigma = -0.01 * 4.0 * np.pi / area if area > 0 else -1e-2
        op = _CholeskyOperator(K - sigma * B)
        v0 = np.random.default_rng(0).standard_normal(k)
        ncv = min(k, max(2 * N + 1, 20))
        res = spla.eigsh(
            K,
            k=N,
            M=B,
            sigma=sigma,
            which="LM",
            OPinv=op,
            v0=v0,
            ncv=ncv,
            tol=0,
            return_eigenvectors=return_vectors,
        )
        if return_vectors:
            lam, phi = res
        else:
            lam, phi = res, None
        order = np.argsort(lam)
        lam = lam[order]
        if phi is not None:
            phi = phi[:, order]
    lam = np.asarray(lam, dtype=np.float64)
    scale = max(1.0, float(np.abs(lam).max()))
    lam[np.abs(lam) < 1e-10 * scale] = 0.0
    lam = np.maximum(lam, 0.0)
    if return_vectors:
        return lam, phi
    return lam


def eigenpairs(mesh, N=100, bc="neumann", mass="consistent"):
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
        Ascending eigenvalues of ``A f = -lam B f`` (Eq. 3).
    phi : ndarray, shape (n, N)
        Eigenfunctions on the mesh vertices, ``phi[:, i]`` for ``lam[i]``; B-orthonormal
        over the unknowns; zero on fixed vertices for ``bc='dirichlet'``.  If the mesh
        was repaired (duplicate or unreferenced vertices), ``n`` is the vertex count of
        the repaired mesh.
    """
    problem = _prepare(mesh, N, bc, mass)
    lam, phi = solve_eigenproblem(problem.A, problem.B, N, return_vectors=True)
    return lam, problem.to_vertices(phi)


def shape_dna(mesh, N=100, bc="neumann", mass="consistent"):
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

    Examples
    --------
    >>> import cshape
    >>> lam = cshape.shape_dna(cshape.shapes.icosphere(3), N=4)
    >>> lam.round(2)  # the unit sphere: 0, then 2 (three times)
    array([0.  , 2.01, 2.01, 2.01])
    """
    problem = _prepare(mesh, N, bc, mass)
    return solve_eigenproblem(problem.A, problem.B, N, return_vectors=False)


def _prepare(mesh, N, bc, mass):
    mesh = as_mesh(mesh)
    problem = fem(mesh, bc=bc, mass=mass)
    _check_N(N, problem.n_unknowns, problem.bc)
    ncomp = mesh.n_components
    if ncomp > 1:
        warnings.warn(
            f"mesh has {ncomp} connected components: its spectrum is the union of theirs, "
            f"with {ncomp} zero eigenvalues under Neumann conditions; use "
            "cshape.largest_component(mesh) to describe one piece",
            CShapeWarning,
            stacklevel=3,
        )
    return problem
