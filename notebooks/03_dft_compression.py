# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 3 · Compressing the Shape-DNA with the DFT: the compact Shape-DNA
#
# **Paper:** Gao, Yu and Pang, *A compact shape descriptor for triangular surface meshes*, Computer-Aided Design 53 (2014) 62-69; Section 2.3, Eq. (8)-(10), Fig. 2 (e)-(f).
#
# **Learning goals.** After this notebook you can
#
# 1. implement the three steps of the cShape-DNA yourself: subtract the Weyl line (Eq. 8), take the DFT (Eq. 9),
#    shift and crop the $2M+1$ lowest frequencies (Eq. 10);
# 2. read a shifted DFT magnitude plot and explain why the low frequencies dominate;
# 3. rebuild the Shape-DNA from the $2M+1$ coefficients and measure what is lost as $M$ shrinks;
# 4. store the complex descriptor as $2M+1$ real numbers with the same Euclidean distances.
#
# **The equations.**
#
# $$\lambda'_k = \lambda^{norm}_k - 4\pi k \quad (8) \qquad
# \Lambda_i = \sum_{k=0}^{N-1} \lambda'_k\, e^{-j 2\pi i k / N},\quad i = 0, \dots, N-1 \quad (9)$$
#
# $$\mathcal S^c = \left(\Lambda^{shift}_{\langle N/2\rangle - M}, \dots, \Lambda^{shift}_{\langle N/2\rangle + M}\right) \quad (10)$$
#
# where $\Lambda^{shift}$ is $\Lambda$ circularly shifted so that the zero frequency sits at index
# $\langle N/2 \rangle$ (NumPy's `fftshift`). $\mathcal S^c[M]$ is the zero frequency, $\mathcal S^c[M \pm k]$ the
# frequencies $\pm k$.

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


# %% nbgrader={"grade": false, "grade_id": "check_close", "locked": true, "schema_version": 3, "solution": false, "task": false}
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


N = size(50, 100)
M = size(8, 16)
real, real_name = real_mesh()
lam = cshape.shape_dna(real, N)
lam_norm = cshape.normalize(lam, real.area)  # the area normalisation of Section 2.1
print(real_name, "- N =", N, ", M =", M)


# %% [markdown]
# ## Exercise 1 (graded): subtract the Weyl line, Eq. (8)
#
# Write `weyl_subtract_mine(lam_norm)` returning $\lambda'_k = \lambda^{norm}_k - 4\pi k$ for $k = 0, \dots, N-1$
# (no loop needed: `np.arange`).

# %% nbgrader={"grade": false, "grade_id": "weyl_subtract_mine", "locked": false, "schema_version": 3, "solution": true, "task": false}
def weyl_subtract_mine(lam_norm):
    """Eq. (8): lam'_k = lam_norm_k - 4 pi k."""
    ### BEGIN SOLUTION
    lam_norm = np.asarray(lam_norm, dtype=float)
    return lam_norm - 4 * np.pi * np.arange(len(lam_norm))
    ### END SOLUTION


# %% nbgrader={"grade": true, "grade_id": "test_weyl_subtract_mine", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
lam_prime = weyl_subtract_mine(lam_norm)
check_close("lam'", lam_prime, cshape.weyl_subtract(lam_norm),
            hint="The line is 4 pi k with k starting at 0 (lam'_0 = lam_norm_0).")

# %% nbgrader={"grade": true, "grade_id": "hidden_weyl_subtract_mine", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
# hidden tests: the autograder runs more checks here
### BEGIN HIDDEN TESTS
check_close("weyl_subtract_mine([0, 1, 2])", weyl_subtract_mine([0.0, 1.0, 2.0]),
            [0.0, 1 - 4 * np.pi, 2 - 8 * np.pi])
### END HIDDEN TESTS

