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
# 2. read a shifted DFT magnitude plot and explain, with a computation, why the low frequencies dominate: the DFT
#    sees a periodic sequence, and the jump at its seam makes a sawtooth whose coefficients fall like $1/k$;
# 3. rebuild the Shape-DNA from the $2M+1$ coefficients and measure what is lost as $M$ shrinks;
# 4. store the complex descriptor as $2M+1$ real numbers with the same Euclidean distances.
#
# *Prerequisites:* lesson 02 (Eq. 8), the DFT (complex exponentials, a geometric series). *Time:* about 1.5 hours,
# with the exercises at the end another hour.
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
# (inverse DFT with the other frequencies set to zero, `cshape.descriptors.inverse_compact_shape_dna`).

# %%
plots.plot_dft(lam, real.area, M, N=N)

# %% [markdown]
# ## Predict, then check: how fast does a sawtooth's DFT fall?
#
# Take the ramp $g_k = k$, $k = 0, \dots, 99$. The DFT sees it as one period of a periodic sequence, i.e. as a
# sawtooth: it climbs by 1 per step and falls by 99 from $k = 99$ back to $k = 100 \equiv 0$. Predict the ratio
# $|G_{10}| / |G_1|$ of its DFT magnitudes at frequencies 10 and 1, before the next section computes it. Write it as
# `prediction = ...` (one number).

# %% nbgrader={"grade": false, "grade_id": "sawtooth_prediction", "locked": false, "schema_version": 3, "solution": true, "task": false}
### BEGIN SOLUTION
prediction = 0.1  # a jump makes the coefficients fall like 1/i: |G_10| / |G_1| is about 1/10
### END SOLUTION

# %% [markdown]
# ## Why the low frequencies dominate: the wrap-around jump
#
# **Step 1: the DFT sees a periodic sequence.** The inverse of Eq. (9), $\lambda'_k = \frac1N\sum_i \Lambda_i
# e^{+j2\pi ik/N}$, is a sum of waves of period $N$: it defines $\lambda'_k$ for every integer $k$, with
# $\lambda'_{k+N} = \lambda'_k$. After $\lambda'_{N-1}$ comes $\lambda'_0$ again.
#
# **Step 2: $\lambda'$ is a slow trend plus fluctuations.** The plot of Eq. (8) in lesson 02 shows it: a trend that
# differs from shape to shape (the lower-order terms of Weyl's law), and small fluctuations from eigenvalue to
# eigenvalue. The trend starts at $\lambda'_0 = 0$ and ends at some value $J = \lambda'_{N-1}$, so the periodic
# sequence falls by $J$ in one step at the seam: a **sawtooth**.
#
# **Step 3: the DFT of a sawtooth.** For the ramp $g_k = k$ write $z = e^{-j2\pi i/N}$ with $i \ne 0$, so $z^N = 1$ and
# $\sum_{k=0}^{N-1} z^k = 0$. Then $G_i = S = \sum_k k z^k$, and
#
# $$S - zS = \sum_{k=0}^{N-1} k z^k - \sum_{k=1}^{N} (k-1) z^k = \sum_{k=1}^{N-1} z^k - (N-1) z^N = -1 - (N - 1) = -N,$$
#
# $$G_i = \frac{-N}{1 - z}, \qquad |G_i| = \frac{N}{|1 - e^{-j2\pi i/N}|} = \frac{N}{2\sin(\pi i/N)} \approx
#   \frac{N^2}{2\pi\, i} \quad (i \ll N).$$
#
# The coefficients fall only like $1/i$: a jump spreads over every frequency, but most of it lands on the lowest ones.
# A trend of slope $J/(N-1)$ gives $|\Lambda_i| \approx \frac{|J|}{N-1}\,\frac{N}{2\sin(\pi i/N)}$.
#
# **Step 4: without the jump.** Subtract from the trend the straight line through its two ends. What is left is
# continuous across the seam (only its slope jumps), and the coefficients of such a sequence fall like $1/i^2$
# (sum by parts once more). The fluctuations, finally, are nearly independent from one eigenvalue to the next:
# their coefficients have no preferred frequency, a flat floor.
#
# We compute all four on Spot: the trend is the least-squares cubic in the index
# (`cshape.descriptors.detrend(x, 3)` returns $x$ less that cubic, the fluctuations).

