"""Smoke tests of the scale benchmarks in ``benchmarks/`` (issue 7): they import and their core
functions run on tiny inputs, so that the scripts cannot rot.  No timing is asserted; speed is
measured by running the scripts themselves (see ``benchmarks/SCALE.md``)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"


def _load(name):
    """Import ``benchmarks/<name>.py`` as a module (benchmarks/ is not a package)."""
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, BENCH / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod
    spec.loader.exec_module(mod)
    return mod


@pytest.fixture
def results(tmp_path, monkeypatch):
    """Point every benchmark's results folder at a temporary one."""
    for name in ("bench_bigmesh", "bench_throughput", "bench_queries"):
        monkeypatch.setattr(_load(name), "RESULTS", tmp_path)
    return tmp_path


@pytest.mark.slow
def test_bigmesh_measure_and_report(results):
    bm = _load("bench_bigmesh")
    r = bm.measure("cshape", 50, 30, N=10)  # 1500 vertices: the sparse (Lanczos) path
    assert r["n_vertices"] == 1500 and len(r["lam"]) == 10
    assert r["seconds"] > 0 and r["peak_mib"] >= r["baseline_mib"] > 0
    assert r["lam"][0] == 0.0
    rows = [{"label": "a", "n": 1500, "cshape_s": r["seconds"], "cshape_peak": r["peak_mib"],
             "cshape_solve": max(r["solve_mib"], 1.0), "lapy_s": float("nan"),
             "lapy_peak": float("nan"), "lapy_solve": float("nan"), "lapy_note": "skipped",
             "maxrel": float("nan"), "load1": 1.0}]
    rows.append({**rows[0], "label": "b", "n": 6000, "cshape_s": 4 * r["seconds"]})
    path = results / "bigmesh.md"
    exps = bm.write_results(rows, path, bm.section_key(["a", "b"], 1), "summary", 10, 1)
    assert exps["cshape time"] == pytest.approx(1.0)
    assert path.read_text().count("\n| ") == 3
    # another set of sizes adds its section; the same set again replaces its own
    bm.write_results(rows[:1], path, bm.section_key(["a"], 1), "one size", 10, 1)
    bm.write_results(rows, path, bm.section_key(["a", "b"], 1), "again", 10, 1)
    text = path.read_text()
    assert text.count("\n| ") == 3 + 2 and "again" in text and "summary" not in text
    assert bm.growth_exponent([1, 10, 100], [2, 20, 200]) == pytest.approx(1.0)
    assert bm.max_relative_difference([0, 2.0], [1e-15, 2.0 + 2e-12]) < 1e-11


def test_bigmesh_lapy_agrees():
    pytest.importorskip("lapy")
    bm = _load("bench_bigmesh")
    a = bm.measure("cshape", 50, 30, N=10)
    b = bm.measure("lapy", 50, 30, N=10)
    assert bm.max_relative_difference(a["lam"], b["lam"]) < 1e-8


def test_throughput_collection_and_serial_mode(results):
    tp = _load("bench_throughput")
    col = tp.make_collection(4, "tiny", seed=1)
    assert len({name for name, _, _ in col}) == 4
    assert all(100 < m.n_vertices < 500 for _, _, m in col)
    r = tp.run_mode(col, "serial", N=20)
    assert r["meshes"] == 4 and r["failed"] == 0 and r["per_minute"] > 0
    assert r["table"].lam.shape == (4, 20)
    with pytest.raises(ValueError, match="mode"):
        tp.run_mode(col, "threads")
    cores = tp.free_cores(2, n=10_000)  # a ratio of two timings: no bound but its sign
    assert isinstance(cores, float) and np.isfinite(cores) and cores > 0


