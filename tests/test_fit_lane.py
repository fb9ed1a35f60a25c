"""Issue 40, sessions 38-39: the fit drawn towards the road's axis where each car stands
(:func:`sdn3d.road_heading.road_axes`, :attr:`sdn3d.geometric.fit.FitSettings.lane_reg` for sharp outlines and
``proposal_lane_reg`` for the semantic branch's proposals)."""

from __future__ import annotations

import math

import pytest
import torch

from sdn3d.geometric.fit import FitRequest, FitSettings, fit_many, fit_to_masks, lane_prior
from sdn3d.math3d.camera import Intrinsics
from sdn3d.road_heading import axis_yaw, road_axes

INTR = Intrinsics(60.0, 60.0, 48.0, 12.0, 96, 48)
#: A small fit that still moves a yaw by tens of degrees (the search's four starts, the fine stage's Adam).
FIT = FitSettings(coarse_size=24, fine_size=32, parts=1, coarse_faces=0)


def _off_axis(ry: float, axis: float) -> float:
    """Degrees between the yaw ``ry`` and the axis ``axis`` (either end)."""
    return abs(math.degrees(math.asin(max(-1.0, min(1.0, math.sin(ry - axis))))))


def _blob():
    """A car-sized rounded outline straight ahead: it fits a car seen from behind, or turned a little, about as well."""
    masks = torch.zeros(1, INTR.height, INTR.width, dtype=torch.bool)
    masks[0, 18:40, 36:62] = True
    return masks, torch.tensor([[36.0, 18.0, 62.0, 40.0]])


@pytest.mark.parametrize("start_deg", [-56.0, -124.0])
def test_the_roads_axis_draws_an_ambiguous_outlines_fit_to_it(start_deg):
    """A prediction 34 degrees off the road's axis: with the road given (and a weight that makes the pull plain)
    the fit ends on the axis; without it, where the outline and the prediction left it."""
    masks, boxes = _blob()
    start = torch.tensor([math.radians(start_deg)])
    axis = -math.pi / 2
    pulled = fit_to_masks(masks, boxes, INTR, settings=FitSettings(**{**FIT.to_dict(), "lane_reg": 1.0}),
                          start_ry=start, road_ry=torch.tensor([axis]))
    free = fit_to_masks(masks, boxes, INTR, settings=FitSettings(**{**FIT.to_dict(), "lane_reg": 1.0}),
                        start_ry=start)
    assert _off_axis(float(pulled.ry[0]), axis) < 3.0
    assert _off_axis(float(free.ry[0]), axis) > 5.0


def test_an_unknown_road_or_no_weight_changes_no_fit():
    """A NaN axis (the edges did not tell) and ``lane_reg`` 0 give the fit without a road, bit for bit."""
    masks, boxes = _blob()
    start = torch.tensor([math.radians(-56.0)])
    plain = fit_to_masks(masks, boxes, INTR, settings=FIT, start_ry=start)
    unknown = fit_to_masks(masks, boxes, INTR, settings=FIT, start_ry=start, road_ry=torch.tensor([math.nan]))
    unweighted = fit_to_masks(masks, boxes, INTR, settings=FitSettings(**{**FIT.to_dict(), "lane_reg": 0.0}),
                              start_ry=start, road_ry=torch.tensor([-math.pi / 2]))
    for other in (unknown, unweighted):
        assert torch.equal(other.ry, plain.ry) and torch.equal(other.location, plain.location)
        assert torch.equal(other.loss, plain.loss)
    with pytest.raises(ValueError, match="road_ry"):
        fit_to_masks(masks, boxes, INTR, settings=FIT, start_ry=start, road_ry=torch.zeros(2))
    with pytest.raises(ValueError, match="lane_width_deg"):
        FitSettings(lane_width_deg=0.0)
    with pytest.raises(ValueError, match="lane_reg"):
        FitSettings(lane_reg=-0.1)
    with pytest.raises(ValueError, match="proposal_lane_reg"):
        FitSettings(proposal_lane_reg=math.nan)
    with pytest.raises(ValueError, match="lane_reg must be"):
        fit_to_masks(masks, boxes, INTR, settings=FIT, start_ry=start, road_ry=torch.zeros(1),
                     lane_reg=torch.tensor([-1.0]))


