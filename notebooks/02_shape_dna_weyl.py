# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 2 · Shape-DNA and the Weyl line
#
# **Paper:** Gao, Yu and Pang, *A compact shape descriptor for triangular surface meshes*, Computer-Aided Design 53 (2014) 62-69; Section 2.1 and 2.3, Fig. 1 and Fig. 2 (a)-(d), Eq. (8).
#
# **Learning goals.** After this notebook you can
#
# 1. compute the Shape-DNA, the $N$ smallest eigenvalues $0 = \lambda_0 \le \lambda_1 \le \dots \le \lambda_{N-1}$;
# 2. explain why every Shape-DNA lies along a straight line (Weyl's law) whose slope depends on the area only;
# 3. normalise a Shape-DNA so that it is scale invariant (by the area, the first non-zero eigenvalue, or the
#    fitted Weyl slope) and see all shapes gather around the common line $L(i) = 4\pi i$;
# 4. subtract that line (Eq. 8) and look at what remains: the part of the spectrum that tells shapes apart.
#
# **Weyl's law.** For a closed surface of area $|\mathcal M|$, $\lambda_i \sim \dfrac{4\pi}{|\mathcal M|}\, i$
# as $i \to \infty$. So $|\mathcal M| \lambda_i \approx 4\pi i$ for every shape, and
#
# $$\lambda'_i = \lambda_i^{norm} - 4\pi i, \qquad i = 0, \dots, N-1. \qquad (8)$$

# %%
# %matplotlib inline
import numpy as np

import cshape
from cshape import plots, shapes
from cshape.course.teaching import SMALL, size  # CSHAPE_SMALL=1: small meshes and N

np.set_printoptions(precision=4, suppress=True, linewidth=100)
print("cshape", cshape.__version__, "(small sizes)" if SMALL else "")


# %%
from cshape.course.teaching import real_mesh  # Spot the cow, shipped with cshape

# %% [markdown]
# ## Three shapes, three lines (Fig. 1)
#
# The paper's Fig. 1 uses the *bimba* statue, a cube and a sphere. We use a real mesh, Spot the cow (by Keenan
# Crane, public domain; a small copy ships with cshape), a cube and a sphere.

# %%
N = size(50, 100)
real, real_name = real_mesh()
models = {
    real_name.split(" ")[0]: real,
    "cube": shapes.cube(size(8, 16)),
    "sphere": shapes.icosphere(size(3, 4)),
}
spectra = {name: cshape.shape_dna(m, N) for name, m in models.items()}
areas = {name: m.area for name, m in models.items()}
for name, m in models.items():
    print(f"{name:20s} {m.n_vertices:6d} vertices, area {m.area:8.4f}, "
          f"lam_1..3 = {spectra[name][1:4]}")

# %%
fig = plots.new_figure((9, 3))
for k, (name, m) in enumerate(models.items()):
    plots.plot_mesh(m, ax=fig.add_subplot(1, 3, k + 1, projection="3d"), title=name, elev=15,
                    azim=-120 if m is real else -60, vertical_axis="y" if m is real else "z")
fig

# %%
plots.plot_weyl(spectra, areas)

# %% [markdown]
# Left: each raw Shape-DNA lies along its own line; a larger shape has smaller eigenvalues (a bigger drum sounds
# lower). Right: multiplied by the area, all three lie around the dashed line $4\pi i$.
#
# ## Scale invariance
#
# Scaling a surface by $s$ multiplies its area by $s^2$ and divides its eigenvalues by $s^2$: the raw Shape-DNA
# changes, the normalised one does not.

# %%
mesh = models["cube"]
big = cshape.Mesh(2.0 * mesh.vertices, mesh.faces)
lam_small, lam_big = spectra["cube"][:6], cshape.shape_dna(big, 6)
print("raw:              ", lam_small, "\n                  ", lam_big)
print("area-normalised:  ", cshape.normalize(lam_small, mesh.area), "\n                  ",
      cshape.normalize(lam_big, big.area))

# %% [markdown]
# ### Three normalisations
#
# `cshape.normalize(lam, area, normalization=...)` offers the paper's choice `'area'` and two others from the Shape-DNA
# literature: `'fiedler'` divides by the first non-zero eigenvalue, `'weyl'` rescales so that the least-squares
# slope of $\lambda_i$ against $i$ becomes $4\pi$ (no area needed, handy for point clouds or damaged meshes).

