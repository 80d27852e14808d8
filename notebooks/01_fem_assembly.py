# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 1 · Laplace-Beltrami eigenvalues with linear finite elements
#
# **Paper:** Gao, Yu and Pang, *A compact shape descriptor for triangular surface meshes*, Computer-Aided Design 53 (2014) 62-69; Section 2.1-2.2, Eq. (3)-(7).
#
# **Learning goals.** After this notebook you can
#
# 1. derive the entries of the stiffness matrix $A$ (Eq. 4) and the mass matrix $B$ (Eq. 5) from the hat
#    functions: the cotangent weights and the $|t|/6$, $|t|/12$ mass entries;
# 2. assemble $A$ and $B$ of a triangle mesh yourself, and check them: symmetry, zero row sums of $A$, entries of
#    $B$ adding up to the area, the signs;
# 3. solve the generalised eigenproblem $A f = -\lambda B f$ (Eq. 3) and read its eigenvalues;
# 4. tell Neumann from Dirichlet boundary conditions (Section 2.2) on a mesh with a boundary;
# 5. predict and measure how the computed spectrum of the sphere approaches the exact one, $\ell(\ell+1)$, as the
#    mesh is refined;
# 6. see why the upper eigenvalues of a coarse mesh drift, and remove the drift by Richardson extrapolation.
#
# *Prerequisites:* linear algebra (symmetric matrices, eigenvalues), vectors in 3-D (dot and cross products), and
# integration by parts. *Time:* about 2 hours, with the exercises at the end another 2-3.
#
# **The equations.** The eigenproblem of the Laplace-Beltrami operator $\Delta f = -\lambda f$ (Eq. 2) becomes, with
# linear finite elements,
#
# $$A f = -\lambda B f, \qquad (3)$$
#
# $$a_{ij} = \begin{cases}\tfrac{\cot\alpha_{ij} + \cot\beta_{ij}}{2} & v_iv_j \text{ an edge}\\ -\sum_{k\in N(i)} a_{ik} & i = j\\ 0 & \text{otherwise}\end{cases}
# \qquad (4)\qquad
# b_{ij} = \begin{cases}\tfrac{|t_1| + |t_2|}{12} & v_iv_j \text{ an edge}\\ \sum_{t \ni v_i} \tfrac{|t|}{6} & i = j\\ 0 & \text{otherwise}\end{cases} \qquad (5)$$
#
# where $\alpha_{ij}, \beta_{ij}$ are the angles opposite the edge $v_iv_j$ in its two triangles $t_1, t_2$.
# On a boundary edge there is one triangle, at a non-manifold edge three or more: Eq. (6)-(7) simply sum over all
# triangles at the edge.
#
# > **Sign conventions.** With the paper's sign, $A$ is *negative* semidefinite (rows sum to zero) and $B$ is positive
# > definite. The paper prints a minus sign on the diagonal of $B$ in Eq. (5) and (7): that is a typo; the diagonal is
# > $+\sum_t |t|/6$.
#
# *Run the cells from top to bottom. `CSHAPE_SMALL=1` in the environment makes every mesh small (the test suite uses it).*

# %%
# %matplotlib inline
import numpy as np

import cshape
from cshape import plots, shapes
from cshape.course.teaching import SMALL, size  # CSHAPE_SMALL=1: small meshes and N

np.set_printoptions(precision=4, suppress=True, linewidth=100)
print("cshape", cshape.__version__, "(small sizes)" if SMALL else "")


# %% nbgrader={"grade": false, "grade_id": "check_close", "locked": true, "schema_version": 3, "solution": false, "task": false}
def check_close(name, got, want, hint="", rtol=1e-9):
    """Compare your result with the expected one and say what is wrong."""
    got = np.asarray(got.toarray() if hasattr(got, "toarray") else got, dtype=float)
    want = np.asarray(want.toarray() if hasattr(want, "toarray") else want, dtype=float)
    if got.shape != want.shape:
        raise AssertionError(f"{name} has shape {got.shape}, expected {want.shape}. {hint}")
    bad = np.argwhere(~np.isclose(got, want, rtol=rtol, atol=1e-12 * max(1.0, abs(want).max())))
    if len(bad):
        idx = tuple(int(k) for k in bad[0])
        raise AssertionError(
            f"{name}{list(idx)} = {got[idx]:.6g}, expected {want[idx]:.6g} "
            f"({len(bad)} of {got.size} entries differ). {hint}"
        )
    print(f"{name}: correct")


# %% [markdown]
# ## A tiny mesh
#
# Five vertices, four triangles: a low tent over the unit square. It has a boundary (the four outer edges), so it
# also shows the Neumann / Dirichlet difference later on.

# %%
V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0.3]])
F = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
tent = cshape.Mesh(V, F)
print(tent)
fig = plots.plot_mesh(tent, elev=35, azim=-70, edges=True, title="the tent: 4 triangles")
middle = V.mean(axis=0)
for i, p in enumerate(V):  # each name a little inside its corner (the apex's above it)
    q = p + 0.15 * (middle - p) if i < 4 else p + [0, 0, 0.06]
    fig.axes[0].text(*q, f"v{i}", color="crimson", fontsize=12, ha="center", va="center")
fig


