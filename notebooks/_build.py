# ruff: noqa: E501  (the cell texts below are markdown and notebook code, wrapped for reading)
"""Write the walkthrough notebooks ``notebooks/NN_topic.ipynb`` from the cell texts below.

The ``.ipynb`` files are the committed source of truth that users open; this script is the
convenient way to edit them in bulk (plain text diffs, no outputs, stable cell ids).  After
editing, run::

    python notebooks/_build.py            # rewrite the notebooks
    python -m cshape assignments          # regenerate notebooks/student/

Editing a notebook in Jupyter instead is fine too: then keep this file in step (the test
suite does not compare them) or delete the notebook's entry here.
"""

from __future__ import annotations

import sys
from pathlib import Path

import nbformat

HERE = Path(__file__).resolve().parent

SETUP = '''\
%matplotlib inline
import os

import numpy as np

import cshape
from cshape import plots, shapes

SMALL = os.environ.get("CSHAPE_SMALL") == "1"  # small meshes and N, for the test suite
np.set_printoptions(precision=4, suppress=True, linewidth=100)
print("cshape", cshape.__version__, "(small sizes)" if SMALL else "")'''

REAL_MESH = '''\
def real_mesh(small=SMALL):
    """A real scanned-style mesh: Spot the cow (Keenan Crane, public domain) from the project's
    shared meshes when that folder is there, else PyMeshLab's sample cow, else a torus."""
    import cshape.data

    try:
        name = "spot_low_resolution" if small else "spot"
        credit = f"{name} (Spot by Keenan Crane, public domain)"
        return cshape.data.load("shared-meshes", name), credit
    except (FileNotFoundError, KeyError, ValueError) as exc:
        print(f"shared meshes not available ({exc}); using PyMeshLab's sample cow instead")
    try:
        return cshape.data.load("pymeshlab-samples", "cow"), "cow (PyMeshLab sample)"
    except (FileNotFoundError, KeyError, ValueError) as exc:
        print(f"PyMeshLab samples not available ({exc}); using a built-in torus")
        return shapes.torus(64, 32), "torus (built-in)"'''

DEMO_COLLECTION = '''\
from cshape import batch, variants


def demo_collection(small=SMALL):
    """(name, label, mesh) triples: a few classes of shapes, all made in code.

    Small: spheres, cubes and tori at two resolutions, and two poses each of a human and a snake
    figure.  Full: cshape's "paper-models" (spheres S1-S3, cube, torus, eight, the
    marching-cubes quadruped CM and its remesh CS, the human D1 and its refinement D2) and
    "articulated" (four classes x five poses), built with PyMeshLab once and then cached.
    """
    if not small:
        import cshape.data

        return [(it.name, it.label, it.mesh)
                for coll in ("paper-models", "articulated")
                for it in cshape.data.load_collection(coll)]
    items = [(f"sphere-{s}", "sphere", shapes.icosphere(s)) for s in (2, 3)]
    items += [(f"cube-{n}", "cube", shapes.cube(n)) for n in (5, 7)]
    items += [(f"torus-{k}", "torus", shapes.torus(8 * k + 24, 4 * k + 12)) for k in (0, 1)]
    for kind in ("human", "snake"):
        for seed in (0, 1):
            fig = variants.articulated_figure(kind, seed, voxelsize=0.05, target_vertices=500)
            items.append((f"{kind}-{seed}", kind, fig))
    return items'''


def md(text):
    return ("markdown", text)


def code(text):
    return ("code", text)


