"""cshape as a user installs it: a built wheel in a fresh virtualenv, run from another folder.

The wheel is built and installed once per session by the ``installed_wheel_env`` fixture
(tests/conftest.py); nothing is downloaded.
"""

from __future__ import annotations

import zipfile
from pathlib import Path

import nbformat
import numpy as np
import pytest
from conftest import REPO, save_mesh

import cshape
from cshape import data, shapes
from cshape.course import assignments as asg

pytestmark = pytest.mark.slow

LESSONS = sorted(asg.lessons_dir().glob(asg.PATTERN))
GRADED = [p for p in LESSONS if asg.is_graded(p)]
ANSWERS = sorted((asg.lessons_dir() / asg.ANSWERS).glob("*.md"))


def test_the_packaged_manifest_is_the_top_level_file():
    """One file to edit: cshape/data/data_manifest.yaml links to the top-level manifest, and
    the package reads it by default."""
    packaged = REPO / "cshape" / "data" / "data_manifest.yaml"
    top = REPO / "data_manifest.yaml"
    assert packaged.is_symlink() and packaged.resolve() == top.resolve(), (
        "cshape/data/data_manifest.yaml must be a symbolic link to ../../data_manifest.yaml; "
        "recreate it with: ln -sf ../../data_manifest.yaml cshape/data/data_manifest.yaml"
    )
    assert data.manifest._DEFAULT_MANIFEST.read_bytes() == top.read_bytes()
    default = data.manifest._DEFAULT_MANIFEST
    assert list(data.manifest.load_manifest(default)) == list(data.manifest.load_manifest(top))
    # relative 'local' paths still resolve against the repository, as before the move
    entry = data.manifest.load_manifest(data.manifest._DEFAULT_MANIFEST)["shared-meshes"]
    assert entry["_root"] == str(REPO.resolve())


def test_wheel_ships_the_manifest_and_every_module(installed_wheel_env):
    with zipfile.ZipFile(installed_wheel_env.wheel) as zf:
        names = set(zf.namelist())
        shipped = zf.read("cshape/data/data_manifest.yaml")
    assert shipped == (REPO / "data_manifest.yaml").read_bytes()
    modules = {f"cshape/{p.relative_to(REPO / 'cshape').as_posix()}"
               for p in (REPO / "cshape").rglob("*.py")}
    assert modules <= names, f"missing from the wheel: {sorted(modules - names)}"
    assert "cshape/py.typed" in names
    # the licence travels with the wheel (PEP 639: .dist-info/licenses/LICENSE)
    with zipfile.ZipFile(installed_wheel_env.wheel) as zf:
        lic = [n for n in zf.namelist() if n.endswith(".dist-info/licenses/LICENSE")]
        assert lic and zf.read(lic[0]) == (REPO / "LICENSE").read_bytes()
        meta = zf.read(next(n for n in zf.namelist() if n.endswith(".dist-info/METADATA")))
    assert b"License-Expression: BSD-3-Clause" in meta and b"License-File: LICENSE" in meta


def test_installed_cshape_ships_the_lessons_mesh(installed_wheel_env):
    """Lessons 02-03 read Spot from the package (no folder outside it), with its licence."""
    with zipfile.ZipFile(installed_wheel_env.wheel) as zf:
        names = set(zf.namelist())
    assert {"cshape/data/meshes/spot_low_resolution.obj.gz",
            "cshape/data/meshes/README.md"} <= names
    r = installed_wheel_env.run("python", "-c", "from cshape.course.teaching import real_mesh; "
                                "m, _ = real_mesh(small=True); print(m.n_vertices, m.n_faces)")
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == ["829", "1654"]


def test_installed_cshape_data_list(installed_wheel_env):
    """The issue's first failure: `cshape data list` from a pip-installed copy."""
    r = installed_wheel_env.run("cshape", "data", "list")
    assert r.returncode == 0, r.stderr
    listed = [line.split()[0] for line in r.stdout.splitlines()[1:] if line.strip()]
    assert listed == data.list_collections(REPO / "data_manifest.yaml")


