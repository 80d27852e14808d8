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
# 2. derive Weyl's law on a surface whose eigenvalues are known in closed form (the flat torus), by counting
#    lattice points, and see it hold on meshes: why every Shape-DNA lies along a straight line whose slope
#    depends on the area only;
# 3. normalise a Shape-DNA so that it is scale invariant (by the area, the first non-zero eigenvalue, or the
#    fitted Weyl slope) and see all shapes gather around the common line $L(i) = 4\pi i$;
# 4. subtract that line (Eq. 8) and say what it does and does not do: it removes the trend that all shapes share,
#    so that what remains is a small signal around zero, ready for the DFT of lesson 03; it changes no distance
#    between two normalised Shape-DNAs (lesson 08 shows it).
#
# *Prerequisites:* lesson 01 (the eigenproblem), the area of a disk. *Time:* about 1.5 hours, with the exercises
# at the end another 1.5.
#
# **Weyl's law.** For a closed surface of area $|\mathcal M|$, the number of eigenvalues up to $\lambda$ grows like
#
# $$N(\lambda) = \#\{i : \lambda_i \le \lambda\} \sim \frac{|\mathcal M|}{4\pi}\,\lambda \qquad (\lambda\to\infty),$$
#
# or, turned around, $\lambda_i \sim \dfrac{4\pi}{|\mathcal M|}\, i$. So $|\mathcal M| \lambda_i \approx 4\pi i$ for
# every shape, and Eq. (8) subtracts that common line:
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
# ## Why a straight line: Weyl's law on a flat torus
#
# One surface has eigenvalues we can write down: the **flat torus**, the rectangle $[0, a]\times[0, b]$ whose
# opposite sides are glued (a video-game screen: leave on the right, come back on the left). It has no boundary
# and no curvature, and its area is $|\mathcal M| = ab$.
#
# **Step 1: the eigenfunctions.** A function on it must be periodic in $x$ with period $a$ and in $y$ with period
# $b$. The waves $f_{mn}(x, y) = e^{2\pi \mathrm i\,(m x/a + n y/b)}$ with integers $m, n$ are, and
# $$\Delta f_{mn} = \partial_x^2 f_{mn} + \partial_y^2 f_{mn} = -4\pi^2\Big(\frac{m^2}{a^2} + \frac{n^2}{b^2}\Big) f_{mn},
# \qquad \lambda_{mn} = 4\pi^2\Big(\frac{m^2}{a^2} + \frac{n^2}{b^2}\Big).$$
# They are all of them (a Fourier series in $x$ and $y$ is complete). Each pair $(m, n) \in \mathbb Z^2$ counts
# once: $(m, n)$ and $(-m, -n)$ give the real eigenfunctions $\cos$ and $\sin$ of $2\pi(mx/a + ny/b)$.
#
# **Step 2: count.** $\lambda_{mn} \le \lambda$ says that the point $(m/a,\ n/b)$ lies in the disk of radius
# $r = \sqrt\lambda / (2\pi)$. These points form a lattice with one point per cell of area $\frac1a\cdot\frac1b$,
# so the disk holds about (its area) / (cell area) of them:
#
# $$N(\lambda) \approx \frac{\pi r^2}{1/(ab)} = \pi\,\frac{\lambda}{4\pi^2}\,ab = \frac{|\mathcal M|}{4\pi}\,\lambda .$$
#
# The error is at most the number of cells that the circle crosses, of the order of its perimeter, $O(\sqrt\lambda)$:
# relative to $N(\lambda)$ it vanishes as $\lambda$ grows. That is Weyl's law, and it says that the slope of
# $\lambda_i$ against $i$ is $4\pi/|\mathcal M|$, whatever $a$ and $b$ are.
#
# **Step 3: any surface.** Weyl (1911) proved the same leading term for plane domains, and it holds for every
# compact surface (Minakshisundaram and Pleijel 1949). The idea: cut the surface into small, nearly flat pieces;
# at high $\lambda$ the waves are short, each piece holds about its area $/4\pi$ times $\lambda$ of them, and the
# cuts and the curvature change only lower-order terms. Curvature, topology and the finer features of the shape
# live in what is left over, the remainder that Eq. (8) keeps.
#
# ## Exercise 1 (graded): the spectrum of the flat torus
#
# Write `flat_torus_spectrum(a, b, N)`, the $N$ smallest eigenvalues of the flat torus $a \times b$, sorted,
# shape `(N,)`, repeated eigenvalues repeated. Make sure your range of $m, n$ is large enough for any $a$, $b$
# and $N$ (a long thin torus, $a \gg b$, needs many more values of $m$ than of $n$).

