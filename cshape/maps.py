"""Stage 7 of the pipeline: maps between shapes (functional maps, ZoomOut).

A *functional map* (Ovsjanikov et al. 2012) carries functions from a source shape ``S`` to a
target shape ``T``.  In the truncated, B-orthonormal eigenbases ``Phi_S`` (``n_S x N_S``)
and ``Phi_T`` (``n_T x N_T``) of :func:`cshape.eigenbasis` it is a small matrix ``C``
(``N_T x N_S``): a function ``f = Phi_S a`` on ``S`` goes to ``Phi_T C a`` on ``T``.  The
functions here take the two :class:`cshape.Eigenbasis` values (``phi``, ``B``, ``lam`` and
the mesh of each shape).  A
vertex map ``p`` (for each target vertex ``y``, a source vertex ``p[y]``; the pyFM
``p2p_21`` convention) and ``C`` determine each other:

``C = Phi_T^T B_T Pi Phi_S``  (``Pi[y, p[y]] = 1``, the pull-back, Eq. 3 of Ovsjanikov et al.)

``p[y] = argmin_x || Phi_T[y] - C Phi_S[x] ||``  (nearest neighbour in spectral space).

==========================  =================================================================
function                    what it does
==========================  =================================================================
:func:`point_map`           the one call: two meshes in, ``p`` (shape ``(n_T,)``) out
:func:`functional_map`      ``C`` from descriptors, Laplacian commutativity, orientation
:func:`zoomout`             spectral upsampling of ``C`` from ``N0`` to ``N`` (Melzi et al. 2019)
:func:`map_to_pointwise`    ``p`` from ``C`` (exact nearest neighbours)
:func:`pointwise_to_map`    ``C`` from ``p``
:func:`transfer_function`   a function on ``S`` carried to ``T`` through ``C``
==========================  =================================================================

The errors of a map are measured with :mod:`cshape.geodesics`
(:func:`cshape.geodesics.geodesic_errors`).

The energy of :func:`functional_map`, for descriptors ``D_S = Phi_S^T B_S F_S`` (``N_S x d``)
and ``D_T`` projected on the bases, eigenvalues ``lam_S``, ``lam_T``:

``E(C) = w_d ||C D_S - D_T||^2 + w_l sum_ij C_ij^2 (lam_T,i - lam_S,j)^2
+ w_o sum_f ||C O_S,f - O_T,f C||^2``

the descriptor preservation (Eq. 5 of Ovsjanikov et al. 2012), the commutativity with the
Laplace-Beltrami operator (their Eq. 6, diagonal in the eigenbases), and the
orientation-preserving term of Ren, Poulenard, Wonka and Ovsjanikov (2018, Eq. 8):
``O_f g = <n x grad f, grad g>`` is the operator "derivative along the rotated gradient of
the descriptor ``f``", which changes sign under a mirror.  Intrinsic descriptors cannot tell
left from right; this term can, because it uses the surface's orientation (face order).
"""

from __future__ import annotations

import os
import warnings
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import scipy.sparse.linalg as spla
from numpy.typing import ArrayLike, NDArray

from . import _candidates
from ._candidates import _fit
from ._checks import (
    check_bool,
    check_choice,
    check_eigenbasis,
    check_int,
    check_landmarks,
    check_real,
    check_vertex_indices,
)
from ._eigensolver.threads import one_blas_thread
from ._nearest import nearest_rows
from .geodesics import _check_mesh, face_gradients
from .mesh import CShapeWarning, MeshLike, as_mesh
from .signatures import heat_kernel, wks, wks_energies
from .spectrum import Eigenbasis, eigenbasis

__all__ = [
    "functional_map",
    "map_to_pointwise",
    "point_map",
    "pointwise_to_map",
    "transfer_function",
    "zoomout",
]

#: Default weights of :func:`functional_map` (descriptors, Laplacian, orientation), for
#: descriptors and eigenvalues scaled as described there.
DESCRIPTOR_WEIGHT = 1.0
LAPLACIAN_WEIGHT = 1e-2
ORIENTATION_WEIGHT = 3e-4
#: Orientation weight of the first map of a sign pattern (:func:`point_map`, step 4).
SIGN_ORIENTATION_WEIGHT = 3e-3

#: :func:`point_map` maps meshes of more vertices than this through coarse copies of about
#: this many vertices (its ``coarse``).
COARSE_VERTICES = 8000

#: Threads among which :func:`point_map` shares its candidate maps (at most the CPUs).
SEARCH_THREADS = 2

#: Unknowns of ``C`` (``N_T N_S``) up to which :func:`functional_map` solves its normal
#: equations with the orientation term directly (one dense matrix); above, by conjugate
#: gradients.
DIRECT_UNKNOWNS = 2500

#: :func:`point_map` keeps every 5th of its WKS energies (pyFM's ``subsample_step``).
DESCRIPTOR_STRIDE = 5


# ---------------------------------------------------------------------- checks
def _check_eigenbasis(name: str, basis: object) -> Eigenbasis:
    """Check an eigenbasis argument, with the package's one check of it."""
    checked: Eigenbasis = check_eigenbasis(name, basis, Eigenbasis)
    return checked


def _check_array(name, x, n=None) -> np.ndarray:
    """``x`` as a finite real 2-D float array (of ``n`` rows if given), or a clear error."""
    if isinstance(x, (str, bytes)) or np.iscomplexobj(x):
        raise TypeError(f"{name} must be a real 2-D array, got {type(x).__name__}")
    a = np.asarray(x, dtype=np.float64)
    if a.ndim != 2:
        raise ValueError(f"{name} must be a 2-D array, got shape {a.shape}")
    if n is not None and a.shape[0] != n:
        raise ValueError(f"{name} has shape {np.shape(x)}: {a.shape[0]} rows where the basis "
                         f"has {n} vertices; pass one row per vertex of the basis's mesh")
    if not np.isfinite(a).all():
        raise ValueError(f"{name} contains NaN or infinite values")
    return a


