"""Stage 3 of the pipeline: the eigensolve ``A f = -lam B f`` (Eq. 3) for the N smallest lam.

What is solved.  ``A`` (stiffness, negative semidefinite: the paper's sign) and ``B``
(mass, positive definite) come from :mod:`cshape.fem`; with ``K = -A`` the problem is
``K f = lam B f`` and every ``lam >= 0``.  ``lam[0] = 0`` for a closed surface or Neumann
boundary conditions, once per connected component.

What is returned.  :func:`shape_dna` gives the ``N`` smallest eigenvalues, ascending,
``lam[0]`` included (Shape-DNA, Section 2.1); :func:`eigenbasis` also gives the
eigenfunctions ``phi`` (n, N), B-orthonormal (``phi.T @ B @ phi = I``), with the same
eigenvalues bit for bit, as one frozen :class:`Eigenbasis` with the mass matrix ``B``, the
area and the (repaired) mesh: what the signatures (:mod:`cshape.signatures`) and the maps
(:mod:`cshape.maps`) take.  Round-off of zero eigenvalues (below :data:`ZERO_ROUNDOFF`
times the largest) is set to 0.
:func:`solve_eigenproblem` does the same for given ``A`` and ``B``.

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

The solver lives in the private subpackage :mod:`cshape._eigensolver`, one module by job:
``shift`` (the shift and its factorisation), ``lanczos`` (the iteration), ``threads`` (the
thread policy), ``cholmod`` (the sparse Cholesky backends).  The derivation is the
eigensolver guide of the documentation; measured figures: ``benchmarks/SCALE.md``.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any, Literal, overload

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph
from numpy.typing import NDArray

from . import _refine
from ._checks import (
    _caller_stacklevel,
    check_bool,
    check_choice,
    check_int,
    check_real,
    check_spectrum,
)
from ._eigensolver import shift as _shift
from ._eigensolver.lanczos import (  # noqa: F401  (block sizes, for benchmarks)
    BLOCK_SIZE,
    MIN_BLOCK_SIZE,
)
from ._eigensolver.threads import one_blas_thread, solver_threads  # noqa: F401  (the policy)
from .fem import BOUNDARY_CONDITIONS, MASS_TYPES
from .fem import _problem as fem
from .mesh import CShapeWarning, Mesh, MeshLike, as_mesh, repair_mesh

__all__ = [
    "Eigenbasis",
    "SpectrumSettings",
    "eigenbasis",
    "shape_dna",
]

#: Problems with at most this many unknowns (or ``3 N`` or more of them) are solved
#: densely by LAPACK: there the sparse path is no faster.
DENSE_LIMIT = 700

#: Values of the ``refine`` option of :func:`shape_dna` (how the eigenvalues are computed).
REFINEMENTS = ("none", "extrapolate")
#: Eigenvalues within this fraction of the largest from 0 are round-off of zero eigenvalues:
#: the eigensolver sets them to 0, and an :class:`Eigenbasis` refuses anything further below.
ZERO_ROUNDOFF = 1e-10

#: An eigensolve estimated (:func:`estimate_seconds`) to take longer warns before it starts.
LONG_SOLVE_SECONDS = 60.0


@dataclass(frozen=True)
class SpectrumSettings:
    """How a spectrum is computed: ``N``, ``bc``, ``mass`` and ``refine``, checked once.

    The settings of :func:`shape_dna` as one frozen value, the way :class:`cshape.Descriptor`
    carries a descriptor's: :func:`cshape.describe` makes it once from its arguments, its
    tasks carry it to the workers, and a :class:`cshape.DescriptorTable` says with it how
    its eigenvalues were computed (``table.settings``), so that one more mesh is described
    the same way.

    Parameters
    ----------
    N : int, default=100
        Number of eigenvalues, lam_0 included, 1 or more.
    bc : {'neumann', 'dirichlet'}, default='neumann'
        Boundary condition (see :func:`shape_dna`).
    mass : {'consistent', 'lumped', 'mixed'}, default='consistent'
        Mass matrix (see :func:`shape_dna`).
    refine : {'none', 'extrapolate'}, default='none'
        Refinement of the eigenvalues (see :func:`shape_dna`).

    Raises
    ------
    TypeError
        ``N`` not an integer (bools are refused), a setting not a string.
    ValueError
        ``N < 1``, an unknown ``bc``, ``mass`` or ``refine``.

    Examples
    --------
    >>> from cshape.spectrum import SpectrumSettings
    >>> SpectrumSettings(30, mass="MIXED")
    SpectrumSettings(N=30, bc='neumann', mass='mixed', refine='none')
    >>> SpectrumSettings(30).as_kwargs()
    {'N': 30, 'bc': 'neumann', 'mass': 'consistent', 'refine': 'none'}
    """

    N: int = 100
    bc: str = "neumann"
    mass: str = "consistent"
    refine: str = "none"

    def __post_init__(self) -> None:
        """Check every setting and store it in its one spelling."""
        object.__setattr__(self, "N", check_int("N", self.N, min=1))
        object.__setattr__(self, "bc", check_choice("bc", self.bc, BOUNDARY_CONDITIONS))
        object.__setattr__(self, "mass", check_choice("mass", self.mass, MASS_TYPES))
        object.__setattr__(self, "refine", check_choice("refine", self.refine, REFINEMENTS))

    def as_kwargs(self) -> dict[str, Any]:
        """Return the settings as keyword arguments of :func:`shape_dna` and :func:`describe`.

        Returns
        -------
        dict
            ``{'N': ..., 'bc': ..., 'mass': ..., 'refine': ...}``.
        """
        return {"N": self.N, "bc": self.bc, "mass": self.mass, "refine": self.refine}


def _check_N(N: object, n_unknowns: int, bc: str) -> int:
    N = check_int("N", N, min=1)
    if N > n_unknowns:
        raise ValueError(
            f"N={N} eigenvalues requested but the {bc} problem has only {n_unknowns} unknowns "
            f"(mesh vertices{' not on the boundary' if bc == 'dirichlet' else ''}); use "
            f"N <= {n_unknowns} or a finer mesh (e.g. cshape.data.variants.subdivide(mesh) or "
            "cshape.data.variants.remesh(mesh))"
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
    (:func:`cshape._eigensolver.shift.solve_inside`), else the shift below the spectrum.
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
    lam[np.abs(lam) < ZERO_ROUNDOFF * scale] = 0.0
    lam = np.maximum(lam, 0.0)
    if return_vectors:
        return lam, phi  # phi is set when return_vectors
    return lam


@dataclass(frozen=True, eq=False, repr=False)
class Eigenbasis:
    """The ``N`` smallest eigenpairs of a mesh with its mass matrix: one value, computed once.

    What the signatures (:func:`cshape.hks`, :func:`cshape.wks`, ...) and the maps
    (:func:`cshape.maps.functional_map`, :func:`cshape.maps.zoomout`, ...) take.  Usually made by
    :func:`eigenbasis`; the constructor builds one from plain arrays (another solver's
    eigenpairs, say) and validates them.  The arrays are kept as read-only views.

    Parameters
    ----------
    lam : array_like, shape (N,)
        Eigenvalues of ``A f = -lam B f`` (Eq. 3), ``>= 0``: negative round-off down to
        ``ZERO_ROUNDOFF`` times the largest is set to 0, anything below is refused.
    phi : array_like, shape (n, N)
        Eigenfunctions on the ``n`` mesh vertices, ``phi[:, i]`` for ``lam[i]``,
        B-orthonormal: ``phi.T @ B @ phi = I``.
    B : scipy.sparse matrix or array_like, shape (n, n)
        Mass matrix over the mesh vertices (:func:`cshape.fem_matrices`), stored as CSR.
    area : float, optional
        Surface area.  Default: ``B.sum()``.
    mesh : Mesh, optional
        The mesh of ``n`` vertices the pairs belong to (the orientation term of
        :func:`cshape.maps.functional_map` needs it).
    bc : {'neumann', 'dirichlet'}, default='neumann'
    mass : {'consistent', 'lumped', 'mixed'}, default='consistent'
        How the pairs were computed (see :func:`cshape.fem_matrices`).

    Attributes
    ----------
    N : int
        Number of eigenpairs.
    n_vertices : int
        Number of rows of ``phi``.

    Raises
    ------
    TypeError
        ``lam``, ``phi`` or ``B`` not real arrays, ``mesh`` not a Mesh, ``bc`` or ``mass``
        not a string.
    ValueError
        Shapes that do not agree, NaN or infinite values, negative eigenvalues, an area
        that is not positive, an unknown ``bc`` or ``mass``.

    Examples
    --------
    >>> import cshape
    >>> basis = cshape.eigenbasis(cshape.shapes.icosphere(3), N=16)
    >>> basis
    Eigenbasis(N=16, n_vertices=642, bc='neumann', mass='consistent', area=12.5, lam=[0 .. 12.2])
    >>> basis.truncate(4).lam.round(2)  # the unit sphere: 0, then 2 (three times)
    array([0.  , 2.01, 2.01, 2.01])
    """

    lam: NDArray[np.float64]
    phi: NDArray[np.float64]
    B: sp.csr_matrix
    area: float = None  # type: ignore[assignment]  # set from B when not given
    mesh: Mesh | None = field(default=None, kw_only=True)
    bc: str = field(default="neumann", kw_only=True)
    mass: str = field(default="consistent", kw_only=True)

    def __post_init__(self) -> None:
        """Validate the fields and store them normalised (read-only arrays, CSR ``B``)."""
        lam = _check_eigenvalues(self.lam)
        phi = _real_array("phi", self.phi)
        if phi.ndim != 2 or phi.shape[1] != len(lam):
            raise ValueError(
                f"phi must have shape (n, N) = (n, {len(lam)}), one column per eigenvalue, "
                f"got shape {phi.shape}; pass lam[:N] and phi[:, :N] of the same eigenpairs"
            )
        if not np.isfinite(phi).all():
            raise ValueError("phi contains NaN or infinite values")
        n = phi.shape[0]
        B = self.B
        if not sp.issparse(B):
            B = _real_array("B", B)
        if B.ndim != 2 or B.shape != (n, n):
            raise ValueError(
                f"B must be the mass matrix of shape (n, n) = ({n}, {n}) (one row per row of "
                f"phi), got shape {B.shape}; pass the B of cshape.fem_matrices(mesh)"
            )
        B = sp.csr_matrix(B, dtype=np.float64)
        area = float(B.sum()) if self.area is None else check_real("area", self.area,
                                                                     positive=True)
        if not area > 0:
            raise ValueError(f"B sums to {area:.6g}: a mass matrix sums to the (positive) "
                             "surface area; pass the B of cshape.fem_matrices(mesh)")
        if self.mesh is not None:
            if not isinstance(self.mesh, Mesh):
                raise TypeError(f"mesh must be a cshape.Mesh or None, got "
                                f"{type(self.mesh).__name__}")
            if self.mesh.n_vertices != n:
                raise ValueError(
                    f"mesh has {self.mesh.n_vertices} vertices but phi has {n} rows; pass the "
                    "(repaired) mesh whose eigenpairs these are"
                )
        set_ = object.__setattr__
        set_(self, "lam", _read_only(lam))
        set_(self, "phi", _read_only(phi))
        set_(self, "B", B)
        set_(self, "area", area)
        set_(self, "bc", check_choice("bc", self.bc, BOUNDARY_CONDITIONS))
        set_(self, "mass", check_choice("mass", self.mass, MASS_TYPES))

    @property
    def N(self) -> int:
        """Number of eigenpairs ``N``."""
        return int(self.lam.shape[0])

    @property
    def n_vertices(self) -> int:
        """Number of vertices ``n`` (rows of ``phi``)."""
        return int(self.phi.shape[0])

    def truncate(self, N: int) -> Eigenbasis:
        """Return the basis of the first ``N`` eigenpairs (views, not copies).

        Parameters
        ----------
        N : int
            ``1 <= N <= self.N``.

        Returns
        -------
        Eigenbasis
            ``lam[:N]`` and ``phi[:, :N]``, with this basis's mass matrix ``B``, area, mesh
            and conditions.

        Raises
        ------
        TypeError
            If ``N`` is not an integer.
        ValueError
            If ``N`` is outside ``1 .. self.N``.
        """
        N = check_int("N", N, min=1, max=self.N)
        out = object.__new__(Eigenbasis)
        for name, value in (("lam", self.lam[:N]), ("phi", self.phi[:, :N]), ("B", self.B),
                            ("area", self.area), ("mesh", self.mesh), ("bc", self.bc),
                            ("mass", self.mass)):
            object.__setattr__(out, name, value)
        return out

    def __repr__(self) -> str:
        """Sizes, conditions, area and the range of the eigenvalues, on one line."""
        return (f"Eigenbasis(N={self.N}, n_vertices={self.n_vertices}, bc={self.bc!r}, "
                f"mass={self.mass!r}, area={self.area:.3g}, "
                f"lam=[{self.lam[0]:.3g} .. {self.lam[-1]:.3g}])")


def _real_array(name: str, x: Any) -> np.ndarray:
    """``x`` as a float64 array, or a TypeError naming ``name``."""
    if isinstance(x, (str, bytes)) or np.iscomplexobj(x):
        raise TypeError(f"{name} must be a real array, got {type(x).__name__}")
    try:
        return np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a real array, got {type(x).__name__}") from None


def _check_eigenvalues(lam: object) -> NDArray[np.float64]:
    """``lam`` checked (:func:`cshape._checks.check_spectrum`), ``>= 0`` up to round-off."""
    lam = check_spectrum(lam, "lam")
    scale = float(np.abs(lam).max())
    if lam.min() < -ZERO_ROUNDOFF * max(scale, np.finfo(float).tiny):
        raise ValueError(
            f"lam must be eigenvalues >= 0 (A f = -lam B f), got a minimum of {lam.min():.6g}; "
            "pass the eigenvalues from cshape.shape_dna or cshape.eigenbasis(...).lam"
        )
    return lam if lam.min() >= 0 else np.maximum(lam, 0.0)


def _read_only(a: np.ndarray) -> np.ndarray:
    """Return a read-only view of ``a`` (``a`` itself stays writable)."""
    v = a.view()
    v.setflags(write=False)
    return v


def eigenbasis(mesh: MeshLike, N: int = 100, bc: str = "neumann", mass: str = "consistent"
               ) -> Eigenbasis:
    """Compute the ``N`` smallest Laplace-Beltrami eigenpairs of a mesh, with ``B`` and the area.

    The one way to the eigenfunctions: the mesh is repaired once
    (:func:`cshape.repair_mesh`), assembled once and solved once, and the result is one
    frozen :class:`Eigenbasis`, what the signatures and the maps take.  ``basis.lam`` are
    the eigenvalues of :func:`shape_dna` for the same arguments (the same bits from the block
    Lanczos solver; on the dense path of small problems, LAPACK with and without vectors, to
    rounding).

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        A triangle mesh (or another library's mesh object).
    N : int, default=100
        Number of eigenpairs (lam_0 included).
    bc : {'neumann', 'dirichlet'}, default='neumann'
        Boundary condition on boundary and non-manifold vertices: ``'neumann'`` keeps every
        vertex as an unknown (Eq. (4)-(7)); ``'dirichlet'`` fixes the function to zero there
        (see :func:`cshape.fem_matrices`).
    mass : {'consistent', 'lumped', 'mixed'}, default='consistent'
        The consistent mass matrix ``B`` of Eq. (5) / (7), its lumped diagonal
        ``sum_t |t|/3``, or their average (see :func:`cshape.fem_matrices`).

    Returns
    -------
    Eigenbasis
        ``lam`` (N,) ascending eigenvalues of ``A f = -lam B f`` (Eq. 3); ``phi`` (n, N) the
        eigenfunctions on the vertices of the repaired mesh, ``phi[:, i]`` for ``lam[i]``,
        B-orthonormal, zero on fixed vertices for ``bc='dirichlet'``; ``B`` (n, n) the mass
        matrix over all vertices; ``area`` the mesh's area; ``mesh`` the repaired mesh.

    Raises
    ------
    TypeError
        ``N`` not an integer (bools are refused), ``bc`` or ``mass`` not a string, ``mesh``
        not a mesh.
    ValueError
        ``N < 1`` or more than the unknowns, an unknown ``bc`` or ``mass``, an invalid or
        zero-area mesh.
    """
    settings = SpectrumSettings(N, bc, mass)
    mesh, problem, lam, phi = _solve_pairs(mesh, settings.N, settings.bc, settings.mass)
    return Eigenbasis(lam, phi, problem.B_vertices, problem.area, mesh=mesh, bc=problem.bc,
                      mass=settings.mass)


def _solve_pairs(mesh, N, bc, mass):
    """``(repaired mesh, FEM problem, lam, phi on the vertices)``: the one path of the pairs."""
    mesh, problem = _prepare(mesh, N, bc, mass)
    lam, phi = solve_eigenproblem(problem.A, problem.B, N, return_vectors=True)
    return mesh, problem, lam, problem.to_vertices(phi)


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
        Boundary condition on boundary and non-manifold vertices: ``'neumann'`` keeps every
        vertex as an unknown (Eq. (4)-(7)); ``'dirichlet'`` fixes the function to zero
        there, so that ``lam[0] > 0`` on an open surface (see :func:`cshape.fem_matrices`).
        A closed manifold mesh has no such vertices: both give the same spectrum.
    mass : {'consistent', 'lumped', 'mixed'}, default='consistent'
        The consistent mass matrix ``B`` of Eq. (5) / (7) (the paper's), its lumped
        diagonal ``sum_t |t|/3``, or ``'mixed'``, their average, whose eigenvalues depend
        far less on the mesh resolution at the cost of a plain solve (see
        :func:`cshape.fem_matrices`).
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
        metric, a small error that does not grow with the index.)  :func:`eigenbasis`
        has no such option: eigenfunctions are not extrapolated.

    Returns
    -------
    lam : ndarray, shape (N,)
        Ascending eigenvalues; ``lam[0] == 0`` for a closed (or Neumann) mesh.  A mesh
        with ``c`` connected components has ``c`` zero eigenvalues (a warning says so).

    Raises
    ------
    TypeError, ValueError
        As :func:`eigenbasis`; also an unknown ``refine``.

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
    return _shape_dna(mesh, SpectrumSettings(N, bc, mass, refine))


def _shape_dna(mesh: MeshLike, settings: SpectrumSettings) -> NDArray[np.float64]:
    """:func:`shape_dna` with its settings checked already (the path of the batch workers)."""
    N, mass = settings.N, settings.mass
    mesh, problem = _prepare(mesh, N, settings.bc, mass)
    lam = solve_eigenproblem(problem.A, problem.B, N, return_vectors=False)
    if settings.refine == "none":
        return lam
    fine = fem(_refine.midpoint_subdivision(mesh), bc=problem.bc, mass=mass, repair=False)
    long = long_solve_message(fine.n_unknowns, N)  # the subdivided mesh's solve
    if long:
        warnings.warn(f"refine='extrapolate' solves its midpoint subdivision too: {long}",
                      CShapeWarning, stacklevel=_caller_stacklevel())
    lam_fine = solve_eigenproblem(fine.A, fine.B, N, return_vectors=False)
    return _refine.extrapolate(lam, lam_fine)


def estimate_seconds(n: int, N: int) -> float:
    """Estimate the wall time of the eigensolve of ``N`` eigenvalues with ``n`` unknowns, in s.

    ``1e-9 n^3`` for the dense path (``n <= DENSE_LIMIT`` or ``3 N >= n``), else
    ``1e-8 n N^2`` (the Lanczos basis of about ``3 N`` vectors of length ``n``, kept
    orthogonal), plus ``2e-5 n`` (FEM, factorisation); the coefficients are fitted to
    measured solves (``benchmarks/SCALE.md``, "Operations notes").  The estimate is for
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
            "truncated log and F1 descriptors drop them; use "
            "cshape.largest_component(mesh) to describe one piece")


def _prepare(mesh, N, bc, mass):
    """``(repaired mesh, FEM problem)`` of an eigensolve of ``N`` pairs, with its warnings."""
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
        warnings.warn(components_message(ncomp), CShapeWarning, stacklevel=_caller_stacklevel())
    long = long_solve_message(problem.n_unknowns, N)
    if long:
        warnings.warn(long, CShapeWarning, stacklevel=_caller_stacklevel())
    return mesh, problem