# %%
fig = plots.new_figure((11, 3.2))
axs = fig.subplots(1, 3)
for ax, norm in zip(axs, ["area", "fiedler", "weyl"], strict=True):
    for name, lam in spectra.items():
        ax.plot(cshape.normalize(lam, areas[name], normalization=norm), ".", ms=3, label=name)
    ax.set(title=f"normalization='{norm}'", xlabel="i")
axs[0].plot(4 * np.pi * np.arange(N), "k--", lw=1, label="4 pi i")
axs[0].legend(fontsize="small")
fig

# %% [markdown] nbgrader={"grade": false, "grade_id": "weyl_task", "locked": true, "schema_version": 3, "solution": false, "task": false}
# ## Exercise (graded): the Weyl line and the `'weyl'` normalisation
#
# After the area normalisation the eigenvalues lie around the Weyl line $4\pi i$ for $i = 0, \dots, N-1$:
# $\lambda_0 = 0$ sits on it at $i = 0$. The `'weyl'` normalisation uses that line without the area: fit the
# slope $s$ of $\lambda_i \approx s\,i$ by least squares through the origin, $s = \sum_i i\,\lambda_i / \sum_i i^2$
# ($i = 0, \dots, N-1$), and multiply the eigenvalues by $4\pi / s$.
#
# Write `weyl_line(N)`, the $N$ values of the line, and `weyl_normalize_mine(lam)`. The check below them prints
# hints; the autograder also runs hidden checks.

# %% nbgrader={"grade": false, "grade_id": "weyl_normalize_mine", "locked": false, "schema_version": 3, "solution": true, "task": false}
def weyl_line(N):
    """The Weyl line 4 pi i, i = 0..N-1, shape (N,)."""
    ### BEGIN SOLUTION
    return 4 * np.pi * np.arange(N)
    ### END SOLUTION


def weyl_normalize_mine(lam):
    """lam * 4 pi / s, with s the least-squares slope of lam_i ~ s i (i = 0..N-1), shape (N,)."""
    ### BEGIN SOLUTION
    lam = np.asarray(lam, dtype=float)
    i = np.arange(len(lam))
    return lam * (4 * np.pi / ((i @ lam) / (i @ i)))
    ### END SOLUTION


# %% nbgrader={"grade": true, "grade_id": "test_weyl_normalize_mine", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
line = weyl_line(N)
assert np.shape(line) == (N,), f"weyl_line(N) must hold N = {N} values, got shape {np.shape(line)}"
assert np.allclose(np.diff(line), 4 * np.pi), "consecutive values of the line differ by 4 pi"
if not np.isclose(line[0], 0.0):
    print(f"hint: your line starts at {line[0]:.4f}; it starts at i = 0, "
          "where lam_0 = 0 lies on it")
lam_cube = spectra["cube"]
mine = weyl_normalize_mine(lam_cube)
assert np.shape(mine) == np.shape(lam_cube), "weyl_normalize_mine(lam) has the length of lam"
assert np.allclose(weyl_normalize_mine(3.0 * lam_cube), mine), (
    "the normalisation is scale invariant: lam and 3 lam must give the same result")
_i = np.arange(N)
if not np.isclose((_i @ mine) / (_i @ _i), 4 * np.pi):
    print("hint: the least-squares slope of your result against i = 0..N-1 should be 4 pi, it is "
          f"{(_i @ mine) / (_i @ _i):.4f}: fit against i = 0..N-1, through the origin")
print("visible checks passed")

# %% nbgrader={"grade": true, "grade_id": "hidden_weyl_normalize_mine", "locked": true, "points": 2, "schema_version": 3, "solution": false, "task": false}
# hidden tests: the autograder runs more checks here
### BEGIN HIDDEN TESTS
assert np.allclose(weyl_line(3), [0.0, 4 * np.pi, 8 * np.pi]), "weyl_line(3) is [0, 4 pi, 8 pi]"
_small = [0.0, 2.0, 3.0]
assert np.allclose(weyl_normalize_mine(_small),
                   cshape.normalize(_small, normalization="weyl")), _small
for _name, _lam in spectra.items():
    assert np.allclose(weyl_normalize_mine(_lam),
                       cshape.normalize(_lam, normalization="weyl")), _name
