# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 7 · The parameter $M$, interactively
#
# **Paper:** Gao, Yu and Pang, *A compact shape descriptor for triangular surface meshes*, Computer-Aided Design 53 (2014) 62-69; Section 3.2, Fig. 6 (and Fig. 3-4).
#
# **Learning goals.** After this notebook you can
#
# 1. predict how the descriptor size $2M+1$ trades accuracy for space;
# 2. read the scaled distance matrices of Shape-DNA and cShape-DNA (values in $[0, 255]$) and their difference,
#    with its mean and standard deviation, the paper's measure of "how much worse" (Fig. 6 e-h);
# 3. compute the difference statistics yourself, and the share of a spectrum's energy that the crop keeps, which
#    decides how far each cShape-DNA distance falls below $\sqrt N$ times the Shape-DNA's (lesson 04);
# 4. use the M-sweep widget: eigenvalues are computed once; moving the slider reruns only the cheap stages (crop,
#    distances, statistics, MDS).
#
# **Prerequisites:** lessons 03 (the crop, Eq. 10) and 04 (scaled differences, $D_{\text{cShape}} \le \sqrt N
# D_{\text{Shape-DNA}}$, Parseval). This lesson stays with the paper's Eq. (8)-(10); lesson 08 goes beyond it.
#
# The paper reports, for the McGill database and $N = 100$, difference means 1.3, 2.3, 4.8 and 6.0 for
# $M = 8, 4, 2, 1$. Our collection is smaller and made in code, so the numbers differ; the trend should not.

# %%
# %matplotlib inline
import numpy as np

import cshape
from cshape import plots
from cshape.course.teaching import SMALL, size  # CSHAPE_SMALL=1: small meshes and N

np.set_printoptions(precision=4, suppress=True, linewidth=100)
print("cshape", cshape.__version__, "(small sizes)" if SMALL else "")

# %%
from cshape import batch

# a few classes made in code (small) or paper-models + articulated (full size)
from cshape.course.teaching import demo_collection

N = size(40, 100)
table = batch.describe(demo_collection(), N=N, progress=not SMALL)
table

# %% [markdown]
# ## The pure functions behind the widget
#
# `widgets.MSweep` holds the eigenvalues and caches everything that does not depend on $M$;
# `sweep.state(M)` returns a `SweepState` with the cropped coefficients, the reconstruction, the scaled distance
# matrices, their difference, its mean and standard deviation, and the MDS coordinates.

# %%
from cshape.plots import widgets

sweep = widgets.MSweep.from_table(table)
for M in [16, 8, 4, 2, 1]:
    if 2 * M + 1 <= N:
        print(sweep.state(M, N=N).summary())

# %% [markdown] nbgrader={"grade": false, "grade_id": "stats_task", "locked": true, "schema_version": 3, "solution": false, "task": false}
# ## Exercise (graded): the paper's difference statistics
#
# Write `scaled_difference_mine(D_ref, D)` returning `(mean, std)` of $\left|D^{255}_{\text{ref}} - D^{255}\right|$,
# with $D^{255} = 255\,D / \max D$ (each matrix scaled by its own maximum), over the whole $p \times p$ image
# (diagonal included), standard deviation with `ddof=0`, as the paper computes them from its images. Do not use
# `cshape.compare`; the check compares with the sweep's `state.mean` and `state.std`.

# %% nbgrader={"grade": false, "grade_id": "scaled_difference_mine", "locked": false, "schema_version": 3, "solution": true, "task": false}
def scaled_difference_mine(D_ref, D):
    """Mean and std of |255 D_ref / max D_ref - 255 D / max D| over the whole matrix."""
    ### BEGIN SOLUTION
    D_ref, D = np.asarray(D_ref, dtype=float), np.asarray(D, dtype=float)
    diff = np.abs(255 * D_ref / D_ref.max() - 255 * D / D.max())
    return float(diff.mean()), float(diff.std())
    ### END SOLUTION


