"""Every descriptor on every benchmark of the suite, and the choice of the exploration default.

The suite (:data:`cshape.data.suite.SUITE`) asks three questions: the class of a shape
(``creatures``, category level), the identity of a body in another pose and resolution
(``identities``, instance level) and the same shape in another meshing (``resolutions``).
:func:`suite_scores` scores every descriptor of :data:`CANDIDATES` on each benchmark with
:func:`cshape.compare.retrieval_scores`; :func:`choose_default` picks the descriptor whose
**worst** first tier over the benchmarks is highest (a default must not fail any kind of
collection; the mean would let a strong benchmark hide a weak one).  Choose on the
development instances, then report the chosen descriptor on the held-out ones.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..compare import distance_matrix, retrieval_scores
from ..descriptors import Descriptor, recipe

if TYPE_CHECKING:
    from collections.abc import Iterable, Sequence

    from ..batch import DescriptorTable

#: The families of the suite: (title, kind, transform, normalization).  Beyond the paper's
#: area normalisation, the truncated log spectrum is also tried with the normalisations
#: that need no area (:func:`cshape.normalize`): 'weyl' (the slope of the kept eigenvalues)
#: and 'fiedler' (``lam_1``); a coarse mesh's area is a little off, and in log space a
#: normalisation is one shift of the whole row.
_FAMILIES = (
    ("cShape-DNA (paper)", "cshape", "weyl", "area"),
    ("log-Weyl DFT", "cshape", "log-weyl", "area"),
    ("log-Weyl DCT", "cshape", "log-weyl-dct", "area"),
    ("truncated Shape-DNA", "truncated", "weyl", "area"),
    ("truncated log spectrum", "truncated-log", "weyl", "area"),
    ("truncated log spectrum, Weyl-normalised", "truncated-log", "weyl", "weyl"),
    ("truncated log spectrum, lam_1-normalised", "truncated-log", "weyl", "fiedler"),
    ("F1", "f1", "weyl", "area"),
)

#: Sizes ``2M+1`` of the suite: the paper's 17 and 33 and more values (an identity differs
#: from another in finer eigenvalues than a class does).
SUITE_MS = (8, 16, 24, 32, 49)

#: The measures reported (see :func:`cshape.compare.retrieval_scores`).
MEASURES = ("nn", "ft", "st", "map")


def candidates(N: int = 100, Ms: Sequence[int] = SUITE_MS) -> list[dict[str, Any]]:
    """The descriptors of the suite computable from ``N`` eigenvalues.

    Parameters
    ----------
    N : int, default=100
        Eigenvalues per shape.
    Ms : sequence of int, default=(8, 16, 24, 32, 49)
        Crop half-widths tried (each where the family allows it).

    Returns
    -------
    list of dict
        ``{'title', 'family', 'kind', 'M', 'N', 'transform', 'size'}``; Shape-DNA with all
        ``N`` values first, then every family of the paper's comparison and its
        extensions at every size ``2M+1`` it allows (F1 of ``N`` eigenvalues has ``N-2``
        values, the log-Weyl transforms ``N-1``, the truncated log spectrum needs ``2M+2``),
        and the two-scale log spectrum (kind ``'two-scale'``, ``M = 4`` and ``8``: ``2M+1``
        first and ``N-1`` detrended values).
    """
    out = [{"title": f"Shape-DNA {N}", "family": "Shape-DNA", "kind": "shape-dna", "M": None,
            "N": N, "transform": "weyl", "normalization": "area", "size": N}]
    for M in Ms:
        size = 2 * M + 1
        for title, kind, tr, norm in _FAMILIES:
            limit = {"cshape": N if tr == "weyl" else N - 1, "truncated": N,
                     "truncated-log": N - 1, "f1": N - 2}[kind]
            if size > limit:
                continue
            n = 2 * M + 3 if kind == "f1" else N  # F1 of 2M+3 eigenvalues: 2M+1 values
            out.append({"title": f"{title} {size}", "family": title, "kind": kind, "M": M,
                        "N": n, "transform": tr, "normalization": norm, "size": size})
    for M in (4, 8):  # the first 2M+1 log-Weyl ratios beside the N-1 detrended ones
        if 2 * M + 1 <= N - 1 and N >= 6:
            size = 2 * M + 1 + N - 1
            out.append({"title": f"two-scale log spectrum {size}",
                        "family": "two-scale log spectrum", "kind": "two-scale", "M": M,
                        "N": N, "transform": "weyl", "normalization": "area", "size": size})
    return out


#: The candidates of the default choice at ``N = 100``.
CANDIDATES = candidates()


def _descriptor(c: dict[str, Any]) -> Descriptor:
    """The :class:`cshape.Descriptor` of a candidate row."""
    M = {} if c["M"] is None else {"M": c["M"]}
    return Descriptor(c["kind"], N=c["N"], transform=c["transform"],
                      normalization=c["normalization"], **M)


def suite_scores(tables: dict[str, DescriptorTable], *,
                 cands: Sequence[dict[str, Any]] | None = None) -> list[dict[str, Any]]:
    """Retrieval scores of every candidate on every benchmark table.

    Parameters
    ----------
    tables : dict of str to DescriptorTable
        Benchmark name -> its table (with class labels), e.g. the development instances.
    cands : list of dict, optional
        Default :func:`candidates` for the smallest ``N`` of the tables.

    Returns
    -------
    list of dict
        One per candidate: its fields and ``scores`` ({benchmark: {measure: value}}),
        ``worst`` and ``mean`` first tier over the benchmarks.  A candidate a table cannot
        give (too few eigenvalues) is left out.
    """
    if not tables:
        raise ValueError("tables is empty; give at least one benchmark table")
    N = min(t.N for t in tables.values())
    rows: list[dict[str, Any]] = []
    for c in cands if cands is not None else candidates(N):
        scores: dict[str, dict[str, float]] = {}
        try:
            for name, table in tables.items():
                s = retrieval_scores(distance_matrix(table.descriptors(_descriptor(c))),
                                     table.labels)
                scores[name] = {k: s[k] for k in MEASURES}
        except ValueError:
            continue
        ft = [s["ft"] for s in scores.values()]
        rows.append({**c, "label": _descriptor(c).label,
                     "scores": scores, "worst": float(min(ft)), "mean": float(np.mean(ft))})
    return rows


def choose_default(rows: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """Choose the row with the highest worst first tier (ties: higher mean, then fewer values).

    Parameters
    ----------
    rows : sequence of dict
        The rows of :func:`suite_scores`.

    Returns
    -------
    dict
        The chosen row.

    Raises
    ------
    ValueError
        If ``rows`` is empty.
    """
    if not rows:
        raise ValueError("rows is empty; score the candidates with suite_scores first")
    return max(rows, key=lambda r: (round(r["worst"], 12), round(r["mean"], 12), -r["size"]))


def default_row(rows: Iterable[dict[str, Any]]) -> dict[str, Any] | None:
    """Find the row of the exploration default :data:`cshape.DEFAULT`.

    Parameters
    ----------
    rows : iterable of dict
        The rows of :func:`suite_scores`.

    Returns
    -------
    dict or None
        The row of the default, or None when no row is.
    """
    d = recipe.DEFAULT  # read when called: the constant, wherever it is set
    for r in rows:
        if r["kind"] != d.kind:
            continue
        if r["kind"] in ("cshape", "cshape-complex") and r["transform"] != d.transform:
            continue
        if r["kind"] != "f1" and r["normalization"] != d.normalization:
            continue
        if r["kind"] == "shape-dna" or r["M"] == d.M:
            return r
    return None


def suite_markdown(rows: Sequence[dict[str, Any]], *, title: str, note: str = "",
                   measure: str = "ft", mark: str | None = None) -> str:
    """Write a Markdown table: one row per descriptor, a column per benchmark, worst and mean.

    Parameters
    ----------
    rows : sequence of dict
        The rows of :func:`suite_scores`.
    title : str
        Heading of the table (the measure's name is added).
    note : str, default=''
        A paragraph under the heading.
    measure : {'ft', 'nn', 'st', 'map'}, default='ft'
        The retrieval measure shown.
    mark : str, optional
        A row's ``title``, set in bold.

    Returns
    -------
    str
        The heading, the note and the table, in Markdown.
    """
    names = list(rows[0]["scores"]) if rows else []
    what = {"ft": "first tier", "nn": "nearest neighbour", "st": "second tier",
            "map": "mean average precision"}[measure]
    lines = [f"### {title}: {what}", ""]
    if note:
        lines += [note, ""]
    lines += ["| descriptor | values | " + " | ".join(names) + " | worst | mean |",
              "|---|---|" + "---|" * len(names) + "---|---|"]
    for r in rows:
        vals = [r["scores"][n][measure] for n in names]
        cells = [f"{v:.3f}" for v in vals] + [f"{min(vals):.3f}", f"{np.mean(vals):.3f}"]
        name = f"**{r['title']}**" if r["title"] == mark else r["title"]
        lines.append(f"| {name} | {r['size']} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"
