"""The red-lamp cue read through haze (issue 40): fog and rain add the air's light to every pixel of a car, so a tail
lamp's red over green falls below the cue's ratio; :func:`sdn3d.geometric.lamps.air_offset` takes the air off."""

import math

import torch

from sdn3d.geometric.lamps import LampCue, air_offset, face_by_lamps, red_lamps, white_lamps

LAMP = (0.78, 0.32, 0.34)  # a tail lamp as the Virtual KITTI clone frames show it


def _car(body: tuple[float, float, float], lamps: bool = True) -> tuple[torch.Tensor, torch.Tensor]:
    """``(crop (1, 3, 32, 32), mask (1, 1, 32, 32))``: a car in clear air seen from behind: its body, dark tyres
    and glass (0.10, as dark as the clone frames show them) in the top and bottom rows, and (``lamps``) two red tail
    lamps at one height near its sides."""
    crop, mask = torch.zeros(1, 3, 32, 32), torch.zeros(1, 1, 32, 32)
    mask[..., 8:28, 2:30] = 1
    crop[0, :, 8:28, 2:30] = torch.tensor(body)[:, None, None]
    crop[0, :, 8:12, 6:26] = 0.10  # glass
    crop[0, :, 25:28, 3:9] = 0.10  # tyres
    crop[0, :, 25:28, 23:29] = 0.10
    if lamps:
        crop[0, :, 17:19, 4:7] = torch.tensor(LAMP)[:, None, None]
        crop[0, :, 17:19, 25:28] = torch.tensor(LAMP)[:, None, None]
    return crop, mask


def _haze(crop: torch.Tensor, mask: torch.Tensor, t: float, air: float) -> torch.Tensor:
    """``observed = t albedo + (1 - t) air`` on the car's pixels (the crop is masked, as the branch reads it)."""
    return (t * crop + (1 - t) * air) * mask


def test_red_lamps_are_read_through_fog_and_rain():
    crop, mask = _car((0.55, 0.56, 0.6))
    clear = [v.tolist() for v in red_lamps(crop, mask, LampCue(min_mask=0))]
    assert clear[:2] == [[True], [True]]
    for t, air in ((0.6, 0.75), (0.3, 0.82)):  # rain; thick fog
        hazy = _haze(crop, mask, t, air)
        old = red_lamps(hazy, mask, LampCue(min_mask=0, clear_dark=None))
        assert not bool(old[0][0])  # the plain ratio test finds no red lamp: a back view read as a front
        new = [v.tolist() for v in red_lamps(hazy, mask, LampCue(min_mask=0))]
        assert new[:2] == [[True], [True]] and math.isclose(new[2][0], clear[2][0], abs_tol=1e-6)
        # the branch's yaw showing the front is turned end for end, as in clear air
        ry = face_by_lamps(torch.tensor([math.pi / 2]), torch.zeros(1), hazy, mask, LampCue(min_mask=0))
        assert math.cos(float(ry[0]) + math.pi / 2) > 0.99


def test_hazy_orange_and_tan_bodies_without_lamps_are_not_red():
    for body in ((0.56, 0.36, 0.16), (0.7, 0.57, 0.43)):  # orange and tan paint: red over green 1.6 and 1.2
        crop, mask = _car(body, lamps=False)
        for t, air in ((1.0, 0.0), (0.6, 0.75), (0.3, 0.82)):
            present, usable, _ = red_lamps(_haze(crop, mask, t, air), mask, LampCue(min_mask=0))
            assert not bool(present[0]) and bool(usable[0]), (body, t)


def test_clear_air_is_read_as_before_and_the_air_estimate():
    crop, mask = _car((0.55, 0.56, 0.6))
    air, t = air_offset(crop, mask[:, 0] > 0.5, 0.10)
    assert air.abs().max() == 0 and t.tolist() == [1.0]  # darks at 0.10: clear air, nothing taken off
    hazy = _haze(crop, mask, 0.5, 0.8)
    air, t = air_offset(hazy, mask[:, 0] > 0.5, 0.10)
    assert torch.allclose(air, torch.full((1, 3), 0.4), atol=0.02)  # (1 - t) air, solved from the darks
    assert 0.3 < float(t[0]) < 0.7
    empty = air_offset(crop, torch.zeros(1, 32, 32, dtype=torch.bool), 0.10)
    assert empty[0].abs().max() == 0 and empty[1].tolist() == [1.0]
    assert [v.shape for v in red_lamps(crop[:0], mask[:0])] == [(0,)] * 3  # no objects
    gen = torch.Generator().manual_seed(0)
    crops = torch.rand(20, 3, 32, 32, generator=gen) * 0.9 + 0.05
    crops[:, :, :4] = 0.02  # every crop has clear-air darks
    masks = torch.ones(20, 1, 32, 32)
    for a, b in zip(red_lamps(crops, masks, LampCue(min_mask=0)),
                    red_lamps(crops, masks, LampCue(min_mask=0, clear_dark=None)), strict=True):
        assert torch.equal(a, b)


def test_a_fogged_red_body_without_headlights_is_not_read_as_white_lamps():
    crop, mask = _car((0.7, 0.2, 0.2), lamps=False)  # a red car seen from behind (its lamps lost in the paint)
    fog = _haze(crop, mask, 0.3, 0.85)  # the body reads (0.81, 0.66, 0.66): near-white in the plain test
    old = white_lamps(fog, mask, LampCue(min_mask=0, clear_dark=None))
    assert not bool(old[1][0])  # plainly the fogged body is not even red: the headlight cue is not used
    present, usable, _ = white_lamps(fog, mask, LampCue(min_mask=0))
    assert bool(usable[0]) and not bool(present[0])  # through the air: a red body, no white lamps (a back view)
