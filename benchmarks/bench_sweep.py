"""Benchmark: ``shape_dna`` / ``eigenpairs`` against LaPy from 1K to 1M vertices, stage by stage.

Run from the repository root (``CSHAPE_SHARED_MESHES`` names the real-mesh folder when the
checkout is not beside ``../shared``)::

    .venv/bin/python benchmarks/bench_sweep.py --quick          # 1k-10k spheres, real meshes
    .venv/bin/python benchmarks/bench_sweep.py --sizes 10k,40k,160k --no-real   # make bench
    .venv/bin/python benchmarks/bench_sweep.py --no-sweep --real --lapy-one-thread
    .venv/bin/python benchmarks/bench_sweep.py --no-real --lapy-one-thread   # 1k-160k
    .venv/bin/python benchmarks/bench_sweep.py --sizes 160k --cshape-threads 1,auto
    .venv/bin/python benchmarks/bench_sweep.py --sizes 1m --repeats 1 --no-real
    .venv/bin/python benchmarks/bench_sweep.py --collection 40 --no-sweep --no-real
    .venv/bin/python benchmarks/bench_sweep.py --eigenpairs     # eigenfunctions too

Each library is timed as its users run it: cshape at its defaults (``CSHAPE_THREADS`` unset,
nothing limited) against LaPy at its defaults, ``lapy.Solver(TriaMesh(v, f)).eigs(k=N)``
with all BLAS threads (LaPy 1.7.0's default is ``use_cholmod=False``: SuperLU), and against
LaPy's fastest setting, ``use_cholmod=True`` (CHOLMOD through cholespy), all BLAS threads
(``--lapy default,cholespy``, the default).  ``--lapy-one-thread`` adds ``use_cholmod=True``
with BLAS held to one thread (threadpoolctl), the setting earlier versions of this script
compared against; ``--cshape-threads 1,auto`` adds cshape on one thread.

Three tables, each naming the processor (:func:`_common.processor`: model, cores, vector
units, caches, load average), every ratio from runs interleaved in this process:

1. **Size sweep** (``--sizes``; unit icospheres of 2.5K-655K vertices, tori of revolution for
   1K and 1M): ``cshape.shape_dna((v, f), N)`` against each LaPy setting, best of
   ``--repeats``, and the *paired* ratio: the median over the repeats of LaPy's time over
   cshape's in the same repeat (the two run next to each other and see the same speed of a
   machine whose speed drifts; the ratio of the bests can pair a fast moment of one with a
   slow one of the other).  Each row also splits one further, instrumented cshape run into
   stages: preparation (checks, repair, FEM assembly), factorisation, the block solves,
   Rayleigh-Ritz (banded and dense LAPACK eigensolves) and the rest (orthogonalisation and
   Python), and LaPy's best run into its assembly, factorisation (``splu`` or
   ``CholeskyFactor``), the solves ARPACK asks for, and the rest of ARPACK.
2. **Real meshes** (``--real``, default on when the shared mesh folder exists): every mesh
   of ``../shared/meshes`` (``CSHAPE_SHARED_MESHES``) with 1K-30K vertices, as in 1; the
   summary gives the ratio of the sums (a collection's time) and the median and smallest
   per-mesh ratios.
3. **Collection throughput** (``--collection K``): K meshes (the real meshes in turn, else
   generated ones) described by ``shape_dna`` in a loop and by a pool of 2 worker
   processes, against the same with each LaPy setting: meshes per minute.

Eigenvalues are checked against every LaPy setting's (relative difference at most
``--rtol``, 1e-8, zeros on the scale of the largest value), and on the icospheres every run
of both libraries against the exact spectrum ``l(l+1)``: LaPy calls ARPACK without a start
vector, so every call starts from a new random vector, and single-vector Lanczos can miss a
copy of an exactly repeated eigenvalue (the table says which library missed one, in how many
runs; cshape is deterministic and must never miss one).  The exit status is 1 if a check
fails, 2 if LaPy is missing (``pip install --group bench``).  The one result file is
``benchmarks/results/sweep.md``: each kind of run (:func:`results_section`: sizes, real
meshes, sizes and real meshes, big meshes, eigenpairs, collection) replaces its own section,
which starts with the command that wrote it; ``--quick`` writes ``sweep_quick.md`` instead.
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
from cshape import shapes, spectrum
from cshape._eigensolver import cholmod as _cholmod

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import (  # noqa: E402
    load_average,
    machine_summary,
    max_relative_difference,
    processor,
    write_section,
)

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
    fn = cshape.spectrum.eigenpairs if vectors else cshape.shape_dna
    with _env("CSHAPE_THREADS", threads), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t = time.perf_counter()
        out = fn((mesh.vertices, mesh.faces), N=N)
        seconds = time.perf_counter() - t
    return seconds, (out[0] if vectors else out)


#: LaPy settings that can be timed: label -> (``use_cholmod`` passed, or None for LaPy's own
#: default; BLAS limited to one thread).
LAPY_SETTINGS = {
    "default": (None, False),     # Solver(TriaMesh(v, f)): as LaPy's users run it
    "cholespy": (True, False),    # use_cholmod=True: LaPy's fastest setting, all BLAS threads
    "cholespy-1t": (True, True),  # use_cholmod=True, BLAS held to one thread (the former figure)
}
DEFAULT_LAPY = "default,cholespy"


def lapy_default_cholmod():
    """LaPy's default ``use_cholmod`` (False in LaPy 1.7.0: SuperLU), read from its signature."""
    import inspect

    import lapy

    return inspect.signature(lapy.Solver).parameters["use_cholmod"].default


