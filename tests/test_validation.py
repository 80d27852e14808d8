"""The contract layer: every argument check of the public boundary, as one table per module.

The rule (cshape/_checks.py): ``TypeError`` for a wrong type, ``ValueError`` for a value out
of range, a message naming the argument, the value and the fix, and the *same* exception and
message for the same bad argument in every function that takes it.  Each table row is
``(callable, kwargs, exception, match)``; the consistency table calls every entry point of an
argument with the same bad value.  Checks run before any eigensolve (``no_eigensolve``).

What the boundary accepts (NumPy integers, lists, other dtypes, case-insensitive options) is
at the end; the one spelling of mode names after it.
Behaviour on imperfect meshes is in test_imperfect_meshes.py, on files in test_readers.py.
"""

from __future__ import annotations

import functools
import gzip
import os

import numpy as np
import pytest
from meshfiles import F_OOR, MALFORMED, OFF_TET, TET_F, TET_V, ply_be_double

import cshape
import cshape.signatures
import cshape.spectrum
from cshape import Descriptor, Mesh, shapes
from cshape._checks import (
    check_bool,
    check_choice,
    check_int,
    check_n_jobs,
    check_path,
    check_real,
)
from cshape._eigensolver.threads import solver_threads
from cshape.batch import DescriptorTable, describe
from cshape.descriptors import inverse_compact_shape_dna, log_weyl_ratio, real_form
from cshape.descriptors.formulas import f1_feature, nonzero_eigenvalues
from cshape.descriptors.recipe import DESCRIPTOR_KINDS
from cshape.fem import _problem as fem
from cshape.index import DescriptorIndex
from cshape.spectrum import solve_eigenproblem

LAM = 4 * np.pi * np.arange(12.0) + np.sin(np.arange(12.0))  # a normalised Shape-DNA
_NAN_V = TET_V.copy()
_NAN_V[2, 1] = np.nan
_INF_V = TET_V.copy()
_INF_V[3, 0] = -np.inf


@functools.cache
def sphere():
    return shapes.icosphere(1)  # 42 vertices; built on first use, never at import time


@functools.cache
def table():
    rng = np.random.default_rng(0)
    lam = np.c_[np.zeros(4), np.cumsum(rng.uniform(0.5, 2.0, (4, 29)), axis=1)]
    return DescriptorTable(["a", "b", "c", "d"], lam, rng.uniform(1, 2, 4), ["x", "x", "y", "y"])


@pytest.fixture
def no_eigensolve(monkeypatch):
    """Fail the test if an eigenproblem is solved: validation must come first."""

    def boom(*args, **kwargs):
        pytest.fail("an eigensolve ran before the parameters were checked")

    monkeypatch.setattr(cshape.spectrum, "shape_dna", boom)
    monkeypatch.setattr(cshape.spectrum, "solve_eigenproblem", boom)


def _raises(call, kwargs, exc, match):
    with pytest.raises(exc, match=match) as info:
        call(**kwargs)
    return str(info.value)


# ====================================================================== the checks themselves
CHECKS = [
    pytest.param(check_int, dict(name="N", value=2.5), TypeError,
                 r"^N must be an integer, got float 2\.5$", id="int-float"),
    pytest.param(check_int, dict(name="N", value=True), TypeError,
                 r"^N must be an integer, got bool True$", id="int-bool"),
    pytest.param(check_int, dict(name="N", value=None), TypeError,
                 r"^N must be an integer, got NoneType$", id="int-None"),
    pytest.param(check_int, dict(name="N", value=0, min=1), ValueError,
                 r"^N must be an integer >= 1, got 0$", id="int-min"),
    pytest.param(check_int, dict(name="k", value=9, max=8), ValueError,
                 r"^k must be an integer <= 8, got 9$", id="int-max"),
    pytest.param(check_int, dict(name="s", value=9, min=0, max=8), ValueError,
                 r"^s must be an integer in \[0, 8\], got 9$", id="int-range"),
    pytest.param(check_real, dict(name="a", value="1"), TypeError,
                 r"^a must be a real number, got str '1'$", id="real-str"),
    pytest.param(check_real, dict(name="a", value=1j), TypeError,
                 r"^a must be a real number, got complex 1j$", id="real-complex"),
    pytest.param(check_real, dict(name="a", value=np.bool_(True)), TypeError,
                 r"^a must be a real number, got bool", id="real-npbool"),
    pytest.param(check_real, dict(name="a", value=np.nan), ValueError,
                 r"^a must be a finite number, got nan$", id="real-nan"),
    pytest.param(check_real, dict(name="a", value=0, positive=True), ValueError,
                 r"^a must be a positive finite number, got 0\.0$", id="real-positive"),
    pytest.param(check_real, dict(name="a", value=-1, min=0), ValueError,
                 r"^a must be a finite number >= 0, got -1\.0$", id="real-min"),
    pytest.param(check_real, dict(name="a", value=np.nan, finite=False), ValueError,
                 r"^a must be a number, got nan$", id="real-nan-not-finite"),
    pytest.param(check_bool, dict(name="b", value=1), TypeError,
                 r"^b must be True or False, got int 1$", id="bool-int"),
    pytest.param(check_path, dict(name="path", value=3), TypeError,
                 r"^path must be a path \(str or os\.PathLike\), got int 3$", id="path-int"),
    pytest.param(check_path, dict(name="path", value=b"x.off"), TypeError,
                 r"^path must be a path", id="path-bytes"),
    pytest.param(check_path, dict(name="path", value=" "), ValueError,
                 r"^path is an empty path", id="path-empty"),
    pytest.param(check_n_jobs, dict(value=0), ValueError,
                 r"^n_jobs must be a positive integer or -1 \(all cores\), got 0$", id="jobs-0"),
    pytest.param(check_choice, dict(name="bc", value=0, allowed=("a", "b")), TypeError,
                 r"^bc must be one of \{'a', 'b'\}, got int 0$", id="choice-type"),
    pytest.param(check_choice, dict(name="bc", value="c", allowed=("a", "b")), ValueError,
                 r"^bc must be one of \{'a', 'b'\}, got 'c'$", id="choice-value"),
]


@pytest.mark.parametrize("call, kwargs, exc, match", CHECKS)
def test_checks(call, kwargs, exc, match):
    _raises(call, kwargs, exc, match)


