# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 6 · Working with your own collection
#
# **Paper:** the whole pipeline of Section 2 (Eq. 3-10), applied the way Section 3 does it to a database.
#
# **Learning goals.** After this notebook you can
#
# 1. point cshape at a folder of meshes (one sub-folder per class) and get names and labels;
# 2. compute every shape's eigenvalues once, with a cache that makes the next run (or an interrupted one) fast,
#    in parallel processes or on a Dask cluster;
# 3. query the nearest neighbours of a new shape with `DescriptorIndex`, and say which descriptor compared them;
# 4. save the table (CSV or NPZ) and load it back;
# 5. find the downloadable benchmarks cshape knows about;
# 6. say how eigenvalues scale with the size of a shape, and compute a query's nearest neighbours and a
#    collection's distance matrix yourself, from descriptors and from a saved CSV (graded).
#
# **Prerequisites:** lessons 02 (normalisation), 03 (the cShape-DNA), 04 (distance matrices, MDS, retrieval).

# %%
# %matplotlib inline
import numpy as np

import cshape
from cshape import plots, shapes
from cshape.course.teaching import SMALL, size  # CSHAPE_SMALL=1: small meshes and N

np.set_printoptions(precision=4, suppress=True, linewidth=100)
print("cshape", cshape.__version__, "(small sizes)" if SMALL else "")

# %% [markdown]
# ## A folder of meshes
#
# Your own collection is a folder such as
#
# ```
# my_meshes/
#     chairs/  chair1.obj  chair2.ply ...
#     cups/    cup1.off ...
# ```
#
# Here we write one from built-in shapes (and PyMeshLab's sample meshes) into a temporary folder, so the
# notebook runs anywhere. Replace `folder` by your own.

# %%
import tempfile
from pathlib import Path

from cshape.data import bodies, variants


