"""Batched training augmentation of the semantic branch (as in the DRN code: random crop, horizontal flip;
plus an optional photometric jitter).

Done on the batch (on the training device) rather than in the dataset, so the shared
:class:`~sdn3d.data.datasets.SemanticDataset` stays deterministic and the crop is one gather.
"""

from __future__ import annotations

import torch
from torch import Tensor

__all__ = ["color_jitter", "crop_size_for", "random_crop_flip"]


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


def color_jitter(image: Tensor, strength: float, generator: torch.Generator | None = None) -> Tensor:
    """Random brightness, contrast and saturation per sample, each a factor in ``[1 - strength, 1 + strength]``.

    Why: the synthetic worlds are seen under a few lights (clone, fog, ...); jitter keeps the network
    from keying classes on exact colours. Labels are unchanged, so only the image is returned.

    Args:
        image: ``(B, 3, H, W)`` in [0, 1].
        strength: in [0, 1); 0 returns ``image`` unchanged.
        generator: random generator (default: torch's global one).

    Returns:
        ``(B, 3, H, W)`` in [0, 1].
    """
    if not 0.0 <= strength < 1.0:
        raise ValueError(f"color jitter strength must be in [0, 1), got {strength}")
    if image.dim() != 4 or image.shape[1] != 3:
        raise ValueError(f"image must be (B, 3, H, W), got {tuple(image.shape)}")
    if strength == 0.0:
        return image
    b = image.shape[0]
    factors = (1.0 + strength * (2.0 * torch.rand(3, b, 1, 1, 1, generator=generator) - 1.0)).to(image)
    brightness, contrast, saturation = factors
    out = image * brightness
    gray = (0.299 * out[:, 0:1] + 0.587 * out[:, 1:2] + 0.114 * out[:, 2:3])  # (B, 1, H, W)
    out = (out - gray.mean(dim=(2, 3), keepdim=True)) * contrast + gray.mean(dim=(2, 3), keepdim=True)
    gray = (0.299 * out[:, 0:1] + 0.587 * out[:, 1:2] + 0.114 * out[:, 2:3])
    out = (out - gray) * saturation + gray
    return out.clamp(0.0, 1.0)
