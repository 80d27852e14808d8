"""Stage 5 of the pipeline: comparing descriptors (Section 3 of the paper).

The descriptors themselves are rows of a :class:`cshape.Descriptor` (its
:meth:`~cshape.Descriptor.matrix`); this module compares them:

* :func:`distance_matrix`    - Euclidean distances between rows (Section 3.1);
* :func:`scale_255`          - a distance matrix scaled to ``[0, 255]`` (Fig. 3 a-b);
* :func:`difference_matrix`, :func:`scaled_difference` - the absolute difference of two scaled
                               matrices and its mean and standard deviation (Fig. 3c, 6, 7);
* :func:`retrieval_scores`, :func:`retrieval_per_query` - nearest neighbour, first and second
                               tier, E-measure, DCG and mean average precision (Princeton
                               Shape Benchmark definitions);
* :func:`nearest_neighbours` - each shape's ``k`` nearest other shapes in a distance matrix;
* :func:`mds_embedding`      - 2-D multidimensional scaling coordinates (Fig. 4-5; drawn by
                               :func:`cshape.plots.plot_mds`), and :func:`mds_outliers`, the
                               points that lie far from the rest.

Exact nearest-neighbour queries against a large database: :class:`cshape.DescriptorIndex`.
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
    check_points,
    check_real,
    check_square,
)

__all__ = [
    "distance_matrix",
    "mds_embedding",
    "nearest_neighbours",
    "retrieval_scores",
    "scale_255",
]

#: The E-measure of the Princeton Shape Benchmark looks at the first 32 results.
E_MEASURE_DEPTH = 32
#: A point of an embedding is an outlier when its median distance to the other points is
#: more than this many times the typical one (:func:`mds_outliers`).
OUTLIER_FACTOR = 5.0
#: :func:`median_distances` measures each point's median distance to at most this many
#: points (evenly spaced through the rows), to stay within memory on large collections.
OUTLIER_REFERENCE_POINTS = 2000


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
    retrieval_per_query : The same measures for each query.
    """
    per = retrieval_per_query(D, labels, min_class_size=min_class_size)
    if np.all(np.isnan(per["nn"])):
        raise ValueError(
            f"labels has no class of {min_class_size} or more models (every model in a class "
            "of its own?); retrieval measures need at least one such class"
        )
    return {k: float(np.nanmean(v)) for k, v in per.items()}


def nearest_neighbours(D: ArrayLike, k: int = 3) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """Each shape's ``k`` nearest other shapes in a distance matrix.

    Parameters
    ----------
    D : array_like, shape (p, p)
        Distances.
    k : int, default=3
        At most ``p - 1`` are returned.

    Returns
    -------
    ind : ndarray of int, shape (p, min(k, p - 1))
        Row ``i``: the nearest shapes to shape ``i``, nearest first, ``i`` itself left out
        (by index: a duplicate at distance 0 is a neighbour); ties in the order of rows.
    dist : ndarray, shape (p, min(k, p - 1))
        Their distances.

    Raises
    ------
    TypeError
        ``k`` not an integer.
    ValueError
        ``D`` not square, negative or not finite; ``k < 1``.

    Examples
    --------
    >>> ind, dist = nearest_neighbours([[0, 1, 3], [1, 0, 1], [3, 1, 0]], k=2)
    >>> ind.tolist(), dist.tolist()
    ([[1, 2], [0, 2], [1, 0]], [[1.0, 3.0], [1.0, 1.0], [1.0, 3.0]])
    """
    A = check_square(D, "D")
    k = check_int("k", k, min=1)
    p = len(A)
    k = min(k, p - 1)
    B = A.astype(np.float64, copy=True)
    np.fill_diagonal(B, np.inf)
    ind = np.argsort(B, axis=1, kind="stable")[:, :k]
    return ind, np.take_along_axis(A, ind, axis=1).astype(np.float64)


