"""``python -m cshape``: the command line (:func:`cshape.cli.main`)."""

import sys

from .cli import main

sys.exit(main())
