"""Test-time augmentation for :class:`~sdn3d.nets.drn.DRNSeg`: the image and its mirror image in one batch.

The mirror image's outputs are mirrored back and averaged with the plain ones: class probabilities
and centre heatmaps are averaged, and offsets too once their horizontal component ``du`` (which
changes sign under a left-right flip) is negated. The averaged ``'logits'`` are the log of the
averaged probabilities, so ``argmax`` and cross-entropy read them as any logits.
"""

from __future__ import annotations

from collections.abc import Callable

import torch
from torch import Tensor

__all__ = ["hflip_outputs", "flip_averaged_outputs"]

_EPS = 1e-6


def hflip_outputs(out: dict[str, Tensor]) -> dict[str, Tensor]:
    """Mirror network outputs left-right: every ``(B, C, H, W)`` map flipped along W, offsets' ``du`` negated."""
    flipped = {k: v.flip(-1) for k, v in out.items()}
    if "offset" in flipped:
        offset = flipped["offset"].clone()
        offset[:, 0] = -offset[:, 0]
        flipped["offset"] = offset
    return flipped


def flip_averaged_outputs(net: Callable[[Tensor], dict[str, Tensor]], image: Tensor) -> dict[str, Tensor]:
    """Outputs of ``net`` on ``image`` ``(B, 3, H, W)`` averaged with those on its mirror image.

    One forward pass on a batch of ``2B`` images. Returns the keys ``net`` returns: ``'logits'`` (log of the
    averaged softmax) ``(B, C, H, W)`` and, with an instance head, ``'center'`` (averaged heatmap),
    ``'center_logits'`` (its logit) ``(B, 1, H, W)`` and ``'offset'`` (averaged) ``(B, 2, H, W)``.
    """
    b = image.shape[0]
    both = net(torch.cat([image, image.flip(-1)]))
    plain = {k: v[:b] for k, v in both.items()}
    mirrored = hflip_outputs({k: v[b:] for k, v in both.items()})
    out = {"logits": ((plain["logits"].softmax(1) + mirrored["logits"].softmax(1)) / 2).clamp_min(_EPS).log()}
    if "center" in plain:
        center = (plain["center"] + mirrored["center"]) / 2
        out["center"] = center
        out["center_logits"] = torch.logit(center, eps=_EPS)
        out["offset"] = (plain["offset"] + mirrored["offset"]) / 2
    return out
