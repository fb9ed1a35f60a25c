"""Dilated Residual Networks (Yu, Koltun, Funkhouser, CVPR 2017) and the segmentation network on top.

- :class:`DRN`: the backbone, ``arch='D'`` (DRN-D: conv stem, no residual degridding layers) or
  ``arch='C'`` (DRN-C: ResNet-like stem, non-residual degridding blocks). Output stride 8,
  512 channels. Parameter names follow the authors' code (``layer0`` ... ``layer8``, ``fc``),
  which are torchvision's ResNet names where the structure is shared (``conv1``, ``bn1``,
  ``layerN.i.conv1``, ``layerN.i.downsample.0`` ...), so the published ImageNet checkpoints
  (or a torchvision-style state dict) load with :func:`sdn3d.nets.weights.load_pretrained`.
- :func:`drn_d_22` (the 3D-SDN default) and :func:`drn_c_26`.
- :class:`DRNSeg`: backbone + 1x1 classifier + bilinear upsampling to the input size (the paper's
  ``decoder='bilinear'``) or a light skip decoder (``decoder='skip'``, :class:`SkipDecoder`) that
  refines the stride-8 features with the stride-4, 2 and 1 backbone features before the classifier;
  and an optional Panoptic-DeepLab style instance head (centre heatmap + offsets, see
  :mod:`sdn3d.semantic.panoptic`) on the stride-8 and stride-4 features.

Inputs are images in [0, 1]; ``DRNSeg`` normalises them with the ImageNet statistics
(the DRN ImageNet weights expect that) so callers never have to.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import torch
import torch.nn.functional as F
from torch import Tensor, nn

from sdn3d.nets.weights import load_pretrained

__all__ = ["BasicBlock", "DRN", "DRNSeg", "DECODERS", "InstanceHead", "SkipDecoder", "drn_d_22", "drn_c_26",
           "DRN_ARCHS", "build_drn"]

#: ImageNet statistics used by the DRN ImageNet models.
IMAGENET_MEAN = (0.485, 0.456, 0.406)
IMAGENET_STD = (0.229, 0.224, 0.225)
_CHANNELS = (16, 32, 64, 128, 256, 512, 512, 512)


def _conv3x3(inplanes: int, planes: int, stride: int = 1, dilation: int = 1) -> nn.Conv2d:
    return nn.Conv2d(inplanes, planes, 3, stride=stride, padding=dilation, dilation=dilation, bias=False)


class BasicBlock(nn.Module):
    """ResNet basic block with per-conv dilation; ``residual=False`` gives DRN-C's degridding blocks."""

    expansion = 1

    def __init__(
        self,
        inplanes: int,
        planes: int,
        stride: int = 1,
        downsample: nn.Module | None = None,
        dilation: tuple[int, int] = (1, 1),
        residual: bool = True,
    ) -> None:
        super().__init__()
        self.conv1 = _conv3x3(inplanes, planes, stride, dilation[0])
        self.bn1 = nn.BatchNorm2d(planes)
        self.relu = nn.ReLU(inplace=True)
        self.conv2 = _conv3x3(planes, planes, 1, dilation[1])
        self.bn2 = nn.BatchNorm2d(planes)
        self.downsample = downsample
        self.residual = residual

    def forward(self, x: Tensor) -> Tensor:
        out = self.relu(self.bn1(self.conv1(x)))
        out = self.bn2(self.conv2(out))
        if self.residual:
            out = out + (x if self.downsample is None else self.downsample(x))
        return self.relu(out)


