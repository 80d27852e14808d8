"""cshape as a user installs it: a built wheel in a fresh virtualenv, run from another folder.

The wheel is built and installed once per session by the ``installed_wheel_env`` fixture
(tests/conftest.py); nothing is downloaded.
"""

from __future__ import annotations

import zipfile

import numpy as np
import pytest
from conftest import REPO, save_mesh

import cshape
from cshape import data, shapes

pytestmark = pytest.mark.slow


def test_the_packaged_manifest_is_the_top_level_file():
    """One file to edit: cshape/data_manifest.yaml links to the top-level manifest, and
    the package reads it by default."""
    packaged = REPO / "cshape" / "data_manifest.yaml"
    top = REPO / "data_manifest.yaml"
    assert packaged.is_symlink() and packaged.resolve() == top.resolve(), (
        "cshape/data_manifest.yaml must be a symbolic link to ../data_manifest.yaml; "
        "recreate it with: ln -sf ../data_manifest.yaml cshape/data_manifest.yaml"
    )
    assert data.manifest._DEFAULT_MANIFEST.read_bytes() == top.read_bytes()
    default = data.manifest._DEFAULT_MANIFEST
    assert list(data.load_manifest(default)) == list(data.load_manifest(top))
    # relative 'local' paths still resolve against the repository, as before the move
    entry = data.load_manifest(data.manifest._DEFAULT_MANIFEST)["shared-meshes"]
    assert entry["_root"] == str(REPO.resolve())


def test_wheel_ships_the_manifest_and_every_module(installed_wheel_env):
    with zipfile.ZipFile(installed_wheel_env.wheel) as zf:
        names = set(zf.namelist())
        shipped = zf.read("cshape/data_manifest.yaml")
    assert shipped == (REPO / "data_manifest.yaml").read_bytes()
    modules = {f"cshape/{p.name}" for p in (REPO / "cshape").glob("*.py")}
    assert modules <= names, f"missing from the wheel: {sorted(modules - names)}"


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
    r = installed_wheel_env.run("cshape", "describe", folder, "-N", 12, "-M", 3, "--out", out,
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
    manifest's contents at cshape/data_manifest.yaml, not a link that would dangle."""
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
        member = tf.getmember(f"{sdist.name[:-len('.tar.gz')]}/cshape/data_manifest.yaml")
        assert member.isfile()
        assert tf.extractfile(member).read() == (REPO / "data_manifest.yaml").read_bytes()
