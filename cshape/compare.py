"""Stage 5 of the pipeline: comparing descriptors (Section 3 of the paper).

* :func:`descriptor_matrix`  - one descriptor per row, for the four kinds the paper compares:
                               normalised Shape-DNA (``N`` values), truncated Shape-DNA
                               (first ``2M+1`` values), cShape-DNA (``2M+1`` reals, with any
                               ``transform`` of :func:`cshape.compact_shape_dna`) and F1, and
                               the truncated log-Weyl ratio (beyond the paper);
* :func:`distance_matrix`    - Euclidean distances between rows (Section 3.1);
* :func:`scale_255`          - a distance matrix scaled to ``[0, 255]`` (Fig. 3 a-b);
* :func:`difference_matrix`, :func:`scaled_difference` - the absolute difference of two scaled
                               matrices and its mean and standard deviation (Fig. 3c, 6, 7);
* :func:`retrieval_scores`   - nearest neighbour, first and second tier, E-measure, DCG and
                               mean average precision (Princeton Shape Benchmark definitions);
* :func:`mds_embedding`      - 2-D multidimensional scaling coordinates (Fig. 4-5; drawn by
                               :func:`cshape.plots.plot_mds`).

Exact nearest-neighbour queries against a large database: :class:`cshape.index.DescriptorIndex`.

Every function takes and returns plain NumPy arrays.
"""

from __future__ import annotations

from collections.abc import Hashable, Sequence
from typing import Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._checks import (
    check_bool,
    check_choice,
    check_descriptors,
    check_int,
    check_labels,
    check_square,
)
from .descriptors import (
    NORMALIZATIONS,
    TRANSFORMS,
    compact_shape_dna,
    count_zero_modes,
    f1_feature,
    log_weyl_ratio,
    normalize,
    real_form,
)

__all__ = [
    "DEFAULT_DESCRIPTOR",
    "DEFAULT_KIND",
    "DEFAULT_M",
    "DEFAULT_NORMALIZATION",
    "DEFAULT_TRANSFORM",
    "DESCRIPTOR_KINDS",
    "PAPER_DESCRIPTOR",
    "default_descriptor",
    "descriptor_label",
    "descriptor_matrix",
    "descriptor_rows",
    "descriptor_size",
    "difference_matrix",
    "distance_matrix",
    "mds_embedding",
    "retrieval_per_query",
    "retrieval_scores",
    "row_problems",
    "scale_255",
    "scaled_difference",
]

#: The descriptor kinds of :func:`descriptor_matrix`.
DESCRIPTOR_KINDS = ("shape-dna", "truncated", "cshape", "cshape-complex", "f1", "truncated-log")

#: The E-measure of the Princeton Shape Benchmark looks at the first 32 results.
E_MEASURE_DEPTH = 32

#: The exploration default: the descriptor that :meth:`cshape.DescriptorTable.descriptors`
#: and ``.distance_matrix()`` with no kind, :class:`cshape.DescriptorIndex`, ``cshape query``,
#: ``cshape describe``'s summary, the MDS of one's own collection and lesson 06 compare.
#: Chosen on the development instances of the benchmark suite (category, instance and
#: resolution level) by its *worst* first tier; see ``benchmarks/results/suite.md``.
DEFAULT_KIND = "truncated-log"
#: Its crop half-width: ``2M+1`` values.
DEFAULT_M = 8
#: Its transform (used by the 'cshape' kinds only).
DEFAULT_TRANSFORM = "weyl"
#: Its scale normalisation (:func:`cshape.normalize`): divide by ``lam_1``, so the row is
#: ``log(lam_i / lam_1) - log(4 pi i)``, ``i = 1 .. 2M+1`` (no area: a coarse mesh's area is
#: a little off, and in log space any normalisation is one shift of the whole row).
DEFAULT_NORMALIZATION = "fiedler"
#: The default as keyword arguments of :func:`descriptor_matrix` (see :func:`default_descriptor`).
DEFAULT_DESCRIPTOR = {"kind": DEFAULT_KIND, "M": DEFAULT_M, "transform": DEFAULT_TRANSFORM,
                      "normalization": DEFAULT_NORMALIZATION}
