"""pix2pixHD networks of the textural branch: global generator G, multi-scale PatchGAN D, texture encoder E.

Architectures follow pix2pixHD (Wang et al., CVPR 2018) as used by 3D-SDN's textural branch:

- :class:`GlobalGenerator`: 7x7 conv, ``n_downsampling`` stride-2 convs, ``n_blocks`` residual
  blocks, as many transposed convs, 7x7 conv + tanh. Output in ``[-1, 1]``.
- :class:`MultiscaleDiscriminator`: ``num_d`` PatchGAN discriminators (``n_layers`` stride-2 4x4
  convs) on the input and its 2x average-pooled copies; every intermediate feature is returned
  for feature matching.
- :class:`TextureEncoder`: a small encoder-decoder followed by instance-wise average pooling
  (:func:`instance_mean`, a scatter-mean over ``(batch, id)`` keys): one ``code_dim`` vector per
  region of the instance label map ``L`` (objects and background classes).

:class:`TexturalSpec` fixes the channel layout of the generator input (semantic one-hot,
instance boundaries, texture-code map, pose map, normal map; the 3D inputs can be switched off
for the decoupling ablation) and builds the networks.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields
from typing import Any

import torch
import torch.nn.functional as F
from torch import Tensor, nn

__all__ = [
    "GlobalGenerator",
    "MultiscaleDiscriminator",
    "NLayerDiscriminator",
    "ResnetBlock",
    "TextureEncoder",
    "TexturalSpec",
    "feature_matching_loss",
    "init_weights",
    "instance_mean",
    "label_one_hot",
    "lsgan_loss",
    "region_index",
]

NORMS = ("instance", "batch")


def _norm(kind: str, channels: int) -> nn.Module:
    if kind == "instance":
        return nn.InstanceNorm2d(channels, affine=False)
    if kind == "batch":
        return nn.BatchNorm2d(channels, affine=True)
    raise ValueError(f"norm must be one of {NORMS}, got {kind!r}")


def init_weights(module: nn.Module, std: float = 0.02) -> None:
    """pix2pixHD initialisation: conv weights ~ N(0, std), batch-norm scales ~ N(1, std), biases 0."""
    for m in module.modules():
        if isinstance(m, (nn.Conv2d, nn.ConvTranspose2d)):
            nn.init.normal_(m.weight, 0.0, std)
            if m.bias is not None:
                nn.init.zeros_(m.bias)
        elif isinstance(m, nn.BatchNorm2d):
            nn.init.normal_(m.weight, 1.0, std)
            nn.init.zeros_(m.bias)


class ResnetBlock(nn.Module):
    """``x + conv-norm-relu-conv-norm(x)`` with reflection padding (channel count kept)."""

    def __init__(self, channels: int, norm: str = "instance") -> None:
        super().__init__()
        self.block = nn.Sequential(
            nn.ReflectionPad2d(1), nn.Conv2d(channels, channels, 3), _norm(norm, channels), nn.ReLU(True),
            nn.ReflectionPad2d(1), nn.Conv2d(channels, channels, 3), _norm(norm, channels),
        )

    def forward(self, x: Tensor) -> Tensor:
        return x + self.block(x)


def _encoder_decoder(in_ch: int, out_ch: int, ngf: int, n_down: int, n_blocks: int, norm: str) -> list[nn.Module]:
    layers: list[nn.Module] = [nn.ReflectionPad2d(3), nn.Conv2d(in_ch, ngf, 7), _norm(norm, ngf), nn.ReLU(True)]
    for i in range(n_down):
        c = ngf * 2**i
        layers += [nn.Conv2d(c, 2 * c, 3, stride=2, padding=1), _norm(norm, 2 * c), nn.ReLU(True)]
    layers += [ResnetBlock(ngf * 2**n_down, norm) for _ in range(n_blocks)]
    for i in range(n_down, 0, -1):
        c = ngf * 2**i
        layers += [nn.ConvTranspose2d(c, c // 2, 3, stride=2, padding=1, output_padding=1),
                   _norm(norm, c // 2), nn.ReLU(True)]
    layers += [nn.ReflectionPad2d(3), nn.Conv2d(ngf, out_ch, 7), nn.Tanh()]
    return layers


def _check_int(minimum: int, **values: int) -> None:
    for name, v in values.items():
        if isinstance(v, bool) or int(v) != v or v < minimum:
            raise ValueError(f"{name} must be an integer >= {minimum}, got {v!r}")


class _PaddedNet(nn.Module):
    """Pads the input (replicate, bottom/right) to a multiple of ``2**n_down`` and crops the output back."""

    n_down: int
    model: nn.Sequential

    def forward(self, x: Tensor) -> Tensor:
        if x.dim() != 4:
            raise ValueError(f"{type(self).__name__}: input must be (B, C, H, W), got {tuple(x.shape)}")
        h, w = x.shape[-2:]
        m = 2**self.n_down
        ph, pw = (-h) % m, (-w) % m
        if ph or pw:  # sizes like 312x96 with 4 downsamplings: pad instead of failing on odd feature maps
            x = F.pad(x, (0, pw, 0, ph), mode="replicate")
        return self.model(x)[..., :h, :w]


class GlobalGenerator(_PaddedNet):
    """pix2pixHD global generator ``(B, in_channels, H, W) -> (B, out_channels, H, W)`` in ``[-1, 1]``.

    Args:
        in_channels: input channels (see :attr:`TexturalSpec.generator_channels`).
        out_channels: 3 for RGB.
        ngf: filters of the first conv; the residual blocks have ``ngf * 2**n_downsampling``.
        n_downsampling: stride-2 convs (paper: 4). Inputs are padded to a multiple of ``2**n_downsampling``.
        n_blocks: residual blocks at the bottleneck (paper: 9).
        norm: ``'instance'`` (paper) or ``'batch'``.
    """

    def __init__(self, in_channels: int, out_channels: int = 3, ngf: int = 64, n_downsampling: int = 4,
                 n_blocks: int = 9, norm: str = "instance") -> None:
        super().__init__()
        _check_int(1, in_channels=in_channels, out_channels=out_channels, ngf=ngf)
        _check_int(0, n_downsampling=n_downsampling, n_blocks=n_blocks)
        self.n_down = n_downsampling
        self.model = nn.Sequential(*_encoder_decoder(in_channels, out_channels, ngf, n_downsampling, n_blocks, norm))
        init_weights(self)


class NLayerDiscriminator(nn.Module):
    """PatchGAN: ``n_layers`` stride-2 4x4 convs, one stride-1 conv, a 1-channel 4x4 conv.

    ``forward`` returns the ``n_layers + 2`` outputs of its stages; the last is the patch prediction.
    """

    def __init__(self, in_channels: int, ndf: int = 64, n_layers: int = 3, norm: str = "instance") -> None:
        super().__init__()
        _check_int(1, in_channels=in_channels, ndf=ndf, n_layers=n_layers)
        pad = math.ceil((4 - 1) / 2)
        stages: list[nn.Module] = [nn.Sequential(nn.Conv2d(in_channels, ndf, 4, 2, pad), nn.LeakyReLU(0.2, True))]
        nf = ndf
        for n in range(1, n_layers + 1):
            prev, nf = nf, min(nf * 2, 512)
            stride = 2 if n < n_layers else 1
            stages.append(nn.Sequential(nn.Conv2d(prev, nf, 4, stride, pad), _norm(norm, nf), nn.LeakyReLU(0.2, True)))
        stages.append(nn.Sequential(nn.Conv2d(nf, 1, 4, 1, pad)))
        self.stages = nn.ModuleList(stages)

    def forward(self, x: Tensor) -> list[Tensor]:
        out = []
        for stage in self.stages:
            x = stage(x)
            out.append(x)
        return out


class MultiscaleDiscriminator(nn.Module):
    """``num_d`` PatchGANs on the input and its 2x, 4x ... average-pooled copies.

    ``forward(x (B, C, H, W))`` returns one list of stage outputs per scale, full resolution
    first; ``out[i][-1]`` is scale ``i``'s patch prediction, ``out[i][:-1]`` its features.
    """

    def __init__(self, in_channels: int, ndf: int = 64, n_layers: int = 3, num_d: int = 2,
                 norm: str = "instance") -> None:
        super().__init__()
        if int(num_d) != num_d or num_d < 1:
            raise ValueError(f"num_d must be a positive integer, got {num_d!r}")
        self.scales = nn.ModuleList(NLayerDiscriminator(in_channels, ndf, n_layers, norm) for _ in range(num_d))
        self.n_layers = n_layers
        init_weights(self)

    def forward(self, x: Tensor) -> list[list[Tensor]]:
        if x.dim() != 4:
            raise ValueError(f"MultiscaleDiscriminator: input must be (B, C, H, W), got {tuple(x.shape)}")
        out = []
        for i, d in enumerate(self.scales):
            if i > 0:
                x = F.avg_pool2d(x, 3, stride=2, padding=1, count_include_pad=False)
            out.append(d(x))
        return out


def region_index(L: Tensor) -> tuple[Tensor, Tensor, Tensor]:
    """Compact ``(batch, id)`` keys of a label map: one region per distinct id of each image.

    Args:
        L: ``(B, H, W)`` non-negative integer map (instance label map).

    Returns:
        index: ``(B, H, W)`` long, the region of each pixel in ``[0, N)``.
        batch: ``(N,)`` image of each region; ids: ``(N,)`` its id. Sorted by (batch, id).
    """
    if L.dim() != 3 or L.dtype.is_floating_point:
        raise ValueError(f"L must be an integer map (B, H, W), got {tuple(L.shape)} {L.dtype}")
    L = L.long()
    if L.numel() and int(L.min()) < 0:
        raise ValueError("L must be non-negative (instance ids and semantic classes)")
    span = int(L.max()) + 1 if L.numel() else 1
    keys = torch.arange(L.shape[0], device=L.device).view(-1, 1, 1) * span + L
    uniq, index = torch.unique(keys, sorted=True, return_inverse=True)
    return index, torch.div(uniq, span, rounding_mode="floor"), uniq % span


def instance_mean(features: Tensor, L: Tensor) -> tuple[Tensor, Tensor, Tensor, Tensor]:
    """Instance-wise average pooling: the mean feature of every region of ``L`` (scatter-mean).

    Args:
        features: ``(B, C, H, W)``.
        L: ``(B, H, W)`` instance label map (same ``B, H, W``).

    Returns:
        pooled: ``(B, C, H, W)`` each pixel's region mean (differentiable w.r.t. ``features``).
        means: ``(N, C)`` region means; batch, ids: ``(N,)`` as :func:`region_index`.
    """
    if features.dim() != 4 or L.shape != (features.shape[0], *features.shape[2:]):
        raise ValueError(f"features (B, C, H, W) and L (B, H, W) must agree, got {tuple(features.shape)} "
                         f"and {tuple(L.shape)}")
    index, batch, ids = region_index(L)
    c = features.shape[1]
    flat_index = index.reshape(-1)
    # float32 sums: a sky region of a 624x192 frame has ~1e5 pixels, beyond float16's range under AMP
    flat = features.permute(0, 2, 3, 1).reshape(-1, c).float()
    sums = flat.new_zeros(batch.numel(), c).index_add_(0, flat_index, flat)
    counts = torch.bincount(flat_index, minlength=batch.numel()).clamp(min=1).to(flat.dtype)
    means = (sums / counts[:, None]).to(features.dtype)
    pooled = means[index].permute(0, 3, 1, 2)
    return pooled, means, batch, ids


class TextureEncoder(_PaddedNet):
    """Texture encoder E: image ``(B, 3, H, W)`` in ``[-1, 1]`` -> per-pixel features -> per-region means.

    Args:
        in_channels: 3 (RGB).
        code_dim: texture code size (paper: 5).
        nef: filters of the first conv (pix2pixHD: 16).
        n_downsampling: stride-2 convs (pix2pixHD: 4).
    """

    def __init__(self, in_channels: int = 3, code_dim: int = 5, nef: int = 16, n_downsampling: int = 4,
                 norm: str = "instance") -> None:
        super().__init__()
        _check_int(1, in_channels=in_channels, code_dim=code_dim, nef=nef)
        _check_int(0, n_downsampling=n_downsampling)
        self.n_down = n_downsampling
        self.code_dim = code_dim
        self.model = nn.Sequential(*_encoder_decoder(in_channels, code_dim, nef, n_downsampling, 0, norm))
        init_weights(self)

    def forward(self, image: Tensor, L: Tensor) -> Tensor:  # type: ignore[override]
        """``(B, code_dim, H, W)`` code map: every pixel carries its region's mean code."""
        return self.encode(image, L)[0]

    def encode(self, image: Tensor, L: Tensor) -> tuple[Tensor, Tensor, Tensor, Tensor]:
        """``(code_map, codes (N, code_dim), batch (N,), ids (N,))``, see :func:`instance_mean`."""
        return instance_mean(super().forward(image), L)


