""":func:`reproduce`: run every experiment and write the report folder.
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass
from functools import reduce
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

import numpy as np

from .._files import atomic_write
from ..batch import describe
from ..compare import difference_matrix
from ..descriptors import PAPER, Descriptor
from .experiments import (
    _MEASURES,
    EXTENSIONS,
    NOISE_LEVELS,
    PAPER_RESULTS,
    _need,
    experiment_3_1,
    experiment_3_2,
    experiment_cost,
    experiment_noise,
    experiment_retrieval,
    experiment_sizes,
    size_verdict,
)
from .figures import _mds_figure, _noise_change_figure, fig1_selection

if TYPE_CHECKING:
    import os
    from collections.abc import Iterable, Mapping, Sequence
    from types import ModuleType

    from matplotlib.figure import Figure

    from ..batch import DescriptorTable


# --------------------------------------------------------------------------- report
def _fmt(x: float | None, nd: int = 2) -> str:
    return "-" if x is None else f"{x:.{nd}f}"


def _pair(pair: Sequence[float] | None, nd: int = 2) -> str:
    """'mean / std' of a pair of numbers, '-' for None."""
    return "-" if pair is None else f"{_fmt(pair[0], nd)} / {_fmt(pair[1], nd)}"


def _md_table(header: Sequence[str], rows: Iterable[Sequence[object]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(lines)


def _jsonable(obj: Any) -> Any:
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


def reproduce(records: Iterable[Any], out_dir: str | os.PathLike[str], *, N: int | None = None,
              M: int | None = None, Ms: Sequence[int] = (8, 4, 2, 1),
              noise_levels: Sequence[float] = NOISE_LEVELS, noise_seed: int = 0,
              quality: tuple[str, str] | None = None, example: str | None = None,
              cache_dir: str | os.PathLike[str] | bool | None = None, n_jobs: int | None = 1,
              client: Any = None, progress: bool = True, random_state: int = 0,
              title: str = "cshape: the paper's Section 3 on our data",
              benchmark: Iterable[Any] | None = None, benchmark_name: str | None = None,
              benchmark_info: str | None = None, size_Ms: Sequence[int] | None = None,
              suite: Mapping[str, Iterable[Any]] | None = None,
              descriptor: Descriptor | None = None) -> dict[str, Any]:
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
        ``table.npz`` (clean descriptors) and ``table_noise_<amplitude>.npz``.
    N, M : int, optional
        The paper's Shape-DNA length and cShape-DNA half-width (default: those of
        ``descriptor``, else of :data:`cshape.PAPER`, 100 and 16).
    Ms : sequence of int, default=(8, 4, 2, 1)
        The smaller ``M`` of Section 3.2.
    noise_levels : sequence of float, default=(0.5, 1, 2, 4, 10)
        Section 3.3's noise levels; every shape gets a noisy copy per level
        (:func:`cshape.data.variants.add_normal_noise`, seeded with ``noise_seed``).  ``()``
        skips the noise experiment.
    noise_seed : int, default=0
        Seed of the noise.
    quality : (str, str), optional
        Names of a low-quality mesh and its improved remesh (the paper's CM and CS), for
        Fig. 9.
    example : str, optional
        Shape of Fig. 2 (default: the first).
    cache_dir : str, os.PathLike, None or False, default=None
        Eigenvalue cache, passed to :func:`cshape.describe` (runs resume).
    n_jobs : int, default=1
        Local worker processes, passed to :func:`cshape.describe`.
    client : dask.distributed.Client or str, optional
        A Dask cluster, passed to :func:`cshape.describe`.
    progress : bool, default=True
        Show progress bars.
    random_state : int, default=0
        Seed of the MDS embeddings.
    title : str, default="cshape: the paper's Section 3 on our data"
        Title of the report.
    benchmark : iterable, optional
        Labelled shapes for the retrieval tables (as ``records``), e.g.
        ``cshape.data.load_collection('creatures')`` (the held-out instance of the creature
        benchmark) or a downloaded benchmark (``'shrec07-watertight'``, ``'mcgill-3dsb'``,
        ``'tosca'``); its descriptors are saved as ``table_benchmark.npz``.
    benchmark_name, benchmark_info : str, optional
        Its name and a description for the report (default: the collection's).
    size_Ms : sequence of int, optional
        The sizes of the equal-size table (:func:`experiment_sizes`; default 16 .. 1).
    suite : dict of str to iterable, optional
        The benchmark suite (:data:`cshape.data.suite.SUITE`), benchmark name -> labelled
        shapes (e.g. the held-out instances): every descriptor of
        :data:`cshape.reproduce.scores.CANDIDATES` on every benchmark, with the exploration
        default (:data:`cshape.DEFAULT`) marked
        (:func:`cshape.reproduce.scores.suite_scores`).
    descriptor : Descriptor, optional
        The cShape-DNA of Section 3 as one value (:data:`cshape.PAPER` with another ``M`` or
        ``N``, e.g. ``cshape.PAPER.replace(M=8)``); instead of ``N`` and ``M``.  Section 3
        compares the paper's descriptor, so its kind, transform and normalisation must be
        the paper's.

    Returns
    -------
    dict
        Every number of the report (also written to ``results.json``).

    Notes
    -----
    Three steps: the numbers (:func:`_compute`: every table and experiment), the figures
    (:func:`_figures`) and the files (:func:`_write`: figures, ``results.json``,
    ``report.md``).
    """
    d = _paper_descriptor(descriptor, N, M)
    run = _Run(N=d.N, M=d.M, Ms=(d.M, *[m for m in Ms if m != d.M]), smaller_Ms=tuple(Ms),
               noise_levels=tuple(noise_levels), noise_seed=noise_seed, quality=quality,
               example=example, random_state=random_state, size_Ms=size_Ms,
               describe={"N": d.N, "cache_dir": cache_dir, "n_jobs": n_jobs,
                         "client": client, "progress": progress})
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    t_start = time.perf_counter()
    results, parts = _compute(list(records), out, run, benchmark=benchmark,
                              benchmark_name=benchmark_name, benchmark_info=benchmark_info,
                              suite=suite)
    figs = _figures(parts, results, run)
    results["seconds"] = time.perf_counter() - t_start
    _write(out, results, figs, title)
    return results


