"""Benchmark: shape retrieval with global descriptors made of signatures, against the log spectrum.

Run from the repository root::

    .venv/bin/python benchmarks/bench_signature_retrieval.py                 # 'creatures'
    .venv/bin/python benchmarks/bench_signature_retrieval.py --collection creatures-small

Issue 21 asks whether the point signatures help *retrieval* when pooled into one vector per
shape.  From ``N = 100`` eigenpairs of each shape (area-normalised: the shape scaled to unit
area, so the descriptors are scale invariant and comparable across shapes):

* ``log spectrum``: the log-Weyl ratio ``log(lam_i area / (4 pi i))``, ``i = 1..99``;
* ``HKS quantiles``: ``log HKS`` at 16 fixed times (units of the area) log-spaced over
  ``[4 ln 10 / (4 pi 99), 4 ln 10 / (4 pi)]`` (Sun et al.'s range for Weyl's ``lam_i area ~
  4 pi i``), and at each time the area-weighted quantiles 0.1, 0.25, 0.5, 0.75, 0.9 over the
  vertices: 80 values;
* ``WKS quantiles``: the same with ``log WKS`` at 16 fixed log-energies over Aubry et al.'s
  range for that Weyl spectrum (``sigma = 7`` steps of a 100-energy grid): 80 values;

compared by Euclidean distance and scored with :func:`cshape.compare.retrieval_scores`
(nearest neighbour, first and second tier, mean average precision).  The choices were made
before the run and not tuned.  Results go to ``benchmarks/results/signature_retrieval_<name>.md``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

import cshape
from cshape import signatures as sg
from cshape.compare import retrieval_scores
from cshape.descriptors import log_weyl_ratio, normalize

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import load_average, machine_summary  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
QUANTILES = (0.1, 0.25, 0.5, 0.75, 0.9)
N_SCALES = 16
WEYL = 4.0 * np.pi


def fixed_scales(N=100, n_scales=N_SCALES):
    """The unit-area times and (energies, sigma) every shape is sampled at."""
    t = np.geomspace(sg.T_FACTOR / (WEYL * (N - 1)), sg.T_FACTOR / WEYL, n_scales)
    e1, eN = np.log(WEYL), np.log(WEYL * (N - 1))
    sigma = sg.WKS_WIDTH * (eN - e1) / 100
    return t, np.linspace(e1 + 2 * sigma, eN - 2 * sigma, n_scales), sigma


def weighted_quantiles(X, w, qs=QUANTILES):
    """Column-wise quantiles of ``X`` (n, k) with vertex weights ``w`` (n,): (len(qs), k).

    Each sorted value sits at the middle of its weight's share of the cumulative weight;
    quantiles interpolate linearly between them (and clip at the ends).
    """
    out = np.empty((len(qs), X.shape[1]))
    for j in range(X.shape[1]):
        order = np.argsort(X[:, j])
        cw = np.cumsum(w[order])
        cw = (cw - 0.5 * w[order]) / cw[-1]
        out[:, j] = np.interp(qs, cw, X[order, j])
    return out


def shape_descriptors(mesh, N=100):
    """The three global descriptors of one mesh, by name."""
    mesh = cshape.repair_mesh(cshape.mesh.as_mesh(mesh), warn=False)
    basis = cshape.eigenbasis(mesh, N)
    w = np.asarray(basis.B.sum(axis=1)).ravel()  # vertex areas (lumped mass)
    t, e, sigma = fixed_scales(N)
    h = np.log(cshape.hks(basis, t, normalization="area"))
    k = np.log(np.maximum(cshape.wks(basis, e, sigma, normalization="area"), 1e-300))
    return {
        "log spectrum": log_weyl_ratio(normalize(basis.lam, area=basis.area)),
        "HKS quantiles": weighted_quantiles(h, w).ravel(),
        "WKS quantiles": weighted_quantiles(k, w).ravel(),
    }


def score(descs, labels):
    rows = []
    for name in descs[0]:
        X = np.array([d[name] for d in descs])
        D = np.linalg.norm(X[:, None, :] - X[None, :, :], axis=2)
        rows.append({"descriptor": name, "values": X.shape[1], **retrieval_scores(D, labels)})
    return rows


def markdown(rows, name, n, classes, header, footer):
    lines = [f"# Retrieval with pooled signatures: `{name}` ({n} shapes, {classes} classes)", "",
             header, "",
             "| descriptor | values | NN | FT | ST | mAP |", "|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['descriptor']} | {r['values']} | {r['nn']:.3f} | {r['ft']:.3f} | "
                     f"{r['st']:.3f} | {r['map']:.3f} |")
    return "\n".join(lines + ["", footer, ""])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--collection", default="creatures")
    parser.add_argument("-N", type=int, default=100)
    args = parser.parse_args(argv)
    from cshape import data

    header = machine_summary()
    print(header, flush=True)
    t0 = time.perf_counter()
    coll = data.load_collection(args.collection)
    print(f"loaded {len(coll)} meshes in {time.perf_counter() - t0:.0f} s", flush=True)
    t0 = time.perf_counter()
    descs = [shape_descriptors(m, args.N) for m in coll.meshes]
    print(f"descriptors in {time.perf_counter() - t0:.0f} s", flush=True)
    rows = score(descs, list(coll.labels))
    footer = f"At the end: load average {' '.join(f'{x:.2f}' for x in load_average())}."
    md = markdown(rows, args.collection, len(coll), len(set(coll.labels)), header, footer)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / f"signature_retrieval_{args.collection}.md").write_text(md)
    print(md)
    return 0


if __name__ == "__main__":
    sys.exit(main())