# %% [markdown]
# ### The hat functions behind Eq. (3)
#
# Linear finite elements write a function on the surface as $f = \sum_i f_i \varphi_i$, one value $f_i$ per
# vertex. The *hat function* $\varphi_j$ is 1 at vertex $v_j$, 0 at every other vertex and linear on each
# triangle, so it lives on the triangles around $v_j$ only. Below, one hat on a coarse sphere: drag to rotate it,
# scroll to zoom.

# %%
ball = shapes.icosphere(1)
eye = plots.viewer.default_eye(ball.vertices)  # where the view below looks from
j = int(np.argmax(ball.vertices @ [eye["x"], eye["y"], eye["z"]]))  # the vertex facing the camera
hat = np.zeros(ball.n_vertices)
hat[j] = 1.0  # phi_j: 1 at v_j, 0 at the other vertices, linear in between
plots.view_mesh(ball, hat, cmap="Reds", edges=True, height=380,
                title=f"the hat function phi_{j} on an icosphere")


# %% [markdown]
# ## Deriving Eq. (3)-(5) from the hat functions
#
# **Step 1: the weak form.** Multiply $\Delta f = -\lambda f$ by a hat $\varphi_i$ and integrate over the closed
# surface $\mathcal M$. Integration by parts (Green's identity; on a closed surface there is no boundary term, and
# with a boundary the Neumann condition $\partial f/\partial n = 0$ removes it) moves one derivative onto $\varphi_i$:
#
# $$-\int_{\mathcal M} \nabla f\cdot\nabla\varphi_i \,dA = -\lambda \int_{\mathcal M} f\,\varphi_i \,dA .$$
#
# Put $f = \sum_j f_j \varphi_j$ in and read off a matrix equation $A f = -\lambda B f$ with
#
# $$a_{ij} = -\int_{\mathcal M} \nabla\varphi_i\cdot\nabla\varphi_j\,dA, \qquad
#   b_{ij} = \int_{\mathcal M} \varphi_i\,\varphi_j\,dA .$$
#
# Both integrals vanish unless $v_i$ and $v_j$ share a triangle: that is why $A$ and $B$ are sparse, with one
# entry per edge. Each integral is a sum over triangles, so we need them on **one triangle** $t$ with corners
# $p_i, p_j, p_k$ (counter-clockwise about its unit normal $n$) and area $|t|$.
#
# **Step 2: the gradient of a hat.** On $t$, $\varphi_i$ is linear, 1 at $p_i$ and 0 along the opposite edge
# $e_i = p_k - p_j$. So its gradient is constant, lies in the plane of $t$, is perpendicular to $e_i$ (the hat does
# not change along that edge) and points towards $p_i$. It rises by 1 over the height $h_i = 2|t| / |e_i|$ of
# $p_i$ above $e_i$, so $|\nabla\varphi_i| = 1/h_i = |e_i| / (2|t|)$. Rotating $e_i$ by $90°$ in the plane gives
# exactly that direction:
#
# $$\nabla\varphi_i = \frac{n \times e_i}{2|t|}, \qquad e_i = p_k - p_j .$$
#
# The three hats add up to 1 on $t$ (they are its barycentric coordinates), so $\nabla\varphi_i + \nabla\varphi_j
# + \nabla\varphi_k = 0$, and indeed $e_i + e_j + e_k = 0$.
#
# **Step 3: one triangle's share of $a_{ij}$.** The gradients are constant, so the integral is the area times a
# dot product. A rotation about $n$ keeps dot products, so $(n\times e_i)\cdot(n\times e_j) = e_i\cdot e_j$ and
#
# $$\int_t \nabla\varphi_i\cdot\nabla\varphi_j\,dA = |t|\,\frac{e_i\cdot e_j}{4|t|^2} = \frac{e_i\cdot e_j}{4|t|}.$$
#
# Now $e_i = p_k - p_j$ and $e_j = p_i - p_k$ both touch the corner $p_k$ *opposite* the edge $v_iv_j$, whose
# angle we call $\gamma$. With $u = p_i - p_k$ and $w = p_j - p_k$, $e_i\cdot e_j = -u\cdot w = -|u||w|\cos\gamma$,
# and $2|t| = |u||w|\sin\gamma$. Hence
#
# $$\int_t \nabla\varphi_i\cdot\nabla\varphi_j\,dA = -\frac{|u||w|\cos\gamma}{2\,|u||w|\sin\gamma} = -\frac{\cot\gamma}{2}.$$
#
# **Step 4: the edge.** An inner edge has two triangles, with opposite angles $\alpha_{ij}$ and $\beta_{ij}$:
#
# $$\int_{\mathcal M}\nabla\varphi_i\cdot\nabla\varphi_j\,dA = -\frac{\cot\alpha_{ij} + \cot\beta_{ij}}{2},
#   \qquad a_{ij} = \frac{\cot\alpha_{ij} + \cot\beta_{ij}}{2}.$$
#
# A boundary edge has one term, a non-manifold edge three or more (Eq. 6). The diagonal needs no new integral:
# the hats add up to 1 everywhere, so $\sum_j \nabla\varphi_j = 0$ and every row of $A$ sums to zero,
# $a_{ii} = -\sum_{j \ne i} a_{ij}$.
#
# Let us check steps 2 and 3 on one triangle of the tent.

