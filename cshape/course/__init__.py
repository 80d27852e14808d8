"""Teaching: run the lessons, make nbgrader courses, and the lessons' helpers (extra
``cshape[course]`` for nbgrader, ``cshape[notebooks]`` to execute the lessons).

* :mod:`cshape.course.lessons`     - execute the walkthrough notebooks into executed ``.ipynb``
  and offline HTML pages (``cshape notebooks``, ``make demo``);
* :mod:`cshape.course.assignments` - nbgrader's student release of the graded lessons and a
  course folder (``cshape assignments``, ``cshape lessons DIR``);
* :mod:`cshape.course.teaching`    - the small data helpers the lessons share.

The modules import their heavy dependencies (nbclient, nbgrader) when used, so that
``cshape.course.teaching`` works with the plain install.
"""
