"""cshape.batch.describe: cache, resume after a kill, failures, process pool, Dask, save/load."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
import types
import warnings
from pathlib import Path

import numpy as np
import pytest

from cshape import CShapeWarning, Descriptor, Mesh, shape_dna, shapes
from cshape.batch import DescriptorTable, describe
from cshape.batch._dask import _SAMPLERS, _pause_samplers, _resume_samplers
from cshape.batch.cache import mesh_key
from cshape.spectrum import SpectrumSettings

N = 20


def small_collection():
    """Six cheap meshes in two classes, as (name, label, mesh) records."""
    return [
        ("s1", "sphere", shapes.icosphere(2)),
        ("s2", "sphere", shapes.icosphere(2, radius=2.0)),
        ("s3", "sphere", shapes.icosphere(2, radius=0.5)),
        ("t1", "torus", shapes.torus(24, 12)),
        ("t2", "torus", shapes.torus(24, 12, r=0.3)),
        ("t3", "torus", shapes.torus(20, 10)),
    ]


def entries(cache: Path):
    return sorted(cache.glob("*.npz"))


def run(collection, **kw):
    kw.setdefault("progress", False)
    kw.setdefault("N", N)
    return describe(collection, **kw)


@pytest.fixture(scope="module")
def reference():
    """The serial, uncached table of small_collection()."""
    return run(small_collection(), cache_dir=False)


# ------------------------------------------------------------------ basics and the cache
def test_describe_matches_shape_dna(reference):
    col = small_collection()
    assert reference.names == [r[0] for r in col]
    assert reference.labels == [r[1] for r in col]
    assert reference.lam.shape == (6, N)
    for i, (_, _, mesh) in enumerate(col):
        np.testing.assert_allclose(reference.lam[i], shape_dna(mesh, N=N), rtol=1e-12, atol=1e-12)
        assert reference.areas[i] == pytest.approx(mesh.area)
    assert not reference.cached.any()
    assert reference.failures == []
    assert reference.descriptors().shape == (6, 28)  # DEFAULT at N = 20: 9 + 19 values
    assert reference.descriptors(Descriptor("cshape", N=N, M=2)).shape == (6, 5)
    assert reference.distance_matrix(Descriptor("shape-dna", N=N)).shape == (6, 6)


def test_cache_is_reused_for_smaller_N(tmp_path, reference):
    first = run(small_collection(), cache_dir=tmp_path)
    assert not first.cached.any()
    assert len(entries(tmp_path)) == 6
    np.testing.assert_array_equal(first.lam, reference.lam)
    again = run(small_collection(), cache_dir=tmp_path)
    assert again.cached.all()
    np.testing.assert_array_equal(again.lam, first.lam)
    shorter = run(small_collection(), cache_dir=tmp_path, N=10)
    assert shorter.cached.all()
    np.testing.assert_array_equal(shorter.lam, first.lam[:, :10])
    longer = run(small_collection(), cache_dir=tmp_path, N=24)  # needs more eigenvalues
    assert not longer.cached.any()
    assert run(small_collection(), cache_dir=tmp_path, N=24).cached.all()
    # entries are plain arrays, readable without pickle, keyed by content + parameters
    with np.load(entries(tmp_path)[0], allow_pickle=False) as z:
        assert z["lam"].shape == (24,)
    # a different boundary condition or mass matrix is a different key
    m = shapes.icosphere(2)
    assert mesh_key(m) == mesh_key(Mesh(m.vertices.copy(), m.faces.copy()))
    assert mesh_key(m) != mesh_key(m, SpectrumSettings(mass="lumped"))


def test_corrupt_cache_entry_is_detected_and_recomputed(tmp_path, reference):
    run(small_collection(), cache_dir=tmp_path)
    paths = entries(tmp_path)
    paths[0].write_bytes(b"not a zip file")
    data = paths[1].read_bytes()
    paths[1].write_bytes(data[: len(data) // 2])  # truncated write
    with pytest.warns(CShapeWarning, match=r"corrupt cache entry"):
        table = run(small_collection(), cache_dir=tmp_path)
    assert int((~table.cached).sum()) == 2
    np.testing.assert_array_equal(table.lam, reference.lam)
    for p in paths:  # rewritten, valid entries
        with np.load(p, allow_pickle=False) as z:
            assert np.all(np.isfinite(z["lam"]))


def test_failing_mesh_is_skipped_and_reported(tmp_path):
    col = small_collection()[:2] + [("tiny", "x", shapes.icosphere(0))]  # 12 vertices < N
    col.append(("missing", "x", tmp_path / "nope.off"))
    with pytest.warns(CShapeWarning, match=r"2 of 4 meshes failed and were skipped"):
        table = run(col, cache_dir=tmp_path)
    assert table.names == ["s1", "s2"]
    assert [f[0] for f in table.failures] == ["tiny", "missing"]
    assert "N=20 eigenvalues requested" in table.failures[0][1]
    assert "FileNotFoundError" in table.failures[1][1]
    with pytest.raises(RuntimeError, match=r"mesh 'tiny' failed"):
        run(col, cache_dir=False, on_error="raise")


class LazyRecord:
    """A record that loads its mesh on access, like cshape.data items."""

    def __init__(self, name, loader):
        self.name, self.label, self._loader, self.loads = name, "lazy", loader, 0

    @property
    def mesh(self):
        self.loads += 1
        return self._loader()


def test_lazy_records_load_once_and_a_failing_load_is_reported():
    def broken():
        raise OSError("disk on fire")

    good = LazyRecord("good", lambda: shapes.icosphere(2))
    bad = LazyRecord("bad", broken)
    with pytest.warns(CShapeWarning, match=r"bad \(OSError: disk on fire\)"):
        table = run([good, bad], cache_dir=False)
    assert table.names == ["good"]
    assert good.loads == 1


def write_off(path, mesh):
    lines = ["OFF", f"{mesh.n_vertices} {mesh.n_faces} 0"]
    lines += [" ".join(repr(float(x)) for x in v) for v in mesh.vertices]
    lines += ["3 " + " ".join(str(int(i)) for i in f) for f in mesh.faces]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_collection_forms(tmp_path):
    m1, m2 = shapes.icosphere(2), shapes.torus(24, 12)
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    p1 = write_off(tmp_path / "a" / "x.off", m1)
    p2 = write_off(tmp_path / "b" / "x.off", m2)
    rec = types.SimpleNamespace(name="rec", label="torus", mesh=m2)
    rec_path = types.SimpleNamespace(name="recp", label="sphere", path=p1)
    table = run([p1, p2, m1, (m2.vertices, m2.faces), ("named", m1), rec, rec_path],
                cache_dir=False)
    # colliding stems fall back to the whole path
    assert table.names == [str(p1), str(p2), "mesh2", "mesh3", "named", "rec", "recp"]
    assert table.labels == ["", "", "", "", "", "torus", "sphere"]
    np.testing.assert_allclose(table.lam[0], table.lam[2], rtol=1e-9, atol=1e-9)
    assert run({"one": m1}, cache_dir=False).names == ["one"]
    with pytest.raises(ValueError, match=r"repeated names \['a'\]"):
        run([("a", m1), ("a", m2)], cache_dir=False)
    with pytest.raises(TypeError, match=r"collection item 0 is a int"):
        run([3], cache_dir=False)
    with pytest.raises(TypeError, match=r"wrap it in a list"):
        run(m1, cache_dir=False)


def test_default_cache_dir_follows_cshape_cache(monkeypatch, tmp_path):
    monkeypatch.setenv("CSHAPE_CACHE", str(tmp_path))
    table = run(small_collection()[:1], cache_dir=None)
    assert len(entries(tmp_path / "eigenvalues")) == 1
    assert len(table) == 1


def test_invalid_parameters():
    col = small_collection()[:1]
    with pytest.raises(ValueError, match=r"n_jobs must be a positive integer or -1"):
        run(col, cache_dir=False, n_jobs=0)
    with pytest.raises(ValueError, match=r"bc must be one of"):
        run(col, cache_dir=False, bc="robin")


# ------------------------------------------------------------------ save / load
@pytest.mark.parametrize("suffix", [".npz", ".csv"])
def test_table_round_trip(tmp_path, reference, suffix):
    t = reference.select([0, 3, 5])
    t.names[0] = 'sphère, "one"'  # commas, quotes and non-ASCII survive
    t.failures = [("bad mesh", "ValueError: too small, sorry")]
    path = t.save(tmp_path / f"table{suffix}")
    back = DescriptorTable.load(path)
    assert back.names == t.names
    assert back.labels == t.labels
    np.testing.assert_array_equal(back.lam, t.lam)
    np.testing.assert_array_equal(back.areas, t.areas)
    np.testing.assert_array_equal(back.seconds, t.seconds)
    np.testing.assert_array_equal(back.cached, t.cached)
    assert (back.N, back.bc, back.mass, back.failures) == (t.N, t.bc, t.mass, t.failures)
    np.testing.assert_array_equal(back.descriptors(), t.descriptors())
    np.testing.assert_array_equal(back.components, t.components)
    files = sorted(p.name for p in tmp_path.iterdir())  # no temp file left
    assert files == ([f"table{suffix}"] if suffix == ".npz"
                     else [f"table{suffix}", f"table{suffix}.json"])


def _write_v1_csv(table, path, drop=()):
    """A CSV table as cshape wrote it before format version 2 (metadata on a first line)."""
    meta = {"format": "cshape-descriptor-table", "format_version": 1, "N": table.N,
            "M": 4, "transform": "weyl", "bc": table.bc, "mass": table.mass,
            "failures": [list(f) for f in table.failures]}
    for key in drop:
        del meta[key]
    lines = [f"# cshape-descriptor-table {json.dumps(meta)}",
             ",".join(["name", "label", "area", "seconds", "cached"]
                      + [f"lam_{i}" for i in range(table.N)])]
    for i in range(len(table)):
        lines.append(",".join([table.names[i], table.labels[i], repr(float(table.areas[i])),
                               repr(float(table.seconds[i])), str(int(table.cached[i]))]
                              + [repr(float(x)) for x in table.lam[i]]))
    path.write_text("\n".join(lines) + "\n")


def test_table_load_rejects(tmp_path):
    with pytest.raises(ValueError, match=r"must end in .npz or .csv"):
        DescriptorTable(["a"], np.zeros((1, 3)), [1.0]).save(tmp_path / "t.txt")
    bad = tmp_path / "t.csv"
    bad.write_text("name,label\n")
    with pytest.raises(ValueError, match=r"not a cshape descriptor table"):
        DescriptorTable.load(bad)
    with pytest.raises(FileNotFoundError, match=r"no descriptor table"):
        DescriptorTable.load(tmp_path / "none.npz")


# ------------------------------------------------------------------ parallel runs
@pytest.mark.slow
def test_process_pool_equals_serial(tmp_path, reference):
    table = run(small_collection(), cache_dir=tmp_path, n_jobs=2)
    assert table.names == reference.names
    np.testing.assert_array_equal(table.lam, reference.lam)
    np.testing.assert_array_equal(table.areas, reference.areas)


def test_dask_local_cluster_equals_serial(tmp_path, reference):
    distributed = pytest.importorskip("distributed")
    col = small_collection() + [("tiny", "x", shapes.icosphere(0))]
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  protocol="tcp://", host="127.0.0.1",
                                  dashboard_address=":0") as cluster:
        with distributed.Client(cluster) as client, warnings.catch_warnings():
            warnings.simplefilter("ignore", CShapeWarning)
            table = run(col, cache_dir=tmp_path, client=client)
        # a scheduler address also works (a client is opened and closed for the run)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", CShapeWarning)
            again = run(col, cache_dir=False, client=cluster.scheduler_address)
    for t in (table, again):
        assert t.names == reference.names
        # same computation; the in-process workers' BLAS may use 2 threads (the serial
        # reference uses 1), which changes the last bits of a few eigenvalues
        np.testing.assert_allclose(t.lam, reference.lam, rtol=1e-12, atol=1e-12)
        np.testing.assert_array_equal(t.areas, reference.areas)
        assert [f[0] for f in t.failures] == ["tiny"]
    assert len(entries(tmp_path)) == 6


@pytest.mark.slow
def test_dask_process_cluster_equals_serial(reference):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  host="127.0.0.1", dashboard_address=":0") as cluster:
        with distributed.Client(cluster) as client:
            table = run(small_collection(), cache_dir=False, client=client)
            # every worker was set up by its first task (allocator thresholds, issue 14)
            ready = client.run(lambda: __import__("cshape.batch._dask").batch._dask._WORKER_READY)
            # the workers' profiler and tick were paused for the run and run again after it
            running = client.run(lambda dask_worker: [
                dask_worker.periodic_callbacks[name].is_running() for name in _SAMPLERS])
            paused = client.run(_pause_samplers)
            stopped = client.run(lambda dask_worker: [
                dask_worker.periodic_callbacks[name].is_running() for name in _SAMPLERS])
            resumed = client.run(_resume_samplers)
    np.testing.assert_array_equal(table.lam, reference.lam)
    assert ready and all(ready.values())
    assert all(all(flags) for flags in running.values())
    assert all(p == list(_SAMPLERS) for p in paused.values())
    assert not any(any(flags) for flags in stopped.values())
    assert resumed == paused


MALLOC_PROBE = """
import resource, sys
import numpy as np
from cshape.batch._dask import _malloc_as_a_plain_process