def test_checks_return_plain_python_values():
    assert check_int("N", np.uint16(5)) == 5 and type(check_int("N", np.int8(5))) is int
    assert check_real("a", np.float32(2.0)) == 2.0 and type(check_real("a", 3)) is float
    assert check_real("a", np.array(2.5)) == 2.5  # a 0-d array
    assert check_bool("b", np.bool_(True)) is True
    assert check_path("p", "a/b.off").name == "b.off"
    assert check_n_jobs(None) is None and check_n_jobs(-1) == -1
    assert check_choice("bc", "Neumann", ("neumann",)) == "neumann"


# ====================================================================== one argument, one error
def _bad_table(**kw):
    t = table()
    return DescriptorTable(t.names, t.lam, t.areas, t.labels, **kw)


def _describe(**kw):
    return describe([("s", sphere())], **{"N": 9, "cache_dir": False,
                                         "progress": False, **kw})


S1 = np.array([1.0 + 0j])  # a cShape-DNA with M = 0

#: Every public entry point of an argument, the argument given by keyword, the others valid.
#: Entries in NONE_OK take None as "the default" and are left out of the None rows.
TAKES = {
    "N": {
        "shape_dna": lambda v: cshape.shape_dna(sphere(), N=v),
        "eigenbasis": lambda v: cshape.eigenbasis(sphere(), N=v),
        "point_map": lambda v: cshape.point_map(sphere(), sphere(), N=v, N0=2),
        "compact_shape_dna": lambda v: cshape.compact_shape_dna(LAM, M=0, N=v,
                                                                     normalization="none"),
        "inverse_compact_shape_dna": lambda v: inverse_compact_shape_dna(S1, N=v),
        "Descriptor": lambda v: Descriptor("shape-dna", N=v),
        "describe": lambda v: _describe(N=v),
        "sphere_spectrum": lambda v: shapes.sphere_spectrum(v),
    },
    "M": {
        "compact_shape_dna": lambda v: cshape.compact_shape_dna(LAM, M=v, N=9,
                                                                     normalization="none"),
        "Descriptor": lambda v: Descriptor("cshape", N=9, M=v),
    },
    "area": {
        "normalize": lambda v: cshape.normalize(LAM, area=v),
        "compact_shape_dna": lambda v: cshape.compact_shape_dna(LAM, M=1, N=5, area=v),
        "Eigenbasis": lambda v: cshape.Eigenbasis(LAM, np.eye(12), np.eye(12), v),
    },
    "bc": {
        "fem_matrices": lambda v: cshape.fem_matrices(sphere(), bc=v),
        "shape_dna": lambda v: cshape.shape_dna(sphere(), N=3, bc=v),
        "eigenbasis": lambda v: cshape.eigenbasis(sphere(), N=3, bc=v),
        "Eigenbasis": lambda v: cshape.Eigenbasis(LAM, np.eye(12), np.eye(12), bc=v),
        "DescriptorTable": lambda v: _bad_table(bc=v),
        "describe": lambda v: _describe(bc=v),
    },
    "mass": {
        "fem_matrices": lambda v: cshape.fem_matrices(sphere(), mass=v),
        "shape_dna": lambda v: cshape.shape_dna(sphere(), N=3, mass=v),
        "eigenbasis": lambda v: cshape.eigenbasis(sphere(), N=3, mass=v),
        "Eigenbasis": lambda v: cshape.Eigenbasis(LAM, np.eye(12), np.eye(12), mass=v),
        "DescriptorTable": lambda v: _bad_table(mass=v),
        "describe": lambda v: _describe(mass=v),
    },
    "normalization": {
        "compact_shape_dna": lambda v: cshape.compact_shape_dna(LAM, M=1, N=5,
                                                                     normalization=v),
        "normalize": lambda v: cshape.normalize(LAM, 1.0, normalization=v),
        "Descriptor": lambda v: Descriptor("cshape", N=9, M=3, normalization=v),
    },
    "transform": {
        "compact_shape_dna": lambda v: cshape.compact_shape_dna(LAM, M=1, N=5, transform=v),
        "inverse_compact_shape_dna": lambda v: inverse_compact_shape_dna(S1, 5,
                                                                                transform=v),
        "Descriptor": lambda v: Descriptor("cshape", N=9, M=3, transform=v),
    },
    "kind": {
        "Descriptor": lambda v: Descriptor(v),
    },
    "length": {
        "nonzero_eigenvalues": lambda v: nonzero_eigenvalues(LAM, length=v),
        "log_weyl_ratio": lambda v: log_weyl_ratio(LAM, length=v),
        "f1_feature": lambda v: f1_feature(LAM, length=v),
    },
    "zero_modes": {
        "nonzero_eigenvalues": lambda v: nonzero_eigenvalues(LAM, v),
        "log_weyl_ratio": lambda v: log_weyl_ratio(LAM, v),
        "f1_feature": lambda v: f1_feature(LAM, v),
        "compact_shape_dna": lambda v: cshape.compact_shape_dna(
            LAM, M=1, N=5, normalization="none", transform="log-weyl", zero_modes=v),
        "compact_shape_dna(weyl)": lambda v: cshape.compact_shape_dna(
            LAM, M=1, N=5, normalization="none", zero_modes=v),
    },
    "n_jobs": {
        "describe": lambda v: _describe(n_jobs=v),
        "DescriptorIndex": lambda v: DescriptorIndex(np.eye(3), n_jobs=v),
    },
    "radius": {
        "icosphere": lambda v: shapes.icosphere(1, radius=v),
        "disk": lambda v: shapes.disk(2, radius=v),
        "hemisphere": lambda v: shapes.hemisphere(2, radius=v),
        "sphere_spectrum": lambda v: shapes.sphere_spectrum(5, radius=v),
    },
    "size": {
        "square": lambda v: shapes.square(2, size=v),
        "cube": lambda v: shapes.cube(1, size=v),
    },
    "R": {"torus": lambda v: shapes.torus(4, 3, R=v, r=0.1)},
}
NONE_OK: set[tuple[str, str]] = set()
#: N = 0 is a legal length of the exact sphere spectrum (an empty array).
RANGE_DIFFERS = {("N", "sphere_spectrum"), ("N", "point_map")}  # point_map: N >= 2

