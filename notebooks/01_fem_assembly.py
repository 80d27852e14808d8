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
# 1. assemble the stiffness matrix $A$ (Eq. 4) and the mass matrix $B$ (Eq. 5) of a triangle mesh by hand;
# 2. check them: symmetry, zero row sums of $A$, entries of $B$ adding up to the area, the signs;
# 3. solve the generalised eigenproblem $A f = -\lambda B f$ (Eq. 3) and read its eigenvalues;
# 4. tell Neumann from Dirichlet boundary conditions (Section 2.2) on a mesh with a boundary;
# 5. measure how the computed spectrum of the sphere approaches the exact one, $\ell(\ell+1)$, as the mesh is refined.
# 6. see why the upper eigenvalues of a coarse mesh drift, and remove the drift by Richardson extrapolation.
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
        idx = tuple(bad[0])
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
# triangle, so it lives on the triangles around $v_j$ only. $a_{ij}$ and $b_{ij}$ integrate products of two hats
# (their gradients for $A$): they vanish unless $v_i$ and $v_j$ share a triangle, which is why $A$ and $B$ are
# sparse, with one entry per edge. Below, one hat on a coarse sphere: drag to rotate it, scroll to zoom.

# %%
ball = shapes.icosphere(1)
eye = plots.viewer.default_eye(ball.vertices)  # where the view below looks from
j = int(np.argmax(ball.vertices @ [eye["x"], eye["y"], eye["z"]]))  # the vertex facing the camera
hat = np.zeros(ball.n_vertices)
hat[j] = 1.0  # phi_j: 1 at v_j, 0 at the other vertices, linear in between
plots.view_mesh(ball, hat, cmap="Reds", edges=True, height=380,
                title=f"the hat function phi_{j} on an icosphere")


# %% [markdown]
# ## The stiffness matrix $A$, Eq. (4), by hand
#
# For the angle at corner $c$ of a triangle with edge vectors $u, w$ leaving $c$,
# $\cot\theta = \dfrac{u\cdot w}{\lVert u \times w\rVert}$. Each triangle adds $\cot\theta/2$ to the entry of the
# edge *opposite* that corner, and the diagonal makes every row sum to zero.

# %%
def stiffness_matrix(V, F):
    """Cotangent stiffness matrix A of Eq. (4)/(6), dense (n, n), negative semidefinite."""
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


A_mine = stiffness_matrix(V, F)
A_mine


# %% [markdown]
# ## Exercise 1 (graded): assemble $B$ yourself, Eq. (5)/(7)
#
# Write `mass_matrix(V, F)` returning the dense consistent mass matrix: every triangle $t$ adds $|t|/12$ to the
# entries of its three edges (both $(i, j)$ and $(j, i)$) and $|t|/6$ to the diagonal entry of each of its three
# corners. $|t| = \tfrac12 \lVert (p_1 - p_0) \times (p_2 - p_0)\rVert$.

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
check_close("B", B_mine, B_ref, hint="Each triangle adds |t|/12 per edge entry, |t|/6 per corner.")
check_close("A", A_mine, A_ref)

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
# `scipy.linalg.eigh` solves directly for a small mesh. `cshape.eigenpairs` does the same (densely for small
# meshes, by shift-invert Lanczos for large ones) and returns $B$-orthonormal eigenfunctions.

# %%
import scipy.linalg as la

lam_dense = la.eigh(-Ad, Bd, eigvals_only=True)[:10]
lam, phi = cshape.eigenpairs(mesh, N=10)
print("scipy.linalg.eigh:", lam_dense)
print("cshape.eigenpairs:", lam)
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
lam_n, phi_n = cshape.eigenpairs(hemi, 4, bc="neumann")
lam_d, phi_d = cshape.eigenpairs(hemi, 4, bc="dirichlet")
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
# ## Convergence on the sphere
#
# Linear elements converge with order 2 in the mesh size $h$ for eigenvalues: halving the edge length should
# divide the error by about four. Each level of the icosphere halves $h$.

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
# ## Exercises
#
# 1. *(graded above)* Assemble $B$ yourself.
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