def lapy_label(setting):
    """How a LaPy setting is called in the tables."""
    cholmod, one = LAPY_SETTINGS[setting]
    if cholmod is None:
        cholmod = lapy_default_cholmod()
        what = f"LaPy defaults (use_cholmod={cholmod}: {'cholespy' if cholmod else 'SuperLU'})"
    else:
        what = f"LaPy use_cholmod={cholmod} ({'cholespy' if cholmod else 'SuperLU'})"
    return what + (", 1 BLAS thread" if one else ", all BLAS threads")


def lapy_setup(setting):
    """The keyword arguments of ``lapy.Solver`` and the BLAS context of a LaPy setting.

    ``{}`` for ``'default'`` (LaPy picks its own ``use_cholmod``); the context holds BLAS to
    one thread for ``'cholespy-1t'`` and limits nothing otherwise.
    """
    if setting not in LAPY_SETTINGS:
        raise ValueError(f"setting must be one of {', '.join(LAPY_SETTINGS)}, got {setting!r}")
    cholmod, one = LAPY_SETTINGS[setting]
    kwargs = {} if cholmod is None else {"use_cholmod": cholmod}
    return kwargs, (_blas_one_thread() if one else contextlib.nullcontext())


class _TimedLU:
    """A LaPy factor (SuperLU or CHOLMOD) whose solves add their time to a clock."""

    def __init__(self, factor, clock):
        self._factor, self._clock = factor, clock

    def solve(self, b):
        t = time.perf_counter()
        out = self._factor.solve(b)
        self._clock["solves"] += time.perf_counter() - t
        return out

    def __getattr__(self, name):
        return getattr(self._factor, name)


@contextlib.contextmanager
def _lapy_clock():
    """Patch LaPy's factorisations (SuperLU's ``splu``, its ``CholeskyFactor``) with clocks."""
    import scipy.sparse.linalg as sla
    from lapy import solver as lsolver

    clock = {"factorise": 0.0, "solves": 0.0}
    splu, chol = sla.splu, getattr(lsolver, "CholeskyFactor", None)

    def timed(fn):
        def f(*args, **kwargs):
            t = time.perf_counter()
            out = fn(*args, **kwargs)
            clock["factorise"] += time.perf_counter() - t
            return _TimedLU(out, clock)
        return f

    sla.splu = timed(splu)  # LaPy imports it from scipy.sparse.linalg inside eigs
    if chol is not None:
        lsolver.CholeskyFactor = timed(chol)
    try:
        yield clock
    finally:
        sla.splu = splu
        if chol is not None:
            lsolver.CholeskyFactor = chol


