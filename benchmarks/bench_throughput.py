"""Benchmark: throughput (meshes per minute) of ``cshape.describe`` on a mesh collection.

Run from the repository root::

    .venv/bin/python benchmarks/bench_throughput.py --quick        # 40 meshes, < 2 minutes
    .venv/bin/python benchmarks/bench_throughput.py                # 300 meshes
    .venv/bin/python benchmarks/bench_throughput.py --count 120 --modes serial,processes

The collection (:func:`make_collection`) has ``--count`` distinct meshes of 10K to 30K
vertices, four families in turn, each mesh with its own random stretch and a little normal
noise so that no two are alike:

* tori of revolution (``cshape.shapes.torus``) with tube radius 0.2-0.6 and 10K-30K vertices;
* ellipsoids: the 10 242-vertex icosphere stretched along its axes;
* boxes: ``cshape.shapes.cube(n)`` (41 <= n <= 70, 10K-29K vertices), stretched;
* real meshes from ``../shared/meshes`` (spot 11.5K vertices as read, penguin_hr 13K,
  fish 11K), stretched (skipped if the folder is absent; ``CSHAPE_SHARED_MESHES`` overrides
  its path).

Every mode computes the Shape-DNA (N=100) and descriptors of the whole collection with
``cshape.describe`` into a fresh, empty temporary cache folder (nothing is cached
beforehand; writing the cache is part of the work):

* ``serial``: ``n_jobs=1`` (this process, one BLAS thread);
* ``processes``: ``n_jobs=2`` local worker processes;
* ``dask``: a ``distributed.LocalCluster`` of 2 worker processes with one thread each on
  loopback (``host='127.0.0.1'``, ``protocol='tcp://'``); the cluster's start-up time is
  reported separately and not counted.

It prints meshes per minute and the speed-up over ``serial`` (2 would be perfectly linear
on 2 cores; other processes running on the machine take their share, hence the load
average next to the figures and the *free cores* probe of :func:`free_cores` before and
after), and writes ``benchmarks/results/throughput.md``
(``throughput_quick.*`` with ``--quick``; the number of meshes is in the table).  Nothing
here asserts a time.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import load_average  # noqa: E402
from _common import machine_summary as _machine_summary


def machine_summary():
    """One line: date, machine, memory, library versions and the load average."""
    return _machine_summary(libs=())

RESULTS = Path(__file__).resolve().parent / "results"
MODES = ("serial", "processes", "dask")
FAMILIES = ("torus", "ellipsoid", "box", "real")
#: Real meshes per resolution (paths relative to the shared mesh folder).
REAL_MESHES = {
    "high": ["spot/spot.obj", "penguin/penguin_hr.obj", "fish/fish.obj"],
    "low": ["spot/spot_low_resolution.obj", "penguin/penguin.obj", "goathead/goathead.obj",
            "wingnut/wingnut.obj", "torus/torus.obj"],
}


def shared_meshes():
    """The real-mesh folder: ``$CSHAPE_SHARED_MESHES``, else ``../shared/meshes`` beside the
    repository (as in ``tests/conftest.py``)."""
    env = os.environ.get("CSHAPE_SHARED_MESHES")
    return Path(env) if env else Path(__file__).resolve().parents[2] / "shared" / "meshes"


_SPIN = ("import time\nt = time.perf_counter()\ns = 0\nfor i in range({n}):\n    s += i\n"
         "print(time.perf_counter() - t)")


def free_cores(workers=2, n=10_000_000):
    """How many cores ``workers`` processes actually get right now.

    Times a pure-Python busy loop in one process alone and then in ``workers`` processes
    at once: ``workers * t_alone / t_together``, about ``workers`` on an idle machine and
    about 1 if other processes hold all but one core.  It puts the speed-ups in context.
    """
    import subprocess

    cmd = [sys.executable, "-c", _SPIN.format(n=int(n))]

    def run(k):
        procs = [subprocess.Popen(cmd, stdout=subprocess.PIPE, text=True) for _ in range(k)]
        return [float(p.communicate()[0]) for p in procs]

    alone = run(1)[0]
    together = run(workers)
    return workers * alone / float(np.mean(together))


# ----------------------------------------------------------------------------- meshes
def _stretch(mesh, rng, lo=0.5):
    """The mesh scaled by ``(1, a, b)`` with ``a, b`` uniform in ``[lo, 1]``."""
    from cshape import Mesh

    s = np.array([1.0, rng.uniform(lo, 1.0), rng.uniform(lo, 1.0)])
    return Mesh(mesh.vertices * s, mesh.faces)


def make_collection(count, resolution="high", seed=0):
    """``count`` distinct meshes from four families (see the module docstring).

    Parameters
    ----------
    count : int
        Number of meshes.
    resolution : {'high', 'low', 'tiny'}, default='high'
        'high': 10K-30K vertices (the throughput benchmark); 'low': 1.3K-5K vertices (base
        spectra of :mod:`bench_queries`); 'tiny': a few hundred vertices (tests).
    seed : int, default=0
        Seed of the random stretches, radii and noise.

    Returns
    -------
    list of (str, str, cshape.Mesh)
        ``(name, label, mesh)`` records, as ``cshape.describe`` takes them; the label is
        the family (``'real-<file stem>'`` for real meshes).
    """
    from cshape import load_mesh, shapes
    from cshape.data import variants

    if resolution not in ("high", "low", "tiny"):
        raise ValueError(f"resolution must be 'high', 'low' or 'tiny', got {resolution!r}")
    rng = np.random.default_rng(seed)
    lo_v, hi_v = {"high": (10_000, 30_000), "low": (1_300, 5_000), "tiny": (200, 400)}[
        resolution]
    real = []
    folder = shared_meshes()
    if resolution != "tiny" and folder.is_dir():
        for rel in REAL_MESHES[resolution]:
            path = folder / rel
            if path.is_file():
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    real.append((path.stem, load_mesh(path)))
    families = [f for f in FAMILIES if f != "real" or real]
    sphere = shapes.icosphere({"high": 5, "low": 4, "tiny": 2}[resolution])
    out = []
    for i in range(count):
        family = families[i % len(families)]
        label = family
        if family == "torus":
            r = rng.uniform(0.2, 0.6)
            nv = rng.uniform(lo_v, hi_v)
            n_minor = max(3, int(round(np.sqrt(nv * r))))
            n_major = max(3, int(round(nv / n_minor)))
            mesh = _stretch(shapes.torus(n_major, n_minor, R=1.0, r=r), rng, 0.7)
        elif family == "ellipsoid":
            mesh = _stretch(sphere, rng, 0.3)
        elif family == "box":
            n = int(rng.integers(int(np.sqrt(lo_v / 6)) + 1, int(np.sqrt(hi_v / 6)) + 1))
            mesh = _stretch(shapes.cube(n), rng, 0.3)
        else:
            stem, base = real[(i // len(families)) % len(real)]
            label = f"real-{stem}"
            mesh = _stretch(base, rng, 0.6)
        mesh = variants.add_normal_noise(mesh, 0.2, random_state=rng, signed=True)
        out.append((f"{label}-{i:04d}", label, mesh))
    return out


# ----------------------------------------------------------------------------- one mode
def start_dask(n_workers=2):
    """A loopback ``LocalCluster`` of worker processes (one thread each) and its client."""
    import distributed

    cluster = distributed.LocalCluster(
        n_workers=n_workers, threads_per_worker=1, processes=True, host="127.0.0.1",
        protocol="tcp://", dashboard_address=None)
    return cluster, distributed.Client(cluster)


def run_mode(collection, mode, *, N=100, n_jobs=2):
    """Describe the whole collection once in one mode, into a fresh temporary cache.

    Parameters
    ----------
    collection : list of (name, label, Mesh)
    mode : {'serial', 'processes', 'dask'}
    N : int
        Shape-DNA length.
    n_jobs : int, default=2
        Worker processes of the 'processes' and 'dask' modes.

    Returns
    -------
    dict
        ``mode``, ``meshes`` (described), ``failed``, ``seconds`` (wall clock of
        ``describe``), ``per_minute``, ``startup`` (cluster start-up seconds, 'dask' only),
        ``solve_seconds`` (sum of the per-mesh times ``describe`` reports), ``load1``
        (1-minute load average at the end) and ``table`` (the DescriptorTable).
    """
    from cshape import describe

    if mode not in MODES:
        raise ValueError(f"mode must be one of {MODES}, got {mode!r}")
    startup = 0.0
    cluster = client = None
    kwargs = {"n_jobs": 1}
    if mode == "processes":
        kwargs = {"n_jobs": n_jobs}
    elif mode == "dask":
        t0 = time.perf_counter()
        cluster, client = start_dask(n_jobs)
        startup = time.perf_counter() - t0
        kwargs = {"client": client}
    try:
        with tempfile.TemporaryDirectory(prefix="cshape-bench-cache-") as cache, \
                warnings.catch_warnings():
            warnings.simplefilter("ignore")
            t0 = time.perf_counter()
            table = describe(collection, N=N, cache_dir=cache, progress=False, **kwargs)
            seconds = time.perf_counter() - t0
            if table.cached.any():
                raise RuntimeError("a mesh came from the cache; the benchmark needs a cold one")
    finally:
        if client is not None:
            client.close()
            cluster.close()
    return {
        "mode": mode, "meshes": len(table), "failed": len(table.failures),
        "seconds": seconds, "per_minute": 60.0 * len(table) / seconds, "startup": startup,
        "solve_seconds": float(np.nansum(table.seconds)), "load1": load_average()[0],
        "table": table,
    }


# ----------------------------------------------------------------------------- main
def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="40 meshes (< 2 minutes)")
    parser.add_argument("--count", type=int, default=None,
                        help="number of meshes (default 300, 40 with --quick)")
    parser.add_argument("--modes", default=",".join(MODES),
                        help=f"comma-separated subset of {','.join(MODES)} (default: all)")
    parser.add_argument("--workers", type=int, default=2,
                        help="worker processes of 'processes' and 'dask' (default 2)")
    parser.add_argument("-N", type=int, default=100, help="Shape-DNA length (default 100)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the collection")
    args = parser.parse_args(argv)
    modes = [m.strip() for m in args.modes.split(",") if m.strip()]
    bad = [m for m in modes if m not in MODES]
    if bad:
        parser.error(f"--modes must be a subset of {','.join(MODES)}, got {bad}")
    if "dask" in modes:
        try:
            import distributed  # noqa: F401
        except ImportError:
            print("dask.distributed is not installed (pip install 'cshape[distributed]'): "
                  "skipping the dask mode")
            modes.remove("dask")
    count = args.count or (40 if args.quick else 300)

    summary = machine_summary()
    print(summary)
    t0 = time.perf_counter()
    collection = make_collection(count, "high", seed=args.seed)
    nv = np.array([m.n_vertices for _, _, m in collection])
    labels = sorted({lab for _, lab, _ in collection})
    print(f"collection: {count} meshes, {nv.min():,}-{nv.max():,} vertices "
          f"(mean {nv.mean():,.0f}), families {', '.join(labels)}; made in "
          f"{time.perf_counter() - t0:.1f} s")
    cores_before = free_cores(args.workers)
    print(f"N={args.N}, fresh temporary cache per mode, {args.workers} workers; free cores "
          f"(busy-loop probe, {args.workers} processes): {cores_before:.2f}\n")
    header = (f"{'mode':<26} {'meshes':>6} {'wall [s]':>9} {'meshes/min':>11} "
              f"{'speed-up':>9} {'start-up [s]':>13} {'load':>5} {'per-mesh sum [s]':>17}")
    print(header)
    print("-" * len(header))
    rows = []
    ref = None
    names = {"serial": "describe(n_jobs=1)", "processes": f"describe(n_jobs={args.workers})",
             "dask": f"Dask LocalCluster ({args.workers}x1)"}
    for mode in modes:
        r = run_mode(collection, mode, N=args.N, n_jobs=args.workers)
        table = r.pop("table")
        if ref is None:
            ref = table
        elif not np.allclose(table.lam, ref.lam, rtol=1e-10, atol=1e-10):
            print(f"WARNING: {mode} gave different eigenvalues from {modes[0]}")
        base = rows[0]["per_minute"] if rows and rows[0]["mode"] == "serial" else float("nan")
        r["speedup"] = r["per_minute"] / base if mode != "serial" else 1.0
        r["label"] = names[mode]
        rows.append(r)
        print(f"{r['label']:<26} {r['meshes']:>6d} {r['seconds']:>9.1f} {r['per_minute']:>11.1f} "
              f"{r['speedup']:>9.2f} {r['startup']:>13.1f} {r['load1']:>5.2f} "
              f"{r['solve_seconds']:>17.1f}", flush=True)
    cores_after = free_cores(args.workers)
    summary_end = machine_summary()
    print(f"\nfree cores at the end: {cores_after:.2f}; at the end: {summary_end}")

    RESULTS.mkdir(parents=True, exist_ok=True)
    stem = "throughput_quick" if args.quick else "throughput"
    md = [f"# Throughput of cshape.describe (N={args.N})", "", summary, "",
          f"At the end: {summary_end}", "",
          f"{count} meshes, {nv.min():,}-{nv.max():,} vertices (mean {nv.mean():,.0f}), "
          f"fresh temporary cache per mode.  Free cores for {args.workers} worker processes "
          f"(busy-loop probe, {args.workers} * t_alone / t_together): {cores_before:.2f} "
          f"before, {cores_after:.2f} after; a speed-up cannot exceed it.", "",
          "The per-mesh sum adds the compute times `describe` reports for each mesh: equal "
          "sums mean equally fast eigensolves in every mode.", "",
          "| mode | meshes | wall [s] | meshes/min | speed-up | cluster start-up [s] | load | "
          "per-mesh sum [s] |",
          "|---|---|---|---|---|---|---|---|"]
    md += [f"| {r['label']} | {r['meshes']} | {r['seconds']:.1f} | {r['per_minute']:.1f} | "
           f"{r['speedup']:.2f} | {r['startup']:.1f} | {r['load1']:.2f} | "
           f"{r['solve_seconds']:.1f} |" for r in rows]
    (RESULTS / f"{stem}.md").write_text("\n".join(md) + "\n")
    print(f"results: {RESULTS / stem}.md")
    return 0 if all(r["failed"] == 0 for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