def _columns(x):
    """Return a 1-D array as one column, anything else as it is (for :func:`_check_array`)."""
    a = np.asarray(x) if not isinstance(x, (str, bytes)) else x
    return a[:, None] if isinstance(a, np.ndarray) and a.ndim == 1 else a


def _check_C(C, N_target=None, N_source=None) -> np.ndarray:
    C = _check_array("C", C)
    if (N_target is not None and C.shape[0] > N_target) or (
            N_source is not None and C.shape[1] > N_source):
        raise ValueError(f"C has shape {C.shape}, larger than the bases (N_target={N_target}, "
                         f"N_source={N_source}); pass C of shape (N_T, N_S) with N_T, N_S at "
                         "most the basis sizes")
    return C


def map_to_pointwise(C: ArrayLike, source: Eigenbasis, target: Eigenbasis, *,
                     vertices: ArrayLike | None = None) -> NDArray[np.int64]:
    """Convert a functional map to a vertex map: ``p[y] = argmin_x ||Phi_T[y] - C Phi_S[x]||``.

    Exact nearest neighbours in ``N_T`` dimensions by blocked dense matrix products
    (k-d trees degrade to a scan in 30-100 dimensions).

    Parameters
    ----------
    C : array_like, shape (N_T, N_S)
        At most the sizes of the bases (their first ``N_T``, ``N_S`` eigenfunctions are used).
    source, target : Eigenbasis
        The bases of the two shapes (:func:`cshape.eigenbasis`).
    vertices : array_like of int, shape (s,), optional
        The target vertices to map; default all.

    Returns
    -------
    ndarray of int64, shape (n_T,) or (s,)
        For each target vertex, a source vertex (pyFM's ``p2p_21``).
    """
    source = _check_eigenbasis("source", source)
    target = _check_eigenbasis("target", target)
    C = _check_C(C, target.N, source.N)
    pT = target.phi
    if vertices is not None:
        pT = pT[check_vertex_indices("vertices", vertices, target.n_vertices)]
    return _pointwise(C, source.phi, pT)


def _pointwise(C, phiS, phiT, single=False):
    """:func:`map_to_pointwise` of checked arguments (the eigenfunctions' arrays).

    ``single``: the search in single precision (:func:`cshape._nearest.nearest_rows`).
    """
    kT, kS = C.shape
    return nearest_rows(np.ascontiguousarray(phiT[:, :kT]), phiS[:, :kS] @ C.T, single=single)


def pointwise_to_map(p2p: ArrayLike, source: Eigenbasis, target: Eigenbasis
                     ) -> NDArray[np.float64]:
    """Convert a vertex map to a functional map: ``C = Phi_T^T B_T Pi Phi_S``, (N_T, N_S).

    Parameters
    ----------
    p2p : array_like of int, shape (n_T,)
        For each target vertex, a source vertex.
    source, target : Eigenbasis
        The bases of the two shapes (:func:`cshape.eigenbasis`), of sizes ``N_S`` and
        ``N_T`` (``target.truncate(N)`` for fewer); ``Phi_T^T B_T`` is the projection onto
        the target basis.

    Returns
    -------
    ndarray, shape (N_T, N_S)
        The functional map ``C`` of the vertex map: it carries the coefficients of a
        function in the source basis to those of its pull-back in the target basis.
    """
    source = _check_eigenbasis("source", source)
    target = _check_eigenbasis("target", target)
    pS, pT = source.phi, target.phi
    p2p = check_vertex_indices("p2p", p2p, len(pS))
    if len(p2p) != len(pT):
        raise ValueError(f"p2p has {len(p2p)} entries but the target {len(pT)} vertices; p2p "
                         "has one source vertex per target vertex")
    return _to_map(p2p, source, target)


def _to_map(p2p, source, target):
    """:func:`pointwise_to_map` of checked arguments."""
    return target.phi.T @ (target.B @ source.phi[p2p])


def transfer_function(f: ArrayLike, C: ArrayLike, source: Eigenbasis, target: Eigenbasis
                      ) -> NDArray[np.float64]:
    """Carry functions from the source to the target through ``C``.

    ``f_T = Phi_T C Phi_S^T B_S f``: project on the source basis, map the coefficients,
    synthesise on the target (Ovsjanikov et al. 2012, Eq. 1).  Smooth functions survive;
    detail above the ``N_S``-th eigenfunction is lost (use ``f[p2p]`` for that).

    Parameters
    ----------
    f : array_like, shape (n_S,) or (n_S, m)
        One function (or ``m`` functions, one per column) on the source's vertices.
    C : array_like, shape (N_T, N_S)
        At most the sizes of the bases (their first ``N_T``, ``N_S`` eigenfunctions are used).
    source, target : Eigenbasis
        The bases of the two shapes (:func:`cshape.eigenbasis`).

    Returns
    -------
    ndarray, shape (n_T,) or (n_T, m)
        The functions carried to the target's vertices (smooth, band-limited to the bases).
    """
    source = _check_eigenbasis("source", source)
    target = _check_eigenbasis("target", target)
    pS, pT = source.phi, target.phi
    C = _check_C(C, pT.shape[1], pS.shape[1])
    kT, kS = C.shape
    f = np.asarray(f, dtype=np.float64)
    if f.ndim not in (1, 2) or f.shape[0] != len(pS):
        raise ValueError(f"f has shape {f.shape} but the source has {len(pS)} vertices; pass "
                         f"f of shape ({len(pS)},) or ({len(pS)}, m), one row per vertex")
    a = pS[:, :kS].T @ (source.B @ f)
    return pT[:, :kT] @ (C @ a)


