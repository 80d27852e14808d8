"""Benchmark: the rule for meshes of several pieces (issue 19), measured on real spectra.

Run from the repository root::

    .venv/bin/python -m cshape describe ../shared/meshes --out /tmp/shared.npz
    .venv/bin/python benchmarks/bench_pieces.py /tmp/shared.npz

A mesh of ``k`` components has ``k`` zero eigenvalues; cshape drops them and indexes the rest
from 1, with the total area (``cshape.descriptors.formulas.nonzero_eigenvalues``).
The spectrum of a disjoint
union is the merge of its pieces' spectra and its area their sum, so multi-piece spectra are
made here from the connected ones of the table, with no eigensolve:

* **index**: each shape ``X`` with a "lid" (a sphere of 1 % or 10 % of ``X``'s area, whose
  spectrum ``l(l+1)/rho^2`` is known), or with a copy of itself; its truncated log spectrum
  (``2M+1`` values) under rule A (drop the ``k`` zeros, index from 1: cshape's) and rule B
  (drop them, keep each eigenvalue's index in the full spectrum, ``i = k..``): distance to
  ``X``'s own descriptor over the median distance between shapes, and how often ``X`` is
  its nearest neighbour;
* **length**: the log-Weyl DCT of ``N`` eigenvalues needs ``N-1`` ratios and a mesh of ``k``
  pieces has ``N-k``: extended by Weyl's law from the last one (``r_i = r_{N-k}``, cshape's)
  or transformed as a shorter sequence (rescaled to the same norm); error against the
  descriptor of all ``N-1`` ratios, over the median distance between shapes;
* **threshold**: the smallest ``lam_1 / lam_{N-1}`` of the table (a real zero-mode
  threshold must stay below it; cshape's is ``ZERO_RTOL = 1e-8``).

Nothing here asserts a number.
"""

from __future__ import annotations

import argparse
import warnings

import numpy as np
from scipy.fft import dct

from cshape import compare
from cshape.batch import DescriptorTable
from cshape.descriptors.formulas import ZERO_RTOL

FOUR_PI = 4 * np.pi


def lid_union(lam, area, frac, N):
    """``X`` and a sphere of ``frac`` times its area: merged spectrum, total area."""
    rho = np.sqrt(frac * area / FOUR_PI)
    sphere = np.concatenate([[ell * (ell + 1) / rho**2] * (2 * ell + 1) for ell in range(30)])
    return np.sort(np.concatenate([lam, sphere]))[:N], area * (1 + frac)


def copy_union(lam, area, N):
    return np.sort(np.concatenate([lam, lam]))[:N], 2 * area


def rule_a(lam, area, k, L):
    """cshape's: drop the k zero modes, index the rest from 1."""
    mu = (lam * area)[k:k + L]
    return np.log(mu / (FOUR_PI * np.arange(1, L + 1)))


def rule_b(lam, area, k, L):
    """Drop the k zero modes, keep the index of the full spectrum (i = k, k+1, ...)."""
    mu = (lam * area)[k:k + L]
    return np.log(mu / (FOUR_PI * np.arange(k, k + L)))


def _median_off(D):
    return float(np.median(D[~np.eye(len(D), dtype=bool)]))


def bench_index(table, M):
    L = 2 * M + 1
    R = np.array([rule_a(lam, a, 1, L) for lam, a in zip(table.lam, table.areas, strict=True)])
    med = _median_off(compare.distance_matrix(R))
    rows = []
    for case in ("lid 1 %", "lid 10 %", "copy"):
        for name, rule in (("A: drop k, index from 1", rule_a),
                           ("B: drop k, keep the index", rule_b)):
            dist, first = [], 0
            for i, (lam, a) in enumerate(zip(table.lam, table.areas, strict=True)):
                if case == "copy":
                    u, au = copy_union(lam, a, table.N)
                else:
                    u, au = lid_union(lam, a, float(case.split()[1]) / 100, table.N)
                d = np.linalg.norm(R - rule(u, au, 2, L), axis=1)
                dist.append(d[i] / med)
                first += int(np.argmin(d) == i)
            rows.append((case, name, float(np.median(dist)), first, len(table)))
    return med, rows


def bench_length(table, M):
    N = table.N

    def crop(r):
        return dct(r, type=2, norm="ortho")[: 2 * M + 1]

    T = np.array([crop(rule_a(lam, a, 1, N - 1))
                  for lam, a in zip(table.lam, table.areas, strict=True)])
    med = _median_off(compare.distance_matrix(T))
    rows = []
    for k in (2, 3, 5):
        for name in ("Weyl extension (cshape)", "shorter sequence"):
            err = []
            for i, (lam, a) in enumerate(zip(table.lam, table.areas, strict=True)):
                u = np.concatenate([np.zeros(k - 1), lam])[:N]  # k-1 small pieces beyond N
                r = rule_a(u, a, k, N - k)
                if name.startswith("Weyl"):
                    c = crop(np.concatenate([r, np.full(k - 1, r[-1])]))
                else:
                    c = crop(r) * np.sqrt((N - 1) / (N - k))
                err.append(np.linalg.norm(c - T[i]) / med)
            rows.append((k, name, float(np.median(err)), float(np.max(err))))
    return med, rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("table", help="a DescriptorTable (.npz or .csv) of connected meshes")
    ap.add_argument("-M", type=int, default=8, help="2M+1 values (default 8: 17 values)")
    args = ap.parse_args(argv)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        table = DescriptorTable.load(args.table)
    table = table.select(table.zero_modes == 1)
    print(f"{len(table)} connected shapes, N = {table.N}, 2M+1 = {2 * args.M + 1}\n")
    med, rows = bench_index(table, args.M)
    print(f"index rule, truncated log spectrum (median distance between shapes {med:.3f})")
    print("| union | rule | distance to itself / median | itself nearest |")
    print("|---|---|---|---|")
    for case, name, d, first, p in rows:
        print(f"| {case} | {name} | {d:.3f} | {first}/{p} |")
    med, rows = bench_length(table, args.M)
    print(f"\nlength rule, log-Weyl DCT of N = {table.N} (median distance {med:.3f})")
    print("| k | rule | error / median (median) | (max) |")
    print("|---|---|---|---|")
    for k, name, e, emax in rows:
        print(f"| {k} | {name} | {e:.4f} | {emax:.4f} |")
    ratio = table.lam[:, 1] / table.lam[:, -1]
    i = int(np.argmin(ratio))
    print(f"\nthreshold: smallest lam_1 / lam_{table.N - 1} = {ratio[i]:.2e} ({table.names[i]}); "
          f"ZERO_RTOL = {ZERO_RTOL:g}")


if __name__ == "__main__":
    main()
