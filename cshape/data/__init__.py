"""Shape collections: the data manifest, generated and cached shapes, packaged, local and
downloadable meshes, and loaders for the classic benchmarks' folder layouts.

Every collection is an entry of ``data_manifest.yaml`` (shipped inside the package, or the file
named by ``CSHAPE_MANIFEST``), of one of four kinds:

==========  ===================================================================================
generated   built by a recipe (:mod:`cshape.shapes`, :mod:`cshape.data.variants`), seeded, cached
package     meshes shipped inside an installed Python package (PyMeshLab's samples)
download    public files fetched *only on request* (:func:`fetch`, ``cshape data build NAME``)
            into the cache and checked against their sha256; benchmarks whose terms forbid
            redistribution (McGill, TOSCA, SHREC'07) are fetched by hand and read by a layout
            loader (:func:`read_mcgill`, :func:`read_tosca`, :func:`read_shrec07`)
local       any folder of meshes, class labels from sub-folder names or a CSV
            (:func:`load_folder`)
==========  ===================================================================================

One call gets a shape or a whole collection, offline and reproducibly::

    import cshape.data
    cshape.data.list_collections()              # ['paper-models', 'articulated', ...]
    S1 = cshape.data.load("paper-models", "S1")  # a cshape.Mesh
    poses = cshape.data.load_collection("articulated")
    poses.names, poses.labels, poses[0].mesh

Cache
-----
Generated meshes live in ``<cache>/generated/<collection>/<item>-<key>.npz`` (arrays
``vertices``, ``faces`` and the recipe as JSON; read with ``allow_pickle=False``), where
``<cache>`` is ``cache_dir=`` if given, else ``$CSHAPE_CACHE``, else the user cache folder
(``~/.cache/cshape`` on Linux) and ``<key>`` hashes the recipe, its parameters, the seed, the
base item's key, :data:`RECIPES_VERSION` and the PyMeshLab version.  Files are written to a
temporary name and moved into place (``os.replace``), so an interrupted build never leaves a
partial file; a cache folder that cannot be written (a file in its place, a full disk) gives an
``OSError`` naming it.  Downloads go to ``<cache>/downloads/<collection>/``; a downloaded file is
checked against the manifest's size and sha256 before each read, so a corrupt or replaced file
is an error, never a silently different mesh.
"""

from __future__ import annotations

from .download import fetch
from .folders import load_folder
from .manifest import Collection, info, list_collections
from .paths import cache_dir
from .store import build, load, load_collection

__all__ = [
    "Collection",
    "build",
    "cache_dir",
    "fetch",
    "info",
    "list_collections",
    "load",
    "load_collection",
    "load_folder",
]
