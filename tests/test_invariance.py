"""Property tests: descriptors are invariant to rigid motions, vertex permutation, face
orientation flips and (after area normalisation) uniform scaling, for every transform of
``compact_shape_dna`` (the paper's and the log-Weyl extensions)."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

import cshape
from cshape import shapes

N, M = 24, 5
TRANSFORMS = cshape.descriptors.TRANSFORMS


@lru_cache(maxsize=1)
def reference():
    """The base torus and its descriptors (one per transform), computed once, on first use."""
    base = shapes.torus(16, 8, R=1.0, r=0.35)
    lam = cshape.shape_dna(base, N=N)
    return base, lam, {t: cshape.compact_shape_dna(lam, M=M, N=N, area=base.area, transform=t)
                       for t in TRANSFORMS}


def rotation(q):
    q = np.asarray(q, float)
    q = q / np.linalg.norm(q)
    w, x, y, z = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def check(mesh, scale=1.0):
    _, LAM0, S0 = reference()
    lam = cshape.shape_dna(mesh, N=N)
    np.testing.assert_allclose(lam * scale**2, LAM0, rtol=1e-8, atol=1e-8)
    assert set(S0) == {"weyl", "log-weyl", "log-weyl-dct"}
    for transform, ref in S0.items():
        S = cshape.compact_shape_dna(lam, M=M, N=N, area=mesh.area, transform=transform)
        # the log-Weyl values are O(1) where the paper's are O(100): same relative tolerance
        atol = 1e-6 if transform == "weyl" else 1e-8
        np.testing.assert_allclose(S, ref, rtol=1e-7, atol=atol, err_msg=transform)


unit = st.floats(-1, 1, allow_nan=False)


@settings(max_examples=8, deadline=None)
@given(q=st.tuples(unit, unit, unit, unit).filter(lambda q: np.linalg.norm(q) > 0.1),
       t=st.tuples(*[st.floats(-100, 100, allow_nan=False)] * 3),
       mirror=st.booleans())
def test_rigid_motions(q, t, mirror):
    BASE = reference()[0]
    R = rotation(q)
    if mirror:
        R = R @ np.diag([1, 1, -1])
    check(cshape.Mesh(BASE.vertices @ R.T + np.array(t), BASE.faces))


@settings(max_examples=8, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_vertex_permutation_and_face_flips(seed):
    BASE = reference()[0]
    rng = np.random.default_rng(seed)
    perm = rng.permutation(BASE.n_vertices)
    inv = np.argsort(perm)
    V = BASE.vertices[perm]
    F = inv[BASE.faces]
    flip = rng.random(len(F)) < 0.5
    F[flip] = F[flip][:, ::-1]
    F = F[rng.permutation(len(F))]
    check(cshape.Mesh(V, F))


@settings(max_examples=8, deadline=None)
@given(s=st.floats(1e-3, 1e3))
def test_uniform_scaling(s):
    BASE = reference()[0]
    check(cshape.Mesh(BASE.vertices * s, BASE.faces), scale=s)
