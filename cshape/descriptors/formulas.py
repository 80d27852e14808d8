"""The formulas of stage 4: descriptors from eigenvalues (Section 2.1 and 2.3).

* :func:`normalize`             - scale invariance (Section 2.1): area, first non-zero
                                  eigenvalue, or fitted Weyl slope;
* :func:`weyl_subtract`         - Eq. (8): ``lam'_i = lam_i^norm - 4 pi i``;
* :func:`compact_shape_dna`     - Eq. (9)-(10): DFT, shift, keep the ``2M+1`` values
                                  around the zero frequency; ``transform=`` also offers two
                                  extensions beyond the paper (the log-Weyl ratio below);
* :func:`log_weyl_ratio`        - ``r_i = log(lam_i^norm / (4 pi i))``, ``i = 1..N-1``: every
                                  index on the same relative footing (not in the paper);
* :func:`detrend`               - a sequence less its least-squares polynomial in the index:
                                  the log-Weyl ratios' fluctuations about their trend (the
                                  second block of the kind ``'two-scale'``; not in the paper);
* :func:`real_form`             - the same descriptor as ``2M+1`` real numbers with the
                                  same Euclidean distances;
* :func:`inverse_compact_shape_dna` - rebuild the smoothed normalised Shape-DNA from the
                                  cropped coefficients;
* :func:`f1_feature`            - the F1 feature ``lam_1 / lam_i`` of the paper's Fig. 5f;
* :func:`count_zero_modes`, :func:`nonzero_eigenvalues` - the zero modes of a spectrum (one
                                  per connected component) and the eigenvalues after them.

All functions take and return plain NumPy arrays.

Meshes of several pieces
------------------------
A mesh with ``k`` connected components has ``k`` zero eigenvalues (the constants on each
piece; Neumann or closed).  The descriptors that need a positive ``lam_i`` (the log-Weyl
ratio and its transforms, the truncated log spectrum, F1) follow one rule:

* drop the ``k`` zero modes and index the rest from 1: ``mu_i = lam_{k-1+i}``,
  ``i = 1..N-k`` (a connected mesh: ``mu_i = lam_i``, nothing changes);
* Weyl's law holds for the disjoint union with its **total** area (the counting functions
  of the pieces add up), so ``mu_i^norm = mu_i * area ~ 4 pi i`` as for one piece, and
  ``r_i = log(mu_i^norm / (4 pi i))``;
* a descriptor of fixed length that needs ``mu`` up to ``i = N-1`` (the log-Weyl transforms
  of an ``N``-eigenvalue Shape-DNA, F1) extends the ``N-k`` measured values by Weyl's law
  from the last one, ``mu_i = mu_{N-k} i / (N-k)`` (``r_i = r_{N-k}``): ``k-1`` values
  for ``k`` pieces; it needs at least ``2M+1`` measured ones (two for F1);
* ``k`` is the mesh's component count where it is known (``zero_modes=``; the
  :class:`cshape.DescriptorTable` stores it), else :func:`count_zero_modes`: the leading
  eigenvalues at most ``ZERO_RTOL = 1e-5`` times the largest (a known count takes
  other solvers' round-off on its zero modes, :data:`KNOWN_ZERO_RATIO`).

The paper's descriptors (``transform='weyl'``, the Shape-DNA and its truncation) take any
spectrum as it is, zero modes included.

Transforms (``transform=`` of :func:`compact_shape_dna`)
--------------------------------------------------------
After area normalisation ``lam_i^norm ~ 4 pi i`` (Weyl's law), and shapes differ by a few
per cent at *every* index.  The paper's ``lam'`` (Eq. 8) keeps those differences in
absolute terms, so the Euclidean distance is dominated by the highest eigenvalues, which
carry mesh detail more than shape class.  The log-Weyl ratio measures them relatively:

============== ====================================================== ==================
transform      sequence, then crop                                    values
============== ====================================================== ==================
'weyl'         ``lam'_i``, i = 0..N-1 (Eq. 8); DFT, 2M+1 low          2M+1 complex
               frequencies (Eq. 9-10): **the paper, bit for bit**
'log-weyl'     ``r_i``, i = 1..N-1; the same DFT crop on the          2M+1 complex
               N-1 values
'log-weyl-dct' ``r_i``, i = 1..N-1; orthonormal DCT-II (the even      2M+1 real
               extension), first 2M+1 coefficients
============== ====================================================== ==================

All three give ``2M+1`` real numbers in :func:`real_form`, so sizes compare one to one.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._checks import (
    check_bool,
    check_choice,
    check_crop,
    check_int,
    check_real,
    check_spectrum,
)
from ..mesh import is_mesh_like

__all__ = [
    "normalize",
    "weyl_subtract",
    "compact_shape_dna",
    "log_weyl_ratio",
    "detrend",
    "real_form",
    "inverse_compact_shape_dna",
    "count_zero_modes",
]

#: The ``normalization=`` options (:func:`normalize`); ``'none'``: already normalised.
NORMALIZATIONS = ("area", "fiedler", "weyl", "none")
#: The ``transform=`` options of :func:`compact_shape_dna`; ``'weyl'`` is the paper's.
TRANSFORMS = ("weyl", "log-weyl", "log-weyl-dct")
FOUR_PI = 4.0 * np.pi
#: An eigenvalue at most ``ZERO_RTOL`` times the largest of its spectrum is a zero mode
#: (:func:`count_zero_modes`).  How the value was chosen: the guide "Imperfect meshes"
#: (``docs/guides/imperfect-meshes.md``).
ZERO_RTOL = 1e-5
#: With a known component count ``k`` (``zero_modes=``) the ``k`` leading eigenvalues are
#: zero modes when each is at most ``ZERO_RTOL`` of the largest or ``KNOWN_ZERO_RATIO`` of
#: the first eigenvalue after them: the count beats the threshold, while eigenvalues of
#: another mesh (or not ascending) are still refused.
KNOWN_ZERO_RATIO = 1e-2


def _first_nonzero(lam: NDArray[np.float64]) -> int:
    # relative to the spectrum: eigenvalues scale as 1/length^2, so a large mesh (in mm or
    # um) has all of them far below any absolute threshold
    tol = ZERO_RTOL * float(np.abs(lam).max())
    nz = np.flatnonzero(np.abs(lam) > tol)
    if len(nz) == 0:
        raise ValueError("lam has no non-zero eigenvalue to normalise by")
    return int(nz[0])


def normalize(lam: ArrayLike, area: float | None = None, *,
              normalization: str = "area") -> NDArray[np.float64]:
    """Scale-normalise a Shape-DNA (Section 2.1).

    Parameters
    ----------
    lam : array_like, shape (N,)
        Ascending eigenvalues, lam_0 first.
    area : float, optional
        Surface area of the mesh; required for ``normalization='area'``.
    normalization : {'area', 'fiedler', 'weyl', 'none'}, default='area'
        ``'area'`` multiplies by the surface area (the paper's choice); afterwards the
        values lie around the Weyl line ``4 pi i``.  ``'fiedler'`` divides by the first
        non-zero eigenvalue.  ``'weyl'`` multiplies by ``4 pi / s`` where ``s`` is the
        least-squares slope of ``lam_i ~ s i`` (through the origin), so the result lies
        around ``4 pi i`` like the area normalisation, without needing the area.
        ``'none'``: the eigenvalues are normalised already and are returned as they are
        (a copy).

    Returns
    -------
    lam_norm : ndarray, shape (N,)
        The normalised eigenvalues ``lam^norm``, a new array.

    Raises
    ------
    TypeError
        Complex or non-numeric ``lam``; ``area`` not a real number; ``normalization`` not
        a string.
    ValueError
        ``lam`` not 1-D, empty or not finite; ``area`` not positive and finite, or missing
        for ``normalization='area'``; an unknown ``normalization``.

    Examples
    --------
    >>> normalize([0.0, 2.0, 6.0], 2.0).tolist()
    [0.0, 4.0, 12.0]
    >>> normalize([0.0, 2.0, 6.0], normalization="fiedler").tolist()
    [0.0, 1.0, 3.0]
    """
    return _normalize(check_spectrum(lam), area, normalization)


def _normalize(x: NDArray[np.float64], area: float | None,
               normalization: str) -> NDArray[np.float64]:
    """:func:`normalize` of a checked spectrum ``x`` (the other arguments unchecked)."""
    normalization = check_choice("normalization", normalization, NORMALIZATIONS)
    if normalization == "area":
        if area is None:
            raise ValueError(
                "normalization='area' needs the surface area: pass area=mesh.area "
                "(or use normalization='weyl', which needs no area)"
            )
        return x * check_real("area", area, positive=True)
    if normalization == "fiedler":
        return x / x[_first_nonzero(x)]
    if normalization == "none":
        return x.copy()
    i = np.arange(len(x), dtype=np.float64)
    s = float(i @ x) / float(i @ i) if len(x) > 1 else 0.0
    if s <= 0:
        raise ValueError("normalization='weyl' needs at least two eigenvalues with a "
                         "positive trend")
    return x * (FOUR_PI / s)


def weyl_subtract(lam_norm: ArrayLike) -> NDArray[np.float64]:
    """Subtract the Weyl line from a normalised Shape-DNA, Eq. (8).

    ``lam'_i = lam_i^norm - 4 pi i`` for ``i = 0, ..., N-1``.

    Parameters
    ----------
    lam_norm : array_like, shape (N,)
        Area-normalised eigenvalues (see :func:`normalize`).

    Returns
    -------
    lam_prime : ndarray, shape (N,)
        ``lam'_i``, the distance of each normalised eigenvalue from the Weyl line.
    """
    return _weyl_subtract(check_spectrum(lam_norm, "lam_norm"))


def _weyl_subtract(x: NDArray[np.float64]) -> NDArray[np.float64]:
    """Eq. (8) of a checked spectrum."""
    return x - FOUR_PI * np.arange(len(x))


def count_zero_modes(lam: ArrayLike, *, rtol: float = ZERO_RTOL) -> int:
    """Count the zero modes of an ascending spectrum: one per connected component.

    Parameters
    ----------
    lam : array_like, shape (N,)
        Ascending eigenvalues, ``lam_0`` first (raw or normalised: the test is relative).
    rtol : float, default=ZERO_RTOL (1e-5)
        The leading eigenvalues at most ``rtol`` times the largest (in absolute value) are
        zero modes.

    Returns
    -------
    int
        ``k``: ``lam_0 .. lam_{k-1}`` are zero modes; ``N`` when all are (too few
        eigenvalues to see past them), ``0`` for a Dirichlet spectrum of open pieces.

    Examples
    --------
    >>> count_zero_modes([0.0, 3e-9, 2.0, 6.0])  # two pieces, one zero mode with round-off
    2
    """
    x = check_spectrum(lam)
    rtol = check_real("rtol", rtol, min=0)
    tol = rtol * float(np.abs(x).max())
    above = np.flatnonzero(x > tol)
    return int(above[0]) if len(above) else len(x)


def _zero_modes(x: np.ndarray, zero_modes: object, tol: float) -> int:
    """Return the number of zero modes of ``x``: counted, or ``zero_modes`` checked against it."""
    if zero_modes is None:
        above = np.flatnonzero(x > tol)
        return int(above[0]) if len(above) else len(x)
    k = check_int("zero_modes", zero_modes, min=0)
    if k > len(x):
        raise ValueError(f"zero_modes={k} is more than the {len(x)} eigenvalues given")
    bound = max(tol, KNOWN_ZERO_RATIO * float(x[k])) if k < len(x) else tol
    big = np.flatnonzero(np.abs(x[:k]) > bound)
    if len(big):
        j = int(big[0])
        raise ValueError(
            f"zero_modes={k} (components) but lam_{j} = {x[j]:.3g} is not zero: the "
            "eigenvalues belong to another mesh, or are not ascending")
    return k


def _after(x: np.ndarray, k: int, tol: float, what: str) -> np.ndarray:
    """``x[k:]``, checked positive (ascending past the zero modes)."""
    mu = x[k:]
    if len(mu) == 0:
        raise ValueError(
            f"{what} needs a non-zero eigenvalue, but all {len(x)} are zero modes (a mesh "
            f"of {len(x)} or more components): compute more eigenvalues (N > {len(x)})")
    bad = np.flatnonzero(~(mu > tol))
    if len(bad):
        i = int(bad[0]) + k
        raise ValueError(
            f"{what} needs lam_i > 0 after the {k} zero mode{'s' if k != 1 else ''}, but "
            f"lam_{i} = {x[i]:.3g}: lam must be ascending, with no more zero eigenvalues "
            "than the mesh has components")
    return mu


def _check_length(length: object) -> int | None:
    return None if length is None else check_int("length", length, min=1)


def _weyl_extend(mu: np.ndarray, length: int | None) -> np.ndarray:
    """``mu`` cut or extended to ``length`` values by Weyl's law ``mu_i ~ mu_L i / L``."""
    L = len(mu)
    if length is None or length == L:
        return mu
    if length < L:
        return mu[:length]
    i = np.arange(L + 1, length + 1, dtype=np.float64)
    return np.concatenate([mu, mu[-1] * i / L])


def nonzero_eigenvalues(lam: ArrayLike, zero_modes: int | None = None, *,
                        length: int | None = None) -> NDArray[np.float64]:
    """Return the eigenvalues after the zero modes, indexed from 1: ``mu_i = lam_{k-1+i}``.

    The rule for meshes of several pieces (see the module notes): a mesh of ``k``
    components has ``k`` zero eigenvalues; they are dropped and the rest indexed from 1,
    so that ``mu_i * area ~ 4 pi i`` (Weyl's law with the total area).

    Parameters
    ----------
    lam : array_like, shape (N,)
        Ascending eigenvalues, ``lam_0`` first.
    zero_modes : int, optional
        ``k``, e.g. the mesh's number of connected components (Neumann or closed pieces);
        checked against the spectrum.  Default: :func:`count_zero_modes`.
    length : int, optional
        Return exactly ``length`` values: the first ones, or the ``N-k`` measured ones
        extended by Weyl's law from the last, ``mu_i = mu_{N-k} i / (N-k)``.

    Returns
    -------
    mu : ndarray, shape (N-k,) or (length,)
        The positive eigenvalues ``mu_1, mu_2, ...``, ascending.

    Raises
    ------
    ValueError
        If no eigenvalue is left, a value after the zero modes is not positive, or
        ``zero_modes`` disagrees with the spectrum (a "zero mode" that is not zero).
    """
    x = check_spectrum(lam)
    tol = ZERO_RTOL * float(np.abs(x).max())
    k = _zero_modes(x, zero_modes, tol)
    return _weyl_extend(_after(x, k, tol, "nonzero_eigenvalues"), _check_length(length))


def log_weyl_ratio(lam_norm: ArrayLike, zero_modes: int | None = None, *,
                   length: int | None = None) -> NDArray[np.float64]:
    """Compute the log-Weyl ratio of a normalised Shape-DNA (an extension beyond the paper).

    ``r_i = log(lam_i^norm / (4 pi i))`` for ``i = 1, ..., N-1``: the relative deviation
    from the Weyl line ``4 pi i`` (``r_i ~ (lam_i^norm - 4 pi i) / (4 pi i)`` when small),
    so that every index weighs alike, where Eq. (8) lets the largest eigenvalues dominate.

    ``lam_0`` is never used: it is 0 for a closed mesh or a Neumann spectrum and has no
    logarithm.  A Dirichlet spectrum (open mesh, ``bc='dirichlet'``) has ``lam_0 > 0``; it
    is dropped as well, so that the sequence, its length ``N-1`` and the index ``i`` in
    ``4 pi i`` are the same for every spectrum (and equal to those of Eq. 8 for ``i >= 1``).

    **Several pieces.**  A mesh of ``k`` components has ``k`` zero eigenvalues: all are
    dropped and the rest indexed from 1 (:func:`nonzero_eigenvalues`),
    ``r_i = log(mu_i^norm / (4 pi i))``, ``i = 1..N-k``, with the total area in the
    normalisation (Weyl's law of the disjoint union).

    Parameters
    ----------
    lam_norm : array_like, shape (N,)
        Area-normalised eigenvalues, ``N >= 2`` (see :func:`normalize`).
    zero_modes : int, optional
        Number of zero eigenvalues (the mesh's components); default: counted
        (:func:`count_zero_modes`).
    length : int, optional
        Return exactly ``length`` ratios; past the ``N - max(k, 1)`` measured ones the
        last is repeated (Weyl's law from the last eigenvalue, ``r_i = r_{N-k}``).

    Returns
    -------
    r : ndarray, shape (N - max(k, 1),) or (length,)
        ``r[i-1] = log(mu_i^norm / (4 pi i))``; ``N-1`` values for a connected mesh.

    Raises
    ------
    ValueError
        If no eigenvalue is left after the zero modes, or one after them is not positive
        (lam not ascending).
    """
    return _log_weyl_ratio(check_spectrum(lam_norm, "lam_norm", min_len=2), zero_modes, length)


def _log_weyl_ratio(x: NDArray[np.float64], zero_modes: object, length: object
                    ) -> NDArray[np.float64]:
    """:func:`log_weyl_ratio` of a checked spectrum of at least 2 values."""
    length = _check_length(length)
    tol = ZERO_RTOL * float(np.abs(x).max())
    k = max(_zero_modes(x, zero_modes, tol), 1)
    mu = _after(x, k, tol, "the log-Weyl ratio")
    r = np.log(mu / (FOUR_PI * np.arange(1, len(mu) + 1)))
    if length is None or length == len(r):
        return r
    if length < len(r):
        return r[:length]
    return np.concatenate([r, np.full(length - len(r), r[-1])])  # Weyl: mu_i ~ mu_L i / L


def _check_transform(transform: object) -> str:
    return check_choice("transform", transform, TRANSFORMS)


def _sequence_length(N: int, transform: str) -> int:
    """Length of the sequence that is transformed: N (Eq. 8) or N-1 (log-Weyl)."""
    return N if transform == "weyl" else N - 1


def _check_M(M: object, N: int, transform: str = "weyl") -> int:
    return check_crop(M, N, log=transform != "weyl")  # the one M-versus-N rule


def _check_N(N: object) -> int:
    return check_int("N", N, min=1)


def _spectrum_from_input(lam: Any, N: int, area: float | None,
                         normalization: str) -> NDArray[np.float64]:
    """Return the normalised Shape-DNA (N,) from eigenvalues (checked here, once)."""
    N = _check_N(N)
    normalization = check_choice("normalization", normalization, NORMALIZATIONS)
    if area is not None:
        area = check_real("area", area, positive=True)
    if normalization == "none" and area is not None:
        raise ValueError(
            "pass either area=... (raw eigenvalues, multiplied by it) or "
            "normalization='none' (eigenvalues already normalised), not both"
        )
    if is_mesh_like(lam):
        raise TypeError(
            "compact_shape_dna takes eigenvalues, not a mesh: compute them first, "
            "lam = cshape.shape_dna(mesh, N), then compact_shape_dna(lam, N=N, M=M, "
            "area=mesh.area)"
        )
    lam = check_spectrum(lam, "lam")  # the one check of the eigenvalues
    if len(lam) < N:
        raise ValueError(
            f"got {len(lam)} eigenvalues but N={N}; pass N={len(lam)} or compute more eigenvalues"
        )
    lam = lam[:N]
    if normalization == "none":
        return lam
    if normalization == "area" and area is None:
        import warnings

        from ..mesh import CShapeWarning

        warnings.warn(
            "compact_shape_dna got eigenvalues without area=: they are taken as already "
            "normalised. Pass area=mesh.area for raw eigenvalues (Section 2.1 multiplies "
            "them by the area; without it the descriptor is off by that factor), or "
            "normalization='none' to say they are normalised already",
            CShapeWarning, stacklevel=3,
        )
        return lam
    return _normalize(lam, area, normalization)


def _dft_crop(x: NDArray[np.float64], M: int) -> NDArray[np.complex128]:
    """Eq. (9)-(10) on any real sequence: DFT, shift, the 2M+1 values around the centre."""
    Lam = np.fft.fft(x)  # Eq. (9)
    shifted = np.fft.fftshift(Lam)  # zero frequency at index len(x) // 2
    c = len(x) // 2
    return shifted[c - M : c + M + 1].copy()  # Eq. (10)


def _dct(x: NDArray[np.float64]) -> NDArray[np.float64]:
    from scipy.fft import dct

    return dct(x, type=2, norm="ortho")


def compact_shape_dna(lam: ArrayLike, *, N: int = 100, M: int = 16,
                      area: float | None = None,
                      normalization: str = "area", transform: str = "weyl",
                      zero_modes: int | None = None) -> NDArray[Any]:
    """Compact Shape-DNA (cShape-DNA), Eq. (8)-(10), and its log-Weyl extensions.

    ``transform='weyl'`` (the default) is the paper, bit for bit: normalise (multiply by
    the area), subtract the Weyl line (Eq. 8) ``lam'_i = lam_i^norm - 4 pi i``,
    ``i = 0..N-1``, take the DFT ``Lambda_k = sum_{i=0}^{N-1} lam'_i exp(-j 2 pi k i / N)``
    (Eq. 9), shift the zero frequency to the centre ``<N/2>`` and keep the ``2M+1`` values
    around it (Eq. 10): frequencies ``k = -M, ..., M``.

    ``transform='log-weyl'`` replaces Eq. (8) by the log-Weyl ratio (:func:`log_weyl_ratio`)
    ``r_i = log(lam_i^norm / (4 pi i))``, ``i = 1..N-1`` (``lam_0`` is not used), and crops
    its DFT the same way: with ``L = N-1`` and ``n = i-1``,
    ``R_k = sum_{n=0}^{L-1} r_{n+1} exp(-j 2 pi k n / L)``, frequencies ``k = -M..M`` taken
    from ``fftshift`` around index ``L // 2``.  ``2M+1 <= L``, so for an even ``L`` the
    unpaired Nyquist frequency ``-L/2`` is never kept and the crop is conjugate-symmetric
    for odd and even ``L`` alike.

    ``transform='log-weyl-dct'`` takes the orthonormal DCT-II of ``r`` (the DFT of its even
    extension ``r_1..r_{N-1}, r_{N-1}..r_1``, which has no jump between ``r_{N-1}`` and
    ``r_1`` for the periodic DFT to smear into every frequency) and keeps the first
    ``2M+1`` coefficients ``C_k = w_k sum_{n=0}^{L-1} r_{n+1} cos(pi k (2n+1) / (2L))``,
    ``k = 0..2M``, with ``w_0 = sqrt(1/L)`` and ``w_k = sqrt(2/L)``.  They are real: the
    same ``2M+1`` numbers as the real form of the DFT crops, so sizes compare one to one.

    Parameters
    ----------
    lam : array_like, shape (>= N,)
        Eigenvalues, ascending (:func:`cshape.shape_dna`; a formula takes numbers, only
        the spectrum stage solves).  Raw eigenvalues need ``area`` (they are multiplied by
        it); already normalised ones need ``normalization='none'``.  Eigenvalues with
        neither are taken as normalised, with a :class:`cshape.CShapeWarning` (a raw
        spectrum would silently be off by the area factor).  Only the first ``N`` are used.
    N : int, default=100
        Length of the Shape-DNA (``lam_0 .. lam_{N-1}``).
    M : int, default=16
        Crop half-width; the descriptor has ``2M+1`` values.  ``0 <= M <= (N-1)//2`` for
        ``'weyl'``, ``0 <= M <= (N-2)//2`` for the log-Weyl transforms (``2M+1 <= N-1``).
    area : float, optional
        Surface area used for the normalisation (``mesh.area``).
    normalization : {'area', 'fiedler', 'weyl', 'none'}, default='area'
        See :func:`normalize`; ``'none'``: the eigenvalues are already normalised
        (``lam^norm``) and are used as they are (no ``area``).
    transform : {'weyl', 'log-weyl', 'log-weyl-dct'}, default='weyl'
        The sequence and transform, as above.
    zero_modes : int, optional
        Log-Weyl transforms only: the number ``k`` of zero eigenvalues (the mesh's
        connected components).  Default: counted from the eigenvalues
        (:func:`count_zero_modes`).  The ``k`` zero modes are
        dropped, the rest indexed from 1 and extended to ``N-1`` ratios by Weyl's law
        (``r_i = r_{N-k}`` for the last ``k-1``; see the module notes); at least ``2M+1``
        must be measured (``N >= 2M+1+k``).  ``'weyl'`` (Eq. 8) takes the spectrum as it
        is, zero modes included.

    Returns
    -------
    S_c : ndarray, shape (2M+1,)
        Complex128 for ``'weyl'`` and ``'log-weyl'``: the DFT coefficients of frequencies
        ``-M, ..., M`` in that order, ``S_c[M]`` the zero frequency, conjugate-symmetric
        (``S_c[M+k] == conj(S_c[M-k])``) because the sequence is real.  float64 for
        ``'log-weyl-dct'``: ``(C_0, ..., C_{2M})``.

    Raises
    ------
    TypeError
        If ``N`` or ``M`` is not an integer (bools are refused), ``area`` not a real
        number, a mode not a string, the eigenvalues are complex, or a mesh is given in
        place of its eigenvalues.
    ValueError
        If ``N < 1``, ``M < 0``, ``2M+1`` exceeds the sequence length, ``area`` is not
        positive, ``normalization`` or ``transform`` is unknown, fewer than ``N``
        eigenvalues are given, both ``area`` and ``normalization='none'`` are given, or, for
        the log-Weyl transforms, some ``lam_i <= 0`` with ``i >= 1``.

    Warns
    -----
    CShapeWarning
        Eigenvalues without ``area`` under ``normalization='area'`` (say
        ``normalization='none'`` for normalised ones).

    See Also
    --------
    real_form : The same descriptor as 2M+1 real numbers with equal distances.
    inverse_compact_shape_dna : What the 2M+1 coefficients keep of the Shape-DNA.
    log_weyl_ratio : The sequence of the log-Weyl transforms.

    Notes
    -----
    ``'weyl'`` reproduces the paper; ``'log-weyl-dct'`` is the transform to retrieve
    shapes with.  Fewer eigenvalues beyond ``2M+1`` (a smaller ``N``) retrieve better on the
    benchmark collections; at ``N = 2M+2`` nothing is cropped and both log-Weyl transforms
    have the distances of the first ``2M+1`` log-Weyl ratios (kind ``'truncated-log'`` of
    :class:`cshape.Descriptor`).  The measurements behind these choices are
    in ``benchmarks/README.md`` ("Which transform, which N").

    Examples
    --------
    A spectrum on the Weyl line ``4 pi i`` (after the area) has nothing left after Eq. (8):

    >>> import numpy as np
    >>> S = compact_shape_dna(4 * np.pi * np.arange(10.0), N=10, M=2, area=1.0)
    >>> S.shape, bool(np.allclose(S, 0))
    ((5,), True)
    """
    transform = _check_transform(transform)
    M = _check_M(M, _check_N(N), transform)  # before the eigensolve
    if zero_modes is not None:
        zero_modes = check_int("zero_modes", zero_modes, min=0)
    lam_norm = _spectrum_from_input(lam, N, area, normalization)
    return _compact(lam_norm, M, zero_modes, transform)


def _compact(lam_norm: NDArray[np.float64], M: int, zero_modes: int | None, transform: str
             ) -> NDArray[Any]:
    """:func:`compact_shape_dna` of a checked, normalised spectrum (M and transform checked)."""
    if transform == "weyl":
        return _dft_crop(_weyl_subtract(lam_norm), M)  # Eq. (8)-(10)
    r = _log_weyl_sequence(lam_norm, M, zero_modes, f"transform={transform!r}")
    if transform == "log-weyl":
        return _dft_crop(r, M)
    return _dct(r)[: 2 * M + 1].copy()


def _log_weyl_sequence(x: NDArray[np.float64], M: int, zero_modes: int | None, what: str
                       ) -> NDArray[np.float64]:
    """Return the ``N-1`` log-Weyl ratios of the log-Weyl transforms and 'two-scale'.

    The rule for several pieces.  ``x``: the checked, normalised spectrum, ``N >= 2M + 2``
    values; ``what`` names the caller in the message.
    """
    N = len(x)
    k0 = _zero_modes(x, zero_modes, ZERO_RTOL * float(np.abs(x).max()))
    k = max(k0, 1)  # lam_0 is dropped also when positive (Dirichlet)
    if N - k < 2 * M + 1:
        raise ValueError(
            f"{what} needs 2M+1 = {2 * M + 1} non-zero eigenvalues, but "
            f"{k} of the N = {N} are zero modes (a mesh of {k} components) and {N - k} are "
            f"left: use N >= {2 * M + 1 + k} or M <= {max(N - k - 1, 0) // 2}")
    return _log_weyl_ratio(x, k0, N - 1)


#: Degree of the polynomial in the index that :func:`detrend` removes by default.  Linear
#: finite elements overestimate ``lam_i`` by a relative error that grows smoothly with ``i``
#: (about ``h^2 lam_i``), so a coarse mesh raises the log-Weyl ratios by a smooth function of
#: ``i``; a cubic takes it, and leaves the spectrum's fluctuations.
TREND_DEGREE = 3


def detrend(r: ArrayLike, degree: int = TREND_DEGREE) -> NDArray[np.float64]:
    """Return a sequence less its least-squares polynomial of ``degree`` in the index.

    For the log-Weyl ratios ``r_1 .. r_L`` (:func:`log_weyl_ratio`) this is
    ``r_i - p(t_i)`` with ``t_i = i / L`` and ``p`` the polynomial of the given degree that
    fits ``r`` best in the least-squares sense: the spectrum's fluctuations about its smooth
    trend.  A constant added to ``r`` (another normalisation) and a smooth drift in ``i`` up
    to that degree (the discretisation error of a coarse mesh) leave it unchanged.

    Parameters
    ----------
    r : array_like, shape (L,)
        A real sequence, ``L >= degree + 2``.
    degree : int, default=TREND_DEGREE (3)
        Degree of the polynomial removed, 0 or more.

    Returns
    -------
    ndarray, shape (L,)
        The residual; orthogonal to ``1, t, ..., t^degree``.

    Raises
    ------
    TypeError
        ``degree`` not an integer, ``r`` complex or not numeric.
    ValueError
        ``r`` not 1-D, not finite, or shorter than ``degree + 2``; ``degree < 0``.

    Examples
    --------
    >>> import numpy as np
    >>> from cshape.descriptors import detrend
    >>> t = np.arange(1, 11) / 10
    >>> bool(np.allclose(detrend(1 + 2 * t - t**3), 0))
    True
    """
    return _detrend(check_spectrum(r, "r"), check_int("degree", degree, min=0))


def _detrend(x: NDArray[np.float64], degree: int = TREND_DEGREE) -> NDArray[np.float64]:
    """:func:`detrend` of a checked sequence ``x`` (``degree`` checked)."""
    if len(x) < degree + 2:
        raise ValueError(f"r has {len(x)} values but a polynomial of degree {degree} needs "
                         f"at least {degree + 2} to leave a residual; use a longer sequence "
                         "(more eigenvalues) or a lower degree")
    t = np.arange(1, len(x) + 1, dtype=np.float64) / len(x)
    V = np.vander(t, degree + 1)
    coef, *_ = np.linalg.lstsq(V, x, rcond=None)
    return x - V @ coef


def real_form(S_c: ArrayLike) -> NDArray[np.float64]:
    """Real form of a cShape-DNA: ``2M+1`` reals with the same Euclidean distances.

    Because the Shape-DNA is real, ``Lambda_{-k} = conj(Lambda_k)``, so

    ``||S_c - T_c||^2 = |dLambda_0|^2 + 2 sum_{k=1..M} |dLambda_k|^2``.

    The real form is ``(Re Lambda_0, sqrt2 Re Lambda_1, sqrt2 Im Lambda_1, ...,
    sqrt2 Re Lambda_M, sqrt2 Im Lambda_M)``.  This holds for both DFT transforms
    (``'weyl'`` and ``'log-weyl'``).  A real descriptor (``'log-weyl-dct'``) is its own
    real form: it is returned unchanged (as a float64 copy).

    Parameters
    ----------
    S_c : array_like, shape (2M+1,) or (p, 2M+1)
        One descriptor or a stack of them (rows): complex (DFT crops) or real (DCT).

    Returns
    -------
    ndarray of float64, same shape as ``S_c``
        The real form of each descriptor; Euclidean distances between real forms equal
        those between the complex descriptors.
    """
    S = np.asarray(S_c)
    if S.ndim not in (1, 2) or S.shape[-1] % 2 != 1:
        raise ValueError(
            f"S_c must have shape (2M+1,) or (p, 2M+1) with an odd last dimension, got {S.shape}"
        )
    if not np.iscomplexobj(S):
        return np.array(S, dtype=np.float64)  # 'log-weyl-dct': already real
    M = (S.shape[-1] - 1) // 2
    pos = S[..., M + 1 :]  # frequencies 1..M
    out = np.empty(S.shape, dtype=np.float64)
    out[..., 0] = S[..., M].real
    out[..., 1::2] = np.sqrt(2.0) * pos.real
    out[..., 2::2] = np.sqrt(2.0) * pos.imag
    return out


def inverse_compact_shape_dna(S_c: ArrayLike, N: int, *, add_weyl: bool = True,
                              transform: str = "weyl") -> NDArray[np.float64]:
    """Rebuild the smoothed normalised Shape-DNA from the cropped coefficients.

    The ``2M+1`` coefficients are put back into a zero vector of the sequence's length
    (the other frequencies are 0, as in Eq. 10) and inverse-transformed.

    Parameters
    ----------
    S_c : array_like, shape (2M+1,)
        A cShape-DNA from :func:`compact_shape_dna` with the same ``transform``.
    N : int
        Length of the original Shape-DNA (``2M+1 <= N``, or ``<= N-1`` for the log-Weyl
        transforms).
    add_weyl : bool, default=True
        Undo the transform's subtraction: return the smoothed normalised Shape-DNA
        ``lam^norm`` (shape ``(N,)``).  ``'weyl'`` adds ``4 pi i`` back (undoes Eq. 8); the
        log-Weyl transforms return ``lam_i^norm = 4 pi i exp(r_i)`` for ``i >= 1`` and
        ``lam_0 = 0`` (not encoded: its value for a closed or Neumann spectrum).  With
        ``False`` return the smoothed sequence itself: ``lam'`` (shape ``(N,)``) or ``r``
        (shape ``(N-1,)``).
    transform : {'weyl', 'log-weyl', 'log-weyl-dct'}, default='weyl'

    Returns
    -------
    ndarray of float64, shape (N,) (or (N-1,) for a log-Weyl ``r``)
        Equal to the input of :func:`compact_shape_dna` when nothing is cropped:
        ``2M+1 = N`` for ``'weyl'`` (N odd), ``2M+1 = N-1`` for the log-Weyl transforms
        (N even; ``lam_0`` excepted).
    """
    transform = _check_transform(transform)
    N = _check_N(N)
    add_weyl = check_bool("add_weyl", add_weyl)
    if transform == "log-weyl-dct":
        if np.iscomplexobj(S_c):
            raise ValueError(
                "transform='log-weyl-dct' descriptors are real, got a complex S_c (a DFT "
                "crop?); pass the transform it was computed with"
            )
        S = np.asarray(S_c, dtype=np.float64)
    else:
        S = np.asarray(S_c, dtype=np.complex128)
    if S.ndim != 1 or len(S) % 2 != 1:
        raise ValueError(f"S_c must be 1-D with an odd length 2M+1, got shape {S.shape}")
    M = (len(S) - 1) // 2
    _check_M(M, N, transform)
    L = _sequence_length(N, transform)
    if transform == "log-weyl-dct":
        from scipy.fft import idct

        full = np.zeros(L)
        full[: len(S)] = S
        seq = idct(full, type=2, norm="ortho")
    else:
        shifted = np.zeros(L, dtype=np.complex128)
        c = L // 2
        shifted[c - M : c + M + 1] = S
        seq = np.fft.ifft(np.fft.ifftshift(shifted)).real
    if not add_weyl:
        return seq
    if transform == "weyl":
        return seq + FOUR_PI * np.arange(N)
    return np.concatenate([[0.0], FOUR_PI * np.arange(1, N) * np.exp(seq)])


def f1_feature(lam: ArrayLike, zero_modes: int | None = None, *,
               length: int | None = None) -> NDArray[np.float64]:
    """Compute the F1 feature vector ``(lam_1/lam_2, lam_1/lam_3, ..., lam_1/lam_{N-1})`` (Fig. 5f).

    ``lam_1`` is the first non-zero eigenvalue (the one after ``lam_0 = 0`` for a
    connected closed mesh); the ratios run over the eigenvalues after it.  A mesh of ``k``
    pieces has ``k`` zero eigenvalues: they are dropped and the rest indexed from 1
    (:func:`nonzero_eigenvalues`), ``F1_i = mu_1 / mu_i``.

    Parameters
    ----------
    lam : array_like, shape (N,)
        Ascending eigenvalues.
    zero_modes : int, optional
        Number of zero eigenvalues (the mesh's components); default: counted
        (:func:`count_zero_modes`).
    length : int, optional
        Return exactly ``length`` ratios, past the measured ones extended by Weyl's law
        (``mu_i = mu_{N-k} i / (N-k)``); :class:`cshape.Descriptor` asks for ``N - 2``,
        the length of a connected mesh.

    Returns
    -------
    ndarray, shape (N - k - 1,) or (length,)
        ``N - 2`` values for a connected closed mesh (``k = 1``); ``k = 0`` for a
        Dirichlet spectrum.  Scale invariant; values in (0, 1].
    """
    return _f1_feature(check_spectrum(lam, min_len=2), zero_modes, length)


def _f1_feature(x: NDArray[np.float64], zero_modes: object, length: object
                ) -> NDArray[np.float64]:
    """:func:`f1_feature` of a checked spectrum of at least 2 values."""
    tol = ZERO_RTOL * float(np.abs(x).max())
    mu = _after(x, _zero_modes(x, zero_modes, tol), tol, "F1")
    if len(mu) < 2:
        raise ValueError("lam needs at least one eigenvalue after the first non-zero one")
    length = _check_length(length)
    mu = _weyl_extend(mu, None if length is None else length + 1)
    return mu[0] / mu[1:]
