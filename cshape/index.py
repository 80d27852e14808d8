""":class:`DescriptorIndex`: exact nearest-neighbour queries against a large database."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._checks import check_choice, check_descriptors, check_int, check_n_jobs
from .descriptors import Descriptor
from .descriptors.recipe import check_descriptor

#: The exact search methods of :class:`sklearn.neighbors.NearestNeighbors` (its spelling).
ALGORITHMS = ("auto", "brute", "kd_tree", "ball_tree")


class TableLike(Protocol):
    """What :meth:`DescriptorIndex.from_table` reads of a :class:`cshape.DescriptorTable`."""

    lam: NDArray[np.float64]
    areas: NDArray[np.float64]

    @property
    def N(self) -> int:
        """Number of eigenvalues of each row of ``lam``."""
        ...

    def described(self, *args: Any, **kwargs: Any
                  ) -> tuple[NDArray[Any], NDArray[np.int64]]:
        """Return the descriptors and the table rows they belong to (``X, rows``)."""
        ...



# --------------------------------------------------------------------------- index
class DescriptorIndex:
    """Exact nearest-neighbour search in a descriptor database (scikit-learn).

    Parameters
    ----------
    X : array_like, shape (n, d)
        The database, one descriptor per row; real or complex (complex rows are stored as
        ``[Re, Im]``, which keeps the Euclidean distances).
    algorithm : {'auto', 'brute', 'kd_tree', 'ball_tree'}, default='auto'
        Passed to :class:`sklearn.neighbors.NearestNeighbors` (scikit-learn's spelling);
        all are exact.  'auto' picks a k-d tree for short descriptors and a brute-force
        scan for long ones (timings in ``benchmarks/SCALE.md``, "Nearest-neighbour
        queries").
    n_jobs : int, optional
        Parallel queries (scikit-learn convention, -1 for all cores).

    Attributes
    ----------
    X_ : ndarray, shape (n, d')
        The stored (real) database.
    nn_ : sklearn.neighbors.NearestNeighbors
        The fitted index.
    descriptor_ : Descriptor or None
        How the rows were made from eigenvalues (a :class:`cshape.Descriptor`), when built
        with :meth:`from_table`; :meth:`query_spectra` describes queries with it, so a
        query can never use another transform.
    rows_ : ndarray of int, shape (n,)
        The table row of each database row (:meth:`from_table` leaves out the shapes the
        descriptor cannot describe); ``arange(n)`` for an index built from descriptors.

    Raises
    ------
    TypeError
        ``algorithm`` not a string, ``n_jobs`` not an integer, ``X`` not numeric.
    ValueError
        Unknown ``algorithm``, ``n_jobs`` 0 or below -1, ``X`` empty, not 2-D or not finite.

    Examples
    --------
    >>> import numpy as np
    >>> from cshape.index import DescriptorIndex
    >>> index = DescriptorIndex(np.array([[0.0, 0], [1, 0], [5, 5]]))
    >>> dist, ind = index.query([[0.9, 0.1]], k=2)
    >>> ind.tolist()
    [[1, 0]]
    """

    def __init__(self, X: ArrayLike, *, algorithm: str = "auto",
                 n_jobs: int | None = None) -> None:
        from sklearn.neighbors import NearestNeighbors

        self.algorithm = check_choice("algorithm", algorithm, ALGORITHMS)
        self.n_jobs = check_n_jobs(n_jobs)
        self._complex = np.iscomplexobj(np.asarray(X))
        self.X_ = check_descriptors(X, "X")
        if len(self.X_) == 0:
            raise ValueError("X is empty; the index needs at least one descriptor")
        self.nn_ = NearestNeighbors(algorithm=self.algorithm, n_jobs=self.n_jobs).fit(self.X_)
        self.descriptor_: Descriptor | None = None
        self.rows_ = np.arange(len(self.X_))

    @classmethod
    def from_table(cls, table: TableLike, descriptor: Descriptor | None = None, *,
                   algorithm: str = "auto", n_jobs: int | None = None) -> DescriptorIndex:
        """Build an index of a :class:`cshape.DescriptorTable`'s descriptors, with their recipe.

        Parameters
        ----------
        table : DescriptorTable
            The eigenvalues of the database's shapes (:func:`cshape.describe`).
        descriptor : Descriptor, optional
            Which descriptor (e.g. :data:`cshape.PAPER`); default: :data:`cshape.DEFAULT`
            at the table's ``N``.
        algorithm : {'auto', 'brute', 'kd_tree', 'ball_tree'}, default='auto'
            As for the constructor.
        n_jobs : int, optional
            As for the constructor.

        Returns
        -------
        DescriptorIndex
            With :attr:`descriptor_` set, for :meth:`query_spectra`, and :attr:`rows_`: the
            shapes the descriptor cannot describe (a mesh of many pieces with too few
            non-zero eigenvalues) are left out with a :class:`cshape.CShapeWarning` naming
            them.

        Raises
        ------
        TypeError
            ``descriptor`` not a :class:`cshape.Descriptor`.
        ValueError
            The descriptor can describe none of the shapes.
        """
        own = getattr(table, "descriptor", None)  # what the table compares, saved with it
        d = (own if descriptor is None and own is not None
             else check_descriptor("descriptor", descriptor, table.N))
        # warns about and leaves out what it cannot describe
        X, rows = table.described(d, stacklevel=4)
        if len(X) == 0:
            raise ValueError(
                f"{d.label} cannot describe any of the {len(table.lam)} shapes (see the "
                "warning); choose another descriptor or compute more eigenvalues")
        index = cls(X, algorithm=algorithm, n_jobs=n_jobs)
        index.descriptor_ = d
        index.rows_ = rows
        return index

    def query_spectra(self, lams: ArrayLike, areas: ArrayLike | None = None, k: int = 1, *,
                      zero_modes: ArrayLike | None = None,
                      names: Sequence[str] | None = None
                      ) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
        """Nearest database rows of shapes given by their eigenvalues.

        The queries are described exactly as the database was (:attr:`descriptor_`: kind,
        ``M``, ``N``, normalisation and transform).

        Parameters
        ----------
        lams : array_like, shape (q, n) or (n,)
            Ascending eigenvalues of each query shape, ``n >= N``.
        areas : array_like, shape (q,) or float, optional
            Surface areas (needed by the area normalisation).
        k : int, default=1
            Neighbours per query.
        zero_modes : array_like of int, shape (q,), optional
            Zero eigenvalues of each query (its component count); default: counted.
        names : sequence of str, optional
            Query names for the error message of a query that cannot be described.

        Returns
        -------
        dist, ind : ndarray, shape (q, k)
            As for :meth:`query`: ``ind`` are database rows (:attr:`rows_` maps them to
            the table's rows).
        """
        if self.descriptor_ is None:
            raise ValueError(
                "this index does not know how its descriptors were made; build it with "
                "DescriptorIndex.from_table(table, ...) to query by eigenvalues, or pass "
                "descriptors to query()"
            )
        L = np.asarray(lams, dtype=np.float64)
        if L.ndim == 1:
            L = L[None, :]
        a = None if areas is None else np.atleast_1d(np.asarray(areas, dtype=np.float64))
        zm = None if zero_modes is None else np.atleast_1d(np.asarray(zero_modes))
        Y = self.descriptor_.matrix(L, a, zero_modes=zm, names=names)
        return self.query(Y, k=k)

    def __len__(self) -> int:
        """Return the number of database descriptors."""
        return len(self.X_)

    def query(self, Y: ArrayLike | None = None, k: int = 1
              ) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
        """Return the ``k`` nearest database descriptors of each query.

        Parameters
        ----------
        Y : array_like, shape (q, d), optional
            Query descriptors, of the same kind and length as the database (a single
            descriptor of shape (d,) is accepted).  ``None`` queries the database with
            itself, each row's own entry excluded.
        k : int, default=1
            Number of neighbours; at most ``n`` (``n - 1`` when ``Y`` is None).

        Returns
        -------
        dist : ndarray, shape (q, k)
            Euclidean distances, ascending along each row.
        ind : ndarray of int, shape (q, k)
            Row indices into the database.
        """
        n = len(self.X_)
        limit = n - 1 if Y is None else n
        k = check_int("k", k, min=1)
        if k > limit:
            raise ValueError(
                f"k must be an integer in [1, {limit}] for a database of {n} descriptors"
                f"{' queried with itself' if Y is None else ''}, got {k!r}"
            )
        if Y is None:
            return self.nn_.kneighbors(None, n_neighbors=int(k))
        Yarr = np.asarray(Y)
        if Yarr.ndim == 1:
            Yarr = Yarr[None, :]
        if np.iscomplexobj(Yarr) != self._complex:
            raise ValueError(
                "Y and the database must both be real or both complex descriptors"
            )
        Q = check_descriptors(Yarr, "Y")
        if Q.shape[1] != self.X_.shape[1]:
            raise ValueError(
                f"Y has descriptors of length {Yarr.shape[1]} but the database has "
                f"{self.X_.shape[1] // (2 if self._complex else 1)}; use the same kind, M and N"
            )
        return self.nn_.kneighbors(Q, n_neighbors=int(k))
