"""Candidate exploration defaults scored on real labelled collections and on the generated suite.

Usage::

    .venv/bin/python benchmarks/bench_real_collections.py --realdev ../shared/realdev \\
        --out benchmarks/results/real_collections.md

``--realdev`` is a folder with ``shrec07-dev/`` (category level: 10 classes of the SHREC 2007
watertight benchmark, 200 meshes) and ``tosca-dev/`` (instance level: 6 TOSCA characters in
poses, 48 meshes), each with its meshes (``.off.gz``), ``classes.csv`` and
``reference-spectra.npz`` (``lam`` (p, 100) raw, ``area``, ``labels``); without it the script
says so and exits with status 2.

Every candidate is scored by retrieval (:func:`cshape.compare.retrieval_scores`, Princeton
Shape Benchmark definitions: NN, first and second tier, DCG, mAP) on

* both real collections: eigenvalue descriptors from the **reference spectra** (an
  independent linear-FEM + ARPACK solver); descriptors that need more than eigenvalues
  (heat / wave kernel signatures, the intrinsic Delaunay Laplacian, D2) from cshape's own
  eigenpairs of the meshes (:mod:`_real_features`);
* the development instances of the generated suite (``creatures-dev``, ``identities-dev``,
  ``resolutions-dev``; :mod:`cshape.data.suite`), from cached :func:`cshape.describe` tables.

Rule: among the candidates with nothing fitted on the real collections (a weight chosen
on them cannot be judged by its scores there) whose ``resolutions-dev`` nearest neighbour is
at least ``GUARD_NN`` (the same shape meshed another way must still be found), take the
highest **worst first tier over the two real collections**; candidates within ``TIE`` of it
are tied, and the tie goes to the simplest: eigenvalues only (what ``cshape describe``
stores), then fewer values, then the higher mean of the two.  Fitted combinations are
scored and reported (what lies beyond the plateau), never chosen.

Per-mesh features are cached under ``--cache`` (default ``/tmp/realdev_cache``): without a
cache the script computes 248 eigenpair sets, 248 intrinsic Delaunay spectra and (with LaPy)
248 LaPy spectra, about 15 minutes on 2 shared cores, and the suite's 384 eigenpair sets
(about 2 minutes); with the cache, 20 seconds.
"""

from __future__ import annotations

import argparse
import csv
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import machine_summary  # noqa: E402

COLLECTIONS = ("shrec07-dev", "tosca-dev")
SUITE_BENCHES = ("creatures", "identities", "resolutions")
#: The rule's guard: nearest neighbour on ``resolutions-dev``.
GUARD_NN = 0.90
#: First-tier differences below this are ties.
TIE = 0.01
FOUR_PI = 4 * np.pi
#: Zero-mode count for the benchmark's own descriptors: generous, the collections' piece
#: counts are known (every realdev mesh is connected; the suite tables store theirs).
ZERO_RTOL = 1e-6


# --------------------------------------------------------------------------- data
def load_real(folder: Path, cache: Path) -> dict:
    """Reference spectra, labels and the cached cshape features of one real collection."""
    import _real_features

    ref = np.load(folder / "reference-spectra.npz")
    files = [str(f) for f in ref["files"]]
    missing = [f for f in files
               if not (cache / folder.name / (f[: -len(".off.gz")] + ".npz")).exists()]
    if missing:
        print(f"{folder.name}: computing features of {len(missing)} meshes (cached in "
              f"{cache})", file=sys.stderr)
        _real_features.main([str(folder), str(cache)])
    feats = [np.load(cache / folder.name / (f[: -len(".off.gz")] + ".npz")) for f in files]
    out = {"name": folder.name, "files": files, "labels": [str(x) for x in ref["labels"]],
           "lam": np.asarray(ref["lam"], float), "area": np.asarray(ref["area"], float),
           "own_lam": np.array([f["lam"] for f in feats]),
           "own_area": np.array([float(f["area"]) for f in feats])}
    for key in ("hks_q", "wks_q", "d2", "lam_idl", "lam_arpack", "n_vertices"):
        out[key] = np.array([f[key] for f in feats])
    if all("lam_lapy" in f for f in feats):
        out["lam_lapy"] = np.array([f["lam_lapy"] for f in feats])
    out["zero_modes"] = np.array([_count_zero(x) for x in out["lam"]])
    return out


