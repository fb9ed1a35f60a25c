"""Textural branch dataset: frames with the label, boundary and geometry maps pix2pixHD needs.

Instance label map ``L`` (one long map): pixels of an instance carry its instance id
``class_id * 1000 + k`` (always >= 1000 here: instance classes have ids >= 1), every other
pixel its semantic class id (< 1000; 255 = ignore). ``L >= 1000`` therefore means "object".
Instances win conflicts with the semantic map, so ``label`` is the semantic map with each
instance pixel set to the instance's class.

Two sources of the generator inputs (``maps``): the ground truth (below), or the other branches'
predictions read from a :class:`~sdn3d.data.map_cache.MapCache` (``predicted``: the semantic branch's
labels and proposals and the geometric branch's meshes, FFD and poses composed by the edit-time code,
:mod:`sdn3d.predicted_maps`), as 3D-SDN trains. The image (the target) is always the frame's own.

With ground-truth maps, geometry maps come from the ground truth: every annotated object of the frame is drawn with
the project's hard rasterizer at the working size (:func:`sdn3d.render.objects.pose_meshes`,
:func:`sdn3d.render.rasterize_meshes`, :func:`sdn3d.render.maps.normal_map`), using the template
named in ``obj.model`` (fallback ``'van'`` for vans, ``'sedan'`` otherwise), its dims, yaw and
box centre, no FFD. The normal map is the camera-frame unit normal of the visible face
(oriented towards the camera), kept only where the rendered object coincides with the
object's visible instance pixels; elsewhere it is 0. The pose map is the one-hot bin
(24 bins over [-pi, pi)) of the object's observation angle, filled inside the object's visible
silhouette (the instance pixels), as in docs/ARCHITECTURE.md. Frames without 3D annotations
(Cityscapes) get zero normal and pose maps and ``has_geometry = False``.
"""

from __future__ import annotations

from collections.abc import Sequence

import torch
import torch.nn.functional as F
from torch import Tensor
from torch.utils.data import Dataset

from sdn3d.data.errors import SkipLog
from sdn3d.data.frames import intrinsics_vector, load_frame
from sdn3d.data.map_cache import MapCache
from sdn3d.data.records import FrameRecord, ObjectAnnotation, mesh_name_for
from sdn3d.data.sources import SourceConfig, load_split
from sdn3d.image_ops import boundary_map, instance_label_map
from sdn3d.labels import INSTANCE_DIVISOR, SemanticClass, class_list
from sdn3d.math3d.camera import Intrinsics
from sdn3d.math3d.rotations import NUM_POSE_BINS, alpha_bins, observation_angle
from sdn3d.math3d.transforms import bottom_to_center
from sdn3d.meshes.bank import MeshBank
from sdn3d.render.maps import normal_map
from sdn3d.render.objects import pose_meshes
from sdn3d.render.rasterize import rasterize_meshes
from sdn3d.render.settings import RasterSettings

__all__ = [
    "TexturalDataset",
    "render_geometry_maps",
]


def render_geometry_maps(
    objects: Sequence[ObjectAnnotation],
    intrinsics: Intrinsics,
    instances: Tensor,
    bank: MeshBank,
    num_bins: int = NUM_POSE_BINS,
) -> tuple[Tensor, Tensor]:
    """Normal ``(3, H, W)`` and pose ``(num_bins, H, W)`` maps of a frame's objects.

    Args:
        objects: the frame's annotated objects (Virtual KITTI ids: ``k = track_id + 1``).
        intrinsics: intrinsics of the instance map's size.
        instances: ``(H, W)`` int64 instance map at that size.
        bank: template bank whose ``names`` are :data:`TEMPLATE_NAMES`.
    """
    height, width = instances.shape
    if (height, width) != intrinsics.size:
        raise ValueError(f"instances is {width}x{height} but intrinsics are for "
                         f"{intrinsics.width}x{intrinsics.height}")
    normal = torch.zeros(3, height, width)
    pose = torch.zeros(num_bins, height, width)
    objects = [o for o in objects if o.location[2] > 0]
    if not objects:
        return normal, pose
    tids = torch.tensor([o.track_id for o in objects])
    dims = torch.tensor([o.dims for o in objects], dtype=torch.float32)
    ry = torch.tensor([o.ry for o in objects], dtype=torch.float32)
    location = torch.tensor([o.location for o in objects], dtype=torch.float32)
    center = bottom_to_center(location, dims[:, 1])

    # Track id of the visible instance at each pixel (-1: none) and its object's row in `objects`.
    pixel_tid = torch.where(instances > 0, instances % INSTANCE_DIVISOR - 1, -1)
    lut = torch.full((INSTANCE_DIVISOR,), -1, dtype=torch.long)
    lut[tids] = torch.arange(len(objects))
    visible_obj = torch.where(pixel_tid >= 0, lut[pixel_tid.clamp(min=0)], -1)

    bins = alpha_bins(observation_angle(ry, location[:, 0], location[:, 2]), num_bins)
    pixel_bin = torch.where(visible_obj >= 0, bins[visible_obj.clamp(min=0)], -1)
    pose = F.one_hot(pixel_bin.clamp(min=0), num_bins).permute(2, 0, 1).float() * (pixel_bin >= 0)

    mesh_ids = torch.tensor([bank.index(mesh_name_for(o)) for o in objects])
    verts, faces = pose_meshes(bank, mesh_ids, dims, ry, center)
    frags = rasterize_meshes(verts, faces, intrinsics.matrix(), RasterSettings(image_size=(height, width)),
                             mesh_to_image=torch.zeros(len(objects), dtype=torch.long), batch_size=1)
    coincide = (frags.pix_to_mesh[0] >= 0) & (frags.pix_to_mesh[0] == visible_obj)
    normal = normal_map(frags, verts, faces)[0] * coincide
    return normal, pose


