"""What the lessons import: their size switch, the paper's reference and their meshes.

* :data:`SMALL` and :func:`size` - the one size switch of every lesson (``CSHAPE_SMALL=1``,
  which ``cshape notebooks --small`` and the test suite set, makes meshes and ``N`` small);
* :data:`CITATION`               - the reference of the paper the lessons follow;
* :func:`spot`, :func:`real_mesh` - the real mesh of lessons 02 and 03, shipped in the package;
* :func:`demo_collection`        - the labelled collection of lessons 04, 05 and 07;
* :func:`retrieval_collection`   - a collection whose descriptors differ (lessons 04 and 08);
* :func:`retrieval_table`        - its eigenvalues (at full size, prepared with the package).

A lesson starts with one line, ``from cshape.course.teaching import SMALL, size``, and writes
its sizes as ``N = size(50, 100)`` (small, full).
"""

from __future__ import annotations

import os
from importlib import resources
from typing import TYPE_CHECKING, TypeVar

from .. import data, shapes
from .._checks import check_int
from ..data import variants
from ..data.bodies import articulated_figure
from ..mesh import Mesh
from ..readers import load_mesh

if TYPE_CHECKING:
    from ..batch import DescriptorTable

_T = TypeVar("_T")

__all__ = [
    "CITATION",
    "SMALL",
    "demo_collection",
    "real_mesh",
    "retrieval_collection",
    "retrieval_table",
    "size",
]

#: True when the environment has ``CSHAPE_SMALL=1``: the lessons then use small meshes and
#: few eigenvalues (the test suite, ``cshape notebooks --small``, the documentation site).
SMALL = os.environ.get("CSHAPE_SMALL") == "1"

#: The paper the lessons follow.
CITATION = ("Z. Gao, Z. Yu and X. Pang, A compact shape descriptor for triangular surface "
         "meshes, Computer-Aided Design 53 (2014) 62-69")


def size(small: _T, full: _T) -> _T:
    """Choose ``small`` when the lessons run at small size (:data:`SMALL`), else ``full``.

    Parameters
    ----------
    small : object
        The value at small size (``CSHAPE_SMALL=1``, the test suite).
    full : object
        The value at full size.

    Returns
    -------
    object
        ``small`` if :data:`SMALL`, else ``full``.

    Examples
    --------
    >>> N = size(50, 100)  # 50 eigenvalues in the test suite, 100 otherwise
    """
    return small if SMALL else full


#: Credit line of :func:`spot`, for figure titles.
SPOT_CREDIT = "spot (Spot the cow by Keenan Crane, public domain)"


def _spot() -> Mesh:
    """Spot the cow, low resolution: 829 vertices, 1,654 triangles, closed, genus 0.

    Shipped in the package (``cshape/data/meshes/spot_low_resolution.obj.gz``, public domain:
    Keenan Crane's Spot, remeshed by the odedstein/meshes collection; see the README there).

    Returns
    -------
    Mesh
    """
    ref = resources.files("cshape.data") / "meshes" / "spot_low_resolution.obj.gz"
    with resources.as_file(ref) as path:
        return load_mesh(path)


def real_mesh(small: bool | None = None) -> tuple[Mesh, str]:
    """Load the lessons' real mesh, Spot the cow, with its credit line.

    Parameters
    ----------
    small : bool, optional
        The shipped mesh as it is (829 vertices); else refined once by Loop subdivision
        (3,312 vertices, the same shape, smoother).  Default :data:`SMALL`.

    Returns
    -------
    mesh : Mesh
        Spot the cow, at the size chosen.
    credit : str
        Its credit line, for figure titles:
        ``"spot (Spot the cow by Keenan Crane, public domain)"``.
    """
    small = SMALL if small is None else bool(small)
    mesh = _spot()
    return (mesh if small else variants.subdivide(mesh, 1)), SPOT_CREDIT


def _build_jobs() -> int:
    """Processes that build a full-size collection the first time: every core."""
    return max(1, os.cpu_count() or 1)


