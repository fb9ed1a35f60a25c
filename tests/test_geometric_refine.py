"""Per-image refinement by reprojection (Cityscapes path): it must pull perturbed poses back to the masks."""

from __future__ import annotations

import pytest
import torch

from sdn3d.geometric import (
    GeometricNet,
    GeometricPredictor,
    RefineSettings,
    refine_by_reprojection,
    render_silhouettes,
)
from sdn3d.math3d.camera import intrinsics_matrix, project_points
from sdn3d.math3d.encodings import AttributeEncoding
from sdn3d.math3d.rotations import wrap_angle
from sdn3d.math3d.transforms import project_box
from sdn3d.meshes.bank import MeshBank

S = 32


def _crop_camera(box: torch.Tensor, intr: torch.Tensor, margin: float = 0.1) -> torch.Tensor:
    """Crop intrinsics of a square window around each box (as the dataset makes them)."""
    side = (box[:, 2:] - box[:, :2]).amax(1) * (1 + 2 * margin)
    centre = (box[:, :2] + box[:, 2:]) / 2
    left, top = centre[:, 0] - side / 2, centre[:, 1] - side / 2
    scale = S / side
    return torch.stack([intr[:, 0] * scale, intr[:, 1] * scale, (intr[:, 2] - left) * scale - 0.5,
                        (intr[:, 3] - top) * scale - 0.5], 1)


@pytest.fixture(scope="module")
def scene():
    intr = torch.tensor([[364.0, 371.0, 311.5, 95.5]]).expand(3, 4)
    dims = torch.tensor([[4.2, 1.5, 1.8], [4.6, 1.8, 1.9], [4.0, 1.4, 1.7]])
    ry = torch.tensor([0.4, -2.0, 1.4])
    center = torch.tensor([[-3.0, 0.9, 12.0], [2.5, 0.8, 15.0], [0.5, 0.9, 9.0]])
    K = intrinsics_matrix(*intr.unbind(1))
    box = project_box(dims, ry, center, K)
    crop_intr = _crop_camera(box, intr)
    bank = MeshBank.templates()
    ids = torch.tensor([0, 3, 1])
    mask = (render_silhouettes(bank, ids, dims, ry, center, None, crop_intr, S) > 0.5).float().unsqueeze(1)
    enc = AttributeEncoding()
    raw = enc.encode(dims, ry, center, box, K)
    logits = torch.full((3, 8), -5.0)
    logits[torch.arange(3), ids] = 5.0
    raw.update(phi=torch.zeros(3, 64, 3), template_logits=logits)
    return {"raw": raw, "box": box, "intr": intr, "crop_intr": crop_intr, "mask": mask, "bank": bank,
            "dims": dims, "ry": ry, "center": center, "K": K}


def test_refinement_recovers_a_perturbed_pose(scene):
    raw = {k: v.clone() for k, v in scene["raw"].items()}
    # Perturb yaw by 0.25 rad, the centre offset by 8 % of the box and the size by 15 %.
    dry = 0.25
    q = raw["rotation"]
    c, s = torch.cos(torch.tensor(dry / 2)), torch.sin(torch.tensor(dry / 2))
    raw["rotation"] = torch.stack([q[:, 0] * c - q[:, 2] * s, q[:, 1], q[:, 2] * c + q[:, 0] * s, q[:, 3]], 1)
    raw["offset"] = raw["offset"] + 0.08
    raw["log_scale"] = raw["log_scale"] + 0.15
    result = refine_by_reprojection(raw, scene["box"], scene["intr"], scene["crop_intr"], scene["mask"],
                                    bank=scene["bank"], settings=RefineSettings(iterations=16))
    assert result.losses.shape == (17, 3)
    first, last = result.losses[0], result.losses[-1]
    assert (last < 0.6 * first).all(), (first, last)
    pred = result.pred
    err_ry = wrap_angle(pred["ry"] - scene["ry"]).abs()
    assert (err_ry < dry).all()
    uv = project_points(pred["center"], scene["K"])
    uv_true = project_points(scene["center"], scene["K"])
    uv_start = project_points(
        AttributeEncoding().decode(raw, scene["box"], scene["K"])[2], scene["K"])
    assert ((uv - uv_true).norm(dim=1) < (uv_start - uv_true).norm(dim=1)).all()
    # The distance (log tau) is not refined by default, and the mesh choice stays.
    torch.testing.assert_close(result.raw["log_distance"], raw["log_distance"])
    assert torch.equal(pred["template_id"], torch.tensor([0, 3, 1]))
    torch.testing.assert_close(raw["offset"], scene["raw"]["offset"] + 0.08)  # input untouched


