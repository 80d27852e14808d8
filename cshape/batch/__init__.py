"""Batch runs: eigenvalues and descriptors of a whole collection, cached, resumable, parallel.

:func:`describe` computes the Shape-DNA (the ``N`` smallest eigenvalues, Section 2.1) of
every mesh of a collection and returns a :class:`DescriptorTable`, from which every
descriptor (a :class:`cshape.Descriptor`: normalised / truncated Shape-DNA, cShape-DNA for
any ``M``, F1, ...) is derived without another eigensolve; :func:`collection_distances` gives
the distances of a collection under one descriptor, with the shapes it cannot describe left
out and named.

The cache
---------
Each mesh's eigenvalues are stored in ``cache_dir`` as one ``<key>.npz`` file (NumPy
arrays only, read with ``allow_pickle=False``), where ``key`` is the SHA-256 of the mesh
content (vertex and face bytes) and of the parameters that change the eigenvalues
(``bc``, ``mass``, :data:`CACHE_VERSION`).  ``N`` is not part of the key: an entry with at
least ``N`` eigenvalues serves any smaller ``N`` (the first ``N`` values).
Entries are written atomically (temporary file in the same folder, then ``os.replace``) by
the calling process only, as each result arrives, so an interrupted run (Ctrl-C, a killed
process or worker) leaves only complete entries and the next run resumes where it stopped.
An unreadable entry is reported, recomputed and overwritten.  Leftover ``.*.tmp`` files of
a killed run are ignored and safe to delete.

Meshes given as file paths are also remembered by file: ``cache_dir/files/<h>.key`` holds
the content key of the file whose resolved path, size and modification time (ns) hash to
``h`` (with ``bc``, ``mass`` and :data:`CACHE_VERSION`).  A second run over unchanged files
finds their eigenvalues without reading the meshes; a changed file has a new ``h`` and is
read (and its content key looked up) again.
"""

from __future__ import annotations

from .run import describe
from .table import DescriptorTable

__all__ = [
    "DescriptorTable",
    "describe",
]
