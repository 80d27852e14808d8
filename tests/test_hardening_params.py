"""Hardening: bad parameters.  Every error names the argument, the bad value and what is
allowed; integer arguments accept NumPy integers and refuse bools; choices are checked
before any eigensolve."""

from __future__ import annotations

import numpy as np
import pytest

import cshape
import cshape.spectrum
from cshape import Mesh, shapes

TET_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
TET_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
LAM = 4 * np.pi * np.arange(12.0) + np.sin(np.arange(12.0))  # a normalised Shape-DNA


@pytest.fixture(scope="module")
def sphere():
    return shapes.icosphere(1)  # 42 vertices


@pytest.fixture
def no_eigensolve(monkeypatch):
    """Fail the test if an eigenproblem is solved: validation must come first."""

    def boom(*args, **kwargs):
        pytest.fail("an eigensolve ran before the parameters were checked")

    monkeypatch.setattr(cshape.spectrum, "shape_dna", boom)
    monkeypatch.setattr(cshape.spectrum, "solve_eigenproblem", boom)


# ------------------------------------------------------------------ N
@pytest.mark.parametrize(
    "N, exc, match",
    [
        (0, ValueError, r"N must be at least 1 .*got 0"),
        (-3, ValueError, r"N must be at least 1 .*got -3"),
        (2.5, TypeError, r"N must be an integer, got float 2.5"),
        (4.0, TypeError, r"N must be an integer, got float 4.0"),
        ("10", TypeError, r"N must be an integer, got str '10'"),
        (None, TypeError, r"N must be an integer, got NoneType"),
        (True, TypeError, r"N must be an integer, got bool True"),
        (np.bool_(True), TypeError, r"N must be an integer"),
    ],
)
@pytest.mark.parametrize("fn", ["shape_dna", "eigenpairs", "compact_shape_dna"])
def test_bad_N(sphere, fn, N, exc, match):
    call = {
        "shape_dna": lambda: cshape.shape_dna(sphere, N=N),
        "eigenpairs": lambda: cshape.eigenpairs(sphere, N=N),
        "compact_shape_dna": lambda: cshape.compact_shape_dna(sphere, M=0, N=N),
    }[fn]
    with pytest.raises(exc, match=match):
        call()


@pytest.mark.parametrize("N", [np.int8(5), np.int32(5), np.int64(5), np.uint16(5)])
def test_numpy_integer_N_and_M_are_accepted(sphere, N):
    lam = cshape.shape_dna(sphere, N=N)
    assert lam.shape == (5,)
    S = cshape.compact_shape_dna(sphere, M=np.int64(2), N=N)
    assert S.shape == (5,)
    np.testing.assert_allclose(S, cshape.compact_shape_dna(lam, M=2, N=5, area=sphere.area))


def test_N_equal_1_is_legal_for_shape_dna_and_for_compact_with_M_0(sphere):
    assert cshape.shape_dna(sphere, N=1).tolist() == [0.0]
    S = cshape.compact_shape_dna(sphere, M=0, N=1)
    assert S.shape == (1,) and S[0] == 0  # lam_0 = 0, Weyl line 0 at i = 0
    with pytest.raises(ValueError, match=r"2M\+1 = 3 values cannot be kept from N = 1"):
        cshape.compact_shape_dna(sphere, M=1, N=1)


def test_N_from_eigenvalues(no_eigensolve):
    with pytest.raises(ValueError, match=r"got 12 eigenvalues but N=20; pass N=12"):
        cshape.compact_shape_dna(LAM, M=2, N=20)
    with pytest.raises(TypeError, match="N must be an integer"):
        cshape.compact_shape_dna(LAM, M=2, N=np.float64(5))
    S = cshape.compact_shape_dna(LAM, M=2, N=5, normalized=True)
    assert S.shape == (5,)  # uses the first 5


# ------------------------------------------------------------------ M
@pytest.mark.parametrize(
    "M, N, exc, match",
    [
        (-1, 9, ValueError, r"M must be >= 0 \(the descriptor has 2M\+1 values\), got -1"),
        (5, 9, ValueError, r"2M\+1 = 11 values cannot be kept from N = 9.*use M <= 4"),
        (5, 10, ValueError, r"use M <= 4 or a larger N"),
        (1.0, 9, TypeError, r"M must be an integer, got float 1.0"),
        ("2", 9, TypeError, r"M must be an integer, got str '2'"),
        (None, 9, TypeError, r"M must be an integer"),
        (True, 9, TypeError, r"M must be an integer, got bool True"),
        (np.bool_(False), 9, TypeError, r"M must be an integer"),
    ],
)
def test_bad_M_is_refused_before_the_eigensolve(sphere, no_eigensolve, M, N, exc, match):
    with pytest.raises(exc, match=match):
        cshape.compact_shape_dna(sphere, M=M, N=N)
    with pytest.raises(exc, match=match):
        cshape.compact_shape_dna(LAM, M=M, N=N)


