"""Geometric branch dataset: one item per annotated object passing the paper's filter.

Index building (at construction): every frame's objects are filtered with
:func:`~sdn3d.data.vkitti1.paper_object_filter` on their visible pixel count at the *native*
resolution. Counts come from the annotation when every object of the frame carries one
(Virtual KITTI 2's ``number_pixels``), otherwise from the frame's instance map, which is then
read once at construction (cached in memory per file version). That costs one instance-map
decode per frame, fine for the datasets used here (a few thousand frames); items only read
their own frame.
An instance map that can not be read there stops indexing naming the file; with a
:class:`~sdn3d.data.errors.SkipLog` (``skip=``, the skip policy) that frame's objects are left out and
the file is recorded instead.

Object <-> instance: Virtual KITTI instance ids are ``class_id * 1000 + tid + 1``, so an
object's visible pixels are those with ``id % 1000 == tid + 1`` (any class; this also
covers objects labelled ``DontCare``).

Crops are **square**: the 2D box (working-size pixels) is enlarged by ``margin`` of its
larger side on every side, made square around the box centre and snapped to whole pixels,
then resampled to ``crop_size x crop_size``. Square crops resize isotropically, so the
crop camera keeps the image's ``fx / fy`` ratio and the posed mesh's soft silhouette can be
rendered straight into the crop with ``crop_intrinsics``. Windows may leave the image
(padding is zero).
"""

from __future__ import annotations

import functools
import math
import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch
from torch import Tensor
from torch.utils.data import Dataset

from sdn3d.data.errors import DataFormatError, SkipLog, missing
from sdn3d.data.frames import Frame, intrinsics_vector, load_frame
from sdn3d.data.records import FrameRecord, ObjectAnnotation, load_instances
from sdn3d.data.sources import SourceConfig, load_split
from sdn3d.data.vkitti1 import paper_object_filter
from sdn3d.image_ops import crop_windows, scale_boxes, square_crop_window
from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.math3d.camera import Intrinsics
from sdn3d.math3d.encodings import AttributeEncoding
from sdn3d.math3d.transforms import bottom_to_center
from sdn3d.meshes.templates import TEMPLATE_NAMES
from sdn3d.meshes.vehicle_family import approximating_template

__all__ = [
    "ObjectFilter",
    "ObjectRef",
    "GeometricDataset",
    "track_pixel_counts",
    "object_mask",
    "closer_object_mask",
    "template_id",
]


@dataclass(frozen=True)
class ObjectFilter:
    """Thresholds of the paper's object filter (:func:`~sdn3d.data.vkitti1.paper_object_filter`): ``> min_pixels``
    visible pixels at native size, estimated occlusion ``1 - occupr / 0.8 < max_occlusion`` (``occupr`` is
    visible / box area; :func:`~sdn3d.data.vkitti1.occlusion_estimate`) and not flagged ``occluded = 2`` where
    the format has the flag, truncation ``truncr < max_truncation``."""

    min_pixels: int = 256
    max_occlusion: float = 0.7
    max_truncation: float = 0.7

    def __call__(self, obj: ObjectAnnotation, visible_pixels: int) -> bool:
        return paper_object_filter(obj, visible_pixels, self.min_pixels, self.max_occlusion,
                                   self.max_truncation)


@dataclass(frozen=True)
class ObjectRef:
    """One indexed object: frame index into ``records``, object index in ``record.objects``."""

    frame: int
    object: int
    visible_pixels: int


def track_pixel_counts(instances: np.ndarray) -> dict[int, int]:
    """Visible pixels per track id (``id % 1000 - 1``) of a Virtual KITTI ``(H, W)`` instance map."""
    ids, counts = np.unique(np.asarray(instances), return_counts=True)
    keep = ids != 0
    tids = ids[keep] % INSTANCE_DIVISOR - 1
    out: dict[int, int] = {}
    for tid, count in zip(tids.tolist(), counts[keep].tolist(), strict=True):
        out[tid] = out.get(tid, 0) + count
    return out