# ---------------------------------------------------------------------- functional map
def _orientation_ops(mesh, phi, F):
    """Reduced orientation operators ``Phi^T W_f Phi`` (N x N) for each column ``f`` of F.

    ``W_f[i, j] = int psi_i <n x grad f, grad psi_j>`` (Ren et al. 2018), times
    ``sqrt(area)``: with ``Phi`` B-orthonormal the operators scale as 1 / length, so this
    makes them those of the shape scaled to unit area (the same weight for any unit).
    """
    G, areas, normals = face_gradients(mesh)
    nF, k = len(areas), phi.shape[1]
    gphi = (G @ phi).reshape(nF, 3, k)
    gf = (G @ F).reshape(nF, 3, -1)
    faces = as_mesh(mesh).faces
    # the face average of phi, times |t|: int_t psi_i = |t| / 3
    pface = phi[faces].sum(axis=1) * (areas / 3.0)[:, None]  # (nF, k)
    ops = []
    for d in range(F.shape[1]):
        J = np.cross(normals, gf[:, :, d])  # n x grad f
        nrm = np.linalg.norm(J, axis=1).mean()
        s = np.einsum("fc,fck->fk", J, gphi)
        op = pface.T @ s
        ops.append(op / max(nrm, np.finfo(float).tiny))
    return np.array(ops) * np.sqrt(areas.sum())


def functional_map(source: Eigenbasis, target: Eigenbasis, desc_source: ArrayLike,
                   desc_target: ArrayLike, *,
                   descriptor_weight: float = DESCRIPTOR_WEIGHT,
                   laplacian_weight: float = LAPLACIAN_WEIGHT,
                   orientation_weight: float = ORIENTATION_WEIGHT,
                   maxiter: int = 1000) -> NDArray[np.float64]:
    """Compute the functional map ``C`` (``N_T x N_S``) that best preserves descriptors.

    Minimises (Ovsjanikov et al. 2012, Eq. 5-6; Ren et al. 2018, Eq. 8)

    ``E(C) = w_d ||C D_S - D_T||^2 + w_l sum_ij C_ij^2 (lam_T,i - lam_S,j)^2
    + w_o sum_f ||C O_S,f - O_T,f C||^2``

    with ``D = Phi^T B F`` the descriptors projected on the bases (each descriptor scaled to
    unit B-norm on its shape), eigenvalues divided by the largest source eigenvalue, and
    ``O_f`` the reduced orientation operators of the descriptors (each divided by the mean
    norm of its field, and taken on the shape scaled to unit area, so that ``C`` and the
    weights do not depend on the unit of length).  Without the orientation term (``w_o = 0``)
    every row of ``C`` is an independent ridge regression, solved in closed form:
    ``(D_S D_S^T + w_l/w_d diag((lam_T,i - lam_S)^2)) c_i = D_S D_T[i]``.  With it the rows
    couple; ``E`` stays a convex quadratic, minimised exactly by conjugate gradients on its
    normal equations, started from the closed-form solution.

    Parameters
    ----------
    source, target : Eigenbasis
        The bases of the two shapes (:func:`cshape.eigenbasis`), of sizes ``N_S`` and
        ``N_T`` (``basis.truncate(N)`` for fewer).  The orientation term needs their meshes
        (the faces' orientation).
    desc_source, desc_target : array_like, shape (n_S, d), (n_T, d)
        Corresponding descriptors (e.g. :func:`cshape.wks` at the same energies).
    descriptor_weight, laplacian_weight, orientation_weight : float
        ``w_d``, ``w_l``, ``w_o`` (>= 0).
    maxiter : int, default=1000
        Conjugate-gradient iterations (the orientation term only; 0 leaves it out).

    Returns
    -------
    ndarray, shape (N_T, N_S)
        The functional map ``C``: row ``i`` gives the coefficients of the target's
        eigenfunction ``i`` over the source's, ``C[i, j] ~ <phi_T_i, phi_S_j o p>``.

    Raises
    ------
    ValueError
        ``orientation_weight > 0`` with a basis built without its mesh, descriptors of
        different counts or rows, both ``w_d`` and ``w_l`` zero.
    """
    source = _check_eigenbasis("source", source)
    target = _check_eigenbasis("target", target)
    pS, pT = source.phi, target.phi
    FS = _check_array("desc_source", _columns(desc_source), len(pS))
    FT = _check_array("desc_target", _columns(desc_target), len(pT))
    if FS.shape[1] != FT.shape[1]:
        raise ValueError(f"desc_source has {FS.shape[1]} descriptors and desc_target "
                         f"{FT.shape[1]}; compute both at the same scales")
    wd = check_real("descriptor_weight", descriptor_weight, min=0)
    wl = check_real("laplacian_weight", laplacian_weight, min=0)
    wo = check_real("orientation_weight", orientation_weight, min=0)
    maxiter = check_int("maxiter", maxiter, min=0)
    if wd == 0 and wl == 0:
        raise ValueError("descriptor_weight and laplacian_weight are both 0; C is then not "
                         "determined; use descriptor_weight > 0")
    if wo > 0 and maxiter > 0:
        for name, b in (("source", source), ("target", target)):
            if b.mesh is None:
                raise ValueError(
                    f"{name} has no mesh, and the orientation term (orientation_weight="
                    f"{wo:g}) needs its faces; compute the basis with cshape.eigenbasis(mesh) "
                    "or pass orientation_weight=0"
                )
    return _fit_descriptors(source, target, FS, FT, wd, wl, wo, maxiter)


