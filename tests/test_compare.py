"""cshape.compare: distances, [0, 255] scaling, difference statistics, retrieval measures,
MDS, plots and the nearest-neighbour index.  Expected values are worked out by hand in the
comments."""

from __future__ import annotations

import numpy as np
import pytest

from cshape import Descriptor, compact_shape_dna, normalize, shape_dna, shapes
from cshape.compare import (
    difference_matrix,
    distance_matrix,
    mds_embedding,
    retrieval_per_query,
    retrieval_scores,
    scale_255,
    scaled_difference,
)
from cshape.descriptors import real_form
from cshape.descriptors.recipe import DESCRIPTOR_KINDS
from cshape.index import DescriptorIndex
from cshape.plots.collection import plot_distance_matrix, plot_mds


# ------------------------------------------------------------------ distance_matrix
def test_distance_matrix_known_values():
    X = np.array([[0.0, 0.0], [3.0, 4.0], [6.0, 8.0]])
    D = distance_matrix(X)
    np.testing.assert_allclose(D, [[0, 5, 10], [5, 0, 5], [10, 5, 0]])
    assert np.array_equal(D, D.T)
    assert np.all(np.diag(D) == 0.0)


def test_distance_matrix_complex_uses_modulus():
    # |(1+1j) - 0|^2 + |(2-1j) - 0|^2 = 2 + 5 = 7
    X = np.array([[0j, 0j], [1 + 1j, 2 - 1j]])
    assert distance_matrix(X)[0, 1] == pytest.approx(np.sqrt(7.0))


def test_distance_matrix_single_row():
    assert np.array_equal(distance_matrix([[1.0, 2.0]]), [[0.0]])


@pytest.mark.parametrize(
    "X, match",
    [
        (np.zeros(3), r"X must be 2-D"),
        (np.array([[0.0, np.nan], [1.0, 2.0]]), r"X contains NaN"),
        (np.zeros((0, 3)), r"X is empty"),
        ([[1.0, 2.0], [3.0]], r"X must be a 2-D numeric array"),
    ],
)
def test_distance_matrix_rejects(X, match):
    with pytest.raises(ValueError, match=match):
        distance_matrix(X)


# ------------------------------------------------------------------ scale_255 / difference
def test_scale_255_divides_by_max():
    D = np.array([[0.0, 2.0, 4.0], [2.0, 0.0, 1.0], [4.0, 1.0, 0.0]])
    # 255 / 4 = 63.75 per unit
    np.testing.assert_allclose(
        scale_255(D), [[0, 127.5, 255], [127.5, 0, 63.75], [255, 63.75, 0]]
    )


def test_scale_255_does_not_subtract_min():
    # no zero anywhere: max-scaling keeps 1 -> 127.5 (min-max scaling would give 0)
    np.testing.assert_allclose(scale_255([[1.0, 2.0], [2.0, 1.0]]), [[127.5, 255], [255, 127.5]])


def test_scale_255_all_zero_and_scale_invariance():
    assert np.array_equal(scale_255(np.zeros((3, 3))), np.zeros((3, 3)))
    D = distance_matrix(np.random.default_rng(0).normal(size=(6, 4)))
    np.testing.assert_allclose(scale_255(D), scale_255(7.5 * D))


@pytest.mark.parametrize(
    "D, match",
    [
        (np.zeros((2, 3)), r"D must be a square"),
        (np.zeros(4), r"D must be a square"),
        (np.array([[0.0, np.nan], [np.nan, 0.0]]), r"D contains NaN"),
        (np.array([[0.0, -1.0], [-1.0, 0.0]]), r"D must hold non-negative"),
    ],
)
def test_scale_255_rejects(D, match):
    with pytest.raises(ValueError, match=match):
        scale_255(D)


