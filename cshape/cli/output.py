"""The command line's one error path and its warnings: what every command prints on failure.

Every expected failure (:data:`EXPECTED_ERRORS`) ends in one line on stderr,
``cshape <command>: error: <message>``, and exit status 2, without a traceback.
"""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import warnings
    from collections.abc import Iterable


class CommandError(Exception):
    """An expected failure of a command; :func:`main` prints its message on one line."""


#: Expected failures: bad values, files (OSError covers FileNotFoundError, PermissionError,
#: a full disk and network errors, requests' and pooch's included), a missing optional
#: dependency, a failed batch run.  KeyError: a name not found (its message is args[0]).
EXPECTED_ERRORS = (CommandError, ValueError, OSError, ImportError, KeyError, RuntimeError)


def one_line(exc: BaseException) -> str:
    """The message of ``exc`` on one line (whitespace runs collapsed), never empty."""
    msg = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
    text = " ".join(str(msg).split())
    return text or type(exc).__name__


#: Warnings listed one by one before a command summarises the rest (``-v``: all).
MAX_WARNINGS = 10


def print_warnings(caught: Iterable[warnings.WarningMessage], command: str, verbose: bool = False,
                   skip: str | tuple[str, ...] = ()) -> None:
    """Print recorded warnings on stderr, one line each: ``cshape <command>: warning: ...``.

    Repeated messages once; messages starting with a prefix in ``skip`` left out; at most
    :data:`MAX_WARNINGS` unless ``verbose``, then a count of the rest.
    """
    msgs = [" ".join(str(w.message).split()) for w in caught]
    msgs = [m for m in dict.fromkeys(msgs) if not m.startswith(skip)]
    shown = msgs if verbose else msgs[:MAX_WARNINGS]
    for m in shown:
        print(f"cshape {command}: warning: {m}", file=sys.stderr)
    if len(msgs) > len(shown):
        print(f"cshape {command}: {len(msgs) - len(shown)} more warnings (-v lists them all)",
              file=sys.stderr)
