"""Stage 4 of the pipeline: descriptors from eigenvalues (Section 2.1 and 2.3).

* :func:`normalize`             - scale invariance (Section 2.1): area, first non-zero
                                  eigenvalue, or fitted Weyl slope;
* :func:`weyl_subtract`         - Eq. (8): ``lam'_i = lam_i^norm - 4 pi i``;
* :func:`compact_shape_dna`     - Eq. (9)-(10): DFT, shift, keep the ``2M+1`` values
                                  around the zero frequency;
* :func:`real_form`             - the same descriptor as ``2M+1`` real numbers with the
                                  same Euclidean distances;
* :func:`inverse_compact_shape_dna` - rebuild the smoothed normalised Shape-DNA from the
                                  cropped coefficients;
* :func:`f1_feature`            - the F1 feature ``lam_1 / lam_i`` of the paper's Fig. 5f.

All functions take and return plain NumPy arrays.
"""

from __future__ import annotations

import numpy as np

from ._checks import check_choice
from .mesh import Mesh

__all__ = [
    "normalize",
    "weyl_subtract",
    "compact_shape_dna",
    "compact_shape_dna_real",
    "real_form",
    "inverse_compact_shape_dna",
    "f1_feature",
    "NORMALIZATIONS",
]

NORMALIZATIONS = ("area", "fiedler", "weyl")
FOUR_PI = 4.0 * np.pi