def test_each_request_weighs_the_lane_prior_its_own_way():
    """Two callers' objects fitted in one call (:func:`fit_many`): the request with its own ``lane_reg`` (a proposal's
    harder pull) ends on the road's axis, the one with the settings' weight 0 is fitted as without a road, bit for
    bit, and a single request's weight is the same as a per-object one."""
    masks, boxes = _blob()
    start = torch.tensor([math.radians(-56.0)])
    axis = torch.tensor([-math.pi / 2])
    settings = FitSettings(**{**FIT.to_dict(), "lane_reg": 0.0})
    # the same pair of objects without a road: the same batch, so the rows compare bit for bit on any machine
    _, plain = fit_many([FitRequest(masks, boxes, start_ry=start), FitRequest(masks, boxes, start_ry=start)], INTR,
                        settings=settings)
    pulled, unweighted = fit_many([FitRequest(masks, boxes, start_ry=start, road_ry=axis, lane_reg=1.0),
                                   FitRequest(masks, boxes, start_ry=start, road_ry=axis)], INTR, settings=settings)
    assert _off_axis(float(pulled.ry[0]), float(axis)) < 3.0
    assert torch.equal(unweighted.ry, plain.ry) and torch.equal(unweighted.loss, plain.loss)
    alone = fit_many([FitRequest(masks, boxes, start_ry=start, road_ry=axis, lane_reg=1.0)], INTR, settings=settings)[0]
    direct = fit_to_masks(masks, boxes, INTR, settings=settings, start_ry=start, road_ry=axis,
                          lane_reg=torch.tensor([1.0]))
    assert torch.equal(alone.ry, direct.ry) and torch.equal(alone.loss, direct.loss)


def test_the_lane_prior_is_blind_to_the_end_and_flat_far_from_the_axis():
    road = torch.full((5,), 0.3)
    ry = torch.tensor([0.3, 0.3 + math.pi, 0.3 - math.pi, 0.3 + math.radians(60), 0.3 + math.radians(90)])
    prior = lane_prior(ry, road, 15.0)
    assert prior[:3].abs().max() < 1e-6  # either end of the axis
    assert 0.98 < float(prior[3]) <= float(prior[4]) <= 1.0  # a car turned well off its lane pays about the same
    assert float(lane_prior(ry[:1], torch.tensor([math.nan]), 15.0)[0]) == 0.0


def _lane_lines(heading_deg: float) -> tuple[torch.Tensor, torch.Tensor]:
    """``(image (3, 96, 256), K)``: five bright lines on grey road below the horizon, meeting on it ``heading_deg``
    degrees right of the camera's forward direction (aliased: a line's direction is read from its edges' gradients,
    which a staircase of a shallow line would spoil)."""
    K = torch.tensor([[120.0, 0.0, 127.5], [0.0, 120.0, 30.0], [0.0, 0.0, 1.0]])
    ys, xs = torch.meshgrid(torch.arange(96.0), torch.arange(256.0), indexing="ij")
    u = 127.5 + 120.0 * math.tan(math.radians(heading_deg))
    lines = (ys > 32) & torch.stack([(xs - u - k * (ys - 30)).abs() <= 1.2 * math.hypot(1, k)
                                     for k in (-2.0, -1.0, 0.0, 1.0, 2.0)]).any(0)  # 2.4 px wide across
    return torch.where(lines, 0.95, 0.4).expand(3, 96, 256).clone(), K


def test_road_axes_read_the_lines_around_each_object():
    """Two cars on a road whose lines run 20 degrees right of the camera's forward direction: both stand along
    ``ry = 20 - 90`` degrees; a car in the sky (no lines around it) gets NaN."""
    image, K = _lane_lines(20.0)
    masks = torch.zeros(3, 96, 256, dtype=torch.bool)
    masks[0, 60:80, 40:80] = True
    masks[1, 50:70, 170:210] = True
    masks[2, 2:8, 120:130] = True  # its 20 px around reach no line
    image[:, :28] = 0.7  # a plain sky
    axes = road_axes(image, K, masks)
    want = axis_yaw(127.5 + 120.0 * math.tan(math.radians(20.0)), K)
    assert math.degrees(want) == pytest.approx(-70.0, abs=1e-4)
    assert math.degrees(float(axes[0])) == pytest.approx(-70.0, abs=1.0)
    assert math.degrees(float(axes[1])) == pytest.approx(-70.0, abs=1.0)
    assert math.isnan(float(axes[2]))
    assert road_axes(image, K, masks[:0]).shape == (0,)
