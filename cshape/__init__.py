"""cshape: Shape-DNA and compact Shape-DNA (cShape-DNA) of triangle meshes.

The core is the method, one module per stage, in pipeline order (data flows one way):

1. :mod:`cshape.mesh`        - :class:`Mesh`, :func:`repair_mesh`, :func:`largest_component`;
   :mod:`cshape.readers`     - :func:`load_mesh` (OBJ, OFF, PLY, STL, ...)
2. :mod:`cshape.fem`         - :func:`fem_matrices`: ``A`` (Eq. 4/6) and ``B`` (Eq. 5/7)
3. :mod:`cshape.spectrum`    - :func:`shape_dna`, :func:`eigenpairs`: ``A f = -lam B f`` (Eq. 3);
   :func:`eigenbasis` - the pairs with ``B``, the area and the mesh as one
   :class:`Eigenbasis`, what signatures and maps take
4. :mod:`cshape.descriptors` - the formulas (:mod:`~cshape.descriptors.formulas`):
   :func:`normalize`, :func:`weyl_subtract` (Eq. 8), :func:`compact_shape_dna` (Eq. 9-10),
   :func:`log_weyl_ratio`, :func:`real_form`, :func:`inverse_compact_shape_dna`,
   :func:`f1_feature`; :func:`count_zero_modes` and :func:`nonzero_eigenvalues` (the rule for
   meshes of several pieces); and the recipe (:mod:`~cshape.descriptors.recipe`):
   :class:`Descriptor`, which descriptor, as one frozen value that builds the rows:
   :data:`PAPER` (the paper's cShape-DNA) and :data:`DEFAULT` (the exploration default)
5. :mod:`cshape.compare`     - :func:`distance_matrix`, :func:`scale_255`,
   :func:`retrieval_scores`, :func:`nearest_neighbours`, :func:`mds_embedding`;
   :mod:`cshape.index`       - :class:`DescriptorIndex` (nearest neighbours in a database)
6. :mod:`cshape.signatures`  - per-point signatures of an :class:`Eigenbasis`: :func:`hks`,
   :func:`wks`, :func:`si_hks`, :func:`heat_kernel`, :func:`heat_trace`, and
   :func:`match_points` (correspondence)
7. :mod:`cshape.maps`        - maps between shapes: :func:`point_map` (the one call),
   :func:`functional_map`, :func:`zoomout`, :func:`map_to_pointwise`,
   :func:`pointwise_to_map`, :func:`transfer_function`;
   :mod:`cshape.geodesics`   - geodesics by the heat method: :func:`geodesic_distance`,
   :class:`HeatGeodesics`, :func:`geodesic_errors` (the error of a map), :func:`face_gradients`

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
from .compare import (
    difference_matrix,
    distance_matrix,
    mds_embedding,
    retrieval_scores,
    scale_255,
    scaled_difference,
)
from .descriptors import (
    DEFAULT,
    PAPER,
    Descriptor,
    compact_shape_dna,
    count_zero_modes,
    f1_feature,
    inverse_compact_shape_dna,
    log_weyl_ratio,
    nonzero_eigenvalues,
    normalize,
    real_form,
    weyl_subtract,
)
from .fem import fem_matrices
from .geodesics import HeatGeodesics, face_gradients, geodesic_distance, geodesic_errors
from .index import DescriptorIndex
from .maps import (
    functional_map,
    map_to_pointwise,
    point_map,
    pointwise_to_map,
    transfer_function,
    zoomout,
)
from .mesh import CShapeWarning, Mesh, as_mesh, largest_component, repair_mesh
from .readers import load_mesh
from .signatures import heat_kernel, heat_trace, hks, match_points, si_hks, wks
from .spectrum import Eigenbasis, eigenbasis, eigenpairs, estimate_seconds, shape_dna

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
    "variants": ("cshape.data.variants", None),
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
    "HeatGeodesics",
    "face_gradients",
    "functional_map",
    "geodesic_distance",
    "geodesic_errors",
    "map_to_pointwise",
    "point_map",
    "pointwise_to_map",
    "transfer_function",
    "zoomout",
    "wks",
    "si_hks",
    "match_points",
    "hks",
    "heat_trace",
    "heat_kernel",
    "CShapeWarning",
    "DEFAULT",
    "Descriptor",
    "DescriptorIndex",
    "DescriptorTable",
    "Mesh",
    "as_mesh",
    "compact_shape_dna",
    "count_zero_modes",
    "data",
    "describe",
    "difference_matrix",
    "distance_matrix",
    "Eigenbasis",
    "eigenbasis",
    "eigenpairs",
    "estimate_seconds",
    "f1_feature",
    "fem_matrices",
    "inverse_compact_shape_dna",
    "largest_component",
    "load_mesh",
    "log_weyl_ratio",
    "mds_embedding",
    "nonzero_eigenvalues",
    "normalize",
    "PAPER",
    "real_form",
    "repair_mesh",
    "retrieval_scores",
    "scale_255",
    "scaled_difference",
    "shape_dna",
    "shapes",
    "variants",
    "weyl_subtract",
]