_BC = r"bc must be one of \{'neumann', 'dirichlet'\}, got "
_MASS = r"mass must be one of \{'consistent', 'lumped', 'mixed'\}, got "
_NORM = r"normalization must be one of \{'area', 'fiedler', 'weyl', 'none'\}, got "
_TR = r"transform must be one of \{'weyl', 'log-weyl', 'log-weyl-dct'\}, got "
_KIND = (r"kind must be one of \{'shape-dna', 'truncated', 'cshape', 'cshape-complex', 'f1', "
         r"'truncated-log', 'two-scale'\}, got ")
_JOBS = r"n_jobs must be a positive integer or -1 \(all cores\), got "
SAME_ERROR = [
    # (argument, bad value, exception, message)
    ("N", 2.5, TypeError, r"^N must be an integer, got float 2\.5$"),
    ("N", 4.0, TypeError, r"^N must be an integer, got float 4\.0$"),
    ("N", np.float64(5), TypeError, r"^N must be an integer, got float64 "),
    ("N", "10", TypeError, r"^N must be an integer, got str '10'$"),
    ("N", None, TypeError, r"^N must be an integer, got NoneType$"),
    ("N", True, TypeError, r"^N must be an integer, got bool True$"),
    ("N", np.bool_(True), TypeError, r"^N must be an integer, got bool"),
    ("N", 0, ValueError, r"^N must be an integer >= 1, got 0$"),
    ("N", -3, ValueError, r"^N must be an integer >= 1, got -3$"),
    ("M", -1, ValueError, r"^M must be an integer >= 0, got -1$"),
    ("M", 1.0, TypeError, r"^M must be an integer, got float 1\.0$"),
    ("M", "2", TypeError, r"^M must be an integer, got str '2'$"),
    ("M", None, TypeError, r"^M must be an integer, got NoneType$"),
    ("M", True, TypeError, r"^M must be an integer, got bool True$"),
    ("M", np.bool_(False), TypeError, r"^M must be an integer, got bool"),
    *[("area", v, ValueError, rf"^area must be a positive finite number, got {s}$")
      for v, s in [(0, r"0\.0"), (-1.0, r"-1\.0"), (np.nan, "nan"), (np.inf, "inf")]],
    ("area", "abc", TypeError, r"^area must be a real number, got str 'abc'$"),
    ("area", True, TypeError, r"^area must be a real number, got bool True$"),
    ("area", [1.0, 2.0], TypeError, r"^area must be a real number, got list \[1\.0, 2\.0\]$"),
    *[("bc", v, ValueError, _BC + repr(v).replace("(", r"\(")) for v in
      ["robin", "", "neumann ", "periodic"]],
    ("bc", None, TypeError, _BC + "NoneType$"),
    ("bc", 0, TypeError, _BC + "int 0$"),
    ("mass", "diagonal", ValueError, _MASS + "'diagonal'$"),
    ("mass", "Lumped!", ValueError, _MASS + "'Lumped!'$"),
    ("mass", None, TypeError, _MASS + "NoneType$"),
    ("normalization", "max", ValueError, _NORM + "'max'$"),
    ("normalization", "", ValueError, _NORM + "''$"),
    ("normalization", None, TypeError, _NORM + "NoneType$"),
    ("normalization", 1, TypeError, _NORM + "int 1$"),
    ("transform", "log", ValueError, _TR + "'log'$"),
    ("transform", "dct", ValueError, _TR + "'dct'$"),
    ("transform", 1, TypeError, _TR + "int 1$"),
    ("kind", "heat", ValueError, _KIND + "'heat'$"),
    ("kind", None, TypeError, _KIND + "NoneType$"),
    ("length", 0, ValueError, r"^length must be an integer >= 1, got 0$"),
    ("length", 2.5, TypeError, r"^length must be an integer, got float 2\.5$"),
    ("zero_modes", -1, ValueError, r"^zero_modes must be an integer >= 0, got -1$"),
    ("zero_modes", True, TypeError, r"^zero_modes must be an integer, got bool True$"),
    ("n_jobs", 0, ValueError, _JOBS + "0$"),
    ("n_jobs", -2, ValueError, _JOBS + "-2$"),
    ("n_jobs", 2.0, TypeError, r"^n_jobs must be an integer, got float 2\.0$"),
    ("n_jobs", True, TypeError, r"^n_jobs must be an integer, got bool True$"),
    *[(arg, v, ValueError, rf"^{arg} must be a positive finite number, got {s}$")
      for arg in ("radius", "size", "R")
      for v, s in [(0, r"0\.0"), (-1.0, r"-1\.0"), (np.nan, "nan"), (np.inf, "inf")]],
    *[(arg, v, TypeError, rf"^{arg} must be a real number, got {s}$")
      for arg in ("radius", "size", "R")
      for v, s in [("1", "str '1'"), (True, "bool True"), (None, "NoneType"),
                   ([1.0], r"list \[1\.0\]")]],
]


@pytest.mark.parametrize("arg, value, exc, match", SAME_ERROR,
                         ids=[f"{a}={v!r}" for a, v, _, _ in SAME_ERROR])
def test_the_same_bad_argument_gives_the_same_error_everywhere(no_eigensolve, arg, value, exc,
                                                               match):
    messages = {}
    for name, call in TAKES[arg].items():
        if (value is None and (arg, name) in NONE_OK) or (
                exc is ValueError and (arg, name) in RANGE_DIFFERS):
            continue
        messages[name] = _raises(call, {"v": value}, exc, match)
    assert len(messages) >= 1
    assert len(set(messages.values())) == 1, messages