def test_refinement_keeps_the_ffd_symmetric_and_small(scene):
    result = refine_by_reprojection(scene["raw"], scene["box"], scene["intr"], scene["crop_intr"], scene["mask"],
                                    bank=scene["bank"], settings=RefineSettings(iterations=4, params=("phi",)))
    phi = result.raw["phi"]
    from sdn3d.math3d.ffd import mirror_ffd

    torch.testing.assert_close(mirror_ffd(phi), phi)
    assert float(phi.abs().max()) < 0.2
    zero = refine_by_reprojection(scene["raw"], scene["box"], scene["intr"], scene["crop_intr"], scene["mask"],
                                  bank=scene["bank"], settings=RefineSettings(iterations=0))
    assert zero.losses.shape == (1, 3)
    torch.testing.assert_close(zero.raw["offset"], scene["raw"]["offset"])


def test_predictor_refine_option_runs_under_no_grad(scene):
    predictor = GeometricPredictor(GeometricNet())
    crop = torch.rand(3, 3, S, S)
    with torch.no_grad():
        plain = predictor.predict(crop, scene["mask"], scene["box"], scene["intr"], scene["crop_intr"])
        refined = predictor.predict(crop, scene["mask"], scene["box"], scene["intr"], scene["crop_intr"],
                                    refine=RefineSettings(iterations=3))
    assert refined["silhouette"].shape == (3, S, S)
    assert not torch.allclose(refined["ry"], plain["ry"])
    with pytest.raises(ValueError, match="refine needs"):
        predictor.predict(crop, None, scene["box"], scene["intr"], refine=RefineSettings())


def test_refine_settings_validation():
    with pytest.raises(ValueError, match="params"):
        RefineSettings(params=("colour",))
    with pytest.raises(ValueError, match="lr"):
        RefineSettings(lr=0.0)
    assert RefineSettings(params=["phi"]).params == ("phi",)


def test_refinement_with_occluder_masks_fits_the_car_behind():
    """An occluded pair: car B stands behind car A, whose mask hides part of B. Refining B's perturbed pose on
    L_reproj lowers it, and ignoring A's pixels (derender's occluder masks, ordered by depth) keeps the fit
    on B instead of pulling it onto B's visible remainder."""
    from sdn3d.derender import occluder_masks

    intr = torch.tensor([[364.0, 371.0, 311.5, 95.5]]).expand(2, 4)
    dims = torch.tensor([[4.2, 1.5, 1.8], [4.4, 1.6, 1.8]])
    ry = torch.tensor([0.3, 0.2])
    center = torch.tensor([[-0.6, 0.9, 9.0], [0.8, 0.9, 13.0]])  # A in front, B behind and to the right
    K = intrinsics_matrix(*intr.unbind(1))
    box = project_box(dims, ry, center, K)
    crop_b = _crop_camera(box[1:], intr[1:]).expand(2, 4)  # both cars seen through B's crop
    bank = MeshBank.templates()
    ids = torch.tensor([0, 0])
    sil = render_silhouettes(bank, ids, dims, ry, center, None, crop_b, S) > 0.5  # (2, S, S)
    hidden = sil[0] & sil[1]
    assert int(hidden.sum()) > 0.15 * int(sil[1].sum()), "the pair must overlap"
    # The ignore mask derender builds: the nearer object's mask (here, A's silhouette in B's crop).
    ignore = occluder_masks(sil, center[:, 2])[1:].float().unsqueeze(1)
    torch.testing.assert_close(ignore[0, 0], sil[0].float())
    visible_b = (sil[1] & ~sil[0]).float()[None, None]
    enc = AttributeEncoding()
    raw = enc.encode(dims[1:], ry[1:], center[1:], box[1:], K[1:])
    logits = torch.full((1, 8), -5.0)
    logits[0, 0] = 5.0
    raw.update(phi=torch.zeros(1, 64, 3), template_logits=logits, offset=raw["offset"] + 0.1,
               log_scale=raw["log_scale"] + 0.12)
    fit = {name: refine_by_reprojection(raw, box[1:], intr[1:], crop_b[1:], visible_b, ign, bank=bank,
                                        settings=RefineSettings(iterations=16))
           for name, ign in (("ignore", ignore), ("plain", None))}
    losses = fit["ignore"].losses[:, 0]
    assert float(losses[-1]) < 0.5 * float(losses[0]), losses
    uv_true = project_points(center[1:], K[1:])
    err = {k: float((project_points(r.pred["center"], K[1:]) - uv_true).norm()) for k, r in fit.items()}
    assert err["ignore"] < err["plain"], err