@pytest.mark.slow
def test_queries_descriptors_and_exact_search(results):
    q = _load("bench_queries")
    from cshape import Descriptor

    rng = np.random.default_rng(0)
    base = np.sort(rng.uniform(0, 4 * np.pi * 100, (5, 100)), axis=1)
    base[:, 0] = 0.0
    lam = q.perturb(base, 300, rng)
    assert lam.shape == (300, 100) and np.all(lam[:, 0] == 0)
    for M in (1, 16):
        np.testing.assert_allclose(q.cshape_rows(lam[:20], M),
                                   Descriptor("cshape", M=M).matrix(lam[:20], np.ones(20)),
                                   rtol=1e-12, atol=1e-9)
    X = q.descriptors(lam, "cShape-DNA M=16")
    Q = q.descriptors(q.perturb(base, 7, rng), "cShape-DNA M=16")
    d_np, i_np = q.NumpyBruteForce(X, group=3).query(Q, k=5)
    d_one, _ = q.NumpyBruteForce(X).query(Q[:1], k=5)
    d_ix, i_ix = q.build("DescriptorIndex", X).query(Q, k=5)
    np.testing.assert_allclose(d_np, d_ix, rtol=1e-10)
    np.testing.assert_allclose(d_one, d_ix[:1], rtol=1e-10)
    res, dist = q.measure("numpy", X, Q, k=3, n_single=2)
    assert dist.shape == (7, 3) and res["single_ms"] > 0 and res["db_mib"] > 0


def test_descriptors_benchmark_scores_every_row_at_equal_size():
    from cshape import DescriptorTable, shape_dna, shapes

    bd = _load("bench_descriptors")
    meshes = [("s1", "sphere", shapes.icosphere(2)), ("s2", "sphere", shapes.icosphere(2, 2.0)),
              ("t1", "torus", shapes.torus(20, 10)), ("t2", "torus", shapes.torus(24, 12))]
    lam = np.array([shape_dna(m, N=12) for _, _, m in meshes])
    table = DescriptorTable([n for n, _, _ in meshes], lam, [m.area for _, _, m in meshes],
                            [c for _, c, _ in meshes])
    rows = bd.score_table(table, [1, 2], 12)
    assert len(rows) == 1 + 2 * len(bd.ROWS) and rows[0]["size"] == 12
    assert {r["size"] for r in rows[1:]} == {3, 5}
    assert all(0 <= r[k] <= 1 for r in rows for k in bd.MEASURES)
    best = bd.winners(rows)
    assert set(best) == {3, 5} and all(0 < s <= 1 for _, s in best.values())
    assert "cShape-DNA (paper)" in best[3][0]  # spheres vs tori: every row is perfect, a tie
    pairs = {5: bd.paired(table, 2, 12)}
    assert set(pairs[5]) == {"ft", "map"}
    sweep = bd.n_sweep(table, Ms=[2], Ns=[8, 12])
    assert {(r["N"], r["transform"]) for r in sweep} >= {(6, "weyl"), (12, "log-weyl-dct")}
    at6 = {r["transform"]: r for r in sweep if r["N"] == 6}  # N = 2M+2: nothing cropped
    assert at6["log-weyl"]["map"] == pytest.approx(at6["log-weyl-dct"]["map"])
    md = bd.markdown(rows, "tiny", 4, 2, 12, "header", pairs, sweep)
    assert md.count("\n| ") >= 3 and "paired" in md
    every = md[md.index("Every descriptor at every size"):]
    assert every.count("\n| ") == 1 + len(rows)  # its header and every row


def test_sweep_checks_every_run_on_a_sphere_against_its_exact_spectrum():
    pytest.importorskip("lapy")
    from cshape import shapes

    sw = _load("bench_sweep")
    exact = shapes.sphere_spectrum(16)  # l = 0..3, every copy
    # a spectrum that skipped one copy of l(l+1) = 6 moves every later value a cluster up
    skipped = np.concatenate([exact[:5], exact[6:], [30.0]])
    assert not sw.missed_copies(exact * 1.001, exact) and sw.missed_copies(skipped, exact)
    r = sw.compare(shapes.icosphere(3), 16, repeats=2, lapy=("default", "cholespy"),
                   exact=exact)  # 642 vertices: 2 cshape runs, 4 LaPy runs
    m = r["missed"]
    assert m["cshape"] == 0 and m["runs_cshape"] == 2 and m["runs_lapy"] == 4
    assert 0 <= m["lapy"] <= 4 and r["maxrel"] < 1e-8 and r["same_bits"]
    line = sw.missed_lines([("tiny", r)])[0]
    assert f"tiny: cshape 0 of 2 runs, LaPy {m['lapy']} of 4" in line
    assert sw.compare(shapes.torus(30, 12), 10, repeats=1)["missed"] is None


