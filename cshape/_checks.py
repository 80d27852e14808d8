"""Argument checks shared by every stage and layer.

A leaf module: it imports nothing from cshape.

The one rule: ``TypeError`` for a wrong type, ``ValueError`` for a value out of range; the
message names the argument, the value and the fix, and is the same in every function that
takes the argument (``N=2.5`` reads ``N must be an integer, got float 2.5`` whether it was
given to :func:`cshape.shape_dna`, :func:`cshape.describe` or
:class:`cshape.Descriptor`).  ``bool`` is not an integer nor a number here;
NumPy integers and floats are.

Mode names (descriptor kinds, transforms, normalizations, boundary conditions, mass
matrices) are written in one style: lower case, words joined by hyphens (``'shape-dna'``,
``'log-weyl-dct'``).
"""

from __future__ import annotations

import numbers
import os
from collections.abc import Collection
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

_PACKAGE_DIR = os.path.dirname(os.path.abspath(__file__))


def _caller_stacklevel() -> int:
    """``stacklevel`` of the first frame outside cshape (where the user wrote the call)."""
    import sys

    level, frame = 1, sys._getframe(1)
    while frame is not None and os.path.abspath(frame.f_code.co_filename).startswith(
            _PACKAGE_DIR + os.sep):
        level += 1
        frame = frame.f_back
    return level


def _describe(value: object) -> str:
    """``float 2.5``, ``str '10'``, ``NoneType``: the type and the value, for messages."""
    if value is None:
        return "NoneType"
    text = repr(value)
    if len(text) > 60:
        text = text[:57] + "..."
    return f"{type(value).__name__} {text}"


def check_choice(name: str, value: object, allowed: Collection[str]) -> str:
    """Return ``value`` lower-cased if it is one of ``allowed``, else raise a clear error.

    Parameters
    ----------
    name : str
        The argument's name, for the message.
    value : object
        What the caller passed.
    allowed : collection of str
        The accepted options (lower case).

    Returns
    -------
    str
        The option, lower case.

    Raises
    ------
    TypeError
        ``value`` is not a string: ``"<name> must be one of {'a', 'b'}, got <type> <value>"``.
    ValueError
        An unknown option: ``"<name> must be one of {'a', 'b'}, got <value>"``.
    """
    opts = ", ".join(repr(a) for a in allowed)
    if not isinstance(value, str):
        raise TypeError(f"{name} must be one of {{{opts}}}, got {_describe(value)}")
    v = value.lower()
    if v in allowed:
        return v
    raise ValueError(f"{name} must be one of {{{opts}}}, got {value!r}")


def check_int(name: str, value: object, *, min: int | None = None,
              max: int | None = None) -> int:
    """Return ``value`` as a Python ``int`` if it is an integer in ``[min, max]``.

    Python and NumPy integers are accepted; ``bool``, floats (even ``4.0``) and strings are
    not.

    Raises
    ------
    TypeError
        ``"<name> must be an integer, got float 2.5"``.
    ValueError
        ``"<name> must be an integer >= 1, got 0"``, or ``... in [0, 8], got 9`` when
        ``max`` is given.
    """
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be an integer, got {_describe(value)}")
    v = int(value)
    if (min is not None and v < min) or (max is not None and v > max):
        if max is None:
            raise ValueError(f"{name} must be an integer >= {min}, got {v}")
        if min is None:
            raise ValueError(f"{name} must be an integer <= {max}, got {v}")
        raise ValueError(f"{name} must be an integer in [{min}, {max}], got {v}")
    return v


