# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 5 · Sensitivity to noise, to triangle quality and to resolution
#
# **Paper:** Gao, Yu and Pang, *A compact shape descriptor for triangular surface meshes*, Computer-Aided Design 53 (2014) 62-69; Section 3.3, Fig. 7 (difference matrices under noise), Fig. 8 (descriptor differences per model),
# Fig. 9 (cShape-DNA of a marching-cubes mesh and of its remesh).
#
# **Learning goals.** After this notebook you can
#
# 1. compute area-weighted outward vertex normals and add the paper's noise: move every vertex along its outward
#    normal by a random distance up to $\sigma \times L$ ($L$ the mean edge length, noise level
#    $\sigma \in \{0.5, 1, 2, 4, 10\}$; the paper calls it $\lambda$, a letter this course keeps for eigenvalues);
# 2. measure how noise changes the distance matrices of the Shape-DNA and of the cShape-DNA (Fig. 7) and each
#    model's descriptor (Fig. 8), and explain why the two react alike;
# 3. measure triangle quality (angles, aspect ratios) and tell its effect on the spectrum apart from the effect of
#    resolution (Fig. 9 and lesson 01).
#
# **Prerequisites:** lessons 01 (the FEM eigenvalues and their resolution drift), 02 and 03, 04 (scaled difference
# matrices).
#
# **Why noise matters.** Noise adds area (a rough surface is larger) and small-scale wiggles that the higher
# eigenfunctions feel: the normalised eigenvalues $\lambda_i$ shift, the more so the larger the noise level
# $\sigma$.
#
# **Vertex normals.** A triangle $t = (a, b, c)$ has the normal $n_t = (b - a)\times(c - a)$, whose length is twice
# its area $|t|$ and whose direction follows the right-hand rule of the vertex order. The area-weighted vertex
# normal sums the faces around vertex $i$ and normalises,
#
# $$n_i = \frac{\sum_{t \ni i} n_t}{\big\lVert \sum_{t \ni i} n_t \big\rVert}
#       = \frac{\sum_{t \ni i} 2|t|\,\hat n_t}{\lVert\cdot\rVert},$$
#
# so large triangles count more and a sliver with almost no area cannot tip the normal. It points outward on a
# closed mesh whose faces run counter-clockwise seen from outside, which the signed volume
# $\tfrac16 \sum_t a \cdot (b \times c)$ tells: positive for outward orientation, negative when every face is
# reversed (then flip all normals).

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
from cshape.data import bodies, quality, variants

collection = demo_collection()
if not SMALL:  # every model is solved once per noise level: leave out the largest meshes, and keep
    # three of the five poses of each articulated class
    collection = [c for c in collection
                  if c[0] not in ("S2", "S3", "D2") and not c[0].endswith(("-3", "-4"))]
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
                    title=f"{name}, sigma = {lev}", edges=False)
fig

# %% [markdown]
# The same model clean and at the middle noise level, side by side: drag each to rotate it, scroll to zoom in on the
# surface. Noise moves every vertex along its normal, so the outline hardly changes while the surface turns rough,
# and the high eigenvalues, which measure small-scale oscillation, go up.

