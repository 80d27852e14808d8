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
# 3. use the M-sweep widget: eigenvalues are computed once; moving the slider reruns only the cheap stages (crop,
#    distances, statistics, MDS).
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

# %% [markdown]
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

# %% [markdown]
# ## The widget
#
# Move **M** (and try **N**, the collection, the normalisation and the shape whose DFT is drawn). Each change reruns only the
# cheap stages; the eigenvalues above are not recomputed. $M$ is clamped to $[0, (N-1)/2]$.
#
# The **transform** toggle goes beyond the paper: `weyl` is Eq. (8)-(10); `log-weyl` crops the DFT of the
# log-Weyl ratio $r_i = \log(\lambda_i^{norm} / 4\pi i)$, $i = 1..N-1$, which weighs every eigenvalue by its
# relative deviation from the Weyl line instead of its absolute one; `log-weyl-dct` keeps the first $2M+1$ DCT
# coefficients of $r$ (no jump at the ends for the periodic DFT to smear). All three give $2M+1$ numbers; the
# reference matrix stays the Shape-DNA's. Notebook 8 measures which one retrieves shapes best.

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
# 1. Find the smallest $M$ for which every shape's nearest neighbour is still in its own class (the statistics
#    line shows the nearest-neighbour rate).
# 2. With the normalisation set to `'fiedler'`, does the difference from Shape-DNA grow or shrink? Why might the
#    Weyl-line subtraction of Eq. (8) suit the area normalisation best?
# 3. Lower $N$ to 20: how do the difference statistics for $M = 4$ change, and why?
# 4. Switch the transform to `log-weyl`: at which $M$ does the difference from Shape-DNA get small? Is a small
#    difference from Shape-DNA the same as a good retrieval (compare the nearest-neighbour rates)?
# 5. Add a third collection to the widget's drop-down: the table of your own meshes from notebook 6
#    (`batch.DescriptorTable.load("descriptors.csv")`), or only the articulated figures of this one.