# %% nbgrader={"grade": false, "grade_id": "flat_torus_spectrum", "locked": false, "schema_version": 3, "solution": true, "task": false}
def flat_torus_spectrum(a, b, N):
    """The N smallest eigenvalues 4 pi^2 (m^2/a^2 + n^2/b^2), (m, n) in Z^2, sorted, shape (N,)."""
    ### BEGIN SOLUTION
    K = int(np.sqrt(N)) + 1
    while True:
        m = np.arange(-K, K + 1)
        lam = np.sort((4 * np.pi**2 * ((m[:, None] / a) ** 2 + (m[None, :] / b) ** 2)).ravel())[:N]
        # every (m, n) outside the box has |m| > K or |n| > K, so lambda >= 4 pi^2 (K+1)^2 / max(a, b)^2
        if lam[-1] <= 4 * np.pi**2 * (K + 1) ** 2 / max(a, b) ** 2:
            return lam
        K *= 2
    ### END SOLUTION


# %% nbgrader={"grade": true, "grade_id": "test_flat_torus_spectrum", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
_want = 4 * np.pi**2 * np.array([0, 1, 1, 1, 1, 2, 2, 2, 2])  # (0,0); (+-1,0),(0,+-1); (+-1,+-1)
_got = np.asarray(flat_torus_spectrum(1.0, 1.0, 9), dtype=float)
assert _got.shape == (9,), f"flat_torus_spectrum(1, 1, 9) must hold 9 values, got shape {_got.shape}"
if not np.isclose(_got[0], 0):
    print("hint: lam_0 = 0: the constant function, (m, n) = (0, 0)")
if np.allclose(_got, _want / 4):
    print("hint: you used pi^2: that is the rectangle with Dirichlet/Neumann sides (half waves); "
          "the glued torus needs whole waves, 4 pi^2")
if np.sum(np.isclose(_got, 4 * np.pi**2)) == 2:
    print("hint: 4 pi^2 has multiplicity 4: (1, 0), (-1, 0), (0, 1), (0, -1); negative m and n count too")
assert np.allclose(_got, _want), f"flat_torus_spectrum(1, 1, 9) = {_got.round(3)}, expected {_want.round(3)}"
print("visible checks passed")

# %% nbgrader={"grade": true, "grade_id": "hidden_flat_torus_spectrum", "locked": true, "points": 2, "schema_version": 3, "solution": false, "task": false}
# hidden tests: the autograder runs more checks here
### BEGIN HIDDEN TESTS
def _torus_ref(a, b, N, K=60, lo=-60, c=4 * np.pi**2):
    _m = np.arange(lo, K + 1)
    return np.sort((c * ((_m[:, None] / a) ** 2 + (_m[None, :] / b) ** 2)).ravel())[:N]


for _a, _b, _N in [(3.0, 1.0, 40), (1.0, 0.2, 30), (8.0, 0.5, 200), (0.5, 0.5, 1)]:
    _got = np.asarray(flat_torus_spectrum(_a, _b, _N), dtype=float)
    _ref = _torus_ref(_a, _b, _N)
    assert _got.shape == (_N,), (
        f"flat_torus_spectrum({_a}, {_b}, {_N}) has shape {_got.shape}, expected ({_N},): your range of (m, n) "
        "holds fewer than N pairs; let it grow with N and with a / b")
    if np.allclose(_got, _ref):
        continue
    if np.allclose(_got, _torus_ref(_a, _b, _N, lo=0)):
        print("hint: negative m and n count too: (m, n) and (-m, n) are different eigenfunctions")
    elif np.allclose(_got, _torus_ref(_a, _b, _N, c=np.pi**2)):
        print("hint: pi^2 is the rectangle with Dirichlet/Neumann sides; the glued torus has 4 pi^2")
    elif np.any(_got > _ref * (1 + 1e-9) + 1e-9):
        print(f"hint: for a = {_a}, b = {_b} your values are too large: your range of m or n misses small "
              "eigenvalues (a long torus needs |m| up to about a sqrt(lam_max) / (2 pi))")
    assert np.allclose(_got, _ref), f"flat_torus_spectrum({_a}, {_b}, {_N}) differs from the exact spectrum"
### END HIDDEN TESTS

