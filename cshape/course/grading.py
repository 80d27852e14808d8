"""What a cshape course changes in nbgrader's grading: read by ``nbgrader_config.py``.

The ``nbgrader_config.py`` that :func:`cshape.course.assignments.write_course` writes ends
with ``configure(c)``, which sets two things (this module imports nbgrader: it is read by
nbgrader's own commands, never by ``import cshape``):

* ``nbgrader autograde`` takes an autograder-test cell whose only difference from the
  source is the hidden tests that the release left out as unchanged
  (:class:`OverwriteCells`): nbgrader warns ``Attribute 'checksum' ... has changed!`` for
  every such cell of every submission, untouched or not, which would drown the one warning
  that matters, a student's edit of a locked cell;
* ``nbgrader generate_feedback`` pages typeset their equations offline
  (:func:`offline_feedback_math`): MathJax comes from a copy in the course folder
  (``mathjax/``) instead of a network host.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from nbgrader import utils
from nbgrader.api import MissingEntry
from nbgrader.preprocessors import (
    CheckCellMetadata,
    ClearHiddenTests,
    ClearOutput,
    DeduplicateIds,
    OverwriteKernelspec,
)
from nbgrader.preprocessors import OverwriteCells as _NbgraderOverwriteCells

from .._files import atomic_write
from .lessons import offline_mathjax

__all__ = [
    "configure",
]

#: The MathJax that nbgrader's feedback template loads from the network.
CDN_MATHJAX = ("https://cdnjs.cloudflare.com/ajax/libs/mathjax/2.7.7/latest.js"
               "?config=TeX-AMS_CHTML-full,Safe")


class OverwriteCells(_NbgraderOverwriteCells):
    """nbgrader's ``OverwriteCells``, quiet about the hidden tests the release removed.

    A locked cell whose source is the source cell's without its ``### BEGIN HIDDEN TESTS``
    region is what the student received: it gets the full source back, as nbgrader does,
    without a warning.  Any other change to a locked cell is reported as before.
    """

    def preprocess_cell(self, cell: Any, resources: Any, cell_index: int) -> Any:
        grade_id = cell.metadata.get("nbgrader", {}).get("grade_id")
        if grade_id is not None and utils.is_locked(cell):
            try:
                source = self.gradebook.find_source_cell(grade_id, self.notebook_id,
                                                         self.assignment_id)
            except MissingEntry:
                source = None
            if source is not None and cell.source != source.source:
                released = cell.copy()
                released.source = source.source
                ClearHiddenTests()._remove_hidden_test_region(released)
                if released.source == cell.source:
                    cell.source = source.source
        return super().preprocess_cell(cell, resources, cell_index)


def offline_feedback_math(assignment: str = "", student: str = "", notebooks: Any = None,
                          root: str | os.PathLike[str] | None = None) -> list[Path]:
    """Point the feedback pages of a course at the course's MathJax copy (a post-convert hook).

    Every ``feedback/<student>/<assignment>/*.html`` that loads MathJax from the network
    loads the copy in ``<root>/mathjax/`` instead (made by
    :func:`cshape.course.lessons.offline_mathjax` when missing), by a relative address: the
    pages typeset their equations with no network, in the course folder.

    Parameters
    ----------
    assignment, student, notebooks
        What nbgrader passes to a post-convert hook; every feedback page is checked.
    root : str or os.PathLike, optional
        The course folder (default: the working directory, where nbgrader runs).

    Returns
    -------
    list of pathlib.Path
        The pages rewritten.
    """
    root = Path.cwd() if root is None else Path(root)
    pages = [p for p in sorted((root / "feedback").glob("*/*/*.html"))
             if CDN_MATHJAX in p.read_text(encoding="utf-8")]
    url = offline_mathjax(root) if pages else None
    if url is None:
        return []
    for page in pages:
        text = page.read_text(encoding="utf-8").replace(CDN_MATHJAX, f"../../../{url}")

        def write(f: Any, text: str = text) -> None:
            f.write(text)

        atomic_write(page, write, binary=False)
    return pages


def configure(c: Any) -> None:
    """Set a cshape course's grading options on nbgrader's config object ``c``.

    Parameters
    ----------
    c : traitlets.config.Config
        The ``c`` of an ``nbgrader_config.py`` (what ``get_config()`` returns there).
    """
    c.Autograde.sanitize_preprocessors = [ClearOutput, DeduplicateIds, OverwriteKernelspec,
                                          OverwriteCells, CheckCellMetadata]
    c.GenerateFeedback.post_convert_hook = offline_feedback_math