# %%
lev = levels[len(levels) // 2]
plots.view_meshes({f"{name}, clean": mesh,
                   f"{name}, sigma = {lev}": variants.add_normal_noise(mesh, lev, random_state=0)},
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
# ones, for the normalised Shape-DNA (top) and the cShape-DNA (bottom), as in lesson 04: both matrices scaled to
# $[0, 255]$ by their own maximum, then the mean of the absolute difference.

# %% [markdown] nbgrader={"grade": false, "grade_id": "predict_noise_task", "locked": true, "schema_version": 3, "solution": false, "task": false}
# ### Predict (graded)
#
# The cShape-DNA keeps $2M+1$ low-frequency DFT coefficients; noise moves mostly the high eigenvalues. Before you
# run the next cells, predict the ratio
#
# $$\frac{\text{mean difference of the cShape-DNA}}{\text{mean difference of the Shape-DNA}}$$
#
# at the largest noise level. Is the compact descriptor more robust (ratio well below 1), as robust (about 1), or
# less (above 1)? Write one number.

# %% nbgrader={"grade": false, "grade_id": "predict_noise", "locked": false, "schema_version": 3, "solution": true, "task": false}
# write your prediction as `prediction = ...` (one number)
### BEGIN SOLUTION
prediction = 1.0
### END SOLUTION

# %%
from cshape import Descriptor, compare

diffs, titles, stats = {"shape-dna": [], "cshape": []}, {"shape-dna": [], "cshape": []}, []
for lev in levels:
    for kind in ("shape-dna", "cshape"):
        d = Descriptor(kind, N=N, M=M)
        D0, D1 = clean.distance_matrix(d), noisy[lev].distance_matrix(d)
        diff = np.abs(compare.scale_255(D0) - compare.scale_255(D1))
        mean, std = diff.mean(), diff.std()
        diffs[kind].append(diff)
        titles[kind].append(f"sigma={lev}: {mean:.1f} / {std:.1f}")
        stats.append((lev, kind, mean, std))
vmax = max(d.max() for v in diffs.values() for d in v)
print("mean / std of each difference image")
plots.plot_matrices(diffs["shape-dna"], [f"Shape-DNA {t}" for t in titles["shape-dna"]], vmax=vmax)

# %%
plots.plot_matrices(diffs["cshape"], [f"cShape-DNA {t}" for t in titles["cshape"]], vmax=vmax)

# %%
print(f"{'sigma':>7s} {'Shape-DNA mean/std':>20s} {'cShape-DNA mean/std':>20s}")
for lev in levels:
    s = {k: (m, sd) for lv, k, m, sd in stats if lv == lev}
    print(f"{lev:7.1f} {s['shape-dna'][0]:12.2f} / {s['shape-dna'][1]:5.2f} "
          f"{s['cshape'][0]:12.2f} / {s['cshape'][1]:5.2f}")

# %%
top = {kind: mean for lv, kind, mean, _ in stats if lv == levels[-1]}
ratio = top["cshape"] / top["shape-dna"]
print(f"sigma = {levels[-1]}: mean difference cShape-DNA / Shape-DNA = {ratio:.3f}")

# %% nbgrader={"grade": true, "grade_id": "test_predict_noise", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
assert np.ndim(prediction) == 0 and np.isfinite(float(prediction)), "prediction is one number"
print(f"you predicted {float(prediction):.3f}; the printed ratio is {ratio:.3f}")
# hidden test: the prediction is within 25 % of the ratio
### BEGIN HIDDEN TESTS
_p = float(prediction)
if abs(_p / ratio - 1) >= 0.25:
    if _p < ratio:
        _why = ("hint: the crop does not protect against noise here: the DFT is linear and nearly "
                "an isometry up to sqrt(N) on the differences of spectra (lesson 04), and each matrix "
                "is scaled by its own maximum, so the sqrt(N) cancels")
    else:
        _why = ("hint: the cShape-DNA sees less of the spectrum, not more: it cannot amplify the "
                "noise beyond the Shape-DNA's, once both are scaled to [0, 255]")
    raise AssertionError(f"{_why} (the ratio is {ratio:.3f}; a prediction within 25 % counts)")
### END HIDDEN TESTS

# %% [markdown]
# As in the paper, the two descriptors react to noise almost alike (the printed ratio): the cShape-DNA inherits
# the Shape-DNA's sensitivity. Lesson 04 showed why: the difference of two cShape-DNAs is the cropped DFT of the
# difference of the two spectra, about $\sqrt N$ times its length, whatever moved the spectrum. Scaling each
# matrix to $[0, 255]$ removes the $\sqrt N$, and what is left is the same picture. The noise does move the high
# eigenvalues most, but it moves them *together*, as a slow trend that a low-frequency crop keeps.
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
        ax.plot(moved[lev] / top, "o-", ms=3, label=f"sigma = {lev}")
    ax.set(title=title, xlabel="model", xticks=range(len(clean)))
    ax.set_xticklabels(clean.names, rotation=90, fontsize="x-small")
    ax.legend(fontsize="small")
axs[0].set_ylabel("scaled difference")
fig

# %% [markdown]
# ## Fig. 9: triangle quality at one resolution
#
# Marching cubes produces needles and nearly flat triangles ("CM"); isotropic remeshing makes them nearly
# equilateral ("CS"), at a similar number of vertices (printed below). The spectrum belongs to the surface, so at
# a similar resolution the two cShape-DNAs should agree closely: their distance is small next to the distance to
# another shape. (The remesh also smooths the surface a little.) This is a statement about the *shape* of the
# triangles, not their *size*: lesson 01 showed that the FEM error grows like $h^2\lambda_i^2$ with the mesh size
# $h$, so the same surface at a much coarser resolution drifts in its upper eigenvalues.

# %%
if SMALL:
    CM = bodies.articulated_figure("quadruped", 0, voxelsize=0.04, target_vertices=None)
    CS = variants.remesh(CM, target_vertices=1200)
else:
    import cshape.data

    CM, CS = cshape.data.load("paper-models", "CM"), cshape.data.load("paper-models", "CS")
for name, m in (("CM (marching cubes)", CM), ("CS (remeshed)", CS)):
    q = quality.mesh_quality(m)
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
    ax2.hist(quality.triangle_angles(m).min(axis=1), bins=40, range=(0, 60), alpha=0.6,
             label=name)
ax2.set(xlabel="smallest angle of a triangle (degrees)", ylabel="triangles",
        title="triangle quality")
ax2.legend()
fig

# %%
import warnings


def cshape_dna(m):
    """The paper's pipeline: Shape-DNA (the eigensolve), then Eq. (8)-(10) with the area."""
    return cshape.compact_shape_dna(cshape.shape_dna(m, N), N=N, M=M, area=m.area)


with warnings.catch_warnings():
    warnings.simplefilter("ignore", cshape.CShapeWarning)  # CM has near-degenerate triangles
    S = {name: cshape_dna(m) for name, m in (("CM", CM), ("CS", CS))}
others = {"a sphere": shapes.icosphere(3), "a torus": shapes.torus(48, 24)}
print(f"distance CM - CS:        {np.linalg.norm(S['CM'] - S['CS']):10.1f}")
coarse = variants.remesh(CS, target_vertices=CS.n_vertices // 8)  # the same surface, 1/8 of the vertices
# (remeshing this coarse also flattens thin parts a little: not only h changes)
S["CS coarse"] = cshape_dna(coarse)
print(f"distance CS - CS coarse: {np.linalg.norm(S['CS'] - S['CS coarse']):10.1f}"
      f"   ({CS.n_vertices} vs {coarse.n_vertices} vertices)")
for name, m in others.items():  # for scale: the distance to another shape
    d = np.linalg.norm(S["CS"] - cshape_dna(m))
    print(f"distance CS - {name:9s} {d:10.1f}")
plots.plot_cshape_dna(S, title="Fig. 9: cShape-DNA of CM and CS")

# %% [markdown] nbgrader={"grade": false, "grade_id": "normals_task", "locked": true, "schema_version": 3, "solution": false, "task": false}
# ## Exercise (graded): area-weighted outward vertex normals
#
# Write `vertex_normals_mine(V, F)` returning the outward unit vertex normals of a closed mesh, shape $(n, 3)$, as
# derived at the top: sum the face vectors $(b - a)\times(c - a)$ (not normalised: their length is twice the
# area, the weight) into each of the face's three vertices, flip every normal when the signed volume is negative,
# and normalise each row. `V` has shape $(n, 3)$, `F` shape $(m, 3)$ (vertex indices).

# %% nbgrader={"grade": false, "grade_id": "vertex_normals_mine", "locked": false, "schema_version": 3, "solution": true, "task": false}
def vertex_normals_mine(V, F):
    """Outward area-weighted unit vertex normals of the closed mesh (V, F), shape (n, 3)."""
    ### BEGIN SOLUTION
    V, F = np.asarray(V, dtype=float), np.asarray(F)
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    fn = np.cross(b - a, c - a)  # 2 |t| times the unit normal
    n = np.zeros_like(V)
    for k in range(3):
        np.add.at(n, F[:, k], fn)  # n[F[:, k]] += fn would add a repeated index only once
    if np.einsum("ij,ij->i", a, np.cross(b, c)).sum() < 0:  # six times the signed volume
        n = -n
    return n / np.linalg.norm(n, axis=1, keepdims=True)
    ### END SOLUTION


# %% nbgrader={"grade": false, "grade_id": "check_normals", "locked": true, "schema_version": 3, "solution": false, "task": false}
def _normals_variant(V, F, weight="area", flip=True, add_at=True, unit=True):
    """Vertex normals with one step changed: the usual mistakes, to recognise them."""
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    fn = np.cross(b - a, c - a)
    if weight == "uniform":
        fn = fn / np.linalg.norm(fn, axis=1, keepdims=True)
    n = np.zeros_like(V)
    for k in range(3):
        if add_at:
            np.add.at(n, F[:, k], fn)
        else:
            n[F[:, k]] += fn
    if flip and np.einsum("ij,ij->i", a, np.cross(b, c)).sum() < 0:
        n = -n
    norm = np.linalg.norm(n, axis=1, keepdims=True)
    return n / np.where(norm > 0, norm, 1) if unit else n


def check_normals(fn, V, F):
    """Compare fn(V, F) with the area-weighted outward normals; name the usual mistake."""
    V, F = np.asarray(V, dtype=float), np.asarray(F)
    got = np.asarray(fn(V, F), dtype=float)
    if got.shape != V.shape:
        raise AssertionError(f"got shape {got.shape}, expected {V.shape}: one unit normal per vertex")
    want = _normals_variant(V, F)
    if np.allclose(got, want, atol=1e-9):
        print("vertex_normals_mine: correct")
        return
    mistakes = [
        (dict(unit=False), "normalise each vertex normal to length 1 at the end"),
        (dict(weight="uniform"), "weight each face by its area: sum the cross products as they are, "
                                 "do not normalise the face normals first"),
        (dict(add_at=False), "n[F[:, k]] += fn adds a vertex that appears twice in F[:, k] only once "
                             "(numpy buffers it): use np.add.at(n, F[:, k], fn)"),
        (dict(flip=False), "the normals point inward: these faces run clockwise seen from outside, "
                           "so the signed volume is negative; flip every normal then"),
    ]
    for kw, hint in mistakes:
        if np.allclose(got, _normals_variant(V, F, **kw), atol=1e-9):
            raise AssertionError(f"hint: {hint}")
    if np.allclose(got, -want, atol=1e-9):
        raise AssertionError("hint: the normals point inward; flip them for a positive signed volume")
    raise AssertionError("your normals differ from the area-weighted outward normals")


# %% nbgrader={"grade": true, "grade_id": "test_vertex_normals_mine", "locked": true, "points": 1, "schema_version": 3, "solution": false, "task": false}
_rng = np.random.default_rng(7)
_ico = shapes.icosphere(2)
_bumpy = _ico.vertices * _rng.uniform(0.7, 1.3, size=(_ico.n_vertices, 1))  # uneven triangles
check_normals(vertex_normals_mine, _bumpy, _ico.faces)
print("visible checks passed")

# %% nbgrader={"grade": true, "grade_id": "hidden_vertex_normals_mine", "locked": true, "points": 2, "schema_version": 3, "solution": false, "task": false}
# hidden tests: the autograder runs more checks here
### BEGIN HIDDEN TESTS
check_normals(vertex_normals_mine, _bumpy, _ico.faces[:, ::-1])  # faces reversed: flip
_cube = shapes.cube(3)
check_normals(vertex_normals_mine, _cube.vertices, _cube.faces)
assert np.allclose(vertex_normals_mine(_ico.vertices, _ico.faces), _ico.vertices / np.linalg.norm(
    _ico.vertices, axis=1, keepdims=True), atol=5e-2), "on a sphere the normal is about x / |x|"
_tor = shapes.torus(24, 12)
check_normals(vertex_normals_mine, _tor.vertices.tolist(), _tor.faces.tolist())
### END HIDDEN TESTS

# %% [markdown] nbgrader={"grade": false, "grade_id": "noise_task", "locked": true, "schema_version": 3, "solution": false, "task": false}
# ## Exercise (graded): noise along the normals
#
# Section 3.3 moves every vertex $v_i$ along its outward unit normal $n_i$ by a random distance $d_i$, drawn
# uniformly from $[0, \sigma L]$ with $L$ the mean edge length: $v_i \mapsto v_i + d_i\, n_i$. Write
# `normal_noise_mine(mesh, sigma, rng)` returning the noisy vertices, shape $(n, 3)$. Take the normals from
# `variants.vertex_normals(mesh)` (the same as yours), $L$ from `mesh.mean_edge_length`, and draw the $d_i$ with
# `rng.uniform`.

# %% nbgrader={"grade": false, "grade_id": "normal_noise_mine", "locked": false, "schema_version": 3, "solution": true, "task": false}
def normal_noise_mine(mesh, sigma, rng):
    """Vertices of `mesh` moved along their outward normals by d_i ~ U[0, sigma L], shape (n, 3)."""
    ### BEGIN SOLUTION
    d = rng.uniform(0.0, sigma * mesh.mean_edge_length, size=mesh.n_vertices)
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
    assert np.all(_d >= -1e-12), "hint: d_i >= 0: the paper's noise moves vertices outward only"
    assert np.all(_d <= _a * _L * (1 + 1e-12)), "hint: d_i <= sigma L: scale by the mean edge length"
    assert abs(_d.mean() / (_a * _L) - 0.5) < 0.1, "d_i ~ U[0, sigma L]: mean sigma L / 2"
    assert _d.std() > 0.2 * _a * _L, ("hint: d_i ~ U[0, sigma L] is one random distance PER VERTEX, "
                                      "not one for the whole mesh")
assert np.allclose(normal_noise_mine(_ball, 0.0, np.random.default_rng(0)), _ball.vertices)
### END HIDDEN TESTS

# %% [markdown] nbgrader={"grade": false, "grade_id": "quality_task", "locked": true, "schema_version": 3, "solution": false, "task": false}
# ## Written answer (graded by hand)
#
# Lesson 01 showed the upper eigenvalues drifting with the resolution; Fig. 9 shows CM and CS, one with needle
# triangles and one with near-equilateral ones, close together. Using the printed vertex counts and the three
# printed distances (CM - CS, CS - CS coarse, CS - another shape), explain why the two observations do not
# contradict each other, and say which property of a mesh a descriptor comparison must control. (4-6 sentences.)

# %% [markdown] nbgrader={"grade": true, "grade_id": "quality_answer", "locked": false, "points": 2, "schema_version": 3, "solution": true, "task": false}
# ### BEGIN SOLUTION
# The FEM error of the eigenvalues is governed by the mesh size: it grows like $h^2\lambda_i^2$ (lesson 01), with
# constants that depend on the angles only mildly (as long as no angle approaches 180 degrees badly). CM and CS have
# a similar number of vertices, so a similar $h$: they differ mainly in the *shape* of their triangles, and the
# printed CM - CS distance is small next to the distance to another shape. The coarse remesh of CS keeps the
# triangles well shaped but has an eighth of the vertices, a larger $h$ (and, that coarse, it also flattens thin
# parts a little); its printed distance from CS is many times CM - CS, the drift of lesson 01 on top of the lost
# detail. So triangle quality matters little and resolution matters: a
# comparison of descriptors must use meshes of similar resolution relative to the wavelength of the
# $N$-th eigenfunction (or refine them, or use fewer eigenvalues).
# ### END SOLUTION

# %% [markdown]
# ## Exercises
#
# 1. Use `signed=True` in `variants.add_normal_noise` (noise in both directions). Does the area still grow?
#    How do the statistics of Fig. 7 change?
# 2. Noise adds area. Normalise with `normalization="weyl"` instead of the area (pass it to
#    `clean.distance_matrix` and `noisy[sigma].distance_matrix`) and repeat Fig. 7. Which normalisation is more
#    robust to noise, and why?
# 3. Smooth a noisy mesh back (PyMeshLab's
#    `pymeshlab.MeshSet.apply_coord_laplacian_smoothing`) and measure how much of the clean descriptor comes
#    back.
# 4. Fig. 9 with the Shape-DNA itself: plot the normalised Shape-DNAs of CM, CS and CS coarse
#    (`cshape.shape_dna` then `cshape.normalize`). Where do they differ most, at low or at high eigenvalues?
# 5. Stability: for one model, plot the distance between its noisy and clean cShape-DNA against $\sigma$ for
#    $\sigma$ from 0.1 to 2. Is the growth about linear (a Lipschitz-like bound) for small $\sigma$?
#
# ## References
#
# - Z. Gao, Z. Yu, X. Pang, *A compact shape descriptor for triangular surface meshes*, Computer-Aided Design 53
#   (2014) 62-69, Section 3.3.
# - M. Reuter, F.-E. Wolter, N. Peinecke, *Laplace-Beltrami spectra as "Shape-DNA" of surfaces and solids*,
#   Computer-Aided Design 38 (2006) 342-366: the spectrum's stability under noise and remeshing.
# - M. Reuter, S. Biasotti, D. Giorgi, G. Patanè, M. Spagnuolo, *Discrete Laplace-Beltrami operators for shape
#   analysis and segmentation*, Computers & Graphics 33 (2009) 381-390: accuracy of the FEM operator.
# - H. Weyl, *Das asymptotische Verteilungsgesetz der Eigenwerte linearer partieller Differentialgleichungen*,
#   Mathematische Annalen 71 (1911) 441-479.