# %% [markdown]
# The counting function $N(\lambda)$ of two flat tori of area 1, a square one and a long one, against Weyl's
# line $|\mathcal M|\lambda/4\pi$. Their spectra differ (different multiplicities, different steps), their slopes
# do not.

# %%
n_count = size(200, 1000)
tori = {"1 x 1": (1.0, 1.0), "4 x 1/4": (4.0, 0.25)}
fig = plots.new_figure((9, 3.4))
ax0, ax1 = fig.subplots(1, 2)
for label, (a, b) in tori.items():
    lam_t = flat_torus_spectrum(a, b, n_count)
    counts = np.arange(1, n_count + 1)  # N(lam_i) = i + 1 (ties: the last copy)
    ax0.step(lam_t, counts, where="post", label=f"torus {label}")
    ax1.plot(lam_t, counts - a * b * lam_t / (4 * np.pi), ".", ms=2, label=f"torus {label}")
    print(f"torus {label}: N({lam_t[-1]:.0f}) = {n_count}, Weyl's estimate {a * b * lam_t[-1] / (4 * np.pi):.1f}, "
          f"ratio {n_count / (a * b * lam_t[-1] / (4 * np.pi)):.4f}")
lam_grid = np.linspace(0, lam_t[-1], 200)
ax0.plot(lam_grid, lam_grid / (4 * np.pi), "k--", lw=1, label="area lam / (4 pi)")
ax0.set(xlabel="lam", ylabel="N(lam)", title="counting function, flat tori of area 1")
ax0.legend(fontsize="small")
ax1.plot(lam_grid, 2 * np.sqrt(lam_grid), "k:", lw=1)
ax1.plot(lam_grid, -2 * np.sqrt(lam_grid), "k:", lw=1, label="+- 2 sqrt(lam)")
ax1.set(xlabel="lam", ylabel="N(lam) - area lam / (4 pi)", title="the remainder grows like sqrt(lam)")
ax1.legend(fontsize="small")
fig

# %% [markdown]
# The printed ratios approach 1; the remainder (right) stays within a band that grows like $\sqrt\lambda$ (the
# dotted curves), much slower than $N(\lambda)$ itself.
#
# ### A boundary adds a second term
#
# The unit square with **Dirichlet** sides ($f = 0$ on the edge) has the eigenvalues $\pi^2(m^2 + n^2)$ with
# $m, n \ge 1$; with **Neumann** sides the same with $m, n \ge 0$. Counting lattice points in a quarter disk now
# misses (Dirichlet) or adds (Neumann) the points on the two axes, about $\sqrt\lambda/\pi$ of them, and Weyl's
# law gets a second term with the perimeter $|\partial\mathcal M|$:
#
# $$N(\lambda) \approx \frac{|\mathcal M|}{4\pi}\lambda \mp \frac{|\partial\mathcal M|}{4\pi}\sqrt\lambda .$$
#
# Below, the closed forms and a mesh of the unit square (Neumann, `shapes.square`), computed with lesson 01's
# finite elements.

# %%
n_sq = size(60, 150)
mn = np.arange(0, 60)
closed = np.pi**2 * (mn[:, None] ** 2 + mn[None, :] ** 2)
lam_dir = np.sort(closed[1:, 1:].ravel())[:n_sq]
lam_neu = np.sort(closed.ravel())[:n_sq]
square_mesh = shapes.square(size(16, 32))
lam_mesh = cshape.shape_dna(square_mesh, n_sq)
counts = np.arange(1, n_sq + 1)
fig = plots.new_figure((6.5, 3.6))
ax = fig.add_subplot()
ax.step(lam_dir, counts, where="post", label="Dirichlet, exact")
ax.step(lam_neu, counts, where="post", label="Neumann, exact")
ax.step(lam_mesh, counts, where="post", ls="--", label=f"Neumann, mesh of {square_mesh.n_vertices} vertices")
lam_grid = np.linspace(0, lam_neu[-1], 200)
ax.plot(lam_grid, lam_grid / (4 * np.pi), "k-", lw=1, label="area lam / (4 pi)")
ax.plot(lam_grid, lam_grid / (4 * np.pi) + np.sqrt(lam_grid) / np.pi, "k:", lw=1, label="with the boundary term")
ax.plot(lam_grid, lam_grid / (4 * np.pi) - np.sqrt(lam_grid) / np.pi, "k:", lw=1)
ax.set(xlabel="lam", ylabel="N(lam)", title="the unit square", xlim=(0, lam_neu[-1]))
ax.legend(fontsize="small")
fig