# %%
p = V[F[0]]  # the corners p_0, p_1, p_2 of the first triangle (local names 0, 1, 2)
normal = np.cross(p[1] - p[0], p[2] - p[0])
area_t = np.linalg.norm(normal) / 2
normal /= 2 * area_t
edges = [p[2] - p[1], p[0] - p[2], p[1] - p[0]]  # e_i, the edge opposite corner i
grads = [np.cross(normal, e) / (2 * area_t) for e in edges]
print("grad phi_i . (p_i - p_j) = 1 (the hat rises by 1 from p_j to p_i):",
      np.array([grads[i] @ (p[i] - p[(i + 1) % 3]) for i in range(3)]))
print("sum of the three gradients:", np.sum(grads, axis=0))
u, w = p[0] - p[2], p[1] - p[2]  # the corner p_2 is opposite the edge (p_0, p_1)
gamma = np.arccos(u @ w / np.linalg.norm(u) / np.linalg.norm(w))
print(f"|t| grad phi_0 . grad phi_1 = {area_t * grads[0] @ grads[1]:.6f},"
      f"  -cot(gamma)/2 = {-0.5 / np.tan(gamma):.6f}")

# %% [markdown]
# **Step 5: the mass entries.** On $t$ the three hats are the barycentric coordinates. The affine map from the
# reference triangle $\hat t = \{(x, y): x, y \ge 0,\ x + y \le 1\}$ to $t$ sends $\varphi_i, \varphi_j$ to $x, y$ and
# multiplies areas by $2|t|$ (the area of $\hat t$ is $\tfrac12$). So
#
# $$\int_t \varphi_i\varphi_j\,dA = 2|t|\int_0^1\!\!\int_0^{1-x} x\,y\,dy\,dx = 2|t|\int_0^1 \frac{x(1-x)^2}{2}dx
#   = 2|t|\cdot\frac{1}{24} = \frac{|t|}{12},$$
#
# $$\int_t \varphi_i^2\,dA = 2|t|\int_0^1\!\!\int_0^{1-x} x^2\,dy\,dx = 2|t|\int_0^1 x^2(1-x)\,dx
#   = 2|t|\cdot\frac{1}{12} = \frac{|t|}{6}.$$
#
# (Both are cases of $\int_t \varphi_i^a\varphi_j^b\varphi_k^c\,dA = 2|t|\,\frac{a!\,b!\,c!}{(a+b+c+2)!}$.)
# Check: the 3 diagonal and 6 off-diagonal shares of one triangle add up to $3\cdot\tfrac{|t|}{6} +
# 6\cdot\tfrac{|t|}{12} = |t|$, as $\int_t (\sum_i\varphi_i)^2 = \int_t 1$ demands. Summed over the triangles at an
# edge and at a vertex this is Eq. (5): $b_{ij} = (|t_1| + |t_2|)/12$, $b_{ii} = \sum_{t\ni v_i} |t|/6$.
#
# The two integrals, checked numerically on the reference triangle (`scipy.integrate.dblquad` integrates over
# $y$ from 0 to $1-x$, then over $x$):

# %%
from scipy.integrate import dblquad

xy = dblquad(lambda y, x: x * y, 0, 1, 0, lambda x: 1 - x)[0]
xx = dblquad(lambda y, x: x * x, 0, 1, 0, lambda x: 1 - x)[0]
print(f"int x y  over the reference triangle: {xy:.6f}   (1/24 = {1 / 24:.6f})")
print(f"int x^2  over the reference triangle: {xx:.6f}   (1/12 = {1 / 12:.6f})")


# %% [markdown]
# ## Exercise 1 (graded): assemble $B$ yourself, Eq. (5)/(7)
#
# Write `mass_matrix(V, F)` returning the dense consistent mass matrix $B$ of Step 5, shape `(n, n)` for
# `n = len(V)` vertices and the triangles `F` (one row of three vertex indices each).

# %% nbgrader={"grade": false, "grade_id": "mass_matrix", "locked": false, "schema_version": 3, "solution": true, "task": false}
def mass_matrix(V, F):
    """Consistent mass matrix B of Eq. (5)/(7), dense (n, n), positive definite."""
    ### BEGIN SOLUTION
    n = len(V)
    B = np.zeros((n, n))
    for tri in F:
        p = V[tri]
        area = 0.5 * np.linalg.norm(np.cross(p[1] - p[0], p[2] - p[0]))
        for a in range(3):
            for b in range(3):
                B[tri[a], tri[b]] += area / 6 if a == b else area / 12
    return B
    ### END SOLUTION


# %% nbgrader={"grade": true, "grade_id": "test_mass_matrix", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
A_ref, B_ref = cshape.fem_matrices(tent)
B_mine = mass_matrix(V, F)
if not np.isclose(np.sum(B_mine), tent.area):
    print(f"hint: the entries of B must add up to the surface area {tent.area:.4f}, "
          f"yours add up to {np.sum(B_mine):.4f}")
if np.any(np.diag(B_mine) <= 0):
    print("hint: the diagonal of B is +sum |t|/6 (the minus sign printed in Eq. 5 is a typo)")
if np.allclose(B_mine, np.diag(np.asarray(B_ref.sum(axis=1)).ravel())):
    print("hint: this is the lumped mass matrix (each row summed onto the diagonal); "
          "Eq. (5) is the consistent one, with |t|/12 on the edges")
check_close("B", B_mine, B_ref, hint="Each triangle adds |t|/12 per edge entry, |t|/6 per corner.")

