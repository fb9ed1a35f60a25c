"""L_pred, L_reproj (silhouettes in crop cameras, ignore masks), the FFD term and REINFORCE."""

from __future__ import annotations

import math

import pytest
import torch

from sdn3d.geometric import (
    MovingAverageBaseline,
    leave_one_out_baseline,
    outside_image_mask,
    prediction_loss,
    prediction_losses,
    reinforce_loss,
    render_silhouettes,
    reprojection_error,
    sample_templates,
)
from sdn3d.geometric.decode import decode_outputs
from sdn3d.math3d.encodings import AttributeEncoding, encode_yaw_quaternion
from sdn3d.math3d.ffd import expand_half_ffd
from sdn3d.meshes.bank import MeshBank
from sdn3d.render.settings import SoftSilhouetteSettings


@pytest.fixture(scope="module")
def bank() -> MeshBank:
    return MeshBank.templates()


def _targets(n: int = 4) -> dict[str, torch.Tensor]:
    g = torch.Generator().manual_seed(1)
    return {"log_scale": torch.randn(n, 3, generator=g), "rotation": encode_yaw_quaternion(torch.rand(n, generator=g)),
            "offset": torch.randn(n, 2, generator=g) * 0.1, "log_distance": torch.randn(n, 1, generator=g)}


def test_prediction_loss_is_zero_at_the_targets_and_sums_the_terms():
    targets = _targets()
    exact = prediction_losses(targets, targets)
    assert all(float(v.abs().max()) < 1e-6 for v in exact.values())
    # A sign-flipped quaternion is the same rotation: no rotation loss.
    flipped = dict(targets, rotation=-3.0 * targets["rotation"])
    assert float(prediction_losses(flipped, targets)["rotation"].abs().max()) < 1e-6
    off = {k: v + 0.5 for k, v in targets.items()}
    terms = prediction_losses(off, targets)
    torch.testing.assert_close(terms["scale"], torch.full((4,), 0.75))  # 3 components x 0.5^2
    torch.testing.assert_close(terms["offset"], torch.full((4,), 0.5))
    torch.testing.assert_close(terms["distance"], torch.full((4,), 0.25))
    total = prediction_loss(terms)
    torch.testing.assert_close(total, sum(t.mean() for t in terms.values()))
    smooth = prediction_losses(off, targets, regression="smooth_l1")
    torch.testing.assert_close(smooth["distance"], torch.full((4,), 0.125))  # 0.5 x 0.5^2 below beta = 1
    with pytest.raises(ValueError, match="regression"):
        prediction_losses(off, targets, regression="l3")


def test_outside_image_mask_marks_samples_beyond_the_border():
    # An 8-px window starting 2 px left of the image and 3 px above it, sampled at 8 x 8: one pixel each.
    crop_box = torch.tensor([[-2.5, -3.5, 5.5, 4.5]])
    out = outside_image_mask(crop_box, (100, 50), 8)[0, 0]
    assert out.shape == (8, 8)
    assert out[:, :2].eq(1).all() and out[3:, 2:].eq(0).all() and out[:3].eq(1).all()
    right = outside_image_mask(torch.tensor([[95.5, 10.5, 103.5, 18.5]]), (100, 50), 8)[0, 0]
    assert right[:, :4].eq(0).all() and right[:, 4:].eq(1).all()  # columns 96..99 inside, 100.. outside


def test_reprojection_error_counts_only_pixels_not_ignored():
    sil = torch.zeros(2, 4, 4)
    sil[0, :2] = 1.0
    mask = torch.zeros(2, 1, 4, 4)
    mask[0, 0, :2] = 1.0
    mask[1, 0, 0, 0] = 1.0  # object 1: one wrong pixel of 16
    err = reprojection_error(sil, mask)
    torch.testing.assert_close(err, torch.tensor([0.0, 1 / 16]))
    ignore = torch.zeros(2, 1, 4, 4)
    ignore[1, 0, 0, 0] = 1.0
    ignore[1, 0, 3] = 1.0
    torch.testing.assert_close(reprojection_error(sil, mask, ignore), torch.tensor([0.0, 0.0]))
    with pytest.raises(ValueError, match="mask"):
        reprojection_error(sil, mask[:, :, :2])


