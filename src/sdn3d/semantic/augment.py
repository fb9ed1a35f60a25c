"""Batched training augmentation of the semantic branch (as in the DRN code: random crop, horizontal flip).

Done on the batch (on the training device) rather than in the dataset, so the shared
:class:`~sdn3d.data.datasets.SemanticDataset` stays deterministic and the crop is one gather.
"""

from __future__ import annotations

import torch
from torch import Tensor

__all__ = ["crop_size_for", "random_crop_flip"]


def crop_size_for(crop_size: int | tuple[int, int] | list[int] | None, height: int, width: int) -> tuple[int, int]:
    """``(h, w)`` of the training crop: ``crop_size`` (a square side or ``[W, H]``) clamped to the image;
    None = the whole image."""
    if crop_size is None:
        return height, width
    if isinstance(crop_size, int):
        cw = ch = crop_size
    elif len(crop_size) == 2:
        cw, ch = int(crop_size[0]), int(crop_size[1])
    else:
        raise ValueError(f"crop_size must be an int, [W, H] or None, got {crop_size!r}")
    if cw <= 0 or ch <= 0:
        raise ValueError(f"crop_size must be positive, got {crop_size!r}")
    return min(ch, height), min(cw, width)


def random_crop_flip(
    image: Tensor,
    maps: list[Tensor],
    crop_size: int | tuple[int, int] | list[int] | None = None,
    hflip: bool = True,
    generator: torch.Generator | None = None,
) -> tuple[Tensor, list[Tensor]]:
    """One random crop window and one coin flip per sample, applied alike to the image and the maps.

    Args:
        image: ``(B, C, H, W)``.
        maps: label-like maps ``(B, H, W)`` (semantic, instance ...), cropped without interpolation.
        crop_size: see :func:`crop_size_for`.
        hflip: mirror each sample left-right with probability 1/2.
        generator: random generator (default: torch's global one, seeded by ``seed_everything``).

    Returns:
        the image ``(B, C, h, w)`` and the maps ``(B, h, w)``.
    """
    b, _, height, width = image.shape
    for m in maps:
        if m.shape != (b, height, width):
            raise ValueError(f"maps must be (B, H, W) = {(b, height, width)}, got {tuple(m.shape)}")
    h, w = crop_size_for(crop_size, height, width)
    if (h, w) == (height, width) and not hflip:
        return image, maps
    device = image.device
    top = torch.randint(0, height - h + 1, (b,), generator=generator).to(device)
    left = torch.randint(0, width - w + 1, (b,), generator=generator).to(device)
    flip = (torch.rand(b, generator=generator) < 0.5).to(device) if hflip else torch.zeros(b, dtype=torch.bool,
                                                                                            device=device)
    rows = top[:, None] + torch.arange(h, device=device)  # (B, h)
    cols = left[:, None] + torch.arange(w, device=device)  # (B, w)
    cols = torch.where(flip[:, None], cols.flip(1), cols)
    bi = torch.arange(b, device=device)[:, None, None]
    ri, ci = rows[:, :, None], cols[:, None, :]
    # Advanced indices around a slice put the indexed dims first: (B, h, w, C).
    out = image[bi, :, ri, ci].permute(0, 3, 1, 2).contiguous()
    return out, [m[bi, ri, ci] for m in maps]
