"""Posed figures that keep the template's vertices (skeleton, linear blend skinning)."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("pymeshlab")

from cshape.data import poses  # noqa: E402

SMALL = {"voxelsize": 0.03, "target_vertices": 800}  # ~700 vertices, under a second


def _edge_ratio(a, b):
    E = a.edges
    la = np.linalg.norm(a.vertices[E[:, 0]] - a.vertices[E[:, 1]], axis=1)
    lb = np.linalg.norm(b.vertices[E[:, 0]] - b.vertices[E[:, 1]], axis=1)
    return lb / la


@pytest.mark.parametrize("kind", poses.POSED_KINDS)
def test_poses_keep_the_template_and_are_near_isometric(kind):
    rest = poses.posed_figure(kind, rest=True, **SMALL)
    assert rest is poses.pose_template(kind, **SMALL)
    assert rest.is_closed and rest.n_components == 1
    a = poses.posed_figure(kind, 1, **SMALL)
    b = poses.posed_figure(kind, 1, **SMALL)
    c = poses.posed_figure(kind, 2, **SMALL)
    np.testing.assert_array_equal(a.faces, rest.faces)  # same triangles: map = identity
    np.testing.assert_array_equal(a.vertices, b.vertices)  # same seed, same pose
    assert np.abs(a.vertices - c.vertices).max() > 0.05  # another seed moves the limbs
    assert np.abs(a.vertices - rest.vertices).max() > 0.05
    r = _edge_ratio(rest, a)
    # rigid parts keep their edges exactly; the joints stretch and compress a few edges
    assert np.mean(np.abs(r - 1) < 1e-9) > 0.5
    assert np.percentile(np.abs(r - 1), 95) < 0.2
    assert a.area == pytest.approx(rest.area, rel=0.02)


def test_skin_weights_partition_of_unity_and_rigid_far_from_joints():
    rest = poses.pose_template("human", **SMALL)
    W = poses.skin_weights("human", rest.vertices)
    assert W.shape == (rest.n_vertices, 10) and (W >= 0).all()
    np.testing.assert_allclose(W.sum(axis=1), 1.0)
    top = rest.vertices[:, 2].argmax()  # the top of the head follows the head bone alone
    assert W[top, 1] == pytest.approx(1.0)


@pytest.mark.parametrize("kind", poses.POSED_KINDS)
def test_mirror_map_is_a_near_symmetry(kind):
    rest = poses.pose_template(kind, **SMALL)
    m = poses.mirror_map(kind, rest)
    axis = {"human": 0, "quadruped": 1}[kind]
    R = rest.vertices.copy()
    R[:, axis] *= -1
    # the mirror image of each vertex is within about an edge of its image vertex
    assert np.linalg.norm(rest.vertices[m] - R, axis=1).max() < 2 * rest.mean_edge_length
    assert np.mean(m[m] == np.arange(rest.n_vertices)) > 0.6  # nearly an involution


def test_bad_kind():
    with pytest.raises(ValueError, match=r"kind must be one of \{'human', 'quadruped'\}"):
        poses.posed_figure("octopus")


def test_manifest_poses_collection_lists_the_rest_pose_and_five_poses_per_class():
    from cshape import data

    entry = data.info("poses")
    items = {it["name"]: it for it in entry["items"]}
    for kind in poses.POSED_KINDS:
        assert items[f"{kind}-rest"]["recipe"] == "pose-template"
        for k in range(5):
            assert items[f"{kind}-{k}"]["base"] == f"poses/{kind}-rest"


@pytest.mark.slow
def test_manifest_poses_share_the_cached_template(tmp_path):
    from cshape import data

    rest = data.load("poses", "quadruped-rest", cache_dir=tmp_path)
    p2 = data.load("poses", "quadruped-2", cache_dir=tmp_path)
    np.testing.assert_array_equal(p2.faces, rest.faces)
    np.testing.assert_array_equal(rest.vertices, poses.pose_template("quadruped").vertices)
    np.testing.assert_array_equal(p2.vertices, poses.posed_figure("quadruped", 2).vertices)
    # from the cache file: the same bits again
    np.testing.assert_array_equal(data.load("poses", "quadruped-2", cache_dir=tmp_path).vertices,
                                  p2.vertices)