def check_real(name: str, value: object, *, min: float | None = None,
               above: float | None = None, positive: bool = False,
               finite: bool = True) -> float:
    """Return ``value`` as a Python ``float`` if it is a real number in range.

    Python and NumPy integers and floats (and 0-d real arrays) are accepted; ``bool``,
    strings, complex numbers, ``None`` and sequences are not.

    Parameters
    ----------
    name : str
        The argument's name, for the message.
    value : object
        What the caller passed.
    min : float, optional
        Smallest allowed value (inclusive).
    above : float, optional
        Exclusive lower bound: require ``value > above``.
    positive : bool, default=False
        Require ``value > 0`` (``above=0``).
    finite : bool, default=True
        Refuse NaN and infinities.

    Raises
    ------
    TypeError
        ``"<name> must be a real number, got str '1'"``.
    ValueError
        ``"<name> must be a positive finite number, got 0.0"``, ``"<name> must be a finite
        number >= 0, got -1.0"``, ``"<name> must be a finite number > 1, got 1.0"``.
    """
    x: Any = value
    if isinstance(x, np.ndarray) and x.ndim == 0:
        x = x[()]
    if isinstance(x, (bool, np.bool_)) or not isinstance(x, numbers.Real):
        raise TypeError(f"{name} must be a real number, got {_describe(value)}")
    v = float(x)
    bad = (finite and not np.isfinite(v)) or np.isnan(v)
    bad = bad or (positive and not v > 0) or (min is not None and not v >= min)
    bad = bad or (above is not None and not v > above)
    if bad:
        what = "finite number" if finite else "number"
        if positive:
            rule = f"a positive {what}"
        elif above is not None:
            rule = f"a {what} > {above:g}"
        elif min is not None:
            rule = f"a {what} >= {min:g}"
        else:
            rule = f"a {what}"
        raise ValueError(f"{name} must be {rule}, got {v!r}")
    return v


def check_crop(M: object, N: object, *, log: bool = False) -> int:
    """Check the one M-versus-N rule: ``2M+1`` values are kept from ``N`` (or ``N-1``) values.

    The crop of Eq. (10) keeps the ``2M+1`` values of frequencies ``-M .. M`` of a sequence
    (or, for the truncated descriptors, its first ``2M+1`` values).  The sequence is the
    Shape-DNA ``lam_0 .. lam_{N-1}`` (``N`` values, Eq. 8) or, with ``log=True``, the
    log-Weyl ratios ``r_1 .. r_{N-1}`` (``N-1`` values: ``lam_0`` has no logarithm).

    Parameters
    ----------
    M : int
        Crop half-width, ``M >= 0``.
    N : int
        Shape-DNA length, ``N >= 1``.
    log : bool, default=False
        The sequence is the ``N-1`` log-Weyl ratios.

    Returns
    -------
    int
        ``M``, as a Python ``int``.

    Raises
    ------
    TypeError
        ``M`` or ``N`` not an integer.
    ValueError
        ``M < 0``, ``N < 1``, or ``2M+1`` more than the sequence holds:
        ``"M=8: 2M+1 = 17 values cannot be kept from N = 12 eigenvalues; use M <= 5 or
        N >= 17"``.
    """
    M = check_int("M", M, min=0)
    N = check_int("N", N, min=1)
    L = N - 1 if log else N
    if 2 * M + 1 <= L:
        return M
    if L < 1:
        raise ValueError(
            f"the log-Weyl ratios need N >= 2 (the log-Weyl ratio starts at lam_1; lam_0 has "
            f"no logarithm), got N = {N}")
    source = (f"the N-1 = {L} log-Weyl ratios (lam_0 has no logarithm)" if log
              else f"N = {N} eigenvalues")
    raise ValueError(
        f"M={M}: 2M+1 = {2 * M + 1} values cannot be kept from {source}; use "
        f"M <= {(L - 1) // 2} or N >= {2 * M + 1 + (N - L)}")


def check_n_jobs(value: object, name: str = "n_jobs") -> int | None:
    """``None`` or a worker count: a positive integer, or -1 for all cores (joblib's rule).

    Raises
    ------
    TypeError
        ``"n_jobs must be an integer, got float 2.0"``.
    ValueError
        ``"n_jobs must be a positive integer or -1 (all cores), got 0"``.
    """
    if value is None:
        return None
    n = check_int(name, value)
    if n == 0 or n < -1:
        raise ValueError(f"{name} must be a positive integer or -1 (all cores), got {n}")
    return n


