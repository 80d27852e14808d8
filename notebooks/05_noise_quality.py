# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 5 · Sensitivity to noise and to mesh quality
#
# **Paper:** Gao, Yu and Pang, *A compact shape descriptor for triangular surface meshes*, Computer-Aided Design 53 (2014) 62-69; Section 3.3, Fig. 7 (difference matrices under noise), Fig. 8 (descriptor differences per model),
# Fig. 9 (cShape-DNA of a marching-cubes mesh and of its remesh).
#
# **Learning goals.** After this notebook you can
#
# 1. add the paper's noise: move every vertex along its outward normal by a random distance up to
#    $\lambda \times L$ ($L$ the mean edge length, $\lambda \in \{0.5, 1, 2, 4, 10\}$);
# 2. measure how noise changes the distance matrices of the Shape-DNA and of the cShape-DNA (Fig. 7) and each
#    model's descriptor (Fig. 8);
# 3. measure triangle quality (angles, aspect ratios) and see that the spectrum depends on the shape, not on the
#    triangulation (Fig. 9).
#
# **Why noise matters.** Noise adds area (a rough surface is larger) and small-scale wiggles that the higher
# eigenfunctions feel: the normalised eigenvalues shift, the more so the larger $\lambda$.

# %%
# %matplotlib inline
import numpy as np

import cshape
from cshape import plots, shapes
from cshape.course.teaching import SMALL, size  # CSHAPE_SMALL=1: small meshes and N

np.set_printoptions(precision=4, suppress=True, linewidth=100)
print("cshape", cshape.__version__, "(small sizes)" if SMALL else "")

# %%
from cshape import batch

# a few classes made in code (small) or paper-models + articulated (full size)
from cshape.course.teaching import demo_collection
from cshape.data import variants

collection = demo_collection()
if not SMALL:  # leave out the largest meshes: every model is solved once per noise level
    collection = [c for c in collection if c[0] not in ("S2", "S3", "D2")]
N = size(30, 100)
M = size(8, 16)
levels = size([0.5, 2.0, 10.0], [0.5, 1.0, 2.0, 4.0, 10.0])
print(len(collection), "models, noise levels", levels)

# %% [markdown]
# ## What the noise looks like

# %%
name, label, mesh = collection[-1]
fig = plots.new_figure((3 * (len(levels) + 1), 3))
for k, lev in enumerate([0.0, *levels]):
    noisy = variants.add_normal_noise(mesh, lev, random_state=0)
    plots.plot_mesh(noisy, ax=fig.add_subplot(1, len(levels) + 1, k + 1, projection="3d"),
                    title=f"{name}, lambda = {lev}", edges=False)
fig

# %% [markdown]
# The same model clean and at the middle noise level, side by side: drag each to rotate it, scroll to zoom in on the
# surface. Noise moves every vertex along its normal, so the outline hardly changes while the surface turns rough,
# and the high eigenvalues, which measure small-scale oscillation, go up.