def test_scaled_difference_hand_computed():
    D1 = np.array([[0.0, 1.0, 2.0], [1.0, 0.0, 4.0], [2.0, 4.0, 0.0]])
    D2 = np.array([[0.0, 2.0, 2.0], [2.0, 0.0, 4.0], [2.0, 4.0, 0.0]])
    # both have max 4, so scale = 63.75; they differ only at (0,1) and (1,0) by 63.75
    diff = difference_matrix(D1, D2)
    expected = np.zeros((3, 3))
    expected[0, 1] = expected[1, 0] = 63.75
    np.testing.assert_allclose(diff, expected)
    # full 3x3 image: mean = 2 * 63.75 / 9; E[x^2] = 2 * 63.75^2 / 9
    # std = 63.75 * sqrt(2/9 - 4/81) = 63.75 * sqrt(14) / 9
    mean, std = scaled_difference(D1, D2)
    assert mean == pytest.approx(2 * 63.75 / 9)
    assert std == pytest.approx(63.75 * np.sqrt(14) / 9)
    # without the 3 diagonal zeros: 6 entries, mean 63.75 / 3, std 63.75 * sqrt(2) / 3
    mean, std = scaled_difference(D1, D2, include_diagonal=False)
    assert mean == pytest.approx(63.75 / 3)
    assert std == pytest.approx(63.75 * np.sqrt(2) / 3)


def test_scaled_difference_of_proportional_matrices_is_zero():
    D = distance_matrix(np.random.default_rng(1).normal(size=(5, 3)))
    assert scaled_difference(D, 3.0 * D) == pytest.approx((0.0, 0.0))


def test_scaled_difference_rejects():
    with pytest.raises(ValueError, match=r"D1 and D2 must describe the same models"):
        scaled_difference(np.zeros((2, 2)), np.zeros((3, 3)))
    with pytest.raises(ValueError, match=r"D2 must be a square"):
        scaled_difference(np.zeros((2, 2)), np.zeros((2, 3)))
    with pytest.raises(ValueError, match=r"D1 contains NaN"):
        scaled_difference(np.full((2, 2), np.nan), np.zeros((2, 2)))


# ------------------------------------------------------------------ retrieval measures
# Five models on a line, no distance ties:
#   model  A    B    C    D    E
#   x      0    1    3    4.5  10
#   class  a    b    a    b    b        (class a: C=2, R=1 relevant; class b: C=3, R=2)
# Rankings (query excluded) and gains G, the E-measure looks at k = min(32, 4) = 4 results:
#   A: B C D E  G=0100  nn 0  ft 0/1  st 1/1  E 2*1/(4+1)=.4  DCG 1/lg2=1 -> 1/1     AP 1/2
#   B: A C D E  G=0011  nn 0  ft 0/2  st 2/2  E 2*2/(4+2)     DCG 1/lg3+1/lg4 -> /2   AP (1/3+2/4)/2
#   C: D B A E  G=0010  nn 0  ft 0/1  st 0/1  E .4            DCG 1/lg3 -> /1         AP 1/3
#   D: C B A E  G=0101  nn 0  ft 1/2  st 2/2  E 4/6           DCG 1+1/lg4 -> /2       AP (1/2+2/4)/2
#   E: D C B A  G=1010  nn 1  ft 1/2  st 2/2  E 4/6           DCG 1+1/lg3 -> /2       AP (1+2/3)/2
LINE_X = np.array([0.0, 1.0, 3.0, 4.5, 10.0])
LINE_LABELS = ["a", "b", "a", "b", "b"]


def test_retrieval_per_query_hand_computed():
    D = distance_matrix(LINE_X[:, None])
    per = retrieval_per_query(D, LINE_LABELS)
    l3 = 1 / np.log2(3)
    np.testing.assert_allclose(per["nn"], [0, 0, 0, 0, 1])
    np.testing.assert_allclose(per["ft"], [0, 0, 0, 0.5, 0.5])
    np.testing.assert_allclose(per["st"], [1, 1, 0, 1, 1])
    np.testing.assert_allclose(per["e"], [0.4, 2 / 3, 0.4, 2 / 3, 2 / 3])
    np.testing.assert_allclose(per["dcg"], [1, (l3 + 0.5) / 2, l3, 1.5 / 2, (1 + l3) / 2])
    np.testing.assert_allclose(per["map"], [0.5, (1 / 3 + 0.5) / 2, 1 / 3, 0.5, (1 + 2 / 3) / 2])


