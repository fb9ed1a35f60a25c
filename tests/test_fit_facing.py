"""Front from back in the box fit (issue 40): the red-lamp cue's absence, the appearance's belief wired from the
geometric branch into the fit (opt-in), and the fit keeping the believed end unless the silhouette clearly
disagrees."""

from __future__ import annotations

import dataclasses
import math

import pytest
import torch

from sdn3d.box_objects import BoxPrompts, _fit_boxes
from sdn3d.geometric.facing import Appearance, facing_belief
from sdn3d.geometric.fit import FitSettings, _choose, fit_to_masks
from sdn3d.geometric.lamps import LampCue, face_by_lamps
from sdn3d.geometric.model import GeometricNet, ray_angle, yaw_distribution
from sdn3d.geometric.predict import GeometricPredictor
from sdn3d.math3d.camera import Intrinsics

SMALL = FitSettings(coarse_steps=2, fine_steps=2, coarse_size=16, fine_size=16, coarse_faces=0)
INTR = Intrinsics(60.0, 60.0, 48.0, 12.0, 96, 48)
BACK, FRONT = -math.pi / 2, math.pi / 2


def _grey_car(n: int = 1) -> tuple[torch.Tensor, torch.Tensor]:
    """``(crop (n, 3, 32, 32), mask (n, 1, 32, 32))``: a grey body with white head lights and no red anywhere."""
    crop, mask = torch.zeros(n, 3, 32, 32), torch.zeros(n, 1, 32, 32)
    mask[:, :, 8:24, 4:28] = 1.0
    crop[:, :, 8:24, 4:28] = 0.5
    crop[:, :, 16:18, 6:9] = 0.95
    crop[:, :, 16:18, 23:26] = 0.95
    return crop, mask


def test_a_large_car_without_red_lamps_is_turned_to_show_its_front():
    """An absence of tail lights is evidence enough to turn a back view (0.3, the old weight, never turned one)."""
    crop, mask = _grey_car()
    ray = torch.zeros(1)
    turned = face_by_lamps(torch.tensor([BACK]), ray, crop, mask)
    assert math.cos(float(turned[0]) - FRONT) > 0.99
    kept = face_by_lamps(torch.tensor([BACK]), ray, crop, mask, LampCue(absent_weight=0.3))
    assert math.cos(float(kept[0]) - BACK) > 0.99
    small = face_by_lamps(torch.tensor([BACK]), ray, crop, mask, LampCue(min_mask=10_000))  # too small: no cue
    assert math.cos(float(small[0]) - BACK) > 0.99


def test_the_predictor_says_what_it_saw_before_and_after_the_lamps():
    torch.manual_seed(0)
    predictor = GeometricPredictor(GeometricNet(rotation="multibin", hidden=16))
    crop, mask = _grey_car(4)
    box = torch.tensor([[10.0, 10.0, 40.0, 30.0], [50.0, 12.0, 80.0, 30.0], [20.0, 5.0, 60.0, 40.0],
                        [5.0, 5.0, 90.0, 45.0]])
    intr = torch.tensor([[60.0, 60.0, 48.0, 12.0]]).expand(4, 4)
    with_lamps = predictor.predict(crop, mask, box, intr)
    predictor.lamp_cue = None
    net_only = predictor.predict(crop, mask, box, intr)
    assert "net_ry" not in net_only and "lamp_usable" not in net_only
    assert torch.allclose(with_lamps["net_ry"], net_only["ry"])
    assert torch.allclose(with_lamps["ray"], ray_angle(box, intr))
    assert with_lamps["lamp_usable"].all() and not with_lamps["lamp_present"].any()
    # a lamp-less car is seen from the front: every yaw after the lamps shows the front
    assert bool((torch.sin(with_lamps["ry"] - with_lamps["ray"]) > 0).all())


def _reading(n: int = 1, present: bool = False) -> dict[str, torch.Tensor]:
    return {"lamp_present": torch.full((n,), present), "lamp_usable": torch.ones(n, dtype=torch.bool),
            "lamp_offset": torch.zeros(n)}


def _appearance(net_ry: float, ray: float, bins: torch.Tensor | None = None,
                reading: dict[str, torch.Tensor] | None = None) -> Appearance:
    values = {"net_ry": torch.tensor([net_ry]), "ray": torch.tensor([ray]), **(reading or {
        "lamp_present": torch.tensor([False]), "lamp_usable": torch.tensor([False]), "lamp_offset": torch.zeros(1)})}
    if bins is not None:
        values.update(yaw_bins=bins, yaw_residual=torch.tensor([[[1.0, 0.0]] * 4]), yaw_ray=torch.tensor([ray]))
    return Appearance(values, torch.tensor([True]))


