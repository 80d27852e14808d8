"""Shared test fixtures.  Meshes are built in code or read lazily, never at import time."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[1]


#: Tests in the slow tier by their measured time (`pytest --durations`: each took 5-90 s on
#: a loaded 2-core machine; subprocesses, process pools, real meshes, Hypothesis searches),
#: by function name so that a test keeps its tier when its file is reorganised.
SLOW_BY_DURATION = frozenset({
    "test_arbitrary_arrays_give_a_mesh_or_a_clear_error",
    "test_articulated_poses_near_isometric_and_seeded",
    "test_backends_give_the_same_eigenvalues_and_every_sphere_copy",
    "test_bigmesh_measure_and_report",
    "test_block_lanczos_agrees_with_arpack_on_a_real_mesh",
    "test_block_lanczos_agrees_with_arpack_tol0",
    "test_cli_reports_bad_arguments_cleanly",
    "test_committed_student_notebooks_are_nbgraders_release",
    "test_dask_nanny_malloc_variable_is_undone_in_the_worker",
    "test_demo_command_prints_descriptors",
    "test_describe_failure_list_exit_status_and_keep_going",
    "test_describe_folder_then_glob_reads_the_cache",
    "test_describe_on_a_dask_cluster_and_an_unreachable_one",
    "test_docs_example_runs",
    "test_every_real_mesh_loads_and_has_a_finite_spectrum",
    "test_exact_sphere_multiplicities_at_10k_vertices",
    "test_expected_failures_end_in_one_line",
    "test_failed_reproduce_leaves_no_report_folder",
    "test_failing_cell_is_reported",
    "test_floor_stages_and_profile",
    "test_fuzzed_files_never_crash_the_interpreter",
    "test_generate_releases_only_graded_lessons",
    "test_hostile_files_do_not_kill_or_exhaust_the_interpreter",
    "test_hull_area_normalised_descriptor_is_scale_invariant",
    "test_hull_invariances",
    "test_hull_shape_dna_is_finite_ascending_with_one_zero",
    "test_hulls_with_slivers_still_give_finite_descriptors",
    "test_interrupt_ends_in_one_line_and_leaves_complete_cache_entries",
    "test_load_creatures_is_cached_and_reproducible",
    "test_matrix_figures_square_with_class_ticks",
    "test_nbgrader_refuses_markers_outside_nbgrader_cells",
    "test_parallel_describe_from_a_plain_script_without_main_guard",
    "test_perturbed_shapes_give_valid_spectra",
    "test_perturbed_shapes_invariances",
    "test_process_pool_equals_serial",
    "test_queries_descriptors_and_exact_search",
    "test_query_by_name_and_by_mesh_file",
    "test_real_meshes_describe_info_query",
    "test_report_mds_figure_panels_square_with_one_legend",
    "test_reproduce_writes_a_report",
    "test_results_are_identical_across_processes",
    "test_resume_after_a_worker_is_killed",
    "test_resume_after_the_run_is_killed",
    "test_shape_dna_is_the_same_bits_in_a_new_process_with_each_backend",
    "test_split_products_give_the_same_bits_with_any_number_of_threads",
    "test_split_products_keep_dense_lapack_eigenvalues_and_icosahedral_copies",
    "test_two_processes_building_the_same_item_do_not_corrupt_it",
})


@pytest.hookimpl(tryfirst=True)  # before pytest's own -m selection
def pytest_collection_modifyitems(config, items):
    """A browser test, and every test of :data:`SLOW_BY_DURATION`, is in the slow tier."""
    for item in items:
        if item.get_closest_marker("slow"):
            continue
        if item.get_closest_marker("browser") or item.originalname in SLOW_BY_DURATION:
            item.add_marker(pytest.mark.slow)


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


def write_off(path, mesh):
    """Write a Mesh or (vertices, faces) as an ASCII OFF file (17 digits: exact round trip)."""
    import cshape

    mesh = cshape.as_mesh(mesh)
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