@pytest.mark.slow
def test_signatures_bench_on_small_meshes(tmp_path, monkeypatch):
    pytest.importorskip("lapy")
    bs = _load("bench_signatures")
    monkeypatch.setattr(bs, "RESULTS", tmp_path)
    mesh = bs.torus_mesh(2000)
    assert abs(mesh.n_vertices - 2000) < 100
    sig = bs.time_signatures(mesh, N=20, n_scales=30, n_match=50)
    assert sig["hks_shape"] == (mesh.n_vertices, 30) and sig["si_hks_shape"] == (mesh.n_vertices, 6)
    assert sig["match_dist"] < 1e-6 and all(sig[k] > 0 for k in ("eigenpairs", "hks", "wks"))
    lines = bs.speed_lines(sig, "header", "footer")
    assert sum(line.startswith("| ") for line in lines) == 7  # the header and six steps
    out = tmp_path / "s.md"
    for _ in range(2):  # a part run again replaces its section
        assert bs.main(["--out", str(out), "speed", "--vertices", "1500", "--scales", "30",
                        "-N", "12"]) == 0
    text = out.read_text()
    assert text.startswith("# Point signatures") and text.count("<!-- section: speed -->") == 1


@pytest.mark.slow
def test_correspondence_bench_on_a_small_template(tmp_path):
    pytest.importorskip("pymeshlab")
    bc = _load("bench_signatures")
    small = {"voxelsize": 0.03, "target_vertices": 800}
    rows = bc.evaluate("quadruped", [None, 1], N=30, n_scales=30, template=small)
    assert len(rows) == 2 * len(bc.DESCRIPTORS)
    assert all(0 <= r["acc"] <= r["acc_mirror"] <= 1 for r in rows)
    assert all(r["mean_err_mirror"] <= r["mean_err"] for r in rows)
    # the rest pose against itself: every descriptor finds every vertex
    assert all(r["acc"] == 1.0 and r["mean_err"] == 0.0 and r["mutual_kept"] == 1.0
               for r in rows if r["seed"] is None)
    assert all(0 < r["mutual_kept"] <= 1 and 0 <= r["mutual_acc"] <= 1 for r in rows)
    # a real pose: the oracle alignment moves only the limbs off, signatures lose some
    posed = {r["descriptor"]: r for r in rows if r["seed"] == 1}
    assert 0.3 < posed["xyz, rigid oracle"]["acc"] < 1.0
    lines = bc.correspondence_lines(rows, "header", "footer")
    # header, quadruped, all
    assert sum(line.startswith("| ") for line in lines) == 1 + 2 * len(bc.DESCRIPTORS)