def test_the_facing_belief_takes_the_lamps_over_the_net_and_the_bins_for_the_net():
    ry = torch.tensor([[-1.4, math.pi - 1.4]])  # ray 0: a back view and its reverse, a front view
    unread = _appearance(1.4, 0.0)  # no lamps to read: the net's yaw decides
    assert unread.belief(bins=False)(ry)[0].argmax() == 1
    no_lamps = _appearance(-1.4, 0.0, reading=_reading())  # the net says back, no red lamps on a readable crop
    score = no_lamps.belief(bins=False)(ry)[0]
    assert score.argmax() == 1 and torch.allclose(score[0], -score[1])
    back_bin = torch.tensor([[0.0, 0.0, 0.0, 9.0]])  # bin 3: alpha = -pi/2
    with_bins = _appearance(1.4, 0.0, back_bin)
    assert with_bins.belief(bins=True)(ry)[0].argmax() == 0 and with_bins.belief(bins=False)(ry)[0].argmax() == 1
    raw = {k: with_bins.values[k] for k in ("yaw_bins", "yaw_residual", "yaw_ray")}
    assert torch.allclose(facing_belief(with_bins.values)(ry), 0.3 * (2 * yaw_distribution(raw, ry) - 1))


def test_the_believed_end_wins_unless_the_silhouette_clearly_disagrees():
    loss = torch.tensor([[1.00, 0.80, 0.95], [1.00, 0.40, 0.95], [1.00, 0.80, 0.60], [1.0, 0.8, 0.9]])
    ry = torch.tensor([[0.0, math.pi, 0.1], [0.0, math.pi, 0.1], [0.0, math.pi, 1.6], [0.0, math.pi, 1.6]])
    belief = torch.tensor([[0.9, -0.9, 0.8], [0.9, -0.9, 0.8], [0.9, -0.9, 0.1], [0.2, -0.2, 0.0]])
    chosen = _choose(loss, belief, ry, FitSettings(facing_tie=0.5, tie=0.1))
    # 0: the reverse end is 20 % better, within 50 %: the believed end's two fits tie, the most believed wins
    # 1: the reverse end is more than 50 % better: the silhouette keeps it
    # 2: a fit across the axis (1.6) has no end-for-end counterpart: the best loss wins, the axis is the silhouette's
    # 3: a start nearly across the axis says little of the end (0.4 < FACING_MARGIN): the best loss wins
    assert chosen.tolist() == [0, 1, 2, 1]
    assert _choose(loss, belief, ry, FitSettings(facing_tie=0.0, tie=0.1)).tolist() == [1, 1, 2, 1]  # the old rule
    with pytest.raises(ValueError, match="facing_tie"):
        FitSettings(facing_tie=-0.1)


def test_the_box_fit_takes_the_branchs_belief():
    """The belief reaches the fit through the box objects: a net that saw the other end turns the chosen fit, though
    the fit starts from the same yaw (every fit ties, so only the belief decides)."""
    masks = torch.zeros(1, INTR.height, INTR.width, dtype=torch.bool)
    masks[0, 20:40, 30:70] = True
    settings = FitSettings(**{**SMALL.to_dict(), "tie": 10.0, "facing_tie": 0.0, "yaw_reg": 0.0, "appearance": True})
    boxes = BoxPrompts(torch.tensor([[30.0, 20.0, 70.0, 40.0]]), ("Car",), settings, masks=masks)
    start = 0.3
    ray = float(ray_angle(torch.tensor([[30.0, 20.0, 69.0, 39.0]]), torch.tensor([[60.0, 60.0, 48.0, 12.0]])))
    geometry = (torch.tensor([2]), torch.tensor([[4.0, 1.5, 1.7]], dtype=torch.float64),
                torch.tensor([start], dtype=torch.float64), torch.tensor([[0.0, 1.65, 8.0]], dtype=torch.float64),
                torch.zeros(1, 64, 3))
    rows = torch.tensor([0])
    yaws = {}
    for name, appearance in (("none", None), ("net", _appearance(start, ray)),
                             ("net turned", _appearance(start + math.pi, ray))):
        (_, _, ry, _, _), _ = _fit_boxes(INTR, masks, rows, boxes, geometry, 64, appearance)
        yaws[name] = float(ry[0])
    assert math.cos(yaws["none"] - start) > 0.5 and math.cos(yaws["net"] - start) > 0.5
    assert math.cos(yaws["net turned"] - start) < -0.5
    off = dataclasses.replace(boxes, fit=dataclasses.replace(settings, appearance=False))  # the default: not believed
    (_, _, ry, _, _), _ = _fit_boxes(INTR, masks, rows, off, geometry, 64, _appearance(start + math.pi, ray))
    assert math.cos(float(ry[0]) - start) > 0.5


def test_a_fit_without_a_belief_keeps_the_start_end_within_facing_tie():
    """No appearance: the start's end is believed (cos to the start), and the result faces it."""
    masks = torch.zeros(1, INTR.height, INTR.width, dtype=torch.bool)
    masks[0, 20:40, 30:70] = True
    for start in (0.3, 0.3 + math.pi):
        result = fit_to_masks(masks, torch.tensor([[30.0, 20.0, 70.0, 40.0]]), INTR, start_ry=torch.tensor([start]),
                              settings=FitSettings(**{**SMALL.to_dict(), "facing_tie": 100.0}))
        assert math.cos(float(result.ry[0]) - start) > 0