@pytest.mark.parametrize("N", [9, 10])
def test_largest_legal_M(N):
    M = (N - 1) // 2
    S = cshape.compact_shape_dna(LAM, M=M, N=N, normalized=True)
    assert S.shape == (2 * M + 1,)
    np.testing.assert_allclose(S[M + 1:], np.conj(S[:M][::-1]))  # conjugate symmetric


def test_inverse_compact_checks_N_and_M():
    S = cshape.compact_shape_dna(LAM, M=2, N=9, normalized=True)
    with pytest.raises(TypeError, match="N must be an integer"):
        cshape.inverse_compact_shape_dna(S, N=True)
    with pytest.raises(ValueError, match=r"use M <= 1"):
        cshape.inverse_compact_shape_dna(S, N=3)
    with pytest.raises(ValueError, match="odd length"):
        cshape.inverse_compact_shape_dna(S[:4], N=9)


# ------------------------------------------------------------------ choices
@pytest.mark.parametrize("bc", ["robin", "", None, 0, "neumann "])
def test_unknown_bc(sphere, no_eigensolve, bc):
    match = r"bc must be one of \{'neumann', 'dirichlet'\}, got"
    exc = ValueError if isinstance(bc, str) else TypeError
    with pytest.raises(exc, match=match):
        cshape.fem_matrices(sphere, bc=bc)
    with pytest.raises(exc, match=match):
        cshape.compact_shape_dna(sphere, M=1, N=5, bc=bc)
    with pytest.raises(exc, match=match):
        cshape.compact_shape_dna(LAM, M=1, N=5, bc=bc)  # checked even for eigenvalues


def test_unknown_bc_in_the_solver_entry_points(sphere):
    for fn in (cshape.shape_dna, cshape.eigenpairs):
        with pytest.raises(ValueError, match=r"bc must be one of"):
            fn(sphere, N=3, bc="periodic")


@pytest.mark.parametrize("mass", ["diagonal", None, "Lumped!"])
def test_unknown_mass(sphere, mass):
    exc = ValueError if isinstance(mass, str) else TypeError
    for call in (lambda: cshape.fem_matrices(sphere, mass=mass),
                 lambda: cshape.shape_dna(sphere, N=3, mass=mass)):
        with pytest.raises(exc, match=r"mass must be one of \{'consistent', 'lumped'\}"):
            call()


def test_choices_are_case_insensitive(sphere):
    A1, B1 = cshape.fem_matrices(sphere, bc="Neumann", mass="LUMPED")
    A2, B2 = cshape.fem_matrices(sphere, bc="neumann", mass="lumped")
    assert abs(A1 - A2).max() == 0 and abs(B1 - B2).max() == 0
    np.testing.assert_array_equal(cshape.compact_shape_dna(LAM, M=1, N=5, normalization="WEYL"),
                                  cshape.compact_shape_dna(LAM, M=1, N=5, normalization="weyl"))


@pytest.mark.parametrize("norm", ["max", "", None, 1])
def test_unknown_normalization_names_the_argument(sphere, no_eigensolve, norm):
    match = r"normalization must be one of \{'area', 'fiedler', 'weyl'\}, got"
    exc = ValueError if isinstance(norm, str) else TypeError
    with pytest.raises(exc, match=match):
        cshape.compact_shape_dna(sphere, M=1, N=5, normalization=norm)
    with pytest.raises(exc, match=match):
        cshape.compact_shape_dna(LAM, M=1, N=5, normalization=norm)
    with pytest.raises(exc, match=r"method must be one of \{'area', 'fiedler', 'weyl'\}"):
        cshape.normalize(LAM, area=1.0, method=norm)


@pytest.mark.parametrize("area", [0, -1.0, np.nan, np.inf, "abc", True, [1.0, 2.0]])
def test_bad_area(area):
    with pytest.raises(ValueError, match="area must be a positive finite number"):
        cshape.normalize(LAM, area=area)
    with pytest.raises(ValueError, match="area must be a positive finite number"):
        cshape.compact_shape_dna(LAM, M=1, N=5, area=area)