# %%
lev = levels[len(levels) // 2]
plots.view_meshes({f"{name}, clean": mesh,
                   f"{name}, lambda = {lev}": variants.add_normal_noise(mesh, lev, random_state=0)},
                  edges=False, height=380)

# %% [markdown]
# ## Descriptors of the clean and the noisy collections
#
# `batch.describe` caches eigenvalues by mesh content, so rerunning this notebook only computes what is new.

# %%
clean = batch.describe(collection, N=N, progress=not SMALL)
noisy = {}
for lev in levels:
    noisy_items = [(n, lab, variants.add_normal_noise(m, lev, random_state=0))
                   for n, lab, m in collection]
    noisy[lev] = batch.describe(noisy_items, N=N, progress=not SMALL)
print(clean)

# %% [markdown]
# ## Fig. 7: difference matrices against the noise-free collection
#
# For each noise level, the scaled distance matrix of the noisy models is compared with that of the clean
# ones, for the normalised Shape-DNA (top) and the cShape-DNA (bottom).

# %%
from cshape import Descriptor, compare

diffs, titles, stats = {"shape-dna": [], "cshape": []}, {"shape-dna": [], "cshape": []}, []
for lev in levels:
    for kind in ("shape-dna", "cshape"):
        d = Descriptor(kind, N=N, M=M)
        D0, D1 = clean.distance_matrix(d), noisy[lev].distance_matrix(d)
        mean, std = compare.scaled_difference(D0, D1)
        diffs[kind].append(compare.difference_matrix(D0, D1))
        titles[kind].append(f"lambda={lev}: {mean:.1f} / {std:.1f}")
        stats.append((lev, kind, mean, std))
vmax = max(d.max() for v in diffs.values() for d in v)
print("mean / std of each difference image")
plots.plot_matrices(diffs["shape-dna"], [f"Shape-DNA {t}" for t in titles["shape-dna"]], vmax=vmax)

# %%
plots.plot_matrices(diffs["cshape"], [f"cShape-DNA {t}" for t in titles["cshape"]], vmax=vmax)

# %%
print(f"{'lambda':>7s} {'Shape-DNA mean/std':>20s} {'cShape-DNA mean/std':>20s}")
for lev in levels:
    s = {k: (m, sd) for lv, k, m, sd in stats if lv == lev}
    print(f"{lev:7.1f} {s['shape-dna'][0]:12.2f} / {s['shape-dna'][1]:5.2f} "
          f"{s['cshape'][0]:12.2f} / {s['cshape'][1]:5.2f}")

# %% [markdown]
# As in the paper, the two descriptors react to noise almost identically: the cShape-DNA inherits the
# Shape-DNA's sensitivity, no more and no less.
#
# ## Fig. 8: how far each model's descriptor moves
#
# For three noise levels, the distance between each model's noisy and clean descriptor, scaled to $[0, 1]$
# over all models and levels.

# %%
show = [levels[0], levels[len(levels) // 2], levels[-1]]
fig = plots.new_figure((11, 3.5))
axs = fig.subplots(1, 2, sharey=True)
for ax, kind, title in ((axs[0], "shape-dna", "(a) normalised Shape-DNA"),
                        (axs[1], "cshape", "(b) cShape-DNA")):
    desc = Descriptor(kind, N=N, M=M)
    moved = {lev: np.linalg.norm(noisy[lev].descriptors(desc) - clean.descriptors(desc), axis=1)
             for lev in show}
    top = max(v.max() for v in moved.values())
    for lev in show:
        ax.plot(moved[lev] / top, "o-", ms=3, label=f"lambda = {lev}")
    ax.set(title=title, xlabel="model", xticks=range(len(clean)))
    ax.set_xticklabels(clean.names, rotation=90, fontsize="x-small")
    ax.legend(fontsize="small")
axs[0].set_ylabel("scaled difference")
fig

# %% [markdown]
# ## Fig. 9: mesh quality does not matter
#
# Marching cubes produces needles and nearly flat triangles ("CM"); isotropic remeshing makes them nearly
# equilateral ("CS"). The spectrum belongs to the surface, not to its triangles, so the two cShape-DNAs should
# agree closely: their distance is small next to the distance to another shape. (The remesh also smooths the
# surface a little, which accounts for most of what remains.)

# %%
if SMALL:
    CM = variants.articulated_figure("quadruped", 0, voxelsize=0.04, target_vertices=None)
    CS = variants.remesh(CM, target_vertices=1200)
else:
    import cshape.data

    CM, CS = cshape.data.load("paper-models", "CM"), cshape.data.load("paper-models", "CS")
for name, m in (("CM (marching cubes)", CM), ("CS (remeshed)", CS)):
    q = variants.mesh_quality(m)
    print(f"{name:20s} {q['n_vertices']:6d} vertices, smallest angle {q['min_angle']:5.2f} deg, "
          f"{q['pct_below_10']:5.1f}% of triangles below 10 deg, "
          f"worst aspect {q['aspect_max']:.3g}")


# %%
def close_up(mesh, frac=0.15):
    """The triangles near the mesh's highest point (the head), to see their shapes."""
    V, F = mesh.vertices, mesh.faces
    c = V[np.argmax(V[:, 2])]
    keep = np.linalg.norm(V[F].mean(axis=1) - c, axis=1) < frac * np.ptp(V, axis=0).max()
    used, F_new = np.unique(F[keep], return_inverse=True)
    return cshape.Mesh(V[used], F_new.reshape(-1, 3))


fig = plots.new_figure((11, 3.6))
ax0 = fig.add_subplot(1, 3, 1, projection="3d")
ax1 = fig.add_subplot(1, 3, 2, projection="3d")
ax2 = fig.add_subplot(1, 3, 3)
for ax, (name, m) in ((ax0, ("CM", CM)), (ax1, ("CS", CS))):
    plots.plot_mesh(close_up(m), ax=ax, edges=True, title=f"{name}, close up", elev=50, azim=-40)
for name, m in (("CM", CM), ("CS", CS)):
    ax2.hist(variants.triangle_angles(m).min(axis=1), bins=40, range=(0, 60), alpha=0.6,
             label=name)
ax2.set(xlabel="smallest angle of a triangle (degrees)", ylabel="triangles",
        title="triangle quality")
ax2.legend()
fig

# %%
import warnings

with warnings.catch_warnings():
    warnings.simplefilter("ignore", cshape.CShapeWarning)  # CM has near-degenerate triangles
    S = {name: cshape.compact_shape_dna(m, N=N, M=M) for name, m in (("CM", CM), ("CS", CS))}
others = {"a sphere": shapes.icosphere(3), "a torus": shapes.torus(48, 24)}
print(f"distance CM - CS:        {np.linalg.norm(S['CM'] - S['CS']):10.1f}")
for name, m in others.items():  # for scale: the distance to another shape
    d = np.linalg.norm(S["CS"] - cshape.compact_shape_dna(m, N=N, M=M))
    print(f"distance CS - {name:9s} {d:10.1f}")
plots.plot_cshape_dna(S, title="Fig. 9: cShape-DNA of CM and CS")

# %% [markdown] nbgrader={"grade": false, "grade_id": "noise_task", "locked": true, "schema_version": 3, "solution": false, "task": false}
# ## Exercise (graded): noise along the normals
#
# Section 3.3 moves every vertex $v_i$ along its outward unit normal $n_i$ by a random distance $d_i$, drawn
# uniformly from $[0, \lambda L]$ with $L$ the mean edge length: $v_i \mapsto v_i + d_i\, n_i$. Write
# `normal_noise_mine(mesh, amplitude, rng)` returning the noisy vertices, shape $(n, 3)$. Take the normals from
# `variants.vertex_normals(mesh)`, $L$ from `mesh.mean_edge_length`, and draw the $d_i$ with `rng.uniform`.

# %% nbgrader={"grade": false, "grade_id": "normal_noise_mine", "locked": false, "schema_version": 3, "solution": true, "task": false}
def normal_noise_mine(mesh, amplitude, rng):
    """Vertices of `mesh` moved along their outward normals by d_i ~ U[0, amplitude L], shape (n, 3)."""
    ### BEGIN SOLUTION
    d = rng.uniform(0.0, amplitude * mesh.mean_edge_length, size=mesh.n_vertices)
    return mesh.vertices + d[:, None] * variants.vertex_normals(mesh)
    ### END SOLUTION


# %% nbgrader={"grade": true, "grade_id": "test_normal_noise_mine", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
_ball = shapes.icosphere(size(2, 3))
_L, _n = _ball.mean_edge_length, variants.vertex_normals(_ball)
_V = normal_noise_mine(_ball, 1.0, np.random.default_rng(0))
assert np.shape(_V) == _ball.vertices.shape, f"return the vertices, shape {_ball.vertices.shape}"
_move = _V - _ball.vertices
assert np.any(_move != 0), "no vertex moved"
_across = np.linalg.norm(np.cross(_move, _n), axis=1).max()
if _across > 1e-9 * _L:
    print(f"hint: a vertex moved {_across:.3g} across its normal: move each vertex only along "
          "its own normal n_i, by one random distance d_i (a number, not a 3-vector)")
print(f"mean displacement {np.linalg.norm(_move, axis=1).mean() / _L:.3f} L (expected about 0.5 L)")
print("visible checks passed")

# %% nbgrader={"grade": true, "grade_id": "hidden_normal_noise_mine", "locked": true, "points": 2, "schema_version": 3, "solution": false, "task": false}
# hidden tests: the autograder runs more checks here
### BEGIN HIDDEN TESTS
for _a in (0.5, 2.0):
    _move = normal_noise_mine(_ball, _a, np.random.default_rng(3)) - _ball.vertices
    _d = np.einsum("ij,ij->i", _move, _n)
    assert np.allclose(_move, _d[:, None] * _n, atol=1e-12), "the noise is along the normals"
    assert np.all(_d >= -1e-12) and np.all(_d <= _a * _L * (1 + 1e-12)), "d_i in [0, amplitude L]"
    assert abs(_d.mean() / (_a * _L) - 0.5) < 0.1, "d_i ~ U[0, amplitude L]: mean amplitude L / 2"
    assert _d.std() > 0.2 * _a * _L, "d_i ~ U[0, amplitude L]: one random distance per vertex"
assert np.allclose(normal_noise_mine(_ball, 0.0, np.random.default_rng(0)), _ball.vertices)
### END HIDDEN TESTS

# %% [markdown]
# ## Exercises
#
# 1. Use `signed=True` in `variants.add_normal_noise` (noise in both directions). Does the area still grow?
#    How do the statistics of Fig. 7 change?
# 2. Noise adds area. Normalise with `normalization="weyl"` instead of the area and repeat Fig. 7. Which
#    normalisation is more robust to noise, and why?
# 3. Smooth a noisy mesh back (PyMeshLab's Laplacian smoothing, `pymeshlab.MeshSet.apply_coord_laplacian_smoothing`)
#    and measure how much of the clean descriptor comes back.
# 4. Fig. 9 with the Shape-DNA itself: plot the normalised Shape-DNAs of CM and CS. Where do they differ most,
#    at low or at high eigenvalues?