# %%
lam_top = lam_neu[-1]
print(f"at lam = {lam_top:.0f}: Dirichlet N = {np.sum(lam_dir <= lam_top)}, Neumann N = {np.sum(lam_neu <= lam_top)}, "
      f"the mesh's Neumann N = {np.sum(lam_mesh <= lam_top)}, area lam / (4 pi) = {lam_top / (4 * np.pi):.1f}")

# %% [markdown] nbgrader={"grade": false, "grade_id": "boundary_question", "locked": true, "schema_version": 3, "solution": false, "task": false}
# ## Exercise 2 (written, graded by hand): reading the square's counting functions
#
# In the answer cell below (5-10 lines): why does the Dirichlet count lie *below* the line $|\mathcal M|\lambda/4\pi$
# and the Neumann count *above* it, in the lattice-point picture? Why does the mesh's Neumann count fall below the
# exact Neumann count at large $\lambda$ (think of lesson 01)? And what does a boundary mean for Eq. (8), which
# subtracts the same line $4\pi i$ from every shape?

# %% [markdown] nbgrader={"grade": true, "grade_id": "boundary_answer", "locked": false, "points": 2, "schema_version": 3, "solution": true, "task": false}
# ### BEGIN SOLUTION
# The eigenvalues are the lattice points $(m, n)$ in the quarter disk $m^2 + n^2 \le \lambda/\pi^2$ of radius
# $R = \sqrt\lambda/\pi$. The area of the quarter disk, $\pi R^2/4 = \lambda/4\pi$, counts each point on the two axes
# only by half (half of its unit cell lies outside). Dirichlet ($m, n \ge 1$) drops the about $2R$ axis points, so
# it counts $\approx \lambda/4\pi - R$; Neumann ($m, n \ge 0$) keeps them whole, $\approx \lambda/4\pi + R$. With
# perimeter 4 this is $\mp|\partial\mathcal M|\sqrt\lambda/4\pi$. The mesh's eigenvalues are too large, and the more
# so the larger they are (the linear-element error grows like $h^2\lambda^2$, lesson 01), so fewer of them lie
# below a given $\lambda$. For Eq. (8): on a surface with a boundary the normalised spectrum lies below the line
# $4\pi i$ by a term growing like $\sqrt i$ (Neumann; above it with Dirichlet), so $\lambda'_i$ is not a wiggle around
# zero but a drift of order $|\partial\mathcal M|\sqrt{i}$; it still compares shapes, but the drift dominates the
# remainder.
# ### END SOLUTION

# %% [markdown]
# ## Predict, then check: the 50th eigenvalue of a cube
#
# Below we mesh the unit cube, a closed surface of area 6. Use Weyl's law to predict its eigenvalue $\lambda_{49}$
# (the 50th, counting $\lambda_0 = 0$) before you see it. Write it as `prediction = ...` (one number).

# %% nbgrader={"grade": false, "grade_id": "cube_prediction", "locked": false, "schema_version": 3, "solution": true, "task": false}
### BEGIN SOLUTION
prediction = 4 * np.pi * 49 / 6  # lam_i ~ 4 pi i / area
### END SOLUTION


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
print(f"the cube's lam_49 = {spectra['cube'][49]:.2f} (area {areas['cube']:.4f})")

# %% nbgrader={"grade": true, "grade_id": "test_cube_prediction", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
assert np.isscalar(prediction) and np.isfinite(prediction), "prediction is one number, e.g. 50.0"
### BEGIN HIDDEN TESTS
_lam49 = spectra["cube"][49]
assert abs(prediction / _lam49 - 1) < 0.15, (
    f"you predicted {prediction:.2f}, the cube's lam_49 is {_lam49:.2f}. Weyl's law: N(lam) ~ area lam / (4 pi), "
    "so lam_i ~ 4 pi i / area = 4 pi 49 / 6; a common slip is to forget the area or the 4 pi")
### END HIDDEN TESTS

# %% [markdown]
# The counting functions of the three meshes, with $\lambda$ multiplied by the area: Weyl's law says they all follow
# the one line $N = |\mathcal M|\lambda / 4\pi$. The printed ratios at the last eigenvalue tell how close.