@pytest.mark.slow
def test_sweep_bench_stages_ratios_and_throughput(tmp_path, monkeypatch):
    pytest.importorskip("lapy")
    sw = _load("bench_sweep")
    monkeypatch.setattr(sw, "RESULTS", tmp_path)
    monkeypatch.setitem(sw.SIZES, "tiny", ("torus", 40, 20))  # 800 vertices: sparse path
    lapy = ("default", "cholespy", "cholespy-1t")
    r = sw.compare(sw.make_mesh("tiny"), 20, repeats=1, threads=(1, 2), lapy=lapy)
    assert r["n"] == 800 and r["maxrel"] < 1e-8 and r["same_bits"] and r["threads_maxrel"] < 1e-10
    assert set(r["cshape"]) == {1, 2} and set(r["lapy"]) == set(lapy)
    for s in lapy:  # LaPy's stages add up to its time
        ls = r["lapy_stages"][s]
        assert all(ls[k] > 0 for k in ("assembly", "factorise", "solves"))
        assert sum(ls.values()) == pytest.approx(r["lapy"][s])
    # one repeat: the paired ratio is that repeat's, the ratio of the bests
    assert set(r["paired"]) == {(s, t) for s in lapy for t in (1, 2)}
    assert all(r["paired"][s, t] == pytest.approx(r["lapy"][s] / r["cshape"][t])
               for s in lapy for t in (1, 2))
    st = r["stages"]
    assert all(st[k] > 0 for k in ("prepare", "factorise", "solves", "rayleigh_ritz"))
    assert sum(st[k] for k in sw.STAGES) == pytest.approx(st["total"]) and not st["missing"]
    lines = (sw.sweep_lines([("tiny", r)], (1, 2), lapy, "t", "a processor")
             + sw.summary_lines([("tiny", r)], (1, 2), lapy))
    assert sum(line.startswith("| tiny | 800 |") for line in lines) == 1
    assert "Processor: a processor." in lines
    assert sum(line.startswith("LaPy ") for line in lines) == 6  # a sum per pair
    # LaPy's defaults are read from LaPy itself (1.7.0: use_cholmod=False, SuperLU)
    assert sw.lapy_label("default").startswith(
        f"LaPy defaults (use_cholmod={sw.lapy_default_cholmod()}")
    meshes = [("a", sw.make_mesh("tiny")), ("b", sw.make_mesh("tiny"))]
    rows = sw.throughput(meshes, 10, workers=1, lapy=("default", "cholespy-1t"))
    assert [(x["who"], x["workers"]) for x in rows] == [
        ("cshape", 1), ("default", 1), ("cholespy-1t", 1)]
    assert all(x["per_minute"] > 0 for x in rows)
    out = tmp_path / "t.md"
    for _ in range(2):  # the same kind of run again replaces its section
        assert sw.main(["--sizes", "1k", "--repeats", "1", "--no-real", "-N", "10",
                        "--out", str(out)]) == 0
    text = out.read_text()
    assert text.count("| 1k | 1,000 |") == 1 and text.startswith(f"# {sw.TITLE}")
    assert "## Sizes: cshape.shape_dna against LaPy (N=10)" in text
    assert f"bench_sweep.py --sizes 1k --repeats 1 --no-real -N 10 --out {out}`" in text
    with pytest.raises(SystemExit):
        sw.main(["--lapy", "fastest"])


def test_sweep_sections_are_named_by_what_they_measure():
    import re

    sw = _load("bench_sweep")
    section = sw.results_section
    assert section(False, True, ["1k", "160k"], False, 0) == "sizes"
    assert section(False, True, ["650k", "1m"], False, 0) == "big meshes"
    assert section(False, True, ["1k"], True, 0) == "sizes and real meshes"
    assert section(False, False, ["1k"], True, 0) == "real meshes"
    assert section(False, False, ["1k"], False, 30) == "collection"
    assert section(True, True, ["160k"], False, 0) == "eigenpairs"
    # the one result file holds a section per kind of run, each ending where it says
    text = sw.RESULT.read_text()
    keys = re.findall(r"<!-- section: (.+?) -->", text)
    assert set(keys) >= {"sizes", "real meshes", "big meshes", "eigenpairs", "collection"}
    assert keys == re.findall(r"<!-- end of section: (.+?) -->", text)


def test_write_section_replaces_its_own_section_and_keeps_the_others(tmp_path):
    common = _load("_common")
    path = tmp_path / "r.md"
    common.write_section(path, "a", ["## A", "first"], "Title")
    common.write_section(path, "b", ["## B", "second"], "Title")
    common.write_section(path, "a", ["## A", "third"], "Title")
    text = path.read_text()
    assert text.startswith("# Title\n") and text.count("# Title") == 1
    assert "first" not in text and text.index("third") < text.index("second")
    assert text.count("<!-- section: a -->") == 1 == text.count("<!-- end of section: a -->")


