"""pix2pixHD networks (G, multi-scale D, texture encoder E), the generator input layout and VGG-19."""

from __future__ import annotations

import logging

import pytest
import torch

from sdn3d.nets.pix2pixhd import (
    GlobalGenerator,
    MultiscaleDiscriminator,
    TexturalSpec,
    TextureEncoder,
    feature_matching_loss,
    instance_mean,
    label_one_hot,
    lsgan_loss,
    region_index,
)
from sdn3d.nets.vgg import TAPS, VGG19Features, VGGPerceptualLoss, load_vgg19
from sdn3d.nets.weights import PretrainedWeightsError


def _label_map() -> torch.Tensor:
    L = torch.zeros(2, 12, 20, dtype=torch.long)
    L[0, :6] = 1  # sky (class 1)
    L[0, 6:, :10] = 12001  # a car
    L[0, 6:, 10:] = 12002  # another car
    L[1, :, :5] = 5
    L[1, :, 5:] = 12001  # same id as image 0's car: a different region
    return L


def test_generator_shapes_range_and_padding():
    g = GlobalGenerator(7, 3, ngf=8, n_downsampling=3, n_blocks=2)
    for h, w in ((32, 64), (30, 50)):  # 30x50 is not a multiple of 8: padded then cropped
        y = g(torch.randn(2, 7, h, w))
        assert y.shape == (2, 3, h, w)
        assert y.abs().max() <= 1.0
    # the bottleneck has ngf * 2**n_downsampling channels, as pix2pixHD
    assert any(isinstance(m, torch.nn.Conv2d) and m.in_channels == 64 for m in g.modules())
    with pytest.raises(ValueError, match="ngf"):
        GlobalGenerator(7, 3, ngf=0)


def test_multiscale_discriminator_returns_features_per_scale():
    d = MultiscaleDiscriminator(5, ndf=8, n_layers=3, num_d=2)
    out = d(torch.randn(2, 5, 64, 96))
    assert len(out) == 2 and all(len(s) == 3 + 2 for s in out)
    assert out[0][-1].shape[1] == 1 and out[0][0].shape[1] == 8
    # scale 1 sees the 2x average-pooled input (3x3 window, pix2pixHD); full resolution comes first
    x = torch.randn(1, 5, 64, 96)
    pooled = torch.nn.functional.avg_pool2d(x, 3, stride=2, padding=1, count_include_pad=False)
    assert torch.allclose(d(x)[1][-1], d.scales[1](pooled)[-1])
    assert out[0][0].shape[-2:] == (33, 49) and out[1][0].shape[-2:] == (17, 25)
    assert lsgan_loss([[torch.ones(1, 1, 3, 3)]] * 2, True) == 0
    assert lsgan_loss([[torch.ones(1, 1, 3, 3)]] * 2, False) == pytest.approx(2.0)  # summed over scales


def test_feature_matching_weights():
    f = [[torch.zeros(1, 2, 4, 4)] * 4 + [torch.zeros(1, 1, 2, 2)] for _ in range(2)]
    r = [[torch.ones(1, 2, 4, 4)] * 4 + [torch.zeros(1, 1, 2, 2)] for _ in range(2)]
    # 4 features per scale (n_layers=3), weight 4 / 4 per feature, 1/2 per scale: total 4 * 1 = 4
    assert feature_matching_loss(f, r).item() == pytest.approx(4.0)
    assert feature_matching_loss(r, r).item() == 0.0
    fake = [[t.clone().requires_grad_() for t in s] for s in f]
    real = [[t.clone().requires_grad_() for t in s] for s in r]
    feature_matching_loss(fake, real).backward()
    assert fake[0][0].grad is not None and fake[0][-1].grad is None  # the prediction is not a feature
    assert all(t.grad is None for s in real for t in s)  # real features are targets (detached)


def test_region_index_and_instance_mean_match_loop_reference():
    L = _label_map()
    feats = torch.randn(2, 3, 12, 20, requires_grad=True)
    index, batch, ids = region_index(L)
    assert batch.tolist() == [0, 0, 0, 1, 1] and ids.tolist() == [1, 12001, 12002, 5, 12001]
    pooled, means, b2, i2 = instance_mean(feats, L)
    assert torch.equal(b2, batch) and torch.equal(i2, ids)
    for n, (b, k) in enumerate(zip(batch.tolist(), ids.tolist(), strict=True)):
        sel = L[b] == k
        ref = feats[b][:, sel].mean(1)
        assert torch.allclose(means[n], ref, atol=1e-6)
        assert torch.allclose(pooled[b][:, sel], ref[:, None].expand(-1, int(sel.sum())), atol=1e-6)
        assert torch.equal(index[b][sel], torch.full((int(sel.sum()),), n))
    # d(sum of pooled)/d(feature) = 1 for every pixel (each region's mean is broadcast to its pixels)
    pooled.sum().backward()
    assert torch.allclose(feats.grad, torch.ones_like(feats.grad), atol=1e-5)
    with pytest.raises(ValueError, match="non-negative"):
        region_index(L - 2)