# %% nbgrader={"grade": true, "grade_id": "hidden_mass_matrix", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
# hidden tests: the autograder runs more checks here
### BEGIN HIDDEN TESTS
_ico = shapes.icosphere(1)
check_close("mass_matrix(icosphere(1))", mass_matrix(_ico.vertices, _ico.faces),
            cshape.fem_matrices(_ico)[1])
_sq = shapes.square(3)
check_close("mass_matrix(square(3))", mass_matrix(_sq.vertices, _sq.faces),
            cshape.fem_matrices(_sq)[1])
### END HIDDEN TESTS

# %% [markdown]
# ## Exercise 2 (graded): assemble $A$ yourself, Eq. (4)/(6)
#
# Write `stiffness_matrix(V, F)`, the dense stiffness matrix $A$ of Steps 3-4, shape `(n, n)`, with the sign of the
# paper ($A$ negative semidefinite). Build it from the triangles' angles, without `cshape.fem_matrices` (the check
# uses it as the reference). Tip: the cotangent of the angle between two vectors $u, w$ leaving a corner is
# $u\cdot w / \lVert u\times w\rVert$.

# %% nbgrader={"grade": false, "grade_id": "stiffness_matrix", "locked": false, "schema_version": 3, "solution": true, "task": false}
def stiffness_matrix(V, F):
    """Cotangent stiffness matrix A of Eq. (4)/(6), dense (n, n), negative semidefinite."""
    ### BEGIN SOLUTION
    n = len(V)
    A = np.zeros((n, n))
    for tri in F:
        for c in range(3):  # corner c, opposite edge (i, j)
            i, j = tri[(c + 1) % 3], tri[(c + 2) % 3]
            u, w = V[i] - V[tri[c]], V[j] - V[tri[c]]
            cot = (u @ w) / np.linalg.norm(np.cross(u, w))
            A[i, j] += cot / 2
            A[j, i] += cot / 2
    A[np.diag_indices(n)] = -A.sum(axis=1)  # zero row sums
    return A
    ### END SOLUTION


# %% nbgrader={"grade": true, "grade_id": "test_stiffness_matrix", "locked": true, "points": 2, "schema_version": 3, "solution": false, "task": false}
def stiffness_hints(A_got, A_want):
    """Name the typical mistake behind a wrong stiffness matrix (prints hints, returns nothing)."""
    A_got = np.asarray(A_got, dtype=float)
    A_want = np.asarray(A_want.toarray() if hasattr(A_want, "toarray") else A_want, dtype=float)
    if A_got.shape != A_want.shape:
        return
    off = ~np.eye(len(A_want), dtype=bool)
    if not np.allclose(A_got, A_got.T):
        print("hint: A is not symmetric: each cotangent belongs to both entries (i, j) and (j, i)")
    if np.allclose(A_got, -A_want):
        print("hint: wrong sign: with the paper's sign a_ij = +(cot a + cot b)/2 on an edge and the diagonal "
              "is negative (A is negative semidefinite); you built -A")
    elif np.allclose(A_got[off], 2 * A_want[off]):
        print("hint: your edge entries are twice too large: a triangle adds cot/2, not cot")
    elif np.allclose(A_got[off], 0.5 * A_want[off]):
        print("hint: your edge entries are half of what they should be: did you add only one of the two "
              "triangles at an edge, or divide by 2 twice?")
    if np.allclose(A_got[off], A_want[off]) and not np.allclose(np.diag(A_got), np.diag(A_want)):
        print("hint: the edge entries are right but the diagonal is not: a_ii is minus the sum of the "
              "other entries of row i (the rows sum to zero)")
    elif not np.allclose(A_got.sum(axis=1), 0):
        print("hint: the rows of A must sum to zero (the hats add up to 1, so constants are in the "
              "null space): set a_ii to minus the sum of the row's other entries")
    elif np.allclose(A_got, A_got.T) and not np.allclose(A_got, A_want):
        print("hint: symmetric with zero row sums, but the weights differ: is each one the cotangent of "
              "the angle OPPOSITE the edge (at the third corner of the triangle), not at v_i or v_j?")


A_mine = stiffness_matrix(V, F)
stiffness_hints(A_mine, A_ref)
check_close("A", A_mine, A_ref, hint="a_ij = (cot alpha + cot beta)/2, a_ii = -sum_j a_ij.")

# %% nbgrader={"grade": true, "grade_id": "hidden_stiffness_matrix", "locked": true, "points": 2, "schema_version": 3, "solution": false, "task": false}
# hidden tests: the autograder runs more checks here
### BEGIN HIDDEN TESTS
_rng = np.random.default_rng(7)
_bump = shapes.icosphere(1)
_Vb = _bump.vertices * (1 + 0.15 * _rng.standard_normal((_bump.n_vertices, 1)))  # no two angles alike
_Ab = cshape.fem_matrices(cshape.Mesh(_Vb, _bump.faces))[0].toarray()


def _wrong_angle(V, F):
    """The cotangent of the angle at an end of the edge, not of the opposite corner."""
    n = len(V)
    A = np.zeros((n, n))
    for tri in F:
        for c in range(3):
            i, j = tri[(c + 1) % 3], tri[(c + 2) % 3]
            u, w = V[j] - V[i], V[tri[c]] - V[i]  # the angle at v_i
            cot = (u @ w) / np.linalg.norm(np.cross(u, w))
            A[i, j] += cot / 2
            A[j, i] += cot / 2
    A[np.diag_indices(n)] = -A.sum(axis=1)
    return A


