"""Sparse Cholesky factorisations for the eigensolver (plumbing of its ``shift`` module).

The shift-invert eigensolver factorises ``S = K - sigma B`` once and then solves with ``S``
for blocks of right-hand sides.  Both steps are CHOLMOD (SuiteSparse's supernodal sparse
Cholesky).  Which build of CHOLMOD does the work decides most of the solve time:

``'cholmod'``
    the CHOLMOD library that the ``cvxopt`` wheel ships (a core dependency), whose BLAS
    calls bind to the wheel's OpenBLAS (a single-threaded build), called directly through
    :mod:`ctypes` with multi-right-hand-side solves: the fastest factorisation and solves
    of the three (measured figures: ``benchmarks/SCALE.md``, "The floor").  The GIL is
    released during both.  cvxopt's own Python interface is not used: it solves one
    right-hand side at a time.
``'cholespy'``
    the ``cholespy`` wheel (CHOLMOD with the reference BLAS), as LaPy uses it;
``'splu'``
    SciPy's SuperLU, if neither is importable.

``CSHAPE_CHOLESKY`` (environment) chooses one of these names; unset or ``'auto'`` takes the
first that works.  A backend is used only after it solved a small known system correctly
in this process (:func:`backend`), so a cvxopt build whose library cannot be found or
loaded (another platform's file layout, an incompatible CHOLMOD) falls back to
``cholespy`` instead of failing.  Each backend is deterministic: the same matrix gives the
same bits in every run and process; two backends agree to rounding (about 1e-13).
"""

from __future__ import annotations

import ctypes
import functools
import glob
import os
import sys
import weakref

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as spla

#: The backends, fastest first.
BACKENDS = ("cholmod", "cholespy", "splu")


class _Sparse(ctypes.Structure):
    """``cholmod_sparse`` (unchanged from CHOLMOD 1.x to 5.x)."""

    _fields_ = [("nrow", ctypes.c_size_t), ("ncol", ctypes.c_size_t),
                ("nzmax", ctypes.c_size_t), ("p", ctypes.c_void_p), ("i", ctypes.c_void_p),
                ("nz", ctypes.c_void_p), ("x", ctypes.c_void_p), ("z", ctypes.c_void_p),
                ("stype", ctypes.c_int), ("itype", ctypes.c_int), ("xtype", ctypes.c_int),
                ("dtype", ctypes.c_int), ("sorted", ctypes.c_int), ("packed", ctypes.c_int)]


class _Dense(ctypes.Structure):
    """``cholmod_dense``: a column-major (nrow, ncol) array with leading dimension ``d``."""

    _fields_ = [("nrow", ctypes.c_size_t), ("ncol", ctypes.c_size_t),
                ("nzmax", ctypes.c_size_t), ("d", ctypes.c_size_t), ("x", ctypes.c_void_p),
                ("z", ctypes.c_void_p), ("xtype", ctypes.c_int), ("dtype", ctypes.c_int)]


_DENSE_P = ctypes.POINTER(_Dense)
#: Bytes reserved for a ``cholmod_common`` (about 2 KB in CHOLMOD 3, 10 KB in CHOLMOD 5).
_COMMON_BYTES = 1 << 16
_CHOLMOD_REAL, _CHOLMOD_A = 1, 0


#: OpenBLAS kernels for CHOLMOD's BLAS on an Intel processor with AVX-512, where the cvxopt
#: wheel's OpenBLAS (0.3.15) would pick its SkylakeX kernels (:func:`openblas_coretype`;
#: the measurement behind the choice: ``benchmarks/SCALE.md``, "Against LaPy").
AVX512_CORETYPE = "Haswell"


def _cpu_flags(path="/proc/cpuinfo"):
    """Return the vendor and flags of the first processor in ``path`` (Linux), or ('', set())."""
    vendor, flags = "", set()
    try:
        with open(path, encoding="ascii", errors="replace") as f:
            for line in f:
                key, _, value = line.partition(":")
                if key.strip() == "vendor_id":
                    vendor = value.strip()
                elif key.strip() == "flags":
                    flags = set(value.split())
                    break
    except OSError:
        pass
    return vendor, flags


def openblas_coretype(environ=None, cpuinfo="/proc/cpuinfo"):
    """Return the OpenBLAS core type to load the cvxopt wheel's OpenBLAS with, or None.

    :data:`AVX512_CORETYPE` on an Intel processor with AVX-512 (and the AVX2 and FMA its
    kernels need); None elsewhere, and when ``OPENBLAS_CORETYPE`` is set in ``environ``
    (default: the process environment): the user's choice is kept.  The choice depends on
    the processor only, so every process on a machine gets the same bits.
    """
    environ = os.environ if environ is None else environ
    if environ.get("OPENBLAS_CORETYPE"):
        return None
    vendor, flags = _cpu_flags(cpuinfo)
    if vendor == "GenuineIntel" and {"avx512f", "avx2", "fma"} <= flags:
        return AVX512_CORETYPE
    return None