# %%
fig = plots.new_figure((6, 3.6))
ax = fig.add_subplot()
for name, lam_m in spectra.items():
    ax.step(areas[name] * lam_m, np.arange(1, N + 1), where="post", label=name)
    print(f"{name:10s} N = {N} at area * lam = {areas[name] * lam_m[-1]:7.1f}: "
          f"N / (area lam / 4 pi) = {N / (areas[name] * lam_m[-1] / (4 * np.pi)):.3f}")
top = max(areas[name] * lam_m[-1] for name, lam_m in spectra.items())
ax.plot([0, top], [0, top / (4 * np.pi)], "k--", lw=1, label="area lam / (4 pi)")
ax.set(xlabel="area * lam", ylabel="N(lam)", title="counting functions of three meshes")
ax.legend(fontsize="small")
fig

# %% [markdown]
# The same in the paper's form, Fig. 1: the Shape-DNA against its index.

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
# ## Exercise 3 (graded): the Weyl line and the `'weyl'` normalisation
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
# $\lambda'_i$ wiggles around zero with a slow trend that differs from shape to shape: the lower-order terms of
# Weyl's law, which carry curvature and shape. Eq. (8) subtracts the *same* line from every normalised Shape-DNA,
# so it does not change the difference of two of them, nor their distance: it adds no information and removes
# none (lesson 08 measures this). What it changes is the signal's form: a small sequence around zero instead of a
# steep ramp, which is what the discrete Fourier transform of lesson 03 compresses well.

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
# 1. *(graded above)* The flat torus's spectrum, the square's counting functions (written), the cube's
#    $\lambda_{49}$ (prediction), the Weyl line and the `'weyl'` normalisation.
# 2. **Isometry.** Bend a mesh without stretching it (e.g. `cshape.data.bodies.articulated_figure("human", seed)` for
#    two seeds gives two poses with the same bone lengths). Compare their normalised Shape-DNAs with those of two
#    different classes.
# 3. **How many eigenvalues?** Plot $\lambda'_i$ of the sphere for $N = 100$. Why does it look like a staircase?
#    (Hint: multiplicities $2\ell+1$; compare with the flat torus's counting function above.)
# 4. **Without the area.** Compute the `'weyl'` normalisation of the real mesh and compare it with the `'area'` one.
#    When would you prefer it?
# 5. **Resolution, and what is the same shape.** `real_mesh()` is the shipped Spot. Make three other meshes from it:
#    `cshape.data.variants.subdivide(mesh, 1, method="midpoint")` splits every triangle into four (the same
#    polyhedron, finer); `cshape.data.variants.subdivide(mesh, 1)` is Loop subdivision, which also *smooths* the
#    surface (a slightly different shape: compare the areas); `cshape.data.variants.remesh(mesh,
#    target_vertices=2000)` remeshes the surface isotropically. How far apart are the four normalised Shape-DNAs,
#    relative to their distance to the cube's? Which change moves the spectrum most, and why?
# 6. **A long torus.** Weyl's law holds for the $4 \times \tfrac14$ flat torus, yet its first eigenvalues are far
#    from the line (plot $\lambda_i$ against $4\pi i / |\mathcal M|$ for $i < 20$). Why, and what does it say about
#    using few eigenvalues for thin shapes?
#
# ## References
#
# - Gao, Yu and Pang (2014). A compact shape descriptor for triangular surface meshes. *Computer-Aided Design* 53,
#   62-69. (Section 2.1 and 2.3, Eq. 8.)
# - Weyl (1911). Über die asymptotische Verteilung der Eigenwerte. *Nachrichten der Gesellschaft der Wissenschaften
#   zu Göttingen*, 110-117. (The law $N(\lambda) \sim |\mathcal M|\lambda / 4\pi$.)
# - Reuter, Wolter and Peinecke (2006). Laplace-Beltrami spectra as "Shape-DNA" of surfaces and solids.
#   *Computer-Aided Design* 38(4), 342-366. (The Shape-DNA, its normalisations and Weyl's law for surfaces.)
# - Reuter, Biasotti, Giorgi, Patanè and Spagnuolo (2009). Discrete Laplace-Beltrami operators for shape analysis
#   and segmentation. *Computers & Graphics* 33(3), 381-390.
# - Minakshisundaram and Pleijel (1949). Some properties of the eigenfunctions of the Laplace-operator on
#   Riemannian manifolds. *Canadian Journal of Mathematics* 1, 242-256. (Weyl's law on closed manifolds.)
# - Kac (1966). Can one hear the shape of a drum? *The American Mathematical Monthly* 73(4), 1-23. (Area and
#   perimeter from the spectrum: the two terms of the counting function.)
