"""Issue 40, session 4: the fit's mirrored hypotheses (the prediction mirrored about the line of sight, and that
mirror's flip) and the headlights of red-bodied cars (the red-lamp cue cannot read a red body)."""

from __future__ import annotations

import math

import pytest
import torch

import sdn3d.geometric.fit as fitmod
from sdn3d.geometric.facing import FRONT_KEYS, facing_belief
from sdn3d.geometric.fit import HYPOTHESES, FitSettings, fit_to_masks
from sdn3d.geometric.lamps import LampCue, face_by_lamps, lamp_evidence, red_lamps, white_lamps
from sdn3d.geometric.model import GeometricNet
from sdn3d.geometric.predict import GeometricPredictor
from sdn3d.math3d.camera import Intrinsics

SMALL = FitSettings(coarse_steps=2, fine_steps=2, coarse_size=16, fine_size=16, coarse_faces=0)
INTR = Intrinsics(60.0, 60.0, 48.0, 12.0, 96, 48)


def _wrapd(a: float) -> float:
    return abs(math.degrees(math.atan2(math.sin(a), math.cos(a))))


def _one_car(x: float = 1.5):
    masks = torch.zeros(1, INTR.height, INTR.width, dtype=torch.bool)
    masks[0, 20:40, 40:80] = True
    location = torch.tensor([[x, 1.65, 8.0]])
    return masks, torch.tensor([[40.0, 20.0, 80.0, 40.0]]), location


def test_the_fine_stage_starts_the_prediction_mirrored_about_its_line_of_sight(monkeypatch):
    """Hypotheses 2 and 3 start at ``alpha -> pi - alpha`` and its flip, ``alpha = ry - ray`` with the ray through
    the prediction's place; without ``mirror`` or without an appearance belief they are not tried, and the search's
    starts keep their names."""
    masks, boxes, location = _one_car()
    starts = []
    real = fitmod._stage

    def stage(*args, **kwargs):
        starts.append(args[2]["ry"].clone())
        return real(*args, **kwargs)

    monkeypatch.setattr(fitmod, "_stage", stage)
    ry0 = -1.2
    kw = dict(start_ry=torch.tensor([ry0]), start_dims=torch.tensor([[4.0, 1.5, 1.7]]),
              start_template=torch.tensor([2]), start_location=location)
    result = fit_to_masks(masks, boxes, INTR, settings=SMALL, yaw_belief=lambda ry: torch.cos(ry - ry0), **kw)
    ray = math.atan2(float(location[0, 0]), float(location[0, 2]))
    fine = starts[-1]
    assert fine.numel() == len(HYPOTHESES) + SMALL.keep
    mirrored = 2 * ray + math.pi - ry0
    assert _wrapd(float(fine[0]) - ry0) < 1e-3 and _wrapd(float(fine[1]) - ry0 - math.pi) < 1e-3
    assert _wrapd(float(fine[2]) - mirrored) < 1e-3 and _wrapd(float(fine[3]) - mirrored - math.pi) < 1e-3
    alpha, alpha_m = ry0 - ray, float(fine[2]) - ray  # the same end seen (sin), the front on the other side (cos)
    assert math.sin(alpha_m) == pytest.approx(math.sin(alpha), abs=1e-4)
    assert math.cos(alpha_m) == pytest.approx(-math.cos(alpha), abs=1e-4)
    assert 0 <= int(result.hypothesis[0]) < len(HYPOTHESES) + SMALL.keep
    starts.clear()
    plain = fit_to_masks(masks, boxes, INTR, settings=FitSettings(**{**SMALL.to_dict(), "mirror": False}),
                         yaw_belief=lambda ry: torch.cos(ry - ry0), **kw)
    assert starts[-1].numel() == 2 + SMALL.keep
    fit_to_masks(masks, boxes, INTR, settings=SMALL, **kw)  # no appearance: nothing tells a mirror, none is tried
    assert starts[-1].numel() == 2 + SMALL.keep
    h = int(plain.hypothesis[0])
    assert h in (0, 1) or h >= len(HYPOTHESES)  # the search's starts are named as with the mirror
    with pytest.raises(ValueError, match="mirror"):
        FitSettings(mirror=1)


def test_a_car_whose_truth_is_the_mirrored_yaw_is_fitted_right():
    """The branch predicted the mirror of the truth (the right end seen, its front to the wrong side); the appearance
    believes the truth's side. Only a fit that tries the mirror finds it: without, every hypothesis stays near the
    prediction, its flip or the search's quarter turns."""
    masks, boxes, location = _one_car(x=0.0)
    truth = -math.pi / 2 - 0.6  # alpha = -124 degrees: the back seen, the front to the left
    predicted = -math.pi / 2 + 0.6  # the mirror about the ray (x = 0: ray 0)
    settings = FitSettings(**{**SMALL.to_dict(), "tie": 10.0, "facing_tie": 0.0, "yaw_reg": 0.0})

    def belief(ry):
        return torch.cos(ry - truth)

    kw = dict(start_ry=torch.tensor([predicted]), start_dims=torch.tensor([[4.0, 1.5, 1.7]]),
              start_template=torch.tensor([2]), start_location=location, yaw_belief=belief)
    with_mirror = fit_to_masks(masks, boxes, INTR, settings=settings, **kw)
    assert _wrapd(float(with_mirror.ry[0]) - truth) < 15
    assert int(with_mirror.hypothesis[0]) == 2 and "mirrored" in with_mirror.hypothesis_name(0)
    without = fit_to_masks(masks, boxes, INTR, settings=FitSettings(**{**settings.to_dict(), "mirror": False}), **kw)
    assert _wrapd(float(without.ry[0]) - truth) > 25


