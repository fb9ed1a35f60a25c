"""ResNet (He et al. 2016) with torchvision's parameter names, so torchvision checkpoints load as is.

``resnet18().state_dict()`` has exactly the keys and shapes of
``torchvision.models.resnet18().state_dict()`` (``conv1.weight``, ``bn1.running_mean``,
``layer1.0.conv1.weight``, ``layer2.0.downsample.0.weight``, ``fc.weight`` ...), and the same
initialisation (Kaiming normal, fan out, for convolutions; BN weight 1, bias 0). torchvision is
not imported: weights come from a local file through :func:`sdn3d.nets.weights.load_pretrained`.

``num_classes=None`` builds the trunk without the classifier (``fc`` is an identity with no
parameters), returning the ``(N, C)`` globally pooled features; load ImageNet weights into it
with ``ignore_prefixes=("fc.",)``.
"""

from __future__ import annotations

from pathlib import Path

from torch import Tensor, nn

from sdn3d.nets.weights import load_pretrained

__all__ = ["BasicBlock", "Bottleneck", "ResNet", "resnet18", "resnet34", "resnet50"]


def _conv3x3(in_planes: int, out_planes: int, stride: int = 1) -> nn.Conv2d:
    return nn.Conv2d(in_planes, out_planes, kernel_size=3, stride=stride, padding=1, bias=False)


def _conv1x1(in_planes: int, out_planes: int, stride: int = 1) -> nn.Conv2d:
    return nn.Conv2d(in_planes, out_planes, kernel_size=1, stride=stride, bias=False)


class BasicBlock(nn.Module):
    """Two 3x3 convolutions with a residual connection (ResNet-18/34)."""

    expansion = 1

    def __init__(self, inplanes: int, planes: int, stride: int = 1, downsample: nn.Module | None = None) -> None:
        super().__init__()
        self.conv1 = _conv3x3(inplanes, planes, stride)
        self.bn1 = nn.BatchNorm2d(planes)
        self.relu = nn.ReLU(inplace=True)
        self.conv2 = _conv3x3(planes, planes)
        self.bn2 = nn.BatchNorm2d(planes)
        self.downsample = downsample

    def forward(self, x: Tensor) -> Tensor:
        identity = x if self.downsample is None else self.downsample(x)
        out = self.relu(self.bn1(self.conv1(x)))
        out = self.bn2(self.conv2(out))
        return self.relu(out + identity)


class Bottleneck(nn.Module):
    """1x1 - 3x3 - 1x1 bottleneck with the stride on the 3x3 convolution (torchvision's "v1.5")."""

    expansion = 4

    def __init__(self, inplanes: int, planes: int, stride: int = 1, downsample: nn.Module | None = None) -> None:
        super().__init__()
        self.conv1 = _conv1x1(inplanes, planes)
        self.bn1 = nn.BatchNorm2d(planes)
        self.conv2 = _conv3x3(planes, planes, stride)
        self.bn2 = nn.BatchNorm2d(planes)
        self.conv3 = _conv1x1(planes, planes * self.expansion)
        self.bn3 = nn.BatchNorm2d(planes * self.expansion)
        self.relu = nn.ReLU(inplace=True)
        self.downsample = downsample

    def forward(self, x: Tensor) -> Tensor:
        identity = x if self.downsample is None else self.downsample(x)
        out = self.relu(self.bn1(self.conv1(x)))
        out = self.relu(self.bn2(self.conv2(out)))
        out = self.bn3(self.conv3(out))
        return self.relu(out + identity)


