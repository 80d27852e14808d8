# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 4 · Comparing and classifying shapes: distance matrices, MDS, retrieval
#
# **Paper:** Gao, Yu and Pang, *A compact shape descriptor for triangular surface meshes*, Computer-Aided Design 53 (2014) 62-69; Section 3.1, Fig. 3 (scaled distance matrices and their difference), Fig. 4 (MDS of the
# cShape-DNA for $M = 16, 8, 4, 2, 1$), Fig. 5 (MDS of the truncated Shape-DNA and of the F1 feature).
#
# **Learning goals.** After this notebook you can
#
# 1. turn a collection of meshes into descriptors once (`cshape.batch.describe`) and derive every descriptor
#    of the paper from the same eigenvalues;
# 2. compare two distance matrices that live on different scales by scaling both to $[0, 255]$ and reading
#    the mean and standard deviation of their difference (Fig. 3);
# 3. draw and read 2-D MDS plots (Fig. 4-5): what "the clustering gets worse" looks like;
# 4. score a descriptor with the retrieval measures of the Princeton Shape Benchmark (nearest neighbour,
#    first and second tier, E-measure, DCG, mean average precision).
#
# **The measures.** With descriptors $x_p$ (one per shape), $D_{pq} = \lVert x_p - x_q\rVert$ (Euclidean),
#
# $$D^{255} = 255\,\frac{D}{\max D}, \qquad \text{difference} = \left|D^{255}_{\text{Shape-DNA}} - D^{255}_{\text{cShape-DNA}}\right|,$$
#
# and the paper reports mean 0.68 and standard deviation 0.69 for the McGill database with $N = 100$, $M = 16$.

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

collection = demo_collection()
N = size(40, 100)
table = batch.describe(collection, N=N, progress=not SMALL)
print(table)
print("classes:", sorted(set(table.labels)))

# %% [markdown]
# ## The collection
#
# One shape of each class. The full-size run uses cshape's generated "paper-models" and "articulated"
# collections: the paper's simple models, a marching-cubes animal and its remesh, a figure at two resolutions,
# and four classes of articulated figures in five poses each (the counterpart of the armadillo poses A1-A5).

# %%
first = {}
for name, label, mesh in collection:
    first.setdefault(label, (name, mesh))
fig = plots.new_figure((2.6 * len(first), 2.8))
for k, (label, (name, mesh)) in enumerate(first.items()):
    plots.plot_mesh(mesh, ax=fig.add_subplot(1, len(first), k + 1, projection="3d"),
                    title=f"{label}: {name}", edges=False)
fig

# %% [markdown]
# ## Fig. 3: scaled distance matrices and their difference
#
# A `cshape.Descriptor` says which descriptor: its kind, `N` and `M` (`cshape.PAPER` is the paper's
# cShape-DNA, `M = 16` of `N = 100`). `table.distance_matrix(descriptor)` builds the descriptors from the stored
# eigenvalues (no new eigensolve) and their Euclidean distances. Shapes are in collection order, so each class
# is a block on the diagonal.

# %%
from cshape import Descriptor, compare

M = 16 if 2 * 16 + 1 <= N else (N - 1) // 2
D_sdna = table.distance_matrix(Descriptor("shape-dna", N=N))
D_cs = table.distance_matrix(Descriptor("cshape", N=N, M=M))
mean, std = compare.scaled_difference(D_sdna, D_cs)
plots.plot_matrices(
    [compare.scale_255(D_sdna), compare.scale_255(D_cs), compare.difference_matrix(D_sdna, D_cs)],
    [f"(a) Shape-DNA, N={N}", f"(b) cShape-DNA, M={M}",
     f"(c) |a - b|: mean {mean:.2f}, std {std:.2f}"],
    vmax=255,
)

# %% [markdown]
# The difference image is nearly all dark blue, the bottom of the jet colour map, on the $[0, 255]$ scale of
# (a) and (b): the two descriptors rank the shapes almost identically, although the cShape-DNA has $2M+1$
# values instead of $N$. (In the small-size run the meshes are
# coarse, e.g. spheres of 162 and 642 vertices, whose higher eigenvalues differ visibly: resolution matters
# when a mesh has few vertices per eigenfunction oscillation.)
#
# ## Fig. 4: MDS of the cShape-DNA as $M$ shrinks
#
# Multidimensional scaling places one point per shape in the plane so that the planar distances approximate
# $D$. A good descriptor gives tight, separated clusters.

