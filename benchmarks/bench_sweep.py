"""Benchmark: ``shape_dna`` / ``eigenpairs`` against LaPy from 1K to 1M vertices, stage by stage.

Run from the repository root::

    .venv/bin/python benchmarks/bench_sweep.py --quick          # 1k-10k spheres, real meshes
    .venv/bin/python benchmarks/bench_sweep.py                  # 1k-160k, real meshes
    .venv/bin/python benchmarks/bench_sweep.py --sizes 160k --cshape-threads 1,2
    .venv/bin/python benchmarks/bench_sweep.py --sizes 650k,1m --repeats 1 --no-real
    .venv/bin/python benchmarks/bench_sweep.py --collection 40 --no-sweep --no-real
    .venv/bin/python benchmarks/bench_sweep.py --eigenpairs     # eigenfunctions too

Three tables, each with the load average, every ratio from runs interleaved in this process:

1. **Size sweep** (``--sizes``; unit icospheres of 2.5K-655K vertices, tori of revolution for
   1K and 1M): ``cshape.shape_dna((v, f), N)`` against
   ``lapy.Solver(TriaMesh(v, f), use_cholmod=True).eigs(k=N)`` (LaPy's fastest setting; BLAS
   limited to one thread for both, see SCALE.md), best of ``--repeats``, and the *paired*
   ratio: the median over the repeats of LaPy's time over cshape's in the same repeat (the
   two run next to each other and see the same speed of a machine whose speed drifts; the
   ratio of the bests can pair a fast moment of one with a slow one of the other).  With
   ``--cshape-threads 1,2`` cshape is timed once per value of ``CSHAPE_THREADS``.  Each row
   also splits one further, instrumented cshape run into stages: preparation (checks,
   repair, FEM assembly), factorisation, the block solves, Rayleigh-Ritz (banded and dense
   LAPACK eigensolves) and the rest (orthogonalisation and Python), and LaPy's run into its
   assembly and its eigensolve.
2. **Real meshes** (``--real``, default on when the shared mesh folder exists): every mesh
   of ``../shared/meshes`` (``CSHAPE_SHARED_MESHES``) with 1K-30K vertices, as in 1; the
   summary gives the ratio of the sums (a collection's time) and the median and smallest
   per-mesh ratios.
3. **Collection throughput** (``--collection K``): K meshes (the real meshes in turn, else
   generated ones) described by ``shape_dna`` in a loop and by 2 worker processes,
   against a LaPy loop and 2 LaPy worker processes: meshes per minute.

Eigenvalues are checked against LaPy's (relative difference at most ``--rtol``, 1e-8,
zeros on the scale of the largest value); the exit status is 1 if a check fails, 2 if LaPy
is missing (``pip install --group bench``).  Tables go to ``benchmarks/results/``, named by
what the run measures (:func:`results_stem`): ``sweep_sizes.md``, ``sweep_real_meshes.md``,
``sweep_big_meshes.md`` (650K and 1M), ``sweep_eigenpairs.md``, ``sweep_collection.md``,
``sweep.md`` (sizes and real meshes together), ``sweep_quick.md``.
Nothing here asserts a time.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
import time
import warnings
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

import cshape
from cshape import _cholmod, shapes, spectrum

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import load_average, machine_summary, max_relative_difference  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"

#: Size labels: ('ico', level) for unit icospheres, ('torus', n_major, n_minor) for tori.
SIZES = {
    "1k": ("torus", 50, 20),          # 1,000 vertices
    "2.5k": ("ico", 4),               # 2,562
    "10k": ("ico", 5),                # 10,242
    "40k": ("ico", 6),                # 40,962
    "160k": ("ico", 7),               # 163,842
    "650k": ("ico", 8),               # 655,362
    "1m": ("torus", 1600, 640),       # 1,024,000
}
DEFAULT_SIZES = "1k,2.5k,10k,40k,160k"
QUICK_SIZES = "1k,2.5k,10k"
STAGES = ("prepare", "factorise", "solves", "rayleigh_ritz", "rest")


def make_mesh(label):
    """The mesh of a size label (see :data:`SIZES`)."""
    kind, *args = SIZES[label]
    if kind == "ico":
        return shapes.icosphere(*args)
    return shapes.torus(*args)


def shared_meshes():
    """``$CSHAPE_SHARED_MESHES``, else ``../shared/meshes`` beside the repository."""
    env = os.environ.get("CSHAPE_SHARED_MESHES")
    return Path(env) if env else Path(__file__).resolve().parents[2] / "shared" / "meshes"


def real_meshes(folder=None, lo=1000, hi=30000):
    """``[(name, Mesh)]`` for every OBJ of the shared folder with ``lo..hi`` vertices."""
    folder = Path(folder) if folder else shared_meshes()
    out = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for path in sorted(folder.glob("*/*.obj")):
            mesh = cshape.repair_mesh(cshape.load_mesh(path))
            if lo <= mesh.n_vertices <= hi:
                out.append((path.stem, mesh))
    return out


# ----------------------------------------------------------------------------- timing
@contextlib.contextmanager
def _blas_one_thread():
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        yield


@contextlib.contextmanager
def _env(name, value):
    old = os.environ.get(name)
    if value is None:
        os.environ.pop(name, None)
    else:
        os.environ[name] = str(value)
    try:
        yield
    finally:
        if old is None:
            os.environ.pop(name, None)
        else:
            os.environ[name] = old


def run_cshape(mesh, N, vectors=False, threads=None):
    """Seconds and eigenvalues of ``shape_dna`` (or ``eigenpairs``) on plain arrays."""
    fn = cshape.eigenpairs if vectors else cshape.shape_dna
    with _env("CSHAPE_THREADS", threads), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t = time.perf_counter()
        out = fn((mesh.vertices, mesh.faces), N=N)
        seconds = time.perf_counter() - t
    return seconds, (out[0] if vectors else out)


def run_lapy(mesh, N):
    """Seconds (total, assembly) and eigenvalues of LaPy's fastest setting, one BLAS thread.

    ``Solver.eigs`` always computes the eigenvectors too.
    """
    import lapy

    with _blas_one_thread(), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t = time.perf_counter()
        solver = lapy.Solver(lapy.TriaMesh(mesh.vertices, mesh.faces), use_cholmod=True)
        t_asm = time.perf_counter() - t
        lam, _ = solver.eigs(k=N)
        seconds = time.perf_counter() - t
    return seconds, t_asm, np.asarray(lam)


class _TimedFactor:
    """A factor whose solves add their time to a clock."""

    def __init__(self, factor, clock):
        self._factor, self._clock = factor, clock
        self.name, self.rhs_order = factor.name, factor.rhs_order
        self.inertia = getattr(factor, "inertia", None)

    def _timed(self, fn, *args):
        t = time.perf_counter()
        out = fn(*args)
        self._clock["solves"] += time.perf_counter() - t
        return out

    def solve(self, X):
        return self._timed(self._factor.solve, X)

    def solve_split(self, X, parts=2):
        return self._timed(self._factor.solve_split, X, parts)


@contextlib.contextmanager
def stage_clock():
    """Patch the solver's stages with clocks; yields the dict of seconds per stage."""
    import scipy.linalg as la

    clock = dict.fromkeys(STAGES, 0.0)
    originals = (spectrum._prepare, _cholmod.factorize, la.eig_banded, la.eigh)

    def timed(key, fn, wrap=None):
        def f(*args, **kwargs):
            t = time.perf_counter()
            out = fn(*args, **kwargs)
            clock[key] += time.perf_counter() - t
            return wrap(out) if wrap else out
        return f

    spectrum._prepare = timed("prepare", originals[0])
    _cholmod.factorize = timed("factorise", originals[1],
                               lambda F: _TimedFactor(F, clock))
    la.eig_banded = timed("rayleigh_ritz", originals[2])
    la.eigh = timed("rayleigh_ritz", originals[3])
    try:
        yield clock
    finally:
        spectrum._prepare, _cholmod.factorize, la.eig_banded, la.eigh = originals


