"""glTF / GLB export of a scene: loads back in trimesh with the right meshes, axes and camera."""

from __future__ import annotations

import numpy as np
import pytest
import torch
import trimesh

from sdn3d.export import KITTI_TO_GLTF, export_gltf, scene_to_trimesh
from sdn3d.labels import VKITTI_CLASS_INDEX
from sdn3d.math3d.camera import VKITTI_INTRINSICS, project_points
from sdn3d.meshes.bank import default_bank
from sdn3d.scene.code import ObjectTable, SceneCode, SceneObject
from sdn3d.scene.maps import posed_meshes

W, H = 96, 32
CAR, VAN = VKITTI_CLASS_INDEX["Car"], VKITTI_CLASS_INDEX["Van"]


def _scene() -> SceneCode:
    gen = torch.Generator().manual_seed(0)
    mask = torch.zeros(H, W, dtype=torch.bool)
    mask[20:25, 3:8] = True
    objects = [
        SceneObject(CAR * 1000 + 1, 1, (4.0, 1.5, 1.8), 0.4, (-1.0, 1.6, 9.0),
                    phi=0.02 * torch.randn(64, 3, generator=gen)),
        SceneObject(VAN * 1000 + 3, 7, (9.0, 3.0, 2.5), 2.0, (4.0, 1.7, 25.0)),
        SceneObject(CAR * 1000 + 5, -1, mask=mask),  # no geometry: not exported
        SceneObject(CAR * 1000 + 6, 0, (4.0, 1.5, 1.8), 0.0, (0.0, 1.6, -5.0)),  # behind the camera: not exported
    ]
    table = ObjectTable.from_objects(objects, H, W)
    return SceneCode(VKITTI_INTRINSICS.resized(W, H), torch.zeros(H, W, dtype=torch.long), "vkitti", table,
                     torch.zeros(14, 5))


@pytest.mark.parametrize("suffix", [".glb", ".gltf"])
def test_export_loads_back_with_the_posed_meshes(tmp_path, suffix):
    scene = _scene()
    path = export_gltf(scene, tmp_path / f"scene{suffix}")
    loaded = trimesh.load(path, process=False)
    assert isinstance(loaded, trimesh.Scene)
    assert set(loaded.geometry) == {"instance_12001", "instance_13003", "ground"}
    bank = default_bank()
    rows, verts, faces = posed_meshes(scene.objects, bank)
    for g, row in enumerate(rows.tolist()):
        template = int(scene.objects.template_id[row])
        mesh = loaded.geometry[f"instance_{int(scene.objects.instance_id[row])}"]
        nv, nf = int(bank.num_verts[template]), int(bank.num_faces[template])
        assert len(mesh.vertices) == nv and len(mesh.faces) == nf
        # Vertices are the renderer's FFD-deformed camera-frame vertices, mapped y -> -y, z -> -z.
        expected = verts[g, :nv].double().numpy() @ KITTI_TO_GLTF.T
        assert np.allclose(mesh.vertices, expected, atol=1e-5)
        assert np.array_equal(mesh.faces, faces[g, :nf].numpy())
    assert len(loaded.geometry["ground"].vertices) == 4
    # Ground at the median bottom height of the objects (1.6, 1.7, 1.6), below the camera (glTF y up).
    assert np.allclose(loaded.geometry["ground"].vertices[:, 1], -1.6)
    if suffix == ".glb":
        assert loaded.has_camera
        meta = loaded.metadata["sdn3d"]
        assert meta["intrinsics"] == scene.intrinsics.to_dict() and meta["instance_ids"] == [12001, 13003]


def test_axis_conversion_keeps_the_image():
    """A glTF camera at the origin looking down -z sees each exported vertex where the KITTI camera does."""
    scene = _scene()
    tm = scene_to_trimesh(scene)
    mesh = tm.geometry["instance_12001"]
    p = np.asarray(mesh.vertices)
    intr = scene.intrinsics
    u = intr.fx * p[:, 0] / -p[:, 2] + intr.cx
    v = intr.cy - intr.fy * p[:, 1] / -p[:, 2]
    kitti = torch.from_numpy(p @ KITTI_TO_GLTF)  # KITTI_TO_GLTF is its own inverse
    uv = project_points(kitti, intr.matrix(torch.float64)).numpy()
    assert np.allclose(np.stack([u, v], 1), uv, atol=1e-9)
    assert np.isclose(np.linalg.det(KITTI_TO_GLTF), 1.0)  # a rotation: winding and handedness kept
    assert np.allclose(tm.camera_transform, np.eye(4))


def test_export_rejects_bad_arguments(tmp_path):
    with pytest.raises(ValueError, match=".glb or .gltf"):
        export_gltf(_scene(), tmp_path / "scene.obj")
    with pytest.raises(ValueError, match="ground_extent"):
        scene_to_trimesh(_scene(), ground_extent=(1.0, -1.0, 1.0, 5.0))
    empty = _scene().replace(objects=ObjectTable.empty(H, W))
    assert set(scene_to_trimesh(empty).geometry) == {"ground"}


@pytest.mark.parametrize("suffix", [".glb", ".gltf"])
def test_camera_aspect_ratio_is_gltfs_tangent_ratio(tmp_path, suffix):
    """glTF defines aspectRatio as tan(xfov / 2) / tan(yfov / 2); with fx != fy (an anisotropic resize) that
    differs from both W / H and the angle ratio xfov / yfov trimesh writes."""
    import json
    import math
    import struct

    scene = _scene()
    intr = scene.intrinsics
    path = export_gltf(scene, tmp_path / f"scene{suffix}")
    data = path.read_bytes()
    if suffix == ".glb":
        (length,) = struct.unpack_from("<I", data, 12)
        doc = json.loads(data[20:20 + length])
    else:
        doc = json.loads(data)
    (camera,) = doc["cameras"]
    yfov = camera["perspective"]["yfov"]
    xfov = 2 * math.atan(intr.width / (2 * intr.fx))
    assert math.isclose(yfov, 2 * math.atan(intr.height / (2 * intr.fy)), rel_tol=1e-6)
    assert math.isclose(camera["perspective"]["aspectRatio"], math.tan(xfov / 2) / math.tan(yfov / 2), rel_tol=1e-9)
    loaded = trimesh.load(path)  # still a valid file
    assert loaded.has_camera