# %% nbgrader={"grade": false, "grade_id": "check_stats", "locked": true, "schema_version": 3, "solution": false, "task": false}
def check_stats(fn, D_ref, D):
    """Compare fn(D_ref, D) with the paper's statistics; name the usual mistake."""
    A, B = np.asarray(D_ref, dtype=float), np.asarray(D, dtype=float)
    diff = np.abs(255 * A / A.max() - 255 * B / B.max())
    got = np.asarray(fn(D_ref, D), dtype=float)
    if got.shape != (2,):
        raise AssertionError(f"return (mean, std), two numbers; got shape {got.shape}")
    if np.allclose(got, (diff.mean(), diff.std()), rtol=1e-9):
        print("scaled_difference_mine: correct")
        return
    off = diff[~np.eye(len(diff), dtype=bool)]
    common = np.abs(255 * A / max(A.max(), B.max()) - 255 * B / max(A.max(), B.max()))
    raw = np.abs(A - B)
    if np.isclose(got[1], diff.std(ddof=1)) and np.isclose(got[0], diff.mean()):
        raise AssertionError("hint: the paper's standard deviation is the population one, ddof=0")
    if np.allclose(got, (off.mean(), off.std())):
        raise AssertionError("hint: the statistics run over the whole p x p image, the zero diagonal "
                             "included")
    if np.allclose(got, (common.mean(), common.std())):
        raise AssertionError("hint: scale each matrix by ITS OWN maximum: the two live on scales "
                             "about sqrt(N) apart (lesson 04)")
    if np.allclose(got, (raw.mean(), raw.std())):
        raise AssertionError("hint: scale both matrices to [0, 255] before you subtract")
    raise AssertionError(f"got {tuple(got)}, expected {(diff.mean(), diff.std())}")


# %% nbgrader={"grade": true, "grade_id": "test_scaled_difference_mine", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
from cshape import Descriptor

D_shape_dna = table.distance_matrix(Descriptor("shape-dna", N=N))
_st = sweep.state(4, N=N)
check_stats(scaled_difference_mine, D_shape_dna, table.distance_matrix(Descriptor("cshape", N=N, M=4)))
assert np.allclose(scaled_difference_mine(D_shape_dna, table.distance_matrix(
    Descriptor("cshape", N=N, M=4))), (_st.mean, _st.std)), "as the sweep's state.mean, state.std"
print("visible checks passed")

# %% nbgrader={"grade": true, "grade_id": "hidden_scaled_difference_mine", "locked": true, "points": 2, "schema_version": 3, "solution": false, "task": false}
# hidden tests: the autograder runs more checks here
### BEGIN HIDDEN TESTS
for _M in (1, 2, 8):
    _st = sweep.state(_M, N=N)
    _D = table.distance_matrix(Descriptor("cshape", N=N, M=_M))
    check_stats(scaled_difference_mine, D_shape_dna, _D)
    assert np.allclose(scaled_difference_mine(D_shape_dna, _D), (_st.mean, _st.std))
_a = np.array([[0.0, 1.0], [1.0, 0.0]])
assert np.allclose(scaled_difference_mine(_a, 7 * _a), (0.0, 0.0)), "a scaled copy differs by nothing"
assert np.allclose(scaled_difference_mine(_a.tolist(), (2 * _a).tolist()), (0.0, 0.0)), "lists work"
### END HIDDEN TESTS

# %% [markdown] nbgrader={"grade": false, "grade_id": "predict_maxM_task", "locked": true, "schema_version": 3, "solution": false, "task": false}
# ### Predict (graded)
#
# The widget lets $M$ go up to $(N-1)/2$ rounded down, where the crop keeps $2M+1 = N - 1$ of the $N$ DFT
# coefficients (for an even $N$, all but the Nyquist frequency $N/2$). Before you run the cell after the next,
# predict the difference mean (on the $[0, 255]$ scale) between the Shape-DNA and the cShape-DNA at that $M$.

# %% nbgrader={"grade": false, "grade_id": "predict_maxM", "locked": false, "schema_version": 3, "solution": true, "task": false}
# write your prediction as `prediction = ...` (one number on the [0, 255] scale)
### BEGIN SOLUTION
prediction = 0.0
### END SOLUTION

# %%
M_max = (N - 1) // 2
top_state = sweep.state(M_max, N=N)
print(top_state.summary())

# %% nbgrader={"grade": true, "grade_id": "test_predict_maxM", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
assert np.ndim(prediction) == 0 and np.isfinite(float(prediction)), "prediction is one number"
print(f"you predicted {float(prediction):.2f}; the printed mean is {top_state.mean:.2f}")
# hidden test: within 2 units of the [0, 255] scale
### BEGIN HIDDEN TESTS
assert abs(float(prediction) - top_state.mean) < 2.0, (
    f"hint: the printed mean is {top_state.mean:.2f}. With (almost) every coefficient kept, Parseval "
    "makes every cShape-DNA distance sqrt(N) times the Shape-DNA distance, and scaling each matrix "
    "by its own maximum removes the factor: the two scaled images (almost) coincide")
### END HIDDEN TESTS

# %% [markdown]
# With all $N$ coefficients the identity of lesson 04 is an equality, $D_{\text{cShape}} = \sqrt N\,D_{\text{Shape-DNA}}$,
# and the scaled images coincide; dropping only the Nyquist coefficient changes almost nothing (the printed mean).
# Every smaller $M$ drops more of the spectrum's energy, and the difference grows, unevenly: a pair of shapes whose
# spectra differ in a slow trend keeps its distance, a pair that differs in fast wiggles loses it. The graded
# exercise after Fig. 6 measures that share.
#
# ## Fig. 6 for this collection
#
# Top: cShape-DNA distance matrices for $M = 8, 4, 2, 1$, scaled to $[0, 255]$. Bottom: their absolute difference
# from the Shape-DNA matrix ($N$ eigenvalues), on one colour scale.

