"""The Descriptor value: checked once, its size and label, rows equal to the functions of the
stages, the shipped PAPER and DEFAULT, and the one M-versus-N rule with one message."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import cshape
from cshape import DEFAULT, PAPER, Descriptor, shapes
from cshape.batch import DescriptorTable
from cshape.descriptor import select_descriptor

N = 30


@pytest.fixture(scope="module")
def spectra():
    meshes = [shapes.icosphere(2), shapes.torus(24, 12), shapes.cube(4)]
    lams = np.array([cshape.shape_dna(m, N=N) for m in meshes])
    areas = np.array([m.area for m in meshes])
    return lams, areas


# ---------------------------------------------------------------------- checked once
@pytest.mark.parametrize("fields, exc, match", [
    (dict(kind="dna"), ValueError, r"^kind must be one of \{'shape-dna', 'truncated', 'cshape', "
     r"'cshape-complex', 'f1', 'truncated-log', 'two-scale'\}, got 'dna'$"),
    (dict(kind=3), TypeError, r"^kind must be one of .*, got int 3$"),
    (dict(M=2.0), TypeError, r"^M must be an integer, got float 2\.0$"),
    (dict(M=-1), ValueError, r"^M must be an integer >= 0, got -1$"),
    (dict(N=True), TypeError, r"^N must be an integer, got bool True$"),
    (dict(N=0), ValueError, r"^N must be an integer >= 1, got 0$"),
    (dict(transform="fft"), ValueError,
     r"^transform must be one of \{'weyl', 'log-weyl', 'log-weyl-dct'\}, got 'fft'$"),
    (dict(normalization="max"), ValueError,
     r"^normalization must be one of \{'area', 'fiedler', 'weyl', 'none'\}, got 'max'$"),
    (dict(M=16, N=30), ValueError,
     r"^M=16: 2M\+1 = 33 values cannot be kept from N = 30 eigenvalues; use M <= 14 or "
     r"N >= 33$"),
    (dict(M=15, N=30, transform="log-weyl-dct"), ValueError,
     r"^M=15: 2M\+1 = 31 values cannot be kept from the N-1 = 29 log-Weyl ratios \(lam_0 "
     r"has no logarithm\); use M <= 14 or N >= 32$"),
    (dict(kind="truncated-log", M=15, N=30), ValueError,
     r"^M=15: 2M\+1 = 31 values cannot be kept from the N-1 = 29 log-Weyl ratios"),
    (dict(kind="truncated", M=15, N=30), ValueError,
     r"^M=15: 2M\+1 = 31 values cannot be kept from N = 30 eigenvalues"),
])
def test_each_bad_field_is_refused_when_made(fields, exc, match):
    with pytest.raises(exc, match=match):
        Descriptor(**fields)


def test_kinds_without_a_crop_take_any_M():
    assert Descriptor("shape-dna", M=40, N=30).size == 30
    assert Descriptor("f1", M=40, N=30).size == 28


def test_frozen_and_compared_by_value():
    d = Descriptor("cshape", M=4, N=30)
    with pytest.raises(dataclasses.FrozenInstanceError):
        d.M = 5  # type: ignore[misc]
    assert d == Descriptor("cshape", 4, 30) and hash(d) == hash(Descriptor("cshape", 4, 30))
    assert d.replace(M=5) == Descriptor("cshape", M=5, N=30) and d.M == 4
    with pytest.raises(ValueError, match=r"^M=15: 2M\+1 = 31 values cannot be kept"):
        d.replace(M=15)  # a copy is checked again


def test_old_spelling_is_stored_in_the_current_one():
    with pytest.warns(DeprecationWarning, match="kind='shape_dna' is deprecated") as rec:
        d = Descriptor("shape_dna", N=20)
    assert d.kind == "shape-dna"
    assert all(r.filename == __file__ for r in rec)  # the warning points at the caller


# ---------------------------------------------------------------------- size and label
@pytest.mark.parametrize("d, size, label", [
    (Descriptor("shape-dna", N=50), 50, "Shape-DNA (50 values)"),
    (Descriptor("truncated", M=4), 9, "truncated Shape-DNA (9 values)"),
    (Descriptor("truncated-log", M=8, normalization="fiedler"), 17,
     "truncated log spectrum, lam_1-normalised (17 values)"),
    (Descriptor("cshape", M=16, N=100), 33, "paper's cShape-DNA (M=16 of N=100, 33 values)"),
    (Descriptor("cshape-complex", M=3, N=20, transform="log-weyl"), 7,
     "log-Weyl DFT cShape-DNA (M=3 of N=20, 7 values)"),
    (Descriptor("cshape", M=8, N=50, transform="log-weyl-dct", normalization="weyl"), 17,
     "log-Weyl DCT cShape-DNA, Weyl-normalised (M=8 of N=50, 17 values)"),
    (Descriptor("f1", N=50, normalization="weyl"), 48, "F1 (N=50, 48 values)"),
    (Descriptor("two-scale", M=4, N=100), 108,
     "two-scale log spectrum (9 first + 99 detrended values)"),
    (Descriptor("two-scale", M=2, N=20, normalization="weyl"), 24,
     "two-scale log spectrum, Weyl-normalised (5 first + 19 detrended values)"),
])
def test_size_and_label(d, size, label):
    assert d.size == size and d.label == label
    assert cshape.compare.descriptor_size(d.kind, d.M, d.N) == size
    assert cshape.compare.descriptor_label(**d.as_dict()) == label


def test_shipped_descriptors():
    assert PAPER == Descriptor("cshape", M=16, N=100, transform="weyl", normalization="area")
    assert DEFAULT == Descriptor("two-scale", M=4, N=100, transform="weyl",
                                 normalization="area")
    assert PAPER.label == "paper's cShape-DNA (M=16 of N=100, 33 values)"
    assert DEFAULT.label == "two-scale log spectrum (9 first + 99 detrended values)"
    # the paper's descriptor is compact_shape_dna's default, and reproduce keeps its numbers
    assert cshape.reproduce.PAPER["3.1"]["M"] == PAPER.M
    assert DEFAULT.for_N(8) == DEFAULT.replace(N=8, M=3)  # M lowered to what N allows
    assert DEFAULT.for_N(1000) == DEFAULT.replace(N=1000)
    with pytest.raises(ValueError, match="needs at least 6 eigenvalues per shape, got N = 5"):
        DEFAULT.for_N(5)
    tl = Descriptor("truncated-log", M=8)
    assert tl.for_N(12) == tl.replace(N=12, M=5)
    with pytest.raises(ValueError, match="needs at least 2 eigenvalues per shape, got N = 1"):
        tl.for_N(1)


# ---------------------------------------------------------------------- rows
def test_paper_row_is_compact_shape_dna_bit_for_bit(spectra):
    lams, areas = spectra
    d = PAPER.replace(M=6, N=N)
    for lam, area in zip(lams, areas, strict=True):
        np.testing.assert_array_equal(
            d.row(lam, area), cshape.real_form(cshape.compact_shape_dna(lam, M=6, N=N,
                                                                        area=area)))
        np.testing.assert_array_equal(
            d.replace(kind="cshape-complex").row(lam, area),
            cshape.compact_shape_dna(lam, M=6, N=N, area=area))


@pytest.mark.parametrize("transform", ["log-weyl", "log-weyl-dct"])
def test_log_weyl_rows_are_compact_shape_dna(spectra, transform):
    lams, areas = spectra
    d = Descriptor("cshape", M=5, N=N, transform=transform)
    for lam, area in zip(lams, areas, strict=True):
        np.testing.assert_array_equal(
            d.row(lam, area),
            cshape.compact_shape_dna_real(lam, M=5, N=N, area=area, transform=transform))


def test_other_rows_are_the_stage_functions(spectra):
    lams, areas = spectra
    lam, area = lams[0], areas[0]
    np.testing.assert_array_equal(Descriptor("shape-dna", N=N).row(lam, area),
                                  cshape.normalize(lam, area))
    np.testing.assert_array_equal(Descriptor("truncated", M=4, N=N).row(lam, area),
                                  cshape.normalize(lam[:9], area))
    np.testing.assert_array_equal(Descriptor("f1", N=N).row(lam), cshape.f1_feature(lam))
    np.testing.assert_array_equal(
        Descriptor("truncated-log", M=8, N=N).row(lam, area),
        cshape.log_weyl_ratio(cshape.normalize(lam[:18], area)))


def test_two_scale_row_is_first_ratios_beside_detrended_ratios(spectra):
    from cshape.descriptor import TWO_SCALE_WEIGHT
    from cshape.descriptors import detrend

    lams, areas = spectra
    d = Descriptor("two-scale", M=4, N=N)
    for lam, area in zip(lams, areas, strict=True):
        r = cshape.log_weyl_ratio(cshape.normalize(lam, area))  # r_1 .. r_29
        row = d.row(lam, area)
        assert row.shape == (d.size,) == (9 + 29,)
        np.testing.assert_array_equal(row[:9], Descriptor("truncated-log", M=4, N=N).row(lam, area))
        np.testing.assert_allclose(row[9:], TWO_SCALE_WEIGHT * detrend(r), atol=1e-14)
    # the second block is scale free: another normalisation shifts r by a constant only
    lam, area = lams[1], areas[1]
    np.testing.assert_allclose(d.replace(normalization="weyl").row(lam)[9:], d.row(lam, area)[9:],
                               atol=1e-12)
    # a smooth drift of the ratios up to the trend's degree (a coarse mesh) leaves it alone
    i = np.arange(1, N)
    drift = np.r_[1.0, np.exp(0.02 + 1e-3 * i - 1e-6 * i**3)]
    np.testing.assert_allclose(d.row(lam * drift, area)[9:], d.row(lam, area)[9:], atol=1e-12)
    with pytest.raises(ValueError, match=r"^kind='two-scale' detrends the N-1 log-Weyl ratios "
                                         r"by a polynomial of degree 3, which needs N >= 6, "
                                         r"got N = 5"):
        Descriptor("two-scale", M=1, N=5)
    with pytest.raises(ValueError, match=r"kind='two-scale' needs 2M\+1 = 9 non-zero "
                                         r"eigenvalues, but 25 of the N = 30 are zero modes"):
        d.row(np.r_[np.zeros(25), lam[25:]], area, zero_modes=25)


def test_detrend_refuses_what_it_cannot_fit():
    from cshape.descriptors import detrend

    t = np.arange(1, 8) / 7
    np.testing.assert_allclose(detrend(2 - t + 3 * t**2, degree=2), 0, atol=1e-12)
    assert abs(float(detrend(np.r_[0.0, 0, 0, 1, 0, 0, 0]) @ t**3)) < 1e-12
    with pytest.raises(ValueError, match=r"^r has 4 values but a polynomial of degree 3 needs "
                                         r"at least 5"):
        detrend(np.ones(4))
    with pytest.raises(TypeError, match=r"^degree must be an integer"):
        detrend(np.ones(8), degree=2.0)
    with pytest.raises(TypeError, match=r"^r must be real"):
        detrend(np.ones(8) + 0j)


def test_matrix_is_descriptor_matrix_and_names_what_it_cannot_describe(spectra):
    lams, areas = spectra
    tl = Descriptor("truncated-log", M=8, N=N)
    for d in (PAPER.replace(M=4, N=N), tl, DEFAULT.for_N(N), Descriptor("f1", N=N)):
        X = d.matrix(lams, areas)
        assert X.shape == (3, d.size)
        np.testing.assert_array_equal(X, cshape.descriptor_matrix(lams, areas, **d.as_dict()))
        np.testing.assert_array_equal(X, cshape.descriptor_matrix(lams, areas, descriptor=d))
    bad = lams.copy()
    bad[1, :20] = 0.0  # 20 zero modes: 10 non-zero eigenvalues, fewer than 2M+1 = 17
    X, problems = tl.rows(bad, areas)
    assert X.shape == (2, 17) and list(problems) == [1]
    with pytest.raises(ValueError, match=r"kind='truncated-log' cannot describe 1 of 3 "
                                         r"shapes \(torus: 20 of its 30 eigenvalues"):
        tl.matrix(bad, areas, names=["sphere", "torus", "cube"])
    with pytest.raises(ValueError, match=r"^kind='cshape' with normalization='area' needs "
                                         r"the surface area: pass area=$"):
        PAPER.replace(M=4, N=N).row(lams[0])
    with pytest.raises(ValueError, match=r"lam has shape \(30,\) but kind='cshape' needs at "
                                         r"least 100 eigenvalues"):
        PAPER.row(lams[0], areas[0])


def test_normalization_none_takes_normalised_eigenvalues(spectra):
    lams, areas = spectra
    lam_norm = cshape.normalize(lams[0], areas[0])
    np.testing.assert_array_equal(
        cshape.compact_shape_dna(lam_norm, M=4, N=N, normalization="none"),
        cshape.compact_shape_dna(lams[0], M=4, N=N, area=areas[0]))
    np.testing.assert_array_equal(
        Descriptor("cshape", M=4, N=N, normalization="none").row(lam_norm),
        PAPER.replace(M=4, N=N).row(lams[0], areas[0]))
    assert Descriptor("shape-dna", N=N, normalization="none").label == (
        "Shape-DNA, eigenvalues as given (30 values)")
    with pytest.raises(ValueError, match=r"normalization='none' \(eigenvalues already "
                                         r"normalised\), not both"):
        cshape.compact_shape_dna(lam_norm, M=4, N=N, area=1.0, normalization="none")
    with pytest.raises(TypeError, match="unexpected keyword argument 'normalized'"):
        cshape.compact_shape_dna(lam_norm, M=4, N=N, normalized=True)


# ---------------------------------------------------------------------- one rule, one message
def test_one_M_versus_N_message_everywhere():
    msg = r"^M=8: 2M\+1 = 17 values cannot be kept from N = 12 eigenvalues; use M <= 5 or N >= 17$"
    lam = 4 * np.pi * np.arange(12.0)
    with pytest.raises(ValueError, match=msg):
        Descriptor("cshape", M=8, N=12)
    with pytest.raises(ValueError, match=msg):
        cshape.compact_shape_dna(lam, M=8, N=12, normalization="none")
    with pytest.raises(ValueError, match=msg):
        cshape.descriptor_matrix(lam[None, :], [1.0], "cshape", M=8, N=12)
    with pytest.raises(ValueError, match=msg):
        cshape.describe([shapes.icosphere(1)], N=12, M=8, cache_dir=False, progress=False)
    log = (r"^M=8: 2M\+1 = 17 values cannot be kept from the N-1 = 12 log-Weyl ratios \(lam_0 "
           r"has no logarithm\); use M <= 5 or N >= 18$")
    with pytest.raises(ValueError, match=log):
        Descriptor("cshape", M=8, N=13, transform="log-weyl")
    with pytest.raises(ValueError, match=log):
        Descriptor("truncated-log", M=8, N=13)
    with pytest.raises(ValueError, match=log):
        cshape.compact_shape_dna(np.r_[lam, 200.0], M=8, N=13, normalization="none",
                                 transform="log-weyl-dct")
    with pytest.raises(ValueError, match=log):
        cshape.describe([shapes.icosphere(1)], N=13, M=8, transform="log-weyl",
                        cache_dir=False, progress=False)


# ---------------------------------------------------------------------- the surfaces take one
@pytest.fixture(scope="module")
def table(spectra):
    lams, areas = spectra
    return DescriptorTable(["sphere", "torus", "cube"], lams, areas, ["a", "b", "c"], M=4)


def test_surfaces_take_a_descriptor(table):
    d = PAPER.replace(M=4, N=N)
    np.testing.assert_array_equal(table.descriptors(descriptor=d), table.descriptors("cshape"))
    np.testing.assert_array_equal(table.distance_matrix(descriptor=d),
                                  table.distance_matrix("cshape"))
    assert table.descriptor_for() == DEFAULT.for_N(N)
    assert table.descriptor_for("cshape") == d
    index = cshape.DescriptorIndex.from_table(table, descriptor=d)
    assert index.descriptor_ == d and index.descriptor == d.label
    assert index.recipe_ == d.as_dict()
    dist, ind = index.query_spectra(table.lam[1], table.areas[1], k=1)
    assert ind[0, 0] == 1 and dist[0, 0] == 0.0
    pytest.importorskip("matplotlib")
    from cshape.plots.explore import collection_distances

    c = collection_distances(table, descriptor=d)
    np.testing.assert_array_equal(c.D, table.distance_matrix("cshape"))
    assert c.descriptor == d.label and c.kind == "cshape"


def test_descriptor_and_fields_are_not_both_given(table):
    with pytest.raises(ValueError, match=r"^pass either descriptor= or kind, M, not both"):
        table.descriptors("cshape", M=3, descriptor=PAPER)
    with pytest.raises(TypeError, match=r"^descriptor must be a cshape.Descriptor \(e.g. "
                                        r"cshape.PAPER\), got dict$"):
        select_descriptor(PAPER.as_dict())  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"unexpected keyword argument 'zero_mode'"):
        table.descriptors(zero_mode=1)


def test_reproduce_takes_the_papers_descriptor_and_refuses_another(tmp_path):
    from cshape.reproduce import reproduce
    from cshape.reproduce.report import _paper_descriptor

    assert _paper_descriptor(None, 30, 4) == PAPER.replace(N=30, M=4)
    assert _paper_descriptor(None, None, None) == PAPER
    assert _paper_descriptor(PAPER.replace(M=8), None, None) == PAPER.replace(M=8)
    out = tmp_path / "report"
    with pytest.raises(ValueError, match=r"^reproduce compares the paper's cShape-DNA, got "
                                         r"two-scale log spectrum \(9 first \+ 99 "
                                         r"detrended values\)"):
        reproduce([], out, descriptor=DEFAULT)
    with pytest.raises(ValueError, match=r"^pass either descriptor= or N and M, not both"):
        reproduce([], out, N=30, descriptor=PAPER)
    with pytest.raises(TypeError, match=r"^descriptor must be a cshape.Descriptor"):
        reproduce([], out, descriptor="paper")
    assert not out.exists()  # refused before any work
