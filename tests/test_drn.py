"""DRN backbones (DRN-D-22, DRN-C-26) and the segmentation network DRNSeg."""

from __future__ import annotations

import pytest
import torch

from sdn3d.nets.drn import DRN_ARCHS, DRNSeg, build_drn, drn_c_26, drn_d_22
from sdn3d.nets.weights import PretrainedWeightsError


def _params(module: torch.nn.Module) -> int:
    return sum(p.numel() for p in module.parameters())


def test_published_parameter_counts():
    # The DRN paper / model zoo: DRN-D-22 16.4 M and DRN-C-26 21.1 M parameters (ImageNet classifier included).
    assert _params(drn_d_22(num_classes=1000)) == pytest.approx(16.4e6, rel=5e-3)
    assert _params(drn_c_26(num_classes=1000)) == pytest.approx(21.1e6, rel=5e-3)


def test_torchvision_style_names():
    d = drn_d_22().state_dict()
    c = drn_c_26(num_classes=1000).state_dict()
    # DRN-D: convolutional stem and conv levels 1, 2, 7, 8; residual levels 3-6 with ResNet block names.
    for key in ("layer0.0.weight", "layer0.1.running_var", "layer2.0.weight", "layer3.0.conv1.weight",
                "layer3.0.downsample.0.weight", "layer3.0.downsample.1.running_mean", "layer6.1.bn2.weight",
                "layer8.0.weight"):
        assert key in d, key
    assert not any(k.startswith("fc.") for k in d)
    # DRN-C: ResNet stem (conv1/bn1) and blocks everywhere, classifier `fc` as a 1x1 convolution.
    for key in ("conv1.weight", "bn1.weight", "layer1.0.conv1.weight", "layer2.0.downsample.0.weight",
                "layer7.0.conv2.weight", "layer8.0.bn2.running_var", "fc.weight", "fc.bias"):
        assert key in c, key
    assert c["fc.weight"].shape == (1000, 512, 1, 1)


@pytest.mark.parametrize("arch", sorted(DRN_ARCHS))
def test_strides_channels_and_dilations(arch):
    net = build_drn(arch).eval()
    x = torch.rand(1, 3, 40, 72)
    with torch.no_grad():
        stages = net.stages(x)
        assert net(x).shape == (1, 512, 5, 9)
    assert [tuple(s.shape[-2:]) for s in stages] == [(40, 72), (20, 36), (10, 18), (5, 9)] + [(5, 9)] * 4
    assert [s.shape[1] for s in stages] == [16, 32, 64, 128, 256, 512, 512, 512]
    # Dilated levels keep the resolution: dilation 2 in level 5, 4 in level 6, then 2 and 1 (degridding).
    assert net.layer5[0].conv1.dilation == (2, 2) and net.layer5[1].conv2.dilation == (2, 2)
    assert net.layer6[0].conv1.dilation == (4, 4)
    if arch == "drn_c_26":
        assert net.layer7[0].conv1.dilation == (2, 2) and not net.layer7[0].residual
        assert net.layer8[0].conv1.dilation == (1, 1) and not net.layer8[0].residual
    else:
        assert net.layer7[0].dilation == (2, 2) and net.layer8[0].dilation == (1, 1)


def test_imagenet_classifier_output():
    net = drn_d_22(num_classes=10).eval()
    with torch.no_grad():
        assert net(torch.rand(2, 3, 32, 32)).shape == (2, 10)


def test_bad_arguments():
    with pytest.raises(ValueError, match="arch"):
        build_drn("drn_x_99")
    with pytest.raises(ValueError, match="num_classes"):
        DRNSeg(0)
    with pytest.raises(ValueError, match=r"\(B, 3, H, W\)"):
        DRNSeg(3, instance_head=False)(torch.rand(1, 1, 16, 16))


def test_drnseg_full_resolution_outputs_any_size():
    net = DRNSeg(5, head_channels=32).eval()
    with torch.no_grad():
        out = net(torch.rand(2, 3, 45, 70))
    assert out["logits"].shape == (2, 5, 45, 70)
    assert out["center"].shape == (2, 1, 45, 70) and out["offset"].shape == (2, 2, 45, 70)
    torch.testing.assert_close(out["center"], out["center_logits"].sigmoid())
    # The instance head starts at "no centre anywhere" (heatmap ~0.01, below the grouping threshold)
    # and near-zero offsets, so its losses start small.
    assert out["center"].max() < 0.05 and out["offset"].abs().max() < 1.0
    plain = DRNSeg(5, instance_head=False).eval()
    with torch.no_grad():
        assert set(plain(torch.rand(1, 3, 16, 24))) == {"logits"}


