"""A car cut by the image border at the end facing the camera (issue 40, session 23 border): that end's lamps lie
outside the picture, so "no red lamps" says nothing about the end, and the traffic's side speaks instead: in
right-hand traffic a car cut by the right border shows its back, one cut by the left border its front. Lamps that
are seen are read as before."""

from __future__ import annotations

import math

import pytest
import torch
from helpers.tiny_models import geometric_net

from sdn3d.geometric.facing import facing_belief
from sdn3d.geometric.lamps import LampCue, Traffic, border_side, evidence_of, face_by_reading
from sdn3d.geometric.predict import GeometricPredictor

# A back view whose back (its near end) lies to the right of its middle (alpha = -90 - 34 degrees: the car seen
# from behind and its left side), and its reverse, a front view whose front lies to the right.
BACK_RIGHT = -math.pi / 2 - 0.6
FRONT_RIGHT = BACK_RIGHT + math.pi
MIRROR = math.pi - FRONT_RIGHT  # the same end seen, its near end to the left


def _no_lamps(border: float | None, net_ry: float = FRONT_RIGHT, **reading) -> dict[str, torch.Tensor]:
    """One car's appearance: a readable crop without red lamps (ray 0, so ``ry = alpha``), the net believing
    ``net_ry``, cut by the ``border`` (+1 right, -1 left, 0 none; None: not read)."""
    values = {"net_ry": torch.tensor([net_ry]), "ray": torch.zeros(1), "lamp_present": torch.tensor([False]),
              "lamp_usable": torch.tensor([True]), "lamp_offset": torch.zeros(1)}
    values.update({k: torch.tensor([v]) for k, v in reading.items()})
    if border is not None:
        values["border_side"] = torch.tensor([border])
    return values


def test_border_side_names_the_border_that_cuts_a_box():
    boxes = torch.tensor([[0.0, 5, 40, 30], [200, 5, 311, 30], [0, 5, 311, 30], [9, 5, 40, 30], [-3, 5, 40, 30]])
    assert border_side(boxes, 312).tolist() == [-1.0, 1.0, 0.0, 0.0, -1.0]
    with pytest.raises(ValueError, match="box"):
        border_side(torch.zeros(4), 312)


def test_a_car_cut_by_the_right_border_without_lamps_is_believed_to_show_its_back():
    ry = torch.tensor([[BACK_RIGHT, FRONT_RIGHT]])
    cut = facing_belief(_no_lamps(1.0), LampCue(min_mask=0))(ry)[0]
    assert float(cut[0]) > 0 > float(cut[1])  # the back, against the net's front
    whole = facing_belief(_no_lamps(0.0), LampCue(min_mask=0))(ry)[0]
    unread = facing_belief(_no_lamps(None), LampCue(min_mask=0))(ry)[0]
    torch.testing.assert_close(whole, unread)  # not cut: as without a border reading
    assert float(whole[1]) > 0 > float(whole[0])  # ... where the absence says "front"
    # the traffic's side at the absence's weight, and the branch's own yaw turned by it
    lamps = evidence_of(torch.tensor([False]), torch.tensor([True]), torch.zeros(1), ry, LampCue(min_mask=0),
                        border=torch.tensor([1.0]))
    torch.testing.assert_close(lamps, 0.5 * torch.tensor([[math.sin(-BACK_RIGHT), math.sin(-FRONT_RIGHT)]]))
    red = (torch.tensor([False]), torch.tensor([True]), torch.zeros(1))
    turned = face_by_reading(torch.tensor([FRONT_RIGHT]), torch.zeros(1), red, None, LampCue(), torch.tensor([1.0]))
    assert math.sin(float(turned[0])) < -0.5
    kept = face_by_reading(torch.tensor([FRONT_RIGHT]), torch.zeros(1), red, None, LampCue(), None)
    assert math.sin(float(kept[0])) > 0.5


