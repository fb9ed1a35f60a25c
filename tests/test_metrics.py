"""Image metrics (whole, masked, crops) and LPIPS."""

from __future__ import annotations

import logging
import math

import pytest
import torch
from torchmetrics.functional.image import structural_similarity_index_measure

from sdn3d.evaluation import image_metrics as metrics
from sdn3d.image_ops import mask_boxes
from sdn3d.nets.lpips import LPIPS, load_lpips, merge_lpips_weights
from sdn3d.nets.weights import PretrainedWeightsError


def _pair(b: int = 2, h: int = 24, w: int = 40) -> tuple[torch.Tensor, torch.Tensor]:
    target = torch.rand(b, 3, h, w)
    pred = (target + 0.1 * torch.randn_like(target)).clamp(0, 1)
    return pred, target


def test_whole_image_metrics_known_values():
    target = torch.full((2, 3, 16, 16), 0.5)
    pred = target + 0.1
    assert torch.allclose(metrics.l1(pred, target), torch.tensor([0.1, 0.1]))
    assert torch.allclose(metrics.psnr(pred, target), torch.tensor([20.0, 20.0]), atol=1e-4)  # 10 log10(1 / 0.01)
    assert torch.allclose(metrics.ssim(target, target), torch.ones(2))
    p, t = _pair()
    assert torch.allclose(metrics.ssim(p, t), structural_similarity_index_measure(p, t, data_range=1.0,
                                                                                   reduction="none"))
    out = metrics.image_metrics(p, t)
    assert set(out) == {"l1", "psnr", "ssim"} and all(v.shape == (2,) for v in out.values())
    with pytest.raises(ValueError, match="pred and target"):
        metrics.l1(p, t[:, :, :10])


def test_masked_metrics():
    p, t = _pair()
    full = torch.ones(2, 24, 40, dtype=torch.bool)
    for name in ("l1", "psnr", "ssim"):  # an all-True mask is the whole image
        fn = getattr(metrics, name)
        assert torch.allclose(fn(p, t, full), fn(p, t), atol=1e-5), name
    mask = torch.zeros(2, 24, 40, dtype=torch.bool)
    mask[:, 4:12, 8:30] = True
    mask[1] = False  # image 1: empty region
    # pixel metrics only see the masked pixels
    corrupted = p.clone()
    corrupted[:, :, 15:] = 1 - corrupted[:, :, 15:]
    assert torch.allclose(metrics.l1(corrupted, t, mask)[:1], metrics.l1(p, t, mask)[:1])
    ref = (p[0, :, 4:12, 8:30] - t[0, :, 4:12, 8:30]).abs().mean()
    assert metrics.l1(p, t, mask)[0] == pytest.approx(float(ref), rel=1e-5)
    mse = ((p[0, :, 4:12, 8:30] - t[0, :, 4:12, 8:30]) ** 2).mean()
    assert metrics.psnr(p, t, mask[:, None])[0] == pytest.approx(float(-10 * torch.log10(mse)), rel=1e-5)
    out = metrics.image_metrics(p, t, mask)
    assert all(math.isnan(v[1]) for v in out.values())  # empty mask: NaN
    assert metrics.ssim(p, t, mask)[0] < 1 and metrics.ssim(t, t, mask)[0] == pytest.approx(1.0)
    with pytest.raises(ValueError, match="mask"):
        metrics.l1(p, t, mask[:, :10])


def test_mask_boxes_and_crop_metrics():
    mask = torch.zeros(3, 20, 30, dtype=torch.bool)
    mask[0, 3:7, 10:25] = True
    mask[1, 19, 0] = True
    assert mask_boxes(mask).tolist() == [[10, 3, 25, 7], [0, 19, 1, 20], [0, 0, 0, 0]]

    p, t = _pair(3, 20, 30)
    boxes = torch.tensor([[10, 3, 25, 17], [-5, -5, 4, 3], [10, 10, 10, 15]])
    out = metrics.crop_metrics(p, t, boxes)
    crop_p, crop_t = p[:1, :, 3:17, 10:25], t[:1, :, 3:17, 10:25]
    assert out["l1"][0] == pytest.approx(float(metrics.l1(crop_p, crop_t)[0]))
    assert out["psnr"][0] == pytest.approx(float(metrics.psnr(crop_p, crop_t)[0]))
    assert out["ssim"][0] == pytest.approx(float(metrics.ssim(crop_p, crop_t)[0]))
    assert out["l1"][1] == pytest.approx(float(metrics.l1(p[1:2, :, :3, :4], t[1:2, :, :3, :4])[0]))  # clipped
    assert torch.isfinite(out["ssim"][1])  # 3 px high crop: the SSIM window shrinks
    assert all(math.isnan(v[2]) for v in out.values())  # empty box
    same = metrics.crop_metrics(t[:2], t[:2], boxes[:2])
    assert torch.allclose(same["ssim"], torch.ones(2)) and torch.all(same["l1"] == 0)
    with pytest.raises(ValueError, match="boxes"):
        metrics.crop_metrics(p, t, boxes[:2])