_fem = cshape.fem_matrices
cshape.fem_matrices = None  # the reference may not be called by the answer
try:
    _got = stiffness_matrix(_Vb, _bump.faces)
except TypeError as _err:
    raise AssertionError("build A from the cotangent weights, not with cshape.fem_matrices") from _err
finally:
    cshape.fem_matrices = _fem
if np.allclose(_got, _wrong_angle(_Vb, _bump.faces)):
    raise AssertionError("cot of the wrong angle: the weight of the edge v_i v_j uses the angle of the "
                         "corner OPPOSITE the edge, not an angle at v_i or v_j")
stiffness_hints(_got, _Ab)
check_close("stiffness_matrix(perturbed icosphere)", _got, _Ab)
_sq = shapes.square(3)  # a boundary: the boundary edges have one triangle
check_close("stiffness_matrix(square(3))", stiffness_matrix(_sq.vertices, _sq.faces),
            cshape.fem_matrices(_sq)[0])
### END HIDDEN TESTS

# %% [markdown] nbgrader={"grade": false, "grade_id": "row_sums_question", "locked": true, "schema_version": 3, "solution": false, "task": false}
# ## Exercise 3 (written, graded by hand): why the rows of $A$ sum to zero
#
# In the answer cell below, in your own words and a few formulas (5-10 lines): why does every row of $A$ sum to
# zero *without* using the rule $a_{ii} = -\sum_j a_{ij}$, i.e. from the hat functions? What does this say about
# the smallest eigenvalue $\lambda_0$ and its eigenfunction on a closed mesh, and why is it no longer so with
# Dirichlet conditions (Section 2.2)?

# %% [markdown] nbgrader={"grade": true, "grade_id": "row_sums_answer", "locked": false, "points": 2, "schema_version": 3, "solution": true, "task": false}
# ### BEGIN SOLUTION
# The hats form a partition of unity: $\sum_j \varphi_j = 1$ on every triangle (they are its barycentric
# coordinates). Hence $\sum_j \nabla\varphi_j = 0$ and
# $\sum_j a_{ij} = -\int \nabla\varphi_i\cdot\nabla\big(\sum_j\varphi_j\big)\,dA = -\int\nabla\varphi_i\cdot\nabla 1\,dA
# = 0$. In matrix form $A\mathbf 1 = 0$: the constant vector is in the null space of $A$, so $A\mathbf 1 = -0\cdot
# B\mathbf 1$ and $\lambda_0 = 0$ with a constant eigenfunction (the continuous fact: $\Delta 1 = 0$). On a mesh
# of $c$ separate pieces, each piece's constant gives a zero eigenvalue. With Dirichlet conditions the boundary
# values are fixed to 0 and their rows and columns are removed, so the rows of inner vertices next to the
# boundary no longer sum to zero. The constant is not admissible (it does not vanish on the boundary), and for
# any other $f$ that vanishes there $f^T A f = -\int|\nabla f|^2\,dA < 0$: $A$ is negative definite and
# $\lambda_0 > 0$.
# ### END SOLUTION

# %% [markdown]
# Both matrices of the tent, yours: the edge entries of $A$ hold the cotangent weights, the diagonal makes the rows
# sum to zero; $B$ holds $|t|/12$ per triangle on the edges and $|t|/6$ on the diagonal.

# %%
print("A =\n", A_mine, "\nrow sums of A:", A_mine.sum(axis=1))
print("B =\n", B_mine, "\nsum of B:", B_mine.sum(), " area:", tent.area)


# %% [markdown]
# ## Properties to check on any mesh
#
# `cshape.fem_matrices` assembles the same matrices for a whole mesh at once (sparse). Whatever the mesh,
# $A$ and $B$ are symmetric, $A$'s rows sum to zero (constants are in its null space), $B$'s entries add up to the
# area, $A \preceq 0$ and $B \succ 0$.

# %%
mesh = shapes.icosphere(size(2, 3))
A, B = cshape.fem_matrices(mesh)
Ad, Bd = A.toarray(), B.toarray()
print("vertices:", mesh.n_vertices)
print("A symmetric:", np.allclose(Ad, Ad.T), "  B symmetric:", np.allclose(Bd, Bd.T))
print("largest |row sum| of A:", np.abs(Ad.sum(axis=1)).max())
print("sum of B:", Bd.sum(), "  area:", mesh.area, "  (4 pi =", 4 * np.pi, ")")
print("largest eigenvalue of A (<= 0):", np.linalg.eigvalsh(Ad).max())
print("smallest eigenvalue of B (> 0):", np.linalg.eigvalsh(Bd).min())

# %% [markdown]
# ## The eigenproblem, Eq. (3)
#
# With $K = -A$ the problem $A f = -\lambda B f$ is the symmetric-definite problem $K f = \lambda B f$, which
# `scipy.linalg.eigh` solves directly for a small mesh. `cshape.eigenbasis` does the same (densely for small
# meshes, by shift-invert Lanczos for large ones) and returns the eigenvalues `lam` and the $B$-orthonormal
# eigenfunctions `phi`, one per column.