# =============================================================================== 01
NB01 = [
    md(r"""# 1 · Laplace-Beltrami eigenvalues with linear finite elements

**Paper:** *A Compact Shape Descriptor for Triangular Surface Meshes*, Section 2.1-2.2, Eq. (3)-(7).

**Learning goals.** After this notebook you can

1. assemble the stiffness matrix $A$ (Eq. 4) and the mass matrix $B$ (Eq. 5) of a triangle mesh by hand;
2. check them: symmetry, zero row sums of $A$, entries of $B$ adding up to the area, the signs;
3. solve the generalised eigenproblem $A f = -\lambda B f$ (Eq. 3) and read its eigenvalues;
4. tell Neumann from Dirichlet boundary conditions (Section 2.2) on a mesh with a boundary;
5. measure how the computed spectrum of the sphere approaches the exact one, $\ell(\ell+1)$, as the mesh is refined.

**The equations.** The eigenproblem of the Laplace-Beltrami operator $\Delta f = -\lambda f$ (Eq. 2) becomes, with
linear finite elements,

$$A f = -\lambda B f, \qquad (3)$$

$$a_{ij} = \begin{cases}\tfrac{\cot\alpha_{ij} + \cot\beta_{ij}}{2} & v_iv_j \text{ an edge}\\ -\sum_{k\in N(i)} a_{ik} & i = j\\ 0 & \text{otherwise}\end{cases}
\qquad (4)\qquad
b_{ij} = \begin{cases}\tfrac{|t_1| + |t_2|}{12} & v_iv_j \text{ an edge}\\ \sum_{t \ni v_i} \tfrac{|t|}{6} & i = j\\ 0 & \text{otherwise}\end{cases} \qquad (5)$$

where $\alpha_{ij}, \beta_{ij}$ are the angles opposite the edge $v_iv_j$ in its two triangles $t_1, t_2$.
On a boundary edge there is one triangle, at a non-manifold edge three or more: Eq. (6)-(7) simply sum over all
triangles at the edge.

> **Sign conventions.** With the paper's sign, $A$ is *negative* semidefinite (rows sum to zero) and $B$ is positive
> definite. The paper prints a minus sign on the diagonal of $B$ in Eq. (5) and (7): that is a typo; the diagonal is
> $+\sum_t |t|/6$.

*Run the cells from top to bottom. `CSHAPE_SMALL=1` in the environment makes every mesh small (the test suite uses it).*"""),
    code(SETUP),
    code('''\
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
    print(f"{name}: correct")'''),
    md(r"""## A tiny mesh

Five vertices, four triangles: a low tent over the unit square. It has a boundary (the four outer edges), so it
also shows the Neumann / Dirichlet difference later on."""),
    code('''\
V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0.3]])
F = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
tent = cshape.Mesh(V, F)
print(tent)
fig = plots.plot_mesh(tent, elev=35, azim=-70, edges=True, title="the tent: 4 triangles")
for i, p in enumerate(V):
    fig.axes[0].text(*p, f" v{i}", color="crimson", fontsize=12)
fig'''),
    md(r"""## The stiffness matrix $A$, Eq. (4), by hand

For the angle at corner $c$ of a triangle with edge vectors $u, w$ leaving $c$,
$\cot\theta = \dfrac{u\cdot w}{\lVert u \times w\rVert}$. Each triangle adds $\cot\theta/2$ to the entry of the
edge *opposite* that corner, and the diagonal makes every row sum to zero."""),
    code('''\
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
A_mine'''),
    md(r"""## Exercise 1 (graded): assemble $B$ yourself, Eq. (5)/(7)

Write `mass_matrix(V, F)` returning the dense consistent mass matrix: every triangle $t$ adds $|t|/12$ to the
entries of its three edges (both $(i, j)$ and $(j, i)$) and $|t|/6$ to the diagonal entry of each of its three
corners. $|t| = \tfrac12 \lVert (p_1 - p_0) \times (p_2 - p_0)\rVert$."""),
    code('''\
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
    ### END SOLUTION'''),
    code('''\
A_ref, B_ref = cshape.fem_matrices(tent)
B_mine = mass_matrix(V, F)
if not np.isclose(np.sum(B_mine), tent.area):
    print(f"hint: the entries of B must add up to the surface area {tent.area:.4f}, "
          f"yours add up to {np.sum(B_mine):.4f}")
if np.any(np.diag(B_mine) <= 0):
    print("hint: the diagonal of B is +sum |t|/6 (the minus sign printed in Eq. 5 is a typo)")
check_close("B", B_mine, B_ref, hint="Each triangle adds |t|/12 per edge entry, |t|/6 per corner.")
check_close("A", A_mine, A_ref)'''),
    code('''\
### BEGIN HIDDEN TESTS
_ico = shapes.icosphere(1)
check_close("mass_matrix(icosphere(1))", mass_matrix(_ico.vertices, _ico.faces),
            cshape.fem_matrices(_ico)[1])
_sq = shapes.square(3)
check_close("mass_matrix(square(3))", mass_matrix(_sq.vertices, _sq.faces),
            cshape.fem_matrices(_sq)[1])
### END HIDDEN TESTS'''),
    md(r"""## Properties to check on any mesh

`cshape.fem_matrices` assembles the same matrices for a whole mesh at once (sparse). Whatever the mesh,
$A$ and $B$ are symmetric, $A$'s rows sum to zero (constants are in its null space), $B$'s entries add up to the
area, $A \preceq 0$ and $B \succ 0$."""),
    code('''\
mesh = shapes.icosphere(2 if SMALL else 3)
A, B = cshape.fem_matrices(mesh)
Ad, Bd = A.toarray(), B.toarray()
print("vertices:", mesh.n_vertices)
print("A symmetric:", np.allclose(Ad, Ad.T), "  B symmetric:", np.allclose(Bd, Bd.T))
print("largest |row sum| of A:", np.abs(Ad.sum(axis=1)).max())
print("sum of B:", Bd.sum(), "  area:", mesh.area, "  (4 pi =", 4 * np.pi, ")")
print("largest eigenvalue of A (<= 0):", np.linalg.eigvalsh(Ad).max())
print("smallest eigenvalue of B (> 0):", np.linalg.eigvalsh(Bd).min())'''),
    md(r"""## The eigenproblem, Eq. (3)

With $K = -A$ the problem $A f = -\lambda B f$ is the symmetric-definite problem $K f = \lambda B f$, which
`scipy.linalg.eigh` solves directly for a small mesh. `cshape.eigenpairs` does the same (densely for small
meshes, by shift-invert Lanczos for large ones) and returns $B$-orthonormal eigenfunctions."""),
    code('''\
import scipy.linalg as la

lam_dense = la.eigh(-Ad, Bd, eigvals_only=True)[:10]
lam, phi = cshape.eigenpairs(mesh, N=10)
print("scipy.linalg.eigh:", lam_dense)
print("cshape.eigenpairs:", lam)
print("exact, unit sphere:", shapes.sphere_spectrum(10))
print("phi is B-orthonormal:", np.allclose(phi.T @ B @ phi, np.eye(10)))'''),
    md(r"""The eigenfunctions of the sphere are the spherical harmonics: three of degree 1 ($\lambda \approx 2$), five of
degree 2 ($\lambda \approx 6$). Red and blue are the two signs (the sign of an eigenfunction is arbitrary)."""),
    code('''\
plots.plot_eigenfunctions(mesh, phi, range(1, 9), lam)'''),
    md(r"""## Neumann versus Dirichlet (Section 2.2)

On a mesh with a boundary, **Neumann** conditions keep every vertex as an unknown (Eq. 6-7: boundary edges have one
triangle), while **Dirichlet** conditions fix $f = 0$ on the boundary and non-manifold vertices and keep only the
inner ones. The unit hemisphere has exact spectra: the degree-$\ell$ spherical harmonics $Y_\ell^m$ whose
$\ell + m$ is even (Neumann) or odd (Dirichlet), each with eigenvalue $\ell(\ell+1)$."""),
    code('''\
def hemisphere_spectrum(N, bc):
    out, ell = [], 0
    while len(out) < N:
        parity = 0 if bc == "neumann" else 1
        count = sum(1 for m in range(-ell, ell + 1) if (ell + m) % 2 == parity)
        out += [ell * (ell + 1)] * count
        ell += 1
    return np.array(out[:N], dtype=float)


hemi = shapes.hemisphere(8 if SMALL else 24)
N = 12
for bc in ("neumann", "dirichlet"):
    A_bc, _ = cshape.fem_matrices(hemi, bc=bc)
    lam_bc = cshape.shape_dna(hemi, N, bc=bc)
    print(f"{bc:9s}: {A_bc.shape[0]} unknowns;  computed", lam_bc.round(2))
    print(f"{'':9s}  exact                     ", hemisphere_spectrum(N, bc))'''),
    code('''\
lam_n, phi_n = cshape.eigenpairs(hemi, 4, bc="neumann")
lam_d, phi_d = cshape.eigenpairs(hemi, 4, bc="dirichlet")
fig = plots.new_figure((10, 3.2))
for k, (f, t) in enumerate([(phi_n[:, 1], f"Neumann phi_1, lam={lam_n[1]:.2f}"),
                            (phi_n[:, 3], f"Neumann phi_3, lam={lam_n[3]:.2f}"),
                            (phi_d[:, 0], f"Dirichlet phi_0, lam={lam_d[0]:.2f}"),
                            (phi_d[:, 1], f"Dirichlet phi_1, lam={lam_d[1]:.2f}")]):
    plots.plot_mesh(hemi, f, ax=fig.add_subplot(1, 4, k + 1, projection="3d"), elev=35, title=t)
fig'''),
    md(r"""Dirichlet eigenfunctions vanish on the rim (white there); Neumann ones meet the rim at a right angle and
take any value on it.

## Convergence on the sphere

Linear elements converge with order 2 in the mesh size $h$ for eigenvalues: halving the edge length should
divide the error by about four. Each level of the icosphere halves $h$."""),
    code('''\
levels = [1, 2, 3] if SMALL else [1, 2, 3, 4, 5]
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
plots.plot_convergence(h, errors[rows], labels=["lam_1 (l=1)", "lam_4 (l=2)", "lam_9 (l=3)"])'''),
    code('''\
orders = np.log(errors[:, :-1] / errors[:, 1:]) / np.log(np.array(h[:-1]) / np.array(h[1:]))
print("observed order between levels (mean over 15 eigenvalues):", orders.mean(axis=0))'''),
    md(r"""## Exercises

1. *(graded above)* Assemble $B$ yourself.
2. **Lumped mass.** Repeat the convergence study with `cshape.shape_dna(m, N, mass="lumped")`. Does the lumped
   spectrum approach the exact one from above or from below? Is the order still 2?
3. **The square.** `shapes.square(n)` is the unit square. Its Dirichlet eigenvalues are
   $\pi^2(m^2 + n^2)$ with $m, n \geq 1$, the Neumann ones the same with $m, n \geq 0$. Check both for
   `n = 8, 16, 32`.
4. **Components.** Build a mesh of two separate icospheres (stack the vertex arrays, offset the second
   face array). How many zero eigenvalues does it have, and why? (cshape warns you.)
5. **Why the typo matters.** Flip the sign of the diagonal of your `mass_matrix`. What happens to the
   eigenvalues, and which property of $B$ breaks?"""),
]

