"""The M sweep: how the crop half-width ``M`` changes the cShape-DNA (Section 3.2, Fig. 6).

The logic is a chain of pure functions on eigenvalues, which the tests call directly:

* :class:`MSweep` holds the eigenvalues of a collection (computed **once**, e.g. by
  :func:`cshape.batch.describe`) and caches the stages that depend only on ``N``, the
  normalisation and the transform: the normalised and Weyl-subtracted Shape-DNA (Eq. 8), its
  full shifted DFT (Eq. 9), the scaled Shape-DNA distance matrix (Fig. 3a) and its MDS
  embedding.  A new ``M`` reruns only the cheap stages: crop (Eq. 10), reconstruction,
  distances, difference statistics and MDS.  ``transform='log-weyl'`` / ``'log-weyl-dct'``
  sweep the extensions of :func:`cshape.compact_shape_dna` instead (the log-Weyl ratio, its
  DFT or DCT) against the same Shape-DNA reference.
* :func:`sweep_state` is the one-call form: ``MSweep(...).state(M, N=N)``.
* :func:`m_sweep_widget` is a thin ipywidgets shell over :class:`MSweep` and
  :func:`cshape.plots.plot_m_sweep`; it returns the widget and never displays it.

Example
-------
>>> import cshape, numpy as np
>>> from cshape import shapes
>>> from cshape.plots import widgets
>>> meshes = {"sphere": shapes.icosphere(2), "cube": shapes.cube(4)}
>>> lams = [cshape.shape_dna(m, N=30) for m in meshes.values()]
>>> st = widgets.sweep_state(lams, [m.area for m in meshes.values()], ["s", "c"], M=4, N=30)
>>> st.coefficients.shape, st.D.shape
((2, 9), (2, 2))
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from .._checks import check_choice, check_int, require_extra
from ..compare import distance_matrix, mds_embedding, retrieval_scores, scale_255
from ..descriptors import log_weyl_ratio, normalize, weyl_subtract
from ..descriptors.formulas import NORMALIZATIONS, TRANSFORMS

if TYPE_CHECKING:
    from collections.abc import Iterable

    from matplotlib.figure import Figure
    from numpy.typing import ArrayLike

    from ..batch import DescriptorTable

__all__ = [
    "MSweep",
    "m_sweep_widget",
]


@dataclass
class SweepState:
    """Everything the M-sweep shows for one ``(M, N, normalization, transform)``.

    Parameters
    ----------
    M, N : int
        Crop half-width and Shape-DNA length (``2M+1 <= L``, the sequence length below).
    normalization : str
        See :func:`cshape.normalize`.
    names, labels : list of str, length p
        Name and class of each shape.
    lam_norm : ndarray, shape (p, N)
        Normalised Shape-DNAs.
    lam_prime : ndarray, shape (p, L)
        The sequence that is transformed: ``lam'`` minus the Weyl line, Eq. (8), ``L = N``
        (``transform='weyl'``), or the log-Weyl ratio ``r_1..r_{N-1}``, ``L = N-1``.
    spectra : ndarray, shape (p, L)
        Shifted DFT of ``lam_prime`` (Eq. 9), zero frequency at column ``L // 2`` (complex),
        or its orthonormal DCT-II (real, ``'log-weyl-dct'``).
    coefficients : ndarray, shape (p, 2M+1)
        The cShape-DNAs (Eq. 10), frequencies ``-M..M`` (complex), or the first ``2M+1``
        DCT coefficients (real).
    reconstruction : ndarray, shape (p, L)
        ``lam_prime`` rebuilt from the ``2M+1`` coefficients (the others set to 0).
    reconstruction_error : ndarray, shape (p,)
        ``||reconstruction - lam_prime|| / ||lam_prime||`` of each shape.
    D_ref : ndarray, shape (p, p)
        Scaled (``[0, 255]``) distances of the normalised Shape-DNAs (Fig. 3a).
    D : ndarray, shape (p, p)
        Scaled distances of the cShape-DNAs (Fig. 6 a-d).
    difference : ndarray, shape (p, p)
        ``|D_ref - D|`` (Fig. 6 e-h).
    mean, std : float
        Mean and (population) standard deviation of ``difference``, as the paper quotes.
    mds : ndarray, shape (p, 2) or None
        MDS coordinates of ``D``, rotated onto the MDS of ``D_ref`` (orthogonal Procrustes)
        so that the picture does not flip from one ``M`` to the next; None for ``p < 3``.
    retrieval : dict or None
        Nearest-neighbour and first-tier rates of the cShape-DNA (``nn``, ``ft``) and of the
        Shape-DNA (``nn_ref``, ``ft_ref``); None without at least one class of two shapes.
    transform : str
        See :func:`cshape.compact_shape_dna`; ``'weyl'`` is the paper's.
    """

    M: int
    N: int
    normalization: str
    names: list[str]
    labels: list[str]
    lam_norm: np.ndarray
    lam_prime: np.ndarray
    spectra: np.ndarray
    coefficients: np.ndarray
    reconstruction: np.ndarray
    reconstruction_error: np.ndarray
    D_ref: np.ndarray
    D: np.ndarray
    difference: np.ndarray
    mean: float
    std: float
    mds: np.ndarray | None = None
    retrieval: dict[str, float] | None = field(default=None)
    transform: str = "weyl"

    @property
    def size(self) -> int:
        """Descriptor size ``2M+1``."""
        return 2 * self.M + 1

    def summary(self) -> str:
        """Return one line of statistics, as the widget prints it.

        Returns
        -------
        str
            ``M``, ``2M+1`` and ``N``, the mean and standard deviation of
            :attr:`difference` and, when known, the retrieval rates.
        """
        tr = "" if self.transform == "weyl" else f" ({self.transform})"
        s = (f"M = {self.M}{tr}: 2M+1 = {self.size} values instead of N = {self.N}; difference "
             f"from Shape-DNA: mean {self.mean:.2f}, std {self.std:.2f} (scaled to [0, 255])")
        if self.retrieval:
            r = self.retrieval
            s += (f"; nearest neighbour {r['nn']:.2f} (Shape-DNA {r['nn_ref']:.2f}), "
                  f"first tier {r['ft']:.2f} (Shape-DNA {r['ft_ref']:.2f})")
        return s


def max_M(N: int, transform: str = "weyl") -> int:
    """Return the largest ``M`` for a Shape-DNA of length ``N``.

    ``(N-1)//2``, or ``(N-2)//2`` for the log-Weyl transforms (their sequence has ``N-1``
    values: ``lam_0`` has no logarithm).

    Parameters
    ----------
    N : int
        Shape-DNA length.
    transform : {'weyl', 'log-weyl', 'log-weyl-dct'}, default='weyl'
        See :func:`cshape.compact_shape_dna`.

    Returns
    -------
    int
        The largest crop half-width.
    """
    transform = check_choice("transform", transform, TRANSFORMS)
    return (int(N) - 1) // 2 if transform == "weyl" else (int(N) - 2) // 2


def clamp_M(M: float, N: int, transform: str = "weyl") -> int:
    """Clamp ``M`` to the valid range ``[0, max_M(N, transform)]``.

    Parameters
    ----------
    M : float
        A slider value.
    N : int
        Shape-DNA length.
    transform : {'weyl', 'log-weyl', 'log-weyl-dct'}, default='weyl'
        See :func:`cshape.compact_shape_dna`.

    Returns
    -------
    int
        ``int(M)`` (truncated), clamped to the range.
    """
    return int(min(max(int(M), 0), max_M(N, transform)))


def _procrustes(Y: np.ndarray, Y_ref: np.ndarray) -> np.ndarray:
    """Rotate / reflect centred ``Y`` onto centred ``Y_ref`` (orthogonal Procrustes)."""
    A = Y - Y.mean(axis=0)
    B = Y_ref - Y_ref.mean(axis=0)
    U, _, Vt = np.linalg.svd(A.T @ B)
    return A @ (U @ Vt)


class MSweep:
    """Eigenvalues of a collection, with the stages of the M sweep cached.

    Parameters
    ----------
    lams : array_like, shape (p, n) or sequence of p 1-D arrays
        Ascending eigenvalues of each shape (computed once); every row needs at least
        ``N`` values for the ``N`` asked later.
    areas : array_like, shape (p,)
        Surface areas (for ``normalization='area'``).
    names : sequence of str, optional
        Default ``'0', '1', ...``.
    labels : sequence of str, optional
        Class labels (colours of the MDS plot, retrieval rates); default: all different.
    normalization : {'area', 'fiedler', 'weyl'}, default='area'
    mds : bool, default=True
        Compute the MDS embedding (the slowest of the cheap stages).
    random_state : int, default=0
        Seed of the MDS iterations.
    transform : {'weyl', 'log-weyl', 'log-weyl-dct'}, default='weyl'
        Default transform of :meth:`state` (see :func:`cshape.compact_shape_dna`).

    Attributes
    ----------
    N_max : int
        The largest ``N`` available (the shortest row of ``lams``).
    """

    def __init__(self, lams: Iterable[ArrayLike], areas: ArrayLike,
                 names: Iterable[object] | None = None, labels: Iterable[object] | None = None,
                 *, normalization: str = "area", mds: bool = True, random_state: int | None = 0,
                 transform: str = "weyl") -> None:
        rows = list(lams)
        if len(rows) == 0:
            raise ValueError("lams is empty; pass the eigenvalues of at least two shapes")
        rows = [np.asarray(r, dtype=np.float64).reshape(-1) for r in rows]
        p = len(rows)
        if p < 2:
            raise ValueError(f"lams has {p} shape; the sweep compares at least two shapes")
        self.N_max = min(len(r) for r in rows)
        if self.N_max < 3:
            raise ValueError(
                f"every shape needs at least 3 eigenvalues, the shortest row has {self.N_max}"
            )
        self.lams = np.vstack([r[: self.N_max] for r in rows])
        self.areas = np.asarray(areas, dtype=np.float64).reshape(-1)
        if len(self.areas) != p:
            raise ValueError(f"areas has {len(self.areas)} entries but lams has {p} rows")
        self.names = [str(i) for i in range(p)] if names is None else [str(n) for n in names]
        if len(self.names) != p:
            raise ValueError(f"names has {len(self.names)} entries but lams has {p} rows")
        self.labels = list(self.names) if labels is None else [str(x) for x in labels]
        if len(self.labels) != p:
            raise ValueError(f"labels has {len(self.labels)} entries but lams has {p} rows")
        self.normalization = self._check_norm(normalization)
        self.transform = self._check_transform(transform)
        self.mds = bool(mds)
        self.random_state = random_state
        self._ref: dict[tuple[int, str], dict[str, Any]] = {}
        self._base: dict[tuple[int, str, str], dict[str, Any]] = {}
        self._states: dict[tuple[int, int, str, str], SweepState] = {}

    @classmethod
    def from_table(cls, table: DescriptorTable, **kwargs: Any) -> MSweep:
        """Make an :class:`MSweep` over a :class:`cshape.batch.DescriptorTable`.

        Parameters
        ----------
        table : DescriptorTable
            Eigenvalues, areas, names and labels of the collection.
        **kwargs
            Further arguments of :class:`MSweep`.

        Returns
        -------
        MSweep
            The sweep of the table's shapes.
        """
        labels = table.labels if any(table.labels) else None
        return cls(table.lam, table.areas, table.names, labels, **kwargs)

    @staticmethod
    def _check_norm(normalization: str) -> str:
        return check_choice("normalization", normalization, NORMALIZATIONS)

    @staticmethod
    def _check_transform(transform: str) -> str:
        return check_choice("transform", transform, TRANSFORMS)

    def _check_N(self, N: int | None) -> int:
        if N is None:
            return self.N_max
        N = check_int("N", N)
        if not 3 <= N <= self.N_max:
            raise ValueError(
                f"N must be in [3, {self.N_max}] (the eigenvalues computed per shape), got {N}; "
                "compute more eigenvalues for a larger N"
            )
        return int(N)

    def base(self, N: int | None = None, normalization: str | None = None,
             transform: str | None = None) -> dict[str, Any]:
        """Return the stages that do not depend on ``M``.

        They are cached per ``N``, normalisation and transform; the Shape-DNA reference and
        its MDS are shared by the transforms.

        Parameters
        ----------
        N : int, optional
            Shape-DNA length, default :attr:`N_max`.
        normalization : {'area', 'fiedler', 'weyl'}, optional
            Default: the sweep's.
        transform : {'weyl', 'log-weyl', 'log-weyl-dct'}, optional
            Default: the sweep's.

        Returns
        -------
        dict
            ``lam_norm``, ``D_ref`` and ``lam_prime``, ``spectra`` as in
            :class:`SweepState`, and ``Y_ref``, the MDS of ``D_ref``.
        """
        N = self._check_N(N)
        norm = self.normalization if normalization is None else self._check_norm(normalization)
        tr = self.transform if transform is None else self._check_transform(transform)
        ref_key = (N, norm)
        if ref_key not in self._ref:
            lam_norm = np.vstack([normalize(r[:N], a, normalization=norm)
                                  for r, a in zip(self.lams, self.areas, strict=True)])
            D_ref = scale_255(distance_matrix(lam_norm))
            self._ref[ref_key] = {"lam_norm": lam_norm, "D_ref": D_ref,
                                  "Y_ref": self._embed(D_ref)}
        key = (N, norm, tr)
        if key not in self._base:
            b = self._ref[ref_key]
            if tr == "weyl":
                seq = np.vstack([weyl_subtract(r) for r in b["lam_norm"]])  # Eq. (8)
            else:
                seq = np.vstack([log_weyl_ratio(r) for r in b["lam_norm"]])
            if tr == "log-weyl-dct":
                from scipy.fft import dct

                spectra = dct(seq, type=2, norm="ortho", axis=1)
            else:
                spectra = np.fft.fftshift(np.fft.fft(seq, axis=1), axes=1)  # Eq. (9)
            self._base[key] = {**b, "lam_prime": seq, "spectra": spectra}
        return self._base[key]

    def _embed(self, D: np.ndarray) -> np.ndarray | None:
        if not self.mds or len(D) < 3:
            return None
        return mds_embedding(D, random_state=self.random_state)

    def _retrieval(self, D: np.ndarray, D_ref: np.ndarray) -> dict[str, float] | None:
        counts = {lab: self.labels.count(lab) for lab in self.labels}
        if max(counts.values()) < 2:
            return None
        r, r_ref = retrieval_scores(D, self.labels), retrieval_scores(D_ref, self.labels)
        return {"nn": r["nn"], "ft": r["ft"], "nn_ref": r_ref["nn"], "ft_ref": r_ref["ft"]}

    def state(self, M: int, *, N: int | None = None, normalization: str | None = None,
              transform: str | None = None) -> SweepState:
        """Return the sweep at one ``M`` (cached).

        Parameters
        ----------
        M : int
            Crop half-width (use :func:`clamp_M` to clamp a slider value).
        N : int, optional
            Shape-DNA length, default :attr:`N_max`.
        normalization : {'area', 'fiedler', 'weyl'}, optional
            Default: the sweep's.
        transform : {'weyl', 'log-weyl', 'log-weyl-dct'}, optional
            Default: the sweep's.

        Returns
        -------
        SweepState
            Every stage at this ``M``.

        Raises
        ------
        ValueError
            Unless ``0 <= M <= max_M(N, transform)``.
        """
        N = self._check_N(N)
        norm = self.normalization if normalization is None else self._check_norm(normalization)
        tr = self.transform if transform is None else self._check_transform(transform)
        M = check_int("M", M)
        top = max_M(N, tr)
        if not 0 <= M <= top:
            bound = "2M+1 <= N" if tr == "weyl" else "2M+1 <= N-1"
            raise ValueError(
                f"M must be in [0, {top}] for N = {N} ({bound}), got {M}; "
                "clamp it with cshape.plots.widgets.clamp_M(M, N, transform)"
            )
        M = int(M)
        key = (M, N, norm, tr)
        if key in self._states:
            return self._states[key]
        b = self.base(N, norm, tr)
        kept = np.zeros_like(b["spectra"])
        if tr == "log-weyl-dct":
            from scipy.fft import idct

            coeffs = b["spectra"][:, : 2 * M + 1].copy()
            kept[:, : 2 * M + 1] = coeffs
            rec = idct(kept, type=2, norm="ortho", axis=1)
        else:
            c = b["spectra"].shape[1] // 2
            coeffs = b["spectra"][:, c - M: c + M + 1].copy()  # Eq. (10)
            kept[:, c - M: c + M + 1] = coeffs
            rec = np.fft.ifft(np.fft.ifftshift(kept, axes=1), axis=1).real
        lp = b["lam_prime"]
        err = np.linalg.norm(rec - lp, axis=1) / np.maximum(np.linalg.norm(lp, axis=1), 1e-300)
        D = scale_255(distance_matrix(coeffs))
        diff = np.abs(b["D_ref"] - D)
        Y = self._embed(D)
        if Y is not None and b["Y_ref"] is not None:
            Y = _procrustes(Y, b["Y_ref"])
        st = SweepState(
            M=M, N=N, normalization=norm, names=list(self.names), labels=list(self.labels),
            lam_norm=b["lam_norm"], lam_prime=lp, spectra=b["spectra"], coefficients=coeffs,
            reconstruction=rec, reconstruction_error=err, D_ref=b["D_ref"], D=D,
            difference=diff, mean=float(diff.mean()), std=float(diff.std()), mds=Y,
            retrieval=self._retrieval(D, b["D_ref"]), transform=tr,
        )
        if len(self._states) > 256:
            self._states.clear()
        self._states[key] = st
        return st


def sweep_state(lams: Iterable[ArrayLike], areas: ArrayLike, labels: Iterable[object] | None = None,
                *, N: int | None = None, M: int = 16, normalization: str = "area",
                names: Iterable[object] | None = None, mds: bool = True,
                random_state: int | None = 0, transform: str = "weyl") -> SweepState:
    """The M sweep at one ``M`` in one call: crop, reconstruction, distances, statistics, MDS.

    Parameters
    ----------
    lams : array_like, shape (p, n) or sequence of p 1-D arrays
        Ascending eigenvalues of each shape.
    areas : array_like, shape (p,)
        Surface areas (for the area normalisation).
    labels : sequence of str, optional
        Class labels.
    N : int, optional
        Shape-DNA length (default: the shortest row of ``lams``).
    M : int, default=16
        Crop half-width, ``0 <= M <= (N-1)//2``.
    normalization : {'area', 'fiedler', 'weyl'}, default='area'
    names : sequence of str, optional
        Shape names.
    mds : bool, default=True
        Compute the MDS coordinates of the cShape-DNA distances.
    random_state : int, default=0
        Seed; the same seed gives the same result.
    transform : {'weyl', 'log-weyl', 'log-weyl-dct'}, default='weyl'
        See :func:`cshape.compact_shape_dna`.

    Returns
    -------
    SweepState
        Every stage at this ``M``.

    See Also
    --------
    MSweep : The same with the ``M``-independent stages cached, for many ``M``.
    """
    sweep = MSweep(lams, areas, names, labels, normalization=normalization, mds=mds,
                   random_state=random_state, transform=transform)
    return sweep.state(M, N=N)


# ------------------------------------------------------------------------------ widget
def _png(fig: Figure, dpi: float) -> bytes:
    import io

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    return buf.getvalue()


def _as_sweeps(data: Any, normalization: str) -> dict[str, MSweep]:
    """{collection name: MSweep} from a table, a mapping of tables, or an MSweep."""
    from ..batch import DescriptorTable

    def one(x: object) -> MSweep:
        if isinstance(x, MSweep):
            return x
        if isinstance(x, DescriptorTable):
            return MSweep.from_table(x, normalization=normalization)
        raise TypeError(
            "data must be a cshape.batch.DescriptorTable (from cshape.batch.describe), an "
            f"MSweep, or a dict {{name: DescriptorTable}}; got {type(x).__name__}"
        )

    if isinstance(data, dict):
        if not data:
            raise ValueError("data is an empty dict; pass at least one collection")
        return {str(k): one(v) for k, v in data.items()}
    return {"collection": one(data)}


_VBox: Any
try:  # the widget class needs ipywidgets (the 'plots' extra); the pure functions do not
    import ipywidgets as _w

    _VBox = _w.VBox
except ImportError:  # pragma: no cover
    _w = None
    _VBox = object


class MSweepWidget(_VBox):
    """The M-sweep widget (an ``ipywidgets.VBox``); build it with :func:`m_sweep_widget`.

    Parameters
    ----------
    sweeps : dict of str to MSweep
        One sweep per collection, by name.
    M : int, default=16
        Initial crop half-width (clamped).
    N : int, optional
        Initial Shape-DNA length (default: all eigenvalues of the first collection).
    normalization : {'area', 'fiedler', 'weyl'}, default='area'
        Initial normalisation.
    figsize : (float, float), default=(12.0, 7.0)
        Size of the figure, in inches.
    dpi : float, default=72
        Resolution of the PNG image.
    transform : {'weyl', 'log-weyl', 'log-weyl-dct'}, default='weyl'
        Initial position of the transform toggle.

    Attributes
    ----------
    sweeps : dict of str to MSweep
        One cached sweep per collection.
    controls : dict of str to ipywidgets.Widget
        ``'collection'``, ``'N'``, ``'M'``, ``'normalization'``, ``'transform'`` (a toggle:
        the paper's ``'weyl'`` or the log-Weyl extensions), ``'shape'``.
    image : ipywidgets.Image
        The figure of :func:`cshape.plots.plot_m_sweep` as PNG.
    stats : ipywidgets.HTML
        :meth:`SweepState.summary` of the current state.
    state : SweepState
        The state on screen.
    """

    def __init__(self, sweeps: dict[str, MSweep], *, M: int = 16, N: int | None = None,
                 normalization: str = "area", figsize: tuple[float, float] = (12.0, 7.0),
                 dpi: float = 72, transform: str = "weyl") -> None:
        self.sweeps = sweeps
        self._figsize = figsize
        self._dpi = dpi
        self._busy = False
        first = next(iter(sweeps.values()))
        N0 = first.N_max if N is None else min(max(int(N), 3), first.N_max)
        tr = MSweep._check_transform(transform)
        style = {"description_width": "initial"}
        ui: Any = _w  # ipywidgets (m_sweep_widget checks that it is installed)
        coll = ui.Dropdown(options=list(sweeps), value=next(iter(sweeps)),
                           description="collection", style=style,
                           layout=ui.Layout(display="" if len(sweeps) > 1 else "none"))
        wN = ui.IntSlider(value=N0, min=3, max=first.N_max, description="N",
                          continuous_update=False, style=style)
        wM = ui.IntSlider(value=clamp_M(M, N0, tr), min=0, max=max_M(N0, tr), description="M",
                          continuous_update=False, style=style)
        wt = ui.ToggleButtons(options=list(TRANSFORMS), value=tr, description="transform",
                              style=style,
                              tooltips=["the paper: DFT of lam' (Eq. 8-10)",
                                        "DFT of the log-Weyl ratio r_i = log(lam_i / 4 pi i)",
                                        "DCT of the log-Weyl ratio"])
        wn = ui.Dropdown(options=list(NORMALIZATIONS),
                         value=MSweep._check_norm(normalization), description="normalisation",
                         style=style)
        ws = ui.Dropdown(options=[(n, i) for i, n in enumerate(first.names)], value=0,
                         description="shape", style=style)
        self.controls = {"collection": coll, "N": wN, "M": wM, "normalization": wn,
                         "transform": wt, "shape": ws}
        self.image = ui.Image(format="png", layout=ui.Layout(max_width="100%"))
        self.stats = ui.HTML()
        self.stats.add_class("cshape-msweep-stats")
        self.image.add_class("cshape-msweep-plot")
        box = ui.HBox([coll, wN, wM]), ui.HBox([wn, ws]), wt
        super().__init__([*box, self.stats, self.image])
        self.add_class("cshape-msweep")
        coll.observe(self._on_collection, names="value")
        for w in (wN, wM, wn, wt, ws):
            w.observe(self._on_change, names="value")
        self.refresh()

    @property
    def sweep(self) -> MSweep:
        """The sweep of the selected collection."""
        return self.sweeps[self.controls["collection"].value]

    def _on_collection(self, change: dict[str, Any]) -> None:
        sw = self.sweep
        c = self.controls
        self._busy = True
        try:
            c["N"].max = sw.N_max
            c["N"].value = min(c["N"].value, sw.N_max)
            c["M"].max = max_M(c["N"].value, c["transform"].value)
            c["shape"].options = [(n, i) for i, n in enumerate(sw.names)]
            c["shape"].value = 0
        finally:
            self._busy = False
        self.refresh()

    def _on_change(self, change: dict[str, Any]) -> None:
        if self._busy:
            return
        c = self.controls
        if change["owner"] is c["N"] or change["owner"] is c["transform"]:
            self._busy = True
            try:  # clamp M to [0, (N-1)//2], or [0, (N-2)//2] for the log-Weyl transforms
                top = max_M(c["N"].value, c["transform"].value)
                c["M"].value = clamp_M(c["M"].value, c["N"].value, c["transform"].value)
                c["M"].max = top
            finally:
                self._busy = False
        self.refresh()

    def static_html(self) -> str:
        """Return the widget's current picture and statistics as plain HTML.

        What a page without a kernel shows in the widget's place.

        Returns
        -------
        str
            A ``<div>`` with the statistics and the picture as an embedded PNG.
        """
        import base64
        import html

        png = base64.b64encode(bytes(self.image.value)).decode("ascii")
        return (f'<div class="cshape-msweep-static"><p><b>{html.escape(self.state.summary())}'
                f'</b></p><img alt="the M sweep at M = {self.state.M}" style="max-width:100%" '
                f'src="data:image/png;base64,{png}"></div>')

    def _repr_mimebundle_(self, **kwargs: Any) -> dict[str, Any]:
        """The live widget, and :meth:`static_html` for pages where no kernel runs (an
        exported lesson, the docs site: nbconvert falls back to it when the notebook saved
        no widget state)."""
        data = dict(super()._repr_mimebundle_(**kwargs) or {})
        data["text/html"] = self.static_html()
        return data

    def refresh(self) -> None:
        """Recompute the state for the current controls (cheap stages only) and redraw."""
        from .figures import plot_m_sweep

        c = self.controls
        N = int(c["N"].value)
        tr = c["transform"].value
        M = clamp_M(c["M"].value, N, tr)
        self.state = self.sweep.state(M, N=N, normalization=c["normalization"].value,
                                      transform=tr)
        fig = plot_m_sweep(self.state, shape=int(c["shape"].value or 0), figsize=self._figsize)
        self.image.value = _png(fig, self._dpi)
        self.stats.value = f"<b>{self.state.summary()}</b>"


def m_sweep_widget(data: Any, *, M: int = 16, N: int | None = None, normalization: str = "area",
                   figsize: tuple[float, float] = (12.0, 7.0), dpi: float = 72,
                   transform: str = "weyl") -> MSweepWidget:
    """Make an ipywidgets M sweep: slide ``M``, pick ``N``, collection, normalisation, shape.

    Eigenvalues are given once (``data``); moving a control reruns only the cheap stages of
    :class:`MSweep` and redraws :func:`cshape.plots.plot_m_sweep`.  ``M`` is clamped to
    ``[0, (N-1)//2]`` (``[0, (N-2)//2]`` for the log-Weyl transforms), also when ``N`` is
    lowered or the transform changes.

    Parameters
    ----------
    data : DescriptorTable, MSweep, or dict of str to DescriptorTable / MSweep
        One collection, or several to choose from (the ``collection`` drop-down).  A table
        comes from :func:`cshape.batch.describe` or ``DescriptorTable(names, lam, areas,
        labels)``.
    M : int, default=16
        Initial crop half-width (clamped).
    N : int, optional
        Initial Shape-DNA length (default: all eigenvalues of the first collection).
    normalization : {'area', 'fiedler', 'weyl'}, default='area'
    figsize : (float, float), default=(12.0, 7.0)
        Size of a new figure, in inches.
    dpi : int, default=72
        Resolution of the PNG image.
    transform : {'weyl', 'log-weyl', 'log-weyl-dct'}, default='weyl'
        Initial position of the transform toggle (see :func:`cshape.compact_shape_dna`).

    Returns
    -------
    MSweepWidget
        An ``ipywidgets.VBox``; show it by making it the last expression of a cell (or with
        ``IPython.display.display``).  This function never displays anything itself.
    """
    if _w is None:  # pragma: no cover
        require_extra("m_sweep_widget", "plots", ("ipywidgets",))
    sweeps = _as_sweeps(data, normalization)
    return MSweepWidget(sweeps, M=M, N=N, normalization=normalization, figsize=figsize, dpi=dpi,
                        transform=transform)
