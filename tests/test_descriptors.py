"""Descriptors: normalisation, Weyl line (Eq. 8), DFT crop (Eq. 9-10), real form, inverse, F1."""

from __future__ import annotations

import numpy as np
import pytest

import cshape
from cshape import shapes

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
    S = cshape.compact_shape_dna(LAM_NORM, M=1, N=8)
    assert S.dtype == np.complex128 and S.shape == (3,)
    np.testing.assert_allclose(S, expected, atol=1e-12)
    # raw eigenvalues with an area are multiplied by it first
    np.testing.assert_allclose(cshape.compact_shape_dna(LAM_NORM / 2.0, M=1, N=8, area=2.0), S)
    # only the first N eigenvalues are used
    longer = np.concatenate([LAM_NORM, [1e6, 2e6]])
    np.testing.assert_allclose(cshape.compact_shape_dna(longer, M=1, N=8), S)


def test_odd_N_centre_and_conjugate_symmetry():
    rng = np.random.default_rng(1)
    lam = np.sort(rng.uniform(0, 100, 9))
    S = cshape.compact_shape_dna(lam, M=4, N=9)
    np.testing.assert_allclose(S, np.conj(S[::-1]), atol=1e-10)
    np.testing.assert_allclose(S[4], cshape.weyl_subtract(lam).sum())


def test_real_form_preserves_distances():
    rng = np.random.default_rng(0)
    lams = np.sort(rng.uniform(0, 1000, (5, 40)), axis=1)
    S = np.array([cshape.compact_shape_dna(x, M=6, N=40) for x in lams])
    R = cshape.real_form(S)
    assert R.shape == (5, 13) and R.dtype == np.float64
    for i in range(5):
        for j in range(5):
            assert np.linalg.norm(R[i] - R[j]) == pytest.approx(
                np.linalg.norm(S[i] - S[j]), rel=1e-12, abs=1e-9
            )
    np.testing.assert_allclose(cshape.compact_shape_dna_real(lams[0], M=6, N=40), R[0])
    with pytest.raises(ValueError, match="odd last dimension"):
        cshape.real_form(np.zeros(4, complex))


def test_inverse_reproduces_input_when_all_frequencies_kept():
    rng = np.random.default_rng(2)
    lam = np.sort(rng.uniform(0, 500, 41))
    S = cshape.compact_shape_dna(lam, M=20, N=41)  # 2M+1 = N
    np.testing.assert_allclose(cshape.inverse_compact_shape_dna(S, 41), lam, atol=1e-9)
    np.testing.assert_allclose(
        cshape.inverse_compact_shape_dna(S, 41, add_weyl=False), cshape.weyl_subtract(lam),
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
        rec = cshape.inverse_compact_shape_dna(S, 60)
        err2 = np.sum((rec - lam_norm) ** 2)
        keep = np.zeros(60, bool)
        keep[30 - M : 30 + M + 1] = True
        # Parseval: the squared error equals (1/N) times the energy of the dropped frequencies
        assert err2 == pytest.approx(np.sum(np.abs(full[~keep]) ** 2) / 60, rel=1e-8, abs=1e-8)
        errs.append(err2)
    assert np.all(np.diff(errs) <= 1e-9)


def test_compact_from_mesh_equals_from_eigenvalues():
    mesh = shapes.icosphere(2)
    lam = cshape.shape_dna(mesh, N=30)
    S1 = cshape.compact_shape_dna(mesh, M=3, N=30)
    S2 = cshape.compact_shape_dna(lam, M=3, N=30, area=mesh.area)
    np.testing.assert_allclose(S1, S2, rtol=1e-9)
    S3 = cshape.compact_shape_dna((mesh.vertices, mesh.faces), M=3, N=30)
    np.testing.assert_allclose(S1, S3, rtol=1e-9)


def test_normalisations():
    lam = np.array([0.0, 2.0, 2.0, 2.0, 6.0])
    np.testing.assert_allclose(cshape.normalize(lam, area=4 * np.pi), lam * 4 * np.pi)
    np.testing.assert_allclose(cshape.normalize(lam, method="fiedler"), lam / 2.0)
    line = 3.0 * np.arange(10)
    np.testing.assert_allclose(cshape.normalize(line, method="weyl"), FOUR_PI * np.arange(10))


@pytest.mark.parametrize(
    "call, exc, match",
    [
        (lambda: cshape.normalize([0, 1, 2]), ValueError, "needs the surface area"),
        (lambda: cshape.normalize([0, 1, 2], area=-1), ValueError, "area must be a positive"),
        (lambda: cshape.normalize([0, 1, 2], area=1, method="max"), ValueError, "method must be"),
        (lambda: cshape.normalize([0, 0, 0], method="fiedler"), ValueError, "no non-zero"),
        (lambda: cshape.normalize([[0, 1]], area=1), ValueError, "1-D"),
        (lambda: cshape.normalize([0, np.nan], area=1), ValueError, "NaN"),
        (lambda: cshape.compact_shape_dna(LAM_NORM, M=4, N=8), ValueError, r"use M <= 3"),
        (lambda: cshape.compact_shape_dna(LAM_NORM, M=-1, N=8), ValueError, "M must be >= 0"),
        (lambda: cshape.compact_shape_dna(LAM_NORM, M=1.5, N=8), TypeError, "M must be an integer"),
        (lambda: cshape.compact_shape_dna(LAM_NORM, M=1, N=100), ValueError, "got 8 eigenvalues"),
        (lambda: cshape.inverse_compact_shape_dna(np.ones(4), 8), ValueError, "odd length"),
        (lambda: cshape.inverse_compact_shape_dna(np.ones(9), 8), ValueError, "2M\\+1 = 9"),
        (lambda: cshape.f1_feature([0, 1]), ValueError, "at least one eigenvalue after"),
    ],
)
def test_descriptor_errors(call, exc, match):
    with pytest.raises(exc, match=match):
        call()


def test_f1_feature():
    np.testing.assert_allclose(cshape.f1_feature([0.0, 2.0, 4.0, 8.0]), [0.5, 0.25])
    # Dirichlet spectra have no zero eigenvalue: the first one is the reference
    np.testing.assert_allclose(cshape.f1_feature([2.0, 4.0, 8.0]), [0.5, 0.25])
    lam = cshape.shape_dna(shapes.torus(24, 12), N=20)
    f = cshape.f1_feature(lam)
    assert f.shape == (18,) and np.all((f > 0) & (f <= 1 + 1e-12))


def test_compact_from_a_mesh_uses_the_area_of_the_repaired_surface():
    mesh = shapes.icosphere(2)
    dup = cshape.Mesh(mesh.vertices, np.vstack([mesh.faces, mesh.faces[:5]]))
    with pytest.warns(cshape.CShapeWarning, match="duplicate faces") as rec:
        S = cshape.compact_shape_dna(dup, M=3, N=30)
    assert len(rec) == 1  # repaired once
    np.testing.assert_allclose(S, cshape.compact_shape_dna(mesh, M=3, N=30), atol=1e-9)