def label_one_hot(label: Tensor, num_classes: int) -> Tensor:
    """``(B, H, W)`` class map -> ``(B, num_classes, H, W)`` float one-hot; ids outside ``[0, K)`` (255) are all 0."""
    if label.dim() != 3:
        raise ValueError(f"label must be (B, H, W), got {tuple(label.shape)}")
    label = label.long()
    valid = (label >= 0) & (label < num_classes)
    onehot = F.one_hot(torch.where(valid, label, 0), num_classes).permute(0, 3, 1, 2).float()
    return onehot * valid[:, None]


def lsgan_loss(preds: list[list[Tensor]], real: bool) -> Tensor:
    """LSGAN loss summed over discriminator scales: ``sum_i mean((D_i - 1{real})^2)``."""
    return sum(F.mse_loss(p[-1], torch.full_like(p[-1], 1.0 if real else 0.0)) for p in preds)  # type: ignore[return-value]


def feature_matching_loss(fake: list[list[Tensor]], real: list[list[Tensor]]) -> Tensor:
    """pix2pixHD discriminator feature matching: L1 between intermediate features (real ones detached).

    Weighted as pix2pixHD: ``4 / (n_layers + 1)`` per feature, ``1 / num_d`` per scale.
    """
    if len(fake) != len(real):
        raise ValueError(f"fake and real must have one entry per scale, got {len(fake)} and {len(real)}")
    total = fake[0][0].new_zeros(())
    for f_scale, r_scale in zip(fake, real, strict=True):
        weight = 4.0 / (len(f_scale) - 1) / len(fake)  # stages = n_layers + 2, features = n_layers + 1
        for f, r in zip(f_scale[:-1], r_scale[:-1], strict=True):
            total = total + weight * F.l1_loss(f, r.detach())
    return total


