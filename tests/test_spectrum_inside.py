"""The eigensolver with its shift inside the spectrum, and the split solves of big meshes.

Known answers: Sylvester's inertia against dense LAPACK's eigenvalue counts, the inside
path against dense LAPACK (every icosahedral copy) and against a tight one-sided
reference on real meshes; properties: each fallback gives the same eigenvalues, split
solves give the same bits, one and two threads agree to a stated tolerance.  No
timings here: benchmarks/bench_sweep.py measures the speed.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
import scipy.linalg as la
from conftest import pairs

import cshape
from cshape import shapes, spectrum
from cshape._eigensolver import cholmod as _cholmod
from cshape._eigensolver import lanczos as _lanczos
from cshape._eigensolver import shift as _shift
from cshape._eigensolver import threads as _threads


def _KB(mesh):
    A, B = cshape.fem_matrices(mesh)
    return (-A).tocsr(), B.tocsr()


@pytest.fixture
def sparse_path(monkeypatch):
    monkeypatch.setattr(spectrum, "DENSE_LIMIT", 0)


@pytest.fixture
def spy(monkeypatch):
    """Record the shifts the eigensolver factorises and whether the inside path answered."""
    seen = {"indefinite": [], "definite": 0, "inside": []}
    factorize, inside = _cholmod.factorize, _shift.solve_inside

    def fact(S, indefinite=False):
        f = factorize(S, indefinite=indefinite)
        if indefinite:
            seen["indefinite"].append(f.inertia)
        else:
            seen["definite"] += 1
        return f

    def ins(*args, **kwargs):
        out = inside(*args, **kwargs)
        seen["inside"].append(out is not None)
        return out

    monkeypatch.setattr(_cholmod, "factorize", fact)
    monkeypatch.setattr(_shift, "solve_inside", ins)
    return seen


@pytest.fixture(scope="module")
def ico3():
    mesh = shapes.icosphere(3)  # 642 vertices, icosahedral multiplets 1, 3, 4, 5
    K, B = _KB(mesh)
    return mesh, K, B, la.eigh(K.toarray(), B.toarray(), eigvals_only=True)


def test_inertia_of_the_indefinite_factor_counts_the_eigenvalues_below_the_shift(ico3):
    _, K, B, lam = ico3
    mids = 0.5 * (lam[1:] + lam[:-1])
    for k in (1, 9, 40, 100, 250):
        sigma = mids[k - 1]  # between lam_{k-1} and lam_k: exactly k eigenvalues below
        S = _shift.shifted(K, B, sigma, same=True)
        f = _cholmod.factorize(S, indefinite=True)
        assert f.inertia == k
        X = np.asfortranarray(np.random.default_rng(0).standard_normal((K.shape[0], 3)))
        np.testing.assert_allclose(S @ f.solve(X), X, atol=1e-8)
    assert _cholmod.factorize(K + B, indefinite=True).inertia == 0  # positive definite


def test_refined_solve_is_at_least_as_accurate(ico3):
    _, K, B, lam = ico3
    S = _shift.shifted(K, B, 0.5 * (lam[60] + lam[61]), same=True)
    f = _cholmod.factorize(S, indefinite=True)
    X = np.asfortranarray(np.random.default_rng(2).standard_normal((K.shape[0], 4)))
    plain = np.abs(S @ f.solve(X) - X).max()
    refined = np.abs(S @ _shift.refined_solve(S, f, X) - X).max()
    assert refined <= plain


def test_refined_solve_from_a_first_guess(ico3):
    # the refined Rayleigh-Ritz step starts from the Lanczos relation's guess, which is off
    # by up to about 1e-6 (the coefficients dropped at re-orthogonalisation passes)
    _, K, B, lam = ico3
    S = _shift.shifted(K, B, 0.5 * (lam[60] + lam[61]), same=True)
    f = _cholmod.factorize(S, indefinite=True)
    X = np.asfortranarray(np.random.default_rng(3).standard_normal((K.shape[0], 4)))
    exact = np.linalg.solve(S.toarray(), X)
    guess = exact * (1.0 + 1e-6 * np.random.default_rng(4).standard_normal(exact.shape))
    Z = _shift.refined_solve(S, f, X, guess)
    assert np.abs(S @ Z - X).max() <= np.abs(S @ f.solve(X) - X).max()  # as a plain solve
    two_steps = _shift.refined_solve(S, f, X)
    assert np.abs(Z - two_steps).max() <= 1e-11 * np.abs(exact).max()
    assert np.abs(guess - exact).max() > 1e-8 * np.abs(exact).max()  # the guess was off


@pytest.mark.parametrize("N", [15, 100])
def test_eigenpairs_keep_the_eigenvalues_of_shape_dna(sparse_path, spy, ico3, N):
    # the vectors are orthonormalised (Loewdin), the eigenvalues stay those computed
    # without vectors, the 2 b smallest below the inside shift included (the refined
    # Rayleigh-Ritz step runs in both): the same bits as shape_dna's
    mesh, K, B, ref = ico3
    lam_dna = cshape.shape_dna(mesh, N=N)
    lam, phi = pairs(mesh, N=N)
    assert spy["inside"] == [True, True] and 0 < spy["indefinite"][-1] < N
    np.testing.assert_array_equal(lam, lam_dna)
    np.testing.assert_allclose(lam[1:], ref[1:N], rtol=1e-10)
    np.testing.assert_allclose(phi.T @ (B @ phi), np.eye(N), atol=1e-12)
    # the vectors belong to the values, the smallest ones (from the refined step) too
    resid = K @ phi - (B @ phi) * lam
    assert np.abs(resid).max() < 1e-7 * lam.max()


def test_few_wanted_eigenvalues_keep_the_shift_below(sparse_path, spy, ico3):
    mesh, K, B, ref = ico3
    lam = cshape.shape_dna(mesh, N=_shift.INSIDE_MIN_N - 1)
    assert spy["inside"] == [] and spy["definite"] == 1
    np.testing.assert_allclose(lam[1:], ref[1:_shift.INSIDE_MIN_N - 1], rtol=1e-9)


@pytest.mark.parametrize("N", [10, 30, 100, 150])
def test_inside_path_finds_every_icosahedral_copy(sparse_path, spy, ico3, N):
    mesh, K, B, ref = ico3
    lam = cshape.shape_dna(mesh, N=N)
    assert spy["inside"] == [True] and spy["definite"] == 0
    p = spy["indefinite"][-1]
    assert 0 < p < N  # the shift lies inside the wanted part of the spectrum
    np.testing.assert_allclose(lam[1:], ref[1:N], rtol=1e-9)
    assert lam[0] == 0.0


def test_inside_path_eigenvectors_are_b_orthonormal_eigenvectors(sparse_path, spy, ico3):
    mesh, K, B, ref = ico3
    lam, phi = pairs(mesh, N=60)
    assert spy["inside"] == [True]
    np.testing.assert_allclose(phi.T @ (B @ phi), np.eye(60), atol=1e-10)
    resid = K @ phi - (B @ phi) * lam
    assert np.abs(resid).max() < 1e-7 * lam.max()
    np.testing.assert_allclose(lam[1:], ref[1:60], rtol=1e-9)


def test_a_shift_with_a_large_backward_error_is_replaced(sparse_path, spy, ico3,
                                                         monkeypatch):
    mesh, K, B, ref = ico3
    calls = []
    backward = _shift.backward_error

    def first_bad(S, factor):
        calls.append(factor.inertia)
        return 1.0 if len(calls) == 1 else backward(S, factor)

    monkeypatch.setattr(_shift, "backward_error", first_bad)
    lam = cshape.shape_dna(mesh, N=100)
    assert len(calls) == 2 and spy["inside"] == [True]  # the second shift of INSIDE_SHIFTS
    np.testing.assert_allclose(lam[1:], ref[1:100], rtol=1e-9)


@pytest.mark.parametrize("why", ["backward error", "shift too high", "no LDL^T backend"])
def test_without_a_usable_inside_shift_the_shift_goes_below(sparse_path, spy, ico3,
                                                            monkeypatch, why):
    mesh, K, B, ref = ico3
    if why == "backward error":
        monkeypatch.setattr(_shift, "INSIDE_BACKWARD_MAX", 0.0)
    elif why == "shift too high":
        monkeypatch.setattr(_shift, "INSIDE_SHIFTS", (3.0,))  # N or more below it
    else:
        monkeypatch.setenv("CSHAPE_CHOLESKY", "cholespy")
    lam = cshape.shape_dna(mesh, N=100)
    assert spy["inside"] == [False] and spy["definite"] == 1
    if why == "shift too high":  # one factorisation, then straight to the shift below
        assert len(spy["indefinite"]) == 1 and spy["indefinite"][0] >= 100
    np.testing.assert_allclose(lam[1:], ref[1:100], rtol=1e-9)


def test_a_given_shift_and_big_meshes_keep_the_shift_below(sparse_path, spy, ico3,
                                                         monkeypatch):
    mesh, K, B, ref = ico3
    A = -K
    lam = spectrum.solve_eigenproblem(A, B, 50, return_vectors=False, sigma=-1.0)
    assert spy["inside"] == [] and spy["definite"] == 1
    monkeypatch.setattr(_shift, "INSIDE_LIMIT", 500)
    lam2 = spectrum.solve_eigenproblem(A, B, 50, return_vectors=False)
    assert spy["inside"] == [] and spy["definite"] == 2
    np.testing.assert_allclose(lam[1:], ref[1:50], rtol=1e-9)
    np.testing.assert_allclose(lam2[1:], ref[1:50], rtol=1e-9)


def test_residual_tolerance_is_tighter_only_far_below_an_inside_shift():
    B = np.eye(3)  # area 3: eigenvalue spacing s = 4 pi / 3
    assert _lanczos.pair_tolerance(B, 100, -1.0, None)(np.array([1.0])) == 1.0
    sigma = 0.65 * 4 * np.pi * 100 / 3
    f = _lanczos.pair_tolerance(B, 100, sigma, 60)
    lam = np.array([0.0, 4 * np.pi / 3, 0.3 * sigma, 0.9 * sigma, 1.1 * sigma, 1.5 * sigma])
    factors = f(1.0 / (lam - sigma))
    assert np.all((factors > 0) & (factors <= 1.0))
    assert np.all(np.diff(factors[:4]) >= 0)  # looser towards the shift
    assert factors[0] < 0.2 and factors[3] == factors[4] == 1.0


def test_first_look_at_the_projected_problem_comes_earlier_with_an_inside_shift():
    for N in (20, 100, 200):
        inside = _lanczos.first_check(N, 8, 5000, inside=True)
        assert N <= inside <= _lanczos.first_check(N, 8, 5000)
    assert _lanczos.first_check(1, 8, 5000, inside=True) >= 1
    # near the end an inside shift converges a pair per 1.2 dimensions, not 2.5
    assert _lanczos.next_check(232, 13, 8, inside=True) == 248
    assert _lanczos.next_check(232, 13, 8) == 272
    # big problems look at every step after the first look (a look costs little there)
    big = _lanczos.CHECK_EVERY_STEP_UNKNOWNS
    assert _lanczos.next_check(416, 8, 16, n=big) == 432
    assert _lanczos.next_check(416, 8, 16, n=big - 1) == 448


def test_split_solves_agree_with_one_solve_and_are_deterministic():
    K, B = _KB(shapes.icosphere(4))
    X = np.asfortranarray(np.random.default_rng(1).standard_normal((K.shape[0], 16)))
    f = _cholmod.factorize(K + B)
    one = f.solve(X)
    for parts in (2, 3):
        split = f.solve_split(X, parts)
        np.testing.assert_allclose(split, one, rtol=0, atol=1e-12 * np.abs(one).max())
        np.testing.assert_array_equal(f.solve_split(X, parts), split)
    np.testing.assert_array_equal(f.solve_split(X[:, :3], 2), f.solve(X[:, :3]))  # too few


def test_split_solves_in_turn_give_the_bits_of_split_solves_at_once():
    # one thread solves the same halves one after the other: the same bits as two threads
    K, B = _KB(shapes.icosphere(4))
    X = np.asfortranarray(np.random.default_rng(2).standard_normal((K.shape[0], 16)))
    op = _shift.CholeskyOperator(K + B)
    at_once = op.solve_split(X, parts=2, threads=2)
    np.testing.assert_array_equal(op.solve_split(X, parts=2, threads=1), at_once)
    np.testing.assert_array_equal(op.solve_split(X, parts=2), at_once)
    np.testing.assert_allclose(at_once, op.matmat(X), rtol=0, atol=1e-12 * np.abs(at_once).max())


def test_one_and_two_threads_give_the_same_bits_on_a_big_mesh(monkeypatch):
    # from THREADS_MIN_UNKNOWNS unknowns the block size is BLOCK_SIZE_THREADED whatever the
    # threads, its solves in the same two halves: one thread and two give the same bits
    mesh = shapes.icosphere(4)
    # the default path, which matches dense LAPACK to 1e-9 (test_spectrum_solver.py:
    # test_icosphere_2562_default_path_matches_dense_lapack_to_1e9)
    default = cshape.shape_dna(mesh, N=100)
    monkeypatch.setattr(_threads, "THREADS_MIN_UNKNOWNS", 2000)
    monkeypatch.setattr(_shift, "INSIDE_LIMIT", 0)
    sizes = []
    block = _lanczos.block_lanczos

    def spy_block(*args, **kwargs):
        sizes.append(kwargs.get("block_size"))
        return block(*args, **kwargs)

    monkeypatch.setattr(_lanczos, "block_lanczos", spy_block)
    runs = {}
    for t in ("1", "2", "3"):
        monkeypatch.setenv("CSHAPE_THREADS", t)
        runs[t] = cshape.shape_dna(mesh, N=100)
    assert sizes == [_lanczos.BLOCK_SIZE_THREADED] * 3
    np.testing.assert_array_equal(runs["2"], runs["1"])
    np.testing.assert_array_equal(runs["3"], runs["1"])
    # and the threaded path is as accurate: within 1e-9 of LAPACK too, so within 2e-9 of the
    # default path, the sphere's multiplets included
    np.testing.assert_allclose(runs["1"][1:], default[1:], rtol=2e-9)


@pytest.mark.slow
@pytest.mark.parametrize("N", [20, 100, 200])
def test_inside_path_matches_a_tight_reference_on_real_meshes(shared_meshes, N):
    # The accuracy contract of the default path on real meshes: every eigenvalue within
    # 1e-9 relative of the one-sided method run to a 1e-10 residual (dense LAPACK is no
    # tight reference for the smallest eigenvalues: off by up to 5e-11 on penguin).
    worst = 0.0
    for name in ("goathead/goathead.obj", "penguin/penguin.obj", "sword/sword.obj",
                 "wingnut/wingnut.obj", "fish/fish.obj"):
        path = shared_meshes / name
        if not path.exists():
            pytest.skip(f"{path} not found")
        lam = cshape.shape_dna(cshape.load_mesh(path), N=N)
        worst = max(worst, _relative_error(lam, _tight_reference(str(path))[:N]))
    assert worst < 1e-9


@functools.cache
def _tight_reference(path: str, N: int = 200) -> np.ndarray:
    """:func:`_reference` of the mesh at ``path`` (``N`` values); the smaller sizes of the
    test above compare with its first values (computed once per mesh)."""
    return _reference(cshape.load_mesh(path), N)


def _error_to_tight_reference(mesh, N):
    """Largest relative error of ``shape_dna(mesh, N)`` against the shift below the
    spectrum run to a 1e-10 residual with a 1e-9 bound on the loss of orthogonality
    (zero eigenvalues on the scale of the largest)."""
    return _relative_error(cshape.shape_dna(mesh, N=N), _reference(mesh, N))


def _relative_error(lam, ref):
    """Largest relative error of ``lam`` against ``ref`` (zero eigenvalues on the scale of
    the largest)."""
    scale = np.where(ref > 1e-9 * ref.max(), ref, ref.max())
    return float((np.abs(lam - ref) / scale).max())


def _reference(mesh, N):
    """The ``N`` smallest eigenvalues of ``mesh`` by the shift below the spectrum, run to a
    1e-10 residual with a 1e-9 bound on the loss of orthogonality."""
    K, B = _KB(mesh)
    s0 = _shift.default_sigma(B, N)
    op = _shift.CholeskyOperator(K - s0 * B)
    bound = _lanczos.OMEGA_MAX
    _lanczos.OMEGA_MAX = 1e-9
    try:
        ref, _ = _lanczos.block_lanczos(K, B, N, op.matmat, s0, tol=1e-10,
                                         return_vectors=False, rhs_order=op.rhs_order)
    finally:
        _lanczos.OMEGA_MAX = bound
    return np.sort(ref)


def test_refine_argument_is_partial_of_the_refined_solve():
    # _shift.solve_inside hands _lanczos.block_lanczos an accurate solve for the last
    # Rayleigh-Ritz step
    K, B = _KB(shapes.icosphere(2))
    S = _shift.shifted(K, B, 5.0, same=True)
    f = _cholmod.factorize(S, indefinite=True)
    refine = functools.partial(_shift.refined_solve, S, f)
    X = np.asfortranarray(np.eye(K.shape[0])[:, :4])
    np.testing.assert_allclose(S @ refine(X), X, atol=1e-12)


def test_a_solve_result_is_not_overwritten_by_the_next_solve():
    # CHOLMOD reuses its output buffer: every solve must return a copy, one column too
    K, B = _KB(shapes.icosphere(2))
    f = _cholmod.factorize(K + B)
    x = np.ones(K.shape[0])
    for X in (x, x[:, None], np.asfortranarray(np.stack([x, 2 * x], axis=1))):
        first = f.solve(X)
        kept = first.copy()
        f.solve(5.0 * X)
        np.testing.assert_array_equal(first, kept)


def test_inside_bound_on_orthogonality_keeps_the_contract_where_it_is_tightest():
    # The inside shift tolerates a loss of orthogonality of 3e-8 (_OMEGA_MAX_INSIDE).  On a
    # 1000-vertex torus (N = 300: the largest N / n the sparse path takes, from 3 N >= n the
    # dense one does) 6e-8 gave 2e-10 and 2e-7 gave 8.4e-9 (N = 200); 3e-8 about 1e-12.
    mesh = shapes.torus(50, 20)
    assert 3 * 300 < mesh.n_vertices <= _shift.INSIDE_LIMIT
    assert _error_to_tight_reference(mesh, 300) < 1e-10
    assert _error_to_tight_reference(mesh, 200) < 1e-10
