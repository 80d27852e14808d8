"""Shared test fixtures.  Meshes are built in code or read lazily, never at import time."""

from __future__ import annotations

import contextlib
import io
import os
import shutil
import subprocess
import sys
import sysconfig
import warnings
from dataclasses import dataclass
from pathlib import Path
from unittest import mock

# A parallel run (pytest -n) shares the cores among its workers: each worker's BLAS and OpenMP
# get their share (before numpy loads them here), as do the kernels and processes it starts.
if os.environ.get("PYTEST_XDIST_WORKER"):
    _share = max(1, (os.cpu_count() or 1) // int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1")))
    for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(_var, str(_share))

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from hypothesis import settings  # noqa: E402

REPO = Path(__file__).resolve().parents[1]

# Hypothesis draws the same examples on every run (derandomize), so no run of the suite can
# fail by chance; the example database is off, so a clone's results do not depend on an earlier
# run.  HYPOTHESIS_PROFILE=explore draws fresh random examples, for a developer hunting bugs.
settings.register_profile("ci", derandomize=True, database=None, print_blob=True)
settings.register_profile("explore", derandomize=False)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


#: Test modules whose tests a parallel run (``pytest -n``, ``make test``) spreads over its
#: workers one by one: each of their tests stands alone and takes long (a lesson, an
#: assignment graded by nbgrader, a browser page).  Every other module runs on one worker,
#: so that its module fixtures are built once.
SPREAD_MODULES = {"test_assignments", "test_notebooks", "test_browser"}
#: Modules that take long in all although they hold few tests (a fixture builds a site, a
#: collection or a wheel and its environment, or one test runs a type check, a whole report or
#: lessons): a parallel run starts them right after the spread tests, so that no worker ends
#: the run alone on one of them.
LONG_MODULES = {"test_docs", "test_creatures", "test_typing", "test_reproduce", "test_wheel",
                "test_prepared"}


@pytest.hookimpl(tryfirst=True)  # before pytest's own -m selection
def pytest_collection_modifyitems(config, items):
    """A browser test is in the slow tier (the other slow tests carry ``@pytest.mark.slow``:
    those that take 5-90 s on a loaded 2-core machine, by ``pytest --durations``)."""
    for item in items:
        if item.get_closest_marker("browser") and not item.get_closest_marker("slow"):
            item.add_marker(pytest.mark.slow)


def _scope(nodeid: str) -> str:
    """The unit a parallel run sends to one worker: a test of :data:`SPREAD_MODULES`, else
    the test's whole module."""
    path = nodeid.split("::", 1)[0]
    return nodeid if Path(path).stem in SPREAD_MODULES else path


def _order(scope: str, n_tests: int) -> tuple[int, int]:
    """Where a parallel run queues a scope of ``n_tests`` tests: the spread tests first, then
    :data:`LONG_MODULES`, then the other modules, more tests first.  (xdist's own order, more
    tests first, would start the long tests that stand alone last, and a worker would end
    the run alone on one of them.)"""
    if "::" in scope:
        return (0, 0)
    return (1, 0) if Path(scope).stem in LONG_MODULES else (2, -n_tests)


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    """``make test``'s parallel run (``pytest -n auto --dist loadscope``): xdist's scope
    scheduling with :func:`_scope` as the scope of a test, in the order of :func:`_order`."""
    from xdist.scheduler import LoadScopeScheduling

    class Scheduling(LoadScopeScheduling):
        def _split_scope(self, nodeid: str) -> str:
            return _scope(nodeid)

        def schedule(self) -> None:
            initial = self.collection is None
            self.config.option.loadscopereorder = False  # the collection's order, then ours
            super().schedule()
            if initial and self.workqueue:  # after the first unit or two of each worker
                units = sorted(self.workqueue.items(), key=lambda u: _order(u[0], len(u[1])))
                self.workqueue.clear()
                self.workqueue.update(units)

    return Scheduling(config, log)


def in_ci() -> bool:
    """Whether the suite runs in CI: ``CI`` set to anything but '', '0', 'false' or 'no'."""
    return os.environ.get("CI", "").strip().lower() not in ("", "0", "false", "no")


def require_tool(name: str, why: str):
    """Import the developer tool ``name`` (ruff, mypy) for a test that runs it.

    Where it is missing the test fails in CI, which must run it, and is skipped elsewhere
    with ``why`` as the reason.
    """
    import importlib

    try:
        return importlib.import_module(name)
    except ImportError:
        msg = f"{name} is not installed ({why})"
        if in_ci():
            pytest.fail(f"{msg}; CI must run this test", pytrace=False)
        pytest.skip(msg)


def shared_meshes_dir() -> Path:
    """The real-mesh folder: $CSHAPE_SHARED_MESHES, else ../shared/meshes beside the repo."""
    env = os.environ.get("CSHAPE_SHARED_MESHES")
    return Path(env) if env else REPO.parent / "shared" / "meshes"


def save_mesh(path, mesh, *, binary=False) -> Path:
    """Write ``mesh`` to ``path`` with PyMeshLab (format from the extension, e.g. ``.off``,
    ``.ply``, ``.stl``, ``.obj``); ``name.off.gz`` writes ``name.off`` gzip-compressed."""
    import gzip

    import pymeshlab

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    plain = path.with_suffix("") if path.suffix.lower() == ".gz" else path
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(np.asarray(mesh.vertices), np.asarray(mesh.faces, np.int32)))
    kw = {"binary": binary} if plain.suffix.lower() in (".ply", ".stl") else {}
    ms.save_current_mesh(str(plain), **kw)
    if plain != path:
        path.write_bytes(gzip.compress(plain.read_bytes()))
        plain.unlink()
    return path


