# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 10 · Maps between shapes: functional maps, ZoomOut and geodesic errors
#
# **Paper:** Gao, Yu and Pang, *A compact shape descriptor for triangular surface meshes*, Computer-Aided Design 53 (2014) 62-69;
# Eq. (1)-(3): the Laplace-Beltrami eigenproblem, on a mesh $A f = -\lambda B f$. Lesson 9 described every point by its
# heat or wave kernel signature and matched points by nearest signature. This lesson maps *functions* instead of points
# (Ovsjanikov, Ben-Chen, Solomon, Butscher and Guibas, *Functional maps*, ACM TOG 31(4) 2012), keeps left and right
# apart with an orientation-preserving term (Ren, Poulenard, Wonka and Ovsjanikov 2018) and refines the map by spectral
# upsampling (ZoomOut, Melzi et al., ACM TOG 38(6) 2019).
#
# **Prerequisites:** lesson 9 (eigenbases, the WKS, matching by nearest signature), least squares (the normal
# equations), a little linear algebra of orthonormal bases.
#
# **Learning goals.** After this notebook you can
#
# 1. write a map between two shapes as a small matrix $C$ between their truncated eigenbases, and read $C$ (near-diagonal
#    between near-isometric shapes);
# 2. set up Ovsjanikov et al.'s least-squares problem (descriptor preservation and commutativity with the Laplacian),
#    solve it, and recover a point-to-point map by nearest neighbours in the spectral embedding;
# 3. show why an intrinsic energy cannot tell a symmetric shape from its mirror image, measure the share of points sent to
#    the wrong side, and fix it with the orientation term;
# 4. refine a map with ZoomOut and measure it the standard way: geodesic error over $\sqrt{\text{area}}$, and the share of
#    points within 5 % of the geodesic diameter.
#
# **The plan.**
#
# | section | what | your work |
# |---|---|---|
# | 1 | the map we want, written as $C$ | `pointwise_to_map_mine` (graded) |
# | 2 | $C$ from descriptors (Ovsjanikov et al.) | `fmap_mine` (graded) |
# | 3 | the pitfall: left and right | a prediction, a written answer |
# | 4 | ZoomOut | `zoomout_step_mine` (graded) |
# | 5-6 | landmarks; between different bodies | exercises 1-5 (open) |
#
# **The formulas.** $\Phi_S$ ($n_S \times N_S$) and $\Phi_T$ ($n_T \times N_T$) hold the first eigenfunctions of the source
# $S$ and the target $T$, B-orthonormal ($\Phi^T B \Phi = I$; `cshape.eigenbasis` holds them with $B$ and the mesh). A point map $p$ (for each target vertex
# $y$ a source vertex $p[y]$; the matrix $\Pi$ with $\Pi_{y, p[y]} = 1$) carries a function $f$ on $S$ to $f \circ p = \Pi f$
# on $T$. In the bases, $f = \Phi_S a$ goes to $\Phi_T C a$ with
#
# $$C = \Phi_T^T B_T\, \Pi\, \Phi_S \qquad (N_T \times N_S).$$
#
# Why $\Phi_T^T B_T$: the coefficients $c$ of a function $g$ on $T$ in the basis are those of its best approximation
# $\Phi_T c$ in the $B_T$-norm, $\min_c (\Phi_T c - g)^T B_T (\Phi_T c - g)$; the normal equations are
# $\Phi_T^T B_T \Phi_T\, c = \Phi_T^T B_T\, g$, and $\Phi_T^T B_T \Phi_T = I$, so $c = \Phi_T^T B_T\, g$. This
# projection is the pseudo-inverse $\Phi_T^+$ of the basis in the $B_T$ inner product. Applied to $g = \Pi \Phi_S a$,
# column by column, it gives $C$.
#
# Ovsjanikov et al. find $C$ without knowing $p$. Descriptors that a correct map carries to each other (WKS at the same
# energies, $F_S$ on $S$ and $F_T$ on $T$, one column each) have coefficients $D_S = \Phi_S^T B_S F_S$ and
# $D_T = \Phi_T^T B_T F_T$ (their paper calls them $A$ and $B$; here $A$ and $B$ are the FEM matrices), and an isometry
# commutes with the Laplace-Beltrami operator, whose matrix in the eigenbases is $\Lambda = \mathrm{diag}(\lambda)$:
#
# $$C^\star = \arg\min_C\; \|C D_S - D_T\|_F^2 + w_l\, \|C \Lambda_S - \Lambda_T C\|_F^2, \qquad
# \|C \Lambda_S - \Lambda_T C\|_F^2 = \sum_{ij} C_{ij}^2 (\lambda_{T,i} - \lambda_{S,j})^2 .$$
#
# The second term is diagonal in the entries of $C$, so the energy splits into one sum per row $c_i$ of $C$ (row $i$
# of $C D_S - D_T$ is $c_i D_S - D_{T,i}$):
#
# $$E(C) = \sum_i \Big( \lVert c_i D_S - D_{T,i}\rVert^2 + w_l \sum_j C_{ij}^2 (\lambda_{T,i} - \lambda_{S,j})^2 \Big).$$
#
# Each row is a ridge regression of its own. Setting the gradient in $c_i$ to zero,
# $2 (c_i D_S - D_{T,i}) D_S^T + 2 w_l\, c_i\, \mathrm{diag}_j[(\lambda_{T,i} - \lambda_{S,j})^2] = 0$, and
# transposing:
#
# $$\left(D_S D_S^T + w_l\, \mathrm{diag}_j\!\left[(\lambda_{T,i} - \lambda_{S,j})^2\right]\right) c_i^T = D_S\, D_{T,i}^T .$$
#
# The point map comes back as the nearest neighbour in the spectral embedding,
# $p[y] = \arg\min_x \|\Phi_T[y] - C\, \Phi_S[x]^T\|$ (rows of $\Phi$ are the points' spectral coordinates).

# %%
# %matplotlib inline
import re
import time
import warnings

import numpy as np

import cshape
from cshape import maps, plots
from cshape import signatures as sg
from cshape.course.teaching import SMALL, size  # CSHAPE_SMALL=1: small meshes and k
from cshape.data import poses, variants

np.set_printoptions(precision=3, suppress=True, linewidth=100)
N = size(50, 100)  # eigenpairs of each shape: the final size of the map
N0 = size(20, 30)  # the size of the first functional map
TEMPLATE = size({"voxelsize": 0.03, "target_vertices": 800}, {})  # the posed figures' size
print("cshape", cshape.__version__, "(small sizes)" if SMALL else "", f"N0 = {N0}, N = {N}")