@dataclass(frozen=True)
class _Run:
    """The settings of one :func:`reproduce`: the paper's ``N`` and ``M``, every ``M`` of
    Section 3.2 (``Ms``, ``M`` first; ``smaller_Ms`` as given), the noise and figure options
    and the keyword arguments of :func:`cshape.describe`."""

    N: int
    M: int
    Ms: tuple
    smaller_Ms: tuple
    noise_levels: tuple
    noise_seed: int
    quality: tuple | None
    example: str | None
    random_state: int
    size_Ms: Sequence[int] | None
    describe: dict


def _paper_descriptor(descriptor: Descriptor | None, N: int | None, M: int | None
                      ) -> Descriptor:
    """The cShape-DNA of Section 3: ``descriptor``, or :data:`cshape.PAPER` with N and M."""
    if descriptor is None:
        given = {k: v for k, v in (("N", N), ("M", M)) if v is not None}
        return PAPER.replace(**given)
    if not isinstance(descriptor, Descriptor):
        raise TypeError("descriptor must be a cshape.Descriptor (e.g. cshape.PAPER), got "
                        f"{type(descriptor).__name__}")
    d = descriptor
    if N is not None or M is not None:
        raise ValueError("pass either descriptor= or N and M, not both "
                         "(descriptor.replace(M=...) changes M)")
    if (d.kind, d.transform, d.normalization) != ("cshape", "weyl", "area"):
        raise ValueError(
            f"reproduce compares the paper's cShape-DNA, got {d.label}: pass "
            f"cshape.PAPER.replace(M={d.M}, N={d.N}) (only M and N may change)")
    return d