# %%
states = [sweep.state(M, N=N) for M in (8, 4, 2, 1)]
plots.plot_matrices([s.D for s in states], [f"M = {s.M}" for s in states], vmax=255)

# %%
plots.plot_matrices([s.difference for s in states],
                    [f"M = {s.M}: mean {s.mean:.1f}, std {s.std:.1f}" for s in states])

# %% [markdown] nbgrader={"grade": false, "grade_id": "energy_task", "locked": true, "schema_version": 3, "solution": false, "task": false}
# ## Exercise (graded): the energy the crop keeps
#
# For a sequence $d_0, \dots, d_{N-1}$ with unnormalised DFT $\hat d_k$ (`np.fft.fft`), the crop keeps the
# frequencies $k = -M, \dots, M$. Write `kept_energy_mine(d, M)` returning the share of the energy they carry,
#
# $$\kappa_M(d) = \frac{\sum_{|k| \le M} |\hat d_k|^2}{\sum_{k} |\hat d_k|^2} \in [0, 1].$$
#
# Applied to the difference of two Weyl-subtracted spectra, $d = \lambda'^a - \lambda'^b$ (`state.lam_prime`), it
# gives the exact ratio of lesson 04's inequality: $D_{\text{cShape}}(a, b) = \sqrt{\kappa_M(d)\,N}\; D_{\text{Shape-DNA}}(a, b)$.
# Mind numpy's order of frequencies: `np.fft.fft` returns $k = 0, 1, \dots, N-1$, and $k = -1$ is entry $N - 1$.

# %% nbgrader={"grade": false, "grade_id": "kept_energy_mine", "locked": false, "schema_version": 3, "solution": true, "task": false}
def kept_energy_mine(d, M):
    """Share of the DFT energy of the sequence d in the frequencies -M..M."""
    ### BEGIN SOLUTION
    d = np.asarray(d, dtype=float)
    e = np.abs(np.fft.fft(d)) ** 2
    k = np.fft.fftfreq(len(d), 1 / len(d))  # 0, 1, ..., -2, -1
    return float(e[np.abs(k) <= M].sum() / e.sum())
    ### END SOLUTION


# %% nbgrader={"grade": false, "grade_id": "check_energy", "locked": true, "schema_version": 3, "solution": false, "task": false}
def check_energy(fn, d, M):
    """Compare fn(d, M) with the energy share; name the usual mistake."""
    d = np.asarray(d, dtype=float)
    L = len(d)
    e = np.abs(np.fft.fft(d)) ** 2
    k = np.fft.fftfreq(L, 1 / L)
    want = e[np.abs(k) <= M].sum() / e.sum()
    got = float(fn(d, M))
    if np.isclose(got, want, rtol=1e-9, atol=1e-12):
        print(f"kept_energy_mine: correct ({got:.4f})")
        return
    if np.isclose(got, e[: 2 * M + 1].sum() / e.sum()):
        raise AssertionError("hint: the first 2M+1 entries of np.fft.fft are k = 0..2M, not -M..M: "
                             "take the first M+1 and the last M (np.fft.fftfreq or fftshift)")
    a = np.sqrt(e)
    if np.isclose(got, a[np.abs(k) <= M].sum() / a.sum()):
        raise AssertionError("hint: energy is |d_k|^2, the squared modulus, not |d_k|")
    if np.isclose(got, e[np.abs(k) <= M].sum() / (L * np.sum(d**2) + 1e-300) / L):
        raise AssertionError("hint: divide by the total energy sum_k |d_k|^2 = N sum_i d_i^2")
    raise AssertionError(f"got {got:.6g}, expected {want:.6g}")


# %% nbgrader={"grade": true, "grade_id": "test_kept_energy_mine", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
_i = np.arange(N)
_wave = np.cos(2 * np.pi * 3 * _i / N)  # all its energy at k = +-3
assert np.isclose(kept_energy_mine(_wave, 3), 1.0) and np.isclose(kept_energy_mine(_wave, 2), 0.0), (
    "a cosine of frequency 3 has all its energy at k = +-3: kept fully from M = 3 on, not at M = 2")
check_energy(kept_energy_mine, _wave + 0.5 * np.sin(2 * np.pi * 7 * _i / N), 5)
print("visible checks passed")