def _fit_descriptors(source, target, FS, FT, wd, wl, wo, maxiter, cache=None):
    """Return :func:`functional_map` of checked arguments.

    ``cache``: a dict that keeps the orientation operators of the first descriptors it is
    given, for later calls whose descriptors begin with the same columns.
    """
    lS, lT = source.lam, target.lam
    pS, pT = source.phi, target.phi
    B_source, B_target = source.B, target.B
    nS = np.sqrt(np.einsum("ij,ij->j", FS, B_source @ FS))
    nT = np.sqrt(np.einsum("ij,ij->j", FT, B_target @ FT))
    keep = (nS > 0) & (nT > 0)
    FS, FT = FS[:, keep] / nS[keep], FT[:, keep] / nT[keep]
    DS, DT = pS.T @ (B_source @ FS), pT.T @ (B_target @ FT)
    scale = max(float(np.abs(lS).max()), np.finfo(float).tiny)
    M = np.square(lT[:, None] / scale - lS[None, :] / scale)  # (N_T, N_S)
    # closed form per row: (wd DS DS^T + wl diag(M_i)) c_i = wd DS DT_i
    with one_blas_thread():  # N x N products: spinning BLAS threads only slow them
        return _solve_map(DS, DT, M, wd, wl, wo, maxiter, source.mesh, target.mesh, pS, pT,
                          FS, FT, cache)


def _cached_ops(cache, side, mesh, phi, F):
    """:func:`_orientation_ops`, reusing those of the first columns kept in ``cache``."""
    if cache is None:
        return _orientation_ops(mesh, phi, F)
    if side not in cache:
        cache[side] = (F, _orientation_ops(mesh, phi, F))
        return cache[side][1]
    F0, O0 = cache[side]
    k0 = F0.shape[1]
    if k0 > F.shape[1] or F0.shape[0] != F.shape[0] or not np.array_equal(F[:, :k0], F0):
        return _orientation_ops(mesh, phi, F)
    if k0 == F.shape[1]:
        return O0
    return np.concatenate([O0, _orientation_ops(mesh, phi, F[:, k0:])])


def _solve_map(DS, DT, M, wd, wl, wo, maxiter, source, target, pS, pT, FS, FT, cache=None):
    """Minimise the energy of :func:`functional_map` (its arguments checked)."""
    kT, kS = M.shape
    H = wd * (DS @ DS.T)
    R = wd * (DS @ DT.T)  # (N_S, N_T)
    C = np.empty((kT, kS))
    for i in range(kT):
        C[i] = np.linalg.solve(H + wl * np.diag(M[i]) + 1e-12 * np.eye(kS), R[:, i])
    if wo == 0 or maxiter == 0:
        return C
    OS = _cached_ops(cache, "S", source, pS, FS)
    OT = _cached_ops(cache, "T", target, pT, FT)

    if kT * kS <= DIRECT_UNKNOWNS:
        return _solve_direct(H, M, wl, wo, OS, OT, R)
    OSt, OTt = OS.transpose(0, 2, 1).copy(), OT.transpose(0, 2, 1).copy()

    # E is a convex quadratic in C: its minimiser solves the normal equations H vec(C) = r,
    # solved by conjugate gradients from the closed-form solution without the orientation
    def hess(x):
        X = x.reshape(kT, kS)
        RO = X @ OS - OT @ X  # (f, N_T, N_S): C O_S,f - O_T,f C
        g = X @ H + wl * M * X + 1e-12 * X  # H = wd DS DS^T, symmetric
        g += wo * ((RO @ OSt).sum(axis=0) - (OTt @ RO).sum(axis=0))
        return g.ravel()

    op = spla.LinearOperator((kT * kS, kT * kS), matvec=hess, dtype=np.float64)
    rhs = R.T.ravel()  # wd DT DS^T
    x, _info = spla.cg(op, rhs, x0=C.ravel(), rtol=1e-10, atol=0.0, maxiter=maxiter)
    return x.reshape(kT, kS)


def _solve_direct(H, M, wl, wo, OS, OT, R):
    """Return the minimiser of the energy of :func:`functional_map`, by one dense solve.

    With ``x`` the rows of ``C`` one after another, ``vec(X A) = (I kron A^T) x`` and
    ``vec(A X) = (A kron I) x``; the orientation residual of descriptor ``f`` is ``L_f x``,
    ``L_f = I kron O_S,f^T - O_T,f kron I``, and the normal equations read
    ``(I kron H + diag(w_l M) + w_o sum_f L_f^T L_f) x = vec(R^T)``, with
    ``L_f^T L_f = I kron O_S O_S^T - O_T kron O_S - O_T^T kron O_S^T + O_T^T O_T kron I``.
    """
    kT, kS = M.shape
    IT, IS = np.eye(kT), np.eye(kS)
    K = np.kron(IT, H + wo * np.einsum("fij,fkj->ik", OS, OS))
    K += wo * np.kron(np.einsum("fji,fjk->ik", OT, OT), IS)
    # sum_f O_T,f kron O_S,f, entry ((i, k), (j, l)) = sum_f O_T,f[i, j] O_S,f[k, l]; the
    # sum of O_T,f^T kron O_S,f^T is its transpose
    X = np.tensordot(OT, OS, axes=([0], [0])).transpose(0, 2, 1, 3).reshape(kT * kS, -1)
    K -= wo * (X + X.T)
    K[np.diag_indices_from(K)] += wl * M.ravel() + 1e-12
    return np.linalg.solve(K, R.T.ravel()).reshape(kT, kS)