# %%
import scipy.linalg as la

lam_dense = la.eigh(-Ad, Bd, eigvals_only=True)[:10]
basis = cshape.eigenbasis(mesh, N=10)
lam, phi = basis.lam, basis.phi
print("scipy.linalg.eigh:", lam_dense)
print("cshape.eigenbasis:", lam)
print("exact, unit sphere:", shapes.sphere_spectrum(10))
print("phi is B-orthonormal:", np.allclose(phi.T @ B @ phi, np.eye(10)))

# %% [markdown]
# The eigenfunctions of the sphere are the spherical harmonics: three of degree 1 ($\lambda \approx 2$), five of
# degree 2 ($\lambda \approx 6$). Red and blue are the two signs (the sign of an eigenfunction is arbitrary).

# %%
plots.plot_eigenfunctions(mesh, phi, range(1, 9), lam)


# %% [markdown]
# ## Neumann versus Dirichlet (Section 2.2)
#
# On a mesh with a boundary, **Neumann** conditions keep every vertex as an unknown (Eq. 6-7: boundary edges have one
# triangle), while **Dirichlet** conditions fix $f = 0$ on the boundary and non-manifold vertices and keep only the
# inner ones. The unit hemisphere has exact spectra: the degree-$\ell$ spherical harmonics $Y_\ell^m$ whose
# $\ell + m$ is even (Neumann) or odd (Dirichlet), each with eigenvalue $\ell(\ell+1)$.

# %%
def hemisphere_spectrum(N, bc):
    out, ell = [], 0
    while len(out) < N:
        parity = 0 if bc == "neumann" else 1
        count = sum(1 for m in range(-ell, ell + 1) if (ell + m) % 2 == parity)
        out += [ell * (ell + 1)] * count
        ell += 1
    return np.array(out[:N], dtype=float)


hemi = shapes.hemisphere(size(8, 24))
N = 12
for bc in ("neumann", "dirichlet"):
    A_bc, _ = cshape.fem_matrices(hemi, bc=bc)
    lam_bc = cshape.shape_dna(hemi, N, bc=bc)
    print(f"{bc:9s}: {A_bc.shape[0]} unknowns;  computed", lam_bc.round(2))
    print(f"{'':9s}  exact                     ", hemisphere_spectrum(N, bc))

# %%
basis_n = cshape.eigenbasis(hemi, 4, bc="neumann")
basis_d = cshape.eigenbasis(hemi, 4, bc="dirichlet")
lam_n, phi_n, lam_d, phi_d = basis_n.lam, basis_n.phi, basis_d.lam, basis_d.phi
fig = plots.new_figure((10, 3.2))
for k, (f, t) in enumerate([(phi_n[:, 1], f"Neumann phi_1, lam={lam_n[1]:.2f}"),
                            (phi_n[:, 3], f"Neumann phi_3, lam={lam_n[3]:.2f}"),
                            (phi_d[:, 0], f"Dirichlet phi_0, lam={lam_d[0]:.2f}"),
                            (phi_d[:, 1], f"Dirichlet phi_1, lam={lam_d[1]:.2f}")]):
    plots.plot_mesh(hemi, f, ax=fig.add_subplot(1, 4, k + 1, projection="3d"), elev=35, title=t)
fig

# %% [markdown]
# Dirichlet eigenfunctions vanish on the rim (white there); Neumann ones meet the rim at a right angle and
# take any value on it.
#
# ## Convergence on the sphere: predict, then check
#
# Each level of the icosphere splits every triangle into four, which halves the mesh size $h$ (the mean edge length,
# printed below). With linear elements the *gradient* of an eigenfunction is approximated with an error of order
# $h$. An eigenvalue is a Rayleigh quotient, $\lambda = \int|\nabla f|^2 / \int f^2$, which is stationary at an
# eigenfunction: an error $\varepsilon$ in the function changes it only by $O(\varepsilon^2)$.
#
# **Predict** before you run the study: by what factor does the largest relative error of
# $\lambda_1, \dots, \lambda_{15}$ shrink from one level to the next (old error / new error)? Write it in the cell
# below as `prediction = ...` (one number).

# %% nbgrader={"grade": false, "grade_id": "convergence_prediction", "locked": false, "schema_version": 3, "solution": true, "task": false}
### BEGIN SOLUTION
prediction = 4.0  # the error is of order h^2: halving h divides it by 2^2
### END SOLUTION

# %%
levels = size([1, 2, 3], [1, 2, 3, 4, 5])
N = 16  # lam_0 .. lam_15: the harmonics of degree 0 to 3
exact = shapes.sphere_spectrum(N)
h, errors = [], []
for s in levels:
    m = shapes.icosphere(s)
    lam_s = cshape.shape_dna(m, N)
    h.append(m.mean_edge_length)
    errors.append(np.abs(lam_s[1:] - exact[1:]) / exact[1:])
    print(f"level {s}: {m.n_vertices:6d} vertices, h = {h[-1]:.4f}, "
          f"max relative error {errors[-1].max():.2e}")
errors = np.array(errors).T  # one row per eigenvalue
rows = [0, 3, 8]  # lam_1 (l=1), lam_4 (l=2), lam_9 (l=3)
plots.plot_convergence(h, errors[rows], labels=["lam_1 (l=1)", "lam_4 (l=2)", "lam_9 (l=3)"])

