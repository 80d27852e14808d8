"""The Descriptor value: checked once, its size and label, rows equal to the formulas (and to
an independent computation of Eq. 8-10, bit for bit), the shipped PAPER and DEFAULT, the one
M-versus-N rule with one message, and the surfaces that take a Descriptor."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

import cshape
from cshape import DEFAULT, PAPER, Descriptor, shapes
from cshape.batch import DescriptorTable
from cshape.descriptors import log_weyl_ratio, real_form
from cshape.descriptors.formulas import f1_feature

N = 30
#: The truncated log spectrum (the default before the two-scale log spectrum).
TL = Descriptor("truncated-log", N=100, M=8)


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
    assert d == Descriptor("cshape", N=30, M=4)
    assert hash(d) == hash(Descriptor("cshape", N=30, M=4))
    assert d.replace(M=5) == Descriptor("cshape", M=5, N=30) and d.M == 4
    with pytest.raises(ValueError, match=r"^M=15: 2M\+1 = 31 values cannot be kept"):
        d.replace(M=15)  # a copy is checked again


def test_a_kind_has_one_spelling():
    with pytest.raises(ValueError, match="kind must be one of .*, got 'shape_dna'"):
        Descriptor("shape_dna", N=20)
    assert Descriptor("Shape-DNA", N=20).kind == "shape-dna"  # lower-cased


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
])
def test_size_and_label(d, size, label):
    assert d.size == size and d.label == label
    assert d.matrix(4 * np.pi * np.arange(100.0)[None, :] * [[1.0], [1.1]],
                    np.ones(2)).shape == (2, size)


def test_N_and_M_are_keywords_N_first():
    d = Descriptor("cshape", N=50, M=8)
    assert [f.name for f in dataclasses.fields(d)] == ["kind", "N", "M", "transform",
                                                       "normalization"]
    assert repr(d) == ("Descriptor(kind='cshape', N=50, M=8, transform='weyl', "
                       "normalization='area')")
    with pytest.raises(TypeError, match="positional argument"):
        Descriptor("cshape", 8, 50)  # type: ignore[misc]
    with pytest.raises(TypeError, match="positional argument"):
        cshape.compact_shape_dna(np.arange(50.0), 8, 50)  # type: ignore[misc]


def test_shipped_descriptors():
    assert PAPER == Descriptor("cshape", N=100, M=16, transform="weyl", normalization="area")
    assert DEFAULT == Descriptor("two-scale", N=100, M=4, transform="weyl",
                                 normalization="area")
    assert PAPER.label == "paper's cShape-DNA (M=16 of N=100, 33 values)"
    assert DEFAULT.label == "two-scale log spectrum (9 first + 99 detrended values)"
    assert DEFAULT.size == 108
    # the paper's descriptor is compact_shape_dna's default, and reproduce keeps its numbers
    assert cshape.reproduce.PAPER_RESULTS["3.1"]["M"] == PAPER.M
    assert DEFAULT.for_N(8) == DEFAULT.replace(N=8, M=3)  # M lowered to what N allows
    assert DEFAULT.for_N(1000) == DEFAULT.replace(N=1000)
    with pytest.raises(ValueError, match="needs at least 6 eigenvalues per shape, got N = 5"):
        DEFAULT.for_N(5)
    tl = Descriptor("truncated-log", N=100, M=8)
    assert tl.for_N(12) == tl.replace(N=12, M=5)
    with pytest.raises(ValueError, match="needs at least 2 eigenvalues per shape, got N = 1"):
        tl.for_N(1)


# ---------------------------------------------------------------------- rows
def test_paper_row_is_compact_shape_dna_bit_for_bit(spectra):
    lams, areas = spectra
    d = PAPER.replace(M=6, N=N)
    for lam, area in zip(lams, areas, strict=True):
        np.testing.assert_array_equal(
            d.row(lam, area), real_form(cshape.compact_shape_dna(lam, M=6, N=N,
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
            real_form(cshape.compact_shape_dna(lam, M=5, N=N, area=area,
                                                      transform=transform)))


def test_other_rows_are_the_stage_functions(spectra):
    lams, areas = spectra
    lam, area = lams[0], areas[0]
    np.testing.assert_array_equal(Descriptor("shape-dna", N=N).row(lam, area),
                                  cshape.normalize(lam, area))
    np.testing.assert_array_equal(Descriptor("truncated", M=4, N=N).row(lam, area),
                                  cshape.normalize(lam[:9], area))
    np.testing.assert_array_equal(Descriptor("f1", N=N).row(lam), f1_feature(lam))
    np.testing.assert_array_equal(
        TL.for_N(N).row(lam, area),
        log_weyl_ratio(cshape.normalize(lam[:18], area)))


def test_matrix_stacks_the_rows_and_names_what_it_cannot_describe(spectra):
    lams, areas = spectra
    for d in (PAPER.replace(M=4, N=N), TL.for_N(N), Descriptor("f1", N=N)):
        X = d.matrix(lams, areas)
        assert X.shape == (3, d.size)
        np.testing.assert_array_equal(
            X, np.vstack([d.row(lam, a) for lam, a in zip(lams, areas, strict=True)]))
        X2, problems = d._rows(list(lams), areas)
        np.testing.assert_array_equal(X2, X)
        assert problems == {}
    bad = lams.copy()
    bad[1, :20] = 0.0  # 20 zero modes: 10 non-zero eigenvalues, fewer than 2M+1 = 17
    X, problems = TL.for_N(N)._rows(bad, areas)
    assert X.shape == (2, 17) and list(problems) == [1]
    with pytest.raises(ValueError, match=r"kind='truncated-log' cannot describe 1 of 3 "
                                         r"shapes \(torus: 20 of its 30 eigenvalues"):
        TL.for_N(N).matrix(bad, areas, names=["sphere", "torus", "cube"])
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
    log = (r"^M=8: 2M\+1 = 17 values cannot be kept from the N-1 = 12 log-Weyl ratios \(lam_0 "
           r"has no logarithm\); use M <= 5 or N >= 18$")
    with pytest.raises(ValueError, match=log):
        Descriptor("cshape", M=8, N=13, transform="log-weyl")
    with pytest.raises(ValueError, match=log):
        Descriptor("truncated-log", M=8, N=13)
    with pytest.raises(ValueError, match=log):
        cshape.compact_shape_dna(np.r_[lam, 200.0], M=8, N=13, normalization="none",
                                 transform="log-weyl-dct")


# ---------------------------------------------------------------------- the same bits
#: A fixed spectrum (ascending, lam_0 = 0) and area, and values of the rows computed before
#: the descriptor modules moved into cshape/descriptors/ (cshape at ca9e8df).
_LAM = np.arange(100.0) + 0.3 * np.sin(np.arange(100.0))
_AREA = 3.0
_PAPER_ROW = {0: -47353.1932659132, 1: 676.9278806773906, 2: -21524.770493301017,
              31: 660.2928254668889, 32: -1291.2420125881642}
_DEFAULT_ROW = {0: -1.207317275329019, 1: -1.3045513268218625, 2: -1.4183986047880586,
                15: -1.4378247683494747, 16: -1.4495233650360373}


def _paper_by_hand(lam, area, N=100, M=16):
    """Eq. (8)-(10) with numpy alone: normalise, subtract 4 pi i, DFT, shift, crop."""
    lam_prime = lam[:N] * area - 4.0 * np.pi * np.arange(N)  # Eq. (8)
    shifted = np.fft.fftshift(np.fft.fft(lam_prime))  # Eq. (9), zero frequency at N // 2
    return shifted[N // 2 - M: N // 2 + M + 1]  # Eq. (10)


def test_the_papers_descriptor_is_eq_8_to_10_bit_for_bit():
    S = _paper_by_hand(_LAM, _AREA)
    np.testing.assert_array_equal(cshape.compact_shape_dna(_LAM, area=_AREA), S)
    np.testing.assert_array_equal(PAPER.replace(kind="cshape-complex").row(_LAM, _AREA), S)
    real = np.empty(33)
    real[0] = S[16].real
    real[1::2] = np.sqrt(2.0) * S[17:].real
    real[2::2] = np.sqrt(2.0) * S[17:].imag
    np.testing.assert_array_equal(PAPER.row(_LAM, _AREA), real)
    np.testing.assert_allclose(PAPER.row(_LAM, _AREA)[list(_PAPER_ROW)],
                               list(_PAPER_ROW.values()), rtol=1e-12)
    # a mesh's: its eigensolve, then the same formula on its spectrum and area
    mesh = shapes.icosphere(2)
    lam = cshape.shape_dna(mesh, N=100)
    np.testing.assert_array_equal(cshape.compact_shape_dna(lam, area=mesh.area),
                                  _paper_by_hand(lam, mesh.area))


def test_the_truncated_log_spectrum_bit_for_bit():
    i = np.arange(1, 18)
    by_hand = np.log(_LAM[1:18] * _AREA / (4.0 * np.pi * i))
    np.testing.assert_array_equal(TL.row(_LAM, _AREA), by_hand)
    np.testing.assert_allclose(TL.row(_LAM, _AREA)[list(_DEFAULT_ROW)],
                               list(_DEFAULT_ROW.values()), rtol=1e-12)


def test_the_default_is_the_two_scale_log_spectrum_by_hand():
    i = np.arange(1, 100)
    r = np.log(_LAM[1:] * _AREA / (4.0 * np.pi * i))
    t = i / 99
    V = np.vander(t, 4)
    trend = V @ np.linalg.lstsq(V, r, rcond=None)[0]
    np.testing.assert_allclose(DEFAULT.row(_LAM, _AREA), np.r_[r[:9], 2.0 * (r - trend)],
                               rtol=0, atol=1e-13)


# ---------------------------------------------------------------------- the surfaces take one
@pytest.fixture(scope="module")
def table(spectra):
    lams, areas = spectra
    return DescriptorTable(["sphere", "torus", "cube"], lams, areas, ["a", "b", "c"])


def test_surfaces_take_a_descriptor(table, spectra):
    lams, areas = spectra
    d = PAPER.replace(M=4, N=N)
    np.testing.assert_array_equal(table.descriptors(d), d.matrix(lams, areas))
    np.testing.assert_array_equal(table.descriptors(), DEFAULT.for_N(N).matrix(lams, areas))
    np.testing.assert_array_equal(table.distance_matrix(descriptor=d),
                                  cshape.distance_matrix(d.matrix(lams, areas)))
    index = cshape.DescriptorIndex.from_table(table, d)
    assert index.descriptor_ == d
    assert cshape.DescriptorIndex.from_table(table).descriptor_ == DEFAULT.for_N(N)
    dist, ind = index.query_spectra(table.lam[1], table.areas[1], k=1)
    assert ind[0, 0] == 1 and dist[0, 0] == 0.0
    c = cshape.batch.table.collection_distances(table, d)
    np.testing.assert_array_equal(c.D, table.distance_matrix(d))
    assert c.descriptor == d and c.left_out == [] and c.rows.tolist() == [0, 1, 2]


@pytest.mark.parametrize("call", [
    lambda t: t.descriptors("cshape"),
    lambda t: t.distance_matrix("shape-dna"),
    lambda t: t.described("f1"),
    lambda t: cshape.DescriptorIndex.from_table(t, "cshape"),
    lambda t: cshape.batch.table.collection_distances(t, "cshape"),
])
def test_a_kind_by_name_is_refused_with_the_fix(table, call):
    with pytest.raises(TypeError, match=r"^descriptor must be a cshape.Descriptor \(e.g. "
                                        r"cshape.PAPER\) or None \(cshape.DEFAULT\), got str "
                                        r"\(a kind: Descriptor\('(cshape|shape-dna|f1)', "
                                        r"N=\.\.\.\)\)$"):
        call(table)


def test_a_descriptor_needing_more_eigenvalues_than_the_table_holds(table):
    with pytest.raises(ValueError, match=r"lams\[0\] has shape \(30,\) but kind='cshape' "
                                         r"needs at least 100 eigenvalues"):
        table.descriptors(PAPER)


def test_the_table_says_what_it_holds(table):
    assert repr(table) == "DescriptorTable(3 shapes, N=30, mass='consistent', 3 classes)"
    # the area-normalised eigenvalues are one descriptor of the table, not a second way
    np.testing.assert_array_equal(table.descriptors(Descriptor("shape-dna", N=N)),
                                  table.lam * table.areas[:, None])
    for gone in ("M", "transform", "shape_dna", "cshape", "f1", "recipe", "describe_recipe",
                 "descriptor_for", "lam_norm", "usable"):
        assert not hasattr(table, gone), gone


def test_the_command_line_describe_takes_no_M_and_query_honours_it(table, tmp_path, capsys):
    """`cshape describe` computes eigenvalues only (no -M it would store and not use);
    `cshape query -M` changes the descriptor it compares and says so."""
    from conftest import write_off

    from cshape.cli import main

    write_off(tmp_path / "m" / "one.off", shapes.icosphere(1))
    with pytest.raises(SystemExit) as stop:  # argparse's own one-line error
        main(["describe", str(tmp_path / "m"), "-N", "5", "-M", "1", "--no-cache"])
    assert stop.value.code == 2
    assert "unrecognized arguments: -M 1" in capsys.readouterr().err
    path = table.save(tmp_path / "t.npz")
    got = {}
    for M in ("2", "4"):
        assert main(["query", str(path), "sphere", "-k", "2", "-M", M, "--json"]) == 0
        got[M] = json.loads(capsys.readouterr().out)
        assert (got[M]["kind"], got[M]["M"]) == ("two-scale", int(M))
        assert got[M]["descriptor"] == DEFAULT.replace(N=N, M=int(M)).label
    d2 = {n["name"]: n["distance"] for n in got["2"]["neighbours"]}
    d4 = {n["name"]: n["distance"] for n in got["4"]["neighbours"]}
    X = DEFAULT.replace(N=N, M=2).matrix(table.lam, table.areas)
    assert d2["torus"] == pytest.approx(np.linalg.norm(X[0] - X[1]), rel=1e-12)
    assert d2 != d4  # -M is used
    assert main(["query", str(path), "sphere", "--kind", "cshape", "-M", "15"]) == 2
    assert "M=15: 2M+1 = 31 values cannot be kept from N = 30" in capsys.readouterr().err


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


# ---------------------------------------------------------------------- the two-scale kind
def test_two_scale_size_label_and_errors():
    d = Descriptor("two-scale", N=100, M=4)
    assert d.size == 108 and d.label == "two-scale log spectrum (9 first + 99 detrended values)"
    w = Descriptor("two-scale", N=20, M=2, normalization="weyl")
    assert w.size == 24
    assert w.label == "two-scale log spectrum, Weyl-normalised (5 first + 19 detrended values)"
    with pytest.raises(ValueError, match=r"^kind='two-scale' detrends the N-1 log-Weyl ratios "
                                         r"by a polynomial of degree 3, which needs N >= 6, "
                                         r"got N = 5"):
        Descriptor("two-scale", N=5, M=1)
    with pytest.raises(ValueError, match=r"^M=15: 2M\+1 = 31 values cannot be kept from the "
                                         r"N-1 = 29 log-Weyl ratios"):
        Descriptor("two-scale", N=30, M=15)


def test_two_scale_row_is_first_ratios_beside_detrended_ratios(spectra):
    from cshape.descriptors import detrend
    from cshape.descriptors.recipe import TWO_SCALE_WEIGHT

    lams, areas = spectra
    d = Descriptor("two-scale", N=N, M=4)
    for lam, area in zip(lams, areas, strict=True):
        r = log_weyl_ratio(cshape.normalize(lam, area))  # r_1 .. r_29
        row = d.row(lam, area)
        assert row.shape == (d.size,) == (9 + 29,)
        np.testing.assert_array_equal(row[:9],
                                      Descriptor("truncated-log", N=N, M=4).row(lam, area))
        np.testing.assert_allclose(row[9:], TWO_SCALE_WEIGHT * detrend(r), atol=1e-14)
    X = d.matrix(lams, areas)
    assert X.shape == (3, d.size)
    # the second block is scale free: another normalisation shifts r by a constant only
    lam, area = lams[1], areas[1]
    np.testing.assert_allclose(d.replace(normalization="weyl").row(lam)[9:],
                               d.row(lam, area)[9:], atol=1e-12)
    # a smooth drift of the ratios up to the trend's degree (a coarse mesh) leaves it alone
    i = np.arange(1, N)
    drift = np.r_[1.0, np.exp(0.02 + 1e-3 * i - 1e-6 * i**3)]
    np.testing.assert_allclose(d.row(lam * drift, area)[9:], d.row(lam, area)[9:], atol=1e-12)
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