class DRN(nn.Module):
    """DRN backbone (stride 8). ``forward`` returns the 512-channel stride-8 features, or ImageNet
    logits ``(B, num_classes)`` when ``num_classes > 0`` (the ``fc`` layer of the published checkpoints).

    Args:
        layers: blocks (C) / convs (D) per level, 8 entries (DRN-22/26: ``(1, 1, 2, 2, 2, 2, 1, 1)``).
        arch: ``'C'`` or ``'D'``.
        channels: channels per level.
        num_classes: ImageNet classifier width; 0 = no classifier (segmentation use).
    """

    def __init__(
        self,
        layers: Sequence[int] = (1, 1, 2, 2, 2, 2, 1, 1),
        arch: str = "D",
        channels: Sequence[int] = _CHANNELS,
        num_classes: int = 0,
    ) -> None:
        super().__init__()
        if arch not in ("C", "D"):
            raise ValueError(f"DRN arch must be 'C' or 'D', got {arch!r}")
        if len(layers) != 8 or len(channels) != 8:
            raise ValueError(f"DRN layers and channels need 8 entries, got {len(layers)} and {len(channels)}")
        self.arch = arch
        self.channels = tuple(int(c) for c in channels)
        self.out_dim = self.channels[-1]
        self.inplanes = self.channels[0]
        c = self.channels
        if arch == "C":
            self.conv1 = nn.Conv2d(3, c[0], 7, stride=1, padding=3, bias=False)
            self.bn1 = nn.BatchNorm2d(c[0])
            self.relu = nn.ReLU(inplace=True)
            self.layer1 = self._make_layer(c[0], layers[0], stride=1)
            self.layer2 = self._make_layer(c[1], layers[1], stride=2)
        else:
            self.layer0 = nn.Sequential(nn.Conv2d(3, c[0], 7, stride=1, padding=3, bias=False),
                                        nn.BatchNorm2d(c[0]), nn.ReLU(inplace=True))
            self.layer1 = self._make_conv_layers(c[0], layers[0], stride=1)
            self.layer2 = self._make_conv_layers(c[1], layers[1], stride=2)
        self.layer3 = self._make_layer(c[2], layers[2], stride=2)
        self.layer4 = self._make_layer(c[3], layers[3], stride=2)
        self.layer5 = self._make_layer(c[4], layers[4], dilation=2, new_level=False)
        self.layer6 = None if layers[5] == 0 else self._make_layer(c[5], layers[5], dilation=4, new_level=False)
        if arch == "C":
            self.layer7 = None if layers[6] == 0 else self._make_layer(
                c[6], layers[6], dilation=2, new_level=False, residual=False)
            self.layer8 = None if layers[7] == 0 else self._make_layer(
                c[7], layers[7], dilation=1, new_level=False, residual=False)
        else:
            self.layer7 = None if layers[6] == 0 else self._make_conv_layers(c[6], layers[6], dilation=2)
            self.layer8 = None if layers[7] == 0 else self._make_conv_layers(c[7], layers[7], dilation=1)
        self.fc = nn.Conv2d(self.out_dim, num_classes, 1) if num_classes > 0 else None
        _init_weights(self)

    def _make_layer(self, planes: int, blocks: int, stride: int = 1, dilation: int = 1,
                    new_level: bool = True, residual: bool = True) -> nn.Sequential:
        downsample = None
        if stride != 1 or self.inplanes != planes:
            downsample = nn.Sequential(nn.Conv2d(self.inplanes, planes, 1, stride=stride, bias=False),
                                       nn.BatchNorm2d(planes))
        # A new dilation level starts at half the dilation in its first conv (as in the authors' code).
        first = (1, 1) if dilation == 1 else (dilation // 2 if new_level else dilation, dilation)
        modules = [BasicBlock(self.inplanes, planes, stride, downsample, dilation=first, residual=residual)]
        self.inplanes = planes
        modules += [BasicBlock(planes, planes, dilation=(dilation, dilation), residual=residual)
                    for _ in range(1, blocks)]
        return nn.Sequential(*modules)

    def _make_conv_layers(self, channels: int, convs: int, stride: int = 1, dilation: int = 1) -> nn.Sequential:
        modules: list[nn.Module] = []
        for i in range(convs):
            modules += [nn.Conv2d(self.inplanes, channels, 3, stride=stride if i == 0 else 1, padding=dilation,
                                  dilation=dilation, bias=False),
                        nn.BatchNorm2d(channels), nn.ReLU(inplace=True)]
            self.inplanes = channels
        return nn.Sequential(*modules)

    def stages(self, x: Tensor) -> list[Tensor]:
        """Outputs of ``layer1`` ... ``layer8`` for ``x`` ``(B, 3, H, W)`` (normalised).

        Strides 1, 2, 4, 8, 8, 8, 8, 8; channels ``self.channels``.
        """
        if self.arch == "C":
            x = self.relu(self.bn1(self.conv1(x)))
        else:
            x = self.layer0(x)
        out = []
        for layer in (self.layer1, self.layer2, self.layer3, self.layer4, self.layer5, self.layer6,
                      self.layer7, self.layer8):
            if layer is not None:
                x = layer(x)
            out.append(x)
        return out

    def forward(self, x: Tensor) -> Tensor:
        """``(B, 512, ceil(H/8), ceil(W/8))`` features, or ``(B, num_classes)`` ImageNet logits."""
        x = self.stages(x)[-1]
        if self.fc is not None:
            return self.fc(F.adaptive_avg_pool2d(x, 1)).flatten(1)
        return x


def _init_weights(module: nn.Module) -> None:
    # He initialisation as in the authors' code: N(0, sqrt(2 / (k*k*out_channels))).
    for m in module.modules():
        if isinstance(m, nn.Conv2d):
            n = m.kernel_size[0] * m.kernel_size[1] * m.out_channels
            m.weight.data.normal_(0.0, math.sqrt(2.0 / n))
            if m.bias is not None:
                m.bias.data.zero_()
        elif isinstance(m, nn.BatchNorm2d):
            m.weight.data.fill_(1.0)
            m.bias.data.zero_()


def drn_d_22(num_classes: int = 0, channels: Sequence[int] = _CHANNELS) -> DRN:
    """DRN-D-22 (the 3D-SDN semantic backbone)."""
    return DRN((1, 1, 2, 2, 2, 2, 1, 1), arch="D", channels=channels, num_classes=num_classes)


def drn_c_26(num_classes: int = 0, channels: Sequence[int] = _CHANNELS) -> DRN:
    """DRN-C-26."""
    return DRN((1, 1, 2, 2, 2, 2, 1, 1), arch="C", channels=channels, num_classes=num_classes)


DRN_ARCHS = {"drn_d_22": drn_d_22, "drn_c_26": drn_c_26}


def build_drn(arch: str, num_classes: int = 0, channels: Sequence[int] = _CHANNELS) -> DRN:
    """The backbone named ``arch`` (a key of :data:`DRN_ARCHS`)."""
    if arch not in DRN_ARCHS:
        raise ValueError(f"arch must be one of {sorted(DRN_ARCHS)}, got {arch!r}")
    return DRN_ARCHS[arch](num_classes=num_classes, channels=channels)


def _conv_bn_relu(cin: int, cout: int, k: int) -> nn.Sequential:
    return nn.Sequential(nn.Conv2d(cin, cout, k, padding=k // 2, bias=False), nn.BatchNorm2d(cout),
                         nn.ReLU(inplace=True))


class InstanceHead(nn.Module):
    """Panoptic-DeepLab style centre / offset head at stride 4.

    The stride-8 features are reduced, upsampled x2 and fused with projected stride-4 features
    (small cars are only a few stride-8 cells wide); two 1x1 predictors give the centre heatmap
    (1 channel, logits of a heatmap in [0, 1]) and the offset to the instance centre (2 channels,
    ``(du, dv)`` in input pixels, predicted in units of ``offset_scale`` pixels).
    """

    def __init__(self, in_channels: int, skip_channels: int, channels: int = 128, skip_proj: int = 32,
                 offset_scale: float = 8.0) -> None:
        super().__init__()
        self.offset_scale = float(offset_scale)
        self.reduce = _conv_bn_relu(in_channels, channels, 1)
        self.skip = _conv_bn_relu(skip_channels, skip_proj, 1)
        self.fuse = _conv_bn_relu(channels + skip_proj, channels, 3)
        self.center = nn.Sequential(_conv_bn_relu(channels, channels // 4, 3), nn.Conv2d(channels // 4, 1, 1))
        self.offset = nn.Sequential(_conv_bn_relu(channels, channels // 4, 3), nn.Conv2d(channels // 4, 2, 1))
        _init_weights(self)
        # Start near "no centre anywhere" (sigmoid 0.01, the focal-loss prior init) and near-zero offsets, so
        # the first steps do not swamp the segmentation loss.
        for predictor, bias in ((self.center[-1], math.log(0.01 / 0.99)), (self.offset[-1], 0.0)):
            nn.init.normal_(predictor.weight, std=1e-3)
            nn.init.constant_(predictor.bias, bias)

    def forward(self, deep: Tensor, skip: Tensor) -> tuple[Tensor, Tensor]:
        """``deep`` ``(B, C8, h8, w8)``, ``skip`` ``(B, C4, h4, w4)`` -> centre logits ``(B, 1, h4, w4)``,
        offsets ``(B, 2, h4, w4)``."""
        x = F.interpolate(self.reduce(deep), size=skip.shape[-2:], mode="bilinear", align_corners=False)
        x = self.fuse(torch.cat([x, self.skip(skip)], dim=1))
        # Offsets are tens of pixels: the predictor works in units of `offset_scale` pixels (the output
        # stride), else plain SGD takes thousands of steps to grow them from the near-zero init.
        return self.center(x), self.offset(x) * self.offset_scale


class SkipDecoder(nn.Module):
    """U-Net style refinement from stride 8 to stride 1 with the backbone's own skip features.

    Why: bilinear upsampling of stride-8 logits cannot draw structures a few pixels wide. On the
    synthetic test split at 624x192, even ideal stride-8 class scores upsampled bilinearly reach only
    ~0.80 mIoU (poles, traffic signs and lights vanish); stride 4 reaches ~0.91 and stride 2 ~0.96
    (``benchmarks/semantic.py ceiling``). Each step upsamples x2, concatenates a 1x1 projection of
    the skip features and applies a 3x3 conv; the widths shrink with the resolution, so the
    full-resolution step stays cheap next to the backbone.

    Args:
        in_channels: channels of the stride-8 features.
        skip_channels: channels of the skip features, finest last (e.g. strides 4, 2, 1).
        channels: decoder width after each step (same length as ``skip_channels``).
    """

    def __init__(self, in_channels: int, skip_channels: Sequence[int], channels: Sequence[int] = (64, 32, 16)) -> None:
        super().__init__()
        if len(skip_channels) != len(channels) or not channels:
            raise ValueError(f"skip_channels and channels need the same, non-zero length, got "
                             f"{list(skip_channels)} and {list(channels)}")
        self.reduce = _conv_bn_relu(in_channels, channels[0], 1)
        widths = [channels[0], *channels]
        self.skips = nn.ModuleList(_conv_bn_relu(c, max(w // 2, 8), 1)
                                   for c, w in zip(skip_channels, channels, strict=True))
        self.fuse = nn.ModuleList(_conv_bn_relu(widths[i] + max(channels[i] // 2, 8), channels[i], 3)
                                  for i in range(len(channels)))
        self.out_channels = int(channels[-1])
        _init_weights(self)

    def forward(self, deep: Tensor, skips: Sequence[Tensor]) -> Tensor:
        """``deep`` ``(B, C8, h8, w8)``, ``skips`` coarse to fine ``(B, Ci, hi, wi)`` -> ``(B, out_channels, h, w)``
        at the finest skip's size."""
        x = self.reduce(deep)
        for skip, proj, fuse in zip(skips, self.skips, self.fuse, strict=True):
            x = F.interpolate(x, size=skip.shape[-2:], mode="bilinear", align_corners=False)
            x = fuse(torch.cat([x, proj(skip)], dim=1))
        return x


#: ``DRNSeg(decoder=...)``: the paper's bilinear upsampling of stride-8 logits, or :class:`SkipDecoder`.
DECODERS = ("bilinear", "skip")


class DRNSeg(nn.Module):
    """Semantic segmentation DRN (+ optional instance head), images in [0, 1] in, full-size maps out.

    Args:
        num_classes: semantic classes (logit channels).
        arch: backbone, a key of :data:`DRN_ARCHS` (default ``'drn_d_22'``).
        instance_head: add the centre / offset head.
        head_channels: width of the instance head.
        pretrained: optional local ImageNet checkpoint of the backbone (DRN / torchvision names;
            its ``fc.`` classifier is dropped); None keeps the random initialisation.
        channels: backbone channels per level (the published models use the default).
        decoder: ``'bilinear'`` (the paper: 1x1 classifier on the stride-8 features, bilinear upsampling)
            or ``'skip'`` (:class:`SkipDecoder` to full resolution, then the classifier).
        decoder_channels: widths of the skip decoder at strides 4, 2, 1.
    """

    def __init__(
        self,
        num_classes: int,
        arch: str = "drn_d_22",
        instance_head: bool = True,
        head_channels: int = 128,
        pretrained: str | None = None,
        channels: Sequence[int] = _CHANNELS,
        decoder: str = "bilinear",
        decoder_channels: Sequence[int] = (64, 32, 16),
    ) -> None:
        super().__init__()
        if num_classes <= 0:
            raise ValueError(f"num_classes must be positive, got {num_classes}")
        if decoder not in DECODERS:
            raise ValueError(f"decoder must be one of {DECODERS}, got {decoder!r}")
        self.num_classes = int(num_classes)
        self.arch = arch
        self.backbone = build_drn(arch, num_classes=0, channels=channels)
        if pretrained:  # None stays silent here: a predictor fills the weights from its checkpoint next
            load_pretrained(self.backbone, pretrained, what=f"{arch} backbone", ignore_prefixes=("fc.",))
        c = self.backbone.channels
        self.decoder = (SkipDecoder(self.backbone.out_dim, (c[2], c[1], c[0]), decoder_channels)
                        if decoder == "skip" else None)
        self.seg = nn.Conv2d(self.backbone.out_dim if self.decoder is None else self.decoder.out_channels,
                             num_classes, 1)
        n = self.seg.kernel_size[0] * self.seg.kernel_size[1] * self.seg.out_channels
        self.seg.weight.data.normal_(0.0, math.sqrt(2.0 / n))
        self.seg.bias.data.zero_()
        self.instance = (InstanceHead(self.backbone.out_dim, self.backbone.channels[2], head_channels)
                         if instance_head else None)
        self.register_buffer("mean", torch.tensor(IMAGENET_MEAN).view(1, 3, 1, 1), persistent=False)
        self.register_buffer("std", torch.tensor(IMAGENET_STD).view(1, 3, 1, 1), persistent=False)

    def forward(self, image: Tensor) -> dict[str, Tensor]:
        """``image`` ``(B, 3, H, W)`` in [0, 1] -> ``{'logits': (B, C, H, W)}``, plus with the instance head
        ``'center_logits'`` and ``'center'`` (its sigmoid, the heatmap) ``(B, 1, H, W)`` and ``'offset'``
        ``(B, 2, H, W)`` (pixels, ``(du, dv)``)."""
        if image.dim() != 4 or image.shape[1] != 3:
            raise ValueError(f"image must be (B, 3, H, W), got {tuple(image.shape)}")
        size = image.shape[-2:]
        stages = self.backbone.stages((image - self.mean) / self.std)
        if self.decoder is None:
            # Bilinear upsampling of the stride-8 logits (the authors' fixed bilinear deconvolution, for any size).
            logits = F.interpolate(self.seg(stages[-1]), size=size, mode="bilinear", align_corners=False)
        else:
            logits = self.seg(self.decoder(stages[-1], (stages[2], stages[1], stages[0])))
        out = {"logits": logits}
        if self.instance is not None:
            center, offset = self.instance(stages[-1], stages[2])
            out["center_logits"] = F.interpolate(center, size=size, mode="bilinear", align_corners=False)
            out["center"] = out["center_logits"].sigmoid()
            out["offset"] = F.interpolate(offset, size=size, mode="bilinear", align_corners=False)
        return out
