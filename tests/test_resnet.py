"""ResNet with torchvision's parameter names: structure, parameter counts, strict local weight loading."""

from __future__ import annotations

import pytest
import torch

from sdn3d.nets.resnet import resnet18, resnet34, resnet50
from sdn3d.nets.weights import PretrainedWeightsError


def _count(net: torch.nn.Module) -> int:
    return sum(p.numel() for p in net.parameters())


def test_parameter_counts_match_torchvision():
    # torchvision.models.resnet18/34/50(): 11,689,512 / 21,797,672 / 25,557,032 parameters.
    assert _count(resnet18()) == 11_689_512
    assert _count(resnet34()) == 21_797_672
    assert _count(resnet50()) == 25_557_032


def test_state_dict_uses_torchvision_names():
    state = resnet18().state_dict()
    # torchvision's resnet18 state dict: 122 entries (62 parameters + 60 BN buffers).
    assert len(state) == 122
    expected = {
        "conv1.weight": (64, 3, 7, 7),
        "bn1.running_mean": (64,),
        "bn1.num_batches_tracked": (),
        "layer1.0.conv1.weight": (64, 64, 3, 3),
        "layer2.0.downsample.0.weight": (128, 64, 1, 1),
        "layer2.0.downsample.1.running_var": (128,),
        "layer4.1.bn2.weight": (512,),
        "fc.weight": (1000, 512),
        "fc.bias": (1000,),
    }
    for key, shape in expected.items():
        assert tuple(state[key].shape) == shape, key
    assert not any("downsample" in k for k in state if k.startswith("layer1."))  # no projection in stage 1


def test_trunk_without_classifier_returns_pooled_features():
    net = resnet18(num_classes=None).eval()
    assert not any(k.startswith("fc.") for k in net.state_dict())
    with torch.no_grad():
        feats = net(torch.rand(2, 3, 64, 64))
        maps = net.features(torch.rand(2, 3, 64, 64))
    assert feats.shape == (2, 512) and maps.shape == (2, 512, 2, 2)
    assert (feats >= 0).all()  # average of ReLU outputs


def test_pretrained_file_loads_strictly(tmp_path):
    source = resnet18()
    with torch.no_grad():
        source.layer3[1].conv2.weight.add_(1.0)  # something the random init of the target can not match
    path = tmp_path / "resnet18.pth"
    torch.save(source.state_dict(), path)

    trunk = resnet18(num_classes=None, pretrained=path)  # ImageNet file with fc: dropped for the trunk
    torch.testing.assert_close(trunk.layer3[1].conv2.weight, source.layer3[1].conv2.weight)
    full = resnet18(pretrained=path)
    torch.testing.assert_close(full.fc.weight, source.fc.weight)

    bad = {k: v for k, v in source.state_dict().items() if not k.startswith("layer4.")}
    torch.save(bad, tmp_path / "partial.pth")
    with pytest.raises(PretrainedWeightsError, match="missing keys"):
        resnet18(pretrained=tmp_path / "partial.pth")
    with pytest.raises(PretrainedWeightsError, match="shape mismatch"):
        resnet18(num_classes=None, pretrained=path, in_channels=4)


def test_bad_arguments_are_rejected():
    with pytest.raises(ValueError, match="num_classes"):
        resnet18(num_classes=0)
    with pytest.raises(ValueError, match=r"\(N, C, H, W\)"):
        resnet18()(torch.rand(3, 32, 32))