def test_retrieval_scores_hand_computed_means():
    s = retrieval_scores(distance_matrix(LINE_X[:, None]), LINE_LABELS)
    assert set(s) == {"nn", "ft", "st", "e", "dcg", "map"}
    l3 = 1 / np.log2(3)
    assert s["nn"] == pytest.approx(1 / 5)
    assert s["ft"] == pytest.approx(1 / 5)
    assert s["st"] == pytest.approx(4 / 5)
    assert s["e"] == pytest.approx((0.4 + 0.4 + 3 * 2 / 3) / 5)
    assert s["dcg"] == pytest.approx((1 + (l3 + 0.5) / 2 + l3 + 0.75 + (1 + l3) / 2) / 5)
    assert s["map"] == pytest.approx((0.5 + 5 / 12 + 1 / 3 + 0.5 + 5 / 6) / 5)


def test_retrieval_perfect_clusters():
    X = np.array([[0.0], [0.1], [0.2], [10.0], [10.1]])
    s = retrieval_scores(distance_matrix(X), [0, 0, 0, 1, 1])
    # every measure is 1 except E: class 0 queries have R=2, k=4 -> 2*2/6; class 1: 2*1/5
    for key in ("nn", "ft", "st", "dcg", "map"):
        assert s[key] == pytest.approx(1.0)
    assert s["e"] == pytest.approx((3 * 4 / 6 + 2 * 2 / 5) / 5)


def test_retrieval_e_measure_looks_at_32_results():
    # two separated classes of 20: R = 19 relevant, all found in the first 32 results
    # E = 2 * 19 / (32 + 19) = 38 / 51 for every query
    X = np.concatenate([np.arange(20.0), 1000 + np.arange(20.0)])[:, None]
    s = retrieval_scores(distance_matrix(X), [0] * 20 + [1] * 20)
    assert s["e"] == pytest.approx(38 / 51)
    assert s["ft"] == pytest.approx(1.0)


def test_retrieval_query_excluded_and_ties_by_index():
    # all distances 0: the query itself is never returned; ties are ranked by index.
    # labels a a b: query 0 ranks [1, 2] -> G=10, query 1 ranks [0, 2] -> G=10,
    # query 2 (class of one) is left out
    per = retrieval_per_query(np.zeros((3, 3)), ["a", "a", "b"])
    np.testing.assert_allclose(per["nn"][:2], [1, 1])
    assert np.isnan(per["nn"][2])


def test_retrieval_singletons_left_out_of_the_mean():
    # the singleton 'c' adds a NaN query that is not averaged; 'c' is never relevant
    X = np.array([[0.0], [0.1], [5.0], [5.1], [2.5]])
    s = retrieval_scores(distance_matrix(X), ["a", "a", "b", "b", "c"])
    assert s["nn"] == pytest.approx(1.0)
    assert s["map"] == pytest.approx(1.0)


def test_retrieval_min_class_size_like_psbtable():
    # psbTable skips classes of <= 2 models: only the class-b queries B, D, E remain
    s = retrieval_scores(distance_matrix(LINE_X[:, None]), LINE_LABELS, min_class_size=3)
    l3 = 1 / np.log2(3)
    assert s["nn"] == pytest.approx(1 / 3)
    assert s["ft"] == pytest.approx(1 / 3)
    assert s["dcg"] == pytest.approx(((l3 + 0.5) / 2 + 0.75 + (1 + l3) / 2) / 3)
    with pytest.raises(ValueError, match=r"min_class_size must be an integer >= 2"):
        retrieval_scores(distance_matrix(LINE_X[:, None]), LINE_LABELS, min_class_size=1)


def test_retrieval_rejects():
    D = distance_matrix(LINE_X[:, None])
    with pytest.raises(ValueError, match=r"labels has 4 entries but the distance matrix has 5"):
        retrieval_scores(D, LINE_LABELS[:4])
    with pytest.raises(ValueError, match=r"D must be a square"):
        retrieval_scores(D[:, :4], LINE_LABELS)
    bad = D.copy()
    bad[0, 1] = np.nan
    with pytest.raises(ValueError, match=r"D contains NaN"):
        retrieval_scores(bad, LINE_LABELS)
    with pytest.raises(ValueError, match=r"labels has no class of 2 or more models"):
        retrieval_scores(D, list("abcde"))
    with pytest.raises(ValueError, match=r"labels must be a sequence"):
        retrieval_scores(D, "ababa")