# %% [markdown]
# ## Exercise 2 (graded): the DFT, Eq. (9), from its definition
#
# Write `dft_mine(x)` computing $\Lambda_i = \sum_k x_k e^{-j2\pi ik/N}$ *from the sum* (an $N\times N$ matrix of
# exponentials is fine; no `np.fft`). Python writes $j$ as `1j`.

# %% nbgrader={"grade": false, "grade_id": "dft_mine", "locked": false, "schema_version": 3, "solution": true, "task": false}
def dft_mine(x):
    """Eq. (9): Lambda_i = sum_k x_k exp(-j 2 pi i k / N), i = 0..N-1."""
    ### BEGIN SOLUTION
    x = np.asarray(x, dtype=float)
    n = len(x)
    k = np.arange(n)
    return np.exp(-2j * np.pi * np.outer(k, k) / n) @ x
    ### END SOLUTION


# %% nbgrader={"grade": true, "grade_id": "test_dft_mine", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
Lam = dft_mine(lam_prime)
if np.allclose(Lam, np.conj(np.fft.fft(lam_prime))) and not np.allclose(Lam, np.fft.fft(lam_prime)):
    print("hint: you computed the conjugate: the exponent of Eq. (9) has a minus sign")
check_close("Lambda", Lam, np.fft.fft(lam_prime), hint="Sum over k of x_k exp(-2j pi i k / N).")

# %% nbgrader={"grade": true, "grade_id": "hidden_dft_mine", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
# hidden tests: the autograder runs more checks here
### BEGIN HIDDEN TESTS
_x = np.random.default_rng(0).standard_normal(7)
check_close("dft_mine(odd length)", dft_mine(_x), np.fft.fft(_x))
check_close("dft_mine(impulse)", dft_mine([1.0, 0, 0, 0]), np.ones(4))
### END HIDDEN TESTS

# %% [markdown]
# ## Exercise 3 (graded): shift and crop, Eq. (10)
#
# Write `crop_mine(Lam, M)`: shift the zero frequency to the centre index `N // 2` (`np.fft.fftshift`), then keep
# the $2M+1$ values from `N//2 - M` to `N//2 + M` inclusive. The result is the cShape-DNA.

# %% nbgrader={"grade": false, "grade_id": "crop_mine", "locked": false, "schema_version": 3, "solution": true, "task": false}
def crop_mine(Lam, M):
    """Eq. (10): the 2M+1 shifted DFT coefficients around the centre <N/2>."""
    ### BEGIN SOLUTION
    shifted = np.fft.fftshift(Lam)
    c = len(Lam) // 2
    return shifted[c - M : c + M + 1]
    ### END SOLUTION


# %% nbgrader={"grade": true, "grade_id": "test_crop_mine", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
S_mine = crop_mine(Lam, M)
S = cshape.compact_shape_dna(lam, M=M, N=N, area=real.area)
check_close("S_c", S_mine, S, hint="Length 2M+1, centred on index N // 2 of the shifted vector; "
            "the middle value S_c[M] is the zero frequency Lambda_0.")

# %% nbgrader={"grade": true, "grade_id": "hidden_crop_mine", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
# hidden tests: the autograder runs more checks here
### BEGIN HIDDEN TESTS
for _n in (9, 10):
    _x = np.arange(_n, dtype=float) ** 1.5
    check_close(f"crop_mine(N={_n}, M=2)", crop_mine(np.fft.fft(cshape.weyl_subtract(_x)), 2),
                cshape.compact_shape_dna(_x, M=2, N=_n, normalization="none"))
### END HIDDEN TESTS

# %% [markdown]
# ## The picture of Eq. (9)-(10): Fig. 2 (e)-(f)
#
# (e) The magnitudes of the shifted DFT: the low frequencies in the middle carry most of the energy. (f) The
# $2M+1$ kept values, the cShape-DNA. Right: the Weyl-subtracted Shape-DNA and what the $2M+1$ values rebuild
# (inverse DFT with the other frequencies set to zero, `cshape.inverse_compact_shape_dna`).

