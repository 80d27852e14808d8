"""The paper's Section 3 experiments on a :class:`~cshape.batch.DescriptorTable`, and the
retrieval tables of every descriptor.
"""

from __future__ import annotations

import time
from collections import Counter
from typing import TYPE_CHECKING, Any

import numpy as np

from ..batch import DescriptorTable
from ..compare import difference_matrix, distance_matrix, retrieval_scores, scaled_difference
from ..descriptors import Descriptor
from ..index import DescriptorIndex

if TYPE_CHECKING:
    from collections.abc import Iterable, Sequence

#: The numbers the paper reports, by section: 3.1 (mean and standard deviation of the
#: difference image), 3.2 (the same for each ``M``), 3.3 (for each noise level) and the
#: space saving it quotes; the report sets its own results beside them.
PAPER_RESULTS: dict[str, Any] = {
    "3.1": {"M": 16, "mean": 0.68, "std": 0.69},
    "3.2": {8: (1.3, 1.1), 4: (2.3, 1.8), 2: (4.8, 3.1), 1: (6.0, 3.8)},
    "3.3": {
        "shape-dna": {0.5: (4.3, 5.5), 1.0: (8.5, 9.1), 2.0: (11.8, 12.0), 4.0: (12.3, 11.5),
                      10.0: (24.9, 23.7)},
        "cshape": {0.5: (4.6, 5.5), 1.0: (9.0, 9.1), 2.0: (12.2, 12.1), 4.0: (12.4, 11.5),
                   10.0: (24.9, 23.7)},
    },
    "saving": 0.97,
}

NOISE_LEVELS = (0.5, 1.0, 2.0, 4.0, 10.0)

#: Fig. 1 draws at most this many Shape-DNAs (one per class, see :func:`fig1_selection`).
FIG1_MAX_SHAPES = 8


def _need(table: DescriptorTable, p: int = 3) -> None:
    if len(table) < p:
        raise ValueError(
            f"the experiments need at least {p} shapes (a distance matrix of 2 shapes always "
            f"scales to the same image), got {len(table)}"
        )


# --------------------------------------------------------------------------- experiments
def experiment_3_1(table: DescriptorTable, *, N: int = 100, M: int = 16) -> dict[str, Any]:
    """Section 3.1: Shape-DNA (``N``) against cShape-DNA (``M``).

    Parameters
    ----------
    table : DescriptorTable
        Eigenvalues and areas of the collection (:func:`cshape.describe`).
    N : int, default=100
        Shape-DNA length.
    M : int, default=16
        Crop half-width of the cShape-DNA (``2M+1`` values).

    Returns
    -------
    dict
        ``mean``, ``std`` of ``|scale_255(D_N) - scale_255(D_M)|`` over the full matrix
        (:func:`cshape.compare.scaled_difference`), and the two distance matrices
        ``D_shape_dna``, ``D_cshape`` (p, p).
    """
    _need(table)
    D_sd = table.distance_matrix(Descriptor("shape-dna", N=N))
    D_cs = table.distance_matrix(Descriptor("cshape", N=N, M=M))
    mean, std = scaled_difference(D_sd, D_cs)
    return {"N": N, "M": M, "mean": mean, "std": std, "D_shape_dna": D_sd, "D_cshape": D_cs}