# %% [markdown]
# ## 1 · The map we want, written as $C$
#
# The two shapes are the rest pose and a pose of the generated quadruped (`cshape.data.poses`, as in lesson 9): the poses
# keep the rest pose's vertices, so the true map is the identity, $p^\star[y] = y$. Its functional map
# $C^\star = \Phi_T^T B_T \Phi_S$ is the matrix of inner products of the eigenfunctions of the two poses. Bending
# without stretching changes the eigenfunctions little, so $C^\star$ is close to diagonal, with entries $\pm 1$ (the
# sign of an eigenfunction is arbitrary) and small blocks where two eigenvalues are close and their eigenfunctions mix.

# %%
rest = poses.posed_figure("quadruped", rest=True, **TEMPLATE)
pose = poses.posed_figure("quadruped", 0, **TEMPLATE)
b_s = cshape.eigenbasis(rest, N)  # lam, phi (n_S, N), B and the mesh of the source
b_t = cshape.eigenbasis(pose, N)
b_s0, b_t0 = b_s.truncate(N0), b_t.truncate(N0)  # their first N0 eigenpairs
n = pose.n_vertices
truth = np.arange(n)
C_true = maps.pointwise_to_map(truth, b_s0, b_t0)
print(f"{rest.n_vertices} vertices, {rest.n_faces} triangles; C* is {C_true.shape[0]} x {C_true.shape[1]}")
print(f"share of C*'s energy on its diagonal: {plots.diagonal_share(C_true):.1%}, within 2 of it: "
      f"{plots.diagonal_share(C_true, band=2):.1%}")
plots.plot_functional_map(C_true, title="C* of the true map (the identity)")

# %% [markdown]
# **Graded exercise.** Write `pointwise_to_map_mine(p, phi_s, phi_t, B_t)`: the functional map
# $C = \Phi_T^T B_T\, \Pi\, \Phi_S$ ($N_T \times N_S$) of the point map `p` (for each target vertex $y$ the source vertex
# `p[y]`), with NumPy/SciPy only; `phi_s`, `phi_t` are the bases' `phi` ($n_S \times N_S$, $n_T \times N_T$), `B_t` the
# target's mass matrix (sparse). Do not build $\Pi$ as a dense $n_T \times n_S$ matrix: $\Pi \Phi_S$ is a choice of rows.

# %% nbgrader={"grade": false, "grade_id": "pointwise_to_map_mine", "locked": false, "schema_version": 3, "solution": true, "task": false}
def pointwise_to_map_mine(p, phi_s, phi_t, B_t):
    """C = Phi_T^T B_T Pi Phi_S, shape (N_T, N_S), for p[y] = the source vertex of target vertex y."""
    ### BEGIN SOLUTION
    p = np.asarray(p, dtype=int)
    phi_s, phi_t = np.asarray(phi_s, dtype=float), np.asarray(phi_t, dtype=float)
    return phi_t.T @ (B_t @ phi_s[p])
    ### END SOLUTION


# %% nbgrader={"grade": false, "grade_id": "check_p2m", "locked": true, "schema_version": 3, "solution": false, "task": false}
def check_p2m(fn, p, b_source, b_target):
    """Compare fn with cshape.maps.pointwise_to_map and name the usual mistakes (a hint for each)."""
    pS, pT, B = b_source.phi, b_target.phi, b_target.B
    want = maps.pointwise_to_map(p, b_source, b_target)
    got = np.asarray(fn(p, pS, pT, B), dtype=float)
    if got.shape == want.T.shape and got.shape != want.shape:
        raise AssertionError(f"got shape {got.shape}, expected {want.shape}: hint: C maps source coefficients "
                             "to target ones, one row per target eigenfunction")
    if got.shape != want.shape:
        raise AssertionError(f"got shape {got.shape}, expected {want.shape} (N_T x N_S)")
    if np.allclose(got, want, rtol=1e-9, atol=1e-12):
        print("pointwise_to_map_mine: correct")
        return
    if got.shape == want.T.shape and np.allclose(got, want.T, rtol=1e-9, atol=1e-12):
        raise AssertionError("hint: got C transposed: row i of C is the target eigenfunction i, C = Phi_T^T B_T Pi Phi_S")
    suspects = [
        (pT.T @ pS[p], "hint: the projection on a B-orthonormal basis is Phi_T^T B_T, not Phi_T^T: the basis is "
                       "orthonormal in the B inner product, not in the plain dot product"),
        (np.linalg.pinv(pT) @ pS[p], "hint: that is the pseudo-inverse in the plain dot product; in the B inner "
                                     "product it is Phi_T^T B_T (the derivation above)"),
        (pT.T @ (B @ pS), "hint: Pi is missing: the source function is read at the matched vertex, phi_s[p]"),
    ]
    if len(pS) == len(pT):
        suspects.append((pT.T @ (B @ pT[p]), "hint: Pi picks rows of the *source* basis: phi_s[p]"))
        inv = np.empty_like(p)
        inv[p] = np.arange(len(p))  # only a permutation has an inverse
        if np.array_equal(np.sort(p), np.arange(len(p))):
            suspects.append((pT.T @ (B @ pS[inv]), "hint: p goes from target to source: row y of Pi Phi_S is "
                                                   "phi_s[p[y]], not the inverse map"))
    for bad, hint in suspects:
        if bad.shape == want.shape and np.allclose(got, bad, rtol=1e-9, atol=1e-12):
            raise AssertionError(hint)
    raise AssertionError(f"hint: the largest difference from C is {np.abs(got - want).max():.3g}: "
                         "compute phi_t.T @ (B_t @ phi_s[p])")


# %% nbgrader={"grade": true, "grade_id": "test_pointwise_to_map_mine", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
check_p2m(pointwise_to_map_mine, truth, b_s0, b_t0)

# %% nbgrader={"grade": true, "grade_id": "hidden_pointwise_to_map_mine", "locked": true, "points": 2, "schema_version": 3, "solution": false, "task": false}
# hidden tests: the autograder runs more checks here
### BEGIN HIDDEN TESTS
import scipy.sparse as _sp

# by hand: 2 source vertices, 3 target vertices, one eigenfunction each side, B_t = diag(1, 2, 3)
_C = pointwise_to_map_mine(np.array([1, 0, 1]), np.array([[1.0], [5.0]]), np.array([[1.0], [1.0], [2.0]]),
                           _sp.diags([1.0, 2.0, 3.0]).tocsr())
