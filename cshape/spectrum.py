"""Stage 3 of the pipeline: the eigensolve ``A f = -lam B f`` (Eq. 3) for the N smallest lam.

What is solved.  ``A`` (stiffness, negative semidefinite: the paper's sign) and ``B``
(mass, positive definite) come from :mod:`cshape.fem`; with ``K = -A`` the problem is
``K f = lam B f`` and every ``lam >= 0``.  ``lam[0] = 0`` for a closed surface or Neumann
boundary conditions, once per connected component.

What is returned.  :func:`shape_dna` gives the ``N`` smallest eigenvalues, ascending,
``lam[0]`` included (Shape-DNA, Section 2.1); :func:`eigenpairs` also gives the
eigenfunctions ``phi`` (n, N), B-orthonormal (``phi.T @ B @ phi = I``), with the same
eigenvalues bit for bit.  Round-off of zero eigenvalues (below ``1e-10`` times the
largest) is set to 0.  :func:`solve_eigenproblem` does the same for given ``A`` and ``B``.

Accuracy.  Small problems (at most :data:`DENSE_LIMIT` unknowns, or ``3 N`` or more of
them) are solved densely by LAPACK.  Larger ones use block shift-invert Lanczos on one
sparse factorisation of ``K - sigma B``, converged to a relative residual of ``1e-6``:
the eigenvalues agree with ARPACK's full-accuracy ones (``tol=0``) and dense LAPACK's to
about ``1e-10`` relative (the tests hold them to ``1e-10`` and ``1e-9``).  If it does not
converge, ARPACK itself answers.

Repeated eigenvalues are all found: below an inside shift they are counted exactly by
the inertia of the factorisation; above it a block of ``b >= 6`` random start vectors
resolves the multiplicities of up to 5 that a connected surface's symmetry gives, and a
mesh of several connected components is solved one component at a time.

Determinism.  Fixed seeds: the same input gives the same bits in every run, with any
number of threads (:func:`solver_threads`).

The solver lives in private modules by job: :mod:`cshape._shift` (the shift and its
factorisation), :mod:`cshape._lanczos` (the iteration), :mod:`cshape._threads` (the thread
policy), :mod:`cshape._cholmod` (the sparse Cholesky backends).  The derivation is the
eigensolver guide of the documentation; measured figures: ``benchmarks/SCALE.md``.
"""

from __future__ import annotations

import warnings
from typing import Literal, overload

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph
from numpy.typing import NDArray

from . import _refine, _shift
from ._checks import check_bool, check_choice, check_int, check_real
from ._lanczos import BLOCK_SIZE, MIN_BLOCK_SIZE  # noqa: F401  (block sizes, for benchmarks)
from ._threads import one_blas_thread, solver_threads
from .fem import _problem as fem
from .mesh import CShapeWarning, MeshLike, as_mesh, repair_mesh

__all__ = ["eigenpairs", "estimate_seconds", "shape_dna", "solve_eigenproblem",
           "solver_threads"]

#: Problems with at most this many unknowns (or ``3 N`` or more of them) are solved
#: densely by LAPACK: there the sparse path is no faster.
DENSE_LIMIT = 700

#: Values of the ``refine`` option of :func:`shape_dna` (how the eigenvalues are computed).
REFINEMENTS = ("none", "extrapolate")

#: An eigensolve estimated (:func:`estimate_seconds`) to take longer warns before it starts.
LONG_SOLVE_SECONDS = 60.0


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


def _is_dense(k: int, N: int) -> bool:
    """Tell whether a problem of ``k`` unknowns and ``N`` pairs takes the dense path.

    A Krylov space would need about ``3 N`` dimensions.
    """
    return k <= DENSE_LIMIT or 3 * N >= k


def _dense(K, B, N, return_vectors):
    """Return the ``N`` smallest pairs by dense LAPACK (``phi`` None unless ``return_vectors``)."""
    out = la.eigh(K.toarray(), B.toarray(), subset_by_index=[0, N - 1],
                  eigvals_only=not return_vectors)
    return out if return_vectors else (out, None)


def _solve_sparse(K, B, N, sigma, return_vectors):
    """Sparse path of :func:`solve_eigenproblem`, one connected component at a time.

    The problem of a mesh with several connected components is block diagonal.  Each
    block is solved on its own (dense if small) and the N smallest eigenvalues of the
    union are kept: identical components would otherwise make every eigenvalue exactly
    repeated once per component, beyond what the block size of the Krylov method can
    resolve.  A connected problem takes the inside shift where it applies
    (:func:`cshape._shift.solve_inside`), else the shift below the spectrum.
    """
    k = K.shape[0]
    same = _shift.same_pattern(K, B)
    if same and bool((B.data > 0).all()):
        pattern = B  # a consistent mass matrix: positive on every edge of the mesh
    else:
        pattern = (K != 0) + (B != 0)  # explicit zeros are no edges
    ncomp, labels = csgraph.connected_components(pattern, directed=False)
    if ncomp > 1:
        return _solve_components(K, B, N, sigma, return_vectors, ncomp, labels)
    if sigma is None and k <= _shift.INSIDE_LIMIT and N >= _shift.INSIDE_MIN_N:
        out = _shift.solve_inside(K, B, N, same, return_vectors)
        if out is not None:
            return out
    return _shift.solve_below(K, B, N, sigma, same, return_vectors)