def load_suite(cache: Path) -> dict:
    """{benchmark: data} of the suite's development instances (cached)."""
    import _real_features

    path = cache / "suite-dev.npz"
    if not path.exists():
        from bench_suite import tables

        arrays = {}
        for b, tab in tables("dev", 100, 1).items():
            arrays.update({f"{b}_lam": tab.lam, f"{b}_area": tab.areas,
                           f"{b}_labels": np.array(tab.labels, dtype=str),
                           f"{b}_names": np.array(tab.names, dtype=str),
                           f"{b}_zero_modes": tab.zero_modes})
        np.savez(path, **arrays)
    z = np.load(path)
    out = {}
    for b in SUITE_BENCHES:
        fpath = cache / f"suite-{b}-features.npz"
        if not fpath.exists():
            _real_features.suite_features(b, fpath)
        f = np.load(fpath)
        if list(f["names"]) != list(z[f"{b}_names"]):
            raise SystemExit(f"{fpath}: names differ from the {b} table; delete the cache")
        out[b] = {"name": f"{b}-dev", "labels": [str(x) for x in z[f"{b}_labels"]],
                  "lam": z[f"{b}_lam"], "area": z[f"{b}_area"],
                  "zero_modes": np.asarray(z[f"{b}_zero_modes"]),
                  "own_lam": f["lam"], "own_area": z[f"{b}_area"],
                  **{k: f[k] for k in ("hks_q", "wks_q", "d2", "lam_idl")}}
    return out


def _count_zero(lam, rtol=ZERO_RTOL):
    above = np.flatnonzero(lam > rtol * np.abs(lam).max())
    return int(above[0]) if len(above) else len(lam)


# --------------------------------------------------------------------------- descriptors
def _mu(lam, area, k, norm, src="lam"):
    """Non-zero eigenvalues after the k zero modes, normalised: list of 1-D arrays."""
    out = []
    for x, a, kk in zip(lam, area, k, strict=True):
        mu = np.asarray(x[max(int(kk), 1):], float)
        if norm == "area":
            mu = mu * a
        elif norm == "fiedler":
            mu = mu / mu[0]
        elif norm == "none":  # already area-normalised (the intrinsic Delaunay spectra)
            pass
        else:  # pragma: no cover
            raise ValueError(norm)
        out.append(mu)
    return out


def log_weyl(d, norm, n, src="lam"):
    """r_i = log(mu_i^norm / (4 pi i)), i = 1..n (n values; Weyl-extended if short)."""
    lam = d[src]
    area = d["area"] if src == "lam" else d["own_area"]
    k = d["zero_modes"]
    if src == "lam_idl":
        norm = "none" if norm == "area" else norm
    rows = []
    for mu in _mu(lam, area, k, norm):
        r = np.log(mu / (FOUR_PI * np.arange(1, len(mu) + 1)))
        r = np.concatenate([r, np.full(max(n - len(r), 0), r[-1])])[:n]
        rows.append(r)
    return np.array(rows)


def truncated_log(M, norm, src="lam"):
    return lambda d: log_weyl(d, norm, 2 * M + 1, src)


def full_log(N, norm, src="lam"):
    return lambda d: log_weyl(d, norm, N - 1, src)


def spectral_crop(M, N, norm, dct, src="lam"):
    """log-Weyl DFT (real form) or DCT of r_1..r_{N-1}, 2M+1 values (cshape's transforms)."""
    def f(d):
        r = log_weyl(d, norm, N - 1, src)
        L = N - 1
        if dct:
            from scipy.fft import dct as _dct
            return _dct(r, type=2, norm="ortho", axis=1)[:, : 2 * M + 1]
        S = np.fft.fftshift(np.fft.fft(r, axis=1), axes=1)
        c = L // 2
        crop = S[:, c: c + M + 1]  # k = 0..M
        parts = [crop[:, :1].real]
        for j in range(1, M + 1):
            parts += [np.sqrt(2) * crop[:, j: j + 1].real, np.sqrt(2) * crop[:, j: j + 1].imag]
        return np.hstack(parts)
    return f


def shape_dna(N, norm="area", src="lam"):
    def f(d):
        lam = d[src][:, :N]
        area = d["area"] if src == "lam" else d["own_area"]
        if src == "lam_idl":
            return lam
        if norm == "area":
            return lam * area[:, None]
        first = [x[max(int(k), 1)] for x, k in zip(d[src], d["zero_modes"], strict=True)]
        return lam / np.array(first)[:, None]
    return f


