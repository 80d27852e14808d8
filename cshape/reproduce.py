"""The paper's Section 3 on any collection: experiments, figures, and a Markdown report.

The pure experiment functions take a :class:`cshape.batch.DescriptorTable` and return plain
numbers, so tests and notebooks call them directly:

* :func:`experiment_3_1`   - Shape-DNA (``N``) vs cShape-DNA (``M``): scaled distance matrices
                              and the mean / std of their difference (paper: 0.68 / 0.69);
* :func:`experiment_3_2`   - the same for ``M = 8, 4, 2, 1`` (paper: means 1.3, 2.3, 4.8, 6.0),
                              beside the truncated Shape-DNA and F1 at equal size;
* :func:`experiment_noise` - Section 3.3: clean vs noisy distance matrices for both descriptors;
* :func:`experiment_retrieval` - PSB retrieval measures for every descriptor and size;
* :func:`experiment_cost`  - descriptor size and comparison time (the "up to 97 %" claim).

:func:`reproduce` runs them all on a list of ``(name, label, mesh)`` records (anything
:func:`cshape.describe` accepts), writes the figures corresponding to the paper's Fig. 1-9,
``results.json``, the descriptor tables and ``report.md`` with the paper's numbers beside ours.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np

from .batch import DescriptorTable, describe
from .compare import (
    MAX_LEGEND_CLASSES,
    MDS_MAX_NAMES,
    DescriptorIndex,
    annotate_points,
    difference_matrix,
    distance_matrix,
    mds_embedding,
    plot_mds,
    retrieval_scores,
    scaled_difference,
    short_labels,
)

__all__ = [
    "EXTENSIONS",
    "FAMILIES",
    "PAPER",
    "experiment_3_1",
    "experiment_3_2",
    "experiment_cost",
    "experiment_noise",
    "experiment_retrieval",
    "experiment_sizes",
    "family_descriptors",
    "fig1_selection",
    "reproduce",
    "size_verdict",
]

#: The numbers the paper reports (McGill database, 458 models, N=100).
PAPER = {
    "3.1": {"M": 16, "mean": 0.68, "std": 0.69},
    "3.2": {8: (1.3, 1.1), 4: (2.3, 1.8), 2: (4.8, 3.1), 1: (6.0, 3.8)},
    "3.3": {
        "shape_dna": {0.5: (4.3, 5.5), 1.0: (8.5, 9.1), 2.0: (11.8, 12.0), 4.0: (12.3, 11.5),
                      10.0: (24.9, 23.7)},
        "cshape": {0.5: (4.6, 5.5), 1.0: (9.0, 9.1), 2.0: (12.2, 12.1), 4.0: (12.4, 11.5),
                   10.0: (24.9, 23.7)},
    },
    "saving": 0.97,
}

NOISE_LEVELS = (0.5, 1.0, 2.0, 4.0, 10.0)

#: Fig. 1 draws at most this many Shape-DNAs (one per class, see :func:`fig1_selection`).
FIG1_MAX_SHAPES = 8


def _need(table, p=3):
    if len(table) < p:
        raise ValueError(
            f"the experiments need at least {p} shapes (a distance matrix of 2 shapes always "
            f"scales to the same image), got {len(table)}"
        )


# --------------------------------------------------------------------------- experiments
def experiment_3_1(table: DescriptorTable, *, N=100, M=16):
    """Section 3.1: Shape-DNA (``N``) against cShape-DNA (``M``).

    Returns
    -------
    dict
        ``mean``, ``std`` of ``|scale_255(D_N) - scale_255(D_M)|`` over the full matrix
        (:func:`cshape.compare.scaled_difference`), and the two distance matrices
        ``D_shape_dna``, ``D_cshape`` (p, p).
    """
    _need(table)
    D_sd = table.distance_matrix("shape_dna", N=N)
    D_cs = table.distance_matrix("cshape", M=M, N=N)
    mean, std = scaled_difference(D_sd, D_cs)
    return {"N": N, "M": M, "mean": mean, "std": std, "D_shape_dna": D_sd, "D_cshape": D_cs}


def experiment_3_2(table: DescriptorTable, *, Ms=(16, 8, 4, 2, 1), N=100):
    """Section 3.2 and the equal-size comparison of Section 3.1 (Fig. 4-6).

    For every ``M``, the difference statistics against Shape-DNA with ``N`` values of the
    cShape-DNA (``2M+1`` values), of the truncated Shape-DNA of the same size, and of the
    extensions beyond the paper of the same size (the log-Weyl DFT and DCT crops,
    :func:`cshape.compact_shape_dna` ``transform=``, and the truncated log spectrum); F1
    (``N``) once.  A descriptor that cannot be computed for the table (a log-Weyl one on a
    spectrum with a second zero eigenvalue) is left out.

    Returns
    -------
    dict
        ``{'cshape': {M: (mean, std)}, 'truncated': {M: (mean, std)}, 'log-weyl': {...},
        'log-weyl-dct': {...}, 'truncated_log': {...}, 'f1': (mean, std)}``.
    """
    _need(table)
    D_sd = table.distance_matrix("shape_dna", N=N)
    out = {"N": N, "cshape": {}, "truncated": {}}
    for M in Ms:
        out["cshape"][M] = scaled_difference(D_sd, table.distance_matrix("cshape", M=M, N=N))
        out["truncated"][M] = scaled_difference(D_sd, table.distance_matrix("truncated", M=M))
    for key in ("log-weyl", "log-weyl-dct", "truncated_log"):
        kind, kw = ("truncated_log", {}) if key == "truncated_log" else ("cshape",
                                                                         {"transform": key})
        try:
            out[key] = {M: scaled_difference(D_sd, table.distance_matrix(kind, M=M, N=N, **kw))
                        for M in Ms if 2 * M + 1 <= N - 1}
        except ValueError:
            out[key] = {}
    out["f1"] = scaled_difference(D_sd, table.distance_matrix("f1", N=N))
    return out


def _pair_rows(clean: DescriptorTable, noisy: DescriptorTable, pairs):
    """Rows of clean and noisy tables for (clean name, noisy name) pairs present in both."""
    ci, ni = [], []
    for a, b in pairs:
        if a in clean.names and b in noisy.names:
            ci.append(clean.index(a))
            ni.append(noisy.index(b))
    return np.array(ci, dtype=int), np.array(ni, dtype=int)


def experiment_noise(clean: DescriptorTable, noisy: dict, *, pairs=None, N=100, M=16):
    """Section 3.3: how noise changes the scaled distance matrices (Fig. 7) and descriptors
    (Fig. 8).

    Parameters
    ----------
    clean : DescriptorTable
    noisy : dict of float to DescriptorTable
        One table per noise level, holding noisy copies of the clean shapes.
    pairs : dict of float to list of (str, str), optional
        ``(clean name, noisy name)`` for each level; default: the same names.
    N, M : int

    Returns
    -------
    dict
        ``{level: {'shape_dna': (mean, std), 'cshape': (mean, std),
        'change_shape_dna': (p,), 'change_cshape': (p,), 'names': [...]}}`` where the
        ``change_*`` arrays are ``||x_noisy - x_clean||`` per shape.
    """
    out = {}
    for level, table in sorted(noisy.items()):
        pr = pairs[level] if pairs is not None else [(n, n) for n in clean.names]
        ci, ni = _pair_rows(clean, table, pr)
        if len(ci) < 3:
            raise ValueError(
                f"noise level {level}: only {len(ci)} shapes are in both the clean and the "
                "noisy table; the experiment needs at least 3"
            )
        res = {"names": [clean.names[i] for i in ci]}
        for kind, kw in (("shape_dna", {"N": N}), ("cshape", {"M": M, "N": N})):
            Xc = clean.select(ci).descriptors(kind, **kw)
            Xn = table.select(ni).descriptors(kind, **kw)
            res[kind] = scaled_difference(distance_matrix(Xc), distance_matrix(Xn))
            res["change_" + kind] = np.linalg.norm(Xn - Xc, axis=1)
            res["diff_" + kind] = difference_matrix(distance_matrix(Xc), distance_matrix(Xn))
        out[float(level)] = res
    return out


def _descriptor_specs(Ms, N):
    specs = [("Shape-DNA", "shape_dna", {"N": N})]
    specs += [(f"cShape-DNA M={M}", "cshape", {"M": M, "N": N}) for M in Ms]
    specs += [(f"truncated Shape-DNA {2 * M + 1}", "truncated", {"M": M}) for M in Ms]
    specs += [("F1", "f1", {"N": N})]
    return specs


#: The descriptor families of the equal-size comparison (:func:`experiment_sizes`): title ->
#: (kind of :func:`cshape.compare.descriptor_matrix`, its keywords).  Every family has
#: ``2M+1`` values at half-width ``M``; 'truncated F1' keeps the first ``2M+1`` F1 values.
FAMILIES = {
    "cShape-DNA (paper)": ("cshape", {"transform": "weyl"}),
    "log-Weyl DFT": ("cshape", {"transform": "log-weyl"}),
    "log-Weyl DCT": ("cshape", {"transform": "log-weyl-dct"}),
    "truncated Shape-DNA": ("truncated", {}),
    "truncated log spectrum": ("truncated_log", {}),
    "truncated F1": ("f1", {}),
}

#: The families beyond the paper (extensions of cshape), marked as such in the report.
EXTENSIONS = ("log-Weyl DFT", "log-Weyl DCT", "truncated log spectrum")


def family_descriptors(table: DescriptorTable, family, M, N=100) -> np.ndarray:
    """Descriptors of a :data:`FAMILIES` member with ``2M+1`` values, shape (p, 2M+1).

    Raises
    ------
    ValueError
        Unknown family, or the family cannot be computed (``2M+1`` too large for ``N``, or
        a log-Weyl family on a spectrum with a zero eigenvalue after ``lam_0``).
    """
    if family not in FAMILIES:
        raise ValueError(f"family must be one of {list(FAMILIES)}, got {family!r}")
    kind, kw = FAMILIES[family]
    if kind == "f1":
        X = table.descriptors("f1", N=N)
        if X.shape[1] < 2 * M + 1:
            raise ValueError(f"F1 of N={N} has {X.shape[1]} values, fewer than 2M+1 = "
                             f"{2 * M + 1}; use a larger N")
        return X[:, : 2 * M + 1]
    return table.descriptors(kind, M=M, N=N, **kw)


def _retrieval_specs(Ms, N):
    """(title, family or None, M, kind, keywords) of every row of the retrieval table."""
    specs = [("Shape-DNA", None, None, "shape_dna", {"N": N}),
             ("log spectrum (all N-1 log-Weyl ratios)", None, None, "truncated_log",
              {"M": (N - 2) // 2}),
             ("F1", None, None, "f1", {"N": N})]
    for M in Ms:
        for fam in FAMILIES:
            specs.append((f"{fam} M={M}" if FAMILIES[fam][0] == "cshape"
                          else f"{fam} {2 * M + 1}", fam, M, None, None))
    return specs


def experiment_retrieval(table: DescriptorTable, *, Ms=(16, 8, 4, 2, 1), N=100):
    """Retrieval measures (:func:`cshape.compare.retrieval_scores`) of every descriptor.

    Rows: Shape-DNA (``N`` values), the whole log spectrum (the ``N-1`` log-Weyl ratios,
    a extension beyond the paper) and F1 (``N-2``); then for every ``M`` each of
    :data:`FAMILIES` with ``2M+1`` values.  A descriptor that cannot be computed for the
    table (see :func:`family_descriptors`) is left out.

    Returns
    -------
    list of dict
        One row per descriptor: ``descriptor``, ``family`` (None for the full-length rows),
        ``M``, ``size`` and the six measures.
    """
    rows = []
    for title, fam, M, kind, kw in _retrieval_specs(Ms, N):
        try:
            X = (table.descriptors(kind, **kw) if fam is None
                 else family_descriptors(table, fam, M, N))
        except ValueError:
            continue
        s = retrieval_scores(distance_matrix(X), table.labels)
        rows.append({"descriptor": title, "family": fam, "M": M, "size": X.shape[1], **s})
    return rows


def experiment_sizes(table: DescriptorTable, *, Ms=None, N=100, measure="ft"):
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
    measure : {'nn', 'ft', 'st', 'e', 'dcg', 'map'}, default='ft'
        The measure that decides the winner (first tier).

    Returns
    -------
    dict
        ``measure``, ``Ms``, ``families`` (computed), ``skipped`` ({family: reason}),
        ``reference`` (the measures of Shape-DNA with ``N`` values) and ``rows``: one per
        ``M`` with ``M``, ``size``, ``scores`` ({family: {measure: value}}), ``best``
        (families tied at the best value), ``runner_up``, ``lead``, ``lead_se``.
    """
    from .compare import retrieval_per_query

    if Ms is None:
        Ms = range(min(16, (N - 3) // 2), 0, -1)
    Ms = [int(m) for m in Ms]
    labels = table.labels
    ref = retrieval_scores(table.distance_matrix("shape_dna", N=N), labels)
    rows, skipped = [], {}
    for M in Ms:
        scores, per = {}, {}
        for fam in FAMILIES:
            if fam in skipped:
                continue
            try:
                X = family_descriptors(table, fam, M, N)
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
            "reference": ref, "N": N, "n_shapes": len(table), "rows": rows}


_MEASURES = {"nn": "nearest neighbour", "ft": "first tier", "st": "second tier",
             "e": "E-measure", "dcg": "DCG", "map": "mean average precision"}


def _ranges(ms) -> str:
    """'16..9, 6, 2..1' for descending integers."""
    parts, start = [], None
    for i, m in enumerate(ms):
        if start is None:
            start = m
        if i + 1 == len(ms) or ms[i + 1] != m - 1:
            parts.append(str(m) if m == start else f"{start}..{m}")
            start = None
    return ", ".join(parts)


def size_verdict(sizes, *, name="this collection") -> list:
    """The verdict under the size table, computed from :func:`experiment_sizes`' numbers.

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
    out = [f"Verdict on {name} by {mname} ({sizes['n_shapes']} queries; a lead is given "
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


def experiment_cost(table: DescriptorTable, *, Ms=(16, 8, 4, 2, 1), N=100, repeats=5,
                    database_size=20000, n_queries=100, random_state=0):
    """Descriptor size and comparison time, relative to Shape-DNA with ``N`` values.

    The table's descriptors are resampled (with a tiny jitter) into a database of
    ``database_size`` rows, and ``n_queries`` of them are compared with the whole database.
    Timings, the best of ``repeats`` (the least disturbed by other work on the machine):
    the full distance matrix of the table (``matrix_seconds``), the distances of the queries
    to every database row (``scan_seconds``, the comparison cost the paper's claim is about,
    proportional to the descriptor length), and the exact 10-nearest-neighbour search with
    :class:`cshape.compare.DescriptorIndex` (``search_seconds``, which adds a selection
    whose cost does not depend on the length).

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
    warm = table.descriptors("shape_dna", N=N)  # first calls pay imports and allocations
    distance_matrix(warm)
    DescriptorIndex(warm, algorithm="brute").query(warm[:1], k=1)
    rows = []
    for title, kind, kw in _descriptor_specs(Ms, N):
        if kind == "truncated":
            continue
        X = table.descriptors(kind, **kw)
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


# --------------------------------------------------------------------------- figures
def _grid(n, size=3.2, cols=3):
    from matplotlib.figure import Figure

    rows = (n + cols - 1) // cols
    fig = Figure(figsize=(size * cols, size * rows), layout="constrained")
    axs = np.atleast_1d(fig.subplots(rows, cols)).ravel()
    for ax in axs[n:]:
        ax.set_visible(False)
    return fig, axs


def _mds_figure(table, panels, random_state):
    """MDS panels (Fig. 4-5): square, names up to MDS_MAX_NAMES shapes, one class legend."""
    fig, axs = _grid(len(panels))
    Ys = []
    for ax, (title, kind, kw) in zip(axs, panels, strict=False):
        Ys.append(mds_embedding(table.distance_matrix(kind, **kw), random_state=random_state))
        plot_mds(Ys[-1], labels=table.labels, ax=ax, title=title, legend=False)
    handles, labels = axs[0].get_legend_handles_labels()
    if handles and len(handles) <= MAX_LEGEND_CLASSES:
        fig.legend(handles, labels, loc="outside right upper", fontsize="small", frameon=False)
    elif handles:
        fig.suptitle(f"{len(handles)} classes (colours repeat)", fontsize="small")
    if len(table) <= MDS_MAX_NAMES:  # names last: they are placed in the final layout
        short = short_labels(table.names)
        for ax, Y in zip(axs, Ys, strict=False):
            annotate_points(ax, Y, short)
    return fig


def fig1_selection(table, max_shapes=FIG1_MAX_SHAPES):
    """The shapes of Fig. 1, and a sentence for the report when they are a sample.

    One shape per class, the first of each class in the table; with more than
    ``max_shapes`` classes, the classes are taken evenly spread over their order.  Without
    class labels (or one class), the first ``max_shapes`` shapes.

    Returns
    -------
    names : list of str
    note : str
        Empty when every shape is drawn.
    """
    p = len(table)
    classes = list(dict.fromkeys(table.labels))
    if all(table.labels) and len(classes) > 1:
        rows = [table.labels.index(c) for c in classes]
        if len(rows) > max_shapes:
            pick = np.unique(np.linspace(0, len(rows) - 1, max_shapes).round().astype(int))
            rows = [rows[k] for k in pick]
        how = (f"one shape of each of the {len(classes)} classes" if len(rows) == len(classes)
               else f"one shape of each of {len(rows)} of the {len(classes)} classes (evenly "
               "spread over the classes)")
    else:
        rows = list(range(min(max_shapes, p)))
        how = f"the first {len(rows)} shapes"
    names = [table.names[i] for i in rows]
    note = "" if len(rows) == p else (
        f"Fig. 1 samples: it shows {how}, {len(rows)} of the {p} shapes ("
        + ", ".join(names) + ").")
    return names, note


def _noise_change_figure(noise, levels):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10, 3.6), layout="constrained")
    axs = fig.subplots(1, 2)
    for ax, kind, title in ((axs[0], "shape_dna", "(a) Shape-DNA"),
                            (axs[1], "cshape", "(b) cShape-DNA")):
        top = max(float(noise[lv]["change_" + kind].max()) for lv in levels) or 1.0
        for lv in levels:
            ax.plot(noise[lv]["change_" + kind] / top, ".-", ms=3, lw=0.8, label=f"lam={lv:g}")
        ax.set(xlabel="model", ylabel="||noisy - clean|| / max", title=title)
        ax.legend(fontsize="small")
    return fig