def _scene(n: int = 3):
    """Objects centred in 32 x 32 crops (a pinhole looking at each object's centre)."""
    dims = torch.tensor([[4.0, 1.5, 1.8], [4.5, 1.7, 1.9], [5.5, 2.2, 2.0]])[:n]
    ry = torch.tensor([0.3, -1.2, 2.5])[:n]
    center = torch.tensor([[0.0, 0.0, 12.0], [0.0, 0.0, 10.0], [0.0, 0.0, 15.0]])[:n]
    crop_k = torch.tensor([[60.0, 60.0, 15.5, 15.5], [55.0, 55.0, 15.5, 15.5], [80.0, 80.0, 15.5, 15.5]])[:n]
    return dims, ry, center, crop_k


def test_silhouette_loss_prefers_the_true_pose_and_template(bank):
    dims, ry, center, crop_k = _scene()
    ids = torch.tensor([0, 3, 7])
    mask = (render_silhouettes(bank, ids, dims, ry, center, None, crop_k, 32) > 0.5).float().unsqueeze(1)
    assert 0.05 < float(mask.mean()) < 0.6
    true = reprojection_error(render_silhouettes(bank, ids, dims, ry, center, None, crop_k, 32), mask)
    turned = reprojection_error(render_silhouettes(bank, ids, dims, ry + 1.0, center, None, crop_k, 32), mask)
    assert (true < 0.05).all() and (turned > 2 * true + 0.01).all()
    other = reprojection_error(render_silhouettes(bank, torch.tensor([7, 7, 0]), dims, ry, center, None, crop_k,
                                                  32), mask)
    assert (other > true).all()


def test_reprojection_chain_gradients_match_finite_differences(bank):
    """gradcheck of raw outputs -> decode -> pose + FFD -> soft silhouette -> L_reproj (float64)."""
    dims, ry, center, crop_k = _scene(1)
    intr = torch.tensor([[300.0, 300.0, 150.0, 50.0]], dtype=torch.float64)
    box = torch.tensor([[120.0, 35.0, 180.0, 62.0]], dtype=torch.float64)
    enc = AttributeEncoding()
    K = torch.tensor([[[300.0, 0, 150.0], [0, 300.0, 50.0], [0, 0, 1]]], dtype=torch.float64)
    raw = {k: v.double() for k, v in enc.encode(dims.double(), ry.double(), center.double(), box, K).items()}
    mask = torch.zeros(1, 1, 16, 16, dtype=torch.float64)
    mask[..., 4:12, 3:13] = 1.0
    settings = SoftSilhouetteSettings((16, 16), sigma=2.0, cull_eps=1e-8)
    crop_k16 = crop_k.double() / 2
    # The FFD enters through two amplitudes of fixed symmetric fields (64 x 3 free entries would make
    # finite differences slow); the chain from phi on is the same.
    fields = expand_half_ffd(torch.randn(2, 32, 3, generator=torch.Generator().manual_seed(0)).double() * 0.05)

    def loss(log_scale, rotation, offset, log_distance, amplitude):
        phi = (amplitude.view(2, 1, 1) * fields).sum(0, keepdim=True)
        values = {"log_scale": log_scale, "rotation": rotation, "offset": offset, "log_distance": log_distance,
                  "phi": phi, "template_logits": torch.zeros(1, 8, dtype=torch.float64)}
        pred = decode_outputs(values, box, intr, enc)
        sil = render_silhouettes(bank, torch.tensor([1]), pred["dims"], pred["ry"], pred["center"], phi, crop_k16,
                                 settings)
        return reprojection_error(sil, mask)

    inputs = tuple(t.clone().requires_grad_(True) for t in (raw["log_scale"], raw["rotation"], raw["offset"],
                                                              raw["log_distance"],
                                                              torch.tensor([0.5, -0.3], dtype=torch.float64)))
    assert torch.autograd.gradcheck(loss, inputs, eps=1e-6, atol=1e-5, rtol=1e-3)