def write_obj(mesh, path):
    """A minimal Wavefront OBJ writer (vertices and triangles)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w") as f:
        f.writelines(f"v {x:.9g} {y:.9g} {z:.9g}\n" for x, y, z in mesh.vertices)
        f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in mesh.faces)


tmp = tempfile.TemporaryDirectory(prefix="cshape-own-")  # removed at the end of the notebook
work = Path(tmp.name)
folder = work / "my_meshes"
for k in range(3):
    write_obj(shapes.icosphere(size(2, 4), radius=1 + 0.5 * k), folder / "spheres" / f"sphere{k}.obj")
    write_obj(shapes.torus(16 * (k + 2), 8 * (k + 2)), folder / "tori" / f"torus{k}.obj")
    write_obj(shapes.cube(4 + 2 * k + size(0, 6)), folder / "cubes" / f"cube{k}.obj")
    human = bodies.articulated_figure("human", k, voxelsize=size(0.05, 0.03),
                                        target_vertices=size(500, 2000))
    write_obj(human, folder / "humans" / f"human{k}.obj")
print(sorted(str(p.relative_to(folder)) for p in folder.rglob("*.obj")))

# %%
import cshape.data

coll = cshape.data.load_folder(folder, labels="subfolder")
print(coll)
print(list(zip(coll.names, coll.labels, strict=True)))

# %% [markdown]
# ## Descriptors, cached
#
# `batch.describe` stores each mesh's eigenvalues in the cache folder under a key made from the mesh's
# *content* (and the boundary condition): renaming or moving a file does not invalidate it, changing a vertex
# does. Only `N` eigenvalues per mesh are kept; every descriptor (any `M`, any transform) is derived from them.

# %%
import time

from cshape import batch

N, M = size(30, 100), size(8, 16)
cache = work / "cache"
t0 = time.perf_counter()
table = batch.describe(coll, N=N, cache_dir=cache, progress=False)
print(f"first run:  {time.perf_counter() - t0:5.2f} s, "
      f"from cache: {table.cached.sum()} of {len(table)}")
t0 = time.perf_counter()
table = batch.describe(coll, N=N, cache_dir=cache, progress=False)
print(f"second run: {time.perf_counter() - t0:5.2f} s, "
      f"from cache: {table.cached.sum()} of {len(table)}")
table

# %% [markdown]
# ### In parallel
#
# `n_jobs=2` computes in two worker processes (each with one BLAS thread); they do not re-run your
# script, so a plain script works as it is. For a cluster, pass a Dask client (or a scheduler address)
# as `client=`; the cache stays on this machine.

# %%
t0 = time.perf_counter()
par = batch.describe(coll, N=N, cache_dir=work / "cache-parallel", n_jobs=2,
                     progress=False)
print(f"2 processes: {time.perf_counter() - t0:5.2f} s;",
      "same eigenvalues:", np.allclose(par.lam, table.lam))

# %%
try:
    from dask.distributed import Client
except ImportError:
    print("Dask is not installed: pip install 'cshape[distributed]'")
else:
    with Client(processes=False, n_workers=1, threads_per_worker=2,
                dashboard_address=None) as client:
        t0 = time.perf_counter()
        dsk = batch.describe(coll, N=N, cache_dir=False, client=client, progress=False)
        print(f"Dask (in-process cluster): {time.perf_counter() - t0:5.2f} s;",
              "same eigenvalues:", np.allclose(dsk.lam, table.lam))

# %% [markdown]
# ## Which stored shape is this?
#
# `cshape.DescriptorIndex` answers nearest-neighbour queries against a database of descriptors. We query a
# shape the collection has never seen: a noisy, rotated, larger copy of one of the tori (rotation and scale do
# not change the normalised spectrum; the noise does, a little).
#
# Which descriptor is one value, a `cshape.Descriptor`. With none given, the index (like `table.descriptors()`,
# `table.distance_matrix()` and `cshape query`) compares the **exploration default**, `cshape.DEFAULT`, a
# descriptor built on the log-Weyl ratios of lesson 08; how it was chosen is told in the guide *Choosing a
# descriptor* (`docs/guides/choosing-a-descriptor.md`). The paper's cShape-DNA is one value away: `cshape.PAPER`
# (here with our `N` and `M`). Always print which descriptor compared your shapes (`index.descriptor_.label`).

# %% [markdown] nbgrader={"grade": false, "grade_id": "predict_scale_task", "locked": true, "schema_version": 3, "solution": false, "task": false}
# ### Predict (graded)
#
# The query below is `torus1` rotated, scaled by $s = 1.7$ and roughened a little. Before you run the cell after
# the next, predict the median over $i \ge 1$ of the ratio of *raw* eigenvalues (before any normalisation)
# $\lambda_i^{\text{query}} / \lambda_i^{\text{torus1}}$. (Hint: $\Delta$ has two derivatives; the eigenvalues
# of a circle of radius $r$ are $k^2/r^2$.)

# %% nbgrader={"grade": false, "grade_id": "predict_scale", "locked": false, "schema_version": 3, "solution": true, "task": false}
# write your prediction as `prediction = ...` (a number or an expression)
### BEGIN SOLUTION
prediction = 1 / 1.7**2
### END SOLUTION

# %%
print("default:", cshape.DEFAULT)
base = coll["torus1"].mesh
c, s_ = np.cos(0.7), np.sin(0.7)
R = np.array([[c, -s_, 0], [s_, c, 0], [0, 0, 1]])
query = cshape.Mesh(1.7 * base.vertices @ R.T, base.faces)
query = variants.add_normal_noise(query, 0.3, random_state=1)
lam_q = cshape.shape_dna(query, N=N)
lam_t = table.lam[table.names.index("torus1")]
scale_ratio = float(np.median(lam_q[1:] / lam_t[1:]))
print(f"median of lam_query / lam_torus1: {scale_ratio:.4f}; 1 / 1.7^2 = {1 / 1.7**2:.4f}")
print(f"area ratio {query.area / base.area:.3f} (1.7^2 = {1.7**2:.2f}); after the area normalisation "
      f"lam * area the ratio is {scale_ratio * query.area / base.area:.3f}")

# %% nbgrader={"grade": true, "grade_id": "test_predict_scale", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
assert np.ndim(prediction) == 0 and np.isfinite(float(prediction)), "prediction is one number"
print(f"you predicted {float(prediction):.4f}; the printed median is {scale_ratio:.4f}")
# hidden test: the prediction is within 10 % of the printed median
### BEGIN HIDDEN TESTS
_p = float(prediction)
if abs(_p / scale_ratio - 1) >= 0.1:
    if abs(_p - 1 / 1.7) < 0.05:
        _why = "hint: eigenvalues scale with 1 / length^2 (two derivatives), not 1 / length"
    elif _p > 1:
        _why = ("hint: a larger shape vibrates more slowly: its eigenvalues are SMALLER, "
                "lam_i(s X) = lam_i(X) / s^2")
    elif abs(_p - 1) < 0.1:
        _why = ("hint: the raw eigenvalues do change with size; only the normalised ones "
                "(lam * area) do not")
    else:
        _why = "hint: lam_i(s X) = lam_i(X) / s^2"
    raise AssertionError(f"{_why} (the median is {scale_ratio:.4f}; within 10 % counts)")
### END HIDDEN TESTS

# %% [markdown]
# The printed median is close to $1/s^2$: scaling a surface by $s$ scales every gradient by $1/s$, so the Rayleigh
# quotient $\int|\nabla u|^2 / \int u^2$ by $1/s^2$, while the area grows by $s^2$ (printed); the product
# $\lambda_i \cdot \text{area}$, the normalisation of lesson 02, does not change. The roughness adds a little area
# and lowers the eigenvalues a little (the two printed departures from $s^2$ and $1/s^2$); in the product they
# nearly cancel, the last printed number. That is why the index can find a shape of another size.

# %%
paper = cshape.PAPER.replace(N=N, M=M)  # the paper's cShape-DNA, with our N and M
for index in (cshape.DescriptorIndex.from_table(table),  # the default
              cshape.DescriptorIndex.from_table(table, paper)):
    dist, ind = index.query_spectra(lam_q, query.area, k=3)
    print("nearest by the", index.descriptor_.label)
    for d, i in zip(dist[0], ind[0], strict=True):
        print(f"    {table.names[i]:10s} ({table.labels[i]:7s}) distance {d:8.3f}")
plots.plot_mesh(query, title="the query: a noisy, rotated, scaled torus", edges=False)

# %% [markdown] nbgrader={"grade": false, "grade_id": "nearest_task", "locked": true, "schema_version": 3, "solution": false, "task": false}
# ## Exercise (graded): a nearest-neighbour query by hand
#
# Write `nearest_mine(X, x, k)`: the `k` rows of the database `X` (shape $(p, d)$, one descriptor per row) nearest
# to the descriptor `x` (shape $(d,)$), by Euclidean distance. Return `(dist, ind)`, two arrays of length `k`,
# nearest first (ties by row index: `np.argsort(..., kind="stable")`), as `DescriptorIndex.query` does for one
# query. The check compares your answer with the index above, for the paper's cShape-DNA of the query (its real
# form, `cshape.descriptors.real_form`, the same numbers the table stores).

# %% nbgrader={"grade": false, "grade_id": "nearest_mine", "locked": false, "schema_version": 3, "solution": true, "task": false}
def nearest_mine(X, x, k):
    """Distances and row indices of the k rows of X nearest to x, nearest first."""
    ### BEGIN SOLUTION
    X, x = np.asarray(X, dtype=float), np.asarray(x, dtype=float)
    d = np.linalg.norm(X - x, axis=1)
    ind = np.argsort(d, kind="stable")[:k]
    return d[ind], ind
    ### END SOLUTION


# %% nbgrader={"grade": false, "grade_id": "check_nearest", "locked": true, "schema_version": 3, "solution": false, "task": false}
def check_nearest(fn, X, x, k):
    """Compare fn(X, x, k) with a brute-force search; name the usual mistake."""
    X, x = np.asarray(X, dtype=float), np.asarray(x, dtype=float)
    d = np.linalg.norm(X - x, axis=1)
    ind = np.argsort(d, kind="stable")[:k]
    got_d, got_i = (np.asarray(v) for v in fn(X, x, k))
    if got_d.shape != (k,) or got_i.shape != (k,):
        raise AssertionError(f"return two arrays of length k = {k}, got shapes {got_d.shape}, "
                             f"{got_i.shape}")
    if np.array_equal(got_i, np.argsort(d, kind="stable")[::-1][:k]):
        raise AssertionError("hint: you returned the FARTHEST rows: sort ascending, nearest first")
    if not np.array_equal(got_i, ind):
        raise AssertionError(f"rows {got_i.tolist()}, expected {ind.tolist()}")
    if np.allclose(got_d, d[ind] ** 2):
        raise AssertionError("hint: these are squared distances: take the square root")
    if np.allclose(got_d, np.abs(X - x).sum(axis=1)[ind]):
        raise AssertionError("hint: this is the L1 (city-block) distance: use the Euclidean norm")
    if not np.allclose(got_d, d[ind]):
        raise AssertionError(f"distances {got_d}, expected {d[ind]}")
    print("nearest_mine: correct")


# %% nbgrader={"grade": true, "grade_id": "test_nearest_mine", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
from cshape.descriptors import real_form

X_paper = table.descriptors(paper)
x_query = real_form(cshape.compact_shape_dna(lam_q, N=N, M=M, area=query.area))
check_nearest(nearest_mine, X_paper, x_query, 3)
_dist, _ind = cshape.DescriptorIndex.from_table(table, paper).query_spectra(lam_q, query.area, k=3)
assert np.array_equal(nearest_mine(X_paper, x_query, 3)[1], _ind[0]), "the index finds other rows"
print("visible checks passed")

# %% nbgrader={"grade": true, "grade_id": "hidden_nearest_mine", "locked": true, "points": 2, "schema_version": 3, "solution": false, "task": false}
# hidden tests: the autograder runs more checks here
### BEGIN HIDDEN TESTS
assert np.allclose(nearest_mine(X_paper, x_query, 3)[0], _dist[0]), "distances as the index's"
check_nearest(nearest_mine, X_paper, x_query, 1)
check_nearest(nearest_mine, X_paper, x_query, len(X_paper))
_Xr = np.random.default_rng(2).standard_normal((20, 5))
check_nearest(nearest_mine, _Xr, _Xr[3] + 0.01, 4)
# ties by index: two equal rows
_Xt = np.array([[0.0, 1.0], [1.0, 0.0], [0.0, 1.0]])
assert nearest_mine(_Xt, np.array([0.0, 0.9]), 2)[1].tolist() == [0, 2], "ties: the lower row first"
### END HIDDEN TESTS

# %% [markdown]
# ## A picture of the collection
#
# Multidimensional scaling of the distance matrix (notebook 4) places similar shapes close together. The title
# says which descriptor was compared; the paper's cShape-DNA is drawn beside it.

# %%
import matplotlib.pyplot as plt

fig, axs = plt.subplots(1, 2, figsize=(10, 4.5))
for ax, descriptor in zip(axs, (cshape.DEFAULT.for_N(N), paper), strict=True):
    Y = cshape.mds_embedding(table.distance_matrix(descriptor))
    plots.plot_mds(Y, table.names, table.labels, ax=ax, title=f"MDS by the {descriptor.label}")
fig.tight_layout()

# %% [markdown]
# ## Save the table, load it back
#
# CSV (a header, then one row per shape: name, label, area, components, eigenvalues; `pandas.read_csv` reads it with no
# options, and the metadata go to `descriptors.csv.json` beside it) is easy to read anywhere; NPZ is compact. Both
# round-trip exactly.

# %%
csv_path = table.save(work / "descriptors.csv")
npz_path = table.save(work / "descriptors.npz")
back = batch.DescriptorTable.load(csv_path)
print(back, "| identical:", np.array_equal(back.lam, table.lam) and back.names == table.names)
print("".join(csv_path.read_text().splitlines(keepends=True)[:3])[:400], "...")

# %% [markdown] nbgrader={"grade": false, "grade_id": "csv_task", "locked": true, "schema_version": 3, "solution": false, "task": false}
# ## Exercise (graded): distances from the CSV alone
#
# A colleague gets only `descriptors.csv`. Write `distances_from_csv_mine(path, N, M)` returning the $p \times p$
# matrix of Euclidean distances between the paper's cShape-DNAs ($N$ eigenvalues, crop $M$, area normalisation)
# of the shapes in the file, in file order. Read it with `pandas.read_csv(path)`: the columns `area` and
# `lam_0, lam_1, ...` are what you need. `cshape.compact_shape_dna(lam, N=N, M=M, area=area)` takes eigenvalues
# as well as a mesh. The check compares your matrix with `table.distance_matrix(...)`.

# %% nbgrader={"grade": false, "grade_id": "distances_from_csv_mine", "locked": false, "schema_version": 3, "solution": true, "task": false}
def distances_from_csv_mine(path, N, M):
    """Distances between the paper's cShape-DNAs of the shapes in a DescriptorTable CSV."""
    ### BEGIN SOLUTION
    import pandas as pd

    df = pd.read_csv(path)
    lam = df[[f"lam_{i}" for i in range(N)]].to_numpy(dtype=float)
    S = np.array([cshape.compact_shape_dna(row, N=N, M=M, area=a)
                  for row, a in zip(lam, df["area"], strict=True)])
    return np.linalg.norm(S[:, None, :] - S[None, :, :], axis=-1)
    ### END SOLUTION