def experiment_3_2(table: DescriptorTable, *, Ms: Sequence[int] = (16, 8, 4, 2, 1), N: int = 100
                   ) -> dict[str, Any]:
    """Section 3.2 and the equal-size comparison of Section 3.1 (Fig. 4-6).

    For every ``M``, the difference statistics against Shape-DNA with ``N`` values of the
    cShape-DNA (``2M+1`` values), of the truncated Shape-DNA of the same size, and of the
    extensions beyond the paper of the same size (the log-Weyl DFT and DCT crops,
    :func:`cshape.compact_shape_dna` ``transform=``, and the truncated log spectrum); F1
    (``N``) once.  A descriptor that cannot be computed for the table (a log-Weyl one on a
    shape with too few non-zero eigenvalues) is left out.

    Parameters
    ----------
    table : DescriptorTable
        Eigenvalues and areas of the collection (:func:`cshape.describe`).
    Ms : sequence of int, default=(16, 8, 4, 2, 1)
        Crop half-widths.
    N : int, default=100
        Shape-DNA length.

    Returns
    -------
    dict
        ``{'cshape': {M: (mean, std)}, 'truncated': {M: (mean, std)}, 'log-weyl': {...},
        'log-weyl-dct': {...}, 'truncated-log': {...}, 'f1': (mean, std)}``.
    """
    _need(table)
    D_sd = table.distance_matrix(Descriptor("shape-dna", N=N))
    out: dict[str, Any] = {"N": N, "cshape": {}, "truncated": {}}
    for M in Ms:
        out["cshape"][M] = scaled_difference(
            D_sd, table.distance_matrix(Descriptor("cshape", N=N, M=M)))
        out["truncated"][M] = scaled_difference(
            D_sd, table.distance_matrix(Descriptor("truncated", N=N, M=M)))
    for key in ("log-weyl", "log-weyl-dct", "truncated-log"):
        kind, kw = ("truncated-log", {}) if key == "truncated-log" else ("cshape",
                                                                         {"transform": key})
        try:
            out[key] = {M: scaled_difference(
                D_sd, table.distance_matrix(Descriptor(kind, N=N, M=M, **kw)))
                for M in Ms if 2 * M + 1 <= N - 1}
        except ValueError:
            out[key] = {}
    out["f1"] = scaled_difference(D_sd, table.distance_matrix(Descriptor("f1", N=N)))
    return out


def _pair_rows(clean: DescriptorTable, noisy: DescriptorTable,
               pairs: Iterable[tuple[str, str]]) -> tuple[np.ndarray, np.ndarray]:
    """Rows of clean and noisy tables for (clean name, noisy name) pairs present in both."""
    ci, ni = [], []
    for a, b in pairs:
        if a in clean.names and b in noisy.names:
            ci.append(clean.index(a))
            ni.append(noisy.index(b))
    return np.array(ci, dtype=int), np.array(ni, dtype=int)


def experiment_noise(clean: DescriptorTable, noisy: dict[float, DescriptorTable], *,
                     pairs: dict[float, Iterable[tuple[str, str]]] | None = None,
                     N: int = 100, M: int = 16
                     ) -> dict[float, dict[str, Any]]:
    """Section 3.3: how noise changes the distance matrices (Fig. 7) and descriptors (Fig. 8).

    Parameters
    ----------
    clean : DescriptorTable
        The shapes without noise.
    noisy : dict of float to DescriptorTable
        One table per noise level, holding noisy copies of the clean shapes.
    pairs : dict of float to list of (str, str), optional
        ``(clean name, noisy name)`` for each level; default: the same names.
    N, M : int
        Shape-DNA length (default 100) and cShape-DNA crop half-width (default 16).

    Returns
    -------
    dict
        ``{level: {'shape-dna': (mean, std), 'cshape': (mean, std),
        'change_shape-dna': (p,), 'change_cshape': (p,), 'names': [...]}}`` where the
        ``change_*`` arrays are ``||x_noisy - x_clean||`` per shape.
    """
    out: dict[float, dict[str, Any]] = {}
    for level, table in sorted(noisy.items()):
        pr = pairs[level] if pairs is not None else [(n, n) for n in clean.names]
        ci, ni = _pair_rows(clean, table, pr)
        if len(ci) < 3:
            raise ValueError(
                f"noise level {level}: only {len(ci)} shapes are in both the clean and the "
                "noisy table; the experiment needs at least 3"
            )
        res: dict[str, Any] = {"names": [clean.names[i] for i in ci]}
        for kind, d in (("shape-dna", Descriptor("shape-dna", N=N)),
                        ("cshape", Descriptor("cshape", N=N, M=M))):
            Xc = clean.select(ci).descriptors(d)
            Xn = table.select(ni).descriptors(d)
            res[kind] = scaled_difference(distance_matrix(Xc), distance_matrix(Xn))
            res["change_" + kind] = np.linalg.norm(Xn - Xc, axis=1)
            res["diff_" + kind] = difference_matrix(distance_matrix(Xc), distance_matrix(Xn))
        out[float(level)] = res
    return out