# --------------------------------------------------------------------------- report
def _fmt(x, nd=2):
    return "-" if x is None else f"{x:.{nd}f}"


def _pair(pair, nd=2):
    """'mean / std' of a pair of numbers, '-' for None."""
    return "-" if pair is None else f"{_fmt(pair[0], nd)} / {_fmt(pair[1], nd)}"


def _md_table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(lines)


def _jsonable(obj):
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items() if not str(k).startswith(("D_",
                                                                                     "diff_"))}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
        return obj.item()
    return obj


def reproduce(records, out_dir, *, N=100, M=16, Ms=(8, 4, 2, 1), noise_levels=NOISE_LEVELS,
              noise_seed=0, quality=None, example=None, cache_dir=None, n_jobs=1, client=None,
              progress=True, random_state=0, title="cshape: the paper's Section 3 on our data",
              benchmark=None, benchmark_name=None, benchmark_info=None, size_Ms=None):
    """Run Section 3 on a collection and write a report folder.

    Two collections may take part: ``records`` for the parts of Section 3 that compare a
    shape with versions of itself (distance matrices, the M sweep, noise, mesh quality,
    figures, size and time), and ``benchmark``, a labelled collection, for the retrieval
    tables (every descriptor, and every size ``M = 16 .. 1`` with the verdict under it).
    Without ``benchmark`` the retrieval tables are made on ``records`` when they carry
    class labels.

    Parameters
    ----------
    records : iterable
        The shapes, as :func:`cshape.describe` accepts them; ``(name, label, mesh)`` records
        (or a cshape data collection) give class labels for the retrieval measures.
    out_dir : str or os.PathLike
        Report folder (created): ``report.md``, ``results.json``, ``fig*.png``,
        ``table.npz`` (clean descriptors) and ``table_noise_<lam>.npz``.
    N, M : int, default=100, 16
        The paper's Shape-DNA length and cShape-DNA half-width.
    Ms : sequence of int, default=(8, 4, 2, 1)
        The smaller ``M`` of Section 3.2.
    noise_levels : sequence of float, default=(0.5, 1, 2, 4, 10)
        Section 3.3's noise levels; every shape gets a noisy copy per level
        (:func:`cshape.variants.add_normal_noise`, seeded with ``noise_seed``).  ``()``
        skips the noise experiment.
    quality : (str, str), optional
        Names of a low-quality mesh and its improved remesh (the paper's CM and CS), for
        Fig. 9.
    example : str, optional
        Shape of Fig. 2 (default: the first).
    cache_dir, n_jobs, client, progress
        Passed to :func:`cshape.describe` (eigenvalues are cached, runs resume).
    random_state : int, default=0
        Seed of the MDS embeddings.
    benchmark : iterable, optional
        Labelled shapes for the retrieval tables (as ``records``), e.g.
        ``cshape.data.load_collection('creatures')`` (the held-out instance of the creature
        benchmark) or a downloaded benchmark (``'shrec07-watertight'``, ``'mcgill-3dsb'``,
        ``'tosca'``); its descriptors are saved as ``table_benchmark.npz``.
    benchmark_name, benchmark_info : str, optional
        Its name and a description for the report (default: the collection's).
    size_Ms : sequence of int, optional
        The sizes of the equal-size table (:func:`experiment_sizes`; default 16 .. 1).

    Returns
    -------
    dict
        Every number of the report (also written to ``results.json``).
    """
    from . import plots

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    t_start = time.perf_counter()
    records = list(records)
    kw = {"N": N, "M": M, "cache_dir": cache_dir, "n_jobs": n_jobs, "client": client,
          "progress": progress}
    table = describe(records, **kw)
    _need(table)
    table.save(out / "table.npz")
    results = {"n_shapes": len(table), "classes": sorted(set(table.labels)),
               "failures": table.failures, "N": N, "M": M}
    all_Ms = (M, *[m for m in Ms if m != M])

    # -- Fig. 1 and 2
    sel, results["fig1_note"] = fig1_selection(table)
    figs = {}
    figs["fig1_weyl"] = plots.plot_weyl({n: table.lam[table.index(n)] for n in sel},
                                        {n: table.areas[table.index(n)] for n in sel})
    ex = table.index(example) if example is not None else 0
    figs["fig2_stages"] = plots.plot_shape_dna_stages(table.lam[ex], table.areas[ex],
                                                      name=table.names[ex])
    figs["fig2_dft"] = plots.plot_dft(table.lam[ex], table.areas[ex], M, N=N)

    # -- 3.1 and 3.2
    r31 = experiment_3_1(table, N=N, M=M)
    r32 = experiment_3_2(table, Ms=all_Ms, N=N)
    results["3.1"] = {"mean": r31["mean"], "std": r31["std"]}
    results["3.2"] = r32
    D_sd = r31["D_shape_dna"]
    ticks = {"names": table.names, "labels": table.labels}
    figs["fig3_matrices"] = plots.plot_matrices(
        [D_sd, r31["D_cshape"]], [f"(a) Shape-DNA N={N}", f"(b) cShape-DNA M={M}"], scale=True,
        **ticks)
    figs["fig3_difference"] = plots.plot_matrices(
        [difference_matrix(D_sd, r31["D_cshape"])],
        [f"(c) difference: mean {r31['mean']:.2f}, std {r31['std']:.2f}"], **ticks)
    figs["fig4_mds_cshape"] = _mds_figure(
        table, [(f"Shape-DNA N={N}", "shape_dna", {"N": N})]
        + [(f"cShape-DNA M={m}", "cshape", {"M": m, "N": N}) for m in all_Ms], random_state)
    figs["fig5_mds_truncated_f1"] = _mds_figure(
        table, [(f"truncated N={2 * m + 1}", "truncated", {"M": m}) for m in all_Ms]
        + [(f"F1 N={N}", "f1", {"N": N})], random_state)
    D_ms = [table.distance_matrix("cshape", M=m, N=N) for m in Ms]
    figs["fig6_matrices"] = plots.plot_matrices(D_ms, [f"cShape-DNA M={m}" for m in Ms],
                                                scale=True, **ticks)
    figs["fig6_differences"] = plots.plot_matrices(
        [difference_matrix(D_sd, D) for D in D_ms],
        [f"M={m}: mean {r32['cshape'][m][0]:.2f}, std {r32['cshape'][m][1]:.2f}" for m in Ms],
        **ticks)

    # -- retrieval (every descriptor, every size) on the benchmark, and cost
    btable, bname = table, "the shapes above"
    if benchmark is not None:
        brecords = list(benchmark)
        bname = benchmark_name or _collection_name(benchmark) or "the benchmark"
        benchmark_info = benchmark_info or _collection_info(benchmark)
        btable = describe(brecords, **kw)
        _need(btable)
        btable.save(out / "table_benchmark.npz")
    keep = _single_zero_rows(btable)
    left_out = [btable.names[i] for i in range(len(btable)) if i not in set(keep.tolist())]
    if left_out:  # the log-Weyl ratios and F1 need lam_1 > 0: one component per mesh
        btable = btable.select(keep)
    results["benchmark"] = {"name": bname, "n_shapes": len(btable),
                            "classes": sorted(set(btable.labels)),
                            "failures": btable.failures if benchmark is not None else [],
                            "left_out": left_out,
                            "info": " ".join((benchmark_info or "").split())}
    labelled = len(set(btable.labels)) < len(btable) and all(btable.labels)
    results["retrieval"] = experiment_retrieval(btable, Ms=all_Ms, N=N) if labelled else None
    results["sizes"] = experiment_sizes(btable, Ms=size_Ms, N=N) if labelled else None
    results["verdict"] = size_verdict(results["sizes"], name=bname) if labelled else []
    results["cost"] = experiment_cost(table, Ms=all_Ms, N=N)

    # -- 3.3 noise
    results["3.3"] = None
    if noise_levels:
        from .batch import _load_source
        from .variants import add_normal_noise

        by_name = {}
        for name, _label, src in _named(records, table):
            by_name[name] = src
        noisy_tables, pairs = {}, {}
        for lv in noise_levels:
            recs = [(f"{n}@{lv:g}", table.labels[table.index(n)],
                     add_normal_noise(_load_source(by_name[n]), lam=lv, random_state=noise_seed))
                    for n in table.names]
            noisy_tables[lv] = describe(recs, **{**kw, "progress": progress})
            noisy_tables[lv].save(out / f"table_noise_{lv:g}.npz")
            pairs[lv] = [(n, f"{n}@{lv:g}") for n in table.names]
        noise = experiment_noise(table, noisy_tables, pairs=pairs, N=N, M=M)
        results["3.3"] = noise
        levels = sorted(noise)
        same_rows = all(len(noise[lv]["diff_cshape"]) == len(table) for lv in levels)
        noise_ticks = ticks if same_rows else {}
        figs["fig7_noise_shape_dna"] = plots.plot_matrices(
            [noise[lv]["diff_shape_dna"] for lv in levels],
            [f"lam={lv:g}: {noise[lv]['shape_dna'][0]:.1f} / {noise[lv]['shape_dna'][1]:.1f}"
             for lv in levels], **noise_ticks)
        figs["fig7_noise_cshape"] = plots.plot_matrices(
            [noise[lv]["diff_cshape"] for lv in levels],
            [f"lam={lv:g}: {noise[lv]['cshape'][0]:.1f} / {noise[lv]['cshape'][1]:.1f}"
             for lv in levels], **noise_ticks)
        figs["fig8_noise_change"] = _noise_change_figure(
            noise, [lv for lv in levels if lv in (0.5, 1.0, 10.0)] or levels)

    # -- 3.3 mesh quality
    results["quality"] = None
    if quality is not None:
        from .compare import descriptor_matrix

        a, b = (table.index(q) for q in quality)
        S = descriptor_matrix(table.lam[[a, b]], table.areas[[a, b]], "cshape_complex",
                              M=M, N=N)
        figs["fig9_quality"] = plots.plot_cshape_dna({quality[0]: S[0], quality[1]: S[1]})
        D_cs = r31["D_cshape"]
        off = D_cs[~np.eye(len(D_cs), dtype=bool)]
        results["quality"] = {"pair": list(quality), "distance": float(D_cs[a, b]),
                              "median_distance": float(np.median(off)),
                              "relative": float(D_cs[a, b] / np.median(off))}

    for name, fig in figs.items():
        fig.savefig(out / f"{name}.png", dpi=110)
    results["seconds"] = time.perf_counter() - t_start
    (out / "results.json").write_text(json.dumps(_jsonable(results), indent=1))
    (out / "report.md").write_text(_report(results, figs, title))
    return results