# ====================================================================== mesh (cshape.mesh)
BAD_ARRAYS = [
    ("complex_V", TET_V + 0j, TET_F, TypeError, "vertices must be real coordinates, got a complex"),
    ("bool_F", TET_V, TET_F.astype(bool), TypeError, "faces must be an integer array .*dtype bool"),
    ("1d_V", TET_V.ravel(), TET_F, ValueError, r"vertices must have shape \(n, 3\), got \(12,\)"),
    ("1d_F", TET_V, TET_F.ravel(), ValueError, r"faces must have shape \(m, 3\)"),
    ("transposed_V", TET_V.T[:, :3], TET_F, ValueError,
     r"faces reference vertex indices outside \[0, 2\]"),
    ("2d_points", TET_V[:, :2], TET_F, ValueError,
     r"vertices must have shape \(n, 3\), got \(4, 2\)"),
    ("3d_V", TET_V[None], TET_F, ValueError, r"vertices must have shape \(n, 3\), got \(1, 4, 3\)"),
    ("object_F", TET_V, TET_F.astype(object), TypeError,
     "faces must be an integer array .*dtype object"),
    ("str_F", TET_V, TET_F.astype(str), TypeError, "faces must be an integer array"),
    ("fractional_F", TET_V, TET_F + 0.25, TypeError, "non-integer floats"),
    ("nan_F", TET_V, np.where(TET_F == 3, np.nan, TET_F), TypeError, "non-integer floats"),
    ("huge_float_F", TET_V, np.array([[0, 1, 1e30]]), ValueError,
     r"vertex index 1e\+30, outside \[0, 3\]"),
    ("ragged_V", [[0, 0, 0], [1, 0], [0, 1, 0]], [[0, 1, 2]], TypeError,
     "vertices must be a real array"),
    ("ragged_F", TET_V, [[0, 1, 2], [0, 1]], TypeError, "faces must be an integer array .*ragged"),
    ("str_V", [["a", "b", "c"]] * 3, [[0, 1, 2]], TypeError, "vertices must be a real array"),
    ("none_V", [[None] * 3] * 3, [[0, 1, 2]], ValueError, "NaN or infinite"),
    ("quads", TET_V, [[0, 1, 2, 3]], ValueError, r"faces must have shape \(m, 3\).*triangulate"),
]
#: Bad (vertices, faces) pairs that every public function taking a mesh refuses alike.
BAD_PAIRS = [
    ("nan", (_NAN_V, TET_F), ValueError, r"vertices contain NaN or infinite .*index 2"),
    ("inf", (_INF_V, TET_F), ValueError, r"vertices contain NaN or infinite .*index 3"),
    ("index_too_big", (TET_V, TET_F + 1), ValueError, r"outside \[0, 3\]"),
    ("negative_index", (TET_V, -TET_F - 1), ValueError, r"outside \[0, 3\]"),
    ("huge_uint_index", (TET_V, TET_F.astype(np.uint64) + np.uint64(2**63)), ValueError,
     r"vertex index 922337203685477\d+, outside \[0, 3\]"),
]
#: Every public function of the core that takes a mesh, with valid other arguments.
TAKES_A_MESH = {
    "Mesh": lambda vf: Mesh(*vf),
    "as_mesh": lambda vf: cshape.mesh.as_mesh(vf),
    "repair_mesh": lambda vf: cshape.repair_mesh(vf),
    "largest_component": lambda vf: cshape.largest_component(vf),
    "fem_matrices": lambda vf: cshape.fem_matrices(vf),
    "shape_dna": lambda vf: cshape.shape_dna(vf, N=3),
    "eigenbasis": lambda vf: cshape.eigenbasis(vf, N=3),
}
MESH = [
    *[pytest.param(fn, dict(vertices=V, faces=F), exc, match, id=f"{fn_name}-{name}")
      for name, V, F, exc, match in BAD_ARRAYS
      for fn_name, fn in [("Mesh", Mesh), ("shape_dna", lambda vertices, faces: cshape.shape_dna(
          (vertices, faces), N=2))]],
    *[pytest.param(TAKES_A_MESH[fn], dict(vf=vf), exc, match, id=f"{fn}-{name}")
      for name, vf, exc, match in BAD_PAIRS for fn in sorted(TAKES_A_MESH) if fn != "Mesh"],
    *[pytest.param(Mesh, dict(vertices=vf[0], faces=vf[1]), exc, match, id=f"Mesh-{name}")
      for name, vf, exc, match in BAD_PAIRS],
    *[pytest.param(cshape.mesh.as_mesh, dict(mesh_or_vf=obj), TypeError,
                   r"expected a mesh: a cshape.Mesh, a \(vertices, faces\) pair of arrays, or a "
                   r"mesh object of trimesh .*; got ", id=f"as_mesh-{i}")
      for i, obj in enumerate([(TET_V, TET_F, None), {"v": TET_V}, TET_V, 3, None])],
    pytest.param(cshape.mesh.as_mesh, dict(mesh_or_vf="bunny.off"), TypeError,
                 r"got a path \('bunny.off'\) where a mesh was expected; load it first",
                 id="as_mesh-path"),
    pytest.param(cshape.repair_mesh, dict(mesh=(TET_V, TET_F), merge_tol=-1.0), ValueError,
                 r"^merge_tol must be a finite number >= 0, got -1\.0$", id="merge_tol-negative"),
    pytest.param(cshape.repair_mesh, dict(mesh=(TET_V, TET_F), merge_tol="0"), TypeError,
                 r"^merge_tol must be a real number, got str '0'$", id="merge_tol-str"),
    pytest.param(cshape.repair_mesh, dict(mesh=(TET_V, TET_F), warn=1), TypeError,
                 r"^warn must be True or False, got int 1$", id="warn-int"),
    pytest.param(cshape.shape_dna, dict(mesh=(np.zeros((4, 3)), TET_F), N=2), ValueError,
                 "no valid triangle left", id="coincident-vertices"),
]


@pytest.mark.parametrize("call, kwargs, exc, match", MESH)
def test_mesh(no_eigensolve, call, kwargs, exc, match):
    _raises(call, kwargs, exc, match)


# ====================================================================== FEM (cshape.fem)
_COLLINEAR = (np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0.0]]),
              np.array([[0, 1, 2], [1, 2, 3], [0, 2, 3]]))


def _sphere_on_a_line():
    s = shapes.icosphere(1)
    return np.c_[s.vertices[:, 0], np.zeros((42, 2))], s.faces


