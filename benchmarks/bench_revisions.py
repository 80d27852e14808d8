"""Benchmark: two source trees of cshape against each other (before / after a change).

Run from the repository root, with the old revision checked out somewhere else::

    git worktree add /tmp/cshape-old <commit>
    .venv/bin/python benchmarks/bench_revisions.py --old /tmp/cshape-old
    .venv/bin/python benchmarks/bench_revisions.py --old /tmp/cshape-old --sizes 160k \\
        --no-real --threads 2 --rounds 3

Each round runs one child process per tree, alternately (old, new, then new, old, ...), so
that a drift of the machine's speed falls on both; a child times ``shape_dna(mesh, N)``
(or ``eigenpairs`` with ``--eigenpairs``) ``--repeats`` times per mesh after one warm-up call,
with BLAS limited to one thread.  The table gives, per mesh, the best CPU time and the best
wall time of each tree over all rounds and their ratios (old / new: above 1, the new tree is
faster), and the largest relative difference between the two trees' eigenvalues.  Meshes:
the real meshes of ``../shared/meshes`` (``CSHAPE_SHARED_MESHES``) with 1K-30K vertices and
the size labels of ``bench_sweep.py`` given by ``--sizes``.  Nothing here asserts a time.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import machine_summary  # noqa: E402
from bench_sweep import SIZES, shared_meshes  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
RESULTS = Path(__file__).resolve().parent / "results"

#: The child: times every mesh of its JSON argument with the cshape found on sys.path.
CHILD = r"""
import json, sys, time, warnings
warnings.simplefilter("ignore")
import numpy as np
from threadpoolctl import threadpool_limits
import cshape
from cshape import shapes
spec = json.loads(sys.argv[1])
fn = cshape.spectrum.eigenpairs if spec["eigenpairs"] else cshape.shape_dna
out = {"file": cshape.__file__}
with threadpool_limits(limits=1, user_api="blas"):
    for name, source in spec["meshes"]:
        if source[0] == "file":
            mesh = cshape.repair_mesh(cshape.load_mesh(source[1]))
            if not 1000 <= mesh.n_vertices <= 30000:  # typical meshes only
                continue
        elif source[0] == "ico":
            mesh = shapes.icosphere(source[1])
        else:
            mesh = shapes.torus(source[1], source[2])
        lam = fn(mesh, spec["N"])
        cpu = wall = np.inf
        for _ in range(spec["repeats"]):
            c, w = time.process_time(), time.perf_counter()
            lam = fn(mesh, spec["N"])
            cpu, wall = min(cpu, time.process_time() - c), min(wall, time.perf_counter() - w)
        lam = lam[0] if spec["eigenpairs"] else lam
        out[name] = {"cpu": cpu, "wall": wall, "n": int(mesh.n_vertices),
                     "lam": np.asarray(lam, dtype=float).tolist()}
print(json.dumps(out))
"""


def mesh_sources(sizes, real):
    """``[(name, source)]``: size labels of bench_sweep, then the real meshes' files."""
    out = [(label, list(SIZES[label])) for label in sizes]
    if real:
        for path in sorted(shared_meshes().glob("*/*.obj")):
            out.append((path.stem, ["file", str(path)]))
    return out


def run_tree(tree, spec, threads):
    """One child process with ``tree`` first on the path; its JSON result."""
    env = dict(os.environ, PYTHONPATH=str(tree))
    if threads:
        env["CSHAPE_THREADS"] = str(threads)
    # run in the tree: ``python -c`` puts the working folder first on sys.path
    proc = subprocess.run([sys.executable, "-c", CHILD, json.dumps(spec)], env=env, cwd=tree,
                          capture_output=True, text=True, check=False)
    if proc.returncode != 0:
        raise SystemExit(f"the child for {tree} failed:\n{proc.stderr[-2000:]}")
    result = json.loads(proc.stdout.strip().splitlines()[-1])
    if not Path(result.pop("file")).resolve().is_relative_to(Path(tree).resolve()):
        raise SystemExit(f"the child for {tree} imported cshape from elsewhere")
    return result