def _descriptor_specs(Ms: Sequence[int], N: int) -> list[tuple[str, Descriptor]]:
    specs = [("Shape-DNA", Descriptor("shape-dna", N=N))]
    specs += [(f"cShape-DNA M={M}", Descriptor("cshape", N=N, M=M)) for M in Ms]
    specs += [(f"truncated Shape-DNA {2 * M + 1}", Descriptor("truncated", N=N, M=M))
              for M in Ms]
    specs += [("F1", Descriptor("f1", N=N))]
    return specs


#: The descriptor families of the equal-size comparison (:func:`experiment_sizes`): title ->
#: (kind of :class:`cshape.Descriptor`, its other fields but ``N`` and ``M``).  Every family has
#: ``2M+1`` values at half-width ``M``; 'truncated F1' keeps the first ``2M+1`` F1 values.
FAMILIES = {
    "cShape-DNA (paper)": ("cshape", {"transform": "weyl"}),
    "log-Weyl DFT": ("cshape", {"transform": "log-weyl"}),
    "log-Weyl DCT": ("cshape", {"transform": "log-weyl-dct"}),
    "truncated Shape-DNA": ("truncated", {}),
    "truncated log spectrum": ("truncated-log", {}),
    "truncated F1": ("f1", {}),
}

#: The families beyond the paper (extensions of cshape), marked as such in the report.
EXTENSIONS = ("log-Weyl DFT", "log-Weyl DCT", "truncated log spectrum")


def family_descriptors(table: DescriptorTable, family: str, *, N: int = 100, M: int
                       ) -> np.ndarray:
    """Compute the descriptors of a :data:`FAMILIES` member with ``2M+1`` values.

    Parameters
    ----------
    table : DescriptorTable
        Eigenvalues and areas of the collection (:func:`cshape.describe`).
    family : str
        A member of :data:`FAMILIES`.
    N : int, default=100
        Shape-DNA length.
    M : int
        Crop half-width.

    Returns
    -------
    ndarray, shape (p, 2M+1)
        One descriptor per shape of the table.

    Raises
    ------
    ValueError
        Unknown family, or the family cannot be computed (``2M+1`` too large for ``N``, or
        a shape with fewer non-zero eigenvalues than the family needs: a mesh of many
        pieces).
    """
    if family not in FAMILIES:
        raise ValueError(f"family must be one of {list(FAMILIES)}, got {family!r}")
    kind, kw = FAMILIES[family]
    if kind == "f1":
        X = _every_row(table, Descriptor("f1", N=N))
        if X.shape[1] < 2 * M + 1:
            raise ValueError(f"F1 of N={N} has {X.shape[1]} values, fewer than 2M+1 = "
                             f"{2 * M + 1}; use a larger N")
        return X[:, : 2 * M + 1]
    return _every_row(table, Descriptor(kind, N=N, M=M, **kw))


def _every_row(table: DescriptorTable, descriptor: Descriptor) -> np.ndarray:
    """``table.descriptors(descriptor)``, or a ValueError if it cannot describe every shape
    (the measures need every shape)."""
    X, rows = table.described(descriptor, warn=False)
    if len(rows) < len(table):
        bad = [table.names[i] for i in np.setdiff1d(np.arange(len(table)), rows)]
        raise ValueError(f"{descriptor.label} cannot describe {len(bad)} shapes: "
                         f"{', '.join(bad[:5])}")
    return X


