"""The paper's Section 3 on any collection: experiments, figures, and a Markdown report.

The pure experiment functions take a :class:`cshape.batch.DescriptorTable` and return plain
numbers, so tests and notebooks call them directly:

* :func:`experiment_3_1`   - Shape-DNA (``N``) vs cShape-DNA (``M``): scaled distance matrices
                              and the mean / std of their difference (paper: 0.68 / 0.69);
* :func:`experiment_3_2`   - the same for ``M = 8, 4, 2, 1`` (paper: means 1.3, 2.3, 4.8, 6.0),
                              beside the truncated Shape-DNA and F1 at equal size;
* :func:`experiment_noise` - Section 3.3: clean vs noisy distance matrices for both descriptors;
* :func:`experiment_retrieval` - PSB retrieval measures for every descriptor and size;
* :func:`experiment_cost`  - descriptor size and comparison time (the "up to 97 %" claim).

:func:`reproduce` runs them all on a list of ``(name, label, mesh)`` records (anything
:func:`cshape.describe` accepts), writes the figures corresponding to the paper's Fig. 1-9,
``results.json``, the descriptor tables and ``report.md`` with the paper's numbers beside ours.
"""

from __future__ import annotations

from .experiments import FAMILIES, PAPER_RESULTS, experiment_retrieval
from .report import reproduce

__all__ = [
    "FAMILIES",
    "PAPER_RESULTS",
    "experiment_retrieval",
    "reproduce",
]