@dataclass(frozen=True)
class TexturalSpec:
    """Channel layout of the generator input and sizes of the three networks.

    Generator input channels, in order: semantic one-hot (``num_classes``), instance boundary (1),
    texture-code map (``code_dim``, if ``use_codes``), pose map (``pose_bins``, if ``use_pose``),
    normal map (3, if ``use_normal``). The discriminator sees one-hot + boundary + image (as in
    3D-SDN's code: the 3D maps condition the generator only).
    """

    num_classes: int
    code_dim: int = 5
    pose_bins: int = 24
    use_codes: bool = True
    use_pose: bool = True
    use_normal: bool = True
    ngf: int = 64
    n_downsampling: int = 4
    n_blocks: int = 9
    nef: int = 16
    n_downsampling_encoder: int = 4
    ndf: int = 64
    n_layers_d: int = 3
    num_d: int = 2
    norm: str = "instance"

    def __post_init__(self) -> None:
        if int(self.num_classes) != self.num_classes or self.num_classes <= 0:
            raise ValueError(f"num_classes must be a positive integer, got {self.num_classes!r}")
        if self.norm not in NORMS:
            raise ValueError(f"norm must be one of {NORMS}, got {self.norm!r}")

    @classmethod
    def from_mapping(cls, values: Mapping[str, Any], **overrides: Any) -> TexturalSpec:
        """Pick this spec's fields out of ``values`` (e.g. a checkpoint's hyper-parameters)."""
        names = {f.name for f in fields(cls)}
        kwargs = {k: v for k, v in values.items() if k in names}
        kwargs.update(overrides)
        return cls(**kwargs)

    @property
    def generator_channels(self) -> int:
        return (self.num_classes + 1 + self.code_dim * self.use_codes + self.pose_bins * self.use_pose
                + 3 * self.use_normal)

    @property
    def condition_channels(self) -> int:
        """Channels of the discriminator's condition (one-hot + boundary)."""
        return self.num_classes + 1

    def generator(self) -> GlobalGenerator:
        return GlobalGenerator(self.generator_channels, 3, self.ngf, self.n_downsampling, self.n_blocks, self.norm)

    def encoder(self) -> TextureEncoder:
        return TextureEncoder(3, self.code_dim, self.nef, self.n_downsampling_encoder, self.norm)

    def discriminator(self) -> MultiscaleDiscriminator:
        return MultiscaleDiscriminator(self.condition_channels + 3, self.ndf, self.n_layers_d, self.num_d, self.norm)

    def condition(self, label: Tensor, boundary: Tensor) -> Tensor:
        """``(B, num_classes + 1, H, W)``: one-hot of ``label (B, H, W)`` and ``boundary (B, 1, H, W)``."""
        if boundary.dim() != 4 or boundary.shape[1] != 1 or boundary.shape[-2:] != label.shape[-2:]:
            raise ValueError(f"boundary must be (B, 1, H, W) matching label {tuple(label.shape)}, "
                             f"got {tuple(boundary.shape)}")
        return torch.cat([label_one_hot(label, self.num_classes), boundary.float()], 1)

    def generator_input(self, condition: Tensor, code_map: Tensor | None, pose: Tensor | None,
                        normal: Tensor | None) -> Tensor:
        """Concatenate the enabled maps: ``condition`` (from :meth:`condition`), ``code_map (B, code_dim, H, W)``,
        ``pose (B, pose_bins, H, W)``, ``normal (B, 3, H, W)``. Disabled inputs are ignored; enabled ones
        that are None are zeros (no code / no geometry)."""
        b, _, h, w = condition.shape
        parts = [condition]
        for used, name, value, ch in (("use_codes", "code_map", code_map, self.code_dim),
                                      ("use_pose", "pose", pose, self.pose_bins),
                                      ("use_normal", "normal", normal, 3)):
            if not getattr(self, used):
                continue
            if value is None:
                value = condition.new_zeros(b, ch, h, w)
            elif value.shape != (b, ch, h, w):
                raise ValueError(f"{name} must have shape {(b, ch, h, w)}, got {tuple(value.shape)}")
            parts.append(value.to(condition.dtype))
        return torch.cat(parts, 1)
