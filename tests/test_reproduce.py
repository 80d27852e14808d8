"""`cshape reproduce`: the paper's Section 3 on a small collection, end to end."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from cshape import shapes
from cshape.reproduce import experiment_3_1, reproduce


def _records():
    out = []
    for s in (2, 3):
        out.append((f"S{s}", "sphere", shapes.icosphere(s)))
    for n in (6, 8):
        out.append((f"C{n}", "cube", shapes.cube(n)))
    for k, r in enumerate((0.3, 0.35)):
        out.append((f"T{k}", "torus", shapes.torus(24, 12, r=r)))
    return out


def test_reproduce_writes_a_report(tmp_path):
    res = reproduce(
        _records(), tmp_path / "rep", N=30, M=4, Ms=(2, 1), noise_levels=(1.0,),
        cache_dir=tmp_path / "cache", progress=False,
    )
    rep = (tmp_path / "rep" / "report.md").read_text()
    assert "0.68" in rep  # the paper's number beside ours
    # Fig. 1 draws one shape per class, and the report says it is a sample
    assert ("Fig. 1 samples: it shows one shape of each of the 3 classes, 3 of the 6 shapes "
            "(S2, C6, T0).") in rep
    data = json.loads((tmp_path / "rep" / "results.json").read_text())
    assert data["n_shapes"] == res["n_shapes"] == 6
    assert list((tmp_path / "rep").glob("fig*.png"))
    # the numbers in results.json are the ones the pure experiment function gives
    from cshape.batch import DescriptorTable

    table = DescriptorTable.load(tmp_path / "rep" / "table.npz")
    r31 = experiment_3_1(table, N=30, M=4)
    assert data["3.1"]["mean"] == pytest.approx(r31["mean"])
    assert data["3.1"]["std"] == pytest.approx(r31["std"])
    assert 0 < r31["mean"] < 255


@pytest.mark.slow
def test_cli_reproduce_on_a_folder(tmp_path):
    import cshape

    folder = tmp_path / "meshes"
    for name, label, mesh in _records()[:4]:
        (folder / label).mkdir(parents=True, exist_ok=True)
        V, F = mesh.vertices, mesh.faces
        lines = ["OFF", f"{len(V)} {len(F)} 0"] + [" ".join(str(float(x)) for x in v) for v in V]
        lines += ["3 " + " ".join(map(str, f)) for f in F]
        (folder / label / f"{name}.off").write_text("\n".join(lines) + "\n")
    assert cshape.load_mesh(folder / "sphere" / "S2.off").n_vertices == 162
    res = subprocess.run(
        [sys.executable, "-m", "cshape", "reproduce", "--folder", str(folder), "--out",
         str(tmp_path / "rep"), "-N", "20", "-M", "3", "--noise", "", "--jobs", "1"],
        capture_output=True, text=True, timeout=600,
        env={**__import__("os").environ, "CSHAPE_CACHE": str(tmp_path / "cache")},
    )
    assert res.returncode == 0, res.stderr[-2000:]
    assert (tmp_path / "rep" / "report.md").exists()
