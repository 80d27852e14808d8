"""The sparse eigensolver: block shift-invert Lanczos (cshape/_eigensolver/lanczos.py), fallback.

Known answers (dense LAPACK, ARPACK with ``tol=0``, exact sphere multiplicities) and
properties (B-orthonormal vectors, determinism, several components).  No timings here:
speed is measured by benchmarks/bench_sweep.py.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import cshape
from cshape import shapes, spectrum
from cshape._eigensolver import lanczos as _lanczos
from cshape._eigensolver import shift as _shift
from cshape._eigensolver import threads as _threads
from cshape.mesh import CShapeWarning


def _KB(mesh, **kw):
    A, B = cshape.fem_matrices(mesh, **kw)
    return (-A).tocsr(), B.tocsr()


def _dense(mesh, N, **kw):
    K, B = _KB(mesh, **kw)
    return la.eigh(K.toarray(), B.toarray(), subset_by_index=[0, N - 1])


def _clusters(lam, rel_gap=0.05):
    """Sizes of the groups of ascending ``lam`` separated by relative jumps > rel_gap."""
    jumps = np.flatnonzero(np.diff(lam) > rel_gap * np.maximum(lam[1:], 1.0))
    return np.diff(np.concatenate([[0], jumps + 1, [len(lam)]])).tolist()


@pytest.fixture
def sparse_path(monkeypatch):
    """Force every problem through the sparse (block Lanczos) path."""
    monkeypatch.setattr(spectrum, "DENSE_LIMIT", 0)


@pytest.mark.parametrize(
    "mesh, kw",
    [
        (lambda: shapes.icosphere(3), {}),
        (lambda: shapes.icosphere(3), {"mass": "lumped"}),
        (lambda: shapes.hemisphere(12), {"bc": "dirichlet"}),
        (lambda: shapes.square(24), {}),
    ],
    ids=["sphere", "sphere-lumped", "hemisphere-dirichlet", "square"],
)
def test_sparse_path_agrees_with_dense_lapack(sparse_path, mesh, kw):
    mesh = mesh()
    N = 60
    lam_ref, phi_ref = _dense(mesh, N, **kw)
    lam, phi = cshape.spectrum.eigenpairs(mesh, N=N, **kw)
    scale = np.where(np.abs(lam_ref) > 1e-9 * lam_ref[-1], np.abs(lam_ref), lam_ref[-1])
    assert np.max(np.abs(lam - lam_ref) / scale) < 1e-9
    # same invariant subspace: the projection of the dense vectors on ours is complete
    K, B = _KB(mesh, **kw)
    free = cshape.fem._problem(mesh, **kw).free
    overlap = phi[free].T @ B @ phi_ref
    # the last cluster may be cut by N: compare the first 50 directions only
    np.testing.assert_allclose(np.linalg.svd(overlap[:, :50], compute_uv=False), 1.0, atol=1e-7)


@pytest.mark.slow
def test_block_lanczos_agrees_with_arpack_tol0():
    mesh = shapes.icosphere(4)  # 2562 vertices: sparse path
    K, B = _KB(mesh)
    sigma = _shift.default_sigma(B, 100)
    op = _shift.CholeskyOperator(K - sigma * B)
    lam_b, _ = _lanczos.block_lanczos(K, B, 100, op.matmat, sigma, return_vectors=False)
    lam_a, _ = _shift.arpack(K, B, 100, op, sigma, return_vectors=False)
    lam_b, lam_a = np.sort(lam_b), np.sort(lam_a)
    np.testing.assert_allclose(lam_b[1:], lam_a[1:], rtol=1e-10)
    assert abs(lam_b[0]) < 1e-10 and abs(lam_a[0]) < 1e-10


@pytest.mark.parametrize("shift", ["inside", "below"])
def test_both_shifts_agree_with_scipy_arpack_tol0_and_keep_the_torus_pairs(shift):
    # An independent reference: scipy's eigsh with tol=0 and its own factorisation
    # (SuperLU), against the public call on a torus (1152 unknowns: sparse path).  Its
    # rotations and reflections make every non-constant mode along the tube a cos/sin pair:
    # the pairs must come out whole from either shift.
    mesh = shapes.torus(48, 24)
    A, B = cshape.fem_matrices(mesh)
    K = (-A).tocsc()
    v0 = np.random.default_rng(3).standard_normal(K.shape[0])
    ref = np.sort(spla.eigsh(K, k=100, M=B.tocsc(), sigma=-1.0, which="LM", v0=v0, tol=0,
                             return_eigenvectors=False))
    sigma = None if shift == "inside" else -0.5
    lam = spectrum.solve_eigenproblem(A, B, 100, return_vectors=False, sigma=sigma)
    assert lam[0] == 0.0 and abs(ref[0]) < 1e-10
    np.testing.assert_allclose(lam[1:], ref[1:], rtol=1e-10)
    # the symmetry group's irreducible representations have dimension 1 or 2: exact pairs
    # (to rounding) and single modes, grouped as in the reference
    sizes = _clusters(lam, rel_gap=1e-8)
    assert sizes == _clusters(ref, rel_gap=1e-8) and set(sizes) == {1, 2}


@pytest.mark.slow
def test_exact_sphere_multiplicities_at_10k_vertices():
    lam = cshape.shape_dna(shapes.icosphere(5), N=100)  # 10242 vertices, l = 0..9
    assert lam[0] == 0.0
    assert _clusters(lam) == [2 * ell + 1 for ell in range(10)]
    exact = shapes.sphere_spectrum(100)
    np.testing.assert_allclose(lam[1:], exact[1:], rtol=1e-2)  # linear FEM, h ~ 0.03


def test_eigenvectors_are_b_orthonormal_eigenvectors():
    mesh = shapes.icosphere(4)
    lam, phi = cshape.spectrum.eigenpairs(mesh, N=100)
    K, B = _KB(mesh)
    np.testing.assert_allclose(phi.T @ (B @ phi), np.eye(100), atol=1e-10)
    res = K @ phi - (B @ phi) * lam
    # residual in the B^-1 norm ~ |Kx - lam Bx| / sqrt(mass per vertex)
    assert np.max(np.linalg.norm(res, axis=0) / np.maximum(lam, 1.0)) < 1e-6
    assert np.all(np.diff(lam) >= 0)


def test_results_are_deterministic():
    mesh = shapes.icosphere(4)
    lam1, phi1 = cshape.spectrum.eigenpairs(mesh, N=50)
    lam2, phi2 = cshape.spectrum.eigenpairs(mesh, N=50)
    np.testing.assert_array_equal(lam1, lam2)
    np.testing.assert_array_equal(phi1, phi2)
    np.testing.assert_array_equal(cshape.shape_dna(mesh, N=50), cshape.shape_dna(mesh, N=50))


def test_two_disjoint_spheres_give_two_zero_eigenvalues():
    one = shapes.icosphere(4)
    V = np.vstack([one.vertices, one.vertices + [3.0, 0.0, 0.0]])
    F = np.vstack([one.faces, one.faces + one.n_vertices])
    with pytest.warns(CShapeWarning, match="2 connected components"):
        lam, phi = cshape.spectrum.eigenpairs((V, F), N=100)
    assert lam[0] == 0.0 and lam[1] == 0.0 and lam[2] > 1.0
    # the union of two identical spectra: every eigenvalue twice, exactly as many copies
    single = cshape.shape_dna(one, N=50)
    np.testing.assert_allclose(lam, np.repeat(single, 2), rtol=1e-9, atol=1e-12)
    assert _clusters(lam) == [2 * (2 * ell + 1) for ell in range(7)] + [2]
    _, B = _KB((V, F))
    np.testing.assert_allclose(phi.T @ (B @ phi), np.eye(100), atol=1e-10)


def test_fallback_to_arpack_when_block_lanczos_fails(monkeypatch):
    mesh = shapes.icosphere(4)
    lam_block = cshape.shape_dna(mesh, N=40)

    def fail(*args, **kwargs):
        raise _lanczos.NoConvergence("forced by the test")

    monkeypatch.setattr(_lanczos, "block_lanczos", fail)
    lam_arpack, phi = cshape.spectrum.eigenpairs(mesh, N=40)
    np.testing.assert_allclose(lam_arpack[1:], lam_block[1:], rtol=1e-10)
    _, B = _KB(mesh)
    np.testing.assert_allclose(phi.T @ (B @ phi), np.eye(40), atol=1e-10)


def test_block_lanczos_gives_up_beyond_its_dimension_budget():
    K, B = _KB(shapes.icosphere(4))
    sigma = _shift.default_sigma(B, 100)
    op = _shift.CholeskyOperator(K - sigma * B)
    with pytest.raises(_lanczos.NoConvergence):
        _lanczos.block_lanczos(K, B, 100, op.matmat, sigma, max_dim=120)


def test_invariant_krylov_space_and_multiplicity_above_block_size():
    # eigenvalues 1, 2, 3 with multiplicities 12, 12, 176: the Krylov space of one block
    # of 8 is invariant after 3 steps and misses copies; random completion finds them.
    d = np.repeat([1.0, 2.0, 3.0], [12, 12, 176])
    perm = np.random.default_rng(1).permutation(len(d))
    K = sp.diags(d[perm]).tocsr()
    B = sp.identity(len(d), format="csr")
    sigma = -0.5
    op = _shift.CholeskyOperator(K - sigma * B)
    lam, phi = _lanczos.block_lanczos(K, B, 20, op.matmat, sigma, block_size=8)
    np.testing.assert_allclose(np.sort(lam), [1.0] * 12 + [2.0] * 8, atol=1e-10)
    np.testing.assert_allclose(phi.T @ phi, np.eye(20), atol=1e-10)


def test_default_shift_is_below_the_spectrum_on_its_scale():
    _, B = _KB(shapes.icosphere(3))
    sigma = _shift.default_sigma(B, 100)
    # Weyl: lam_100 ~ 4 pi 100 / area = 100 on the unit sphere
    assert -2.0 < sigma < -0.5


@pytest.mark.slow
@pytest.mark.realdata
def test_block_lanczos_agrees_with_arpack_on_a_real_mesh(shared_meshes):
    path = shared_meshes / "spot" / "spot.obj"
    if not path.is_file():
        pytest.skip(f"{path} not found")
    K, B = _KB(cshape.load_mesh(path))
    lam = spectrum.solve_eigenproblem(-K, B, 100, return_vectors=False)
    sigma = _shift.default_sigma(B, 100)
    op = _shift.CholeskyOperator(K - sigma * B)
    with _threads.one_blas_thread():
        ref, _ = _shift.arpack(K, B, 100, op, sigma, return_vectors=False)
    ref = np.sort(ref)
    np.testing.assert_allclose(lam[1:], ref[1:], rtol=1e-10)


def test_block_size_below_the_largest_symmetry_multiplicity_is_refused():
    mesh = shapes.icosphere(2)
    K = -cshape.fem_matrices(mesh)[0]
    B = cshape.fem_matrices(mesh)[1]
    with pytest.raises(ValueError, match="block_size must be at least 6"):
        _lanczos.block_lanczos(K, B, 20, lambda X: X, -0.1, block_size=4)


# ------------------------------------------------------------------ row-split products
@pytest.fixture
def split_path(monkeypatch):
    """Small problems take the row-split (threadable) products of big ones."""
    monkeypatch.setattr(_threads, "THREADS_MIN_UNKNOWNS", 500)


@pytest.mark.slow
@pytest.mark.parametrize("threads", [1, 3])
def test_split_products_keep_dense_lapack_eigenvalues_and_icosahedral_copies(
        sparse_path, split_path, threads):
    # icosphere(3): the sphere's l(l+1) split into exact icosahedral multiplicities
    # (1, 3, 4, 5): every copy must be found, to 1e-10 of dense LAPACK, with any threads
    mesh = shapes.icosphere(3)
    K, B = _KB(mesh)
    N = 100
    lam_ref = la.eigh(K.toarray(), B.toarray(), eigvals_only=True, subset_by_index=[0, N - 1])
    sigma = _shift.default_sigma(B, N)
    op = _shift.CholeskyOperator(K - sigma * B)
    with _threads.one_blas_thread():
        lam, phi = _lanczos.block_lanczos(K, B, N, op.matmat, sigma, threads=threads)
    lam = np.sort(lam)
    np.testing.assert_allclose(lam[1:], lam_ref[1:], rtol=1e-10)
    # the exact multiplicities: groups of eigenvalues equal to 1e-8
    groups = np.diff(np.flatnonzero(np.diff(np.concatenate([[-1.0], lam_ref, [1e9]]))
                                    > 1e-8 * lam_ref[-1]))
    assert groups.max() == 5 and set(groups.tolist()) <= {1, 3, 4, 5}
    np.testing.assert_allclose(phi.T @ (B @ phi), np.eye(N), atol=1e-10)


@pytest.mark.slow
def test_split_products_give_the_same_bits_with_any_number_of_threads(split_path):
    K, B = _KB(shapes.icosphere(4))
    sigma = _shift.default_sigma(B, 100)
    op = _shift.CholeskyOperator(K - sigma * B)
    with _threads.one_blas_thread():
        runs = [_lanczos.block_lanczos(K, B, 100, op.matmat, sigma, threads=t)
                for t in (1, 3)]
    for lam, phi in runs[1:]:
        np.testing.assert_array_equal(lam, runs[0][0])
        np.testing.assert_array_equal(phi, runs[0][1])
    # and the same eigenvalues as ARPACK with tol=0
    ref, _ = _shift.arpack(K, B, 100, op, sigma, return_vectors=False)
    np.testing.assert_allclose(np.sort(runs[0][0])[1:], np.sort(ref)[1:], rtol=1e-10)


def test_thread_policy_and_its_environment_override(monkeypatch):
    monkeypatch.delenv("CSHAPE_THREADS", raising=False)
    assert spectrum.solver_threads(1000) == 1  # small: never threaded
    big = _threads.THREADS_MIN_UNKNOWNS
    assert 1 <= spectrum.solver_threads(big) <= _threads.ROW_PARTS
    # off the main thread (a threads-only Dask cluster, a user's thread pool): one thread
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(1) as ex:
        assert ex.submit(spectrum.solver_threads, big).result() == 1
    monkeypatch.setenv("CSHAPE_THREADS", "3")
    assert spectrum.solver_threads(10) == 3
    for bad in ("0", "two", "-1", "1.5"):
        monkeypatch.setenv("CSHAPE_THREADS", bad)
        with pytest.raises(ValueError, match="CSHAPE_THREADS must be a positive integer"):
            spectrum.solver_threads(big)


def test_thread_policy_takes_the_cores_whatever_the_load(monkeypatch):
    # the load average lags and counts other libraries' spinning threads: not read
    import os

    monkeypatch.delenv("CSHAPE_THREADS", raising=False)
    big = _threads.THREADS_MIN_UNKNOWNS
    cores = len(os.sched_getaffinity(0))
    expected = min(cores, _threads.ROW_PARTS)
    monkeypatch.setattr(os, "getloadavg", lambda: (100.0, 100.0, 100.0))
    assert spectrum.solver_threads(big) == expected
    monkeypatch.setattr(os, "getloadavg", lambda: (0.0, 0.0, 0.0))
    assert spectrum.solver_threads(big) == expected


def test_block_size_follows_the_size_only(monkeypatch):
    small, big = _threads.THREADS_MIN_UNKNOWNS - 1, _lanczos.BIG_BLOCK_MAX_UNKNOWNS
    assert _lanczos.block_size(small) == _lanczos.BLOCK_SIZE
    assert _lanczos.block_size(small + 1) == _lanczos.BLOCK_SIZE_THREADED
    assert _lanczos.block_size(big - 1) == _lanczos.BLOCK_SIZE_THREADED
    assert _lanczos.block_size(big) == _lanczos.BLOCK_SIZE
    for threads in ("1", "4"):  # whatever the threads
        monkeypatch.setenv("CSHAPE_THREADS", threads)
        assert _lanczos.block_size(small + 1) == _lanczos.BLOCK_SIZE_THREADED


def _probe(chooser, threads_time):
    """Run a chooser through its probe steps with a solve time per thread count."""
    picked = []
    for _ in range(1 + _threads.ThreadChooser.PROBE_STEPS):
        picked.append(chooser.start_step())
        chooser.record(threads_time[chooser.current])
    return picked, chooser.start_step()


def test_thread_chooser_keeps_the_threads_that_solve_faster():
    probe = [2, 2, 1, 2, 1]  # step 0 at the most threads, then alternating
    assert _probe(_threads.ThreadChooser(2), {2: 0.5, 1: 1.0}) == (probe, 2)
    assert _probe(_threads.ThreadChooser(2), {2: 1.2, 1: 1.0}) == (probe, 1)
    # a gain under GAIN (5 %) is not worth a second thread
    assert _probe(_threads.ThreadChooser(2), {2: 0.97, 1: 1.0}) == (probe, 1)
    # one thread allowed: never probes
    assert _probe(_threads.ThreadChooser(1), {1: 1.0}) == ([1] * 5, 1)
    # probes again after REPROBE_EVERY steps
    chooser = _threads.ThreadChooser(2)
    _probe(chooser, {2: 1.2, 1: 1.0})
    for _ in range(_threads.ThreadChooser.REPROBE_EVERY - 6):
        assert chooser.start_step() == 1
        chooser.record(1.0)
    assert chooser.start_step() == 1  # step REPROBE_EVERY: phase 0 keeps the choice
    assert chooser.start_step() == 2  # then the probe


DETERMINISM = """
import sys
import numpy as np
from cshape import shapes, shape_dna
lam = shape_dna(shapes.icosphere(4), N=100)
sys.stdout.write(lam.tobytes().hex())
"""


@pytest.mark.slow
def test_results_are_identical_across_processes():
    # fixed seeds, no dependence on threads or on the state of the process: a fresh
    # interpreter (here with 2 threads allowed for the products) gives the same bits
    import os
    import subprocess
    import sys

    lam = cshape.shape_dna(shapes.icosphere(4), N=100)
    env = dict(os.environ, CSHAPE_THREADS="2")
    out = subprocess.run([sys.executable, "-c", DETERMINISM], capture_output=True, text=True,
                         check=True, env=env).stdout
    np.testing.assert_array_equal(np.frombuffer(bytes.fromhex(out)), lam)


@pytest.mark.parametrize("N", [1, 7, 30, 150])
def test_rayleigh_ritz_schedule_finds_every_copy_for_any_N(sparse_path, N):
    # The projected problem is solved only where the pairs are predicted to have
    # converged (_lanczos.first_check, _next_check): for small and large N alike the
    # result is dense LAPACK's, every icosahedral copy included (groups of 1, 3, 4, 5).
    mesh = shapes.icosphere(3)
    K, B = _KB(mesh)
    lam_ref = la.eigh(K.toarray(), B.toarray(), eigvals_only=True, subset_by_index=[0, N - 1])
    lam = cshape.shape_dna(mesh, N=N)
    scale = np.maximum(lam_ref, 1.0)  # unit sphere: lam_0 = 0, then lam >= 2
    assert np.max(np.abs(lam - lam_ref) / scale) < 1e-9
    assert _lanczos.first_check(N) >= N
    assert _lanczos.next_check(200, 3, 8) == 208 and _lanczos.next_check(200, 10, 8) == 232


@pytest.mark.slow
def test_icosphere_2562_default_path_matches_dense_lapack_to_1e9():
    # The default path as users call it (sparse at 2562 unknowns, Rayleigh-Ritz only where
    # predicted): every eigenvalue of the icosahedral multiplets within 1e-9 of LAPACK.
    mesh = shapes.icosphere(4)
    K, B = _KB(mesh)
    ref = la.eigh(K.toarray(), B.toarray(), eigvals_only=True, subset_by_index=[0, 99])
    lam = cshape.shape_dna(mesh, N=100)
    assert lam[0] == 0.0
    np.testing.assert_allclose(lam[1:], ref[1:], rtol=1e-9)


def test_a_loss_of_orthogonality_above_the_bound_brings_a_pass_at_every_step():
    bound = _lanczos.OMEGA_MAX
    assert _lanczos.next_skip(3, 2 * bound) == 0  # not 2: the loss spreads
    assert _lanczos.next_skip(0, 0.5 * bound) == 0
    assert _lanczos.next_skip(1, 0.5 * bound) == 1
    assert _lanczos.next_skip(1, 1e-4 * bound) == 2
    assert _lanczos.next_skip(4, 1e-4 * bound) == 4
    assert _lanczos.next_skip(1, 0.5 * bound, bound=1e-3 * bound) == 0  # another bound
    # the bounds stay near sqrt(eps), where the Ritz values keep their accuracy
    assert 1e-9 <= bound <= 1.5e-8 and bound <= _lanczos.OMEGA_MAX_INSIDE <= 3e-8


@pytest.mark.slow
def test_the_threaded_path_gives_the_bits_of_one_thread(split_path, monkeypatch):
    # blocks of 16 solved whole (one thread) or as halves at once (two), the basis written
    # in another thread while the matrix is factorised: the same eigenpairs, bit for bit,
    # and the dense LAPACK ones
    K, B = _KB(shapes.icosphere(3))
    lam_ref = la.eigh(K.toarray(), B.toarray(), eigvals_only=True, subset_by_index=[0, 59])
    runs = []
    for threads in ("1", "2"):
        monkeypatch.setenv("CSHAPE_THREADS", threads)
        assert _lanczos.block_size(K.shape[0]) == _lanczos.BLOCK_SIZE_THREADED
        assert (_shift._basis_beside(K.shape[0], 60, 16, int(threads)) is None) == \
            (threads == "1")
        runs.append(_shift.solve_below(K, B, 60, None, _shift.same_pattern(K, B), True))
    np.testing.assert_array_equal(runs[1][0], runs[0][0])
    np.testing.assert_array_equal(runs[1][1], runs[0][1])
    np.testing.assert_allclose(runs[0][0][1:], lam_ref[1:], rtol=1e-10)


def test_a_basis_given_to_block_lanczos_must_have_its_shape():
    K, B = _KB(shapes.icosphere(3))
    sigma = _shift.default_sigma(B, 30)
    op = _shift.CholeskyOperator(K - sigma * B)
    blocks, columns, touched = _lanczos.basis_shape(K.shape[0], 30, 8)
    assert blocks == max(6 * 30, 30 + 40 * 8) // 8 and columns == (blocks + 1) * 8
    assert touched == _lanczos.first_check(30, 8, K.shape[0]) + 16
    V = _lanczos.empty_basis(K.shape[0], columns, touched)
    given = _lanczos.block_lanczos(K, B, 30, op.matmat, sigma, basis=V)
    own = _lanczos.block_lanczos(K, B, 30, op.matmat, sigma)
    np.testing.assert_array_equal(given[0], own[0])
    np.testing.assert_array_equal(given[1], own[1])
    with pytest.raises(ValueError, match=r"basis must be a column-major array of shape"):
        _lanczos.block_lanczos(K, B, 30, op.matmat, sigma, basis=np.asfortranarray(V[:, :-8]))
    with pytest.raises(ValueError, match=r"basis must be a column-major array"):
        _lanczos.block_lanczos(K, B, 30, op.matmat, sigma, basis=np.ascontiguousarray(V))