assert np.allclose(_C, [[1 * 1 * 5 + 1 * 2 * 1 + 2 * 3 * 5]]), f"the 3-vertex example by hand: got {_C}"
# a map that is not the identity, and not a permutation (several targets on one source vertex)
_rng = np.random.default_rng(2)
check_p2m(pointwise_to_map_mine, _rng.permutation(n), b_s0, b_t0)
check_p2m(pointwise_to_map_mine, _rng.integers(0, rest.n_vertices, n), b_s0, b_t.truncate(7))
### END HIDDEN TESTS

# %% [markdown]
# $C$ carries any function: project on the source basis, multiply by $C$, synthesise on the target
# (`cshape.maps.transfer_function`). A smooth function survives; detail above the $N$-th eigenfunction is lost. Here the
# height on the rest pose, carried to the pose through $C^\star$ of growing size and compared with the height carried
# by the true map itself:

# %%
for k in (5, 10, N0, N):
    Ck = maps.pointwise_to_map(truth, b_s.truncate(k), b_t.truncate(k))
    g = maps.transfer_function(rest.vertices[:, 2], Ck, b_s, b_t)  # a k x k C uses the first k pairs
    z = rest.vertices[:, 2]
    print(f"N = {k:>3}: relative error of the carried height {np.linalg.norm(g - z) / np.linalg.norm(z):.3f}")

# %% [markdown]
# ## 2 · $C$ from descriptors (Ovsjanikov et al. 2012)
#
# Now forget the true map. The WKS of both shapes at the *source's* energies (every 5th of 100, both shapes scaled to unit
# area) are descriptors that the correct map preserves; `cshape.maps.functional_map` minimises the energy above (each
# descriptor scaled to unit B-norm, the eigenvalues divided by the largest source eigenvalue, $w_l = 10^{-2}$), then
# `cshape.maps.map_to_pointwise` takes nearest neighbours in the spectral embedding.
#
# The measure of a map is geodesic: the distance on the source between the matched vertex $p[y]$ and the true one
# $p^\star[y]$, by the heat method (`cshape.geodesics.HeatGeodesics`, Crane et al. 2013), reported as its mean over
# $\sqrt{\text{area}}$ (Kim et al.'s measure) and as the share of target vertices within 5 % of the geodesic diameter.
# Each evaluated vertex costs one heat solve, so, as the benchmarks of the field do, the errors are taken over a few
# hundred target vertices spread over the mesh, not all of them.

# %%
e, sigma = sg.wks_energies(b_s, 100, normalization="area")
F_s = cshape.wks(b_s, e, sigma, normalization="area")[:, ::5]
F_t = cshape.wks(b_t, e, sigma, normalization="area")[:, ::5]
geo = cshape.geodesics.HeatGeodesics(rest)
sample = np.unique(np.linspace(0, n - 1, min(n, 400)).round().astype(int))  # evaluated target vertices
D_geo = geo.distances(sample)  # (n, s): from every source vertex to each evaluated one (its true image)
diameter = D_geo.max()
side = rest.vertices[:, 1]  # left (y > 0) and right (y < 0) of the animal
off_plane = np.abs(side) > 0.1 * np.ptp(side)  # vertices clearly on one side


def measure(p):
    """Mean geodesic error / sqrt(area), share within 5 % of the diameter, share on the wrong side."""
    err = D_geo[p[sample], np.arange(len(sample))]  # d(p[y], p*[y]) with p*[y] = y
    wrong_side = (np.sign(side[p]) != np.sign(side))[off_plane].mean()
    return err.mean() / np.sqrt(rest.area), (err <= 0.05 * diameter).mean(), wrong_side


table = {}
t0 = time.perf_counter()
table["nearest WKS (lesson 9)"] = (sg.match_points(F_t, F_s), time.perf_counter() - t0)
t0 = time.perf_counter()
C_plain = maps.functional_map(b_s0, b_t0, F_s, F_t, orientation_weight=0)
table["functional map"] = (maps.map_to_pointwise(C_plain, b_s, b_t), time.perf_counter() - t0)
for name, (p, seconds) in table.items():
    err, within, wrong = measure(p)
    print(f"{name:<26} error/sqrt(area) {err:.3f}  within 5 %: {within:.1%}  wrong side: {wrong:.1%}  ({seconds:.2f} s)")
plots.plot_functional_map(C_plain, title="C from the WKS, Eq. (5)-(6) of Ovsjanikov et al.")

# %% [markdown]
# **Graded exercise.** Write `fmap_mine(D_s, D_t, lam_s, lam_t, w)`: the $C$ ($N_T \times N_S$) minimising
# $\|C D_S - D_T\|_F^2 + w \sum_{ij} C_{ij}^2 (\lambda_{T,i} - \lambda_{S,j})^2$, row by row as derived at the top,
# with NumPy only. It is checked against `cshape.maps.functional_map` without the orientation term.

# %% nbgrader={"grade": false, "grade_id": "fmap_mine", "locked": false, "schema_version": 3, "solution": true, "task": false}
def fmap_mine(D_s, D_t, lam_s, lam_t, w):
    """C (N_T x N_S) minimising ||C D_s - D_t||^2 + w sum_ij C_ij^2 (lam_t[i] - lam_s[j])^2."""
    ### BEGIN SOLUTION
    D_s = np.asarray(D_s, dtype=float)
    D_t = np.asarray(D_t, dtype=float)
    lam_s = np.asarray(lam_s, dtype=float)
    lam_t = np.asarray(lam_t, dtype=float)
    H = D_s @ D_s.T
    C = np.empty((len(lam_t), len(lam_s)))
    for i in range(len(lam_t)):
        C[i] = np.linalg.solve(H + w * np.diag((lam_t[i] - lam_s) ** 2), D_s @ D_t[i])
    return C
    ### END SOLUTION