@pytest.fixture
def shared_meshes() -> Path:
    """Path of the real meshes; skips the test when the folder is absent."""
    d = shared_meshes_dir()
    if not d.is_dir():
        pytest.skip(f"real meshes not found at {d} (set CSHAPE_SHARED_MESHES to their folder)")
    return d


def cli(*args, cache=None, check=False, env=None, process=False, cwd=None):
    """Run ``cshape ARGS`` in the folder ``cwd`` (default: the current one): in this process,
    through :func:`cshape.cli.main` (what ``python -m cshape`` runs), with stdout and stderr
    captured and the warnings filters of a fresh interpreter; ``process=True`` starts
    ``python -m cshape`` instead (for what only a process shows: its exit status and its last
    line of stderr, an interrupt).  Returns a ``subprocess.CompletedProcess``."""
    env = {**(env or {})}
    if cache is not None:
        env["CSHAPE_CACHE"] = str(cache)
    argv = [str(a) for a in args]
    if process:
        res = subprocess.run([sys.executable, "-m", "cshape", *argv], capture_output=True,
                             text=True, timeout=600, env={**os.environ, **env}, cwd=cwd)
    else:
        from cshape.cli import main

        out, err = io.StringIO(), io.StringIO()
        here = os.getcwd()
        with mock.patch.dict(os.environ, env), contextlib.redirect_stdout(out), \
                contextlib.redirect_stderr(err), warnings.catch_warnings():
            warnings.resetwarnings()
            try:
                if cwd is not None:
                    os.chdir(cwd)
                code = main(argv)
            except SystemExit as exc:  # argparse's usage errors
                code = exc.code
            finally:
                os.chdir(here)
        res = subprocess.CompletedProcess(argv, code, out.getvalue(), err.getvalue())
    if check:
        assert res.returncode == 0, res.stderr
    return res


def write_off(path, mesh):
    """Write a Mesh or (vertices, faces) as an ASCII OFF file (17 digits: exact round trip)."""
    import cshape

    mesh = cshape.mesh.as_mesh(mesh)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    lines = ["OFF", f"{mesh.n_vertices} {mesh.n_faces} 0"]
    lines += [f"{x:.17g} {y:.17g} {z:.17g}" for x, y, z in mesh.vertices]
    lines += [f"3 {a} {b} {c}" for a, b, c in mesh.faces]
    path.write_text("\n".join(lines) + "\n")
    return path


# ------------------------------------------------------------------ the installed wheel
_BUILD_IGNORE = shutil.ignore_patterns(
    ".git", ".venv", "build", "dist", "out", "test-artifacts", "*.egg-info", "__pycache__",
    ".pytest_cache", ".ruff_cache", ".hypothesis", ".ipynb_checkpoints", "benchmarks",
)


@dataclass
class InstalledWheel:
    """cshape built as a wheel and installed (not editable) into a fresh virtualenv.

    Attributes
    ----------
    wheel : Path
        The built ``cshape-*.whl``.
    venv : Path
        The virtualenv; its ``site-packages`` holds cshape, and a ``.pth`` file there points
        at the test interpreter's own ``site-packages`` for the dependencies (numpy, scipy,
        PyMeshLab, ...), which are therefore not downloaded.
    bin : Path
        The venv's script folder (``python``, ``cshape``).
    workdir : Path
        An empty folder outside the checkout, the working folder of :meth:`run`.
    env : dict
        The environment of :meth:`run`: the test's, without ``PYTHONPATH`` and friends (so
        the checkout's cshape cannot leak in), with ``CSHAPE_CACHE`` in a temporary folder.
    """

    wheel: Path
    venv: Path
    bin: Path
    workdir: Path
    env: dict

    @property
    def python(self) -> Path:
        return self.bin / ("python.exe" if os.name == "nt" else "python")

    def run(self, *args, cwd=None, timeout=600) -> subprocess.CompletedProcess:
        """Run a command of the venv (``"python"``, ``"cshape"``, ...) from :attr:`workdir`;
        returns the completed process (text output captured, no check)."""
        exe = self.bin / args[0]
        cmd = [str(exe if exe.exists() else args[0]), *map(str, args[1:])]
        return subprocess.run(cmd, cwd=cwd or self.workdir, env=self.env, capture_output=True,
                              text=True, timeout=timeout)


