"""Benchmark: Shape-DNA (N=100) of big meshes, 10K to 1M vertices: time, peak memory, growth.

Run from the repository root::

    .venv/bin/python benchmarks/bench_bigmesh.py --quick      # 10K and 40K, < 2 minutes
    .venv/bin/python benchmarks/bench_bigmesh.py              # 10K ... 1M (tens of minutes)
    .venv/bin/python benchmarks/bench_bigmesh.py --sizes 160k,640k --no-lapy

The meshes are one family, tori of revolution (``cshape.shapes.torus(n_major, n_minor)``,
``R = 1``, ``r = 0.4``, ``n_major = 2.5 n_minor`` so that the grid cells are about square):
10 240, 40 960, 163 840, 655 360 and 1 024 000 vertices.  Every measurement runs in a fresh
Python process (so that one size's memory cannot hide in another's), which

1. builds the mesh (and, for LaPy, its ``TriaMesh``), then resets the peak resident set
   size (``/proc/self/clear_refs``) and records the resident size as the *baseline*;
2. times the solve: ``cshape.shape_dna(mesh, N)`` (repair checks, FEM assembly,
   eigensolve: all a user pays), or LaPy's fastest setting
   ``lapy.Solver(TriaMesh(v, f), use_cholmod=True).eigs(k=N)`` (assembly and eigensolve);
3. reads the peak resident size ``VmHWM`` from ``/proc/self/status``.

*Peak* is that high-water mark (the whole process, Python and the mesh included);
*solve* is peak minus baseline, the memory the solve itself needed.  Both libraries run at
their defaults, as their users run them (``--threads 0``, the default: nothing limited);
``--threads 1`` limits BLAS and OpenMP to one thread for both (``results/bigmesh.md`` was
measured so; on a shared 2-core machine spinning OpenBLAS threads make ARPACK, LaPy's
eigensolver, several times slower).  LaPy's time against cshape's at its defaults, interleaved
in one process, is ``bench_sweep.py``'s size sweep.  LaPy is run at every size whose
predicted time (from its previous size and a growth exponent of 1.5) fits in
``--lapy-timeout`` seconds; a run that exceeds it is killed and reported as such.

The growth exponent ``p`` of ``time ~ n^p`` (and of the solve memory) is the slope of a
least-squares line through ``(log n, log t)``; the table also gives the local exponent
between neighbouring sizes.  The one result file is ``benchmarks/results/bigmesh.md``: a run
replaces its section (one per set of sizes and threads) and, for two sizes or more, the
figure ``bigmesh.png``; ``--quick`` writes ``bigmesh_quick.*``.  A section is rewritten after
every size, so an interrupted run keeps what it measured.  Nothing here asserts a time.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import (  # noqa: E402
    load_average,
    max_relative_difference,
    proc_status_kib,
    reset_peak,
    write_section,
)
from _common import machine_summary as _machine_summary
from _common import run_child as _run_child  # noqa: E402


def machine_summary():
    """One line: date, machine, memory, library versions and the load average."""
    return _machine_summary(libs=('scipy',))

#: Size label -> (n_major, n_minor) of the torus; vertices = n_major * n_minor.
SIZES = {
    "10k": (160, 64),
    "40k": (320, 128),
    "160k": (640, 256),
    "640k": (1280, 512),
    "1m": (1600, 640),
}
QUICK_SIZES = ["10k", "40k"]
RESULTS = Path(__file__).resolve().parent / "results"
ENGINES = ("cshape", "lapy")


# ----------------------------------------------------------------------------- memory
# ----------------------------------------------------------------------------- one run
def make_mesh(n_major, n_minor):
    """The benchmark torus with ``n_major * n_minor`` vertices."""
    from cshape import shapes

    return shapes.torus(int(n_major), int(n_minor), R=1.0, r=0.4)


def measure(engine, n_major, n_minor, N=100):
    """Time and memory of one Shape-DNA solve, in this process.

    Parameters
    ----------
    engine : {'cshape', 'lapy'}
    n_major, n_minor : int
        Torus resolution (``n_major * n_minor`` vertices).
    N : int, default=100
        Number of eigenvalues.

    Returns
    -------
    dict
        ``engine``, ``n_vertices``, ``seconds`` (wall clock of the solve), ``baseline_mib``
        (resident size before it), ``peak_mib`` (peak resident size of the process),
        ``solve_mib`` (peak minus baseline), ``peak_reset`` (whether the peak could be
        reset after building the mesh) and ``lam`` (list of N ascending eigenvalues).
    """
    if engine not in ENGINES:
        raise ValueError(f"engine must be one of {ENGINES}, got {engine!r}")
    mesh = make_mesh(n_major, n_minor)
    if engine == "cshape":
        import cshape

        def solve():
            return cshape.shape_dna(mesh, N=N)
    else:
        from lapy import Solver, TriaMesh

        v, f = np.array(mesh.vertices), np.array(mesh.faces)

        def solve():
            lam, _ = Solver(TriaMesh(v, f), use_cholmod=True).eigs(k=N)
            return np.sort(lam)

    reset = reset_peak()
    base = proc_status_kib("VmRSS")
    t0 = time.perf_counter()
    lam = solve()
    seconds = time.perf_counter() - t0
    peak = proc_status_kib("VmHWM")
    return {
        "engine": engine,
        "n_vertices": int(mesh.n_vertices),
        "seconds": seconds,
        "baseline_mib": base / 1024,
        "peak_mib": peak / 1024,
        "solve_mib": (peak - base) / 1024,
        "peak_reset": reset,
        "lam": [float(x) for x in lam],
    }


def run_child(engine, dims, N, threads, timeout):
    """:func:`measure` in a fresh Python process; None if it timed out or failed.

    Returns
    -------
    dict or None
        The result of :func:`measure`, or ``{'error': message}``.
    """
    return _run_child(Path(__file__).resolve(),
                      ["--child", engine, f"{dims[0]}x{dims[1]}", "-N", N],
                      threads=threads, timeout=timeout)


# ----------------------------------------------------------------------------- analysis
def growth_exponent(n, y):
    """Slope ``p`` of the least-squares line through ``(log n, log y)`` (NaN if < 2 points)."""
    n = np.asarray(n, dtype=float)
    y = np.asarray(y, dtype=float)
    ok = np.isfinite(y) & (y > 0)
    if ok.sum() < 2:
        return float("nan")
    return float(np.polyfit(np.log(n[ok]), np.log(y[ok]), 1)[0])


def _fmt(x, spec):
    return "-" if x is None or not np.isfinite(x) else format(x, spec)


def table_rows(rows):
    """Rows of the printed / markdown table (strings), with the local exponents."""
    out = []
    prev = None
    for r in rows:
        local = float("nan")
        if prev is not None:
            local = np.log(r["cshape_s"] / prev["cshape_s"]) / np.log(r["n"] / prev["n"])
        ratio = r["lapy_s"] / r["cshape_s"] if np.isfinite(r["lapy_s"]) else float("nan")
        out.append([
            f"{r['n']:,}", _fmt(r["cshape_s"], ".2f"), _fmt(local, ".2f"),
            _fmt(r["cshape_peak"], ".0f"), _fmt(r["cshape_solve"], ".0f"),
            _fmt(r["lapy_s"], ".2f") if np.isfinite(r["lapy_s"]) else r["lapy_note"] or "-",
            _fmt(r["lapy_peak"], ".0f"), _fmt(r["lapy_solve"], ".0f"), _fmt(ratio, ".2f"),
            _fmt(r["maxrel"], ".1e"),
        ])
        prev = r
    return out


HEADER = ["vertices", "cshape [s]", "local p", "cshape peak [MiB]", "cshape solve [MiB]",
          "LaPy [s]", "LaPy peak [MiB]", "LaPy solve [MiB]", "LaPy/cshape", "max rel diff"]


TITLE = "Shape-DNA (N=100) of big meshes: time, peak memory, growth"


def section_key(labels, threads):
    """The section of the result file a run writes: its sizes and BLAS threads."""
    return f"sizes {','.join(labels)}, threads {threads}"


def write_results(rows, path, key, summary, N, threads):
    """The run's section of the Markdown result file ``path`` and, for two sizes or more, the
    figure beside it (``path`` with ``.png``, if matplotlib is there)."""
    n = [r["n"] for r in rows]
    exps = {
        "cshape time": growth_exponent(n, [r["cshape_s"] for r in rows]),
        "cshape solve memory": growth_exponent(n, [r["cshape_solve"] for r in rows]),
        "LaPy time": growth_exponent(n, [r["lapy_s"] for r in rows]),
        "LaPy solve memory": growth_exponent(n, [r["lapy_solve"] for r in rows]),
    }
    lines = [f"## {', '.join(r['label'] for r in rows)} vertices, N = {N}, BLAS/OpenMP threads: "
             f"{threads}", "", summary, "",
             f"Tori of revolution, one fresh process per run, BLAS/OpenMP threads: {threads}.",
             "Peak = peak resident size of the process; solve = peak minus the resident size "
             "before the solve.", "",
             "| " + " | ".join(HEADER) + " |", "|" + "---|" * len(HEADER)]
    lines += ["| " + " | ".join(c) + " |" for c in table_rows(rows)]
    lines += ["", "Growth exponents p (log-log least squares over the sizes measured):", ""]
    lines += [f"- {k}: {_fmt(v, '.2f')}" for k, v in exps.items()]
    write_section(path, key, lines + [""], TITLE)
    if len(rows) < 2:
        return exps
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:  # pragma: no cover
        return exps
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for key, lab, mark in (("cshape", "cshape", "o-"), ("lapy", "LaPy (CHOLMOD)", "s--")):
        t = np.array([r[f"{key}_s"] for r in rows], dtype=float)
        m = np.array([r[f"{key}_peak"] for r in rows], dtype=float)
        ok = np.isfinite(t)
        if ok.any():
            p = exps["cshape time" if key == "cshape" else "LaPy time"]
            axes[0].loglog(np.array(n)[ok], t[ok], mark, label=f"{lab}, p = {p:.2f}")
            axes[1].loglog(np.array(n)[ok], m[ok], mark, label=lab)
    axes[0].set_xlabel("vertices")
    axes[0].set_ylabel("time [s]")
    axes[0].set_title(f"Shape-DNA, N = {N}: time")
    axes[1].set_xlabel("vertices")
    axes[1].set_ylabel("peak resident memory [MiB]")
    axes[1].set_title("peak memory")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.tight_layout()
    fig.savefig(Path(path).with_suffix(".png"), dpi=110)
    plt.close(fig)
    return exps


# ----------------------------------------------------------------------------- main
def _parse_dims(text):
    a, b = text.lower().split("x")
    return int(a), int(b)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="10K and 40K only (< 2 minutes)")
    parser.add_argument("--sizes", default=None,
                        help=f"comma-separated subset of {','.join(SIZES)} (default: all)")
    parser.add_argument("-N", type=int, default=100, help="number of eigenvalues (default 100)")
    parser.add_argument("--threads", type=int, default=0,
                        help="BLAS/OpenMP threads of both libraries (default 0: each library "
                             "at its defaults)")
    parser.add_argument("--no-lapy", action="store_true", help="skip LaPy")
    parser.add_argument("--lapy-timeout", type=float, default=1200.0,
                        help="largest time for one LaPy run in seconds (default 1200)")
    parser.add_argument("--timeout", type=float, default=3600.0,
                        help="largest time for one cshape run in seconds (default 3600)")
    parser.add_argument("--rtol", type=float, default=1e-8,
                        help="largest accepted relative eigenvalue difference (default 1e-8)")
    parser.add_argument("--child", default=None, help=argparse.SUPPRESS)
    parser.add_argument("dims", nargs="?", default=None, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)

    if args.child:  # one measurement in this (fresh) process; JSON on the last line
        print(json.dumps(measure(args.child, *_parse_dims(args.dims), N=args.N)))
        return 0

    if args.sizes:
        labels = [s.strip().lower() for s in args.sizes.split(",") if s.strip()]
        bad = [s for s in labels if s not in SIZES]
        if bad:
            parser.error(f"--sizes must be a subset of {','.join(SIZES)}, got {bad}")
    else:
        labels = QUICK_SIZES if args.quick else list(SIZES)
    threads = None if args.threads == 0 else args.threads
    use_lapy = not args.no_lapy
    if use_lapy:
        try:
            import lapy  # noqa: F401
        except ImportError:
            print("LaPy is not installed (pip install --group bench): running cshape only")
            use_lapy = False
    path = RESULTS / ("bigmesh_quick.md" if args.quick else "bigmesh.md")
    key = section_key(labels, threads or "default")
    summary = machine_summary()
    print(summary)
    print(f"N={args.N}, tori, one fresh process per run, BLAS/OpenMP threads: "
          f"{threads or 'default'}\n")
    widths = [10, 10, 7, 17, 18, 16, 15, 16, 11, 12]
    print("  ".join(h.rjust(w) for h, w in zip(HEADER, widths, strict=True)))
    rows = []
    failed = False
    lapy_last = None  # (n, seconds) of LaPy's largest successful run
    lapy_dead = None
    loads = []
    for label in labels:
        dims = SIZES[label]
        n = dims[0] * dims[1]
        loads.append(load_average()[0])
        cs = run_child("cshape", dims, args.N, threads, args.timeout)
        row = {"label": label, "n": n, "cshape_s": float("nan"), "cshape_peak": float("nan"),
               "cshape_solve": float("nan"), "lapy_s": float("nan"),
               "lapy_peak": float("nan"), "lapy_solve": float("nan"), "lapy_note": "",
               "maxrel": float("nan"), "load1": loads[-1]}
        if "error" in cs:
            print(f"{n:>10,}  cshape failed: {cs['error']}")
            failed = True
            continue
        row.update(cshape_s=cs["seconds"], cshape_peak=cs["peak_mib"],
                   cshape_solve=cs["solve_mib"])
        if use_lapy:
            predicted = 0.0 if lapy_last is None else lapy_last[1] * (n / lapy_last[0]) ** 1.5
            if lapy_dead:
                row["lapy_note"] = lapy_dead
            elif predicted > args.lapy_timeout:
                row["lapy_note"] = f"skipped (~{predicted:.0f} s predicted)"
            else:
                lp = run_child("lapy", dims, args.N, threads, args.lapy_timeout)
                if "error" in lp:
                    row["lapy_note"] = lp["error"]
                    lapy_dead = f"not run (LaPy {lp['error']} at a smaller size)"
                else:
                    row.update(lapy_s=lp["seconds"], lapy_peak=lp["peak_mib"],
                               lapy_solve=lp["solve_mib"],
                               maxrel=max_relative_difference(cs["lam"], lp["lam"]))
                    lapy_last = (n, lp["seconds"])
                    failed |= not row["maxrel"] <= args.rtol
        rows.append(row)
        cells = table_rows(rows)[-1]
        print("  ".join(c.rjust(w) for c, w in zip(cells, widths, strict=True)), flush=True)
        write_results(rows, path, key, summary, args.N, threads or "default")
    if not rows:
        return 1
    summary_end = machine_summary()
    exps = write_results(rows, path, key, summary + f"\n\nAt the end: {summary_end}", args.N,
                         threads or "default")
    print("\ngrowth exponents (time ~ n^p): " + ", ".join(
        f"{k} {_fmt(v, '.2f')}" for k, v in exps.items()))
    print(f"load average at the start of each size: {', '.join(f'{x:.2f}' for x in loads)}")
    print(f"at the end: {summary_end}")
    print(f"results: {path}, section {key!r}" + (", and its figure" if len(rows) > 1 else ""))
    if failed:
        print(f"\nFAIL: a run failed or eigenvalues differ from LaPy's by more than "
              f"rtol={args.rtol:g}")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