def stages(mesh, N, vectors=False, threads=None):
    """Seconds per stage of one instrumented cshape run (``rest``: everything else)."""
    with stage_clock() as clock:
        total, _ = run_cshape(mesh, N, vectors, threads)
    clock["rest"] = total - sum(clock[k] for k in STAGES if k != "rest")
    clock["total"] = total
    return clock


def compare(mesh, N, repeats=3, vectors=False, threads=(None,)):
    """Best-of-``repeats`` times of cshape (per thread setting) and LaPy, interleaved.

    Returns a dict with ``n``, ``cshape`` (thread setting -> seconds), ``lapy``,
    ``lapy_assembly``, ``paired`` (thread setting -> the median over the repeats of LaPy's
    time over cshape's in the same repeat: run next to each other, the two see the same
    speed of the machine, which drifts by 25-50 % within minutes here), ``maxrel``
    (against LaPy), ``stages`` (one instrumented cshape run),
    ``load1`` (1-minute load average at the start), ``same_bits`` (the runs of each thread
    setting, and those of all settings from 2 threads on, gave the same eigenvalues bit
    for bit) and ``threads_maxrel`` (the largest relative difference between the
    settings: one thread and two solve with different block sizes, so they agree to
    rounding).
    """
    load1 = load_average()[0]
    best = {t: np.inf for t in threads}
    paired = {t: [] for t in threads}  # LaPy / cshape within each repeat
    lapy_best = lapy_asm = np.inf
    lam = ref = None
    first = {}  # thread setting -> eigenvalues of its first run
    same_bits = True
    for _ in range(repeats):
        seconds = {}
        for t in threads:
            s, lam_t = run_cshape(mesh, N, vectors, t)
            key = "many" if t is not None and t >= 2 else t
            same_bits = same_bits and np.array_equal(first.setdefault(key, lam_t), lam_t)
            lam = lam_t
            best[t] = min(best[t], s)
            seconds[t] = s
        s, a, ref = run_lapy(mesh, N)
        if s < lapy_best:
            lapy_best, lapy_asm = s, a
        for t in threads:
            paired[t].append(s / seconds[t])
    return {"n": mesh.n_vertices, "cshape": best, "lapy": lapy_best, "lapy_assembly": lapy_asm,
            "paired": {t: float(np.median(v)) for t, v in paired.items()},
            "maxrel": max_relative_difference(np.sort(lam), np.sort(ref)),
            "stages": stages(mesh, N, vectors, threads[-1]), "load1": load1,
            "same_bits": same_bits,
            "threads_maxrel": max(max_relative_difference(np.sort(a), np.sort(b))
                                  for a in first.values() for b in first.values())}