def run_lapy(mesh, N, setting="default"):
    """Seconds, stages and eigenvalues of one LaPy setting (:data:`LAPY_SETTINGS`).

    ``Solver.eigs`` always computes the eigenvectors too.  The stages (``assembly``,
    ``factorise``, ``solves`` inside ARPACK, ``arpack``: the rest of ``eigs``) come from
    clocks around LaPy's factorisation and its solves, in the timed run itself (a clock per
    solve adds microseconds to a Python callback ARPACK makes anyway).
    """
    import lapy

    kwargs, limit = lapy_setup(setting)
    with limit, _lapy_clock() as clock, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t = time.perf_counter()
        solver = lapy.Solver(lapy.TriaMesh(mesh.vertices, mesh.faces), **kwargs)
        t_asm = time.perf_counter() - t
        lam, _ = solver.eigs(k=N)
        seconds = time.perf_counter() - t
    st = {"assembly": t_asm, **clock}
    st["arpack"] = seconds - t_asm - clock["factorise"] - clock["solves"]
    return seconds, st, np.asarray(lam)


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

    def solve_split(self, X, parts=2, threads=None):
        return self._timed(self._factor.solve_split, X, parts, threads)

    def __getattr__(self, name):  # anything else the solver asks of its factor, untimed
        return getattr(self._factor, name)


@contextlib.contextmanager
def stage_clock():
    """Patch the solver's stages with clocks; yields the dict of seconds per stage.

    A hook the solver no longer has is left out (its time falls into ``rest``) and named in
    ``clock['missing']``.
    """
    import scipy.linalg as la

    clock = dict.fromkeys(STAGES, 0.0)
    clock["missing"] = []

    def timed(key, fn, wrap=None):
        def f(*args, **kwargs):
            t = time.perf_counter()
            out = fn(*args, **kwargs)
            clock[key] += time.perf_counter() - t
            return wrap(out) if wrap else out
        return f

    hooks = [(spectrum, "_prepare", "prepare", None),
             (_cholmod, "factorize", "factorise", lambda F: _TimedFactor(F, clock)),
             (la, "eig_banded", "rayleigh_ritz", None), (la, "eigh", "rayleigh_ritz", None)]
    saved = []
    for mod, name, key, wrap in hooks:
        fn = getattr(mod, name, None)
        if fn is None:
            clock["missing"].append(f"{mod.__name__}.{name}")
            continue
        saved.append((mod, name, fn))
        setattr(mod, name, timed(key, fn, wrap))
    try:
        yield clock
    finally:
        for mod, name, fn in saved:
            setattr(mod, name, fn)


def stages(mesh, N, vectors=False, threads=None):
    """Seconds per stage of one instrumented cshape run (``rest``: everything else)."""
    with stage_clock() as clock:
        total, _ = run_cshape(mesh, N, vectors, threads)
    clock["rest"] = total - sum(clock[k] for k in STAGES if k != "rest")
    clock["total"] = total
    return clock


def missed_copies(lam, exact):
    """Whether ``lam`` is off the ``exact`` spectrum (a unit sphere's) by more than 5 % anywhere.

    The discretisation error of the icospheres is below 1 %; a solver that misses one copy of
    a repeated eigenvalue ``l(l+1)`` shifts every later value to the next cluster (>= 10 %).
    """
    lam = np.sort(np.asarray(lam))[: len(exact)]
    return bool(np.any(np.abs(lam[1:] - exact[1:]) / exact[1:] > 0.05))