# ------------------------------------------------------------------ Descriptor.matrix
@pytest.fixture
def spectra():
    meshes = [shapes.icosphere(2), shapes.icosphere(2, radius=2.0), shapes.torus(24, 12)]
    lams = np.array([shape_dna(m, N=30) for m in meshes])
    areas = np.array([m.area for m in meshes])
    return lams, areas


def test_descriptor_rows_matrix_kinds(spectra):
    lams, areas = spectra
    M, N = 4, 30
    for kind in DESCRIPTOR_KINDS:
        X = Descriptor(kind, N=N, M=M).matrix(lams, areas)
        assert X.shape == (3, {"shape-dna": N, "f1": N - 2,
                               "two-scale": 2 * M + 1 + N - 1}.get(kind, 2 * M + 1)), kind
    sd = Descriptor("shape-dna", N=N, M=M).matrix(lams, areas)
    np.testing.assert_allclose(sd[2], normalize(lams[2], areas[2]))
    np.testing.assert_allclose(Descriptor("truncated", N=N, M=M).matrix(lams, areas),
                               sd[:, : 2 * M + 1])
    np.testing.assert_allclose(Descriptor("cshape", N=N, M=M).matrix(lams, areas)[2],
                               real_form(compact_shape_dna(lams[2], M=M, N=N, area=areas[2])))
    np.testing.assert_allclose(Descriptor("cshape-complex", N=N, M=M).matrix(lams, areas)[2],
                               compact_shape_dna(lams[2], M=M, N=N, area=areas[2]))


def test_descriptor_rows_matrix_real_and_complex_cshape_give_the_same_distances(spectra):
    lams, areas = spectra
    Dr = distance_matrix(Descriptor("cshape", N=30, M=5).matrix(lams, areas))
    Dc = distance_matrix(Descriptor("cshape-complex", N=30, M=5).matrix(lams, areas))
    np.testing.assert_allclose(Dr, Dc, atol=1e-9 * Dr.max())
    # scale invariance: the unit and radius-2 spheres have the same normalised descriptors
    assert Dr[0, 1] < 1e-6 * Dr.max()


def test_descriptor_rows_matrix_ragged_rows(spectra):
    lams, areas = spectra
    rows = [lams[0], lams[1][:20], lams[2]]
    X = Descriptor("shape-dna", N=20).matrix(rows, areas)
    assert X.shape == (3, 20)


def test_descriptor_rows_matrix_rejects(spectra):
    lams, areas = spectra
    with pytest.raises(ValueError, match=r"kind must be one of"):
        Descriptor("heat").matrix(lams, areas)
    with pytest.raises(ValueError, match=r"needs areas"):
        Descriptor("cshape", N=30, M=4).matrix(lams, None)
    with pytest.raises(ValueError, match=r"areas has 2 entries but lams has 3 rows"):
        Descriptor("shape-dna", N=30).matrix(lams, areas[:2])
    with pytest.raises(ValueError, match=r"lams\[1\] has shape \(10,\)"):
        Descriptor("shape-dna", N=30).matrix([lams[0], lams[1][:10]], areas[:2])
    with pytest.raises(ValueError, match=r"2M\+1 = 31 values cannot be kept from N = 30"):
        Descriptor("cshape", N=30, M=15).matrix(lams, areas)
    # F1 needs no area
    assert Descriptor("f1", N=30).matrix(lams, None).shape == (3, 28)


# ------------------------------------------------------------------ MDS and plots
def test_mds_recovers_planar_configuration():
    P = np.random.default_rng(2).normal(size=(8, 2))
    D = distance_matrix(P)
    Y = mds_embedding(D, random_state=0)
    assert Y.shape == (8, 2)
    np.testing.assert_allclose(distance_matrix(Y), D, atol=1e-3 * D.max())
    np.testing.assert_array_equal(Y, mds_embedding(D, random_state=0))  # seeded