@pytest.fixture(scope="session")
def installed_wheel_env(tmp_path_factory) -> InstalledWheel:
    """Build cshape's wheel from this checkout and install it into a fresh virtualenv, offline.

    Session-scoped (built once, about 15 s): any test that must see cshape as a user who ran
    ``pip install cshape`` sees it takes this fixture and calls ``env.run("cshape", ...)`` or
    ``env.run("python", "-c", ...)``.  The build copies the source tree to a temporary
    folder (the checkout stays clean) and runs ``pip wheel --no-deps --no-build-isolation``
    with the test interpreter's setuptools; the install is ``pip install --no-deps
    --no-index``.  Asserts that the installed ``cshape`` is the venv's, not the checkout's.
    """
    root = tmp_path_factory.mktemp("wheel")
    src, dist, venv, work = root / "src", root / "dist", root / "venv", root / "work"
    shutil.copytree(REPO, src, symlinks=True, ignore=_BUILD_IGNORE)
    work.mkdir()
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "PYTHONHOME", "PYTHONSTARTUP", "VIRTUAL_ENV",
                        "PYTHONUSERBASE", "CSHAPE_MANIFEST")}
    env["CSHAPE_CACHE"] = str(root / "cache")
    env["PIP_NO_INDEX"] = "1"
    env["PIP_DISABLE_PIP_VERSION_CHECK"] = "1"

    def call(*cmd):
        r = subprocess.run([str(c) for c in cmd], cwd=work, env=env, capture_output=True,
                           text=True, timeout=600)
        assert r.returncode == 0, f"{' '.join(map(str, cmd))} failed:\n{r.stdout}\n{r.stderr}"
        return r

    call(sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation",
         "--no-index", "-q", "-w", dist, src)
    (wheel,) = dist.glob("cshape-*.whl")
    call(sys.executable, "-m", "venv", "--without-pip", venv)
    bindir = venv / ("Scripts" if os.name == "nt" else "bin")
    py = bindir / ("python.exe" if os.name == "nt" else "python")
    # install first, then point the venv at our dependencies: pip then sees no other cshape
    call(sys.executable, "-m", "pip", "--python", py, "install", "--no-deps", "--no-index",
         "-q", wheel)
    venv_site = Path(call(py, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])")
                     .stdout.strip())
    ours = {sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"]}
    (venv_site / "_cshape_test_deps.pth").write_text("\n".join(sorted(ours)) + "\n")
    installed = InstalledWheel(wheel, venv, bindir, work, env)
    where = installed.run("python", "-c", "import cshape; print(cshape.__file__)")
    assert where.returncode == 0, where.stderr
    assert Path(where.stdout.strip()).resolve().is_relative_to(venv.resolve()), (
        f"the venv imports cshape from {where.stdout.strip()}, not from its own site-packages"
    )
    return installed


@pytest.fixture
def private_tmpdir(tmp_path, monkeypatch):
    """A temporary folder of our own for load_mesh's decompressed copies (to see them go)."""
    import tempfile

    d = tmp_path / "tmpdir"
    d.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(d))
    return d


def pairs(mesh, N=100, **kw):
    """``(lam, phi)`` of :func:`cshape.eigenbasis`: the eigenpairs as two arrays."""
    import cshape

    b = cshape.eigenbasis(mesh, N, **kw)
    return b.lam.copy(), b.phi.copy()


def compact_of(mesh, *, N, M, bc="neumann", **kw):
    """The cShape-DNA of a mesh, in the two steps of the pipeline: its Shape-DNA
    (:func:`cshape.shape_dna`, repaired once there), then :func:`cshape.compact_shape_dna`
    with its area."""
    import cshape
    from cshape.mesh import as_mesh

    mesh = cshape.repair_mesh(as_mesh(mesh))
    lam = cshape.shape_dna(mesh, N, bc=bc)
    return cshape.compact_shape_dna(lam, N=N, M=M, area=mesh.area, **kw)


def equilateral(subdivisions):
    """The unit equilateral triangle split ``subdivisions`` times at its edge midpoints:
    every level is the same pattern at half the size."""
    from cshape import Mesh, _refine

    m = Mesh([[0, 0, 0], [1, 0, 0], [0.5, np.sqrt(3) / 2, 0]], [[0, 1, 2]])
    for _ in range(subdivisions):
        m = _refine.midpoint_subdivision(m)
    return m


def equilateral_dirichlet(n):
    """Lame: ``16 pi^2 / 9 (j^2 + jk + k^2)`` for ``j, k >= 1``, side 1."""
    k = np.arange(1, 30)
    return np.sort((16 * np.pi**2 / 9 * (np.add.outer(k**2, k**2) + np.outer(k, k))).ravel())[:n]
