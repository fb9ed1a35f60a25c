"""Red pixels in the roof's rows are not tail lamps (issue 40, session 34): the semantic branch's proposals spill up
and sideways onto red-bordered road signs, and the red-lamp test read the sign as tail lamps on front views and, on
back views, the sign's rows joined the lamps' and failed the one-band test. ``LampCue.lamp_top`` leaves the top
share of the mask's rows out of the test."""

from __future__ import annotations

import math

import pytest
import torch

from sdn3d.geometric.lamps import LampCue, face_by_lamps, red_lamps

BACK, FRONT = -math.pi / 2, math.pi / 2


def _grey_car(sign: bool, lamps: bool) -> tuple[torch.Tensor, torch.Tensor]:
    """``(crop (1, 3, 32, 32), mask (1, 1, 32, 32))``: a grey car (rows 10-29) and, with ``sign``, the proposal's
    spill onto a red sign above its roof (rows 4-7, the mask's top); with ``lamps``, two red tail lamps at about the
    middle of the car's height."""
    crop, mask = torch.full((1, 3, 32, 32), 0.05), torch.zeros(1, 1, 32, 32)
    mask[:, :, 10:30, 4:28] = 1.0
    crop[:, :, 10:30, 4:28] = 0.55
    crop[:, :, 11:16, 8:24] = 0.08  # the rear or front glass
    crop[:, :, 26:30, 5:9] = 0.05  # tyres
    crop[:, :, 26:30, 23:27] = 0.05
    if lamps:
        crop[:, 0, 19:21, 6:9], crop[:, 1:, 19:21, 6:9] = 0.8, 0.1
        crop[:, 0, 19:21, 23:26], crop[:, 1:, 19:21, 23:26] = 0.8, 0.1
    if sign:
        mask[:, :, 4:10, 18:26] = 1.0
        crop[:, :, 4:10, 18:26] = 0.9  # the sign's white face ...
        crop[:, 0, 4:8, 18:26], crop[:, 1:, 4:8, 18:26] = 0.8, 0.1  # ... under its red border
    return crop, mask


def test_a_red_sign_above_a_front_view_is_not_read_as_tail_lamps():
    crop, mask = _grey_car(sign=True, lamps=False)
    present, usable, _ = red_lamps(crop, mask, LampCue(min_mask=0))
    assert bool(usable[0]) and not bool(present[0])  # no lamps: the front is seen
    kept = face_by_lamps(torch.tensor([FRONT]), torch.zeros(1), crop, mask, LampCue(min_mask=0))
    assert math.sin(float(kept[0])) > 0.99
    # every row read (0): the sign's red passes as lamps and turns the front view to a back
    every_row = LampCue(min_mask=0, lamp_top=0.0)
    assert bool(red_lamps(crop, mask, every_row)[0][0])
    turned = face_by_lamps(torch.tensor([FRONT]), torch.zeros(1), crop, mask, every_row)
    assert math.sin(float(turned[0])) < -0.99


def test_a_back_views_lamps_stay_one_band_under_a_red_sign():
    crop, mask = _grey_car(sign=True, lamps=True)
    present, usable, offset = red_lamps(crop, mask, LampCue(min_mask=0))
    assert bool(present[0]) and bool(usable[0])
    assert abs(float(offset[0])) < 0.1  # the two lamps, not the sign at the right
    every_row = red_lamps(crop, mask, LampCue(min_mask=0, lamp_top=0.0))
    assert bool(every_row[0][0]) and not bool(every_row[1][0])  # the sign's rows spread the band: unusable


def test_without_a_spill_the_reading_is_the_same_whatever_lamp_top():
    for lamps in (False, True):
        crop, mask = _grey_car(sign=False, lamps=lamps)
        a, b = red_lamps(crop, mask, LampCue(min_mask=0)), red_lamps(crop, mask, LampCue(min_mask=0, lamp_top=0.0))
        for x, y in zip(a, b, strict=True):
            torch.testing.assert_close(x, y)


@pytest.mark.parametrize("value", [-0.1, 1.0, True, "0.3"])
def test_a_lamp_top_outside_zero_to_one_is_refused_by_name(value):
    with pytest.raises(ValueError, match="lamp_top"):
        LampCue(lamp_top=value)