@pytest.mark.slow
def test_signature_retrieval_bench_descriptors_are_scale_invariant():
    from cshape import shapes

    br = _load("bench_signatures")
    X = np.array([[1.0], [2.0], [3.0], [4.0]])
    q = br.weighted_quantiles(X, np.array([1.0, 1.0, 1.0, 5.0]), qs=(0.5, 0.9))
    # value 4 holds 5/8 of the weight, centred at 3/8 + 5/16 = 0.6875; value 3 at 0.3125
    np.testing.assert_allclose(q[:, 0], [3.5, 4.0])
    meshes = [shapes.icosphere(3), shapes.icosphere(3, 2.5), shapes.torus(24, 12),
              shapes.torus(24, 12, R=2.0, r=0.8)]
    descs = [br.shape_descriptors(m, N=30) for m in meshes]
    assert [len(descs[0][k]) for k in descs[0]] == [29, 80, 80]
    for k in descs[0]:  # area-normalised: a scaled copy has the same descriptor
        np.testing.assert_allclose(descs[1][k], descs[0][k], rtol=1e-6, atol=1e-8)
        np.testing.assert_allclose(descs[3][k], descs[2][k], rtol=1e-6, atol=1e-8)
        assert np.abs(descs[2][k] - descs[0][k]).max() > 1e-2
    rows = br.score(descs, ["sphere", "sphere", "torus", "torus"])
    assert all(r["nn"] == 1.0 and r["map"] == 1.0 for r in rows)
    lines = br.retrieval_lines(rows, "tiny", 4, 2, "h", "f")
    assert sum(line.startswith("| ") for line in lines) == 4


def test_machine_summary_names_the_processor(monkeypatch, tmp_path):
    """Every benchmark header names the processor (ratios moved up to 1.7x with it)."""
    common = _load("_common")
    cpuinfo = tmp_path / "cpuinfo"
    cpuinfo.write_text("processor\t: 0\nmodel name\t: Test CPU 9000\ncpu MHz\t\t: 2599.998\n"
                       "flags\t\t: fpu sse4_2 avx avx2 fma\n\nprocessor\t: 1\n"
                       "model name\t: Other\n")
    real_open = open

    def fake_open(path, *args, **kwargs):
        if str(path) == "/proc/cpuinfo":
            return real_open(cpuinfo, *args, **kwargs)
        if str(path).startswith("/sys/devices/system/cpu/cpu0/cache/"):
            raise OSError("no cache information")
        return real_open(path, *args, **kwargs)

    monkeypatch.setattr("builtins.open", fake_open)
    assert common.cpu_summary() == "Test CPU 9000, 2600 MHz, avx2"
    assert "cores (Test CPU 9000, 2600 MHz, avx2), " in common.machine_summary()


def test_maps_measure_and_report(tmp_path, monkeypatch):
    bm = _load("bench_maps")
    monkeypatch.setattr(bm, "RESULTS", tmp_path)
    import cshape

    m = cshape.shapes.icosphere(2)
    S = cshape.Mesh(m.vertices * [1.0, 0.7, 0.5] + 0.1 * m.vertices[:, :1] ** 2, m.faces)
    res, common_s = bm.measure(S, S, n=40)
    assert set(res) == set(bm.METHODS) and common_s > 0
    assert all(0 <= w <= 1 and 0 <= g <= 1 and e >= 0 and s >= 0
               for w, g, e, s in res.values())
    # a shape mapped to itself: ZoomOut with the orientation term finds the identity
    assert res["FM + ZoomOut, orientation"][0] > 0.9
    rows = [("a", "a -> a", S.n_vertices, common_s, res)]
    text = bm.write_accuracy(rows, "maps_test", "--quick")
    assert (tmp_path / "maps_test.md").read_text() == text + "\n"
    assert text.count("| a -> a |") == len(bm.METHODS)
    # the identity check: a pose of itself keeps every edge length
    share, stretch = bm.identity_check(S, S)
    assert share == 1.0 and stretch == 0.0