#: The paper's cShape-DNA (Eq. 8-10, ``M = 16`` of ``N = 100``, area-normalised): ``--kind
#: cshape`` everywhere.
PAPER_DESCRIPTOR = {"kind": "cshape", "M": 16, "transform": "weyl", "normalization": "area"}


# --------------------------------------------------------------------------- descriptors
def descriptor_size(kind: str, M: int = 16, N: int = 100) -> int:
    """Number of values of a descriptor of the given kind (its storage, in numbers).

    Parameters
    ----------
    kind : {'shape-dna', 'truncated', 'cshape', 'cshape-complex', 'f1', 'truncated-log'}
    M, N : int
        See :func:`descriptor_matrix`.

    Returns
    -------
    int
        ``N`` for 'shape-dna', ``2M+1`` for 'truncated', 'truncated-log', 'cshape' and
        'cshape-complex' (complex numbers counted once, as the paper does; the same for
        every transform), ``N - 2`` for 'f1' (for every mesh: see
        :func:`descriptor_matrix` for meshes of several pieces).
    """
    kind = _check_kind(kind)
    M = check_int("M", M, min=0)
    N = check_int("N", N, min=1)
    return {"shape-dna": N, "truncated": 2 * M + 1, "cshape": 2 * M + 1,
            "cshape-complex": 2 * M + 1, "f1": N - 2, "truncated-log": 2 * M + 1}[kind]


