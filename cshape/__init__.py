"""cshape: Shape-DNA and compact Shape-DNA (cShape-DNA) of triangle meshes.

The pipeline, one module per stage (data flows one way):

1. :mod:`cshape.mesh`        - :class:`Mesh`, :func:`repair_mesh`; :mod:`cshape.readers` -
   :func:`load_mesh` (OBJ, OFF, PLY, STL, ...)
2. :mod:`cshape.fem`         - :func:`fem_matrices`: ``A`` (Eq. 4/6) and ``B`` (Eq. 5/7)
3. :mod:`cshape.spectrum`    - :func:`shape_dna`, :func:`eigenpairs`: ``A f = -lam B f`` (Eq. 3)
4. :mod:`cshape.descriptors` - :func:`normalize`, :func:`weyl_subtract` (Eq. 8),
   :func:`compact_shape_dna` (Eq. 9-10; ``transform='log-weyl'``, ``'log-weyl-dct'``),
   :func:`log_weyl_ratio`, :func:`real_form`, :func:`inverse_compact_shape_dna`,
   :func:`f1_feature`
   :mod:`cshape.signatures` - per-point signatures from :func:`eigenpairs`: :func:`hks`,
   :func:`wks`, :func:`si_hks`, :func:`heat_kernel`, :func:`heat_trace`, and
   :func:`match_points` (correspondence)
5. :mod:`cshape.compare`     - :func:`distance_matrix`, :func:`scale_255`,
   :func:`scaled_difference`,
   :func:`retrieval_scores`, :func:`mds_embedding`, :class:`DescriptorIndex`
6. :mod:`cshape.variants`    - marching cubes, remeshing, Section 3.3 noise (PyMeshLab)
   (:mod:`cshape.creatures`: the generated retrieval benchmark, twelve classes of creatures)
7. :mod:`cshape.data`        - the data manifest and shape collections

:mod:`cshape.batch` runs many meshes (cached, parallel, Dask); :mod:`cshape.reproduce` the
paper's Section 3; :mod:`cshape.plots` and :mod:`cshape.widgets` draw the notebooks' figures
and the M-sweep widget (import them on demand).

:mod:`cshape.shapes` builds analytic test shapes (sphere, square, disk, hemisphere, ...).

The ``cshape`` command (:mod:`cshape.cli`: the parser and the one error path;
:mod:`cshape.commands`: ``describe``, ``info``, ``query``, ``data``) is a thin shell over
these functions.
"""

from . import data, shapes, variants
from .batch import DescriptorTable, describe
from .compare import (
    DescriptorIndex,
    descriptor_matrix,
    difference_matrix,
    distance_matrix,
    mds_embedding,
    retrieval_scores,
    scale_255,
    scaled_difference,
)
from .descriptors import (
    compact_shape_dna,
    compact_shape_dna_real,
    f1_feature,
    inverse_compact_shape_dna,
    log_weyl_ratio,
    normalize,
    real_form,
    weyl_subtract,
)
from .fem import fem_matrices
from .mesh import CShapeWarning, Mesh, as_mesh, largest_component, repair_mesh
from .readers import load_mesh
from .signatures import heat_kernel, heat_trace, hks, match_points, si_hks, wks
from .spectrum import eigenpairs, shape_dna

__version__ = "0.1.0"

__all__ = [
    "CShapeWarning",
    "DescriptorIndex",
    "DescriptorTable",
    "describe",
    "descriptor_matrix",
    "difference_matrix",
    "distance_matrix",
    "mds_embedding",
    "retrieval_scores",
    "scale_255",
    "scaled_difference",
    "data",
    "variants",
    "Mesh",
    "as_mesh",
    "compact_shape_dna",
    "compact_shape_dna_real",
    "eigenpairs",
    "f1_feature",
    "fem_matrices",
    "heat_kernel",
    "heat_trace",
    "hks",
    "inverse_compact_shape_dna",
    "largest_component",
    "load_mesh",
    "log_weyl_ratio",
    "match_points",
    "normalize",
    "real_form",
    "repair_mesh",
    "shape_dna",
    "shapes",
    "si_hks",
    "weyl_subtract",
    "wks",
]