# ----------------------------------------------------------------------------- collection
def _cshape_one(args):
    v, f, N = args
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return cshape.shape_dna((v, f), N=N)


def _lapy_one(args):
    import lapy
    from threadpoolctl import threadpool_limits

    v, f, N = args
    with threadpool_limits(limits=1, user_api="blas"), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return lapy.Solver(lapy.TriaMesh(v, f), use_cholmod=True).eigs(k=N)[0]


def throughput(meshes, N, workers=2):
    """Meshes per minute of cshape and LaPy, in a loop and with ``workers`` processes.

    Worker processes run one BLAS thread each (``OMP_NUM_THREADS`` and friends are set
    before they start); the pool's start-up is not counted (it is warmed up first).
    """
    jobs = [(m.vertices, m.faces, N) for _, m in meshes]
    rows = []
    for name, fn in (("cshape", _cshape_one), ("LaPy", _lapy_one)):
        load1 = load_average()[0]
        with _blas_one_thread():
            t = time.perf_counter()
            for job in jobs:
                fn(job)
            seconds = time.perf_counter() - t
        rows.append({"who": name, "workers": 1, "seconds": seconds, "load1": load1,
                     "per_minute": 60 * len(jobs) / seconds})
        if workers > 1:
            env = {k: "1" for k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS",
                                    "MKL_NUM_THREADS")}
            with contextlib.ExitStack() as stack:
                for k, v in env.items():
                    stack.enter_context(_env(k, v))
                load1 = load_average()[0]
                with ProcessPoolExecutor(workers) as pool:
                    list(pool.map(fn, jobs[:workers]))  # start the workers
                    t = time.perf_counter()
                    list(pool.map(fn, jobs))
                    seconds = time.perf_counter() - t
            rows.append({"who": name, "workers": workers, "seconds": seconds, "load1": load1,
                         "per_minute": 60 * len(jobs) / seconds})
    return rows


# ----------------------------------------------------------------------------- report
def _thread_label(t):
    return "auto" if t is None else str(t)