def test_mds_is_scikit_learns_mds_from_classical_scaling():
    """The same coordinates as scikit-learn's metric MDS started from classical scaling
    (scikit-learn >= 1.8), on Euclidean distances and on distances no point set has."""
    sklearn = pytest.importorskip("sklearn")
    if tuple(int(x) for x in sklearn.__version__.split(".")[:2]) < (1, 8):
        pytest.skip("init='classical_mds' comes with scikit-learn 1.8")
    from sklearn.manifold import MDS

    rng = np.random.default_rng(5)
    for p, d in ((2, 1), (5, 3), (12, 2), (40, 30)):
        D = distance_matrix(rng.normal(size=(p, d)) * 7.0)
        noisy = D + rng.uniform(0, D.mean(), D.shape)
        noisy = (noisy + noisy.T) / 2
        np.fill_diagonal(noisy, 0)
        for A in (D, noisy):
            theirs = MDS(n_components=2, metric="precomputed", init="classical_mds",
                         max_iter=300, normalized_stress="auto").fit_transform(A)
            np.testing.assert_allclose(mds_embedding(A), theirs, rtol=0,
                                       atol=1e-12 * A.max())


def test_mds_starts_from_classical_scaling_and_lowers_the_stress():
    """Distances of three points on a line are embedded exactly; on distances no point set
    has, the iterations go on lowering the stress after the first one."""
    D = distance_matrix(np.array([[0.0], [1.0], [3.0]]))
    Y = mds_embedding(D)
    np.testing.assert_allclose(distance_matrix(Y), D, atol=1e-12)
    # a line: the second axis is unused (up to the square root of round-off, sqrt(1e-16))
    np.testing.assert_allclose(Y[:, 1], 0, atol=1e-6)
    assert Y[np.argmax(np.abs(Y[:, 0])), 0] > 0  # the largest coordinate is positive

    def stress(Y, A):
        return float(((distance_matrix(Y) - A) ** 2).sum())

    rng = np.random.default_rng(6)
    A = distance_matrix(rng.normal(size=(15, 6)))
    A = A + rng.uniform(0, 1, A.shape)
    A = (A + A.T) / 2
    np.fill_diagonal(A, 0)
    assert stress(mds_embedding(A), A) < stress(mds_embedding(A, max_iter=1), A)


def test_mds_rejects_asymmetric():
    D = np.array([[0.0, 1.0], [2.0, 0.0]])
    with pytest.raises(ValueError, match=r"D must be symmetric"):
        mds_embedding(D)


def test_plots_return_figures_without_pyplot():
    import matplotlib.pyplot as plt
    from matplotlib.figure import Figure

    before = plt.get_fignums()
    D = distance_matrix(LINE_X[:, None])
    fig = plot_mds(mds_embedding(D), names=list("ABCDE"), labels=LINE_LABELS, title="MDS")
    assert isinstance(fig, Figure)
    texts = [t.get_text() for t in fig.axes[0].texts]
    assert texts == list("ABCDE")
    fig2 = plot_distance_matrix(D, names=list("ABCDE"), title="scaled")
    assert isinstance(fig2, Figure)
    np.testing.assert_allclose(fig2.axes[0].images[0].get_array(), scale_255(D))
    assert plt.get_fignums() == before  # nothing registered with pyplot, nothing shown
    # drawing into a given Axes returns that Axes' figure
    fig3 = Figure()
    ax = fig3.add_subplot()
    assert plot_distance_matrix(difference_matrix(D, D**2), scale=False, ax=ax) is fig3
    with pytest.raises(ValueError, match=r"Y must have shape \(p, 2\)"):
        plot_mds(np.zeros((3, 3)))


# ------------------------------------------------------------------ DescriptorIndex
def test_descriptor_index_matches_brute_force():
    rng = np.random.default_rng(3)
    X = rng.normal(size=(200, 9))
    Y = rng.normal(size=(7, 9))
    dist, ind = DescriptorIndex(X).query(Y, k=5)
    full = np.linalg.norm(Y[:, None, :] - X[None, :, :], axis=2)
    np.testing.assert_array_equal(ind, np.argsort(full, axis=1)[:, :5])
    np.testing.assert_allclose(dist, np.sort(full, axis=1)[:, :5])


def test_descriptor_index_self_query_excludes_self_and_complex():
    X = np.array([[0.0], [1.0], [3.0]]) * (1 + 1j)
    index = DescriptorIndex(X)
    dist, ind = index.query(k=1)
    assert ind[:, 0].tolist() == [1, 0, 1]
    np.testing.assert_allclose(dist[:, 0], np.sqrt(2) * np.array([1, 1, 2]))
    _, ind = index.query(np.array([2.9 + 2.9j]), k=1)  # one descriptor of shape (d,)
    assert ind.tolist() == [[2]]


