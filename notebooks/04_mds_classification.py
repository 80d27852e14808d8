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
#    the mean and standard deviation of their difference (Fig. 3), and say why the cShape-DNA's distances are
#    about $\sqrt{N}$ times the Shape-DNA's;
# 3. derive classical multidimensional scaling (double centring, eigenvectors), implement it, and read a 2-D MDS
#    plot (Fig. 4-5) together with its stress: what "the clustering gets worse" looks like, and when a picture
#    can be trusted;
# 4. define and compute the retrieval measures of the Princeton Shape Benchmark (nearest neighbour, first and
#    second tier, E-measure, DCG, mean average precision) and score descriptors with them.
#
# **Prerequisites:** lessons 02 (normalised Shape-DNA) and 03 (the cShape-DNA, Eq. 8-10); linear algebra
# (symmetric eigenvalue problems).
#
# **The scaled difference.** With descriptors $x_p$ (one per shape), $D_{pq} = \lVert x_p - x_q\rVert$
# (Euclidean),
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
if not SMALL:  # the finest sphere (S3, 40962 vertices) alone costs a third of the eigensolves
    collection = [c for c in collection if c[0] != "S3"]
N = size(40, 100)
table = batch.describe(collection, N=N, progress=not SMALL)
print(table)
print("classes:", sorted(set(table.labels)))

# %% [markdown]
# ## The collection
#
# One shape of each class. The full-size run uses cshape's generated "paper-models" and "articulated"
# collections (without the finest sphere S3): the paper's simple models, a marching-cubes animal and its remesh, a
# figure at two resolutions,
# and four classes of articulated figures in five poses each (the counterpart of the armadillo poses A1-A5).
# The small run uses spheres, cubes and tori at two resolutions and two poses of two figures.

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
S_sdna, S_cs = compare.scale_255(D_sdna), compare.scale_255(D_cs)
diff = np.abs(S_sdna - S_cs)  # the image of Fig. 3c, over the whole p x p matrix
print(f"difference on the [0, 255] scale: mean {diff.mean():.2f}, std {diff.std():.2f}, "
      f"largest {diff.max():.1f}")
plots.plot_matrices(
    [S_sdna, S_cs, diff],
    [f"(a) Shape-DNA, N={N}", f"(b) cShape-DNA, M={M}",
     f"(c) |a - b|: mean {diff.mean():.2f}, std {diff.std():.2f}"],
    vmax=255,
)

# %% [markdown]
# Read the printed mean and largest value against the scale of 255: where they are a few units, the difference
# image is dark blue (the bottom of the jet colour map) and the two descriptors rank the shapes almost alike,
# although the cShape-DNA has $2M+1$ values instead of $N$. Meshes with few vertices per eigenfunction
# oscillation (the small run's coarse spheres and cubes) have higher eigenvalues that depend on the resolution,
# which the two descriptors weigh differently.
#
# ## Two scales: predict before you look
#
# Fig. 3 scales each matrix by its own maximum, so it hides how large the two kinds of distance are. The
# cShape-DNA of lesson 03 is the *unnormalised* DFT (`np.fft.fft`) of the $N$ Weyl-subtracted eigenvalues,
# cropped to its $2M+1$ lowest frequencies.

# %% [markdown] nbgrader={"grade": false, "grade_id": "predict_scale_task", "locked": true, "schema_version": 3, "solution": false, "task": false}
# ### Predict (graded)
#
# Before you run the cell after the next one, predict the ratio
# $\max D_{\text{cShape-DNA}} / \max D_{\text{Shape-DNA}}$ for this collection ($M = 16$, or the largest $M$ that fits in
# $N$). Write one number (you may write it as an expression of `N` and `M`).

# %% nbgrader={"grade": false, "grade_id": "predict_scale", "locked": false, "schema_version": 3, "solution": true, "task": false}
# write your prediction as `prediction = ...` (a number, or an expression of N and M)
### BEGIN SOLUTION
prediction = np.sqrt(N)
### END SOLUTION

# %%
ratio = D_cs.max() / D_sdna.max()
off = ~np.eye(len(D_sdna), dtype=bool)  # pairs of different shapes
per_pair = D_cs[off] / D_sdna[off]
print(f"max D_cShape / max D_Shape-DNA = {ratio:.3f}; sqrt(N) = {np.sqrt(N):.3f}; "
      f"per pair between {per_pair.min():.3f} and {per_pair.max():.3f} (median {np.median(per_pair):.3f})")

