"""A red body's headlights (geometric/lamps.py ``white_lamps``): a rain streak's few near-white pixels across a red
car's back are not headlights; a pair of lamps is (``LampCue.white_min_share``, session 35)."""

from __future__ import annotations

import torch

from sdn3d.geometric.lamps import LampCue, white_lamps


def red_back(size: int = 40) -> tuple[torch.Tensor, torch.Tensor]:
    """``(crop (1, 3, S, S), mask (1, 1, S, S))``: a red body filling the crop (a car's back seen close)."""
    crop = torch.zeros(1, 3, size, size)
    crop[:, 0] = 0.7
    crop[:, 1:] = 0.08
    return crop, torch.ones(1, 1, size, size)


def test_a_rain_streak_across_a_red_back_is_not_headlights() -> None:
    crop, mask = red_back()
    for i in range(6):  # a thin slanted streak in the lower half: 6 pixels, 0.4 % of the mask
        crop[0, :, 24 + i, 10 + i // 3] = 0.9
    present, usable, _ = white_lamps(crop, mask)
    assert bool(usable[0]) and not bool(present[0])
    # the former threshold (0.1 % of the mask) read it as headlights
    assert bool(white_lamps(crop, mask, LampCue(white_min_share=0.001))[0][0])


def test_a_pair_of_headlights_on_a_red_front_is_read() -> None:
    crop, mask = red_back()
    crop[0, :, 28:31, 4:8] = 0.95  # two lamps of 3 x 4 pixels: 1.5 % of the mask
    crop[0, :, 28:31, 32:36] = 0.95
    present, usable, offset = white_lamps(crop, mask)
    assert bool(present[0]) and bool(usable[0]) and abs(float(offset[0])) < 0.05
    # one lamp alone, the other end's side hidden: still read, and on its side
    crop, mask = red_back()
    crop[0, :, 28:31, 30:36] = 0.95
    present, _, offset = white_lamps(crop, mask)
    assert bool(present[0]) and float(offset[0]) > 0.2
