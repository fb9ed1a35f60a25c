"""The edit operations of :mod:`sdn3d.editing.apply`: small frozen dataclasses that validate their arguments.

Each names its object by instance id; :mod:`sdn3d.editing.apply` documents what each one does to a scene.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from sdn3d.errors import UserInputError

__all__ = ["EditError", "Move", "Zoom", "Rotate", "Modify", "Delete", "SetCode", "SetBackgroundCode", "Duplicate",
           "EditOp", "shown_point"]


class EditError(UserInputError):
    """An edit that cannot be applied (no such object, target outside the frame, bad numbers)."""


def _finite(value: float, what: str) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise EditError(f"{what} must be a number, got {value!r}") from None
    if not math.isfinite(value):
        raise EditError(f"{what} must be finite, got {value}")
    return value


def _uv(uv: Sequence[float], what: str) -> tuple[float, float]:
    if uv is None or len(uv) != 2:
        raise EditError(f"{what} must be a (u, v) pixel, got {uv!r}")
    return (_finite(uv[0], f"{what}.u"), _finite(uv[1], f"{what}.v"))


def shown_point(uv: Sequence[float]) -> list[float]:
    """A pixel ``(u, v)`` as the edit messages print it: ``[u, v]`` to one decimal.

    >>> shown_point((12.345, 6.0))
    [12.3, 6.0]
    """
    return [round(float(uv[0]), 1), round(float(uv[1]), 1)]


def _zoom(zoom: float, what: str) -> float:
    zoom = _finite(zoom, what)
    if zoom <= 0:
        raise EditError(f"{what} must be > 0, got {zoom}")
    return zoom


@dataclass(frozen=True)
class Move:
    instance_id: int
    uv: tuple[float, float]

    def __post_init__(self) -> None:
        object.__setattr__(self, "uv", _uv(self.uv, "Move.uv"))


@dataclass(frozen=True)
class Zoom:
    instance_id: int
    zoom: float
    on_ground: bool = False

    def __post_init__(self) -> None:
        object.__setattr__(self, "zoom", _zoom(self.zoom, "Zoom.zoom"))


@dataclass(frozen=True)
class Rotate:
    instance_id: int
    delta_ry: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "delta_ry", _finite(self.delta_ry, "Rotate.delta_ry"))


@dataclass(frozen=True)
class Modify:
    """Benchmark ``modify``; ``check_frame=False`` accepts a ``to_uv`` outside the image (the
    published benchmark has four such targets)."""

    instance_id: int
    to_uv: tuple[float, float] | None = None
    zoom: float = 1.0
    delta_ry: float = 0.0
    check_frame: bool = True

    def __post_init__(self) -> None:
        if self.to_uv is not None:
            object.__setattr__(self, "to_uv", _uv(self.to_uv, "Modify.to_uv"))
        object.__setattr__(self, "zoom", _zoom(self.zoom, "Modify.zoom"))
        object.__setattr__(self, "delta_ry", _finite(self.delta_ry, "Modify.delta_ry"))


@dataclass(frozen=True)
class Delete:
    instance_id: int


@dataclass(frozen=True)
class SetCode:
    """Give an object a texture ``code`` (what the generator draws); ``color``: the sRGB paint in [0, 1] a named
    colour asked for, which the photo appearance repaints the car's body with (:mod:`sdn3d.editing.photo`)."""

    instance_id: int
    code: tuple[float, ...]
    color: tuple[float, float, float] | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "code", tuple(_finite(c, "SetCode.code") for c in np.asarray(self.code).ravel()))
        if self.color is not None:
            color = tuple(_finite(c, "SetCode.color") for c in np.asarray(self.color).ravel())
            if len(color) != 3 or not all(0.0 <= c <= 1.0 for c in color):
                raise EditError(f"SetCode.color must be 3 sRGB values in [0, 1], got {self.color!r}")
            object.__setattr__(self, "color", color)


@dataclass(frozen=True)
class SetBackgroundCode:
    class_id: int
    code: tuple[float, ...]

    def __post_init__(self) -> None:
        code = tuple(_finite(c, "SetBackgroundCode.code") for c in np.asarray(self.code).ravel())
        object.__setattr__(self, "code", code)


@dataclass(frozen=True)
class Duplicate:
    """Copy an object (code, shape, yaw) to ``uv`` (as :class:`Move`); ``new_id`` None = next free ``k``."""

    instance_id: int
    uv: tuple[float, float]
    new_id: int | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "uv", _uv(self.uv, "Duplicate.uv"))


EditOp = Move | Zoom | Rotate | Modify | Delete | SetCode | SetBackgroundCode | Duplicate