# --------------------------------------------------------------------------- the numbers
def _compute(records: list[Any], out: Path, run: _Run, *, benchmark: Iterable[Any] | None,
             benchmark_name: str | None, benchmark_info: str | None,
             suite: Mapping[str, Iterable[Any]] | None
             ) -> tuple[dict[str, Any], dict[str, Any]]:
    """Every table and experiment: the results dict, and what the figures need besides."""
    table = describe(records, **run.describe)
    _need(table)
    table.save(out / "table.npz")
    results = {"n_shapes": len(table), "classes": sorted(set(table.labels)),
               "failures": table.failures, "N": run.N, "M": run.M}
    sel, results["fig1_note"] = fig1_selection(table)
    r31 = experiment_3_1(table, N=run.N, M=run.M)
    results["3.1"] = {"mean": r31["mean"], "std": r31["std"]}
    results["3.2"] = experiment_3_2(table, Ms=run.Ms, N=run.N)
    results.update(_compute_retrieval(table, out, run, benchmark, benchmark_name,
                                      benchmark_info))
    results["cost"] = experiment_cost(table, Ms=run.Ms, N=run.N)
    results["suite"] = _compute_suite(suite, run) if suite else None
    results["3.3"] = _compute_noise(records, table, out, run) if run.noise_levels else None
    results["quality"] = None
    if run.quality is not None:
        D_cs = r31["D_cshape"]
        a, b = (table.index(q) for q in run.quality)
        off = D_cs[~np.eye(len(D_cs), dtype=bool)]
        results["quality"] = {"pair": list(run.quality), "distance": float(D_cs[a, b]),
                              "median_distance": float(np.median(off)),
                              "relative": float(D_cs[a, b] / np.median(off))}
    return results, {"table": table, "fig1": sel, "3.1": r31}


def _compute_retrieval(table: DescriptorTable, out: Path, run: _Run,
                       benchmark: Iterable[Any] | None, benchmark_name: str | None,
                       benchmark_info: str | None) -> dict[str, Any]:
    """The retrieval tables (every descriptor, every size) on the benchmark, or the shapes."""
    btable, bname = table, "the shapes above"
    if benchmark is not None:
        bname = benchmark_name or _collection_name(benchmark) or "the benchmark"
        benchmark_info = benchmark_info or _collection_info(benchmark)
        btable = describe(list(benchmark), **run.describe)
        _need(btable)
        btable.save(out / "table_benchmark.npz")
    keep = _describable_rows(btable, max([*run.Ms, *(run.size_Ms or [16])]), run.N)
    left_out = [btable.names[i] for i in range(len(btable)) if i not in set(keep.tolist())]
    if left_out:  # too few non-zero eigenvalues for some descriptor (a mesh of many pieces)
        btable = btable.select(keep)
    labelled = len(set(btable.labels)) < len(btable) and all(btable.labels)
    sizes = experiment_sizes(btable, Ms=run.size_Ms, N=run.N) if labelled else None
    return {
        "benchmark": {"name": bname, "n_shapes": len(btable),
                      "classes": sorted(set(btable.labels)),
                      "failures": btable.failures if benchmark is not None else [],
                      "left_out": left_out, "info": " ".join((benchmark_info or "").split())},
        "retrieval": experiment_retrieval(btable, Ms=run.Ms, N=run.N) if labelled else None,
        "sizes": sizes,
        "verdict": size_verdict(sizes, name=bname) if sizes is not None else [],
    }