def test_refinement_of_half_precision_outputs_runs_in_float32(scene):
    """Mixed-precision inference hands over float16 outputs; Adam on float16 leaves made a zero gradient 0 / 0
    (its eps underflows) and the fit NaN (Table 2's test-time fit on a GPU, 2026-11-26)."""
    half = {k: v.half() for k, v in scene["raw"].items()}
    result = refine_by_reprojection(half, scene["box"], scene["intr"], scene["crop_intr"], scene["mask"],
                                    bank=scene["bank"], settings=RefineSettings(iterations=4))
    assert all(v.dtype == torch.float32 and bool(torch.isfinite(v).all()) for v in result.raw.values())
    assert bool(torch.isfinite(result.losses).all())


def test_adam_fit_takes_torch_optim_adams_steps():
    """adam_fit writes Adam out (torch.optim's first step imports torch._dynamo, 1.3 s of a fresh process): the same
    iterates as torch.optim.Adam's defaults, a parameter the loss does not reach left alone."""
    from sdn3d.geometric.refine import adam_fit

    target = torch.tensor([[1.0, -2.0, 0.5], [3.0, 0.0, -1.0]])
    start = torch.tensor([[0.3, 0.1, -0.2], [0.0, 0.5, 0.7]])

    def loss(x: torch.Tensor) -> torch.Tensor:  # per-object, with a curvature that differs between coordinates
        return ((x - target) ** 2 * torch.tensor([1.0, 3.0, 0.2])).sum(1) + x[:, 0].sin()

    ours, unused = start.clone().requires_grad_(True), torch.ones(2, requires_grad=True)
    history = adam_fit([ours, unused], lambda: loss(ours), 25, 0.05)
    theirs = start.clone().requires_grad_(True)
    optimizer = torch.optim.Adam([theirs], lr=0.05)
    reference = []
    for _ in range(25):
        optimizer.zero_grad()
        value = loss(theirs)
        reference.append(value.detach())
        value.sum().backward()
        optimizer.step()
    torch.testing.assert_close(ours.detach(), theirs.detach(), rtol=0, atol=1e-6)
    torch.testing.assert_close(torch.stack(history), torch.stack(reference), rtol=0, atol=1e-5)
    assert unused.tolist() == [1.0, 1.0]
    assert float(history[-1].sum()) < float(history[0].sum())


def test_fitting_a_box_does_not_import_torch_dynamo():
    """A fresh sdn3d-edit process paid 1.2-1.4 s for torch._dynamo, imported by torch.optim's first step."""
    import subprocess
    import sys

    code = ("import sys, torch\n"
            "from sdn3d.geometric.fit import FitSettings, fit_to_masks\n"
            "from sdn3d.math3d.camera import Intrinsics\n"
            "mask = torch.zeros(1, 48, 96, dtype=torch.bool); mask[0, 20:40, 30:70] = True\n"
            "fit_to_masks(mask, torch.tensor([[30.0, 20.0, 70.0, 40.0]]), Intrinsics(60.0, 60.0, 48.0, 12.0, 96, 48),\n"
            "             settings=FitSettings(coarse_steps=2, fine_steps=2, coarse_size=16, fine_size=16))\n"
            "print('torch._dynamo' in sys.modules)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, check=True)
    assert done.stdout.strip() == "False", done.stdout + done.stderr
