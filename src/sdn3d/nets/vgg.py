"""VGG-19 features and the pix2pixHD perceptual loss, with torchvision parameter names.

:class:`VGG19Features` keeps torchvision's ``vgg19().features`` layers 0..29 (up to relu5_1), so a
file saved from ``torchvision.models.vgg19(weights="IMAGENET1K_V1").state_dict()`` loads as is
(:func:`load_vgg19`; the unused deeper convs ``features.30/32/34`` and the ``classifier.`` are
dropped explicitly). Without a weights file the perceptual term is off: a random VGG is no
perceptual metric.
"""

from __future__ import annotations

import logging
from pathlib import Path

import torch
import torch.nn.functional as F
from torch import Tensor, nn

from sdn3d.nets.weights import load_pretrained

__all__ = ["VGG19Features", "VGGPerceptualLoss", "load_vgg19", "IMAGENET_MEAN", "IMAGENET_STD"]

log = logging.getLogger(__name__)

IMAGENET_MEAN = (0.485, 0.456, 0.406)
IMAGENET_STD = (0.229, 0.224, 0.225)
# torchvision's configuration "E" (VGG-19), truncated after conv5_1.
_CFG = (64, 64, "M", 128, 128, "M", 256, 256, 256, 256, "M", 512, 512, 512, 512, "M", 512)
#: Indices (in ``features``) of relu1_1, relu2_1, relu3_1, relu4_1, relu5_1.
TAPS = (1, 6, 11, 20, 29)
#: pix2pixHD's weights of those layers in the perceptual loss.
TAP_WEIGHTS = (1.0 / 32, 1.0 / 16, 1.0 / 8, 1.0 / 4, 1.0)
_UNUSED_PREFIXES = ("features.30.", "features.32.", "features.34.", "classifier.")


class VGG19Features(nn.Module):
    """VGG-19 conv layers up to relu5_1; ``forward`` returns the 5 tapped activations.

    Input: ``(B, 3, H, W)`` ImageNet-normalised RGB.
    """

    def __init__(self) -> None:
        super().__init__()
        layers: list[nn.Module] = []
        ch = 3
        for v in _CFG:
            if v == "M":
                layers.append(nn.MaxPool2d(2, 2))
            else:
                layers += [nn.Conv2d(ch, int(v), 3, padding=1), nn.ReLU(inplace=True)]
                ch = int(v)
        self.features = nn.Sequential(*layers)

    def forward(self, x: Tensor) -> list[Tensor]:
        out = []
        for i, layer in enumerate(self.features):
            x = layer(x)
            if i in TAPS:
                out.append(x)
        return out


def load_vgg19(path: str | Path | None) -> VGG19Features | None:
    """Frozen, eval-mode :class:`VGG19Features` from a torchvision VGG-19 state dict; None when ``path`` is None."""
    if path is None or str(path) == "":
        log.warning("VGG-19 perceptual loss is off: no weights file given (model.perceptual_weights=null)")
        return None
    net = VGG19Features()
    load_pretrained(net, path, what="VGG-19 (perceptual loss)", ignore_prefixes=_UNUSED_PREFIXES)
    return net.eval().requires_grad_(False)


class VGGPerceptualLoss(nn.Module):
    """pix2pixHD perceptual loss ``sum_i w_i |phi_i(pred) - phi_i(target)|_1`` on images in ``[0, 1]``.

    ``phi_i`` are relu1_1 .. relu5_1 of a frozen VGG-19, ``w = (1/32, 1/16, 1/8, 1/4, 1)``. Inputs are
    ImageNet-normalised first (pix2pixHD fed ``[-1, 1]`` images; normalising matches the weights).
    """

    def __init__(self, vgg: VGG19Features) -> None:
        super().__init__()
        self.vgg = vgg.eval().requires_grad_(False)
        self.register_buffer("mean", torch.tensor(IMAGENET_MEAN).view(1, 3, 1, 1), persistent=False)
        self.register_buffer("std", torch.tensor(IMAGENET_STD).view(1, 3, 1, 1), persistent=False)

    @classmethod
    def from_file(cls, path: str | Path | None) -> VGGPerceptualLoss | None:
        vgg = load_vgg19(path)
        return None if vgg is None else cls(vgg)

    def train(self, mode: bool = True) -> VGGPerceptualLoss:
        super().train(mode)
        self.vgg.eval()  # frozen feature extractor: never in training mode
        return self

    def forward(self, pred: Tensor, target: Tensor) -> Tensor:
        if pred.shape != target.shape or pred.dim() != 4 or pred.shape[1] != 3:
            raise ValueError(f"pred and target must both be (B, 3, H, W), got {tuple(pred.shape)} and "
                             f"{tuple(target.shape)}")
        x = (torch.cat([pred, target]) - self.mean) / self.std
        feats = self.vgg(x)
        total = pred.new_zeros(())
        for w, f in zip(TAP_WEIGHTS, feats, strict=True):
            fp, ft = f.chunk(2)
            total = total + w * F.l1_loss(fp, ft.detach())
        return total
