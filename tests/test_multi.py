"""Meshes of several pieces (issue 19): one rule for every descriptor, and no mesh fails a
whole table, query or summary.

Known answers: two disjoint unit spheres have the spectrum 0, 0, 2 (x6), 6 (x10), ... and
the total area 8 pi; two copies of one shape have every eigenvalue of the shape twice, so
with the total area and the zero modes dropped (index from 1) their log-Weyl ratios at even
indices are the shape's own, exactly.
"""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest
from conftest import write_off

import cshape
from cshape import Descriptor, shapes
from cshape.batch import DescriptorTable, describe
from cshape.descriptors import log_weyl_ratio
from cshape.descriptors.formulas import ZERO_RTOL, f1_feature, nonzero_eigenvalues

N, M = 30, 4
FOUR_PI = 4 * np.pi


def copies(mesh, k, gap=5.0):
    """``k`` copies of ``mesh`` side by side along x: one mesh of ``k`` components."""
    V, F = mesh.vertices, mesh.faces
    return cshape.Mesh(np.vstack([V + [gap * i, 0, 0] for i in range(k)]),
                       np.vstack([F + i * len(V) for i in range(k)]))


@pytest.fixture(scope="module")
def sphere():
    return shapes.icosphere(2)  # 162 vertices: the unit sphere's spectrum within 5 %


@pytest.fixture(scope="module")
def spectra(sphere):
    """(lam, area) of one sphere, two spheres and a dozen spheres (N eigenvalues each)."""
    out = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cshape.CShapeWarning)
        for k in (1, 2, 12):
            m = copies(sphere, k)
            out[k] = (cshape.shape_dna(m, N=N), m.area)
    return out