# ---------------------------------------------------------------------- ZoomOut
def zoomout(C: ArrayLike, source: Eigenbasis, target: Eigenbasis, N: int | None = None, *,
            step: int = 1, sample: int | None = None, bijective: bool = False,
            random_state: int = 0) -> NDArray[np.float64]:
    """Spectral upsampling of a functional map (ZoomOut, Melzi et al. 2019, Algorithm 1).

    From ``C`` of size ``N0``, repeat until size ``N``: the vertex map of ``C``
    (:func:`map_to_pointwise`), then ``C`` of size ``+step`` from it
    (``C = Phi_T^T B_T Pi Phi_S``, Eq. 4 of Melzi et al.).  Each step makes the map more
    nearly an isometry between more eigenfunctions; the noise of the first map, in the high
    frequencies, is filtered out.

    With ``sample``, the iterations use that many random vertices of each shape (the
    map of the samples to all source vertices nearest in spectral space is replaced by a
    map to the source samples; ``C`` is fitted by least squares on the target samples,
    weighted by their mass): the cost falls from ``n_T n_S N`` to ``sample^2 N`` per step,
    with the same result to within a few per cent of accuracy (Magnet and Ovsjanikov 2021).

    Parameters
    ----------
    C : array_like, shape (N0, N0)
        The functional map to start from (e.g. of :func:`functional_map`).
    source, target : Eigenbasis
        The bases of the two shapes (:func:`cshape.eigenbasis`), of at least ``N`` pairs.
    N : int, optional
        Final size (default: the size of the smaller basis).
    step : int, default=1
        Basis functions added per iteration.
    sample : int, optional
        Vertices per shape used in the iterations (default: all).
    bijective : bool, default=False
        Average ``C`` with the adjoint of the map the other way, ``(Phi_S^T B_S Pi_ST
        Phi_T)^T``, at every step, so the map is pushed towards a bijection.
    random_state : int, default=0
        Seed of the samples.

    Returns
    -------
    ndarray, shape (N, N)
        The upsampled functional map (convert it with :func:`map_to_pointwise`).
    """
    source = _check_eigenbasis("source", source)
    target = _check_eigenbasis("target", target)
    C = _check_C(C, target.phi.shape[1], source.phi.shape[1])
    kmax = min(source.phi.shape[1], target.phi.shape[1])
    k = kmax if N is None else check_int("N", N, min=max(C.shape), max=kmax)
    step = check_int("step", step, min=1)
    bijective = check_bool("bijective", bijective)
    if sample is not None:
        sample = check_int("sample", sample, min=1)
    return _zoomout(C, source, target, k, step=step, sample=sample, bijective=bijective,
                    random_state=random_state)


def _zoomout(C, source, target, k, *, step, sample, bijective, random_state, single=False):
    """:func:`zoomout` of checked arguments, to size ``k``.

    ``single``: its searches in single precision (:func:`cshape._nearest.nearest_rows`).
    """
    pS, pT = source.phi, target.phi
    B_source, B_target = source.B, target.B
    wT = np.asarray(B_target.sum(axis=1)).ravel()
    wS = np.asarray(B_source.sum(axis=1)).ravel()
    if sample is not None:
        rng = np.random.default_rng(random_state)
        iS = np.sort(rng.choice(len(pS), min(sample, len(pS)), replace=False))
        iT = np.sort(rng.choice(len(pT), min(sample, len(pT)), replace=False))
    else:
        iS, iT = np.arange(len(pS)), np.arange(len(pT))
    subS, subT = pS[iS], pT[iT]
    full = sample is None
    with one_blas_thread():  # small products: spinning BLAS threads only slow them
        kc = C.shape[0]
        while True:
            kT, kS = C.shape
            p = nearest_rows(np.ascontiguousarray(subT[:, :kT]), subS[:, :kS] @ C.T,
                             single=single)
            if kc >= k and kT >= k:
                break
            kc = min(kc + step, k)
            C = _fit(subT[:, :kc], subS[p, :kc], wT[iT], B_target if full else None)
            if bijective:
                q = nearest_rows(np.ascontiguousarray(subS[:, :kS]), subT[:, :kT] @ C[:kT, :kS],
                                 single=single)
                C2 = _fit(subS[:, :kc], subT[q, :kc], wS[iS], B_source if full else None)
                C = 0.5 * (C + C2.T)
            if kc >= k:
                break
    return C


# ---------------------------------------------------------------------- one call
def _descriptors(source, target, n_descr, landmarks):
    """WKS (and landmark heat kernels) of two bases at the source's energies, unit area."""
    e, sigma = wks_energies(source, n_descr, normalization="area")
    dS = wks(source, e, sigma, normalization="area")[:, ::DESCRIPTOR_STRIDE]
    dT = wks(target, e, sigma, normalization="area")[:, ::DESCRIPTOR_STRIDE]
    return (dS, dT) if landmarks is None else _with_landmarks(source, target, dS, dT, landmarks)


def _with_landmarks(source, target, dS, dT, landmarks):
    """Descriptors and heat kernels from the landmarks, at a few times (units of the area)."""
    for t in (0.002, 0.005, 0.01):
        dS = np.hstack([dS, heat_kernel(source, t, landmarks[:, 0], normalization="area")])
        dT = np.hstack([dT, heat_kernel(target, t, landmarks[:, 1], normalization="area")])
    return dS, dT