# %% nbgrader={"grade": false, "grade_id": "check_fmap", "locked": true, "schema_version": 3, "solution": false, "task": false}
def check_fmap(fn, w=1e-2):
    """Compare fn with cshape.maps.functional_map on the poses of this lesson; a hint for each usual mistake.

    D_s D_s^T has rank at most the number of descriptors, so C is compared by the energy it reaches (which every
    exact solver reaches to many digits), not entry by entry."""
    F_sn = F_s / np.sqrt(np.einsum("ij,ij->j", F_s, b_s.B @ F_s))
    F_tn = F_t / np.sqrt(np.einsum("ij,ij->j", F_t, b_t.B @ F_t))
    D_s = b_s0.phi.T @ (b_s.B @ F_sn)
    D_t = b_t0.phi.T @ (b_t.B @ F_tn)
    ls, lt = b_s0.lam / b_s0.lam[-1], b_t0.lam / b_s0.lam[-1]  # functional_map's scaling
    want = maps.functional_map(b_s0, b_t0, F_sn, F_tn, laplacian_weight=w, orientation_weight=0.0)

    def energy(C, w=w):
        return np.sum((C @ D_s - D_t) ** 2) + w * np.sum(C**2 * (lt[:, None] - ls[None, :]) ** 2)

    got = np.asarray(fn(D_s, D_t, ls, lt, w), dtype=float)
    if got.shape != want.shape:
        raise AssertionError(f"got shape {got.shape}, expected {want.shape}: hint: one row per target "
                             "eigenfunction, one column per source eigenfunction")
    if not np.all(np.isfinite(got)):
        raise AssertionError("hint: C holds NaN or inf: solve each row's system, do not invert D_s alone")
    best = energy(want)
    if energy(got) > best * (1 + 1e-6) + 1e-12:
        if energy(got.T) <= best * (1 + 1e-6) + 1e-12:
            raise AssertionError("hint: got C transposed: C maps source coefficients to target ones, C D_s ~ D_t")
        if energy(got, 0.0) <= energy(want, 0.0) * (1 + 1e-6) + 1e-12:
            raise AssertionError("hint: w changes nothing: add w (lam_t[i] - lam_s[j])^2 to the diagonal of row "
                                 "i's system")
        raise AssertionError(f"hint: the energy of your C is {energy(got):.6g}, the minimum {best:.6g}: each row "
                             "i solves (D_s D_s^T + w diag((lam_t[i] - lam_s)^2)) c_i = D_s D_t[i]")
    print("fmap_mine: correct")


# %% nbgrader={"grade": true, "grade_id": "test_fmap_mine", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
check_fmap(fmap_mine)

# %% nbgrader={"grade": true, "grade_id": "hidden_fmap_mine", "locked": true, "points": 2, "schema_version": 3, "solution": false, "task": false}
# hidden tests: the autograder runs more checks here
### BEGIN HIDDEN TESTS
# by hand, one eigenfunction each: C = (d_s . d_t) / (d_s . d_s + w (lam_t - lam_s)^2)
_got = fmap_mine(np.array([[1.0, 2.0]]), np.array([[3.0, 1.0]]), [0.5], [1.5], 4.0)
assert np.allclose(_got, [[(3 + 2) / (5 + 4 * 1.0)]]), f"the 1 x 1 example by hand: got {_got}"
# no Laplacian term and an invertible square D_s: C = D_t D_s^-1 exactly
_rng = np.random.default_rng(1)
_Ds, _Dt = _rng.normal(size=(4, 4)), _rng.normal(size=(3, 4))
assert np.allclose(fmap_mine(_Ds, _Dt, np.arange(4.0), np.arange(3.0), 0.0), _Dt @ np.linalg.inv(_Ds))
# N_T differs from N_S, lists work as well as arrays
assert fmap_mine(_Ds.tolist(), _Dt.tolist(), list(range(4)), [0.0, 1.0, 2.0], 0.1).shape == (3, 4)
# a huge weight keeps only the entries of equal eigenvalues
_big = fmap_mine(_Ds, _Dt, np.arange(4.0), np.arange(3.0), 1e12)
assert np.abs(_big[~np.eye(3, 4, dtype=bool)]).max() < 1e-6, "w -> inf: only C_ii may stay"
check_fmap(fmap_mine, w=1e-1)
### END HIDDEN TESTS

# %% [markdown]
# ## 3 · The pitfall: left and right
#
# The animal is left-right symmetric, and the mirror $m$ (vertex $i$ to its mirror image, `poses.mirror_map`) is an
# isometry of it. Its functional map $C_m = \Phi_T^T B_T \Pi_m \Phi_S$ differs from $C^\star$ in the sign of the rows
# of the *antisymmetric* eigenfunctions ($\phi \circ m = -\phi$). The mirror is a wrong map: how does the energy of
# section 2 rate it?

# %% [markdown]
# **Predict first.** Below, the two terms of the energy are computed for three maps: $C^\star$, the mirror $C_m$ and a
# shuffled map. Write your prediction of the ratio (descriptor term of $C_m$) / (descriptor term of $C^\star$).

# %% nbgrader={"grade": false, "grade_id": "predict_mirror_ratio", "locked": false, "schema_version": 3, "solution": true, "task": false}
# prediction_mirror_ratio = (descriptor term of the mirror C_m) / (descriptor term of the true C*)
### BEGIN SOLUTION
prediction_mirror_ratio = 1.0  # the WKS is intrinsic: the mirror preserves it as well as the truth does
### END SOLUTION

# %%
mirror = poses.mirror_map("quadruped", rest)
C_mirror = maps.pointwise_to_map(mirror, b_s0, b_t0)


def energies(C):
    """The two terms of Ovsjanikov et al.'s energy, with functional_map's scalings."""
    F_sn = F_s / np.sqrt(np.einsum("ij,ij->j", F_s, b_s.B @ F_s))
    F_tn = F_t / np.sqrt(np.einsum("ij,ij->j", F_t, b_t.B @ F_t))
    D_s = b_s0.phi.T @ (b_s.B @ F_sn)
    D_t = b_t0.phi.T @ (b_t.B @ F_tn)
    ls, lt = b_s0.lam / b_s0.lam[-1], b_t0.lam / b_s0.lam[-1]
    return np.sum((C @ D_s - D_t) ** 2), np.sum(C**2 * (lt[:, None] - ls[None, :]) ** 2)


shuffled = np.random.default_rng(0).permutation(n)
C_shuffled = maps.pointwise_to_map(shuffled, b_s0, b_t0)
for name, C in (("C* (the identity)", C_true), ("C_m (the mirror)", C_mirror), ("a shuffled map", C_shuffled)):
    ed, el = energies(C)
    print(f"{name:<18} descriptor term {ed:.4f}  Laplacian term {el:.4f}")
fig = plots.new_figure((9, 3.8))
ax1, ax2 = fig.subplots(1, 2)
plots.plot_functional_map(C_true, ax=ax1, title="C*: the identity", colorbar=False)
plots.plot_functional_map(C_mirror, ax=ax2, title="C_m: the mirror (antisymmetric rows flip sign)")
fig