def check_bool(name: str, value: object) -> bool:
    """Return ``value`` as a Python ``bool`` (``True``/``False``, NumPy bools accepted).

    Raises
    ------
    TypeError
        ``"<name> must be True or False, got int 1"``.
    """
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be True or False, got {_describe(value)}")
    return bool(value)


def check_flag_or_choice(name: str, value: object, allowed: Collection[str]) -> bool | str:
    """Return ``value`` if it is ``True``, ``False`` or one of the options ``allowed``.

    For an argument that switches a feature on or off and, as a string, says how (the
    ``legend=True | False | 'outside'`` of :func:`cshape.plots.plot_mds`).

    Returns
    -------
    bool or str
        A Python ``bool``, or the option lower-cased (as :func:`check_choice` returns it).

    Raises
    ------
    TypeError
        Neither a bool nor a string: ``"legend must be True, False or one of {'outside'},
        got int 1"``.
    ValueError
        An unknown option: ``"legend must be True, False or one of {'outside'}, got 'in'"``.
    """
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    opts = ", ".join(repr(a) for a in allowed)
    rule = f"{name} must be True, False or one of {{{opts}}}"
    if not isinstance(value, str):
        raise TypeError(f"{rule}, got {_describe(value)}")
    v = value.lower()
    if v not in allowed:
        raise ValueError(f"{rule}, got {value!r}")
    return v


def check_path(name: str, value: object) -> Path:
    """Return ``value`` as a :class:`pathlib.Path` (a ``str`` or ``os.PathLike``).

    Raises
    ------
    TypeError
        ``"<name> must be a path (str or os.PathLike), got int 3"``.
    ValueError
        An empty string: ``"<name> is an empty path"``.
    """
    if isinstance(value, bytes) or not isinstance(value, (str, os.PathLike)):
        raise TypeError(f"{name} must be a path (str or os.PathLike), got {_describe(value)}")
    if isinstance(value, str) and not value.strip():
        raise ValueError(f"{name} is an empty path; pass a file or folder name")
    return Path(value)


def require_extra(layer: str, extra: str, modules: tuple[str, ...]) -> None:
    """Import ``modules`` or raise one ``ImportError`` line naming the extra that brings them.

    Called first thing by each layer subpackage (``cshape.plots``, ``cshape.course``, ...),
    so that importing a layer without its extra says what to install.
    """
    import importlib.util

    def absent(module: str) -> bool:
        try:
            return importlib.util.find_spec(module) is None
        except (ImportError, ValueError):  # a broken or blocked install
            return True

    missing = [m for m in modules if absent(m)]
    if missing:
        raise ImportError(
            f"{layer} needs {', '.join(missing)}, which the '{extra}' extra installs: "
            f"pip install 'cshape[{extra}]'"
        )


# --------------------------------------------------------------------------- validation
def check_descriptors(X: ArrayLike, name: str = "X") -> NDArray[np.float64]:
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


def check_square(D: ArrayLike, name: str = "D", *, nonnegative: bool = True
                 ) -> NDArray[np.float64]:
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