# %% nbgrader={"grade": false, "grade_id": "check_csv", "locked": true, "schema_version": 3, "solution": false, "task": false}
def check_csv(fn, path, table, N, M):
    """Compare fn(path, N, M) with the table's distance matrix; name the usual mistake."""
    want = table.distance_matrix(cshape.PAPER.replace(N=N, M=M))
    got = np.asarray(fn(path, N, M), dtype=float)
    if got.shape != want.shape:
        raise AssertionError(f"got shape {got.shape}, expected {want.shape}: one row and one column "
                             "per shape of the file")
    if np.allclose(got, want, rtol=1e-8, atol=1e-8 * want.max()):
        print("distances_from_csv_mine: correct")
        return
    raw = np.array([cshape.compact_shape_dna(lam[:N], N=N, M=M, area=1.0) for lam in table.lam])
    if np.allclose(got, np.linalg.norm(raw[:, None] - raw[None], axis=-1), rtol=1e-6):
        raise AssertionError("hint: your distances depend on the shapes' sizes: pass each shape's "
                             "area (area=...) so that the eigenvalues are normalised, lam * area")
    if not np.allclose(np.diag(got), 0):
        raise AssertionError("hint: a shape's distance to itself is 0: are rows and columns in the "
                             "same (file) order?")
    raise AssertionError("your distances differ from table.distance_matrix(cshape.PAPER.replace("
                         f"N={N}, M={M})): use the first N eigenvalue columns lam_0 .. lam_{N - 1}")


