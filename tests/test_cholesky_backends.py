"""The sparse Cholesky backends of the eigensolver (cshape/_eigensolver/cholmod.py): known
answers, the same eigenvalues from each, the choice by CSHAPE_CHOLESKY, and errors."""

import os
import platform
import subprocess
import sys

import numpy as np
import pytest
import scipy.linalg as la
import scipy.sparse as sp

import cshape
from cshape._eigensolver import cholmod as _cholmod
from cshape._eigensolver.shift import CholeskyOperator
from cshape.spectrum import solve_eigenproblem

WORKING = [name for name in _cholmod.BACKENDS if _cholmod._probe(name)[0]]


def _laplacian_plus_identity(n):
    """1-D Laplacian + identity, tridiagonal (-1, 3, -1): positive definite."""
    return sp.diags([-np.ones(n - 1), 3.0 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1],
                    format="csr")


def test_the_fast_backend_works_on_linux_x86_64():
    # cvxopt is a core dependency: if its CHOLMOD stopped loading, every big eigensolve
    # would silently be 4x slower in its factorisation
    if sys.platform != "linux" or platform.machine() != "x86_64":
        pytest.skip("the cvxopt wheel's library layout is checked on Linux x86_64")
    assert _cholmod._probe("cholmod") == (True, "")
    assert "cholespy" in WORKING and "splu" in WORKING


@pytest.mark.parametrize("name", WORKING)
@pytest.mark.parametrize("order", ["C", "F"])
def test_each_backend_solves_known_systems(name, order, monkeypatch):
    monkeypatch.setenv("CSHAPE_CHOLESKY", name)
    rng = np.random.default_rng(1)
    # a random sparse SPD matrix of 2000 unknowns (supernodal in CHOLMOD) and the 1-D case
    R = sp.random(2000, 2000, density=0.002, random_state=2, format="csr")
    S = (R @ R.T + 2000 * sp.eye(2000) * 1e-3 + _laplacian_plus_identity(2000)).tocsr()
    for M in (S, _laplacian_plus_identity(50)):
        n = M.shape[0]
        X = np.asarray(rng.standard_normal((n, 8)), order=order)
        factor = _cholmod.factorize(M)
        assert factor.name == name
        Y = factor.solve(X)
        assert Y.shape == (n, 8) and Y.flags.c_contiguous
        np.testing.assert_allclose(M @ Y, X, atol=1e-10 * np.abs(X).max())
        x = factor.solve(X[:, 3].copy())
        assert x.shape == (n,)
        np.testing.assert_allclose(x, Y[:, 3], rtol=0, atol=1e-12 * np.abs(Y).max())
        assert np.array_equal(factor.solve(X), Y)  # workspace reuse changes nothing


@pytest.mark.slow
def test_backends_give_the_same_eigenvalues_and_every_sphere_copy(monkeypatch):
    mesh = cshape.shapes.icosphere(5)  # 10242 vertices: sparse path, icosahedral clusters
    lams = {}
    for name in WORKING:
        monkeypatch.setenv("CSHAPE_CHOLESKY", name)
        lams[name] = cshape.shape_dna(mesh, N=60)
    ref = lams[WORKING[0]]
    # the unit sphere: 1, 3, 5, 7, 9, 11, 13 copies of l(l+1), split by the icosphere
    # into clusters 2 (l + 1) apart, within 1 % of l (l + 1): every copy is in its cluster
    groups = np.cumsum([2 * l + 1 for l in range(8)])
    for lo, hi, l in zip(np.r_[0, groups[:-1]], np.minimum(groups, 60), range(8), strict=True):
        np.testing.assert_allclose(ref[lo:hi], l * (l + 1), rtol=1e-2, atol=1e-12)
    for name, lam in lams.items():
        np.testing.assert_allclose(lam, ref, rtol=1e-11, atol=1e-12, err_msg=name)


def test_cholmod_refuses_a_matrix_that_is_not_positive_definite(monkeypatch):
    if "cholmod" not in WORKING:
        pytest.skip("the cholmod backend is not available here")
    monkeypatch.setenv("CSHAPE_CHOLESKY", "cholmod")
    for n in (30, 3000):  # CHOLMOD's simplicial L D L^T would accept the small one
        S = sp.diags([-np.ones(n - 1), np.ones(n), -np.ones(n - 1)], [-1, 0, 1], format="csr")
        with pytest.raises(la.LinAlgError, match="not positive definite.*below the smallest"):
            CholeskyOperator(S)


def test_a_shift_above_the_spectrum_is_refused_not_answered():
    mesh = cshape.shapes.icosphere(4)
    A, B = cshape.fem_matrices(mesh)
    with pytest.raises(ValueError, match="not positive definite"):
        solve_eigenproblem(A, B, 10, sigma=5.0)