def test_texture_encoder_gives_one_code_per_region():
    enc = TextureEncoder(3, code_dim=5, nef=4, n_downsampling=2)
    L = _label_map()
    code_map, codes, batch, ids = enc.encode(torch.rand(2, 3, 12, 20) * 2 - 1, L)
    assert code_map.shape == (2, 5, 12, 20) and codes.shape == (5, 5)
    # constant inside each region; the two images' "12001" regions have their own codes
    car0 = code_map[0][:, L[0] == 12001]
    assert torch.allclose(car0, car0[:, :1].expand_as(car0))
    assert not torch.allclose(code_map[0, :, 11, 0], code_map[1, :, 11, 19])
    assert codes.abs().max() <= 1.0  # tanh output, averaged


def test_label_one_hot_ignores_out_of_range():
    label = torch.tensor([[[0, 2, 255]]])
    oh = label_one_hot(label, 3)
    assert oh.shape == (1, 3, 1, 3)
    assert oh[0, :, 0, 0].tolist() == [1, 0, 0] and oh[0, :, 0, 1].tolist() == [0, 0, 1]
    assert oh[0, :, 0, 2].sum() == 0


def test_spec_layout_and_ablation_switches():
    full = TexturalSpec(num_classes=14)
    assert full.generator_channels == 14 + 1 + 5 + 24 + 3
    assert TexturalSpec(num_classes=14, use_pose=False, use_normal=False).generator_channels == 20
    assert TexturalSpec(num_classes=19, use_codes=False).generator_channels == 19 + 1 + 24 + 3
    spec = TexturalSpec(num_classes=4, ngf=4, n_downsampling=1, n_blocks=1, nef=4, n_downsampling_encoder=1, ndf=4)
    label = torch.randint(0, 4, (1, 8, 8))
    cond = spec.condition(label, torch.zeros(1, 1, 8, 8))
    x = spec.generator_input(cond, None, torch.ones(1, 24, 8, 8), None)
    assert x.shape == (1, spec.generator_channels, 8, 8)
    assert x[:, 5:10].abs().sum() == 0 and x[:, 10:34].min() == 1 and x[:, 34:].abs().sum() == 0
    assert spec.generator()(x).shape == (1, 3, 8, 8)
    assert spec.discriminator()(torch.cat([cond, torch.zeros(1, 3, 8, 8)], 1))[0][-1].shape[1] == 1
    with pytest.raises(ValueError, match="pose"):
        spec.generator_input(cond, None, torch.ones(1, 3, 8, 8), None)
    with pytest.raises(ValueError, match="boundary"):
        spec.condition(label, torch.zeros(1, 8, 8))
    with pytest.raises(ValueError, match="norm"):
        TexturalSpec(num_classes=4, norm="layer")
    assert TexturalSpec.from_mapping({"num_classes": 3, "ngf": 8, "lr": 1.0}).ngf == 8


def test_vgg19_torchvision_names_and_loading(tmp_path, caplog):
    net = VGG19Features()
    keys = [k for k in net.state_dict() if k.endswith(".weight")]
    assert keys[0] == "features.0.weight" and keys[-1] == "features.28.weight" and len(keys) == 13
    assert TAPS == (1, 6, 11, 20, 29)
    # a torchvision-like file: deeper convs and the classifier are present and dropped explicitly
    state = dict(net.state_dict())
    state.update({"features.30.weight": torch.zeros(512, 512, 3, 3), "features.34.bias": torch.zeros(512),
                  "classifier.0.weight": torch.zeros(4, 4)})
    torch.save(state, tmp_path / "vgg19.pth")
    loaded = load_vgg19(tmp_path / "vgg19.pth")
    assert loaded is not None and not loaded.training
    assert torch.equal(loaded.features[0].weight, net.features[0].weight)
    assert all(not p.requires_grad for p in loaded.parameters())
    del state["features.2.weight"]
    torch.save(state, tmp_path / "broken.pth")
    with pytest.raises(PretrainedWeightsError, match="features.2.weight"):
        load_vgg19(tmp_path / "broken.pth")
    with caplog.at_level(logging.WARNING):
        assert load_vgg19(None) is None and VGGPerceptualLoss.from_file(None) is None
    assert "perceptual loss is off" in caplog.text


def test_vgg_perceptual_loss():
    loss = VGGPerceptualLoss(VGG19Features())
    a, b = torch.rand(1, 3, 32, 32), torch.rand(1, 3, 32, 32)
    assert loss(a, a).item() == 0.0
    pred = a.clone().requires_grad_()
    value = loss(pred, b)
    value.backward()
    assert value > 0 and pred.grad.abs().sum() > 0
    loss.train()
    assert not loss.vgg.training


def test_instance_mean_is_safe_for_half_precision_large_regions():
    feats = torch.full((1, 2, 300, 300), 0.75, dtype=torch.float16)  # 9e4 pixels: a float16 sum overflows
    pooled, means, _, _ = instance_mean(feats, torch.zeros(1, 300, 300, dtype=torch.long))
    assert means.dtype == torch.float16 and torch.all(means == 0.75) and torch.all(pooled == 0.75)
