"""Perceptual loss with the project's own semantic DRN as the frozen feature extractor F.

pix2pixHD's perceptual term is ``sum_i w_i |F_i(fake) - F_i(real)|_1`` with F an ImageNet VGG-19
(:class:`sdn3d.nets.vgg.VGGPerceptualLoss`, from a local weights file). Where no ImageNet weights can be had,
the semantic branch's trained DRN (:class:`~sdn3d.nets.drn.DRNSeg`, the same network that de-renders the
image) is a feature extractor of street scenes: :class:`DRNPerceptualLoss` taps its backbone stages
``layer1, layer2, layer3, layer4, layer6`` (strides 1, 2, 4, 8, 8; channels 16 ... 512 for DRN-D-22), the
same progression as VGG's ``relu1_1 .. relu5_1``, with VGG's weights ``(1/32, 1/16, 1/8, 1/4, 1)``. Images are
normalised exactly as the DRN was trained (ImageNet mean / std on ``[0, 1]`` RGB, ``DRNSeg``'s own buffers);
the net stays frozen and in eval mode (its BatchNorm uses the running statistics).

Loading the semantic checkpoint is the caller's (``SemanticPredictor.from_checkpoint(path).net``, a
higher floor): this module only needs the network.
"""

from __future__ import annotations

from collections.abc import Sequence

import torch
import torch.nn.functional as F
from torch import Tensor, nn

from sdn3d.nets.drn import DRNSeg

__all__ = ["DRN_TAPS", "DRN_TAP_WEIGHTS", "DRNPerceptualLoss"]

#: Indices into :meth:`sdn3d.nets.drn.DRN.stages` (layer1 ... layer8) of the tapped features.
DRN_TAPS = (0, 1, 2, 3, 5)
#: Their weights (pix2pixHD's VGG weights, shallow to deep).
DRN_TAP_WEIGHTS = (1.0 / 32, 1.0 / 16, 1.0 / 8, 1.0 / 4, 1.0)


class DRNPerceptualLoss(nn.Module):
    """``sum_i w_i |F_i(pred) - F_i(target)|_1`` on images in ``[0, 1]``, F = a trained DRN's backbone stages.

    Args:
        net: a trained semantic :class:`DRNSeg` (frozen here; its classifier and heads are not used).
        taps: stage indices (0 = layer1 ... 7 = layer8); weights: one per tap.
    """

    def __init__(self, net: DRNSeg, taps: Sequence[int] = DRN_TAPS,
                 weights: Sequence[float] = DRN_TAP_WEIGHTS) -> None:
        super().__init__()
        if len(taps) != len(weights) or not taps or any(not 0 <= int(t) < 8 for t in taps):
            raise ValueError(f"taps must be stage indices in [0, 8) with one weight each, got {taps} and {weights}")
        self.net = net.eval().requires_grad_(False)
        self.taps = tuple(int(t) for t in taps)
        self.weights = tuple(float(w) for w in weights)

    def train(self, mode: bool = True) -> DRNPerceptualLoss:
        super().train(mode)
        self.net.eval()  # frozen feature extractor: BatchNorm keeps its running statistics
        return self

    def features(self, image: Tensor) -> list[Tensor]:
        """The tapped features of ``image (B, 3, H, W)`` in ``[0, 1]`` (normalised as the DRN was trained)."""
        stages = self.net.backbone.stages((image - self.net.mean) / self.net.std)
        return [stages[t] for t in self.taps]

    def forward(self, pred: Tensor, target: Tensor) -> Tensor:
        if pred.shape != target.shape or pred.dim() != 4 or pred.shape[1] != 3:
            raise ValueError(f"pred and target must both be (B, 3, H, W), got {tuple(pred.shape)} and "
                             f"{tuple(target.shape)}")
        both = self.features(torch.cat([pred, target]))
        total = pred.new_zeros(())
        for w, f in zip(self.weights, both, strict=True):
            fp, ft = f.chunk(2)
            total = total + w * F.l1_loss(fp, ft.detach())
        return total
