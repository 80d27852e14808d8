"""`cshape describe`, `cshape info`, `cshape query` on meshes built in code, run through
`cshape.cli.main` in the test's process (the code `python -m cshape` runs) and, where a process
shows more, as `python -m cshape`.

Every expected failure must end in one line on stderr, exit status 2, no traceback and no
file written.
"""

from __future__ import annotations

import contextlib
import json
import os
import socket
import subprocess
import sys

import numpy as np
import pytest
from conftest import cli, write_off

import cshape
from cshape import Descriptor, shapes
from cshape.batch import DescriptorTable
from cshape.cli import main
from cshape.cli.explore import collect_mesh_files

N, M = 20, 4


@contextlib.contextmanager
def socket_port():
    """A free local TCP port (closed again on exit)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        yield s.getsockname()[1]


def assert_one_line_error(res, match):
    assert res.returncode == 2, (res.returncode, res.stderr)
    assert "Traceback" not in res.stderr
    last = res.stderr.strip().splitlines()[-1]
    assert last.startswith("cshape ") and ": error: " in last, res.stderr
    assert match in last, res.stderr


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    """sphere/{small, big} (the same sphere at two scales) and torus/ring, as OFF files."""
    root = tmp_path_factory.mktemp("meshes")
    ico = shapes.icosphere(2)
    write_off(root / "sphere" / "small.off", ico)
    write_off(root / "sphere" / "big.off", (2.0 * ico.vertices, ico.faces))
    write_off(root / "torus" / "ring.off", shapes.torus(24, 12))
    return root


@pytest.mark.slow
def test_describe_folder_then_glob_reads_the_cache(folder, tmp_path):
    out = tmp_path / "table.csv"
    res = cli("describe", folder, "--out", out, "-N", N, "--jobs", 2,
              cache=tmp_path / "c", check=True)
    table = DescriptorTable.load(out)
    assert sorted(zip(table.names, table.labels, strict=True)) == [
        ("big", "sphere"), ("ring", "torus"), ("small", "sphere")]
    assert table.N == N and not table.cached.any()
    assert "3 meshes (0 from the cache)" in res.stderr
    # the eigenvalues are the library's
    lam = cshape.shape_dna(cshape.load_mesh(folder / "torus" / "ring.off"), N=N)
    np.testing.assert_allclose(table.lam[table.index("ring")], lam, rtol=1e-12, atol=1e-12)
    # cShape-DNA is scale invariant: the two spheres have the same descriptor
    S = table.descriptors(Descriptor("cshape", N=N, M=M))
    assert np.abs(S[table.index("big")] - S[table.index("small")]).max() < 1e-8

    # a glob over the same files, to .npz: every mesh from the cache, labels = parent folder
    out2 = tmp_path / "again.npz"
    res = cli("describe", f"{folder}/*/*.off", "--out", out2, "-N", N, cache=tmp_path / "c",
              check=True)
    again = DescriptorTable.load(out2)
    assert again.cached.all() and "3 from the cache" in res.stderr
    d = Descriptor("cshape", N=N, M=M, transform="log-weyl")
    np.testing.assert_array_equal(
        again.descriptors(d), table.descriptors(d)[[table.index(n) for n in again.names]])
    assert sorted(again.names) == sorted(table.names)
    assert again.labels[again.index("ring")] == "torus"
    np.testing.assert_array_equal(again.lam[again.index("ring")], table.lam[table.index("ring")])


@pytest.mark.slow
def test_describe_failure_list_and_exit_status(folder, tmp_path):
    bad = tmp_path / "in" / "bad.off"
    bad.parent.mkdir()
    bad.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n")  # truncated: one vertex and the face missing
    out = tmp_path / "t.csv"
    res = cli("describe", folder / "torus", bad, "--out", out, "-N", N, "--strict",
              cache=tmp_path / "c")
    assert_one_line_error(res, "1 of 2 meshes failed")
    assert "failed: bad:" in res.stderr and "leave out --strict" in res.stderr
    assert not out.exists()
    # by default one mesh never fails the table: it is listed by name and left out
    res = cli("describe", folder / "torus", bad, "--out", out, "-N", N,
              cache=tmp_path / "c", check=True)
    assert "failed: bad:" in res.stderr
    # the counts add up to the meshes tried
    assert "1 meshes (" not in res.stderr
    assert "1 of 2 meshes described (1 from the cache), 1 failed, in " in res.stderr
    table = DescriptorTable.load(out)
    assert table.names == ["ring"] and [n for n, _ in table.failures] == ["bad"]
    assert table.cached.all()  # the first, failed run cached the good mesh
    # every mesh failing is still an error
    res = cli("describe", bad, "--out", out.with_name("u.csv"), "-N", N,
              cache=tmp_path / "c")
    assert_one_line_error(res, "1 of 1 meshes failed")


@pytest.mark.slow
@pytest.mark.parametrize("args, match", [
    (["describe", "no/such/folder"], "no file or folder 'no/such/folder'"),
    (["PROCESS", "describe", "no/such/folder"], "no file or folder 'no/such/folder'"),
    (["describe", "MESHES", "--out", "table.txt"], "--out must end in .csv or .npz"),
    (["describe", "MESHES/*.stl"], "matches no mesh file"),
    (["info", "no_such.obj"], "no mesh file at 'no_such.obj'"),
    (["query", "no_such.csv", "x"], "no descriptor table at 'no_such.csv'"),
    (["describe"], "the following arguments are required: PATH"),  # argparse's errors too
    (["describe", "MESHES", "-N", "x"], "argument -N: invalid int value: 'x'"),
    (["PROCESS", "describe", "MESHES", "-N", "x"], "argument -N: invalid int value: 'x'"),
])
def test_expected_failures_end_in_one_line(folder, tmp_path, args, match):
    """(PROCESS: as ``python -m cshape``, its exit status and stderr.)"""
    args = [str(folder) + a[6:] if a.startswith("MESHES") else a for a in args]
    process = args[0] == "PROCESS"
    res = cli(*args[process:], cache=tmp_path / "c", process=process)
    assert_one_line_error(res, match)
    assert len(res.stderr.strip().splitlines()) == 1, res.stderr
    assert list(tmp_path.iterdir()) == []  # nothing written, not even the cache folder


@pytest.mark.slow
def test_describe_takes_no_descriptor_options(folder, tmp_path):
    """The table holds eigenvalues; the descriptor is chosen by query and overview."""
    for option in (["-M", "10"], ["--transform", "log-weyl"]):
        res = cli("describe", folder, "-N", "20", *option, cache=tmp_path / "c")
        assert res.returncode == 2 and "Traceback" not in res.stderr
        assert res.stderr.strip().splitlines() == [
            f"cshape: error: unrecognized arguments: {' '.join(option)}; see `cshape --help`"]
    assert list(tmp_path.iterdir()) == []


def test_info_topology_angles_and_repair(tmp_path):
    torus = write_off(tmp_path / "torus.off", shapes.torus(24, 12))
    sq = shapes.square(6)
    square = write_off(tmp_path / "square.off", sq)
    # the square with one face repeated and one unused vertex at the end
    V = np.vstack([sq.vertices, [[5.0, 5.0, 5.0]]])
    F = np.vstack([sq.faces, sq.faces[:1]])
    dirty = write_off(tmp_path / "dirty.off", (V, F))
    res = cli("info", torus, square, dirty, "--json", check=True)
    t, s, d = (json.loads(line) for line in res.stdout.splitlines())
    assert (t["vertices"], t["faces"], t["components"]) == (288, 576, 1)
    assert t["closed"] and t["genus"] == 1 and t["euler_characteristic"] == 0
    assert t["boundary_edges"] == t["nonmanifold_edges"] == 0 and t["repair"] == []
    assert s["genus"] == 0 and s["boundary_edges"] == 4 * 6 and s["boundary_loops"] == 1
    assert s["genus_note"] == "open surface, 1 boundary loop"
    assert s["min_angle"] == pytest.approx(45.0)  # a grid of right isosceles triangles
    assert s["area"] == pytest.approx(1.0)
    assert d["vertices"] == sq.n_vertices + 1 and d["faces"] == sq.n_faces + 1
    assert sorted(d["repair"]) == ["removed 1 duplicate faces", "removed 1 unreferenced vertices"]
    assert (d["repaired_vertices"], d["repaired_faces"]) == (sq.n_vertices, sq.n_faces)
    # the text form names the same facts
    res = cli("info", torus, check=True)
    rows = dict(line.split(None, 1) for line in res.stdout.splitlines()
                if line.split(None, 1)[0] in ("vertices", "faces", "components", "genus"))
    assert rows == {"vertices": "288", "faces": "576", "components": "1", "genus": "1"}
    # a folder stands for its mesh files (as describe finds them), in sorted order
    res = cli("info", tmp_path, "--json", check=True)
    assert [json.loads(line)["vertices"] for line in res.stdout.splitlines()] == [
        sq.n_vertices + 1, sq.n_vertices, 288]  # dirty, square, torus


@pytest.fixture(scope="module")
def table_file(folder, tmp_path_factory):
    out = tmp_path_factory.mktemp("table") / "table.npz"
    recs = [(p.stem, p.parent.name, p) for p in sorted(folder.glob("*/*.off"))]
    cshape.describe(recs, N=N, cache_dir=False, progress=False).save(out)
    return out


@pytest.mark.slow
def test_query_by_name_and_by_mesh_file(table_file, folder, tmp_path):
    res = cli("query", table_file, "small", "-k", "5", "--json", check=True)
    got = json.loads(res.stdout)
    # only the 2 other shapes; the same sphere at twice the size is at distance ~0
    assert [n["name"] for n in got["neighbours"]] == ["big", "ring"]
    assert got["neighbours"][0]["distance"] < 1e-8 < got["neighbours"][1]["distance"]
    assert "only 2 other shapes" in res.stderr

    # a mesh file not in the table: a sphere at a third scale matches both spheres
    ico = shapes.icosphere(2)
    q = write_off(tmp_path / "q.off", (0.5 * ico.vertices, ico.faces))
    res = cli("query", table_file, q, "-k", "3", "--kind", "cshape", "-M", "4",
              cache=tmp_path / "c", check=True)
    lines = res.stdout.splitlines()
    assert lines[0].startswith("nearest to") and "paper's cShape-DNA (M=4 of N=20" in lines[0]
    ranked = [line.split() for line in lines[2:]]
    assert [r[0] for r in ranked] == ["1", "2", "3"]
    assert {ranked[0][2], ranked[1][2]} == {"small", "big"} and ranked[2][2] == "ring"
    assert float(ranked[0][1]) < 1e-8 and float(ranked[1][1]) < 1e-8

    res = cli("query", table_file, "smal")
    assert_one_line_error(res, "names containing it: ['small']")


def test_offline_download_ends_in_one_line_and_leaves_no_folder(tmp_path):
    """`cshape data build` of a download collection whose server refuses the connection."""
    import yaml

    entry = cshape.data.info("odedstein-meshes")
    with socket_port() as port:  # nobody listens there once closed
        pass
    entry["items"] = [{**it, "url": f"https://127.0.0.1:{port}/{it['file']}"}
                      for it in entry["items"][:2]]
    manifest = tmp_path / "manifest.yaml"
    manifest.write_text(yaml.safe_dump({"version": 1, "collections": [entry]}))
    cache = tmp_path / "cache"
    cache.mkdir()
    res = cli("data", "build", "odedstein-meshes", "--manifest", manifest, "--cache-dir", cache)
    assert_one_line_error(res, "cannot download odedstein-meshes/cube from https://127.0.0.1")
    assert "Connection refused" in res.stderr and len(res.stderr.strip().splitlines()) == 1
    assert list(cache.iterdir()) == []  # no empty downloads/odedstein-meshes/cube/ left


@pytest.mark.slow
@pytest.mark.realdata
def test_real_meshes_describe_info_query(shared_meshes, tmp_path):
    """The real meshes: a torus, a coarse unit sphere, and cubes too coarse for N=30."""
    out = tmp_path / "real.csv"
    dirs = [shared_meshes / d for d in ("torus", "sphere", "cube")]
    res = cli("describe", *dirs, "--out", out, "-N", 30, "--strict",
              cache=tmp_path / "c")
    assert_one_line_error(res, "2 of 4 meshes failed")  # cube.obj has 26 vertices, 30 > 26
    assert "failed: cube: ValueError: N=30 eigenvalues requested" in res.stderr
    res = cli("describe", *dirs, "--out", out, "-N", 30, cache=tmp_path / "c",
              check=True)  # by default the cubes are listed and left out
    assert "failed: cube: ValueError: N=30 eigenvalues requested" in res.stderr
    table = DescriptorTable.load(out)
    assert sorted(zip(table.names, table.labels, strict=True)) == [
        ("sphere", "sphere"), ("torus", "torus")]
    # the unit sphere's first non-zero eigenvalue l(l+1) = 2, three times
    np.testing.assert_allclose(table.lam[table.index("sphere")][1:4], 2.0, rtol=0.02)

    res = cli("info", shared_meshes / "torus" / "torus.obj",
              shared_meshes / "cube" / "cube_no_bottom.obj", "--json", check=True)
    torus, open_cube = (json.loads(line) for line in res.stdout.splitlines())
    assert torus["genus"] == 1 and torus["closed"] and torus["components"] == 1
    assert open_cube["genus"] == 0 and open_cube["boundary_loops"] == 1

    res = cli("query", out, shared_meshes / "sphere" / "sphere.obj", "-k", "1", "--json",
              cache=tmp_path / "c", check=True)
    hit = json.loads(res.stdout)["neighbours"][0]
    assert hit["name"] == "sphere" and hit["distance"] == 0.0  # the same file, cached


@pytest.mark.slow
def test_describe_on_a_dask_cluster_and_an_unreachable_one(folder, tmp_path):
    distributed = pytest.importorskip("distributed")
    out = tmp_path / "t.npz"
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  protocol="tcp://", host="127.0.0.1",
                                  dashboard_address=":0") as cluster:
        cli("describe", folder, "--dask", cluster.scheduler_address, "--out", out, "-N", N,
            "--no-cache", check=True, process=True)
    table = DescriptorTable.load(out)
    lam = cshape.shape_dna(cshape.load_mesh(folder / "torus" / "ring.off"), N=N)
    np.testing.assert_allclose(table.lam[table.index("ring")], lam, rtol=1e-12, atol=1e-12)

    with socket_port() as port:  # nobody listens there
        pass
    env = {"DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT": "2s"}
    # (dask reads its configuration from the environment when it is imported: a process)
    res = cli("describe", folder, "--dask", f"tcp://127.0.0.1:{port}", "--no-cache",
              "-N", N, env=env, process=True)
    assert_one_line_error(res, f"Timed out trying to connect to tcp://127.0.0.1:{port}")


@pytest.mark.slow
def test_interrupt_ends_in_one_line_and_leaves_complete_cache_entries(tmp_path):
    import signal
    import time

    ico = shapes.icosphere(3)
    for k in range(40):  # distinct contents: 40 eigensolves, far more than the wait below
        write_off(tmp_path / "in" / f"s{k:02d}.off", ((1 + k / 40) * ico.vertices, ico.faces))
    cache, out = tmp_path / "c", tmp_path / "t.csv"
    env = {**os.environ, "CSHAPE_CACHE": str(cache)}
    # `python -m cshape` with Python's own Ctrl-C handler, as in a terminal: a suite started
    # as a background job (`make test &`) passes its ignored SIGINT down to its processes
    start = ("import runpy, signal, sys; signal.signal(signal.SIGINT, signal.default_int_handler);"
             " sys.argv[0] = 'cshape'; runpy.run_module('cshape', run_name='__main__')")
    proc = subprocess.Popen([sys.executable, "-c", start, "describe", str(tmp_path / "in"),
                             "--out", str(out), "-N", "60"], stderr=subprocess.PIPE,
                            text=True, env=env)
    entries = cache / "eigenvalues"
    while proc.poll() is None and len(list(entries.glob("*.npz"))) < 1:
        time.sleep(0.05)
    if proc.poll() is not None:
        pytest.skip("describe finished before it could be interrupted")
    proc.send_signal(signal.SIGINT)
    err = proc.communicate(timeout=300)[1]
    assert proc.returncode == 130 and err.strip() == "cshape describe: interrupted", err
    assert not out.exists()
    assert [p for p in entries.rglob("*") if p.name.startswith(".")] == []  # no temp file
    # what was finished is cached and complete (resuming from it: tests/test_batch.py)
    done = list(entries.glob("*.npz"))
    assert 1 <= len(done) < 40
    for entry in done:
        with np.load(entry) as z:
            assert z["lam"].shape == (60,)


def test_collect_mesh_files_names_labels_and_globs(tmp_path):
    ico = shapes.icosphere(1)
    for rel in ("a/cls/x.off", "b/cls/x.off", "b/y.off", "c/z.off", "c/z.ply.gz"):
        write_off(tmp_path / rel, ico)  # contents do not matter here
    (tmp_path / "b" / "notes.txt").write_text("not a mesh")
    got = collect_mesh_files([tmp_path / "a", tmp_path / "b", tmp_path / "b" / "y.off",
                              f"{tmp_path}/*/cls/*.off", f"{tmp_path}/c/*"])
    assert [(n, lab, p.relative_to(tmp_path).as_posix()) for n, lab, p in got] == [
        ("a/cls/x", "cls", "a/cls/x.off"),   # same stem, same sub-folder: the path below
        ("b/cls/x", "cls", "b/cls/x.off"),   # the folder both are in
        ("y", "b", "b/y.off"),                # once, although named three ways; directly
                                              # in one of several folders given: its name
        ("z.off", "c", "c/z.off"),            # only the suffix differs: kept
        ("z.ply.gz", "c", "c/z.ply.gz"),
    ]
    with pytest.raises(ValueError, match="matches no mesh file"):
        collect_mesh_files([f"{tmp_path}/b/*.txt"])


def test_flat_folder_has_no_classes_in_describe_and_query(tmp_path, capsys):
    flat = tmp_path / "my-meshes"
    write_off(flat / "ball.off", shapes.icosphere(1))
    write_off(flat / "big.off", (2.0 * shapes.icosphere(1).vertices, shapes.icosphere(1).faces))
    write_off(flat / "ring.off", shapes.torus(12, 6))
    out = tmp_path / "t.csv"
    assert main(["describe", str(flat), "-N", "12", "--no-cache", "-q", "--out", str(out)]) == 0
    table = DescriptorTable.load(out)
    assert table.labels == ["", "", ""]  # not the folder's own name
    capsys.readouterr()
    assert main(["query", str(out), "ball", "-k", "2"]) == 0
    text = capsys.readouterr().out
    assert "my-meshes" not in text
    rows = text.splitlines()[2:]
    assert len(rows) == 2 and all(len(r.split()) == 3 for r in rows)  # rank, distance, name
    # a folder with classes keeps them, and a loose file beside them has none
    write_off(tmp_path / "mixed" / "round" / "a.off", shapes.icosphere(1))
    write_off(tmp_path / "mixed" / "b.off", shapes.icosphere(1))
    got = {n: lab for n, lab, _ in collect_mesh_files([tmp_path / "mixed"])}
    assert got == {"a": "round", "b": ""}
    # several flat folders given: each is a class, named after it (cats/ dogs/)
    write_off(tmp_path / "cats" / "c1.off", shapes.icosphere(1))
    write_off(tmp_path / "dogs" / "d1.off", shapes.icosphere(1))
    got = {n: lab for n, lab, _ in collect_mesh_files([tmp_path / "cats", tmp_path / "dogs"])}
    assert got == {"c1": "cats", "d1": "dogs"}
    got = {n: lab for n, lab, _ in collect_mesh_files([f"{tmp_path}/[cd]*s"])}
    assert got == {"c1": "cats", "d1": "dogs"}


@pytest.mark.slow
def test_failed_reproduce_leaves_no_report_folder(folder, tmp_path):
    """Two shapes are too few for Section 3: one line, exit 2, and no folder created."""
    out = tmp_path / "new" / "report"
    res = cli("reproduce", "--folder", folder / "sphere", "--out", out, "-N", N, "-M", 3,
              "--noise", "", cache=tmp_path / "c")
    assert_one_line_error(res, "the experiments need at least 3 shapes")
    assert not (tmp_path / "new").exists()