# %% nbgrader={"grade": true, "grade_id": "test_predict_scale", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
assert np.ndim(prediction) == 0 and np.isfinite(float(prediction)), "prediction is one number"
print(f"you predicted {float(prediction):.3f}; the printed ratio is {ratio:.3f}")
# hidden test: the prediction is within 25 % of the ratio
### BEGIN HIDDEN TESTS
_p = float(prediction)
if abs(_p / ratio - 1) >= 0.25:
    if abs(_p - 1) < 0.3 or abs(_p - (2 * M + 1) / N) < 0.1:
        _why = ("hint: you predicted about 1, as if the DFT kept lengths or the crop shrank them; "
                "numpy's unnormalised DFT multiplies the length of a vector by sqrt(N) (Parseval), "
                "and the crop keeps the low frequencies, where two spectra differ")
    elif abs(_p / N - 1) < 0.25:
        _why = "hint: lengths grow by sqrt(N), not N: Parseval's identity sums squares"
    else:
        _why = "hint: use Parseval's identity for numpy's unnormalised DFT"
    raise AssertionError(f"{_why} (the ratio is {ratio:.3f}; a prediction within 25 % counts)")
### END HIDDEN TESTS

# %% [markdown]
# **Why $\sqrt{N}$.** Write $\lambda^a, \lambda^b \in \mathbb{R}^N$ for the normalised spectra of two shapes
# and $w_i = 4\pi i$ for the Weyl line of Eq. (8). The DFT $F$ is linear, and both shapes subtract the same line
# (both spectra are normalised to area 1), so
#
# $$S^a - S^b = P F\big((\lambda^a - w) - (\lambda^b - w)\big) = P F(\lambda^a - \lambda^b),$$
#
# with $P$ the crop to the $2M+1$ lowest frequencies. Parseval's identity for the unnormalised DFT,
# $\sum_k |\hat x_k|^2 = N \sum_i x_i^2$, gives $\lVert F d\rVert = \sqrt{N}\,\lVert d\rVert$, and the crop can
# only remove terms:
#
# $$D_{\text{cShape-DNA}}(a, b) = \lVert P F(\lambda^a - \lambda^b)\rVert \le \sqrt{N}\,
# \lVert\lambda^a - \lambda^b\rVert = \sqrt{N}\, D_{\text{Shape-DNA}}(a, b),$$
#
# with equality when the difference of the two spectra has all its energy in the kept frequencies. No printed
# per-pair ratio exceeds $\sqrt N$, and their median sits just below it: for most pairs the difference between two
# shapes' spectra is a slow trend, a low frequency. The MDS pictures below inherit this: the axes of the cShape-DNA's plots run about
# $\sqrt{N}$ times as far as the Shape-DNA's. Lesson 08 uses the same identity.
#
# ## Multidimensional scaling, derived
#
# MDS places one point $y_i \in \mathbb{R}^k$ per shape ($k = 2$ for a picture) so that the planar distances
# $\lVert y_i - y_j\rVert$ approximate $D_{ij}$. There are two classical ways to do it (Borg & Groenen 2005).
#
# **Classical MDS (Torgerson).** Suppose first that $D$ comes from points $x_1, \dots, x_p$ in some
# $\mathbb{R}^d$, centred ($\sum_i x_i = 0$). Expand a squared distance:
#
# $$D_{ij}^2 = \lVert x_i\rVert^2 + \lVert x_j\rVert^2 - 2\,x_i\cdot x_j .$$
#
# The Gram matrix $G = X X^\top$ ($G_{ij} = x_i \cdot x_j$) is what we want: its eigenvectors give coordinates.
# The centring matrix $J = I - \tfrac1p \mathbf{1}\mathbf{1}^\top$ subtracts row and column means. Applied on both
# sides of $D^{(2)} = (D_{ij}^2)$, it kills the terms that depend on one index only
# ($J\mathbf{1} = 0$, so $J(\mathbf{1} c^\top) = 0$ and $(c\,\mathbf{1}^\top)J = 0$), and keeps $JGJ = G$ for
# centred points:
#
# $$B = -\tfrac12\, J D^{(2)} J = -\tfrac12 J\big(c\mathbf 1^\top + \mathbf 1 c^\top - 2G\big)J = G,
# \qquad c_i = \lVert x_i\rVert^2 .$$
#
# $B$ is symmetric and positive semidefinite, $B = V \Lambda V^\top$ with eigenvalues
# $\ell_1 \ge \ell_2 \ge \dots \ge 0$. The coordinates
#
# $$Y = V_k\, \Lambda_k^{1/2} \qquad (\text{the top } k \text{ eigenvectors, each scaled by } \sqrt{\ell_j})$$
#
# satisfy $Y Y^\top = V_k \Lambda_k V_k^\top$, the best rank-$k$ approximation of $B$ (Eckart-Young). When $D$ comes
# from points in $\mathbb{R}^k$, $Y$ reproduces every distance exactly (up to a rotation or reflection). When it
# does not (a Shape-DNA distance matrix lives in $\mathbb{R}^N$, or is not Euclidean at all), the dropped
# eigenvalues measure what the picture loses, and negative eigenvalues of $B$ say that no point set has these
# distances.
#
# **Metric MDS by SMACOF.** Classical MDS fits inner products, not distances. `cshape.mds_embedding` (metric MDS, the
# iterations of scikit-learn's) minimises the raw *stress*
#
# $$\sigma(Y) = \sum_{i<j} \big(D_{ij} - \lVert y_i - y_j\rVert\big)^2$$
#
# directly, by SMACOF (Scaling by MAjorizing a COmplicated Function): at the current $Y$ it builds a quadratic
# function that lies above $\sigma$ everywhere and touches it at $Y$ (the majorizer, from the Cauchy-Schwarz
# inequality), and jumps to that quadratic's minimum, the Guttman transform $Y \leftarrow \tfrac1p B(Y)\,Y$ with
# $B(Y)_{ij} = -D_{ij}/\lVert y_i - y_j\rVert$ off the diagonal and rows summing to zero. Each step can only lower
# $\sigma$. It starts from classical MDS and stops at a local minimum (when a step lowers $\sigma$ by less than a
# millionth of $\sum_{i<j} \lVert y_i - y_j\rVert^2$). We report Kruskal's **stress-1**,
# $\sqrt{\sigma(Y) / \sum_{i<j} D_{ij}^2}$: 0 is a perfect picture; Kruskal (1964) called 0.05 good and 0.2 poor.