@pytest.fixture(scope="module")
def table(spectra):
    """A table of a torus, the sphere, two spheres and twelve spheres (components stored)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cshape.CShapeWarning)
        torus = shapes.torus(24, 12)
        lam_t = cshape.shape_dna(torus, N=N)
    names = ["torus", "sphere", "two", "dozen"]
    lam = np.array([lam_t, spectra[1][0], spectra[2][0], spectra[12][0]])
    areas = [torus.area, spectra[1][1], spectra[2][1], spectra[12][1]]
    return DescriptorTable(names, lam, areas, ["t", "s", "s", "s"], components=[1, 1, 2, 12])


# ------------------------------------------------------------------ the rule
def test_two_unit_spheres_known_spectrum_and_area(sphere, spectra):
    lam, area = spectra[2]
    assert area == pytest.approx(8 * np.pi, rel=2e-2)  # icosphere(2): 1.9 % below
    assert lam[0] == lam[1] == 0.0  # the solver sets round-off zero modes to 0
    np.testing.assert_allclose(lam[2:8], 2.0, rtol=3e-2)  # l = 1, twice: 2 x 3
    np.testing.assert_allclose(lam[8:18], 6.0, rtol=5e-2)  # l = 2, twice: 2 x 5
    assert lam[18] > 11.0
    assert cshape.descriptors.count_zero_modes(lam) == 2
    mu = nonzero_eigenvalues(lam)
    np.testing.assert_array_equal(mu, lam[2:])  # zero modes dropped, the rest from index 1
    np.testing.assert_array_equal(nonzero_eigenvalues(lam, 2), mu)


def test_log_weyl_ratio_of_a_disjoint_union_uses_the_total_area(spectra):
    """Two copies: mu_{2j-1} = mu_{2j} = lam_j, area 2A, so r_{2j} = r_j of one copy."""
    (lam1, a1), (lam2, a2) = spectra[1], spectra[2]
    assert a2 == pytest.approx(2 * a1, rel=1e-12)
    r1 = log_weyl_ratio(cshape.normalize(lam1, a1))
    r2 = log_weyl_ratio(cshape.normalize(lam2, a2))
    assert len(r1) == N - 1 and len(r2) == N - 2
    np.testing.assert_allclose(r2[1::2], r1[: len(r2[1::2])], rtol=0, atol=1e-6)
    # the odd indices: r_{2j-1} = r_j + log(2j / (2j - 1))
    j = np.arange(1, len(r2[0::2]) + 1)
    np.testing.assert_allclose(r2[0::2], r1[: len(j)] + np.log(2 * j / (2 * j - 1)),
                               atol=1e-6)


def test_connected_spectra_give_the_same_bits_as_before(spectra):
    lam, area = spectra[1]
    x = cshape.normalize(lam, area)
    np.testing.assert_array_equal(log_weyl_ratio(x),
                                  np.log(x[1:] / (FOUR_PI * np.arange(1, N))))
    np.testing.assert_array_equal(f1_feature(lam), lam[1] / lam[2:])
    # compact_shape_dna's default, the paper, takes any spectrum as it is: Eq. (8)-(10)
    for k in (1, 2, 12):
        lam_k, a_k = spectra[k]
        lp = lam_k * a_k - FOUR_PI * np.arange(N)
        ref = np.fft.fftshift(np.fft.fft(lp))[N // 2 - M: N // 2 + M + 1]
        np.testing.assert_array_equal(cshape.compact_shape_dna(lam_k, M=M, N=N, area=a_k), ref)


def test_fixed_length_descriptors_extend_by_weyls_law(spectra):
    lam, area = spectra[2]
    x = cshape.normalize(lam, area)
    r = log_weyl_ratio(x, length=N - 1)
    assert len(r) == N - 1 and r[-1] == r[-2]  # the one missing ratio repeats the last
    np.testing.assert_array_equal(r[:-1], log_weyl_ratio(x))
    f = f1_feature(lam, length=N - 2)
    mu = lam[2:]
    np.testing.assert_allclose(f[:-1], mu[0] / mu[1:])
    assert f[-1] == pytest.approx(mu[0] / (mu[-1] * (N - 1) / (N - 2)))
    for transform in ("log-weyl", "log-weyl-dct"):
        S = cshape.compact_shape_dna(x, M=M, N=N, normalization="none", transform=transform)
        assert S.shape == (2 * M + 1,) and np.all(np.isfinite(S))


def test_every_kind_describes_a_multi_piece_mesh(spectra):
    lam, area = spectra[2]
    for kind in cshape.descriptors.recipe.DESCRIPTOR_KINDS:
        for transform in cshape.descriptors.formulas.TRANSFORMS:
            X = Descriptor(kind, N=N, M=M, transform=transform).matrix([lam], [area])
            assert X.shape == (1, {"shape-dna": N, "f1": N - 2, "two-scale": 2 * M + N}.get(
                kind, 2 * M + 1))
            assert np.all(np.isfinite(X))


def test_compact_shape_dna_counts_the_zero_modes_of_a_mesh_of_pieces(sphere):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cshape.CShapeWarning)
        two = copies(sphere, 2)
        lam = cshape.shape_dna(two, N=N)
    S = cshape.compact_shape_dna(lam, M=M, N=N, area=two.area, transform="log-weyl-dct")
    ref = cshape.compact_shape_dna(lam, M=M, N=N, area=two.area, transform="log-weyl-dct",
                                   zero_modes=2)
    np.testing.assert_allclose(S, ref, rtol=1e-10, atol=1e-12)


def test_the_zero_threshold_is_relative(spectra):
    lam, _ = spectra[2]
    for scale in (1e-9, 1.0, 1e9):  # meshes in any unit
        assert cshape.descriptors.count_zero_modes(lam * scale) == 2
    noisy = lam.copy()
    noisy[:2] = np.array([-3e-10, 4e-10]) * lam.max()  # round-off on the zero modes
    assert cshape.descriptors.count_zero_modes(noisy) == 2
    assert cshape.descriptors.count_zero_modes(noisy, rtol=1e-12) == 1
    assert ZERO_RTOL == 1e-5


def test_other_solvers_round_off_on_lam0_is_a_zero_mode():
    # a connected icosphere's spectrum as another solver returns it: lam_0 slightly negative
    # (ARPACK on a real mesh: -2.6e-8 of lam_99) or stored in float32
    mesh = shapes.icosphere(3)
    lam = cshape.shape_dna(mesh, N=50)
    ref = cshape.compact_shape_dna(lam, M=8, N=50, area=mesh.area, transform="log-weyl")
    for lam0 in (-2.6e-8, 3e-7, -1e-6):
        other = lam.copy()
        other[0] = lam0 * lam.max()
        assert cshape.descriptors.count_zero_modes(other) == 1
        S = cshape.compact_shape_dna(other, M=8, N=50, area=mesh.area, transform="log-weyl")
        np.testing.assert_array_equal(S, ref)  # lam_0 is dropped: the same bits
    single = lam.astype(np.float32)
    assert cshape.descriptors.count_zero_modes(single) == 1
    S32 = cshape.compact_shape_dna(single, M=8, N=50, area=mesh.area, transform="log-weyl")
    np.testing.assert_allclose(S32, ref, rtol=1e-5, atol=1e-6)
    # a real non-zero lam_1 is never taken for a zero mode: the smallest measured on a
    # connected real mesh is 4.9e-4 of its largest
    assert ZERO_RTOL < 4.9e-4 / 10


def test_a_known_piece_count_beats_the_threshold(spectra):
    lam, _ = spectra[2]  # two pieces
    noisy = lam.copy()
    noisy[1] = 3 * ZERO_RTOL * lam.max()  # round-off above the threshold on one zero mode
    assert cshape.descriptors.count_zero_modes(noisy) == 1
    assert nonzero_eigenvalues(noisy, zero_modes=2).tolist() == lam[2:].tolist()
    # but eigenvalues that cannot be the mesh's are refused, with the reason
    wrong = lam.copy()
    wrong[1] = 0.5 * lam[2]
    with pytest.raises(ValueError, match="zero_modes=2 .*is not zero"):
        nonzero_eigenvalues(wrong, zero_modes=2)


@pytest.mark.parametrize("call, match", [
    (lambda lam: nonzero_eigenvalues(lam, 3), r"zero_modes=3 \(components\) but "
     r"lam_2 = 2.* is not zero"),
    (lambda lam: nonzero_eigenvalues(lam, -1), r"zero_modes must be an integer >= 0"),
    (lambda lam: nonzero_eigenvalues(np.zeros(5)), r"all 5 are zero modes.*N > 5"),
    (lambda lam: log_weyl_ratio(np.r_[0.0, 0.0, 3.0, 0.0]),
     r"lam_i > 0 after the 2 zero modes, but lam_3 = 0.*ascending"),
    (lambda lam: cshape.compact_shape_dna(lam[:10], M=4, N=10, normalization="none",
                                          transform="log-weyl"),
     r"2M\+1 = 9 non-zero eigenvalues, but 2 of the N = 10 are zero modes .* use N >= 11"),
    (lambda lam: f1_feature(np.r_[0.0, 0.0, 3.0]), r"at least one eigenvalue after"),
])
def test_rule_errors(spectra, call, match):
    with pytest.raises(ValueError, match=match):
        call(spectra[2][0])


# ------------------------------------------------------------------ one mesh never fails all
def test_matrix_names_every_row_it_cannot_describe(table):
    with pytest.raises(ValueError, match=r"kind='truncated-log' cannot describe 1 of 4 "
                       r"shapes \(dozen: 12 of its 30 eigenvalues are zero modes"):
        Descriptor("truncated-log", N=N, M=9).matrix(table.lam, table.areas,
                                                     names=table.names,
                                                     zero_modes=table.zero_modes)
    bad = Descriptor("truncated-log", N=N, M=9)._rows(table.lam, table.areas)[1]
    assert list(bad) == [3] and "2M+1 = 19 are needed" in bad[3]


def test_table_leaves_out_with_a_warning_and_answers_the_rest(table):
    np.testing.assert_array_equal(table.zero_modes, [1, 1, 2, 12])
    for kind in cshape.descriptors.recipe.DESCRIPTOR_KINDS:  # M = 4: every shape can be described
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            assert len(table.descriptors(Descriptor(kind, N=N, M=M))) == 4
    d9 = Descriptor("truncated-log", N=N, M=9)
    with pytest.warns(cshape.CShapeWarning, match=r"cannot describe 1 of 4 shapes, left out: "
                      r"dozen \(12 of its 30"):
        D = table.distance_matrix(d9)
    assert table.described(d9, warn=False)[1].tolist() == [0, 1, 2]
    sub = table.select(table.described(d9, warn=False)[1])
    np.testing.assert_array_equal(D, sub.distance_matrix(d9))
    with pytest.warns(cshape.CShapeWarning, match="dozen"):
        X = table.descriptors(Descriptor("cshape", N=N, M=9, transform="log-weyl-dct"))
    assert X.shape == (3, 19)
    with pytest.raises(ValueError, match="cannot describe any of the 1 shapes"), \
            pytest.warns(cshape.CShapeWarning):
        table.select([3]).descriptors(d9)


def test_index_maps_its_rows_to_the_table(table):
    with pytest.warns(cshape.CShapeWarning, match="dozen"):
        index = cshape.DescriptorIndex.from_table(table, Descriptor("truncated-log", N=N, M=9))
    np.testing.assert_array_equal(index.rows_, [0, 1, 2])
    dist, ind = index.query_spectra(table.lam[2], table.areas[2], k=1, zero_modes=[2])
    assert index.rows_[ind[0, 0]] == 2 and dist[0, 0] == 0.0
    with pytest.raises(ValueError, match="cannot describe 1 of 1 shapes \\(dozen:"):
        index.query_spectra(table.lam[3], table.areas[3], names=["dozen"])


def test_components_are_cached_and_warned_again_on_a_cached_run(sphere, tmp_path):
    meshes = [("two", "s", copies(sphere, 2)), ("one", "s", sphere)]
    with pytest.warns(cshape.CShapeWarning, match="two: mesh has 2 connected components"):
        first = describe(meshes, N=N, cache_dir=tmp_path, progress=False)
    with pytest.warns(cshape.CShapeWarning, match="two: mesh has 2 connected components"):
        again = describe(meshes, N=N, cache_dir=tmp_path, progress=False)
    assert again.cached.all() and not first.cached.any()
    np.testing.assert_array_equal(again.components, [2, 1])
    np.testing.assert_array_equal(again.zero_modes, [2, 1])


# ------------------------------------------------------------------ files
def test_csv_reads_with_plain_pandas_and_keeps_the_metadata(table, tmp_path):
    pd = pytest.importorskip("pandas")
    t = DescriptorTable(table.names, table.lam, table.areas, table.labels,
                        failures=[("bad", "ValueError: x")], components=table.components)
    path = t.save(tmp_path / "t.csv")
    df = pd.read_csv(path)
    assert list(df.columns[:6]) == ["name", "label", "area", "seconds", "cached", "components"]
    assert df.shape == (4, 6 + N)
    np.testing.assert_array_equal(df[[f"lam_{i}" for i in range(N)]].to_numpy(), t.lam)
    assert df["components"].tolist() == [1, 1, 2, 12]
    meta = json.loads((tmp_path / "t.csv.json").read_text())
    assert meta["format_version"] == 4 and "M" not in meta and "transform" not in meta
    assert meta["descriptor"]["kind"] == t.descriptor.kind
    back = DescriptorTable.load(path)
    assert (back.bc, back.mass, back.failures) == ("neumann", "consistent", t.failures)
    np.testing.assert_array_equal(back.components, t.components)
    (tmp_path / "t.csv.json").unlink()  # a CSV copied alone: defaults, with a warning
    with pytest.warns(cshape.CShapeWarning, match=r"no metadata file .*t.csv.json"):
        alone = DescriptorTable.load(path)
    assert (alone.bc, alone.mass) == ("neumann", "consistent")
    np.testing.assert_array_equal(alone.lam, t.lam)


def test_out_into_a_missing_folder_names_it(tmp_path, capsys):
    from cshape.cli import main

    write_off(tmp_path / "m" / "one.off", shapes.icosphere(1))
    out = tmp_path / "no_such" / "t.csv"
    assert main(["describe", str(tmp_path / "m"), "-N", "5", "--out", str(out),
                 "--no-cache"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"the folder {str(out.parent)!r} does not exist" in err[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m"]


# ------------------------------------------------------------------ command line
def test_cli_describe_and_query_report_pieces(sphere, tmp_path, capsys):
    from cshape.cli import main

    write_off(tmp_path / "m" / "two.off", copies(sphere, 2))
    write_off(tmp_path / "m" / "dozen.off", copies(sphere, 12))
    write_off(tmp_path / "m" / "one.off", sphere)
    out = tmp_path / "t.csv"
    assert main(["describe", str(tmp_path / "m"), "-N", str(N), "--out", str(out),
                 "--no-cache", "-q"]) == 0
    assert main(["describe", str(tmp_path / "m"), "-N", str(N), "--no-cache"]) == 0
    cap = capsys.readouterr()
    assert "2 with several components: dozen (12), two (2)" in cap.err
    line = next(x for x in cap.out.splitlines() if x.startswith("dozen"))
    assert line.split()[2] == "12"  # name, area, pieces (a flat folder: no label)
    assert main(["query", str(out), "two", "--kind", "truncated-log", "-M", "9", "-k",
                 "3"]) == 0
    cap = capsys.readouterr()
    assert "left out: dozen" in cap.err and "among the 2 of 3 shapes it describes" in cap.out
    assert main(["query", str(out), "dozen", "--kind", "truncated-log", "-M", "9"]) == 2
    assert "--kind truncated-log cannot describe 'dozen'" in capsys.readouterr().err
    assert main(["info", str(tmp_path / "m" / "two.off")]) == 0
    assert "components             2" in capsys.readouterr().out


# ------------------------------------------------------------------ the lessons
def test_lessons_use_the_packages_zero_mode_rule():
    """Lesson 08 leaves out meshes of several pieces by the package's rule (the component
    count, else count_zero_modes and ZERO_RTOL), not by a threshold of its own: a zero mode
    carrying another solver's round-off (1e-7 of the largest eigenvalue, above 1e-8) is one."""
    import re

    from conftest import REPO

    sources = {p.name: p.read_text() for p in sorted((REPO / "notebooks").glob("[0-9]*.py"))}
    own = [n for n, src in sources.items() if re.search(r"lam\[:, *1\] *[<>]", src)]
    assert own == [], own
    assert "ok = table.zero_modes <= 1" in sources["08_beyond_the_paper.py"]
    lam = 4 * np.pi * np.arange(30.0)
    two = np.r_[0.0, 1e-7 * lam[-1], lam[2:]]  # two pieces, the second zero mode not exact
    t = DescriptorTable(["one", "two"], np.array([lam, two]), [1.0, 1.0])
    np.testing.assert_array_equal(t.zero_modes, [1, 2])
    assert two[1] > 1e-8 * two[-1]  # the lesson's former threshold took it for one piece
    assert cshape.descriptors.count_zero_modes(two) == 2 and 1e-7 <= ZERO_RTOL
