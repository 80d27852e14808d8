"""The :class:`Descriptor`: which descriptor to compute from a Shape-DNA, as one frozen value.

A descriptor is a recipe of five fields, checked once when it is made:

* ``kind``          - what is computed (Section 3.1 of the paper, and two beyond it):
                      ``'shape-dna'``, ``'truncated'``, ``'cshape'``, ``'cshape-complex'``,
                      ``'f1'``, ``'truncated-log'``, ``'two-scale'`` (the table of
                      :class:`Descriptor`);
* ``N``, ``M``      - the Shape-DNA length and the crop half-width (``2M+1`` values); the
                      one M-versus-N rule is :func:`cshape._checks.check_crop`;
* ``transform``     - the cShape-DNA transform (:func:`cshape.compact_shape_dna`);
* ``normalization`` - the scale normalisation (:func:`cshape.normalize`).

It knows its :attr:`~Descriptor.size` and its :attr:`~Descriptor.label`, and builds a
:meth:`~Descriptor.row` from one spectrum, or the :meth:`~Descriptor.matrix` of many (a
:class:`cshape.DescriptorTable` leaves out, with a warning, the shapes it cannot describe).
Two are shipped: :data:`PAPER`, the paper's cShape-DNA (Eq. 8-10, ``M = 16`` of ``N = 100``,
area-normalised), and :data:`DEFAULT`, the exploration
default that tables, the index, the figures and the command line compare when no descriptor
is given.

>>> from cshape import PAPER, DEFAULT
>>> PAPER.label
"paper's cShape-DNA (M=16 of N=100, 33 values)"
>>> DEFAULT.label, DEFAULT.size
('two-scale log spectrum (9 first + 99 detrended values)', 108)
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._checks import check_choice, check_crop, check_int, check_spectrum
from .formulas import (
    NORMALIZATIONS,
    TRANSFORMS,
    TREND_DEGREE,
    ZERO_RTOL,
    _compact,
    _detrend,
    _f1_feature,
    _log_weyl_ratio,
    _log_weyl_sequence,
    _normalize,
    real_form,
)
from .formulas import _zero_modes as _leading_zero_modes

__all__ = [
    "DEFAULT",
    "PAPER",
    "Descriptor",
]

#: The descriptor kinds (the table of :class:`Descriptor`).
DESCRIPTOR_KINDS = ("shape-dna", "truncated", "cshape", "cshape-complex", "f1", "truncated-log",
                    "two-scale")
#: Weight of the detrended block of the kind 'two-scale' (its row is
#: ``(r_1 .. r_{2M+1}, TWO_SCALE_WEIGHT * detrend(r_1 .. r_{N-1}))``), chosen with
#: :data:`DEFAULT` from a grid of round numbers.
TWO_SCALE_WEIGHT = 2.0

_NORMALISED = {"weyl": "Weyl-normalised", "fiedler": "lam_1-normalised",
               "none": "eigenvalues as given"}
_TRANSFORM_NAMES = {"weyl": "paper's cShape-DNA", "log-weyl": "log-Weyl DFT cShape-DNA",
                    "log-weyl-dct": "log-Weyl DCT cShape-DNA"}


@dataclass(frozen=True, init=False)
class Descriptor:
    """A descriptor recipe: kind, ``N``, ``M``, transform and normalisation, checked once.

    The four descriptors of the paper's Section 3.1, and two beyond it:

    ================ ============ =========================================================
    kind             row length   definition
    ================ ============ =========================================================
    'shape-dna'      N            normalised Shape-DNA: ``lam[:N] * area`` (Section 2.1)
    'truncated'      2M+1         the first ``2M+1`` values of the normalised Shape-DNA
                                  (Fig. 5 a-e: "the first 33, 17, 9, 5 and 3 eigenvalues")
    'cshape'         2M+1         cShape-DNA of ``lam[:N]`` (Eq. 8-10, or the ``transform``
                                  given) in its real form (``cshape.descriptors.real_form``:
                                  same Euclidean distances)
    'cshape-complex' 2M+1         the cShape-DNA as :func:`cshape.compact_shape_dna` returns
                                  it (complex for the DFT transforms, real for the DCT)
    'f1'             N-2          F1 feature ``lam_1 / lam_i`` of ``lam[:N]`` (Fig. 5f)
    'truncated-log'  2M+1         the first ``2M+1`` log-Weyl ratios ``r_1 .. r_{2M+1}``
                                  (:func:`cshape.descriptors.log_weyl_ratio`; needs ``2M+2``
                                  eigenvalues).  Its distances equal those of the truncated
                                  *log spectrum* ``log lam_1^norm .. log lam_{2M+1}^norm``:
                                  ``log 4 pi i`` is the same for every shape
    'two-scale'      2M+1 + N-1   ``r_1 .. r_{2M+1}`` beside ``2 * detrend(r_1 .. r_{N-1})``
                                  (:func:`cshape.descriptors.detrend`: the ratios less
                                  their least-squares cubic in ``i``); :data:`DEFAULT`
    ================ ============ =========================================================

    ``2M+1`` values must fit in ``N`` eigenvalues (the ``N-1`` log-Weyl ratios for
    'truncated-log' and the log-Weyl transforms).

    **Meshes of several pieces** (``k`` components, ``k`` zero eigenvalues), by kind:
    'shape-dna', 'truncated' and 'cshape' with the paper's ``transform='weyl'`` take the
    spectrum as it is, its ``k`` zeros included (Eq. 8 needs no logarithm).
    'truncated-log', the log-Weyl transforms and 'f1' drop the ``k`` zero modes and index
    the rest from 1 (``mu_i = lam_{k-1+i}``, normalised by the total area: Weyl's law of
    the disjoint union; :func:`cshape.descriptors.formulas.nonzero_eigenvalues`): 'truncated-log' is
    ``r_1 .. r_{2M+1}`` of ``mu`` (needs ``N >= 2M+1+k``), the log-Weyl transforms extend
    the ``N-k`` ratios to ``N-1`` by Weyl's law (``r_i = r_{N-k}``) and need ``2M+1``
    measured ones, 'f1' is ``mu_1 / mu_i`` for ``i = 2..N-1``, extended the same way
    (``mu_i = mu_{N-k} i / (N-k)``), and needs two.  A row without enough non-zero
    eigenvalues cannot be described: :meth:`matrix` names them and says why.

    Parameters
    ----------
    kind : {'shape-dna', 'truncated', 'cshape', 'cshape-complex', 'f1', 'truncated-log', \
'two-scale'}, default='cshape'
        What is computed, as in the table above.
    N : int, default=100
        Shape-DNA length: the eigenvalues ``lam_0 .. lam_{N-1}`` used (keyword only).
    M : int, default=16
        Crop half-width: ``2M+1`` values for 'truncated', 'truncated-log' and the 'cshape'
        kinds (the others do not use it; keyword only).
    transform : {'weyl', 'log-weyl', 'log-weyl-dct'}, default='weyl'
        The cShape-DNA transform of the 'cshape' kinds (:func:`cshape.compact_shape_dna`).
    normalization : {'area', 'fiedler', 'weyl', 'none'}, default='area'
        Scale normalisation (:func:`cshape.normalize`; ``'none'``: the eigenvalues are
        normalised already and used as given).  'f1' is scale invariant and ignores it.

    Raises
    ------
    TypeError
        A mode that is not a string, ``N`` or ``M`` not an integer.
    ValueError
        An unknown mode, ``N < 1``, ``M < 0``, or ``2M+1`` more values than the kind's
        sequence holds (:func:`cshape._checks.check_crop`: ``N`` eigenvalues for
        'truncated' and the paper's transform, the ``N-1`` log-Weyl ratios for
        'truncated-log' and the log-Weyl transforms).

    Examples
    --------
    >>> from cshape import Descriptor
    >>> d = Descriptor("cshape", N=50, M=8, transform="log-weyl-dct")
    >>> d.size, d.label
    (17, 'log-Weyl DCT cShape-DNA (M=8 of N=50, 17 values)')
    >>> d.replace(M=4).size
    9
    """

    kind: str = "cshape"
    N: int = 100
    M: int = 16
    transform: str = "weyl"
    normalization: str = "area"

    def __init__(self, kind: str = "cshape", *, N: int = 100, M: int = 16,
                 transform: str = "weyl", normalization: str = "area") -> None:
        kind = check_choice("kind", kind, DESCRIPTOR_KINDS)
        transform = check_choice("transform", transform, TRANSFORMS)
        normalization = check_choice("normalization", normalization, NORMALIZATIONS)
        N = check_int("N", N, min=1)
        M = check_int("M", M, min=0)
        if kind == "truncated":
            check_crop(M, N)
        elif kind == "truncated-log":
            check_crop(M, N, log=True)
        elif kind == "two-scale":
            check_crop(M, N, log=True)
            if N - 1 < TREND_DEGREE + 2:
                raise ValueError(
                    f"kind='two-scale' detrends the N-1 log-Weyl ratios by a polynomial of "
                    f"degree {TREND_DEGREE}, which needs N >= {TREND_DEGREE + 3}, got N = {N}; "
                    "compute more eigenvalues or use kind='truncated-log'")
        elif kind in ("cshape", "cshape-complex"):
            check_crop(M, N, log=transform != "weyl")
        for name, value in (("kind", kind), ("N", N), ("M", M), ("transform", transform),
                            ("normalization", normalization)):
            object.__setattr__(self, name, value)  # the checked, current spelling

    # ------------------------------------------------------------------ what it is
    @property
    def size(self) -> int:
        """Number of values of a row.

        ``N`` for 'shape-dna', ``N - 2`` for 'f1', ``2M+1 + N-1`` for 'two-scale', else
        ``2M+1`` (complex numbers counted once, as the paper does).
        """
        return {"shape-dna": self.N, "f1": self.N - 2,
                "two-scale": 2 * self.M + 1 + self.N - 1}.get(self.kind, 2 * self.M + 1)

    @property
    def label(self) -> str:
        """What the descriptor compares, in words (query headers, figure titles, summaries).

        The normalisation is named when it is not the paper's (the area).

        >>> Descriptor("truncated-log", M=8, normalization="weyl").label
        'truncated log spectrum, Weyl-normalised (17 values)'
        """
        size = self.size
        if self.kind in ("cshape", "cshape-complex"):
            base = f"{_TRANSFORM_NAMES[self.transform]} (M={self.M} of N={self.N}, {size} values)"
        elif self.kind == "shape-dna":
            base = f"Shape-DNA ({size} values)"
        elif self.kind == "f1":
            return f"F1 (N={self.N}, {size} values)"  # scale invariant: no normalisation
        elif self.kind == "truncated":
            base = f"truncated Shape-DNA ({size} values)"
        elif self.kind == "two-scale":
            base = (f"two-scale log spectrum ({2 * self.M + 1} first + {self.N - 1} detrended "
                    "values)")
        else:
            base = f"truncated log spectrum ({size} values)"
        if self.normalization == "area":
            return base
        head, _, tail = base.partition(" (")
        return f"{head}, {_NORMALISED[self.normalization]} ({tail}"

    @property
    def needs_area(self) -> bool:
        """Whether a row needs the shape's surface area (``normalization='area'``, not F1)."""
        return self.kind != "f1" and self.normalization == "area"

    @property
    def min_eigenvalues(self) -> int:
        """Eigenvalues a spectrum needs.

        ``2M+1`` ('truncated'), ``2M+2`` ('truncated-log'), else ``N``.
        """
        return {"truncated": 2 * self.M + 1, "truncated-log": 2 * self.M + 2}.get(self.kind,
                                                                               self.N)

    def replace(self, **changes: Any) -> Descriptor:
        """Return a copy with some fields changed (checked again).

        Parameters
        ----------
        **changes
            New values of fields (``kind``, ``N``, ``M``, ``normalization``, ...).

        Returns
        -------
        Descriptor
            The copy; the constructor checks its fields as for a new descriptor.
        """
        fields = {**dataclasses.asdict(self), **changes}
        return Descriptor(fields.pop("kind"), **fields)

    def for_N(self, N: int) -> Descriptor:
        """Return the same descriptor for spectra of ``N`` eigenvalues.

        ``N`` is replaced and ``M`` lowered to the largest the kind allows (the label says so).

        Parameters
        ----------
        N : int
            Length of the spectra to describe.

        Returns
        -------
        Descriptor
            The descriptor with this ``N``.

        Raises
        ------
        ValueError
            If ``N`` is too small for any ``M`` of the kind.
        """
        N = check_int("N", N, min=1)
        top = {"truncated-log": (N - 2) // 2, "two-scale": (N - 2) // 2,
               "truncated": (N - 1) // 2,
               "cshape": (N - 1) // 2 if self.transform == "weyl" else (N - 2) // 2,
               "cshape-complex": (N - 1) // 2 if self.transform == "weyl" else (N - 2) // 2,
               }.get(self.kind, self.M)
        least = TREND_DEGREE + 3 if self.kind == "two-scale" else 2
        if top < 0 or N < least:
            raise ValueError(f"the descriptor {self.label!r} needs at least {least} "
                             f"eigenvalues per shape, got N = {N}")
        return self.replace(N=N, M=min(self.M, top))

    # ------------------------------------------------------------------ rows
    def row(self, lam: ArrayLike, area: float | None = None,
            zero_modes: int | None = None) -> NDArray[Any]:
        """Return the descriptor of one shape.

        Parameters
        ----------
        lam : array_like, shape (n,)
            Ascending eigenvalues, ``lam_0`` first; ``n >=`` :attr:`min_eigenvalues`.
        area : float, optional
            Surface area; needed when :attr:`needs_area`.
        zero_modes : int, optional
            Zero eigenvalues of the shape (its connected components); default: counted
            (:func:`cshape.descriptors.count_zero_modes`).

        Returns
        -------
        ndarray, shape (:attr:`size`,)
            Float64, or complex128 for 'cshape-complex' with a DFT transform.

        Raises
        ------
        ValueError
            The spectrum cannot be described (too few eigenvalues or non-zero ones, not
            ascending, a missing or bad area).
        """
        r = np.asarray(lam, dtype=np.float64)
        if r.ndim != 1 or len(r) < self.min_eigenvalues:
            raise ValueError(
                f"lam has shape {r.shape} but kind={self.kind!r} needs at least "
                f"{self.min_eigenvalues} eigenvalues per shape; compute more eigenvalues or "
                "lower N / M")
        if self.needs_area and area is None:
            raise ValueError(f"kind={self.kind!r} with normalization='area' needs the "
                             "surface area: pass area=")
        return self._row(r, area if self.needs_area else None, zero_modes)

    def _row(self, r: NDArray[np.float64], area: float | None, k: int | None
             ) -> NDArray[Any]:
        """One descriptor of a spectrum, checked here once; ValueError if it cannot be described."""
        kind, M, N, norm = self.kind, self.M, self.N, self.normalization
        r = check_spectrum(r, "lam", min_len=2 if kind == "f1" else 1)
        if k is not None:
            k = check_int("zero_modes", k, min=0)
        if kind == "shape-dna":
            return _normalize(r[:N], area, norm)
        if kind == "truncated":
            return _normalize(r[: 2 * M + 1], area, norm)
        if kind == "f1":
            return _f1_feature(r[:N], k, N - 2)
        if kind == "truncated-log":  # r_1 .. r_{2M+1} of the eigenvalues after the zero modes
            k0 = (_leading_zero_modes(r, None, ZERO_RTOL * float(np.abs(r).max()))
                  if k is None else k)
            kk = max(k0, 1)
            if len(r) - kk < 2 * M + 1:
                raise ValueError(
                    f"{kk} of its {len(r)} eigenvalues are zero modes (a mesh of {kk} "
                    f"components): {len(r) - kk} non-zero ones are left and 2M+1 = "
                    f"{2 * M + 1} are needed (compute N >= {2 * M + 1 + kk} eigenvalues, or "
                    f"use M <= {max(len(r) - kk - 1, 0) // 2})")
            lam_norm = _normalize(r[: 2 * M + 1 + kk], area, norm)
            return _log_weyl_ratio(lam_norm, k0, None)
        if kind == "two-scale":  # r_1 .. r_{2M+1} beside the detrended r_1 .. r_{N-1}
            seq = _log_weyl_sequence(_normalize(r[:N], area, norm), M, k, "kind='two-scale'")
            return np.concatenate([seq[: 2 * M + 1], TWO_SCALE_WEIGHT * _detrend(seq)])
        S = _compact(_normalize(r[:N], area, norm), M, k, self.transform)
        return S if kind == "cshape-complex" else real_form(S)

    def _rows(self, lams: ArrayLike | Sequence[ArrayLike], areas: ArrayLike | None = None,
             zero_modes: ArrayLike | None = None) -> tuple[NDArray[Any], dict[int, str]]:
        """Return the descriptors of the shapes that can be described, and why the others cannot.

        Parameters
        ----------
        lams : array_like, shape (p, n), or sequence of p 1-D arrays
            Ascending eigenvalues of each shape (ragged rows allowed), each with at least
            :attr:`min_eigenvalues` values.
        areas : array_like, shape (p,), optional
            Surface areas; needed when :attr:`needs_area`.
        zero_modes : array_like of int, shape (p,), optional
            Zero eigenvalues of each shape; a negative entry: counted from its eigenvalues.

        Returns
        -------
        X : ndarray, shape (q, size)
            The rows that can be described, in order (``q = 0``: shape ``(0, 0)``).
        problems : dict of int to str
            ``{row: reason}`` of the others.

        Raises
        ------
        ValueError
            Errors of the arguments: ``lams`` empty or of a short row, ``areas`` missing or
            of the wrong length, ``zero_modes`` not one integer per row.
        """
        rows, a, zm = self._prepare(lams, areas, zero_modes)
        out: list[NDArray[Any]] = []
        problems: dict[int, str] = {}
        for i, r in enumerate(rows):
            try:
                out.append(self._row(r, a[i], zm[i]))
            except ValueError as exc:
                problems[i] = str(exc)
        if not out:
            return np.zeros((0, 0)), problems
        return np.vstack(out), problems

    def matrix(self, lams: ArrayLike | Sequence[ArrayLike], areas: ArrayLike | None = None,
               zero_modes: ArrayLike | None = None,
               names: Sequence[str] | None = None) -> NDArray[Any]:
        """Return the descriptors of many shapes, one row per shape; all must be describable.

        Parameters
        ----------
        lams : array_like, shape (p, n), or sequence of p 1-D arrays
            Ascending eigenvalues of each shape (ragged rows allowed), each with at least
            :attr:`min_eigenvalues` values.
        areas : array_like, shape (p,), optional
            Surface areas; needed when :attr:`needs_area`.
        zero_modes : array_like of int, shape (p,), optional
            Zero eigenvalues of each shape; a negative entry: counted from its eigenvalues.
        names : sequence of str, optional
            Names of the ``p`` shapes, for the message of those that cannot be described.

        Returns
        -------
        X : ndarray, shape (p, size)
            Row ``i``: the descriptor of shape ``i`` (:meth:`row`).

        Raises
        ------
        ValueError
            ``lams`` empty or of a short row, ``areas`` missing or of the wrong length,
            ``zero_modes`` not one integer per row; and when some shapes cannot be described
            (all named, with the reason).
        """
        X, problems = self._rows(lams, areas, zero_modes)
        p = len(X) + len(problems)
        labels = _row_names(names, p)
        if problems:
            shown = "; ".join(f"{labels[i]}: {m}" for i, m in list(problems.items())[:5])
            more = f"; and {len(problems) - 5} more" if len(problems) > 5 else ""
            raise ValueError(
                f"kind={self.kind!r} cannot describe {len(problems)} of {p} shapes "
                f"({shown}{more}); leave them out (a DescriptorTable leaves them out "
                "with a warning: table.described) or choose another kind")
        return X

    def _prepare(self, lams: ArrayLike | Sequence[ArrayLike], areas: ArrayLike | None,
                 zero_modes: ArrayLike | None
                 ) -> tuple[list[np.ndarray], list[float | None], list[int | None]]:
        """Check and return the rows, areas (None where unused) and zero modes (None: count)."""
        if isinstance(lams, np.ndarray) and lams.ndim == 2:
            rows = list(np.asarray(lams, dtype=np.float64))
        elif isinstance(lams, np.ndarray) or not hasattr(lams, "__len__"):
            raise ValueError(
                "lams must be a (p, n) array or a sequence of p 1-D eigenvalue arrays, got "
                f"{type(lams).__name__} of shape {np.shape(lams)}")
        else:
            rows = [np.asarray(r, dtype=np.float64)
                    for r in cast("Sequence[ArrayLike]", lams)]
        p = len(rows)
        if p == 0:
            raise ValueError("lams is empty; it needs the eigenvalues of at least one shape")
        need = self.min_eigenvalues
        for i, r in enumerate(rows):
            if r.ndim != 1 or len(r) < need:
                raise ValueError(
                    f"lams[{i}] has shape {r.shape} but kind={self.kind!r} needs at least "
                    f"{need} eigenvalues per shape; compute more eigenvalues or lower N / M")
        return rows, self._areas(areas, p), _zero_modes(zero_modes, p)

    def _areas(self, areas: ArrayLike | None, p: int) -> list[float | None]:
        if not self.needs_area:
            return [None] * p
        if areas is None:
            raise ValueError(
                f"kind={self.kind!r} with normalization='area' needs areas (one surface area "
                "per shape); pass areas=np.ones(p) if lams are already normalised, or "
                "normalization='weyl'")
        a = np.asarray(areas, dtype=np.float64).reshape(-1)
        if len(a) != p:
            raise ValueError(f"areas has {len(a)} entries but lams has {p} rows")
        return [float(x) for x in a]