ok = _malloc_as_a_plain_process() if sys.argv[1] == "fix" else None
np.ones(2**17)  # 1 MiB: warm up
before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
for _ in range(50):
    np.ones(2**17).sum()  # allocate, touch and free 1 MiB
print(ok, resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before)
"""


@pytest.mark.slow
@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="glibc's mallopt")
def test_dask_nanny_malloc_variable_is_undone_in_the_worker():
    # MALLOC_TRIM_THRESHOLD_ (set by the Dask nanny) freezes glibc's mmap threshold at
    # 128 KiB: every 1 MiB temporary is mapped afresh and page-faulted in (256 faults each).
    # After _malloc_as_a_plain_process the freed block is reused: almost no new faults.
    def faults(mode, **extra):
        env = dict(os.environ, MALLOC_TRIM_THRESHOLD_="65536", **extra)
        out = subprocess.run([sys.executable, "-c", MALLOC_PROBE, mode], env=env, check=True,
                             capture_output=True, text=True).stdout.split()
        return out[0], int(out[1])

    ok, frozen = faults("plain")
    assert frozen > 50 * 200
    ok, fixed = faults("fix")
    assert ok == "True" and fixed < 50 * 20
    # an explicit MALLOC_MMAP_THRESHOLD_ is the user's choice: left alone
    ok, _ = faults("fix", MALLOC_MMAP_THRESHOLD_="131072")
    assert ok == "False"


# ------------------------------------------------------------------ interruption
SCRIPT = """
import json, sys
from cshape import shapes
from cshape.batch import describe