# %% nbgrader={"grade": true, "grade_id": "test_distances_from_csv_mine", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
check_csv(distances_from_csv_mine, csv_path, table, N, M)
print("visible checks passed")

# %% nbgrader={"grade": true, "grade_id": "hidden_distances_from_csv_mine", "locked": true, "points": 2, "schema_version": 3, "solution": false, "task": false}
# hidden tests: the autograder runs more checks here
### BEGIN HIDDEN TESTS
check_csv(distances_from_csv_mine, csv_path, table, N - 10, 4)  # fewer eigenvalues than stored
check_csv(distances_from_csv_mine, str(csv_path), table, N, 1)  # a path given as a string
### END HIDDEN TESTS

# %% [markdown]
# ## Benchmarks
#
# `cshape data list` (or `cshape.data.list_collections()`) shows every collection cshape knows: generated ones
# (built on your machine), PyMeshLab's samples, downloadable ones (fetched only when you ask:
# `cshape data build NAME`), and benchmarks whose terms ask you to download them by hand (McGill, the paper's
# database; TOSCA; SHREC'07): the description says where they go.

# %%
for name in cshape.data.list_collections():
    info = cshape.data.info(name)
    print(f"{name:20s} {info['kind']:9s} {info['description'][:90]}...")

# %% [markdown]
# ## Cleaning up
#
# The example folder, its caches and the tables were temporary: remove them (your own `folder` stays where it is).