# %%
factors = errors.max(axis=0)[:-1] / errors.max(axis=0)[1:]
print("the largest error shrinks, level by level, by the factors", factors.round(2))

# %% nbgrader={"grade": true, "grade_id": "test_convergence_prediction", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
assert np.isscalar(prediction) and np.isfinite(prediction), "prediction is one number, e.g. 3.0"
### BEGIN HIDDEN TESTS
assert prediction > 1, (
    f"you predicted {prediction}: the factor is old error / new error, larger than 1 as the mesh is refined")
assert abs(prediction - factors[-1]) < 1, (
    f"you predicted {prediction}, the measured factor is {factors[-1]:.2f}. An error of order h falls by 2 "
    "when h halves; the eigenvalue error is the square of the gradient error, of order h^2, so it falls by 4")
### END HIDDEN TESTS

# %%
orders = np.log(errors[:, :-1] / errors[:, 1:]) / np.log(np.array(h[:-1]) / np.array(h[1:]))
print("observed order between levels (mean over 15 eigenvalues):", orders.mean(axis=0))

# %% [markdown]
# ## The upper spectrum drifts, and how to fix it
#
# The error of linear elements is not the same for every eigenvalue: it grows like $h^2 \lambda_i^2$, so the
# *relative* error grows like $h^2 \lambda_i$. On a coarse mesh the first eigenvalues are fine, while the upper
# half of a Shape-DNA of $N = 100$ values describes the triangulation about as much as the shape. The same
# object meshed twice then disagrees in exactly the values a descriptor of the whole spectrum uses.
#
# Since the error is $C_i h^2$, one more solve removes it. Split every triangle into four at its edge midpoints
# (the triangles stay flat, $h$ halves) and solve again: $\lambda_i^{h/2} \approx \lambda_i + C_i h^2 / 4$.
# Richardson extrapolation eliminates $C_i$:
#
# $$\lambda_i^{\mathrm{ex}} = \frac{4 \lambda_i^{h/2} - \lambda_i^{h}}{3}.$$
#
# `cshape.shape_dna(mesh, N, refine="extrapolate")` does exactly this. Both solves use Eq. (3)-(7) unchanged.

# %%
coarse = shapes.icosphere(size(2, 3))
N = size(49, 100)  # the harmonics of degree 0 to 6 (small) or 9
exact = shapes.sphere_spectrum(N)
lam_lin = cshape.shape_dna(coarse, N)
lam_ex = cshape.shape_dna(coarse, N, refine="extrapolate")
i = np.arange(1, N)
fig = plots.new_figure((7, 3.4))
ax = fig.add_subplot(1, 1, 1)
ax.semilogy(i, np.abs(lam_lin[1:] / exact[1:] - 1), ".", label="linear FEM, $\\lambda_i^h$")
ax.semilogy(i, np.abs(lam_ex[1:] / exact[1:] - 1), ".", label="extrapolated, $\\lambda_i^{\\mathrm{ex}}$")
ax.set_xlabel("index $i$")
ax.set_ylabel("relative error against $\\ell(\\ell+1)$")
ax.set_title(f"unit icosphere, {coarse.n_vertices} vertices")
ax.legend()
fig

# %%
print(f"largest relative error of lam_1 .. lam_{N - 1}: linear {np.abs(lam_lin[1:] / exact[1:] - 1).max():.2%},"
      f" extrapolated {np.abs(lam_ex[1:] / exact[1:] - 1).max():.2%}")

# %% [markdown]
# The linear error climbs with the index; the extrapolated one stays flat and small. Every repeated eigenvalue
# $\ell(\ell+1)$ keeps its $2\ell+1$ copies: the eigenvalues of the two meshes are paired by their index, and the
# min-max principle orders both lists alike (the linear functions of the coarse mesh are linear functions of the
# subdivided one too, so $\lambda_i^{h/2} \le \lambda_i^{h}$ for every $i$).
#
# **What it converges to.** The subdivided mesh keeps the flat triangles, so both solves discretise the same
# *polyhedron*, and the extrapolated spectrum converges to the polyhedron's spectrum. A curved surface differs from
# its polyhedron by $O(h^2)$ in the metric: a small error that does not grow with $\lambda_i$. That is what remains
# on the sphere:

# %%
for s in levels[:-1] if SMALL else levels[1:-1]:
    m = shapes.icosphere(s)
    e_lin = np.abs(cshape.shape_dna(m, 16)[1:] / exact[1:16] - 1).max()
    e_ex = np.abs(cshape.shape_dna(m, 16, refine="extrapolate")[1:] / exact[1:16] - 1).max()
    print(f"level {s}: {m.n_vertices:5d} vertices, lam_1..lam_15: linear {e_lin:.2e}, extrapolated {e_ex:.2e}")

# %% [markdown]
# The price is a second eigensolve on four times the triangles (several times the time of the first:
# `benchmarks/results/refine.md`). On a flat domain, where the polyhedron *is* the domain, the extrapolated
# error falls like $h^4$ (exercise 6).