# %%
Ms = [m for m in (16, 8, 4, 2, 1) if 2 * m + 1 <= N]
nrows = -(-(len(Ms) + 1) // 3)
fig = plots.new_figure((11, 3.6 * nrows))
axs = fig.subplots(nrows, 3).ravel()
plots.plot_mds(compare.mds_embedding(D_sdna), labels=table.labels, ax=axs[0],
                 title=f"(a) Shape-DNA, N={N}")
for ax, m in zip(axs[1:], Ms, strict=False):
    Y = compare.mds_embedding(table.distance_matrix(Descriptor("cshape", N=N, M=m)))
    plots.plot_mds(Y, labels=table.labels, ax=ax, title=f"cShape-DNA M={m} ({2 * m + 1} values)")
for ax in axs[1:]:  # one legend is enough
    if ax.get_legend() is not None:
        ax.get_legend().remove()
for ax in axs[len(Ms) + 1:]:
    ax.set_axis_off()
fig

# %% [markdown]
# ## Fig. 5: the truncated Shape-DNA with the same budget, and F1
#
# The fair comparison: keep the *first* $2M+1$ normalised eigenvalues instead (Fig. 5 a-e), or use the F1 feature
# $\left(\lambda_1/\lambda_2, \dots, \lambda_1/\lambda_N\right)$ (Fig. 5f).

# %%
fig = plots.new_figure((11, 3.6 * nrows))
axs = fig.subplots(nrows, 3).ravel()
for ax, m in zip(axs, Ms, strict=False):
    Y = compare.mds_embedding(table.distance_matrix(Descriptor("truncated", N=N, M=m)))
    plots.plot_mds(Y, labels=table.labels, ax=ax, title=f"first {2 * m + 1} eigenvalues")
Y = compare.mds_embedding(table.distance_matrix(Descriptor("f1", N=N)))
plots.plot_mds(Y, labels=table.labels, ax=axs[len(Ms)], title=f"(f) F1, N={N}")
for ax in axs[1:]:  # one legend is enough
    if ax.get_legend() is not None:
        ax.get_legend().remove()
for ax in axs[len(Ms) + 1:]:
    ax.set_axis_off()
fig

# %% [markdown]
# ## Retrieval measures, on a collection where descriptors differ
#
# Every shape is used once as a query against all the others; the measures (in $[0, 1]$, higher is better)
# tell how often and how early shapes of the same class come back. See `cshape.compare.retrieval_scores`
# for the exact definitions.
#
# On the collection above every descriptor scores 1.000: each class is *one* shape with its remeshings or poses,
# exactly the isometries Shape-DNA ignores. Retrieval tells descriptors apart only when the members of a class
# differ. cshape's `creatures` benchmark makes such classes: 12 kinds of creature (human, centaur, teddy,
# quadruped, bird, spider, ant, crab, octopus, starfish, hand, snake) whose members each draw their own limb
# lengths and thicknesses, pose, resolution and a little noise. Its development instance `creatures-dev`
# (12 classes x 10 members; in the small run 6 classes x 3 coarse members), generated in code and cached, is the
# one used here, and again in lesson 08.
#
# Building its 120 meshes and solving 120 eigenproblems takes minutes, so at full size its eigenvalues come
# prepared with the package (`retrieval_table`: the output of
# `batch.describe(cshape.data.load_collection("creatures-dev"), N=100)`, checked by the test suite), and only
# the meshes drawn below are built, each in about a second the first time.

# %%
from cshape.course.teaching import retrieval_collection, retrieval_table

creatures = retrieval_collection()
ctable = retrieval_table(N)
first = {}
for item in creatures:
    if item.label not in first:  # one mesh per class: only these are built
        first[item.label] = item.mesh
fig = plots.new_figure((2.0 * len(first), 2.2))
for k, (label, mesh) in enumerate(first.items()):
    plots.plot_mesh(mesh, ax=fig.add_subplot(1, len(first), k + 1, projection="3d"), title=label,
                    edges=False)
fig

# %%
def scores(descriptor):
    """The retrieval measures of one descriptor on the creatures."""
    return compare.retrieval_scores(ctable.distance_matrix(descriptor), ctable.labels)


D_ret = ctable.distance_matrix(Descriptor("shape-dna", N=N))
rows = [("Shape-DNA", N, compare.retrieval_scores(D_ret, ctable.labels))]
for m in Ms:
    rows.append((f"cShape-DNA M={m}", 2 * m + 1, scores(Descriptor("cshape", N=N, M=m))))
    rows.append((f"truncated, first {2 * m + 1}", 2 * m + 1,
                 scores(Descriptor("truncated", N=N, M=m))))
rows.append(("F1", N - 2, scores(Descriptor("f1", N=N))))
keys = ["nn", "ft", "st", "e", "dcg", "map"]
print(f"{'descriptor':24s} {'size':>4s} " + " ".join(f"{k:>6s}" for k in keys))
for name, n_values, sc in rows:
    print(f"{name:24s} {n_values:4d} " + " ".join(f"{sc[k]:6.3f}" for k in keys))

# %%
fig = plots.new_figure((6, 3.6))
ax = fig.add_subplot()
sizes = [2 * m + 1 for m in Ms]
for kind, marker in (("cshape", "o-"), ("truncated", "s--")):
    ft = [scores(Descriptor(kind, N=N, M=m))["ft"] for m in Ms]
    ax.plot(sizes, ft, marker, label=kind)
ax.axhline(rows[0][2]["ft"], color="k", lw=0.8, label=f"Shape-DNA, N={N}")
ax.set(xlabel="descriptor size (values)", ylabel="first tier", xscale="log",
       title="same budget, different descriptors")
ax.legend(fontsize="small")
fig

# %% [markdown]
# With the same number of values, the first eigenvalues (truncated) and the cropped DFT (cShape-DNA) are not
# equally good: compare the curves at 17 and 33 values. Lesson 08 asks why, and finds descriptors that do better.

# %% [markdown] nbgrader={"grade": false, "grade_id": "retrieval_task", "locked": true, "schema_version": 3, "solution": false, "task": false}
# ## Exercise (graded): nearest neighbour and first tier
#
# Write `nn_ft_mine(D, labels)` returning the mean nearest-neighbour rate and the mean first tier over all
# queries, as `compare.retrieval_scores` defines them. Every model $i$ is the query once; the *other* $p - 1$
# models are ranked by increasing $D_{ij}$ (ties by index: `np.argsort(D[i], kind="stable")`). With $C$ the size
# of the query's class, NN is 1 when the first result is of the query's class, and FT is the fraction of the
# first $C - 1$ results that are. A query whose class has no other model ($C = 1$: the cube, the torus and
# the eight of the demo collection's full-size run) has no right answer and is left out of both means, as in
# `compare.retrieval_scores`.

# %% nbgrader={"grade": false, "grade_id": "nn_ft_mine", "locked": false, "schema_version": 3, "solution": true, "task": false}
def nn_ft_mine(D, labels):
    """Mean nearest-neighbour rate and mean first tier of the distance matrix D, shape (p, p)."""
    ### BEGIN SOLUTION
    D, labels = np.asarray(D, dtype=float), np.asarray(labels)
    nn, ft = [], []
    for i in range(len(D)):
        R = int(np.sum(labels == labels[i])) - 1  # relevant models: the class minus the query
        if R == 0:
            continue  # a class of one: nothing to retrieve
        order = np.argsort(D[i], kind="stable")
        order = order[order != i]  # the query is not one of its own results
        same = labels[order] == labels[i]
        nn.append(float(same[0]))
        ft.append(same[:R].sum() / R)
    return float(np.mean(nn)), float(np.mean(ft))
    ### END SOLUTION


# %% nbgrader={"grade": true, "grade_id": "test_nn_ft_mine", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
nn, ft = nn_ft_mine(D_ret, ctable.labels)
print(f"creatures, Shape-DNA, N = {N}: nearest neighbour {nn:.3f}, first tier {ft:.3f}")
assert 0 <= nn <= 1 and 0 <= ft <= 1, "both measures lie in [0, 1]"
_rng = np.random.default_rng(1)
_X = _rng.standard_normal((12, 2))
_D = np.linalg.norm(_X[:, None] - _X[None], axis=-1)
_labels = np.repeat(["a", "b", "c"], 4)
if nn_ft_mine(_D, _labels) == (1.0, 1.0):
    print("hint: random points score a perfect NN and FT with your function: is the query its own "
          "first result? D[i, i] = 0; leave the query out of its ranking")
print("visible checks passed")

# %% nbgrader={"grade": true, "grade_id": "hidden_nn_ft_mine", "locked": true, "points": 2, "schema_version": 3, "solution": false, "task": false}
# hidden tests: the autograder runs more checks here
### BEGIN HIDDEN TESTS
_square = np.array([[0, 1, 2, 3], [1, 0, 3, 2], [2, 3, 0, 1], [3, 2, 1, 0]], dtype=float)
assert np.allclose(nn_ft_mine(_square, ["a", "b", "a", "b"]), (0.0, 0.0)), "hand example: (0, 0)"
_lonely = np.r_[_labels[:-1], ["d"]]  # "d" is a class of one: its query is left out
for _DD, _ll in ((_D, _labels), (_D, _lonely), (D_sdna, table.labels), (D_ret, ctable.labels)):
    _want = compare.retrieval_scores(_DD, _ll)
    assert np.allclose(nn_ft_mine(_DD, _ll), (_want["nn"], _want["ft"])), "against retrieval_scores"
### END HIDDEN TESTS

# %% [markdown]
# ## Exercises
#
# 1. Which pair of shapes does the cShape-DNA with $M = 1$ confuse most? Find it in the distance matrix
#    (`np.argsort`) and draw both meshes.
# 2. The spheres S1-S3 (full size) differ only in resolution. How large is their mutual distance relative to
#    the distance from the sphere to the cube, for the Shape-DNA and for the cShape-DNA?
# 3. Compute the difference statistics of Fig. 3 for `normalization="weyl"` (pass it to
#    `table.distance_matrix`). Does the choice of normalisation matter here?
# 4. Replace the MDS by a nearest-neighbour classifier (`cshape.DescriptorIndex`): leave one shape out, predict
#    its class from its nearest neighbour, and count the errors for each descriptor.