@functools.lru_cache(maxsize=8192)
def _cached_counts(record: FrameRecord, _mtime_ns: int) -> dict[int, int]:
    return track_pixel_counts(load_instances(record))


def _frame_counts(record: FrameRecord) -> dict[int, int]:
    if record.objects and all(o.num_pixels is not None for o in record.objects):
        return {o.track_id: int(o.num_pixels) for o in record.objects}
    if record.instance_path is None:
        raise ValueError(f"{record.key}: no instance map and no annotated pixel counts to filter with")
    try:
        mtime = os.stat(Path(record.instance_path)).st_mtime_ns
    except FileNotFoundError:
        raise missing(record.instance_path, "instance map") from None
    return _cached_counts(record, mtime)


def object_mask(instances: Tensor, track_id: int) -> Tensor:
    """``(H, W)`` bool visible pixels of track ``track_id`` (ids ``class * 1000 + tid + 1``)."""
    return (instances > 0) & (instances % INSTANCE_DIVISOR == track_id + 1)


def closer_object_mask(
    instances: Tensor, depth: Tensor, mask: Tensor, reference_depth: float | Tensor
) -> Tensor:
    """``(H, W)`` bool pixels of *other* instances nearer than the object.

    A pixel is marked when it belongs to an instance (id != 0) other than the object
    (``~mask``) and its depth is below ``reference_depth`` (the object's median visible
    depth): those objects may hide part of the object, so a silhouette loss must not
    penalise the object's projection there. Farther objects and background are not marked.

    Args:
        instances: ``(H, W)`` int64 instance ids; depth: ``(H, W)`` metres; mask: ``(H, W)`` bool.
    """
    if instances.shape != depth.shape or instances.shape != mask.shape:
        raise ValueError(f"instances, depth and mask must share one (H, W) shape, got "
                         f"{tuple(instances.shape)}, {tuple(depth.shape)}, {tuple(mask.shape)}")
    return (instances != 0) & ~mask & (depth < reference_depth)


def template_id(model: str) -> int:
    """Index in :data:`TEMPLATE_NAMES` of the template standing for ``model``: the template it names, or the
    approximating template of a held-out vehicle shape (:func:`sdn3d.meshes.vehicle_family.approximating_template`;
    on ``vehicles: heldout`` synthetic data mesh accuracy means "picked the approximating template"); -1 otherwise."""
    template = approximating_template(model)
    return -1 if template is None else TEMPLATE_NAMES.index(template)


