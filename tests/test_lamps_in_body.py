"""A red body's headlights are read in the body only (issue 40, session 25 pose40).

The headlight test (:func:`sdn3d.geometric.lamps.white_lamps`) read every near-white pixel of a red body's mask's lower
half as a headlight: on the semantic branch's proposals, which spill past a car onto the road, a lane marking beside
a red van's back was its "headlights", and the fit turned it end for end. A headlight sits in the body: between the
leftmost and the rightmost red pixel of the rows near its own (:func:`~sdn3d.geometric.lamps.in_the_body`; a lamp at
the body's corner has the bumper or the bonnet beside it), and only those pixels count now.
"""

from __future__ import annotations

import math

import pytest
import torch
from helpers.tiny_models import geometric_net

import sdn3d.derender as dr
from sdn3d.geometric.lamps import LampCue, in_the_body, lamp_evidence, white_lamps
from sdn3d.geometric.predict import GeometricPredictor
from sdn3d.math3d.camera import Intrinsics
from sdn3d.models import Models

BACK, FRONT = -math.pi / 2, math.pi / 2
RED = torch.tensor([0.75, 0.08, 0.08])


def _red_body(lamps: bool, marking: bool) -> tuple[torch.Tensor, torch.Tensor]:
    """``(crop (1, 3, 32, 32), mask (1, 1, 32, 32))``: a red body (rows 8-23, columns 10-27), dark glass on top;
    with ``lamps`` two near-white headlights low in it (a front view); with ``marking`` the mask spills left of its
    lower half (columns 2-9) onto grey road with a white lane marking (columns 5-6), as a semantic proposal does."""
    crop, mask = torch.full((1, 3, 32, 32), 0.4), torch.zeros(1, 1, 32, 32)
    mask[:, :, 8:24, 10:28] = 1.0
    crop[0, :, 8:24, 10:28] = RED[:, None, None]
    crop[0, :, 9:13, 13:25] = 0.05  # glass
    if lamps:
        crop[0, :, 18:20, 12:15] = 0.9
        crop[0, :, 18:20, 23:26] = 0.9
    if marking:
        mask[:, :, 16:24, 2:10] = 1.0
        crop[0, :, 16:24, 5:7] = 0.95
    return crop, mask


def test_in_the_body_is_between_the_red_of_the_rows_near_a_pixel():
    red = torch.zeros(1, 5, 8, dtype=torch.bool)
    red[0, 0, [2, 5]] = True  # row 0: red at columns 2 and 5
    red[0, 1, 3] = True  # row 1: one red pixel
    inside = in_the_body(red, 0)
    assert inside[0, 0].nonzero().flatten().tolist() == [2, 3, 4, 5]
    assert inside[0, 1].nonzero().flatten().tolist() == [3]
    assert not bool(inside[0, 2].any())  # no red on the row: nothing is in the body
    near = in_the_body(red, 1)
    assert near[0, 1].nonzero().flatten().tolist() == [2, 3, 4, 5]  # row 0's red one row away
    assert near[0, 2].nonzero().flatten().tolist() == [3]  # row 1's
    assert not bool(near[0, 4].any())  # no red within a row


def test_a_lane_marking_beside_a_red_back_is_no_headlight():
    cue = LampCue(min_mask=0)
    crop, mask = _red_body(lamps=False, marking=True)
    present, usable, _ = white_lamps(crop, mask, cue)
    assert bool(usable[0]) and not bool(present[0])  # main read the marking as headlights
    # so the back view is believed: no headlights on a red body
    evidence = lamp_evidence(crop, mask, torch.tensor([[BACK, FRONT]]), cue)[0]
    assert float(evidence[0]) > 0 > float(evidence[1])


def test_headlights_in_a_red_front_are_read_as_before():
    cue = LampCue(min_mask=0)
    for marking in (False, True):
        crop, mask = _red_body(lamps=True, marking=marking)
        present, usable, offset = white_lamps(crop, mask, cue)
        assert bool(present[0]) and bool(usable[0])
    crop, mask = _red_body(lamps=True, marking=False)
    crop[0, :, 18:20, 23:26] = RED[:, None, None]  # only the left headlight: its offset is to the left
    assert float(white_lamps(crop, mask, cue)[2][0]) < 0
    evidence = lamp_evidence(crop, mask, torch.tensor([[BACK, FRONT]]), cue)[0]
    assert float(evidence[1]) > 0 > float(evidence[0])


def test_headlights_at_the_body_corners_count():
    """A front view whose headlights end the body's row (no red beyond them on their rows): the bumper below them
    spans the body's width, so they lie in the body."""
    cue = LampCue(min_mask=0)
    crop, mask = _red_body(lamps=False, marking=False)
    crop[0, :, 18:20, 10:13] = 0.9  # at the body's left end ...
    crop[0, :, 18:20, 25:28] = 0.9  # ... and at its right end
    present, usable, offset = white_lamps(crop, mask, cue)
    assert bool(present[0]) and bool(usable[0]) and abs(float(offset[0])) < 0.05  # both, one each side
    crop[0, :, 20:24, 10:28] = 0.05  # no red below them (a dark bumper): only the rows beside them, none beyond
    crop[0, :, 16:18, 10:28] = 0.05
    assert not bool(white_lamps(crop, mask, cue)[0][0])


@pytest.mark.parametrize("rows", [-0.1, 1.5, True, "2"])
def test_a_headlight_rows_share_outside_zero_to_one_is_refused_by_name(rows):
    with pytest.raises(ValueError, match="headlight_rows"):
        LampCue(headlight_rows=rows)


def test_a_rain_streak_across_the_body_still_counts():
    """The rule is about the body, not the pixels' shape: a near-white streak across the red paint still passes
    (what LampCue.headlight_weight is for)."""
    crop, mask = _red_body(lamps=False, marking=False)
    crop[0, :, 16:23, 18] = 0.9
    assert bool(white_lamps(crop, mask, LampCue(min_mask=0))[0][0])


def test_the_proposals_reading_in_derender_drops_the_marking():
    """The branch's reading of a spilt proposal (:func:`sdn3d.derender._geometry`, the predictor's lamp cue): no
    headlights on the red back whose mask spills onto a lane marking, without the fit's re-reading."""
    intr = Intrinsics(fx=150.0, fy=150.0, cx=80.0, cy=32.0, width=160, height=64)
    image = torch.full((3, 64, 160), 0.4)
    masks = torch.zeros(1, 64, 160, dtype=torch.bool)
    masks[0, 20:44, 60:100] = True
    image[:, 20:44, 60:100] = RED[:, None, None]
    image[:, 22:28, 66:94] = 0.05  # the rear window
    masks[0, 34:44, 48:60] = True  # the road beside the car ...
    image[:, 34:44, 52:55] = 0.95  # ... with a lane marking
    torch.manual_seed(0)
    models = Models(geometric=GeometricPredictor(geometric_net(), lamp_cue=LampCue(min_mask=50)), crop_size=48,
                    margin=0.1)
    _, appearance = dr._geometry(image, intr, masks, torch.tensor([12001]), None, models, 1, None)
    assert bool(appearance.values["front_usable"][0]) and not bool(appearance.values["front_present"][0])
