"""A user's own image at the working size: its camera, and an aspect-preserving fit.

:func:`camera_for_image` never guesses: an image of Virtual KITTI's aspect ratio gets the Virtual KITTI
camera resized, any other needs its intrinsics. :func:`fit_transform` resizes when the aspect ratios
agree and otherwise scales to cover the working size and crops centrally (no invented pixels);
:func:`fit_image` applies it to the image and its intrinsics. The transform
(:class:`~sdn3d.editing.frame.PixelFrame`) also maps the user's pixel coordinates.
"""

from __future__ import annotations

import numpy as np
from torch import Tensor

from sdn3d.editing.frame import PixelFrame
from sdn3d.errors import InputError
from sdn3d.image_ops import resize_image, to_image_tensor
from sdn3d.math3d.camera import VKITTI_INTRINSICS, Intrinsics

__all__ = ["ASPECT_TOLERANCE", "same_aspect", "camera_for_image", "fit_transform", "fit_image"]

#: How far (relative) an image's aspect ratio may be from another's and still count as the same camera
#: resized: Virtual KITTI's 1242x375 (3.312) and the paper's 624x192 working size (3.25) are 1.9 % apart.
ASPECT_TOLERANCE = 0.02


def same_aspect(a: tuple[int, int], b: tuple[int, int]) -> bool:
    return abs((a[0] / a[1]) / (b[0] / b[1]) - 1) <= ASPECT_TOLERANCE


def camera_for_image(width: int, height: int, given: Intrinsics | None = None) -> tuple[Intrinsics, str]:
    """``(Intrinsics at the image's size, where they came from)``: ``given`` (checked against the size),
    else the Virtual KITTI camera for an image of its aspect ratio (within :data:`ASPECT_TOLERANCE`); any
    other image is refused rather than guessed.

    Raises:
        InputError: ``given`` is for another size, or the image's camera is unknown (the message says
            what to pass).
    """
    if given is not None:
        if (given.width, given.height) != (width, height):
            raise InputError(f"input.intrinsics are for {given.width}x{given.height} but the image is "
                             f"{width}x{height}")
        return given, "given"
    vkitti = (VKITTI_INTRINSICS.width, VKITTI_INTRINSICS.height)
    if same_aspect((width, height), vkitti):
        return VKITTI_INTRINSICS.resized(width, height), "the Virtual KITTI camera (the image has its aspect ratio)"
    raise InputError(
        f"input.image is {width}x{height}, not Virtual KITTI's {vkitti[0]}x{vkitti[1]} (or that aspect ratio), so "
        f"its camera is unknown: give input.intrinsics={{fx: F, fy: F, cx: CX, cy: CY}} (pixels of the "
        f"{width}x{height} image) or input.camera=<Cityscapes camera.json>")


def fit_transform(size: tuple[int, int], image_size: tuple[int, int]) -> PixelFrame:
    """The input -> working transform (:class:`~sdn3d.editing.frame.PixelFrame`): a plain resize when the
    aspect ratios agree (within :data:`ASPECT_TOLERANCE`), else scale to cover the working size keeping the
    aspect ratio and crop the excess centrally (no invented pixels)."""
    if same_aspect(image_size, size):
        return PixelFrame(tuple(image_size), tuple(size))
    scale = max(size[0] / image_size[0], size[1] / image_size[1])
    scaled = (max(size[0], round(image_size[0] * scale)), max(size[1], round(image_size[1] * scale)))
    return PixelFrame(tuple(image_size), tuple(size), scaled, ((scaled[0] - size[0]) // 2, (scaled[1] - size[1]) // 2))


def fit_image(rgb: np.ndarray, intrinsics: Intrinsics, size: tuple[int, int]) -> tuple[Tensor, Intrinsics, PixelFrame]:
    """``(image (3, H, W) float in [0, 1], intrinsics, transform)`` of an ``(h, w, 3)`` uint8 image at the
    working ``size = (W, H)`` (:func:`fit_transform`); the intrinsics follow the resize and the crop."""
    height, width = rgb.shape[:2]
    frame = fit_transform(size, (width, height))
    scaled = frame.scaled_size or size
    image = resize_image(to_image_tensor(rgb), scaled)
    left, top = frame.offset
    image = image[:, top:top + size[1], left:left + size[0]]
    intrinsics = intrinsics.resized(*scaled)
    if not frame.is_plain_resize:
        intrinsics = intrinsics.cropped(left, top, *size)
    return image, intrinsics, frame