def default_descriptor(N: int = 100) -> dict[str, Any]:
    """The exploration default (:data:`DEFAULT_DESCRIPTOR`) for shapes with ``N`` eigenvalues.

    Parameters
    ----------
    N : int, default=100
        Eigenvalues available per shape.  With fewer than the default needs, ``M`` is
        lowered to the largest the kind allows (the label says so).

    Returns
    -------
    dict
        ``{'kind', 'M', 'N', 'transform', 'normalization'}``, keyword arguments of
        :func:`descriptor_matrix`.
    """
    N = check_int("N", N, min=1)
    kind, M, tr = DEFAULT_KIND, DEFAULT_M, DEFAULT_TRANSFORM
    top = {"truncated-log": (N - 2) // 2, "truncated": (N - 1) // 2,
           "cshape": (N - 1) // 2 if tr == "weyl" else (N - 2) // 2}.get(kind, M)
    if top < 0:
        raise ValueError(f"the default descriptor ({kind!r}) needs at least 2 eigenvalues "
                         f"per shape, got N = {N}")
    return {"kind": kind, "M": min(M, top), "N": N, "transform": tr,
            "normalization": DEFAULT_NORMALIZATION}


def descriptor_label(kind: str, M: int = 16, N: int = 100, transform: str = "weyl",
                     normalization: str = "area") -> str:
    """What a descriptor compares, in words, e.g. for a query header or a figure title.

    The normalisation is named when it is not the paper's (the area).

    >>> descriptor_label("truncated-log", M=16)
    'truncated log spectrum (33 values)'
    >>> descriptor_label("truncated-log", M=8, normalization="weyl")
    'truncated log spectrum, Weyl-normalised (17 values)'
    >>> descriptor_label("cshape", M=16, N=100)
    "paper's cShape-DNA (M=16 of N=100, 33 values)"
    """
    kind = _check_kind(kind)
    norm = check_choice("normalization", normalization, NORMALIZATIONS)
    size = 2 * M + 1
    if norm != "area" and kind != "f1":
        name = {"weyl": "Weyl-normalised", "fiedler": "lam_1-normalised"}[norm]
        base = descriptor_label(kind, M=M, N=N, transform=transform)
        head, _, tail = base.partition(" (")
        return f"{head}, {name} ({tail}"
    if kind in ("cshape", "cshape-complex"):
        name = {"weyl": "paper's cShape-DNA", "log-weyl": "log-Weyl DFT cShape-DNA",
                "log-weyl-dct": "log-Weyl DCT cShape-DNA"}[check_choice(
                    "transform", transform, TRANSFORMS)]
        return f"{name} (M={M} of N={N}, {size} values)"
    if kind == "shape-dna":
        return f"Shape-DNA ({N} values)"
    if kind == "f1":
        return f"F1 (N={N}, {N - 2} values)"
    if kind == "truncated":
        return f"truncated Shape-DNA ({size} values)"
    return f"truncated log spectrum ({size} values)"


def _check_kind(kind: object) -> str:
    return check_choice("kind", kind, DESCRIPTOR_KINDS)


def descriptor_matrix(lams: ArrayLike | Sequence[ArrayLike], areas: ArrayLike | None = None,
                      kind: str = "cshape", M: int = 16, N: int = 100, *,
                      normalization: str = "area", transform: str = "weyl",
                      zero_modes: ArrayLike | None = None,
                      names: Sequence[str] | None = None) -> NDArray[Any]:
    """Descriptors of many shapes from their eigenvalues, one row per shape.

    The four descriptors of the paper's Section 3.1, and one beyond it:

    ================ ============ =========================================================
    kind             row length   definition
    ================ ============ =========================================================
    'shape-dna'      N            normalised Shape-DNA: ``lam[:N] * area`` (Section 2.1)
    'truncated'      2M+1         the first ``2M+1`` values of the normalised Shape-DNA
                                  (Fig. 5 a-e: "the first 33, 17, 9, 5 and 3 eigenvalues")
    'cshape'         2M+1         cShape-DNA of ``lam[:N]`` (Eq. 8-10, or the ``transform``
                                  given) in its real form (:func:`cshape.real_form`: same
                                  Euclidean distances)
    'cshape-complex' 2M+1         the cShape-DNA as :func:`cshape.compact_shape_dna` returns
                                  it (complex for the DFT transforms, real for the DCT)
    'f1'             N-2          F1 feature ``lam_1 / lam_i`` of ``lam[:N]`` (Fig. 5f)
    'truncated-log'  2M+1         the first ``2M+1`` log-Weyl ratios ``r_1 .. r_{2M+1}``
                                  (:func:`cshape.log_weyl_ratio`; needs ``2M+2`` eigenvalues).
                                  Its distances equal those of the truncated *log spectrum*
                                  ``log lam_1^norm .. log lam_{2M+1}^norm``: ``log 4 pi i``
                                  is the same for every shape
    ================ ============ =========================================================

    **Meshes of several pieces** (``k`` components, ``k`` zero eigenvalues), by kind:
    'shape-dna', 'truncated' and 'cshape' with the paper's ``transform='weyl'`` take the
    spectrum as it is, its ``k`` zeros included (Eq. 8 needs no logarithm).
    'truncated-log', the log-Weyl transforms and 'f1' drop the ``k`` zero modes and index
    the rest from 1 (``mu_i = lam_{k-1+i}``, normalised by the total area: Weyl's law of
    the disjoint union; :func:`cshape.nonzero_eigenvalues`): 'truncated-log' is
    ``r_1 .. r_{2M+1}`` of ``mu`` (needs ``N >= 2M+1+k``), the log-Weyl transforms extend
    the ``N-k`` ratios to ``N-1`` by Weyl's law (``r_i = r_{N-k}``) and need ``2M+1``
    measured ones, 'f1' is ``mu_1 / mu_i`` for ``i = 2..N-1``, extended the same way
    (``mu_i = mu_{N-k} i / (N-k)``), and needs two.  A row without enough non-zero
    eigenvalues cannot be described: :func:`row_problems` says which and why.

    Parameters
    ----------
    lams : array_like, shape (p, n), or sequence of p 1-D arrays
        Ascending eigenvalues of each shape (``lam_0`` first); each needs at least
        ``N`` values (``2M+1`` for 'truncated').  Ragged rows are allowed.
    areas : array_like, shape (p,), optional
        Surface areas, used by ``normalization='area'`` (the paper's choice) for all kinds
        but 'f1' (scale invariant already).  For eigenvalues that are already normalised
        pass ``areas=np.ones(p)``.
    kind : {'shape-dna', 'truncated', 'cshape', 'cshape-complex', 'f1', 'truncated-log'}, \
default='cshape'
        The old spellings 'shape_dna', 'cshape_complex' and 'truncated_log' still work, with
        a ``DeprecationWarning``.
    M : int, default=16
        Crop half-width: ``2M+1`` values for 'cshape' and 'truncated'.
    N : int, default=100
        Shape-DNA length for 'shape-dna', 'cshape' and 'f1'.
    normalization : {'area', 'fiedler', 'weyl'}, default='area'
        See :func:`cshape.normalize`.
    transform : {'weyl', 'log-weyl', 'log-weyl-dct'}, default='weyl'
        The transform of the 'cshape' and 'cshape-complex' kinds (see
        :func:`cshape.compact_shape_dna`); the other kinds do not use it.
    zero_modes : array_like of int, shape (p,), optional
        Number of zero eigenvalues of each shape (its connected components, e.g.
        :attr:`cshape.DescriptorTable.zero_modes`); a negative entry or ``None``: counted
        from that row's eigenvalues (:func:`cshape.count_zero_modes`).
    names : sequence of str, length p, optional
        Shape names, for the error messages (default: ``row <i>``).

    Returns
    -------
    X : ndarray, shape (p, d)
        float64, or complex128 for 'cshape-complex' with a DFT transform; ``d`` as in the
        table.

    Raises
    ------
    ValueError
        Unknown ``kind``, too few eigenvalues in a row, missing or wrong-length ``areas``,
        or rows that cannot be described (all of them named, with the reason; see
        :func:`row_problems`).
    """
    X, problems = descriptor_rows(lams, areas, kind, M, N, normalization=normalization,
                                  transform=transform, zero_modes=zero_modes)
    if problems:
        p = len(X) + len(problems)
        labels = _row_names(names, p)
        shown = "; ".join(f"{labels[i]}: {m}" for i, m in list(problems.items())[:5])
        more = f"; and {len(problems) - 5} more" if len(problems) > 5 else ""
        raise ValueError(
            f"kind={_check_kind(kind)!r} cannot describe {len(problems)} of {p} shapes "
            f"({shown}{more}); leave them out (cshape.compare.row_problems lists them; "
            "a DescriptorTable leaves them out with a warning) or choose another kind")
    if names is not None:
        _row_names(names, len(X))
    return X


def descriptor_rows(lams: ArrayLike | Sequence[ArrayLike], areas: ArrayLike | None = None,
                    kind: str = "cshape", M: int = 16, N: int = 100, *,
                    normalization: str = "area", transform: str = "weyl",
                    zero_modes: ArrayLike | None = None
                    ) -> tuple[NDArray[Any], dict[int, str]]:
    """The descriptors of the rows that can be described, and why the others cannot.

    Takes the arguments of :func:`descriptor_matrix`.

    Returns
    -------
    X : ndarray, shape (q, d)
        The descriptors of the ``q`` rows that can be described, in order (``q = 0``:
        shape ``(0, 0)``).
    problems : dict of int to str
        ``{row: reason}`` of the others (see :func:`row_problems`).
    """
    rows, a, zm, recipe = _prepare_rows(lams, areas, kind, M, N, normalization, transform,
                                        zero_modes)
    out: list[NDArray[Any]] = []
    problems: dict[int, str] = {}
    for i, r in enumerate(rows):
        try:
            out.append(_one_row(r, a[i], zm[i], **recipe))
        except ValueError as exc:
            problems[i] = str(exc)
    if not out:
        return np.zeros((0, 0)), problems
    lengths = {len(x) for x in out}
    if len(lengths) > 1:  # pragma: no cover - every kind has a fixed length
        raise ValueError(f"the {kind!r} descriptors have different lengths {sorted(lengths)}")
    return np.vstack(out), problems


def row_problems(lams: ArrayLike | Sequence[ArrayLike], areas: ArrayLike | None = None,
                 kind: str = "cshape", M: int = 16, N: int = 100, *,
                 normalization: str = "area", transform: str = "weyl",
                 zero_modes: ArrayLike | None = None) -> dict[int, str]:
    """The rows of :func:`descriptor_matrix` that cannot be described, with the reason.

    Takes the arguments of :func:`descriptor_matrix`.  A row cannot be described when it
    has too few non-zero eigenvalues for the kind (a mesh of many pieces with a small
    ``N``), when its eigenvalues are not ascending, or when its area is not a positive
    number.  Errors in the arguments themselves (an unknown kind, ``M`` too large for
    ``N``) are raised, as by :func:`descriptor_matrix`.

    Returns
    -------
    dict of int to str
        ``{row: reason}``; empty when every row can be described.
    """
    return descriptor_rows(lams, areas, kind, M, N, normalization=normalization,
                           transform=transform, zero_modes=zero_modes)[1]


def _row_names(names, p):
    if names is None:
        return [f"row {i}" for i in range(p)]
    names = [str(n) for n in names]
    if len(names) != p:
        raise ValueError(f"names has {len(names)} entries but lams has {p} rows")
    return names


def _prepare_rows(lams, areas, kind, M, N, normalization, transform, zero_modes):
    """Checked rows, areas (None where unused), zero modes (None: count) and the recipe."""
    kind = _check_kind(kind)
    transform = check_choice("transform", transform, TRANSFORMS)
    normalization = check_choice("normalization", normalization, NORMALIZATIONS)
    M = check_int("M", M, min=0)
    N = check_int("N", N, min=1)
    if isinstance(lams, np.ndarray) and lams.ndim == 2:
        rows = list(np.asarray(lams, dtype=np.float64))
    elif isinstance(lams, np.ndarray) or not hasattr(lams, "__len__"):
        raise ValueError(
            "lams must be a (p, n) array or a sequence of p 1-D eigenvalue arrays, got "
            f"{type(lams).__name__} of shape {np.shape(lams)}"
        )
    else:
        rows = [np.asarray(r, dtype=np.float64) for r in cast("Sequence[ArrayLike]", lams)]
    p = len(rows)
    if p == 0:
        raise ValueError("lams is empty; it needs the eigenvalues of at least one shape")
    need = {"truncated": 2 * M + 1, "truncated-log": 2 * M + 2}.get(kind, N)
    if kind in ("cshape", "cshape-complex"):
        L = N if transform == "weyl" else N - 1  # lam_0 has no logarithm
        if 2 * M + 1 > L:
            raise ValueError(
                f"2M+1 = {2 * M + 1} values cannot be kept from "
                + (f"N = {N} eigenvalues" if transform == "weyl"
                   else f"the N-1 = {L} log-Weyl ratios of transform={transform!r}")
                + f"; use M <= {(L - 1) // 2} or a larger N"
            )
    for i, r in enumerate(rows):
        if r.ndim != 1 or len(r) < need:
            raise ValueError(
                f"lams[{i}] has shape {r.shape} but kind={kind!r} needs at least {need} "
                "eigenvalues per shape; compute more eigenvalues or lower N / M"
            )
    needs_area = kind != "f1" and normalization == "area"
    if needs_area:
        if areas is None:
            raise ValueError(
                f"kind={kind!r} with normalization='area' needs areas (one surface area "
                "per shape); pass areas=np.ones(p) if lams are already normalised, or "
                "normalization='weyl'"
            )
        a = np.asarray(areas, dtype=np.float64).reshape(-1)
        if len(a) != p:
            raise ValueError(f"areas has {len(a)} entries but lams has {p} rows")
        a = [float(x) for x in a]
    else:
        a = [None] * p
    if zero_modes is None:
        zm = [None] * p
    else:
        z = np.asarray(zero_modes).reshape(-1)
        if len(z) != p or not np.issubdtype(z.dtype, np.integer):
            raise ValueError(
                f"zero_modes must hold one integer per row ({p}), got {np.shape(zero_modes)} "
                f"of {z.dtype}")
        zm = [None if x < 0 else int(x) for x in z]
    recipe = {"kind": kind, "M": M, "N": N, "normalization": normalization,
              "transform": transform}
    return rows, a, zm, recipe


def _one_row(r, area, k, *, kind, M, N, normalization, transform):
    """One descriptor; ValueError if this row cannot be described under the kind."""
    if kind == "shape-dna":
        return normalize(r[:N], area=area, method=normalization)
    if kind == "truncated":
        return normalize(r[: 2 * M + 1], area=area, method=normalization)
    if kind == "f1":
        return f1_feature(r[:N], k, length=N - 2)
    if kind == "truncated-log":  # r_1 .. r_{2M+1} of the eigenvalues after the zero modes
        k0 = count_zero_modes(r) if k is None else k
        kk = max(k0, 1)
        if len(r) - kk < 2 * M + 1:
            raise ValueError(
                f"{kk} of its {len(r)} eigenvalues are zero modes (a mesh of {kk} "
                f"components): {len(r) - kk} non-zero ones are left and 2M+1 = {2 * M + 1} "
                f"are needed (compute N >= {2 * M + 1 + kk} eigenvalues, or use "
                f"M <= {max(len(r) - kk - 1, 0) // 2})")
        lam_norm = normalize(r[: 2 * M + 1 + kk], area=area, method=normalization)
        return log_weyl_ratio(lam_norm, k0)
    lam_norm = normalize(r[:N], area=area, method=normalization)
    S = compact_shape_dna(lam_norm, M=M, N=N, normalized=True, transform=transform,
                          zero_modes=k)
    return S if kind == "cshape-complex" else real_form(S)


# --------------------------------------------------------------------------- distances
def distance_matrix(X: ArrayLike) -> NDArray[np.float64]:
    """Euclidean distances between descriptors (Section 3.1).

    Parameters
    ----------
    X : array_like, shape (p, d)
        One descriptor per row; real or complex (for complex rows the distance is
        ``sqrt(sum |x_k - y_k|^2)``, e.g. the cShape-DNA of Eq. 10).

    Returns
    -------
    D : ndarray, shape (p, p)
        Symmetric, ``D[i, j] = ||X[i] - X[j]||``, exact zeros on the diagonal.

    Raises
    ------
    ValueError
        If ``X`` is not 2-D or holds NaN / infinite values.
    """
    from scipy.spatial.distance import pdist, squareform

    A = check_descriptors(X, "X")
    if len(A) == 0:
        raise ValueError("X is empty; it needs at least one descriptor (row)")
    if len(A) == 1:
        return np.zeros((1, 1))
    return squareform(pdist(A, metric="euclidean"))


def scale_255(D: ArrayLike) -> NDArray[np.float64]:
    """Scale a distance matrix into ``[0, 255]`` (Section 3.1, Fig. 3 a-b).

    ``D_255 = 255 * D / max(D)``.  The minimum is *not* subtracted: a distance of 0
    (identical descriptors) stays 0.  For a proper distance matrix the diagonal is 0, so
    this is the same as min-max scaling; it differs only for matrices without zeros.

    Parameters
    ----------
    D : array_like, shape (p, p)
        Non-negative distances.

    Returns
    -------
    ndarray, shape (p, p)
        Values in ``[0, 255]``, float64 (not rounded to integers).  An all-zero ``D``
        (all shapes identical) gives all zeros.

    Raises
    ------
    ValueError
        If ``D`` is not square or holds negative, NaN or infinite values.
    """
    A = check_square(D, "D")
    top = float(A.max())
    if top == 0.0:
        return np.zeros_like(A)
    return A * (255.0 / top)


def difference_matrix(D1: ArrayLike, D2: ArrayLike) -> NDArray[np.float64]:
    """``|scale_255(D1) - scale_255(D2)|``, the difference image of Fig. 3c, 6 e-h and 7.

    Parameters
    ----------
    D1, D2 : array_like, shape (p, p)
        Distance matrices over the same models in the same order (e.g. Shape-DNA with
        ``N=100`` and cShape-DNA with ``M=16``).

    Returns
    -------
    ndarray, shape (p, p)
        Values in ``[0, 255]``.
    """
    A = check_square(D1, "D1")
    B = check_square(D2, "D2")
    if A.shape != B.shape:
        raise ValueError(
            f"D1 and D2 must describe the same models: got shapes {A.shape} and {B.shape}"
        )
    return np.abs(scale_255(A) - scale_255(B))


def scaled_difference(D1: ArrayLike, D2: ArrayLike, *, include_diagonal: bool = True
                      ) -> tuple[float, float]:
    """Mean and standard deviation of ``|scale_255(D1) - scale_255(D2)|`` (Section 3.1-3.3).

    The statistics the paper quotes for its difference images (mean 0.68, standard
    deviation 0.69 for Shape-DNA ``N=100`` against cShape-DNA ``M=16`` on McGill).

    Parameters
    ----------
    D1, D2 : array_like, shape (p, p)
        Distance matrices over the same models in the same order.
    include_diagonal : bool, default=True
        By default the statistics run over the full ``p x p`` matrix image, both triangles
        and the (zero) diagonal, as the paper computes them from its Fig. 3c image.  Both
        triangles hold the same values for symmetric matrices, so they do not change the
        statistics; with ``False`` the ``p`` diagonal zeros are left out, which raises the
        mean by the factor ``p / (p - 1)``.

    Returns
    -------
    mean, std : float
        Population standard deviation (``ddof=0``).

    Raises
    ------
    ValueError
        If the matrices are not square, differ in shape, or hold negative / NaN values.
    """
    include_diagonal = check_bool("include_diagonal", include_diagonal)
    diff = difference_matrix(D1, D2)
    if not include_diagonal:
        if len(diff) < 2:
            raise ValueError("include_diagonal=False needs at least two models")
        diff = diff[~np.eye(len(diff), dtype=bool)]
    return float(diff.mean()), float(diff.std())


# --------------------------------------------------------------------------- retrieval
def _ranking(D: NDArray[np.float64], i: int) -> NDArray[np.int64]:
    """Indices of the other models, nearest first; ties by index (stable sort)."""
    order = np.argsort(D[i], kind="stable")
    return order[order != i]


def retrieval_per_query(D: ArrayLike, labels: Sequence[Hashable] | ArrayLike, *,
                        min_class_size: int = 2) -> dict[str, NDArray[np.float64]]:
    """Per-query retrieval measures; see :func:`retrieval_scores` for the definitions.

    Parameters
    ----------
    D : array_like, shape (p, p)
        ``D[i, j]`` is the distance from query ``i`` to model ``j`` (need not be symmetric).
    labels : sequence, length p
        Class label of each model.
    min_class_size : int, default=2
        Queries from smaller classes are not scored (NaN).

    Returns
    -------
    dict of str to ndarray, shape (p,)
        Keys ``nn``, ``ft``, ``st``, ``e``, ``dcg``, ``map`` (average precision of each
        query); NaN for queries whose class has fewer than ``min_class_size`` models.
    """
    A = check_square(D, "D")
    codes = check_labels(labels, len(A))
    min_class_size = check_int("min_class_size", min_class_size, min=2)
    p = len(A)
    sizes = np.bincount(codes)
    keys = ("nn", "ft", "st", "e", "dcg", "map")
    out = {k: np.full(p, np.nan) for k in keys}
    for i in range(p):
        R = int(sizes[codes[i]]) - 1  # relevant models: the class minus the query
        if R + 1 < min_class_size:
            continue
        G = (codes[_ranking(A, i)] == codes[i]).astype(np.float64)  # length p - 1
        ranks = np.flatnonzero(G) + 1  # 1-based positions of the R relevant results
        out["nn"][i] = G[0]
        out["ft"][i] = G[:R].sum() / R
        out["st"][i] = G[: 2 * R].sum() / R
        k = min(E_MEASURE_DEPTH, p - 1)
        hits = G[:k].sum()
        # E = 2 / (1/P + 1/R) with P = hits / k, recall = hits / R  ->  2 hits / (k + R)
        out["e"][i] = 2.0 * hits / (k + R)
        disc = np.ones(p - 1)
        disc[1:] = 1.0 / np.log2(np.arange(2, p))  # 1, 1/lg 2, 1/lg 3, ...
        out["dcg"][i] = (G * disc).sum() / disc[:R].sum()
        out["map"][i] = np.mean(np.arange(1, R + 1) / ranks)
    return out


def retrieval_scores(D: ArrayLike, labels: Sequence[Hashable] | ArrayLike, *,
                     min_class_size: int = 2) -> dict[str, float]:
    """Retrieval measures of the Princeton Shape Benchmark, averaged over all queries.

    Every model is used once as the query; the remaining ``p - 1`` models are ranked by
    increasing distance (the query is excluded from its own results; ties are broken by
    the model's index).  With ``C`` the size of the query's class, ``R = C - 1`` models are
    relevant, and with ``G_k = 1`` when the k-th result is relevant (Shilane et al. 2004):

    * ``nn``  nearest neighbour: ``G_1``;
    * ``ft``  first tier: recall in the first ``C - 1`` results, ``sum_{k <= R} G_k / R``;
    * ``st``  second tier: recall in the first ``2(C - 1)`` results;
    * ``e``   E-measure over the first ``K = 32`` results (fewer if ``p - 1 < 32``):
      ``2 / (1/P + 1/Rc)`` with precision ``P = hits / K`` and recall ``Rc = hits / R``
      (0 when there is no hit);
    * ``dcg`` normalised discounted cumulative gain: ``(G_1 + sum_{k >= 2} G_k / log2 k)``
      divided by its ideal value ``1 + sum_{k=2}^{R} 1 / log2 k``, so 1 is perfect;
    * ``map`` mean average precision: the mean over queries of the mean, over the relevant
      results, of the precision at their rank.

    All measures lie in ``[0, 1]``; the scores are micro-averages (every query weighs the
    same).  The definitions, the tie rule and the exclusion of the query follow the PSB's
    ``psbTable`` program.  **Small classes**: a query whose class has a single model has no
    relevant result and every measure is undefined; it is left out of the averages (its
    model still appears in the other queries' results, where it is never relevant).
    ``psbTable`` also leaves out classes of two models; ``min_class_size=3`` does the same.

    Parameters
    ----------
    D : array_like, shape (p, p)
        Distance matrix, ``D[i, j]`` from query ``i`` to model ``j``.
    labels : sequence, length p
        Class label of each model (str or int).
    min_class_size : int, default=2
        Queries from classes with fewer models are left out of the averages.

    Returns
    -------
    dict
        ``{'nn': float, 'ft': float, 'st': float, 'e': float, 'dcg': float, 'map': float}``.

    Raises
    ------
    ValueError
        If ``D`` is not square or holds negative / NaN values, if ``labels`` has the wrong
        length, or if no class has ``min_class_size`` models (no query can be scored).

    See Also
    --------
    retrieval_per_query : the same measures for each query.
    """
    per = retrieval_per_query(D, labels, min_class_size=min_class_size)
    if np.all(np.isnan(per["nn"])):
        raise ValueError(
            f"labels has no class of {min_class_size} or more models (every model in a class "
            "of its own?); retrieval measures need at least one such class"
        )
    return {k: float(np.nanmean(v)) for k, v in per.items()}


# --------------------------------------------------------------------------- MDS
def mds_embedding(D: ArrayLike, *, n_components: int = 2, random_state: Any = 0,
                  n_init: int = 4, max_iter: int = 300) -> NDArray[np.float64]:
    """Metric multidimensional scaling of a distance matrix (Fig. 4-5).

    Parameters
    ----------
    D : array_like, shape (p, p)
        Symmetric distance matrix.
    n_components : int, default=2
    random_state : int or None, default=0
        Seed of the SMACOF iterations; the result is reproducible for a fixed seed.
    n_init : int, default=4
        Random restarts (used by scikit-learn < 1.8; with >= 1.8 the iteration starts from
        classical MDS, which is deterministic, and ``n_init`` is ignored).
    max_iter : int, default=300

    Returns
    -------
    Y : ndarray, shape (p, n_components)
        Coordinates whose distances approximate ``D``.  The embedding is defined up to
        rotation and reflection.

    Raises
    ------
    ValueError
        If ``D`` is not a square, symmetric, non-negative matrix with at least 2 rows.
    """
    import inspect

    from sklearn.manifold import MDS

    n_components = check_int("n_components", n_components, min=1)
    n_init = check_int("n_init", n_init, min=1)
    max_iter = check_int("max_iter", max_iter, min=1)
    A = check_square(D, "D")
    if len(A) < 2:
        raise ValueError(f"D needs at least 2 models for an embedding, got {len(A)}")
    if not np.allclose(A, A.T, rtol=1e-10, atol=1e-12 * max(1.0, float(A.max()))):
        raise ValueError("D must be symmetric for MDS; use (D + D.T) / 2")
    A = 0.5 * (A + A.T)
    params = inspect.signature(MDS.__init__).parameters
    if "metric_mds" in params:  # scikit-learn >= 1.8
        mds = MDS(n_components=n_components, metric="precomputed", init="classical_mds",
                  random_state=random_state, max_iter=max_iter, normalized_stress="auto")
    else:  # pragma: no cover - older scikit-learn
        mds = MDS(n_components=n_components, dissimilarity="precomputed", n_init=n_init,
                  random_state=random_state, max_iter=max_iter)
    return mds.fit_transform(A)