# =============================================================================== 02
NB02 = [
    md(r"""# 2 · Shape-DNA and the Weyl line

**Paper:** Section 2.1 and 2.3, Fig. 1 and Fig. 2 (a)-(d), Eq. (8).

**Learning goals.** After this notebook you can

1. compute the Shape-DNA, the $N$ smallest eigenvalues $0 = \lambda_0 \le \lambda_1 \le \dots \le \lambda_{N-1}$;
2. explain why every Shape-DNA lies along a straight line (Weyl's law) whose slope depends on the area only;
3. normalise a Shape-DNA so that it is scale invariant (by the area, the first non-zero eigenvalue, or the
   fitted Weyl slope) and see all shapes gather around the common line $L(i) = 4\pi i$;
4. subtract that line (Eq. 8) and look at what remains: the part of the spectrum that tells shapes apart.

**Weyl's law.** For a closed surface of area $|\mathcal M|$, $\lambda_i \sim \dfrac{4\pi}{|\mathcal M|}\, i$
as $i \to \infty$. So $|\mathcal M| \lambda_i \approx 4\pi i$ for every shape, and

$$\lambda'_i = \lambda_i^{norm} - 4\pi i, \qquad i = 0, \dots, N-1. \qquad (8)$$"""),
    code(SETUP),
    code(REAL_MESH),
    md(r"""## Three shapes, three lines (Fig. 1)

The paper's Fig. 1 uses the *bimba* statue, a cube and a sphere. We use a real mesh (Spot the cow when the
project's shared meshes are there), a cube and a sphere."""),
    code('''\
N = 50 if SMALL else 100
real, real_name = real_mesh()
models = {
    real_name.split(" ")[0]: real,
    "cube": shapes.cube(8 if SMALL else 16),
    "sphere": shapes.icosphere(3 if SMALL else 4),
}
spectra = {name: cshape.shape_dna(m, N) for name, m in models.items()}
areas = {name: m.area for name, m in models.items()}
for name, m in models.items():
    print(f"{name:20s} {m.n_vertices:6d} vertices, area {m.area:8.4f}, "
          f"lam_1..3 = {spectra[name][1:4]}")'''),
    code('''\
fig = plots.new_figure((9, 3))
for k, (name, m) in enumerate(models.items()):
    plots.plot_mesh(m, ax=fig.add_subplot(1, 3, k + 1, projection="3d"), title=name, elev=15,
                    vertical_axis="y" if m is real else "z")
fig'''),
    code('''\
plots.plot_weyl(spectra, areas)'''),
    md(r"""Left: each raw Shape-DNA lies along its own line; a larger shape has smaller eigenvalues (a bigger drum sounds
lower). Right: multiplied by the area, all three lie around the dashed line $4\pi i$.

## Scale invariance

Scaling a surface by $s$ multiplies its area by $s^2$ and divides its eigenvalues by $s^2$: the raw Shape-DNA
changes, the normalised one does not."""),
    code('''\
mesh = models["cube"]
big = cshape.Mesh(2.0 * mesh.vertices, mesh.faces)
lam_small, lam_big = spectra["cube"][:6], cshape.shape_dna(big, 6)
print("raw:              ", lam_small, "\\n                  ", lam_big)
print("area-normalised:  ", cshape.normalize(lam_small, mesh.area), "\\n                  ",
      cshape.normalize(lam_big, big.area))'''),
    md(r"""### Three normalisations

`cshape.normalize(lam, area, method=...)` offers the paper's choice `'area'` and two others from the Shape-DNA
literature: `'fiedler'` divides by the first non-zero eigenvalue, `'weyl'` rescales so that the least-squares
slope of $\lambda_i$ against $i$ becomes $4\pi$ (no area needed, handy for point clouds or damaged meshes)."""),
    code('''\
fig = plots.new_figure((11, 3.2))
axs = fig.subplots(1, 3)
for ax, method in zip(axs, ["area", "fiedler", "weyl"], strict=True):
    for name, lam in spectra.items():
        ax.plot(cshape.normalize(lam, areas[name], method=method), ".", ms=3, label=name)
    ax.set(title=f"method='{method}'", xlabel="i")
axs[0].plot(4 * np.pi * np.arange(N), "k--", lw=1, label="4 pi i")
axs[0].legend(fontsize="small")
fig'''),
    md(r"""## One shape through the pipeline (Fig. 2 a-d)

(a) the model, here coloured by one of its eigenfunctions; (b) its Shape-DNA; (c) multiplied by the area, around
the Weyl line; (d) the Weyl line subtracted, Eq. (8)."""),
    code('''\
lam, phi = cshape.eigenpairs(real, N)
plots.plot_mesh(real, phi[:, 6], title=f"(a) {real_name.split(' (')[0]}: phi_6", elev=15, azim=30,
                vertical_axis="y", figsize=(5, 5))'''),
    code('''\
plots.plot_shape_dna_stages(lam, real.area, name=real_name.split(" ")[0])'''),
    md(r"""Low eigenfunctions vary slowly over the whole shape (they "see" its global layout: legs, head, body); higher
ones oscillate faster. That is why the first eigenvalues already describe the shape."""),
    code('''\
plots.plot_eigenfunctions(real, phi, [1, 2, 3, 5, 10, 20, 30, N - 1], lam, elev=15, azim=30,
                          vertical_axis="y")'''),
    md(r"""## What is left after Eq. (8)

$\lambda'_i$ wiggles around zero with a slow trend that differs from shape to shape. The next notebook compresses
exactly this signal with a discrete Fourier transform."""),
    code('''\
fig = plots.new_figure((6, 3.5))
ax = fig.add_subplot()
for name, lam_i in spectra.items():
    lam_prime = cshape.weyl_subtract(cshape.normalize(lam_i, areas[name]))
    ax.plot(lam_prime, ".-", ms=3, lw=0.7, label=name)
ax.axhline(0, color="k", lw=0.6)
ax.set(xlabel="i", ylabel="lam'_i", title="Eq. (8) for the three models")
ax.legend(fontsize="small")
fig'''),
    md(r"""## Exercises

1. **Isometry.** Bend a mesh without stretching it (e.g. `cshape.variants.articulated_figure("human", seed)` for
   two seeds gives two poses with the same bone lengths). Compare their normalised Shape-DNAs with those of two
   different classes.
2. **How many eigenvalues?** Plot $\lambda'_i$ of the sphere for $N = 100$. Why does it look like a staircase?
   (Hint: multiplicities $2\ell+1$.)
3. **Without the area.** Compute the `'weyl'` normalisation of the real mesh and compare it with the `'area'` one.
   When would you prefer it?
4. **Resolution.** If the shared meshes are available, compare `spot_low_resolution` and `spot` (same shape,
   different triangulations): how far apart are their normalised Shape-DNAs, relative to the distance to the
   cube?"""),
]