def paper_cshape(M=16, N=100):
    """The paper's cShape-DNA (Eq. 8-10, area), through cshape itself."""
    def f(d):
        import cshape
        return np.array([cshape.real_form(cshape.compact_shape_dna(x, M=M, N=N, area=a))
                         for x, a in zip(d["lam"], d["area"], strict=True)])
    return f


def log_gaps(n, norm="area"):
    """log of the normalised gaps mu_{i+1} - mu_i, i = 1..n (eigenvalue spacings)."""
    def f(d):
        rows = []
        for mu in _mu(d["lam"], d["area"], d["zero_modes"], norm):
            g = np.diff(mu[: n + 1]) / FOUR_PI
            rows.append(np.log(np.maximum(g, 1e-3)))
        return np.array(rows)
    return f


def heat_trace(n_t=16, src="lam"):
    """log of the unit-area heat trace sum_{i>=k} exp(-mu_i t), n_t times in [1e-3, 1]."""
    t = np.geomspace(1e-3, 1.0, n_t)
    def f(d):
        rows = []
        for mu in _mu(d[src], d["area"] if src == "lam" else d["own_area"], d["zero_modes"],
                      "none" if src == "lam_idl" else "area"):
            rows.append(np.log(np.exp(-np.outer(t, mu)).sum(axis=1)))
        return np.array(rows)
    return f


def quantile_block(key, times=slice(None)):
    """Area-weighted quantiles of log HKS / log WKS at fixed unit-area scales, flattened."""
    return lambda d: d[key][:, times, :].reshape(len(d[key]), -1)


def d2(d):
    return np.sqrt(d["d2"])  # Hellinger: Euclidean distance of square-root histograms


def concat(*parts):
    """Blocks side by side, each multiplied by its weight: parts = ((f, w), ...)."""
    return lambda d: np.hstack([w * f(d) for f, w in parts])


def candidates():
    """(title, family, function, values, eigenvalues only, fitted on realdev) of every
    candidate, in families."""
    C = []

    def add(title, family, f, size, eig=True, fitted=False):
        C.append({"title": title, "family": family, "f": f, "size": size, "eig": eig,
                  "fitted": fitted})

    add("the former default: truncated log, lam_1-norm., M=8", "default",
        truncated_log(8, "fiedler"), 17)
    add("paper's cShape-DNA M=16 N=100 (area)", "paper", paper_cshape(16, 100), 33)
    for N in (30, 100):
        add(f"Shape-DNA N={N} (area)", "Shape-DNA", shape_dna(N), N)
    for norm in ("area", "fiedler"):
        nm = "area" if norm == "area" else "lam_1"
        for M in (4, 8, 12, 16, 24, 32, 49):
            if 2 * M + 1 <= 99:
                add(f"truncated log M={M} ({nm})", "truncated log", truncated_log(M, norm),
                    2 * M + 1)
        for N in (30, 50, 100):
            add(f"full log N={N}, {N - 1} ratios ({nm})", "full log", full_log(N, norm), N - 1)
            for M in (4, 8, 12, 16, 24):
                if 2 * M + 1 > N - 1:
                    continue
                for dct in (False, True):
                    name = "DCT" if dct else "DFT"
                    add(f"log-Weyl {name} M={M} N={N} ({nm})", f"log-Weyl {name}",
                        spectral_crop(M, N, norm, dct), 2 * M + 1)
    for n in (16, 32, 64):
        add(f"log gaps n={n} (area)", "log gaps", log_gaps(n), n)
    add("log heat trace, 16 unit-area times", "heat trace", heat_trace(16), 16)
    # beyond eigenvalues: cshape's eigenpairs of the meshes
    add("HKS quantiles 8 times x 10", "HKS", quantile_block("hks_q"), 80, eig=False)
    add("WKS quantiles 8 energies x 10", "WKS", quantile_block("wks_q"), 80, eig=False)
    add("D2 shape distribution, 64 bins (Hellinger)", "D2", d2, 64, eig=False)
    # the intrinsic Delaunay Laplacian (robust-laplacian, lumped mass)
    for M in (8, 16, 24):
        add(f"intrinsic Delaunay: truncated log M={M} (area)", "intrinsic Delaunay",
            truncated_log(M, "area", "lam_idl"), 2 * M + 1, eig=False)
    add("intrinsic Delaunay: full log N=100 (area)", "intrinsic Delaunay",
        full_log(100, "area", "lam_idl"), 99, eig=False)
    add("intrinsic Delaunay: log-Weyl DFT M=8 N=100 (area)", "intrinsic Delaunay",
        spectral_crop(8, 100, "area", False, "lam_idl"), 17, eig=False)
    add("intrinsic Delaunay: log-Weyl DCT M=12 N=100 (area)", "intrinsic Delaunay",
        spectral_crop(12, 100, "area", True, "lam_idl"), 25, eig=False)
    # combinations, weights w from a small grid; the best of a grid is fitted on realdev
    for w in (0.05, 0.1, 0.2, 0.4, 0.8, 1.6):
        add(f"truncated log M=16 (area) + {w} x HKS quantiles", "eig + HKS",
            concat((truncated_log(16, "area"), 1.0), (quantile_block("hks_q"), w)), 113,
            eig=False, fitted=True)
        add(f"truncated log M=16 (area) + {w} x WKS quantiles", "eig + WKS",
            concat((truncated_log(16, "area"), 1.0), (quantile_block("wks_q"), w)), 113,
            eig=False, fitted=True)
        add(f"truncated log M=16 (area) + {w} x log heat trace", "eig + heat trace",
            concat((truncated_log(16, "area"), 1.0), (heat_trace(16), w)), 49, fitted=True)
    for w in (0.5, 1.0, 2.0):
        add(f"truncated log M=16 (area) + {w} x D2", "eig + D2",
            concat((truncated_log(16, "area"), 1.0), (d2, w)), 97, eig=False, fitted=True)
    return C


