"""Benchmark: exact k-nearest-neighbour queries against 10^6 stored descriptors.

Run from the repository root::

    .venv/bin/python benchmarks/bench_queries.py --quick      # 10^5 descriptors, < 2 minutes
    .venv/bin/python benchmarks/bench_queries.py              # 10^6 descriptors
    .venv/bin/python benchmarks/bench_queries.py --size 300000 --base 100

The paper claims that the compact Shape-DNA "reduces up to 97% space and time consumptions
compared to Shape-DNA" (3 reals at M = 1 instead of N = 100).  This measures it for the
descriptors it recommends, cShape-DNA with M = 16 (33 reals), and for M = 1 (3 reals),
against the area-normalised Shape-DNA with N = 100:

1. *Base spectra*: real Shape-DNAs (N = 100) of ``--base`` generated meshes of 0.8K-5K
   vertices (tori, ellipsoids, boxes and real meshes, stretched and noisy; see
   ``bench_throughput.make_collection``), area-normalised.
2. *Database*: ``--size`` rows, each a base spectrum times a smooth random factor
   ``1 + 0.03 g0 + 0.03 g1 i/N + 0.005 e_i`` (``g0, g1, e_i`` standard normal): the
   few-percent, low-frequency changes that deformation, noise and remeshing cause.  The
   cShape-DNA rows are computed from these spectra with a vectorised Eq. (8)-(10) and
   :func:`cshape.descriptors.real_form`, checked against :meth:`cshape.Descriptor.matrix`.
3. *Queries*: new perturbations of the base spectra, ``k = 10`` neighbours, exact search by

   * ``DescriptorIndex``: :class:`cshape.DescriptorIndex` (scikit-learn; its 'auto' choice:
     brute force for 33 and 100 values, a k-d tree for 3);
   * ``numpy``: plain NumPy brute force, ``|x|^2 - 2 X q + |q|^2`` with one matrix-vector
     product (for a batch, one matrix product per 8 queries), ``argpartition``, and the
     exact distances of the candidates recomputed and sorted.

Each (descriptor, method) pair runs in a fresh process that loads the database and reports
the build time, the latency of single queries (median of ``--single`` queries one at a
time) and of a batch (``--batch`` queries in one call, time per query), the memory the
index adds to the stored array, and the peak extra memory while querying (``VmHWM`` after a
reset).  The pairs run in ``--repeats`` interleaved rounds and each figure is the best.
BLAS runs with ``--threads`` threads (default 1).  Both methods must return the same
neighbour distances.  Results: ``benchmarks/results/queries.md``
(``queries_quick.*`` with ``--quick``).  Nothing here asserts a time.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import load_average, proc_status_kib, reset_peak  # noqa: E402
from _common import machine_summary as _machine_summary
from _common import run_child as _run_child  # noqa: E402


def machine_summary():
    """One line: date, machine, memory, library versions and the load average."""
    return _machine_summary(libs=('sklearn',))

RESULTS = Path(__file__).resolve().parent / "results"
FOUR_PI = 4.0 * np.pi
#: Descriptor name -> (kind, M) ; the length is N for 'shape-dna' and 2M+1 otherwise.
DESCRIPTORS = {
    "Shape-DNA N=100": ("shape-dna", None),
    "cShape-DNA M=16": ("cshape", 16),
    "cShape-DNA M=1": ("cshape", 1),
}
METHODS = ("DescriptorIndex", "numpy")


# ----------------------------------------------------------------------------- helpers
def _sibling(name):
    """Import ``benchmarks/<name>.py`` (works whether or not benchmarks/ is on sys.path)."""
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, Path(__file__).with_name(f"{name}.py"))
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod
    spec.loader.exec_module(mod)
    return mod


# ----------------------------------------------------------------------------- data
def base_spectra(count, N=100, seed=0, resolution="low"):
    """Area-normalised Shape-DNAs of ``count`` generated meshes, shape (count, N)."""
    from cshape import describe

    collection = _sibling("bench_throughput").make_collection(count, resolution, seed=seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        table = describe(collection, N=N, cache_dir=False, progress=False)
    return table.lam * table.areas[:, None]


def perturb(base, rows, rng, out=None):
    """Random smooth perturbations of base spectra (see the module docstring).

    Parameters
    ----------
    base : ndarray, shape (p, N)
        Normalised spectra.
    rows : int
        Number of perturbed spectra.
    rng : numpy.random.Generator
    out : ndarray, shape (rows, N), optional
        Where to write them.

    Returns
    -------
    ndarray, shape (rows, N)
    """
    p, N = base.shape
    if out is None:
        out = np.empty((rows, N))
    t = np.arange(N) / N
    chunk = 100_000
    for lo in range(0, rows, chunk):
        hi = min(rows, lo + chunk)
        m = hi - lo
        pick = rng.integers(0, p, size=m)
        g = rng.standard_normal((m, 2))
        factor = 1.0 + 0.03 * g[:, :1] + 0.03 * g[:, 1:] * t + 0.005 * rng.standard_normal((m, N))
        np.multiply(base[pick], factor, out=out[lo:hi])
    return out


def cshape_rows(lam_norm, M):
    """Real-form cShape-DNAs (Eq. 8-10) of normalised spectra, one per row, vectorised.

    Parameters
    ----------
    lam_norm : ndarray, shape (p, N)
    M : int

    Returns
    -------
    ndarray, shape (p, 2M+1)
        Same values as ``Descriptor('cshape', N=N, M=M).matrix(lam_norm, np.ones(p))``.
    """
    from cshape.descriptors import real_form

    p, N = lam_norm.shape
    out = np.empty((p, 2 * M + 1))
    c = N // 2
    line = FOUR_PI * np.arange(N)
    for lo in range(0, p, 100_000):
        blk = lam_norm[lo:lo + 100_000] - line  # Eq. (8)
        S = np.fft.fftshift(np.fft.fft(blk, axis=1), axes=1)[:, c - M:c + M + 1]  # Eq. (9-10)
        out[lo:lo + 100_000] = real_form(S)
    return out


def descriptors(lam_norm, name):
    """The database / query rows of descriptor ``name`` (a key of :data:`DESCRIPTORS`)."""
    kind, M = DESCRIPTORS[name]
    if kind == "shape-dna":
        return lam_norm
    return cshape_rows(lam_norm, M)


# ----------------------------------------------------------------------------- search
class NumpyBruteForce:
    """Exact k-NN by plain NumPy: ``|x|^2 - 2 X q + |q|^2``, argpartition, exact re-rank.

    Parameters
    ----------
    X : ndarray, shape (n, d)
        The database (kept by reference, not copied).
    group : int, default=8
        Queries per matrix product in a batch (memory about ``16 * group * n`` bytes; 8 was
        the fastest of 4, 8, 16 and 32 here: the ``argpartition`` over all ``n`` distances
        of each query, not the product, dominates).
    """

    def __init__(self, X, group=8):
        self.X = np.ascontiguousarray(X, dtype=np.float64)
        self.xx = np.einsum("ij,ij->i", self.X, self.X)
        self.group = int(group)

    def _rerank(self, q, cand, k):
        d = np.sqrt(((self.X[cand] - q) ** 2).sum(1))
        o = np.argsort(d, kind="stable")[:k]
        return d[o], cand[o]

    def query(self, Q, k=10):
        """Distances and indices of the ``k`` nearest rows of each query, shape (q, k)."""
        Q = np.atleast_2d(np.asarray(Q, dtype=np.float64))
        kk = min(len(self.X), 2 * k)  # candidates, re-ranked with exact distances
        dist = np.empty((len(Q), k))
        ind = np.empty((len(Q), k), dtype=np.int64)
        for lo in range(0, len(Q), self.group):
            Qg = Q[lo:lo + self.group]
            if len(Qg) == 1:
                d2 = (self.xx - 2.0 * (self.X @ Qg[0]))[None, :]
            else:
                d2 = self.xx - 2.0 * (Qg @ self.X.T)  # (group, n), rows contiguous
            cand = np.argpartition(d2, kk - 1, axis=1)[:, :kk]
            for j in range(len(Qg)):
                dist[lo + j], ind[lo + j] = self._rerank(Qg[j], cand[j], k)
        return dist, ind


def build(method, X):
    """An index of ``X`` for ``method`` ('DescriptorIndex' or 'numpy')."""
    if method == "DescriptorIndex":
        from cshape import DescriptorIndex

        return DescriptorIndex(X)
    if method == "numpy":
        return NumpyBruteForce(X)
    raise ValueError(f"method must be one of {METHODS}, got {method!r}")


def measure(method, X, Q, k=10, n_single=20):
    """Build an index of ``X`` and time queries with ``Q``, in this process.

    Parameters
    ----------
    method : {'DescriptorIndex', 'numpy'}
    X : ndarray, shape (n, d)
        Database.
    Q : ndarray, shape (q, d)
        Queries: the first ``n_single`` are sent one at a time, then all of them as one
        batch.
    k : int, default=10
    n_single : int, default=20

    Returns
    -------
    result : dict
        ``build_s``; ``single_ms`` (median latency of one query) and ``batch_ms`` (batch
        time per query), in milliseconds; ``db_mib`` (the stored array),
        ``index_mib`` (resident memory the index added), ``query_mib`` (peak extra
        resident memory while querying).
    dist : ndarray, shape (q, k)
        Neighbour distances of the batch.
    """
    import sklearn.neighbors  # noqa: F401 - imported first: its code is not index memory

    import cshape.compare  # noqa: F401

    db_mib = X.nbytes / 2**20
    rss0 = proc_status_kib("VmRSS")
    t0 = time.perf_counter()
    index = build(method, X)
    build_s = time.perf_counter() - t0
    rss1 = proc_status_kib("VmRSS")
    reset_peak()
    rss2 = proc_status_kib("VmRSS")
    index.query(Q[:1], k=k)  # warm-up (first calls); its memory counts in the query peak
    single = []
    for q in Q[:n_single]:
        t0 = time.perf_counter()
        index.query(q[None, :], k=k)
        single.append(time.perf_counter() - t0)
    t0 = time.perf_counter()
    dist, _ = index.query(Q, k=k)
    batch = time.perf_counter() - t0
    peak = proc_status_kib("VmHWM")
    return {
        "build_s": build_s,
        "single_ms": 1e3 * float(np.median(single)),
        "batch_ms": 1e3 * batch / len(Q),
        "db_mib": db_mib,
        "index_mib": (rss1 - rss0) / 1024,
        "query_mib": (peak - rss2) / 1024,
    }, np.asarray(dist)


def run_child(method, db_path, q_path, out_path, k, n_single, threads, timeout=3600):
    """:func:`measure` in a fresh process on saved arrays; the result dict or an error."""
    return _run_child(Path(__file__).resolve(),
                      ["--child", method, db_path, q_path, out_path, "-k", k,
                       "--single", n_single],
                      threads=threads, timeout=timeout)


# ----------------------------------------------------------------------------- main
def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true",
                        help="10^5 descriptors, 16 base meshes, 200 queries (< 2 minutes)")
    parser.add_argument("--size", type=int, default=None,
                        help="stored descriptors (default 10^6, 10^5 with --quick)")
    parser.add_argument("--base", type=int, default=None,
                        help="meshes whose spectra are perturbed (default 200, 16 with --quick)")
    parser.add_argument("--batch", type=int, default=None,
                        help="queries in the batch (default 1000, 200 with --quick)")
    parser.add_argument("--single", type=int, default=20, help="single queries (default 20)")
    parser.add_argument("--repeats", type=int, default=2,
                        help="interleaved rounds; each figure is the best (default 2)")
    parser.add_argument("-k", type=int, default=10, help="neighbours per query (default 10)")
    parser.add_argument("--threads", type=int, default=1,
                        help="BLAS threads (default 1; 0: library default)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--spectra", default=None,
                        help="a .npy file of base spectra: loaded if it exists, else written "
                             "(skips recomputing them in later runs)")
    parser.add_argument("--child", default=None, help=argparse.SUPPRESS)
    parser.add_argument("paths", nargs="*", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)

    if args.child:  # one (method, database) measurement in this fresh process
        db_path, q_path, out_path = args.paths
        X = np.load(db_path)
        Q = np.load(q_path)
        res, dist = measure(args.child, X, Q, k=args.k, n_single=args.single)
        np.save(out_path, dist)
        print(json.dumps(res))
        return 0

    size = args.size or (100_000 if args.quick else 1_000_000)
    n_base = args.base or (16 if args.quick else 200)
    n_batch = args.batch or (200 if args.quick else 1000)
    summary = machine_summary()
    print(summary)
    t0 = time.perf_counter()
    if args.spectra and Path(args.spectra).is_file():
        base = np.load(args.spectra)
    else:
        base = base_spectra(n_base, seed=args.seed)
        if args.spectra:
            np.save(args.spectra, base)
    print(f"base spectra: {len(base)} meshes, N = {base.shape[1]}, "
          f"{time.perf_counter() - t0:.1f} s")
    rng = np.random.default_rng(args.seed + 1)
    lam_db = perturb(base, size, rng)
    lam_q = perturb(base, n_batch, rng)
    # the vectorised cShape-DNA must equal the library's, row by row
    from cshape import Descriptor

    for name, (kind, M) in DESCRIPTORS.items():
        if kind == "cshape":
            ref = Descriptor("cshape", N=base.shape[1], M=M).matrix(lam_db[:50], np.ones(50))
            np.testing.assert_allclose(cshape_rows(lam_db[:50], M), ref, rtol=1e-12,
                                       atol=1e-9, err_msg=name)
    print(f"database: {size:,} spectra synthesised; {n_batch} queries, k = {args.k}, "
          f"BLAS threads: {args.threads or 'default'}\n")
    header = (f"{'descriptor':<17} {'values':>6} {'method':<16} {'stored [MiB]':>12} "
              f"{'index +[MiB]':>12} {'query peak +[MiB]':>17} {'build [s]':>9} "
              f"{'1 query [ms]':>12} {'batch [ms/q]':>12}")
    rows = []
    ok = True
    with tempfile.TemporaryDirectory(prefix="cshape-bench-queries-") as tmp:
        tmp = Path(tmp)
        dims = {}
        for j, name in enumerate(DESCRIPTORS):
            X = descriptors(lam_db, name)
            np.save(tmp / f"db{j}.npy", X)
            np.save(tmp / f"q{j}.npy", descriptors(lam_q, name))
            dims[name] = X.shape[1]
            del X
        del lam_db
        # rounds over all (descriptor, method) pairs, interleaved so that every pair sees
        # the same machine load; each figure is the best over the rounds
        best = {}
        ref_dist = {}
        for rnd in range(args.repeats):
            for j, name in enumerate(DESCRIPTORS):
                for method in METHODS:
                    res = run_child(method, tmp / f"db{j}.npy", tmp / f"q{j}.npy",
                                    tmp / "dist.npy", args.k, args.single, args.threads)
                    if "error" in res:
                        print(f"{name:<17} {method:<16} failed: {res['error']}")
                        ok = False
                        best.setdefault((name, method), res)
                        continue
                    dist = np.load(tmp / "dist.npy")
                    if name in ref_dist and not np.allclose(dist, ref_dist[name], rtol=1e-9,
                                                            atol=1e-9):
                        print(f"WARNING: {method} and {METHODS[0]} disagree on {name}")
                        ok = False
                    ref_dist.setdefault(name, dist)
                    prev = best.get((name, method))
                    if prev is None or "error" in prev:
                        best[(name, method)] = {**res, "load1": load_average()[0]}
                    else:
                        for key in ("build_s", "single_ms", "batch_ms", "index_mib",
                                    "query_mib"):
                            prev[key] = min(prev[key], res[key])
                        prev["load1"] = max(prev["load1"], load_average()[0])
            print(f"round {rnd + 1} of {args.repeats} done, load average "
                  f"{load_average()[0]:.2f}", flush=True)
    print()
    print(header)
    print("-" * len(header))
    for (name, method), res in best.items():
        row = {"descriptor": name, "values": dims[name], "method": method, **res}
        rows.append(row)
        if "error" in res:
            continue
        print(f"{name:<17} {dims[name]:>6} {method:<16} {res['db_mib']:>12.1f} "
              f"{res['index_mib']:>12.1f} {res['query_mib']:>17.1f} "
              f"{res['build_s']:>9.2f} {res['single_ms']:>12.2f} "
              f"{res['batch_ms']:>12.3f}")
    summary_end = machine_summary()
    # savings against Shape-DNA, method by method (the paper's "up to 97 %")
    lines = []
    ref = {r["method"]: r for r in rows if r["descriptor"].startswith("Shape-DNA")
           and "error" not in r}
    for r in rows:
        if r["descriptor"].startswith("Shape-DNA") or "error" in r or r["method"] not in ref:
            continue
        s = ref[r["method"]]
        lines.append(
            f"{r['descriptor']} vs Shape-DNA N=100, {r['method']}: storage "
            f"{100 * (r['db_mib'] / s['db_mib'] - 1):+.0f} %, single query "
            f"{100 * (r['single_ms'] / s['single_ms'] - 1):+.0f} % "
            f"({s['single_ms'] / r['single_ms']:.1f}x as fast), batch "
            f"{100 * (r['batch_ms'] / s['batch_ms'] - 1):+.0f} % "
            f"({s['batch_ms'] / r['batch_ms']:.1f}x as fast)")
    print("\nsavings:")
    for line in lines:
        print("  " + line)
    print(f"at the end: {summary_end}")

    RESULTS.mkdir(parents=True, exist_ok=True)
    stem = "queries_quick" if args.quick else "queries"
    md = [f"# Exact {args.k}-NN queries against {size:,} descriptors", "", summary, "",
          f"At the end: {summary_end}", "",
          f"{n_base} base spectra (N = 100), perturbed; {n_batch} queries; BLAS threads: "
          f"{args.threads or 'default'}.", "",
          "| descriptor | values | method | stored [MiB] | index + [MiB] | query peak + [MiB] "
          "| build [s] | 1 query [ms] | batch [ms/query] |", "|" + "---|" * 9]
    md += [f"| {r['descriptor']} | {r['values']} | {r['method']} | {r['db_mib']:.1f} | "
           f"{r['index_mib']:.1f} | {r['query_mib']:.1f} | {r['build_s']:.2f} | "
           f"{r['single_ms']:.2f} | {r['batch_ms']:.3f} |" for r in rows if "error" not in r]
    md += ["", "Savings against Shape-DNA (N = 100):", ""] + [f"- {x}" for x in lines]
    (RESULTS / f"{stem}.md").write_text("\n".join(md) + "\n")
    print(f"results: {RESULTS / stem}.md")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