def _import_cvxopt():
    """Import cvxopt's CHOLMOD, its OpenBLAS loaded with :func:`openblas_coretype`.

    OpenBLAS reads ``OPENBLAS_CORETYPE`` once, when it is loaded: the variable is set for
    the import only (NumPy's and SciPy's OpenBLAS are loaded already and keep theirs; child
    processes do not inherit it).  If cvxopt was imported before, its kernels stay.  A
    program that imports cshape first and then calls cvxopt's own BLAS gets the same
    kernels (correct ones, whose rounding may differ from its SkylakeX ones).
    """
    coretype = None if "cvxopt" in sys.modules else openblas_coretype()
    if coretype is not None:
        os.environ["OPENBLAS_CORETYPE"] = coretype
    try:
        import cvxopt
        import cvxopt.cholmod  # noqa: F401 - loads the library's own dependencies (BLAS)
    finally:
        if coretype is not None:
            del os.environ["OPENBLAS_CORETYPE"]
    return cvxopt


@functools.cache
def _cholmod_library():
    """Return the CHOLMOD shared library of the cvxopt wheel, with ctypes signatures; or raise.

    Loaded once per process (the result is cached; a failure raises again).
    """
    cvxopt = _import_cvxopt()
    root = os.path.dirname(os.path.abspath(cvxopt.__file__))
    pattern = [os.path.join(root, "..", "cvxopt.libs", "libcholmod*.so*"),  # Linux wheels
               os.path.join(root, ".dylibs", "libcholmod*.dylib")]  # macOS wheels
    paths = sorted(p for pat in pattern for p in glob.glob(pat))
    if not paths:
        raise OSError(f"no CHOLMOD library in the cvxopt installation at {root}")
    lib = ctypes.CDLL(paths[0])
    version = (ctypes.c_int * 3)()
    lib.cholmod_version.argtypes = [ctypes.c_void_p]
    if lib.cholmod_version(version) < 3000:  # the structures above hold from CHOLMOD 3
        raise OSError(f"CHOLMOD {tuple(version)} in {paths[0]} is older than 3.0")
    lib.cholmod_start.argtypes = [ctypes.c_void_p]
    lib.cholmod_finish.argtypes = [ctypes.c_void_p]
    lib.cholmod_analyze.restype = ctypes.c_void_p
    lib.cholmod_analyze.argtypes = [ctypes.POINTER(_Sparse), ctypes.c_void_p]
    lib.cholmod_factorize.argtypes = [ctypes.POINTER(_Sparse), ctypes.c_void_p, ctypes.c_void_p]
    lib.cholmod_solve2.argtypes = [
        ctypes.c_int, ctypes.c_void_p, ctypes.POINTER(_Dense), ctypes.c_void_p,
        ctypes.POINTER(_DENSE_P), ctypes.c_void_p, ctypes.POINTER(_DENSE_P),
        ctypes.POINTER(_DENSE_P), ctypes.c_void_p,
    ]
    lib.cholmod_free_dense.argtypes = [ctypes.POINTER(_DENSE_P), ctypes.c_void_p]
    lib.cholmod_free_factor.argtypes = [ctypes.POINTER(ctypes.c_void_p), ctypes.c_void_p]
    return lib


def _start(lib, simplicial=False):
    """Return a ``cholmod_common`` set to always factorise ``L L^T`` (supernodal), printing nothing.

    With ``simplicial=True`` it is set to factorise ``L D L^T`` (simplicial, CHOLMOD's
    default final form), which also exists for a symmetric *indefinite* matrix whose
    leading blocks are all invertible (CHOLMOD does not pivot).

    ``cholmod_common`` is a large structure whose layout depends on the CHOLMOD version; its
    first fields are checked against CHOLMOD's documented defaults before two of them are
    set, and an unknown layout raises (the backend is then not used).  Supernodal ``L L^T``
    fails on a matrix that is not positive definite (CHOLMOD's simplicial ``L D L^T``, which
    it may choose for small matrices, would not), and the failure is reported by an
    exception instead of a message on standard output.
    """
    common = ctypes.create_string_buffer(_COMMON_BYTES)
    lib.cholmod_start(common)
    head = np.frombuffer(common, dtype=np.float64, count=6)
    flags = np.frombuffer(common, dtype=np.int32, count=38)
    relax = np.frombuffer(common, dtype=np.float64, count=3, offset=80)
    if not (np.array_equal(head[[0, 1, 2, 5]], [0.0, 1.2, 1.2, 40.0]) and flags[12] == 1
            and np.array_equal(relax, [0.8, 0.1, 0.05]) and flags[36] == 3):
        lib.cholmod_finish(common)
        raise OSError("unknown cholmod_common layout (CHOLMOD version)")
    flags[12] = 0 if simplicial else 2  # supernodal = CHOLMOD_SIMPLICIAL / _SUPERNODAL
    flags[36] = 0  # print = 0 (offset 144)
    return common