def crosscheck(real):
    """Largest difference between this script's distances and cshape's, per descriptor."""
    from cshape import Descriptor
    from cshape.compare import distance_matrix

    checks = (("truncated log M=8 (lam_1)", truncated_log(8, "fiedler"),
               {"kind": "truncated-log", "M": 8, "normalization": "fiedler"}),
              ("truncated log M=8 (area)", truncated_log(8, "area"),
               {"kind": "truncated-log", "M": 8, "normalization": "area"}),
              ("log-Weyl DFT M=8 N=100 (area)", spectral_crop(8, 100, "area", False),
               {"kind": "cshape", "M": 8, "transform": "log-weyl"}),
              ("log-Weyl DCT M=8 N=100 (area)", spectral_crop(8, 100, "area", True),
               {"kind": "cshape", "M": 8, "transform": "log-weyl-dct"}))
    out = []
    for title, f, kw in checks:
        diff = 0.0
        for d in real:
            A = distance_matrix(f(d))
            B = distance_matrix(Descriptor(**kw, N=100).matrix(d["lam"], d["area"],
                                                               zero_modes=d["zero_modes"]))
            diff = max(diff, float(np.abs(A - B).max() / B.max()))
        out.append((title, diff))
    return out


# --------------------------------------------------------------------------- scoring
def score(X, labels):
    from cshape.compare import distance_matrix, retrieval_per_query

    per = retrieval_per_query(distance_matrix(X), labels)
    return per


def evaluate(cands, real, suite):
    rows = []
    for c in cands:
        r = {k: v for k, v in c.items() if k != "f"}
        r["real"], r["suite"], r["per_ft"] = {}, {}, {}
        for d in real:
            per = score(c["f"](d), d["labels"])
            r["real"][d["name"]] = {k: float(np.nanmean(per[k]))
                                    for k in ("nn", "ft", "st", "dcg", "map")}
            r["per_ft"][d["name"]] = per["ft"]
        for b, d in suite.items():
            per = score(c["f"](d), d["labels"])
            r["suite"][b] = {k: float(np.nanmean(per[k])) for k in ("nn", "ft")}
        ft = [s["ft"] for s in r["real"].values()]
        r["worst"], r["mean"] = float(min(ft)), float(np.mean(ft))
        r["guard"] = r["suite"]["resolutions"]["nn"] >= GUARD_NN
        rows.append(r)
    return rows


def choose(rows):
    ok = [r for r in rows if r["guard"] and not r["fitted"]]
    best = max(r["worst"] for r in ok)
    tied = [r for r in ok if r["worst"] >= best - TIE]
    tied.sort(key=lambda r: (not r["eig"], r["size"], -r["mean"]))
    return tied[0], tied, best