def _compute_suite(suite: Mapping[str, Iterable[Any]], run: _Run) -> dict[str, Any]:
    """The benchmark suite: every descriptor on every benchmark, the default marked."""
    from .scores import default_row, suite_scores

    tables: dict[str, DescriptorTable] = {}
    for name, recs in suite.items():
        tables[name] = describe(list(recs), **run.describe)
        _need(tables[name])
    rows = suite_scores(tables)
    return {"benchmarks": {k: {"n_shapes": len(t), "n_classes": len(set(t.labels))}
                           for k, t in tables.items()},
            "rows": rows, "default": default_row(rows)}


def _compute_noise(records: list[Any], table: DescriptorTable, out: Path, run: _Run
                   ) -> dict[float, dict[str, Any]]:
    """Section 3.3: a noisy copy of every shape per level, described and compared."""
    from ..batch.work import load_source
    from ..data.variants import add_normal_noise

    by_name = {name: src for name, _label, src in _named(records, table)}
    noisy_tables: dict[float, DescriptorTable] = {}
    pairs: dict[float, Iterable[tuple[str, str]]] = {}
    for lv in run.noise_levels:
        recs = [(f"{n}@{lv:g}", table.labels[table.index(n)],
                 add_normal_noise(load_source(by_name[n]), amplitude=lv,
                                  random_state=run.noise_seed))
                for n in table.names]
        noisy_tables[lv] = describe(recs, **run.describe)
        noisy_tables[lv].save(out / f"table_noise_{lv:g}.npz")
        pairs[lv] = [(n, f"{n}@{lv:g}") for n in table.names]
    return experiment_noise(table, noisy_tables, pairs=pairs, N=run.N, M=run.M)


# --------------------------------------------------------------------------- the figures
def _figures(parts: dict[str, Any], results: dict[str, Any], run: _Run) -> dict[str, Figure]:
    """The figures of the paper's Fig. 1-9, by name (``fig1_weyl``, ...)."""
    from .. import plots

    table, r31, N, M = parts["table"], parts["3.1"], run.N, run.M
    sel = parts["fig1"]
    figs = {"fig1_weyl": plots.plot_weyl({n: table.lam[table.index(n)] for n in sel},
                                         {n: table.areas[table.index(n)] for n in sel})}
    ex = table.index(run.example) if run.example is not None else 0
    figs["fig2_stages"] = plots.plot_shape_dna_stages(table.lam[ex], table.areas[ex],
                                                      name=table.names[ex])
    figs["fig2_dft"] = plots.plot_dft(table.lam[ex], table.areas[ex], M, N=N)
    figs.update(_section_3_figures(plots, table, r31, results["3.2"], run))
    if results["3.3"]:
        figs.update(_noise_figures(plots, table, results["3.3"]))
    if run.quality is not None:
        a, b = (table.index(q) for q in run.quality)
        S = PAPER.replace(kind="cshape-complex", M=M, N=N).matrix(
            table.lam[[a, b]], table.areas[[a, b]])
        figs["fig9_quality"] = plots.plot_cshape_dna({run.quality[0]: S[0],
                                                      run.quality[1]: S[1]})
    return figs