def test_refine_bench_p2_prototype_and_report(tmp_path):
    br = _load("bench_refine")
    from cshape import shapes

    # the P2 prototype: the Dirichlet square's 2 pi^2 to order h^4, its mass matrix the area
    A, B = br.p2_matrices(shapes.square(4), "dirichlet")
    assert np.isclose(br.p2_matrices(shapes.square(4))[1].sum(), 1.0)
    lam = br.spectrum(shapes.square(8), "p2", "dirichlet", 3)
    assert abs(lam[0] / (2 * np.pi**2) - 1) < 1e-3
    assert np.allclose(br.square_spectrum(3, "neumann"), [0, np.pi**2, np.pi**2])
    assert np.isclose(br.disk_spectrum(1, "dirichlet")[0], 2.404825557695773**2)
    known = [("case", 10, [0.1, 0.01, 0.02])]
    orders = {("square", "linear"): ((8, 16), [0.1, 0.025], 2.0)}
    pairs = [("spot", 100, 50, [(0.1, 0.2), (0.01, 0.02), (0.01, 0.02)])]
    costs = [{"size": "1k", "method": "linear", "n": 1000, "seconds": 0.1, "cpu": 0.1,
              "peak_mib": 80, "extra_mib": 10},
             {"size": "1k", "method": "extrapolated", "n": 1000, "seconds": 0.3, "cpu": 0.3,
              "peak_mib": 90, "extra_mib": 20}]
    weights = [("disk", 20, [0.02] * len(br.WEIGHTS), 0.52, 0.004, 0.005)]
    text = br.report(known, orders, pairs, costs, weights)
    assert "| case | 10 | 10 % | 1 % | 2 % |" in text
    assert "| disk | 20 | " + "2 % | " * len(br.WEIGHTS) + "0.52 | 0.4 % | 0.5 % |" in text
    # the weight 1/2 is mass='mixed'
    mesh = shapes.icosphere(2)
    np.testing.assert_allclose(br.weighted_spectrum(mesh, 0.5, n=10),
                               br.spectrum(mesh, "mixed", n=10), rtol=1e-10, atol=1e-12)
    assert "| 1000 | extrapolated | 0.30 | 3.00 |" in text
    assert "| spot 100 / 50 |" in text
def test_choices_bench_compares_like_with_like(tmp_path, capsys):
    from cshape import shapes

    bc = _load("bench_choices")
    mesh = shapes.icosphere(2)
    assert bc.edge_keys(mesh, 1)[2] is True  # the integer keys give np.unique's edges
    assert bc.distinct_rows(mesh, 1)[2] is True
    first, second, nbytes = bc.first_touch(rows=1000, cols=3, repeats=1)
    assert nbytes == 24_000 and first >= 0 and second >= 0
    bc.main(["--level", "1", "--repeats", "1", "--basis-rows", "100",
             "--out", str(tmp_path / "c.md")])
    text = (tmp_path / "c.md").read_text()
    assert text.count("\n| ") == 4 and "Processor:" in text


def test_maps_people_and_stages_tables_show_every_label(tmp_path, monkeypatch):
    """The kept results' label first, another version's beside it, each file's rows as they
    are."""
    bm = _load("bench_maps")
    monkeypatch.setattr(bm, "RESULTS", tmp_path)
    group = bm.GROUPS["remeshed-different"]
    for label, err in (("branch", 0.0300), (bm.CURRENT, 0.0201)):
        (tmp_path / f"maps_people_{label}.csv").write_text(
            f"{bm.HEADER}\n{group},006->049,4676,{err:.4f},0.8180,12.5,2.7,0.0000,12.6\n")
        (tmp_path / f"maps_stages_{label}.csv").write_text(
            'group,pair,vertices,load,"eigenbases",total\n'
            f'"{group}",006->049,4676,3.32,0.50,{err * 500:.2f}\n')
    people = bm.write_people("--people current")
    assert "Labels: *current*; *branch*." in people
    assert "| 006->049 | 4676 | 0.0201 | 0.818 | 12.5 | 12.6 | 2.7 | no | 0.0300 |" in people
    stages = bm.write_stages("--stages current")
    assert stages.index("## current") < stages.index("## branch")
    assert "| total | 10.05 |" in stages and "| total | 15.00 |" in stages
