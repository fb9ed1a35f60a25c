"""Scene maps: instance ids, depth, camera-facing normals and pose one-hots from fragments."""

from __future__ import annotations

import math

import pytest
import torch
import trimesh

from sdn3d.math3d.rotations import alpha_bins
from sdn3d.render import (
    RasterSettings,
    depth_map,
    instance_map,
    normal_map,
    pose_map,
    rasterize_meshes,
    render_scene_maps,
)

H, W = 48, 64
K = torch.tensor([[60.0, 0.0, (W - 1) / 2], [0.0, 60.0, (H - 1) / 2], [0.0, 0.0, 1.0]])
SETTINGS = RasterSettings(image_size=(H, W))


def boxes(
    *specs: tuple[tuple[float, float, float], tuple[float, float, float]],
) -> tuple[torch.Tensor, torch.Tensor]:
    """Axis-aligned boxes ``(extents, centre)`` as padded ``(N, 8, 3)`` verts and ``(N, 12, 3)`` faces."""
    verts, faces = [], []
    for extents, centre in specs:
        box = trimesh.creation.box(extents=extents).apply_translation(centre)
        verts.append(torch.tensor(box.vertices, dtype=torch.float32))
        faces.append(torch.tensor(box.faces))
    return torch.stack(verts), torch.stack(faces)


def test_front_face_normal_depth_and_instance() -> None:
    verts, faces = boxes(((2.0, 2.0, 2.0), (0.0, 0.0, 10.0)))
    frags = rasterize_meshes(verts, faces, K, SETTINGS)
    normals = normal_map(frags, verts, faces)
    assert normals.shape == (1, 3, H, W)
    centre = normals[0, :, H // 2 - 3 : H // 2 + 3, W // 2 - 3 : W // 2 + 3]
    assert torch.allclose(centre, torch.tensor([0.0, 0.0, -1.0]).view(3, 1, 1).expand_as(centre), atol=1e-6)
    depth = depth_map(frags)
    assert torch.allclose(depth[0][frags.mask[0]], torch.tensor(9.0))  # the front face is at z = 10 - 1
    assert (depth[~frags.mask] == 0).all() and (normals.permute(0, 2, 3, 1)[~frags.mask] == 0).all()
    ids = instance_map(frags, torch.tensor([26001]))
    assert set(ids.unique().tolist()) == {0, 26001} and torch.equal(ids > 0, frags.mask)
    # Winding does not matter: flipped faces give the same camera-facing unit normals.
    flipped = normal_map(frags, verts, faces.flip(-1))
    assert torch.allclose(flipped, normals)
    unit = normals.norm(dim=1)[frags.mask]
    assert torch.allclose(unit, torch.ones_like(unit), atol=1e-6)


def test_side_face_normal_points_to_camera() -> None:
    # A box off to the right, turned by 45 degrees: every visible normal faces the camera.
    box = trimesh.creation.box(extents=(2.0, 2.0, 2.0))
    box.apply_transform(trimesh.transformations.rotation_matrix(math.pi / 4, [0, 1, 0]))
    box.apply_translation([3.0, 0.0, 12.0])
    verts = torch.tensor(box.vertices, dtype=torch.float32)[None]
    faces = torch.tensor(box.faces)[None]
    frags = rasterize_meshes(verts, faces, K, SETTINGS)
    normals = normal_map(frags, verts, faces).permute(0, 2, 3, 1)[frags.mask]
    rows, cols = frags.mask[0].nonzero().unbind(1)
    rays = torch.stack([(cols - K[0, 2]) / K[0, 0], (rows - K[1, 2]) / K[1, 1], torch.ones(len(rows))], -1)
    assert (normals * rays).sum(-1).max() < 0
    assert normals[:, 1].abs().max() < 1e-6  # vertical faces only are visible (camera at box height)


def test_front_most_object_wins_instance_and_depth() -> None:
    verts, faces = boxes(((4.0, 2.0, 2.0), (0.0, 0.0, 15.0)), ((1.0, 1.0, 1.0), (0.0, 0.0, 8.0)))
    maps = render_scene_maps(
        verts,
        faces,
        K,
        SETTINGS,
        torch.tensor([26001, 26002]),
        torch.tensor([0.1, -2.0]),
        mesh_to_image=torch.tensor([0, 0]),
        batch_size=1,
    )
    centre = (0, H // 2, W // 2)
    assert maps.instance[centre] == 26002 and maps.depth[centre] == pytest.approx(7.5)
    assert (maps.instance == 26001).sum() > (maps.instance == 26002).sum() > 0
    assert torch.equal(maps.mask, maps.instance > 0)
    assert (
        maps.depth.shape == (1, H, W)
        and maps.normal.shape == (1, 3, H, W)
        and maps.pose.shape == (1, 24, H, W)
    )


def test_pose_map_one_hot_inside_objects_only() -> None:
    verts, faces = boxes(
        ((2.0, 2.0, 2.0), (-4.0, 0.0, 12.0)),
        ((2.0, 2.0, 2.0), (4.0, 0.0, 12.0)),
        ((40.0, 0.1, 40.0), (0.0, 3.0, 30.0)),
    )
    alpha = torch.tensor([0.3, -2.9, math.nan])  # the third mesh (ground) has no pose
    frags = rasterize_meshes(verts, faces, K, SETTINGS, torch.zeros(3, dtype=torch.long), 1)
    pose = pose_map(frags, alpha)
    assert pose.shape == (1, 24, H, W)
    total = pose.sum(1)[0]
    objects = frags.mask[0] & (frags.pix_to_mesh[0] < 2)
    assert objects.sum() > 50 and (frags.pix_to_mesh[0] == 2).sum() > 50
    assert (total[objects] == 1).all() and (total[~objects] == 0).all()
    bins = alpha_bins(alpha[:2])
    for mesh in range(2):
        where = frags.pix_to_mesh[0] == mesh
        assert (pose[0].argmax(0)[where] == bins[mesh]).all()
    assert pose_map(frags, alpha, num_bins=8).shape == (1, 8, H, W)


def test_maps_on_empty_frames_and_bad_input() -> None:
    verts, faces = boxes(((2.0, 2.0, 2.0), (0.0, 0.0, -10.0)))  # behind the camera
    maps = render_scene_maps(verts, faces, K, SETTINGS, torch.tensor([7]), torch.tensor([0.0]))
    assert not maps.mask.any() and (maps.instance == 0).all() and (maps.pose == 0).all()
    assert (maps.depth == 0).all() and (maps.normal == 0).all()
    frags = rasterize_meshes(*boxes(((2.0, 2.0, 2.0), (0.0, 0.0, 10.0))), K, SETTINGS)
    with pytest.raises(ValueError, match="mesh_ids"):
        instance_map(frags, torch.tensor([1.5]))
    with pytest.raises(ValueError, match="alpha"):
        pose_map(frags, torch.tensor([], dtype=torch.float32))
