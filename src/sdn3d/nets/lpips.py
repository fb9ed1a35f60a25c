"""LPIPS (Zhang et al., CVPR 2018), AlexNet variant, from one local weights file.

Parameter names: torchvision's AlexNet ``features.{0,3,6,8,10}.{weight,bias}`` plus the LPIPS
linear layers ``lin0..lin4`` under the names of the reference ``lpips`` package
(``lin{k}.model.1.weight``, a 1x1 conv without bias after a dropout). The file is thus the union
of ``torchvision.models.alexnet(weights=...).state_dict()`` (its ``classifier.`` is dropped) and
the package's ``weights/v0.1/alex.pth``; :func:`merge_lpips_weights` builds it from those two
files. Without a file LPIPS is off (no random "perceptual" distance).
"""

from __future__ import annotations

import logging
from pathlib import Path

import torch
import torch.nn.functional as F
from torch import Tensor, nn

from sdn3d.nets.weights import PretrainedWeightsError, load_pretrained, read_state_dict

__all__ = ["LPIPS", "MIN_SIDE", "load_lpips", "merge_lpips_weights"]

log = logging.getLogger(__name__)

_CHANNELS = (64, 192, 384, 256, 256)
#: Inputs whose shorter side is under this many pixels are upsampled (bilinear, both images) first.
MIN_SIDE = 32
#: Indices of the ReLUs after conv1..conv5 in torchvision's ``alexnet().features``.
_TAPS = (1, 4, 7, 9, 11)
# The LPIPS input scaling layer (constants of the reference implementation).
_SHIFT = (-0.030, -0.088, -0.188)
_SCALE = (0.458, 0.448, 0.450)


class _Lin(nn.Module):
    """One LPIPS linear layer: dropout then a 1x1 conv to one channel (reference package layout)."""

    def __init__(self, channels: int) -> None:
        super().__init__()
        self.model = nn.Sequential(nn.Dropout(), nn.Conv2d(channels, 1, 1, bias=False))

    def forward(self, x: Tensor) -> Tensor:
        return self.model(x)


class LPIPS(nn.Module):
    """LPIPS distance between images in ``[0, 1]`` (lower is more similar).

    ``forward(pred, target)`` -> ``(B,)``; ``forward(..., spatial=True)`` -> ``(B, 1, H, W)``
    per-pixel distances (each layer's map bilinearly upsampled), whose mean over a region gives
    a masked LPIPS. Images with a side under ``MIN_SIDE`` (32) px are upsampled bilinearly (both
    alike, aspect kept) before AlexNet, which cannot take less; spatial maps keep the input's size.
    """

    def __init__(self) -> None:
        super().__init__()
        self.features = nn.Sequential(
            nn.Conv2d(3, 64, 11, 4, 2), nn.ReLU(inplace=True), nn.MaxPool2d(3, 2),
            nn.Conv2d(64, 192, 5, padding=2), nn.ReLU(inplace=True), nn.MaxPool2d(3, 2),
            nn.Conv2d(192, 384, 3, padding=1), nn.ReLU(inplace=True),
            nn.Conv2d(384, 256, 3, padding=1), nn.ReLU(inplace=True),
            nn.Conv2d(256, 256, 3, padding=1), nn.ReLU(inplace=True),
        )
        for k, c in enumerate(_CHANNELS):
            self.add_module(f"lin{k}", _Lin(c))
        self.register_buffer("shift", torch.tensor(_SHIFT).view(1, 3, 1, 1), persistent=False)
        self.register_buffer("scale", torch.tensor(_SCALE).view(1, 3, 1, 1), persistent=False)
        self.eval().requires_grad_(False)

    def train(self, mode: bool = True) -> LPIPS:
        return super().train(False)  # a metric: dropout stays off

    def _taps(self, x: Tensor) -> list[Tensor]:
        out = []
        for i, layer in enumerate(self.features):
            x = layer(x)
            if i in _TAPS:
                out.append(x)
        return out

    def forward(self, pred: Tensor, target: Tensor, spatial: bool = False) -> Tensor:
        if pred.shape != target.shape or pred.dim() != 4 or pred.shape[1] != 3:
            raise ValueError(f"pred and target must both be (B, 3, H, W), got {tuple(pred.shape)} and "
                             f"{tuple(target.shape)}")
        x = ((torch.cat([pred, target]) * 2 - 1) - self.shift) / self.scale
        side = min(x.shape[-2:])
        if side < MIN_SIDE:  # AlexNet's strides and pools need this much input: upsample both images alike
            size = [max(MIN_SIDE, round(s * MIN_SIDE / side)) for s in x.shape[-2:]]
            x = F.interpolate(x, size=size, mode="bilinear", align_corners=False)
        maps = []
        for k, f in enumerate(self._taps(x)):
            f = f / (f.pow(2).sum(1, keepdim=True).sqrt() + 1e-10)
            fp, ft = f.chunk(2)
            d = getattr(self, f"lin{k}")((fp - ft) ** 2)
            if spatial:
                d = F.interpolate(d, size=pred.shape[-2:], mode="bilinear", align_corners=False)
            else:
                d = d.mean((2, 3), keepdim=True)
            maps.append(d)
        total = torch.stack(maps).sum(0)
        return total if spatial else total.view(-1)


def load_lpips(path: str | Path | None) -> LPIPS | None:
    """:class:`LPIPS` with weights from ``path`` (see module doc); None, with a warning, when ``path`` is None."""
    if path is None or str(path) == "":
        log.warning("LPIPS is off: no weights file given (lpips_weights=null)")
        return None
    net = LPIPS()
    load_pretrained(net, path, what="LPIPS (AlexNet + lin0..lin4)", ignore_prefixes=("classifier.",))
    return net.eval()


def merge_lpips_weights(alexnet: str | Path, lin: str | Path) -> dict[str, Tensor]:
    """One LPIPS state dict from a torchvision AlexNet file and the reference package's ``alex.pth``.

    Save the result with ``torch.save(merge_lpips_weights(a, b), 'lpips_alex.pth')``.
    """
    feats = {k: v for k, v in read_state_dict(alexnet).items() if k.startswith("features.")}
    lins = read_state_dict(lin)
    bad = [k for k in lins if not k.startswith("lin")]
    if bad:
        raise PretrainedWeightsError(f"{str(lin)!r} should hold only lin0..lin4 keys, found {bad[:3]}")
    return {**feats, **lins}
