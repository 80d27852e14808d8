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

The recipe of a descriptor (kind, ``M``, ``N``, transform, normalisation) is one frozen value,
:class:`cshape.Descriptor` (:mod:`cshape.descriptor`), which builds the rows; the functions
here take its fields as keyword arguments, or ``descriptor=``.  Exact nearest-neighbour
queries against a large database: :class:`cshape.index.DescriptorIndex`.

Every function takes and returns plain NumPy arrays.
"""

from __future__ import annotations

from collections.abc import Hashable, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._checks import (
    check_bool,
    check_descriptors,
    check_int,
    check_labels,
    check_square,
)
from .descriptor import DEFAULT, DESCRIPTOR_KINDS, PAPER, Descriptor

__all__ = [
    "DEFAULT_DESCRIPTOR",
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

#: The E-measure of the Princeton Shape Benchmark looks at the first 32 results.
E_MEASURE_DEPTH = 32

#: The exploration default, :data:`cshape.DEFAULT` (a :class:`cshape.Descriptor`; the same
#: object).  The surfaces read :data:`cshape.descriptor.DEFAULT` when they are called.
DEFAULT_DESCRIPTOR = DEFAULT
#: The paper's cShape-DNA, :data:`cshape.PAPER` (the same object): ``--kind cshape``.
PAPER_DESCRIPTOR = PAPER


# --------------------------------------------------------------------------- descriptors
def descriptor_size(kind: str, M: int = 16, N: int = 100) -> int:
    """Return the number of values of a descriptor of the given kind (its storage, in numbers).

    ``Descriptor(kind, M, N).size`` (:attr:`cshape.Descriptor.size`).

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
    return Descriptor(kind, M=M, N=N).size


def default_descriptor(N: int = 100) -> dict[str, Any]:
    """Return the exploration default (:data:`cshape.DEFAULT`) for shapes with ``N`` eigenvalues.

    Parameters
    ----------
    N : int, default=100
        Eigenvalues available per shape.  With fewer than the default needs, ``M`` is
        lowered to the largest the kind allows (the label says so).

    Returns
    -------
    dict
        ``{'kind', 'M', 'N', 'transform', 'normalization'}``, keyword arguments of
        :func:`descriptor_matrix`: ``select_descriptor(N=N).as_dict()``.
    """
    from .descriptor import select_descriptor

    return select_descriptor(N=check_int("N", N, min=1)).as_dict()


def descriptor_label(kind: str, M: int = 16, N: int = 100, transform: str = "weyl",
                     normalization: str = "area") -> str:
    """Say what a descriptor compares, in words: ``Descriptor(...).label``.

    The normalisation is named when it is not the paper's (the area).

    >>> descriptor_label("truncated-log", M=16)
    'truncated log spectrum (33 values)'
    >>> descriptor_label("truncated-log", M=8, normalization="weyl")
    'truncated log spectrum, Weyl-normalised (17 values)'
    >>> descriptor_label("cshape", M=16, N=100)
    "paper's cShape-DNA (M=16 of N=100, 33 values)"
    """
    return Descriptor(kind, M=M, N=N, transform=transform, normalization=normalization).label