# =============================================================================== 03
NB03 = [
    md(r"""# 3 · Compressing the Shape-DNA with the DFT: the compact Shape-DNA

**Paper:** Section 2.3, Eq. (8)-(10), Fig. 2 (e)-(f).

**Learning goals.** After this notebook you can

1. implement the three steps of the cShape-DNA yourself: subtract the Weyl line (Eq. 8), take the DFT (Eq. 9),
   shift and crop the $2M+1$ lowest frequencies (Eq. 10);
2. read a shifted DFT magnitude plot and explain why the low frequencies dominate;
3. rebuild the Shape-DNA from the $2M+1$ coefficients and measure what is lost as $M$ shrinks;
4. store the complex descriptor as $2M+1$ real numbers with the same Euclidean distances.

**The equations.**

$$\lambda'_k = \lambda^{norm}_k - 4\pi k \quad (8) \qquad
\Lambda_i = \sum_{k=0}^{N-1} \lambda'_k\, e^{-j 2\pi i k / N},\quad i = 0, \dots, N-1 \quad (9)$$

$$\mathcal S^c = \left(\Lambda^{shift}_{\langle N/2\rangle - M}, \dots, \Lambda^{shift}_{\langle N/2\rangle + M}\right) \quad (10)$$

where $\Lambda^{shift}$ is $\Lambda$ circularly shifted so that the zero frequency sits at index
$\langle N/2 \rangle$ (NumPy's `fftshift`). $\mathcal S^c[M]$ is the zero frequency, $\mathcal S^c[M \pm k]$ the
frequencies $\pm k$."""),
    code(SETUP),
    code(REAL_MESH),
    code('''\
def check_close(name, got, want, hint="", rtol=1e-9):
    """Compare your result with the expected one and say what is wrong."""
    got, want = np.asarray(got), np.asarray(want)
    if got.shape != want.shape:
        raise AssertionError(f"{name} has shape {got.shape}, expected {want.shape}. {hint}")
    atol = 1e-9 * max(1.0, np.abs(want).max())
    bad = np.flatnonzero(~np.isclose(got, want, rtol=rtol, atol=atol))
    if len(bad):
        k = bad[0]
        raise AssertionError(f"{name}[{k}] = {got.flat[k]:.6g}, expected {want.flat[k]:.6g} "
                             f"({len(bad)} of {got.size} values differ). {hint}")
    print(f"{name}: correct")


N = 50 if SMALL else 100
M = 8 if SMALL else 16
real, real_name = real_mesh()
lam = cshape.shape_dna(real, N)
lam_norm = cshape.normalize(lam, real.area)  # the area normalisation of Section 2.1
print(real_name, "- N =", N, ", M =", M)'''),
    md(r"""## Exercise 1 (graded): subtract the Weyl line, Eq. (8)

Write `weyl_subtract_mine(lam_norm)` returning $\lambda'_k = \lambda^{norm}_k - 4\pi k$ for $k = 0, \dots, N-1$
(no loop needed: `np.arange`)."""),
    code('''\
def weyl_subtract_mine(lam_norm):
    """Eq. (8): lam'_k = lam_norm_k - 4 pi k."""
    ### BEGIN SOLUTION
    lam_norm = np.asarray(lam_norm, dtype=float)
    return lam_norm - 4 * np.pi * np.arange(len(lam_norm))
    ### END SOLUTION


lam_prime = weyl_subtract_mine(lam_norm)
check_close("lam'", lam_prime, cshape.weyl_subtract(lam_norm),
            hint="The line is 4 pi k with k starting at 0 (lam'_0 = lam_norm_0).")'''),
    code('''\
### BEGIN HIDDEN TESTS
check_close("weyl_subtract_mine([0, 1, 2])", weyl_subtract_mine([0.0, 1.0, 2.0]),
            [0.0, 1 - 4 * np.pi, 2 - 8 * np.pi])
### END HIDDEN TESTS'''),
    md(r"""## Exercise 2 (graded): the DFT, Eq. (9), from its definition

Write `dft_mine(x)` computing $\Lambda_i = \sum_k x_k e^{-j2\pi ik/N}$ *from the sum* (an $N\times N$ matrix of
exponentials is fine; no `np.fft`). Python writes $j$ as `1j`."""),
    code('''\
def dft_mine(x):
    """Eq. (9): Lambda_i = sum_k x_k exp(-j 2 pi i k / N), i = 0..N-1."""
    ### BEGIN SOLUTION
    x = np.asarray(x, dtype=float)
    n = len(x)
    k = np.arange(n)
    return np.exp(-2j * np.pi * np.outer(k, k) / n) @ x
    ### END SOLUTION


Lam = dft_mine(lam_prime)
if np.allclose(Lam, np.conj(np.fft.fft(lam_prime))) and not np.allclose(Lam, np.fft.fft(lam_prime)):
    print("hint: you computed the conjugate: the exponent of Eq. (9) has a minus sign")
check_close("Lambda", Lam, np.fft.fft(lam_prime), hint="Sum over k of x_k exp(-2j pi i k / N).")'''),
    code('''\
### BEGIN HIDDEN TESTS
_x = np.random.default_rng(0).standard_normal(7)
check_close("dft_mine(odd length)", dft_mine(_x), np.fft.fft(_x))
check_close("dft_mine(impulse)", dft_mine([1.0, 0, 0, 0]), np.ones(4))
### END HIDDEN TESTS'''),
    md(r"""## Exercise 3 (graded): shift and crop, Eq. (10)

Write `crop_mine(Lam, M)`: shift the zero frequency to the centre index `N // 2` (`np.fft.fftshift`), then keep
the $2M+1$ values from `N//2 - M` to `N//2 + M` inclusive. The result is the cShape-DNA."""),
    code('''\
def crop_mine(Lam, M):
    """Eq. (10): the 2M+1 shifted DFT coefficients around the centre <N/2>."""
    ### BEGIN SOLUTION
    shifted = np.fft.fftshift(Lam)
    c = len(Lam) // 2
    return shifted[c - M : c + M + 1]
    ### END SOLUTION


S_mine = crop_mine(Lam, M)
S = cshape.compact_shape_dna(lam, M=M, N=N, area=real.area)
check_close("S_c", S_mine, S, hint="Length 2M+1, centred on index N // 2 of the shifted vector; "
            "the middle value S_c[M] is the zero frequency Lambda_0.")'''),
    code('''\
### BEGIN HIDDEN TESTS
for _n in (9, 10):
    _x = np.arange(_n, dtype=float) ** 1.5
    check_close(f"crop_mine(N={_n}, M=2)", crop_mine(np.fft.fft(cshape.weyl_subtract(_x)), 2),
                cshape.compact_shape_dna(_x, M=2, N=_n))
### END HIDDEN TESTS'''),
    md(r"""## The picture of Eq. (9)-(10): Fig. 2 (e)-(f)

(e) The magnitudes of the shifted DFT: the low frequencies in the middle carry most of the energy. (f) The
$2M+1$ kept values, the cShape-DNA. Right: the Weyl-subtracted Shape-DNA and what the $2M+1$ values rebuild
(inverse DFT with the other frequencies set to zero, `cshape.inverse_compact_shape_dna`)."""),
    code('''\
plots.plot_dft(lam, real.area, M, N=N)'''),
    md(r"""## How small can $M$ be?

The reconstruction gets smoother as $M$ shrinks; the error tells how much of the spectrum's shape the descriptor
has lost. We compare a few shapes, since the paper notes that the best $M$ depends on the shapes."""),
    code('''\
fig = plots.new_figure((7, 3.6))
ax = fig.add_subplot()
i = np.arange(N)
ax.plot(i, cshape.weyl_subtract(lam_norm), "k.", ms=4, label="lam'")
for m in [1, 2, 4, M]:
    rec = cshape.inverse_compact_shape_dna(cshape.compact_shape_dna(lam_norm, M=m, N=N), N)
    ax.plot(i, cshape.weyl_subtract(rec), lw=1.2, label=f"M={m} ({2 * m + 1} values)")
ax.set(xlabel="i", ylabel="lam'_i", title=f"reconstructions, {real_name.split(' ')[0]}")
ax.legend(fontsize="small")
fig'''),
    code('''\
models = {real_name.split(" ")[0]: lam_norm}
others = {
    "sphere": shapes.icosphere(3 if SMALL else 4),
    "cube": shapes.cube(8 if SMALL else 16),
    "torus": shapes.torus(48, 24) if SMALL else shapes.torus(96, 48),
}
for name, m in others.items():
    models[name] = cshape.normalize(cshape.shape_dna(m, N), m.area)
Ms = np.arange(0, (N - 1) // 2 + 1)
errors = []
for ln in models.values():
    lp = cshape.weyl_subtract(ln)
    errors.append([np.linalg.norm(cshape.inverse_compact_shape_dna(
        cshape.compact_shape_dna(ln, M=int(m), N=N), N, add_weyl=False) - lp) / np.linalg.norm(lp)
        for m in Ms])
plots.plot_reconstruction_error(Ms, errors, labels=list(models), N=N)'''),
    md(r"""## Storing the descriptor: $2M+1$ real numbers

The input is real, so $\Lambda_{-k} = \overline{\Lambda_k}$: half of the complex values are redundant.
`cshape.real_form` keeps $\mathrm{Re}\,\Lambda_0$ and $\sqrt2\,(\mathrm{Re}, \mathrm{Im})$ of
$\Lambda_1..\Lambda_M$: $2M+1$ reals, with exactly the Euclidean distances of the complex descriptors."""),
    code('''\
S_a = cshape.compact_shape_dna(models["sphere"], M=M, N=N)
S_b = cshape.compact_shape_dna(models["cube"], M=M, N=N)
print("conjugate symmetric:", np.allclose(S_a[::-1], np.conj(S_a)))
print("complex distance:", np.linalg.norm(S_a - S_b))
print("real-form distance:", np.linalg.norm(cshape.real_form(S_a) - cshape.real_form(S_b)))
print("sizes: Shape-DNA", N, "values, cShape-DNA", len(cshape.real_form(S_a)), "values")'''),
    md(r"""## Exercises

1. *(graded above)* Eq. (8), (9) and (10) by hand.
2. **Why the line first?** Skip Eq. (8): take the DFT of the normalised Shape-DNA itself and crop it. Reconstruct
   and compare the error with the one above. What does the jump between $\lambda_{N-1}$ and $\lambda_0$ (the DFT
   treats the signal as periodic) do to the high frequencies?
3. **Even and odd $N$.** For $N = 10$ and $N = 11$, which indices of the shifted vector are kept for $M = 2$?
   Check with `np.fft.fftshift(np.fft.fftfreq(N) * N)`.
4. **A budget of 9 numbers.** Compare the first 9 normalised eigenvalues with the cShape-DNA for $M = 4$:
   which one tells the sphere from the cube better (distance between them, relative to the distance between
   two spheres of different resolution)? Notebook 4 does this for a whole collection."""),
]