def sweep_lines(rows, threads, title):
    """Markdown lines of a sweep / real-mesh table."""
    tcols = " | ".join(f"cshape [s] (threads {_thread_label(t)})" for t in threads)
    rcols = " | ".join(f"LaPy / cshape ({_thread_label(t)})" for t in threads)
    pcols = " | ".join(f"paired ({_thread_label(t)})" for t in threads)
    lines = [f"### {title}", "",
             f"| mesh | vertices | {tcols} | LaPy [s] | {rcols} | {pcols} | max rel. diff | "
             "load | cshape stages: prepare / factorise / solves / Rayleigh-Ritz / rest [s] | "
             "LaPy: assembly / eigs [s] |",
             "|---|---:|" + "---:|" * (3 * len(threads) + 3) + "---|---|"]
    for label, r in rows:
        st = r["stages"]
        lines.append(
            f"| {label} | {r['n']:,} | "
            + " | ".join(f"{r['cshape'][t]:.3f}" for t in threads)
            + f" | {r['lapy']:.3f} | "
            + " | ".join(f"**{r['lapy'] / r['cshape'][t]:.2f}**" for t in threads)
            + " | " + " | ".join(f"{r['paired'][t]:.2f}" for t in threads)
            + f" | {r['maxrel']:.1e} | {r['load1']:.2f} | "
            + " / ".join(f"{st[k]:.3f}" for k in STAGES)
            + f" | {r['lapy_assembly']:.3f} / {r['lapy'] - r['lapy_assembly']:.3f} |")
    return lines


def summary_lines(rows, threads):
    """Sum, median and smallest ratios of a set of rows (a collection's view)."""
    out = []
    for t in threads:
        cs = np.array([r["cshape"][t] for _, r in rows])
        lp = np.array([r["lapy"] for _, r in rows])
        ratios = lp / cs
        paired = np.array([r["paired"][t] for _, r in rows])
        out.append(f"threads {_thread_label(t)}: sum cshape {cs.sum():.2f} s, LaPy "
                   f"{lp.sum():.2f} s, ratio of sums **{lp.sum() / cs.sum():.2f}**; per mesh "
                   f"median **{np.median(ratios):.2f}**, smallest {ratios.min():.2f}, largest "
                   f"{ratios.max():.2f}; paired per mesh: median {np.median(paired):.2f}, "
                   f"smallest {paired.min():.2f}")
    return out