def _single_zero_rows(table) -> np.ndarray:
    """Rows whose spectrum has one zero eigenvalue (``lam_1 > 0``: a connected mesh)."""
    lam = np.asarray(table.lam)
    tol = 1e-8 * np.abs(lam).max(axis=1)
    return np.flatnonzero(lam[:, 1] > tol)


def _collection_name(coll):
    name = getattr(coll, "name", None)
    return name if isinstance(name, str) else None


def _collection_info(coll):
    info = getattr(coll, "info", None)
    return info.get("description") if isinstance(info, dict) else None


def _named(records, table):
    """(name, label, source) of the records, in the names describe gave them."""
    from .batch import _records

    return [r for r in _records(records) if r[0] in table.names]


def _retrieval_report(res) -> list:
    """The report's retrieval section: every descriptor, every size, the verdict."""
    b = res.get("benchmark") or {}
    name = b.get("name", "the shapes above")
    s = [f"## Retrieval on {name} (Princeton Shape Benchmark measures)", ""]
    if not res["retrieval"]:
        return s + ["Not computed: the collection needs class labels with two or more shapes "
                    "per class.", ""]
    s += [f"{b['n_shapes']} shapes in {len(b['classes'])} classes."
          + (f" {b['info']}" if b.get("info") else ""), ""]
    if b.get("failures"):
        s += [f"Skipped (failed): {', '.join(n for n, _ in b['failures'])}", ""]
    if b.get("left_out"):
        s += [f"Left out of the retrieval tables ({len(b['left_out'])}: a second zero "
              "eigenvalue, i.e. several connected components, which the log-Weyl ratios and "
              f"F1 cannot take): {', '.join(b['left_out'])}.", ""]
    s += [_md_table(["descriptor", "size", "NN", "FT", "ST", "E", "DCG", "MAP"],
                    [[r["descriptor"] + ("*" if r["family"] in EXTENSIONS
                                         or r["descriptor"].startswith("log spectrum") else ""),
                      r["size"]] + [_fmt(r[k], 3) for k in ("nn", "ft", "st", "e", "dcg", "map")]
                     for r in res["retrieval"]]), "",
          "\\* extensions beyond the paper: the log-Weyl DFT and DCT crops "
          "(`compact_shape_dna(..., transform='log-weyl' / 'log-weyl-dct')`) and the "
          "truncated log spectrum (the first 2M+1 log-Weyl ratios r_i = log(lam_i^norm / "
          "(4 pi i))). E is the E-measure over the first 32 results (all results when the "
          "collection is smaller), so with small classes it stays well below 1 even for a "
          "perfect ranking.", ""]
    sz = res.get("sizes")
    if sz and sz["rows"]:
        meas = sz["measure"]
        fams = sz["families"]
        s += [f"### Every size: {_MEASURES[meas]} at 2M+1 values, M = {sz['Ms'][0]} .. "
              f"{sz['Ms'][-1]}", "",
              f"The {_MEASURES[meas]} of each descriptor family at equal size on {name} "
              f"(bold: the best at that size; Shape-DNA with N={sz['N']} values: "
              f"{sz['reference'][meas]:.3f}).", ""]
        rows = []
        for r in sz["rows"]:
            cells = []
            for f in fams:
                v = r["scores"].get(f, {}).get(meas)
                txt = _fmt(v, 3)
                cells.append(f"**{txt}**" if f in r["best"] else txt)
            rows.append([r["M"], r["size"], *cells])
        s += [_md_table(["M", "size"] + [f + ("*" if f in EXTENSIONS else "") for f in fams],
                        rows), ""]
        if sz["skipped"]:
            s += ["Not computed: " + "; ".join(f"{f} ({why})" for f, why in
                                               sz["skipped"].items()), ""]
        s += [" ".join(res["verdict"]), ""]
    return s