def point_map(source: MeshLike, target: MeshLike, *, N: int = 100, N0: int = 30,
              n_descriptors: int = 100, orientation: bool = True,
              step: int = 1, landmarks: ArrayLike | None = None,
              bijective: bool = False, sample: int | None = 3000,
              initial: str = "search", return_map: bool = False, random_state: int = 0,
              coarse: int | None = COARSE_VERTICES
              ) -> NDArray[np.int64] | tuple[NDArray[np.int64], NDArray[np.float64]]:
    """Map the vertices of two meshes in one call, by functional maps and ZoomOut.

    1. the :class:`cshape.Eigenbasis` of each mesh, ``N`` pairs (:func:`cshape.eigenbasis`:
       ``A`` and ``B`` assembled once);
    2. WKS descriptors (:func:`cshape.wks`, the shapes scaled to unit area, ``n_descriptors``
       energies of the source), plus heat kernels from the landmarks when given;
    3. ``C`` of size ``N0`` by :func:`functional_map` (with the orientation term);
    4. with ``initial='search'``, ZoomOut and no landmarks, more starting maps: every sign
       pattern of the first few eigenfunctions (between different bodies these still
       correspond one to one, up to sign and the order of two of close eigenvalues, while
       the descriptors no longer agree), upsampled on samples, the two of the smallest
       spectral residual that differ; each one also as an oriented map (step 3 with the
       pattern's eigenfunctions among the descriptors, so that the orientation term settles
       left and right, which those eigenfunctions often leave open);
    5. each start upsampled by :func:`zoomout` to a common size and its vertex map
       (:func:`map_to_pointwise`), with its residual ``mean_y |Phi_T[y] - C Phi_S[p[y]]|``,
       the share of the target's area whose image triangles keep the orientation of the
       source (a mirror image reverses them all), the disagreement of the WKS and the
       extrinsic misfit: what remains of ``V_T - V_S[p]`` after the best rotation, scale and
       translation and a smooth bending (the span of the target's first eigenfunctions);
    6. each map that reverses the orientation on most of the area (a mirror image: on a body,
       often front to back) once more, turned the right way round in space: the rotation and
       smooth bending that carry its images onto the target place the source over the
       target, and each target vertex takes the source vertex nearest in position and normal
       (upsampled alike); it competes in step 8 only if no other map beats it on all three
       intrinsic criteria (residual, orientation share, descriptor error);
    7. for each start that fits (residual within 20 % of the smallest), one more map: steps
       2-3 with landmarks, the target's extremities (farthest points of its commute-time
       embedding) and their images, upsampled alike;
    8. of the maps that keep the orientation on more than half the area (all, if none
       does), those whose residual is within 20 % of their smallest and whose orientation
       share is at most 0.1 below the best of those, the one of the smallest extrinsic
       misfit is kept (a body looks nearly alike in front and behind to every intrinsic
       measure; a half turn moves its toes, face and chest in space); if another map that
       differs from it (its images on average more than 0.1 ``sqrt(area)`` away) matches it
       within noise on all four criteria (residual within 5 %, orientation share within
       0.03, descriptor error within 3 %, extrinsic misfit within 5 %), a
       :class:`cshape.CShapeWarning` names both and the target vertices where they disagree
       most: true landmarks there settle it;
    9. :func:`zoomout` to size ``N`` and the vertex map :func:`map_to_pointwise`.

    The nearest rows of the search (steps 4-8) and of the ZoomOut iterations are searched in
    single precision (a query may get either of two rows that tie to that round-off; each
    step's map is fitted again at the next); the final vertex map is exact.

    A mesh of more than ``coarse`` vertices is replaced by a copy of about ``coarse``
    vertices (PyMeshLab's quadric edge collapse, the vertices kept where they are) for
    steps 1-9; each vertex of the full target then takes the images of its three nearest
    vertices of the copy, blended by inverse distance, and the source vertex nearest to that
    point.

    Parameters
    ----------
    source, target : Mesh or (vertices, faces)
        Consistently oriented triangle meshes without duplicate or unreferenced vertices.
    N : int, default=100
        Final basis size (eigenpairs computed per mesh).
    N0 : int, default=30
        Size of the first functional map.
    n_descriptors : int, default=100
        WKS energies (Aubry et al.'s default grid); every ``DESCRIPTOR_STRIDE``-th is kept
        (20 descriptors, as pyFM).
    orientation : bool, default=True
        Use the orientation-preserving term (Ren et al. 2018): without it a left-right
        symmetric shape may be mapped onto its mirror image.
    step : int, default=1
        ZoomOut from ``N0`` to ``N``, adding ``step`` basis functions per iteration (as
        :func:`zoomout`'s ``step``); 0: no ZoomOut, the map of the size-``N0`` ``C``.
    landmarks : array_like of int, shape (L, 2), optional
        Known corresponding vertices ``(source vertex, target vertex)``.
    bijective : bool, default=False
        Bijective ZoomOut (see :func:`zoomout`).
    sample : int or None, default=3000
        Vertices per shape in the ZoomOut iterations (None: all; slower on big meshes).
    initial : {'search', 'descriptors'}, default='search'
        'search': the descriptors' map, the sign patterns, their oriented maps, the mirror
        images turned in space and the maps from their extremities compete (steps 4-8);
        'descriptors': the descriptors' map alone.  Landmarks, or no ZoomOut, imply
        'descriptors'.
    return_map : bool, default=False
        Also return ``C`` (``N x N``).
    random_state : int, default=0
        Seed of the vertices sampled by ZoomOut and the search (the same seed, the same map).
    coarse : int or None, default=COARSE_VERTICES
        Meshes of more vertices are mapped through coarse copies of about this many
        vertices, as described above (at least ``max(N, 100)``; None: never).  With
        ``return_map=True`` the returned ``C`` is that of the full meshes' bases, fitted to
        the vertex map (:func:`pointwise_to_map`).

    Returns
    -------
    p2p : ndarray of int64, shape (n_target,)
        ``p2p[y]`` is the source vertex matched to target vertex ``y`` (pyFM's ``p2p_21``).
    C : ndarray, shape (N, N)
        Only with ``return_map=True``.

    Warns
    -----
    CShapeWarning
        Two candidate maps cannot be told apart (step 8): a nearly symmetric shape.  The
        message names the target vertices whose true source vertices, passed as
        ``landmarks``, settle the choice.

    Examples
    --------
    >>> import numpy as np, cshape
    >>> mesh = cshape.shapes.icosphere(2)
    >>> p = cshape.point_map(mesh, mesh, N=20, N0=10)
    >>> p.shape
    (162,)
    """
    S = _check_mesh("source", source)
    T = _check_mesh("target", target)
    N = check_int("N", N, min=2)
    N0 = check_int("N0", N0, min=2, max=N)
    n_descriptors = check_int("n_descriptors", n_descriptors, min=int(4 * 7) + 1)
    orientation = check_bool("orientation", orientation)
    step = check_int("step", step, min=0)
    bijective = check_bool("bijective", bijective)
    initial = check_choice("initial", initial, ("search", "descriptors"))
    return_map = check_bool("return_map", return_map)
    lm = check_landmarks(landmarks, S.n_vertices, T.n_vertices)
    if N > min(S.n_vertices, T.n_vertices):
        raise ValueError(f"N={N} is more than the vertices of the smaller mesh "
                         f"({min(S.n_vertices, T.n_vertices)}); use a smaller N")
    if sample is not None:
        sample = check_int("sample", sample, min=1)
    if coarse is not None:
        coarse = check_int("coarse", coarse, min=max(N, 100))
    options = dict(N=N, N0=N0, n_descriptors=n_descriptors, orientation=orientation,
                   step=step, bijective=bijective, sample=sample, initial=initial,
                   random_state=random_state)
    if coarse is not None and max(S.n_vertices, T.n_vertices) > coarse:
        return _via_coarse(S, T, coarse, lm, return_map, options)
    p2p, C = _point_map(S, T, lm, **options)
    return (p2p, C) if return_map else p2p


