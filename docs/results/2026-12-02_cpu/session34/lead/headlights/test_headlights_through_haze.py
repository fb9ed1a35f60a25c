"""A red body's near-white pixels seen through haze are no reading (issue 40, session 34): in rain they were on nine
back views and five front views of the tuning trees' red bodies, so where the air a crop shows
(:func:`~sdn3d.geometric.lamps.air_offset`) is over ``LampCue.headlight_max_air`` the headlights' test says nothing
either way, and the MultiBin bins and the silhouette decide; in clear air it reads as before."""

from __future__ import annotations

import math

import pytest
import torch

from sdn3d.geometric.lamps import LampCue, air_offset, face_by_lamps, lamp_evidence, white_lamps

BACK, FRONT = -math.pi / 2, math.pi / 2


def _red_body_with_near_white_low(air: float) -> tuple[torch.Tensor, torch.Tensor]:
    """``(crop (1, 3, 32, 32), mask (1, 1, 32, 32))``: a red body, dark glass on top, two near-white columns in its
    lower half (rain streaks or headlights: the test cannot tell), seen through ``air`` (``observed = t albedo +
    air`` with ``t = 1 - air``)."""
    crop, mask = torch.zeros(1, 3, 32, 32), torch.zeros(1, 1, 32, 32)
    mask[:, :, 8:24, 4:28] = 1.0
    crop[:, 0, 8:24, 4:28] = 0.7
    crop[:, 1:, 8:24, 4:28] = 0.08
    crop[:, :, 9:13, 8:24] = 0.05  # glass
    crop[:, :, 17:23, 9] = 0.95
    crop[:, :, 16:22, 21] = 0.95
    return crop * (1 - air) + air, mask


def test_the_scene_has_the_air_it_is_built_with():
    for air in (0.0, 0.05, 0.3):
        crop, mask = _red_body_with_near_white_low(air)
        measured = float(air_offset(crop, mask[:, 0] > 0.5, LampCue().clear_dark)[0].mean())
        assert (measured == 0.0) if air == 0.0 else (measured < 0.15 if air < 0.1 else measured > 0.15)


def test_near_white_pixels_through_haze_are_no_reading():
    crop, mask = _red_body_with_near_white_low(0.3)
    cue = LampCue(min_mask=0)
    present, usable, _ = white_lamps(crop, mask, cue)
    assert bool(present[0]) and not bool(usable[0])  # seen, but not read
    alphas = torch.tensor([[FRONT, BACK]])
    assert lamp_evidence(crop, mask, alphas, cue).abs().max() == 0  # no say for either end
    for start in (BACK, FRONT):  # the branch's yaw stands either way
        kept = face_by_lamps(torch.tensor([start]), torch.zeros(1), crop, mask, cue)
        assert math.isclose(float(kept[0]), start, abs_tol=1e-6)
    # read in any air (None), the same pixels say "front" and turn a back view round at full weight
    anywhere = LampCue(min_mask=0, headlight_max_air=None, headlight_weight=1.0)
    assert bool(white_lamps(crop, mask, anywhere)[1][0])
    turned = face_by_lamps(torch.tensor([BACK]), torch.zeros(1), crop, mask, anywhere)
    assert math.sin(float(turned[0])) > 0.99


@pytest.mark.parametrize("air", [0.0, 0.05])
def test_in_clear_or_light_air_the_headlights_are_read_as_before(air):
    crop, mask = _red_body_with_near_white_low(air)
    cue, anywhere = LampCue(min_mask=0), LampCue(min_mask=0, headlight_max_air=None)
    reading = white_lamps(crop, mask, cue)
    assert bool(reading[0][0]) and bool(reading[1][0])
    for a, b in zip(reading, white_lamps(crop, mask, anywhere), strict=True):
        torch.testing.assert_close(a, b)


def test_an_absence_through_haze_still_reads_as_a_back():
    crop, mask = _red_body_with_near_white_low(0.3)
    crop[:, :, 16:23, [9, 21]] = crop[:, :, 16:23, [10, 20]]  # no near-white pixels
    present, usable, _ = white_lamps(crop, mask, LampCue(min_mask=0))
    assert not bool(present[0]) and bool(usable[0])
    turned = face_by_lamps(torch.tensor([FRONT]), torch.zeros(1), crop, mask, LampCue(min_mask=0))
    assert math.sin(float(turned[0])) < -0.99


@pytest.mark.parametrize("value", [-0.1, 1.5, True, "0.1"])
def test_a_headlight_max_air_outside_zero_to_one_is_refused_by_name(value):
    with pytest.raises(ValueError, match="headlight_max_air"):
        LampCue(headlight_max_air=value)