def _section_3_figures(plots: ModuleType, table: DescriptorTable, r31: dict[str, Any],
                       r32: dict[str, Any], run: _Run) -> dict[str, Figure]:
    """Fig. 3-6: the distance matrices, their differences and the MDS panels."""
    N, M, Ms = run.N, run.M, run.smaller_Ms
    D_sd = r31["D_shape_dna"]
    ticks = {"names": table.names, "labels": table.labels}
    figs = {"fig3_matrices": plots.plot_matrices(
        [D_sd, r31["D_cshape"]], [f"(a) Shape-DNA N={N}", f"(b) cShape-DNA M={M}"],
        scale=True, **ticks)}
    figs["fig3_difference"] = plots.plot_matrices(
        [difference_matrix(D_sd, r31["D_cshape"])],
        [f"(c) difference: mean {r31['mean']:.2f}, std {r31['std']:.2f}"], **ticks)
    figs["fig4_mds_cshape"] = _mds_figure(
        table, [(f"Shape-DNA N={N}", Descriptor("shape-dna", N=N))]
        + [(f"cShape-DNA M={m}", Descriptor("cshape", N=N, M=m)) for m in run.Ms],
        run.random_state)
    figs["fig5_mds_truncated_f1"] = _mds_figure(
        table, [(f"truncated N={2 * m + 1}", Descriptor("truncated", N=N, M=m))
                for m in run.Ms]
        + [(f"F1 N={N}", Descriptor("f1", N=N))], run.random_state)
    D_ms = [table.distance_matrix(Descriptor("cshape", N=N, M=m)) for m in Ms]
    figs["fig6_matrices"] = plots.plot_matrices(D_ms, [f"cShape-DNA M={m}" for m in Ms],
                                                scale=True, **ticks)
    figs["fig6_differences"] = plots.plot_matrices(
        [difference_matrix(D_sd, D) for D in D_ms],
        [f"M={m}: mean {r32['cshape'][m][0]:.2f}, std {r32['cshape'][m][1]:.2f}" for m in Ms],
        **ticks)
    return figs


def _noise_figures(plots: ModuleType, table: DescriptorTable,
                   noise: dict[float, dict[str, Any]]) -> dict[str, Figure]:
    """Fig. 7-8: clean against noisy distance matrices, and how the descriptors change."""
    levels = sorted(noise)
    same_rows = all(len(noise[lv]["diff_cshape"]) == len(table) for lv in levels)
    ticks = {"names": table.names, "labels": table.labels} if same_rows else {}
    return {
        "fig7_noise_shape_dna": plots.plot_matrices(
            [noise[lv]["diff_shape-dna"] for lv in levels],
            [f"amplitude={lv:g}: {noise[lv]['shape-dna'][0]:.1f} / {noise[lv]['shape-dna'][1]:.1f}"
             for lv in levels], **ticks),
        "fig7_noise_cshape": plots.plot_matrices(
            [noise[lv]["diff_cshape"] for lv in levels],
            [f"amplitude={lv:g}: {noise[lv]['cshape'][0]:.1f} / {noise[lv]['cshape'][1]:.1f}"
             for lv in levels], **ticks),
        "fig8_noise_change": _noise_change_figure(
            noise, [lv for lv in levels if lv in (0.5, 1.0, 10.0)] or levels),
    }


# --------------------------------------------------------------------------- the files
def _write(out: Path, results: dict[str, Any], figs: dict[str, Figure], title: str) -> None:
    """The figures as PNG, ``results.json`` and ``report.md``, each written atomically."""
    for name, fig in figs.items():
        def save_png(f: IO[Any], fig: Figure = fig) -> None:
            fig.savefig(f, format="png", dpi=110)

        atomic_write(out / f"{name}.png", save_png)
    atomic_write(out / "results.json",
                 lambda f: f.write(json.dumps(_jsonable(results), indent=1)), binary=False)
    report = _report(results, figs, title)
    atomic_write(out / "report.md", lambda f: f.write(report), binary=False)


