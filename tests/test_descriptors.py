"""Descriptors: normalisation, Weyl line (Eq. 8), DFT crop (Eq. 9-10), real form, inverse, F1."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import compact_of

import cshape
from cshape import shapes
from cshape.descriptors import inverse_compact_shape_dna, log_weyl_ratio, real_form
from cshape.descriptors.formulas import f1_feature

FOUR_PI = 4 * np.pi
# lam' of a hand-checkable case (N = 8): lam_norm = lam' + 4 pi i
LAM_PRIME = np.array([1.0, 2.0, 0.0, -1.0, 0.0, 0.0, 0.0, 2.0])
LAM_NORM = LAM_PRIME + FOUR_PI * np.arange(8)


def test_weyl_subtract_eq8():
    np.testing.assert_allclose(cshape.weyl_subtract(LAM_NORM), LAM_PRIME, atol=1e-12)


def test_hand_computed_dft_crop_N8_M1():
    # Eq. (9) by hand with w = exp(-j pi / 4):
    #   Lambda_0 = 1 + 2 + 0 - 1 + 0 + 0 + 0 + 2 = 4
    #   Lambda_1 = 1 + 2w - w^3 + 2w^7 = (1 + 2.5 sqrt2) + j sqrt2/2
    #   Lambda_{-1} = conj(Lambda_1)   (real input)
    # Eq. (10): after the shift the centre <N/2> = 4 holds frequency 0; keep -1, 0, 1.
    r2 = np.sqrt(2.0)
    expected = np.array([1 + 2.5 * r2 - 0.5j * r2, 4.0, 1 + 2.5 * r2 + 0.5j * r2])
    S = cshape.compact_shape_dna(LAM_NORM, M=1, N=8, normalization="none")
    assert S.dtype == np.complex128 and S.shape == (3,)
    np.testing.assert_allclose(S, expected, atol=1e-12)
    # raw eigenvalues with an area are multiplied by it first
    np.testing.assert_allclose(cshape.compact_shape_dna(LAM_NORM / 2.0, M=1, N=8, area=2.0), S)
    # only the first N eigenvalues are used
    longer = np.concatenate([LAM_NORM, [1e6, 2e6]])
    np.testing.assert_allclose(cshape.compact_shape_dna(longer, M=1, N=8, normalization="none"), S)


def test_odd_N_centre_and_conjugate_symmetry():
    rng = np.random.default_rng(1)
    lam = np.sort(rng.uniform(0, 100, 9))
    S = cshape.compact_shape_dna(lam, M=4, N=9, normalization="none")
    np.testing.assert_allclose(S, np.conj(S[::-1]), atol=1e-10)
    np.testing.assert_allclose(S[4], cshape.weyl_subtract(lam).sum())


def test_real_form_preserves_distances():
    rng = np.random.default_rng(0)
    lams = np.sort(rng.uniform(0, 1000, (5, 40)), axis=1)
    S = np.array([cshape.compact_shape_dna(x, M=6, N=40, normalization="none") for x in lams])
    R = real_form(S)
    assert R.shape == (5, 13) and R.dtype == np.float64
    for i in range(5):
        for j in range(5):
            assert np.linalg.norm(R[i] - R[j]) == pytest.approx(
                np.linalg.norm(S[i] - S[j]), rel=1e-12, abs=1e-9
            )
    np.testing.assert_allclose(
        real_form(cshape.compact_shape_dna(lams[0], M=6, N=40, normalization="none")), R[0])
    with pytest.raises(ValueError, match="odd last dimension"):
        real_form(np.zeros(4, complex))


def test_inverse_reproduces_input_when_all_frequencies_kept():
    rng = np.random.default_rng(2)
    lam = np.sort(rng.uniform(0, 500, 41))
    S = cshape.compact_shape_dna(lam, M=20, N=41, normalization="none")  # 2M+1 = N
    np.testing.assert_allclose(inverse_compact_shape_dna(S, 41), lam, atol=1e-9)
    np.testing.assert_allclose(
        inverse_compact_shape_dna(S, 41, add_weyl=False), cshape.weyl_subtract(lam),
        atol=1e-9,
    )


def test_inverse_error_is_the_dropped_energy_and_shrinks_with_M():
    lam = cshape.shape_dna(shapes.torus(32, 16), N=60)
    area = shapes.torus(32, 16).area
    lam_norm = cshape.normalize(lam, area)
    full = np.fft.fftshift(np.fft.fft(cshape.weyl_subtract(lam_norm)))
    errs = []
    for M in range(0, 30):
        S = cshape.compact_shape_dna(lam, M=M, N=60, area=area)
        rec = inverse_compact_shape_dna(S, 60)
        err2 = np.sum((rec - lam_norm) ** 2)
        keep = np.zeros(60, bool)
        keep[30 - M : 30 + M + 1] = True
        # Parseval: the squared error equals (1/N) times the energy of the dropped frequencies
        assert err2 == pytest.approx(np.sum(np.abs(full[~keep]) ** 2) / 60, rel=1e-8, abs=1e-8)
        errs.append(err2)
    assert np.all(np.diff(errs) <= 1e-9)


def test_compact_takes_eigenvalues_not_a_mesh():
    """A formula takes numbers; a mesh (any layout) is refused with the two-step recipe."""
    mesh = shapes.icosphere(2)
    for given in (mesh, (mesh.vertices, mesh.faces)):
        with pytest.raises(TypeError, match=r"takes eigenvalues, not a mesh: .*"
                           r"lam = cshape.shape_dna\(mesh, N\).*area=mesh.area"):
            cshape.compact_shape_dna(given, M=3, N=30)


def test_normalisations():
    lam = np.array([0.0, 2.0, 2.0, 2.0, 6.0])
    np.testing.assert_allclose(cshape.normalize(lam, area=4 * np.pi), lam * 4 * np.pi)
    np.testing.assert_allclose(cshape.normalize(lam, normalization="fiedler"), lam / 2.0)
    line = 3.0 * np.arange(10)
    np.testing.assert_allclose(cshape.normalize(line, normalization="weyl"),
                               FOUR_PI * np.arange(10))


@pytest.mark.parametrize(
    "call, exc, match",
    [
        (lambda: cshape.normalize([0, 1, 2]), ValueError, "needs the surface area"),
        (lambda: cshape.normalize([0, 1, 2], area=-1), ValueError, "area must be a positive"),
        (lambda: cshape.normalize([0, 1, 2], area=1, normalization="max"), ValueError,
         "normalization must be"),
        (lambda: cshape.normalize([0, 0, 0], normalization="fiedler"), ValueError, "no non-zero"),
        (lambda: cshape.normalize([[0, 1]], area=1), ValueError, "1-D"),
        (lambda: cshape.normalize([0, np.nan], area=1), ValueError, "NaN"),
        (lambda: cshape.compact_shape_dna(LAM_NORM, M=4, N=8), ValueError, r"use M <= 3"),
        (lambda: cshape.compact_shape_dna(LAM_NORM, M=-1, N=8), ValueError,
         "M must be an integer >= 0, got -1"),
        (lambda: cshape.compact_shape_dna(LAM_NORM, M=1.5, N=8), TypeError, "M must be an integer"),
        (lambda: cshape.compact_shape_dna(LAM_NORM, M=1, N=100), ValueError, "got 8 eigenvalues"),
        (lambda: cshape.compact_shape_dna(LAM_NORM, M=1, N=8, transform="log"), ValueError,
         r"transform must be one of \{'weyl', 'log-weyl', 'log-weyl-dct'\}, got 'log'"),
        (lambda: cshape.compact_shape_dna(LAM_NORM, M=4, N=9, transform="log-weyl"), ValueError,
         r"2M\+1 = 9 values cannot be kept from the N-1 = 8 log-Weyl ratios"),
        (lambda: cshape.compact_shape_dna(LAM_NORM, M=4, N=8, transform="log-weyl-dct"),
         ValueError, r"use M <= 3 or N >= 10"),
        (lambda: cshape.compact_shape_dna([0.0, 0.0, 30.0, 40.0], M=1, N=4, normalization="none",
                                          transform="log-weyl"), ValueError,
         r"needs 2M\+1 = 3 non-zero eigenvalues, but 2 of the N = 4 are zero modes \(a mesh "
         r"of 2 components\) and 2 are left: use N >= 5 or M <= 0"),
        (lambda: cshape.compact_shape_dna([0.0, 20.0, -3.0, 40.0], M=1, N=4, normalization="none",
                                          transform="log-weyl-dct"), ValueError,
         r"needs lam_i > 0 after the 1 zero mode, but lam_2 = -3.*ascending"),
        (lambda: log_weyl_ratio([0.0]), ValueError, "at least 2 eigenvalues"),
        (lambda: cshape.compact_shape_dna([0.0], M=0, N=1, normalization="none",
                                          transform="log-weyl"),
         ValueError, r"the log-Weyl ratios need N >= 2 \(the log-Weyl ratio starts at lam_1"),
        (lambda: cshape.compact_shape_dna(LAM_NORM, M=1, N=8, area=2.0, normalization="none"),
         ValueError, "not both"),
        (lambda: cshape.compact_shape_dna(LAM_NORM, M=1, N=8, normalization=True), TypeError,
         r"normalization must be one of \{'area', 'fiedler', 'weyl', 'none'\}, got bool True"),
        (lambda: inverse_compact_shape_dna(np.ones(3, complex), 8,
                                                  transform="log-weyl-dct"),
         ValueError, "descriptors are real"),
        (lambda: inverse_compact_shape_dna(np.ones(9), 9, transform="log-weyl"),
         ValueError, r"N-1 = 8 log-Weyl ratios"),
        (lambda: inverse_compact_shape_dna(np.ones(3), 8, transform="dct"),
         ValueError, "transform must be one of"),
        (lambda: inverse_compact_shape_dna(np.ones(4), 8), ValueError, "odd length"),
        (lambda: inverse_compact_shape_dna(np.ones(9), 8), ValueError, "2M\\+1 = 9"),
        (lambda: f1_feature([0, 1]), ValueError, "at least one eigenvalue after"),
    ],
)
def test_descriptor_errors(call, exc, match):
    with pytest.raises(exc, match=match):
        call()


def test_f1_feature():
    np.testing.assert_allclose(f1_feature([0.0, 2.0, 4.0, 8.0]), [0.5, 0.25])
    # Dirichlet spectra have no zero eigenvalue: the first one is the reference
    np.testing.assert_allclose(f1_feature([2.0, 4.0, 8.0]), [0.5, 0.25])
    lam = cshape.shape_dna(shapes.torus(24, 12), N=20)
    f = f1_feature(lam)
    assert f.shape == (18,) and np.all((f > 0) & (f <= 1 + 1e-12))


# ------------------------------------------------------------------ transforms beyond the paper
TRANSFORMS = ("weyl", "log-weyl", "log-weyl-dct")


def _paper_code_path(lam, M, N, area):
    """The cShape-DNA exactly as cshape computed it before ``transform=`` existed."""
    x = np.asarray(lam, dtype=np.float64)[:N] * float(area)  # normalize(..., 'area')
    lam_prime = x - 4.0 * np.pi * np.arange(len(x))  # weyl_subtract, Eq. (8)
    shifted = np.fft.fftshift(np.fft.fft(lam_prime))  # Eq. (9)
    c = N // 2
    return shifted[c - M : c + M + 1].copy()  # Eq. (10)


@pytest.mark.parametrize("N", [5, 8, 9, 40, 100])
def test_default_transform_is_the_paper_bit_for_bit(N):
    rng = np.random.default_rng(N)
    for _ in range(5):
        lam = np.sort(rng.uniform(0, 50, N + 3))
        lam[0] = 0.0
        area = float(rng.uniform(0.01, 100))
        for M in {0, 1, (N - 1) // 2}:
            ref = _paper_code_path(lam, M, N, area)
            assert np.array_equal(cshape.compact_shape_dna(lam, M=M, N=N, area=area), ref)
            assert np.array_equal(
                cshape.compact_shape_dna(lam, M=M, N=N, area=area, transform="weyl"), ref)
            assert np.array_equal(cshape.compact_shape_dna(lam * area, M=M, N=N,
                                                           normalization="none"), ref)


def _lam_from_r(r):
    """lam^norm with lam_0 = 0 and log(lam_i / (4 pi i)) = r_i."""
    r = np.asarray(r, dtype=float)
    return np.concatenate([[0.0], FOUR_PI * np.arange(1, len(r) + 1) * np.exp(r)])


# N = 5: r = (r_1, r_2, r_3, r_4) = (0.2, 0.0, -0.1, 0.1), L = N - 1 = 4
R_HAND = [0.2, 0.0, -0.1, 0.1]


def test_log_weyl_ratio_by_hand():
    lam = [0.0, FOUR_PI * np.exp(0.2), 2 * FOUR_PI, 3 * FOUR_PI * np.exp(-0.1),
           4 * FOUR_PI * np.exp(0.1)]
    np.testing.assert_allclose(log_weyl_ratio(lam), R_HAND, atol=1e-15)
    # a Dirichlet spectrum (lam_0 > 0): lam_0 is dropped, the rest is unchanged
    np.testing.assert_allclose(log_weyl_ratio([3.0] + lam[1:]), R_HAND, atol=1e-15)


def test_log_weyl_dft_crop_by_hand_N5_M1():
    # L = 4, w = exp(-j 2 pi / 4) = -j:
    #   R_0 = 0.2 + 0 - 0.1 + 0.1 = 0.2
    #   R_1 = 0.2 + 0 (-j) - 0.1 (-1) + 0.1 (j) = 0.3 + 0.1j,   R_{-1} = conj(R_1)
    # fftshift puts R_0 at L // 2 = 2; keep frequencies -1, 0, 1
    S = cshape.compact_shape_dna(_lam_from_r(R_HAND), M=1, N=5, normalization="none",
                                 transform="log-weyl")
    assert S.dtype == np.complex128 and S.shape == (3,)
    np.testing.assert_allclose(S, [0.3 - 0.1j, 0.2, 0.3 + 0.1j], atol=1e-14)


def test_log_weyl_dct_by_hand_N5_M1():
    # orthonormal DCT-II, L = 4: C_k = w_k sum_n r_n cos(pi k (2n + 1) / 8),
    # w_0 = sqrt(1/4) = 0.5, w_k = sqrt(2/4);  cos(5pi/8) = -cos(3pi/8), cos(7pi/8) = -cos(pi/8)
    #   C_0 = 0.5 (0.2 + 0 - 0.1 + 0.1) = 0.1
    #   C_1 = sqrt(1/2) (0.2 c1 + 0.1 c3 - 0.1 c1) = sqrt(1/2) 0.1 (c1 + c3)
    #   C_2 = sqrt(1/2) (0.2 + 0.1 + 0.1) cos(pi/4) = 0.2
    c1, c3 = np.cos(np.pi / 8), np.cos(3 * np.pi / 8)
    S = cshape.compact_shape_dna(_lam_from_r(R_HAND), M=1, N=5, normalization="none",
                                 transform="log-weyl-dct")
    assert S.dtype == np.float64 and S.shape == (3,)
    np.testing.assert_allclose(S, [0.1, np.sqrt(0.5) * 0.1 * (c1 + c3), 0.2], atol=1e-14)
    np.testing.assert_array_equal(real_form(S), S)  # already real


def test_paper_dft_crop_by_hand_N5_M1():
    # lam' = (0, 1, 0, -1, 0); w = exp(-j 2 pi / 5):
    #   Lambda_0 = 0,  Lambda_1 = w - w^3 = -2j sin(2 pi / 5) ... written out:
    #   w - w^3 = (cos 2pi/5 - cos 6pi/5) - j (sin 2pi/5 - sin 6pi/5)
    lam_prime = np.array([0.0, 1.0, 0.0, -1.0, 0.0])
    a, b = 2 * np.pi / 5, 6 * np.pi / 5
    L1 = (np.cos(a) - np.cos(b)) - 1j * (np.sin(a) - np.sin(b))
    S = cshape.compact_shape_dna(lam_prime + FOUR_PI * np.arange(5), M=1, N=5, normalization="none")
    np.testing.assert_allclose(S, [np.conj(L1), 0.0, L1], atol=1e-14)


@pytest.mark.parametrize("transform", TRANSFORMS)
@pytest.mark.parametrize("N", [9, 10])
def test_largest_M_conjugate_symmetric_for_odd_and_even_length(transform, N):
    rng = np.random.default_rng(N)
    lam = np.concatenate([[0.0], np.sort(rng.uniform(5, 400, N - 1))])
    M = (N - 1) // 2 if transform == "weyl" else (N - 2) // 2
    S = cshape.compact_shape_dna(lam, M=M, N=N, normalization="none", transform=transform)
    assert S.shape == (2 * M + 1,)
    if transform != "log-weyl-dct":
        np.testing.assert_allclose(S[M + 1:], np.conj(S[:M][::-1]), atol=1e-12)
        assert abs(S[M].imag) < 1e-12
    with pytest.raises(ValueError, match="cannot be kept"):
        cshape.compact_shape_dna(lam, M=M + 1, N=N, normalization="none", transform=transform)


@pytest.mark.parametrize("transform", TRANSFORMS)
def test_real_form_distance_identity_for_every_transform(transform):
    rng = np.random.default_rng(3)
    lams = np.sort(rng.uniform(1, 1000, (6, 40)), axis=1)
    lams[:, 0] = 0.0
    S = np.array([cshape.compact_shape_dna(x, M=6, N=40, normalization="none", transform=transform)
                  for x in lams])
    R = real_form(S)
    assert R.shape == (6, 13) and R.dtype == np.float64
    for i in range(6):
        for j in range(6):
            assert np.linalg.norm(R[i] - R[j]) == pytest.approx(
                np.linalg.norm(S[i] - S[j]), rel=1e-12, abs=1e-12)
    np.testing.assert_array_equal(
        real_form(cshape.compact_shape_dna(lams[0], M=6, N=40, normalization="none",
                                      transform=transform)),
        R[0])


@pytest.mark.parametrize("transform", ["log-weyl", "log-weyl-dct"])
def test_log_weyl_inverse_is_exact_when_nothing_is_cropped(transform):
    rng = np.random.default_rng(4)
    lam = np.concatenate([[0.0], np.sort(rng.uniform(10, 500, 41))])  # N = 42, L = 41
    S = cshape.compact_shape_dna(lam, M=20, N=42, normalization="none", transform=transform)
    rec = inverse_compact_shape_dna(S, 42, transform=transform)
    assert rec.shape == (42,) and rec[0] == 0.0
    np.testing.assert_allclose(rec, lam, rtol=1e-12)
    r = inverse_compact_shape_dna(S, 42, add_weyl=False, transform=transform)
    np.testing.assert_allclose(r, log_weyl_ratio(lam), atol=1e-12)


@pytest.mark.parametrize("transform", ["log-weyl", "log-weyl-dct"])
def test_log_weyl_inverse_error_is_the_dropped_energy(transform):
    mesh = shapes.torus(24, 12)
    lam = cshape.normalize(cshape.shape_dna(mesh, N=40), mesh.area)
    r = log_weyl_ratio(lam)  # L = 39
    if transform == "log-weyl":
        full, c = np.fft.fftshift(np.fft.fft(r)), 39 // 2
    else:
        from scipy.fft import dct

        full = dct(r, type=2, norm="ortho")
    errs = []
    for M in range(0, 19):
        S = cshape.compact_shape_dna(lam, M=M, N=40, normalization="none", transform=transform)
        rec = inverse_compact_shape_dna(S, 40, add_weyl=False, transform=transform)
        keep = np.zeros(39, bool)
        if transform == "log-weyl":
            keep[c - M : c + M + 1] = True
            dropped = np.sum(np.abs(full[~keep]) ** 2) / 39  # Parseval, unnormalised DFT
        else:
            keep[: 2 * M + 1] = True
            dropped = np.sum(full[~keep] ** 2)  # Parseval, orthonormal DCT
        err2 = np.sum((rec - r) ** 2)
        assert err2 == pytest.approx(dropped, rel=1e-8, abs=1e-14)
        errs.append(err2)
    assert np.all(np.diff(errs) <= 1e-15)
    # with add_weyl the result is 4 pi i exp(r_smooth), lam_0 = 0
    S = cshape.compact_shape_dna(lam, M=5, N=40, normalization="none", transform=transform)
    rs = inverse_compact_shape_dna(S, 40, add_weyl=False, transform=transform)
    np.testing.assert_allclose(inverse_compact_shape_dna(S, 40, transform=transform),
                               np.concatenate([[0], FOUR_PI * np.arange(1, 40) * np.exp(rs)]))


@pytest.mark.parametrize("transform", TRANSFORMS)
def test_transforms_of_raw_and_of_normalised_eigenvalues_agree(transform):
    mesh = shapes.torus(20, 10)
    lam = cshape.shape_dna(mesh, N=30)
    S2 = cshape.compact_shape_dna(lam, M=3, N=30, area=mesh.area, transform=transform)
    S3 = cshape.compact_shape_dna(lam * mesh.area, M=3, N=30, normalization="none",
                                  transform=transform)
    np.testing.assert_allclose(S3, S2, rtol=1e-14, atol=1e-12)


def test_log_weyl_ignores_lam_0_and_takes_dirichlet_spectra():
    lam = _lam_from_r(R_HAND)
    for transform in ("log-weyl", "log-weyl-dct"):
        a = cshape.compact_shape_dna(lam, M=1, N=5, normalization="none", transform=transform)
        lam_d = lam.copy()
        lam_d[0] = 7.0  # a Dirichlet spectrum's first eigenvalue is positive
        b = cshape.compact_shape_dna(lam_d, M=1, N=5, normalization="none", transform=transform)
        np.testing.assert_array_equal(a, b)
    S = compact_of(shapes.disk(12), M=3, N=20, bc="dirichlet", transform="log-weyl")
    assert S.shape == (7,) and np.all(np.isfinite(S))


def test_eigenvalues_without_area_warn_and_explicit_choices_do_not():
    import warnings

    with pytest.warns(cshape.CShapeWarning, match="without area=.*normalization='none'"):
        S = cshape.compact_shape_dna(LAM_NORM, M=1, N=8)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        np.testing.assert_array_equal(
            cshape.compact_shape_dna(LAM_NORM, M=1, N=8, normalization="none"), S)
        cshape.compact_shape_dna(LAM_NORM / 3, M=1, N=8, area=3.0)
        cshape.compact_shape_dna(LAM_NORM, M=1, N=8, normalization="weyl")  # needs no area