_ZERO_AREA = "zero surface area.*coincident or collinear"
FEM = [
    *[pytest.param(lambda make, fn=fn: TAKES_A_MESH[fn](make()), dict(make=make), ValueError,
                   _ZERO_AREA, id=f"{fn}-{name}",
                   marks=pytest.mark.filterwarnings("ignore::cshape.CShapeWarning"))
      for name, make in [("collinear", lambda: _COLLINEAR), ("sphere_on_a_line", _sphere_on_a_line)]
      for fn in ("fem_matrices", "shape_dna")],
    pytest.param(fem, dict(mesh=(np.zeros((4, 3)), TET_F), repair=False), ValueError,
                 "zero surface area", id="coincident-without-repair"),
    pytest.param(lambda: cshape.fem_matrices(Mesh(shapes.icosphere(2).vertices * 1e160,
                                                  shapes.icosphere(2).faces)), {},
                 ValueError, "overflows.*rescale the mesh", id="overflow",
                 marks=[pytest.mark.filterwarnings("ignore:overflow encountered:RuntimeWarning"),
                        pytest.mark.filterwarnings("ignore:invalid value encountered")]),
    pytest.param(cshape.shape_dna, dict(mesh=(TET_V[:3], [[0, 1, 2]]), N=1, bc="dirichlet"),
                 ValueError, "leaves no unknowns", id="dirichlet-no-unknowns"),
    pytest.param(fem, dict(mesh=(TET_V, TET_F), repair="yes"), TypeError,
                 r"^repair must be True or False, got str 'yes'$", id="repair-str"),
]


@pytest.mark.parametrize("call, kwargs, exc, match", FEM)
def test_fem(call, kwargs, exc, match):
    _raises(call, kwargs, exc, match)


@pytest.mark.parametrize("far, match", [
    (1e200, r"edge lengths range from 1 to 1e\+200, a ratio beyond 1e\+150: their squares .* "
            r"underflow float64 in any unit"),
    (-1e160, r"edge lengths range from 1 to 1e\+160, a ratio beyond 1e\+150"),
    (1e20, r"needle triangles: its area 1.71e\+20 is only 1.7e-20 of .* edge lengths from 1 "
           r"to 1e\+20"),
])
@pytest.mark.parametrize("fn", ["fem_matrices", "shape_dna"])
@pytest.mark.filterwarnings("ignore::cshape.CShapeWarning")
def test_one_far_vertex_is_named_not_called_zero_area(far, match, fn):
    """A tetrahedron with one vertex at 1e200 was refused as having "zero surface area
    (area=1.71e+200)": the message now says what is wrong and which vertex to fix."""
    V = TET_V.copy()
    V[3, 2] = far
    message = _raises(TAKES_A_MESH[fn], dict(vf=(V, TET_F)), ValueError, match)
    assert f"vertex 3 at [0.0, 0.0, {far!r}]" in message
    assert "zero surface area" not in message and "misplaced" in message


# ====================================================================== spectrum (cshape.spectrum)
SPECTRUM = [
    pytest.param(lambda: cshape.shape_dna(shapes.icosphere(1), N=50), {}, ValueError,
                 r"N=50 .*only 42 unknowns.*N <= 42", id="neumann-unknowns"),
    pytest.param(lambda: cshape.shape_dna(shapes.square(6), N=50, bc="dirichlet"), {},
                 ValueError, r"N=50 .*only 25 unknowns.*N <= 25", id="dirichlet-unknowns"),
    pytest.param(solve_eigenproblem, dict(A=np.eye(3), B=np.eye(3), N=2, return_vectors=1),
                 TypeError,
                 r"^return_vectors must be True or False, got int 1$", id="return_vectors"),
    pytest.param(solve_eigenproblem, dict(A=np.eye(3), B=np.eye(3), N=2, sigma="0"),
                 TypeError, r"^sigma must be a real number, got str '0'$", id="sigma"),
    pytest.param(solver_threads, dict(n=1.5), TypeError,
                 r"^n must be an integer, got float 1\.5$", id="solver_threads"),
]


@pytest.mark.parametrize("call, kwargs, exc, match", SPECTRUM)
def test_spectrum(call, kwargs, exc, match):
    _raises(call, kwargs, exc, match)


# ====================================================================== descriptors
S9 = 4 * np.pi * np.arange(9.0)  # 2M+1 = 9 values: M = 4
DESCRIPTORS = [
    pytest.param(cshape.compact_shape_dna, dict(lam=LAM, M=2, N=20), ValueError,
                 r"got 12 eigenvalues but N=20; pass N=12", id="fewer-eigenvalues-than-N"),
    *[pytest.param(lambda M, N: cshape.compact_shape_dna(LAM, M=M, N=N), dict(M=M, N=N),
                   ValueError, match, id=f"M-too-large-N{N}")
      for M, N, match in [(5, 9, r"2M\+1 = 11 values cannot be kept from N = 9.*use M <= 4"),
                          (5, 10, r"^M=5: 2M\+1 = 11 values cannot be kept from N = 10 "
                                  r"eigenvalues; use M <= 4 or N >= 11$")]],
    pytest.param(lambda: cshape.compact_shape_dna(LAM, M=1, N=1), {}, ValueError,
                 r"2M\+1 = 3 values cannot be kept from N = 1", id="M1-N1"),
    pytest.param(lambda: inverse_compact_shape_dna(
        cshape.compact_shape_dna(LAM, M=2, N=9, normalization="none"), N=3), {}, ValueError,
        r"use M <= 1", id="inverse-M-too-large"),
    pytest.param(lambda: inverse_compact_shape_dna(
        cshape.compact_shape_dna(LAM, M=2, N=9, normalization="none")[:4], N=9), {}, ValueError,
        "odd length", id="inverse-even-length"),
    pytest.param(inverse_compact_shape_dna, dict(S_c=S9, N=9, add_weyl="no"), TypeError,
                 r"^add_weyl must be True or False, got str 'no'$", id="inverse-add_weyl"),
    pytest.param(cshape.compact_shape_dna, dict(lam=LAM, M=1, N=5, normalization=1),
                 TypeError, r"^normalization must be one of \{'area', 'fiedler', 'weyl', "
                 r"'none'\}, got int 1$", id="normalization-none-type"),
    *[pytest.param(fn, dict(lam_or=lam), exc, match, id=f"{fn_name}-{name}")
      for name, lam, exc, match in [
          ("complex", LAM + 1j, TypeError, "real eigenvalues, got a complex array"),
          ("2d", LAM[None, :], ValueError, r"1-D \(one spectrum\), got shape \(1, 12\)"),
          ("nan", np.r_[LAM[:3], np.nan], ValueError, "NaN or infinite"),
          ("empty", [], ValueError, "at least 1 eigenvalues, got 0"),
          ("strings", ["a", "b"], TypeError, "1-D array of real eigenvalues")]
      for fn_name, fn in [("normalize", lambda lam_or: cshape.normalize(lam_or, area=1.0)),
                          ("weyl_subtract", lambda lam_or: cshape.weyl_subtract(lam_or))]],
    *[pytest.param(cshape.normalize, dict(lam=LAM, area=1.0, normalization=m), exc,
                   r"normalization must be one of \{'area', 'fiedler', 'weyl', 'none'\}",
                   id=f"normalization-{m!r}")
      for m, exc in [("max", ValueError), ("", ValueError), (None, TypeError), (1, TypeError)]],
    pytest.param(real_form, dict(S_c=np.ones(4, complex)), ValueError,
                 "odd last dimension", id="real_form-even"),
    pytest.param(real_form, dict(S_c=np.ones((2, 2, 3), complex)), ValueError,
                 "odd last dimension", id="real_form-3d"),
]


