"""Stage 6 of the pipeline: point signatures from the eigenpairs, and point correspondence.

Shape-DNA keeps the eigenvalues ``lam``; the eigenfunctions ``phi`` (``A phi_i = -lam_i B
phi_i``, Eq. 3, B-orthonormal: ``phi.T @ B @ phi = I``) describe each *point*.  Everything here
takes an :class:`cshape.Eigenbasis` (:func:`cshape.eigenbasis`) and uses every pair it holds:
pass ``basis.truncate(N)`` to use fewer.

=====================  =====================================================================
function               definition
=====================  =====================================================================
:func:`heat_trace`     ``Z(t) = sum_i exp(-lam_i t)``
:func:`heat_kernel`    ``k_t(x, y) = sum_i exp(-lam_i t) phi_i(x) phi_i(y)``
:func:`hks`            ``HKS(x, t) = k_t(x, x)`` (Sun, Ovsjanikov and Guibas 2009)
:func:`wks`            ``WKS(x, e) = C_e sum_i phi_i(x)^2 exp(-(e - log lam_i)^2 / (2 sigma^2))``,
                       ``C_e = 1 / sum_i exp(-(e - log lam_i)^2 / (2 sigma^2))`` (Aubry,
                       Schlickewei and Cremers 2011); ``lam_0 = 0`` left out
:func:`si_hks`         ``|FFT_tau(d/dtau log HKS(x, base^tau))|``, the first frequencies
                       (Bronstein and Kokkinos 2010)
:func:`match_points`   nearest signature (optionally mutual nearest neighbours)
=====================  =====================================================================

Per-vertex signatures are arrays of shape ``(n, number of scales)``, one row per row of
``phi``.  :func:`cshape.eigenbasis` repairs a mesh first (duplicate or unreferenced vertices
removed), and ``n`` is then the vertex count of the repaired mesh, ``basis.mesh``.

Normalisation and scale
-----------------------
* ``normalization='area'`` gives the signature of the shape scaled to unit area, the
  paper's normalisation of Section 2.1 (``lam -> lam * area``, ``phi -> phi * sqrt(area)``,
  ``area`` the basis's): times are then in units of the area, energies are
  ``log(lam * area)``, and values are dimensionless, so a scaled copy of a shape has the same
  signature.  With ``'none'``, the HKS of a shape scaled by ``s`` is ``HKS_s(x, s^2 t) =
  HKS(x, t) / s^2``.
* ``scale='trace'`` divides by the signature's integral over the surface, so each column
  integrates to 1: the heat trace ``Z(t)`` for the HKS (Sun et al.'s scaled HKS),
  ``sum_i exp(-(e - log lam_i)^2 / (2 sigma^2))`` for the WKS (Aubry et al.'s ``C_e``, the
  WKS default).  Since ``int_M k_t(x, x) dx = Z(t)``, a surface whose HKS is constant (the
  sphere) has ``HKS = Z(t) / area``.  On a mesh the integral ``1^T B s`` of a signature ``s``
  equals ``Z(t)`` (or 1) exactly for the lumped mass matrix (``mass='lumped'``) and up to the
  discretisation error for the consistent one (``1^T B phi_i^2 != phi_i^T B phi_i``).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ._checks import check_bool, check_choice, check_eigenbasis, check_int, check_real
from ._nearest import nearest_rows
from .descriptors.formulas import ZERO_RTOL
from .spectrum import Eigenbasis

__all__ = [
    "heat_kernel",
    "heat_trace",
    "hks",
    "hks_times",
    "match_points",
    "si_hks",
    "wks",
    "wks_energies",
]

#: ``t_min = T_FACTOR / lam_max`` and ``t_max = T_FACTOR / lam_1`` (Sun et al. 2009).
T_FACTOR = 4.0 * np.log(10.0)

#: The WKS's Gaussian width in energy steps (Aubry et al. 2011: ``sigma = 7 delta``).
WKS_WIDTH = 7.0

# ---------------------------------------------------------------------- checks
#: The ``normalization=`` options: the eigenpairs as they are, or of the shape scaled to
#: unit area (Section 2.1).
NORMALIZATIONS = ("none", "area")


def _check_basis(basis: object) -> Eigenbasis:
    return check_eigenbasis("basis", basis, Eigenbasis)


def _eigenvalues(basis: object, normalization: object) -> np.ndarray:
    """``lam`` of a checked basis, times the area for ``normalization='area'``."""
    basis = _check_basis(basis)
    normalization = check_choice("normalization", normalization, NORMALIZATIONS)
    return basis.lam * basis.area if normalization == "area" else basis.lam


def _pairs(basis: object, normalization: object) -> tuple[np.ndarray, np.ndarray]:
    """``(lam, phi)`` of a checked basis, scaled to unit area for ``normalization='area'``."""
    basis = _check_basis(basis)
    normalization = check_choice("normalization", normalization, NORMALIZATIONS)
    if normalization == "area":
        return basis.lam * basis.area, basis.phi * np.sqrt(basis.area)
    return basis.lam, basis.phi


def _as_real_2d(x: ArrayLike, name: str) -> np.ndarray:
    if isinstance(x, (str, bytes)) or np.iscomplexobj(x):
        raise TypeError(f"{name} must be a real array, got {type(x).__name__}")
    try:
        a = np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a real array, got {type(x).__name__}") from None
    return a


def _check_positive(name: str, value: object, *, allow_none: bool = True) -> float | None:
    """Check a positive finite real number, returned as float (``None`` passes when allowed)."""
    if value is None and allow_none:
        return None
    return check_real(name, value, positive=True)


def _check_scales(name: str, values: ArrayLike, *, positive: bool = True) -> np.ndarray:
    """Check a scalar or 1-D array of finite (positive) scales, returned as a 1-D float array."""
    a = _as_real_2d(values, name)
    if a.ndim > 1:
        raise ValueError(f"{name} must be a number or a 1-D array, got shape {a.shape}")
    a = np.atleast_1d(a)
    if a.size == 0:
        raise ValueError(f"{name} is empty; pass at least one value")
    if not np.isfinite(a).all() or (positive and (a <= 0).any()):
        bad = a[~np.isfinite(a) | ((a <= 0) if positive else False)][0]
        kind = "positive finite" if positive else "finite"
        raise ValueError(f"{name} must be {kind} values, got {bad!r}")
    return a


def _nonzero(lam: np.ndarray) -> np.ndarray:
    """Mask of the eigenvalues that are not zero modes (``ZERO_RTOL``, the descriptors' rule)."""
    return lam > ZERO_RTOL * lam.max()


def _first_nonzero(lam: np.ndarray) -> float:
    nz = lam[_nonzero(lam)] if lam.max() > 0 else lam[:0]
    if len(nz) == 0:
        raise ValueError(
            "lam has no non-zero eigenvalue, so the default scales are undefined; compute "
            "more eigenpairs (N >= 2) or pass the scales explicitly"
        )
    return float(nz[0])


# ---------------------------------------------------------------------- heat
def heat_trace(basis: Eigenbasis, t: ArrayLike, *, normalization: str = "none") -> np.ndarray:
    """Compute the heat trace ``Z(t) = sum_i exp(-lam_i t)`` over the basis's eigenvalues.

    ``Z(t) = int_M k_t(x, x) dx``: the integral of the HKS over the surface.

    Parameters
    ----------
    basis : Eigenbasis
        The ``N`` eigenpairs (:func:`cshape.eigenbasis`); only ``lam`` is used.
    t : float or array_like, shape (T,)
        Positive times (units of length^2, or of the area with ``normalization='area'``).
    normalization : {'none', 'area'}, default='none'
        ``'area'``: the trace of the shape scaled to unit area, ``sum_i exp(-lam_i area t)``.

    Returns
    -------
    ndarray, shape (T,)
        ``Z(t)`` at each time (a float array of one value for a scalar ``t``).
    """
    lam = _eigenvalues(basis, normalization)
    t = _check_scales("t", t)
    return np.exp(-np.outer(t, lam)).sum(axis=1)


def heat_kernel(basis: Eigenbasis, t: float, sources: ArrayLike, *,
                normalization: str = "none") -> np.ndarray:
    """Compute the heat kernel ``k_t(x, y) = sum_i exp(-lam_i t) phi_i(x) phi_i(y)`` from vertices.

    The temperature at every vertex ``x`` at time ``t`` after a unit of heat was put at
    ``y`` (a Dirac delta: ``int k_t(x, y) dx = 1`` for Neumann or closed surfaces).
    Truncated to the ``N`` eigenpairs of the basis, it is smooth at the scale of the
    ``N``-th eigenfunction: for small ``t`` it needs many eigenpairs.

    Parameters
    ----------
    basis : Eigenbasis
        The ``N`` eigenpairs (:func:`cshape.eigenbasis`).
    t : float
        Positive time.
    sources : int or array_like of int, shape (s,)
        Vertex indices ``y``.
    normalization : {'none', 'area'}, default='none'
        ``'area'``: the kernel of the shape scaled to unit area (see the module notes).

    Returns
    -------
    ndarray, shape (n, N_sources)
        ``k_t(x, y)``, rows ``x`` (all vertices), columns ``y``; shape (n,) for one source
        given as an int.  Symmetric in ``x, y``.
    """
    basis = _check_basis(basis)
    tt = _check_scales("t", t)
    if tt.size != 1:
        raise ValueError(f"t must be one time, got {tt.size} values; call once per time")
    n = basis.n_vertices
    src = np.asarray(sources)
    if src.dtype.kind not in "iu" or src.ndim > 1:
        raise TypeError(
            f"sources must be a vertex index or a 1-D array of them, got {sources!r}"
        )
    if src.size and (src.min() < 0 or src.max() >= n):
        raise ValueError(
            f"sources holds vertex index {int(src.max() if src.max() >= n else src.min())}, "
            f"outside [0, {n - 1}]; indices are zero-based vertex numbers"
        )
    lam, phi = _pairs(basis, normalization)
    w = np.exp(-lam * tt[0])
    return phi @ (w[:, None] * phi[src].T) if src.ndim else phi @ (w * phi[src])


# ---------------------------------------------------------------------- HKS
def hks_times(basis: Eigenbasis, n_times: int = 100, *, normalization: str = "none"
              ) -> np.ndarray:
    """Return the default HKS times of Sun et al. (2009): log-spaced over the spectrum's range.

    ``t`` runs from ``4 ln 10 / lam_max`` to ``4 ln 10 / lam_1`` (``lam_1`` the first
    non-zero eigenvalue): at ``t_min`` the last eigenfunction's term has decayed to
    ``1e-4``, at ``t_max`` the first non-constant one's.

    Parameters
    ----------
    basis : Eigenbasis
        Only ``lam`` is used.
    n_times : int, default=100
        Number of times.
    normalization : {'none', 'area'}, default='none'
        ``'area'``: times for the shape scaled to unit area (in units of the area).

    Returns
    -------
    ndarray, shape (n_times,)
        Ascending.
    """
    lam = _eigenvalues(basis, normalization)
    return _hks_times(lam, check_int("n_times", n_times, min=1))


def _hks_times(lam: np.ndarray, n_times: int) -> np.ndarray:
    lam1 = _first_nonzero(lam)
    return np.geomspace(T_FACTOR / lam.max(), T_FACTOR / lam1, n_times)


def hks(basis: Eigenbasis, t: ArrayLike | None = None, *, n_times: int = 100,
        normalization: str = "none", scale: str = "none") -> np.ndarray:
    """Heat kernel signature ``HKS(x, t) = k_t(x, x) = sum_i exp(-lam_i t) phi_i(x)^2``.

    The heat that stays at ``x`` after time ``t`` (Sun, Ovsjanikov and Guibas 2009): small
    ``t`` sees the curvature near ``x``, large ``t`` the whole shape.  It is invariant to
    isometries (pose), rigid motions and the order of the vertices.

    Parameters
    ----------
    basis : Eigenbasis
        The ``N`` eigenpairs (:func:`cshape.eigenbasis`), all used.
    t : float or array_like, shape (T,), optional
        Positive times.  Default: ``n_times`` values from :func:`hks_times` (for the
        normalised eigenvalues).
    n_times : int, default=100
        Number of default times (ignored when ``t`` is given).
    normalization : {'none', 'area'}, default='none'
        ``'area'``: the HKS of the shape scaled to unit area (times in units of the area,
        values multiplied by it), invariant to scale.
    scale : {'none', 'trace'}, default='none'
        ``'trace'`` divides each column by the heat trace ``Z(t)`` (Sun et al.'s scaled HKS),
        so that it integrates to 1 over the surface (see the module notes).

    Returns
    -------
    ndarray, shape (n, T)
        ``HKS[x, j]`` at time ``t[j]``.

    Examples
    --------
    >>> import cshape
    >>> basis = cshape.eigenbasis(cshape.shapes.icosphere(3), N=16)
    >>> cshape.hks(basis).shape   # on the unit sphere ~ heat_trace / (4 pi)
    (642, 100)
    """
    n_times = check_int("n_times", n_times, min=1)
    scale = check_choice("scale", scale, ("none", "trace"))
    lam, phi = _pairs(basis, normalization)
    t = _hks_times(lam, n_times) if t is None else _check_scales("t", t)
    E = np.exp(-np.outer(lam, t))  # (N, T)
    out = np.square(phi) @ E
    if scale == "trace":
        out /= E.sum(axis=0)
    return out


# ---------------------------------------------------------------------- WKS
def wks_energies(basis: Eigenbasis, n_energies: int = 100, *, normalization: str = "none"
                 ) -> tuple[np.ndarray, float]:
    """Return the default WKS energies and width of Aubry et al. (2011).

    With ``e_1 = log lam_1`` (first non-zero) and ``e_N = log lam_max``, the step is
    ``delta = (e_N - e_1) / n_energies`` and ``sigma = 7 delta``; the energies are
    ``n_energies`` values evenly spaced over ``[e_1 + 2 sigma, e_N - 2 sigma]`` (not empty for
    ``n_energies >= 29``).

    Parameters
    ----------
    basis : Eigenbasis
        At least two distinct non-zero eigenvalues; only ``lam`` is used.
    n_energies : int, default=100
        At least 29 (``4 sigma`` must fit in the range).
    normalization : {'none', 'area'}, default='none'
        ``'area'``: energies of the shape scaled to unit area (``log(lam * area)``).

    Returns
    -------
    energies : ndarray, shape (n_energies,)
        Increasing log-energies ``e``.
    sigma : float
        Width of the band filter ``g`` in log-energy, ``7 delta``.
    """
    lam = _eigenvalues(basis, normalization)
    return _wks_energies(lam, check_int("n_energies", n_energies, min=1))


def _wks_energies(lam: np.ndarray, n_energies: int) -> tuple[np.ndarray, float]:
    e1, eN = np.log(_first_nonzero(lam)), np.log(lam.max())
    if not eN > e1:
        raise ValueError(
            "lam needs two distinct non-zero eigenvalues for the default WKS energies; "
            "compute more eigenpairs or pass energies= and sigma="
        )
    if 4 * WKS_WIDTH >= n_energies:
        raise ValueError(
            f"n_energies must be at least {int(4 * WKS_WIDTH) + 1} for the default width "
            f"sigma = {WKS_WIDTH:g} steps (the energies keep 2 sigma from both ends of the "
            f"spectrum), got {n_energies}; use more energies, or pass energies= and sigma="
        )
    sigma = WKS_WIDTH * (eN - e1) / n_energies
    return np.linspace(e1 + 2 * sigma, eN - 2 * sigma, n_energies), float(sigma)


def wks(basis: Eigenbasis, energies: ArrayLike | None = None, sigma: float | None = None, *,
        n_energies: int = 100, normalization: str = "none", scale: str = "trace"
        ) -> np.ndarray:
    """Wave kernel signature (Aubry, Schlickewei and Cremers 2011).

    ``WKS(x, e) = C_e sum_i phi_i(x)^2 g_i(e)``, ``g_i(e) = exp(-(e - log lam_i)^2 /
    (2 sigma^2))``, ``C_e = 1 / sum_i g_i(e)``: the probability of finding at ``x`` a quantum
    particle whose log-energy is distributed around ``e``.  A band-pass filter in
    ``log lam``, where the HKS is a low-pass one: it separates fine features better and
    sees the large scales less.  ``lam_0 = 0`` (the constant) is left out.

    Parameters
    ----------
    basis : Eigenbasis
        The ``N`` eigenpairs (:func:`cshape.eigenbasis`), all used.
    energies : float or array_like, shape (E,), optional
        Log-energies ``e``.  Default: :func:`wks_energies`.
    sigma : float, optional
        Width of ``g`` in log-energy.  Default: 7 energy steps (:func:`wks_energies`); must
        be given with explicit ``energies``.
    n_energies : int, default=100
        Number of default energies (ignored when ``energies`` is given).
    normalization : {'none', 'area'}, default='none'
        ``'area'``: the WKS of the shape scaled to unit area (energies ``log(lam area)``,
        values multiplied by the area), invariant to scale.
    scale : {'trace', 'none'}, default='trace'
        ``'trace'`` multiplies by ``C_e`` (each column integrates to 1 over the surface);
        ``'none'`` leaves it out.

    Returns
    -------
    ndarray, shape (n, E)
        ``WKS(x, e)``: one row per vertex, one column per energy.
    """
    n_energies = check_int("n_energies", n_energies, min=1)
    sigma = _check_positive("sigma", sigma)
    scale = check_choice("scale", scale, ("trace", "none"))
    lam, phi = _pairs(basis, normalization)
    if energies is None:
        energies, default_sigma = _wks_energies(lam, n_energies)
        sigma = default_sigma if sigma is None else sigma
    else:
        energies = _check_scales("energies", energies, positive=False)
        if sigma is None:
            raise ValueError(
                "sigma is required with explicit energies (the Gaussian width in log-energy); "
                "e.g. sigma = 7 * the step between energies, as in wks_energies"
            )
    keep = _nonzero(lam) if lam.max() > 0 else np.zeros(len(lam), bool)
    if not keep.any():
        raise ValueError("lam has no non-zero eigenvalue: the WKS needs log(lam_i)")
    G = np.exp(-np.square(energies[None, :] - np.log(lam[keep])[:, None]) / (2 * sigma**2))
    out = np.square(phi[:, keep]) @ G  # (n, E)
    if scale == "trace":
        total = G.sum(axis=0)
        if (total == 0).any():
            e = float(energies[np.flatnonzero(total == 0)[0]])
            raise ValueError(
                f"energies holds {e:.6g}, too far from every log(lam_i) (all the weights "
                f"exp(-(e - log lam_i)^2 / (2 sigma^2)) underflow to 0; log lam_i is "
                f"in [{np.log(lam[keep]).min():.4g}, {np.log(lam[keep]).max():.4g}]); "
                "choose energies in the spectrum's range or a larger sigma"
            )
        out /= total
    return out


# ---------------------------------------------------------------------- SI-HKS
def si_hks_tau(step: float = 1 / 8) -> np.ndarray:
    """Return the default log-time grid of :func:`si_hks`: ``t = 2^tau`` for a fixed ``tau``.

    The grid is fixed, not fitted to a spectrum (a grid that follows the spectrum would
    scale with the shape and hide what SI-HKS removes): ``tau`` from -24 to 16 in steps of
    ``step`` (``t`` from ``6e-8`` to ``6.6e4``), wide enough for shapes from about ``1e-2``
    to ``1e2`` units across with up to a few hundred eigenpairs.  The HKS varies smoothly in
    ``tau`` (over a few units), so a step of 1/8 samples it finely.

    Parameters
    ----------
    step : float, default=1/8
        Spacing of ``tau``.

    Returns
    -------
    ndarray, shape (40 / step + 1,)
        Increasing ``tau``, from -24 to 16.
    """
    step = check_real("step", step, positive=True)
    return np.arange(-24.0, 16.0 + step / 2, step)


def si_hks(basis: Eigenbasis, tau: ArrayLike | None = None, *, base: float = 2.0,
           n_freqs: int = 6) -> np.ndarray:
    """Scale-invariant HKS (Bronstein and Kokkinos 2010).

    Scaling a shape by ``s`` maps ``HKS(x, t)`` to ``HKS(x, t / s^2) / s^2``.  With
    ``t = base^tau`` on an even grid, ``log HKS`` is shifted in ``tau`` by ``2 log_base s``
    and offset by ``-2 log s``; the derivative in ``tau`` removes the offset and the modulus
    of its Fourier transform the shift:

    ``SI-HKS(x, w) = |FFT_tau( d/dtau log HKS(x, base^tau) )|(w)``, ``w = 0 .. n_freqs-1``.

    The derivative is computed exactly, ``d log HKS / d tau = -ln(base) t sum_i lam_i
    exp(-lam_i t) phi_i(x)^2 / HKS(x, t)``, rather than by a finite difference.

    The shift is removed exactly when the derivative is zero at both ends of the grid: with
    ``N`` eigenpairs the HKS is constant for ``t << 1 / lam_max`` (``sum_i phi_i(x)^2``)
    and for ``t >> 1 / lam_1`` (``phi_0^2 = 1 / area``), so the grid must reach past both
    (the default :func:`si_hks_tau` does for shapes of a size between about 0.01 and 100);
    a ``ValueError`` says when it does not.

    Parameters
    ----------
    basis : Eigenbasis
        The ``N`` eigenpairs (:func:`cshape.eigenbasis`) of a closed or Neumann problem
        (``lam_0 = 0``, so the HKS is positive everywhere).
    tau : array_like, shape (T,), optional
        Evenly spaced, increasing log-times.  Default: :func:`si_hks_tau` (``T = 321``).
    base : float, default=2.0
        ``t = base^tau``.
    n_freqs : int, default=6
        Number of low frequencies kept (the zero frequency included).

    Returns
    -------
    ndarray, shape (n, n_freqs)
        ``SI-HKS(x, w)``: one row per vertex, one column per frequency.
    """
    lam, phi = _pairs(basis, "none")
    base = check_real("base", base, positive=True)
    if base == 1.0:
        raise ValueError("base must differ from 1 (t = base^tau), got 1.0")
    n_freqs = check_int("n_freqs", n_freqs, min=1)
    tau = si_hks_tau() if tau is None else _check_scales("tau", tau, positive=False)
    if len(tau) < 3:
        raise ValueError(f"tau must hold at least 3 log-times, got {len(tau)}")
    d = np.diff(tau)
    if not (d > 0).all() or np.ptp(d) > 1e-9 * abs(d.mean()):
        raise ValueError("tau must be evenly spaced and increasing (e.g. np.arange(-8, 8, 1/16))")
    if n_freqs > len(tau) // 2:
        raise ValueError(
            f"n_freqs={n_freqs} is more than half the {len(tau) - 1} derivative samples; "
            f"use n_freqs <= {len(tau) // 2} or a finer tau"
        )
    t = np.power(base, tau)
    # d log HKS / d tau = ln(base) t d log HKS / dt = -ln(base) t (P @ (lam E)) / (P @ E),
    # P = phi^2, E = exp(-(lam - lam_0) t) (the common factor exp(-lam_0 t) cancels: no
    # overflow, and the slowest term never underflows); exact, no finite difference.
    E = np.exp(-np.outer(lam - lam.min(), t))
    EE = np.hstack([E, lam[:, None] * E])
    T = len(t)
    out = np.empty((phi.shape[0], n_freqs))
    edge = peak = 0.0
    for a in range(0, phi.shape[0], _ROWS):
        S = np.square(phi[a:a + _ROWS]) @ EE
        if not (S[:, :T] > 0).all():
            raise ValueError(
                "the HKS vanishes at some vertices (every eigenfunction is zero there, e.g. "
                "fixed vertices with bc='dirichlet'); SI-HKS needs bc='neumann' or a closed "
                "surface"
            )
        dlog = (-np.log(base) * t) * (S[:, T:] / S[:, :T])
        edge = max(edge, float(np.abs(dlog[:, [0, -1]]).max()))
        peak = max(peak, float(np.abs(dlog).max()))
        out[a:a + _ROWS] = np.abs(np.fft.rfft(dlog, axis=1)[:, :n_freqs])
    if edge > 1e-3 * max(peak, np.finfo(float).tiny):
        raise ValueError(
            "tau does not cover the HKS's whole decay (d log HKS / d tau is not ~0 at both "
            f"ends: {edge:.3g}); widen tau to t from well below 1/lam_max = "
            f"{1 / lam.max():.3g} to well above 1/lam_1"
        )
    return out


#: Rows (vertices) per block in :func:`si_hks`, which needs (rows, 2 T) floats at a time.
_ROWS = 4096


# ---------------------------------------------------------------------- matching
def _as_signature(x: ArrayLike, name: str) -> np.ndarray:
    a = _as_real_2d(x, name)
    if a.ndim == 1:
        a = a[:, None]
    if a.ndim != 2 or a.shape[0] == 0:
        raise ValueError(
            f"{name} must have shape (n, n_scales) (one row per vertex), got {a.shape}"
        )
    if not np.isfinite(a).all():
        raise ValueError(f"{name} contains NaN or infinite values")
    return a


def match_points(sig_a: ArrayLike, sig_b: ArrayLike, *, mutual: bool = False) -> np.ndarray:
    """Match every vertex of shape a to the vertex of shape b with the nearest signature.

    The distance is Euclidean over the columns (scales); transform the signatures first to
    weight them (e.g. :func:`hks` with ``scale='trace'`` and log-spaced times is Sun
    et al.'s distance; ``np.log`` of it weighs the scales equally).

    Parameters
    ----------
    sig_a : array_like, shape (n_a, k) or (n_a,)
        Signatures of shape a, one row per vertex.
    sig_b : array_like, shape (n_b, k) or (n_b,)
        Signatures at the same scales.
    mutual : bool, default=False
        Keep only mutual nearest neighbours (``a -> b -> a`` returns to the same vertex);
        the others get ``-1``.

    Returns
    -------
    ndarray of int64, shape (n_a,)
        ``match[i]`` is the vertex of b matched to vertex ``i`` of a (or -1).
    """
    a = _as_signature(sig_a, "sig_a")
    b = _as_signature(sig_b, "sig_b")
    mutual = check_bool("mutual", mutual)
    if a.shape[1] != b.shape[1]:
        raise ValueError(
            f"sig_a has {a.shape[1]} scales and sig_b {b.shape[1]}; compute both at the same "
            "times or energies"
        )
    ab = nearest_rows(a, b)
    if not mutual:
        return ab
    ba = nearest_rows(b, a)
    return np.where(ba[ab] == np.arange(len(a)), ab, -1)
