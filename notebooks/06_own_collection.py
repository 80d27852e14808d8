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
# 5. find the downloadable benchmarks cshape knows about.

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

from cshape.data import variants


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
    human = variants.articulated_figure("human", k, voxelsize=size(0.05, 0.03),
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
# `table.distance_matrix()` and `cshape query`) compares the **exploration default**, `cshape.DEFAULT`: the
# two-scale log spectrum (the first nine log-Weyl ratios beside the whole spectrum's fluctuations about its
# trend), whose *worst shortfall* from the best descriptor of each set was smallest over three real labelled
# collections (a category benchmark, characters in poses, five people in poses) and the generated suite, with
# the same shape at several resolutions as a guard. The paper's cShape-DNA is one
# value away: `cshape.PAPER` (here with our `N` and `M`). Always print which descriptor compared your shapes
# (`index.descriptor_.label`).

# %%
print("default:", cshape.DEFAULT)
base = coll["torus1"].mesh
c, s_ = np.cos(0.7), np.sin(0.7)
R = np.array([[c, -s_, 0], [s_, c, 0], [0, 0, 1]])
query = cshape.Mesh(1.7 * base.vertices @ R.T, base.faces)
query = variants.add_normal_noise(query, 0.3, random_state=1)
lam_q = cshape.shape_dna(query, N=N)
paper = cshape.PAPER.replace(N=N, M=M)  # the paper's cShape-DNA, with our N and M
for index in (cshape.DescriptorIndex.from_table(table),  # the default
              cshape.DescriptorIndex.from_table(table, paper)):
    dist, ind = index.query_spectra(lam_q, query.area, k=3)
    print("nearest by the", index.descriptor_.label)
    for d, i in zip(dist[0], ind[0], strict=True):
        print(f"    {table.names[i]:10s} ({table.labels[i]:7s}) distance {d:8.3f}")
plots.plot_mesh(query, title="the query: a noisy, rotated, scaled torus", edges=False)

# %% [markdown]
# ## A picture of the collection
#
# Multidimensional scaling of the distance matrix (notebook 4) places similar shapes close together. The title
# says which descriptor was compared; the paper's cShape-DNA is drawn beside it.

# %%
import matplotlib.pyplot as plt

from cshape import compare

fig, axs = plt.subplots(1, 2, figsize=(10, 4.5))
for ax, descriptor in zip(axs, (cshape.DEFAULT.for_N(N), paper), strict=True):
    Y = compare.mds_embedding(table.distance_matrix(descriptor))
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
# 1. Point `folder` at a folder of your own meshes (labels come from the sub-folders; no meshes at hand? write
#    `cshape.course.teaching.spot()`, its `cshape.variants.subdivide` and its `cshape.variants.remesh` into a
#    folder `cow/`, beside this notebook's `spheres/` and `tori/`) and draw the MDS plot of notebook 4 for them.
# 2. Interrupt a `describe` run on a large collection (Kernel > Interrupt) and run it again: how many meshes
#    come from the cache?
# 3. Measure the time of `describe` for `n_jobs=1` and `n_jobs=2` on 20 meshes of 5000 vertices. Where is the
#    time spent: FEM assembly or the eigensolve? (`cshape.fem_matrices` vs `cshape.shape_dna`.)
# 4. Build a `DescriptorIndex` of the F1 features and of the cShape-DNA with $M = 2$. Which one finds the torus?
# 5. `cshape.DEFAULT` was chosen on three real collections and the suite. Score it against the paper's
#    cShape-DNA on your own labelled folder with
#    `compare.retrieval_scores(table.distance_matrix(descriptor), table.labels)`.