def check_points(Y: ArrayLike, name: str = "Y", *, d: int | None = None,
                 min_points: int = 0, fix: str = "") -> NDArray[np.float64]:
    """Return ``Y`` as a finite (p, d) float array: one point per row.

    Parameters
    ----------
    Y : array_like, shape (p, d)
        Coordinates (an MDS embedding, say).
    name : str, default='Y'
        The argument's name, for the message.
    d : int, optional
        The number of columns required (2 for a planar picture); any when not given.
    min_points : int, default=0
        The fewest rows allowed.
    fix : str, optional
        How to make a right one, appended to the shape message
        (``'use mds_embedding(D)'``).

    Raises
    ------
    TypeError
        Not an array of real numbers: ``"Y must be an array of real coordinates, shape
        (p, 2), got str 'ab'"``.
    ValueError
        The wrong shape (``"Y must have shape (p, 2), got (3, 3); use mds_embedding(D)"``),
        too few points or NaN / infinite values (naming the first).
    """
    cols = "d" if d is None else str(d)
    try:
        A = np.asarray(Y)
        ok = not isinstance(Y, (str, bytes)) and A.dtype != object and (
            np.issubdtype(A.dtype, np.integer) or np.issubdtype(A.dtype, np.floating))
    except (TypeError, ValueError):  # a ragged sequence
        ok = False
    if not ok:
        raise TypeError(f"{name} must be an array of real coordinates, shape (p, {cols}), "
                        f"got {_describe(Y)}")
    if A.ndim != 2 or (d is not None and A.shape[1] != d):
        hint = f"; {fix}" if fix else ""
        raise ValueError(f"{name} must have shape (p, {cols}), got {A.shape}{hint}")
    if len(A) < min_points:
        raise ValueError(f"{name} has {len(A)} points; pass at least {min_points}")
    A = np.asarray(A, dtype=np.float64)
    if not np.all(np.isfinite(A)):
        bad = np.argwhere(~np.isfinite(A))[0]
        raise ValueError(f"{name} contains NaN or infinite values (first at row {bad[0]}, "
                         f"column {bad[1]}); pass finite coordinates")
    return A


def check_entries(name: str, value: Any, p: int, *, of: str = "Y",
                  unit: str = "points") -> list[Any]:
    """Return ``value`` as a list of ``p`` entries: one per point (name, label, mask, ...).

    Parameters
    ----------
    name : str
        The argument's name, for the message.
    value : sequence or 1-D array
        What the caller passed; a string is not taken for a sequence of characters.
    p : int
        The number of entries required.
    of, unit : str, default='Y', 'points'
        What holds the ``p`` points, for the message: ``"names has 3 entries but Y has
        12 points"``.

    Raises
    ------
    TypeError
        A string, a scalar or another object without a length: ``"names must be a sequence
        with one entry for each of the points of Y, got str 'abc'"``.
    ValueError
        The wrong length: ``"names has 3 entries but Y has 12 points; pass one entry for
        each, in order"``.
    """
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or (
            isinstance(value, np.ndarray) and value.ndim != 1):
        raise TypeError(f"{name} must be a sequence with one entry for each of the {unit} "
                        f"of {of}, got {_describe(value)}")
    if len(value) != p:
        raise ValueError(f"{name} has {len(value)} entries but {of} has {p} {unit}; pass "
                         "one entry for each, in order")
    return list(value)


def check_labels(labels: Any, p: int, name: str = "labels") -> NDArray[np.int64]:
    """Integer class codes (p,) from any sequence of hashable labels."""
    if isinstance(labels, (str, bytes)):
        raise ValueError(f"{name} must be a sequence of one label per model, got a string")
    lab = list(np.asarray(labels).tolist()) if isinstance(labels, np.ndarray) else list(labels)
    if len(lab) != p:
        raise ValueError(
            f"{name} has {len(lab)} entries but the distance matrix has {p} rows; "
            "pass one class label per model, in the order of the rows"
        )
    codes: dict[object, int] = {}
    try:
        return np.array([codes.setdefault(x, len(codes)) for x in lab], dtype=np.int64)
    except TypeError:
        raise ValueError(f"{name} must hold hashable labels (str or int)") from None


