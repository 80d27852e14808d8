"""Argument checks shared by every stage and layer (a leaf module: it imports nothing from
cshape).  The one rule: ``TypeError`` for a wrong type, ``ValueError`` for a value out of
range; the message names the argument, the value and the fix."""

from __future__ import annotations

import numpy as np

__all__ = ["check_choice", "check_descriptors", "check_labels", "check_square", "require_extra"]


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


def require_extra(layer: str, extra: str, modules: tuple[str, ...]) -> None:
    """Import ``modules`` or raise one ``ImportError`` line naming the extra that brings them.

    Called first thing by each layer subpackage (``cshape.plots``, ``cshape.course``, ...),
    so that importing a layer without its extra says what to install.
    """
    import importlib.util

    missing = [m for m in modules if importlib.util.find_spec(m) is None]
    if missing:
        raise ImportError(
            f"{layer} needs {', '.join(missing)}, which the '{extra}' extra installs: "
            f"pip install 'cshape[{extra}]'"
        )


# --------------------------------------------------------------------------- validation
def check_descriptors(X, name="X") -> np.ndarray:
    """(p, d) real array from real or complex descriptors (complex -> [Re, Im] columns)."""
    try:
        A = np.asarray(X)
    except (TypeError, ValueError):  # pragma: no cover - ragged input on old numpy
        A = None
    if A is None or A.dtype == object:
        raise ValueError(
            f"{name} must be a 2-D numeric array (one descriptor per row, all of equal "
            "length); got a ragged or non-numeric sequence"
        )
    if A.ndim != 2:
        raise ValueError(
            f"{name} must be 2-D with shape (p, d), one descriptor per row; got shape "
            f"{A.shape} (use X[None, :] for a single descriptor)"
        )
    if not (np.issubdtype(A.dtype, np.number) or A.dtype == bool):
        raise ValueError(f"{name} must be numeric, got dtype {A.dtype}")
    if np.iscomplexobj(A):
        # |x - y|^2 = |Re x - Re y|^2 + |Im x - Im y|^2: same Euclidean distances
        A = np.hstack([A.real, A.imag])
    A = np.asarray(A, dtype=np.float64)
    if not np.all(np.isfinite(A)):
        bad = np.argwhere(~np.isfinite(A))[0]
        raise ValueError(
            f"{name} contains NaN or infinite values (first at row {bad[0]}, column {bad[1]}); "
            "drop or recompute that descriptor"
        )
    return A


def check_square(D, name="D", *, nonnegative=True) -> np.ndarray:
    try:
        A = np.asarray(D, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a square numeric matrix") from None
    if A.ndim != 2 or A.shape[0] != A.shape[1]:
        raise ValueError(
            f"{name} must be a square (p, p) distance matrix, got shape {A.shape}; "
            "build one with cshape.distance_matrix(X)"
        )
    if A.shape[0] == 0:
        raise ValueError(f"{name} is empty (shape {A.shape}); it needs at least one model")
    if not np.all(np.isfinite(A)):
        bad = np.argwhere(~np.isfinite(A))[0]
        raise ValueError(
            f"{name} contains NaN or infinite values (first at [{bad[0]}, {bad[1]}]); "
            "check the descriptors it was computed from"
        )
    if nonnegative and A.min() < 0:
        bad = np.unravel_index(np.argmin(A), A.shape)
        raise ValueError(
            f"{name} must hold non-negative distances, got {A[bad]:g} at [{bad[0]}, {bad[1]}]"
        )
    return A


def check_labels(labels, p, name="labels") -> np.ndarray:
    """Integer class codes (p,) from any sequence of hashable labels."""
    if isinstance(labels, (str, bytes)):
        raise ValueError(f"{name} must be a sequence of one label per model, got a string")
    lab = list(np.asarray(labels).tolist()) if isinstance(labels, np.ndarray) else list(labels)
    if len(lab) != p:
        raise ValueError(
            f"{name} has {len(lab)} entries but the distance matrix has {p} rows; "
            "pass one class label per model, in the order of the rows"
        )
    codes = {}
    try:
        return np.array([codes.setdefault(x, len(codes)) for x in lab], dtype=np.int64)
    except TypeError:
        raise ValueError(f"{name} must hold hashable labels (str or int)") from None
