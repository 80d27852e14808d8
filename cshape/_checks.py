"""Argument checks shared by every stage (a leaf module: it imports nothing from cshape)."""

from __future__ import annotations

__all__ = ["check_choice"]


def check_choice(name, value, allowed):
    """Return ``value`` lower-cased if it is one of ``allowed``, else raise a clear error.

    Parameters
    ----------
    name : str
        The argument's name, for the message.
    value : object
        What the caller passed.
    allowed : sequence of str
        The accepted options (lower case).

    Raises
    ------
    ValueError
        ``"<name> must be one of {'a', 'b'}, got <value>"``.
    """
    if not isinstance(value, str) or value.lower() not in allowed:
        opts = ", ".join(repr(a) for a in allowed)
        raise ValueError(f"{name} must be one of {{{opts}}}, got {value!r}")
    return value.lower()