def test_sample_templates_follows_the_distribution():
    logits = torch.tensor([[2.0, 0.0, -1.0], [0.0, 0.0, 0.0]])
    idx, log_probs = sample_templates(logits, 4000, torch.Generator().manual_seed(0))
    assert idx.shape == log_probs.shape == (2, 4000)
    freq = torch.stack([(idx == j).float().mean(1) for j in range(3)], 1)
    torch.testing.assert_close(freq, logits.softmax(1), atol=0.03, rtol=0)
    torch.testing.assert_close(log_probs, logits.log_softmax(1).gather(1, idx))
    with pytest.raises(ValueError, match="num_samples"):
        sample_templates(logits, 0)


def test_reinforce_gradient_is_the_score_function_estimate():
    logits = torch.tensor([[0.5, -0.2, 0.1]], requires_grad=True)
    idx = torch.tensor([[0, 2]])
    log_probs = logits.log_softmax(1).gather(1, idx)
    rewards = torch.tensor([[-0.1, -0.4]])
    reinforce_loss(log_probs, rewards, baseline=-0.2).backward()
    p = logits.detach().softmax(1)[0]
    onehot = torch.eye(3)[idx[0]]
    expected = -((rewards[0] + 0.2)[:, None] * (onehot - p)).mean(0)
    torch.testing.assert_close(logits.grad[0], expected)
    torch.testing.assert_close(leave_one_out_baseline(torch.tensor([[1.0, 2.0, 6.0]])), torch.tensor([[4.0, 3.5, 1.5]]))


def test_reinforce_finds_the_template_with_the_lowest_reprojection_error():
    """A bandit: template 5 reprojects best; REINFORCE with a moving-average baseline must learn that."""
    torch.manual_seed(0)
    error = torch.tensor([0.30, 0.25, 0.28, 0.22, 0.35, 0.05, 0.20, 0.40])
    logits = torch.zeros(16, 8, requires_grad=True)
    opt = torch.optim.Adam([logits], lr=0.05)
    baseline = MovingAverageBaseline(0.9)
    for _ in range(150):
        idx, log_probs = sample_templates(logits, 4)
        rewards = -(error[idx] + 0.02 * torch.randn(idx.shape))
        loss = reinforce_loss(log_probs, rewards, baseline())
        baseline.update(rewards)
        opt.zero_grad()
        loss.backward()
        opt.step()
    assert (logits.argmax(1) == 5).all() and float(logits.detach().softmax(1)[:, 5].mean()) > 0.8
    assert -0.2 < float(baseline.value) < -0.04 and int(baseline.count) == 150


def test_moving_average_baseline_resumes_from_its_state_dict():
    b = MovingAverageBaseline(0.5)
    assert float(b()) == 0.0
    b.update(torch.tensor([-1.0, -3.0]))  # first update takes the mean
    b.update(torch.tensor([0.0]))
    assert math.isclose(float(b.value), -1.0) and int(b.count) == 2
    restored = MovingAverageBaseline(0.5)
    restored.load_state_dict(b.state_dict())
    restored.update(torch.tensor([1.0]))
    assert math.isclose(float(restored.value), 0.0) and int(restored.count) == 3
    with pytest.raises(ValueError, match="momentum"):
        MovingAverageBaseline(1.0)


def test_expected_reward_loss_is_the_exact_policy_gradient():
    from sdn3d.geometric import expected_reward_loss

    logits = torch.tensor([[0.2, -0.5, 1.0], [0.0, 0.3, -0.1]], requires_grad=True)
    rewards = torch.tensor([[-1.0, -2.0, -0.5], [-0.3, -0.2, -0.9]])
    expected_reward_loss(logits, rewards).backward()
    p = logits.detach().softmax(1)
    # d/dlogit_m of -mean_n sum_m p_m r_m = -p_m (r_m - sum_k p_k r_k) / N
    want = -p * (rewards - (p * rewards).sum(1, keepdim=True)) / 2
    torch.testing.assert_close(logits.grad, want)
    with pytest.raises(ValueError, match="must match"):
        expected_reward_loss(logits, rewards[:, :2])