def compare(mesh, N, repeats=3, vectors=False, threads=(None,), lapy=("default",), exact=None):
    """Best-of-``repeats`` times of cshape (per thread setting) and LaPy (per setting),
    interleaved.

    Each repeat runs cshape once per thread setting, then LaPy once per setting of
    :data:`LAPY_SETTINGS`.  Returns a dict with ``n``, ``cshape`` (thread setting ->
    seconds), ``lapy`` (LaPy setting -> seconds), ``lapy_stages`` (LaPy setting -> the
    stages of its best run), ``paired`` ((LaPy setting, thread setting) -> the median over
    the repeats of LaPy's time over cshape's in the same repeat: run next to each other,
    the two see the same speed of the machine, which drifts by 25-50 % within minutes
    here), ``maxrel`` (cshape against each LaPy setting, the largest), ``stages`` (one
    instrumented cshape run), ``load1`` (1-minute load average at the start), ``same_bits``
    (the runs of each thread setting, and those of all settings from 2 threads on, gave
    the same eigenvalues bit for bit) and ``threads_maxrel`` (the largest relative
    difference between the settings: one thread and two solve with different block sizes,
    so they agree to rounding).  With ``exact`` (a unit sphere's spectrum) every run of each
    library is checked against it: ``cshape_missed`` and ``lapy_missed`` count the runs that
    missed a copy of a repeated eigenvalue (LaPy's ARPACK starts from a new random vector at
    every call), and ``maxrel`` is taken against the LaPy runs that found every copy.  Per LaPy
    setting, ``maxrel`` is against the run that agrees best: ARPACK's random start can take a
    copy from the neighbouring cluster of a multiplet that a mesh's symmetry splits (the
    icosphere's l = 4: 4 + 5 copies, about 6e-4 apart), which no check of copies can see.
    """
    load1 = load_average()[0]
    best = {t: np.inf for t in threads}
    lbest = {s: np.inf for s in lapy}
    lstages = {}
    paired = {(s, t): [] for s in lapy for t in threads}  # LaPy / cshape within each repeat
    lam = None
    refs = {}  # LaPy setting -> eigenvalues of each of its runs
    first = {}  # thread setting -> eigenvalues of its first run
    same_bits = True
    missed = {"cshape": 0, "lapy": 0, "runs_cshape": 0, "runs_lapy": 0}
    good = {}  # LaPy setting -> eigenvalues of a run that found every copy
    for _ in range(repeats):
        seconds = {}
        for t in threads:
            sec, lam_t = run_cshape(mesh, N, vectors, t)
            key = "many" if t is not None and t >= 2 else t
            same_bits = same_bits and np.array_equal(first.setdefault(key, lam_t), lam_t)
            lam = lam_t
            if exact is not None:
                missed["runs_cshape"] += 1
                missed["cshape"] += missed_copies(lam_t, exact)
            best[t] = min(best[t], sec)
            seconds[t] = sec
        for setting in lapy:
            sec, st, lam_l = run_lapy(mesh, N, setting)
            refs.setdefault(setting, []).append(lam_l)
            if exact is not None:
                miss = missed_copies(lam_l, exact)
                missed["runs_lapy"] += 1
                missed["lapy"] += miss
                if not miss:
                    good.setdefault(setting, []).append(lam_l)
            if sec < lbest[setting]:
                lbest[setting], lstages[setting] = sec, st
            for t in threads:
                paired[setting, t].append(sec / seconds[t])
    return {"n": mesh.n_vertices, "cshape": best, "lapy": lbest, "lapy_stages": lstages,
            "paired": {k: float(np.median(v)) for k, v in paired.items()},
            "maxrel": max(min(max_relative_difference(np.sort(lam), np.sort(ref))
                              for ref in runs) for runs in {**refs, **good}.values()),
            "missed": missed if exact is not None else None,
            "stages": stages(mesh, N, vectors, threads[-1]), "load1": load1,
            "same_bits": same_bits,
            "threads_maxrel": max(max_relative_difference(np.sort(a), np.sort(b))
                                  for a in first.values() for b in first.values())}


# ----------------------------------------------------------------------------- collection
def _cshape_one(args):
    v, f, N = args[:3]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return cshape.shape_dna((v, f), N=N)


def _lapy_one(args):
    v, f, N, setting = args
    return run_lapy(cshape.Mesh(v, f), N, setting)[2]


def throughput(meshes, N, workers=2, lapy=("default",)):
    """Meshes per minute of cshape and of each LaPy setting, in a loop and with ``workers``
    processes, each library at its defaults.

    The loop runs in this process; the pool is a ``ProcessPoolExecutor`` as a user would
    write it, nothing limited (cshape's own policy gives its solves one thread in a child
    process; LaPy's BLAS keeps its threads), except the ``cholespy-1t`` setting, which
    holds LaPy's BLAS to one thread (threadpoolctl) in the loop and in the workers.  The
    pool's start-up is not counted (it is warmed up first).  Rows are in the order
    cshape, then each LaPy setting.
    """
    rows = []
    whos = [("cshape", _cshape_one, None)] + [(s, _lapy_one, s) for s in lapy]
    for name, fn, setting in whos:
        jobs = [(m.vertices, m.faces, N, setting) for _, m in meshes]
        load1 = load_average()[0]
        t = time.perf_counter()
        for job in jobs:
            fn(job)
        seconds = time.perf_counter() - t
        rows.append({"who": name, "workers": 1, "seconds": seconds, "load1": load1,
                     "per_minute": 60 * len(jobs) / seconds})
        if workers > 1:
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


def _col(setting, t, threads):
    """A short column name of a (LaPy setting, cshape threads) pair."""
    return setting if len(threads) == 1 else f"{setting} / cshape {_thread_label(t)}"