def test_installed_cshape_reads_a_folder_and_computes_shape_dna(installed_wheel_env, tmp_path):
    """import cshape, load a mesh file and compute its Shape-DNA with the installed copy:
    the unit sphere's first eigenvalues are 0 and 2 (x3); the clone gives the same numbers."""
    path = save_mesh(tmp_path / "meshes" / "spheres" / "sphere.ply", shapes.icosphere(3),
                     binary=True)
    code = (
        "import sys, cshape\n"
        "c = cshape.data.load_folder(sys.argv[1])\n"
        "lam = cshape.shape_dna(c.items[0].mesh, N=8)\n"
        "print(c.items[0].label, *map(repr, lam.tolist()))\n"
    )
    r = installed_wheel_env.run("python", "-c", code, tmp_path / "meshes")
    assert r.returncode == 0, r.stderr
    label, *vals = r.stdout.split()
    lam = np.array([float(v) for v in vals])
    assert label == "spheres"
    np.testing.assert_allclose(lam[:4], [0, 2, 2, 2], atol=0.02)
    np.testing.assert_allclose(lam, cshape.shape_dna(cshape.load_mesh(path),
                                                     N=8), rtol=1e-8, atol=1e-10)


def test_installed_cshape_describe_on_a_folder(installed_wheel_env, tmp_path):
    """`cshape describe FOLDER --out table.csv` (the issue's contract) with the installed copy:
    labels from the sub-folders, the eigenvalues of the clone."""
    folder = tmp_path / "meshes"
    paths = [save_mesh(folder / "round" / "sphere.off", shapes.icosphere(2)),
             save_mesh(folder / "ring" / "torus.ply", shapes.torus(24, 12), binary=True)]
    out = tmp_path / "table.csv"
    r = installed_wheel_env.run("cshape", "describe", folder, "-N", 12, "--out", out,
                                "-q")
    assert r.returncode == 0, r.stderr
    table = cshape.DescriptorTable.load(out)
    assert sorted(zip(table.labels, table.names, strict=True))[0][0] == "ring"
    assert sorted(table.labels) == ["ring", "round"]
    for path in paths:
        i = table.labels.index(path.parent.name)
        np.testing.assert_allclose(table.lam[i], cshape.shape_dna(cshape.load_mesh(path), N=12),
                                   rtol=1e-8, atol=1e-10)