def _point_map(S, T, lm, *, N, N0, n_descriptors, orientation, step, bijective, sample,
               initial, random_state):
    """:func:`point_map` of checked arguments, without coarse copies: ``p2p`` and ``C``."""
    bS, bT = eigenbasis(S, N), eigenbasis(T, N)
    start = _Start(bS, bT, N0, n_descriptors, orientation)
    C = start(lm)
    if initial == "search" and lm is None and step:
        C = _search(C, start, N, dict(step=step, sample=sample, bijective=bijective,
                                      random_state=random_state))
    if step:
        C = _zoomout(C, bS, bT, N, step=step, sample=sample, bijective=bijective,
                     random_state=random_state, single=True)
    return _pointwise(C, bS.phi, bT.phi), C


def _coarse_copy(mesh, n):
    """Return a copy of ``mesh`` with about ``n`` vertices, and the vertex of ``mesh`` of each.

    PyMeshLab's quadric edge collapse, keeping the topology, the normals' directions and the
    vertices where they are (each vertex of the copy is one of ``mesh``).
    """
    import pymeshlab
    from scipy.spatial import cKDTree

    from .mesh import Mesh

    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=mesh.vertices, face_matrix=mesh.faces))
    # every parameter given: one left out may take an earlier call's value (data.variants)
    ms.meshing_decimation_quadric_edge_collapse(
        targetfacenum=int(2 * n), targetperc=0.0, qualitythr=0.3, preserveboundary=True,
        boundaryweight=1.0, preservenormal=True, preservetopology=True,
        optimalplacement=False, planarquadric=True, planarweight=0.001, qualityweight=False,
        autoclean=True, selected=False)
    m = ms.current_mesh()
    copy = Mesh(m.vertex_matrix(), m.face_matrix())
    return copy, cKDTree(mesh.vertices).query(copy.vertices)[1].astype(np.int64)


def _via_coarse(S, T, n, lm, return_map, options):
    """:func:`point_map` of two big meshes through coarse copies, carried to the full meshes.

    Each mesh of more than ``n`` vertices is replaced by a copy of about ``n``
    (:func:`_coarse_copy`); the landmarks go to the nearest vertices of the copies.  Each
    vertex of the full target takes the images of its three nearest vertices of the
    target's copy, blended by inverse distance, and then the source vertex nearest to that
    point.
    """
    from scipy.spatial import cKDTree

    Sc = _coarse_copy(S, n)[0] if S.n_vertices > n else S
    Tc = _coarse_copy(T, n)[0] if T.n_vertices > n else T
    lmc = None
    if lm is not None:
        lmc = np.column_stack([cKDTree(Sc.vertices).query(S.vertices[lm[:, 0]])[1],
                               cKDTree(Tc.vertices).query(T.vertices[lm[:, 1]])[1]])
    pc = _point_map(Sc, Tc, lmc, **options)[0]
    images = Sc.vertices[pc]
    d, j = cKDTree(Tc.vertices).query(T.vertices, k=3)
    w = 1.0 / np.maximum(d, 1e-12 * np.sqrt(T.area))
    w /= w.sum(axis=1, keepdims=True)
    p2p = cKDTree(S.vertices).query(np.einsum("yk,ykc->yc", w, images[j]))[1].astype(np.int64)
    if lm is not None:
        p2p[lm[:, 1]] = lm[:, 0]
    if not return_map:
        return p2p
    N = options["N"]
    return p2p, _to_map(p2p, eigenbasis(S, N), eigenbasis(T, N))


class _Start:
    """The first functional map of :func:`point_map` (steps 2-3), from landmarks or none."""

    def __init__(self, bS, bT, N0, n_descriptors, orientation):
        self.bS, self.bT, self.N0, self.orientation = bS, bT, N0, orientation
        self.dS, self.dT = _descriptors(bS, bT, n_descriptors, None)
        self.cache = {}

    def __call__(self, lm):
        dS, dT = ((self.dS, self.dT) if lm is None else
                  _with_landmarks(self.bS, self.bT, self.dS, self.dT, lm))
        return self._fit(dS, dT, ORIENTATION_WEIGHT if self.orientation else 0.0)

    def _fit(self, dS, dT, wo):
        """:func:`functional_map` at size ``N0`` (the orientation operators of the WKS once)."""
        with one_blas_thread():
            return _fit_descriptors(self.bS.truncate(self.N0), self.bT.truncate(self.N0),
                                    dS, dT, DESCRIPTOR_WEIGHT, LAPLACIAN_WEIGHT, wo, 1000,
                                    self.cache)

    def oriented(self, P):
        """Return the first map of a sign pattern ``P`` (``m x m``), with its eigenfunctions.

        The source's eigenfunctions ``1 .. m-1`` and their images under ``P`` on the target
        join the descriptors; the orientation term (weight ``SIGN_ORIENTATION_WEIGHT``)
        settles what they leave open (left and right, when every one of them is symmetric).
        """
        m = len(P)
        dS = np.hstack([self.dS, self.bS.phi[:, 1:m]])
        dT = np.hstack([self.dT, self.bT.phi[:, :m] @ P[:, 1:]])
        return self._fit(dS, dT, SIGN_ORIENTATION_WEIGHT)


