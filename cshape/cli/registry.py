"""The ``cshape`` parser and :func:`main`.

Sub-commands are small functions ``add_<name>(subparsers)`` in the modules of this package
that define their parser and set ``func``; :data:`SUBCOMMANDS` lists them all, and
:func:`main` runs the chosen one.  Heavy imports happen inside the commands.

The one error path (:mod:`cshape.cli.output`): every expected failure (bad input, a missing
or unreadable file, an offline or failed download, a missing optional dependency) ends in one
line on stderr, ``cshape <command>: error: <message>``, and exit status 2, without a
traceback; Ctrl-C ends in ``cshape <command>: interrupted`` and exit status 130.  Anything
else is a bug and keeps its traceback.
"""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING, NoReturn

from . import apps, course, data, explore, pictures
from .output import EXPECTED_ERRORS, one_line

if TYPE_CHECKING:
    from collections.abc import Sequence


class _Parser(argparse.ArgumentParser):
    """An argument parser whose usage errors are one line too (argparse prints the usage
    first); sub-command parsers are of this class as well."""

    def error(self, message: str) -> NoReturn:
        print(f"{self.prog}: error: {' '.join(message.split())}; see `{self.prog} --help`",
              file=sys.stderr)
        sys.exit(2)


#: The sub-commands, in the order ``cshape --help`` lists them: one static registry.
SUBCOMMANDS = (
    apps.add_demo,
    apps.add_reproduce,
    explore.add_describe,
    explore.add_info,
    explore.add_query,
    pictures.add_overview,
    data.add_data,
    course.add_notebooks,
    course.add_assignments,
)


def build_parser() -> argparse.ArgumentParser:
    """The ``cshape`` parser with every sub-command of :data:`SUBCOMMANDS`."""
    parser = _Parser(
        prog="cshape", description="Shape-DNA and compact Shape-DNA of triangle meshes"
    )
    sub = parser.add_subparsers(dest="command", required=True)
    for add in SUBCOMMANDS:
        add(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``cshape`` command line.

    Parameters
    ----------
    argv : sequence of str, optional
        The arguments after ``cshape`` (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status: 0 on success, 2 on an expected error (one line on stderr), 130
        when interrupted (Ctrl-C).
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except KeyboardInterrupt:
        print(f"cshape {args.command}: interrupted", file=sys.stderr)
        return 130
    except EXPECTED_ERRORS as exc:
        print(f"cshape {args.command}: error: {one_line(exc)}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