if __name__ == "__main__":
    col = [(f"s{{i}}", "sphere", shapes.icosphere(3, radius=1.0 + 0.1 * i)) for i in range({n})]
    t = describe(col, N=30, cache_dir=sys.argv[1], n_jobs={n_jobs}, progress=False)
    print(json.dumps({{"ok": t.names, "failures": t.failures}}))
"""

N_KILL = 16


def start_describe(tmp_path, n_jobs):
    script = tmp_path / "run.py"
    script.write_text(SCRIPT.format(n=N_KILL, n_jobs=n_jobs))
    cache = tmp_path / "cache"
    proc = subprocess.Popen([sys.executable, str(script), str(cache)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while not (cache.is_dir() and entries(cache)):
        if proc.poll() is not None or time.monotonic() > deadline:
            proc.kill()
            out, err = proc.communicate()
            pytest.fail(f"describe subprocess wrote no cache entry: {err[-2000:]}")
        time.sleep(0.005)
    return proc, cache


def collection_for_resume():
    return [(f"s{i}", "sphere", shapes.icosphere(3, radius=1.0 + 0.1 * i)) for i in range(N_KILL)]


def check_resume(cache):
    """Entries left by the killed run are valid, are not recomputed, and the rest is."""
    done = entries(cache)
    stamps = {p: p.stat().st_mtime_ns for p in done}
    for p in done:
        with np.load(p, allow_pickle=False) as z:
            assert z["lam"].shape == (30,) and np.all(np.isfinite(z["lam"]))
    table = describe(collection_for_resume(), N=30, cache_dir=cache, progress=False)
    assert len(table) == N_KILL and table.failures == []
    assert int(table.cached.sum()) == len(done)
    assert {p: p.stat().st_mtime_ns for p in done} == stamps  # not rewritten
    assert len(entries(cache)) == N_KILL
    fresh = describe(collection_for_resume()[:3], N=30, cache_dir=False, progress=False)
    np.testing.assert_array_equal(table.lam[:3], fresh.lam)


@pytest.mark.slow
def test_resume_after_the_run_is_killed(tmp_path):
    proc, cache = start_describe(tmp_path, n_jobs=1)
    proc.send_signal(signal.SIGKILL)
    proc.communicate()
    n_done = len(entries(cache))
    assert 1 <= n_done < N_KILL, "the run finished before it could be killed"
    check_resume(cache)


@pytest.mark.slow
def test_resume_after_a_worker_is_killed(tmp_path):
    psutil = pytest.importorskip("psutil")
    proc, cache = start_describe(tmp_path, n_jobs=2)
    # the pool workers are the leaves of the process tree (below the forkserver, if any),
    # apart from multiprocessing's resource tracker
    workers = [c for c in psutil.Process(proc.pid).children(recursive=True)
               if not c.children() and "resource_tracker" not in " ".join(c.cmdline())]
    assert workers, "no worker process found"
    os.kill(workers[0].pid, signal.SIGKILL)
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == 0, err[-2000:]
    summary = json.loads(out.strip().splitlines()[-1])
    if not summary["failures"]:
        pytest.skip("the pool finished before the worker was killed")
    assert all("worker process died" in msg for _, msg in summary["failures"])
    assert len(summary["ok"]) + len(summary["failures"]) == N_KILL
    assert len(entries(cache)) == len(summary["ok"])
    check_resume(cache)


NO_GUARD = """
import json, sys
from cshape import shapes
from cshape.batch import describe