# ------------------------------------------------------------------ array shapes and dtypes
@pytest.mark.parametrize(
    "V, F, exc, match",
    [
        (TET_V + 0j, TET_F, TypeError, "vertices must be real coordinates, got a complex"),
        (TET_V, TET_F.astype(bool), TypeError, "faces must be an integer array .*dtype bool"),
        (TET_V.ravel(), TET_F, ValueError, r"vertices must have shape \(n, 3\), got \(12,\)"),
        (TET_V, TET_F.ravel(), ValueError, r"faces must have shape \(m, 3\)"),
        (TET_V.T[:, :3], TET_F, ValueError, r"faces reference vertex indices outside \[0, 2\]"),
        (TET_V[:, :2], TET_F, ValueError, r"vertices must have shape \(n, 3\), got \(4, 2\)"),
        (TET_V[None], TET_F, ValueError, r"vertices must have shape \(n, 3\), got \(1, 4, 3\)"),
        (TET_V, TET_F.astype(object), TypeError, "faces must be an integer array .*dtype object"),
        (TET_V, TET_F.astype(str), TypeError, "faces must be an integer array"),
        (TET_V, TET_F + 0.25, TypeError, "non-integer floats"),
        (TET_V, np.where(TET_F == 3, np.nan, TET_F), TypeError, "non-integer floats"),
        (TET_V, np.array([[0, 1, 1e30]]), ValueError, r"vertex index 1e\+30, outside \[0, 3\]"),
        ([[0, 0, 0], [1, 0], [0, 1, 0]], [[0, 1, 2]], TypeError, "vertices must be a real array"),
        (TET_V, [[0, 1, 2], [0, 1]], TypeError, "faces must be an integer array .*ragged"),
        ([["a", "b", "c"]] * 3, [[0, 1, 2]], TypeError, "vertices must be a real array"),
        ([[None] * 3] * 3, [[0, 1, 2]], ValueError, "NaN or infinite"),
        (TET_V, [[0, 1, 2, 3]], ValueError, r"faces must have shape \(m, 3\).*triangulate"),
    ],
    ids=["complex_V", "bool_F", "1d_V", "1d_F", "transposed_V", "2d_points", "3d_V",
         "object_F", "str_F", "fractional_F", "nan_F", "huge_float_F", "ragged_V", "ragged_F",
         "str_V", "none_V", "quads"],
)
def test_bad_arrays(V, F, exc, match):
    with pytest.raises(exc, match=match):
        Mesh(V, F)
    with pytest.raises(exc, match=match):
        cshape.shape_dna((V, F), N=2)


@pytest.mark.parametrize(
    "V, F",
    [
        (TET_V.tolist(), TET_F.tolist()),
        (TET_V.astype(np.float32), TET_F.astype(np.int8)),
        (TET_V.astype(int), TET_F.astype(np.uint16)),
        (TET_V.astype(object), TET_F),
        (TET_V, TET_F.astype(float)),  # integral floats, e.g. from np.loadtxt
        (np.asfortranarray(TET_V), np.asfortranarray(TET_F)),
        (TET_V[:, [2, 1, 0]][:, ::-1], TET_F),  # a non-contiguous view
    ],
    ids=["lists", "float32_int8", "int_uint16", "object_V", "float_F", "fortran", "view"],
)
def test_accepted_array_forms(V, F):
    m = Mesh(V, F)
    assert m.vertices.dtype == np.float64 and m.faces.dtype == np.int64
    assert m.vertices.flags.c_contiguous and m.faces.flags.c_contiguous
    np.testing.assert_array_equal(m.vertices, np.asarray(TET_V, float))
    np.testing.assert_array_equal(m.faces, TET_F)


@pytest.mark.parametrize("obj", [(TET_V, TET_F, None), {"v": TET_V}, TET_V, 3, None])
def test_as_mesh_rejects_other_objects(obj):
    with pytest.raises(TypeError, match="expected a cshape.Mesh or a \\(vertices, faces\\) pair"):
        cshape.as_mesh(obj)