def test_the_left_border_the_other_traffic_and_no_side():
    # cut by the left border, its near end on the left (the mirror's axis): the front is believed
    ry = torch.tensor([[MIRROR, MIRROR + math.pi]])
    left = facing_belief(_no_lamps(-1.0, net_ry=MIRROR + math.pi), LampCue(min_mask=0))(ry)[0]
    assert float(left[0]) > 0 > float(left[1])
    # left-hand traffic: a car cut by the right border shows its front; no side: the absence counts nothing
    ry = torch.tensor([[BACK_RIGHT, FRONT_RIGHT]])
    present, usable, offset = torch.tensor([False]), torch.tensor([True]), torch.zeros(1)
    border = torch.tensor([1.0])
    right = evidence_of(present, usable, offset, ry, LampCue(traffic=Traffic.RIGHT), border=border)
    torch.testing.assert_close(evidence_of(present, usable, offset, ry, LampCue(traffic="left"), border=border),
                               -right)
    none = evidence_of(present, usable, offset, ry, LampCue(traffic=Traffic.NONE), border=border)
    torch.testing.assert_close(none, torch.zeros_like(none))


def test_seen_lamps_read_as_before_and_the_depth_reflection_follows_the_traffic_side():
    cue = LampCue(min_mask=0)
    border = torch.tensor([1.0])
    # red lamps seen on a cut car: the back, as without the border
    present, usable, offset = torch.tensor([True]), torch.tensor([True]), torch.tensor([0.2])
    ry = torch.tensor([[BACK_RIGHT, FRONT_RIGHT, MIRROR, MIRROR + math.pi]])
    torch.testing.assert_close(evidence_of(present, usable, offset, ry, cue, border=border),
                               evidence_of(present, usable, offset, ry, cue))
    # no lamps, cut by the right border, at hypotheses that put the near end inwards (the silhouette's depth
    # reflection of the true axis): the absence is not read there either, the back is believed
    absent = torch.tensor([False])
    mirror = torch.tensor([[MIRROR + math.pi, MIRROR]])  # a back view and its reverse
    cut = evidence_of(absent, usable, offset, mirror, cue, border=border)[0]
    assert float(cut[0]) > 0 > float(cut[1])
    whole = evidence_of(absent, usable, offset, mirror, cue)[0]
    assert float(whole[1]) > 0 > float(whole[0])


def test_a_cut_red_body_without_headlights_follows_the_traffic_side_too():
    values = _no_lamps(-1.0, net_ry=MIRROR, front_present=False, front_usable=True, front_offset=0.0)
    values["lamp_usable"] = torch.tensor([False])  # a red body: the red test cannot read it
    ry = torch.tensor([[MIRROR, MIRROR + math.pi]])  # near end on the left: a front and its reverse, a back
    cut = facing_belief(values, LampCue(min_mask=0))(ry)[0]
    assert float(cut[0]) > 0 > float(cut[1])  # the front (the traffic's side)
    del values["border_side"]
    whole = facing_belief(values, LampCue(min_mask=0))(ry)[0]
    assert float(whole[1]) > float(whole[0])  # no headlights read as a back where the border is not read


def test_the_predictor_reads_the_border_with_the_image_width():
    torch.manual_seed(0)
    predictor = GeometricPredictor(geometric_net(), lamp_cue=LampCue(min_mask=50))
    crop = torch.full((3, 3, 32, 32), 0.45)
    crop[:, :, 6:10, 8:24] = 0.08
    mask = torch.zeros(3, 1, 32, 32)
    mask[:, :, 4:26, 5:27] = 1
    box = torch.tensor([[0.0, 20.0, 30.0, 36.0], [120.0, 22.0, 159.0, 34.0], [60.0, 22.0, 90.0, 34.0]])
    intr = torch.tensor([[100.0, 100.0, 80.0, 32.0]]).expand(3, 4)
    out = predictor.predict(crop * mask, mask, box, intr, image_width=160)
    assert out["border_side"].tolist() == [-1.0, 1.0, 0.0]
    red = (out["lamp_present"], out["lamp_usable"], out["lamp_offset"])
    white = (out["front_present"], out["front_usable"], out["front_offset"])
    torch.testing.assert_close(out["ry"], face_by_reading(out["net_ry"], out["ray"], red, white,
                                                          predictor.lamp_cue, out["border_side"]))
    assert "border_side" not in predictor.predict(crop * mask, mask, box, intr)


@pytest.mark.parametrize("traffic", ["sideways", 1, ["right"]])
def test_an_unknown_traffic_side_is_refused_by_name(traffic):
    with pytest.raises(ValueError, match="traffic"):
        LampCue(traffic=traffic)