# =============================================================================== 04
NB04 = [
    md(r"""# 4 · Comparing and classifying shapes: distance matrices, MDS, retrieval

**Paper:** Section 3.1, Fig. 3 (scaled distance matrices and their difference), Fig. 4 (MDS of the
cShape-DNA for $M = 16, 8, 4, 2, 1$), Fig. 5 (MDS of the truncated Shape-DNA and of the F1 feature).

**Learning goals.** After this notebook you can

1. turn a collection of meshes into descriptors once (`cshape.batch.describe`) and derive every descriptor
   of the paper from the same eigenvalues;
2. compare two distance matrices that live on different scales by scaling both to $[0, 255]$ and reading
   the mean and standard deviation of their difference (Fig. 3);
3. draw and read 2-D MDS plots (Fig. 4-5): what "the clustering gets worse" looks like;
4. score a descriptor with the retrieval measures of the Princeton Shape Benchmark (nearest neighbour,
   first and second tier, E-measure, DCG, mean average precision).

**The measures.** With descriptors $x_p$ (one per shape), $D_{pq} = \lVert x_p - x_q\rVert$ (Euclidean),

$$D^{255} = 255\,\frac{D}{\max D}, \qquad \text{difference} = \left|D^{255}_{\text{Shape-DNA}} - D^{255}_{\text{cShape-DNA}}\right|,$$

and the paper reports mean 0.68 and standard deviation 0.69 for the McGill database with $N = 100$, $M = 16$."""),
    code(SETUP),
    code(DEMO_COLLECTION + '''


collection = demo_collection()
N = 40 if SMALL else 100
table = batch.describe(collection, N=N, progress=not SMALL)
print(table)
print("classes:", sorted(set(table.labels)))'''),
    md(r"""## The collection

One shape of each class. The full-size run uses cshape's generated "paper-models" and "articulated"
collections: the paper's simple models, a marching-cubes animal and its remesh, a figure at two resolutions,
and four classes of articulated figures in five poses each (the counterpart of the armadillo poses A1-A5)."""),
    code('''\
first = {}
for name, label, mesh in collection:
    first.setdefault(label, (name, mesh))
fig = plots.new_figure((2.6 * len(first), 2.8))
for k, (label, (name, mesh)) in enumerate(first.items()):
    plots.plot_mesh(mesh, ax=fig.add_subplot(1, len(first), k + 1, projection="3d"),
                    title=f"{label}: {name}", edges=False)
fig'''),
    md(r"""## Fig. 3: scaled distance matrices and their difference

`table.distance_matrix(kind, M=...)` builds the descriptors from the stored eigenvalues (no new eigensolve)
and their Euclidean distances. Shapes are in collection order, so each class is a block on the diagonal."""),
    code('''\
from cshape import compare

M = 16 if 2 * 16 + 1 <= N else (N - 1) // 2
D_sdna = table.distance_matrix("shape_dna")
D_cs = table.distance_matrix("cshape", M=M)
mean, std = compare.scaled_difference(D_sdna, D_cs)
plots.plot_matrices(
    [compare.scale_255(D_sdna), compare.scale_255(D_cs), compare.difference_matrix(D_sdna, D_cs)],
    [f"(a) Shape-DNA, N={N}", f"(b) cShape-DNA, M={M}",
     f"(c) |a - b|: mean {mean:.2f}, std {std:.2f}"],
    vmax=255,
)'''),
    md(r"""The difference image is nearly black on the $[0, 255]$ scale: the two descriptors rank the shapes almost
identically, although the cShape-DNA has $2M+1$ values instead of $N$. (In the small-size run the meshes are
coarse, e.g. spheres of 162 and 642 vertices, whose higher eigenvalues differ visibly: resolution matters
when a mesh has few vertices per eigenfunction oscillation.)

## Fig. 4: MDS of the cShape-DNA as $M$ shrinks

Multidimensional scaling places one point per shape in the plane so that the planar distances approximate
$D$. A good descriptor gives tight, separated clusters."""),
    code('''\
Ms = [m for m in (16, 8, 4, 2, 1) if 2 * m + 1 <= N]
nrows = -(-(len(Ms) + 1) // 3)
fig = plots.new_figure((11, 3.6 * nrows))
axs = fig.subplots(nrows, 3).ravel()
compare.plot_mds(compare.mds_embedding(D_sdna), labels=table.labels, ax=axs[0],
                 title=f"(a) Shape-DNA, N={N}")
for ax, m in zip(axs[1:], Ms, strict=False):
    Y = compare.mds_embedding(table.distance_matrix("cshape", M=m))
    compare.plot_mds(Y, labels=table.labels, ax=ax, title=f"cShape-DNA M={m} ({2 * m + 1} values)")
for ax in axs[1:]:  # one legend is enough
    if ax.get_legend() is not None:
        ax.get_legend().remove()
for ax in axs[len(Ms) + 1:]:
    ax.set_axis_off()
fig'''),
    md(r"""## Fig. 5: the truncated Shape-DNA with the same budget, and F1

The fair comparison: keep the *first* $2M+1$ normalised eigenvalues instead (Fig. 5 a-e), or use the F1 feature
$\left(\lambda_1/\lambda_2, \dots, \lambda_1/\lambda_N\right)$ (Fig. 5f)."""),
    code('''\
fig = plots.new_figure((11, 3.6 * nrows))
axs = fig.subplots(nrows, 3).ravel()
for ax, m in zip(axs, Ms, strict=False):
    Y = compare.mds_embedding(table.distance_matrix("truncated", M=m))
    compare.plot_mds(Y, labels=table.labels, ax=ax, title=f"first {2 * m + 1} eigenvalues")
Y = compare.mds_embedding(table.distance_matrix("f1"))
compare.plot_mds(Y, labels=table.labels, ax=axs[len(Ms)], title=f"(f) F1, N={N}")
for ax in axs[1:]:  # one legend is enough
    if ax.get_legend() is not None:
        ax.get_legend().remove()
for ax in axs[len(Ms) + 1:]:
    ax.set_axis_off()
fig'''),
    md(r"""## Retrieval measures

Every shape is used once as a query against all the others; the measures (in $[0, 1]$, higher is better)
tell how often and how early shapes of the same class come back. See `cshape.compare.retrieval_scores`
for the exact definitions."""),
    code('''\
rows = [("Shape-DNA", N, compare.retrieval_scores(D_sdna, table.labels))]
for m in Ms:
    rows.append((f"cShape-DNA M={m}", 2 * m + 1,
                 compare.retrieval_scores(table.distance_matrix("cshape", M=m), table.labels)))
    rows.append((f"truncated, first {2 * m + 1}", 2 * m + 1,
                 compare.retrieval_scores(table.distance_matrix("truncated", M=m), table.labels)))
rows.append(("F1", N - 2, compare.retrieval_scores(table.distance_matrix("f1"), table.labels)))
keys = ["nn", "ft", "st", "e", "dcg", "map"]
print(f"{'descriptor':24s} {'size':>4s} " + " ".join(f"{k:>6s}" for k in keys))
for name, size, sc in rows:
    print(f"{name:24s} {size:4d} " + " ".join(f"{sc[k]:6.3f}" for k in keys))'''),
    code('''\
fig = plots.new_figure((6, 3.6))
ax = fig.add_subplot()
sizes = [2 * m + 1 for m in Ms]
for kind, marker in (("cshape", "o-"), ("truncated", "s--")):
    ft = [compare.retrieval_scores(table.distance_matrix(kind, M=m), table.labels)["ft"]
          for m in Ms]
    ax.plot(sizes, ft, marker, label=kind)
ax.axhline(rows[0][2]["ft"], color="k", lw=0.8, label=f"Shape-DNA, N={N}")
ax.set(xlabel="descriptor size (values)", ylabel="first tier", xscale="log",
       title="same budget, different descriptors")
ax.legend(fontsize="small")
fig'''),
    md(r"""## Exercises

1. Which pair of shapes does the cShape-DNA with $M = 1$ confuse most? Find it in the distance matrix
   (`np.argsort`) and draw both meshes.
2. The spheres S1-S3 (full size) differ only in resolution. How large is their mutual distance relative to
   the distance from the sphere to the cube, for the Shape-DNA and for the cShape-DNA?
3. Compute the difference statistics of Fig. 3 for `normalization="weyl"` (pass it to
   `table.distance_matrix`). Does the choice of normalisation matter here?
4. Replace the MDS by a nearest-neighbour classifier (`compare.DescriptorIndex`): leave one shape out, predict
   its class from its nearest neighbour, and count the errors for each descriptor."""),
]

