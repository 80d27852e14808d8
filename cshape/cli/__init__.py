"""The ``cshape`` command line: a thin shell over the package's functions.

* :mod:`cshape.cli.registry`    - the parser, the static registry of sub-commands, :func:`main`;
* :mod:`cshape.cli.output`  - the one error path (one line, exit status 2) and warnings;
* :mod:`cshape.cli.explore` - ``describe``, ``info``, ``query`` (``--plot``): one's own meshes;
* :mod:`cshape.cli.pictures` - ``overview``: MDS, distance matrix and classes of a table;
* :mod:`cshape.cli.data`    - ``data list|build|path``: the data manifest's collections;
* :mod:`cshape.cli.apps`    - ``demo`` and ``reproduce``;
* :mod:`cshape.cli.course`  - ``notebooks``, ``assignments``, ``lessons``.

Heavy imports happen inside the commands.
"""

from __future__ import annotations

from .registry import main

__all__ = [
    "main",
]