def test_sdist_stores_the_manifest_itself(tmp_path):
    """The source distribution (what `python -m build` turns into the wheel) holds the
    manifest's contents at cshape/data/data_manifest.yaml, not a link that would dangle."""
    import shutil
    import subprocess
    import sys
    import tarfile

    from conftest import _BUILD_IGNORE

    src = tmp_path / "src"
    shutil.copytree(REPO, src, symlinks=True, ignore=_BUILD_IGNORE)
    r = subprocess.run([sys.executable, "-c", "from setuptools import build_meta as b; "
                        "print(b.build_sdist('dist'))"], cwd=src, capture_output=True,
                       text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    sdist = src / "dist" / r.stdout.strip().splitlines()[-1]
    with tarfile.open(sdist) as tf:
        member = tf.getmember(f"{sdist.name[:-len('.tar.gz')]}/cshape/data/data_manifest.yaml")
        assert member.isfile()
        assert tf.extractfile(member).read() == (REPO / "data_manifest.yaml").read_bytes()


def _core_distributions(wheel) -> set[str]:
    """The distributions the wheel requires and theirs, transitively (extras not followed)."""
    import importlib.metadata as md
    import re

    def names(reqs):
        return [re.split(r"[\s;<>=!~\[(]", r, maxsplit=1)[0] for r in reqs if "extra ==" not in r]

    with zipfile.ZipFile(wheel) as zf:
        meta = next(n for n in zf.namelist() if n.endswith(".dist-info/METADATA"))
        direct = [line.split(":", 1)[1].strip() for line in zf.read(meta).decode().splitlines()
                  if line.startswith("Requires-Dist:")]
    stack, seen = names(direct), set()
    while stack:
        name = stack.pop()
        key = re.sub(r"[-_.]+", "-", name).lower()
        if key in seen:
            continue
        seen.add(key)
        try:
            stack += names(md.requires(name) or [])
        except md.PackageNotFoundError:
            pass
    return seen


@pytest.mark.slow
def test_wheel_without_extras_describes_and_queries(installed_wheel_env, tmp_path):
    """`pip install cshape` without extras: a site folder that holds only cshape's required
    distributions (numpy, scipy, PyMeshLab, ...; no matplotlib, plotly, Jupyter, nbgrader, Dask,
    pooch) runs `cshape describe` and `cshape query`, and `import cshape.plots` names its extra."""
    import importlib.metadata as md
    import re
    import subprocess
    import sys

    env = installed_wheel_env
    lean = tmp_path / "lean-site"
    lean.mkdir()
    wanted = _core_distributions(env.wheel)
    for dist in md.distributions():
        key = re.sub(r"[-_.]+", "-", dist.metadata["Name"]).lower()
        if key not in wanted or dist.files is None:
            continue
        for top in {f.parts[0] for f in dist.files if not f.parts[0].startswith("..")}:
            src = Path(dist.locate_file(top))
            if src.exists() and not (lean / top).exists():
                (lean / top).symlink_to(src)
    for heavy in ("matplotlib", "plotly", "nbformat", "nbgrader", "dask", "pooch", "ipywidgets"):
        assert not (lean / heavy).exists(), heavy
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
    py = venv / "bin" / "python"
    where = "import sysconfig; print(sysconfig.get_paths()['purelib'])"
    site = subprocess.run([str(py), "-c", where], capture_output=True, text=True,
                          check=True).stdout.strip()
    with zipfile.ZipFile(env.wheel) as zf:
        zf.extractall(site)
    (Path(site) / "_lean.pth").write_text(str(lean) + "\n")
    folder = tmp_path / "meshes"
    for i, level in enumerate((2, 3)):
        save_mesh(folder / "spheres" / f"s{i}.ply", shapes.icosphere(level))
    save_mesh(folder / "tori" / "t0.ply", shapes.torus(24, 12))
    save_mesh(folder / "tori" / "t1.ply", shapes.torus(32, 16))
    run_env = dict(env.env, CSHAPE_CACHE=str(tmp_path / "cache"))

    def run(*args):
        return subprocess.run([str(py), "-m", "cshape", *args], capture_output=True, text=True,
                              cwd=tmp_path, env=run_env, timeout=600)

    r = run("describe", str(folder), "--out", str(tmp_path / "t.csv"), "-N", "40")
    assert r.returncode == 0, r.stderr
    r = run("query", str(tmp_path / "t.csv"), "s0", "-k", "1")
    assert r.returncode == 0, r.stderr
    assert "s1" in r.stdout
    r = subprocess.run([str(py), "-c", "import cshape.plots"], capture_output=True, text=True,
                       env=run_env)
    assert r.returncode != 0
    assert "pip install 'cshape[plots]'" in r.stderr.strip().splitlines()[-1]


def test_lessons_from_an_installed_wheel_run_there(installed_wheel_env):
    """`pip install cshape`, no clone: `cshape lessons DIR` copies the lessons out of the
    package, and a lesson and its student version run in DIR with the installed cshape."""
    env = installed_wheel_env
    with zipfile.ZipFile(env.wheel) as zf:
        names = set(zf.namelist())
    packages = {f"{p.parent.relative_to(REPO).as_posix()}/__init__.py"
                for p in (REPO / "cshape").rglob("__init__.py")}
    assert packages <= names, f"add to [tool.setuptools] packages: {sorted(packages - names)}"
    dest = env.workdir / "my-course"
    r = env.run("cshape", "lessons", dest)
    assert r.returncode == 0, r.stderr
    assert sorted(p.name for p in dest.glob(asg.PATTERN)) == [p.name for p in LESSONS]
    assert sorted(p.name for p in (dest / "student").glob(asg.PATTERN)) == [
        p.name for p in GRADED]
    assert (dest / "nbgrader_config.py").is_file()
    assert "nbgrader autograde week1" in (dest / "README.md").read_text()
    # the answer keys ship in the wheel, for `cshape lessons`, outside every student folder
    keys = {n for n in names if "/answers/" in n}
    assert keys == {f"cshape/lessons/answers/{p.name}" for p in ANSWERS}
    assert sorted(p.name for p in (dest / asg.ANSWERS).iterdir()) == [p.name for p in ANSWERS]
    assert not any("student/" in n and n.endswith(".md") for n in names)
    for extra in ([], ["--student"]):
        out = env.workdir / f"executed{'-'.join(extra)}"
        # lesson 03, the shortest to run
        r = env.run("cshape", "notebooks", "03", "--small", "--no-html", "--src", dest,
                    "--out", out, *extra)
        assert r.returncode == 0, r.stdout + r.stderr
        assert "03_dft_compression.ipynb: ok" in r.stdout, r.stdout
        executed = nbformat.read(out / "03_dft_compression.ipynb", as_version=4)
        printed = "".join(o.get("text", "") for o in executed.cells[1].outputs)
        assert printed.startswith("cshape ") and "(small sizes)" in printed, printed