# %% nbgrader={"grade": true, "grade_id": "test_predict_mirror_ratio", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
# the autograder compares your prediction with the printed ratio (within a factor 1.5)
assert prediction_mirror_ratio > 0, "a ratio of two sums of squares is positive"
### BEGIN HIDDEN TESTS
_ratio = energies(C_mirror)[0] / energies(C_true)[0]
assert 1 / 1.5 <= prediction_mirror_ratio / _ratio <= 1.5, (
    f"you predicted {prediction_mirror_ratio:.3g}, the printed ratio is {_ratio:.3g}. "
    + ("hint: the mirror is a *wrong* map, but not a random one: it is an isometry, and the WKS is intrinsic, "
       "so it preserves the descriptors as well as the truth does (compare the shuffled map)"
       if prediction_mirror_ratio > _ratio else
       "hint: the mirror does not preserve the descriptors better than the truth; on an exactly symmetric "
       "shape the two terms would be equal"))
### END HIDDEN TESTS

# %% [markdown]
# The WKS is intrinsic, so it is the same at a point and at its mirror image, and the eigenvalues are those of the same
# operator: on an exactly symmetric shape both terms of the energy would rate the mirror exactly as the truth. This
# animal is symmetric up to its meshing (the mirror image of a vertex is snapped to the nearest vertex), so the two
# cost a little differently, in either direction; a map that is merely wrong (the vertices shuffled) costs far more.
#
# **Written answer (graded by hand).** Explain with the formulas why both terms rate $C_m$ (nearly) as $C^\star$. Use
# that on an exactly symmetric shape $C_m = S\, C^\star$ with $S = \mathrm{diag}(\pm 1)$ ($-1$ for the antisymmetric
# eigenfunctions of the target), and that a descriptor $f$ with $f \circ m = f$ has no component on an antisymmetric
# eigenfunction.

# %% [markdown] nbgrader={"grade": true, "grade_id": "written_mirror_energy", "locked": false, "points": 2, "schema_version": 3, "solution": true, "task": false}
# **Model answer.** *Laplacian term:* $\sum_{ij} C_{ij}^2 (\lambda_{T,i} - \lambda_{S,j})^2$ depends on the squares of
# the entries only, and $(S C^\star)_{ij} = \pm C^\star_{ij}$, so it is the same for $C_m$ and $C^\star$.
# *Descriptor term:* $S$ is orthogonal and $S^2 = I$, so $\lVert S C^\star D_S - D_T\rVert = \lVert C^\star D_S - S
# D_T\rVert$. Row $i$ of $D_T = \Phi_T^T B_T F_T$ is the component of the descriptors on $\phi_{T,i}$; the WKS is
# intrinsic, so $F_T \circ m = F_T$, and its component on an antisymmetric eigenfunction ($\phi \circ m = -\phi$)
# is zero (the integral of a symmetric times an antisymmetric function vanishes). The rows that $S$ flips are zero,
# so $S D_T = D_T$ and the term is the same. On the meshed animal, which is symmetric only up to its triangles,
# both hold approximately, which is why the printed terms differ a little, in either direction, and far less than
# for the shuffled map.

# %% [markdown]
# The minimiser of such an energy may take either, or a mixture, region by region: above, a large share of the
# vertices away from the symmetry plane were sent to the wrong side, by the nearest WKS and by the functional map alike
# (the printed table of section 2; the functional map of size $N_0$ alone need not beat the nearest WKS). The orientation-preserving term of
# Ren et al. (2018) adds $w_o \sum_f \|C\, O_{S,f} - O_{T,f}\, C\|^2$, where $O_f$ is the operator "derivative along
# $n \times \nabla f$" (the gradient of the descriptor $f$ turned by a right angle about the normal) in the bases. It
# uses the faces' orientation, and changes sign under a mirror. Colour the rest pose by $y$ (one side blue, the other
# red) and look at the legs of the pose, first without the term, then with it (`orientation_weight`, on by default:
# the eigenbases carry their meshes):

# %%
t0 = time.perf_counter()
C_orient = maps.functional_map(b_s0, b_t0, F_s, F_t)
table["+ orientation term"] = (maps.map_to_pointwise(C_orient, b_s, b_t), time.perf_counter() - t0)
for name in ("functional map", "+ orientation term"):
    print(f"{name:<20} wrong side: {measure(table[name][0])[2]:.1%} of the vertices off the symmetry plane")
plots.plot_map(rest, pose, table["functional map"][0], values=side, cmap="coolwarm",
               titles=("rest pose, coloured by y", "pose, without the orientation term"))

# %%
plots.plot_map(rest, pose, table["+ orientation term"][0], values=side, cmap="coolwarm",
               titles=("rest pose, coloured by y", "pose, with the orientation term"))

# %% [markdown]
# ## 4 · ZoomOut
#
# A map of size $N_0$ sees only smooth functions, so its points are blurred. ZoomOut (Melzi et al. 2019) alternates the
# two directions of the first section, one more eigenfunction at a time: the point map of $C$ (nearest neighbours with
# $k$ eigenfunctions), then $C$ of size $k+1$ from that point map ($C = \Phi_T^T B_T \Pi \Phi_S$). Each step keeps
# what is consistent with an isometry at the larger size; the noise of the first map, in the high frequencies, is
# filtered out. It also makes a *consistent* map out of the mixture of identity and mirror that the map without the
# orientation term was: often the mirror, which is an isometry too (the wrong-side column).

# %% [markdown]
# **Graded exercise.** Write one ZoomOut step, `zoomout_step_mine(C, phi_s, phi_t, B_t)`: from $C$ of size
# $k \times k$, (1) the point map $p[y] = \arg\min_x \lVert \Phi_T[y, :k] - C\, \Phi_S[x, :k]^T\rVert$ (use
# `sg.match_points(a, b)`, which gives for every row of `a` the nearest row of `b`), then (2) the functional map of
# size $(k+1) \times (k+1)$ of that point map, with your `pointwise_to_map_mine` on the first $k+1$ eigenfunctions.
# It is checked against `cshape.maps.zoomout(C, b_s, b_t, k + 1)`.

# %% nbgrader={"grade": false, "grade_id": "zoomout_step_mine", "locked": false, "schema_version": 3, "solution": true, "task": false}
def zoomout_step_mine(C, phi_s, phi_t, B_t):
    """One ZoomOut step: the point map of C (k x k), then C of size k+1 from it."""
    ### BEGIN SOLUTION
    C = np.asarray(C, dtype=float)
    k = C.shape[0]
    p = sg.match_points(phi_t[:, :k], phi_s[:, :k] @ C.T)
    return pointwise_to_map_mine(p, phi_s[:, :k + 1], phi_t[:, :k + 1], B_t)
    ### END SOLUTION