def _zero_modes(zero_modes: ArrayLike | None, p: int) -> list[int | None]:
    if zero_modes is None:
        return [None] * p
    z = np.asarray(zero_modes).reshape(-1)
    if len(z) != p or not np.issubdtype(z.dtype, np.integer):
        raise ValueError(
            f"zero_modes must hold one integer per row ({p}), got {np.shape(zero_modes)} "
            f"of {z.dtype}")
    return [None if x < 0 else int(x) for x in z]


def _row_names(names: Sequence[Any] | None, p: int) -> list[str]:
    if names is None:
        return [f"row {i}" for i in range(p)]
    names = [str(n) for n in names]
    if len(names) != p:
        raise ValueError(f"names has {len(names)} entries but lams has {p} rows")
    return names


#: The paper's cShape-DNA: Eq. (8)-(10), ``M = 16`` of ``N = 100``, area-normalised (the
#: default of :func:`cshape.compact_shape_dna`): ``--kind cshape`` on the command line.
PAPER = Descriptor("cshape", N=100, M=16, transform="weyl", normalization="area")

#: The exploration default: what a :class:`cshape.DescriptorTable`, a
#: :class:`cshape.DescriptorIndex`, the figures of a collection and the command line compare
#: when no descriptor is given (at the table's ``N``: :meth:`Descriptor.for_N`).  The
#: two-scale log spectrum of the area-normalised eigenvalues: the first nine log-Weyl ratios
#: ``r_i = log(lam_i * area / (4 pi i))`` of the eigenvalues after the zero modes, beside twice
#: the ratios ``r_1 .. r_99`` less their least-squares cubic in ``i``.  How it was chosen (the
#: smallest worst regret over three real collections and the generated suite,
#: ``benchmarks/bench_real_collections.py``): the guide "Choosing a descriptor"
#: (``docs/guides/choosing-a-descriptor.md``).
DEFAULT = Descriptor("two-scale", N=100, M=4, transform="weyl", normalization="area")


def check_descriptor(name: str, descriptor: object, N: int) -> Descriptor:
    """Return ``descriptor`` checked, or :data:`cshape.DEFAULT` for ``N`` eigenvalues if None.

    The one rule of the surfaces that take ``descriptor=`` (tables, the index, the
    figures); the error names ``name`` and, for a kind given by name, the fix.
    """
    if descriptor is None:
        return DEFAULT.for_N(N)
    if not isinstance(descriptor, Descriptor):
        hint = (f" (a kind: Descriptor({descriptor!r}, N=...))"
                if isinstance(descriptor, str) else "")
        raise TypeError(f"{name} must be a cshape.Descriptor (e.g. cshape.PAPER) or None "
                        f"(cshape.DEFAULT), got {type(descriptor).__name__}{hint}")
    return descriptor
