"""SceneCode: the de-rendered, editable representation of one image (3D-SDN, Sec. 3.4).

A scene is a *background layer* plus *objects*:

- ``semantic`` ``(H, W)`` int64: class indices of the class list ``classes`` (``'vkitti'`` or
  ``'cityscapes'``; 255 = ignore), objects' pixels included as the semantic branch saw them.
  Edits that move or delete an observed object relabel the pixels it leaves
  (:func:`sdn3d.editing.apply.apply_edits`), so this map is always the background the objects are drawn on.
- ``objects``: an :class:`ObjectTable`, the objects stacked into batched tensors. Per object:
  instance id ``class_id * 1000 + k``, template id (index into
  :data:`~sdn3d.meshes.templates.TEMPLATE_NAMES`, ``-1`` = no geometry), FFD ``phi (64, 3)``,
  ``dims (l, h, w)``, yaw ``ry``, ``location`` = KITTI bottom-face centre ``(x3d, y3d, z3d)``,
  texture ``code (C,)`` (C = 5 in the paper), an optional 2D ``mask`` and ``observed``.
  ``observed`` means "the object is where the image shows it": ``semantic`` holds its pixels, and
  a mask, if any, is its visible footprint. Objects without geometry must have a mask.
- ``background_codes`` ``(num_classes, C)``: one texture code per semantic class.

Storage (:func:`sdn3d.scene.io.save_scene` / :func:`~sdn3d.scene.io.load_scene`):
``<name>.json`` (format tag ``sdn3d-scene``, version, intrinsics, per-object scalars as exact float64
reprs) and ``<name>.npz`` (semantic map, phi, codes, masks; its SHA-256 is recorded in the JSON), both
written atomically. Loading is lossless and checks every field.
"""

from __future__ import annotations

import dataclasses
import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import torch
from torch import Tensor

from sdn3d.errors import UserInputError
from sdn3d.labels import (
    CLASS_LISTS,
    IGNORE_INDEX,
    INSTANCE_DIVISOR,
    SemanticClass,
)
from sdn3d.math3d.camera import Intrinsics
from sdn3d.math3d.ffd import FFD_NUM_POINTS
from sdn3d.math3d.transforms import bottom_to_center

__all__ = [
    "SCENE_FORMAT",
    "SCENE_VERSION",
    "DEFAULT_CODE_DIM",
    "SceneFormatError",
    "SceneObject",
    "ObjectTable",
    "SceneCode",
]

SCENE_FORMAT = "sdn3d-scene"
SCENE_VERSION = 1
#: Texture code size of the paper's encoder.
DEFAULT_CODE_DIM = 5
_TABLE_FIELDS = ("instance_id", "template_id", "phi", "dims", "ry", "location", "code", "mask", "has_mask", "observed")


class SceneFormatError(UserInputError):
    """A scene file is missing, of another format or version, or has a bad field."""


def _as(value: Any, dtype: torch.dtype) -> Tensor:
    return torch.as_tensor(np.asarray(value) if not isinstance(value, Tensor) else value).to(dtype)


@dataclass(frozen=True)
class SceneObject:
    """One object, for building and inspecting scenes (:class:`ObjectTable` stores them stacked).

    ``phi``/``code`` default to zeros; ``template_id = -1`` means no geometry (then ``mask`` is required).
    """

    instance_id: int
    template_id: int = -1
    dims: tuple[float, float, float] = (1.0, 1.0, 1.0)
    ry: float = 0.0
    location: tuple[float, float, float] = (0.0, 0.0, 1.0)
    phi: Any = None
    code: Any = None
    mask: Any = None
    observed: bool = True

    @property
    def class_id(self) -> int:
        return int(self.instance_id) // INSTANCE_DIVISOR