def _retrieval_specs(Ms: Sequence[int], N: int) -> list[tuple[Any, ...]]:
    """(title, family or None, M, descriptor or None) of every row of the retrieval table."""
    specs: list[tuple[Any, ...]] = [
        ("Shape-DNA", None, None, Descriptor("shape-dna", N=N)),
        ("log spectrum (all N-1 log-Weyl ratios)", None, None,
         Descriptor("truncated-log", N=N, M=(N - 2) // 2)),
        ("F1", None, None, Descriptor("f1", N=N))]
    for M in Ms:
        for fam in FAMILIES:
            specs.append((f"{fam} M={M}" if FAMILIES[fam][0] == "cshape"
                          else f"{fam} {2 * M + 1}", fam, M, None))
    return specs


def experiment_retrieval(table: DescriptorTable, *, Ms: Sequence[int] = (16, 8, 4, 2, 1),
                         N: int = 100) -> list[dict[str, Any]]:
    """Retrieval measures (:func:`cshape.compare.retrieval_scores`) of every descriptor.

    Rows: Shape-DNA (``N`` values), the whole log spectrum (the ``N-1`` log-Weyl ratios,
    a extension beyond the paper) and F1 (``N-2``); then for every ``M`` each of
    :data:`FAMILIES` with ``2M+1`` values.  A descriptor that cannot be computed for the
    table (see :func:`family_descriptors`) is left out.

    Parameters
    ----------
    table : DescriptorTable
        Eigenvalues, areas and class labels of the collection.
    Ms : sequence of int, default=(16, 8, 4, 2, 1)
        Crop half-widths.
    N : int, default=100
        Shape-DNA length.

    Returns
    -------
    list of dict
        One row per descriptor: ``descriptor``, ``family`` (None for the full-length rows),
        ``M``, ``size`` and the six measures.
    """
    rows = []
    for title, fam, M, d in _retrieval_specs(Ms, N):
        try:
            X = (_every_row(table, d) if fam is None
                 else family_descriptors(table, fam, N=N, M=M))
        except ValueError:
            continue
        s = retrieval_scores(distance_matrix(X), table.labels)
        rows.append({"descriptor": title, "family": fam, "M": M, "size": X.shape[1], **s})
    return rows


def experiment_sizes(table: DescriptorTable, *, Ms: Sequence[int] | None = None, N: int = 100,
                     measure: str = "ft") -> dict[str, Any]:
    """Section 3.2 by retrieval: every family of :data:`FAMILIES` at every size ``2M+1``.

    For each ``M`` the retrieval measures of every family, the best family by ``measure``
    and its lead over the runner-up with the paired standard error over the queries
    (``std(a_q - b_q) / sqrt(p)`` of the per-query values,
    :func:`cshape.compare.retrieval_per_query`).

    Parameters
    ----------
    table : DescriptorTable
        With class labels.
    Ms : sequence of int, optional
        Default ``16, 15, ..., 1``, limited to ``2M+1 <= N-2`` (F1 has ``N-2`` values).
    N : int, default=100
        Shape-DNA length.
    measure : {'nn', 'ft', 'st', 'e', 'dcg', 'map'}, default='ft'
        The measure that decides the winner (first tier).

    Returns
    -------
    dict
        ``measure``, ``Ms``, ``families`` (computed), ``skipped`` ({family: reason}),
        ``reference`` (the measures of Shape-DNA with ``N`` values), ``n_queries`` (the
        queries scored: shapes of classes of one have no relevant answer and are not) and
        ``rows``: one per
        ``M`` with ``M``, ``size``, ``scores`` ({family: {measure: value}}), ``best``
        (families tied at the best value), ``runner_up``, ``lead``, ``lead_se``.
    """
    from ..compare import retrieval_per_query

    if Ms is None:
        Ms = range(min(16, (N - 3) // 2), 0, -1)
    Ms = [int(m) for m in Ms]
    labels = table.labels
    ref = retrieval_scores(table.distance_matrix(Descriptor("shape-dna", N=N)), labels)
    sizes = Counter(labels)
    n_queries = sum(sizes[x] >= 2 for x in labels)
    rows, skipped = [], {}
    for M in Ms:
        scores, per = {}, {}
        for fam in FAMILIES:
            if fam in skipped:
                continue
            try:
                X = family_descriptors(table, fam, N=N, M=M)
            except ValueError as exc:
                skipped[fam] = str(exc)
                continue
            q = retrieval_per_query(distance_matrix(X), labels)
            per[fam] = q[measure]
            scores[fam] = {k: float(np.nanmean(v)) for k, v in q.items()}
        order = sorted(scores, key=lambda f: -scores[f][measure])
        top = scores[order[0]][measure]
        best = [f for f in order if scores[f][measure] == top]
        rest = [f for f in order if f not in best]
        row = {"M": M, "size": 2 * M + 1, "scores": scores, "best": best,
               "runner_up": rest[0] if rest else None, "lead": 0.0, "lead_se": 0.0}
        if rest:
            d = per[best[0]] - per[rest[0]]
            d = d[~np.isnan(d)]
            row["lead"] = float(d.mean())
            row["lead_se"] = float(d.std(ddof=1) / np.sqrt(len(d))) if len(d) > 1 else 0.0
        rows.append(row)
    families = [f for f in FAMILIES if f not in skipped]
    return {"measure": measure, "Ms": Ms, "families": families, "skipped": skipped,
            "reference": ref, "N": N, "n_shapes": len(table), "n_queries": n_queries,
            "rows": rows}


_MEASURES = {"nn": "nearest neighbour", "ft": "first tier", "st": "second tier",
             "e": "E-measure", "dcg": "DCG", "map": "mean average precision"}


def _ranges(ms: Sequence[int]) -> str:
    """'16..9, 6, 2..1' for descending integers."""
    parts, start = [], None
    for i, m in enumerate(ms):
        if start is None:
            start = m
        if i + 1 == len(ms) or ms[i + 1] != m - 1:
            parts.append(str(m) if m == start else f"{start}..{m}")
            start = None
    return ", ".join(parts)


def size_verdict(sizes: dict[str, Any], *, name: str = "this collection") -> list[str]:
    """The verdict under the size table, computed from :func:`experiment_sizes`' numbers.

    Parameters
    ----------
    sizes : dict
        The result of :func:`experiment_sizes`.
    name : str, default='this collection'
        The collection's name in the sentences.

    Returns
    -------
    list of str
        Sentences: which family wins at how many sizes, the winners at 17 and 33 values
        with their lead and its standard error, how the paper's cShape-DNA compares with
        the truncated Shape-DNA and the extensions, and where the best family reaches
        Shape-DNA with ``N`` values.  Nothing in them is fixed text about a winner.
    """
    meas, rows = sizes["measure"], sizes["rows"]
    if not rows:
        return []
    mname = _MEASURES[meas]
    n = len(rows)
    nq, ns = sizes.get("n_queries", sizes["n_shapes"]), sizes["n_shapes"]
    scored = (f"{nq} queries" if nq == ns else
              f"{nq} queries scored of {ns} shapes: {ns - nq} in classes of one, which have "
              "no relevant answer")
    out = [f"Verdict on {name} by {mname} ({scored}; a lead is given "
           "with its paired standard error over the queries, and a lead below two "
           "standard errors is not clear):"]
    wins = {f: [r["M"] for r in rows if f in r["best"]] for f in sizes["families"]}
    ranked = sorted((f for f in wins if wins[f]), key=lambda f: -len(wins[f]))
    out.append("Best (ties count for each): " + "; ".join(
        f"{f} at {len(wins[f])} of {n} sizes (M = {_ranges(wins[f])})" for f in ranked) + ".")
    for M in (8, 16):
        r = next((r for r in rows if r["M"] == M), None)
        if r is None:
            continue
        sc = r["scores"]
        others = ", ".join(f"{f} {sc[f][meas]:.3f}" for f in
                           sorted((f for f in sc if f not in r["best"]),
                                  key=lambda f: -sc[f][meas]))
        lead = ""
        if r["runner_up"] is not None:
            clear = "clear" if r["lead"] > 2 * r["lead_se"] else "not clear"
            lead = (f"; lead over {r['runner_up']} {r['lead']:.3f} +- {r['lead_se']:.3f} "
                    f"({clear})")
        out.append(f"At {r['size']} values (M={M}): best {' = '.join(r['best'])} "
                   f"{sc[r['best'][0]][meas]:.3f}{lead}; then {others}.")
    paper, trunc = "cShape-DNA (paper)", "truncated Shape-DNA"
    pairs = [(paper, trunc)] + [(f, paper) for f in EXTENSIONS]
    for a, b in pairs:
        if a in sizes["families"] and b in sizes["families"]:
            diff = np.array([r["scores"][a][meas] - r["scores"][b][meas] for r in rows])
            out.append(f"{a} vs {b}: higher at {int(np.sum(diff > 0))}, lower at "
                       f"{int(np.sum(diff < 0))} of {n} sizes (mean difference "
                       f"{diff.mean():+.3f}).")
    ref = sizes["reference"][meas]
    if ranked:
        top = ranked[0]
        reach = [r["size"] for r in rows if r["scores"][top][meas] >= ref]
        where = (f"reaches it at {len(reach)} of {n} sizes (smallest: {min(reach)} values)"
                 if reach else "stays below it at every size")
        out.append(f"Shape-DNA with N={sizes['N']} values scores {ref:.3f}; {top} {where}.")
    return out


def experiment_cost(table: DescriptorTable, *, Ms: Sequence[int] = (16, 8, 4, 2, 1),
                    N: int = 100, repeats: int = 5, database_size: int = 20000,
                    n_queries: int = 100, random_state: int = 0) -> list[dict[str, Any]]:
    """Descriptor size and comparison time, relative to Shape-DNA with ``N`` values.

    The table's descriptors are resampled (with a tiny jitter) into a database of
    ``database_size`` rows, and ``n_queries`` of them are compared with the whole database.
    Timings, the best of ``repeats`` (the least disturbed by other work on the machine):
    the full distance matrix of the table (``matrix_seconds``), the distances of the queries
    to every database row (``scan_seconds``, the comparison cost the paper's claim is about,
    proportional to the descriptor length), and the exact 10-nearest-neighbour search with
    :class:`cshape.compare.DescriptorIndex` (``search_seconds``, which adds a selection
    whose cost does not depend on the length).

    Parameters
    ----------
    table : DescriptorTable
        Eigenvalues and areas of the collection (:func:`cshape.describe`).
    Ms : sequence of int, default=(16, 8, 4, 2, 1)
        Crop half-widths of the cShape-DNAs timed.
    N : int, default=100
        Shape-DNA length.
    repeats : int, default=5
        Timings per measurement; the best is kept.
    database_size : int, default=20000
        Rows of the resampled database.
    n_queries : int, default=100
        Queries compared with the database.
    random_state : int, default=0
        Seed of the resampling, the jitter and the choice of queries.

    Returns
    -------
    list of dict
        ``descriptor``, ``values``, ``bytes`` (float64), ``size_saving`` (1 - values / N),
        ``matrix_seconds``, ``scan_seconds``, ``search_seconds``, ``time_saving``
        (1 - scan time / Shape-DNA scan time).
    """
    from scipy.spatial.distance import cdist

    rng = np.random.default_rng(random_state)
    rows_idx = rng.integers(0, len(table), size=database_size)
    q_idx = rng.integers(0, database_size, size=n_queries)
    warm = table.descriptors(Descriptor("shape-dna", N=N))  # first calls pay imports
    distance_matrix(warm)
    DescriptorIndex(warm, algorithm="brute").query(warm[:1], k=1)
    rows = []
    for title, d in _descriptor_specs(Ms, N):
        if d.kind == "truncated":
            continue
        X = table.descriptors(d)
        scale = float(np.abs(X).max()) or 1.0
        big = X[rows_idx] + 1e-6 * scale * rng.standard_normal((database_size, X.shape[1]))
        index = DescriptorIndex(big, algorithm="brute")
        Q = big[q_idx]
        t_mat, t_scan, t_q = [], [], []
        for _ in range(repeats):
            t0 = time.perf_counter()
            distance_matrix(X)
            t_mat.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            cdist(Q, big)
            t_scan.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            index.query(Q, k=10)
            t_q.append(time.perf_counter() - t0)
        rows.append({"descriptor": title, "values": X.shape[1], "bytes": 8 * X.shape[1],
                     "size_saving": 1.0 - X.shape[1] / N,
                     "matrix_seconds": min(t_mat), "scan_seconds": min(t_scan),
                     "search_seconds": min(t_q)})
    base = rows[0]["scan_seconds"]
    for r in rows:
        r["time_saving"] = 1.0 - r["scan_seconds"] / base if base > 0 else float("nan")
    return rows