def _red_car(n: int = 1, headlights: str | None = None) -> tuple[torch.Tensor, torch.Tensor]:
    """``(crop (n, 3, 32, 32), mask)``: a red body with dark glass on top and, optionally, white head lights low on
    the ``'left'``, ``'right'`` or ``'both'`` sides."""
    crop, mask = torch.zeros(n, 3, 32, 32), torch.zeros(n, 1, 32, 32)
    mask[:, :, 8:24, 4:28] = 1.0
    crop[:, 0, 8:24, 4:28] = 0.7
    crop[:, 1:, 8:24, 4:28] = 0.08
    crop[:, :, 9:13, 8:24] = 0.1  # glass
    cols = {"left": [(6, 10)], "right": [(22, 26)], "both": [(6, 10), (22, 26)]}.get(headlights, [])
    for a, b in cols:
        crop[:, :, 18:20, a:b] = 0.95
    return crop, mask


def test_a_red_cars_front_and_back_are_read_from_its_headlights():
    """The red cue cannot read a red body (its red share is too high); white lights low on the body mark the front
    and their side, none the back. (At full weight: by default a presence weighs only ``headlight_weight``,
    tests/test_lamps_headlight_weight.py.)"""
    cue = LampCue(min_mask=0, headlight_weight=1.0)
    crop, mask = _red_car(3)
    crop[1], crop[2] = _red_car(1, "both")[0][0], _red_car(1, "left")[0][0]
    _, red_usable, _ = red_lamps(crop, mask, cue)
    assert not red_usable.any()  # the red cue is blind here
    present, usable, offset = white_lamps(crop, mask, cue)
    assert usable.all() and present.tolist() == [False, True, True]
    assert abs(float(offset[1])) < 0.05 and float(offset[2]) < -0.2
    back, front = -math.pi / 2, math.pi / 2
    ray = torch.zeros(3)
    # predicted facing the camera, predicted facing away, predicted facing away: each read end wins
    turned = face_by_lamps(torch.tensor([front, back, back]), ray, crop, mask, cue)
    assert [math.sin(float(t)) > 0 for t in turned] == [False, True, True]
    # the side: headlights on the left make alpha = pi (front to the left) beat alpha = 0
    evidence = lamp_evidence(crop[2:], mask[2:], torch.tensor([[math.pi * 0.75, math.pi * 0.25]]), cue)
    assert float(evidence[0, 0]) > float(evidence[0, 1]) + 0.3
    off = face_by_lamps(torch.tensor([front, back, back]), ray, crop, mask, LampCue(min_mask=0, red_body=False))
    assert [math.sin(float(t)) > 0 for t in off] == [True, False, False]  # no cue: the prediction stands
    # a white lamp above the middle (a reflection on glass or roof) is not a headlight
    high = _red_car(1)[0]
    high[:, :, 10:12, 6:10] = 0.95
    assert not bool(white_lamps(high, mask[:1], cue)[0][0])


def test_the_predictor_and_the_facing_belief_carry_the_headlights():
    torch.manual_seed(0)
    predictor = GeometricPredictor(GeometricNet(rotation="multibin", hidden=16), lamp_cue=LampCue(min_mask=0))
    crop, mask = _red_car(1, "right")
    out = predictor.predict(crop, mask, torch.tensor([[30.0, 10.0, 70.0, 30.0]]), torch.tensor([[60.0, 60.0, 48.0,
                                                                                                    12.0]]))
    assert all(k in out for k in FRONT_KEYS) and bool(out["front_usable"][0]) and bool(out["front_present"][0])
    values = {k: out[k] for k in ("net_ry", "ray", "lamp_present", "lamp_usable", "lamp_offset") + FRONT_KEYS}
    ray = float(out["ray"][0])
    front_right, front_left = ray + math.pi * 0.25, ray + math.pi * 0.75  # both show the front; right matches
    score = facing_belief(values, LampCue(min_mask=0), bins=False)(torch.tensor([[front_right, front_left]]))
    assert float(score[0, 0]) > float(score[0, 1])
    without = {k: v for k, v in values.items() if k not in FRONT_KEYS}  # an older reading: the red cue alone, blind
    ry = torch.tensor([[front_right, front_left]])
    score = facing_belief(without, LampCue(min_mask=0), bins=False)(ry)
    assert torch.allclose(score, 0.3 * torch.cos(ry - out["net_ry"][:, None]), atol=1e-6)  # the net's say alone