# =============================================================================== 05
NB05 = [
    md(r"""# 5 · Sensitivity to noise and to mesh quality

**Paper:** Section 3.3, Fig. 7 (difference matrices under noise), Fig. 8 (descriptor differences per model),
Fig. 9 (cShape-DNA of a marching-cubes mesh and of its remesh).

**Learning goals.** After this notebook you can

1. add the paper's noise: move every vertex along its outward normal by a random distance up to
   $\lambda \times L$ ($L$ the mean edge length, $\lambda \in \{0.5, 1, 2, 4, 10\}$);
2. measure how noise changes the distance matrices of the Shape-DNA and of the cShape-DNA (Fig. 7) and each
   model's descriptor (Fig. 8);
3. measure triangle quality (angles, aspect ratios) and see that the spectrum depends on the shape, not on the
   triangulation (Fig. 9).

**Why noise matters.** Noise adds area (a rough surface is larger) and small-scale wiggles that the higher
eigenfunctions feel: the normalised eigenvalues shift, the more so the larger $\lambda$."""),
    code(SETUP),
    code(DEMO_COLLECTION + '''


collection = demo_collection()
if not SMALL:  # leave out the largest meshes: every model is solved once per noise level
    collection = [c for c in collection if c[0] not in ("S2", "S3", "D2")]
N = 30 if SMALL else 100
M = 8 if SMALL else 16
levels = [0.5, 2.0, 10.0] if SMALL else [0.5, 1.0, 2.0, 4.0, 10.0]
print(len(collection), "models, noise levels", levels)'''),
    md(r"""## What the noise looks like"""),
    code('''\
name, label, mesh = collection[-1]
fig = plots.new_figure((3 * (len(levels) + 1), 3))
for k, lev in enumerate([0.0, *levels]):
    noisy = variants.add_normal_noise(mesh, lev, random_state=0)
    plots.plot_mesh(noisy, ax=fig.add_subplot(1, len(levels) + 1, k + 1, projection="3d"),
                    title=f"{name}, lambda = {lev}", edges=False)
fig'''),
    md(r"""## Descriptors of the clean and the noisy collections

`batch.describe` caches eigenvalues by mesh content, so rerunning this notebook only computes what is new."""),
    code('''\
clean = batch.describe(collection, N=N, M=M, progress=not SMALL)
noisy = {}
for lev in levels:
    noisy_items = [(n, lab, variants.add_normal_noise(m, lev, random_state=0))
                   for n, lab, m in collection]
    noisy[lev] = batch.describe(noisy_items, N=N, M=M, progress=not SMALL)
print(clean)'''),
    md(r"""## Fig. 7: difference matrices against the noise-free collection

For each noise level, the scaled distance matrix of the noisy models is compared with that of the clean
ones, for the normalised Shape-DNA (top) and the cShape-DNA (bottom)."""),
    code('''\
from cshape import compare

diffs, titles, stats = {"shape_dna": [], "cshape": []}, {"shape_dna": [], "cshape": []}, []
for lev in levels:
    for kind in ("shape_dna", "cshape"):
        D0, D1 = clean.distance_matrix(kind), noisy[lev].distance_matrix(kind)
        mean, std = compare.scaled_difference(D0, D1)
        diffs[kind].append(compare.difference_matrix(D0, D1))
        titles[kind].append(f"lambda={lev}: {mean:.1f} / {std:.1f}")
        stats.append((lev, kind, mean, std))
vmax = max(d.max() for v in diffs.values() for d in v)
print("mean / std of each difference image")
plots.plot_matrices(diffs["shape_dna"], [f"Shape-DNA {t}" for t in titles["shape_dna"]], vmax=vmax)'''),
    code('''\
plots.plot_matrices(diffs["cshape"], [f"cShape-DNA {t}" for t in titles["cshape"]], vmax=vmax)'''),
    code('''\
print(f"{'lambda':>7s} {'Shape-DNA mean/std':>20s} {'cShape-DNA mean/std':>20s}")
for lev in levels:
    s = {k: (m, sd) for lv, k, m, sd in stats if lv == lev}
    print(f"{lev:7.1f} {s['shape_dna'][0]:12.2f} / {s['shape_dna'][1]:5.2f} "
          f"{s['cshape'][0]:12.2f} / {s['cshape'][1]:5.2f}")'''),
    md(r"""As in the paper, the two descriptors react to noise almost identically: the cShape-DNA inherits the
Shape-DNA's sensitivity, no more and no less.

## Fig. 8: how far each model's descriptor moves

For three noise levels, the distance between each model's noisy and clean descriptor, scaled to $[0, 1]$
over all models and levels."""),
    code('''\
show = [levels[0], levels[len(levels) // 2], levels[-1]]
fig = plots.new_figure((11, 3.5))
axs = fig.subplots(1, 2, sharey=True)
for ax, kind, title in ((axs[0], "shape_dna", "(a) normalised Shape-DNA"),
                        (axs[1], "cshape", "(b) cShape-DNA")):
    d = {lev: np.linalg.norm(noisy[lev].descriptors(kind) - clean.descriptors(kind), axis=1)
         for lev in show}
    top = max(v.max() for v in d.values())
    for lev in show:
        ax.plot(d[lev] / top, "o-", ms=3, label=f"lambda = {lev}")
    ax.set(title=title, xlabel="model", xticks=range(len(clean)))
    ax.set_xticklabels(clean.names, rotation=90, fontsize="x-small")
    ax.legend(fontsize="small")
axs[0].set_ylabel("scaled difference")
fig'''),
    md(r"""## Fig. 9: mesh quality does not matter

Marching cubes produces needles and nearly flat triangles ("CM"); isotropic remeshing makes them nearly
equilateral ("CS"). The spectrum belongs to the surface, not to its triangles, so the two cShape-DNAs should
agree closely: their distance is small next to the distance to another shape. (The remesh also smooths the
surface a little, which accounts for most of what remains.)"""),
    code('''\
if SMALL:
    CM = variants.articulated_figure("quadruped", 0, voxelsize=0.04, target_vertices=None)
    CS = variants.remesh(CM, target_vertices=1200)
else:
    import cshape.data

    CM, CS = cshape.data.load("paper-models", "CM"), cshape.data.load("paper-models", "CS")
for name, m in (("CM (marching cubes)", CM), ("CS (remeshed)", CS)):
    q = variants.mesh_quality(m)
    print(f"{name:20s} {q['n_vertices']:6d} vertices, smallest angle {q['min_angle']:5.2f} deg, "
          f"{q['pct_below_10']:5.1f}% of triangles below 10 deg, "
          f"worst aspect {q['aspect_max']:.3g}")'''),
    code('''\
def close_up(mesh, frac=0.15):
    """The triangles near the mesh's highest point (the head), to see their shapes."""
    V, F = mesh.vertices, mesh.faces
    c = V[np.argmax(V[:, 2])]
    keep = np.linalg.norm(V[F].mean(axis=1) - c, axis=1) < frac * np.ptp(V, axis=0).max()
    used, F_new = np.unique(F[keep], return_inverse=True)
    return cshape.Mesh(V[used], F_new.reshape(-1, 3))


fig = plots.new_figure((11, 3.6))
ax0 = fig.add_subplot(1, 3, 1, projection="3d")
ax1 = fig.add_subplot(1, 3, 2, projection="3d")
ax2 = fig.add_subplot(1, 3, 3)
for ax, (name, m) in ((ax0, ("CM", CM)), (ax1, ("CS", CS))):
    plots.plot_mesh(close_up(m), ax=ax, edges=True, title=f"{name}, close up", elev=50, azim=-40)
for name, m in (("CM", CM), ("CS", CS)):
    ax2.hist(variants.triangle_angles(m).min(axis=1), bins=40, range=(0, 60), alpha=0.6,
             label=name)
ax2.set(xlabel="smallest angle of a triangle (degrees)", ylabel="triangles",
        title="triangle quality")
ax2.legend()
fig'''),
    code('''\
import warnings

with warnings.catch_warnings():
    warnings.simplefilter("ignore", cshape.CShapeWarning)  # CM has near-degenerate triangles
    S = {name: cshape.compact_shape_dna(m, M=M, N=N) for name, m in (("CM", CM), ("CS", CS))}
others = {"a sphere": shapes.icosphere(3), "a torus": shapes.torus(48, 24)}
print(f"distance CM - CS:        {np.linalg.norm(S['CM'] - S['CS']):10.1f}")
for name, m in others.items():  # for scale: the distance to another shape
    d = np.linalg.norm(S["CS"] - cshape.compact_shape_dna(m, M, N))
    print(f"distance CS - {name:9s} {d:10.1f}")
plots.plot_cshape_dna(S, title="Fig. 9: cShape-DNA of CM and CS")'''),
    md(r"""## Exercises

1. Use `signed=True` in `variants.add_normal_noise` (noise in both directions). Does the area still grow?
   How do the statistics of Fig. 7 change?
2. Noise adds area. Normalise with `normalization="weyl"` instead of the area and repeat Fig. 7. Which
   normalisation is more robust to noise, and why?
3. Smooth a noisy mesh back (PyMeshLab's Laplacian smoothing, `pymeshlab.MeshSet.apply_coord_laplacian_smoothing`)
   and measure how much of the clean descriptor comes back.
4. Fig. 9 with the Shape-DNA itself: plot the normalised Shape-DNAs of CM and CS. Where do they differ most,
   at low or at high eigenvalues?"""),
]

