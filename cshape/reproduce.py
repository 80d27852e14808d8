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
    short_label,
)

__all__ = [
    "PAPER",
    "experiment_3_1",
    "experiment_3_2",
    "experiment_cost",
    "experiment_noise",
    "experiment_retrieval",
    "fig1_selection",
    "reproduce",
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
    cShape-DNA (``2M+1`` values) and of the truncated Shape-DNA of the same size; F1 (``N``)
    once.

    Returns
    -------
    dict
        ``{'cshape': {M: (mean, std)}, 'truncated': {M: (mean, std)}, 'f1': (mean, std)}``.
    """
    _need(table)
    D_sd = table.distance_matrix("shape_dna", N=N)
    out = {"N": N, "cshape": {}, "truncated": {}}
    for M in Ms:
        out["cshape"][M] = scaled_difference(D_sd, table.distance_matrix("cshape", M=M, N=N))
        out["truncated"][M] = scaled_difference(D_sd, table.distance_matrix("truncated", M=M))
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


def experiment_retrieval(table: DescriptorTable, *, Ms=(16, 8, 4, 2, 1), N=100):
    """Retrieval measures (:func:`cshape.compare.retrieval_scores`) of every descriptor.

    Returns
    -------
    list of dict
        One row per descriptor: ``descriptor``, ``size`` and the six measures.
    """
    rows = []
    for title, kind, kw in _descriptor_specs(Ms, N):
        s = retrieval_scores(table.distance_matrix(kind, **kw), table.labels)
        rows.append({"descriptor": title, "size": table.descriptors(kind, **kw).shape[1], **s})
    return rows


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
        short = [short_label(n) for n in table.names]
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
              progress=True, random_state=0, title="cshape: the paper's Section 3 on our data"):
    """Run Section 3 on a collection and write a report folder.

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

    # -- retrieval and cost
    labelled = len(set(table.labels)) < len(table) and all(table.labels)
    results["retrieval"] = experiment_retrieval(table, Ms=all_Ms, N=N) if labelled else None
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


def _named(records, table):
    """(name, label, source) of the records, in the names describe gave them."""
    from .batch import _records

    return [r for r in _records(records) if r[0] in table.names]


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
    rows = []
    for m in r32["cshape"]:
        paper = PAPER["3.2"].get(m)
        if paper is None and m == p31["M"]:
            paper = (p31["mean"], p31["std"])
        rows.append([m, 2 * m + 1, _pair(r32["cshape"][m]), _pair(r32["truncated"][m]),
                     _pair(paper)])
    s += [_md_table(["M", "size", "cShape-DNA", "truncated Shape-DNA", "paper cShape-DNA"],
                    rows), "",
          f"F1 (N={N}): {_fmt(r32['f1'][0])} / {_fmt(r32['f1'][1])}.", "",
          "![](fig4_mds_cshape.png)", "", "![](fig5_mds_truncated_f1.png)", "",
          "![](fig6_matrices.png)", "", "![](fig6_differences.png)", ""]
    s += ["## Retrieval (Princeton Shape Benchmark measures)", ""]
    if res["retrieval"]:
        s += [_md_table(["descriptor", "size", "NN", "FT", "ST", "E", "DCG", "MAP"],
                        [[r["descriptor"], r["size"]] + [_fmt(r[k], 3) for k in
                                                         ("nn", "ft", "st", "e", "dcg", "map")]
                         for r in res["retrieval"]]), "",
              "E is the E-measure over the first 32 results (all results when the collection "
              "is smaller), so with small classes it stays well below 1 even for a perfect "
              "ranking.", ""]
    else:
        s += ["Not computed: the collection needs class labels with two or more shapes "
              "per class.", ""]
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