def _release(lib, common, factor, dense):
    """Free a factor, the solve workspaces and the common block (a finaliser)."""
    for d in dense:
        if d:
            lib.cholmod_free_dense(ctypes.byref(d), common)
    if factor.value:
        lib.cholmod_free_factor(ctypes.byref(factor), common)
    lib.cholmod_finish(common)


class _CholmodFactor:
    """CHOLMOD's factorisation of a symmetric matrix, through ctypes.

    Positive definite: supernodal ``L L^T``.  ``indefinite=True``: simplicial ``L D L^T``
    without pivoting, and :attr:`inertia`, the number of negative entries of ``D``, which by
    Sylvester's law of inertia is the number of negative eigenvalues of the matrix.
    """

    name = "cholmod"
    rhs_order = "F"
    inertia: int | None = None

    def __init__(self, lib, S, indefinite=False):
        n = S.shape[0]
        # The rows of the upper triangle in CSR are the columns of the lower one in CSC.
        U = sp.triu(S, format="csr")
        U.sort_indices()
        self._arrays = (U.indptr.astype(np.int32), U.indices.astype(np.int32),
                        np.ascontiguousarray(U.data, dtype=np.float64))
        ip, ix, x = self._arrays
        A = _Sparse(n, n, U.nnz, ip.ctypes.data, ix.ctypes.data, None, x.ctypes.data, None,
                    -1, 0, _CHOLMOD_REAL, 0, 1, 1)
        self.n, self._lib = n, lib
        self._common = _start(lib, simplicial=indefinite)
        self._factor = ctypes.c_void_p(lib.cholmod_analyze(ctypes.byref(A), self._common))
        self._work = [_DENSE_P(), _DENSE_P(), _DENSE_P()]  # X, Y, E of cholmod_solve2
        self._handles, self._pool = [], None  # for solve_split's other threads
        weakref.finalize(self, _release, lib, self._common, self._factor, self._work)
        if not self._factor.value:
            raise la.LinAlgError("CHOLMOD could not analyse the matrix (out of memory?)")
        lib.cholmod_factorize(ctypes.byref(A), self._factor, self._common)
        # cholmod_factor starts with (size_t n, size_t minor); minor < n: not positive definite
        minor = ctypes.cast(self._factor, ctypes.POINTER(ctypes.c_size_t))[1]
        if indefinite:
            if minor < n:
                raise la.LinAlgError("K - sigma B has a zero pivot at this shift (L D L^T)")
            self.inertia = self._ldl_inertia()
        elif minor < n:
            raise la.LinAlgError(
                f"the shifted matrix K - sigma B is not positive definite (its leading "
                f"{minor + 1} x {minor + 1} block is not): the shift sigma must lie below "
                "the smallest eigenvalue")

    def _ldl_inertia(self):
        """Count the negative entries of ``D`` of a simplicial ``L D L^T``.

        ``cholmod_factor`` (CHOLMOD 3 to 5) starts with ``n, minor, Perm, ColCount, IPerm,
        nzmax, p, i, x``: column ``j`` of a simplicial factor starts at ``x[p[j]]`` with its
        diagonal entry, ``D[j]`` for ``L D L^T`` (unit diagonal of ``L`` not stored).
        ``is_ll`` and ``is_super`` follow at bytes 180 and 184; a layout that does not say
        "simplicial L D L^T" there raises OSError (the caller then does without).
        """
        head = ctypes.cast(self._factor, ctypes.POINTER(ctypes.c_void_p))
        sizes = ctypes.cast(self._factor, ctypes.POINTER(ctypes.c_size_t))
        flags = ctypes.cast(self._factor, ctypes.POINTER(ctypes.c_int))
        is_ll, is_super, xtype = flags[45], flags[46], flags[49]
        if (is_ll, is_super, xtype) != (0, 0, _CHOLMOD_REAL) or not head[6] or not head[8]:
            raise OSError("unknown cholmod_factor layout (CHOLMOD version)")
        n, nzmax = self.n, int(sizes[5])
        p = np.ctypeslib.as_array(ctypes.cast(head[6], ctypes.POINTER(ctypes.c_int)),
                                  shape=(n + 1,))
        x = np.ctypeslib.as_array(ctypes.cast(head[8], ctypes.POINTER(ctypes.c_double)),
                                  shape=(nzmax,))
        if p[n] > nzmax or p[0] != 0:
            raise OSError("unknown cholmod_factor layout (CHOLMOD version)")
        return int(np.count_nonzero(x[p[:-1]] < 0))

    def solve(self, X):
        """``S^{-1} X`` for X of shape (n,) or (n, b); returns a new array of X's shape."""
        return self._solve(X, self._common, self._work)

    def solve_split(self, X, parts=2, threads=None):
        """:meth:`solve` with the columns of X in ``parts`` groups solved at once (threads).

        Deterministic, and the same bits as :meth:`solve` when every group has a multiple
        of 8 columns (CHOLMOD solves each column of a block with the same BLAS kernels:
        checked for 16 columns in two groups of 8, the eigensolver's use, on OpenBLAS's
        SkylakeX, Haswell, Zen, SandyBridge, Nehalem and Prescott kernels; groups of 6 can
        differ in the last bit).  A solve reads the whole factor once for all its columns:
        two groups at once may gain where the memory keeps two cores fed.  With
        ``threads=1`` all columns are solved in one call (faster than the groups in turn);
        default: the groups at once.
        """
        X = np.asarray(X, dtype=np.float64)
        if X.ndim != 2 or parts < 2 or X.shape[1] < 2 * parts \
                or (threads is not None and threads <= 1):
            return self.solve(X)
        out = np.empty(X.shape)  # each group's solution written into its columns
        edges = np.linspace(0, X.shape[1], parts + 1).astype(int)
        if self._pool is None or len(self._handles) < parts - 1:
            from concurrent.futures import ThreadPoolExecutor

            while len(self._handles) < parts - 1:  # a common and workspaces per thread
                common, work = _start(self._lib), [_DENSE_P(), _DENSE_P(), _DENSE_P()]
                weakref.finalize(self, _release, self._lib, common, ctypes.c_void_p(), work)
                self._handles.append((common, work))
            if self._pool is not None:  # too few workers for this many groups
                self._pool.shutdown()
            self._pool = ThreadPoolExecutor(parts - 1)
            weakref.finalize(self, self._pool.shutdown)
        futures = [self._pool.submit(self._solve, X[:, a:b], *handle, out[:, a:b])
                   for (a, b), handle in zip(zip(edges[1:-1], edges[2:], strict=True),
                                             self._handles, strict=False)]  # handles >= groups
        self._solve(X[:, : edges[1]], self._common, self._work, out[:, : edges[1]])
        for f in futures:
            f.result()
        return out

    def _solve(self, X, common, work, out=None):
        """``S^{-1} X`` with the given CHOLMOD workspaces, into ``out`` if given (n, b)."""
        X = np.asarray(X, dtype=np.float64)
        cols = np.asfortranarray(X.reshape(self.n, -1))
        b = cols.shape[1]
        rhs = _Dense(self.n, b, self.n * b, self.n, cols.ctypes.data, None, _CHOLMOD_REAL, 0)
        X_out, Y, E = work
        ok = self._lib.cholmod_solve2(_CHOLMOD_A, self._factor, ctypes.byref(rhs), None,
                                      ctypes.byref(X_out), None, ctypes.byref(Y),
                                      ctypes.byref(E), common)
        if not ok or not X_out:  # pragma: no cover - out of memory inside CHOLMOD
            raise MemoryError("CHOLMOD could not allocate the solution of a solve")
        data = ctypes.cast(X_out.contents.x, ctypes.POINTER(ctypes.c_double))
        # a row-major copy of CHOLMOD's column-major buffer (reused by the next solve;
        # np.array always copies, where ascontiguousarray returned the buffer itself for
        # one column, which the next solve then overwrote)
        result = np.ctypeslib.as_array(data, shape=(b, self.n)).T
        if out is not None:
            out[...] = result
            return out
        return np.array(result, order="C").reshape(X.shape)