def test_lpips_names_identity_and_masks(tmp_path, caplog):
    net = LPIPS()
    keys = set(net.state_dict())
    assert {"features.0.weight", "features.10.bias", "lin0.model.1.weight", "lin4.model.1.weight"} <= keys
    assert len(keys) == 10 + 5  # 5 convs (weight + bias) + 5 linear layers; scaling constants are not saved
    torch.manual_seed(0)
    for p in net.parameters():  # LPIPS weights are non-negative 1x1 convs; random but valid
        p.data = p.data.abs() if p.dim() == 4 and p.shape[-1] == 1 else p.data
    p, t = _pair(2, 64, 64)
    assert torch.allclose(net(t, t), torch.zeros(2))
    d = net(p, t)
    assert d.shape == (2,) and torch.all(d > 0)
    spatial = net(p, t, spatial=True)
    assert spatial.shape == (2, 1, 64, 64)
    full = torch.ones(2, 64, 64, dtype=torch.bool)
    assert torch.allclose(metrics.lpips(p, t, net, full), spatial.mean((1, 2, 3)))
    out = metrics.image_metrics(p, t, lpips_net=net)
    assert torch.allclose(out["lpips"], d)
    small = metrics.crop_metrics(p, t, torch.tensor([[0, 0, 12, 9], [0, 0, 64, 64]]), lpips_net=net)
    assert torch.isfinite(small["lpips"]).all() and small["lpips"][1] == pytest.approx(float(d[1]), rel=1e-4)

    # file layout: torchvision AlexNet (+ classifier, dropped) merged with the lpips package's lin file
    alex = {k: v for k, v in net.state_dict().items() if k.startswith("features.")}
    alex["classifier.1.weight"] = torch.zeros(2, 2)
    lin = {k: v for k, v in net.state_dict().items() if k.startswith("lin")}
    torch.save(alex, tmp_path / "alexnet.pth")
    torch.save(lin, tmp_path / "alex_lin.pth")
    torch.save(merge_lpips_weights(tmp_path / "alexnet.pth", tmp_path / "alex_lin.pth"), tmp_path / "lpips.pth")
    loaded = load_lpips(tmp_path / "lpips.pth")
    assert torch.allclose(loaded(p, t), d)
    torch.save(alex, tmp_path / "only_alex.pth")
    with pytest.raises(PretrainedWeightsError, match="lin0"):
        load_lpips(tmp_path / "only_alex.pth")
    with caplog.at_level(logging.WARNING):
        assert load_lpips(None) is None
    assert "LPIPS is off" in caplog.text


def test_lpips_small_whole_images_upsample_like_crops():
    """Whole images under 32 px (AlexNet's minimum) are upsampled inside LPIPS, as crops always were."""
    net = LPIPS()
    torch.manual_seed(1)
    for p in net.parameters():
        p.data = p.data.abs() if p.dim() == 4 and p.shape[-1] == 1 else p.data
    p, t = _pair(2, 12, 20)  # (B, 3, 12, 20)
    d = metrics.image_metrics(p, t, lpips_net=net)["lpips"]
    assert d.shape == (2,) and torch.isfinite(d).all() and torch.all(d > 0)
    assert torch.allclose(net(t, t), torch.zeros(2))
    spatial = net(p, t, spatial=True)
    assert spatial.shape == (2, 1, 12, 20)  # the map keeps the input's size
    mask = torch.zeros(2, 12, 20, dtype=torch.bool)
    mask[:, 2:8, 3:15] = True
    masked = metrics.lpips(p, t, net, mask)
    assert torch.allclose(masked, spatial[:, 0][mask].view(2, -1).mean(1))
    # Same result as the explicit upsampling to a 32-px short side (aspect kept: 12x20 -> 32x53).
    up = [torch.nn.functional.interpolate(x, size=(32, 53), mode="bilinear", align_corners=False) for x in (p, t)]
    assert torch.allclose(d, net(*up), atol=1e-6)
    crop = metrics.crop_metrics(p, t, torch.tensor([[0, 0, 20, 12], [0, 0, 20, 12]]), lpips_net=net)["lpips"]
    assert torch.allclose(crop, d, atol=1e-6)


def test_region_image_metrics_equal_the_single_metrics_per_mask_with_one_ssim_map(monkeypatch):
    import sdn3d.evaluation.image_metrics as im

    g = torch.Generator().manual_seed(3)
    pred, target = torch.rand(1, 3, 24, 40, generator=g), torch.rand(1, 3, 24, 40, generator=g)
    masks = {"whole": None, "all": torch.rand(1, 24, 40, generator=g) > 0.5, "none": torch.zeros(1, 24, 40, dtype=bool)}
    expected = {name: {"l1": im.l1(pred, target, mask), "psnr": im.psnr(pred, target, mask),
                       "ssim": im.ssim(pred, target, mask)} for name, mask in masks.items()}
    calls = []
    ssim_fn = im.structural_similarity_index_measure
    monkeypatch.setattr(im, "structural_similarity_index_measure", lambda *a, **k: calls.append(1) or ssim_fn(*a, **k))
    got = im.region_image_metrics(pred, target, masks)
    assert len(calls) == 1 and list(got) == list(masks)
    for name in masks:
        assert list(got[name]) == list(expected[name])
        for k, v in expected[name].items():
            assert torch.equal(got[name][k], v) or (v.isnan().all() and got[name][k].isnan().all()), (name, k)