# --------------------------------------------------------------------------- MDS
def mds_embedding(D: ArrayLike, *, n_components: int = 2, random_state: Any = 0,
                  n_init: int = 4, max_iter: int = 300) -> NDArray[np.float64]:
    """Metric multidimensional scaling of a distance matrix (Fig. 4-5).

    Classical (Torgerson) scaling gives the start: the top ``n_components`` eigenvectors of
    the double-centred matrix ``-J D**2 J / 2``, each scaled by the square root of its
    eigenvalue and signed so that its largest entry is positive.  SMACOF's Guttman transforms
    then lower the raw stress ``sum_{i<j} (|y_i - y_j| - D_ij)**2`` until it falls by less
    than ``1e-6`` of ``sum_{i<j} |y_i - y_j|**2`` in one step, or ``max_iter`` steps are
    done.  These are the iterations of scikit-learn's
    ``MDS(metric="precomputed", init="classical_mds")`` (scikit-learn 1.8 and later), in plain
    NumPy and SciPy: the same coordinates, whatever version is installed, without its import.

    Parameters
    ----------
    D : array_like, shape (p, p)
        Symmetric distance matrix.
    n_components : int, default=2
        Dimension of the embedding.
    random_state : int or None, default=0
        No effect: the start is classical scaling, which is deterministic (kept so that calls
        written for random starts run unchanged).
    n_init : int, default=4
        No effect, as ``random_state`` (there is one start).
    max_iter : int, default=300
        Most SMACOF iterations.

    Returns
    -------
    Y : ndarray, shape (p, n_components)
        Coordinates whose distances approximate ``D``.  The embedding is defined up to
        rotation and reflection; this one is reproducible bit for bit on one machine.

    Raises
    ------
    ValueError
        If ``D`` is not a square, symmetric, non-negative matrix with at least 2 rows.
    """
    from scipy import linalg

    del random_state  # one deterministic start
    n_components = check_int("n_components", n_components, min=1)
    check_int("n_init", n_init, min=1)
    max_iter = check_int("max_iter", max_iter, min=1)
    A = check_square(D, "D")
    if len(A) < 2:
        raise ValueError(f"D needs at least 2 models for an embedding, got {len(A)}")
    if not np.allclose(A, A.T, rtol=1e-10, atol=1e-12 * max(1.0, float(A.max()))):
        raise ValueError("D must be symmetric for MDS; use (D + D.T) / 2")
    A = np.ascontiguousarray(0.5 * (A + A.T), dtype=np.float64)
    p = len(A)
    # the start: classical scaling
    B = A**2
    B -= np.mean(B, axis=0)
    B -= np.mean(B, axis=1, keepdims=True)
    B *= -0.5
    w, U = linalg.eigh(B)
    w, U = w[::-1][:n_components], U[:, ::-1][:, :n_components]
    U = U * np.sign(U[np.argmax(np.abs(U), axis=0), np.arange(U.shape[1])])
    Y = np.sqrt(w) * U
    # SMACOF: Guttman transforms until the stress stops falling
    dist = _row_distances(Y)
    old = None
    diag = np.arange(p)
    for _ in range(max_iter):
        dist[dist == 0] = 1e-5
        ratio = A / dist
        G = -ratio
        G[diag, diag] += ratio.sum(axis=1)
        Y = 1.0 / p * np.dot(G, Y)
        dist = _row_distances(Y)
        stress = ((dist.ravel() - A.ravel()) ** 2).sum() / 2
        if old is not None and (old - stress) / ((dist.ravel() ** 2).sum() / 2) < 1e-6:
            break
        old = stress
    return Y


def _row_distances(Y: NDArray[np.float64]) -> NDArray[np.float64]:
    """Euclidean distances between the rows of ``Y``, as scikit-learn's ``euclidean_distances``.

    ``sqrt(|a|^2 - 2 a.b + |b|^2)``, clipped at 0, with a zero diagonal.
    """
    sq = np.einsum("ij,ij->i", Y, Y)[:, None]
    d2 = -2 * (Y @ Y.T)
    d2 += sq
    d2 += sq.T
    np.maximum(d2, 0, out=d2)
    np.fill_diagonal(d2, 0)
    return np.sqrt(d2)


def median_distances(Y: ArrayLike, *, reference: int = OUTLIER_REFERENCE_POINTS
                     ) -> NDArray[np.float64]:
    """Each point's median Euclidean distance to the other points.

    Parameters
    ----------
    Y : array_like, shape (p, d)
    reference : int, default=OUTLIER_REFERENCE_POINTS
        Measure against at most this many points, evenly spaced through the rows (all of
        them when ``p <= reference``), a point never against itself.

    Returns
    -------
    ndarray, shape (p,)
        Zeros when ``p < 2``.
    """
    Y = check_points(Y)
    reference = check_int("reference", reference, min=1)
    p = len(Y)
    if p < 2:
        return np.zeros(p)
    ref = np.unique(np.linspace(0, p - 1, min(p, reference)).round().astype(np.int64))
    out = np.empty(p)
    for start in range(0, p, 512):  # blocks of rows: memory 512 x reference
        rows = np.arange(start, min(p, start + 512))
        d = np.linalg.norm(Y[rows, None, :] - Y[None, ref, :], axis=2)
        own = rows[:, None] == ref[None, :]
        d[own] = np.inf  # not against itself: sorted last, and left out of the count
        d.sort(axis=1)
        m = len(ref) - own.any(axis=1)  # values counted in each row
        lo, hi = (m - 1) // 2, m // 2
        r = np.arange(len(rows))
        out[rows] = (d[r, lo] + d[r, hi]) / 2
    return out


def mds_outliers(Y: ArrayLike, *, factor: float = OUTLIER_FACTOR) -> NDArray[np.bool_]:
    """Return the points of an embedding that lie far from the rest (a robust rule).

    Point ``i`` is an outlier when its median distance to the other points,
    ``m_i = median_j |Y_i - Y_j|`` (:func:`median_distances`), exceeds ``factor`` times the
    median of all ``m``.  Fewer than half of the points can be outliers.

    Parameters
    ----------
    Y : array_like, shape (p, d)
        Coordinates (an MDS embedding, :func:`mds_embedding`).
    factor : float, default=OUTLIER_FACTOR
        Greater than 1.

    Returns
    -------
    ndarray of bool, shape (p,)
        None when ``p < 3`` or when most points coincide (a typical distance of 0).

    Raises
    ------
    ValueError
        ``Y`` not a 2-D array of finite coordinates; ``factor <= 1``.
    """
    Y = check_points(Y)
    factor = check_real("factor", factor, above=1)
    if len(Y) < 3:
        return np.zeros(len(Y), dtype=bool)
    m = median_distances(Y)
    typical = float(np.median(m))
    if not typical > 0:
        return np.zeros(len(Y), dtype=bool)
    return m > factor * typical