def results_stem(quick, eigenpairs, sweep, sizes, real, collection):
    """The name of a run's results file in ``benchmarks/results``, by what the run measures."""
    if quick:
        return "sweep_quick"
    if eigenpairs:
        return "sweep_eigenpairs"
    if sweep and set(sizes) <= {"650k", "1m"} and not real:
        return "sweep_big_meshes"
    if sweep:
        return "sweep" if real else "sweep_sizes"
    if real:
        return "sweep_real_meshes"
    return "sweep_collection" if collection else "sweep"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true",
                        help=f"sizes {QUICK_SIZES}, best of 2 (a few minutes)")
    parser.add_argument("--sizes", default=None,
                        help=f"comma-separated subset of {','.join(SIZES)} "
                             f"(default {DEFAULT_SIZES})")
    parser.add_argument("--no-sweep", action="store_true", help="skip the size sweep")
    parser.add_argument("--real", dest="real", action="store_true", default=None,
                        help="time the real meshes (default: when the folder exists)")
    parser.add_argument("--no-real", dest="real", action="store_false")
    parser.add_argument("--collection", type=int, default=0,
                        help="meshes of the throughput table (default 0: skipped)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=None, help="best of (default 3)")
    parser.add_argument("--cshape-threads", default="auto",
                        help="CSHAPE_THREADS values to time, e.g. '1,2' (default 'auto': unset)")
    parser.add_argument("--eigenpairs", action="store_true",
                        help="time cshape.eigenpairs (eigenvalues and eigenfunctions)")
    parser.add_argument("-N", type=int, default=100)
    parser.add_argument("--rtol", type=float, default=1e-8)
    parser.add_argument("--out", default=None,
                        help="results stem (default: named by what is measured, see results_stem)")
    args = parser.parse_args(argv)
    try:
        import lapy  # noqa: F401
    except ImportError:
        print("LaPy is not installed (pip install --group bench)")
        return 2
    sizes = (args.sizes or (QUICK_SIZES if args.quick else DEFAULT_SIZES)).split(",")
    bad = [s for s in sizes if s not in SIZES]
    if bad:
        parser.error(f"--sizes must be a subset of {','.join(SIZES)}, got {bad}")
    repeats = args.repeats or (2 if args.quick else 3)
    threads = tuple(None if t.strip() == "auto" else int(t)
                    for t in args.cshape_threads.split(","))
    folder = shared_meshes()
    real = folder.is_dir() if args.real is None else args.real
    what = "eigenpairs" if args.eigenpairs else "shape_dna"
    head = machine_summary(libs=("scipy", "lapy"))
    print(head)
    print(f"cshape.{what}(N={args.N}) against LaPy Solver(use_cholmod=True).eigs, best of "
          f"{repeats}, interleaved; BLAS one thread; CSHAPE_THREADS "
          f"{', '.join(map(_thread_label, threads))}\n")
    md = [f"# cshape.{what} against LaPy (N={args.N})", "", head, "",
          f"Best of {repeats}, cshape and LaPy interleaved, BLAS limited to one thread for "
          "both; ratio = LaPy time / cshape time.", ""]
    ok = True

    def check(label, r):
        nonlocal ok
        if not r["maxrel"] <= args.rtol:
            ok = False
            print(f"  ACCURACY: {label} differs from LaPy by {r['maxrel']:.1e}")
        if not r["same_bits"]:
            ok = False
            print(f"  BITS: {label}: cshape's eigenvalues depend on the run (or on the "
                  "number of threads from 2 on)")
        if r["threads_maxrel"] > 1e-10:
            ok = False
            print(f"  THREADS: {label}: one thread and two differ by {r['threads_maxrel']:.1e}")

    def show(label, r):
        st = r["stages"]
        print(f"{label:<22} {r['n']:>9,} "
              + " ".join(f"{r['cshape'][t]:8.3f}" for t in threads)
              + f" {r['lapy']:8.3f} "
              + " ".join(f"{r['lapy'] / r['cshape'][t]:6.2f}" for t in threads)
              + " (paired " + " ".join(f"{r['paired'][t]:.2f}" for t in threads) + ")"
              + f" {r['maxrel']:8.1e} {r['load1']:5.2f}  "
              + "/".join(f"{st[k]:.3f}" for k in STAGES), flush=True)

    if not args.no_sweep:
        rows = []
        for label in sizes:
            r = compare(make_mesh(label), args.N, repeats, args.eigenpairs, threads)
            rows.append((label, r))
            show(label, r)
            check(label, r)
        md += sweep_lines(rows, threads, "Size sweep (icospheres; tori at 1k and 1m)") + [""]
    if real:
        meshes = real_meshes(folder)
        rows = []
        print(f"\nreal meshes of 1K-30K vertices in {folder}: {len(meshes)}")
        for name, mesh in meshes:
            r = compare(mesh, args.N, repeats, args.eigenpairs, threads)
            rows.append((name, r))
            show(name, r)
            check(name, r)
        if rows:
            lines = summary_lines(rows, threads)
            print("\n".join(lines))
            md += sweep_lines(rows, threads, f"Real meshes of 1K-30K vertices ({folder.name})")
            md += [""] + [f"* {line}" for line in lines] + [""]
    if args.collection:
        meshes = real_meshes(folder) if folder.is_dir() else []
        if not meshes:
            meshes = [(f"torus{i}", shapes.torus(40 + 10 * i, 20 + 4 * i)) for i in range(6)]
        coll = [meshes[i % len(meshes)] for i in range(args.collection)]
        nv = [m.n_vertices for _, m in coll]
        print(f"\ncollection: {len(coll)} meshes, {min(nv):,}-{max(nv):,} vertices")
        trows = throughput(coll, args.N, args.workers)
        md += [f"### Collection throughput ({len(coll)} meshes, {min(nv):,}-{max(nv):,} "
               "vertices, shape_dna)", "",
               "| solver | workers | wall [s] | meshes / min | load at start |",
               "|---|---:|---:|---:|---:|"]
        for r in trows:
            print(f"{r['who']:<8} {r['workers']} workers {r['seconds']:8.2f} s "
                  f"{r['per_minute']:8.1f} meshes/min  load {r['load1']:.2f}")
            md.append(f"| {r['who']} | {r['workers']} | {r['seconds']:.2f} | "
                      f"{r['per_minute']:.1f} | {r['load1']:.2f} |")
        md.append("")
    end = machine_summary(libs=())
    print(f"\nat the end: {end}")
    md += [f"At the end: {end}", ""]
    RESULTS.mkdir(parents=True, exist_ok=True)
    stem = args.out or results_stem(args.quick, args.eigenpairs, not args.no_sweep, sizes, real,
                                    args.collection)
    (RESULTS / f"{stem}.md").write_text("\n".join(md))
    print(f"results: {RESULTS / stem}.md")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
