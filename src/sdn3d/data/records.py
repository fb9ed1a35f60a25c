"""Records shared by all dataset readers, and dataset-agnostic array loaders.

Readers (:mod:`sdn3d.data.vkitti1`, :mod:`~sdn3d.data.vkitti2`,
:mod:`~sdn3d.data.cityscapes`) index a dataset into :class:`FrameRecord` objects
holding paths and parsed text annotations; pixel arrays are only read when one of
:func:`load_rgb`, :func:`load_semantic`, :func:`load_instances`, :func:`load_depth`
is called (these dispatch on ``record.dataset``).

Array conventions (all readers):

- rgb: ``(H, W, 3)`` uint8.
- semantic: ``(H, W)`` int64 indices into the dataset's class list;
  :data:`IGNORE_INDEX` (255) where the dataset has no usable label.
- instances: ``(H, W)`` int64, ``class_id * 1000 + k``, 0 where there is no
  instance (Cityscapes style, see docs/ARCHITECTURE.md). How ``k`` is chosen is
  dataset specific and documented in each reader (Virtual KITTI: ``k = tid + 1``).
- depth: ``(H, W)`` float32 metres along the camera z axis.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from sdn3d.data.errors import DataFormatError
from sdn3d.math3d.camera import Intrinsics
from sdn3d.meshes.vehicle_family import approximating_template

__all__ = [
    "ObjectAnnotation",
    "FrameRecord",
    "visible_pixel_counts",
    "mesh_name_for",
    "check_dims",
    "check_size",
    "load_rgb",
    "load_semantic",
    "load_instances",
    "load_depth",
]

_READER_MODULES = {
    "vkitti1": "sdn3d.data.vkitti1",
    "vkitti2": "sdn3d.data.vkitti2",
    "cityscapes": "sdn3d.data.cityscapes",
}


@dataclass(frozen=True)
class ObjectAnnotation:
    """One annotated object in one frame (KITTI / Virtual KITTI conventions).

    Attributes:
        track_id: the object's track id (``tid`` / ``trackID``), stable over a sequence.
        label: object type, e.g. ``'Car'``, ``'Van'``, ``'DontCare'`` (VKITTI 1 marks
            heavily truncated/occluded objects ``DontCare``; ``orig_label`` keeps the type).
        box2d: ``(left, top, right, bottom)`` in pixels, inclusive, origin at the top-left pixel.
        dims: ``(l, h, w)`` metres (length, height, width). NOTE the files store
            ``w3d h3d l3d`` / ``width height length``; readers reorder.
        location: ``(x3d, y3d, z3d)``, centre of the bottom face of the 3D box, camera frame.
        ry: yaw about the camera y axis; 0 points the object along +x.
        alpha: observation angle ``ry - atan2(x3d, z3d)`` exactly as stored in the file, not re-wrapped: Virtual
            KITTI 1 keeps it in ``[-pi, pi]``, but a few rows of real Virtual KITTI 2 files fall outside. Nothing
            in the library reads it: the pose maps and the geometric targets recompute the angle from ``ry`` and
            the location, wrapped (:func:`sdn3d.math3d.rotations.observation_angle`).
        truncr: fraction of the object outside the image, in [0, 1].
        occupr: the share of the 2D box that the object's visible pixels cover, in [0, 1], as the file holds it:
            Virtual KITTI 1.3.1 motgt ``occupr`` (visible pixels / 2D box area; the synthetic data divides by the
            inclusive box's pixel count ``(r - l + 1) (b - t + 1)``) and Virtual KITTI 2 ``occupancy_ratio``
            (visible pixels / ``((r - l) (b - t))``, which reproduces the published rows). It is *not* the
            visible share of the object: an unoccluded car reads about 0.8 (its silhouette does not fill its
            box); see :func:`sdn3d.data.vkitti1.occlusion_estimate`.
        truncated, occluded: VKITTI 1 KITTI-like flags (0, 1, 2); None where absent.
        rx, rz: pitch and roll in the camera frame.
        orig_label: type before the DontCare rule (VKITTI 1); None where absent.
        moving: whether the object moves between this frame and the next.
        model, color: CAD model and colour names ("" where absent).
        num_pixels: visible pixel count from the annotation (VKITTI 2); None where absent.
    """

    track_id: int
    label: str
    box2d: tuple[float, float, float, float]
    dims: tuple[float, float, float]
    location: tuple[float, float, float]
    ry: float
    alpha: float
    truncr: float
    occupr: float
    truncated: int | None = None
    occluded: int | None = None
    rx: float = 0.0
    rz: float = 0.0
    orig_label: str | None = None
    moving: bool = False
    model: str = ""
    color: str = ""
    num_pixels: int | None = None

    def __post_init__(self) -> None:
        for name, size in (("box2d", 4), ("dims", 3), ("location", 3)):
            value = getattr(self, name)
            if len(value) != size:
                raise ValueError(f"ObjectAnnotation.{name} must have {size} values, got {value!r}")

    @property
    def center(self) -> tuple[float, float, float]:
        """Centre of the 3D box, ``(x3d, y3d - h / 2, z3d)`` (camera y points down)."""
        x, y, z = self.location
        return (x, y - self.dims[1] / 2.0, z)


@dataclass(frozen=True)
class FrameRecord:
    """One image of a dataset with its annotations; arrays load lazily.

    Attributes:
        dataset: ``'vkitti1'``, ``'vkitti2'`` or ``'cityscapes'`` (selects the loaders).
        world: VKITTI world (``'0006'``, ``'Scene06'``) or Cityscapes city.
        variation: VKITTI variation (``'clone'``, ``'30-deg-right'``, ...) or Cityscapes split.
        frame: frame index within the sequence.
        intrinsics: camera intrinsics at the stored image size.
        rgb_path, semantic_path, instance_path, depth_path: files; None where the
            dataset has no such modality on disk.
        extrinsics: world->camera 4x4, row-major 16-tuple; None where absent.
            Use :meth:`extrinsics_matrix`.
        objects: the frame's annotated objects.
        camera: VKITTI 2 camera (``'Camera_0'``/``'Camera_1'``); None elsewhere.
        sequence: Cityscapes sequence number; None elsewhere.
        aux: named auxiliary files the loaders need (class/colour tables, track info).
    """

    dataset: str
    world: str
    variation: str
    frame: int
    intrinsics: Intrinsics
    rgb_path: Path
    semantic_path: Path | None = None
    instance_path: Path | None = None
    depth_path: Path | None = None
    extrinsics: tuple[float, ...] | None = None
    objects: tuple[ObjectAnnotation, ...] = ()
    camera: str | None = None
    sequence: int | None = None
    aux: tuple[tuple[str, Path], ...] = field(default=())

    def __post_init__(self) -> None:
        if self.dataset not in _READER_MODULES:
            known = sorted(_READER_MODULES)
            raise ValueError(f"FrameRecord.dataset must be one of {known}, got {self.dataset!r}")
        if self.extrinsics is not None and len(self.extrinsics) != 16:
            raise ValueError(f"FrameRecord.extrinsics must hold 16 values, got {len(self.extrinsics)}")

    @property
    def key(self) -> str:
        """A unique, human-readable id, e.g. ``vkitti1/0006/30-deg-right/00043``."""
        parts = [self.dataset, self.world, self.variation]
        if self.camera is not None:
            parts.append(self.camera)
        if self.sequence is not None:
            parts.append(f"{self.sequence:06d}")
        parts.append(f"{self.frame:06d}" if self.dataset == "cityscapes" else f"{self.frame:05d}")
        return "/".join(parts)

    def extrinsics_matrix(self) -> np.ndarray | None:
        """World->camera ``(4, 4)`` float64 matrix, or None."""
        if self.extrinsics is None:
            return None
        return np.asarray(self.extrinsics, dtype=np.float64).reshape(4, 4)

    def aux_path(self, name: str) -> Path:
        for key, path in self.aux:
            if key == name:
                return path
        raise KeyError(f"{self.key}: no auxiliary file {name!r} (have {[k for k, _ in self.aux]})")


def mesh_name_for(obj: ObjectAnnotation) -> str:
    """Template drawn for ``obj``: the template ``obj.model`` names, or the approximating template of the
    held-out vehicle shape it names (synthetic ``vehicles: heldout`` data, :mod:`sdn3d.meshes.vehicle_family`;
    mesh accuracy there means "picked the approximating template"), else by type."""
    template = approximating_template(obj.model)
    if template is not None:
        return template
    label = obj.orig_label if obj.label == "DontCare" and obj.orig_label else obj.label
    return "van" if label == "Van" else "sedan"


def visible_pixel_counts(instances: np.ndarray) -> dict[int, int]:
    """Pixel count of every non-zero instance id in an ``(H, W)`` instance map."""
    ids, counts = np.unique(np.asarray(instances), return_counts=True)
    keep = ids != 0
    return {int(i): int(c) for i, c in zip(ids[keep], counts[keep], strict=True)}


def check_dims(dims: tuple[float, float, float], label: str, where: str) -> None:
    """Raise naming ``where`` (``file:line``) unless the object's ``dims = (l, h, w)`` are all positive.

    The one exception is KITTI's ``DontCare`` convention, all three ``-1`` (no 3D box): such an object
    passes (its location is then far behind the camera, which the datasets' ``z > 0`` tests drop).
    """
    if all(d > 0 for d in dims) or (label == "DontCare" and all(d == -1 for d in dims)):
        return
    length, height, width = dims
    raise DataFormatError(f"{where}: object dimensions must be positive, got length {length:g}, height "
                          f"{height:g}, width {width:g} ({label})")


def check_size(array: np.ndarray, record: FrameRecord, path: Path | None) -> np.ndarray:
    """Raise if ``array`` does not have the record's image size.

    The record's size is the one its sequence's frames agree on (:func:`~sdn3d.data.imageio.agreed_size`,
    decided when the dataset is indexed), so the file named here is the odd one.
    """
    expected = record.intrinsics.size
    if tuple(array.shape[:2]) != expected:
        raise DataFormatError(
            f"{path}: image is {array.shape[1]}x{array.shape[0]}, expected {expected[1]}x{expected[0]} "
            f"(the size of {record.key}'s intrinsics)"
        )
    return array


def _reader(record: FrameRecord):
    return importlib.import_module(_READER_MODULES[record.dataset])


def load_rgb(record: FrameRecord) -> np.ndarray:
    """``(H, W, 3)`` uint8 image of ``record``."""
    return _reader(record).load_rgb(record)


def load_semantic(record: FrameRecord) -> np.ndarray:
    """``(H, W)`` int64 class indices of ``record`` in its dataset's class list."""
    return _reader(record).load_semantic(record)


def load_instances(record: FrameRecord) -> np.ndarray:
    """``(H, W)`` int64 instance ids ``class_id * 1000 + k`` (0 = none)."""
    return _reader(record).load_instances(record)


def load_depth(record: FrameRecord) -> np.ndarray:
    """``(H, W)`` float32 depth in metres along the camera z axis."""
    return _reader(record).load_depth(record)
