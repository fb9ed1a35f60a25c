"""The proposals' fit leaves out the pixels the semantic branch is unsure are a vehicle's (issue 40, session 36:
``FitSettings.unsure_vehicle``): a predicted mask spills past its car where the branch is unsure, and a silhouette
fitted to the spill turns."""

from __future__ import annotations

import math

import pytest
import torch
from helpers.tiny_models import write_checkpoints
from test_box_objects import HEIGHT, WORK, _picture, _render

import sdn3d.derender as D
from sdn3d.derender import GroundTruth, derender
from sdn3d.geometric.fit import FitSettings, fit_to_masks
from sdn3d.image_ops import mask_boxes
from sdn3d.labels import VKITTI_CLASS_INDEX
from sdn3d.models import Models
from sdn3d.semantic.predict import Segmentation

CAR, ROAD = VKITTI_CLASS_INDEX["Car"], VKITTI_CLASS_INDEX["Road"]
TRUE_RY = -1.2


def _spilled_car() -> tuple[torch.Tensor, torch.Tensor]:
    """``(car (H, W), spill (H, W))``: a car 9 m ahead and a block of road beside its right end, lower two thirds,
    half its width wide (as a predicted mask takes in the road and a neighbour where the branch is unsure)."""
    _, masks = _render([0], [(4.2, 1.5, 1.8)], [TRUE_RY], [(1.5, HEIGHT, 9.0)])
    car = masks[0]
    ys, xs = car.nonzero().T
    top, bottom, right = int(ys.min()), int(ys.max()) + 1, int(xs.max()) + 1
    spill = torch.zeros_like(car)
    spill[top + (bottom - top) // 3:bottom, right:right + int(xs.max() - xs.min()) // 2] = True
    return car, spill


def _yaw_error_deg(ry: float) -> float:
    return abs(math.degrees(math.remainder(ry - TRUE_RY, 2 * math.pi)))


def test_a_spill_left_out_of_the_loss_no_longer_turns_the_fit():
    car, spill = _spilled_car()
    mask = (car | spill)[None]
    box = mask_boxes(mask).float()
    settings = FitSettings(camera_height=HEIGHT)
    start = torch.tensor([TRUE_RY + 0.3])
    plain = fit_to_masks(mask, box, WORK, settings=settings, start_ry=start)
    unsure = fit_to_masks(mask, box, WORK, settings=settings, start_ry=start, unsure_pixels=spill[None])
    assert _yaw_error_deg(float(plain.ry[0])) > 20  # the spill turns the plain fit (40 degrees here)
    assert _yaw_error_deg(float(unsure.ry[0])) < 8  # 3 degrees
    _, drawn = _render([int(unsure.template[0])], [tuple(unsure.dims[0].tolist())], [float(unsure.ry[0])],
                       [tuple(unsure.location[0].tolist())])
    assert float((drawn[0] & car).sum() / (drawn[0] | car).sum()) > 0.85


def test_unsure_pixels_must_be_shaped_as_the_masks():
    car, spill = _spilled_car()
    with pytest.raises(ValueError, match="unsure_pixels must be shaped as masks"):
        fit_to_masks(car[None], mask_boxes(car[None]).float(), WORK, unsure_pixels=spill)


@pytest.mark.parametrize("bad", [0, -0.1, 0.6, True, math.nan])
def test_the_unsure_margin_lies_in_0_half_or_is_none(bad):
    assert FitSettings(unsure_vehicle=None).unsure_vehicle is None
    assert FitSettings(unsure_vehicle=0.5).unsure_vehicle == 0.5
    with pytest.raises(ValueError, match="FitSettings.unsure_vehicle"):
        FitSettings(unsure_vehicle=bad)


@pytest.fixture(scope="module")
def models(tmp_path_factory):
    ckpts = write_checkpoints(tmp_path_factory.mktemp("ckpt"))
    return Models.from_checkpoints(geometric=ckpts["geometric"], crop_size=32)


def test_derender_hands_the_proposals_fit_the_pixels_the_branch_is_unsure_of(models, monkeypatch):
    """The semantic branch's vehicle probability (Car + Van) within ``unsure_vehicle`` of 0.5 is what the proposals'
    fit leaves out; with ``None``, or with ground-truth masks (an oracle), nothing is."""
    car, spill = _spilled_car()
    mask = car | spill
    instances = torch.where(mask, CAR * 1000 + 1, 0)
    semantic = torch.where(mask, CAR, ROAD)
    probability = torch.zeros(1, len(VKITTI_CLASS_INDEX), *car.shape)
    probability[0, ROAD] = 1.0
    probability[0, :, car] = 0.0
    probability[0, CAR, car] = 0.95
    probability[0, ROAD, car] = 0.05
    probability[0, :, spill] = 0.0
    probability[0, CAR, spill] = 0.45  # unsure: a vehicle's at 0.45 + 0.1
    probability[0, VKITTI_CLASS_INDEX["Van"], spill] = 0.1
    probability[0, ROAD, spill] = 0.45
    seg = Segmentation(semantic[None], instances[None], probability)
    image = _picture(mask[None], [(0.2, 0.2, 0.25)])
    gt = GroundTruth("spill", "vkitti", semantic, instances)

    real = D._semantics_and_instances

    def as_predicted(source: str):
        monkeypatch.setattr(D, "_semantics_and_instances", lambda *a: (*real(*a)[:2], source, "branch", seg))

    seen = []
    real_fit = D.fit_proposals
    monkeypatch.setattr(D, "fit_proposals", lambda *a, **k: seen.append(a[9]) or real_fit(*a, **k))  # unsure_pixels
    as_predicted("semantic")
    derender(image, WORK, models, "gt", gt, fit=FitSettings(camera_height=HEIGHT))
    assert torch.equal(seen[-1], spill)  # 0.55: within 0.2 of 0.5; the car's 0.95 and the road's 0 are not
    derender(image, WORK, models, "gt", gt, fit=FitSettings(camera_height=HEIGHT, unsure_vehicle=0.04))
    assert not seen[-1].any()  # 0.55 is not within 0.04 of 0.5
    derender(image, WORK, models, "gt", gt, fit=FitSettings(camera_height=HEIGHT, unsure_vehicle=None))
    assert seen[-1] is None
    as_predicted("gt")
    derender(image, WORK, models, "gt", gt, fit=FitSettings(camera_height=HEIGHT))
    assert seen[-1] is None  # ground-truth masks are taken as they are
