"""Ground truth of a dataset frame for the inference path: oracle scenes and oracle de-rendering inputs.

The inference modules (:mod:`sdn3d.derender`, :mod:`sdn3d.scene`, :mod:`sdn3d.editing`) never read
datasets; this data-side adapter turns a :class:`~sdn3d.data.records.FrameRecord` into what they take:

- :func:`scene_from_frame`: a :class:`~sdn3d.scene.code.SceneCode` from the frame's annotations
  (the editing benchmark's "oracle" de-rendering);
- :func:`ground_truth`: a :class:`~sdn3d.derender.GroundTruth` (maps and annotated boxes at the
  working size) for ``derender(..., proposals='gt')``;
- :func:`frame_photo`: the frame as stored (its own resolution), for ``derender(..., photo=...)``: the geometric
  branch's crops read from it.
"""

from __future__ import annotations

import torch

from sdn3d.data.records import FrameRecord, load_instances, load_rgb, load_semantic, mesh_name_for
from sdn3d.derender import GroundTruth
from sdn3d.image_ops import InputPhoto, resize_map, scale_boxes, to_image_tensor
from sdn3d.labels import CLASS_LISTS, INSTANCE_DIVISOR, VKITTI_CLASS_INDEX
from sdn3d.meshes.templates import TEMPLATE_NAMES
from sdn3d.scene.code import DEFAULT_CODE_DIM, ObjectTable, SceneCode, SceneObject

__all__ = ["scene_from_frame", "ground_truth", "frame_photo"]


def _class_list_name(record: FrameRecord) -> str:
    return "cityscapes" if record.dataset == "cityscapes" else "vkitti"


def scene_from_frame(record: FrameRecord, image_size: tuple[int, int] | None = None,
                     code_dim: int = DEFAULT_CODE_DIM) -> SceneCode:
    """A scene from a frame's ground truth (the editing benchmark's "oracle" de-rendering).

    Every instance of the instance map becomes an observed object with its visible mask.
    Annotated objects in front of the camera get geometry: dims, yaw and location from the
    annotation, template from ``obj.model`` (:func:`~sdn3d.data.records.mesh_name_for`), ``phi = 0``;
    one with no visible pixel gets an empty mask (hidden until edited). Codes are zeros.

    Args:
        record: a frame of any reader (Cityscapes frames have no 3D annotations: mask-only objects).
        image_size: ``(W, H)`` working size (maps resized nearest-exact, intrinsics follow); None = stored size.
    """
    semantic = torch.from_numpy(load_semantic(record)).long()
    instances = torch.from_numpy(load_instances(record)).long()
    intrinsics = record.intrinsics
    if image_size is not None:
        semantic, instances = resize_map(semantic, image_size), resize_map(instances, image_size)
        intrinsics = intrinsics.resized(*image_size)
    height, width = intrinsics.size
    visible = [int(i) for i in instances.unique().tolist() if i != 0]
    objects: dict[int, SceneObject] = {}
    for obj in record.objects:
        if obj.location[2] <= 0:
            continue
        matches = [i for i in visible if i % INSTANCE_DIVISOR == obj.track_id + 1]
        label = obj.orig_label if obj.label == "DontCare" and obj.orig_label else obj.label
        class_id = VKITTI_CLASS_INDEX.get(label, VKITTI_CLASS_INDEX["Car"])
        iid = matches[0] if matches else class_id * INSTANCE_DIVISOR + obj.track_id + 1
        # An annotated object with no visible pixel at this size keeps an empty footprint.
        objects[iid] = SceneObject(iid, TEMPLATE_NAMES.index(mesh_name_for(obj)), tuple(obj.dims), obj.ry,
                                   tuple(obj.location), mask=instances == iid)
    for iid in visible:
        if iid not in objects:
            objects[iid] = SceneObject(iid, mask=instances == iid)
    table = ObjectTable.from_objects([objects[k] for k in sorted(objects)], height, width, code_dim)
    classes = _class_list_name(record)
    return SceneCode(intrinsics, semantic, classes, table, torch.zeros(len(CLASS_LISTS[classes]), code_dim),
                     {"source": record.key})


def ground_truth(record: FrameRecord, size: tuple[int, int]) -> GroundTruth:
    """``record``'s semantic and instance maps at ``size = (W, H)`` (nearest-exact) and its annotated 2D
    boxes (Virtual KITTI: instance ``k = track_id + 1``) scaled to that size, for oracle de-rendering."""
    semantic = resize_map(torch.from_numpy(load_semantic(record)).long(), size)
    instances = None
    if record.instance_path is not None:
        instances = resize_map(torch.from_numpy(load_instances(record)).long(), size)
    boxes = {}
    for obj in record.objects:
        if obj.box2d[2] > obj.box2d[0] and obj.box2d[3] > obj.box2d[1]:
            box = torch.tensor(obj.box2d, dtype=torch.float32)
            boxes[obj.track_id + 1] = scale_boxes(box, record.intrinsics, size)
    return GroundTruth(record.key, _class_list_name(record), semantic, instances, boxes)


def frame_photo(record: FrameRecord, size: tuple[int, int]) -> InputPhoto:
    """The frame's image as stored, with the plain resize to the working ``size = (W, H)`` that
    :func:`~sdn3d.data.frames.load_frame` applies (:class:`~sdn3d.image_ops.InputPhoto`, for ``derender``'s
    ``photo``)."""
    image = to_image_tensor(load_rgb(record))
    return InputPhoto(image, (size[0] / image.shape[-1], size[1] / image.shape[-2]))