# =============================================================================== 06
NB06 = [
    md(r"""# 6 · Working with your own collection

**Paper:** the whole pipeline of Section 2 (Eq. 3-10), applied the way Section 3 does it to a database.

**Learning goals.** After this notebook you can

1. point cshape at a folder of meshes (one sub-folder per class) and get names and labels;
2. compute every shape's eigenvalues once, with a cache that makes the next run (or an interrupted one) fast,
   in parallel processes or on a Dask cluster;
3. query the nearest neighbours of a new shape with `DescriptorIndex`;
4. save the table (CSV or NPZ) and load it back;
5. find the downloadable benchmarks cshape knows about."""),
    code(SETUP),
    md(r"""## A folder of meshes

Your own collection is a folder such as

```
my_meshes/
    chairs/  chair1.obj  chair2.ply ...
    cups/    cup1.off ...
```

Here we write one from built-in shapes (and PyMeshLab's sample meshes) into a temporary folder, so the
notebook runs anywhere. Replace `folder` by your own."""),
    code('''\
import tempfile
from pathlib import Path

from cshape import variants


def write_obj(mesh, path):
    """A minimal Wavefront OBJ writer (vertices and triangles)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w") as f:
        f.writelines(f"v {x:.9g} {y:.9g} {z:.9g}\\n" for x, y, z in mesh.vertices)
        f.writelines(f"f {a + 1} {b + 1} {c + 1}\\n" for a, b, c in mesh.faces)


work = Path(tempfile.mkdtemp(prefix="cshape-own-"))
folder = work / "my_meshes"
s = 2 if SMALL else 4
for k in range(3):
    write_obj(shapes.icosphere(s, radius=1 + 0.5 * k), folder / "spheres" / f"sphere{k}.obj")
    write_obj(shapes.torus(16 * (k + 2), 8 * (k + 2)), folder / "tori" / f"torus{k}.obj")
    write_obj(shapes.cube(4 + 2 * k + (0 if SMALL else 6)), folder / "cubes" / f"cube{k}.obj")
    human = variants.articulated_figure("human", k, voxelsize=0.05 if SMALL else 0.03,
                                        target_vertices=500 if SMALL else 2000)
    write_obj(human, folder / "humans" / f"human{k}.obj")
print(sorted(str(p.relative_to(folder)) for p in folder.rglob("*.obj")))'''),
    code('''\
import cshape.data

coll = cshape.data.load_folder(folder, labels="subfolder")
print(coll)
print(list(zip(coll.names, coll.labels, strict=True)))'''),
    md(r"""## Descriptors, cached

`batch.describe` stores each mesh's eigenvalues in the cache folder under a key made from the mesh's
*content* (and the boundary condition): renaming or moving a file does not invalidate it, changing a vertex
does. Only `N` eigenvalues per mesh are kept; every descriptor (any `M`) is derived from them."""),
    code('''\
import time

from cshape import batch

N, M = (30, 8) if SMALL else (100, 16)
cache = work / "cache"
t0 = time.perf_counter()
table = batch.describe(coll, N=N, M=M, cache_dir=cache, progress=False)
print(f"first run:  {time.perf_counter() - t0:5.2f} s, "
      f"from cache: {table.cached.sum()} of {len(table)}")
t0 = time.perf_counter()
table = batch.describe(coll, N=N, M=M, cache_dir=cache, progress=False)
print(f"second run: {time.perf_counter() - t0:5.2f} s, "
      f"from cache: {table.cached.sum()} of {len(table)}")
table'''),
    md(r"""### In parallel

`n_jobs=2` computes in two worker processes (each with one BLAS thread). In a script, guard the entry
point with `if __name__ == "__main__":`. For a cluster, pass a Dask client (or a scheduler address) as
`client=`; the cache stays on this machine."""),
    code('''\
t0 = time.perf_counter()
par = batch.describe(coll, N=N, M=M, cache_dir=work / "cache-parallel", n_jobs=2,
                     progress=False)
print(f"2 processes: {time.perf_counter() - t0:5.2f} s;",
      "same eigenvalues:", np.allclose(par.lam, table.lam))'''),
    code('''\
try:
    from dask.distributed import Client
except ImportError:
    print("Dask is not installed: pip install 'cshape[distributed]'")
else:
    with Client(processes=False, n_workers=1, threads_per_worker=2,
                dashboard_address=None) as client:
        t0 = time.perf_counter()
        dsk = batch.describe(coll, N=N, M=M, cache_dir=False, client=client, progress=False)
        print(f"Dask (in-process cluster): {time.perf_counter() - t0:5.2f} s;",
              "same eigenvalues:", np.allclose(dsk.lam, table.lam))'''),
    md(r"""## Which stored shape is this?

`compare.DescriptorIndex` answers nearest-neighbour queries against a database of descriptors. We query a
shape the collection has never seen: a noisy, rotated, larger copy of one of the tori (rotation and scale do
not change the normalised spectrum; the noise does, a little)."""),
    code('''\
from cshape import compare

index = compare.DescriptorIndex(table.descriptors("cshape", M=M))
base = coll["torus1"].mesh
c, s_ = np.cos(0.7), np.sin(0.7)
R = np.array([[c, -s_, 0], [s_, c, 0], [0, 0, 1]])
query = cshape.Mesh(1.7 * base.vertices @ R.T, base.faces)
query = variants.add_normal_noise(query, 0.3, random_state=1)
q = cshape.compact_shape_dna_real(query, M=M, N=N)
dist, ind = index.query(q, k=3)
for d, i in zip(dist[0], ind[0], strict=True):
    print(f"{table.names[i]:10s} ({table.labels[i]:7s}) distance {d:8.3f}")
plots.plot_mesh(query, title="the query: a noisy, rotated, scaled torus", edges=False)'''),
    md(r"""## Save the table, load it back

CSV (a metadata line, then one row per shape: name, label, area, eigenvalues) is easy to read anywhere; NPZ is
compact. Both round-trip exactly."""),
    code('''\
csv_path = table.save(work / "descriptors.csv")
npz_path = table.save(work / "descriptors.npz")
back = batch.DescriptorTable.load(csv_path)
print(back, "| identical:", np.array_equal(back.lam, table.lam) and back.names == table.names)
print("".join(csv_path.read_text().splitlines(keepends=True)[:3])[:400], "...")'''),
    md(r"""## Benchmarks

`cshape data list` (or `cshape.data.list_collections()`) shows every collection cshape knows: generated ones
(built on your machine), PyMeshLab's samples, downloadable ones (fetched only when you ask:
`cshape data build NAME`), and benchmarks whose terms ask you to download them by hand (McGill, the paper's
database; TOSCA; SHREC'07): the description says where they go."""),
    code('''\
for name in cshape.data.list_collections():
    info = cshape.data.info(name)
    print(f"{name:20s} {info['kind']:9s} {info['description'][:90]}...")'''),
    md(r"""## Exercises

1. Point `folder` at your own meshes (or at the project's `../shared/meshes` if you have it: labels come from the
   sub-folders) and draw the MDS plot of notebook 4 for them.
2. Interrupt a `describe` run on a large collection (Kernel > Interrupt) and run it again: how many meshes
   come from the cache?
3. Measure the time of `describe` for `n_jobs=1` and `n_jobs=2` on 20 meshes of 5000 vertices. Where is the
   time spent: FEM assembly or the eigensolve? (`cshape.fem_matrices` vs `cshape.shape_dna`.)
4. Build a `DescriptorIndex` of the F1 features and of the cShape-DNA with $M = 2$. Which one finds the torus?"""),
]

