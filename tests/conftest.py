"""Shared test fixtures.  Meshes are built in code or read lazily, never at import time."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]


def shared_meshes_dir() -> Path:
    """The real-mesh folder: $CSHAPE_SHARED_MESHES, else ../shared/meshes beside the repo."""
    env = os.environ.get("CSHAPE_SHARED_MESHES")
    return Path(env) if env else REPO.parent / "shared" / "meshes"


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
