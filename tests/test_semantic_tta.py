"""Flip test-time augmentation: mirrored outputs, exact flip equivariance, predictor and module wiring."""

from __future__ import annotations

import torch

from sdn3d.nets.drn import DRNSeg
from sdn3d.semantic import flip_averaged_outputs, hflip_outputs

SLIM = [8, 8, 16, 16, 16, 16, 16, 16]


def _net(decoder: str = "skip") -> DRNSeg:
    torch.manual_seed(0)
    return DRNSeg(5, channels=SLIM, head_channels=16, decoder=decoder, decoder_channels=[8, 8, 8]).eval()


def test_hflip_outputs_mirrors_maps_and_negates_du():
    out = {"logits": torch.randn(2, 5, 6, 7), "center": torch.rand(2, 1, 6, 7), "offset": torch.randn(2, 2, 6, 7)}
    flipped = hflip_outputs(out)
    assert torch.equal(flipped["logits"], out["logits"].flip(-1))
    assert torch.equal(flipped["center"], out["center"].flip(-1))
    assert torch.equal(flipped["offset"][:, 0], -out["offset"][:, 0].flip(-1))  # du changes sign
    assert torch.equal(flipped["offset"][:, 1], out["offset"][:, 1].flip(-1))
    back = hflip_outputs(flipped)
    assert all(torch.equal(back[k], out[k]) for k in out)
    assert torch.equal(out["offset"], out["offset"].clone())  # the input dict is left alone


def test_flip_averaged_outputs_are_flip_equivariant_and_average_probabilities():
    net = _net()
    torch.manual_seed(1)
    image = torch.rand(2, 3, 24, 40)
    with torch.no_grad():
        tta = flip_averaged_outputs(net, image)
        tta_mirror = flip_averaged_outputs(net, image.flip(-1))
        plain, mirror = net(image), hflip_outputs(net(image.flip(-1)))
    assert set(tta) == {"logits", "center", "center_logits", "offset"}
    assert all(tta[k].shape == plain[k].shape for k in tta)
    # The averaged outputs of the mirror image are exactly the mirrored averaged outputs (a plain
    # network is not equivariant: its outputs differ).
    back = hflip_outputs(tta_mirror)
    for key in tta:
        torch.testing.assert_close(back[key], tta[key], atol=1e-5, rtol=1e-4)
    assert not torch.allclose(plain["offset"], mirror["offset"], atol=1e-3)
    expected = (plain["logits"].softmax(1) + mirror["logits"].softmax(1)) / 2
    torch.testing.assert_close(tta["logits"].softmax(1), expected, atol=1e-5, rtol=1e-4)
    torch.testing.assert_close(tta["center"], (plain["center"] + mirror["center"]) / 2)
    torch.testing.assert_close(tta["center_logits"].sigmoid(), tta["center"], atol=1e-5, rtol=1e-4)
    torch.testing.assert_close(tta["offset"], (plain["offset"] + mirror["offset"]) / 2)


def test_flip_without_instance_head():
    torch.manual_seed(0)
    net = DRNSeg(5, channels=SLIM, instance_head=False).eval()
    with torch.no_grad():
        out = flip_averaged_outputs(net, torch.rand(1, 3, 16, 32))
    assert set(out) == {"logits"} and out["logits"].shape == (1, 5, 16, 32)