# %% nbgrader={"grade": true, "grade_id": "hidden_kept_energy_mine", "locked": true, "points": 2, "schema_version": 3, "solution": false, "task": false}
# hidden tests: the autograder runs more checks here
### BEGIN HIDDEN TESTS
_rng = np.random.default_rng(11)
for _M in (0, 1, 4):
    check_energy(kept_energy_mine, _rng.standard_normal(N), _M)
    check_energy(kept_energy_mine, _rng.standard_normal(N - 1), _M)  # odd length
# lesson 04's identity, exact for every pair: D_cs = sqrt(kappa N) D_sdna
_st = sweep.state(4, N=N)
_Dc = table.distance_matrix(Descriptor("cshape", N=N, M=4))
for _a, _b in ((0, 1), (0, len(table) - 1), (2, 5)):
    _k = kept_energy_mine(_st.lam_prime[_a] - _st.lam_prime[_b], 4)
    assert np.isclose(_Dc[_a, _b], np.sqrt(_k * N) * D_shape_dna[_a, _b], rtol=1e-8), (
        "the identity D_cs = sqrt(kappa N) D_sdna fails: check the frequencies you keep")
### END HIDDEN TESTS

# %% [markdown]
# The share $\kappa_M$ for every pair of shapes, as $M$ shrinks: the median falls, and the spread between pairs
# grows, which is what the difference images of Fig. 6 show (a pair with a small $\kappa$ loses its distance).
# Computed here from the distance matrices alone, with the identity above: $\kappa_M = (D_{\text{cShape}} /
# \sqrt N D_{\text{Shape-DNA}})^2$.

# %%
off = ~np.eye(len(table), dtype=bool)
print(f"{'M':>3s} {'median kappa':>12s} {'smallest kappa':>14s} {'difference mean':>16s}")
for M in (M_max, 16, 8, 4, 2, 1):
    if 2 * M + 1 <= N:
        kappa = (table.distance_matrix(Descriptor("cshape", N=N, M=M))[off]
                 / (np.sqrt(N) * D_shape_dna[off])) ** 2
        print(f"{M:3d} {np.median(kappa):12.4f} {kappa.min():14.4f} "
              f"{sweep.state(M, N=N).mean:16.2f}")

# %% [markdown]
# ## The widget
#
# Move **M** (and try **N**, the collection, the normalisation and the shape whose DFT is drawn). Each change reruns only the
# cheap stages; the eigenvalues above are not recomputed. $M$ is clamped to $[0, (N-1)/2]$.
#
# The **transform** toggle belongs to lesson 08, which derives its two other settings: leave it at `weyl`, the
# paper's Eq. (8)-(10), in this lesson.

# %%
no_spheres = table.select([i for i, lab in enumerate(table.labels) if lab != "sphere"])
w = widgets.m_sweep_widget({"all shapes": table, "without spheres": no_spheres}, M=8, N=N)
w

# %% [markdown]
# A widget needs a live kernel. Where none runs (an HTML export of this notebook, the documentation site) the
# cell above shows the widget's picture and statistics as it was drawn, without the controls: run the notebook
# to move them. `plots.plot_m_sweep(w.state)` draws the current state as a plain figure at any time.

# %% [markdown]
# ## Exercises
#
# 1. Find the smallest $M$ whose difference mean from the Shape-DNA is below 2 on the $[0, 255]$ scale
#    (`sweep.state(M, N=N).mean`, for $M$ from 0 up). Which printed $\kappa$ column predicts it best, the median or
#    the smallest?
# 2. With the normalisation set to `'fiedler'`, does the difference from Shape-DNA grow or shrink? Why might the
#    Weyl-line subtraction of Eq. (8) suit the area normalisation best?
# 3. Lower $N$ to 20: how do the difference statistics for $M = 4$ change, and why?
# 4. Is a small difference from the Shape-DNA the same as a good retrieval? Compare the nearest-neighbour rates
#    the widget prints for $M = 1$, $4$ and $16$ with their difference means.
# 5. Add a third collection to the widget's drop-down: the creatures of lesson 04
#    (`from cshape.course.teaching import retrieval_table`; `retrieval_table(N)`), and compare the difference means
#    at $M = 4$ on the two collections.
#
# ## References
#
# - Z. Gao, Z. Yu, X. Pang, *A compact shape descriptor for triangular surface meshes*, Computer-Aided Design 53
#   (2014) 62-69, Section 3.2.
# - M. Reuter, F.-E. Wolter, N. Peinecke, *Laplace-Beltrami spectra as "Shape-DNA" of surfaces and solids*,
#   Computer-Aided Design 38 (2006) 342-366.
# - H. Weyl, *Das asymptotische Verteilungsgesetz der Eigenwerte linearer partieller Differentialgleichungen*,
#   Mathematische Annalen 71 (1911) 441-479: the line of Eq. (8).
