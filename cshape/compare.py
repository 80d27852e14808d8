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
* :func:`mds_embedding`, :func:`plot_mds` - 2-D multidimensional scaling plots (Fig. 4-5);
* :func:`plot_distance_matrix` - the matrix image of Fig. 3 and 6;
* :class:`DescriptorIndex`   - exact nearest-neighbour queries against a large database.

Every function takes and returns plain NumPy arrays; plots return a matplotlib
``Figure`` and never call ``show``.
"""

from __future__ import annotations

import numbers

import numpy as np

from ._checks import check_choice
from .descriptors import (
    TRANSFORMS,
    compact_shape_dna,
    f1_feature,
    log_weyl_ratio,
    normalize,
    real_form,
)

__all__ = [
    "DESCRIPTOR_KINDS",
    "DescriptorIndex",
    "descriptor_matrix",
    "descriptor_size",
    "difference_matrix",
    "distance_matrix",
    "annotate_points",
    "matrix_ticks",
    "mds_embedding",
    "plot_distance_matrix",
    "plot_mds",
    "retrieval_per_query",
    "retrieval_scores",
    "scale_255",
    "scaled_difference",
    "short_label",
    "short_labels",
]

#: The descriptor kinds of :func:`descriptor_matrix`.
DESCRIPTOR_KINDS = ("shape_dna", "truncated", "cshape", "cshape_complex", "f1", "truncated_log")

#: The E-measure of the Princeton Shape Benchmark looks at the first 32 results.
E_MEASURE_DEPTH = 32


# --------------------------------------------------------------------------- validation
def _as_descriptors(X, name="X") -> np.ndarray:
    """(p, d) real array from real or complex descriptors (complex -> [Re, Im] columns)."""
    try:
        A = np.asarray(X)
    except (TypeError, ValueError):  # pragma: no cover - ragged input on old numpy
        A = None
    if A is None or A.dtype == object:
        raise ValueError(
            f"{name} must be a 2-D numeric array (one descriptor per row, all of equal "
            "length); got a ragged or non-numeric sequence"
        )
    if A.ndim != 2:
        raise ValueError(
            f"{name} must be 2-D with shape (p, d), one descriptor per row; got shape "
            f"{A.shape} (use X[None, :] for a single descriptor)"
        )
    if not (np.issubdtype(A.dtype, np.number) or A.dtype == bool):
        raise ValueError(f"{name} must be numeric, got dtype {A.dtype}")
    if np.iscomplexobj(A):
        # |x - y|^2 = |Re x - Re y|^2 + |Im x - Im y|^2: same Euclidean distances
        A = np.hstack([A.real, A.imag])
    A = np.asarray(A, dtype=np.float64)
    if not np.all(np.isfinite(A)):
        bad = np.argwhere(~np.isfinite(A))[0]
        raise ValueError(
            f"{name} contains NaN or infinite values (first at row {bad[0]}, column {bad[1]}); "
            "drop or recompute that descriptor"
        )
    return A


def _check_square(D, name="D", *, nonnegative=True) -> np.ndarray:
    try:
        A = np.asarray(D, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a square numeric matrix") from None
    if A.ndim != 2 or A.shape[0] != A.shape[1]:
        raise ValueError(
            f"{name} must be a square (p, p) distance matrix, got shape {A.shape}; "
            "build one with cshape.distance_matrix(X)"
        )
    if A.shape[0] == 0:
        raise ValueError(f"{name} is empty (shape {A.shape}); it needs at least one model")
    if not np.all(np.isfinite(A)):
        bad = np.argwhere(~np.isfinite(A))[0]
        raise ValueError(
            f"{name} contains NaN or infinite values (first at [{bad[0]}, {bad[1]}]); "
            "check the descriptors it was computed from"
        )
    if nonnegative and A.min() < 0:
        bad = np.unravel_index(np.argmin(A), A.shape)
        raise ValueError(
            f"{name} must hold non-negative distances, got {A[bad]:g} at [{bad[0]}, {bad[1]}]"
        )
    return A


def _check_labels(labels, p, name="labels") -> np.ndarray:
    """Integer class codes (p,) from any sequence of hashable labels."""
    if isinstance(labels, (str, bytes)):
        raise ValueError(f"{name} must be a sequence of one label per model, got a string")
    lab = list(np.asarray(labels).tolist()) if isinstance(labels, np.ndarray) else list(labels)
    if len(lab) != p:
        raise ValueError(
            f"{name} has {len(lab)} entries but the distance matrix has {p} rows; "
            "pass one class label per model, in the order of the rows"
        )
    codes = {}
    try:
        return np.array([codes.setdefault(x, len(codes)) for x in lab], dtype=np.int64)
    except TypeError:
        raise ValueError(f"{name} must hold hashable labels (str or int)") from None


# --------------------------------------------------------------------------- descriptors
def descriptor_size(kind, M=16, N=100) -> int:
    """Number of values of a descriptor of the given kind (its storage, in numbers).

    Parameters
    ----------
    kind : {'shape_dna', 'truncated', 'cshape', 'cshape_complex', 'f1', 'truncated_log'}
    M, N : int
        See :func:`descriptor_matrix`.

    Returns
    -------
    int
        ``N`` for 'shape_dna', ``2M+1`` for 'truncated', 'truncated_log', 'cshape' and
        'cshape_complex' (complex numbers counted once, as the paper does; the same for
        every transform), ``N - 2`` for 'f1' (a connected mesh, one zero eigenvalue).
    """
    kind = _check_kind(kind)
    return {"shape_dna": N, "truncated": 2 * M + 1, "cshape": 2 * M + 1,
            "cshape_complex": 2 * M + 1, "f1": N - 2, "truncated_log": 2 * M + 1}[kind]


def _check_kind(kind):
    return check_choice("kind", kind, DESCRIPTOR_KINDS)


def _check_int(value, name, lo):
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < lo:
        raise ValueError(f"{name} must be an integer >= {lo}, got {value!r}")
    return int(value)


def descriptor_matrix(lams, areas=None, kind="cshape", M=16, N=100, *, normalization="area",
                      transform="weyl"):
    """Descriptors of many shapes from their eigenvalues, one row per shape.

    The four descriptors of the paper's Section 3.1, and one beyond it:

    ============== ============ =========================================================
    kind           row length   definition
    ============== ============ =========================================================
    'shape_dna'    N            normalised Shape-DNA: ``lam[:N] * area`` (Section 2.1)
    'truncated'    2M+1         the first ``2M+1`` values of the normalised Shape-DNA
                                (Fig. 5 a-e: "the first 33, 17, 9, 5 and 3 eigenvalues")
    'cshape'       2M+1         cShape-DNA of ``lam[:N]`` (Eq. 8-10, or the ``transform``
                                given) in its real form (:func:`cshape.real_form`: same
                                Euclidean distances)
    'cshape_complex' 2M+1       the cShape-DNA as :func:`cshape.compact_shape_dna` returns
                                it (complex for the DFT transforms, real for the DCT)
    'f1'           N-2          F1 feature ``lam_1 / lam_i`` of ``lam[:N]`` (Fig. 5f)
    'truncated_log' 2M+1        the first ``2M+1`` log-Weyl ratios ``r_1 .. r_{2M+1}``
                                (:func:`cshape.log_weyl_ratio`; needs ``2M+2`` eigenvalues).
                                Its distances equal those of the truncated *log spectrum*
                                ``log lam_1^norm .. log lam_{2M+1}^norm``: ``log 4 pi i``
                                is the same for every shape
    ============== ============ =========================================================

    Parameters
    ----------
    lams : array_like, shape (p, n), or sequence of p 1-D arrays
        Ascending eigenvalues of each shape (``lam_0`` first); each needs at least
        ``N`` values (``2M+1`` for 'truncated').  Ragged rows are allowed.
    areas : array_like, shape (p,), optional
        Surface areas, used by ``normalization='area'`` (the paper's choice) for all kinds
        but 'f1' (scale invariant already).  For eigenvalues that are already normalised
        pass ``areas=np.ones(p)``.
    kind : {'shape_dna', 'truncated', 'cshape', 'cshape_complex', 'f1'}, default='cshape'
    M : int, default=16
        Crop half-width: ``2M+1`` values for 'cshape' and 'truncated'.
    N : int, default=100
        Shape-DNA length for 'shape_dna', 'cshape' and 'f1'.
    normalization : {'area', 'fiedler', 'weyl'}, default='area'
        See :func:`cshape.normalize`.
    transform : {'weyl', 'log-weyl', 'log-weyl-dct'}, default='weyl'
        The transform of the 'cshape' and 'cshape_complex' kinds (see
        :func:`cshape.compact_shape_dna`); the other kinds do not use it.

    Returns
    -------
    X : ndarray, shape (p, d)
        float64, or complex128 for 'cshape_complex' with a DFT transform; ``d`` as in the
        table.

    Raises
    ------
    ValueError
        Unknown ``kind``, too few eigenvalues in a row, missing or wrong-length ``areas``,
        or F1 rows of different lengths (a mesh with several zero eigenvalues).
    """
    kind = _check_kind(kind)
    transform = check_choice("transform", transform, TRANSFORMS)
    M = _check_int(M, "M", 0)
    N = _check_int(N, "N", 1)
    if isinstance(lams, np.ndarray) and lams.ndim == 2:
        rows = list(lams)
    elif isinstance(lams, np.ndarray) or not hasattr(lams, "__len__"):
        raise ValueError(
            "lams must be a (p, n) array or a sequence of p 1-D eigenvalue arrays, got "
            f"{type(lams).__name__} of shape {np.shape(lams)}"
        )
    else:
        rows = [np.asarray(r, dtype=np.float64) for r in lams]
    p = len(rows)
    if p == 0:
        raise ValueError("lams is empty; it needs the eigenvalues of at least one shape")
    need = {"truncated": 2 * M + 1, "truncated_log": 2 * M + 2}.get(kind, N)
    if kind in ("cshape", "cshape_complex"):
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
    else:
        a = np.full(p, np.nan)
    out = []
    for i, r in enumerate(rows):
        area = float(a[i]) if needs_area else None
        if kind == "shape_dna":
            out.append(normalize(r[:N], area=area, method=normalization))
        elif kind == "truncated":
            out.append(normalize(r[: 2 * M + 1], area=area, method=normalization))
        elif kind == "truncated_log":
            out.append(log_weyl_ratio(normalize(r[: 2 * M + 2], area=area,
                                                method=normalization)))
        elif kind in ("cshape", "cshape_complex"):
            lam_norm = normalize(r[:N], area=area, method=normalization)
            S = compact_shape_dna(lam_norm, M=M, N=N, normalized=True, transform=transform)
            out.append(S if kind == "cshape_complex" else real_form(S))
        else:
            out.append(f1_feature(r[:N]))
    lengths = {len(x) for x in out}
    if len(lengths) > 1:
        first = len(out[0])
        bad = next(i for i, x in enumerate(out) if len(x) != first)
        raise ValueError(
            f"the {kind!r} descriptors have different lengths ({sorted(lengths)}): row {bad} "
            "probably has several zero eigenvalues (a mesh with several components); use "
            "cshape.largest_component on that mesh"
        )
    return np.vstack(out)


# --------------------------------------------------------------------------- distances
def distance_matrix(X):
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

    A = _as_descriptors(X, "X")
    if len(A) == 0:
        raise ValueError("X is empty; it needs at least one descriptor (row)")
    if len(A) == 1:
        return np.zeros((1, 1))
    return squareform(pdist(A, metric="euclidean"))


def scale_255(D):
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
    A = _check_square(D, "D")
    top = float(A.max())
    if top == 0.0:
        return np.zeros_like(A)
    return A * (255.0 / top)


def difference_matrix(D1, D2):
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
    A = _check_square(D1, "D1")
    B = _check_square(D2, "D2")
    if A.shape != B.shape:
        raise ValueError(
            f"D1 and D2 must describe the same models: got shapes {A.shape} and {B.shape}"
        )
    return np.abs(scale_255(A) - scale_255(B))


def scaled_difference(D1, D2, *, include_diagonal=True):
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
    diff = difference_matrix(D1, D2)
    if not include_diagonal:
        if len(diff) < 2:
            raise ValueError("include_diagonal=False needs at least two models")
        diff = diff[~np.eye(len(diff), dtype=bool)]
    return float(diff.mean()), float(diff.std())


# --------------------------------------------------------------------------- retrieval
def _ranking(D, i):
    """Indices of the other models, nearest first; ties by index (stable sort)."""
    order = np.argsort(D[i], kind="stable")
    return order[order != i]


def retrieval_per_query(D, labels, *, min_class_size=2):
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
    A = _check_square(D, "D")
    codes = _check_labels(labels, len(A))
    min_class_size = _check_int(min_class_size, "min_class_size", 2)
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


def retrieval_scores(D, labels, *, min_class_size=2):
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
def mds_embedding(D, *, n_components=2, random_state=0, n_init=4, max_iter=300):
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

    A = _check_square(D, "D")
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


# --------------------------------------------------------------------------- plots
#: An MDS plot names its points up to this many shapes; beyond, only the class legend.
MDS_MAX_NAMES = 40
#: A distance matrix gets one tick per shape up to this many shapes; beyond, one per class.
MATRIX_MAX_NAMES = 40
#: A legend lists up to this many classes; beyond, colours repeat and no legend is drawn.
MAX_LEGEND_CLASSES = 20
#: Longest point or tick label, in characters; longer names are cut in the middle.
LABEL_WIDTH = 16


def short_label(name, width=LABEL_WIDTH) -> str:
    """A name short enough for a plot: the part after the last ``/``, cut in the middle.

    >>> short_label("animals/spot_low_resolution", 12)
    'spot_…lution'
    """
    text = str(name).replace("\\", "/").rstrip("/")
    return _cut_middle(text.rsplit("/", 1)[-1] or str(name), width)


def _cut_middle(text, width):
    """``text`` cut to ``width`` characters in the middle (an ellipsis marks the cut)."""
    if len(text) <= width:
        return text
    head = (width - 1) // 2
    return text[:head] + "\u2026" + text[len(text) - (width - 1 - head):]


def short_labels(names, width=LABEL_WIDTH) -> list:
    """:func:`short_label` of every name, kept distinct where the names are.

    Names whose short labels would coincide (``a/spot`` and ``b/spot`` both give ``spot``)
    keep their parent folder (``a/spot``, ``b/spot``), cut in the middle to ``width``; if
    they still coincide, each gets its position in ``names`` as a suffix (``spot#3``).

    >>> short_labels(["a/spot", "b/spot", "c/bob"])
    ['a/spot', 'b/spot', 'bob']
    """
    names = [str(n) for n in names]
    out = [short_label(n, width) for n in names]

    def clashes(labels):
        seen = {}
        for i, (lab, name) in enumerate(zip(labels, names, strict=True)):
            seen.setdefault(lab, {}).setdefault(name, []).append(i)
        return [i for group in seen.values() if len(group) > 1
                for idx in group.values() for i in idx]

    for i in clashes(out):
        parts = names[i].replace("\\", "/").rstrip("/").split("/")
        out[i] = _cut_middle("/".join(parts[-2:]), width)
    for i in clashes(out):
        suffix = f"#{i}"
        out[i] = _cut_middle(out[i], max(width - len(suffix), 2)) + suffix
    return out


def _figure_and_ax(ax, figsize):
    if ax is not None:
        return ax.figure, ax
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, layout="constrained")
    return fig, fig.add_subplot()


def _class_colours(labels, p):
    """(colour of each point, [(class, colour)] in first-seen order)."""
    import matplotlib as mpl

    codes = _check_labels(labels, p)
    first = {}
    for i, c in enumerate(codes):
        first.setdefault(c, i)
    cmap = mpl.colormaps["tab10" if len(first) <= 10 else "tab20"]
    lab = list(labels)
    return ([cmap(c % cmap.N) for c in codes],
            [(str(lab[i]), cmap(c % cmap.N)) for c, i in first.items()])


def _square_limits(ax, Y, margin=0.08):
    """Equal x and y ranges around the points and a square box: the panel stays square
    and one unit is as long on both axes, whatever the spread of the embedding."""
    lo, hi = Y.min(axis=0), Y.max(axis=0)
    centre = (lo + hi) / 2
    half = max(float((hi - lo).max()) / 2, 1e-12 * max(1.0, float(np.abs(Y).max())))
    half *= 1 + 2 * margin
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_aspect("equal", adjustable="box")
    return 2 * half


def _side_points(ax) -> float:
    """The shorter side of ``ax`` in points (after a layout pass, if the figure has a
    layout engine; a fixed layout, as the M-sweep widget's, needs none)."""
    fig = ax.figure
    if fig.get_layout_engine() is not None:
        fig.draw_without_rendering()  # the axes get their final size
    box = ax.get_window_extent()
    return 72.0 * min(box.width, box.height) / fig.dpi


def annotate_points(ax, Y, texts, *, fontsize="x-small", offset=3.0, safety=1.15):
    """Write ``texts[i]`` beside point ``Y[i]`` where it covers no text already written.

    Greedy, in order: a text's box is estimated from its length, the font size and the
    axes' size after a layout pass (``safety`` times larger), and skipped when it would
    overlap a box kept before.  The texts take no part in the layout, so call this last,
    after the axis limits, legends and colour bars are set.

    Returns
    -------
    list of int
        The indices of the points that got their text.
    """
    from matplotlib.font_manager import FontProperties

    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    per_pt = max(x1 - x0, y1 - y0) / max(_side_points(ax), 1.0) * safety
    size = FontProperties(size=fontsize).get_size_in_points()
    boxes, kept = [], []
    for i, text in enumerate(texts):
        w, h = 0.62 * size * len(text) * per_pt, 1.25 * size * per_pt
        d = offset * per_pt
        # right of and above the point, or left / below where the axes end
        right = Y[i, 0] + d + w <= max(x0, x1)
        up = Y[i, 1] + d + h <= max(y0, y1)
        bx = Y[i, 0] + d if right else Y[i, 0] - d - w
        by = Y[i, 1] + d if up else Y[i, 1] - d - h
        box = (bx, by, bx + w, by + h)
        if any(box[0] < b[2] and b[0] < box[2] and box[1] < b[3] and b[1] < box[3]
               for b in boxes):
            continue
        boxes.append(box)
        kept.append(i)
        t = ax.annotate(text, tuple(Y[i]), xytext=(offset if right else -offset,
                                                   offset if up else -offset),
                        textcoords="offset points", fontsize=fontsize,
                        ha="left" if right else "right", va="bottom" if up else "top",
                        annotation_clip=True)
        t.set_in_layout(False)
        t.set_clip_on(True)
    return kept


def _spread_out(points, min_gap):
    """Indices of points kept so that no two are closer than ``min_gap`` (greedy, in
    order): the points whose labels can be written without writing over each other."""
    kept = []
    for i, x in enumerate(points):
        if all(np.linalg.norm(x - points[j]) >= min_gap for j in kept):
            kept.append(i)
    return kept


def plot_mds(Y, names=None, labels=None, *, ax=None, title=None, figsize=(5.0, 4.5),
             max_names=MDS_MAX_NAMES, legend=True):
    """Scatter plot of a 2-D MDS embedding, square, coloured by class (Fig. 4-5).

    Readable from 3 to thousands of shapes with any names: the panel is square with equal
    units on both axes; points are named (the part after the last ``/``, at most
    :data:`LABEL_WIDTH` characters) only up to ``max_names`` shapes, and only where a name
    does not cover another; classes are told apart by colour, listed in a legend outside
    the panel up to :data:`MAX_LEGEND_CLASSES` classes.

    Parameters
    ----------
    Y : array_like, shape (p, 2)
        From :func:`mds_embedding`.
    names : sequence of str, length p, optional
        Shape names, written beside the points (up to ``max_names`` shapes).
    labels : sequence, length p, optional
        Classes; points of one class share a colour.
    ax : matplotlib Axes, optional
        Draw here; by default a new Figure is made (not registered with pyplot).
    title : str, optional
    figsize : (float, float), default=(5.0, 4.5)
    max_names : int, default=MDS_MAX_NAMES
        Write no name when there are more shapes.
    legend : bool, default=True
        Draw the class legend: outside the panel, on the right, on a figure of its own;
        inside (where it covers the fewest points) when ``ax`` is given.  A figure of
        several panels reads best with ``legend=False`` and one ``fig.legend``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    Y = np.asarray(Y, dtype=np.float64)
    if Y.ndim != 2 or Y.shape[1] != 2:
        raise ValueError(f"Y must have shape (p, 2), got {Y.shape}; use mds_embedding(D)")
    p = len(Y)
    if names is not None and len(names) != p:
        raise ValueError(f"names has {len(names)} entries but Y has {p} points")
    own = ax is None
    fig, ax = _figure_and_ax(ax, figsize)
    size = 25.0 if p <= 100 else max(4.0, 2500.0 / p)
    if labels is not None:
        colours, classes = _class_colours(labels, p)
        ax.scatter(Y[:, 0], Y[:, 1], c=colours, s=size, linewidths=0)
        for lab, col in classes:
            ax.scatter([], [], color=col, label=short_label(lab))
        if legend and len(classes) <= MAX_LEGEND_CLASSES and own:
            ax.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.02, 1.0),
                      borderaxespad=0.0, frameon=False)
        elif legend and len(classes) <= MAX_LEGEND_CLASSES:  # a panel of a larger figure
            ax.legend(fontsize="x-small", loc="best", framealpha=0.7)
    else:
        ax.scatter(Y[:, 0], Y[:, 1], s=size, linewidths=0)
    _square_limits(ax, Y)
    if names is not None and p <= max_names:
        annotate_points(ax, Y, short_labels(names))
    ax.set_xlabel("MDS 1", fontsize="small")
    ax.set_ylabel("MDS 2", fontsize="small")
    ax.locator_params(nbins=4)
    ax.ticklabel_format(style="sci", scilimits=(-3, 3))
    ax.tick_params(labelsize="x-small")
    if title:
        ax.set_title(title, fontsize="medium")
    return fig


def _runs(labels):
    """Contiguous runs of equal labels: [(start, stop, label)]."""
    out = []
    for i, lab in enumerate(labels):
        if out and out[-1][2] == lab:
            out[-1][1] = i + 1
        else:
            out.append([i, i + 1, lab])
    return [tuple(r) for r in out]


def matrix_ticks(ax, p, names=None, labels=None, *, max_names=MATRIX_MAX_NAMES,
                 fontsize="x-small", safety=1.5, side_pt=None):
    """Ticks of a (p, p) matrix image that never write over each other.

    One tick per shape (short names) when there are at most ``max_names`` shapes and their
    labels fit the axes' height; else one per class, at the middle of each run of a class,
    as many as fit (the axes' size after a layout pass without ticks, ``safety`` times
    smaller for the room the tick labels take), with thin white lines at the class
    boundaries.

    Parameters
    ----------
    side_pt : float, optional
        The axes' shorter side in points; measured (a layout pass) when not given.  Pass
        the value returned for one panel to give panels of one size the same ticks.

    Returns
    -------
    float
        The side used.
    """
    from matplotlib.font_manager import FontProperties

    ax.set_xticks([])
    ax.set_yticks([])
    if side_pt is None:
        side_pt = _side_points(ax)
    size = FontProperties(size=fontsize).get_size_in_points()
    n_fit = max(1, int(side_pt / safety / (1.2 * size)))
    runs = _runs([str(x) for x in labels]) if labels is not None and len(labels) == p else []
    if names is not None and len(names) == p and p <= min(max_names, n_fit):
        where, text = list(range(p)), short_labels(names)
    elif len(runs) > 1:
        mids = np.array([[(a + b - 1) / 2, 0.0] for a, b, _ in runs])
        keep = _spread_out(mids, p / n_fit)
        where, text = [mids[k, 0] for k in keep], [short_label(runs[k][2]) for k in keep]
    else:
        return side_pt
    ax.set_xticks(where, text, rotation=90, fontsize=fontsize)
    ax.set_yticks(where, text, fontsize=fontsize)
    if 1 < len(runs) <= 100:  # beyond, the lines would hide the matrix
        for a, _, _ in runs[1:]:
            ax.axhline(a - 0.5, color="white", lw=0.6)
            ax.axvline(a - 0.5, color="white", lw=0.6)
    return side_pt


def plot_distance_matrix(D, *, scale=True, ax=None, title=None, names=None, labels=None,
                         cmap="jet", vmax=None, colorbar=True, figsize=(5.0, 4.5)):
    """Image of a distance matrix, as in Fig. 3 and 6 (blue: similar, red: dissimilar).

    Parameters
    ----------
    D : array_like, shape (p, p)
        Distances, or a difference matrix from :func:`difference_matrix` (then pass
        ``scale=False``).
    scale : bool, default=True
        Show :func:`scale_255` of ``D`` on a fixed ``[0, 255]`` colour range.
    ax : matplotlib Axes, optional
        Draw here; by default a new Figure is made (not registered with pyplot).
    title : str, optional
    names : sequence of str, optional
        Tick labels, one per shape (shortened), drawn for at most
        :data:`MATRIX_MAX_NAMES` shapes.
    labels : sequence, optional
        Classes of the rows: beyond :data:`MATRIX_MAX_NAMES` shapes (or without
        ``names``) one tick per class, and lines between classes (see
        :func:`matrix_ticks`).
    cmap : str, default='jet'
        The paper's colours.
    vmax : float, optional
        Top of the colour range; default 255 when scaled, else ``D.max()``.
    colorbar : bool, default=True
    figsize : (float, float), default=(5.0, 4.5)

    Returns
    -------
    matplotlib.figure.Figure
    """
    A = _check_square(D, "D")
    img = scale_255(A) if scale else A
    if vmax is None:
        vmax = 255.0 if scale else (float(img.max()) or 1.0)
    fig, ax = _figure_and_ax(ax, figsize)
    im = ax.imshow(img, cmap=cmap, vmin=0.0, vmax=vmax, interpolation="nearest")
    matrix_ticks(ax, len(A), names, labels)
    if colorbar:
        fig.colorbar(im, ax=ax, shrink=0.8)
    if title:
        ax.set_title(title, fontsize="medium")
    return fig


# --------------------------------------------------------------------------- index
class DescriptorIndex:
    """Exact nearest-neighbour search in a descriptor database (scikit-learn).

    Parameters
    ----------
    X : array_like, shape (n, d)
        The database, one descriptor per row; real or complex (complex rows are stored as
        ``[Re, Im]``, which keeps the Euclidean distances).
    algorithm : {'auto', 'brute', 'kd_tree', 'ball_tree'}, default='auto'
        Passed to :class:`sklearn.neighbors.NearestNeighbors`; all are exact.  Measured on
        this project's 2-core machine (100 000 descriptors, 1000 queries, k=10): 'auto'
        picks a k-d tree up to 15 values (3 values: 0.01 s, 9: 0.2 s) and a brute-force
        scan above (33 values: 0.5 s, 100 values: 1.3 s; trees took 2-24 s there), so the
        default is the right choice for every descriptor size of the paper.
    n_jobs : int, optional
        Parallel queries (scikit-learn convention, -1 for all cores).

    Attributes
    ----------
    X_ : ndarray, shape (n, d')
        The stored (real) database.
    nn_ : sklearn.neighbors.NearestNeighbors
        The fitted index.
    recipe_ : dict or None
        How the rows were made from eigenvalues (``kind``, ``M``, ``N``, ``normalization``,
        ``transform``), when built with :meth:`from_table`; :meth:`query_spectra` describes
        queries with the same recipe, so a query can never use another transform.

    Examples
    --------
    >>> import numpy as np
    >>> from cshape.compare import DescriptorIndex
    >>> index = DescriptorIndex(np.array([[0.0, 0], [1, 0], [5, 5]]))
    >>> dist, ind = index.query([[0.9, 0.1]], k=2)
    >>> ind.tolist()
    [[1, 0]]
    """

    def __init__(self, X, *, algorithm="auto", n_jobs=None):
        from sklearn.neighbors import NearestNeighbors

        self.algorithm = algorithm
        self.n_jobs = n_jobs
        self._complex = np.iscomplexobj(np.asarray(X))
        self.X_ = _as_descriptors(X, "X")
        if len(self.X_) == 0:
            raise ValueError("X is empty; the index needs at least one descriptor")
        self.nn_ = NearestNeighbors(algorithm=algorithm, n_jobs=n_jobs).fit(self.X_)
        self.recipe_ = None

    @classmethod
    def from_table(cls, table, kind="cshape", M=None, N=None, *, transform=None,
                   normalization="area", algorithm="auto", n_jobs=None):
        """An index of a :class:`cshape.DescriptorTable`'s descriptors, with their recipe.

        Parameters
        ----------
        table : DescriptorTable
        kind : str, default='cshape'
            See :func:`descriptor_matrix`.
        M, N : int, optional
            Default: the table's.
        transform : {'weyl', 'log-weyl', 'log-weyl-dct'}, optional
            Default: the table's ``transform`` (see :func:`cshape.compact_shape_dna`).
        normalization : {'area', 'fiedler', 'weyl'}, default='area'
        algorithm, n_jobs
            As for the constructor.

        Returns
        -------
        DescriptorIndex
            With :attr:`recipe_` set, for :meth:`query_spectra`.
        """
        recipe = {"kind": _check_kind(kind), "M": table.M if M is None else M,
                  "N": table.N if N is None else N, "normalization": normalization,
                  "transform": table.transform if transform is None else transform}
        X = descriptor_matrix(table.lam, table.areas, **recipe)
        index = cls(X, algorithm=algorithm, n_jobs=n_jobs)
        index.recipe_ = recipe
        return index

    def query_spectra(self, lams, areas=None, k=1):
        """Nearest database rows of shapes given by their eigenvalues.

        The queries are described exactly as the database was (:attr:`recipe_`: kind,
        ``M``, ``N``, normalisation and transform).

        Parameters
        ----------
        lams : array_like, shape (q, n) or (n,)
            Ascending eigenvalues of each query shape, ``n >= N``.
        areas : array_like, shape (q,) or float, optional
            Surface areas (needed by the area normalisation).
        k : int, default=1

        Returns
        -------
        dist, ind : ndarray, shape (q, k)
            As for :meth:`query`.
        """
        if self.recipe_ is None:
            raise ValueError(
                "this index does not know how its descriptors were made; build it with "
                "DescriptorIndex.from_table(table, ...) to query by eigenvalues, or pass "
                "descriptors to query()"
            )
        L = np.asarray(lams, dtype=np.float64)
        if L.ndim == 1:
            L = L[None, :]
        a = None if areas is None else np.atleast_1d(np.asarray(areas, dtype=np.float64))
        Y = descriptor_matrix(L, a, **self.recipe_)
        return self.query(Y, k=k)

    def __len__(self):
        return len(self.X_)

    def query(self, Y=None, k=1):
        """The ``k`` nearest database descriptors of each query.

        Parameters
        ----------
        Y : array_like, shape (q, d), optional
            Query descriptors, of the same kind and length as the database (a single
            descriptor of shape (d,) is accepted).  ``None`` queries the database with
            itself, each row's own entry excluded.
        k : int, default=1
            Number of neighbours; at most ``n`` (``n - 1`` when ``Y`` is None).

        Returns
        -------
        dist : ndarray, shape (q, k)
            Euclidean distances, ascending along each row.
        ind : ndarray of int, shape (q, k)
            Row indices into the database.
        """
        n = len(self.X_)
        limit = n - 1 if Y is None else n
        if isinstance(k, bool) or not isinstance(k, numbers.Integral) or not 1 <= k <= limit:
            raise ValueError(
                f"k must be an integer in [1, {limit}] for a database of {n} descriptors"
                f"{' queried with itself' if Y is None else ''}, got {k!r}"
            )
        if Y is None:
            return self.nn_.kneighbors(None, n_neighbors=int(k))
        Yarr = np.asarray(Y)
        if Yarr.ndim == 1:
            Yarr = Yarr[None, :]
        if np.iscomplexobj(Yarr) != self._complex:
            raise ValueError(
                "Y and the database must both be real or both complex descriptors"
            )
        Q = _as_descriptors(Yarr, "Y")
        if Q.shape[1] != self.X_.shape[1]:
            raise ValueError(
                f"Y has descriptors of length {Yarr.shape[1]} but the database has "
                f"{self.X_.shape[1] // (2 if self._complex else 1)}; use the same kind, M and N"
            )
        return self.nn_.kneighbors(Q, n_neighbors=int(k))
