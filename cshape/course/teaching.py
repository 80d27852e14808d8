"""Shared helpers of the lessons: the meshes several notebooks start from.

* :func:`real_mesh`       - the real mesh of lessons 02 and 03 (Spot the cow, else a fallback);
* :func:`demo_collection` - the labelled collection of lessons 04, 05 and 07.

Kept here, once, so that each lesson imports the same meshes instead of carrying its own copy.
"""

from __future__ import annotations

import warnings

from .. import data, shapes
from ..data import variants
from ..mesh import CShapeWarning

__all__ = ["real_mesh", "demo_collection"]


def real_mesh(small=False):
    """``(mesh, credit)``: a real scanned-style mesh.

    Spot the cow (Keenan Crane, public domain) from the project's shared meshes when that
    folder is there (``spot_low_resolution`` when ``small``), else PyMeshLab's sample cow,
    else a built-in torus.
    """
    try:
        name = "spot_low_resolution" if small else "spot"
        credit = f"{name} (Spot by Keenan Crane, public domain)"
        return data.load("shared-meshes", name), credit
    except (FileNotFoundError, KeyError, ValueError) as exc:
        print(f"shared meshes not available ({exc}); using PyMeshLab's sample cow instead")
    try:
        # PyMeshLab's cow stores one vertex twice; loading welds the copies into one (the FEM
        # would otherwise see a crack there). Say so here, once, instead of a warning box.
        with warnings.catch_warnings(record=True) as repairs:
            warnings.simplefilter("always", CShapeWarning)
            cow = data.load("pymeshlab-samples", "cow")
        for w in repairs:
            print(f"note: {str(w.message).replace('repaired mesh', 'repaired on loading')}")
        return cow, "cow (PyMeshLab sample)"
    except (FileNotFoundError, KeyError, ValueError) as exc:
        print(f"PyMeshLab samples not available ({exc}); using a built-in torus")
        return shapes.torus(64, 32), "torus (built-in)"


def demo_collection(small=False):
    """``(name, label, mesh)`` triples: a few classes of shapes, all made in code.

    Small: spheres, cubes and tori at two resolutions, and two poses each of a human and a snake
    figure.  Full: cshape's "paper-models" (spheres S1-S3, cube, torus, eight, the
    marching-cubes quadruped CM and its remesh CS, the human D1 and its refinement D2) and
    "articulated" (four classes x five poses), built with PyMeshLab once and then cached.
    """
    if not small:
        return [(it.name, it.label, it.mesh)
                for coll in ("paper-models", "articulated")
                for it in data.load_collection(coll)]
    items = [(f"sphere-{s}", "sphere", shapes.icosphere(s)) for s in (2, 3)]
    items += [(f"cube-{n}", "cube", shapes.cube(n)) for n in (5, 7)]
    items += [(f"torus-{k}", "torus", shapes.torus(8 * k + 24, 4 * k + 12)) for k in (0, 1)]
    for kind in ("human", "snake"):
        for seed in (0, 1):
            fig = variants.articulated_figure(kind, seed, voxelsize=0.05, target_vertices=500)
            items.append((f"{kind}-{seed}", kind, fig))
    return items