# %% nbgrader={"grade": false, "grade_id": "check_zoomout_step", "locked": true, "schema_version": 3, "solution": false, "task": false}
def check_zoomout_step(fn, C, b_source, b_target):
    """Compare fn with one step of cshape.maps.zoomout and name the usual mistakes."""
    k = C.shape[0]
    want = maps.zoomout(C, b_source, b_target, k + 1)
    got = np.asarray(fn(C, b_source.phi, b_target.phi, b_target.B), dtype=float)
    if got.shape == (k, k):
        raise AssertionError(f"got shape {got.shape}: hint: the step grows C by one eigenfunction, to {k + 1} x {k + 1}")
    if got.shape != want.shape:
        raise AssertionError(f"got shape {got.shape}, expected {want.shape}")
    pS, pT = b_source.phi, b_target.phi
    # the same step with sg.match_points (another exact nearest-neighbour search than zoomout's): either is right
    p_ref = sg.match_points(pT[:, :k], pS[:, :k] @ C.T)
    ref = pT[:, :k + 1].T @ (b_target.B @ pS[p_ref, :k + 1])
    if np.allclose(got, want, rtol=1e-8, atol=1e-10) or np.allclose(got, ref, rtol=1e-8, atol=1e-10):
        print("zoomout_step_mine: correct")
        return
    p_t = sg.match_points(pT[:, :k], pS[:, :k] @ C)  # C instead of C^T
    p_inv = sg.match_points(pS[:, :k] @ C.T, pT[:, :k])  # the map the wrong way round
    for p_bad, hint in ((p_t, "hint: the embedded source point is C Phi_S[x]^T, i.e. the rows phi_s[:, :k] @ C.T"),
                        (p_inv, "hint: match target rows to source rows: sg.match_points(target, source) gives "
                                "one source vertex per target vertex")):
        if len(p_bad) == len(pT):
            bad = pT[:, :k + 1].T @ (b_target.B @ pS[p_bad, :k + 1])
            if np.allclose(got, bad, rtol=1e-8, atol=1e-10):
                raise AssertionError(hint)
    raise AssertionError(f"hint: the largest difference from ZoomOut's step is {np.abs(got - want).max():.3g}: "
                         "the point map uses the first k eigenfunctions, the new C the first k+1")


# %% nbgrader={"grade": true, "grade_id": "test_zoomout_step_mine", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
check_zoomout_step(zoomout_step_mine, C_orient, b_s, b_t)

# %% nbgrader={"grade": true, "grade_id": "hidden_zoomout_step_mine", "locked": true, "points": 2, "schema_version": 3, "solution": false, "task": false}
# hidden tests: the autograder runs more checks here
### BEGIN HIDDEN TESTS
check_zoomout_step(zoomout_step_mine, C_plain, b_s, b_t)
check_zoomout_step(zoomout_step_mine, C_true[:5, :5], b_s, b_t)
# a list for C works as well
check_zoomout_step(lambda C, *a: zoomout_step_mine(np.asarray(C).tolist(), *a), C_true[:12, :12], b_s, b_t)
### END HIDDEN TESTS

# %%
t0 = time.perf_counter()
C_zoom_plain = maps.zoomout(C_plain, b_s, b_t, N)
table["+ ZoomOut, no orientation"] = (maps.map_to_pointwise(C_zoom_plain, b_s, b_t),
                                      time.perf_counter() - t0 + table["functional map"][1])
t0 = time.perf_counter()
C_zoom = maps.zoomout(C_orient, b_s, b_t, N)
table["+ ZoomOut"] = (maps.map_to_pointwise(C_zoom, b_s, b_t), time.perf_counter() - t0 + table["+ orientation term"][1])
t0 = time.perf_counter()
table["cshape.point_map (one call)"] = (cshape.point_map(rest, pose, N=N, N0=N0), time.perf_counter() - t0)
print(f"{'method':<28} {'error/sqrt(area)':>16} {'within 5 %':>11} {'wrong side':>11} {'seconds':>8}")
for name, (p, seconds) in table.items():
    err, within, wrong = measure(p)
    print(f"{name:<28} {err:>16.4f} {within:>11.1%} {wrong:>11.1%} {seconds:>8.2f}")
print(f"diagonal share of C after ZoomOut (within 2): {plots.diagonal_share(C_zoom, band=2):.1%}")
plots.plot_map(rest, pose, table["+ ZoomOut"][0], titles=("rest pose", "pose, functional map + ZoomOut"))

# %% [markdown]
# `cshape.point_map(source, target)` is the whole pipeline in one call: eigenpairs, WKS, the functional map with the
# orientation term, ZoomOut (on 3000 sampled vertices for big meshes), and for every target vertex the index of a
# source vertex, shape `(n_target,)`. `return_map=True` also returns $C$.
#
# ## 5 · Landmarks
#
# A few known pairs of points help where the descriptors are ambiguous: `landmarks=` adds heat kernels from them to the
# descriptors (each pair $(s, t)$ gives a function on each shape that a correct map preserves). Here six tips (the four
# feet, the head, the tail), found on the rest pose; their partners on the pose are the same vertices. Even without
# the orientation term they keep left and right apart:

# %%
along, height = rest.vertices[:, 0], rest.vertices[:, 2]
feet = [int(np.argmin(np.where((np.sign(along) == sx) & (np.sign(side) == sy), height, np.inf)))
        for sx in (-1, 1) for sy in (-1, 1)]
tips = feet + [int(np.argmax(along)), int(np.argmin(along))]  # the four feet, the head, the tail
landmarks = np.column_stack([tips, tips])
p_lm = cshape.point_map(rest, pose, N=N, N0=N0, orientation=False, step=0, landmarks=landmarks)
p_no = cshape.point_map(rest, pose, N=N, N0=N0, orientation=False, step=0)
for name, p in (("no orientation, no landmarks", p_no), ("no orientation, 6 landmarks", p_lm)):
    err, within, wrong = measure(p)
    print(f"{name:<30} within 5 %: {within:.1%}  wrong side: {wrong:.1%}")
plots.plot_map(rest, pose, p_lm, values=side, landmarks=landmarks, cmap="coolwarm",
               titles=("rest pose, landmarks", "pose, 6 landmarks, no orientation term"))

# %% [markdown]
# The same in 3-D (drag to turn; offline in the exported page):