# %% [markdown] nbgrader={"grade": false, "grade_id": "mds_task", "locked": true, "schema_version": 3, "solution": false, "task": false}
# ## Exercise (graded): classical MDS
#
# Write `classical_mds_mine(D, k=2)` returning the classical MDS coordinates $Y = V_k \Lambda_k^{1/2}$, shape
# $(p, k)$, of a distance matrix $D$: square the distances, double-centre, take the eigenvectors of the $k$
# largest eigenvalues of $B$ (`np.linalg.eigh`), scale each by the square root of its eigenvalue (a round-off
# negative eigenvalue counts as 0). The checks compare distances, so the rotation and the signs of your axes are
# free.

# %% nbgrader={"grade": false, "grade_id": "classical_mds_mine", "locked": false, "schema_version": 3, "solution": true, "task": false}
def classical_mds_mine(D, k=2):
    """Classical (Torgerson) MDS of the distance matrix D, shape (p, p): Y, shape (p, k)."""
    ### BEGIN SOLUTION
    D = np.asarray(D, dtype=float)
    p = len(D)
    J = np.eye(p) - np.ones((p, p)) / p
    B = -0.5 * J @ (D**2) @ J
    ell, V = np.linalg.eigh(B)  # ascending
    top = np.argsort(ell)[::-1][:k]
    return V[:, top] * np.sqrt(np.maximum(ell[top], 0.0))
    ### END SOLUTION


# %% nbgrader={"grade": false, "grade_id": "check_mds", "locked": true, "schema_version": 3, "solution": false, "task": false}
def _dist(Y):
    Y = np.asarray(Y, dtype=float)
    return np.linalg.norm(Y[:, None, :] - Y[None, :, :], axis=-1)