def check_spectrum(lam: Any, name: str = "lam", min_len: int = 1) -> NDArray[np.float64]:
    """Return ``lam`` as a 1-D float array of at least ``min_len`` finite real eigenvalues.

    Raises
    ------
    TypeError
        If ``lam`` is not an array of real numbers (a complex cShape-DNA, say).
    ValueError
        If it is not 1-D, too short, or holds NaN or infinite values.
    """
    try:
        is_complex = np.iscomplexobj(lam)
        x = np.empty(0) if is_complex else np.asarray(lam, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a 1-D array of real eigenvalues") from None
    if is_complex:
        raise TypeError(
            f"{name} must be real eigenvalues, got a complex array (a cShape-DNA?); pass the "
            "Shape-DNA from cshape.shape_dna"
        )
    if x.ndim != 1:
        raise ValueError(f"{name} must be 1-D (one spectrum), got shape {x.shape}")
    if len(x) < min_len:
        raise ValueError(f"{name} must hold at least {min_len} eigenvalues, got {len(x)}")
    if not np.all(np.isfinite(x)):
        raise ValueError(f"{name} contains NaN or infinite values")
    return x


def check_vertex_indices(name: str, idx: ArrayLike, n: int) -> NDArray[np.int64]:
    """Return vertex indices as a 1-D int64 array, each in ``[0, n)``.

    Parameters
    ----------
    name : str
        The argument's name, for the message.
    idx : array_like of int, shape (m,) or scalar
        Zero-based vertex numbers of a mesh of ``n`` vertices.
    n : int
        The number of vertices.

    Raises
    ------
    TypeError
        If the values are not integers.
    ValueError
        If the array is not 1-D or an index lies outside ``[0, n)``.
    """
    a = np.asarray(idx)
    if a.dtype.kind not in "iu":
        raise TypeError(f"{name} must be an integer array of vertex indices, got "
                        f"{a.dtype} values")
    a = np.atleast_1d(a).astype(np.int64)
    if a.ndim != 1:
        raise ValueError(f"{name} must be 1-D, got shape {a.shape}")
    if a.size and (a.min() < 0 or a.max() >= n):
        bad = int(a.min() if a.min() < 0 else a.max())
        raise ValueError(f"{name} holds vertex index {bad}, outside [0, {n - 1}]; indices are "
                         "zero-based vertex numbers")
    return a


def check_landmarks(landmarks: ArrayLike | None, n_source: int,
                    n_target: int) -> NDArray[np.int64] | None:
    """Return landmark pairs ``(source vertex, target vertex)``, shape (L, 2), or None.

    Parameters
    ----------
    landmarks : array_like of int, shape (L, 2), or None
        Row ``j`` pairs a vertex of the source (of ``n_source`` vertices) with one of the
        target (of ``n_target``); ``L >= 1``.
    n_source, n_target : int
        The vertex counts of the two meshes.

    Raises
    ------
    TypeError
        If the values are not integers.
    ValueError
        If the shape is not (L, 2) with L >= 1, or a vertex is out of range.
    """
    if landmarks is None:
        return None
    a = np.asarray(landmarks)
    if a.dtype.kind not in "iu":
        raise TypeError(f"landmarks must be integer vertex indices of shape (L, 2), got "
                        f"{a.dtype} values")
    if a.ndim != 2 or a.shape[1] != 2 or a.shape[0] == 0:
        raise ValueError(f"landmarks must have shape (L, 2): rows (source vertex, target "
                         f"vertex), L >= 1, got shape {a.shape}")
    check_vertex_indices("landmarks[:, 0]", a[:, 0], n_source)
    check_vertex_indices("landmarks[:, 1]", a[:, 1], n_target)
    return a.astype(np.int64)


def check_eigenbasis(name: str, basis: object, cls: type) -> Any:
    """Return ``basis`` if it is a ``cls`` (:class:`cshape.Eigenbasis`), else raise TypeError.

    The error names ``name`` and how to compute one.  The one check of an eigenbasis
    argument (signatures, maps, the viewer's explorers); the caller passes the class, which
    the spectrum stage defines on top of this module.
    """
    if not isinstance(basis, cls):
        raise TypeError(
            f"{name} must be a cshape.Eigenbasis, got {type(basis).__name__}; compute it with "
            "cshape.eigenbasis(mesh, N) (or build one from arrays: cshape.Eigenbasis(lam, "
            "phi, B))"
        )
    return basis

