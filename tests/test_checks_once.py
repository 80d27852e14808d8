"""One call checks its spectrum once: the public entry point validates the eigenvalues, the
steps behind it take them as checked (counted by wrapping the one shared check)."""

from __future__ import annotations

import sys

import pytest

import cshape
from cshape import _checks, shapes


@pytest.fixture
def count_checks(monkeypatch):
    """Calls of ``check_spectrum``, from every cshape module that holds it."""
    calls: list[str] = []
    real = _checks.check_spectrum

    def counted(lam, name="lam", min_len=1):
        calls.append(name)
        return real(lam, name, min_len)

    for mod_name, mod in list(sys.modules.items()):
        if mod_name.startswith("cshape") and getattr(mod, "check_spectrum", None) is real:
            monkeypatch.setattr(mod, "check_spectrum", counted)
    return calls


@pytest.fixture(scope="module")
def sphere():
    return shapes.icosphere(3)


@pytest.fixture(scope="module")
def lam(sphere):
    return cshape.shape_dna(sphere, 40)


@pytest.mark.parametrize("transform", ["weyl", "log-weyl", "log-weyl-dct"])
def test_compact_shape_dna_checks_its_eigenvalues_once(count_checks, sphere, lam, transform):
    cshape.compact_shape_dna(lam, M=8, N=40, area=sphere.area, transform=transform)
    assert len(count_checks) == 1


@pytest.mark.parametrize("call", [
    lambda lam, a: cshape.normalize(lam, a),
    lambda lam, a: cshape.weyl_subtract(lam * a),
    lambda lam, a: cshape.descriptors.log_weyl_ratio(lam * a),
    lambda lam, a: cshape.descriptors.formulas.nonzero_eigenvalues(lam),
    lambda lam, a: cshape.descriptors.count_zero_modes(lam),
])
def test_each_formula_checks_once(count_checks, sphere, lam, call):
    call(lam, sphere.area)
    assert len(count_checks) == 1


def test_an_eigenbasis_is_checked_when_made_and_not_again(count_checks, sphere):
    basis = cshape.eigenbasis(sphere, 16)
    assert count_checks == ["lam"]
    count_checks.clear()
    cshape.hks(basis)
    cshape.wks(basis, normalization="area")
    cshape.signatures.si_hks(basis)
    cshape.signatures.heat_kernel(basis, 0.1, [0, 1])
    cshape.signatures.heat_trace(basis, [0.1, 1.0])
    cshape.hks(basis.truncate(8))
    assert count_checks == []


@pytest.mark.parametrize("descriptor", [
    cshape.PAPER.for_N(40), cshape.DEFAULT.for_N(40),
    cshape.Descriptor("cshape", N=40, M=8, transform="log-weyl-dct"),
    cshape.Descriptor("f1", N=40), cshape.Descriptor("shape-dna", N=40),
])
def test_a_descriptor_row_checks_its_spectrum_once(count_checks, sphere, lam, descriptor):
    descriptor.row(lam, sphere.area)
    assert len(count_checks) == 1
    count_checks.clear()
    descriptor._rows([lam, lam, lam], [sphere.area] * 3)
    assert len(count_checks) == 3  # one per row