print("script body ran")
col = [(f"s{i}", "sphere", shapes.icosphere(2, radius=1.0 + 0.1 * i)) for i in range(4)]
t = describe(col, N=20, cache_dir=sys.argv[1], n_jobs=2, progress=False)
print(json.dumps({"ok": t.names, "failures": t.failures, "lam": t.lam.tolist()}))
"""


@pytest.mark.slow
def test_parallel_describe_from_a_plain_script_without_main_guard(tmp_path):
    """The usual script, no ``if __name__ == "__main__":``: the workers must not re-run it
    (with multiprocessing's spawn/forkserver every mesh 'failed' as a dead worker)."""
    script = tmp_path / "plain.py"
    script.write_text(NO_GUARD)
    res = subprocess.run([sys.executable, str(script), str(tmp_path / "cache")], cwd=tmp_path,
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr[-2000:]
    lines = res.stdout.strip().splitlines()
    assert lines.count("script body ran") == 1, res.stdout  # not re-run by any worker
    summary = json.loads(lines[-1])
    assert summary["failures"] == []
    assert summary["ok"] == ["s0", "s1", "s2", "s3"]
    assert len(entries(tmp_path / "cache")) == 4
    col = [(f"s{i}", "sphere", shapes.icosphere(2, radius=1.0 + 0.1 * i)) for i in range(4)]
    ref = describe(col, N=20, cache_dir=False, progress=False)
    np.testing.assert_array_equal(np.array(summary["lam"]), ref.lam)


@pytest.mark.parametrize(
    "name, content",
    [
        ("bad_json.csv", "# cshape-descriptor-table {not json\nname,label\n"),
        ("not_a_table.csv", "a,b,c\n1,2,3\n"),
        ("truncated.npz", b"PK\x03\x04 truncated zip"),
        ("garbage.npz", b"\x00" * 64),
    ],
)
def test_corrupt_tables_give_a_clear_error_naming_the_file(tmp_path, name, content):
    p = tmp_path / name
    if isinstance(content, bytes):
        p.write_bytes(content)
    else:
        p.write_text(content)
    with pytest.raises(ValueError, match=name):
        DescriptorTable.load(p)


def test_table_missing_an_array_names_the_file(tmp_path):
    p = tmp_path / "partial.npz"
    np.savez(p, lam=np.zeros((1, 3)))
    with pytest.raises(ValueError, match="partial.npz.*corrupt"):
        DescriptorTable.load(p)


def test_unchanged_files_are_found_in_the_cache_without_reading_them(tmp_path):
    ico = shapes.icosphere(1)

    def write(path, scale):  # "%+.6f": the same file size for both scales
        lines = ["OFF", f"{ico.n_vertices} {ico.n_faces} 0"]
        lines += [" ".join(f"{scale * x:+.6f}" for x in v) for v in ico.vertices]
        lines += ["3 " + " ".join(str(int(i)) for i in f) for f in ico.faces]
        path.write_text("\n".join(lines) + "\n")

    p = tmp_path / "m.off"
    write(p, 1.0)
    first = run([p], cache_dir=tmp_path / "c")
    assert not first.cached.any() and len(list((tmp_path / "c" / "files").iterdir())) == 1
    # new content, same size and modification time: the file is not read again
    st = p.stat()
    write(p, 0.5)
    os.utime(p, ns=(st.st_atime_ns, st.st_mtime_ns))
    assert p.stat().st_size == st.st_size
    same = run([p], cache_dir=tmp_path / "c")
    assert same.cached.all() and same.areas[0] == first.areas[0]
    # a new modification time: read, recomputed, a quarter of the area
    os.utime(p, ns=(st.st_atime_ns, st.st_mtime_ns + 10**9))
    new = run([p], cache_dir=tmp_path / "c")
    assert not new.cached.any()
    assert new.areas[0] == pytest.approx(first.areas[0] / 4, rel=1e-5)
# ------------------------------------------------------------------ saved tables keep loading
@pytest.mark.parametrize("suffix", [".npz", ".csv"])
def test_tables_of_earlier_versions_load_and_mean_what_they_meant(tmp_path, reference, suffix):
    """Versions 1-2 stored an M and a transform (defaults of a keyword form of descriptors());
    they still load, with the same eigenvalues, areas, names and descriptors."""
    old = tmp_path / f"old{suffix}"
    if suffix == ".csv":
        _write_v1_csv(reference, old)
    else:
        reference.save(old)
        with np.load(old) as z:
            arrays = dict(z)
        meta = json.loads(str(arrays["meta"]))
        meta.update(format_version=2, M=3, transform="log-weyl")
        arrays["meta"] = np.array(json.dumps(meta))
        np.savez(old, **arrays)
    loaded = DescriptorTable.load(old)
    assert loaded.names == reference.names and loaded.labels == reference.labels
    np.testing.assert_array_equal(loaded.lam, reference.lam)
    np.testing.assert_array_equal(loaded.areas, reference.areas)
    for d in (Descriptor("cshape", N=N, M=4), Descriptor("shape-dna", N=N)):
        np.testing.assert_array_equal(loaded.descriptors(d), reference.descriptors(d))
    # with no descriptor: what the table compared when it was written (version 1 saved none:
    # the default of those versions; the .npz here keeps the descriptor its metadata name)
    then = (Descriptor("truncated-log", N=100, M=8).for_N(N) if suffix == ".csv"
            else reference.descriptor)
    assert loaded.descriptor == then
    np.testing.assert_array_equal(loaded.descriptors(), reference.descriptors(then))
    new = DescriptorTable.load(loaded.save(tmp_path / f"new{suffix}"))  # the current version
    np.testing.assert_array_equal(new.lam, reference.lam)
    assert new.descriptor == then


def test_a_table_of_a_later_version_is_refused_by_name(tmp_path, reference):
    path = reference.save(tmp_path / "t.npz")
    with np.load(path) as z:
        arrays = dict(z)
    meta = json.loads(str(arrays["meta"]))
    meta["format_version"] = 5
    arrays["meta"] = np.array(json.dumps(meta))
    np.savez(path, **arrays)
    with pytest.raises(ValueError, match=r"not a cshape descriptor table of a version this "
                                         r"cshape reads \(format 'cshape-descriptor-table', "
                                         r"version 5\)"):
        DescriptorTable.load(path)


def test_describe_and_the_table_take_no_descriptor_fields(reference):
    """describe computes eigenvalues; which descriptor is asked of the table later."""
    with pytest.raises(TypeError, match="unexpected keyword argument 'M'"):
        run(small_collection()[:1], cache_dir=False, M=3)
    with pytest.raises(TypeError, match="unexpected keyword argument 'transform'"):
        run(small_collection()[:1], cache_dir=False, transform="log-weyl")
    with pytest.raises(TypeError, match="unexpected keyword argument 'M'"):
        DescriptorTable(["a"], np.ones((1, 3)), [1.0], M=3)
    d = Descriptor("cshape", N=N, M=3, transform="log-weyl-dct")
    assert reference.descriptors(d).shape == (6, 7)


def test_a_task_is_a_frozen_record_with_named_fields(tmp_path):
    """The work of one mesh travels as a frozen Task (pickled to a worker process) and its
    result names the row it came from."""
    import dataclasses
    import pickle

    from cshape.batch.work import Task, _work

    mesh = shapes.icosphere(1)
    t = Task(index=3, source=mesh, settings=SpectrumSettings(5), cache_dir=None, key=None)
    assert [f.name for f in dataclasses.fields(Task)] == [
        "index", "source", "settings", "cache_dir", "key"]
    back = pickle.loads(pickle.dumps(t))
    assert back.index == 3 and back.settings == SpectrumSettings(5)
    assert back.source.n_vertices == mesh.n_vertices
    with pytest.raises(dataclasses.FrozenInstanceError):
        t.settings = SpectrumSettings(6)  # type: ignore[misc]
    with pytest.raises(dataclasses.FrozenInstanceError):
        t.settings.N = 6  # type: ignore[misc]
    res = _work(t)
    assert res["ok"] and res["index"] == 3
    np.testing.assert_array_equal(res["lam"], shape_dna(mesh, N=5))
    bad = _work(dataclasses.replace(t, source=tmp_path / "missing.off"))
    assert not bad["ok"] and bad["index"] == 3 and "FileNotFoundError" in bad["error"]


# ------------------------------------------------------------- the table's own descriptor
def test_a_saved_table_keeps_comparing_what_it_compared(tmp_path):
    """A table saves the descriptor it compares with no argument; a table of an older
    format loads with that format's default, the truncated log spectrum of 17 values."""
    import json

    from cshape import DEFAULT, PAPER, Descriptor, DescriptorTable

    i = np.arange(40.0)
    lam = np.array([4 * np.pi * i * (1 + 0.1 * k * np.sin(i)) for k in range(4)])
    lam[:, 0] = 0.0
    table = DescriptorTable(list("abcd"), lam, np.ones(4))
    assert table.descriptor == DEFAULT.for_N(40)
    own = DescriptorTable(list("abcd"), lam, np.ones(4), descriptor=PAPER.for_N(40))
    for suffix in (".npz", ".csv"):
        path = tmp_path / f"t{suffix}"
        own.save(path)
        back = DescriptorTable.load(path)
        assert back.descriptor == PAPER.for_N(40)
        np.testing.assert_array_equal(back.descriptors(), own.descriptors(PAPER.for_N(40)))
        assert back.select([0, 2]).descriptor == PAPER.for_N(40)
    # format 3 (no descriptor saved): the default of that format
    table.save(tmp_path / "old.csv")
    side = tmp_path / "old.csv.json"
    meta = json.loads(side.read_text())
    del meta["descriptor"]
    meta["format_version"] = 3
    side.write_text(json.dumps(meta))
    old = DescriptorTable.load(tmp_path / "old.csv")
    assert old.descriptor == Descriptor("truncated-log", N=40, M=8)
    assert old.descriptors().shape == (4, 17)


def test_a_table_refuses_a_descriptor_it_cannot_hold():
    from cshape import PAPER, DescriptorTable

    lam = np.tile(np.arange(40.0), (2, 1))
    with pytest.raises(ValueError, match=r"needs 100 eigenvalues per shape but the table "
                                         r"holds N = 40; pass descriptor.for_N\(N\)"):
        DescriptorTable(["a", "b"], lam, np.ones(2), descriptor=PAPER)
    with pytest.raises(TypeError, match="descriptor must be a cshape.Descriptor"):
        DescriptorTable(["a", "b"], lam, np.ones(2), descriptor="cshape")