def test_the_environment_chooses_the_backend(monkeypatch):
    S = _laplacian_plus_identity(40)
    monkeypatch.setenv("CSHAPE_CHOLESKY", "splu")
    assert _cholmod.backend() == "splu" and _cholmod.factorize(S).name == "splu"
    monkeypatch.setenv("CSHAPE_CHOLESKY", " Auto ")
    assert _cholmod.backend() == WORKING[0]
    monkeypatch.delenv("CSHAPE_CHOLESKY")
    assert _cholmod.backend() == WORKING[0]
    monkeypatch.setenv("CSHAPE_CHOLESKY", "mkl")
    with pytest.raises(ValueError, match="CSHAPE_CHOLESKY must be one of auto, cholmod"):
        _cholmod.backend()


def test_a_backend_that_does_not_work_is_named_with_its_reason(monkeypatch):
    monkeypatch.setitem(_cholmod._STATUS, "cholmod", (False, "OSError: no CHOLMOD library"))
    monkeypatch.setenv("CSHAPE_CHOLESKY", "cholmod")
    with pytest.raises(ValueError, match="CSHAPE_CHOLESKY=cholmod does not work here "
                                         r"\(OSError: no CHOLMOD library\); unset it"):
        _cholmod.backend()
    monkeypatch.setenv("CSHAPE_CHOLESKY", "auto")  # auto falls back to the next one
    assert _cholmod.backend() == "cholespy"


@pytest.mark.slow
def test_shape_dna_is_the_same_bits_in_a_new_process_with_each_backend(tmp_path):
    code = ("import sys, numpy as np, cshape; "
            "np.save(sys.argv[1], cshape.shape_dna(cshape.shapes.icosphere(5), N=30))")
    for name in WORKING[:2]:
        runs = []
        for k in range(2):
            out = tmp_path / f"{name}{k}.npy"
            env = dict(os.environ, CSHAPE_CHOLESKY=name)
            subprocess.run([sys.executable, "-c", code, str(out)], check=True, env=env)
            runs.append(np.load(out))
        assert np.array_equal(runs[0], runs[1]), name


def _cpuinfo(tmp_path, vendor, flags):
    path = tmp_path / "cpuinfo"
    path.write_text(f"processor\t: 0\nvendor_id\t: {vendor}\nflags\t\t: {' '.join(flags)}\n\n"
                    "processor\t: 1\nvendor_id\t: Other\nflags\t\t: fpu\n")
    return str(path)


def test_openblas_kernels_follow_the_processor_and_keep_the_users_choice(tmp_path):
    xeon = _cpuinfo(tmp_path, "GenuineIntel", ["fpu", "avx2", "fma", "avx512f", "avx512bw"])
    assert _cholmod.openblas_coretype({}, xeon) == _cholmod.AVX512_CORETYPE == "Haswell"
    assert _cholmod.openblas_coretype({"OPENBLAS_CORETYPE": "SkylakeX"}, xeon) is None
    assert _cholmod.openblas_coretype({"OPENBLAS_CORETYPE": ""}, xeon) == "Haswell"
    for vendor, flags in [("GenuineIntel", ["avx2", "fma"]),           # no AVX-512
                          ("AuthenticAMD", ["avx2", "fma", "avx512f"]),  # Zen 4: its own
                          ("GenuineIntel", ["avx512f"])]:              # no AVX2/FMA kernels
        assert _cholmod.openblas_coretype({}, _cpuinfo(tmp_path, vendor, flags)) is None
    assert _cholmod.openblas_coretype({}, str(tmp_path / "missing")) is None  # not Linux
    assert _cholmod._cpu_flags(xeon)[0] == "GenuineIntel"


@pytest.mark.skipif("cholmod" not in WORKING, reason="no CHOLMOD from cvxopt here")
def test_cvxopts_openblas_gets_the_kernels_and_the_environment_is_left_as_it_was():
    # in a new process: NumPy's OpenBLAS keeps its own kernels, cvxopt's takes
    # openblas_coretype()'s, and OPENBLAS_CORETYPE is not left set for child processes
    code = ("import os, ctypes, glob, numpy, cshape; "
            "from cshape._eigensolver import cholmod as _cholmod; "
            "assert _cholmod.backend() == 'cholmod'; import cvxopt; "
            "lib = glob.glob(os.path.dirname(cvxopt.__file__) + '/../cvxopt.libs/libopenblas*'); "
            "ob = ctypes.CDLL(lib[0]) if lib else None; "
            "ob and setattr(ob.openblas_get_corename, 'restype', ctypes.c_char_p); "
            "print(ob.openblas_get_corename().decode() if ob else '-', "
            "'OPENBLAS_CORETYPE' in os.environ, _cholmod.openblas_coretype())")
    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_CORETYPE"}
    out = subprocess.run([sys.executable, "-c", code], check=True, env=env,
                         capture_output=True, text=True).stdout.split()
    corename, left, wanted = out
    assert left == "False"
    if wanted != "None" and corename != "-":
        assert corename == wanted