def paired(r1, r2, name):
    d = r1["per_ft"][name] - r2["per_ft"][name]
    d = d[~np.isnan(d)]
    return float(d.mean()), float(d.std(ddof=1) / np.sqrt(len(d)))


# --------------------------------------------------------------------------- zero modes
def zero_mode_report(real):
    """Round-off of the zero modes and the lam_1 / lam_max room, per solver; refusals."""
    import cshape

    lines = ["## Zero modes", "",
             "Round-off of `lam_0` relative to `lam_max` (the 100th eigenvalue) per solver on "
             "the real meshes (all connected), and the room above: `lam_1 / lam_max`.", "",
             "| collection | solver | max abs(lam_0) / lam_max | min lam_0 | min lam_1 / lam_max |",
             "|---|---|---|---|---|"]
    worst_zero, min_room = 0.0, np.inf
    for d in real:
        for key, what in (("lam", "reference (linear FEM + ARPACK, independent)"),
                          ("own_lam", "cshape.eigenpairs"),
                          ("lam_arpack", "scipy eigsh on cshape's A, B (tol=0, sigma<0)"),
                          ("lam_lapy", "LaPy Solver.eigs")):
            if key not in d:
                continue
            lam = d[key]
            z = np.abs(lam[:, 0]) / lam[:, -1]
            room = lam[:, 1] / lam[:, -1]
            worst_zero, min_room = max(worst_zero, z.max()), min(min_room, room.min())
            lines.append(f"| {d['name']} | {what} | {z.max():.2g} | {lam[:, 0].min():.2g} | "
                         f"{room.min():.2g} |")
    lines.append("")
    refused = []
    for d in real:
        for i, (x, a) in enumerate(zip(d["lam"], d["area"], strict=True)):
            try:
                cshape.compact_shape_dna(x, M=8, N=100, area=a, transform="log-weyl")
            except ValueError as exc:
                refused.append(f"{d['name']}/{d['files'][i]}: {exc}")
            if cshape.count_zero_modes(x) != 1:
                refused.append(f"{d['name']}/{d['files'][i]}: count_zero_modes = "
                               f"{cshape.count_zero_modes(x)}")
    lines += ["Refused today by `compact_shape_dna(lam, M=8, N=100, area=a, "
              "transform='log-weyl')` or counted wrong by `count_zero_modes` (reference "
              "spectra): " + ("; ".join(refused) if refused else "**none of the 248**") + ".",
              ""]
    return lines, worst_zero, min_room


def pieces_report(k_values=(4, 44)):
    """Zero modes of meshes of k disjoint pieces (icospheres of 3 sizes), per solver."""
    import cshape
    from cshape.fem import fem_matrices

    lines = ["Meshes of `k` disjoint pieces (icospheres of radius 0.5 to 2, 162 vertices "
             "each): largest abs(lam_j) / lam_max over the `k` zero modes, and "
             "lam_k / lam_max (the first non-zero).", "",
             "| k | solver | max zero mode / lam_max | lam_k / lam_max |", "|---|---|---|---|"]
    out = 0.0
    for k in k_values:
        s = cshape.shapes.icosphere(2)
        V0, F0 = np.asarray(s.vertices), np.asarray(s.faces)
        Vs, Fs = [], []
        for j in range(k):
            Vs.append(V0 * (0.5 + 1.5 * j / max(k - 1, 1)) + np.array([5.0 * j, 0, 0]))
            Fs.append(F0 + j * len(V0))
        mesh = cshape.Mesh(np.vstack(Vs), np.vstack(Fs))
        N = k + 40
        sols = {"cshape.shape_dna": cshape.shape_dna(mesh, N=N)}
        A, B = fem_matrices(mesh)[:2]
        from scipy.sparse.linalg import eigsh
        sols["scipy eigsh (tol=0, sigma<0)"] = np.sort(eigsh(
            (-A).tocsc(), k=N, M=B.tocsc(), sigma=-0.01, which="LM",
            return_eigenvectors=False))
        try:
            from lapy import Solver, TriaMesh
            sols["LaPy Solver.eigs"] = np.sort(Solver(TriaMesh(mesh.vertices, mesh.faces))
                                               .eigs(k=N)[0])
        except ImportError:
            pass
        for what, lam in sols.items():
            z = np.abs(lam[:k]).max() / lam[-1]
            out = max(out, z)
            lines.append(f"| {k} | {what} | {z:.2g} | {lam[k] / lam[-1]:.2g} |")
    return lines + [""], out