# %%
plots.view_map(rest, pose, table["+ ZoomOut"][0], values=side, landmarks=landmarks, cmap="RdBu",
               titles=("rest pose", "pose, + ZoomOut"), height=380)

# %% [markdown]
# ## 6 · Between different bodies
#
# Poses of one body are near-isometric, and everything above relies on it. Two *people* are not: a wider, shorter body
# stretches the surface, the WKS of the two no longer agree, and the descriptors' map of section 2 can start ZoomOut
# from a wrong $C$ that it cannot repair. What survives a change of body shape is the start of the spectrum: the
# first few eigenfunctions still correspond one to one, up to their signs. `cshape.point_map` (`initial='search'`,
# the default) therefore also tries the sign patterns of the first eigenfunctions as starts, refines each by ZoomOut,
# and keeps the map that fits best and keeps the surface's orientation. How it decides, and why, is cshape's own
# heuristic, told in the guide *Maps between shapes*, section "Between different people" (`docs/guides/maps.md`).
#
# The pair: the generated human at rest, and its pose 0 made stockier ($x, y$ times 1.3, $z$ times 0.9; the same
# vertices, so the truth is still the identity), at the small size of the lesson's quick run whatever the size switch.

# %%
small = {"voxelsize": 0.03, "target_vertices": 800}
body = poses.posed_figure("human", rest=True, **small)
stocky = poses.posed_figure("human", 0, **small)
stocky = cshape.Mesh(stocky.vertices * [1.3, 1.3, 0.9], stocky.faces)  # another body: wider and shorter
geo_body = cshape.geodesics.HeatGeodesics(body)
across = {}
for initial in ("descriptors", "search"):
    t0 = time.perf_counter()
    across[initial] = cshape.point_map(body, stocky, N=50, N0=20, initial=initial)
    err = cshape.geodesics.geodesic_errors(body, across[initial], geodesics=geo_body)
    print(f"initial={initial!r:<14} error/sqrt(area) {err.mean() / np.sqrt(body.area):.3f}  "
          f"({time.perf_counter() - t0:.1f} s)")
left_right = body.vertices[:, 0]  # the human's mirror axis: one side blue, the other red
plots.plot_map(body, stocky, across["descriptors"], values=left_right, cmap="coolwarm",
               titles=("body at rest, coloured by x", "a stockier body: the descriptors' map fails"))

# %%
plots.plot_map(body, stocky, across["search"], values=left_right, cmap="coolwarm",
               titles=("body at rest, coloured by x", "the same pair with the search"))

# %% [markdown]
# Compare the two printed errors and the two pictures. The search is not a proof: a body symmetric in more ways than
# left and right has more maps that fit and keep the orientation (the generated figure is built from capsules, the
# same in front and behind, so a half turn about the vertical axis is one of them). Where a map must be right, give a
# few landmarks (section 5): they override the search.
#
# **A pair remeshed on its own.** The stocky body above keeps the vertices and triangles of the rest pose, so the two
# meshes are triangulated alike. Real collections are not: every scan is meshed on its own (the published benchmark
# FAUST_r remeshes each body on purpose). Remesh the stocky body with PyMeshLab's isotropic remeshing
# (`cshape.data.variants.remesh`): new vertices, new triangles, the same surface. There is no shared vertex any more,
# so the truth of a remeshed vertex is the vertex of the unremeshed stocky body nearest to it in space (and that
# vertex's own truth is the identity, as above). *Predict* before you run: does the descriptors' map do better or
# worse than on the pair triangulated alike, and does the default `point_map` still find the body's front and left?

# %%
remeshed = variants.remesh(stocky, target_vertices=stocky.n_vertices)  # a triangulation of its own
truth_re = sg.match_points(remeshed.vertices, stocky.vertices)  # nearest stocky vertex = its body vertex
print(f"body: {body.n_vertices} vertices, {body.n_faces} triangles; remeshed stocky body: "
      f"{remeshed.n_vertices} vertices, {remeshed.n_faces} triangles")
across_re = {}
for initial in ("descriptors", "search"):
    t0 = time.perf_counter()
    across_re[initial] = cshape.point_map(body, remeshed, N=50, N0=20, initial=initial)
    err = cshape.geodesics.geodesic_errors(body, across_re[initial], truth_re, geodesics=geo_body)
    print(f"remeshed, initial={initial!r:<14} error/sqrt(area) {err.mean() / np.sqrt(body.area):.3f}  "
          f"({time.perf_counter() - t0:.1f} s)")
plots.plot_map(body, remeshed, across_re["search"], values=left_right, cmap="coolwarm",
               titles=("body at rest, coloured by x", "remeshed stocky body, point_map's defaults"))

# %% [markdown]
# The first line shows that the two meshes share neither their vertex count nor their triangles. The error of the
# descriptors' map alone (`initial='descriptors'`) is the "before": what a map between differently meshed bodies
# gives without the search. The default (`initial='search'`) is the "after": compare its error with the one of the
# pair triangulated alike, and the colours of the picture (blue and red on the same sides as on the body at rest).
#
# **What the warning means.** The search chooses among candidate maps by four criteria: the residual of the
# functional map's energy, the share of the surface whose orientation the map keeps, the disagreement of the
# descriptors (the WKS), and the misfit of the source laid over the target in space. Take a shape whose only symmetry is a half
# turn about the vertical axis: an ellipsoid with two bumps, one the half turn of the other. The turn is an isometry,
# so it keeps every intrinsic quantity (the eigenvalues, the WKS, the energy's residual); it is a rotation, not a
# mirror, so it keeps the orientation; and a rigid motion lays the shape over itself exactly, so the misfit in space
# is zero too. Map the shape to itself: the identity and the turn are two candidate maps that every criterion rates
# alike, and nothing in the two meshes says which one you mean. `point_map` then returns one of them (which one is
# round-off's choice) and warns. The warning is caught and printed here, with the share of vertices the returned map
# sends to themselves and to their turned image.

# %%
ball = cshape.shapes.icosphere(2)  # 162 vertices
U = ball.vertices
V = U * [1.0, 0.7, 0.5]  # an ellipsoid
for c in ([0.6, 0.5, 0.3], [-0.6, -0.5, 0.3]):  # two bumps, each the half turn of the other about z
    c = np.array(c) / np.linalg.norm(c)
    V = V + 0.35 * np.exp(-np.sum((U - c) ** 2, axis=1) / 0.08)[:, None] * U