def _as_lam(lam, name="lam", min_len=1) -> np.ndarray:
    try:
        is_complex = np.iscomplexobj(lam)
        x = None if is_complex else np.asarray(lam, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a 1-D array of real eigenvalues") from None
    if is_complex:
        raise TypeError(
            f"{name} must be real eigenvalues, got a complex array (a cShape-DNA?); pass the "
            "Shape-DNA from cshape.shape_dna"
        )
    if x.ndim != 1:
        raise ValueError(f"{name} must be 1-D (one spectrum), got shape {x.shape}")
    if len(x) < min_len:
        raise ValueError(f"{name} must hold at least {min_len} eigenvalues, got {len(x)}")
    if not np.all(np.isfinite(x)):
        raise ValueError(f"{name} contains NaN or infinite values")
    return x


def _first_nonzero(lam: np.ndarray) -> int:
    # relative to the spectrum: eigenvalues scale as 1/length^2, so a large mesh (in mm or
    # um) has all of them far below any absolute threshold
    tol = 1e-8 * float(np.abs(lam).max())
    nz = np.flatnonzero(np.abs(lam) > tol)
    if len(nz) == 0:
        raise ValueError("lam has no non-zero eigenvalue to normalise by")
    return int(nz[0])


def normalize(lam, area=None, method="area"):
    """Scale-normalise a Shape-DNA (Section 2.1).

    Parameters
    ----------
    lam : array_like, shape (N,)
        Ascending eigenvalues, lam_0 first.
    area : float, optional
        Surface area of the mesh; required for ``method='area'``.
    method : {'area', 'fiedler', 'weyl'}, default='area'
        ``'area'`` multiplies by the surface area (the paper's choice); afterwards the
        values lie around the Weyl line ``4 pi i``.  ``'fiedler'`` divides by the first
        non-zero eigenvalue.  ``'weyl'`` multiplies by ``4 pi / s`` where ``s`` is the
        least-squares slope of ``lam_i ~ s i`` (through the origin), so the result lies
        around ``4 pi i`` like the area normalisation, without needing the area.

    Returns
    -------
    lam_norm : ndarray, shape (N,)
    """
    x = _as_lam(lam)
    method = check_choice("method", method, NORMALIZATIONS)
    if method == "area":
        if area is None:
            raise ValueError(
                "method='area' needs the surface area: pass area=mesh.area "
                "(or use method='weyl', which needs no area)"
            )
        try:
            a = float(area)
        except (TypeError, ValueError):
            raise ValueError(
                f"area must be a positive finite number, got {type(area).__name__} {area!r}"
            ) from None
        if isinstance(area, bool) or not np.isfinite(a) or a <= 0:
            raise ValueError(f"area must be a positive finite number, got {area!r}")
        return x * a
    if method == "fiedler":
        return x / x[_first_nonzero(x)]
    i = np.arange(len(x), dtype=np.float64)
    s = float(i @ x) / float(i @ i) if len(x) > 1 else 0.0
    if s <= 0:
        raise ValueError("method='weyl' needs at least two eigenvalues with a positive trend")
    return x * (FOUR_PI / s)


def weyl_subtract(lam_norm):
    """Subtract the Weyl line from a normalised Shape-DNA, Eq. (8).

    ``lam'_i = lam_i^norm - 4 pi i`` for ``i = 0, ..., N-1``.

    Parameters
    ----------
    lam_norm : array_like, shape (N,)
        Area-normalised eigenvalues (see :func:`normalize`).

    Returns
    -------
    lam_prime : ndarray, shape (N,)
    """
    x = _as_lam(lam_norm, "lam_norm")
    return x - FOUR_PI * np.arange(len(x))


def _check_M(M, N):
    if isinstance(M, bool) or not isinstance(M, (int, np.integer)):
        raise TypeError(f"M must be an integer, got {type(M).__name__} {M!r}")
    M = int(M)
    if M < 0:
        raise ValueError(f"M must be >= 0 (the descriptor has 2M+1 values), got {M}")
    if 2 * M + 1 > N:
        raise ValueError(
            f"2M+1 = {2 * M + 1} values cannot be kept from N = {N} eigenvalues; "
            f"use M <= {(N - 1) // 2} or a larger N"
        )
    return M


def _check_N(N):
    if isinstance(N, bool) or not isinstance(N, (int, np.integer)):
        raise TypeError(f"N must be an integer, got {type(N).__name__} {N!r}")
    if N < 1:
        raise ValueError(f"N must be at least 1 (the number of eigenvalues), got {N}")
    return int(N)


def _spectrum_from_input(mesh_or_lam, N, area, bc, normalization):
    """Return the normalised Shape-DNA (N,) from a mesh or from eigenvalues."""
    N = _check_N(N)
    normalization = check_choice("normalization", normalization, NORMALIZATIONS)
    check_choice("bc", bc, ("neumann", "dirichlet"))
    if isinstance(mesh_or_lam, Mesh) or (
        isinstance(mesh_or_lam, (tuple, list))
        and len(mesh_or_lam) == 2
        and np.ndim(mesh_or_lam[0]) == 2
    ):
        from .mesh import as_mesh, repair_mesh
        from .spectrum import shape_dna

        # repair here, once, so that the area is that of the surface whose spectrum is
        # computed (a duplicated face would otherwise count twice in the area only)
        mesh = repair_mesh(as_mesh(mesh_or_lam))
        lam = shape_dna(mesh, N=N, bc=bc)
        return normalize(lam, area=mesh.area if area is None else area, method=normalization)
    lam = _as_lam(mesh_or_lam, "mesh_or_lam")
    if len(lam) < N:
        raise ValueError(
            f"got {len(lam)} eigenvalues but N={N}; pass N={len(lam)} or compute more eigenvalues"
        )
    lam = lam[:N]
    if normalization == "area" and area is None:
        return lam  # documented: eigenvalues without an area are taken as already normalised
    return normalize(lam, area=area, method=normalization)


def compact_shape_dna(mesh_or_lam, M=16, N=100, area=None, *, bc="neumann", normalization="area"):
    """Compact Shape-DNA (cShape-DNA), Eq. (8)-(10).

    Steps: normalise (multiply by the area), subtract the Weyl line ``4 pi i`` (Eq. 8),
    take the DFT ``Lambda_i = sum_k lam'_k exp(-j 2 pi i k / N)`` (Eq. 9), shift the zero
    frequency to the centre ``<N/2>`` and keep the ``2M+1`` values around it (Eq. 10).

    Parameters
    ----------
    mesh_or_lam : Mesh, (vertices, faces) or array_like of shape (>= N,)
        A mesh (everything is computed: Shape-DNA with ``N`` eigenvalues, its area), or
        eigenvalues.  Raw eigenvalues need ``area`` (they are multiplied by it); given
        without ``area`` they are taken as **already normalised**.  Only the first ``N``
        are used.
    M : int, default=16
        Crop half-width; the descriptor has ``2M+1`` values.  ``0 <= M <= (N-1)//2``.
    N : int, default=100
        Length of the Shape-DNA.
    area : float, optional
        Surface area used for the normalisation (default for a mesh: ``mesh.area``).
    bc : {'neumann', 'dirichlet'}, default='neumann'
        Boundary condition, when a mesh is given.
    normalization : {'area', 'fiedler', 'weyl'}, default='area'
        See :func:`normalize`.

    Returns
    -------
    S_c : ndarray of complex128, shape (2M+1,)
        ``(Lambda^shift_{<N/2>-M}, ..., Lambda^shift_{<N/2>+M})``: the DFT coefficients
        of frequencies ``-M, ..., M`` in that order; ``S_c[M]`` is the zero frequency.
        Conjugate-symmetric (``S_c[M+k] == conj(S_c[M-k])``) because the input is real.

    Raises
    ------
    TypeError
        If ``N`` or ``M`` is not an integer (bools are refused), or the eigenvalues are
        complex.
    ValueError
        If ``N < 1``, ``M < 0``, ``2M+1 > N``, ``bc`` or ``normalization`` is unknown, or
        fewer than ``N`` eigenvalues are given; checked before any eigensolve.

    See Also
    --------
    real_form : the same descriptor as 2M+1 real numbers with equal distances.
    inverse_compact_shape_dna : what the 2M+1 coefficients keep of the Shape-DNA.
    """
    M = _check_M(M, _check_N(N))  # before the eigensolve
    lam_norm = _spectrum_from_input(mesh_or_lam, N, area, bc, normalization)
    N = len(lam_norm)
    lam_prime = weyl_subtract(lam_norm)  # Eq. (8)
    Lam = np.fft.fft(lam_prime)  # Eq. (9)
    shifted = np.fft.fftshift(Lam)  # zero frequency at index N // 2
    c = N // 2
    return shifted[c - M : c + M + 1].copy()  # Eq. (10)


def real_form(S_c):
    """Real form of a cShape-DNA: ``2M+1`` reals with the same Euclidean distances.

    Because the Shape-DNA is real, ``Lambda_{-k} = conj(Lambda_k)``, so

    ``||S_c - T_c||^2 = |dLambda_0|^2 + 2 sum_{k=1..M} |dLambda_k|^2``.

    The real form is ``(Re Lambda_0, sqrt2 Re Lambda_1, sqrt2 Im Lambda_1, ...,
    sqrt2 Re Lambda_M, sqrt2 Im Lambda_M)``.

    Parameters
    ----------
    S_c : array_like of complex, shape (2M+1,) or (p, 2M+1)
        One descriptor or a stack of them (rows).

    Returns
    -------
    ndarray of float64, same shape as ``S_c``
    """
    S = np.asarray(S_c)
    if S.ndim not in (1, 2) or S.shape[-1] % 2 != 1:
        raise ValueError(
            f"S_c must have shape (2M+1,) or (p, 2M+1) with an odd last dimension, got {S.shape}"
        )
    M = (S.shape[-1] - 1) // 2
    pos = S[..., M + 1 :]  # frequencies 1..M
    out = np.empty(S.shape, dtype=np.float64)
    out[..., 0] = S[..., M].real
    out[..., 1::2] = np.sqrt(2.0) * pos.real
    out[..., 2::2] = np.sqrt(2.0) * pos.imag
    return out


def compact_shape_dna_real(mesh_or_lam, M=16, N=100, area=None, **kwargs):
    """:func:`compact_shape_dna` in its :func:`real_form`: shape (2M+1,), float64."""
    return real_form(compact_shape_dna(mesh_or_lam, M=M, N=N, area=area, **kwargs))


def inverse_compact_shape_dna(S_c, N, *, add_weyl=True):
    """Rebuild the smoothed normalised Shape-DNA from the cropped DFT coefficients.

    The ``2M+1`` coefficients are put back around the centre of a zero vector of length
    ``N`` (the other frequencies are 0, as in Eq. 10), un-shifted and inverse-transformed.

    Parameters
    ----------
    S_c : array_like of complex, shape (2M+1,)
        A cShape-DNA from :func:`compact_shape_dna`.
    N : int
        Length of the original Shape-DNA (``2M+1 <= N``).
    add_weyl : bool, default=True
        Add the Weyl line ``4 pi i`` back (undo Eq. 8), returning the smoothed
        normalised Shape-DNA; otherwise return the smoothed ``lam'``.

    Returns
    -------
    ndarray of float64, shape (N,)
        Equal to the input of :func:`compact_shape_dna` when ``2M+1 = N`` (N odd).
    """
    S = np.asarray(S_c, dtype=np.complex128)
    if S.ndim != 1 or len(S) % 2 != 1:
        raise ValueError(f"S_c must be 1-D with an odd length 2M+1, got shape {S.shape}")
    M = (len(S) - 1) // 2
    if isinstance(N, bool) or not isinstance(N, (int, np.integer)):
        raise TypeError(f"N must be an integer, got {N!r}")
    _check_M(M, int(N))
    shifted = np.zeros(int(N), dtype=np.complex128)
    c = int(N) // 2
    shifted[c - M : c + M + 1] = S
    lam_prime = np.fft.ifft(np.fft.ifftshift(shifted)).real
    if add_weyl:
        return lam_prime + FOUR_PI * np.arange(int(N))
    return lam_prime


def f1_feature(lam):
    """The F1 feature vector ``(lam_1/lam_2, lam_1/lam_3, ..., lam_1/lam_{N-1})`` (Fig. 5f).

    ``lam_1`` is the first non-zero eigenvalue (the one after ``lam_0 = 0`` for a
    connected closed mesh); the ratios run over the eigenvalues after it.

    Parameters
    ----------
    lam : array_like, shape (N,)
        Ascending eigenvalues.

    Returns
    -------
    ndarray, shape (N - p - 1,)
        With ``p`` the index of the first non-zero eigenvalue (``p = 1`` for a connected
        closed mesh, so the length is ``N - 2``).  Scale invariant; values in (0, 1].
    """
    x = _as_lam(lam, min_len=2)
    p = _first_nonzero(x)
    if p + 1 >= len(x):
        raise ValueError("lam needs at least one eigenvalue after the first non-zero one")
    return x[p] / x[p + 1 :]