# %%
tmp.cleanup()
print("removed", work, "| exists:", work.exists())

# %% [markdown]
# ## Exercises
#
# 1. Build a folder of your own (the example folder above is gone): for instance `Path("my_meshes")` with
#    `cow/` holding `cshape.course.teaching.real_mesh()[0]`, its `cshape.data.variants.subdivide(mesh, 1)` and its
#    `cshape.data.variants.remesh(mesh, target_vertices=1500)`, and `spheres/` and `tori/` written as above
#    (`write_obj`). Describe it and draw the MDS plot of notebook 4 for it. Where do the three cows fall?
# 2. Interrupt a `describe` run on a large collection (Kernel > Interrupt) and run it again: how many meshes
#    come from the cache?
# 3. Measure the time of `describe` for `n_jobs=1` and `n_jobs=2` on 20 meshes of 5000 vertices. Where is the
#    time spent: FEM assembly or the eigensolve? (`cshape.fem_matrices` vs `cshape.shape_dna`.)
# 4. Build a `DescriptorIndex` of the F1 features and of the cShape-DNA with $M = 2$. Which one finds the torus?
# 5. Score `cshape.DEFAULT` against the paper's cShape-DNA on your own labelled folder with
#    `cshape.retrieval_scores(table.distance_matrix(descriptor), table.labels)`. Why is a score on a handful of
#    shapes weak evidence for either?
#
# ## References
#
# - Z. Gao, Z. Yu, X. Pang, *A compact shape descriptor for triangular surface meshes*, Computer-Aided Design 53
#   (2014) 62-69, Sections 2-3.
# - M. Reuter, F.-E. Wolter, N. Peinecke, *Laplace-Beltrami spectra as "Shape-DNA" of surfaces and solids*,
#   Computer-Aided Design 38 (2006) 342-366: scaling and normalisation of the spectrum.
# - P. Shilane, P. Min, M. Kazhdan, T. Funkhouser, *The Princeton Shape Benchmark*, Shape Modeling International
#   (2004).
# - The guide *Choosing a descriptor* (`docs/guides/choosing-a-descriptor.md`): how `cshape.DEFAULT` was chosen.