class GeometricDataset(Dataset):
    """Objects for the geometric branch (ResNet-18 on masked object crops).

    Item (``S`` = crop_size, boxes in working-size pixels)::

        crop             (3, S, S) float32 masked object crop (pixels outside the object's mask are 0)
        mask             (1, S, S) float32 the object's visible mask
        ignore           (1, S, S) float32 pixels of closer objects (see closer_object_mask)
        box              (4,) l, t, r, b of the 2D box (annotation box scaled to the working size)
        crop_box         (4,) edges l, t, r, b of the square crop window
        crop_intrinsics  (4,) fx, fy, cx, cy of the S x S crop
        intrinsics       (4,) fx, fy, cx, cy of the working-size image
        targets          dict of AttributeEncoding.encode: log_scale (3,), rotation (4,), offset (2,),
                         log_distance (1,), from the working-size box and intrinsics
        dims (3,) l h w; ry (); center (3,) box centre (camera frame)
        template_id      int64, template_id(obj.model): the template it names or approximates, or -1
        track_id         int64; visible_pixels int64 (native resolution)
        key              str, "<frame key>/<track id>"

    Args:
        records: frames.
        image_size: working size ``(W, H)``.
        crop_size: ``S``.
        margin: crop enlargement per side, as a fraction of the box's larger side.
        object_filter: thresholds of the paper's filter.
        encoding: target parameterisation (paper default).
        cache_items: keep every item after its first read (items are deterministic), and read the other
            objects of its frame with it, from the one decoded frame: a shuffled epoch otherwise decodes a
            whole frame per object (most of a read's time; about 3 objects per synthetic frame). With 64-px
            crops an object is ~90 kB, so a few thousand objects fit easily (256-px crops: ~1.4 MB each).
            Each loader worker keeps its own.
        skip: None: an instance map unreadable while indexing raises; a :class:`SkipLog`: that frame's
            objects are left out and the file recorded (the skip policy).
        mirror: also serve every object mirrored left to right (items ``len(objects) ..`` of twice the length; issue
            40): the scene reflected about the camera's vertical plane through the principal point (``x -> -x``,
            ``u -> 2 cx - u``, ``ry -> pi - ry``), with its crop, masks, boxes, crop camera and targets; the
            templates are mirror-symmetric. No randomness: an epoch's shuffled order decides which are seen.
    """

    def __init__(
        self,
        records: Sequence[FrameRecord],
        image_size: tuple[int, int],
        crop_size: int = 64,
        margin: float = 0.1,
        object_filter: ObjectFilter | None = None,
        encoding: AttributeEncoding | None = None,
        cache_items: bool = False,
        skip: SkipLog | None = None,
        mirror: bool = False,
    ) -> None:
        if crop_size <= 0:
            raise ValueError(f"crop_size must be positive, got {crop_size}")
        if margin < 0:
            raise ValueError(f"margin must be non-negative, got {margin}")
        self.records = list(records)
        self.image_size = (int(image_size[0]), int(image_size[1]))
        self.crop_size = int(crop_size)
        self.margin = float(margin)
        self.object_filter = object_filter or ObjectFilter()
        self.encoding = encoding or AttributeEncoding()
        self.objects: list[ObjectRef] = self._build_index(skip)
        self._last: tuple[int, Frame] | None = None  # items of one frame are adjacent when not shuffled
        self._items: dict[int, dict] | None = {} if cache_items else None
        self._frame_objects: dict[int, list[int]] = {}  # frame index -> its objects' indices, for cache_items
        for i, ref in enumerate(self.objects if cache_items else ()):
            self._frame_objects.setdefault(ref.frame, []).append(i)
        self.mirror = bool(mirror)

    @classmethod
    def from_source(cls, source: SourceConfig, part: str, skip: SkipLog | None = None,
                    **kwargs) -> GeometricDataset:
        """The ``part`` of ``source``; ``skip`` as in :func:`~sdn3d.data.sources.load_split` and the class."""
        return cls(load_split(source, part, skip), source.image_size, skip=skip, **kwargs)

    def _build_index(self, skip: SkipLog | None = None) -> list[ObjectRef]:
        refs = []
        for f, record in enumerate(self.records):
            if not record.objects:
                continue
            try:
                counts = _frame_counts(record)
            except DataFormatError as exc:
                if skip is None:
                    raise
                skip.skip(exc, "frame", record.key)
                continue
            for o, obj in enumerate(record.objects):
                l, t, r, b = obj.box2d
                visible = counts.get(obj.track_id, 0)
                if r > l and b > t and obj.location[2] > 0 and self.object_filter(obj, visible):
                    refs.append(ObjectRef(f, o, visible))
        return refs

    def __len__(self) -> int:
        return len(self.objects) * (2 if self.mirror else 1)

    def _frame(self, index: int) -> Frame:
        if self._last is None or self._last[0] != index:
            record = self.records[index]
            frame = load_frame(record, self.image_size, semantic=False, instances=True, depth=True)
            self._last = (index, frame)
        return self._last[1]

    def __getitem__(self, index: int) -> dict:
        if not 0 <= index < len(self):
            raise IndexError(f"object index {index} out of range for {len(self)} items")
        base = index % len(self.objects)
        if self._items is not None:
            item = self._items.get(base)
            if item is None:
                for sibling in self._frame_objects[self.objects[base].frame]:
                    if sibling not in self._items:
                        self._items[sibling] = self._read(sibling)
                item = self._items[base]
        else:
            item = self._read(base)
        return self._mirrored(item) if index >= len(self.objects) else item

    def _mirrored(self, item: dict) -> dict:
        """``item`` reflected left to right about the principal point's column (class doc, ``mirror``)."""
        fx, fy, cx, cy = item["intrinsics"].tolist()
        s = self.crop_size

        def flip_box(box: Tensor) -> Tensor:
            return torch.stack([2 * cx - box[2], box[1], 2 * cx - box[0], box[3]])

        box = flip_box(item["box"])
        center = item["center"] * torch.tensor([-1.0, 1.0, 1.0])
        ry = torch.atan2(torch.sin(math.pi - item["ry"]), torch.cos(math.pi - item["ry"]))
        crop_intr = item["crop_intrinsics"].clone()
        crop_intr[2] = s - 1 - crop_intr[2]
        K = torch.tensor([[fx, 0.0, cx], [0.0, fy, cy], [0.0, 0.0, 1.0]])
        targets = self.encoding.encode(item["dims"][None], ry[None], center[None], box[None], K)
        return {**item, "crop": item["crop"].flip(-1), "mask": item["mask"].flip(-1), "ignore": item["ignore"].flip(-1),
                "box": box, "crop_box": flip_box(item["crop_box"]), "crop_intrinsics": crop_intr,
                "targets": {k: v[0] for k, v in targets.items()}, "ry": ry, "center": center,
                "key": f"{item['key']}/mirrored"}

    def _read(self, index: int) -> dict:
        ref = self.objects[index]
        record = self.records[ref.frame]
        obj = record.objects[ref.object]
        frame = self._frame(ref.frame)
        intr: Intrinsics = frame.intrinsics
        mask = object_mask(frame.instances, obj.track_id)
        dims = torch.tensor(obj.dims, dtype=torch.float32)
        ry = torch.tensor(obj.ry, dtype=torch.float32)
        center = bottom_to_center(torch.tensor([obj.location], dtype=torch.float32), dims[1:2])[0]
        reference = frame.depth[mask].median() if bool(mask.any()) else center[2]
        ignore = closer_object_mask(frame.instances, frame.depth, mask, reference)

        box = scale_boxes(torch.tensor(obj.box2d, dtype=torch.float32), record.intrinsics, self.image_size)
        left, top, side = square_crop_window(box, self.margin)
        s = self.crop_size
        window = torch.tensor([[left, top, side]], dtype=torch.float32)
        image = crop_windows(frame.image, window, s, "bilinear")[0]
        masks = crop_windows(torch.stack([mask, ignore]).float(), window, s, "nearest")[0]
        crop_intr = intr.cropped(left, top, side, side).resized(s, s)
        K = intr.matrix()
        targets = self.encoding.encode(dims[None], ry[None], center[None], box[None], K)
        return {
            "crop": image * masks[:1],
            "mask": masks[:1],
            "ignore": masks[1:],
            "box": box,
            "crop_box": torch.tensor([left - 0.5, top - 0.5, left + side - 0.5, top + side - 0.5]),
            "crop_intrinsics": intrinsics_vector(crop_intr),
            "intrinsics": intrinsics_vector(intr),
            "targets": {k: v[0] for k, v in targets.items()},
            "dims": dims,
            "ry": ry,
            "center": center,
            "template_id": torch.tensor(template_id(obj.model), dtype=torch.long),
            "track_id": torch.tensor(obj.track_id, dtype=torch.long),
            "visible_pixels": torch.tensor(ref.visible_pixels, dtype=torch.long),
            "key": f"{record.key}/{obj.track_id}",
        }