def legend_lines(lapy, threads):
    """What each column's LaPy setting and cshape setting are."""
    out = [f"* LaPy `{s}`: {lapy_label(s)}." for s in lapy]
    out += [f"* cshape `{_thread_label(t)}`: "
            + ("its defaults (CSHAPE_THREADS unset, nothing limited)." if t is None
               else f"CSHAPE_THREADS={t}.") for t in threads]
    return out


def sweep_lines(rows, threads, lapy, title, processor):
    """Markdown lines of a sweep / real-mesh table."""
    tcols = " | ".join(f"cshape {_thread_label(t)} [s]" for t in threads)
    lcols = " | ".join(f"LaPy {s} [s]" for s in lapy)
    pcols = " | ".join(f"paired ratio ({_col(s, t, threads)})" for s in lapy for t in threads)
    bcols = " | ".join(f"ratio of bests ({_col(s, t, threads)})"
                       for s in lapy for t in threads)
    scols = " | ".join(f"LaPy {s}: assembly / factorise / solves / ARPACK [s]" for s in lapy)
    npair = len(lapy) * len(threads)
    lines = [f"### {title}", "", f"Processor: {processor}.", "",
             f"| mesh | vertices | {tcols} | {lcols} | {pcols} | {bcols} | max rel. diff | "
             f"load | cshape stages: prepare / factorise / solves / Rayleigh-Ritz / rest [s] | "
             f"{scols} |",
             "|---|---:|" + "---:|" * (len(threads) + len(lapy) + 2 * npair + 2) + "---|"
             + "---|" * len(lapy)]
    for label, r in rows:
        st = r["stages"]
        lines.append(
            f"| {label} | {r['n']:,} | "
            + " | ".join(f"{r['cshape'][t]:.3f}" for t in threads) + " | "
            + " | ".join(f"{r['lapy'][s]:.3f}" for s in lapy) + " | "
            + " | ".join(f"**{r['paired'][s, t]:.2f}**" for s in lapy for t in threads) + " | "
            + " | ".join(f"{r['lapy'][s] / r['cshape'][t]:.2f}" for s in lapy for t in threads)
            + f" | {r['maxrel']:.1e} | {r['load1']:.2f} | "
            + " / ".join(f"{st[k]:.3f}" for k in STAGES) + " | "
            + " | ".join(" / ".join(f"{r['lapy_stages'][s][k]:.3f}"
                                    for k in ("assembly", "factorise", "solves", "arpack"))
                         for s in lapy) + " |")
    missing = sorted({m for _, r in rows for m in r["stages"].get("missing", [])})
    if missing:
        lines += ["", f"Stage hooks the solver no longer has (their time is in rest): "
                      f"{', '.join(missing)}."]
    return lines


def missed_lines(rows):
    """A line on the spheres' repeated eigenvalues: which library missed a copy, how often."""
    checked = [(label, r["missed"]) for label, r in rows if r.get("missed")]
    if not checked:
        return []
    parts = [f"{label}: cshape {m['cshape']} of {m['runs_cshape']} runs, LaPy {m['lapy']} of "
             f"{m['runs_lapy']}" for label, m in checked]
    return ["Runs that missed a copy of a repeated eigenvalue of the sphere (every run checked "
            "against the exact spectrum l(l+1)): " + "; ".join(parts) + ".", ""]


def summary_lines(rows, threads, lapy):
    """Sum, median and smallest ratios of a set of rows (a collection's view)."""
    out = []
    for s in lapy:
        for t in threads:
            cs = np.array([r["cshape"][t] for _, r in rows])
            lp = np.array([r["lapy"][s] for _, r in rows])
            ratios = lp / cs
            paired = np.array([r["paired"][s, t] for _, r in rows])
            out.append(f"LaPy {s} against cshape {_thread_label(t)}: sum cshape {cs.sum():.2f} s, "
                       f"LaPy {lp.sum():.2f} s, ratio of sums **{lp.sum() / cs.sum():.2f}**; "
                       f"per mesh median {np.median(ratios):.2f}, smallest {ratios.min():.2f}, "
                       f"largest {ratios.max():.2f}; paired per mesh: median "
                       f"{np.median(paired):.2f}, smallest {paired.min():.2f}")
    return out