@pytest.mark.parametrize("call, kwargs, exc, match", DESCRIPTORS)
def test_descriptors(no_eigensolve, call, kwargs, exc, match):
    _raises(call, kwargs, exc, match)


# ====================================================================== comparison and index
COMPARE = [
    pytest.param(Descriptor, dict(kind="cshape", M=-1), ValueError,
                 r"^M must be an integer >= 0, got -1$", id="Descriptor-M"),
    pytest.param(lambda descriptor: table().descriptors(descriptor), dict(descriptor="cshape"),
                 TypeError, r"^descriptor must be a cshape.Descriptor \(e.g. cshape.PAPER\) or "
                 r"None \(cshape.DEFAULT\), got str \(a kind: Descriptor\('cshape', N=...\)\)$",
                 id="DescriptorTable.descriptors-kind"),
    pytest.param(cshape.compare.scaled_difference, dict(D1=np.zeros((2, 2)), D2=np.zeros((2, 2)),
                                                        include_diagonal="no"),
                 TypeError, r"^include_diagonal must be True or False, got str 'no'$",
                 id="scaled_difference-include_diagonal"),
    pytest.param(cshape.compare.retrieval_scores, dict(D=np.zeros((2, 2)), labels=[0, 0],
                                                       min_class_size=1.5),
                 TypeError, r"^min_class_size must be an integer, got float 1\.5$",
                 id="retrieval-min_class_size"),
    pytest.param(cshape.compare.mds_embedding, dict(D=np.ones((3, 3)) - np.eye(3),
                                                    n_components=0),
                 ValueError, r"^n_components must be an integer >= 1, got 0$", id="mds-components"),
    pytest.param(DescriptorIndex, dict(X=np.eye(3), algorithm="kd-tree"), ValueError,
                 r"algorithm must be one of \{'auto', 'brute', 'kd_tree', 'ball_tree'\}, got",
                 id="index-algorithm"),
    pytest.param(lambda k: DescriptorIndex(np.eye(3)).query(k=k), dict(k=2.0), TypeError,
                 r"^k must be an integer, got float 2\.0$", id="index-k-type"),
    pytest.param(lambda k: DescriptorIndex(np.eye(3)).query(k=k), dict(k=3), ValueError,
                 r"k must be an integer in \[1, 2\] for a database of 3 descriptors queried "
                 "with itself, got 3", id="index-k-range"),
]


@pytest.mark.parametrize("call, kwargs, exc, match", COMPARE)
def test_compare(call, kwargs, exc, match):
    _raises(call, kwargs, exc, match)


# ====================================================================== batch runs and tables
BATCH = [
    pytest.param(_describe, dict(progress=1), TypeError,
                 r"^progress must be True or False, got int 1$", id="describe-progress"),
    pytest.param(_describe, dict(cache_dir=3), TypeError,
                 r"^cache_dir must be a path \(str or os\.PathLike\), got int 3$",
                 id="describe-cache_dir"),
    pytest.param(_describe, dict(blas_threads=0), ValueError,
                 r"^blas_threads must be an integer >= 1, got 0$", id="describe-blas_threads"),
    pytest.param(_describe, dict(on_error="ignore"), ValueError,
                 r"^on_error must be one of \{'warn', 'raise'\}, got 'ignore'$",
                 id="describe-on_error"),
    pytest.param(_describe, dict(M=5), TypeError,
                 r"unexpected keyword argument 'M'", id="describe-M-is-not-its-business"),
    pytest.param(lambda path: table().save(path), dict(path=3), TypeError,
                 r"^path must be a path \(str or os\.PathLike\), got int 3$", id="save-path"),
    pytest.param(DescriptorTable.load, dict(path=None), TypeError,
                 r"^path must be a path \(str or os\.PathLike\), got NoneType$",
                 id="load-path"),
]


@pytest.mark.parametrize("call, kwargs, exc, match", BATCH)
def test_batch(no_eigensolve, call, kwargs, exc, match):
    _raises(call, kwargs, exc, match)


# ====================================================================== shapes
SHAPES = [
    pytest.param(shapes.icosphere, dict(subdivisions=True), TypeError,
                 r"^subdivisions must be an integer, got bool True$", id="icosphere-bool"),
    pytest.param(shapes.square, dict(n=2.0), TypeError, r"^n must be an integer, got float 2\.0$",
                 id="square-float"),
    pytest.param(shapes.icosphere, dict(subdivisions=9), ValueError,
                 r"^subdivisions must be an integer in \[0, 8\], got 9$", id="icosphere-9"),
    pytest.param(shapes.sphere_spectrum, dict(N=-1), ValueError,
                 r"^N must be an integer in \[0, 100000000\], got -1$", id="sphere_spectrum-N"),
    pytest.param(shapes.torus, dict(R=1.0, r=2.0), ValueError, r"torus needs 0 < r < R",
                 id="torus-r-above-R"),
]


@pytest.mark.parametrize("call, kwargs, exc, match", SHAPES)
def test_shapes(call, kwargs, exc, match):
    _raises(call, kwargs, exc, match)


# ====================================================================== readers (files)
def _gz(content):
    return gzip.compress(content)


