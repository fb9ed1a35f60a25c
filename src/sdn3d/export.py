"""Export a :class:`~sdn3d.scene.code.SceneCode` as a 3D scene (glTF 2.0 / GLB, through trimesh).

Contents: one mesh per object with geometry in front of the camera (posed and FFD-deformed as
the renderer draws it, node and mesh named ``instance_<id>``, coloured by class), a ground quad
named ``ground`` and a perspective camera at the origin.

Parts: each object mesh's glTF ``extras`` hold ``sdn3d_parts = {"names": [...], "faces": [...]}``: the part
names by label (:data:`sdn3d.meshes.parts.PART_NAMES`: body, glass, tyre, front_lights, tail_lights, plate) and
one label per triangle in the primitive's index order (the bank's ``face_parts``; the FFD moves vertices only,
so the deformed mesh keeps the template's labels). ``trimesh.load`` reads them back into the mesh's ``metadata``.

Axes: the scene lives in the KITTI camera frame (x right, y *down*, z forward); glTF is y *up*
with cameras looking down their local -z. Every point is mapped by ``(x, y, z) -> (x, -y, -z)``
(:data:`KITTI_TO_GLTF`, a 180 degree rotation about x: lengths, handedness and face winding are
kept), so the camera sits at the origin with the identity transform and sees exactly what the
image shows. glTF cameras are symmetric, so the principal point (and fx != fy) cannot be stored
in the camera itself; the exact intrinsics and the image size go into the scene's ``extras``
(``sdn3d`` key) along with the axis convention.
"""

from __future__ import annotations

import json
import math
import os
import struct
from pathlib import Path

import numpy as np
import trimesh

from sdn3d.io import write_bytes_atomic
from sdn3d.meshes.bank import MeshBank, default_bank
from sdn3d.meshes.parts import PART_NAMES
from sdn3d.scene.code import SceneCode
from sdn3d.scene.maps import posed_meshes

__all__ = ["KITTI_TO_GLTF", "DEFAULT_GROUND_HEIGHT", "PARTS_KEY", "scene_to_trimesh", "export_gltf"]

#: Maps KITTI camera-frame points to glTF (y up, camera looking along -z): ``p_gltf = KITTI_TO_GLTF @ p``.
KITTI_TO_GLTF = np.diag([1.0, -1.0, -1.0])
#: Ground height (camera-frame y, metres) when the scene has no object to take it from.
DEFAULT_GROUND_HEIGHT = 1.65
#: Key of the per-face part labels in each object mesh's glTF ``extras`` (module doc).
PARTS_KEY = "sdn3d_parts"


def scene_to_trimesh(scene: SceneCode, bank: MeshBank | None = None, ground_height: float | None = None,
                     ground_extent: tuple[float, float, float, float] = (-20.0, 20.0, 1.0, 80.0)) -> trimesh.Scene:
    """The scene as a :class:`trimesh.Scene` in glTF axes (module doc).

    Args:
        scene: the scene.
        bank: template meshes of the objects' ``template_id`` (default: the 8 templates).
        ground_height: camera-frame y of the ground quad; None = median bottom ``y3d`` of the
            objects with geometry, or :data:`DEFAULT_GROUND_HEIGHT` without any.
        ground_extent: ``(x_min, x_max, z_min, z_max)`` of the quad in the camera frame, metres.
    """
    bank = bank or default_bank()
    obj = scene.objects
    rows, verts, _ = posed_meshes(obj, bank)
    verts = verts.detach().cpu().double().numpy() @ KITTI_TO_GLTF.T
    colors = {c.id: c.color for c in scene.class_list}
    out = trimesh.Scene()
    for g, row in enumerate(rows.cpu().tolist()):  # one trimesh per object: export only, not a hot path
        tid = int(obj.template_id[row])
        mesh = bank.to_trimesh(tid, verts[g])
        mesh.visual.face_colors = [*colors[int(obj.class_id[row])], 255]
        mesh.metadata[PARTS_KEY] = {"names": list(PART_NAMES),
                                    "faces": bank.face_parts[tid, : int(bank.num_faces[tid])].tolist()}
        name = f"instance_{int(obj.instance_id[row])}"
        out.add_geometry(mesh, node_name=name, geom_name=name)

    if ground_height is None:
        geo = obj.has_geometry
        ground_height = float(obj.location[geo, 1].median()) if bool(geo.any()) else DEFAULT_GROUND_HEIGHT
    x0, x1, z0, z1 = (float(v) for v in ground_extent)
    if not (x0 < x1 and 0 < z0 < z1) or not math.isfinite(ground_height):
        raise ValueError(f"ground_extent must be (x_min < x_max, 0 < z_min < z_max) and ground_height finite, "
                         f"got {ground_extent}, {ground_height}")
    corners = np.array([[x0, ground_height, z0], [x1, ground_height, z0], [x1, ground_height, z1],
                        [x0, ground_height, z1]]) @ KITTI_TO_GLTF.T
    # Wound counter-clockwise seen from above (glTF +y), so the quad's front face looks up.
    ground = trimesh.Trimesh(corners, [[0, 2, 1], [0, 3, 2]], process=False)
    ground.visual.face_colors = [128, 128, 128, 255]
    out.add_geometry(ground, node_name="ground", geom_name="ground")

    intr = scene.intrinsics
    out.camera = trimesh.scene.Camera(name="camera", resolution=(intr.width, intr.height), focal=(intr.fx, intr.fy))
    out.camera_transform = np.eye(4)
    out.metadata["sdn3d"] = {
        "intrinsics": intr.to_dict(),
        "axes": "glTF = diag(1, -1, -1) @ KITTI camera frame (x right, y down, z forward)",
        "instance_ids": obj.instance_id[rows.cpu()].tolist(),
        "ground_height": ground_height,
    }
    return out