def _solve_components(K, B, N, sigma, return_vectors, ncomp, labels):
    """:func:`_solve_sparse` of each of ``ncomp`` components (``labels``), merged."""
    k = K.shape[0]
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
        if _is_dense(len(idx), Nc):
            with one_blas_thread():  # as in solve_eigenproblem's dense path
                lc, pc = _dense(Kc, Bc, Nc, return_vectors)
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
    """Return the ``N`` smallest eigenpairs of ``A f = -lam B f`` (Eq. 3).

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
    if small) by block shift-invert Lanczos on one sparse factorisation, with the shift
    inside the spectrum where it applies (``sigma`` not given), falling back to ARPACK
    (``eigsh``, ``tol=0``) if it does not converge.  The result is deterministic: fixed
    random seeds.
    """
    return_vectors = check_bool("return_vectors", return_vectors)
    if sigma is not None:
        sigma = check_real("sigma", sigma)
    K = (-sp.csr_matrix(A)).tocsr()
    B = sp.csr_matrix(B)
    k = K.shape[0]
    N = _check_N(N, k, "")
    if _is_dense(k, N):
        # one BLAS thread: at this size threading gains little, and spinning BLAS threads
        # slow it down severalfold on a busy machine
        with one_blas_thread():
            lam, phi = _dense(K, B, N, return_vectors)
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
        return lam, phi  # phi is set when return_vectors
    return lam


def eigenpairs(mesh: MeshLike, N: int = 100, bc: str = "neumann", mass: str = "consistent"
               ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Return the ``N`` smallest Laplace-Beltrami eigenvalues and B-orthonormal eigenfunctions.

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


def shape_dna(mesh: MeshLike, N: int = 100, bc: str = "neumann", mass: str = "consistent",
              refine: str = "none") -> NDArray[np.float64]:
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
    refine : {'none', 'extrapolate'}, default='none'
        ``'none'``: the eigenvalues of the linear FEM problem of Eq. (3)-(7), whose error
        grows like ``h^2 lam^2`` (``h`` the edge length).  ``'extrapolate'``: Richardson
        extrapolation ``(4 lam_fine - lam) / 3`` over one midpoint subdivision of the
        mesh (every triangle split into four, kept flat; ``lam_fine`` its eigenvalues),
        paired by index.  It removes the ``h^2`` term of the error against the spectrum
        of the polyhedral surface where the subdivision repeats the mesh's pattern at half
        the size (the error is then ``O(h^4)``); elsewhere the term shrinks by a large
        factor but need not vanish.  It solves a second problem of about four times the
        unknowns.  (A curved surface differs from its polyhedron by ``O(h^2)`` in its
        metric, a small error that does not grow with the index.)  :func:`eigenpairs`
        has no such option: eigenfunctions are not extrapolated.

    Returns
    -------
    lam : ndarray, shape (N,)
        Ascending eigenvalues; ``lam[0] == 0`` for a closed (or Neumann) mesh.  A mesh
        with ``c`` connected components has ``c`` zero eigenvalues (a warning says so).

    Raises
    ------
    TypeError, ValueError
        As :func:`eigenpairs`; also an unknown ``refine``.

    Notes
    -----
    Meshes of 50,000 vertices and more may use several threads for the solves and the
    products of the eigensolver (never in batch workers), where timing during the solve
    shows that they help; the environment variable ``CSHAPE_THREADS`` sets the most.  The
    eigenvalues are the same bits with any number of threads (:func:`solver_threads`).

    Examples
    --------
    >>> import cshape
    >>> lam = cshape.shape_dna(cshape.shapes.icosphere(3), N=4)
    >>> lam.round(2)  # the unit sphere: 0, then 2 (three times)
    array([0.  , 2.01, 2.01, 2.01])
    """
    refine = check_choice("refine", refine, REFINEMENTS)
    if refine == "none":
        problem = _prepare(mesh, N, bc, mass)
        return solve_eigenproblem(problem.A, problem.B, N, return_vectors=False)
    problem, mesh = _prepare(mesh, N, bc, mass, with_mesh=True)
    lam = solve_eigenproblem(problem.A, problem.B, N, return_vectors=False)
    fine = fem(_refine.midpoint_subdivision(mesh), bc=problem.bc, mass=mass, repair=False)
    long = long_solve_message(fine.n_unknowns, N)  # the subdivided mesh's solve
    if long:
        warnings.warn(f"refine='extrapolate' solves its midpoint subdivision too: {long}",
                      CShapeWarning, stacklevel=2)
    lam_fine = solve_eigenproblem(fine.A, fine.B, N, return_vectors=False)
    return _refine.extrapolate(lam, lam_fine)


def estimate_seconds(n: int, N: int) -> float:
    """Estimate the wall time of the eigensolve of ``N`` eigenvalues with ``n`` unknowns, in s.

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
    """Return the warning of an eigensolve estimated to take long, or None.

    See :func:`estimate_seconds` and ``LONG_SOLVE_SECONDS``.
    """
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
    """Return the warning about a mesh of ``ncomp`` connected components.

    Also shown by a batch run whose eigenvalues come from the cache.
    """
    return (f"mesh has {ncomp} connected components: its spectrum is the union of theirs, "
            f"with {ncomp} zero eigenvalues under Neumann conditions; the log-Weyl, "
            "truncated log and F1 descriptors drop them (cshape.nonzero_eigenvalues); use "
            "cshape.largest_component(mesh) to describe one piece")


def _prepare(mesh, N, bc, mass, with_mesh=False):
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
    return (problem, mesh) if with_mesh else problem