def _report(res, figs, title):
    N, M = res["N"], res["M"]
    p31 = PAPER["3.1"]
    s = [f"# {title}", "",
         f"{res['n_shapes']} shapes in {len(res['classes'])} classes; N = {N}, M = {M}. "
         f"Run time {res['seconds']:.0f} s. The paper's numbers are for the McGill database "
         "(458 models); ours are for this collection, so expect the same trends, not the "
         "same values.", ""]
    if res["failures"]:
        s += [f"Skipped (failed): {', '.join(n for n, _ in res['failures'])}", ""]
    s += ["## Fig. 1-2: Shape-DNA, normalisation, DFT", ""]
    if res.get("fig1_note"):
        s += [res["fig1_note"], ""]
    s += ["![](fig1_weyl.png)", "",
          "![](fig2_stages.png)", "", "![](fig2_dft.png)", "",
          "## 3.1 Shape-DNA vs cShape-DNA", "",
          "Mean and standard deviation of |scale_255(D_Shape-DNA) - scale_255(D_cShape-DNA)| "
          "over the full matrix (0 to 255).", "",
          _md_table(["", "mean", "std"],
                    [["ours", _fmt(res["3.1"]["mean"]), _fmt(res["3.1"]["std"])],
                     [f"paper (M={p31['M']})", _fmt(p31["mean"]), _fmt(p31["std"])]]),
          "", "![](fig3_matrices.png)", "", "![](fig3_difference.png)", "",
          "## 3.2 The parameter M, and equal-size descriptors", "",
          f"Difference statistics against Shape-DNA N={N} (mean / std).", ""]
    r32 = res["3.2"]
    ext = [(k, t) for k, t in (("log-weyl", "log-Weyl DFT*"), ("log-weyl-dct", "log-Weyl DCT*"),
                               ("truncated_log", "truncated log spectrum*")) if r32.get(k)]
    rows = []
    for m in r32["cshape"]:
        paper = PAPER["3.2"].get(m)
        if paper is None and m == p31["M"]:
            paper = (p31["mean"], p31["std"])
        rows.append([m, 2 * m + 1, _pair(r32["cshape"][m]), _pair(r32["truncated"][m])]
                    + [_pair(r32[k].get(m)) for k, _ in ext] + [_pair(paper)])
    s += [_md_table(["M", "size", "cShape-DNA", "truncated Shape-DNA"] + [t for _, t in ext]
                    + ["paper cShape-DNA"], rows), "",
          f"F1 (N={N}): {_fmt(r32['f1'][0])} / {_fmt(r32['f1'][1])}."
          + (" * Extensions beyond the paper (cshape's `transform=` and the truncated log "
             "spectrum): they are not meant to be faithful to Shape-DNA's distances, so a "
             "large difference here is expected." if ext else ""), "",
          "![](fig4_mds_cshape.png)", "", "![](fig5_mds_truncated_f1.png)", "",
          "![](fig6_matrices.png)", "", "![](fig6_differences.png)", ""]
    s += _retrieval_report(res)
    s += ["## Size and comparison time", "",
          f"Paper: cShape-DNA saves \"up to {PAPER['saving']:.0%}\" of space and time "
          f"(3 values instead of 100 at M=1). Times (best of 5): the full distance matrix "
          f"of the {res['n_shapes']} shapes; the distances of 100 queries to a database of "
          "20000 descriptors resampled from them (scan: the comparison cost); and the exact "
          "10-nearest-neighbour search of the same queries (search).", "",
          _md_table(["descriptor", "values", "bytes", "size saving", "matrix ms", "scan ms",
                     "scan time saving", "search ms"],
                    [[r["descriptor"], r["values"], r["bytes"], f"{r['size_saving']:.0%}",
                      _fmt(1e3 * r["matrix_seconds"], 3), _fmt(1e3 * r["scan_seconds"], 1),
                      f"{r['time_saving']:.0%}", _fmt(1e3 * r["search_seconds"], 1)]
                     for r in res["cost"]]), "",
          "The matrix of a small collection is dominated by fixed overheads; the scan shows "
          "the cost per value; the search adds a selection whose cost does not shrink "
          "with the descriptor.", ""]
    if res["3.3"]:
        rows = []
        for lv, r in sorted(res["3.3"].items()):
            psd = PAPER["3.3"]["shape_dna"].get(lv)
            pcs = PAPER["3.3"]["cshape"].get(lv)
            rows.append([f"{lv:g}", _pair(r["shape_dna"], 1), _pair(psd, 1),
                         _pair(r["cshape"], 1), _pair(pcs, 1)])
        s += ["## 3.3 Noise", "",
              "Clean vs noisy scaled distance matrices (mean / std of the difference).", "",
              _md_table(["lam", "Shape-DNA", "paper", "cShape-DNA", "paper"], rows), "",
              "![](fig7_noise_shape_dna.png)", "", "![](fig7_noise_cshape.png)", "",
              "![](fig8_noise_change.png)", ""]
    if res["quality"]:
        q = res["quality"]
        s += ["## 3.3 Mesh quality", "",
              f"cShape-DNA distance between {q['pair'][0]} and {q['pair'][1]}: "
              f"{q['distance']:.3g}, that is {q['relative']:.2f} times the median distance "
              "between two shapes of the collection.", "", "![](fig9_quality.png)", ""]
    return "\n".join(s)