def describe_tree(tree):
    """``path (commit abc1234[, with local changes])``, or the path alone outside git."""
    git = ["git", "-C", str(tree)]
    head = subprocess.run([*git, "rev-parse", "--short", "HEAD"], capture_output=True,
                          text=True, check=False)
    if head.returncode != 0:
        return f"`{tree}`"
    dirty = subprocess.run([*git, "status", "--porcelain", "--untracked-files=no"],
                           capture_output=True, text=True, check=False).stdout.strip()
    return f"`{tree}` (commit {head.stdout.strip()}{', with local changes' if dirty else ''})"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--old", required=True, help="source tree of the old revision")
    parser.add_argument("--new", default=str(ROOT), help="source tree of the new one (here)")
    parser.add_argument("--sizes", default="", help=f"size labels among {','.join(SIZES)}")
    parser.add_argument("--no-real", dest="real", action="store_false",
                        help="without the real meshes of the shared folder")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--repeats", type=int, default=3, help="timed calls per child")
    parser.add_argument("--threads", type=int, default=1, help="CSHAPE_THREADS (default 1)")
    parser.add_argument("--eigenpairs", action="store_true")
    parser.add_argument("-N", type=int, default=100)
    parser.add_argument("--out", default=None, help="results stem (none: print only)")
    args = parser.parse_args(argv)
    for tree in (args.old, args.new):
        if not (Path(tree) / "cshape" / "__init__.py").is_file():
            parser.error(f"{tree} is not a cshape source tree (no cshape/__init__.py)")
    sizes = [s for s in args.sizes.split(",") if s]
    bad = [s for s in sizes if s not in SIZES]
    if bad:
        parser.error(f"--sizes must be among {','.join(SIZES)}, got {bad}")
    meshes = mesh_sources(sizes, args.real)
    if not meshes:
        parser.error("no meshes: give --sizes, or keep the real meshes (CSHAPE_SHARED_MESHES)")
    spec = {"meshes": meshes, "N": args.N, "repeats": args.repeats,
            "eigenpairs": args.eigenpairs}
    head = machine_summary()
    print(head, flush=True)
    best = {"old": {}, "new": {}}
    lams = {}
    for r in range(args.rounds):
        order = ("old", "new") if r % 2 == 0 else ("new", "old")
        for which in order:
            res = run_tree(getattr(args, which), spec, args.threads)
            for name, row in res.items():
                b = best[which].setdefault(name, {"cpu": np.inf, "wall": np.inf, "n": row["n"]})
                b["cpu"], b["wall"] = min(b["cpu"], row["cpu"]), min(b["wall"], row["wall"])
                lams[which, name] = np.asarray(row["lam"])
        print(f"round {r + 1} of {args.rounds} done", flush=True)
    what = "eigenpairs" if args.eigenpairs else "shape_dna"
    lines = [f"# cshape {what}(N={args.N}): two source trees", "", head, "",
             f"old: {describe_tree(args.old)}, new: {describe_tree(args.new)}; "
             f"{args.rounds} rounds of alternating "
             f"child processes, best of {args.repeats} calls per child, BLAS one thread, "
             f"CSHAPE_THREADS={args.threads}; ratio = old / new.", "",
             "| mesh | vertices | old CPU [ms] | new CPU [ms] | CPU old / new | "
             "old wall [ms] | new wall [ms] | wall old / new | max rel. diff |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    tot = np.zeros(4)
    for name in best["new"]:
        o, n = best["old"][name], best["new"][name]
        a, b = lams["old", name], lams["new", name]
        diff = float(np.max(np.abs(a - b) / np.maximum(np.abs(a), 1e-9 * np.abs(a).max())))
        tot += (o["cpu"], n["cpu"], o["wall"], n["wall"])
        lines.append(f"| {name} | {n['n']:,} | {o['cpu'] * 1e3:.1f} | {n['cpu'] * 1e3:.1f} | "
                     f"**{o['cpu'] / n['cpu']:.2f}** | {o['wall'] * 1e3:.1f} | "
                     f"{n['wall'] * 1e3:.1f} | {o['wall'] / n['wall']:.2f} | {diff:.1e} |")
    lines += ["", f"Sums: CPU {tot[0]:.2f} s / {tot[1]:.2f} s = **{tot[0] / tot[1]:.2f}**, "
              f"wall {tot[2]:.2f} s / {tot[3]:.2f} s = {tot[2] / tot[3]:.2f}.", "",
              f"At the end: {machine_summary()}"]
    text = "\n".join(lines) + "\n"
    print(text)
    if args.out:
        RESULTS.mkdir(exist_ok=True)
        (RESULTS / f"{args.out}.md").write_text(text)
        print(f"results: {RESULTS / (args.out + '.md')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
