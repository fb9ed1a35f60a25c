"""A red body's near-white pixels weigh less than red tail lamps (issue 40, session 22 flip): rain streaks and a
red body's paler tail lamps pass the headlights' test as often as headlights do, so a presence counts
``LampCue.headlight_weight`` of the lamps' evidence: it does not turn the branch's yaw by itself, and in the fit's
belief it weighs as much as sure MultiBin bins, while an absence of headlights still reads as a back."""

from __future__ import annotations

import math

import pytest
import torch

from sdn3d.geometric.facing import facing_belief
from sdn3d.geometric.fit import FACING_MARGIN
from sdn3d.geometric.lamps import LampCue, face_by_lamps, lamp_evidence, white_lamps

BACK, FRONT = -math.pi / 2, math.pi / 2


def _red_back_in_rain(n: int = 1) -> tuple[torch.Tensor, torch.Tensor]:
    """``(crop (n, 3, 32, 32), mask (n, 1, 32, 32))``: a red body seen from behind, dark glass on top, crossed low
    by two near-white rain streaks (one column each, several rows): no headlights, but the test's white pixels."""
    crop, mask = torch.zeros(n, 3, 32, 32), torch.zeros(n, 1, 32, 32)
    mask[:, :, 8:24, 4:28] = 1.0
    crop[:, 0, 8:24, 4:28] = 0.7
    crop[:, 1:, 8:24, 4:28] = 0.08
    crop[:, :, 9:13, 8:24] = 0.1  # glass
    crop[:, :, 17:23, 9] = 0.9  # rain streaks in the lower half
    crop[:, :, 16:22, 21] = 0.9
    return crop, mask


def test_near_white_pixels_on_a_red_back_do_not_turn_the_branchs_yaw():
    crop, mask = _red_back_in_rain()
    cue = LampCue(min_mask=0)
    present, usable, _ = white_lamps(crop, mask, cue)
    assert bool(present[0]) and bool(usable[0])  # the streaks pass the headlights' test
    kept = face_by_lamps(torch.tensor([BACK]), torch.zeros(1), crop, mask, cue)
    assert math.sin(float(kept[0])) < -0.99  # the net's back view stands
    full = face_by_lamps(torch.tensor([BACK]), torch.zeros(1), crop, mask, LampCue(min_mask=0, headlight_weight=1.0))
    assert math.sin(float(full[0])) > 0.99  # at the red lamps' weight the streaks turned it to a front
    # the presence still says "front": its evidence is the red lamps' times the weight
    alphas = torch.tensor([[FRONT, BACK]])
    scaled, whole = lamp_evidence(crop, mask, alphas, cue), lamp_evidence(crop, mask, alphas, LampCue(
        min_mask=0, headlight_weight=1.0))
    torch.testing.assert_close(scaled, cue.headlight_weight * whole)
    assert float(scaled[0, 0]) > 0 > float(scaled[0, 1])


def test_sure_bins_against_a_headlight_reading_leave_the_end_to_the_silhouette():
    """The bins sure of a back view (all confidence on alpha = -90 degrees) against near-white pixels: neither end
    is believed more by the fit's FACING_MARGIN, so the silhouette decides; at full weight the pixels decided."""
    values = {"net_ry": torch.tensor([BACK]), "ray": torch.zeros(1), "lamp_present": torch.tensor([False]),
              "lamp_usable": torch.tensor([False]), "lamp_offset": torch.zeros(1),
              "front_present": torch.tensor([True]), "front_usable": torch.tensor([True]),
              "front_offset": torch.zeros(1),
              # 4 bins (centres 0, 90, 180, 270 degrees): all confidence on the fourth, alpha = -90 degrees
              "yaw_bins": torch.tensor([[-20.0, -20.0, -20.0, 20.0]]),
              "yaw_residual": torch.tensor([[[1.0, 0.0]] * 4]), "yaw_ray": torch.zeros(1)}
    ry = torch.tensor([[BACK, FRONT]])
    belief = facing_belief(values, LampCue(min_mask=0))(ry)[0]
    assert abs(float(belief[0] - belief[1])) < FACING_MARGIN
    old = facing_belief(values, LampCue(min_mask=0, headlight_weight=1.0))(ry)[0]
    assert float(old[1] - old[0]) >= FACING_MARGIN


def test_no_headlights_on_a_red_body_still_read_as_a_back():
    crop, mask = _red_back_in_rain()
    crop[:, :, 16:23, [9, 21]] = crop[:, :, 16:23, [10, 20]]  # the streaks gone
    cue = LampCue(min_mask=0)
    assert not bool(white_lamps(crop, mask, cue)[0][0])
    turned = face_by_lamps(torch.tensor([FRONT]), torch.zeros(1), crop, mask, cue)
    assert math.sin(float(turned[0])) < -0.99  # a front prediction turned to the back, as before


@pytest.mark.parametrize("weight", [-0.1, 1.5])
def test_a_headlight_weight_outside_zero_to_one_is_refused_by_name(weight):
    with pytest.raises(ValueError, match="headlight_weight"):
        LampCue(headlight_weight=weight)
