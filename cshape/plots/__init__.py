"""Figures, the 3-D viewer and the widgets: the pictures layer (extra ``cshape[plots]``).

* :mod:`cshape.plots.figures`    - the lessons' matplotlib figures (meshes, eigenfunctions,
  the paper's Fig. 1-2 and 9, the DFT, convergence, the M-sweep panels);
* :mod:`cshape.plots.collection` - pictures of a collection: MDS scatter plots (Fig. 4-5, with
  outliers marked on the border) and distance-matrix images (Fig. 3, 6) with readable labels;
* :mod:`cshape.plots.overview`    - exploring one's own collection: the interactive MDS (names
  and nearest neighbours on hover), the nearest-neighbour strip of thumbnails, the overview
  page (offline HTML or PNG);
* :mod:`cshape.plots.maps`       - maps between shapes: a field carried across a point map with
  matched landmarks (matplotlib and offline 3-D), the functional map ``C`` as an image;
* :mod:`cshape.plots.viewer`     - interactive 3-D views (plotly), offline in exported HTML;
* :mod:`cshape.plots.widgets`    - the M-sweep widget (ipywidgets) over pure functions.

Every figure function returns a :class:`matplotlib.figure.Figure` made without pyplot
(nothing is registered globally, nothing is shown); in a notebook the figure displays as a
cell's last expression.
"""

from __future__ import annotations

from .._checks import require_extra

require_extra("cshape.plots", "plots", ("matplotlib", "plotly"))

from .collection import plot_distance_matrix, plot_mds  # noqa: E402
from .figures import (  # noqa: E402
    new_figure,
    plot_convergence,
    plot_cshape_dna,
    plot_dft,
    plot_eigenfunctions,
    plot_m_sweep,
    plot_matrices,
    plot_mesh,
    plot_reconstruction_error,
    plot_shape_dna_stages,
    plot_weyl,
)
from .maps import diagonal_share, plot_functional_map, plot_map, view_map  # noqa: E402
from .overview import interactive_mds, overview_html, plot_neighbour_strip, save_figure  # noqa: E402
from .viewer import (  # noqa: E402
    eigenfunction_explorer,
    signature_explorer,
    view_mesh,
    view_meshes,
)

__all__ = [
    "diagonal_share",
    "eigenfunction_explorer",
    "interactive_mds",
    "new_figure",
    "overview_html",
    "plot_convergence",
    "plot_cshape_dna",
    "plot_dft",
    "plot_distance_matrix",
    "plot_eigenfunctions",
    "plot_functional_map",
    "plot_m_sweep",
    "plot_map",
    "plot_matrices",
    "plot_mds",
    "plot_mesh",
    "plot_neighbour_strip",
    "plot_reconstruction_error",
    "plot_shape_dna_stages",
    "plot_weyl",
    "save_figure",
    "signature_explorer",
    "view_map",
    "view_mesh",
    "view_meshes",
]
