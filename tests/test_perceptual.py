"""DRN perceptual loss (the semantic branch's DRN as the frozen F) and the textural module's perceptual choice."""

from __future__ import annotations

import pytest
import torch
from helpers.tiny_models import semantic_net, write_checkpoints

from lightning_modules.textural import perceptual_loss
from sdn3d.errors import UserInputError
from sdn3d.nets.perceptual import DRN_TAP_WEIGHTS, DRNPerceptualLoss
from sdn3d.nets.vgg import VGG19Features, VGGPerceptualLoss


def test_drn_loss_is_the_weighted_l1_of_normalised_stage_features():
    torch.manual_seed(0)
    net = semantic_net()
    loss = DRNPerceptualLoss(net)
    a, b = torch.rand(2, 3, 32, 48), torch.rand(2, 3, 32, 48)
    stages_a = net.backbone.stages((a - net.mean) / net.std)
    stages_b = net.backbone.stages((b - net.mean) / net.std)
    taps = zip((0, 1, 2, 3, 5), DRN_TAP_WEIGHTS, strict=True)
    expected = sum(w * (stages_a[t] - stages_b[t]).abs().mean() for t, w in taps)
    torch.testing.assert_close(loss(a, b), expected)
    assert float(loss(a, a)) == 0
    assert [f.shape[1] for f in loss.features(a)] == [4, 4, 8, 8, 16]  # the tiny DRN's channels at the taps


def test_drn_loss_is_frozen_and_passes_gradients_to_the_prediction():
    net = semantic_net()
    loss = DRNPerceptualLoss(net)
    loss.train()
    assert not net.training and not any(p.requires_grad for p in net.parameters())
    running = net.backbone.layer0[1].running_mean.clone()
    pred = torch.rand(1, 3, 32, 48, requires_grad=True)
    loss(pred, torch.rand(1, 3, 32, 48)).backward()
    assert pred.grad is not None and float(pred.grad.abs().sum()) > 0
    assert torch.equal(net.backbone.layer0[1].running_mean, running)  # BatchNorm statistics untouched
    with pytest.raises(ValueError, match="taps"):
        DRNPerceptualLoss(net, taps=(0, 9), weights=(1.0, 1.0))


def test_perceptual_choice_loads_the_semantic_checkpoint_or_a_vgg_file(tmp_path):
    paths = write_checkpoints(tmp_path)
    drn = perceptual_loss("drn", str(paths["semantic"]))
    assert isinstance(drn, DRNPerceptualLoss)
    reference = torch.load(paths["semantic"], weights_only=True)["state_dict"]
    key = "backbone.layer0.0.weight"
    torch.testing.assert_close(drn.net.state_dict()[key], reference[f"net.{key}"])
    torch.save(VGG19Features().state_dict(), tmp_path / "vgg19.pth")
    assert isinstance(perceptual_loss("vgg", str(tmp_path / "vgg19.pth")), VGGPerceptualLoss)
    assert perceptual_loss("none", None) is None
    with pytest.raises(UserInputError, match="model.perceptual=drn needs model.perceptual_weights"):
        perceptual_loss("drn", None)
    with pytest.raises(UserInputError, match="model.perceptual must be one of"):
        perceptual_loss("alexnet", "x")
    with pytest.raises(UserInputError, match="geometric"):  # a checkpoint of another branch is named as such
        perceptual_loss("drn", str(paths["geometric"]))