#: The one result file; each kind of run replaces its own section (:func:`results_section`).
RESULT = RESULTS / "sweep.md"
#: Where ``--quick`` writes (not kept in the repository).
QUICK_RESULT = RESULTS / "sweep_quick.md"
TITLE = "shape_dna and eigenpairs against LaPy"


def results_section(eigenpairs, sweep, sizes, real, collection):
    """The section of :data:`RESULT` a run writes, by what the run measures."""
    if eigenpairs:
        return "eigenpairs"
    if sweep and set(sizes) <= {"650k", "1m"} and not real:
        return "big meshes"
    if sweep:
        return "sizes and real meshes" if real else "sizes"
    if real:
        return "real meshes"
    return "collection" if collection else "sizes"


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
                        help="CSHAPE_THREADS values to time, e.g. '1,auto' (default 'auto': "
                             "unset, cshape's defaults)")
    parser.add_argument("--lapy", default=DEFAULT_LAPY,
                        help=f"LaPy settings to time, a subset of {','.join(LAPY_SETTINGS)} "
                             f"(default {DEFAULT_LAPY}: LaPy's defaults and use_cholmod=True, "
                             "all BLAS threads)")
    parser.add_argument("--lapy-one-thread", action="store_true",
                        help="also time LaPy use_cholmod=True with BLAS held to one thread "
                             "(the setting 'cholespy-1t')")
    parser.add_argument("--eigenpairs", action="store_true",
                        help="time cshape.spectrum.eigenpairs (eigenvalues and eigenfunctions)")
    parser.add_argument("-N", type=int, default=100)
    parser.add_argument("--rtol", type=float, default=1e-8)
    parser.add_argument("--out", default=None,
                        help="the result file (default benchmarks/results/sweep.md, its section "
                             "for this kind of run; --quick: sweep_quick.md)")
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
    lapy_set = [s.strip() for s in args.lapy.split(",") if s.strip()]
    if args.lapy_one_thread and "cholespy-1t" not in lapy_set:
        lapy_set.append("cholespy-1t")
    bad = [s for s in lapy_set if s not in LAPY_SETTINGS]
    if bad or not lapy_set:
        parser.error(f"--lapy must be a subset of {','.join(LAPY_SETTINGS)}, got {args.lapy!r}")
    lapy_set = tuple(lapy_set)
    repeats = args.repeats or (2 if args.quick else 3)
    threads = tuple(None if t.strip() == "auto" else int(t)
                    for t in args.cshape_threads.split(","))
    folder = shared_meshes()
    real = folder.is_dir() if args.real is None else args.real
    what = "eigenpairs" if args.eigenpairs else "shape_dna"
    head = machine_summary(libs=("scipy", "lapy", "cholespy"))
    proc = processor()
    env = " ".join(f"{k}={os.environ[k]}" for k in ("CSHAPE_SHARED_MESHES", "CSHAPE_THREADS")
                   if k in os.environ)
    command = (f"{env} " if env else "") + "python benchmarks/bench_sweep.py " + " ".join(
        sys.argv[1:] if argv is None else argv)
    print(head)
    print(f"cshape.{what}(N={args.N}) against LaPy Solver.eigs ({', '.join(lapy_set)}), "
          f"best of {repeats}, interleaved; CSHAPE_THREADS "
          f"{', '.join(map(_thread_label, threads))}\n")
    section = results_section(args.eigenpairs, not args.no_sweep, sizes, real, args.collection)
    md = [f"## {section[0].upper() + section[1:]}: cshape.{what} against LaPy (N={args.N})", "",
          f"Measured with `{command.strip()}` (from the repository root).", "", head, "",
          f"Best of {repeats}, cshape and LaPy interleaved in one process.  Paired ratio: the "
          "median over the repeats of LaPy's time over cshape's in the same repeat; ratio of "
          "bests: LaPy's best over cshape's best.", ""] + legend_lines(lapy_set, threads) + [""]
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
        m = r.get("missed")
        if m and m["cshape"]:
            ok = False
            print(f"  COPIES: {label}: cshape missed a copy of a repeated eigenvalue in "
                  f"{m['cshape']} of {m['runs_cshape']} runs")
        if m and m["lapy"]:
            print(f"  note: {label}: LaPy missed a copy of a repeated eigenvalue in "
                  f"{m['lapy']} of {m['runs_lapy']} runs")

    def show(label, r):
        st = r["stages"]
        print(f"{label:<22} {r['n']:>9,} cshape "
              + " ".join(f"{r['cshape'][t]:7.3f}" for t in threads) + " LaPy "
              + " ".join(f"{r['lapy'][s]:7.3f}" for s in lapy_set) + " paired "
              + " ".join(f"{r['paired'][s, t]:5.2f}" for s in lapy_set for t in threads)
              + f" {r['maxrel']:8.1e} load {r['load1']:5.2f}  "
              + "/".join(f"{st[k]:.3f}" for k in STAGES), flush=True)

    out = Path(args.out) if args.out else (QUICK_RESULT if args.quick else RESULT)

    def save(lines, done=False):
        """Write this run's section (after every row, so that a cut run keeps its rows)."""
        tail = [] if done else ["(Incomplete: the run was still going or was stopped here.)", ""]
        write_section(out, section, lines + tail, TITLE)

    if not args.no_sweep:
        rows = []
        title = "Size sweep (icospheres; tori at 1k and 1m)"
        for label in sizes:
            exact = shapes.sphere_spectrum(args.N) if SIZES[label][0] == "ico" else None
            r = compare(make_mesh(label), args.N, repeats, args.eigenpairs, threads, lapy_set,
                        exact)
            rows.append((label, r))
            show(label, r)
            check(label, r)
            save(md + sweep_lines(rows, threads, lapy_set, title, proc))
        md += sweep_lines(rows, threads, lapy_set, title, proc) + [""] + missed_lines(rows)
    if real:
        meshes = real_meshes(folder)
        rows = []
        print(f"\nreal meshes of 1K-30K vertices in {folder}: {len(meshes)}")
        for name, mesh in meshes:
            r = compare(mesh, args.N, repeats, args.eigenpairs, threads, lapy_set)
            rows.append((name, r))
            show(name, r)
            check(name, r)
            save(md + sweep_lines(rows, threads, lapy_set, "Real meshes (so far)", proc))
        if rows:
            lines = summary_lines(rows, threads, lapy_set)
            print("\n".join(lines))
            nv = [r["n"] for _, r in rows]
            md += sweep_lines(rows, threads, lapy_set,
                              f"Real meshes of 1K-30K vertices ({folder.name}: {len(rows)} "
                              f"meshes, {min(nv):,}-{max(nv):,} vertices, median "
                              f"{int(np.median(nv)):,})", proc)
            md += [""] + [f"* {line}" for line in lines] + [""]
    if args.collection:
        meshes = real_meshes(folder) if folder.is_dir() else []
        if not meshes:
            meshes = [(f"torus{i}", shapes.torus(40 + 10 * i, 20 + 4 * i)) for i in range(6)]
        coll = [meshes[i % len(meshes)] for i in range(args.collection)]
        nv = [m.n_vertices for _, m in coll]
        print(f"\ncollection: {len(coll)} meshes, {min(nv):,}-{max(nv):,} vertices")
        trows = throughput(coll, args.N, args.workers, lapy_set)
        base = {r["workers"]: r["seconds"] for r in trows if r["who"] == "cshape"}
        md += [f"### Collection throughput ({len(coll)} meshes, {min(nv):,}-{max(nv):,} "
               "vertices, shape_dna)", "", f"Processor: {proc}.", "",
               "Each library at its defaults in a loop (1 worker) and in a "
               f"`ProcessPoolExecutor({args.workers})`; ratio: LaPy's wall time over cshape's "
               "with as many workers.", "",
               "| solver | workers | wall [s] | meshes / min | LaPy / cshape | load at start |",
               "|---|---:|---:|---:|---:|---:|"]
        for r in trows:
            who = "cshape" if r["who"] == "cshape" else f"LaPy {r['who']}"
            ratio = ("" if r["who"] == "cshape"
                     else f"**{r['seconds'] / base[r['workers']]:.2f}**")
            print(f"{who:<18} {r['workers']} workers {r['seconds']:8.2f} s "
                  f"{r['per_minute']:8.1f} meshes/min {ratio.strip('*'):>5} "
                  f"load {r['load1']:.2f}")
            md.append(f"| {who} | {r['workers']} | {r['seconds']:.2f} | "
                      f"{r['per_minute']:.1f} | {ratio} | {r['load1']:.2f} |")
        md.append("")
    end = machine_summary(libs=())
    print(f"\nat the end: {end}")
    md += [f"At the end: {end}", ""]
    save(md, done=True)
    print(f"results: {out}, section {section!r}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