# %%
from cshape.descriptors import detrend

g = np.arange(100.0)
G = np.abs(np.fft.fft(g))
print(f"the ramp, N = 100: |G_10| / |G_1| = {G[10] / G[1]:.4f};  sin(pi/100) / sin(10 pi/100) = "
      f"{np.sin(np.pi / 100) / np.sin(np.pi / 10):.4f};  1/10 = 0.1")

# %% nbgrader={"grade": true, "grade_id": "test_sawtooth_prediction", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
assert np.isscalar(prediction) and np.isfinite(prediction), "prediction is one number, e.g. 0.5"
### BEGIN HIDDEN TESTS
_ratio = np.abs(np.fft.fft(np.arange(100.0)))
_ratio = _ratio[10] / _ratio[1]
assert abs(prediction - _ratio) < 0.03, (
    f"you predicted {prediction}, the ratio is {_ratio:.4f}. A jump makes the DFT coefficients fall like 1/i "
    "(1/10 here); 1/i^2 (0.01) is for a sequence that is continuous across the seam, and a smooth periodic "
    "sequence falls faster still")
### END HIDDEN TESTS

# %%
k = np.arange(N)
fluct = detrend(lam_prime, 3)  # the fluctuations about the cubic trend
trend = lam_prime - fluct
J = trend[-1] - trend[0]  # the trend's jump at the seam
no_jump = trend - (trend[0] + J * k / (N - 1))  # the trend less the line through its two ends
i = np.arange(1, N // 2 + 1)
sawtooth = abs(J) / (N - 1) * N / (2 * np.sin(np.pi * i / N))
curves = {"lam' (Eq. 8)": lam_prime, "its cubic trend": trend, "the trend without its jump": no_jump,
          "the fluctuations": fluct}
fig = plots.new_figure((7, 4))
ax = fig.add_subplot()
low = np.arange(1, N // 4 + 1)  # the fit of the slopes uses i = 1 .. N/4
for (label, x), style in zip(curves.items(), ["k.", "-", "-", "-"], strict=True):
    X = np.abs(np.fft.fft(x))[i]
    slope = np.polyfit(np.log(low), np.log(X[: len(low)]), 1)[0]
    ax.loglog(i, X, style, ms=4, label=f"{label}: slope {slope:.2f}")
    print(f"{label:28s} log-log slope of |DFT| for i = 1..{N // 4}: {slope:6.2f}")
ax.loglog(i, sawtooth, "k--", lw=1, label="sawtooth of the jump, N / (2 sin(pi i/N)) |J|/(N-1)")
ax.set(xlabel="frequency i", ylabel="|DFT|", title=f"why the low frequencies dominate ({real_name.split(' ')[0]})")
ax.legend(fontsize="small")
fig

# %% [markdown]
# The printed slopes tell the story: the trend's coefficients fall like $1/i$ (slope near $-1$) and follow the
# sawtooth of its jump (dashed); without the jump they fall like $1/i^2$ (slope near $-2$), far below; the
# fluctuations are flat (slope near 0). The coefficients of $\lambda'$ itself are the sum of the two: at the lowest
# frequencies the sawtooth of the trend is the larger part, further out the fluctuations are as large (compare
# the curves), and the floor does not fall. The $2M+1$ lowest frequencies keep the trend and the part of the fluctuations that falls on them, and they
# hold this share of the energy $\sum_i |\Lambda_i|^2$:

# %%
shifted = np.fft.fftshift(np.fft.fft(lam_prime))
kept = np.sum(np.abs(shifted[N // 2 - M : N // 2 + M + 1]) ** 2) / np.sum(np.abs(shifted) ** 2)
print(f"the {2 * M + 1} lowest of {N} frequencies hold {kept:.1%} of the energy of lam'")

# %% [markdown]
# So the low frequencies dominate largely *because* of the seam: the DFT's periodic view turns the trend into a
# sawtooth. Lesson 08 takes this further: a transform without the seam (the DCT, which mirrors the sequence
# instead of repeating it) and what either choice does to the distances.

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
    rec = cshape.descriptors.inverse_compact_shape_dna(S_m, N)
    ax.plot(i, cshape.weyl_subtract(rec), lw=1.2, label=f"M={m} ({2 * m + 1} values)")
ax.set(xlabel="i", ylabel="lam'_i", title=f"reconstructions, {real_name.split(' ')[0]}")
ax.legend(fontsize="small")
fig

# %% [markdown] nbgrader={"grade": false, "grade_id": "ends_question", "locked": true, "schema_version": 3, "solution": false, "task": false}
# ## Exercise 4 (written, graded by hand): the ends of the reconstruction
#
# Look at the two ends of the reconstructions above, at $i = 0$ and $i = N-1$. In the answer cell below (5-10 lines):
# what do the reconstructions do there, and why, in terms of the previous section? Towards which value would you
# expect them to go at the two ends, and does a larger $M$ fix it? The cell after your answer prints the numbers.

# %% [markdown] nbgrader={"grade": true, "grade_id": "ends_answer", "locked": false, "points": 2, "schema_version": 3, "solution": true, "task": false}
# ### BEGIN SOLUTION
# The reconstructions miss both ends: at $i = 0$ they lie above $\lambda'_0 = 0$, at $i = N-1$ below $\lambda'_{N-1}$.
# The inverse DFT of the kept frequencies is a smooth periodic sequence, and the periodic $\lambda'$ has a jump at
# the seam, from $\lambda'_{N-1}$ back to $\lambda'_0$. A sum of a few low-frequency waves cannot jump: it passes
# through the seam continuously, so near the seam it goes towards the middle of the jump,
# $(\lambda'_0 + \lambda'_{N-1})/2$, from both sides, and it overshoots a little beside it (the Gibbs phenomenon).
# A larger $M$ narrows the region where this happens and the miss shrinks (with all $N$ frequencies the inverse DFT
# is exact), but at the $M$ of a descriptor it is large, because the jump's coefficients fall only like $1/i$.
# Removing the jump first (subtracting a line, or mirroring the sequence as the DCT does) would fix it.
# ### END SOLUTION

# %%
ends = np.array([lam_prime[0], lam_prime[-1]])
print(f"lam'_0 = {ends[0]:.2f}, lam'_N-1 = {ends[1]:.2f}, the middle of the jump: {ends.mean():.2f}")
for m in [2, M, (N - 1) // 2]:
    rec = cshape.weyl_subtract(cshape.descriptors.inverse_compact_shape_dna(
        cshape.compact_shape_dna(lam_norm, M=m, N=N, normalization="none"), N))
    print(f"M = {m:2d}: the reconstruction at i = 0 is {rec[0]:7.2f}, at i = N-1 {rec[-1]:7.2f}")

# %% [markdown]
# The relative error $\lVert \mathrm{rec} - \lambda' \rVert / \lVert \lambda' \rVert$ of the reconstruction, for four
# shapes and every $M$ up to the largest, $(N-1)/2$:

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
    errors.append([np.linalg.norm(cshape.descriptors.inverse_compact_shape_dna(
        cshape.compact_shape_dna(ln, M=int(m), N=N, normalization="none"), N, add_weyl=False) - lp)
        / np.linalg.norm(lp) for m in Ms])
plots.plot_reconstruction_error(Ms, errors, labels=list(models), N=N)

# %%
for name, err in zip(models, errors, strict=True):
    spectrum = np.fft.fft(cshape.weyl_subtract(models[name]))
    nyquist = np.abs(spectrum[N // 2]) / np.linalg.norm(spectrum)  # the share of the highest frequency
    print(f"{name:8s} error at M = {M}: {err[M]:.2f}, at M = {Ms[-1]}: {err[-1]:.2f};"
          f"  the highest frequency N/2 alone: {nyquist:.2f}")
lam_torus = models["torus"]
twins = np.isclose(lam_torus[1:], lam_torus[:-1], rtol=1e-6)
paired = np.zeros(N, bool)
paired[1:] |= twins
paired[:-1] |= twins
print(f"torus: {paired.sum()} of its {N} eigenvalues have a twin (equal to 6 digits)")

# %% [markdown]
# Read the printed errors with the picture. At the descriptor's $M$ every shape keeps an error between about a
# quarter and two thirds of $\lVert\lambda'\rVert$ (the printed values): the $2M+1$ coefficients keep the trend and drop most of
# the fluctuations, which are spread evenly over all frequencies. A descriptor does not need to rebuild the
# spectrum, only to tell shapes apart (lessons 04 and 07 measure that).
#
# The torus's error falls more and more slowly and levels off at the value printed for its highest frequency,
# which it keeps up to the last $M$: the crop keeps the frequencies $-M..M$ with $M \le (N-1)/2$, never the highest one, $N/2$ (for even $N$). The
# round torus is symmetric under rotation about its axis, so most of its eigenvalues come in pairs (the cosine and
# the sine of one wave around the axis). Inside each pair $\lambda_i$ stays and $4\pi i$ grows, so $\lambda'$
# drops by $4\pi$ from one member to the next: a zigzag of period 2, which is exactly the highest frequency. The
# other shapes have a negligible share there.

# %% [markdown]
# ## Storing the descriptor: $2M+1$ real numbers
#
# The input is real, so $\Lambda_{-k} = \overline{\Lambda_k}$: half of the complex values are redundant.
# `cshape.descriptors.real_form` keeps $\mathrm{Re}\,\Lambda_0$ and $\sqrt2\,(\mathrm{Re}, \mathrm{Im})$ of
# $\Lambda_1..\Lambda_M$: $2M+1$ reals, with exactly the Euclidean distances of the complex descriptors.

# %%
S_a = cshape.compact_shape_dna(models["sphere"], M=M, N=N, normalization="none")
S_b = cshape.compact_shape_dna(models["cube"], M=M, N=N, normalization="none")
print("conjugate symmetric:", np.allclose(S_a[::-1], np.conj(S_a)))
print("complex distance:", np.linalg.norm(S_a - S_b))
print("real-form distance:", np.linalg.norm(cshape.descriptors.real_form(S_a) - cshape.descriptors.real_form(S_b)))
print("sizes: Shape-DNA", N, "values, cShape-DNA", len(cshape.descriptors.real_form(S_a)), "values")

# %% [markdown]
# ## Exercises
#
# 1. *(graded above)* Eq. (8), (9) and (10) by hand, the sawtooth prediction, the ends of the reconstruction.
# 2. **Why the line first?** Skip Eq. (8): take the DFT of the normalised Shape-DNA itself and crop it. Reconstruct
#    and compare the error with the one above. What does the jump between $\lambda_{N-1}$ and $\lambda_0$ (the DFT
#    treats the signal as periodic) do to the high frequencies?
# 3. **Even and odd $N$.** For $N = 10$ and $N = 11$, which indices of the shifted vector are kept for $M = 2$?
#    Check with `np.fft.fftshift(np.fft.fftfreq(N) * N)`.
# 4. **A budget of 9 numbers.** Compare the first 9 normalised eigenvalues with the cShape-DNA for $M = 4$:
#    which one tells the sphere from the cube better (distance between them, relative to the distance between
#    two spheres of different resolution)? Notebook 4 does this for a whole collection.
# 5. **Remove the jump yourself.** Before the DFT, subtract from $\lambda'$ the line through $\lambda'_0$ and
#    $\lambda'_{N-1}$ (and add it back after the inverse). How do the reconstruction error at $M$ and the ends of the
#    reconstruction change? What would the descriptor then have to store besides the $2M+1$ coefficients?
#
# ## References
#
# - Gao, Yu and Pang (2014). A compact shape descriptor for triangular surface meshes. *Computer-Aided Design* 53,
#   62-69. (Section 2.3, Eq. 8-10, Fig. 2.)
# - Reuter, Wolter and Peinecke (2006). Laplace-Beltrami spectra as "Shape-DNA" of surfaces and solids.
#   *Computer-Aided Design* 38(4), 342-366. (The Shape-DNA that Eq. 8-10 compress.)
# - Weyl (1911). Über die asymptotische Verteilung der Eigenwerte. *Nachrichten der Gesellschaft der Wissenschaften
#   zu Göttingen*, 110-117. (The line that Eq. 8 subtracts.)
# - Oppenheim and Schafer (2010). *Discrete-Time Signal Processing*, 3rd ed., Pearson, chapter 8 (the DFT, its
#   periodic view of a finite sequence).
# - Strang (1999). The discrete cosine transform. *SIAM Review* 41(1), 135-147. (Why mirroring instead of repeating
#   removes the seam: lesson 08.)