def _variant(D, k, square=True, half=True, centre=True, top=True, power=0.5):
    """Classical MDS with one step changed: the usual mistakes, to recognise them."""
    p = len(D)
    J = np.eye(p) - np.ones((p, p)) / p if centre else np.eye(p)
    B = -(0.5 if half else 1.0) * J @ (D**2 if square else D) @ J
    ell, V = np.linalg.eigh(B)
    pick = np.argsort(ell)[::-1][:k] if top else np.argsort(ell)[:k]
    return V[:, pick] * np.maximum(ell[pick], 0.0) ** power


def check_mds(fn, D, k):
    """Compare fn(D, k) with classical MDS by the distances of the points; name the usual mistake."""
    D = np.asarray(D, dtype=float)
    p = len(D)
    got = np.asarray(fn(D, k), dtype=float)
    if got.shape == (k, p) and k != p:
        raise AssertionError(f"got shape {got.shape}: hint: one row per shape, expected ({p}, {k})")
    if got.shape != (p, k):
        raise AssertionError(f"got shape {got.shape}, expected ({p}, {k})")
    want = _dist(_variant(D, k))
    scale = max(1.0, want.max())
    if np.allclose(_dist(got), want, atol=1e-7 * scale):
        print("classical_mds_mine: correct")
        return
    mistakes = [
        (dict(square=False), "double-centre the SQUARED distances D**2, not D"),
        (dict(half=False), "B = -1/2 J D^2 J: the factor 1/2 is missing (distances come out sqrt(2) too long)"),
        (dict(centre=False), "centre D^2 on both sides, J D^2 J with J = I - 11^T/p"),
        (dict(top=False), "np.linalg.eigh returns the eigenvalues in ascending order: take the LAST k"),
        (dict(power=0.0), "scale each eigenvector by the square root of its eigenvalue"),
        (dict(power=1.0), "scale by the SQUARE ROOT of each eigenvalue, not by the eigenvalue"),
    ]
    for kw, hint in mistakes:
        if np.allclose(_dist(got), _dist(_variant(D, k, **kw)), atol=1e-7 * scale):
            raise AssertionError(f"hint: {hint}")
    raise AssertionError("the distances between your points are not those of classical MDS")


# %% nbgrader={"grade": true, "grade_id": "test_classical_mds_mine", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
_rng = np.random.default_rng(4)
_X = _rng.standard_normal((9, 2)) * [3.0, 1.0]  # points in the plane
_Dx = _dist(_X)
check_mds(classical_mds_mine, _Dx, 2)
assert np.allclose(_dist(classical_mds_mine(_Dx, 2)), _Dx), "planar points come back exactly"
print("visible checks passed")

# %% nbgrader={"grade": true, "grade_id": "hidden_classical_mds_mine", "locked": true, "points": 2, "schema_version": 3, "solution": false, "task": false}
# hidden tests: the autograder runs more checks here
### BEGIN HIDDEN TESTS
_X3 = np.random.default_rng(5).standard_normal((12, 3)) * [4.0, 2.0, 1.0]
check_mds(classical_mds_mine, _dist(_X3), 3)  # exact in three dimensions
check_mds(classical_mds_mine, _dist(_X3), 1)  # one axis: the longest
check_mds(classical_mds_mine, D_sdna, 2)  # a real distance matrix: not Euclidean in 2-D
assert np.allclose(_dist(classical_mds_mine(_Dx.tolist(), 2)), _Dx), "a nested list works too"
### END HIDDEN TESTS

# %% [markdown]
# ## Fig. 4: MDS of the cShape-DNA as $M$ shrinks
#
# The pictures below are SMACOF embeddings (`cshape.mds_embedding`), as in the paper; each title gives its
# stress-1, computed by `stress1`. A good descriptor gives tight, separated clusters; a low stress says the picture
# shows the distances faithfully.

# %%
def stress1(D, Y):
    """Kruskal's stress-1 of the embedding Y, shape (p, k), of the distance matrix D."""
    iu = np.triu_indices(len(D), 1)
    return float(np.sqrt(np.sum((D[iu] - _dist(Y)[iu]) ** 2) / np.sum(D[iu] ** 2)))


def name_of(kind, m):
    """A row name for a descriptor kind and its M (or N)."""
    return {"shape-dna": f"Shape-DNA, N={m}", "cshape": f"cShape-DNA M={m}",
            "truncated": f"truncated, first {2 * m + 1}", "f1": f"F1, N={m}"}[kind]