# --------------------------------------------------------------------------- report
def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--realdev", default="../shared/realdev",
                    help="folder with shrec07-dev/ and tosca-dev/")
    ap.add_argument("--out", default=str(Path(__file__).resolve().parent / "results"
                                         / "real_collections.md"))
    ap.add_argument("--cache", default="/tmp/realdev_cache")
    args = ap.parse_args(argv)
    realdev = Path(args.realdev)
    if not all((realdev / c / "reference-spectra.npz").exists() for c in COLLECTIONS):
        print(f"no real development collections in {realdev} (needs "
              f"{' and '.join(COLLECTIONS)} with reference-spectra.npz); nothing measured",
              file=sys.stderr)
        return 2
    cache = Path(args.cache)
    cache.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    real = [load_real(realdev / c, cache) for c in COLLECTIONS]
    suite = load_suite(cache)
    cands = candidates()
    rows = evaluate(cands, real, suite)
    chosen, tied, best = choose(rows)
    default = rows[0]
    paper = rows[1]
    others = sorted((r for r in rows if r is not chosen and r["guard"] and not r["fitted"]),
                    key=lambda r: -r["worst"])
    runner = others[0]
    best_any = max(rows, key=lambda r: r["worst"])

    # own spectra check: the chosen descriptor from cshape's eigenvalues of the meshes
    own = []
    for c in cands:
        if c["title"] == chosen["title"] or c["title"] == default["title"]:
            for d in real:
                dd = dict(d, lam=d["own_lam"], area=d["own_area"])
                own.append((c["title"], d["name"],
                            float(np.nanmean(score(c["f"](dd), d["labels"])["ft"]))))

    zlines, worst_zero, min_room = zero_mode_report(real)
    plines, worst_pieces = pieces_report()

    cmd = "benchmarks/bench_real_collections.py " + " ".join(
        argv if argv is not None else sys.argv[1:])
    S, T = COLLECTIONS
    lines = [
        "# Candidate descriptors on real labelled collections and the generated suite", "",
        f"`{cmd.strip()}`; {machine_summary(('scipy', 'robust_laplacian', 'lapy'))}; "
        f"{time.perf_counter() - t0:.0f} s", "",
        f"Real: `{S}` (category level: 10 classes of SHREC 2007 watertight, 200 meshes) and "
        f"`{T}` (instance level: 6 TOSCA characters in poses, 48 meshes). Eigenvalue "
        "descriptors use the collections' reference spectra (N = 100, an independent solver); "
        "HKS, WKS, D2 and the intrinsic Delaunay spectra come from the meshes (cshape's "
        "eigenpairs; `robust_laplacian.mesh_laplacian`, lumped mass). Generated: the suite's "
        "development instances (`creatures-dev`, `identities-dev`, `resolutions-dev`). "
        "Scores: `cshape.compare.retrieval_scores` (Princeton Shape Benchmark).", "",
        "**Rule**: among the candidates with nothing fitted on the real collections and "
        f"nearest neighbour >= {GUARD_NN} on `resolutions-dev`, the highest **worst first "
        f"tier over the two real collections**; within {TIE} of it is a tie, broken by "
        "simplicity: eigenvalues only, then fewer values, then the higher mean. Combinations "
        "whose weight was picked from a grid on these collections are reported, never chosen "
        "(their scores here are fitted ones).", "",
        f"**Chosen: {chosen['title']}** ({chosen['size']} values, "
        f"{'eigenvalues only' if chosen['eig'] else 'needs eigenvectors'}, "
        f"{'weights fitted on realdev' if chosen['fitted'] else 'nothing fitted'}): first "
        f"tier {chosen['real'][S]['ft']:.3f} on {S}, {chosen['real'][T]['ft']:.3f} on {T} "
        f"(worst {chosen['worst']:.3f}); resolutions-dev NN "
        f"{chosen['suite']['resolutions']['nn']:.3f}.", "",
        f"Tied within {TIE} (best worst {best:.3f}): "
        + "; ".join(f"{r['title']} ({r['worst']:.3f})" for r in tied) + ".", "",
        f"Margin: over the best other candidate ({runner['title']}, worst "
        f"{runner['worst']:.3f}) {chosen['worst'] - runner['worst']:+.3f}; over today's "
        f"default {chosen['worst'] - default['worst']:+.3f}; over the paper's cShape-DNA "
        f"{chosen['worst'] - paper['worst']:+.3f}. First tier paired over the queries, "
        "chosen minus runner-up (mean +- standard error): "
        + "; ".join(f"{n} {m:+.3f} +- {se:.3f}" for n, (m, se) in
                    ((n, paired(chosen, runner, n)) for n in COLLECTIONS))
        + "; chosen minus the former default: "
        + "; ".join(f"{n} {m:+.3f} +- {se:.3f}" for n, (m, se) in
                    ((n, paired(chosen, default, n)) for n in COLLECTIONS)) + ".", "",
        f"Best worst first tier of any candidate, guard or not, fitted or not: "
        f"{best_any['title']} ({best_any['worst']:.3f}; first tier "
        f"{best_any['real'][S]['ft']:.3f} on {S}, weight picked on these collections; "
        f"resolutions-dev NN {best_any['suite']['resolutions']['nn']:.3f}).", "",
        "Check of this script's descriptors against `cshape.Descriptor.matrix` "
        "(largest difference of the distance matrices, reference spectra): "
        + "; ".join(f"{t}: {v:.1g}" for t, v in crosscheck(real)) + ".", "",
        "From cshape's own eigenvalues of the meshes instead of the reference spectra "
        "(first tier): " + "; ".join(f"{t} on {n}: {v:.3f}" for t, n, v in own) + ".", "",
    ]

    def table(title, rs):
        out = [f"## {title}", "",
               f"| candidate | values | eig. only | fitted | {S} NN | FT | ST | DCG | mAP | "
               f"{T} NN | FT | ST | DCG | mAP | worst FT | creatures FT | identities FT | "
               "resolutions FT | resolutions NN |",
               "|---|---|---|---|" + "---|" * 15]
        for r in rs:
            name = f"**{r['title']}**" if r is chosen else r["title"]
            cells = [f"{r['real'][n][k]:.3f}" for n in COLLECTIONS
                     for k in ("nn", "ft", "st", "dcg", "map")]
            cells.append(f"{r['worst']:.3f}")
            cells += [f"{r['suite'][b]['ft']:.3f}" for b in SUITE_BENCHES]
            cells.append(f"{r['suite']['resolutions']['nn']:.3f}"
                         + ("" if r["guard"] else " (guard)"))
            out.append(f"| {name} | {r['size']} | {'yes' if r['eig'] else 'no'} | "
                       f"{'yes' if r['fitted'] else 'no'} | " + " | ".join(cells) + " |")
        return out + [""]

    ranked = sorted(rows, key=lambda r: -r["worst"])
    lines += table("The 20 best by worst real first tier, with the former default and the "
                   "paper's", ranked[:20] + [r for r in (default, paper) if r not in ranked[:20]])
    fam_best = {}
    for r in ranked:
        fam_best.setdefault(r["family"], r)
    lines += table("The best of each family", list(fam_best.values()))
    lines += table("Every candidate", rows)
    tol = np.sqrt(max(worst_zero, worst_pieces) * min_room)
    lines += zlines + plines + [
        f"Largest zero-mode round-off measured: {max(worst_zero, worst_pieces):.2g} of "
        f"lam_max; smallest lam_1 / lam_max of a connected real mesh: {min_room:.2g}. Their "
        f"geometric mean is {tol:.2g}.", ""]
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text("\n".join(lines) + "\n")
    with open(Path(args.out).with_suffix(".csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["candidate", "family", "values", "eigenvalues_only", "fitted_on_realdev",
                    *(f"{n}_{k}" for n in COLLECTIONS for k in ("nn", "ft", "st", "dcg", "map")),
                    *(f"{b}-dev_{k}" for b in SUITE_BENCHES for k in ("nn", "ft"))])
        for r in rows:
            w.writerow([r["title"], r["family"], r["size"], r["eig"], r["fitted"],
                        *(f"{r['real'][n][k]:.4f}" for n in COLLECTIONS
                          for k in ("nn", "ft", "st", "dcg", "map")),
                        *(f"{r['suite'][b][k]:.4f}" for b in SUITE_BENCHES
                          for k in ("nn", "ft"))])
    print("\n".join(lines[:30]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