_GZ_DATA = gzip.compress(OFF_TET.encode())
READERS = [
    *[pytest.param(name, content, match, id=name) for name, content, match in MALFORMED],
    # the pre-scan guards every compressed file as it guards the plain one
    *[pytest.param(name + ".gz", _gz(content), match, id=name + ".gz")
      for name, content, match in MALFORMED],
    pytest.param("be_double_quads.ply",
                 ply_be_double(F=[[0, 2, 1, 3], [0, 1, 3], [0, 3, 2], [1, 2, 3]]),
                 "big-endian PLY with double coordinates and faces that are not all triangles",
                 id="be_double_quads"),
    pytest.param("be_double_oor.ply", ply_be_double(F=F_OOR),
                 "references vertex 99 but the file has only 4", id="be_double_out_of_range"),
    pytest.param("be_double_truncated.ply", ply_be_double(nv=5)[:-40],
                 "declares 5 vertex, 4 face records", id="be_double_truncated"),
    pytest.param("cloud.ply", b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                 b"property float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n",
                 r"cloud\.ply.*no triangles", id="point_cloud"),
    pytest.param("truncated.off.gz", _GZ_DATA[: len(_GZ_DATA) // 2], "corrupt or truncated",
                 id="gz-truncated"),
    pytest.param("crc.off.gz", _GZ_DATA[:-8] + bytes([_GZ_DATA[-8] ^ 0xFF]) + _GZ_DATA[-7:],
                 "corrupt or truncated", id="gz-crc"),
    pytest.param("not_compressed.off.gz", OFF_TET.encode(), "drop the '.gz'",
                 id="gz-not-compressed"),
    pytest.param("empty_inside.off.gz", gzip.compress(b""), "decompresses to an empty file",
                 id="gz-empty-inside"),
    pytest.param("no_format.gz", _GZ_DATA, "must name its format before '.gz'",
                 id="gz-no-format"),
    pytest.param("unknown_format.docx.gz", _GZ_DATA, r"extension '\.docx' is not a mesh format",
                 id="gz-unknown-format"),
]


@pytest.mark.parametrize("name, content, match", READERS)
def test_readers(tmp_path, private_tmpdir, name, content, match):
    """Every bad file raises a ValueError that names the file (the .gz file, never the
    temporary copy, which is removed)."""
    p = tmp_path / name
    p.write_bytes(content)
    message = _raises(cshape.load_mesh, dict(path=p), ValueError, match)
    assert repr(str(p)) in message
    assert str(private_tmpdir) not in message
    assert list(private_tmpdir.iterdir()) == []


def test_readers_arguments(tmp_path):
    _raises(cshape.load_mesh, dict(path=3), TypeError,
            r"^path must be a path \(str or os\.PathLike\), got int 3$")
    _raises(cshape.load_mesh, dict(path=tmp_path / "x.off", repair="yes"), TypeError,
            r"^repair must be True or False, got str 'yes'$")
    _raises(cshape.load_mesh, dict(path=tmp_path / "none.off"), FileNotFoundError,
            "no mesh file at")
    from cshape.readers import split_mesh_name

    _raises(split_mesh_name, dict(path=None), TypeError, r"^path must be a path")


def test_directory_named_like_a_mesh(tmp_path):
    d = tmp_path / "x.obj"
    d.mkdir()
    _raises(cshape.load_mesh, dict(path=d), ValueError, r"x\.obj.*is a folder, not a mesh file")


def test_fifo_named_like_a_mesh_does_not_hang(tmp_path):
    if not hasattr(os, "mkfifo"):
        pytest.skip("no named pipes on this platform")
    p = tmp_path / "pipe.off"
    os.mkfifo(p)  # opening it for reading would block forever without a writer
    _raises(cshape.load_mesh, dict(path=p), ValueError, r"pipe\.off.*empty")


TOSCA = [
    ("fractional", "0 0 0\n1 0 0\n0 1 0\n", "1 2 3.5\n", "non-integer floats"),
    ("nan_index", "0 0 0\n1 0 0\n0 1 0\n", "1 2 nan\n", "non-integer floats"),
    ("out_of_range", "0 0 0\n1 0 0\n0 1 0\n", "1 2 4\n", r"outside \[0, 2\]"),
    ("ragged", "0 0 0\n1 0\n0 1 0\n", "1 2 3\n", "cannot read TOSCA mesh"),
    ("nan_vertex", "0 0 0\n1 0 0\n0 1 nan\n", "1 2 3\n", "NaN or infinite"),
    ("2d", "0 0\n1 0\n0 1\n", "1 2 3\n", r"vertices must have shape \(n, 3\)"),
]


@pytest.mark.parametrize("vert, tri, match", [t[1:] for t in TOSCA], ids=[t[0] for t in TOSCA])
def test_data_tosca_files(tmp_path, vert, tri, match):
    from cshape.data.files import read_vert_tri

    (tmp_path / "cat0.vert").write_text(vert)
    (tmp_path / "cat0.tri").write_text(tri)
    message = _raises(read_vert_tri, dict(vert_path=tmp_path / "cat0.vert"), ValueError, match)
    assert "cat0" in message


# ====================================================================== data: variants
def _variants():
    from cshape.data import variants

    return variants


VARIANTS = [
    pytest.param(lambda: _variants().remesh(shapes.icosphere(2), target_length=1e-4), {},
                 ValueError, r"target_length=0.0001 would make about .* use "
                 r"target_length >= 0\.00\d+", id="remesh-memory"),
    pytest.param(lambda: _variants().subdivide(shapes.icosphere(2), iterations=8), {},
                 ValueError, r"iterations=8 would make .* use iterations <= 7",
                 id="subdivide-memory"),
    pytest.param(lambda: _variants().subdivide(shapes.icosphere(2), iterations=9), {},
                 ValueError, r"iterations must be an integer in \[0, 8\]", id="subdivide-9"),
    pytest.param(lambda: _variants().subdivide(shapes.icosphere(2), iterations=True), {},
                 TypeError, "iterations must be an integer", id="subdivide-bool"),
    *[pytest.param(lambda a: _variants().add_normal_noise(shapes.icosphere(1), amplitude=a),
                   dict(a=a), ValueError, r"amplitude must be a finite number >= 0",
                   id=f"noise-{a!r}")
      for a in [np.inf, np.nan, -1.0]],
    *[pytest.param(lambda a: _variants().add_normal_noise(shapes.icosphere(1), amplitude=a),
                   dict(a=a), TypeError, r"amplitude must be a real number", id=f"noise-{a!r}")
      for a in [True, "1"]],
    *[pytest.param(lambda expr: _variants().marching_cubes(expr, (-1, -1, -1, 1, 1, 1), 0.1),
                   dict(expr=expr), ValueError,
                   rf"expr .* is not a valid muparser expression.*{match}", id=f"mc-{expr}")
      for expr, match in [("x+", "Unexpected end of expression"),
                          ("foo(x)", 'Unexpected token "foo"'),
                          ("((((", "Unexpected end of expression")]],
    *[pytest.param(lambda expr: _variants().marching_cubes(expr, (-1, -1, -1, 1, 1, 1), 0.1),
                   dict(expr=expr), ValueError, "produced no triangles", id=f"mc-empty-{expr}")
      for expr in ["sqrt(-1)", "1/0", "x^2+y^2+z^2+1"]],
]


@pytest.mark.parametrize("call, kwargs, exc, match", VARIANTS)
def test_data_variants(call, kwargs, exc, match):
    _raises(call, kwargs, exc, match)


# ====================================================================== what is accepted
@pytest.mark.parametrize("N", [np.int8(5), np.int32(5), np.int64(5), np.uint16(5)])
def test_numpy_integer_N_and_M_are_accepted(N):
    lam = cshape.shape_dna(sphere(), N=N)
    assert lam.shape == (5,)
    S = cshape.compact_shape_dna(lam, M=np.int64(2), N=N, area=sphere().area)
    assert S.shape == (5,)
    np.testing.assert_allclose(S, cshape.compact_shape_dna(lam, M=2, N=5, area=sphere().area))


def test_N_equal_1_is_legal_for_shape_dna_and_for_compact_with_M_0():
    assert cshape.shape_dna(sphere(), N=1).tolist() == [0.0]
    S = cshape.compact_shape_dna(cshape.shape_dna(sphere(), N=1), M=0, N=1, area=1.0)
    assert S.shape == (1,) and S[0] == 0  # lam_0 = 0, Weyl line 0 at i = 0


def test_only_the_first_N_eigenvalues_are_used():
    S = cshape.compact_shape_dna(LAM, M=2, N=5, normalization="none")
    assert S.shape == (5,)
    np.testing.assert_array_equal(S, cshape.compact_shape_dna(LAM[:5], M=2, N=5,
                                                              normalization="none"))


@pytest.mark.parametrize("N", [9, 10])
def test_largest_legal_M(N):
    M = (N - 1) // 2
    S = cshape.compact_shape_dna(LAM, M=M, N=N, normalization="none")
    assert S.shape == (2 * M + 1,)
    np.testing.assert_allclose(S[M + 1:], np.conj(S[:M][::-1]))  # conjugate symmetric


def test_choices_are_case_insensitive():
    A1, B1 = cshape.fem_matrices(sphere(), bc="Neumann", mass="LUMPED")
    A2, B2 = cshape.fem_matrices(sphere(), bc="neumann", mass="lumped")
    assert abs(A1 - A2).max() == 0 and abs(B1 - B2).max() == 0
    np.testing.assert_array_equal(cshape.compact_shape_dna(LAM, M=1, N=5, normalization="WEYL"),
                                  cshape.compact_shape_dna(LAM, M=1, N=5, normalization="weyl"))


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


def test_real_form_of_a_stack():
    assert real_form(np.ones((2, 3), complex)).shape == (2, 3)


@pytest.mark.parametrize("make", [
    lambda v: shapes.icosphere(1, radius=v), lambda v: shapes.square(2, size=v),
    lambda v: shapes.disk(2, radius=v), lambda v: shapes.hemisphere(2, radius=v),
    lambda v: shapes.cube(1, size=v), lambda v: shapes.torus(4, 3, R=v, r=0.1),
    lambda v: shapes.sphere_spectrum(5, radius=v)])
def test_shape_lengths_take_numpy_scalars(make):
    out = make(np.float32(2.0))
    assert isinstance(out, (Mesh, np.ndarray))


def test_icosphere_takes_a_numpy_integer():
    assert shapes.icosphere(np.int64(0)).n_vertices == 12


@pytest.mark.parametrize("bc, n_unknowns", [("neumann", 42), ("dirichlet", 25)])
def test_N_up_to_the_number_of_unknowns(bc, n_unknowns):
    m = shapes.icosphere(1) if bc == "neumann" else shapes.square(6)  # 42 / 25 unknowns
    assert len(cshape.shape_dna(m, N=n_unknowns, bc=bc)) == n_unknowns


# ------------------------------------------------------------------ mode names
def test_mode_names_are_hyphenated_lower_case():
    for names in (DESCRIPTOR_KINDS, cshape.descriptors.formulas.TRANSFORMS,
                  cshape.descriptors.formulas.NORMALIZATIONS, cshape.fem.BOUNDARY_CONDITIONS,
                  cshape.fem.MASS_TYPES):
        assert all(n == n.lower() and "_" not in n and " " not in n for n in names), names


@pytest.mark.parametrize("call, match", [
    (lambda: cshape.Descriptor("shape_dna"),
     r"kind must be one of \{.*'shape-dna'.*\}, got 'shape_dna'"),
    (lambda: cshape.Descriptor(transform="log_weyl"),
     r"transform must be one of \{'weyl', 'log-weyl', 'log-weyl-dct'\}, got 'log_weyl'"),
    (lambda: cshape.compact_shape_dna(LAM, M=1, N=5, transform="shape_dna"),
     r"transform must be one of \{'weyl', 'log-weyl', 'log-weyl-dct'\}, got 'shape_dna'"),
])
def test_a_mode_name_has_one_spelling(call, match):
    """Mode names are written with hyphens only: an underscore spelling is an unknown option."""
    with pytest.raises(ValueError, match=match):
        call()


def test_cli_kind_has_one_spelling(capsys):
    from cshape.cli import main

    with pytest.raises(SystemExit) as exc:
        main(["query", "t.npz", "a", "--kind", "shape_dna"])
    assert exc.value.code == 2
    assert "invalid choice: 'shape_dna'" in capsys.readouterr().err