twofold = cshape.Mesh(V, ball.faces)
turn = sg.match_points(U * [-1, -1, 1], U)  # the vertex each vertex goes to under the half turn
identity = np.arange(twofold.n_vertices)
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always", cshape.CShapeWarning)
    p_tie = cshape.point_map(twofold, twofold, N=50, N0=20)
message = "\n".join(str(w.message) for w in caught if issubclass(w.category, cshape.CShapeWarning))
print(message)
b_two = cshape.eigenbasis(twofold, 6)
C_turn = maps.pointwise_to_map(turn, b_two, b_two)  # the turn's functional map, 6 x 6
print("diagonal of the turn's C (eigenfunctions 1-5):", np.diag(C_turn)[1:].round(3))
print(f"the map returned: {(p_tie == identity).mean():.1%} of the vertices on themselves, "
      f"{(p_tie == turn).mean():.1%} on their turned image")

# %% [markdown]
# Read the message: it names the two candidates, each with its four criteria (equal up to round-off), and three
# target vertices where the two maps disagree most, with the image of each under either map. The turn's functional
# map is diagonal with entries $\pm 1$: it keeps the eigenfunctions the turn leaves alone and reverses the sign of the
# others, so a start from that sign pattern of the first eigenfunctions (compare the printed diagonal with the
# pattern of `+` and `-` the message names) leads ZoomOut to the turn: one candidate is the identity, the other the turn.
# The warning does not say the map returned is wrong: it says the meshes alone cannot tell.
#
# **Landmarks settle it.** Only you know which map you mean. Read the named target vertices out of the message,
# give each its true source vertex as a landmark (`landmarks=[[source vertex, target vertex], ...]`), and map again:
# once meaning the identity, once meaning the turn.

# %%
named = [int(v) for v in re.search(r"target vertices \[([\d, ]+)\]", message)[1].split(",")]
print("target vertices named by the warning:", named)
for name, chosen in (("the identity", identity), ("the turn", turn)):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", cshape.CShapeWarning)
        p_chosen = cshape.point_map(twofold, twofold, N=50, N0=20,
                                    landmarks=np.column_stack([chosen[named], named]))
    print(f"landmarks meaning {name:<12}: {len(caught)} warnings, {(p_chosen == chosen).mean():.1%} of the "
          f"vertices go where {name} sends them")
plots.plot_map(twofold, twofold, p_chosen, values=twofold.vertices[:, 0], cmap="coolwarm", elev=70,
               landmarks=np.column_stack([turn[named], named]),
               titles=("the shape, coloured by x", "landmarks meaning the turn"))

# %% [markdown]
# With the landmarks the search is off (they decide), no warning comes, and the map is the one the landmarks meant,
# either way: in the picture the turn carries the blue side of the shape to the red side and back. On a real body the
# same three target vertices are where to look (or any few well-spread points: hands, feet, head).

# %% [markdown]
# **Where it loses.** The functional map needs near-isometric shapes with the same topology: a pose that stretches the
# surface much beyond a change of body shape, a hole, or a shape glued at the hands breaks the commutativity with the
# Laplacian. The descriptors must agree (the WKS at the same energies, both shapes scaled to unit area). And a
# perfectly symmetric shape is only told from its mirror by its orientation: meshes whose faces are not consistently
# oriented lose that, and even on good meshes the term can settle on the mirror (print the wrong-side share of
# `measure` whenever the shape is symmetric). The search lays each candidate over the target in space (a rotation, a
# scale and a smooth bending, never a mirror); that uses the vertices' positions, so it assumes a change of pose is
# mostly a bending. The measured tables (the real poses of TOSCA, the generated poses, `point_map` between different
# people of FAUST, each body remeshed on its own, and the pairs where the search or the landmarks fall short) are in
# the guide `docs/guides/maps.md` and in `benchmarks/results/`.

# %% [markdown]
# ## Exercises
#
# The graded exercises are above (`pointwise_to_map_mine`, `fmap_mine`, the prediction and the written answer of
# section 3, `zoomout_step_mine`). These are open:
#
# 1. **How many descriptors?** Keep every 10th, 5th and 2nd WKS energy. How do the accuracy and the wrong-side share
#    of the functional map (without ZoomOut) change? What happens with fewer descriptors than $N_0$?
# 2. **The Laplacian weight.** Solve with $w_l = 0, 10^{-3}, 10^{-2}, 10^{-1}, 1$ (`laplacian_weight=`). Plot
#    `plots.diagonal_share(C, band=2)` and the accuracy against $w_l$. What happens at $w_l = 0$, and why (look at
#    the condition number of $D_S D_S^T$)?
# 3. **Flip it yourself.** Multiply the rows of `C_orient` of the antisymmetric eigenfunctions by $-1$ (find them:
#    $\phi_i \circ m \approx -\phi_i$ on the rest pose). Where do the points of the resulting map go?
# 4. **Bijectivity.** Compare `cshape.point_map(rest, pose)` with `bijective=True`: how many source vertices are hit
#    by no target vertex in each case?
# 5. **ZoomOut by hand.** Run your `zoomout_step_mine` from `C_plain` up to size $N$ and compare the map with the
#    table's "+ ZoomOut, no orientation" row. Does it end on the identity, the mirror, or a mixture (the wrong-side
#    column of `measure`)?
#
# ## References
#
# - Ovsjanikov, M., Ben-Chen, M., Solomon, J., Butscher, A. and Guibas, L. (2012). Functional maps: a flexible
#   representation of maps between shapes. *ACM Transactions on Graphics* 31(4), 30:1-30:11.
# - Ren, J., Poulenard, A., Wonka, P. and Ovsjanikov, M. (2018). Continuous and orientation-preserving
#   correspondences via functional maps. *ACM Transactions on Graphics* 37(6), 248:1-248:16.
# - Melzi, S., Ren, J., Rodolà, E., Sharma, A., Wonka, P. and Ovsjanikov, M. (2019). ZoomOut: spectral upsampling
#   for efficient shape correspondence. *ACM Transactions on Graphics* 38(6), 155:1-155:14.
# - Aubry, M., Schlickewei, U. and Cremers, D. (2011). The wave kernel signature: a quantum mechanical approach to
#   shape analysis. *ICCV Workshops*, 1626-1633.
# - Crane, K., Weischedel, C. and Wardetzky, M. (2013). Geodesics in heat: a new approach to computing distance
#   based on heat flow. *ACM Transactions on Graphics* 32(5), 152:1-152:11.
# - Kim, V. G., Lipman, Y. and Funkhouser, T. (2011). Blended intrinsic maps. *ACM Transactions on Graphics* 30(4),
#   79:1-79:12.