# %%
plots.plot_dft(lam, real.area, M, N=N)

# %% [markdown]
# ## How small can $M$ be?
#
# The reconstruction gets smoother as $M$ shrinks; the error tells how much of the spectrum's shape the descriptor
# has lost. We compare a few shapes, since the paper notes that the best $M$ depends on the shapes.

# %%
fig = plots.new_figure((7, 3.6))
ax = fig.add_subplot()
i = np.arange(N)
ax.plot(i, cshape.weyl_subtract(lam_norm), "k.", ms=4, label="lam'")
for m in [1, 2, 4, M]:
    S_m = cshape.compact_shape_dna(lam_norm, M=m, N=N, normalization="none")
    rec = cshape.inverse_compact_shape_dna(S_m, N)
    ax.plot(i, cshape.weyl_subtract(rec), lw=1.2, label=f"M={m} ({2 * m + 1} values)")
ax.set(xlabel="i", ylabel="lam'_i", title=f"reconstructions, {real_name.split(' ')[0]}")
ax.legend(fontsize="small")
fig

# %%
models = {real_name.split(" ")[0]: lam_norm}
others = {
    "sphere": shapes.icosphere(size(3, 4)),
    "cube": shapes.cube(size(8, 16)),
    "torus": shapes.torus(*size((48, 24), (96, 48))),
}
for name, m in others.items():
    models[name] = cshape.normalize(cshape.shape_dna(m, N), m.area)
Ms = np.arange(0, (N - 1) // 2 + 1)
errors = []
for ln in models.values():
    lp = cshape.weyl_subtract(ln)
    errors.append([np.linalg.norm(cshape.inverse_compact_shape_dna(
        cshape.compact_shape_dna(ln, M=int(m), N=N, normalization="none"), N, add_weyl=False) - lp)
        / np.linalg.norm(lp) for m in Ms])
plots.plot_reconstruction_error(Ms, errors, labels=list(models), N=N)

# %% [markdown]
# ## Storing the descriptor: $2M+1$ real numbers
#
# The input is real, so $\Lambda_{-k} = \overline{\Lambda_k}$: half of the complex values are redundant.
# `cshape.real_form` keeps $\mathrm{Re}\,\Lambda_0$ and $\sqrt2\,(\mathrm{Re}, \mathrm{Im})$ of
# $\Lambda_1..\Lambda_M$: $2M+1$ reals, with exactly the Euclidean distances of the complex descriptors.

# %%
S_a = cshape.compact_shape_dna(models["sphere"], M=M, N=N, normalization="none")
S_b = cshape.compact_shape_dna(models["cube"], M=M, N=N, normalization="none")
print("conjugate symmetric:", np.allclose(S_a[::-1], np.conj(S_a)))
print("complex distance:", np.linalg.norm(S_a - S_b))
print("real-form distance:", np.linalg.norm(cshape.real_form(S_a) - cshape.real_form(S_b)))
print("sizes: Shape-DNA", N, "values, cShape-DNA", len(cshape.real_form(S_a)), "values")

# %% [markdown]
# ## Exercises
#
# 1. *(graded above)* Eq. (8), (9) and (10) by hand.
# 2. **Why the line first?** Skip Eq. (8): take the DFT of the normalised Shape-DNA itself and crop it. Reconstruct
#    and compare the error with the one above. What does the jump between $\lambda_{N-1}$ and $\lambda_0$ (the DFT
#    treats the signal as periodic) do to the high frequencies?
# 3. **Even and odd $N$.** For $N = 10$ and $N = 11$, which indices of the shifted vector are kept for $M = 2$?
#    Check with `np.fft.fftshift(np.fft.fftfreq(N) * N)`.
# 4. **A budget of 9 numbers.** Compare the first 9 normalised eigenvalues with the cShape-DNA for $M = 4$:
#    which one tells the sphere from the cube better (distance between them, relative to the distance between
#    two spheres of different resolution)? Notebook 4 does this for a whole collection.
