"""cshape: Shape-DNA and compact Shape-DNA (cShape-DNA) of triangle meshes.

The top level holds the entry points a user needs; every other public name lives in its
stage's module.  The core is the method, one module per stage, in pipeline order (data flows
one way):

1. :mod:`cshape.mesh`        - :class:`Mesh`, :func:`repair_mesh`, :func:`largest_component`;
   :mod:`cshape.readers`     - :func:`load_mesh` (OBJ, OFF, PLY, STL, ...)
2. :mod:`cshape.fem`         - :func:`fem_matrices`: ``A`` (Eq. 4/6) and ``B`` (Eq. 5/7)
3. :mod:`cshape.spectrum`    - :func:`shape_dna`: ``A f = -lam B f`` (Eq. 3);
   :func:`eigenbasis` - the eigenpairs with ``B``, the area and the mesh as one
   :class:`Eigenbasis`, what signatures and maps take
4. :mod:`cshape.descriptors` - the formulas: :func:`normalize`, :func:`weyl_subtract`
   (Eq. 8), :func:`compact_shape_dna` (Eq. 9-10), and in the module ``log_weyl_ratio``,
   ``real_form``, ``inverse_compact_shape_dna``, ``detrend``, ``count_zero_modes``; the
   recipe :class:`Descriptor`, which descriptor, as one frozen value that builds the rows:
   :data:`PAPER` (the paper's cShape-DNA) and :data:`DEFAULT` (the exploration default)
5. :mod:`cshape.compare`     - :func:`distance_matrix`, :func:`retrieval_scores`,
   :func:`mds_embedding`, and in the module ``scale_255``, ``nearest_neighbours``;
   :mod:`cshape.index`       - :class:`DescriptorIndex` (nearest neighbours in a database)
6. :mod:`cshape.signatures`  - per-point signatures of an :class:`Eigenbasis`: :func:`hks`,
   :func:`wks`, and in the module ``si_hks``, ``heat_kernel``, ``heat_trace``,
   ``match_points`` (correspondence)
7. :mod:`cshape.maps`        - maps between shapes: :func:`point_map` (the one call), and in
   the module ``functional_map``, ``zoomout``, ``map_to_pointwise``, ``pointwise_to_map``,
   ``transfer_function``; :mod:`cshape.geodesics` - geodesics by the heat method:
   :func:`geodesic_distance`, and in the module ``HeatGeodesics``, ``geodesic_errors``
   (the error of a map)

:mod:`cshape.shapes` builds analytic test shapes (sphere, square, disk, torus, ...).

The applications and the layers on top are subpackages, imported on first use:

* :mod:`cshape.batch`     - :func:`describe` a whole collection into a :class:`DescriptorTable`
  (cached, parallel, Dask);
* :mod:`cshape.reproduce` - the paper's Section 3 and the retrieval tables, as a report;
* :mod:`cshape.plots`     - figures, the 3-D viewer, widgets (extra ``plots``);
* :mod:`cshape.data`      - the data manifest, collections, generated shapes, PyMeshLab
  variants, downloads (extra ``download`` for downloads);
* :mod:`cshape.course`    - lessons runner, nbgrader assignments (extras ``notebooks``,
  ``course``);
* :mod:`cshape.cli`       - the ``cshape`` command.

The core imports none of them.
"""

from __future__ import annotations

import importlib
from typing import Any

from . import shapes
from .compare import distance_matrix, mds_embedding, retrieval_scores
from .descriptors import DEFAULT, PAPER, Descriptor, compact_shape_dna, normalize, weyl_subtract
from .fem import fem_matrices
from .geodesics import geodesic_distance
from .index import DescriptorIndex
from .maps import point_map
from .mesh import CShapeWarning, Mesh, largest_component, repair_mesh
from .readers import load_mesh
from .signatures import hks, wks
from .spectrum import Eigenbasis, eigenbasis, shape_dna

__version__ = "0.1.0"

#: Names served on first use (``cshape.describe``, ``cshape.data``, ...): the applications
#: and layers are imported only when asked for, so ``import cshape`` stays light.
_LAZY = {
    "describe": ("cshape.batch", "describe"),
    "DescriptorTable": ("cshape.batch", "DescriptorTable"),
    "batch": ("cshape.batch", None),
    "data": ("cshape.data", None),
    "plots": ("cshape.plots", None),
    "course": ("cshape.course", None),
    "reproduce": ("cshape.reproduce", None),
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        module, attr = _LAZY[name]
        mod = importlib.import_module(module)
        value = mod if attr is None else getattr(mod, attr)
        if name != "reproduce":  # cshape.reproduce is the subpackage once imported
            globals()[name] = value
        return value
    raise AttributeError(f"module 'cshape' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))


__all__ = [
    "CShapeWarning",
    "DEFAULT",
    "Descriptor",
    "DescriptorIndex",
    "DescriptorTable",
    "Eigenbasis",
    "Mesh",
    "PAPER",
    "compact_shape_dna",
    "describe",
    "distance_matrix",
    "eigenbasis",
    "fem_matrices",
    "geodesic_distance",
    "hks",
    "largest_component",
    "load_mesh",
    "mds_embedding",
    "normalize",
    "point_map",
    "repair_mesh",
    "retrieval_scores",
    "shape_dna",
    "shapes",
    "weyl_subtract",
    "wks",
]