def test_descriptor_index_rejects():
    index = DescriptorIndex(np.zeros((4, 3)))
    with pytest.raises(ValueError, match=r"k must be an integer in \[1, 3\]"):
        index.query(k=4)
    with pytest.raises(ValueError, match=r"Y has descriptors of length 2"):
        index.query(np.zeros((1, 2)), k=1)
    with pytest.raises(ValueError, match=r"Y contains NaN"):
        index.query(np.full((1, 3), np.nan), k=1)


# ------------------------------------------------------------------ transforms beyond the paper
@pytest.mark.parametrize("transform", ["weyl", "log-weyl", "log-weyl-dct"])
def test_descriptor_rows_matrix_transforms(spectra, transform):
    lams, areas = spectra
    X = Descriptor("cshape", N=30, M=4, transform=transform).matrix(lams, areas)
    Xc = Descriptor("cshape-complex", N=30, M=4, transform=transform).matrix(lams, areas)
    assert X.shape == Xc.shape == (3, 9) and X.dtype == np.float64
    for i in range(3):
        np.testing.assert_array_equal(
            X[i], real_form(compact_shape_dna(lams[i], N=30, M=4, area=areas[i],
                                              transform=transform)))
    np.testing.assert_allclose(distance_matrix(X), distance_matrix(Xc), rtol=1e-12, atol=1e-12)
    # the sequence kinds do not use the transform
    np.testing.assert_array_equal(
        Descriptor("truncated", N=30, M=4, transform=transform).matrix(lams, areas),
        Descriptor("truncated", N=30, M=4).matrix(lams, areas))


def test_truncated_log_is_the_truncated_log_spectrum(spectra):
    lams, areas = spectra
    X = Descriptor("truncated-log", N=30, M=4).matrix(lams, areas)
    assert X.shape == (3, 9)
    for i in range(3):  # r_1 .. r_9 = log(lam_i A / (4 pi i))
        np.testing.assert_allclose(
            X[i], np.log(lams[i, 1:10] * areas[i] / (4 * np.pi * np.arange(1, 10))), rtol=1e-13)
    logs = np.log(lams[:, 1:10] * areas[:, None])
    np.testing.assert_allclose(distance_matrix(X), distance_matrix(logs), atol=1e-12)
    with pytest.raises(ValueError, match=r"^M=4: 2M\+1 = 9 values cannot be kept from the N-1 = 8 "
                       r"log-Weyl ratios \(lam_0 has no logarithm\); use M <= 3 or N >= 10$"):
        Descriptor("truncated-log", N=9, M=4).matrix(lams[:, :9], areas)


def test_descriptor_rows_matrix_transform_errors(spectra):
    lams, areas = spectra
    with pytest.raises(ValueError, match=r"transform must be one of"):
        Descriptor("cshape", N=30, M=4, transform="dct").matrix(lams, areas)
    with pytest.raises(ValueError, match=r"N-1 = 29 log-Weyl ratios.*use M <= 14"):
        Descriptor("cshape", N=30, M=15, transform="log-weyl").matrix(lams, areas)
    assert Descriptor("cshape", N=30, M=14, transform="log-weyl").matrix(lams, areas).shape \
        == (3, 29)


def test_index_from_table_queries_spectra_with_its_descriptor(spectra):
    from cshape import DescriptorTable

    lams, areas = spectra
    table = DescriptorTable(["a", "b", "c"], lams, areas)
    d = Descriptor("cshape", N=30, M=4, transform="log-weyl-dct")
    index = DescriptorIndex.from_table(table, d)
    assert index.descriptor_ == d
    np.testing.assert_array_equal(index.X_, table.descriptors(d))
    dist, ind = index.query_spectra(lams[2] * 2.0, areas[2] / 2.0, k=2)  # same normalised lam
    assert ind[0, 0] == 2 and dist[0, 0] < 1e-12
    other = DescriptorIndex.from_table(table, d.replace(transform="weyl", M=2))
    np.testing.assert_allclose(other.X_, Descriptor("cshape", N=30, M=2).matrix(lams, areas))
    with pytest.raises(ValueError, match="build it with DescriptorIndex.from_table"):
        DescriptorIndex(index.X_).query_spectra(lams, areas)