### END HIDDEN TESTS

# %% [markdown]
# ## One shape through the pipeline (Fig. 2 a-d)
#
# (a) the model, here coloured by one of its eigenfunctions; (b) its Shape-DNA; (c) multiplied by the area, around
# the Weyl line; (d) the Weyl line subtracted, Eq. (8).

# %%
basis = cshape.eigenbasis(real, N)  # the eigenpairs, with B, the area and the mesh
lam, phi = basis.lam, basis.phi
plots.plot_mesh(real, phi[:, 6], title=f"(a) {real_name.split(' (')[0]}: phi_6", elev=15, azim=-120,
                vertical_axis="y", figsize=(5, 5))

# %%
plots.plot_shape_dna_stages(lam, real.area, name=real_name.split(" ")[0])

# %% [markdown]
# Low eigenfunctions vary slowly over the whole shape (they "see" its global layout: legs, head, body); higher
# ones oscillate faster. That is why the first eigenvalues already describe the shape.

# %%
plots.plot_eigenfunctions(real, phi, [1, 2, 3, 5, 10, 20, 30, N - 1], lam, elev=15, azim=-120,
                          vertical_axis="y")

# %% [markdown]
# ### Turn it by hand
#
# The picture above is flat and fixed (it is what a PDF export keeps). Below, the same eigenfunctions on a mesh you
# can **drag to rotate** and **scroll to zoom**; the **slider** steps through $\varphi_i$, with $\lambda_i$ in the
# title. Red and blue are the two signs, white the *nodal lines* where $\varphi_i = 0$: count the nodal domains
# (the regions of one sign) as $i$ grows. The colour range of every mode is symmetric about 0, because the sign
# of an eigenfunction is arbitrary. The eigenfunctions are the ones computed above (`basis=`), not recomputed.

# %%
plots.eigenfunction_explorer(real, 21, basis=basis, vertical_axis="y")

# %% [markdown]
# On a symmetric shape eigenvalues repeat. The sphere's are $\ell(\ell+1)/r^2$ with multiplicity $2\ell+1$: slide
# through $i = 1, 2, 3$ ($\ell = 1$), then $i = 4..8$ ($\ell = 2$). Modes of one $\lambda$ are rotated copies of one
# pattern (or mixtures of them): the solver may return any orthonormal basis of that eigenspace, which is one
# reason why Shape-DNA keeps the eigenvalues and not the eigenfunctions.

# %%
plots.eigenfunction_explorer(models["sphere"], 16)

# %% [markdown]
# ## What is left after Eq. (8)
#
# $\lambda'_i$ wiggles around zero with a slow trend that differs from shape to shape. The next notebook compresses
# exactly this signal with a discrete Fourier transform.

# %%
fig = plots.new_figure((6, 3.5))
ax = fig.add_subplot()
for name, lam_i in spectra.items():
    lam_prime = cshape.weyl_subtract(cshape.normalize(lam_i, areas[name]))
    ax.plot(lam_prime, ".-", ms=3, lw=0.7, label=name)
ax.axhline(0, color="k", lw=0.6)
ax.set(xlabel="i", ylabel="lam'_i", title="Eq. (8) for the three models")
ax.legend(fontsize="small")
fig

# %% [markdown]
# ## Exercises
#
# 1. **Isometry.** Bend a mesh without stretching it (e.g. `cshape.data.variants.articulated_figure("human", seed)` for
#    two seeds gives two poses with the same bone lengths). Compare their normalised Shape-DNAs with those of two
#    different classes.
# 2. **How many eigenvalues?** Plot $\lambda'_i$ of the sphere for $N = 100$. Why does it look like a staircase?
#    (Hint: multiplicities $2\ell+1$.)
# 3. **Without the area.** Compute the `'weyl'` normalisation of the real mesh and compare it with the `'area'` one.
#    When would you prefer it?
# 4. **Resolution.** `cshape.course.teaching.spot()` is the shipped Spot (829 vertices); make two other
#    triangulations of the same shape, `cshape.data.variants.subdivide(spot(), 1)` (Loop subdivision, about 4x the
#    triangles) and `cshape.data.variants.remesh(spot(), target_vertices=2000)` (isotropic remeshing). How far apart
#    are the three normalised Shape-DNAs, relative to their distance to the cube's?