@dataclass(frozen=True, eq=False)
class ObjectTable:
    """``N`` objects as batched tensors (see the module doc).

    Attributes:
        instance_id: ``(N,)`` int64, unique, ``class_id * 1000 + k`` (``k`` in [0, 999]).
        template_id: ``(N,)`` int64 mesh id, ``-1`` = no geometry.
        phi: ``(N, 64, 3)`` float32 FFD control displacements.
        dims: ``(N, 3)`` float64 ``(l, h, w)`` metres.
        ry: ``(N,)`` float64 yaw.
        location: ``(N, 3)`` float64 bottom-face centre (KITTI camera frame).
        code: ``(N, C)`` float32 texture codes.
        mask: ``(N, H, W)`` bool 2D masks (all False where ``has_mask`` is False).
        has_mask: ``(N,)`` bool.
        observed: ``(N,)`` bool, see the module doc.
    """

    instance_id: Tensor
    template_id: Tensor
    phi: Tensor
    dims: Tensor
    ry: Tensor
    location: Tensor
    code: Tensor
    mask: Tensor
    has_mask: Tensor
    observed: Tensor

    def __post_init__(self) -> None:
        n = self.instance_id.shape[0] if self.instance_id.dim() == 1 else -1
        shapes = {"instance_id": (n,), "template_id": (n,), "phi": (n, FFD_NUM_POINTS, 3), "dims": (n, 3),
                  "ry": (n,), "location": (n, 3), "has_mask": (n,), "observed": (n,)}
        for name, shape in shapes.items():
            if tuple(getattr(self, name).shape) != shape:
                raise ValueError(f"ObjectTable.{name} must have shape {shape}, got {tuple(getattr(self, name).shape)}")
        if self.code.dim() != 2 or self.code.shape[0] != n or self.mask.dim() != 3 or self.mask.shape[0] != n:
            raise ValueError(f"ObjectTable.code must be (N={n}, C) and mask (N, H, W), got "
                             f"{tuple(self.code.shape)} and {tuple(self.mask.shape)}")
        ids = self.instance_id
        if n and int(ids.min()) < INSTANCE_DIVISOR:
            raise ValueError(f"ObjectTable.instance_id must be class_id * 1000 + k, class_id >= 1, got {ids.tolist()}")
        if ids.unique().numel() != n:
            raise ValueError(f"ObjectTable.instance_id must be unique, got {ids.tolist()}")
        if n and int(self.template_id.min()) < -1:
            raise ValueError(f"ObjectTable.template_id must be >= -1, got {self.template_id.tolist()}")
        geo = self.has_geometry
        if bool((~geo & ~self.has_mask).any()):
            bad = ids[~geo & ~self.has_mask].tolist()
            raise ValueError(f"objects {bad} have neither geometry (template_id -1) nor a mask")
        pose = torch.cat([self.dims, self.location, self.ry[:, None]], 1)[geo]
        if not bool(torch.isfinite(pose).all()) or bool((self.dims[geo] <= 0).any()):
            raise ValueError("ObjectTable: objects with geometry need finite dims > 0, location and ry")
        if not (bool(torch.isfinite(self.phi).all()) and bool(torch.isfinite(self.code).all())):
            raise ValueError("ObjectTable.phi and code must be finite")

    @classmethod
    def empty(cls, height: int, width: int, code_dim: int = DEFAULT_CODE_DIM) -> ObjectTable:
        return cls.from_objects([], height, width, code_dim)

    @classmethod
    def from_objects(cls, objects: Sequence[SceneObject], height: int, width: int,
                     code_dim: int = DEFAULT_CODE_DIM) -> ObjectTable:
        """Stack :class:`SceneObject` s (masks must be ``(H, W)``)."""
        n = len(objects)

        def stack(values: list, shape: tuple[int, ...], dtype: torch.dtype) -> Tensor:
            out = torch.zeros((n, *shape), dtype=dtype)
            for i, value in enumerate(values):
                if value is not None:
                    value = _as(value, dtype)
                    if tuple(value.shape) != shape:
                        raise ValueError(f"object {objects[i].instance_id}: expected shape {shape}, "
                                         f"got {tuple(value.shape)}")
                    out[i] = value
            return out

        return cls(
            instance_id=torch.tensor([int(o.instance_id) for o in objects], dtype=torch.long),
            template_id=torch.tensor([int(o.template_id) for o in objects], dtype=torch.long),
            phi=stack([o.phi for o in objects], (FFD_NUM_POINTS, 3), torch.float32),
            dims=stack([o.dims for o in objects], (3,), torch.float64),
            ry=torch.tensor([float(o.ry) for o in objects], dtype=torch.float64),
            location=stack([o.location for o in objects], (3,), torch.float64),
            code=stack([o.code for o in objects], (code_dim,), torch.float32),
            mask=stack([o.mask for o in objects], (height, width), torch.bool),
            has_mask=torch.tensor([o.mask is not None for o in objects], dtype=torch.bool),
            observed=torch.tensor([bool(o.observed) for o in objects], dtype=torch.bool),
        )

    def __len__(self) -> int:
        return self.instance_id.shape[0]

    @property
    def class_id(self) -> Tensor:
        """``(N,)`` ``instance_id // 1000``."""
        return self.instance_id // INSTANCE_DIVISOR

    @property
    def has_geometry(self) -> Tensor:
        """``(N,)`` bool, ``template_id >= 0``."""
        return self.template_id >= 0

    @property
    def center(self) -> Tensor:
        """``(N, 3)`` box centres ``(x3d, y3d - h/2, z3d)``."""
        return bottom_to_center(self.location, self.dims[:, 1])

    def index_of(self, instance_id: int) -> int:
        """Row of ``instance_id``; ``KeyError`` if absent."""
        hit = (self.instance_id == int(instance_id)).nonzero()
        if hit.numel() == 0:
            raise KeyError(f"no object with instance id {instance_id} (have {self.instance_id.tolist()})")
        return int(hit[0, 0])

    def object(self, i: int) -> SceneObject:
        return SceneObject(int(self.instance_id[i]), int(self.template_id[i]), tuple(self.dims[i].tolist()),
                           float(self.ry[i]), tuple(self.location[i].tolist()), self.phi[i], self.code[i],
                           self.mask[i] if bool(self.has_mask[i]) else None, bool(self.observed[i]))

    def select(self, index: Tensor) -> ObjectTable:
        """Rows ``index`` (bool ``(N,)`` or long indices)."""
        return ObjectTable(**{name: getattr(self, name)[index] for name in _TABLE_FIELDS})

    def cat(self, other: ObjectTable) -> ObjectTable:
        return ObjectTable(**{n: torch.cat([getattr(self, n), getattr(other, n)]) for n in _TABLE_FIELDS})

    def replace(self, **changes: Tensor) -> ObjectTable:
        return dataclasses.replace(self, **changes)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, ObjectTable):
            return NotImplemented
        return all(torch.equal(getattr(self, n), getattr(other, n)) for n in _TABLE_FIELDS)

    __hash__ = None  # type: ignore[assignment]