@pytest.mark.parametrize(
    "lam, exc, match",
    [
        (LAM + 1j, TypeError, "real eigenvalues, got a complex array"),
        (LAM[None, :], ValueError, r"1-D \(one spectrum\), got shape \(1, 12\)"),
        (np.r_[LAM[:3], np.nan], ValueError, "NaN or infinite"),
        ([], ValueError, "at least 1 eigenvalues, got 0"),
        (["a", "b"], TypeError, "1-D array of real eigenvalues"),
    ],
)
def test_bad_eigenvalue_arrays(lam, exc, match):
    with pytest.raises(exc, match=match):
        cshape.normalize(lam, area=1.0)
    with pytest.raises(exc, match=match):
        cshape.weyl_subtract(lam)


def test_real_form_shapes():
    with pytest.raises(ValueError, match="odd last dimension"):
        cshape.real_form(np.ones(4, complex))
    with pytest.raises(ValueError, match="odd last dimension"):
        cshape.real_form(np.ones((2, 2, 3), complex))
    assert cshape.real_form(np.ones((2, 3), complex)).shape == (2, 3)


# ------------------------------------------------------------------ variants: memory guards
def test_remesh_and_subdivide_refuse_outputs_that_would_exhaust_memory():
    from cshape.data import variants

    s = shapes.icosphere(2)  # 320 faces, area ~12.5
    with pytest.raises(ValueError, match=r"target_length=0.0001 would make about .* use "
                                         r"target_length >= 0\.00\d+"):
        variants.remesh(s, target_length=1e-4)
    with pytest.raises(ValueError, match=r"iterations=8 would make .* use iterations <= 7"):
        variants.subdivide(s, iterations=8)
    with pytest.raises(ValueError, match=r"iterations must be an integer in \[0, 8\]"):
        variants.subdivide(s, iterations=9)
    with pytest.raises(TypeError, match="iterations must be an integer"):
        variants.subdivide(s, iterations=True)


@pytest.mark.parametrize("lam", [np.inf, np.nan, -1.0, True, "1"])
def test_noise_level_must_be_finite_and_non_negative(lam):
    from cshape.data import variants

    with pytest.raises(ValueError, match=r"lam must be a number >= 0"):
        variants.add_normal_noise(shapes.icosphere(1), lam=lam)


@pytest.mark.parametrize("expr, match", [
    ("x+", "Unexpected end of expression"),
    ("foo(x)", 'Unexpected token "foo"'),
    ("((((", "Unexpected end of expression"),
])
def test_marching_cubes_bad_expression(expr, match):
    from cshape.data import variants

    with pytest.raises(ValueError, match=rf"expr .* is not a valid muparser expression.*{match}"):
        variants.marching_cubes(expr, (-1, -1, -1, 1, 1, 1), 0.1)


@pytest.mark.parametrize("expr", ["sqrt(-1)", "1/0", "x^2+y^2+z^2+1"])
def test_marching_cubes_without_a_surface(expr):
    from cshape.data import variants

    with pytest.raises(ValueError, match="produced no triangles"):
        variants.marching_cubes(expr, (-1, -1, -1, 1, 1, 1), 0.1)


# ------------------------------------------------------------------ shapes
@pytest.mark.parametrize("make, arg", [
    (lambda v: shapes.icosphere(1, radius=v), "radius"),
    (lambda v: shapes.square(2, size=v), "size"),
    (lambda v: shapes.disk(2, radius=v), "radius"),
    (lambda v: shapes.hemisphere(2, radius=v), "radius"),
    (lambda v: shapes.cube(1, size=v), "size"),
    (lambda v: shapes.torus(4, 3, R=v, r=0.1), "R"),
    (lambda v: shapes.sphere_spectrum(5, radius=v), "radius"),
])
def test_shape_lengths_must_be_positive_finite_numbers(make, arg):
    for bad in (0, -1.0, np.nan, np.inf):
        with pytest.raises(ValueError, match=rf"{arg} must be a positive finite number"):
            make(bad)
    for bad in ("1", True, None, [1.0]):
        with pytest.raises(TypeError, match=rf"{arg} must be a positive number"):
            make(bad)
    make(np.float32(2.0))  # NumPy scalars are fine


def test_shape_levels_refuse_bools_and_floats():
    with pytest.raises(ValueError, match=r"subdivisions must be an integer in \[0, 8\]"):
        shapes.icosphere(True)
    with pytest.raises(ValueError, match=r"n must be an integer in \[1, 4096\]"):
        shapes.square(2.0)
    with pytest.raises(ValueError, match=r"N must be an integer in \[0, 100000000\]"):
        shapes.sphere_spectrum(True)
    assert shapes.icosphere(np.int64(0)).n_vertices == 12