# =============================================================================== 07
NB07 = [
    md(r"""# 7 · The parameter $M$, interactively

**Paper:** Section 3.2, Fig. 6 (and Fig. 3-4).

**Learning goals.** After this notebook you can

1. predict how the descriptor size $2M+1$ trades accuracy for space;
2. read the scaled distance matrices of Shape-DNA and cShape-DNA (values in $[0, 255]$) and their difference,
   with its mean and standard deviation, the paper's measure of "how much worse" (Fig. 6 e-h);
3. use the M-sweep widget: eigenvalues are computed once; moving the slider reruns only the cheap stages (crop,
   distances, statistics, MDS).

The paper reports, for the McGill database and $N = 100$, difference means 1.3, 2.3, 4.8 and 6.0 for
$M = 8, 4, 2, 1$. Our collection is smaller and made in code, so the numbers differ; the trend should not."""),
    code(SETUP),
    code(DEMO_COLLECTION + '''


N = 40 if SMALL else 100
table = batch.describe(demo_collection(), N=N, progress=not SMALL)
table'''),
    md(r"""## The pure functions behind the widget

`widgets.MSweep` holds the eigenvalues and caches everything that does not depend on $M$;
`sweep.state(M)` returns a `SweepState` with the cropped coefficients, the reconstruction, the scaled distance
matrices, their difference, its mean and standard deviation, and the MDS coordinates."""),
    code('''\
from cshape import widgets

sweep = widgets.MSweep.from_table(table)
for M in [16, 8, 4, 2, 1]:
    if 2 * M + 1 <= N:
        print(sweep.state(M, N).summary())'''),
    md(r"""## Fig. 6 for this collection

Top: cShape-DNA distance matrices for $M = 8, 4, 2, 1$, scaled to $[0, 255]$. Bottom: their absolute difference
from the Shape-DNA matrix ($N$ eigenvalues), on one colour scale."""),
    code('''\
states = [sweep.state(M, N) for M in (8, 4, 2, 1)]
plots.plot_matrices([s.D for s in states], [f"M = {s.M}" for s in states], vmax=255)'''),
    code('''\
plots.plot_matrices([s.difference for s in states],
                    [f"M = {s.M}: mean {s.mean:.1f}, std {s.std:.1f}" for s in states])'''),
    md(r"""## The widget

Move **M** (and try **N**, the collection, the normalisation and the shape whose DFT is drawn). Each change reruns only the
cheap stages; the eigenvalues above are not recomputed. $M$ is clamped to $[0, (N-1)/2]$."""),
    code('''\
no_spheres = table.select([i for i, lab in enumerate(table.labels) if lab != "sphere"])
w = widgets.m_sweep_widget({"all shapes": table, "without spheres": no_spheres}, M=8, N=N)
w'''),
    md(r"""A widget needs a live kernel; in a static copy of this notebook (an HTML export, a viewer on the web)
it shows as text. Its current picture, as a plain figure:"""),
    code('''\
plots.plot_m_sweep(w.state, shape=int(w.controls["shape"].value))'''),
    md(r"""## Exercises

1. Find the smallest $M$ for which every shape's nearest neighbour is still in its own class (the statistics
   line shows the nearest-neighbour rate).
2. With the normalisation set to `'fiedler'`, does the difference from Shape-DNA grow or shrink? Why might the
   Weyl-line subtraction of Eq. (8) suit the area normalisation best?
3. Lower $N$ to 20: how do the difference statistics for $M = 4$ change, and why?
4. Add a third collection to the widget's drop-down: the table of your own meshes from notebook 6
   (`batch.DescriptorTable.load("descriptors.csv")`), or only the articulated figures of this one."""),
]


NOTEBOOKS = {
    "01_fem_assembly.ipynb": NB01,
    "02_shape_dna_weyl.ipynb": NB02,
    "03_dft_compression.ipynb": NB03,
    "04_mds_classification.ipynb": NB04,
    "05_noise_quality.ipynb": NB05,
    "06_own_collection.ipynb": NB06,
    "07_m_sweep.ipynb": NB07,
}


def make_notebook(stem, cells):
    """An nbformat v4 notebook with stable cell ids and no outputs."""
    nb = nbformat.v4.new_notebook()
    nb.metadata = {
        "kernelspec": {"display_name": "Python 3", "language": "python", "name": "python3"},
        "language_info": {"name": "python"},
    }
    for k, (kind, text) in enumerate(cells):
        cell = (nbformat.v4.new_markdown_cell if kind == "markdown" else nbformat.v4.new_code_cell)(
            text
        )
        cell["id"] = f"{stem[:2]}-{k:02d}"
        nb.cells.append(cell)
    nbformat.validate(nb)
    return nb


def main(argv=None):
    names = (argv or sys.argv[1:]) or list(NOTEBOOKS)
    for name in names:
        nb = make_notebook(Path(name).stem, NOTEBOOKS[name])
        nbformat.write(nb, HERE / name)
        print("wrote", HERE / name)


if __name__ == "__main__":
    main()