class TexturalDataset(Dataset):
    """Frames for the textural branch (pix2pixHD generator / encoder).

    Item (``H, W`` = working size)::

        image               (3, H, W) float32 in [0, 1]
        label               (H, W) int64 semantic classes, instance classes win (255 ignore)
        instance            (H, W) int64 class_id * 1000 + k, 0 = none
        instance_label_map  (H, W) int64 L (module doc)
        boundary            (1, H, W) float32 instance boundaries of L
        normal              (3, H, W) float32 camera-frame normals (0 off objects)
        pose                (24, H, W) float32 one-hot observation-angle bins (0 off objects)
        depth               (1, H, W) float32 metres (ground truth; 0 where none on disk)
        intrinsics          (4,) float32; has_geometry bool tensor; key str

    Args:
        records, image_size, classes: as :class:`~sdn3d.data.datasets.SemanticDataset`.
        render: draw normal/pose maps (False leaves them zero); ground-truth maps only.
        predicted: read label, instance, normal and pose maps from this cache instead of the ground truth.
    """

    def __init__(
        self,
        records: Sequence[FrameRecord],
        image_size: tuple[int, int],
        classes: Sequence[SemanticClass] | None = None,
        render: bool = True,
        predicted: MapCache | None = None,
    ) -> None:
        self.records = list(records)
        self.image_size = (int(image_size[0]), int(image_size[1]))
        kinds = {r.dataset for r in self.records}
        if len(kinds) > 1:
            raise ValueError(f"records must all come from one dataset kind, got {sorted(kinds)}")
        self.classes = tuple(classes) if classes is not None else (class_list(kinds.pop()) if kinds else ())
        self.render = render
        self.predicted = predicted
        if predicted is not None and predicted.size != (self.image_size[1], self.image_size[0]):
            raise ValueError(f"the predicted-map cache {predicted.directory} is at {predicted.size[::-1]}, the "
                             f"dataset at {self.image_size}")
        self._bank: MeshBank | None = None

    @classmethod
    def from_source(cls, source: SourceConfig, part: str, skip: SkipLog | None = None, **kwargs) -> TexturalDataset:
        """The ``part`` of ``source``; ``skip`` as in :func:`~sdn3d.data.sources.load_split` (the skip policy)."""
        return cls(load_split(source, part, skip), source.image_size, source.class_list, **kwargs)

    @property
    def bank(self) -> MeshBank:
        if self._bank is None:  # built lazily, once per worker process
            self._bank = MeshBank.templates()
        return self._bank

    def __len__(self) -> int:
        return len(self.records)

    def __getitem__(self, index: int) -> dict:
        record = self.records[index]
        gt_maps = self.predicted is None
        frame = load_frame(record, self.image_size, semantic=gt_maps, instances=gt_maps, depth=True)
        if gt_maps:
            instances = frame.instances
            label, lmap = instance_label_map(frame.semantic, instances)
            height, width = label.shape
            has_geometry = self.render and bool(record.objects)
            if has_geometry:
                normal, pose = render_geometry_maps(record.objects, frame.intrinsics, instances, self.bank)
            else:
                normal, pose = torch.zeros(3, height, width), torch.zeros(NUM_POSE_BINS, height, width)
        else:
            maps = self.predicted.load(record.key)
            instances, normal = maps.instance, maps.normal
            label, lmap = instance_label_map(maps.semantic, instances)
            drawn = maps.pose_bin >= 0
            pose = F.one_hot(maps.pose_bin.clamp(min=0), NUM_POSE_BINS).permute(2, 0, 1).float() * drawn
            has_geometry = bool(drawn.any())
        return {
            "image": frame.image,
            "label": label,
            "instance": instances,
            "instance_label_map": lmap,
            "boundary": boundary_map(lmap[None])[0],
            "normal": normal,
            "pose": pose,
            "depth": frame.depth[None],
            "intrinsics": intrinsics_vector(frame.intrinsics),
            "has_geometry": torch.tensor(has_geometry),
            "key": record.key,
        }