def demo_collection(small: bool | None = None) -> list[tuple[str, str, Mesh]]:
    """Make a few classes of shapes, all in code, as ``(name, label, mesh)`` triples.

    Small: spheres, cubes and tori at two resolutions, and two poses each of a human and a
    snake figure.  Full: cshape's "paper-models" (spheres S1-S3, cube, torus, eight, the
    marching-cubes quadruped CM and its remesh CS, the human D1 and its refinement D2) and
    "articulated" (four classes x five poses), built with PyMeshLab once, on every core and
    with a progress bar, and then cached.
    Every class is a shape and its remeshings or poses, so Shape-DNA tells them apart
    perfectly: the collection of the paper's Section 3.1.

    Parameters
    ----------
    small : bool, optional
        Make the small collection, else the full one.  Default :data:`SMALL`.

    Returns
    -------
    list of (str, str, Mesh)
        ``(name, label, mesh)`` of every shape, the label naming its class.
    """
    small = SMALL if small is None else bool(small)
    if not small:
        return [(it.name, it.label, it.mesh)
                for coll in ("paper-models", "articulated")
                for it in data.load_collection(coll, progress=True, n_jobs=_build_jobs())]
    items = [(f"sphere-{s}", "sphere", shapes.icosphere(s)) for s in (2, 3)]
    items += [(f"cube-{n}", "cube", shapes.cube(n)) for n in (5, 7)]
    items += [(f"torus-{k}", "torus", shapes.torus(8 * k + 24, 4 * k + 12)) for k in (0, 1)]
    for kind in ("human", "snake"):
        for seed in (0, 1):
            fig = articulated_figure(kind, seed, voxelsize=0.05, target_vertices=500)
            items.append((f"{kind}-{seed}", kind, fig))
    return items


#: The classes of the small :func:`retrieval_collection`, chosen for their build time.
SMALL_CREATURES = ("human", "quadruped", "bird", "spider", "hand", "snake")


def retrieval_collection(small: bool | None = None) -> data.Collection:
    """A collection where retrieval is not trivial: cshape's creature benchmark.

    Its classes (human, centaur, teddy, quadruped, bird, spider, ...) have members that
    differ in proportions, pose, resolution and noise, so descriptors score differently
    (on :func:`demo_collection` every descriptor retrieves perfectly).  Its eigenvalues are
    :func:`retrieval_table`.

    Parameters
    ----------
    small : bool, optional
        Six classes of three coarse members (500-1000 vertices), built now; else the
        development instance ``creatures-dev`` (12 classes x 10 members), whose meshes are
        built one by one when first used (about a second each), then cached.  Default
        :data:`SMALL`.

    Returns
    -------
    cshape.data.Collection
        Iterate for :class:`cshape.data.manifest.Item` (``name``, ``label``, ``mesh``).
    """
    small = SMALL if small is None else bool(small)
    if not small:
        return data.load_collection("creatures-dev", lazy=True)
    return data.store.load_creatures(0, members=3, kinds=list(SMALL_CREATURES),
                                     vertices=[500, 1000],
                               voxelsize=0.04, progress=False)


#: The eigenvalues of ``creatures-dev`` shipped with the package (``N = 100``, linear FEM,
#: Neumann, consistent mass), written by ``tools/prepare_lesson_data.py``.
PREPARED_RETRIEVAL = "creatures-dev-spectra.npz"


def retrieval_table(N: int = 100, small: bool | None = None) -> DescriptorTable:
    """The eigenvalues of :func:`retrieval_collection`, the first ``N`` of each shape.

    At full size they come prepared with the package: computed by
    ``batch.describe(cshape.data.load_collection("creatures-dev"), N=100)``, which builds
    120 meshes with PyMeshLab and solves 120 eigenproblems, minutes on a laptop.  The test
    suite rebuilds members of every class and checks their eigenvalues against these.  At
    small size the six small classes are described now.

    Parameters
    ----------
    N : int, default=100
        Eigenvalues per shape, 1 to 100 at full size.
    small : bool, optional
        Default :data:`SMALL`.

    Returns
    -------
    cshape.batch.DescriptorTable
        Rows in the order of :func:`retrieval_collection`, named and labelled as its items.
    """
    from ..batch import DescriptorTable, describe

    small = SMALL if small is None else bool(small)
    if small:
        N = check_int("N", N, min=1)
        return describe(retrieval_collection(True), N=N, progress=False)
    N = check_int("N", N, min=1, max=100)
    ref = resources.files("cshape.course") / PREPARED_RETRIEVAL
    with resources.as_file(ref) as path:
        table = DescriptorTable.load(path)
    return DescriptorTable(table.names, table.lam[:, :N], table.areas, table.labels,
                           bc=table.bc, mass=table.mass, refine=table.refine,
                           components=table.components)