def _describable_rows(table: DescriptorTable, M: int, N: int) -> np.ndarray:
    """Rows that every descriptor of the tables can describe at the largest size ``M``.

    Meshes of several pieces are described (their zero modes dropped); one of so many
    pieces that fewer than ``2M+1`` non-zero eigenvalues are left cannot be.
    """
    N = min(N, table.N)
    M = min(M, (N - 2) // 2)
    rows = [table.described(d, warn=False)[1]
            for d in (Descriptor("truncated-log", N=N, M=M),
                      Descriptor("cshape", N=N, M=M, transform="log-weyl-dct"),
                      Descriptor("f1", N=N))]
    return reduce(np.intersect1d, rows)


def _collection_name(coll: object) -> str | None:
    name = getattr(coll, "name", None)
    return name if isinstance(name, str) else None


def _collection_info(coll: object) -> str | None:
    info = getattr(coll, "info", None)
    return info.get("description") if isinstance(info, dict) else None


def _named(records: Iterable[Any], table: DescriptorTable) -> list[tuple[str, str, Any]]:
    """(name, label, source) of the records, in the names describe gave them."""
    from ..batch.run import collection_records

    return [r for r in collection_records(records) if r[0] in table.names]


def _retrieval_report(res: dict[str, Any]) -> list[str]:
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
        s += [f"Left out of the retrieval tables ({len(b['left_out'])}: so many connected "
              "components, hence zero eigenvalues, that fewer than 2M+1 non-zero ones are "
              f"left): {', '.join(b['left_out'])}.", ""]
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


def _suite_report(res: dict[str, Any]) -> list[str]:
    """The report's suite section: every descriptor on every benchmark of the suite."""
    st = res.get("suite")
    if not st:
        return []
    from .scores import suite_markdown

    bench = ", ".join(f"{k} ({v['n_shapes']} shapes, {v['n_classes']} classes)"
                      for k, v in st["benchmarks"].items())
    d = st["default"]
    s = ["## The benchmark suite", "",
         f"Every descriptor on every benchmark: {bench}. Bold: the exploration default "
         "(`cshape.DEFAULT`, chosen by its worst regret over three real collections and the "
         "suite; see benchmarks/results/real_collections.md)"
         + (f", here worst {d['worst']:.3f}, mean {d['mean']:.3f}." if d else "."), ""]
    for m in ("ft", "nn"):
        s += [suite_markdown(st["rows"], title="Suite", measure=m,
                             mark=d["title"] if d else None), ""]
    return s


def _section_3_2_report(res: dict[str, Any]) -> list[str]:
    """The report's Section 3.2: every M against Shape-DNA, beside the paper's numbers."""
    N, p31 = res["N"], PAPER_RESULTS["3.1"]
    s = []
    r32 = res["3.2"]
    ext = [(k, t) for k, t in (("log-weyl", "log-Weyl DFT*"), ("log-weyl-dct", "log-Weyl DCT*"),
                               ("truncated-log", "truncated log spectrum*")) if r32.get(k)]
    rows = []
    for m in r32["cshape"]:
        paper = PAPER_RESULTS["3.2"].get(m)
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
    return s


def _report(res: dict[str, Any], figs: dict[str, Figure], title: str) -> str:
    N, M = res["N"], res["M"]
    p31 = PAPER_RESULTS["3.1"]
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
    s += _section_3_2_report(res)
    s += _retrieval_report(res)
    s += _suite_report(res)
    s += ["## Size and comparison time", "",
          f"Paper: cShape-DNA saves \"up to {PAPER_RESULTS['saving']:.0%}\" of space and time "
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
            psd = PAPER_RESULTS["3.3"]["shape-dna"].get(lv)
            pcs = PAPER_RESULTS["3.3"]["cshape"].get(lv)
            rows.append([f"{lv:g}", _pair(r["shape-dna"], 1), _pair(psd, 1),
                         _pair(r["cshape"], 1), _pair(pcs, 1)])
        s += ["## 3.3 Noise", "",
              "Clean vs noisy scaled distance matrices (mean / std of the difference).", "",
              _md_table(["amplitude", "Shape-DNA", "paper", "cShape-DNA", "paper"], rows), "",
              "![](fig7_noise_shape_dna.png)", "", "![](fig7_noise_cshape.png)", "",
              "![](fig8_noise_change.png)", ""]
    if res["quality"]:
        q = res["quality"]
        s += ["## 3.3 Mesh quality", "",
              f"cShape-DNA distance between {q['pair'][0]} and {q['pair'][1]}: "
              f"{q['distance']:.3g}, that is {q['relative']:.2f} times the median distance "
              "between two shapes of the collection.", "", "![](fig9_quality.png)", ""]
    return "\n".join(s)