class ResNet(nn.Module):
    """ResNet trunk and optional classifier.

    Args:
        block: :class:`BasicBlock` or :class:`Bottleneck`.
        layers: blocks per stage, e.g. ``(2, 2, 2, 2)`` for ResNet-18.
        num_classes: classifier outputs; ``None`` drops the classifier (``forward`` returns the
            ``(N, 512 * block.expansion)`` pooled features).
        in_channels: input channels (3 for RGB; other values can not use ImageNet ``conv1``).
    """

    def __init__(
        self,
        block: type[BasicBlock] | type[Bottleneck],
        layers: tuple[int, int, int, int],
        num_classes: int | None = 1000,
        in_channels: int = 3,
    ) -> None:
        super().__init__()
        if len(layers) != 4 or any(n <= 0 for n in layers):
            raise ValueError(f"layers must be four positive block counts, got {layers}")
        if num_classes is not None and num_classes <= 0:
            raise ValueError(f"num_classes must be positive or None, got {num_classes}")
        self.inplanes = 64
        self.conv1 = nn.Conv2d(in_channels, 64, kernel_size=7, stride=2, padding=3, bias=False)
        self.bn1 = nn.BatchNorm2d(64)
        self.relu = nn.ReLU(inplace=True)
        self.maxpool = nn.MaxPool2d(kernel_size=3, stride=2, padding=1)
        self.layer1 = self._make_layer(block, 64, layers[0])
        self.layer2 = self._make_layer(block, 128, layers[1], stride=2)
        self.layer3 = self._make_layer(block, 256, layers[2], stride=2)
        self.layer4 = self._make_layer(block, 512, layers[3], stride=2)
        self.avgpool = nn.AdaptiveAvgPool2d(1)
        self.num_features = 512 * block.expansion
        self.fc: nn.Module = nn.Identity() if num_classes is None else nn.Linear(self.num_features, num_classes)
        for m in self.modules():
            if isinstance(m, nn.Conv2d):
                nn.init.kaiming_normal_(m.weight, mode="fan_out", nonlinearity="relu")
            elif isinstance(m, nn.BatchNorm2d):
                nn.init.constant_(m.weight, 1.0)
                nn.init.constant_(m.bias, 0.0)

    def _make_layer(self, block, planes: int, blocks: int, stride: int = 1) -> nn.Sequential:
        downsample = None
        if stride != 1 or self.inplanes != planes * block.expansion:
            downsample = nn.Sequential(
                _conv1x1(self.inplanes, planes * block.expansion, stride), nn.BatchNorm2d(planes * block.expansion)
            )
        layers = [block(self.inplanes, planes, stride, downsample)]
        self.inplanes = planes * block.expansion
        layers += [block(self.inplanes, planes) for _ in range(1, blocks)]
        return nn.Sequential(*layers)

    def features(self, x: Tensor) -> Tensor:
        """``(N, C_in, H, W)`` -> ``(N, C, H / 32, W / 32)`` last-stage feature maps."""
        x = self.maxpool(self.relu(self.bn1(self.conv1(x))))
        return self.layer4(self.layer3(self.layer2(self.layer1(x))))

    def forward(self, x: Tensor) -> Tensor:
        """``(N, C_in, H, W)`` -> logits ``(N, num_classes)``, or pooled features ``(N, C)`` without ``fc``."""
        if x.dim() != 4:
            raise ValueError(f"x must have shape (N, C, H, W), got {tuple(x.shape)}")
        return self.fc(self.avgpool(self.features(x)).flatten(1))


def _build(
    block, layers, num_classes: int | None, pretrained: str | Path | None, in_channels: int, what: str
) -> ResNet:
    net = ResNet(block, layers, num_classes=num_classes, in_channels=in_channels)
    if pretrained is not None:
        # ImageNet files carry the 1000-way classifier; a trunk without fc drops it explicitly.
        load_pretrained(net, pretrained, what=what, ignore_prefixes=("fc.",) if num_classes is None else ())
    return net


def resnet18(num_classes: int | None = 1000, pretrained: str | Path | None = None, in_channels: int = 3) -> ResNet:
    """ResNet-18; ``pretrained``: optional local torchvision-format weights file (strict load)."""
    return _build(BasicBlock, (2, 2, 2, 2), num_classes, pretrained, in_channels, "ResNet-18")


def resnet34(num_classes: int | None = 1000, pretrained: str | Path | None = None, in_channels: int = 3) -> ResNet:
    """ResNet-34; ``pretrained`` as in :func:`resnet18`."""
    return _build(BasicBlock, (3, 4, 6, 3), num_classes, pretrained, in_channels, "ResNet-34")


def resnet50(num_classes: int | None = 1000, pretrained: str | Path | None = None, in_channels: int = 3) -> ResNet:
    """ResNet-50 (bottleneck blocks); ``pretrained`` as in :func:`resnet18`."""
    return _build(Bottleneck, (3, 4, 6, 3), num_classes, pretrained, in_channels, "ResNet-50")