class _CholespyFactor:
    """The ``cholespy`` wheel's CHOLMOD (reference BLAS; holds the GIL)."""

    name = "cholespy"
    rhs_order = "C"

    def __init__(self, S):
        import cholespy

        self.n = S.shape[0]
        # CSR input: cholespy copies it (a CSC input would be reallocated in place).
        self._solver = cholespy.CholeskySolverD(
            self.n, S.indptr.astype(np.int32), S.indices.astype(np.int32),
            S.data.astype(np.float64), cholespy.MatrixType.CSR,
        )

    def solve_split(self, X, parts=2, threads=None):
        """:meth:`solve` (this backend solves in one thread: the same bits with any threads)."""
        return self.solve(X)

    def solve(self, X):
        X = np.ascontiguousarray(X, dtype=np.float64)
        out = np.empty_like(X)
        self._solver.solve(X, out)
        return out


class _SpluFactor:
    """SciPy's SuperLU (no Cholesky; the last resort)."""

    name = "splu"
    rhs_order = "C"

    def __init__(self, S):
        self.n = S.shape[0]
        self._lu = spla.splu(S.tocsc())

    def solve_split(self, X, parts=2, threads=None):
        """:meth:`solve` (this backend solves in one thread: the same bits with any threads)."""
        return self.solve(X)

    def solve(self, X):
        return np.ascontiguousarray(self._lu.solve(np.asarray(X, dtype=np.float64)))