def meta_json(meta: Mapping[str, Any]) -> dict:
    """``meta`` as plain JSON values, as scene files store it: a typed record in it (e.g. a box object's fit,
    :class:`sdn3d.box_objects.BoxFit`) is written by its ``to_json()``.

    Raises:
        TypeError: a value that is neither JSON nor has ``to_json()``.
    """
    def plain(value: Any) -> Any:
        if hasattr(value, "to_json"):
            return value.to_json()
        raise TypeError(f"SceneCode.meta: {type(value).__name__} is not JSON and has no to_json()")

    return json.loads(json.dumps(meta, default=plain))


@dataclass(frozen=True, eq=False)
class SceneCode:
    """One de-rendered image; see the module doc. Equality (``==``) is exact.

    Example:
        >>> import torch
        >>> from sdn3d.math3d.camera import Intrinsics
        >>> car = SceneObject(12001, template_id=0, dims=(4.0, 1.5, 1.8), ry=0.3, location=(0.0, 1.6, 12.0))
        >>> scene = SceneCode(Intrinsics(fx=60.0, fy=60.0, cx=31.5, cy=11.5, width=64, height=24),
        ...                   semantic=torch.zeros(24, 64, dtype=torch.long), classes="vkitti",
        ...                   objects=ObjectTable.from_objects([car], height=24, width=64), background_codes={})
        >>> len(scene.objects), scene.image_size, scene.code_dim, scene.background_codes.shape
        (1, (64, 24), 5, torch.Size([14, 5]))
        >>> scene.objects.center  # the box centre is half a height above the bottom-face location
        tensor([[ 0.0000,  0.8500, 12.0000]], dtype=torch.float64)
        >>> farther = scene.replace(objects=scene.objects.replace(location=scene.objects.location * 2))
        >>> farther == scene, farther.objects.location[0, 2].item()
        (False, 24.0)
    """

    intrinsics: Intrinsics
    semantic: Tensor
    classes: str
    objects: ObjectTable
    background_codes: Tensor
    meta: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.classes not in CLASS_LISTS:
            raise ValueError(f"SceneCode.classes must be one of {sorted(CLASS_LISTS)}, got {self.classes!r}")
        semantic = self.semantic
        if semantic.dim() != 2 or tuple(semantic.shape) != self.intrinsics.size:
            raise ValueError(f"SceneCode.semantic must be (H, W) = {self.intrinsics.size} (the intrinsics' size), "
                             f"got {tuple(semantic.shape)}")
        if semantic.is_floating_point():
            raise ValueError(f"SceneCode.semantic must hold integer class indices, got {semantic.dtype}")
        object.__setattr__(self, "semantic", semantic.long())
        num = len(self.class_list)
        bad = (semantic < 0) | ((semantic >= num) & (semantic != IGNORE_INDEX))
        if bool(bad.any()):
            raise ValueError(f"SceneCode.semantic has values outside [0, {num}) and {IGNORE_INDEX}: "
                             f"{semantic[bad].unique()[:10].tolist()}")
        codes = self.background_codes
        if isinstance(codes, Mapping):
            codes = self._codes_from_mapping(codes, num, self.objects.code.shape[1])
        codes = _as(codes, torch.float32)
        if tuple(codes.shape) != (num, self.objects.code.shape[1]):
            raise ValueError(f"SceneCode.background_codes must be (num_classes={num}, C={self.objects.code.shape[1]}), "
                             f"got {tuple(codes.shape)}")
        if not bool(torch.isfinite(codes).all()):
            raise ValueError("SceneCode.background_codes must be finite")
        object.__setattr__(self, "background_codes", codes)
        if tuple(self.objects.mask.shape[1:]) != self.intrinsics.size:
            raise ValueError(f"SceneCode.objects.mask must be (N, {self.intrinsics.size}), "
                             f"got {tuple(self.objects.mask.shape)}")
        cls = self.objects.class_id
        things = self.thing_classes
        if len(cls) and not bool(torch.isin(cls, things).all()):
            raise ValueError(f"SceneCode: instance ids {self.objects.instance_id[~torch.isin(cls, things)].tolist()} "
                             f"belong to classes without instances in {self.classes!r} (instance classes: "
                             f"{things.tolist()})")
        meta_json(self.meta)  # meta is stored as JSON: fail early, not at save time

    @staticmethod
    def _codes_from_mapping(codes: Mapping[int, Any], num: int, dim: int) -> Tensor:
        out = torch.zeros(num, dim)
        for key, value in codes.items():
            if not 0 <= int(key) < num:
                raise ValueError(f"SceneCode.background_codes: class {key} is outside [0, {num})")
            out[int(key)] = _as(value, torch.float32)
        return out

    # -- properties ---------------------------------------------------------------------------

    @property
    def image_size(self) -> tuple[int, int]:
        """``(W, H)``."""
        return (int(self.intrinsics.width), int(self.intrinsics.height))

    @property
    def class_list(self) -> tuple[SemanticClass, ...]:
        return CLASS_LISTS[self.classes]

    @property
    def thing_classes(self) -> Tensor:
        """``(T,)`` ids of the classes that have instances (e.g. Car, Van)."""
        return torch.tensor([c.id for c in self.class_list if c.has_instances], dtype=torch.long)

    @property
    def code_dim(self) -> int:
        return int(self.objects.code.shape[1])

    def replace(self, **changes: Any) -> SceneCode:
        return dataclasses.replace(self, **changes)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, SceneCode):
            return NotImplemented
        return (self.intrinsics == other.intrinsics and self.classes == other.classes and self.meta == other.meta
                and torch.equal(self.semantic, other.semantic) and self.objects == other.objects
                and torch.equal(self.background_codes, other.background_codes))

    __hash__ = None  # type: ignore[assignment]