# %% [markdown]
# ## The same repair at no cost: the mixed mass matrix
#
# Predict first: do the sphere's computed eigenvalues lie above or below the exact $\ell(\ell+1)$? The min-max
# principle answers for the consistent mass matrix of Eq. (5): the linear functions are a subspace of all
# functions, so every $\lambda_i^h \ge \lambda_i$, too high by about $h^2 \lambda_i^2$.
#
# The **lumped** mass matrix puts each triangle's mass on the diagonal, $|t|/3$ per corner. On one triangle,
# lumped minus consistent is
#
# $$\frac{|t|}{3} I - \frac{|t|}{12}\begin{pmatrix}2&1&1\\1&2&1\\1&1&2\end{pmatrix}
#   = \frac{|t|}{12}\begin{pmatrix}2&-1&-1\\-1&2&-1\\-1&-1&2\end{pmatrix},$$
#
# a graph Laplacian: positive semidefinite. More mass in the Rayleigh quotient's denominator lowers every
# eigenvalue, by about as much as the consistent matrix raised it. Their average, `mass="mixed"`,
# $B = (B_{\mathrm{consistent}} + B_{\mathrm{lumped}})/2$ ($|t|/4$ on the diagonal, $|t|/24$ off it), cancels
# the leading term, with the same sparsity and the same cost as one plain solve.

# %%
sphere = shapes.icosphere(size(2, 3))
N_mix = size(49, 100)
exact_mix = shapes.sphere_spectrum(N_mix)
i = np.arange(1, N_mix)
fig = plots.new_figure((7, 3.4))
ax = fig.add_subplot(1, 1, 1)
for mass in ("consistent", "lumped", "mixed"):
    err = cshape.shape_dna(sphere, N_mix, mass=mass)[1:] / exact_mix[1:] - 1
    ax.plot(i, 100 * err, ".", label=f"{mass}: worst {100 * np.abs(err).max():.2f} %")
ax.axhline(0, color="k", lw=0.5)
ax.set_xlabel("index $i$")
ax.set_ylabel("relative error of $\\lambda_i$ (%)")
ax.set_title(f"unit icosphere, {sphere.n_vertices} vertices")
ax.legend()
fig

# %% [markdown]
# The consistent matrix errs upwards, the lumped one downwards, the mixed one stays near zero over the whole
# spectrum (the legend prints the worst error of each). Extrapolation is more accurate still, at several times
# the cost; the resolution guide (`docs/guides/resolution-free-spectra.md`) compares the two. The paper's
# functions keep Eq. (5) by default.

# %% [markdown]
# ## Exercises
#
# 1. *(graded above)* Assemble $B$ and $A$ yourself, explain the zero row sums, predict the convergence factor.
# 2. **Lumped mass.** Repeat the convergence study with `cshape.shape_dna(m, N, mass="lumped")`. Does the lumped
#    spectrum approach the exact one from above or from below? Is the order still 2?
# 3. **The square.** `shapes.square(n)` is the unit square. Its Dirichlet eigenvalues are
#    $\pi^2(m^2 + n^2)$ with $m, n \geq 1$, the Neumann ones the same with $m, n \geq 0$. Check both for
#    `n = 8, 16, 32`.
# 4. **Components.** Build a mesh of two separate icospheres (stack the vertex arrays, offset the second
#    face array). How many zero eigenvalues does it have, and why? (cshape warns you.)
# 5. **Why the typo matters.** Flip the sign of the diagonal of your `mass_matrix`. What happens to the
#    eigenvalues, and which property of $B$ breaks?
# 6. **Order four.** Repeat exercise 3 with `refine="extrapolate"` (Dirichlet, the first 10 eigenvalues) and
#    measure the order. Then do it on the equilateral triangle of side 1, refined by splitting every triangle
#    into four (its Dirichlet eigenvalues: $\tfrac{16\pi^2}{9}(m^2 + mn + n^2)$, $m, n \ge 1$). Why is the order
#    four on the triangle but lower on the square, whose cells alternate their diagonals?
# 7. **Obtuse angles.** Move the apex of the tent sideways until one triangle has an angle above $90°$. Which entry
#    of $A$ changes sign? Is $A$ still negative semidefinite, and do its rows still sum to zero? (Use Steps 3-4.)
#
# ## References
#
# - Gao, Yu and Pang (2014). A compact shape descriptor for triangular surface meshes. *Computer-Aided Design* 53,
#   62-69. (Section 2.1-2.2, Eq. 3-7.)
# - Reuter, Wolter and Peinecke (2006). Laplace-Beltrami spectra as "Shape-DNA" of surfaces and solids.
#   *Computer-Aided Design* 38(4), 342-366. (The finite element method behind Eq. 3-7, linear and cubic elements.)
# - Reuter, Biasotti, Giorgi, Patanè and Spagnuolo (2009). Discrete Laplace-Beltrami operators for shape analysis
#   and segmentation. *Computers & Graphics* 33(3), 381-390. (The cotangent, lumped and consistent forms compared.)
# - Pinkall and Polthier (1993). Computing discrete minimal surfaces and their conjugates. *Experimental
#   Mathematics* 2(1), 15-36. (The cotangent formula.)
# - Crane (2023). *Discrete Differential Geometry: An Applied Introduction*, course notes, Carnegie Mellon
#   University, the chapter on the Laplace-Beltrami operator; and its exercises, GeometryCollective/ddg-exercises.
# - Strang and Fix (1973). *An Analysis of the Finite Element Method*, Prentice-Hall, chapter 6 (eigenvalue
#   errors of order $h^{2}$ for linear elements).