_STATUS: dict[str, tuple[bool, str]] = {}  # backend name -> (usable, reason), once per process


def _make(name, S):
    if name == "cholmod":
        return _CholmodFactor(_cholmod_library(), S)
    if name == "cholespy":
        return _CholespyFactor(S)
    return _SpluFactor(S)


def _probe(name):
    """Whether backend ``name`` loads and solves a small known system correctly here."""
    if name in _STATUS:
        return _STATUS[name]
    try:
        # 1-D Laplacian + identity (30 unknowns): exact inverse known from dense LAPACK
        n = 30
        S = sp.diags([-np.ones(n - 1), 3.0 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1],
                     format="csr")
        X = np.arange(2.0 * n).reshape(n, 2)
        err = np.abs(_make(name, S).solve(X) - np.linalg.solve(S.toarray(), X)).max()
        status = (bool(err < 1e-10), "" if err < 1e-10 else f"wrong solve (error {err:.1e})")
    except (ImportError, OSError, AttributeError, ValueError, la.LinAlgError) as exc:
        status = (False, f"{type(exc).__name__}: {exc}")
    _STATUS[name] = status
    return status


def backend():
    """Return the name of the Cholesky backend this process uses (see the module docstring).

    Returns
    -------
    str
        One of :data:`BACKENDS`.

    Raises
    ------
    ValueError
        If ``CSHAPE_CHOLESKY`` names an unknown backend, or one that does not work here
        (with the reason).
    """
    wanted = os.environ.get("CSHAPE_CHOLESKY", "").strip().lower() or "auto"
    if wanted == "auto":
        for name in BACKENDS:
            if _probe(name)[0]:
                return name
    if wanted not in BACKENDS:
        raise ValueError(f"CSHAPE_CHOLESKY must be one of auto, {', '.join(BACKENDS)}; "
                         f"got {wanted!r}")
    ok, reason = _probe(wanted)
    if not ok:
        raise ValueError(f"CSHAPE_CHOLESKY={wanted} does not work here ({reason}); unset it "
                         "to use the fastest backend that does")
    return wanted


def factorize(S, indefinite=False):
    """Factorise a symmetric positive definite sparse matrix with :func:`backend`.

    Parameters
    ----------
    S : scipy.sparse matrix, shape (n, n)
        Symmetric positive definite (both triangles stored).
    indefinite : bool, default=False
        ``S`` may be indefinite: factorise ``L D L^T`` (CHOLMOD, simplicial, no pivoting)
        and count its negative eigenvalues (the factor's ``inertia``).  Only the
        ``'cholmod'`` backend can: with another one this raises ValueError.

    Returns
    -------
    factor
        An object with ``solve(X) -> S^{-1} X`` for X of shape (n,) or (n, b) (a new
        row-major array of the same shape), ``name`` (the backend) and ``rhs_order``, the
        memory order of X that needs no copy ('F' for CHOLMOD, 'C' otherwise).

    Raises
    ------
    scipy.linalg.LinAlgError
        If ``S`` is not positive definite (CHOLMOD backend), or with ``indefinite=True``
        has a zero pivot.
    ValueError
        With ``indefinite=True`` if the backend is not ``'cholmod'``.
    OSError
        With ``indefinite=True`` if the CHOLMOD factor's layout is not the known one.
    """
    S = sp.csr_matrix(S)
    S.sum_duplicates()
    name = backend()
    if indefinite:
        if name != "cholmod":
            raise ValueError(f"the {name!r} backend has no indefinite factorisation")
        return _CholmodFactor(_cholmod_library(), S, indefinite=True)
    return _make(name, S)