def export_gltf(scene: SceneCode, path: str | os.PathLike, bank: MeshBank | None = None,
                ground_height: float | None = None) -> Path:
    """Write the scene to ``path`` (``.glb`` binary or ``.gltf`` with embedded buffers), atomically."""
    path = Path(path)
    kind = path.suffix.lower().lstrip(".")
    if kind not in ("glb", "gltf"):
        raise ValueError(f"path must end in .glb or .gltf, got {str(path)!r}")
    tm = scene_to_trimesh(scene, bank, ground_height)
    data = tm.export(file_type=kind) if kind == "glb" else tm.export(file_type="gltf", embed_buffers=True)
    if isinstance(data, dict):  # some trimesh versions return {name: bytes} for .gltf
        data = data[next(iter(data))]
    if isinstance(data, str):
        data = data.encode("utf-8")
    return write_bytes_atomic(path, _with_gltf_aspect_ratio(data, kind, gltf_aspect_ratio(scene.intrinsics)))


def gltf_aspect_ratio(intr) -> float:
    """glTF's ``aspectRatio`` of the image's camera: ``tan(xfov / 2) / tan(yfov / 2) = (W / fx) / (H / fy)``.

    trimesh writes the ratio of the angles ``xfov / yfov`` instead, which viewers (Blender, three.js) read
    as the tangent ratio, so the view would not line up with the image.
    """
    return (intr.width / intr.fx) / (intr.height / intr.fy)


def _with_gltf_aspect_ratio(data: bytes, kind: str, aspect: float) -> bytes:
    """``data`` (a .glb or an embedded .gltf) with every perspective camera's ``aspectRatio`` set to ``aspect``."""
    if kind == "gltf":
        doc = json.loads(data)
        _set_aspect(doc, aspect)
        return json.dumps(doc).encode("utf-8")
    magic, version, _ = struct.unpack_from("<4sII", data, 0)
    json_len, json_type = struct.unpack_from("<I4s", data, 12)
    if magic != b"glTF" or json_type != b"JSON":
        raise ValueError("trimesh wrote an unexpected GLB layout")
    doc = json.loads(data[20:20 + json_len])
    _set_aspect(doc, aspect)
    chunk = json.dumps(doc).encode("utf-8")
    chunk += b" " * (-len(chunk) % 4)  # GLB chunks are 4-byte aligned; JSON pads with spaces
    rest = data[20 + json_len:]
    header = struct.pack("<4sII", b"glTF", version, 12 + 8 + len(chunk) + len(rest))
    return header + struct.pack("<I4s", len(chunk), b"JSON") + chunk + rest


def _set_aspect(doc: dict, aspect: float) -> None:
    for camera in doc.get("cameras", []):
        if camera.get("type") == "perspective":
            camera["perspective"]["aspectRatio"] = aspect