def descriptor_matrix(lams: ArrayLike | Sequence[ArrayLike], areas: ArrayLike | None = None,
                      kind: str = "cshape", M: int = 16, N: int = 100, *,
                      normalization: str = "area", transform: str = "weyl",
                      zero_modes: ArrayLike | None = None,
                      names: Sequence[str] | None = None,
                      descriptor: Descriptor | None = None) -> NDArray[Any]:
    """Descriptors of many shapes from their eigenvalues, one row per shape.

    The four descriptors of the paper's Section 3.1, and two beyond it:

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
    'two-scale'      2M+1 + N-1   ``r_1 .. r_{2M+1}`` beside ``2 * detrend(r_1 .. r_{N-1})``
                                  (:func:`cshape.descriptors.detrend`: the ratios less
                                  their least-squares cubic in ``i``); the exploration
                                  default :data:`cshape.DEFAULT`
    ================ ============ =========================================================

    The recipe (kind, ``M``, ``N``, normalisation, transform) is a :class:`cshape.Descriptor`
    (``descriptor=``, or built from the keywords); this function is its
    :meth:`~cshape.Descriptor.matrix`.  ``2M+1`` values must fit in ``N`` eigenvalues (the
    ``N-1`` log-Weyl ratios for 'truncated-log' and the log-Weyl transforms).

    **Meshes of several pieces** (``k`` components, ``k`` zero eigenvalues), by kind:
    'shape-dna', 'truncated' and 'cshape' with the paper's ``transform='weyl'`` take the
    spectrum as it is, its ``k`` zeros included (Eq. 8 needs no logarithm).
    'truncated-log', 'two-scale', the log-Weyl transforms and 'f1' drop the ``k`` zero modes
    and index the rest from 1 (``mu_i = lam_{k-1+i}``, normalised by the total area: Weyl's law of
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
        ``N`` values (``2M+1`` for 'truncated', ``2M+2`` for 'truncated-log').  Ragged rows
        are allowed.
    areas : array_like, shape (p,), optional
        Surface areas, used by ``normalization='area'`` (the paper's choice) for all kinds
        but 'f1' (scale invariant already).  For eigenvalues that are already normalised
        pass ``areas=np.ones(p)``.
    kind : {'shape-dna', 'truncated', 'cshape', 'cshape-complex', 'f1', 'truncated-log', \
'two-scale'}, default='cshape'
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
    descriptor : Descriptor, optional
        The recipe as one value (e.g. :data:`cshape.PAPER`); then ``kind``, ``M``, ``N``,
        ``normalization`` and ``transform`` are not used.

    Returns
    -------
    X : ndarray, shape (p, d)
        float64, or complex128 for 'cshape-complex' with a DFT transform; ``d`` as in the
        table.

    Raises
    ------
    ValueError
        Unknown ``kind``, ``2M+1`` more than ``N`` allows, too few eigenvalues in a row,
        missing or wrong-length ``areas``, or rows that cannot be described (all of them
        named, with the reason; see :func:`row_problems`).
    """
    d = descriptor if descriptor is not None else Descriptor(
        kind, M=M, N=N, transform=transform, normalization=normalization)
    return d.matrix(lams, areas, zero_modes, names=names)


def descriptor_rows(lams: ArrayLike | Sequence[ArrayLike], areas: ArrayLike | None = None,
                    kind: str = "cshape", M: int = 16, N: int = 100, *,
                    normalization: str = "area", transform: str = "weyl",
                    zero_modes: ArrayLike | None = None,
                    descriptor: Descriptor | None = None
                    ) -> tuple[NDArray[Any], dict[int, str]]:
    """Return the descriptors of the rows that can be described, and why the others cannot.

    Takes the arguments of :func:`descriptor_matrix` (:meth:`cshape.Descriptor.rows`).

    Returns
    -------
    X : ndarray, shape (q, d)
        The descriptors of the ``q`` rows that can be described, in order (``q = 0``:
        shape ``(0, 0)``).
    problems : dict of int to str
        ``{row: reason}`` of the others (see :func:`row_problems`).
    """
    d = descriptor if descriptor is not None else Descriptor(
        kind, M=M, N=N, transform=transform, normalization=normalization)
    return d.rows(lams, areas, zero_modes)


def row_problems(lams: ArrayLike | Sequence[ArrayLike], areas: ArrayLike | None = None,
                 kind: str = "cshape", M: int = 16, N: int = 100, *,
                 normalization: str = "area", transform: str = "weyl",
                 zero_modes: ArrayLike | None = None,
                 descriptor: Descriptor | None = None) -> dict[int, str]:
    """Return the rows of :func:`descriptor_matrix` that cannot be described, with the reason.

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
                           transform=transform, zero_modes=zero_modes,
                           descriptor=descriptor)[1]


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
    """Return the indices of the other models, nearest first; ties by index (stable sort)."""
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
    """Compute the retrieval measures of the Princeton Shape Benchmark, averaged over queries.

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