Ms = [m for m in (16, 8, 4, 2, 1) if 2 * m + 1 <= N]
D_of = {("shape-dna", N): D_sdna}  # every distance matrix of the figures, computed once
for m in Ms:
    for kind in ("cshape", "truncated"):
        D_of[kind, m] = table.distance_matrix(Descriptor(kind, N=N, M=m))
D_of["f1", N] = table.distance_matrix(Descriptor("f1", N=N))
embedding = {key: cshape.mds_embedding(D) for key, D in D_of.items()}
stress = {key: stress1(D_of[key], Y) for key, Y in embedding.items()}
print(f"{'descriptor':22s} {'stress-1':>8s} {'axis span':>10s}")
for (kind, m), s in stress.items():
    span = np.ptp(embedding[kind, m], axis=0).max()
    print(f"{name_of(kind, m):22s} {s:8.3f} {span:10.4g}")


# %%
def mds_grid(panels):
    """One MDS panel per (key, title), three to a row, one legend."""
    nrows = -(-len(panels) // 3)
    fig = plots.new_figure((11, 3.6 * nrows))
    axs = fig.subplots(nrows, 3).ravel()
    for ax, (key, title) in zip(axs, panels, strict=False):
        plots.plot_mds(embedding[key], labels=table.labels, ax=ax,
                       title=f"{title}\nstress-1 {stress[key]:.3f}")
    for ax in axs[1:]:  # one legend is enough
        if ax.get_legend() is not None:
            ax.get_legend().remove()
    for ax in axs[len(panels):]:
        ax.set_axis_off()
    return fig


mds_grid([(("shape-dna", N), f"(a) Shape-DNA, N={N}")]
         + [(("cshape", m), f"cShape-DNA M={m} ({2 * m + 1} values)") for m in Ms])

# %% [markdown]
# Compare the axes of panel (a) with the others: the printed "axis span" of the cShape-DNA's embeddings is about
# $\sqrt N$ times the Shape-DNA's, as derived above. Only the shapes of the clusters are comparable across panels.
#
# ## Fig. 5: the truncated Shape-DNA with the same budget, and F1
#
# The fair comparison: keep the *first* $2M+1$ normalised eigenvalues instead (Fig. 5 a-e), or use the F1 feature
# $\left(\lambda_1/\lambda_2, \dots, \lambda_1/\lambda_N\right)$ (Fig. 5f).

# %%
mds_grid([(("truncated", m), f"first {2 * m + 1} eigenvalues") for m in Ms]
         + [(("f1", N), f"(f) F1, N={N}")])

# %% [markdown]
# ## Retrieval measures
#
# Every shape $i$ is used once as the query; the other $p-1$ shapes are ranked by increasing $D_{ij}$ (ties by
# index). With $C$ the size of the query's class, $R = C - 1$ shapes are *relevant*, and $G_k = 1$ when the
# $k$-th result is relevant, else 0 (Shilane et al. 2004):
#
# | measure | formula for one query | meaning |
# |---|---|---|
# | nearest neighbour (NN) | $G_1$ | is the closest shape of the query's class? |
# | first tier (FT) | $\frac1R \sum_{k=1}^{R} G_k$ | recall in the first $R$ results |
# | second tier (ST) | $\frac1R \sum_{k=1}^{2R} G_k$ | recall in the first $2R$ results |
# | E-measure (E) | $\frac{2}{1/P + 1/\text{Rc}} = \frac{2h}{K + R}$, $h = \sum_{k=1}^{K} G_k$, $P = h/K$, $\text{Rc} = h/R$ | precision and recall in the first $K = \min(32, p-1)$ results |
# | DCG | $\Big(G_1 + \sum_{k\ge2} \frac{G_k}{\log_2 k}\Big) \Big/ \Big(1 + \sum_{k=2}^{R} \frac{1}{\log_2 k}\Big)$ | relevant results early count more; 1 is perfect |
# | average precision (AP) | $\frac1R \sum_{k:\,G_k=1} \frac{1}{k}\sum_{j \le k} G_j$ | precision at each relevant result, averaged |
#
# Each measure is averaged over the queries (mAP is the mean of AP); a query whose class has no other shape
# ($R = 0$) has no right answer and is left out. All lie in $[0, 1]$, higher is better. `cshape.retrieval_scores`
# computes the six.
#
# First on the collection above, where each class is one shape with its remeshings or poses, the isometries that
# the Shape-DNA ignores:

# %%
keys = ["nn", "ft", "st", "e", "dcg", "map"]


def score_table(D_by_name, labels):
    """Print the six measures of each named distance matrix; return them."""
    out = {name: cshape.retrieval_scores(D, labels) for name, D in D_by_name.items()}
    print(f"{'descriptor':26s} " + " ".join(f"{k:>6s}" for k in keys))
    for name, sc in out.items():
        print(f"{name:26s} " + " ".join(f"{sc[k]:6.3f}" for k in keys))
    return out


demo_scores = score_table({name_of(*key): D for key, D in D_of.items()}, table.labels)
nn_demo = [sc["nn"] for sc in demo_scores.values()]
print(f"\nnearest neighbour between {min(nn_demo):.3f} and {max(nn_demo):.3f} over these descriptors; "
      f"distinct E values: {sorted({round(sc['e'], 6) for sc in demo_scores.values()})}")

# %% [markdown]
# Read the printed range: how well a descriptor retrieves here depends on the collection's resolution (the small
# run's coarse meshes make it harder, the full-size run's fine ones easy). The E-measure looks at the first
# $K = \min(32, p - 1)$ results; when $p - 1 \le 32$ every relevant shape is among them, $h = R$, and
# $E = 2R/(K + R)$ is the same for every descriptor: the printed distinct E values. Retrieval tells descriptors
# apart best when the members of a class differ and the collection is larger than 33 shapes.
#
# cshape's `creatures` benchmark makes such classes: kinds of creature (human, centaur, teddy, quadruped, bird,
# spider, ant, crab, octopus, starfish, hand, snake) whose members each draw their own limb lengths and
# thicknesses, pose, resolution and a little noise. Its development instance `creatures-dev` (12 classes of 10
# members at full size; 6 classes of 3 coarse members in the small run) is the one used here, and again in
# lesson 08. At full size its eigenvalues come prepared with the package (`retrieval_table`: the output of
# `batch.describe(cshape.data.load_collection("creatures-dev"), N=100)`, checked by the test suite). The picture
# below draws the first member of each class from a coarse copy: `cshape.data.creatures.creature` with the
# member's own seed (the same proportions and pose) on a coarser grid, which builds in a fraction of the time.

# %%
from cshape.course.teaching import retrieval_collection, retrieval_table
from cshape.data import creatures as cr

creatures = retrieval_collection()
ctable = retrieval_table(N)
first = {}
for item in creatures:
    if item.label not in first:  # the first member of each class
        first[item.label] = item
if SMALL:  # the small members are coarse already
    first = {label: item.mesh for label, item in first.items()}
else:  # the member's seed, a coarser grid and fewer vertices: the same creature, drawn coarse
    first = {label: cr.creature(label, item.meta["seed"], voxelsize=0.035, vertices=900)
             for label, item in first.items()}
print(f"{len(ctable)} shapes in {len(first)} classes; p - 1 = {len(ctable) - 1}")
fig = plots.new_figure((2.0 * len(first), 2.2))
for k, (label, mesh) in enumerate(first.items()):
    plots.plot_mesh(mesh, ax=fig.add_subplot(1, len(first), k + 1, projection="3d"), title=label,
                    edges=False)
fig

# %%
D_ret = ctable.distance_matrix(Descriptor("shape-dna", N=N))
C_of = {("shape-dna", N): D_ret}
for m in Ms:
    for kind in ("cshape", "truncated"):
        C_of[kind, m] = ctable.distance_matrix(Descriptor(kind, N=N, M=m))
C_of["f1", N] = ctable.distance_matrix(Descriptor("f1", N=N))
creature_scores = score_table({name_of(*key): D for key, D in C_of.items()}, ctable.labels)

# %%
fig = plots.new_figure((6, 3.6))
ax = fig.add_subplot()
sizes = [2 * m + 1 for m in Ms]
for kind, marker in (("cshape", "o-"), ("truncated", "s--")):
    ax.plot(sizes, [creature_scores[name_of(kind, m)]["ft"] for m in Ms], marker, label=kind)
ax.axhline(creature_scores[name_of("shape-dna", N)]["ft"], color="k", lw=0.8,
           label=f"Shape-DNA, N={N}")
ax.set(xlabel="descriptor size (values)", ylabel="first tier", xscale="log",
       title="same budget, different descriptors")
ax.legend(fontsize="small")
fig

# %% [markdown]
# With the same number of values, the first eigenvalues (truncated) and the cropped DFT (cShape-DNA) are not
# equally good: compare the two curves at each size. Lesson 08 asks why, and finds descriptors that do better.

# %% [markdown] nbgrader={"grade": false, "grade_id": "retrieval_task", "locked": true, "schema_version": 3, "solution": false, "task": false}
# ## Exercise (graded): nearest neighbour and first tier
#
# Write `nn_ft_mine(D, labels)` returning the mean nearest-neighbour rate and the mean first tier over all
# queries, as defined in the table above. Every model $i$ is the query once; the *other* $p - 1$
# models are ranked by increasing $D_{ij}$ (ties by index: `np.argsort(D[i], kind="stable")`). A query whose class
# has no other model ($R = 0$: the cube, the torus and the eight of the demo collection's full-size run) is left
# out of both means, as in `cshape.retrieval_scores`.

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
assert nn_ft_mine(_D, _labels) != (1.0, 1.0), (
    "hint: random points score a perfect NN and FT with your function: is the query its own "
    "first result? D[i, i] = 0; leave the query out of its ranking")
print("visible checks passed")

# %% nbgrader={"grade": true, "grade_id": "hidden_nn_ft_mine", "locked": true, "points": 2, "schema_version": 3, "solution": false, "task": false}
# hidden tests: the autograder runs more checks here
### BEGIN HIDDEN TESTS
_square = np.array([[0, 1, 2, 3], [1, 0, 3, 2], [2, 3, 0, 1], [3, 2, 1, 0]], dtype=float)
assert np.allclose(nn_ft_mine(_square, ["a", "b", "a", "b"]), (0.0, 0.0)), "hand example: (0, 0)"
# first tier over C results instead of C - 1: on this example FT would be 1/2, not 0
_chain = np.array([[0, 1, 5, 9], [1, 0, 4, 8], [5, 4, 0, 3], [9, 8, 3, 0]], dtype=float)
_got = nn_ft_mine(_chain, ["a", "a", "b", "b"])
assert np.allclose(_got, (1.0, 1.0)), (
    f"hand example: two tight pairs give (1, 1), got {_got}; hint: the first tier counts the "
    "first R = C - 1 results, the class size minus the query")
_lonely = np.r_[_labels[:-1], ["d"]]  # "d" is a class of one: its query is left out
_want = cshape.retrieval_scores(_D, _lonely)
assert np.allclose(nn_ft_mine(_D, _lonely), (_want["nn"], _want["ft"])), (
    "hint: a query whose class has no other member has no right answer: leave it out of the means")
for _DD, _ll in ((_D, _labels), (D_sdna, table.labels), (D_ret, ctable.labels)):
    _want = cshape.retrieval_scores(_DD, _ll)
    assert np.allclose(nn_ft_mine(_DD, _ll), (_want["nn"], _want["ft"])), "against retrieval_scores"
### END HIDDEN TESTS

# %% [markdown]
# ## The other measures, for one query
#
# The E-measure, DCG and average precision of the table above, computed from the ranking of one query (the first
# creature, by the Shape-DNA) with the formulas, and checked against `cshape.retrieval_scores` over all queries.

# %%
def measures(D, labels, i):
    """E, DCG and AP of query i, from the formulas of the table."""
    labels = np.asarray(labels)
    order = np.argsort(D[i], kind="stable")
    order = order[order != i]
    G = (labels[order] == labels[i]).astype(float)  # G_k, k = 1 .. p-1
    R = int(G.sum())
    K = min(32, len(G))
    h = G[:K].sum()
    e = 2 * h / (K + R)
    k = np.arange(1, len(G) + 1)
    discount = np.r_[1.0, 1 / np.log2(k[1:])]
    dcg = (G * discount).sum() / discount[:R].sum()
    ap = np.sum(np.cumsum(G)[G == 1] / k[G == 1]) / R
    return {"G": G, "e": e, "dcg": dcg, "ap": ap}


q = measures(D_ret, ctable.labels, 0)
print(f"query {ctable.names[0]} ({ctable.labels[0]}): first results G = {q['G'][:12].astype(int)} ...")
print(f"E = {q['e']:.3f}, DCG = {q['dcg']:.3f}, AP = {q['ap']:.3f}")
mean = {key: np.mean([measures(D_ret, ctable.labels, i)[key] for i in range(len(D_ret))])
        for key in ("e", "dcg", "ap")}
want = creature_scores[name_of("shape-dna", N)]
print("mean over queries:", {k: round(float(v), 4) for k, v in mean.items()},
      "| retrieval_scores:", {k: round(want[k], 4) for k in ("e", "dcg", "map")})
assert np.allclose([mean["e"], mean["dcg"], mean["ap"]], [want["e"], want["dcg"], want["map"]])

# %% [markdown] nbgrader={"grade": false, "grade_id": "explain_m1_task", "locked": true, "schema_version": 3, "solution": false, "task": false}
# ## Written answer (graded by hand)
#
# In Fig. 4 the classes of the panel $M = 1$ overlap more than in the panel of the Shape-DNA. Is that a failure of
# the picture (MDS) or of the descriptor? Argue from two printed numbers of this notebook: the stress-1 of the
# panels and the retrieval measures, which use the full distance matrix and no picture. (4-6 sentences.)

# %% [markdown] nbgrader={"grade": true, "grade_id": "explain_m1", "locked": false, "points": 2, "schema_version": 3, "solution": true, "task": false}
# ### BEGIN SOLUTION
# The cShape-DNA with $M = 1$ has three values, so its distance matrix is nearly three-dimensional and a
# two-dimensional embedding shows it with a low stress-1 (the printed value is of the same order as, or below,
# the Shape-DNA's): the picture is faithful, and what it shows is in $D$ itself. The retrieval measures, computed
# from $D$ without any embedding, agree: the nearest-neighbour and first-tier rates of $M = 1$ are at or below
# those of the Shape-DNA and of $M = 16$ on both collections. So the overlap is the descriptor's: three
# low-frequency DFT coefficients keep only the slow trend of the Weyl-subtracted spectrum, which different
# shapes can share. A high stress would have pointed at the picture instead: then two clusters may overlap in the
# plane while their distances in $D$ are large.
# ### END SOLUTION

# %% [markdown]
# ## Exercises
#
# 1. Which pair of shapes of different classes does the cShape-DNA with $M = 1$ confuse most (the smallest
#    distance between two classes)? Find it in `D_of["cshape", 1]` with `np.argsort` and draw both meshes.
# 2. The spheres of the demo collection (S1 and S2 at full size, sphere-2 and sphere-3 in the small run) differ only
#    in resolution. How large is their mutual distance relative to the distance from a sphere to the cube, for the
#    Shape-DNA and for the cShape-DNA?
# 3. Compute the difference statistics of Fig. 3 for `normalization="weyl"` (pass it to
#    `table.distance_matrix`). Does the choice of normalisation matter here?
# 4. SMACOF against classical MDS: compute the stress-1 of `classical_mds_mine(D, 2)` for the Shape-DNA and for
#    the cShape-DNA with $M = 1$, and compare it with the stress of `cshape.mds_embedding`. Which is lower, and
#    must it be? What do the eigenvalues of $B$ beyond the second say about how many dimensions the distances
#    need?
# 5. With the first eigenvalue of $B$ for the Shape-DNA, compare $\sqrt{\ell_1}$ for the two descriptors: is their
#    ratio again close to $\sqrt N$? Why must it be, given the derivation of the two scales?
#
# ## References
#
# - Z. Gao, Z. Yu, X. Pang, *A compact shape descriptor for triangular surface meshes*, Computer-Aided Design 53
#   (2014) 62-69.
# - M. Reuter, F.-E. Wolter, N. Peinecke, *Laplace-Beltrami spectra as "Shape-DNA" of surfaces and solids*,
#   Computer-Aided Design 38 (2006) 342-366.
# - I. Borg, P. J. F. Groenen, *Modern Multidimensional Scaling*, 2nd ed., Springer (2005): classical MDS
#   (ch. 12) and SMACOF (ch. 8).
# - J. B. Kruskal, *Multidimensional scaling by optimizing goodness of fit to a nonmetric hypothesis*,
#   Psychometrika 29 (1964) 1-27: stress-1.
# - P. Shilane, P. Min, M. Kazhdan, T. Funkhouser, *The Princeton Shape Benchmark*, Shape Modeling International
#   (2004): NN, FT, ST, E, DCG.