def _search(C, start, N, zoom):
    """Return the map that steps 4-8 of :func:`point_map` keep, at the common size."""
    bS, bT = start.bS, start.bT
    threads = max(1, min(SEARCH_THREADS, os.cpu_count() or 1))
    with one_blas_thread(), ThreadPoolExecutor(threads) as pool:
        # small products: spinning BLAS threads only slow them; the candidates are shared
        # among threads instead (the same result)
        found, maps, scores, names, turned, m = _candidates_of(C, start, N, zoom, pool,
                                                               threads)
    keep = _candidates.pick_extrinsic(scores, turned)
    # step 8: a rival within noise of the map kept is named in a warning
    V = bS.mesh.vertices
    dist = [float(np.linalg.norm(V[p] - V[maps[keep]], axis=1).mean() / np.sqrt(bS.mesh.area))
            for p in maps]
    floor = 1e-6 * float(np.linalg.norm(bT.phi[:, :m], axis=1).mean())
    other = _candidates.rival(scores, dist, keep, floor)
    if other is not None:
        _warn_tie(names, scores, maps, keep, other, V)
    return found[keep]


def _candidates_of(C, start, N, zoom, pool, threads):
    """Every candidate of steps 4-7 of :func:`point_map`, at the common size ``m``.

    Returns the lists of their ``C``, vertex maps, scores (residual, orientation share,
    descriptor error, extrinsic misfit) and names, the indices of the maps turned in space,
    and ``m``; ``pool`` shares the candidates among ``threads`` threads.
    """
    bS, bT = start.bS, start.bT
    wT = np.asarray(bT.B.sum(axis=1)).ravel()
    patterns = _candidates.sign_candidates(bS.phi, bT.phi, wT,
                                           np.random.default_rng(zoom["random_state"]),
                                           bS.lam, bT.lam, threads=threads)
    starts = [C] + [Cs for _P, Cs in patterns]
    names = ["the descriptors' map"] + [f"the sign pattern {_signs(P)}" for P, _C in patterns]
    if start.orientation:  # the same patterns, left and right settled by the orientation
        starts += list(pool.map(start.oriented, [P for P, _C in patterns]))
        names += [f"the oriented map of the sign pattern {_signs(P)}" for P, _C in patterns]
    m = max(min(N, _candidates.COMPARE_SIZE), max(C.shape[0] for C in starts))
    ends = _candidates.extremities(bT.phi, bT.lam)
    found, maps, scores = [], [], []
    zoom = dict(zoom, sample=None if zoom["sample"] is None
                else min(zoom["sample"], _candidates.COMPARE_SAMPLE))

    def evaluate(make):
        C = _zoomout(make(), bS, bT, m, **zoom, single=True)
        p = _pointwise(C, bS.phi, bT.phi, single=True)
        return C, p, (_candidates.residual(C, bS.phi, bT.phi, p),
                      _candidates.orientation_share(bS.mesh, bT.mesh, p)
                      if start.orientation else 0.0,
                      _candidates.descriptor_error(start.dS, start.dT, wT, p),
                      _candidates.extrinsic_residual(bS.mesh, bT.mesh, bT.phi, bT.B, p))

    def add(makers):  # evaluated in the threads, kept in order
        for C, p, s in pool.map(evaluate, makers):
            found.append(C)
            maps.append(p)
            scores.append(s)

    add([lambda C=C: C for C in starts])
    # a mirror image (front to back on a body) turned the right way round in space
    k0 = min(_candidates.SIGN_ZOOM, m)
    mirrors = [i for i in range(len(maps))
               if start.orientation and scores[i][1] <= _candidates.MIRROR_SHARE]
    turned = list(range(len(maps), len(maps) + len(mirrors)))

    def turn(i):
        q = _candidates.turned_in_space(bS.mesh, bT.mesh, bT.B, maps[i], bT.phi)
        return _to_map(q, bS.truncate(k0), bT.truncate(k0))

    add([lambda i=i: turn(i) for i in mirrors])
    names += [f"{names[i]}, turned in space" for i in mirrors]
    best, n_starts = min(s[0] for s in scores), len(maps)
    # self-landmarks from the sign patterns' maps (the descriptors' map is fitted to the WKS
    # already: a map from its extremities would fit them once more, and so win on the WKS)
    fits = [i for i in range(1, n_starts) if scores[i][0] <= _candidates.RESIDUAL_SLACK * best]
    add([lambda i=i: start(np.column_stack([maps[i][ends], ends])) for i in fits])
    names += [f"the map from the extremities of {names[i]}" for i in fits]
    return found, maps, scores, names, turned, m


def _signs(P):
    """Return a sign pattern without its first entry, and the eigenfunctions it swaps.

    The pattern is written as ``(+-++-)`` (the first, constant, eigenfunction left out).
    """
    rows = np.argmax(np.abs(P), axis=0)
    out = "(" + "".join("+" if P[rows[j], j] >= 0 else "-" for j in range(1, len(P))) + ")"
    swapped = [f"{j} and {rows[j]}" for j in range(1, len(P)) if rows[j] > j]
    return out + "".join(f", eigenfunctions {s} swapped" for s in swapped)


def _warn_tie(names, scores, maps, keep, other, V):
    """Warn that two candidate maps are within noise, and name the landmarks that settle it."""
    y = _candidates.settling_vertices(V, maps[keep], maps[other]).tolist()

    def describe(i):
        r, o, d, e = scores[i]
        return (f"{names[i]} (residual {r:.3g}, orientation share {o:.2f}, descriptor error "
                f"{d:.3g}, extrinsic misfit {e:.3g})")

    warnings.warn(
        f"point_map cannot tell two candidate maps apart: {describe(keep)}, returned, and "
        f"{describe(other)} agree within noise (a nearly symmetric shape). They send target "
        f"vertices {y} to source vertices {maps[keep][y].tolist()} and "
        f"{maps[other][y].tolist()} respectively; landmarks settle it: pass "
        "landmarks=[[source vertex, target vertex], ...] giving the true source vertex of the "
        f"target vertices {y}",
        CShapeWarning, stacklevel=4)