def test_drnseg_eval_is_per_sample_and_gradients_reach_the_stem():
    torch.manual_seed(0)
    net = DRNSeg(3, head_channels=32).eval()
    x = torch.rand(3, 3, 32, 48)
    with torch.no_grad():
        together = net(x)
        alone = net(x[1:2])
    for key in ("logits", "center_logits", "offset"):
        torch.testing.assert_close(together[key][1:2], alone[key], atol=1e-4, rtol=1e-4)
    net.train()
    out = net(x)
    (out["logits"].mean() + out["center"].mean() + out["offset"].mean()).backward()
    assert net.backbone.layer0[0].weight.grad.abs().sum() > 0
    assert net.instance.skip[0].weight.grad.abs().sum() > 0  # the stride-4 skip feeds the instance head


def test_pretrained_backbone_from_local_file(tmp_path):
    source = drn_d_22(num_classes=1000)
    path = tmp_path / "drn_d_22.pth"
    torch.save(source.state_dict(), path)
    net = DRNSeg(4, pretrained=str(path))
    for key, value in net.backbone.state_dict().items():
        torch.testing.assert_close(value, source.state_dict()[key])
    torch.save(drn_c_26(num_classes=1000).state_dict(), tmp_path / "c26.pth")
    with pytest.raises(PretrainedWeightsError, match="does not match"):
        DRNSeg(4, pretrained=str(tmp_path / "c26.pth"))


def test_skip_decoder_predicts_at_full_resolution_and_every_skip_gets_gradient():
    torch.manual_seed(0)
    slim = (8, 16, 16, 32, 32, 32, 32, 32)
    net = DRNSeg(4, instance_head=False, channels=slim, decoder="skip", decoder_channels=(16, 8, 8))
    x = torch.rand(2, 3, 37, 53)  # odd sizes: each step upsamples to its skip's exact size
    out = net(x)["logits"]
    assert out.shape == (2, 4, 37, 53)
    out.square().mean().backward()
    for proj in net.decoder.skips:  # strides 4, 2 and 1 all feed the prediction
        assert proj[0].weight.grad.abs().sum() > 0
    # A one-pixel change of the input changes the skip decoder's logits near it far more than the
    # bilinear head's: the stride-1 path carries fine detail the stride-8 head smooths away.
    net.eval()
    bilinear = DRNSeg(4, instance_head=False, channels=slim).eval()
    base = torch.full((1, 3, 32, 32), 0.5)
    poked = base.clone()
    poked[0, :, 16, 16] = 1.0

    def local_change(model: DRNSeg) -> float:
        with torch.no_grad():
            d = (model(poked)["logits"] - model(base)["logits"]).abs().sum(1)[0]
        return float(d[16, 16] / d.mean())

    assert local_change(net) > 2 * local_change(bilinear)


def test_skip_decoder_gradcheck():
    torch.manual_seed(0)
    from sdn3d.nets.drn import SkipDecoder

    dec = SkipDecoder(6, (4, 3), (5, 4)).double().eval()
    deep = torch.rand(1, 6, 3, 4, dtype=torch.double, requires_grad=True)
    skips = (torch.rand(1, 4, 5, 7, dtype=torch.double, requires_grad=True),
             torch.rand(1, 3, 9, 13, dtype=torch.double, requires_grad=True))
    assert dec(deep, skips).shape == (1, 4, 9, 13)
    assert torch.autograd.gradcheck(lambda d, a, b: dec(d, (a, b)), (deep, *skips))


def test_decoder_arguments_are_checked():
    with pytest.raises(ValueError, match="decoder"):
        DRNSeg(3, decoder="fpn")
    from sdn3d.nets.drn import SkipDecoder

    with pytest.raises(ValueError, match="same, non-zero length"):
        SkipDecoder(8, (4, 4), (8,))
