"""Stage 4 of the pipeline: descriptors from eigenvalues (Section 2.1, 2.3 and 3.1).

* :mod:`cshape.descriptors.formulas` - the formulas, on plain arrays: :func:`normalize`
  (Section 2.1), :func:`weyl_subtract` (Eq. 8), :func:`compact_shape_dna` (Eq. 9-10),
  :func:`log_weyl_ratio`, :func:`detrend`, :func:`real_form`, :func:`inverse_compact_shape_dna`,
  :func:`f1_feature`, and the rule for meshes of several pieces (:func:`count_zero_modes`,
  :func:`nonzero_eigenvalues`);
* :mod:`cshape.descriptors.recipe`   - :class:`Descriptor`, which descriptor to compute, as one
  frozen value that builds rows from spectra: :data:`PAPER` (the paper's cShape-DNA) and
  :data:`DEFAULT` (the exploration default).
"""

from __future__ import annotations

from .formulas import (
    compact_shape_dna,
    count_zero_modes,
    detrend,
    inverse_compact_shape_dna,
    log_weyl_ratio,
    normalize,
    real_form,
    weyl_subtract,
)
from .recipe import DEFAULT, PAPER, Descriptor

__all__ = [
    "DEFAULT",
    "PAPER",
    "Descriptor",
    "compact_shape_dna",
    "count_zero_modes",
    "detrend",
    "inverse_compact_shape_dna",
    "log_weyl_ratio",
    "normalize",
    "real_form",
    "weyl_subtract",
]
